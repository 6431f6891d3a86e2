!> Exact discrete contact errors of the central-difference scheme for a linear
!> compression-only spring, with an optional lagged viscous dashpot, as functions
!> of N = T/dt and the onset s.
!>
!> The onset s in (0, 1] is the overlap at the first force evaluation in contact,
!> as a fraction of v0 dt: the step before sits at overlap (s - 1) v0 dt (no force),
!> the first in contact at s v0 dt. s = 1: contact begins exactly at a step.
!> Units: overlaps in v0/omega, times in the exact contact time of the undamped
!> spring T/2 = pi/omega, velocities in v0.
!>
!> While in contact the scheme is the linear recurrence
!> x_{n+1} = (2 - 2 zeta h - h^2) x_n - (1 - 2 zeta h) x_{n-1}, h = omega dt,
!> whose solution through x_0 = (s - 1) h, x_1 = s h (units v0/omega) is
!> x_n = R rho^n sin(n theta + phi), rho^2 = 1 - 2 zeta h,
!> cos theta = (2 - 2 zeta h - h^2)/(2 rho). Contact ends at the first n >= 1 with
!> n theta + phi >= pi: n_c = ceil((pi - phi)/theta); the force acts at steps
!> 1 .. n_c - 1 and the rebound velocity is v_{n_c - 1} = (x_{n_c} - x_{n_c - 1})/h.
!> A centred dashpot (the average of the half-step velocities) gives the same
!> form with x_{n+1} = ((2 - h^2) x_n - (1 - a) x_{n-1})/(1 + a), a = zeta h,
!> rho^2 = (1 - a)/(1 + a).
!> These closed forms are used whenever the roots are complex (every stable
!> undamped step; damped steps with 2 zeta h < 1 below the limit); otherwise
!> (beyond the limit, or an overdamped discrete contact) the recurrence is
!> stepped exactly.
module demstep_contact
  use demstep_kinds, only: dp, i8, pi
  use demstep_status, only: demstep_status_type, demstep_stat, set_status
  use demstep_spring, only: saturated_count, ceiling_real, dashpot_kind
  use demstep_text, only: real_text
  use, intrinsic :: ieee_arithmetic, only: ieee_is_finite
  implicit none
  private

  public :: contact_with_onset, contact_worst_case, exact_contact, contact_error_of, &
    period_error, check_contact_damping

  !> The quantities whose error can be asked for, by name: `quantity_kind%restitution`.
  type, public :: quantity_kinds
    !> Rebound over impact speed.
    integer :: restitution = 1
    !> Duration of the contact.
    integer :: contact_time = 2
    !> Largest overlap.
    integer :: overlap = 3
    !> Period of the undamped oscillation.
    integer :: period = 4
  end type quantity_kinds
  !> The quantities by name.
  type(quantity_kinds), parameter, public :: quantity_kind = quantity_kinds()
  !> How many quantities there are (their codes are 1 .. n_quantities).
  integer, parameter, public :: n_quantities = 4
  character(len=*), parameter, public :: quantity_names(n_quantities) = [character(len=12) :: &
    "restitution", "contact_time", "overlap", "period"]

  !> Onsets sampled for a worst case; the best is then refined by golden section.
  integer, parameter, public :: worst_case_samples = 256
  !> Steps a contact may take when stepped (beyond the closed forms).
  integer(i8), parameter :: max_contact_steps = 100000000_i8

  !> One discrete contact.
  type, public :: onset_contact_type
    !> Onset s in (0, 1].
    real(dp) :: onset = 1.0_dp
    !> Force evaluations with a positive overlap (saturates at huge(1_i8)).
    integer(i8) :: steps = 0_i8
    !> True when `steps` saturated: the count is above huge(1_i8) = 2^63 - 1.
    logical :: steps_saturated = .false.
    !> Force evaluations times dt, in units of T/2.
    real(dp) :: contact_time = 0.0_dp
    !> -v_out/v0.
    real(dp) :: restitution = 0.0_dp
    !> Largest overlap at a force evaluation, in units of v0/omega.
    real(dp) :: max_overlap = 0.0_dp
    !> dt below the scheme's stability limit.
    logical :: stable = .true.
  end type onset_contact_type

contains

  !> The discrete contact at N steps per period and onset s, with damping ratio
  !> zeta (default 0) of a lagged dashpot (default) or a centred one (`dashpot =
  !> dashpot_kind%centred`). Status invalid_input for N outside
  !> [2 pi (1 + zeta)/1e50, huge], s outside (0, 1], zeta < 0 (messages name
  !> `n_per_period`, `onset`, `damping_ratio`); not_converged when the discrete
  !> contact never ends (an overdamped step: the overlap decays without crossing
  !> zero) or a stepped contact exceeds 1e8 steps. N <= pi (or beyond the damped
  !> limit) is computed by stepping and flagged `stable = .false.`.
  pure subroutine contact_with_onset(n_per_period, onset, contact, status, damping_ratio, dashpot)
    !> N = T/dt and the onset s.
    real(dp), intent(in) :: n_per_period, onset
    type(onset_contact_type), intent(out) :: contact
    type(demstep_status_type), intent(out) :: status
    !> zeta >= 0 (default 0).
    real(dp), intent(in), optional :: damping_ratio
    !> `dashpot_kind%lagged` (default) or `dashpot_kind%centred`.
    integer, intent(in), optional :: dashpot
    real(dp) :: h, zeta, rho, theta, a, b, r, phi, q, x, xm, best, nc, f, k, lo, hi, log_rho, n_min, d
    logical :: closed, centred
    zeta = 0.0_dp
    if (present(damping_ratio)) zeta = damping_ratio
    centred = .false.
    if (present(dashpot)) then
      if (dashpot /= dashpot_kind%lagged .and. dashpot /= dashpot_kind%centred) then
        call set_status(status, demstep_stat%invalid_input, "dashpot: must be lagged or centred")
        return
      end if
      centred = dashpot == dashpot_kind%centred
    end if
    if (.not. (ieee_is_finite(zeta) .and. zeta >= 0.0_dp)) then
      call set_status(status, demstep_stat%invalid_input, "damping_ratio: must be finite and >= 0")
      return
    end if
    ! beyond the limit the contact is stepped: (1 + zeta) h <= 1e50 keeps it in range
    n_min = 2.0_dp*pi*(1.0_dp + zeta)/1.0e50_dp
    if (.not. (ieee_is_finite(n_per_period) .and. n_per_period >= n_min)) then
      call set_status(status, demstep_stat%invalid_input, "n_per_period: must be finite and >= " &
        //real_text(n_min*1.001_dp)//" (2 pi (1 + damping_ratio)/1e50)")
      return
    end if
    if (.not. (onset > 0.0_dp .and. onset <= 1.0_dp)) then
      call set_status(status, demstep_stat%invalid_input, "onset: must be in (0, 1]")
      return
    end if
    status%stat = demstep_stat%ok
    contact%onset = onset
    h = 2.0_dp*pi/n_per_period
    ! the stability limit: lagged h < 2 (sqrt(1 + zeta^2) - zeta), centred h < 2
    if (centred) then
      contact%stable = h < 2.0_dp
    else
      contact%stable = h < 2.0_dp/(sqrt(1.0_dp + zeta**2) + zeta)
    end if
    a = (onset - 1.0_dp)*h
    b = onset*h
    call discrete_phase(h, zeta, centred, rho, theta, closed)
    if (.not. closed) then
      call step_contact(h, zeta, centred, onset, contact, status)
      return
    end if
    ! x_0 = R sin(phi) = a, x_1 = R rho sin(theta + phi) = b
    phi = atan2(a, (b/rho - a*cos(theta))/sin(theta))
    r = hypot(a, (b/rho - a*cos(theta))/sin(theta))
    ! in reals: q reaches 1e308 for the finest steps
    q = (pi - phi)/theta
    nc = ceiling_real(q)
    call saturated_count(nc - 1.0_dp, contact%steps, contact%steps_saturated)
    contact%contact_time = (nc - 1.0_dp)*(h/pi)
    ! rho^n as exp(n log rho), log rho = log(rho^2)/2 without cancellation;
    ! d = 1 - rho cos(theta) exactly: zeta h + h^2/2, over 1 + zeta h when centred
    if (centred) then
      log_rho = 0.5_dp*(log1p(-zeta*h) - log1p(zeta*h))
      d = (zeta*h + 0.5_dp*h**2)/(1.0_dp + zeta*h)
    else
      log_rho = 0.5_dp*log1p(-2.0_dp*zeta*h)
      d = zeta*h + 0.5_dp*h**2
    end if
    ! v_n = (x_{n+1} - x_n)/h = R rho^n (rho sin(theta) cos(A) - d sin(A))/h,
    ! A = n theta + phi; at n = nc - 1, A = pi - (1 - f) theta with f = nc - q in [0, 1)
    f = nc - q
    contact%restitution = r*exp((nc - 1.0_dp)*log_rho)*(rho*sin(theta)*cos((1.0_dp - f)*theta) &
      + d*sin((1.0_dp - f)*theta))/h
    ! the largest overlap: the continuous peak of rho^t sin(t theta + phi) is at
    ! t theta + phi = atan2(theta, -log rho); check the steps on either side
    best = (atan2(theta, -log_rho) - phi)/theta
    lo = min(max(1.0_dp, aint(best)), max(1.0_dp, nc - 1.0_dp))
    hi = min(nc - 1.0_dp, lo + 1.0_dp)
    xm = 0.0_dp
    k = lo
    do
      if (k > hi) exit
      x = r*exp(k*log_rho)*sin(k*theta + phi)
      xm = max(xm, x)
      k = k + 1.0_dp
      ! beyond 2^53 k + 1 rounds to k: the two steps are one
      if (k == lo) exit
    end do
    contact%max_overlap = xm
  end subroutine contact_with_onset

  !> The roots rho e^(+-i theta) of the contact recurrence at h = omega dt,
  !> x_{n+1} = beta x_n - rho^2 x_{n-1}. With f = 1 - (zeta + h/2)^2 (lagged) or
  !> 1 - zeta^2 - h^2/4 (centred), the discriminant is beta^2/4 - rho^2 = -h^2 f
  !> (over (1 + zeta h)^2 when centred), so the roots are complex when f > 0 and
  !> sin^2(theta/2) = (2 rho - beta)/(4 rho) = h^2 f/(rho (2 rho + beta)) (over
  !> (1 + zeta h)^2 when centred): no cancellation near critical damping, and
  !> 2 asin(h/2) undamped. `closed` is false beyond the stability limit or where
  !> the roots are real: step there instead.
  elemental subroutine discrete_phase(h, zeta, centred, rho, theta, closed)
    real(dp), intent(in) :: h, zeta
    logical, intent(in) :: centred
    real(dp), intent(out) :: rho, theta
    logical, intent(out) :: closed
    real(dp) :: f, beta, sin_half, a
    rho = 0.0_dp
    theta = 0.0_dp
    a = zeta*h
    if (centred) then
      closed = a < 1.0_dp .and. h < 2.0_dp
      if (.not. closed) return
      rho = sqrt((1.0_dp - a)/(1.0_dp + a))
      beta = (2.0_dp - h**2)/(1.0_dp + a)
    else
      closed = a < 0.5_dp .and. h < 2.0_dp/(sqrt(1.0_dp + zeta**2) + zeta)
      if (.not. closed) return
      rho = sqrt(1.0_dp - 2.0_dp*a)
      beta = 2.0_dp - 2.0_dp*a - h**2
    end if
    f = root_factor(h, zeta, centred)
    closed = f > 0.0_dp
    if (.not. closed) return
    ! sin(theta/2) itself: its square underflows for the finest steps
    sin_half = h*sqrt(f)/sqrt(rho*(2.0_dp*rho + beta))
    if (centred) sin_half = sin_half/(1.0_dp + a)
    closed = sin_half < 1.0_dp
    if (closed) theta = 2.0_dp*asin(sin_half)
  end subroutine discrete_phase

  !> f of `discrete_phase`: > 0 for complex roots; 1 - zeta is exact for zeta
  !> in [1/2, 2], so f keeps its digits next to critical damping.
  elemental real(dp) function root_factor(h, zeta, centred) result(f)
    real(dp), intent(in) :: h, zeta
    logical, intent(in) :: centred
    if (centred) then
      f = (1.0_dp - zeta)*(1.0_dp + zeta) - 0.25_dp*h**2
    else
      f = ((1.0_dp - zeta) - 0.5_dp*h)*((1.0_dp + zeta) + 0.5_dp*h)
    end if
  end function root_factor

  !> The contact by exact stepping of the recurrence (beyond the closed forms).
  !> With real roots r1 > 0 (dominant) and r2 of r^2 - beta r + gamma,
  !> x_n = A r1^n + B r2^n: if r2 >= 0 too, x(t) has at most one zero, already
  !> passed between steps 0 and 1, so the overlap stays positive for ever; if
  !> r2 < 0 and A > 0, |B r2^n|/(A r1^n) decreases, so a contact that survives
  !> steps 2 and 3 (both signs of r2^n) never ends. Either: status not_converged.
  pure subroutine step_contact(h, zeta, centred, onset, contact, status)
    real(dp), intent(in) :: h, zeta, onset
    logical, intent(in) :: centred
    type(onset_contact_type), intent(inout) :: contact
    type(demstep_status_type), intent(inout) :: status
    real(dp) :: x, v, xm, beta, gam, disc, r1, r2, x0, ca
    logical :: watch
    x0 = (onset - 1.0_dp)*h
    x = x0
    v = 1.0_dp
    xm = 0.0_dp
    if (centred) then
      beta = (2.0_dp - h**2)/(1.0_dp + zeta*h)
      gam = (1.0_dp - zeta*h)/(1.0_dp + zeta*h)
    else
      beta = 2.0_dp - 2.0_dp*zeta*h - h**2
      gam = 1.0_dp - 2.0_dp*zeta*h
    end if
    ! beta^2/4 - gamma = -h^2 f (see discrete_phase), its sign kept next to critical damping
    disc = -h**2*root_factor(h, zeta, centred)
    if (centred) disc = disc/(1.0_dp + zeta*h)**2
    watch = .false.
    if (disc >= 0.0_dp .and. beta > 0.0_dp) then
      if (gam >= 0.0_dp) then
        call set_status(status, demstep_stat%not_converged, never_ends(h, zeta))
        return
      end if
      r1 = 0.5_dp*beta + sqrt(disc)
      r2 = gam/r1
      ca = (onset*h - r2*x0)/(r1 - r2)
      watch = ca > 0.0_dp .and. r1 > abs(r2)
    end if
    do
      x = x + v*h
      if (.not. x > 0.0_dp) exit
      if (centred) then
        v = ((1.0_dp - zeta*h)*v - h*x)/(1.0_dp + zeta*h)
      else
        v = v - h*(x + 2.0_dp*zeta*v)
      end if
      contact%steps = contact%steps + 1_i8
      xm = max(xm, x)
      if (watch .and. contact%steps >= 3_i8) then
        call set_status(status, demstep_stat%not_converged, never_ends(h, zeta))
        return
      end if
      if (contact%steps > max_contact_steps .or. .not. ieee_is_finite(v)) then
        call set_status(status, demstep_stat%not_converged, "n_per_period: the stepped contact " &
          //"did not end within 1e8 steps")
        return
      end if
    end do
    contact%contact_time = real(contact%steps, dp)*h/pi
    contact%restitution = -v
    contact%max_overlap = xm
  end subroutine step_contact

  pure function never_ends(h, zeta) result(message)
    real(dp), intent(in) :: h, zeta
    character(len=:), allocatable :: message
    message = "n_per_period: at N = "//real_text(2.0_dp*pi/h)//" with damping_ratio " &
      //real_text(zeta)//" the discrete contact never ends (an overdamped step: the overlap " &
      //"decays without crossing zero)"
  end function never_ends

  !> log(1 + x) accurate for small |x| (x > -1).
  elemental real(dp) function log1p(x)
    real(dp), intent(in) :: x
    real(dp) :: u
    u = 1.0_dp + x
    if (u == 1.0_dp) then
      log1p = x
    else
      ! the rounding of 1 + x cancels in the ratio
      log1p = log(u)*(x/(u - 1.0_dp))
    end if
  end function log1p

  !> Status invalid_input unless 0 <= zeta < 1: the worst-case contact errors are
  !> relative to the continuous contact, which for zeta >= 1 does not rebound (its
  !> restitution is 0) and, overdamped, approaches zero overlap without reaching it.
  pure subroutine check_contact_damping(damping_ratio, status)
    !> zeta.
    real(dp), intent(in) :: damping_ratio
    type(demstep_status_type), intent(out) :: status
    if (.not. (ieee_is_finite(damping_ratio) .and. damping_ratio >= 0.0_dp .and. &
        damping_ratio < 1.0_dp)) then
      call set_status(status, demstep_stat%invalid_input, "damping_ratio: must be in [0, 1) for " &
        //"contact errors (an overdamped contact, damping_ratio >= 1, does not rebound), got " &
        //real_text(damping_ratio))
    else
      status%stat = demstep_stat%ok
    end if
  end subroutine check_contact_damping

  !> The continuous (exact) contact of the linear spring-dashpot, in the same
  !> units: restitution exp(-zeta pi/sqrt(1 - zeta^2)), contact time
  !> 1/sqrt(1 - zeta^2), largest overlap exp(-zeta t*) sin(w t*)/w at
  !> tan(w t*) = w/zeta, w = sqrt(1 - zeta^2). For zeta >= 1 (no rebound) the
  !> restitution and time are 0.
  elemental function exact_contact(damping_ratio) result(contact)
    real(dp), intent(in) :: damping_ratio
    type(onset_contact_type) :: contact
    real(dp) :: w, t
    contact%onset = 1.0_dp
    if (damping_ratio >= 1.0_dp) then
      contact%restitution = 0.0_dp
      contact%contact_time = 0.0_dp
      contact%max_overlap = 0.0_dp
      return
    end if
    w = sqrt(1.0_dp - damping_ratio**2)
    contact%restitution = exp(-damping_ratio*pi/w)
    contact%contact_time = 1.0_dp/w
    t = atan2(w, damping_ratio)/w
    contact%max_overlap = exp(-damping_ratio*t)*sin(w*t)/w
  end function exact_contact

  !> Relative error of one quantity of a discrete contact against the exact one.
  elemental real(dp) function contact_error_of(quantity, contact, exact) result(err)
    integer, intent(in) :: quantity
    type(onset_contact_type), intent(in) :: contact, exact
    select case (quantity)
    case (quantity_kind%restitution)
      err = abs(contact%restitution - exact%restitution)/max(exact%restitution, tiny(1.0_dp))
    case (quantity_kind%contact_time)
      err = abs(contact%contact_time - exact%contact_time)/max(exact%contact_time, tiny(1.0_dp))
    case (quantity_kind%overlap)
      err = abs(contact%max_overlap - exact%max_overlap)/max(exact%max_overlap, tiny(1.0_dp))
    case default
      err = 0.0_dp
    end select
  end function contact_error_of

  !> Relative period error of the undamped scheme, 1 - omega dt/theta (> 0:
  !> the numerical period is shorter); huge beyond the stability limit.
  elemental real(dp) function period_error(n_per_period) result(err)
    real(dp), intent(in) :: n_per_period
    real(dp) :: h
    real(dp) :: x, u
    h = 2.0_dp*pi/n_per_period
    x = 0.5_dp*h
    if (h >= 2.0_dp) then
      err = huge(1.0_dp)
    else if (x < 1.0e-3_dp) then
      ! asin(x)/x - 1 by its series (next term 35 x^8/1152 < 3e-26), no cancellation
      u = x**2*(1.0_dp/6.0_dp + x**2*(3.0_dp/40.0_dp + x**2*(5.0_dp/112.0_dp)))
      err = u/(1.0_dp + u)
    else
      err = 1.0_dp - h/(2.0_dp*asin(x))
    end if
  end function period_error

  !> The onset in (0, 1] at which a quantity's error is largest, and the contact
  !> there: 256 evenly spaced onsets, the best refined by 40 golden-section steps
  !> in its neighbourhood (the error is piecewise smooth in s, with jumps where
  !> the number of steps in contact changes).
  pure subroutine contact_worst_case(n_per_period, quantity, worst, error, status, damping_ratio)
    real(dp), intent(in) :: n_per_period
    integer, intent(in) :: quantity
    type(onset_contact_type), intent(out) :: worst
    real(dp), intent(out) :: error
    type(demstep_status_type), intent(out) :: status
    real(dp), intent(in), optional :: damping_ratio
    type(onset_contact_type) :: c, c1, c2, exact
    real(dp) :: zeta, s, e, a, b, x1, x2, e1, e2
    integer :: k, kbest, it
    real(dp), parameter :: golden = 0.6180339887498949_dp
    zeta = 0.0_dp
    if (present(damping_ratio)) zeta = damping_ratio
    error = -1.0_dp
    call check_contact_damping(zeta, status)
    if (status%stat /= demstep_stat%ok) return
    exact = exact_contact(zeta)
    if (quantity == quantity_kind%contact_time) then
      call worst_contact_time(n_per_period, zeta, exact, worst, error, status)
      if (status%stat == demstep_stat%ok) return
    end if
    kbest = worst_case_samples
    do k = 1, worst_case_samples
      s = real(k, dp)/real(worst_case_samples, dp)
      call contact_with_onset(n_per_period, s, c, status, zeta)
      if (status%stat /= demstep_stat%ok) return
      e = contact_error_of(quantity, c, exact)
      if (e > error) then
        error = e
        worst = c
        kbest = k
      end if
    end do
    ! golden-section search on the neighbourhood of the best sample
    a = real(kbest - 1, dp)/real(worst_case_samples, dp)
    b = min(1.0_dp, real(kbest + 1, dp)/real(worst_case_samples, dp))
    x1 = b - golden*(b - a)
    x2 = a + golden*(b - a)
    call onset_error(n_per_period, quantity, zeta, exact, x1, c1, e1)
    call onset_error(n_per_period, quantity, zeta, exact, x2, c2, e2)
    do it = 1, 40
      if (e1 > error) then
        error = e1
        worst = c1
      end if
      if (e2 > error) then
        error = e2
        worst = c2
      end if
      if (e1 > e2) then
        b = x2
        x2 = x1
        e2 = e1
        c2 = c1
        x1 = b - golden*(b - a)
        call onset_error(n_per_period, quantity, zeta, exact, x1, c1, e1)
      else
        a = x1
        x1 = x2
        e1 = e2
        c1 = c2
        x2 = a + golden*(b - a)
        call onset_error(n_per_period, quantity, zeta, exact, x2, c2, e2)
      end if
    end do
    status%stat = demstep_stat%ok
  end subroutine contact_worst_case

  !> The contact time's worst case in closed form: as s sweeps (0, 1], (pi - phi)/theta
  !> sweeps [pi/theta, pi/theta + 1), so the contact lasts ceil(pi/theta) - 1 or
  !> ceil(pi/theta) steps (the latter as s -> 0+ when pi/theta is not an integer).
  !> Status not_converged outside the closed forms' range (the caller samples).
  pure subroutine worst_contact_time(n_per_period, zeta, exact, worst, error, status)
    real(dp), intent(in) :: n_per_period, zeta
    type(onset_contact_type), intent(in) :: exact
    type(onset_contact_type), intent(out) :: worst
    real(dp), intent(out) :: error
    type(demstep_status_type), intent(out) :: status
    real(dp) :: h, rho, theta, q, e1, e2, m
    logical :: closed
    h = 2.0_dp*pi/n_per_period
    error = -1.0_dp
    call set_status(status, demstep_stat%not_converged, "outside the closed forms")
    call discrete_phase(h, zeta, .false., rho, theta, closed)
    if (.not. closed) return
    q = pi/theta
    m = ceiling_real(q)
    e1 = abs((m - 1.0_dp)*(h/pi) - exact%contact_time)/exact%contact_time
    e2 = abs(m*(h/pi) - exact%contact_time)/exact%contact_time
    if (m == q) e2 = -1.0_dp
    worst%stable = .true.
    if (e1 >= e2) then
      call contact_with_onset(n_per_period, 1.0_dp, worst, status, zeta)
      error = e1
    else
      ! approached as the onset tends to 0
      call contact_with_onset(n_per_period, 1.0_dp/real(worst_case_samples, dp)**2, worst, status, zeta)
      call saturated_count(m, worst%steps, worst%steps_saturated)
      worst%contact_time = m*(h/pi)
      error = e2
    end if
  end subroutine worst_contact_time

  !> A quantity's error at one onset (-1 where the contact cannot be computed).
  pure subroutine onset_error(n_per_period, quantity, zeta, exact, onset, contact, error)
    real(dp), intent(in) :: n_per_period, zeta, onset
    integer, intent(in) :: quantity
    type(onset_contact_type), intent(in) :: exact
    type(onset_contact_type), intent(out) :: contact
    real(dp), intent(out) :: error
    type(demstep_status_type) :: st
    error = -1.0_dp
    if (.not. (onset > 0.0_dp .and. onset <= 1.0_dp)) return
    call contact_with_onset(n_per_period, onset, contact, st, zeta)
    if (st%stat == demstep_stat%ok) error = contact_error_of(quantity, contact, exact)
  end subroutine onset_error

end module demstep_contact
