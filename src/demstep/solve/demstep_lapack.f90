!> LAPACK through explicit interfaces, in one place, with `info` turned into a
!> message. Only what demstep needs: the largest eigenpair of a symmetric
!> matrix, every eigenpair of a small one (a rigid body's inertia tensor),
!> the largest eigenvalue of a complex Hermitian one (a periodic system's
!> Bloch operator, the reference for tiled packings), the largest eigenvalue
!> of a symmetric tridiagonal one (a Lanczos run's), and the spectral radius
!> of a general one (a one-step map's, the reference for the damped stability
!> limit), and the Cholesky factor and solves of a positive definite one (a
!> linear program's normal equations).
module demstep_lapack
  use demstep_kinds, only: dp
  use demstep_status, only: demstep_status_type, demstep_stat, set_status
  implicit none
  private

  public :: largest_eigenpair, spectral_radius, largest_hermitian_eigenvalue, symmetric_eigensystem, &
    largest_tridiagonal_eigenvalue, largest_tridiagonal_eigenpair, cholesky_factor, cholesky_solve

  interface
    !> LAPACK dsyevr: selected eigenvalues (and vectors) of a real symmetric matrix
    !> by the MRRR algorithm.
    pure subroutine dsyevr(jobz, range, uplo, n, a, lda, vl, vu, il, iu, abstol, m, w, z, ldz, &
        isuppz, work, lwork, iwork, liwork, info)
      import :: dp
      character(len=1), intent(in) :: jobz, range, uplo
      integer, intent(in) :: n, lda, il, iu, ldz, lwork, liwork
      real(dp), intent(inout) :: a(lda, *)
      real(dp), intent(in) :: vl, vu, abstol
      integer, intent(out) :: m, info
      real(dp), intent(out) :: w(*), z(ldz, *)
      integer, intent(out) :: isuppz(*)
      real(dp), intent(inout) :: work(*)
      integer, intent(inout) :: iwork(*)
    end subroutine dsyevr

    !> LAPACK dgeev: eigenvalues (and optionally vectors) of a general real matrix.
    pure subroutine dgeev(jobvl, jobvr, n, a, lda, wr, wi, vl, ldvl, vr, ldvr, work, lwork, info)
      import :: dp
      character(len=1), intent(in) :: jobvl, jobvr
      integer, intent(in) :: n, lda, ldvl, ldvr, lwork
      real(dp), intent(inout) :: a(lda, *)
      real(dp), intent(out) :: wr(*), wi(*), vl(ldvl, *), vr(ldvr, *)
      real(dp), intent(inout) :: work(*)
      integer, intent(out) :: info
    end subroutine dgeev

    !> LAPACK zheev: all eigenvalues (and optionally vectors) of a complex
    !> Hermitian matrix, ascending.
    pure subroutine zheev(jobz, uplo, n, a, lda, w, work, lwork, rwork, info)
      import :: dp
      character(len=1), intent(in) :: jobz, uplo
      integer, intent(in) :: n, lda, lwork
      complex(dp), intent(inout) :: a(lda, *)
      real(dp), intent(out) :: w(*)
      complex(dp), intent(inout) :: work(*)
      real(dp), intent(inout) :: rwork(*)
      integer, intent(out) :: info
    end subroutine zheev
    !> LAPACK dsterf: all eigenvalues of a symmetric tridiagonal matrix (ascending
    !> in d on return), by the root-free QL/QR iteration.
    pure subroutine dsterf(n, d, e, info)
      import :: dp
      integer, intent(in) :: n
      real(dp), intent(inout) :: d(*), e(*)
      integer, intent(out) :: info
    end subroutine dsterf

    !> LAPACK dstevr: selected eigenvalues (and vectors) of a real symmetric
    !> tridiagonal matrix (d and e are overwritten).
    pure subroutine dstevr(jobz, range, n, d, e, vl, vu, il, iu, abstol, m, w, z, ldz, isuppz, &
        work, lwork, iwork, liwork, info)
      import :: dp
      character(len=1), intent(in) :: jobz, range
      integer, intent(in) :: n, il, iu, ldz, lwork, liwork
      real(dp), intent(inout) :: d(*), e(*)
      real(dp), intent(in) :: vl, vu, abstol
      integer, intent(out) :: m, info
      real(dp), intent(out) :: w(*), z(ldz, *)
      integer, intent(out) :: isuppz(*)
      real(dp), intent(inout) :: work(*)
      integer, intent(inout) :: iwork(*)
    end subroutine dstevr

    !> LAPACK dpotrf: the Cholesky factor of a symmetric positive definite matrix.
    pure subroutine dpotrf(uplo, n, a, lda, info)
      import :: dp
      character(len=1), intent(in) :: uplo
      integer, intent(in) :: n, lda
      real(dp), intent(inout) :: a(lda, *)
      integer, intent(out) :: info
    end subroutine dpotrf

    !> LAPACK dpotrs: solves with a Cholesky factor from dpotrf.
    pure subroutine dpotrs(uplo, n, nrhs, a, lda, b, ldb, info)
      import :: dp
      character(len=1), intent(in) :: uplo
      integer, intent(in) :: n, nrhs, lda, ldb
      real(dp), intent(in) :: a(lda, *)
      real(dp), intent(inout) :: b(ldb, *)
      integer, intent(out) :: info
    end subroutine dpotrs
  end interface

contains

  !> The largest eigenvalue of the symmetric tridiagonal matrix with diagonal
  !> `diag` (n >= 1) and off-diagonal `off` (n - 1), by dsterf. Status
  !> `lapack_failure` with LAPACK's info explained.
  pure subroutine largest_tridiagonal_eigenvalue(diag, off, eigenvalue, status)
    real(dp), intent(in) :: diag(:), off(:)
    real(dp), intent(out) :: eigenvalue
    type(demstep_status_type), intent(out) :: status
    real(dp), allocatable :: d(:), e(:)
    integer :: n, info
    n = size(diag)
    eigenvalue = 0.0_dp
    if (n < 1 .or. size(off) < n - 1) then
      call set_status(status, demstep_stat%invalid_input, "need n >= 1 diagonal and n - 1 " &
        //"off-diagonal entries", where="largest_tridiagonal_eigenvalue")
      return
    end if
    d = diag
    allocate(e(max(1, n - 1)))
    e = 0.0_dp
    if (n > 1) e(:n - 1) = off(:n - 1)
    call dsterf(n, d, e, info)
    if (info /= 0) then
      call set_status(status, demstep_stat%lapack_failure, info_message(info, "dsterf"))
      return
    end if
    eigenvalue = d(n)
    status%stat = demstep_stat%ok
  end subroutine largest_tridiagonal_eigenvalue

  !> The largest eigenvalue of the symmetric tridiagonal matrix with diagonal
  !> `diag` (n >= 1) and off-diagonal `off` (n - 1) and a unit eigenvector
  !> (size n), by dstevr (that one eigenpair: O(n) work). Status
  !> `lapack_failure` with LAPACK's info explained.
  pure subroutine largest_tridiagonal_eigenpair(diag, off, eigenvalue, vector, status)
    real(dp), intent(in) :: diag(:), off(:)
    real(dp), intent(out) :: eigenvalue
    real(dp), intent(out) :: vector(:)
    type(demstep_status_type), intent(out) :: status
    real(dp), allocatable :: d(:), e(:), work(:), w(:)
    integer, allocatable :: iwork(:), isuppz(:)
    integer :: n, m, info
    n = size(diag)
    eigenvalue = 0.0_dp
    vector = 0.0_dp
    if (n < 1 .or. size(off) < n - 1 .or. size(vector) /= n) then
      call set_status(status, demstep_stat%invalid_input, "need n >= 1 diagonal, n - 1 " &
        //"off-diagonal and n vector entries", where="largest_tridiagonal_eigenpair")
      return
    end if
    d = diag
    ! (w of size n as dstevr declares it, though one eigenvalue is asked)
    allocate(e(n), w(n), isuppz(2*n), work(20*n), iwork(10*n))
    e = 0.0_dp
    if (n > 1) e(:n - 1) = off(:n - 1)
    call dstevr("V", "I", n, d, e, 0.0_dp, 0.0_dp, n, n, 0.0_dp, m, w, vector, n, isuppz, work, &
      size(work), iwork, size(iwork), info)
    if (info /= 0 .or. m /= 1) then
      call set_status(status, demstep_stat%lapack_failure, info_message(info, "dstevr"))
      return
    end if
    eigenvalue = w(1)
    status%stat = demstep_stat%ok
  end subroutine largest_tridiagonal_eigenpair

  !> The largest eigenvalue of the complex Hermitian matrix `a` (its lower
  !> triangle is used and destroyed), by zheev (eigenvalues only). Status
  !> `lapack_failure` with LAPACK's info explained.
  subroutine largest_hermitian_eigenvalue(a, eigenvalue, status)
    !> n-by-n Hermitian matrix; destroyed.
    complex(dp), intent(inout) :: a(:, :)
    real(dp), intent(out) :: eigenvalue
    type(demstep_status_type), intent(out) :: status
    complex(dp), allocatable :: work(:)
    complex(dp) :: work_query(1)
    real(dp), allocatable :: w(:), rwork(:)
    integer :: n, info
    n = size(a, 1)
    eigenvalue = 0.0_dp
    if (n < 1 .or. size(a, 2) /= n) then
      call set_status(status, demstep_stat%invalid_input, "need " &
        //"an n-by-n matrix, n >= 1", where="largest_hermitian_eigenvalue")
      return
    end if
    allocate(w(n), rwork(max(1, 3*n - 2)))
    call zheev("N", "L", n, a, n, w, work_query, -1, rwork, info)
    if (info == 0) then
      allocate(work(max(1, int(real(work_query(1), dp)))))
      call zheev("N", "L", n, a, n, w, work, size(work), rwork, info)
    end if
    if (info /= 0) then
      call set_status(status, demstep_stat%lapack_failure, info_message(info, "zheev"))
      return
    end if
    eigenvalue = w(n)
    status%stat = demstep_stat%ok
  end subroutine largest_hermitian_eigenvalue

  !> The largest eigenvalue of the symmetric matrix `a` (its lower triangle is
  !> used and overwritten) and a unit eigenvector, by dsyevr with an index range.
  !> The top two are asked for: with only the top index, dsyevr returns nothing
  !> when the largest eigenvalue is double (a ring of odd length, say).
  !> Status `lapack_failure` with LAPACK's info explained.
  subroutine largest_eigenpair(a, eigenvalue, eigenvector, status)
    !> n-by-n symmetric matrix; destroyed.
    real(dp), intent(inout) :: a(:, :)
    real(dp), intent(out) :: eigenvalue
    !> Unit eigenvector (size n).
    real(dp), intent(out) :: eigenvector(:)
    type(demstep_status_type), intent(out) :: status
    integer :: n, m, info, lwork, liwork, iwork_query(1), il
    real(dp) :: work_query(1)
    ! dsyevr uses all n entries of w, whatever the range asked for
    real(dp), allocatable :: work(:), z(:, :), w(:)
    integer, allocatable :: iwork(:)
    integer :: isuppz(4)
    n = size(a, 1)
    eigenvalue = 0.0_dp
    eigenvector = 0.0_dp
    if (n < 1 .or. size(a, 2) /= n .or. size(eigenvector) /= n) then
      call set_status(status, demstep_stat%invalid_input, "need an n-by-n " &
        //"matrix, n >= 1, and an eigenvector of size n", where="largest_eigenpair")
      return
    end if
    il = max(1, n - 1)
    allocate(z(n, 2), w(n))
    ! workspace query
    call dsyevr("V", "I", "L", n, a, n, 0.0_dp, 0.0_dp, il, n, 0.0_dp, m, w, z, n, isuppz, &
      work_query, -1, iwork_query, -1, info)
    if (info /= 0) then
      call set_status(status, demstep_stat%lapack_failure, info_message(info))
      return
    end if
    lwork = max(1, int(work_query(1)))
    liwork = max(1, iwork_query(1))
    allocate(work(lwork), iwork(liwork))
    call dsyevr("V", "I", "L", n, a, n, 0.0_dp, 0.0_dp, il, n, 0.0_dp, m, w, z, n, isuppz, &
      work, lwork, iwork, liwork, info)
    if (info /= 0) then
      call set_status(status, demstep_stat%lapack_failure, info_message(info))
      return
    end if
    if (m /= n - il + 1) then
      call set_status(status, demstep_stat%lapack_failure, "dsyevr returned too few eigenvalues")
      return
    end if
    ! ascending order: the largest is the last
    eigenvalue = w(m)
    eigenvector = z(:, m)
    status%stat = demstep_stat%ok
  end subroutine largest_eigenpair

  !> Every eigenvalue of the symmetric matrix `a` (its lower triangle is used
  !> and overwritten), ascending, and orthonormal eigenvectors (columns of z),
  !> by dsyevr. Status `lapack_failure` with LAPACK's info explained.
  subroutine symmetric_eigensystem(a, w, z, status)
    !> n-by-n symmetric matrix; destroyed.
    real(dp), intent(inout) :: a(:, :)
    !> Eigenvalues (size n), ascending, and eigenvectors (n, n).
    real(dp), intent(out) :: w(:), z(:, :)
    type(demstep_status_type), intent(out) :: status
    integer :: n, m, info, iwork_query(1)
    real(dp) :: work_query(1)
    real(dp), allocatable :: work(:)
    integer, allocatable :: iwork(:), isuppz(:)
    n = size(a, 1)
    w = 0.0_dp
    z = 0.0_dp
    if (n < 1 .or. size(a, 2) /= n .or. size(w) /= n .or. size(z, 1) /= n .or. size(z, 2) /= n) then
      call set_status(status, demstep_stat%invalid_input, "need an n-by-n " &
        //"matrix, n >= 1, n eigenvalues and n-by-n eigenvectors", where="symmetric_eigensystem")
      return
    end if
    allocate(isuppz(2*n))
    call dsyevr("V", "A", "L", n, a, n, 0.0_dp, 0.0_dp, 1, n, 0.0_dp, m, w, z, n, isuppz, &
      work_query, -1, iwork_query, -1, info)
    if (info == 0) then
      allocate(work(max(1, int(work_query(1)))), iwork(max(1, iwork_query(1))))
      call dsyevr("V", "A", "L", n, a, n, 0.0_dp, 0.0_dp, 1, n, 0.0_dp, m, w, z, n, isuppz, &
        work, size(work), iwork, size(iwork), info)
    end if
    if (info /= 0) then
      call set_status(status, demstep_stat%lapack_failure, info_message(info))
      return
    end if
    if (m /= n) then
      call set_status(status, demstep_stat%lapack_failure, "dsyevr returned too few eigenvalues")
      return
    end if
    status%stat = demstep_stat%ok
  end subroutine symmetric_eigensystem

  !> The spectral radius max |z| of the general n-by-n matrix `a` (destroyed),
  !> by dgeev (eigenvalues only). Status `lapack_failure` with LAPACK's info
  !> explained.
  subroutine spectral_radius(a, rho, status)
    real(dp), intent(inout) :: a(:, :)
    real(dp), intent(out) :: rho
    type(demstep_status_type), intent(out) :: status
    real(dp), allocatable :: wr(:), wi(:), work(:)
    real(dp) :: vl(1, 1), vr(1, 1), work_query(1)
    integer :: n, info
    n = size(a, 1)
    rho = 0.0_dp
    if (n < 1 .or. size(a, 2) /= n) then
      call set_status(status, demstep_stat%invalid_input, "need an n-by-n matrix, n >= 1", where="spectral_radius")
      return
    end if
    allocate(wr(n), wi(n))
    call dgeev("N", "N", n, a, n, wr, wi, vl, 1, vr, 1, work_query, -1, info)
    if (info == 0) then
      allocate(work(max(1, int(work_query(1)))))
      call dgeev("N", "N", n, a, n, wr, wi, vl, 1, vr, 1, work, size(work), info)
    end if
    if (info /= 0) then
      call set_status(status, demstep_stat%lapack_failure, info_message(info, "dgeev"))
      return
    end if
    rho = maxval(hypot(wr, wi))
    status%stat = demstep_stat%ok
  end subroutine spectral_radius

  !> The Cholesky factor L L' of the symmetric positive definite n-by-n
  !> matrix `a` (its lower triangle is used and overwritten by L), by dpotrf.
  !> Status `lapack_failure` when it is not positive definite (to rounding).
  pure subroutine cholesky_factor(a, status)
    real(dp), intent(inout) :: a(:, :)
    type(demstep_status_type), intent(out) :: status
    integer :: n, info
    n = size(a, 1)
    if (n < 1 .or. size(a, 2) /= n) then
      call set_status(status, demstep_stat%invalid_input, "need an n-by-n matrix, n >= 1", where="cholesky_factor")
      return
    end if
    call dpotrf("L", n, a, n, info)
    if (info > 0) then
      call set_status(status, demstep_stat%lapack_failure, "dpotrf: the matrix is not positive definite")
      return
    else if (info < 0) then
      call set_status(status, demstep_stat%lapack_failure, info_message(info, "dpotrf"))
      return
    end if
    status%stat = demstep_stat%ok
  end subroutine cholesky_factor

  !> Solves L L' x = b in place (b: size n) with the factor of `cholesky_factor`.
  pure subroutine cholesky_solve(factor, b, status)
    real(dp), intent(in) :: factor(:, :)
    real(dp), intent(inout) :: b(:)
    type(demstep_status_type), intent(out) :: status
    integer :: n, info
    n = size(factor, 1)
    if (n < 1 .or. size(factor, 2) /= n .or. size(b) /= n) then
      call set_status(status, demstep_stat%invalid_input, "need an n-by-n factor and b of size n", &
        where="cholesky_solve")
      return
    end if
    call dpotrs("L", n, 1, factor, n, b, n, info)
    if (info /= 0) then
      call set_status(status, demstep_stat%lapack_failure, info_message(info, "dpotrs"))
      return
    end if
    status%stat = demstep_stat%ok
  end subroutine cholesky_solve

  !> A LAPACK routine's info as words.
  pure function info_message(info, routine) result(message)
    integer, intent(in) :: info
    !> The routine's name (default dsyevr).
    character(len=*), intent(in), optional :: routine
    character(len=:), allocatable :: message, name
    character(len=16) :: buf
    name = "dsyevr"
    if (present(routine)) name = routine
    write(buf, '(i0)') abs(info)
    if (info < 0) then
      message = name//": argument "//trim(buf)//" had an illegal value"
    else
      message = name//": internal error "//trim(buf)//" (the eigenvalue computation did not converge)"
    end if
  end function info_message

end module demstep_lapack
