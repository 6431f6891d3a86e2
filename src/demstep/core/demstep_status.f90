!> Status reporting: a code from a named set, the location of the fault and a message.
!>
!> Every library call that can fail takes an `intent(out)` argument of
!> `demstep_status_type`; the library never stops the program. The location
!> (`where`: the argument or field to change, `index`: its element or row, 0
!> for none) is a component, so callers map it without reading the message.
module demstep_status
  implicit none
  private

  !> The named status codes, as components of a parameter: `demstep_stat%invalid_input`.
  type, public :: demstep_stat_enum
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
    !> The resource is in use by another thread (ARPACK's SAVEd state: one
    !> Lanczos solve per process at a time); call again when it is done.
    integer :: busy = 12
  end type demstep_stat_enum

  !> The status codes by name.
  type(demstep_stat_enum), parameter, public :: demstep_stat = demstep_stat_enum()

  !> Status of a library call: `stat == demstep_stat%ok` on success, else a message.
  type, public :: demstep_status_type
    !> One of the codes of `demstep_stat`.
    integer :: stat = 0
    !> The whole message, `where: detail` when a location is known; unallocated
    !> on success.
    character(len=:), allocatable :: message
    !> The argument or field to change (blank when the fault has no single one).
    character(len=:), allocatable :: where
    !> The element, row or item of `where` (1-based), 0 when none applies.
    integer :: index = 0
    !> What is wrong with it, without the location.
    character(len=:), allocatable :: detail
  end type demstep_status_type

  public :: set_status, is_ok, status_at, status_restate

contains

  !> Set a status code, its location and message. With `where`, the message
  !> becomes `where: detail` (the detail names the element where one applies),
  !> or `where(index): detail` with `subscript` (a deck's subscripted keyword).
  pure subroutine set_status(status, stat, message, where, index, subscript)
    !> Status to set.
    type(demstep_status_type), intent(out) :: status
    !> Code from `demstep_stat`.
    integer, intent(in) :: stat
    !> What is wrong (the whole message when `where` is absent).
    character(len=*), intent(in) :: message
    !> The argument or field to change.
    character(len=*), intent(in), optional :: where
    !> Its element or row (1-based).
    integer, intent(in), optional :: index
    !> Write the location as `where(index)` (when index > 0).
    logical, intent(in), optional :: subscript
    character(len=24) :: buf
    status%stat = stat
    status%detail = message
    status%where = ""
    if (present(where)) status%where = where
    if (present(index)) status%index = index
    if (len(status%where) > 0) then
      status%message = status%where//": "//message
      if (present(subscript)) then
        if (subscript .and. status%index > 0) then
          write(buf, '(i0)') status%index
          status%message = status%where//"("//trim(buf)//"): "//message
        end if
      end if
    else
      status%message = message
    end if
  end subroutine set_status

  !> Put a failed status at another location: the caller's `where`, the old
  !> message (after `lead`, if given) as its detail; the message becomes
  !> `where: lead old-message`. A successful status is left alone.
  pure subroutine status_at(status, where, lead)
    !> The status, relabelled.
    type(demstep_status_type), intent(inout) :: status
    !> The argument or field the caller's user gave.
    character(len=*), intent(in) :: where
    !> Words put before the old message.
    character(len=*), intent(in), optional :: lead
    character(len=:), allocatable :: detail
    if (status%stat == demstep_stat%ok) return
    detail = ""
    if (allocated(status%message)) detail = status%message
    if (present(lead)) detail = lead//detail
    status%where = where
    status%index = 0
    status%detail = detail
    status%message = where//": "//detail
  end subroutine status_at

  !> Restate a failed status: its location `where` (blank for none) and `detail`;
  !> the code and index are kept, the message becomes `where: detail`. Pass
  !> copies, not the status's own components.
  pure subroutine status_restate(status, where, detail)
    !> The status, restated.
    type(demstep_status_type), intent(inout) :: status
    !> The new location.
    character(len=*), intent(in) :: where
    !> What is wrong, without the location.
    character(len=*), intent(in) :: detail
    status%where = where
    status%detail = detail
    if (len(where) > 0) then
      status%message = where//": "//detail
    else
      status%message = detail
    end if
  end subroutine status_restate

  !> True when the status reports success.
  elemental function is_ok(status) result(ok)
    !> Status to test.
    type(demstep_status_type), intent(in) :: status
    logical :: ok
    ok = status%stat == demstep_stat%ok
  end function is_ok

end module demstep_status
