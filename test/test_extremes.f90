!> Extreme inputs over the whole double range for `&system`, `&harmonic_error`,
!> `&contact_error` and `&accuracy_cost` and the library behind them: each is
!> computed correctly (checked against quad-precision references or closed-form
!> limits) or refused with exit status 2 and one stderr line naming the variable;
!> no result ever holds NaN or Infinity; user file names never reach a shell.
module test_extremes
  use testdrive, only: new_unittest, unittest_type, error_type, check, test_failed
  use demstep
  use demstep_harmonic, only: harmonic_error_check
  use demstep_spring, only: numerical_phase, spring_omega
  use demstep_kinds, only: pi
  use test_support, only: count_lines, remove, run_app, write_file, read_file, file_exists, work_dir, reference
  use, intrinsic :: iso_fortran_env, only: qp => real128
  use, intrinsic :: ieee_arithmetic, only: ieee_is_finite
  use demstep_results, only: result_group_type
  use test_support, only: read_group, take
  implicit none
  private
  public :: collect_extremes

  character(len=*), parameter :: deck = work_dir//"/extreme.nml"
  character(len=*), parameter :: out = work_dir//"/extreme_result.nml"
  real(qp), parameter :: pi_q = 3.14159265358979323846264338327950288_qp

contains

  subroutine collect_extremes(testsuite)
    type(unittest_type), allocatable, intent(out) :: testsuite(:)
    testsuite = [ &
      new_unittest("&system: stiffness 1e308 and mass 1e-308, scaled", test_system_scaled), &
      new_unittest("&system: n_per_period 1e308 and 1e-308", test_system_n_extremes), &
      new_unittest("&system: velocity 1e308", test_system_velocity), &
      new_unittest("&harmonic_error: lambda 1e-308, 1e-150, 1e308", test_harmonic_lambda), &
      new_unittest("&contact_error: onset -1.8e308, N 1e308", test_contact_extremes), &
      new_unittest("&accuracy_cost: n_particles 1e308, damping_ratio 3.14", test_cost_extremes), &
      new_unittest("&accuracy_cost: csv a directory, '.', ''", test_cost_csv_names), &
      new_unittest("&accuracy_cost: figure and csv names never reach a shell", test_no_injection), &
      new_unittest("library: random extremes, finite or a status", test_library_random), &
      new_unittest("app: random extremes, finite or one error line", test_app_random) &
      ]
  end subroutine collect_extremes

  ! ---------------------------------------------------------------- references

  !> The undamped discrete contact in quad precision, written out from the
  !> leapfrog solution x_k = h sin(k theta)/sin(theta) (onset at a step):
  !> contact ends at nc = ceiling(pi/theta); restitution -cos((nc - 1/2) theta)/cos(theta/2);
  !> largest overlap over the steps k = 1 .. nc - 1 (in units v0/omega).
  subroutine contact_q(h, steps, restitution, overlap)
    real(qp), intent(in) :: h
    integer(i8), intent(out) :: steps
    real(qp), intent(out) :: restitution, overlap
    real(qp) :: theta
    integer(i8) :: k, nc
    theta = 2.0_qp*asin(0.5_qp*h)
    nc = ceiling(pi_q/theta, i8)
    steps = nc - 1_i8
    restitution = -cos((real(nc, qp) - 0.5_qp)*theta)/cos(0.5_qp*theta)
    overlap = 0.0_qp
    do k = 1_i8, nc - 1_i8
      overlap = max(overlap, h*sin(real(k, qp)*theta)/sin(theta))
    end do
  end subroutine contact_q

  ! ------------------------------------------------------------------ &system

  subroutine test_system_scaled(error)
    type(error_type), allocatable, intent(out) :: error
    ! the stiffest and the lightest of the issue's cases, with the template's other value
    call system_case(error, 0.01_dp, 1.0e308_dp, "mass = 0.01, stiffness = 1e308")
    if (allocated(error)) return
    call system_case(error, 1.0e-308_dp, 1.0e5_dp, "mass = 1e-308, stiffness = 1e5")
    if (allocated(error)) return
    ! omega = sqrt(K/M) = 1e308 is beyond the documented range: refused with the range
    call expect_refusal(error, "&system mass = 1e-308, stiffness = 1e308 /", &
      "&system: stiffness: stiffness/mass must be in [1e-600, 1e600]")
    if (allocated(error)) return
    ! omega dt = 1e151: the growth factor (omega dt)^2 would leave the double range
    call expect_refusal(error, "&system mass = 1, stiffness = 1e308, dt = 1e-3 /", &
      "&system: dt: must be in [")
  end subroutine test_system_scaled

  !> `&system` at N = 10 with an extreme mass or stiffness: every result against
  !> quad precision. omega, T and the critical step are a square root and a
  !> quotient or two (2 eps); the contact is scale-free and equals the quad
  !> contact at h = 2 pi/10 up to the rounding of h = omega (T/N) (a few eps).
  subroutine system_case(error, mass_in, stiffness_in, label)
    type(error_type), allocatable, intent(out) :: error
    real(dp), intent(in) :: mass_in, stiffness_in
    character(len=*), intent(in) :: label
    real(dp) :: period, omega, dt_critical, dt, n_per_period, growth_factor, theta, &
      period_numerical, contact_time, restitution, max_overlap
    integer(i8) :: contact_steps, steps_q
    logical :: stable
    real(dp) :: dt_recommended
    type(result_group_type) :: system_result_fields
    real(qp) :: omega_q, restitution_q, overlap_q
    character(len=:), allocatable :: text
    integer :: ios
    call run_ok(error, "&system "//label//", n_per_period = 10 /", text)
    if (allocated(error)) return
    call read_group(text, "system_result", system_result_fields, ios)
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
    call check(error, ios, 0, message="read back &system_result for "//label)
    if (allocated(error)) return
    omega_q = sqrt(real(stiffness_in, qp)/real(mass_in, qp))
    call contact_q(2.0_qp*pi_q/10.0_qp, steps_q, restitution_q, overlap_q)
    call check(error, omega, real(omega_q, dp), thr=4*epsilon(1.0_dp), rel=.true., message="omega, "//label)
    if (allocated(error)) return
    call check(error, period, real(2.0_qp*pi_q/omega_q, dp), thr=4*epsilon(1.0_dp), rel=.true., &
      message="period, "//label)
    if (allocated(error)) return
    call check(error, dt_critical, real(2.0_qp/omega_q, dp), thr=4*epsilon(1.0_dp), rel=.true., &
      message="dt_critical, "//label)
    if (allocated(error)) return
    call check(error, contact_steps, steps_q, message="contact steps, "//label)
    if (allocated(error)) return
    call check(error, restitution, real(restitution_q, dp), thr=16*epsilon(1.0_dp), rel=.true., &
      message="restitution, "//label)
    if (allocated(error)) return
    call check(error, max_overlap, real(overlap_q/omega_q, dp), thr=16*epsilon(1.0_dp), rel=.true., &
      message="max overlap v0/omega x ratio, "//label)
    if (allocated(error)) return
    call check(error, contact_time, real(steps_q, dp)*dt, thr=4*epsilon(1.0_dp), rel=.true., &
      message="contact time = steps dt, "//label)
  end subroutine system_case

  subroutine test_system_n_extremes(error)
    type(error_type), allocatable, intent(out) :: error
    real(dp) :: period, omega, dt_critical, dt, n_per_period, growth_factor, theta, &
      period_numerical, contact_time, restitution, max_overlap
    integer(i8) :: contact_steps
    logical :: stable
    real(dp) :: dt_recommended
    type(result_group_type) :: system_result_fields
    character(len=:), allocatable :: text
    real(qp) :: w
    integer :: ios
    ! N = 1e308: about 5e307 steps in contact, saturated at 2^63 - 1; the contact is
    ! the exact one to working precision (its errors are O(1/N^2) and O(1/N))
    call run_ok(error, "&system mass = 1, stiffness = 1, n_per_period = 1e308 /", text)
    if (allocated(error)) return
    call read_group(text, "system_result", system_result_fields, ios)
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
    call check(error, ios, 0, message="read back")
    if (allocated(error)) return
    call check(error, contact_steps, huge(1_i8), message="steps saturate at 2^63 - 1")
    if (allocated(error)) return
    call check(error, restitution, 1.0_dp, thr=2*epsilon(1.0_dp), message="restitution 1")
    if (allocated(error)) return
    call check(error, max_overlap, 1.0_dp, thr=2*epsilon(1.0_dp), message="max overlap v0/omega")
    if (allocated(error)) return
    call check(error, contact_time, real(pi_q, dp), thr=4*epsilon(1.0_dp), rel=.true., &
      message="contact time T/2")
    if (allocated(error)) return
    call check(error, growth_factor, 1.0_dp, message="growth factor")
    if (allocated(error)) return
    ! damped, N = 1e308: the continuous contact of the spring-dashpot, restitution
    ! exp(-zeta pi/w), time pi/w, w = sqrt(1 - zeta^2); 1e-13 allows for the
    ! subnormal zeta h = 6e-309 (50 bits) the closed form goes through
    call run_ok(error, "&system mass = 1, stiffness = 1, n_per_period = 1e308, damping_ratio = 0.1 /", &
      text)
    if (allocated(error)) return
    call read_group(text, "system_result", system_result_fields, ios)
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
    call check(error, ios, 0, message="read back, damped")
    if (allocated(error)) return
    w = sqrt(1.0_qp - 0.01_qp)
    call check(error, restitution, real(exp(-0.1_qp*pi_q/w), dp), thr=1.0e-13_dp, rel=.true., &
      message="damped restitution")
    if (allocated(error)) return
    call check(error, contact_time, real(pi_q/w, dp), thr=1.0e-13_dp, rel=.true., &
      message="damped contact time")
    if (allocated(error)) return
    ! with the template's spring dt = T/1e308 would be subnormal: refused with the range
    call expect_refusal(error, "&system mass = 0.01, stiffness = 1e5, n_per_period = 1e308 /", &
      "&system: n_per_period: must be in [")
    if (allocated(error)) return
    call expect_refusal(error, "&system mass = 1, stiffness = 1, n_per_period = 1e-308 /", &
      "&system: n_per_period: must be in [")
  end subroutine test_system_n_extremes

  subroutine test_system_velocity(error)
    type(error_type), allocatable, intent(out) :: error
    real(dp) :: period, omega, dt_critical, dt, n_per_period, growth_factor, theta, &
      period_numerical, contact_time, restitution, max_overlap
    integer(i8) :: contact_steps, steps_q
    logical :: stable
    real(dp) :: dt_recommended
    type(result_group_type) :: system_result_fields
    character(len=:), allocatable :: text
    real(qp) :: restitution_q, overlap_q
    integer :: ios
    ! omega = 1: the largest overlap 1e308 x 1.0086 is still a double
    call run_ok(error, "&system mass = 1, stiffness = 1, velocity = 1e308, n_per_period = 10 /", text)
    if (allocated(error)) return
    call read_group(text, "system_result", system_result_fields, ios)
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
    call check(error, ios, 0, message="read back")
    if (allocated(error)) return
    call contact_q(2.0_qp*pi_q/10.0_qp, steps_q, restitution_q, overlap_q)
    call check(error, max_overlap, real(1.0e308_qp*overlap_q, dp), thr=16*epsilon(1.0_dp), rel=.true., &
      message="max overlap at v0 = 1e308")
    if (allocated(error)) return
    ! omega = 0.316: 3.2e308 is not a double; refused with the range that works
    call expect_refusal(error, "&system mass = 10, stiffness = 1, velocity = 1e308, n_per_period = 10 /", &
      "&system: velocity: must be in [")
  end subroutine test_system_velocity

  ! ---------------------------------------------------------- &harmonic_error

  subroutine test_harmonic_lambda(error)
    type(error_type), allocatable, intent(out) :: error
    real(dp) :: n_per_period(1), lambda(1), n_steps(1), e(1)
    integer :: status(1), ios
    type(result_group_type) :: harmonic_error_result_fields
    character(len=:), allocatable :: text
    real(qp) :: e_q, pole
    ! E ~ -1e616 at lambda = 1e-308, and phases 5e307 turns at 1e308: both refused
    call expect_refusal(error, "&harmonic_error n_per_period = 10, lambda = 1e-308, steps_fraction = 0.5 /", &
      "&harmonic_error: lambda: element 1 (n_per_period = 10, lambda = 1e-308, n = 5): must be >= 6.03")
    if (allocated(error)) return
    call expect_refusal(error, "&harmonic_error n_per_period = 10, lambda = 1e308, steps_fraction = 0.5 /", &
      "&harmonic_error: lambda: element 1 (n_per_period = 10, lambda = 1e308, n = 5): must be <= ")
    if (allocated(error)) return
    call expect_refusal(error, "&harmonic_error n_per_period = 10, lambda = 1e-160, n_steps = 5 /", &
      "&harmonic_error: lambda: element 1 (n_per_period = 10, lambda = 1e-160, n = 5): |E| exceeds")
    if (allocated(error)) return
    ! lambda = 1e-150: E = -3.27e299, computed; against the quad closed form (1e-12,
    ! the evaluator's stated accuracy relative to |E|)
    call run_ok(error, "&harmonic_error n_per_period = 10, lambda = 1e-150, steps_fraction = 0.5 /", text)
    if (allocated(error)) return
    call read_group(text, "harmonic_error_result", harmonic_error_result_fields, ios)
    if (ios == 0) call take(harmonic_error_result_fields, "n_per_period", n_per_period, ios)
    if (ios == 0) call take(harmonic_error_result_fields, "lambda", lambda, ios)
    if (ios == 0) call take(harmonic_error_result_fields, "n_steps", n_steps, ios)
    if (ios == 0) call take(harmonic_error_result_fields, "e", e, ios)
    if (ios == 0) call take(harmonic_error_result_fields, "status", status, ios)
    call check(error, ios, 0, message="read back")
    if (allocated(error)) return
    call reference(10.0_dp, 1.0e-150_dp, 5.0_dp, e_q, pole)
    call check(error, e(1), real(e_q, dp), thr=1.0e-12_dp, rel=.true., message="E at lambda = 1e-150")
    if (allocated(error)) return
    call check(error, status(1), 0, message="status")
  end subroutine test_harmonic_lambda

  ! ----------------------------------------------------------- &contact_error

  subroutine test_contact_extremes(error)
    type(error_type), allocatable, intent(out) :: error
    real(dp) :: n_per_period(1), contact_time(1), restitution(1), max_overlap(1), &
      onset_contact_time(1), onset_restitution(1), onset_overlap(1)
    integer(i8) :: steps_in_contact(1)
    logical :: stable(1)
    type(result_group_type) :: contact_error_result_fields
    character(len=:), allocatable :: text
    integer :: ios
    ! -1.8e308 overflows to -Inf when read; -1.7e308 is a double: both outside (0, 1]
    call expect_refusal(error, "&contact_error n_per_period = 10, onset = -1.8e308 /", &
      "&contact_error: onset: element 1 is -Inf; must be in (0, 1]")
    if (allocated(error)) return
    call expect_refusal(error, "&contact_error n_per_period = 10, onset = -1.7e308 /", &
      "&contact_error: onset: element 1 is -1.7e308; must be in (0, 1]")
    if (allocated(error)) return
    call expect_refusal(error, "&contact_error n_per_period = 1e-308 /", &
      "&contact_error: n_per_period: element 1 is 1e-308; must be finite and >= ")
    if (allocated(error)) return
    call expect_refusal(error, "&contact_error n_per_period = 10, damping_ratio = 3.14 /", &
      "&contact_error: damping_ratio: must be in [0, 1)")
    if (allocated(error)) return
    ! N = 1e308, worst case: the exact contact to working precision, steps saturated
    call run_ok(error, "&contact_error n_per_period = 1e308 /", text)
    if (allocated(error)) return
    call read_group(text, "contact_error_result", contact_error_result_fields, ios)
    if (ios == 0) call take(contact_error_result_fields, "n_per_period", n_per_period, ios)
    if (ios == 0) call take(contact_error_result_fields, "steps_in_contact", steps_in_contact, ios)
    if (ios == 0) call take(contact_error_result_fields, "contact_time", contact_time, ios)
    if (ios == 0) call take(contact_error_result_fields, "restitution", restitution, ios)
    if (ios == 0) call take(contact_error_result_fields, "max_overlap", max_overlap, ios)
    if (ios == 0) call take(contact_error_result_fields, "onset_contact_time", onset_contact_time, ios)
    if (ios == 0) call take(contact_error_result_fields, "onset_restitution", onset_restitution, ios)
    if (ios == 0) call take(contact_error_result_fields, "onset_overlap", onset_overlap, ios)
    if (ios == 0) call take(contact_error_result_fields, "stable", stable, ios)
    call check(error, ios, 0, message="read back")
    if (allocated(error)) return
    call check(error, steps_in_contact(1), huge(1_i8), message="steps saturate")
    if (allocated(error)) return
    call check(error, restitution(1), 1.0_dp, thr=2*epsilon(1.0_dp), message="restitution")
    if (allocated(error)) return
    call check(error, max_overlap(1), 1.0_dp, thr=2*epsilon(1.0_dp), message="max overlap")
    if (allocated(error)) return
    call check(error, contact_time(1), 1.0_dp, thr=4*epsilon(1.0_dp), message="contact time")
  end subroutine test_contact_extremes

  ! ----------------------------------------------------------- &accuracy_cost

  subroutine test_cost_extremes(error)
    type(error_type), allocatable, intent(out) :: error
    real(dp) :: tolerances(1), n_per_period(1), dt(1), predicted_seconds(1), &
      cost_per_particle_step, period
    integer(i8) :: steps(1)
    logical :: steps_saturated(1)
    integer :: status(1), ios
    real(dp) :: dt_recommended
    type(result_group_type) :: accuracy_cost_result_fields
    character(len=:), allocatable :: text
    character(len=*), parameter :: g = "&accuracy_cost quantity = 'restitution', tolerances = 1e-2, " &
      //"duration = 1, mass = 0.01, stiffness = 1e5, cost_per_particle_step = 2e-7, figure = 'none', " &
      //"csv = '"//work_dir//"/extreme.csv', "
    real(qp) :: steps_q
    ! 1e308 particles: the time steps x 1e308 x 2e-7 is a double (about 2e305)
    call run_ok(error, g//"n_particles = 1e308 /", text)
    if (allocated(error)) return
    call read_group(text, "accuracy_cost_result", accuracy_cost_result_fields, ios)
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
    call check(error, ios, 0, message="read back")
    if (allocated(error)) return
    steps_q = real(ceiling(real(1.0_dp, qp)/real(dt(1), qp), i8), qp)
    call check(error, steps(1), int(steps_q, i8), message="steps = ceiling(duration/dt)")
    if (allocated(error)) return
    call check(error, predicted_seconds(1), real(steps_q*1.0e308_qp*real(2.0e-7_dp, qp), dp), &
      thr=4*epsilon(1.0_dp), rel=.true., message="predicted seconds")
    if (allocated(error)) return
    call expect_refusal(error, g//"n_particles = 1e308, duration = 1e10 /", &
      "&accuracy_cost: n_particles: the predicted run time exceeds the double range")
    if (allocated(error)) return
    ! an overdamped contact never rebounds: refused at once, nothing left behind
    call expect_refusal(error, g//"n_particles = 10, damping_ratio = 3.14 /", &
      "&accuracy_cost: damping_ratio: must be in [0, 1)")
  end subroutine test_cost_extremes

  subroutine test_cost_csv_names(error)
    type(error_type), allocatable, intent(out) :: error
    character(len=*), parameter :: g = "&accuracy_cost quantity = 'period', tolerances = 1e-2, " &
      //"duration = 1, n_particles = 10, mass = 1, stiffness = 1, cost_per_particle_step = 1e-7, " &
      //"figure = 'none', "
    integer :: rc, cs
    call execute_command_line("mkdir -p "//work_dir//"/csvdir", wait=.true., exitstat=rc, cmdstat=cs)
    call expect_refusal(error, g//"csv = '"//work_dir//"/csvdir' /", &
      "&accuracy_cost: csv: '"//work_dir//"/csvdir' is a directory; give a file name")
    if (allocated(error)) return
    call expect_refusal(error, g//"csv = '.' /", "&accuracy_cost: csv: '.' is a directory")
    if (allocated(error)) return
    call expect_refusal(error, g//"csv = '' /", "&accuracy_cost: csv: must name a file, got ''")
    if (allocated(error)) return
    call expect_refusal(error, g//"csv = '"//work_dir//"/no_such_dir/x.csv' /", &
      "&accuracy_cost: csv: '"//work_dir//"/no_such_dir/x.csv': cannot write")
  end subroutine test_cost_csv_names

  !> Names with shell syntax become files of exactly that name (gnuplot present)
  !> and never run a command; a csv name starting with '<' is not a gnuplot pipe.
  subroutine test_no_injection(error)
    type(error_type), allocatable, intent(out) :: error
    character(len=*), parameter :: names(6) = [character(len=40) :: "x;touch INJECTED;y", &
      "x$(touch INJECTED)y", "x`touch INJECTED`y", "x&&touch INJECTED", "x|touch INJECTED", &
      "q'uote;touch INJECTED"]
    character(len=*), parameter :: g = "&accuracy_cost quantity = 'period', tolerances = 1e-2, " &
      //"duration = 1, n_particles = 10, mass = 1, stiffness = 1, cost_per_particle_step = 1e-7, "
    character(len=400) :: lines(size(names))
    character(len=:), allocatable :: stdout, stderr, name
    integer :: i, rc, cs
    logical :: have_gnuplot
    call execute_command_line("command -v gnuplot > /dev/null 2>&1", exitstat=rc, cmdstat=cs)
    have_gnuplot = rc == 0 .and. cs == 0
    call remove(work_dir//"/INJECTED")
    call remove("INJECTED")
    do i = 1, size(names)
      name = trim(names(i))
      ! in namelist text a quote inside quotes is doubled
      lines(i) = g//"figure = '"//doubled(name)//"', csv = '<touch INJECTED "//achar(48 + i)//"' /"
    end do
    call write_file(deck, lines)
    call run_app("extreme.nml", rc, stdout, stderr, in_work_dir=.true.)
    call check(error, rc, 0, message="exit status; stderr: "//stderr)
    if (allocated(error)) return
    call check(error, .not. (file_exists(work_dir//"/INJECTED") .or. file_exists("INJECTED")), &
      "no injected command ran")
    if (allocated(error)) return
    do i = 1, size(names)
      name = trim(names(i))
      call check(error, file_exists(work_dir//"/<touch INJECTED "//achar(48 + i)), &
        "the csv is a file of that name: '<touch INJECTED "//achar(48 + i)//"'")
      if (allocated(error)) return
      if (have_gnuplot) then
        call check(error, file_exists(work_dir//"/"//name//".png") .and. &
          file_exists(work_dir//"/"//name//".svg"), "figure written under its literal name: "//name)
        if (allocated(error)) return
      end if
      call remove(work_dir//"/"//name//".png")
      call remove(work_dir//"/"//name//".svg")
      call remove(work_dir//"/<touch INJECTED "//achar(48 + i))
    end do
    if (.not. have_gnuplot) write(*, '(a)') "    (gnuplot not found: the figure files were not checked)"
  contains
    pure function doubled(text) result(quoted)
      character(len=*), intent(in) :: text
      character(len=:), allocatable :: quoted
      integer :: k
      quoted = ""
      do k = 1, len(text)
        if (text(k:k) == "'") then
          quoted = quoted//"''"
        else
          quoted = quoted//text(k:k)
        end if
      end do
    end function doubled
  end subroutine test_no_injection

  ! ------------------------------------------------------------- properties

  !> One random extreme double: 10^U(-308, 308) with a random sign most of the
  !> time, else one of the special values (0, 1, tiny, huge, subnormals, 1e+-308).
  function extreme(positive_bias) result(x)
    !> Probability of a positive value.
    real(dp), intent(in) :: positive_bias
    real(dp) :: x, u, v
    real(dp), parameter :: specials(9) = [0.0_dp, 1.0_dp, tiny(1.0_dp), huge(1.0_dp), &
      tiny(1.0_dp)*epsilon(1.0_dp), 1.0e-310_dp, 1.0e-308_dp, 1.0e308_dp, 0.5_dp]
    call random_number(u)
    call random_number(v)
    if (u < 0.2_dp) then
      x = specials(1 + min(size(specials) - 1, int(v*size(specials))))
    else
      x = 10.0_dp**(-308.0_dp + 616.0_dp*v)
    end if
    call random_number(u)
    if (u > positive_bias) x = -x
  end function extreme

  !> A value either moderate (10^U(-3, 3)) or extreme, so that groups get past
  !> their first check often enough to reach the rest.
  function mixed(p_extreme) result(x)
    real(dp), intent(in) :: p_extreme
    real(dp) :: x, u, v
    call random_number(u)
    if (u < p_extreme) then
      x = extreme(0.9_dp)
    else
      call random_number(v)
      x = 10.0_dp**(-3.0_dp + 6.0_dp*v)
    end if
  end function mixed

  function num(x) result(text)
    real(dp), intent(in) :: x
    character(len=:), allocatable :: text
    character(len=32) :: buf
    write(buf, '(es25.17e3)') x
    text = trim(adjustl(buf))
  end function num

  subroutine seed_rng(k)
    integer, intent(in) :: k
    integer :: n, i
    integer, allocatable :: seed(:)
    call random_seed(size=n)
    allocate(seed(n))
    seed = [(104729*i + 7919*k, i = 1, n)]
    call random_seed(put=seed)
  end subroutine seed_rng

  !> The library over 20 000 random extreme inputs (seeded): every ok result is a
  !> finite double, every refusal is a status whose message starts with the
  !> name of the argument.
  subroutine test_library_random(error)
    type(error_type), allocatable, intent(out) :: error
    integer :: i, stat
    type(spring_type) :: spring
    type(demstep_status_type) :: status
    type(discrete_contact_type) :: contact
    type(discrete_contact_type) :: oc
    type(run_prediction_type) :: prediction
    real(dp) :: mass, stiffness, zeta, dt, e, n, lambda, steps, s, theta
    character(len=:), allocatable :: case
    call seed_rng(1)
    do i = 1, 5000
      mass = mixed(0.7_dp)
      stiffness = mixed(0.7_dp)
      zeta = merge(0.0_dp, mixed(0.5_dp), i <= 2500)
      case = "mass "//num(mass)//", stiffness "//num(stiffness)//", zeta "//num(zeta)
      call new_spring(spring, mass, stiffness, status, damping_ratio=zeta)
      if (.not. named(status, ["mass         ", "stiffness    ", "damping_ratio"])) exit
      if (status%stat /= demstep_stat%ok) cycle
      if (.not. all_normal([spring_omega(spring), spring_period(spring), critical_time_step(spring)])) exit
      call step_for_n_per_period(spring, mixed(0.7_dp), dt, status)
      if (.not. named(status, ["n_per_period"])) exit
      if (status%stat /= demstep_stat%ok) cycle
      case = case//", dt "//num(dt)
      if (.not. all_normal([dt, spring_period(spring)/dt, growth_factor(spring, dt)])) exit
      if (dt < critical_time_step(spring) .and. zeta == 0.0_dp) then
        call spring_contact(spring, dt, contact, status)
        if (status%stat /= demstep_stat%ok) exit
        call numerical_phase(spring_omega(spring)*dt, theta, status)
        if (.not. all_normal([contact%restitution, contact%max_overlap, contact%contact_time, theta])) exit
        if (contact%steps < 0_i8) exit
      end if
    end do
    if (i <= 5000) then
      call test_failed(error, "spring: "//case//": "//message_of(status))
      return
    end if
    do i = 1, 5000
      n = mixed(0.6_dp)
      lambda = mixed(0.6_dp)
      steps = max(1.0_dp, abs(mixed(0.3_dp)))
      case = "N "//num(n)//", lambda "//num(lambda)//", n "//num(steps)
      call harmonic_error(n, lambda, steps, e, stat)
      if (.not. ieee_is_finite(e)) exit
      if (stat == demstep_stat%invalid_input .and. e /= 0.0_dp) exit
      call harmonic_error_check(n, lambda, steps, status)
      if (status%stat /= stat) exit
      if (.not. named(status, ["n_per_period", "lambda      ", "n_steps     "])) exit
    end do
    if (i <= 5000) then
      call test_failed(error, "harmonic_error: "//case//": "//message_of(status))
      return
    end if
    do i = 1, 5000
      n = mixed(0.6_dp)
      s = merge(1.0_dp, mixed(0.3_dp), i <= 1000)
      zeta = merge(0.0_dp, mixed(0.5_dp), i <= 2500)
      case = "N "//num(n)//", onset "//num(s)//", zeta "//num(zeta)
      call contact_with_onset(n, s, oc, status, zeta)
      if (.not. named(status, ["n_per_period ", "onset        ", "damping_ratio"])) exit
      if (status%stat /= demstep_stat%ok) cycle
      if (.not. (ieee_is_finite(oc%restitution) .and. ieee_is_finite(oc%max_overlap) .and. &
        ieee_is_finite(oc%contact_time) .and. oc%steps >= 0_i8)) exit
    end do
    if (i <= 5000) then
      call test_failed(error, "contact_with_onset: "//case//": "//message_of(status))
      return
    end if
    do i = 1, 5000
      case = ""
      mass = abs(mixed(0.5_dp)) + tiny(1.0_dp)
      n = 4.0_dp + abs(mixed(0.5_dp))
      dt = abs(mixed(0.5_dp)) + tiny(1.0_dp)
      s = abs(mixed(0.5_dp)) + tiny(1.0_dp)
      e = abs(mixed(0.5_dp)) + tiny(1.0_dp)
      case = num(mass)//", "//num(n)//", "//num(dt)//", "//num(s)//", "//num(e)
      call predict_run(mass, n, dt, s, e, prediction, status)
      if (.not. named(status, ["stiffness             ", "duration              ", &
        "n_particles           ", "cost_per_particle_step"])) exit
      if (status%stat /= demstep_stat%ok) cycle
      if (.not. all_normal([prediction%dt, prediction%steps_real, prediction%seconds])) exit
      if (prediction%steps < 1_i8) exit
    end do
    if (i <= 5000) call test_failed(error, "predict_run: "//case//": "//message_of(status))
  end subroutine test_library_random

  !> True for ok, or a message starting with one of `names` and ": ".
  logical function named(status, names)
    type(demstep_status_type), intent(in) :: status
    character(len=*), intent(in) :: names(:)
    integer :: k
    named = status%stat == demstep_stat%ok
    if (named) return
    if (.not. allocated(status%message)) return
    do k = 1, size(names)
      if (index(status%message, trim(names(k))//": ") == 1) named = .true.
    end do
  end function named

  function message_of(status) result(text)
    type(demstep_status_type), intent(in) :: status
    character(len=:), allocatable :: text
    text = "(no message)"
    if (allocated(status%message)) text = status%message
  end function message_of

  logical function all_normal(x)
    real(dp), intent(in) :: x(:)
    all_normal = all(ieee_is_finite(x) .and. (x == 0.0_dp .or. abs(x) >= tiny(1.0_dp)))
  end function all_normal

  !> The app over random extreme decks (seeded): 100 &system, 70 &harmonic_error,
  !> 60 &contact_error and 12 &accuracy_cost groups. Each ends with exit 0 and a
  !> result namelist without NaN or Infinity, or exit 2 and one stderr line
  !> `demstep: FILE: &group: variable: ...` naming a variable of the group.
  subroutine test_app_random(error)
    type(error_type), allocatable, intent(out) :: error
    integer :: i
    character(len=:), allocatable :: line
    character(len=*), parameter :: system_vars(7) = [character(len=16) :: "mass", "stiffness", &
      "damping_ratio", "dashpot", "velocity", "dt", "n_per_period"]
    character(len=*), parameter :: harmonic_vars(4) = [character(len=16) :: "n_per_period", "lambda", &
      "steps_fraction", "n_steps"]
    character(len=*), parameter :: contact_vars(3) = [character(len=16) :: "n_per_period", "onset", &
      "damping_ratio"]
    character(len=*), parameter :: cost_vars(12) = [character(len=24) :: "quantity", "tolerances", &
      "duration", "n_particles", "mass", "stiffness", "damping_ratio", "lambda", &
      "cost_per_particle_step", "n_max", "csv", "figure"]
    character(len=*), parameter :: stiffness_vars(11) = [character(len=16) :: "mass", "stiffness", &
      "tolerance", "lambda", "steps", "n_steps", "n_max", "resolution", "aggregate", "weights", "pick"]
    character(len=*), parameter :: scene_vars(13) = [character(len=20) :: "dim", "position", "mass", &
      "radius", "k_normal", "e_star", "law", "effects", "damping_ratio", "bonds", "k_bond", "fixed", &
      "hertz_linearization"]
    character(len=*), parameter :: quantities(5) = [character(len=12) :: "restitution", &
      "contact_time", "overlap", "period", "harmonic"]
    real(dp) :: u
    call seed_rng(2)
    do i = 1, 100
      line = "&system mass = "//num(mixed(0.5_dp))//", stiffness = "//num(mixed(0.5_dp))// &
        ", velocity = "//num(mixed(0.4_dp))
      call random_number(u)
      if (u < 0.5_dp) line = line//", damping_ratio = "//num(mixed(0.5_dp))
      if (u < 0.2_dp) line = line//", dashpot = 'centred'"
      call random_number(u)
      if (u < 0.45_dp) then
        line = line//", n_per_period = "//num(mixed(0.5_dp))
      else if (u < 0.9_dp) then
        line = line//", dt = "//num(mixed(0.5_dp))
      end if
      call check_deck(error, line//" /", "system", system_vars)
      if (allocated(error)) return
    end do
    do i = 1, 70
      line = "&harmonic_error n_per_period = "//num(mixed(0.5_dp))//", lambda = "//num(mixed(0.5_dp))
      call random_number(u)
      if (u < 0.5_dp) then
        line = line//", steps_fraction = "//num(mixed(0.4_dp))
      else
        line = line//", n_steps = "//num(mixed(0.4_dp))
      end if
      call check_deck(error, line//" /", "harmonic_error", harmonic_vars)
      if (allocated(error)) return
    end do
    do i = 1, 60
      line = "&contact_error n_per_period = "//num(mixed(0.5_dp))
      call random_number(u)
      if (u < 0.6_dp) line = line//", onset = "//num(mixed(0.5_dp))
      call random_number(u)
      if (u < 0.6_dp) line = line//", damping_ratio = "//num(mixed(0.5_dp)/1000.0_dp)
      call check_deck(error, line//" /", "contact_error", contact_vars)
      if (allocated(error)) return
    end do
    do i = 1, 12
      call random_number(u)
      line = "&accuracy_cost quantity = '"//trim(quantities(1 + int(u*5)))//"', tolerances = " &
        //num(mixed(0.5_dp))//", duration = "//num(mixed(0.5_dp))//", n_particles = " &
        //num(mixed(0.5_dp))//", mass = "//num(mixed(0.5_dp))//", stiffness = " &
        //num(mixed(0.5_dp))//", cost_per_particle_step = "//num(mixed(0.5_dp)/1.0e6_dp) &
        //", lambda = "//num(mixed(0.3_dp)/1000.0_dp)//", figure = 'none', csv = '" &
        //work_dir//"/random.csv'"
      call random_number(u)
      if (u < 0.3_dp) line = line//", damping_ratio = "//num(mixed(0.5_dp)/1000.0_dp)
      call check_deck(error, line//" /", "accuracy_cost", cost_vars)
      if (allocated(error)) return
    end do
    do i = 1, 30
      ! lambdas mostly in (0, 1), some extreme; resolutions that a scan can afford or
      ! extreme ones (refused); every other value extreme or ordinary
      call random_number(u)
      line = "&simulated_stiffness mass = "//num(mixed(0.5_dp))//", stiffness = "//num(mixed(0.5_dp)) &
        //", tolerance = "//num(mixed(0.5_dp)/1000.0_dp)//", lambda = "//num(mixed(0.3_dp)/1000.0_dp) &
        //", "//num(mixed(0.3_dp)/1000.0_dp)
      if (u < 0.3_dp) line = line//", steps = 'fixed', n_steps = "//num(mixed(0.5_dp))
      call random_number(u)
      if (u < 0.3_dp) line = line//", n_max = "//num(mixed(0.5_dp)*1000.0_dp)
      call random_number(u)
      if (u < 0.3_dp) line = line//", resolution = "//num(merge(extreme(0.9_dp), 0.01_dp + u, u < 0.15_dp))
      call random_number(u)
      if (u < 0.3_dp) line = line//", aggregate = 'weighted', weights = "//num(mixed(0.5_dp))//", " &
        //num(mixed(0.5_dp))
      call check_deck(error, line//" /", "simulated_stiffness", stiffness_vars)
      if (allocated(error)) return
    end do
    do i = 1, 30
      ! three particles in a bent chain; the critical steps only (a run's length is
      ! work the user asks for, tested elsewhere)
      call random_number(u)
      line = "&scene dim = 2, position = 0, 0, "//num(mixed(0.3_dp))//", 0, "//num(mixed(0.3_dp)) &
        //", "//num(mixed(0.3_dp))//", mass = "//num(mixed(0.5_dp))//", radius = "//num(mixed(0.5_dp))
      if (u < 0.5_dp) then
        line = line//", k_normal = "//num(mixed(0.5_dp))
      else
        line = line//", law = 'hertz', e_star = "//num(mixed(0.5_dp))
      end if
      call random_number(u)
      if (u < 0.4_dp) line = line//", effects = 'contacts', 'damping', damping_ratio = "//num(mixed(0.5_dp))
      call random_number(u)
      if (u < 0.3_dp) line = line//", bonds = 1, 3, k_bond = "//num(mixed(0.5_dp))
      call check_deck(error, line//" /", "scene", scene_vars)
      if (allocated(error)) return
    end do
  end subroutine test_app_random

  subroutine check_deck(error, line, group, variables)
    type(error_type), allocatable, intent(out) :: error
    character(len=*), intent(in) :: line, group
    character(len=*), intent(in) :: variables(:)
    integer :: rc, k, cs
    character(len=:), allocatable :: stdout, stderr, listing, upper, prefix
    logical :: ok
    call write_file(deck, [character(len=len(line)) :: line])
    call run_app(deck//" --namelist", rc, stdout, stderr)
    if (rc == 0) then
      upper = to_upper(stdout)
      call check(error, index(upper, "NAN") == 0 .and. index(upper, "INF") == 0 .and. &
        index(upper, "&"//to_upper(group)//"_RESULT") > 0, &
        "finite result namelist for: "//line//new_line("a")//stdout)
    else if (rc == 2) then
      prefix = "demstep: "//deck//": &"//group//": "
      ok = .false.
      do k = 1, size(variables)
        if (index(stderr, prefix//trim(variables(k))//": ") == 1) ok = .true.
      end do
      call check(error, ok .and. count_lines(stderr) == 1, "one line naming a variable for: " &
        //line//new_line("a")//stderr)
    else
      call test_failed(error, "exit status "//num(real(rc, dp))//" for: "//line//new_line("a")//stderr)
    end if
    if (allocated(error)) return
    call execute_command_line("ls -a "//work_dir//" > "//work_dir//"/listing", wait=.true., &
      exitstat=k, cmdstat=cs)
    call read_file(work_dir//"/listing", listing)
    call check(error, index(listing, ".tmp") == 0 .and. index(listing, ".gp") == 0, &
      "no temporary left behind by: "//line)
  end subroutine check_deck

  ! --------------------------------------------------------------- helpers

  !> Run a one-line deck with --namelist; exit 0, nothing on stderr, no NaN or
  !> Infinity in the result namelist (returned in `text`).
  subroutine run_ok(error, line, text)
    type(error_type), allocatable, intent(out) :: error
    character(len=*), intent(in) :: line
    character(len=:), allocatable, intent(out) :: text
    integer :: rc
    character(len=:), allocatable :: stderr, upper
    call write_file(deck, [character(len=len(line)) :: line])
    call run_app(deck//" --namelist", rc, text, stderr)
    call check(error, rc, 0, message="exit status for '"//line//"'; stderr: "//stderr)
    if (allocated(error)) return
    upper = to_upper(text)
    call check(error, index(upper, "NAN") == 0 .and. index(upper, "INF") == 0, &
      "no NaN or Infinity in: "//text)
  end subroutine run_ok

  !> Run a one-line deck with -o; exit 2, one stderr line starting with
  !> "demstep: DECK: <expected>", no output and no temporary file left.
  subroutine expect_refusal(error, line, expected)
    type(error_type), allocatable, intent(out) :: error
    character(len=*), intent(in) :: line, expected
    integer :: rc, cs
    character(len=:), allocatable :: stdout, stderr, listing
    call remove(out)
    call write_file(deck, [character(len=len(line)) :: line])
    call run_app(deck//" -o "//out, rc, stdout, stderr)
    call check(error, rc, 2, message="exit status for '"//line//"'; stderr: "//stderr)
    if (allocated(error)) return
    if (index(stderr, "demstep: "//deck//": "//expected) /= 1) then
      call test_failed(error, "stderr '"//stderr//"' does not start with 'demstep: "//deck//": " &
        //expected//"'")
      return
    end if
    call check(error, count_lines(stderr), 1, message="one line on stderr: "//stderr)
    if (allocated(error)) return
    call check(error, .not. file_exists(out), "no output file")
    if (allocated(error)) return
    call execute_command_line("ls -a "//work_dir//" > "//work_dir//"/listing", wait=.true., &
      exitstat=rc, cmdstat=cs)
    call read_file(work_dir//"/listing", listing)
    call check(error, index(listing, ".tmp") == 0, "no temporary file left behind")
  end subroutine expect_refusal

  pure function to_upper(text) result(upper)
    character(len=*), intent(in) :: text
    character(len=len(text)) :: upper
    integer :: i
    upper = text
    do i = 1, len(text)
      if (text(i:i) >= "a" .and. text(i:i) <= "z") upper(i:i) = achar(iachar(text(i:i)) - 32)
    end do
  end function to_upper

end module test_extremes
