!> Tests of the N-roots of E and the simulated-stiffness procedure against
!> bisection in real128 on the quad-precision E.
module test_stiffness
  use, intrinsic :: iso_fortran_env, only: qp => real128
  use testdrive, only: new_unittest, unittest_type, error_type, check, test_failed
  use demstep
  use demstep_stiffness, only: error_limit
  use demstep_harmonic, only: harmonic_error_steps
  use demstep_stiffness, only: aggregate_picks, interval_kind
  use demstep_kinds, only: pi
  use demstep_stiffness, only: n_scan_start, default_n_max, default_resolution
  use test_support, only: real_str, reference_steps
  use demstep_stiffness, only: measure_evaluation_cost
  use, intrinsic :: ieee_arithmetic, only: ieee_is_finite
  implicit none
  private
  public :: collect_stiffness

  !> Roots and interval ends must match the quad bisection to this, relative.
  real(dp), parameter :: root_tol = 1.0e-12_dp

contains

  subroutine collect_stiffness(testsuite)
    type(unittest_type), allocatable, intent(out) :: testsuite(:)
    testsuite = [ &
      new_unittest("half-period roots, lambda 0.5 .. 0.999999, vs quad bisection", test_roots_quad), &
      new_unittest("interval ends for tolerances 1e-1 .. 1e-10, vs quad", test_interval_ends), &
      new_unittest("unbounded and truncated last intervals", test_unbounded), &
      new_unittest("fixed n: poles between roots are never roots", test_fixed_n_poles), &
      new_unittest("fixed n = 10, 1000: smallest root next to a pole, vs quad from the poles", &
        test_fixed_roots_by_poles), &
      new_unittest("extreme weights, first-only scans, n_max and tolerance limits", test_limits), &
      new_unittest("rounded steps: jumps are never roots", test_rounded_jumps), &
      new_unittest("huge fixed n: picks meet the tolerance as evaluated, or a status says why", &
        test_narrow_intervals), &
      new_unittest("root near 2/(1 - lambda) - 2/3", test_asymptote), &
      new_unittest("aggregation rules", test_aggregate), &
      new_unittest("procedure end to end: dt = T*/N*, K' = lambda*^2 K*", test_procedure), &
      new_unittest("invalid input gives a status", test_invalid), &
      new_unittest("the measured cost of an evaluation is a time", test_measure_cost) &
      ]
  end subroutine collect_stiffness

  !> Accuracy attainable for the half-period root: 1e-12 relative, or the
  !> conditioning limit where E's rounding floor, a few eps (1 - lambda) next to its
  !> root, meets a slope N dE/dN of only about (1 - lambda)^2/4:
  !> dN/N = 8 eps (1 - lambda) / |N dE/dN|.
  function conditioned_tol(root, lambda) result(tol)
    real(dp), intent(in) :: root, lambda
    real(dp) :: tol, e1, e2, h
    integer :: s1, s2
    h = 1.0e-6_dp*root
    call harmonic_error(root + h, lambda, 0.5_dp*(root + h), e2, s2)
    call harmonic_error(root - h, lambda, 0.5_dp*(root - h), e1, s1)
    tol = max(root_tol, 8.0_dp*epsilon(1.0_dp)*(1.0_dp - lambda)/abs((e2 - e1)/(2.0_dp*h)*root))
  end function conditioned_tol

  !> Bisect g(N) = E(N) - shift (or |E| - shift) in quad on [a, b] to 1e-30.
  function quad_bisect(a, b, lambda, fixed, value, shift, absolute) result(x)
    real(dp), intent(in) :: a, b, lambda, value, shift
    logical, intent(in) :: fixed, absolute
    real(qp) :: x, lo, hi, glo, gm
    integer :: it
    lo = a
    hi = b
    glo = g(lo)
    do it = 1, 200
      x = 0.5_qp*(lo + hi)
      if (hi - lo <= 1.0e-30_qp*x) exit
      gm = g(x)
      if ((gm > 0.0_qp) .eqv. (glo > 0.0_qp)) then
        lo = x
        glo = gm
      else
        hi = x
      end if
    end do
  contains
    real(qp) function g(n)
      real(qp), intent(in) :: n
      g = reference_steps(n, lambda, fixed, value)
      if (absolute) g = abs(g)
      g = g - shift
    end function g
  end function quad_bisect

  subroutine test_roots_quad(error)
    type(error_type), allocatable, intent(out) :: error
    real(dp), parameter :: lambdas(8) = [0.5_dp, 0.7_dp, 0.9_dp, 0.99_dp, 0.999_dp, 0.9999_dp, &
      0.99999_dp, 0.999999_dp]
    type(nroots_options_type) :: options
    type(nroots_type) :: r
    type(demstep_status_type) :: status
    real(qp) :: ref
    integer :: i
    options%tolerance = 1.0e-3_dp
    do i = 1, size(lambdas)
      call n_roots(lambdas(i), options, r, status)
      call check(error, status%stat, demstep_stat%ok)
      if (allocated(error)) return
      call check(error, size(r%roots), 1, message="one root at lambda = "//real_str(lambdas(i)))
      if (allocated(error)) return
      ref = quad_bisect(r%roots(1)*(1.0_dp - 1.0e-6_dp), r%roots(1)*(1.0_dp + 1.0e-6_dp), &
        lambdas(i), .false., 0.5_dp, 0.0_dp, .false.)
      call check(error, r%roots(1), real(ref, dp), thr=conditioned_tol(r%roots(1), lambdas(i)), &
        rel=.true., message="root at lambda = "//real_str(lambdas(i)))
      if (allocated(error)) return
    end do
  end subroutine test_roots_quad

  subroutine test_interval_ends(error)
    type(error_type), allocatable, intent(out) :: error
    real(dp), parameter :: lambdas(4) = [0.6_dp, 0.9_dp, 0.99_dp, 0.9999_dp]
    type(nroots_options_type) :: options
    type(nroots_type) :: r
    type(demstep_status_type) :: status
    real(qp) :: ref
    real(dp) :: x, mid
    integer :: i, k, j
    do i = 1, size(lambdas)
      do k = 1, 10
        options%tolerance = 10.0_dp**(-k)
        call n_roots(lambdas(i), options, r, status)
        do j = 1, size(r%lower)
          ! bracket each end between just outside it and the interval's middle
          mid = 0.5_dp*(r%lower(j) + r%upper(j))
          x = r%lower(j)
          if (x > n_scan_start) then
            ref = quad_bisect(x*(1.0_dp - 1.0e-9_dp), mid, lambdas(i), .false., &
              0.5_dp, options%tolerance, .true.)
            call check(error, x, real(ref, dp), thr=root_tol, rel=.true., message="lower end, lambda = " &
              //real_str(lambdas(i))//", E0 = "//real_str(options%tolerance))
            if (allocated(error)) return
          end if
          x = r%upper(j)
          if (x < options%n_max) then
            ref = quad_bisect(mid, x*(1.0_dp + 1.0e-9_dp), lambdas(i), .false., &
              0.5_dp, options%tolerance, .true.)
            call check(error, x, real(ref, dp), thr=root_tol, rel=.true., message="upper end, lambda = " &
              //real_str(lambdas(i))//", E0 = "//real_str(options%tolerance))
            if (allocated(error)) return
          end if
        end do
      end do
    end do
  end subroutine test_interval_ends

  subroutine test_unbounded(error)
    type(error_type), allocatable, intent(out) :: error
    type(nroots_options_type) :: options
    type(nroots_type) :: r
    type(demstep_status_type) :: status
    ! lambda = 0.99: E tends to 1 - 1/sin^2(0.495 pi) = -2.5e-4, inside 1e-3
    options%tolerance = 1.0e-3_dp
    call n_roots(0.99_dp, options, r, status)
    call check(error, r%last_interval, interval_kind%unbounded, message="lambda = 0.99, E0 = 1e-3")
    if (allocated(error)) return
    call check(error, abs(error_limit(0.99_dp, options%policy)) < 1.0e-3_dp, "limit inside")
    if (allocated(error)) return
    ! lambda = 0.9, cut just after the root: the interval goes on but must end
    options%n_max = 19.5_dp
    call n_roots(0.9_dp, options, r, status)
    call check(error, r%last_interval, interval_kind%truncated, message="cut at n_max = 19.5")
    if (allocated(error)) return
    options%n_max = default_n_max
    call n_roots(0.9_dp, options, r, status)
    call check(error, r%last_interval, interval_kind%bounded, message="lambda = 0.9 closes at 20.07")
  end subroutine test_unbounded

  subroutine test_fixed_n_poles(error)
    type(error_type), allocatable, intent(out) :: error
    type(nroots_options_type) :: options, fine
    type(nroots_type) :: r, rf
    type(demstep_status_type) :: status
    real(dp) :: pole, e_lo, e_hi, h
    real(qp) :: ref
    integer :: i, k, s1, s2
    options%tolerance = 1.0e-3_dp
    options%policy = step_policy_type(step_kind%fixed, 100.0_dp)
    options%n_max = 1.0e3_dp
    call n_roots(0.9_dp, options, r, status)
    call check(error, size(r%roots) > 30, "many roots: "//real_str(real(size(r%roots), dp)))
    if (allocated(error)) return
    do i = 1, size(r%roots)
      ! a genuine root: E changing sign within 1e-10 relative, and equal to the quad
      ! bisection's root (the scan now also finds roots within 1e-4 of a pole, where
      ! N dE/dN ~ 1e5 makes |E| at 1e-10 relative reach 1e-5)
      h = 1.0e-10_dp*r%roots(i)
      call harmonic_error_steps(r%roots(i) - h, 0.9_dp, options%policy, e_lo, s1)
      call harmonic_error_steps(r%roots(i) + h, 0.9_dp, options%policy, e_hi, s2)
      call check(error, e_lo*e_hi <= 0.0_dp, "not a root at N = "//real_str(r%roots(i)))
      if (allocated(error)) return
      ref = quad_bisect(r%roots(i) - h, r%roots(i) + h, 0.9_dp, .true., 100.0_dp, 0.0_dp, .false.)
      call check(error, r%roots(i), real(ref, dp), thr=root_tol, rel=.true., message="quad root near N = " &
        //real_str(r%roots(i)))
      if (allocated(error)) return
      ! poles at n lambda/N = k and (n + 1) lambda/N = k: never reported
      do k = 1, 40
        pole = 90.0_dp/k
        call check(error, abs(r%roots(i) - pole) > 1.0e-9_dp*pole, "pole reported as root: " &
          //real_str(pole))
        if (allocated(error)) return
        pole = 90.9_dp/k
        call check(error, abs(r%roots(i) - pole) > 1.0e-9_dp*pole, "pole reported as root: " &
          //real_str(pole))
        if (allocated(error)) return
      end do
    end do
    ! every root: an 8 times finer scan finds the same roots
    fine = options
    fine%resolution = options%resolution/8.0_dp
    call n_roots(0.9_dp, fine, rf, status)
    call check(error, size(rf%roots), size(r%roots), message="roots of a finer scan")
    if (allocated(error)) return
    call check(error, maxval(abs(rf%roots - r%roots)/r%roots) < root_tol, "same roots")
  end subroutine test_fixed_n_poles

  !> The smallest root of E in quad: the poles n lambda/k and (n + 1) lambda/k split
  !> (pi, top] into pieces; each piece is sampled at 256 points from 1e-25 (relative)
  !> inside its poles, and the first sign change is bisected in quad.
  function quad_first_root(n, lambda, top) result(root)
    real(dp), intent(in) :: n, lambda, top
    real(qp) :: root
    real(qp), allocatable :: poles(:)
    real(qp) :: a, b, x, e, e_prev, x_prev, start
    integer :: k, kmax, m, i, j, count
    start = 3.14159265358979323846264338327950288_qp*(1.0_qp + 1.0e-9_qp)
    kmax = ceiling((n + 1.0_dp)*lambda/3.0_dp)
    allocate(poles(2*kmax + 2))
    count = 0
    do k = 1, kmax
      do m = 0, 1
        x = (real(n, qp) + m)*real(lambda, qp)/k
        if (x > start .and. x < real(top, qp)) then
          count = count + 1
          poles(count) = x
        end if
      end do
    end do
    count = count + 1
    poles(count) = real(top, qp)
    poles(:count) = sorted(poles(:count))
    root = -1.0_qp
    a = start
    do i = 1, count
      b = poles(i)
      do j = 0, 256
        x = a + (b - a)*(1.0e-25_qp + (1.0_qp - 2.0e-25_qp)*j/256.0_qp)
        e = reference_steps(x, lambda, .true., n)
        if (j > 0 .and. (e > 0.0_qp .neqv. e_prev > 0.0_qp)) then
          root = bisect_q(x_prev, x)
          return
        end if
        e_prev = e
        x_prev = x
      end do
      a = b
    end do
  contains
    pure function sorted(v) result(w)
      real(qp), intent(in) :: v(:)
      real(qp) :: w(size(v)), s
      integer :: p, q
      w = v
      do p = 2, size(w)
        s = w(p)
        q = p - 1
        do while (q >= 1)
          if (w(q) <= s) exit
          w(q + 1) = w(q)
          q = q - 1
        end do
        w(q + 1) = s
      end do
    end function sorted
    function bisect_q(lo0, hi0) result(xm)
      real(qp), intent(in) :: lo0, hi0
      real(qp) :: xm, lo, hi, glo
      integer :: it
      lo = lo0
      hi = hi0
      glo = reference_steps(lo, lambda, .true., n)
      do it = 1, 300
        xm = 0.5_qp*(lo + hi)
        if (hi - lo <= 1.0e-30_qp*xm) exit
        if ((reference_steps(xm, lambda, .true., n) > 0.0_qp) .eqv. (glo > 0.0_qp)) then
          lo = xm
        else
          hi = xm
        end if
      end do
    end function bisect_q
  end function quad_first_root

  subroutine test_fixed_roots_by_poles(error)
    type(error_type), allocatable, intent(out) :: error
    real(dp), parameter :: lambdas(5) = [0.9_dp, 0.95_dp, 0.99_dp, 0.999_dp, 0.9999_dp]
    real(dp), parameter :: steps(2) = [10.0_dp, 1000.0_dp]
    type(nroots_options_type) :: options, first
    type(nroots_type) :: r, rf
    type(demstep_status_type) :: status
    real(qp) :: ref
    integer :: i, j
    options%tolerance = 1.0e-3_dp
    do j = 1, size(steps)
      options%policy = step_policy_type(step_kind%fixed, steps(j))
      options%n_max = 1.0e4_dp
      first = options
      first%first_only = .true.
      do i = 1, size(lambdas)
        call n_roots(lambdas(i), options, r, status)
        call check(error, status%stat == demstep_stat%ok .and. size(r%roots) > 0, "n = " &
          //real_str(steps(j))//", lambda = "//real_str(lambdas(i))//": a root")
        if (allocated(error)) return
        ref = quad_first_root(steps(j), lambdas(i), 2.0_dp*r%roots(1))
        call check(error, r%roots(1), real(ref, dp), thr=root_tol, rel=.true., message="smallest root, n = " &
          //real_str(steps(j))//", lambda = "//real_str(lambdas(i)))
        if (allocated(error)) return
        ! the first-only scan stops there with the same root, interval and pick
        call n_roots(lambdas(i), first, rf, status)
        call check(error, rf%roots(1) == r%roots(1) .and. rf%lower(1) == r%lower(1) .and. &
          rf%upper(1) == r%upper(1) .and. rf%n_pick == r%n_pick, "first-only scan agrees")
        if (allocated(error)) return
        call check(error, rf%evaluations < r%evaluations, "first-only scan is cheaper")
        if (allocated(error)) return
      end do
    end do
    ! the issue's values (8 digits): a root 0.53 % from the pole 9.9/3
    options%policy = step_policy_type(step_kind%fixed, 10.0_dp)
    call n_roots(0.9_dp, options, r, status)
    call check(error, r%roots(1), 3.3174587_dp, thr=1.0e-7_dp, rel=.true., message="n = 10, lambda = 0.9")
    if (allocated(error)) return
    options%policy = step_policy_type(step_kind%fixed, 1000.0_dp)
    call n_roots(0.999_dp, options, r, status)
    call check(error, r%roots(1), 3.14465252_dp, thr=1.0e-8_dp, rel=.true., message="n = 1000, lambda = 0.999")
  end subroutine test_fixed_roots_by_poles

  subroutine test_limits(error)
    type(error_type), allocatable, intent(out) :: error
    type(stiffness_input_type) :: input
    type(stiffness_result_type) :: result
    type(nroots_options_type) :: options
    type(nroots_type) :: r
    type(demstep_status_type) :: status
    real(dp) :: e
    integer :: stat
    input%mass = 1.0_dp
    input%stiffness = 1.0_dp
    input%options%tolerance = 1.0e-3_dp
    input%lambdas = [0.9_dp, 0.95_dp]
    input%aggregate = aggregate_kind%weighted
    input%weights = [1.0e308_dp, 1.0_dp]
    call simulated_stiffness(input, result, status)
    call check(error, status%stat, demstep_stat%ok, message="weights 1e308, 1")
    if (allocated(error)) return
    ! N* = (1e308 p1 + p2)/(1e308 + 1) = p1 to rounding
    call check(error, result%n_star, result%rows(1)%n_pick, thr=4.0_dp*epsilon(1.0_dp), rel=.true., &
      message="N* with weights 1e308, 1")
    if (allocated(error)) return
    ! n = 1e12 steps: the first-only scan stops at the first root next to pi
    options%tolerance = 1.0e-3_dp
    options%first_only = .true.
    options%policy = step_policy_type(step_kind%fixed, 1.0e12_dp)
    call n_roots(0.9_dp, options, r, status)
    call check(error, status%stat == demstep_stat%ok .and. size(r%roots) == 1, "n = 1e12")
    if (allocated(error)) return
    call check(error, abs(r%n_pick - pi) < 1.0e-8_dp*pi, "n = 1e12: the pick lies next to pi")
    if (allocated(error)) return
    ! every scan for every root with n = 1e12 is refused, naming n_steps
    options%first_only = .false.
    call n_roots(0.9_dp, options, r, status)
    call check(error, status%stat == demstep_stat%invalid_input .and. index(status%message, "n_steps") == 1, &
      "full scan at n = 1e12")
    if (allocated(error)) return
    ! half-period steps evaluate up to N = 2e12; the interval to there is unbounded
    options = nroots_options_type()
    options%tolerance = 0.1_dp
    options%n_max = 2.0e12_dp
    call n_roots(0.9_dp, options, r, status)
    call check(error, status%stat == demstep_stat%ok .and. r%last_interval == interval_kind%unbounded, &
      "lambda 0.9, E0 0.1 up to 2e12: unbounded")
    if (allocated(error)) return
    options%n_max = 2.5e12_dp
    call n_roots(0.9_dp, options, r, status)
    call check(error, status%stat == demstep_stat%invalid_input .and. index(status%message, "n_max") == 1, &
      "n_max beyond n = 1e12")
    if (allocated(error)) return
    options%n_max = default_n_max
    options%resolution = 1.0e-308_dp
    call n_roots(0.9_dp, options, r, status)
    call check(error, status%stat == demstep_stat%invalid_input .and. index(status%message, "resolution") == 1, &
      "resolution 1e-308")
    if (allocated(error)) return
    options%resolution = default_resolution
    options%tolerance = 1.0e-308_dp
    call n_roots(0.9_dp, options, r, status)
    call check(error, status%stat == demstep_stat%invalid_input .and. index(status%message, "tolerance") == 1, &
      "tolerance 1e-308")
    if (allocated(error)) return
    ! the smallest tolerance: the pick meets it
    options%tolerance = 1.0e-10_dp
    call n_roots(0.9_dp, options, r, status)
    call harmonic_error(r%n_pick, 0.9_dp, 0.5_dp*r%n_pick, e, stat)
    call check(error, abs(e) <= options%tolerance, "|E(pick)| <= 1e-10: "//real_str(e))
  end subroutine test_limits

  !> With n up to 1e12 the admissible interval next to the first root can be a
  !> few doubles wide or hold none: every pick and interval end must meet the
  !> tolerance as the public evaluator computes it, or the scan is refused naming
  !> the tolerance. n = 1e12, lambda = 0.9, E0 = 1e-3 gave a pick with |E| = 6.5e-3
  !> before; there three doubles meet the tolerance.
  subroutine test_narrow_intervals(error)
    type(error_type), allocatable, intent(out) :: error
    real(dp), parameter :: ns(3) = [1.0e9_dp, 2147483648.0_dp, 1.0e12_dp]
    real(dp), parameter :: lambdas(3) = [0.5_dp, 0.9_dp, 0.999_dp]
    real(dp), parameter :: tols(6) = [0.1_dp, 1.0e-3_dp, 1.0e-4_dp, 1.0e-5_dp, 1.0e-7_dp, 1.0e-10_dp]
    type(nroots_options_type) :: options
    type(nroots_type) :: r
    type(demstep_status_type) :: status
    real(dp) :: e
    integer :: i, j, k, stat, refused, picked
    refused = 0
    picked = 0
    do i = 1, size(ns)
      do j = 1, size(lambdas)
        do k = 1, size(tols)
          options%policy = step_policy_type(step_kind%fixed, ns(i))
          options%tolerance = tols(k)
          options%first_only = .true.
          call n_roots(lambdas(j), options, r, status)
          if (status%stat /= demstep_stat%ok) then
            call check(error, status%stat == demstep_stat%invalid_input .and. &
              index(status%message, "tolerance: ") == 1 .and. index(status%message, "use tolerance >= ") > 0, &
              "n = "//real_str(ns(i))//", lambda = "//real_str(lambdas(j))//", E0 = "//real_str(tols(k)) &
              //": refused with "//status%message)
            if (allocated(error)) return
            refused = refused + 1
            cycle
          end if
          call check(error, r%stat /= demstep_stat%not_found .and. size(r%lower) == 1, "a pick")
          if (allocated(error)) return
          picked = picked + 1
          call harmonic_error_steps(r%n_pick, lambdas(j), options%policy, e, stat)
          call check(error, stat == demstep_stat%ok .and. abs(e) <= tols(k), "n = "//real_str(ns(i))// &
            ", lambda = "//real_str(lambdas(j))//", E0 = "//real_str(tols(k))//": |E(pick)| = "//real_str(e))
          if (allocated(error)) return
          call harmonic_error_steps(r%upper(1), lambdas(j), options%policy, e, stat)
          call check(error, stat == demstep_stat%ok .and. abs(e) <= tols(k) .and. r%upper(1) >= r%n_pick, &
            "upper end admissible: |E| = "//real_str(e))
          if (allocated(error)) return
        end do
      end do
    end do
    ! both outcomes occur over this set (the loop above tests each)
    call check(error, refused > 0 .and. picked > 0, "some picks and some refusals")
    if (allocated(error)) return
    ! the case that failed before
    options%policy = step_policy_type(step_kind%fixed, 1.0e12_dp)
    options%tolerance = 1.0e-3_dp
    call n_roots(0.9_dp, options, r, status)
    call check(error, status%stat, demstep_stat%ok, message="n = 1e12, lambda 0.9, E0 = 1e-3")
    if (allocated(error)) return
    call harmonic_error(r%n_pick, 0.9_dp, 1.0e12_dp, e, stat)
    call check(error, abs(e) <= 1.0e-3_dp, "n = 1e12, lambda 0.9: |E(pick)| = "//real_str(e))
  end subroutine test_narrow_intervals

  subroutine test_rounded_jumps(error)
    type(error_type), allocatable, intent(out) :: error
    type(nroots_options_type) :: options
    type(nroots_type) :: r
    type(demstep_status_type) :: status
    real(dp) :: e_lo, e_hi, h
    integer :: i, s1, s2, jumps
    options%tolerance = 1.0e-3_dp
    options%policy = step_policy_type(step_kind%rounded, 0.5_dp)
    options%n_max = 1.0e3_dp
    call n_roots(0.9_dp, options, r, status)
    ! n = nint(N/2) jumps at every odd N; E changes sign across many of them
    jumps = 0
    do i = 3, 999, 2
      call harmonic_error_steps(real(i, dp) - 1.0e-9_dp, 0.9_dp, options%policy, e_lo, s1)
      call harmonic_error_steps(real(i, dp) + 1.0e-9_dp, 0.9_dp, options%policy, e_hi, s2)
      if (e_lo*e_hi < 0.0_dp) jumps = jumps + 1
    end do
    call check(error, jumps > 0, "the rounded policy has sign-changing jumps")
    if (allocated(error)) return
    do i = 1, size(r%roots)
      call check(error, abs(r%roots(i) - (2.0_dp*anint(0.5_dp*(r%roots(i) - 1.0_dp)) + 1.0_dp)) > 1.0e-6_dp, &
        "a jump reported as a root at N = "//real_str(r%roots(i)))
      if (allocated(error)) return
      h = 1.0e-10_dp*r%roots(i)
      call harmonic_error_steps(r%roots(i) - h, 0.9_dp, options%policy, e_lo, s1)
      call harmonic_error_steps(r%roots(i) + h, 0.9_dp, options%policy, e_hi, s2)
      call check(error, max(abs(e_lo), abs(e_hi)) < 1.0e-6_dp, "|E| small at the root")
      if (allocated(error)) return
    end do
  end subroutine test_rounded_jumps

  subroutine test_asymptote(error)
    type(error_type), allocatable, intent(out) :: error
    real(dp), parameter :: lambdas(4) = [0.99_dp, 0.999_dp, 0.9999_dp, 0.999999_dp]
    type(nroots_options_type) :: options
    type(nroots_type) :: r
    type(demstep_status_type) :: status
    real(dp) :: n0
    integer :: i
    do i = 1, size(lambdas)
      call n_roots(lambdas(i), options, r, status)
      n0 = 2.0_dp/(1.0_dp - lambdas(i)) - 2.0_dp/3.0_dp
      ! the asymptote's next term is O(1 - lambda) relative
      call check(error, r%roots(1), n0, thr=2.0_dp*(1.0_dp - lambdas(i)), rel=.true., &
        message="lambda = "//real_str(lambdas(i)))
      if (allocated(error)) return
    end do
  end subroutine test_asymptote

  subroutine test_aggregate(error)
    type(error_type), allocatable, intent(out) :: error
    real(dp) :: n_star
    type(demstep_status_type) :: status
    real(dp), parameter :: p(5) = [10.0_dp, 40.0_dp, 20.0_dp, 99.0_dp, 30.0_dp]
    logical, parameter :: use(5) = [.true., .true., .true., .false., .true.]
    real(dp), parameter :: w(5) = [1.0_dp, 0.0_dp, 3.0_dp, 5.0_dp, 0.0_dp]
    call aggregate_picks(p, use, aggregate_kind%mean, w, n_star, status)
    call check(error, n_star, 25.0_dp, thr=1.0e-15_dp, rel=.true., message="mean, one excluded")
    if (allocated(error)) return
    call aggregate_picks(p, use, aggregate_kind%weighted, w, n_star, status)
    call check(error, n_star, 17.5_dp, thr=1.0e-15_dp, rel=.true., message="weighted")
    if (allocated(error)) return
    call aggregate_picks(p, use, aggregate_kind%median, w, n_star, status)
    call check(error, n_star, 25.0_dp, thr=1.0e-15_dp, rel=.true., message="median of 4")
    if (allocated(error)) return
    call aggregate_picks(p, use, aggregate_kind%min, w, n_star, status)
    call check(error, n_star, 10.0_dp, thr=0.0_dp, message="min")
    if (allocated(error)) return
    call aggregate_picks(p, use, aggregate_kind%max, w, n_star, status)
    call check(error, n_star, 40.0_dp, thr=0.0_dp, message="max")
    if (allocated(error)) return
    call aggregate_picks(p, [.false., .false., .false., .false., .false.], aggregate_kind%mean, w, n_star, status)
    call check(error, status%stat, demstep_stat%not_found, message="nothing usable")
  end subroutine test_aggregate

  subroutine test_procedure(error)
    type(error_type), allocatable, intent(out) :: error
    type(stiffness_input_type) :: input
    type(stiffness_result_type) :: result
    type(nroots_type) :: r
    type(demstep_status_type) :: status
    integer :: i
    ! the seed's setting: M = 0.01, K* = 1e5, E0 = 1e-3, lambda in [0.9, 0.99]
    input%mass = 0.01_dp
    input%stiffness = 1.0e5_dp
    input%options%tolerance = 1.0e-3_dp
    input%lambdas = [(0.9_dp + 0.01_dp*i, i = 0, 9)]
    call simulated_stiffness(input, result, status)
    call check(error, status%stat, demstep_stat%ok)
    if (allocated(error)) return
    call check(error, result%n_star, sum(result%rows%n_pick)/10.0_dp, thr=1.0e-14_dp, rel=.true., &
      message="N* is the mean of the picks")
    if (allocated(error)) return
    call check(error, result%period, 2.0_dp*pi*sqrt(0.01_dp/1.0e5_dp), thr=2*epsilon(1.0_dp), &
      rel=.true., message="T*")
    if (allocated(error)) return
    call check(error, result%dt, result%period/result%n_star, thr=0.0_dp, message="dt = T*/N* (28)")
    if (allocated(error)) return
    call check(error, result%stiffness_actual, result%lambda_star**2*1.0e5_dp, thr=0.0_dp, &
      message="K' = lambda*^2 K* (29)")
    if (allocated(error)) return
    call check(error, result%lambda_star_stat, demstep_stat%ok, message="lambda* found")
    if (allocated(error)) return
    ! lambda* really picks N*
    call n_roots(result%lambda_star, input%options, r, status)
    call check(error, r%n_pick, result%n_star, thr=1.0e-10_dp, rel=.true., message="pick(lambda*) = N*")
    if (allocated(error)) return
    ! a lambda without admissible N is reported and left out, not dropped
    input%lambdas = [0.3_dp, 0.9_dp, 0.95_dp]
    call simulated_stiffness(input, result, status)
    call check(error, size(result%rows), 3, message="every lambda has a row")
    if (allocated(error)) return
    call check(error, result%rows(1)%stat, demstep_stat%not_found, message="lambda = 0.3")
    if (allocated(error)) return
    call check(error, result%excluded, 1, message="one excluded")
    if (allocated(error)) return
    call check(error, result%n_star, 0.5_dp*(result%rows(2)%n_pick + result%rows(3)%n_pick), &
      thr=1.0e-14_dp, rel=.true., message="N* from the others")
  end subroutine test_procedure

  subroutine test_invalid(error)
    type(error_type), allocatable, intent(out) :: error
    type(stiffness_input_type) :: input
    type(stiffness_result_type) :: result
    type(nroots_options_type) :: options
    type(nroots_type) :: r
    type(demstep_status_type) :: status
    options%tolerance = 1.5_dp
    call n_roots(0.9_dp, options, r, status)
    call check(error, status%stat, demstep_stat%invalid_input, message="tolerance 1.5")
    if (allocated(error)) return
    options%tolerance = 1.0e-3_dp
    call n_roots(1.5_dp, options, r, status)
    call check(error, status%stat, demstep_stat%invalid_input, message="lambda 1.5")
    if (allocated(error)) return
    input%options%tolerance = 1.0e-3_dp
    input%lambdas = [0.95_dp, 0.9_dp]
    call simulated_stiffness(input, result, status)
    call check(error, status%stat, demstep_stat%invalid_input, message="unsorted set")
    if (allocated(error)) return
    input%lambdas = [0.9_dp, 0.95_dp]
    input%aggregate = aggregate_kind%weighted
    input%weights = [1.0_dp]
    call simulated_stiffness(input, result, status)
    call check(error, status%stat, demstep_stat%invalid_input, message="weights of the wrong length")
    if (allocated(error)) return
    input%weights = [1.0_dp, -1.0_dp]
    call simulated_stiffness(input, result, status)
    call check(error, status%stat, demstep_stat%invalid_input, message="negative weight")
    if (allocated(error)) return
    deallocate(input%lambdas)
    allocate(input%lambdas(0))
    input%aggregate = aggregate_kind%mean
    call simulated_stiffness(input, result, status)
    call check(error, status%stat, demstep_stat%invalid_input, message="empty set")
  end subroutine test_invalid

  !> Only that a positive finite time comes back (timings belong to benchmarks).
  subroutine test_measure_cost(error)
    type(error_type), allocatable, intent(out) :: error
    type(stiffness_input_type) :: input
    real(dp) :: seconds
    input%lambdas = [0.9_dp, 0.99_dp]
    call measure_evaluation_cost(input, seconds)
    call check(error, seconds > 0.0_dp .and. ieee_is_finite(seconds), "seconds = "//real_str(seconds))
    if (allocated(error)) return
    input%options%policy = step_policy_type(step_kind%fixed, 1.0e12_dp)
    input%options%n_max = 1.0e300_dp
    call measure_evaluation_cost(input, seconds)
    call check(error, seconds > 0.0_dp .and. ieee_is_finite(seconds), "fixed n: seconds = "//real_str(seconds))
  end subroutine test_measure_cost

end module test_stiffness
