!> Tests of demstep_sort's radix sort of 64-bit keys: ascending order and the
!> same keys, on random keys over the whole range (negative ones, the
!> extremes, repeats), keys that share their high bytes (the passes skipped),
!> equal keys, and the short arrays; of `count_before` against a count
!> over the whole list; and of a counting sort on `bucket_starts` against
!> the keys' order and each key's entries in their order.
module test_sort
  use testdrive, only: new_unittest, unittest_type, error_type, check
  use demstep_kinds, only: i8
  use demstep_sort, only: radix_sort, count_before, bucket_starts
  implicit none
  private
  public :: collect_sort

contains

  subroutine collect_sort(testsuite)
    type(unittest_type), allocatable, intent(out) :: testsuite(:)
    testsuite = [ &
      new_unittest("radix_sort: random keys, negative, extreme and repeated", test_radix_random), &
      new_unittest("radix_sort: keys sharing their high bytes, all equal, short", test_radix_special), &
      new_unittest("count_before: equal to a count over the list, both kinds", test_count_before), &
      new_unittest("bucket_starts: a counting sort by key, stable; empty buckets and lists", test_buckets) &
      ]
  end subroutine collect_sort

  subroutine test_radix_random(error)
    type(error_type), allocatable, intent(out) :: error
    integer(i8), allocatable :: a(:)
    integer(i8) :: seed
    integer :: i
    seed = 12345_i8
    allocate(a(3000))
    do i = 1, size(a)
      a(i) = next(seed)
    end do
    ! the extremes and repeats of values already present
    a(7) = huge(1_i8)
    a(8) = -huge(1_i8) - 1_i8
    a(9) = 0_i8
    a(10) = -1_i8
    a(11:40) = a(101:130)
    a(41:45) = -huge(1_i8) - 1_i8
    call expect_sorted(error, a)
  end subroutine test_radix_random

  subroutine test_radix_special(error)
    type(error_type), allocatable, intent(out) :: error
    integer(i8), allocatable :: a(:)
    integer(i8) :: seed
    integer :: i
    seed = 777_i8
    ! the same top six bytes: two passes move, six are skipped
    allocate(a(1000))
    do i = 1, size(a)
      a(i) = ior(shiftl(int(z'12345678ABCD', i8), 16), iand(next(seed), int(z'FFFF', i8)))
    end do
    call expect_sorted(error, a)
    if (allocated(error)) return
    ! negative keys differing only in their low byte
    a = -int(z'100', i8) + iand(a, 255_i8)
    call expect_sorted(error, a)
    if (allocated(error)) return
    a = 42_i8
    call expect_sorted(error, a)
    if (allocated(error)) return
    call expect_sorted(error, [-5_i8])
    if (allocated(error)) return
    call expect_sorted(error, [3_i8, -3_i8])
    if (allocated(error)) return
    deallocate(a)
    allocate(a(0))
    call expect_sorted(error, a)
  end subroutine test_radix_special

  !> count_before on sorted lists with repeats, the extremes, values below,
  !> between and above the entries, one entry and none: the same as count()
  !> over the list, for default and 64-bit integers, < and <=.
  subroutine test_count_before(error)
    type(error_type), allocatable, intent(out) :: error
    integer(i8), allocatable :: a(:)
    integer, allocatable :: b(:)
    integer(i8) :: seed, v
    integer :: n, i, t
    seed = 4242_i8
    do n = 0, 40
      allocate(a(n))
      do i = 1, n
        ! (few distinct values: repeats)
        a(i) = modulo(next(seed), 11_i8) - 5_i8
      end do
      if (n > 3) a(n) = huge(1_i8)
      if (n > 4) a(1) = -huge(1_i8) - 1_i8
      call radix_sort(a)
      b = int(max(min(a, 1000_i8), -1000_i8))
      do t = -7, 8
        v = int(t, i8)
        call check(error, count_before(a, v, .false.) == count(a < v), "64-bit, <")
        if (allocated(error)) return
        call check(error, count_before(a, v, .true.) == count(a <= v), "64-bit, <=")
        if (allocated(error)) return
        call check(error, count_before(b, t, .false.) == count(b < t), "default, <")
        if (allocated(error)) return
        call check(error, count_before(b, t, .true.) == count(b <= t), "default, <=")
        if (allocated(error)) return
      end do
      do i = 1, n
        call check(error, count_before(a, a(i), .true.) == count(a <= a(i)), "64-bit, <= an entry")
        if (allocated(error)) return
      end do
      call check(error, count_before(a, huge(1_i8), .true.) == n, "64-bit, <= the largest")
      if (allocated(error)) return
      call check(error, count_before(a, -huge(1_i8) - 1_i8, .false.) == 0, "64-bit, < the smallest")
      if (allocated(error)) return
      deallocate(a)
    end do
  end subroutine test_count_before

  !> Entries 1..n with keys in 1..m (few keys: repeats; some keys unused)
  !> placed by `bucket_starts`: the placed keys ascend, each key's entries
  !> keep their order, every entry is placed once, and start(k) is 1 plus the
  !> count of keys below k. n from 0 (no entries) to 60, m from 1 to 9; and
  !> no keys at all.
  subroutine test_buckets(error)
    type(error_type), allocatable, intent(out) :: error
    integer, allocatable :: key(:), per_key(:), placed(:)
    integer(i8), allocatable :: start(:), next(:)
    integer(i8) :: seed
    integer :: n, m, i, k
    seed = 777_i8
    start = bucket_starts([integer ::])
    call check(error, size(start) == 1 .and. start(1) == 1, "no keys: one start, 1")
    if (allocated(error)) return
    do n = 0, 60
      m = 1 + mod(n, 9)
      allocate(key(n), per_key(m), placed(n))
      per_key = 0
      do i = 1, n
        key(i) = int(modulo(next_key(seed), int(m, i8))) + 1
        per_key(key(i)) = per_key(key(i)) + 1
      end do
      start = bucket_starts(per_key)
      call check(error, size(start) == m + 1 .and. start(m + 1) == n + 1, "one past the last entry")
      if (allocated(error)) return
      do k = 1, m
        call check(error, start(k) == 1 + count(key < k), "start of key "//char(48 + k))
        if (allocated(error)) return
      end do
      next = start(:m)
      placed = 0
      do i = 1, n
        placed(next(key(i))) = i
        next(key(i)) = next(key(i)) + 1
      end do
      do i = 2, n
        call check(error, key(placed(i - 1)) < key(placed(i)) .or. (key(placed(i - 1)) == key(placed(i)) &
          .and. placed(i - 1) < placed(i)), "by key, then in order")
        if (allocated(error)) return
      end do
      call check(error, all(placed > 0), "every entry placed")
      if (allocated(error)) return
      deallocate(key, per_key, placed)
    end do
  contains
    integer(i8) function next_key(state)
      integer(i8), intent(inout) :: state
      ! (a small linear congruential sequence that stays far from overflow)
      state = modulo(state*48271_i8, 2147483647_i8)
      next_key = state/1000_i8
    end function next_key
  end subroutine test_buckets

  !> radix_sort(a) ascends and holds a's keys, each as often (counted).
  subroutine expect_sorted(error, keys)
    type(error_type), allocatable, intent(out) :: error
    integer(i8), intent(in) :: keys(:)
    integer(i8), allocatable :: a(:)
    integer :: i
    a = keys
    call radix_sort(a)
    call check(error, size(a) == size(keys), "the same length")
    if (allocated(error)) return
    do i = 2, size(a)
      call check(error, a(i - 1) <= a(i), "ascending at entry")
      if (allocated(error)) return
    end do
    do i = 1, size(a)
      call check(error, count(a == a(i)) == count(keys == a(i)), "each key as often as given")
      if (allocated(error)) return
    end do
  end subroutine expect_sorted

  !> A 64-bit pseudo-random key (xorshift64; every bit pattern but 0).
  integer(i8) function next(state)
    integer(i8), intent(inout) :: state
    state = ieor(state, shiftl(state, 13))
    state = ieor(state, shiftr(state, 7))
    state = ieor(state, shiftl(state, 17))
    next = state
  end function next

end module test_sort
