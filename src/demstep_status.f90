!> Status reporting: a code from a named set plus a message.
!>
!> Every library call that can fail takes an `intent(out)` argument of
!> `demstep_status_type`; the library never stops the program.
module demstep_status
  implicit none
  private

  !> The named status codes, as components of a parameter: `demstep_stat%invalid_input`.
  type, public :: demstep_stat_codes
    !> Success.
    integer :: ok = 0
    !> An argument is out of its domain (non-positive mass, NaN, ...).
    integer :: invalid_input = 1
    !> The time step is at or beyond the stability limit.
    integer :: unstable = 2
    !> A denominator vanished: the function cannot be evaluated there (a pole).
    integer :: pole = 3
    !> An iteration did not reach its tolerance.
    integer :: not_converged = 4
    !> Nothing satisfies the request (no root, no admissible value).
    integer :: not_found = 5
    !> A LAPACK routine reported failure.
    integer :: lapack_failure = 6
    !> Reading or writing a file failed.
    integer :: io_error = 7
    !> A simulated value grew without bound.
    integer :: blow_up = 8
    !> The tolerance already holds at the stability limit: the answer is the
    !> limit itself (a scan of E whose first admissible N is where it starts).
    integer :: at_stability_limit = 9
    !> A sign change or a pick lies on a jump or a pole, not a root: the value
    !> returned is where the function jumps.
    integer :: discontinuous = 10
    !> The iterative eigensolver (ARPACK) failed: no Lanczos factorization could
    !> be built, or its data was inconsistent.
    integer :: eigensolver_failure = 11
  end type demstep_stat_codes

  !> The status codes by name.
  type(demstep_stat_codes), parameter, public :: demstep_stat = demstep_stat_codes()

  !> Status of a library call: `stat == demstep_stat%ok` on success, else a message.
  type, public :: demstep_status_type
    !> One of the codes of `demstep_stat`.
    integer :: stat = 0
    !> What went wrong; unallocated on success.
    character(len=:), allocatable :: message
  end type demstep_status_type

  public :: set_status, is_ok

contains

  !> Set a status code and message.
  pure subroutine set_status(status, stat, message)
    !> Status to set.
    type(demstep_status_type), intent(out) :: status
    !> Code from `demstep_stat`.
    integer, intent(in) :: stat
    !> Explanation, naming the offending argument.
    character(len=*), intent(in) :: message
    status%stat = stat
    status%message = message
  end subroutine set_status

  !> True when the status reports success.
  elemental function is_ok(status) result(ok)
    !> Status to test.
    type(demstep_status_type), intent(in) :: status
    logical :: ok
    ok = status%stat == demstep_stat%ok
  end function is_ok

end module demstep_status
