!> Tests of the harmonic-sum evaluator against independent references: the closed
!> form and direct sums in quad precision (real128), each with its own argument
!> reduction, plus identities, poles and step policies.
module test_harmonic
  use, intrinsic :: iso_fortran_env, only: qp => real128
  use testdrive, only: new_unittest, unittest_type, error_type, check, test_failed
  use demstep
  use demstep_harmonic, only: harmonic_sum, harmonic_error_steps, harmonic_error_check
  use demstep_kinds, only: pi
  use test_support, only: ieee_nan, real_str, sinpi_q, reference
  implicit none
  private
  public :: collect_harmonic

  !> The guaranteed accuracy: |E - E_true| <= 1e-12 (|E_true| + |1 - lambda|).
  real(dp), parameter :: accuracy = 1.0e-12_dp
  !> Points within this relative distance of a pole are exempt (issue statement).
  real(qp), parameter :: pole_margin = 1.0e-9_qp

contains

  subroutine collect_harmonic(testsuite)
    type(unittest_type), allocatable, intent(out) :: testsuite(:)
    testsuite = [ &
      new_unittest("lambda = 1 - 2^-k, k = 1..52", test_lambda_near_one), &
      new_unittest("N just above pi", test_n_near_pi), &
      new_unittest("n in the millions and up to 1e9", test_large_n), &
      new_unittest("next to roots of E (bisected in quad)", test_near_roots), &
      new_unittest("integral n/N gives E = 1 exactly", test_integral_n_over_n), &
      new_unittest("integral n lambda/N is a pole", test_poles), &
      new_unittest("direct sums for n <= 1000, random inputs", test_direct_sums), &
      new_unittest("identities: lambda = 1, symmetry and period of S", test_identities), &
      new_unittest("step policies and continuity in N", test_policies), &
      new_unittest("half-period root near 2/(1 - lambda) - 2/3", test_root_asymptote), &
      new_unittest("invalid input gives a status, no NaN", test_invalid), &
      new_unittest("the domain: refusals name the argument and the range", test_domain) &
      ]
  end subroutine collect_harmonic

  !> Compare with the reference at one point; silently accept points within the
  !> pole margin. `worst` tracks the largest error over the allowed error.
  subroutine compare(error, big_n, lambda, n, worst)
    type(error_type), allocatable, intent(out) :: error
    real(dp), intent(in) :: big_n, lambda, n
    real(dp), intent(inout) :: worst
    real(qp) :: e_ref, pole
    real(dp) :: e, ratio
    integer :: stat
    call reference(big_n, lambda, n, e_ref, pole)
    if (pole < pole_margin) return
    call harmonic_error(big_n, lambda, n, e, stat)
    if (stat /= demstep_stat%ok) then
      call test_failed(error, "status "//real_str(real(stat, dp))//" at N = "//real_str(big_n)// &
        ", lambda = "//real_str(lambda)//", n = "//real_str(n))
      return
    end if
    ratio = real(abs(e - e_ref)/(accuracy*(abs(e_ref) + abs(1.0_qp - real(lambda, qp)))), dp)
    worst = max(worst, ratio)
    if (ratio > 1.0_dp) call test_failed(error, "E = "//real_str(e)//", reference "// &
      real_str(real(e_ref, dp))//" at N = "//real_str(big_n)//", lambda = "//real_str(lambda)// &
      ", n = "//real_str(n))
  end subroutine compare

  subroutine test_lambda_near_one(error)
    type(error_type), allocatable, intent(out) :: error
    real(dp), parameter :: ns(6) = [1.0_dp, 7.0_dp, 1.0e3_dp, 123457.0_dp, 1.0e7_dp, 1.0e9_dp]
    real(dp) :: lambda, big_n, worst
    integer :: k, i, j
    worst = 0.0_dp
    do k = 1, 52
      lambda = 1.0_dp - 2.0_dp**(-k)
      do j = 1, 7
        big_n = pi*(1.0_dp + 1.0e-6_dp) + 37.3_dp*real(j - 1, dp)**2
        call compare(error, big_n, lambda, 0.5_dp*big_n, worst)
        if (allocated(error)) return
        do i = 1, size(ns)
          call compare(error, big_n, lambda, ns(i), worst)
          if (allocated(error)) return
        end do
      end do
    end do
  end subroutine test_lambda_near_one

  subroutine test_n_near_pi(error)
    type(error_type), allocatable, intent(out) :: error
    real(dp) :: big_n, worst, lambda
    integer :: j, i
    worst = 0.0_dp
    do j = 1, 14
      big_n = pi*(1.0_dp + 10.0_dp**(-j))
      do i = 0, 12
        lambda = 1.0_dp - 10.0_dp**(-i)
        if (i == 0) lambda = 0.3_dp
        call compare(error, big_n, lambda, 0.5_dp*big_n, worst)
        if (allocated(error)) return
        call compare(error, big_n, lambda, 3.0_dp, worst)
        if (allocated(error)) return
        call compare(error, big_n, lambda, 2.0_dp**20 + 1.0_dp, worst)
        if (allocated(error)) return
      end do
    end do
  end subroutine test_n_near_pi

  subroutine test_large_n(error)
    type(error_type), allocatable, intent(out) :: error
    real(dp) :: u(4), big_n, lambda, n, worst
    integer :: i
    call seed(7)
    worst = 0.0_dp
    do i = 1, 3000
      call random_number(u)
      big_n = 3.2_dp*10.0_dp**(5.0_dp*u(1))
      lambda = 0.3_dp + 0.7_dp*u(2)
      if (u(4) > 0.5_dp) lambda = 1.0_dp - 10.0_dp**(-1.0_dp - 14.0_dp*u(2))
      n = anint(10.0_dp**(6.0_dp + 3.0_dp*u(3)))
      call compare(error, big_n, lambda, n, worst)
      if (allocated(error)) return
      ! real n in the millions
      call compare(error, big_n, lambda, n*(1.0_dp + 0.37_dp*u(4)) + u(1), worst)
      if (allocated(error)) return
    end do
  end subroutine test_large_n

  !> At roots of E the terms cancel most: bisect sign changes of the quad
  !> reference in N and test the last bracket points.
  subroutine test_near_roots(error)
    type(error_type), allocatable, intent(out) :: error
    real(dp) :: u(3), lambda, n, a, b, m, worst
    real(qp) :: fa, fm, pole
    integer :: trial, it, found
    call seed(11)
    worst = 0.0_dp
    found = 0
    do trial = 1, 400
      call random_number(u)
      lambda = 1.0_dp - 10.0_dp**(-2.0_dp - 12.0_dp*u(1))
      n = anint(10.0_dp**(1.0_dp + 8.0_dp*u(2)))
      a = 3.2_dp + 50.0_dp*u(3)
      b = a*(1.0_dp + 1.0e-3_dp)
      call reference(a, lambda, n, fa, pole)
      call reference(b, lambda, n, fm, pole)
      if (fa*fm > 0.0_qp) cycle
      found = found + 1
      do it = 1, 60
        m = 0.5_dp*(a + b)
        if (m == a .or. m == b) exit
        call reference(m, lambda, n, fm, pole)
        if ((fm > 0.0_qp) .eqv. (fa > 0.0_qp)) then
          a = m
          fa = fm
        else
          b = m
        end if
        if (it > 35) then
          call compare(error, m, lambda, n, worst)
          if (allocated(error)) return
        end if
      end do
    end do
    call check(error, found > 20, "enough sign changes found: "//real_str(real(found, dp)))
  end subroutine test_near_roots

  subroutine test_integral_n_over_n(error)
    type(error_type), allocatable, intent(out) :: error
    real(dp) :: e
    integer :: stat, i
    ! N = 1000, n = 1e7: the naive form returned garbage here (README, "The harmonic-sum evaluator");
    ! lambda = 1/3 keeps n lambda/N away from an integer (0.9 would be a pole)
    call harmonic_error(1000.0_dp, 1.0_dp/3.0_dp, 1.0e7_dp, e, stat)
    call check(error, stat, demstep_stat%ok)
    if (allocated(error)) return
    call check(error, e, 1.0_dp, thr=0.0_dp, message="n/N = 1e4")
    if (allocated(error)) return
    do i = 1, 200
      ! (n + 1)/N integral too
      call harmonic_error(real(4 + i, dp), 0.77_dp, real((4 + i)*(1000*i + 3), dp) - 1.0_dp, e, stat)
      call check(error, stat == demstep_stat%ok .and. e == 1.0_dp, "(n+1)/N integral, i = "// &
        real_str(real(i, dp)))
      if (allocated(error)) return
    end do
  end subroutine test_integral_n_over_n

  subroutine test_poles(error)
    type(error_type), allocatable, intent(out) :: error
    real(dp) :: e, s
    integer :: stat
    ! n lambda/N = 2e6 exactly
    call harmonic_error(10.0_dp, 0.5_dp, 4.0e7_dp, e, stat)
    call check(error, stat, demstep_stat%pole, message="n lambda/N integral")
    if (allocated(error)) return
    call check(error, e == huge(1.0_dp), "value at a pole is huge(), not Inf or NaN")
    if (allocated(error)) return
    ! (n + 1) lambda/N = 1 exactly
    call harmonic_error(12.0_dp, 0.75_dp, 15.0_dp, e, stat)
    call check(error, stat, demstep_stat%pole, message="(n+1) lambda/N integral")
    if (allocated(error)) return
    ! within rounding of a pole
    call harmonic_error(10.0_dp, nearest(0.5_dp, 1.0_dp), 4.0e7_dp, e, stat)
    call check(error, stat, demstep_stat%pole, message="one ulp from a pole")
    if (allocated(error)) return
    ! n lambda/N = 1 - 1e-6 while n/N = 10/7: large but an ordinary value
    call harmonic_error(7.0_dp*(1.0_dp + 1.0e-6_dp), 0.7_dp, 10.0_dp, e, stat)
    call check(error, stat == demstep_stat%ok .and. abs(e) > 1.0e4_dp, "near, not at, a pole")
    if (allocated(error)) return
    ! the sum itself is zero there
    call harmonic_sum(0.5_dp, 10.0_dp, 20.0_dp, s, stat)
    call check(error, s, 0.0_dp, thr=0.0_dp, message="S at the pole")
  end subroutine test_poles

  subroutine test_direct_sums(error)
    type(error_type), allocatable, intent(out) :: error
    real(dp) :: u(3), big_n, lambda, n, s, e, scale
    real(qp) :: s1, s2, e_ref, t
    integer :: i, k, stat
    call seed(3)
    do i = 1, 3000
      call random_number(u)
      big_n = 3.2_dp + 200.0_dp*u(1)
      lambda = 0.05_dp + 0.95_dp*u(2)
      n = real(1 + int(u(3)**2*1000.0_dp), dp)
      s1 = 0.0_qp
      s2 = 0.0_qp
      do k = 1, int(n)
        t = real(k, qp)/real(big_n, qp)
        s1 = s1 + sinpi_q(2.0_qp*t)
        s2 = s2 + sinpi_q(2.0_qp*t*real(lambda, qp))
      end do
      ! S: accurate relative to the largest partial term scale 1/sin(pi c/N)
      call harmonic_sum(lambda, big_n, n, s, stat)
      scale = 1.0_dp/abs(sin(pi*lambda/big_n))
      call check(error, s, real(s2, dp), thr=1.0e-14_dp*scale, &
        message="S at N = "//real_str(big_n)//", n = "//real_str(n))
      if (allocated(error)) return
      if (abs(s2) < 1.0e-6_qp*scale) cycle
      e_ref = 1.0_qp - s1/(real(lambda, qp)*s2)
      call harmonic_error(big_n, lambda, n, e, stat)
      call check(error, e, real(e_ref, dp), thr=accuracy*real(abs(e_ref) + (1.0_qp - lambda), dp), &
        message="E against direct sums at N = "//real_str(big_n)//", n = "//real_str(n))
      if (allocated(error)) return
    end do
  end subroutine test_direct_sums

  subroutine test_identities(error)
    type(error_type), allocatable, intent(out) :: error
    real(dp) :: e, s1, s2
    integer :: stat, i
    do i = 1, 100
      call harmonic_error(3.3_dp + i, 1.0_dp, 0.37_dp*i*i + 1.0_dp, e, stat)
      call check(error, stat == demstep_stat%ok .and. e == 0.0_dp, "lambda = 1 gives E = 0 exactly")
      if (allocated(error)) return
      ! S is odd in its phase and has period N in c (c = i/64 and c + 17 are exact)
      call harmonic_sum(i/64.0_dp, 17.0_dp, 1.0e5_dp + i, s1, stat)
      call harmonic_sum(-i/64.0_dp, 17.0_dp, 1.0e5_dp + i, s2, stat)
      call check(error, s2, -s1, thr=0.0_dp, message="S(-phi) = -S(phi)")
      if (allocated(error)) return
      call harmonic_sum(i/64.0_dp + 17.0_dp, 17.0_dp, 1.0e5_dp + i, s2, stat)
      call check(error, s2, s1, thr=1.0e-13_dp*max(1.0_dp, abs(s1)), rel=.false., &
        message="S(phi + 2 pi) = S(phi)")
      if (allocated(error)) return
    end do
    call harmonic_sum(0.25_dp, 1.0_dp, 3.0_dp, s1, stat)
    ! sin(pi/2) + sin(pi) + sin(3pi/2) = 0
    call check(error, s1, 0.0_dp, thr=4*epsilon(1.0_dp), message="S(pi/2, 3)")
  end subroutine test_identities

  subroutine test_policies(error)
    type(error_type), allocatable, intent(out) :: error
    type(step_policy_type) :: half, fixed
    real(dp) :: e1, e2, big_n, prev, de
    integer :: stat, i
    type(demstep_status_type) :: status
    call new_step_policy(half, step_kind%fraction, 0.5_dp, status)
    call check(error, status%stat, demstep_stat%ok)
    if (allocated(error)) return
    call harmonic_error_steps(19.0_dp, 0.9_dp, half, e1, stat)
    call harmonic_error(19.0_dp, 0.9_dp, 9.5_dp, e2, stat)
    call check(error, e1, e2, thr=0.0_dp, message="half period is n = N/2")
    if (allocated(error)) return
    call new_step_policy(fixed, step_kind%fixed, 40.0_dp, status)
    call harmonic_error_steps(19.0_dp, 0.9_dp, fixed, e1, stat)
    call harmonic_error(19.0_dp, 0.9_dp, 40.0_dp, e2, stat)
    call check(error, e1, e2, thr=0.0_dp, message="fixed n")
    if (allocated(error)) return
    ! continuity: the fraction policy is smooth in N (no jumps between steps)
    call harmonic_error_steps(10.0_dp, 0.9_dp, half, prev, stat)
    do i = 1, 2000
      big_n = 10.0_dp + 0.001_dp*i
      call harmonic_error_steps(big_n, 0.9_dp, half, e1, stat)
      de = abs(e1 - prev)
      call check(error, de < 1.0e-4_dp, "jump of "//real_str(de)//" at N = "//real_str(big_n))
      if (allocated(error)) return
      prev = e1
    end do
    call new_step_policy(fixed, step_kind%fixed, 0.5_dp, status)
    call check(error, status%stat, demstep_stat%invalid_input, message="fixed n < 1")
    if (allocated(error)) return
    call check(error, index(status%message, "n_steps: ") == 1, "names n_steps")
    if (allocated(error)) return
    call new_step_policy(fixed, step_kind%fraction, -1.0_dp, status)
    call check(error, status%stat, demstep_stat%invalid_input, message="negative fraction")
    if (allocated(error)) return
    call check(error, index(status%message, "steps_fraction: ") == 1, "names steps_fraction")
    if (allocated(error)) return
    call new_step_policy(fixed, 7, 1.0_dp, status)
    call check(error, status%stat, demstep_stat%invalid_input, message="unknown kind")
  end subroutine test_policies

  !> With n = N/2, E(N) = 0 near 2/(1 - lambda) - 2/3
  !> (lambda = 0.9: 19.316; 0.99: 199.331).
  subroutine test_root_asymptote(error)
    type(error_type), allocatable, intent(out) :: error
    real(dp) :: lambdas(2), roots(2), e_lo, e_hi
    integer :: i, stat
    lambdas = [0.9_dp, 0.99_dp]
    roots = [19.316_dp, 199.331_dp]
    do i = 1, 2
      call harmonic_error(roots(i) - 0.001_dp, lambdas(i), 0.5_dp*(roots(i) - 0.001_dp), e_lo, stat)
      call harmonic_error(roots(i) + 0.001_dp, lambdas(i), 0.5_dp*(roots(i) + 0.001_dp), e_hi, stat)
      call check(error, e_lo*e_hi < 0.0_dp, "E changes sign across N = "//real_str(roots(i)))
      if (allocated(error)) return
    end do
  end subroutine test_root_asymptote

  subroutine test_invalid(error)
    type(error_type), allocatable, intent(out) :: error
    real(dp) :: e
    integer :: stat
    call harmonic_error(0.0_dp, 0.9_dp, 5.0_dp, e, stat)
    call check(error, stat == demstep_stat%invalid_input .and. e == 0.0_dp, "N = 0")
    if (allocated(error)) return
    call harmonic_error(10.0_dp, -0.1_dp, 5.0_dp, e, stat)
    call check(error, stat, demstep_stat%invalid_input, message="lambda < 0")
    if (allocated(error)) return
    call harmonic_error(10.0_dp, 0.9_dp, 0.5_dp, e, stat)
    call check(error, stat, demstep_stat%invalid_input, message="n < 1")
    if (allocated(error)) return
    call harmonic_error(10.0_dp, 0.9_dp, 2.0e12_dp, e, stat)
    call check(error, stat, demstep_stat%invalid_input, message="n > 1e12")
    if (allocated(error)) return
    call harmonic_error(ieee_nan(), 0.9_dp, 5.0_dp, e, stat)
    call check(error, stat == demstep_stat%invalid_input .and. e == 0.0_dp, "NaN N")
    if (allocated(error)) return
    call harmonic_error(10.0_dp, ieee_nan(), 5.0_dp, e, stat)
    call check(error, stat, demstep_stat%invalid_input, message="NaN lambda")
  end subroutine test_invalid

  !> A fixed seed, so every run tests the same points.
  subroutine seed(k)
    integer, intent(in) :: k
    integer :: n, i
    call random_seed(size=n)
    call random_seed(put=[(1000*k + 17*i, i = 1, n)])
  end subroutine seed

  !> Outside the evaluator's domain E is 0 with invalid_input, never NaN or
  !> Infinity, and harmonic_error_check names the argument; inside it, tiny
  !> lambda gives a huge but finite E, against quad (1e-12 relative).
  subroutine test_domain(error)
    type(error_type), allocatable, intent(out) :: error
    type(demstep_status_type) :: status
    real(dp) :: e
    real(qp) :: e_q, pole
    integer :: stat
    call harmonic_error(10.0_dp, 1.0e-308_dp, 5.0_dp, e, stat)
    call check(error, stat == demstep_stat%invalid_input .and. e == 0.0_dp, "lambda = 1e-308")
    if (allocated(error)) return
    call harmonic_error_check(10.0_dp, 1.0e-308_dp, 5.0_dp, status)
    call check(error, index(status%message, "lambda: must be >= 6.03") == 1, status%message)
    if (allocated(error)) return
    call harmonic_error(10.0_dp, 1.0e308_dp, 5.0_dp, e, stat)
    call check(error, stat == demstep_stat%invalid_input .and. e == 0.0_dp, "lambda = 1e308")
    if (allocated(error)) return
    call harmonic_error_check(10.0_dp, 1.0e308_dp, 5.0_dp, status)
    call check(error, index(status%message, "lambda: must be <= ") == 1, status%message)
    if (allocated(error)) return
    ! E ~ -1e320 at lambda = 1e-160: out of range, refused naming lambda
    call harmonic_error(10.0_dp, 1.0e-160_dp, 5.0_dp, e, stat)
    call check(error, stat == demstep_stat%invalid_input .and. e == 0.0_dp, "lambda = 1e-160")
    if (allocated(error)) return
    call harmonic_error_check(10.0_dp, 1.0e-160_dp, 5.0_dp, status)
    call check(error, index(status%message, "lambda: |E| exceeds the double range") == 1, status%message)
    if (allocated(error)) return
    call harmonic_error_check(1.0e-5_dp, 0.9_dp, 1.0e12_dp, status)
    call check(error, index(status%message, "n_per_period: must be >= ") == 1, status%message)
    if (allocated(error)) return
    call harmonic_error_check(1.0e308_dp, 0.9_dp, 1.0_dp, status)
    call check(error, index(status%message, "n_per_period: must be <= ") == 1, status%message)
    if (allocated(error)) return
    call harmonic_error(10.0_dp, 1.0e-150_dp, 5.0_dp, e, stat)
    call reference(10.0_dp, 1.0e-150_dp, 5.0_dp, e_q, pole)
    call check(error, stat, demstep_stat%ok, message="lambda = 1e-150")
    if (allocated(error)) return
    call check(error, e, real(e_q, dp), thr=1.0e-12_dp, rel=.true., message="E at lambda = 1e-150")
  end subroutine test_domain

end module test_harmonic
