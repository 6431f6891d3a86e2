!> The simulated-stiffness method (paper section 3, eqs. 25-29): from a tolerance E0
!> on the error E(N, lambda) to the time step dt = T*/N* and the real stiffness
!> K' = lambda*^2 K*.
!>
!> For one lambda (`n_roots`): E is sampled from just above the stability limit pi
!> to `n_max` in smooth pieces split at every pole of E and every jump of a rounded
!> step policy (both known in closed form), and refined with `find_root`:
!> - the roots of E = 0 (sign changes through a pole or a jump are rejected);
!> - the admissible intervals of N where |E| <= E0, their ends being where |E|
!>   crosses E0 (an end may sit on a jump of a rounded step policy: |E| <= E0
!>   does change there). The last interval may reach `n_max`: it is flagged
!>   `interval_kind%unbounded` when E tends, as N grows, to a limit inside the
!>   tolerance, and `interval_kind%truncated` otherwise;
!> - the pick N_i: the smallest admissible N (largest step meeting the tolerance,
!>   default) or the smallest root of E.
!> Interval ends and the pick meet |E| <= E0 as E is evaluated. With a huge fixed
!> n, E can change by more than E0 between neighbouring doubles next to a root:
!> such an interval holds no double and is left out (`unresolved`); when it
!> would hold the pick, the scan is refused naming the tolerance that works.
!> Inside a piece the grid steps by `resolution` N, and for a fixed step count n by
!> at most N^2/(4n), a quarter of the spacing of E's oscillations in N there.
!> A scan whose estimated cost exceeds `max_scan_evaluations` is refused.
module demstep_stiffness
  use demstep_kinds, only: dp, pi
  use demstep_status, only: demstep_status_type, demstep_stat, set_status
  use demstep_harmonic, only: step_policy_type, step_kind, harmonic_error_steps, harmonic_error, &
    harmonic_n_max
  use demstep_sort, only: sort_ascending
  use demstep_roots, only: root_context_type, find_root, scan_roots, append, &
    scan_break, scan_cell_type
  use demstep_progress, only: progress_type
  use demstep_text, only: int_text, real_text
  use demstep_spring, only: spring_type, new_spring, spring_period
  use demstep_kinds, only: i8
  use, intrinsic :: ieee_arithmetic, only: ieee_is_finite
  use demstep_words, only: word_index, word_of
  implicit none
  private

  public :: n_roots, aggregate_picks, simulated_stiffness, error_limit, scan_cost, procedure_cost, &
    n_max_limit, measure_evaluation_cost

  !> The picks N_i one lambda can give, by name: `pick_kind%largest_step`.
  type, public :: pick_kind_enum
    !> The smallest N with |E| <= E0 (the largest step meeting the tolerance).
    integer :: largest_step = 1
    !> The smallest root of E = 0.
    integer :: zero = 2
  end type pick_kind_enum
  !> The picks by name.
  type(pick_kind_enum), parameter, public :: pick_kind = pick_kind_enum()
  !> Their words, in code order (`pick_kind_from_name`, `pick_kind_name`).
  character(len=*), parameter, public :: pick_kind_names(2) = [character(len=12) :: "largest_step", "zero"]
  public :: pick_kind_from_name, pick_kind_name

  !> The rules aggregating the picks N_i into N*, by name: `aggregate_kind%mean`.
  type, public :: aggregate_kind_enum
    !> The mean.
    integer :: mean = 1
    !> The weighted mean (one weight per lambda).
    integer :: weighted = 2
    !> The median.
    integer :: median = 3
    !> The smallest pick.
    integer :: min = 4
    !> The largest pick.
    integer :: max = 5
  end type aggregate_kind_enum
  !> The aggregation rules by name.
  type(aggregate_kind_enum), parameter, public :: aggregate_kind = aggregate_kind_enum()
  !> Their words, in code order (`aggregate_kind_from_name`, `aggregate_kind_name`).
  character(len=*), parameter, public :: aggregate_kind_names(5) = [character(len=8) :: "mean", "weighted", "median", "min", "max"]
  public :: aggregate_kind_from_name, aggregate_kind_name

  !> The kinds of the last admissible interval, by name: `interval_kind%unbounded`.
  type, public :: interval_kind_enum
    !> Closed at both ends.
    integer :: bounded = 0
    !> Reaches n_max and E tends to a limit with |E| < E0: admissible for all larger N.
    integer :: unbounded = 1
    !> Cut at n_max, but the limit of |E| exceeds E0: it ends somewhere beyond n_max.
    integer :: truncated = 2
  end type interval_kind_enum
  !> The interval kinds by name.
  type(interval_kind_enum), parameter, public :: interval_kind = interval_kind_enum()
  !> Their words, in code order (`interval_kind_from_name`, `interval_kind_name`).
  character(len=*), parameter, public :: interval_kind_names(3) = [character(len=9) :: "bounded", "unbounded", "truncated"]
  public :: interval_kind_from_name, interval_kind_name

  !> The scan starts at pi (1 + 1e-9), just above the stability limit N = pi.
  real(dp), parameter, public :: n_scan_start = pi*(1.0_dp + 1.0e-9_dp)
  !> Default largest N scanned.
  real(dp), parameter, public :: default_n_max = 1.0e8_dp
  !> Default grid step, relative to N: E(N) varies slowly in log N under the
  !> fraction policies; fixed n adds the N^2/(4n) limit.
  real(dp), parameter, public :: default_resolution = 0.5_dp
  !> Relative tolerance of roots and interval ends in N.
  real(dp), parameter, public :: n_root_x_rel = 1.0e-13_dp
  !> Smallest tolerance E0: E is computed to 1e-12 (|E| + (1 - lambda)) <= 1e-12, so
  !> at E0 = 1e-10 |E| <= E0 holds to within 1 % of E0.
  real(dp), parameter, public :: min_tolerance = 1.0e-10_dp
  !> Largest estimated cost of one lambda's scan, in evaluations of E (seconds:
  !> `measure_evaluation_cost` and bench_stiffness measure the cost of one).
  real(dp), parameter, public :: max_scan_evaluations = 2.0e7_dp
  !> Largest estimated cost of the whole procedure (a few minutes): a fine scan
  !> the user asks for; the app says so up front and shows progress.
  real(dp), parameter, public :: max_procedure_evaluations = 1.0e9_dp
  !> Scans of the search for lambda* (ITP along lambda to 1e-13 and its probes).
  integer, parameter, public :: lambda_star_scans = 50
  !> A rounded policy's jumps are breakpoints up to this many steps n (N = 1e5/f);
  !> beyond, E's jumps are O(1/N) and the scan samples n = nint(f N) on the grid.
  real(dp), parameter, public :: rounded_exact_steps = 1.0e5_dp
  !> Largest n_max for a fixed n: E's closed form is evaluated in double to here.
  real(dp), parameter :: fixed_n_max_limit = 1.0e300_dp


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
    !> `pick_kind%largest_step` or `pick_kind%zero`.
    integer :: pick = pick_kind%largest_step
    !> Stop the scan once the first root and the first admissible interval are
    !> known (all the pick needs); `roots`, `lower`, `upper` then hold only those.
    logical :: first_only = .false.
  end type nroots_options_type

  !> What the scan found for one lambda.
  type, public :: nroots_type
    real(dp) :: lambda = 1.0_dp
    !> Roots of E = 0 on (pi, n_max], increasing.
    real(dp), allocatable :: roots(:)
    !> Admissible intervals [lower(k), upper(k)] where |E| <= E0, increasing.
    real(dp), allocatable :: lower(:), upper(:)
    !> Kind of the last interval: interval_kind%bounded, _unbounded or _truncated.
    integer :: last_interval = interval_kind%bounded
    !> The pick N_i (0 when there is none).
    real(dp) :: n_pick = 0.0_dp
    !> ok; not_found (no admissible N / no root up to n_max); at_stability_limit
    !> (the tolerance already holds at the stability limit: the pick is n_scan_start).
    integer :: stat = 0
    !> Evaluations of E made.
    integer :: evaluations = 0
    !> Roots of E whose admissible interval holds no double N (|E| changes by
    !> more than E0 between neighbouring doubles there): left out of lower/upper.
    integer :: unresolved = 0
  end type nroots_type

  !> The whole procedure's input.
  type, public :: stiffness_input_type
    !> Mass M and ideal stiffness K* (> 0).
    real(dp) :: mass = 1.0_dp, stiffness = 1.0_dp
    !> The lambda set, increasing, in (0, 1).
    real(dp), allocatable :: lambdas(:)
    type(nroots_options_type) :: options
    !> aggregate_kind%mean (default), _weighted, _median, _min, _max.
    integer :: aggregate = aggregate_kind%mean
    !> Weights for aggregate_kind%weighted (>= 0, one per lambda).
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
    !> set spans (lambda* is then the nearest end); discontinuous when the pick
    !> jumps at lambda* (lambda* is where it jumps).
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
    !> The piece's step count, or 0 where n follows the policy.
    real(dp) :: n = 0.0_dp
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

  !> One sample of the scan.
  type :: sample_type
    real(dp) :: x = 0.0_dp, e = 0.0_dp
    logical :: ok = .false., inside = .false.
  end type sample_type

  !> What a scan has found so far: the context `scan_roots` passes to E and to
  !> the scan's callbacks.
  type, extends(e_context_type) :: scan_state_type
    type(nroots_options_type) :: options
    real(dp) :: tolerance = 0.0_dp
    !> The step count of the piece after the next breakpoint (0: n = f N).
    real(dp) :: n_next = 0.0_dp
    real(dp), allocatable :: lower(:), upper(:)
    integer :: n_roots = 0, n_lower = 0, n_upper = 0
    type(sample_type) :: prev
    logical :: inside_at_start = .false.
    !> Set when the scan must be refused (see `budget`, `blocked`).
    type(demstep_status_type) :: refusal
    !> A hard stop on the evaluations, should the estimate be far off.
    real(dp) :: budget = 0.0_dp
    !> Roots whose admissible interval holds no double N (narrower than the
    !> spacing of doubles there): left out of the intervals.
    integer :: unresolved = 0
    !> Set when the first such root comes before any admissible interval: the
    !> smallest admissible N cannot be represented. `blocked_root` is that root,
    !> `blocked_e` the smallest |E| at a double next to it.
    logical :: blocked = .false.
    real(dp) :: blocked_root = 0.0_dp, blocked_e = 0.0_dp
  end type scan_state_type

contains

  !> Roots, admissible intervals and pick of E(N, lambda) for one lambda.
  !>
  !> The scan runs from the start (pi, or 1/f where n = f N reaches 1) to `n_max`
  !> in smooth pieces: every pole of E (a zero of S(2 pi lambda/N, n)) and every
  !> jump of a rounded step policy is a breakpoint, sampled one-sidedly on both
  !> sides, so a root or an interval end next to a pole is bracketed however close
  !> it lies. Inside a piece the grid steps by `resolution` N (and by N^2/(4n)
  !> with a fixed n). Cost: one evaluation per grid point and per piece end, about
  !> 30 per root or interval end; with `first_only` the scan stops once the first
  !> root and the first interval are known.
  pure subroutine n_roots(lambda, options, result, status)
    !> lambda in (0, 1].
    real(dp), intent(in) :: lambda
    type(nroots_options_type), intent(in) :: options
    type(nroots_type), intent(out) :: result
    type(demstep_status_type), intent(out) :: status
    type(scan_state_type) :: s
    real(dp), allocatable :: roots(:), jumps(:)
    real(dp) :: limit

    call check_options(lambda, options, status)
    if (status%stat /= demstep_stat%ok) return
    result%lambda = lambda
    s%lambda = lambda
    s%policy = options%policy
    s%options = options
    s%tolerance = options%tolerance
    allocate(s%lower(8), s%upper(8))
    s%budget = 4.0_dp*max_scan_evaluations
    s%n_next = piece_steps(options%policy, scan_start(options%policy))
    call scan_roots(e_function, s, scan_start(options%policy), options%n_max, roots, jumps, status, &
      x_rel=n_root_x_rel, next_break=piece_break, step=piece_step, visit=visit_sample)
    if (status%stat /= demstep_stat%ok) return
    if (s%refusal%stat /= demstep_stat%ok) then
      status = s%refusal
      return
    end if
    s%n_roots = size(roots)

    result%last_interval = interval_kind%bounded
    if (s%n_lower > s%n_upper) then
      ! the last interval reaches n_max: unbounded when E's limit lies inside
      call append(s%upper, s%n_upper, options%n_max)
      limit = error_limit(lambda, options%policy)
      if (abs(limit) < options%tolerance) then
        result%last_interval = interval_kind%unbounded
      else
        result%last_interval = interval_kind%truncated
      end if
    end if
    if (options%first_only) then
      s%n_roots = min(s%n_roots, 1)
      if (s%n_lower > 1) result%last_interval = interval_kind%bounded
      s%n_lower = min(s%n_lower, 1)
      s%n_upper = s%n_lower
    end if
    result%roots = roots(:s%n_roots)
    result%lower = s%lower(:s%n_lower)
    result%upper = s%upper(:s%n_upper)
    result%unresolved = s%unresolved

    result%stat = demstep_stat%ok
    if (options%pick == pick_kind%zero) then
      if (size(result%roots) > 0) then
        result%n_pick = result%roots(1)
      else
        result%stat = demstep_stat%not_found
      end if
    else if (size(result%lower) > 0) then
      call check_pick(s, options, result, status)
      if (status%stat /= demstep_stat%ok) return
      result%n_pick = result%lower(1)
      if (s%inside_at_start .and. result%lower(1) == n_scan_start) result%stat = demstep_stat%at_stability_limit
    else
      result%stat = demstep_stat%not_found
    end if
    result%evaluations = s%evaluations
    status%stat = demstep_stat%ok
  end subroutine n_roots

  !> The pick must meet the tolerance as the public evaluator (`harmonic_error_steps`)
  !> computes it: the scan evaluates E piece by piece with the piece's step count,
  !> which can differ from the policy's exactly at a jump. When it does not, the
  !> next doubles up inside the interval are tried; else the scan is refused.
  pure subroutine check_pick(s, options, result, status)
    type(scan_state_type), intent(inout) :: s
    type(nroots_options_type), intent(in) :: options
    type(nroots_type), intent(inout) :: result
    type(demstep_status_type), intent(out) :: status
    real(dp) :: x, e, e_min
    integer :: k, stat
    status%stat = demstep_stat%ok
    x = result%lower(1)
    e_min = huge(1.0_dp)
    do k = 1, 16
      call harmonic_error_steps(x, s%lambda, options%policy, e, stat)
      s%evaluations = s%evaluations + 1
      if (stat == demstep_stat%ok .and. ieee_is_finite(e)) then
        if (abs(e) <= options%tolerance) then
          result%lower(1) = x
          return
        end if
        e_min = min(e_min, abs(e))
      end if
      x = nearest(x, 1.0_dp)
      if (x > result%upper(1)) exit
    end do
    call unresolvable(s%lambda, options, result%lower(1), e_min, status)
  end subroutine check_pick

  !> The status of a scan whose smallest admissible N lies in an interval holding
  !> no double (E changes by more than E0 between neighbouring doubles there).
  pure subroutine unresolvable(lambda, options, x, e_min, status)
    real(dp), intent(in) :: lambda, x, e_min
    type(nroots_options_type), intent(in) :: options
    type(demstep_status_type), intent(out) :: status
    character(len=:), allocatable :: advice
    advice = "use tolerance >= "//real_text(round_up_2(max(e_min, min_tolerance)))
    if (options%policy%kind == step_kind%fixed) advice = advice//" or fewer n_steps"
    call set_status(status, demstep_stat%invalid_input, "for lambda = "//real_text(lambda) &
      //" the smallest N with |E| <= "//real_text(options%tolerance)//" lies next to N = " &
      //real_text(x, 15)//" in an interval narrower than the spacing of doubles: |E| >= " &
      //real_text(e_min)//" at every double N there; "//advice, where="tolerance")
  end subroutine unresolvable

  !> The scan's bookkeeping of one sample (`scan_roots` found the roots): the
  !> admissible intervals, and the refusals (a blocked pick, the budget).
  pure subroutine visit_sample(context, cell, halt)
    class(root_context_type), intent(inout) :: context
    type(scan_cell_type), intent(in) :: cell
    logical, intent(inout) :: halt
    type(sample_type) :: cur
    select type (s => context)
    class is (scan_state_type)
      cur%x = cell%cur%x
      cur%e = cell%cur%f
      cur%ok = cell%cur%ok
      cur%inside = cur%ok .and. abs(cur%e) <= s%tolerance
      s%n_roots = cell%roots
      if (cell%across == scan_break%start) then
        if (cur%inside) call append(s%lower, s%n_lower, cur%x)
        s%inside_at_start = cur%inside
      else if (cell%across == scan_break%pole) then
        ! E is not evaluable at a pole: the samples either side are the ends
        call across(s, cur, s%prev%x, cur%x)
      else if (cell%across == scan_break%jump) then
        call across(s, cur, cell%at, cell%at)
      else
        call within(s, cur, cell)
      end if
      s%prev = cur
      if (s%options%first_only .and. s%n_roots > 0 .and. s%n_upper > 0) halt = .true.
      if (s%blocked .and. s%options%pick == pick_kind%largest_step) then
        call unresolvable(s%lambda, s%options, s%blocked_root, s%blocked_e, s%refusal)
        halt = .true.
      else if (real(s%evaluations, dp) > s%budget) then
        if (s%options%policy%kind == step_kind%fixed) then
          call set_status(s%refusal, demstep_stat%invalid_input, "the scan of E for " &
            //"lambda = "//real_text(s%lambda)//" took more than "//real_text(s%budget) &
            //" evaluations; use fewer steps, a coarser resolution or a smaller n_max", where="n_steps")
        else
          call set_status(s%refusal, demstep_stat%invalid_input, "the scan of E for " &
            //"lambda = "//real_text(s%lambda)//" took more than "//real_text(s%budget) &
            //" evaluations; use a coarser resolution or a smaller n_max", where="resolution")
        end if
        halt = .true.
      end if
    end select
  end subroutine visit_sample

  !> The next breakpoint of the scan after a (`next_break`), and the step count
  !> of the piece starting at a.
  pure subroutine piece_break(context, a, b, kind)
    class(root_context_type), intent(inout) :: context
    real(dp), intent(in) :: a
    real(dp), intent(inout) :: b
    integer, intent(inout) :: kind
    select type (s => context)
    class is (scan_state_type)
      s%n = s%n_next
      call next_break(s%lambda, s%policy, a, s%n, s%options%n_max, b, kind, s%n_next)
    end select
  end subroutine piece_break

  !> The grid step at x in the current piece (`grid_step`).
  pure function piece_step(context, x) result(h)
    class(root_context_type), intent(in) :: context
    real(dp), intent(in) :: x
    real(dp) :: h
    h = 0.0_dp
    select type (s => context)
    class is (scan_state_type)
      h = grid_step(s%options, s%n, x)
    end select
  end function piece_step

  !> The first sample of a new piece: admissibility may change at the breakpoint
  !> `at` itself (a jump; or a removable pole); no root is sought across it.
  pure subroutine across(s, cur, at_upper, at_lower)
    type(scan_state_type), intent(inout) :: s
    type(sample_type), intent(in) :: cur
    real(dp), intent(in) :: at_upper, at_lower
    if (s%prev%inside .and. .not. cur%inside) then
      call append(s%upper, s%n_upper, at_upper)
    else if (.not. s%prev%inside .and. cur%inside) then
      call append(s%lower, s%n_lower, at_lower)
    end if
  end subroutine across

  !> A cell inside a smooth piece: its root (sign change of E) and the interval
  !> ends in it (where |E| crosses E0, or around a root between outside points).
  pure subroutine within(s, cur, cell)
    type(scan_state_type), intent(inout) :: s
    type(sample_type), intent(in) :: cur
    !> The cell as `scan_roots` saw it: its root, if any, and find_root's bracket.
    type(scan_cell_type), intent(in) :: cell
    type(sample_type) :: prev
    real(dp) :: r, b, r_lo, r_hi, x_in, e_min
    logical :: found, resolved
    prev = s%prev
    found = cell%root_found
    r = cell%root
    r_lo = cell%bracket_lo
    r_hi = cell%bracket_hi
    if (prev%inside .and. .not. cur%inside) then
      call boundary(s, prev%x, cur%x, abs(prev%e), abs(cur%e), b)
      call append(s%upper, s%n_upper, b)
    else if (.not. prev%inside .and. cur%inside) then
      call boundary(s, cur%x, prev%x, abs(cur%e), abs(prev%e), b)
      call append(s%lower, s%n_lower, b)
    else if (.not. (prev%inside .or. cur%inside) .and. found) then
      ! a root between two outside points carries a narrow interval around it,
      ! found from an admissible double next to the root
      call admissible_near_root(s, r, r_lo, r_hi, x_in, resolved, e_min)
      if (resolved) then
        call boundary(s, x_in, prev%x, e_min, abs(prev%e), b)
        call append(s%lower, s%n_lower, b)
        call boundary(s, x_in, cur%x, e_min, abs(cur%e), b)
        call append(s%upper, s%n_upper, b)
      else
        s%unresolved = s%unresolved + 1
        if (s%n_lower == 0 .and. .not. s%blocked) then
          s%blocked = .true.
          s%blocked_root = r
          s%blocked_e = e_min
        end if
      end if
    end if
  end subroutine within

  !> An admissible double next to a root r of E (bracket [lo, hi] from find_root):
  !> r itself when |E(r)| <= E0; else every double of the bracket shrunk to a few
  !> ulps is tried (E is monotone there, so none further away can do better).
  !> `found` is false when none meets the tolerance; `e_min` is the smallest |E| seen
  !> (|E(x)|).
  pure subroutine admissible_near_root(s, r, lo, hi, x, found, e_min)
    type(scan_state_type), intent(inout) :: s
    real(dp), intent(in) :: r, lo, hi
    real(dp), intent(out) :: x, e_min
    logical, intent(out) :: found
    type(demstep_status_type) :: st
    real(dp) :: e, y, lo2, hi2, r2
    integer :: stat, k
    s%absolute = .false.
    x = r
    e_min = huge(1.0_dp)
    found = .false.
    call e_function(r, s, e, stat)
    s%evaluations = s%evaluations + 1
    if (stat == demstep_stat%ok) then
      e_min = abs(e)
      found = e_min <= s%tolerance
      if (found) return
    end if
    ! a bracket of at most 8 ulps (find_root's floor on its tolerance)
    call find_root(e_function, s, lo, hi, r2, st, x_rel=0.0_dp, x_abs=tiny(1.0_dp), &
      check_continuity=.false., bracket_lo=lo2, bracket_hi=hi2)
    if (st%stat /= demstep_stat%ok) return
    y = lo2
    do k = 1, 16
      call e_function(y, s, e, stat)
      s%evaluations = s%evaluations + 1
      if (stat == demstep_stat%ok .and. abs(e) < e_min) then
        e_min = abs(e)
        x = y
      end if
      if (y >= hi2) exit
      y = nearest(y, 1.0_dp)
    end do
    found = e_min <= s%tolerance
  end subroutine admissible_near_root

  !> Where |E| crosses E0 between an admissible x_in and an inadmissible x_out:
  !> the end of find_root's final bracket on x_in's side, so admissible as
  !> evaluated (|E| <= E0 there) however narrow the interval, and within
  !> 2 n_root_x_rel (relative) of the crossing. A jump of a rounded policy may be
  !> that end. `e_in`, `e_out` are |E| at x_in, x_out (known from the scan). All
  !> evaluations go through find_root and are counted.
  pure subroutine boundary(s, x_in, x_out, e_in, e_out, b)
    type(scan_state_type), intent(inout) :: s
    real(dp), intent(in) :: x_in, x_out, e_in, e_out
    real(dp), intent(out) :: b
    type(demstep_status_type) :: st
    real(dp) :: r, lo, hi, g_in, g_out
    s%absolute = .true.
    s%shift = s%tolerance
    g_in = e_in - s%tolerance
    g_out = e_out - s%tolerance
    if (x_in < x_out) then
      call find_root(e_function, s, x_in, x_out, r, st, x_rel=n_root_x_rel, fa=g_in, fb=g_out, &
        check_continuity=.false., bracket_lo=lo, bracket_hi=hi)
    else
      call find_root(e_function, s, x_out, x_in, r, st, x_rel=n_root_x_rel, fa=g_out, fb=g_in, &
        check_continuity=.false., bracket_lo=lo, bracket_hi=hi)
    end if
    b = x_in
    if (st%stat == demstep_stat%ok) b = merge(lo, hi, x_in < x_out)
    s%absolute = .false.
  end subroutine boundary


  !> Where the scan starts: just above the stability limit pi, and where n = f N
  !> reaches one step (N = 1/f) for the fraction policy.
  pure real(dp) function scan_start(policy) result(x)
    type(step_policy_type), intent(in) :: policy
    x = n_scan_start
    if (policy%kind == step_kind%fraction) x = max(x, (1.0_dp/policy%value)*(1.0_dp + 4.0_dp*epsilon(1.0_dp)))
  end function scan_start

  !> The fixed step count of the piece starting at x, or 0 where n follows the policy.
  pure real(dp) function piece_steps(policy, x) result(n)
    type(step_policy_type), intent(in) :: policy
    real(dp), intent(in) :: x
    n = 0.0_dp
    select case (policy%kind)
    case (step_kind%fixed)
      n = policy%value
    case (step_kind%rounded)
      n = max(1.0_dp, anint(policy%value*x))
      if (n > rounded_exact_steps) n = 0.0_dp
    end select
  end function piece_steps

  !> The grid step at x inside a piece with n steps (0: n = f N); `scan_roots`
  !> steps by at least 4 ulps.
  pure real(dp) function grid_step(options, n, x) result(h)
    type(nroots_options_type), intent(in) :: options
    real(dp), intent(in) :: n, x
    h = options%resolution*x
    if (n > 0.0_dp) h = min(h, x*(x/(4.0_dp*n)))
  end function grid_step

  !> The smallest pole c/k > a (k = 1, 2, ...) of a family c = m lambda; huge if none.
  pure real(dp) function next_pole(c, a) result(p)
    real(dp), intent(in) :: c, a
    real(dp) :: k
    p = huge(1.0_dp)
    if (.not. c > a) return
    ! the largest k with c/k > a
    k = aint(c/a)
    if (k >= 1.0_dp) then
      if (.not. c/k > a) k = k - 1.0_dp
    end if
    if (c/(k + 1.0_dp) > a) k = k + 1.0_dp
    if (k >= 1.0_dp) p = c/k
  end function next_pole

  !> The next breakpoint b > a of the scan (a pole of E, a jump of the rounded
  !> policy, or n_max), its kind, and the step count n of the piece after it.
  pure subroutine next_break(lambda, policy, a, n_piece, n_max, b, kind, n_next)
    real(dp), intent(in) :: lambda, a, n_piece, n_max
    type(step_policy_type), intent(in) :: policy
    real(dp), intent(out) :: b, n_next
    integer, intent(out) :: kind
    real(dp) :: p, jump, f, k
    b = n_max
    kind = scan_break%end
    n_next = n_piece
    p = huge(1.0_dp)
    if (n_piece > 0.0_dp) then
      ! S(2 pi lambda/N, n) = 0 where n lambda/N or (n + 1) lambda/N is an integer
      p = min(next_pole(n_piece*lambda, a), next_pole((n_piece + 1.0_dp)*lambda, a))
      if (policy%kind == step_kind%rounded) then
        jump = (n_piece + 0.5_dp)/policy%value
        if (jump < b .and. jump <= p) then
          b = jump
          kind = scan_break%jump
          n_next = n_piece + 1.0_dp
          if (n_next > rounded_exact_steps) n_next = 0.0_dp
        end if
      end if
    else if (policy%kind == step_kind%fraction) then
      ! n = f N: only (n + 1) lambda/N = f lambda + lambda/N can be an integer k,
      ! at N = lambda/(k - f lambda), k the first integer above f lambda
      f = policy%value
      k = aint(f*lambda) + 1.0_dp
      if (k - f*lambda > 0.0_dp) then
        p = lambda/(k - f*lambda)
        if (.not. p > a) p = huge(1.0_dp)
      end if
    end if
    if (p < b) then
      b = p
      kind = scan_break%pole
      n_next = n_piece
    end if
  end subroutine next_break

  !> Estimated evaluations of E for one lambda's scan: the grid (log(n_max/start)
  !> / log(1 + resolution)), with a fixed n also the N^2/(4n) grid and two samples
  !> per pole below n lambda (about 4n/pi and 4n/pi); with a rounded policy two
  !> samples per exact segment. Roots and interval ends add about 30 each. With
  !> `first_only` a fixed n's dense part is counted only to its first root, which
  !> lies within a few poles (an allowance of 4096 samples).
  pure real(dp) function scan_cost(options) result(cost)
    type(nroots_options_type), intent(in) :: options
    real(dp) :: start, top, n, dense, segments
    start = scan_start(options%policy)
    top = max(options%n_max, start)
    cost = log(top/start)/ln_1p(options%resolution) + 2.0_dp
    select case (options%policy%kind)
    case (step_kind%fixed)
      n = options%policy%value
      dense = min(top, 4.0_dp*n*options%resolution)
      if (options%first_only) then
        cost = cost + 4096.0_dp
      else
        if (dense > start) cost = cost + 4.0_dp*n*(1.0_dp/start - 1.0_dp/dense)
        if (min(top, n + 1.0_dp) > start) cost = cost + 4.0_dp*(n + 1.0_dp)*(1.0_dp/start - 1.0_dp/min(top, n + 1.0_dp))
      end if
    case (step_kind%rounded)
      segments = max(0.0_dp, min(options%policy%value*top, rounded_exact_steps) - options%policy%value*start)
      cost = cost + 3.0_dp*segments
    end select
  end function scan_cost

  !> Estimated evaluations of E for the whole procedure: every lambda's scan and
  !> the scans of the search for lambda* (about `lambda_star_scans`).
  pure real(dp) function procedure_cost(input) result(cost)
    type(stiffness_input_type), intent(in) :: input
    cost = 0.0_dp
    if (.not. allocated(input%lambdas)) return
    ! one lambda needs no search for lambda*
    cost = scan_cost(input%options)*real(size(input%lambdas) + &
      merge(lambda_star_scans, 0, size(input%lambdas) > 1), dp)
  end function procedure_cost

  !> Measure on the spot the time of one evaluation of E as the procedure makes
  !> them: E at the input's lambdas and step policy, N spread geometrically over
  !> the scanned range; rounds of 1024 evaluations until 1 ms has passed, three
  !> times, the median, in seconds per evaluation (a few ms in all). For up-front
  !> estimates of a long procedure.
  subroutine measure_evaluation_cost(input, seconds)
    type(stiffness_input_type), intent(in) :: input
    real(dp), intent(out) :: seconds
    integer, parameter :: batch = 1024
    real(dp), volatile :: sink
    real(dp) :: x(batch), lam(batch), times(3), start, top, e
    integer(i8) :: c0, c1, rate, count
    integer :: i, r, stat, n_lambda
    seconds = 0.0_dp
    start = scan_start(input%options%policy)
    top = max(min(input%options%n_max, n_max_limit(input%options%policy)), 2.0_dp*start)
    n_lambda = 0
    if (allocated(input%lambdas)) n_lambda = size(input%lambdas)
    do i = 1, batch
      x(i) = start*(top/start)**(real(i - 1, dp)/real(batch - 1, dp))
      lam(i) = 0.9_dp
      if (n_lambda > 0) lam(i) = input%lambdas(1 + mod(i - 1, n_lambda))
    end do
    sink = 0.0_dp
    do r = 1, 3
      count = 0
      call system_clock(c0, rate)
      do
        do i = 1, batch
          call harmonic_error_steps(x(i), lam(i), input%options%policy, e, stat)
          if (stat == demstep_stat%ok) sink = e
        end do
        count = count + batch
        call system_clock(c1)
        if (real(c1 - c0, dp) >= 1.0e-3_dp*real(rate, dp) .or. count >= 64*batch) exit
      end do
      times(r) = real(c1 - c0, dp)/real(rate, dp)/real(count, dp)
    end do
    seconds = times(1) + times(2) + times(3) - maxval(times) - minval(times)
  end subroutine measure_evaluation_cost

  !> The finest resolution whose grid keeps one lambda's scan within `limit` samples.
  pure real(dp) function finest_resolution(options, limit) result(r)
    type(nroots_options_type), intent(in) :: options
    real(dp), intent(in) :: limit
    real(dp) :: y
    y = log(max(options%n_max, 2.0_dp*scan_start(options%policy))/scan_start(options%policy)) &
      /max(limit - 8192.0_dp, 1.0_dp)
    ! exp(y) - 1, rounded up to two digits
    r = y*(1.0_dp + 0.5_dp*y + y*y/6.0_dp)
    r = round_up_2(r)
  end function finest_resolution

  !> log(1 + r) for 0 < r <= 1, accurate for small r too.
  pure real(dp) function ln_1p(r) result(y)
    real(dp), intent(in) :: r
    if (r < 1.0e-4_dp) then
      y = r*(1.0_dp - r*(0.5_dp - r/3.0_dp))
    else
      y = log(1.0_dp + r)
    end if
  end function ln_1p

  !> x > 0 rounded up to two significant digits (for messages).
  pure real(dp) function round_up_2(x) result(r)
    real(dp), intent(in) :: x
    real(dp) :: scale
    scale = 10.0_dp**(floor(log10(x)) - 1)
    r = ceiling(x/scale*(1.0_dp - 1.0e-12_dp))*scale
  end function round_up_2

  !> The limit of E(N, lambda, n) as N grows: 1 - 1/lambda^2 for a fixed n, and
  !> 1 - sin^2(pi f)/sin^2(pi f lambda) for n = f N.
  elemental function error_limit(lambda, policy) result(limit)
    real(dp), intent(in) :: lambda
    type(step_policy_type), intent(in) :: policy
    real(dp) :: limit
    if (policy%kind == step_kind%fixed) then
      limit = 1.0_dp - 1.0_dp/lambda**2
    else
      limit = 1.0_dp - (sin(pi*policy%value)/sin(pi*policy%value*lambda))**2
      if (.not. ieee_is_finite(limit)) limit = huge(1.0_dp)
    end if
  end function error_limit

  !> E(N) or |E(N)| - E0 for the root finder; a pole is not evaluable.
  pure subroutine e_function(x, context, fx, stat)
    real(dp), intent(in) :: x
    class(root_context_type), intent(inout) :: context
    real(dp), intent(out) :: fx
    integer, intent(out) :: stat
    fx = 0.0_dp
    stat = demstep_stat%invalid_input
    select type (context)
    class is (e_context_type)
      if (context%n > 0.0_dp) then
        call harmonic_error(x, context%lambda, context%n, fx, stat)
      else
        call harmonic_error_steps(x, context%lambda, context%policy, fx, stat)
      end if
      if (stat == demstep_stat%pole .and. context%absolute) then
        ! |E| is infinite at a pole: outside any tolerance
        fx = huge(1.0_dp)
        stat = demstep_stat%ok
      else if (context%absolute) then
        fx = abs(fx) - context%shift
      end if
    end select
  end subroutine e_function

  !> Validate the options of a scan for one lambda; messages name the option.
  pure subroutine check_options(lambda, options, status)
    real(dp), intent(in) :: lambda
    type(nroots_options_type), intent(in) :: options
    type(demstep_status_type), intent(out) :: status
    real(dp) :: top, cost, r
    status%stat = demstep_stat%ok
    if (.not. (ieee_is_finite(lambda) .and. lambda > 0.0_dp .and. lambda <= 1.0_dp)) then
      call set_status(status, demstep_stat%invalid_input, "must be in (0, 1], got "//real_text(lambda), where="lambda")
    else if (.not. (options%tolerance >= min_tolerance .and. options%tolerance < 1.0_dp)) then
      call set_status(status, demstep_stat%invalid_input, "must be in (0, 1) and at least 1e-10 (E is " &
        //"computed to 1e-12), got "//real_text(options%tolerance), where="tolerance")
    else if (options%pick /= pick_kind%largest_step .and. options%pick /= pick_kind%zero) then
      call set_status(status, demstep_stat%invalid_input, "unknown pick", where="pick")
    else if (.not. valid_policy(options%policy)) then
      call set_status(status, demstep_stat%invalid_input, "invalid step policy (n_steps in " &
        //"[1, 1e12], or steps_fraction > 0)", where="steps")
    else if (.not. (options%resolution > 0.0_dp .and. options%resolution <= 1.0_dp)) then
      call set_status(status, demstep_stat%invalid_input, "must be in (0, 1], got " &
        //real_text(options%resolution), where="resolution")
    end if
    if (status%stat /= demstep_stat%ok) return
    top = n_max_limit(options%policy)
    if (.not. (ieee_is_finite(options%n_max) .and. options%n_max > 2.0_dp*scan_start(options%policy) &
        .and. options%n_max <= top)) then
      call set_status(status, demstep_stat%invalid_input, "must be in ("// &
        real_text(2.0_dp*scan_start(options%policy))//", "//real_text(top)//"] for this step policy " &
        //"(n <= 1e12 steps), got "//real_text(options%n_max), where="n_max")
      return
    end if
    if (options%policy%kind == step_kind%fraction) then
      if (aint(options%policy%value*lambda) == options%policy%value*lambda) then
        call set_status(status, demstep_stat%invalid_input, "f lambda = "// &
          real_text(options%policy%value*lambda)//" is an integer: E has a pole at every N", where="steps_fraction")
        return
      end if
    end if
    cost = scan_cost(options)
    if (.not. cost <= max_scan_evaluations) then
      r = finest_resolution(options, max_scan_evaluations)
      if (options%policy%kind == step_kind%fixed .and. .not. options%first_only .and. r <= 1.0_dp .and. &
          options%resolution >= r) then
        call set_status(status, demstep_stat%invalid_input, "a scan for every root with n = " &
          //real_text(options%policy%value)//" needs "//count_text(cost)//" evaluations of E " &
          //"(at most "//real_text(max_scan_evaluations)//"); scan for the first root only, or " &
          //"use n_steps <= "//real_text(0.1_dp*max_scan_evaluations), where="n_steps")
      else
        call set_status(status, demstep_stat%invalid_input, "the scan up to n_max = "// &
          real_text(options%n_max)//" would need "//count_text(cost)//" evaluations of E per " &
          //"lambda (at most "//real_text(max_scan_evaluations)//"); use resolution >= "//real_text(r), &
          where="resolution")
      end if
    end if
  end subroutine check_options

  !> The largest n_max a step policy can be evaluated at: n = f N <= 1e12 steps
  !> (fraction, rounded); for a fixed n the double range of the closed form.
  pure real(dp) function n_max_limit(policy) result(top)
    type(step_policy_type), intent(in) :: policy
    top = fixed_n_max_limit
    if (policy%kind == step_kind%fraction .or. policy%kind == step_kind%rounded) then
      if (policy%value > 0.0_dp) top = min(top, harmonic_n_max/policy%value)
    end if
  end function n_max_limit

  !> An estimated count for a message: "about X", or "more than 1e308".
  pure function count_text(x) result(text)
    real(dp), intent(in) :: x
    character(len=:), allocatable :: text
    if (ieee_is_finite(x)) then
      text = "about "//real_text(x)
    else if (x > 0.0_dp) then
      text = "more than 1e308"
    else
      text = real_text(x)
    end if
  end function count_text

  pure logical function valid_policy(policy)
    type(step_policy_type), intent(in) :: policy
    select case (policy%kind)
    case (step_kind%fixed)
      valid_policy = policy%value >= 1.0_dp .and. policy%value <= harmonic_n_max
    case (step_kind%fraction, step_kind%rounded)
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
      call set_status(status, demstep_stat%not_found, "no lambda has a usable pick", where="lambda")
      return
    end if
    status%stat = demstep_stat%ok
    select case (rule)
    case (aggregate_kind%mean)
      n_star = sum(x)/n
    case (aggregate_kind%weighted)
      w = pack(weights, use)
      if (.not. (all(w >= 0.0_dp) .and. all(ieee_is_finite(w)) .and. any(w > 0.0_dp))) then
        call set_status(status, demstep_stat%invalid_input, "the weights of the usable " &
          //"lambdas must be finite, >= 0 and not all 0", where="weights")
        return
      end if
      ! scaled by the largest weight: no overflow for weights up to huge
      w = w/maxval(w)
      n_star = sum(w*x)/sum(w)
    case (aggregate_kind%median)
      call sort_ascending(x)
      if (mod(n, 2) == 1) then
        n_star = x((n + 1)/2)
      else
        n_star = 0.5_dp*(x(n/2) + x(n/2 + 1))
      end if
    case (aggregate_kind%min)
      n_star = minval(x)
    case (aggregate_kind%max)
      n_star = maxval(x)
    case default
      call set_status(status, demstep_stat%invalid_input, "unknown aggregation rule", where="aggregate")
    end select
  end subroutine aggregate_picks

  !> The whole procedure: picks for every lambda, N*, lambda*, T*, dt, K'.
  !> `progress` (optional) hears of every lambda's scan (`procedure_cost` gives
  !> the estimated evaluations of E up front).
  subroutine simulated_stiffness(input, result, status, progress)
    type(stiffness_input_type), intent(in) :: input
    type(stiffness_result_type), intent(out) :: result
    type(demstep_status_type), intent(out) :: status
    class(progress_type), intent(inout), optional :: progress
    type(pick_context_type) :: ctx
    real(dp), allocatable :: picks(:), weights(:)
    logical, allocatable :: use(:)
    real(dp) :: g1, g2, x
    integer :: i, n, k
    logical :: jump
    type(demstep_status_type) :: st
    type(spring_type) :: spring

    call check_input(input, status)
    if (status%stat /= demstep_stat%ok) return
    n = size(input%lambdas)
    allocate(result%rows(n))
    if (present(progress)) call progress%start("lambdas scanned", int(n, i8))
    do i = 1, n
      call n_roots(input%lambdas(i), input%options, result%rows(i), status)
      if (status%stat /= demstep_stat%ok) then
        if (present(progress)) call progress%finish()
        return
      end if
      result%evaluations = result%evaluations + result%rows(i)%evaluations
      if (present(progress)) call progress%update(int(i, i8))
    end do
    if (present(progress)) call progress%finish()
    picks = result%rows%n_pick
    use = result%rows%stat /= demstep_stat%not_found
    result%excluded = count(.not. use)
    if (allocated(input%weights)) then
      weights = input%weights
    else
      allocate(weights(n), source=1.0_dp)
    end if
    call aggregate_picks(picks, use, input%aggregate, weights, result%n_star, status)
    if (status%stat == demstep_stat%not_found) then
      if (input%options%pick == pick_kind%zero) then
        call set_status(status, demstep_stat%not_found, "no lambda has a root of E up to n_max = " &
          //real_text(input%options%n_max)//"; raise n_max or pick the largest step", where="n_max")
      else
        call set_status(status, demstep_stat%not_found, "no lambda has an admissible N up to " &
          //"n_max = "//real_text(input%options%n_max)//"; raise tolerance or n_max", where="tolerance")
      end if
    end if
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
        result%lambda_star_stat = demstep_stat%discontinuous
      end if
      exit
    end do
    result%evaluations = result%evaluations + ctx%e_evaluations
    ! T* as the spring's (scaled: M/K* may leave the double range where T* does not)
    call new_spring(spring, input%mass, input%stiffness, status)
    if (status%stat /= demstep_stat%ok) return
    result%period = spring_period(spring)
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
    real(dp) :: cost, r
    integer :: n, i
    type(spring_type) :: spring
    status%stat = demstep_stat%ok
    ! mass and stiffness: a spring's (their ratio in its range, so that T* is a double)
    call new_spring(spring, input%mass, input%stiffness, status)
    if (status%stat /= demstep_stat%ok) then
      return
    else if (.not. allocated(input%lambdas)) then
      call set_status(status, demstep_stat%invalid_input, "the lambda set is empty; give " &
        //"at least one lambda in (0, 1)", where="lambda")
    else if (size(input%lambdas) == 0) then
      call set_status(status, demstep_stat%invalid_input, "the lambda set is empty; give " &
        //"at least one lambda in (0, 1)", where="lambda")
    else if (any(.not. (input%lambdas > 0.0_dp .and. input%lambdas < 1.0_dp))) then
      i = findloc(input%lambdas > 0.0_dp .and. input%lambdas < 1.0_dp, .false., dim=1)
      call set_status(status, demstep_stat%invalid_input, "element "//int_text(i)//" is " &
        //real_text(input%lambdas(i))//"; must be in (0, 1)", where="lambda", index=int(i))
    end if
    if (status%stat /= demstep_stat%ok) return
    n = size(input%lambdas)
    do i = 2, n
      if (.not. input%lambdas(i) > input%lambdas(i-1)) then
        call set_status(status, demstep_stat%invalid_input, "the set must increase (element " &
          //int_text(i)//" is "//real_text(input%lambdas(i))//")", where="lambda")
        return
      end if
    end do
    if (input%aggregate == aggregate_kind%weighted) then
      if (.not. allocated(input%weights)) then
        call set_status(status, demstep_stat%invalid_input, "weighted aggregation needs weights", where="weights")
      else if (size(input%weights) /= n) then
        call set_status(status, demstep_stat%invalid_input, int_text(size(input%weights))// &
          " given for "//int_text(n)//" lambdas (one weight per lambda)", where="weights")
      else if (any(.not. (input%weights >= 0.0_dp .and. input%weights <= huge(1.0_dp)))) then
        i = findloc(input%weights >= 0.0_dp .and. input%weights <= huge(1.0_dp), .false., dim=1)
        call set_status(status, demstep_stat%invalid_input, "element "//int_text(i)//" is " &
          //real_text(input%weights(i))//"; must be finite and >= 0", where="weights", index=int(i))
      else if (.not. any(input%weights > 0.0_dp)) then
        call set_status(status, demstep_stat%invalid_input, "must not all be 0", where="weights")
      end if
    else if (input%aggregate < aggregate_kind%mean .or. input%aggregate > aggregate_kind%max) then
      call set_status(status, demstep_stat%invalid_input, "unknown aggregation rule", where="aggregate")
    end if
    if (status%stat /= demstep_stat%ok) return
    do i = 1, n
      call check_options(input%lambdas(i), input%options, status)
      if (status%stat /= demstep_stat%ok) return
    end do
    cost = procedure_cost(input)
    if (.not. cost <= max_procedure_evaluations) then
      r = finest_resolution(input%options, max_procedure_evaluations/real(n + lambda_star_scans, dp))
      call set_status(status, demstep_stat%invalid_input, "the procedure would need " &
        //count_text(cost)//" evaluations of E (at most "//real_text(max_procedure_evaluations)// &
        "); use resolution >= "//real_text(r)//" or fewer lambdas", where="resolution")
    end if
  end subroutine check_input

  !> The `pick_kind` code of a word (case ignored); 0 for another word.
  pure integer function pick_kind_from_name(name) result(code)
    !> The word, one of `pick_kind_names`.
    character(len=*), intent(in) :: name
    code = word_index(pick_kind_names, name)
  end function pick_kind_from_name

  !> The word of a `pick_kind` code (`?` for another value).
  pure function pick_kind_name(code) result(name)
    !> A code of `pick_kind`.
    integer, intent(in) :: code
    character(len=:), allocatable :: name
    name = word_of(pick_kind_names, code)
  end function pick_kind_name

  !> The `aggregate_kind` code of a word (case ignored); 0 for another word.
  pure integer function aggregate_kind_from_name(name) result(code)
    !> The word, one of `aggregate_kind_names`.
    character(len=*), intent(in) :: name
    code = word_index(aggregate_kind_names, name)
  end function aggregate_kind_from_name

  !> The word of a `aggregate_kind` code (`?` for another value).
  pure function aggregate_kind_name(code) result(name)
    !> A code of `aggregate_kind`.
    integer, intent(in) :: code
    character(len=:), allocatable :: name
    name = word_of(aggregate_kind_names, code)
  end function aggregate_kind_name

  !> The `interval_kind` code of a word (case ignored); `-huge(0)` for another word.
  pure integer function interval_kind_from_name(name) result(code)
    !> The word, one of `interval_kind_names`.
    character(len=*), intent(in) :: name
    code = word_index(interval_kind_names, name)
    if (code == 0) then
      code = -huge(code)
    else
      code = code + (-1)
    end if
  end function interval_kind_from_name

  !> The word of a `interval_kind` code (`?` for another value).
  pure function interval_kind_name(code) result(name)
    !> A code of `interval_kind`.
    integer, intent(in) :: code
    character(len=:), allocatable :: name
    name = word_of(interval_kind_names, code - (-1))
  end function interval_kind_name

end module demstep_stiffness
