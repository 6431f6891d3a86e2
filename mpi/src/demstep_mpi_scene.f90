!> The critical time steps of a scene on MPI ranks: the distributed
!> counterpart of `assembly_critical_steps` with `eigen_solver%lanczos`.
!>
!> Input. Every rank holds the whole scene (replicated input) and builds the
!> matrix-free operator from it (`assembly_operator`: O(particles + springs)
!> per rank). For a scene read in parts, each rank holding only its own
!> particles and their contacts, see `demstep_mpi_dist_scene`. What grows with the work is distributed: each rank assembles only
!> the rows of its own bodies (`assembly_matrix_rows`), and holds only its block
!> of every Lanczos vector and its halo.
!>
!> Partition by space. The free bodies are sorted by their coordinate along the
!> axis on which they spread furthest (ties by body number) and cut into
!> contiguous slabs, one per rank in rank order, balanced by count. They are
!> renumbered in that order, so each rank owns a contiguous block of rows and
!> its halo is the bodies across the slab faces.
!>
!> Estimates, as in the serial path: omega_max from PARPACK (the Rayleigh
!> quotient of the returned unit mode, its residual and the error bar
!> `omega_upper`, `dt_critical_safe`); the bound from the rows without
!> pre-stress (`dist_collatz_bound`, the serial bound's Collatz-Wielandt steps);
!> the per-contact rule as a minimum
!> over each rank's springs; the exact damped limit by the serial path's
!> Newton steps (`damped_newton`), each a distributed Lanczos solve of
!> tau^2 A' + 2 tau B' (this rank's rows rebuilt per step, warm-started), the
!> converged steps confirmed by a cold solve as the serial path's
!> (`mpi_damped_lanczos`; the undamped top is always certified here), its
!> lower bound from the dashpots' bound (replicated, O(springs) per rank).
module demstep_mpi_scene
  use mpi_f08
  use demstep_kinds, only: dp, i8
  use demstep_status, only: demstep_status_type, demstep_stat, set_status
  use demstep_text, only: int_text
  use demstep_progress, only: progress_type
  use demstep_scene_data, only: scene_type, scene_effect
  use demstep_interaction, only: reduced_mass
  use demstep_assembly, only: assembly_operator_type, assembly_operator, assembly_matrix_rows, &
    assembly_check_options, assembly_set_bound, assembly_set_estimates, assembly_dashpot_bound, &
    critical_step_type, eigen_solver, scene_lanczos_ncv, scene_lanczos_restarts, bound_iterations, &
    damped_problem_type, damped_newton, dashpot_names, safe_basis
  use demstep_lanczos, only: eigen_result_type, lanczos_tolerance_default, krylov_min_order
  use demstep_mpi_lanczos, only: dist_csr_type, dist_csr_create, dist_csr_apply, dist_csr_free, &
    dist_collatz_bound, parallel_lanczos_largest, dist_operator_type
  implicit none
  private

  public :: mpi_scene_critical_steps, scene_slabs, slab_axis, mpi_lanczos_estimates, mpi_damped_solve_done, &
    mpi_damped_lanczos

  !> The distributed damped-limit problem: this rank's rows of the operator
  !> (mixed per tau, same pattern), the matrix and the last mode's block.
  type, extends(damped_problem_type) :: mpi_damped_type
    type(assembly_operator_type), pointer :: op => null()
    type(dist_csr_type), pointer :: matrix => null()
    integer, allocatable :: bodies(:), new_index(:)
    real(dp), allocatable :: a_val(:), vec(:)
  contains
    procedure :: top => mpi_damped_top
  end type mpi_damped_type

contains

  !> The critical time steps of a scene, computed on the ranks of `comm`.
  !> Collective: every rank passes the same scene and options, and gets the
  !> same result and status. The result is `assembly_critical_steps`' with
  !> `solver = eigen_solver%lanczos` (same Krylov size, restarts, tolerance and
  !> error bar); the bound is the tight Gershgorin bound (diagonal blocks summed)
  !> at every size. Statuses: those of `assembly_critical_steps`, and
  !> invalid_input `comm:` when there are fewer free particles than ranks;
  !> PARPACK's through `parallel_lanczos_largest`.
  subroutine mpi_scene_critical_steps(comm, scene, result, status, hertz_mode, impact_velocity, &
      prestress, tolerance, progress)
    !> The ranks sharing the work.
    type(MPI_Comm), intent(in) :: comm
    !> The whole scene, the same on every rank.
    type(scene_type), intent(in) :: scene
    type(critical_step_type), intent(out) :: result
    type(demstep_status_type), intent(out) :: status
    !> `hertz_linearization%current` (default) or `%impact` with impact_velocity > 0.
    integer, intent(in), optional :: hertz_mode
    real(dp), intent(in), optional :: impact_velocity
    !> Count the pre-stress (geometric) stiffness of loaded contacts (default no).
    logical, intent(in), optional :: prestress
    !> Relative residual tolerance on omega_max^2, in [2.2e-16, 0.1]
    !> (default `lanczos_tolerance_default`).
    real(dp), intent(in), optional :: tolerance
    !> Reports the Lanczos products (pass it on one rank, e.g. rank 0).
    class(progress_type), intent(inout), optional :: progress
    type(assembly_operator_type), target :: op
    type(dist_csr_type), target :: matrix
    integer, allocatable :: order(:), new_index(:), bodies(:), col(:)
    integer(i8), allocatable :: row_start(:)
    real(dp), allocatable :: val(:), geo(:)
    real(dp) :: rate, tol, b_bound
    integer :: i
    integer :: nranks, rank, lo, hi, nc
    logical :: with_geo

    call MPI_Comm_size(comm, nranks)
    call MPI_Comm_rank(comm, rank)
    with_geo = .false.
    if (present(prestress)) with_geo = prestress
    tol = lanczos_tolerance_default
    if (present(tolerance)) tol = tolerance
    call assembly_check_options(scene, tol, status)
    if (status%stat /= demstep_stat%ok) return
    ! replicated: every rank builds the same operator and gets the same status
    call assembly_operator(scene, op, rate, status, hertz_mode, impact_velocity, with_geo)
    if (status%stat /= demstep_stat%ok) return
    if (op%n_bodies < nranks) then
      call set_status(status, demstep_stat%invalid_input, "comm: each MPI rank needs a " &
        //"free particle: the scene has "//int_text(op%n_bodies)//" for "//int_text(nranks) &
        //" ranks (run it on at most "//int_text(op%n_bodies)//")")
      return
    end if
    nc = op%nc
    result%rotation = scene%effects(scene_effect%rotation) .and. scene%dim > 1
    result%periodic = any(scene%periodic)
    result%prestress = with_geo
    result%dof_per_particle = nc
    result%n_dof = op%n
    result%n_springs = op%n_springs
    result%tangential = any(op%coef(2, :) > 0.0_dp)
    result%n_springs = op%n_springs - merge(count(op%ends(1, :) == 0 .and. op%coef(1, :) == 0.0_dp .and. &
      op%coef(2, :) == 0.0_dp), 0, scene%drag > 0.0_dp .and. scene%effects(scene_effect%damping))
    if (size(op%dcoef, 2) > 0) then
      do i = 1, 4
        result%dashpots(i) = any(op%dcoef(i, :) > 0.0_dp)
      end do
    end if
    result%dashpots(5) = size(scene%bonds, 2) > 0 .and. result%dashpots(1)
    result%dashpots(6) = scene%drag > 0.0_dp .and. scene%effects(scene_effect%damping)
    b_bound = assembly_dashpot_bound(op)
    result%solver = eigen_solver%lanczos
    result%eigen_tolerance = tol

    ! the slabs, and this rank's rows (without pre-stress first: the bound)
    call scene_slabs(scene, op, nranks, order, new_index)
    lo = slab_start(rank)
    hi = slab_start(rank + 1) - 1
    bodies = order(lo:hi)
    deallocate(order)
    if (with_geo) then
      geo = op%coef(5, :)
      op%coef(5, :) = 0.0_dp
    end if
    call assembly_matrix_rows(op, bodies, new_index, row_start, col, val, status)
    if (status%stat /= demstep_stat%ok) return
    call dist_csr_create(comm, op%n, (lo - 1)*nc + 1, row_start, col, val, matrix, status)
    if (status%stat /= demstep_stat%ok) return
    deallocate(col, val)
    call estimates()
    call dist_csr_free(matrix)

  contains

    !> First sorted position of rank r's slab (r = nranks: one past the end).
    integer function slab_start(r)
      integer, intent(in) :: r
      slab_start = int(int(r, i8)*op%n_bodies/nranks) + 1
    end function slab_start

    !> Bound, contact rule, Lanczos and damping on the distributed rows.
    subroutine estimates()
      type(eigen_result_type) :: lanczos
      real(dp), allocatable :: vec(:)
      real(dp) :: bound, rule, lower
      logical :: has_mode

      call dist_collatz_bound(matrix, bound_iterations, bound)
      call assembly_set_bound(result, rate, bound, status)
      if (status%stat /= demstep_stat%ok) return
      rule = contact_rule(op, bodies)
      call MPI_Allreduce(MPI_IN_PLACE, rule, 1, MPI_DOUBLE_PRECISION, MPI_MIN, comm)
      result%dt_contact_rule = rule/rate
      if (with_geo) then
        ! the operator's rows with pre-stress: same pattern, other values
        op%coef(5, :) = geo
        deallocate(geo)
        call assembly_matrix_rows(op, bodies, new_index, row_start, col, val, status)
        if (status%stat /= demstep_stat%ok) return
        matrix%val = val
        deallocate(col, val)
      end if

      allocate(vec(matrix%n_local))
      ! (with pre-stress the operator may be indefinite, above minus the bound)
      lower = 0.0_dp
      if (with_geo) lower = -(result%omega_bound/rate)**2
      call parallel_lanczos_largest(matrix, lanczos, status, eigenvector=vec, tolerance=tol, &
        ncv=min(scene_lanczos_ncv, op%n), max_restarts=scene_lanczos_restarts, progress=progress, &
        certify=.true., lower_bound=lower)
      call mpi_lanczos_estimates(comm, lanczos, vec, rate, b_bound, result, status, has_mode)
      if (status%stat /= demstep_stat%ok .or. .not. has_mode .or. .not. b_bound > 0.0_dp) return
      call exact_damped(vec, lanczos%eigenvalue, lanczos%certified)
    end subroutine estimates

    !> The exact damped limit from the top undamped mode's block `vec`, its
    !> converged steps confirmed by a cold solve when that top was certified.
    subroutine exact_damped(vec, lam, certified)
      real(dp), intent(in) :: vec(:), lam
      logical, intent(in) :: certified
      type(mpi_damped_type) :: problem
      real(dp), allocatable :: y(:)
      real(dp) :: vb
      problem%confirm_cold = certified
      problem%op => op
      problem%matrix => matrix
      problem%bodies = bodies
      problem%new_index = new_index
      problem%a_val = matrix%val
      problem%vec = vec
      ! v'B'v from B's rows
      op%alpha = 0.0_dp
      op%beta = 1.0_dp
      call assembly_matrix_rows(op, bodies, new_index, row_start, col, val, status)
      op%alpha = 1.0_dp
      op%beta = 0.0_dp
      if (status%stat /= demstep_stat%ok) return
      matrix%val = val
      allocate(y(size(vec)))
      call dist_csr_apply(matrix, vec, y)
      vb = sum(vec*y)
      call MPI_Allreduce(MPI_IN_PLACE, vb, 1, MPI_DOUBLE_PRECISION, MPI_SUM, matrix%comm)
      call damped_newton(problem, lam, vb, rate, tol, result, status, progress)
      matrix%val = problem%a_val
    end subroutine exact_damped

  end subroutine mpi_scene_critical_steps

  !> The slabs: free bodies sorted by their coordinate along the axis of their
  !> widest spread (ties by body number). `order(k)` is the k-th body in that
  !> order, `new_index` its inverse; rank r takes sorted positions
  !> r n/nranks + 1 .. (r + 1) n/nranks. The same on every rank. O(n log n).
  pure subroutine scene_slabs(scene, op, nranks, order, new_index)
    type(scene_type), intent(in) :: scene
    type(assembly_operator_type), intent(in) :: op
    !> Number of slabs.
    integer, intent(in) :: nranks
    integer, allocatable, intent(out) :: order(:), new_index(:)
    real(dp), allocatable :: key(:)
    real(dp) :: lo(3), hi(3)
    integer :: i, b, ax
    allocate(key(op%n_bodies), order(op%n_bodies), new_index(op%n_bodies))
    lo = huge(1.0_dp)
    hi = -huge(1.0_dp)
    b = 0
    do i = 1, scene%n
      if (scene%fixed(i)) cycle
      b = b + 1
      lo = min(lo, scene%x(:, i))
      hi = max(hi, scene%x(:, i))
    end do
    ax = slab_axis(scene%dim, lo, hi)
    b = 0
    do i = 1, scene%n
      if (scene%fixed(i)) cycle
      b = b + 1
      key(b) = scene%x(ax, i)
      order(b) = b
    end do
    call sort_by_key(key, order)
    do b = 1, op%n_bodies
      new_index(order(b)) = b
    end do
  end subroutine scene_slabs

  !> The slabs' axis: the one along which the free bodies spread furthest
  !> (`lo`, `hi`: their smallest and largest coordinates; the first such
  !> axis; 1 when there are none, lo > hi).
  pure integer function slab_axis(dim, lo, hi) result(ax)
    integer, intent(in) :: dim
    real(dp), intent(in) :: lo(3), hi(3)
    ax = 1
    if (all(lo(:dim) <= hi(:dim))) ax = maxloc(hi(:dim) - lo(:dim), 1)
  end function slab_axis

  !> The per-contact rule min 2 sqrt(m*/k) over the springs of the listed
  !> bodies, in the operator's scaled units (divide by its rate); huge when
  !> they touch none.
  pure function contact_rule(op, bodies) result(rule)
    type(assembly_operator_type), intent(in) :: op
    integer, intent(in) :: bodies(:)
    real(dp) :: rule
    real(dp) :: m(2)
    integer :: k, s, e
    integer(i8) :: p
    rule = huge(1.0_dp)
    do k = 1, size(bodies)
      do p = op%first(bodies(k)), op%first(bodies(k) + 1) - 1
        s = (op%incident(p) + 1)/2
        do e = 1, 2
          m(e) = huge(1.0_dp)
          if (op%ends(e, s) > 0) m(e) = (1.0_dp/op%w(1, op%ends(e, s)))**2
        end do
        rule = min(rule, 2.0_dp*sqrt(reduced_mass(m(2), m(1)))/sqrt(max(op%coef(1, s), op%coef(2, s))))
      end do
    end do
  end function contact_rule

  !> Sort `order` by ascending key, ties by ascending `order` (heap sort: the
  !> same permutation on every rank, O(n log n)). `key` is permuted with it.
  pure subroutine sort_by_key(key, order)
    real(dp), intent(inout) :: key(:)
    integer, intent(inout) :: order(:)
    integer :: n, i
    n = size(key)
    do i = n/2, 1, -1
      call sift(key, order, i, n)
    end do
    do i = n, 2, -1
      call swap(key, order, 1, i)
      call sift(key, order, 1, i - 1)
    end do
  end subroutine sort_by_key

  !> Entry a comes before entry b: smaller key, or equal keys and smaller order.
  pure logical function before(key, order, a, b)
    real(dp), intent(in) :: key(:)
    integer, intent(in) :: order(:), a, b
    before = key(a) < key(b) .or. (.not. key(a) > key(b) .and. order(a) < order(b))
  end function before

  !> Exchange entries a and b of both arrays.
  pure subroutine swap(key, order, a, b)
    real(dp), intent(inout) :: key(:)
    integer, intent(inout) :: order(:)
    integer, intent(in) :: a, b
    key([a, b]) = key([b, a])
    order([a, b]) = order([b, a])
  end subroutine swap

  !> Move entry `start` down the heap start..last to its place.
  pure subroutine sift(key, order, start, last)
    real(dp), intent(inout) :: key(:)
    integer, intent(inout) :: order(:)
    integer, intent(in) :: start, last
    integer :: root, child
    root = start
    do
      child = 2*root
      if (child > last) exit
      if (child < last) then
        if (before(key, order, child, child + 1)) child = child + 1
      end if
      if (.not. before(key, order, root, child)) exit
      call swap(key, order, root, child)
      root = child
    end do
  end subroutine sift

  !> Top eigenpair of tau^2 A' + 2 tau B' on the ranks (this rank's rows
  !> rebuilt, same pattern; warm start from the last mode, or with `cold`
  !> set none: `mpi_damped_lanczos`) and v'A'v of it.
  subroutine mpi_damped_top(problem, tau, tol, theta, err, va, has_mode, result, status, progress)
    class(mpi_damped_type), intent(inout) :: problem
    real(dp), intent(in) :: tau, tol
    real(dp), intent(out) :: theta, err, va
    logical, intent(out) :: has_mode
    type(critical_step_type), intent(inout) :: result
    type(demstep_status_type), intent(out) :: status
    class(progress_type), intent(inout), optional :: progress
    type(eigen_result_type) :: lanczos
    integer, allocatable :: col(:)
    integer(i8), allocatable :: row_start(:)
    real(dp), allocatable :: val(:), y(:)
    problem%op%alpha = tau**2
    problem%op%beta = 2.0_dp*tau
    call assembly_matrix_rows(problem%op, problem%bodies, problem%new_index, row_start, col, val, status)
    problem%op%alpha = 1.0_dp
    problem%op%beta = 0.0_dp
    theta = 0.0_dp
    err = 0.0_dp
    va = 0.0_dp
    has_mode = .false.
    if (status%stat /= demstep_stat%ok) return
    problem%matrix%val = val
    call mpi_damped_lanczos(problem%matrix, problem%cold, tol, problem%vec, lanczos, status, progress)
    call mpi_damped_solve_done(problem%matrix%comm, lanczos, problem%vec, result, status, theta, err, has_mode)
    if (status%stat /= demstep_stat%ok) return
    ! v'A'v with A's rows
    problem%matrix%val = problem%a_val
    allocate(y(size(problem%vec)))
    call dist_csr_apply(problem%matrix, problem%vec, y)
    va = sum(problem%vec*y)
    call MPI_Allreduce(MPI_IN_PLACE, va, 1, MPI_DOUBLE_PRECISION, MPI_SUM, problem%matrix%comm)
  end subroutine mpi_damped_top

  !> The estimates from a parallel Lanczos solve (`parallel_lanczos_largest`
  !> with its status `status`): its products, and omega_max with its error bar
  !> and certificate (`assembly_set_estimates`), the top mode's Rayleigh
  !> quotient and residual as the solver measured them. Out of restarts with
  !> no converged Ritz pair on any rank of `comm`, the Ritz value and PARPACK's
  !> residual estimate (as the serial path) and `mode` false; `mode` true when
  !> `vec` holds the top mode (for the exact damped limit).
  subroutine mpi_lanczos_estimates(comm, lanczos, vec, rate, b_bound, result, status, mode)
    type(MPI_Comm), intent(in) :: comm
    type(eigen_result_type), intent(in) :: lanczos
    real(dp), intent(in) :: vec(:), rate, b_bound
    type(critical_step_type), intent(inout) :: result
    type(demstep_status_type), intent(inout) :: status
    logical, intent(out) :: mode
    result%eigen_products = lanczos%applications
    result%eigen_restarts = lanczos%iterations
    mode = .false.
    if (status%stat == demstep_stat%not_converged) then
      mode = any(vec /= 0.0_dp)
      call MPI_Allreduce(MPI_IN_PLACE, mode, 1, MPI_LOGICAL, MPI_LOR, comm)
      if (.not. mode) then
        call assembly_set_estimates(result, rate, lanczos%eigenvalue, lanczos%residual, .false., &
          b_bound, status, lanczos%upper_bound, safe_basis%randomised, lanczos%failure_probability)
        return
      end if
      status%stat = demstep_stat%ok
    end if
    if (status%stat /= demstep_stat%ok) return
    call assembly_set_estimates(result, rate, lanczos%eigenvalue, lanczos%residual, lanczos%converged, &
      b_bound, status, lanczos%upper_bound, safe_basis%randomised, lanczos%failure_probability)
    mode = status%stat == demstep_stat%ok
  end subroutine mpi_lanczos_estimates

  !> One damped-limit Lanczos solve of `matrix` (mixed as tau^2 A' + 2 tau
  !> B') on its ranks, the mode's block left in `vec`: warm-started from
  !> `vec`, or, `cold`, the cold solve that confirms the converged Newton
  !> steps (`damped_newton`), the serial `cold_top_eigenpair`'s: no start,
  !> above `krylov_min_order` the certified one (one unrestarted run from the
  !> certificate's random start, as the undamped top's), at or below it the
  !> ARPACK solve with its confirmation run (no separate certificate run;
  !> the certificate's bound is not used). Collective.
  subroutine mpi_damped_lanczos(matrix, cold, tol, vec, lanczos, status, progress)
    class(dist_operator_type), intent(inout) :: matrix
    logical, intent(in) :: cold
    real(dp), intent(in) :: tol
    real(dp), intent(inout) :: vec(:)
    type(eigen_result_type), intent(out) :: lanczos
    type(demstep_status_type), intent(out) :: status
    class(progress_type), intent(inout), optional :: progress
    real(dp), allocatable :: start(:)
    if (cold) then
      call parallel_lanczos_largest(matrix, lanczos, status, eigenvector=vec, tolerance=tol, &
        ncv=min(scene_lanczos_ncv, matrix%n_global), max_restarts=scene_lanczos_restarts, progress=progress, &
        certify=matrix%n_global > krylov_min_order)
    else
      start = vec
      call parallel_lanczos_largest(matrix, lanczos, status, eigenvector=vec, tolerance=tol, &
        ncv=min(scene_lanczos_ncv, matrix%n_global), max_restarts=scene_lanczos_restarts, progress=progress, &
        start=start)
    end if
  end subroutine mpi_damped_lanczos

  !> After one damped-limit Lanczos solve on the ranks of `comm`: its products
  !> and restarts counted in `result`, whether any rank holds its mode
  !> (`has_mode`), and its eigenvalue `theta` with the error bar `err` (the
  !> residual plus rounding); status ok when restarts ran out (the bracket
  !> still holds).
  subroutine mpi_damped_solve_done(comm, lanczos, vec, result, status, theta, err, has_mode)
    type(MPI_Comm), intent(in) :: comm
    type(eigen_result_type), intent(in) :: lanczos
    real(dp), intent(in) :: vec(:)
    type(critical_step_type), intent(inout) :: result
    type(demstep_status_type), intent(inout) :: status
    real(dp), intent(out) :: theta, err
    logical, intent(out) :: has_mode
    result%eigen_products = result%eigen_products + lanczos%applications
    result%eigen_restarts = result%eigen_restarts + lanczos%iterations
    result%damped_solves = result%damped_solves + 1
    has_mode = any(vec /= 0.0_dp)
    call MPI_Allreduce(MPI_IN_PLACE, has_mode, 1, MPI_LOGICAL, MPI_LOR, comm)
    theta = 0.0_dp
    err = 0.0_dp
    if (status%stat == demstep_stat%not_converged) status%stat = demstep_stat%ok
    if (status%stat /= demstep_stat%ok) return
    theta = lanczos%eigenvalue
    err = lanczos%residual + 8.0_dp*epsilon(1.0_dp)*theta
  end subroutine mpi_damped_solve_done

end module demstep_mpi_scene
