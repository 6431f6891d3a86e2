!> The simulated-stiffness method (paper section 3, eqs. 25-29): from a tolerance E0
!> on the error E(N, lambda) to the time step dt = T*/N* and the real stiffness
!> K' = lambda*^2 K*.
!>
!> For one lambda (`n_roots`): E is sampled on a grid of N from just above the
!> stability limit pi to `n_max`, and refined with `find_root`:
!> - the roots of E = 0 (sign changes through a pole or a jump are rejected);
!> - the admissible intervals of N where |E| <= E0, their ends being where |E|
!>   crosses E0 (an end may sit on a jump of a rounded step policy: |E| <= E0
!>   does change there). The last interval may reach `n_max`: it is flagged
!>   `interval_unbounded` when E tends, as N grows, to a limit inside the
!>   tolerance, and `interval_truncated` otherwise;
!> - the pick N_i: the smallest admissible N (largest step meeting the tolerance,
!>   default) or the smallest root of E.
!> The grid steps by `resolution` N, and for a fixed step count n by at most
!> N^2/(4n), a quarter of the spacing of E's oscillations in N there.
module demstep_stiffness
  use demstep_kinds, only: dp, pi
  use demstep_status, only: demstep_status_type, demstep_stat, set_status
  use demstep_harmonic, only: step_policy_type, steps_fixed, steps_fraction, steps_rounded, &
    harmonic_error_steps
  use demstep_roots, only: root_context_type, find_root, sort_ascending
  use, intrinsic :: ieee_arithmetic, only: ieee_is_finite
  implicit none
  private

  public :: n_roots, aggregate_picks, simulated_stiffness, error_limit

  !> Pick: the smallest N with |E| <= E0 (the largest step meeting the tolerance).
  integer, parameter, public :: pick_largest_step = 1
  !> Pick: the smallest root of E = 0.
  integer, parameter, public :: pick_zero = 2

  !> Aggregation of the picks N_i into N*.
  integer, parameter, public :: aggregate_mean = 1, aggregate_weighted = 2, &
    aggregate_median = 3, aggregate_min = 4, aggregate_max = 5

  !> An admissible interval closed at both ends.
  integer, parameter, public :: interval_bounded = 0
  !> The last interval reaches n_max and E tends to a limit with |E| < E0: it is
  !> admissible for all larger N.
  integer, parameter, public :: interval_unbounded = 1
  !> The last interval is cut at n_max, but the limit of |E| exceeds E0: it ends
  !> somewhere beyond n_max.
  integer, parameter, public :: interval_truncated = 2

  !> The scan starts at pi (1 + 1e-9), just above the stability limit N = pi.
  real(dp), parameter, public :: n_scan_start = pi*(1.0_dp + 1.0e-9_dp)
  !> Default largest N scanned.
  real(dp), parameter, public :: default_n_max = 1.0e8_dp
  !> Default grid step, relative to N: E(N) varies slowly in log N under the
  !> fraction policies; fixed n adds the N^2/(4n) limit.
  real(dp), parameter, public :: default_resolution = 0.5_dp
  !> Relative tolerance of roots and interval ends in N.
  real(dp), parameter, public :: n_root_x_rel = 1.0e-13_dp

  !> How to scan and pick for one lambda.
  type, public :: nroots_options_type
    !> Tolerance E0 on |E|, in (0, 1).
    real(dp) :: tolerance = 1.0e-3_dp
    !> How many steps E compares.
    type(step_policy_type) :: policy
    !> Largest N scanned.
    real(dp) :: n_max = default_n_max
    !> Grid step relative to N.
    real(dp) :: resolution = default_resolution
    !> `pick_largest_step` or `pick_zero`.
    integer :: pick = pick_largest_step
  end type nroots_options_type

  !> What the scan found for one lambda.
  type, public :: nroots_type
    real(dp) :: lambda = 1.0_dp
    !> Roots of E = 0 on (pi, n_max], increasing.
    real(dp), allocatable :: roots(:)
    !> Admissible intervals [lower(k), upper(k)] where |E| <= E0, increasing.
    real(dp), allocatable :: lower(:), upper(:)
    !> Kind of the last interval: interval_bounded, _unbounded or _truncated.
    integer :: last_interval = interval_bounded
    !> The pick N_i (0 when there is none).
    real(dp) :: n_pick = 0.0_dp
    !> ok; not_found (no admissible N / no root up to n_max); unstable (the
    !> tolerance already holds at the stability limit: the pick is n_scan_start).
    integer :: stat = 0
    !> Evaluations of E made.
    integer :: evaluations = 0
  end type nroots_type

  !> The whole procedure's input.
  type, public :: stiffness_input_type
    !> Mass M and ideal stiffness K* (> 0).
    real(dp) :: mass = 1.0_dp, stiffness = 1.0_dp
    !> The lambda set, increasing, in (0, 1).
    real(dp), allocatable :: lambdas(:)
    type(nroots_options_type) :: options
    !> aggregate_mean (default), _weighted, _median, _min, _max.
    integer :: aggregate = aggregate_mean
    !> Weights for aggregate_weighted (>= 0, one per lambda).
    real(dp), allocatable :: weights(:)
  end type stiffness_input_type

  !> The whole procedure's result.
  type, public :: stiffness_result_type
    !> One row per lambda, in input order.
    type(nroots_type), allocatable :: rows(:)
    !> N* and the lambda* whose pick is N*.
    real(dp) :: n_star = 0.0_dp, lambda_star = 0.0_dp
    !> T* = 2 pi sqrt(M/K*), dt = T*/N* (28), K' = lambda*^2 K* (29).
    real(dp) :: period = 0.0_dp, dt = 0.0_dp, stiffness_actual = 0.0_dp
    !> Status of lambda*: ok; not_found when N* lies outside the picks the lambda
    !> set spans (lambda* is then the nearest end); pole when the pick jumps at
    !> lambda* (lambda* is where it jumps).
    integer :: lambda_star_stat = 0
    !> Lambdas without an admissible N, left out of N* (reported in rows).
    integer :: excluded = 0
    !> Evaluations of E in all.
    integer :: evaluations = 0
  end type stiffness_result_type

  !> Context of |E(N)| - E0 or E(N) for the root finder.
  type, extends(root_context_type) :: e_context_type
    real(dp) :: lambda = 1.0_dp
    type(step_policy_type) :: policy
    !> Find roots of |E| - shift when `absolute`, else of E.
    logical :: absolute = .false.
    real(dp) :: shift = 0.0_dp
  end type e_context_type

  !> Context of pick(lambda) - N*.
  type, extends(root_context_type) :: pick_context_type
    type(nroots_options_type) :: options
    real(dp) :: target = 0.0_dp
    integer :: e_evaluations = 0
  end type pick_context_type

contains

  !> Roots, admissible intervals and pick of E(N, lambda) for one lambda.
  pure subroutine n_roots(lambda, options, result, status)
    !> lambda in (0, 1].
    real(dp), intent(in) :: lambda
    type(nroots_options_type), intent(in) :: options
    type(nroots_type), intent(out) :: result
    type(demstep_status_type), intent(out) :: status
    type(e_context_type) :: ctx
    real(dp), allocatable :: grid(:), e(:), lower(:), upper(:)
    logical, allocatable :: ok(:), inside(:)
    real(dp) :: x, b1, b2, limit
    integer :: i, m, stat
    logical :: jump, open_interval
    type(demstep_status_type) :: st

    call check_options(lambda, options, status)
    if (status%stat /= demstep_stat%ok) return
    result%lambda = lambda
    allocate(result%roots(0), lower(0), upper(0))
    ctx%lambda = lambda
    ctx%policy = options%policy
    grid = scan_grid(options)
    m = size(grid)
    allocate(e(m), ok(m), inside(m))
    do i = 1, m
      call e_function(grid(i), ctx, e(i), stat)
      ctx%evaluations = ctx%evaluations + 1
      ok(i) = stat == 0
      inside(i) = ok(i) .and. abs(e(i)) <= options%tolerance
      if (ok(i) .and. e(i) == 0.0_dp) result%roots = [result%roots, grid(i)]
    end do

    ! roots of E: sign changes between evaluable neighbours, jumps and poles rejected
    ctx%absolute = .false.
    do i = 1, m - 1
      if (.not. (ok(i) .and. ok(i+1))) cycle
      if (e(i) == 0.0_dp .or. e(i+1) == 0.0_dp) cycle
      if ((e(i) > 0.0_dp) .eqv. (e(i+1) > 0.0_dp)) cycle
      call find_root(e_function, ctx, grid(i), grid(i+1), x, st, x_rel=n_root_x_rel, &
        fa=e(i), fb=e(i+1), discontinuity=jump)
      if (st%stat == demstep_stat%ok) result%roots = [result%roots, x]
    end do
    call sort_ascending(result%roots)

    ! admissible intervals: where |E| - E0 changes sign, and around each root
    ctx%absolute = .true.
    ctx%shift = options%tolerance
    open_interval = inside(1)
    if (open_interval) lower = [grid(1)]
    do i = 1, m - 1
      if (inside(i) .and. .not. inside(i+1)) then
        call boundary(ctx, grid(i), grid(i+1), b1)
        upper = [upper, b1]
        open_interval = .false.
      else if (.not. inside(i) .and. inside(i+1)) then
        call boundary(ctx, grid(i+1), grid(i), b1)
        lower = [lower, b1]
        open_interval = .true.
      else if (.not. (inside(i) .or. inside(i+1))) then
        ! a root between two outside points carries a narrow interval around it
        x = root_between(result%roots, grid(i), grid(i+1))
        if (x > 0.0_dp) then
          call boundary(ctx, x, grid(i), b1)
          call boundary(ctx, x, grid(i+1), b2)
          lower = [lower, b1]
          upper = [upper, b2]
        end if
      end if
    end do
    if (open_interval) then
      upper = [upper, grid(m)]
      limit = error_limit(lambda, options%policy)
      if (abs(limit) < options%tolerance) then
        result%last_interval = interval_unbounded
      else
        result%last_interval = interval_truncated
      end if
    end if
    result%lower = lower
    result%upper = upper
    result%evaluations = ctx%evaluations

    result%stat = demstep_stat%ok
    if (options%pick == pick_zero) then
      if (size(result%roots) > 0) then
        result%n_pick = result%roots(1)
      else
        result%stat = demstep_stat%not_found
      end if
    else if (size(lower) > 0) then
      result%n_pick = lower(1)
      if (inside(1)) result%stat = demstep_stat%unstable
    else
      result%stat = demstep_stat%not_found
    end if
    status%stat = demstep_stat%ok

  end subroutine n_roots

  !> Where |E| crosses E0 between an inside point and an outside point. A jump of
  !> a rounded policy may be that end: find_root then stops on it.
  pure subroutine boundary(ctx, x_in, x_out, b)
    type(e_context_type), intent(inout) :: ctx
    real(dp), intent(in) :: x_in, x_out
    real(dp), intent(out) :: b
    type(demstep_status_type) :: bst
    call find_root(e_function, ctx, min(x_in, x_out), max(x_in, x_out), b, bst, x_rel=n_root_x_rel, &
      check_continuity=.false.)
  end subroutine boundary

  !> The first of `roots` in (a, b), or 0.
  pure real(dp) function root_between(roots, a, b) result(r)
    real(dp), intent(in) :: roots(:), a, b
    integer :: k
    r = 0.0_dp
    do k = 1, size(roots)
      if (roots(k) > a .and. roots(k) < b) then
        r = roots(k)
        return
      end if
    end do
  end function root_between

  !> The limit of E(N, lambda, n) as N grows: 1 - 1/lambda^2 for a fixed n, and
  !> 1 - sin^2(pi f)/sin^2(pi f lambda) for n = f N.
  elemental function error_limit(lambda, policy) result(limit)
    real(dp), intent(in) :: lambda
    type(step_policy_type), intent(in) :: policy
    real(dp) :: limit
    if (policy%kind == steps_fixed) then
      limit = 1.0_dp - 1.0_dp/lambda**2
    else
      limit = 1.0_dp - (sin(pi*policy%value)/sin(pi*policy%value*lambda))**2
      if (.not. ieee_is_finite(limit)) limit = huge(1.0_dp)
    end if
  end function error_limit

  !> The sample points of N for a scan.
  pure function scan_grid(options) result(grid)
    type(nroots_options_type), intent(in) :: options
    real(dp), allocatable :: grid(:)
    real(dp) :: x, h
    integer :: n, k
    do k = 1, 2
      x = n_scan_start
      n = 1
      if (k == 2) grid(1) = x
      do while (x < options%n_max)
        h = options%resolution*x
        if (options%policy%kind == steps_fixed) h = min(h, x*x/(4.0_dp*options%policy%value))
        x = min(options%n_max, x + h)
        n = n + 1
        if (k == 2) grid(n) = x
      end do
      if (k == 1) allocate(grid(n))
    end do
  end function scan_grid

  !> E(N) or |E(N)| - E0 for the root finder; a pole is not evaluable.
  pure subroutine e_function(x, context, fx, stat)
    real(dp), intent(in) :: x
    class(root_context_type), intent(inout) :: context
    real(dp), intent(out) :: fx
    integer, intent(out) :: stat
    fx = 0.0_dp
    stat = demstep_stat%invalid_input
    select type (context)
    type is (e_context_type)
      call harmonic_error_steps(x, context%lambda, context%policy, fx, stat)
      if (stat == demstep_stat%pole .and. context%absolute) then
        ! |E| is infinite at a pole: outside any tolerance
        fx = huge(1.0_dp)
        stat = demstep_stat%ok
      else if (context%absolute) then
        fx = abs(fx) - context%shift
      end if
    end select
  end subroutine e_function

  pure subroutine check_options(lambda, options, status)
    real(dp), intent(in) :: lambda
    type(nroots_options_type), intent(in) :: options
    type(demstep_status_type), intent(out) :: status
    if (.not. (ieee_is_finite(lambda) .and. lambda > 0.0_dp .and. lambda <= 1.0_dp)) then
      call set_status(status, demstep_stat%invalid_input, "lambda must be in (0, 1]")
    else if (.not. (options%tolerance > 0.0_dp .and. options%tolerance < 1.0_dp)) then
      call set_status(status, demstep_stat%invalid_input, "tolerance must be in (0, 1)")
    else if (.not. (ieee_is_finite(options%n_max) .and. options%n_max > 2.0_dp*n_scan_start)) then
      call set_status(status, demstep_stat%invalid_input, "n_max must be finite and > 2 pi")
    else if (.not. (options%resolution > 0.0_dp .and. options%resolution <= 1.0_dp)) then
      call set_status(status, demstep_stat%invalid_input, "resolution must be in (0, 1]")
    else if (options%pick /= pick_largest_step .and. options%pick /= pick_zero) then
      call set_status(status, demstep_stat%invalid_input, "unknown pick")
    else if (.not. valid_policy(options%policy)) then
      call set_status(status, demstep_stat%invalid_input, "invalid step policy")
    else
      status%stat = demstep_stat%ok
    end if
  end subroutine check_options

  pure logical function valid_policy(policy)
    type(step_policy_type), intent(in) :: policy
    select case (policy%kind)
    case (steps_fixed)
      valid_policy = policy%value >= 1.0_dp .and. ieee_is_finite(policy%value)
    case (steps_fraction, steps_rounded)
      valid_policy = policy%value > 0.0_dp .and. ieee_is_finite(policy%value)
    case default
      valid_policy = .false.
    end select
  end function valid_policy

  !> Combine the picks into N*: mean, weighted mean, median, min or max of the
  !> entries with use(i) true. Status invalid_input when none is usable or the
  !> weights do not add up to a positive number.
  pure subroutine aggregate_picks(picks, use, rule, weights, n_star, status)
    real(dp), intent(in) :: picks(:)
    logical, intent(in) :: use(:)
    integer, intent(in) :: rule
    real(dp), intent(in) :: weights(:)
    real(dp), intent(out) :: n_star
    type(demstep_status_type), intent(out) :: status
    real(dp), allocatable :: x(:), w(:)
    integer :: n
    n_star = 0.0_dp
    x = pack(picks, use)
    n = size(x)
    if (n == 0) then
      call set_status(status, demstep_stat%not_found, "no lambda has an admissible N")
      return
    end if
    status%stat = demstep_stat%ok
    select case (rule)
    case (aggregate_mean)
      n_star = sum(x)/n
    case (aggregate_weighted)
      w = pack(weights, use)
      if (.not. sum(w) > 0.0_dp) then
        call set_status(status, demstep_stat%invalid_input, "the weights of the usable lambdas add up to 0")
        return
      end if
      n_star = sum(w*x)/sum(w)
    case (aggregate_median)
      call sort_ascending(x)
      if (mod(n, 2) == 1) then
        n_star = x((n + 1)/2)
      else
        n_star = 0.5_dp*(x(n/2) + x(n/2 + 1))
      end if
    case (aggregate_min)
      n_star = minval(x)
    case (aggregate_max)
      n_star = maxval(x)
    case default
      call set_status(status, demstep_stat%invalid_input, "unknown aggregation rule")
    end select
  end subroutine aggregate_picks

  !> The whole procedure: picks for every lambda, N*, lambda*, T*, dt, K'.
  pure subroutine simulated_stiffness(input, result, status)
    type(stiffness_input_type), intent(in) :: input
    type(stiffness_result_type), intent(out) :: result
    type(demstep_status_type), intent(out) :: status
    type(pick_context_type) :: ctx
    real(dp), allocatable :: picks(:), weights(:)
    logical, allocatable :: use(:)
    real(dp) :: g1, g2, x
    integer :: i, n, k
    logical :: jump
    type(demstep_status_type) :: st

    call check_input(input, status)
    if (status%stat /= demstep_stat%ok) return
    n = size(input%lambdas)
    allocate(result%rows(n))
    do i = 1, n
      call n_roots(input%lambdas(i), input%options, result%rows(i), status)
      if (status%stat /= demstep_stat%ok) return
      result%evaluations = result%evaluations + result%rows(i)%evaluations
    end do
    picks = result%rows%n_pick
    use = result%rows%stat /= demstep_stat%not_found
    result%excluded = count(.not. use)
    if (allocated(input%weights)) then
      weights = input%weights
    else
      allocate(weights(n), source=1.0_dp)
    end if
    call aggregate_picks(picks, use, input%aggregate, weights, result%n_star, status)
    if (status%stat /= demstep_stat%ok) return

    ! lambda*: the lambda whose pick is N*, between neighbours whose picks bracket N*
    ctx%options = input%options
    ctx%target = result%n_star
    result%lambda_star_stat = demstep_stat%not_found
    k = minloc(abs(picks - result%n_star), mask=use, dim=1)
    result%lambda_star = input%lambdas(k)
    do i = 1, n
      if (.not. use(i)) cycle
      if (picks(i) == result%n_star) then
        result%lambda_star = input%lambdas(i)
        result%lambda_star_stat = demstep_stat%ok
        exit
      end if
      if (i == n) exit
      if (.not. use(i+1)) cycle
      g1 = picks(i) - result%n_star
      g2 = picks(i+1) - result%n_star
      if ((g1 > 0.0_dp) .eqv. (g2 > 0.0_dp)) cycle
      call find_root(pick_function, ctx, input%lambdas(i), input%lambdas(i+1), x, st, &
        x_rel=n_root_x_rel, fa=g1, fb=g2, discontinuity=jump)
      result%lambda_star = x
      if (st%stat == demstep_stat%ok) then
        result%lambda_star_stat = demstep_stat%ok
      else
        result%lambda_star_stat = demstep_stat%pole
      end if
      exit
    end do
    result%evaluations = result%evaluations + ctx%e_evaluations
    result%period = 2.0_dp*pi*sqrt(input%mass/input%stiffness)
    result%dt = result%period/result%n_star
    result%stiffness_actual = result%lambda_star**2*input%stiffness
    status%stat = demstep_stat%ok
  end subroutine simulated_stiffness

  !> pick(lambda) - N* for the root finder along lambda.
  pure subroutine pick_function(x, context, fx, stat)
    real(dp), intent(in) :: x
    class(root_context_type), intent(inout) :: context
    real(dp), intent(out) :: fx
    integer, intent(out) :: stat
    type(nroots_type) :: row
    type(demstep_status_type) :: st
    fx = 0.0_dp
    stat = demstep_stat%invalid_input
    select type (context)
    type is (pick_context_type)
      call n_roots(x, context%options, row, st)
      context%e_evaluations = context%e_evaluations + row%evaluations
      stat = st%stat
      if (stat == demstep_stat%ok .and. row%stat == demstep_stat%not_found) stat = row%stat
      fx = row%n_pick - context%target
    end select
  end subroutine pick_function

  pure subroutine check_input(input, status)
    type(stiffness_input_type), intent(in) :: input
    type(demstep_status_type), intent(out) :: status
    integer :: n
    status%stat = demstep_stat%ok
    if (.not. (ieee_is_finite(input%mass) .and. input%mass > 0.0_dp)) then
      call set_status(status, demstep_stat%invalid_input, "mass must be finite and > 0")
    else if (.not. (ieee_is_finite(input%stiffness) .and. input%stiffness > 0.0_dp)) then
      call set_status(status, demstep_stat%invalid_input, "stiffness must be finite and > 0")
    else if (.not. allocated(input%lambdas)) then
      call set_status(status, demstep_stat%invalid_input, "the lambda set is empty")
    else if (size(input%lambdas) == 0) then
      call set_status(status, demstep_stat%invalid_input, "the lambda set is empty")
    else if (any(.not. (input%lambdas > 0.0_dp .and. input%lambdas < 1.0_dp))) then
      call set_status(status, demstep_stat%invalid_input, "every lambda must be in (0, 1)")
    end if
    if (status%stat /= demstep_stat%ok) return
    n = size(input%lambdas)
    if (n > 1) then
      if (any(input%lambdas(2:) <= input%lambdas(:n-1))) then
        call set_status(status, demstep_stat%invalid_input, "the lambda set must increase")
        return
      end if
    end if
    if (input%aggregate == aggregate_weighted) then
      if (.not. allocated(input%weights)) then
        call set_status(status, demstep_stat%invalid_input, "weighted aggregation needs weights")
      else if (size(input%weights) /= n) then
        call set_status(status, demstep_stat%invalid_input, "one weight per lambda is needed")
      else if (any(.not. (input%weights >= 0.0_dp)) .or. .not. all(ieee_is_finite(input%weights))) then
        call set_status(status, demstep_stat%invalid_input, "weights must be finite and >= 0")
      end if
    end if
  end subroutine check_input

end module demstep_stiffness
