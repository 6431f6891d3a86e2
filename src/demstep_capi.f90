!> The C API of demstep (bind(C)), declared in include/demstep.h.
!>
!> Every function returns a status code (0 on success, the codes of
!> `demstep_stat` otherwise) and, when `err` is not NULL, fills it with the code
!> and a NUL-terminated message. Pointers to outputs must not be NULL; arrays
!> are passed with their lengths; particle and bond numbers are 0-based.
module demstep_capi
  use, intrinsic :: iso_c_binding, only: c_int, c_double, c_int64_t, c_char, c_ptr, c_null_char, &
    c_associated, c_f_pointer
  use, intrinsic :: ieee_arithmetic, only: ieee_is_finite, ieee_is_nan
  use demstep_kinds, only: dp, i8
  use demstep_status, only: demstep_status_type, demstep_stat, set_status
  use demstep_spring, only: spring_type, spring_state_type, new_spring, spring_step, &
    critical_time_step
  use demstep_harmonic, only: harmonic_error, step_policy_type, new_step_policy
  use demstep_stiffness, only: nroots_options_type, nroots_type, n_roots, stiffness_input_type, &
    stiffness_result_type, simulated_stiffness
  use demstep_scene, only: scene_type, new_scene, scene_add_bonds, n_effects
  use demstep_assembly, only: critical_step_type, assembly_critical_steps
  use demstep_contact, only: discrete_contact_type, contact_with_onset
  use demstep_cost, only: n_for_tolerance
  implicit none
  private

  !> Length of the message buffer of demstep_error (with the NUL).
  integer, parameter, public :: capi_message_length = 256

  !> struct demstep_error.
  type, bind(C), public :: demstep_error_c
    integer(c_int) :: stat
    character(kind=c_char) :: message(capi_message_length)
  end type demstep_error_c

  !> struct demstep_spring.
  type, bind(C), public :: demstep_spring_c
    real(c_double) :: mass, stiffness, damping
    integer(c_int) :: compression_only, dashpot
  end type demstep_spring_c

  !> struct demstep_spring_state.
  type, bind(C), public :: demstep_spring_state_c
    real(c_double) :: x, v
    integer(c_int64_t) :: step
  end type demstep_spring_state_c

  !> struct demstep_nroots.
  type, bind(C), public :: demstep_nroots_c
    real(c_double) :: n_pick, n_zero, n_lower, n_upper
    integer(c_int) :: interval, stat, evaluations
  end type demstep_nroots_c

  !> struct demstep_stiffness_result.
  type, bind(C), public :: demstep_stiffness_result_c
    real(c_double) :: n_star, lambda_star, period, dt, stiffness_actual
    integer(c_int) :: lambda_star_stat, excluded
  end type demstep_stiffness_result_c

  !> struct demstep_critical_step.
  type, bind(C), public :: demstep_critical_step_c
    real(c_double) :: omega_max, dt_critical_eigen, omega_bound, dt_critical_bound, &
      dt_contact_rule, damping_ratio_top, dt_critical_damped
    integer(c_int) :: n_dof, n_springs, eigen_computed
  end type demstep_critical_step_c

  !> struct demstep_contact.
  type, bind(C), public :: demstep_contact_c
    real(c_double) :: onset, contact_time, restitution, max_overlap
    integer(c_int64_t) :: steps
    integer(c_int) :: stable
  end type demstep_contact_c

  public :: c_contact_with_onset, c_n_for_tolerance
  public :: c_spring_new, c_spring_step, c_critical_time_step, c_harmonic_error, c_n_roots, &
    c_simulated_stiffness, c_scene_critical_step

contains

  !> Store a status into the caller's error struct (if any) and return its code.
  function report(err, status) result(code)
    type(c_ptr), intent(in) :: err
    type(demstep_status_type), intent(in) :: status
    integer(c_int) :: code
    type(demstep_error_c), pointer :: e
    integer :: i, n
    code = int(status%stat, c_int)
    if (.not. c_associated(err)) return
    call c_f_pointer(err, e)
    e%stat = code
    e%message = c_null_char
    if (.not. allocated(status%message)) return
    n = min(len(status%message), capi_message_length - 1)
    do i = 1, n
      e%message(i) = status%message(i:i)
    end do
  end function report

  function invalid(err, message) result(code)
    type(c_ptr), intent(in) :: err
    character(len=*), intent(in) :: message
    integer(c_int) :: code
    type(demstep_status_type) :: status
    call set_status(status, demstep_stat%invalid_input, message)
    code = report(err, status)
  end function invalid

  !> The backstop of every entry point: DEMSTEP_OK only with finite outputs.
  !> `code` is kept when an error is already reported; a non-finite value turns it
  !> into DEMSTEP_INVALID_INPUT with a message naming the function.
  subroutine guard_finite(values, name, err, code)
    real(dp), intent(in) :: values(:)
    character(len=*), intent(in) :: name
    type(c_ptr), intent(in) :: err
    integer(c_int), intent(inout) :: code
    if (code /= demstep_stat%ok) return
    if (all(ieee_is_finite(values))) return
    code = invalid(err, name//": the result is not finite (an input is beyond the computable range)")
  end subroutine guard_finite

  function ok(err) result(code)
    type(c_ptr), intent(in) :: err
    integer(c_int) :: code
    type(demstep_status_type) :: status
    status%stat = demstep_stat%ok
    code = report(err, status)
  end function ok

  !> int demstep_spring_new(double mass, double stiffness, double damping_ratio,
  !>   int compression_only, int dashpot, demstep_spring *spring, demstep_error *err)
  function c_spring_new(mass, stiffness, damping_ratio, compression_only, dashpot, spring, err) &
      result(code) bind(C, name="demstep_spring_new")
    real(c_double), value :: mass, stiffness, damping_ratio
    integer(c_int), value :: compression_only, dashpot
    type(c_ptr), value :: spring, err
    integer(c_int) :: code
    type(demstep_spring_c), pointer :: s
    type(spring_type) :: f
    type(demstep_status_type) :: status
    if (.not. c_associated(spring)) then
      code = invalid(err, "demstep_spring_new: spring is NULL")
      return
    end if
    call new_spring(f, mass, stiffness, status, damping_ratio=damping_ratio, &
      compression_only=compression_only /= 0, dashpot=int(dashpot))
    code = report(err, status)
    call guard_finite([f%mass, f%stiffness, f%damping], "demstep_spring_new", err, code)
    if (code /= demstep_stat%ok) return
    call c_f_pointer(spring, s)
    s = demstep_spring_c(f%mass, f%stiffness, f%damping, merge(1, 0, f%compression_only), f%dashpot)
  end function c_spring_new

  !> int demstep_spring_step(const demstep_spring *spring, double dt,
  !>   demstep_spring_state *state, demstep_error *err)
  function c_spring_step(spring, dt, state, err) result(code) bind(C, name="demstep_spring_step")
    type(c_ptr), value :: spring, state, err
    real(c_double), value :: dt
    integer(c_int) :: code
    type(spring_type) :: f
    type(spring_state_type) :: st
    type(demstep_spring_state_c), pointer :: cs
    if (.not. (c_associated(spring) .and. c_associated(state))) then
      code = invalid(err, "demstep_spring_step: spring or state is NULL")
      return
    end if
    if (.not. from_c_spring(spring, f, err, code)) return
    if (.not. (ieee_is_finite(dt) .and. dt > 0.0_dp)) then
      code = invalid(err, "demstep_spring_step: dt must be finite and > 0")
      return
    end if
    call c_f_pointer(state, cs)
    st = spring_state_type(x=cs%x, v=cs%v, step=int(cs%step, i8))
    call spring_step(f, dt, st)
    code = ok(err)
    call guard_finite([st%x, st%v], "demstep_spring_step", err, code)
    if (code /= demstep_stat%ok) return
    cs = demstep_spring_state_c(st%x, st%v, int(st%step, c_int64_t))
  end function c_spring_step

  !> int demstep_critical_time_step(const demstep_spring *spring, double *dt_critical,
  !>   demstep_error *err)
  function c_critical_time_step(spring, dt_critical, err) result(code) &
      bind(C, name="demstep_critical_time_step")
    type(c_ptr), value :: spring, dt_critical, err
    integer(c_int) :: code
    type(spring_type) :: f
    real(c_double), pointer :: out
    real(dp) :: value
    if (.not. (c_associated(spring) .and. c_associated(dt_critical))) then
      code = invalid(err, "demstep_critical_time_step: spring or dt_critical is NULL")
      return
    end if
    if (.not. from_c_spring(spring, f, err, code)) return
    value = critical_time_step(f)
    code = ok(err)
    call guard_finite([value], "demstep_critical_time_step", err, code)
    if (code /= demstep_stat%ok) return
    call c_f_pointer(dt_critical, out)
    out = value
  end function c_critical_time_step

  !> A validated Fortran spring from a C one.
  logical function from_c_spring(spring, f, err, code)
    type(c_ptr), intent(in) :: spring, err
    type(spring_type), intent(out) :: f
    integer(c_int), intent(out) :: code
    type(demstep_spring_c), pointer :: s
    type(demstep_status_type) :: status
    call c_f_pointer(spring, s)
    call new_spring(f, s%mass, s%stiffness, status, compression_only=s%compression_only /= 0, &
      dashpot=int(s%dashpot))
    from_c_spring = status%stat == demstep_stat%ok .and. ieee_is_finite(s%damping) .and. s%damping >= 0.0_dp
    code = demstep_stat%ok
    if (status%stat /= demstep_stat%ok) then
      code = report(err, status)
    else if (.not. from_c_spring) then
      code = invalid(err, "spring: damping must be finite and >= 0")
    end if
    f%damping = s%damping
  end function from_c_spring

  !> int demstep_harmonic_error(double n_per_period, double lambda, double n_steps,
  !>   double *e, demstep_error *err)
  function c_harmonic_error(n_per_period, lambda, n_steps, e, err) result(code) &
      bind(C, name="demstep_harmonic_error")
    real(c_double), value :: n_per_period, lambda, n_steps
    type(c_ptr), value :: e, err
    integer(c_int) :: code
    real(c_double), pointer :: out
    real(dp) :: value
    integer :: stat
    type(demstep_status_type) :: status
    if (.not. c_associated(e)) then
      code = invalid(err, "demstep_harmonic_error: e is NULL")
      return
    end if
    call harmonic_error(n_per_period, lambda, n_steps, value, stat)
    call c_f_pointer(e, out)
    out = value
    if (stat == demstep_stat%ok) then
      code = ok(err)
      call guard_finite([value], "demstep_harmonic_error", err, code)
    else if (stat == demstep_stat%pole) then
      call set_status(status, stat, "demstep_harmonic_error: a pole, S(2 pi lambda/N, n) = 0")
      code = report(err, status)
    else
      call set_status(status, stat, "demstep_harmonic_error: N, lambda must be finite and > 0, " &
        //"1 <= n_steps <= 1e12")
      code = report(err, status)
    end if
  end function c_harmonic_error

  !> Options of an N-scan from C arguments.
  logical function nroots_options(tolerance, steps_kind, steps_value, pick, n_max, resolution, &
      options, err, code)
    real(c_double), intent(in) :: tolerance, steps_value, n_max, resolution
    integer(c_int), intent(in) :: steps_kind, pick
    type(nroots_options_type), intent(out) :: options
    type(c_ptr), intent(in) :: err
    integer(c_int), intent(out) :: code
    type(demstep_status_type) :: status
    code = demstep_stat%ok
    nroots_options = .false.
    call new_step_policy(options%policy, int(steps_kind), steps_value, status)
    if (status%stat /= demstep_stat%ok) then
      code = invalid(err, "steps_value: step policy kind 1 (fixed, 1 <= n <= 1e12), 2 (fraction " &
        //"f > 0) or 3 (rounded f > 0)")
      return
    end if
    options%tolerance = tolerance
    options%pick = int(pick)
    ! only n_max, resolution <= 0 mean the defaults; NaN and the rest go to the library's checks
    if (.not. n_max <= 0.0_dp) options%n_max = n_max
    if (.not. resolution <= 0.0_dp) options%resolution = resolution
    ! the C API reports the first root and the first interval: the scan stops there
    options%first_only = .true.
    nroots_options = .true.
  end function nroots_options

  !> int demstep_n_roots(double lambda, double tolerance, int steps_kind, double steps_value,
  !>   int pick, double n_max, double resolution, demstep_nroots *result, demstep_error *err)
  function c_n_roots(lambda, tolerance, steps_kind, steps_value, pick, n_max, resolution, result, &
      err) result(code) bind(C, name="demstep_n_roots")
    real(c_double), value :: lambda, tolerance, steps_value, n_max, resolution
    integer(c_int), value :: steps_kind, pick
    type(c_ptr), value :: result, err
    integer(c_int) :: code
    type(nroots_options_type) :: options
    type(nroots_type) :: r
    type(demstep_status_type) :: status
    type(demstep_nroots_c), pointer :: out
    type(demstep_nroots_c) :: row
    if (.not. c_associated(result)) then
      code = invalid(err, "demstep_n_roots: result is NULL")
      return
    end if
    if (.not. nroots_options(tolerance, steps_kind, steps_value, pick, n_max, resolution, options, &
      err, code)) return
    call n_roots(lambda, options, r, status)
    if (status%stat /= demstep_stat%ok) status%message = "demstep_n_roots: "//status%message
    code = report(err, status)
    if (code /= demstep_stat%ok) return
    row = demstep_nroots_c(r%n_pick, 0.0_dp, 0.0_dp, 0.0_dp, r%last_interval, r%stat, r%evaluations)
    if (size(r%roots) > 0) row%n_zero = r%roots(1)
    if (size(r%lower) > 0) then
      row%n_lower = r%lower(1)
      row%n_upper = r%upper(1)
    end if
    call guard_finite([row%n_pick, row%n_zero, row%n_lower, row%n_upper], "demstep_n_roots", err, code)
    if (code /= demstep_stat%ok) return
    call c_f_pointer(result, out)
    out = row
  end function c_n_roots

  !> int demstep_simulated_stiffness(double mass, double stiffness, double tolerance,
  !>   const double *lambdas, int n_lambdas, int steps_kind, double steps_value, int pick,
  !>   int aggregate, const double *weights, double *n_pick, int *row_status,
  !>   demstep_stiffness_result *result, demstep_error *err)
  function c_simulated_stiffness(mass, stiffness, tolerance, lambdas, n_lambdas, steps_kind, &
      steps_value, pick, aggregate, weights, n_pick, row_status, result, err) result(code) &
      bind(C, name="demstep_simulated_stiffness")
    real(c_double), value :: mass, stiffness, tolerance, steps_value
    integer(c_int), value :: n_lambdas, steps_kind, pick, aggregate
    type(c_ptr), value :: lambdas, weights, n_pick, row_status, result, err
    integer(c_int) :: code
    type(stiffness_input_type) :: input
    type(stiffness_result_type) :: r
    type(demstep_status_type) :: status
    real(c_double), pointer :: lam(:), w(:), picks(:)
    integer(c_int), pointer :: stats(:)
    type(demstep_stiffness_result_c), pointer :: out
    if (n_lambdas < 1) then
      code = invalid(err, "demstep_simulated_stiffness: n_lambdas must be >= 1")
      return
    end if
    if (.not. (c_associated(lambdas) .and. c_associated(result))) then
      code = invalid(err, "demstep_simulated_stiffness: lambdas or result is NULL")
      return
    end if
    if (.not. nroots_options(tolerance, steps_kind, steps_value, pick, 0.0_dp, 0.0_dp, &
      input%options, err, code)) return
    call c_f_pointer(lambdas, lam, [n_lambdas])
    input%mass = mass
    input%stiffness = stiffness
    input%lambdas = lam
    input%aggregate = int(aggregate)
    if (c_associated(weights)) then
      call c_f_pointer(weights, w, [n_lambdas])
      input%weights = w
    end if
    call simulated_stiffness(input, r, status)
    if (status%stat /= demstep_stat%ok) status%message = "demstep_simulated_stiffness: "//status%message
    code = report(err, status)
    if (code == demstep_stat%ok) call guard_finite([r%n_star, r%lambda_star, r%period, r%dt, r%stiffness_actual, &
      r%rows%n_pick], "demstep_simulated_stiffness", err, code)
    if (code /= demstep_stat%ok) return
    call c_f_pointer(result, out)
    out = demstep_stiffness_result_c(r%n_star, r%lambda_star, r%period, r%dt, r%stiffness_actual, &
      r%lambda_star_stat, r%excluded)
    if (c_associated(n_pick)) then
      call c_f_pointer(n_pick, picks, [n_lambdas])
      picks = r%rows%n_pick
    end if
    if (c_associated(row_status)) then
      call c_f_pointer(row_status, stats, [n_lambdas])
      stats = r%rows%stat
    end if
  end function c_simulated_stiffness

  !> int demstep_scene_critical_step(int dim, int n, const double *x, const double *mass,
  !>   const double *radius, const int *fixed, int n_bonds, const int *bonds, double k_bond,
  !>   double k_bond_tangential, int law, double k_normal, double e_star, int effects,
  !>   double damping_ratio, demstep_critical_step *result, demstep_error *err)
  function c_scene_critical_step(dim, n, x, mass, radius, fixed, n_bonds, bonds, k_bond, &
      k_bond_tangential, law, k_normal, e_star, effects, damping_ratio, result, err) result(code) &
      bind(C, name="demstep_scene_critical_step")
    integer(c_int), value :: dim, n, n_bonds, law, effects
    real(c_double), value :: k_bond, k_bond_tangential, k_normal, e_star, damping_ratio
    type(c_ptr), value :: x, mass, radius, fixed, bonds, result, err
    integer(c_int) :: code
    real(c_double), pointer :: px(:, :), pm(:), pr(:)
    integer(c_int), pointer :: pf(:), pb(:, :)
    type(scene_type) :: scene
    type(critical_step_type) :: c
    type(demstep_status_type) :: status
    type(demstep_critical_step_c), pointer :: out
    integer :: k
    if (dim < 1 .or. dim > 3 .or. n < 1 .or. n_bonds < 0) then
      code = invalid(err, "demstep_scene_critical_step: need 1 <= dim <= 3, n >= 1, n_bonds >= 0")
      return
    end if
    if (.not. (c_associated(x) .and. c_associated(mass) .and. c_associated(radius) .and. &
        c_associated(result))) then
      code = invalid(err, "demstep_scene_critical_step: x, mass, radius or result is NULL")
      return
    end if
    if (n_bonds > 0 .and. .not. c_associated(bonds)) then
      code = invalid(err, "demstep_scene_critical_step: bonds is NULL")
      return
    end if
    call c_f_pointer(x, px, [dim, n])
    call c_f_pointer(mass, pm, [n])
    call c_f_pointer(radius, pr, [n])
    if (c_associated(fixed)) then
      call c_f_pointer(fixed, pf, [n])
      call new_scene(scene, int(dim), px, pm, pr, status, fixed=pf /= 0)
    else
      call new_scene(scene, int(dim), px, pm, pr, status)
    end if
    code = report(err, status)
    if (code /= demstep_stat%ok) return
    if (n_bonds > 0) then
      call c_f_pointer(bonds, pb, [2, n_bonds])
      call scene_add_bonds(scene, pb + 1, status)
      code = report(err, status)
      if (code /= demstep_stat%ok) return
    end if
    if (.not. all(ieee_is_finite([k_bond, k_bond_tangential, k_normal, e_star, damping_ratio]))) then
      code = invalid(err, "demstep_scene_critical_step: stiffnesses and damping must be finite")
      return
    end if
    scene%k_bond = k_bond
    scene%k_bond_tangential = k_bond_tangential
    scene%law = int(law)
    scene%k_normal = k_normal
    scene%e_star = e_star
    scene%damping_ratio = damping_ratio
    do k = 1, n_effects
      scene%effects(k) = btest(effects, k - 1)
    end do
    call assembly_critical_steps(scene, c, status)
    code = report(err, status)
    call guard_finite([c%omega_max, c%dt_critical_eigen, c%omega_bound, c%dt_critical_bound, &
      c%dt_contact_rule, c%damping_ratio_top, c%dt_critical_damped], "demstep_scene_critical_step", err, code)
    if (code /= demstep_stat%ok) return
    call c_f_pointer(result, out)
    out = demstep_critical_step_c(c%omega_max, c%dt_critical_eigen, c%omega_bound, c%dt_critical_bound, &
      c%dt_contact_rule, c%damping_ratio_top, c%dt_critical_damped, c%n_dof, c%n_springs, &
      merge(1, 0, c%eigen_computed))
  end function c_scene_critical_step

  !> int demstep_contact_with_onset(double n_per_period, double onset, double damping_ratio,
  !>   demstep_contact *contact, demstep_error *err)
  function c_contact_with_onset(n_per_period, onset, damping_ratio, contact, err) result(code) &
      bind(C, name="demstep_contact_with_onset")
    real(c_double), value :: n_per_period, onset, damping_ratio
    type(c_ptr), value :: contact, err
    integer(c_int) :: code
    type(discrete_contact_type) :: c
    type(demstep_status_type) :: status
    type(demstep_contact_c), pointer :: out
    if (.not. c_associated(contact)) then
      code = invalid(err, "demstep_contact_with_onset: contact is NULL")
      return
    end if
    call contact_with_onset(n_per_period, onset, c, status, damping_ratio)
    code = report(err, status)
    call guard_finite([c%onset, c%contact_time, c%restitution, c%max_overlap], &
      "demstep_contact_with_onset", err, code)
    if (code /= demstep_stat%ok) return
    call c_f_pointer(contact, out)
    out = demstep_contact_c(c%onset, c%contact_time, c%restitution, c%max_overlap, &
      int(c%steps, c_int64_t), merge(1, 0, c%stable))
  end function c_contact_with_onset

  !> int demstep_n_for_tolerance(int quantity, double tolerance, double damping_ratio,
  !>   double n_max, double *n, demstep_error *err)
  function c_n_for_tolerance(quantity, tolerance, damping_ratio, n_max, n, err) result(code) &
      bind(C, name="demstep_n_for_tolerance")
    integer(c_int), value :: quantity
    real(c_double), value :: tolerance, damping_ratio, n_max
    type(c_ptr), value :: n, err
    integer(c_int) :: code
    type(demstep_status_type) :: status
    real(c_double), pointer :: out
    real(dp) :: value, top
    if (.not. c_associated(n)) then
      code = invalid(err, "demstep_n_for_tolerance: n is NULL")
      return
    end if
    if (.not. (ieee_is_finite(damping_ratio) .and. damping_ratio >= 0.0_dp)) then
      code = invalid(err, "demstep_n_for_tolerance: damping_ratio must be finite and >= 0")
      return
    end if
    top = 1.0e7_dp
    if (.not. n_max <= 0.0_dp) top = n_max
    call n_for_tolerance(int(quantity), tolerance, value, status, damping_ratio=damping_ratio, n_max=top)
    code = report(err, status)
    call guard_finite([value], "demstep_n_for_tolerance", err, code)
    if (code /= demstep_stat%ok) return
    call c_f_pointer(n, out)
    out = value
  end function c_n_for_tolerance

end module demstep_capi
