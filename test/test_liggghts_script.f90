!> Tests of the LIGGGHTS input script reader: the validation scenes' scripts
!> against the hand-written decks' values, each command, variables and their
!> arithmetic as LIGGGHTS evaluates it, include, continuation, comments and
!> quotes, what it cannot read named by file, line and command, and Debian's
!> liggghts-doc tutorial scripts (when installed).
module test_liggghts_script
  use testdrive, only: new_unittest, unittest_type, error_type, check, skip_test
  use demstep_kinds, only: dp
  use demstep_status, only: demstep_status_type, demstep_stat
  use demstep_text, only: int_text
  use demstep_liggghts_formula, only: liggghts_variable_type, liggghts_evaluate, liggghts_number_text
  use demstep_liggghts_script, only: liggghts_script_type, read_liggghts_script, parse_liggghts_script, &
    liggghts_units, liggghts_contacts_type, liggghts_script_contacts
  use demstep_material, only: code_convention
  use test_support, only: write_file, work_dir
  implicit none
  private
  public :: collect_liggghts_script

  character(len=*), parameter :: nl = new_line("a")
  character(len=*), parameter :: inputs = "validation/liggghts/inputs/"
  character(len=*), parameter :: examples = "/usr/share/doc/liggghts/examples/LIGGGHTS/Tutorials_public/"

contains

  subroutine collect_liggghts_script(testsuite)
    type(unittest_type), allocatable, intent(out) :: testsuite(:)
    testsuite = [ &
      new_unittest("validation scripts: materials, model, walls, gravity, step", test_validation), &
      new_unittest("validation scripts: Hooke, rolling friction, periodic, controls", test_validation_variants), &
      new_unittest("formulas: LIGGGHTS' precedence, functions, errors", test_formulas), &
      new_unittest("variables: ${}, $x, $( ), styles, 15 digits", test_variables), &
      new_unittest("include, continuation, comments, quotes", test_syntax), &
      new_unittest("what is not read is named by file, line and command", test_refused), &
      new_unittest("Debian's liggghts-doc tutorial scripts", test_tutorials), &
      new_unittest("contacts from the validation scripts = the hand-written decks", test_contacts), &
      new_unittest("contacts: what demstep's conventions do not cover is named", test_contacts_refused) &
      ]
  end subroutine collect_liggghts_script

  subroutine read_ok(path, script, error)
    character(len=*), intent(in) :: path
    type(liggghts_script_type), intent(out) :: script
    type(error_type), allocatable, intent(out) :: error
    type(demstep_status_type) :: status
    call read_liggghts_script(path, script, status)
    call check(error, status%stat == demstep_stat%ok, path//": "//status_text(status))
  end subroutine read_ok

  subroutine parse_ok(text, script, error)
    character(len=*), intent(in) :: text
    type(liggghts_script_type), intent(out) :: script
    type(error_type), allocatable, intent(out) :: error
    type(demstep_status_type) :: status
    call parse_liggghts_script(text, script, status)
    call check(error, status%stat == demstep_stat%ok, "parse: "//status_text(status))
  end subroutine parse_ok

  pure function status_text(status) result(text)
    type(demstep_status_type), intent(in) :: status
    character(len=:), allocatable :: text
    text = "ok"
    if (allocated(status%message)) text = status%message
  end function status_text

  !> The walled box of the validation scenes: planes at x, y = -0.01, 0.01 and
  !> z = 0, 0.05, inward normals, wall type 1 (a_hertz.nml's walls).
  subroutine check_box_walls(error, script, what)
    type(error_type), allocatable, intent(out) :: error
    type(liggghts_script_type), intent(in) :: script
    character(len=*), intent(in) :: what
    real(dp), parameter :: positions(6) = [-0.01_dp, 0.01_dp, -0.01_dp, 0.01_dp, 0.0_dp, 0.05_dp]
    integer, parameter :: axes(6) = [1, 1, 2, 2, 3, 3]
    real(dp), parameter :: signs(6) = [1, -1, 1, -1, 1, -1]
    integer :: k
    call check(error, script%n_walls, 6, what//": six walls")
    if (allocated(error)) return
    do k = 1, 6
      call check(error, script%walls(k)%axis == axes(k) .and. script%walls(k)%position == positions(k) .and. &
        script%walls(k)%normal(axes(k)) == signs(k) .and. script%walls(k)%wall_type == 1, what//": wall "// &
        script%walls(k)%id)
      if (allocated(error)) return
    end do
  end subroutine check_box_walls

  subroutine test_validation(error)
    type(error_type), allocatable, intent(out) :: error
    type(liggghts_script_type) :: s
    call read_ok(inputs//"in.build_a_hertz", s, error)
    if (allocated(error)) return
    ! a_hertz.nml: young 1e7, poisson 0.3, e 0.5 (friction 0.5), liggghts_hertz
    call check(error, s%units == liggghts_units%si .and. s%n_types == 1 .and. s%young(1) == 1.0e7_dp .and. &
      s%poisson(1) == 0.3_dp .and. s%restitution(1, 1) == 0.5_dp .and. s%friction(1, 1) == 0.5_dp .and. &
      .not. allocated(s%rolling_friction), "materials")
    if (allocated(error)) return
    call check(error, s%pair%model == "hertz" .and. s%pair%tangential == "history" .and. s%pair%rolling == "off" &
      .and. s%pair%tangential_damping, "pair_style gran model hertz tangential history")
    if (allocated(error)) return
    call check(error, all(s%gravity == [0.0_dp, 0.0_dp, -9.81_dp]) .and. s%timestep == 5.0e-6_dp .and. &
      .not. any(s%periodic) .and. s%box_known, "gravity, timestep, boundary m m m, the box")
    if (allocated(error)) return
    call check_box_walls(error, s, "a_hertz build")
    if (allocated(error)) return
    call check(error, s%n_templates == 3 .and. s%templates(3)%radius == 0.0015_dp .and. &
      s%templates(3)%density == 2500.0_dp .and. s%templates(3)%atom_type == 1, "particle templates")
    if (allocated(error)) return
    ! the bisection trial: read_restart (no box: the walls' pairs orient them),
    ! control flow and a thermo-keyword variable never substituted
    call read_ok(inputs//"in.trial_a_hertz_example", s, error)
    if (allocated(error)) return
    call check_box_walls(error, s, "trial")
    if (allocated(error)) return
    call check(error, s%timestep == 4.236711885e-05_dp .and. .not. s%box_known, "the trial's timestep")
  end subroutine test_validation

  subroutine test_validation_variants(error)
    type(error_type), allocatable, intent(out) :: error
    type(liggghts_script_type) :: s
    call read_ok(inputs//"in.export_b_hooke", s, error)
    if (allocated(error)) return
    call check(error, s%pair%model == "hooke" .and. s%characteristic_velocity == 0.5_dp .and. &
      s%restitution(1, 1) == 0.3_dp .and. s%walls(1)%model%model == "hooke", "b_hooke")
    if (allocated(error)) return
    call read_ok(inputs//"in.build_c_epsd2", s, error)
    if (allocated(error)) return
    call check(error, s%pair%rolling == "epsd2" .and. s%rolling_friction(1, 1) == 0.1_dp .and. &
      s%walls(6)%model%rolling == "epsd2", "c_epsd2")
    if (allocated(error)) return
    call read_ok(inputs//"in.build_d_periodic", s, error)
    if (allocated(error)) return
    call check(error, all(s%periodic) .and. s%n_walls == 0 .and. all(s%gravity == 0.0_dp), "d_periodic")
    if (allocated(error)) return
    call read_ok(inputs//"in.export_e_undamped", s, error)
    if (allocated(error)) return
    call check(error, s%restitution(1, 1) == 1.0_dp .and. s%friction(1, 1) == 10.0_dp, "e_undamped")
    if (allocated(error)) return
    call read_ok(inputs//"in.export_f_tdoff", s, error)
    if (allocated(error)) return
    call check(error, .not. s%pair%tangential_damping .and. .not. s%walls(1)%model%tangential_damping, &
      "f_tdoff: tangential_damping off, pairs and walls")
    if (allocated(error)) return
    call read_ok(inputs//"in.export_g_hooke_undamped", s, error)
    if (allocated(error)) return
    call check(error, s%pair%model == "hooke" .and. s%restitution(1, 1) == 1.0_dp, "g_hooke_undamped")
  end subroutine test_validation_variants

  !> One formula's value, exactly (each is exact in binary or computed the
  !> same way on both sides).
  subroutine check_formula(error, formula, want)
    type(error_type), allocatable, intent(out) :: error
    character(len=*), intent(in) :: formula
    real(dp), intent(in) :: want
    type(liggghts_variable_type) :: vars(1)
    type(demstep_status_type) :: status
    real(dp) :: x
    call liggghts_evaluate(formula, vars, 0, x, status)
    call check(error, status%stat == demstep_stat%ok .and. x == want, formula//": "//status_text(status))
  end subroutine check_formula

  subroutine check_formula_error(error, formula, part)
    type(error_type), allocatable, intent(out) :: error
    character(len=*), intent(in) :: formula, part
    type(liggghts_variable_type) :: vars(1)
    type(demstep_status_type) :: status
    real(dp) :: x
    call liggghts_evaluate(formula, vars, 0, x, status)
    call check(error, status%stat == demstep_stat%invalid_input .and. index(status_text(status), part) > 0, &
      formula//": '"//status_text(status)//"' has '"//part//"'")
  end subroutine check_formula_error

  subroutine test_formulas(error)
    type(error_type), allocatable, intent(out) :: error
    call check_formula(error, "1+2*3", 7.0_dp)
    if (allocated(error)) return
    call check_formula(error, "(1+2)*3", 9.0_dp)
    if (allocated(error)) return
    ! every binary operator is left-associative (variable.cpp:1567)
    call check_formula(error, "2^3^2", 64.0_dp)
    if (allocated(error)) return
    call check_formula(error, "8-2-1", 5.0_dp)
    if (allocated(error)) return
    call check_formula(error, "8/2/2", 2.0_dp)
    if (allocated(error)) return
    ! the unary minus binds tighter than ^ (precedence 8 against 7)
    call check_formula(error, "-2^2", 4.0_dp)
    if (allocated(error)) return
    call check_formula(error, "2^-1", 0.5_dp)
    if (allocated(error)) return
    call check_formula(error, "7%4", 3.0_dp)
    if (allocated(error)) return
    call check_formula(error, "1 < 2 && 3 >= 3 || 0", 1.0_dp)
    if (allocated(error)) return
    call check_formula(error, "!0 + (2 != 2)", 1.0_dp)
    if (allocated(error)) return
    call check_formula(error, "sqrt(16)+abs(-1)+floor(2.7)+ceil(2.1)", 10.0_dp)
    if (allocated(error)) return
    ! MYROUND: halves go up
    call check_formula(error, "round(2.5)+round(-2.5)", 1.0_dp)
    if (allocated(error)) return
    call check_formula(error, "log(1000)", log10(1000.0_dp))
    if (allocated(error)) return
    call check_formula(error, "ln(exp(2))", log(exp(2.0_dp)))
    if (allocated(error)) return
    call check_formula(error, "atan2(1,1)*4", atan2(1.0_dp, 1.0_dp)*4)
    if (allocated(error)) return
    call check_formula(error, "2*PI", 2*3.14159265358979323846_dp)
    if (allocated(error)) return
    call check_formula(error, "1.5e-3*2E3", 3.0_dp)
    if (allocated(error)) return
    ! LIGGGHTS' errors
    call check_formula_error(error, "2^0", "power by 0")
    if (allocated(error)) return
    call check_formula_error(error, "1/(2-2)", "at column 2: divide by 0")
    if (allocated(error)) return
    call check_formula_error(error, "sqrt(-1)", "sqrt of a negative value")
    if (allocated(error)) return
    call check_formula_error(error, "ke+1", "'ke' is a thermo keyword")
    if (allocated(error)) return
    call check_formula_error(error, "c_rke*2", "'c_rke' needs a running simulation")
    if (allocated(error)) return
    call check_formula_error(error, "normal(0,1,5)", "random numbers")
    if (allocated(error)) return
    call check_formula_error(error, "(1+2", "'(' without ')'")
    if (allocated(error)) return
    call check_formula_error(error, "1+", "a value is missing")
    if (allocated(error)) return
    call check_formula_error(error, "v_nope", "no variable 'nope'")
    if (allocated(error)) return
    ! substitution texts: %.15g and %.20g
    call check(error, liggghts_number_text(50000.0_dp, 15) == "50000" .and. &
      liggghts_number_text(0.1_dp, 15) == "0.1" .and. liggghts_number_text(1.0_dp/3, 15) == &
      "0.333333333333333" .and. liggghts_number_text(-2.5e-7_dp, 15) == "-2.5e-07" .and. &
      liggghts_number_text(1.0e300_dp, 15) == "1e+300" .and. liggghts_number_text(0.1_dp, 20) == &
      "0.10000000000000000555", "%g texts: "//liggghts_number_text(1.0_dp/3, 15)//" " &
      //liggghts_number_text(-2.5e-7_dp, 15)//" "//liggghts_number_text(0.1_dp, 20))
  end subroutine test_formulas

  subroutine test_variables(error)
    type(error_type), allocatable, intent(out) :: error
    type(liggghts_script_type) :: s
    ! the packing tutorial's pattern: equal-style arithmetic substituted
    call parse_ok("units si" // nl // &
      "variable E equal 5.e6" // nl // &
      "variable nu index 0.45" // nl // &
      "variable nu index 0.2" // nl // &  ! an index variable keeps its first value
      "variable e equal 0.1*3" // nl // &
      "variable dt equal 1/3*1e-5" // nl // &
      "variable g string 9.81" // nl // &
      "variable n equal 2-1" // nl // &
      "fix m1 all property/global youngsModulus peratomtype ${E}" // nl // &
      "fix m2 all property/global poissonsRatio peratomtype $(v_nu)" // nl // &
      "fix m3 all property/global coefficientRestitution peratomtypepair ${n} ${e}" // nl // &
      "variable a equal 2" // nl // &
      "variable a equal v_a*3" // nl // &  ! redefined in terms of itself: circular when used
      "timestep ${dt}" // nl // &
      "fix grav all gravity $g vector 0 0 -1", s, error)
    if (allocated(error)) return
    call check(error, s%young(1) == 5.0e6_dp .and. s%poisson(1) == 0.45_dp, "${E}, $(v_nu), index kept")
    if (allocated(error)) return
    ! 0.1*3 = 0.30000000000000004 is written with 15 digits: 0.3
    call check(error, s%restitution(1, 1) == 0.3_dp .and. s%n_types == 1, "${e}: 15 significant digits")
    if (allocated(error)) return
    call check(error, s%timestep == 3.33333333333333e-6_dp .and. s%timestep /= 1.0_dp/3*1e-5_dp, &
      "${dt}: 15 significant digits")
    if (allocated(error)) return
    call check(error, s%gravity(3) == -9.81_dp, "$g: a one-letter string variable")
    if (allocated(error)) return
    call check(error, s%n_vars >= 7, "variables kept")
    if (allocated(error)) return
    call expect_refusal(error, "variable a equal 2" // nl // "variable a equal v_a*3" // nl // "timestep ${a}", &
      "script: line 3: timestep: ${a}: variable a (line 2): ", "circular")
    if (allocated(error)) return
    ! each variable using the previous twice: 2^40 evaluations refused, not run
    block
      character(len=:), allocatable :: chain
      integer :: k
      chain = "variable a0 equal 1"
      do k = 1, 40
        chain = chain//nl//"variable a"//int_text(k)//" equal v_a"//int_text(k - 1)//"+v_a"//int_text(k - 1)
      end do
      call expect_refusal(error, chain//nl//"timestep ${a40}", "script: line 42: timestep: ${a40}: ", &
        "more than a million variable references")
      if (allocated(error)) return
    end block
    call expect_refusal(error, "timestep ${nope}", "script: line 1: timestep: $nope: no variable 'nope'", "")
    if (allocated(error)) return
    call expect_refusal(error, "variable v string abc" // nl // "variable v equal 1", &
      "script: line 2: variable: 'v': cannot redefine a variable as a different style", "")
    if (allocated(error)) return
    call expect_refusal(error, "variable r equal ke*2" // nl // "timestep ${r}", &
      "script: line 2: timestep: ${r}: variable r (line 1): 'ke*2' at column 1: 'ke' is a thermo keyword", "")
  end subroutine test_variables

  subroutine expect_refusal(error, text, start, part)
    type(error_type), allocatable, intent(out) :: error
    character(len=*), intent(in) :: text, start, part
    type(liggghts_script_type) :: s
    type(demstep_status_type) :: status
    call parse_liggghts_script(text, s, status)
    call check(error, status%stat == demstep_stat%invalid_input .and. index(status_text(status), start) == 1 &
      .and. index(status_text(status), part) > 0, "'"//status_text(status)//"' starts with '"//start//"'" &
      //" and has '"//part//"'")
  end subroutine expect_refusal

  subroutine test_syntax(error)
    type(error_type), allocatable, intent(out) :: error
    type(liggghts_script_type) :: s
    type(demstep_status_type) :: status
    character(len=*), parameter :: dir = work_dir//"/lig/"
    integer :: cs
    call execute_command_line("mkdir -p "//dir, cmdstat=cs)
    call write_file(dir//"materials.in", [character(len=70) :: &
      "# materials, included", &
      "fix m1 all property/global youngsModulus peratomtype 1e7 2e7", &
      "fix m2 all property/global poissonsRatio peratomtype 0.3 0.25", &
      "include sub/friction.in"])
    call execute_command_line("mkdir -p "//dir//"sub", cmdstat=cs)
    ! included files are found relative to the including script
    call write_file(dir//"sub/friction.in", [character(len=70) :: &
      "fix m4 all property/global coefficientFriction peratomtypepair 2 &", &
      "   0.5 0.4 &   ", &
      "   0.4 0.3   # a comment after the continuation"])
    call write_file(dir//"in.main", [character(len=120) :: &
      "units cgs", &
      "boundary p f m", &
      "region box block -1 1 -1 1 0 4 units box", &
      "create_box 2 box", &
      "include materials.in", &
      "fix m3 all property/global coefficientRestitution peratomtypepair 2 0.9 0.8 0.8 0.7", &
      "pair_style gran model hertz tangential history rolling_friction cdt tangential_damping off limitForce on", &
      "fix floor all wall/gran model hertz tangential history primitive type 2 zplane 0", &
      "print ""a # inside quotes is no comment ${undefined}""", &
      "fix grav all gravity 981 vector 1 0 -1"])
    call read_liggghts_script(dir//"in.main", s, status)
    call check(error, status%stat == demstep_stat%ok, "reads: "//status_text(status))
    if (allocated(error)) return
    call check(error, s%units == liggghts_units%cgs .and. all(s%periodic .eqv. [.true., .false., .false.]) .and. &
      s%n_types == 2 .and. all(s%young == [1.0e7_dp, 2.0e7_dp]) .and. all(s%poisson == [0.3_dp, 0.25_dp]), &
      "units, boundary, included materials")
    if (allocated(error)) return
    call check(error, all(s%friction == reshape([0.5_dp, 0.4_dp, 0.4_dp, 0.3_dp], [2, 2])) .and. &
      s%restitution(2, 2) == 0.7_dp, "continued lines, nested include")
    if (allocated(error)) return
    call check(error, s%pair%rolling == "cdt" .and. .not. s%pair%tangential_damping .and. s%pair%limit_force, &
      "model settings")
    if (allocated(error)) return
    ! a lone floor: the box's centre (z = 2) is above it
    call check(error, s%n_walls == 1 .and. s%walls(1)%normal(3) == 1.0_dp .and. s%walls(1)%wall_type == 2, &
      "the floor's normal from the box")
    if (allocated(error)) return
    call check(error, abs(s%gravity(1) - 981/sqrt(2.0_dp)) < 1.0e-12_dp*981 .and. s%gravity(1) == -s%gravity(3), &
      "gravity normalised")
    if (allocated(error)) return
    ! an error in an included file names that file
    call write_file(dir//"sub/friction.in", [character(len=70) :: "fix m4 all property/global coefficientFriction &", &
      "  peratomtypepair 2 0.5 0.4 0.3 0.3"])
    call read_liggghts_script(dir//"in.main", s, status)
    call check(error, status%stat == demstep_stat%invalid_input .and. index(status_text(status), &
      dir//"sub/friction.in: line 1: fix property/global: coefficientFriction: the matrix must be symmetric") == 1, &
      status_text(status))
    if (allocated(error)) return
    ! a script that includes itself stops at the nesting limit
    call write_file(dir//"in.loop", [character(len=20) :: "units si", "include in.loop"])
    call read_liggghts_script(dir//"in.loop", s, status)
    call check(error, status%stat == demstep_stat%invalid_input .and. index(status_text(status), &
      "line 2: include: more than 16 nested includes") > 0, "include loop: "//status_text(status))
    if (allocated(error)) return
    call read_liggghts_script(dir//"no_such.in", s, status)
    call check(error, status%stat == demstep_stat%io_error .and. index(status_text(status), dir//"no_such.in: ") &
      == 1, "a missing script")
  end subroutine test_syntax

  subroutine test_refused(error)
    type(error_type), allocatable, intent(out) :: error
    type(liggghts_script_type) :: s
    type(demstep_status_type) :: status
    call expect_refusal(error, "units si" // nl // "frobnicate 1 2", &
      "script: line 2: frobnicate: unknown command", "")
    if (allocated(error)) return
    call parse_liggghts_script("units si" // nl // "frobnicate 1 2", s, status)
    call check(error, status%where == "frobnicate", "the command as the location")
    if (allocated(error)) return
    call expect_refusal(error, "units lj", "script: line 1: units: 'lj' is not read", "")
    if (allocated(error)) return
    call expect_refusal(error, "fix c all property/global cohesionEnergyDensity peratomtypepair 1 300", &
      "script: line 1: fix property/global: cohesionEnergyDensity: cohesion is not supported", "")
    if (allocated(error)) return
    call expect_refusal(error, "pair_style gran model hertz tangential history cohesion sjkr", &
      "script: line 1: pair_style: cohesion 'sjkr' is not supported", "")
    if (allocated(error)) return
    call expect_refusal(error, "pair_style gran/hertz/history", "script: line 1: pair_style: 'gran/hertz/history'" &
      //" is not read", "")
    if (allocated(error)) return
    call expect_refusal(error, "pair_style gran model hertz tangential history frobnicate on", &
      "script: line 1: pair_style: 'frobnicate' is not a setting", "")
    if (allocated(error)) return
    call expect_refusal(error, "fix w all wall/gran model hertz tangential history mesh n_meshes 1 meshes cad", &
      "script: line 1: fix wall/gran: mesh walls are not read", "")
    if (allocated(error)) return
    call expect_refusal(error, "fix w all wall/gran model hertz tangential history primitive type 1 zcylinder " &
      //"0.1 0 0", "script: line 1: fix wall/gran: primitive 'zcylinder' is not read", "")
    if (allocated(error)) return
    call expect_refusal(error, "fix g all gravity 9.81 chute 26", "script: line 1: fix gravity: expected", "")
    if (allocated(error)) return
    call expect_refusal(error, "fix ms all multisphere", "script: line 1: fix multisphere: fix style not read " &
      //"by demstep (rigid bodies: give the settled state as a dump with its mol and mass columns", "")
    if (allocated(error)) return
    call expect_refusal(error, "fix m all property/global youngsModulus peratomtype 1e7 -1", &
      "script: line 1: youngsModulus(2): value for type 2 must be > 0", "")
    if (allocated(error)) return
    call expect_refusal(error, "create_box 2 box" // nl // "fix m all property/global poissonsRatio peratomtype 0.3", &
      "script: line 2: fix property/global: poissonsRatio: 1 types, but the script has 2", "")
    if (allocated(error)) return
    call expect_refusal(error, "fix m all property/global coefficientRestitution peratomtypepair 2 0.5 0.5 0.5", &
      "script: line 1: fix property/global: coefficientRestitution: 2 types need 4 values, got 3", "")
    if (allocated(error)) return
    call expect_refusal(error, "timestep abc", "script: line 1: timestep: 'abc' is not a number", "")
    if (allocated(error)) return
    call expect_refusal(error, "fix m all property/global hardness peratomtype 1", &
      "script: line 1: fix property/global: property 'hardness' is not read", "")
  end subroutine test_refused

  !> Every tutorial script of Debian's liggghts-doc is read or refused with
  !> one located message; the packing tutorial is read, with its values.
  subroutine test_tutorials(error)
    type(error_type), allocatable, intent(out) :: error
    type(liggghts_script_type) :: s
    type(demstep_status_type) :: status
    character(len=*), parameter :: list = work_dir//"/liggghts_tutorials.txt"
    !> Each script's outcome, one line each, for the record.
    character(len=*), parameter :: outcome = work_dir//"/liggghts_tutorials_outcome.txt"
    type(liggghts_contacts_type) :: c
    character(len=1024) :: path
    logical :: there
    integer :: unit, ios, cs, n, out
    inquire(file=examples//"packing/in.packing", exist=there)
    if (.not. there) then
      call skip_test(error, "Debian's liggghts-doc is not installed ("//examples//")")
      return
    end if
    call read_liggghts_script(examples//"packing/in.packing", s, status)
    call check(error, status%stat == demstep_stat%ok, "in.packing: "//status_text(status))
    if (allocated(error)) return
    call check(error, s%young(1) == 5.0e6_dp .and. s%poisson(1) == 0.45_dp .and. s%restitution(1, 1) == 0.3_dp &
      .and. s%friction(1, 1) == 0.5_dp .and. s%timestep == 1.0e-5_dp .and. s%n_walls == 6 .and. &
      s%walls(6)%normal(3) == -1.0_dp .and. s%pair%model == "hertz", "in.packing's values")
    if (allocated(error)) return
    ! every tutorial script (28 in liggghts-doc 3.8.0): read, or refused with
    ! one message naming the file and the line
    call execute_command_line("mkdir -p "//work_dir//" && find "//examples//" -name 'in.*' -type f | sort > " &
      //list, cmdstat=cs)
    open(newunit=unit, file=list, status="old", action="read", iostat=ios)
    call check(error, ios == 0 .and. cs == 0, "the list of tutorial scripts")
    if (allocated(error)) return
    open(newunit=out, file=outcome, status="replace", action="write")
    n = 0
    do
      read(unit, '(a)', iostat=ios) path
      if (ios /= 0) exit
      n = n + 1
      call tutorial(trim(path))
      if (allocated(error)) exit
    end do
    close(unit)
    close(out)
    if (allocated(error)) return
    call check(error, n >= 20, "the tutorial scripts were found")
  contains
    !> Read, or refused with `FILE: line N: command: ...` naming the file;
    !> when read, its contacts given to a scene or refused naming the file
    !> (and the line, except for what the script lacks).
    subroutine tutorial(name)
      character(len=*), intent(in) :: name
      call read_liggghts_script(name, s, status)
      call check(error, status%stat == demstep_stat%ok .or. (status%stat == demstep_stat%invalid_input .and. &
        index(status_text(status), name//": line ") == 1 .and. allocated(status%where)), &
        name//": "//status_text(status))
      if (allocated(error)) return
      if (status%stat /= demstep_stat%ok) then
        write(out, '(a)') "refused: "//status_text(status)
        return
      end if
      call liggghts_script_contacts(s, c, status, file=name)
      call check(error, status%stat == demstep_stat%ok .or. (status%stat == demstep_stat%invalid_input .and. &
        index(status_text(status), name//": ") == 1 .and. allocated(status%where)), &
        name//": contacts: "//status_text(status))
      if (status%stat == demstep_stat%ok) then
        write(out, '(a)') "read, contacts: "//name
      else
        write(out, '(a)') "read, contacts refused: "//status_text(status)
      end if
    end subroutine tutorial
  end subroutine test_tutorials

  !> The scene's inputs from a validation script and from its hand-written
  !> deck (validation/liggghts/demstep/*.nml) are the same values.
  subroutine test_contacts(error)
    type(error_type), allocatable, intent(out) :: error
    type(liggghts_script_type) :: s
    type(liggghts_contacts_type) :: c
    type(demstep_status_type) :: status
    ! a_hertz.nml: liggghts_hertz, young 1e7, poisson 0.3, restitution 0.5,
    ! the box's six walls (point, inward normal), wall_type 1
    real(dp), parameter :: walls(6, 6) = reshape([-0.01_dp, 0.0_dp, 0.0_dp, 1.0_dp, 0.0_dp, 0.0_dp, &
      0.01_dp, 0.0_dp, 0.0_dp, -1.0_dp, 0.0_dp, 0.0_dp, 0.0_dp, -0.01_dp, 0.0_dp, 0.0_dp, 1.0_dp, 0.0_dp, &
      0.0_dp, 0.01_dp, 0.0_dp, 0.0_dp, -1.0_dp, 0.0_dp, 0.0_dp, 0.0_dp, 0.0_dp, 0.0_dp, 0.0_dp, 1.0_dp, &
      0.0_dp, 0.0_dp, 0.05_dp, 0.0_dp, 0.0_dp, -1.0_dp], [6, 6])
    call read_ok(inputs//"in.export_a_hertz", s, error)
    if (allocated(error)) return
    call liggghts_script_contacts(s, c, status)
    call check(error, status%stat == demstep_stat%ok, "a_hertz: "//status_text(status))
    if (allocated(error)) return
    call check(error, c%convention == code_convention%liggghts_hertz .and. all(c%young == [1.0e7_dp]) .and. &
      all(c%poisson == [0.3_dp]) .and. c%restitution == 0.5_dp .and. c%tangential_damping .and. &
      c%rolling_ratio == 0.0_dp .and. c%wall_type == 1 .and. .not. any(c%periodic), "a_hertz.nml's values")
    if (allocated(error)) return
    call check(error, all(c%wall_points == walls(1:3, :)) .and. all(c%wall_normals == walls(4:6, :)), &
      "a_hertz.nml's walls")
    if (allocated(error)) return
    ! b_hooke.nml: liggghts_hooke, restitution 0.3, impact_velocity 0.5
    call read_ok(inputs//"in.export_b_hooke", s, error)
    if (allocated(error)) return
    call liggghts_script_contacts(s, c, status)
    call check(error, status%stat == demstep_stat%ok .and. c%convention == code_convention%liggghts_hooke .and. &
      c%restitution == 0.3_dp .and. c%impact_velocity == 0.5_dp, "b_hooke.nml's values: "//status_text(status))
    if (allocated(error)) return
    ! c_epsd2.nml: rolling_ratio 1
    call read_ok(inputs//"in.export_c_epsd2", s, error)
    if (allocated(error)) return
    call liggghts_script_contacts(s, c, status)
    call check(error, status%stat == demstep_stat%ok .and. c%rolling_ratio == 1.0_dp, "c_epsd2.nml's rolling")
    if (allocated(error)) return
    ! d_periodic: periodic, no walls (the build script states 'boundary p p p';
    ! the export script's read_restart takes it from the restart file)
    call read_ok(inputs//"in.build_d_periodic", s, error)
    if (allocated(error)) return
    call liggghts_script_contacts(s, c, status)
    call check(error, status%stat == demstep_stat%ok .and. all(c%periodic) .and. c%wall_type == 0 .and. &
      size(c%wall_points, 2) == 0, "d_periodic: "//status_text(status))
    if (allocated(error)) return
    ! f_tdoff.nml: tangential_damping = F
    call read_ok(inputs//"in.export_f_tdoff", s, error)
    if (allocated(error)) return
    call liggghts_script_contacts(s, c, status)
    call check(error, status%stat == demstep_stat%ok .and. .not. c%tangential_damping, "f_tdoff")
    if (allocated(error)) return
    ! e_undamped and g_hooke_undamped: restitution 1
    call read_ok(inputs//"in.export_g_hooke_undamped", s, error)
    if (allocated(error)) return
    call liggghts_script_contacts(s, c, status)
    call check(error, status%stat == demstep_stat%ok .and. c%restitution == 1.0_dp .and. &
      c%convention == code_convention%liggghts_hooke, "g_hooke_undamped")
    if (allocated(error)) return
    ! friction: one value taken (c_epsd2: 0.5, rolling 0.1); differing between
    ! type pairs, none taken and said so
    call read_ok(inputs//"in.export_c_epsd2", s, error)
    if (allocated(error)) return
    call liggghts_script_contacts(s, c, status)
    call check(error, status%stat == demstep_stat%ok .and. c%friction == 0.5_dp .and. c%rolling_friction == 0.1_dp &
      .and. .not. c%friction_per_pair, "c_epsd2's friction")
    if (allocated(error)) return
    call parse_ok("fix m1 all property/global youngsModulus peratomtype 1e7 1e7"//nl//"fix m2 all " &
      //"property/global poissonsRatio peratomtype 0.3 0.3"//nl//"fix m3 all property/global " &
      //"coefficientRestitution peratomtypepair 2 0.5 0.5 0.5 0.5"//nl//"fix m4 all property/global " &
      //"coefficientFriction peratomtypepair 2 0.1 0.3 0.3 0.1"//nl//"pair_style gran model hertz tangential " &
      //"history", s, error)
    if (allocated(error)) return
    call liggghts_script_contacts(s, c, status)
    call check(error, status%stat == demstep_stat%ok .and. c%friction == -1.0_dp .and. c%friction_per_pair, &
      "friction per type pair: none taken, said so: "//status_text(status))
  end subroutine test_contacts

  subroutine expect_contacts_refusal(error, text, start)
    type(error_type), allocatable, intent(out) :: error
    character(len=*), intent(in) :: text, start
    type(liggghts_script_type) :: s
    type(liggghts_contacts_type) :: c
    type(demstep_status_type) :: status
    call parse_ok(text, s, error)
    if (allocated(error)) return
    call liggghts_script_contacts(s, c, status)
    call check(error, status%stat == demstep_stat%invalid_input .and. index(status_text(status), start) == 1, &
      "'"//status_text(status)//"' starts with '"//start//"'")
  end subroutine expect_contacts_refusal

  subroutine test_contacts_refused(error)
    type(error_type), allocatable, intent(out) :: error
    character(len=*), parameter :: materials = "fix m1 all property/global youngsModulus peratomtype 1e7 1e7" &
      //nl//"fix m2 all property/global poissonsRatio peratomtype 0.3 0.3"//nl
    call expect_contacts_refusal(error, "units si", "script: pair_style: missing")
    if (allocated(error)) return
    call expect_contacts_refusal(error, materials//"pair_style gran model hertz/stiffness tangential history", &
      "script: line 3: pair_style: model 'hertz/stiffness'")
    if (allocated(error)) return
    call expect_contacts_refusal(error, materials//"pair_style gran model hertz tangential no_history", &
      "script: line 3: pair_style: tangential 'no_history'")
    if (allocated(error)) return
    call expect_contacts_refusal(error, materials//"pair_style gran model hertz tangential history " &
      //"rolling_friction epsd", "script: line 3: pair_style: rolling_friction 'epsd'")
    if (allocated(error)) return
    call expect_contacts_refusal(error, "pair_style gran model hertz tangential history", &
      "script: youngsModulus: missing")
    if (allocated(error)) return
    call expect_contacts_refusal(error, materials//"pair_style gran model hertz tangential history"//nl// &
      "fix m3 all property/global coefficientRestitution peratomtypepair 2 0.5 0.6 0.6 0.5", &
      "script: line 4: fix property/global: coefficientRestitution differs between type pairs")
    if (allocated(error)) return
    call expect_contacts_refusal(error, materials//"pair_style gran model hooke tangential history"//nl// &
      "fix m3 all property/global coefficientRestitution peratomtypepair 2 0.5 0.5 0.5 0.5", &
      "script: line 3: pair_style: model hooke needs")
    if (allocated(error)) return
    call expect_contacts_refusal(error, materials//"pair_style gran model hertz tangential history"//nl// &
      "fix m3 all property/global coefficientRestitution peratomtypepair 2 0.5 0.5 0.5 0.5"//nl// &
      "fix w1 all wall/gran model hertz tangential history primitive type 1 zplane 0"//nl// &
      "fix w2 all wall/gran model hertz tangential history primitive type 2 zplane 1", &
      "script: line 6: fix wall/gran: wall 'w2' is of type 2, wall 'w1' of type 1")
    if (allocated(error)) return
    call expect_contacts_refusal(error, materials//"pair_style gran model hertz tangential history"//nl// &
      "fix m3 all property/global coefficientRestitution peratomtypepair 2 0.5 0.5 0.5 0.5"//nl// &
      "fix w1 all wall/gran model hooke tangential history primitive type 1 zplane 0", &
      "script: line 5: fix wall/gran: wall 'w1': its model differs")
    if (allocated(error)) return
    call expect_contacts_refusal(error, materials//"pair_style gran model hertz tangential history"//nl// &
      "fix m3 all property/global coefficientRestitution peratomtypepair 2 0.5 0.5 0.5 0.5"//nl// &
      "fix w1 all wall/gran model hertz tangential history primitive type 1 zplane 0", &
      "script: line 5: fix wall/gran: wall 'w1': the script does not tell its side")
  end subroutine test_contacts_refused

end module test_liggghts_script
