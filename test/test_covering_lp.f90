!> Tests of the covering linear program (min c't, A t >= r, t >= 0, A >= 0)
!> behind the mass scaling: known optima, a degenerate one, random programs
!> checked by their duality certificate, bad input refused by name.
module test_covering_lp
  use testdrive, only: new_unittest, unittest_type, error_type, check
  use demstep_kinds, only: dp
  use demstep_status, only: demstep_status_type, demstep_stat, is_ok
  use demstep_covering_lp, only: covering_lp
  use test_support, only: real_str, seed_fixed
  implicit none
  private
  public :: collect_covering_lp

contains

  subroutine collect_covering_lp(testsuite)
    type(unittest_type), allocatable, intent(out) :: testsuite(:)
    testsuite = [ &
      new_unittest("two cuts, two columns: the known vertex and prices", test_known), &
      new_unittest("a tied optimum, a redundant row, r <= 0 rows and repeated entries", test_degenerate), &
      new_unittest("random sparse programs: primal and dual feasible, no gap", test_random), &
      new_unittest("bad input refused by name and index", test_bad_input) &
      ]
  end subroutine collect_covering_lp

  !> min t1 + t2, t1 + 2 t2 >= 2, 3 t1 + t2 >= 3: the vertex (0.8, 0.6), value
  !> 1.4, dual prices (0.4, 0.2). A unique non-degenerate vertex: the interior
  !> point iterates reach it to about their tolerance 1e-9 (asserted to 1e-7).
  subroutine test_known(error)
    type(error_type), allocatable, intent(out) :: error
    type(demstep_status_type) :: status
    real(dp), allocatable :: t(:), y(:)
    call covering_lp([1, 3, 5], [1, 2, 1, 2], [1.0_dp, 2.0_dp, 3.0_dp, 1.0_dp], [2.0_dp, 3.0_dp], &
      [1.0_dp, 1.0_dp], t, y, status)
    call check(error, is_ok(status), "status "//status%message)
    if (allocated(error)) return
    call check(error, maxval(abs(t - [0.8_dp, 0.6_dp])) < 1.0e-7_dp .and. maxval(abs(y - [0.4_dp, 0.2_dp])) &
      < 1.0e-7_dp, "t "//real_str(t(1))//" "//real_str(t(2))//", y "//real_str(y(1))//" "//real_str(y(2)))
  end subroutine test_known

  !> min 2a + b + c with a + b >= 1, 3b + c >= 1 (3b given as two entries 1
  !> and 2 of one column), a + b + c >= 0.5 (redundant) and a row with r = -1
  !> (holds for every t >= 0): the vertex (0, 1, 0), value 1, prices (1, 0,
  !> 0, 0). Then a tied face: min a + b + c with a + b >= 1 and a + b + c >=
  !> 0.5 is 1 at any a + b = 1, c = 0; and the triangle a + b, b + c, a + c
  !> >= 1: 1.5 at (0.5, 0.5, 0.5). Each to 1e-7 (the iterates' tolerance 1e-9).
  subroutine test_degenerate(error)
    type(error_type), allocatable, intent(out) :: error
    type(demstep_status_type) :: status
    real(dp), allocatable :: t(:), y(:)
    integer :: k
    call covering_lp([1, 3, 6, 9, 10], [1, 2, 2, 2, 3, 1, 2, 3, 1], &
      [1.0_dp, 1.0_dp, 1.0_dp, 2.0_dp, 1.0_dp, 1.0_dp, 1.0_dp, 1.0_dp, 1.0_dp], &
      [1.0_dp, 1.0_dp, 0.5_dp, -1.0_dp], [2.0_dp, 1.0_dp, 1.0_dp], t, y, status)
    call check(error, is_ok(status), "status "//status%message)
    if (allocated(error)) return
    call check(error, maxval(abs(t - [0.0_dp, 1.0_dp, 0.0_dp])) < 1.0e-7_dp .and. &
      maxval(abs(y - [1.0_dp, 0.0_dp, 0.0_dp, 0.0_dp])) < 1.0e-7_dp, "t "//real_str(t(1))//" " &
      //real_str(t(2))//" "//real_str(t(3))//", y "//real_str(y(1))//" "//real_str(y(2)))
    if (allocated(error)) return
    ! a tied face
    call covering_lp([1, 3, 6], [1, 2, 1, 2, 3], [(1.0_dp, k = 1, 5)], [1.0_dp, 0.5_dp], &
      [1.0_dp, 1.0_dp, 1.0_dp], t, y, status)
    call check(error, is_ok(status) .and. abs(t(1) + t(2) - 1.0_dp) < 1.0e-7_dp .and. abs(t(3)) < 1.0e-7_dp &
      .and. minval(t) >= 0.0_dp, "tied face: "//real_str(t(1) + t(2))//", "//real_str(t(3)))
    if (allocated(error)) return
    ! the triangle
    call covering_lp([1, 3, 5, 7], [1, 2, 2, 3, 1, 3], [(1.0_dp, k = 1, 6)], [1.0_dp, 1.0_dp, 1.0_dp], &
      [1.0_dp, 1.0_dp, 1.0_dp], t, y, status)
    call check(error, is_ok(status) .and. maxval(abs(t - 0.5_dp)) < 1.0e-7_dp, "triangle: "//real_str(sum(t)))
  end subroutine test_degenerate

  !> Random sparse programs (40 rows, 60 columns, 5 entries a row, some rows
  !> with r <= 0): the answer and its prices are a duality certificate, each
  !> within 1e-7 relative: A t >= r, t >= 0, A'y <= c, y >= 0 and c't = r'y.
  !> (Any pair meeting these is optimal: the test fails on a wrong optimum.)
  subroutine test_random(error)
    type(error_type), allocatable, intent(out) :: error
    type(demstep_status_type) :: status
    real(dp), allocatable :: t(:), y(:), val(:), r(:), c(:), at(:), aty(:), u(:)
    integer, allocatable :: row_start(:), col(:)
    integer, parameter :: m = 40, n = 60, per_row = 5
    integer :: trial, k, p
    real(dp) :: primal, dual
    call seed_fixed(29)
    do trial = 1, 5
      allocate(val(m*per_row), col(m*per_row), r(m), c(n), u(m*per_row))
      row_start = [(1 + (k - 1)*per_row, k = 1, m + 1)]
      call random_number(u)
      col = 1 + int(u*n)
      call random_number(val)
      call random_number(r)
      r = 2.0_dp*r - 0.3_dp
      call random_number(c)
      c = 0.1_dp + c
      call covering_lp(row_start, col, val, r, c, t, y, status)
      call check(error, is_ok(status), "trial "//real_str(real(trial, dp))//": "//status%message)
      if (allocated(error)) return
      allocate(at(m), aty(n), source=0.0_dp)
      do k = 1, m
        do p = row_start(k), row_start(k + 1) - 1
          at(k) = at(k) + val(p)*t(col(p))
          aty(col(p)) = aty(col(p)) + val(p)*y(k)
        end do
      end do
      primal = dot_product(c, t)
      dual = dot_product(r, y)
      call check(error, all(at >= r - 1.0e-7_dp*(1.0_dp + abs(r))) .and. minval(t) >= 0.0_dp .and. &
        all(aty <= c*(1.0_dp + 1.0e-7_dp)) .and. minval(y) >= 0.0_dp .and. &
        abs(primal - dual) <= 1.0e-7_dp*(1.0_dp + primal), "trial "//real_str(real(trial, dp))//": primal " &
        //real_str(primal)//", dual "//real_str(dual)//", worst row "//real_str(minval(at - r)))
      if (allocated(error)) return
      deallocate(val, col, r, c, u, at, aty)
    end do
  end subroutine test_random

  subroutine test_bad_input(error)
    type(error_type), allocatable, intent(out) :: error
    type(demstep_status_type) :: status
    real(dp), allocatable :: t(:), y(:)
    ! a negative entry
    call covering_lp([1, 3], [1, 2], [1.0_dp, -1.0_dp], [1.0_dp], [1.0_dp, 1.0_dp], t, y, status)
    call check(error, status%stat == demstep_stat%invalid_input .and. status%where == "val" .and. &
      status%index == 2, "negative entry: "//status%message)
    if (allocated(error)) return
    ! a column out of range
    call covering_lp([1, 3], [1, 3], [1.0_dp, 1.0_dp], [1.0_dp], [1.0_dp, 1.0_dp], t, y, status)
    call check(error, status%stat == demstep_stat%invalid_input .and. status%where == "col" .and. &
      status%index == 2, "column: "//status%message)
    if (allocated(error)) return
    ! a cost not > 0
    call covering_lp([1, 3], [1, 2], [1.0_dp, 1.0_dp], [1.0_dp], [1.0_dp, 0.0_dp], t, y, status)
    call check(error, status%stat == demstep_stat%invalid_input .and. status%where == "c" .and. &
      status%index == 2, "cost: "//status%message)
    if (allocated(error)) return
    ! a row that can not be met (r > 0, no positive entry)
    call covering_lp([1, 2, 3], [1, 2], [1.0_dp, 0.0_dp], [1.0_dp, 1.0_dp], [1.0_dp, 1.0_dp], t, y, status)
    call check(error, status%stat == demstep_stat%invalid_input .and. status%where == "r" .and. &
      status%index == 2, "infeasible row: "//status%message)
    if (allocated(error)) return
    ! row starts of the wrong size
    call covering_lp([1, 3], [1, 2], [1.0_dp, 1.0_dp], [1.0_dp, 1.0_dp], [1.0_dp, 1.0_dp], t, y, status)
    call check(error, status%stat == demstep_stat%invalid_input .and. status%where == "row_start", &
      "row starts: "//status%message)
    if (allocated(error)) return
    ! entries past the last row's (one unused, with a column out of range)
    call covering_lp([1, 3], [1, 2, 99], [1.0_dp, 1.0_dp, 1.0_dp], [1.0_dp], [1.0_dp, 1.0_dp], t, y, status)
    call check(error, status%stat == demstep_stat%invalid_input .and. status%where == "row_start", &
      "unused entries: "//status%message)
  end subroutine test_bad_input

end module test_covering_lp
