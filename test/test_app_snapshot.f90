!> End-to-end tests of `&scene` with `snapshot_file`: each format (a LIGGGHTS
!> dump and data file written by LIGGGHTS, a Yade export written by Yade, all
!> in example/), the file's box as the periodic cell, the materials from a
!> `&material` group against the same scene given inline and against the
!> LIGGGHTS Hooke formula in quad precision, the peers' rules, and each bad
!> input in one line naming the variable (and the file and line).
module test_app_snapshot
  use testdrive, only: new_unittest, unittest_type, error_type, check
  use demstep, only: dp, i8
  use test_support, only: run_app, write_file, read_file, work_dir, count_lines
  use, intrinsic :: iso_fortran_env, only: qp => real128
  use demstep_results, only: result_group_type
  use test_support, only: read_group, take
  implicit none
  private
  public :: collect_app_snapshot

  real(qp), parameter :: pq = 3.14159265358979323846264338327950288_qp
  character(len=*), parameter :: deck = work_dir//"/snapshot_deck.nml"
  character(len=*), parameter :: inline = work_dir//"/snapshot_inline.nml"
  character(len=*), parameter :: out = work_dir//"/snapshot_out.nml"
  character(len=*), parameter :: out2 = work_dir//"/snapshot_out2.nml"
  character(len=*), parameter :: dump = work_dir//"/snap.dump"
  !> The scalars of `&scene_result` compared between two runs.
  character(len=*), parameter :: compared(5) = [character(len=18) :: "OMEGA_MAX", "DT_CRITICAL_EIGEN", &
    "DT_CRITICAL_BOUND", "DT_CONTACT_RULE", "DT_CRITICAL_DAMPED"]

  !> `&snapshot_result`, as a user's script reads it back.
  type :: snapshot_result_type
    character(len=11) :: format = ""
    integer :: n_particles = -1, n_types = -1, frame = -1, n_frames = -1
    integer(i8) :: timestep = -1
    logical :: periodic(3) = .false., have_materials = .false.
    real(dp) :: box_lo(3) = -1, box_hi(3) = -1, peer_dt(9) = -1, peer_ratio(9) = -1, dt_exact = -1
    character(len=20) :: peer_rules(9) = ""
  end type snapshot_result_type

contains

  subroutine collect_app_snapshot(testsuite)
    type(unittest_type), allocatable, intent(out) :: testsuite(:)
    testsuite = [ &
      new_unittest("LIGGGHTS dump: peers' rules beside the exact limit, one recommended dt", test_dump), &
      new_unittest("LIGGGHTS data file: the same packing as its dump", test_data), &
      new_unittest("Yade export: matIds as types, FrictPhys springs undamped", test_yade), &
      new_unittest("the box's pp axes are the periodic cell; same numbers as inline", test_box_inline), &
      new_unittest("&material Hertz: same numbers as the inline types", test_hertz_inline), &
      new_unittest("&material liggghts_hooke: k_n of LIGGGHTS' formula (quad)", test_hooke_quad), &
      new_unittest("LIGGGHTS' own Hooke k_n, recovered from a run, is liggghts_hooke's", test_liggghts_kn), &
      new_unittest("a bad file: one line naming the file and the line", test_bad_file), &
      new_unittest("exclusive inputs and missing materials refused naming the variable", test_refused), &
      new_unittest("a packing's &material reports single contacts: one recommended dt, either order", &
        test_one_recommended) &
      ]
  end subroutine collect_app_snapshot

  !> The value of a scalar `NAME=value` of a result file (the first one).
  real(dp) function scalar(text, name) result(x)
    character(len=*), intent(in) :: text, name
    integer :: k, e, ios
    x = -huge(1.0_dp)
    k = index(text, " "//name//"=")
    if (k == 0) return
    k = k + len(name) + 2
    e = index(text(k:), ",") + k - 2
    read(text(k:e), *, iostat=ios) x
    if (ios /= 0) x = -huge(1.0_dp)
  end function scalar

  !> Run `args`; expect a clean exit and read `&snapshot_result` back from `path`.
  subroutine expect_run(error, args, path, res, text, stdout)
    type(error_type), allocatable, intent(out) :: error
    character(len=*), intent(in) :: args, path
    type(snapshot_result_type), intent(out) :: res
    character(len=:), allocatable, intent(out) :: text, stdout
    integer :: rc, unit, ios
    character(len=:), allocatable :: stderr
    character(len=11) :: format
    integer :: n_particles, n_types, frame, n_frames
    integer(i8) :: timestep
    logical :: periodic(3), have_materials
    real(dp) :: box_lo(3), box_hi(3), peer_dt(9), peer_ratio(9), dt_exact
    character(len=20) :: peer_rules(9)
    type(result_group_type) :: snapshot_result_fields
    call execute_command_line("rm -f "//path, cmdstat=ios)
    call run_app(args//" -o "//path, rc, stdout, stderr)
    call check(error, rc == 0 .and. len(stderr) == 0, "runs cleanly: "//args//": "//stderr)
    if (allocated(error)) return
    call read_file(path, text)
    open(newunit=unit, file=path, status="old", action="read", iostat=ios)
    if (ios == 0) call read_group(unit, "snapshot_result", snapshot_result_fields, ios)
    if (ios == 0) call take(snapshot_result_fields, "format", format, ios)
    if (ios == 0) call take(snapshot_result_fields, "n_particles", n_particles, ios)
    if (ios == 0) call take(snapshot_result_fields, "n_types", n_types, ios)
    if (ios == 0) call take(snapshot_result_fields, "frame", frame, ios)
    if (ios == 0) call take(snapshot_result_fields, "n_frames", n_frames, ios)
    if (ios == 0) call take(snapshot_result_fields, "timestep", timestep, ios)
    if (ios == 0) call take(snapshot_result_fields, "periodic", periodic, ios)
    if (ios == 0) call take(snapshot_result_fields, "box_lo", box_lo, ios)
    if (ios == 0) call take(snapshot_result_fields, "box_hi", box_hi, ios)
    if (ios == 0) call take(snapshot_result_fields, "have_materials", have_materials, ios)
    if (ios == 0) call take(snapshot_result_fields, "peer_rules", peer_rules, ios)
    if (ios == 0) call take(snapshot_result_fields, "peer_dt", peer_dt, ios)
    if (ios == 0) call take(snapshot_result_fields, "peer_ratio", peer_ratio, ios)
    if (ios == 0) call take(snapshot_result_fields, "dt_exact", dt_exact, ios)
    call check(error, ios, 0, message="&snapshot_result reads back")
    if (allocated(error)) return
    close(unit)
    res = snapshot_result_type(format, n_particles, n_types, frame, n_frames, timestep, periodic, &
      have_materials, box_lo, box_hi, peer_dt, peer_ratio, dt_exact, peer_rules)
  end subroutine expect_run

  !> Run `args`; expect exit 2 and one line on stderr holding every piece of `wants`.
  subroutine expect_refusal(error, args, wants)
    type(error_type), allocatable, intent(out) :: error
    character(len=*), intent(in) :: args
    character(len=*), intent(in) :: wants(:)
    integer :: rc, k
    character(len=:), allocatable :: stdout, stderr
    call run_app(args, rc, stdout, stderr)
    call check(error, rc == 2 .and. count_lines(stderr) == 1 .and. index(stderr, "demstep: ") == 1, &
      "refused in one line: "//stderr)
    if (allocated(error)) return
    do k = 1, size(wants)
      call check(error, index(stderr, trim(wants(k))) > 0, "message names '"//trim(wants(k))//"': "//stderr)
      if (allocated(error)) return
    end do
  end subroutine expect_refusal

  !> Two runs' `&scene_result` scalars agree to 1e-12 relative.
  subroutine same_numbers(error, a, b)
    type(error_type), allocatable, intent(out) :: error
    character(len=*), intent(in) :: a, b
    integer :: k
    real(dp) :: x, y
    ! the same particles, springs and masses give the same matrix: only the
    ! order of summation may differ (a few roundings, far below 1e-12)
    do k = 1, size(compared)
      x = scalar(a, trim(compared(k)))
      y = scalar(b, trim(compared(k)))
      call check(error, x > 0.0_dp .and. abs(x - y) <= 1.0e-12_dp*abs(y), trim(compared(k))// &
        ": snapshot and inline agree")
      if (allocated(error)) return
    end do
  end subroutine same_numbers

  !> How often `piece` stands in `text`.
  pure integer function occurrences(text, piece) result(n)
    character(len=*), intent(in) :: text, piece
    integer :: k, at
    n = 0
    at = 1
    do
      k = index(text(at:), piece)
      if (k == 0) return
      n = n + 1
      at = at + k + len(piece) - 1
    end do
  end function occurrences

  !> A deck whose &scene takes its materials from &material prints one
  !> recommended dt (the packing's), whichever group comes first, as the report's
  !> last line; the &material report is marked as single contacts. A &scene with
  !> stiffness of its own: still one recommended dt, the scene's, last (the
  !> &material's is its single-contact step).
  subroutine test_one_recommended(error)
    type(error_type), allocatable, intent(out) :: error
    type(snapshot_result_type) :: res
    character(len=:), allocatable :: text, stdout, first, last
    real(dp) :: dt_last
    integer :: ios
    character(len=80), parameter :: scene(3) = [character(len=80) :: "&scene", &
      "dim = 3, snapshot_file = '../../example/liggghts_pour.dump' /", ""]
    character(len=80), parameter :: material(4) = [character(len=80) :: "&material", &
      "young = 1.0e7, poisson = 0.25, density = 2500.0, radius = 1.0e-3, 0.8e-3,", &
      "restitution = 0.9, impact_velocity = 1.0, code = 'liggghts_hertz' /", ""]
    character(len=*), parameter :: line = "recommended dt = "
    call expect_run(error, "example/snapshot_liggghts.nml", out, res, text, stdout)
    if (allocated(error)) return
    call check(error, occurrences(stdout, line) == 1 .and. occurrences(stdout, "single-contact step") == 1 &
      .and. index(stdout, "(single contacts of each pair of types;") > 0, &
      "the example: one recommended dt, the &material marked single-contact: "//stdout)
    if (allocated(error)) return
    ! the packing's recommendation is 0.9 of its damped limit, as in test_dump
    call check(error, scalar(text, "DT_RECOMMENDED") == 0.9_dp*scalar(text, "DT_CRITICAL_DAMPED"), &
      "the first DT_RECOMMENDED is the packing's")
    if (allocated(error)) return
    first = stdout(index(stdout, line):)
    first = first(:index(first, new_line("a")))
    ! &material before &scene: the same single recommended dt
    call write_file(deck, [material, scene])
    call expect_run(error, deck, out, res, text, stdout)
    if (allocated(error)) return
    call check(error, occurrences(stdout, line) == 1 .and. occurrences(stdout, "single-contact step") == 1 &
      .and. index(stdout, first) > 0, "&material first: one recommended dt, the packing's: "//stdout)
    if (allocated(error)) return
    ! the scene's own k_normal: the &material group is not the packing's, it recommends its own dt
    call write_file(deck, [character(len=80) :: scene(1), &
      "dim = 3, snapshot_file = '../../example/liggghts_pour.dump', k_normal = 1.0e3 /", "", material])
    call expect_run(error, deck, out, res, text, stdout)
    if (allocated(error)) return
    call check(error, occurrences(stdout, line) == 1 .and. occurrences(stdout, "single-contact step") == 1, &
      "a scene with its own stiffness: one recommended dt: "//stdout)
    if (allocated(error)) return
    ! ... the last line, and the scene's (the first DT_RECOMMENDED of the result is
    ! the packing's; the report prints 10 significant digits)
    last = stdout(:len(stdout) - 1)
    last = last(index(last, new_line("a"), back=.true.) + 1:)
    dt_last = -1
    if (index(last, line) == 1) read(last(len(line) + 1:index(last, " s") - 1), *, iostat=ios) dt_last
    call check(error, abs(dt_last/scalar(text, "DT_RECOMMENDED") - 1) < 1.0e-9_dp, &
      "a scene with its own stiffness: the last line is the scene's step: "//stdout)
  end subroutine test_one_recommended

  !> Rayleigh time pi r sqrt(rho/G)/(0.1631 nu + 0.8766), G = E/(2 (1 + nu)), in quad.
  pure real(qp) function rayleigh_q(e, nu, rho, r) result(t)
    real(qp), intent(in) :: e, nu, rho, r
    t = pq*r*sqrt(rho/(e/(2*(1 + nu))))/(0.1631_qp*nu + 0.8766_qp)
  end function rayleigh_q

  subroutine test_dump(error)
    type(error_type), allocatable, intent(out) :: error
    type(snapshot_result_type) :: res
    character(len=:), allocatable :: text, stdout
    real(qp) :: t_r
    real(dp) :: damped
    call expect_run(error, "example/snapshot_liggghts.nml", out, res, text, stdout)
    if (allocated(error)) return
    call check(error, res%format == "lammps_dump" .and. res%n_particles == 128 .and. res%n_types == 2 .and. &
      res%frame == 2 .and. res%n_frames == 2 .and. res%timestep == 61000_i8, "the last frame of 128 beads")
    if (allocated(error)) return
    call check(error, all(res%periodic .eqv. [.true., .true., .false.]) .and. index(text, " PERIODIC=T,") > 0, &
      "pp pp ff: a cell periodic in x and y")
    if (allocated(error)) return
    ! EDEM 20 % of the Rayleigh time of the smallest bead (type 2, r = 0.8 mm;
    ! E = 1e7, nu = 0.25, rho = 2500): 1e-13, a few roundings against quad
    t_r = rayleigh_q(1.0e7_qp, 0.25_qp, 2500.0_qp, 0.8e-3_qp)
    call check(error, abs(res%peer_dt(1) - t_r/5) <= 1.0e-13_qp*t_r, "EDEM 20 % of the Rayleigh time")
    if (allocated(error)) return
    damped = scalar(text, "DT_CRITICAL_DAMPED")
    call check(error, res%dt_exact == damped .and. all(abs(res%peer_ratio - res%peer_dt/damped) <= &
      1.0e-15_dp*res%peer_ratio), "the rules as ratios to the exact (damped) limit")
    if (allocated(error)) return
    ! the recommendation: 0.9 of the damped limit (no tolerance given)
    call check(error, scalar(text, "DT_RECOMMENDED") == 0.9_dp*damped .and. &
      index(stdout, "recommended dt = ") > 0 .and. index(stdout, "dt/exact limit") > 0 .and. &
      index(stdout, "yade_pwave_30") > 0, "one recommended dt; the rules in the report")
    if (allocated(error)) return
    ! a chosen frame
    call write_file(deck, [character(len=80) :: "&scene", "dim = 3, snapshot_file = '../../example/" &
      //"liggghts_pour.dump',", "snapshot_frame = 1, k_normal = 1.0e3 /"])
    call expect_run(error, deck, out, res, text, stdout)
    if (allocated(error)) return
    call check(error, res%frame == 1 .and. res%timestep == 60000_i8 .and. .not. res%have_materials .and. &
      index(stdout, "add a &material group") > 0, "snapshot_frame = 1: the first frame")
  end subroutine test_dump

  subroutine test_data(error)
    type(error_type), allocatable, intent(out) :: error
    type(snapshot_result_type) :: res
    character(len=:), allocatable :: a, b, stdout
    integer :: k
    real(dp) :: x, y
    call expect_run(error, "example/snapshot_liggghts.nml", out, res, a, stdout)
    if (allocated(error)) return
    call expect_run(error, "example/snapshot_data.nml", out2, res, b, stdout)
    if (allocated(error)) return
    call check(error, res%format == "lammps_data" .and. res%n_particles == 128 .and. &
      all(res%box_hi == [0.01_dp, 0.01_dp, 0.024_dp]), "128 beads in the file's box")
    if (allocated(error)) return
    ! written at the dump's last step: the dump prints 6 significant digits,
    ! the data file 17. With the impact linearisation the stiffness does not
    ! depend on the overlaps, only on masses and contact normals, which carry the
    ! dump's rounding (5e-7 relative): 1e-5 bounds the difference (1e-7 measured)
    do k = 1, size(compared)
      x = scalar(a, trim(compared(k)))
      y = scalar(b, trim(compared(k)))
      call check(error, x > 0.0_dp .and. abs(x - y) <= 1.0e-5_dp*abs(y), trim(compared(k))// &
        ": the data file gives the dump's packing")
      if (allocated(error)) return
    end do
  end subroutine test_data

  subroutine test_yade(error)
    type(error_type), allocatable, intent(out) :: error
    type(snapshot_result_type) :: res
    character(len=:), allocatable :: text, stdout
    call expect_run(error, "example/snapshot_yade.nml", out, res, text, stdout)
    if (allocated(error)) return
    call check(error, res%format == "yade_text" .and. res%n_particles == 100 .and. res%n_types == 2 .and. &
      .not. any(res%periodic), "100 spheres, matIds 0 and 1 as types 1 and 2, no cell")
    if (allocated(error)) return
    ! FrictPhys has no contact damping: the damped limit is the undamped one
    ! (taken at the step safe to the eigensolver's error bar)
    call check(error, scalar(text, "DAMPING_RATIO_TOP") == 0.0_dp .and. &
      scalar(text, "DT_CRITICAL_DAMPED") == scalar(text, "DT_CRITICAL_SAFE") .and. &
      scalar(text, "DT_CRITICAL_SAFE") <= scalar(text, "DT_CRITICAL_EIGEN") .and. &
      index(stdout, "yade_frictphys") > 0, "FrictPhys: undamped springs")
  end subroutine test_yade

  !> Two particles touching only through the periodic x boundary (pp ff pp);
  !> the same scene inline.
  subroutine test_box_inline(error)
    type(error_type), allocatable, intent(out) :: error
    type(snapshot_result_type) :: res
    character(len=:), allocatable :: a, b, stdout
    call write_file(dump, [character(len=60) :: "ITEM: TIMESTEP", "7", "ITEM: NUMBER OF ATOMS", "3", &
      "ITEM: BOX BOUNDS pp ff pp", "0 1", "0 1", "0 1", "ITEM: ATOMS id type x y z mass radius", &
      "1 1 0.05 0.5 0.5 2.0 0.06", "2 1 0.95 0.5 0.5 3.0 0.06", "3 1 0.5 0.5 0.5 1.5 0.06"])
    call write_file(deck, [character(len=60) :: "&scene", "dim = 3, snapshot_file = 'snap.dump',", &
      "k_normal = 1.0e4, kt_ratio = 0.3 /"])
    call expect_run(error, deck, out, res, a, stdout)
    if (allocated(error)) return
    call check(error, all(res%periodic .eqv. [.true., .false., .true.]) .and. scalar(a, "N_SPRINGS") == 1.0_dp, &
      "one contact, through the periodic x boundary")
    if (allocated(error)) return
    call write_file(inline, [character(len=70) :: "&scene", "dim = 3,", &
      "position = 0.05, 0.5, 0.5,  0.95, 0.5, 0.5,  0.5, 0.5, 0.5,", "mass = 2.0, 3.0, 1.5, radius = 0.06,", &
      "periodic = T, F, T, cell_lo = 0, 0, 0, cell_hi = 1, 1, 1,", "k_normal = 1.0e4, kt_ratio = 0.3 /"])
    call run_inline(error, a)
  end subroutine test_box_inline

  !> Run the inline deck and compare with the snapshot's result text `a`.
  subroutine run_inline(error, a)
    type(error_type), allocatable, intent(out) :: error
    character(len=*), intent(in) :: a
    integer :: rc, ios
    character(len=:), allocatable :: b, stdout, stderr
    call execute_command_line("rm -f "//out2, cmdstat=ios)
    call run_app(inline//" -o "//out2, rc, stdout, stderr)
    call check(error, rc == 0 .and. len(stderr) == 0, "the inline scene runs: "//stderr)
    if (allocated(error)) return
    call read_file(out2, b)
    call same_numbers(error, a, b)
  end subroutine run_inline

  !> Three overlapping particles of two types, Hertz from &material (impact
  !> linearisation and the restitution's damping), against the inline types.
  subroutine test_hertz_inline(error)
    type(error_type), allocatable, intent(out) :: error
    type(snapshot_result_type) :: res
    character(len=:), allocatable :: a, stdout
    call write_file(dump, [character(len=60) :: "ITEM: TIMESTEP", "0", "ITEM: NUMBER OF ATOMS", "3", &
      "ITEM: BOX BOUNDS ff ff ff", "-1 1", "-1 1", "-1 1", "ITEM: ATOMS id type x y z radius", &
      "1 1 0.0 0.0 0.0 0.0010", "2 2 0.00195 0.0 0.0 0.0010", "3 1 0.0 0.0019 0.0 0.0010"])
    call write_file(deck, [character(len=90) :: "&scene", "dim = 3, snapshot_file = 'snap.dump' /", &
      "&material", "young = 1.0e7, 2.0e7, poisson = 0.25, 0.3, density = 2500, 7800,", &
      "radius = 1.0e-3, restitution = 0.8, impact_velocity = 0.5, code = 'liggghts_hertz' /"])
    call expect_run(error, deck, out, res, a, stdout)
    if (allocated(error)) return
    ! masses 4/3 pi r^3 rho, written to 17 digits
    call write_file(inline, [character(len=90) :: "&scene", "dim = 3,", &
      "position = 0.0, 0.0, 0.0,  0.00195, 0.0, 0.0,  0.0, 0.0019, 0.0, radius = 0.0010,", &
      "mass = "//mass(2500.0_qp)//", "//mass(7800.0_qp)//", "//mass(2500.0_qp)//",", &
      "types = 1, 2, 1, law = 'hertz', young = 1.0e7, 2.0e7, poisson = 0.25, 0.3,", &
      "hertz_linearization = 'larger', impact_velocity = 0.5,", &
      "effects = 'contacts', 'damping', 'rotation', damping_ratio = "//zeta()//" /"])
    call run_inline(error, a)
  contains
    !> LIGGGHTS Hertz's damping ratio on the tangent stiffness, normal and
    !> tangential alike: sqrt(5/6) |ln e|/sqrt(ln^2 e + pi^2) (normal_model_hertz.h).
    function zeta() result(text)
      character(len=:), allocatable :: text
      character(len=40) :: buffer
      write(buffer, '(es25.17)') real(sqrt(5.0_qp/6)*(-log(0.8_qp))/sqrt(log(0.8_qp)**2 + pq**2), dp)
      text = trim(adjustl(buffer))
    end function zeta
    function mass(rho) result(text)
      real(qp), intent(in) :: rho
      character(len=:), allocatable :: text
      character(len=40) :: buffer
      write(buffer, '(es25.17)') real(4*pq/3*1.0e-3_qp**3*rho, dp)
      text = trim(adjustl(buffer))
    end function mass
  end subroutine test_hertz_inline

  !> One type, LIGGGHTS Hooke: k_n = 16/15 sqrt(R*) Y* (15 m* v^2/(16 sqrt(R*) Y*))^(1/5)
  !> (normal_model_hooke.h), k_t = k_n, evaluated in quad and given inline.
  subroutine test_hooke_quad(error)
    type(error_type), allocatable, intent(out) :: error
    type(snapshot_result_type) :: res
    character(len=:), allocatable :: a, stdout
    real(qp) :: y, r_star, m_star, kn
    character(len=40) :: buffer
    call write_file(dump, [character(len=60) :: "ITEM: TIMESTEP", "0", "ITEM: NUMBER OF ATOMS", "2", &
      "ITEM: BOX BOUNDS ff ff ff", "-1 1", "-1 1", "-1 1", "ITEM: ATOMS id type x y z radius mass", &
      "1 1 0.0 0.0 0.0 0.0010 1.0e-5", "2 1 0.00195 0.0 0.0 0.0010 1.0e-5"])
    call write_file(deck, [character(len=90) :: "&scene", "dim = 3, snapshot_file = 'snap.dump' /", &
      "&material", "young = 1.0e7, poisson = 0.25, density = 2500, radius = 1.0e-3,", &
      "restitution = 0.9, impact_velocity = 1.0, code = 'liggghts_hooke' /"])
    call expect_run(error, deck, out, res, a, stdout)
    if (allocated(error)) return
    ! the &material's particles: R* = r/2, m* = m/2 of 4/3 pi r^3 rho, Y* = E/(2 (1 - nu^2))
    y = 1.0e7_qp/(2*(1 - 0.25_qp**2))
    r_star = 0.5e-3_qp
    m_star = 4*pq/3*1.0e-3_qp**3*2500/2
    kn = 16*sqrt(r_star)*y/15*(15*m_star/(16*sqrt(r_star)*y))**0.2_qp
    write(buffer, '(es25.17)') real(kn, dp)
    call write_file(inline, [character(len=90) :: "&scene", "dim = 3,", &
      "position = 0.0, 0.0, 0.0,  0.00195, 0.0, 0.0, radius = 0.0010, mass = 1.0e-5,", &
      "types = 1, 1, type_k_normal = "//trim(adjustl(buffer))//", kt_ratio = 1.0,", &
      "effects = 'contacts', 'damping', 'rotation', restitution = 0.9 /"])
    call run_inline(error, a)
  end subroutine test_hooke_quad

  !> test/data/liggghts/hooke_kn.local: LIGGGHTS' normal force and overlap of
  !> two beads at rest (no dashpot force), so |F|/delta is its k_n.
  subroutine test_liggghts_kn(error)
    type(error_type), allocatable, intent(out) :: error
    character(len=:), allocatable :: text, stdout, stderr
    real(dp) :: row(7), k_liggghts, k_demstep
    integer :: k, ios, rc
    call read_file("test/data/liggghts/hooke_kn.local", text)
    k = index(text(:len(text) - 1), new_line("a"), back=.true.)
    read(text(k+1:), *, iostat=ios) row
    call check(error, ios == 0 .and. row(7) > 0.0_dp, "the fixture's contact row reads")
    if (allocated(error)) return
    k_liggghts = norm2(row(4:6))/row(7)
    call write_file(deck, [character(len=90) :: "&material", "young = 1.0e7, poisson = 0.25, density = 2500,", &
      "radius = 1.0e-3, restitution = 0.9, impact_velocity = 1.0, code = 'liggghts_hooke' /"])
    call execute_command_line("rm -f "//out, cmdstat=ios)
    call run_app(deck//" -o "//out, rc, stdout, stderr)
    call check(error, rc == 0 .and. len(stderr) == 0, "runs cleanly: "//stderr)
    if (allocated(error)) return
    call read_file(out, text)
    k_demstep = scalar(text, "K_N")
    ! the same formula in double on both sides (LIGGGHTS' pow, demstep's
    ! logarithms) and LIGGGHTS' own delta: a few roundings, far below 1e-12
    call check(error, abs(k_demstep - k_liggghts) <= 1.0e-12_dp*k_liggghts, "k_n: LIGGGHTS "// &
      trim(real_text(k_liggghts))//", demstep "//trim(real_text(k_demstep)))
  contains
    function real_text(x) result(t)
      real(dp), intent(in) :: x
      character(len=30) :: t
      write(t, '(es25.17)') x
    end function real_text
  end subroutine test_liggghts_kn

  subroutine test_bad_file(error)
    type(error_type), allocatable, intent(out) :: error
    ! a truncated dump: 3 atoms declared, 2 rows
    call write_file(dump, [character(len=60) :: "ITEM: TIMESTEP", "0", "ITEM: NUMBER OF ATOMS", "3", &
      "ITEM: BOX BOUNDS pp pp pp", "0 1", "0 1", "0 1", "ITEM: ATOMS id type x y z radius mass", &
      "1 1 0.1 0.1 0.1 0.05 1.0", "2 1 0.3 0.1 0.1 0.05 1.0"])
    call write_file(deck, [character(len=60) :: "&scene", "dim = 3, snapshot_file = 'snap.dump',", &
      "k_normal = 1.0e4 /"])
    call expect_refusal(error, deck, [character(len=60) :: "&scene: snapshot_file: ", work_dir//"/snap.dump: line 11: ", &
      "truncated"])
    if (allocated(error)) return
    ! an unknown column
    call write_file(dump, [character(len=60) :: "ITEM: TIMESTEP", "0", "ITEM: NUMBER OF ATOMS", "1", &
      "ITEM: BOX BOUNDS pp pp pp", "0 1", "0 1", "0 1", "ITEM: ATOMS id type x y z radius spin", &
      "1 1 0.1 0.1 0.1 0.05 1.0"])
    call expect_refusal(error, deck, [character(len=60) :: "snap.dump: line 9: unknown column 'spin'"])
    if (allocated(error)) return
    ! a frame the file does not have
    call write_file(deck, [character(len=80) :: "&scene", "dim = 3, snapshot_file = '../../example/" &
      //"liggghts_pour.dump',", "snapshot_frame = 5, k_normal = 1.0e3 /"])
    call expect_refusal(error, deck, [character(len=60) :: "&scene: snapshot_frame: ", "has 2 frames"])
    if (allocated(error)) return
    ! a format word
    call write_file(deck, [character(len=80) :: "&scene", "dim = 3, snapshot_file = 'snap.dump',", &
      "snapshot_format = 'vtk', k_normal = 1.0e3 /"])
    call expect_refusal(error, deck, [character(len=60) :: "&scene: snapshot_format: unknown word 'vtk'"])
    if (allocated(error)) return
    ! a missing file
    call write_file(deck, [character(len=80) :: "&scene", "dim = 3, snapshot_file = 'no_such.dump',", &
      "k_normal = 1.0e3 /"])
    call expect_refusal(error, deck, [character(len=60) :: "&scene: snapshot_file: ", "no_such.dump"])
  end subroutine test_bad_file

  subroutine test_refused(error)
    type(error_type), allocatable, intent(out) :: error
    call write_file(dump, [character(len=60) :: "ITEM: TIMESTEP", "0", "ITEM: NUMBER OF ATOMS", "2", &
      "ITEM: BOX BOUNDS ff ff ff", "-1 1", "-1 1", "-1 1", "ITEM: ATOMS id type x y z radius", &
      "1 1 0.0 0.0 0.0 0.0010", "2 2 0.00195 0.0 0.0 0.0010"])
    ! with particles_file, or with the position array
    call write_file(deck, [character(len=80) :: "&scene", "dim = 3, snapshot_file = 'snap.dump',", &
      "particles_file = 'p.txt', k_normal = 1.0e3 /"])
    call expect_refusal(error, deck, [character(len=60) :: "&scene: ", "give either", "snapshot_file", &
      "particles_file"])
    if (allocated(error)) return
    call write_file(deck, [character(len=80) :: "&scene", "dim = 3, snapshot_file = 'snap.dump',", &
      "position = 0, 0, 0, k_normal = 1.0e3 /"])
    call expect_refusal(error, deck, [character(len=80) :: &
      "&scene: snapshot_file: give either snapshot_file or position, not both"])
    if (allocated(error)) return
    ! no mass, no density, no &material
    call write_file(deck, [character(len=80) :: "&scene", "dim = 3, snapshot_file = 'snap.dump',", &
      "k_normal = 1.0e3 /"])
    call expect_refusal(error, deck, [character(len=60) :: "&scene: snapshot_file: ", "no masses", &
      "&material group with density"])
    if (allocated(error)) return
    ! masses but no stiffness
    call write_file(deck, [character(len=80) :: "&scene", "dim = 3, snapshot_file = '../../example/" &
      //"liggghts_pour.dump' /"])
    call expect_refusal(error, deck, [character(len=60) :: "&scene: k_normal: required with snapshot_file"])
    if (allocated(error)) return
    ! a &material with fewer types than the file
    call write_file(deck, [character(len=80) :: "&scene", "dim = 3, snapshot_file = 'snap.dump' /", &
      "&material", "young = 1.0e7, 1.0e7, 1.0e7, poisson = 0.25, density = 2500,", &
      "radius = 1.0e-3, restitution = 0.9, impact_velocity = 1.0 /"])
    call write_file(dump, [character(len=60) :: "ITEM: TIMESTEP", "0", "ITEM: NUMBER OF ATOMS", "2", &
      "ITEM: BOX BOUNDS ff ff ff", "-1 1", "-1 1", "-1 1", "ITEM: ATOMS id type x y z radius", &
      "1 1 0.0 0.0 0.0 0.0010", "2 5 0.00195 0.0 0.0 0.0010"])
    call expect_refusal(error, deck, [character(len=60) :: "&material: young: one value per particle type", &
      "types 1 to 5"])
    if (allocated(error)) return
    ! an absurd type number
    call write_file(dump, [character(len=60) :: "ITEM: TIMESTEP", "0", "ITEM: NUMBER OF ATOMS", "2", &
      "ITEM: BOX BOUNDS ff ff ff", "-1 1", "-1 1", "-1 1", "ITEM: ATOMS id type x y z radius", &
      "1 1 0.0 0.0 0.0 0.0010", "2 2000000000 0.00195 0.0 0.0 0.0010"])
    call expect_refusal(error, deck, [character(len=60) :: "&scene: snapshot_file: ", &
      "particle 2 has type 2000000000; types count from 1 to at most 1000"])
    if (allocated(error)) return
    ! the linear law needs one code
    call write_file(dump, [character(len=60) :: "ITEM: TIMESTEP", "0", "ITEM: NUMBER OF ATOMS", "2", &
      "ITEM: BOX BOUNDS ff ff ff", "-1 1", "-1 1", "-1 1", "ITEM: ATOMS id type x y z radius", &
      "1 1 0.0 0.0 0.0 0.0010", "2 1 0.00195 0.0 0.0 0.0010"])
    call write_file(deck, [character(len=80) :: "&scene", "dim = 3, snapshot_file = 'snap.dump', law = 'linear' /", &
      "&material", "young = 1.0e7, poisson = 0.25, density = 2500,", &
      "radius = 1.0e-3, restitution = 0.9, impact_velocity = 1.0 /"])
    call expect_refusal(error, deck, [character(len=60) :: "&material: code: ", "name it"])
    if (allocated(error)) return
    ! snapshot_frame without snapshot_file
    call write_file(deck, [character(len=80) :: "&scene", "dim = 3, position = 0, 0, 0, mass = 1, radius = 1,", &
      "snapshot_frame = 2, k_normal = 1.0e3 /"])
    call expect_refusal(error, deck, [character(len=60) :: "&scene: snapshot_file: required with snapshot_frame"])
  end subroutine test_refused

end module test_app_snapshot
