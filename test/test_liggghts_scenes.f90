!> `&scene liggghts_script`: a LIGGGHTS input script and LIGGGHTS' own dump
!> give each validation scene the same limits as its hand-written deck
!> (validation/liggghts/demstep/*.nml, whose dumps split the one LIGGGHTS type
!> by radius class); Hooke's stiffness per contact against LIGGGHTS' formula;
!> the report's timestep line; and what the script and snapshot cannot give
!> refused in one line naming the file, line and command.
module test_liggghts_scenes
  use testdrive, only: new_unittest, unittest_type, error_type, check
  use demstep_kinds, only: dp
  use demstep_status, only: demstep_status_type, demstep_stat
  use demstep_material, only: material_type, material_pair_type, code_convention, contact_parameters_type, &
    contact_parameters
  use demstep_scene_data, only: scene_type, contact_values, wall_values
  use demstep_scene_builders, only: new_scene
  use demstep_scene_materials, only: scene_set_materials
  use demstep_results, only: result_group_type
  use test_support, only: run_app, write_file, read_file, work_dir, read_group, take
  implicit none
  private
  public :: collect_liggghts_scenes

  !> LIGGGHTS' own settled states (one atom type, as LIGGGHTS wrote them).
  character(len=*), parameter :: states = "test/data/liggghts/validation/"
  character(len=*), parameter :: inputs = "validation/liggghts/inputs/"
  character(len=*), parameter :: decks = "validation/liggghts/demstep/"
  character(len=*), parameter :: nl = new_line("a")
  !> The seven validation scenes and the settled state each starts from.
  character(len=*), parameter :: scenes(7) = [character(len=16) :: "a_hertz", "b_hooke", "c_epsd2", &
    "d_periodic", "e_undamped", "f_tdoff", "g_hooke_undamped"]
  character(len=*), parameter :: state_of(7) = [character(len=10) :: "a_hertz", "b_hooke", "c_epsd2", &
    "d_periodic", "a_hertz", "a_hertz", "b_hooke"]

contains

  subroutine collect_liggghts_scenes(testsuite)
    type(unittest_type), allocatable, intent(out) :: testsuite(:)
    testsuite = [ &
      new_unittest("validation scenes: script + LIGGGHTS' dump = hand-written deck (1e-12)", test_validation), &
      new_unittest("Hooke per contact: LIGGGHTS' k_n of each pair's own R* and m*", test_hooke_per_contact), &
      new_unittest("the report: the script's timestep against the exact limit", test_report), &
      new_unittest("script and snapshot disagree, or the script is not read: one line, file and line", &
        test_refused) &
      ]
  end subroutine collect_liggghts_scenes

  !> Run a deck; expect exit 0 and read the limits of `&scene_result`.
  subroutine run_limits(error, deck, limits, stdout)
    type(error_type), allocatable, intent(out) :: error
    character(len=*), intent(in) :: deck
    !> DT_CRITICAL_EIGEN, DT_CRITICAL_DAMPED, DT_CRITICAL_BOUND.
    real(dp), intent(out) :: limits(3)
    character(len=:), allocatable, intent(out) :: stdout
    character(len=:), allocatable :: stderr, text
    type(result_group_type) :: fields
    integer :: rc, ios
    limits = -1.0_dp
    call run_app("-q -o "//deck//".out "//deck, rc, stdout, stderr)
    call check(error, rc == 0 .and. len(stderr) == 0, deck//": "//stderr)
    if (allocated(error)) return
    call read_file(deck//".out", text)
    call read_group(text, "scene_result", fields, ios)
    if (ios == 0) call take(fields, "dt_critical_eigen", limits(1), ios)
    if (ios == 0) call take(fields, "dt_critical_damped", limits(2), ios)
    if (ios == 0) call take(fields, "dt_critical_bound", limits(3), ios)
    call check(error, ios == 0 .and. all(limits > 0.0_dp), deck//": &scene_result reads back")
  end subroutine run_limits

  !> Each scene twice: its hand-written deck (the dump split into three types
  !> by radius, &material in LIGGGHTS' convention at the nominal radii, the
  !> walls, rolling and damping options written out) and the four lines of a
  !> script deck (LIGGGHTS' one-type dump and the export script LIGGGHTS ran).
  !> Both at eigen_tolerance 1e-14: at the default 1e-10 the damped limit, a
  !> step certified safe to the Lanczos error bar, moves by up to 1e-11 with
  !> the rounding of the dashpots (measured 8.6e-12 on c_epsd2); at 1e-14 the
  !> two agree to 4e-14 (Hooke: the masses of the file against the nominal
  !> densities' in k_n), checked to 1e-12.
  subroutine test_validation(error)
    type(error_type), allocatable, intent(out) :: error
    character(len=:), allocatable :: text, root, stdout, s
    real(dp) :: by_deck(3), by_script(3)
    integer :: k, at
    character(len=4096) :: pwd
    integer :: length
    call get_environment_variable("PWD", pwd, length)
    root = trim(pwd)//"/"
    do k = 1, size(scenes)
      s = trim(scenes(k))
        ! the hand-written deck, its dump named from the project root
        call read_file(decks//s//".nml", text)
        at = index(text, "snapshot_file = '")
        call check(error, at > 0 .and. index(text, "&scene"//nl) > 0, decks//s//".nml")
        if (allocated(error)) return
        text = text(:at + 16)//root//decks//text(at + 17:)
        at = index(text, "&scene"//nl) + 6
        text = text(:at)//"  eigen_tolerance = 1e-14"//nl//text(at + 1:)
        call write_file(work_dir//"/deck_"//s//".nml", [text])
        call run_limits(error, work_dir//"/deck_"//s//".nml", by_deck, stdout)
        if (allocated(error)) return
        call write_file(work_dir//"/script_"//s//".nml", [character(len=300) :: "&scene", "  dim = 3", &
          "  snapshot_file = '"//root//states//trim(state_of(k))//".dump'", &
          "  liggghts_script = '"//root//inputs//"in.export_"//s//"'", "  eigen_tolerance = 1e-14", "/"])
        call run_limits(error, work_dir//"/script_"//s//".nml", by_script, stdout)
        if (allocated(error)) return
        call check(error, all(abs(by_script(1:2) - by_deck(1:2)) <= 1.0e-12_dp*by_deck(1:2)), s// &
          ": script "//real_text(by_script(2))//", deck "//real_text(by_deck(2)))
        if (allocated(error)) return
    end do
  end subroutine test_validation

  pure function real_text(x) result(text)
    real(dp), intent(in) :: x
    character(len=:), allocatable :: text
    character(len=32) :: buffer
    write(buffer, '(es24.16)') x
    text = trim(adjustl(buffer))
  end function real_text

  !> Two particles of radii 1 and 2 mm of one type (density 2500) and a wall:
  !> with `per_contact` each spring is LIGGGHTS' Hooke k_n of its own R* and
  !> m* (normal_model_hooke.h:269, `contact_parameters` of a pair of types of
  !> those radii), to 1e-14; without it, that of the type's nominal radius.
  subroutine test_hooke_per_contact(error)
    type(error_type), allocatable, intent(out) :: error
    type(scene_type) :: sc
    type(demstep_status_type) :: status
    type(material_type) :: mat(1)
    type(contact_parameters_type) :: pair, wall
    type(material_type) :: small, big
    real(dp), parameter :: r(2) = [1.0e-3_dp, 2.0e-3_dp], rho = 2500.0_dp, v = 0.5_dp
    real(dp) :: x(3, 2), m(2), f_n, k(4)
    m = rho*4.0_dp/3.0_dp*acos(-1.0_dp)*r**3
    x = 0.0_dp
    x(1, 2) = 2.9e-3_dp
    call new_scene(sc, 3, x, m, r, status)
    call check(error, status%stat == demstep_stat%ok, "the scene")
    if (allocated(error)) return
    mat(1) = material_type(young=1.0e7_dp, poisson=0.3_dp, density=rho, radius=1.5e-3_dp)
    call scene_set_materials(sc, [1, 1], mat, code_convention%liggghts_hooke, 0.5_dp, status, &
      impact_velocity=v, per_contact=.true.)
    call check(error, status%stat == demstep_stat%ok, "materials")
    if (allocated(error)) return
    small = material_type(young=1.0e7_dp, poisson=0.3_dp, density=rho, radius=r(1))
    big = material_type(young=1.0e7_dp, poisson=0.3_dp, density=rho, radius=r(2))
    call contact_parameters(material_pair_type(small, big, 0.5_dp, impact_velocity=v), &
      code_convention%liggghts_hooke, pair, status)
    call contact_values(sc, 0, 1, 2, 1.0e-4_dp, f_n, k)
    call check(error, abs(k(1)/pair%k_n - 1.0_dp) < 1.0e-14_dp .and. k(2) == k(1), &
      "pair: k_n of the pair's own R*, m*")
    if (allocated(error)) return
    ! a wall: R* = r, m* = m of the particle
    call contact_parameters(material_pair_type(big, big, 0.5_dp, impact_velocity=v), &
      code_convention%liggghts_hooke, wall, status, wall=.true.)
    call wall_values(sc, 2, 1.0e-4_dp, f_n, k)
    call check(error, abs(k(1)/wall%k_n - 1.0_dp) < 1.0e-14_dp, "wall: k_n of r and m")
    if (allocated(error)) return
    ! without per_contact: the nominal radius's, not the pair's
    call scene_set_materials(sc, [1, 1], mat, code_convention%liggghts_hooke, 0.5_dp, status, impact_velocity=v)
    call contact_values(sc, 0, 1, 2, 1.0e-4_dp, f_n, k)
    call check(error, abs(k(1)/pair%k_n - 1.0_dp) > 1.0e-3_dp .and. .not. sc%hooke_per_contact, &
      "nominal without per_contact")
  end subroutine test_hooke_per_contact

  !> The report names the script and compares its timestep with the exact
  !> limit (a_hertz: 1e-6 s against 4.24e-5 s, Lanczos at 1e-10 for the
  !> 9 digits compared; the README's example, its figures to the 10 digits
  !> printed: the same library on the same file).
  subroutine test_report(error)
    type(error_type), allocatable, intent(out) :: error
    character(len=:), allocatable :: stdout, stderr, text
    type(result_group_type) :: fields
    real(dp) :: limits(3), timestep, ratio
    integer :: rc, ios, line
    call write_file(work_dir//"/script_report.nml", [character(len=200) :: "&scene", "  dim = 3", &
      "  eigen_tolerance = 1e-10", &
      "  snapshot_file = '../../"//states//"a_hertz.dump'", &
      "  liggghts_script = '../../"//inputs//"in.export_a_hertz'", "/"])
    call run_app(work_dir//"/script_report.nml", rc, stdout, stderr)
    call check(error, rc == 0, "runs: "//stderr)
    if (allocated(error)) return
    call check(error, index(stdout, "script: "//work_dir//"/../../"//inputs//"in.export_a_hertz: liggghts_hertz, " &
      //"1 atom type, 6 primitive walls of type 1, restitution 0.5, tangential_damping on") > 0 .and. &
      index(stdout, "your script's timestep 1e-6 s (line 25) is 0.0235767") > 0 .and. &
      index(stdout, "times the exact limit 4.24146877e-5 s") > 0 .and. index(stdout, "it is stable") > 0, &
      "the script's lines: "//stdout)
    if (allocated(error)) return
    ! a script of its own: the export script included, a variable's timestep
    ! above the limit (5e-5 s against 4.24e-5 s)
    call write_file(work_dir//"/in.unstable", [character(len=200) :: "variable dt equal 2*2.5e-5", &
      "include ../../"//inputs//"in.export_a_hertz", "timestep ${dt}"])
    call write_file(work_dir//"/script_report.nml", [character(len=200) :: "&scene", "  dim = 3", &
      "  eigen_tolerance = 1e-10", &
      "  snapshot_file = '../../"//states//"a_hertz.dump'", "  liggghts_script = 'in.unstable'", "/"])
    ! (the included script's timestep, named with its file, is replaced by line 3's)
    call run_app(work_dir//"/script_report.nml", rc, stdout, stderr)
    call check(error, rc == 0 .and. index(stdout, "your script's timestep 5e-5 s (line 3) is 1.178836924 " &
      //"times the exact limit 4.24146877e-5 s") > 0 .and. index(stdout, "it is not stable: lower it to " &
      //"3.817321893e-5 s") > 0, "an unstable timestep: "//stdout//stderr)
    if (allocated(error)) return
    ! the same in &script_result: the timestep, its line, and its ratio to
    ! &scene_result's damped limit (the same doubles divided: to rounding)
    call run_limits(error, work_dir//"/script_report.nml", limits, stdout)
    if (allocated(error)) return
    call read_file(work_dir//"/script_report.nml.out", text)
    call read_group(text, "script_result", fields, ios)
    if (ios == 0) call take(fields, "timestep", timestep, ios)
    if (ios == 0) call take(fields, "timestep_line", line, ios)
    if (ios == 0) call take(fields, "timestep_ratio", ratio, ios)
    call check(error, ios == 0 .and. timestep == 5.0e-5_dp .and. line == 3 .and. &
      abs(ratio - 5.0e-5_dp/limits(2)) <= 4*epsilon(1.0_dp)*ratio .and. abs(ratio - 1.178836924_dp) < 1e-9_dp, &
      "&script_result: "//text)
    if (allocated(error)) return
    ! the timestep of an included script is named with its file
    call write_file(work_dir//"/in.unstable", [character(len=200) :: "include ../../"//inputs//"in.export_a_hertz"])
    call run_app(work_dir//"/script_report.nml", rc, stdout, stderr)
    call check(error, rc == 0 .and. index(stdout, "your script's timestep 1e-6 s ("//work_dir//"/../../"//inputs// &
      "in.export_a_hertz: line 25) is 0.02357673849") > 0, "an included script's timestep: "//stdout//stderr)
    if (allocated(error)) return
    ! the README's example: LIGGGHTS' pour (two types, periodic in x and y, a
    ! floor) from its own input script
    call run_app("example/snapshot_liggghts_script.nml", rc, stdout, stderr)
    call check(error, rc == 0 .and. index(stdout, "periodic yes") > 0 .and. index(stdout, "2 atom types, " &
      //"1 primitive wall of type 1, restitution 0.9") > 0 .and. index(stdout, "your script's timestep 2e-6 s " &
      //"(line 21) is 0.02574364345 times the exact limit 7.768908096e-5 s") > 0 .and. &
      index(stdout, "recommended dt = 6.992017286e-5 s") > 0, "the README's example: "//stdout//stderr)
  end subroutine test_report

  !> Run a deck; expect exit 2 and one line on stderr starting with `start`.
  subroutine expect_refused(error, lines, start)
    type(error_type), allocatable, intent(out) :: error
    character(len=*), intent(in) :: lines(:), start
    character(len=:), allocatable :: stdout, stderr
    integer :: rc
    call write_file(work_dir//"/script_bad.nml", lines)
    call run_app(work_dir//"/script_bad.nml", rc, stdout, stderr)
    call check(error, rc == 2 .and. index(stderr, "demstep: "//start) == 1 .and. &
      index(stderr, new_line("a")) == len(stderr), "exit 2, one line starting '"//start//"': "//stderr)
  end subroutine expect_refused

  subroutine test_refused(error)
    type(error_type), allocatable, intent(out) :: error
    character(len=*), parameter :: deck = work_dir//"/script_bad.nml"
    character(len=*), parameter :: script = work_dir//"/in.bad"
    character(len=*), parameter :: prefix = deck//": &scene: liggghts_script: "
    character(len=*), parameter :: hertz = "units si"//nl//"fix m1 all property/global youngsModulus " &
      //"peratomtype 1e7"//nl//"fix m2 all property/global poissonsRatio peratomtype 0.3"//nl// &
      "fix m3 all property/global coefficientRestitution peratomtypepair 1 0.5"//nl// &
      "pair_style gran model hertz tangential history"//nl
    character(len=200) :: lines(5)
    character(len=:), allocatable :: stdout, stderr
    integer :: rc
    lines = [character(len=200) :: "&scene", "  dim = 3", "  snapshot_file = '../../"//states//"a_hertz.dump'", &
      "  liggghts_script = 'in.bad'", "/"]
    ! the hand-written deck's dump has three types, the script one
    call write_file(script, [hertz])
    call expect_refused(error, [character(len=200) :: lines(1:2), "  snapshot_file = '../../"//decks// &
      "a_hertz.dump'", lines(4:5)], prefix//work_dir//"/in.bad: line 2: fix property/global: youngsModulus " &
      //"gives 1 atom type, the snapshot's particle 1 is of type 3")
    if (allocated(error)) return
    ! a periodic script for a walled box's dump
    call write_file(script, ["boundary p p f"//nl//hertz])
    call expect_refused(error, lines, prefix//work_dir//"/in.bad: line 1: boundary: the periodic axes differ " &
      //"from the snapshot's box (periodic: none)")
    if (allocated(error)) return
    ! a lone plane without create_box: the side the particles are on, or
    ! refused when they lie on both
    call write_file(script, [hertz//"fix w all wall/gran model hertz tangential history primitive type 1 " &
      //"zplane 0.0"])
    call write_file(deck, lines)
    call run_app(deck, rc, stdout, stderr)
    call check(error, rc == 0 .and. index(stdout, "1 primitive wall of type 1") > 0 .and. &
      index(stdout, "effects: contacts damping walls rotation") > 0, "a floor below the particles: "//stderr)
    if (allocated(error)) return
    call write_file(script, [hertz//"fix w all wall/gran model hertz tangential history primitive type 1 " &
      //"zplane 0.01"])
    call expect_refused(error, lines, prefix//work_dir//"/in.bad: line 6: fix wall/gran: wall 'w': the " &
      //"script does not tell its side")
    if (allocated(error)) return
    ! a command the reader does not know
    call write_file(script, [hertz//"fix ts all check/timestep/gran 1 0.1 0.1"//nl//"frobnicate 3"])
    call expect_refused(error, lines, prefix//work_dir//"/in.bad: line 7: frobnicate: unknown command")
    if (allocated(error)) return
    ! a model demstep does not reproduce
    call write_file(script, [hertz//"fix w all wall/gran model hertz/stiffness tangential history primitive " &
      //"type 1 zplane 0"])
    call expect_refused(error, lines, prefix//work_dir//"/in.bad: line 6: fix wall/gran: model 'hertz/stiffness'")
    if (allocated(error)) return
    ! a 2D scene for a 3D script
    call write_file(script, ["dimension 3"//nl//hertz])
    call expect_refused(error, [character(len=200) :: "&scene", "  dim = 2", lines(3:5)], &
      prefix//work_dir//"/in.bad: line 1: dimension: the script is 3D, the scene 2D")
    if (allocated(error)) return
    ! the script gives the materials: the deck's own are refused
    call write_file(script, [hertz])
    call expect_refused(error, [character(len=200) :: lines(1:4), "  young = 1e7", "/"], &
      prefix//"give either liggghts_script or young, not both")
    if (allocated(error)) return
    ! a missing script
    call expect_refused(error, [character(len=200) :: lines(1:3), "  liggghts_script = 'in.none'", "/"], &
      prefix//work_dir//"/in.none: no such file")
    if (allocated(error)) return
    ! a script needs the snapshot
    call expect_refused(error, [character(len=200) :: lines(1:2), "  particles_file = 'p.txt'", lines(4:5)], &
      deck//": &scene: snapshot_file: required with liggghts_script")
  end subroutine test_refused

end module test_liggghts_scenes
