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
!> stepped exactly, by the spring's own stepper `spring_step`.
!>
!> Undamped, with onset 1 (contact beginning exactly at a step), the closed form
!> is the simplest: with theta = 2 asin(h/2) and n_c = ceil(pi/theta), the force
!> acts at steps 1 .. n_c - 1 and the rebound velocity is
!> v0 cos((n_c - 1/2) theta)/cos(theta/2), so the restitution lies in
!> [1, 1/cos(theta/2)].
!>
!> One result type, `discrete_contact_type`, serves every entry point:
!> `contact_with_onset` (any N, onset, damping), `spring_contact` (a spring and
!> its step, onset 1), `simulate_contact` (a spring stepped), `exact_contact`
!> (the continuous contact).
module demstep_contact
  use demstep_kinds, only: dp, i8, pi
  use demstep_status, only: demstep_status_type, demstep_stat, set_status
  use demstep_spring, only: saturated_count, ceiling_real, dashpot_kind, spring_type, &
    spring_state_type, spring_step, spring_omega, spring_damping_ratio, critical_time_step, &
    check_time_step, damped_limit, scheme_phase, phase_factor
  use demstep_text, only: real_text, int_text
  use, intrinsic :: ieee_arithmetic, only: ieee_is_finite
  use demstep_words, only: word_index, word_of
  implicit none
  private

  public :: contact_with_onset, spring_contact, simulate_contact, contact_worst_case, &
    exact_contact, contact_error_of, period_error, check_contact_damping

  !> The quantities whose error can be asked for, by name: `quantity_kind%restitution`.
  type, public :: quantity_kind_enum
    !> Rebound over impact speed.
    integer :: restitution = 1
    !> Duration of the contact.
    integer :: contact_time = 2
    !> Largest overlap.
    integer :: overlap = 3
    !> Period of the undamped oscillation.
    integer :: period = 4
  end type quantity_kind_enum
  !> The quantities by name.
  type(quantity_kind_enum), parameter, public :: quantity_kind = quantity_kind_enum()
  public :: quantity_kind_from_name, quantity_kind_name
  !> How many quantities there are (their codes are 1 .. n_quantities).
  integer, parameter, public :: n_quantities = 4
  character(len=*), parameter, public :: quantity_kind_names(n_quantities) = [character(len=12) :: &
    "restitution", "contact_time", "overlap", "period"]

  !> Onsets sampled for a worst case; the best is then refined by golden section.
  integer, parameter, public :: worst_case_samples = 256
  !> Steps a contact may take when stepped (beyond the closed forms).
  integer(i8), parameter :: max_contact_steps = 100000000_i8

  !> One contact of a mass arriving at speed v0: overlaps in v0/omega, times in
  !> the undamped contact time T/2 = pi/omega, velocities in v0.
  type, public :: discrete_contact_type
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
  end type discrete_contact_type

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
    type(discrete_contact_type), intent(out) :: contact
    type(demstep_status_type), intent(out) :: status
    !> zeta >= 0 (default 0).
    real(dp), intent(in), optional :: damping_ratio
    !> `dashpot_kind%lagged` (default) or `dashpot_kind%centred`.
    integer, intent(in), optional :: dashpot
    real(dp) :: zeta, n_min
    logical :: centred
    zeta = 0.0_dp
    if (present(damping_ratio)) zeta = damping_ratio
    centred = .false.
    if (present(dashpot)) then
      if (dashpot /= dashpot_kind%lagged .and. dashpot /= dashpot_kind%centred) then
        call set_status(status, demstep_stat%invalid_input, "must be lagged or centred", where="dashpot")
        return
      end if
      centred = dashpot == dashpot_kind%centred
    end if
    if (.not. (ieee_is_finite(zeta) .and. zeta >= 0.0_dp)) then
      call set_status(status, demstep_stat%invalid_input, "must be finite and >= 0", where="damping_ratio")
      return
    end if
    ! beyond the limit the contact is stepped: (1 + zeta) h <= 1e50 keeps it in range
    n_min = 2.0_dp*pi*(1.0_dp + zeta)/1.0e50_dp
    if (.not. (ieee_is_finite(n_per_period) .and. n_per_period >= n_min)) then
      call set_status(status, demstep_stat%invalid_input, "must be finite and >= " &
        //real_text(n_min*1.001_dp)//" (2 pi (1 + damping_ratio)/1e50)", where="n_per_period")
      return
    end if
    if (.not. (onset > 0.0_dp .and. onset <= 1.0_dp)) then
      call set_status(status, demstep_stat%invalid_input, "must be in (0, 1]", where="onset")
      return
    end if
    call contact_kernel(2.0_dp*pi/n_per_period, onset, zeta, centred, contact, status)
  end subroutine contact_with_onset

  !> The contact of a spring at its step dt, beginning exactly at a step (onset 1),
  !> either dashpot: `contact_with_onset` at N = T/dt, with h = omega dt formed from
  !> the spring. Status invalid_input for a dt `check_time_step` refuses (the
  !> message names `dt`); not_converged as `contact_with_onset`.
  pure subroutine spring_contact(spring, dt, contact, status)
    !> The spring (from new_spring).
    type(spring_type), intent(in) :: spring
    !> Time step.
    real(dp), intent(in) :: dt
    type(discrete_contact_type), intent(out) :: contact
    type(demstep_status_type), intent(out) :: status
    call check_time_step(spring, dt, status)
    if (status%stat /= demstep_stat%ok) return
    call contact_kernel(spring_omega(spring)*dt, 1.0_dp, spring_damping_ratio(spring), &
      spring%dashpot == dashpot_kind%centred, contact, status)
  end subroutine spring_contact

  !> The contact of a spring at its step dt by stepping (`spring_step`): the mass
  !> arrives at speed v0 with zero overlap at step 0 and is stepped until the
  !> overlap is no longer positive. Units as in `discrete_contact_type`.
  !> Status `unstable` at or beyond the stability limit, `not_converged` past
  !> `max_steps` or when the contact never ends.
  pure subroutine simulate_contact(spring, dt, contact, status, max_steps)
    !> The spring (from new_spring).
    type(spring_type), intent(in) :: spring
    !> Time step, finite and > 0.
    real(dp), intent(in) :: dt
    type(discrete_contact_type), intent(out) :: contact
    type(demstep_status_type), intent(out) :: status
    !> Give up after this many steps (default 10**8).
    integer(i8), intent(in), optional :: max_steps
    integer(i8) :: limit
    limit = max_contact_steps
    if (present(max_steps)) limit = max_steps
    if (.not. (ieee_is_finite(dt) .and. dt > 0.0_dp)) then
      call set_status(status, demstep_stat%invalid_input, "dt must be finite and > 0")
      return
    end if
    if (dt >= critical_time_step(spring)) then
      call set_status(status, demstep_stat%unstable, "dt is at or beyond the stability limit")
      return
    end if
    status%stat = demstep_stat%ok
    contact%onset = 1.0_dp
    call step_contact(spring_omega(spring)*dt, spring_damping_ratio(spring), &
      spring%dashpot == dashpot_kind%centred, 1.0_dp, limit, contact, status)
  end subroutine simulate_contact

  !> The contact at h = omega dt and onset s (both checked by the caller): the
  !> undamped onset-1 closed form, the general closed form where the roots are
  !> complex, else exact stepping.
  pure subroutine contact_kernel(h, onset, zeta, centred, contact, status)
    real(dp), intent(in) :: h, onset, zeta
    logical, intent(in) :: centred
    type(discrete_contact_type), intent(out) :: contact
    type(demstep_status_type), intent(out) :: status
    real(dp) :: rho, theta, a, b, r, phi, q, x, xm, best, nc, f, k, lo, hi, log_rho, d
    logical :: closed
    status%stat = demstep_stat%ok
    contact%onset = onset
    ! the stability limit: lagged h < 2 (sqrt(1 + zeta^2) - zeta), centred h < 2
    if (centred) then
      contact%stable = h < 2.0_dp
    else
      contact%stable = h < damped_limit(2.0_dp, zeta)
    end if
    if (zeta == 0.0_dp .and. onset == 1.0_dp .and. h < 2.0_dp) then
      call undamped_at_step(h, contact)
      return
    end if
    a = (onset - 1.0_dp)*h
    b = onset*h
    call scheme_phase(h, zeta, centred, rho, theta, closed)
    if (.not. closed) then
      call step_contact(h, zeta, centred, onset, max_contact_steps, contact, status)
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
  end subroutine contact_kernel

  !> The undamped contact beginning at a step (onset 1) in closed form, h < 2.
  pure subroutine undamped_at_step(h, contact)
    real(dp), intent(in) :: h
    type(discrete_contact_type), intent(inout) :: contact
    real(dp) :: rho, theta, q, nc, f, half, d, k
    logical :: closed
    call scheme_phase(h, 0.0_dp, .false., rho, theta, closed)
    ! in reals: pi/theta reaches 1e308 for the finest steps
    q = pi/theta
    nc = ceiling_real(q)
    call saturated_count(nc - 1.0_dp, contact%steps, contact%steps_saturated)
    ! (nc - 1/2) theta = pi + (f - 1/2) theta with f = nc - q in [0, 1)
    f = nc - q
    contact%restitution = cos((f - 0.5_dp)*theta)/cos(0.5_dp*theta)
    ! the overlap h sin(k theta)/sin(theta) = sin(k theta)/cos(theta/2) peaks at the
    ! step k in [1, nc - 1] nearest to q/2, where sin(k theta) = cos((q/2 - k) theta)
    half = 0.5_dp*q
    k = min(max(1.0_dp, anint(half)), max(1.0_dp, nc - 1.0_dp))
    d = half - k
    contact%max_overlap = cos(d*theta)/cos(0.5_dp*theta)
    if (nc < 2.0_dp) contact%max_overlap = 0.0_dp
    contact%contact_time = (nc - 1.0_dp)*(h/pi)
  end subroutine undamped_at_step

  !> The contact by exact stepping of the recurrence (beyond the closed forms).
  !> With real roots r1 > 0 (dominant) and r2 of r^2 - beta r + gamma,
  !> x_n = A r1^n + B r2^n: if r2 >= 0 too, x(t) has at most one zero, already
  !> passed between steps 0 and 1, so the overlap stays positive for ever; if
  !> r2 < 0 and A > 0, |B r2^n|/(A r1^n) decreases, so a contact that survives
  !> steps 2 and 3 (both signs of r2^n) never ends. Either: status not_converged.
  pure subroutine step_contact(h, zeta, centred, onset, limit, contact, status)
    real(dp), intent(in) :: h, zeta, onset
    logical, intent(in) :: centred
    !> Give up after this many steps in contact.
    integer(i8), intent(in) :: limit
    type(discrete_contact_type), intent(inout) :: contact
    type(demstep_status_type), intent(inout) :: status
    type(spring_type) :: unit
    type(spring_state_type) :: state
    real(dp) :: xm, beta, gam, disc, r1, r2, x0, ca
    logical :: watch
    x0 = (onset - 1.0_dp)*h
    xm = 0.0_dp
    if (centred) then
      beta = (2.0_dp - h**2)/(1.0_dp + zeta*h)
      gam = (1.0_dp - zeta*h)/(1.0_dp + zeta*h)
    else
      beta = 2.0_dp - 2.0_dp*zeta*h - h**2
      gam = 1.0_dp - 2.0_dp*zeta*h
    end if
    ! beta^2/4 - gamma = -h^2 f (see scheme_phase), its sign kept next to critical damping
    disc = -h**2*phase_factor(h, zeta, centred)
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
    ! the spring's own stepper in these units: M = K = 1 (omega = 1), dt = h,
    ! c = 2 zeta (exact), overlap in v0/omega and velocity in v0
    unit = spring_type(mass=1.0_dp, stiffness=1.0_dp, damping=2.0_dp*zeta, &
      compression_only=.true., dashpot=merge(dashpot_kind%centred, dashpot_kind%lagged, centred))
    state = spring_state_type(x=x0, v=1.0_dp, step=0_i8)
    do
      call spring_step(unit, h, state)
      if (.not. state%x > 0.0_dp) exit
      contact%steps = contact%steps + 1_i8
      xm = max(xm, state%x)
      if (watch .and. contact%steps >= 3_i8) then
        call set_status(status, demstep_stat%not_converged, never_ends(h, zeta))
        return
      end if
      if (contact%steps > limit .or. .not. ieee_is_finite(state%v)) then
        call set_status(status, demstep_stat%not_converged, "the stepped contact " &
          //"did not end within "//int_text(limit)//" steps", where="n_per_period")
        return
      end if
    end do
    contact%contact_time = real(contact%steps, dp)*h/pi
    contact%restitution = -state%v
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
      call set_status(status, demstep_stat%invalid_input, "must be in [0, 1) for " &
        //"contact errors (an overdamped contact, damping_ratio >= 1, does not rebound), got " &
        //real_text(damping_ratio), where="damping_ratio")
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
    type(discrete_contact_type) :: contact
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
    type(discrete_contact_type), intent(in) :: contact, exact
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
    type(discrete_contact_type), intent(out) :: worst
    real(dp), intent(out) :: error
    type(demstep_status_type), intent(out) :: status
    real(dp), intent(in), optional :: damping_ratio
    type(discrete_contact_type) :: c, c1, c2, exact
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
    type(discrete_contact_type), intent(in) :: exact
    type(discrete_contact_type), intent(out) :: worst
    real(dp), intent(out) :: error
    type(demstep_status_type), intent(out) :: status
    real(dp) :: h, rho, theta, q, e1, e2, m
    logical :: closed
    h = 2.0_dp*pi/n_per_period
    error = -1.0_dp
    call set_status(status, demstep_stat%not_converged, "outside the closed forms")
    call scheme_phase(h, zeta, .false., rho, theta, closed)
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
    type(discrete_contact_type), intent(in) :: exact
    type(discrete_contact_type), intent(out) :: contact
    real(dp), intent(out) :: error
    type(demstep_status_type) :: st
    error = -1.0_dp
    if (.not. (onset > 0.0_dp .and. onset <= 1.0_dp)) return
    call contact_with_onset(n_per_period, onset, contact, st, zeta)
    if (st%stat == demstep_stat%ok) error = contact_error_of(quantity, contact, exact)
  end subroutine onset_error

  !> The `quantity_kind` code of a word (case ignored); 0 for another word.
  pure integer function quantity_kind_from_name(name) result(code)
    !> The word, one of `quantity_kind_names`.
    character(len=*), intent(in) :: name
    code = word_index(quantity_kind_names, name)
  end function quantity_kind_from_name

  !> The word of a `quantity_kind` code (`?` for another value).
  pure function quantity_kind_name(code) result(name)
    !> A code of `quantity_kind`.
    integer, intent(in) :: code
    character(len=:), allocatable :: name
    name = word_of(quantity_kind_names, code)
  end function quantity_kind_name

end module demstep_contact
