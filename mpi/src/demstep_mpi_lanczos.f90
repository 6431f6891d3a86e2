!> The largest eigenvalue of a symmetric positive semi-definite sparse operator
!> whose rows are partitioned across MPI ranks, by PARPACK's Lanczos iteration:
!> `demstep_lanczos`'s one driver (`lanczos_solve`) on a distributed space, so
!> the same start vector, stopping rule, error bar and messages as the serial
!> `lanczos_largest`.
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
  use demstep_parpack, only: pdsaupd, pdseupd, pdsaupd_status, pdseupd_status
  use demstep_lanczos, only: eigen_result_type, lanczos_space_type, lanczos_solve, &
    lanczos_start_vector, accurate_dot_parts
  use demstep_progress, only: progress_type
  use demstep_sort, only: heap_sort, count_before
  use, intrinsic :: ieee_arithmetic, only: ieee_is_finite
  implicit none
  private

  public :: dist_csr_create, dist_csr_apply, dist_gershgorin_bound, dist_collatz_bound, &
    parallel_lanczos_largest
  public :: offsets_of
  public :: dist_start_vector, dist_csr_bytes, dist_csr_free, dist_halo_create, dist_halo_exchange, &
    dist_halo_free

  !> The solver's name in a result.
  character(len=*), parameter, public :: parallel_lanczos_solver_name = &
    "lanczos (PARPACK pdsaupd, MPI)"

  !> A symmetric operator whose rows are partitioned across MPI ranks in
  !> contiguous blocks (rank order): what `parallel_lanczos_largest` solves.
  type, abstract, public :: dist_operator_type
    !> Global order, rows owned here and the first of them (global index).
    integer :: n_global = 0, n_local = 0, first_row = 1
    !> The ranks holding the rows (every one at least one row): the solver's
    !> reductions run over it.
    type(MPI_Comm) :: comm
  contains
    !> y = A x on this rank's rows (x, y: this rank's block). Collective.
    procedure(dist_apply), deferred :: apply
  end type dist_operator_type

  abstract interface
    subroutine dist_apply(op, x, y)
      import :: dist_operator_type, dp
      class(dist_operator_type), intent(inout) :: op
      real(dp), intent(in) :: x(:)
      real(dp), intent(out) :: y(:)
    end subroutine dist_apply
  end interface

  !> The halo exchange of a row-partitioned vector: the entries of other
  !> ranks' blocks this rank reads (ascending global indices, so by owner),
  !> and the pattern that brings them with one `MPI_Neighbor_alltoallv` on a
  !> graph communicator of the ranks that share entries.
  type, public :: dist_halo_type
    !> Halo entries received per exchange.
    integer :: n_halo = 0
    !> Graph communicator of the ranks exchanged with (neighbour collectives).
    type(MPI_Comm) :: graph
    !> Counts and 0-based displacements per neighbour, received and sent.
    integer, allocatable :: recv_count(:), recv_displ(:), send_count(:), send_displ(:)
    !> Local indices of the entries sent, neighbour by neighbour.
    integer, allocatable :: send_index(:)
    !> The send buffer.
    real(dp), allocatable :: send_buffer(:)
  end type dist_halo_type

  !> A row block of a sparse symmetric matrix with its halo-exchange pattern.
  type, extends(dist_operator_type), public :: dist_csr_type
    !> Halo entries received per product.
    integer :: n_halo = 0
    !> Local row i holds entries row_start(i) .. row_start(i+1)-1.
    integer(i8), allocatable :: row_start(:)
    !> Column of each entry in the extended local vector: 1..n_local own
    !> entries, n_local + k the k-th halo entry.
    integer, allocatable :: col(:)
    real(dp), allocatable :: val(:)
    !> The halo exchange; its graph communicator is also `comm`.
    type(dist_halo_type) :: halo
    !> The extended vector [own x, halo].
    real(dp), allocatable :: x_ext(:)
  contains
    procedure :: apply => dist_csr_apply_op
  end type dist_csr_type

  !> The distributed Lanczos space: PARPACK and a `dist_csr_type`'s product,
  !> inner products and "and" reduced over the matrix's communicator.
  type, extends(lanczos_space_type) :: dist_space_type
    class(dist_operator_type), pointer :: matrix => null()
  contains
    procedure :: product => dist_product
    procedure :: dot => dist_dot
    procedure :: all_ranks => dist_all
    procedure :: saupd => dist_saupd
    procedure :: seupd => dist_seupd
    procedure :: saupd_status => dist_saupd_status
    procedure :: seupd_status => dist_seupd_status
  end type dist_space_type

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
    integer :: nranks, rank, r, i, n_local, n_out, k, last_row
    integer, allocatable :: blocks(:, :), outside(:), halo(:)
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
    call dist_halo_create(comm, blocks, halo(:matrix%n_halo), matrix%halo)
    matrix%comm = matrix%halo%graph
    ! the local rows, columns renumbered into the extended vector
    allocate(matrix%row_start(n_local + 1), matrix%col(nnz), matrix%val(nnz))
    matrix%row_start = row_start
    matrix%val = val
    do e = 1, nnz
      if (col(e) >= first_row .and. col(e) <= last_row) then
        matrix%col(e) = col(e) - first_row + 1
      else
        matrix%col(e) = n_local + count_before(halo(:matrix%n_halo), col(e), .false.) + 1
      end if
    end do
    allocate(matrix%x_ext(n_local + matrix%n_halo), source=0.0_dp)
    status%stat = demstep_stat%ok
  end subroutine dist_csr_create

  !> Release the matrix's graph communicator and arrays. Collective; call it
  !> before MPI_Finalize and before building a new matrix into the same variable.
  subroutine dist_csr_free(matrix)
    type(dist_csr_type), intent(inout) :: matrix
    type(dist_csr_type) :: empty
    if (matrix%n_global >= 1) call dist_halo_free(matrix%halo)
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
      call dist_halo_exchange(matrix%halo, x, matrix%x_ext(n + 1:))
      do i = 1, n
        s = 0.0_dp
        do p = matrix%row_start(i), matrix%row_start(i + 1) - 1
          s = s + matrix%val(p)*matrix%x_ext(matrix%col(p))
        end do
        y(i) = s
      end do
    end associate
  end subroutine dist_csr_apply

  !> `dist_csr_apply` as the operator's binding.
  subroutine dist_csr_apply_op(op, x, y)
    class(dist_csr_type), intent(inout) :: op
    real(dp), intent(in) :: x(:)
    real(dp), intent(out) :: y(:)
    call dist_csr_apply(op, x, y)
  end subroutine dist_csr_apply_op

  !> The halo-exchange pattern of this rank's block: `halo` lists the global
  !> indices it reads from other ranks' blocks, ascending and distinct;
  !> `blocks(:, r)` = (first index, count) of rank r's block (rank order,
  !> every rank one). Collective over `comm`.
  subroutine dist_halo_create(comm, blocks, halo, pattern)
    type(MPI_Comm), intent(in) :: comm
    integer, intent(in) :: blocks(:, 0:)
    integer, intent(in) :: halo(:)
    type(dist_halo_type), intent(out) :: pattern
    integer :: nranks, rank, r, i, p, nb_in, nb_out
    integer, allocatable :: want(:), give(:), want_displ(:), give_displ(:), requested(:), &
      sources(:), dests(:)
    call MPI_Comm_size(comm, nranks)
    call MPI_Comm_rank(comm, rank)
    pattern%n_halo = size(halo)
    ! how many halo entries each rank owns
    allocate(want(0:nranks - 1), give(0:nranks - 1), want_displ(0:nranks - 1), &
      give_displ(0:nranks - 1))
    want = 0
    r = 0
    do i = 1, size(halo)
      do while (halo(i) > blocks(1, r) + blocks(2, r) - 1)
        r = r + 1
      end do
      want(r) = want(r) + 1
    end do
    call MPI_Alltoall(want, 1, MPI_INTEGER, give, 1, MPI_INTEGER, comm)
    want_displ = offsets_of(want)
    give_displ = offsets_of(give)
    allocate(requested(sum(give)))
    call MPI_Alltoallv(halo, want, want_displ, MPI_INTEGER, requested, give, give_displ, &
      MPI_INTEGER, comm)
    ! the neighbour graph: sources send to this rank, destinations receive from it
    nb_in = count(want > 0)
    nb_out = count(give > 0)
    allocate(sources(nb_in), dests(nb_out), pattern%recv_count(nb_in), pattern%recv_displ(nb_in), &
      pattern%send_count(nb_out), pattern%send_displ(nb_out))
    p = 0
    do r = 0, nranks - 1
      if (want(r) == 0) cycle
      p = p + 1
      sources(p) = r
      pattern%recv_count(p) = want(r)
      pattern%recv_displ(p) = want_displ(r)
    end do
    p = 0
    do r = 0, nranks - 1
      if (give(r) == 0) cycle
      p = p + 1
      dests(p) = r
      pattern%send_count(p) = give(r)
      pattern%send_displ(p) = give_displ(r)
    end do
    pattern%send_index = requested - blocks(1, rank) + 1
    allocate(pattern%send_buffer(size(requested)))
    call MPI_Dist_graph_create_adjacent(comm, nb_in, sources, MPI_UNWEIGHTED, nb_out, dests, &
      MPI_UNWEIGHTED, MPI_INFO_NULL, .false., pattern%graph)
  end subroutine dist_halo_create

  !> The halo entries of a vector: `x` this rank's block, `x_halo` (n_halo)
  !> the entries it reads from other ranks. Collective over the pattern's graph.
  subroutine dist_halo_exchange(pattern, x, x_halo)
    type(dist_halo_type), intent(inout) :: pattern
    real(dp), intent(in) :: x(:)
    real(dp), intent(inout) :: x_halo(:)
    pattern%send_buffer = x(pattern%send_index)
    call MPI_Neighbor_alltoallv(pattern%send_buffer, pattern%send_count, pattern%send_displ, &
      MPI_DOUBLE_PRECISION, x_halo, pattern%recv_count, pattern%recv_displ, &
      MPI_DOUBLE_PRECISION, pattern%graph)
  end subroutine dist_halo_exchange

  !> Release a halo pattern's graph communicator. Collective.
  subroutine dist_halo_free(pattern)
    type(dist_halo_type), intent(inout) :: pattern
    call MPI_Comm_free(pattern%graph)
  end subroutine dist_halo_free

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
    call MPI_Allreduce(MPI_IN_PLACE, bound, 1, MPI_DOUBLE_PRECISION, MPI_MAX, matrix%comm)
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
      call MPI_Allreduce(MPI_IN_PLACE, q, 2, MPI_DOUBLE_PRECISION, MPI_MAX, matrix%comm)
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
      + storage_size(matrix%halo%send_index, i8)*size(matrix%halo%send_index, kind=i8) &
      + storage_size(matrix%x_ext, i8)*size(matrix%x_ext, kind=i8) &
      + storage_size(matrix%halo%send_buffer, i8)*size(matrix%halo%send_buffer, kind=i8))/8_i8
  end function dist_csr_bytes

  !> This rank's block of `lanczos_start_vector`'s global vector (entered at
  !> `first_row`), so the distributed iteration starts where the serial one does.
  pure subroutine dist_start_vector(first_row, x)
    !> Global index of x(1).
    integer, intent(in) :: first_row
    !> Filled with entries first_row .. first_row + size(x) - 1.
    real(dp), intent(out) :: x(:)
    call lanczos_start_vector(x, first_row)
  end subroutine dist_start_vector

  !> The largest eigenvalue of the distributed operator and this rank's block of
  !> a unit eigenvector, by PARPACK: `lanczos_solve` (the serial driver's
  !> arguments, statuses and error bar) on the distributed space, PARPACK's
  !> failures through `pdsaupd_status`, `pdseupd_status`. Collective; the
  !> result is the same on every rank.
  subroutine parallel_lanczos_largest(matrix, result, status, eigenvector, tolerance, ncv, &
      nev, max_restarts, progress, start, certify, lower_bound)
    class(dist_operator_type), intent(inout), target :: matrix
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
    !> Add the randomised certificate (default no) with a lower bound of the
    !> spectrum (default 0), as `lanczos_largest`'s.
    logical, intent(in), optional :: certify
    real(dp), intent(in), optional :: lower_bound
    type(dist_space_type) :: space
    result%solver = parallel_lanczos_solver_name
    if (present(eigenvector)) eigenvector = 0.0_dp
    if (matrix%n_global < 1) then
      call set_status(status, demstep_stat%invalid_input, "parallel_lanczos_largest: " &
        //"matrix: not built (no rows)")
      return
    end if
    space%matrix => matrix
    space%n_global = matrix%n_global
    space%n_local = matrix%n_local
    space%first_row = matrix%first_row
    space%caller = "parallel_lanczos_largest"
    space%solver = parallel_lanczos_solver_name
    ! the arguments are the same on every rank but the eigenvector's size
    if (present(eigenvector)) then
      if (.not. space%all_ranks(size(eigenvector) == matrix%n_local)) then
        call set_status(status, demstep_stat%invalid_input, "parallel_lanczos_largest: " &
          //"eigenvector: need this rank's n_local entries on every rank")
        return
      end if
    end if
    call lanczos_solve(space, result, status, eigenvector, tolerance, ncv, nev, max_restarts, &
      progress, start, certify, lower_bound)
  end subroutine parallel_lanczos_largest

  subroutine dist_product(space, x, y)
    class(dist_space_type), intent(inout) :: space
    real(dp), intent(in) :: x(:)
    real(dp), intent(out) :: y(:)
    call space%matrix%apply(x, y)
  end subroutine dist_product

  !> x.y over all ranks: compensated local sums, then an MPI sum of the
  !> (value, error) pairs, rounded once.
  function dist_dot(space, x, y) result(s)
    class(dist_space_type), intent(inout) :: space
    real(dp), intent(in) :: x(:), y(:)
    real(dp) :: s
    real(dp) :: pair(2)
    pair = accurate_dot_parts(x, y)
    call MPI_Allreduce(MPI_IN_PLACE, pair, 2, MPI_DOUBLE_PRECISION, MPI_SUM, space%matrix%comm)
    s = pair(1) + pair(2)
  end function dist_dot

  function dist_all(space, condition) result(held)
    class(dist_space_type), intent(inout) :: space
    logical, intent(in) :: condition
    logical :: held
    held = condition
    call MPI_Allreduce(MPI_IN_PLACE, held, 1, MPI_LOGICAL, MPI_LAND, space%matrix%comm)
  end function dist_all

  subroutine dist_saupd(space, ido, nev, tol, resid, ncv, v, iparam, ipntr, workd, workl, info)
    class(dist_space_type), intent(inout) :: space
    integer, intent(inout) :: ido
    integer, intent(in) :: nev, ncv
    real(dp), intent(inout) :: tol
    real(dp), intent(inout) :: resid(:), v(:, :), workd(:), workl(:)
    integer, intent(inout) :: iparam(:), ipntr(:), info
    call pdsaupd(space%matrix%comm%MPI_VAL, ido, "I", space%n_local, "LA", nev, tol, resid, &
      ncv, v, space%n_local, iparam, ipntr, workd, workl, size(workl), info)
  end subroutine dist_saupd

  subroutine dist_seupd(space, rvec, select, d, z, nev, tol, resid, ncv, v, iparam, ipntr, &
      workd, workl, info)
    class(dist_space_type), intent(inout) :: space
    logical, intent(in) :: rvec
    logical, intent(inout) :: select(:)
    real(dp), intent(out) :: d(:)
    real(dp), intent(inout) :: z(:, :)
    integer, intent(in) :: nev, ncv
    real(dp), intent(in) :: tol
    real(dp), intent(inout) :: resid(:), v(:, :), workd(:), workl(:)
    integer, intent(inout) :: iparam(:), ipntr(:)
    integer, intent(out) :: info
    call pdseupd(space%matrix%comm%MPI_VAL, rvec, "A", select, d, z, space%n_local, 0.0_dp, &
      "I", space%n_local, "LA", nev, tol, resid, ncv, v, space%n_local, iparam, ipntr, workd, &
      workl, size(workl), info)
  end subroutine dist_seupd

  pure function dist_saupd_status(space, info) result(status)
    class(dist_space_type), intent(in) :: space
    integer, intent(in) :: info
    type(demstep_status_type) :: status
    status = pdsaupd_status(info)
  end function dist_saupd_status

  pure function dist_seupd_status(space, info) result(status)
    class(dist_space_type), intent(in) :: space
    integer, intent(in) :: info
    type(demstep_status_type) :: status
    status = pdseupd_status(info)
  end function dist_seupd_status

  !> The displacements of `counts` laid end to end in rank order (0,
  !> counts(0), counts(0) + counts(1), ...), as MPI_Alltoallv takes them.
  pure function offsets_of(counts) result(at)
    integer, intent(in) :: counts(0:)
    integer :: at(0:size(counts) - 1)
    integer :: r
    if (size(counts) == 0) return
    at(0) = 0
    do r = 1, size(counts) - 1
      at(r) = at(r - 1) + counts(r - 1)
    end do
  end function offsets_of

end module demstep_mpi_lanczos
