!> Tests of the general root finder and scanner on functions with known roots,
!> many close roots, poles and jumps.
module test_roots
  use testdrive, only: new_unittest, unittest_type, error_type, check, test_failed
  use demstep
  use demstep_roots, only: scan_break
  use demstep_kinds, only: pi
  use test_support, only: real_str
  implicit none
  private
  public :: collect_roots

  !> Which test function the context selects, and its parameter.
  type, extends(root_context_type) :: test_context_type
    integer :: which = 1
    real(dp) :: p = 0.0_dp
  end type test_context_type

contains

  subroutine collect_roots(testsuite)
    type(unittest_type), allocatable, intent(out) :: testsuite(:)
    testsuite = [ &
      new_unittest("smooth roots to the tolerance, few evaluations", test_smooth), &
      new_unittest("a pole in the bracket is not a root", test_pole), &
      new_unittest("a jump in the bracket is not a root", test_jump), &
      new_unittest("scan: 50 close roots of sin(50 pi x)", test_many_roots), &
      new_unittest("scan: roots of tan(20 pi x), poles apart", test_tan), &
      new_unittest("scan: known poles as breakpoints, a coarse grid, first root only", test_breaks), &
      new_unittest("f tolerance and bad brackets", test_statuses), &
      new_unittest("final bracket: each end keeps its side's sign", test_bracket) &
      ]
  end subroutine collect_roots

  pure subroutine f(x, context, fx, stat)
    real(dp), intent(in) :: x
    class(root_context_type), intent(inout) :: context
    real(dp), intent(out) :: fx
    integer, intent(out) :: stat
    stat = 0
    fx = 0.0_dp
    select type (context)
    type is (test_context_type)
      select case (context%which)
      case (1)
        fx = cos(x) - x
      case (2)
        fx = x**3 - context%p
      case (3)
        fx = 1.0_dp/(x - context%p)
      case (4)
        fx = merge(1.1_dp, -0.9_dp, x > context%p) + 1.0e-3_dp*(x - context%p)
      case (5)
        fx = sin(50.0_dp*pi*x)
      case (6)
        fx = tan(20.0_dp*pi*x)
      end select
    end select
  end subroutine f

  subroutine test_smooth(error)
    type(error_type), allocatable, intent(out) :: error
    type(test_context_type) :: ctx
    type(demstep_status_type) :: status
    real(dp) :: x
    ! the Dottie number, cos x = x
    ctx%which = 1
    call find_root(f, ctx, 0.0_dp, 1.0_dp, x, status, x_rel=1.0e-14_dp)
    call check(error, status%stat, demstep_stat%ok)
    if (allocated(error)) return
    call check(error, x, 0.7390851332151607_dp, thr=2.0e-14_dp, rel=.true., message="cos x = x")
    if (allocated(error)) return
    ! ITP never needs more than bisection (+1), plus 2 probe evaluations and 2 ends
    call check(error, ctx%evaluations <= 50 + 1 + 4, "evaluations "//real_str(real(ctx%evaluations, dp)))
    if (allocated(error)) return
    ctx%which = 2
    ctx%p = 2.0_dp
    ctx%evaluations = 0
    call find_root(f, ctx, 1.0_dp, 2.0_dp, x, status)
    call check(error, x, 2.0_dp**(1.0_dp/3.0_dp), thr=2.0e-13_dp, rel=.true., message="cube root of 2")
    if (allocated(error)) return
    call check(error, ctx%evaluations <= 20, "superlinear on a smooth root: " // &
      real_str(real(ctx%evaluations, dp))//" evaluations")
  end subroutine test_smooth

  subroutine test_pole(error)
    type(error_type), allocatable, intent(out) :: error
    type(test_context_type) :: ctx
    type(demstep_status_type) :: status
    real(dp) :: x
    logical :: jump
    ctx%which = 3
    ctx%p = 0.3_dp
    call find_root(f, ctx, 0.0_dp, 1.0_dp, x, status, discontinuity=jump)
    call check(error, status%stat, demstep_stat%discontinuous, message="1/(x - 0.3)")
    if (allocated(error)) return
    call check(error, jump, "flagged as a discontinuity")
    if (allocated(error)) return
    call check(error, x, 0.3_dp, thr=1.0e-12_dp, message="located at the pole")
  end subroutine test_pole

  subroutine test_jump(error)
    type(error_type), allocatable, intent(out) :: error
    type(test_context_type) :: ctx
    type(demstep_status_type) :: status
    real(dp) :: x
    logical :: jump
    ctx%which = 4
    ctx%p = 0.61_dp
    call find_root(f, ctx, 0.0_dp, 1.0_dp, x, status, discontinuity=jump)
    call check(error, status%stat == demstep_stat%discontinuous .and. jump, "a jump from -0.9 to 1.1")
  end subroutine test_jump

  subroutine test_many_roots(error)
    type(error_type), allocatable, intent(out) :: error
    type(test_context_type) :: ctx
    type(demstep_status_type) :: status
    real(dp), allocatable :: roots(:), poles(:)
    integer :: k
    ctx%which = 5
    ! roots k/50, 0.02 apart; grid step 0.005 (finer than the separation)
    call scan_roots(f, ctx, 0.013_dp, 1.007_dp, roots, poles, status, abs_step=0.005_dp, &
      x_abs=1.0e-15_dp, x_rel=0.0_dp)
    call check(error, status%stat, demstep_stat%ok)
    if (allocated(error)) return
    call check(error, size(roots), 50, message="every root found")
    if (allocated(error)) return
    call check(error, size(poles), 0, message="no discontinuity")
    if (allocated(error)) return
    do k = 1, 50
      call check(error, roots(k), real(k, dp)/50.0_dp, thr=1.0e-14_dp, message="root "//real_str(real(k, dp)))
      if (allocated(error)) return
    end do
  end subroutine test_many_roots

  subroutine test_tan(error)
    type(error_type), allocatable, intent(out) :: error
    type(test_context_type) :: ctx
    type(demstep_status_type) :: status
    real(dp), allocatable :: roots(:), poles(:)
    integer :: k
    ctx%which = 6
    ! roots k/20, poles (k + 1/2)/20: a sign change at every one of both
    call scan_roots(f, ctx, 0.0101_dp, 0.9899_dp, roots, poles, status, abs_step=0.004_dp, &
      x_abs=1.0e-15_dp, x_rel=0.0_dp)
    call check(error, size(roots), 19, message="roots k/20, k = 1..19")
    if (allocated(error)) return
    call check(error, size(poles), 20, message="poles (k + 1/2)/20, k = 0..19")
    if (allocated(error)) return
    do k = 1, 19
      call check(error, roots(k), real(k, dp)/20.0_dp, thr=1.0e-14_dp, message="root")
      if (allocated(error)) return
    end do
    do k = 1, 20
      call check(error, poles(k), (real(k, dp) - 0.5_dp)/20.0_dp, thr=1.0e-12_dp, message="pole")
      if (allocated(error)) return
    end do
  end subroutine test_tan

  subroutine test_statuses(error)
    type(error_type), allocatable, intent(out) :: error
    type(test_context_type) :: ctx
    type(demstep_status_type) :: status
    real(dp) :: x
    ctx%which = 1
    call find_root(f, ctx, 1.0_dp, 0.0_dp, x, status)
    call check(error, status%stat, demstep_stat%invalid_input, message="a > b")
    if (allocated(error)) return
    call find_root(f, ctx, 0.8_dp, 1.0_dp, x, status)
    call check(error, status%stat, demstep_stat%not_found, message="no sign change")
    if (allocated(error)) return
    call find_root(f, ctx, 0.0_dp, 1.0_dp, x, status, x_rel=0.0_dp, x_abs=0.0_dp)
    call check(error, status%stat, demstep_stat%invalid_input, message="zero x tolerance")
    if (allocated(error)) return
    ctx%evaluations = 0
    call find_root(f, ctx, 0.0_dp, 1.0_dp, x, status, f_tol=1.0e-3_dp)
    call check(error, status%stat == demstep_stat%ok .and. abs(cos(x) - x) <= 1.0e-3_dp, &
      "stops once |f| <= f_tol")
  end subroutine test_statuses

  !> The next pole (k + 1/2)/20 of tan(20 pi x) above a.
  pure subroutine tan_poles(context, a, b, kind)
    class(root_context_type), intent(inout) :: context
    real(dp), intent(in) :: a
    real(dp), intent(inout) :: b
    integer, intent(inout) :: kind
    real(dp) :: p
    p = (real(floor(20.0_dp*a - 0.5_dp), dp) + 1.5_dp)/20.0_dp
    if (.not. p > a) p = p + 0.05_dp
    if (p < b) then
      b = p
      kind = scan_break%pole
    end if
  end subroutine tan_poles

  !> With the poles given as breakpoints the scan never crosses one, so none is
  !> reported, and a grid coarser than the root spacing still finds every root:
  !> each piece between poles holds one root and one sign change. `first_only`
  !> stops at the first root.
  subroutine test_breaks(error)
    type(error_type), allocatable, intent(out) :: error
    type(test_context_type) :: ctx
    type(demstep_status_type) :: status
    real(dp), allocatable :: roots(:), poles(:)
    integer :: k, all_evaluations
    ctx%which = 6
    ! grid step 0.3, six times the spacing of the roots k/20
    call scan_roots(f, ctx, 0.0101_dp, 0.9899_dp, roots, poles, status, abs_step=0.3_dp, &
      x_abs=1.0e-15_dp, x_rel=0.0_dp, next_break=tan_poles)
    call check(error, status%stat, demstep_stat%ok)
    if (allocated(error)) return
    call check(error, size(poles), 0, message="no pole crossed")
    if (allocated(error)) return
    call check(error, size(roots), 19, message="roots k/20, k = 1..19")
    if (allocated(error)) return
    do k = 1, 19
      call check(error, roots(k), real(k, dp)/20.0_dp, thr=1.0e-14_dp, message="root")
      if (allocated(error)) return
    end do
    ctx%which = 5
    ctx%evaluations = 0
    call scan_roots(f, ctx, 0.013_dp, 1.007_dp, roots, poles, status, abs_step=0.005_dp, &
      x_abs=1.0e-15_dp, x_rel=0.0_dp)
    all_evaluations = ctx%evaluations
    ctx%evaluations = 0
    call scan_roots(f, ctx, 0.013_dp, 1.007_dp, roots, poles, status, abs_step=0.005_dp, &
      x_abs=1.0e-15_dp, x_rel=0.0_dp, first_only=.true.)
    call check(error, size(roots), 1, message="first_only: one root")
    if (allocated(error)) return
    call check(error, roots(1), 0.02_dp, thr=1.0e-14_dp, message="first_only: the first root")
    if (allocated(error)) return
    call check(error, ctx%evaluations < all_evaluations/10, "first_only stops early: " &
      //real_str(real(ctx%evaluations, dp))//" evaluations")
    if (allocated(error)) return
    call scan_roots(f, ctx, 1.0_dp, 0.5_dp, roots, poles, status, abs_step=0.1_dp)
    call check(error, status%stat, demstep_stat%invalid_input, message="lo > hi")
    if (allocated(error)) return
    call scan_roots(f, ctx, 0.0_dp, 1.0_dp, roots, poles, status)
    call check(error, status%stat, demstep_stat%invalid_input, message="no grid step")
  end subroutine test_breaks

  !> The final bracket holds the sign change, each end on its own side, and is
  !> as narrow as asked, down to find_root's floor of a few ulps.
  subroutine test_bracket(error)
    type(error_type), allocatable, intent(out) :: error
    type(test_context_type) :: ctx
    type(demstep_status_type) :: status
    real(dp) :: x, lo, hi, flo, fhi
    integer :: stat, k
    real(dp), parameter :: rel(3) = [1.0e-6_dp, 1.0e-13_dp, 0.0_dp]
    ctx%which = 2
    ctx%p = 2.0_dp
    do k = 1, size(rel)
      ! x^3 - 2 on [2, 1]: negative at a = 1, positive at b = 2
      call find_root(f, ctx, 1.0_dp, 2.0_dp, x, status, x_rel=rel(k), x_abs=tiny(1.0_dp), &
        check_continuity=.false., bracket_lo=lo, bracket_hi=hi)
      call check(error, status%stat, demstep_stat%ok)
      if (allocated(error)) return
      call f(lo, ctx, flo, stat)
      call f(hi, ctx, fhi, stat)
      ! (both ends are the root where f(root) = 0 was hit)
      call check(error, flo <= 0.0_dp .and. fhi >= 0.0_dp, "f(lo) <= 0 <= f(hi) at x_rel "//real_str(rel(k)))
      if (allocated(error)) return
      call check(error, lo <= x .and. x <= hi, "the root lies in its bracket")
      if (allocated(error)) return
      ! width at most 2 max(x_rel |x|, 4 ulp(x))
      call check(error, hi - lo <= 2.0_dp*max(rel(k)*lo, 4.0_dp*spacing(hi)), &
        "bracket width "//real_str(hi - lo)//" at x_rel "//real_str(rel(k)))
      if (allocated(error)) return
    end do
    ! f(a) = 0: the bracket is that point
    call find_root(f, ctx, 2.0_dp**(1.0_dp/3.0_dp), 2.0_dp, x, status, fa=0.0_dp, bracket_lo=lo, bracket_hi=hi)
    call check(error, lo == x .and. hi == x, "f(a) = 0: bracket [a, a]")
  end subroutine test_bracket

end module test_roots
