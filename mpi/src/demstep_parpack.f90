!> PARPACK (the MPI build of ARPACK) through explicit interfaces, in one place:
!> `pdsaupd` and `pdseupd`, the distributed symmetric Lanczos iteration and its
!> post-processing (double precision, default integers, Debian `libparpack2`).
!> Each rank holds a contiguous block of every vector; PARPACK reduces the
!> inner products over the communicator.
!>
!> The `info` codes are ARPACK's own (PARPACK shares dsaupd/dseupd's tables):
!> the statuses reuse `dsaupd_status`/`dseupd_status` with PARPACK's name.
module demstep_parpack
  use demstep_kinds, only: dp
  use demstep_status, only: demstep_status_type
  use demstep_arpack, only: dsaupd_status, dseupd_status
  implicit none
  private

  public :: pdsaupd, pdseupd, pdsaupd_status, pdseupd_status

  interface
    !> PARPACK pdsaupd: dsaupd on a distributed vector of local length `n`;
    !> `comm` is the MPI communicator's Fortran handle (`comm%MPI_VAL`).
    subroutine pdsaupd(comm, ido, bmat, n, which, nev, tol, resid, ncv, v, ldv, iparam, &
        ipntr, workd, workl, lworkl, info)
      import :: dp
      integer, intent(in) :: comm
      integer, intent(inout) :: ido
      character(len=1), intent(in) :: bmat
      integer, intent(in) :: n
      character(len=2), intent(in) :: which
      integer, intent(in) :: nev
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
    end subroutine pdsaupd
    !> PARPACK pdseupd: dseupd on the distributed factorization pdsaupd finished.
    subroutine pdseupd(comm, rvec, howmny, select, d, z, ldz, sigma, bmat, n, which, nev, &
        tol, resid, ncv, v, ldv, iparam, ipntr, workd, workl, lworkl, info)
      import :: dp
      integer, intent(in) :: comm
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
    end subroutine pdseupd
  end interface

contains

  !> pdsaupd's final `info` as a status: `dsaupd_status`'s code and message,
  !> named after PARPACK.
  pure function pdsaupd_status(info) result(status)
    !> pdsaupd's `info` on its last return.
    integer, intent(in) :: info
    type(demstep_status_type) :: status
    status = renamed(dsaupd_status(info), "ARPACK dsaupd: ", "PARPACK pdsaupd: ")
  end function pdsaupd_status

  !> pdseupd's `info` as a status: `dseupd_status`'s code and message, named
  !> after PARPACK.
  pure function pdseupd_status(info) result(status)
    !> pdseupd's `info`.
    integer, intent(in) :: info
    type(demstep_status_type) :: status
    status = renamed(dseupd_status(info), "ARPACK dseupd: ", "PARPACK pdseupd: ")
  end function pdseupd_status

  !> The status with its message's leading `from` replaced by `to`.
  pure function renamed(status, from, to) result(out)
    type(demstep_status_type), intent(in) :: status
    character(len=*), intent(in) :: from, to
    type(demstep_status_type) :: out
    out = status
    if (.not. allocated(status%message)) return
    if (index(status%message, from) == 1) out%message = to//status%message(len(from) + 1:)
  end function renamed

end module demstep_parpack
