!> Tests of the central-difference spring: stepping against the exact discrete
!> solution and the paper's closed form, the stability limit, the discrete contact.
module test_spring
  use testdrive, only: new_unittest, unittest_type, error_type, check, test_failed
  use demstep
  use demstep_spring, only: exact_discrete_state, paper_closed_form_velocity, numerical_period
  use demstep_spring, only: numerical_phase
  use demstep_contact, only: simulate_contact
  use demstep_spring, only: spring_damping_ratio, spring_omega
  use demstep_kinds, only: pi
  use demstep_spring, only: saturated_count
  use test_support, only: ieee_nan, real_str, int_str, unit_contact
  use, intrinsic :: iso_fortran_env, only: qp => real128
  implicit none
  private
  public :: collect_spring

contains


  subroutine collect_spring(testsuite)
    type(unittest_type), allocatable, intent(out) :: testsuite(:)
    testsuite = [ &
      new_unittest("stepping matches the exact discrete solution", test_exact_solution), &
      new_unittest("exact solution with an initial overlap", test_exact_with_offset), &
      new_unittest("paper closed form (2)/(4) matches stepping", test_paper_closed_form), &
      new_unittest("bounded just below the limit, 1e6 steps", test_just_below_limit), &
      new_unittest("grows just above the limit at the predicted rate", test_just_above_limit), &
      new_unittest("stability limit and phase statuses", test_limit_status), &
      new_unittest("damped limits: lagged and centred dashpot", test_damped_limits), &
      new_unittest("discrete contact equals brute-force stepping", test_discrete_contact), &
      new_unittest("discrete contact restitution in [1, 1/cos(theta/2)]", test_restitution_bounds), &
      new_unittest("simulated contact equals the closed form", test_simulate_contact), &
      new_unittest("invalid springs give a status", test_invalid_spring), &
      new_unittest("extreme springs: scaled, or refused naming the argument", test_extreme_springs), &
      new_unittest("growth factor up to omega dt = 1e100; counts saturate", test_extreme_steps) &
      ]
  end subroutine collect_spring

  !> Tolerance, relative to the amplitude, for n steps. Rounding errors of the
  !> stepper and of the closed form both grow linearly in n (a phase drift of a
  !> few eps per step); the worst measured is 3.1 n eps, at N = pi(1 + 1e-4).
  !> 1e-12 (1 + n/100) leaves a margin of 15 or more at every n.
  pure real(dp) function growth_tol(n)
    integer(i8), intent(in) :: n
    growth_tol = 1.0e-12_dp*(1.0_dp + real(n, dp)/100.0_dp)
  end function growth_tol

  subroutine test_exact_solution(error)
    type(error_type), allocatable, intent(out) :: error
    real(dp), parameter :: ns(5) = [pi*(1.0_dp + 1.0e-4_dp), 4.0_dp, 10.0_dp, 50.0_dp, 1000.0_dp]
    type(spring_type) :: spring
    type(spring_state_type) :: state, exact
    type(demstep_status_type) :: status
    real(dp) :: dt, theta, amp_x, amp_v, omega
    integer(i8) :: k, next
    integer :: i
    omega = 3.0_dp
    call new_spring(spring, 2.0_dp, 2.0_dp*omega**2, status, compression_only=.false.)
    call check(error, status%stat, demstep_stat%ok)
    if (allocated(error)) return
    do i = 1, size(ns)
      dt = 2.0_dp*pi/(omega*ns(i))
      call numerical_phase(omega*dt, theta, status)
      amp_x = 0.7_dp*dt/sin(theta)
      amp_v = 0.7_dp/cos(0.5_dp*theta)
      state = spring_state_type(x=0.0_dp, v=0.7_dp)
      next = 1_i8
      do k = 1_i8, 1000000_i8
        call spring_step(spring, dt, state)
        if (k /= next) cycle
        next = next*10_i8
        call exact_discrete_state(omega, dt, 0.0_dp, 0.7_dp, k, exact, status)
        call check(error, status%stat, demstep_stat%ok)
        if (allocated(error)) return
        call check(error, state%x/amp_x, exact%x/amp_x, thr=growth_tol(k), &
          message="x_n at N = "//real_str(ns(i))//", n = "//int_str(k))
        if (allocated(error)) return
        call check(error, state%v/amp_v, exact%v/amp_v, thr=growth_tol(k), &
          message="v_n at N = "//real_str(ns(i))//", n = "//int_str(k))
        if (allocated(error)) return
      end do
    end do
    ! a long run: 1e7 steps at N = 10 still on the closed form
    dt = 2.0_dp*pi/(omega*10.0_dp)
    call numerical_phase(omega*dt, theta, status)
    state = spring_state_type(x=0.0_dp, v=0.7_dp)
    call spring_run(spring, dt, state, 10000000_i8)
    call exact_discrete_state(omega, dt, 0.0_dp, 0.7_dp, 10000000_i8, exact, status)
    call check(error, state%x/(0.7_dp*dt/sin(theta)), exact%x/(0.7_dp*dt/sin(theta)), &
      thr=growth_tol(10000000_i8), message="x_n after 1e7 steps")
  end subroutine test_exact_solution

  subroutine test_exact_with_offset(error)
    type(error_type), allocatable, intent(out) :: error
    type(spring_type) :: spring
    type(spring_state_type) :: state, exact
    type(demstep_status_type) :: status
    real(dp) :: dt, x0, v0, amp
    integer(i8) :: k
    call new_spring(spring, 1.0_dp, 4.0_dp, status, compression_only=.false.)
    dt = 0.3_dp
    x0 = -0.4_dp
    v0 = 1.3_dp
    amp = abs(x0) + abs(v0)
    state = spring_state_type(x=x0, v=v0)
    do k = 1_i8, 2000_i8
      call spring_step(spring, dt, state)
      call exact_discrete_state(2.0_dp, dt, x0, v0, k, exact, status)
      call check(error, state%x/amp, exact%x/amp, thr=growth_tol(k), message="x_n, n = "//int_str(k))
      if (allocated(error)) return
      call check(error, state%v/amp, exact%v/amp, thr=growth_tol(k), message="v_n, n = "//int_str(k))
      if (allocated(error)) return
    end do
  end subroutine test_exact_with_offset

  subroutine test_paper_closed_form(error)
    type(error_type), allocatable, intent(out) :: error
    real(dp), parameter :: ns(6) = [3.2_dp, 4.0_dp, 7.5_dp, 10.0_dp, 100.0_dp, 2.9_dp]
    type(spring_type) :: spring
    type(spring_state_type) :: state
    type(demstep_status_type) :: status
    real(dp) :: dt, ratio, scale
    integer :: i, k
    call new_spring(spring, 1.0_dp, 1.0_dp, status, compression_only=.false.)
    do i = 1, size(ns)
      dt = 2.0_dp*pi/ns(i)
      state = spring_state_type(x=0.0_dp, v=1.0_dp)
      do k = 1, 300
        call spring_step(spring, dt, state)
        call paper_closed_form_velocity(dt**2, k, ratio, status)
        call check(error, status%stat, demstep_stat%ok)
        if (allocated(error)) return
        ! stable: relative to the amplitude 1/cos(theta/2); N = 2.9 is beyond the
        ! limit and the velocity grows, so relative to the value itself there
        if (ns(i) > pi) then
          scale = 1.0_dp/cos(asin(0.5_dp*dt))
        else
          scale = max(abs(state%v), 1.0_dp)
        end if
        call check(error, ratio/scale, state%v/scale, thr=growth_tol(int(k, i8)), &
          message="v_n/v0 at N = "//real_str(ns(i))//", n = "//int_str(int(k, i8)))
        if (allocated(error)) return
      end do
    end do
    call paper_closed_form_velocity(4.0_dp, 3, ratio, status)
    call check(error, status%stat, demstep_stat%pole, message="A_r = 4 is the double root")
  end subroutine test_paper_closed_form

  subroutine test_just_below_limit(error)
    type(error_type), allocatable, intent(out) :: error
    type(spring_type) :: spring
    type(spring_state_type) :: state
    type(demstep_status_type) :: status
    real(dp) :: dt, theta, amp, xmax
    integer(i8) :: k
    call new_spring(spring, 1.0_dp, 1.0_dp, status, compression_only=.false.)
    dt = 2.0_dp*pi/(pi*(1.0_dp + 1.0e-6_dp))
    call numerical_phase(dt, theta, status)
    call check(error, status%stat, demstep_stat%ok, message="N = pi(1 + 1e-6) is stable")
    if (allocated(error)) return
    amp = dt/sin(theta)
    state = spring_state_type(x=0.0_dp, v=1.0_dp)
    xmax = 0.0_dp
    do k = 1_i8, 1000000_i8
      call spring_step(spring, dt, state)
      xmax = max(xmax, abs(state%x))
    end do
    ! the exact discrete amplitude is dt/sin(theta); it must be reached, not exceeded
    call check(error, xmax/amp <= 1.0_dp + 1.0e-6_dp .and. xmax/amp > 0.99_dp, &
      "max |x| over 1e6 steps is "//real_str(xmax/amp)//" amplitudes")
  end subroutine test_just_below_limit

  subroutine test_just_above_limit(error)
    type(error_type), allocatable, intent(out) :: error
    type(spring_type) :: spring
    type(spring_state_type) :: state
    type(demstep_status_type) :: status
    real(dp) :: dt, theta, rho, x1, x2
    integer(i8) :: k
    call new_spring(spring, 1.0_dp, 1.0_dp, status, compression_only=.false.)
    dt = 2.0_dp*pi/(pi*(1.0_dp - 1.0e-6_dp))
    call numerical_phase(dt, theta, status)
    call check(error, status%stat, demstep_stat%unstable, message="N = pi(1 - 1e-6)")
    if (allocated(error)) return
    rho = growth_factor(spring, dt)
    call check(error, rho > 1.0_dp, "growth factor above 1 beyond the limit")
    if (allocated(error)) return
    state = spring_state_type(x=0.0_dp, v=1.0_dp)
    call spring_run(spring, dt, state, 2000_i8)
    x1 = abs(state%x)
    do k = 1_i8, 1000_i8
      call spring_step(spring, dt, state)
    end do
    x2 = abs(state%x)
    ! after the transient, |x| grows as rho**n (the other root has decayed by
    ! rho**-4000 < 1e-4); the measured log-rate matches log(rho) to 1e-3
    call check(error, log(x2/x1)/1000.0_dp, log(rho), thr=1.0e-3_dp, rel=.true., &
      message="growth rate per step")
  end subroutine test_just_above_limit

  subroutine test_limit_status(error)
    type(error_type), allocatable, intent(out) :: error
    type(spring_type) :: spring
    type(demstep_status_type) :: status
    real(dp) :: theta, ratio
    call new_spring(spring, 0.25_dp, 9.0_dp, status)
    ! 2 sqrt(M/K) = 2 * 0.5/3
    call check(error, critical_time_step(spring), 1.0_dp/3.0_dp, thr=2*epsilon(1.0_dp), rel=.true.)
    if (allocated(error)) return
    call check(error, spring_period(spring), 2.0_dp*pi/6.0_dp, thr=2*epsilon(1.0_dp), rel=.true.)
    if (allocated(error)) return
    call numerical_phase(2.0_dp, theta, status)
    call check(error, status%stat, demstep_stat%unstable, message="omega dt = 2 is the limit")
    if (allocated(error)) return
    call numerical_phase(nearest(2.0_dp, -1.0_dp), theta, status)
    call check(error, status%stat, demstep_stat%ok, message="just below 2")
    if (allocated(error)) return
    call check(error, theta < pi .and. theta > 3.14_dp, "theta just below pi")
    if (allocated(error)) return
    call numerical_phase(ieee_nan(), theta, status)
    call check(error, status%stat, demstep_stat%invalid_input, message="NaN")
    if (allocated(error)) return
    call numerical_phase(-1.0_dp, theta, status)
    call check(error, status%stat, demstep_stat%invalid_input, message="negative")
    if (allocated(error)) return
    ! numerical period: 1 + h^2/24 + 3 h^4/640 + ... (series of h/(2 asin(h/2)))
    call numerical_period(1.0e-3_dp, ratio, status)
    call check(error, ratio, 1.0_dp - 1.0e-6_dp/24.0_dp, thr=1.0e-13_dp, rel=.true., &
      message="period ratio at omega dt = 1e-3")
    if (allocated(error)) return
    call check(error, growth_factor(spring, 0.999_dp*critical_time_step(spring)), 1.0_dp, &
      message="undamped growth factor is 1 below the limit")
  end subroutine test_limit_status

  subroutine test_damped_limits(error)
    type(error_type), allocatable, intent(out) :: error
    real(dp), parameter :: zetas(3) = [0.1_dp, 0.5_dp, 1.0_dp]
    ! the lagged dashpot limit 2 (sqrt(1 + z^2) - z): omega dt_crit = 1.810, 1.236, 0.828 (to 3 decimals)
    real(dp), parameter :: published(3) = [1.810_dp, 1.236_dp, 0.828_dp]
    type(spring_type) :: lagged, centred
    type(spring_state_type) :: state
    type(demstep_status_type) :: status
    real(dp) :: dtc, rho
    integer :: i
    do i = 1, size(zetas)
      call new_spring(lagged, 1.0_dp, 1.0_dp, status, damping_ratio=zetas(i), compression_only=.false.)
      call new_spring(centred, 1.0_dp, 1.0_dp, status, damping_ratio=zetas(i), &
        compression_only=.false., dashpot=dashpot_kind%centred)
      dtc = critical_time_step(lagged)
      call check(error, dtc, 2.0_dp*(sqrt(1.0_dp + zetas(i)**2) - zetas(i)), thr=4*epsilon(1.0_dp), &
        rel=.true., message="lagged dashpot limit")
      if (allocated(error)) return
      call check(error, dtc, published(i), thr=5.0e-4_dp, message="published figure")
      if (allocated(error)) return
      call check(error, growth_factor(lagged, 0.999_dp*dtc) < 1.0_dp .and. &
        growth_factor(lagged, 1.001_dp*dtc) > 1.0_dp, "lagged growth factor crosses 1 at the limit")
      if (allocated(error)) return
      call check(error, critical_time_step(centred), 2.0_dp, thr=4*epsilon(1.0_dp), &
        message="centred dashpot keeps 2/omega")
      if (allocated(error)) return
      call check(error, growth_factor(centred, 1.999_dp) < 1.0_dp .and. &
        growth_factor(centred, 2.001_dp) > 1.0_dp, "centred growth factor crosses 1 at 2/omega")
      if (allocated(error)) return
      ! stepping: decays at 0.99 of the limit, grows at 1.01
      state = spring_state_type(x=0.0_dp, v=1.0_dp)
      call spring_run(lagged, 0.99_dp*dtc, state, 20000_i8)
      call check(error, abs(state%v) < 1.0_dp, "lagged: decays at 0.99 dt_crit")
      if (allocated(error)) return
      ! beyond: enough steps for rho**n to reach 1e6, plus a transient
      state = spring_state_type(x=0.0_dp, v=1.0_dp)
      rho = growth_factor(lagged, 1.01_dp*dtc)
      call spring_run(lagged, 1.01_dp*dtc, state, 1000_i8 + ceiling(log(1.0e6_dp)/log(rho), i8))
      call check(error, abs(state%v) > 1.0e3_dp, "lagged: grows at 1.01 dt_crit")
      if (allocated(error)) return
    end do
  end subroutine test_damped_limits

  !> Independent brute force: the leapfrog loop written out, not the library stepper.
  subroutine brute_contact(h, steps, restitution, max_overlap)
    real(dp), intent(in) :: h
    integer(i8), intent(out) :: steps
    real(dp), intent(out) :: restitution, max_overlap
    real(dp) :: x, v
    x = 0.0_dp
    v = 1.0_dp
    steps = 0_i8
    max_overlap = 0.0_dp
    do
      x = x + v*h
      if (x <= 0.0_dp) exit
      v = v - x*h
      steps = steps + 1_i8
      max_overlap = max(max_overlap, x)
    end do
    restitution = -v
  end subroutine brute_contact

  subroutine test_discrete_contact(error)
    type(error_type), allocatable, intent(out) :: error
    type(discrete_contact_type) :: contact
    type(demstep_status_type) :: status
    integer(i8) :: steps
    real(dp) :: n, h, e, xmax, theta, q
    integer :: i
    ! omega = 1, so overlaps are in units of v0/omega already; N from 4 to 1000
    do i = 0, 400
      n = 4.0_dp*250.0_dp**(real(i, dp)/400.0_dp)
      h = 2.0_dp*pi/n
      call numerical_phase(h, theta, status)
      q = pi/theta
      ! pi/theta an integer to rounding: the last overlap is +-0 and either count is right
      if (abs(q - anint(q)) < 1.0e-9_dp) cycle
      call unit_contact(h, contact, status)
      call check(error, status%stat, demstep_stat%ok)
      if (allocated(error)) return
      call brute_contact(h, steps, e, xmax)
      call check(error, contact%steps, steps, message="steps in contact at N = "//real_str(n))
      if (allocated(error)) return
      ! rounding in stepping grows with the number of steps (n eps each, see growth_tol)
      call check(error, contact%restitution, e, thr=growth_tol(steps), &
        message="restitution at N = "//real_str(n))
      if (allocated(error)) return
      call check(error, contact%max_overlap, xmax, thr=growth_tol(steps), &
        message="max overlap at N = "//real_str(n))
      if (allocated(error)) return
      call check(error, contact%contact_time, real(steps, dp)*h/pi, thr=4*epsilon(1.0_dp), &
        rel=.true., message="contact time at N = "//real_str(n))
      if (allocated(error)) return
    end do
  end subroutine test_discrete_contact

  subroutine test_restitution_bounds(error)
    type(error_type), allocatable, intent(out) :: error
    type(discrete_contact_type) :: contact
    type(demstep_status_type) :: status
    real(dp) :: n, h, theta, upper
    integer :: i
    do i = 0, 2000
      n = 3.2_dp*3125.0_dp**(real(i, dp)/2000.0_dp)
      h = 2.0_dp*pi/n
      call numerical_phase(h, theta, status)
      call unit_contact(h, contact, status)
      upper = 1.0_dp/cos(0.5_dp*theta)
      ! 4 eps: rounding of the two cosines
      call check(error, contact%restitution >= 1.0_dp - 4*epsilon(1.0_dp) .and. &
        contact%restitution <= upper*(1.0_dp + 4*epsilon(1.0_dp)), &
        "restitution "//real_str(contact%restitution)//" outside [1, "//real_str(upper)// &
        "] at N = "//real_str(n))
      if (allocated(error)) return
    end do
    ! errors vanish as N grows: 1/cos(theta/2) - 1 ~ theta^2/8 ~ (pi/N)^2/2
    call unit_contact(2.0_dp*pi/1.0e4_dp, contact, status)
    call check(error, contact%restitution - 1.0_dp <= 0.5_dp*(pi/1.0e4_dp)**2*(1.0_dp + 1.0e-3_dp), &
      "restitution error at N = 1e4")
  end subroutine test_restitution_bounds

  subroutine test_simulate_contact(error)
    type(error_type), allocatable, intent(out) :: error
    type(spring_type) :: spring
    type(discrete_contact_type) :: closed, stepped
    type(demstep_status_type) :: status
    real(dp) :: dt
    integer :: i
    call new_spring(spring, 0.01_dp, 1.0e5_dp, status)
    do i = 1, 50
      dt = critical_time_step(spring)*(0.02_dp*i - 0.01_dp)
      call unit_contact(spring_omega(spring)*dt, closed, status)
      call simulate_contact(spring, dt, stepped, status)
      call check(error, status%stat, demstep_stat%ok)
      if (allocated(error)) return
      call check(error, stepped%steps, closed%steps, message="steps")
      if (allocated(error)) return
      call check(error, stepped%restitution, closed%restitution, thr=growth_tol(closed%steps), &
        message="restitution")
      if (allocated(error)) return
      call check(error, stepped%max_overlap, closed%max_overlap, thr=growth_tol(closed%steps), &
        message="overlap")
      if (allocated(error)) return
    end do
    ! a damped contact loses energy
    call new_spring(spring, 0.01_dp, 1.0e5_dp, status, damping_ratio=0.2_dp)
    call simulate_contact(spring, 0.01_dp*critical_time_step(spring), stepped, status)
    call check(error, stepped%restitution < 1.0_dp .and. stepped%restitution > 0.0_dp, &
      "damped restitution in (0, 1)")
    if (allocated(error)) return
    call simulate_contact(spring, 1.5_dp*critical_time_step(spring), stepped, status)
    call check(error, status%stat, demstep_stat%unstable, message="beyond the damped limit")
  end subroutine test_simulate_contact

  subroutine test_invalid_spring(error)
    type(error_type), allocatable, intent(out) :: error
    type(spring_type) :: spring
    type(demstep_status_type) :: status
    call new_spring(spring, 0.0_dp, 1.0_dp, status)
    call check(error, status%stat, demstep_stat%invalid_input, message="zero mass")
    if (allocated(error)) return
    call check(error, index(status%message, "mass") > 0, "message names the mass")
    if (allocated(error)) return
    call new_spring(spring, 1.0_dp, ieee_nan(), status)
    call check(error, status%stat, demstep_stat%invalid_input, message="NaN stiffness")
    if (allocated(error)) return
    call new_spring(spring, 1.0_dp, 1.0_dp, status, damping_ratio=-0.1_dp)
    call check(error, status%stat, demstep_stat%invalid_input, message="negative damping")
    if (allocated(error)) return
    call new_spring(spring, 1.0_dp, 1.0_dp, status, dashpot=7)
    call check(error, status%stat, demstep_stat%invalid_input, message="unknown dashpot")
  end subroutine test_invalid_spring

  !> K/M overflows or underflows where omega does not: omega, T and the critical
  !> step against quad precision (a square root and a quotient: 4 eps); refusals
  !> name the argument and the range.
  subroutine test_extreme_springs(error)
    type(error_type), allocatable, intent(out) :: error
    real(dp), parameter :: masses(4) = [0.01_dp, 1.0e-308_dp, 1.0e300_dp, 1.0e-300_dp]
    real(dp), parameter :: stiffnesses(4) = [1.0e308_dp, 1.0e5_dp, 1.0e-250_dp, 1.0e-300_dp]
    type(spring_type) :: spring
    type(demstep_status_type) :: status
    real(qp) :: omega_q
    real(dp) :: dt
    integer :: i
    do i = 1, size(masses)
      call new_spring(spring, masses(i), stiffnesses(i), status, damping_ratio=0.5_dp)
      call check(error, status%stat, demstep_stat%ok, message="M = "//real_str(masses(i)))
      if (allocated(error)) return
      omega_q = sqrt(real(stiffnesses(i), qp)/real(masses(i), qp))
      call check(error, spring_omega(spring), real(omega_q, dp), thr=4*epsilon(1.0_dp), rel=.true., &
        message="omega, M = "//real_str(masses(i)))
      if (allocated(error)) return
      call check(error, spring_period(spring), real(2*acos(-1.0_qp)/omega_q, dp), thr=4*epsilon(1.0_dp), &
        rel=.true., message="period, M = "//real_str(masses(i)))
      if (allocated(error)) return
      call check(error, spring_damping_ratio(spring), 0.5_dp, thr=4*epsilon(1.0_dp), rel=.true., &
        message="damping ratio round trip, M = "//real_str(masses(i)))
      if (allocated(error)) return
      ! lagged limit (2/omega)(sqrt(1 + 1/4) - 1/2)
      call check(error, critical_time_step(spring), real(2/omega_q*(sqrt(1.25_qp) - 0.5_qp), dp), &
        thr=8*epsilon(1.0_dp), rel=.true., message="critical step, M = "//real_str(masses(i)))
      if (allocated(error)) return
    end do
    call new_spring(spring, 1.0e-308_dp, 1.0e308_dp, status)
    call check(error, index(status%message, "stiffness: stiffness/mass must be in [1e-600, 1e600]") == 1, &
      "omega beyond 1e300 refused, naming stiffness: "//status%message)
    if (allocated(error)) return
    call new_spring(spring, 1.0e308_dp, 1.0e308_dp, status, damping_ratio=1.0_dp)
    call check(error, index(status%message, "damping_ratio: must be 0 or in [") == 1, &
      "a dashpot 2 zeta sqrt(K M) beyond the double range refused, naming damping_ratio")
    if (allocated(error)) return
    call new_spring(spring, 1.0_dp, 1.0_dp, status)
    call step_for_n_per_period(spring, 1.0e-308_dp, dt, status)
    call check(error, index(status%message, "n_per_period: must be in [") == 1, "N = 1e-308 refused")
    if (allocated(error)) return
    call step_for_n_per_period(spring, 1.0e308_dp, dt, status)
    call check(error, status%stat, demstep_stat%ok, message="N = 1e308 gives a normal dt")
    if (allocated(error)) return
    call check(error, dt, real(2*acos(-1.0_qp)/1.0e308_qp, dp), thr=2*epsilon(1.0_dp), rel=.true., &
      message="dt = T/1e308")
    if (allocated(error)) return
    call check_time_step(spring, 1.0e-309_dp, status)
    call check(error, index(status%message, "dt: must be in [") == 1, "a subnormal dt refused")
  end subroutine test_extreme_springs

  !> The growth factor's roots scaled where (b/2)^2 overflows: at h = omega dt
  !> = 1e100 the undamped factor is the larger root of r^2 - (2 - h^2) r + 1,
  !> h^2 - 2 + O(1/h^2), i.e. 1e200 to working precision; at h = 1e6 against
  !> quad. The discrete contact at omega dt = 1e-300: steps saturate, restitution
  !> and overlap 1, contact time 1 (units T/2) to a few eps.
  subroutine test_extreme_steps(error)
    type(error_type), allocatable, intent(out) :: error
    type(spring_type) :: spring
    type(demstep_status_type) :: status
    type(discrete_contact_type) :: contact
    real(qp) :: b
    integer(i8) :: count
    logical :: saturated
    call new_spring(spring, 1.0_dp, 1.0_dp, status)
    call check(error, growth_factor(spring, 1.0e100_dp), 1.0e200_dp, thr=4*epsilon(1.0_dp), rel=.true., &
      message="growth factor at omega dt = 1e100")
    if (allocated(error)) return
    b = 2.0_qp - 1.0e12_qp
    call check(error, growth_factor(spring, 1.0e6_dp), real(0.5_qp*(abs(b) + sqrt(b**2 - 4)), dp), &
      thr=4*epsilon(1.0_dp), rel=.true., message="growth factor at omega dt = 1e6")
    if (allocated(error)) return
    call unit_contact(1.0e-300_dp, contact, status)
    call check(error, status%stat, demstep_stat%ok, message="omega dt = 1e-300")
    if (allocated(error)) return
    call check(error, contact%steps == huge(1_i8) .and. contact%steps_saturated, "steps saturate")
    if (allocated(error)) return
    call check(error, contact%restitution, 1.0_dp, thr=2*epsilon(1.0_dp), message="restitution")
    if (allocated(error)) return
    call check(error, contact%max_overlap, 1.0_dp, thr=2*epsilon(1.0_dp), message="overlap")
    if (allocated(error)) return
    call check(error, contact%contact_time, 1.0_dp, thr=4*epsilon(1.0_dp), message="contact time")
    if (allocated(error)) return
    call saturated_count(9.2e18_dp, count, saturated)
    call check(error, count == 9200000000000000000_i8 .and. .not. saturated, "9.2e18 fits")
    if (allocated(error)) return
    call saturated_count(9.3e18_dp, count, saturated)
    call check(error, count == huge(1_i8) .and. saturated, "9.3e18 saturates")
  end subroutine test_extreme_steps

end module test_spring
