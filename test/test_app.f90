!> End-to-end tests of the demstep executable, run through execute_command_line.
module test_app
  use testdrive, only: new_unittest, unittest_type, error_type, check, test_failed, skip_test
  use demstep
  use demstep_kinds, only: pi
  use test_support, only: count_lines, remove, run_app, write_file, read_file, file_exists, work_dir, real_str
  use demstep_results, only: result_group_type
  use test_support, only: read_group, take
  implicit none
  private
  public :: collect_app

  character(len=*), parameter :: deck = work_dir//"/deck.nml"
  character(len=*), parameter :: out = work_dir//"/out.nml"

contains

  subroutine collect_app(testsuite)
    type(unittest_type), allocatable, intent(out) :: testsuite(:)
    testsuite = [ &
      new_unittest("paper example: report and result namelist", test_paper_example), &
      new_unittest("result namelist reads back into Fortran", test_read_back), &
      new_unittest("beyond the limit is reported, not an error", test_unstable), &
      new_unittest("--namelist, --template, --help, --version", test_options), &
      new_unittest("missing or unreadable file", test_bad_file), &
      new_unittest("unknown variable, wrong type, no value", test_bad_variables), &
      new_unittest("no known group; unterminated group", test_bad_groups), &
      new_unittest("out-of-domain values", test_bad_values), &
      new_unittest("bad command lines", test_bad_usage), &
      new_unittest("-o: never the deck, links kept, long names, directories", test_output_files), &
      new_unittest("&harmonic_error: results read back, broadcast", test_harmonic_group), &
      new_unittest("&harmonic_error: each bad input", test_harmonic_bad), &
      new_unittest("&simulated_stiffness: the seed's setting read back", test_stiffness_group), &
      new_unittest("&simulated_stiffness: each bad input", test_stiffness_bad), &
      new_unittest("&scene: the chain example read back", test_scene_group), &
      new_unittest("&scene: tables, and each bad input", test_scene_bad), &
      new_unittest("&contact_error: worst case and given onsets read back", test_contact_group), &
      new_unittest("&accuracy_cost: table, result, CSV and figure", test_cost_group), &
      new_unittest("&accuracy_cost without gnuplot: CSV and a note", test_cost_no_gnuplot), &
      new_unittest("&contact_error, &accuracy_cost: each bad input", test_accuracy_bad), &
      new_unittest("the group table: defaults as the template says them", test_table_defaults), &
      new_unittest("the group table: capacities and the either-or rules", test_table_rules), &
      new_unittest("&accuracy_cost: the paper's E at lambda, N from the library", test_cost_harmonic) &
      ]
  end subroutine collect_app

  subroutine test_paper_example(error)
    type(error_type), allocatable, intent(out) :: error
    integer :: rc
    character(len=:), allocatable :: stdout, stderr
    call remove(out)
    call run_app("example/paper.nml -o "//out, rc, stdout, stderr)
    call check(error, rc, 0, message="exit status; stderr: "//stderr)
    if (allocated(error)) return
    call check(error, len(stderr), 0, message="nothing on stderr")
    if (allocated(error)) return
    call check(error, index(stdout, "restitution") > 0 .and. index(stdout, "&solver") > 0, &
      "report shows the contact and the skipped solver group")
    if (allocated(error)) return
    call check(error, file_exists(out), "output file written")
  end subroutine test_paper_example

  subroutine test_read_back(error)
    type(error_type), allocatable, intent(out) :: error
    integer :: rc, unit, ios
    character(len=:), allocatable :: stdout, stderr
    real(dp) :: period, omega, dt_critical, dt, n_per_period, growth_factor, theta, &
      period_numerical, contact_time, restitution, max_overlap
    integer(i8) :: contact_steps
    logical :: stable
    real(dp) :: dt_recommended
    type(result_group_type) :: system_result_fields
    type(discrete_contact_type) :: contact
    type(spring_type) :: unit_spring
    type(demstep_status_type) :: status
    call write_file(deck, [character(len=80) :: "&other x = 1 /", &
      "&system mass = 2.0, stiffness = 50.0, velocity = 3.0, dt = 0.1 /"])
    call remove(out)
    call run_app(deck//" --output "//out, rc, stdout, stderr)
    call check(error, rc, 0, message="exit status; stderr: "//stderr)
    if (allocated(error)) return
    open(newunit=unit, file=out, status="old", action="read")
    call read_group(unit, "system_result", system_result_fields, ios)
    if (ios == 0) call take(system_result_fields, "dt_recommended", dt_recommended, ios)
    if (ios == 0) call take(system_result_fields, "period", period, ios)
    if (ios == 0) call take(system_result_fields, "omega", omega, ios)
    if (ios == 0) call take(system_result_fields, "dt_critical", dt_critical, ios)
    if (ios == 0) call take(system_result_fields, "dt", dt, ios)
    if (ios == 0) call take(system_result_fields, "n_per_period", n_per_period, ios)
    if (ios == 0) call take(system_result_fields, "stable", stable, ios)
    if (ios == 0) call take(system_result_fields, "growth_factor", growth_factor, ios)
    if (ios == 0) call take(system_result_fields, "theta", theta, ios)
    if (ios == 0) call take(system_result_fields, "period_numerical", period_numerical, ios)
    if (ios == 0) call take(system_result_fields, "contact_steps", contact_steps, ios)
    if (ios == 0) call take(system_result_fields, "contact_time", contact_time, ios)
    if (ios == 0) call take(system_result_fields, "restitution", restitution, ios)
    if (ios == 0) call take(system_result_fields, "max_overlap", max_overlap, ios)
    close(unit)
    call check(error, ios, 0, message="read(nml=system_result)")
    if (allocated(error)) return
    ! omega = 5; values must round-trip to the last bit the runtime writes
    call check(error, period, 2.0_dp*pi/5.0_dp, thr=2*epsilon(1.0_dp), rel=.true., message="period")
    if (allocated(error)) return
    call check(error, dt_critical, 0.4_dp, thr=2*epsilon(1.0_dp), rel=.true., message="dt_critical")
    if (allocated(error)) return
    call check(error, n_per_period, 4.0_dp*pi, thr=4*epsilon(1.0_dp), rel=.true., message="N")
    if (allocated(error)) return
    call check(error, stable, .true.)
    if (allocated(error)) return
    call check(error, theta, 2.0_dp*asin(0.25_dp), thr=2*epsilon(1.0_dp), rel=.true., message="theta")
    if (allocated(error)) return
    ! the unit spring at dt = 0.5: omega dt = 0.5 as in the app (omega = 5, dt = 0.1)
    call new_spring(unit_spring, 1.0_dp, 1.0_dp, status)
    call spring_contact(unit_spring, 0.5_dp, contact, status)
    call check(error, contact_steps, contact%steps, message="contact steps")
    if (allocated(error)) return
    call check(error, restitution, contact%restitution, thr=0.0_dp, message="restitution")
    if (allocated(error)) return
    call check(error, max_overlap, contact%max_overlap*3.0_dp/5.0_dp, thr=2*epsilon(1.0_dp), &
      rel=.true., message="max overlap scaled by v0/omega")
  end subroutine test_read_back

  subroutine test_unstable(error)
    type(error_type), allocatable, intent(out) :: error
    integer :: rc, unit, ios
    character(len=:), allocatable :: stdout, stderr
    real(dp) :: period, omega, dt_critical, dt, n_per_period, growth_factor
    logical :: stable
    real(dp) :: dt_recommended
    type(result_group_type) :: system_result_fields
    call write_file(deck, [character(len=60) :: "&system mass=1, stiffness=1, n_per_period=3 /"])
    call remove(out)
    call run_app(deck//" -o "//out, rc, stdout, stderr)
    call check(error, rc, 0, message="exit status; stderr: "//stderr)
    if (allocated(error)) return
    open(newunit=unit, file=out, status="old", action="read")
    call read_group(unit, "system_result", system_result_fields, ios)
    if (ios == 0) call take(system_result_fields, "dt_recommended", dt_recommended, ios)
    if (ios == 0) call take(system_result_fields, "period", period, ios)
    if (ios == 0) call take(system_result_fields, "omega", omega, ios)
    if (ios == 0) call take(system_result_fields, "dt_critical", dt_critical, ios)
    if (ios == 0) call take(system_result_fields, "dt", dt, ios)
    if (ios == 0) call take(system_result_fields, "n_per_period", n_per_period, ios)
    if (ios == 0) call take(system_result_fields, "stable", stable, ios)
    if (ios == 0) call take(system_result_fields, "growth_factor", growth_factor, ios)
    close(unit)
    call check(error, ios, 0, message="read back")
    if (allocated(error)) return
    call check(error, stable, .false.)
    if (allocated(error)) return
    call check(error, growth_factor > 1.0_dp, "growth factor above 1")
    if (allocated(error)) return
    call check(error, index(stdout, "NO") > 0, "report says unstable")
  end subroutine test_unstable

  subroutine test_options(error)
    type(error_type), allocatable, intent(out) :: error
    integer :: rc, unit, ios
    character(len=:), allocatable :: stdout, stderr, manifest
    real(dp) :: period, omega, dt_critical
    real(dp) :: dt_recommended
    type(result_group_type) :: system_result_fields
    call write_file(deck, [character(len=60) :: "&system mass=4, stiffness=1 /"])
    call run_app(deck//" --namelist", rc, stdout, stderr)
    call check(error, rc, 0, message="--namelist")
    if (allocated(error)) return
    call read_group(stdout, "system_result", system_result_fields, ios)
    if (ios == 0) call take(system_result_fields, "dt_recommended", dt_recommended, ios)
    if (ios == 0) call take(system_result_fields, "period", period, ios)
    if (ios == 0) call take(system_result_fields, "omega", omega, ios)
    if (ios == 0) call take(system_result_fields, "dt_critical", dt_critical, ios)
    call check(error, ios, 0, message="stdout of --namelist reads as a namelist")
    if (allocated(error)) return
    call check(error, dt_critical, 4.0_dp, thr=2*epsilon(1.0_dp), rel=.true., message="2 sqrt(M/K)")
    if (allocated(error)) return
    ! the template is itself a valid input
    call run_app("--template", rc, stdout, stderr)
    call check(error, rc, 0, message="--template")
    if (allocated(error)) return
    open(newunit=unit, file=deck, status="replace", action="write")
    write(unit, '(a)') stdout
    close(unit)
    ! in the scratch directory: the template's &accuracy_cost writes files there
    call run_app("deck.nml", rc, stdout, stderr, in_work_dir=.true.)
    call check(error, rc, 0, message="running the template: "//stderr)
    if (allocated(error)) return
    call run_app("--help", rc, stdout, stderr)
    call check(error, rc == 0 .and. index(stdout, "usage") > 0, "--help")
    if (allocated(error)) return
    call run_app("--version", rc, stdout, stderr)
    call check(error, rc == 0 .and. index(stdout, demstep_version_string) > 0, "--version")
    if (allocated(error)) return
    ! the version lives in fpm.toml; the Fortran constant must say the same
    call read_file("fpm.toml", manifest)
    call check(error, index(manifest, new_line("a")//'version = "'//demstep_version_string//'"') > 0, &
      "demstep_version_string equals fpm.toml's version")
  end subroutine test_options

  subroutine test_bad_file(error)
    type(error_type), allocatable, intent(out) :: error
    call expect_failure(error, work_dir//"/no-such-file.nml", &
      "demstep: "//work_dir//"/no-such-file.nml: no such file")
    if (allocated(error)) return
    ! a directory exists but cannot be read as a deck
    call expect_failure(error, work_dir, "demstep: "//work_dir//": ")
  end subroutine test_bad_file

  subroutine test_bad_variables(error)
    type(error_type), allocatable, intent(out) :: error
    call expect_bad(error, "&system mass = 1, stifness = 2 /", "&system: stifness: unknown variable")
    if (allocated(error)) return
    call expect_bad(error, "&system mass = abc, stiffness = 2 /", &
      "&system: mass: cannot read 'abc' as a real number")
    if (allocated(error)) return
    call expect_bad(error, "&system mass = 1 2, stiffness = 2 /", "&system: mass: cannot read")
    if (allocated(error)) return
    call expect_bad(error, "&system mass = .true., stiffness = 2 /", "&system: mass: cannot read")
    if (allocated(error)) return
    call expect_bad(error, "&system mass = , stiffness = 2 /", "&system: mass: no value given")
    if (allocated(error)) return
    call expect_bad(error, "&system stiffness = 2 /", "&system: mass: required")
    if (allocated(error)) return
    call expect_bad(error, "&system mass = 1, stiffness = 2, dashpot = 'sideways' /", &
      "&system: dashpot: unknown word 'sideways' (lagged, centred)")
  end subroutine test_bad_variables

  subroutine test_bad_groups(error)
    type(error_type), allocatable, intent(out) :: error
    call expect_bad(error, "&solver n = 1 /", "no demstep group in the file")
    if (allocated(error)) return
    call expect_bad(error, "&system mass = 1, stiffness = 2", "&system: line 1: group has no closing")
  end subroutine test_bad_groups

  subroutine test_bad_values(error)
    type(error_type), allocatable, intent(out) :: error
    ! the library's checks (new_spring, check_time_step, step_for_n_per_period)
    call expect_bad(error, "&system mass = 0, stiffness = 2 /", "&system: mass: must be finite and > 0")
    if (allocated(error)) return
    call expect_bad(error, "&system mass = -1, stiffness = 2 /", "&system: mass: must be finite and > 0")
    if (allocated(error)) return
    call expect_bad(error, "&system mass = 1, stiffness = 0 /", "&system: stiffness: must be finite and > 0")
    if (allocated(error)) return
    call expect_bad(error, "&system mass = NaN, stiffness = 2 /", &
      "&system: mass: must be finite and > 0")
    if (allocated(error)) return
    call expect_bad(error, "&system mass = 1, stiffness = Inf /", &
      "&system: stiffness: must be finite and > 0")
    if (allocated(error)) return
    call expect_bad(error, "&system mass = 1, stiffness = 2, damping_ratio = -0.1 /", &
      "&system: damping_ratio: must be finite and >= 0")
    if (allocated(error)) return
    call expect_bad(error, "&system mass = 1, stiffness = 2, dt = 0 /", "&system: dt: must be in [")
    if (allocated(error)) return
    call expect_bad(error, "&system mass = 1, stiffness = 2, dt = -1e-3 /", "&system: dt: must be in [")
    if (allocated(error)) return
    call expect_bad(error, "&system mass = 1, stiffness = 2, n_per_period = 0 /", &
      "&system: n_per_period: must be in [")
    if (allocated(error)) return
    call expect_bad(error, "&system mass = 1, stiffness = 2, dt = 1, n_per_period = 9 /", &
      "&system: dt: give either dt or n_per_period")
  end subroutine test_bad_values

  subroutine test_bad_usage(error)
    type(error_type), allocatable, intent(out) :: error
    call expect_failure(error, "", "demstep: no input file")
    if (allocated(error)) return
    call expect_failure(error, "--frobnicate x.nml", "demstep: unknown option '--frobnicate'")
    if (allocated(error)) return
    call expect_failure(error, "example/paper.nml -o", "demstep: option -o needs a file name")
  end subroutine test_bad_usage

  subroutine test_output_files(error)
    type(error_type), allocatable, intent(out) :: error
    integer :: rc, cs, es
    character(len=:), allocatable :: stdout, stderr, before, after, long, listing
    character(len=*), parameter :: paper = "example/paper.nml"
    ! -o naming the input deck, directly or through a link, is refused; the deck stays
    call write_file(deck, [character(len=80) :: "&system mass = 0.01, stiffness = 1e5 /"])
    call read_file(deck, before)
    call run_app(deck//" -o "//deck, rc, stdout, stderr)
    call check(error, rc, 2, message="-o equal to the input: exit status")
    if (allocated(error)) return
    call check(error, index(stderr, "demstep: "//deck//": is the input deck") == 1, &
      "one line naming the file: "//stderr)
    if (allocated(error)) return
    call execute_command_line("cd "//work_dir//" && rm -f deck_link.nml && ln -s deck.nml deck_link.nml", &
      exitstat=es, cmdstat=cs)
    call check(error, cs == 0 .and. es == 0, "ln -s")
    if (allocated(error)) return
    call run_app(deck//" -o "//work_dir//"/deck_link.nml", rc, stdout, stderr)
    call read_file(deck, after)
    call check(error, rc == 2 .and. after == before, "a link to the input is refused, the deck kept")
    if (allocated(error)) return
    ! an existing link as output: the file it points to gets the results, the link stays
    call execute_command_line("cd "//work_dir//" && rm -rf linked && mkdir linked && " &
      //"touch linked/r.nml && rm -f r_link.nml && ln -s linked/r.nml r_link.nml", exitstat=es, cmdstat=cs)
    call run_app(paper//" -o "//work_dir//"/r_link.nml", rc, stdout, stderr)
    call check(error, rc, 0, message="-o a link: exit status; stderr: "//stderr)
    if (allocated(error)) return
    call read_file(work_dir//"/linked/r.nml", after)
    call check(error, index(after, "&SYSTEM_RESULT") == 1, "the link's target holds the results")
    if (allocated(error)) return
    call execute_command_line("test -L "//work_dir//"/r_link.nml", exitstat=es, cmdstat=cs)
    call check(error, cs == 0 .and. es == 0, "the link is still a link")
    if (allocated(error)) return
    ! a name of the longest length a directory entry may have (255) is written
    long = repeat("r", 251)//".nml"
    call run_app(paper//" -o "//work_dir//"/"//long, rc, stdout, stderr)
    call check(error, rc == 0 .and. file_exists(work_dir//"/"//long), &
      "a 255-character name is written; stderr: "//stderr)
    if (allocated(error)) return
    call execute_command_line("rm -f "//work_dir//"/"//long, exitstat=es, cmdstat=cs)
    ! a directory as output: exit 1, one line, nothing left behind
    call run_app(paper//" -o "//work_dir//"/linked", rc, stdout, stderr)
    call check(error, rc == 1 .and. index(stderr, "is a directory") > 0, &
      "a directory is not an output file: "//stderr)
    if (allocated(error)) return
    call execute_command_line("ls -a "//work_dir//" "//work_dir//"/linked > "//work_dir//"/listing", &
      exitstat=es, cmdstat=cs)
    call read_file(work_dir//"/listing", listing)
    call check(error, index(listing, ".tmp") == 0, "no temporary left: "//listing)
  end subroutine test_output_files

  subroutine test_harmonic_group(error)
    type(error_type), allocatable, intent(out) :: error
    integer :: rc, unit, ios, i, stat_lib
    character(len=:), allocatable :: stdout, stderr
    real(dp) :: n_per_period(3), lambda(3), n_steps(3), e(3), e_lib
    integer :: status(3)
    type(result_group_type) :: harmonic_error_result_fields
    call write_file(deck, [character(len=80) :: "&solver dt = 1e-5 /", &
      "&harmonic_error n_per_period = 10.0, 20.0, 1000.0,", &
      "  lambda = 0.9, steps_fraction = 0.5 /"])
    call remove(out)
    call run_app(deck//" -o "//out, rc, stdout, stderr)
    call check(error, rc, 0, message="exit status; stderr: "//stderr)
    if (allocated(error)) return
    open(newunit=unit, file=out, status="old", action="read")
    call read_group(unit, "harmonic_error_result", harmonic_error_result_fields, ios)
    if (ios == 0) call take(harmonic_error_result_fields, "n_per_period", n_per_period, ios)
    if (ios == 0) call take(harmonic_error_result_fields, "lambda", lambda, ios)
    if (ios == 0) call take(harmonic_error_result_fields, "n_steps", n_steps, ios)
    if (ios == 0) call take(harmonic_error_result_fields, "e", e, ios)
    if (ios == 0) call take(harmonic_error_result_fields, "status", status, ios)
    close(unit)
    call check(error, ios, 0, message="read(nml=harmonic_error_result)")
    if (allocated(error)) return
    do i = 1, 3
      call harmonic_error(n_per_period(i), 0.9_dp, 0.5_dp*n_per_period(i), e_lib, stat_lib)
      call check(error, lambda(i), 0.9_dp, thr=0.0_dp, message="lambda broadcast")
      if (allocated(error)) return
      call check(error, n_steps(i), 0.5_dp*n_per_period(i), thr=0.0_dp, message="n = N/2")
      if (allocated(error)) return
      call check(error, e(i), e_lib, thr=2*epsilon(1.0_dp), rel=.true., message="E as the library")
      if (allocated(error)) return
      call check(error, status(i), stat_lib, message="status")
      if (allocated(error)) return
    end do
    ! a pole is reported with its status, not as an error
    call write_file(deck, [character(len=80) :: &
      "&harmonic_error n_per_period = 10, lambda = 0.5, n_steps = 20 /"])
    call run_app(deck//" --namelist", rc, stdout, stderr)
    call check(error, rc == 0 .and. index(stdout, "STATUS=3") + index(stdout, "STATUS= 3") > 0, &
      "pole status in the result: "//stdout)
  end subroutine test_harmonic_group

  subroutine test_harmonic_bad(error)
    type(error_type), allocatable, intent(out) :: error
    character(len=*), parameter :: g = "&harmonic_error "
    call expect_bad(error, g//"n_per_period = 10, lambda = 0.0, steps_fraction = 0.5 /", &
      "&harmonic_error: lambda: element 1 (n_per_period = 10, lambda = 0, n = 5): must be finite and > 0")
    if (allocated(error)) return
    call expect_bad(error, g//"n_per_period = 10, 20, lambda = 0.9, -0.9, n_steps = 5 /", &
      "&harmonic_error: lambda: element 2 (n_per_period = 20, lambda = -0.9, n = 5): must be finite and > 0")
    if (allocated(error)) return
    call expect_bad(error, g//"n_per_period = 0, lambda = 0.9, steps_fraction = 0.5 /", &
      "&harmonic_error: n_per_period: element 1 (n_per_period = 0, lambda = 0.9, n = 0): must be finite " &
      //"and > 0")
    if (allocated(error)) return
    call expect_bad(error, g//"n_per_period = 10, lambda = 0.9, n_steps = 0.5 /", &
      "&harmonic_error: n_steps: element 1 (n_per_period = 10, lambda = 0.9, n = 0.5): n must be in " &
      //"[1, 1e12], got 0.5")
    if (allocated(error)) return
    call expect_bad(error, g//"n_per_period = 10, 20, 30, lambda = 0.9, 0.8, n_steps = 5 /", &
      "&harmonic_error: lambda: arrays of different lengths (n_per_period: 3, lambda: 2")
    if (allocated(error)) return
    call expect_bad(error, g//"n_per_period = 10, lambda = 0.9, n_steps = 5, steps_fraction = 0.5 /", &
      "&harmonic_error: n_steps: give either n_steps or steps_fraction")
    if (allocated(error)) return
    call expect_bad(error, g//"n_per_period = 10, lambda = 0.9 /", &
      "&harmonic_error: n_steps: give either n_steps or steps_fraction")
    if (allocated(error)) return
    call expect_bad(error, g//"n_per_period = 10, lambda(2) = 0.9, n_steps = 5 /", &
      "&harmonic_error: lambda(1): no value")
    if (allocated(error)) return
    call expect_bad(error, g//"lambda = 0.9, n_steps = 5 /", "&harmonic_error: n_per_period: required")
    if (allocated(error)) return
    call expect_bad(error, g//"n_per_period = 10, lambda = 0.9, steps_fraction = 0.01 /", &
      "&harmonic_error: steps_fraction: element 1 (n_per_period = 10, lambda = 0.9, n = 0.1): n must be " &
      //"in [1, 1e12], got 0.1")
    if (allocated(error)) return
    call expect_bad(error, g//"n_per_period = 10, lambda = NaN, steps_fraction = 0.5 /", &
      "&harmonic_error: lambda: element 1 (n_per_period = 10, lambda = NaN, n = 5): must be finite and > 0")
    if (allocated(error)) return
    call expect_bad(error, g//"n_per_period = 10, lambda = abc, steps_fraction = 0.5 /", &
      "&harmonic_error: lambda: cannot read 'abc' as a list of real numbers")
  end subroutine test_harmonic_bad

  subroutine test_stiffness_group(error)
    type(error_type), allocatable, intent(out) :: error
    integer :: rc, unit, ios
    character(len=:), allocatable :: stdout, stderr
    real(dp) :: lambda(10), n_zero(10), n_lower(10), n_upper(10), n_pick(10)
    logical :: bounded(10)
    integer :: status(10), lambda_star_status, excluded
    real(dp) :: n_star, lambda_star, period, dt, stiffness_actual
    real(dp) :: dt_recommended
    type(result_group_type) :: simulated_stiffness_result_fields
    type(stiffness_input_type) :: input
    type(stiffness_result_type) :: result
    type(demstep_status_type) :: st
    integer :: i
    call remove(out)
    call run_app("example/stiffness.nml -o "//out, rc, stdout, stderr)
    call check(error, rc, 0, message="exit status; stderr: "//stderr)
    if (allocated(error)) return
    call check(error, index(stdout, "dt = T*/N*") > 0 .and. index(stdout, "K' = lambda*^2 K*") > 0, &
      "the report gives dt and K'")
    if (allocated(error)) return
    open(newunit=unit, file=out, status="old", action="read")
    call read_group(unit, "simulated_stiffness_result", simulated_stiffness_result_fields, ios)
    if (ios == 0) call take(simulated_stiffness_result_fields, "dt_recommended", dt_recommended, ios)
    if (ios == 0) call take(simulated_stiffness_result_fields, "lambda", lambda, ios)
    if (ios == 0) call take(simulated_stiffness_result_fields, "n_zero", n_zero, ios)
    if (ios == 0) call take(simulated_stiffness_result_fields, "n_lower", n_lower, ios)
    if (ios == 0) call take(simulated_stiffness_result_fields, "n_upper", n_upper, ios)
    if (ios == 0) call take(simulated_stiffness_result_fields, "bounded", bounded, ios)
    if (ios == 0) call take(simulated_stiffness_result_fields, "n_pick", n_pick, ios)
    if (ios == 0) call take(simulated_stiffness_result_fields, "status", status, ios)
    if (ios == 0) call take(simulated_stiffness_result_fields, "n_star", n_star, ios)
    if (ios == 0) call take(simulated_stiffness_result_fields, "lambda_star", lambda_star, ios)
    if (ios == 0) call take(simulated_stiffness_result_fields, "lambda_star_status", lambda_star_status, ios)
    if (ios == 0) call take(simulated_stiffness_result_fields, "period", period, ios)
    if (ios == 0) call take(simulated_stiffness_result_fields, "dt", dt, ios)
    if (ios == 0) call take(simulated_stiffness_result_fields, "stiffness_actual", stiffness_actual, ios)
    if (ios == 0) call take(simulated_stiffness_result_fields, "excluded", excluded, ios)
    close(unit)
    call check(error, ios, 0, message="read(nml=simulated_stiffness_result)")
    if (allocated(error)) return
    ! the same procedure through the library
    input%mass = 0.01_dp
    input%stiffness = 1.0e5_dp
    input%options%tolerance = 1.0e-3_dp
    input%lambdas = [(0.9_dp + (0.99_dp - 0.9_dp)*real(i, dp)/9.0_dp, i = 0, 9)]
    call simulated_stiffness(input, result, st)
    call check(error, n_star, result%n_star, thr=2*epsilon(1.0_dp), rel=.true., message="N*")
    if (allocated(error)) return
    call check(error, dt, result%dt, thr=2*epsilon(1.0_dp), rel=.true., message="dt")
    if (allocated(error)) return
    call check(error, stiffness_actual, result%stiffness_actual, thr=2*epsilon(1.0_dp), rel=.true., &
      message="K'")
    if (allocated(error)) return
    call check(error, all(status == 0) .and. lambda_star_status == 0 .and. excluded == 0, "statuses")
    if (allocated(error)) return
    call check(error, count(bounded), 8, message="lambda 0.98, 0.99: unbounded intervals")
  end subroutine test_stiffness_group

  subroutine test_stiffness_bad(error)
    type(error_type), allocatable, intent(out) :: error
    character(len=*), parameter :: g = "&simulated_stiffness mass = 0.01, stiffness = 1e5, "
    call expect_bad(error, g//"tolerance = 1.5, lambda = 0.9 /", &
      "&simulated_stiffness: tolerance: must be in (0, 1)")
    if (allocated(error)) return
    call expect_bad(error, g//"tolerance = 0, lambda = 0.9 /", "&simulated_stiffness: tolerance: must be in (0, 1)")
    if (allocated(error)) return
    call expect_bad(error, g//"tolerance = 1e-3, lambda = 0.9, 1.0 /", &
      "&simulated_stiffness: lambda: element 2 is 1; must be in (0, 1)")
    if (allocated(error)) return
    call expect_bad(error, g//"tolerance = 1e-3, lambda = 0.95, 0.9 /", &
      "&simulated_stiffness: lambda: the set must increase")
    if (allocated(error)) return
    call expect_bad(error, g//"tolerance = 1e-3 /", "&simulated_stiffness: lambda: give either lambda " &
      //"or lambda_min, lambda_max and lambda_count (one of them is required)")
    if (allocated(error)) return
    call expect_bad(error, g//"tolerance = 1e-3, lambda = 0.9, lambda_min = 0.8 /", &
      "&simulated_stiffness: lambda: give either")
    if (allocated(error)) return
    call expect_bad(error, g//"tolerance = 1e-3, lambda_min = 0.9, lambda_max = 0.8, lambda_count = 3 /", &
      "&simulated_stiffness: lambda_max: must be > lambda_min")
    if (allocated(error)) return
    call expect_bad(error, g//"tolerance = 1e-3, lambda = 0.9, 0.95, aggregate = 'weighted', weights = 1 /", &
      "&simulated_stiffness: weights: 1 given for 2 lambdas")
    if (allocated(error)) return
    call expect_bad(error, g//"tolerance = 1e-3, lambda = 0.9, 0.95, aggregate = 'weighted', weights = 1, -1 /", &
      "&simulated_stiffness: weights: element 2 is -1; must be finite and >= 0")
    if (allocated(error)) return
    call expect_bad(error, g//"tolerance = 1e-3, lambda = 0.9, steps = 'quarter' /", &
      "&simulated_stiffness: steps: unknown word 'quarter'")
    if (allocated(error)) return
    call expect_bad(error, g//"tolerance = 1e-3, lambda = 0.9, pick = 'best' /", &
      "&simulated_stiffness: pick: unknown word 'best'")
    if (allocated(error)) return
    call expect_bad(error, g//"tolerance = 1e-3, lambda = 0.9, aggregate = 'mode' /", &
      "&simulated_stiffness: aggregate: unknown word 'mode'")
    if (allocated(error)) return
    call expect_bad(error, g//"tolerance = 1e-3, lambda = 0.9, steps = 'fixed' /", &
      "&simulated_stiffness: n_steps: required with steps = 'fixed'")
    if (allocated(error)) return
    call expect_bad(error, "&simulated_stiffness stiffness = 1e5, tolerance = 1e-3, lambda = 0.9 /", &
      "&simulated_stiffness: mass: required")
  end subroutine test_stiffness_bad

  subroutine test_scene_group(error)
    type(error_type), allocatable, intent(out) :: error
    integer :: rc, unit, ios
    character(len=:), allocatable :: stdout, stderr
    integer :: n_particles, n_dof, n_springs, max_contacts
    real(dp) :: omega_max, dt_critical_eigen, dt_critical_bound, dt_contact_rule, &
      dt_critical_damped, damping_ratio_top, dt_used, energy_drift, max_overlap, dt_recommended
    integer(i8) :: steps
    logical :: eigen_computed, blew_up
    integer :: dof_per_particle
    logical :: rotation, tangential, periodic, prestress
    logical :: eigen_converged
    character(len=8) :: eigen_solver
    real(dp) :: eigen_tolerance, eigen_residual, omega_upper, dt_critical_safe
    logical :: damped_exact
    real(dp) :: dt_critical_damped_bound
    type(result_group_type) :: scene_result_fields
    call remove(out)
    call run_app("example/chain.nml -o "//out, rc, stdout, stderr)
    call check(error, rc, 0, message="exit status; stderr: "//stderr)
    if (allocated(error)) return
    open(newunit=unit, file=out, status="old", action="read")
    call read_group(unit, "scene_result", scene_result_fields, ios)
    if (ios == 0) call take(scene_result_fields, "n_particles", n_particles, ios)
    if (ios == 0) call take(scene_result_fields, "n_dof", n_dof, ios)
    if (ios == 0) call take(scene_result_fields, "n_springs", n_springs, ios)
    if (ios == 0) call take(scene_result_fields, "dof_per_particle", dof_per_particle, ios)
    if (ios == 0) call take(scene_result_fields, "rotation", rotation, ios)
    if (ios == 0) call take(scene_result_fields, "tangential", tangential, ios)
    if (ios == 0) call take(scene_result_fields, "periodic", periodic, ios)
    if (ios == 0) call take(scene_result_fields, "prestress", prestress, ios)
    if (ios == 0) call take(scene_result_fields, "omega_max", omega_max, ios)
    if (ios == 0) call take(scene_result_fields, "eigen_computed", eigen_computed, ios)
    if (ios == 0) call take(scene_result_fields, "eigen_converged", eigen_converged, ios)
    if (ios == 0) call take(scene_result_fields, "eigen_solver", eigen_solver, ios)
    if (ios == 0) call take(scene_result_fields, "eigen_tolerance", eigen_tolerance, ios)
    if (ios == 0) call take(scene_result_fields, "eigen_residual", eigen_residual, ios)
    if (ios == 0) call take(scene_result_fields, "omega_upper", omega_upper, ios)
    if (ios == 0) call take(scene_result_fields, "dt_critical_safe", dt_critical_safe, ios)
    if (ios == 0) call take(scene_result_fields, "dt_critical_eigen", dt_critical_eigen, ios)
    if (ios == 0) call take(scene_result_fields, "dt_critical_bound", dt_critical_bound, ios)
    if (ios == 0) call take(scene_result_fields, "dt_contact_rule", dt_contact_rule, ios)
    if (ios == 0) call take(scene_result_fields, "dt_critical_damped", dt_critical_damped, ios)
    if (ios == 0) call take(scene_result_fields, "damping_ratio_top", damping_ratio_top, ios)
    if (ios == 0) call take(scene_result_fields, "dt_used", dt_used, ios)
    if (ios == 0) call take(scene_result_fields, "steps", steps, ios)
    if (ios == 0) call take(scene_result_fields, "energy_drift", energy_drift, ios)
    if (ios == 0) call take(scene_result_fields, "max_overlap", max_overlap, ios)
    if (ios == 0) call take(scene_result_fields, "max_contacts", max_contacts, ios)
    if (ios == 0) call take(scene_result_fields, "blew_up", blew_up, ios)
    if (ios == 0) call take(scene_result_fields, "dt_recommended", dt_recommended, ios)
    if (ios == 0) call take(scene_result_fields, "damped_exact", damped_exact, ios)
    if (ios == 0) call take(scene_result_fields, "dt_critical_damped_bound", dt_critical_damped_bound, ios)
    close(unit)
    call check(error, ios, 0, message="read(nml=scene_result)")
    if (allocated(error)) return
    ! 10 free unit masses, k = 100, fixed ends: omega_max = 20 sin(10 pi/22)
    call check(error, omega_max, 20.0_dp*sin(10.0_dp*pi/22.0_dp), thr=1.0e-13_dp, rel=.true., &
      message="omega_max")
    if (allocated(error)) return
    call check(error, dt_critical_bound <= dt_critical_eigen .and. dt_contact_rule > dt_critical_eigen, &
      "bound below, contact rule above the exact limit")
    if (allocated(error)) return
    call check(error, dt_used, 2.0_dp*pi/omega_max/10.0_dp, thr=1.0e-14_dp, rel=.true., message="dt = T/10")
    if (allocated(error)) return
    ! undamped chain: 0.9 of the exact limit 2/omega_max (one multiplication)
    call check(error, dt_recommended, 0.9_dp*(2.0_dp/omega_max), thr=4*epsilon(1.0_dp), rel=.true., &
      message="dt_recommended")
    if (allocated(error)) return
    call check(error, index(stdout, "recommended dt = ") > 0, "the report ends with the recommended step")
    if (allocated(error)) return
    call check(error, .not. blew_up .and. energy_drift < 1.0e-9_dp, "a stable, conservative run")
    if (allocated(error)) return
    call check(error, n_dof == 10 .and. n_springs == 11 .and. steps > 0, "sizes")
    if (allocated(error)) return
    call run_app("example/lattice.nml", rc, stdout, stderr)
    call check(error, rc, 0, message="lattice from table files: "//stderr)
    if (allocated(error)) return
    call run_app("example/packing.nml", rc, stdout, stderr)
    call check(error, rc, 0, message="packing: "//stderr)
  end subroutine test_scene_group

  subroutine test_scene_bad(error)
    type(error_type), allocatable, intent(out) :: error
    character(len=*), parameter :: g = "&scene dim = 1, position = 0.0, 1.0, radius = 0.3, "
    call expect_bad(error, g//"mass = 1.0, bonds = 1, 2, k_bond = 1, effects = 'gravity', 'magnetism' /", &
      "&scene: effects: unknown effect 'magnetism'")
    if (allocated(error)) return
    call expect_bad(error, g//"mass = 1.0, -2.0, bonds = 1, 2, k_bond = 1 /", &
      "&scene: mass: particle 2: must be > 0")
    if (allocated(error)) return
    call expect_bad(error, "&scene dim = 1, position = 0.0, 1.0, radius = -0.3, mass = 1 /", &
      "&scene: radius: particle 1: must be > 0")
    if (allocated(error)) return
    ! the library's scene builders check the law, the bonds and gravity; the app names the variable
    call expect_bad(error, g//"mass = 1.0, k_normal = -1e4 /", "&scene: k_normal: must be > 0 and finite")
    if (allocated(error)) return
    call expect_bad(error, g//"mass = 1.0 /", "&scene: k_normal: must be > 0 and finite")
    if (allocated(error)) return
    call expect_bad(error, g//"mass = 1.0, k_normal = 1e4, k_tangential = -1.0 /", &
      "&scene: k_tangential: must be >= 0 and finite")
    if (allocated(error)) return
    call expect_bad(error, g//"mass = 1.0, k_normal = 1e4, kt_ratio = -0.5 /", &
      "&scene: kt_ratio: must be >= 0, got -0.5")
    if (allocated(error)) return
    call expect_bad(error, g//"mass = 1.0, law = 'hertz', e_star = 0.0 /", "&scene: e_star: must be > 0 and finite")
    if (allocated(error)) return
    call expect_bad(error, g//"mass = 1.0, law = 'hertz', e_star = 1e8, g_star = -1e7 /", &
      "&scene: g_star: must be >= 0 and finite")
    if (allocated(error)) return
    call expect_bad(error, g//"mass = 1.0, bonds = 1, 2, k_bond = 0, effects = 'none' /", &
      "&scene: k_bond: must be > 0 and finite")
    if (allocated(error)) return
    call expect_bad(error, g//"mass = 1.0, bonds = 1, 2, k_bond = 1, k_bond_tangential = -1, effects = 'none' /", &
      "&scene: k_bond_tangential: must be >= 0 and finite")
    if (allocated(error)) return
    call expect_bad(error, g//"mass = 1.0, bonds = 1, 2, k_bond = 1, effects = 'gravity', gravity = 1, 2 /", &
      "&scene: gravity: needs 1 finite components")
    if (allocated(error)) return
    call expect_bad(error, g//"mass = 1.0, k_normal = 1e4, hertz_linearization = 'impact', impact_velocity = -1 /", &
      "&scene: impact_velocity: the Hertz linearisation at impact needs a finite impact velocity > 0")
    if (allocated(error)) return
    call expect_bad(error, g//"mass = 1.0, bonds = 1, 2, k_bond = 1, effects = 'none', duration = 1, " &
      //"n_per_period = -5 /", &
      "&scene: n_per_period: must be finite and > 0")
    if (allocated(error)) return
    call expect_bad(error, g//"mass = 1.0, k_normal = 1e4, effects = 'contacts', 'damping', damping_ratio = -0.1 /", &
      "&scene: damping_ratio: must be in [0, 1e100]")
    if (allocated(error)) return
    call expect_bad(error, g//"mass = 1.0, bonds = 1, 3, k_bond = 1 /", &
      "&scene: bonds: bond 1 names a missing particle")
    if (allocated(error)) return
    call expect_bad(error, "&scene dim = 1, position = 0.0, 0.5, radius = 0.3, mass = 1, fixed = 1, 2 /", &
      "&scene: position: fixed particles 1 and 2 overlap")
    if (allocated(error)) return
    call expect_bad(error, g//"mass = 1.0, effects = 'none' /", "&scene: effects: the scene has no stiffness")
    if (allocated(error)) return
    call expect_bad(error, g//"mass = 1.0, bonds = 1, 2, k_bond = 1, effects = 'damping' /", &
      "&scene: damping_ratio: the 'damping' effect needs damping_ratio or restitution")
    if (allocated(error)) return
    call expect_bad(error, g//"mass = 1.0, bonds = 1, 2, k_bond = 1, effects = 'none', duration = 1 /", &
      "&scene: dt: a run (duration > 0) needs dt or n_per_period")
    if (allocated(error)) return
    call expect_bad(error, "&scene dim = 4, position = 0.0 /", "&scene: dim: must be 1, 2 or 3")
    if (allocated(error)) return
    ! table files: a malformed row is reported with its line number
    call write_file(work_dir//"/p.txt", [character(len=40) :: "# x vx m r fixed", "0.0 0.0 1.0 0.3 0", &
      "", "1.0 0.0 1.0 0.3", "2.0 0.0 1.0 0.3 0"])
    call expect_bad(error, "&scene dim = 1, particles_file = 'p.txt', bonds = 1, 2, k_bond = 1 /", &
      "&scene: particles_file: "//work_dir//"/p.txt: line 4: expected 5 numbers, found 4")
    if (allocated(error)) return
    call write_file(work_dir//"/p.txt", [character(len=40) :: "0.0 0.0 1.0 0.3 0", "1.0 0.0 one 0.3 0"])
    call expect_bad(error, "&scene dim = 1, particles_file = 'p.txt', bonds = 1, 2, k_bond = 1 /", &
      "&scene: particles_file: "//work_dir//"/p.txt: line 2: cannot read")
    if (allocated(error)) return
    call write_file(work_dir//"/p.txt", [character(len=40) :: "0.0 0.0 1.0 0.3 0", "1.0 0.0 1.0 0.3 0"])
    call write_file(work_dir//"/b.txt", [character(len=40) :: "1 2", "2 7"])
    call expect_bad(error, "&scene dim = 1, particles_file = 'p.txt', bonds_file = 'b.txt', k_bond = 1 /", &
      "&scene: bonds: bond 2 names a missing particle")
    if (allocated(error)) return
    call expect_bad(error, "&scene dim = 1, particles_file = 'nothere.txt' /", &
      "&scene: particles_file: "//work_dir//"/nothere.txt: no such file")
  end subroutine test_scene_bad

  subroutine test_contact_group(error)
    type(error_type), allocatable, intent(out) :: error
    integer :: rc, unit, ios, i
    character(len=:), allocatable :: stdout, stderr
    real(dp) :: n_per_period(3), onset(3), contact_time(3), restitution(3), max_overlap(3)
    real(dp) :: onset_contact_time(3), onset_restitution(3), onset_overlap(3)
    integer(i8) :: steps_in_contact(3)
    logical :: stable(3)
    type(result_group_type) :: contact_error_result_fields
    type(discrete_contact_type) :: c
    type(demstep_status_type) :: st
    real(dp) :: e
    ! given onsets, one N beyond the stability limit: computed and flagged
    call write_file(deck, [character(len=80) :: "&contact_error n_per_period = 3.0, 10.0, 50.0,", &
      "  onset = 0.5 /"])
    call remove(out)
    call run_app(deck//" -o "//out, rc, stdout, stderr)
    call check(error, rc, 0, message="exit status; stderr: "//stderr)
    if (allocated(error)) return
    open(newunit=unit, file=out, status="old", action="read")
    call read_group(unit, "contact_error_result", contact_error_result_fields, ios)
    if (ios == 0) call take(contact_error_result_fields, "n_per_period", n_per_period, ios)
    if (ios == 0) call take(contact_error_result_fields, "onset", onset, ios)
    if (ios == 0) call take(contact_error_result_fields, "steps_in_contact", steps_in_contact, ios)
    if (ios == 0) call take(contact_error_result_fields, "contact_time", contact_time, ios)
    if (ios == 0) call take(contact_error_result_fields, "restitution", restitution, ios)
    if (ios == 0) call take(contact_error_result_fields, "max_overlap", max_overlap, ios)
    if (ios == 0) call take(contact_error_result_fields, "onset_contact_time", onset_contact_time, ios)
    if (ios == 0) call take(contact_error_result_fields, "onset_restitution", onset_restitution, ios)
    if (ios == 0) call take(contact_error_result_fields, "onset_overlap", onset_overlap, ios)
    if (ios == 0) call take(contact_error_result_fields, "stable", stable, ios)
    close(unit)
    call check(error, ios, 0, message="read back")
    if (allocated(error)) return
    call check(error, .not. stable(1) .and. stable(2) .and. stable(3), "N = 3 flagged unstable")
    if (allocated(error)) return
    do i = 1, 3
      call contact_with_onset(n_per_period(i), 0.5_dp, c, st)
      call check(error, steps_in_contact(i) == c%steps .and. restitution(i) == c%restitution .and. &
        max_overlap(i) == c%max_overlap .and. contact_time(i) == c%contact_time, "as the library")
      if (allocated(error)) return
    end do
    call check(error, index(stdout, "beyond the stability limit") > 0, "the report flags it")
    if (allocated(error)) return
    ! worst case: reported with the onset attaining it
    call write_file(deck, [character(len=80) :: "&contact_error n_per_period = 20.0 /"])
    call run_app(deck//" --namelist", rc, stdout, stderr)
    call read_group(stdout, "contact_error_result", contact_error_result_fields, ios)
    if (ios == 0) call take(contact_error_result_fields, "n_per_period", n_per_period, ios)
    if (ios == 0) call take(contact_error_result_fields, "onset", onset, ios)
    if (ios == 0) call take(contact_error_result_fields, "steps_in_contact", steps_in_contact, ios)
    if (ios == 0) call take(contact_error_result_fields, "contact_time", contact_time, ios)
    if (ios == 0) call take(contact_error_result_fields, "restitution", restitution, ios)
    if (ios == 0) call take(contact_error_result_fields, "max_overlap", max_overlap, ios)
    if (ios == 0) call take(contact_error_result_fields, "onset_contact_time", onset_contact_time, ios)
    if (ios == 0) call take(contact_error_result_fields, "onset_restitution", onset_restitution, ios)
    if (ios == 0) call take(contact_error_result_fields, "onset_overlap", onset_overlap, ios)
    if (ios == 0) call take(contact_error_result_fields, "stable", stable, ios)
    call check(error, ios, 0, message="read --namelist")
    if (allocated(error)) return
    call contact_worst_case(20.0_dp, quantity_kind%restitution, c, e, st)
    call check(error, restitution(1), c%restitution, thr=0.0_dp, message="worst restitution")
    if (allocated(error)) return
    call check(error, onset_restitution(1), c%onset, thr=0.0_dp, message="its onset")
  end subroutine test_contact_group

  subroutine test_cost_group(error)
    type(error_type), allocatable, intent(out) :: error
    integer :: rc, unit, ios, i, st_gp, st_cmd
    character(len=:), allocatable :: stdout, stderr, csv
    real(dp) :: tolerances(2), n_per_period(2), dt(2), predicted_seconds(2), cost_per_particle_step, period
    integer(i8) :: steps(2)
    logical :: steps_saturated(2)
    integer :: status(2)
    real(dp) :: dt_recommended
    type(result_group_type) :: accuracy_cost_result_fields
    real(dp) :: n
    type(demstep_status_type) :: st
    call remove(work_dir//"/ac.csv")
    call remove(work_dir//"/ac.png")
    call remove(work_dir//"/ac.svg")
    call write_file(deck, [character(len=160) :: "&accuracy_cost quantity = 'overlap',", &
      "  tolerances = 1e-2, 1e-3, duration = 2.0, n_particles = 1000,", &
      "  mass = 0.01, stiffness = 1e5, cost_per_particle_step = 1e-7,", &
      "  csv = '"//work_dir//"/ac.csv', figure = '"//work_dir//"/ac' /"])
    call remove(out)
    call run_app(deck//" -o "//out, rc, stdout, stderr)
    call check(error, rc, 0, message="exit status; stderr: "//stderr)
    if (allocated(error)) return
    open(newunit=unit, file=out, status="old", action="read")
    call read_group(unit, "accuracy_cost_result", accuracy_cost_result_fields, ios)
    if (ios == 0) call take(accuracy_cost_result_fields, "dt_recommended", dt_recommended, ios)
    if (ios == 0) call take(accuracy_cost_result_fields, "tolerances", tolerances, ios)
    if (ios == 0) call take(accuracy_cost_result_fields, "n_per_period", n_per_period, ios)
    if (ios == 0) call take(accuracy_cost_result_fields, "dt", dt, ios)
    if (ios == 0) call take(accuracy_cost_result_fields, "steps", steps, ios)
    if (ios == 0) call take(accuracy_cost_result_fields, "steps_saturated", steps_saturated, ios)
    if (ios == 0) call take(accuracy_cost_result_fields, "predicted_seconds", predicted_seconds, ios)
    if (ios == 0) call take(accuracy_cost_result_fields, "status", status, ios)
    if (ios == 0) call take(accuracy_cost_result_fields, "cost_per_particle_step", cost_per_particle_step, ios)
    if (ios == 0) call take(accuracy_cost_result_fields, "period", period, ios)
    close(unit)
    call check(error, ios, 0, message="read back")
    if (allocated(error)) return
    do i = 1, 2
      call n_for_tolerance(quantity_kind%overlap, tolerances(i), n, st)
      call check(error, n_per_period(i), n, thr=0.0_dp, message="N as n_for_tolerance")
      if (allocated(error)) return
      call check(error, dt(i), period/n, thr=0.0_dp, message="dt = T/N")
      if (allocated(error)) return
      call check(error, steps(i), ceiling(2.0_dp/dt(i), i8), message="steps for the duration")
      if (allocated(error)) return
      call check(error, predicted_seconds(i), real(steps(i), dp)*1000.0_dp*1.0e-7_dp, thr=1.0e-15_dp, &
        rel=.true., message="predicted time")
      if (allocated(error)) return
    end do
    call check(error, index(stdout, "predicted time") > 0, "a table on stdout")
    if (allocated(error)) return
    call read_file(work_dir//"/ac.csv", csv)
    call check(error, index(csv, "n_per_period,steps_per_contact") == 1 .and. len(csv) > 1000, &
      "the CSV has its header and rows")
    if (allocated(error)) return
    ! without cmdstat a missing shell command would end the whole test program
    call execute_command_line("command -v gnuplot > /dev/null 2>&1", exitstat=st_gp, cmdstat=st_cmd)
    if (st_cmd /= 0 .or. st_gp /= 0) then
      call skip_test(error, "table and CSV checked; the PNG/SVG figure check is skipped " &
        //"(gnuplot is not installed)")
      return
    end if
    call check(error, file_exists(work_dir//"/ac.png") .and. file_exists(work_dir//"/ac.svg"), &
      "PNG and SVG figures (gnuplot is installed)")
    if (allocated(error)) return
    call check(error, .not. file_exists(work_dir//"/ac.png.tmp"), "no temporary left")
  end subroutine test_cost_group

  subroutine test_cost_no_gnuplot(error)
    type(error_type), allocatable, intent(out) :: error
    integer :: rc
    character(len=:), allocatable :: stdout, stderr
    call remove(work_dir//"/ng.csv")
    call remove(work_dir//"/ng.png")
    call write_file(deck, [character(len=160) :: "&accuracy_cost quantity = 'period',", &
      "  tolerances = 1e-3, duration = 1.0, n_particles = 10,", &
      "  mass = 1, stiffness = 1, cost_per_particle_step = 1e-7,", &
      "  csv = '"//work_dir//"/ng.csv', figure = '"//work_dir//"/ng' /"])
    call run_app(deck, rc, stdout, stderr, env="PATH=/nonexistent")
    call check(error, rc, 0, message="exit status; stderr: "//stderr)
    if (allocated(error)) return
    call check(error, index(stdout, "gnuplot not found") > 0, "says so in one line")
    if (allocated(error)) return
    call check(error, file_exists(work_dir//"/ng.csv") .and. .not. file_exists(work_dir//"/ng.png"), &
      "CSV written, no figure")
  end subroutine test_cost_no_gnuplot

  subroutine test_accuracy_bad(error)
    type(error_type), allocatable, intent(out) :: error
    character(len=*), parameter :: g = "&accuracy_cost duration = 1, n_particles = 10, mass = 1, " &
      //"stiffness = 1, cost_per_particle_step = 1e-7, "
    call expect_bad(error, "&contact_error n_per_period = 10, onset = 1.5 /", &
      "&contact_error: onset: element 1 is 1.5; must be in (0, 1]")
    if (allocated(error)) return
    call expect_bad(error, "&contact_error n_per_period = 10, onset = 0 /", &
      "&contact_error: onset: element 1 is 0; must be in (0, 1]")
    if (allocated(error)) return
    call expect_bad(error, "&contact_error n_per_period = 0 /", &
      "&contact_error: n_per_period: element 1 is 0; must be finite and >= 6.289e-50")
    if (allocated(error)) return
    call expect_bad(error, g//"quantity = 'speed', tolerances = 1e-3 /", &
      "&accuracy_cost: quantity: unknown word 'speed'")
    if (allocated(error)) return
    call expect_bad(error, g//"quantity = 'period', tolerances = 1e-3, 0 /", &
      "&accuracy_cost: tolerances: element 2 is 0; must be finite and > 0")
    if (allocated(error)) return
    call expect_bad(error, g//"quantity = 'period', tolerances = -1e-3 /", &
      "&accuracy_cost: tolerances: element 1 is -0.001; must be finite and > 0")
  end subroutine test_accuracy_bad

  !> Run on a one-line deck with -o; expect exit 2, one stderr line
  !> "demstep: DECK: <expected>...", no output file and no temporary left.
  !> A default in the template is the value the code uses: a group without the
  !> variable gives the same result namelist as one that sets the template's value.
  subroutine test_table_defaults(error)
    type(error_type), allocatable, intent(out) :: error
    integer :: rc
    character(len=:), allocatable :: stdout, stderr, template, implicit, explicit
    character(len=*), parameter :: g = "&simulated_stiffness mass = 0.01, stiffness = 1e5, " &
      //"tolerance = 1e-3, lambda = 0.9, 0.95"
    call run_app("--template", rc, template, stderr)
    call check(error, rc, 0, message="--template")
    if (allocated(error)) return
    ! the library's constants, as the template words them
    call check(error, index(template, "scan step relative to N, in (0, 1] (default 0.5)") > 0, &
      "resolution: the template says the library's default 0.5")
    if (allocated(error)) return
    call check(error, index(template, "largest N scanned (default 1e8)") > 0, &
      "n_max: the template says the library's default 1e8")
    if (allocated(error)) return
    call check(error, index(template, "dense eigensolver (default 1000)") > 0, &
      "max_eigen_dof: the template says the library's default 1000")
    if (allocated(error)) return
    call write_file(deck, [g//" /"])
    call run_app(deck//" -q --namelist", rc, implicit, stderr)
    call check(error, rc, 0, message="defaults: "//stderr)
    if (allocated(error)) return
    call write_file(deck, [g//", n_max = 1e8, resolution = 0.5, steps = 'half_period', " &
      //"pick = 'largest_step', aggregate = 'mean' /"])
    call run_app(deck//" -q --namelist", rc, explicit, stderr)
    call check(error, rc, 0, message="explicit: "//stderr)
    if (allocated(error)) return
    call check(error, implicit == explicit, "the defaults give the same result as the template's values")
    if (allocated(error)) return
    call write_file(deck, ["&system mass = 0.01, stiffness = 1e5, n_per_period = 10 /"])
    call run_app(deck//" -q --namelist", rc, implicit, stderr)
    call write_file(deck, ["&system mass = 0.01, stiffness = 1e5, n_per_period = 10, " &
      //"damping_ratio = 0, dashpot = 'lagged', velocity = 1 /"])
    call run_app(deck//" -q --namelist", rc, explicit, stderr)
    call check(error, rc == 0 .and. implicit == explicit, "&system: defaults as the template says")
    if (allocated(error)) return
    call check(error, index(template, "impact speed v0 > 0, scales overlaps (default 1)") > 0, &
      "&system: velocity's default in the template")
  end subroutine test_table_defaults

  !> quantity = 'harmonic': N is the smallest N with |E(N, lambda, N/2)| <= tolerance,
  !> checked against E itself (a root of |E| - tolerance, above every sampled N
  !> below it where |E| exceeds the tolerance).
  subroutine test_cost_harmonic(error)
    type(error_type), allocatable, intent(out) :: error
    integer :: rc, ios, k, stat
    character(len=:), allocatable :: stdout, stderr
    real(dp) :: tolerances(1), n_per_period(1), dt(1), predicted_seconds(1), cost_per_particle_step, &
      period, e, big_n
    integer(i8) :: steps(1)
    logical :: steps_saturated(1)
    integer :: status(1)
    real(dp) :: dt_recommended
    type(result_group_type) :: accuracy_cost_result_fields
    call write_file(deck, [character(len=160) :: "&accuracy_cost quantity = 'harmonic', lambda = 0.9,", &
      "  tolerances = 1e-3, duration = 1.0, n_particles = 100, mass = 0.01, stiffness = 1e5,", &
      "  cost_per_particle_step = 1e-7, csv = '"//work_dir//"/h.csv', figure = 'none' /"])
    call run_app(deck//" -q --namelist", rc, stdout, stderr)
    call check(error, rc, 0, message="exit status; stderr: "//stderr)
    if (allocated(error)) return
    call read_group(stdout, "accuracy_cost_result", accuracy_cost_result_fields, ios)
    if (ios == 0) call take(accuracy_cost_result_fields, "dt_recommended", dt_recommended, ios)
    if (ios == 0) call take(accuracy_cost_result_fields, "tolerances", tolerances, ios)
    if (ios == 0) call take(accuracy_cost_result_fields, "n_per_period", n_per_period, ios)
    if (ios == 0) call take(accuracy_cost_result_fields, "dt", dt, ios)
    if (ios == 0) call take(accuracy_cost_result_fields, "steps", steps, ios)
    if (ios == 0) call take(accuracy_cost_result_fields, "steps_saturated", steps_saturated, ios)
    if (ios == 0) call take(accuracy_cost_result_fields, "predicted_seconds", predicted_seconds, ios)
    if (ios == 0) call take(accuracy_cost_result_fields, "status", status, ios)
    if (ios == 0) call take(accuracy_cost_result_fields, "cost_per_particle_step", cost_per_particle_step, ios)
    if (ios == 0) call take(accuracy_cost_result_fields, "period", period, ios)
    call check(error, ios, 0, message="read back: "//stdout)
    if (allocated(error)) return
    call check(error, status(1), 0, message="met")
    if (allocated(error)) return
    ! the N found is a root of |E| - tolerance: the root finder works to about
    ! 1e-12 in N, and dE/dN there is of order E/N, so 1e-6 relative is generous
    call harmonic_error(n_per_period(1), 0.9_dp, 0.5_dp*n_per_period(1), e, stat)
    call check(error, abs(e), 1.0e-3_dp, thr=1.0e-6_dp, rel=.true., message="|E| = tolerance at N")
    if (allocated(error)) return
    ! and the smallest: |E| exceeds the tolerance on a grid of N below it (above pi)
    do k = 0, 999
      big_n = 3.2_dp + (0.999_dp*n_per_period(1) - 3.2_dp)*real(k, dp)/999.0_dp
      call harmonic_error(big_n, 0.9_dp, 0.5_dp*big_n, e, stat)
      if (stat /= demstep_stat%ok) cycle
      if (.not. abs(e) > 1.0e-3_dp) then
        call test_failed(error, "|E| <= tolerance already at N = "//real_str(big_n))
        return
      end if
    end do
  end subroutine test_cost_harmonic

  !> More values than a list holds, and the required / either-or rules: one line
  !> in one style each.
  subroutine test_table_rules(error)
    type(error_type), allocatable, intent(out) :: error
    character(len=*), parameter :: g = "&simulated_stiffness mass = 0.01, stiffness = 1e5, tolerance = 1e-3, "
    call expect_bad(error, "&harmonic_error n_per_period = 100001*10.0, lambda = 0.9, n_steps = 5 /", &
      "&harmonic_error: n_per_period: holds at most 100000 values, got 100001")
    if (allocated(error)) return
    call expect_bad(error, "&harmonic_error n_per_period(99999) = 10, 20, 30, lambda = 0.9, n_steps = 5 /", &
      "&harmonic_error: n_per_period: holds at most 100000 values, got 100001")
    if (allocated(error)) return
    call expect_bad(error, "&scene dim = 1, position = 0, 1, mass = 1, radius = 0.1, gravity = 1, 2, 3, 4 /", &
      "&scene: gravity: holds at most 3 values, got 4")
    if (allocated(error)) return
    ! a list within its capacity that the runtime cannot read keeps its message
    call expect_bad(error, "&harmonic_error n_per_period = 10, 'x', lambda = 0.9, n_steps = 5 /", &
      "&harmonic_error: n_per_period: cannot read")
    if (allocated(error)) return
    call expect_bad(error, g//"lambda_min = 0.9 /", "&simulated_stiffness: lambda_max: required with lambda_min")
    if (allocated(error)) return
    call expect_bad(error, g//"lambda_min = 0.9, lambda_max = 0.99 /", &
      "&simulated_stiffness: lambda_count: required with lambda_min")
    if (allocated(error)) return
    call expect_bad(error, "&scene dim = 1, position = 0, particles_file = 'p.txt' /", &
      "&scene: position: give either position or particles_file, not both")
    if (allocated(error)) return
    call expect_bad(error, "&scene dim = 1, particles_file = 'p.txt', mass = 1 /", &
      "&scene: particles_file: give either particles_file or mass, not both")
    if (allocated(error)) return
    call expect_bad(error, "&scene dim = 1, mass = 1 /", &
      "&scene: position: give either position or particles_file (one of them is required)")
    if (allocated(error)) return
    call expect_bad(error, "&accuracy_cost tolerances = 1e-3, duration = 1, n_particles = 1, mass = 1, " &
      //"stiffness = 1 /", "&accuracy_cost: quantity: required")
    if (allocated(error)) return
    call expect_bad(error, "&accuracy_cost quantity = 'harmonic', tolerances = 1e-3, duration = 1, " &
      //"n_particles = 1, mass = 1, stiffness = 1, cost_per_particle_step = 1e-7, figure = 'none' /", &
      "&accuracy_cost: lambda: required with quantity = 'harmonic'")
  end subroutine test_table_rules

  subroutine expect_bad(error, line, expected)
    type(error_type), allocatable, intent(out) :: error
    character(len=*), intent(in) :: line, expected
    call write_file(deck, [line])
    call expect_failure(error, deck//" -o "//out, "demstep: "//deck//": "//expected)
  end subroutine expect_bad

  subroutine expect_failure(error, args, expected)
    type(error_type), allocatable, intent(out) :: error
    character(len=*), intent(in) :: args, expected
    integer :: rc
    character(len=:), allocatable :: stdout, stderr, listing
    integer :: cmdstat
    call remove(out)
    call run_app(args, rc, stdout, stderr)
    call check(error, rc, 2, message="exit status for '"//args//"'")
    if (allocated(error)) return
    if (index(stderr, expected) /= 1) then
      call test_failed(error, "stderr '"//stderr//"' does not start with '"//expected//"'")
      return
    end if
    call check(error, count_lines(stderr), 1, message="one line on stderr: "//stderr)
    if (allocated(error)) return
    call check(error, .not. file_exists(out), "no output file left behind")
    if (allocated(error)) return
    call execute_command_line("ls "//work_dir//" > "//work_dir//"/listing", wait=.true., cmdstat=cmdstat)
    call read_file(work_dir//"/listing", listing)
    call check(error, index(listing, ".tmp") == 0, "no temporary file left behind")
  end subroutine expect_failure

end module test_app
