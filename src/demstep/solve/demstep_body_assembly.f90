!> The stability limit of a scene of rigid bodies (clumps, multispheres).
!>
!> The scene's interactions are linearised as for single spheres
!> (`linearise`: the same tangent blocks of `contact_product`) between member
!> spheres; interactions between members of one body are internal and drop
!> out. A member's displacement and rotation follow its body's (u, theta):
!> u_m = u + theta x d_m, theta_m = theta (d_m = x_m - x_com), i.e. the rigid
!> map T_m = [I, -[d_m]x; 0, I], so the body stiffness is T^T K T and a
!> member's force f and torque t act on its body as f and t + d_m x f. The
!> mass matrix per body is diag(M, M, M, J) with J the full inertia tensor
!> about the centre of mass (global axes); the operator is
!> A = W T^T K T W with W = M^-1/2 per body, its rotational block
!> J^-1/2 = V diag(lambda^-1/2) V^T from J's eigen-decomposition (LAPACK).
!> Degrees of freedom per free body: dim translations and (with the
!> `rotation` effect) theta_z in 2D or three rotations in 3D. The limits
!> (per-contact rule, rigorous bound, exact undamped and damped) are those of
!> `demstep_assembly` on this operator: the same estimates, Newton steps and
!> eigensolvers (dense LAPACK or matrix-free Lanczos).
!>
!> Scaled units: stiffness over the largest spring stiffness, masses over the
!> smallest body mass or principal moment over l^2, lengths over l (the
!> largest particle radius), rotations as l theta. A scene of one-member
!> bodies gives the same operator as `demstep_assembly` (up to this scaling).
!> The pre-stress term and the Hertz impact linearisation are not offered:
!> contacts are linearised at their current overlap.
!>
!> Yade's `GlobalStiffnessTimeStepper` on the same bodies is `body_gst_step`,
!> exaDEM's rule `body_exadem_step`.
module demstep_body_assembly
  use demstep_kinds, only: dp, i8
  use demstep_status, only: demstep_status_type, demstep_stat, set_status
  use demstep_text, only: int_text
  use demstep_interaction, only: contact_block, contact_product_arms, dof_components, reduced_mass, cross
  use demstep_scene_data, only: scene_type, scene_effect
  use demstep_bodies, only: body_set_type, check_bodies
  use demstep_bonds, only: exadem_step
  use demstep_assembly, only: critical_step_type, spring_block_type, damped_problem_type, linearise, &
    hertz_linearization, eigen_solver, default_max_eigen_dof, scene_lanczos_ncv, scene_lanczos_restarts, &
    assembly_check_options, assembly_set_bound, assembly_set_estimates, &
    assembly_set_damped, assembly_set_springs, damped_newton, damped_lower_bound, top_eigenpair, cold_top_eigenpair, &
    collatz_bound
  use demstep_lanczos, only: lanczos_context_type, lanczos_tolerance_default
  use demstep_lapack, only: symmetric_eigensystem
  use demstep_csr, only: csr_matrix_type, csr_abs_product
  use demstep_sort, only: bucket_starts
  use demstep_progress, only: progress_type
  implicit none
  private

  public :: body_critical_steps, body_operator, body_operator_apply, body_matrix, body_gst_step, &
    body_exadem_step, inverse_sqrt_inertia

  !> Yade's constant in `GlobalStiffnessTimeStepper` (1.41044, "sqrt(2)" in
  !> its source: pkg/dem/GlobalStiffnessTimeStepper.cpp:102).
  real(dp), parameter, public :: yade_gst_factor = 1.41044_dp

  !> Below this many springs an operator product runs on one thread.
  integer, parameter :: parallel_springs = 4096

  !> The mass-scaled stiffness W T^T K T W of rigid bodies as a matrix-free
  !> operator (a Lanczos context): O(springs) per product.
  type, extends(lanczos_context_type), public :: body_operator_type
    !> Order, dof per free body, free bodies, springs.
    integer :: n = 0, nc = 0, n_bodies = 0, n_springs = 0
    !> The components (of u(1:3), l theta(4:6)) that are degrees of freedom.
    integer, allocatable :: comp(:)
    !> Free body of each end of each spring (0: ground, a wall or fixed).
    integer, allocatable :: ends(:, :)
    !> What a product reads of each spring, contiguous (13, springs): its
    !> unit normal n, the arms from each end's body centre to the contact
    !> point (c_a = d_a + arm_a n, c_b = d_b - arm_b n, over l) and its
    !> (k_n, k_t, k_r, k_w) scaled; its dashpots (c_n, c_t, c_r, c_w) scaled
    !> (size 0: none).
    real(dp), allocatable :: spring(:, :), dcoef(:, :)
    !> For the compressed rows (`body_block`): each spring end's member
    !> offset d_m from its body's centre (3, 2, springs) and the member's
    !> arm to the contact point (2, springs), over l.
    real(dp), allocatable :: lever(:, :, :), arm(:, :)
    !> 1/l (unscaled): the rotation scale of l theta.
    real(dp) :: rot = 1.0_dp
    !> The operator is alpha A' + beta B'.
    real(dp) :: alpha = 1.0_dp, beta = 0.0_dp
    !> M'^-1/2 per free body: translational, and the rotational 3 x 3 block.
    real(dp), allocatable :: wt(:), wr(:, :, :)
    !> Spring ends at each free body (as `assembly_operator_type`): the first
    !> of each body's run, and the runs.
    integer(i8), allocatable :: first(:)
    !> The spring ends of the runs (2 (spring - 1) + end).
    integer, allocatable :: incident(:)
    !> The work arrays: each spring end's generalised force on its body, each body's
    !> scaled displacement (column 0: the ground).
    real(dp), allocatable :: work(:, :), xs(:, :)
  end type body_operator_type

  !> The damped-limit problem of a body operator (see `damped_newton`).
  type, extends(damped_problem_type) :: body_damped_type
    type(body_operator_type), pointer :: op => null()
    integer :: choice = 0
    integer :: ncv = scene_lanczos_ncv
    real(dp), allocatable :: vec(:)
  contains
    procedure :: top => body_damped_top
  end type body_damped_type

contains

  !> The critical time steps of a scene of rigid bodies at its current
  !> configuration: the fields of `critical_step_type` as
  !> `assembly_critical_steps` fills them, per body (dof_per_particle: dof
  !> per body); the per-contact rule takes the bodies' reduced mass. Status
  !> invalid_input naming `eigen_solver`, `tolerance`, the damping values,
  !> `bodies` (not made for this scene), `inertia` (a singular tensor),
  !> `position` (no free body touches a spring), `fixed`; lapack_failure;
  !> the Lanczos solver's statuses.
  subroutine body_critical_steps(scene, bodies, result, status, solver, tolerance, max_eigen_dof, progress)
    type(scene_type), intent(in) :: scene
    type(body_set_type), intent(in) :: bodies
    type(critical_step_type), intent(out) :: result
    type(demstep_status_type), intent(out) :: status
    !> `eigen_solver%auto` (default), `%dense`, `%lanczos` or `%none`.
    integer, intent(in), optional :: solver
    !> The Lanczos relative residual tolerance (default `lanczos_tolerance_default`).
    real(dp), intent(in), optional :: tolerance
    !> With `eigen_solver%auto`: the largest problem given to the dense solver.
    integer, intent(in), optional :: max_eigen_dof
    class(progress_type), intent(inout), optional :: progress
    type(body_operator_type), target :: op
    type(spring_block_type), allocatable :: springs(:)
    type(body_damped_type) :: problem
    real(dp), allocatable :: vec(:), y(:)
    real(dp) :: rate, tol, lam, err, b_bound, va, vb, upper, failure
    integer :: choice, limit, basis
    logical :: has_mode, converged
    choice = eigen_solver%auto
    if (present(solver)) choice = solver
    tol = lanczos_tolerance_default
    if (present(tolerance)) tol = tolerance
    limit = default_max_eigen_dof
    if (present(max_eigen_dof)) limit = max_eigen_dof
    if (choice < eigen_solver%auto .or. choice > eigen_solver%none) then
      call set_status(status, demstep_stat%invalid_input, "must be 'auto', 'dense', 'lanczos' or 'none'", &
        where="eigen_solver")
      return
    end if
    call assembly_check_options(scene, tol, status)
    if (status%stat /= demstep_stat%ok) return
    call body_operator(scene, bodies, op, rate, status, springs)
    if (status%stat /= demstep_stat%ok) return
    result%rotation = scene%effects(scene_effect%rotation) .and. scene%dim > 1
    result%periodic = any(scene%periodic)
    result%dof_per_particle = op%nc
    result%n_dof = op%n
    call assembly_set_springs(result, springs)
    call assembly_set_bound(result, rate, body_bound(op), status)
    if (status%stat /= demstep_stat%ok) return
    b_bound = 0.0_dp
    if (size(op%dcoef, 2) > 0) then
      op%alpha = 0.0_dp
      op%beta = 1.0_dp
      b_bound = body_bound(op)
      op%alpha = 1.0_dp
      op%beta = 0.0_dp
    end if
    if (choice == eigen_solver%auto) then
      choice = eigen_solver%lanczos
      if (op%n <= limit) choice = eigen_solver%dense
    end if
    result%solver = choice
    if (choice == eigen_solver%none) then
      call assembly_set_damped(result, result%dt_critical_bound, b_bound, rate, status)
      return
    end if
    allocate(vec(op%n), source=0.0_dp)
    ! (the body operator is semi-definite: no pre-stress; the certificate
    ! unshifted)
    call top_eigenpair(op, body_operator_apply, body_matrix_of, op%n, choice, tol, vec, lam, err, has_mode, &
      result%eigen_products, result%eigen_restarts, status, progress, scene_lanczos_ncv, converged, &
      0.0_dp, upper, failure, basis=basis)
    if (status%stat /= demstep_stat%ok) return
    result%eigen_tolerance = tol
    if (choice == eigen_solver%dense) result%eigen_tolerance = epsilon(1.0_dp)
    call assembly_set_estimates(result, rate, lam, err, converged, b_bound, status, upper, basis, failure)
    if (status%stat /= demstep_stat%ok) return
    if (.not. (b_bound > 0.0_dp .and. has_mode)) return
    ! the exact damped limit: Newton from the undamped mode's quadratic
    allocate(y(op%n))
    call body_operator_apply(op, vec, y)
    va = dot_product(vec, y)
    op%alpha = 0.0_dp
    op%beta = 1.0_dp
    call body_operator_apply(op, vec, y)
    vb = dot_product(vec, y)
    op%alpha = 1.0_dp
    op%beta = 0.0_dp
    problem%op => op
    problem%choice = choice
    problem%vec = vec
    ! (the undamped top is certified: its damped steps are confirmed cold)
    problem%confirm_cold = choice /= eigen_solver%dense
    call damped_newton(problem, va, vb, rate, tol, result, status, progress)
    op%alpha = 1.0_dp
    op%beta = 0.0_dp
  end subroutine body_critical_steps

  !> The body operator of a scene (see the module's notes), `rate`: omega =
  !> rate sqrt(lambda), and the springs between bodies (member ends, each
  !> `m_eff` the two bodies' reduced mass). Status invalid_input naming
  !> `bodies`, `inertia` (singular: a body must resist rotation about every
  !> axis it may turn about) or `position` (no free body touches a spring);
  !> lapack_failure.
  subroutine body_operator(scene, bodies, op, rate, status, springs)
    type(scene_type), intent(in) :: scene
    type(body_set_type), intent(in) :: bodies
    type(body_operator_type), intent(out) :: op
    real(dp), intent(out) :: rate
    type(demstep_status_type), intent(out) :: status
    type(spring_block_type), allocatable, intent(out) :: springs(:)
    type(spring_block_type), allocatable :: found(:)
    integer, allocatable :: free(:), member(:, :)
    integer, allocatable :: ends_at(:)
    integer(i8), allocatable :: next(:)
    real(dp), allocatable :: lam(:, :), vecs(:, :, :)
    real(dp) :: k_scale, m_scale, c_scale, ell, mb(2)
    integer :: b, s, e, i, nfree, ns, ba, bb, rot_dim
    logical :: keep
    rate = 0.0_dp
    call check_bodies(scene, bodies, status)
    if (status%stat /= demstep_stat%ok) return
    op%comp = dof_components(scene%dim, scene%effects(scene_effect%rotation) .and. scene%dim > 1)
    op%nc = size(op%comp)
    ! the dimension the rotations see (0: none)
    rot_dim = 0
    if (op%nc > scene%dim) rot_dim = scene%dim
    ell = maxval(scene%radius)
    op%rot = 1.0_dp/ell
    ! free bodies, and each one's inertia eigen-decomposition (over l^2)
    allocate(free(0:bodies%n), source=0)
    allocate(lam(3, bodies%n), vecs(3, 3, bodies%n))
    nfree = 0
    m_scale = huge(1.0_dp)
    do b = 1, bodies%n
      if (bodies%fixed(b)) cycle
      nfree = nfree + 1
      free(b) = nfree
      call body_inertia_eigen(rot_dim, bodies%inertia(:, :, b)/ell**2, lam(:, b), vecs(:, :, b), status)
      if (status%stat /= demstep_stat%ok) then
        call set_status(status, demstep_stat%invalid_input, "the inertia tensor of body "//int_text(b) &
          //" is singular or not positive definite", where="inertia", index=b)
        return
      end if
      m_scale = min(m_scale, bodies%mass(b))
      if (rot_dim > 0) m_scale = min(m_scale, minval(lam(:, b), mask=lam(:, b) > 0.0_dp))
    end do
    if (nfree == 0) then
      call set_status(status, demstep_stat%invalid_input, "every body is fixed: the scene has no " &
        //"stiffness", where="fixed")
      return
    end if
    ! the scene's springs between members, kept between different bodies
    call linearise(scene, hertz_linearization%current, 0.0_dp, .false., found, status)
    if (status%stat /= demstep_stat%ok) return
    allocate(member(2, size(found)))
    ns = 0
    k_scale = 0.0_dp
    do s = 1, size(found)
      ba = 0
      if (found(s)%a > 0) ba = bodies%body_of(found(s)%a)
      bb = bodies%body_of(found(s)%b)
      keep = ba /= bb .and. (free(ba) > 0 .or. free(bb) > 0)
      if (found(s)%kind == 6) keep = free(bb) > 0
      if (.not. keep) cycle
      ns = ns + 1
      found(ns) = found(s)
      member(:, ns) = [found(s)%a, found(s)%b]
      mb = huge(1.0_dp)
      if (free(ba) > 0) mb(1) = bodies%mass(ba)
      if (free(bb) > 0) mb(2) = bodies%mass(bb)
      found(ns)%m_eff = reduced_mass(mb(1), mb(2))
      if (found(ns)%kind /= 6) k_scale = max(k_scale, found(ns)%k(1), found(ns)%k(2))
    end do
    springs = found(:ns)
    if (.not. k_scale > 0.0_dp) then
      call set_status(status, demstep_stat%invalid_input, "the scene has no stiffness: no free body " &
        //"touches a bond, a contact or a wall of another body", where="position")
      return
    end if
    ! the operator's arrays, scaled
    op%n_bodies = nfree
    op%n = nfree*op%nc
    op%n_springs = ns
    allocate(op%ends(2, ns), op%spring(13, ns), op%lever(3, 2, ns), op%arm(2, ns))
    allocate(op%wt(nfree), op%wr(3, 3, nfree), op%work(6, 2*ns), ends_at(nfree))
    allocate(op%xs(6, 0:nfree), source=0.0_dp)
    if (any(springs%c(1) > 0.0_dp .or. springs%c(2) > 0.0_dp .or. springs%c(3) > 0.0_dp .or. &
        springs%c(4) > 0.0_dp)) then
      allocate(op%dcoef(4, ns))
    else
      allocate(op%dcoef(4, 0))
    end if
    c_scale = sqrt(k_scale)*sqrt(m_scale)
    do b = 1, bodies%n
      i = free(b)
      if (i == 0) cycle
      op%wt(i) = 1.0_dp/sqrt(bodies%mass(b)/m_scale)
      op%wr(:, :, i) = 0.0_dp
      do e = 1, 3
        if (lam(e, b) > 0.0_dp) op%wr(:, :, i) = op%wr(:, :, i) + spread(vecs(:, e, b), 2, 3) &
          *spread(vecs(:, e, b), 1, 3)/sqrt(lam(e, b)/m_scale)
      end do
    end do
    ends_at = 0
    do s = 1, ns
      associate(sp => springs(s))
        op%arm(:, s) = [sp%arm_a, sp%arm_b]/ell
        if (size(op%dcoef, 2) > 0) op%dcoef(:, s) = sp%c/c_scale
        do e = 1, 2
          op%ends(e, s) = 0
          op%lever(:, e, s) = 0.0_dp
          if (member(e, s) == 0) cycle
          op%ends(e, s) = free(bodies%body_of(member(e, s)))
          if (op%ends(e, s) == 0) cycle
          op%lever(:, e, s) = bodies%offset(:, member(e, s))/ell
          ends_at(op%ends(e, s)) = ends_at(op%ends(e, s)) + 1
        end do
        op%spring(:, s) = [sp%n, op%lever(:, 1, s) + op%arm(1, s)*sp%n, op%lever(:, 2, s) - op%arm(2, s)*sp%n, &
          sp%k/k_scale]
      end associate
    end do
    ! each body's spring ends, in spring order (a counting sort)
    op%first = bucket_starts(ends_at)
    allocate(op%incident(op%first(nfree + 1) - 1), next(nfree))
    next = op%first(:nfree)
    do s = 1, ns
      do e = 1, 2
        i = op%ends(e, s)
        if (i == 0) cycle
        op%incident(next(i)) = 2*(s - 1) + e
        next(i) = next(i) + 1
      end do
    end do
    rate = sqrt(k_scale)/sqrt(m_scale)
    status%stat = demstep_stat%ok
  end subroutine body_operator

  !> Eigenvalues (ascending) and eigenvectors of the part of an inertia
  !> tensor that rotations of a `dim`-dimensional body see: all of it in 3D,
  !> J_zz in 2D (the other entries 0), nothing for dim 0 or 1 (no rotations). Status invalid_input
  !> when an eigenvalue seen is not positive; lapack_failure.
  subroutine body_inertia_eigen(dim, j, lam, v, status)
    integer, intent(in) :: dim
    real(dp), intent(in) :: j(3, 3)
    real(dp), intent(out) :: lam(3), v(3, 3)
    type(demstep_status_type), intent(out) :: status
    real(dp) :: a(3, 3)
    lam = 0.0_dp
    v = 0.0_dp
    status%stat = demstep_stat%ok
    if (dim == 3) then
      a = j
      call symmetric_eigensystem(a, lam, v, status)
      if (status%stat /= demstep_stat%ok) return
      ! (positive definite to the working precision of its largest eigenvalue)
      if (.not. lam(1) > 8.0_dp*epsilon(1.0_dp)*lam(3)) &
        call set_status(status, demstep_stat%invalid_input, "singular inertia tensor", where="inertia")
    else if (dim == 2) then
      lam(3) = j(3, 3)
      v(3, 3) = 1.0_dp
      if (.not. lam(3) > 0.0_dp) &
        call set_status(status, demstep_stat%invalid_input, "singular inertia tensor", where="inertia")
    end if
  end subroutine body_inertia_eigen

  !> J^-1/2 of a symmetric positive definite inertia tensor J, from its
  !> eigen-decomposition V diag(lambda) V^T (LAPACK): V diag(lambda^-1/2) V^T.
  !> Status invalid_input naming `inertia` when J is singular; lapack_failure.
  subroutine inverse_sqrt_inertia(j, s, status)
    real(dp), intent(in) :: j(3, 3)
    real(dp), intent(out) :: s(3, 3)
    type(demstep_status_type), intent(out) :: status
    real(dp) :: lam(3), v(3, 3)
    integer :: e
    s = 0.0_dp
    call body_inertia_eigen(3, j, lam, v, status)
    if (status%stat /= demstep_stat%ok) return
    do e = 1, 3
      s = s + spread(v(:, e), 2, 3)*spread(v(:, e), 1, 3)/sqrt(lam(e))
    end do
  end subroutine inverse_sqrt_inertia

  !> The coefficients (k_n, k_t, k_r, k_w) of spring s in alpha A' + beta B'.
  pure function mixed(op, s) result(k)
    type(body_operator_type), intent(in) :: op
    integer, intent(in) :: s
    real(dp) :: k(4)
    k = op%alpha*op%spring(10:13, s)
    if (op%beta /= 0.0_dp) k = k + op%beta*op%dcoef(:, s)
  end function mixed

  !> y = A' x (mixed: (alpha A' + beta B') x) for a `body_operator_type`:
  !> each body's scaled displacement W x, each spring's generalised forces
  !> on its two bodies (`contact_product_arms`: the kernel with the rigid map
  !> fused in), each body's sum in spring order, times W. Parallel under
  !> OpenMP with fixed summation orders: the same result for every thread
  !> count. O(springs).
  subroutine body_operator_apply(context, x, y)
    class(lanczos_context_type), intent(inout) :: context
    real(dp), intent(in) :: x(:)
    real(dp), intent(out) :: y(:)
    integer :: i, c, s, nc
    integer(i8) :: p
    real(dp) :: r(3), acc(6)
    y = 0.0_dp
    select type (op => context)
    class is (body_operator_type)
      nc = op%nc
      !$omp parallel do private(i, c, r) schedule(static) if(op%n_springs >= parallel_springs)
      do i = 1, op%n_bodies
        if (nc == 6) then
          ! 3D with rotations (every component a dof)
          op%xs(1:3, i) = op%wt(i)*x(6*i - 5:6*i - 3)
          op%xs(4:6, i) = op%wr(:, 1, i)*x(6*i - 2) + op%wr(:, 2, i)*x(6*i - 1) + op%wr(:, 3, i)*x(6*i)
          cycle
        end if
        op%xs(:, i) = 0.0_dp
        r = 0.0_dp
        do c = 1, nc
          if (op%comp(c) <= 3) then
            op%xs(op%comp(c), i) = op%wt(i)*x((i - 1)*nc + c)
          else
            r(op%comp(c) - 3) = x((i - 1)*nc + c)
          end if
        end do
        op%xs(4:6, i) = matmul(op%wr(:, :, i), r)
      end do
      !$omp end parallel do
      !$omp parallel do private(s) schedule(static) if(op%n_springs >= parallel_springs)
      do s = 1, op%n_springs
        call contact_product_arms(op%spring(1:3, s), mixed(op, s), op%spring(4:6, s), op%spring(7:9, s), &
          op%rot, op%xs(:, op%ends(1, s)), op%xs(:, op%ends(2, s)), op%work(:, 2*s - 1), op%work(:, 2*s))
      end do
      !$omp end parallel do
      !$omp parallel do private(i, p, c, acc, r) schedule(static) if(op%n_springs >= parallel_springs)
      do i = 1, op%n_bodies
        acc = 0.0_dp
        do p = op%first(i), op%first(i + 1) - 1
          acc = acc + op%work(:, op%incident(p))
        end do
        if (nc == 6) then
          y(6*i - 5:6*i - 3) = op%wt(i)*acc(1:3)
          y(6*i - 2:6*i) = op%wr(:, 1, i)*acc(4) + op%wr(:, 2, i)*acc(5) + op%wr(:, 3, i)*acc(6)
          cycle
        end if
        r = matmul(op%wr(:, :, i), acc(4:6))
        do c = 1, nc
          if (op%comp(c) <= 3) then
            y((i - 1)*nc + c) = op%wt(i)*acc(op%comp(c))
          else
            y((i - 1)*nc + c) = r(op%comp(c) - 3)
          end if
        end do
      end do
      !$omp end parallel do
    end select
  end subroutine body_operator_apply

  !> The 12 x 12 block of spring s on its two bodies' scaled coordinates
  !> (W T^T K T W, K the kernel's `contact_block`, the ground's half zero).
  pure function body_block(op, s) result(g)
    type(body_operator_type), intent(in) :: op
    integer, intent(in) :: s
    real(dp) :: g(12, 12)
    real(dp) :: map(12, 12), kb(12, 12)
    integer :: e, o, b
    kb = contact_block(op%spring(1:3, s), mixed(op, s), op%arm(1, s), op%arm(2, s), 0.0_dp, op%rot, op%rot)
    ! map = blockdiag(T_a W_a, T_b W_b): member motion from scaled body coordinates
    map = 0.0_dp
    do e = 1, 2
      o = 6*(e - 1)
      b = op%ends(e, s)
      if (b == 0) cycle
      map(o + 1, o + 1) = op%wt(b)
      map(o + 2, o + 2) = op%wt(b)
      map(o + 3, o + 3) = op%wt(b)
      map(o + 4:o + 6, o + 4:o + 6) = op%wr(:, :, b)
      ! u_m = u + theta x d = u - [d]x theta
      map(o + 1:o + 3, o + 4:o + 6) = -matmul(skew(op%lever(:, e, s)), op%wr(:, :, b))
    end do
    g = matmul(transpose(map), matmul(kb, map))
  end function body_block

  !> The operator's matrix A' (as mixed) in compressed rows: per free body
  !> its diagonal block, then one block per spring to another free body
  !> (columns may repeat). O(springs) entries.
  subroutine body_matrix(op, matrix)
    type(body_operator_type), intent(in) :: op
    type(csr_matrix_type), intent(out) :: matrix
    real(dp) :: g(12, 12), d(6, 6)
    integer :: i, s, e, o, j, r, q, nc, row
    integer(i8) :: p, pos, width
    nc = op%nc
    matrix%n = op%n
    allocate(matrix%row_start(op%n + 1))
    matrix%row_start(1) = 1
    do i = 1, op%n_bodies
      width = nc
      do p = op%first(i), op%first(i + 1) - 1
        s = (op%incident(p) + 1)/2
        e = op%incident(p) - 2*(s - 1)
        if (op%ends(3 - e, s) > 0) width = width + nc
      end do
      do r = 1, nc
        matrix%row_start((i - 1)*nc + r + 1) = matrix%row_start((i - 1)*nc + r) + width
      end do
    end do
    allocate(matrix%col(matrix%row_start(op%n + 1) - 1), matrix%val(matrix%row_start(op%n + 1) - 1))
    do i = 1, op%n_bodies
      row = (i - 1)*nc
      d = 0.0_dp
      pos = nc
      do p = op%first(i), op%first(i + 1) - 1
        s = (op%incident(p) + 1)/2
        e = op%incident(p) - 2*(s - 1)
        g = body_block(op, s)
        d = d + g(6*(e - 1) + 1:6*e, 6*(e - 1) + 1:6*e)
        o = 3 - e
        j = op%ends(o, s)
        if (j == 0) cycle
        do r = 1, nc
          do q = 1, nc
            matrix%col(matrix%row_start(row + r) + pos + q - 1) = (j - 1)*nc + q
            matrix%val(matrix%row_start(row + r) + pos + q - 1) = g(6*(e - 1) + op%comp(r), 6*(o - 1) + op%comp(q))
          end do
        end do
        pos = pos + nc
      end do
      do r = 1, nc
        do q = 1, nc
          matrix%col(matrix%row_start(row + r) + q - 1) = row + q
          matrix%val(matrix%row_start(row + r) + q - 1) = d(op%comp(r), op%comp(q))
        end do
      end do
    end do
  end subroutine body_matrix

  !> `body_matrix` for `top_eigenpair` (an `operator_matrix`).
  subroutine body_matrix_of(context, matrix)
    class(lanczos_context_type), intent(inout) :: context
    type(csr_matrix_type), intent(out) :: matrix
    select type (op => context)
    class is (body_operator_type)
      call body_matrix(op, matrix)
    end select
  end subroutine body_matrix_of

  !> The rigorous bound of lambda_max of the operator as mixed: the
  !> Collatz-Wielandt quotients max_i (|A'| v)_i/v_i of the compressed rows'
  !> absolute values (|A'| entrywise; repeated columns summed after the
  !> absolute value, which only raises it; `csr_abs_product`), by
  !> `collatz_bound`, each row raised by its rounding allowance.
  function body_bound(op) result(bound)
    type(body_operator_type), intent(in) :: op
    real(dp) :: bound
    type(csr_matrix_type) :: a
    call body_matrix(op, a)
    bound = collatz_bound(a, op%n, csr_abs_product)
  end function body_bound

  !> Top eigenpair of the body operator mixed as tau^2 A' + 2 tau B' (warm
  !> start from the previous mode) and v'A'v of that mode.
  subroutine body_damped_top(problem, tau, tol, theta, err, va, has_mode, result, status, progress)
    class(body_damped_type), intent(inout) :: problem
    real(dp), intent(in) :: tau, tol
    real(dp), intent(out) :: theta, err, va
    logical, intent(out) :: has_mode
    type(critical_step_type), intent(inout) :: result
    type(demstep_status_type), intent(out) :: status
    class(progress_type), intent(inout), optional :: progress
    real(dp), allocatable :: y(:)
    problem%op%alpha = tau**2
    problem%op%beta = 2.0_dp*tau
    if (problem%cold) then
      ! the cold confirming solve (`damped_newton`)
      call cold_top_eigenpair(problem%op, body_operator_apply, body_matrix_of, problem%op%n, problem%choice, &
        tol, problem%vec, theta, err, has_mode, result%eigen_products, result%eigen_restarts, status, progress, &
        problem%ncv)
    else
      ! (warm from the previous mode)
      call top_eigenpair(problem%op, body_operator_apply, body_matrix_of, problem%op%n, problem%choice, tol, &
        problem%vec, theta, err, has_mode, result%eigen_products, result%eigen_restarts, status, progress, &
        problem%ncv)
    end if
    problem%op%alpha = 1.0_dp
    problem%op%beta = 0.0_dp
    if (status%stat /= demstep_stat%ok) return
    err = err + 8.0_dp*epsilon(1.0_dp)*theta
    result%damped_solves = result%damped_solves + 1
    allocate(y(problem%op%n))
    call body_operator_apply(problem%op, problem%vec, y)
    va = dot_product(problem%vec, y)
  end subroutine body_damped_top

  !> Yade's `GlobalStiffnessTimeStepper` on a scene of bodies, raw
  !> (`timestepSafetyCoefficient` 1; Yade's default is 0.8). Per contact with
  !> a non-zero normal force (pkg/dem/GlobalStiffnessTimeStepper.cpp:260-262:
  !> the scene's contacts and wall contacts; bonds are left out, as at their
  !> rest length, where they carry none)
  !> each member gets the diagonal translational stiffness
  !> k_n n_a^2 + k_s (1 - n_a^2) and rotational k_s r^2 (1 - n_a^2) +
  !> (k_w - k_r) n_a^2 + k_r, r the member's radius (lines 265-286): about the
  !> member's own centre, global axes. A clump sums its members' values with
  !> no lever arm to its centre of mass (lines 40-52) and divides them by
  !> its mass and its principal moments of inertia (lines 77-101: Yade's
  !> `state->inertia`, the eigenvalues of the inertia tensor in ascending
  !> order, core/Clump.cpp:258-265), whatever the axes;
  !> dt = 1.41044 min over bodies sqrt(min(m/max_a K_a, min_a I_a/R_a))
  !> (line 102; a zero stiffness is skipped). Status invalid_input naming
  !> `position` when no free body has a contact; the statuses of
  !> `body_operator`.
  subroutine body_gst_step(scene, bodies, dt, status)
    type(scene_type), intent(in) :: scene
    type(body_set_type), intent(in) :: bodies
    real(dp), intent(out) :: dt
    type(demstep_status_type), intent(out) :: status
    type(body_operator_type) :: op
    type(spring_block_type), allocatable :: springs(:)
    real(dp), allocatable :: kt(:, :), kr(:, :)
    real(dp) :: rate, nn(3), dt2, lam(3), v(3, 3), a(3, 3)
    integer :: s, e, m, b
    dt = 0.0_dp
    call body_operator(scene, bodies, op, rate, status, springs)
    if (status%stat /= demstep_stat%ok) return
    allocate(kt(3, bodies%n), kr(3, bodies%n), source=0.0_dp)
    do s = 1, size(springs)
      associate(sp => springs(s))
        ! (drag is no interaction; a bond at its rest length has no normal
        ! force, which Yade's rule skips)
        if (sp%kind == 6 .or. sp%kind == 5) cycle
        nn = sp%n**2
        do e = 1, 2
          m = sp%a
          if (e == 2) m = sp%b
          if (m == 0) cycle
          b = bodies%body_of(m)
          kt(:, b) = kt(:, b) + (sp%k(1) - sp%k(2))*nn + sp%k(2)
          kr(:, b) = kr(:, b) + sp%k(2)*scene%radius(m)**2*(1.0_dp - nn) + (sp%k(4) - sp%k(3))*nn + sp%k(3)
        end do
      end associate
    end do
    dt2 = huge(1.0_dp)
    do b = 1, bodies%n
      if (bodies%fixed(b) .or. .not. maxval(kt(:, b)) > 0.0_dp) cycle
      dt2 = min(dt2, bodies%mass(b)/maxval(kt(:, b)))
      a = bodies%inertia(:, :, b)
      call symmetric_eigensystem(a, lam, v, status)
      if (status%stat /= demstep_stat%ok) return
      do e = 1, 3
        if (kr(e, b) > 0.0_dp) dt2 = min(dt2, lam(e)/kr(e, b))
      end do
    end do
    if (dt2 >= huge(1.0_dp)) then
      call set_status(status, demstep_stat%invalid_input, "no free body has a contact", where="position")
      return
    end if
    dt = yade_gst_factor*sqrt(dt2)
    status%stat = demstep_stat%ok
  end subroutine body_gst_step

  !> exaDEM's rule (`exadem_step`) on a scene of bodies, raw: pi sqrt(m/k_n)
  !> with m the lightest free body's mass (a polyhedron or clump is one
  !> particle there) and k_n the largest normal stiffness of the springs
  !> between bodies and on walls (exaDEM takes the largest k_n of its
  !> parameter table: the same for one linear law). Status: those of
  !> `body_operator`; invalid_input (`k_normal`) without a normal stiffness.
  subroutine body_exadem_step(scene, bodies, dt, status)
    type(scene_type), intent(in) :: scene
    type(body_set_type), intent(in) :: bodies
    real(dp), intent(out) :: dt
    type(demstep_status_type), intent(out) :: status
    type(body_operator_type) :: op
    type(spring_block_type), allocatable :: springs(:)
    real(dp) :: rate, k_max
    dt = 0.0_dp
    call body_operator(scene, bodies, op, rate, status, springs)
    if (status%stat /= demstep_stat%ok) return
    k_max = 0.0_dp
    if (any(springs%kind /= 6)) k_max = maxval(springs%k(1), mask=springs%kind /= 6)
    if (.not. k_max > 0.0_dp) then
      ! exaDEM's rule needs a normal stiffness (tangential springs only: none)
      call set_status(status, demstep_stat%invalid_input, "no normal stiffness between bodies or on walls: " &
        //"exaDEM's rule pi sqrt(m/k_n) has none to take", where="k_normal")
      return
    end if
    dt = exadem_step(minval(bodies%mass, mask=.not. bodies%fixed), k_max)
  end subroutine body_exadem_step

  !> [d]x, the matrix of d x . (so that [d]x w = d x w).
  pure function skew(d) result(m)
    real(dp), intent(in) :: d(3)
    real(dp) :: m(3, 3)
    m = reshape([0.0_dp, d(3), -d(2), -d(3), 0.0_dp, d(1), d(2), -d(1), 0.0_dp], [3, 3])
  end function skew

end module demstep_body_assembly
