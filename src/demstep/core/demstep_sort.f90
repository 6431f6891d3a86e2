!> Small in-place sorts shared by the library: reals by insertion (the short
!> lists of roots and breakpoints), integers by heapsort (ids, any length) and
!> 64-bit keys by merge sort (long lists of keys).
module demstep_sort
  use demstep_kinds, only: dp, i8
  implicit none
  private

  public :: sort_ascending, heap_sort, merge_sort

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

  !> Sort 64-bit integers ascending in place (bottom-up merge sort: O(n log n)
  !> in sequential passes over the array, n integers of scratch).
  pure subroutine merge_sort(a)
    integer(i8), intent(inout) :: a(:)
    integer(i8), allocatable :: scratch(:)
    integer :: n, width
    logical :: in_scratch
    n = size(a)
    if (n < 2) return
    allocate(scratch(n))
    width = 1
    in_scratch = .false.
    do while (width < n)
      if (in_scratch) then
        call merge_runs(scratch, a, width)
      else
        call merge_runs(a, scratch, width)
      end if
      in_scratch = .not. in_scratch
      if (width > (n - 1)/2) exit
      width = 2*width
    end do
    if (in_scratch) a = scratch
  end subroutine merge_sort

  !> One pass of `merge_sort`: the sorted runs of `width` in `from` merged
  !> pairwise into `to`.
  pure subroutine merge_runs(from, to, width)
    integer(i8), intent(in) :: from(:)
    integer(i8), intent(out) :: to(:)
    integer, intent(in) :: width
    integer :: n, first, mid, last, i, j, k
    n = size(from)
    first = 1
    do while (first <= n)
      mid = min(first + width - 1, n)
      last = min(first + 2*width - 1, n)
      if (mid == last) then
        to(first:last) = from(first:last)
        exit
      end if
      i = first
      j = mid + 1
      do k = first, last
        if (j > last) then
          to(k:last) = from(i:mid)
          exit
        else if (i > mid) then
          to(k:last) = from(j:last)
          exit
        else if (from(j) < from(i)) then
          to(k) = from(j)
          j = j + 1
        else
          to(k) = from(i)
          i = i + 1
        end if
      end do
      first = last + 1
    end do
  end subroutine merge_runs

end module demstep_sort
