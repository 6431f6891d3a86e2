!> Tests of the text progress reporter.
module test_progress
  use demstep_kinds, only: dp, i8
  use demstep_progress, only: text_progress_type
  use testdrive, only: new_unittest, unittest_type, error_type, check
  implicit none
  private
  public :: collect_progress

contains

  subroutine collect_progress(testsuite)
    type(unittest_type), allocatable, intent(out) :: testsuite(:)
    testsuite = [ &
      new_unittest("silent before the delay", test_silent), &
      new_unittest("lines with the fraction done and a final line", test_lines) &
      ]
  end subroutine collect_progress

  subroutine test_silent(error)
    type(error_type), allocatable, intent(out) :: error
    type(text_progress_type) :: p
    integer :: u, n, ios
    character(len=200) :: line
    open(newunit=u, status="scratch", action="readwrite")
    p = text_progress_type(unit=u, label="t", delay=1.0e6_dp)
    call p%start("steps", 100_i8)
    call p%update(50_i8)
    call p%finish()
    rewind(u)
    n = 0
    do
      read(u, '(a)', iostat=ios) line
      if (ios /= 0) exit
      n = n + 1
    end do
    close(u)
    call check(error, n, 0, "nothing is written before the delay")
  end subroutine test_silent

  subroutine test_lines(error)
    type(error_type), allocatable, intent(out) :: error
    type(text_progress_type) :: p
    integer :: u, ios
    character(len=200) :: first, second
    open(newunit=u, status="scratch", action="readwrite")
    p = text_progress_type(unit=u, label="t", delay=0.0_dp, interval=0.0_dp)
    call p%start("steps", 2000_i8)
    call p%update(5_i8)
    call p%finish()
    rewind(u)
    read(u, '(a)', iostat=ios) first
    read(u, '(a)', iostat=ios) second
    close(u)
    call check(error, index(first, "t: 5 of 2000 steps (0.2 %), about") == 1, &
      "progress line: "//trim(first))
    if (allocated(error)) return
    call check(error, index(second, "t: done in") == 1, "final line: "//trim(second))
  end subroutine test_lines

end module test_progress
