!> The exact limit inside a running DEM solver, from the solver's own arrays.
!>
!> `solver_critical_steps` takes positions, masses, radii (and inertia), the
!> solver's contact list `pairs(2, nc)` with scalar (size 1) or per-contact
!> (size nc) stiffness and dashpots, walls and a periodic cell, and returns
!> what `assembly_critical_steps` returns for the same scene: no scene is
!> built, nothing is searched (a listed pair acts while it overlaps, through
!> the nearest periodic image), the arrays are read in place. Rotations are
!> on whenever any tangential stiffness is given.
!>
!> `step_monitor_type` keeps the operator, the springs and the top mode
!> between calls: `update` re-solves warm-started from the previous modes
!> (taken as they are when their measured residuals on the new operator meet
!> the tolerance; else refined from themselves, and when the refined top
!> left its place (`in_place`), Lanczos with its confirmation run, at least
!> `ncv` products from the mode plus a fresh random start; that confirmed
!> solve also every `confirm_every`-th update; with dashpots the
!> confirmation is the damped limit's cold solve instead, see
!> `operator_critical_steps`). A body that could
!> carry the top (its per-body bound at or above omega_max^2) and stiffened
!> by more than `drift` (a new contact, say) has its neighbourhood solved on
!> its own (`region_top`, a dense eigenproblem of a few dozen unknowns); when
!> that top reaches `local_margin` omega_max^2 it joins the start and the
!> confirmed Lanczos solve runs from it. Warm updates skip the randomised certificate unless
!> `certify` (the first update always makes it). `check`
!> says from one O(contacts) pass over the arrays (no operator built) whether
!> a step is still safe:
!> - the rigorous per-body bound (`cheap_bound`): with K_c the contact's
!>   stiffness, (A + B)' K_c (A + B) <= 2 A' K_c A + 2 B' K_c B splits each
!>   contact between its bodies, and per body k_n (n.u)^2 + k_t |P u + n x phi|^2
!>   <= max(k_n, 2 k_t) |u|^2 + 2 k_t |phi|^2 (phi = arm theta), so
!>   omega_max^2 <= max_i sum_{c at i} 2 max(max(k_n, 2 k_t)/m_i, 2 k_t arm_i^2/I_i)
!>   (a wall contact without the factor 2); a step below its (damped) limit is
!>   safe whatever the mode;
!> - the Rayleigh quotient of the previous top mode on the current contacts
!>   (the interaction kernel once per contact): a lower estimate of the new
!>   omega_max^2. The previous exact
!>   limit scaled by sqrt(omega_then^2/quotient) is the estimate the step is
!>   held against; when the quotient or the bound has moved by more than
!>   `drift` since the update, or the step is above the estimate, the verdict
!>   is "re-solve now".
!> `mode_participation` gives each particle's share of the top mode (its
!> degrees of freedom's squared amplitude) and each contact's share of the
!> mode's energy v'A'v, each summing to 1 (no pre-stress).
!>
!> A monitor holds ARPACK's SAVEd state only during a solve: see
!> `demstep_lanczos` (concurrent solves are refused with `demstep_stat%busy`).
module demstep_monitor
  use demstep_kinds, only: dp, i8
  use demstep_status, only: demstep_status_type, demstep_stat, set_status
  use demstep_interaction, only: reduced_mass, contact_arm, wall_overlap, dashpot_coefficient, contact_product, &
    contact_products
  use demstep_progress, only: progress_type
  use demstep_assembly, only: critical_step_type, assembly_operator_type, spring_block_type, &
    operator_from_springs, operator_critical_steps, assembly_operator_apply, eigen_solver, &
    default_max_eigen_dof, damped_lower_bound, scene_lanczos_ncv, assembly_matrix_rows, operator_spring_energies, &
    parallel_springs
  use demstep_lapack, only: largest_eigenpair
  use demstep_lanczos, only: lanczos_tolerance_default
  use demstep_scene_data, only: scene_type
  use demstep_packing, only: random_periodic_packing
  use demstep_assembly, only: assembly_critical_steps, locality_order
  use, intrinsic :: ieee_arithmetic, only: ieee_is_finite
  implicit none
  private

  public :: solver_critical_steps, mode_participation, top_shares, cheap_bound, fresh_pour_estimate, &
    scene_participation
  ! (for `demstep_mass_scaling`)
  public :: sphere_inertia, region_of, region_top

  !> Particles of the generated packing of `fresh_pour_estimate` (default).
  integer, parameter, public :: fresh_pour_particles = 500
  !> Default Lanczos tolerance of a monitor: a relative residual of 1e-4 on
  !> omega_max^2 (and on the damped limit's eigenvalue 4) puts the certified
  !> steps within 5e-5 (undamped) and 1e-4 (damped) below the exact ones, far
  !> inside any safety factor, and lets a settled bed's previous modes stand
  !> as they are (`solver_critical_steps` keeps the scene's 1e-10).
  real(dp), parameter, public :: monitor_tolerance_default = 1.0e-3_dp
  !> Default Krylov size of a monitor's warm-started (confirmed) Lanczos
  !> solves, the scene solve's: with 8, an agitated bed (example/dem_solver
  !> at 1.2 times its limit, 300 updates checked against cold ones) got warm
  !> limits up to 2.9 % above the cold ones, the confirmation run converging
  !> to a lower top; with 32 the 150 checked agreed to 1e-6.
  integer, parameter, public :: monitor_ncv_default = scene_lanczos_ncv
  !> Default relative drift of the mode's Rayleigh quotient or of the bound
  !> (omega^2) since the last update above which `check` asks for a re-solve.
  real(dp), parameter, public :: monitor_drift_default = 0.02_dp
  !> Default `confirm_every` of a monitor.
  integer, parameter, public :: monitor_confirm_default = 10
  !> Default `local_margin` of a monitor: a stiffened body's neighbourhood
  !> whose own top reaches this fraction of omega_max^2 joins the warm start.
  !> Measured in example/dem_solver's settled beds: the top mode's peak body's
  !> neighbourhood reaches 0.98 to 0.996 of omega_max^2; 10 of 3000 bodies'
  !> reach 0.9 (81 reach 0.8).
  real(dp), parameter, public :: monitor_local_margin_default = 0.9_dp
  !> Default `in_place` of a monitor: a re-solved top mode whose overlap with
  !> the previous one is at least this stayed where it was.
  real(dp), parameter, public :: monitor_in_place_default = 0.9_dp
  !> Largest |coordinate| and radius (as scenes: squared distances stay finite).
  real(dp), parameter :: max_value = 1.0e150_dp

  !> How many particles and springs a report lists (`participation_top`).
  integer, parameter, public :: participation_top = 10
  !> The kinds of spring a participation names (`participation_type%spring_kind`).
  character(len=*), parameter, public :: spring_kind_names(4) = [character(len=7) :: "contact", "wall", &
    "bond", "drag"]

  !> Which particles and springs carry a scene's top mode (`scene_participation`).
  type, public :: participation_type
    !> Whether there is a top mode (an eigensolver returned one).
    logical :: computed = .false.
    !> Each particle's share of the mode (its degrees of freedom's squared
    !> amplitude; 0 when fixed), summing to 1.
    real(dp), allocatable :: particle_share(:)
    !> Each linearised spring's share of the mode's energy v'A'v (summing to
    !> 1; negative parts only with pre-stress), its particles (a = 0: a wall
    !> or the ground), its kind (an index into `spring_kind_names`) and its
    !> stiffness (k_n, k_t).
    real(dp), allocatable :: spring_share(:)
    integer, allocatable :: spring_a(:), spring_b(:), spring_kind(:)
    real(dp), allocatable :: spring_k(:, :)
  end type participation_type

  !> The verdicts of `check`.
  type, public :: monitor_verdict_enum
    !> The step is at or below the rigorous bound's limit: safe whatever changed.
    integer :: safe_bound = 1
    !> The step is below the previous exact limit scaled by the mode's
    !> Rayleigh quotient, which moved less than `drift`: still safe (estimate).
    integer :: safe_estimate = 2
    !> Re-solve now (`update`): the step is above the estimate, or the
    !> packing changed by more than `drift`, or there is no update yet.
    integer :: resolve = 3
  end type monitor_verdict_enum
  !> The verdicts by name.
  type(monitor_verdict_enum), parameter, public :: monitor_verdict = monitor_verdict_enum()

  !> A persistent monitor of a running solver's stability limit.
  type, public :: step_monitor_type
    !> Eigensolver (`eigen_solver%...`, default auto: dense up to
    !> `default_max_eigen_dof`), its relative tolerance, and the drift that asks
    !> for a re-solve.
    integer :: solver = 1
    real(dp) :: tolerance = monitor_tolerance_default
    real(dp) :: drift = monitor_drift_default
    !> Krylov size of the warm-started Lanczos solves (the first, cold, solve
    !> takes the scene solve's, `scene_lanczos_ncv`): a confirmation run
    !> makes at least ncv products.
    integer :: ncv = monitor_ncv_default
    !> The rigorous bound of an update: the per-body bound of `check`
    !> (`cheap_bound`, O(contacts), default) or, false, the Collatz-Wielandt
    !> bound of `assembly_critical_steps` (tighter, about 36 products each
    !> for the stiffness and the dashpots).
    logical :: cheap = .true.
    !> Every confirm_every-th update runs the Lanczos solves in full even
    !> when the previous modes would do (0: never; 1: every update); the
    !> others take them when their residuals meet the tolerance.
    integer :: confirm_every = monitor_confirm_default
    !> Whether warm updates add the randomised Lanczos certificate
    !> (`safe_basis%randomised`; about 70 products at 18 000 degrees of
    !> freedom, more than the rest of a confirmed update). The first, cold,
    !> update always does; warm ones rest on the previous mode, the local
    !> solves and the confirmations (`safe_basis%estimate`).
    logical :: certify = .false.
    !> A stiffened body's neighbourhood whose own top (`region_top`) reaches
    !> local_margin omega_max^2 joins the warm start (see `update`).
    real(dp) :: local_margin = monitor_local_margin_default
    !> A previous undamped mode whose residual fails is refined from itself
    !> alone; when the mode found overlaps it by at least in_place
    !> (|cosine|; above 1: never) the top stayed in place: no confirmation,
    !> and the previous damped mode is tried as it is (taken when its residual
    !> meets the tolerance, else refined). A top that left its place is solved
    !> again with its confirmation run, and so are the damped Newton steps.
    !> (At a scheduled confirmation the same overlap decides the damped one.)
    real(dp) :: in_place = monitor_in_place_default
    !> Whether the last update took the previous modes as they were, and
    !> whether it was a warm update that was confirmed: the undamped solve's
    !> confirmation run or, with dashpots, the damped top's cold solve (on the
    !> operator the step is held against; it confirms the damped limit, and
    !> the undamped mode with it).
    logical :: accepted = .false., confirmed = .false.
    !> The last update's stiffened bodies that were looked at, and whether a
    !> neighbourhood's top joined its start (a Lanczos solve from it).
    integer :: flagged = 0
    logical :: local_start = .false.
    !> Each free body's per-body bound (omega^2) when it was last looked at
    !> (at the last confirmed solve, or since, when it stiffened by more than
    !> `drift`).
    real(dp), allocatable :: confirmed_rows(:)
    !> The last update's result (`critical_step_type`), valid after an update.
    type(critical_step_type) :: last
    logical :: ready = .false.
    !> Updates and checks made.
    integer :: updates = 0, checks = 0
    !> The last check: its verdict, the quotient's and the bound's omega^2 over
    !> the update's, and the estimated limit it held the step against.
    integer :: verdict = 3
    real(dp) :: quotient_ratio = 0.0_dp, bound_ratio = 0.0_dp, dt_estimate = 0.0_dp
    !> The limit the step is held against (damped when dashpots are given),
    !> omega_max^2 and the cheap bound's omega^2 at the update.
    real(dp) :: dt_limit = 0.0_dp, omega2 = 0.0_dp, bound2 = 0.0_dp
    !> Particles and dimension of the last update.
    integer :: n_particles = 0, dim = 3
    !> The top undamped unit mode (scaled coordinates of `op`), the operator
    !> and springs of the update, and which particle each body is and which
    !> contact row each spring is (> 0: row of pairs; < 0: -particle on a wall).
    real(dp), allocatable :: mode(:), damped_mode(:)
    type(assembly_operator_type) :: op
    !> springs(1:n_springs) and spring_row(1:n_springs) are the update's (the
    !> arrays keep their size between updates while it suffices).
    type(spring_block_type), allocatable :: springs(:)
    integer, allocatable :: body_particle(:), spring_row(:)
    integer :: n_springs = 0
    !> The free particles in the order of the operator's bodies where its
    !> locality order is taken (`locality_order`; size 0: the arrays' order),
    !> chosen at the first update and kept while the particles and free
    !> particles stay as many: the modes, rows and regions kept from update
    !> to update are by body in this order.
    integer, allocatable :: order(:)
    integer :: order_n = -1, order_nfree = -1
    real(dp) :: rate = 0.0_dp
    !> The top mode per particle, proportional to its physical displacement
    !> and rotation times radius (6, particles; 0 for fixed ones): the check's
    !> Rayleigh quotient needs no operator.
    real(dp), allocatable :: mode_particles(:, :)
    !> The same for the damped limit's mode (the damped Newton steps' last;
    !> 0 without dashpots).
    real(dp), allocatable :: damped_particles(:, :)
    !> The check's per-particle bound rows (work arrays kept between checks).
    real(dp), allocatable, private :: check_rows(:, :)
    !> Work of the updates, kept between them: each contact's row (or
    !> -particle) and geometry as `solver_springs` finds them, and the
    !> unit previous mode with its product as `stands` measures it.
    integer, allocatable, private :: contact_hit(:)
    real(dp), allocatable, private :: contact_geo(:, :), unit_mode(:), mode_av(:)
  contains
    !> Re-solve the exact limit, warm-started from the previous mode.
    procedure :: update => monitor_update
    !> Whether a step is still safe on the current contacts.
    procedure :: check => monitor_check
  end type step_monitor_type

contains

  !> The critical steps of a solver's particles and contact list (see the
  !> module notes), equal to `assembly_critical_steps` on the same scene.
  !> x(dim, n) (dim 1 to 3); pairs(2, nc); k_n, k_t, c_n, c_t of size 1 (every
  !> contact) or nc; wall points and unit normals (dim, nw) with wall_k =
  !> (k_n, k_t) and wall_damping = (zeta_n, zeta_t), dashpots 2 zeta sqrt(m k);
  !> periodic axes with the cell [cell_lo, cell_hi). Status invalid_input with
  !> `where` the argument and `index` the particle, contact or wall.
  subroutine solver_critical_steps(x, mass, radius, pairs, k_n, result, status, k_t, c_n, c_t, &
      inertia, fixed, wall_point, wall_normal, wall_k, wall_damping, periodic, cell_lo, cell_hi, &
      solver, tolerance, solved)
    real(dp), intent(in) :: x(:, :), mass(:), radius(:)
    integer, intent(in) :: pairs(:, :)
    real(dp), intent(in) :: k_n(:)
    type(critical_step_type), intent(out) :: result
    type(demstep_status_type), intent(out) :: status
    real(dp), intent(in), optional :: k_t(:), c_n(:), c_t(:), inertia(:)
    logical, intent(in), optional :: fixed(:)
    real(dp), intent(in), optional :: wall_point(:, :), wall_normal(:, :), wall_k(:), wall_damping(:)
    logical, intent(in), optional :: periodic(:)
    real(dp), intent(in), optional :: cell_lo(:), cell_hi(:)
    !> `eigen_solver%auto` (default), `%dense`, `%lanczos` or `%none`; tolerance
    !> as `assembly_critical_steps`.
    integer, intent(in), optional :: solver
    real(dp), intent(in), optional :: tolerance
    !> The monitor that made the solve (e.g. for `mode_participation`).
    type(step_monitor_type), intent(out), optional :: solved
    type(step_monitor_type) :: monitor
    ! the same bound and tolerance as assembly_critical_steps
    monitor%cheap = .false.
    monitor%tolerance = lanczos_tolerance_default
    if (present(solver)) monitor%solver = solver
    if (present(tolerance)) monitor%tolerance = tolerance
    call monitor%update(x, mass, radius, pairs, k_n, status, k_t, c_n, c_t, inertia, fixed, &
      wall_point, wall_normal, wall_k, wall_damping, periodic, cell_lo, cell_hi)
    if (status%stat == demstep_stat%ok) result = monitor%last
    if (present(solved)) solved = monitor
  end subroutine solver_critical_steps

  !> Re-solve the exact limit on the current arrays (as `solver_critical_steps`),
  !> the Lanczos solve warm-started from the previous top mode when the
  !> degrees of freedom are the same. Keeps the operator, springs and mode.
  subroutine monitor_update(monitor, x, mass, radius, pairs, k_n, status, k_t, c_n, c_t, &
      inertia, fixed, wall_point, wall_normal, wall_k, wall_damping, periodic, cell_lo, cell_hi)
    class(step_monitor_type), intent(inout) :: monitor
    real(dp), intent(in) :: x(:, :), mass(:), radius(:)
    integer, intent(in) :: pairs(:, :)
    real(dp), intent(in) :: k_n(:)
    type(demstep_status_type), intent(out) :: status
    real(dp), intent(in), optional :: k_t(:), c_n(:), c_t(:), inertia(:)
    logical, intent(in), optional :: fixed(:)
    real(dp), intent(in), optional :: wall_point(:, :), wall_normal(:, :), wall_k(:), wall_damping(:)
    logical, intent(in), optional :: periodic(:)
    real(dp), intent(in), optional :: cell_lo(:), cell_hi(:)
    logical :: rotation, warm, accept, certify, stood, stood_damped
    integer :: i, nfree, ncv
    real(dp) :: a_bound, in_place
    real(dp), allocatable :: rows(:), damped_rows(:)
    ! (whether `stands` made its product: then monitor%mode_av)
    integer :: made
    monitor%ready = .false.
    monitor%accepted = .false.
    if (monitor%solver < eigen_solver%auto .or. monitor%solver > eigen_solver%none) then
      call set_status(status, demstep_stat%invalid_input, "must be auto, dense, lanczos or none", &
        where="solver")
      return
    end if
    if (.not. (monitor%in_place >= 0.0_dp)) then
      call set_status(status, demstep_stat%invalid_input, "must be >= 0 (above 1: never in place)", &
        where="in_place")
      return
    end if
    call build_operator(monitor, x, mass, radius, pairs, k_n, rotation, status, k_t, c_n, c_t, inertia, &
      fixed, wall_point, wall_normal, wall_k, wall_damping, periodic, cell_lo, cell_hi)
    if (status%stat /= demstep_stat%ok) return
    ! the previous mode is a warm start while the degrees of freedom are the same
    if (allocated(monitor%mode)) then
      if (size(monitor%mode) /= monitor%op%n) deallocate(monitor%mode, monitor%damped_mode)
    end if
    if (.not. allocated(monitor%mode)) allocate(monitor%mode(monitor%op%n), &
      monitor%damped_mode(monitor%op%n), source=0.0_dp)
    monitor%last = critical_step_type()
    monitor%last%rotation = rotation .and. size(x, 1) > 1
    monitor%last%periodic = .false.
    if (present(periodic)) monitor%last%periodic = any(periodic)
    ! each free body's per-body bound (omega^2), and the update's (its largest)
    call body_bounds(monitor%op, rows, damped_row=damped_rows)
    a_bound = bound_of_rows(rows)
    monitor%bound2 = a_bound*monitor%rate**2
    rows = rows*monitor%rate**2
    ! a cold solve with the scene's Krylov size, a warm one with the monitor's;
    ! a warm one takes the previous modes as they are when their residuals on
    ! the new operator meet the tolerance; when the undamped one does not, it
    ! is refined from itself alone, and when the refined mode left its place
    ! (overlap below `in_place`: the top moved), and every confirm_every-th
    ! update, the undamped Lanczos solve runs with its confirmation (one run
    ! of at least ncv products from the mode plus a fresh random start: a
    ! top mode elsewhere is found)
    ncv = scene_lanczos_ncv
    warm = any(monitor%mode /= 0.0_dp)
    if (warm .and. monitor%ncv > 1) ncv = monitor%ncv
    accept = warm .and. monitor%confirm_every /= 1
    if (accept .and. monitor%confirm_every > 1) accept = mod(monitor%updates + 1, monitor%confirm_every) /= 0
    ! a top elsewhere needs a body that could carry it (its own bound at or
    ! above the last omega_max^2) to have stiffened (a new contact, say): its
    ! bound risen by more than `drift` since it was last looked at. Such a
    ! body's neighbourhood (`region_top`) is solved on its own: when its top
    ! reaches `local_margin` omega_max^2, its vector joins the start
    monitor%flagged = 0
    monitor%local_start = .false.
    if (accept .and. allocated(monitor%confirmed_rows)) then
      if (size(monitor%confirmed_rows) /= size(rows)) then
        accept = .false.
      else
        call look_at_stiffened(monitor, rows, status)
        if (status%stat /= demstep_stat%ok) return
      end if
    end if
    ! (a start with a neighbourhood's top added: the confirmed solve from it;
    ! the damped mode is tried as it is when the undamped one stood or stayed
    ! in place, else its Newton steps confirm their solves too)
    ! (only a mode that may be taken is tried: a confirmed solve makes no
    ! use of the product)
    accept = accept .and. .not. monitor%local_start
    stood = accept
    made = 0
    if (stood) then
      stood = stands(monitor%op, monitor%mode, monitor%tolerance, monitor%unit_mode, monitor%mode_av)
      made = monitor%op%n
    end if
    if (.not. allocated(monitor%mode_av)) allocate(monitor%mode_av(0))
    certify = monitor%certify .or. .not. warm
    ! (the undamped mode's product from `stands` spares the solve's; a top
    ! re-solved in place, not moved, lets the damped mode be tried as it is)
    ! (a scheduled confirmation confirms the damped steps too: neither the
    ! previous damped mode nor a top in place is taken then)
    in_place = 2.0_dp
    if (accept) in_place = monitor%in_place
    stood_damped = stood .and. accept
    if (monitor%cheap) then
      call operator_critical_steps(monitor%op, monitor%springs(:monitor%n_springs), monitor%rate, .false., &
        monitor%solver, &
        default_max_eigen_dof, monitor%tolerance, monitor%mode, monitor%last, status, &
        bounds=[a_bound, bound_of_rows(damped_rows)], ncv=ncv, &
        damped_vec=monitor%damped_mode, accept_start=accept, accept_damped=stood_damped, certify=certify, &
        start_av=monitor%mode_av(:made), in_place=in_place, confirm_steps=merge(ncv, 0, warm), confirmed=monitor%confirmed)
    else
      call operator_critical_steps(monitor%op, monitor%springs(:monitor%n_springs), monitor%rate, .false., &
        monitor%solver, &
        default_max_eigen_dof, monitor%tolerance, monitor%mode, monitor%last, status, ncv=ncv, &
        damped_vec=monitor%damped_mode, accept_start=accept, accept_damped=stood_damped, certify=certify, &
        start_av=monitor%mode_av(:made), in_place=in_place, confirm_steps=merge(ncv, 0, warm), confirmed=monitor%confirmed)
    end if
    monitor%confirmed = warm .and. monitor%confirmed
    monitor%accepted = accept .and. stood
    ! (the product `stands` made)
    if (made > 0) monitor%last%eigen_products = monitor%last%eigen_products + 1
    if (status%stat /= demstep_stat%ok) then
      monitor%mode = 0.0_dp
      monitor%damped_mode = 0.0_dp
      return
    end if
    nfree = size(mass)
    if (present(fixed)) nfree = count(.not. fixed)
    if (allocated(monitor%body_particle)) deallocate(monitor%body_particle)
    allocate(monitor%body_particle(nfree))
    if (allocated(monitor%op%order)) then
      ! (the operator's bodies in the monitor's locality order)
      monitor%body_particle = monitor%order
    else
      nfree = 0
      do i = 1, size(mass)
        if (present(fixed)) then
          if (fixed(i)) cycle
        end if
        nfree = nfree + 1
        monitor%body_particle(nfree) = i
      end do
    end if
    if (monitor%last%eigen_computed) then
      monitor%omega2 = monitor%last%omega_max**2
      monitor%dt_limit = monitor%last%dt_critical_damped
    else
      monitor%omega2 = monitor%last%omega_bound**2
      monitor%dt_limit = monitor%last%dt_critical_damped
    end if
    monitor%n_particles = size(mass)
    monitor%dim = size(x, 1)
    ! (the bodies' bounds the next updates are held against)
    if (monitor%confirmed .or. .not. warm) call move_alloc(rows, monitor%confirmed_rows)
    call store_mode(monitor, size(mass))
    monitor%updates = monitor%updates + 1
    monitor%ready = .true.
  end subroutine monitor_update

  !> Whether the step dt is still safe on the current arrays (the same as
  !> `update` takes), from one O(contacts) pass over them with no operator
  !> built: the rigorous per-body bound and the previous mode's Rayleigh
  !> quotient (the interaction kernel on each listed contact). `safe` is true
  !> for the verdicts `safe_bound` and `safe_estimate`; monitor%verdict,
  !> %dt_estimate, %quotient_ratio and %bound_ratio say why. Without an
  !> update yet, or when the degrees of freedom changed (particles, free
  !> particles or rotations), the verdict is `resolve`. Status invalid_input
  !> as `update`, or naming `dt` (not finite and > 0).
  subroutine monitor_check(monitor, dt, safe, x, mass, radius, pairs, k_n, status, k_t, c_n, c_t, &
      inertia, fixed, wall_point, wall_normal, wall_k, wall_damping, periodic, cell_lo, cell_hi)
    class(step_monitor_type), intent(inout) :: monitor
    real(dp), intent(in) :: dt
    logical, intent(out) :: safe
    real(dp), intent(in) :: x(:, :), mass(:), radius(:)
    integer, intent(in) :: pairs(:, :)
    real(dp), intent(in) :: k_n(:)
    type(demstep_status_type), intent(out) :: status
    real(dp), intent(in), optional :: k_t(:), c_n(:), c_t(:), inertia(:)
    logical, intent(in), optional :: fixed(:)
    real(dp), intent(in), optional :: wall_point(:, :), wall_normal(:, :), wall_k(:), wall_damping(:)
    logical, intent(in), optional :: periodic(:)
    real(dp), intent(in), optional :: cell_lo(:), cell_hi(:)
    real(dp) :: a_bound, b_bound, q, dt_bound
    logical :: same
    safe = .false.
    monitor%verdict = monitor_verdict%resolve
    monitor%dt_estimate = 0.0_dp
    if (.not. (ieee_is_finite(dt) .and. dt > 0.0_dp)) then
      call set_status(status, demstep_stat%invalid_input, "must be finite and > 0", where="dt")
      return
    end if
    call check_solver_arrays(x, mass, radius, pairs, k_n, status, k_t, c_n, c_t, inertia, fixed, &
      wall_point, wall_normal, wall_k, wall_damping, periodic, cell_lo, cell_hi)
    if (status%stat /= demstep_stat%ok) return
    call check_pass(monitor, x, mass, radius, pairs, k_n, a_bound, b_bound, q, same, status, k_t, c_n, &
      c_t, inertia, fixed, wall_point, wall_normal, wall_k, wall_damping, periodic, cell_lo, cell_hi)
    if (status%stat /= demstep_stat%ok) return
    monitor%checks = monitor%checks + 1
    ! the rigorous bound (damped: its lower bound with the dashpots' own bound)
    if (.not. a_bound > 0.0_dp) then
      dt_bound = huge(1.0_dp)
    else
      dt_bound = damped_lower_bound(2.0_dp/sqrt(a_bound), b_bound)
    end if
    if (dt <= dt_bound) then
      safe = .true.
      monitor%verdict = monitor_verdict%safe_bound
      monitor%dt_estimate = dt_bound
    end if
    if (.not. (monitor%ready .and. same)) return
    monitor%quotient_ratio = q/monitor%omega2
    monitor%bound_ratio = a_bound/monitor%bound2
    if (safe) return
    if (.not. (q > 0.0_dp)) return
    monitor%dt_estimate = monitor%dt_limit*sqrt(monitor%omega2/max(q, monitor%omega2))
    if (abs(monitor%quotient_ratio - 1.0_dp) > monitor%drift) return
    if (monitor%bound_ratio - 1.0_dp > monitor%drift) return
    if (dt <= monitor%dt_estimate) then
      safe = .true.
      monitor%verdict = monitor_verdict%safe_estimate
    end if
  end subroutine monitor_check

  !> The check's one pass over the listed contacts and the wall contacts (the
  !> springs `solver_springs` would make, none stored): the per-body bounds
  !> a_bound >= omega_max^2 and b_bound >= lambda_max(M^-1/2 C M^-1/2) (1/s;
  !> 0 without dashpots) as `cheap_bound` takes them, and the Rayleigh
  !> quotient q (omega^2) of the last update's mode (`mode_particles`) on
  !> these springs; `same` false (q = 0) when the degrees of freedom are not
  !> the update's. Status invalid_input naming `pairs` (coincident particles).
  subroutine check_pass(monitor, x, mass, radius, pairs, k_n, a_bound, b_bound, q, same, status, k_t, &
      c_n, c_t, inertia, fixed, wall_point, wall_normal, wall_k, wall_damping, periodic, cell_lo, cell_hi)
    class(step_monitor_type), intent(inout) :: monitor
    real(dp), intent(in) :: x(:, :), mass(:), radius(:)
    integer, intent(in) :: pairs(:, :)
    real(dp), intent(in) :: k_n(:)
    real(dp), intent(out) :: a_bound, b_bound, q
    logical, intent(out) :: same
    type(demstep_status_type), intent(out) :: status
    real(dp), intent(in), optional :: k_t(:), c_n(:), c_t(:), inertia(:)
    logical, intent(in), optional :: fixed(:)
    real(dp), intent(in), optional :: wall_point(:, :), wall_normal(:, :), wall_k(:), wall_damping(:)
    logical, intent(in), optional :: periodic(:)
    real(dp), intent(in), optional :: cell_lo(:), cell_hi(:)
    real(dp) :: box(3), d(3), dist, nn(3), arm(2), k(4), c(4), kw(2), zw(2), p(3), nw(3), xi(3), overlap, &
      energy, norm, y(3, 4), wu(2), wr(2), rinv(2), f
    real(dp), parameter :: zero3(3) = 0.0_dp
    logical :: wrap(3), damped, rotation, touching, free(2)
    integer :: n, nc, cc, i, j, e, w, n_walls, nfree
    ! a batch of contacts for the mode's energy: normals, coefficients,
    ! ends (2c - 1, 2c), the mode at them, their 1/r, the forces
    integer, parameter :: batch = 64
    real(dp), parameter :: no_dashpots(4, 1) = 0.0_dp
    real(dp) :: bn(3, batch), bc(7, batch), bx(6, 0:2*batch), br(0:2*batch), bf(6, 2*batch)
    integer :: be(2, batch), nb
    n = size(mass)
    nb = 0
    be = reshape([(e, e = 1, 2*batch)], [2, batch])
    bx(:, 0) = 0.0_dp
    br(0) = 0.0_dp
    nc = size(pairs, 2)
    status%stat = demstep_stat%ok
    call solver_options(size(x, 1), wrap, box, kw, zw, damped, rotation, k_t, c_n, c_t, wall_k, &
      wall_damping, periodic, cell_lo, cell_hi)
    nfree = n
    if (present(fixed)) nfree = count(.not. fixed)
    same = monitor%ready .and. n == monitor%n_particles .and. (rotation .eqv. monitor%last%rotation) &
      .and. nfree == size(monitor%body_particle) .and. allocated(monitor%mode_particles)
    if (same) same = size(monitor%mode_particles, 2) == n
    ! per particle: (the stiffness row, the dashpot row)
    if (allocated(monitor%check_rows)) then
      if (size(monitor%check_rows, 2) /= n) deallocate(monitor%check_rows)
    end if
    if (.not. allocated(monitor%check_rows)) allocate(monitor%check_rows(2, n))
    monitor%check_rows = 0.0_dp
    energy = 0.0_dp
    k = 0.0_dp
    c = 0.0_dp
    do cc = 1, nc
      i = pairs(1, cc)
      j = pairs(2, cc)
      free = [.true., .true.]
      if (present(fixed)) free = [.not. fixed(i), .not. fixed(j)]
      if (.not. any(free)) cycle
      call pair_geometry(x(:, i), x(:, j), radius(i) + radius(j), wrap, box, d, dist, touching)
      if (.not. touching) cycle
      if (.not. dist > 0.0_dp) then
        call coincident(cc, status)
        return
      end if
      nn = d/dist
      overlap = radius(i) + radius(j) - dist
      arm = [contact_arm(radius(i), overlap)/radius(i), contact_arm(radius(j), overlap)/radius(j)]
      k(1) = pick(k_n, cc)
      if (present(k_t)) k(2) = pick(k_t, cc)
      if (present(c_n)) c(1) = pick(c_n, cc)
      if (present(c_t)) c(2) = pick(c_t, cc)
      f = merge(2.0_dp, 1.0_dp, all(free))
      call body_scales(i, 1)
      call body_scales(j, 2)
      if (free(1)) call add_rows(i, 1)
      if (free(2)) call add_rows(j, 2)
      if (same) then
        ! (the mode's energy on a batch of contacts at once: `contact_products`)
        nb = nb + 1
        bn(:, nb) = nn
        bc(:, nb) = [k(1), k(2), arm(1), arm(2), 0.0_dp, k(3), k(4)]
        bx(:, 2*nb - 1) = monitor%mode_particles(:, i)
        bx(:, 2*nb) = monitor%mode_particles(:, j)
        br(2*nb - 1:2*nb) = rinv
        if (nb == batch) call add_batch()
      end if
    end do
    if (nb > 0) call add_batch()
    n_walls = 0
    if (present(wall_point)) n_walls = size(wall_point, 2)
    k = [kw(1), kw(2), 0.0_dp, 0.0_dp]
    f = 1.0_dp
    do w = 1, n_walls
      call wall_of(wall_point, wall_normal, w, p, nw)
      do i = 1, n
        if (present(fixed)) then
          if (fixed(i)) cycle
        end if
        xi = 0.0_dp
        xi(:size(x, 1)) = x(:, i)
        overlap = wall_overlap(xi, radius(i), p, nw)
        if (.not. overlap > 0.0_dp) cycle
        arm(2) = contact_arm(radius(i), overlap)/radius(i)
        c = 0.0_dp
        if (damped) c(1:2) = dashpot_coefficient(zw, mass(i), kw)
        call body_scales(i, 2)
        call add_rows(i, 2)
        if (same) then
          call contact_product(nw, k, 0.0_dp, arm(2), 0.0_dp, rinv(2), 0.0_dp, zero3, zero3, &
            mode_u(i), mode_r(i), y(:, 1), y(:, 2), y(:, 3), y(:, 4))
          energy = energy + dot_product(mode_u(i), y(:, 3)) + dot_product(mode_r(i), y(:, 4))
        end if
      end do
    end do
    a_bound = bound_of_rows(monitor%check_rows(1, :))
    b_bound = 0.0_dp
    if (damped) b_bound = bound_of_rows(monitor%check_rows(2, :))
    q = 0.0_dp
    if (.not. same) return
    ! the mode's kinetic norm with the current masses (rotations as r theta: I/r^2)
    norm = 0.0_dp
    do i = 1, n
      norm = norm + mass(i)*sum(monitor%mode_particles(1:3, i)**2) &
        + (particle_inertia(i)/radius(i)**2)*sum(monitor%mode_particles(4:6, i)**2)
    end do
    if (norm > 0.0_dp) q = energy/norm
  contains
    !> The batch's energy on the mode (each contact's terms in the order of
    !> one `contact_product`), and the batch emptied.
    subroutine add_batch()
      integer :: b
      call contact_products(1, nb, bn, bc, no_dashpots, 1.0_dp, 0.0_dp, be, br, bx, bf)
      do b = 1, 2*nb, 2
        energy = energy + dot_product(bx(1:3, b), bf(1:3, b)) + dot_product(bx(4:6, b), bf(4:6, b)) &
          + dot_product(bx(1:3, b + 1), bf(1:3, b + 1)) + dot_product(bx(4:6, b + 1), bf(4:6, b + 1))
      end do
      nb = 0
    end subroutine add_batch
    !> Body i at end e of the spring: 1/sqrt(m), r/sqrt(I) (0 without
    !> rotations) and 1/r.
    subroutine body_scales(i, e)
      integer, intent(in) :: i, e
      wu(e) = 1.0_dp/sqrt(mass(i))
      wr(e) = 0.0_dp
      if (rotation) wr(e) = radius(i)/sqrt(particle_inertia(i))
      rinv(e) = 1.0_dp/radius(i)
    end subroutine body_scales
    !> Body i's rows gain the spring's terms (end e).
    subroutine add_rows(i, e)
      integer, intent(in) :: i, e
      monitor%check_rows(1, i) = monitor%check_rows(1, i) + row_term(k, arm(e), wu(e), wr(e), rinv(e), f)
      if (damped) monitor%check_rows(2, i) = monitor%check_rows(2, i) + &
        row_term(c, arm(e), wu(e), wr(e), rinv(e), f)
    end subroutine add_rows
    real(dp) function particle_inertia(i)
      integer, intent(in) :: i
      if (present(inertia)) then
        particle_inertia = inertia(i)
      else
        particle_inertia = sphere_inertia(mass(i), radius(i))
      end if
    end function particle_inertia
    function mode_u(i) result(u)
      integer, intent(in) :: i
      real(dp) :: u(3)
      u = monitor%mode_particles(1:3, i)
    end function mode_u
    function mode_r(i) result(r)
      integer, intent(in) :: i
      real(dp) :: r(3)
      r = monitor%mode_particles(4:6, i)
    end function mode_r
  end subroutine check_pass

  !> The rigorous per-body bound of lambda_max of the operator's scaled
  !> stiffness A' (or, with `dashpots`, of its scaled dashpots B'; see the
  !> module notes): max over free bodies of the sum over its springs of
  !> f max(max(k_n, 2 k_t) w_u^2, 2 k_t (arm w_r)^2 + max(k_r, k_w) (w_r/r)^2)
  !> (w the M'^-1/2 factors, arm in radii, f = 2, or 1 on the ground; the
  !> rolling and twisting springs on the relative rotation split between the
  !> bodies the same way). O(springs), no product; rounding is covered by a
  !> relative 1e-12.
  function cheap_bound(op, dashpots) result(bound)
    type(assembly_operator_type), intent(in) :: op
    logical, intent(in), optional :: dashpots
    real(dp) :: bound
    real(dp), allocatable :: row(:)
    call body_bounds(op, row, dashpots)
    bound = bound_of_rows(row)
  end function cheap_bound

  !> The rigorous bound from each body's row of `cheap_bound`: their largest,
  !> raised by a relative 1e-12 for rounding (0 without bodies).
  pure real(dp) function bound_of_rows(row) result(bound)
    real(dp), intent(in) :: row(:)
    bound = 0.0_dp
    if (size(row) > 0) bound = maxval(row)*(1.0_dp + 1.0e-12_dp)
  end function bound_of_rows

  !> Each free body's row of `cheap_bound` (scaled; none without dashpots
  !> when `dashpots`); with `damped_row`, the dashpots' rows too, from the
  !> same pass (all 0 without dashpots).
  subroutine body_bounds(op, row, dashpots, damped_row)
    type(assembly_operator_type), intent(in) :: op
    real(dp), allocatable, intent(out) :: row(:)
    logical, intent(in), optional :: dashpots
    real(dp), allocatable, intent(out), optional :: damped_row(:)
    real(dp) :: k(4), wr, f
    integer :: s, e, i, rot
    logical :: damped, both
    damped = .false.
    if (present(dashpots)) damped = dashpots
    allocate(row(op%n_bodies), source=0.0_dp)
    if (present(damped_row)) allocate(damped_row(op%n_bodies), source=0.0_dp)
    if (damped .and. size(op%dcoef, 2) == 0) return
    both = present(damped_row) .and. size(op%dcoef, 2) > 0 .and. .not. damped
    ! the first rotational component (4 to 6), 0 without rotations
    rot = 0
    if (any(op%comp >= 4)) rot = op%comp(findloc(op%comp >= 4, .true., 1))
    do s = 1, op%n_springs
      if (damped) then
        k = op%dcoef(:, s)
      else
        k = [op%coef(1, s), op%coef(2, s), op%coef(6, s), op%coef(7, s)]
      end if
      f = 2.0_dp
      if (op%ends(1, s) == 0 .or. op%ends(2, s) == 0) f = 1.0_dp
      do e = 1, 2
        i = op%ends(e, s)
        if (i == 0) cycle
        wr = 0.0_dp
        if (rot > 0) wr = op%w(rot, i)
        row(i) = row(i) + row_term(k, op%coef(2 + e, s), op%w(1, i), wr, op%rinv(i), f)
        if (both) damped_row(i) = damped_row(i) + row_term(op%dcoef(:, s), op%coef(2 + e, s), op%w(1, i), wr, &
          op%rinv(i), f)
      end do
    end do
  end subroutine body_bounds

  !> One spring's term in its body's row of `cheap_bound` (see the module
  !> notes): f max(max(k_n, 2 k_t) wu^2, 2 k_t (arm wr)^2 + max(k_r, k_w)
  !> (wr rinv)^2), k = (k_n, k_t, k_r, k_w) (or the dashpots), arm in radii,
  !> wu and wr the body's translational and rotational (r theta) inverse
  !> square-root masses (wr 0 without rotations), rinv = 1/r, f = 2 (1 on the
  !> ground).
  pure real(dp) function row_term(k, arm, wu, wr, rinv, f) result(term)
    real(dp), intent(in) :: k(4), arm, wu, wr, rinv, f
    term = f*max(max(k(1), 2.0_dp*k(2))*wu**2, 2.0_dp*k(2)*(arm*wr)**2 + max(k(3), k(4))*(wr*rinv)**2)
  end function row_term

  !> Look at each body that could carry the top (its row at or above the last
  !> omega_max^2) and stiffened by more than `drift` since it was last looked
  !> at: its neighbourhood's own top (`region_top`, depth 1); when it reaches
  !> `local_margin` omega_max^2, that vector is added to the warm start
  !> (monitor%mode, then no longer a mode: the update's Lanczos solve runs
  !> from it). Counts them in monitor%flagged.
  subroutine look_at_stiffened(monitor, rows, status)
    class(step_monitor_type), intent(inout) :: monitor
    !> Each free body's row (omega^2).
    real(dp), intent(in) :: rows(:)
    type(demstep_status_type), intent(out) :: status
    integer, allocatable :: identity(:), place(:), bodies(:)
    real(dp), allocatable :: v(:), start(:)
    real(dp) :: lam, sgn
    integer :: b, k, nc, lo
    status%stat = demstep_stat%ok
    nc = monitor%op%nc
    do b = 1, size(rows)
      if (.not. (rows(b) >= monitor%omega2 .and. rows(b) > (1.0_dp + monitor%drift)*monitor%confirmed_rows(b))) &
        cycle
      if (.not. allocated(identity)) then
        identity = [(k, k = 1, monitor%op%n_bodies)]
        allocate(place(monitor%op%n_bodies), source=0)
      end if
      monitor%flagged = monitor%flagged + 1
      monitor%confirmed_rows(b) = rows(b)
      call region_top(monitor%op, b, 1, identity, place, bodies, lam, v, status)
      if (status%stat /= demstep_stat%ok) return
      if (lam*monitor%rate**2 < monitor%local_margin*monitor%omega2) cycle
      if (.not. allocated(start)) start = monitor%mode/norm2(monitor%mode)
      ! (the sign that does not cancel the start where they overlap)
      sgn = 0.0_dp
      do k = 1, size(bodies)
        lo = (bodies(k) - 1)*nc
        sgn = sgn + dot_product(start(lo + 1:lo + nc), v((k - 1)*nc + 1:k*nc))
      end do
      sgn = sign(1.0_dp, sgn)
      do k = 1, size(bodies)
        lo = (bodies(k) - 1)*nc
        start(lo + 1:lo + nc) = start(lo + 1:lo + nc) + sgn*v((k - 1)*nc + 1:k*nc)
      end do
    end do
    if (allocated(start)) then
      monitor%mode = start
      monitor%local_start = .true.
    end if
  end subroutine look_at_stiffened

  !> Whether a unit start vector stands as the operator's mode: its measured
  !> residual within the tolerance of its Rayleigh quotient (as
  !> `top_eigenpair` takes a start). One product, kept in `y`; `unit` and
  !> `y` are work kept by the caller (reallocated only when their size is
  !> not the vector's).
  logical function stands(op, vec, tol, unit, y)
    type(assembly_operator_type), intent(inout) :: op
    real(dp), intent(in) :: vec(:), tol
    !> The unit vector, and A' times it (for `operator_critical_steps`' start_av).
    real(dp), allocatable, intent(inout) :: unit(:), y(:)
    real(dp) :: lam, length
    if (allocated(unit)) then
      if (size(unit) /= size(vec)) deallocate(unit)
    end if
    if (.not. allocated(unit)) allocate(unit(size(vec)))
    if (allocated(y)) then
      if (size(y) /= size(vec)) deallocate(y)
    end if
    if (.not. allocated(y)) allocate(y(size(vec)))
    length = norm2(vec)
    stands = length > 0.0_dp
    if (.not. stands) return
    ! (the unit start as `top_eigenpair` makes it: y is its start_av; the
    ! quotient and residual only decide, in vectorised sums)
    unit = vec/length
    call assembly_operator_apply(op, unit, y)
    lam = split_dot(unit, y)
    stands = lam > 0.0_dp .and. residual_norm(y, lam, unit) <= tol*lam
  end function stands

  !> x.y in eight interleaved partial sums: a loop the compiler vectorises
  !> (dot_product's one running sum is a chain of dependent additions, about
  !> three times slower at 18 000 entries). The same value to rounding.
  pure real(dp) function split_dot(x, y) result(d)
    real(dp), intent(in) :: x(:), y(:)
    real(dp) :: s(8)
    integer :: i, m
    s = 0.0_dp
    m = size(x) - mod(size(x), 8)
    do i = 1, m, 8
      s = s + x(i:i + 7)*y(i:i + 7)
    end do
    do i = m + 1, size(x)
      s(1) = s(1) + x(i)*y(i)
    end do
    d = ((s(1) + s(5)) + (s(2) + s(6))) + ((s(3) + s(7)) + (s(4) + s(8)))
  end function split_dot

  !> |y - lam v| in the partial sums of `split_dot`, without a temporary;
  !> norm2 (which scales against overflow and underflow, dividing per entry)
  !> where the sum of squares leaves [1e-280, 1e280].
  pure real(dp) function residual_norm(y, lam, v) result(r)
    real(dp), intent(in) :: y(:), lam, v(:)
    real(dp) :: s(8), q
    integer :: i, m
    s = 0.0_dp
    m = size(y) - mod(size(y), 8)
    do i = 1, m, 8
      s = s + (y(i:i + 7) - lam*v(i:i + 7))**2
    end do
    do i = m + 1, size(y)
      s(1) = s(1) + (y(i) - lam*v(i))**2
    end do
    q = ((s(1) + s(5)) + (s(2) + s(6))) + ((s(3) + s(7)) + (s(4) + s(8)))
    if (q >= 1.0e-280_dp .and. q <= 1.0e280_dp) then
      r = sqrt(q)
    else
      r = norm2(y - lam*v)
    end if
  end function residual_norm

  !> The free bodies within `depth` springs of body b (b first); `place`
  !> (n_bodies entries, all 0 on entry) holds each listed body's position.
  subroutine region_of(op, b, depth, place, bodies)
    type(assembly_operator_type), intent(in) :: op
    integer, intent(in) :: b, depth
    integer, intent(inout) :: place(:)
    integer, allocatable, intent(out) :: bodies(:)
    integer(i8) :: p
    integer :: nb, level, lo, hi, k, i, s, e, j
    allocate(bodies(16))
    nb = 1
    bodies(1) = b
    place(b) = 1
    lo = 1
    do level = 1, depth
      hi = nb
      do k = lo, hi
        i = bodies(k)
        do p = op%first(i), op%first(i + 1) - 1
          s = (op%incident(p) + 1)/2
          e = op%incident(p) - 2*(s - 1)
          j = op%ends(3 - e, s)
          if (j == 0) cycle
          if (place(j) > 0) cycle
          if (nb == size(bodies)) bodies = [bodies, bodies]
          nb = nb + 1
          bodies(nb) = j
          place(j) = nb
        end do
      end do
      lo = hi + 1
    end do
    bodies = bodies(:nb)
  end subroutine region_of

  !> The top of the region within `depth` springs of body b (free bodies
  !> only, the rest held): the largest eigenvalue lam of the principal
  !> submatrix of the operator as it is mixed on `bodies` (b first) and its
  !> unit vector v (nc per listed body). A principal submatrix's: lam <=
  !> lambda_max(A') (Cauchy's interlacing). `place` (n_bodies entries, all
  !> 0) is work, returned all 0.
  subroutine region_top(op, b, depth, identity, place, bodies, lam, v, status)
    type(assembly_operator_type), intent(in) :: op
    integer, intent(in) :: b, depth
    !> 1..n_bodies (`assembly_matrix_rows`' new_index, made once by the caller).
    integer, intent(in) :: identity(:)
    integer, intent(inout) :: place(:)
    integer, allocatable, intent(out) :: bodies(:)
    real(dp), intent(out) :: lam
    real(dp), allocatable, intent(out) :: v(:)
    type(demstep_status_type), intent(out) :: status
    integer(i8), allocatable :: row_start(:)
    integer, allocatable :: col(:)
    real(dp), allocatable :: val(:), a(:, :)
    integer(i8) :: p
    integer :: nb, k, j, nc, m, r, q
    nc = op%nc
    lam = 0.0_dp
    call region_of(op, b, depth, place, bodies)
    nb = size(bodies)
    call assembly_matrix_rows(op, bodies, identity, row_start, col, val, status)
    if (status%stat == demstep_stat%ok) then
      m = nc*nb
      allocate(a(m, m), source=0.0_dp)
      allocate(v(m))
      do r = 1, m
        do p = row_start(r), row_start(r + 1) - 1
          j = (col(p) - 1)/nc + 1
          q = col(p) - (j - 1)*nc
          k = place(j)
          if (k > 0) a(r, (k - 1)*nc + q) = a(r, (k - 1)*nc + q) + val(p)
        end do
      end do
      call largest_eigenpair(a, lam, v, status)
    end if
    place(bodies) = 0
  end subroutine region_top

  !> The update's modes per particle (`mode_particles`, `damped_particles`):
  !> each free body's components times its M'^-1/2 factors (proportional to
  !> the physical displacement and r theta), 0 for fixed particles and absent
  !> components.
  subroutine store_mode(monitor, n)
    class(step_monitor_type), intent(inout) :: monitor
    integer, intent(in) :: n
    call per_particle(monitor%mode, monitor%mode_particles)
    call per_particle(monitor%damped_mode, monitor%damped_particles)
  contains
    subroutine per_particle(mode, particles)
      real(dp), intent(in) :: mode(:)
      real(dp), allocatable, intent(inout) :: particles(:, :)
      integer :: b, c, nc
      if (allocated(particles)) then
        if (size(particles, 2) /= n) deallocate(particles)
      end if
      if (.not. allocated(particles)) allocate(particles(6, n))
      particles = 0.0_dp
      nc = monitor%op%nc
      do b = 1, monitor%op%n_bodies
        do c = 1, nc
          particles(monitor%op%comp(c), monitor%body_particle(b)) = mode((b - 1)*nc + c) &
            *monitor%op%w(monitor%op%comp(c), b)
        end do
      end do
    end subroutine per_particle
  end subroutine store_mode

  !> An ESTIMATE of a settled bed's (damped) limit before any contact exists
  !> (a fresh pour): the exact limit of a generated packing with the solver's
  !> size distribution and contact law (`random_periodic_packing`: n spheres,
  !> radii uniform in r (1 +- polydispersity), jammed at a small overlap, a
  !> periodic cell, linear springs with dashpots 2 zeta sqrt(m* k)). It stands
  !> for the bed the pour will make; a settled frictional bed has fewer
  !> contacts per particle than the jammed packing, so its own limit is
  !> usually at or above this (measured in example/dem_solver). `result`
  !> holds the packing's full report. Status as `random_periodic_packing` and
  !> `assembly_critical_steps`.
  subroutine fresh_pour_estimate(radius, polydispersity, density, k_n, k_t, damping_ratio, &
      tangential_damping_ratio, result, status, n)
    !> Mean radius, relative spread, density of the spheres.
    real(dp), intent(in) :: radius, polydispersity, density
    !> Contact stiffness, normal and tangential; damping ratios normal and tangential.
    real(dp), intent(in) :: k_n, k_t, damping_ratio, tangential_damping_ratio
    type(critical_step_type), intent(out) :: result
    type(demstep_status_type), intent(out) :: status
    !> Particles of the packing (default `fresh_pour_particles`).
    integer, intent(in), optional :: n
    type(scene_type) :: scene
    integer :: np
    np = fresh_pour_particles
    if (present(n)) np = n
    call random_periodic_packing(scene, np, status, radius=radius, polydispersity=polydispersity, &
      density=density, k_normal=k_n, k_tangential=k_t, damping_ratio=damping_ratio)
    if (status%stat /= demstep_stat%ok) return
    if (.not. (ieee_is_finite(tangential_damping_ratio) .and. tangential_damping_ratio >= 0.0_dp)) then
      call set_status(status, demstep_stat%invalid_input, "must be >= 0 and finite", &
        where="tangential_damping_ratio")
      return
    end if
    scene%damping_ratio_tangential = tangential_damping_ratio
    call assembly_critical_steps(scene, result, status)
  end subroutine fresh_pour_estimate

  !> The top mode's share per particle (the squared amplitude of its degrees
  !> of freedom; 0 for fixed particles) and per contact row of `pairs` and per
  !> wall contact (the spring's part of v'A'v over v'A'v; wall contacts summed
  !> per particle into `wall_share`), from the monitor's last update. Each
  !> share is >= 0 up to rounding and each of particle_share and
  !> contact_share + wall_share sums to 1. Status invalid_input naming
  !> `monitor` without an update with an eigensolve.
  subroutine mode_participation(monitor, n_contacts, particle_share, contact_share, wall_share, status)
    class(step_monitor_type), intent(inout) :: monitor
    !> Rows of the contact list given to the update (size of contact_share).
    integer, intent(in) :: n_contacts
    real(dp), allocatable, intent(out) :: particle_share(:), contact_share(:), wall_share(:)
    type(demstep_status_type), intent(out) :: status
    real(dp), allocatable :: spring_share(:)
    integer :: c, s
    if (.not. (monitor%ready .and. monitor%last%eigen_computed)) then
      call set_status(status, demstep_stat%invalid_input, "needs an update with an eigensolver", &
        where="monitor")
      return
    end if
    call mode_shares(monitor%op, monitor%mode, monitor%body_particle, monitor%n_particles, particle_share, &
      spring_share)
    allocate(wall_share(monitor%n_particles), source=0.0_dp)
    allocate(contact_share(n_contacts), source=0.0_dp)
    do s = 1, monitor%op%n_springs
      c = monitor%spring_row(s)
      if (c > 0) then
        if (c <= n_contacts) contact_share(c) = contact_share(c) + spring_share(s)
      else
        wall_share(-c) = wall_share(-c) + spring_share(s)
      end if
    end do
    status%stat = demstep_stat%ok
  end subroutine mode_participation

  !> The shares of a unit mode of an operator (scaled coordinates): per
  !> particle its degrees of freedom's squared amplitude (body b is particle
  !> body_particle(b) of np), per spring its part of v'A'v over v'A'v
  !> (`operator_spring_energies`: one pass of the kernel over the springs).
  subroutine mode_shares(op, mode, body_particle, np, particle_share, spring_share)
    type(assembly_operator_type), intent(inout) :: op
    real(dp), intent(in) :: mode(:)
    integer, intent(in) :: body_particle(:), np
    real(dp), allocatable, intent(out) :: particle_share(:), spring_share(:)
    real(dp) :: total
    integer :: b, s
    allocate(particle_share(np), spring_share(op%n_springs))
    ! (the bodies' and springs' entries in parallel; the totals summed in order)
    !$omp parallel private(b, s) if(np + op%n_springs >= parallel_springs)
    !$omp do schedule(static)
    do b = 1, np
      particle_share(b) = 0.0_dp
    end do
    !$omp end do
    !$omp do schedule(static)
    do s = 1, op%n_springs
      spring_share(s) = 0.0_dp
    end do
    !$omp end do
    !$omp do schedule(static)
    do b = 1, op%n_bodies
      particle_share(body_particle(b)) = sum(mode((b - 1)*op%nc + 1:b*op%nc)**2)
    end do
    !$omp end do
    !$omp end parallel
    total = sum(particle_share)
    if (total > 0.0_dp) call scale_shares(particle_share, total)
    call operator_spring_energies(op, mode, spring_share)
    total = sum(spring_share)
    if (total > 0.0_dp) call scale_shares(spring_share, total)
  end subroutine mode_shares

  !> share = share/total, in parallel.
  subroutine scale_shares(share, total)
    real(dp), intent(inout) :: share(:)
    real(dp), intent(in) :: total
    integer :: i
    !$omp parallel do schedule(static) if(size(share) >= parallel_springs)
    do i = 1, size(share)
      share(i) = share(i)/total
    end do
    !$omp end parallel do
  end subroutine scale_shares

  !> The critical steps of a scene (`assembly_critical_steps`, the same
  !> options) and which particles and springs carry its top undamped mode:
  !> `part%computed` is false when no eigensolver returned a mode (solver
  !> none, or Lanczos out of restarts). One product more than the steps.
  !> Statuses as `assembly_critical_steps`.
  subroutine scene_participation(scene, result, part, status, hertz_mode, impact_velocity, &
      max_eigen_dof, prestress, solver, tolerance, progress)
    type(scene_type), intent(in) :: scene
    type(critical_step_type), intent(out) :: result
    type(participation_type), intent(out) :: part
    type(demstep_status_type), intent(out) :: status
    integer, intent(in), optional :: hertz_mode, max_eigen_dof, solver
    real(dp), intent(in), optional :: impact_velocity, tolerance
    logical, intent(in), optional :: prestress
    class(progress_type), intent(inout), optional :: progress
    real(dp), allocatable :: mode(:)
    type(spring_block_type), allocatable :: springs(:)
    type(assembly_operator_type) :: op
    integer, allocatable :: body_particle(:)
    integer :: i, s
    ! (the solve's own operator: not built again)
    call assembly_critical_steps(scene, result, status, hertz_mode, impact_velocity, max_eigen_dof, &
      prestress, solver, tolerance, progress, mode, springs, op)
    if (status%stat /= demstep_stat%ok) return
    if (size(mode) == 0) return
    allocate(body_particle(count(.not. scene%fixed)))
    s = 0
    do i = 1, scene%n
      if (scene%fixed(i)) cycle
      s = s + 1
      body_particle(s) = i
    end do
    call mode_shares(op, mode, body_particle, scene%n, part%particle_share, part%spring_share)
    allocate(part%spring_a(size(springs)), part%spring_b(size(springs)), part%spring_kind(size(springs)), &
      part%spring_k(2, size(springs)))
    ! (one pass over the springs)
    !$omp parallel do private(s) schedule(static) if(size(springs) >= parallel_springs)
    do s = 1, size(springs)
      part%spring_a(s) = springs(s)%a
      part%spring_b(s) = springs(s)%b
      part%spring_kind(s) = spring_kind_of(springs(s)%a, springs(s)%kind)
      part%spring_k(:, s) = springs(s)%k(1:2)
    end do
    !$omp end parallel do
    part%computed = .true.
  end subroutine scene_participation

  !> The kind of a linearised spring with first end `a` (0: a wall or the
  !> ground) and `spring_block_type%kind` (0: contact, 5: bond, 6: drag to
  !> ground), as an index into `spring_kind_names`.
  elemental integer function spring_kind_of(a, kind) result(k)
    integer, intent(in) :: a, kind
    if (kind == 5) then
      k = 3
    else if (kind == 6) then
      k = 4
    else if (a == 0) then
      k = 2
    else
      k = 1
    end if
  end function spring_kind_of

  !> The indices of the `k` largest shares, largest first (fewer when there
  !> are fewer entries). O(n k).
  pure function top_shares(share, k) result(idx)
    real(dp), intent(in) :: share(:)
    integer, intent(in) :: k
    integer, allocatable :: idx(:)
    integer :: m, i, p, q
    m = min(max(k, 0), size(share))
    allocate(idx(m))
    if (m == 0) return
    p = 0
    do i = 1, size(share)
      if (p < m) then
        p = p + 1
        idx(p) = i
        q = p
      else
        if (.not. share(i) > share(idx(m))) cycle
        idx(m) = i
        q = m
      end if
      ! insertion: idx(1:p) stays in descending order of share
      do while (q > 1)
        if (.not. share(idx(q)) > share(idx(q - 1))) exit
        idx([q - 1, q]) = idx([q, q - 1])
        q = q - 1
      end do
    end do
  end function top_shares

  !> The solver's arrays checked, linearised (`solver_springs`: the monitor's
  !> springs and spring rows) and made the monitor's matrix-free operator
  !> (`operator_from_springs`, its arrays reused where they fit; inertia
  !> default 2/5 m r^2), with its rate.
  subroutine build_operator(monitor, x, mass, radius, pairs, k_n, rotation, status, k_t, c_n, c_t, inertia, &
      fixed, wall_point, wall_normal, wall_k, wall_damping, periodic, cell_lo, cell_hi)
    class(step_monitor_type), intent(inout) :: monitor
    real(dp), intent(in) :: x(:, :), mass(:), radius(:)
    integer, intent(in) :: pairs(:, :)
    real(dp), intent(in) :: k_n(:)
    logical, intent(out) :: rotation
    type(demstep_status_type), intent(out) :: status
    real(dp), intent(in), optional :: k_t(:), c_n(:), c_t(:), inertia(:)
    logical, intent(in), optional :: fixed(:)
    real(dp), intent(in), optional :: wall_point(:, :), wall_normal(:, :), wall_k(:), wall_damping(:)
    logical, intent(in), optional :: periodic(:)
    real(dp), intent(in), optional :: cell_lo(:), cell_hi(:)
    integer :: nfree
    logical :: keep
    monitor%rate = 0.0_dp
    rotation = .false.
    call check_solver_arrays(x, mass, radius, pairs, k_n, status, k_t, c_n, c_t, inertia, fixed, &
      wall_point, wall_normal, wall_k, wall_damping, periodic, cell_lo, cell_hi)
    if (status%stat /= demstep_stat%ok) return
    call solver_springs(monitor, x, mass, radius, pairs, k_n, rotation, status, k_t, c_n, c_t, fixed, &
      wall_point, wall_normal, wall_k, wall_damping, periodic, cell_lo, cell_hi)
    if (status%stat /= demstep_stat%ok) return
    associate(springs => monitor%springs(:monitor%n_springs))
      ! (the bodies' order kept while the particles and free particles are
      ! as many and none it lists is fixed: it then lists the free ones)
      nfree = size(mass)
      if (present(fixed)) nfree = count(.not. fixed)
      if (allocated(monitor%order)) then
        keep = monitor%order_n == size(mass) .and. monitor%order_nfree == nfree
        if (keep .and. present(fixed) .and. size(monitor%order) > 0) keep = .not. any(fixed(monitor%order))
        if (.not. keep) deallocate(monitor%order)
      end if
      if (.not. allocated(monitor%order)) then
        monitor%order = locality_order(x, springs, fixed)
        monitor%order_n = size(mass)
        monitor%order_nfree = nfree
      end if
      if (present(inertia)) then
        call operator_from_springs(size(x, 1), rotation, mass, inertia, radius, springs, .false., monitor%op, &
          monitor%rate, status, fixed, order=monitor%order)
      else
        call operator_from_springs(size(x, 1), rotation, mass, sphere_inertia(mass, radius), radius, springs, &
          .false., monitor%op, monitor%rate, status, fixed, order=monitor%order)
      end if
    end associate
  end subroutine build_operator

  !> Solid spheres' moments of inertia 2/5 m r^2 (as `new_scene`'s default).
  elemental function sphere_inertia(mass, radius) result(inertia)
    real(dp), intent(in) :: mass, radius
    real(dp) :: inertia
    inertia = min(0.4_dp*mass*radius, huge(1.0_dp)/max(1.0_dp, radius))*radius
  end function sphere_inertia

  !> The value of a size-1 (every contact) or per-contact array for contact c.
  pure real(dp) function pick(a, c)
    real(dp), intent(in) :: a(:)
    integer, intent(in) :: c
    pick = a(min(c, size(a)))
  end function pick

  !> x_j - x_i (dim 1 to 3, padded to 3) through the nearest image along the
  !> axes that wrap (periodic, cell lengths box).
  pure function nearest_image(xi, xj, wrap, box) result(d)
    real(dp), intent(in) :: xi(:), xj(:)
    logical, intent(in) :: wrap(3)
    real(dp), intent(in) :: box(3)
    real(dp) :: d(3)
    integer :: ax
    real(dp) :: q
    d = 0.0_dp
    d(:size(xi)) = xj - xi
    do ax = 1, size(xi)
      if (.not. wrap(ax)) cycle
      ! (anint(q) is 0 for |q| < 1/2: the image is taken without rounding then)
      q = d(ax)/box(ax)
      if (abs(q) >= 0.5_dp) d(ax) = d(ax) - box(ax)*anint(q)
    end do
  end function nearest_image

  !> Every refusal of the solver's arrays, by argument name and index.
  subroutine check_solver_arrays(x, mass, radius, pairs, k_n, status, k_t, c_n, c_t, inertia, fixed, &
      wall_point, wall_normal, wall_k, wall_damping, periodic, cell_lo, cell_hi)
    real(dp), intent(in) :: x(:, :), mass(:), radius(:)
    integer, intent(in) :: pairs(:, :)
    real(dp), intent(in) :: k_n(:)
    type(demstep_status_type), intent(out) :: status
    real(dp), intent(in), optional :: k_t(:), c_n(:), c_t(:), inertia(:)
    logical, intent(in), optional :: fixed(:)
    real(dp), intent(in), optional :: wall_point(:, :), wall_normal(:, :), wall_k(:), wall_damping(:)
    logical, intent(in), optional :: periodic(:)
    real(dp), intent(in), optional :: cell_lo(:), cell_hi(:)
    integer :: n, nc, dim, i, c, ax
    n = size(mass)
    nc = size(pairs, 2)
    dim = size(x, 1)
    status%stat = demstep_stat%ok
    if (dim < 1 .or. dim > 3 .or. size(x, 2) /= n) then
      call set_status(status, demstep_stat%invalid_input, "must be (dim, n) with dim 1 to 3 and n = " &
        //"size(mass)", where="x")
      return
    end if
    if (size(radius) /= n) then
      call set_status(status, demstep_stat%invalid_input, "one per particle (size(mass))", where="radius")
      return
    end if
    do i = 1, n
      if (.not. (all(ieee_is_finite(x(:, i))) .and. all(abs(x(:, i)) <= max_value))) then
        call set_status(status, demstep_stat%invalid_input, "must be finite, within +-1e150", &
          where="x", index=i, subscript=.true.)
        return
      end if
      if (.not. (ieee_is_finite(mass(i)) .and. mass(i) > 0.0_dp)) then
        call set_status(status, demstep_stat%invalid_input, "must be > 0 and finite", where="mass", index=i, subscript=.true.)
        return
      end if
      if (.not. ieee_is_finite(1.0_dp/mass(i))) then
        call set_status(status, demstep_stat%invalid_input, "must have a finite inverse", where="mass", index=i, subscript=.true.)
        return
      end if
      if (.not. (ieee_is_finite(radius(i)) .and. radius(i) > 0.0_dp .and. radius(i) <= max_value)) then
        call set_status(status, demstep_stat%invalid_input, "must be > 0, at most 1e150", where="radius", &
          index=i, subscript=.true.)
        return
      end if
    end do
    if (present(inertia)) then
      if (size(inertia) /= n) then
        call set_status(status, demstep_stat%invalid_input, "one per particle", where="inertia")
        return
      end if
      do i = 1, n
        if (.not. (ieee_is_finite(inertia(i)) .and. inertia(i) > 0.0_dp)) then
          call set_status(status, demstep_stat%invalid_input, "must be > 0 and finite", where="inertia", &
            index=i, subscript=.true.)
          return
        end if
      end do
    end if
    if (present(fixed)) then
      if (size(fixed) /= n) then
        call set_status(status, demstep_stat%invalid_input, "one per particle", where="fixed")
        return
      end if
    end if
    if (size(pairs, 1) /= 2) then
      call set_status(status, demstep_stat%invalid_input, "must be (2, number of contacts)", where="pairs")
      return
    end if
    do c = 1, nc
      if (any(pairs(:, c) < 1) .or. any(pairs(:, c) > n)) then
        call set_status(status, demstep_stat%invalid_input, "names a particle outside 1 to size(mass)", &
          where="pairs", index=c, subscript=.true.)
        return
      end if
      if (pairs(1, c) == pairs(2, c)) then
        call set_status(status, demstep_stat%invalid_input, "pairs a particle with itself", where="pairs", &
          index=c, subscript=.true.)
        return
      end if
    end do
    call check_values("k_n", k_n, nc, .true., status)
    if (status%stat /= demstep_stat%ok) return
    if (present(k_t)) call check_values("k_t", k_t, nc, .false., status)
    if (status%stat /= demstep_stat%ok) return
    if (present(c_n)) call check_values("c_n", c_n, nc, .false., status)
    if (status%stat /= demstep_stat%ok) return
    if (present(c_t)) call check_values("c_t", c_t, nc, .false., status)
    if (status%stat /= demstep_stat%ok) return
    if (present(wall_point) .neqv. present(wall_normal)) then
      call set_status(status, demstep_stat%invalid_input, "walls need wall_point and wall_normal", &
        where="wall_normal")
      return
    end if
    if (present(wall_point)) then
      if (size(wall_point, 1) /= dim .or. any(shape(wall_normal) /= shape(wall_point))) then
        call set_status(status, demstep_stat%invalid_input, "must be (dim, walls) as wall_point", &
          where="wall_normal")
        return
      end if
      do i = 1, size(wall_point, 2)
        if (.not. (all(ieee_is_finite(wall_point(:, i))) .and. all(ieee_is_finite(wall_normal(:, i))) &
            .and. norm2(wall_normal(:, i)) > 0.0_dp)) then
          call set_status(status, demstep_stat%invalid_input, "needs a finite point and a finite " &
            //"non-zero normal", where="wall_normal", index=i, subscript=.true.)
          return
        end if
      end do
      if (.not. present(wall_k)) then
        call set_status(status, demstep_stat%invalid_input, "walls need (k_n, k_t)", where="wall_k")
        return
      end if
    end if
    if (present(wall_k)) call check_pair("wall_k", wall_k, "(k_n, k_t)", status)
    if (status%stat /= demstep_stat%ok) return
    if (present(wall_damping)) call check_pair("wall_damping", wall_damping, "(zeta_n, zeta_t)", status)
    if (status%stat /= demstep_stat%ok) return
    if (present(periodic)) then
      if (size(periodic) /= 3 .or. .not. (present(cell_lo) .and. present(cell_hi))) then
        call set_status(status, demstep_stat%invalid_input, "three flags, with cell_lo and cell_hi", &
          where="periodic")
        return
      end if
      if (any(periodic(dim + 1:))) then
        call set_status(status, demstep_stat%invalid_input, "only the first dim axes can be periodic", &
          where="periodic")
        return
      end if
      if (size(cell_lo) /= 3 .or. size(cell_hi) /= 3) then
        call set_status(status, demstep_stat%invalid_input, "three values each for cell_lo and cell_hi", &
          where="cell_hi")
        return
      end if
      do ax = 1, dim
        if (.not. periodic(ax)) cycle
        ! the nearest image must be the only one in contact (as scene_set_cell)
        if (.not. (ieee_is_finite(cell_hi(ax) - cell_lo(ax)) .and. &
            cell_hi(ax) - cell_lo(ax) >= 4.0_dp*maxval(radius) .and. &
            cell_hi(ax) - cell_lo(ax) > 0.0_dp)) then
          call set_status(status, demstep_stat%invalid_input, "the periodic length must be finite and " &
            //"at least twice the longest contact (4 r_max)", where="cell_hi", index=ax, subscript=.true.)
          return
        end if
      end do
    end if
  end subroutine check_solver_arrays

  !> A normal and tangential pair of values (size 2, each >= 0 and finite),
  !> `what` naming them in the refusal.
  subroutine check_pair(name, a, what, status)
    character(len=*), intent(in) :: name, what
    real(dp), intent(in) :: a(:)
    type(demstep_status_type), intent(out) :: status
    if (size(a) /= 2) then
      call set_status(status, demstep_stat%invalid_input, "must be "//what, where=name)
      return
    end if
    call check_values(name, a, 2, .false., status)
  end subroutine check_pair

  !> A size-1 or per-contact array of values >= 0 (> 0 when `positive`), finite.
  subroutine check_values(name, a, nc, positive, status)
    character(len=*), intent(in) :: name
    real(dp), intent(in) :: a(:)
    integer, intent(in) :: nc
    logical, intent(in) :: positive
    type(demstep_status_type), intent(out) :: status
    integer :: c
    status%stat = demstep_stat%ok
    if (size(a) /= 1 .and. size(a) /= nc) then
      call set_status(status, demstep_stat%invalid_input, "one value (every contact) or one per contact", &
        where=name)
      return
    end if
    do c = 1, size(a)
      if (.not. (ieee_is_finite(a(c)) .and. (a(c) > 0.0_dp .or. (.not. positive .and. a(c) >= 0.0_dp)))) then
        if (positive) then
          call set_status(status, demstep_stat%invalid_input, "must be > 0 and finite", where=name, index=c, subscript=.true.)
        else
          call set_status(status, demstep_stat%invalid_input, "must be >= 0 and finite", where=name, index=c, subscript=.true.)
        end if
        return
      end if
    end do
  end subroutine check_values

  !> The linearised springs of the solver's overlapping listed pairs and wall
  !> contacts (as `linearise` makes them for a scene with the same list),
  !> with the contact row (or -particle on a wall) of each: the monitor's
  !> springs(1:n_springs) and spring_row(1:n_springs). O(n walls + nc):
  !> one pass finds the contacts and keeps their geometry, then the springs
  !> are filled from it (the monitor's arrays reallocated only when they are
  !> too small: a solver's contacts change in number at every update).
  subroutine solver_springs(monitor, x, mass, radius, pairs, k_n, rotation, status, k_t, c_n, c_t, &
      fixed, wall_point, wall_normal, wall_k, wall_damping, periodic, cell_lo, cell_hi)
    class(step_monitor_type), intent(inout) :: monitor
    real(dp), intent(in) :: x(:, :), mass(:), radius(:)
    integer, intent(in) :: pairs(:, :)
    real(dp), intent(in) :: k_n(:)
    logical, intent(out) :: rotation
    type(demstep_status_type), intent(out) :: status
    real(dp), intent(in), optional :: k_t(:), c_n(:), c_t(:)
    logical, intent(in), optional :: fixed(:)
    real(dp), intent(in), optional :: wall_point(:, :), wall_normal(:, :), wall_k(:), wall_damping(:)
    logical, intent(in), optional :: periodic(:)
    real(dp), intent(in), optional :: cell_lo(:), cell_hi(:)
    integer :: dim, nc, c, i, j, m, w, n_walls, n_springs, n_pairs, most
    real(dp) :: d(3), box(3), dist, overlap, p(3), nw(3), mi, mj, kw(2), zw(2), xi(3)
    logical :: wrap(3), damped, touching
    ! fixed flags of every particle (none given: none fixed)
    logical, allocatable :: fx(:)
    ! the springs of walls 1 .. w end at wall_end(w)
    integer, allocatable :: wall_end(:)
    dim = size(x, 1)
    nc = size(pairs, 2)
    call solver_options(dim, wrap, box, kw, zw, damped, rotation, k_t, c_n, c_t, wall_k, wall_damping, &
      periodic, cell_lo, cell_hi)
    n_walls = 0
    if (present(wall_point)) n_walls = size(wall_point, 2)
    if (present(fixed)) then
      fx = fixed
    else
      allocate(fx(size(mass)), source=.false.)
    end if
    allocate(wall_end(0:n_walls))
    ! each spring's contact row or -particle (hit), and (d, |d|) or the wall
    ! overlap (geo): the monitor's work, kept between updates
    most = nc + n_walls*size(mass)
    if (allocated(monitor%contact_hit)) then
      if (size(monitor%contact_hit) < most) deallocate(monitor%contact_hit, monitor%contact_geo)
    end if
    if (.not. allocated(monitor%contact_hit)) allocate(monitor%contact_hit(most), monitor%contact_geo(4, most))
    associate(hit => monitor%contact_hit, geo => monitor%contact_geo)
    ! the contacts: overlapping pairs (not both fixed) and wall contacts
    n_springs = 0
    do c = 1, nc
      i = pairs(1, c)
      j = pairs(2, c)
      if (fx(i) .and. fx(j)) cycle
      call pair_geometry(x(:, i), x(:, j), radius(i) + radius(j), wrap, box, d, dist, touching)
      if (.not. touching) cycle
      if (.not. dist > 0.0_dp) then
        call coincident(c, status)
        monitor%n_springs = 0
        return
      end if
      n_springs = n_springs + 1
      hit(n_springs) = c
      geo(1:3, n_springs) = d
      geo(4, n_springs) = dist
    end do
    n_pairs = n_springs
    wall_end(0) = n_springs
    do w = 1, n_walls
      call wall_of(wall_point, wall_normal, w, p, nw)
      do i = 1, size(mass)
        if (fx(i)) cycle
        xi = 0.0_dp
        xi(:dim) = x(:, i)
        overlap = wall_overlap(xi, radius(i), p, nw)
        if (.not. overlap > 0.0_dp) cycle
        n_springs = n_springs + 1
        hit(n_springs) = -i
        geo(1, n_springs) = overlap
      end do
      wall_end(w) = n_springs
    end do
    ! (grown with an eighth to spare: the next updates' counts fit)
    if (allocated(monitor%springs)) then
      if (size(monitor%springs) < n_springs .or. size(monitor%spring_row) /= size(monitor%springs)) &
        deallocate(monitor%springs, monitor%spring_row)
    end if
    if (.not. allocated(monitor%springs)) allocate(monitor%springs(n_springs + n_springs/8), &
      monitor%spring_row(n_springs + n_springs/8))
    monitor%n_springs = n_springs
    associate(springs => monitor%springs, rows => monitor%spring_row)
    do m = 1, n_pairs
      c = hit(m)
      i = pairs(1, c)
      j = pairs(2, c)
      dist = geo(4, m)
      overlap = radius(i) + radius(j) - dist
      mi = huge(1.0_dp)
      mj = huge(1.0_dp)
      if (.not. fx(i)) mi = mass(i)
      if (.not. fx(j)) mj = mass(j)
      springs(m) = spring_block_type(a=i, b=j, n=geo(1:3, m)/dist, arm_a=contact_arm(radius(i), overlap), &
        arm_b=contact_arm(radius(j), overlap), m_eff=reduced_mass(mj, mi))
      springs(m)%k(1) = pick(k_n, c)
      if (present(k_t)) springs(m)%k(2) = pick(k_t, c)
      if (present(c_n)) springs(m)%c(1) = pick(c_n, c)
      if (present(c_t)) springs(m)%c(2) = pick(c_t, c)
      rows(m) = c
    end do
    do w = 1, n_walls
      call wall_of(wall_point, wall_normal, w, p, nw)
      do m = wall_end(w - 1) + 1, wall_end(w)
        i = -hit(m)
        springs(m) = spring_block_type(a=0, b=i, k=[kw(1), kw(2), 0.0_dp, 0.0_dp], n=nw, &
          arm_b=contact_arm(radius(i), geo(1, m)), m_eff=mass(i))
        if (damped) springs(m)%c(1:2) = dashpot_coefficient(zw, mass(i), kw)
        rows(m) = -i
      end do
    end do
    end associate
    end associate
    status%stat = demstep_stat%ok
  end subroutine solver_springs

  !> Wall w's point and unit normal, padded to 3D.
  pure subroutine wall_of(wall_point, wall_normal, w, point, unit)
    real(dp), intent(in) :: wall_point(:, :), wall_normal(:, :)
    integer, intent(in) :: w
    real(dp), intent(out) :: point(3), unit(3)
    point = 0.0_dp
    unit = 0.0_dp
    point(:size(wall_point, 1)) = wall_point(:, w)
    unit(:size(wall_point, 1)) = wall_normal(:, w)/norm2(wall_normal(:, w))
  end subroutine wall_of

  !> What the solver's optional arrays switch on (as `solver_springs` reads
  !> them): the axes that wrap and the cell lengths, the wall stiffness and
  !> damping ratios (0 when not given), whether any dashpot acts, and
  !> whether rotations are degrees of freedom (any tangential stiffness, dim > 1).
  pure subroutine solver_options(dim, wrap, box, kw, zw, damped, rotation, k_t, c_n, c_t, wall_k, &
      wall_damping, periodic, cell_lo, cell_hi)
    integer, intent(in) :: dim
    logical, intent(out) :: wrap(3), damped, rotation
    real(dp), intent(out) :: box(3), kw(2), zw(2)
    real(dp), intent(in), optional :: k_t(:), c_n(:), c_t(:), wall_k(:), wall_damping(:)
    logical, intent(in), optional :: periodic(:)
    real(dp), intent(in), optional :: cell_lo(:), cell_hi(:)
    wrap = .false.
    box = 0.0_dp
    if (present(periodic)) then
      wrap(:dim) = periodic(:dim)
      box = cell_hi - cell_lo
    end if
    kw = 0.0_dp
    if (present(wall_k)) kw = wall_k
    zw = 0.0_dp
    if (present(wall_damping)) zw = wall_damping
    damped = present(c_n) .or. present(c_t) .or. any(zw > 0.0_dp)
    rotation = kw(2) > 0.0_dp
    if (present(k_t)) rotation = rotation .or. any(k_t > 0.0_dp)
    rotation = rotation .and. dim > 1
  end subroutine solver_options

  !> A listed pair: d = x_j - x_i through the nearest image, its length, and
  !> whether the spheres overlap (|d| < reach = r_i + r_j).
  pure subroutine pair_geometry(xi, xj, reach, wrap, box, d, dist, touching)
    real(dp), intent(in) :: xi(:), xj(:), reach
    logical, intent(in) :: wrap(3)
    real(dp), intent(in) :: box(3)
    real(dp), intent(out) :: d(3), dist
    logical, intent(out) :: touching
    d = nearest_image(xi, xj, wrap, box)
    dist = 0.0_dp
    touching = d(1)**2 + d(2)**2 + d(3)**2 < reach**2
    if (touching) dist = norm2(d)
  end subroutine pair_geometry

  !> The refusal of a listed pair whose particles are at the same point.
  pure subroutine coincident(c, status)
    integer, intent(in) :: c
    type(demstep_status_type), intent(out) :: status
    call set_status(status, demstep_stat%invalid_input, "its particles are at the same point (the " &
      //"normal is undefined)", where="pairs", index=c, subscript=.true.)
  end subroutine coincident

end module demstep_monitor
