!> Tests of demstep_table_io: tables of numbers read exactly, layouts with a fixed
!> or an allowed set of column counts, and every malformed file refused with the
!> file, the line and what is wrong.
module test_table_io
  use testdrive, only: new_unittest, unittest_type, error_type, check, test_failed
  use demstep_kinds, only: dp
  use demstep_status, only: demstep_status_type, demstep_stat
  use demstep_table_io, only: read_table, table_max_line, table_scan, table_rows, table_scan_type
  use demstep_text, only: read_text_file, int_text
  use test_support, only: write_file, work_dir
  !$ use omp_lib, only: omp_get_max_threads, omp_set_num_threads
  implicit none
  private
  public :: collect_table_io

  character(len=*), parameter :: table = work_dir//"/table.txt"

contains

  subroutine collect_table_io(testsuite)
    type(unittest_type), allocatable, intent(out) :: testsuite(:)
    testsuite = [ &
      new_unittest("numbers, separators, comments and blank lines", test_values), &
      new_unittest("an allowed set of column counts", test_allowed), &
      new_unittest("an empty table", test_empty), &
      new_unittest("malformed rows: file, line and what is wrong", test_malformed), &
      new_unittest("binary input, long lines, missing files", test_refused), &
      new_unittest("line ends: LF, CR LF, a lone CR; devices read by records", test_line_ends), &
      new_unittest("1e5 rows, each value in its place", test_many_rows), &
      new_unittest("particle numbers: integers in [1, huge], refused by line and column", test_index_columns), &
      new_unittest("rows converted in parallel: the first faulty row in file order is named", &
        test_first_fault), &
      new_unittest("a large table scanned in parts: the whole text's scan; faults by line", &
        test_scan_parts) &
      ]
  end subroutine collect_table_io

  subroutine test_values(error)
    type(error_type), allocatable, intent(out) :: error
    real(dp), allocatable :: rows(:, :)
    type(demstep_status_type) :: status
    call write_file(table, [character(len=40) :: "# particle numbers", "", "1 2", &
      "2,3   # a comment", achar(9)//"3"//achar(9)//"4", "  ", "-1.5e2 2.5d-1"])
    call read_table(table, 2, rows, status)
    call check(error, status%stat, demstep_stat%ok, message=status%message)
    if (allocated(error)) return
    call check(error, size(rows, 1) == 2 .and. size(rows, 2) == 4, "2 columns, 4 rows")
    if (allocated(error)) return
    ! decimal text read by the runtime: exact for these values
    call check(error, all(rows(:, 1:3) == reshape([1.0_dp, 2.0_dp, 2.0_dp, 3.0_dp, 3.0_dp, &
      4.0_dp], [2, 3])), "rows 1 to 3")
    if (allocated(error)) return
    call check(error, rows(1, 4) == -150.0_dp .and. rows(2, 4) == 0.25_dp, "exponents e and d")
  end subroutine test_values

  subroutine test_allowed(error)
    type(error_type), allocatable, intent(out) :: error
    real(dp), allocatable :: rows(:, :)
    type(demstep_status_type) :: status
    call write_file(table, [character(len=40) :: "1 2 3", "4 5 6"])
    call read_table(table, [2, 3], rows, status)
    call check(error, status%stat, demstep_stat%ok, message=status%message)
    if (allocated(error)) return
    call check(error, size(rows, 1) == 3 .and. size(rows, 2) == 2 .and. rows(3, 2) == 6.0_dp, &
      "the first row's count, 3 of [2, 3]")
    if (allocated(error)) return
    call write_file(table, [character(len=40) :: "1 2", "# two columns first", "4 5 6"])
    call read_table(table, [2, 3], rows, status)
    call expect(error, status, demstep_stat%invalid_input, &
      table//": line 3: expected 2 numbers, found 3 (line 1 has 2; every row the same)")
    if (allocated(error)) return
    call write_file(table, [character(len=40) :: "1 2 3 4 5"])
    call read_table(table, [2, 3, 4], rows, status)
    call expect(error, status, demstep_stat%invalid_input, &
      table//": line 1: expected 2, 3 or 4 numbers, found 5")
  end subroutine test_allowed

  subroutine test_empty(error)
    type(error_type), allocatable, intent(out) :: error
    real(dp), allocatable :: rows(:, :)
    type(demstep_status_type) :: status
    call write_file(table, [character(len=40) :: "# nothing here", ""])
    call read_table(table, [7, 8], rows, status)
    call check(error, status%stat, demstep_stat%ok, message=status%message)
    if (allocated(error)) return
    call check(error, size(rows, 1) == 8 .and. size(rows, 2) == 0, "8 by 0: the widest layout")
  end subroutine test_empty

  subroutine test_malformed(error)
    type(error_type), allocatable, intent(out) :: error
    real(dp), allocatable :: rows(:, :)
    type(demstep_status_type) :: status
    call write_file(table, [character(len=40) :: "1 2", "1 2 3"])
    call read_table(table, 2, rows, status)
    call expect(error, status, demstep_stat%invalid_input, table//": line 2: expected 2 numbers, found 3")
    if (allocated(error)) return
    ! a first row of a wrong count is named, not taken as the layout
    call write_file(table, [character(len=40) :: "1", "1 2"])
    call read_table(table, 2, rows, status)
    call expect(error, status, demstep_stat%invalid_input, table//": line 1: expected 2 numbers, found 1")
    if (allocated(error)) return
    ! list-directed extras cannot invent or hide a column
    call write_file(table, [character(len=40) :: "1 2", "2*0"])
    call read_table(table, 2, rows, status)
    call expect(error, status, demstep_stat%invalid_input, table//": line 2: cannot read '2*0'")
    if (allocated(error)) return
    call write_file(table, [character(len=40) :: "1 nan"])
    call read_table(table, 2, rows, status)
    call expect(error, status, demstep_stat%invalid_input, table//": line 1: cannot read '1 nan'")
    if (allocated(error)) return
    call write_file(table, [character(len=40) :: "1 1e999"])
    call read_table(table, 2, rows, status)
    call expect(error, status, demstep_stat%invalid_input, table//": line 1: cannot read '1 1e999' as " &
      //"finite numbers")
  end subroutine test_malformed

  subroutine test_refused(error)
    type(error_type), allocatable, intent(out) :: error
    real(dp), allocatable :: rows(:, :)
    type(demstep_status_type) :: status
    call write_file(table, [character(len=8) :: "1 2", "3 "//achar(0)//" 4"])
    call read_table(table, 2, rows, status)
    call expect(error, status, demstep_stat%invalid_input, table//": line 2: not a text file (byte 0 " &
      //"in column 3)")
    if (allocated(error)) return
    ! the longest line is read; one character more is refused
    call write_file(table, ["1"//repeat(" ", table_max_line - 2)//"2"])
    call read_table(table, 2, rows, status)
    call check(error, status%stat, demstep_stat%ok, message="a line of 64512 characters: "//status%message)
    if (allocated(error)) return
    call write_file(table, ["1"//repeat(" ", table_max_line - 1)//"2"])
    call read_table(table, 2, rows, status)
    call expect(error, status, demstep_stat%invalid_input, table//": line 1: longer than 64512 characters")
    if (allocated(error)) return
    call read_table(work_dir//"/no-such-table.txt", 2, rows, status)
    call expect(error, status, demstep_stat%io_error, work_dir//"/no-such-table.txt: no such file")
  end subroutine test_refused

  !> Lines end as the runtime's formatted reads end them (a line feed, a
  !> carriage return and line feed, or a lone carriage return), so rows and
  !> line numbers are those of the former record-by-record reader; a device of
  !> unknown size is read by records and refused at its first byte.
  subroutine test_line_ends(error)
    type(error_type), allocatable, intent(out) :: error
    real(dp), allocatable :: rows(:, :)
    integer, allocatable :: lines(:)
    type(demstep_status_type) :: status
    integer :: unit
    open(newunit=unit, file=table, access="stream", status="replace", action="write")
    write(unit) "1 2"//achar(13)//"3 4"//achar(13)//achar(10)//achar(13)//achar(10)//"5 6"//achar(13)
    close(unit)
    call read_table(table, 2, rows, status, lines=lines)
    call check(error, status%stat, demstep_stat%ok, message=status%message)
    if (allocated(error)) return
    call check(error, size(rows, 2) == 3 .and. all(lines == [1, 2, 4]) .and. rows(2, 3) == 6.0_dp, &
      "three rows on lines 1, 2 and 4")
    if (allocated(error)) return
    open(newunit=unit, file=table, access="stream", status="replace", action="write")
    write(unit) "1 2"//achar(13)//achar(10)//"1 x"//achar(13)
    close(unit)
    call read_table(table, 2, rows, status)
    call expect(error, status, demstep_stat%invalid_input, table//": line 2: cannot read '1 x' as finite numbers")
    if (allocated(error)) return
    call read_table("/dev/zero", 2, rows, status)
    call expect(error, status, demstep_stat%invalid_input, "/dev/zero: line 1: not a text file (byte 0 in column 1)")
  end subroutine test_line_ends

  subroutine test_many_rows(error)
    type(error_type), allocatable, intent(out) :: error
    real(dp), allocatable :: rows(:, :)
    type(demstep_status_type) :: status
    integer, parameter :: n = 100000
    integer :: unit, i
    open(newunit=unit, file=table, status="replace", action="write")
    do i = 1, n
      write(unit, '(i0, 1x, i0, " # row")') i, n - i
    end do
    close(unit)
    call read_table(table, 2, rows, status)
    call check(error, status%stat, demstep_stat%ok, message=status%message)
    if (allocated(error)) return
    call check(error, size(rows, 2), n, message="rows")
    if (allocated(error)) return
    call check(error, all(rows(1, :) == [(real(i, dp), i = 1, n)]) .and. &
      all(rows(2, :) == [(real(n - i, dp), i = 1, n)]), "every value in its place")
  end subroutine test_many_rows

  !> A table above 1 MB is scanned in parts in parallel (cut after line
  !> feeds, each part's lines counted first): its rows, their lines and the
  !> layout are those of one scan of the whole text (`table_scan`,
  !> `table_rows`) on 1 and 2 threads, with LF, CR LF and lone CR line ends,
  !> comments and blank lines throughout and the first row of the layout's
  !> count past the first part; a control byte or an overlong line in the
  !> second half is refused naming its line.
  subroutine test_scan_parts(error)
    type(error_type), allocatable, intent(out) :: error
    integer, parameter :: n = 90000
    real(dp), allocatable :: rows(:, :), ref_rows(:, :)
    integer, allocatable :: lines(:), ref_lines(:)
    character(len=:), allocatable :: text
    type(table_scan_type) :: scan
    type(demstep_status_type) :: status
    integer :: threads, t, fault
    threads = 1
    !$ threads = omp_get_max_threads()
    call write_text(0)
    call read_text_file(table, text, status)
    call check(error, status%stat == demstep_stat%ok .and. len(text) > 1100000, "a text above 1 MB")
    if (allocated(error)) return
    call table_scan(text, table, [3, 4], scan, status)
    call check(error, status%stat, demstep_stat%ok, "one scan: "//status%message)
    if (allocated(error)) return
    call check(error, scan%ncol == 3 .and. scan%first_line == 65003, "the layout's first row: line " &
      //int_text(scan%first_line)//", columns "//int_text(scan%ncol)//" (want 65003, 3)")
    if (allocated(error)) return
    call table_rows(text, table, [3, 4], scan, ref_rows, status, ref_lines)
    call check(error, status%stat, demstep_stat%ok, "one scan's rows: "//status%message)
    if (allocated(error)) return
    do t = 1, 2
      !$ call omp_set_num_threads(t)
      call read_table(table, [3, 4], rows, status, lines)
      call check(error, status%stat, demstep_stat%ok, status%message)
      if (allocated(error)) exit
      call check(error, size(rows, 2) == size(ref_rows, 2) .and. size(rows, 1) == 3, "rows counted as one scan")
      if (allocated(error)) exit
      call check(error, all(rows == ref_rows) .and. all(lines == ref_lines), "rows and lines as one scan's")
      if (allocated(error)) exit
      do fault = 1, 2
        call write_text(fault)
        call read_table(table, [3, 4], rows, status, lines)
        if (fault == 1) then
          call expect(error, status, demstep_stat%invalid_input, table//": line 80001: not a text file (byte 1 " &
            //"in column 3)")
        else
          call expect(error, status, demstep_stat%invalid_input, table//": line 80001: longer than")
        end if
        if (allocated(error)) exit
      end do
      if (allocated(error)) exit
      call write_text(0)
    end do
    !$ call omp_set_num_threads(threads)
  contains
    !> n lines: comments and blank lines by turns up to line 65000, then rows
    !> of 3 numbers with a comment and a blank line every 1000; line ends LF,
    !> CR LF or a lone CR by turns; `fault` 1 puts a control byte, 2 an
    !> overlong line, at line 80001.
    subroutine write_text(fault)
      integer, intent(in) :: fault
      integer :: unit, i
      character(len=40) :: row
      character(len=2) :: ends(3)
      ends = [character(len=2) :: achar(10), achar(13)//achar(10), achar(13)]
      open(newunit=unit, file=table, status="replace", action="write", access="stream", form="unformatted")
      do i = 1, n
        if (mod(i, 1000) == 1 .or. (i <= 65000 .and. mod(i, 2) == 1)) then
          row = "# a comment line"
        else if (mod(i, 1000) == 2 .or. i <= 65000) then
          row = "   "
        else
          write(row, '(i0, 1x, i0, " 0.5 # row")') i, i + 1
        end if
        if (i == 80001 .and. fault == 1) row = "1 "//achar(1)//" 2"
        if (i == 80001 .and. fault == 2) then
          write(unit) repeat("1 ", table_max_line)
        else
          ! (a blank line keeps a space: an empty line after a lone carriage
          ! return would make a carriage return and line feed, one line end)
          write(unit) row(:max(1, len_trim(row)))
        end if
        write(unit) trim(ends(mod(i, 3) + 1))
      end do
      close(unit)
    end subroutine write_text
  end subroutine test_scan_parts

  !> The rows are converted in parallel (OpenMP, each thread a stretch of
  !> rows): with faults in several stretches (1 and 2 threads), the first
  !> in file order is the one refused, whatever its kind; a table whose only
  !> fault lies in its last stretch names that one.
  subroutine test_first_fault(error)
    type(error_type), allocatable, intent(out) :: error
    real(dp), allocatable :: rows(:, :)
    type(demstep_status_type) :: status
    integer, parameter :: n = 40000
    integer :: case, threads, t
    threads = 1
    !$ threads = omp_get_max_threads()
    do t = 1, 2
      !$ call omp_set_num_threads(t)
      do case = 1, 3
        call write_rows(case)
        call read_table(table, 3, rows, status, index_columns=[1, 2])
        select case (case)
        case (1)
          ! (a bad particle number at 5000, a short row at 15000, a word at 39000)
          call expect(error, status, demstep_stat%invalid_input, table//": line 5000: column 2: '2.5' is " &
            //"not an integer (a particle number)")
        case (2)
          call expect(error, status, demstep_stat%invalid_input, table//": line 15000: expected 3 numbers, " &
            //"found 2")
        case (3)
          call expect(error, status, demstep_stat%invalid_input, table//": line 39000: cannot read " &
            //"'3 4 x' as finite numbers")
        end select
        if (allocated(error)) exit
      end do
      if (allocated(error)) exit
    end do
    !$ call omp_set_num_threads(threads)
  contains
    !> Rows "i i+1 0.5", with the faults from `case` on (1: all three).
    subroutine write_rows(case)
      integer, intent(in) :: case
      integer :: unit, i
      open(newunit=unit, file=table, status="replace", action="write")
      do i = 1, n
        if (i == 5000 .and. case <= 1) then
          write(unit, '(a)') "1 2.5 0.5"
        else if (i == 15000 .and. case <= 2) then
          write(unit, '(a)') "1 2"
        else if (i == 39000) then
          write(unit, '(a)') "3 4 x"
        else
          write(unit, '(i0, 1x, i0, " 0.5")') i, i + 1
        end if
      end do
      close(unit)
    end subroutine write_rows
  end subroutine test_first_fault

  !> Particle numbers were read as reals: 4294967297 wrapped around, 1.5 was
  !> caught only by the app and without a line. Now read as integers.
  subroutine test_index_columns(error)
    type(error_type), allocatable, intent(out) :: error
    real(dp), allocatable :: rows(:, :)
    type(demstep_status_type) :: status
    integer :: i
    character(len=20), parameter :: bad(6) = [character(len=20) :: "1.5", "2.0", "1e3", "4294967297", "0", &
      "-2"]
    call write_file(table, [character(len=40) :: "# i j k_n k_t", "1 2 1e4 0.5", "+2,3,2.5e3,1", &
      "2147483647 1 1 1"])
    call read_table(table, 4, rows, status, index_columns=[1, 2])
    call check(error, status%stat, demstep_stat%ok, message=status%message)
    if (allocated(error)) return
    call check(error, all(rows(1:2, :) == reshape([1.0_dp, 2.0_dp, 2.0_dp, 3.0_dp, 2147483647.0_dp, 1.0_dp], &
      [2, 3])) .and. rows(3, 2) == 2500.0_dp, "integers, and the other columns as reals")
    if (allocated(error)) return
    do i = 1, size(bad)
      call write_file(table, [character(len=40) :: "1 2 1e4 0.5", "3 "//trim(bad(i))//" 1e4 0.5"])
      call read_table(table, 4, rows, status, index_columns=[1, 2])
      if (i <= 3) then
        call expect(error, status, demstep_stat%invalid_input, table//": line 2: column 2: '"//trim(bad(i))// &
          "' is not an integer (a particle number)")
      else
        call expect(error, status, demstep_stat%invalid_input, table//": line 2: column 2: particle number '" &
          //trim(bad(i))//"' must lie in [1, 2147483647]")
      end if
      if (allocated(error)) return
      call check(error, index(status%message, new_line("a")) == 0, "one line")
      if (allocated(error)) return
    end do
    ! the same rows without index columns: reals, as before
    call read_table(table, 4, rows, status)
    call check(error, status%stat == demstep_stat%ok .and. rows(2, 2) == -2.0_dp, "no index columns: reals")
  end subroutine test_index_columns

  !> The status code and the exact message.
  subroutine expect(error, status, stat, message)
    type(error_type), allocatable, intent(out) :: error
    type(demstep_status_type), intent(in) :: status
    integer, intent(in) :: stat
    character(len=*), intent(in) :: message
    call check(error, status%stat, stat, message="status for: "//message)
    if (allocated(error)) return
    if (index(status%message, message) /= 1) call test_failed(error, "message '"//status%message// &
      "' does not start with '"//message//"'")
  end subroutine expect

end module test_table_io
