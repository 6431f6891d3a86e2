!> demstep's unit-test harness.
!>
!> Written for demstep to the public API of fortran-lang/test-drive (the names and
!> argument lists of its procedures and types), so that a project can switch to the
!> upstream package by changing one line of fpm.toml. The implementation is our own.
module testdrive
  use, intrinsic :: iso_fortran_env, only: real64, int32, int64
  use, intrinsic :: ieee_arithmetic, only: ieee_is_nan
  implicit none
  private

  public :: error_type, unittest_type, testsuite_type
  public :: test_interface, collect_interface
  public :: new_unittest, new_testsuite
  public :: run_testsuite, run_selected, select_suite, select_test, get_argument
  public :: check, test_failed, skip_test

  integer, parameter :: dp = real64
  !> Status of a passing test.
  integer, parameter :: success = 0
  !> Status of a failed check.
  integer, parameter :: fatal = 1
  !> Status of a skipped test.
  integer, parameter :: skipped = 77

  !> Outcome of a failed or skipped test; unallocated means the test passed.
  type :: error_type
    !> One of success, fatal or skipped.
    integer :: stat = success
    !> What went wrong, or why the test was skipped.
    character(len=:), allocatable :: message
  end type error_type

  abstract interface
    !> A single test: leaves `error` unallocated on success.
    subroutine test_interface(error)
      import :: error_type
      type(error_type), allocatable, intent(out) :: error
    end subroutine test_interface
  end interface

  !> A named test.
  type :: unittest_type
    character(len=:), allocatable :: name
    procedure(test_interface), pointer, nopass :: test => null()
    !> The test is expected to fail.
    logical :: should_fail = .false.
  end type unittest_type

  abstract interface
    !> Returns the tests of one suite.
    subroutine collect_interface(testsuite)
      import :: unittest_type
      type(unittest_type), allocatable, intent(out) :: testsuite(:)
    end subroutine collect_interface
  end interface

  !> A named collection of tests.
  type :: testsuite_type
    character(len=:), allocatable :: name
    procedure(collect_interface), pointer, nopass :: collect => null()
  end type testsuite_type

  !> Compare values or assert a condition; allocates `error` on failure.
  interface check
    module procedure :: check_condition
    module procedure :: check_status
    module procedure :: check_logical
    module procedure :: check_int32
    module procedure :: check_int64
    module procedure :: check_string
    module procedure :: check_real_dp
  end interface check

contains

  !> Create a test from a name and a procedure.
  function new_unittest(name, test, should_fail) result(self)
    character(len=*), intent(in) :: name
    procedure(test_interface) :: test
    logical, intent(in), optional :: should_fail
    type(unittest_type) :: self
    self%name = name
    self%test => test
    if (present(should_fail)) self%should_fail = should_fail
  end function new_unittest

  !> Create a suite from a name and a collector.
  function new_testsuite(name, collect) result(self)
    character(len=*), intent(in) :: name
    procedure(collect_interface) :: collect
    type(testsuite_type) :: self
    self%name = name
    self%collect => collect
  end function new_testsuite

  !> Run every test of a suite, print one line per test to `unit` and add the
  !> number of failed tests to `stat`. `parallel` is accepted for compatibility.
  subroutine run_testsuite(collect, unit, stat, parallel)
    procedure(collect_interface) :: collect
    integer, intent(in) :: unit
    integer, intent(inout) :: stat
    logical, intent(in), optional :: parallel
    type(unittest_type), allocatable :: tests(:)
    integer :: i
    if (present(parallel)) continue
    call collect(tests)
    do i = 1, size(tests)
      call run_unittest(tests(i), unit, stat)
    end do
  end subroutine run_testsuite

  !> Run the test called `name` of a suite; `stat` becomes negative if there is none.
  subroutine run_selected(collect, name, unit, stat)
    procedure(collect_interface) :: collect
    character(len=*), intent(in) :: name
    integer, intent(in) :: unit
    integer, intent(inout) :: stat
    type(unittest_type), allocatable :: tests(:)
    integer :: i
    call collect(tests)
    i = select_test(tests, name)
    if (i >= 1 .and. i <= size(tests)) then
      call run_unittest(tests(i), unit, stat)
    else
      write(unit, '(a)') "no test named '"//name//"'; available:"
      do i = 1, size(tests)
        write(unit, '(2x, a)') tests(i)%name
      end do
      stat = -1
    end if
  end subroutine run_selected

  !> Index of the suite called `name`, or size(suites) + 1.
  pure function select_suite(suites, name) result(pos)
    type(testsuite_type), intent(in) :: suites(:)
    character(len=*), intent(in) :: name
    integer :: pos
    do pos = 1, size(suites)
      if (suites(pos)%name == name) return
    end do
    pos = size(suites) + 1
  end function select_suite

  !> Index of the test called `name`, or size(tests) + 1.
  pure function select_test(tests, name) result(pos)
    type(unittest_type), intent(in) :: tests(:)
    character(len=*), intent(in) :: name
    integer :: pos
    do pos = 1, size(tests)
      if (tests(pos)%name == name) return
    end do
    pos = size(tests) + 1
  end function select_test

  !> Command-line argument `idx`, left unallocated when absent.
  subroutine get_argument(idx, arg)
    integer, intent(in) :: idx
    character(len=:), allocatable, intent(out) :: arg
    integer :: length, stat
    if (idx > command_argument_count()) return
    call get_command_argument(idx, length=length, status=stat)
    if (stat /= 0) return
    allocate(character(len=length) :: arg)
    if (length > 0) call get_command_argument(idx, arg, status=stat)
    if (stat /= 0) deallocate(arg)
  end subroutine get_argument

  !> Run one test and report it on one line.
  subroutine run_unittest(test, unit, stat)
    type(unittest_type), intent(in) :: test
    integer, intent(in) :: unit
    integer, intent(inout) :: stat
    type(error_type), allocatable :: error
    logical :: failed
    character(len=:), allocatable :: label
    call test%test(error)
    if (allocated(error)) then
      if (error%stat == skipped) then
        write(unit, '(2x, a, 1x, a)') "[SKIP]", test%name//": "//message_of(error)
        return
      end if
    end if
    failed = allocated(error) .neqv. test%should_fail
    if (failed) then
      stat = stat + 1
      label = "[FAIL]"
    else
      label = "[PASS]"
    end if
    if (allocated(error) .and. failed) then
      write(unit, '(2x, a, 1x, a)') label, test%name//": "//message_of(error)
    else if (failed) then
      write(unit, '(2x, a, 1x, a)') label, test%name//": expected to fail, but passed"
    else
      write(unit, '(2x, a, 1x, a)') label, test%name
    end if
  end subroutine run_unittest

  pure function message_of(error) result(text)
    type(error_type), intent(in) :: error
    character(len=:), allocatable :: text
    if (allocated(error%message)) then
      text = error%message
    else
      text = "(no message)"
    end if
  end function message_of

  !> Mark the test as failed.
  subroutine test_failed(error, message, more)
    type(error_type), allocatable, intent(out) :: error
    character(len=*), intent(in) :: message
    character(len=*), intent(in), optional :: more
    call set_error(error, fatal, message, more)
  end subroutine test_failed

  !> Mark the test as skipped; return right after calling it.
  subroutine skip_test(error, message, more)
    type(error_type), allocatable, intent(out) :: error
    character(len=*), intent(in) :: message
    character(len=*), intent(in), optional :: more
    call set_error(error, skipped, message, more)
  end subroutine skip_test

  subroutine set_error(error, stat, message, more)
    type(error_type), allocatable, intent(out) :: error
    integer, intent(in) :: stat
    character(len=*), intent(in) :: message
    character(len=*), intent(in), optional :: more
    allocate(error)
    error%stat = stat
    if (present(more)) then
      error%message = message//" ("//more//")"
    else
      error%message = message
    end if
  end subroutine set_error

  !> Fails unless `expression` holds.
  subroutine check_condition(error, expression, message, more)
    type(error_type), allocatable, intent(out) :: error
    logical, intent(in) :: expression
    character(len=*), intent(in), optional :: message, more
    if (expression) return
    call fail(error, "condition not met", message, more)
  end subroutine check_condition

  !> Fails unless `stat` is zero.
  subroutine check_status(error, stat, message, more)
    type(error_type), allocatable, intent(out) :: error
    integer, intent(in) :: stat
    character(len=*), intent(in), optional :: message, more
    if (stat == success) return
    call fail(error, "non-zero status "//itoa(int(stat, int64)), message, more)
  end subroutine check_status

  !> Fails unless two logicals agree.
  subroutine check_logical(error, actual, expected, message, more)
    type(error_type), allocatable, intent(out) :: error
    logical, intent(in) :: actual, expected
    character(len=*), intent(in), optional :: message, more
    character(len=*), parameter :: word(0:1) = ["F", "T"]
    if (actual .eqv. expected) return
    call fail(error, "expected "//word(merge(1, 0, expected))//", got " &
      //word(merge(1, 0, actual)), message, more)
  end subroutine check_logical

  !> Fails unless two default integers are equal.
  subroutine check_int32(error, actual, expected, message, more)
    type(error_type), allocatable, intent(out) :: error
    integer(int32), intent(in) :: actual, expected
    character(len=*), intent(in), optional :: message, more
    if (actual == expected) return
    call fail(error, "expected "//itoa(int(expected, int64))//", got " &
      //itoa(int(actual, int64)), message, more)
  end subroutine check_int32

  !> Fails unless two 64-bit integers are equal.
  subroutine check_int64(error, actual, expected, message, more)
    type(error_type), allocatable, intent(out) :: error
    integer(int64), intent(in) :: actual, expected
    character(len=*), intent(in), optional :: message, more
    if (actual == expected) return
    call fail(error, "expected "//itoa(expected)//", got "//itoa(actual), message, more)
  end subroutine check_int64

  !> Fails unless two strings are equal.
  subroutine check_string(error, actual, expected, message, more)
    type(error_type), allocatable, intent(out) :: error
    character(len=*), intent(in) :: actual, expected
    character(len=*), intent(in), optional :: message, more
    if (actual == expected) return
    call fail(error, "expected '"//expected//"', got '"//actual//"'", message, more)
  end subroutine check_string

  !> Fails when |actual - expected| > thr, or > thr*|expected| with rel;
  !> `thr` defaults to epsilon, and a NaN always fails.
  subroutine check_real_dp(error, actual, expected, message, more, thr, rel)
    type(error_type), allocatable, intent(out) :: error
    real(dp), intent(in) :: actual, expected
    character(len=*), intent(in), optional :: message, more
    real(dp), intent(in), optional :: thr
    logical, intent(in), optional :: rel
    real(dp) :: tol, diff
    logical :: relative
    character(len=160) :: text
    tol = epsilon(expected)
    if (present(thr)) tol = thr
    relative = .false.
    if (present(rel)) relative = rel
    diff = abs(actual - expected)
    if (relative) diff = diff/abs(expected)
    if (.not. (ieee_is_nan(actual) .or. ieee_is_nan(expected) .or. diff > tol)) return
    write(text, '(a, es24.16e3, a, es24.16e3, a, a, es9.2e3, a, es9.2e3)') &
      "expected", expected, ", got", actual, merge(", rel diff", ", abs diff", relative), &
      " ", diff, " > thr", tol
    call fail(error, trim(text), message, more)
  end subroutine check_real_dp

  subroutine fail(error, default, message, more)
    type(error_type), allocatable, intent(out) :: error
    character(len=*), intent(in) :: default
    character(len=*), intent(in), optional :: message, more
    if (present(message)) then
      call test_failed(error, message//": "//default, more)
    else
      call test_failed(error, default, more)
    end if
  end subroutine fail

  pure function itoa(i) result(text)
    integer(int64), intent(in) :: i
    character(len=:), allocatable :: text
    character(len=24) :: buf
    write(buf, '(i0)') i
    text = trim(buf)
  end function itoa

end module testdrive
