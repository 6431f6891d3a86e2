!> Small in-place sorts shared by the library: reals by insertion (the short
!> lists of roots and breakpoints), integers by heapsort (ids, any length) and
!> 64-bit keys by radix sort (long lists of keys); the binary search of
!> an ascending list (`count_before`); and the buckets of a counting sort
!> (`bucket_starts`).
module demstep_sort
  use demstep_kinds, only: dp, i8
  implicit none
  private

  public :: sort_ascending, heap_sort, radix_sort, count_before, bucket_starts

  !> The number of entries of an ascending integer list that come before a
  !> value: those < v, or with `inclusive` those <= v (a binary search,
  !> O(log n)). For a list of distinct entries holding v, the count plus one
  !> is v's place.
  interface count_before
    module procedure count_before_int, count_before_i8
  end interface count_before

contains

  !> Sort in place, ascending (insertion sort: for short arrays).
  pure subroutine sort_ascending(x)
    real(dp), intent(inout) :: x(:)
    real(dp) :: v
    integer :: i, j
    do i = 2, size(x)
      v = x(i)
      j = i - 1
      do while (j >= 1)
        if (x(j) <= v) exit
        x(j + 1) = x(j)
        j = j - 1
      end do
      x(j + 1) = v
    end do
  end subroutine sort_ascending

  !> Sort integers ascending in place (heapsort: O(n log n), no recursion, no
  !> extra memory).
  pure subroutine heap_sort(a)
    integer, intent(inout) :: a(:)
    integer :: n, i, t
    n = size(a)
    do i = n/2, 1, -1
      call sift_down(a, i, n)
    end do
    do i = n, 2, -1
      t = a(1)
      a(1) = a(i)
      a(i) = t
      call sift_down(a, 1, i - 1)
    end do
  end subroutine heap_sort

  !> Restore the heap order of a(start:last) below `start` (for `heap_sort`).
  pure subroutine sift_down(a, start, last)
    integer, intent(inout) :: a(:)
    integer, intent(in) :: start, last
    integer :: root, child, t
    root = start
    do while (2*root <= last)
      child = 2*root
      if (child < last) then
        if (a(child) < a(child + 1)) child = child + 1
      end if
      if (a(root) >= a(child)) exit
      t = a(root)
      a(root) = a(child)
      a(child) = t
      root = child
    end do
  end subroutine sift_down

  !> Sort 64-bit integers ascending in place (least significant digit radix
  !> sort, 8 bits a digit: at most 8 stable passes over the array, a pass
  !> skipped where every key has the same digit; n integers of scratch).
  pure subroutine radix_sort(a)
    integer(i8), intent(inout) :: a(:)
    integer(i8), allocatable :: scratch(:)
    integer :: pass
    logical :: in_scratch, moved
    if (size(a) < 2) return
    allocate(scratch(size(a)))
    in_scratch = .false.
    do pass = 0, 7
      if (in_scratch) then
        call radix_pass(scratch, a, pass, moved)
      else
        call radix_pass(a, scratch, pass, moved)
      end if
      if (moved) in_scratch = .not. in_scratch
    end do
    if (in_scratch) a = scratch
  end subroutine radix_sort

  !> One pass of `radix_sort`: `from` ordered stably by its digit `pass`
  !> (bits 8 pass to 8 pass + 7; the sign bit flipped in the top digit, so
  !> negative keys come first) into `to`, unless every key has the same digit
  !> (then `moved` is false and `to` is untouched).
  pure subroutine radix_pass(from, to, pass, moved)
    integer(i8), intent(in) :: from(:)
    integer(i8), intent(inout) :: to(:)
    integer, intent(in) :: pass
    logical, intent(out) :: moved
    integer :: counts(0:255), at(0:255), i, d, flip
    flip = 0
    if (pass == 7) flip = 128
    counts = 0
    do i = 1, size(from)
      d = ieor(int(ibits(from(i), 8*pass, 8)), flip)
      counts(d) = counts(d) + 1
    end do
    moved = maxval(counts) < size(from)
    if (.not. moved) return
    at(0) = 1
    do d = 1, 255
      at(d) = at(d - 1) + counts(d - 1)
    end do
    do i = 1, size(from)
      d = ieor(int(ibits(from(i), 8*pass, 8)), flip)
      to(at(d)) = from(i)
      at(d) = at(d) + 1
    end do
  end subroutine radix_pass

  !> The buckets of a counting sort: with counts(k) entries of key k (k = 1 ..
  !> n), start(k) = 1 + counts(1) + ... + counts(k - 1) for k = 1 .. n + 1
  !> (start(n + 1): one past the last entry). Placing each entry at next(k),
  !> next a copy of start(:n) advanced by one as each entry of key k comes,
  !> sorts the entries by key and keeps their order within a key.
  pure function bucket_starts(counts) result(start)
    integer, intent(in) :: counts(:)
    integer(i8), allocatable :: start(:)
    integer :: k
    allocate(start(size(counts) + 1))
    start(1) = 1
    do k = 1, size(counts)
      start(k + 1) = start(k) + counts(k)
    end do
  end function bucket_starts

  !> `count_before` for default integers.
  pure integer function count_before_int(list, v, inclusive) result(n)
    integer, intent(in) :: list(:), v
    include "count_before.inc"
  end function count_before_int

  !> `count_before` for 64-bit integers.
  pure integer function count_before_i8(list, v, inclusive) result(n)
    integer(i8), intent(in) :: list(:), v
    include "count_before.inc"
  end function count_before_i8

end module demstep_sort
