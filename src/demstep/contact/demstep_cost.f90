!> What accuracy costs: the smallest N = T/dt that meets a tolerance on a contact
!> quantity in the worst case over the onset, and the run time that N implies.
module demstep_cost
  use demstep_kinds, only: dp, i8, pi
  use demstep_status, only: demstep_status_type, demstep_stat, set_status
  use demstep_contact, only: discrete_contact_type, contact_worst_case, period_error, quantity_kind, &
    n_quantities, check_contact_damping
  use demstep_spring, only: saturated_count, ceiling_real
  use demstep_text, only: real_text, int_text
  use demstep_progress, only: progress_type
  use demstep_stiffness, only: nroots_options_type, nroots_type, n_roots
  use, intrinsic :: ieee_arithmetic, only: ieee_is_finite
  implicit none
  private

  public :: worst_error, n_for_tolerance, n_for_harmonic_tolerance, predict_run, accuracy_cost_table

  !> The paper's E at lambda as a quantity of [[accuracy_cost_table]], beside
  !> the contact quantities `quantity_kind%...`.
  integer, parameter, public :: quantity_harmonic = n_quantities + 1

  !> Largest N searched by default.
  real(dp), parameter, public :: default_cost_n_max = 1.0e7_dp
  !> Ratio of the grid on which "for every larger N" is checked.
  real(dp), parameter, public :: tolerance_grid_ratio = 1.02_dp
  !> Largest n_max accepted: the sweep from n_max down costs a worst case per
  !> grid point, about 1750 points from 1e15 (a few seconds at most).
  real(dp), parameter, public :: cost_n_max_limit = 1.0e15_dp

  !> What a run at N steps per period costs.
  type, public :: run_prediction_type
    !> Time step T/N.
    real(dp) :: dt = 0.0_dp
    !> Steps for the duration, ceiling(duration/dt), as a real (exact below 2^53).
    real(dp) :: steps_real = 0.0_dp
    !> The same as a 64-bit count, saturating at huge(1_i8).
    integer(i8) :: steps = 0_i8
    !> True when `steps` saturated.
    logical :: steps_saturated = .false.
    !> Predicted run time, steps x particles x cost per particle-step.
    real(dp) :: seconds = 0.0_dp
  end type run_prediction_type

contains

  !> The worst error over the onset of a quantity at N steps per period (the
  !> period error does not depend on the onset).
  pure subroutine worst_error(n_per_period, quantity, error, status, damping_ratio, onset)
    real(dp), intent(in) :: n_per_period
    integer, intent(in) :: quantity
    real(dp), intent(out) :: error
    type(demstep_status_type), intent(out) :: status
    real(dp), intent(in), optional :: damping_ratio
    !> The onset attaining it.
    real(dp), intent(out), optional :: onset
    type(discrete_contact_type) :: worst
    if (quantity < 1 .or. quantity > n_quantities) then
      call set_status(status, demstep_stat%invalid_input, "unknown quantity", where="quantity")
      error = 0.0_dp
      return
    end if
    if (quantity == quantity_kind%period) then
      error = period_error(n_per_period)
      if (present(onset)) onset = 1.0_dp
      status%stat = demstep_stat%ok
      return
    end if
    call contact_worst_case(n_per_period, quantity, worst, error, status, damping_ratio)
    if (present(onset)) onset = worst%onset
  end subroutine worst_error

  !> The smallest N such that the worst error is at most `tolerance` at N and at
  !> every larger N checked: a geometric grid of ratio 1.02 from n_max down, then
  !> of ratio 1.002 from 1.25 times that answer down (the errors jump where the
  !> number of steps in contact changes), and bisection to 1e-6 relative in the
  !> last cell. Between grid points an error can exceed the tolerance by its
  !> variation within one cell. Status not_found when the tolerance is not met at
  !> n_max; `at_limit` is set when it holds down to the stability limit (N is
  !> then that limit). Status invalid_input (naming `tolerance`, `n_max` or
  !> `damping_ratio`) for a tolerance not finite and > 0, n_max outside (limit,
  !> 1e15], or a contact quantity with damping_ratio outside [0, 1).
  pure subroutine n_for_tolerance(quantity, tolerance, n, status, damping_ratio, n_max, at_limit)
    integer, intent(in) :: quantity
    real(dp), intent(in) :: tolerance
    real(dp), intent(out) :: n
    type(demstep_status_type), intent(out) :: status
    real(dp), intent(in), optional :: damping_ratio, n_max
    logical, intent(out), optional :: at_limit
    real(dp) :: zeta, hi, lo, mid, e, limit, top
    integer :: it, pass
    logical :: reached_limit
    zeta = 0.0_dp
    if (present(damping_ratio)) zeta = damping_ratio
    top = default_cost_n_max
    if (present(n_max)) top = n_max
    if (present(at_limit)) at_limit = .false.
    n = 0.0_dp
    if (.not. (ieee_is_finite(tolerance) .and. tolerance > 0.0_dp)) then
      call set_status(status, demstep_stat%invalid_input, "must be finite and > 0", where="tolerance")
      return
    end if
    if (quantity /= quantity_kind%period) then
      call check_contact_damping(zeta, status)
      if (status%stat /= demstep_stat%ok) return
    else if (.not. (ieee_is_finite(zeta) .and. zeta >= 0.0_dp .and. zeta <= 1.0e100_dp)) then
      call set_status(status, demstep_stat%invalid_input, "must be in [0, 1e100]", where="damping_ratio")
      return
    end if
    ! just above the (damped) stability limit 2 pi/h_crit
    limit = pi*(hypot(1.0_dp, zeta) + zeta)*(1.0_dp + 1.0e-9_dp)
    if (.not. (ieee_is_finite(top) .and. top > limit .and. top <= cost_n_max_limit)) then
      call set_status(status, demstep_stat%invalid_input, "must be in (" &
        //real_text(limit)//", "//real_text(cost_n_max_limit)//"], got "//real_text(top), where="n_max")
      return
    end if
    call worst_error(top, quantity, e, status, zeta)
    if (status%stat /= demstep_stat%ok) return
    if (e > tolerance) then
      call set_status(status, demstep_stat%not_found, "the tolerance is not met up to n_max")
      return
    end if
    hi = top
    do pass = 1, 2
      if (pass == 2) hi = min(top, 1.25_dp*hi)
      call sweep_down(merge(tolerance_grid_ratio, 1.002_dp, pass == 1), hi, lo, reached_limit)
      if (status%stat /= demstep_stat%ok) return
      if (reached_limit) then
        n = limit
        if (present(at_limit)) at_limit = .true.
        return
      end if
    end do
    do it = 1, 60
      if (hi - lo <= 1.0e-6_dp*hi) exit
      mid = 0.5_dp*(lo + hi)
      call worst_error(mid, quantity, e, status, zeta)
      ! an error that cannot be computed (a contact that never ends) fails
      if (status%stat /= demstep_stat%ok .or. e > tolerance) then
        lo = mid
      else
        hi = mid
      end if
    end do
    n = hi
    status%stat = demstep_stat%ok
  contains
    !> From `pass_at` down by `ratio` until the error exceeds the tolerance:
    !> `pass_at` ends at the last point that passes, `fail` at the first that fails.
    pure subroutine sweep_down(ratio, pass_at, fail, hit_limit)
      real(dp), intent(in) :: ratio
      real(dp), intent(inout) :: pass_at
      real(dp), intent(out) :: fail
      logical, intent(out) :: hit_limit
      real(dp) :: x, ex
      type(demstep_status_type) :: sx
      hit_limit = .false.
      x = pass_at
      do
        fail = max(limit, x/ratio)
        call worst_error(fail, quantity, ex, sx, zeta)
        if (sx%stat /= demstep_stat%ok .or. ex > tolerance) exit
        x = fail
        if (fail <= limit) then
          hit_limit = .true.
          exit
        end if
      end do
      pass_at = x
    end subroutine sweep_down
  end subroutine n_for_tolerance

  !> The smallest N = T/dt at which the paper's |E| (eq. 23, half-period steps) at
  !> `lambda` meets the tolerance: the simulated-stiffness pick of [[n_roots]],
  !> with a pick at the stability limit counted as met. Status not_found when no
  !> N up to n_max (default `default_cost_n_max`) meets it, discontinuous when the
  !> pick jumps there; invalid_input (naming `lambda`, `tolerance` or `n_max`) as
  !> for `n_roots`.
  pure subroutine n_for_harmonic_tolerance(lambda, tolerance, n, status, n_max)
    !> sqrt(K'/K*), in (0, 1].
    real(dp), intent(in) :: lambda
    !> Tolerance on |E|, in [1e-10, 1).
    real(dp), intent(in) :: tolerance
    !> The N found (0 when none).
    real(dp), intent(out) :: n
    type(demstep_status_type), intent(out) :: status
    !> Largest N searched.
    real(dp), intent(in), optional :: n_max
    type(nroots_options_type) :: options
    type(nroots_type) :: r
    options%tolerance = tolerance
    options%n_max = default_cost_n_max
    if (present(n_max)) options%n_max = n_max
    call n_roots(lambda, options, r, status)
    n = 0.0_dp
    if (status%stat /= demstep_stat%ok) return
    n = r%n_pick
    if (r%stat == demstep_stat%ok .or. r%stat == demstep_stat%at_stability_limit) then
      status%stat = demstep_stat%ok
    else if (r%stat == demstep_stat%not_found) then
      call set_status(status, r%stat, "the tolerance is not met up to n_max")
    else
      call set_status(status, r%stat, "the pick of N jumps at this tolerance")
    end if
  end subroutine n_for_harmonic_tolerance

  !> What accuracy costs, per tolerance: the smallest N meeting it (the worst
  !> case over the onset of a contact quantity `quantity_kind%...`, or the
  !> paper's E at `lambda` with `quantity_harmonic`, N/2 steps per contact), and
  !> what a run at that N costs. A tolerance not met up to `n_max` has its
  !> library code in `stat` (its row zero); bad input is a status naming
  !> `tolerances` (and the element), `lambda` or the run's sizes.
  subroutine accuracy_cost_table(quantity, tolerances, period, duration, n_particles, cost, &
      n, rows, stat, status, damping_ratio, lambda, n_max, progress)
    integer, intent(in) :: quantity
    real(dp), intent(in) :: tolerances(:)
    !> T, the simulated duration, the particles and the seconds per particle-step.
    real(dp), intent(in) :: period, duration, n_particles, cost
    !> N per tolerance (0 where not met).
    real(dp), intent(out) :: n(size(tolerances))
    !> The run at each N.
    type(run_prediction_type), intent(out) :: rows(size(tolerances))
    !> The library's code per tolerance: ok, or why it is not met.
    integer, intent(out) :: stat(size(tolerances))
    type(demstep_status_type), intent(out) :: status
    !> The lagged dashpot's ratio (contact quantities), lambda (harmonic), the
    !> largest N searched.
    real(dp), intent(in), optional :: damping_ratio, lambda, n_max
    !> Told of each tolerance done.
    class(progress_type), intent(inout), optional :: progress
    type(demstep_status_type) :: st
    real(dp) :: zeta, lam, top
    integer :: i
    zeta = 0.0_dp
    if (present(damping_ratio)) zeta = damping_ratio
    lam = 0.0_dp
    if (present(lambda)) lam = lambda
    top = default_cost_n_max
    if (present(n_max)) top = n_max
    n = 0.0_dp
    stat = demstep_stat%ok
    status%stat = demstep_stat%ok
    if (present(progress)) call progress%start("tolerances", int(size(tolerances), i8))
    do i = 1, size(tolerances)
      if (quantity == quantity_harmonic) then
        call n_for_harmonic_tolerance(lam, tolerances(i), n(i), st, n_max=top)
      else
        call n_for_tolerance(quantity, tolerances(i), n(i), st, damping_ratio=zeta, n_max=top)
      end if
      if (present(progress)) call progress%update(int(i, i8))
      stat(i) = st%stat
      if (st%stat == demstep_stat%invalid_input) then
        select case (st%where)
        case ("tolerance")
          call set_status(status, st%stat, "element "//int_text(i)//" is "//real_text(tolerances(i), 10)// &
            "; "//st%detail, where="tolerances", index=i)
        case ("steps_fraction")
          ! N/2 steps per contact: the steps fraction is lambda's to set
          call set_status(status, st%stat, real_text(lam, 10)//" with N/2 steps per contact (f = 0.5): "// &
            st%detail, where="lambda")
        case default
          status = st
        end select
        exit
      end if
      if (st%stat == demstep_stat%ok) then
        call predict_run(period, n(i), duration, n_particles, cost, rows(i), status)
        if (status%stat /= demstep_stat%ok) exit
      else
        n(i) = 0.0_dp
      end if
    end do
    if (present(progress)) call progress%finish()
  end subroutine accuracy_cost_table

  !> The time step, steps and predicted run time of a run at N steps per period.
  !> Status invalid_input, naming the variable to change and the range that works,
  !> when a result would leave the range of normal doubles: `stiffness` (dt = T/N
  !> underflows), `duration` (the steps overflow), `n_particles` (the time overflows)
  !> or `cost_per_particle_step` (the time underflows). Steps saturate at 2^63 - 1.
  pure subroutine predict_run(period, n_per_period, duration, n_particles, &
      cost_per_particle_step, prediction, status)
    !> T, N = T/dt, simulated duration, particles and seconds per particle-step:
    !> finite and > 0.
    real(dp), intent(in) :: period, n_per_period, duration, n_particles, cost_per_particle_step
    type(run_prediction_type), intent(out) :: prediction
    type(demstep_status_type), intent(out) :: status
    real(dp) :: x, f, log_bound
    integer :: e
    prediction%dt = period/n_per_period
    if (.not. prediction%dt >= tiny(1.0_dp)) then
      call set_status(status, demstep_stat%invalid_input, "the step T/N = " &
        //real_text(prediction%dt)//" at N = "//real_text(n_per_period)//" underflows; " &
        //"sqrt(stiffness/mass) must be <= "//real_text(2.0_dp*pi/(n_per_period*tiny(1.0_dp))), where="stiffness")
      return
    end if
    x = duration/prediction%dt
    if (.not. x <= 0.5_dp*huge(1.0_dp)) then
      call set_status(status, demstep_stat%invalid_input, "the steps duration/dt at N = " &
        //real_text(n_per_period)//" exceed the double range; duration must be <= " &
        //real_text(0.25_dp*huge(1.0_dp)*prediction%dt), where="duration")
      return
    end if
    prediction%steps_real = max(1.0_dp, ceiling_real(x))
    call saturated_count(prediction%steps_real, prediction%steps, prediction%steps_saturated)
    ! the product by fractions and exponents: no intermediate overflow or underflow
    e = exponent(prediction%steps_real) + exponent(n_particles) + exponent(cost_per_particle_step)
    f = fraction(prediction%steps_real)*fraction(n_particles)*fraction(cost_per_particle_step)
    if (e + exponent(f) > maxexponent(1.0_dp)) then
      ! the largest n_particles (or duration) that keeps the time in range, by logarithms
      log_bound = log(huge(1.0_dp)) - log(prediction%steps_real) - log(cost_per_particle_step)
      if (log_bound >= 0.0_dp) then
        call set_status(status, demstep_stat%invalid_input, "the predicted run time " &
          //"exceeds the double range at N = "//real_text(n_per_period)//"; n_particles must be <= " &
          //real_text(0.999_dp*exp(log_bound)), where="n_particles")
      else
        call set_status(status, demstep_stat%invalid_input, "the predicted run time " &
          //"exceeds the double range at N = "//real_text(n_per_period)//"; duration must be <= " &
          //real_text(0.999_dp*duration*exp(log_bound - log(n_particles))), where="duration")
      end if
      return
    end if
    prediction%seconds = scale(f, e)
    if (.not. prediction%seconds >= tiny(1.0_dp)) then
      call set_status(status, demstep_stat%invalid_input, "the predicted " &
        //"run time underflows; cost_per_particle_step must be >= " &
        //real_text(1.001_dp*(tiny(1.0_dp)/prediction%steps_real)/n_particles), where="cost_per_particle_step")
      return
    end if
    status%stat = demstep_stat%ok
  end subroutine predict_run

end module demstep_cost
