!> Mass (density) scaling for a target step, verified by the exact damped
!> limit: per-particle factors >= 1 on the masses and inertia of a monitor's
!> last update (`demstep_monitor`), its springs and dashpots held as they were.
module demstep_mass_scaling
  use demstep_kinds, only: dp, i8
  use demstep_status, only: demstep_status_type, demstep_stat, set_status
  use demstep_assembly, only: critical_step_type, assembly_operator_type, operator_from_springs, &
    operator_critical_steps, default_max_eigen_dof, damped_lower_bound, scene_lanczos_ncv, operator_mix, &
    assembly_matrix_rows
  use demstep_lapack, only: largest_eigenpair
  use demstep_monitor, only: step_monitor_type, cheap_bound, sphere_inertia
  use, intrinsic :: ieee_arithmetic, only: ieee_is_finite
  implicit none
  private

  public :: scale_masses

contains

  !> Mass (density) scaling for a target step: per-particle factors
  !> scale(i) >= 1 (mass and inertia both scaled, as a density would be)
  !> with which the exact damped limit of the monitor's last update (its
  !> springs and dashpots as they were) reaches `target`, verified by that
  !> exact limit. Two stages, each pass one exact (warm-started) solve:
  !> - the mode that sets the limit (the damped Newton steps' last mode, or
  !>   the top undamped one without dashpots): up to `mode_passes` passes scale
  !>   every free particle by g^min(1, p_i/p_c), g = (target/h)^2 (h the
  !>   current limit, p_i the particle's share of the mode, p_c the smallest
  !>   share of its core: the largest shares holding half of it). One
  !>   defect (a light or stiff particle) is fixed in a pass or two;
  !> - a crowded top (many near-equal localised modes) is not: then each free
  !>   particle gets max(its factor so far, c (target/h_i)^2), h_i its own
  !>   block's limit (the particle alone, its partners held: the lower bound
  !>   `damped_lower_bound` from the largest eigenvalues of its diagonal
  !>   blocks of A' and B'), and the one coefficient c is the smallest that
  !>   makes the exact limit reach the target (doubled from 1 until it does,
  !>   then bisected to 0.5 %).
  !> Increasing any mass lowers every eigenvalue, so the exact limit does not
  !> decrease as c grows. `result` is the scaled system's report (its
  !> dt_critical_damped >= target), `added` the added mass over the total,
  !> `passes` the exact solves made. Status invalid_input naming `monitor`
  !> (no update with an eigensolve), `mass` (not the update's particles) or
  !> `target` (not finite and > 0); not_converged after `max_passes` solves
  !> (default 40).
  subroutine scale_masses(monitor, target, mass, radius, scale, added, result, status, inertia, fixed, &
      max_passes, passes)
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
    integer, intent(in), optional :: max_passes
    integer, intent(out), optional :: passes
    !> Passes of the first stage.
    integer, parameter :: mode_passes = 3
    type(assembly_operator_type) :: op
    real(dp), allocatable :: vec(:), dvec(:), base_inertia(:), share(:), base(:), local(:), best(:)
    type(critical_step_type) :: best_result
    real(dp) :: h, g, core, c_lo, c_hi, c, rate_of_op
    integer :: pass, max_solves, b, nc, solves
    added = 0.0_dp
    solves = 0
    if (present(passes)) passes = 0
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
    max_solves = 40
    if (present(max_passes)) max_solves = max_passes
    if (present(inertia)) then
      base_inertia = inertia
    else
      base_inertia = sphere_inertia(mass, radius)
    end if
    allocate(scale(size(mass)), source=1.0_dp)
    vec = monitor%mode
    dvec = monitor%damped_mode
    nc = monitor%op%nc
    ! stage 1: the limiting mode's particles
    do pass = 1, min(mode_passes, max_solves)
      call exact_limit(scale, h)
      if (status%stat /= demstep_stat%ok) return
      if (h >= target) then
        call finish()
        return
      end if
      ! each free body's share of the mode that sets the limit (the damped
      ! Newton steps' last mode when there are dashpots: the damped limit's
      ! mode need not be the undamped top one), and its growth
      if (result%damped_exact .and. any(dvec /= 0.0_dp)) then
        share = [(sum(dvec((b - 1)*nc + 1:b*nc)**2), b = 1, op%n_bodies)]
      else
        share = [(sum(vec((b - 1)*nc + 1:b*nc)**2), b = 1, op%n_bodies)]
      end if
      g = (target/h)**2
      core = core_share(share)
      do b = 1, op%n_bodies
        scale(monitor%body_particle(b)) = scale(monitor%body_particle(b))*g**min(1.0_dp, share(b)/core)
      end do
    end do
    ! stage 2: every particle by its own block's limit, one coefficient
    base = scale
    call local_limits(local)
    if (status%stat /= demstep_stat%ok) return
    c_lo = 0.0_dp
    c_hi = 1.0_dp
    do
      if (solves >= max_solves) exit
      c = c_hi
      if (c_lo > 0.0_dp) c = sqrt(c_lo*c_hi)
      call set_scale(c)
      call exact_limit(scale, h)
      if (status%stat /= demstep_stat%ok) return
      if (h >= target) then
        c_hi = c
        best = scale
        best_result = result
        if (c_lo > 0.0_dp .and. c_hi <= 1.005_dp*c_lo) exit
      else
        c_lo = c
        if (.not. allocated(best)) c_hi = 2.0_dp*c_hi
      end if
    end do
    if (allocated(best)) then
      scale = best
      result = best_result
      call finish()
      return
    end if
    added = sum((scale - 1.0_dp)*mass)/sum(mass)
    if (present(passes)) passes = solves
    call set_status(status, demstep_stat%not_converged, "the scaled limit stayed below the target after " &
      //"max_passes exact solves", where="max_passes")
  contains
    !> The exact damped limit h of the scaled system (result set), warm-started.
    subroutine exact_limit(factor, h)
      real(dp), intent(in) :: factor(:)
      real(dp), intent(out) :: h
      h = 0.0_dp
      call operator_from_springs(monitor%dim, monitor%last%rotation, mass*factor, base_inertia*factor, &
        radius, monitor%springs, .false., op, rate_of_op, status, fixed)
      if (status%stat /= demstep_stat%ok) return
      result = critical_step_type()
      result%rotation = monitor%last%rotation
      result%periodic = monitor%last%periodic
      ! (each solve moves the mode: the scene solve's Krylov size)
      call operator_critical_steps(op, monitor%springs, rate_of_op, .false., monitor%solver, &
        default_max_eigen_dof, monitor%tolerance, vec, result, status, &
        bounds=[cheap_bound(op), cheap_bound(op, dashpots=.true.)], ncv=scene_lanczos_ncv, damped_vec=dvec)
      solves = solves + 1
      h = result%dt_critical_damped
    end subroutine exact_limit
    !> Each free body's factor at coefficient c.
    subroutine set_scale(c)
      real(dp), intent(in) :: c
      integer :: k
      scale = base
      do k = 1, size(local)
        associate(i => monitor%body_particle(k))
          scale(i) = max(base(i), c*(target/local(k))**2)
        end associate
      end do
    end subroutine set_scale
    !> Each free body's own damped limit (its partners held), unscaled.
    subroutine local_limits(h_local)
      real(dp), allocatable, intent(out) :: h_local(:)
      real(dp), allocatable :: a_max(:), b_max(:)
      call block_maxima(monitor%op, a_max, status)
      if (status%stat /= demstep_stat%ok) return
      b_max = [(0.0_dp, b = 1, size(a_max))]
      if (size(monitor%op%dcoef, 2) > 0) then
        call operator_mix(monitor%op, 0.0_dp, 1.0_dp)
        call block_maxima(monitor%op, b_max, status)
        call operator_mix(monitor%op, 1.0_dp, 0.0_dp)
        if (status%stat /= demstep_stat%ok) return
      end if
      h_local = damped_lower_bound(2.0_dp/sqrt(max(a_max, tiny(1.0_dp))), b_max)/monitor%rate
    end subroutine local_limits
    subroutine finish()
      added = sum((scale - 1.0_dp)*mass)/sum(mass)
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
    integer :: b, r, nc
    nc = op%nc
    allocate(lam(op%n_bodies), source=0.0_dp)
    allocate(block(nc, nc), v(nc))
    status%stat = demstep_stat%ok
    do b = 1, op%n_bodies
      call assembly_matrix_rows(op, [b], [(r, r = 1, op%n_bodies)], row_start, col, val, status)
      if (status%stat /= demstep_stat%ok) return
      do r = 1, nc
        block(r, :) = val(row_start(r):row_start(r) + nc - 1)
      end do
      call largest_eigenpair(block, lam(b), v, status)
      if (status%stat /= demstep_stat%ok) return
    end do
  end subroutine block_maxima

  !> The smallest share of the core of a distribution of shares (>= 0): the
  !> largest ones that together hold at least half of the total (bisection
  !> on the threshold, O(n) per step).
  pure real(dp) function core_share(share) result(t)
    real(dp), intent(in) :: share(:)
    real(dp) :: lo, hi, half
    integer :: it
    half = 0.5_dp*sum(share)
    lo = 0.0_dp
    hi = maxval(share)
    ! the shares >= lo hold at least half of the total
    do it = 1, 60
      t = 0.5_dp*(lo + hi)
      if (sum(share, mask=share >= t) >= half) then
        lo = t
      else
        hi = t
      end if
    end do
    t = max(lo, tiny(1.0_dp))
  end function core_share

end module demstep_mass_scaling
