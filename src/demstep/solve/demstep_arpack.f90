!> ARPACK through explicit interfaces, in one place, with every `info` code
!> turned into a status and a message. Only what demstep needs: the symmetric
!> implicitly restarted Lanczos iteration (`dsaupd`, reverse communication) and
!> its post-processing (`dseupd`), in double precision with default integers
!> (the Debian `libarpack2` build).
!>
!> ARPACK keeps its state in SAVEd variables: one iteration at a time per
!> process (never two interleaved, never from two threads at once).
module demstep_arpack
  use demstep_kinds, only: dp
  use demstep_status, only: demstep_status_type, demstep_stat, set_status
  use demstep_text, only: int_text
  implicit none
  private

  public :: dsaupd, dseupd, dsaupd_status, dseupd_status

  !> The length of `iparam` and `ipntr` for dsaupd and dseupd.
  integer, parameter, public :: arpack_iparam_size = 11

  interface
    !> ARPACK dsaupd: one step of the implicitly restarted Lanczos iteration for
    !> a few eigenpairs of a symmetric operator, by reverse communication
    !> (`ido` asks the caller for y = OP x on `workd`).
    subroutine dsaupd(ido, bmat, n, which, nev, tol, resid, ncv, v, ldv, iparam, ipntr, &
        workd, workl, lworkl, info)
      import :: dp
      integer, intent(inout) :: ido
      character(len=1), intent(in) :: bmat
      integer, intent(in) :: n
      character(len=2), intent(in) :: which
      integer, intent(in) :: nev
      ! a tolerance <= 0 is replaced by the machine epsilon
      real(dp), intent(inout) :: tol
      real(dp), intent(inout) :: resid(*)
      integer, intent(in) :: ncv, ldv
      real(dp), intent(inout) :: v(ldv, *)
      integer, intent(inout) :: iparam(*)
      integer, intent(inout) :: ipntr(*)
      real(dp), intent(inout) :: workd(*)
      real(dp), intent(inout) :: workl(*)
      integer, intent(in) :: lworkl
      integer, intent(inout) :: info
    end subroutine dsaupd
    !> ARPACK dseupd: the converged Ritz values (and vectors) of the factorization
    !> that dsaupd has just finished; the arguments from `bmat` on are dsaupd's.
    subroutine dseupd(rvec, howmny, select, d, z, ldz, sigma, bmat, n, which, nev, tol, &
        resid, ncv, v, ldv, iparam, ipntr, workd, workl, lworkl, info)
      import :: dp
      logical, intent(in) :: rvec
      character(len=1), intent(in) :: howmny
      logical, intent(inout) :: select(*)
      real(dp), intent(out) :: d(*)
      integer, intent(in) :: ldz
      real(dp), intent(inout) :: z(ldz, *)
      real(dp), intent(in) :: sigma
      character(len=1), intent(in) :: bmat
      integer, intent(in) :: n
      character(len=2), intent(in) :: which
      integer, intent(in) :: nev
      real(dp), intent(in) :: tol
      real(dp), intent(inout) :: resid(*)
      integer, intent(in) :: ncv, ldv
      real(dp), intent(inout) :: v(ldv, *)
      integer, intent(inout) :: iparam(*)
      integer, intent(inout) :: ipntr(*)
      real(dp), intent(inout) :: workd(*)
      real(dp), intent(inout) :: workl(*)
      integer, intent(in) :: lworkl
      integer, intent(out) :: info
    end subroutine dseupd
  end interface

contains

  !> dsaupd's final `info` as a status: `ok` for a normal exit, `not_converged`
  !> when the iteration stopped short of its tolerance (1, 3), `invalid_input`
  !> for an argument ARPACK rejects, `lapack_failure` when LAPACK's dsteqr failed
  !> inside it (-8), `eigensolver_failure` when no Lanczos factorization could be
  !> built (-9999) or the code is not one ARPACK documents.
  pure function dsaupd_status(info) result(status)
    !> dsaupd's `info` on its last return (`ido = 99`).
    integer, intent(in) :: info
    type(demstep_status_type) :: status
    character(len=*), parameter :: who = "ARPACK dsaupd: "
    select case (info)
    case (0)
      status%stat = demstep_stat%ok
    case (1)
      call set_status(status, demstep_stat%not_converged, who//"the maximum number of " &
        //"restarts was taken before the Ritz value met its tolerance")
    case (2)
      ! deprecated since ARPACK 2: dsaupd itself turns it into 3
      call set_status(status, demstep_stat%not_converged, who//"no shifts could be " &
        //"applied (info 2, deprecated)")
    case (3)
      call set_status(status, demstep_stat%not_converged, who//"no shifts could be " &
        //"applied during a restart; a larger Krylov size (ncv) may help")
    case (-4)
      call set_status(status, demstep_stat%invalid_input, who//"the maximum number of " &
        //"restarts must be positive")
    case (-12)
      call set_status(status, demstep_stat%invalid_input, who//"the shift choice iparam(1) " &
        //"must be 0 or 1")
    case (-13)
      call set_status(status, demstep_stat%invalid_input, who//"which = 'BE' needs nev > 1")
    case (-9999)
      call set_status(status, demstep_stat%eigensolver_failure, who//"no Lanczos " &
        //"factorization could be built")
    case default
      status = shared_info_status(who, info)
    end select
  end function dsaupd_status

  !> dseupd's `info` as a status: `ok`, `invalid_input` for an argument ARPACK
  !> rejects, `lapack_failure` for dsteqr (-8), `not_converged` when nothing met
  !> the tolerance (-14), `eigensolver_failure` when dsaupd's data was changed
  !> between the calls (-17) or for a code ARPACK does not document.
  pure function dseupd_status(info) result(status)
    !> dseupd's `info`.
    integer, intent(in) :: info
    type(demstep_status_type) :: status
    character(len=*), parameter :: who = "ARPACK dseupd: "
    select case (info)
    case (0)
      status%stat = demstep_stat%ok
    case (-12)
      call set_status(status, demstep_stat%invalid_input, who//"which = 'BE' needs nev > 1")
    case (-14)
      call set_status(status, demstep_stat%not_converged, who//"dsaupd found no eigenvalue " &
        //"to its tolerance")
    case (-15)
      call set_status(status, demstep_stat%invalid_input, who//"howmny must be 'A' or 'S' " &
        //"when Ritz vectors are wanted")
    case (-16)
      call set_status(status, demstep_stat%invalid_input, who//"howmny = 'S' is not implemented")
    case (-17)
      call set_status(status, demstep_stat%eigensolver_failure, who//"it counted a different " &
        //"number of converged Ritz values than dsaupd (dsaupd's data was changed between " &
        //"the calls)")
    case default
      status = shared_info_status(who, info)
    end select
  end function dseupd_status

  !> The `info` codes dsaupd and dseupd share (-1 to -11 but -4, one meaning
  !> each), and any other as an undocumented code.
  pure function shared_info_status(who, info) result(status)
    character(len=*), intent(in) :: who
    integer, intent(in) :: info
    type(demstep_status_type) :: status
    select case (info)
    case (-1)
      call set_status(status, demstep_stat%invalid_input, who//"the dimension n must be positive")
    case (-2)
      call set_status(status, demstep_stat%invalid_input, who//"the number of wanted " &
        //"eigenvalues (nev) must be positive")
    case (-3)
      call set_status(status, demstep_stat%invalid_input, who//"the Krylov size ncv must " &
        //"be greater than nev and at most n")
    case (-5)
      call set_status(status, demstep_stat%invalid_input, who//"which must be one of " &
        //"'LM', 'SM', 'LA', 'SA', 'BE'")
    case (-6)
      call set_status(status, demstep_stat%invalid_input, who//"bmat must be 'I' or 'G'")
    case (-7)
      call set_status(status, demstep_stat%invalid_input, who//"the work array workl is " &
        //"shorter than ncv**2 + 8*ncv")
    case (-8)
      call set_status(status, demstep_stat%lapack_failure, who//"LAPACK dsteqr failed on " &
        //"the tridiagonal eigenvalue problem")
    case (-9)
      call set_status(status, demstep_stat%invalid_input, who//"the starting vector is zero")
    case (-10)
      call set_status(status, demstep_stat%invalid_input, who//"the mode iparam(7) must be " &
        //"1 to 5")
    case (-11)
      call set_status(status, demstep_stat%invalid_input, who//"mode 1 and bmat = 'G' are " &
        //"incompatible")
    case default
      call set_status(status, demstep_stat%eigensolver_failure, who//"undocumented info " &
        //int_text(info))
    end select
  end function shared_info_status

end module demstep_arpack
