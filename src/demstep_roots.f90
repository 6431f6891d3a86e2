!> Root finding for any real function of one variable.
!>
!> User functions come through the abstract interface `root_function` with a
!> context: extend `root_context_type` with the data the function needs and
!> recover it with `select type`. The context also counts evaluations.
!>
!> - `find_root`: ITP (interpolate, truncate, project; Oliveira & Takahashi,
!>   ACM TOMS 47(1), 2020) on a sign-change bracket. It never needs more
!>   evaluations than bisection plus one, and converges superlinearly on smooth
!>   functions. After convergence a continuity probe rejects poles and jumps.
!> - `scan_roots`: every sign change of f on a grid, each refined by find_root;
!>   poles and jumps are returned apart from the roots.
!>
!> Tolerances: the bracket is shrunk until its width is at most
!> `2 (x_abs + x_rel |x|)`, so the returned root is within `x_abs + x_rel |x|` of a
!> sign change of f; with `f_tol > 0` the search also stops at the first point
!> where |f| <= f_tol.
module demstep_roots
  use demstep_kinds, only: dp
  use demstep_status, only: demstep_status_type, demstep_stat, set_status
  use, intrinsic :: ieee_arithmetic, only: ieee_is_finite
  implicit none
  private

  public :: root_function, find_root, scan_roots, geometric_grid, sort_ascending

  !> Base of the user's context: extend it with the function's data.
  type, public :: root_context_type
    !> Evaluations of the function made through this module.
    integer :: evaluations = 0
  end type root_context_type

  abstract interface
    !> f(x); `stat /= 0` means f cannot be evaluated at x (a pole, say).
    pure subroutine root_function(x, context, fx, stat)
      import :: dp, root_context_type
      real(dp), intent(in) :: x
      class(root_context_type), intent(inout) :: context
      real(dp), intent(out) :: fx
      integer, intent(out) :: stat
    end subroutine root_function
  end interface

  !> Default relative tolerance in x.
  real(dp), parameter, public :: root_x_rel_default = 1.0e-13_dp
  !> The continuity probe first looks this many final bracket widths away.
  real(dp), parameter :: probe_factor = 128.0_dp
  !> At a root |f| at the final bracket must be below this share of |f| at the probes.
  real(dp), parameter :: probe_ratio = 0.25_dp

contains

  !> A root of f in [a, b], where f(a) and f(b) differ in sign.
  !>
  !> `status`: ok; `not_found` when f(a), f(b) do not bracket a sign change;
  !> `discontinuous` when the bracket closed onto a discontinuity (pole or jump:
  !> |f| did not shrink with the bracket; `root` is then where it is);
  !> `invalid_input` for a bad interval or tolerance; `pole` when f cannot be
  !> evaluated inside the bracket.
  pure subroutine find_root(f, context, a, b, root, status, x_rel, x_abs, f_tol, fa, fb, &
      discontinuity, check_continuity, bracket_lo, bracket_hi)
    procedure(root_function) :: f
    class(root_context_type), intent(inout) :: context
    !> The bracket.
    real(dp), intent(in) :: a, b
    !> The root (or the discontinuity, see status).
    real(dp), intent(out) :: root
    type(demstep_status_type), intent(out) :: status
    !> Tolerances in x (defaults 1e-13 relative, 0 absolute) and in f (default 0).
    real(dp), intent(in), optional :: x_rel, x_abs, f_tol
    !> f(a), f(b) when the caller has them (saves two evaluations).
    real(dp), intent(in), optional :: fa, fb
    !> Set when the bracket closed onto a discontinuity rather than a root.
    logical, intent(out), optional :: discontinuity
    !> Probe continuity after convergence (default true; 2 evaluations). Turn it
    !> off where a sign change at a jump is an answer too.
    logical, intent(in), optional :: check_continuity
    !> The final bracket: f(bracket_lo) has the sign of f(a), f(bracket_hi) that of
    !> f(b) (both are `root` where f(root) = 0 was hit). A caller that needs a point
    !> on a given side of the sign change takes that end.
    real(dp), intent(out), optional :: bracket_lo, bracket_hi
    real(dp) :: lo, hi, flo, fhi, rel, abst, ftol, y, x, width0, tol, fl, fr, h
    integer :: stat
    logical :: jump
    rel = root_x_rel_default
    abst = 0.0_dp
    ftol = 0.0_dp
    if (present(x_rel)) rel = x_rel
    if (present(x_abs)) abst = x_abs
    if (present(f_tol)) ftol = f_tol
    if (present(discontinuity)) discontinuity = .false.
    root = 0.5_dp*(a + b)
    if (present(bracket_lo)) bracket_lo = a
    if (present(bracket_hi)) bracket_hi = b
    if (.not. (ieee_is_finite(a) .and. ieee_is_finite(b) .and. a < b)) then
      call set_status(status, demstep_stat%invalid_input, "find_root: need finite a < b")
      return
    end if
    if (.not. (rel >= 0.0_dp .and. abst >= 0.0_dp .and. ftol >= 0.0_dp .and. rel + abst > 0.0_dp)) then
      call set_status(status, demstep_stat%invalid_input, "find_root: tolerances must be >= 0, " &
        //"x_rel + x_abs > 0")
      return
    end if
    lo = a
    hi = b
    if (present(fa)) then
      flo = fa
    else
      call evaluate(f, context, lo, flo, stat)
      if (stat /= 0) then
        call set_status(status, demstep_stat%pole, "find_root: f cannot be evaluated at a")
        return
      end if
    end if
    if (present(fb)) then
      fhi = fb
    else
      call evaluate(f, context, hi, fhi, stat)
      if (stat /= 0) then
        call set_status(status, demstep_stat%pole, "find_root: f cannot be evaluated at b")
        return
      end if
    end if
    status%stat = demstep_stat%ok
    if (flo == 0.0_dp .or. abs(flo) <= ftol) then
      root = lo
      if (present(bracket_lo)) bracket_lo = root
      if (present(bracket_hi)) bracket_hi = root
      return
    end if
    if (fhi == 0.0_dp .or. abs(fhi) <= ftol) then
      root = hi
      if (present(bracket_lo)) bracket_lo = root
      if (present(bracket_hi)) bracket_hi = root
      return
    end if
    if ((flo > 0.0_dp) .eqv. (fhi > 0.0_dp)) then
      call set_status(status, demstep_stat%not_found, "find_root: f(a) and f(b) have the same sign")
      return
    end if
    width0 = hi - lo
    call itp(f, context, lo, hi, flo, fhi, rel, abst, ftol, x, y, stat)
    if (present(bracket_lo)) bracket_lo = lo
    if (present(bracket_hi)) bracket_hi = hi
    if (stat /= 0) then
      root = x
      call set_status(status, demstep_stat%pole, "find_root: f cannot be evaluated inside the bracket")
      return
    end if
    root = x
    if (y == 0.0_dp .or. abs(y) <= ftol) return
    if (present(check_continuity)) then
      if (.not. check_continuity) return
    end if
    ! continuity probe: at a root |f| grows away from the final bracket, at a pole
    ! or a jump it does not. Where rounding noise hides a shallow root the probe
    ! widens (x16) until |f| rises clear of the bracket's values.
    tol = max(hi - lo, tiny(1.0_dp))
    h = probe_factor*tol
    jump = width0 > 2.0_dp*h
    do while (jump)
      call evaluate(f, context, max(a, root - h), fl, stat)
      if (stat /= 0) exit
      call evaluate(f, context, min(b, root + h), fr, stat)
      if (stat /= 0) exit
      if (max(abs(flo), abs(fhi)) <= probe_ratio*min(abs(fl), abs(fr))) jump = .false.
      if (h >= 0.25_dp*width0) exit
      h = 16.0_dp*h
    end do
    if (jump) then
      if (present(discontinuity)) discontinuity = .true.
      call set_status(status, demstep_stat%discontinuous, &
        "find_root: the bracket closed onto a discontinuity (pole or jump), not a root")
    end if
  end subroutine find_root

  !> ITP iteration on [lo, hi] with f(lo) f(hi) < 0; returns the last point x, f(x)
  !> and the final bracket in lo, hi with flo, fhi.
  pure subroutine itp(f, context, lo, hi, flo, fhi, rel, abst, ftol, x, y, stat)
    procedure(root_function) :: f
    class(root_context_type), intent(inout) :: context
    real(dp), intent(inout) :: lo, hi, flo, fhi
    real(dp), intent(in) :: rel, abst, ftol
    real(dp), intent(out) :: x, y
    integer, intent(out) :: stat
    real(dp) :: eps, kappa1, xh, r, delta, xf, sigma, xt, s
    integer :: nmax, j
    ! work with g = s f, so that g(lo) < 0 < g(hi)
    s = sign(1.0_dp, fhi)
    ! ITP's guarantee needs one fixed tolerance: take the smallest |x| of the bracket
    eps = abst
    if (.not. (lo < 0.0_dp .and. hi > 0.0_dp)) eps = eps + rel*min(abs(lo), abs(hi))
    eps = max(eps, 4.0_dp*spacing(max(abs(lo), abs(hi))))
    kappa1 = 0.2_dp/(hi - lo)
    nmax = max(0, ceiling(log((hi - lo)/(2.0_dp*eps))/log(2.0_dp))) + 1
    j = 0
    stat = 0
    x = 0.5_dp*(lo + hi)
    y = flo
    do while (hi - lo > 2.0_dp*eps .and. j <= nmax + 8)
      xh = 0.5_dp*(lo + hi)
      r = eps*2.0_dp**(nmax - j) - 0.5_dp*(hi - lo)
      delta = kappa1*(hi - lo)**2
      xf = (hi*flo - lo*fhi)/(flo - fhi)
      if (.not. (xf > lo .and. xf < hi)) xf = xh
      sigma = sign(1.0_dp, xh - xf)
      if (delta <= abs(xh - xf)) then
        xt = xf + sigma*delta
      else
        xt = xh
      end if
      if (abs(xt - xh) <= r) then
        x = xt
      else
        x = xh - sigma*r
      end if
      if (.not. (x > lo .and. x < hi)) x = xh
      call evaluate(f, context, x, y, stat)
      if (stat /= 0) return
      if (y == 0.0_dp .or. abs(y) <= ftol) then
        lo = x
        hi = x
        flo = y
        fhi = y
        return
      end if
      if (s*y > 0.0_dp) then
        hi = x
        fhi = y
      else
        lo = x
        flo = y
      end if
      j = j + 1
    end do
    ! the point of the final bracket nearest to the sign change (linear estimate)
    x = (hi*flo - lo*fhi)/(flo - fhi)
    if (.not. (x >= lo .and. x <= hi)) x = 0.5_dp*(lo + hi)
    y = min(abs(flo), abs(fhi))
  end subroutine itp

  !> Every root of f at the sign changes between consecutive points of `grid`.
  !>
  !> Sign changes through a discontinuity are returned in `discontinuities`; grid
  !> points where f cannot be evaluated split the scan. Two roots closer than the
  !> grid spacing (or a root next to a pole in one cell) can cancel and be missed,
  !> and a root where f touches zero without changing sign is found only if it
  !> falls on a grid point.
  pure subroutine scan_roots(f, context, grid, roots, discontinuities, status, x_rel, x_abs)
    procedure(root_function) :: f
    class(root_context_type), intent(inout) :: context
    !> Increasing sample points.
    real(dp), intent(in) :: grid(:)
    real(dp), allocatable, intent(out) :: roots(:), discontinuities(:)
    type(demstep_status_type), intent(out) :: status
    !> Tolerances in x, as for `find_root`.
    real(dp), intent(in), optional :: x_rel, x_abs
    real(dp), allocatable :: fx(:)
    logical, allocatable :: ok(:)
    real(dp) :: x
    integer :: i, stat
    logical :: jump
    type(demstep_status_type) :: st
    allocate(roots(0), discontinuities(0))
    if (size(grid) < 2) then
      call set_status(status, demstep_stat%invalid_input, "scan_roots: need at least 2 grid points")
      return
    end if
    if (any(grid(2:) <= grid(:size(grid)-1))) then
      call set_status(status, demstep_stat%invalid_input, "scan_roots: grid must increase")
      return
    end if
    allocate(fx(size(grid)), ok(size(grid)))
    do i = 1, size(grid)
      call evaluate(f, context, grid(i), fx(i), stat)
      ok(i) = stat == 0
      if (ok(i) .and. fx(i) == 0.0_dp) roots = [roots, grid(i)]
    end do
    do i = 1, size(grid) - 1
      if (.not. (ok(i) .and. ok(i+1))) cycle
      if (fx(i) == 0.0_dp .or. fx(i+1) == 0.0_dp) cycle
      if ((fx(i) > 0.0_dp) .eqv. (fx(i+1) > 0.0_dp)) cycle
      call find_root(f, context, grid(i), grid(i+1), x, st, x_rel=x_rel, x_abs=x_abs, &
        fa=fx(i), fb=fx(i+1), discontinuity=jump)
      if (st%stat == demstep_stat%ok) then
        roots = [roots, x]
      else if (st%stat == demstep_stat%discontinuous .or. st%stat == demstep_stat%pole) then
        discontinuities = [discontinuities, x]
      end if
    end do
    call sort_ascending(roots)
    status%stat = demstep_stat%ok
  end subroutine scan_roots

  !> Points from a to b with x_{i+1} = x_i + max(abs_step, rel_step |x_i|); b is last.
  pure function geometric_grid(a, b, rel_step, abs_step) result(grid)
    real(dp), intent(in) :: a, b, rel_step, abs_step
    real(dp), allocatable :: grid(:)
    real(dp) :: x, h
    integer :: n
    h = max(abs_step, rel_step*abs(a))
    if (.not. (b > a .and. h > 0.0_dp)) then
      grid = [a]
      return
    end if
    ! count first, then fill
    n = 1
    x = a
    do while (x < b)
      x = x + max(abs_step, rel_step*abs(x))
      n = n + 1
    end do
    allocate(grid(n))
    grid(1) = a
    do n = 2, size(grid)
      grid(n) = min(b, grid(n-1) + max(abs_step, rel_step*abs(grid(n-1))))
    end do
    grid(size(grid)) = b
  end function geometric_grid

  !> One counted evaluation; a non-finite value counts as not evaluable.
  pure subroutine evaluate(f, context, x, fx, stat)
    procedure(root_function) :: f
    class(root_context_type), intent(inout) :: context
    real(dp), intent(in) :: x
    real(dp), intent(out) :: fx
    integer, intent(out) :: stat
    call f(x, context, fx, stat)
    context%evaluations = context%evaluations + 1
    if (stat == 0 .and. .not. ieee_is_finite(fx)) stat = demstep_stat%pole
  end subroutine evaluate

  !> Sort in place, ascending (insertion sort: the arrays here are short).
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

end module demstep_roots
