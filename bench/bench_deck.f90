!> Benchmark of reading large decks: the library's scan_namelist on the deck text in
!> memory, and the demstep app end to end (process start, read, check, compute,
!> report; output to /dev/null), for decks of size n = 1e3, 1e4, 1e5.
!> Median of several runs, in milliseconds: wall time, and for the app also the CPU
!> time (user + system) of the child processes from getrusage (POSIX), which a
!> busy machine does not inflate.
!> Run: fpm run --profile release --example bench_deck
!> (the app must be built with the same profile: fpm build --profile release).
program bench_deck
  use, intrinsic :: iso_c_binding, only: c_int, c_long
  use demstep, only: dp, i8, demstep_status_type
  use demstep_namelist, only: nml_group_type, scan_namelist
  use demstep_sort, only: sort_ascending
  implicit none
  !> struct rusage of Linux/glibc: two timevals, then 14 longs.
  type, bind(c) :: rusage_type
    integer(c_long) :: utime_sec, utime_usec, stime_sec, stime_usec
    integer(c_long) :: rest(14)
  end type rusage_type
  interface
    function c_getrusage(who, usage) result(rc) bind(c, name="getrusage")
      import :: c_int, rusage_type
      integer(c_int), value :: who
      type(rusage_type), intent(out) :: usage
      integer(c_int) :: rc
    end function c_getrusage
  end interface
  integer(c_int), parameter :: rusage_children = -1
  integer, parameter :: n_cases = 9, scan_repeats = 5, app_repeats = 3
  integer, parameter :: sizes(3) = [1000, 10000, 100000]
  character(len=*), parameter :: nl = new_line("a")
  character(len=*), parameter :: system_tail = " stiffness = 1e4, n_per_period = 20.0 /"//nl
  character(len=*), parameter :: dir = "build/bench-deck-files"
  character(len=*), parameter :: names(n_cases) = [character(len=10) :: "list", "lines", &
    "assign", "items", "blank", "spaces", "number", "name", "foreign"]
  character(len=*), parameter :: what(n_cases) = [character(len=52) :: &
    "n values in one list, one line", "n values in one list, one a line", &
    "mass = 1.0 assigned n times", "n_per_period(i) = v for i = 1..n", &
    "10 n line breaks around and inside a group", "a line of 10 n blanks inside a group", &
    "a number of 10 n digits (read as 4)", "a name of 10 n characters (error, exit 2)", &
    "n groups of another code (skipped)"]
  integer, parameter :: expected_exit(n_cases) = [0, 0, 0, 0, 0, 0, 0, 2, 0]
  character(len=:), allocatable :: text, app, deck
  real(dp) :: t_scan(size(sizes)), t_app(size(sizes)), cpu_app(size(sizes))
  integer :: c, s, cmdstat, exitstat
  logical :: all_ok

  app = app_path()
  call execute_command_line("mkdir -p "//dir, wait=.true., exitstat=exitstat, cmdstat=cmdstat)
  if (cmdstat /= 0 .or. exitstat /= 0) error stop "cannot create "//dir
  all_ok = .true.
  write(*, '(a)') "median ms: library scan_namelist on the text in memory; app end to end ("//app// &
    "), wall and CPU"
  write(*, '(a)') "| case | n = | scan 1e3 | scan 1e4 | scan 1e5 | app 1e3 | app 1e4 | app 1e5 " &
    //"| app CPU 1e3 | app CPU 1e4 | app CPU 1e5 |"
  write(*, '(a)') "|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|"
  do c = 1, n_cases
    do s = 1, size(sizes)
      text = make_deck(c, sizes(s))
      t_scan(s) = scan_time(text)
      deck = dir//"/"//trim(names(c))//".nml"
      call write_text(deck, text)
      call app_time(deck, expected_exit(c), t_app(s), cpu_app(s))
    end do
    write(*, '("| ", a, " | ", a, 9(" | ", f8.1), " |")') trim(names(c)), trim(what(c)), t_scan, &
      t_app, cpu_app
  end do
  if (.not. all_ok) write(*, '(a)') "SOME RUNS ENDED WITH AN UNEXPECTED EXIT STATUS (see above)"

contains

  !> The deck of case `c` at size `n`, filled into one buffer or built by repeat.
  function make_deck(c, n) result(deck_text)
    integer, intent(in) :: c, n
    character(len=:), allocatable :: deck_text
    character(len=:), allocatable :: body
    character(len=40) :: line
    integer :: i, at
    select case (c)
    case (1)
      deck_text = "&harmonic_error n_per_period = "//repeat("12.5, ", n)//nl// &
        " lambda = 0.9, steps_fraction = 0.5 /"//nl
    case (2)
      deck_text = "&harmonic_error n_per_period = "//repeat("12.5,"//nl, n)// &
        " lambda = 0.9, steps_fraction = 0.5 /"//nl
    case (3)
      deck_text = "&system"//nl//repeat(" mass = 1.0"//nl, n)//system_tail
    case (4)
      allocate(character(len=40*n) :: body)
      at = 0
      do i = 1, n
        write(line, '(a, i0, a)') " n_per_period(", i, ") = 12.5"
        body(at+1:at+len_trim(line)+1) = trim(line)//nl
        at = at + len_trim(line) + 1
      end do
      deck_text = "&harmonic_error"//nl//body(1:at)//" lambda = 0.9, steps_fraction = 0.5 /"//nl
    case (5)
      deck_text = repeat(nl, 5*n)//"&system mass = 1.0"//repeat(nl, 5*n)//system_tail
    case (6)
      deck_text = "&system mass = 1.0,"//repeat(" ", 10*n)//system_tail
    case (7)
      deck_text = "&system mass = 4."//repeat("0", 10*n)//","//system_tail
    case (8)
      deck_text = "&system "//repeat("m", 10*n)//" = 1.0,"//system_tail
    case default
      deck_text = repeat("&solver steps = 10, name = 'a / b' /"//nl, n)// &
        "&system mass = 1.0,"//system_tail
    end select
  end function make_deck

  !> Median time of scan_namelist on `deck_text`, ms.
  real(dp) function scan_time(deck_text) result(t)
    character(len=*), intent(in) :: deck_text
    type(nml_group_type), allocatable :: groups(:)
    type(demstep_status_type) :: status
    real(dp) :: times(scan_repeats)
    integer(i8) :: c0, c1, rate
    integer :: r
    do r = 1, scan_repeats
      call system_clock(c0, rate)
      call scan_namelist(deck_text, groups, status)
      call system_clock(c1)
      times(r) = real(c1 - c0, dp)/real(rate, dp)*1.0e3_dp
    end do
    t = median(times)
  end function scan_time

  !> Median wall and CPU time of the app on `path`, ms; flags an unexpected exit status.
  subroutine app_time(path, expected, wall, cpu)
    character(len=*), intent(in) :: path
    integer, intent(in) :: expected
    real(dp), intent(out) :: wall, cpu
    real(dp) :: times(app_repeats), cpus(app_repeats)
    integer(i8) :: c0, c1, rate
    integer :: r, exitstat, cmdstat
    real(dp) :: cpu0
    do r = 1, app_repeats
      cpu0 = children_cpu()
      call system_clock(c0, rate)
      call execute_command_line(app//" -q "//path//" >/dev/null 2>&1", wait=.true., &
        exitstat=exitstat, cmdstat=cmdstat)
      call system_clock(c1)
      times(r) = real(c1 - c0, dp)/real(rate, dp)*1.0e3_dp
      cpus(r) = (children_cpu() - cpu0)*1.0e3_dp
      if (cmdstat /= 0 .or. exitstat /= expected) then
        write(*, '(a, i0, a, i0)') "unexpected: "//path//" exit ", exitstat, " cmdstat ", cmdstat
        all_ok = .false.
      end if
    end do
    wall = median(times)
    cpu = median(cpus)
  end subroutine app_time

  !> CPU seconds (user + system) of the waited-for child processes so far.
  real(dp) function children_cpu() result(t)
    type(rusage_type) :: usage
    t = 0.0_dp
    if (c_getrusage(rusage_children, usage) /= 0) return
    t = real(usage%utime_sec + usage%stime_sec, dp) + &
      real(usage%utime_usec + usage%stime_usec, dp)*1.0e-6_dp
  end function children_cpu

  real(dp) function median(x)
    real(dp), intent(in) :: x(:)
    real(dp) :: y(size(x))
    y = x
    call sort_ascending(y)
    median = y((size(y) + 1)/2)
  end function median

  subroutine write_text(path, content)
    character(len=*), intent(in) :: path, content
    integer :: unit
    open(newunit=unit, file=path, access="stream", form="unformatted", status="replace", &
      action="write")
    write(unit) content
    close(unit)
  end subroutine write_text

  !> The demstep app of the same build profile: build/<profile>/app/demstep.
  function app_path() result(path)
    character(len=:), allocatable :: path
    character(len=1024) :: arg0
    integer :: k
    call get_command_argument(0, arg0)
    k = index(arg0, "/example/", back=.true.)
    if (k == 0) then
      path = "demstep"
    else
      path = arg0(1:k)//"app/demstep"
    end if
  end function app_path

end program bench_deck
