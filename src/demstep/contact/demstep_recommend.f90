!> One recommended time step from a stability limit and, when a tolerance was
!> given, an accuracy requirement.
!>
!> The stability limit is demstep's exact limit of the model (a linear contact
!> with its dashpot, a linearised Hertz contact, an assembly). The recommended
!> step is `safety` times that limit, or the step the accuracy requirement
!> allows when that is smaller; the caller reports which of the two governs.
!>
!> The default safety factor, 0.9, is a margin on the inputs, not on the
!> formula (which is exact for the model): the limit scales as 1/sqrt(k/m), so
!> 0.9 of it stays stable for a contact up to 1/0.81 = 1.23 times stiffer (or
!> lighter) than the one described, the usual uncertainty of a Young's modulus
!> or of a Hertz linearisation. It buys stability only: near the limit a contact
!> lasts one or two steps, so accuracy needs a tolerance.
module demstep_recommend
  use demstep_kinds, only: dp, i8, pi
  use demstep_status, only: demstep_status_type, demstep_stat, set_status
  use demstep_text, only: real_text
  use demstep_spring, only: damped_limit, restitution_to_damping_ratio
  use demstep_contact, only: discrete_contact_type, contact_with_onset, contact_worst_case, &
    quantity_kind
  use demstep_cost, only: n_for_tolerance
  use demstep_material, only: material_pair_type, effective_pair_type, effective_pair, &
    hertz_impact_stiffness
  use demstep_words, only: word_index, word_of
  use, intrinsic :: ieee_arithmetic, only: ieee_is_finite
  implicit none
  private

  public :: recommended_step, assess_contact, assess_material_pair

  !> Default fraction of the exact stability limit recommended.
  real(dp), parameter, public :: default_safety = 0.9_dp

  !> What governs a recommended step, as components of a parameter.
  type, public :: step_governs_enum
    !> The stability limit times the safety factor.
    integer :: stability = 1
    !> The accuracy requirement (a tolerance).
    integer :: accuracy = 2
  end type step_governs_enum
  !> What governs, by name.
  type(step_governs_enum), parameter, public :: step_governs = step_governs_enum()
  public :: step_governs_from_name, step_governs_name
  !> Words for reports, indexed by `step_governs%...`.
  character(len=*), parameter, public :: step_governs_names(2) = [character(len=9) :: &
    "stability", "accuracy"]

  !> demstep's exact answers for one linear contact (mass, stiffness, lagged
  !> dashpot) stepped by central differences, at a given step and for a tolerance.
  type, public :: contact_assessment_type
    !> Natural period `2 pi sqrt(m/k)` and damping ratio `c/(2 sqrt(k m))`.
    real(dp) :: period = 0.0_dp, damping_ratio = 0.0_dp
    !> Exact stability limit of the lagged dashpot, `(2/omega)(sqrt(1 + z^2) - z)`.
    real(dp) :: dt_critical = 0.0_dp
    !> At the given step: N = T/dt, stable (dt below the limit), force
    !> evaluations in contact (onset at a step), the worst relative errors over
    !> the onset of the restitution and of the largest overlap (-1: not
    !> computed, the step being more than 1e50/omega beyond the limit).
    real(dp) :: n_per_period = 0.0_dp
    logical :: stable = .true.
    integer(i8) :: steps = 0_i8
    real(dp) :: restitution_error = 0.0_dp, overlap_error = 0.0_dp
    !> For the tolerance on the restitution: the smallest N meeting it and the
    !> step T/N (0 without a tolerance); `at_limit` when it holds up to the limit.
    real(dp) :: n_tolerance = 0.0_dp, dt_accuracy = 0.0_dp
    logical :: at_limit = .false.
  end type contact_assessment_type

contains

  !> Assess one linear contact: its exact limit; with `dt`, the contact at that
  !> step; with `tolerance`, the step whose worst restitution error meets it.
  !> Status `invalid_input` naming `mass`, `stiffness`, `damping_ratio` (in
  !> [0, 1): a contact that rebounds), `dt` or `tolerance`; `not_found` when the
  !> tolerance is not met below 1e7 steps per period.
  pure subroutine assess_contact(mass, stiffness, damping_ratio, assessment, status, dt, tolerance)
    !> Effective mass and (linearised) normal stiffness, finite and > 0.
    real(dp), intent(in) :: mass, stiffness
    !> Damping ratio of the dashpot, in [0, 1).
    real(dp), intent(in) :: damping_ratio
    type(contact_assessment_type), intent(out) :: assessment
    type(demstep_status_type), intent(out) :: status
    !> A step to assess (> 0).
    real(dp), intent(in), optional :: dt
    !> Tolerance on the relative restitution error (> 0).
    real(dp), intent(in), optional :: tolerance
    type(discrete_contact_type) :: c
    real(dp) :: omega
    if (.not. (mass > 0.0_dp .and. ieee_is_finite(mass))) then
      call set_status(status, demstep_stat%invalid_input, "must be finite and > 0", where="mass")
      return
    else if (.not. (stiffness > 0.0_dp .and. ieee_is_finite(stiffness))) then
      call set_status(status, demstep_stat%invalid_input, "must be finite and > 0", where="stiffness")
      return
    else if (.not. (damping_ratio >= 0.0_dp .and. damping_ratio < 1.0_dp)) then
      call set_status(status, demstep_stat%invalid_input, "must lie in [0, 1) " &
        //"(a contact that rebounds), got "//real_text(damping_ratio), where="damping_ratio")
      return
    end if
    omega = sqrt(stiffness)/sqrt(mass)
    assessment%period = 2.0_dp*pi/omega
    assessment%damping_ratio = damping_ratio
    assessment%dt_critical = damped_limit(2.0_dp/omega, damping_ratio)
    if (.not. (ieee_is_finite(assessment%period) .and. assessment%dt_critical >= tiny(1.0_dp))) then
      call set_status(status, demstep_stat%invalid_input, "sqrt(stiffness/mass) " &
        //"leaves the double range; rescale the units", where="stiffness")
      return
    end if
    status%stat = demstep_stat%ok
    if (present(dt)) then
      if (.not. (dt > 0.0_dp .and. ieee_is_finite(dt))) then
        call set_status(status, demstep_stat%invalid_input, "must be finite and > 0", where="dt")
        return
      end if
      assessment%n_per_period = assessment%period/dt
      assessment%stable = dt < assessment%dt_critical
      ! far beyond the limit ((1 + z) omega dt > 1e50) the contact is not stepped
      if (assessment%n_per_period < 2.0_dp*pi*(1.0_dp + damping_ratio)/1.0e50_dp) then
        assessment%restitution_error = -1.0_dp
        assessment%overlap_error = -1.0_dp
        return
      end if
      call contact_with_onset(assessment%n_per_period, 1.0_dp, c, status, damping_ratio)
      if (status%stat /= demstep_stat%ok) return
      assessment%steps = c%steps
      call contact_worst_case(assessment%n_per_period, quantity_kind%restitution, c, &
        assessment%restitution_error, status, damping_ratio)
      if (status%stat /= demstep_stat%ok) return
      call contact_worst_case(assessment%n_per_period, quantity_kind%overlap, c, &
        assessment%overlap_error, status, damping_ratio)
      if (status%stat /= demstep_stat%ok) return
    end if
    if (present(tolerance)) then
      call n_for_tolerance(quantity_kind%restitution, tolerance, assessment%n_tolerance, status, &
        damping_ratio=damping_ratio, at_limit=assessment%at_limit)
      if (status%stat /= demstep_stat%ok) return
      assessment%dt_accuracy = assessment%period/assessment%n_tolerance
    end if
  end subroutine assess_contact

  !> The recommended step `min(safety dt_stability, dt_accuracy)` and which of
  !> the two governs (stability on a tie). Status `invalid_input` (naming
  !> `dt_stability`, `safety` or `dt_accuracy`) for a limit or step not finite
  !> and > 0 or a safety factor outside (0, 1].
  pure subroutine recommended_step(dt_stability, dt, governs, status, safety, dt_accuracy)
    !> The exact stability limit (> 0).
    real(dp), intent(in) :: dt_stability
    !> The recommended step (0 on error).
    real(dp), intent(out) :: dt
    !> `step_governs%stability` or `step_governs%accuracy`.
    integer, intent(out) :: governs
    type(demstep_status_type), intent(out) :: status
    !> Fraction of the limit, in (0, 1] (default `default_safety`, 0.9).
    real(dp), intent(in), optional :: safety
    !> The largest step meeting the accuracy requirement (> 0); absent: none.
    real(dp), intent(in), optional :: dt_accuracy
    real(dp) :: f
    dt = 0.0_dp
    governs = step_governs%stability
    f = default_safety
    if (present(safety)) f = safety
    if (.not. (dt_stability > 0.0_dp .and. ieee_is_finite(dt_stability))) then
      call set_status(status, demstep_stat%invalid_input, "must be finite and > 0, got " &
        //real_text(dt_stability), where="dt_stability")
      return
    end if
    if (.not. (f > 0.0_dp .and. f <= 1.0_dp)) then
      call set_status(status, demstep_stat%invalid_input, "must lie in (0, 1], got " &
        //real_text(f), where="safety")
      return
    end if
    dt = f*dt_stability
    if (present(dt_accuracy)) then
      if (.not. (dt_accuracy > 0.0_dp .and. ieee_is_finite(dt_accuracy))) then
        dt = 0.0_dp
        call set_status(status, demstep_stat%invalid_input, "must be finite and > 0, got " &
          //real_text(dt_accuracy), where="dt_accuracy")
        return
      end if
      if (dt_accuracy < dt) then
        dt = dt_accuracy
        governs = step_governs%accuracy
      end if
    end if
    ! a limit near tiny times a safety factor may underflow
    if (.not. dt >= tiny(1.0_dp)) then
      dt = 0.0_dp
      call set_status(status, demstep_stat%invalid_input, "the recommended step " &
        //"underflows; rescale the units", where="dt_stability")
      return
    end if
    status%stat = demstep_stat%ok
  end subroutine recommended_step

  !> demstep's exact answers for a pair of materials: the Hertz contact
  !> linearised at the largest overlap of an impact at `pair%impact_velocity`
  !> (its tangent stiffness, the stiffest state the contact reaches, so the
  !> limit bounds the whole impact), with the lagged dashpot of the pair's
  !> restitution, `z = |ln e|/sqrt(pi^2 + ln^2 e)`; see [[assess_contact]].
  pure subroutine assess_material_pair(pair, assessment, status, tolerance, stiffness)
    !> The pair, its restitution and impact velocity.
    type(material_pair_type), intent(in) :: pair
    type(contact_assessment_type), intent(out) :: assessment
    type(demstep_status_type), intent(out) :: status
    !> Tolerance on the relative restitution error (> 0).
    real(dp), intent(in), optional :: tolerance
    !> The linearised stiffness used.
    real(dp), intent(out), optional :: stiffness
    type(effective_pair_type) :: eff
    real(dp) :: k
    call effective_pair(pair%a, pair%b, eff, status)
    if (status%stat /= demstep_stat%ok) return
    call hertz_impact_stiffness(eff, pair%impact_velocity, k, status)
    if (status%stat /= demstep_stat%ok) return
    if (present(stiffness)) stiffness = k
    if (.not. (pair%restitution > 0.0_dp .and. pair%restitution <= 1.0_dp)) then
      call set_status(status, demstep_stat%invalid_input, "must lie in (0, 1]", where="restitution")
      return
    end if
    call assess_contact(eff%m_star, k, restitution_to_damping_ratio(pair%restitution), assessment, &
      status, tolerance=tolerance)
  end subroutine assess_material_pair

  !> The `step_governs` code of a word (case ignored); 0 for another word.
  pure integer function step_governs_from_name(name) result(code)
    !> The word, one of `step_governs_names`.
    character(len=*), intent(in) :: name
    code = word_index(step_governs_names, name)
  end function step_governs_from_name

  !> The word of a `step_governs` code (`?` for another value).
  pure function step_governs_name(code) result(name)
    !> A code of `step_governs`.
    integer, intent(in) :: code
    character(len=:), allocatable :: name
    name = word_of(step_governs_names, code)
  end function step_governs_name

end module demstep_recommend
