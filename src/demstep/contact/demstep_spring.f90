!> The seed's model: one mass on a linear spring, integrated by central differences.
!>
!> Recurrence (paper eq. 1, leapfrog form), from a state (x_{n-1}, v_{n-1}):
!>
!>     x_n = x_{n-1} + v_{n-1} dt
!>     v_n = v_{n-1} + (F(x_n, v) / M) dt,   F = -K x_n - c v
!>
!> `x` is the overlap (positive in compression) at whole steps and `v` the velocity
!> over the half step that follows. A compression-only spring (a DEM contact) acts
!> only while `x > 0`; a bilateral spring (a bond) always acts. The dashpot uses the
!> lagged velocity v_{n-1} (what leapfrog and velocity-Verlet DEM codes do) or the
!> centred average (v_{n-1} + v_n)/2.
!>
!> The undamped scheme is exact in closed form with `theta = 2 asin(omega dt / 2)`;
!> it is stable for `omega dt < 2`, i.e. `dt < 2 sqrt(M/K)` (paper eq. 6).
module demstep_spring
  use demstep_kinds, only: dp, i8, pi
  use demstep_status, only: demstep_status_type, demstep_stat, set_status, status_at
  use demstep_text, only: real_text
  use, intrinsic :: ieee_arithmetic, only: ieee_is_finite
  use demstep_words, only: word_index, word_of
  implicit none
  private

  public :: new_spring, spring_step, spring_run
  public :: spring_omega, spring_period, spring_damping_ratio, critical_time_step
  public :: numerical_phase, numerical_period, growth_factor
  public :: exact_discrete_state, paper_closed_form_velocity
  public :: check_time_step, step_for_n_per_period, saturated_count, ceiling_real
  public :: damped_limit, scheme_phase, phase_factor, restitution_to_damping_ratio

  !> The velocity a dashpot uses, by name: `dashpot_kind%lagged`.
  type, public :: dashpot_kind_enum
    !> The velocity of the previous half step (explicit, DEM default).
    integer :: lagged = 1
    !> The average of the half-step velocities around the force evaluation.
    integer :: centred = 2
  end type dashpot_kind_enum
  !> The dashpot kinds by name.
  type(dashpot_kind_enum), parameter, public :: dashpot_kind = dashpot_kind_enum()
  !> Their words, in code order (`dashpot_kind_from_name`, `dashpot_kind_name`).
  character(len=*), parameter, public :: dashpot_kind_names(2) = [character(len=7) :: "lagged", "centred"]
  public :: dashpot_kind_from_name, dashpot_kind_name
  !> Range of omega = sqrt(K/M) a spring may have: its period, critical step and
  !> the quantities built on them then stay well inside the double range.
  real(dp), parameter, public :: spring_omega_min = 1.0e-300_dp, spring_omega_max = 1.0e300_dp
  !> Largest (1 + zeta) omega dt assessed: beyond it the growth factor per step,
  !> about (omega dt)^2, would leave the double range.
  real(dp), parameter, public :: spring_h_max = 1.0e100_dp

  !> A mass on a linear spring with an optional viscous dashpot.
  type, public :: spring_type
    !> Mass M (> 0).
    real(dp) :: mass = 1.0_dp
    !> Stiffness K (> 0).
    real(dp) :: stiffness = 1.0_dp
    !> Viscous coefficient c = 2 zeta sqrt(K M) (>= 0).
    real(dp) :: damping = 0.0_dp
    !> Force only while the overlap is positive (a contact), else a bond.
    logical :: compression_only = .true.
    !> `dashpot_kind%lagged` or `dashpot_kind%centred`.
    integer :: dashpot = dashpot_kind%lagged
  end type spring_type

  !> State of the stepper after `step` steps.
  type, public :: spring_state_type
    !> Overlap x_n (positive in compression).
    real(dp) :: x = 0.0_dp
    !> Velocity v_n over the half step after x_n (positive towards compression).
    real(dp) :: v = 0.0_dp
    !> Number of steps taken.
    integer(i8) :: step = 0_i8
  end type spring_state_type


contains

  !> Build a validated spring from mass, stiffness and damping ratio.
  pure subroutine new_spring(spring, mass, stiffness, status, damping_ratio, &
      compression_only, dashpot)
    !> The spring built.
    type(spring_type), intent(out) :: spring
    !> Mass M and stiffness K, finite and > 0.
    real(dp), intent(in) :: mass, stiffness
    !> Status: invalid_input names the offending argument.
    type(demstep_status_type), intent(out) :: status
    !> Damping ratio zeta >= 0 (default 0).
    real(dp), intent(in), optional :: damping_ratio
    !> Contact spring (default) or bond.
    logical, intent(in), optional :: compression_only
    !> `dashpot_kind%lagged` (default) or `dashpot_kind%centred`.
    integer, intent(in), optional :: dashpot
    real(dp) :: zeta, omega, root_km, c, dt_critical, bound
    zeta = 0.0_dp
    if (present(damping_ratio)) zeta = damping_ratio
    if (.not. positive_finite(mass)) then
      call set_status(status, demstep_stat%invalid_input, "must be finite and > 0", where="mass")
      return
    end if
    if (.not. positive_finite(stiffness)) then
      call set_status(status, demstep_stat%invalid_input, "must be finite and > 0", where="stiffness")
      return
    end if
    if (.not. (ieee_is_finite(zeta) .and. zeta >= 0.0_dp)) then
      call set_status(status, demstep_stat%invalid_input, "must be finite and >= 0", where="damping_ratio")
      return
    end if
    ! scaled: K/M itself may overflow or underflow where its square root does not
    omega = sqrt(stiffness)/sqrt(mass)
    if (.not. (omega >= spring_omega_min .and. omega <= spring_omega_max)) then
      call set_status(status, demstep_stat%invalid_input, "stiffness/mass must be in " &
        //"[1e-600, 1e600] (omega = sqrt(stiffness/mass) in [1e-300, 1e300]), got omega = " &
        //real_text(omega), where="stiffness")
      return
    end if
    root_km = sqrt(stiffness)*sqrt(mass)
    c = 2.0_dp*zeta*root_km
    dt_critical = damped_limit(2.0_dp/omega, zeta)
    if (zeta > 0.0_dp .and. .not. (c <= huge(1.0_dp) .and. c >= tiny(1.0_dp) .and. &
        dt_critical >= tiny(1.0_dp))) then
      ! the dashpot c = 2 zeta sqrt(K M) and the critical step must be normal doubles
      bound = min(0.5_dp*(huge(1.0_dp)/root_km), (1.0_dp/omega)/tiny(1.0_dp))
      call set_status(status, demstep_stat%invalid_input, "must be 0 or in [" &
        //real_text(max(tiny(1.0_dp)/root_km, tiny(1.0_dp)))//", "//real_text(0.999_dp*bound) &
        //"] with this mass and stiffness (the dashpot 2 damping_ratio sqrt(stiffness mass) " &
        //"and the critical step must stay in the double range)", where="damping_ratio")
      return
    end if
    spring%mass = mass
    spring%stiffness = stiffness
    spring%damping = c
    if (present(compression_only)) spring%compression_only = compression_only
    if (present(dashpot)) then
      if (dashpot /= dashpot_kind%lagged .and. dashpot /= dashpot_kind%centred) then
        call set_status(status, demstep_stat%invalid_input, "must be lagged or centred", where="dashpot")
        return
      end if
      spring%dashpot = dashpot
    end if
    status%stat = demstep_stat%ok
  end subroutine new_spring

  !> One central-difference step: (x_{n-1}, v_{n-1}) -> (x_n, v_n).
  elemental subroutine spring_step(spring, dt, state)
    !> The spring.
    type(spring_type), intent(in) :: spring
    !> Time step.
    real(dp), intent(in) :: dt
    !> State, advanced by one step.
    type(spring_state_type), intent(inout) :: state
    real(dp) :: a
    state%x = state%x + state%v*dt
    state%step = state%step + 1_i8
    if (spring%compression_only .and. .not. state%x > 0.0_dp) return
    if (.not. spring%damping > 0.0_dp) then
      state%v = state%v - (spring%stiffness/spring%mass)*state%x*dt
    else if (spring%dashpot == dashpot_kind%lagged) then
      state%v = state%v - (spring%stiffness*state%x + spring%damping*state%v)/spring%mass*dt
    else
      a = 0.5_dp*spring%damping/spring%mass*dt
      state%v = ((1.0_dp - a)*state%v - (spring%stiffness/spring%mass)*state%x*dt)/(1.0_dp + a)
    end if
  end subroutine spring_step

  !> `nsteps` central-difference steps.
  pure subroutine spring_run(spring, dt, state, nsteps)
    !> The spring.
    type(spring_type), intent(in) :: spring
    !> Time step.
    real(dp), intent(in) :: dt
    !> State, advanced by `nsteps` steps.
    type(spring_state_type), intent(inout) :: state
    !> Number of steps.
    integer(i8), intent(in) :: nsteps
    integer(i8) :: i
    do i = 1_i8, nsteps
      call spring_step(spring, dt, state)
    end do
  end subroutine spring_run

  !> Natural angular frequency omega = sqrt(K/M).
  elemental function spring_omega(spring) result(omega)
    type(spring_type), intent(in) :: spring
    real(dp) :: omega
    ! sqrt(K)/sqrt(M): K/M may overflow where omega does not
    omega = sqrt(spring%stiffness)/sqrt(spring%mass)
  end function spring_omega

  !> Natural period T = 2 pi sqrt(M/K) (undamped).
  elemental function spring_period(spring) result(period)
    type(spring_type), intent(in) :: spring
    real(dp) :: period
    period = 2.0_dp*pi*(sqrt(spring%mass)/sqrt(spring%stiffness))
  end function spring_period

  !> Damping ratio zeta = c / (2 sqrt(K M)).
  elemental function spring_damping_ratio(spring) result(zeta)
    type(spring_type), intent(in) :: spring
    real(dp) :: zeta
    zeta = ((0.5_dp*spring%damping)/sqrt(spring%stiffness))/sqrt(spring%mass)
  end function spring_damping_ratio

  !> Largest stable time step. Undamped or centred dashpot: 2/omega (paper eq. 6);
  !> lagged dashpot: (2/omega)(sqrt(1 + zeta^2) - zeta).
  elemental function critical_time_step(spring) result(dt_critical)
    type(spring_type), intent(in) :: spring
    real(dp) :: dt_critical
    if (spring%dashpot == dashpot_kind%lagged) then
      dt_critical = damped_limit(2.0_dp/spring_omega(spring), spring_damping_ratio(spring))
    else
      dt_critical = 2.0_dp/spring_omega(spring)
    end if
  end function critical_time_step

  !> Damping ratio of a linear spring-dashpot whose restitution coefficient is e:
  !> zeta = -ln e / sqrt(pi^2 + ln^2 e).
  elemental real(dp) function restitution_to_damping_ratio(e) result(zeta)
    !> Restitution coefficient in (0, 1].
    real(dp), intent(in) :: e
    zeta = -log(e)/sqrt(pi**2 + log(e)**2)
  end function restitution_to_damping_ratio

  !> The stability limit of a lagged dashpot from the undamped one:
  !> `dt_undamped (sqrt(1 + zeta^2) - zeta)`, the damped-limit factor written as
  !> `dt_undamped/(sqrt(1 + zeta^2) + zeta)`: no cancellation, and no overflow for
  !> large zeta. Any scale works in place of a time step (h = omega dt: 2).
  elemental function damped_limit(dt_undamped, zeta) result(limit)
    !> The limit without a dashpot (2/omega for one spring).
    real(dp), intent(in) :: dt_undamped
    !> Damping ratio >= 0.
    real(dp), intent(in) :: zeta
    real(dp) :: limit
    if (zeta <= 1.0_dp) then
      limit = dt_undamped/(sqrt(1.0_dp + zeta**2) + zeta)
    else
      limit = (dt_undamped/zeta)/(sqrt(1.0_dp + (1.0_dp/zeta)**2) + 1.0_dp)
    end if
  end function damped_limit

  !> The roots rho e^(+-i theta) of the scheme's two-step recurrence for an acting
  !> spring at h = omega dt, x_{n+1} = beta x_n - rho^2 x_{n-1}: the phase per step
  !> theta and the decay per step rho. Undamped, theta = 2 asin(h/2), rho = 1. With
  !> f = `phase_factor`, the discriminant is beta^2/4 - rho^2 = -h^2 f (over
  !> (1 + zeta h)^2 when centred), so the roots are complex when f > 0 and
  !> sin^2(theta/2) = (2 rho - beta)/(4 rho) = h^2 f/(rho (2 rho + beta)) (over
  !> (1 + zeta h)^2 when centred): no cancellation near critical damping.
  !> `closed` is false beyond the stability limit or where the roots are real.
  elemental subroutine scheme_phase(h, zeta, centred, rho, theta, closed)
    !> omega dt and the damping ratio (>= 0).
    real(dp), intent(in) :: h, zeta
    !> Centred dashpot (else lagged).
    logical, intent(in) :: centred
    !> Decay and phase per step; 0 when not `closed`.
    real(dp), intent(out) :: rho, theta
    !> The roots are complex and the step below the limit.
    logical, intent(out) :: closed
    real(dp) :: f, beta, sin_half, a
    rho = 0.0_dp
    theta = 0.0_dp
    if (zeta == 0.0_dp) then
      closed = h < 2.0_dp
      if (.not. closed) return
      rho = 1.0_dp
      theta = 2.0_dp*asin(0.5_dp*h)
      return
    end if
    a = zeta*h
    if (centred) then
      closed = a < 1.0_dp .and. h < 2.0_dp
      if (.not. closed) return
      rho = sqrt((1.0_dp - a)/(1.0_dp + a))
      beta = (2.0_dp - h**2)/(1.0_dp + a)
    else
      closed = a < 0.5_dp .and. h < damped_limit(2.0_dp, zeta)
      if (.not. closed) return
      rho = sqrt(1.0_dp - 2.0_dp*a)
      beta = 2.0_dp - 2.0_dp*a - h**2
    end if
    f = phase_factor(h, zeta, centred)
    closed = f > 0.0_dp
    if (.not. closed) return
    ! sin(theta/2) itself: its square underflows for the finest steps
    sin_half = h*sqrt(f)/sqrt(rho*(2.0_dp*rho + beta))
    if (centred) sin_half = sin_half/(1.0_dp + a)
    closed = sin_half < 1.0_dp
    if (closed) theta = 2.0_dp*asin(sin_half)
  end subroutine scheme_phase

  !> f of `scheme_phase`: 1 - (zeta + h/2)^2 (lagged) or 1 - zeta^2 - h^2/4
  !> (centred), > 0 for complex roots; 1 - zeta is exact for zeta in [1/2, 2], so
  !> f keeps its digits next to critical damping.
  elemental real(dp) function phase_factor(h, zeta, centred) result(f)
    !> omega dt and the damping ratio.
    real(dp), intent(in) :: h, zeta
    !> Centred dashpot (else lagged).
    logical, intent(in) :: centred
    if (centred) then
      f = (1.0_dp - zeta)*(1.0_dp + zeta) - 0.25_dp*h**2
    else
      f = ((1.0_dp - zeta) - 0.5_dp*h)*((1.0_dp + zeta) + 0.5_dp*h)
    end if
  end function phase_factor

  !> Check a time step to assess on a spring: finite, a normal double, and
  !> (1 + zeta) omega dt <= spring_h_max, so that N = T/dt and the growth factor
  !> stay in the double range. Messages name `dt`.
  pure subroutine check_time_step(spring, dt, status)
    !> The spring (from new_spring).
    type(spring_type), intent(in) :: spring
    !> The time step.
    real(dp), intent(in) :: dt
    type(demstep_status_type), intent(out) :: status
    real(dp) :: period, dt_max, dt_min
    period = spring_period(spring)
    dt_max = min(huge(1.0_dp), (spring_h_max/(1.0_dp + spring_damping_ratio(spring))) &
      /spring_omega(spring))
    ! N = T/dt <= huge and dt a normal double
    dt_min = max(tiny(1.0_dp), period/huge(1.0_dp))
    if (.not. (ieee_is_finite(dt) .and. dt >= dt_min .and. dt <= dt_max)) then
      call set_status(status, demstep_stat%invalid_input, "must be in [" &
        //real_text(dt_min*1.001_dp)//", "//real_text(dt_max*0.999_dp)//"] for this spring, got " &
        //real_text(dt), where="dt")
      return
    end if
    status%stat = demstep_stat%ok
  end subroutine check_time_step

  !> The time step dt = T/N for N steps per period, checked as `check_time_step`;
  !> messages name `n_per_period`.
  pure subroutine step_for_n_per_period(spring, n_per_period, dt, status)
    !> The spring (from new_spring).
    type(spring_type), intent(in) :: spring
    !> N = T/dt, finite and > 0.
    real(dp), intent(in) :: n_per_period
    !> T/N; 0 when not ok.
    real(dp), intent(out) :: dt
    type(demstep_status_type), intent(out) :: status
    real(dp) :: period, n_min, n_max
    period = spring_period(spring)
    dt = 0.0_dp
    n_min = 2.0_dp*pi*(1.0_dp + spring_damping_ratio(spring))/spring_h_max
    n_max = min(huge(1.0_dp), period/tiny(1.0_dp))
    if (.not. (ieee_is_finite(n_per_period) .and. n_per_period >= n_min .and. &
        n_per_period <= n_max)) then
      call set_status(status, demstep_stat%invalid_input, "must be in [" &
        //real_text(n_min*1.001_dp)//", "//real_text(n_max*0.999_dp)//"] for this spring, got " &
        //real_text(n_per_period), where="n_per_period")
      return
    end if
    dt = period/n_per_period
    call check_time_step(spring, dt, status)
    call status_at(status, "n_per_period", lead="gives ")
  end subroutine step_for_n_per_period

  !> A count held in a real as a 64-bit integer, saturating at huge(1_i8)
  !> (`saturated` then true). `x` >= 0; its fraction is dropped.
  elemental subroutine saturated_count(x, count, saturated)
    real(dp), intent(in) :: x
    integer(i8), intent(out) :: count
    logical, intent(out) :: saturated
    ! 2^63 is a double; every double below it converts exactly after aint
    saturated = .not. x < 9223372036854775808.0_dp
    if (saturated) then
      count = huge(1_i8)
    else
      count = int(max(0.0_dp, aint(x)), i8)
    end if
  end subroutine saturated_count

  !> Phase advance per step of the undamped scheme, theta = 2 asin(omega dt / 2).
  !> Status `unstable` when omega dt >= 2 (theta is then not real).
  pure subroutine numerical_phase(omega_dt, theta, status)
    !> omega * dt, finite and > 0.
    real(dp), intent(in) :: omega_dt
    !> Phase per step in (0, pi); 0 when not ok.
    real(dp), intent(out) :: theta
    type(demstep_status_type), intent(out) :: status
    real(dp) :: rho
    logical :: closed
    theta = 0.0_dp
    if (.not. (ieee_is_finite(omega_dt) .and. omega_dt >= tiny(1.0_dp))) then
      call set_status(status, demstep_stat%invalid_input, "omega*dt must be finite and >= " &
        //real_text(tiny(1.0_dp)))
      return
    end if
    call scheme_phase(omega_dt, 0.0_dp, .false., rho, theta, closed)
    if (closed) then
      status%stat = demstep_stat%ok
    else
      call set_status(status, demstep_stat%unstable, &
        "omega*dt >= 2: the time step is at or beyond the stability limit 2 sqrt(M/K)")
    end if
  end subroutine numerical_phase

  !> Period of the undamped discrete solution, 2 pi dt / theta, in units of the
  !> natural period T (so 1 + (omega dt)^2/24 + ...). Status as `numerical_phase`.
  pure subroutine numerical_period(omega_dt, period_ratio, status)
    real(dp), intent(in) :: omega_dt
    !> Numerical period over T; 0 when not ok.
    real(dp), intent(out) :: period_ratio
    type(demstep_status_type), intent(out) :: status
    real(dp) :: theta
    period_ratio = 0.0_dp
    call numerical_phase(omega_dt, theta, status)
    if (status%stat == demstep_stat%ok) period_ratio = omega_dt/theta
  end subroutine numerical_period

  !> Spectral radius of the one-step map of a spring's scheme (acting spring):
  !> 1 for the undamped scheme below the limit, < 1 when damped and stable,
  !> > 1 beyond the limit (amplitude growth per step). With h = omega dt,
  !> a = zeta h, the characteristic polynomial is r^2 - b r + c with
  !> lagged dashpot b = 2 - 2a - h^2, c = 1 - 2a; centred b = (2 - h^2)/(1 + a),
  !> c = (1 - a)/(1 + a).
  elemental function growth_factor(spring, dt) result(rho)
    type(spring_type), intent(in) :: spring
    !> Time step.
    real(dp), intent(in) :: dt
    real(dp) :: rho, h, a, b, c, t, disc
    h = spring_omega(spring)*dt
    a = spring_damping_ratio(spring)*h
    if (spring%dashpot == dashpot_kind%lagged) then
      b = 2.0_dp - 2.0_dp*a - h**2
      c = 1.0_dp - 2.0_dp*a
    else
      b = (2.0_dp - h**2)/(1.0_dp + a)
      c = (1.0_dp - a)/(1.0_dp + a)
    end if
    ! roots b/2 +- sqrt((b/2)^2 - c), scaled where (b/2)^2 would overflow
    t = 0.5_dp*abs(b)
    if (t > 1.0e100_dp) then
      rho = t + t*sqrt(max(0.0_dp, 1.0_dp - (c/t)/t))
    else
      disc = t**2 - c
      if (disc < 0.0_dp) then
        rho = sqrt(c)
      else
        rho = t + sqrt(disc)
      end if
    end if
  end function growth_factor

  !> Exact state of the undamped bilateral scheme after n steps from (x0, v0):
  !>
  !>     x_n = x0 cos(n theta) + (x0 h^2/2 + v0 dt) sin(n theta)/sin(theta)
  !>     v_n = -x0 omega sin((n+1/2) theta) + (v0 + x0 omega h/2) cos((n+1/2) theta)/cos(theta/2)
  !>
  !> with h = omega dt (Yan & Guo 2014 give the x0 = 0 case, eqs. 2-4).
  pure subroutine exact_discrete_state(omega, dt, x0, v0, n, state, status)
    !> Natural angular frequency and time step.
    real(dp), intent(in) :: omega, dt
    !> Initial overlap and half-step velocity.
    real(dp), intent(in) :: x0, v0
    !> Number of steps (>= 0).
    integer(i8), intent(in) :: n
    !> State after n steps.
    type(spring_state_type), intent(out) :: state
    type(demstep_status_type), intent(out) :: status
    real(dp) :: h, theta, phase, half
    if (.not. (positive_finite(omega) .and. positive_finite(dt))) then
      call set_status(status, demstep_stat%invalid_input, "omega and dt must be finite and > 0")
      return
    end if
    if (n < 0_i8 .or. .not. (ieee_is_finite(x0) .and. ieee_is_finite(v0))) then
      call set_status(status, demstep_stat%invalid_input, "n must be >= 0 and x0, v0 finite")
      return
    end if
    h = omega*dt
    call numerical_phase(h, theta, status)
    if (status%stat /= demstep_stat%ok) return
    phase = real(n, dp)*theta
    half = phase + 0.5_dp*theta
    state%x = x0*cos(phase) + (0.5_dp*x0*h**2 + v0*dt)*sin(phase)/sin(theta)
    state%v = -x0*omega*sin(half) + (v0 + 0.5_dp*x0*omega*h)*cos(half)/cos(0.5_dp*theta)
    state%step = n
  end subroutine exact_discrete_state

  !> The paper's closed form (eq. 2, with eq. 4 its complex form) of v_n/v0 for
  !> x0 = 0, from A = -A_r, A_r = (K/M) dt^2:
  !>
  !>     v_n/v0 = [(1 + A/D) ((A+2+D)/2)^n + (1 - A/D) ((A+2-D)/2)^n] / 2,  D = sqrt(A^2 + 4A)
  !>
  !> evaluated in complex arithmetic, so it also shows the growth for A_r > 4.
  !> Status `pole` at A_r = 4 exactly (double root, D = 0).
  pure subroutine paper_closed_form_velocity(a_r, n, ratio, status)
    !> A_r = (omega dt)^2, finite and > 0.
    real(dp), intent(in) :: a_r
    !> Step number (>= 0).
    integer, intent(in) :: n
    !> v_n / v0.
    real(dp), intent(out) :: ratio
    type(demstep_status_type), intent(out) :: status
    complex(dp) :: d, r1, r2
    real(dp) :: a
    ratio = 0.0_dp
    if (.not. positive_finite(a_r) .or. n < 0) then
      call set_status(status, demstep_stat%invalid_input, "A_r must be finite and > 0, n >= 0")
      return
    end if
    if (a_r == 4.0_dp) then
      call set_status(status, demstep_stat%pole, "A_r = 4: double root, eq. (2) is singular")
      return
    end if
    a = -a_r
    d = sqrt(cmplx(a*a + 4.0_dp*a, 0.0_dp, kind=dp))
    r1 = 0.5_dp*(a + 2.0_dp + d)
    r2 = 0.5_dp*(a + 2.0_dp - d)
    ratio = real(0.5_dp*((1.0_dp + a/d)*r1**n + (1.0_dp - a/d)*r2**n), dp)
    status%stat = demstep_stat%ok
  end subroutine paper_closed_form_velocity

  !> ceiling(x) as a real, for any finite x (doubles from 2^52 up are integers).
  elemental function ceiling_real(x) result(c)
    !> Any finite real.
    real(dp), intent(in) :: x
    real(dp) :: c
    if (abs(x) >= 4503599627370496.0_dp) then
      c = x
    else
      c = aint(x)
      if (c < x) c = c + 1.0_dp
    end if
  end function ceiling_real

  elemental function positive_finite(x) result(ok)
    real(dp), intent(in) :: x
    logical :: ok
    ok = ieee_is_finite(x) .and. x > 0.0_dp
  end function positive_finite

  !> The `dashpot_kind` code of a word (case ignored); 0 for another word.
  pure integer function dashpot_kind_from_name(name) result(code)
    !> The word, one of `dashpot_kind_names`.
    character(len=*), intent(in) :: name
    code = word_index(dashpot_kind_names, name)
    ! the American spelling, accepted as well
    if (code == 0 .and. word_index(["centered"], name) == 1) code = dashpot_kind%centred
  end function dashpot_kind_from_name

  !> The word of a `dashpot_kind` code (`?` for another value).
  pure function dashpot_kind_name(code) result(name)
    !> A code of `dashpot_kind`.
    integer, intent(in) :: code
    character(len=:), allocatable :: name
    name = word_of(dashpot_kind_names, code)
  end function dashpot_kind_name

end module demstep_spring
