!> Reading a table file in parts on MPI ranks, and the collective agreements
!> on a refusal that the distributed readers and drivers share.
!>
!> Reading. The file is cut into one byte range per rank at line starts
!> (rank r's range starts at the first line start at or after byte r S/P of
!> a file of S bytes; a line starts after a line feed, or after a carriage
!> return not followed by a line feed, as `read_table` counts lines). Each
!> rank reads only its range (one stream read) and parses it with the serial
!> reader's two passes (`table_scan`, `table_rows`); the file lines before
!> the range are summed over the ranks before it (`MPI_Exscan`). A rank holds
!> its range's text and rows, never the whole table.
!>
!> Refusals. Every rank checks its part; the refusal reported is the one the
!> serial reader reports (the first in file order, pass 1 before pass 2),
!> chosen by the smallest key (a file line, a particle number) over the
!> ranks and sent from the rank holding it to all (`agree_status`): every
!> rank returns the same status.
module demstep_mpi_parts
  use mpi_f08
  use demstep_kinds, only: dp, i8
  use demstep_status, only: demstep_status_type, demstep_stat, set_status
  use demstep_table_io, only: table_scan, table_rows, table_scan_type
  implicit none
  private

  public :: read_table_part, agree_status, broadcast_status

  !> The key of "no refusal here".
  integer(i8), parameter, public :: no_fault = huge(1_i8)

  !> Bytes read at a time while looking for a line start.
  integer, parameter :: window = 65536
  integer, parameter :: lf = 10, cr = 13

contains

  !> This rank's part of a table file (see the module's notes): its rows in
  !> file order with their file lines, the global number of its first row
  !> less one (`row_offset`) and the table's rows in all (`n_total`). The
  !> layout is the whole file's (its first row of an allowed count).
  !> Statuses as `read_table`'s (the message names the file and the line),
  !> the same on every rank. Collective.
  subroutine read_table_part(comm, path, allowed, rows, lines, row_offset, n_total, status, &
      index_columns)
    type(MPI_Comm), intent(in) :: comm
    !> File name.
    character(len=*), intent(in) :: path
    !> The column counts a row may have (each >= 1).
    integer, intent(in) :: allowed(:)
    real(dp), allocatable, intent(out) :: rows(:, :)
    integer, allocatable, intent(out) :: lines(:)
    integer(i8), intent(out) :: row_offset, n_total
    type(demstep_status_type), intent(out) :: status
    !> Columns of particle numbers: integers in [1, huge(1)].
    integer, intent(in), optional :: index_columns(:)
    character(len=:), allocatable :: text
    type(table_scan_type) :: scan
    integer(i8), allocatable :: starts(:)
    integer(i8) :: size_bytes, first, mine(2), counts(2), sizes(2)
    integer :: nranks, rank, fault, line_offset, r, layout(2), ios
    logical :: exists

    call MPI_Comm_size(comm, nranks)
    call MPI_Comm_rank(comm, rank)
    row_offset = 0
    n_total = 0
    allocate(rows(maxval(allowed), 0), lines(0))
    inquire(file=path, exist=exists, size=size_bytes)
    ! every rank must see the file, the same size: otherwise all refuse it
    ! (a rank returning alone would leave the others waiting)
    if (.not. agreed(exists)) then
      call set_status(status, demstep_stat%io_error, path//": no such file")
      return
    end if
    if (.not. agreed(size_bytes >= 0)) then
      call set_status(status, demstep_stat%io_error, path//": its size is unknown (not a regular file?): " &
        //"it cannot be read in parts")
      return
    end if
    call MPI_Allreduce(size_bytes, sizes(1), 1, MPI_INTEGER8, MPI_MIN, comm)
    call MPI_Allreduce(size_bytes, sizes(2), 1, MPI_INTEGER8, MPI_MAX, comm)
    if (sizes(1) /= sizes(2)) then
      call set_status(status, demstep_stat%io_error, path//": the ranks see files of different sizes")
      return
    end if
    ! the ranges: every rank finds its start, all learn all starts
    first = 1
    ios = 0
    if (rank > 0) call line_start(path, int(rank, i8)*max(size_bytes, 0_i8)/nranks + 1, &
      size_bytes, first, ios)
    if (.not. agreed(ios == 0)) then
      call set_status(status, demstep_stat%io_error, path//": cannot read")
      return
    end if
    allocate(starts(0:nranks))
    call MPI_Allgather(first, 1, MPI_INTEGER8, starts, 1, MPI_INTEGER8, comm)
    starts(nranks) = max(size_bytes, 0_i8) + 1
    call read_range(path, starts(rank), starts(rank + 1) - 1, text, ios)
    if (.not. agreed(ios == 0)) then
      call set_status(status, demstep_stat%io_error, path//": cannot read")
      return
    end if

    ! pass 1 with the lines before this range counted
    call table_scan(text, path, allowed, scan, status, fault_line=fault)
    line_offset = 0
    call MPI_Exscan(scan%n_lines, line_offset, 1, MPI_INTEGER, MPI_SUM, comm)
    if (rank == 0) line_offset = 0
    if (status%stat /= demstep_stat%ok) then
      ! again with the right line numbers in the message
      call table_scan(text, path, allowed, scan, status, line_offset=line_offset, fault_line=fault)
    else
      scan%row_line(:scan%n_rows) = scan%row_line(:scan%n_rows) + line_offset
      if (scan%ncol > 0 .and. scan%n_rows > 0) scan%first_line = scan%first_line + line_offset
    end if
    call agree_status(comm, status, key(fault))
    if (status%stat /= demstep_stat%ok) return

    ! the layout: the first rank's (in rank order) that found one; the
    ! widest for an empty table, none (refused at the first row) otherwise
    mine = [int(scan%n_rows, i8), 0_i8]
    call MPI_Allreduce(mine, counts, 2, MPI_INTEGER8, MPI_SUM, comm)
    n_total = counts(1)
    r = huge(1)
    if (scan%n_rows > 0 .and. scan%ncol > 0) r = rank
    call MPI_Allreduce(MPI_IN_PLACE, r, 1, MPI_INTEGER, MPI_MIN, comm)
    if (r < nranks) then
      layout = [scan%ncol, scan%first_line]
      call MPI_Bcast(layout, 2, MPI_INTEGER, r, comm)
    else if (n_total == 0) then
      layout = [maxval(allowed), 0]
    else
      layout = 0
    end if
    scan%ncol = layout(1)
    scan%first_line = layout(2)
    row_offset = 0
    call MPI_Exscan(int(scan%n_rows, i8), row_offset, 1, MPI_INTEGER8, MPI_SUM, comm)
    if (rank == 0) row_offset = 0

    ! pass 2
    deallocate(rows, lines)
    call table_rows(text, path, allowed, scan, rows, status, lines, index_columns, fault)
    call agree_status(comm, status, key(fault))

  contains

    !> The agreement key of a refusal at file line `line` (none: no_fault).
    integer(i8) function key(line)
      integer, intent(in) :: line
      key = no_fault
      if (status%stat /= demstep_stat%ok) key = line
    end function key

    !> Whether a condition holds on every rank.
    logical function agreed(condition)
      logical, intent(in) :: condition
      call MPI_Allreduce(condition, agreed, 1, MPI_LOGICAL, MPI_LAND, comm)
    end function agreed

  end subroutine read_table_part

  !> The first line start at or after byte `from` of a file of `size_bytes`
  !> bytes (size_bytes + 1: none), reading forward a window at a time.
  subroutine line_start(path, from, size_bytes, first, ios)
    character(len=*), intent(in) :: path
    integer(i8), intent(in) :: from, size_bytes
    integer(i8), intent(out) :: first
    integer, intent(out) :: ios
    character(len=:), allocatable :: buf
    integer(i8) :: at, last, p
    first = size_bytes + 1
    ios = 0
    if (from <= 1) then
      first = 1
      return
    end if
    p = from
    do while (p <= size_bytes)
      ! a line starts at p when byte p-1 ends a line: read from p-1
      at = p - 1
      last = min(at + window, size_bytes)
      call read_range(path, at, last, buf, ios)
      if (ios /= 0) return
      do while (p <= last)
        if (starts_line(buf, p - at + 1)) then
          first = p
          return
        end if
        p = p + 1
      end do
    end do
  end subroutine line_start

  !> Whether position q of `buf` (q >= 2) starts a line: byte q-1 is a line
  !> feed, or a carriage return not followed by a line feed.
  pure logical function starts_line(buf, q)
    character(len=*), intent(in) :: buf
    integer(i8), intent(in) :: q
    integer :: b
    b = iachar(buf(q-1:q-1))
    starts_line = b == lf .or. (b == cr .and. iachar(buf(q:q)) /= lf)
  end function starts_line

  !> Bytes first .. last of a file (empty when last < first), one stream read.
  subroutine read_range(path, first, last, text, ios)
    character(len=*), intent(in) :: path
    integer(i8), intent(in) :: first, last
    character(len=:), allocatable, intent(out) :: text
    integer, intent(out) :: ios
    integer :: unit
    allocate(character(len=max(last - first + 1, 0_i8)) :: text)
    ios = 0
    if (last < first) return
    open(newunit=unit, file=path, access="stream", form="unformatted", action="read", &
      status="old", iostat=ios)
    if (ios /= 0) return
    read(unit, pos=first, iostat=ios) text
    close(unit)
  end subroutine read_range

  !> Make every rank's status the refusal with the smallest key over the
  !> ranks (`no_fault` on a rank without one; ties: the lowest rank), sent
  !> from the rank that holds it. Collective.
  subroutine agree_status(comm, status, key)
    type(MPI_Comm), intent(in) :: comm
    type(demstep_status_type), intent(inout) :: status
    integer(i8), intent(in) :: key
    integer(i8) :: least
    integer :: rank, root
    call MPI_Comm_rank(comm, rank)
    call MPI_Allreduce(key, least, 1, MPI_INTEGER8, MPI_MIN, comm)
    if (least == no_fault) then
      status%stat = demstep_stat%ok
      return
    end if
    root = huge(1)
    if (key == least) root = rank
    call MPI_Allreduce(MPI_IN_PLACE, root, 1, MPI_INTEGER, MPI_MIN, comm)
    call broadcast_status(comm, status, root)
  end subroutine agree_status

  !> Send rank root's status (code, location, index, detail, message) to all.
  subroutine broadcast_status(comm, status, root)
    type(MPI_Comm), intent(in) :: comm
    type(demstep_status_type), intent(inout) :: status
    integer, intent(in) :: root
    integer :: head(5), rank
    call MPI_Comm_rank(comm, rank)
    if (rank == root) then
      if (.not. allocated(status%where)) status%where = ""
      if (.not. allocated(status%detail)) status%detail = ""
      if (.not. allocated(status%message)) status%message = ""
      head = [status%stat, status%index, len(status%where), len(status%detail), len(status%message)]
    end if
    call MPI_Bcast(head, 5, MPI_INTEGER, root, comm)
    if (rank /= root) then
      status%stat = head(1)
      status%index = head(2)
      status%where = repeat(" ", head(3))
      status%detail = repeat(" ", head(4))
      status%message = repeat(" ", head(5))
    end if
    call MPI_Bcast(status%where, head(3), MPI_CHARACTER, root, comm)
    call MPI_Bcast(status%detail, head(4), MPI_CHARACTER, root, comm)
    call MPI_Bcast(status%message, head(5), MPI_CHARACTER, root, comm)
  end subroutine broadcast_status

end module demstep_mpi_parts
