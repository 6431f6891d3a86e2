!> Helpers shared by the test suites: formatting, NaN, and running the app.
module test_support
  use demstep, only: dp, i8
  implicit none
  private
  public :: ieee_nan, real_str, int_str, app_path, run_app, write_file, read_file, &
    file_exists, work_dir

  !> Scratch directory of the app tests, relative to the project root.
  character(len=*), parameter :: work_dir = "build/demstep-test-files"

contains

  !> A quiet NaN.
  function ieee_nan() result(x)
    use, intrinsic :: ieee_arithmetic, only: ieee_value, ieee_quiet_nan
    real(dp) :: x
    x = ieee_value(x, ieee_quiet_nan)
  end function ieee_nan

  pure function real_str(x) result(text)
    real(dp), intent(in) :: x
    character(len=:), allocatable :: text
    character(len=32) :: buf
    write(buf, '(g0.8)') x
    text = trim(adjustl(buf))
  end function real_str

  pure function int_str(i) result(text)
    integer(i8), intent(in) :: i
    character(len=:), allocatable :: text
    character(len=24) :: buf
    write(buf, '(i0)') i
    text = trim(buf)
  end function int_str

  !> The demstep executable built beside this tester: fpm puts tests in
  !> build/<profile>/test/ and apps in build/<profile>/app/.
  function app_path() result(path)
    character(len=:), allocatable :: path
    character(len=1024) :: arg0
    integer :: k
    call get_command_argument(0, arg0)
    k = index(arg0, "/test/", back=.true.)
    if (k == 0) then
      path = "demstep"
    else
      path = arg0(1:k)//"app/demstep"
    end if
  end function app_path

  !> Run the app with `args` (a shell word list); capture stdout and stderr.
  subroutine run_app(args, exitstat, stdout, stderr)
    character(len=*), intent(in) :: args
    integer, intent(out) :: exitstat
    character(len=:), allocatable, intent(out) :: stdout, stderr
    integer :: cmdstat
    call execute_command_line("mkdir -p "//work_dir, wait=.true.)
    call execute_command_line(app_path()//" "//args//" >"//work_dir//"/stdout 2>" &
      //work_dir//"/stderr", wait=.true., exitstat=exitstat, cmdstat=cmdstat)
    if (cmdstat /= 0) exitstat = -1000
    call read_file(work_dir//"/stdout", stdout)
    call read_file(work_dir//"/stderr", stderr)
  end subroutine run_app

  !> Write lines to a file (replacing it).
  subroutine write_file(path, lines)
    character(len=*), intent(in) :: path
    character(len=*), intent(in) :: lines(:)
    integer :: unit, i
    call execute_command_line("mkdir -p "//work_dir, wait=.true.)
    open(newunit=unit, file=path, status="replace", action="write")
    do i = 1, size(lines)
      write(unit, '(a)') trim(lines(i))
    end do
    close(unit)
  end subroutine write_file

  !> A whole file as a string ("" when missing).
  subroutine read_file(path, text)
    character(len=*), intent(in) :: path
    character(len=:), allocatable, intent(out) :: text
    integer :: unit, length, ios
    text = ""
    open(newunit=unit, file=path, access="stream", form="unformatted", status="old", &
      action="read", iostat=ios)
    if (ios /= 0) return
    inquire(unit=unit, size=length)
    if (length > 0) then
      deallocate(text)
      allocate(character(len=length) :: text)
      read(unit, iostat=ios) text
    end if
    close(unit)
  end subroutine read_file

  logical function file_exists(path)
    character(len=*), intent(in) :: path
    inquire(file=path, exist=file_exists)
  end function file_exists

end module test_support
