!> demstep's assessment of an MFiX deck: the exact stability limit of each
!> pair under MFiX's EULER scheme, the contact at MFiX's DTSOLID, the step that
!> meets a tolerance on the restitution, the smallest particles of a size
!> distribution, and the DTSOLID_FACTOR to give MFiX.
module demstep_mfix_assess
  use demstep_kinds, only: dp, i8
  use demstep_material, only: effective_pair_type, hertz_impact_stiffness, hertz_contact_duration
  use demstep_recommend, only: contact_assessment_type, assess_contact, recommended_step
  use demstep_spring, only: ceiling_real
  use demstep_cost, only: default_cost_n_max
  use demstep_status, only: demstep_status_type, demstep_stat, set_status
  use demstep_text, only: int_text, real_text
  use demstep_mfix_input, only: mfix_input_type, mfix_model, mfix_pair_index
  use demstep_mfix, only: mfix_result_type, mfix_compute, mfix_pair_name
  use, intrinsic :: ieee_arithmetic, only: ieee_is_finite
  implicit none
  private

  public :: mfix_assess

  !> demstep's exact answers for a deck at MFiX's step, per pair in the order of
  !> [[mfix_result_type]], in the deck's units (times in seconds).
  type, public :: mfix_assessment_type
    !> The tolerance on the restitution error and the impact velocity used
    !> (0: none given).
    real(dp) :: tolerance = 0.0_dp, velocity = 0.0_dp
    !> True when the exact answers exist: LSD, or Hertzian with an impact
    !> velocity (the Hertz contact is linearised at its largest overlap).
    logical :: linearised = .false.
    !> Damping ratio of the (linearised) contact: `eta_n/(2 sqrt(k m))`, for
    !> Hertzian `eta_n/(2 sqrt(1.5 HERT_KN m))` at every overlap.
    real(dp), allocatable :: damping_ratio(:)
    !> Linear stiffness: `KN` (LSD), the Hertz tangent stiffness at the largest
    !> overlap of the impact (Hertzian); 0 where undefined.
    real(dp), allocatable :: k_linear(:)
    !> The contact's true duration: the damped linear one (LSD), the Hertz
    !> duration at the impact velocity (Hertzian); 0 where undefined.
    real(dp), allocatable :: t_contact(:)
    !> Exact stability limit of the lagged dashpot (EULER); 0 where undefined.
    real(dp), allocatable :: dt_critical(:)
    !> At DTSOLID: N = T/DTSOLID, force evaluations per contact (onset at a
    !> step), stable, worst relative restitution and overlap errors.
    real(dp), allocatable :: n_per_period(:), restitution_error(:), overlap_error(:)
    integer(i8), allocatable :: steps(:)
    logical, allocatable :: stable(:)
    !> Largest step meeting the tolerance, per pair (0 without a tolerance).
    real(dp), allocatable :: dt_accuracy(:)
    !> Smallest limit and accuracy step over all pairs (walls and the smallest
    !> particles of a size distribution included); the recommended step and
    !> what governs it (`step_governs%...`); the DTSOLID_FACTOR giving a DTSOLID
    !> at most the recommended step (an integer >= 10, MFiX's lower bound).
    real(dp) :: dt_stability = 0.0_dp, dt_accuracy_min = 0.0_dp, dt_recommended = 0.0_dp
    integer :: governs = 0
    real(dp) :: dtsolid_factor = 0.0_dp
    !> True when a wall pair has a smaller limit than every particle pair
    !> (MFiX leaves walls out of TCOLL).
    logical :: walls_govern = .false.
    !> Size distributions (`d_min` of [[mfix_input_type]] below `D_P0`): MFiX's
    !> TCOLL and demstep's smallest limit with those diameters in place of `D_P0`.
    logical :: psd = .false.
    real(dp) :: tcoll_psd = 0.0_dp, dt_stability_psd = 0.0_dp
  end type mfix_assessment_type

contains

  !> demstep's exact answers for a deck at MFiX's step (see
  !> [[mfix_assessment_type]]): per pair the exact limit under MFiX's EULER
  !> scheme (central differences, dashpot on the previous velocity), the contact
  !> at DTSOLID, the step meeting `tolerance` on the restitution; the smallest
  !> particles of a size distribution; the recommended step and DTSOLID_FACTOR.
  !> Status `invalid_input` naming `tolerance` or `velocity`, or the pair.
  pure subroutine mfix_assess(input, result, assessment, status, tolerance, velocity)
    !> A deck's DEM inputs and what MFiX computes from them.
    type(mfix_input_type), intent(in) :: input
    type(mfix_result_type), intent(in) :: result
    type(mfix_assessment_type), intent(out) :: assessment
    type(demstep_status_type), intent(out) :: status
    !> Tolerance on the relative restitution error (> 0); absent: stability only.
    real(dp), intent(in), optional :: tolerance
    !> Impact velocity in the deck's units (> 0), needed for Hertzian decks.
    real(dp), intent(in), optional :: velocity
    type(mfix_assessment_type) :: small
    type(mfix_input_type) :: psd_input
    type(mfix_result_type) :: psd_result
    integer :: k, np
    if (present(tolerance)) then
      if (.not. (tolerance > 0.0_dp .and. tolerance < 1.0_dp)) then
        call set_status(status, demstep_stat%invalid_input, "must lie in (0, 1), got " &
          //real_text(tolerance), where="tolerance")
        return
      end if
      assessment%tolerance = tolerance
    end if
    if (present(velocity)) then
      if (.not. (velocity > 0.0_dp .and. ieee_is_finite(velocity))) then
        call set_status(status, demstep_stat%invalid_input, "must be finite and > 0, got " &
          //real_text(velocity), where="velocity")
        return
      end if
      assessment%velocity = velocity
    end if
    call assess_pairs(input, result, assessment, status)
    if (status%stat /= demstep_stat%ok) return
    np = result%n_pairs

    ! size distributions: the smallest diameter of each DEM phase in place of D_P0
    psd_input = input
    do k = 1, input%n_phases
      if (input%d_min(k) > 0.0_dp .and. input%d_min(k) < input%d_p0(k)) then
        assessment%psd = .true.
        psd_input%d_p0(k) = input%d_min(k)
      end if
    end do

    assessment%dt_stability = 0.0_dp
    if (assessment%linearised) then
      assessment%dt_stability = minval(assessment%dt_critical)
      assessment%walls_govern = minval(assessment%dt_critical(np+1:)) < minval(assessment%dt_critical(:np))
    end if
    if (present(tolerance) .and. assessment%linearised) assessment%dt_accuracy_min = minval(assessment%dt_accuracy)
    if (assessment%psd) then
      call mfix_compute(psd_input, psd_result, status)
      if (status%stat /= demstep_stat%ok) return
      assessment%tcoll_psd = psd_result%tcoll
      small%tolerance = assessment%tolerance
      small%velocity = assessment%velocity
      call assess_pairs(psd_input, psd_result, small, status)
      if (status%stat /= demstep_stat%ok) return
      if (small%linearised) then
        assessment%dt_stability_psd = minval(small%dt_critical)
        assessment%dt_stability = min(assessment%dt_stability, assessment%dt_stability_psd)
        if (present(tolerance)) assessment%dt_accuracy_min = min(assessment%dt_accuracy_min, &
          minval(small%dt_accuracy))
      end if
    end if

    status%stat = demstep_stat%ok
    if (.not. assessment%linearised) return
    if (present(tolerance)) then
      call recommended_step(assessment%dt_stability, assessment%dt_recommended, assessment%governs, &
        status, dt_accuracy=assessment%dt_accuracy_min)
    else
      call recommended_step(assessment%dt_stability, assessment%dt_recommended, assessment%governs, status)
    end if
    if (status%stat /= demstep_stat%ok) return
    ! DTSOLID = TCOLL/factor <= the recommended step
    assessment%dtsolid_factor = max(10.0_dp, ceiling_real(result%tcoll/assessment%dt_recommended))
  end subroutine mfix_assess

  !> The per-pair part of [[mfix_assess]] for one input (D_P0 or the smallest sizes).
  pure subroutine assess_pairs(input, result, a, status)
    type(mfix_input_type), intent(in) :: input
    type(mfix_result_type), intent(in) :: result
    type(mfix_assessment_type), intent(inout) :: a
    type(demstep_status_type), intent(out) :: status
    type(contact_assessment_type) :: c
    type(effective_pair_type) :: eff
    integer :: p, n, j, code
    real(dp) :: m, k_lin, t_contact, n_tol(result%n_pairs + result%n_walls)
    character(len=:), allocatable :: what
    n = result%n_pairs + result%n_walls
    allocate(a%damping_ratio(n), a%k_linear(n), a%t_contact(n), a%dt_critical(n), a%n_per_period(n), &
      a%restitution_error(n), a%overlap_error(n), a%steps(n), a%stable(n), a%dt_accuracy(n))
    a%k_linear = 0.0_dp
    a%t_contact = 0.0_dp
    a%dt_critical = 0.0_dp
    a%n_per_period = 0.0_dp
    a%restitution_error = 0.0_dp
    a%overlap_error = 0.0_dp
    a%steps = 0_i8
    a%stable = .true.
    a%dt_accuracy = 0.0_dp
    a%linearised = input%model == mfix_model%lsd .or. a%velocity > 0.0_dp
    status%stat = demstep_stat%ok
    do p = 1, n
      m = result%m_eff(p)
      if (input%model == mfix_model%lsd) then
        a%damping_ratio(p) = result%eta_n(p)/(2.0_dp*sqrt(result%k_n(p)*m))
        k_lin = result%k_n(p)
        t_contact = result%t_coll(p)
      else
        ! force HERT_KN d^(3/2) + eta_n d^(1/4) v: tangent 1.5 HERT_KN d^(1/2), so
        ! the linearised damping ratio does not depend on the overlap
        a%damping_ratio(p) = result%eta_n(p)/(2.0_dp*sqrt(1.5_dp*result%k_n(p)*m))
        if (.not. a%linearised) cycle
        ! HERT_KN = 4/3 E* sqrt(R*): E* sqrt(R*) is all the Hertz law needs
        eff%e_star = 0.75_dp*result%k_n(p)
        eff%r_star = 1.0_dp
        eff%m_star = m
        call hertz_impact_stiffness(eff, a%velocity, k_lin, status)
        if (status%stat == demstep_stat%ok) call hertz_contact_duration(eff, a%velocity, t_contact, status)
        if (status%stat /= demstep_stat%ok) then
          code = status%stat
          what = status%message
          call set_status(status, code, mfix_pair_name(result, p)//": "//what, where="velocity")
          return
        end if
      end if
      a%k_linear(p) = k_lin
      a%t_contact(p) = t_contact
      call assess_contact(m, k_lin, a%damping_ratio(p), c, status, dt=result%dtsolid)
      if (status%stat /= demstep_stat%ok) then
        call name_pair(input, result, p, status)
        return
      end if
      a%dt_critical(p) = c%dt_critical
      a%n_per_period(p) = c%n_per_period
      a%steps(p) = c%steps
      a%stable(p) = c%stable
      a%restitution_error(p) = c%restitution_error
      a%overlap_error(p) = c%overlap_error
      if (a%tolerance > 0.0_dp) then
        ! N for a tolerance depends on the damping ratio alone: reuse it
        n_tol(p) = 0.0_dp
        do j = 1, p - 1
          if (a%damping_ratio(j) == a%damping_ratio(p) .and. n_tol(j) > 0.0_dp) n_tol(p) = n_tol(j)
        end do
        if (n_tol(p) == 0.0_dp) then
          call assess_contact(m, k_lin, a%damping_ratio(p), c, status, tolerance=a%tolerance)
          if (status%stat == demstep_stat%not_found) then
            call set_status(status, demstep_stat%invalid_input, real_text(a%tolerance)// &
              " is not met below "//real_text(default_cost_n_max)//" steps per period ("// &
              mfix_pair_name(result, p)//"); use a larger one", where="tolerance")
            return
          else if (status%stat /= demstep_stat%ok) then
            call name_pair(input, result, p, status)
            return
          end if
          n_tol(p) = c%n_tolerance
        end if
        a%dt_accuracy(p) = c%period/n_tol(p)
      end if
    end do
  end subroutine assess_pairs

  !> A pair's failure, named: `the pair of phases i and j: what`, and a failure of
  !> its steps per period (a damping the discrete contact cannot end with) first
  !> names the keyword that gives the damping, the pair's restitution
  !> (`DES_EN_INPUT(k)` in MFiX's packed order, `DES_EN_WALL_INPUT(i)`).
  pure subroutine name_pair(input, result, p, status)
    type(mfix_input_type), intent(in) :: input
    type(mfix_result_type), intent(in) :: result
    integer, intent(in) :: p
    type(demstep_status_type), intent(inout) :: status
    character(len=*), parameter :: internal = "n_per_period: "
    integer :: i, j
    if (index(status%message, internal) /= 1) then
      status%message = mfix_pair_name(result, p)//": "//status%message
      return
    end if
    i = findloc(input%phase, result%phase_i(p), dim=1)
    if (result%phase_j(p) == 0) then
      status%message = "DES_EN_WALL_INPUT("//int_text(i)//"): "//mfix_pair_name(result, p)//": " &
        //status%message(len(internal) + 1:)
    else
      j = findloc(input%phase, result%phase_j(p), dim=1)
      status%message = "DES_EN_INPUT("//int_text(mfix_pair_index(min(i, j), max(i, j), input%n_phases)) &
        //"): "//mfix_pair_name(result, p)//": "//status%message(len(internal) + 1:)
    end if
  end subroutine name_pair

end module demstep_mfix_assess
