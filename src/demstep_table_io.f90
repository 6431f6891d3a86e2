!> Tables of numbers in text files: particles, bonds, contacts, one row a line.
!>
!> A table has numbers separated by blanks, tabs or commas; `#` starts a comment
!> and blank lines are skipped. Every row has the same number of columns, one of
!> the counts the caller allows (a fixed layout, or a layout with optional
!> columns). The file is read in time linear in its size: one pass counts the
!> rows and checks the text, the rows are allocated once, a second pass fills
!> them. A binary file (a control character), an endless line, a field that is
!> not a plain number and a row of the wrong length are refused; the status
!> message names the file, the line and what is wrong. Columns of particle
!> numbers (`index_columns`) must hold integers from 1 to `huge(1)`, written as
!> integers (`2`, not `2.0` or `1.5`): the message then names the column too.
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
  use demstep_text, only: int_text, integer_of, printable
  use, intrinsic :: ieee_arithmetic, only: ieee_is_finite
  implicit none
  private

  public :: read_table

  !> Read a table of numbers: `rows(:, k)` is the k-th row.
  interface read_table
    module procedure :: read_table_fixed, read_table_allowed
  end interface read_table

  !> Longest line read (characters, comment included).
  integer, parameter, public :: table_max_line = 64512
  !> The line is read in chunks of this many characters, each checked at once.
  integer, parameter :: chunk = 1024
  !> What separates the numbers of a row: blank, comma, tab, carriage return.
  character(len=*), parameter :: separators = " ,"//achar(9)//achar(13)

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
    integer :: unit, ios, line, n, n_rows, got, pass, k, count, n_read, ncol, first_line, c
    integer(i8) :: number
    logical :: whole, too_large
    character(len=table_max_line + chunk) :: buf
    real(dp), allocatable :: values(:)
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
    open(newunit=unit, file=path, status="old", action="read", form="formatted", &
      access="sequential", iostat=ios)
    if (ios /= 0) then
      call set_status(status, demstep_stat%io_error, path//": cannot open")
      return
    end if
    allocate(values(maxval(allowed)))
    n_rows = 0
    ncol = 0
    first_line = 0
    n = 0
    do pass = 1, 2
      if (pass == 2) then
        ! an empty table has the widest layout; a table without a row of an
        ! allowed count fails below, at its first line
        if (n_rows == 0) ncol = maxval(allowed)
        allocate(rows(ncol, n_rows))
        if (present(lines)) allocate(lines(n_rows))
        rewind(unit, iostat=ios)
        if (ios /= 0) then
          call fail_at(demstep_stat%io_error, "cannot read it twice (a regular file is needed)")
          return
        end if
      end if
      n = 0
      line = 0
      do
        ! the line in chunks: each is checked before the next is read, so a
        ! binary file or an endless line is refused after one chunk
        got = 0
        do
          read(unit, '(a)', advance="no", size=n_read, iostat=ios) buf(got+1:got+chunk)
          if (is_iostat_end(ios) .and. got == 0) exit
          k = scan(buf(got+1:got+n_read), control_characters())
          if (k > 0) then
            call fail_at(demstep_stat%invalid_input, "line "//int_text(line + 1)//": not a " &
              //"text file (byte "//int_text(iachar(buf(got+k:got+k)))//" in column "// &
              int_text(got + k)//")")
            return
          end if
          got = got + n_read
          if (got > table_max_line) then
            call fail_at(demstep_stat%invalid_input, "line "//int_text(line + 1)//": longer " &
              //"than "//int_text(table_max_line)//" characters")
            return
          end if
          if (ios /= 0) exit
        end do
        if (is_iostat_end(ios) .and. got == 0) exit
        line = line + 1
        if (ios /= 0 .and. .not. (is_iostat_eor(ios) .or. is_iostat_end(ios))) then
          call fail_at(demstep_stat%io_error, "line "//int_text(line)//": cannot be read")
          return
        end if
        k = index(buf(:got), "#")
        if (k > 0) got = k - 1
        if (len_trim(buf(:got)) == 0) cycle
        n = n + 1
        if (pass == 2 .and. n > n_rows) then
          call fail_at(demstep_stat%io_error, "changed while it was read")
          return
        end if
        call parse_row(buf(:got), values, count)
        if (pass == 1) then
          ! the layout: the first row's count, which every row must repeat
          if (count >= 0 .and. ncol == 0) then
            if (any(allowed == count)) then
              ncol = count
              first_line = line
            end if
          end if
          cycle
        end if
        if (count >= 0 .and. count /= ncol) then
          if (ncol == 0) then
            ! no row has an allowed count: the layout is not known
            call fail_at(demstep_stat%invalid_input, "line "//int_text(line)//": expected "// &
              counts_text(allowed)//" numbers, found "//int_text(count))
          else if (any(allowed == count)) then
            call fail_at(demstep_stat%invalid_input, "line "//int_text(line)//": expected "// &
              int_text(ncol)//" numbers, found "//int_text(count)//" (line "//int_text(first_line) &
              //" has "//int_text(ncol)//"; every row the same)")
          else
            call fail_at(demstep_stat%invalid_input, "line "//int_text(line)//": expected "// &
              int_text(ncol)//" numbers, found "//int_text(count))
          end if
          return
        end if
        if (count < 0 .or. .not. all(ieee_is_finite(values(:max(count, 1))))) then
          call fail_at(demstep_stat%invalid_input, "line "//int_text(line)//": cannot read '"// &
            shortened(trim(adjustl(buf(:got))))//"' as finite numbers")
          return
        end if
        if (present(index_columns)) then
          do k = 1, size(index_columns)
            c = index_columns(k)
            if (c < 1 .or. c > ncol) cycle
            call integer_of(field(buf(:got), c), number, whole, too_large)
            if (.not. (whole .or. too_large)) then
              call fail_at(demstep_stat%invalid_input, "line "//int_text(line)//": column "//int_text(c)// &
                ": '"//shortened(field(buf(:got), c))//"' is not an integer (a particle number)")
              return
            else if (too_large .or. number < 1 .or. number > huge(1)) then
              call fail_at(demstep_stat%invalid_input, "line "//int_text(line)//": column "//int_text(c)// &
                ": particle number '"//shortened(field(buf(:got), c))//"' must lie in [1, "// &
                int_text(huge(1))//"]")
              return
            end if
          end do
        end if
        rows(:, n) = values(:ncol)
        if (present(lines)) lines(n) = line
      end do
      if (pass == 1) n_rows = n
    end do
    close(unit)
    if (n /= n_rows) then
      call set_status(status, demstep_stat%io_error, path//": changed while it was read")
      return
    end if
    status%stat = demstep_stat%ok
  contains
    subroutine fail_at(stat, what)
      integer, intent(in) :: stat
      character(len=*), intent(in) :: what
      call set_status(status, stat, path//": "//what)
      close(unit)
    end subroutine fail_at
  end subroutine read_table_allowed

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

  !> Bytes 0 to 31 and 127, except tab and carriage return.
  pure function control_characters() result(set)
    character(len=31) :: set
    integer :: i, k
    k = 0
    do i = 0, 31
      if (i == 9 .or. i == 13) cycle
      k = k + 1
      set(k:k) = achar(i)
    end do
    set(31:31) = achar(127)
  end function control_characters

  !> The numbers of one row (blanks, tabs, carriage returns and commas separate
  !> them). `count` is the number of fields, or -1 when a field is not a plain
  !> number: only digits, signs, '.' and the exponent letters e and d may appear,
  !> so list-directed extras (`2*0` repeats, `/`, quotes) cannot hide or invent a
  !> column. The values are read only when the count fits `values`.
  subroutine parse_row(text, values, count)
    character(len=*), intent(in) :: text
    real(dp), intent(out) :: values(:)
    integer, intent(out) :: count
    character(len=len(text)) :: clean
    integer :: i, ios
    logical :: inside, sep
    clean = text
    values = 0.0_dp
    count = 0
    inside = .false.
    do i = 1, len(clean)
      if (index(separators, clean(i:i)) > 0) then
        clean(i:i) = " "
        sep = .true.
      else if (index("0123456789+-.eEdD", clean(i:i)) > 0) then
        sep = .false.
      else
        count = -1
        return
      end if
      if (.not. sep .and. .not. inside) count = count + 1
      inside = .not. sep
    end do
    if (count > size(values) .or. count == 0) return
    read(clean, *, iostat=ios) values(:count)
    if (ios /= 0) count = -1
  end subroutine parse_row

  !> Field `j` of a row (fields as `parse_row` separates them; '' beyond the last).
  pure function field(text, j) result(f)
    character(len=*), intent(in) :: text
    integer, intent(in) :: j
    character(len=:), allocatable :: f
    integer :: i, start, count
    f = ""
    count = 0
    i = 1
    do while (i <= len(text))
      if (index(separators, text(i:i)) > 0) then
        i = i + 1
        cycle
      end if
      start = i
      do while (i <= len(text))
        if (index(separators, text(i:i)) > 0) exit
        i = i + 1
      end do
      count = count + 1
      if (count == j) then
        f = text(start:i-1)
        return
      end if
    end do
  end function field

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
