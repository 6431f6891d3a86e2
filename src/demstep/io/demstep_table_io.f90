!> Tables of numbers in text files: particles, bonds, contacts, one row a line.
!>
!> A table has numbers separated by blanks, tabs or commas; `#` starts a comment
!> and blank lines are skipped. Every row has the same number of columns, one of
!> the counts the caller allows (a fixed layout, or a layout with optional
!> columns). The file is read whole (one stream read) and parsed in memory in
!> time linear in its size: one pass checks the text, counts the rows and finds
!> the layout, the rows are allocated once, a second pass converts them (see
!> `real_of`: the values are bit for bit those of a list-directed read). Lines
!> end at a line feed, a carriage return and line feed, or a lone carriage
!> return (as the Fortran runtime's formatted reads count them). A binary file
!> (a control character), a line longer than `table_max_line`, a field that is
!> not a plain number and a row of the wrong length are refused; the status
!> message names the file, the line and what is wrong. Columns of particle
!> numbers (`index_columns`) must hold integers from 1 to `huge(1)`, written as
!> integers (`2`, not `2.0` or `1.5`): the message then names the column too.
!> Memory: the file's text, the rows and their lines.
!>
!> ```fortran
!> real(dp), allocatable :: rows(:, :)
!> call read_table("bonds.txt", 2, rows, status)          ! two columns
!> call read_table("particles.txt", [7, 8], rows, status) ! 7, or 8 with an extra column
!> call read_table("contacts.txt", 4, rows, status, index_columns=[1, 2])
!> ```
module demstep_table_io
  use demstep_kinds, only: dp, i8
  use demstep_status, only: demstep_status_type, demstep_stat, set_status
  use demstep_text, only: int_text, integer_of, printable, read_text_file
  use demstep_decimal, only: real_of, little_endian
  use, intrinsic :: ieee_arithmetic, only: ieee_is_finite
  !$ use omp_lib, only: omp_get_max_threads
  implicit none
  private

  public :: read_table, table_scan, table_rows

  !> Read a table of numbers: `rows(:, k)` is the k-th row.
  interface read_table
    module procedure :: read_table_fixed, read_table_allowed
  end interface read_table

  !> Longest line read (characters, comment included).
  integer, parameter, public :: table_max_line = 64512
  !> A longer line is refused for a control character in its first this many
  !> columns, else for its length (the columns the former chunked reads saw).
  integer, parameter :: checked_columns = 65536
  !> Byte classes: a separator, a character of a number, anything else.
  integer, parameter :: other_byte = 0, separator_byte = 1, number_byte = 2
  integer, parameter :: lf = 10, cr = 13
  !> Seven bytes of 1, of 127 and of 128 each, the low seven bytes of eight,
  !> and seven blanks (for `next_line` and `plain_bytes`).
  integer(i8), parameter :: ones = 282578800148737_i8, low7 = 35887507618889599_i8, &
    high7 = 36170086419038336_i8, low7_bytes = 72057594037927935_i8, seven_blanks = 9042521604759584_i8
  !> Texts at least this long are scanned in parts in parallel (`parallel_scan`).
  integer(i8), parameter :: parallel_scan_bytes = 1048576_i8
  !> What `row_fault` finds in a row.
  integer, parameter :: row_fine = 0, row_count = 1, row_unread = 2, row_not_integer = 3, row_range = 4

  !> What pass 1 (`table_scan`) found in a table's text: each row's first and
  !> last character (comment cut) and file line, the layout (numbers per row,
  !> 0 when no row has an allowed count) and the line that set it, and the
  !> lines scanned (the offset included).
  type, public :: table_scan_type
    integer :: n_rows = 0, ncol = 0, first_line = 0, n_lines = 0
    integer(i8), allocatable :: row_first(:), row_last(:)
    integer, allocatable :: row_line(:)
  end type table_scan_type

contains

  !> A table with exactly `columns` numbers per row.
  subroutine read_table_fixed(path, columns, rows, status, lines, index_columns)
    !> File name.
    character(len=*), intent(in) :: path
    !> Numbers per row.
    integer, intent(in) :: columns
    !> The rows, `columns` by the number of rows (0 rows for an empty table).
    real(dp), allocatable, intent(out) :: rows(:, :)
    !> io_error (missing, unreadable, not rewindable, changed while read) or
    !> invalid_input (not text, line too long, malformed row), the message
    !> starting with `path: ` and naming the line.
    type(demstep_status_type), intent(out) :: status
    !> The file line of each row (for messages about a row found later).
    integer, allocatable, intent(out), optional :: lines(:)
    !> Columns of particle numbers: integers in [1, huge(1)].
    integer, intent(in), optional :: index_columns(:)
    call read_table_allowed(path, [columns], rows, status, lines, index_columns)
  end subroutine read_table_fixed

  !> A table whose rows all have the same number of columns, one of `allowed`;
  !> the first row decides which.
  subroutine read_table_allowed(path, allowed, rows, status, lines, index_columns)
    !> File name.
    character(len=*), intent(in) :: path
    !> The column counts a row may have (each >= 1).
    integer, intent(in) :: allowed(:)
    !> The rows, columns by the number of rows (maxval(allowed) by 0 for an
    !> empty table).
    real(dp), allocatable, intent(out) :: rows(:, :)
    !> As for the fixed layout; a row of another length than the first is
    !> refused naming both lines.
    type(demstep_status_type), intent(out) :: status
    !> The file line of each row (for messages about a row found later).
    integer, allocatable, intent(out), optional :: lines(:)
    !> Columns of particle numbers: integers in [1, huge(1)].
    integer, intent(in), optional :: index_columns(:)
    character(len=:), allocatable :: text
    type(table_scan_type) :: scan
    logical :: exists
    inquire(file=path, exist=exists)
    if (.not. exists) then
      call set_status(status, demstep_stat%io_error, path//": no such file")
      return
    end if
    if (size(allowed) == 0 .or. any(allowed < 1)) then
      call set_status(status, demstep_stat%invalid_input, path//": no column count allowed")
      return
    end if
    call read_whole_file(path, text, status)
    if (status%stat /= demstep_stat%ok) then
      status%message = path//": "//status%message
      return
    end if
    ! a size of 0: an empty file, or a device or pipe whose size is not known
    if (len(text) == 0) call read_by_records(path, text, status)
    if (status%stat /= demstep_stat%ok) return
    call parallel_scan(text, path, allowed, scan, status)
    if (status%stat /= demstep_stat%ok) return
    call table_rows(text, path, allowed, scan, rows, status, lines, index_columns)
  end subroutine read_table_allowed

  !> A file's text (`read_text_file`, and its status), a large regular file
  !> read in parallel (OpenMP): one part per thread, each thread reading its
  !> part through a unit of its own into its place in the text (whose pages
  !> it thus touches first). Any part that does not open or read: the file is
  !> read again whole by `read_text_file`, whose status then tells what is
  !> wrong.
  subroutine read_whole_file(path, text, status)
    character(len=*), intent(in) :: path
    character(len=:), allocatable, intent(out) :: text
    type(demstep_status_type), intent(out) :: status
    integer(i8) :: length, first, last
    integer :: np, k, unit, ios
    logical :: ok
    np = 1
    !$ np = omp_get_max_threads()
    inquire(file=path, size=length)
    if (length < parallel_scan_bytes .or. np < 2) then
      call read_text_file(path, text, status)
      return
    end if
    allocate(character(len=length) :: text)
    ok = .true.
    !$omp parallel do private(k, unit, ios, first, last) reduction(.and.:ok) schedule(static, 1)
    do k = 1, np
      first = (length*(k - 1))/np + 1
      last = (length*k)/np
      open(newunit=unit, file=path, access="stream", form="unformatted", action="read", status="old", &
        iostat=ios)
      if (ios == 0) then
        read(unit, pos=first, iostat=ios) text(first:last)
        close(unit)
      end if
      ok = ok .and. ios == 0
    end do
    !$omp end parallel do
    if (ok) then
      status%stat = demstep_stat%ok
    else
      deallocate(text)
      call read_text_file(path, text, status)
    end if
  end subroutine read_whole_file

  !> `table_scan` of a whole text in parts, in parallel (OpenMP): the text
  !> cut after line feeds into one part per thread (a text below
  !> `parallel_scan_bytes`, or one thread: one part), each part scanned with
  !> its own line numbers, then the parts' rows joined in order, their lines
  !> moved by the lines of the parts before. The same scan as one `table_scan`
  !> of the whole text: a line feed always ends a line, so every part starts
  !> at a line's start and ends a whole number of lines; the layout is the
  !> first part's that found one. A part that refuses its text (or more lines
  !> than an integer counts) is scanned again with the lines before it
  !> counted, so that the fault refused and its message are the first part's
  !> that has one, as one scan gives them.
  subroutine parallel_scan(text, name, allowed, scan, status)
    character(len=*), intent(in) :: text
    character(len=*), intent(in) :: name
    integer, intent(in) :: allowed(:)
    type(table_scan_type), intent(out) :: scan
    type(demstep_status_type), intent(out) :: status
    type(table_scan_type), allocatable :: part(:)
    type(demstep_status_type), allocatable :: part_status(:)
    integer(i8), allocatable :: cut(:), lines_before(:), rows_before(:)
    integer(i8) :: n, i, j
    integer :: np, k, total
    n = len(text, i8)
    np = 1
    !$ np = omp_get_max_threads()
    if (n < parallel_scan_bytes .or. np < 2) then
      call table_scan(text, name, allowed, scan, status)
      return
    end if
    ! the parts: cut(k) + 1 .. cut(k + 1), each cut just after a line feed
    ! (parts without one are merged into the one before)
    allocate(cut(np + 1))
    cut(1) = 0
    k = 1
    do while (k < np)
      i = max(cut(k) + 1, (n*k)/np)
      ! (the first line feed at or after i; none, or the text's last byte: no more parts)
      j = index(text(i:), achar(lf), kind=i8)
      if (j == 0) exit
      i = i + j - 1
      if (i >= n) exit
      k = k + 1
      cut(k) = i
    end do
    np = k
    cut(np + 1) = n
    allocate(part(np), part_status(np), lines_before(np + 1), rows_before(np + 1))
    !$omp parallel do schedule(static, 1)
    do k = 1, np
      call table_scan(text(cut(k) + 1:cut(k + 1)), name, allowed, part(k), part_status(k))
    end do
    !$omp end parallel do
    lines_before(1) = 0
    rows_before(1) = 0
    do k = 1, np
      lines_before(k + 1) = lines_before(k) + part(k)%n_lines
      rows_before(k + 1) = rows_before(k) + part(k)%n_rows
    end do
    do k = 1, np
      if (part_status(k)%stat /= demstep_stat%ok .or. lines_before(k + 1) > huge(1)) then
        ! (the parts before scanned whole: their lines are the file's before this one)
        call table_scan(text(cut(k) + 1:cut(k + 1)), name, allowed, part(k), status, &
          line_offset=int(min(lines_before(k), int(huge(1), i8))))
        if (status%stat /= demstep_stat%ok) return
      end if
    end do
    ! joined: rows in order (their positions in the whole text), the first layout
    total = int(rows_before(np + 1))
    allocate(scan%row_first(max(total, 1)), scan%row_last(max(total, 1)), scan%row_line(max(total, 1)))
    scan%n_rows = total
    scan%ncol = 0
    scan%first_line = 0
    ! (each part's rows copied by one thread: the pages the rows' pass reads)
    !$omp parallel do schedule(static, 1)
    do k = 1, np
      associate(p => part(k), m => part(k)%n_rows, r => int(rows_before(k)))
        scan%row_first(r + 1:r + m) = p%row_first(:m) + cut(k)
        scan%row_last(r + 1:r + m) = p%row_last(:m) + cut(k)
        scan%row_line(r + 1:r + m) = p%row_line(:m) + int(lines_before(k))
      end associate
    end do
    !$omp end parallel do
    do k = 1, np
      if (part(k)%n_rows > 0 .and. part(k)%ncol > 0 .and. part(k)%first_line > 0) then
        scan%ncol = part(k)%ncol
        scan%first_line = part(k)%first_line + int(lines_before(k))
        exit
      end if
    end do
    scan%n_lines = int(lines_before(np + 1))
    if (scan%n_rows == 0) scan%ncol = maxval(allowed)
    status%stat = demstep_stat%ok
  end subroutine parallel_scan

  !> Pass 1 of reading a table held in `text` (a whole file, or a part of one
  !> that starts at a line's start and ends at a line's end): the text
  !> checked (no control character, no line longer than `table_max_line`),
  !> its rows found (extent without the comment, file line) and the layout
  !> (the first row of an allowed count whose numbers read; the widest
  !> layout for no rows). Status invalid_input naming `name` and the line.
  pure subroutine table_scan(text, name, allowed, scan, status, line_offset, fault_line)
    !> The text.
    character(len=*), intent(in) :: text
    !> The file's name, for messages.
    character(len=*), intent(in) :: name
    !> The column counts a row may have (each >= 1).
    integer, intent(in) :: allowed(:)
    type(table_scan_type), intent(out) :: scan
    type(demstep_status_type), intent(out) :: status
    !> Lines of the file before `text` (default 0).
    integer, intent(in), optional :: line_offset
    !> The line refused (0: none).
    integer, intent(out), optional :: fault_line
    real(dp), allocatable :: values(:)
    integer(i8), allocatable :: field_first(:), field_last(:)
    integer(i8) :: first, last, next, comment, control
    integer :: line, count, capacity
    logical :: blank
    allocate(values(maxval(allowed)), field_first(maxval(allowed)), field_last(maxval(allowed)))
    if (present(fault_line)) fault_line = 0
    ! (room for a row per 32 characters at first: the rows' pages are touched
    ! only as rows are found, and most tables need no regrowth)
    capacity = int(max(1024_i8, min(len(text, i8)/32, int(huge(1), i8))))
    allocate(scan%row_first(capacity), scan%row_last(capacity), scan%row_line(capacity))
    scan%n_rows = 0
    scan%ncol = 0
    scan%first_line = 0
    line = 0
    if (present(line_offset)) line = line_offset
    next = 1
    do while (next <= len(text, i8))
      call next_line(text, next, first, last, comment, control, blank)
      if (line == huge(line)) then
        call set_status(status, demstep_stat%invalid_input, name//": more than "//int_text(huge(line))//" lines")
        return
      end if
      line = line + 1
      if (control > 0) then
        call set_status(status, demstep_stat%invalid_input, name//": line "//int_text(line)//": not a text " &
          //"file (byte "//int_text(iachar(text(first+control-1:first+control-1)))//" in column "// &
          int_text(control)//")")
        if (present(fault_line)) fault_line = line
        return
      end if
      if (last - first + 1 > table_max_line) then
        call set_status(status, demstep_stat%invalid_input, name//": line "//int_text(line)//": longer than " &
          //int_text(table_max_line)//" characters")
        if (present(fault_line)) fault_line = line
        return
      end if
      ! blank: spaces only (a tab or a comma makes a row without numbers)
      if (blank) cycle
      if (scan%n_rows == size(scan%row_first)) call grow_rows(scan%row_first, scan%row_last, scan%row_line)
      scan%n_rows = scan%n_rows + 1
      scan%row_first(scan%n_rows) = first
      scan%row_last(scan%n_rows) = first + comment - 2
      scan%row_line(scan%n_rows) = line
      ! the layout: the first row of an allowed count whose numbers read
      if (scan%ncol == 0) then
        call parse_row(text(first:first+comment-2), values, count, field_first, field_last)
        if (count >= 0 .and. any(allowed == count)) then
          scan%ncol = count
          scan%first_line = line
        end if
      end if
    end do
    scan%n_lines = line
    ! an empty table has the widest layout; a table without a row of an
    ! allowed count fails in `table_rows`, at its first row
    if (scan%n_rows == 0) scan%ncol = maxval(allowed)
    status%stat = demstep_stat%ok
  end subroutine table_scan

  !> Pass 2 of reading a table: the rows `table_scan` found converted and
  !> checked against the layout `scan%ncol` (0: none found) of line
  !> `scan%first_line` (a caller reading a file in parts may set the whole
  !> file's); in parallel over the rows (OpenMP), the first faulty row in
  !> file order refused. Status invalid_input naming `name` and the line.
  subroutine table_rows(text, name, allowed, scan, rows, status, lines, index_columns, fault_line)
    !> The text `scan` came from.
    character(len=*), intent(in) :: text
    !> The file's name, for messages.
    character(len=*), intent(in) :: name
    !> The column counts a row may have (each >= 1).
    integer, intent(in) :: allowed(:)
    type(table_scan_type), intent(in) :: scan
    !> The rows, ncol by the number of rows.
    real(dp), allocatable, intent(out) :: rows(:, :)
    type(demstep_status_type), intent(out) :: status
    !> The file line of each row.
    integer, allocatable, intent(out), optional :: lines(:)
    !> Columns of particle numbers: integers in [1, huge(1)].
    integer, intent(in), optional :: index_columns(:)
    !> The line refused (0: none).
    integer, intent(out), optional :: fault_line
    real(dp), allocatable :: values(:)
    integer(i8), allocatable :: field_first(:), field_last(:)
    integer, allocatable :: index_cols(:)
    integer(i8) :: first, last
    integer :: line, n, count, ncol, c, fault, bad
    if (present(fault_line)) fault_line = 0
    ncol = scan%ncol
    allocate(rows(ncol, scan%n_rows))
    if (present(lines)) lines = scan%row_line(:scan%n_rows)
    allocate(index_cols(0))
    if (present(index_columns)) index_cols = index_columns
    ! (the rows are independent: converted in parallel, the first faulty one
    ! in file order kept; its message made after, from the same check)
    bad = huge(bad)
    !$omp parallel private(n, values, field_first, field_last, count, fault, c)
    allocate(values(maxval(allowed)), field_first(maxval(allowed)), field_last(maxval(allowed)))
    !$omp do schedule(static) reduction(min:bad)
    do n = 1, scan%n_rows
      call row_fault(text(scan%row_first(n):scan%row_last(n)), ncol, index_cols, values, count, &
        field_first, field_last, fault, c)
      if (fault == row_fine) then
        rows(:, n) = values(:ncol)
      else
        bad = min(bad, n)
      end if
    end do
    !$omp end do
    !$omp end parallel
    status%stat = demstep_stat%ok
    if (bad > scan%n_rows) return
    ! (built without OpenMP the region's arrays are these, still allocated)
    if (.not. allocated(values)) allocate(values(maxval(allowed)), field_first(maxval(allowed)), &
      field_last(maxval(allowed)))
    n = bad
    first = scan%row_first(n)
    last = scan%row_last(n)
    line = scan%row_line(n)
    call row_fault(text(first:last), ncol, index_cols, values, count, field_first, field_last, fault, c)
    select case (fault)
    case (row_count)
      if (ncol == 0) then
        ! no row has an allowed count: the layout is not known
        call fail(demstep_stat%invalid_input, "line "//int_text(line)//": expected "// &
          counts_text(allowed)//" numbers, found "//int_text(count))
      else if (any(allowed == count)) then
        call fail(demstep_stat%invalid_input, "line "//int_text(line)//": expected "// &
          int_text(ncol)//" numbers, found "//int_text(count)//" (line "//int_text(scan%first_line) &
          //" has "//int_text(ncol)//"; every row the same)")
      else
        call fail(demstep_stat%invalid_input, "line "//int_text(line)//": expected "// &
          int_text(ncol)//" numbers, found "//int_text(count))
      end if
    case (row_unread)
      call fail(demstep_stat%invalid_input, "line "//int_text(line)//": cannot read '"// &
        shortened(trim(adjustl(text(first:last))))//"' as finite numbers")
    case (row_not_integer)
      associate(f => text(first+field_first(c)-1:first+field_last(c)-1))
        call fail(demstep_stat%invalid_input, "line "//int_text(line)//": column "//int_text(c)// &
          ": '"//shortened(f)//"' is not an integer (a particle number)")
      end associate
    case default
      associate(f => text(first+field_first(c)-1:first+field_last(c)-1))
        call fail(demstep_stat%invalid_input, "line "//int_text(line)//": column "//int_text(c)// &
          ": particle number '"//shortened(f)//"' must lie in [1, "//int_text(huge(1))//"]")
      end associate
    end select
  contains
    subroutine fail(stat, what)
      integer, intent(in) :: stat
      character(len=*), intent(in) :: what
      call set_status(status, stat, name//": "//what)
      if (present(fault_line)) fault_line = line
    end subroutine fail
  end subroutine table_rows

  !> The check of one row of `table_rows` (its text, comment cut): its
  !> numbers in `values` and their columns, and `fault`: `row_fine`, or
  !> `row_count` (not ncol numbers; `count` the fields found), `row_unread`
  !> (a field not a finite number), `row_not_integer` or `row_range` (column
  !> `c`, one of `index_columns`, not an integer, or not in [1, huge(1)]).
  pure subroutine row_fault(text, ncol, index_columns, values, count, field_first, field_last, fault, c)
    character(len=*), intent(in) :: text
    integer, intent(in) :: ncol, index_columns(:)
    real(dp), intent(out) :: values(:)
    integer, intent(out) :: count
    integer(i8), intent(out) :: field_first(:), field_last(:)
    integer, intent(out) :: fault, c
    integer(i8) :: number
    integer :: j
    logical :: whole, too_large
    fault = row_fine
    c = 0
    call parse_row(text, values, count, field_first, field_last)
    if (count >= 0 .and. count /= ncol) then
      fault = row_count
      return
    end if
    if (count >= 0) then
      if (.not. all(ieee_is_finite(values(:ncol)))) count = -1
    end if
    if (count < 0) then
      fault = row_unread
      return
    end if
    do j = 1, size(index_columns)
      c = index_columns(j)
      if (c < 1 .or. c > ncol) cycle
      call integer_of(text(field_first(c):field_last(c)), number, whole, too_large)
      if (.not. (whole .or. too_large)) then
        fault = row_not_integer
        return
      else if (too_large .or. number < 1 .or. number > huge(1)) then
        fault = row_range
        return
      end if
    end do
    c = 0
  end subroutine row_fault

  !> A file whose size the system does not tell (a device such as /dev/zero, a
  !> pipe; or an empty file): read record by record in chunks of 1024
  !> characters, each checked at once, so that a binary stream or an endless
  !> line is refused after one chunk (status as `read_table`'s); the records
  !> joined by line feeds.
  subroutine read_by_records(path, text, status)
    character(len=*), intent(in) :: path
    character(len=:), allocatable, intent(out) :: text
    type(demstep_status_type), intent(out) :: status
    integer, parameter :: chunk = 1024
    character(len=chunk) :: buf
    character(len=:), allocatable :: bigger
    integer :: unit, ios, n_read, line, got, k
    integer(i8) :: used
    open(newunit=unit, file=path, status="old", action="read", form="formatted", access="sequential", &
      iostat=ios)
    if (ios /= 0) then
      call set_status(status, demstep_stat%io_error, path//": cannot open")
      return
    end if
    allocate(character(len=16*chunk) :: text)
    used = 0
    line = 0
    do
      got = 0
      do
        read(unit, '(a)', advance="no", size=n_read, iostat=ios) buf
        if (is_iostat_end(ios) .and. got == 0) exit
        k = 0
        do while (k < n_read)
          k = k + 1
          if ((iachar(buf(k:k)) < 32 .and. iachar(buf(k:k)) /= 9) .or. iachar(buf(k:k)) == 127) then
            call fail(demstep_stat%invalid_input, "line "//int_text(line + 1)//": not a text file (byte "// &
              int_text(iachar(buf(k:k)))//" in column "//int_text(got + k)//")")
            return
          end if
        end do
        call append(buf(:n_read))
        got = got + n_read
        if (got > table_max_line) then
          call fail(demstep_stat%invalid_input, "line "//int_text(line + 1)//": longer than "// &
            int_text(table_max_line)//" characters")
          return
        end if
        if (ios /= 0) exit
      end do
      if (is_iostat_end(ios) .and. got == 0) exit
      line = line + 1
      if (ios /= 0 .and. .not. (is_iostat_eor(ios) .or. is_iostat_end(ios))) then
        call fail(demstep_stat%io_error, "line "//int_text(line)//": cannot be read")
        return
      end if
      call append(achar(lf))
    end do
    close(unit)
    text = text(:used)
    status%stat = demstep_stat%ok
  contains
    subroutine append(part)
      character(len=*), intent(in) :: part
      if (used + len(part) > len(text, i8)) then
        allocate(character(len=2*len(text, i8) + len(part)) :: bigger)
        bigger(:used) = text(:used)
        call move_alloc(bigger, text)
      end if
      text(used+1:used+len(part)) = part
      used = used + len(part)
    end subroutine append
    subroutine fail(stat, what)
      integer, intent(in) :: stat
      character(len=*), intent(in) :: what
      call set_status(status, stat, path//": "//what)
      close(unit)
    end subroutine fail
  end subroutine read_by_records

  !> The line starting at `next`, in one pass over its bytes: its first and
  !> last character (last < first for an empty line), without its end (a line
  !> feed, a carriage return and line feed, or a lone carriage return); the
  !> column of its first `#` (its length + 1 if none); the column of its first
  !> control character (bytes 0 to 31 but tab, and 127) among its first
  !> `checked_columns`, 0 if none; and whether it holds only spaces before the
  !> `#`. `next` moves past the line's end. Eight bytes at a time while none
  !> of them needs a look of its own (`plain_bytes`, seven at a time), else byte by byte.
  pure subroutine next_line(text, next, first, last, comment, control, blank)
    character(len=*), intent(in) :: text
    integer(i8), intent(inout) :: next
    integer(i8), intent(out) :: first, last, comment, control
    logical, intent(out) :: blank
    integer(i8) :: i, n, x
    integer :: b
    first = next
    n = len(text, i8)
    comment = 0
    control = 0
    blank = .true.
    i = next
    do while (i <= n)
      if (i + 7 <= n) then
        ! (the eight bytes from i read at once, the first seven tested)
        x = transfer(text(i:i+7), x)
        if (little_endian) then
          x = iand(x, low7_bytes)
        else
          x = ishft(x, -8)
        end if
        if (plain_bytes(x)) then
          ! (no line end, control character or '#' among them)
          if (blank .and. comment == 0) blank = x == seven_blanks
          i = i + 7
          cycle
        end if
      end if
      b = iachar(text(i:i))
      if (b < 32 .or. b == 127 .or. b == 35) then
        if (b == lf .or. b == cr) exit
        if (b == 35) then
          if (comment == 0) comment = i - first + 1
        else if (b /= 9 .and. control == 0 .and. i - first < checked_columns) then
          control = i - first + 1
        end if
      end if
      if (b /= 32 .and. comment == 0) blank = .false.
      i = i + 1
    end do
    last = i - 1
    if (comment == 0) comment = last - first + 2
    next = i + 1
    if (i < n) then
      if (iachar(text(i:i)) == cr .and. iachar(text(i+1:i+1)) == lf) next = i + 2
    end if
  end subroutine next_line

  !> Whether the seven bytes of 0 <= x < 2^56 are all plain: none below 32,
  !> 127 or `#` (bytes from 128 are plain). Per byte b, over its low seven
  !> bits y: bit 7 of y + 96 is set from 32 up, of y + 1 from 127 up, of
  !> (y xor 35) + 127 unless y is 35; no sum carries into the next byte, and
  !> none leaves the integer's range. Exact, without false alarms.
  elemental logical function plain_bytes(x) result(plain)
    integer(i8), intent(in) :: x
    integer(i8) :: y, fine
    y = iand(x, low7)
    fine = iand(iand(y + 96_i8*ones, not(y + ones)), ieor(y, 35_i8*ones) + low7)
    plain = iand(ior(fine, x), high7) == high7
  end function plain_bytes

  !> Double the capacity of the row lists, keeping their values.
  pure subroutine grow_rows(row_first, row_last, row_line)
    integer(i8), allocatable, intent(inout) :: row_first(:), row_last(:)
    integer, allocatable, intent(inout) :: row_line(:)
    integer(i8), allocatable :: f(:), l(:)
    integer, allocatable :: k(:)
    integer :: n
    n = size(row_first)
    allocate(f(2*n), l(2*n), k(2*n))
    f(:n) = row_first
    l(:n) = row_last
    k(:n) = row_line
    call move_alloc(f, row_first)
    call move_alloc(l, row_last)
    call move_alloc(k, row_line)
  end subroutine grow_rows

  !> The allowed counts as prose: `7`, `7 or 8`, `2, 3 or 4`.
  pure function counts_text(allowed) result(text)
    integer, intent(in) :: allowed(:)
    character(len=:), allocatable :: text
    integer :: i
    text = int_text(allowed(1))
    do i = 2, size(allowed)
      if (i == size(allowed)) then
        text = text//" or "//int_text(allowed(i))
      else
        text = text//", "//int_text(allowed(i))
      end if
    end do
  end function counts_text

  !> The numbers of one row (blanks, tabs and commas separate them). `count` is
  !> the number of fields, or -1 when a field is not a plain number: only
  !> digits, signs, '.' and the exponent letters e and d may appear, so
  !> list-directed extras (`2*0` repeats, `/`, quotes) cannot hide or invent a
  !> column. When the count fits `values`, the fields are read into it (one
  !> that does not read makes the count -1) and their columns in the row are
  !> `field_first`, `field_last`.
  pure subroutine parse_row(text, values, count, field_first, field_last)
    character(len=*), intent(in) :: text
    real(dp), intent(out) :: values(:)
    integer, intent(out) :: count
    integer(i8), intent(out) :: field_first(:), field_last(:)
    integer(i8) :: i, start, n
    logical :: ok, all_read
    n = len(text, i8)
    count = 0
    all_read = .true.
    i = 1
    do while (i <= n)
      select case (byte_class(text(i:i)))
      case (separator_byte)
        i = i + 1
      case (number_byte)
        start = i
        do while (i <= n)
          if (byte_class(text(i:i)) /= number_byte) exit
          i = i + 1
        end do
        count = count + 1
        if (count <= size(values)) then
          field_first(count) = start
          field_last(count) = i - 1
          call real_of(text(start:i-1), values(count), ok)
          all_read = all_read .and. ok
        end if
      case default
        count = -1
        return
      end select
    end do
    if (count <= size(values) .and. .not. all_read) count = -1
  end subroutine parse_row

  !> The class of a byte: a separator (blank, comma, tab), a character of a
  !> number (see `number_characters`) or another byte.
  elemental integer function byte_class(c) result(class)
    character, intent(in) :: c
    select case (iachar(c))
    case (32, 44, 9)
      class = separator_byte
    case (48:57, 43, 45, 46, 68, 69, 100, 101)
      class = number_byte
    case default
      class = other_byte
    end select
  end function byte_class

  !> At most 60 characters of a text, for a message (see [[printable]]).
  pure function shortened(text) result(short)
    character(len=*), intent(in) :: text
    character(len=:), allocatable :: short
    if (len(text) <= 60) then
      short = printable(text)
    else
      short = printable(text(:57))//"..."
    end if
  end function shortened

end module demstep_table_io
