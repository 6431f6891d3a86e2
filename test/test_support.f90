!> Helpers shared by the test suites: formatting, NaN, and running the app.
module test_support
  use demstep, only: dp, i8, spring_type, new_spring, spring_contact, discrete_contact_type, &
    demstep_status_type, demstep_stat
  use demstep_results, only: result_group_type, parse_result, result_get
  use, intrinsic :: iso_fortran_env, only: qp => real128
  implicit none
  private
  public :: read_group, take
  public :: sinpi_q, reference, reference_steps, unit_contact
  public :: result_value
  public :: count_lines, remove, ieee_nan, real_str, int_str, app_path, run_app, write_file, read_file, &
    file_exists, work_dir, seed_fixed

  !> A result group from an open unit (its remaining lines) or from text.
  interface read_group
    module procedure :: read_group_unit, read_group_text
  end interface read_group

  !> One field of a result group into a variable, as a namelist read would: left
  !> as it was when absent; `ios` becomes 1 when the field does not convert.
  interface take
    module procedure :: take_real, take_int, take_int64, take_logical, take_char, take_reals, take_ints, &
      take_logicals, take_chars, take_int64s, take_reals2
  end interface take

  real(qp), parameter :: pi_q = 3.14159265358979323846264338327950288_qp

  !> Scratch directory of the app tests, relative to the project root.
  character(len=*), parameter :: work_dir = "build/demstep-test-files"

contains

  !> Seed the intrinsic generator with a fixed sequence from k (a test's data
  !> the same on every run).
  subroutine seed_fixed(k)
    integer, intent(in) :: k
    integer :: n
    integer, allocatable :: s(:)
    call random_seed(size=n)
    allocate(s(n))
    s = 104729*k + [(n, n = 1, size(s))]
    call random_seed(put=s)
  end subroutine seed_fixed

  !> The value of a scalar `KEY=` in a result file's text (as the app writes
  !> its namelists: upper-case names), -1 when it is not there.
  real(dp) function result_value(text, key) result(x)
    character(len=*), intent(in) :: text, key
    integer :: k, ios
    x = -1.0_dp
    k = index(text, key//"=")
    if (k == 0) return
    read(text(k + len(key) + 1:), *, iostat=ios) x
    if (ios /= 0) x = -1.0_dp
  end function result_value

  !> sin(pi x) with x reduced modulo 2 in quad.
  elemental real(qp) function sinpi_q(x)
    real(qp), intent(in) :: x
    sinpi_q = sin(pi_q*(x - 2.0_qp*anint(0.5_qp*x)))
  end function sinpi_q

  !> Quad reference of E by the closed form. The phases n c/N are formed in quad:
  !> n (<= 2^53) times c (53 bits) is exact in 113 bits; the division rounds at
  !> 1e-34 relative. `pole` is the relative distance of n lambda/N or
  !> (n+1) lambda/N to the nearest integer.
  pure subroutine reference(big_n, lambda, n, e, pole)
    real(dp), intent(in) :: big_n, lambda, n
    real(qp), intent(out) :: e, pole
    real(qp) :: nq, lq, bq, s1, s2, t1, t2
    nq = n
    lq = lambda
    bq = big_n
    t1 = nq*lq/bq
    t2 = (nq + 1.0_qp)*lq/bq
    pole = min(abs(t1 - anint(t1))/t1, abs(t2 - anint(t2))/t2)
    s1 = sinpi_q(nq/bq)*sinpi_q((nq + 1.0_qp)/bq)/sinpi_q(1.0_qp/bq)
    s2 = sinpi_q(t1)*sinpi_q(t2)/sinpi_q(lq/bq)
    e = 1.0_qp - s1/(lq*s2)
  end subroutine reference

  !> Quad reference of E with n = f N (fraction) or a fixed n, N in quad:
  !> for root bisection in quad, where N itself carries more than 53 bits.
  pure real(qp) function reference_steps(big_n, lambda, fixed, value) result(e)
    real(qp), intent(in) :: big_n
    real(dp), intent(in) :: lambda, value
    logical, intent(in) :: fixed
    real(qp) :: nq, lq
    nq = merge(real(value, qp), real(value, qp)*big_n, fixed)
    lq = lambda
    e = 1.0_qp - (sinpi_q(nq/big_n)*sinpi_q((nq + 1.0_qp)/big_n)/sinpi_q(1.0_qp/big_n)) &
      /(lq*sinpi_q(nq*lq/big_n)*sinpi_q((nq + 1.0_qp)*lq/big_n)/sinpi_q(lq/big_n))
  end function reference_steps


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
  !> `env` (say "PATH=/nonexistent") is put before the command; with `in_work_dir`
  !> the app runs in the scratch directory (file arguments then relative to it).
  subroutine run_app(args, exitstat, stdout, stderr, env, in_work_dir)
    character(len=*), intent(in) :: args
    integer, intent(out) :: exitstat
    character(len=:), allocatable, intent(out) :: stdout, stderr
    character(len=*), intent(in), optional :: env
    logical, intent(in), optional :: in_work_dir
    integer :: cmdstat, length
    character(len=:), allocatable :: prefix, root
    character(len=4096) :: pwd
    prefix = ""
    if (present(env)) prefix = env//" "
    call get_environment_variable("PWD", pwd, length)
    root = trim(pwd)//"/"
    if (present(in_work_dir)) then
      if (in_work_dir) prefix = "cd "//work_dir//" && "//prefix
    end if
    call execute_command_line("mkdir -p "//work_dir, wait=.true., cmdstat=cmdstat)
    call execute_command_line(prefix//root//app_path()//" "//args//" >"//root//work_dir// &
      "/stdout 2>"//root//work_dir//"/stderr", wait=.true., exitstat=exitstat, cmdstat=cmdstat)
    if (cmdstat /= 0) exitstat = -1000
    call read_file(work_dir//"/stdout", stdout)
    call read_file(work_dir//"/stderr", stderr)
  end subroutine run_app

  !> Write lines to a file (replacing it).
  subroutine write_file(path, lines)
    character(len=*), intent(in) :: path
    character(len=*), intent(in) :: lines(:)
    integer :: unit, i, cmdstat
    ! (cmdstat: a missing shell would otherwise end the test program)
    call execute_command_line("mkdir -p "//work_dir, wait=.true., cmdstat=cmdstat)
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

  !> The contact of the unit spring (M = K = 1, so omega dt = dt) at h = omega dt,
  !> onset 1: `spring_contact` with h formed exactly as given.
  subroutine unit_contact(h, contact, status)
    real(dp), intent(in) :: h
    type(discrete_contact_type), intent(out) :: contact
    type(demstep_status_type), intent(out) :: status
    type(spring_type) :: unit
    call new_spring(unit, 1.0_dp, 1.0_dp, status)
    if (status%stat /= demstep_stat%ok) return
    call spring_contact(unit, h, contact, status)
  end subroutine unit_contact

  !> Lines in a text: its line feeds.
  pure integer function count_lines(text)
    character(len=*), intent(in) :: text
    integer :: i
    count_lines = 0
    do i = 1, len(text)
      if (text(i:i) == new_line("a")) count_lines = count_lines + 1
    end do
  end function count_lines

  !> Delete a file if it exists.
  subroutine remove(path)
    character(len=*), intent(in) :: path
    integer :: unit, ios
    open(newunit=unit, file=path, status="old", iostat=ios)
    if (ios == 0) close(unit, status="delete")
  end subroutine remove

  !> Group `name` of the result text left on `unit`; `ios` 0 when found.
  subroutine read_group_unit(unit, name, fields, ios)
    integer, intent(in) :: unit
    character(len=*), intent(in) :: name
    type(result_group_type), intent(out) :: fields
    integer, intent(out) :: ios
    character(len=4096) :: line
    character(len=:), allocatable :: text
    integer :: rc
    text = ""
    do
      read(unit, '(a)', iostat=rc) line
      if (rc /= 0) exit
      text = text//trim(line)//new_line("a")
    end do
    call read_group_text(text, name, fields, ios)
  end subroutine read_group_unit

  !> Group `name` of result text; `ios` 0 when found.
  subroutine read_group_text(text, name, fields, ios)
    character(len=*), intent(in) :: text, name
    type(result_group_type), intent(out) :: fields
    integer, intent(out) :: ios
    type(demstep_status_type) :: status
    call parse_result(text, name, fields, status)
    ios = merge(0, 1, status%stat == demstep_stat%ok)
  end subroutine read_group_text

  !> ios 1 for a field that is there but does not convert.
  subroutine fold(status, ios)
    type(demstep_status_type), intent(in) :: status
    integer, intent(inout) :: ios
    if (status%stat == demstep_stat%invalid_input) ios = 1
  end subroutine fold

  subroutine take_real(fields, name, value, ios)
    type(result_group_type), intent(in) :: fields
    character(len=*), intent(in) :: name
    real(dp), intent(inout) :: value
    integer, intent(inout) :: ios
    type(demstep_status_type) :: status
    call result_get(fields, name, value, status)
    call fold(status, ios)
  end subroutine take_real

  subroutine take_int(fields, name, value, ios)
    type(result_group_type), intent(in) :: fields
    character(len=*), intent(in) :: name
    integer, intent(inout) :: value
    integer, intent(inout) :: ios
    type(demstep_status_type) :: status
    call result_get(fields, name, value, status)
    call fold(status, ios)
  end subroutine take_int

  subroutine take_int64(fields, name, value, ios)
    type(result_group_type), intent(in) :: fields
    character(len=*), intent(in) :: name
    integer(i8), intent(inout) :: value
    integer, intent(inout) :: ios
    type(demstep_status_type) :: status
    call result_get(fields, name, value, status)
    call fold(status, ios)
  end subroutine take_int64

  subroutine take_logical(fields, name, value, ios)
    type(result_group_type), intent(in) :: fields
    character(len=*), intent(in) :: name
    logical, intent(inout) :: value
    integer, intent(inout) :: ios
    type(demstep_status_type) :: status
    call result_get(fields, name, value, status)
    call fold(status, ios)
  end subroutine take_logical

  !> A text field, or a list of texts into an array of fixed-length texts.
  subroutine take_char(fields, name, value, ios)
    type(result_group_type), intent(in) :: fields
    character(len=*), intent(in) :: name
    character(len=*), intent(inout) :: value
    integer, intent(inout) :: ios
    type(demstep_status_type) :: status
    character(len=:), allocatable :: text
    call result_get(fields, name, text, status)
    call fold(status, ios)
    if (status%stat == demstep_stat%ok) value = text
  end subroutine take_char

  !> A list into the leading elements of a fixed array (the rest left as they were).
  subroutine take_reals(fields, name, value, ios)
    type(result_group_type), intent(in) :: fields
    character(len=*), intent(in) :: name
    real(dp), intent(inout) :: value(:)
    integer, intent(inout) :: ios
    type(demstep_status_type) :: status
    real(dp), allocatable :: got(:)
    integer :: n
    call result_get(fields, name, got, status)
    call fold(status, ios)
    if (status%stat /= demstep_stat%ok) return
    n = min(size(got), size(value))
    if (size(got) > size(value)) ios = 1
    value(:n) = got(:n)
  end subroutine take_reals

  subroutine take_ints(fields, name, value, ios)
    type(result_group_type), intent(in) :: fields
    character(len=*), intent(in) :: name
    integer, intent(inout) :: value(:)
    integer, intent(inout) :: ios
    type(demstep_status_type) :: status
    integer, allocatable :: got(:)
    integer :: n
    call result_get(fields, name, got, status)
    call fold(status, ios)
    if (status%stat /= demstep_stat%ok) return
    n = min(size(got), size(value))
    if (size(got) > size(value)) ios = 1
    value(:n) = got(:n)
  end subroutine take_ints

  subroutine take_int64s(fields, name, value, ios)
    type(result_group_type), intent(in) :: fields
    character(len=*), intent(in) :: name
    integer(i8), intent(inout) :: value(:)
    integer, intent(inout) :: ios
    type(demstep_status_type) :: status
    integer(i8), allocatable :: got(:)
    integer :: n
    call result_get(fields, name, got, status)
    call fold(status, ios)
    if (status%stat /= demstep_stat%ok) return
    n = min(size(got), size(value))
    if (size(got) > size(value)) ios = 1
    value(:n) = got(:n)
  end subroutine take_int64s

  subroutine take_logicals(fields, name, value, ios)
    type(result_group_type), intent(in) :: fields
    character(len=*), intent(in) :: name
    logical, intent(inout) :: value(:)
    integer, intent(inout) :: ios
    type(demstep_status_type) :: status
    call result_get(fields, name, value, status)
    call fold(status, ios)
  end subroutine take_logicals

  subroutine take_chars(fields, name, value, ios)
    type(result_group_type), intent(in) :: fields
    character(len=*), intent(in) :: name
    character(len=*), intent(inout) :: value(:)
    integer, intent(inout) :: ios
    type(demstep_status_type) :: status
    call result_get(fields, name, value, status)
    call fold(status, ios)
  end subroutine take_chars

  !> A list into a rank-2 array in array element order, as a namelist read fills it.
  subroutine take_reals2(fields, name, value, ios)
    type(result_group_type), intent(in) :: fields
    character(len=*), intent(in) :: name
    real(dp), intent(inout) :: value(:, :)
    integer, intent(inout) :: ios
    real(dp) :: flat(size(value))
    flat = reshape(value, [size(value)])
    call take_reals(fields, name, flat, ios)
    value = reshape(flat, shape(value))
  end subroutine take_reals2

end module test_support
