!> The largest eigenvalue (and its vector) of a large symmetric positive
!> semi-definite operator, matrix-free, by the implicitly restarted Lanczos
!> iteration of ARPACK (`dsaupd`/`dseupd`, mode 1, `which = 'LA'`): one
!> driver (`lanczos_solve`) for the serial and the distributed solve.
!>
!> The driver sees the problem through `lanczos_space_type`: the product
!> y = A x on this process's block of the vectors, the global inner product,
!> a global "and", and ARPACK's call pair with its statuses. `lanczos_largest`
!> is the serial solve (ARPACK, a `lanczos_operator` with its context: extend
!> `lanczos_context_type` with the data the product needs and recover it with
!> `select type`); the MPI package extends the space with PARPACK and a
!> row-partitioned matrix. The product may run in parallel (OpenMP inside the
!> callback); the driver starts from a fixed pseudo-random vector (never
!> ARPACK's own random one), so a result depends on the thread or rank count
!> only through the rounding of the products and sums.
!>
!> Tolerance and error bar. The tolerance is the relative accuracy asked of the
!> largest eigenvalue lambda_max = omega_max^2 (a time step 2/omega_max is then
!> good to half of it). ARPACK stops when the Ritz estimate of the wanted
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
!> The stopping rule is a test on the eigenvalue: a run is accepted when the
!> bracket [theta, theta + r] is at most `tolerance * theta` wide and a second
!> run from new random components does not raise theta by more than
!> `tolerance * theta` (the top found to the tolerance; see `iterate`), or,
!> for a cold certified solve, when the single unrestarted run from the
!> certificate's random start meets it (`krylov_top`, below).
!>
!> Certificate (`certify`). The bracket says where *an* eigenvalue lies, not
!> that none lies above it (an eigenvector missing from the starts). With
!> `certify`, a Lanczos run of j products from a Gaussian (so uniformly
!> distributed on the unit sphere) start b gives the largest Ritz value xi of
!> its tridiagonal matrix T_j, the largest Rayleigh quotient over the Krylov
!> space {p(A) b: degree p <= d = j - 1}, and
!> `upper_bound` = max(theta, xi)/(1 - eps) bounds lambda_max except with
!> probability at most `certificate_failure` (eps = `certificate_margin`; an
!> operator that is not semi-definite is shifted by a lower bound of its
!> spectrum). The bound used is proved here (`certificate_steps`), not
!> quoted: for A >= 0 with eigenpairs (lambda_i, x_i), lambda_1 the largest,
!> mu = (1 - eps) lambda_1 and p(x) = T_d(2x/mu - 1) (Chebyshev), |p| <= 1 on
!> [0, mu] and p(lambda_1) = T_d((1 + eps)/(1 - eps)) = cosh(d t) with
!> t = ln((1 + sqrt eps)/(1 - sqrt eps)), so u = p(A) b, c_i = x_i.b, has
!> u.Au - mu u.u = sum c_i^2 p(lambda_i)^2 (lambda_i - mu)
!>              >= lambda_1 (eps c_1^2 cosh(d t)^2 - (1 - eps)),
!> and xi >= mu unless c_1^2 < (1 - eps)/(eps cosh(d t)^2). For b uniform on
!> the sphere c_1 has the density (1 - u^2)^((n-3)/2)/B(1/2, (n-1)/2), at most
!> Gamma(n/2)/(sqrt(pi) Gamma((n-1)/2)) <= sqrt((n-1)/(2 pi)) (Wendel's
!> inequality), so (n >= 3; for n <= 2 the Krylov space is the whole space)
!>   P(xi < (1 - eps) lambda_max) <= sqrt(2 n (1 - eps)/(pi eps))/cosh(d t).
!> It has the rate of Kuczynski and Wozniakowski's bound for Lanczos from a
!> random start (SIAM J. Matrix Anal. Appl. 13(4), 1094-1122, 1992; its
!> abstract, Columbia Academic Commons doi:10.7916/D8B56SVV, gives the
!> failure probability as at most of the order sqrt(n) e^(-(2k - 1) sqrt eps);
!> t >= 2 sqrt(eps)); their constant was not checked against the paper, so
!> this explicit one is used. What it rests on besides: exact arithmetic (the
!> run is the three-term recurrence without reorthogonalisation; its largest
!> Ritz value is taken to converge no slower in floating point, as Paige's and
!> Greenbaum's analyses describe) and a random start (a fixed pseudo-random
!> sequence, the same for every run: the probability is over that draw, for
!> operators not chosen in view of it).
!>
!> One run for both (`krylov_top`). A cold certified solve of an operator
!> larger than `krylov_min_order` makes a single run: the certificate's
!> Gaussian start, the plain three-term recurrence (no restarts, no
!> reorthogonalisation: a product and two dot products a step), at least
!> `certificate_steps` products, on until the top Ritz pair's estimate
!> beta_j |s_j| meets the tolerance; then its Ritz vector is formed (from the
!> Lanczos vectors kept while they fit in `lanczos_store_bytes`, or else by
!> running the recurrence again from the same start, the same bits; none are
!> kept when the certificate's products do not fit), and its
!> Rayleigh quotient and residual are measured as above. A crowded top is
!> what an unrestarted Krylov space from a random start resolves best: the
!> top's component is never filtered out by a restart (ARPACK's restarts
!> with one wanted value did that on tilings), so no second start is run
!> (basis `lanczos_basis_random`). A warm start to be confirmed (the damped
!> limit's Newton solves, from the previous mode) likewise makes one run,
!> from its vector plus the random one (what the ARPACK path's confirmation
!> run starts from), without a certificate of its own; one not to be
!> confirmed (a monitor's previous mode refined) makes one run from its
!> vector alone (basis `lanczos_basis_warm`).
!>
!> ARPACK keeps its state in SAVEd variables: one solve at a time per process.
!> A solve started while another runs (another thread) is refused with status
!> `busy` (`arpack_claim`); it never shares the state.
module demstep_lanczos
  use demstep_kinds, only: dp, sp, i8, pi
  use demstep_lapack, only: largest_tridiagonal_eigenvalue, largest_tridiagonal_eigenpair
  use demstep_status, only: demstep_status_type, demstep_stat, set_status
  use demstep_arpack, only: dsaupd, dseupd, dsaupd_status, dseupd_status, arpack_iparam_size
  use demstep_progress, only: progress_type
  use demstep_text, only: int_text, real_text
  use demstep_double_double, only: dot_parts, two_sum
  use, intrinsic :: ieee_arithmetic, only: ieee_is_finite
  implicit none
  private

  public :: lanczos_operator, lanczos_largest, lanczos_solve, lanczos_start_vector, &
    check_lanczos_options, lanczos_options, accurate_dot_parts, certificate_steps
  public :: arpack_claim, arpack_release

  !> Default relative tolerance on the largest eigenvalue omega_max^2: 1e-6, so
  !> the time step 2/omega_max is good to 5e-7, far below what a DEM step needs
  !> (stiffnesses are known to a few per cent; steps are taken at a fraction of
  !> the limit). A tighter one (1e-10) does not converge on crowded tops (a
  !> tiling of 1e5 particles: out of restarts after 1763 products), where 1e-6
  !> takes under a hundred products.
  real(dp), parameter, public :: lanczos_tolerance_default = 1.0e-6_dp
  !> The certificate's failure probability and relative margin eps (see the
  !> module notes): `upper_bound` exceeds the found top by the factor
  !> 1/(1 - eps) (a step 1 % below the estimate) and fails to bound
  !> lambda_max with probability at most 1e-6.
  real(dp), parameter, public :: certificate_failure = 1.0e-6_dp, certificate_margin = 2.0e-2_dp
  !> A cold certified solve of an operator of larger order is one unrestarted
  !> run from the certificate's start (`krylov_top`); smaller ones (where the
  !> Krylov space soon is the whole space) run ARPACK and the certificate.
  integer, parameter, public :: krylov_min_order = 1000
  !> Memory (bytes, counted at the global order: all processes together,
  !> each holding its share) for the Lanczos vectors of `krylov_top`
  !> (at least the Krylov size asked, ncv, are kept as ARPACK would): beyond
  !> it the Ritz vector is formed by running the recurrence again, which
  !> doubles the products, and none are kept when the certificate's products
  !> alone would not fit. 3 GiB keeps 134 vectors in single precision
  !> (`single_basis_tolerance`) at 6e6 degrees of freedom: the 1e6-particle
  !> tiled packing of `bench_scene_eigen` (rotations) took 132 steps.
  integer(i8), parameter, public :: lanczos_store_bytes = 3_i8*2_i8**30
  !> At tolerances this loose or looser `krylov_top` keeps its Lanczos
  !> vectors rounded to single precision, twice as many in the same memory:
  !> the Ritz vector formed from them is off by about 6e-8 of its length (the
  !> rounding, weighted by the Ritz coefficients), which moves its measured
  !> residual by about 1e-7 of the top eigenvalue, a tenth of this tolerance;
  !> should the measured residual miss the tolerance, the Ritz vector is
  !> formed again in full from a second run of the recurrence.
  real(dp), parameter, public :: single_basis_tolerance = 1.0e-6_dp
  !> `krylov_top` keeps its Lanczos vectors in blocks of this many columns,
  !> each allocated when the run reaches it: a run that stops soon touches no
  !> more memory than it uses (and, for blocks below the C library's mmap
  !> threshold, as in a monitor's small solves, the next run's allocations
  !> reuse them instead of mapping pages afresh).
  integer, parameter :: basis_block = 64

  !> One block of `krylov_top`'s kept Lanczos vectors (single or double precision).
  type :: basis_block_type
    real(sp), allocatable :: single(:, :)
    real(dp), allocatable :: full(:, :)
  end type basis_block_type
  !> Default Krylov size (Lanczos vectors kept between restarts), capped at n.
  integer, parameter, public :: lanczos_ncv_default = 24
  !> Default number of wanted Ritz values kept at each restart (a block of the
  !> top of the spectrum: resolves near-degenerate top eigenvalues).
  integer, parameter, public :: lanczos_nev_default = 1
  !> Default maximum number of implicit restarts.
  integer, parameter, public :: lanczos_restarts_default = 1000
  !> The solver's name in a result.
  character(len=*), parameter, public :: lanczos_solver_name = "lanczos (ARPACK dsaupd)"

  !> ARPACK runs of one solve at most (a first, its confirmation, one more when
  !> the top rose or the restarts ran out), and how far the Krylov size may
  !> grow (a multiple of the asked ncv) when the restarts run out.
  integer, parameter, public :: lanczos_runs = 3, lanczos_ncv_growth = 2
  !> Entries per block of the serial space's recurrence sums: each block is
  !> summed in index order, then the blocks' sums in block order, so the sum
  !> has the same bits for every thread count (and is one plain sum for a
  !> vector of one block); the blocks run in parallel under OpenMP.
  integer, parameter :: recurrence_block = 65536

  !> Rounding allowance of the error bar, in units of epsilon * |theta|: the
  !> residual and the Rayleigh quotient are sums of rounded products.
  real(dp), parameter, public :: rounding_ulps = 8.0_dp

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

  !> What the Lanczos driver needs of a problem, serial or distributed: every
  !> vector is this process's block (rows first_row .. first_row + n_local - 1
  !> of n_global). Each procedure is collective where the space is distributed.
  type, abstract, public :: lanczos_space_type
    !> Global order, entries held here, global index of the first of them.
    integer :: n_global = 0, n_local = 0, first_row = 1
    !> The public routine that runs the solve, for messages.
    character(len=:), allocatable :: caller
    !> The solver's name in the result.
    character(len=:), allocatable :: solver
    !> Memory (bytes, at the global order) for the Lanczos vectors `krylov_top` keeps.
    integer(i8) :: store_bytes = lanczos_store_bytes
  contains
    !> y = A x on this block.
    procedure(space_product), deferred :: product
    !> x.y over the whole vector, as accurate as a sum in twice the precision.
    procedure(space_dot), deferred :: dot
    !> x.y for the recurrence's coefficients (`krylov_top`), where an
    !> ordinary sum's rounding is the recurrence's own: `dot` unless a space
    !> has a cheaper one (the serial space's plain sum).
    procedure :: recurrence_dot => space_recurrence_dot
    !> w = w - c u, then `recurrence_dot` of x (absent: w) and the new w, in
    !> one pass over the vectors where a space can (the serial one).
    procedure :: recurrence_update => space_recurrence_update
    !> True when the condition holds on every process.
    procedure(space_all), deferred :: all_ranks
    !> One reverse-communication step of the (P)ARPACK iteration.
    procedure(space_saupd), deferred :: saupd
    !> The (P)ARPACK post-processing: Ritz values and vectors.
    procedure(space_seupd), deferred :: seupd
    !> The statuses of saupd's and seupd's `info`.
    procedure(space_info_status), deferred :: saupd_status, seupd_status
  end type lanczos_space_type

  abstract interface
    subroutine space_product(space, x, y)
      import :: dp, lanczos_space_type
      class(lanczos_space_type), intent(inout) :: space
      real(dp), intent(in) :: x(:)
      real(dp), intent(out) :: y(:)
    end subroutine space_product
    function space_dot(space, x, y) result(s)
      import :: dp, lanczos_space_type
      class(lanczos_space_type), intent(inout) :: space
      real(dp), intent(in) :: x(:), y(:)
      real(dp) :: s
    end function space_dot
    function space_all(space, condition) result(held)
      import :: lanczos_space_type
      class(lanczos_space_type), intent(inout) :: space
      logical, intent(in) :: condition
      logical :: held
    end function space_all
    !> dsaupd's arguments with bmat = 'I', which = 'LA', n = ldv = n_local.
    subroutine space_saupd(space, ido, nev, tol, resid, ncv, v, iparam, ipntr, workd, workl, info)
      import :: dp, lanczos_space_type
      class(lanczos_space_type), intent(inout) :: space
      integer, intent(inout) :: ido
      integer, intent(in) :: nev, ncv
      real(dp), intent(inout) :: tol
      real(dp), intent(inout) :: resid(:), v(:, :), workd(:), workl(:)
      integer, intent(inout) :: iparam(:), ipntr(:), info
    end subroutine space_saupd
    !> dseupd's arguments with howmny = 'A', sigma = 0 and saupd's settings.
    subroutine space_seupd(space, rvec, select, d, z, nev, tol, resid, ncv, v, iparam, ipntr, &
        workd, workl, info)
      import :: dp, lanczos_space_type
      class(lanczos_space_type), intent(inout) :: space
      logical, intent(in) :: rvec
      logical, intent(inout) :: select(:)
      real(dp), intent(out) :: d(:)
      real(dp), intent(inout) :: z(:, :)
      integer, intent(in) :: nev, ncv
      real(dp), intent(in) :: tol
      real(dp), intent(inout) :: resid(:), v(:, :), workd(:), workl(:)
      integer, intent(inout) :: iparam(:), ipntr(:)
      integer, intent(out) :: info
    end subroutine space_seupd
    pure function space_info_status(space, info) result(status)
      import :: lanczos_space_type, demstep_status_type
      class(lanczos_space_type), intent(in) :: space
      integer, intent(in) :: info
      type(demstep_status_type) :: status
    end function space_info_status
  end interface

  !> The serial space: ARPACK and a `lanczos_operator` with its context.
  type, extends(lanczos_space_type) :: serial_space_type
    procedure(lanczos_operator), pointer, nopass :: apply => null()
    class(lanczos_context_type), pointer :: context => null()
  contains
    procedure :: product => serial_product
    procedure :: dot => serial_dot
    procedure :: recurrence_dot => serial_recurrence_dot
    procedure :: recurrence_update => serial_recurrence_update
    procedure :: all_ranks => serial_all
    procedure :: saupd => serial_saupd
    procedure :: seupd => serial_seupd
    procedure :: saupd_status => serial_saupd_status
    procedure :: seupd_status => serial_seupd_status
  end type serial_space_type

  !> The values of `eigen_result_type%basis`.
  character(len=*), parameter, public :: lanczos_basis_whole = "whole space", &
    lanczos_basis_confirmed = "confirmed by a second start", lanczos_basis_estimate = "estimate", &
    lanczos_basis_warm = "a warm start, not confirmed", &
    lanczos_basis_random = "one unrestarted run from a random start", &
    lanczos_basis_warm_random = "one unrestarted run from a warm start plus a random one"

  !> What one ARPACK run found (see `arpack_run`).
  type :: run_type
    !> A Ritz pair met the tolerance (theta and rnorm then measured on its vector).
    logical :: converged = .false.
    !> The start vector was in A's null space: the zero operator.
    logical :: zero = .false.
    !> The top Ritz value (or Rayleigh quotient) and its residual (or ARPACK's
    !> estimate).
    real(dp) :: theta = 0.0_dp, rnorm = 0.0_dp
    !> ARPACK's status (ok or not_converged).
    type(demstep_status_type) :: step_status
  end type run_type

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
    !> Krylov size and number of wanted Ritz values used (the last run's).
    integer :: ncv = 0, nev = 0
    !> What the claim that `eigenvalue` is the top (within the tolerance)
    !> rests on: `lanczos_basis_whole` (the Krylov space was the whole space),
    !> `lanczos_basis_random` (one unrestarted run from the certificate's
    !> random start met the tolerance, `krylov_top`), `lanczos_basis_warm_random`
    !> (the same from a warm start's vector plus a random one),
    !> `lanczos_basis_confirmed` (a second run from a fresh random start did
    !> not raise it), `lanczos_basis_warm` (a warm start's first converged run,
    !> asked for without confirmation), or `lanczos_basis_estimate` (none: not converged or
    !> not settled). None of them excludes an eigenvalue whose eigenvector is
    !> missing from both starts; no inertia or probabilistic bound is made.
    character(len=:), allocatable :: basis
    !> Which solver ran.
    character(len=:), allocatable :: solver
    !> With `certify`: an upper bound of the largest eigenvalue that fails with
    !> probability at most `failure_probability` (module notes); otherwise 0
    !> and `certified` false.
    real(dp) :: upper_bound = 0.0_dp, failure_probability = 0.0_dp
    logical :: certified = .false.
    !> The certificate's products (included in `applications`).
    integer :: certificate_products = 0
  end type eigen_result_type


  !> Whether a Lanczos solve is under way in this process (ARPACK's SAVEd
  !> state is in use); set and cleared under the critical section
  !> `demstep_arpack` (`arpack_claim`, `arpack_release`).
  logical, save :: arpack_in_use = .false.

contains

  !> The largest eigenvalue of the symmetric positive semi-definite operator
  !> `apply` of order `n` and a unit eigenvector, by ARPACK's implicitly
  !> restarted Lanczos iteration (`lanczos_solve` on the serial space; see the
  !> module notes for the error bar).
  !>
  !> Status: `invalid_input` for a bad argument or a non-finite product,
  !> `not_converged` when the restarts ran out (the result then holds the best
  !> Ritz value and ARPACK's estimate of its residual, the vector is zero),
  !> otherwise ARPACK's own failures (`dsaupd_status`, `dseupd_status`).
  subroutine lanczos_largest(apply, context, n, result, status, eigenvector, tolerance, ncv, &
      nev, max_restarts, progress, start, certify, lower_bound, confirm, confirm_steps, store_bytes)
    !> y = A x (a module procedure, never an internal one).
    procedure(lanczos_operator) :: apply
    !> The operator's data, passed to `apply`.
    class(lanczos_context_type), intent(inout), target :: context
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
    !> Maximum implicit restarts of each ARPACK run (>= 1; ARPACK's mxiter; a
    !> solve makes at most `lanczos_runs` runs; a single unrestarted run,
    !> `krylov_top`, makes at most max_restarts * ncv products). Default
    !> `lanczos_restarts_default`.
    integer, intent(in), optional :: max_restarts
    !> Reports the products made (no total: convergence is not known ahead).
    class(progress_type), intent(inout), optional :: progress
    !> A start vector (size n; e.g. the previous solve's mode, a warm start):
    !> a thousandth of the default start vector is added, so that no
    !> eigenvector is missing from it.
    real(dp), intent(in), optional :: start(:)
    !> Add the randomised certificate `upper_bound` (default no). Without a
    !> warm start and for n > `krylov_min_order` the certificate's run is the
    !> solve (module notes).
    logical, intent(in), optional :: certify
    !> A lower bound of the smallest eigenvalue (default 0: A is positive
    !> semi-definite), for the certificate.
    real(dp), intent(in), optional :: lower_bound
    !> Confirm a converged top by a second run from a fresh random start
    !> (default true). False: the first converged run is the answer (basis
    !> `lanczos_basis_warm`), for a start known to be near the top mode.
    logical, intent(in), optional :: confirm
    !> The least products of a confirming run from a warm start (its one
    !> unrestarted run from the start plus a random one, n above
    !> `krylov_min_order`): default 0, on until the top Ritz pair converges.
    integer, intent(in), optional :: confirm_steps
    !> Memory (bytes, >= 0) for the Lanczos vectors a single run keeps; default
    !> `lanczos_store_bytes`. Fewer than its products: the Ritz vector comes
    !> from a second run of the recurrence (twice the products, no vectors kept).
    integer(i8), intent(in), optional :: store_bytes
    type(serial_space_type) :: space
    result%solver = lanczos_solver_name
    if (present(eigenvector)) eigenvector = 0.0_dp
    if (n < 1) then
      call set_status(status, demstep_stat%invalid_input, "n: the order " &
        //"must be at least 1, not "//int_text(n), where="lanczos_largest")
      return
    end if
    if (present(eigenvector)) then
      if (size(eigenvector) /= n) then
        call set_status(status, demstep_stat%invalid_input, "eigenvector: " &
          //"size "//int_text(size(eigenvector))//", need n = "//int_text(n), where="lanczos_largest")
        return
      end if
    end if
    space%n_global = n
    space%n_local = n
    space%first_row = 1
    space%caller = "lanczos_largest"
    space%solver = lanczos_solver_name
    if (present(store_bytes)) space%store_bytes = max(0_i8, store_bytes)
    space%apply => apply
    space%context => context
    call lanczos_solve(space, result, status, eigenvector, tolerance, ncv, nev, max_restarts, &
      progress, start, certify, lower_bound, confirm, confirm_steps)
  end subroutine lanczos_largest

  !> The Lanczos driver for any `lanczos_space_type`, serial or distributed:
  !> the largest eigenvalue, this block of a unit eigenvector and the error bar
  !> (see the module notes). The options are `lanczos_largest`'s; the space's
  !> sizes must be set and the eigenvector (when present) of size n_local on
  !> every process. Collective where the space is; the result and status are
  !> the same on every process. Statuses as `lanczos_largest`'s, ARPACK's
  !> through the space's `saupd_status` and `seupd_status`.
  subroutine lanczos_solve(space, result, status, eigenvector, tolerance, ncv, nev, &
      max_restarts, progress, start, certify, lower_bound, confirm, confirm_steps)
    class(lanczos_space_type), intent(inout) :: space
    type(eigen_result_type), intent(out) :: result
    type(demstep_status_type), intent(out) :: status
    !> This block of the unit eigenvector (n_local).
    real(dp), intent(out), optional :: eigenvector(:)
    real(dp), intent(in), optional :: tolerance
    integer, intent(in), optional :: ncv, nev, max_restarts
    class(progress_type), intent(inout), optional :: progress
    !> This block of a start vector (n_local), the same on every process or
    !> absent on every process.
    real(dp), intent(in), optional :: start(:)
    !> Add the randomised certificate (default no), and a lower bound of the
    !> spectrum for it (default 0).
    logical, intent(in), optional :: certify
    real(dp), intent(in), optional :: lower_bound
    !> As `lanczos_largest`'s (default true, and 0).
    logical, intent(in), optional :: confirm
    integer, intent(in), optional :: confirm_steps
    real(dp) :: tol, lower
    integer :: k, m, restarts, least
    logical :: wanted, confirming, warm

    call lanczos_options(tol, m, k, restarts, tolerance, ncv, nev, max_restarts)
    result%solver = space%solver
    result%tolerance = tol
    result%basis = lanczos_basis_estimate
    if (present(eigenvector)) eigenvector = 0.0_dp
    call check_lanczos_options(space%caller, tol, k, m, restarts, status)
    if (status%stat /= demstep_stat%ok) return
    ! ARPACK's SAVEd state: one solve per process at a time
    call arpack_claim(status)
    if (status%stat /= demstep_stat%ok) return
    if (present(progress)) call progress%start("Lanczos products", 0_i8)
    confirming = .true.
    if (present(confirm)) confirming = confirm
    wanted = .false.
    if (present(certify)) wanted = certify
    lower = 0.0_dp
    if (present(lower_bound)) lower = lower_bound
    warm = .false.
    if (present(start)) then
      ! (a zero, non-finite or wrongly sized start is no warm start)
      if (space%all_ranks(size(start) == space%n_local)) warm = space%all_ranks(any(start /= 0.0_dp)) &
        .and. space%all_ranks(all(ieee_is_finite(start)))
    end if
    if (wanted .and. .not. warm .and. space%n_global > krylov_min_order) then
      ! one run is the certificate and the solve (module notes)
      call krylov_top(space, tol, certificate_steps(space%n_global), restarts*m, &
        store_count(space, m), lower, result, status, eigenvector, progress)
    else if (warm .and. space%n_global > krylov_min_order) then
      ! one run from the warm start plus a random one (the start the ARPACK
      ! path's confirmation run would take), or, not confirming, from the
      ! warm start alone (a near mode refined: no restarted Krylov space of
      ! ncv products to fill first), then the certificate if asked
      least = 0
      if (confirming .and. present(confirm_steps)) least = max(0, min(confirm_steps, space%n_global))
      call krylov_top(space, tol, least, restarts*m, store_count(space, m), lower, result, status, &
        eigenvector, progress, start, confirming)
      if (wanted .and. (status%stat == demstep_stat%ok .or. status%stat == demstep_stat%not_converged)) &
        call random_certificate(space, lower, result, status, progress)
    else
      call iterate(space, tol, k, m, restarts, confirming, result, status, eigenvector, progress, start)
      if (wanted .and. (status%stat == demstep_stat%ok .or. status%stat == demstep_stat%not_converged)) &
        call random_certificate(space, lower, result, status, progress)
    end if
    if (present(progress)) call progress%finish()
    call arpack_release()
  end subroutine lanczos_solve

  !> Claim ARPACK's SAVEd state for one solve: status `busy` when another
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

  !> The body of `lanczos_solve` after the options' checks: ARPACK runs until
  !> the top eigenvalue has settled. A small residual only says that some
  !> eigenvalue lies near the Ritz value; on a crowded top (tiled packings,
  !> lattices) a run can converge on an eigenvalue below the top while the
  !> top's component is still small. So a converged top is confirmed by a
  !> second run from its vector plus a fresh stretch of the start sequence
  !> (every eigenvector gets a random component again), and accepted when the
  !> second top does not rise above the first by more than the tolerance (the
  !> larger of the two is kept); it is accepted at once only when the Krylov
  !> space is the whole space. A run out of restarts is followed by one from
  !> ARPACK's filtered start vector with twice the Krylov size (up to
  !> `lanczos_ncv_growth` times the asked one); at most `lanczos_runs` runs.
  subroutine iterate(space, tol, k_asked, m_asked, restarts, confirm, result, status, eigenvector, &
      progress, start)
    class(lanczos_space_type), intent(inout) :: space
    real(dp), intent(in) :: tol
    integer, intent(in) :: k_asked, m_asked, restarts
    !> Confirm a converged top by a second run (false: the first converged run).
    logical, intent(in) :: confirm
    type(eigen_result_type), intent(inout) :: result
    type(demstep_status_type), intent(out) :: status
    real(dp), intent(out), optional :: eigenvector(:)
    class(progress_type), intent(inout), optional :: progress
    real(dp), intent(in), optional :: start(:)
    real(dp) :: norms(2)
    integer :: n, k, m, m_cap, attempt
    real(dp), allocatable :: w(:), z(:), best_z(:), y(:)
    type(run_type) :: run, best
    logical :: settled

    n = space%n_local
    allocate(y(n))
    if (space%n_global == 1) then
      ! a 1-by-1 operator is its own eigenvalue; ARPACK needs nev < ncv <= n
      call product(space, [1.0_dp], y, result, status, progress)
      if (status%stat /= demstep_stat%ok) return
      result%eigenvalue = y(1)
      result%converged = .true.
      result%basis = lanczos_basis_whole
      result%error_bound = rounding_ulps*epsilon(1.0_dp)*abs(y(1))
      if (present(eigenvector)) eigenvector = 1.0_dp
      return
    end if
    ! small operators: the whole space (k must stay below it)
    m = min(m_asked, space%n_global)
    m_cap = min(space%n_global, lanczos_ncv_growth*m_asked)
    k = min(k_asked, m - 1)
    allocate(w(n), z(n), best_z(n))
    call lanczos_start_vector(w, space%first_row)
    if (present(start)) then
      ! (a zero, non-finite or wrongly sized start is ignored: the default start vector)
      if (space%all_ranks(size(start) == n)) then
        norms = [space%dot(start, start), space%dot(w, w)]
        if (norms(1) > 0.0_dp .and. norms(1) <= huge(1.0_dp)) &
          w = start/sqrt(norms(1)) + 1.0e-3_dp*w/sqrt(norms(2))
      end if
    end if
    settled = .false.
    do attempt = 1, lanczos_runs
      result%ncv = m
      result%nev = k
      call arpack_run(space, tol, k, m, restarts, w, z, run, result, status, progress)
      if (status%stat /= demstep_stat%ok) return
      if (run%zero) then
        ! the zero operator (see arpack_run): every eigenvalue is zero
        result%converged = .true.
        if (present(eigenvector)) then
          call lanczos_start_vector(eigenvector, space%first_row)
          eigenvector = eigenvector/sqrt(space%dot(eigenvector, eigenvector))
        end if
        return
      end if
      if (run%converged) then
        ! no higher than the last converged top, or the whole space: settled
        settled = m >= space%n_global .or. .not. confirm
        if (best%converged) settled = settled .or. run%theta <= best%theta*(1.0_dp + tol)
        if (.not. best%converged .or. run%theta > best%theta) then
          best = run
          best_z = z
        end if
        if (settled) exit
        ! confirm it: a run from the best vector and new random components
        call lanczos_start_vector(w, space%first_row + attempt*space%n_global)
        w = best_z + w/sqrt(space%dot(w, w))
      else
        if (.not. best%converged) best = run
        ! out of restarts: go on from ARPACK's filtered start vector, with a
        ! larger basis
        w = z
        m = min(2*m, m_cap)
        k = min(k, m - 1)
      end if
    end do

    if (.not. best%converged) then
      ! no run met the tolerance: the largest Ritz value of the last run and
      ! ARPACK's Ritz estimate of its residual
      result%eigenvalue = best%theta
      result%residual = best%rnorm
      result%error_bound = result%residual + rounding_ulps*epsilon(1.0_dp)*abs(result%eigenvalue)
      status = best%step_status
      if (status%stat == demstep_stat%ok) call set_status(status, demstep_stat%not_converged, &
        arpack_name(space%saupd_status(1))//"no Ritz value met the tolerance")
      status%message = status%message//" (largest Ritz value "//real_text(result%eigenvalue) &
        //", relative residual estimate "//real_text(result%residual/max(abs(result%eigenvalue), &
        tiny(1.0_dp)))//" after "//int_text(result%iterations)//" restarts, tolerance " &
        //real_text(tol)//"; raise max_restarts or ncv)"
      return
    end if
    if (present(eigenvector)) eigenvector = best_z
    ! (a run whose measured residual met the tolerance converged, whatever
    ! ARPACK said of the other wanted values)
    run%step_status%stat = demstep_stat%ok
    if (.not. settled) call set_status(run%step_status, demstep_stat%not_converged, &
      space%caller//": the top of the spectrum did not settle: a new start raised the " &
      //"largest eigenvalue by more than the tolerance")
    call lanczos_finish(best%theta, best%rnorm, tol, run%step_status, result, status)
    if (settled .and. m >= space%n_global) then
      result%basis = lanczos_basis_whole
    else if (settled .and. .not. confirm) then
      result%basis = lanczos_basis_warm
    else if (settled) then
      result%basis = lanczos_basis_confirmed
    end if
  end subroutine iterate

  !> One ARPACK solve from the start vector `w` with `k` wanted values in a
  !> Krylov space of `m`: its top Ritz pair's measured Rayleigh quotient and
  !> residual and the unit vector in `z` (converged), or the largest Ritz value
  !> with ARPACK's estimate and the filtered start vector in `z` (out of
  !> restarts).
  !> `status` is ok unless the solve failed (an ARPACK error or a non-finite
  !> product); the products and restarts are added to `result`.
  subroutine arpack_run(space, tol, k, m, restarts, w, z, run, result, status, progress)
    class(lanczos_space_type), intent(inout) :: space
    real(dp), intent(in) :: tol
    integer, intent(in) :: k, m, restarts
    real(dp), intent(in) :: w(:)
    real(dp), intent(out) :: z(:)
    type(run_type), intent(out) :: run
    type(eigen_result_type), intent(inout) :: result
    type(demstep_status_type), intent(out) :: status
    class(progress_type), intent(inout), optional :: progress
    real(dp) :: rnorm, znorm, tol_used
    integer :: n, ido, info, lworkl, nconv, itop
    integer :: iparam(arpack_iparam_size), ipntr(arpack_iparam_size)
    real(dp), allocatable :: v(:, :), workd(:), workl(:), resid(:), zz(:, :), d(:), y(:)
    logical, allocatable :: select(:)

    n = space%n_local
    lworkl = m*(m + 8)
    allocate(v(n, m), workd(3*n), workl(lworkl), resid(n), d(k), select(m), zz(n, k), y(n))
    workl = 0.0_dp
    resid = w
    z = 0.0_dp
    iparam = 0
    iparam(1) = 1         ! exact shifts
    iparam(3) = restarts
    iparam(7) = 1         ! mode 1: OP = A, B = I
    ido = 0
    info = 1              ! start from resid, not ARPACK's random vector
    tol_used = tol
    do
      call space%saupd(ido, k, tol_used, resid, m, v, iparam, ipntr, workd, workl, info)
      if (ido /= -1 .and. ido /= 1) exit
      call product(space, workd(ipntr(1):ipntr(1) + n - 1), workd(ipntr(2):ipntr(2) + n - 1), &
        result, status, progress)
      ! every process leaves the loop together: a distributed ARPACK waits on all
      if (status%stat /= demstep_stat%ok) return
    end do
    result%iterations = result%iterations + iparam(3)
    status%stat = demstep_stat%ok
    if (info == -9) then
      ! ARPACK's first step replaces the (nonzero) start vector x0 by A x0: it
      ! found A x0 = 0. Under Lanczos' own assumption (x0 has a component along
      ! every eigenvector) that makes every eigenvalue zero: the zero operator
      ! (a scene without contacts, say)
      run%zero = .true.
      return
    end if
    run%step_status = space%saupd_status(info)
    nconv = iparam(5)
    if (run%step_status%stat /= demstep_stat%ok .and. &
        run%step_status%stat /= demstep_stat%not_converged) then
      status = run%step_status
      return
    end if
    if (nconv < 1) then
      ! no Ritz pair met the tolerance: the largest of the k wanted Ritz values
      ! and ARPACK's Ritz estimate of its residual; the filtered start vector
      itop = maxloc(workl(ipntr(6):ipntr(6) + k - 1), 1) - 1
      run%theta = workl(ipntr(6) + itop)
      run%rnorm = abs(workl(ipntr(7) + itop))
      z = v(:, 1)
      return
    end if

    call space%seupd(.true., select, d, zz, k, tol_used, resid, m, v, iparam, ipntr, workd, &
      workl, info)
    if (info /= 0) then
      status = space%seupd_status(info)
      return
    end if
    ! converged values come in ascending order: the largest is the last one
    ! computed (nconv of them, nconv <= k)
    z = zz(:, min(nconv, k))
    znorm = sqrt(space%dot(z, z))
    if (.not. (znorm > 0.0_dp)) then
      call set_status(status, demstep_stat%eigensolver_failure, arpack_name(space%seupd_status(1)) &
        //"returned a zero Ritz vector")
      return
    end if
    z = z/znorm
    ! the measured Rayleigh quotient and residual of the returned vector
    call product(space, z, y, result, status, progress)
    if (status%stat /= demstep_stat%ok) return
    ! compensated sums: a plain sum of n nearly equal terms (a lattice mode) is
    ! off by up to n*epsilon/2, 1e-12 at n = 1e5, far above the tolerance
    run%theta = space%dot(z, y)/space%dot(z, z)
    y = y - run%theta*z
    rnorm = sqrt(space%dot(y, y))
    run%rnorm = rnorm
    run%converged = rnorm <= tol*abs(run%theta) .or. run%step_status%stat == demstep_stat%ok
  end subroutine arpack_run

  !> Products of the certificate's run for an operator of order n: the
  !> fewest j for which the bound proved in the module notes,
  !> sqrt(2 n (1 - eps)/(pi eps))/cosh((j - 1) t) with t = ln((1 + sqrt
  !> eps)/(1 - sqrt eps)), is at most `certificate_failure` (eps =
  !> `certificate_margin`): j products give the Krylov space of the
  !> polynomials of degree j - 1 in A applied to the start.
  pure integer function certificate_steps(n) result(steps)
    integer, intent(in) :: n
    real(dp) :: ratio, t
    ratio = sqrt(2.0_dp*real(max(n, 1), dp)*(1.0_dp - certificate_margin)/(pi*certificate_margin)) &
      /certificate_failure
    t = log((1.0_dp + sqrt(certificate_margin))/(1.0_dp - sqrt(certificate_margin)))
    steps = ceiling(acosh(max(ratio, 1.0_dp))/t) + 1
  end function certificate_steps

  !> Lanczos vectors `krylov_top` may keep: as many as fit in the space's
  !> `store_bytes` (default `lanczos_store_bytes`) at the global order (the same count on every
  !> process), and at least the Krylov size `m` asked for.
  pure integer function store_count(space, m) result(count)
    class(lanczos_space_type), intent(in) :: space
    integer, intent(in) :: m
    count = int(min(int(huge(1)/2, i8), max(int(m, i8), space%store_bytes/(8_i8*max(space%n_global, 1)))))
  end function store_count

  !> The certified cold solve in one run (module notes, "One run for both"):
  !> the three-term Lanczos recurrence from the certificate's Gaussian start
  !> for at least `steps_min` and at most `steps_max` products, until the
  !> top Ritz pair's estimate beta_j |s_j| is within the tolerance; the Ritz
  !> vector's measured Rayleigh quotient and residual (the result's
  !> eigenvalue, residual and error bar; a measured residual above the
  !> tolerance sends the run on with a tenfold stricter estimate) and the
  !> certificate from the largest Ritz value. Keeps up to `store_max` Lanczos
  !> vectors (twice as many in single precision at `single_basis_tolerance`),
  !> else forms the Ritz vector by a second pass. Status
  !> `not_converged` when `steps_max` products did not meet the tolerance
  !> (the result still has the measured pair and the certificate).
  subroutine krylov_top(space, tol, steps_min, steps_max, store_max, lower, result, status, eigenvector, &
      progress, warm, random)
    class(lanczos_space_type), intent(inout) :: space
    real(dp), intent(in) :: tol
    integer, intent(in) :: steps_min, steps_max, store_max
    !> A lower bound of the smallest eigenvalue (the certificate's shift).
    real(dp), intent(in) :: lower
    type(eigen_result_type), intent(inout) :: result
    type(demstep_status_type), intent(out) :: status
    real(dp), intent(out), optional :: eigenvector(:)
    class(progress_type), intent(inout), optional :: progress
    !> A warm start (this block, non-zero): the run starts from its unit
    !> vector plus the certificate's unit Gaussian one, and makes no
    !> certificate (basis `lanczos_basis_warm_random`; steps_min is the
    !> confirmation's least products, 0 for none).
    real(dp), intent(in), optional :: warm(:)
    !> With `warm`: false, the run starts from the warm vector alone (basis
    !> `lanczos_basis_warm`: not confirmed). Default true.
    logical, intent(in), optional :: random
    real(dp), allocatable :: v(:), v_old(:), w(:), z(:), y(:), alpha(:), beta(:), s(:)
    type(basis_block_type), allocatable :: basis(:)
    real(dp), allocatable :: swap(:)
    real(dp) :: xi, estimate, threshold, scale, shift, theta, rnorm, beta_old, beta2
    integer :: n, j, last, capacity
    logical :: stored, invariant, met, single
    type(demstep_status_type) :: step_status

    n = space%n_local
    last = max(steps_max, steps_min)
    allocate(v(n), v_old(n), w(n), alpha(last), beta(last))
    call run_start(v)
    single = tol >= single_basis_tolerance
    ! (the columns that may be kept, in single precision twice as many in the
    ! same memory, taken only as they are filled; the run makes at least
    ! steps_min products: fewer kept vectors would all be dropped, so then
    ! none are kept)
    capacity = store_max
    if (single) capacity = 2*store_max
    stored = capacity >= max(1, steps_min)
    capacity = min(capacity, last)
    if (stored) allocate(basis((capacity - 1)/basis_block + 1))
    v_old = 0.0_dp
    beta_old = 0.0_dp
    scale = 0.0_dp
    threshold = tol
    met = .false.
    theta = 0.0_dp
    rnorm = 0.0_dp
    xi = 0.0_dp
    if (stored) call keep(1)
    do j = 1, last
      ! (the product's finiteness is checked on the recurrence's sums below)
      call product(space, v, w, result, status, progress, checked=.false.)
      ! (v_old is 0 at j = 1)
      alpha(j) = space%recurrence_update(w, beta_old, v_old, v)
      beta2 = space%recurrence_update(w, alpha(j), v)
      ! a non-finite entry of A v makes the sum of squares of w non-finite
      ! (Inf and NaN survive both updates): one check instead of a pass
      if (.not. (ieee_is_finite(alpha(j)) .and. ieee_is_finite(beta2))) then
        call nonfinite_product(space, result, status)
        return
      end if
      beta(j) = sqrt(beta2)
      scale = max(scale, abs(alpha(j)) + beta(j) + beta_old)
      ! an invariant Krylov space: its Ritz values are eigenvalues (exact
      ! arithmetic), its largest one xi_k for every later k
      invariant = .not. beta(j) > 1.0e3_dp*epsilon(1.0_dp)*scale
      if (j >= steps_min .or. invariant .or. j == last) then
        if (allocated(s)) deallocate(s)
        allocate(s(j))
        call largest_tridiagonal_eigenpair(alpha(:j), beta(:j - 1), xi, s, step_status)
        if (step_status%stat /= demstep_stat%ok) then
          status = step_status
          return
        end if
        estimate = beta(j)*abs(s(j))
        if (invariant .or. estimate <= threshold*abs(xi) .or. j == last) then
          call ritz_vector(j)
          if (status%stat /= demstep_stat%ok) return
          met = measured_met()
          if (.not. met .and. stored .and. single) then
            ! (the single-precision vectors may have cost the tolerance: the
            ! same Ritz vector from the recurrence run again, in full)
            stored = .false.
            deallocate(basis)
            call ritz_vector(j)
            if (status%stat /= demstep_stat%ok) return
            met = measured_met()
          end if
          if (met .or. invariant) exit
          ! (the estimate said converged, the measurement did not: on, stricter)
          threshold = 0.1_dp*threshold
        end if
      end if
      ! v_old <- v, v <- w/beta_j (the arrays trade places, no copy), kept
      ! as column j + 1 in the same pass
      call move_alloc(v_old, swap)
      call move_alloc(v, v_old)
      call move_alloc(swap, v)
      if (stored .and. j < last) call keep(j + 1, w, beta(j))
      if (.not. (stored .and. j < last)) call scaled_copy(w, beta(j), v)
      beta_old = beta(j)
    end do
    result%ncv = min(j, last)
    result%nev = 1
    if (present(eigenvector)) eigenvector = z
    step_status%stat = demstep_stat%ok
    if (.not. met) call set_status(step_status, demstep_stat%not_converged, space%caller &
      //": the Lanczos run from a random start did not meet the tolerance in " &
      //int_text(result%applications)//" products")
    call lanczos_finish(theta, rnorm, tol, step_status, result, status)
    result%basis = lanczos_basis_estimate
    if (met) result%basis = lanczos_basis_random
    if (met .and. present(warm)) result%basis = lanczos_basis_warm_random
    if (met .and. present(warm) .and. present(random)) then
      if (.not. random) result%basis = lanczos_basis_warm
    end if
    if (present(warm)) return
    ! the certificate (module notes) from the largest Ritz value of T_j,
    ! j >= steps_min or an invariant Krylov space
    shift = -min(lower, 0.0_dp)
    result%upper_bound = (max(theta, xi) + shift)/(1.0_dp - certificate_margin) - shift &
      + rounding_ulps*epsilon(1.0_dp)*(scale + shift)
    result%failure_probability = certificate_failure
    result%certified = .true.
    result%certificate_products = min(steps_min, result%ncv)
  contains
    !> The run's unit start vector (the same bits each time it is made).
    subroutine run_start(u)
      real(dp), intent(out) :: u(:)
      logical :: mixed
      mixed = .true.
      if (present(random)) mixed = random
      if (present(warm) .and. .not. mixed) then
        u = warm/sqrt(space%dot(warm, warm))
        return
      end if
      call certificate_start(space, u)
      if (present(warm)) then
        u = u + warm/sqrt(space%dot(warm, warm))
        u = u/sqrt(space%dot(u, u))
      end if
    end subroutine run_start

    !> Whether the measured residual of the Ritz pair meets the tolerance (or
    !> rounding's, in an invariant Krylov space).
    logical function measured_met()
      measured_met = rnorm <= tol*abs(theta) .or. (invariant .and. rnorm <= 1.0e3_dp*epsilon(1.0_dp)*scale)
    end function measured_met

    !> Keep the Lanczos vector v as column j (in single precision when
    !> `single`); with `from` and `by`, first set v = from/by in the same
    !> pass (`scaled_copy`). Past the columns allocated, none are kept.
    subroutine keep(j, from, by)
      integer, intent(in) :: j
      real(dp), intent(in), optional :: from(:), by
      integer :: i, b, c
      if (j > capacity) then
        stored = .false.
        deallocate(basis)
        if (present(from)) call scaled_copy(from, by, v)
        return
      end if
      b = (j - 1)/basis_block + 1
      c = j - (b - 1)*basis_block
      if (c == 1) then
        if (single) allocate(basis(b)%single(n, min(basis_block, capacity - (b - 1)*basis_block)))
        if (.not. single) allocate(basis(b)%full(n, min(basis_block, capacity - (b - 1)*basis_block)))
      end if
      if (single .and. present(from)) then
        call scaled_copy(from, by, v, basis(b)%single(:, c))
      else if (single) then
        !$omp parallel do schedule(static) if(n > recurrence_block)
        do i = 1, n
          basis(b)%single(i, c) = real(v(i), sp)
        end do
        !$omp end parallel do
      else
        if (present(from)) call scaled_copy(from, by, v)
        basis(b)%full(:, c) = v
      end if
    end subroutine keep

    !> z = the unit Ritz vector of T_j's top pair (s), theta and rnorm its
    !> measured Rayleigh quotient and residual; a second pass of the
    !> recurrence when the vectors were not kept (its previous vector in
    !> v_old, which the run sets anew before it goes on).
    subroutine ritz_vector(j)
      integer, intent(in) :: j
      real(dp), allocatable :: u(:), t(:)
      integer, parameter :: ritz_block = 1024
      integer :: i, b, c, k, k1
      if (stored .and. single) then
        if (.not. allocated(z)) allocate(z(n))
        ! (a block of z at a time over the columns in order: each entry's
        ! sum in column order, in parallel over the blocks)
        !$omp parallel do private(i, b, c, k, k1) schedule(static) if(n > recurrence_block)
        do k = 1, n, ritz_block
          k1 = min(n, k + ritz_block - 1)
          z(k:k1) = 0.0_dp
          do i = 1, j
            b = (i - 1)/basis_block + 1
            c = i - (b - 1)*basis_block
            z(k:k1) = z(k:k1) + s(i)*real(basis(b)%single(k:k1, c), dp)
          end do
        end do
        !$omp end parallel do
      else if (stored) then
        if (.not. allocated(z)) allocate(z(n))
        z = 0.0_dp
        do i = 1, j, basis_block
          ! (a block's columns at once)
          b = (i - 1)/basis_block + 1
          z = z + matmul(basis(b)%full(:, :min(basis_block, j - i + 1)), s(i:min(i + basis_block - 1, j)))
        end do
      else
        allocate(u(n), t(n))
        call run_start(u)
        v_old = 0.0_dp
        z = s(1)*u
        do i = 1, j - 1
          call product(space, u, t, result, status, progress)
          if (status%stat /= demstep_stat%ok) return
          if (i > 1) t = t - beta(i - 1)*v_old
          t = t - alpha(i)*u
          v_old = u
          u = t/beta(i)
          z = z + s(i + 1)*u
        end do
        deallocate(u, t)
      end if
      z = z/sqrt(space%dot(z, z))
      if (.not. allocated(y)) allocate(y(n))
      call product(space, z, y, result, status, progress)
      if (status%stat /= demstep_stat%ok) return
      theta = space%dot(z, y)/space%dot(z, z)
      y = y - theta*z
      rnorm = sqrt(space%dot(y, y))
    end subroutine ritz_vector
  end subroutine krylov_top

  !> The certificate's start: a unit Gaussian vector from a stretch of the
  !> start sequence that the ARPACK runs' starts do not use (this block).
  subroutine certificate_start(space, v)
    class(lanczos_space_type), intent(inout) :: space
    real(dp), intent(out) :: v(:)
    call gaussian_vector(v, 2*(space%first_row - 1) + 1 + lanczos_runs*2*space%n_global)
    v = v/sqrt(space%dot(v, v))
  end subroutine certificate_start

  !> The randomised certificate (module notes): the three-term Lanczos
  !> recurrence from a Gaussian start for `certificate_steps` products (fewer
  !> when its Krylov space is invariant), the largest eigenvalue xi of its
  !> tridiagonal matrix, and `result%upper_bound` = max(theta, xi)/(1 - eps)
  !> for the operator shifted by -min(lower, 0) (theta the eigenvalue found,
  !> a Ritz value: at most lambda_max), plus the rounding allowance.
  !> Three vectors; collective where the space is.
  subroutine random_certificate(space, lower, result, status, progress)
    class(lanczos_space_type), intent(inout) :: space
    !> A lower bound of the smallest eigenvalue.
    real(dp), intent(in) :: lower
    type(eigen_result_type), intent(inout) :: result
    type(demstep_status_type), intent(inout) :: status
    class(progress_type), intent(inout), optional :: progress
    real(dp), allocatable :: v(:), v_old(:), w(:), alpha(:), beta(:)
    real(dp) :: xi, shift, beta_old, scale, top
    integer :: n, m, j, steps
    type(demstep_status_type) :: step_status
    n = space%n_local
    m = certificate_steps(space%n_global)
    allocate(v(n), v_old(n), w(n), alpha(m), beta(m))
    call certificate_start(space, v)
    v_old = 0.0_dp
    beta_old = 0.0_dp
    scale = 0.0_dp
    steps = 0
    do j = 1, m
      call product(space, v, w, result, step_status, progress)
      if (step_status%stat /= demstep_stat%ok) then
        status = step_status
        return
      end if
      result%certificate_products = result%certificate_products + 1
      if (j > 1) w = w - beta_old*v_old
      alpha(j) = space%dot(v, w)
      w = w - alpha(j)*v
      beta(j) = sqrt(space%dot(w, w))
      steps = j
      scale = max(scale, abs(alpha(j)) + beta(j) + beta_old)
      ! an invariant Krylov space: its Ritz values are eigenvalues (exact
      ! arithmetic), the largest one xi_k for every later k
      if (.not. beta(j) > 1.0e3_dp*epsilon(1.0_dp)*scale) exit
      v_old = v
      v = w/beta(j)
      beta_old = beta(j)
    end do
    call largest_tridiagonal_eigenvalue(alpha(:steps), beta(:steps - 1), xi, step_status)
    if (step_status%stat /= demstep_stat%ok) then
      status = step_status
      return
    end if
    shift = -min(lower, 0.0_dp)
    top = (max(result%eigenvalue, xi) + shift)/(1.0_dp - certificate_margin) - shift
    ! (the recurrence's rounding: a few ulps of the shifted operator's norm)
    result%upper_bound = top + rounding_ulps*epsilon(1.0_dp)*(scale + shift)
    result%failure_probability = certificate_failure
    result%certified = .true.
  end subroutine random_certificate

  !> Standard normal entries by the Box-Muller transform of two uniform
  !> entries of the start sequence (`lanczos_start_vector` plus 1/2, in (0, 1))
  !> each: entry i uses the sequence's entries first + 2(i - 1) and the next.
  !> Normalised, it is uniform on the unit sphere (as far as the sequence is
  !> random).
  subroutine gaussian_vector(x, first)
    real(dp), intent(out) :: x(:)
    !> The sequence's index for x(1)'s first uniform entry.
    integer, intent(in) :: first
    ! (the uniform entries a block at a time: no copy of x's size; each
    ! block enters the sequence at its own index, so the blocks run in
    ! parallel with the same bits)
    integer, parameter :: block = 4096
    real(dp) :: u(2*block)
    integer :: i, i0, nb
    !$omp parallel do private(i, i0, nb, u) schedule(static) if(size(x) > recurrence_block)
    do i0 = 1, size(x), block
      nb = min(block, size(x) - i0 + 1)
      call lanczos_start_vector(u(:2*nb), first + 2*(i0 - 1))
      u(:2*nb) = u(:2*nb) + 0.5_dp
      do i = 1, nb
        x(i0 + i - 1) = sqrt(-2.0_dp*log(u(2*i - 1)))*cos(2.0_dp*pi*u(2*i))
      end do
    end do
    !$omp end parallel do
  end subroutine gaussian_vector

  !> The routine's name that starts an ARPACK status message ("ARPACK dsaupd: ").
  pure function arpack_name(status) result(who)
    type(demstep_status_type), intent(in) :: status
    character(len=:), allocatable :: who
    who = ""
    if (allocated(status%message)) who = status%message(:index(status%message, ": ") + 1)
  end function arpack_name

  !> One product, counted, reported and checked for finiteness on every
  !> process (`checked` false: not checked, the caller checks it on sums it
  !> takes of ax, as `krylov_top` does; the same on every process).
  subroutine product(space, x, ax, result, status, progress, checked)
    class(lanczos_space_type), intent(inout) :: space
    real(dp), intent(in) :: x(:)
    real(dp), intent(out) :: ax(:)
    type(eigen_result_type), intent(inout) :: result
    type(demstep_status_type), intent(out) :: status
    class(progress_type), intent(inout), optional :: progress
    logical, intent(in), optional :: checked
    call space%product(x, ax)
    result%applications = result%applications + 1
    if (present(progress)) call progress%update(result%applications)
    status%stat = demstep_stat%ok
    if (present(checked)) then
      if (.not. checked) return
    end if
    if (.not. space%all_ranks(all_finite(ax))) call nonfinite_product(space, result, status)
  end subroutine product

  !> The status of a product that returned a non-finite value (the last one counted).
  subroutine nonfinite_product(space, result, status)
    class(lanczos_space_type), intent(in) :: space
    type(eigen_result_type), intent(in) :: result
    type(demstep_status_type), intent(out) :: status
    call set_status(status, demstep_stat%invalid_input, space%caller//": the operator " &
      //"returned a non-finite value (product "//int_text(result%applications)//")")
  end subroutine nonfinite_product

  !> The end of a Lanczos solve: the result from the measured Rayleigh quotient
  !> `theta` and residual `rnorm` of the returned unit vector (error bar
  !> `rnorm` plus the rounding allowance), and ARPACK's status with the
  !> numbers that say how far it got when it is not ok.
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

  !> x.y by compensated summation (Ogita, Rump and Oishi's Dot2) as the pair
  !> (sum, its rounding error): sum(parts) is as accurate as a sum in twice the
  !> working precision (`dot_parts`). The pairs of several blocks add up (a distributed dot).
  pure function accurate_dot_parts(x, y) result(parts)
    real(dp), intent(in) :: x(:), y(:)
    real(dp) :: parts(2)
    parts = dot_parts(x, y)
  end function accurate_dot_parts

  !> The fixed start vector: a Park-Miller (minimal standard, multiplier 48271)
  !> sequence from seed 1, mapped to (-0.5, 0.5). The same for every run,
  !> thread and rank count, and with a component along any eigenvector in
  !> practice. A block from global index `first` on is entered by modular
  !> powers (a distributed vector's block).
  pure subroutine lanczos_start_vector(x, first)
    !> Filled with entries first .. first + size(x) - 1 of the sequence.
    real(dp), intent(out) :: x(:)
    !> Global index of x(1) (default 1).
    integer, intent(in), optional :: first
    integer(i8), parameter :: modulus = 2147483647_i8, multiplier = 48271_i8
    integer(i8) :: state, base
    integer :: i, k
    ! state after first - 1 steps: multiplier**(first - 1) mod modulus
    state = 1_i8
    base = multiplier
    k = 0
    if (present(first)) k = first - 1
    do while (k > 0)
      if (mod(k, 2) == 1) state = mod(state*base, modulus)
      base = mod(base*base, modulus)
      k = k/2
    end do
    do i = 1, size(x)
      state = mod(multiplier*state, modulus)
      x(i) = real(state, dp)/real(modulus, dp) - 0.5_dp
    end do
  end subroutine lanczos_start_vector

  subroutine serial_product(space, x, y)
    class(serial_space_type), intent(inout) :: space
    real(dp), intent(in) :: x(:)
    real(dp), intent(out) :: y(:)
    call space%apply(space%context, x, y)
  end subroutine serial_product

  !> The serial `dot`: `accurate_dot_parts` of each block of
  !> `recurrence_block` entries (in parallel), then the blocks' pairs in block
  !> order, the sums by `two_sum` and the errors apart (the compensated sum
  !> carried across the blocks: still as accurate as a sum in twice the
  !> working precision, and the same bits for every thread count).
  function serial_dot(space, x, y) result(s)
    class(serial_space_type), intent(inout) :: space
    real(dp), intent(in) :: x(:), y(:)
    real(dp) :: s
    real(dp), allocatable :: part(:, :)
    real(dp) :: h, e, q, t
    integer :: b, nb
    nb = max(1, (size(x) + recurrence_block - 1)/recurrence_block)
    allocate(part(2, nb))
    !$omp parallel do private(b) schedule(static) if(nb > 1)
    do b = 1, nb
      part(:, b) = accurate_dot_parts(x((b - 1)*recurrence_block + 1:min(size(x), b*recurrence_block)), &
        y((b - 1)*recurrence_block + 1:min(size(x), b*recurrence_block)))
    end do
    !$omp end parallel do
    h = 0.0_dp
    e = 0.0_dp
    do b = 1, nb
      call two_sum(h, part(1, b), t, q)
      h = t
      e = e + (q + part(2, b))
    end do
    s = h + e
  end function serial_dot

  function space_recurrence_dot(space, x, y) result(s)
    class(lanczos_space_type), intent(inout) :: space
    real(dp), intent(in) :: x(:), y(:)
    real(dp) :: s
    s = space%dot(x, y)
  end function space_recurrence_dot

  function space_recurrence_update(space, w, c, u, x) result(s)
    class(lanczos_space_type), intent(inout) :: space
    real(dp), intent(inout) :: w(:)
    real(dp), intent(in) :: c, u(:)
    real(dp), intent(in), optional :: x(:)
    real(dp) :: s
    w = w - c*u
    if (present(x)) then
      s = space%recurrence_dot(x, w)
    else
      s = space%recurrence_dot(w, w)
    end if
  end function space_recurrence_update

  !> The serial `recurrence_update`: the update and the plain sum (as
  !> `serial_recurrence_dot`'s) in one loop, in blocks of `recurrence_block`
  !> in parallel.
  function serial_recurrence_update(space, w, c, u, x) result(s)
    class(serial_space_type), intent(inout) :: space
    real(dp), intent(inout) :: w(:)
    real(dp), intent(in) :: c, u(:)
    real(dp), intent(in), optional :: x(:)
    real(dp) :: s
    real(dp), allocatable :: part(:)
    real(dp) :: t
    integer :: i, b, nb
    logical :: other
    other = present(x)
    nb = max(1, (size(w) + recurrence_block - 1)/recurrence_block)
    allocate(part(nb))
    !$omp parallel do private(b, i, t) schedule(static) if(nb > 1)
    do b = 1, nb
      t = 0.0_dp
      if (other) then
        do i = (b - 1)*recurrence_block + 1, min(size(w), b*recurrence_block)
          w(i) = w(i) - c*u(i)
          t = t + x(i)*w(i)
        end do
      else
        do i = (b - 1)*recurrence_block + 1, min(size(w), b*recurrence_block)
          w(i) = w(i) - c*u(i)
          t = t + w(i)*w(i)
        end do
      end if
      part(b) = t
    end do
    !$omp end parallel do
    s = sum_in_order(part)
  end function serial_recurrence_update

  !> The serial `recurrence_dot`: the plain sum of x(i) y(i), each block of
  !> `recurrence_block` in index order (in parallel), then the blocks' sums
  !> in order (`sum_in_order`): the same bits for every thread count.
  function serial_recurrence_dot(space, x, y) result(s)
    class(serial_space_type), intent(inout) :: space
    real(dp), intent(in) :: x(:), y(:)
    real(dp) :: s
    real(dp), allocatable :: part(:)
    real(dp) :: t
    integer :: i, b, nb
    nb = max(1, (size(x) + recurrence_block - 1)/recurrence_block)
    allocate(part(nb))
    !$omp parallel do private(b, i, t) schedule(static) if(nb > 1)
    do b = 1, nb
      t = 0.0_dp
      do i = (b - 1)*recurrence_block + 1, min(size(x), b*recurrence_block)
        t = t + x(i)*y(i)
      end do
      part(b) = t
    end do
    !$omp end parallel do
    s = sum_in_order(part)
  end function serial_recurrence_dot

  !> The plain sum of the entries in index order (`serial_recurrence_update`'s
  !> blocks: one block's sum is returned as it is).
  pure real(dp) function sum_in_order(part) result(s)
    real(dp), intent(in) :: part(:)
    integer :: b
    s = 0.0_dp
    do b = 1, size(part)
      s = s + part(b)
    end do
  end function sum_in_order

  !> y = x/c, entrywise in parallel (the Lanczos vectors' normalisation),
  !> and y rounded to single precision in `y_single` when present (the kept
  !> vector, in the same pass).
  subroutine scaled_copy(x, c, y, y_single)
    real(dp), intent(in) :: x(:), c
    real(dp), intent(out) :: y(:)
    real(sp), intent(out), optional :: y_single(:)
    integer :: i
    if (present(y_single)) then
      !$omp parallel do schedule(static) if(size(x) > recurrence_block)
      do i = 1, size(x)
        y(i) = x(i)/c
        y_single(i) = real(y(i), sp)
      end do
      !$omp end parallel do
      return
    end if
    !$omp parallel do schedule(static) if(size(x) > recurrence_block)
    do i = 1, size(x)
      y(i) = x(i)/c
    end do
    !$omp end parallel do
  end subroutine scaled_copy

  !> Whether every entry is finite, checked in parallel.
  logical function all_finite(x) result(finite)
    real(dp), intent(in) :: x(:)
    integer :: i
    finite = .true.
    !$omp parallel do reduction(.and.:finite) schedule(static) if(size(x) > recurrence_block)
    do i = 1, size(x)
      finite = finite .and. ieee_is_finite(x(i))
    end do
    !$omp end parallel do
  end function all_finite

  function serial_all(space, condition) result(held)
    class(serial_space_type), intent(inout) :: space
    logical, intent(in) :: condition
    logical :: held
    held = condition
  end function serial_all

  subroutine serial_saupd(space, ido, nev, tol, resid, ncv, v, iparam, ipntr, workd, workl, info)
    class(serial_space_type), intent(inout) :: space
    integer, intent(inout) :: ido
    integer, intent(in) :: nev, ncv
    real(dp), intent(inout) :: tol
    real(dp), intent(inout) :: resid(:), v(:, :), workd(:), workl(:)
    integer, intent(inout) :: iparam(:), ipntr(:), info
    call dsaupd(ido, "I", space%n_local, "LA", nev, tol, resid, ncv, v, space%n_local, iparam, &
      ipntr, workd, workl, size(workl), info)
  end subroutine serial_saupd

  subroutine serial_seupd(space, rvec, select, d, z, nev, tol, resid, ncv, v, iparam, ipntr, &
      workd, workl, info)
    class(serial_space_type), intent(inout) :: space
    logical, intent(in) :: rvec
    logical, intent(inout) :: select(:)
    real(dp), intent(out) :: d(:)
    real(dp), intent(inout) :: z(:, :)
    integer, intent(in) :: nev, ncv
    real(dp), intent(in) :: tol
    real(dp), intent(inout) :: resid(:), v(:, :), workd(:), workl(:)
    integer, intent(inout) :: iparam(:), ipntr(:)
    integer, intent(out) :: info
    call dseupd(rvec, "A", select, d, z, space%n_local, 0.0_dp, "I", space%n_local, "LA", nev, &
      tol, resid, ncv, v, space%n_local, iparam, ipntr, workd, workl, size(workl), info)
  end subroutine serial_seupd

  pure function serial_saupd_status(space, info) result(status)
    class(serial_space_type), intent(in) :: space
    integer, intent(in) :: info
    type(demstep_status_type) :: status
    status = dsaupd_status(info)
  end function serial_saupd_status

  pure function serial_seupd_status(space, info) result(status)
    class(serial_space_type), intent(in) :: space
    integer, intent(in) :: info
    type(demstep_status_type) :: status
    status = dseupd_status(info)
  end function serial_seupd_status

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
      call set_status(status, demstep_stat%invalid_input, real_text(tol)//" is outside [2.2e-16, 0.1]", &
        where="tolerance")
    else if (nev < 1) then
      call set_status(status, demstep_stat%invalid_input, "need at least 1, not "//int_text(nev), where="nev")
    else if (ncv <= nev) then
      call set_status(status, demstep_stat%invalid_input, "the Krylov size "//int_text(ncv)// &
        " must exceed nev = "//int_text(nev), where="ncv")
    else if (restarts < 1) then
      call set_status(status, demstep_stat%invalid_input, "need at least 1, not "//int_text(restarts), &
        where="max_restarts")
    end if
    ! the message names the driver too
    if (status%stat /= demstep_stat%ok) status%message = caller//": "//status%message
  end subroutine check_lanczos_options

end module demstep_lanczos
