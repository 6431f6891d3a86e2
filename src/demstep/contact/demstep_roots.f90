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
!>   poles and jumps are returned apart from the roots. The grid may be split
!>   at known poles and jumps (sampled one-sidedly), and a caller's `visit`
!>   sees every sample: `n_roots` of demstep_stiffness is built on it.
!>
!> Tolerances: the bracket is shrunk until its width is at most
!> `2 (x_abs + x_rel |x|)`, so the returned root is within `x_abs + x_rel |x|` of a
!> sign change of f; with `f_tol > 0` the search also stops at the first point
!> where |f| <= f_tol.
module demstep_roots
  use demstep_sort, only: sort_ascending
  use demstep_kinds, only: dp
  use demstep_status, only: demstep_status_type, demstep_stat, set_status
  use, intrinsic :: ieee_arithmetic, only: ieee_is_finite
  use demstep_words, only: word_index, word_of
  implicit none
  private

  public :: root_function, find_root, scan_roots, append
  public :: scan_break_function, scan_step_function, scan_visit_function

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

  !> The kinds of breakpoints of a scan, by name: `scan_break%pole`.
  type, public :: scan_break_enum
    !> Inside a piece (no breakpoint).
    integer :: none = -1
    !> The start of the range.
    integer :: start = 0
    !> A pole: f is sampled a relative `scan_pole_offset` away on either side.
    integer :: pole = 1
    !> A jump: f is sampled on it and just after it, with no root sought across.
    integer :: jump = 2
    !> The end of the range.
    integer :: end = 3
  end type scan_break_enum
  !> The breakpoint kinds by name.
  type(scan_break_enum), parameter, public :: scan_break = scan_break_enum()
  !> Their words, in code order (`scan_break_from_name`, `scan_break_name`).
  character(len=*), parameter, public :: scan_break_names(5) = [character(len=5) :: "none", "start", "pole", "jump", "end"]
  public :: scan_break_from_name, scan_break_name
  !> One-sided samples sit this far (relative) from a pole: beyond a 4-ulp pole
  !> test, far below the 1e-13 to which roots are located.
  real(dp), parameter, public :: scan_pole_offset = 32.0_dp*epsilon(1.0_dp)

  !> One sample of a scan.
  type, public :: scan_sample_type
    !> Where, f there, and whether f could be evaluated (finite).
    real(dp) :: x = 0.0_dp, f = 0.0_dp
    logical :: ok = .false.
  end type scan_sample_type

  !> A sample and the cell it closes, as `scan_roots` shows it to `visit`.
  type, public :: scan_cell_type
    !> The previous sample (undefined for the first) and this one.
    type(scan_sample_type) :: prev, cur
    !> `scan_break%start` for the first sample; `pole` or `jump` when the cell
    !> crosses that breakpoint at `at` (a sample where f cannot be evaluated
    !> counts as a pole at the previous sample); `none` inside a piece.
    integer :: across = -1
    real(dp) :: at = 0.0_dp
    !> A root refined inside the cell, with the final bracket of `find_root`.
    logical :: root_found = .false.
    real(dp) :: root = 0.0_dp, bracket_lo = 0.0_dp, bracket_hi = 0.0_dp
    !> Roots found so far, this one included.
    integer :: roots = 0
  end type scan_cell_type

  !> Default relative tolerance in x.
  real(dp), parameter, public :: root_x_rel_default = 1.0e-13_dp
  !> The continuity probe first looks this many final bracket widths away.
  real(dp), parameter :: probe_factor = 128.0_dp
  !> At a root |f| at the final bracket must be below this share of |f| at the probes.
  real(dp), parameter :: probe_ratio = 0.25_dp

  abstract interface
    !> The next breakpoint b > a of f (a pole or jump) and its kind; leave b and
    !> kind as given (the end of the range) when there is none before it.
    pure subroutine scan_break_function(context, a, b, kind)
      import :: dp, root_context_type
      class(root_context_type), intent(inout) :: context
      real(dp), intent(in) :: a
      real(dp), intent(inout) :: b
      integer, intent(inout) :: kind
    end subroutine scan_break_function
    !> The grid step at x (> 0).
    pure function scan_step_function(context, x) result(h)
      import :: dp, root_context_type
      class(root_context_type), intent(in) :: context
      real(dp), intent(in) :: x
      real(dp) :: h
    end function scan_step_function
    !> Bookkeeping of one sample of a scan; set `halt` to end the scan.
    pure subroutine scan_visit_function(context, cell, halt)
      import :: root_context_type, scan_cell_type
      class(root_context_type), intent(inout) :: context
      type(scan_cell_type), intent(in) :: cell
      logical, intent(inout) :: halt
    end subroutine scan_visit_function
  end interface

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
      call set_status(status, demstep_stat%invalid_input, "need finite a < b", where="find_root")
      return
    end if
    if (.not. (rel >= 0.0_dp .and. abst >= 0.0_dp .and. ftol >= 0.0_dp .and. rel + abst > 0.0_dp)) then
      call set_status(status, demstep_stat%invalid_input, "tolerances must be >= 0, " &
        //"x_rel + x_abs > 0", where="find_root")
      return
    end if
    lo = a
    hi = b
    if (present(fa)) then
      flo = fa
    else
      call evaluate(f, context, lo, flo, stat)
      if (stat /= 0) then
        call set_status(status, demstep_stat%pole, "f cannot be evaluated at a", where="find_root")
        return
      end if
    end if
    if (present(fb)) then
      fhi = fb
    else
      call evaluate(f, context, hi, fhi, stat)
      if (stat /= 0) then
        call set_status(status, demstep_stat%pole, "f cannot be evaluated at b", where="find_root")
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
      call set_status(status, demstep_stat%not_found, "f(a) and f(b) have the same sign", where="find_root")
      return
    end if
    width0 = hi - lo
    call itp(f, context, lo, hi, flo, fhi, rel, abst, ftol, x, y, stat)
    if (present(bracket_lo)) bracket_lo = lo
    if (present(bracket_hi)) bracket_hi = hi
    if (stat /= 0) then
      root = x
      call set_status(status, demstep_stat%pole, "f cannot be evaluated inside the bracket", where="find_root")
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
        "the bracket closed onto a discontinuity (pole or jump), not a root", where="find_root")
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

  !> Every root of f on [lo, hi] by a scan: f is sampled on a grid and every sign
  !> change between neighbouring samples is refined by `find_root`.
  !>
  !> The range falls into smooth pieces at breakpoints that `next_break` gives
  !> (optional; default none): at a `scan_break%pole` f is sampled one-sidedly on
  !> both sides (a relative `scan_pole_offset` away, so a root next to a pole is
  !> bracketed however close it lies), and no root is sought across any
  !> breakpoint. Inside a piece the grid steps by `step(context, x)` (optional),
  !> else by max(abs_step, rel_step |x|) as given; never by less than 4 ulps.
  !> Grid points where f cannot be evaluated split the scan too.
  !>
  !> Sign changes through a discontinuity are returned in `discontinuities`. Two
  !> roots closer than the grid spacing can cancel and be missed, and a root
  !> where f touches zero without changing sign is found only on a grid point.
  !> `visit` (optional) hears of every sample with the cell it closes (the
  !> caller's own bookkeeping, such as where |f| crosses a level) and may stop
  !> the scan; `first_only` stops it at the first root.
  pure subroutine scan_roots(f, context, lo, hi, roots, discontinuities, status, rel_step, &
      abs_step, x_rel, x_abs, next_break, step, visit, first_only)
    procedure(root_function) :: f
    class(root_context_type), intent(inout) :: context
    !> The range, lo < hi.
    real(dp), intent(in) :: lo, hi
    !> Roots and discontinuities found, increasing.
    real(dp), allocatable, intent(out) :: roots(:), discontinuities(:)
    type(demstep_status_type), intent(out) :: status
    !> Grid step max(abs_step, rel_step |x|) where `step` is not given.
    real(dp), intent(in), optional :: rel_step, abs_step
    !> Tolerances in x, as for `find_root`.
    real(dp), intent(in), optional :: x_rel, x_abs
    !> The breakpoints of f (poles, jumps).
    procedure(scan_break_function), optional :: next_break
    !> The grid step at x.
    procedure(scan_step_function), optional :: step
    !> The caller's bookkeeping of every sample.
    procedure(scan_visit_function), optional :: visit
    !> Stop at the first root.
    logical, intent(in), optional :: first_only
    type(scan_cell_type) :: cell
    type(demstep_status_type) :: st
    real(dp) :: a, b, x, xb, h, rel, abst, r, r_lo, r_hi
    real(dp), allocatable :: found(:), jumps(:)
    integer :: a_kind, b_kind, n_found, n_jumps, stat
    logical :: halt, have_prev, first_in_piece, first, jump
    allocate(roots(0), discontinuities(0))
    rel = 0.0_dp
    abst = 0.0_dp
    if (present(rel_step)) rel = rel_step
    if (present(abs_step)) abst = abs_step
    first = .false.
    if (present(first_only)) first = first_only
    if (.not. (ieee_is_finite(lo) .and. ieee_is_finite(hi) .and. lo < hi)) then
      call set_status(status, demstep_stat%invalid_input, "need finite lo < hi", where="scan_roots")
      return
    end if
    if (.not. present(step) .and. .not. (rel >= 0.0_dp .and. abst >= 0.0_dp .and. &
        max(rel, abst) > 0.0_dp)) then
      call set_status(status, demstep_stat%invalid_input, "need rel_step, abs_step " &
        //">= 0, one of them > 0", where="scan_roots")
      return
    end if
    status%stat = demstep_stat%ok
    allocate(found(8), jumps(8))
    n_found = 0
    n_jumps = 0
    halt = .false.
    have_prev = .false.
    a = lo
    a_kind = scan_break%start
    do while (a < hi .and. .not. halt)
      b = hi
      b_kind = scan_break%end
      if (present(next_break)) call next_break(context, a, b, b_kind)
      if (.not. b < hi) then
        b = hi
        b_kind = scan_break%end
      end if
      x = a
      if (a_kind == scan_break%pole) x = a*(1.0_dp + scan_pole_offset)
      xb = b
      if (b_kind == scan_break%pole) xb = b*(1.0_dp - scan_pole_offset)
      first_in_piece = .true.
      do while (x <= xb)
        cell%prev = cell%cur
        call evaluate(f, context, x, cell%cur%f, stat)
        cell%cur%x = x
        cell%cur%ok = stat == 0
        cell%root_found = .false.
        if (.not. have_prev) then
          cell%across = scan_break%start
          cell%at = x
        else if (first_in_piece) then
          cell%across = a_kind
          cell%at = a
        else if (.not. (cell%prev%ok .and. cell%cur%ok)) then
          ! a sample where f cannot be evaluated splits the scan like a pole
          cell%across = scan_break%pole
          cell%at = cell%prev%x
        else
          cell%across = scan_break%none
          cell%at = x
        end if
        if (cell%cur%ok .and. cell%cur%f == 0.0_dp) then
          call append(found, n_found, x)
        else if (cell%across == scan_break%none .and. cell%prev%f /= 0.0_dp .and. &
            ((cell%prev%f > 0.0_dp) .neqv. (cell%cur%f > 0.0_dp))) then
          call find_root(f, context, cell%prev%x, x, r, st, x_rel=x_rel, x_abs=x_abs, &
            fa=cell%prev%f, fb=cell%cur%f, discontinuity=jump, bracket_lo=r_lo, bracket_hi=r_hi)
          if (st%stat == demstep_stat%ok) then
            call append(found, n_found, r)
            cell%root_found = .true.
            cell%root = r
            cell%bracket_lo = r_lo
            cell%bracket_hi = r_hi
          else if (st%stat == demstep_stat%discontinuous .or. st%stat == demstep_stat%pole) then
            call append(jumps, n_jumps, r)
          end if
        end if
        cell%roots = n_found
        if (present(visit)) call visit(context, cell, halt)
        if (first .and. n_found > 0) halt = .true.
        have_prev = .true.
        first_in_piece = .false.
        if (halt .or. x >= xb) exit
        if (present(step)) then
          h = step(context, x)
        else
          h = max(abst, rel*abs(x))
        end if
        x = min(xb, x + max(h, 4.0_dp*spacing(x)))
      end do
      a = b
      a_kind = b_kind
    end do
    roots = found(:n_found)
    discontinuities = jumps(:n_jumps)
    call sort_ascending(roots)
  end subroutine scan_roots

  !> Append to a buffer, doubling its size when full (linear cost over many calls).
  pure subroutine append(buffer, n, x)
    !> The buffer; holds `n` values.
    real(dp), allocatable, intent(inout) :: buffer(:)
    !> Values held, incremented.
    integer, intent(inout) :: n
    !> The value appended.
    real(dp), intent(in) :: x
    real(dp), allocatable :: grown(:)
    if (.not. allocated(buffer)) allocate(buffer(8))
    if (n == size(buffer)) then
      allocate(grown(max(8, 2*n)))
      grown(:n) = buffer(:n)
      call move_alloc(grown, buffer)
    end if
    n = n + 1
    buffer(n) = x
  end subroutine append

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

  !> The `scan_break` code of a word (case ignored); `-huge(0)` for another word.
  pure integer function scan_break_from_name(name) result(code)
    !> The word, one of `scan_break_names`.
    character(len=*), intent(in) :: name
    code = word_index(scan_break_names, name)
    if (code == 0) then
      code = -huge(code)
    else
      code = code + (-2)
    end if
  end function scan_break_from_name

  !> The word of a `scan_break` code (`?` for another value).
  pure function scan_break_name(code) result(name)
    !> A code of `scan_break`.
    integer, intent(in) :: code
    character(len=:), allocatable :: name
    name = word_of(scan_break_names, code - (-2))
  end function scan_break_name

end module demstep_roots
