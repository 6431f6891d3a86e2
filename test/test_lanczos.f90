!> Tests of the matrix-free Lanczos driver (ARPACK) for the largest eigenvalue:
!> against dense LAPACK on random contact networks, against closed forms on
!> periodic lattices (degenerate tops), at 1e5 degrees of freedom, its error bar,
!> its statuses, and ARPACK's info codes.
module test_lanczos
  use testdrive, only: new_unittest, unittest_type, error_type, check, test_failed
  use demstep_kinds, only: dp, i8, pi
  use demstep_status, only: demstep_status_type, demstep_stat
  use demstep_lapack, only: largest_eigenpair
  use demstep_arpack, only: dsaupd, dsaupd_status, dseupd_status
  use demstep_lanczos, only: lanczos_largest, lanczos_context_type, eigen_result_type, &
    lanczos_start_vector, lanczos_tolerance_default, lanczos_runs, lanczos_basis_confirmed, &
    lanczos_basis_estimate, lanczos_basis_whole, certificate_failure, certificate_margin, certificate_steps, &
    single_basis_tolerance
  use demstep_csr, only: csr_matrix_type, csr_from_springs, csr_apply, csr_to_dense
  use test_support, only: real_str
  use demstep_progress, only: progress_type
  use demstep_text, only: int_text
  !$ use omp_lib, only: omp_set_num_threads, omp_get_max_threads
  use, intrinsic :: ieee_arithmetic, only: ieee_value, ieee_positive_inf, ieee_quiet_nan
  implicit none
  private
  public :: collect_lanczos

  !> An operator that fails (NaN) or does nothing (zero).
  type, extends(lanczos_context_type) :: odd_operator_type
    integer :: which = 0
    !> Products made; with which = 7, the product that returns a NaN.
    integer :: products = 0, bad_product = 0
  end type odd_operator_type

  !> Counts the progress calls.
  type, extends(progress_type) :: count_progress_type
    integer :: starts = 0, updates = 0, finishes = 0
    integer(i8) :: total = 0, last = 0
  contains
    procedure :: start => count_start
    procedure :: update => count_update
    procedure :: finish => count_finish
  end type count_progress_type

contains

  subroutine count_start(self, what, total)
    class(count_progress_type), intent(inout) :: self
    character(len=*), intent(in) :: what
    integer(i8), intent(in) :: total
    if (len(what) > 0) self%starts = self%starts + 1
    self%total = total
  end subroutine count_start

  subroutine count_update(self, done)
    class(count_progress_type), intent(inout) :: self
    integer(i8), intent(in) :: done
    self%updates = self%updates + 1
    self%last = done
  end subroutine count_update

  subroutine count_finish(self)
    class(count_progress_type), intent(inout) :: self
    self%finishes = self%finishes + 1
  end subroutine count_finish

  subroutine collect_lanczos(testsuite)
    type(unittest_type), allocatable, intent(out) :: testsuite(:)
    testsuite = [ &
      new_unittest("random contact networks: the dense eigenvalue to 1e-10", test_random), &
      new_unittest("lattices with degenerate tops: closed forms", test_lattices), &
      new_unittest("a 1e5-dof lattice with an 8-fold top converges", test_large_lattice), &
      new_unittest("restarts run out: not converged, a bound still", test_not_converged), &
      new_unittest("bad arguments, n = 1, a zero and a NaN operator", test_arguments), &
      new_unittest("ARPACK info codes as statuses (some provoked)", test_arpack_codes), &
      new_unittest("springs to CSR: the dense matrix, bad springs refused", test_csr), &
      new_unittest("same result for 1 and 2 threads, run after run", test_threads), &
      new_unittest("same bits for 1 and 2 threads at 2e5: blocked sums, double and single store, none kept", &
        test_threads_blocked), &
      new_unittest("progress: one start, a update per product, one finish", test_progress), &
      new_unittest("the randomised certificate bounds the top (semi-definite, shifted)", test_certificate), &
      new_unittest("a certified run whose vectors are not kept: the Ritz vector from a second pass", &
        test_second_pass), &
      new_unittest("the Lanczos store: double, single, none kept, dropped mid-run, single's fallback", &
        test_store_paths), &
      new_unittest("a non-finite product in the certified single run is refused", test_single_run_nonfinite) &
      ]
  end subroutine collect_lanczos

  !> A reproducible uniform number in (0, 1) (Park-Miller, multiplier 16807).
  subroutine uniform(state, u)
    integer(i8), intent(inout) :: state
    real(dp), intent(out) :: u
    state = mod(16807_i8*state, 2147483647_i8)
    u = real(state, dp)/2147483647.0_dp
  end subroutine uniform

  !> A random contact network on n nodes: each node touches `per_node` random
  !> others, stiffness spread over two decades, masses over a factor 4, a few
  !> nodes grounded.
  subroutine random_network(n, per_node, seed, a)
    integer, intent(in) :: n, per_node
    integer(i8), intent(in) :: seed
    type(csr_matrix_type), intent(out) :: a
    integer, allocatable :: first(:), second(:)
    real(dp), allocatable :: k(:), mass(:), ground(:)
    integer(i8) :: state
    integer :: i, j, e
    real(dp) :: u
    type(demstep_status_type) :: status
    state = seed
    allocate(first(n*per_node), second(n*per_node), k(n*per_node), mass(n), ground(n))
    e = 0
    do i = 1, n
      do j = 1, per_node
        e = e + 1
        first(e) = i
        do
          call uniform(state, u)
          second(e) = 1 + min(n - 1, int(u*n))
          if (second(e) /= i) exit
        end do
        call uniform(state, u)
        k(e) = 10.0_dp**(2.0_dp*u - 1.0_dp)
      end do
      call uniform(state, u)
      mass(i) = 0.5_dp + 1.5_dp*u
      call uniform(state, u)
      ground(i) = merge(1.0_dp, 0.0_dp, u < 0.05_dp)
    end do
    call csr_from_springs(n, first, second, k, a, status, ground=ground, mass=mass)
    if (status%stat /= demstep_stat%ok) error stop "random_network: "//status%message
  end subroutine random_network

  !> The periodic lattice of L**dim unit-spring nodes, `copies` disconnected
  !> copies of it; its largest eigenvalue in closed form: dim * 4 sin^2(pi m/L)
  !> with m = L/2 rounded down (for odd L the top is 2**dim-fold per copy).
  subroutine periodic_lattice(dim, l, copies, a, top)
    integer, intent(in) :: dim, l, copies
    type(csr_matrix_type), intent(out) :: a
    real(dp), intent(out) :: top
    integer, allocatable :: first(:), second(:)
    real(dp), allocatable :: k(:)
    integer :: n1, c, node, d, e, idx(3), nb(3)
    type(demstep_status_type) :: status
    n1 = l**dim
    allocate(first(dim*n1*copies), second(dim*n1*copies), k(dim*n1*copies))
    e = 0
    do c = 0, copies - 1
      do node = 0, n1 - 1
        idx = 0
        idx(1) = mod(node, l)
        if (dim >= 2) idx(2) = mod(node/l, l)
        if (dim >= 3) idx(3) = node/(l*l)
        do d = 1, dim
          nb = idx
          nb(d) = mod(nb(d) + 1, l)
          e = e + 1
          first(e) = 1 + c*n1 + node
          second(e) = 1 + c*n1 + nb(1) + l*nb(2) + l*l*nb(3)
        end do
      end do
    end do
    k = 1.0_dp
    call csr_from_springs(n1*copies, first, second, k, a, status)
    if (status%stat /= demstep_stat%ok) error stop "periodic_lattice: "//status%message
    top = dim*4.0_dp*sin(pi*real(l/2, dp)/real(l, dp))**2
  end subroutine periodic_lattice

  !> Checks of a converged result against a reference eigenvalue `ref` known to
  !> `ref_err` (absolute): relative agreement `rel`, the lower-bound property and
  !> the error bar holding the reference.
  subroutine check_result(error, r, status, ref, ref_err, rel, label)
    type(error_type), allocatable, intent(out) :: error
    type(eigen_result_type), intent(in) :: r
    type(demstep_status_type), intent(in) :: status
    real(dp), intent(in) :: ref, ref_err, rel
    character(len=*), intent(in) :: label
    call check(error, status%stat, demstep_stat%ok, label//": status")
    if (allocated(error)) return
    call check(error, r%converged, label//": converged")
    if (allocated(error)) return
    call check(error, r%eigenvalue, ref, thr=rel, rel=.true., message=label//": eigenvalue " &
      //real_str(r%eigenvalue)//" vs "//real_str(ref))
    if (allocated(error)) return
    ! a Rayleigh quotient never exceeds the largest eigenvalue (up to rounding)
    call check(error, r%eigenvalue <= ref + ref_err + r%error_bound, label//": above the top")
    if (allocated(error)) return
    call check(error, abs(r%eigenvalue - ref) <= r%error_bound + ref_err, label//": error bar " &
      //real_str(r%error_bound)//" misses "//real_str(abs(r%eigenvalue - ref)))
    if (allocated(error)) return
    call check(error, r%residual <= r%tolerance*r%eigenvalue, label//": residual " &
      //real_str(r%residual)//" above the tolerance")
    if (allocated(error)) return
    call check(error, r%solver == "lanczos (ARPACK dsaupd)" .and. r%applications > 0 &
      .and. r%iterations > 0, label//": solver, counts")
  end subroutine check_result

  subroutine test_random(error)
    type(error_type), allocatable, intent(out) :: error
    integer, parameter :: sizes(4) = [12, 80, 300, 900], per_node(4) = [2, 3, 4, 6]
    type(csr_matrix_type) :: a
    type(eigen_result_type) :: r
    type(demstep_status_type) :: status
    real(dp), allocatable :: dense(:, :), z_dense(:), z(:)
    real(dp) :: lambda
    integer :: t
    do t = 1, size(sizes)
      call random_network(sizes(t), per_node(t), int(1000 + t, i8), a)
      call csr_to_dense(a, dense)
      if (allocated(z_dense)) deallocate(z_dense)
      allocate(z_dense(sizes(t)))
      call largest_eigenpair(dense, lambda, z_dense, status)
      call check(error, status%stat, demstep_stat%ok, "dense")
      if (allocated(error)) return
      allocate(z(sizes(t)))
      call lanczos_largest(csr_apply, a, sizes(t), r, status, eigenvector=z)
      ! dsyevr's eigenvalue is backward stable: within a few n*epsilon of lambda
      ! (|A| = lambda for PSD A); 1e-10 is the tolerance asked of Lanczos
      call check_result(error, r, status, lambda, 4*sizes(t)*epsilon(1.0_dp)*lambda, 1.0e-10_dp, &
        "n = "//int_text(sizes(t)))
      if (allocated(error)) return
      ! a unit vector along the dense one (the random tops are simple): the
      ! angle is at most residual/gap, far below 1e-4 here
      call check(error, abs(norm2(z) - 1.0_dp) < 1.0e-12_dp .and. &
        abs(abs(dot_product(z, z_dense)) - 1.0_dp) < 1.0e-8_dp, "eigenvector, n = "//int_text(sizes(t)))
      if (allocated(error)) return
      deallocate(z)
    end do
  end subroutine test_random

  subroutine test_lattices(error)
    type(error_type), allocatable, intent(out) :: error
    ! dim, L, copies: multiplicity of the top = copies * 2**dim for odd L, copies for even L
    integer, parameter :: cases(3, 6) = reshape([1, 40, 1, 1, 41, 3, 2, 13, 1, 2, 13, 3, &
      3, 7, 1, 3, 8, 3], [3, 6])
    type(csr_matrix_type) :: a
    type(eigen_result_type) :: r
    type(demstep_status_type) :: status
    real(dp) :: top
    integer :: t
    character(len=:), allocatable :: label
    do t = 1, size(cases, 2)
      call periodic_lattice(cases(1, t), cases(2, t), cases(3, t), a, top)
      call lanczos_largest(csr_apply, a, a%n, r, status)
      label = int_text(cases(1, t))//"D L = "//int_text(cases(2, t))//" x "//int_text(cases(3, t))
      ! the closed form: sin in double, a few ulps
      call check_result(error, r, status, top, 4*epsilon(1.0_dp)*top, 1.0e-10_dp, label)
      if (allocated(error)) return
      ! a block of 4 wanted Ritz values
      call lanczos_largest(csr_apply, a, a%n, r, status, nev=4, ncv=20)
      call check_result(error, r, status, top, 4*epsilon(1.0_dp)*top, 1.0e-10_dp, label//", nev = 4")
      if (allocated(error)) return
      ! (a crowded top is confirmed by a second run with twice the Krylov size)
      call check(error, r%nev == 4 .and. (r%ncv == 20 .or. r%ncv == 40), label//": nev, ncv reported")
      if (allocated(error)) return
      ! (20 < n: the top confirmed by a second start)
      call check(error, r%basis == lanczos_basis_confirmed, label//": basis "//r%basis)
      if (allocated(error)) return
    end do
  end subroutine test_lattices

  subroutine test_large_lattice(error)
    type(error_type), allocatable, intent(out) :: error
    type(csr_matrix_type) :: a
    type(eigen_result_type) :: r
    type(demstep_status_type) :: status
    real(dp) :: top
    ! 47**3 = 103823 nodes, top 12 cos^2(pi/94) eight-fold, next 0.04 below
    call periodic_lattice(3, 47, 1, a, top)
    call lanczos_largest(csr_apply, a, a%n, r, status)
    call check_result(error, r, status, top, 4*epsilon(1.0_dp)*top, 1.0e-10_dp, "47^3")
    if (allocated(error)) return
    ! the benchmark tolerance
    call lanczos_largest(csr_apply, a, a%n, r, status, tolerance=1.0e-6_dp)
    call check_result(error, r, status, top, 4*epsilon(1.0_dp)*top, 1.0e-6_dp, "47^3 at 1e-6")
  end subroutine test_large_lattice

  subroutine test_not_converged(error)
    type(error_type), allocatable, intent(out) :: error
    type(csr_matrix_type) :: a
    type(eigen_result_type) :: r
    type(demstep_status_type) :: status
    real(dp) :: top
    real(dp), allocatable :: z(:)
    ! a 2D lattice: its top cluster is 1e-3 wide, one restart cannot resolve it
    call periodic_lattice(2, 60, 1, a, top)
    allocate(z(a%n))
    call lanczos_largest(csr_apply, a, a%n, r, status, eigenvector=z, max_restarts=1, ncv=8)
    call check(error, status%stat, demstep_stat%not_converged, "status")
    if (allocated(error)) return
    ! each of the lanczos_runs runs (ncv 8, 16, 16: the growth stops at twice
    ! the asked size) makes 2 passes
    call check(error, .not. r%converged .and. r%iterations == 2*lanczos_runs .and. r%ncv == 16, &
      "not converged, 2 passes a run: "//int_text(r%iterations))
    if (allocated(error)) return
    call check(error, index(status%message, "restarts") > 0 .and. index(status%message, &
      "max_restarts") > 0, "message: "//status%message)
    if (allocated(error)) return
    ! the best Ritz value is below the top, and ARPACK's residual estimate still
    ! brackets the top (a generous bar: the Ritz value is far from converged)
    call check(error, r%eigenvalue < top .and. r%eigenvalue > 0.5_dp*top, "Ritz value " &
      //real_str(r%eigenvalue))
    if (allocated(error)) return
    call check(error, top - r%eigenvalue <= r%error_bound, "bar")
    if (allocated(error)) return
    call check(error, all(z == 0.0_dp), "no vector")
    if (allocated(error)) return
    call check(error, r%basis == lanczos_basis_estimate, "basis "//r%basis)
  end subroutine test_not_converged

  subroutine odd_apply(context, x, y)
    class(lanczos_context_type), intent(inout) :: context
    real(dp), intent(in) :: x(:)
    real(dp), intent(out) :: y(:)
    integer :: i
    y = 0.0_dp
    select type (context)
    type is (odd_operator_type)
      select case (context%which)
      case (1)
        y = 2.5_dp*x
      case (2)
        y = x
        y(size(y)) = ieee_value(1.0_dp, ieee_positive_inf)
      case (3)
        ! diag(i/n): top 1, gaps 1/n
        y = [(real(i, dp), i = 1, size(x))]/size(x)*x
      case (4)
        ! diag(-5 + 6 i/n): indefinite, top 1
        y = (-5.0_dp + 6.0_dp*[(real(i, dp), i = 1, size(x))]/size(x))*x
      case (5)
        ! diag(i/n) with the last entry 2: a simple top 2, gap 1
        do i = 1, size(x) - 1
          y(i) = real(i, dp)/size(x)*x(i)
        end do
        y(size(x)) = 2.0_dp*x(size(x))
      case (6)
        ! diag(-100 + 100 i/n) with the last entry 1: a simple top 1, gap 1,
        ! 100 times as much spectrum below 0
        do i = 1, size(x) - 1
          y(i) = (-100.0_dp + 100.0_dp*real(i, dp)/size(x))*x(i)
        end do
        y(size(x)) = x(size(x))
      case (7)
        ! diag(i/n), one NaN in product bad_product
        context%products = context%products + 1
        y = [(real(i, dp), i = 1, size(x))]/size(x)*x
        if (context%products == context%bad_product) y(size(x)/2) = ieee_value(1.0_dp, ieee_quiet_nan)
      end select
    end select
  end subroutine odd_apply

  !> The certified single run (`krylov_top`, n above krylov_min_order) checks
  !> its products' finiteness on the recurrence's sums: an Inf in the first
  !> product and a NaN in the fifth (the recurrence under way, vectors kept in
  !> single precision and in full) are refused as invalid input naming the
  !> product, as the checked products of the other paths are.
  subroutine test_single_run_nonfinite(error)
    type(error_type), allocatable, intent(out) :: error
    type(odd_operator_type) :: op
    type(eigen_result_type) :: r
    type(demstep_status_type) :: status
    integer, parameter :: n = 3000
    real(dp) :: tol
    integer :: t
    op%which = 2
    call lanczos_largest(odd_apply, op, n, r, status, tolerance=1.0e-6_dp, certify=.true.)
    call check(error, status%stat == demstep_stat%invalid_input .and. index(status%message, &
      "non-finite value (product 1)") > 0, "Inf in the first product: "//status%message)
    if (allocated(error)) return
    do t = 1, 2
      ! (1e-6 keeps the vectors in single precision, 1e-8 in full)
      tol = merge(1.0e-6_dp, 1.0e-8_dp, t == 1)
      op%which = 7
      op%products = 0
      op%bad_product = 5
      call lanczos_largest(odd_apply, op, n, r, status, tolerance=tol, certify=.true.)
      call check(error, status%stat == demstep_stat%invalid_input .and. index(status%message, &
        "non-finite value (product 5)") > 0 .and. r%applications == 5, "NaN in the fifth product: " &
        //status%message)
      if (allocated(error)) return
    end do
    ! (the same operator without the NaN converges: the refusal is the NaN's)
    op%products = 0
    op%bad_product = 0
    call lanczos_largest(odd_apply, op, n, r, status, tolerance=1.0e-6_dp, certify=.true.)
    call check(error, status%stat, demstep_stat%ok, "diag(i/n) without a NaN")
  end subroutine test_single_run_nonfinite

  !> The certificate on diagonal operators of order 3000 with a crowded top
  !> (eigenvalues i/n) and an indefinite one (-5 + 6 i/n, shifted by the
  !> lower bound -5): upper_bound at or above the top 1 and at most the
  !> margin's factor above the eigenvalue found (1e-12 for rounding); made
  !> only when asked.
  subroutine test_certificate(error)
    type(error_type), allocatable, intent(out) :: error
    type(odd_operator_type) :: op
    type(eigen_result_type) :: r
    type(demstep_status_type) :: status
    integer, parameter :: n = 3000
    op%which = 3
    call lanczos_largest(odd_apply, op, n, r, status, tolerance=1.0e-6_dp)
    call check(error, status%stat == demstep_stat%ok .and. .not. r%certified .and. r%upper_bound == 0.0_dp &
      .and. r%certificate_products == 0, "no certificate unless asked")
    if (allocated(error)) return
    call lanczos_largest(odd_apply, op, n, r, status, tolerance=1.0e-6_dp, certify=.true.)
    call check(error, status%stat, demstep_stat%ok, status%message)
    if (allocated(error)) return
    call check(error, r%certified .and. r%failure_probability == certificate_failure .and. &
      r%certificate_products > 0 .and. r%certificate_products < r%applications, "certified")
    if (allocated(error)) return
    call check(error, r%upper_bound >= 1.0_dp .and. r%upper_bound <= r%eigenvalue/(1.0_dp - certificate_margin) &
      *(1.0_dp + 1.0e-12_dp), "upper bound "//real_str(r%upper_bound)//" for the top 1, found " &
      //real_str(r%eigenvalue))
    if (allocated(error)) return
    op%which = 4
    call lanczos_largest(odd_apply, op, n, r, status, tolerance=1.0e-6_dp, certify=.true., lower_bound=-5.0_dp)
    call check(error, status%stat, demstep_stat%ok, status%message)
    if (allocated(error)) return
    call check(error, r%upper_bound >= 1.0_dp .and. r%upper_bound <= (r%eigenvalue + 5.0_dp) &
      /(1.0_dp - certificate_margin)*(1.0_dp + 1.0e-12_dp) - 5.0_dp, "indefinite: upper bound " &
      //real_str(r%upper_bound)//", found "//real_str(r%eigenvalue))
  end subroutine test_certificate

  !> A certified cold run of order 2e5 with no memory for its Lanczos vectors
  !> (`store_bytes` 0: the Krylov size's fit, fewer than the certificate's
  !> steps), so none are kept: the Ritz vector comes from a second pass of
  !> the recurrence (as many products again, plus one for the residual); with
  !> the default memory they are kept (one product besides the run). The
  !> top 2 is simple with gap 1, so its eigenvector is e_n: the eigenvalue to
  !> the tolerance 1e-6 and the vector to 1e-6.
  subroutine test_second_pass(error)
    type(error_type), allocatable, intent(out) :: error
    type(odd_operator_type) :: op
    type(eigen_result_type) :: r
    type(demstep_status_type) :: status
    real(dp), allocatable :: z(:)
    integer, parameter :: n = 200000
    op%which = 5
    allocate(z(n))
    call lanczos_largest(odd_apply, op, n, r, status, eigenvector=z, tolerance=1.0e-6_dp, certify=.true., &
      store_bytes=0_i8)
    call check(error, status%stat, demstep_stat%ok, status%message)
    if (allocated(error)) return
    call check(error, r%converged .and. r%certified .and. abs(r%eigenvalue - 2.0_dp) <= 2.0e-6_dp, &
      "top "//real_str(r%eigenvalue)//" for 2")
    if (allocated(error)) return
    call check(error, r%applications == 2*r%ncv .and. r%ncv >= certificate_steps(n), &
      "a second pass: "//int_text(r%applications)//" products for "//int_text(r%ncv)//" steps")
    if (allocated(error)) return
    call check(error, abs(abs(z(n)) - 1.0_dp) <= 1.0e-6_dp, "eigenvector e_n: |z(n)| = "//real_str(abs(z(n))))
    if (allocated(error)) return
    call lanczos_largest(odd_apply, op, n, r, status, eigenvector=z, tolerance=1.0e-6_dp, certify=.true.)
    call check(error, status%stat, demstep_stat%ok, status%message)
    if (allocated(error)) return
    call check(error, r%converged .and. r%applications == r%ncv + 1 .and. abs(abs(z(n)) - 1.0_dp) <= 1.0e-6_dp, &
      "kept: "//int_text(r%applications)//" products for "//int_text(r%ncv)//" steps, |z(n)| = " &
      //real_str(abs(z(n))))
  end subroutine test_second_pass

  !> Every path of `krylov_top`'s store (module notes of demstep_lanczos), by
  !> `store_bytes` at order n = 3000 (so each kept vector is 8 n bytes, and
  !> the store holds max(ncv, store_bytes/(8 n)) vectors, twice as many in
  !> single precision), each against the run with the default store at the
  !> same tolerance, which keeps them all (j steps, j + 1 products):
  !> - double (tolerance 1e-8, below `single_basis_tolerance`): kept when j
  !>   fit (j + 1 products), not when j - 1 fit (dropped mid-run: the Ritz
  !>   vector from a second pass, 2 j products), nor when the store is below
  !>   the certificate's steps or 0 (none kept: 2 j);
  !> - single (tolerance 1e-6): kept when ceil(j/2) fit in double (twice as
  !>   many: j + 1), not with one fewer, nor below the certificate's steps
  !>   (2 j);
  !> - single's fallback: an operator with 100 times as much spectrum below
  !>   0 as its top 1 (diag(-100 + 100 i/n), last entry 1) magnifies the
  !>   single-precision rounding of the kept vectors (about 6e-8) in the
  !>   Ritz vector's residual above the tolerance 1e-6: the Ritz vector is
  !>   formed again from a second pass (2 j + 1 products; 2 j with none kept).
  !> The same run (the same j) on every path, and the same top: within the
  !> tolerance of the exact top 1 (the residual r <= tol theta bounds the
  !> distance to an eigenvalue, and these runs converge to the top), and the
  !> measured residual within the tolerance.
  subroutine test_store_paths(error)
    type(error_type), allocatable, intent(out) :: error
    type(odd_operator_type) :: op
    type(eigen_result_type) :: r
    type(demstep_status_type) :: status
    integer, parameter :: n = 3000
    integer(i8), parameter :: vector = 8_i8*n
    integer :: j, steps
    real(dp) :: tol
    steps = certificate_steps(n)
    ! double precision: diag(i/n), a crowded top 1 (its runs outlast the certificate's steps)
    op%which = 3
    tol = 1.0e-8_dp
    call solve(-1_i8)
    if (allocated(error)) return
    j = r%ncv
    call check(error, tol < single_basis_tolerance .and. j > steps .and. r%applications == j + 1, &
      "1e-8, default store: kept, "//counts())
    if (allocated(error)) return
    call expect(vector*j, j + 1, "1e-8, j fit: kept")
    if (allocated(error)) return
    call expect(vector*(j - 1), 2*j, "1e-8, j - 1 fit: dropped mid-run")
    if (allocated(error)) return
    call expect(vector*(steps - 1), 2*j, "1e-8, below the certificate's steps: none kept")
    if (allocated(error)) return
    call expect(0_i8, 2*j, "1e-8, store 0: none kept")
    if (allocated(error)) return
    ! single precision
    tol = 1.0e-6_dp
    call solve(-1_i8)
    if (allocated(error)) return
    j = r%ncv
    call check(error, tol >= single_basis_tolerance .and. j > steps .and. r%applications == j + 1, &
      "1e-6, default store: kept, "//counts())
    if (allocated(error)) return
    call expect(vector*((j + 1)/2), j + 1, "1e-6, ceil(j/2) fit in double: kept in single")
    if (allocated(error)) return
    call expect(vector*((j + 1)/2 - 1), 2*j, "1e-6, one fewer: dropped mid-run")
    if (allocated(error)) return
    call expect(vector*((steps + 1)/2 - 1), 2*j, "1e-6, below the certificate's steps in single: none kept")
    if (allocated(error)) return
    ! single precision's fallback
    op%which = 6
    call solve(-1_i8)
    if (allocated(error)) return
    j = r%ncv
    call check(error, r%applications == 2*j + 1, "wide spectrum, 1e-6, default store: single kept, then the " &
      //"second pass, "//counts())
    if (allocated(error)) return
    call expect(0_i8, 2*j, "wide spectrum, 1e-6, store 0: none kept")
  contains
    !> The certified cold solve at tol with store_bytes (< 0: the default).
    subroutine solve(store)
      integer(i8), intent(in) :: store
      if (store < 0) then
        call lanczos_largest(odd_apply, op, n, r, status, tolerance=tol, certify=.true., lower_bound=-100.0_dp)
      else
        call lanczos_largest(odd_apply, op, n, r, status, tolerance=tol, certify=.true., lower_bound=-100.0_dp, &
          store_bytes=store)
      end if
      call check(error, status%stat, demstep_stat%ok, status%message)
      if (allocated(error)) return
      call check(error, r%converged .and. r%certified .and. abs(r%eigenvalue - 1.0_dp) <= tol .and. &
        r%residual <= tol*r%eigenvalue, "the top 1 to "//real_str(tol)//": "//real_str(r%eigenvalue) &
        //", residual "//real_str(r%residual)//", "//counts())
    end subroutine solve
    !> The run with store_bytes `store`: the same steps j, `products` products.
    subroutine expect(store, products, label)
      integer(i8), intent(in) :: store
      integer, intent(in) :: products
      character(len=*), intent(in) :: label
      call solve(store)
      if (allocated(error)) then
        error%message = label//": "//error%message
        return
      end if
      call check(error, r%ncv == j .and. r%applications == products, label//": "//counts() &
        //", expected "//int_text(products)//" for "//int_text(j)//" steps")
    end subroutine expect
    function counts() result(text)
      character(len=:), allocatable :: text
      text = int_text(r%applications)//" products for "//int_text(r%ncv)//" steps"
    end function counts
  end subroutine test_store_paths

  subroutine test_arguments(error)
    type(error_type), allocatable, intent(out) :: error
    type(odd_operator_type) :: op
    type(eigen_result_type) :: r
    type(demstep_status_type) :: status
    real(dp) :: z1(1), z3(3)
    call lanczos_largest(odd_apply, op, 0, r, status)
    call check(error, status%stat == demstep_stat%invalid_input .and. index(status%message, "n:") > 0, &
      "n = 0")
    if (allocated(error)) return
    call lanczos_largest(odd_apply, op, 3, r, status, eigenvector=z1)
    call check(error, status%stat == demstep_stat%invalid_input .and. &
      index(status%message, "eigenvector") > 0, "eigenvector size")
    if (allocated(error)) return
    call lanczos_largest(odd_apply, op, 3, r, status, tolerance=0.0_dp)
    call check(error, status%stat == demstep_stat%invalid_input .and. &
      index(status%message, "tolerance") > 0, "tolerance 0")
    if (allocated(error)) return
    call lanczos_largest(odd_apply, op, 3, r, status, tolerance=ieee_value(1.0_dp, ieee_positive_inf))
    call check(error, status%stat, demstep_stat%invalid_input, "tolerance Inf")
    if (allocated(error)) return
    call lanczos_largest(odd_apply, op, 30, r, status, ncv=1)
    call check(error, status%stat == demstep_stat%invalid_input .and. index(status%message, "ncv") > 0, &
      "ncv = nev")
    if (allocated(error)) return
    call lanczos_largest(odd_apply, op, 30, r, status, nev=0)
    call check(error, status%stat == demstep_stat%invalid_input .and. index(status%message, "nev") > 0, &
      "nev = 0")
    if (allocated(error)) return
    call lanczos_largest(odd_apply, op, 30, r, status, max_restarts=0)
    call check(error, status%stat == demstep_stat%invalid_input .and. &
      index(status%message, "max_restarts") > 0, "max_restarts = 0")
    if (allocated(error)) return
    ! n = 1: the operator's single entry
    op%which = 1
    call lanczos_largest(odd_apply, op, 1, r, status, eigenvector=z1)
    call check(error, status%stat == demstep_stat%ok .and. r%eigenvalue == 2.5_dp .and. z1(1) == 1.0_dp &
      .and. r%converged, "n = 1")
    if (allocated(error)) return
    ! n = 3 < the default Krylov size: the whole space
    call lanczos_largest(odd_apply, op, 3, r, status, eigenvector=z3)
    call check(error, status%stat, demstep_stat%ok, "n = 3")
    if (allocated(error)) return
    call check(error, r%eigenvalue, 2.5_dp, thr=1.0e-14_dp, rel=.true., message="n = 3, 2.5 I")
    if (allocated(error)) return
    call check(error, r%basis == lanczos_basis_whole, "n = 3: basis "//r%basis)
    if (allocated(error)) return
    call check(error, r%ncv == 3 .and. r%nev == 1, "ncv capped at n")
    if (allocated(error)) return
    ! the zero operator: eigenvalue 0
    op%which = 0
    call lanczos_largest(odd_apply, op, 50, r, status)
    call check(error, status%stat == demstep_stat%ok .and. r%eigenvalue == 0.0_dp, "zero operator: " &
      //real_str(r%eigenvalue)//" status "//int_text(status%stat))
    if (allocated(error)) return
    ! an operator that overflows
    op%which = 2
    call lanczos_largest(odd_apply, op, 50, r, status)
    call check(error, status%stat == demstep_stat%invalid_input .and. &
      index(status%message, "non-finite") > 0, "Inf from the operator")
  end subroutine test_arguments

  subroutine test_arpack_codes(error)
    type(error_type), allocatable, intent(out) :: error
    integer, parameter :: saupd_codes(19) = [1, 2, 3, -1, -2, -3, -4, -5, -6, -7, -8, -9, &
      -10, -11, -12, -13, -9999, 0, 0]
    integer, parameter :: seupd_codes(15) = [-1, -2, -3, -5, -6, -7, -8, -9, -10, -11, -12, &
      -14, -15, -16, -17]
    type(demstep_status_type) :: s
    integer :: i, j
    character(len=64) :: seen(size(saupd_codes))
    ! every documented code: a failure status with its own message
    do i = 1, size(saupd_codes) - 2
      s = dsaupd_status(saupd_codes(i))
      call check(error, s%stat /= demstep_stat%ok .and. allocated(s%message), "dsaupd "//int_text(saupd_codes(i)))
      if (allocated(error)) return
      call check(error, index(s%message, "ARPACK dsaupd: ") == 1 .and. index(s%message, "undocumented") == 0, &
        "dsaupd message "//s%message)
      if (allocated(error)) return
      seen(i) = s%message
      do j = 1, i - 1
        if (seen(j) == seen(i)) then
          call test_failed(error, "dsaupd message repeated: "//s%message)
          return
        end if
      end do
    end do
    do i = 1, size(seupd_codes)
      s = dseupd_status(seupd_codes(i))
      call check(error, s%stat /= demstep_stat%ok .and. index(s%message, "ARPACK dseupd: ") == 1 &
        .and. index(s%message, "undocumented") == 0, "dseupd "//int_text(seupd_codes(i)))
      if (allocated(error)) return
    end do
    ! the meanings: not converged, bad argument, LAPACK inside, ARPACK itself
    call check(error, saupd_stat(0) == demstep_stat%ok .and. seupd_stat(0) == demstep_stat%ok &
      .and. saupd_stat(1) == demstep_stat%not_converged &
      .and. saupd_stat(3) == demstep_stat%not_converged &
      .and. saupd_stat(-3) == demstep_stat%invalid_input &
      .and. saupd_stat(-8) == demstep_stat%lapack_failure &
      .and. saupd_stat(-9999) == demstep_stat%eigensolver_failure &
      .and. seupd_stat(-14) == demstep_stat%not_converged &
      .and. seupd_stat(-17) == demstep_stat%eigensolver_failure, "meanings")
    if (allocated(error)) return
    s = dsaupd_status(-77)
    call check(error, s%stat == demstep_stat%eigensolver_failure .and. index(s%message, "-77") > 0, &
      "an undocumented code")
    if (allocated(error)) return
    ! provoked: ARPACK's own checks on its first call
    call check(error, first_call_info(n=0), -1, "n = 0")
    if (allocated(error)) return
    call check(error, first_call_info(nev=0), -2, "nev = 0")
    if (allocated(error)) return
    call check(error, first_call_info(ncv=1), -3, "ncv = nev")
    if (allocated(error)) return
    call check(error, first_call_info(ncv=11), -3, "ncv > n")
    if (allocated(error)) return
    call check(error, first_call_info(mxiter=0), -4, "mxiter = 0")
    if (allocated(error)) return
    call check(error, first_call_info(short_workl=.true.), -7, "short workl")
    if (allocated(error)) return
    call check(error, first_call_info(zero_start=.true.), -9, "zero start vector")
  end subroutine test_arpack_codes

  integer function saupd_stat(info)
    integer, intent(in) :: info
    type(demstep_status_type) :: s
    s = dsaupd_status(info)
    saupd_stat = s%stat
  end function saupd_stat

  integer function seupd_stat(info)
    integer, intent(in) :: info
    type(demstep_status_type) :: s
    s = dseupd_status(info)
    seupd_stat = s%stat
  end function seupd_stat

  !> dsaupd's info after its first call, on 10-by-10 2I with one argument spoiled;
  !> the reverse communication is served (y = 2 x) until ARPACK stops.
  integer function first_call_info(n, nev, ncv, mxiter, short_workl, zero_start) result(info)
    integer, intent(in), optional :: n, nev, ncv, mxiter
    logical, intent(in), optional :: short_workl, zero_start
    integer :: nn, k, m, ido, lworkl, iparam(11), ipntr(11), calls
    real(dp) :: tol, v(10, 12), workd(30), workl(12*20), resid(10)
    nn = 10
    if (present(n)) nn = n
    k = 1
    if (present(nev)) k = nev
    m = 4
    if (present(ncv)) m = ncv
    lworkl = size(workl)
    if (present(short_workl)) lworkl = m*m
    call lanczos_start_vector(resid)
    if (present(zero_start)) resid = 0.0_dp
    iparam = 0
    iparam(1) = 1
    iparam(3) = 100
    if (present(mxiter)) iparam(3) = mxiter
    iparam(7) = 1
    ido = 0
    info = 1
    tol = 1.0e-10_dp
    calls = 0
    do
      call dsaupd(ido, "I", nn, "LA", k, tol, resid, m, v, 10, iparam, ipntr, workd, workl, &
        lworkl, info)
      if (ido /= -1 .and. ido /= 1) exit
      calls = calls + 1
      if (calls > 1000) exit
      workd(ipntr(2):ipntr(2) + 9) = 2.0_dp*workd(ipntr(1):ipntr(1) + 9)
    end do
  end function first_call_info

  subroutine test_csr(error)
    type(error_type), allocatable, intent(out) :: error
    type(csr_matrix_type) :: a
    type(demstep_status_type) :: status
    real(dp), allocatable :: dense(:, :)
    real(dp) :: x(3), y(3)
    ! springs 1-2 (k = 2), 2-3 (k = 3), 1-3 (k = 5), node 2 grounded (1), masses 1, 4, 1
    call csr_from_springs(3, [1, 2, 1], [2, 3, 3], [2.0_dp, 3.0_dp, 5.0_dp], a, status, &
      ground=[0.0_dp, 1.0_dp, 0.0_dp], mass=[1.0_dp, 4.0_dp, 1.0_dp])
    call check(error, status%stat, demstep_stat%ok, "build")
    if (allocated(error)) return
    call csr_to_dense(a, dense)
    call check(error, all(abs(dense - reshape([7.0_dp, -1.0_dp, -5.0_dp, -1.0_dp, 1.5_dp, -1.5_dp, &
      -5.0_dp, -1.5_dp, 8.0_dp], [3, 3])) < 1.0e-15_dp), "dense matrix")
    if (allocated(error)) return
    x = [1.0_dp, 2.0_dp, -1.0_dp]
    call csr_apply(a, x, y)
    call check(error, all(abs(y - matmul(dense, x)) < 1.0e-14_dp), "product")
    if (allocated(error)) return
    call csr_from_springs(3, [1, 2], [2, 2], [1.0_dp, 1.0_dp], a, status)
    call check(error, status%stat == demstep_stat%invalid_input .and. index(status%message, "first") > 0, &
      "self spring")
    if (allocated(error)) return
    call csr_from_springs(3, [1, 2], [2, 4], [1.0_dp, 1.0_dp], a, status)
    call check(error, status%stat, demstep_stat%invalid_input, "node 4 of 3")
    if (allocated(error)) return
    call csr_from_springs(3, [1, 2], [2, 3], [1.0_dp, -1.0_dp], a, status)
    call check(error, status%stat == demstep_stat%invalid_input .and. index(status%message, "stiffness") > 0, &
      "negative stiffness")
    if (allocated(error)) return
    call csr_from_springs(3, [1, 2], [2, 3], [1.0_dp, 1.0_dp], a, status, mass=[1.0_dp, 0.0_dp, 1.0_dp])
    call check(error, status%stat == demstep_stat%invalid_input .and. index(status%message, "mass") > 0, &
      "zero mass")
    if (allocated(error)) return
    call csr_from_springs(3, [1, 2], [2, 3], [1.0_dp, 1.0_dp], a, status, ground=[1.0_dp, 1.0_dp])
    call check(error, status%stat == demstep_stat%invalid_input .and. index(status%message, "ground") > 0, &
      "ground size")
  end subroutine test_csr

  subroutine test_threads(error)
    type(error_type), allocatable, intent(out) :: error
    type(csr_matrix_type) :: a
    type(eigen_result_type) :: r1, r2, r3
    type(demstep_status_type) :: status
    real(dp), allocatable :: z1(:), z2(:), z3(:)
    integer :: threads
    call random_network(20000, 4, 77_i8, a)
    allocate(z1(a%n), z2(a%n), z3(a%n))
    threads = 1
    !$ threads = omp_get_max_threads()
    !$ call omp_set_num_threads(1)
    call lanczos_largest(csr_apply, a, a%n, r1, status, eigenvector=z1)
    call check(error, status%stat, demstep_stat%ok, "1 thread")
    if (allocated(error)) return
    !$ call omp_set_num_threads(2)
    call lanczos_largest(csr_apply, a, a%n, r2, status, eigenvector=z2)
    call check(error, status%stat, demstep_stat%ok, "2 threads")
    if (allocated(error)) return
    !$ call omp_set_num_threads(threads)
    call lanczos_largest(csr_apply, a, a%n, r3, status, eigenvector=z3)
    ! the CSR product sums each row in one order whatever the threads, and the
    ! start vector is fixed: the same bits (ARPACK's BLAS keeps its own threads)
    call check(error, r1%eigenvalue == r2%eigenvalue .and. r1%eigenvalue == r3%eigenvalue &
      .and. r1%applications == r2%applications .and. all(z1 == z2) .and. all(z1 == z3), &
      "thread count or a rerun changed the result: "//real_str(r1%eigenvalue)//" "// &
      real_str(r2%eigenvalue)//" "//real_str(r3%eigenvalue))
    if (allocated(error)) return
    call check(error, r1%tolerance == lanczos_tolerance_default, "default tolerance")
  end subroutine test_threads

  !> The certified cold solve at order n = 2e5 (above `recurrence_block`, so
  !> the recurrence sums run in blocks, and the Lanczos vectors' copies, the
  !> finiteness check and the single-precision store and Ritz sum run in
  !> parallel) with 1 and with 2 threads: the same bits (eigenvalue, upper
  !> bound, Ritz vector, products, steps) on each path of the store:
  !> tolerance 1e-8 (double) and 1e-6 (single), each kept (store_bytes for
  !> 128 double columns, so the run's j > 64 steps, at least
  !> `certificate_steps`(2e5) = 80, fill two 64-column blocks: j + 1
  !> products) and not kept (store_bytes 0: the second pass, 2 j products).
  !> The operator is a free chain of unit springs and unit masses, one node
  !> of mass 1/4 in the middle: a simple top (a mode bound to the light node,
  !> measured 9.142857 = 64/7) well above the band's top 4, met within the
  !> tolerance in j = 80 steps on every path (measured).
  subroutine test_threads_blocked(error)
    type(error_type), allocatable, intent(out) :: error
    integer, parameter :: n = 200000
    type(csr_matrix_type) :: a
    type(eigen_result_type) :: r1, r2
    type(demstep_status_type) :: status
    real(dp), allocatable :: z1(:), z2(:), mass(:)
    integer :: threads, i, path
    real(dp) :: tol
    integer(i8) :: store
    logical :: kept
    character(len=:), allocatable :: label
    mass = [(1.0_dp, i = 1, n)]
    mass(n/2) = 0.25_dp
    call csr_from_springs(n, [(i, i = 1, n - 1)], [(i + 1, i = 1, n - 1)], [(1.0_dp, i = 1, n - 1)], a, status, &
      mass=mass)
    call check(error, status%stat, demstep_stat%ok, "chain")
    if (allocated(error)) return
    allocate(z1(n), z2(n))
    threads = 1
    !$ threads = omp_get_max_threads()
    do path = 1, 4
      tol = merge(1.0e-8_dp, 1.0e-6_dp, path <= 2)
      kept = mod(path, 2) == 1
      store = merge(8_i8*n*128_i8, 0_i8, kept)
      label = "tolerance "//real_str(tol)//merge(", kept    ", ", not kept", kept)//": "
      !$ call omp_set_num_threads(1)
      call lanczos_largest(csr_apply, a, n, r1, status, eigenvector=z1, tolerance=tol, certify=.true., &
        store_bytes=store)
      call check(error, status%stat, demstep_stat%ok, label//"1 thread: "//status%message)
      if (allocated(error)) exit
      !$ call omp_set_num_threads(2)
      call lanczos_largest(csr_apply, a, n, r2, status, eigenvector=z2, tolerance=tol, certify=.true., &
        store_bytes=store)
      call check(error, status%stat, demstep_stat%ok, label//"2 threads: "//status%message)
      if (allocated(error)) exit
      ! the path: converged and certified, more than one block of steps, kept or not
      call check(error, r1%converged .and. r1%certified .and. r1%ncv > 64 .and. r1%ncv <= 128 .and. &
        r1%applications == merge(r1%ncv + 1, 2*r1%ncv, kept), label//int_text(r1%applications) &
        //" products for "//int_text(r1%ncv)//" steps")
      if (allocated(error)) exit
      call check(error, r1%eigenvalue == r2%eigenvalue .and. r1%upper_bound == r2%upper_bound .and. &
        r1%applications == r2%applications .and. r1%ncv == r2%ncv .and. all(z1 == z2), &
        label//"1 and 2 threads differ: "//real_str(r1%eigenvalue)//" "//real_str(r2%eigenvalue)//", " &
        //int_text(r1%applications)//" "//int_text(r2%applications)//" products, " &
        //int_text(count(z1 /= z2))//" vector entries")
      if (allocated(error)) exit
    end do
    !$ call omp_set_num_threads(threads)
  end subroutine test_threads_blocked

  subroutine test_progress(error)
    type(error_type), allocatable, intent(out) :: error
    type(csr_matrix_type) :: a
    type(eigen_result_type) :: r
    type(demstep_status_type) :: status
    type(count_progress_type) :: p
    real(dp) :: top
    call periodic_lattice(2, 20, 1, a, top)
    call lanczos_largest(csr_apply, a, a%n, r, status, progress=p)
    call check(error, status%stat, demstep_stat%ok, "status")
    if (allocated(error)) return
    ! every product is reported, the final residual check included (as the
    ! distributed solve, which shares the driver)
    call check(error, p%starts == 1 .and. p%finishes == 1 .and. p%updates == r%applications &
      .and. p%last == r%applications .and. p%total == 0, "calls: "//int_text(p%starts)//" " &
      //int_text(p%updates)//" "//int_text(p%finishes)//" of "//int_text(r%applications))
  end subroutine test_progress

end module test_lanczos
