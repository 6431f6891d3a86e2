!> The dense operator of the benchmark, in a module: a procedure passed as an
!> argument must not be internal (that would need an executable stack).
module bench_eigen_dense
  use demstep_kinds, only: dp
  use demstep_lanczos, only: lanczos_context_type
  implicit none
  private
  public :: dense_operator_type, dense_operator

  !> A dense symmetric matrix as a Lanczos operator (BLAS dsymv).
  type, extends(lanczos_context_type) :: dense_operator_type
    real(dp), allocatable :: a(:, :)
  end type dense_operator_type

  interface
    !> BLAS dsymv: y = alpha A x + beta y, A symmetric (its lower triangle).
    subroutine dsymv(uplo, n, alpha, a, lda, x, incx, beta, y, incy)
      import :: dp
      character(len=1), intent(in) :: uplo
      integer, intent(in) :: n, lda, incx, incy
      real(dp), intent(in) :: alpha, beta, a(lda, *), x(*)
      real(dp), intent(inout) :: y(*)
    end subroutine dsymv
  end interface

contains

  !> y = A x for a [[dense_operator_type]] (zero for any other context).
  subroutine dense_operator(context, x, y)
    class(lanczos_context_type), intent(inout) :: context
    real(dp), intent(in) :: x(:)
    real(dp), intent(out) :: y(:)
    select type (context)
    type is (dense_operator_type)
      call dsymv("L", size(x), 1.0_dp, context%a, size(context%a, 1), x, 1, 0.0_dp, y, 1)
    class default
      y = 0.0_dp
    end select
  end subroutine dense_operator
end module bench_eigen_dense

!> Benchmark of the largest eigenvalue of a mass-scaled stiffness matrix:
!> dense LAPACK (dsyevr) against matrix-free Lanczos (ARPACK) on the same dense
!> matrices, then Lanczos on sparse contact-network operators of 1e4 to 1e6
!> degrees of freedom. Wall-clock median of 3 runs. The BLAS/LAPACK in use is
!> whatever the system routes libblas.so.3/liblapack.so.3 to (reference or
!> OpenBLAS), and the threads are OMP_NUM_THREADS's.
!>
!>   fpm run --example bench_eigen --profile release [-- quick]
program bench_eigen
  use, intrinsic :: iso_fortran_env, only: output_unit
  use demstep_kinds, only: dp, i8
  use demstep_status, only: demstep_status_type, demstep_stat
  use demstep_progress, only: progress_seconds
  use demstep_lapack, only: largest_eigenpair
  use demstep_lanczos, only: lanczos_largest, lanczos_context_type, eigen_result_type
  use demstep_csr, only: csr_matrix_type, csr_from_springs, csr_apply, csr_to_dense
  use bench_eigen_dense, only: dense_operator_type, dense_operator
  !$ use omp_lib, only: omp_get_max_threads
  implicit none

  integer, parameter :: repeats = 3
  integer, parameter :: dense_sizes(2) = [900, 2739]
  integer, parameter :: sparse_sizes(3) = [10000, 100000, 1000000]
  integer, parameter :: lattice_sides(2) = [46, 100]
  character(len=16) :: arg
  logical :: quick, dense_only
  integer :: threads, t, i
  type(csr_matrix_type) :: net
  type(dense_operator_type) :: op
  real(dp), allocatable :: work(:, :), z(:)
  real(dp) :: lambda, times(repeats), t0
  type(eigen_result_type) :: r
  type(demstep_status_type) :: status

  call get_command_argument(1, arg)
  quick = arg == "quick"
  dense_only = arg == "dense"
  threads = 1
  !$ threads = omp_get_max_threads()
  write(output_unit, '(a, i0, a)') "# largest eigenvalue of mass-scaled contact-network stiffness; ", &
    threads, " OpenMP thread(s); wall-clock median of 3"
  write(output_unit, '(a)') "# solver            dof    nnz/row  tol      seconds    products  passes  " &
    //"eigenvalue               rel. error bar"

  do t = 1, size(dense_sizes)
    if (quick .and. t > 1) exit
    call contact_network(dense_sizes(t), 3, int(7 + t, i8), net)
    call csr_to_dense(net, op%a)
    allocate(work(dense_sizes(t), dense_sizes(t)), z(dense_sizes(t)))
    do i = 1, repeats
      work = op%a
      t0 = progress_seconds()
      call largest_eigenpair(work, lambda, z, status)
      times(i) = progress_seconds() - t0
      call require(status, "dsyevr")
    end do
    write(output_unit, '(a, i10, f9.1, a, f10.3, 2a10, es25.16)') "dense dsyevr    ", dense_sizes(t), &
      nnz_per_row(net), "  -      ", median(times), "-", "-", lambda
    call run_lanczos("lanczos dense   ", dense_operator, op, dense_sizes(t), 1.0e-10_dp, &
      nnz_per_row(net))
    deallocate(work, z)
  end do

  do t = 1, size(sparse_sizes)
    if (dense_only .or. (quick .and. t > 1)) exit
    call contact_network(sparse_sizes(t), 3, int(20 + t, i8), net)
    call run_lanczos("lanczos sparse  ", csr_apply, net, net%n, 1.0e-6_dp, nnz_per_row(net))
    call run_lanczos("lanczos sparse  ", csr_apply, net, net%n, 1.0e-10_dp, nnz_per_row(net))
  end do
  ! periodic cubic lattices: a near-degenerate top (the next eigenvalue 3e-3 to
  ! 1.5e-3 below it, relative), the hard case for Lanczos; the top is 12
  do t = 1, size(lattice_sides)
    if (quick .or. dense_only) exit
    call cubic_lattice_laplacian(lattice_sides(t), net)
    call run_lanczos("lanczos lattice ", csr_apply, net, net%n, 1.0e-6_dp, nnz_per_row(net))
    call run_lanczos("lanczos lattice ", csr_apply, net, net%n, 1.0e-10_dp, nnz_per_row(net))
  end do

contains

  !> Lanczos on `context`, median of 3, one table line.
  subroutine run_lanczos(label, apply, context, n, tol, per_row)
    character(len=*), intent(in) :: label
    interface
      subroutine apply(context, x, y)
        import :: dp, lanczos_context_type
        class(lanczos_context_type), intent(inout) :: context
        real(dp), intent(in) :: x(:)
        real(dp), intent(out) :: y(:)
      end subroutine apply
    end interface
    class(lanczos_context_type), intent(inout) :: context
    integer, intent(in) :: n
    real(dp), intent(in) :: tol, per_row
    real(dp) :: times(repeats), t0
    integer :: i
    do i = 1, repeats
      t0 = progress_seconds()
      call lanczos_largest(apply, context, n, r, status, tolerance=tol)
      times(i) = progress_seconds() - t0
      call require(status, "lanczos")
    end do
    write(output_unit, '(a, i10, f9.1, es9.1, f10.3, 2i10, es25.16, es12.2)') label, n, per_row, &
      tol, median(times), r%applications, r%iterations, r%eigenvalue, r%error_bound/r%eigenvalue
  end subroutine run_lanczos

  !> A contact network ordered by space: node i touches `per_node` nodes among
  !> the next 60 (periodically), stiffness over two decades, masses over a
  !> factor 4, 1% of the nodes grounded (walls).
  subroutine contact_network(n, per_node, seed, a)
    integer, intent(in) :: n, per_node
    integer(i8), intent(in) :: seed
    type(csr_matrix_type), intent(out) :: a
    integer, allocatable :: first(:), second(:)
    real(dp), allocatable :: k(:), mass(:), ground(:)
    integer(i8) :: state
    integer :: i, j, e
    state = seed
    allocate(first(n*per_node), second(n*per_node), k(n*per_node), mass(n), ground(n))
    e = 0
    do i = 1, n
      do j = 1, per_node
        e = e + 1
        first(e) = i
        second(e) = 1 + mod(i + int(uniform(state)*min(60, n - 1)), n)
        k(e) = 10.0_dp**(2.0_dp*uniform(state) - 1.0_dp)
      end do
      mass(i) = 0.5_dp + 1.5_dp*uniform(state)
      ground(i) = merge(1.0_dp, 0.0_dp, uniform(state) < 0.01_dp)
    end do
    call csr_from_springs(n, first, second, k, a, status, ground=ground, mass=mass)
    call require(status, "contact_network")
  end subroutine contact_network

  !> The periodic L**3 lattice of unit springs (top eigenvalue 12 for even L).
  subroutine cubic_lattice_laplacian(l, a)
    integer, intent(in) :: l
    type(csr_matrix_type), intent(out) :: a
    integer, allocatable :: first(:), second(:)
    real(dp), allocatable :: k(:)
    integer :: i, j, m, e
    allocate(first(3*l**3), second(3*l**3), k(3*l**3))
    e = 0
    do m = 0, l - 1
      do j = 0, l - 1
        do i = 0, l - 1
          first(e + 1:e + 3) = 1 + i + l*j + l*l*m
          second(e + 1) = 1 + mod(i + 1, l) + l*j + l*l*m
          second(e + 2) = 1 + i + l*mod(j + 1, l) + l*l*m
          second(e + 3) = 1 + i + l*j + l*l*mod(m + 1, l)
          e = e + 3
        end do
      end do
    end do
    k = 1.0_dp
    call csr_from_springs(l**3, first, second, k, a, status)
    call require(status, "cubic_lattice_laplacian")
  end subroutine cubic_lattice_laplacian

  !> Park-Miller uniform in (0, 1).
  function uniform(state) result(u)
    integer(i8), intent(inout) :: state
    real(dp) :: u
    state = mod(16807_i8*state, 2147483647_i8)
    u = real(state, dp)/2147483647.0_dp
  end function uniform

  real(dp) function nnz_per_row(a)
    type(csr_matrix_type), intent(in) :: a
    nnz_per_row = real(a%row_start(a%n + 1) - 1, dp)/real(a%n, dp)
  end function nnz_per_row

  real(dp) function median(x)
    real(dp), intent(in) :: x(3)
    median = max(min(x(1), x(2)), min(max(x(1), x(2)), x(3)))
  end function median

  subroutine require(s, what)
    type(demstep_status_type), intent(in) :: s
    character(len=*), intent(in) :: what
    if (s%stat /= demstep_stat%ok) then
      write(output_unit, '(a)') "bench_eigen: "//what//": "//s%message
      error stop 1
    end if
  end subroutine require

end program bench_eigen
