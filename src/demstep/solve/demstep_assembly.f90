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
!> - the exact damped limit of the scheme with every dashpot on the lagged
!>   half-step velocity (v' = v - h M^-1 (K x + C v), x' = x + h v'): with K and
!>   C symmetric positive semi-definite an eigenvalue of the one-step map can
!>   leave the unit circle only through -1, so the limit is the smallest h with
!>   lambda_max(h^2 A + 2 h B) = 4, B = M^-1/2 C M^-1/2 (for one spring
!>   (2/omega)(sqrt(1 + z^2) - z)). lambda_max of h^2 A + 2 h B is convex and
!>   increasing in h: Newton's method from the top undamped mode's estimate
!>   (above the root) converges from above, each step one eigensolve of the
!>   same matrix-free operator with mixed coefficients (warm-started); the
!>   reported step is then verified below the root. A warm-started Lanczos
!>   step finds a top near its start, not necessarily lambda_max (a crowded
!>   top, a damped top away from the undamped one): the converged steps are
!>   confirmed by a cold solve (`damped_newton`) whenever the undamped top
!>   had its certificate or a warm start's steps are confirmed. Confirmed so,
!>   with Lanczos: the serial spheres (here), rigid bodies
!>   (demstep_body_assembly) and the MPI paths (mpi/src/demstep_mpi_scene.f90,
!>   demstep_mpi_dist_scene.f90: `mpi_damped_lanczos`, the distributed cold
!>   solve; their undamped top is always certified). C holds the normal,
!>   tangential, rolling and twisting dashpots of contacts and walls, the
!>   bonds' dashpots (normal; a bond model's own four) and the drag to ground. Its rigorous lower bound:
!>   (2/a)(sqrt(1 + z^2) - z) with a^2 >= lambda_max(A), z = b/(2 a) and b >=
!>   lambda_max(B) (the Collatz-Wielandt bound of B).
!> Hertz contacts are linearised with their tangent stiffness 2 E* sqrt(R* d)
!> (tangential 8 G* sqrt(R* d)), at the current overlap d or at the overlap an
!> impact at a given speed would reach, d = (15 m* v^2 / (16 E* sqrt(R*)))^(2/5).
!> The spring list is counted, allocated once and filled: linear in interactions.
module demstep_assembly
  use demstep_kinds, only: dp, i8, pi
  use demstep_status, only: demstep_status_type, demstep_stat, set_status
  use demstep_text, only: int_text, real_text
  use demstep_spring, only: damped_limit
  use demstep_interaction, only: contact_law, contact_block, contact_end_blocks, contact_product, &
    contact_products, contact_products_listed, contact_products_add, mixed_stiffness, dashpot_coefficient, &
    wall_overlap, reduced_radius, dof_components, contact_arm, &
    contact_abs_springs
  use demstep_scene_data, only: scene_type, scene_effect, effective_mass, contact_values, wall_values, &
    contact_dashpots, check_scene_damping
  use demstep_neighbours, only: contact_list, spatial_order
  use demstep_sort, only: bucket_starts
  use demstep_scene_bonds, only: scene_bond_law
  use demstep_bonds, only: bond_law_type
  use, intrinsic :: ieee_arithmetic, only: ieee_is_finite
  use demstep_lapack, only: largest_eigenpair
  use demstep_lanczos, only: lanczos_context_type, lanczos_largest, eigen_result_type, lanczos_operator, &
    lanczos_tolerance_default, check_lanczos_options, krylov_min_order
  use demstep_csr, only: csr_matrix_type, csr_to_dense
  use demstep_progress, only: progress_type
  use demstep_words, only: word_index, word_of
  !$ use omp_lib, only: omp_get_max_threads
  implicit none
  private

  public :: assembly_critical_steps, assembly_step_for_n_per_period, assembly_operator, &
    assembly_operator_apply, assembly_matrix, assembly_matrix_rows, top_eigenpair, cold_top_eigenpair, &
    operator_matrix, &
    assembly_check_options, assembly_set_bound, assembly_set_estimates, assembly_set_damped, &
    damped_lower_bound, dashpot_names, damped_newton, assembly_dashpot_bound, operator_from_springs, &
    operator_critical_steps, operator_mix, assembly_set_springs, linearise, operator_abs_product, &
    dof_masses, collatz_bound, abs_product_operator, operator_bound, operator_set_blocks, operator_spring_energies, &
    operator_products, locality_order

  !> Hertz linearisation at the current overlap, at an impact's largest
  !> overlap (`hertz_linearization%impact`), or at the larger of the two
  !> (`%larger`: a settled contact that may also be struck).
  type, public :: hertz_linearization_enum
    integer :: current = 1
    integer :: impact = 2
    integer :: larger = 3
  end type hertz_linearization_enum
  !> The Hertz linearisations by name.
  type(hertz_linearization_enum), parameter, public :: hertz_linearization = hertz_linearization_enum()
  !> Their words, in code order (`hertz_linearization_from_name`, `hertz_linearization_name`).
  character(len=*), parameter, public :: hertz_linearization_names(3) = [character(len=7) :: "current", "impact", "larger"]
  public :: hertz_linearization_from_name, hertz_linearization_name
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
  public :: eigen_solver_from_name, eigen_solver_name
  !> Their names, indexed by value.
  character(len=*), parameter, public :: eigen_solver_names(4) = [character(len=7) :: "auto", &
    "dense", "lanczos", "none"]
  !> What `dt_critical_safe` rests on: `safe_basis%dense` (the whole spectrum,
  !> LAPACK: the error bar of the top eigenvalue is all), `%randomised` (the
  !> Lanczos certificate: an upper bound of omega_max^2 that fails with a
  !> stated probability; `demstep_lanczos`'s notes), `%bound` (the rigorous
  !> Gershgorin/Collatz bound, lower than the other), `%estimate` (no
  !> certificate: the top found to the tolerance, no claim that none lies
  !> above it).
  type, public :: safe_basis_enum
    integer :: dense = 1
    integer :: randomised = 2
    integer :: bound = 3
    integer :: estimate = 4
  end type safe_basis_enum
  !> The bases by name.
  type(safe_basis_enum), parameter, public :: safe_basis = safe_basis_enum()
  public :: safe_basis_from_name, safe_basis_name, safe_basis_note
  !> Their words, in code order.
  character(len=*), parameter, public :: safe_basis_names(4) = [character(len=10) :: "dense", &
    "randomised", "bound", "estimate"]
  !> Krylov size of the scene Lanczos solve: tiled packings have clusters of
  !> nearly equal top eigenvalues, which a larger basis separates in fewer
  !> restarts (32: a third to a quarter of the products of 16 on tilings of
  !> random packings; the driver doubles it when the restarts run out).
  integer, parameter, public :: scene_lanczos_ncv = 32
  !> Restarts of each ARPACK run of the scene Lanczos solve (at most
  !> `lanczos_runs` runs) before it settles for the bracket the Ritz value and
  !> its residual estimate give (`eigen_converged` false); a single
  !> unrestarted run (`krylov_top`) makes at most this times the Krylov size,
  !> 1280 products (a 1e5-particle tiling, 110 592 particles, converged in 387
  !> steps; denser tops need more).
  integer, parameter, public :: scene_lanczos_restarts = 40
  !> Collatz-Wielandt steps of the bound after Gershgorin's (see operator_bound).
  integer, parameter, public :: bound_iterations = 2
  !> Newton steps of the exact damped limit (it converges in 3 to 6).
  integer, parameter, public :: damped_newton_steps = 40
  !> Cold solves that confirm the damped Newton steps at most (`damped_newton`):
  !> each one that finds a higher top sends the steps on from its mode.
  integer, parameter, public :: damped_confirmations = 3
  !> The dashpots C may hold, as `critical_step_type%dashpots` flags them.
  character(len=*), parameter :: dashpot_names(6) = [character(len=10) :: "normal", "tangential", &
    "rolling", "twisting", "bond", "drag"]
  !> Below this many springs an operator product runs on one thread.
  integer, parameter, public :: parallel_springs = 4096
  !> Springs per call of the product's kernel loop (`contact_products`).
  integer, parameter :: spring_block = 512
  !> Bodies per block of the operator product (`operator_set_blocks`): fixed,
  !> not the thread count's, so that the product's sums have one order. A
  !> block's scaled displacements and sums (2 x 48 bytes a body) stay in a
  !> core's cache while its springs run.
  integer, parameter, public :: product_block_bodies = 2**15
  !> From this many springs `operator_products` makes its products in one
  !> pass (below, one at a time). Measured on one thread (three products, CPU
  !> time): at 66 000 springs the one pass took 3 % longer than the products
  !> one at a time (the spring forces of a product still fit in the cache), at
  !> 354 000 (108 000 spheres) 19 % less.
  integer, parameter, public :: fused_springs = 131072
  !> An operator given the bodies' positions (`operator_from_springs`; a
  !> scene's, by `assembly_critical_steps`) of at least this many free
  !> bodies numbers them in a locality order (`spatial_order`) when more
  !> than `order_crossing` of its springs between free bodies would cross
  !> the product's blocks in the given order (a table in random order:
  !> nearly all; a packing listed region by region: a few per cent).
  integer, parameter, public :: order_min_bodies = product_block_bodies
  real(dp), parameter, public :: order_crossing = 0.25_dp

  !> The mass-scaled stiffness A' = M'^-1/2 K' M'^-1/2 of a scene as a matrix-free
  !> operator (a Lanczos context): the linearised springs and, per free body, the
  !> springs it touches. A product costs O(springs), never a matrix.
  type, extends(lanczos_context_type), public :: assembly_operator_type
    !> Order (degrees of freedom), dof per free body, free bodies, springs.
    integer :: n = 0, nc = 0, n_bodies = 0, n_springs = 0
    !> The components (of u(1:3), r theta(4:6)) that are degrees of freedom.
    integer, allocatable :: comp(:)
    !> Free-body index of each end of each spring (0: ground, a wall or
    !> fixed), in the operator's numbering (`order`).
    integer, allocatable :: ends(:, :)
    !> Where the operator numbers its bodies and springs in a locality order
    !> (`order_min_bodies`; else not allocated: the caller's order): its
    !> body b is the vectors' free body order(b), its spring s the caller's
    !> spring_order(s). Its per-body and per-spring arrays are in its own
    !> numbering; the vectors of products, energies, the matrix and |A'| v
    !> are in the caller's unless `own_vectors` (`assembly_critical_steps`
    !> sets it while it solves: its Lanczos vectors are then in the
    !> operator's numbering, which spares each product a scattered pass
    !> through x and y); spring energies are always by the caller's springs.
    !> `assembly_matrix_rows`' bodies and the monitor's regions take the
    !> operator's own body numbers.
    integer, allocatable :: order(:), spring_order(:)
    logical :: own_vectors = .false.
    !> Unit normal and (k_n, k_t, arm_a, arm_b, geo, k_r, k_w) of each spring,
    !> scaled (stiffness over k_scale, arms over the body's radius), and its
    !> dashpots (c_n, c_t, c_r, c_w) over sqrt(k_scale m_scale) (none: size 0).
    real(dp), allocatable :: normal(:, :), coef(:, :), dcoef(:, :)
    !> 1/r per free body (0: the ground), the rotation scale of r theta.
    real(dp), allocatable :: rinv(:)
    !> The operator is alpha A' + beta B' (B' the scaled dashpots): A' by default.
    real(dp) :: alpha = 1.0_dp, beta = 0.0_dp
    !> M'^-1/2 per component (1..6) and free body.
    real(dp), allocatable :: w(:, :)
    !> Spring ends at each free body: entries first(i) .. first(i+1)-1 of
    !> `incident`, each 2(s-1)+e for end e of spring s, in spring order.
    integer(i8), allocatable :: first(:)
    integer, allocatable :: incident(:)
    !> The product's blocks (`operator_set_blocks`): free bodies in blocks of
    !> block_bodies (block b holds bodies (b-1) block_bodies + 1 ..). A spring
    !> whose free ends lie in one block is interior to it: block b's are
    !> block_springs(block_first(b) .. block_first(b+1)-1), in spring order.
    !> The others cross blocks: cross(:), in spring order; their free ends
    !> at block b's bodies are entries cross_first(b) .. cross_first(b+1)-1
    !> of cross_body (the body) and cross_col (its column of `work`), by
    !> body, then in spring order. (A spring without free ends is in neither.)
    integer :: block_bodies = 0, n_blocks = 0
    integer, allocatable :: block_first(:), block_springs(:), cross(:)
    integer, allocatable :: cross_first(:), cross_body(:), cross_col(:)
    !> Each crossing spring's end forces (6, 2 per entry of `cross`: columns
    !> 2k - 1 and 2k for cross(k)) and each body's scaled displacement
    !> (6, 0:bodies; 0 the ground), filled per product.
    real(dp), allocatable :: work(:, :), xs(:, :)
    !> Work of `operator_products` (each vector's scaled displacements, each
    !> body's sums of the products side by side) and
    !> of the damped limit's start (its vectors and products), kept with the
    !> operator: a monitor's updates reuse them.
    real(dp), allocatable :: many_xs(:, :, :), many_sum(:, :, :), many_x(:, :), many_y(:, :)
  end type assembly_operator_type

  !> The context of `operator_bound`'s absolute products: the operator, its
  !> diagonal blocks' sums (`operator_abs_product`'s dsum) and whether the
  !> first product has made them (pointers: the products get the context
  !> as intent(in)).
  type, extends(lanczos_context_type) :: abs_bound_type
    type(assembly_operator_type), pointer :: op => null()
    real(dp), pointer :: dsum(:, :) => null()
    logical, pointer :: known => null()
  end type abs_bound_type

  !> The four estimates and what they rest on.
  !> (Plain data only: the MPI paths broadcast it as bytes.)
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
    !> What omega_upper (dt_critical_safe) rests on (`safe_basis`), and the
    !> probability that it fails to bound omega_max (`%randomised`; else 0).
    integer :: safe_basis = 4
    real(dp) :: safe_failure = 0.0_dp
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
    !> The damped limit (lagged dashpots): exact (`damped_exact`, verified
    !> below the smallest h with lambda_max(h^2 A + 2 h B) = 4, to the
    !> eigensolver's tolerance) or its rigorous lower bound (no eigensolver);
    !> the damping ratio z of one spring with the same limit,
    !> (2/omega_b)(sqrt(1 + z^2) - z) with omega_b the bracket's upper end (`bracket_omega`;
    !> not the certificate's omega_upper); the rigorous lower bound itself.
    real(dp) :: damping_ratio_top = 0.0_dp, dt_critical_damped = 0.0_dp
    real(dp) :: dt_critical_damped_bound = 0.0_dp
    logical :: damped_exact = .false.
    !> Eigensolves of the damped limit's Newton steps, and how many of them
    !> were cold solves from a random start confirming the converged steps.
    integer :: damped_solves = 0, damped_confirmations = 0
    !> Which dashpots entered C (`dashpot_names`: normal, tangential, rolling,
    !> twisting, bond, drag).
    logical :: dashpots(6) = .false.
  end type critical_step_type

  abstract interface
    !> The matrix of an operator given as a Lanczos context (for the dense
    !> solver of `top_eigenpair`).
    subroutine operator_matrix(context, matrix)
      import :: lanczos_context_type, csr_matrix_type
      class(lanczos_context_type), intent(inout) :: context
      type(csr_matrix_type), intent(out) :: matrix
    end subroutine operator_matrix
    !> r >= |A| v (entrywise absolute values, rounding included) for v >= 0,
    !> of an operator given as a Lanczos context (for `collatz_bound`).
    subroutine abs_product_operator(context, v, r)
      import :: lanczos_context_type, dp
      class(lanczos_context_type), intent(in) :: context
      real(dp), intent(in) :: v(:)
      real(dp), intent(out) :: r(:)
    end subroutine abs_product_operator
  end interface

  !> A damped-limit problem for `damped_newton`: the top eigenpair of
  !> tau^2 A' + 2 tau B' at a given tau (serial or distributed).
  type, abstract, public :: damped_problem_type
    !> Whether the converged Newton steps are confirmed by a cold solve (set
    !> by a problem whose `top` makes one when `cold` is set; see
    !> `damped_newton`), and whether the next `top` is that solve.
    logical :: confirm_cold = .false., cold = .false.
    !> After `damped_newton`: the cold solves made, and whether one found a
    !> top above the warm steps' (the steps then went on from its mode).
    integer :: confirms = 0
    logical :: higher = .false.
  contains
    procedure(damped_top), deferred :: top
  end type damped_problem_type

  abstract interface
    !> The top eigenpair of tau^2 A' + 2 tau B' to the tolerance `tol`: theta,
    !> the Rayleigh quotient of its unit mode v, and err, its error bar
    !> (residual and rounding; [theta, theta + err] holds lambda_max); va =
    !> v'A'v; has_mode false when no mode came back. Counts its solves and
    !> products in `result`.
    subroutine damped_top(problem, tau, tol, theta, err, va, has_mode, result, status, progress)
      import :: damped_problem_type, dp, critical_step_type, demstep_status_type, progress_type
      class(damped_problem_type), intent(inout) :: problem
      !> tau, and the eigensolve's relative tolerance.
      real(dp), intent(in) :: tau, tol
      real(dp), intent(out) :: theta, err, va
      logical, intent(out) :: has_mode
      type(critical_step_type), intent(inout) :: result
      type(demstep_status_type), intent(out) :: status
      class(progress_type), intent(inout), optional :: progress
    end subroutine damped_top
  end interface

  !> The serial damped-limit problem: the scene's operator (mixed per tau),
  !> the eigensolver and the last mode (the next solve's warm start).
  type, extends(damped_problem_type) :: serial_damped_type
    type(assembly_operator_type), pointer :: op => null()
    integer :: choice = 0
    !> Krylov size of the Lanczos solves.
    integer :: ncv = scene_lanczos_ncv
    !> Take the start vector as it is when its own residual meets the
    !> tolerance (see `top_eigenpair`).
    logical :: accept_start = .false.
    !> The least products of a confirmed solve (`top_eigenpair`).
    integer :: confirm_steps = 0
    !> Steps that refine a top by Lanczos (a start tried as it is that does
    !> not stand: the damped top moved; or any later step) have the converged
    !> steps confirmed by a cold solve (`confirm_cold` is set then).
    logical :: confirm_refined = .false.
    real(dp), allocatable :: vec(:)
    !> A' vec and B' vec when known (`cached`): the first solve's start is
    !> then tried without a product.
    real(dp), allocatable :: av(:), bv(:)
    logical :: cached = .false.
    !> The other warm start (the undamped mode or the previous damped one):
    !> the first confirmed solve starts from both.
    real(dp), allocatable :: other(:)
  contains
    procedure :: top => serial_damped_top
  end type serial_damped_type

  !> A linearised interaction between bodies a and b (a = 0: the ground), n from
  !> a to b; lever arms and the pre-stress F_n/l (0 when not asked for).
  !> (Public for the solver-facing builders of `demstep_monitor`.)
  type, public :: spring_block_type
    integer :: a = 0, b = 0
    !> The pair's reduced mass m* (for the per-contact rule).
    real(dp) :: m_eff = 0.0_dp
    !> (k_n, k_t, k_r, k_w) and the dashpots (c_n, c_t, c_r, c_w).
    real(dp) :: k(4) = 0.0_dp, c(4) = 0.0_dp
    real(dp) :: arm_a = 0.0_dp, arm_b = 0.0_dp, geo = 0.0_dp
    real(dp) :: n(3) = 0.0_dp
    !> Which entry of `dashpot_names` a bond (5) or drag (6) spring is (0: contact).
    integer :: kind = 0
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
      max_eigen_dof, prestress, solver, tolerance, progress, mode, springs_out, operator_out)
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
    !> The top undamped unit mode in the operator's scaled coordinates (nc
    !> per free particle, `dof_components`; size 0 when no eigensolver
    !> returned one) and the linearised springs it was computed with (e.g.
    !> for `scene_participation`).
    real(dp), allocatable, intent(out), optional :: mode(:)
    type(spring_block_type), allocatable, intent(out), optional :: springs_out(:)
    !> The operator the steps were computed on (A' unmixed: alpha 1, beta 0),
    !> e.g. for `scene_participation`'s shares without building it again.
    type(assembly_operator_type), intent(out), target, optional :: operator_out
    type(spring_block_type), allocatable :: springs(:)
    type(assembly_operator_type), target :: op_here
    logical :: built
    real(dp), allocatable :: vec(:), vec_out(:)
    real(dp) :: rate, tol
    integer :: limit, choice
    logical :: geo

    limit = default_max_eigen_dof
    if (present(max_eigen_dof)) limit = max_eigen_dof
    geo = .false.
    if (present(prestress)) geo = prestress
    choice = eigen_solver%auto
    if (present(solver)) choice = solver
    tol = lanczos_tolerance_default
    if (present(tolerance)) tol = tolerance
    if (choice < eigen_solver%auto .or. choice > eigen_solver%none) then
      call set_status(status, demstep_stat%invalid_input, "must be 'auto', " &
        //"'dense', 'lanczos' or 'none'", where="eigen_solver")
      return
    end if
    call assembly_check_options(scene, tol, status)
    if (status%stat /= demstep_stat%ok) return
    built = .false.
    if (present(operator_out)) then
      call steps_on(operator_out)
    else
      call steps_on(op_here)
    end if
    if (.not. built) return
    if (present(mode)) then
      if (status%stat == demstep_stat%ok .and. result%eigen_computed .and. any(vec /= 0.0_dp)) then
        call move_alloc(vec, mode)
      else
        allocate(mode(0))
      end if
    end if
    if (present(springs_out)) call move_alloc(springs, springs_out)
  contains
    !> Build the operator into `op` and compute the steps on it.
    subroutine steps_on(op)
      type(assembly_operator_type), intent(inout), target :: op
      call prepare(scene, hertz_mode, impact_velocity, geo, springs, op, rate, status, position=scene%x)
      if (status%stat /= demstep_stat%ok) return
      built = .true.
      result%rotation = scene%effects(scene_effect%rotation) .and. scene%dim > 1
      result%periodic = any(scene%periodic)
      allocate(vec(op%n), source=0.0_dp)
      ! (the solves in the operator's own numbering, from a cold start; the
      ! mode back in the scene's)
      op%own_vectors = allocated(op%order)
      call operator_critical_steps(op, springs, rate, geo, choice, limit, tol, vec, result, status, progress)
      if (op%own_vectors) then
        op%own_vectors = .false.
        allocate(vec_out(op%n))
        call reorder_vector(op, vec, vec_out, .false.)
        call move_alloc(vec_out, vec)
      end if
      call operator_mix(op, 1.0_dp, 0.0_dp)
    end subroutine steps_on
  end subroutine assembly_critical_steps

  !> The estimates of `assembly_critical_steps` from a built operator and its
  !> springs (`prepare`, or a solver's own arrays): the per-contact rule, the
  !> bound, the exact top eigenpair (Lanczos warm-started from `vec` when it is
  !> non-zero; the undamped unit mode on return) and the damped limit. The
  !> caller sets result%rotation and result%periodic. A monitor may give
  !> rigorous bounds of its own (`bounds` = (a, b) >= (lambda_max(A'),
  !> lambda_max(B')), scaled: the Collatz-Wielandt bound is then not
  !> computed), the Krylov size `ncv`, and `damped_vec`: the damped Newton
  !> steps start from it when it is non-zero (its own quadratic's root lies at
  !> or above the damped root as any vector's does) and it returns their last
  !> mode. With `accept_start` (the undamped solve) and `accept_damped` (the
  !> damped Newton steps), a warm start whose own residual already meets the
  !> tolerance is taken as it is (`top_eigenpair`): one product instead of a
  !> Lanczos solve. `start_av` (A' times the unit start, measured by the
  !> caller) spares that product, and the damped quotients' A' product when
  !> the start is taken. `in_place`: when the undamped start was re-solved
  !> by Lanczos and the mode found overlaps it by at least this (|cosine|),
  !> the top stayed where it was and the damped start is tried as it is, as
  !> with `accept_damped`; when a start refined without confirmation (an
  !> `accept_start` whose residual failed) moved, the undamped solve is made
  !> again with its confirmation run, and the damped Newton steps confirm
  !> theirs. With dashpots, a warm start and no certificate, the confirmation
  !> is the damped limit's (`confirm_steps`): the undamped top refined from
  !> its start plus a random one with no least length, the damped start tried
  !> as it is, the converged damped steps confirmed by a cold solve (the
  !> damped floor meanwhile the rigorous bound's); a cold solve that finds a
  !> higher damped top sends the undamped solve on, confirmed, then the damped
  !> steps. `certify` (default true) false: no randomised Lanczos
  !> certificate (a monitor's warm updates: `safe_basis%estimate`).
  subroutine operator_critical_steps(op, springs, rate, geo, choice, limit, tol, vec, result, status, progress, &
      bounds, ncv, damped_vec, accept_start, accept_damped, certify, start_av, in_place, confirm_steps, &
      confirmed)
    type(assembly_operator_type), intent(inout), target :: op
    type(spring_block_type), intent(in) :: springs(:)
    !> omega = rate sqrt(lambda); whether the pre-stress is counted.
    real(dp), intent(in) :: rate
    logical, intent(in) :: geo
    !> The eigensolver (`eigen_solver%...`), auto's dense limit, the tolerance.
    integer, intent(in) :: choice, limit
    real(dp), intent(in) :: tol
    !> Warm start (size op%n; zero: none), then the top undamped unit mode.
    real(dp), intent(inout) :: vec(:)
    type(critical_step_type), intent(inout) :: result
    type(demstep_status_type), intent(out) :: status
    class(progress_type), intent(inout), optional :: progress
    real(dp), intent(in), optional :: bounds(2)
    integer, intent(in), optional :: ncv
    real(dp), intent(inout), optional :: damped_vec(:)
    logical, intent(in), optional :: accept_start, accept_damped, certify
    real(dp), intent(in), optional :: start_av(:)
    real(dp), intent(in), optional :: in_place
    !> The least products of a confirmed Lanczos solve from a warm start (the
    !> undamped one, and the damped Newton steps' where no cold solve confirms
    !> them; default 0). With dashpots the cold solve stands for them (above).
    integer, intent(in), optional :: confirm_steps
    !> Whether the undamped top was confirmed: made by a Lanczos solve with its
    !> confirmation run, or, with dashpots when that run was deferred, by the
    !> damped limit's cold solve (the damped top is then what is confirmed:
    !> the cold solve on the operator the step is held against found no top
    !> above the warm steps', and the undamped mode stands with it).
    logical, intent(out), optional :: confirmed
    real(dp) :: lam, err, b_bound, lower, upper, failure
    real(dp), allocatable :: start(:)
    integer :: i, solver, basis
    logical :: has_mode, converged, certified, taken, damped_taken, refine, moved, known, cold, defer, higher, &
      may_defer
    integer :: damped_steps, confirms, undamped_steps
    status%stat = demstep_stat%ok
    if (present(confirmed)) confirmed = .false.
    result%prestress = geo
    result%dof_per_particle = op%nc
    result%n_dof = op%n
    call assembly_set_springs(result, springs)
    ! the Gershgorin bound (scaled, without pre-stress)
    if (present(bounds)) then
      call assembly_set_bound(result, rate, bounds(1), status)
      b_bound = bounds(2)
    else
      call assembly_set_bound(result, rate, operator_bound(op), status)
      b_bound = assembly_dashpot_bound(op)
    end if
    if (status%stat /= demstep_stat%ok) return

    ! the exact omega_max: dense LAPACK or matrix-free Lanczos
    solver = choice
    if (solver == eigen_solver%auto) then
      solver = eigen_solver%lanczos
      if (result%n_dof <= limit) solver = eigen_solver%dense
    end if
    result%solver = solver
    if (solver /= eigen_solver%none) then
      ! (warm start from vec when the caller gives one)
      ! (with pre-stress A' may be indefinite: its spectrum lies above minus
      ! the bound, which shifts the certificate's operator)
      lower = 0.0_dp
      if (geo) lower = -(result%omega_bound/rate)**2
      ! (a dense solve's bracket end costs nothing: always given)
      certified = .true.
      if (present(certify)) certified = certify .or. solver == eigen_solver%dense
      ! (the start, to tell whether the top stayed in place)
      if (present(in_place)) start = vec
      refine = .false.
      if (present(accept_start)) refine = accept_start
      ! with dashpots, a warm start's confirmation is the damped limit's cold
      ! solve (on the operator the step is held against, at least the
      ! certificate's products from a random start): the undamped start is
      ! taken as it is or refined from itself, and when that cold solve finds
      ! a damped top above the warm steps' the undamped solve is made again
      ! with its own confirmation run (after the damped steps)
      may_defer = .false.
      if (present(confirm_steps) .and. b_bound > 0.0_dp .and. solver == eigen_solver%lanczos .and. &
        .not. certified) may_defer = confirm_steps > 0 .and. any(vec /= 0.0_dp)
      defer = may_defer .and. .not. refine
      undamped_steps = 0
      if (present(confirm_steps) .and. .not. defer) undamped_steps = confirm_steps
      call solve_top(refine)
      if (status%stat /= demstep_stat%ok) return
      ! a start re-solved: did the top stay in place (the mode found overlaps
      ! the start by at least in_place)? A refinement (no confirmation) whose
      ! top left its place is solved again with its confirmation run
      moved = .false.
      known = .false.
      if (present(in_place) .and. .not. taken .and. solver /= eigen_solver%dense) then
        known = any(start /= 0.0_dp)
        if (known) moved = abs(dot_product(start, vec))/(norm2(start)*norm2(vec)) < in_place
      end if
      if (moved .and. refine) then
        defer = may_defer
        if (defer) undamped_steps = 0
        call solve_top(.false.)
        if (status%stat /= demstep_stat%ok) return
      end if
      ! (a dense solve is exact: it counts as confirmed)
      if (present(confirmed)) confirmed = solver == eigen_solver%dense .or. (.not. taken .and. &
        (moved .or. .not. refine) .and. .not. defer)
      result%eigen_tolerance = tol
      if (solver == eigen_solver%dense) result%eigen_tolerance = epsilon(1.0_dp)
      call assembly_set_estimates(result, rate, lam, err, converged, b_bound, status, upper, &
        basis, failure)
      if (status%stat /= demstep_stat%ok) return
      if (b_bound > 0.0_dp .and. has_mode) then
        ! (the damped start is tried as it is when asked, or when the top
        ! was re-solved in place)
        damped_taken = defer
        if (present(accept_damped)) damped_taken = damped_taken .or. accept_damped
        if (known) damped_taken = damped_taken .or. .not. moved
        ! (the converged damped steps confirmed by a cold solve when the
        ! undamped top made the certificate, and when a warm start's steps
        ! are to be confirmed: `damped_newton`; the warm steps then make no
        ! confirmation run of their own)
        cold = certified .or. defer
        if (present(confirm_steps)) cold = cold .or. (confirm_steps > 0 .and. .not. damped_taken)
        damped_steps = 0
        if (present(confirm_steps) .and. .not. cold) damped_steps = confirm_steps
        ! (an undamped top not confirmed is no floor for the damped limit: the
        ! rigorous bound's is)
        if (defer) call assembly_set_damped(result, result%dt_critical_bound, b_bound, rate, status)
        if (status%stat /= demstep_stat%ok) return
        call damped_solve()
        if (status%stat /= demstep_stat%ok) return
        if (defer .and. higher) then
          ! the cold solve found a damped top above the warm steps': the top
          ! moved, the undamped solve is made again with its confirmation
          ! run, from its mode and the damped one, then the damped steps
          if (present(damped_vec)) then
            if (size(damped_vec) == op%n) vec = vec + sign(1.0_dp, dot_product(vec, damped_vec))*damped_vec
          end if
          defer = .false.
          taken = .false.
          if (present(confirm_steps)) undamped_steps = confirm_steps
          call solve_top(.false.)
          if (status%stat /= demstep_stat%ok) return
          call assembly_set_estimates(result, rate, lam, err, converged, b_bound, status, upper, basis, failure)
          if (status%stat /= demstep_stat%ok) return
          ! (no mode back, out of restarts: the damped limit stays the floor
          ! assembly_set_estimates set, nothing confirmed)
          if (has_mode) call damped_solve()
          if (status%stat /= demstep_stat%ok) return
          if (present(confirmed)) confirmed = has_mode
        end if
        ! (the damped top confirmed cold stands for the undamped one's
        ! confirmation)
        if (defer .and. present(confirmed)) confirmed = confirms > 0
      end if
    else
      ! no eigensolver: the damped limit's rigorous lower bound from the bound
      result%safe_basis = safe_basis%bound
      call assembly_set_damped(result, result%dt_critical_bound, b_bound, rate, status)
    end if
  contains
    !> The exact damped limit from the undamped mode vec and the damped start.
    subroutine damped_solve()
      logical :: known_av
      known_av = taken .and. present(start_av)
      if (known_av) known_av = size(start_av) == op%n
      if (known_av) then
        call damped_exact(op, solver, tol, rate, vec, result, status, progress, ncv, damped_vec, damped_taken, &
          start_av, damped_steps, confirm_cold=cold, confirms=confirms, higher=higher, confirm_refined=may_defer)
      else
        call damped_exact(op, solver, tol, rate, vec, result, status, progress, ncv, damped_vec, damped_taken, &
          confirm_steps=damped_steps, confirm_cold=cold, confirms=confirms, higher=higher, &
          confirm_refined=may_defer)
      end if
    end subroutine damped_solve

    !> The top eigenpair from vec (taken as it is when `accept` and its
    !> residual meets the tolerance), with the certificate when asked.
    subroutine solve_top(accept)
      logical, intent(in) :: accept
      if (certified) then
        call top_eigenpair(op, assembly_operator_apply, assembly_matrix_of, op%n, solver, tol, vec, lam, err, &
          has_mode, result%eigen_products, result%eigen_restarts, status, progress, ncv, converged, lower, &
          upper, failure, accept, basis, start_av, taken, undamped_steps)
      else
        upper = 0.0_dp
        failure = 0.0_dp
        call top_eigenpair(op, assembly_operator_apply, assembly_matrix_of, op%n, solver, tol, vec, lam, err, &
          has_mode, result%eigen_products, result%eigen_restarts, status, progress, ncv, converged, &
          accept_start=accept, basis=basis, start_av=start_av, taken=taken, confirm_steps=undamped_steps)
      end if
    end subroutine solve_top
  end subroutine operator_critical_steps

  !> What the springs of an operator tell a result: their count (drag
  !> excluded), whether any is tangential, which dashpots C holds, and the
  !> per-contact rule min 2 sqrt(m*/k) over them (m* each spring's `m_eff`).
  subroutine assembly_set_springs(result, springs)
    type(critical_step_type), intent(inout) :: result
    type(spring_block_type), intent(in) :: springs(:)
    integer :: i, n_springs
    real(dp) :: k, t, t_least, rule
    logical :: tangential, dashpots(6)
    ! (one pass over the springs, in parallel: a count, "or"s and a least
    ! value do not depend on the order)
    n_springs = 0
    tangential = .false.
    dashpots = .false.
    rule = huge(1.0_dp)
    ! the least m*/k so far (each thread's own): a spring whose m*/k is above
    ! it by more than rounding (1e-12, against a few ulps in either form)
    ! cannot lower the rule
    t_least = huge(1.0_dp)
    !$omp parallel do private(i, k, t) firstprivate(t_least) reduction(+:n_springs) &
    !$omp reduction(.or.:tangential, dashpots) reduction(min:rule) schedule(static) &
    !$omp if(size(springs) >= parallel_springs)
    do i = 1, size(springs)
      associate(sp => springs(i))
        if (sp%kind /= 6) n_springs = n_springs + 1
        tangential = tangential .or. sp%k(2) > 0.0_dp
        if (sp%kind == 0) then
          dashpots(1:4) = dashpots(1:4) .or. sp%c > 0.0_dp
        else if (sp%kind == 5) then
          dashpots(5) = dashpots(5) .or. any(sp%c > 0.0_dp)
        else if (sp%kind == 6) then
          dashpots(6) = .true.
        end if
        k = max(sp%k(1), sp%k(2))
        if (k > 0.0_dp) then
          t = sp%m_eff/k
          if (.not. t > t_least*(1.0_dp + 1.0e-12_dp)) then
            rule = min(rule, 2.0_dp*sqrt(sp%m_eff)/sqrt(k))
            t_least = min(t_least, t)
          end if
        end if
      end associate
    end do
    !$omp end parallel do
    result%n_springs = n_springs
    result%tangential = tangential
    result%dashpots = dashpots
    result%dt_contact_rule = rule
  end subroutine assembly_set_springs

  !> The options every assembly driver (serial, MPI) checks before it builds
  !> anything: the Lanczos tolerance, and the scene's damping values
  !> (`check_scene_damping`). Status invalid_input naming `tolerance` or the
  !> damping value.
  pure subroutine assembly_check_options(scene, tol, status)
    type(scene_type), intent(in) :: scene
    real(dp), intent(in) :: tol
    type(demstep_status_type), intent(out) :: status
    character(len=:), allocatable :: detail
    call check_lanczos_options("tolerance", tol, 1, 2, 1, status)
    if (status%stat /= demstep_stat%ok) then
      ! here the caller is the tolerance itself: its location and detail
      detail = status%detail
      call set_status(status, demstep_stat%invalid_input, detail, where="tolerance")
      return
    end if
    call check_scene_damping(scene, status)
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
      call set_status(status, demstep_stat%invalid_input, "the bound of omega_max = sqrt(k/m) " &
        //"overflows: the largest stiffness over the smallest mass must stay below about 1e600", where="mass")
      return
    end if
    result%dt_critical_bound = 2.0_dp/result%omega_bound
    status%stat = demstep_stat%ok
  end subroutine assembly_set_bound

  !> The exact estimates from the top mode's Rayleigh quotient `lam` (scaled) and
  !> residual `err` (measured, or ARPACK's estimate when the solve ran out of
  !> restarts): [lam, lam + err] holds the largest eigenvalue, capped by the
  !> bound (set first); omega = rate sqrt(.); and the damped limit's rigorous
  !> lower bound at the safe step from `b_bound` >= lambda_max(B') (scaled
  !> dashpots; 0: undamped). The safe end omega_upper: from `upper` (an upper
  !> bound of lambda_max(A'), scaled) with what it rests on (`basis`, a
  !> `safe_basis` code, and its failure probability) when given, else from
  !> the bracket as `safe_basis%estimate`; the rigorous bound where lower
  !> (`safe_basis%bound`). Status invalid_input naming `position` (lam <= 0)
  !> or `damping_ratio`.
  pure subroutine assembly_set_estimates(result, rate, lam, err, converged, b_bound, status, &
      upper, basis, failure)
    type(critical_step_type), intent(inout) :: result
    real(dp), intent(in) :: rate, lam, err, b_bound
    !> Whether the residual met the tolerance.
    logical, intent(in) :: converged
    type(demstep_status_type), intent(out) :: status
    real(dp), intent(in), optional :: upper
    integer, intent(in), optional :: basis
    real(dp), intent(in), optional :: failure
    real(dp) :: lam_upper
    if (.not. lam > 0.0_dp) then
      call set_status(status, demstep_stat%invalid_input, "the scene has no stiffness", where="position")
      return
    end if
    result%eigen_residual = err/lam
    result%eigen_converged = converged
    result%omega_max = rate*sqrt(lam)
    lam_upper = lam + err + 8.0_dp*epsilon(1.0_dp)*lam
    result%safe_basis = safe_basis%estimate
    result%safe_failure = 0.0_dp
    if (present(upper) .and. present(basis)) then
      if (upper > 0.0_dp) then
        lam_upper = max(lam_upper, upper)
        result%safe_basis = basis
        if (present(failure)) result%safe_failure = failure
      end if
    end if
    result%omega_upper = rate*sqrt(lam_upper)
    if (result%omega_upper >= result%omega_bound) then
      result%omega_upper = result%omega_bound
      result%safe_basis = safe_basis%bound
      result%safe_failure = 0.0_dp
    end if
    result%dt_critical_eigen = 2.0_dp/result%omega_max
    result%dt_critical_safe = 2.0_dp/result%omega_upper
    result%eigen_computed = .true.
    ! the damped limit (and the recommended step) from the bracket's end, as
    ! before the certificate: its margin is the recommendation's, and the
    ! certificate's own margin would only lower every step by up to 1 %
    ! (the same expression as omega_upper's without a certificate: the same
    ! bits when the safe step is the bracket's, as a dense solve's)
    call assembly_set_damped(result, 2.0_dp/min(rate*sqrt(lam + err + 8.0_dp*epsilon(1.0_dp)*lam), &
      result%omega_bound), b_bound, rate, status)
  end subroutine assembly_set_estimates

  !> The upper end of omega_max's bracket (Weinstein: [omega_max^2, omega_max^2
  !> (1 + eigen_residual)] plus 8 ulps, capped by the bound), from which the
  !> damped limit and the recommended step are taken (omega_upper may be the
  !> certificate's, higher).
  pure real(dp) function bracket_omega(result) result(omega)
    type(critical_step_type), intent(in) :: result
    omega = min(result%omega_max*sqrt(1.0_dp + result%eigen_residual + 8.0_dp*epsilon(1.0_dp)), &
      result%omega_bound)
  end function bracket_omega

  !> The damped limit's rigorous lower bound, in scaled time tau = h rate, from
  !> an undamped limit tau_u <= 2/sqrt(lambda_max(A')) and b >= lambda_max(B'):
  !> lambda_max(tau^2 A' + 2 tau B') <= tau^2 (2/tau_u)^2 + 2 tau b = 4 at
  !> tau = tau_u (sqrt(1 + z^2) - z), z = b tau_u/4 (one spring: b = 2 zeta
  !> omega, z = zeta). With tau_u = 2/sqrt(a) and b of one vector's Rayleigh
  !> quotients a, b, it is the root of that vector's t^2 a + 2 t b = 4.
  elemental real(dp) function damped_lower_bound(tau_u, b) result(tau)
    real(dp), intent(in) :: tau_u, b
    tau = damped_limit(tau_u, 0.25_dp*b*tau_u)
  end function damped_lower_bound

  !> The damped limit set to its rigorous lower bound (`damped_lower_bound`)
  !> from an undamped limit dt_u (at or below the exact one) and b >=
  !> lambda_max(B') (scaled; 0: undamped, the limit is dt_u), with the
  !> equivalent damping ratio. Status invalid_input naming `damping_ratio`
  !> when it is not representable.
  pure subroutine assembly_set_damped(result, dt_u, b, rate, status)
    type(critical_step_type), intent(inout) :: result
    real(dp), intent(in) :: dt_u, b, rate
    type(demstep_status_type), intent(out) :: status
    result%damping_ratio_top = 0.25_dp*b*(dt_u*rate)
    result%dt_critical_damped_bound = dt_u
    if (b > 0.0_dp) result%dt_critical_damped_bound = damped_lower_bound(dt_u*rate, b)/rate
    result%dt_critical_damped = result%dt_critical_damped_bound
    result%damped_exact = .false.
    if (.not. (ieee_is_finite(result%damping_ratio_top) .and. result%dt_critical_damped > 0.0_dp)) then
      call set_status(status, demstep_stat%invalid_input, "the damped limit " &
        //"dt/(sqrt(1 + z^2) + z) is not representable; use a smaller damping_ratio", where="damping_ratio")
      return
    end if
    status%stat = demstep_stat%ok
  end subroutine assembly_set_damped

  !> The top eigenpair of an operator (a scene's, rigid bodies') as it is
  !> mixed now: dense (LAPACK on its matrix) or Lanczos (warm-started from `vec` when it is non-zero); the
  !> Rayleigh quotient `lam` of the returned unit mode and its residual `err`
  !> (measured; ARPACK's estimate when Lanczos ran out of restarts without a
  !> mode, `has_mode` false). Products and restarts are added to the counts.
  !> With `accept_start` and a non-zero `vec` (Lanczos only), the start is
  !> tried first: when its own measured residual meets the tolerance it is
  !> the answer (one product; the same error bar as a converged Lanczos
  !> pair, resting on the start being near the top mode, as a monitor's
  !> previous top mode is, without the fresh random start that confirms a
  !> Lanczos solve). When it does not, the Lanczos solve starts from it
  !> and takes its first converged top without a confirmation run.
  !> `start_av` (A times the unit start, when the caller has it) spares the
  !> start's product; `taken` says the start was the answer.
  subroutine top_eigenpair(op, apply, to_matrix, n, choice, tol, vec, lam, err, has_mode, products, &
      restarts, status, progress, ncv, converged, lower, upper, failure, accept_start, basis, start_av, taken, &
      confirm_steps)
    !> The operator (a scene's `assembly_operator_type`, rigid bodies' ...),
    !> its product y = A x, its matrix (module procedures) and its order.
    class(lanczos_context_type), intent(inout) :: op
    procedure(lanczos_operator) :: apply
    procedure(operator_matrix) :: to_matrix
    integer, intent(in) :: n
    integer, intent(in) :: choice
    real(dp), intent(in) :: tol
    real(dp), intent(inout) :: vec(:)
    real(dp), intent(out) :: lam, err
    logical, intent(out) :: has_mode
    integer(i8), intent(inout) :: products
    integer, intent(inout) :: restarts
    type(demstep_status_type), intent(out) :: status
    class(progress_type), intent(inout), optional :: progress
    !> Krylov size of a Lanczos solve (default `scene_lanczos_ncv`).
    integer, intent(in), optional :: ncv
    !> Whether the eigensolve met its tolerance (dense: always; Lanczos: the
    !> residual and its check that the top settled).
    logical, intent(out), optional :: converged
    !> With `upper`: a lower bound of the spectrum (0: semi-definite) and an
    !> upper bound of lambda_max (dense: the bracket's end; Lanczos: the
    !> randomised certificate, 0 when it was not made) with the probability
    !> that it fails.
    real(dp), intent(in), optional :: lower
    real(dp), intent(out), optional :: upper, failure
    logical, intent(in), optional :: accept_start
    !> What `upper` rests on (a `safe_basis` code: dense or randomised).
    integer, intent(out), optional :: basis
    real(dp), intent(in), optional :: start_av(:)
    logical, intent(out), optional :: taken
    !> The least products of a confirmed solve from a warm start (default 0).
    integer, intent(in), optional :: confirm_steps
    type(eigen_result_type) :: lanczos
    type(csr_matrix_type) :: sparse
    real(dp), allocatable :: a(:, :), av(:), start(:)
    integer :: m
    logical :: refine, reuse
    has_mode = .true.
    refine = .false.
    if (present(taken)) taken = .false.
    m = scene_lanczos_ncv
    if (present(ncv)) m = ncv
    if (present(converged)) converged = .true.
    if (present(basis)) basis = merge(safe_basis%dense, safe_basis%randomised, choice == eigen_solver%dense)
    if (choice == eigen_solver%dense) then
      ! the operator's own matrix, dense
      call to_matrix(op, sparse)
      call csr_to_dense(sparse, a)
      call largest_eigenpair(a, lam, vec, status)
      if (status%stat /= demstep_stat%ok) return
      deallocate(a)
      ! the mode's Rayleigh quotient and residual, one matrix-free product
      allocate(av(n))
      call apply(op, vec, av)
      lam = dot_product(vec, av)
      err = norm2(av - lam*vec)
      if (present(upper)) upper = lam + err + 8.0_dp*epsilon(1.0_dp)*abs(lam)
      if (present(failure)) failure = 0.0_dp
    else
      if (present(accept_start)) then
        if (accept_start .and. any(vec /= 0.0_dp)) then
          start = vec/norm2(vec)
          reuse = present(start_av)
          if (reuse) reuse = size(start_av) == n
          if (reuse) then
            lam = dot_product(start, start_av)
            err = norm2(start_av - lam*start)
          else
            allocate(av(n))
            call apply(op, start, av)
            products = products + 1
            lam = dot_product(start, av)
            err = norm2(av - lam*start)
          end if
          refine = .true.
          if (lam > 0.0_dp .and. err <= tol*lam) then
            if (present(taken)) taken = .true.
            vec = start
            ! (no randomised certificate for a start taken as it is)
            if (present(upper)) upper = 0.0_dp
            if (present(failure)) failure = 0.0_dp
            status%stat = demstep_stat%ok
            return
          end if
        end if
      end if
      start = vec
      ! (a start that was to be taken as it is, refined: no confirmation run)
      call lanczos_largest(apply, op, n, lanczos, status, eigenvector=vec, &
        tolerance=tol, ncv=m, max_restarts=scene_lanczos_restarts, &
        progress=progress, start=start, certify=present(upper), lower_bound=lower, confirm=.not. refine, &
        confirm_steps=confirm_steps)
      if (present(upper)) upper = lanczos%upper_bound
      if (present(failure)) failure = lanczos%failure_probability
      products = products + lanczos%applications
      restarts = restarts + lanczos%iterations
      ! the Rayleigh quotient and residual lanczos_largest measured on its
      ! unit mode; out of restarts without a mode (a top crowded with nearly
      ! equal eigenvalues), the Ritz value and ARPACK's estimate of its
      ! residual, which still bracket omega_max
      has_mode = any(vec /= 0.0_dp)
      if (status%stat == demstep_stat%not_converged) status%stat = demstep_stat%ok
      if (status%stat /= demstep_stat%ok) return
      lam = lanczos%eigenvalue
      err = lanczos%residual
      if (present(converged)) converged = lanczos%converged
    end if
  end subroutine top_eigenpair

  !> The cold solve that confirms converged damped Newton steps
  !> (`damped_newton`): no start (`vec` is set to 0), the run of a cold
  !> certified solve. Above `krylov_min_order` that is `top_eigenpair` with
  !> the certificate (one unrestarted run from a random start of at least
  !> `certificate_steps` products); at or below it, the ARPACK solve with its
  !> confirmation run, whose certificate would be a separate run and is not
  !> asked for. The certificate's bound is not used: the step is taken from
  !> the bracket, as the undamped one's.
  subroutine cold_top_eigenpair(op, apply, to_matrix, n, choice, tol, vec, lam, err, has_mode, products, &
      restarts, status, progress, ncv)
    class(lanczos_context_type), intent(inout) :: op
    procedure(lanczos_operator) :: apply
    procedure(operator_matrix) :: to_matrix
    integer, intent(in) :: n, choice
    real(dp), intent(in) :: tol
    real(dp), intent(inout) :: vec(:)
    real(dp), intent(out) :: lam, err
    logical, intent(out) :: has_mode
    integer(i8), intent(inout) :: products
    integer, intent(inout) :: restarts
    type(demstep_status_type), intent(out) :: status
    class(progress_type), intent(inout), optional :: progress
    integer, intent(in), optional :: ncv
    real(dp) :: upper, failure
    vec = 0.0_dp
    if (n > krylov_min_order) then
      call top_eigenpair(op, apply, to_matrix, n, choice, tol, vec, lam, err, has_mode, products, &
        restarts, status, progress, ncv, lower=0.0_dp, upper=upper, failure=failure)
    else
      call top_eigenpair(op, apply, to_matrix, n, choice, tol, vec, lam, err, has_mode, products, &
        restarts, status, progress, ncv)
    end if
  end subroutine cold_top_eigenpair

  !> The exact damped limit (see the module's notes), in place of the lower
  !> bound when it is larger: `damped_newton` on the serial operator, from the
  !> top undamped unit mode `vec`, or from `start` when it is given non-zero
  !> (then the last damped mode on return); `vec_av` = A' vec when known.
  subroutine damped_exact(op, choice, tol, rate, vec, result, status, progress, ncv, start, accept_start, vec_av, &
      confirm_steps, confirm_cold, confirms, higher, confirm_refined)
    type(assembly_operator_type), intent(inout), target :: op
    integer, intent(in) :: choice
    real(dp), intent(in) :: tol, rate
    real(dp), intent(in) :: vec(:)
    type(critical_step_type), intent(inout) :: result
    type(demstep_status_type), intent(out) :: status
    class(progress_type), intent(inout), optional :: progress
    integer, intent(in), optional :: ncv
    real(dp), intent(inout), optional :: start(:)
    !> Take a Newton step's start as it is when its residual meets `tol`.
    logical, intent(in), optional :: accept_start
    real(dp), intent(in), optional :: vec_av(:)
    !> The least products of a Newton step's confirmed solve (default 0).
    integer, intent(in), optional :: confirm_steps
    !> Confirm the converged Newton steps by a cold solve (`damped_newton`;
    !> default false; a dense solve needs none).
    logical, intent(in), optional :: confirm_cold
    !> The cold solves made, and whether one found a higher top (`damped_newton`).
    integer, intent(out), optional :: confirms
    logical, intent(out), optional :: higher
    !> Confirm the steps by a cold solve when any of them refines its top (the
    !> start tried as it is does not stand; default false).
    logical, intent(in), optional :: confirm_refined
    type(serial_damped_type) :: problem
    ! the undamped mode and the damped start (unit), their A' and B' products
    real(dp), allocatable :: x(:, :), y(:, :), alpha(:), beta(:)
    integer, allocatable :: which(:)
    real(dp) :: lam_a, vb, lam_w, vb_w
    logical :: from_vec, two
    integer :: av, bv, aw, bw, nq
    two = .false.
    if (present(start)) two = size(start) == op%n .and. any(start /= 0.0_dp)
    ! (in the operator's work arrays, kept between calls: taken, then given back)
    call move_alloc(op%many_x, x)
    call move_alloc(op%many_y, y)
    call fit_columns(x, op%n, merge(2, 1, two))
    x(:, 1) = vec
    if (two) x(:, 2) = start/norm2(start)
    ! (the products in one pass, `operator_products`: B' vec and, when not
    ! given, A' vec; A' and B' of the start; columns av, bv, aw, bw of y)
    allocate(which(merge(1, 2, present(vec_av)) + merge(2, 0, two)))
    allocate(alpha(size(which)), beta(size(which)))
    nq = 0
    av = 0
    aw = 0
    bw = 0
    if (.not. present(vec_av)) call add_product(av, 1, 1.0_dp, 0.0_dp)
    call add_product(bv, 1, 0.0_dp, 1.0_dp)
    if (two) then
      call add_product(aw, 2, 1.0_dp, 0.0_dp)
      call add_product(bw, 2, 0.0_dp, 1.0_dp)
    end if
    call fit_columns(y, op%n, size(which))
    call operator_products(op, x(:, :merge(2, 1, two)), which, alpha, beta, y(:, :size(which)))
    ! v'A'v and v'B'v of each
    if (present(vec_av)) then
      lam_a = dot_product(vec, vec_av)
    else
      lam_a = dot_product(vec, y(:, av))
    end if
    vb = dot_product(vec, y(:, bv))
    from_vec = .true.
    if (two) then
      ! the start's quadratic root, when it is the lower (closer) of the two
      lam_w = dot_product(x(:, 2), y(:, aw))
      vb_w = dot_product(x(:, 2), y(:, bw))
      if (lam_w > 0.0_dp) then
        if (damped_lower_bound(2.0_dp/sqrt(lam_w), vb_w) < damped_lower_bound(2.0_dp/sqrt(lam_a), vb)) then
          from_vec = .false.
          problem%av = y(:, aw)
          problem%bv = y(:, bw)
          lam_a = lam_w
          vb = vb_w
          ! (the other start serves only a start not to be taken as it is)
          if (.not. accepting()) problem%other = vec
          problem%vec = x(:, 2)
        else
          if (.not. accepting()) problem%other = x(:, 2)
        end if
      end if
    end if
    if (from_vec) then
      if (present(vec_av)) then
        problem%av = vec_av
      else
        problem%av = y(:, av)
      end if
      problem%bv = y(:, bv)
    end if
    call move_alloc(x, op%many_x)
    call move_alloc(y, op%many_y)
    if (from_vec) problem%vec = vec
    problem%cached = .true.
    problem%op => op
    problem%choice = choice
    if (present(ncv)) problem%ncv = ncv
    if (present(accept_start)) problem%accept_start = accept_start
    if (present(confirm_steps)) problem%confirm_steps = confirm_steps
    if (present(confirm_cold)) problem%confirm_cold = confirm_cold .and. choice /= eigen_solver%dense
    if (present(confirm_refined)) problem%confirm_refined = confirm_refined .and. choice /= eigen_solver%dense
    call damped_newton(problem, lam_a, vb, rate, tol, result, status, progress)
    if (present(confirms)) confirms = problem%confirms
    if (present(higher)) higher = problem%higher
    call operator_mix(op, 1.0_dp, 0.0_dp)
    if (present(start)) then
      if (size(start) == op%n) start = problem%vec
    end if
  contains
    !> The next product (of x(:, vector), as alpha A' + beta B'): its column
    !> of y.
    subroutine add_product(column, vector, a, b)
      integer, intent(out) :: column
      integer, intent(in) :: vector
      real(dp), intent(in) :: a, b
      nq = nq + 1
      which(nq) = vector
      alpha(nq) = a
      beta(nq) = b
      column = nq
    end subroutine add_product
    !> Whether a Newton step's start is taken as it is when it stands.
    logical function accepting()
      accepting = .false.
      if (present(accept_start)) accepting = accept_start
    end function accepting
  end subroutine damped_exact

  !> The root of lambda(tau) = lambda_max(tau^2 A' + 2 tau B') = 4 (tau = h
  !> rate) for any `damped_problem_type`, from the top undamped mode's
  !> estimate (its Rayleigh quotients lam_a of A' and vb of B' put lambda at
  !> or above 4 there). Each step takes the root of the current top mode's own
  !> quadratic t^2 v'A'v + 2 t v'B'v, which equals lambda and its slope at the
  !> current tau and lies below lambda elsewhere (lambda is a maximum of such
  !> quadratics): the steps come down to the root from above, quadratically,
  !> as Newton's do. Each evaluated tau gives a safe step at once:
  !> lambda(tau)/tau = lambda_max(tau A' + 2 B') does not decrease with tau,
  !> so lambda(s) <= U s/tau for s <= tau and any U >= lambda(tau) (the upper
  !> end of the eigensolve's error bar): s = 4 tau/U is stable. The first
  !> solves run at a looser tolerance (the step they feed is corrected by the
  !> next); it stops when |theta - 4| is within the error bar of a solve at
  !> half of `tol` (s = 4 tau/U loses the whole residual of U, where the
  !> undamped step 2/sqrt(U) loses half of it: the damped step is then good to
  !> the same tol/2), and takes the largest safe step found. A problem with
  !> `confirm_cold` certifies no step until the converged tau is confirmed by
  !> a cold solve (its `top` with `cold` set) that finds no top above the
  !> last one's error bar; one that does sends the steps on from its mode
  !> (at most `damped_confirmations` cold solves).
  subroutine damped_newton(problem, lam_a, vb, rate, tol, result, status, progress)
    class(damped_problem_type), intent(inout) :: problem
    real(dp), intent(in) :: lam_a, vb, rate
    !> The eigensolves' relative tolerance.
    real(dp), intent(in) :: tol
    type(critical_step_type), intent(inout) :: result
    type(demstep_status_type), intent(out) :: status
    class(progress_type), intent(inout), optional :: progress
    real(dp) :: tau, tau_safe, theta, err, va, vb_k, step, q, tol_k, upper, tol_end, theta_c, err_c, va_c
    integer :: it, confirms
    logical :: has_mode, certifying, done, exact
    tau = damped_lower_bound(2.0_dp/sqrt(lam_a), vb)
    tau_safe = result%dt_critical_damped_bound*rate
    tol_end = max(0.5_dp*tol, epsilon(1.0_dp))
    tol_k = max(tol_end, 1.0e-4_dp)
    confirms = 0
    exact = .false.
    problem%cold = .false.
    problem%confirms = 0
    problem%higher = .false.
    status%stat = demstep_stat%ok
    do it = 1, damped_newton_steps
      call problem%top(tau, tol_k, theta, err, va, has_mode, result, status, progress)
      if (status%stat /= demstep_stat%ok) return
      if (.not. has_mode) exit
      ! (only a solve to the full tolerance certifies a step: a looser one
      ! only steers; with `confirm_cold` only the cold solve that confirms
      ! the converged steps does)
      upper = theta + err
      certifying = tol_k <= tol_end
      if (certifying .and. .not. problem%confirm_cold) tau_safe = max(tau_safe, tau*min(1.0_dp, 4.0_dp/upper))
      ! the next tau: the root of the current mode's own quadratic
      ! q(t) = t^2 v'A'v + 2 t v'B'v (v'B'v = (theta - tau^2 v'A'v)/(2 tau)),
      ! which touches lambda at tau (value and slope) and lies below it: a
      ! Newton step that keeps the curvature, from above
      step = newton_step(theta, va)
      ! converged: theta = 4 within its error bar, or to rounding (a dense
      ! solve's error bar is a few ulps)
      done = certifying .and. (abs(theta - 4.0_dp) <= err .or. abs(step) <= 4.0_dp*epsilon(1.0_dp)*tau)
      if (done .and. problem%confirm_cold) then
        ! the converged tau confirmed by a cold solve (a random start, as
        ! long a run as the undamped top's cold solve): the warm-started
        ! steps find a top near their start, and on a crowded top or where
        ! the damped top sits apart from the undamped one that need not be
        ! lambda's. No higher top, or one whose step 4 tau/U is within tol/2
        ! of tau: the step is certified from it. A higher one: the Newton
        ! steps go on from its mode, and the new tau is confirmed too
        problem%cold = .true.
        call problem%top(tau, tol_end, theta_c, err_c, va_c, has_mode, result, status, progress)
        problem%cold = .false.
        if (status%stat /= demstep_stat%ok) return
        if (.not. has_mode) exit
        confirms = confirms + 1
        problem%confirms = confirms
        result%damped_confirmations = result%damped_confirmations + 1
        if (theta_c <= upper .or. theta_c + err_c <= 4.0_dp*(1.0_dp + tol_end) .or. &
            confirms >= damped_confirmations) then
          tau_safe = max(tau_safe, tau*min(1.0_dp, 4.0_dp/max(upper, theta_c + err_c)))
          ! (out of confirmations with a higher top: a safe step, not the root)
          exact = theta_c <= upper .or. theta_c + err_c <= 4.0_dp*(1.0_dp + tol_end)
          problem%higher = problem%higher .or. .not. exact
          exit
        end if
        problem%higher = .true.
        theta = theta_c
        err = err_c
        va = va_c
        step = newton_step(theta, va)
        done = .false.
      end if
      if (done) then
        exact = .true.
        exit
      end if
      ! Newton squares the relative error: the next solve to a hundredth of it
      tol_k = max(tol_end, min(1.0e-4_dp, 1.0e-2_dp*(step/tau)**2))
      tau = max(tau - step, tau_safe)
    end do
    if (.not. has_mode) return
    ! (never below the rigorous bound, which the solves confirm or beat)
    result%dt_critical_damped = max(tau_safe/rate, result%dt_critical_damped_bound)
    ! exact only where a certified solve converged on the root (out of steps:
    ! the largest safe step found, or the bound, is no root)
    result%damped_exact = exact
    ! the one-spring damping ratio with the same limit at the bracket's end
    q = result%dt_critical_damped*bracket_omega(result)/2.0_dp
    result%damping_ratio_top = max(0.0_dp, (1.0_dp - q**2)/(2.0_dp*q))
  contains
    !> tau minus the root of the quadratic of a mode with Rayleigh quotients
    !> theta (of tau^2 A' + 2 tau B') and va (of A'); a drag-only mode (va =
    !> 0: no spring moves it) has the linear 2 t v'B'v, its root 2/v'B'v.
    real(dp) function newton_step(theta, va) result(s)
      real(dp), intent(in) :: theta, va
      vb_k = max(0.0_dp, (theta - tau**2*va)/(2.0_dp*tau))
      if (va > 0.0_dp) then
        s = tau - damped_lower_bound(2.0_dp/sqrt(va), vb_k)
      else if (vb_k > 0.0_dp) then
        s = tau - 2.0_dp/vb_k
      else
        ! (theta = 0: no root, no step)
        s = 0.0_dp
      end if
    end function newton_step
  end subroutine damped_newton

  !> Top eigenpair of the serial operator mixed as tau^2 A' + 2 tau B'
  !> (warm start from the previous mode; with `cold` set, none: see
  !> `damped_newton`), and v'A'v of that mode.
  subroutine serial_damped_top(problem, tau, tol, theta, err, va, has_mode, result, status, progress)
    class(serial_damped_type), intent(inout) :: problem
    real(dp), intent(in) :: tau, tol
    real(dp), intent(out) :: theta, err, va
    logical, intent(out) :: has_mode
    type(critical_step_type), intent(inout) :: result
    type(demstep_status_type), intent(out) :: status
    class(progress_type), intent(inout), optional :: progress
    real(dp), allocatable :: y(:)
    if (problem%cached .and. problem%accept_start .and. .not. problem%cold) then
      ! the start as it is, its mixed product from A'v and B'v (as
      ! `top_eigenpair` tries a start: its residual within the tolerance)
      problem%cached = .false.
      y = tau**2*problem%av + 2.0_dp*tau*problem%bv
      theta = dot_product(problem%vec, y)
      err = norm2(y - theta*problem%vec)
      if (theta > 0.0_dp .and. err <= tol*theta) then
        has_mode = .true.
        status%stat = demstep_stat%ok
        err = err + 8.0_dp*epsilon(1.0_dp)*theta
        result%damped_solves = result%damped_solves + 1
        va = dot_product(problem%vec, problem%av)
        return
      end if
    end if
    ! (a start that did not stand is refined, confirmed cold when asked. A
    ! start that stood is at its own quadratic root, theta = 4 to rounding
    ! within its error bar, so the steps end there; should rounding send them
    ! on, these later refined steps are confirmed cold too: no refined damped
    ! top is left unconfirmed)
    if (problem%confirm_refined .and. .not. problem%cold) problem%confirm_cold = .true.
    problem%cached = .false.
    call operator_mix(problem%op, tau**2, 2.0_dp*tau)
    if (problem%cold) then
      ! the cold confirming solve (`cold_top_eigenpair`)
      if (allocated(problem%other)) deallocate(problem%other)
      call cold_top_eigenpair(problem%op, assembly_operator_apply, assembly_matrix_of, problem%op%n, &
        problem%choice, tol, problem%vec, theta, err, has_mode, &
        result%eigen_products, result%eigen_restarts, status, progress, problem%ncv)
    else
      if (allocated(problem%other) .and. .not. problem%accept_start) then
        ! (a damped top where the undamped one is, or where it was: both in the start)
        problem%vec = problem%vec + sign(1.0_dp, dot_product(problem%vec, problem%other))*problem%other
        deallocate(problem%other)
      end if
      call top_eigenpair(problem%op, assembly_operator_apply, assembly_matrix_of, problem%op%n, &
        problem%choice, tol, problem%vec, theta, err, has_mode, &
        result%eigen_products, result%eigen_restarts, status, progress, problem%ncv, &
        accept_start=problem%accept_start, confirm_steps=problem%confirm_steps)
    end if
    if (status%stat /= demstep_stat%ok) return
    err = err + 8.0_dp*epsilon(1.0_dp)*theta
    result%damped_solves = result%damped_solves + 1
    if (.not. allocated(y)) allocate(y(problem%op%n))
    call operator_mix(problem%op, 1.0_dp, 0.0_dp)
    call assembly_operator_apply(problem%op, problem%vec, y)
    va = dot_product(problem%vec, y)
  end subroutine serial_damped_top

  !> The rigorous bound b >= lambda_max(B') of the operator's scaled dashpots
  !> (`operator_bound` of B'; 0 without dashpots), for the damped limit's
  !> lower bound. O(springs).
  function assembly_dashpot_bound(op) result(b)
    type(assembly_operator_type), intent(inout) :: op
    real(dp) :: b
    b = 0.0_dp
    if (size(op%dcoef, 2) == 0) return
    call operator_mix(op, 0.0_dp, 1.0_dp)
    b = operator_bound(op)
    call operator_mix(op, 1.0_dp, 0.0_dp)
  end function assembly_dashpot_bound

  !> Set the operator to alpha A' + beta B'.
  pure subroutine operator_mix(op, alpha, beta)
    type(assembly_operator_type), intent(inout) :: op
    real(dp), intent(in) :: alpha, beta
    op%alpha = alpha
    op%beta = beta
  end subroutine operator_mix

  !> The coefficients (k_n, k_t, k_r, k_w) of spring s in the mixed operator
  !> alpha A' + beta B', and its pre-stress (`mixed_stiffness`).
  pure subroutine mixed_coefficients(op, s, k, geo)
    type(assembly_operator_type), intent(in) :: op
    integer, intent(in) :: s
    real(dp), intent(out) :: k(4), geo
    call mixed_stiffness(op%coef(:, s), op%dcoef, s, op%alpha, op%beta, k, geo)
  end subroutine mixed_coefficients

  !> r = |A'| v (each entry raised by its rounding allowance) for the operator
  !> as it is mixed (alpha A' + beta B'), without its pre-stress (|A'| the assembled
  !> matrix's absolute values: each body's diagonal block summed over its springs
  !> before they are taken, so the contacts of one body cancel there), from
  !> the closed form of the kernel's blocks (the columns of the body's end of
  !> each spring are its rows, by symmetry). With 6 components spring by
  !> spring (`contact_abs_springs`, in parallel over ranges of bodies, each
  !> scanning the springs; a body's sums in its `incident` order), the
  !> diagonal blocks kept in dsum(18, bodies) for the next products of the
  !> same operator (`known`: already there); else per body from
  !> `contact_end_blocks` (dsum unused). O(springs).
  subroutine operator_abs_product(op, v, r, dsum, known)
    type(assembly_operator_type), intent(in) :: op
    !> size n, >= 0.
    real(dp), intent(in) :: v(:)
    real(dp), intent(out) :: r(:)
    !> (18, bodies) with 6 components (else not used); `known`: summed by an
    !> earlier product of the operator as it is now mixed.
    real(dp), intent(inout) :: dsum(:, :)
    logical, intent(in) :: known
    real(dp), allocatable :: v_own(:), r_own(:)
    if (.not. allocated(op%order) .or. op%own_vectors) then
      call abs_product_own(op, v, r, dsum, known)
      return
    end if
    ! (in the operator's numbering, and back)
    allocate(v_own(op%n), r_own(op%n))
    call reorder_vector(op, v, v_own, .true.)
    call abs_product_own(op, v_own, r_own, dsum, known)
    call reorder_vector(op, r_own, r, .false.)
  end subroutine operator_abs_product

  !> `operator_abs_product` with v and r in the operator's own numbering of
  !> the bodies.
  subroutine abs_product_own(op, v, r, dsum, known)
    type(assembly_operator_type), intent(in) :: op
    real(dp), intent(in) :: v(:)
    real(dp), intent(out) :: r(:)
    real(dp), intent(inout) :: dsum(:, :)
    logical, intent(in) :: known
    real(dp) :: d(6, 6), off(6), own(6, 6), other(6, 6), row, k(4), geo
    integer :: i, s, en, o, j, c, q, nc, parts, part, lo, hi
    integer(i8) :: p
    nc = op%nc
    if (nc == 6) then
      parts = 1
      !$ if (op%n_springs >= parallel_springs) parts = omp_get_max_threads()
      !$omp parallel do private(part, lo, hi) schedule(static, 1) if(parts > 1)
      do part = 1, parts
        lo = int((part - 1)*int(op%n_bodies, i8)/parts) + 1
        hi = int(part*int(op%n_bodies, i8)/parts)
        r(6*lo - 5:6*hi) = 0.0_dp
        if (.not. known) dsum(:, lo:hi) = 0.0_dp
        call contact_abs_springs(lo, hi, op%n_springs, op%ends, op%normal, op%coef, op%dcoef, op%alpha, &
          op%beta, op%rinv, op%w, v, .not. known, r(6*lo - 5:6*hi), dsum(:, lo:hi))
      end do
      !$omp end parallel do
      !$omp parallel do private(i, c) schedule(static) if(op%n_springs >= parallel_springs)
      do i = 1, op%n_bodies
        do c = 1, 6
          r(6*(i - 1) + c) = r(6*(i - 1) + c)*op%w(c, i)*abs_rounding(op, i)
        end do
      end do
      !$omp end parallel do
      return
    end if
    !$omp parallel do private(i, s, en, o, j, c, q, p, d, off, own, other, row, k, geo) &
    !$omp schedule(static) if(op%n_springs >= parallel_springs)
    do i = 1, op%n_bodies
      d = 0.0_dp
      off = 0.0_dp
      do p = op%first(i), op%first(i + 1) - 1
        s = (op%incident(p) + 1)/2
        en = op%incident(p) - 2*(s - 1)
        o = 3 - en
        call mixed_coefficients(op, s, k, geo)
        call contact_end_blocks(op%normal(:, s), k, op%coef(3, s), op%coef(4, s), &
          op%rinv(op%ends(1, s)), op%rinv(op%ends(2, s)), 0.0_dp, en == 1, own, other)
        j = op%ends(o, s)
        do c = 1, nc
          d(:, c) = d(:, c) + own(:, op%comp(c))
        end do
        if (j == 0) cycle
        do c = 1, nc
          do q = 1, nc
            off(c) = off(c) + abs(other(op%comp(q), op%comp(c)))*op%w(op%comp(q), j)*v((j - 1)*nc + q)
          end do
        end do
      end do
      do c = 1, nc
        row = off(c)
        do q = 1, nc
          row = row + abs(d(op%comp(q), c))*op%w(op%comp(q), i)*v((i - 1)*nc + q)
        end do
        r((i - 1)*nc + c) = row*op%w(op%comp(c), i)*abs_rounding(op, i)
      end do
    end do
    !$omp end parallel do
  end subroutine abs_product_own

  !> The factor that raises body i's entries of |A'| v by their rounding: each
  !> is a sum of nc (springs + 1) positive terms, each product rounded a few
  !> times.
  pure real(dp) function abs_rounding(op, i) result(f)
    type(assembly_operator_type), intent(in) :: op
    integer, intent(in) :: i
    f = 1.0_dp + real(op%nc*(op%first(i + 1) - op%first(i) + 1) + 4, dp)*epsilon(1.0_dp)
  end function abs_rounding

  !> The vectors' free body (the caller's numbering) of the operator's body
  !> b (`assembly_operator_type%order`).
  pure integer function outer_body(op, b) result(e)
    type(assembly_operator_type), intent(in) :: op
    integer, intent(in) :: b
    e = b
    if (allocated(op%order) .and. .not. op%own_vectors) e = op%order(b)
  end function outer_body

  !> The caller's spring of the operator's spring s.
  pure integer function outer_spring(op, s) result(e)
    type(assembly_operator_type), intent(in) :: op
    integer, intent(in) :: s
    e = s
    if (allocated(op%spring_order)) e = op%spring_order(s)
  end function outer_spring

  !> A vector (nc per free body) from the caller's numbering of the bodies
  !> into the operator's (`own`), or back, for an operator with an order.
  subroutine reorder_vector(op, x, y, own)
    type(assembly_operator_type), intent(in) :: op
    real(dp), intent(in) :: x(:)
    real(dp), intent(out) :: y(:)
    logical, intent(in) :: own
    integer :: b, e, nc
    nc = op%nc
    !$omp parallel do private(b, e) schedule(static) if(op%n_bodies >= parallel_springs)
    do b = 1, op%n_bodies
      e = op%order(b)
      if (own) then
        y((b - 1)*nc + 1:b*nc) = x((e - 1)*nc + 1:e*nc)
      else
        y((e - 1)*nc + 1:e*nc) = x((b - 1)*nc + 1:b*nc)
      end if
    end do
    !$omp end parallel do
  end subroutine reorder_vector

  !> The rigorous bound of omega_max^2 (scaled), without the pre-stress (which
  !> only softens): lambda_max(A') <= rho(|A'|) <= max_i (|A'| v)_i / v_i for any
  !> v > 0 (Collatz-Wielandt). v = 1 gives Gershgorin's row sums; each further
  !> v <- |A'| v (floored at 1e-3 of its largest entry) tightens it towards
  !> rho(|A'|): on random packings dt bound/limit 0.66 with v = 1, 0.74 and 0.77
  !> after one and two steps (one |A'| product each, the cost of the first).
  !> The smallest of the quotients (`assembly_set_bound` adds the rounding).
  !> The first product sums the diagonal blocks for the others (18 reals a
  !> body while it runs).
  function operator_bound(op) result(bound)
    type(assembly_operator_type), intent(in), target :: op
    real(dp) :: bound
    type(abs_bound_type) :: context
    real(dp), allocatable, target :: dsum(:, :)
    logical, target :: known
    allocate(dsum(18, merge(op%n_bodies, 0, op%nc == 6)))
    known = .false.
    context%op => op
    context%dsum => dsum
    context%known => known
    bound = collatz_bound(context, op%n, abs_bound_product)
  end function operator_bound

  !> The Collatz-Wielandt iteration of `operator_bound` on any operator given
  !> by its absolute product `abs_product` (r >= |A| v for v >= 0) of order n:
  !> the smallest max_i r_i/v_i from v = 1 and `bound_iterations` further
  !> steps v <- r/max(r), floored at 1e-3.
  function collatz_bound(context, n, abs_product) result(bound)
    class(lanczos_context_type), intent(in) :: context
    integer, intent(in) :: n
    procedure(abs_product_operator) :: abs_product
    real(dp) :: bound
    ! (the vector passes in parallel over blocks, each block's maxval, then
    ! the maxval of those: the same values as maxval over the whole)
    integer, parameter :: block = 65536
    real(dp), allocatable :: v(:), r(:), part(:, :)
    real(dp) :: r_max
    integer :: k, b, nb, i0, i1
    nb = max(1, (n + block - 1)/block)
    allocate(v(n), r(n), part(2, nb))
    !$omp parallel do private(b, i0, i1) schedule(static) if(nb > 1)
    do b = 1, nb
      v((b - 1)*block + 1:min(n, b*block)) = 1.0_dp
    end do
    !$omp end parallel do
    bound = huge(1.0_dp)
    do k = 0, bound_iterations
      call abs_product(context, v, r)
      !$omp parallel do private(b, i0, i1) schedule(static) if(nb > 1)
      do b = 1, nb
        i0 = (b - 1)*block + 1
        i1 = min(n, b*block)
        part(1, b) = maxval(r(i0:i1)/v(i0:i1))
        part(2, b) = maxval(r(i0:i1))
      end do
      !$omp end parallel do
      bound = min(bound, maxval(part(1, :)))
      r_max = maxval(part(2, :))
      if (.not. r_max > 0.0_dp) exit
      !$omp parallel do private(b, i0, i1) schedule(static) if(nb > 1)
      do b = 1, nb
        i0 = (b - 1)*block + 1
        i1 = min(n, b*block)
        v(i0:i1) = max(r(i0:i1)/r_max, 1.0e-3_dp)
      end do
      !$omp end parallel do
    end do
  end function collatz_bound

  !> `operator_abs_product` as an `abs_product_operator` (for `collatz_bound`)
  !> on an `abs_bound_type`: the diagonal blocks summed by the first product.
  subroutine abs_bound_product(context, v, r)
    class(lanczos_context_type), intent(in) :: context
    real(dp), intent(in) :: v(:)
    real(dp), intent(out) :: r(:)
    real(dp), pointer :: dsum(:, :)
    logical, pointer :: known
    r = 0.0_dp
    select type (bound => context)
    class is (abs_bound_type)
      dsum => bound%dsum
      known => bound%known
      ! (in the operator's own numbering: the iteration, from v = 1, only
      ! takes entrywise quotients and maxima, which no numbering changes)
      call abs_product_own(bound%op, v, r, dsum, known)
      known = .true.
    end select
  end subroutine abs_bound_product

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

  !> y = A' x (or, mixed, (alpha A' + beta B') x) for an
  !> `assembly_operator_type` (a `lanczos_operator`), each spring's generalised
  !> forces from the interaction kernel (`contact_product`), in three passes:
  !> block by block (`operator_set_blocks`), its bodies' scaled displacements,
  !> then its interior springs in spring order, each end's force added to its
  !> body's sum as it comes, and y = M'^-1/2 times the sums; then the springs
  !> that cross blocks, their ends' forces kept in `work`; then at each body
  !> with crossing ends y += M'^-1/2 times their sum in spring order. Every
  !> pass runs in parallel under OpenMP and every sum has an order fixed by the
  !> operator alone: the result is the same for every thread count, bit for
  !> bit. O(springs + dof); interior springs store nothing.
  subroutine assembly_operator_apply(context, x, y)
    class(lanczos_context_type), intent(inout) :: context
    real(dp), intent(in) :: x(:)
    real(dp), intent(out) :: y(:)
    integer :: k, blk, lo, hi, i, c, nc, q, e
    real(dp) :: f(6)
    real(dp), allocatable :: acc(:, :)
    select type (op => context)
    class is (assembly_operator_type)
      nc = op%nc
      !$omp parallel private(blk, lo, hi, i, c, e, acc) if(op%n_springs >= parallel_springs)
      allocate(acc(6, min(op%block_bodies, op%n_bodies)))
      !$omp do schedule(dynamic)
      do blk = 1, op%n_blocks
        lo = (blk - 1)*op%block_bodies + 1
        hi = min(op%n_bodies, blk*op%block_bodies)
        call operator_scatter(op, x, lo, hi)
        acc(:, :hi - lo + 1) = 0.0_dp
        call contact_products_add(op%block_first(blk), op%block_first(blk + 1) - 1, op%block_springs, &
          op%normal, op%coef, op%dcoef, op%alpha, op%beta, op%ends, op%rinv, op%xs, lo, hi, acc)
        if (nc == 6) then
          ! (all six components, in order: the common 3D case without indirection)
          do i = lo, hi
            e = outer_body(op, i)
            y(6*e - 5:6*e) = acc(:, i - lo + 1)*op%w(:, i)
          end do
        else
          do i = lo, hi
            e = outer_body(op, i)
            do c = 1, nc
              y((e - 1)*nc + c) = acc(op%comp(c), i - lo + 1)*op%w(op%comp(c), i)
            end do
          end do
        end if
      end do
      !$omp end do
      !$omp end parallel
      ! the crossing springs (in blocks of springs: the kernel is compiled into its loop)
      !$omp parallel do private(k) schedule(static) if(op%n_springs >= parallel_springs)
      do k = 1, size(op%cross), spring_block
        call contact_products_listed(k, min(k + spring_block - 1, size(op%cross)), op%cross, op%normal, op%coef, &
          op%dcoef, op%alpha, op%beta, op%ends, op%rinv, op%xs, op%work)
      end do
      !$omp end parallel do
      !$omp parallel do private(blk, q, i, c, e, f) schedule(static) if(op%n_springs >= parallel_springs)
      do blk = 1, op%n_blocks
        f = 0.0_dp
        do q = op%cross_first(blk), op%cross_first(blk + 1) - 1
          i = op%cross_body(q)
          f = f + op%work(:, op%cross_col(q))
          if (q < op%cross_first(blk + 1) - 1) then
            if (op%cross_body(q + 1) == i) cycle
          end if
          ! the body's last crossing end
          e = outer_body(op, i)
          if (nc == 6) then
            y(6*e - 5:6*e) = y(6*e - 5:6*e) + f*op%w(:, i)
          else
            do c = 1, nc
              y((e - 1)*nc + c) = y((e - 1)*nc + c) + f(op%comp(c))*op%w(op%comp(c), i)
            end do
          end if
          f = 0.0_dp
        end do
      end do
      !$omp end parallel do
    class default
      y = 0.0_dp
    end select
  end subroutine assembly_operator_apply

  !> Bodies lo..hi's scaled displacements xs(:, i) = M'^-1/2 x (six components,
  !> 0 where not a degree of freedom; column 0, the ground, stays 0).
  subroutine operator_scatter(op, x, lo, hi)
    type(assembly_operator_type), intent(inout) :: op
    real(dp), intent(in) :: x(:)
    integer, intent(in) :: lo, hi
    integer :: i, c, nc, e
    nc = op%nc
    do i = lo, hi
      e = outer_body(op, i)
      if (nc == 6) then
        ! (all six components, in order: the common 3D case without indirection)
        op%xs(:, i) = x(6*e - 5:6*e)*op%w(:, i)
      else
        op%xs(:, i) = 0.0_dp
        do c = 1, nc
          op%xs(op%comp(c), i) = x((e - 1)*nc + c)*op%w(op%comp(c), i)
        end do
      end if
    end do
  end subroutine operator_scatter

  !> Each spring's part of x'A'x (A' as mixed): energy(s) = xs_a.f_a + xs_b.f_b
  !> over its two ends (xs the ends' scaled displacements, `operator_scatter`;
  !> f their forces from the kernel; the ground's term 0). Sums to x'A'x up to
  !> rounding. O(springs), in parallel.
  subroutine operator_spring_energies(op, x, energy)
    type(assembly_operator_type), intent(inout) :: op
    !> size n.
    real(dp), intent(in) :: x(:)
    !> size n_springs.
    real(dp), intent(out) :: energy(:)
    integer :: s0, s1, s, j, list(spring_block)
    real(dp) :: f(6, 2*spring_block)
    integer :: blk
    !$omp parallel do private(blk) schedule(static) if(op%n_springs >= parallel_springs)
    do blk = 1, op%n_blocks
      call operator_scatter(op, x, (blk - 1)*op%block_bodies + 1, min(op%n_bodies, blk*op%block_bodies))
    end do
    !$omp end parallel do
    !$omp parallel do private(s0, s1, s, j, list, f) schedule(static) if(op%n_springs >= parallel_springs)
    do s0 = 1, op%n_springs, spring_block
      s1 = min(s0 + spring_block - 1, op%n_springs)
      do s = s0, s1
        list(s - s0 + 1) = s
      end do
      call contact_products_listed(1, s1 - s0 + 1, list, op%normal, op%coef, op%dcoef, op%alpha, op%beta, &
        op%ends, op%rinv, op%xs, f)
      do s = s0, s1
        j = s - s0 + 1
        energy(outer_spring(op, s)) = dot_product(op%xs(:, op%ends(1, s)), f(:, 2*j - 1)) &
          + dot_product(op%xs(:, op%ends(2, s)), f(:, 2*j))
      end do
    end do
    !$omp end parallel do
  end subroutine operator_spring_energies

  !> The product's blocks of an operator (`assembly_operator_type`): free
  !> bodies in blocks of block_bodies (> 0; `operator_from_springs` sets
  !> `product_block_bodies`), each spring with free ends interior to the
  !> block of its free ends (the ground counts as inside any) or crossing.
  !> Products' sums depend on it in their last bits only. O(springs).
  subroutine operator_set_blocks(op, block_bodies)
    type(assembly_operator_type), intent(inout) :: op
    integer, intent(in) :: block_bodies
    integer, allocatable :: home(:), per_block(:), per_body(:)
    integer(i8), allocatable :: body_start(:), next_block(:), next_body(:)
    integer :: nb, s, blk, k, e, i, nx
    op%block_bodies = max(1, block_bodies)
    nb = max(1, (op%n_bodies + op%block_bodies - 1)/op%block_bodies)
    op%n_blocks = nb
    ! each spring's block (0: crossing, -1: no free end); the interior
    ! springs per block, and the crossing ends per body
    allocate(home(op%n_springs), per_block(nb), per_body(op%n_bodies))
    per_block = 0
    per_body = 0
    nx = 0
    do s = 1, op%n_springs
      home(s) = spring_home(op, s)
      if (home(s) > 0) then
        per_block(home(s)) = per_block(home(s)) + 1
      else if (home(s) == 0) then
        nx = nx + 1
        do e = 1, 2
          per_body(op%ends(e, s)) = per_body(op%ends(e, s)) + 1
        end do
      end if
    end do
    call fit_int1(op%block_first, nb + 1)
    op%block_first = int(bucket_starts(per_block))
    body_start = bucket_starts(per_body)
    call fit_int1(op%cross_first, nb + 1)
    do blk = 1, nb
      op%cross_first(blk) = int(body_start((blk - 1)*op%block_bodies + 1))
    end do
    op%cross_first(nb + 1) = int(body_start(op%n_bodies + 1))
    call fit_int1(op%block_springs, op%block_first(nb + 1) - 1)
    call fit_int1(op%cross, nx)
    call fit_int1(op%cross_body, op%cross_first(nb + 1) - 1)
    call fit_int1(op%cross_col, op%cross_first(nb + 1) - 1)
    call fit_real2(op%work, 6, 1, 2*nx)
    ! the lists, in spring order (a counting sort by block and by body)
    next_block = op%block_first(:nb)
    next_body = body_start(:op%n_bodies)
    k = 0
    do s = 1, op%n_springs
      if (home(s) > 0) then
        op%block_springs(next_block(home(s))) = s
        next_block(home(s)) = next_block(home(s)) + 1
      else if (home(s) == 0) then
        k = k + 1
        op%cross(k) = s
        do e = 1, 2
          i = op%ends(e, s)
          op%cross_body(next_body(i)) = i
          op%cross_col(next_body(i)) = 2*(k - 1) + e
          next_body(i) = next_body(i) + 1
        end do
      end if
    end do
  end subroutine operator_set_blocks

  !> The product's block of spring s (`operator_set_blocks`): its free ends'
  !> block, 0 when they lie in two blocks, -1 when it has none.
  pure integer function spring_home(op, s) result(home)
    type(assembly_operator_type), intent(in) :: op
    integer, intent(in) :: s
    integer :: a, b
    a = op%ends(1, s)
    b = op%ends(2, s)
    if (a == 0 .and. b == 0) then
      home = -1
    else if (a == 0) then
      home = (b - 1)/op%block_bodies + 1
    else if (b == 0) then
      home = (a - 1)/op%block_bodies + 1
    else
      home = (a - 1)/op%block_bodies + 1
      if ((b - 1)/op%block_bodies + 1 /= home) home = 0
    end if
  end function spring_home
  !> Several products of the operator in one pass over its springs: product
  !> q is (alpha(q) A' + beta(q) B') x(:, which(q)) into y(:, q) (B' the
  !> scaled dashpots; none: 0). Each block of springs goes through the
  !> kernel (`contact_products`) once per product while it is in cache, and
  !> its forces are added to their bodies in spring order (over all of a
  !> body's springs; `assembly_operator_apply` adds a block's interior springs
  !> first): every product equals that one's, alpha and beta set by
  !> `operator_mix`, to rounding. One thread, from `fused_springs`
  !> springs (`one_pass` true: always): below, on several threads (OpenMP,
  !> and springs enough for the product's parallel loops) and with fewer
  !> than six components per body, the products are made one by one by
  !> `assembly_operator_apply` instead. The operator's mix is left as it was.
  !> O(springs + dof) per product, no array of spring forces.
  subroutine operator_products(op, x, which, alpha, beta, y, one_pass)
    type(assembly_operator_type), intent(inout) :: op
    !> The vectors (op%n, any number).
    real(dp), intent(in) :: x(:, :)
    !> Each product's vector (a column of x) and coefficients of A' and B'.
    integer, intent(in) :: which(:)
    real(dp), intent(in) :: alpha(:), beta(:)
    !> The products (op%n, size(which)).
    real(dp), intent(out) :: y(:, :)
    !> The one pass whatever the springs (default: from `fused_springs`).
    logical, intent(in), optional :: one_pass
    ! (a block's spring forces per product)
    real(dp), allocatable :: f(:, :, :)
    real(dp) :: a0, b0, bq(size(which))
    integer :: q, nq, v, i, s, s0, m, k, j, threads, e
    logical :: fused
    nq = size(which)
    fused = op%n_springs >= fused_springs
    if (present(one_pass)) fused = fused .or. one_pass
    threads = 1
    !$ threads = omp_get_max_threads()
    ! (B' is 0 without dashpots: its kernel then reads none)
    bq = beta
    if (size(op%dcoef, 2) == 0) bq = 0.0_dp
    if (op%nc /= 6 .or. .not. fused .or. (threads > 1 .and. op%n_springs >= parallel_springs)) then
      a0 = op%alpha
      b0 = op%beta
      do q = 1, nq
        call operator_mix(op, alpha(q), bq(q))
        call assembly_operator_apply(op, x(:, which(q)), y(:, q))
      end do
      call operator_mix(op, a0, b0)
      return
    end if
    ! each vector's scaled displacements (column 0: the ground)
    if (allocated(op%many_xs)) then
      if (ubound(op%many_xs, 2) /= op%n_bodies .or. size(op%many_xs, 3) < size(x, 2)) deallocate(op%many_xs)
    end if
    if (.not. allocated(op%many_xs)) allocate(op%many_xs(6, 0:op%n_bodies, size(x, 2)))
    if (allocated(op%many_sum)) then
      if (size(op%many_sum, 2) < nq .or. size(op%many_sum, 3) /= op%n_bodies) deallocate(op%many_sum)
    end if
    if (.not. allocated(op%many_sum)) allocate(op%many_sum(6, nq, op%n_bodies))
    allocate(f(6, 2*spring_block, nq))
    associate(xs => op%many_xs, acc => op%many_sum)
    do v = 1, size(x, 2)
      xs(:, 0, v) = 0.0_dp
      do i = 1, op%n_bodies
        e = outer_body(op, i)
        xs(:, i, v) = x(6*e - 5:6*e, v)*op%w(:, i)
      end do
    end do
    acc(:, :nq, :) = 0.0_dp
    do s0 = 1, op%n_springs, spring_block
      m = min(spring_block, op%n_springs - s0 + 1)
      ! (the block's springs, renumbered from 1: its forces are f(:, 1:2m, q))
      do q = 1, nq
        if (size(op%dcoef, 2) > 0) then
          call contact_products(1, m, op%normal(1, s0), op%coef(1, s0), op%dcoef(1, s0), alpha(q), bq(q), &
            op%ends(1, s0), op%rinv, xs(1, 0, which(q)), f(1, 1, q))
        else
          call contact_products(1, m, op%normal(1, s0), op%coef(1, s0), op%dcoef, alpha(q), bq(q), &
            op%ends(1, s0), op%rinv, xs(1, 0, which(q)), f(1, 1, q))
        end if
      end do
      ! each end's force added to its body, in spring order
      do k = 1, m
        s = s0 + k - 1
        do j = 1, 2
          i = op%ends(j, s)
          if (i == 0) cycle
          do q = 1, nq
            acc(:, q, i) = acc(:, q, i) + f(:, 2*k - 2 + j, q)
          end do
        end do
      end do
    end do
    do i = 1, op%n_bodies
      e = outer_body(op, i)
      do q = 1, nq
        y(6*e - 5:6*e, q) = acc(:, q, i)*op%w(:, i)
      end do
    end do
    end associate
  end subroutine operator_products

  !> The operator's matrix A' in compressed rows (each body's diagonal block
  !> once, then one block per spring to another free body; columns may repeat),
  !> e.g. to hand the same problem to another eigensolver. O(springs) entries.
  subroutine assembly_matrix(op, matrix)
    type(assembly_operator_type), intent(in) :: op
    type(csr_matrix_type), intent(out) :: matrix
    type(demstep_status_type) :: status
    integer, allocatable :: bodies(:), outer(:)
    integer :: i
    matrix%n = op%n
    ! every body in its place in the caller's numbering: the rows cannot be refused
    allocate(bodies(op%n_bodies), outer(op%n_bodies))
    do i = 1, op%n_bodies
      outer(i) = outer_body(op, i)
      bodies(outer(i)) = i
    end do
    call assembly_matrix_rows(op, bodies, outer, matrix%row_start, matrix%col, matrix%val, status)
  end subroutine assembly_matrix

  !> `assembly_matrix` for `top_eigenpair` (an `operator_matrix`).
  subroutine assembly_matrix_of(context, matrix)
    class(lanczos_context_type), intent(inout) :: context
    type(csr_matrix_type), intent(out) :: matrix
    select type (op => context)
    class is (assembly_operator_type)
      call assembly_matrix(op, matrix)
    end select
  end subroutine assembly_matrix_of

  !> The rows of A' that belong to a list of free bodies, with the bodies
  !> renumbered (e.g. to give each MPI rank the rows of its region): nc rows per
  !> listed body, in list order; body j's component q is column
  !> (new_index(j) - 1) nc + q. Each body's rows hold its diagonal block, then
  !> one nc x nc block per spring to another free body in `incident` order
  !> (columns may repeat). O(springs of the listed bodies).
  !> Status invalid_input when a listed body is outside 1..n_bodies,
  !> new_index has not n_bodies entries, or an entry of it the rows read (a
  !> listed body's or a partner's) is outside 1..n_bodies; entries the rows
  !> do not read are not looked at (the check is O(rows asked)).
  subroutine assembly_matrix_rows(op, bodies, new_index, row_start, col, val, status)
    type(assembly_operator_type), intent(in) :: op
    !> Free bodies (the operator's own numbering: `order` maps it to the
    !> caller's where the operator chose one) whose rows are wanted.
    integer, intent(in) :: bodies(:)
    !> New number of each free body (n_bodies entries).
    integer, intent(in) :: new_index(:)
    !> Row k holds entries row_start(k) .. row_start(k+1)-1 (nc size(bodies) + 1 starts).
    integer(i8), allocatable, intent(out) :: row_start(:)
    !> Column (new numbering) and value of each entry.
    integer, allocatable, intent(out) :: col(:)
    real(dp), allocatable, intent(out) :: val(:)
    type(demstep_status_type), intent(out) :: status
    real(dp) :: b(12, 12), d(6, 6), kk(4), geo
    integer :: k, i, s, e, o, j, r, q, nc, row
    integer(i8) :: p, pos, width
    nc = op%nc
    allocate(row_start(nc*size(bodies) + 1))
    row_start(1) = 1
    ! (each entry of new_index the rows read is checked as it is met: the
    ! listed bodies' and their partners', O(rows asked), not O(n_bodies))
    if (size(new_index) /= op%n_bodies) then
      call refuse("new_index", 0)
      return
    end if
    do k = 1, size(bodies)
      i = bodies(k)
      if (i < 1 .or. i > op%n_bodies) then
        call refuse("bodies", k)
        return
      end if
      if (new_index(i) < 1 .or. new_index(i) > op%n_bodies) then
        call refuse("new_index", i)
        return
      end if
      width = nc
      do p = op%first(i), op%first(i + 1) - 1
        s = (op%incident(p) + 1)/2
        e = op%incident(p) - 2*(s - 1)
        j = op%ends(3 - e, s)
        if (j == 0) cycle
        if (new_index(j) < 1 .or. new_index(j) > op%n_bodies) then
          call refuse("new_index", j)
          return
        end if
        width = width + nc
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
        call mixed_coefficients(op, s, kk, geo)
        b = contact_block(op%normal(:, s), kk, op%coef(3, s), op%coef(4, s), geo, &
          op%rinv(op%ends(1, s)), op%rinv(op%ends(2, s)))
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
  contains
    !> A listed body or a new number read out of range (argument `name`,
    !> entry `at`; 0: its size): no rows.
    subroutine refuse(name, at)
      character(len=*), intent(in) :: name
      integer, intent(in) :: at
      row_start = 1
      allocate(col(0), val(0))
      call set_status(status, demstep_stat%invalid_input, "bodies, new_index: need free bodies " &
        //"in 1.."//int_text(op%n_bodies)//" and a new number in that range for each", &
        where=name, index=at, subscript=.true.)
    end subroutine refuse
  end subroutine assembly_matrix_rows

  !> The common start of every assembly computation: options checked, degrees
  !> of freedom numbered, scaled masses, the springs linearised and the
  !> matrix-free operator built. O(particles + springs).
  subroutine prepare(scene, hertz_mode, impact_velocity, geo, springs, op, rate, status, position)
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
    !> The particles' positions (the scene's): the operator may then number
    !> its bodies in a locality order (`order_min_bodies`). Default no.
    real(dp), intent(in), optional :: position(:, :)
    integer :: mode
    real(dp) :: v_impact
    logical :: rotation
    mode = hertz_linearization%current
    if (present(hertz_mode)) mode = hertz_mode
    v_impact = 0.0_dp
    if (present(impact_velocity)) v_impact = impact_velocity
    rate = 0.0_dp
    if (mode /= hertz_linearization%current .and. .not. (v_impact > 0.0_dp .and. ieee_is_finite(v_impact))) then
      call set_status(status, demstep_stat%invalid_input, "the Hertz linearisation " &
        //"at impact needs a finite impact velocity > 0", where="impact_velocity")
      return
    end if
    rotation = scene%effects(scene_effect%rotation) .and. scene%dim > 1
    call linearise(scene, mode, v_impact, geo, springs, status)
    if (status%stat /= demstep_stat%ok) return
    call operator_from_springs(scene%dim, rotation, scene%mass, scene%inertia, scene%radius, springs, &
      geo, op, rate, status, scene%fixed, position=position)
    if (status%stat == demstep_stat%invalid_input .and. status%where == "position") then
      if (size(scene%bonds, 2) == 0 .and. .not. (scene%effects(scene_effect%contacts) .or. &
          scene%effects(scene_effect%walls))) then
        call set_status(status, demstep_stat%invalid_input, "the scene has no stiffness: " &
          //"no bonds, and neither 'contacts' nor 'walls' is switched on", where="effects")
      end if
    end if
  end subroutine prepare

  !> The matrix-free operator of linearised springs on bodies with these
  !> masses, moments of inertia and radii (`fixed`: ground, default none):
  !> degrees of freedom numbered (dim translations, and rotations when
  !> `rotation` and dim > 1), masses scaled, springs scaled and indexed per
  !> body. O(particles + springs). Status invalid_input naming `fixed` (every
  !> particle fixed) or `position` (no free particle touches a spring).
  !> An operator built before keeps its arrays where their sizes still fit
  !> (a monitor rebuilds it every update and check).
  subroutine operator_from_springs(dim, rotation, mass, inertia, radius, springs, geo, op, rate, status, fixed, &
      scales, position, order)
    integer, intent(in) :: dim
    logical, intent(in) :: rotation
    real(dp), intent(in) :: mass(:), inertia(:), radius(:)
    type(spring_block_type), intent(in) :: springs(:)
    logical, intent(in) :: geo
    type(assembly_operator_type), intent(inout) :: op
    !> omega = rate sqrt(lambda) (0 on failure).
    real(dp), intent(out) :: rate
    type(demstep_status_type), intent(out) :: status
    logical, intent(in), optional :: fixed(:)
    !> (k_scale, m_scale) to scale by instead of the springs' largest
    !> stiffness and the bodies' smallest mass (`dof_masses`): a caller
    !> holding one part of a scene gives the whole scene's; a part whose
    !> springs touch no free body is then not refused.
    real(dp), intent(in), optional :: scales(2)
    !> The bodies' positions (dim, bodies): the operator may then number its
    !> bodies and springs in a locality order (`order_min_bodies`).
    real(dp), intent(in), optional :: position(:, :)
    !> Or the order itself (`locality_order`; size 0: the given order): the
    !> free particles in the order of the operator's bodies. Its vectors are
    !> then in that order too (`own_vectors`). Status invalid_input naming
    !> `order` when it does not list every free particle once.
    integer, intent(in), optional :: order(:)
    integer, allocatable :: body(:), particle(:)
    integer(i8), allocatable :: at(:, :)
    real(dp) :: k_scale, m_scale, c_scale, mdof(6)
    integer :: i, nfree, nc, s, e, t, nchunk, sc
    integer(i8) :: p, ends_here
    logical :: touches, damped
    rate = 0.0_dp
    k_scale = 0.0_dp
    op%alpha = 1.0_dp
    op%beta = 0.0_dp
    op%n_springs = 0
    ! (the given order unless chosen below)
    if (allocated(op%order)) deallocate(op%order)
    if (allocated(op%spring_order)) deallocate(op%spring_order)
    op%own_vectors = .false.
    op%comp = dof_components(dim, rotation)
    nc = size(op%comp)
    op%nc = nc
    ! degrees of freedom: nc per free particle; the mass scale, the smallest
    ! mass of a component (`dof_masses`; each body's are scaled below)
    body = free_numbers(size(mass), fixed)
    nfree = count(body > 0)
    m_scale = huge(1.0_dp)
    do i = 1, size(mass)
      if (body(i) == 0) cycle
      mdof = dof_masses(mass(i), inertia(i), radius(i))
      m_scale = min(m_scale, minval(mdof(op%comp)))
    end do
    op%n_bodies = nfree
    op%n = nfree*nc
    if (nfree == 0) then
      call set_status(status, demstep_stat%invalid_input, "every particle is fixed: the " &
        //"scene has no stiffness", where="fixed")
      return
    end if
    if (present(scales)) m_scale = scales(2)
    touches = .false.
    damped = .false.
    ! (whether any spring has a dashpot, in the same pass; in parallel: a
    ! largest value and "or"s do not depend on the order)
    !$omp parallel do private(i) reduction(.or.:touches, damped) reduction(max:k_scale) &
    !$omp schedule(static) if(size(springs) >= parallel_springs)
    do i = 1, size(springs)
      damped = damped .or. any(springs(i)%c > 0.0_dp)
      if (.not. maxval(springs(i)%k) > 0.0_dp) cycle
      if (springs(i)%a > 0) touches = touches .or. body(springs(i)%a) > 0
      touches = touches .or. body(springs(i)%b) > 0
      k_scale = max(k_scale, springs(i)%k(1), springs(i)%k(2))
    end do
    !$omp end parallel do
    if (present(scales)) then
      k_scale = scales(1)
      touches = .true.
    end if
    if (.not. (touches .and. k_scale > 0.0_dp)) then
      call set_status(status, demstep_stat%invalid_input, "the scene has no stiffness: no free " &
        //"particle touches a bond, a contact or a wall", where="position")
      return
    end if

    ! a locality order of the bodies and springs: the caller's, or where the
    ! given one would scatter the product's blocks, by position (body then
    ! holds the operator's numbers)
    if (present(order)) then
      if (size(order) > 0) then
        if (.not. free_permutation(order, body)) then
          call set_status(status, demstep_stat%invalid_input, "must list every free particle once, " &
            //"or nothing", where="order")
          return
        end if
        call locality_numbering(order, springs, body, op%order, op%spring_order)
        op%own_vectors = .true.
      end if
    else if (present(position)) then
      if (size(position, 2) == size(mass)) then
        particle = locality_order(position, springs, fixed)
        if (size(particle) > 0) call locality_numbering(particle, springs, body, op%order, op%spring_order)
      end if
    end if

    ! the operator: scaled springs, and each free body's spring ends in order
    op%n_springs = size(springs)
    call fit_int2(op%ends, 2, op%n_springs)
    call fit_real2(op%normal, 3, 1, op%n_springs)
    call fit_real2(op%coef, 7, 1, op%n_springs)
    call fit_real2(op%w, 6, 1, nfree)
    ! (each product fills the bodies' columns; column 0, the ground, stays 0)
    if (allocated(op%xs)) then
      if (size(op%xs, 1) /= 6 .or. lbound(op%xs, 2) /= 0 .or. ubound(op%xs, 2) /= nfree) deallocate(op%xs)
    end if
    if (.not. allocated(op%xs)) then
      allocate(op%xs(6, 0:nfree))
      ! (zeroed in parallel: each thread faults in its own pages)
      !$omp parallel do private(i) schedule(static) if(nfree >= parallel_springs)
      do i = 0, nfree
        op%xs(:, i) = 0.0_dp
      end do
      !$omp end parallel do
    end if
    op%xs(:, 0) = 0.0_dp
    if (allocated(op%first)) then
      if (size(op%first) /= nfree + 1) deallocate(op%first)
    end if
    if (.not. allocated(op%first)) allocate(op%first(nfree + 1))
    if (allocated(op%rinv)) then
      if (lbound(op%rinv, 1) /= 0 .or. ubound(op%rinv, 1) /= nfree) deallocate(op%rinv)
    end if
    if (.not. allocated(op%rinv)) allocate(op%rinv(0:nfree))
    op%rinv = 0.0_dp
    c_scale = sqrt(k_scale)*sqrt(m_scale)
    if (damped) then
      call fit_real2(op%dcoef, 4, 1, op%n_springs)
    else
      call fit_real2(op%dcoef, 4, 1, 0)
    end if
    !$omp parallel do private(i) schedule(static) if(size(mass) >= parallel_springs)
    do i = 1, size(mass)
      if (body(i) > 0) then
        op%w(:, body(i)) = 1.0_dp/sqrt(dof_masses(mass(i), inertia(i), radius(i))/m_scale)
        op%rinv(body(i)) = 1.0_dp/radius(i)
      end if
    end do
    !$omp end parallel do
    ! (each spring's entries in parallel, in the products' static partition,
    ! which then find their pages where they are used; the count after)
    !$omp parallel do private(s, sc) schedule(static) if(op%n_springs >= parallel_springs)
    do s = 1, op%n_springs
      sc = outer_spring(op, s)
      associate(sp => springs(sc))
        op%ends(:, s) = 0
        op%coef(3:4, s) = 0.0_dp
        if (sp%a > 0) then
          op%ends(1, s) = body(sp%a)
          op%coef(3, s) = sp%arm_a/radius(sp%a)
        end if
        op%ends(2, s) = body(sp%b)
        op%coef(4, s) = sp%arm_b/radius(sp%b)
        op%normal(:, s) = sp%n
        op%coef(1, s) = sp%k(1)/k_scale
        op%coef(2, s) = sp%k(2)/k_scale
        op%coef(6:7, s) = sp%k(3:4)/k_scale
        op%coef(5, s) = 0.0_dp
        if (geo) op%coef(5, s) = sp%geo/k_scale
        if (size(op%dcoef, 2) > 0) op%dcoef(:, s) = sp%c/c_scale
      end associate
    end do
    !$omp end parallel do
    ! each free body's spring ends (`first`, `incident`) in spring order:
    ! counted and placed by chunks of springs in parallel, a chunk's entries
    ! of a body after the chunks' before it (`at`: where each chunk's next
    ! entry of each body goes), so the lists are those of one serial pass
    nchunk = 1
    !$ if (op%n_springs >= parallel_springs) nchunk = max(1, omp_get_max_threads())
    allocate(at(nfree, nchunk))
    !$omp parallel do private(t, s, e) schedule(static, 1) if(nchunk > 1)
    do t = 1, nchunk
      at(:, t) = 0
      do s = int((int(op%n_springs, i8)*(t - 1))/nchunk) + 1, int((int(op%n_springs, i8)*t)/nchunk)
        do e = 1, 2
          if (op%ends(e, s) > 0) at(op%ends(e, s), t) = at(op%ends(e, s), t) + 1
        end do
      end do
    end do
    !$omp end parallel do
    op%first(1) = 1
    do i = 1, nfree
      p = op%first(i)
      do t = 1, nchunk
        ends_here = at(i, t)
        at(i, t) = p
        p = p + ends_here
      end do
      op%first(i + 1) = p
    end do
    if (allocated(op%incident)) then
      if (size(op%incident, kind=i8) /= op%first(nfree + 1) - 1) deallocate(op%incident)
    end if
    if (.not. allocated(op%incident)) allocate(op%incident(op%first(nfree + 1) - 1))
    !$omp parallel do private(t, s, e, i, p) schedule(static, 1) if(nchunk > 1)
    do t = 1, nchunk
      do s = int((int(op%n_springs, i8)*(t - 1))/nchunk) + 1, int((int(op%n_springs, i8)*t)/nchunk)
        do e = 1, 2
          i = op%ends(e, s)
          if (i == 0) cycle
          p = at(i, t)
          op%incident(p) = 2*(s - 1) + e
          at(i, t) = p + 1
        end do
      end do
    end do
    !$omp end parallel do
    call operator_set_blocks(op, product_block_bodies)
    rate = sqrt(k_scale)/sqrt(m_scale)
    status%stat = demstep_stat%ok
  end subroutine operator_from_springs

  !> Each of n particles' free-body number in particle order (0: `fixed`).
  pure function free_numbers(n, fixed) result(body)
    integer, intent(in) :: n
    logical, intent(in), optional :: fixed(:)
    integer :: body(n)
    integer :: i, nfree
    nfree = 0
    do i = 1, n
      body(i) = 0
      if (present(fixed)) then
        if (fixed(i)) cycle
      end if
      nfree = nfree + 1
      body(i) = nfree
    end do
  end function free_numbers

  !> Whether `particle` lists each free particle (body(i) > 0) once.
  pure logical function free_permutation(particle, body) result(ok)
    integer, intent(in) :: particle(:), body(:)
    logical, allocatable :: seen(:)
    integer :: k
    ok = size(particle) == count(body > 0)
    if (.not. ok) return
    allocate(seen(size(body)), source=.false.)
    do k = 1, size(particle)
      ok = particle(k) >= 1 .and. particle(k) <= size(body)
      if (ok) ok = body(particle(k)) > 0 .and. .not. seen(particle(k))
      if (.not. ok) return
      seen(particle(k)) = .true.
    end do
  end function free_permutation

  !> The free particles (not `fixed`) in the locality order an operator of
  !> these springs would take from these positions (`operator_from_springs`
  !> with `position`; `order_min_bodies`, `order_crossing`), or none (size
  !> 0) where it would keep the given order. For a caller that keeps one
  !> order over many operators (`operator_from_springs` with `order`).
  !> O(particles + springs).
  function locality_order(position, springs, fixed) result(order)
    real(dp), intent(in) :: position(:, :)
    type(spring_block_type), intent(in) :: springs(:)
    logical, intent(in), optional :: fixed(:)
    integer, allocatable :: order(:)
    integer, allocatable :: body(:)
    body = free_numbers(size(position, 2), fixed)
    allocate(order(0))
    if (count(body > 0) < order_min_bodies) return
    if (.not. crossing_share(body, springs, product_block_bodies) > order_crossing) return
    order = spatial_order(position, body > 0)
  end function locality_order

  !> The share of the springs between two free bodies whose ends lie in two
  !> blocks of `block` bodies, body(i) the free body of particle i (0: none).
  function crossing_share(body, springs, block) result(share)
    integer, intent(in) :: body(:)
    type(spring_block_type), intent(in) :: springs(:)
    integer, intent(in) :: block
    real(dp) :: share
    integer(i8) :: both, crossing
    integer :: s, a, b
    both = 0
    crossing = 0
    !$omp parallel do private(s, a, b) reduction(+:both, crossing) schedule(static) &
    !$omp if(size(springs) >= parallel_springs)
    do s = 1, size(springs)
      if (springs(s)%a <= 0) cycle
      a = body(springs(s)%a)
      b = body(springs(s)%b)
      if (a == 0 .or. b == 0) cycle
      both = both + 1
      if ((a - 1)/block /= (b - 1)/block) crossing = crossing + 1
    end do
    !$omp end parallel do
    share = real(crossing, dp)/real(max(both, 1_i8), dp)
  end function crossing_share

  !> The operator's locality numbering (`assembly_operator_type%order`): the
  !> free bodies in the order of `particle` (the free particles, each once),
  !> body(i) renumbered to match, and the springs by their first free end in
  !> the new numbering (a stable counting sort; springs without a free end
  !> last). O(bodies + springs).
  subroutine locality_numbering(particle, springs, body, order, spring_order)
    integer, intent(in) :: particle(:)
    type(spring_block_type), intent(in) :: springs(:)
    integer, intent(inout) :: body(:)
    integer, allocatable, intent(out) :: order(:), spring_order(:)
    integer, allocatable :: key(:), per_key(:)
    integer(i8), allocatable :: start(:)
    integer :: nfree, b, s, k
    nfree = size(particle)
    allocate(order(nfree))
    do b = 1, nfree
      order(b) = body(particle(b))
      body(particle(b)) = b
    end do
    allocate(key(size(springs)), per_key(nfree + 1))
    per_key = 0
    do s = 1, size(springs)
      k = body(springs(s)%b)
      if (springs(s)%a > 0) then
        if (body(springs(s)%a) > 0 .and. (k == 0 .or. body(springs(s)%a) < k)) k = body(springs(s)%a)
      end if
      if (k == 0) k = nfree + 1
      key(s) = k
      per_key(k) = per_key(k) + 1
    end do
    start = bucket_starts(per_key)
    allocate(spring_order(size(springs)))
    do s = 1, size(springs)
      spring_order(start(key(s))) = s
      start(key(s)) = start(key(s)) + 1
    end do
  end subroutine locality_numbering

  !> The masses of a body's six components (translations u(1:3), rotations
  !> as r theta(4:6)): m, and I/r^2 for r theta.
  pure function dof_masses(mass, inertia, radius) result(m)
    real(dp), intent(in) :: mass, inertia, radius
    real(dp) :: m(6)
    m(1:3) = mass
    m(4:6) = (inertia/radius)/radius
  end function dof_masses

  !> a(n, at least m), reallocated only when it has not n rows or fewer
  !> than m columns (contents undefined).
  pure subroutine fit_columns(a, n, m)
    real(dp), allocatable, intent(inout) :: a(:, :)
    integer, intent(in) :: n, m
    if (allocated(a)) then
      if (size(a, 1) /= n .or. size(a, 2) < m) deallocate(a)
    end if
    if (.not. allocated(a)) allocate(a(n, m))
  end subroutine fit_columns

  !> a(m, lo:hi), reallocated only when its shape differs (contents undefined).
  pure subroutine fit_real2(a, m, lo, hi)
    real(dp), allocatable, intent(inout) :: a(:, :)
    integer, intent(in) :: m, lo, hi
    if (allocated(a)) then
      if (size(a, 1) /= m .or. lbound(a, 2) /= lo .or. ubound(a, 2) /= max(hi, lo - 1)) deallocate(a)
    end if
    if (.not. allocated(a)) allocate(a(m, lo:hi))
  end subroutine fit_real2

  !> a(n), reallocated only when its size differs (contents undefined).
  pure subroutine fit_int1(a, n)
    integer, allocatable, intent(inout) :: a(:)
    integer, intent(in) :: n
    if (allocated(a)) then
      if (size(a) /= n) deallocate(a)
    end if
    if (.not. allocated(a)) allocate(a(n))
  end subroutine fit_int1

  !> a(m, n), reallocated only when its shape differs (contents undefined).
  pure subroutine fit_int2(a, m, n)
    integer, allocatable, intent(inout) :: a(:, :)
    integer, intent(in) :: m, n
    if (allocated(a)) then
      if (size(a, 1) /= m .or. size(a, 2) /= n) deallocate(a)
    end if
    if (.not. allocated(a)) allocate(a(m, n))
  end subroutine fit_int2

  !> Every interaction of the scene, linearised at the current configuration
  !> (`mode`: a `hertz_linearization` code, with `v_impact`; `geo`: with the
  !> pre-stress F_n/l), with its dashpots: bonds, particle contacts, wall
  !> contacts and (with damping and a drag) one drag spring to the ground per
  !> free particle.
  !> Counted, allocated once and filled (linear in interactions).
  subroutine linearise(scene, mode, v_impact, geo, springs, status)
    type(scene_type), intent(in) :: scene
    integer, intent(in) :: mode
    real(dp), intent(in) :: v_impact
    logical, intent(in) :: geo
    type(spring_block_type), allocatable, intent(out) :: springs(:)
    type(demstep_status_type), intent(out) :: status
    integer, allocatable :: pi(:), pj(:), pc(:), place(:)
    real(dp), allocatable :: pn(:, :), pd(:)
    integer :: k, i, j, w, m, n_contacts, n_walls, n_drag, bad
    real(dp) :: overlap, d, f_n, kc(4), rs, l, e_pair, f_now, k_now(4)
    type(bond_law_type) :: law
    logical :: damped
    damped = scene%effects(scene_effect%damping)
    m = size(scene%bonds, 2)
    n_contacts = 0
    n_walls = 0
    n_drag = 0
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
    if (damped .and. scene%drag > 0.0_dp) n_drag = count(.not. scene%fixed)
    allocate(springs(m + n_contacts + n_walls + n_drag))
    do k = 1, m
      i = scene%bonds(1, k)
      j = scene%bonds(2, k)
      if (scene%bond_model > 0) then
        ! a code's bond: the kernel's four springs at the model's arms, its dashpots
        law = scene_bond_law(scene, k)
        springs(k) = spring_block_type(a=i, b=j, k=law%k, c=law%c, arm_a=law%arm(1), arm_b=law%arm(2), &
          n=scene%bond_normal(:, k), kind=5, m_eff=effective_mass(scene, j, i))
        cycle
      end if
      springs(k) = spring_block_type(a=i, b=j, k=[scene%k_bond, scene%k_bond_tangential, 0.0_dp, 0.0_dp], &
        n=scene%bond_normal(:, k), kind=5, m_eff=effective_mass(scene, j, i))
      if (damped) springs(k)%c(1) = dashpot_coefficient(scene%damping_ratio, effective_mass(scene, i, j), &
        scene%k_bond)
    end do
    if (scene%effects(scene_effect%contacts)) then
      ! (each contact's spring at its place in the list, known ahead: the
      ! contacts in parallel, the first overflow in list order refused)
      allocate(place(size(pi)))
      do k = 1, size(pi)
        place(k) = 0
        if (scene%fixed(pi(k)) .and. scene%fixed(pj(k))) cycle
        m = m + 1
        place(k) = m
      end do
      bad = huge(bad)
      !$omp parallel do private(k, i, j, rs, e_pair, d, f_n, kc, f_now, k_now, l) reduction(min:bad) &
      !$omp schedule(static) if(size(pi) >= parallel_springs)
      do k = 1, size(pi)
        if (place(k) == 0) cycle
        i = pi(k)
        j = pj(k)
        rs = reduced_radius(scene%radius(i), scene%radius(j))
        ! the pair's E* (per-type materials) or the scene's
        e_pair = scene%e_star
        if (allocated(scene%ptype)) e_pair = scene%pair_law(3, scene%ptype(i), scene%ptype(j))
        d = linearisation_overlap(scene, pc(k), pd(k), rs, effective_mass(scene, i, j), mode, v_impact, e_pair)
        call contact_values(scene, pc(k), i, j, d, f_n, kc)
        if (.not. all(ieee_is_finite(kc))) then
          bad = min(bad, k)
          cycle
        end if
        springs(place(k)) = spring_block_type(a=i, b=j, k=kc, c=contact_dashpots(scene, pc(k), i, j, kc), &
          n=pn(:, k), arm_a=contact_arm(scene%radius(i), pd(k)), arm_b=contact_arm(scene%radius(j), pd(k)), &
          m_eff=effective_mass(scene, j, i))
        if (geo) then
          ! F_n at the current overlap over the branch length
          call contact_values(scene, pc(k), i, j, pd(k), f_now, k_now)
          l = scene%radius(i) + scene%radius(j) - pd(k)
          springs(place(k))%geo = f_now/l
        end if
      end do
      !$omp end parallel do
      if (bad <= size(pi)) then
        call stiffness_overflow(pi(bad), pj(bad))
        return
      end if
    end if
    if (scene%effects(scene_effect%walls)) then
      do w = 1, size(scene%wall_normal, 2)
        do i = 1, scene%n
          if (scene%fixed(i)) cycle
          overlap = wall_overlap(scene%x(:, i), scene%radius(i), scene%wall_point(:, w), scene%wall_normal(:, w))
          if (.not. overlap > 0.0_dp) cycle
          d = linearisation_overlap(scene, 0, overlap, scene%radius(i), scene%mass(i), mode, v_impact, &
            scene%e_star)
          call wall_values(scene, i, d, f_n, kc)
          if (.not. all(ieee_is_finite(kc))) then
            call stiffness_overflow(i, 0)
            return
          end if
          m = m + 1
          springs(m) = spring_block_type(a=0, b=i, k=kc, c=contact_dashpots(scene, 0, i, 0, kc), &
            n=scene%wall_normal(:, w), arm_b=contact_arm(scene%radius(i), overlap), &
            m_eff=effective_mass(scene, i, 0))
        end do
      end do
    end if
    if (n_drag > 0) then
      do i = 1, scene%n
        if (scene%fixed(i)) cycle
        m = m + 1
        ! F = -drag v on the translations: a dashpot to the ground in every direction
        springs(m) = spring_block_type(a=0, b=i, c=[scene%drag, scene%drag, 0.0_dp, 0.0_dp], &
          n=[1.0_dp, 0.0_dp, 0.0_dp], kind=6)
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
      if (mode /= hertz_linearization%current) then
        call set_status(status, demstep_stat%invalid_input, "the Hertz tangent stiffness " &
          //"2 E* sqrt(R* d) of "//who//" overflows (lower e_star or impact_velocity)", where="e_star")
      else
        call set_status(status, demstep_stat%invalid_input, "the Hertz tangent stiffness " &
          //"2 E* sqrt(R* d) of "//who//" overflows (lower e_star)", where="e_star")
      end if
    end subroutine stiffness_overflow
  end subroutine linearise

  !> The overlap a contact is linearised at: the current one, or (Hertz, detected
  !> contacts) the largest overlap of an impact at v_impact (or the larger of
  !> the two),
  !> d = (15 m* v^2/(16 E* sqrt(R*)))^(2/5) (through logarithms: no overflow).
  pure real(dp) function linearisation_overlap(scene, c, overlap, rs, m_eff, mode, v_impact, e_star) result(d)
    type(scene_type), intent(in) :: scene
    integer, intent(in) :: c, mode
    !> E* of the pair (per-type materials) or of the scene.
    real(dp), intent(in) :: overlap, rs, m_eff, v_impact, e_star
    d = overlap
    if (c == 0 .and. scene%law == contact_law%hertz .and. mode /= hertz_linearization%current) then
      d = exp(0.4_dp*(log(15.0_dp/16.0_dp) + log(m_eff) + 2.0_dp*log(v_impact) - log(e_star) &
        - 0.5_dp*log(rs)))
      if (mode == hertz_linearization%larger) d = max(d, overlap)
    end if
  end function linearisation_overlap

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
      call set_status(status, demstep_stat%invalid_input, "must be finite and > 0", where="n_per_period")
      return
    end if
    omega = crit%omega_bound
    if (crit%eigen_computed) omega = crit%omega_max
    if (crit%eigen_computed .and. .not. crit%eigen_converged) omega = crit%omega_upper
    dt = 2.0_dp*pi/omega/n_per_period
    if (.not. ieee_is_finite(dt)) then
      dt = 0.0_dp
      call set_status(status, demstep_stat%invalid_input, "the time step 2 pi/(omega_max " &
        //"n_per_period) overflows: n_per_period must be above "// &
        real_text(2.0_dp*pi/crit%omega_bound/huge(1.0_dp)), where="n_per_period")
      return
    end if
    status%stat = demstep_stat%ok
  end subroutine assembly_step_for_n_per_period

  !> The `hertz_linearization` code of a word (case ignored); 0 for another word.
  pure integer function hertz_linearization_from_name(name) result(code)
    !> The word, one of `hertz_linearization_names`.
    character(len=*), intent(in) :: name
    code = word_index(hertz_linearization_names, name)
  end function hertz_linearization_from_name

  !> The word of a `hertz_linearization` code (`?` for another value).
  pure function hertz_linearization_name(code) result(name)
    !> A code of `hertz_linearization`.
    integer, intent(in) :: code
    character(len=:), allocatable :: name
    name = word_of(hertz_linearization_names, code)
  end function hertz_linearization_name

  !> The `safe_basis` code of a word (case ignored); 0 for another word.
  pure integer function safe_basis_from_name(name) result(code)
    !> The word, one of `safe_basis_names`.
    character(len=*), intent(in) :: name
    code = word_index(safe_basis_names, name)
  end function safe_basis_from_name

  !> The word of a `safe_basis` code (`?` for another value).
  pure function safe_basis_name(code) result(name)
    !> A code of `safe_basis`.
    integer, intent(in) :: code
    character(len=:), allocatable :: name
    name = word_of(safe_basis_names, code)
  end function safe_basis_name

  !> What a result's `dt_critical_safe` rests on, in words (for a report).
  pure function safe_basis_note(result) result(note)
    type(critical_step_type), intent(in) :: result
    character(len=:), allocatable :: note
    select case (result%safe_basis)
    case (1)
      note = "the whole spectrum (dense): no eigenvalue above omega_upper^2"
    case (2)
      note = "certified: no eigenvalue above omega_upper^2 but with probability <= " &
        //real_text(result%safe_failure)//" (randomised Lanczos bound)"
    case (3)
      note = "the rigorous bound"
    case default
      note = "an estimate to the tolerance " &
        //real_text(result%eigen_tolerance)//", not certified: keep the recommended step's margin"
    end select
  end function safe_basis_note

  !> The `eigen_solver` code of a word (case ignored); 0 for another word.
  pure integer function eigen_solver_from_name(name) result(code)
    !> The word, one of `eigen_solver_names`.
    character(len=*), intent(in) :: name
    code = word_index(eigen_solver_names, name)
  end function eigen_solver_from_name

  !> The word of a `eigen_solver` code (`?` for another value).
  pure function eigen_solver_name(code) result(name)
    !> A code of `eigen_solver`.
    integer, intent(in) :: code
    character(len=:), allocatable :: name
    name = word_of(eigen_solver_names, code)
  end function eigen_solver_name

end module demstep_assembly
