!> A sparse symmetric matrix in compressed rows: built from springs (a
!> weighted graph Laplacian, optionally grounded and mass-scaled), applied as
!> a Lanczos operator (`csr_apply`) and expanded to a dense matrix for small
!> checks. (Moved out of `demstep_lanczos`; the names are unchanged.)
module demstep_csr
  use demstep_kinds, only: dp, i8
  use demstep_status, only: demstep_status_type, demstep_stat, set_status
  use demstep_lanczos, only: lanczos_context_type
  use, intrinsic :: ieee_arithmetic, only: ieee_is_finite
  implicit none
  private

  public :: csr_from_springs, csr_apply, csr_abs_product, csr_to_dense

  !> Below this many rows a product runs on one thread: a parallel region costs
  !> more than the ~10 flops per row it would share.
  integer, parameter :: csr_parallel_rows = 20000

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
      call set_status(status, demstep_stat%invalid_input, "need n >= 1 " &
        //"and first, second, stiffness of one size", where="csr_from_springs")
      return
    end if
    if (any(first < 1 .or. first > n .or. second < 1 .or. second > n .or. first == second)) then
      call set_status(status, demstep_stat%invalid_input, "first, second: " &
        //"each spring joins two different nodes in 1..n", where="csr_from_springs")
      return
    end if
    if (.not. all(ieee_is_finite(stiffness) .and. stiffness >= 0.0_dp)) then
      call set_status(status, demstep_stat%invalid_input, "stiffness: " &
        //"must be finite and >= 0", where="csr_from_springs")
      return
    end if
    allocate(scale(n))
    scale = 1.0_dp
    if (present(mass)) then
      if (size(mass) /= n) then
        call set_status(status, demstep_stat%invalid_input, "mass: need size n", where="csr_from_springs")
        return
      end if
      if (.not. all(ieee_is_finite(mass) .and. mass > 0.0_dp)) then
        call set_status(status, demstep_stat%invalid_input, "mass: must " &
          //"be finite and > 0", where="csr_from_springs")
        return
      end if
      scale = 1.0_dp/sqrt(mass)
    end if
    if (present(ground)) then
      if (size(ground) /= n) then
        call set_status(status, demstep_stat%invalid_input, "ground: need size n", where="csr_from_springs")
        return
      end if
      if (.not. all(ieee_is_finite(ground) .and. ground >= 0.0_dp)) then
        call set_status(status, demstep_stat%invalid_input, "ground: must " &
          //"be finite and >= 0", where="csr_from_springs")
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

  !> r = |A| v for a `csr_matrix_type` (entrywise absolute values, a repeated
  !> column summed after them) and v >= 0, each row raised by its rounding
  !> allowance (1 + (entries + 4) eps): an upper bound of the exact |A| v,
  !> for Collatz-Wielandt bounds (`collatz_bound`).
  subroutine csr_abs_product(context, v, r)
    class(lanczos_context_type), intent(in) :: context
    real(dp), intent(in) :: v(:)
    real(dp), intent(out) :: r(:)
    integer :: i
    integer(i8) :: p
    r = 0.0_dp
    select type (a => context)
    class is (csr_matrix_type)
      do i = 1, a%n
        r(i) = 0.0_dp
        do p = a%row_start(i), a%row_start(i + 1) - 1
          r(i) = r(i) + abs(a%val(p))*v(a%col(p))
        end do
        r(i) = r(i)*(1.0_dp + real(a%row_start(i + 1) - a%row_start(i) + 4, dp)*epsilon(1.0_dp))
      end do
    end select
  end subroutine csr_abs_product

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

end module demstep_csr
