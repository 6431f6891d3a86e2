!> The rigid-body (clump) table: which particles move together.
!>
!> One row per clump member, two integers: the particle's number (1..n, as in
!> the particle table or arrays) and its body's id (a positive integer; the
!> ids need not be consecutive: Yade's clump ids do). Particles not listed
!> move on their own. `#` starts a
!> comment, blank lines are skipped (the layout of `read_table`). A particle may be listed once: a second row for it (in
!> the same body or another) is refused naming both lines.
!>
!> ```text
!> # particle  body
!> 1  1
!> 2  1
!> 3  2
!> 4  2
!> ```
module demstep_body_table
  use demstep_kinds, only: dp
  use demstep_status, only: demstep_status_type, demstep_stat, set_status
  use demstep_text, only: int_text
  use demstep_table_io, only: read_table
  implicit none
  private

  public :: read_body_table

contains

  !> The body id of each of n particles from a body table (0: not listed, the
  !> particle moves alone), for `bodies_from_members`. Status io_error or
  !> invalid_input with the message `path: line L: what` (a row of the wrong
  !> form, a particle number above n, a particle listed twice).
  subroutine read_body_table(path, n, body_of, status)
    character(len=*), intent(in) :: path
    !> Number of particles.
    integer, intent(in) :: n
    integer, allocatable, intent(out) :: body_of(:)
    type(demstep_status_type), intent(out) :: status
    real(dp), allocatable :: rows(:, :)
    integer, allocatable :: lines(:), line_of(:)
    integer :: k, p, b
    allocate(body_of(max(n, 0)), source=0)
    call read_table(path, 2, rows, status, lines=lines, index_columns=[1, 2])
    if (status%stat /= demstep_stat%ok) return
    allocate(line_of(max(n, 0)), source=0)
    do k = 1, size(rows, 2)
      p = nint(rows(1, k))
      b = nint(rows(2, k))
      if (p > n) then
        call set_status(status, demstep_stat%invalid_input, path//": line "//int_text(lines(k)) &
          //": column 1: particle "//int_text(p)//" does not exist (1 to "//int_text(n)//")")
        return
      end if
      if (body_of(p) /= 0) then
        call set_status(status, demstep_stat%invalid_input, path//": line "//int_text(lines(k)) &
          //": particle "//int_text(p)//" is already in body "//int_text(body_of(p))//" (line " &
          //int_text(line_of(p))//"): a particle belongs to one body")
        return
      end if
      body_of(p) = b
      line_of(p) = lines(k)
    end do
    if (size(rows, 2) == 0) call set_status(status, demstep_stat%invalid_input, path//": no rows " &
      //"(particle body)")
  end subroutine read_body_table

end module demstep_body_table
