!> The largest eigenvalue (and its vector) of a large symmetric positive
!> semi-definite operator, matrix-free, by the implicitly restarted Lanczos
!> iteration of ARPACK (`dsaupd`/`dseupd`, mode 1, `which = 'LA'`).
!>
!> The operator comes through the abstract interface `lanczos_operator`
!> (`y = A x`) with a context: extend `lanczos_context_type` with the data the
!> product needs and recover it with `select type`. The product may run in
!> parallel (OpenMP inside the callback); the driver itself is serial, starts
!> from a fixed pseudo-random vector (never ARPACK's own random one), so a
!> result depends on the thread count only through the rounding of the product.
!>
!> Tolerance and error bar. ARPACK stops when the Ritz estimate of the wanted
!> Ritz value is at most `tolerance * theta`. The driver then measures, with one
!> more product, the Rayleigh quotient `theta = z.Az` of the returned unit vector
!> `z` and its residual `r = ||A z - theta z||`. For symmetric A two facts hold:
!> `theta <= lambda_max` (a Rayleigh quotient), and some eigenvalue lies within
!> `r` of `theta` (Weinstein's bound; Parlett, The Symmetric Eigenvalue Problem,
!> Thm 4.5.1). The reported `error_bound` is `r` plus a rounding allowance of a
!> few ulps of theta, so `[theta, theta + error_bound]` holds `lambda_max`
!> whenever the eigenvalue within reach is the largest one, which is what
!> Lanczos converges to from a start vector with a component along its
!> eigenvector. The sharper gap bound `r**2 / gap` is not used: Lanczos only
!> gives the second eigenvalue from below, which overstates the gap (unsafe).
!>
!> ARPACK keeps its state in SAVEd variables: one solve at a time per process.
!> A solve started while another runs (another thread) is refused with status
!> `busy` (`arpack_claim`); it never shares the state.
module demstep_lanczos
  use demstep_kinds, only: dp, i8
  use demstep_status, only: demstep_status_type, demstep_stat, set_status
  use demstep_arpack, only: dsaupd, dseupd, dsaupd_status, dseupd_status, arpack_iparam_size
  use demstep_progress, only: progress_type
  use demstep_text, only: int_text, real_text
  use demstep_double_double, only: two_sum, two_prod
  use, intrinsic :: ieee_arithmetic, only: ieee_is_finite
  implicit none
  private

  public :: lanczos_operator, lanczos_largest, lanczos_start_vector, check_lanczos_options, &
    lanczos_finish, lanczos_options
  public :: csr_matrix_type, csr_from_springs, csr_apply, csr_to_dense
  public :: arpack_claim, arpack_release

  !> Default relative tolerance: the residual of the Ritz pair at most 1e-10 of
  !> the Ritz value (the eigenvalue itself is then good to about 1e-10 or better).
  real(dp), parameter, public :: lanczos_tolerance_default = 1.0e-10_dp
  !> Default Krylov size (Lanczos vectors kept between restarts), capped at n.
  integer, parameter, public :: lanczos_ncv_default = 24
  !> Default number of wanted Ritz values kept at each restart (a block of the
  !> top of the spectrum: resolves near-degenerate top eigenvalues).
  integer, parameter, public :: lanczos_nev_default = 1
  !> Default maximum number of implicit restarts.
  integer, parameter, public :: lanczos_restarts_default = 1000
  !> The solver's name in a result.
  character(len=*), parameter, public :: lanczos_solver_name = "lanczos (ARPACK dsaupd)"

  !> Rounding allowance of the error bar, in units of epsilon * |theta|: the
  !> residual and the Rayleigh quotient are sums of rounded products.
  real(dp), parameter, public :: rounding_ulps = 8.0_dp

  !> Below this many rows a product runs on one thread: a parallel region costs
  !> more than the ~10 flops per row it would share.
  integer, parameter :: csr_parallel_rows = 20000

  !> Whether an ARPACK iteration is under way in this process (its SAVEd
  !> state is in use); set and cleared under the critical section
  !> `demstep_arpack` (`arpack_claim`, `arpack_release`).
  logical, save :: arpack_in_use = .false.

  !> Base of the caller's context: extend it with the operator's data.
  type, public :: lanczos_context_type
  end type lanczos_context_type

  abstract interface
    !> y = A x for a symmetric positive semi-definite A (size(x) = size(y) = n).
    subroutine lanczos_operator(context, x, y)
      import :: dp, lanczos_context_type
      class(lanczos_context_type), intent(inout) :: context
      real(dp), intent(in) :: x(:)
      real(dp), intent(out) :: y(:)
    end subroutine lanczos_operator
  end interface

  !> The largest eigenvalue found by an eigensolver, with its error bar and how
  !> it was obtained.
  type, public :: eigen_result_type
    !> The eigenvalue: the Rayleigh quotient of the returned vector (a lower
    !> bound of the largest eigenvalue).
    real(dp) :: eigenvalue = 0.0_dp
    !> Half-width of the error bar: an eigenvalue lies in
    !> [eigenvalue - error_bound, eigenvalue + error_bound].
    real(dp) :: error_bound = 0.0_dp
    !> ||A z - eigenvalue z|| for the unit vector z (measured), or ARPACK's Ritz
    !> estimate of it when the iteration did not converge (no vector then).
    real(dp) :: residual = 0.0_dp
    !> Whether the residual met the relative tolerance.
    logical :: converged = .false.
    !> ARPACK's update iterations: Lanczos passes, each after an implicit
    !> restart but the first (max_restarts + 1 when the restarts ran out).
    integer :: iterations = 0
    !> Products y = A x made, the final residual check included.
    integer(i8) :: applications = 0
    !> The relative tolerance asked for (residual <= tolerance * eigenvalue).
    real(dp) :: tolerance = 0.0_dp
    !> Krylov size and number of wanted Ritz values used.
    integer :: ncv = 0, nev = 0
    !> Which solver ran.
    character(len=:), allocatable :: solver
  end type eigen_result_type

  !> A sparse symmetric matrix in compressed rows, usable as a Lanczos operator
  !> (`csr_apply`). Built from springs by `csr_from_springs`.
  type, extends(lanczos_context_type), public :: csr_matrix_type
    !> Order.
    integer :: n = 0
    !> Row i holds entries row_start(i) .. row_start(i+1)-1.
    integer(i8), allocatable :: row_start(:)
    !> Column and value of each entry (a column may repeat within a row).
    integer, allocatable :: col(:)
    real(dp), allocatable :: val(:)
  end type csr_matrix_type

contains

  !> The largest eigenvalue of the symmetric positive semi-definite operator
  !> `apply` of order `n` and a unit eigenvector, by ARPACK's implicitly
  !> restarted Lanczos iteration (see the module notes for the error bar).
  !>
  !> Status: `invalid_input` for a bad argument or a non-finite product,
  !> `not_converged` when the restarts ran out (the result then holds the best
  !> Ritz value and ARPACK's estimate of its residual, the vector is zero),
  !> otherwise ARPACK's own failures (`dsaupd_status`, `dseupd_status`).
  subroutine lanczos_largest(apply, context, n, result, status, eigenvector, tolerance, ncv, &
      nev, max_restarts, progress, start)
    !> y = A x.
    procedure(lanczos_operator) :: apply
    !> The operator's data, passed to `apply`.
    class(lanczos_context_type), intent(inout) :: context
    !> Order of the operator (>= 1).
    integer, intent(in) :: n
    type(eigen_result_type), intent(out) :: result
    type(demstep_status_type), intent(out) :: status
    !> Unit eigenvector (size n).
    real(dp), intent(out), optional :: eigenvector(:)
    !> Relative residual tolerance, in [epsilon, 0.1]; default `lanczos_tolerance_default`.
    real(dp), intent(in), optional :: tolerance
    !> Krylov size, > nev; capped at n. Default `lanczos_ncv_default`.
    integer, intent(in), optional :: ncv
    !> Wanted Ritz values kept at restarts, >= 1 and < ncv. Default `lanczos_nev_default`.
    integer, intent(in), optional :: nev
    !> Maximum implicit restarts (>= 1; ARPACK's mxiter). Default `lanczos_restarts_default`.
    integer, intent(in), optional :: max_restarts
    !> Reports the products made (no total: convergence is not known ahead).
    class(progress_type), intent(inout), optional :: progress
    !> A start vector (size n; e.g. the previous solve's mode, a warm start):
    !> a thousandth of the default start vector is added, so that no
    !> eigenvector is missing from it.
    real(dp), intent(in), optional :: start(:)
    real(dp) :: tol, theta, rnorm, znorm
    integer :: k, m, restarts, ido, info, lworkl, nconv, ldv, itop
    integer :: iparam(arpack_iparam_size), ipntr(arpack_iparam_size)
    real(dp), allocatable :: v(:, :), workd(:), workl(:), resid(:), z(:, :), d(:), y(:)
    logical, allocatable :: select(:)
    type(demstep_status_type) :: step_status

    call lanczos_options(tol, m, k, restarts, tolerance, ncv, nev, max_restarts)
    result%solver = lanczos_solver_name
    result%tolerance = tol
    if (present(eigenvector)) eigenvector = 0.0_dp

    if (n < 1) then
      call set_status(status, demstep_stat%invalid_input, "lanczos_largest: n: the order " &
        //"must be at least 1, not "//int_text(n))
      return
    end if
    if (present(eigenvector)) then
      if (size(eigenvector) /= n) then
        call set_status(status, demstep_stat%invalid_input, "lanczos_largest: eigenvector: " &
          //"size "//int_text(size(eigenvector))//", need n = "//int_text(n))
        return
      end if
    end if
    call check_lanczos_options("lanczos_largest", tol, k, m, restarts, status)
    if (status%stat /= demstep_stat%ok) return

    allocate(y(n))
    if (n == 1) then
      ! a 1-by-1 operator is its own eigenvalue; ARPACK needs nev < ncv <= n
      y = 1.0_dp
      call product([1.0_dp], y, status)
      if (status%stat /= demstep_stat%ok) return
      result%eigenvalue = y(1)
      result%converged = .true.
      result%error_bound = rounding_ulps*epsilon(1.0_dp)*abs(y(1))
      if (present(eigenvector)) eigenvector = 1.0_dp
      return
    end if
    ! small operators: the whole space (k must stay below it)
    m = min(m, n)
    k = min(k, m - 1)
    result%ncv = m
    result%nev = k
    ldv = n
    lworkl = m*(m + 8)
    allocate(v(n, m), workd(3*n), workl(lworkl), resid(n), d(k), select(m), z(n, k))
    call lanczos_start_vector(resid)
    if (present(start)) then
      ! (a zero or non-finite start is ignored: the default start vector)
      if (size(start) == n) then
        if (sum(start**2) > 0.0_dp .and. sum(start**2) <= huge(1.0_dp)) &
          resid = start/norm2(start) + 1.0e-3_dp*resid/norm2(resid)
      end if
    end if
    ! ARPACK's SAVEd state: one iteration per process at a time
    call arpack_claim(status)
    if (status%stat /= demstep_stat%ok) return
    iparam = 0
    iparam(1) = 1         ! exact shifts
    iparam(3) = restarts
    iparam(7) = 1         ! mode 1: OP = A, B = I
    ido = 0
    info = 1              ! start from resid, not ARPACK's random vector
    ! how many products convergence takes is not known ahead: no total
    if (present(progress)) call progress%start("Lanczos products", 0_i8)
    do
      call dsaupd(ido, "I", n, "LA", k, tol, resid, m, v, ldv, iparam, ipntr, workd, workl, &
        lworkl, info)
      if (ido /= -1 .and. ido /= 1) exit
      call product(workd(ipntr(1):ipntr(1) + n - 1), workd(ipntr(2):ipntr(2) + n - 1), status)
      if (status%stat /= demstep_stat%ok) then
        call arpack_release()
        if (present(progress)) call progress%finish()
        return
      end if
      if (present(progress)) call progress%update(result%applications)
    end do
    result%iterations = iparam(3)
    if (info == -9) then
      ! dsaupd's first step replaces the (nonzero) start vector x0 by A x0: it
      ! found A x0 = 0. Under Lanczos' own assumption (x0 has a component along
      ! every eigenvector) that makes every eigenvalue zero: the zero operator
      ! (a scene without contacts, say)
      call arpack_release()
      if (present(progress)) call progress%finish()
      result%converged = .true.
      if (present(eigenvector)) then
        call lanczos_start_vector(eigenvector)
        eigenvector = eigenvector/sqrt(accurate_dot(eigenvector, eigenvector))
      end if
      status%stat = demstep_stat%ok
      return
    end if
    step_status = dsaupd_status(info)
    nconv = iparam(5)
    if (step_status%stat /= demstep_stat%ok .and. step_status%stat /= demstep_stat%not_converged) then
      call arpack_release()
      if (present(progress)) call progress%finish()
      status = step_status
      return
    end if

    if (nconv < 1) then
      ! no Ritz pair met the tolerance: the largest of the k wanted Ritz values
      ! and ARPACK's Ritz estimate of its residual
      itop = maxloc(workl(ipntr(6):ipntr(6) + k - 1), 1) - 1
      result%eigenvalue = workl(ipntr(6) + itop)
      result%residual = abs(workl(ipntr(7) + itop))
      result%error_bound = result%residual + rounding_ulps*epsilon(1.0_dp)*abs(result%eigenvalue)
      call arpack_release()
      if (present(progress)) call progress%finish()
      if (step_status%stat == demstep_stat%ok) then
        call set_status(status, demstep_stat%not_converged, "ARPACK dsaupd: no Ritz value met " &
          //"the tolerance")
      else
        status = step_status
      end if
      status%message = status%message//" (largest Ritz value "//real_text(result%eigenvalue) &
        //", relative residual estimate "//real_text(result%residual/max(abs(result%eigenvalue), &
        tiny(1.0_dp)))//" after "//int_text(result%iterations)//" restarts, tolerance " &
        //real_text(tol)//"; raise max_restarts or ncv)"
      return
    end if

    call dseupd(.true., "A", select, d, z, n, 0.0_dp, "I", n, "LA", k, tol, resid, m, v, ldv, &
      iparam, ipntr, workd, workl, lworkl, info)
    call arpack_release()
    if (info /= 0) then
      if (present(progress)) call progress%finish()
      status = dseupd_status(info)
      return
    end if
    ! converged values come in ascending order: the largest is the last one
    ! computed (nconv of them, nconv <= k)
    z(:, 1) = z(:, min(nconv, k))
    znorm = sqrt(accurate_dot(z(:, 1), z(:, 1)))
    if (.not. (znorm > 0.0_dp)) then
      if (present(progress)) call progress%finish()
      call set_status(status, demstep_stat%eigensolver_failure, "ARPACK dseupd: returned a " &
        //"zero Ritz vector")
      return
    end if
    z(:, 1) = z(:, 1)/znorm
    ! the measured Rayleigh quotient and residual of the returned vector
    call product(z(:, 1), y, status)
    if (present(progress)) call progress%finish()
    if (status%stat /= demstep_stat%ok) return
    ! compensated sums: a plain sum of n nearly equal terms (a lattice mode) is
    ! off by up to n*epsilon/2, 1e-12 at n = 1e5, far above the tolerance
    theta = accurate_dot(z(:, 1), y)/accurate_dot(z(:, 1), z(:, 1))
    y = y - theta*z(:, 1)
    rnorm = sqrt(accurate_dot(y, y))
    if (present(eigenvector)) eigenvector = z(:, 1)
    call lanczos_finish(theta, rnorm, tol, step_status, result, status)

  contains

    !> One product, counted and checked for finiteness.
    subroutine product(x, ax, stat)
      real(dp), intent(in) :: x(:)
      real(dp), intent(out) :: ax(:)
      type(demstep_status_type), intent(out) :: stat
      call apply(context, x, ax)
      result%applications = result%applications + 1
      if (.not. all(ieee_is_finite(ax))) then
        call set_status(stat, demstep_stat%invalid_input, "lanczos_largest: the operator " &
          //"returned a non-finite value (product "//int_text(result%applications)//")")
        return
      end if
      stat%stat = demstep_stat%ok
    end subroutine product

  end subroutine lanczos_largest

  !> Claim ARPACK's SAVEd state for one iteration: status `busy` when another
  !> solve (another thread) holds it, never a wait and never a shared state.
  !> Every claim is followed by one `arpack_release`.
  subroutine arpack_claim(status)
    type(demstep_status_type), intent(out) :: status
    logical :: was
    !$omp critical (demstep_arpack)
    was = arpack_in_use
    arpack_in_use = .true.
    !$omp end critical (demstep_arpack)
    if (was) then
      call set_status(status, demstep_stat%busy, "another Lanczos solve is running in this process " &
        //"(ARPACK keeps its state in SAVEd variables: one solve at a time; call again when it is done)", &
        where="lanczos_largest")
      return
    end if
    status%stat = demstep_stat%ok
  end subroutine arpack_claim

  !> Release ARPACK's state after `arpack_claim`.
  subroutine arpack_release()
    !$omp critical (demstep_arpack)
    arpack_in_use = .false.
    !$omp end critical (demstep_arpack)
  end subroutine arpack_release

  !> The end of a Lanczos solve, serial or distributed: the result from the
  !> measured Rayleigh quotient `theta` and residual `rnorm` of the returned unit
  !> vector (error bar `rnorm` plus the rounding allowance), and ARPACK's status
  !> with the numbers that say how far it got when it is not ok.
  pure subroutine lanczos_finish(theta, rnorm, tol, step_status, result, status)
    real(dp), intent(in) :: theta, rnorm, tol
    !> The status of the iteration (ok or not_converged).
    type(demstep_status_type), intent(in) :: step_status
    type(eigen_result_type), intent(inout) :: result
    type(demstep_status_type), intent(out) :: status
    result%eigenvalue = theta
    result%residual = rnorm
    result%error_bound = rnorm + rounding_ulps*epsilon(1.0_dp)*abs(theta)
    result%converged = step_status%stat == demstep_stat%ok
    status = step_status
    if (status%stat /= demstep_stat%ok) status%message = status%message//" (largest Ritz value " &
      //real_text(theta)//", relative residual "//real_text(rnorm/max(abs(theta), tiny(1.0_dp))) &
      //" after "//int_text(result%iterations)//" restarts, tolerance "//real_text(tol)//")"
  end subroutine lanczos_finish

  !> x.y by compensated summation (Ogita, Rump and Oishi's Dot2): as accurate
  !> as a sum in twice the working precision, then rounded.
  pure function accurate_dot(x, y) result(s)
    real(dp), intent(in) :: x(:), y(:)
    real(dp) :: s
    real(dp) :: p, q, h, r, c
    integer :: i
    s = 0.0_dp
    c = 0.0_dp
    do i = 1, size(x)
      call two_prod(x(i), y(i), h, r)
      call two_sum(s, h, p, q)
      s = p
      c = c + (q + r)
    end do
    s = s + c
  end function accurate_dot

  !> The fixed start vector: a Park-Miller (minimal standard, multiplier 48271)
  !> sequence from seed 1, mapped to (-0.5, 0.5). The same for every run and
  !> thread count, and with a component along any eigenvector in practice.
  pure subroutine lanczos_start_vector(x)
    !> Filled with the sequence.
    real(dp), intent(out) :: x(:)
    integer(i8), parameter :: modulus = 2147483647_i8, multiplier = 48271_i8
    integer(i8) :: state
    integer :: i
    state = 1_i8
    do i = 1, size(x)
      state = mod(multiplier*state, modulus)
      x(i) = real(state, dp)/real(modulus, dp) - 0.5_dp
    end do
  end subroutine lanczos_start_vector

  !> Assemble the n-by-n matrix sum_e k_e (u_i - u_j)(u_i - u_j)^T + diag(ground)
  !> of springs e between nodes i = first(e) and j = second(e) (a weighted graph
  !> Laplacian, positive semi-definite for k_e >= 0, ground >= 0), optionally
  !> mass-scaled: M^-1/2 (...) M^-1/2. O(n + springs) time and memory.
  !> Status `invalid_input` for an index out of 1..n, i = j, a negative or
  !> non-finite stiffness, ground or a non-positive mass, or mismatched sizes.
  subroutine csr_from_springs(n, first, second, stiffness, matrix, status, ground, mass)
    !> Number of nodes (>= 1).
    integer, intent(in) :: n
    !> Ends of each spring.
    integer, intent(in) :: first(:), second(:)
    !> Spring stiffness (>= 0).
    real(dp), intent(in) :: stiffness(:)
    type(csr_matrix_type), intent(out) :: matrix
    type(demstep_status_type), intent(out) :: status
    !> Stiffness to ground of each node (>= 0, size n); default none.
    real(dp), intent(in), optional :: ground(:)
    !> Mass of each node (> 0, size n); default 1.
    real(dp), intent(in), optional :: mass(:)
    integer :: e, i, j, ns
    integer(i8), allocatable :: fill(:)
    real(dp), allocatable :: scale(:)
    ns = size(first)
    if (n < 1 .or. size(second) /= ns .or. size(stiffness) /= ns) then
      call set_status(status, demstep_stat%invalid_input, "csr_from_springs: need n >= 1 " &
        //"and first, second, stiffness of one size")
      return
    end if
    if (any(first < 1 .or. first > n .or. second < 1 .or. second > n .or. first == second)) then
      call set_status(status, demstep_stat%invalid_input, "csr_from_springs: first, second: " &
        //"each spring joins two different nodes in 1..n")
      return
    end if
    if (.not. all(ieee_is_finite(stiffness) .and. stiffness >= 0.0_dp)) then
      call set_status(status, demstep_stat%invalid_input, "csr_from_springs: stiffness: " &
        //"must be finite and >= 0")
      return
    end if
    allocate(scale(n))
    scale = 1.0_dp
    if (present(mass)) then
      if (size(mass) /= n) then
        call set_status(status, demstep_stat%invalid_input, "csr_from_springs: mass: need size n")
        return
      end if
      if (.not. all(ieee_is_finite(mass) .and. mass > 0.0_dp)) then
        call set_status(status, demstep_stat%invalid_input, "csr_from_springs: mass: must " &
          //"be finite and > 0")
        return
      end if
      scale = 1.0_dp/sqrt(mass)
    end if
    if (present(ground)) then
      if (size(ground) /= n) then
        call set_status(status, demstep_stat%invalid_input, "csr_from_springs: ground: need size n")
        return
      end if
      if (.not. all(ieee_is_finite(ground) .and. ground >= 0.0_dp)) then
        call set_status(status, demstep_stat%invalid_input, "csr_from_springs: ground: must " &
          //"be finite and >= 0")
        return
      end if
    end if
    matrix%n = n
    ! row i: its diagonal first, then one entry per spring at i
    allocate(matrix%row_start(n + 1), fill(n))
    fill = 1_i8
    do e = 1, ns
      fill(first(e)) = fill(first(e)) + 1
      fill(second(e)) = fill(second(e)) + 1
    end do
    matrix%row_start(1) = 1
    do i = 1, n
      matrix%row_start(i + 1) = matrix%row_start(i) + fill(i)
    end do
    allocate(matrix%col(matrix%row_start(n + 1) - 1), matrix%val(matrix%row_start(n + 1) - 1))
    do i = 1, n
      matrix%col(matrix%row_start(i)) = i
      matrix%val(matrix%row_start(i)) = 0.0_dp
      if (present(ground)) matrix%val(matrix%row_start(i)) = ground(i)
    end do
    fill = matrix%row_start(1:n) + 1
    do e = 1, ns
      i = first(e)
      j = second(e)
      matrix%val(matrix%row_start(i)) = matrix%val(matrix%row_start(i)) + stiffness(e)
      matrix%val(matrix%row_start(j)) = matrix%val(matrix%row_start(j)) + stiffness(e)
      matrix%col(fill(i)) = j
      matrix%val(fill(i)) = -stiffness(e)
      fill(i) = fill(i) + 1
      matrix%col(fill(j)) = i
      matrix%val(fill(j)) = -stiffness(e)
      fill(j) = fill(j) + 1
    end do
    if (present(mass)) then
      do i = 1, n
        do e = int(matrix%row_start(i)), int(matrix%row_start(i + 1) - 1)
          matrix%val(e) = matrix%val(e)*scale(i)*scale(matrix%col(e))
        end do
      end do
    end if
    status%stat = demstep_stat%ok
  end subroutine csr_from_springs

  !> y = A x for a `csr_matrix_type` (a `lanczos_operator`). Rows run in
  !> parallel under OpenMP; each row is summed in a fixed order by one thread,
  !> so the result is the same for every thread count, bit for bit.
  subroutine csr_apply(context, x, y)
    class(lanczos_context_type), intent(inout) :: context
    real(dp), intent(in) :: x(:)
    real(dp), intent(out) :: y(:)
    integer :: i
    integer(i8) :: p
    real(dp) :: s
    y = 0.0_dp
    select type (context)
    class is (csr_matrix_type)
      !$omp parallel do private(i, p, s) schedule(static) if(context%n >= csr_parallel_rows)
      do i = 1, context%n
        s = 0.0_dp
        do p = context%row_start(i), context%row_start(i + 1) - 1
          s = s + context%val(p)*x(context%col(p))
        end do
        y(i) = s
      end do
      !$omp end parallel do
    end select
  end subroutine csr_apply

  !> The dense matrix of a `csr_matrix_type` (for small checks).
  pure subroutine csr_to_dense(matrix, a)
    type(csr_matrix_type), intent(in) :: matrix
    !> n-by-n.
    real(dp), allocatable, intent(out) :: a(:, :)
    integer :: i
    integer(i8) :: p
    allocate(a(matrix%n, matrix%n))
    a = 0.0_dp
    do i = 1, matrix%n
      do p = matrix%row_start(i), matrix%row_start(i + 1) - 1
        a(i, matrix%col(p)) = a(i, matrix%col(p)) + matrix%val(p)
      end do
    end do
  end subroutine csr_to_dense

  !> The Lanczos options a driver was given, the defaults where it was not (one
  !> place for the serial and the distributed driver; `check_lanczos_options`
  !> then checks them).
  pure subroutine lanczos_options(tol, ncv_used, nev_used, restarts, tolerance, ncv, nev, max_restarts)
    real(dp), intent(out) :: tol
    integer, intent(out) :: ncv_used, nev_used, restarts
    real(dp), intent(in), optional :: tolerance
    integer, intent(in), optional :: ncv, nev, max_restarts
    tol = lanczos_tolerance_default
    if (present(tolerance)) tol = tolerance
    ncv_used = lanczos_ncv_default
    if (present(ncv)) ncv_used = ncv
    nev_used = lanczos_nev_default
    if (present(nev)) nev_used = nev
    restarts = lanczos_restarts_default
    if (present(max_restarts)) restarts = max_restarts
  end subroutine lanczos_options

  !> The Lanczos options' rules, for the serial and the distributed driver: a
  !> tolerance in [eps, 0.1], nev >= 1, ncv > nev, max_restarts >= 1. The message
  !> starts with `caller: option:`; `status` is ok when all hold.
  pure subroutine check_lanczos_options(caller, tol, nev, ncv, restarts, status)
    !> The driver's name, for the message.
    character(len=*), intent(in) :: caller
    real(dp), intent(in) :: tol
    integer, intent(in) :: nev, ncv, restarts
    type(demstep_status_type), intent(out) :: status
    status%stat = demstep_stat%ok
    if (.not. (tol >= epsilon(1.0_dp) .and. tol <= 0.1_dp)) then
      call set_status(status, demstep_stat%invalid_input, caller//": tolerance: " &
        //real_text(tol)//" is outside [2.2e-16, 0.1]")
    else if (nev < 1) then
      call set_status(status, demstep_stat%invalid_input, caller//": nev: need at " &
        //"least 1, not "//int_text(nev))
    else if (ncv <= nev) then
      call set_status(status, demstep_stat%invalid_input, caller//": ncv: the " &
        //"Krylov size "//int_text(ncv)//" must exceed nev = "//int_text(nev))
    else if (restarts < 1) then
      call set_status(status, demstep_stat%invalid_input, caller//": max_restarts: " &
        //"need at least 1, not "//int_text(restarts))
    end if
  end subroutine check_lanczos_options

end module demstep_lanczos
