!> A property test of the snapshot readers on damaged copies of every example
!> snapshot (the LIGGGHTS dump and data file of example/ and test/data/liggghts,
!> the Yade export of example/): truncated at many cut points, with bytes
!> changed, and with the header's atom counts set to huge values. Each copy is
!> read from memory; the reader must return either the original particles (a
!> truncated copy: a prefix of them, at most the row cut through changed) or a
!> refusal in one line, and every snapshot it returns must hold what the
!> readers promise (finite values, positive radii, types from 1, distinct ids,
!> no more particles than the text has lines). The copies are chosen by a fixed
!> seed, so every run reads the same ones.
!>
!> Memory: every array a reader allocates is sized by the lines present, so no
!> count can ask for more; where /proc/self/status exists, the test checks that
!> the process's peak resident size grew by less than 64 MiB over the whole run
!> (a count of 1e8 atoms allocated from the header took 4 GiB before).
module test_snapshot_hostile
  use testdrive, only: error_type, check, test_failed
  use demstep_kinds, only: dp, i8
  use demstep_status, only: demstep_status_type, demstep_stat
  use demstep_text, only: read_text_file
  use demstep_text, only: int_text
  use demstep_snapshot
  use, intrinsic :: ieee_arithmetic, only: ieee_is_finite
  implicit none
  private
  public :: test_truncated, test_flipped, test_inflated

  !> The example snapshots and their formats.
  character(len=*), parameter :: files(5) = [character(len=32) :: "example/liggghts_pour.dump", &
    "example/liggghts_pour.data", "example/yade_packing.txt", "test/data/liggghts/dump.liggghts", &
    "test/data/liggghts/data.liggghts"]
  integer, parameter :: formats(5) = [snapshot_format%lammps_dump, snapshot_format%lammps_data, &
    snapshot_format%yade_text, snapshot_format%lammps_dump, snapshot_format%lammps_data]
  character(len=*), parameter :: nl = achar(10)
  !> Peak resident growth allowed over one test (KiB): the texts are < 40 kB.
  integer(i8), parameter :: max_growth_kib = 65536_i8

contains

  !> Every cut point in the first 256 and the last 128 bytes (headers, last
  !> rows), and 150 more drawn at random.
  subroutine test_truncated(error)
    type(error_type), allocatable, intent(out) :: error
    integer :: f, cut, k, tally(2)
    integer(i8) :: seed, peak0
    character(len=:), allocatable :: text
    type(snapshot_type) :: original
    seed = 20261126_i8
    peak0 = peak_kib()
    do f = 1, size(files)
      call load(error, f, text, original)
      if (allocated(error)) return
      tally = 0
      do k = 0, len(text) - 1
        if (k >= 256 .and. k < len(text) - 128) cycle
        call check_truncated(error, f, text, k, original, tally)
        if (allocated(error)) return
      end do
      do k = 1, 150
        cut = int(next_random(seed, int(len(text), i8)))
        call check_truncated(error, f, text, cut, original, tally)
        if (allocated(error)) return
      end do
      call exercised(error, f, tally)
      if (allocated(error)) return
    end do
    call check_memory(error, peak0)
  end subroutine test_truncated

  !> 300 copies of each file with one byte changed and 100 with three, the
  !> bytes drawn from digits, signs, separators, newlines, `#`, letters and
  !> binary bytes, or a bit of the original flipped.
  subroutine test_flipped(error)
    type(error_type), allocatable, intent(out) :: error
    integer :: f, k, j, pos, c, tally(2)
    integer(i8) :: seed, peak0
    character(len=:), allocatable :: text, copy
    type(snapshot_type) :: original
    character(len=*), parameter :: pool = "0123456789-+.eE #"//nl//achar(13)//achar(9)//"xI"//achar(0)//achar(255)
    seed = 7_i8
    peak0 = peak_kib()
    do f = 1, size(files)
      call load(error, f, text, original)
      if (allocated(error)) return
      tally = 0
      do k = 1, 400
        copy = text
        do j = 1, merge(1, 3, k <= 300)
          pos = 1 + int(next_random(seed, int(len(copy), i8)))
          if (next_random(seed, 4_i8) == 0) then
            copy(pos:pos) = achar(ieor(modulo(iachar(copy(pos:pos)), 256), 2**int(next_random(seed, 8_i8))))
          else
            c = 1 + int(next_random(seed, int(len(pool), i8)))
            copy(pos:pos) = pool(c:c)
          end if
        end do
        call check_any(error, f, "byte changes (copy "//int_text(k)//")", copy, formats(f), tally)
        if (allocated(error)) return
      end do
      call exercised(error, f, tally)
      if (allocated(error)) return
    end do
    call check_memory(error, peak0)
  end subroutine test_flipped

  !> Each atom count of a header (a dump's every `NUMBER OF ATOMS`, a data
  !> file's `N atoms`) set to 2147483647, 2^31-2, 2147483640, 1e8, 4294967296,
  !> the int64 limit, beyond it, -1, 0 and one fewer: all refused in one line.
  !> (The Yade export has no count.)
  subroutine test_inflated(error)
    type(error_type), allocatable, intent(out) :: error
    integer :: f, c, first, last, n_counts
    integer(i8) :: peak0
    character(len=:), allocatable :: text, copy, line
    type(snapshot_type) :: original, s
    type(demstep_status_type) :: status
    character(len=20), parameter :: counts(9) = [character(len=20) :: "2147483647", "2147483646", &
      "2147483640", "100000000", "4294967296", "9223372036854775807", "99999999999999999999", "-1", "0"]
    peak0 = peak_kib()
    do f = 1, size(files)
      if (formats(f) == snapshot_format%yade_text) cycle
      call load(error, f, text, original)
      if (allocated(error)) return
      n_counts = 0
      first = 1
      do while (first <= len(text))
        last = index(text(first:), nl) + first - 2
        if (last < first - 1) last = len(text)
        line = text(first:last)
        if (is_count_line(text, first, line, formats(f))) then
          n_counts = n_counts + 1
          do c = 1, size(counts) + 1
            if (c <= size(counts)) then
              copy = text(:first - 1)//replaced_count(line, trim(counts(c)), formats(f))//text(last + 1:)
            else
              copy = text(:first - 1)//replaced_count(line, int_text(count_of(line) - 1), formats(f))// &
                text(last + 1:)
            end if
            call parse_snapshot(copy, s, status, format=formats(f))
            call check(error, status%stat == demstep_stat%invalid_input, trim(files(f))//": count on the line " &
              //"starting at byte "//int_text(first)//" set to "//trim(counts(min(c, size(counts))))// &
              " (or one fewer): not refused")
            if (allocated(error)) return
            call one_line(error, f, "inflated count", status)
            if (allocated(error)) return
          end do
        end if
        first = last + 2
      end do
      call check(error, n_counts > 0, trim(files(f))//": no count line found")
      if (allocated(error)) return
    end do
    call check_memory(error, peak0)
  end subroutine test_inflated

  ! ------------------------------------------------------------------ helpers

  !> The text of file f and its snapshot (which must read).
  subroutine load(error, f, text, original)
    type(error_type), allocatable, intent(out) :: error
    integer, intent(in) :: f
    character(len=:), allocatable, intent(out) :: text
    type(snapshot_type), intent(out) :: original
    type(demstep_status_type) :: status
    call read_text_file(trim(files(f)), text, status)
    call check(error, status%stat == demstep_stat%ok, trim(files(f))//": cannot read")
    if (allocated(error)) return
    call parse_snapshot(text, original, status, format=formats(f))
    call check(error, status%stat == demstep_stat%ok .and. original%n > 1, trim(files(f))//": the original " &
      //"does not read")
  end subroutine load

  !> The text cut after `cut` bytes: refused in one line, or a prefix of the
  !> original's particles (of the frame it ends with) with at most one changed.
  subroutine check_truncated(error, f, text, cut, original, tally)
    type(error_type), allocatable, intent(out) :: error
    integer, intent(in) :: f, cut
    integer, intent(inout) :: tally(2)
    character(len=*), intent(in) :: text
    type(snapshot_type), intent(in) :: original
    type(snapshot_type) :: s, ref
    type(demstep_status_type) :: status
    integer :: i, changed
    character(len=:), allocatable :: what
    what = "cut after "//int_text(cut)//" bytes"
    call check_any(error, f, what, text(:cut), formats(f), tally, s, status)
    if (allocated(error) .or. status%stat /= demstep_stat%ok) return
    if (formats(f) == snapshot_format%lammps_dump .and. s%frame /= original%frame) then
      call parse_snapshot(text, ref, status, format=formats(f), frame=s%frame)
    else
      ref = original
    end if
    ! a cut can drop rows and the Velocities section, nothing else
    call check(error, s%n <= ref%n .and. (ref%has_velocity .or. .not. s%has_velocity) .and. &
      (s%has_mass .eqv. ref%has_mass), trim(files(f))//": "//what//": more particles or other columns " &
      //"than the original")
    if (allocated(error)) return
    changed = 0
    do i = 1, s%n
      if (s%id(i) /= ref%id(i) .or. s%type(i) /= ref%type(i) .or. any(s%x(:, i) /= ref%x(:, i)) .or. &
        s%radius(i) /= ref%radius(i) .or. s%mass(i) /= ref%mass(i)) then
        changed = changed + 1
      else if (s%has_velocity) then
        if (any(s%v(:, i) /= ref%v(:, i)) .or. any(s%omega(:, i) /= ref%omega(:, i))) changed = changed + 1
      end if
    end do
    call check(error, changed <= 1, trim(files(f))//": "//what//": "//int_text(changed)//" particles differ " &
      //"from the original (at most the row cut through may)")
  end subroutine check_truncated

  !> Read a text: refused in one line, or a snapshot that keeps the promises.
  subroutine check_any(error, f, what, text, format, tally, s, status)
    type(error_type), allocatable, intent(out) :: error
    integer, intent(in) :: f, format
    character(len=*), intent(in) :: what, text
    !> Copies read and refused (in the given format), counted.
    integer, intent(inout) :: tally(2)
    type(snapshot_type), intent(out), optional :: s
    type(demstep_status_type), intent(out), optional :: status
    type(snapshot_type) :: s1
    type(demstep_status_type) :: status1
    integer :: i, j, n_lines
    ! as the given format, then as detected (the app's default)
    call parse_snapshot(text, s1, status1, format=format)
    if (status1%stat == demstep_stat%ok) then
      tally(1) = tally(1) + 1
    else
      tally(2) = tally(2) + 1
    end if
    if (present(s)) s = s1
    if (present(status)) status = status1
    do j = 1, 2
      if (j == 2) call parse_snapshot(text, s1, status1)
      if (status1%stat /= demstep_stat%ok) then
        call one_line(error, f, what, status1)
        if (allocated(error)) return
        cycle
      end if
      n_lines = count(transfer(text, "a", len(text)) == nl) + 1
      call check(error, s1%n >= 0 .and. s1%n <= n_lines .and. size(s1%radius) == s1%n, trim(files(f))//": " &
        //what//": "//int_text(s1%n)//" particles from "//int_text(n_lines)//" lines")
      if (allocated(error)) return
      call check(error, all(ieee_is_finite(s1%x)) .and. all(ieee_is_finite(s1%v)) .and. &
        all(ieee_is_finite(s1%omega)) .and. all(ieee_is_finite(s1%radius)) .and. all(s1%radius > 0.0_dp), &
        trim(files(f))//": "//what//": a value not finite or a radius not > 0")
      if (allocated(error)) return
      call check(error, all(s1%type >= 1) .and. all(s1%id >= 1_i8), trim(files(f))//": "//what// &
        ": a type or id below 1")
      if (allocated(error)) return
      if (s1%has_mass) then
        call check(error, all(ieee_is_finite(s1%mass)) .and. all(s1%mass > 0.0_dp), trim(files(f))//": "// &
          what//": a mass not finite and > 0")
        if (allocated(error)) return
      end if
      do i = 2, s1%n
        if (any(s1%id(:i - 1) == s1%id(i))) then
          call test_failed(error, trim(files(f))//": "//what//": id "//int_text(s1%id(i))//" twice")
          return
        end if
      end do
    end do
  end subroutine check_any

  !> Both outcomes occurred: some copies read, some refused (else the
  !> mutations test one path only).
  subroutine exercised(error, f, tally)
    type(error_type), allocatable, intent(out) :: error
    integer, intent(in) :: f, tally(2)
    call check(error, all(tally > 0), trim(files(f))//": "//int_text(tally(1))//" copies read, "// &
      int_text(tally(2))//" refused: both should occur")
  end subroutine exercised

  !> A refusal: invalid_input with a message of one line.
  subroutine one_line(error, f, what, status)
    type(error_type), allocatable, intent(out) :: error
    integer, intent(in) :: f
    character(len=*), intent(in) :: what
    type(demstep_status_type), intent(in) :: status
    call check(error, status%stat == demstep_stat%invalid_input .and. allocated(status%message), &
      trim(files(f))//": "//what//": status "//int_text(status%stat)//" without a message")
    if (allocated(error)) return
    call check(error, len(status%message) > 0 .and. len(status%message) < 400 .and. &
      scan(status%message, nl//achar(13)) == 0, trim(files(f))//": "//what//": not one line: '"// &
      status%message//"'")
  end subroutine one_line

  !> Whether the line starting at byte `first` holds an atom count.
  logical function is_count_line(text, first, line, format)
    character(len=*), intent(in) :: text, line
    integer, intent(in) :: first, format
    integer :: before
    is_count_line = .false.
    if (format == snapshot_format%lammps_data) then
      is_count_line = index(line, " atoms") > 0 .and. verify(line(:index(line, " atoms") - 1), "0123456789") == 0 &
        .and. index(line, " atoms") > 1
    else if (first > 1) then
      ! the line after "ITEM: NUMBER OF ATOMS"
      before = index(text(:first - 2), nl, back=.true.)
      is_count_line = text(before + 1:first - 2) == "ITEM: NUMBER OF ATOMS"
    end if
  end function is_count_line

  !> The count line with the count replaced.
  pure function replaced_count(line, count, format) result(r)
    character(len=*), intent(in) :: line, count
    integer, intent(in) :: format
    character(len=:), allocatable :: r
    if (format == snapshot_format%lammps_data) then
      r = count//line(index(line, " atoms"):)
    else
      r = count
    end if
  end function replaced_count

  !> The count a count line holds.
  integer function count_of(line)
    character(len=*), intent(in) :: line
    integer :: ios
    read(line, *, iostat=ios) count_of
  end function count_of

  !> A number in [0, m) from a 64-bit linear congruential generator (Knuth's
  !> MMIX constants; the high bits used). 0 for m = 0.
  integer(i8) function next_random(seed, m) result(r)
    integer(i8), intent(inout) :: seed
    integer(i8), intent(in) :: m
    seed = seed*6364136223846793005_i8 + 1442695040888963407_i8
    r = 0
    if (m > 0) r = modulo(ishft(seed, -33), m)
  end function next_random

  !> The process's peak resident size (KiB, VmHWM of /proc/self/status); -1
  !> where that file does not exist.
  integer(i8) function peak_kib() result(kib)
    integer :: unit, ios
    character(len=256) :: line
    kib = -1
    open(newunit=unit, file="/proc/self/status", action="read", status="old", iostat=ios)
    if (ios /= 0) return
    do
      read(unit, '(a)', iostat=ios) line
      if (ios /= 0) exit
      if (index(line, "VmHWM:") == 1) then
        read(line(7:), *, iostat=ios) kib
        if (ios /= 0) kib = -1
        exit
      end if
    end do
    close(unit)
  end function peak_kib

  subroutine check_memory(error, peak0)
    type(error_type), allocatable, intent(out) :: error
    integer(i8), intent(in) :: peak0
    integer(i8) :: peak1
    if (peak0 < 0) return
    peak1 = peak_kib()
    call check(error, peak1 - peak0 < max_growth_kib, "peak resident size grew by "//int_text(peak1 - peak0)// &
      " KiB (at most "//int_text(max_growth_kib)//")")
  end subroutine check_memory

end module test_snapshot_hostile
