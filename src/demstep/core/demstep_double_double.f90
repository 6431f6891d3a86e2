!> Double-double arithmetic: a value is the unevaluated sum hi + lo of two doubles
!> (about 106 bits). Error-free transformations (Knuth's two-sum, Dekker's product)
!> and the few operations the accurate evaluators need, including sin and cos of
!> pi t for |t| <= 1/2. Pure double arithmetic: no extended or quad precision.
module demstep_double_double
  use demstep_kinds, only: dp
  use, intrinsic :: iso_fortran_env, only: int64
  implicit none
  private

  public :: dd_type, two_sum, two_prod, dd, dd_add, dd_sub, dd_mul, dd_mul_d, &
    dd_div, dd_div_d, dd_neg, dd_sinpi, dd_cospi, dot_parts

  !> The value hi + lo with |lo| <= ulp(hi)/2.
  type :: dd_type
    real(dp) :: hi = 0.0_dp
    real(dp) :: lo = 0.0_dp
  end type dd_type

  !> Clears the low 27 of the 52 stored mantissa bits: Dekker's split without a
  !> multiplication, so no compiler can contract it into a fused multiply-add.
  integer(int64), parameter :: high_bits = not(134217727_int64)
  !> 1/((2k)(2k+1)), k = 1..15, the ratios of successive sine Taylor terms.
  type(dd_type), parameter :: sin_coef(15) = [ &
    dd_type(0.16666666666666666_dp, 9.25185853854297e-18_dp), &
    dd_type(0.05_dp, -2.7755575615628915e-18_dp), &
    dd_type(0.023809523809523808_dp, 1.32169407693471e-18_dp), &
    dd_type(0.013888888888888888_dp, 7.709882115452476e-19_dp), &
    dd_type(0.00909090909090909_dp, 4.415659757031872e-19_dp), &
    dd_type(0.00641025641025641_dp, 2.2240044563805217e-19_dp), &
    dd_type(0.004761904761904762_dp, -4.295505750037808e-19_dp), &
    dd_type(0.003676470588235294_dp, 5.102127870520021e-20_dp), &
    dd_type(0.0029239766081871343_dp, 1.6231330769373633e-19_dp), &
    dd_type(0.002380952380952381_dp, -2.147752875018904e-19_dp), &
    dd_type(0.001976284584980237_dp, 1.3370398332627564e-19_dp), &
    dd_type(0.0016666666666666668_dp, -1.0697461435190311e-19_dp), &
    dd_type(0.0014245014245014246_dp, -7.104458680104445e-20_dp), &
    dd_type(0.0012315270935960591_dp, -1.3886333243656708e-20_dp), &
    dd_type(0.001075268817204301_dp, 9.326470300950576e-22_dp) ]
  !> 1/((2k-1)(2k)), k = 1..15, the ratios of successive cosine Taylor terms.
  type(dd_type), parameter :: cos_coef(15) = [ &
    dd_type(0.5_dp, 0.0_dp), &
    dd_type(0.08333333333333333_dp, 4.625929269271485e-18_dp), &
    dd_type(0.03333333333333333_dp, 4.625929269271486e-19_dp), &
    dd_type(0.017857142857142856_dp, 9.912705577010326e-19_dp), &
    dd_type(0.011111111111111112_dp, -4.2404351634988616e-19_dp), &
    dd_type(0.007575757575757576_dp, -2.1026951223961299e-19_dp), &
    dd_type(0.005494505494505495_dp, -4.2891514515910067e-19_dp), &
    dd_type(0.004166666666666667_dp, 5.782411586589357e-20_dp), &
    dd_type(0.0032679738562091504_dp, -9.920804192677818e-20_dp), &
    dd_type(0.002631578947368421_dp, 5.934580312552235e-20_dp), &
    dd_type(0.0021645021645021645_dp, 1.8774063592822588e-21_dp), &
    dd_type(0.0018115942028985507_dp, -2.199830494898125e-20_dp), &
    dd_type(0.0015384615384615385_dp, 1.3344026738283131e-21_dp), &
    dd_type(0.0013227513227513227_dp, 7.3427448718595e-20_dp), &
    dd_type(0.0011494252873563218_dp, 1.595148023886719e-20_dp) ]
  !> pi as a double-double.
  type(dd_type), parameter :: dd_pi = dd_type(3.141592653589793116_dp, 1.2246467991473532e-16_dp)

contains

  !> s + e = a + b exactly (Knuth).
  elemental subroutine two_sum(a, b, s, e)
    real(dp), intent(in) :: a, b
    real(dp), intent(out) :: s, e
    call sum_kernel(a, b, s, e)
  end subroutine two_sum

  !> p + e = a b (Dekker's product): exact but for the rounding of the last,
  !> 27-by-27-bit partial product, an error below |a b| 2^-104.
  elemental subroutine two_prod(a, b, p, e)
    real(dp), intent(in) :: a, b
    real(dp), intent(out) :: p, e
    call prod_kernel(a, b, p, e)
  end subroutine two_prod

  !> x.y as (sum, its error) in twice the working precision: each product
  !> split exactly (`two_prod`) and summed with `two_sum`, the errors summed
  !> apart (a compensated dot product, Ogita, Rump and Oishi's Dot2).
  pure function dot_parts(x, y) result(parts)
    real(dp), intent(in) :: x(:), y(:)
    real(dp) :: parts(2)
    real(dp) :: p, q, h, r
    integer :: i
    parts = 0.0_dp
    do i = 1, size(x)
      call prod_kernel(x(i), y(i), h, r)
      call sum_kernel(parts(1), h, p, q)
      parts(1) = p
      parts(2) = parts(2) + (q + r)
    end do
  end function dot_parts

  !> The body of `two_sum` (private: compiled into this module's loops, which
  !> a public procedure under -fPIC is not).
  elemental subroutine sum_kernel(a, b, s, e)
    real(dp), intent(in) :: a, b
    real(dp), intent(out) :: s, e
    real(dp) :: v
    s = a + b
    v = s - a
    e = (a - (s - v)) + (b - v)
  end subroutine sum_kernel

  !> The body of `two_prod` (private, as `sum_kernel`).
  elemental subroutine prod_kernel(a, b, p, e)
    real(dp), intent(in) :: a, b
    real(dp), intent(out) :: p, e
    real(dp) :: ah, al, bh, bl
    p = a*b
    ah = transfer(iand(transfer(a, 0_int64), high_bits), 1.0_dp)
    al = a - ah
    bh = transfer(iand(transfer(b, 0_int64), high_bits), 1.0_dp)
    bl = b - bh
    e = ((ah*bh - p) + ah*bl + al*bh) + al*bl
  end subroutine prod_kernel

  !> Normalise hi + lo.
  elemental function dd(hi, lo) result(c)
    real(dp), intent(in) :: hi, lo
    type(dd_type) :: c
    call two_sum(hi, lo, c%hi, c%lo)
  end function dd

  elemental function dd_neg(a) result(c)
    type(dd_type), intent(in) :: a
    type(dd_type) :: c
    c = dd_type(-a%hi, -a%lo)
  end function dd_neg

  elemental function dd_add(a, b) result(c)
    type(dd_type), intent(in) :: a, b
    type(dd_type) :: c
    real(dp) :: s, e, t, f, s2, e2
    call two_sum(a%hi, b%hi, s, e)
    call two_sum(a%lo, b%lo, t, f)
    e = e + t
    call fast_two_sum(s, e, s2, e2)
    e2 = e2 + f
    call fast_two_sum(s2, e2, c%hi, c%lo)
  end function dd_add

  elemental function dd_abs(a) result(c)
    type(dd_type), intent(in) :: a
    type(dd_type) :: c
    c = a
    if (a%hi < 0.0_dp) c = dd_neg(a)
  end function dd_abs

  elemental function dd_sub(a, b) result(c)
    type(dd_type), intent(in) :: a, b
    type(dd_type) :: c
    c = dd_add(a, dd_neg(b))
  end function dd_sub

  elemental function dd_mul(a, b) result(c)
    type(dd_type), intent(in) :: a, b
    type(dd_type) :: c
    real(dp) :: p, e
    call two_prod(a%hi, b%hi, p, e)
    e = e + (a%hi*b%lo + a%lo*b%hi)
    call fast_two_sum(p, e, c%hi, c%lo)
  end function dd_mul

  elemental function dd_mul_d(a, b) result(c)
    type(dd_type), intent(in) :: a
    real(dp), intent(in) :: b
    type(dd_type) :: c
    real(dp) :: p, e
    call two_prod(a%hi, b, p, e)
    e = e + a%lo*b
    call fast_two_sum(p, e, c%hi, c%lo)
  end function dd_mul_d

  !> a / b by two correction steps.
  elemental function dd_div(a, b) result(c)
    type(dd_type), intent(in) :: a, b
    type(dd_type) :: c, r
    real(dp) :: q1, q2, q3
    q1 = a%hi/b%hi
    r = dd_sub(a, dd_mul_d(b, q1))
    q2 = r%hi/b%hi
    r = dd_sub(r, dd_mul_d(b, q2))
    q3 = r%hi/b%hi
    call fast_two_sum(q1, q2, c%hi, c%lo)
    c = dd_add(c, dd_type(q3, 0.0_dp))
  end function dd_div

  elemental function dd_div_d(a, b) result(c)
    type(dd_type), intent(in) :: a
    real(dp), intent(in) :: b
    type(dd_type) :: c
    c = dd_div(a, dd_type(b, 0.0_dp))
  end function dd_div_d

  !> sin(pi t) for |t| <= 1/2 (a little beyond is fine).
  elemental function dd_sinpi(t) result(s)
    type(dd_type), intent(in) :: t
    type(dd_type) :: s
    type(dd_type) :: u
    if (abs(t%hi) <= 0.25_dp) then
      s = sin_series(dd_mul(dd_pi, t))
    else
      ! sin(pi t) = sign(t) cos(pi (1/2 - |t|))
      u = dd_sub(dd_type(0.5_dp, 0.0_dp), dd_abs(t))
      s = cos_series(dd_mul(dd_pi, u))
      if (t%hi < 0.0_dp) s = dd_neg(s)
    end if
  end function dd_sinpi

  !> cos(pi t) for |t| <= 1/2 (a little beyond is fine).
  elemental function dd_cospi(t) result(c)
    type(dd_type), intent(in) :: t
    type(dd_type) :: c
    type(dd_type) :: u
    if (abs(t%hi) <= 0.25_dp) then
      c = cos_series(dd_mul(dd_pi, t))
    else
      u = dd_sub(dd_type(0.5_dp, 0.0_dp), dd_abs(t))
      c = sin_series(dd_mul(dd_pi, u))
    end if
  end function dd_cospi

  !> Taylor series of sin for |x| <= pi/4 + a little: 15 terms reach 2^-110.
  elemental function sin_series(x) result(s)
    type(dd_type), intent(in) :: x
    type(dd_type) :: s, x2
    integer :: k
    x2 = dd_mul(x, x)
    s = dd_type(1.0_dp, 0.0_dp)
    do k = 15, 1, -1
      ! s = 1 - x^2 s / ((2k)(2k+1))
      s = dd_sub(dd_type(1.0_dp, 0.0_dp), dd_mul(dd_mul(x2, s), sin_coef(k)))
    end do
    s = dd_mul(x, s)
  end function sin_series

  !> Taylor series of cos for |x| <= pi/4 + a little.
  elemental function cos_series(x) result(c)
    type(dd_type), intent(in) :: x
    type(dd_type) :: c, x2
    integer :: k
    x2 = dd_mul(x, x)
    c = dd_type(1.0_dp, 0.0_dp)
    do k = 15, 1, -1
      ! c = 1 - x^2 c / ((2k-1)(2k))
      c = dd_sub(dd_type(1.0_dp, 0.0_dp), dd_mul(dd_mul(x2, c), cos_coef(k)))
    end do
  end function cos_series

  !> s + e = a + b exactly when |a| >= |b|.
  elemental subroutine fast_two_sum(a, b, s, e)
    real(dp), intent(in) :: a, b
    real(dp), intent(out) :: s, e
    s = a + b
    e = b - (s - a)
  end subroutine fast_two_sum

end module demstep_double_double
