!> Benchmark of the file readers on large generated files (about 26 MB each, the
!> size of the tables of the 114 125-sphere tiled packing of issue 24): a
!> particles table and a contacts table (`read_table`), a LIGGGHTS dump, a
!> LIGGGHTS data file and a Yade text export (`read_snapshot`).
!>
!> Numbers are written as the codes write them: full precision (17 significant
!> digits, `1.2345678901234567E-03`, as LIGGGHTS' write_data and a careful
!> exporter) or short (6 digits, `1.23457E-03`, as LIGGGHTS' dump `%g` and
!> Yade's text export). The files are read from the page cache (written just
!> before): the figure is the parser's speed, the ceiling a disk would impose
!> is not in it. Median of several reads, in MB/s (1 MB = 1e6 bytes), from the
!> wall time and from the process's CPU time (which a busy machine inflates
!> less: the figures to compare on a shared machine).
!> Run: fpm run --profile release --example bench_read [-- MB [CASE]]
program bench_read
  use demstep, only: dp, i8, demstep_status_type, demstep_stat, read_snapshot, snapshot_type
  use demstep_table_io, only: read_table
  use demstep_sort, only: sort_ascending
  implicit none
  integer, parameter :: repeats = 5, n_cases = 6
  character(len=*), parameter :: dir = "build/bench-read-files"
  character(len=*), parameter :: names(n_cases) = [character(len=16) :: "particles_full", &
    "particles_short", "contacts_full", "dump_short", "data_full", "yade_short"]
  character(len=*), parameter :: what(n_cases) = [character(len=60) :: &
    "particles table, 9 columns, 17 digits", "particles table, 9 columns, 6 digits", &
    "contacts table, i j k_n k_t, 17 digits", "LIGGGHTS dump, 13 columns, 6 digits", &
    "LIGGGHTS data file (sphere), 17 digits", "Yade text x_y_z_r, 6 digits"]
  character(len=:), allocatable :: text, path
  character(len=32) :: arg
  real(dp) :: mb, times(repeats), cpus(repeats), target_mb, t0, t1
  integer :: c, r, ios, only
  integer(i8) :: c0, c1, rate
  logical :: ok

  target_mb = 26.0_dp
  if (command_argument_count() > 0) then
    call get_command_argument(1, arg)
    read(arg, *, iostat=ios) target_mb
    if (ios /= 0 .or. .not. target_mb > 0.0_dp) error stop "usage: bench_read [MB [CASE]]"
  end if
  only = 0
  if (command_argument_count() > 1) then
    call get_command_argument(2, arg)
    read(arg, *, iostat=ios) only
    if (ios /= 0 .or. only < 0 .or. only > n_cases) error stop "usage: bench_read [MB [CASE]]"
  end if
  call execute_command_line("mkdir -p "//dir, wait=.true.)
  write(*, '(a)') "| file | what | MB | wall s | MB/s (wall) | CPU s | MB/s (CPU) |"
  write(*, '(a)') "|---|---|---:|---:|---:|---:|---:|"
  do c = 1, n_cases
    if (only > 0 .and. c /= only) cycle
    text = make_file(c, nint(target_mb*1.0e6_dp))
    path = dir//"/"//trim(names(c))//".txt"
    call write_text(path, text)
    mb = len(text)/1.0e6_dp
    deallocate(text)
    do r = 1, repeats
      call system_clock(c0, rate)
      call cpu_time(t0)
      ok = read_once(c, path)
      call cpu_time(t1)
      call system_clock(c1)
      times(r) = real(c1 - c0, dp)/real(rate, dp)
      cpus(r) = t1 - t0
      if (.not. ok) error stop "a benchmark file was refused"
    end do
    call sort_ascending(times)
    call sort_ascending(cpus)
    write(*, '("| ", a, " | ", a, " | ", f6.1, 2(" | ", f7.3, " | ", f7.1), " |")') trim(names(c)), &
      trim(what(c)), mb, times((repeats + 1)/2), mb/times((repeats + 1)/2), cpus((repeats + 1)/2), &
      mb/cpus((repeats + 1)/2)
  end do

contains

  !> Read file `c` once with the library's reader; false if it was refused.
  logical function read_once(c, path) result(ok)
    integer, intent(in) :: c
    character(len=*), intent(in) :: path
    real(dp), allocatable :: rows(:, :)
    type(snapshot_type) :: s
    type(demstep_status_type) :: status
    select case (c)
    case (1, 2)
      call read_table(path, [9, 10], rows, status)
    case (3)
      call read_table(path, [4, 6, 10], rows, status, index_columns=[1, 2])
    case default
      call read_snapshot(path, s, status)
    end select
    ok = status%stat == demstep_stat%ok
    if (.not. ok) write(*, '(a)') status%message
  end function read_once

  !> The text of file `c`, about `bytes` long, from a fixed pseudo-random sequence.
  function make_file(c, bytes) result(t)
    integer, intent(in) :: c, bytes
    character(len=:), allocatable :: t
    character(len=400) :: line
    character(len=*), parameter :: full = "es24.16e2", short = "es12.5e2"
    integer(i8) :: state
    integer :: at, n, i, k, rows
    real(dp) :: v(13)
    character(len=:), allocatable :: head
    state = 0_i8
    call random_seed(size=k)
    call random_seed(put=[(12345 + 7*i, i = 1, k)])
    allocate(character(len=bytes + 2000) :: t)
    head = ""
    select case (c)
    case (4)
      head = "ITEM: TIMESTEP"//new_line("a")//"60000"//new_line("a")//"ITEM: NUMBER OF ATOMS"//new_line("a")
    case (5)
      head = "LAMMPS data file (generated for bench_read)"//new_line("a")//new_line("a")
    case (6)
      head = "#format x_y_z_r"//new_line("a")
    end select
    ! rows until the size is reached; the header (which states the count) is
    ! placed in front afterwards
    at = 0
    n = 0
    do while (at < bytes - 1000)
      n = n + 1
      do k = 1, size(v)
        v(k) = uniform(state)
      end do
      select case (c)
      case (1)
        write(line, '(9('//full//', 1x))') v(1:3), v(4:6) - 0.5_dp, v(7)*1.0e-5_dp, v(8)*1.0e-3_dp, 0.0_dp
      case (2)
        write(line, '(9('//short//', 1x))') v(1:3), v(4:6) - 0.5_dp, v(7)*1.0e-5_dp, v(8)*1.0e-3_dp, 0.0_dp
      case (3)
        write(line, '(i0, 1x, i0, 2(1x, '//full//'))') 1 + int(v(1)*1.0e5_dp), 1 + int(v(2)*1.0e5_dp), &
          1.0e5_dp*(1.0_dp + v(3)), 3.0e4_dp*(1.0_dp + v(4))
      case (4)
        write(line, '(i0, 1x, i0, 11(1x, '//short//'))') n, 1 + int(2*v(1)), v(2:4)*1.0e-2_dp, &
          (v(5:7) - 0.5_dp)*1.0e-3_dp, 1.0e-3_dp*(0.5_dp + v(8)), 1.0e-5_dp*v(9), v(10:12) - 0.5_dp
      case (5)
        write(line, '(i0, " 1", 5(1x, '//full//'), " 0 0 0")') n, 2.0e-3_dp*(0.5_dp + v(1)), 2500.0_dp, &
          v(2:4)*1.0e-2_dp
      case (6)
        write(line, '(4('//short//', :, a))') (v(k)*1.0e-2_dp, achar(9), k = 1, 3), 1.0e-3_dp*(0.5_dp + v(4))
      end select
      k = len_trim(line)
      t(at+1:at+k+1) = line(:k)//new_line("a")
      at = at + k + 1
    end do
    rows = n
    select case (c)
    case (4)
      write(line, '(i0)') rows
      head = head//trim(line)//new_line("a")//"ITEM: BOX BOUNDS pp pp ff"//new_line("a")//"0 0.01"// &
        new_line("a")//"0 0.01"//new_line("a")//"0 0.01"//new_line("a")// &
        "ITEM: ATOMS id type x y z vx vy vz radius mass omegax omegay omegaz"//new_line("a")
    case (5)
      write(line, '(i0)') rows
      head = head//trim(line)//" atoms"//new_line("a")//"1 atom types"//new_line("a")//new_line("a")// &
        "0 0.01 xlo xhi"//new_line("a")//"0 0.01 ylo yhi"//new_line("a")//"0 0.01 zlo zhi"//new_line("a")// &
        new_line("a")//"Atoms # sphere"//new_line("a")//new_line("a")
    end select
    t = head//t(:at)
  end function make_file

  !> A uniform number in [0, 1) from the compiler's generator (seeded in make_file).
  real(dp) function uniform(state)
    integer(i8), intent(inout) :: state
    call random_number(uniform)
    state = state + 1
  end function uniform

  subroutine write_text(file, t)
    character(len=*), intent(in) :: file, t
    integer :: unit
    open(newunit=unit, file=file, access="stream", form="unformatted", status="replace", action="write")
    write(unit) t
    close(unit)
  end subroutine write_text

end program bench_read
