!> Small in-place sorts shared by the library: reals by insertion (the short
!> lists of roots and breakpoints) and integers by heapsort (ids, any length).
module demstep_sort
  use demstep_kinds, only: dp
  implicit none
  private

  public :: sort_ascending, heap_sort

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

end module demstep_sort
