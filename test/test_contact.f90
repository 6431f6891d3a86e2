!> Tests of the exact discrete contact with onset and damping, its worst cases,
!> convergence rates and tolerance -> N.
module test_contact
  use testdrive, only: new_unittest, unittest_type, error_type, check, test_failed
  use demstep
  use demstep_spring, only: numerical_phase
  use demstep_contact, only: simulate_contact, period_error
  use demstep_kinds, only: pi
  use test_support, only: real_str, unit_contact
  use, intrinsic :: iso_fortran_env, only: qp => real128
  implicit none
  private
  public :: collect_contact

contains

  subroutine collect_contact(testsuite)
    type(unittest_type), allocatable, intent(out) :: testsuite(:)
    testsuite = [ &
      new_unittest("closed forms equal brute-force stepping, N 3.2 .. 1e4", test_vs_stepping), &
      new_unittest("onset 1: restitution in [1, 1/cos(theta/2)], as discrete_contact", test_onset_one), &
      new_unittest("damped contact tends to the continuous one", test_damped_limit), &
      new_unittest("beyond the limit: computed, flagged; bad input", test_flags), &
      new_unittest("centred dashpot: closed form equals stepping", test_centred), &
      new_unittest("extreme N: saturated steps, the continuous limit", test_extreme_n), &
      new_unittest("overdamped steps never end: refused, brute force agrees", test_never_ends) &
      ]
  end subroutine collect_contact

  !> Independent brute force: the leapfrog contact written out.
  subroutine brute(n, s, zeta, steps, restitution, max_overlap)
    real(dp), intent(in) :: n, s, zeta
    integer(i8), intent(out) :: steps
    real(dp), intent(out) :: restitution, max_overlap
    real(dp) :: h, x, v
    h = 2.0_dp*pi/n
    x = (s - 1.0_dp)*h
    v = 1.0_dp
    steps = 0_i8
    max_overlap = 0.0_dp
    do
      x = x + v*h
      if (x <= 0.0_dp) exit
      v = v - h*(x + 2.0_dp*zeta*v)
      steps = steps + 1_i8
      max_overlap = max(max_overlap, x)
    end do
    restitution = -v
  end subroutine brute

  subroutine test_vs_stepping(error)
    type(error_type), allocatable, intent(out) :: error
    real(dp), parameter :: zetas(3) = [0.0_dp, 0.1_dp, 0.3_dp]
    type(discrete_contact_type) :: c
    type(demstep_status_type) :: status
    real(dp) :: n, s, e, xm, tol
    integer(i8) :: steps
    integer :: i, j, k
    do k = 1, size(zetas)
      do i = 0, 120
        n = 3.2_dp*3125.0_dp**(real(i, dp)/120.0_dp)
        do j = 1, 23
          s = real(j, dp)/23.0_dp
          call contact_with_onset(n, s, c, status, zetas(k))
          call check(error, status%stat, demstep_stat%ok)
          if (allocated(error)) return
          call brute(n, s, zetas(k), steps, e, xm)
          call check(error, c%steps, steps, message="steps at N = "//real_str(n)//", s = "//real_str(s))
          if (allocated(error)) return
          ! both sides round about eps per step: 1e-12 (1 + steps/100) of the scale 1
          tol = 1.0e-12_dp*(1.0_dp + real(steps, dp)/100.0_dp)
          call check(error, c%restitution, e, thr=tol, message="restitution at N = "//real_str(n)// &
            ", s = "//real_str(s)//", zeta = "//real_str(zetas(k)))
          if (allocated(error)) return
          call check(error, c%max_overlap, xm, thr=tol, message="overlap at N = "//real_str(n))
          if (allocated(error)) return
          call check(error, c%contact_time, real(steps, dp)*2.0_dp/n, thr=1.0e-14_dp, rel=.true., &
            message="contact time")
          if (allocated(error)) return
        end do
      end do
    end do
  end subroutine test_vs_stepping

  subroutine test_onset_one(error)
    type(error_type), allocatable, intent(out) :: error
    type(discrete_contact_type) :: c
    type(discrete_contact_type) :: d
    type(demstep_status_type) :: status
    real(dp) :: n, theta
    integer :: i
    do i = 0, 400
      n = 3.2_dp*3125.0_dp**(real(i, dp)/400.0_dp)
      call contact_with_onset(n, 1.0_dp, c, status)
      call numerical_phase(2.0_dp*pi/n, theta, status)
      call check(error, c%restitution >= 1.0_dp - 1.0e-13_dp .and. &
        c%restitution <= (1.0_dp + 1.0e-13_dp)/cos(0.5_dp*theta), "restitution bounds at N = "//real_str(n))
      if (allocated(error)) return
      call unit_contact(2.0_dp*pi/n, d, status)
      call check(error, c%steps, d%steps, message="steps as discrete_contact")
      if (allocated(error)) return
      call check(error, c%restitution, d%restitution, thr=1.0e-12_dp, rel=.true., &
        message="restitution as discrete_contact")
      if (allocated(error)) return
    end do
  end subroutine test_onset_one

  subroutine test_damped_limit(error)
    type(error_type), allocatable, intent(out) :: error
    type(discrete_contact_type) :: c, exact
    type(demstep_status_type) :: status
    exact = exact_contact(0.2_dp)
    call contact_with_onset(2.0e4_dp, 0.5_dp, c, status, 0.2_dp)
    ! at 2e4 steps per period the discrete contact is within O(1/N) of the continuous one
    call check(error, c%restitution, exact%restitution, thr=1.0e-3_dp, rel=.true., message="restitution")
    if (allocated(error)) return
    call check(error, c%max_overlap, exact%max_overlap, thr=1.0e-3_dp, rel=.true., message="overlap")
    if (allocated(error)) return
    call check(error, c%contact_time, exact%contact_time, thr=1.0e-3_dp, rel=.true., message="time")
    if (allocated(error)) return
    ! the closed forms: restitution exp(-zeta pi/sqrt(1 - zeta^2))
    call check(error, exact%restitution, exp(-0.2_dp*pi/sqrt(0.96_dp)), thr=1.0e-15_dp, rel=.true.)
  end subroutine test_damped_limit

  subroutine test_flags(error)
    type(error_type), allocatable, intent(out) :: error
    type(discrete_contact_type) :: c
    type(demstep_status_type) :: status
    integer(i8) :: steps
    real(dp) :: e, xm
    call contact_with_onset(3.0_dp, 0.7_dp, c, status)
    call check(error, status%stat == demstep_stat%ok .and. .not. c%stable, "N = 3 computed, flagged")
    if (allocated(error)) return
    call brute(3.0_dp, 0.7_dp, 0.0_dp, steps, e, xm)
    call check(error, c%steps == steps .and. abs(c%restitution - e) < 1.0e-14_dp, "stepped exactly")
    if (allocated(error)) return
    call contact_with_onset(10.0_dp, 0.0_dp, c, status)
    call check(error, status%stat, demstep_stat%invalid_input, message="onset 0")
    if (allocated(error)) return
    call contact_with_onset(10.0_dp, 1.5_dp, c, status)
    call check(error, status%stat, demstep_stat%invalid_input, message="onset 1.5")
    if (allocated(error)) return
    call contact_with_onset(-1.0_dp, 0.5_dp, c, status)
    call check(error, status%stat, demstep_stat%invalid_input, message="N < 0")
  end subroutine test_flags

  !> The centred dashpot's closed form against the spring stepper (simulate_contact,
  !> an independent implementation of the same scheme), onset at a step. The
  !> closed form and the stepper both carry a phase error of a few eps per step;
  !> 1e-12 (1 + steps/100) relative leaves a wide margin up to 1e4 steps.
  subroutine test_centred(error)
    type(error_type), allocatable, intent(out) :: error
    real(dp), parameter :: zetas(4) = [0.05_dp, 0.1_dp, 0.3_dp, 0.7_dp]
    type(spring_type) :: spring
    type(discrete_contact_type) :: stepped
    type(discrete_contact_type) :: c
    type(demstep_status_type) :: status
    real(dp) :: n, tol
    integer :: i, k
    do k = 1, size(zetas)
      call new_spring(spring, 1.0_dp, 1.0_dp, status, damping_ratio=zetas(k), dashpot=dashpot_kind%centred)
      do i = 0, 60
        n = 3.5_dp*(2000.0_dp/3.5_dp)**(real(i, dp)/60.0_dp)
        call contact_with_onset(n, 1.0_dp, c, status, zetas(k), dashpot=dashpot_kind%centred)
        call check(error, status%stat, demstep_stat%ok, message="centred at N = "//real_str(n))
        if (allocated(error)) return
        call simulate_contact(spring, 2.0_dp*pi/n, stepped, status)
        call check(error, status%stat, demstep_stat%ok, message="stepped at N = "//real_str(n))
        if (allocated(error)) return
        call check(error, c%steps, stepped%steps, message="steps at N = "//real_str(n))
        if (allocated(error)) return
        tol = 1.0e-12_dp*(1.0_dp + real(c%steps, dp)/100.0_dp)
        call check(error, c%restitution, stepped%restitution, thr=tol, rel=.true., &
          message="restitution at N = "//real_str(n)//", zeta = "//real_str(zetas(k)))
        if (allocated(error)) return
        call check(error, c%max_overlap, stepped%max_overlap, thr=tol, rel=.true., &
          message="overlap at N = "//real_str(n)//", zeta = "//real_str(zetas(k)))
        if (allocated(error)) return
      end do
    end do
  end subroutine test_centred

  !> N up to 1e308: the steps saturate (their count is above 2^63 - 1) and the
  !> contact is the continuous one to working precision (its discrete errors are
  !> O(1/N)); undamped exactly 1, damped (zeta = 0.3) the closed forms of
  !> exact_contact, checked to 1e-12 (the subnormal zeta h at N = 1e308 keeps
  !> 50 bits).
  subroutine test_extreme_n(error)
    type(error_type), allocatable, intent(out) :: error
    real(dp), parameter :: ns(3) = [1.0e20_dp, 1.0e200_dp, 1.0e308_dp]
    type(discrete_contact_type) :: c, exact
    type(demstep_status_type) :: status
    integer :: i, d
    real(dp) :: zeta
    do d = 1, 2
      do i = 1, size(ns)
        zeta = merge(0.0_dp, 0.3_dp, i == 1 .and. d == 1)
        call contact_with_onset(ns(i), 1.0_dp, c, status, zeta, dashpot=merge(dashpot_kind%lagged, &
          dashpot_kind%centred, d == 1))
        call check(error, status%stat, demstep_stat%ok, message="N = "//real_str(ns(i)))
        if (allocated(error)) return
        call check(error, c%steps, huge(1_i8), message="saturated steps")
        if (allocated(error)) return
        call check(error, c%steps_saturated, .true., message="saturation flagged")
        if (allocated(error)) return
        exact = exact_contact(zeta)
        call check(error, c%restitution, exact%restitution, thr=1.0e-12_dp, rel=.true., &
          message="restitution at N = "//real_str(ns(i)))
        if (allocated(error)) return
        call check(error, c%contact_time, exact%contact_time, thr=1.0e-12_dp, rel=.true., &
          message="contact time at N = "//real_str(ns(i)))
        if (allocated(error)) return
        call check(error, c%max_overlap, exact%max_overlap, thr=1.0e-12_dp, rel=.true., &
          message="overlap at N = "//real_str(ns(i)))
        if (allocated(error)) return
      end do
    end do
    ! the period error by its series (x = pi/N < 1e-3) against 1 - x/asin(x) in quad,
    ! where the cancellation costs at most 1e-34/1e-12: 1e-13 relative
    do i = 4, 6
      call check(error, period_error(10.0_dp**i), real(period_error_q(10.0_qp**i), dp), &
        thr=1.0e-13_dp, rel=.true., message="period error at N = 1e"//real_str(real(i, dp)))
      if (allocated(error)) return
    end do
  end subroutine test_extreme_n

  !> 1 - x/asin(x), x = pi/N, in quad.
  pure real(qp) function period_error_q(n)
    real(qp), intent(in) :: n
    real(qp) :: x
    x = 3.14159265358979323846264338327950288_qp/n
    period_error_q = 1.0_qp - x/asin(x)
  end function period_error_q

  !> An overdamped step (real positive roots): the overlap decays without
  !> crossing zero; the library refuses at once, and brute-force stepping shows
  !> the overlap still positive after 1e5 steps. zeta >= 1 in a worst case: refused.
  subroutine test_never_ends(error)
    type(error_type), allocatable, intent(out) :: error
    type(discrete_contact_type) :: c
    type(demstep_status_type) :: status
    real(dp) :: h, x, v, e
    integer :: k
    call contact_with_onset(20.0_dp, 0.5_dp, c, status, 0.95_dp)
    call check(error, status%stat, demstep_stat%not_converged, message="zeta 0.95, N = 20")
    if (allocated(error)) return
    call check(error, index(status%message, "n_per_period: ") == 1, "names n_per_period")
    if (allocated(error)) return
    h = 2.0_dp*pi/20.0_dp
    x = -0.5_dp*h
    v = 1.0_dp
    do k = 1, 100000
      x = x + v*h
      if (.not. x > 0.0_dp) exit
      v = v - h*(x + 2.0_dp*0.95_dp*v)
    end do
    call check(error, k > 100000 .or. x == 0.0_dp, "brute force: positive until it underflows")
    if (allocated(error)) return
    call contact_worst_case(10.0_dp, quantity_kind%restitution, c, e, status, 3.14_dp)
    call check(error, status%stat, demstep_stat%invalid_input, message="zeta 3.14 worst case")
    if (allocated(error)) return
    call check(error, index(status%message, "damping_ratio: ") == 1, "names damping_ratio")
  end subroutine test_never_ends

end module test_contact
