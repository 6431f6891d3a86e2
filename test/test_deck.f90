!> Large decks end to end: long value lists, many assignments, megabyte lines and
!> many foreign groups are read completely and give the right result or the
!> one-line error. Completion and correctness only; timing is in bench/bench_deck.
module test_deck
  use testdrive, only: new_unittest, unittest_type, error_type, check
  use demstep, only: dp, i8, harmonic_error
  use test_support, only: run_app, work_dir, int_str
  use demstep_results, only: result_group_type
  use test_support, only: read_group, take
  implicit none
  private
  public :: collect_deck

  character(len=*), parameter :: nl = new_line("a")
  character(len=*), parameter :: deck = work_dir//"/big_deck.nml"
  !> The largest list a variable may hold (`max_values` of the app).
  integer, parameter :: big = 100000
  !> One megabyte.
  integer, parameter :: mega = 1000000
  character(len=*), parameter :: system_tail = " stiffness = 1e4, n_per_period = 20.0 /"//nl

contains

  subroutine collect_deck(testsuite)
    type(unittest_type), allocatable, intent(out) :: testsuite(:)
    testsuite = [ &
      new_unittest("a list of 1e5 values gives 1e5 results", test_long_list), &
      new_unittest("1e5 values one per line, and 1e5 subscripted items", test_many_items), &
      new_unittest("1e5 assignments of one variable: the last wins", test_repeated), &
      new_unittest("1 MB of blank lines, inside and outside a group", test_blank_lines), &
      new_unittest("a 1 MB number is read, or refused naming the variable", test_long_number), &
      new_unittest("a 1 MB name gives the one-line error naming the group", test_long_name), &
      new_unittest("1e5 foreign groups are skipped and counted", test_foreign_groups) &
      ]
  end subroutine collect_deck

  !> Write `text` as the whole file `path`.
  subroutine write_text(path, text)
    character(len=*), intent(in) :: path, text
    integer :: unit
    call make_work_dir()
    open(newunit=unit, file=path, access="stream", form="unformatted", status="replace", &
      action="write")
    write(unit) text
    close(unit)
  end subroutine write_text

  subroutine make_work_dir()
    integer :: cmdstat, exitstat
    call execute_command_line("mkdir -p "//work_dir, wait=.true., exitstat=exitstat, &
      cmdstat=cmdstat)
  end subroutine make_work_dir

  !> `count` numbers `10 + mod(i, 50)` as "10.0, 11.0, ..." joined by `sep`,
  !> filled into one buffer (each entry is 4 characters plus the separator).
  pure function value_list(count, sep) result(text)
    integer, intent(in) :: count
    character(len=*), intent(in) :: sep
    character(len=:), allocatable :: text
    integer :: i, at, width
    width = 4 + len(sep)
    allocate(character(len=count*width - len(sep)) :: text)
    at = 0
    do i = 1, count
      write(text(at+1:at+4), '(i2, a)') 10 + mod(i - 1, 50), ".0"
      at = at + 4
      if (i < count) then
        text(at+1:at+len(sep)) = sep
        at = at + len(sep)
      end if
    end do
  end function value_list

  !> Expected n_per_period(i) of [[value_list]].
  elemental real(dp) function list_value(i)
    integer, intent(in) :: i
    list_value = real(10 + mod(i - 1, 50), dp)
  end function list_value

  !> Run the app on `deck` with --namelist, expect exit 0 and read back
  !> `&harmonic_error_result` with exactly `count` entries, checked against the library.
  subroutine check_harmonic(error, count, what)
    type(error_type), allocatable, intent(out) :: error
    integer, intent(in) :: count
    character(len=*), intent(in) :: what
    integer :: rc, ios, i, stat_lib
    character(len=:), allocatable :: stdout, stderr
    real(dp), allocatable :: n_per_period(:), lambda(:), n_steps(:), e(:)
    integer, allocatable :: status(:)
    real(dp) :: e_lib
    type(result_group_type) :: harmonic_error_result_fields
    call run_app(deck//" -q --namelist", rc, stdout, stderr)
    call check(error, rc, 0, message=what//": exit status; stderr: "//stderr(1:min(len(stderr), 300)))
    if (allocated(error)) return
    ! one spare element: it must stay unset, so exactly `count` results came back
    allocate(n_per_period(count+1), lambda(count+1), n_steps(count+1), e(count+1), status(count+1))
    n_per_period = -1.0_dp
    call read_group(stdout, "harmonic_error_result", harmonic_error_result_fields, ios)
    if (ios == 0) call take(harmonic_error_result_fields, "n_per_period", n_per_period, ios)
    if (ios == 0) call take(harmonic_error_result_fields, "lambda", lambda, ios)
    if (ios == 0) call take(harmonic_error_result_fields, "n_steps", n_steps, ios)
    if (ios == 0) call take(harmonic_error_result_fields, "e", e, ios)
    if (ios == 0) call take(harmonic_error_result_fields, "status", status, ios)
    call check(error, ios, 0, message=what//": the result namelist reads back")
    if (allocated(error)) return
    call check(error, n_per_period(count+1), -1.0_dp, message=what//": no result beyond the last")
    if (allocated(error)) return
    call check(error, all(n_per_period(1:count) == list_value([(i, i = 1, count)])), &
      what//": every N read in order")
    if (allocated(error)) return
    ! a few results against the library (the app adds nothing to the numbers)
    do i = 1, count, count/7
      call harmonic_error(n_per_period(i), 0.9_dp, 0.5_dp*n_per_period(i), e_lib, stat_lib)
      call check(error, e(i), e_lib, thr=2*epsilon(1.0_dp), rel=.true., message=what//": E as the library")
      if (allocated(error)) return
      call check(error, status(i), stat_lib, message=what//": status")
      if (allocated(error)) return
    end do
  end subroutine check_harmonic

  subroutine test_long_list(error)
    type(error_type), allocatable, intent(out) :: error
    call write_text(deck, "&harmonic_error"//nl//"  n_per_period = "//value_list(big, ", ")//nl// &
      "  lambda = 0.9, steps_fraction = 0.5 /"//nl)
    call check_harmonic(error, big, "one line of 1e5 values")
  end subroutine test_long_list

  subroutine test_many_items(error)
    type(error_type), allocatable, intent(out) :: error
    character(len=:), allocatable :: text
    character(len=32) :: line
    integer :: i, at
    call write_text(deck, "&harmonic_error"//nl//"  n_per_period = "//value_list(big, ","//nl)//nl// &
      "  lambda = 0.9, steps_fraction = 0.5 /"//nl)
    call check_harmonic(error, big, "1e5 lines of values")
    if (allocated(error)) return
    ! n_per_period(i) = v, one assignment each: filled into one buffer
    allocate(character(len=32*big) :: text)
    at = 0
    do i = 1, big
      write(line, '(a, i0, a, f4.1)') "n_per_period(", i, ") = ", list_value(i)
      text(at+1:at+len_trim(line)+1) = trim(line)//nl
      at = at + len_trim(line) + 1
    end do
    call write_text(deck, "&harmonic_error"//nl//text(1:at)//"  lambda = 0.9, steps_fraction = 0.5 /"//nl)
    call check_harmonic(error, big, "1e5 subscripted assignments")
  end subroutine test_many_items

  !> Read back `&system_result` from the app's --namelist output on `deck`.
  subroutine run_system(error, omega, what)
    type(error_type), allocatable, intent(out) :: error
    real(dp), intent(out) :: omega
    character(len=*), intent(in) :: what
    integer :: rc, ios
    character(len=:), allocatable :: stdout, stderr
    real(dp) :: period, dt_critical, dt, n_per_period, growth_factor, theta, period_numerical, &
      contact_time, restitution, max_overlap
    integer :: contact_steps
    logical :: stable
    real(dp) :: dt_recommended
    type(result_group_type) :: system_result_fields
    omega = -1.0_dp
    call run_app(deck//" -q --namelist", rc, stdout, stderr)
    call check(error, rc, 0, message=what//": exit status; stderr: "//stderr(1:min(len(stderr), 300)))
    if (allocated(error)) return
    call read_group(stdout, "system_result", system_result_fields, ios)
    if (ios == 0) call take(system_result_fields, "dt_recommended", dt_recommended, ios)
    if (ios == 0) call take(system_result_fields, "period", period, ios)
    if (ios == 0) call take(system_result_fields, "omega", omega, ios)
    if (ios == 0) call take(system_result_fields, "dt_critical", dt_critical, ios)
    if (ios == 0) call take(system_result_fields, "dt", dt, ios)
    if (ios == 0) call take(system_result_fields, "n_per_period", n_per_period, ios)
    if (ios == 0) call take(system_result_fields, "stable", stable, ios)
    if (ios == 0) call take(system_result_fields, "growth_factor", growth_factor, ios)
    if (ios == 0) call take(system_result_fields, "theta", theta, ios)
    if (ios == 0) call take(system_result_fields, "period_numerical", period_numerical, ios)
    if (ios == 0) call take(system_result_fields, "contact_steps", contact_steps, ios)
    if (ios == 0) call take(system_result_fields, "contact_time", contact_time, ios)
    if (ios == 0) call take(system_result_fields, "restitution", restitution, ios)
    if (ios == 0) call take(system_result_fields, "max_overlap", max_overlap, ios)
    call check(error, ios, 0, message=what//": the result namelist reads back")
  end subroutine run_system

  subroutine test_repeated(error)
    type(error_type), allocatable, intent(out) :: error
    real(dp) :: omega
    ! omega = sqrt(K/M): with K = 1e4 and the last mass 4, omega is 50 to rounding
    call write_text(deck, "&system"//nl//repeat("  mass = 1.0"//nl, big)//"  mass = 4.0"//nl//system_tail)
    call run_system(error, omega, "1e5 times mass")
    if (allocated(error)) return
    call check(error, omega, 50.0_dp, thr=4*epsilon(1.0_dp), rel=.true., message="the last mass counts")
  end subroutine test_repeated

  subroutine test_blank_lines(error)
    type(error_type), allocatable, intent(out) :: error
    real(dp) :: omega
    integer :: rc
    character(len=:), allocatable :: stdout, stderr
    ! outside: the group's line number in the report counts every line before it
    call write_text(deck, repeat(nl, mega)//"&system mass = 1.0,"//system_tail//repeat(nl, mega))
    call run_app(deck//" -q", rc, stdout, stderr)
    call check(error, rc, 0, message="1 MB of blank lines around the group: "//stderr(1:min(len(stderr), 300)))
    if (allocated(error)) return
    call check(error, index(stdout, "&system (line 1000001)") > 0, "group line after 1e6 blank lines")
    if (allocated(error)) return
    ! inside, between two assignments, and a 1 MB line of blanks
    call write_text(deck, "&system mass = 1.0"//repeat(nl, mega)//system_tail)
    call run_system(error, omega, "1 MB of blank lines in the group")
    if (allocated(error)) return
    call check(error, omega, 100.0_dp, thr=4*epsilon(1.0_dp), rel=.true., message="omega = sqrt(K/M)")
    if (allocated(error)) return
    call write_text(deck, "&system mass = 1.0,"//repeat(" ", mega)//system_tail)
    call run_system(error, omega, "a 1 MB line of blanks")
    if (allocated(error)) return
    call check(error, omega, 100.0_dp, thr=4*epsilon(1.0_dp), rel=.true., message="omega = sqrt(K/M)")
  end subroutine test_blank_lines

  subroutine test_long_number(error)
    type(error_type), allocatable, intent(out) :: error
    real(dp) :: omega
    ! 4.000...0 with 1e6 zeros is 4
    call write_text(deck, "&system mass = 4."//repeat("0", mega)//","//system_tail)
    call run_system(error, omega, "1 MB number")
    if (allocated(error)) return
    call check(error, omega, 50.0_dp, thr=4*epsilon(1.0_dp), rel=.true., message="the number is 4")
    if (allocated(error)) return
    ! 1e6 digits overflow the double range: refused naming the variable
    call expect_one_line(error, "&system mass = 1"//repeat("3", mega)//","//system_tail, &
      "&system: mass: must be finite and > 0")
    if (allocated(error)) return
    ! a 1 MB list for a scalar: the value is quoted in short
    call expect_one_line(error, "&system mass = "//repeat("1.0, ", mega/5)//system_tail, &
      "&system: mass: cannot read '1.0, 1.0,")
  end subroutine test_long_number

  subroutine test_long_name(error)
    type(error_type), allocatable, intent(out) :: error
    call expect_one_line(error, "&system "//repeat("m", mega)//" = 1.0,"//system_tail, &
      "&system: line 1: variable name 'mmm")
    if (allocated(error)) return
    call expect_one_line(error, "&system "//repeat("m", mega)//system_tail, &
      "&system: line 1: text before the first assignment: 'mmm")
    if (allocated(error)) return
    call expect_one_line(error, "&"//repeat("g", mega)//" a = 1 /"//nl//"&system mass = 1.0,"//system_tail, &
      "line 1: group name 'ggg")
  end subroutine test_long_name

  subroutine test_foreign_groups(error)
    type(error_type), allocatable, intent(out) :: error
    integer :: rc
    character(len=:), allocatable :: stdout, stderr
    real(dp) :: omega
    call write_text(deck, repeat("&solver steps = 10, name = 'a / b' /"//nl, big)// &
      "&system mass = 1.0,"//system_tail//"&post_processing every = 3 /"//nl)
    call run_app(deck//" -q", rc, stdout, stderr)
    call check(error, rc, 0, message="1e5 foreign groups: "//stderr(1:min(len(stderr), 300)))
    if (allocated(error)) return
    call check(error, index(stdout, "&system (line 100001)") > 0, "the known group is processed")
    if (allocated(error)) return
    call check(error, index(stdout, "skipped groups (not demstep's): &solver (line 1) &solver (line 2)") > 0, &
      "the first skipped groups are listed")
    if (allocated(error)) return
    ! 100001 foreign groups, 20 listed by name
    call check(error, index(stdout, "&solver (line 20) and 99981 more") > 0, "the rest are counted")
    if (allocated(error)) return
    call check(error, index(stdout, "&solver (line 21)") == 0, "the listing stops at 20")
    if (allocated(error)) return
    call run_system(error, omega, "1e5 foreign groups")
    if (allocated(error)) return
    call check(error, omega, 100.0_dp, thr=4*epsilon(1.0_dp), rel=.true., message="omega = sqrt(K/M)")
  end subroutine test_foreign_groups

  !> The deck `text` fails with exit 2 and one short line on stderr holding `expected`.
  subroutine expect_one_line(error, text, expected)
    type(error_type), allocatable, intent(out) :: error
    character(len=*), intent(in) :: text, expected
    integer :: rc
    character(len=:), allocatable :: stdout, stderr
    call write_text(deck, text)
    call run_app(deck//" -q", rc, stdout, stderr)
    call check(error, rc, 2, message="exit status for "//expected)
    if (allocated(error)) return
    call check(error, index(stderr, expected) > 0, "message '"//expected//"' in: "// &
      stderr(1:min(len(stderr), 300)))
    if (allocated(error)) return
    ! one line, and the quoted text cut short
    call check(error, index(stderr, nl) == len(stderr) .and. len(stderr) < 300, &
      "one short line on stderr, got "//int_str(int(len(stderr), i8))//" characters")
  end subroutine expect_one_line

end module test_deck
