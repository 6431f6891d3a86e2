!> Mass (density) scaling for a target step, verified by the exact damped
!> limit: per-particle factors s_i >= 1 on the masses and inertia of a
!> monitor's last update (`demstep_monitor`), its springs and dashpots held
!> as they were.
!>
!> The damped limit (lagged dashpots) is the smallest h with
!> lambda_max(h^2 A + 2 h B) = 4 (`demstep_assembly`), and lambda increases
!> with h, so the scaled system reaches a target h exactly when
!> 4 S M - (h^2 K + 2 h C) is positive semi-definite: a linear matrix
!> inequality in the factors s. Minimising the added mass sum m_i (s_i - 1)
!> subject to it is a convex (semidefinite) program, approached by cutting
!> planes. Any vector u gives a necessary condition, linear in s:
!> 4 sum_i s_i u_i' M_i u_i >= u' (h^2 K + 2 h C) u (u_i the particle's
!> components, M_i its mass and inertia block). At the current factors the
!> cuts come from
!> - the whole system's modes of an exact solve (the damped Newton steps'
!>   last mode and the top undamped one), and
!> - small regions, the rest held (a dense eigenproblem each): the particles
!>   within one spring of a centre, and within two around a centre whose
!>   one-spring region reaches `ring_fraction` of 4; a region whose top at
!>   the target is above 4 makes a cut when it peaks at its centre (else the
!>   peak's own two-spring region is looked at); a region is skipped while
!>   the upper bound of its top (its last top times its factors' largest
!>   decrease since) stays below the threshold.
!> The covering linear program min sum m_i t_i over every cut so far
!> (t = s - 1 >= 0, `covering_lp`) gives the next factors; regions and
!> program alternate without an exact solve until the program's value
!> settles (`inner_change`), then an exact solve adds the whole system's
!> cuts. The program's value only grows, and its dual bound is a lower
!> bound of the added mass of ANY factors >= 1 that reach the target
!> (`least`). Every "reached" is an exact solve warm-started from the last
!> modes, confirmed from a random start (a warm start may settle on a lower
!> top when the top moved elsewhere). When the program's factors reach the
!> target they are the answer. Else, once their limit is within
!> `repair_gap` of the target or stops moving (`outer_change`), they are
!> repaired: the added masses times one common factor c (s = 1 + c t, up to
!> `common_factor_cap`), the least c that reaches the target; when even the
!> cap does not (a mode on particles the cuts left alone), every particle
!> gets max(1 + t_i, g (target/h_i)^2) (h_i its own limit with its partners
!> held, from its diagonal blocks), the least g. Both bisected on the exact
!> limit: each added mass lowers every eigenvalue of the scaled problem, so
!> the limit does not decrease along either family. Last, the pure diagonal
!> floor max(1, g (target/h_i)^2) (a per-body rule, as Yade's) is a second
!> candidate: g bisected on the exact limit below the g at which it would add
!> as much as the first candidate (one solve when it does not reach there),
!> with up to `diagonal_solves` solves of its own; the lighter verified
!> candidate is the answer, so it never adds more than that diagonal rule.
module demstep_mass_scaling
  use demstep_kinds, only: dp, i8
  use demstep_status, only: demstep_status_type, demstep_stat, set_status
  use demstep_text, only: int_text
  use demstep_assembly, only: critical_step_type, assembly_operator_type, operator_from_springs, &
    operator_critical_steps, default_max_eigen_dof, scene_lanczos_ncv, operator_mix, assembly_operator_apply, &
    assembly_matrix_rows, damped_lower_bound
  use demstep_lapack, only: largest_eigenpair
  use demstep_monitor, only: step_monitor_type, cheap_bound, sphere_inertia, region_of, region_top
  use demstep_covering_lp, only: covering_lp
  use, intrinsic :: ieee_arithmetic, only: ieee_is_finite
  implicit none
  private

  public :: scale_masses

  !> Default most exact (damped) solves of `scale_masses`.
  integer, parameter, public :: scale_masses_solves_default = 40
  !> The cutting-plane rounds stop when the exact limit of the linear
  !> program's factors is within this relative gap below the target; the
  !> repair closes it.
  real(dp), parameter, public :: repair_gap = 5.0e-3_dp
  !> A repair's bisection stops when its bracket is within this fraction of
  !> its parameter.
  real(dp), parameter :: repair_resolution = 2.0e-3_dp
  !> Rounds of neighbourhood cuts and linear program between exact solves.
  integer, parameter :: inner_rounds = 6
  !> The rounds between exact solves stop when the program's value grew by
  !> less than this fraction.
  real(dp), parameter :: inner_change = 5.0e-3_dp
  !> A neighbourhood whose top at the target is above 4 (1 + this) makes a cut.
  real(dp), parameter :: local_tolerance = 1.0e-4_dp
  !> The widest region (springs from its centre) whose top makes a cut, and
  !> the fraction of 4 a narrower one's top must reach for the next wider.
  integer, parameter :: ring_depth = 2
  real(dp), parameter :: ring_fraction = 0.7_dp
  !> The rounds stop when an exact solve's limit grew by less than this
  !> fraction since the last.
  real(dp), parameter :: outer_change = 1.0e-3_dp
  !> The largest common factor on the linear program's added masses tried
  !> before the diagonal floor joins.
  real(dp), parameter :: common_factor_cap = 4.0_dp
  !> Exact solves kept for the repair (at most half of them).
  integer, parameter :: repair_solves = 16
  !> Exact solves of the diagonal-floor candidate beyond `max_passes`.
  integer, parameter, public :: diagonal_solves = 16

contains

  !> Mass (density) scaling for a target step (see the module notes):
  !> factors scale(i) >= 1 (mass and inertia both scaled, as a density would
  !> be) with which the exact damped limit of the monitor's last update (its
  !> springs and dashpots as they were) reaches `target`, with as little
  !> added mass as the cutting planes find, verified by that exact limit.
  !> `result` is the scaled system's report (its dt_critical_damped >=
  !> target), `added` the added mass over the total, `passes` the exact solves
  !> made, `least` the lower bound of the added mass fraction of any factors
  !> >= 1 reaching the target (the linear programs' dual bound; 0 when the
  !> limit already reaches it). The answer is the lighter of the cutting
  !> planes' (repaired) factors and the diagonal floor's. Status
  !> invalid_input naming `monitor` (no update with an eigensolve), `mass`
  !> (not the update's particles) or
  !> `target` (not finite and > 0) or `max_passes` (below 2: a warm solve
  !> and its confirmation); not_converged when neither candidate
  !> reached the target (`max_passes` exact solves, default
  !> `scale_masses_solves_default`, then `diagonal_solves` more).
  subroutine scale_masses(monitor, target, mass, radius, scale, added, result, status, inertia, fixed, &
      max_passes, passes, least)
    class(step_monitor_type), intent(inout) :: monitor
    real(dp), intent(in) :: target
    !> The arrays of the last update.
    real(dp), intent(in) :: mass(:), radius(:)
    real(dp), allocatable, intent(out) :: scale(:)
    real(dp), intent(out) :: added
    type(critical_step_type), intent(out) :: result
    type(demstep_status_type), intent(out) :: status
    real(dp), intent(in), optional :: inertia(:)
    logical, intent(in), optional :: fixed(:)
    !> Most exact solves of the cutting planes and their repair, >= 2
    !> (default `scale_masses_solves_default`).
    integer, intent(in), optional :: max_passes
    integer, intent(out), optional :: passes
    real(dp), intent(out), optional :: least
    type(assembly_operator_type) :: op
    type(critical_step_type) :: best_result
    real(dp), allocatable :: vec(:), dvec(:), base_inertia(:), cost(:), t(:), y(:), best(:), &
      cut_val(:), cut_r(:)
    integer, allocatable :: cut_start(:), cut_col(:), identity(:), place(:)
    real(dp), allocatable :: top_bound(:, :), seen(:)
    real(dp), allocatable :: t_lp(:), q(:)
    real(dp) :: h, rate_of_op, total, bound, lp_lower, lp_value, h_last, c_cap
    integer :: max_solves, budget, solves, nb, b, m_cuts, n_entries, inner, new_cuts
    logical :: feasible, found, found_diagonal
    integer, parameter :: common_factor = 1, diagonal_floor = 2, pure_diagonal = 3
    added = 0.0_dp
    solves = 0
    if (present(passes)) passes = 0
    if (present(least)) least = 0.0_dp
    if (.not. (monitor%ready .and. monitor%last%eigen_computed)) then
      call set_status(status, demstep_stat%invalid_input, "needs an update with an eigensolver", &
        where="monitor")
      return
    end if
    if (size(mass) /= monitor%n_particles .or. size(radius) /= size(mass)) then
      call set_status(status, demstep_stat%invalid_input, "must be the last update's particles", where="mass")
      return
    end if
    if (.not. (ieee_is_finite(target) .and. target > 0.0_dp)) then
      call set_status(status, demstep_stat%invalid_input, "must be finite and > 0", where="target")
      return
    end if
    max_solves = scale_masses_solves_default
    if (present(max_passes)) then
      ! (at least a warm solve and its confirmation, else a target the
      ! limit already reaches is never confirmed; the diagonal candidate's
      ! budget, max_passes + diagonal_solves, must not overflow)
      if (max_passes < 2 .or. max_passes > huge(1) - diagonal_solves) then
        call set_status(status, demstep_stat%invalid_input, "must be in 2.." &
          //int_text(huge(1) - diagonal_solves)//", not "//int_text(max_passes), where="max_passes")
        return
      end if
      max_solves = max_passes
    end if
    budget = max_solves
    if (present(inertia)) then
      base_inertia = inertia
    else
      base_inertia = sphere_inertia(mass, radius)
    end if
    allocate(scale(size(mass)), source=1.0_dp)
    vec = monitor%mode
    dvec = monitor%damped_mode
    nb = monitor%op%n_bodies
    total = sum(mass)
    cost = mass(monitor%body_particle)
    identity = [(b, b = 1, nb)]
    bound = 0.0_dp
    h_last = 0.0_dp
    m_cuts = 0
    n_entries = 0
    allocate(cut_start(1), source=1)
    allocate(cut_col(0), cut_val(0), cut_r(0))
    ! cutting-plane rounds: each one exact solve at the current factors
    feasible = .false.
    do
      ! (the last solves are kept for the repair)
      if (solves >= max_solves - min(repair_solves, max_solves/2) .and. solves > 0) exit
      feasible = reaches(scale, h)
      if (status%stat /= demstep_stat%ok) return
      if (feasible) exit
      if (m_cuts > 0 .and. h >= (1.0_dp - repair_gap)*target) exit
      ! (the exact limit hardly moved since the last round: the repair)
      if (m_cuts > 0 .and. h <= (1.0_dp + outer_change)*h_last) exit
      h_last = h
      ! the whole system's modes at the target, then the regions' cuts and
      ! the linear program in turn (no exact solve) until no region makes a
      ! new cut or the program's value settles
      call mix_at_target()
      if (any(dvec /= 0.0_dp)) call whole_cut(dvec)
      if (any(vec /= 0.0_dp)) call whole_cut(vec)
      do inner = 1, inner_rounds
        call local_cuts(new_cuts)
        if (status%stat /= demstep_stat%ok) return
        if (inner > 1 .and. new_cuts == 0) exit
        call covering_lp(cut_start(:m_cuts + 1), cut_col(:n_entries), cut_val(:n_entries), cut_r(:m_cuts), cost, t, y, &
          status, lower=lp_lower)
        if (status%stat /= demstep_stat%ok) return
        bound = max(bound, lp_lower/total)
        ! (the value's last relative change small: the neighbourhoods are met)
        if (inner > 1) then
          if (dot_product(cost, t) <= (1.0_dp + inner_change)*lp_value) new_cuts = 0
        end if
        lp_value = dot_product(cost, t)
        scale(monitor%body_particle) = 1.0_dp + t
        if (inner > 1 .and. new_cuts == 0) exit
        call operator_from_springs(monitor%dim, monitor%last%rotation, mass*scale, base_inertia*scale, &
          radius, monitor%springs(:monitor%n_springs), .false., op, rate_of_op, status, fixed, &
          order=monitor%order)
        if (status%stat /= demstep_stat%ok) return
        call mix_at_target()
      end do
    end do
    if (present(least)) least = bound
    ! the repair: the common factor on the added masses (doubled until the
    ! exact limit reaches the target, then bisected); when the limit stays
    ! below it (a mode on particles the cuts left alone), every particle
    ! also gets the diagonal floor g (target/h_i)^2, h_i its own limit with
    ! its partners held, g the least that reaches the target
    found = feasible
    if (feasible) then
      best = scale
      best_result = result
    else if (allocated(t)) then
      t_lp = t
      call repair(common_factor, found)
      if (status%stat /= demstep_stat%ok) return
      if (.not. found) then
        call floor_weights()
        if (status%stat /= demstep_stat%ok) return
        call repair(diagonal_floor, found)
        if (status%stat /= demstep_stat%ok) return
      end if
    end if
    ! the second candidate, the pure diagonal floor, tried only below the g
    ! at which it adds as much as the first (c_cap); none when the first
    ! adds nothing
    found_diagonal = .not. found
    if (found) found_diagonal = any(best > 1.0_dp)
    if (found_diagonal) then
      budget = max_solves + diagonal_solves
      call floor_weights()
      if (status%stat /= demstep_stat%ok) return
      if (found) then
        c_cap = floor_matching(dot_product(cost, best(monitor%body_particle) - 1.0_dp))
        call repair(pure_diagonal, found_diagonal, c_cap)
      else
        call repair(pure_diagonal, found_diagonal)
      end if
      if (status%stat /= demstep_stat%ok) return
      found = found .or. found_diagonal
    end if
    if (found) then
      scale = best
      result = best_result
      call finish()
      return
    end if
    added = sum((scale - 1.0_dp)*mass)/total
    if (present(passes)) passes = solves
    call set_status(status, demstep_stat%not_converged, "the scaled limit stayed below the target after " &
      //"max_passes exact solves", where="max_passes")
  contains
    !> The exact damped limit h of the scaled system (result set), warm-started.
    subroutine exact_limit(factor, h, cold)
      real(dp), intent(in) :: factor(:)
      real(dp), intent(out) :: h
      !> From a random start with its confirmation run (not the last modes).
      logical, intent(in), optional :: cold
      real(dp), allocatable :: start(:), damped_start(:)
      logical :: fresh
      h = 0.0_dp
      fresh = .false.
      if (present(cold)) fresh = cold
      call operator_from_springs(monitor%dim, monitor%last%rotation, mass*factor, base_inertia*factor, &
        radius, monitor%springs(:monitor%n_springs), .false., op, rate_of_op, status, fixed, &
        order=monitor%order)
      if (status%stat /= demstep_stat%ok) return
      result = critical_step_type()
      result%rotation = monitor%last%rotation
      result%periodic = monitor%last%periodic
      ! (each solve moves the mode: the scene solve's Krylov size)
      if (fresh) then
        allocate(start(op%n), damped_start(op%n), source=0.0_dp)
        call operator_critical_steps(op, monitor%springs(:monitor%n_springs), rate_of_op, .false., monitor%solver, &
          default_max_eigen_dof, monitor%tolerance, start, result, status, &
          bounds=[cheap_bound(op), cheap_bound(op, dashpots=.true.)], ncv=scene_lanczos_ncv, &
          damped_vec=damped_start)
      else
        call operator_critical_steps(op, monitor%springs(:monitor%n_springs), rate_of_op, .false., monitor%solver, &
          default_max_eigen_dof, monitor%tolerance, vec, result, status, &
          bounds=[cheap_bound(op), cheap_bound(op, dashpots=.true.)], ncv=scene_lanczos_ncv, damped_vec=dvec)
      end if
      solves = solves + 1
      h = result%dt_critical_damped
    end subroutine exact_limit
    !> Whether the factors reach the target: a warm-started exact solve (h),
    !> confirmed from a random start when it says so (a warm start may settle
    !> on a lower top when the top mode moved elsewhere).
    logical function reaches(factor, h)
      real(dp), intent(in) :: factor(:)
      real(dp), intent(out) :: h
      reaches = .false.
      call exact_limit(factor, h)
      if (status%stat /= demstep_stat%ok .or. h < target) return
      if (solves >= budget) return
      call exact_limit(factor, h, cold=.true.)
      if (status%stat /= demstep_stat%ok) return
      reaches = h >= target
    end function reaches
    !> The operator (built at the current factors) mixed as h^2 A' + 2 h B' at the target.
    subroutine mix_at_target()
      real(dp) :: tau
      tau = target*rate_of_op
      call operator_mix(op, tau**2, 2.0_dp*tau)
    end subroutine mix_at_target
    !> The cuts of the neighbourhoods (op built at the current factors and
    !> mixed at the target) whose top is above 4 (1 + local_tolerance) and
    !> peaks at their centre (the neighbourhoods around one local mode all
    !> see it: the one at its peak makes the cut); `added` of them.
    subroutine local_cuts(added)
      integer, intent(out) :: added
      real(dp), allocatable :: v(:)
      integer, allocatable :: bodies(:)
      real(dp) :: lam, ratio
      integer :: nc, depth, peak, n_forced, k
      integer, allocatable :: forced(:)
      nc = op%nc
      added = 0
      n_forced = 0
      allocate(forced(nb))
      if (.not. allocated(place)) then
        allocate(place(nb), source=0)
        allocate(top_bound(ring_depth, nb), source=huge(1.0_dp))
        seen = scale(monitor%body_particle)
      end if
      do b = 1, nb
        do depth = 1, ring_depth
          ! (an upper bound of the region's top since it was last computed:
          ! its factors' largest decrease; a region well below 4 is skipped)
          call region_of(op, b, depth, place, bodies)
          ratio = maxval(seen(bodies)/scale(monitor%body_particle(bodies)))
          place(bodies) = 0
          if (top_bound(depth, b) < huge(1.0_dp)) top_bound(depth, b) = top_bound(depth, b)*ratio
          if (top_bound(depth, b) < 4.0_dp*merge(ring_fraction, 1.0_dp + local_tolerance, depth < ring_depth)) &
            exit
          call region_top(op, b, depth, identity, place, bodies, lam, v, status)
          if (status%stat /= demstep_stat%ok) return
          top_bound(depth, b) = lam
          if (lam > 4.0_dp*(1.0_dp + local_tolerance)) then
            peak = peak_body(v, nc)
            if (peak == 1) then
              call append_cut(bodies, v, lam)
              added = added + 1
            else if (depth == ring_depth) then
              ! (the peak's own widest region makes the cut, below)
              if (.not. any(forced(:n_forced) == bodies(peak))) then
                n_forced = n_forced + 1
                forced(n_forced) = bodies(peak)
              end if
            end if
          end if
          ! (a wider region only around a neighbourhood near the target)
          if (lam < 4.0_dp*ring_fraction) exit
        end do
      end do
      ! the widest regions around the peaks other regions saw, not yet made
      do k = 1, n_forced
        call region_top(op, forced(k), ring_depth, identity, place, bodies, lam, v, status)
        if (status%stat /= demstep_stat%ok) return
        top_bound(ring_depth, forced(k)) = lam
        if (.not. lam > 4.0_dp*(1.0_dp + local_tolerance) .or. peak_body(v, nc) /= 1) cycle
        call append_cut(bodies, v, lam)
        added = added + 1
      end do
      seen = scale(monitor%body_particle)
    end subroutine local_cuts
    !> The body (position in the region, centre first) with the largest
    !> squared amplitude of a region's vector (nc per body); the centre when
    !> it holds at least half of that largest.
    integer function peak_body(v, nc)
      real(dp), intent(in) :: v(:)
      integer, intent(in) :: nc
      real(dp), allocatable :: amp(:)
      integer :: k
      amp = [(sum(v((k - 1)*nc + 1:k*nc)**2), k = 1, size(v)/nc)]
      peak_body = maxloc(amp, 1)
      if (amp(1) >= 0.5_dp*amp(peak_body)) peak_body = 1
    end function peak_body
    !> The cut of a mode of the whole system (scaled coordinates), when its
    !> quotient at the target is above 4.
    subroutine whole_cut(mode)
      real(dp), intent(in) :: mode(:)
      real(dp), allocatable :: u(:), au(:)
      real(dp) :: theta
      u = mode/norm2(mode)
      allocate(au(size(u)))
      call assembly_operator_apply(op, u, au)
      theta = dot_product(u, au)
      if (theta > 4.0_dp) call append_cut(identity, u, theta)
    end subroutine whole_cut
    !> The cut 4 sum_k s_k' p_k/s_k >= theta of a unit vector v over
    !> `bodies` (nc components each, scaled coordinates at the current
    !> factors s; p_k its squared amplitude on body k) with quotient theta at
    !> the target: as a row over t' = s' - 1, coefficients 4 p_k/s_k and
    !> right-hand side theta - 4 sum_k p_k/s_k.
    subroutine append_cut(bodies, v, theta)
      integer, intent(in) :: bodies(:)
      real(dp), intent(in) :: v(:), theta
      real(dp) :: p, s, rhs
      integer :: k, nc
      nc = op%nc
      call grow(size(bodies))
      rhs = theta
      do k = 1, size(bodies)
        p = sum(v((k - 1)*nc + 1:k*nc)**2)
        if (.not. p > 0.0_dp) cycle
        s = scale(monitor%body_particle(bodies(k)))
        n_entries = n_entries + 1
        cut_col(n_entries) = bodies(k)
        cut_val(n_entries) = 4.0_dp*p/s
        rhs = rhs - 4.0_dp*p/s
      end do
      m_cuts = m_cuts + 1
      cut_r(m_cuts) = rhs
      cut_start(m_cuts + 1) = n_entries + 1
    end subroutine append_cut
    !> Room for one more cut of up to `entries` entries (storage doubled).
    subroutine grow(entries)
      integer, intent(in) :: entries
      integer, allocatable :: ic(:)
      real(dp), allocatable :: rv(:)
      if (n_entries + entries > size(cut_col)) then
        allocate(ic(2*(n_entries + entries)), rv(2*(n_entries + entries)))
        ic(:n_entries) = cut_col(:n_entries)
        rv(:n_entries) = cut_val(:n_entries)
        call move_alloc(ic, cut_col)
        call move_alloc(rv, cut_val)
      end if
      if (m_cuts + 1 > size(cut_r)) then
        allocate(rv(2*(m_cuts + 1)))
        rv(:m_cuts) = cut_r(:m_cuts)
        call move_alloc(rv, cut_r)
        allocate(ic(2*(m_cuts + 1) + 1))
        ic(:m_cuts + 1) = cut_start(:m_cuts + 1)
        call move_alloc(ic, cut_start)
      end if
    end subroutine grow
    !> The least parameter of a family of factors (`common_factor`: s = 1 +
    !> c t; `diagonal_floor`: s = max(1 + t, c q); `pure_diagonal`: s =
    !> max(1, c q)) whose exact limit reaches the target: doubled (from `cap`
    !> when given: then not above it), then bisected to `repair_resolution`
    !> (best, best_result; found false when the solves, the common factor's
    !> cap or `cap` ran out first).
    subroutine repair(family, found, cap)
      integer, intent(in) :: family
      logical, intent(out) :: found
      real(dp), intent(in), optional :: cap
      real(dp) :: lo, hi, c
      found = .false.
      if (family == common_factor) then
        lo = 1.0_dp
        hi = 1.0_dp + 4.0_dp*((target/h)**2 - 1.0_dp)
      else
        lo = 0.0_dp
        hi = 1.0_dp
        if (present(cap)) hi = cap
      end if
      do
        if (solves >= budget) exit
        c = hi
        if (found) c = 0.5_dp*(lo + hi)
        call set_family(family, c)
        if (reaches(scale, h)) then
          hi = c
          best = scale
          best_result = result
          found = .true.
        else
          if (status%stat /= demstep_stat%ok) return
          lo = c
        end if
        if (found) then
          if (hi - lo <= repair_resolution*hi) exit
        else
          if (present(cap)) exit
          if (family == common_factor) then
            if (hi >= common_factor_cap) exit
            hi = min(common_factor_cap, 1.0_dp + 2.0_dp*(hi - 1.0_dp))
          else
            hi = 2.0_dp*hi
          end if
        end if
      end do
    end subroutine repair
    !> The factors of a repair family at parameter c.
    subroutine set_family(family, c)
      integer, intent(in) :: family
      real(dp), intent(in) :: c
      scale = 1.0_dp
      select case (family)
      case (common_factor)
        scale(monitor%body_particle) = 1.0_dp + c*t_lp
      case (diagonal_floor)
        scale(monitor%body_particle) = max(1.0_dp + t_lp, c*q)
      case default
        scale(monitor%body_particle) = max(1.0_dp, c*q)
      end select
    end subroutine set_family
    !> The diagonal floor's weights q = (target/h_i)^2 (once).
    subroutine floor_weights()
      if (allocated(q)) return
      call local_limits(q)
      if (status%stat /= demstep_stat%ok) return
      q = (target/q)**2
    end subroutine floor_weights
    !> The largest g (to rounding) at which the pure diagonal floor adds at
    !> most the mass `mass_added` (its added mass grows with g).
    real(dp) function floor_matching(mass_added) result(g)
      real(dp), intent(in) :: mass_added
      real(dp) :: g_hi
      integer :: k
      g = 0.0_dp
      g_hi = 1.0_dp
      do while (dot_product(cost, max(1.0_dp, g_hi*q) - 1.0_dp) <= mass_added)
        g = g_hi
        g_hi = 2.0_dp*g_hi
      end do
      do k = 1, 60
        if (dot_product(cost, max(1.0_dp, 0.5_dp*(g + g_hi)*q) - 1.0_dp) <= mass_added) then
          g = 0.5_dp*(g + g_hi)
        else
          g_hi = 0.5_dp*(g + g_hi)
        end if
      end do
    end function floor_matching
    !> Each free body's own damped limit (its partners held), unscaled: the
    !> lower bound `damped_lower_bound` from the largest eigenvalues of its
    !> diagonal blocks of A' and B'.
    subroutine local_limits(h_local)
      real(dp), allocatable, intent(out) :: h_local(:)
      real(dp), allocatable :: a_max(:), b_max(:)
      call block_maxima(monitor%op, a_max, status)
      if (status%stat /= demstep_stat%ok) return
      allocate(b_max(size(a_max)), source=0.0_dp)
      if (size(monitor%op%dcoef, 2) > 0) then
        call operator_mix(monitor%op, 0.0_dp, 1.0_dp)
        call block_maxima(monitor%op, b_max, status)
        call operator_mix(monitor%op, 1.0_dp, 0.0_dp)
        if (status%stat /= demstep_stat%ok) return
      end if
      h_local = damped_lower_bound(2.0_dp/sqrt(max(a_max, tiny(1.0_dp))), b_max)/monitor%rate
    end subroutine local_limits
    subroutine finish()
      added = sum((scale - 1.0_dp)*mass)/total
      if (present(passes)) passes = solves
      status%stat = demstep_stat%ok
    end subroutine finish
  end subroutine scale_masses

  !> The largest eigenvalue of each free body's diagonal block of the
  !> operator as it is mixed (its rows' first nc x nc entries,
  !> `assembly_matrix_rows`): the body's own frequency with its partners held.
  subroutine block_maxima(op, lam, status)
    type(assembly_operator_type), intent(in) :: op
    real(dp), allocatable, intent(out) :: lam(:)
    type(demstep_status_type), intent(out) :: status
    integer(i8), allocatable :: row_start(:)
    integer, allocatable :: col(:)
    real(dp), allocatable :: val(:), block(:, :), v(:)
    integer, allocatable :: identity(:)
    integer :: b, r, nc
    nc = op%nc
    allocate(lam(op%n_bodies), source=0.0_dp)
    allocate(block(nc, nc), v(nc))
    ! (the identity map made once: O(springs) in all, not O(bodies^2))
    identity = [(r, r = 1, op%n_bodies)]
    status%stat = demstep_stat%ok
    do b = 1, op%n_bodies
      call assembly_matrix_rows(op, [b], identity, row_start, col, val, status)
      if (status%stat /= demstep_stat%ok) return
      do r = 1, nc
        block(r, :) = val(row_start(r):row_start(r) + nc - 1)
      end do
      call largest_eigenpair(block, lam(b), v, status)
      if (status%stat /= demstep_stat%ok) return
    end do
  end subroutine block_maxima

end module demstep_mass_scaling
