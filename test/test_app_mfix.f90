!> End-to-end tests of the MFiX mode of the executable: the tutorial fixtures'
!> DTSOLID against MFiX's formulas in quad precision, demstep's exact limit and
!> recommended step read back from `&mfix_result`, the recognition rules, and
!> each bad deck or option reported in one line.
module test_app_mfix
  use testdrive, only: new_unittest, unittest_type, error_type, check
  use demstep, only: dp, i8
  use test_support, only: run_app, write_file, read_file, work_dir, file_exists
  use, intrinsic :: iso_fortran_env, only: qp => real128
  use demstep_results, only: result_group_type
  use test_support, only: read_group, take
  implicit none
  private
  public :: collect_app_mfix

  real(qp), parameter :: pq = 3.14159265358979323846264338327950288_qp
  character(len=*), parameter :: data_dir = "test/data/mfix/"
  character(len=*), parameter :: out = work_dir//"/mfix_out.nml"
  character(len=*), parameter :: deck = work_dir//"/deck.mfx"
  integer, parameter :: np_max = 20

  !> The result group as read back.
  type :: mfix_read_type
    real(dp) :: tcoll = -1, dtsolid = -1, dtsolid_factor = -1, dtsolid_factor_recommended = -1, &
      dt_recommended = -1, tolerance = -1, dt_stability = -1, dt_accuracy_min = -1
    character(len=16) :: governs = ""
    integer :: phase_i(np_max) = -1, phase_j(np_max) = -1
    integer(i8) :: steps_per_contact(np_max) = -1
    real(dp), dimension(np_max) :: m_eff = -1, k_n = -1, eta_n = -1, damping_ratio = -1, t_coll = -1, &
      dt_critical = -1, restitution_error = -1, overlap_error = -1, dt_accuracy = -1
  end type mfix_read_type

contains

  subroutine collect_app_mfix(testsuite)
    type(unittest_type), allocatable, intent(out) :: testsuite(:)
    testsuite = [ &
      new_unittest("fluid bed tutorial: MFiX's DTSOLID, exact limit, recommended step", test_fluid_bed), &
      new_unittest("hopper tutorial: two phases in MFiX's pair order", test_hopper), &
      new_unittest("Hertzian CGS deck: undefined without a velocity, linearised with one", test_hertz), &
      new_unittest("CGP tutorial: coarse-grained phases scaled as MFiX scales them", test_cgp), &
      new_unittest("DEM05 test deck: MFiX's @( ) arithmetic read, its value reported", test_dem05), &
      new_unittest("recognition: MFiX lines, namelist groups, --format", test_recognition), &
      new_unittest("walls above KN and a size distribution are pointed out", test_misleads), &
      new_unittest("bad decks and options: one line with file and line", test_bad) &
      ]
  end subroutine collect_app_mfix

  !> Run the app on a deck with -o and read `&mfix_result` back.
  subroutine run_read(args, r, stdout, error)
    character(len=*), intent(in) :: args
    type(mfix_read_type), intent(out) :: r
    character(len=:), allocatable, intent(out) :: stdout
    type(error_type), allocatable, intent(out) :: error
    character(len=:), allocatable :: stderr
    integer :: rc, unit, ios
    real(dp) :: tcoll, dtsolid, dtsolid_factor, dtsolid_factor_recommended, dt_recommended, tolerance, &
      dt_stability, dt_accuracy_min
    character(len=16) :: governs
    integer :: phase_i(np_max), phase_j(np_max)
    integer(i8) :: steps_per_contact(np_max)
    real(dp), dimension(np_max) :: m_eff, k_n, eta_n, damping_ratio, t_coll, dt_critical, &
      restitution_error, overlap_error, dt_accuracy
    type(result_group_type) :: mfix_result_fields
    call execute_command_line("rm -f "//out, cmdstat=ios)
    call run_app(args//" -o "//out, rc, stdout, stderr)
    call check(error, rc, 0, message="exit status; stderr: "//stderr)
    if (allocated(error)) return
    call check(error, len(stderr), 0, message="nothing on stderr: "//stderr)
    if (allocated(error)) return
    tcoll = r%tcoll; dtsolid = r%dtsolid; dtsolid_factor = r%dtsolid_factor
    dtsolid_factor_recommended = r%dtsolid_factor_recommended; dt_recommended = r%dt_recommended
    tolerance = r%tolerance; dt_stability = r%dt_stability; dt_accuracy_min = r%dt_accuracy_min
    governs = r%governs; phase_i = r%phase_i; phase_j = r%phase_j; steps_per_contact = r%steps_per_contact
    m_eff = r%m_eff; k_n = r%k_n; eta_n = r%eta_n; damping_ratio = r%damping_ratio; t_coll = r%t_coll
    dt_critical = r%dt_critical; restitution_error = r%restitution_error; overlap_error = r%overlap_error
    dt_accuracy = r%dt_accuracy
    open(newunit=unit, file=out, status="old", action="read", iostat=ios)
    if (ios == 0) call read_group(unit, "mfix_result", mfix_result_fields, ios)
    if (ios == 0) call take(mfix_result_fields, "tcoll", tcoll, ios)
    if (ios == 0) call take(mfix_result_fields, "dtsolid", dtsolid, ios)
    if (ios == 0) call take(mfix_result_fields, "dtsolid_factor", dtsolid_factor, ios)
    if (ios == 0) call take(mfix_result_fields, "dtsolid_factor_recommended", dtsolid_factor_recommended, ios)
    if (ios == 0) call take(mfix_result_fields, "dt_recommended", dt_recommended, ios)
    if (ios == 0) call take(mfix_result_fields, "governs", governs, ios)
    if (ios == 0) call take(mfix_result_fields, "tolerance", tolerance, ios)
    if (ios == 0) call take(mfix_result_fields, "dt_stability", dt_stability, ios)
    if (ios == 0) call take(mfix_result_fields, "dt_accuracy_min", dt_accuracy_min, ios)
    if (ios == 0) call take(mfix_result_fields, "phase_i", phase_i, ios)
    if (ios == 0) call take(mfix_result_fields, "phase_j", phase_j, ios)
    if (ios == 0) call take(mfix_result_fields, "m_eff", m_eff, ios)
    if (ios == 0) call take(mfix_result_fields, "k_n", k_n, ios)
    if (ios == 0) call take(mfix_result_fields, "eta_n", eta_n, ios)
    if (ios == 0) call take(mfix_result_fields, "damping_ratio", damping_ratio, ios)
    if (ios == 0) call take(mfix_result_fields, "t_coll", t_coll, ios)
    if (ios == 0) call take(mfix_result_fields, "dt_critical", dt_critical, ios)
    if (ios == 0) call take(mfix_result_fields, "steps_per_contact", steps_per_contact, ios)
    if (ios == 0) call take(mfix_result_fields, "restitution_error", restitution_error, ios)
    if (ios == 0) call take(mfix_result_fields, "overlap_error", overlap_error, ios)
    if (ios == 0) call take(mfix_result_fields, "dt_accuracy", dt_accuracy, ios)
    call check(error, ios, 0, message="&mfix_result reads back")
    if (allocated(error)) return
    close(unit)
    r = mfix_read_type(tcoll, dtsolid, dtsolid_factor, dtsolid_factor_recommended, dt_recommended, &
      tolerance, dt_stability, dt_accuracy_min, governs, phase_i, phase_j, steps_per_contact, m_eff, k_n, &
      eta_n, damping_ratio, t_coll, dt_critical, restitution_error, overlap_error, dt_accuracy)
  end subroutine run_read

  !> MFiX's LSD pair arithmetic in quad: TCOLL of one pair.
  pure real(qp) function lsd_tcoll(m_eff, kn, e) result(t)
    real(qp), intent(in) :: m_eff, kn, e
    real(qp) :: eta
    eta = 2*sqrt(kn*m_eff)*abs(log(e))/sqrt(pq**2 + log(e)**2)
    t = pq/sqrt(kn/m_eff - (eta/m_eff)**2/4)
  end function lsd_tcoll

  !> The exact limit of the lagged dashpot in quad: (2/omega)(sqrt(1 + z^2) - z).
  pure real(qp) function limit_q(m_eff, kn, e) result(dt)
    real(qp), intent(in) :: m_eff, kn, e
    real(qp) :: z
    z = abs(log(e))/sqrt(pq**2 + log(e)**2)
    dt = 2*sqrt(m_eff/kn)*(sqrt(1 + z**2) - z)
  end function limit_q

  !> 1e-12 relative: MFiX's double arithmetic against its formulas in quad
  !> differs by a few roundings (the issue's requirement).
  subroutine check_rel(error, got, want, what)
    type(error_type), allocatable, intent(out) :: error
    real(dp), intent(in) :: got
    real(qp), intent(in) :: want
    character(len=*), intent(in) :: what
    call check(error, abs(real(got, qp) - want) <= 1.0e-12_qp*abs(want), &
      what//": got "//trim(adjustl(q_text(real(got, qp))))//", want "//trim(adjustl(q_text(want))))
  end subroutine check_rel

  pure function q_text(x) result(text)
    real(qp), intent(in) :: x
    character(len=40) :: text
    write(text, '(es40.25)') x
  end function q_text

  !> The recommended step is min(0.9 limit, accuracy step); DTSOLID_FACTOR
  !> gives a DTSOLID at most the recommended step; the report ends with it.
  subroutine check_recommendation(error, r, stdout)
    type(error_type), allocatable, intent(out) :: error
    type(mfix_read_type), intent(in) :: r
    character(len=*), intent(in) :: stdout
    real(dp) :: want
    want = min(0.9_dp*r%dt_stability, r%dt_accuracy_min)
    call check(error, r%dt_recommended == want, "dt_recommended = min(0.9 dt_stability, dt_accuracy_min)")
    if (allocated(error)) return
    call check(error, r%governs == merge("accuracy ", "stability", r%dt_accuracy_min < 0.9_dp*r%dt_stability), &
      "governs names the smaller")
    if (allocated(error)) return
    call check(error, r%tcoll/r%dtsolid_factor_recommended <= r%dt_recommended .and. &
      r%tcoll/(r%dtsolid_factor_recommended - 1) > r%dt_recommended .or. r%dtsolid_factor_recommended == 10, &
      "the factor is the smallest integer meeting the recommendation (or MFiX's lowest, 10)")
    if (allocated(error)) return
    call check(error, index(stdout, new_line("a")//"dtsolid_factor = ") > 0, "a dtsolid_factor line for MFiX")
    if (allocated(error)) return
    call check(error, index(stdout, new_line("a")//"recommended dt = ") > 0 .and. &
      index(stdout, " s"//new_line("a"), back=.true.) > index(stdout, "recommended dt = "), &
      "the report's last line is the recommended step")
  end subroutine check_recommendation

  subroutine test_fluid_bed(error)
    type(error_type), allocatable, intent(out) :: error
    type(mfix_read_type) :: r
    character(len=:), allocatable :: stdout
    real(qp) :: m, t
    call run_read(data_dir//"fluid_bed_2d.mfx", r, stdout, error)
    if (allocated(error)) return
    m = pq/6*0.004_qp**3*2700
    t = lsd_tcoll(m/2, 1000.0_qp, 0.9_qp)
    call check_rel(error, r%tcoll, t, "TCOLL")
    if (allocated(error)) return
    call check_rel(error, r%dtsolid, t/50, "DTSOLID")
    if (allocated(error)) return
    call check_rel(error, r%m_eff(1), m/2, "m_eff 1-1")
    if (allocated(error)) return
    call check_rel(error, r%m_eff(2), m, "m_eff 1-W")
    if (allocated(error)) return
    call check(error, all(r%phase_i(:2) == [1, 1]) .and. all(r%phase_j(:2) == [1, 0]) .and. r%phase_i(3) == -1, &
      "pairs 1-1 then 1-W, no more")
    if (allocated(error)) return
    call check_rel(error, r%dt_critical(1), limit_q(m/2, 1000.0_qp, 0.9_qp), "exact limit 1-1")
    if (allocated(error)) return
    ! the wall has e = 1: no dashpot, 2 sqrt(m/k)
    call check_rel(error, r%dt_critical(2), 2*sqrt(m/1000), "exact limit 1-W (undamped)")
    if (allocated(error)) return
    call check(error, r%tolerance == 1.0e-2_dp .and. index(stdout, "the default") > 0, &
      "default tolerance 1e-2, stated")
    if (allocated(error)) return
    ! at DTSOLID (N = 50 collision times ~ 97 per period) the restitution error
    ! is inside the tolerance, and the accuracy step is above DTSOLID
    call check(error, r%restitution_error(1) < 1.0e-2_dp .and. r%dt_accuracy(1) > r%dtsolid, &
      "MFiX's step meets 1e-2 on this deck")
    if (allocated(error)) return
    call check_recommendation(error, r, stdout)
  end subroutine test_fluid_bed

  subroutine test_hopper(error)
    type(error_type), allocatable, intent(out) :: error
    type(mfix_read_type) :: r
    character(len=:), allocatable :: stdout
    real(qp) :: m1, m2, t(3)
    call run_read(data_dir//"hopper_two_phase.mfx --tolerance 0.05", r, stdout, error)
    if (allocated(error)) return
    m1 = pq/6*0.002_qp**3*2500
    m2 = pq/6*0.004_qp**3*1000
    t = [lsd_tcoll(m1/2, 1000.0_qp, 0.5_qp), lsd_tcoll(m1*m2/(m1 + m2), 1000.0_qp, 0.5_qp), &
      lsd_tcoll(m2/2, 1000.0_qp, 0.5_qp)]
    call check_rel(error, r%dtsolid, minval(t)/50, "DTSOLID")
    if (allocated(error)) return
    call check_rel(error, r%t_coll(2), t(2), "t_coll of the pair 1-2")
    if (allocated(error)) return
    call check(error, all(r%phase_i(:5) == [1, 1, 2, 1, 2]) .and. all(r%phase_j(:5) == [1, 2, 2, 0, 0]), &
      "MFiX's order 11, 12, 22, 1W, 2W")
    if (allocated(error)) return
    call check(error, r%tolerance == 0.05_dp .and. index(stdout, "(--tolerance)") > 0, "--tolerance is used")
    if (allocated(error)) return
    ! equal restitution: one damping ratio, so each pair's accuracy step is the
    ! same fraction of its period, and scales as sqrt(m_eff)
    call check(error, abs(r%dt_accuracy(3)/r%dt_accuracy(1) - sqrt(real(m2/m1, dp))) < 1.0e-12_dp, &
      "accuracy steps scale as sqrt(m_eff)")
    if (allocated(error)) return
    call check_recommendation(error, r, stdout)
  end subroutine test_hopper

  subroutine test_hertz(error)
    type(error_type), allocatable, intent(out) :: error
    type(mfix_read_type) :: r
    character(len=:), allocatable :: stdout
    real(qp) :: m, kn, estar, delta, k_lin
    call run_read(data_dir//"hertz_cgs.dat", r, stdout, error)
    if (allocated(error)) return
    call check(error, all(r%dt_critical(:5) == 0) .and. r%dt_recommended == 0, &
      "undefined without an impact velocity: 0")
    if (allocated(error)) return
    call check(error, index(stdout, "--velocity") > 0 .and. index(stdout, "sqrt(10)") > 0 .and. &
      index(stdout, "ADAMS_BASHFORTH: an undamped contact gains energy") > 0, &
      "asks for a velocity; states the units issue and Adams-Bashforth's growth")
    if (allocated(error)) return
    call check(error, index(stdout, "recommended dt") == 0, "no step, no recommendation")
    if (allocated(error)) return
    call run_read(data_dir//"hertz_cgs.dat --velocity 100", r, stdout, error)
    if (allocated(error)) return
    ! pair 1-1: glass on glass, D = 0.2 cm, rho = 2.5, E = 6.3e11, nu = 0.22
    m = pq/6*0.2_qp**3*2.5_qp/2
    estar = 6.3e11_qp/(2*(1 - 0.22_qp**2))
    kn = 4*sqrt(0.05_qp)*estar/3
    call check_rel(error, r%k_n(1), kn, "HERT_KN 1-1")
    if (allocated(error)) return
    delta = (15*m*100**2/(16*estar*sqrt(0.05_qp)))**0.4_qp
    k_lin = 2*estar*sqrt(0.05_qp*delta)
    ! damping ratio of the linearised contact: eta_n/(2 sqrt(1.5 HERT_KN m))
    call check(error, abs(r%dt_critical(1) - real(2*sqrt(m/k_lin)*(sqrt(1 + real(r%damping_ratio(1), qp)**2) &
      - r%damping_ratio(1)), dp)) < 1.0e-12_dp*r%dt_critical(1), "limit of the tangent stiffness at impact")
    if (allocated(error)) return
    call check(error, index(stdout, "des_intg_method = 'EULER'") > 0, "Adams-Bashforth: EULER advised")
    if (allocated(error)) return
    call check_recommendation(error, r, stdout)
  end subroutine test_hertz

  !> MFiX 21.3's tutorials/cgp/fluidbed_cgp_3d: D_P0 := D_P0 CGP_STAT_WT^(1/3)
  !> (check_solids_common_discrete.f:147) with weight 8 doubles both diameters;
  !> the same scaling from CGP_D_P0 (weight (CGP_D_P0/D_P0)^3, :132).
  subroutine test_cgp(error)
    type(error_type), allocatable, intent(out) :: error
    type(mfix_read_type) :: r
    character(len=:), allocatable :: stdout
    character(len=100) :: lines(40)
    real(qp) :: m1, m2, t(3)
    integer :: unit, ios, n
    call run_read(data_dir//"fluidbed_cgp_3d.mfx", r, stdout, error)
    if (allocated(error)) return
    m1 = pq/6*0.002_qp**3*2500
    m2 = pq/6*0.003_qp**3*500
    t = [lsd_tcoll(m1/2, 100.0_qp, 0.9_qp), lsd_tcoll(m1*m2/(m1 + m2), 100.0_qp, 0.6_qp), &
      lsd_tcoll(m2/2, 100.0_qp, 0.6_qp)]
    call check_rel(error, r%tcoll, minval(t), "TCOLL of the coarse-grained particles")
    if (allocated(error)) return
    call check_rel(error, r%dtsolid, minval(t)/50, "DTSOLID")
    if (allocated(error)) return
    call check_rel(error, r%m_eff(1), m1/2, "m_eff 1-1: 8 times the real particles'")
    if (allocated(error)) return
    call check(error, index(stdout, "coarse-grained: phase 2: D_P0 = 0.0015 x CGP_STAT_WT^(1/3) with " &
      //"CGP_STAT_WT = 8: 0.003 m") > 0, "the scaling is reported: "//stdout)
    if (allocated(error)) return
    ! the same deck with the coarse-grained diameters instead of the weights
    n = 0
    open(newunit=unit, file=data_dir//"fluidbed_cgp_3d.mfx", status="old", action="read", iostat=ios)
    call check(error, ios, 0, message="fixture readable")
    if (allocated(error)) return
    do while (n < size(lines))
      read(unit, '(a)', iostat=ios) lines(n + 1)
      if (ios /= 0) exit
      n = n + 1
      if (index(lines(n), "cgp_stat_wt(1)") == 1) lines(n) = "cgp_d_p0(1) = 0.002"
      if (index(lines(n), "cgp_stat_wt(2)") == 1) lines(n) = "cgp_d_p0(2) = 0.003"
    end do
    close(unit)
    call write_file(deck, lines(1:n))
    call run_read(deck, r, stdout, error)
    if (allocated(error)) return
    call check_rel(error, r%dtsolid, minval(t)/50, "DTSOLID from CGP_D_P0")
  end subroutine test_cgp

  !> MFiX 21.3's tests/dem/DEM05: elastic LSD contacts (e = 1, no dashpot),
  !> KT_FAC = @(1.48/1.72).
  subroutine test_dem05(error)
    type(error_type), allocatable, intent(out) :: error
    type(mfix_read_type) :: r
    character(len=:), allocatable :: stdout
    real(qp) :: m1, m2, t(3)
    call run_read(data_dir//"dem05.dat", r, stdout, error)
    if (allocated(error)) return
    m1 = pq/6*0.005_qp**3*4000
    m2 = pq/6*0.005_qp**3*5000
    t = [lsd_tcoll(m1/2, 1.72e7_qp, 1.0_qp), lsd_tcoll(m1*m2/(m1 + m2), 1.72e7_qp, 1.0_qp), &
      lsd_tcoll(m2/2, 1.72e7_qp, 1.0_qp)]
    call check_rel(error, r%dtsolid, minval(t)/50, "DTSOLID")
    if (allocated(error)) return
    call check_rel(error, r%t_coll(2), t(2), "t_coll of the pair 1-2")
    if (allocated(error)) return
    call check(error, index(stdout, "line 15: KT_FAC = @(1.48/1.72) = 0.860465116279070") > 0 .and. &
      index(stdout, "line 16: KT_W_FAC = @(1.48/1.72) = 0.860465116279070") > 0, &
      "the evaluated values are reported: "//stdout)
  end subroutine test_dem05

  subroutine test_recognition(error)
    type(error_type), allocatable, intent(out) :: error
    integer :: rc
    character(len=:), allocatable :: stdout, stderr, text
    ! a deck with no group: MFiX
    call run_app(data_dir//"hopper_two_phase.mfx", rc, stdout, stderr)
    call check(error, rc == 0 .and. index(stdout, "MFiX deck") > 0, "no group, MFiX keywords: MFiX")
    if (allocated(error)) return
    ! --format namelist: the deck has no group
    call run_app("--format namelist "//data_dir//"hopper_two_phase.mfx", rc, stdout, stderr)
    call check(error, rc == 2 .and. index(stderr, "no demstep group") > 0, "--format namelist: " &
      //"no group: "//stderr)
    if (allocated(error)) return
    ! a namelist deck stays one in auto mode
    call run_app("example/paper.nml", rc, stdout, stderr)
    call check(error, rc == 0 .and. index(stdout, "MFiX") == 0, "namelist groups: namelist")
    if (allocated(error)) return
    ! --format mfix forces MFiX: the namelist deck has no UNITS
    call run_app("--format=mfix example/paper.nml", rc, stdout, stderr)
    call check(error, rc == 2 .and. index(stderr, "demstep: example/paper.nml: line 6: ") == 1, "--format mfix: " &
      //"read as MFiX: "//stderr)
    if (allocated(error)) return
    ! neither groups nor MFiX keywords
    call write_file(deck, [character(len=20) :: "mass = 1.0", "! nothing else"])
    call run_app(deck, rc, stdout, stderr)
    call check(error, rc == 2 .and. index(stderr, "no demstep group") > 0, "neither: the usual error: " &
      //stderr)
    if (allocated(error)) return
    ! an MFiX deck with a bad line is still recognised, and the line named
    call write_file(deck, [character(len=40) :: "units = 'SI'", "mmax = 1", "kn 1000", "d_p0(1) = 0.01"])
    call run_app(deck, rc, stdout, stderr)
    call check(error, rc == 2 .and. index(stderr, "demstep: "//deck//": line 3: ") == 1, &
      "a bad MFiX line: "//stderr)
    if (allocated(error)) return
    call run_app("--format xml "//deck, rc, stdout, stderr)
    call check(error, rc == 2 .and. index(stderr, "--format: must be") > 0, "unknown --format")
    if (allocated(error)) return
    call run_app("--tolerance 0.01 example/paper.nml", rc, stdout, stderr)
    call check(error, rc == 2 .and. index(stderr, "apply to MFiX decks") > 0, "--tolerance on a namelist deck")
    text = ""
  end subroutine test_recognition

  subroutine test_misleads(error)
    type(error_type), allocatable, intent(out) :: error
    type(mfix_read_type) :: r, r0
    character(len=:), allocatable :: stdout
    character(len=40), parameter :: base(10) = [character(len=40) :: "units = 'SI'", "mmax = 1", &
      "solids_model(1) = 'DEM'", "d_p0(1) = 0.004", "ro_s0(1) = 2700.0", "des_en_input(1) = 0.9", &
      "des_en_wall_input(1) = 0.9", "kn = 1000.0", "", ""]
    character(len=40) :: lines(10)
    lines = base
    lines(9) = "kn_w = 1000.0"
    call write_file(deck, lines)
    call run_read(deck, r0, stdout, error)
    if (allocated(error)) return
    call check(error, index(stdout, "walls:") == 0, "equal springs: no wall note")
    if (allocated(error)) return
    ! a wall 100 times stiffer: its limit is 10 times smaller, MFiX ignores it
    lines(9) = "kn_w = 1.0e5"
    call write_file(deck, lines)
    call run_read(deck, r, stdout, error)
    if (allocated(error)) return
    call check(error, index(stdout, "walls: a wall pair has a smaller limit") > 0, "wall note")
    if (allocated(error)) return
    call check(error, r%tcoll == r0%tcoll .and. r%dt_stability == r%dt_critical(2) .and. &
      r%dt_critical(2) < r%dt_critical(1), "TCOLL unchanged; the wall's limit governs demstep's")
    if (allocated(error)) return
    ! a size distribution down to half of D_P0
    lines(9) = "kn_w = 1000.0"
    lines(10) = "bc_psd_min_dp(3,1) = 0.002"
    call write_file(deck, lines)
    call run_read(deck, r, stdout, error)
    if (allocated(error)) return
    call check(error, index(stdout, "size distribution: phase 1 has particles of 0.002 m (line 10)") > 0, &
      "PSD note: "//stdout)
    if (allocated(error)) return
    ! LSD, fixed KN: the limit scales as sqrt(m) ~ d^(3/2): 2^(-3/2) of D_P0's
    call check(error, abs(r%dt_stability/r0%dt_stability - 0.5_dp**1.5_dp) < 1.0e-12_dp, &
      "the smallest particles' limit is used")
    if (allocated(error)) return
    ! a particle spring of 1e-300: MFiX's DTSOLID is 1e149 times the wall's
    ! limit; that contact is not stepped (-1), the output stays finite
    lines(8) = "kn = 1e-300"
    lines(10) = ""
    call write_file(deck, lines)
    call run_read(deck, r, stdout, error)
    if (allocated(error)) return
    call check(error, r%restitution_error(2) == -1 .and. r%steps_per_contact(2) == 0 .and. &
      index(stdout, "UNSTABLE") > 0 .and. index(stdout, "NaN") == 0 .and. index(stdout, "Inf") == 0, &
      "far beyond the limit: flagged, not stepped")
  end subroutine test_misleads

  subroutine test_bad(error)
    type(error_type), allocatable, intent(out) :: error
    integer :: rc
    character(len=:), allocatable :: stdout, stderr
    character(len=40) :: lines(8)
    lines = [character(len=40) :: "units = 'SI'", "mmax = 2", "solids_model(1:2) = 2*'DEM'", &
      "d_p0 = 2*0.004", "ro_s0 = 2700.0 2700.0", "des_en_input = 3*0.9", "des_en_wall_input = 2*0.9", &
      "kn = abc"]
    call write_file(deck, lines)
    call expect(deck, "demstep: "//deck//": line 8: KN: 'abc' is not a number")
    if (allocated(error)) return
    lines(8) = "kn = 1000"
    lines(4) = "d_p0(1) = 0.004"
    call write_file(deck, lines)
    call expect(deck, "demstep: "//deck//": D_P0(2): missing for DEM solids phase 2")
    if (allocated(error)) return
    lines(4) = "d_p0 = 0.004 @(2+0.002)"
    call write_file(deck, lines)
    call expect(deck, "demstep: "//deck//": line 4, column 17: D_P0: @(2+0.002): '2+0.002': MFiX's @( ) has " &
      //"no '+' or '-' operator")
    if (allocated(error)) return
    lines(4) = "d_p0 = 2*0.004"
    lines(6) = "des_en_input = 0.9 1.5 0.9"
    call write_file(deck, lines)
    call expect(deck, "demstep: "//deck//": line 6: DES_EN_INPUT(2): must lie in [0, 1]")
    if (allocated(error)) return
    lines(6) = "des_en_input = 3*0.9"
    call write_file(deck, lines)
    call expect("--tolerance 1.5 "//deck, "demstep: --tolerance: must lie in (0, 1)")
    if (allocated(error)) return
    call expect("--velocity -1 "//deck, "demstep: --velocity: must be a finite number > 0")
    if (allocated(error)) return
    call expect("--tolerance abc "//deck, "demstep: --tolerance: 'abc' is not a number")
    if (allocated(error)) return
    ! a tolerance no step below 1e7 per period meets
    call write_file(deck, [lines, "kn_w = 1000.0                           "])
    call expect("--tolerance 1e-13 "//deck, "demstep: "//deck//": --tolerance: 1e-13 is not met below")
    if (allocated(error)) return
    ! masses that underflow
    lines(4) = "d_p0 = 2*1e-100"
    call write_file(deck, [lines, "kn_w = 1000.0                           "])
    call expect(deck, "demstep: "//deck//": D_P0: MFiX's masses, springs or dashpots leave the double range")
  contains
    subroutine expect(args, start)
      character(len=*), intent(in) :: args, start
      integer :: cs
      call execute_command_line("rm -f "//out, cmdstat=cs)
      call run_app(args//" -o "//out, rc, stdout, stderr)
      call check(error, rc == 2 .and. index(stderr, start) == 1 .and. &
        index(stderr, new_line("a")) == len(stderr), "one line starting '"//start//"', got: "//stderr)
      if (allocated(error)) return
      call check(error, .not. file_exists(out), "no output file")
    end subroutine expect
  end subroutine test_bad

end module test_app_mfix
