!> Tests of demstep_double_double against quad precision (real128): the
!> error-free transformations are exact, and the operations and sin/cos of pi t
!> are correct to double-double precision.
!>
!> Tolerances: a double-double holds about 106 bits; the operations used here
!> (Dekker/Knuth with one renormalisation) are accurate to a few units of 2^-104
!> relative, so 2^-100 leaves a margin of 16 while staying 2^-47 below what a
!> plain double could reach. Quad has 113 bits, so its own rounding (2^-113) is
!> negligible against the bound.
module test_double_double
  use testdrive, only: new_unittest, unittest_type, error_type, check, test_failed
  use demstep_kinds, only: dp
  use demstep_double_double, only: dd_type, two_sum, two_prod, dd, dd_add, dd_sub, dd_mul, &
    dd_mul_d, dd_div, dd_div_d, dd_neg, dd_sinpi, dd_cospi
  use test_support, only: real_str, sinpi_q
  use, intrinsic :: iso_fortran_env, only: qp => real128
  implicit none
  private
  public :: collect_double_double

  !> Relative accuracy asked of every double-double result (see the module header).
  real(qp), parameter :: dd_tol = 2.0_qp**(-100)

contains

  subroutine collect_double_double(testsuite)
    type(unittest_type), allocatable, intent(out) :: testsuite(:)
    testsuite = [ &
      new_unittest("two_sum and two_prod are exact", test_error_free), &
      new_unittest("add, sub, mul, div to 2^-100 against quad", test_arithmetic), &
      new_unittest("sin(pi t), cos(pi t) on [-1/2, 1/2] to 2^-100 against quad", test_trig) &
      ]
  end subroutine collect_double_double

  !> The quad value of a double-double.
  elemental real(qp) function q(a)
    type(dd_type), intent(in) :: a
    q = real(a%hi, qp) + real(a%lo, qp)
  end function q

  !> A random double-double in [-1, 1] x 2^e, with a lo part of its own.
  function random_dd(e) result(a)
    integer, intent(in) :: e
    type(dd_type) :: a
    real(dp) :: u(2)
    call random_number(u)
    a = dd(scale(2.0_dp*u(1) - 1.0_dp, e), 0.0_dp)
    ! the lo part: a random fraction of half an ulp of hi, renormalised by dd_add
    a = dd_add(a, dd((u(2) - 0.5_dp)*spacing(a%hi), 0.0_dp))
  end function random_dd

  subroutine seed()
    integer :: n
    integer, allocatable :: s(:)
    call random_seed(size=n)
    allocate(s(n), source=20260522)
    call random_seed(put=s)
  end subroutine seed

  subroutine test_error_free(error)
    type(error_type), allocatable, intent(out) :: error
    real(dp) :: a, b, s, e, u(2)
    integer :: i
    call seed()
    do i = 1, 10000
      call random_number(u)
      a = scale(2.0_dp*u(1) - 1.0_dp, int(60.0_dp*u(2)) - 30)
      call random_number(u)
      b = scale(2.0_dp*u(1) - 1.0_dp, int(60.0_dp*u(2)) - 30)
      ! quad holds the exact sum and product of two doubles whose exponents are close
      ! enough (sum: within 113 - 53 bits; product: 106 bits)
      call two_sum(a, b, s, e)
      call check(error, real(s, qp) + real(e, qp) == real(a, qp) + real(b, qp), &
        "two_sum("//real_str(a)//", "//real_str(b)//") not exact")
      if (allocated(error)) return
      call check(error, abs(e) <= 0.5_dp*spacing(s), "two_sum: |e| <= ulp(s)/2")
      if (allocated(error)) return
      call two_prod(a, b, s, e)
      call check(error, real(s, qp) + real(e, qp) == real(a, qp)*real(b, qp), &
        "two_prod("//real_str(a)//", "//real_str(b)//") not exact")
      if (allocated(error)) return
    end do
  end subroutine test_error_free

  subroutine test_arithmetic(error)
    type(error_type), allocatable, intent(out) :: error
    type(dd_type) :: a, b
    real(qp) :: x, y, r
    integer :: i, k
    character(len=4), parameter :: names(6) = [character(len=4) :: "add", "sub", "mul", "div", &
      "muld", "divd"]
    call seed()
    do i = 1, 5000
      a = random_dd(mod(i, 17) - 8)
      b = random_dd(mod(3*i, 13) - 6)
      x = q(a)
      y = q(b)
      do k = 1, size(names)
        select case (k)
        case (1)
          r = abs(q(dd_add(a, b)) - (x + y))/max(abs(x) + abs(y), tiny(1.0_qp))
        case (2)
          r = abs(q(dd_sub(a, b)) - (x - y))/max(abs(x) + abs(y), tiny(1.0_qp))
        case (3)
          r = abs(q(dd_mul(a, b)) - x*y)/abs(x*y)
        case (4)
          r = abs(q(dd_div(a, b)) - x/y)/abs(x/y)
        case (5)
          r = abs(q(dd_mul_d(a, b%hi)) - x*real(b%hi, qp))/abs(x*real(b%hi, qp))
        case (6)
          r = abs(q(dd_div_d(a, b%hi)) - x/real(b%hi, qp))/abs(x/real(b%hi, qp))
        end select
        call check(error, r <= dd_tol, trim(names(k))//": relative error "// &
          real_str(real(r, dp))//" at case "//real_str(real(i, dp)))
        if (allocated(error)) return
      end do
      call check(error, q(dd_neg(a)) == -x, "neg is exact")
      if (allocated(error)) return
    end do
  end subroutine test_arithmetic

  !> sin and cos of pi t against quad sin(pi t); cos(pi t) = sin(pi (1/2 - t)) in
  !> quad. The error is relative to max(|value|, 2^-8): at a zero the quad
  !> reference itself is off by about 1e-34 (pi rounded to quad, times the
  !> unreduced argument), which the floor 2^-8 x 2^-100 = 6e-33 absorbs. Near
  !> t = 0 sin(pi t) is checked relative to itself as well.
  subroutine test_trig(error)
    type(error_type), allocatable, intent(out) :: error
    type(dd_type) :: t
    real(qp) :: tq, s, c, r
    integer :: i
    call seed()
    do i = 0, 4000
      if (i <= 2000) then
        ! a grid over [-1/2, 1/2], ends included
        t = dd(-0.5_dp + real(i, dp)/2000.0_dp, 0.0_dp)
      else
        t = random_dd(-1)
      end if
      tq = q(t)
      s = sinpi_q(tq)
      c = sinpi_q(0.5_qp - tq)
      r = abs(q(dd_sinpi(t)) - s)/max(abs(s), 2.0_qp**(-8))
      call check(error, r <= dd_tol, "sin(pi t): relative error "//real_str(real(r, dp))// &
        " at t = "//real_str(t%hi))
      if (allocated(error)) return
      r = abs(q(dd_cospi(t)) - c)/max(abs(c), 2.0_qp**(-8))
      call check(error, r <= dd_tol, "cos(pi t): relative error "//real_str(real(r, dp))// &
        " at t = "//real_str(t%hi))
      if (allocated(error)) return
    end do
    ! small t: sin(pi t) relative to itself
    t = dd(1.0e-10_dp, 0.0_dp)
    s = sinpi_q(q(t))
    call check(error, abs(q(dd_sinpi(t)) - s) <= dd_tol*abs(s), "sin(pi 1e-10) to 2^-100 relative")
  end subroutine test_trig

end module test_double_double
