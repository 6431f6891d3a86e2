!> The stability limit of a whole scene at its current configuration.
!>
!> The scene is linearised with the interaction kernel's tangent blocks
!> (`contact_block`): every bond, particle contact and wall contact couples the
!> translations (and, with the `rotation` effect, the rotations) of its two
!> bodies through its normal and tangential springs with their lever arms;
!> fixed particles and walls are ground. Degrees of freedom per particle: dim
!> translations, plus theta_z in 2D or three rotations in 3D with rotations on.
!> The smallest period of the assembly is 2 pi/omega_max with omega_max^2 the
!> largest eigenvalue of A = M^-1/2 K M^-1/2 (M: masses and moments of inertia),
!> and the undamped central-difference limit is dt = 2/omega_max. Four estimates:
!> - the per-contact rule min 2 sqrt(m*/k): NOT safe, a particle held by several
!>   springs vibrates faster than any one of them;
!> - a rigorous bound: Gershgorin's row sums of |A| bound omega_max^2 from above,
!>   so 2/omega_bound <= the true limit; cost linear in interactions. The
!>   pre-stress of compressed contacts only softens K, so the bound (taken
!>   without it) holds for the integrated system as well;
!> - the exact omega_max from LAPACK (dsyevr, largest eigenpair only);
!> - the damped limit of the lagged dashpot, (2/omega)(sqrt(1 + z^2) - z), with z
!>   the modal damping ratio of the top mode (its eigenvector's Rayleigh quotient
!>   of the dashpot matrix).
!> Hertz contacts are linearised with their tangent stiffness 2 E* sqrt(R* d)
!> (tangential 8 G* sqrt(R* d)), at the current overlap d or at the overlap an
!> impact at a given speed would reach, d = (15 m* v^2 / (16 E* sqrt(R*)))^(2/5).
!> The spring list is counted, allocated once and filled: linear in interactions.
module demstep_assembly
  use demstep_kinds, only: dp, i8, pi
  use demstep_status, only: demstep_status_type, demstep_stat, set_status
  use demstep_text, only: int_text, real_text
  use demstep_spring, only: damped_limit
  use demstep_interaction, only: contact_law, contact_block, contact_product, dashpot_coefficient, &
    normal_stiffness, wall_overlap, reduced_radius, reduced_mass, dof_components
  use demstep_scene_data, only: scene_type, scene_effect, effective_mass, contact_values
  use demstep_neighbours, only: contact_list
  use demstep_stepper, only: max_damping_ratio
  use, intrinsic :: ieee_arithmetic, only: ieee_is_finite
  use demstep_lapack, only: largest_eigenpair
  use demstep_lanczos, only: lanczos_context_type, lanczos_largest, eigen_result_type, &
    csr_matrix_type, csr_to_dense, lanczos_tolerance_default, check_lanczos_options
  use demstep_progress, only: progress_type
  implicit none
  private

  public :: assembly_critical_steps, assembly_step_for_n_per_period, assembly_operator, &
    assembly_operator_apply, assembly_matrix, assembly_matrix_rows, eigen_solver_name, eigen_solver_value, &
    assembly_check_options, assembly_set_bound, assembly_set_estimates, assembly_set_damped, &
    spring_damping

  !> Hertz linearisation at the current overlap, or at an impact's largest
  !> overlap: `hertz_linearization%impact`.
  type, public :: hertz_linearization_enum
    integer :: current = 1
    integer :: impact = 2
  end type hertz_linearization_enum
  !> The Hertz linearisations by name.
  type(hertz_linearization_enum), parameter, public :: hertz_linearization = hertz_linearization_enum()
  !> Largest number of degrees of freedom given to the dense eigensolver by
  !> `eigen_solver%auto` (above it: Lanczos). Measured on random packings: dense
  !> takes 0.01-0.05 s at 600-1200 dof and grows as n^3 (2.4 s at 3900), Lanczos
  !> 1-3 ms there and agrees to 1e-15; dense stays below this for its robustness
  !> on crowded spectra (long chains), where Lanczos may only bracket.
  integer, parameter, public :: default_max_eigen_dof = 1000

  !> Which eigensolver gives the exact omega_max: `eigen_solver%auto` (dense up to
  !> max_eigen_dof, Lanczos above), `%dense` (LAPACK dsyevr), `%lanczos` (ARPACK,
  !> matrix-free), `%none` (the bound only).
  type, public :: eigen_solver_enum
    integer :: auto = 1
    integer :: dense = 2
    integer :: lanczos = 3
    integer :: none = 4
  end type eigen_solver_enum
  !> The eigensolvers by name.
  type(eigen_solver_enum), parameter, public :: eigen_solver = eigen_solver_enum()
  !> Their names, indexed by value.
  character(len=*), parameter, public :: eigen_solver_names(4) = [character(len=7) :: "auto", &
    "dense", "lanczos", "none"]
  !> Krylov size of the scene Lanczos solve: tiled packings have clusters of
  !> nearly equal top eigenvalues, which a larger basis separates in fewer restarts.
  integer, parameter, public :: scene_lanczos_ncv = 16
  !> Restarts of the scene Lanczos solve before it settles for the bracket the
  !> Ritz value and its residual estimate give (`eigen_converged` false).
  integer, parameter, public :: scene_lanczos_restarts = 20
  !> Collatz-Wielandt steps of the bound after Gershgorin's (see operator_bound).
  integer, parameter, public :: bound_iterations = 2
  !> Below this many springs an operator product runs on one thread.
  integer, parameter :: parallel_springs = 4096

  !> The mass-scaled stiffness A' = M'^-1/2 K' M'^-1/2 of a scene as a matrix-free
  !> operator (a Lanczos context): the linearised springs and, per free body, the
  !> springs it touches. A product costs O(springs), never a matrix.
  type, extends(lanczos_context_type), public :: assembly_operator_type
    !> Order (degrees of freedom), dof per free body, free bodies, springs.
    integer :: n = 0, nc = 0, n_bodies = 0, n_springs = 0
    !> The components (of u(1:3), r theta(4:6)) that are degrees of freedom.
    integer, allocatable :: comp(:)
    !> Free-body index of each end of each spring (0: ground, a wall or fixed).
    integer, allocatable :: ends(:, :)
    !> Unit normal and (k_n, k_t, arm_a, arm_b, geo) of each spring, scaled
    !> (stiffness over k_scale, arms over the body's radius).
    real(dp), allocatable :: normal(:, :), coef(:, :)
    !> M'^-1/2 per component (1..6) and free body.
    real(dp), allocatable :: w(:, :)
    !> Spring ends at each free body: entries first(i) .. first(i+1)-1 of
    !> `incident`, each 2(s-1)+e for end e of spring s, in spring order.
    integer(i8), allocatable :: first(:)
    integer, allocatable :: incident(:)
    !> Each spring end's generalised force (6, 2 springs) and each body's scaled
    !> displacement (6, 0:bodies; 0 the ground), filled per product.
    real(dp), allocatable :: work(:, :), xs(:, :)
  end type assembly_operator_type

  !> The four estimates and what they rest on.
  type, public :: critical_step_type
    !> Degrees of freedom (free particles times dof_per_particle) and springs
    !> (bonds + contacts + wall contacts).
    integer :: n_dof = 0, n_springs = 0, dof_per_particle = 0
    !> The model: rotations, tangential springs counted, periodic cell, pre-stress.
    logical :: rotation = .false., tangential = .false., periodic = .false., prestress = .false.
    !> Exact: omega_max and 2/omega_max (0 when not computed).
    real(dp) :: omega_max = 0.0_dp, dt_critical_eigen = 0.0_dp
    logical :: eigen_computed = .false.
    !> Which solver ran (`eigen_solver%dense`, `%lanczos`, or `%none`).
    integer :: solver = 4
    !> The solver's relative tolerance (for Lanczos, residual <= tolerance * omega^2;
    !> dense: the working precision), and the measured relative residual
    !> ||A z - theta z||/theta of the returned mode z (one more product).
    real(dp) :: eigen_tolerance = 0.0_dp, eigen_residual = 0.0_dp
    !> Upper end of omega_max's error bar (from the residual, Weinstein's bound)
    !> and the step safe to it, max(2/omega_upper, dt_critical_bound) <=
    !> dt_critical_eigen.
    real(dp) :: omega_upper = 0.0_dp, dt_critical_safe = 0.0_dp
    !> Whether the residual met the tolerance (false: Lanczos ran out of restarts;
    !> omega_max is then bracketed by [omega_max, omega_upper], wider).
    logical :: eigen_converged = .false.
    !> Operator products and restarts of the Lanczos solve.
    integer(i8) :: eigen_products = 0
    integer :: eigen_restarts = 0
    !> Gershgorin bound: omega_bound >= omega_max, 2/omega_bound <= the limit.
    real(dp) :: omega_bound = 0.0_dp, dt_critical_bound = 0.0_dp
    !> The per-contact rule min 2 sqrt(m*/k) (unsafe).
    real(dp) :: dt_contact_rule = 0.0_dp
    !> Modal damping ratio of the top mode and the damped limit (lagged dashpot).
    real(dp) :: damping_ratio_top = 0.0_dp, dt_critical_damped = 0.0_dp
  end type critical_step_type

  !> A linearised interaction between bodies a and b (a = 0: the ground), n from
  !> a to b; lever arms and the pre-stress F_n/l (0 when not asked for).
  type :: spring_block_type
    integer :: a = 0, b = 0
    real(dp) :: k_n = 0.0_dp, k_t = 0.0_dp, arm_a = 0.0_dp, arm_b = 0.0_dp, geo = 0.0_dp
    real(dp) :: n(3) = 0.0_dp
  end type spring_block_type

contains

  !> The critical time steps of a scene at its current configuration.
  !>
  !> The eigenproblem is solved in scaled units (stiffness over the largest
  !> spring stiffness, masses over the smallest free mass or I/r^2, rotations as
  !> r theta), so any finite stiffness and any mass with a finite inverse give
  !> finite results unless omega_max itself overflows. Whatever solver runs, the
  !> returned mode's residual is measured with one matrix-free product and
  !> reported with the error bar it gives (`omega_upper`, `dt_critical_safe`);
  !> the damped limit is taken at the safe end.
  !> Status invalid_input, the message starting with the variable to change:
  !> `fixed:` (every particle fixed), `effects:` (no bonds and no contact effect),
  !> `position:` (no free particle touches a spring; coincident particles; too
  !> many contacts), `e_star:` (a Hertz stiffness overflows), `damping_ratio:`
  !> (above `max_damping_ratio`, or a damped limit that underflows), `mass:`
  !> (omega_max overflows), `eigen_solver:`, `tolerance:`, bad Hertz options;
  !> lapack_failure; the Lanczos solver's statuses (not_converged names
  !> `tolerance`).
  subroutine assembly_critical_steps(scene, result, status, hertz_mode, impact_velocity, &
      max_eigen_dof, prestress, solver, tolerance, progress)
    type(scene_type), intent(in) :: scene
    type(critical_step_type), intent(out) :: result
    type(demstep_status_type), intent(out) :: status
    !> `hertz_linearization%current` (default) or `%impact` with impact_velocity > 0.
    integer, intent(in), optional :: hertz_mode
    real(dp), intent(in), optional :: impact_velocity
    !> With `eigen_solver%auto`: the largest problem given to the dense solver
    !> (default `default_max_eigen_dof`); Lanczos above.
    integer, intent(in), optional :: max_eigen_dof
    !> Count the pre-stress (geometric) stiffness -(F_n/l)(I - n n^T) of the
    !> loaded contacts (default no).
    logical, intent(in), optional :: prestress
    !> `eigen_solver%auto` (default), `%dense`, `%lanczos` or `%none`.
    integer, intent(in), optional :: solver
    !> The Lanczos relative residual tolerance on omega_max^2, in [2.2e-16, 0.1]
    !> (default `lanczos_tolerance_default`).
    real(dp), intent(in), optional :: tolerance
    !> Reports the Lanczos products.
    class(progress_type), intent(inout), optional :: progress
    type(spring_block_type), allocatable :: springs(:)
    type(assembly_operator_type) :: op
    type(eigen_result_type) :: lanczos
    type(csr_matrix_type) :: sparse
    real(dp), allocatable :: a(:, :), vec(:), av(:)
    real(dp) :: lam, zeta, rate, tol, err
    integer :: limit, i, choice
    logical :: geo, has_mode

    limit = default_max_eigen_dof
    if (present(max_eigen_dof)) limit = max_eigen_dof
    geo = .false.
    if (present(prestress)) geo = prestress
    choice = eigen_solver%auto
    if (present(solver)) choice = solver
    tol = lanczos_tolerance_default
    if (present(tolerance)) tol = tolerance
    if (choice < eigen_solver%auto .or. choice > eigen_solver%none) then
      call set_status(status, demstep_stat%invalid_input, "eigen_solver: must be 'auto', " &
        //"'dense', 'lanczos' or 'none'")
      return
    end if
    call assembly_check_options(scene, tol, zeta, status)
    if (status%stat /= demstep_stat%ok) return
    call prepare(scene, hertz_mode, impact_velocity, geo, springs, op, rate, status)
    if (status%stat /= demstep_stat%ok) return
    result%rotation = scene%effects(scene_effect%rotation) .and. scene%dim > 1
    result%periodic = any(scene%periodic)
    result%prestress = geo
    result%dof_per_particle = op%nc
    result%n_dof = op%n
    result%n_springs = size(springs)
    result%tangential = any(springs%k_t > 0.0_dp)
    ! per-contact rule and the Gershgorin bound (scaled, without pre-stress)
    result%dt_contact_rule = huge(1.0_dp)
    do i = 1, size(springs)
      associate(s => springs(i))
        result%dt_contact_rule = min(result%dt_contact_rule, &
          2.0_dp*sqrt(effective_mass(scene, s%b, s%a))/sqrt(max(s%k_n, s%k_t)))
      end associate
    end do
    call assembly_set_bound(result, rate, operator_bound(op), status)
    if (status%stat /= demstep_stat%ok) return

    ! the exact omega_max: dense LAPACK or matrix-free Lanczos
    if (choice == eigen_solver%auto) then
      choice = eigen_solver%lanczos
      if (result%n_dof <= limit) choice = eigen_solver%dense
    end if
    result%solver = choice
    if (choice /= eigen_solver%none) then
      allocate(vec(result%n_dof))
      has_mode = .true.
      if (choice == eigen_solver%dense) then
        ! the operator's own matrix, dense
        call assembly_matrix(op, sparse)
        call csr_to_dense(sparse, a)
        call largest_eigenpair(a, lam, vec, status)
        if (status%stat /= demstep_stat%ok) return
        deallocate(a)
        result%eigen_tolerance = epsilon(1.0_dp)
        ! the mode's Rayleigh quotient and residual, one matrix-free product
        allocate(av(result%n_dof))
        call assembly_operator_apply(op, vec, av)
        lam = dot_product(vec, av)
        err = norm2(av - lam*vec)
      else
        call lanczos_largest(assembly_operator_apply, op, op%n, lanczos, status, eigenvector=vec, &
          tolerance=tol, ncv=min(scene_lanczos_ncv, op%n), max_restarts=scene_lanczos_restarts, &
          progress=progress)
        result%eigen_products = lanczos%applications
        result%eigen_restarts = lanczos%iterations
        result%eigen_tolerance = tol
        ! the Rayleigh quotient and residual lanczos_largest measured on its
        ! unit mode; out of restarts without a mode (a top crowded with nearly
        ! equal eigenvalues), the Ritz value and ARPACK's estimate of its
        ! residual, which still bracket omega_max, and the nominal damping ratio
        has_mode = any(vec /= 0.0_dp)
        if (status%stat == demstep_stat%not_converged) status%stat = demstep_stat%ok
        if (status%stat /= demstep_stat%ok) return
        lam = lanczos%eigenvalue
        err = lanczos%residual
      end if
      if (scene%effects(scene_effect%damping) .and. has_mode .and. lam > 0.0_dp) then
        zeta = zeta*modal_damping(op, vec)/(2.0_dp*sqrt(lam))
      end if
      call assembly_set_estimates(result, rate, lam, err, choice == eigen_solver%dense .or. &
        (has_mode .and. err <= tol*lam), zeta, status)
    else
      ! no eigensolver: the damped limit from the bound
      call assembly_set_damped(result, result%dt_critical_bound, zeta, status)
    end if
  end subroutine assembly_critical_steps

  !> The options every assembly driver (serial, MPI) checks before it builds
  !> anything: the Lanczos tolerance, and the scene's damping ratio, returned as
  !> `zeta` (0 without the damping effect). Status invalid_input naming
  !> `tolerance` or `damping_ratio`.
  pure subroutine assembly_check_options(scene, tol, zeta, status)
    type(scene_type), intent(in) :: scene
    real(dp), intent(in) :: tol
    real(dp), intent(out) :: zeta
    type(demstep_status_type), intent(out) :: status
    zeta = 0.0_dp
    call check_lanczos_options("tolerance", tol, 1, 2, 1, status)
    if (status%stat /= demstep_stat%ok) then
      status%message = status%message(len("tolerance: ") + 1:)
      return
    end if
    if (scene%effects(scene_effect%damping)) zeta = scene%damping_ratio
    if (.not. (zeta >= 0.0_dp .and. zeta <= max_damping_ratio)) then
      call set_status(status, demstep_stat%invalid_input, "damping_ratio: must be in [0, 1e100]")
    end if
  end subroutine assembly_check_options

  !> The rigorous bound from a bound `row_max` of lambda_max(A') (scaled; a
  !> Collatz-Wielandt quotient of |A'| with its rounding allowance):
  !> omega_bound = rate sqrt(row_max) and its step. Status invalid_input naming
  !> `mass` when it overflows.
  pure subroutine assembly_set_bound(result, rate, row_max, status)
    type(critical_step_type), intent(inout) :: result
    real(dp), intent(in) :: rate, row_max
    type(demstep_status_type), intent(out) :: status
    result%omega_bound = rate*sqrt(row_max)
    if (.not. ieee_is_finite(result%omega_bound)) then
      call set_status(status, demstep_stat%invalid_input, "mass: the bound of omega_max = sqrt(k/m) " &
        //"overflows: the largest stiffness over the smallest mass must stay below about 1e600")
      return
    end if
    result%dt_critical_bound = 2.0_dp/result%omega_bound
    status%stat = demstep_stat%ok
  end subroutine assembly_set_bound

  !> The exact estimates from the top mode's Rayleigh quotient `lam` (scaled) and
  !> residual `err` (measured, or ARPACK's estimate when the solve ran out of
  !> restarts): [lam, lam + err] holds the largest eigenvalue, capped by the
  !> bound (set first); omega = rate sqrt(.); the damped limit at the safe step
  !> with the top mode's damping ratio `zeta`. Status invalid_input naming
  !> `position` (lam <= 0) or `damping_ratio`.
  pure subroutine assembly_set_estimates(result, rate, lam, err, converged, zeta, status)
    type(critical_step_type), intent(inout) :: result
    real(dp), intent(in) :: rate, lam, err, zeta
    !> Whether the residual met the tolerance.
    logical, intent(in) :: converged
    type(demstep_status_type), intent(out) :: status
    if (.not. lam > 0.0_dp) then
      call set_status(status, demstep_stat%invalid_input, "position: the scene has no stiffness")
      return
    end if
    result%eigen_residual = err/lam
    result%eigen_converged = converged
    result%omega_max = rate*sqrt(lam)
    result%omega_upper = min(rate*sqrt(lam + err + 8.0_dp*epsilon(1.0_dp)*lam), result%omega_bound)
    result%dt_critical_eigen = 2.0_dp/result%omega_max
    result%dt_critical_safe = 2.0_dp/result%omega_upper
    result%eigen_computed = .true.
    call assembly_set_damped(result, result%dt_critical_safe, zeta, status)
  end subroutine assembly_set_estimates

  !> The damping ratio `zeta` of the top mode and the damped limit at `dt`.
  !> Status invalid_input naming `damping_ratio` when it is not representable.
  pure subroutine assembly_set_damped(result, dt, zeta, status)
    type(critical_step_type), intent(inout) :: result
    real(dp), intent(in) :: dt, zeta
    type(demstep_status_type), intent(out) :: status
    result%damping_ratio_top = zeta
    result%dt_critical_damped = damped_limit(dt, zeta)
    if (.not. (ieee_is_finite(result%damping_ratio_top) .and. result%dt_critical_damped > 0.0_dp)) then
      call set_status(status, demstep_stat%invalid_input, "damping_ratio: the damped limit " &
        //"dt/(sqrt(1 + z^2) + z) is not representable; use a smaller damping_ratio")
      return
    end if
    status%stat = demstep_stat%ok
  end subroutine assembly_set_damped

  !> r = |A'| v (each entry raised by its rounding allowance) for the operator
  !> without its pre-stress (|A'| the assembled
  !> matrix's absolute values: each body's diagonal block summed over its springs
  !> before they are taken, so the contacts of one body cancel there). Per body,
  !> in parallel, from the kernel (`contact_product`; the columns of the body's
  !> end of each spring are its rows, by symmetry): O(springs), no storage.
  subroutine operator_abs_product(op, v, r)
    type(assembly_operator_type), intent(in) :: op
    !> size n, >= 0.
    real(dp), intent(in) :: v(:)
    real(dp), intent(out) :: r(:)
    real(dp) :: d(6, 6), off(6), col(12, 6), e(12), row
    integer :: i, s, en, o, j, c, q, nc
    integer(i8) :: p
    nc = op%nc
    !$omp parallel do private(i, s, en, o, j, c, q, p, d, off, col, e, row) &
    !$omp schedule(static) if(op%n_springs >= parallel_springs)
    do i = 1, op%n_bodies
      d = 0.0_dp
      off = 0.0_dp
      do p = op%first(i), op%first(i + 1) - 1
        s = (op%incident(p) + 1)/2
        en = op%incident(p) - 2*(s - 1)
        o = 3 - en
        do c = 1, nc
          e = 0.0_dp
          e(6*(en - 1) + op%comp(c)) = 1.0_dp
          call contact_product(op%normal(:, s), op%coef(1, s), op%coef(2, s), op%coef(3, s), &
            op%coef(4, s), 0.0_dp, e(1:3), e(4:6), e(7:9), e(10:12), col(1:3, c), col(4:6, c), &
            col(7:9, c), col(10:12, c))
          d(:, c) = d(:, c) + col(6*(en - 1) + 1:6*en, c)
        end do
        j = op%ends(o, s)
        if (j == 0) cycle
        do c = 1, nc
          do q = 1, nc
            off(c) = off(c) + abs(col(6*(o - 1) + op%comp(q), c))*op%w(op%comp(q), j)*v((j - 1)*nc + q)
          end do
        end do
      end do
      do c = 1, nc
        row = off(c)
        do q = 1, nc
          row = row + abs(d(op%comp(q), c))*op%w(op%comp(q), i)*v((i - 1)*nc + q)
        end do
        ! raised by its rounding: a sum of nc (springs + 1) positive terms,
        ! each product rounded a few times
        r((i - 1)*nc + c) = row*op%w(op%comp(c), i)*(1.0_dp + real(nc*(op%first(i + 1) - op%first(i) &
          + 1) + 4, dp)*epsilon(1.0_dp))
      end do
    end do
    !$omp end parallel do
  end subroutine operator_abs_product

  !> The rigorous bound of omega_max^2 (scaled), without the pre-stress (which
  !> only softens): lambda_max(A') <= rho(|A'|) <= max_i (|A'| v)_i / v_i for any
  !> v > 0 (Collatz-Wielandt). v = 1 gives Gershgorin's row sums; each further
  !> v <- |A'| v (floored at 1e-3 of its largest entry) tightens it towards
  !> rho(|A'|): on random packings dt bound/limit 0.66 with v = 1, 0.74 and 0.77
  !> after one and two steps (one |A'| product each, the cost of the first).
  !> The smallest of the quotients (`assembly_set_bound` adds the rounding).
  function operator_bound(op) result(bound)
    type(assembly_operator_type), intent(in) :: op
    real(dp) :: bound
    real(dp), allocatable :: v(:), r(:)
    integer :: k
    allocate(v(op%n), r(op%n))
    v = 1.0_dp
    bound = huge(1.0_dp)
    do k = 0, bound_iterations
      call operator_abs_product(op, v, r)
      bound = min(bound, maxval(r/v))
      if (.not. maxval(r) > 0.0_dp) exit
      v = max(r/maxval(r), 1.0e-3_dp)
    end do
  end function operator_bound

  !> The name of an `eigen_solver` value ('auto', 'dense', 'lanczos', 'none';
  !> '' for another value).
  pure function eigen_solver_name(solver) result(name)
    integer, intent(in) :: solver
    character(len=:), allocatable :: name
    name = ""
    if (solver >= 1 .and. solver <= size(eigen_solver_names)) name = trim(eigen_solver_names(solver))
  end function eigen_solver_name

  !> The `eigen_solver` value of a name in `eigen_solver_names` (lower case), 0
  !> for another word.
  pure integer function eigen_solver_value(name) result(solver)
    character(len=*), intent(in) :: name
    solver = findloc(eigen_solver_names, trim(name), 1)
  end function eigen_solver_value

  !> The scene's mass-scaled stiffness as a matrix-free operator (see
  !> `assembly_operator_apply`), with `rate`: omega = rate sqrt(lambda) for an
  !> eigenvalue lambda of the operator. Same options and statuses as
  !> `assembly_critical_steps`.
  subroutine assembly_operator(scene, op, rate, status, hertz_mode, impact_velocity, prestress)
    type(scene_type), intent(in) :: scene
    type(assembly_operator_type), intent(out) :: op
    real(dp), intent(out) :: rate
    type(demstep_status_type), intent(out) :: status
    integer, intent(in), optional :: hertz_mode
    real(dp), intent(in), optional :: impact_velocity
    logical, intent(in), optional :: prestress
    type(spring_block_type), allocatable :: springs(:)
    logical :: geo
    geo = .false.
    if (present(prestress)) geo = prestress
    call prepare(scene, hertz_mode, impact_velocity, geo, springs, op, rate, status)
  end subroutine assembly_operator

  !> y = A' x for an `assembly_operator_type` (a `lanczos_operator`): each
  !> spring's generalised forces from the interaction kernel (`contact_product`),
  !> then each body's sum over its springs in spring order. Both loops run in
  !> parallel under OpenMP and every sum has a fixed order: the result is the
  !> same for every thread count, bit for bit. O(springs + dof).
  subroutine assembly_operator_apply(context, x, y)
    class(lanczos_context_type), intent(inout) :: context
    real(dp), intent(in) :: x(:)
    real(dp), intent(out) :: y(:)
    integer :: s, a, b, i, c, nc
    integer(i8) :: p
    real(dp) :: acc(6)
    y = 0.0_dp
    select type (op => context)
    class is (assembly_operator_type)
      nc = op%nc
      ! every body's scaled displacement, six components (0 where not a dof);
      ! column 0 is the ground
      !$omp parallel do private(i, c) schedule(static) if(op%n_springs >= parallel_springs)
      do i = 1, op%n_bodies
        op%xs(:, i) = 0.0_dp
        do c = 1, nc
          op%xs(op%comp(c), i) = x((i - 1)*nc + c)*op%w(op%comp(c), i)
        end do
      end do
      !$omp end parallel do
      !$omp parallel do private(s, a, b) schedule(static) if(op%n_springs >= parallel_springs)
      do s = 1, op%n_springs
        a = op%ends(1, s)
        b = op%ends(2, s)
        call contact_product(op%normal(:, s), op%coef(1, s), op%coef(2, s), op%coef(3, s), &
          op%coef(4, s), op%coef(5, s), op%xs(1:3, a), op%xs(4:6, a), op%xs(1:3, b), op%xs(4:6, b), &
          op%work(1:3, 2*s - 1), op%work(4:6, 2*s - 1), op%work(1:3, 2*s), op%work(4:6, 2*s))
      end do
      !$omp end parallel do
      !$omp parallel do private(i, p, c, acc) schedule(static) if(op%n_springs >= parallel_springs)
      do i = 1, op%n_bodies
        acc = 0.0_dp
        do p = op%first(i), op%first(i + 1) - 1
          acc = acc + op%work(:, op%incident(p))
        end do
        do c = 1, nc
          y((i - 1)*nc + c) = acc(op%comp(c))*op%w(op%comp(c), i)
        end do
      end do
      !$omp end parallel do
    end select
  end subroutine assembly_operator_apply

  !> The operator's matrix A' in compressed rows (each body's diagonal block
  !> once, then one block per spring to another free body; columns may repeat),
  !> e.g. to hand the same problem to another eigensolver. O(springs) entries.
  subroutine assembly_matrix(op, matrix)
    type(assembly_operator_type), intent(in) :: op
    type(csr_matrix_type), intent(out) :: matrix
    type(demstep_status_type) :: status
    integer :: i
    matrix%n = op%n
    ! every body in its own place: the rows cannot be refused
    call assembly_matrix_rows(op, [(i, i = 1, op%n_bodies)], [(i, i = 1, op%n_bodies)], &
      matrix%row_start, matrix%col, matrix%val, status)
  end subroutine assembly_matrix

  !> The rows of A' that belong to a list of free bodies, with the bodies
  !> renumbered (e.g. to give each MPI rank the rows of its region): nc rows per
  !> listed body, in list order; body j's component q is column
  !> (new_index(j) - 1) nc + q. Each body's rows hold its diagonal block, then
  !> one nc x nc block per spring to another free body in `incident` order
  !> (columns may repeat). O(springs of the listed bodies).
  !> Status invalid_input when a listed body is outside 1..n_bodies or
  !> new_index does not map 1..n_bodies into 1..n_bodies.
  subroutine assembly_matrix_rows(op, bodies, new_index, row_start, col, val, status)
    type(assembly_operator_type), intent(in) :: op
    !> Free bodies (operator numbering) whose rows are wanted.
    integer, intent(in) :: bodies(:)
    !> New number of each free body (n_bodies entries).
    integer, intent(in) :: new_index(:)
    !> Row k holds entries row_start(k) .. row_start(k+1)-1 (nc size(bodies) + 1 starts).
    integer(i8), allocatable, intent(out) :: row_start(:)
    !> Column (new numbering) and value of each entry.
    integer, allocatable, intent(out) :: col(:)
    real(dp), allocatable, intent(out) :: val(:)
    type(demstep_status_type), intent(out) :: status
    real(dp) :: b(12, 12), d(6, 6)
    integer :: k, i, s, e, o, j, r, q, nc, row
    integer(i8) :: p, pos, width
    nc = op%nc
    allocate(row_start(nc*size(bodies) + 1))
    row_start(1) = 1
    if (size(new_index) /= op%n_bodies .or. any(bodies < 1 .or. bodies > op%n_bodies) .or. &
        any(new_index < 1 .or. new_index > op%n_bodies)) then
      row_start = 1
      allocate(col(0), val(0))
      call set_status(status, demstep_stat%invalid_input, "bodies, new_index: need free bodies " &
        //"in 1.."//int_text(op%n_bodies)//" and a new number in that range for each")
      return
    end if
    do k = 1, size(bodies)
      i = bodies(k)
      width = nc
      do p = op%first(i), op%first(i + 1) - 1
        s = (op%incident(p) + 1)/2
        e = op%incident(p) - 2*(s - 1)
        if (op%ends(3 - e, s) > 0) width = width + nc
      end do
      do r = 1, nc
        row_start((k - 1)*nc + r + 1) = row_start((k - 1)*nc + r) + width
      end do
    end do
    allocate(col(row_start(size(row_start)) - 1), val(row_start(size(row_start)) - 1))
    do k = 1, size(bodies)
      i = bodies(k)
      row = (k - 1)*nc
      d = 0.0_dp
      ! column offset (within each of the body's rows) of the next block
      pos = nc
      do p = op%first(i), op%first(i + 1) - 1
        s = (op%incident(p) + 1)/2
        e = op%incident(p) - 2*(s - 1)
        b = contact_block(op%normal(:, s), op%coef(1, s), op%coef(2, s), op%coef(3, s), &
          op%coef(4, s), op%coef(5, s))
        d = d + b(6*(e - 1) + 1:6*e, 6*(e - 1) + 1:6*e)
        o = 3 - e
        j = op%ends(o, s)
        if (j == 0) cycle
        do r = 1, nc
          do q = 1, nc
            col(row_start(row + r) + pos + q - 1) = (new_index(j) - 1)*nc + q
            val(row_start(row + r) + pos + q - 1) = b(6*(e - 1) + op%comp(r), 6*(o - 1) + op%comp(q)) &
              *(op%w(op%comp(r), i)*op%w(op%comp(q), j))
          end do
        end do
        pos = pos + nc
      end do
      do r = 1, nc
        do q = 1, nc
          col(row_start(row + r) + q - 1) = (new_index(i) - 1)*nc + q
          val(row_start(row + r) + q - 1) = d(op%comp(r), op%comp(q)) &
            *op%w(op%comp(r), i)*op%w(op%comp(q), i)
        end do
      end do
    end do
    status%stat = demstep_stat%ok
  end subroutine assembly_matrix_rows

  !> The common start of every assembly computation: options checked, degrees
  !> of freedom numbered, scaled masses, the springs linearised and the
  !> matrix-free operator built. O(particles + springs).
  subroutine prepare(scene, hertz_mode, impact_velocity, geo, springs, op, rate, status)
    type(scene_type), intent(in) :: scene
    integer, intent(in), optional :: hertz_mode
    real(dp), intent(in), optional :: impact_velocity
    logical, intent(in) :: geo
    type(spring_block_type), allocatable, intent(out) :: springs(:)
    type(assembly_operator_type), intent(out) :: op
    !> omega = rate sqrt(lambda) for an eigenvalue lambda of the scaled operator
    !> (0 on failure).
    real(dp), intent(out) :: rate
    type(demstep_status_type), intent(out) :: status
    integer, allocatable :: body(:)
    real(dp), allocatable :: mdof(:, :)
    real(dp) :: k_scale, m_scale
    integer :: mode, i, nfree, nc, s, e
    integer(i8) :: p
    real(dp) :: v_impact
    logical :: touches, rotation
    mode = hertz_linearization%current
    if (present(hertz_mode)) mode = hertz_mode
    v_impact = 0.0_dp
    if (present(impact_velocity)) v_impact = impact_velocity
    rate = 0.0_dp
    k_scale = 0.0_dp
    if (mode == hertz_linearization%impact .and. .not. (v_impact > 0.0_dp .and. ieee_is_finite(v_impact))) then
      call set_status(status, demstep_stat%invalid_input, "impact_velocity: the Hertz linearisation " &
        //"at impact needs a finite impact velocity > 0")
      return
    end if
    rotation = scene%effects(scene_effect%rotation) .and. scene%dim > 1
    op%comp = dof_components(scene%dim, rotation)
    nc = size(op%comp)
    op%nc = nc
    ! degrees of freedom: nc per free particle, scaled masses per component
    allocate(body(scene%n), source=0)
    allocate(mdof(6, scene%n), source=1.0_dp)
    nfree = 0
    m_scale = huge(1.0_dp)
    do i = 1, scene%n
      if (scene%fixed(i)) cycle
      nfree = nfree + 1
      body(i) = nfree
      mdof(1:3, i) = scene%mass(i)
      ! a rotation counts as r theta: its mass is I/r^2
      mdof(4:6, i) = (scene%inertia(i)/scene%radius(i))/scene%radius(i)
      m_scale = min(m_scale, minval(mdof(op%comp, i)))
    end do
    op%n_bodies = nfree
    op%n = nfree*nc
    if (nfree == 0) then
      call set_status(status, demstep_stat%invalid_input, "fixed: every particle is fixed: the " &
        //"scene has no stiffness")
      return
    end if
    mdof = mdof/m_scale
    call linearise(scene, mode, v_impact, geo, springs, status)
    if (status%stat /= demstep_stat%ok) return
    touches = .false.
    do i = 1, size(springs)
      if (springs(i)%a > 0) touches = touches .or. .not. scene%fixed(springs(i)%a)
      touches = touches .or. .not. scene%fixed(springs(i)%b)
      k_scale = max(k_scale, springs(i)%k_n, springs(i)%k_t)
    end do
    if (.not. (touches .and. k_scale > 0.0_dp)) then
      if (size(scene%bonds, 2) == 0 .and. .not. (scene%effects(scene_effect%contacts) .or. &
          scene%effects(scene_effect%walls))) then
        call set_status(status, demstep_stat%invalid_input, "effects: the scene has no stiffness: " &
          //"no bonds, and neither 'contacts' nor 'walls' is switched on")
      else
        call set_status(status, demstep_stat%invalid_input, "position: the scene has no stiffness: " &
          //"no free particle touches a bond, a contact or a wall")
      end if
      return
    end if

    ! the operator: scaled springs, and each free body's spring ends in order
    op%n_springs = size(springs)
    allocate(op%ends(2, op%n_springs), op%normal(3, op%n_springs), op%coef(5, op%n_springs))
    allocate(op%w(6, nfree), op%first(nfree + 1), op%work(6, 2*op%n_springs))
    allocate(op%xs(6, 0:nfree), source=0.0_dp)
    do i = 1, scene%n
      if (body(i) > 0) op%w(:, body(i)) = 1.0_dp/sqrt(mdof(:, i))
    end do
    op%first = 0
    do s = 1, op%n_springs
      associate(sp => springs(s))
        op%ends(:, s) = 0
        op%coef(3:4, s) = 0.0_dp
        if (sp%a > 0) then
          op%ends(1, s) = body(sp%a)
          op%coef(3, s) = sp%arm_a/scene%radius(sp%a)
        end if
        op%ends(2, s) = body(sp%b)
        op%coef(4, s) = sp%arm_b/scene%radius(sp%b)
        op%normal(:, s) = sp%n
        op%coef(1, s) = sp%k_n/k_scale
        op%coef(2, s) = sp%k_t/k_scale
        op%coef(5, s) = 0.0_dp
        if (geo) op%coef(5, s) = sp%geo/k_scale
        do e = 1, 2
          if (op%ends(e, s) > 0) op%first(op%ends(e, s) + 1) = op%first(op%ends(e, s) + 1) + 1
        end do
      end associate
    end do
    op%first(1) = 1
    do i = 1, nfree
      op%first(i + 1) = op%first(i + 1) + op%first(i)
    end do
    allocate(op%incident(op%first(nfree + 1) - 1))
    do s = 1, op%n_springs
      do e = 1, 2
        i = op%ends(e, s)
        if (i == 0) cycle
        p = op%first(i)
        op%incident(p) = 2*(s - 1) + e
        op%first(i) = p + 1
      end do
    end do
    ! first(i) now points past body i's entries: shift back
    do i = nfree, 1, -1
      op%first(i + 1) = op%first(i)
    end do
    op%first(1) = 1
    rate = sqrt(k_scale)/sqrt(m_scale)
    status%stat = demstep_stat%ok
  end subroutine prepare

  !> Every interaction of the scene, linearised at the current configuration:
  !> counted, allocated once and filled (linear in interactions).
  subroutine linearise(scene, mode, v_impact, geo, springs, status)
    type(scene_type), intent(in) :: scene
    integer, intent(in) :: mode
    real(dp), intent(in) :: v_impact
    logical, intent(in) :: geo
    type(spring_block_type), allocatable, intent(out) :: springs(:)
    type(demstep_status_type), intent(out) :: status
    integer, allocatable :: pi(:), pj(:), pc(:)
    real(dp), allocatable :: pn(:, :), pd(:)
    integer :: k, i, j, w, m, n_contacts, n_walls
    real(dp) :: overlap, d, f_n, k_n, k_t, rs, l, e_pair
    m = size(scene%bonds, 2)
    n_contacts = 0
    n_walls = 0
    if (scene%effects(scene_effect%contacts)) then
      call contact_list(scene, pi, pj, pn, pd, status, pc)
      if (status%stat /= demstep_stat%ok) return
      do k = 1, size(pi)
        if (.not. (scene%fixed(pi(k)) .and. scene%fixed(pj(k)))) n_contacts = n_contacts + 1
      end do
    end if
    if (scene%effects(scene_effect%walls)) then
      do w = 1, size(scene%wall_normal, 2)
        do i = 1, scene%n
          if (.not. scene%fixed(i) .and. wall_overlap(scene%x(:, i), scene%radius(i), &
            scene%wall_point(:, w), scene%wall_normal(:, w)) > 0.0_dp) n_walls = n_walls + 1
        end do
      end do
    end if
    allocate(springs(m + n_contacts + n_walls))
    do k = 1, m
      springs(k) = spring_block_type(a=scene%bonds(1, k), b=scene%bonds(2, k), k_n=scene%k_bond, &
        k_t=scene%k_bond_tangential, n=scene%bond_normal(:, k))
    end do
    if (scene%effects(scene_effect%contacts)) then
      do k = 1, size(pi)
        i = pi(k)
        j = pj(k)
        if (scene%fixed(i) .and. scene%fixed(j)) cycle
        rs = reduced_radius(scene%radius(i), scene%radius(j))
        ! the pair's E* (per-type materials) or the scene's
        e_pair = scene%e_star
        if (allocated(scene%ptype)) e_pair = scene%pair_law(3, scene%ptype(i), scene%ptype(j))
        d = linearisation_overlap(scene, pc(k), pd(k), rs, effective_mass(scene, i, j), mode, v_impact, e_pair)
        call contact_values(scene, pc(k), i, j, d, f_n, k_n, k_t)
        if (.not. (ieee_is_finite(k_n) .and. ieee_is_finite(k_t))) then
          call stiffness_overflow(i, j)
          return
        end if
        m = m + 1
        springs(m) = spring_block_type(a=i, b=j, k_n=k_n, k_t=k_t, n=pn(:, k), &
          arm_a=scene%radius(i), arm_b=scene%radius(j))
        if (geo) then
          ! F_n at the current overlap over the branch length
          call contact_values(scene, pc(k), i, j, pd(k), f_n, k_n, k_t)
          l = scene%radius(i) + scene%radius(j) - pd(k)
          springs(m)%geo = f_n/l
        end if
      end do
    end if
    if (scene%effects(scene_effect%walls)) then
      do w = 1, size(scene%wall_normal, 2)
        do i = 1, scene%n
          if (scene%fixed(i)) cycle
          overlap = wall_overlap(scene%x(:, i), scene%radius(i), scene%wall_point(:, w), scene%wall_normal(:, w))
          if (.not. overlap > 0.0_dp) cycle
          d = linearisation_overlap(scene, 0, overlap, scene%radius(i), scene%mass(i), mode, v_impact, &
            scene%e_star)
          k_n = normal_stiffness(scene%law, scene%k_normal, scene%e_star, d, scene%radius(i))
          if (.not. ieee_is_finite(k_n)) then
            call stiffness_overflow(i, 0)
            return
          end if
          m = m + 1
          springs(m) = spring_block_type(a=0, b=i, k_n=k_n, k_t=0.0_dp, n=scene%wall_normal(:, w), &
            arm_b=scene%radius(i))
        end do
      end do
    end if
    status%stat = demstep_stat%ok
  contains
    subroutine stiffness_overflow(i, j)
      integer, intent(in) :: i, j
      character(len=:), allocatable :: who
      if (j == 0) then
        who = "particle "//int_text(i)//" on a wall"
      else
        who = "particles "//int_text(i)//" and "//int_text(j)
      end if
      if (mode == hertz_linearization%impact) then
        call set_status(status, demstep_stat%invalid_input, "e_star: the Hertz tangent stiffness " &
          //"2 E* sqrt(R* d) of "//who//" overflows (lower e_star or impact_velocity)")
      else
        call set_status(status, demstep_stat%invalid_input, "e_star: the Hertz tangent stiffness " &
          //"2 E* sqrt(R* d) of "//who//" overflows (lower e_star)")
      end if
    end subroutine stiffness_overflow
  end subroutine linearise

  !> The overlap a contact is linearised at: the current one, or (Hertz, detected
  !> contacts) the largest overlap of an impact at v_impact,
  !> d = (15 m* v^2/(16 E* sqrt(R*)))^(2/5) (through logarithms: no overflow).
  pure real(dp) function linearisation_overlap(scene, c, overlap, rs, m_eff, mode, v_impact, e_star) result(d)
    type(scene_type), intent(in) :: scene
    integer, intent(in) :: c, mode
    !> E* of the pair (per-type materials) or of the scene.
    real(dp), intent(in) :: overlap, rs, m_eff, v_impact, e_star
    d = overlap
    if (c == 0 .and. scene%law == contact_law%hertz .and. mode == hertz_linearization%impact) &
      d = exp(0.4_dp*(log(15.0_dp/16.0_dp) + log(m_eff) + 2.0_dp*log(v_impact) - log(e_star) &
        - 0.5_dp*log(rs)))
  end function linearisation_overlap

  !> The top mode's damping per unit damping ratio, in scaled units: with the
  !> dashpots 2 zeta sqrt(m* k_n) along n and v a unit vector of the scaled
  !> problem, v^T M^-1/2 C M^-1/2 v = zeta sqrt(k_scale/m_scale) times this sum
  !> of `spring_damping` over the springs. O(springs).
  pure real(dp) function modal_damping(op, v) result(q)
    type(assembly_operator_type), intent(in) :: op
    real(dp), intent(in) :: v(:)
    real(dp) :: nu(2)
    integer :: s, e, i, nt
    ! the translations are the first components of a body's dof
    nt = count(op%comp <= 3)
    q = 0.0_dp
    do s = 1, op%n_springs
      nu = 0.0_dp
      do e = 1, 2
        i = op%ends(e, s)
        if (i > 0) nu(e) = dot_product(op%normal(:nt, s), v((i - 1)*op%nc + 1:(i - 1)*op%nc + nt))
      end do
      q = q + spring_damping(op, s, nu)
    end do
  end function modal_damping

  !> One spring's term of `modal_damping`: its dashpot c = 2 sqrt(m* k_n) (scaled,
  !> per unit damping ratio) times the squared rate of its normal stretch,
  !> (w_b n.v_b - w_a n.v_a)^2, from `nu` = n.v at each end (0 at the ground);
  !> the serial and the distributed drivers both sum it.
  pure real(dp) function spring_damping(op, s, nu) result(q)
    type(assembly_operator_type), intent(in) :: op
    integer, intent(in) :: s
    real(dp), intent(in) :: nu(2)
    real(dp) :: m(2), rel
    integer :: e
    rel = 0.0_dp
    m = huge(1.0_dp)
    do e = 1, 2
      if (op%ends(e, s) == 0) cycle
      rel = rel + real(2*e - 3, dp)*nu(e)*op%w(1, op%ends(e, s))
      m(e) = (1.0_dp/op%w(1, op%ends(e, s)))**2
    end do
    q = dashpot_coefficient(1.0_dp, reduced_mass(m(2), m(1)), op%coef(1, s))*rel**2
  end function spring_damping

  !> The time step of a run at `n_per_period` steps per smallest period
  !> 2 pi/omega_max: the exact omega_max when it was computed, else the safe bound
  !> omega_bound (which gives the smaller step). Status invalid_input naming
  !> `n_per_period` when it is not finite and > 0 or the step overflows.
  pure subroutine assembly_step_for_n_per_period(crit, n_per_period, dt, status)
    !> The critical steps of the assembly.
    type(critical_step_type), intent(in) :: crit
    !> Steps per smallest period.
    real(dp), intent(in) :: n_per_period
    !> The time step.
    real(dp), intent(out) :: dt
    type(demstep_status_type), intent(out) :: status
    real(dp) :: omega
    dt = 0.0_dp
    if (.not. (ieee_is_finite(n_per_period) .and. n_per_period > 0.0_dp)) then
      call set_status(status, demstep_stat%invalid_input, "n_per_period: must be finite and > 0")
      return
    end if
    omega = crit%omega_bound
    if (crit%eigen_computed) omega = crit%omega_max
    if (crit%eigen_computed .and. .not. crit%eigen_converged) omega = crit%omega_upper
    dt = 2.0_dp*pi/omega/n_per_period
    if (.not. ieee_is_finite(dt)) then
      dt = 0.0_dp
      call set_status(status, demstep_stat%invalid_input, "n_per_period: the time step 2 pi/(omega_max " &
        //"n_per_period) overflows: n_per_period must be above "// &
        real_text(2.0_dp*pi/crit%omega_bound/huge(1.0_dp)))
      return
    end if
    status%stat = demstep_stat%ok
  end subroutine assembly_step_for_n_per_period

end module demstep_assembly
