!> The largest eigenvalue of a symmetric positive semi-definite sparse operator
!> whose rows are partitioned across MPI ranks, by PARPACK's Lanczos iteration:
!> the distributed counterpart of `demstep_lanczos`'s `lanczos_largest`, with
!> the same start vector, stopping rule and error bar.
!>
!> Partition. Rank r owns the contiguous block of global rows
!> `first_row .. first_row + n_local - 1`; blocks follow the rank order and
!> cover 1..n_global (particles partitioned by space: number them by region and
!> each rank owns one region's rows). Its rows refer to global columns; the
!> entries of x it does not own (the halo) come from their owners before each
!> product. The pattern is built once (`dist_csr_create`): each rank lists the
!> columns it needs, and tells their owners, who then know what to send. Each
!> product is one `MPI_Neighbor_alltoallv` on a graph communicator of the
!> ranks that share rows.
!>
!> Error bar: as in `lanczos_largest`, the Rayleigh quotient of the returned
!> unit vector and its residual norm, from local compensated sums reduced with
!> `MPI_Allreduce`. Gershgorin's bound is a row-sum maximum reduced the same way.
!>
!> Every routine is collective over the matrix's communicator and returns the
!> same status on every rank.
module demstep_mpi_lanczos
  use mpi_f08
  use demstep_kinds, only: dp, i8
  use demstep_status, only: demstep_status_type, demstep_stat, set_status
  use demstep_arpack, only: arpack_iparam_size
  use demstep_parpack, only: pdsaupd, pdseupd, pdsaupd_status, pdseupd_status
  use demstep_lanczos, only: check_lanczos_options, eigen_result_type, lanczos_options, &
    lanczos_finish, rounding_ulps
  use demstep_double_double, only: two_sum, two_prod
  use demstep_text, only: int_text, real_text
  use demstep_progress, only: progress_type
  use, intrinsic :: ieee_arithmetic, only: ieee_is_finite
  implicit none
  private

  public :: dist_csr_create, dist_csr_apply, dist_gershgorin_bound, dist_collatz_bound, &
    parallel_lanczos_largest
  public :: dist_start_vector, dist_csr_bytes, dist_csr_free

  !> The solver's name in a result.
  character(len=*), parameter, public :: parallel_lanczos_solver_name = &
    "lanczos (PARPACK pdsaupd, MPI)"

  !> A row block of a sparse symmetric matrix with its halo-exchange pattern.
  type, public :: dist_csr_type
    !> Global order, rows owned here and the first of them (global index).
    integer :: n_global = 0, n_local = 0, first_row = 1
    !> Halo entries received per product.
    integer :: n_halo = 0
    !> Local row i holds entries row_start(i) .. row_start(i+1)-1.
    integer(i8), allocatable :: row_start(:)
    !> Column of each entry in the extended local vector: 1..n_local own
    !> entries, n_local + k the k-th halo entry.
    integer, allocatable :: col(:)
    real(dp), allocatable :: val(:)
    !> Graph communicator of the ranks exchanged with (neighbour collectives).
    type(MPI_Comm) :: graph
    !> Counts and 0-based displacements per neighbour, received and sent.
    integer, allocatable :: recv_count(:), recv_displ(:), send_count(:), send_displ(:)
    !> Local indices of the entries sent, neighbour by neighbour.
    integer, allocatable :: send_index(:)
    !> The extended vector [own x, halo] and the send buffer.
    real(dp), allocatable :: x_ext(:), send_buffer(:)
  end type dist_csr_type

contains

  !> Build the row block of this rank and the halo-exchange pattern from its
  !> rows in compressed form with global column indices. Collective.
  !> Status `invalid_input` (on every rank) when the blocks do not tile
  !> 1..n_global in rank order, a rank owns no row, a column is outside
  !> 1..n_global, or a value is not finite.
  subroutine dist_csr_create(comm, n_global, first_row, row_start, col, val, matrix, status)
    !> The ranks sharing the matrix.
    type(MPI_Comm), intent(in) :: comm
    !> Global order.
    integer, intent(in) :: n_global
    !> Global index of this rank's first row.
    integer, intent(in) :: first_row
    !> Local row i: entries row_start(i) .. row_start(i+1)-1 (row_start(1) = 1).
    integer(i8), intent(in) :: row_start(:)
    !> Global column and value of each entry.
    integer, intent(in) :: col(:)
    real(dp), intent(in) :: val(:)
    type(dist_csr_type), intent(out) :: matrix
    type(demstep_status_type), intent(out) :: status
    integer :: nranks, rank, r, i, n_local, n_out, k, p, nb_in, nb_out, last_row
    integer, allocatable :: blocks(:, :), outside(:), halo(:), want(:), give(:), &
      want_displ(:), give_displ(:), requested(:), sources(:), dests(:)
    integer(i8) :: nnz, e
    logical :: bad

    call MPI_Comm_size(comm, nranks)
    call MPI_Comm_rank(comm, rank)
    n_local = size(row_start) - 1
    nnz = 0
    if (n_local >= 0) nnz = row_start(n_local + 1) - 1
    ! the partition, checked the same way on every rank
    allocate(blocks(2, 0:nranks - 1))
    call MPI_Allgather([first_row, n_local], 2, MPI_INTEGER, blocks, 2, MPI_INTEGER, comm)
    bad = n_global < 1 .or. any(blocks(2, :) < 1) .or. blocks(1, 0) /= 1
    do r = 1, nranks - 1
      if (blocks(1, r) /= blocks(1, r - 1) + blocks(2, r - 1)) bad = .true.
    end do
    if (.not. bad) bad = blocks(1, nranks - 1) + blocks(2, nranks - 1) - 1 /= n_global
    if (bad) then
      call set_status(status, demstep_stat%invalid_input, "dist_csr_create: first_row, " &
        //"row_start: the row blocks must tile 1..n_global in rank order, at least one " &
        //"row per rank")
      return
    end if
    ! the local arrays, checked here and agreed on by all
    bad = row_start(1) /= 1 .or. nnz < 0 .or. size(col) /= nnz .or. size(val) /= nnz
    if (.not. bad) bad = any(row_start(2:) < row_start(:n_local))
    if (.not. bad) bad = any(col < 1 .or. col > n_global) .or. .not. all(ieee_is_finite(val))
    call MPI_Allreduce(MPI_IN_PLACE, bad, 1, MPI_LOGICAL, MPI_LOR, comm)
    if (bad) then
      call set_status(status, demstep_stat%invalid_input, "dist_csr_create: row_start, " &
        //"col, val: need ascending row starts from 1, columns in 1..n_global and finite values")
      return
    end if

    matrix%n_global = n_global
    matrix%n_local = n_local
    matrix%first_row = first_row
    last_row = first_row + n_local - 1
    ! the halo: distinct columns outside the block, ascending (hence by owner)
    n_out = count(col < first_row .or. col > last_row)
    allocate(outside(n_out))
    outside = pack(col, col < first_row .or. col > last_row)
    call heap_sort(outside)
    allocate(halo(n_out))
    k = 0
    do i = 1, n_out
      if (k > 0) then
        if (halo(k) == outside(i)) cycle
      end if
      k = k + 1
      halo(k) = outside(i)
    end do
    matrix%n_halo = k
    ! how many halo entries each rank owns
    allocate(want(0:nranks - 1), give(0:nranks - 1), want_displ(0:nranks - 1), &
      give_displ(0:nranks - 1))
    want = 0
    r = 0
    do i = 1, matrix%n_halo
      do while (halo(i) > blocks(1, r) + blocks(2, r) - 1)
        r = r + 1
      end do
      want(r) = want(r) + 1
    end do
    call MPI_Alltoall(want, 1, MPI_INTEGER, give, 1, MPI_INTEGER, comm)
    want_displ(0) = 0
    give_displ(0) = 0
    do r = 1, nranks - 1
      want_displ(r) = want_displ(r - 1) + want(r - 1)
      give_displ(r) = give_displ(r - 1) + give(r - 1)
    end do
    allocate(requested(sum(give)))
    call MPI_Alltoallv(halo, want, want_displ, MPI_INTEGER, requested, give, give_displ, &
      MPI_INTEGER, comm)
    ! the neighbour graph: sources send to this rank, destinations receive from it
    nb_in = count(want > 0)
    nb_out = count(give > 0)
    allocate(sources(nb_in), dests(nb_out), matrix%recv_count(nb_in), matrix%recv_displ(nb_in), &
      matrix%send_count(nb_out), matrix%send_displ(nb_out))
    p = 0
    do r = 0, nranks - 1
      if (want(r) == 0) cycle
      p = p + 1
      sources(p) = r
      matrix%recv_count(p) = want(r)
      matrix%recv_displ(p) = want_displ(r)
    end do
    p = 0
    do r = 0, nranks - 1
      if (give(r) == 0) cycle
      p = p + 1
      dests(p) = r
      matrix%send_count(p) = give(r)
      matrix%send_displ(p) = give_displ(r)
    end do
    matrix%send_index = requested - first_row + 1
    call MPI_Dist_graph_create_adjacent(comm, nb_in, sources, MPI_UNWEIGHTED, nb_out, dests, &
      MPI_UNWEIGHTED, MPI_INFO_NULL, .false., matrix%graph)
    ! the local rows, columns renumbered into the extended vector
    allocate(matrix%row_start(n_local + 1), matrix%col(nnz), matrix%val(nnz))
    matrix%row_start = row_start
    matrix%val = val
    do e = 1, nnz
      if (col(e) >= first_row .and. col(e) <= last_row) then
        matrix%col(e) = col(e) - first_row + 1
      else
        matrix%col(e) = n_local + position(halo(:matrix%n_halo), col(e))
      end if
    end do
    allocate(matrix%x_ext(n_local + matrix%n_halo), matrix%send_buffer(size(requested)))
    matrix%x_ext = 0.0_dp
    status%stat = demstep_stat%ok
  end subroutine dist_csr_create

  !> Release the matrix's graph communicator and arrays. Collective; call it
  !> before MPI_Finalize and before building a new matrix into the same variable.
  subroutine dist_csr_free(matrix)
    type(dist_csr_type), intent(inout) :: matrix
    type(dist_csr_type) :: empty
    if (matrix%n_global >= 1) call MPI_Comm_free(matrix%graph)
    matrix = empty
  end subroutine dist_csr_free

  !> y = A x on this rank's rows (x and y: this rank's block). Collective: one
  !> halo exchange, then the local rows, each summed in a fixed order.
  subroutine dist_csr_apply(matrix, x, y)
    type(dist_csr_type), intent(inout) :: matrix
    !> This rank's entries of x (n_local).
    real(dp), intent(in) :: x(:)
    !> This rank's entries of A x (n_local).
    real(dp), intent(out) :: y(:)
    integer :: i
    integer(i8) :: p
    real(dp) :: s
    associate (n => matrix%n_local)
      matrix%x_ext(1:n) = x(1:n)
      matrix%send_buffer = x(matrix%send_index)
      call MPI_Neighbor_alltoallv(matrix%send_buffer, matrix%send_count, matrix%send_displ, &
        MPI_DOUBLE_PRECISION, matrix%x_ext(n + 1:), matrix%recv_count, matrix%recv_displ, &
        MPI_DOUBLE_PRECISION, matrix%graph)
      do i = 1, n
        s = 0.0_dp
        do p = matrix%row_start(i), matrix%row_start(i + 1) - 1
          s = s + matrix%val(p)*matrix%x_ext(matrix%col(p))
        end do
        y(i) = s
      end do
    end associate
  end subroutine dist_csr_apply

  !> Gershgorin's bound of the largest eigenvalue: the largest row sum of |A|
  !> over all ranks (an MPI maximum). Collective; the matrix must come from a
  !> successful `dist_csr_create`.
  subroutine dist_gershgorin_bound(matrix, bound)
    type(dist_csr_type), intent(in) :: matrix
    !> max_i sum_j |a_ij| >= lambda_max, the same on every rank.
    real(dp), intent(out) :: bound
    integer :: i
    bound = 0.0_dp
    do i = 1, matrix%n_local
      bound = max(bound, sum(abs(matrix%val(matrix%row_start(i):matrix%row_start(i + 1) - 1))))
    end do
    call MPI_Allreduce(MPI_IN_PLACE, bound, 1, MPI_DOUBLE_PRECISION, MPI_MAX, matrix%graph)
  end subroutine dist_gershgorin_bound

  !> Collatz-Wielandt's bound of the largest eigenvalue: lambda_max(A) <=
  !> rho(|A|) <= max_i (|A| v)_i / v_i for any v > 0; v = 1 (Gershgorin's row
  !> sums), then `steps` times v <- |A| v floored at 1e-3 of its largest entry
  !> (as the serial scene bound); the smallest quotient, each row sum raised
  !> by its rounding allowance, the same on every rank. Collective; the
  !> matrix's values are restored.
  subroutine dist_collatz_bound(matrix, steps, bound)
    type(dist_csr_type), intent(inout) :: matrix
    !> Steps after Gershgorin's (>= 0).
    integer, intent(in) :: steps
    real(dp), intent(out) :: bound
    real(dp), allocatable :: v(:), r(:), saved(:)
    real(dp) :: q(2)
    integer :: k
    saved = matrix%val
    matrix%val = abs(matrix%val)
    allocate(v(matrix%n_local), r(matrix%n_local))
    v = 1.0_dp
    bound = huge(1.0_dp)
    do k = 0, steps
      call dist_csr_apply(matrix, v, r)
      ! raised by the rounding of a sum of a row's positive terms
      r = r*(1.0_dp + real(matrix%row_start(2:) - matrix%row_start(:matrix%n_local) + 4, dp) &
        *epsilon(1.0_dp))
      ! the largest quotient and the largest entry, over all ranks
      q = [maxval(r/v), maxval(r)]
      call MPI_Allreduce(MPI_IN_PLACE, q, 2, MPI_DOUBLE_PRECISION, MPI_MAX, matrix%graph)
      bound = min(bound, q(1))
      if (.not. q(2) > 0.0_dp) exit
      v = max(r/q(2), 1.0e-3_dp)
    end do
    matrix%val = saved
  end subroutine dist_collatz_bound

  !> Bytes held by the matrix on this rank: rows, entries, pattern and halo buffers.
  pure function dist_csr_bytes(matrix) result(bytes)
    type(dist_csr_type), intent(in) :: matrix
    integer(i8) :: bytes
    bytes = (storage_size(matrix%row_start, i8)*size(matrix%row_start, kind=i8) &
      + storage_size(matrix%col, i8)*size(matrix%col, kind=i8) &
      + storage_size(matrix%val, i8)*size(matrix%val, kind=i8) &
      + storage_size(matrix%send_index, i8)*size(matrix%send_index, kind=i8) &
      + storage_size(matrix%x_ext, i8)*size(matrix%x_ext, kind=i8) &
      + storage_size(matrix%send_buffer, i8)*size(matrix%send_buffer, kind=i8))/8_i8
  end function dist_csr_bytes

  !> This rank's block of `lanczos_start_vector`'s global vector (the same
  !> Park-Miller sequence, entered at `first_row` by modular powers), so the
  !> distributed iteration starts where the serial one does.
  pure subroutine dist_start_vector(first_row, x)
    !> Global index of x(1).
    integer, intent(in) :: first_row
    !> Filled with entries first_row .. first_row + size(x) - 1.
    real(dp), intent(out) :: x(:)
    integer(i8), parameter :: modulus = 2147483647_i8, multiplier = 48271_i8
    integer(i8) :: state, base
    integer :: i, k
    ! state after first_row - 1 steps: multiplier**(first_row - 1) mod modulus
    state = 1_i8
    base = multiplier
    k = first_row - 1
    do while (k > 0)
      if (mod(k, 2) == 1) state = mod(state*base, modulus)
      base = mod(base*base, modulus)
      k = k/2
    end do
    do i = 1, size(x)
      state = mod(multiplier*state, modulus)
      x(i) = real(state, dp)/real(modulus, dp) - 0.5_dp
    end do
  end subroutine dist_start_vector

  !> The largest eigenvalue of the distributed operator and this rank's block of
  !> a unit eigenvector, by PARPACK (the arguments and statuses of
  !> `lanczos_largest`; PARPACK's failures through `pdsaupd_status`,
  !> `pdseupd_status`). Collective; the result is the same on every rank.
  subroutine parallel_lanczos_largest(matrix, result, status, eigenvector, tolerance, ncv, &
      nev, max_restarts, progress, start)
    type(dist_csr_type), intent(inout) :: matrix
    type(eigen_result_type), intent(out) :: result
    type(demstep_status_type), intent(out) :: status
    !> This rank's block of the unit eigenvector (n_local).
    real(dp), intent(out), optional :: eigenvector(:)
    !> Relative residual tolerance, in [epsilon, 0.1]; default `lanczos_tolerance_default`.
    real(dp), intent(in), optional :: tolerance
    !> Krylov size, > nev; capped at n_global. Default `lanczos_ncv_default`.
    integer, intent(in), optional :: ncv
    !> Wanted Ritz values kept at restarts, >= 1 and < ncv. Default `lanczos_nev_default`.
    integer, intent(in), optional :: nev
    !> Maximum implicit restarts (>= 1). Default `lanczos_restarts_default`.
    integer, intent(in), optional :: max_restarts
    !> Told the products done on this rank (pass it on one rank, e.g. rank 0).
    class(progress_type), intent(inout), optional :: progress
    !> This rank's block of a start vector (n_local; a warm start, as the
    !> serial `lanczos_largest`'s), the same on every rank or absent on every rank.
    real(dp), intent(in), optional :: start(:)
    real(dp) :: tol, theta, rnorm, znorm
    integer :: k, m, restarts, ido, info, lworkl, nconv, n, itop, fcomm
    integer :: iparam(arpack_iparam_size), ipntr(arpack_iparam_size)
    real(dp), allocatable :: v(:, :), workd(:), workl(:), resid(:), z(:, :), d(:), y(:)
    logical, allocatable :: select(:)
    type(demstep_status_type) :: step_status

    call lanczos_options(tol, m, k, restarts, tolerance, ncv, nev, max_restarts)
    result%solver = parallel_lanczos_solver_name
    result%tolerance = tol
    n = matrix%n_local
    if (present(eigenvector)) eigenvector = 0.0_dp
    if (matrix%n_global < 1) then
      call set_status(status, demstep_stat%invalid_input, "parallel_lanczos_largest: " &
        //"matrix: not built by dist_csr_create")
      return
    end if
    ! the arguments are the same on every rank but the eigenvector's size
    if (present(eigenvector)) then
      if (.not. all_ranks(size(eigenvector) == n)) then
        call set_status(status, demstep_stat%invalid_input, "parallel_lanczos_largest: " &
          //"eigenvector: need this rank's n_local entries on every rank")
        return
      end if
    end if
    call check_lanczos_options("parallel_lanczos_largest", tol, k, m, restarts, status)
    if (status%stat /= demstep_stat%ok) return
    if (present(progress)) call progress%start("Lanczos products", 0_i8)
    call iterate()
    if (present(progress)) call progress%finish()

  contains

    !> resid = start/|start| + 1e-3 resid/|resid| (global norms), when start
    !> is non-zero on some rank and has n_local entries on every rank.
    subroutine warm_start()
      real(dp) :: norms(2)
      logical :: fits
      fits = size(start) == n
      call MPI_Allreduce(MPI_IN_PLACE, fits, 1, MPI_LOGICAL, MPI_LAND, matrix%graph)
      if (.not. fits) return
      norms = [sum(start**2), sum(resid**2)]
      call MPI_Allreduce(MPI_IN_PLACE, norms, 2, MPI_DOUBLE_PRECISION, MPI_SUM, matrix%graph)
      if (.not. norms(1) > 0.0_dp) return
      resid = start/sqrt(norms(1)) + 1.0e-3_dp*resid/sqrt(norms(2))
    end subroutine warm_start

    !> The iteration, the eigenvector and the error bar.
    subroutine iterate()
      allocate(y(n))
      if (matrix%n_global == 1) then
        ! one rank, one row: the operator is its own eigenvalue
        call product([1.0_dp], y, status)
        if (status%stat /= demstep_stat%ok) return
        result%eigenvalue = y(1)
        result%converged = .true.
        result%error_bound = rounding_ulps*epsilon(1.0_dp)*abs(y(1))
        if (present(eigenvector)) eigenvector = 1.0_dp
        return
      end if
      m = min(m, matrix%n_global)
      k = min(k, m - 1)
      result%ncv = m
      result%nev = k
      lworkl = m*(m + 8)
      allocate(v(n, m), workd(3*n), workl(lworkl), resid(n), d(k), select(m), z(n, k))
      call dist_start_vector(matrix%first_row, resid)
      if (present(start)) call warm_start()
      fcomm = matrix%graph%MPI_VAL
      iparam = 0
      iparam(1) = 1         ! exact shifts
      iparam(3) = restarts
      iparam(7) = 1         ! mode 1: OP = A, B = I
      ido = 0
      info = 1              ! start from resid
      do
        call pdsaupd(fcomm, ido, "I", n, "LA", k, tol, resid, m, v, n, iparam, ipntr, workd, &
          workl, lworkl, info)
        if (ido /= -1 .and. ido /= 1) exit
        call product(workd(ipntr(1):ipntr(1) + n - 1), workd(ipntr(2):ipntr(2) + n - 1), status)
        ! every rank leaves the loop together: PARPACK waits on all of them
        if (status%stat /= demstep_stat%ok) return
      end do
      result%iterations = iparam(3)
      if (info == -9) then
        ! A x0 = 0 for the start vector: the zero operator (see lanczos_largest)
        result%converged = .true.
        if (present(eigenvector)) then
          call dist_start_vector(matrix%first_row, eigenvector)
          eigenvector = eigenvector/sqrt(global_dot(eigenvector, eigenvector))
        end if
        status%stat = demstep_stat%ok
        return
      end if
      step_status = pdsaupd_status(info)
      nconv = iparam(5)
      if (step_status%stat /= demstep_stat%ok .and. step_status%stat /= demstep_stat%not_converged) then
        status = step_status
        return
      end if
      if (nconv < 1) then
        itop = maxloc(workl(ipntr(6):ipntr(6) + k - 1), 1) - 1
        result%eigenvalue = workl(ipntr(6) + itop)
        result%residual = abs(workl(ipntr(7) + itop))
        result%error_bound = result%residual + rounding_ulps*epsilon(1.0_dp)*abs(result%eigenvalue)
        if (step_status%stat == demstep_stat%ok) then
          call set_status(status, demstep_stat%not_converged, "PARPACK pdsaupd: no Ritz value " &
            //"met the tolerance")
        else
          status = step_status
        end if
        status%message = status%message//" (largest Ritz value "//real_text(result%eigenvalue) &
          //" after "//int_text(result%iterations)//" restarts, tolerance "//real_text(tol) &
          //"; raise max_restarts or ncv)"
        return
      end if

      call pdseupd(fcomm, .true., "A", select, d, z, n, 0.0_dp, "I", n, "LA", k, tol, resid, m, &
        v, n, iparam, ipntr, workd, workl, lworkl, info)
      if (info /= 0) then
        status = pdseupd_status(info)
        return
      end if
      z(:, 1) = z(:, min(nconv, k))
      znorm = sqrt(global_dot(z(:, 1), z(:, 1)))
      if (.not. (znorm > 0.0_dp)) then
        call set_status(status, demstep_stat%eigensolver_failure, "PARPACK pdseupd: returned " &
          //"a zero Ritz vector")
        return
      end if
      z(:, 1) = z(:, 1)/znorm
      call product(z(:, 1), y, status)
      if (status%stat /= demstep_stat%ok) return
      theta = global_dot(z(:, 1), y)/global_dot(z(:, 1), z(:, 1))
      y = y - theta*z(:, 1)
      rnorm = sqrt(global_dot(y, y))
      if (present(eigenvector)) eigenvector = z(:, 1)
      call lanczos_finish(theta, rnorm, tol, step_status, result, status)
    end subroutine iterate

    !> One product, counted; a non-finite value on any rank fails all of them.
    subroutine product(x, ax, stat)
      real(dp), intent(in) :: x(:)
      real(dp), intent(out) :: ax(:)
      type(demstep_status_type), intent(out) :: stat
      call dist_csr_apply(matrix, x, ax)
      result%applications = result%applications + 1
      if (present(progress)) call progress%update(result%applications)
      if (.not. all_ranks(all(ieee_is_finite(ax)))) then
        call set_status(stat, demstep_stat%invalid_input, "parallel_lanczos_largest: the " &
          //"operator returned a non-finite value (product "//int_text(result%applications)//")")
        return
      end if
      stat%stat = demstep_stat%ok
    end subroutine product

    !> x.y over all ranks: compensated local sums, then an MPI sum of the
    !> (value, error) pairs, rounded once.
    function global_dot(x, y) result(s)
      real(dp), intent(in) :: x(:), y(:)
      real(dp) :: s
      real(dp) :: pair(2), p, q, h, r
      integer :: i
      pair = 0.0_dp
      do i = 1, size(x)
        call two_prod(x(i), y(i), h, r)
        call two_sum(pair(1), h, p, q)
        pair(1) = p
        pair(2) = pair(2) + (q + r)
      end do
      call MPI_Allreduce(MPI_IN_PLACE, pair, 2, MPI_DOUBLE_PRECISION, MPI_SUM, matrix%graph)
      s = pair(1) + pair(2)
    end function global_dot

    !> True when the condition holds on every rank.
    function all_ranks(condition) result(held)
      logical, intent(in) :: condition
      logical :: held
      held = condition
      call MPI_Allreduce(MPI_IN_PLACE, held, 1, MPI_LOGICAL, MPI_LAND, matrix%graph)
    end function all_ranks

  end subroutine parallel_lanczos_largest

  !> Ascending heap sort, in place (O(n log n), no extra memory).
  pure subroutine heap_sort(a)
    integer, intent(inout) :: a(:)
    integer :: n, i, t
    n = size(a)
    do i = n/2, 1, -1
      call sift(a, i, n)
    end do
    do i = n, 2, -1
      t = a(1)
      a(1) = a(i)
      a(i) = t
      call sift(a, 1, i - 1)
    end do
  end subroutine heap_sort

  !> Move a(start) down the heap a(start:last) to its place.
  pure subroutine sift(a, start, last)
      integer, intent(inout) :: a(:)
      integer, intent(in) :: start, last
      integer :: root, child, tmp
      root = start
      do
        child = 2*root
        if (child > last) exit
        if (child < last) then
          if (a(child + 1) > a(child)) child = child + 1
        end if
        if (a(root) >= a(child)) exit
        tmp = a(root)
        a(root) = a(child)
        a(child) = tmp
        root = child
      end do
  end subroutine sift

  !> Index of `value` in the ascending array `a` (which holds it), by bisection.
  pure function position(a, value) result(i)
    integer, intent(in) :: a(:), value
    integer :: i
    integer :: lo, hi
    lo = 1
    hi = size(a)
    do while (lo < hi)
      i = (lo + hi)/2
      if (a(i) < value) then
        lo = i + 1
      else
        hi = i
      end if
    end do
    i = lo
  end function position

end module demstep_mpi_lanczos
