!> End-to-end tests of the `&scene` group on large, degenerate and extreme
!> inputs: each either computed (the result namelist read back) or refused with
!> one line naming the variable. Timing is left to the benchmarks: these tests
!> only assert that the work completes and what it gives.
module test_app_scene
  use testdrive, only: new_unittest, unittest_type, error_type, check, test_failed
  use demstep, only: dp, i8
  use test_support, only: run_app, write_file, read_file, file_exists, work_dir, real_str
  use, intrinsic :: ieee_arithmetic, only: ieee_is_finite
  use demstep_results, only: result_group_type
  use test_support, only: read_group, take
  implicit none
  private
  public :: collect_app_scene

  character(len=*), parameter :: deck = work_dir//"/scene_deck.nml"
  character(len=*), parameter :: out = work_dir//"/scene_out.nml"

  !> The result namelist, as a legacy code would read it back.
  type :: scene_result_type
    integer :: n_particles = -1, n_dof = -1, n_springs = -1, max_contacts = -1
    real(dp) :: omega_max = -1, dt_critical_eigen = -1, dt_critical_bound = -1, dt_contact_rule = -1, &
      dt_critical_damped = -1, damping_ratio_top = -1, dt_used = -1, energy_drift = -1, max_overlap = -1
    integer(i8) :: steps = -1
    logical :: eigen_computed = .false., blew_up = .false.
  end type scene_result_type

contains

  subroutine collect_app_scene(testsuite)
    type(unittest_type), allocatable, intent(out) :: testsuite(:)
    testsuite = [ &
      new_unittest("1e5 particles from a table: a chain, and on a wall", test_large_tables), &
      new_unittest("1e5 particles inline: a chain", test_large_inline), &
      new_unittest("3e4 touching particles", test_touching), &
      new_unittest("3000 all overlapping: every pair a spring", test_all_overlapping), &
      new_unittest("1000 particles at one point: refused by number", test_one_point), &
      new_unittest("/dev/zero, a binary file and an endless line are refused", test_not_text), &
      new_unittest("a row with an extra or hidden column is refused", test_extra_column), &
      new_unittest("extreme radius, damping, mass and stiffness", test_extremes), &
      new_unittest("no stiffness: the message names the variable", test_no_stiffness), &
      new_unittest("eigen_solver and eigen_tolerance: computed or refused by name", test_eigen_solver), &
      new_unittest("long runs: announced with progress, absurd ones refused", test_long_runs), &
      new_unittest("inertia column, contacts_file, periodic cell: computed or refused", test_assembly_inputs), &
      new_unittest("particle numbers 1.5, 4294967297 in contacts and bonds files; fixed 0.5", test_particle_numbers), &
      new_unittest("dashpots, rolling springs, walls' material: computed or refused by name", test_dashpot_inputs) &
      ]
  end subroutine collect_app_scene

  !> A particles table of n rows, written directly (faster than a line array).
  subroutine write_table(path, n, row)
    character(len=*), intent(in) :: path
    integer, intent(in) :: n
    interface
      function row(i) result(text)
        integer, intent(in) :: i
        character(len=:), allocatable :: text
      end function row
    end interface
    integer :: unit, i, cmdstat
    call execute_command_line("mkdir -p "//work_dir, wait=.true., cmdstat=cmdstat)
    open(newunit=unit, file=path, status="replace", action="write")
    do i = 1, n
      write(unit, '(a)') row(i)
    end do
    close(unit)
  end subroutine write_table

  !> Run the deck; expect exit 0 and read the result back.
  subroutine expect_result(error, line, res, env)
    type(error_type), allocatable, intent(out) :: error
    character(len=*), intent(in) :: line
    type(scene_result_type), intent(out) :: res
    character(len=*), intent(in), optional :: env
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
    integer :: cmdstat
    type(result_group_type) :: scene_result_fields
    call write_file(deck, [line])
    call execute_command_line("rm -f "//out, wait=.true., cmdstat=cmdstat)
    if (present(env)) then
      call run_app("-q "//deck//" -o "//out, rc, stdout, stderr, env=env)
    else
      call run_app("-q "//deck//" -o "//out, rc, stdout, stderr)
    end if
    call check(error, rc, 0, message="exit status; stderr: "//stderr)
    if (allocated(error)) return
    open(newunit=unit, file=out, status="old", action="read", iostat=ios)
    call check(error, ios, 0, message="result file")
    if (allocated(error)) return
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
    res = scene_result_type(n_particles, n_dof, n_springs, max_contacts, omega_max, dt_critical_eigen, &
      dt_critical_bound, dt_contact_rule, dt_critical_damped, damping_ratio_top, dt_used, energy_drift, &
      max_overlap, steps, eigen_computed, blew_up)
    call check(error, all(ieee_is_finite([omega_max, dt_critical_eigen, dt_critical_bound, &
      dt_contact_rule, dt_critical_damped, damping_ratio_top, dt_used, energy_drift, max_overlap])), &
      "every real in the result is finite")
  end subroutine expect_result

  !> Run the deck; expect exit 2 and one line on stderr starting with `expected`
  !> (after "demstep: DECK: "), and no output file.
  subroutine expect_refusal(error, line, expected)
    type(error_type), allocatable, intent(out) :: error
    character(len=*), intent(in) :: line, expected
    integer :: rc
    character(len=:), allocatable :: stdout, stderr
    integer :: cmdstat
    call write_file(deck, [line])
    call execute_command_line("rm -f "//out, wait=.true., cmdstat=cmdstat)
    call run_app(deck//" -o "//out, rc, stdout, stderr)
    call check(error, rc, 2, message="exit status for '"//line(:min(len(line), 200))//"'")
    if (allocated(error)) return
    if (index(stderr, "demstep: "//deck//": "//expected) /= 1) then
      call test_failed(error, "stderr '"//stderr//"' does not start with 'demstep: "//deck//": "// &
        expected//"'")
      return
    end if
    call check(error, count(transfer(stderr, "a", len(stderr)) == new_line("a")), 1, &
      message="one line on stderr: "//stderr)
    if (allocated(error)) return
    call check(error, .not. file_exists(out), "no output file")
  end subroutine expect_refusal

  !> The deck variables of the damped model: each bad value refused naming
  !> it, and a good deck's damped limit exact and below the undamped one.
  subroutine test_dashpot_inputs(error)
    type(error_type), allocatable, intent(out) :: error
    type(scene_result_type) :: res
    character(len=*), parameter :: g = "&scene dim = 3, position = 0, 0, 0, 1.9, 0, 0, radius = 1.0, " &
      //"mass = 1.0, k_normal = 1e3, k_tangential = 300, "
    call expect_result(error, g//"effects = 'contacts', 'damping', damping_ratio = 0.2, " &
      //"damping_ratio_tangential = 0.1, rolling_ratio = 0.5, twisting_ratio = 0.2, " &
      //"damping_ratio_rolling = 0.3, drag = 0.1 /", res)
    if (allocated(error)) return
    call check(error, res%dt_critical_damped > 0.0_dp .and. res%dt_critical_damped < res%dt_critical_eigen, &
      "damped below undamped")
    if (allocated(error)) return
    call expect_refusal(error, g//"effects = 'contacts', 'damping', damping_ratio = 0.2, " &
      //"damping_ratio_tangential = -1 /", "&scene: damping_ratio_tangential: must be in [0, 1e100]")
    if (allocated(error)) return
    call expect_refusal(error, g//"effects = 'contacts', 'damping', damping_ratio = 0.2, " &
      //"damping_ratio_rolling = 2e100 /", "&scene: damping_ratio_rolling: must be in [0, 1e100]")
    if (allocated(error)) return
    call expect_refusal(error, g//"effects = 'contacts', 'damping', damping_ratio = 0.2, drag = -1 /", &
      "&scene: drag: must be >= 0 and finite")
    if (allocated(error)) return
    call expect_refusal(error, g//"drag = 0.5 /", "&scene: effects: dashpots (damping_ratio_tangential, " &
      //"damping_ratio_rolling, drag) need the 'damping' effect")
    if (allocated(error)) return
    call expect_refusal(error, g//"rolling_ratio = -0.5 /", "&scene: rolling_ratio: must be >= 0 and finite")
    if (allocated(error)) return
    call expect_refusal(error, g//"twisting_ratio = -0.5 /", "&scene: twisting_ratio: must be >= 0 and finite")
    if (allocated(error)) return
    call expect_refusal(error, g//"rolling_friction = -1.8e308 /", "&scene: rolling_friction:")
  end subroutine test_dashpot_inputs

  subroutine test_large_tables(error)
    type(error_type), allocatable, intent(out) :: error
    type(scene_result_type) :: res
    ! a 2D chain, 1 apart, radius 0.55: 99999 contacts
    call write_table(work_dir//"/chain.txt", 100000, chain_row)
    call expect_result(error, "&scene dim = 2, particles_file = 'chain.txt', k_normal = 1e4 /", res)
    if (allocated(error)) return
    call check(error, res%n_particles == 100000 .and. res%n_springs == 99999 .and. res%n_dof == 200000, &
      "chain: particles, springs and dof")
    if (allocated(error)) return
    ! 1e5 particles, 1 apart, each 0.1 into the wall y = 0: 1e5 wall contacts
    call write_table(work_dir//"/wall.txt", 100000, wall_row)
    call expect_result(error, "&scene dim = 2, particles_file = 'wall.txt', effects = 'walls', " &
      //"walls = 0.0, 0.0, 0.0, 1.0, k_normal = 1e4 /", res)
    if (allocated(error)) return
    call check(error, res%n_particles == 100000 .and. res%n_springs == 100000, "wall: springs")
    if (allocated(error)) return
    ! each particle alone on the wall: the bound is exact, 2/sqrt(k/m)
    call check(error, res%dt_critical_bound, 2.0_dp/sqrt(1.0e4_dp), thr=1.0e-12_dp, rel=.true., &
      message="wall: bound")
  end subroutine test_large_tables

  subroutine test_large_inline(error)
    type(error_type), allocatable, intent(out) :: error
    type(scene_result_type) :: res
    character(len=:), allocatable :: line
    integer, parameter :: n = 100000
    integer :: i, k
    character(len=16) :: buf
    ! the chain of test_large_tables, as 2e5 inline coordinates (one text, filled once)
    allocate(character(len=16*n + 200) :: line)
    k = 0
    call put("&scene dim = 2, k_normal = 1e4, mass = 1, radius = 0.55, position = ")
    do i = 0, n - 1
      write(buf, '(i0, a)') i, ", 0, "
      call put(trim(buf))
    end do
    call put(" /")
    call expect_result(error, line(1:k), res)
    if (allocated(error)) return
    call check(error, res%n_particles == n .and. res%n_springs == n - 1, &
      "inline chain: particles and springs")
  contains
    subroutine put(text)
      character(len=*), intent(in) :: text
      line(k+1:k+len(text)) = text
      k = k + len(text)
    end subroutine put
  end subroutine test_large_inline

  function chain_row(i) result(text)
    integer, intent(in) :: i
    character(len=:), allocatable :: text
    character(len=64) :: buf
    write(buf, '(i0, a)') i - 1, " 0 0 0 1 0.55 0"
    text = trim(buf)
  end function chain_row

  function wall_row(i) result(text)
    integer, intent(in) :: i
    character(len=:), allocatable :: text
    character(len=64) :: buf
    write(buf, '(i0, a)') i - 1, " 0.3 0 0 1 0.4 0"
    text = trim(buf)
  end function wall_row

  !> 31^3 = 29791 particles on a unit lattice, radius 0.51: each touches its 6
  !> neighbours, 3*31*31*30 contacts.
  subroutine test_touching(error)
    type(error_type), allocatable, intent(out) :: error
    type(scene_result_type) :: res
    call write_table(work_dir//"/touch.txt", 31**3, lattice_row)
    call expect_result(error, "&scene dim = 3, particles_file = 'touch.txt', k_normal = 1e4 /", res)
    if (allocated(error)) return
    call check(error, res%n_particles == 29791 .and. res%n_springs == 3*31*31*30, &
      "touching: "//real_str(real(res%n_springs, dp))//" springs")
    if (allocated(error)) return
    ! above the dense limit Lanczos gives the exact value (it was silently skipped
    ! before): normal springs only, so every lattice row is an open chain of 31,
    ! omega_max^2 = 4 (k/m) sin^2(30 pi/62), each top eigenvalue 2883-fold
    ! degenerate; the 1e-10 residual bounds the eigenvalue's error
    call check(error, res%n_dof == 89373 .and. res%eigen_computed, "89373 dof, computed")
    if (allocated(error)) return
    call check(error, res%omega_max**2, 4.0e4_dp*sin(30.0_dp*acos(-1.0_dp)/62.0_dp)**2, rel=.true., &
      thr=1.0e-9_dp, message="the lattice's omega_max by Lanczos")
  end subroutine test_touching

  function lattice_row(p) result(text)
    integer, intent(in) :: p
    character(len=:), allocatable :: text
    character(len=64) :: buf
    integer :: i, j, k
    i = mod(p - 1, 31)
    j = mod((p - 1)/31, 31)
    k = (p - 1)/961
    write(buf, '(3(i0, 1x), a)') i, j, k, "0 0 0 1 0.51 0"
    text = trim(buf)
  end function lattice_row

  !> 3000 distinct points in a unit cube, radius 2: every pair overlaps, 4498500
  !> contacts, found and linearised in time linear in contacts.
  subroutine test_all_overlapping(error)
    type(error_type), allocatable, intent(out) :: error
    type(scene_result_type) :: res
    character(len=:), allocatable :: line
    character(len=40) :: buf
    integer :: i, pos
    ! (filled in place: an assignment to the whole string would reallocate it)
    allocate(character(len=3000*40 + 200) :: line)
    pos = 0
    ! a deterministic scatter (golden-ratio sequences): distinct points
    do i = 1, 3000
      write(buf, '(3(f0.8, ", "))') modulo(0.6180339887_dp*i, 1.0_dp), &
        modulo(0.7548776662_dp*i, 1.0_dp), modulo(0.5698402910_dp*i, 1.0_dp)
      line(pos + 1:pos + len_trim(buf) + 1) = trim(buf)//" "
      pos = pos + len_trim(buf) + 1
    end do
    call expect_result(error, "&scene dim = 3, position = "//line(:pos - 2)//", mass = 1.0, radius = 2.0, " &
      //"k_normal = 1e4 /", res)
    if (allocated(error)) return
    call check(error, res%n_springs, 4498500, message="springs")
  end subroutine test_all_overlapping

  subroutine test_one_point(error)
    type(error_type), allocatable, intent(out) :: error
    call expect_refusal(error, "&scene dim = 3, position = 3000*0.0, mass = 1.0, radius = 0.5, k_normal = 1e4 /", &
      "&scene: position: particles 1 and 2 are at the same point")
  end subroutine test_one_point

  subroutine test_not_text(error)
    type(error_type), allocatable, intent(out) :: error
    integer :: unit
    call expect_refusal(error, "&scene dim = 2, particles_file = '/dev/zero', k_normal = 1e4 /", &
      "&scene: particles_file: /dev/zero: line 1: not a text file (byte 0 in column 1)")
    if (allocated(error)) return
    ! a binary file after a good row
    open(newunit=unit, file=work_dir//"/binary.txt", access="stream", status="replace", action="write")
    write(unit) "0 0 0 0 1 0.6 0"//new_line("a")//"1 0 "//achar(1)//achar(200)//"xyz"//new_line("a")
    close(unit)
    call expect_refusal(error, "&scene dim = 2, particles_file = 'binary.txt', k_normal = 1e4 /", &
      "&scene: particles_file: "//work_dir//"/binary.txt: line 2: not a text file (byte 1 in column 5)")
    if (allocated(error)) return
    ! one line of 100000 characters
    open(newunit=unit, file=work_dir//"/long.txt", access="stream", status="replace", action="write")
    write(unit) repeat("1 ", 50000)//new_line("a")
    close(unit)
    call expect_refusal(error, "&scene dim = 2, particles_file = 'long.txt', k_normal = 1e4 /", &
      "&scene: particles_file: "//work_dir//"/long.txt: line 1: longer than 64512 characters")
  end subroutine test_not_text

  subroutine test_extra_column(error)
    type(error_type), allocatable, intent(out) :: error
    call write_file(work_dir//"/extra.txt", [character(len=40) :: "0 0 0 0 1 0.6 0", "1 0 0 0 1 0.6 0 5"])
    call expect_refusal(error, "&scene dim = 2, particles_file = 'extra.txt', k_normal = 1e4 /", &
      "&scene: particles_file: "//work_dir//"/extra.txt: line 2: expected 7 numbers, found 8")
    if (allocated(error)) return
    ! a list-directed repeat would hide an eighth value in seven fields
    call write_file(work_dir//"/extra.txt", [character(len=40) :: "0 0 0 0 1 0.6 0", "1 0 0 0 1 0.6 2*0"])
    call expect_refusal(error, "&scene dim = 2, particles_file = 'extra.txt', k_normal = 1e4 /", &
      "&scene: particles_file: "//work_dir//"/extra.txt: line 2: cannot read '1 0 0 0 1 0.6 2*0'")
    if (allocated(error)) return
    ! commas and tabs separate fields too
    call write_file(work_dir//"/extra.txt", [character(len=40) :: "0, 0, 0, 0, 1, 0.6, 0", &
      "1"//achar(9)//"0 0 0 1 0.6 0 7"])
    call expect_refusal(error, "&scene dim = 2, particles_file = 'extra.txt', k_normal = 1e4 /", &
      "&scene: particles_file: "//work_dir//"/extra.txt: line 2: expected 7 numbers, found 8")
  end subroutine test_extra_column

  !> radius 1e308 and damping_ratio 1e308 are refused with the range; mass
  !> 1e-308 and k_normal 1e308 are computed: two free particles on one contact,
  !> omega_max = sqrt(2 k/m) (1e-13 relative: a few roundings).
  subroutine test_extremes(error)
    type(error_type), allocatable, intent(out) :: error
    character(len=*), parameter :: g = "&scene dim = 1, position = 0.0, 1.0, radius = 0.6, "
    type(scene_result_type) :: res
    call expect_refusal(error, "&scene dim = 1, position = 0.0, 1.0, radius = 1e308, mass = 1.0, " &
      //"k_normal = 1e4, duration = 1.0, n_per_period = 20 /", "&scene: radius: particle 1: must be at " &
      //"most 1e150")
    if (allocated(error)) return
    call expect_refusal(error, g//"mass = 1.0, k_normal = 1e4, effects = 'contacts', 'damping', " &
      //"damping_ratio = 1e308 /", "&scene: damping_ratio: must be in [0, 1e100]")
    if (allocated(error)) return
    call expect_result(error, g//"mass = 1e-308, k_normal = 1e4 /", res)
    if (allocated(error)) return
    call check(error, res%omega_max, sqrt(2.0_dp)*1.0e2_dp/1.0e-154_dp, thr=1.0e-13_dp, rel=.true., &
      message="mass 1e-308: omega_max")
    if (allocated(error)) return
    call expect_result(error, g//"mass = 1.0, k_normal = 1e308 /", res)
    if (allocated(error)) return
    call check(error, res%omega_max, sqrt(2.0_dp)*1.0e154_dp, thr=1.0e-13_dp, rel=.true., &
      message="k_normal 1e308: omega_max")
    if (allocated(error)) return
    call check(error, res%dt_contact_rule, 2.0_dp*sqrt(0.5_dp)/1.0e154_dp, thr=1.0e-13_dp, rel=.true., &
      message="k_normal 1e308: contact rule")
  end subroutine test_extremes

  subroutine test_no_stiffness(error)
    type(error_type), allocatable, intent(out) :: error
    character(len=*), parameter :: g = "&scene dim = 1, position = 0.0, 3.0, radius = 0.6, mass = 1.0, "
    call expect_refusal(error, g//"k_normal = 1e4, fixed = 1, 2 /", &
      "&scene: fixed: every particle is fixed: the scene has no stiffness")
    if (allocated(error)) return
    call write_file(work_dir//"/empty.txt", [character(len=20) :: "# no bonds"])
    call expect_refusal(error, g//"bonds_file = 'empty.txt', k_bond = 1.0, effects = 'none' /", &
      "&scene: bonds_file: "//work_dir//"/empty.txt: holds no bonds")
    if (allocated(error)) return
    call expect_refusal(error, g//"effects = 'none' /", "&scene: effects: the scene has no stiffness")
    if (allocated(error)) return
    call expect_refusal(error, g//"k_normal = 1e4 /", "&scene: position: the scene has no stiffness")
  end subroutine test_no_stiffness

  !> A pair from a 10-column particle table (with inertia), its contact from a
  !> contacts_file, through a periodic cell (the second particle wrapped in);
  !> each bad input refused with the line.
  subroutine test_assembly_inputs(error)
    type(error_type), allocatable, intent(out) :: error
    type(scene_result_type) :: res
    character(len=*), parameter :: g = "&scene dim = 3, particles_file = 'p.txt', contacts_file = 'c.txt', " &
      //"periodic = T, F, F, "
    call write_file(work_dir//"/p.txt", [character(len=60) :: "# x y z vx vy vz m r fixed inertia", &
      "0.1 0 0  0 0 0  1 0.6 0 0.4", "5.1 0 0  0 0 0  1 0.6 0 0.4"])
    call write_file(work_dir//"/c.txt", [character(len=20) :: "# i j k_n k_t", "1 2 100 80"])
    ! x = 5.1 wraps to 1.1: one contact; the tangential-rotational mode is on top:
    ! omega^2 = k_t (2/m + 2 c^2/I) = 80 x 3.25 = 260 > 2 k_n = 200, with the
    ! lever arm to the contact point c = r - d/2 = 0.5
    call expect_result(error, g//"cell_hi = 4.0, 1.0, 1.0 /", res)
    if (allocated(error)) return
    call check(error, res%n_springs, 1, "one contact")
    if (allocated(error)) return
    call check(error, res%omega_max, sqrt(260.0_dp), rel=.true., thr=1.0e-12_dp, message="omega_max")
    if (allocated(error)) return
    call expect_refusal(error, g//"cell_hi = 2.0, 1.0, 1.0 /", "&scene: cell_hi: axis 1: the periodic cell " &
      //"must be at least twice the longest contact")
    if (allocated(error)) return
    call expect_refusal(error, g//"cell_lo = 0.0, 0.0, 0.0 /", "&scene: cell_hi: required with periodic axes")
    if (allocated(error)) return
    call write_file(work_dir//"/c.txt", [character(len=20) :: "# i j k_n k_t", "1 3 100 60"])
    call expect_refusal(error, g//"cell_hi = 4.0, 1.0, 1.0 /", "&scene: contacts_file: "//work_dir// &
      "/c.txt: line 2: names a missing particle (1, 3; there are 2)")
    if (allocated(error)) return
    call write_file(work_dir//"/c.txt", [character(len=20) :: "1 2 100 -1"])
    call expect_refusal(error, g//"cell_hi = 4.0, 1.0, 1.0 /", "&scene: contacts_file: "//work_dir// &
      "/c.txt: line 1: k_t must be >= 0")
    if (allocated(error)) return
    call write_file(work_dir//"/c.txt", [character(len=20) :: "1 2 100"])
    call expect_refusal(error, g//"cell_hi = 4.0, 1.0, 1.0 /", "&scene: contacts_file: "//work_dir// &
      "/c.txt: line 1: expected 4, 6 or 10 numbers, found 3")
    if (allocated(error)) return
    call write_file(work_dir//"/p.txt", [character(len=60) :: "0.1 0 0  0 0 0  1 0.6 0 0.4", &
      "5.1 0 0  0 0 0  1 0.6 0 0"])
    call expect_refusal(error, g//"cell_hi = 4.0, 1.0, 1.0 /", "&scene: particles_file: "//work_dir// &
      "/p.txt: inertia: particle 2: must be > 0")
    if (allocated(error)) return
    ! materials per type: the pair's k_n, k_t from the type table
    call expect_result(error, "&scene dim = 2, position = 0.0, 0.0, 1.0, 0.0, radius = 0.6, mass = 1.0, " &
      //"types = 1, 2, type_k_normal = 1.0, 100.0, 100.0, 1.0, type_k_tangential = 0.0, 60.0, 60.0, 0.0 /", res)
    if (allocated(error)) return
    ! omega^2 = k_t (2/m + 2 c^2/I) = 60 x (2 + 3.47) = 328 > 2 k_n = 200, with the
    ! lever arm to the contact point c = r - d/2 = 0.5 and I = 2/5 m r^2
    call check(error, res%omega_max, sqrt(60.0_dp*(2.0_dp + 2.0_dp*0.5_dp**2/(0.4_dp*0.6_dp**2))), rel=.true., &
      thr=1.0e-12_dp, message="types: omega_max")
    if (allocated(error)) return
    call expect_refusal(error, "&scene dim = 2, position = 0.0, 0.0, 1.0, 0.0, radius = 0.6, mass = 1.0, " &
      //"types = 1, 3, type_k_normal = 1.0, 100.0, 100.0, 1.0 /", "&scene: types: particle 2: type 3 is " &
      //"not one of the 2 materials")
    if (allocated(error)) return
    call expect_refusal(error, "&scene dim = 2, position = 0.0, 0.0, 1.0, 0.0, radius = 0.6, mass = 1.0, " &
      //"types = 1, 2, type_k_normal = 1.0, 100.0, 90.0, 1.0 /", "&scene: type_k_normal: must be symmetric")
    if (allocated(error)) return
    call expect_refusal(error, "&scene dim = 2, position = 0.0, 0.0, 1.0, 0.0, radius = 0.6, mass = 1.0, " &
      //"types = 1, 2, type_k_normal = 1.0, 100.0, 100.0 /", "&scene: type_k_normal: needs nt x nt values")
    if (allocated(error)) return
    call expect_refusal(error, "&scene dim = 2, position = 0.0, 0.0, 1.0, 0.0, radius = 0.6, mass = 1.0, " &
      //"law = 'hertz', types = 1, 1, young = 1e9, poisson = 0.7 /", "&scene: poisson: must be in (-1, 0.5]")
  end subroutine test_assembly_inputs

  !> Particle numbers in contacts_file and bonds_file are integers: `1.5` and
  !> `4294967297` (which wrapped around to 1) refused with the line and column;
  !> so is a fixed flag other than 0 or 1 in a particles table.
  subroutine test_particle_numbers(error)
    type(error_type), allocatable, intent(out) :: error
    character(len=*), parameter :: g = "&scene dim = 1, position = 0.0, 1.0, radius = 0.6, mass = 1.0, "
    call write_file(work_dir//"/c.txt", [character(len=30) :: "# i j k_n k_t", "1 1.5 100 60"])
    call expect_refusal(error, g//"contacts_file = 'c.txt' /", "&scene: contacts_file: "//work_dir// &
      "/c.txt: line 2: column 2: '1.5' is not an integer (a particle number)")
    if (allocated(error)) return
    call write_file(work_dir//"/c.txt", [character(len=30) :: "4294967297 2 100 60"])
    call expect_refusal(error, g//"contacts_file = 'c.txt' /", "&scene: contacts_file: "//work_dir// &
      "/c.txt: line 1: column 1: particle number '4294967297' must lie in [1, 2147483647]")
    if (allocated(error)) return
    call write_file(work_dir//"/b.txt", [character(len=30) :: "1 1.5"])
    call expect_refusal(error, g//"bonds_file = 'b.txt', k_bond = 1.0, effects = 'none' /", "&scene: " &
      //"bonds_file: "//work_dir//"/b.txt: line 1: column 2: '1.5' is not an integer (a particle number)")
    if (allocated(error)) return
    call write_file(work_dir//"/b.txt", [character(len=30) :: "# i j", "1 2", "4294967297 2"])
    call expect_refusal(error, g//"bonds_file = 'b.txt', k_bond = 1.0, effects = 'none' /", "&scene: " &
      //"bonds_file: "//work_dir//"/b.txt: line 3: column 1: particle number '4294967297' must lie in " &
      //"[1, 2147483647]")
    if (allocated(error)) return
    ! the fixed column of a particles table: 0 or 1, named by line and column
    call write_file(work_dir//"/p.txt", [character(len=30) :: "0 0 1 0.6 0", "# x v m r fixed", "1 0 1 0.6 0.5"])
    call expect_refusal(error, "&scene dim = 1, particles_file = 'p.txt', k_normal = 1e4 /", "&scene: " &
      //"particles_file: "//work_dir//"/p.txt: line 3: column 5: the fixed column must be 0 or 1")
  end subroutine test_particle_numbers

  !> A run of 1e9 steps says up front how much it will do and then shows
  !> progress (it is stopped after 8 s by `timeout`); with -q it says nothing;
  !> 1e18 steps are refused with the duration that fits.
  subroutine test_long_runs(error)
    type(error_type), allocatable, intent(out) :: error
    character(len=*), parameter :: g = "&scene dim = 1, position = 0.0, 1.0, radius = 0.6, mass = 1.0, " &
      //"k_normal = 1e4, "
    integer :: rc, k
    character(len=:), allocatable :: stdout, stderr
    call expect_refusal(error, g//"duration = 1e9, dt = 1e-9 /", "&scene: duration: 1e9 at dt = 1e-9 is 1e18 " &
      //"steps of 2 particles")
    if (allocated(error)) return
    call write_file(deck, [g//"duration = 1e7, dt = 1e-2 /"])
    call run_app(deck, rc, stdout, stderr, env="timeout 8")
    call check(error, rc, 124, message="stopped by timeout; stderr: "//stderr)
    if (allocated(error)) return
    call check(error, index(stderr, "demstep: &scene: 1000000000 steps of 2 particles, about ") == 1 .and. &
      index(stderr, " s per particle-step measured)") > 0, "announced up front: "//stderr)
    if (allocated(error)) return
    k = index(stderr, new_line("a"))
    call check(error, index(stderr(k + 1:), "demstep: &scene: ") == 1 .and. &
      index(stderr(k + 1:), " of 1000000000 steps (") > 0, "then progress: "//stderr)
    if (allocated(error)) return
    call run_app("-q "//deck, rc, stdout, stderr, env="timeout 2")
    call check(error, rc == 124 .and. len(stderr) == 0, "quiet: nothing on stderr: "//stderr)
  end subroutine test_long_runs

  !> The solver choice through the deck: 'none' gives the bound only, 'lanczos'
  !> the dense value (1e-10: the tolerance bounds the residual, the Rayleigh
  !> quotient's error is below it); a word outside the list and a tolerance
  !> outside [2.2e-16, 0.1] are refused naming the deck's variable.
  subroutine test_eigen_solver(error)
    type(error_type), allocatable, intent(out) :: error
    type(scene_result_type) :: dense, lanczos, none
    character(len=*), parameter :: pair = "&scene dim = 2, position = 0,0, 1.9,0, 3.8,0, mass = 1,1,1, " &
      //"radius = 1,1,1, k_normal = 100, "
    call expect_result(error, pair//"eigen_solver = 'dense' /", dense)
    if (allocated(error)) return
    call expect_result(error, pair//"eigen_solver = 'Lanczos' /", lanczos)
    if (allocated(error)) return
    call check(error, lanczos%omega_max, dense%omega_max, rel=.true., thr=1.0e-10_dp, message="lanczos")
    if (allocated(error)) return
    ! a chain of three: omega_max^2 = 3 k/m
    call check(error, dense%omega_max, sqrt(300.0_dp), rel=.true., thr=1.0e-14_dp, message="dense")
    if (allocated(error)) return
    call expect_result(error, pair//"eigen_solver = 'none' /", none)
    if (allocated(error)) return
    call check(error, .not. none%eigen_computed .and. none%dt_critical_bound == dense%dt_critical_bound, &
      "'none': the bound only")
    if (allocated(error)) return
    call expect_refusal(error, pair//"eigen_solver = 'fast' /", &
      "&scene: eigen_solver: unknown word 'fast' (auto, dense, lanczos, none)")
    if (allocated(error)) return
    call expect_refusal(error, pair//"eigen_solver = 'lanczos', eigen_tolerance = 1.0 /", &
      "&scene: eigen_tolerance: 1 is outside [2.2e-16, 0.1]")
  end subroutine test_eigen_solver

end module test_app_scene
