!> End-to-end tests of what the app must never do (issue 18): run with an
!> executable stack, write an output over a file the deck reads (directly or
!> through a link), print more than one `recommended dt` (or not as the last
!> line), accept a value the runtime reads without a word, or name a variable the
!> deck does not have. Every input is quoted here as the test writes it.
module test_app_safety
  use testdrive, only: new_unittest, unittest_type, error_type, check
  use demstep, only: dp, i8
  use test_support, only: run_app, write_file, read_file, work_dir, count_lines, remove, app_path, &
    file_exists
  use, intrinsic :: iso_fortran_env, only: qp => real128
  use demstep_results, only: result_group_type
  use test_support, only: read_group, take
  implicit none
  private
  public :: collect_app_safety

  real(qp), parameter :: pq = 3.14159265358979323846264338327950288_qp
  character(len=*), parameter :: deck = work_dir//"/safe_deck.nml"
  character(len=*), parameter :: out = work_dir//"/safe_out.nml"
  character(len=*), parameter :: dump = work_dir//"/safe_s.dump"
  character(len=*), parameter :: dump_link = work_dir//"/safe_link.dump"
  !> A deck (beside the dump) whose &scene reads the dump, with its materials.
  character(len=80), parameter :: dump_deck(5) = [character(len=80) :: &
    "&scene dim = 3, snapshot_file = 'safe_s.dump' /", &
    "&material", "young = 1.0e7, poisson = 0.25, density = 2500.0, radius = 1.0e-3, 0.8e-3,", &
    "restitution = 0.9, impact_velocity = 1.0, code = 'liggghts_hertz' /", ""]

contains

  !> The suite.
  subroutine collect_app_safety(testsuite)
    type(unittest_type), allocatable, intent(out) :: testsuite(:)
    testsuite = [ &
      new_unittest("no executable stack: the app and this tester (readelf)", test_stack), &
      new_unittest("-o never replaces a file the deck reads, nor through a link", test_output_inputs), &
      new_unittest("csv and figure never replace a file the deck reads", test_curve_inputs), &
      new_unittest("one recommended dt, the last line, the step of the whole deck", test_one_recommended), &
      new_unittest("LIGGGHTS' Hertz rule at 2 v, and the report says so", test_liggghts_velocity), &
      new_unittest("the header's link line is pkg-config's", test_link_line), &
      new_unittest("values read without a word are refused, naming the variable", test_silent_values), &
      new_unittest("messages name the deck's variable or MFiX keyword", test_named_variables), &
      new_unittest("&simulated_stiffness and &accuracy_cost at the double range's edge", test_range_edges) &
      ]
  end subroutine collect_app_safety

  !> The ELF program headers of the app built beside this tester and of the tester
  !> itself: a GNU_STACK header without the execute flag (an internal procedure
  !> passed as an argument makes gfortran build a trampoline, and the linker then
  !> asks for an executable stack: `RWE`).
  subroutine test_stack(error)
    type(error_type), allocatable, intent(out) :: error
    character(len=1024) :: tester
    call get_command_argument(0, tester)
    call check_stack(error, app_path())
    if (allocated(error)) return
    call check_stack(error, trim(tester))
  end subroutine test_stack

  subroutine check_stack(error, path)
    type(error_type), allocatable, intent(out) :: error
    character(len=*), intent(in) :: path
    character(len=:), allocatable :: text, line
    integer :: es, cs, k, e
    call execute_command_line("mkdir -p "//work_dir//" && readelf -lW "//path//" > "//work_dir// &
      "/safe_readelf.txt 2>&1", exitstat=es, cmdstat=cs)
    call check(error, cs == 0 .and. es == 0, "readelf -lW "//path//" (binutils) runs")
    if (allocated(error)) return
    call read_file(work_dir//"/safe_readelf.txt", text)
    k = index(text, "GNU_STACK")
    call check(error, k > 0, path//": a GNU_STACK program header: "//text)
    if (allocated(error)) return
    e = index(text(k:), new_line("a"))
    line = text(k:k + e - 2)
    ! the flags follow the six numbers: 'RW ' or 'RWE'
    call check(error, index(line, " RW ") > 0 .and. index(line, "RWE") == 0, &
      path//": the stack is not executable: "//line)
  end subroutine check_stack

  !> Copy `from` to `to` with cp (the test's fixtures).
  subroutine copy(error, from, to)
    type(error_type), allocatable, intent(out) :: error
    character(len=*), intent(in) :: from, to
    integer :: es, cs
    call execute_command_line("mkdir -p "//work_dir//" && cp "//from//" "//to, exitstat=es, cmdstat=cs)
    call check(error, cs == 0 .and. es == 0, "cp "//from//" "//to)
  end subroutine copy

  !> `ln -sf target link` in the scratch directory.
  subroutine make_link(error, target, name)
    type(error_type), allocatable, intent(out) :: error
    character(len=*), intent(in) :: target, name
    integer :: es, cs
    call execute_command_line("cd "//work_dir//" && ln -sf "//target//" "//name, exitstat=es, cmdstat=cs)
    call check(error, cs == 0 .and. es == 0, "ln -sf "//target//" "//name)
  end subroutine make_link

  !> `args` ends with exit 2 and one line on stderr starting with `expected`, and
  !> `kept` (a file) still holds `before`.
  subroutine expect_kept(error, args, expected, kept, before)
    type(error_type), allocatable, intent(out) :: error
    character(len=*), intent(in) :: args, expected, kept, before
    integer :: rc
    character(len=:), allocatable :: stdout, stderr, after
    call run_app(args, rc, stdout, stderr)
    call check(error, rc, 2, message="exit status of '"//args//"'; stderr: "//stderr)
    if (allocated(error)) return
    call check(error, index(stderr, expected) == 1 .and. count_lines(stderr) == 1, &
      "one line starting '"//expected//"', got '"//stderr//"'")
    if (allocated(error)) return
    call read_file(kept, after)
    call check(error, len(after) > 0 .and. after == before, kept//" is unchanged")
  end subroutine expect_kept

  !> `demstep deck.nml -o FILE` where FILE is each kind of file the deck reads
  !> (snapshot_file, particles_file, bonds_file, contacts_file, the deck itself,
  !> an MFiX deck itself), directly and through a symbolic link made here.
  subroutine test_output_inputs(error)
    type(error_type), allocatable, intent(out) :: error
    character(len=:), allocatable :: before, prefix
    integer :: cmdstat
    prefix = "demstep: "
    call copy(error, "example/liggghts_pour.dump", dump)
    if (allocated(error)) return
    call write_file(deck, dump_deck)
    call read_file(dump, before)
    ! deck: "&scene dim = 3, snapshot_file = 'safe_s.dump' /" and a &material
    call expect_kept(error, deck//" -o "//dump, prefix//dump//": is the deck's &scene snapshot_file; " &
      //"the results would replace it (choose another -o file)", dump, before)
    if (allocated(error)) return
    call make_link(error, "safe_s.dump", "safe_link.dump")
    if (allocated(error)) return
    call expect_kept(error, deck//" -o "//dump_link, prefix//dump_link//": is the deck's &scene " &
      //"snapshot_file", dump, before)
    if (allocated(error)) return
    ! a link in another directory, reached through a relative path with '..'
    call execute_command_line("mkdir -p "//work_dir//"/safe_sub", wait=.true., cmdstat=cmdstat)
    call make_link(error, "../safe_s.dump", "safe_sub/back.dump")
    if (allocated(error)) return
    call expect_kept(error, deck//" -o "//work_dir//"/safe_sub/../safe_sub/back.dump", prefix//work_dir// &
      "/safe_sub/../safe_sub/back.dump: is the deck's &scene snapshot_file", dump, before)
    if (allocated(error)) return
    ! particles_file and bonds_file: the lattice example's tables
    call copy(error, "example/lattice_particles.txt", work_dir//"/safe_p.txt")
    if (allocated(error)) return
    call copy(error, "example/lattice_bonds.txt", work_dir//"/safe_b.txt")
    if (allocated(error)) return
    call write_file(deck, [character(len=100) :: "&scene dim = 2, particles_file = 'safe_p.txt', " &
      //"bonds_file = 'safe_b.txt',", "k_bond = 1.0e3, k_bond_tangential = 2.0e2, effects = 'none' /"])
    call read_file(work_dir//"/safe_p.txt", before)
    call expect_kept(error, deck//" -o "//work_dir//"/safe_p.txt", prefix//work_dir//"/safe_p.txt: is " &
      //"the deck's &scene particles_file", work_dir//"/safe_p.txt", before)
    if (allocated(error)) return
    call read_file(work_dir//"/safe_b.txt", before)
    call make_link(error, "safe_b.txt", "safe_b_link.txt")
    if (allocated(error)) return
    call expect_kept(error, deck//" -o "//work_dir//"/safe_b_link.txt", prefix//work_dir// &
      "/safe_b_link.txt: is the deck's &scene bonds_file", work_dir//"/safe_b.txt", before)
    if (allocated(error)) return
    ! contacts_file
    call write_file(work_dir//"/safe_p2.txt", [character(len=60) :: "0.1 0 0  0 0 0  1 0.6 0 0.4", &
      "5.1 0 0  0 0 0  1 0.6 0 0.4"])
    call write_file(work_dir//"/safe_c.txt", [character(len=20) :: "1 2 100 60"])
    call write_file(deck, [character(len=100) :: "&scene dim = 3, particles_file = 'safe_p2.txt', " &
      //"contacts_file = 'safe_c.txt',", "periodic = T, F, F, cell_hi = 4.0, 1.0, 1.0 /"])
    call read_file(work_dir//"/safe_c.txt", before)
    call expect_kept(error, deck//" -o "//work_dir//"/safe_c.txt", prefix//work_dir//"/safe_c.txt: is " &
      //"the deck's &scene contacts_file", work_dir//"/safe_c.txt", before)
    if (allocated(error)) return
    ! the deck itself, through a link
    call read_file(deck, before)
    call make_link(error, "safe_deck.nml", "safe_deck_link.nml")
    if (allocated(error)) return
    call expect_kept(error, deck//" -o "//work_dir//"/safe_deck_link.nml", prefix//work_dir// &
      "/safe_deck_link.nml: is the input deck", deck, before)
    if (allocated(error)) return
    ! an MFiX deck (it reads no other file: its size distributions are keywords)
    call copy(error, "example/hopper_psd.mfx", work_dir//"/safe.mfx")
    if (allocated(error)) return
    call read_file(work_dir//"/safe.mfx", before)
    call expect_kept(error, work_dir//"/safe.mfx -o "//work_dir//"/safe.mfx", prefix//work_dir// &
      "/safe.mfx: is the input deck", work_dir//"/safe.mfx", before)
  end subroutine test_output_inputs

  !> `&accuracy_cost csv` or `figure` (its .png, .svg and gnuplot's .tmp files)
  !> naming a file the deck reads, directly or through a link.
  subroutine test_curve_inputs(error)
    type(error_type), allocatable, intent(out) :: error
    character(len=:), allocatable :: before, deck_before
    character(len=*), parameter :: cost = "&accuracy_cost quantity = 'restitution', tolerances = 1e-2, " &
      //"duration = 1, n_particles = 10, mass = 0.01, stiffness = 1e5, cost_per_particle_step = 1e-7,"
    call copy(error, "example/liggghts_pour.dump", dump)
    if (allocated(error)) return
    call make_link(error, "safe_s.dump", "safe_link.dump")
    if (allocated(error)) return
    call read_file(dump, before)
    call write_file(deck, [character(len=200) :: cost, "csv = '"//dump_link//"', figure = 'none' /", &
      dump_deck])
    call expect_kept(error, deck, "demstep: "//deck//": &accuracy_cost: csv: '"//dump_link//"' is the " &
      //"deck's &scene snapshot_file; the output would replace it (choose another name)", dump, before)
    if (allocated(error)) return
    call write_file(deck, [character(len=200) :: cost, "csv = '"//dump//"', figure = 'none' /", dump_deck])
    call expect_kept(error, deck, "demstep: "//deck//": &accuracy_cost: csv: '"//dump//"' is the " &
      //"deck's &scene snapshot_file", dump, before)
    if (allocated(error)) return
    ! figure = 'safe_fig': safe_fig.svg is a link to the deck
    call write_file(deck, [character(len=200) :: cost, "csv = '"//work_dir//"/safe.csv', figure = '" &
      //work_dir//"/safe_fig' /"])
    call read_file(deck, deck_before)
    call make_link(error, "safe_deck.nml", "safe_fig.svg")
    if (allocated(error)) return
    call expect_kept(error, deck, "demstep: "//deck//": &accuracy_cost: figure: '"//work_dir// &
      "/safe_fig.svg' is the input deck", deck, deck_before)
    if (allocated(error)) return
    call make_link(error, "safe_deck.nml", "safe_fig.png.tmp")
    if (allocated(error)) return
    call remove(work_dir//"/safe_fig.svg")
    call expect_kept(error, deck, "demstep: "//deck//": &accuracy_cost: figure: '"//work_dir// &
      "/safe_fig.png.tmp' is the input deck", deck, deck_before)
    if (allocated(error)) return
    call remove(work_dir//"/safe_fig.png.tmp")
  end subroutine test_curve_inputs

  !> The last line of a report, and how many lines hold `piece`.
  subroutine last_line(text, line)
    character(len=*), intent(in) :: text
    character(len=:), allocatable, intent(out) :: line
    line = text
    if (len(line) > 0) then
      if (line(len(line):) == new_line("a")) line = line(:len(line) - 1)
    end if
    line = line(index(line, new_line("a"), back=.true.) + 1:)
  end subroutine last_line

  pure integer function occurrences(text, piece) result(n)
    character(len=*), intent(in) :: text, piece
    integer :: at, k
    n = 0
    at = 1
    do
      k = index(text(at:), piece)
      if (k == 0) return
      n = n + 1
      at = at + k + len(piece) - 1
    end do
  end function occurrences

  !> Decks of several groups: one `recommended dt` line, the last line of the
  !> report (after "results written to"), the smallest step without a &scene,
  !> the scene's with one (a scene with its own stiffness plus a &material: the
  !> case of issue 18, where the single-contact step came last); each group's own
  !> step is named for what it is.
  subroutine test_one_recommended(error)
    type(error_type), allocatable, intent(out) :: error
    integer :: rc
    character(len=:), allocatable :: stdout, stderr, last
    ! &system's single contact: 0.9 x 2 sqrt(0.01/1e5) = 5.692099788e-4 s; the
    ! &accuracy_cost's 1 % step of the same spring is smaller
    call write_file(deck, [character(len=200) :: "&system mass = 0.01, stiffness = 1.0e5 /", &
      "&accuracy_cost quantity = 'restitution', tolerances = 1e-2, duration = 1, n_particles = 10,", &
      "mass = 0.01, stiffness = 1e5, cost_per_particle_step = 1e-7, csv = '"//work_dir//"/safe.csv', " &
      //"figure = 'none' /"])
    call run_app(deck//" -o "//out, rc, stdout, stderr)
    call check(error, rc == 0, "runs: "//stderr)
    if (allocated(error)) return
    call last_line(stdout, last)
    call check(error, occurrences(stdout, "recommended dt = ") == 1 .and. occurrences(stdout, &
      "  single-contact step      ") == 2 .and. index(last, "recommended dt = ") == 1, &
      "one recommended dt, last; two single-contact steps: "//stdout)
    if (allocated(error)) return
    call check(error, index(stdout, "the deck's step: &accuracy_cost (line 2): single-contact step (the " &
      //"smallest of the 2 steps)"//new_line("a")//last) > 0 .and. last /= "recommended dt = 5.692099788e-4 s", &
      "the smaller step governs and is named: "//stdout)
    if (allocated(error)) return
    ! a &scene with its own stiffness and a &material: the scene's assembly step
    call write_file(deck, [character(len=100) :: "&material", &
      "young = 1.0e7, poisson = 0.25, density = 2500.0, radius = 1.0e-3, 0.8e-3,", &
      "restitution = 0.9, impact_velocity = 1.0, code = 'liggghts_hertz' /", &
      "&scene dim = 3, snapshot_file = '../../example/liggghts_pour.dump', k_normal = 1.0e3 /"])
    call run_app(deck//" -o "//out, rc, stdout, stderr)
    call check(error, rc == 0, "runs: "//stderr)
    if (allocated(error)) return
    call last_line(stdout, last)
    call check(error, occurrences(stdout, "recommended dt = ") == 1 .and. index(last, "recommended dt = ") == 1 &
      .and. index(stdout, "the deck's step: &scene (line 4): assembly step") > 0, &
      "a scene with its own stiffness: its step is the deck's, last: "//stdout)
    if (allocated(error)) return
    ! the assembly step is the one printed last
    call check(error, index(stdout, "assembly step            "//last(len("recommended dt = ") + 1:)) > 0, &
      "the last line repeats the assembly step: "//stdout)
  end subroutine test_one_recommended

  !> LIGGGHTS' check/timestep/gran takes its Hertz time at max(2 vmax, vmax +
  !> vmax_mesh): the report says the relative velocity (2 x the impact velocity).
  subroutine test_liggghts_velocity(error)
    type(error_type), allocatable, intent(out) :: error
    integer :: rc
    character(len=:), allocatable :: stdout, stderr
    call write_file(deck, [character(len=100) :: "&material young = 1.0e7, poisson = 0.25, " &
      //"density = 2500.0, radius = 1.0e-3,", "restitution = 0.9, impact_velocity = 1.0, code = " &
      //"'liggghts_hertz' /"])
    call run_app(deck, rc, stdout, stderr)
    call check(error, rc == 0, "runs: "//stderr)
    if (allocated(error)) return
    ! LIGGGHTS 3.8.0 printed dt/hertz_time = 0.00421605382998205 at dt = 1e-6 for
    ! this bead (test/data/liggghts/check_timestep.in): 2.371886224e-4 s
    call check(error, index(stdout, "LIGGGHTS' estimate 2.371886224e-4 at relative velocity 2 x 1, as " &
      //"check/timestep/gran") > 0, "the rule's time and velocity: "//stdout)
  end subroutine test_liggghts_velocity

  !> include/demstep.h's "Link with" flags are those of demstep.pc's Libs and
  !> Libs.private (the static link; checked by hand against libdemstep.a).
  subroutine test_link_line(error)
    type(error_type), allocatable, intent(out) :: error
    character(len=:), allocatable :: header, pc, flags, want
    integer :: k, e
    call read_file("include/demstep.h", header)
    call read_file("config/demstep.pc.in", pc)
    k = index(header, "Link with ")
    call check(error, k > 0, "the header has a link line")
    if (allocated(error)) return
    e = index(header(k:), new_line("a"))
    flags = header(k + len("Link with "):k + e - 2)
    k = index(pc, "Libs.private: ")
    call check(error, k > 0, "demstep.pc.in has Libs.private")
    if (allocated(error)) return
    e = index(pc(k:), new_line("a"))
    want = "-ldemstep "//pc(k + len("Libs.private: "):k + e - 2)
    call check(error, flags == want, "the header's '"//flags//"' is pkg-config's '"//want//"'")
  end subroutine test_link_line

  !> `args` (or the deck `lines`) ends with exit 2 and one line on stderr that
  !> starts with "demstep: FILE: " and `expected`.
  subroutine expect_refused(error, lines, expected, file)
    type(error_type), allocatable, intent(out) :: error
    character(len=*), intent(in) :: lines(:), expected
    !> The deck's name (default the namelist deck).
    character(len=*), intent(in), optional :: file
    integer :: rc
    character(len=:), allocatable :: stdout, stderr, path
    path = deck
    if (present(file)) path = file
    call write_file(path, lines)
    call remove(out)
    call run_app(path//" -o "//out, rc, stdout, stderr)
    call check(error, rc, 2, message="exit status; stderr: "//stderr)
    if (allocated(error)) return
    call check(error, index(stderr, "demstep: "//path//": "//expected) == 1 .and. count_lines(stderr) == 1, &
      "one line starting 'demstep: "//path//": "//expected//"', got '"//stderr//"'")
    if (allocated(error)) return
    call check(error, .not. file_exists(out), "no output written")
  end subroutine expect_refused

  !> Values the runtime reads without a word: a null (`3*`, `1*`, an empty field),
  !> a lone sign (read as 0), and a list element equal to the mark of elements
  !> not given (-huge).
  subroutine test_silent_values(error)
    type(error_type), allocatable, intent(out) :: error
    call expect_refused(error, [character(len=80) :: &
      "&harmonic_error n_per_period = 3*, lambda = 0.5, steps_fraction = 0.5 /"], &
      "&harmonic_error: n_per_period: '3*' holds a null value")
    if (allocated(error)) return
    call expect_refused(error, [character(len=80) :: "&system mass = 1*, stiffness = 1.0e5 /"], &
      "&system: mass: '1*' holds a null value")
    if (allocated(error)) return
    call expect_refused(error, [character(len=80) :: &
      "&harmonic_error n_per_period = 10,,20, lambda = 0.5, steps_fraction = 0.5 /"], &
      "&harmonic_error: n_per_period: '10,,20' holds a null value")
    if (allocated(error)) return
    call expect_refused(error, [character(len=80) :: "&system mass = -, stiffness = 1.0e5 /"], &
      "&system: mass: cannot read '-' as a real number")
    if (allocated(error)) return
    call expect_refused(error, [character(len=120) :: "&simulated_stiffness mass = -, stiffness = 1.0e5, " &
      //"tolerance = 1.0e-3 /"], "&simulated_stiffness: mass: cannot read '-' as a real number")
    if (allocated(error)) return
    call expect_refused(error, [character(len=80) :: &
      "&contact_error n_per_period = 10, onset = -1.7976931348623157e308 /"], &
      "&contact_error: onset: element 1 is -1.797693135e308, the value that marks an element not given")
    if (allocated(error)) return
    call expect_refused(error, [character(len=80) :: &
      "&contact_error n_per_period = 10, -1.7976931348623157e308 /"], &
      "&contact_error: n_per_period: element 2 is -1.797693135e308")
    if (allocated(error)) return
    call expect_refused(error, [character(len=120) :: "&accuracy_cost quantity = 'restitution', " &
      //"duration = 1, n_particles = 10, mass = 1, stiffness = 1,", "tolerances = 0.01, " &
      //"-1.7976931348623157e308, csv = '"//work_dir//"/safe.csv', figure = 'none' /"], &
      "&accuracy_cost: tolerances: element 2 is -1.797693135e308")
    if (allocated(error)) return
    ! -1.8e308 overflows to -Inf: refused as before, by the library's check
    call expect_refused(error, [character(len=120) :: "&accuracy_cost quantity = 'restitution', " &
      //"duration = 1, n_particles = 10, mass = 1, stiffness = 1,", "tolerances = -1.8e308, csv = '" &
      //work_dir//"/safe.csv', figure = 'none' /"], "&accuracy_cost: tolerances: element 1 is -Inf")
    if (allocated(error)) return
    call expect_refused(error, [character(len=80) :: "&contact_error n_per_period = -1.8e308 /"], &
      "&contact_error: n_per_period: element 1 is -Inf")
    if (allocated(error)) return
    call expect_refused(error, [character(len=80) :: "&contact_error n_per_period = 10, onset = -1.797e308 /"], &
      "&contact_error: onset: element 1 is -1.797e308; must be in (0, 1]")
  end subroutine test_silent_values

  !> A deck with the MFiX example's keywords, `old` replaced by `new`.
  subroutine mfix_deck(error, old, new, path)
    type(error_type), allocatable, intent(out) :: error
    character(len=*), intent(in) :: old, new, path
    character(len=:), allocatable :: text
    integer :: k, unit
    call read_file("example/hopper_psd.mfx", text)
    k = index(text, old)
    call check(error, k > 0, "example/hopper_psd.mfx holds '"//old//"'")
    if (allocated(error)) return
    text = text(:k - 1)//new//text(k + len(old):)
    open(newunit=unit, file=path, access="stream", form="unformatted", status="replace", action="write")
    write(unit) text
    close(unit)
  end subroutine mfix_deck

  !> `demstep FILE.mfx` ends with exit 2 and one line starting with `expected`.
  subroutine expect_mfix_refused(error, path, expected)
    type(error_type), allocatable, intent(out) :: error
    character(len=*), intent(in) :: path, expected
    integer :: rc
    character(len=:), allocatable :: stdout, stderr
    call run_app(path, rc, stdout, stderr)
    call check(error, rc, 2, message="exit status; stderr: "//stderr)
    if (allocated(error)) return
    call check(error, index(stderr, "demstep: "//path//": "//expected) == 1 .and. count_lines(stderr) == 1, &
      "one line starting 'demstep: "//path//": "//expected//"', got '"//stderr//"'")
  end subroutine expect_mfix_refused

  !> Each message names what the user changes: the MFiX keyword, the &material
  !> variable (never an internal name such as k_n, n_per_period, damping_ratio or
  !> steps_fraction, and never the &scene for a &material value).
  subroutine test_named_variables(error)
    type(error_type), allocatable, intent(out) :: error
    character(len=*), parameter :: mfx = work_dir//"/safe_bad.mfx"
    character(len=*), parameter :: psd = "bc_psd_min_dp(3,1)   = 1.0000e-03"
    character(len=*), parameter :: hertz = "young = 1.0e7, poisson = 0.25, density = 2500.0, radius = 1.0e-3,"
    character(len=12), parameter :: bad_phase(3) = [character(len=12) :: "3,11", "3,0", "3,2147483647"]
    character(len=16), parameter :: bad_restitution(3) = [character(len=16) :: "0.0", "1.5", "NaN"]
    character(len=16), parameter :: bad_velocity(3) = [character(len=16) :: "0.0", "-1.0", "NaN"]
    character(len=100) :: lines(4)
    integer :: i
    ! MFiX: a phase subscript outside [1, 10], as D_P0(11) is
    do i = 1, size(bad_phase)
      call mfix_deck(error, psd, "bc_psd_min_dp("//trim(bad_phase(i))//")   = 1.0000e-03", mfx)
      if (allocated(error)) return
      call expect_mfix_refused(error, mfx, "line 27: BC_PSD_MIN_DP("//trim(bad_phase(i))//"): index out of range")
      if (allocated(error)) return
    end do
    ! MFiX: des_en_input(1) = 1e-300, a contact that never ends at DTSOLID
    call mfix_deck(error, "des_en_input(1)      = 0.5", "des_en_input(1)      = 1e-300", mfx)
    if (allocated(error)) return
    call expect_mfix_refused(error, mfx, "DES_EN_INPUT(1): the pair of phases 1 and 1: at N = ")
    if (allocated(error)) return
    call mfix_deck(error, "des_en_wall_input(2) = 0.5", "des_en_wall_input(2) = 1e-300", mfx)
    if (allocated(error)) return
    call expect_mfix_refused(error, mfx, "DES_EN_WALL_INPUT(2): phase 2 against walls: at N = ")
    if (allocated(error)) return
    ! &material
    call expect_refused(error, [character(len=120) :: "&material code = 'mfix_hertzian', young = 1e-300, " &
      //"poisson = 0.25, density = 2500.0,", "radius = 1.0e-3, restitution = 0.9, impact_velocity = 1.0 /"], &
      "&material: young: types 1 and 1: mfix_hertzian: the contact stiffness k_n it gives")
    if (allocated(error)) return
    call expect_refused(error, [character(len=120) :: "&material code = 'yade_frictphys', young = 1.0e7, " &
      //"poisson = -0.9999999999,", "density = 2500.0, radius = 1.0e-3, restitution = 0.9, " &
      //"impact_velocity = 1.0 /"], "&material: poisson: types 1 and 1: yade_frictphys: ")
    if (allocated(error)) return
    ! a snapshot deck's &material: its restitution and impact velocity, named as such
    lines(1) = "&scene dim = 3, snapshot_file = '../../example/liggghts_pour.dump' /"
    lines(2) = "&material"
    lines(3) = hertz
    do i = 1, size(bad_restitution)
      lines(4) = "restitution = "//trim(bad_restitution(i))//", impact_velocity = 1.0, code = 'liggghts_hertz' /"
      call expect_refused(error, lines, "&material: restitution: must lie in (0, 1]")
      if (allocated(error)) return
      lines(4) = "restitution = 0.9, impact_velocity = "//trim(bad_velocity(i))//", code = 'liggghts_hertz' /"
      call expect_refused(error, lines, "&material: impact_velocity: must be a finite number > 0")
      if (allocated(error)) return
    end do
    ! &accuracy_cost lambda = 4.9e-324: f lambda underflows to an integer (0)
    call expect_refused(error, [character(len=120) :: "&accuracy_cost quantity = 'harmonic', " &
      //"lambda = 4.9e-324, duration = 1, n_particles = 10,", "mass = 1, stiffness = 1, tolerances = 0.01, " &
      //"csv = '"//work_dir//"/safe.csv', figure = 'none' /"], "&accuracy_cost: lambda: 4.940656458e-324")
  end subroutine test_named_variables

  !> `&simulated_stiffness mass = 4.9e-324` (or stiffness): T* = 2 pi sqrt(M/K*)
  !> and dt = T*/N* are tiny or huge but doubles (were 0, and a `dt_accuracy`
  !> message); `&accuracy_cost` counts above 2^63 - 1 are marked in the result.
  subroutine test_range_edges(error)
    type(error_type), allocatable, intent(out) :: error
    integer :: rc, unit, ios
    character(len=:), allocatable :: stdout, stderr
    real(dp) :: period, dt, n_star, tolerances(1), n_per_period(1), predicted_seconds(1), &
      cost_per_particle_step, dt_recommended
    integer(i8) :: steps(1)
    logical :: steps_saturated(1)
    integer :: status(1)
    type(result_group_type) :: accuracy_cost_result_fields
    character(len=*), parameter :: rest = "tolerance = 1.0e-3, lambda_min = 0.9, lambda_max = 0.99, " &
      //"lambda_count = 10 /"
    ! the doubles the deck's values read as: 4.9e-324 is the smallest subnormal 2^-1074
    real(qp), parameter :: masses(2) = [2.0_qp**(-1074), real(0.01_dp, qp)], &
      stiffnesses(2) = [1.0e5_qp, 2.0_qp**(-1074)]
    character(len=40), parameter :: given(2) = [character(len=40) :: "mass = 4.9e-324, stiffness = 1.0e5", &
      "mass = 0.01, stiffness = 4.9e-324"]
    integer :: i
    character(len=160) :: line
    do i = 1, 2
      line = "&simulated_stiffness "//trim(given(i))//", "//rest
      call write_file(deck, [line])
      call remove(out)
      call run_app(deck//" -o "//out, rc, stdout, stderr)
      call check(error, rc == 0, trim(given(i))//": runs: "//stderr)
      if (allocated(error)) return
      call read_stiffness_result(out, period, dt, n_star, ios)
      ! T* from two square roots and a product: a few roundings (1e-14)
      call check(error, ios == 0 .and. abs(period/(2*pq*sqrt(masses(i)/stiffnesses(i))) - 1) < 1.0e-14_qp, &
        trim(given(i))//": T* = 2 pi sqrt(M/K*)")
      if (allocated(error)) return
      ! dt = T*/N* in one division (1 rounding on top of T*'s: 1e-14)
      call check(error, ios == 0 .and. dt > 0 .and. abs(dt/(period/n_star) - 1) < 1.0e-14_dp, &
        trim(given(i))//": dt = T*/N* > 0")
      if (allocated(error)) return
    end do
    ! a run of 1e300 s at steps of 0.29 s: 3.4e300 steps, above 2^63 - 1
    call write_file(deck, [character(len=160) :: "&accuracy_cost quantity = 'restitution', duration = 1e300, " &
      //"n_particles = 10, mass = 1, stiffness = 1,", "tolerances = 0.01, cost_per_particle_step = 1e-7, " &
      //"csv = '"//work_dir//"/safe.csv', figure = 'none' /"])
    call remove(out)
    call run_app(deck//" -o "//out, rc, stdout, stderr)
    call check(error, rc == 0, "duration 1e300: runs: "//stderr)
    if (allocated(error)) return
    steps_saturated = .false.
    open(newunit=unit, file=out, status="old", action="read", iostat=ios)
    if (ios == 0) call read_group(unit, "accuracy_cost_result", accuracy_cost_result_fields, ios)
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
    call check(error, ios == 0 .and. steps_saturated(1) .and. steps(1) == huge(1_i8), &
      "the saturated count is marked in &accuracy_cost_result")
    if (allocated(error)) return
    ! and the report's steps column shows the count whole, after a blank
    call check(error, index(stdout, " 9223372036854775807 ") > 0, "the 19 digits in the table: "//stdout)
  end subroutine test_range_edges

  !> T*, dt and N* from the `&simulated_stiffness_result` of a 10-lambda run.
  subroutine read_stiffness_result(path, period, dt, n_star, ios)
    character(len=*), intent(in) :: path
    real(dp), intent(out) :: period, dt, n_star
    integer, intent(out) :: ios
    real(dp) :: lambda(10), n_zero(10), n_lower(10), n_upper(10), n_pick(10), lambda_star, &
      stiffness_actual, dt_recommended
    logical :: bounded(10)
    integer :: status(10), lambda_star_status, excluded, unit
    type(result_group_type) :: simulated_stiffness_result_fields
    period = -1
    dt = -1
    n_star = -1
    open(newunit=unit, file=path, status="old", action="read", iostat=ios)
    if (ios == 0) call read_group(unit, "simulated_stiffness_result", simulated_stiffness_result_fields, ios)
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
  end subroutine read_stiffness_result

end module test_app_safety
