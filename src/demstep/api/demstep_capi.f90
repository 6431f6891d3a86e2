!> The C API of demstep (bind(C)), declared in include/demstep.h.
!>
!> Every function returns a status code (0 on success, the codes of
!> `demstep_stat` otherwise) and, when `err` is not NULL, fills it with the code
!> and a NUL-terminated message. Pointers to outputs must not be NULL; arrays
!> are passed with their lengths; particle and bond numbers are 0-based.
!>
!> Scenes are opaque handles (`demstep_scene *`): a `capi_scene_type` allocated
!> by demstep_scene_create and passed to C by `c_loc`, filled call by call
!> through the library's builders (which check the values; this module checks
!> pointers, counts and the enum values the library takes as plain integers, and
!> maps statuses), computed by demstep_scene_compute and freed by
!> demstep_scene_free, which also sets the caller's pointer to NULL.
module demstep_capi
  use, intrinsic :: iso_c_binding, only: c_int, c_double, c_int64_t, c_char, c_ptr, c_null_char, &
    c_associated, c_f_pointer, c_loc, c_null_ptr, c_size_t
  use, intrinsic :: ieee_arithmetic, only: ieee_is_finite, ieee_is_nan
  use demstep_kinds, only: dp, i8
  use demstep_status, only: demstep_status_type, demstep_stat, set_status
  use demstep_spring, only: spring_type, spring_state_type, new_spring, spring_step, critical_time_step
  use demstep_harmonic, only: harmonic_error, step_policy_type, new_step_policy, step_kind
  use demstep_stiffness, only: nroots_options_type, nroots_type, n_roots, stiffness_input_type, &
    stiffness_result_type, simulated_stiffness
  use demstep_text, only: int_text
  use demstep_scene_data, only: scene_type, n_effects, scene_effect, scene_effect_names
  use demstep_scene_builders, only: new_scene, scene_add_bonds, scene_add_walls, scene_set_contacts, &
    scene_set_cell, scene_set_types, scene_set_hertz_types, scene_set_law, scene_set_bond_stiffness, &
    scene_set_gravity, scene_set_damping, scene_set_rolling
  use demstep_interaction, only: contact_law
  use demstep_material, only: material_type, material_pair_type, effective_pair_type, effective_pair, &
    contact_parameters_type, contact_parameters, convention_limit, peer_steps_type, peer_time_steps, &
    n_peer_rules, code_convention
  use demstep_scene_materials, only: scene_set_materials
  use demstep_assembly, only: critical_step_type, assembly_critical_steps, hertz_linearization, &
    default_max_eigen_dof, eigen_solver
  use demstep_lanczos, only: lanczos_tolerance_default, check_lanczos_options
  use demstep_contact, only: discrete_contact_type, contact_with_onset
  use demstep_monitor, only: solver_critical_steps, step_monitor_type, mode_participation
  use demstep_cost, only: n_for_tolerance
  use demstep_snapshot, only: snapshot_type, snapshot_format, read_snapshot
  use demstep_scene_bonds, only: scene_set_bond_model
  use demstep_bodies, only: body_set_type, bodies_from_members, bodies_given
  use demstep_body_assembly, only: body_critical_steps, body_gst_step, body_exadem_step
  implicit none
  private

  !> Length of the message buffer of demstep_error (with the NUL).
  integer, parameter, public :: capi_message_length = 256

  !> Length of the location buffer of demstep_error (with the NUL).
  integer, parameter, public :: capi_where_length = 64

  !> struct demstep_error.
  type, bind(C), public :: demstep_error_c
    integer(c_int) :: stat
    character(kind=c_char) :: message(capi_message_length)
    character(kind=c_char) :: where(capi_where_length)
    !> 0-based element or row of `where`, -1 for none.
    integer(c_int) :: index
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

  !> struct demstep_contact.
  type, bind(C), public :: demstep_contact_c
    real(c_double) :: onset, contact_time, restitution, max_overlap
    integer(c_int64_t) :: steps
    integer(c_int) :: stable
  end type demstep_contact_c

  !> The scene behind a `demstep_scene *` handle. Live from demstep_scene_create
  !> to demstep_scene_free; `failure` holds the message of the first builder call
  !> that failed (the handle is unusable from then on).
  type, public :: capi_scene_type
    !> `scene_tag` while the handle is live.
    integer :: tag = 0
    !> Whether demstep_scene_set_particles succeeded.
    logical :: has_particles = .false.
    !> The law named by demstep_scene_set_contact_law and the law of the
    !> per-type materials (0: none yet): they must agree.
    integer :: law_given = 0, types_law = 0
    character(len=:), allocatable :: failure
    !> The eigensolver and Lanczos tolerance of demstep_scene_set_eigen_solver.
    integer :: solver = eigen_solver%auto
    real(dp) :: tolerance = lanczos_tolerance_default
    !> The library scene every builder call goes to.
    type(scene_type) :: scene
    !> The rigid bodies of demstep_scene_set_bodies (when has_bodies).
    logical :: has_bodies = .false.
    type(body_set_type) :: bodies
  end type capi_scene_type

  !> Marks a live handle (a pointer that is not one is refused, not followed further).
  integer, parameter :: scene_tag = 31415926

  !> The C effect flags (powers of two, fixed by the header): `capi_effect%walls`.
  type, public :: capi_effect_enum
    integer(c_int) :: contacts = 1, gravity = 2, damping = 4, local_damping = 8, walls = 16, rotation = 32
  end type capi_effect_enum
  !> The C effect flags by name.
  type(capi_effect_enum), parameter, public :: capi_effect = capi_effect_enum()
  !> Each C flag and the library effect it switches on (independent of the
  !> library's index order).
  integer, parameter, public :: capi_effect_map(2, n_effects) = reshape([ &
    capi_effect%contacts, scene_effect%contacts, capi_effect%gravity, scene_effect%gravity, &
    capi_effect%damping, scene_effect%damping, capi_effect%local_damping, scene_effect%local_damping, &
    capi_effect%walls, scene_effect%walls, capi_effect%rotation, scene_effect%rotation], [2, n_effects])

  !> struct demstep_scene_result: fields are only ever appended (the caller
  !> passes the size it knows; see c_scene_compute).
  type, bind(C), public :: demstep_scene_result_c
    real(c_double) :: omega_max = 0.0_dp, dt_critical_eigen = 0.0_dp, omega_bound = 0.0_dp, &
      dt_critical_bound = 0.0_dp, dt_contact_rule = 0.0_dp, damping_ratio_top = 0.0_dp, &
      dt_critical_damped = 0.0_dp
    integer(c_int) :: n_dof = 0, n_springs = 0, dof_per_particle = 0, eigen_computed = 0, rotation = 0, &
      tangential = 0, periodic = 0, prestress = 0
    ! appended in version 2: the eigensolver's report
    real(c_double) :: eigen_tolerance = 0.0_dp, eigen_residual = 0.0_dp, omega_upper = 0.0_dp, &
      dt_critical_safe = 0.0_dp
    integer(c_int64_t) :: eigen_products = 0
    integer(c_int) :: eigen_solver = 0, eigen_converged = 0
    ! appended in version 3: the exact damped limit
    real(c_double) :: dt_critical_damped_bound = 0.0_dp
    integer(c_int) :: damped_exact = 0, damped_solves = 0
  end type demstep_scene_result_c

  !> sizeof(demstep_scene_result) of the first version: the least result_size accepted.
  integer(c_size_t), parameter, public :: capi_scene_result_size_v1 = 7*8 + 8*4

  !> The snapshot behind a `demstep_snapshot *` handle (demstep_snapshot_read
  !> to demstep_snapshot_free).
  type, public :: capi_snapshot_type
    !> `snapshot_tag` while the handle is live.
    integer :: tag = 0
    !> The snapshot read.
    type(snapshot_type) :: snapshot
  end type capi_snapshot_type

  !> Marks a live snapshot handle.
  integer, parameter :: snapshot_tag = 27182818

  !> The longest path demstep_snapshot_read takes (with its NUL).
  integer, parameter :: capi_path_length = 4096

  !> struct demstep_snapshot_info.
  type, bind(C), public :: demstep_snapshot_info_c
    integer(c_int) :: n = 0, format = 0, frame = 0, n_frames = 0
    integer(c_int64_t) :: timestep = 0
    integer(c_int) :: has_velocity = 0, has_omega = 0, has_mass = 0, has_density = 0, has_box = 0
    integer(c_int) :: periodic(3) = 0
    real(c_double) :: lo(3) = 0.0_dp, hi(3) = 0.0_dp
  end type demstep_snapshot_info_c

  !> struct demstep_material.
  type, bind(C), public :: demstep_material_c
    real(c_double) :: young = 0.0_dp, poisson = 0.0_dp, density = 0.0_dp, radius = 0.0_dp
  end type demstep_material_c

  !> struct demstep_material_pair.
  type, bind(C), public :: demstep_material_pair_c
    type(demstep_material_c) :: a, b
    real(c_double) :: restitution = 1.0_dp, restitution_t = 0.0_dp, impact_velocity = 1.0_dp, &
      contact_time = 0.0_dp, stiffness = 0.0_dp
  end type demstep_material_pair_c

  !> struct demstep_code_contact.
  type, bind(C), public :: demstep_code_contact_c
    real(c_double) :: k_n = 0.0_dp, k_t = 0.0_dp, gamma_n = 0.0_dp, gamma_t = 0.0_dp, overlap = 0.0_dp, &
      t_contact = 0.0_dp, code_collision_time = 0.0_dp, m_star = 0.0_dp, dt_code = 0.0_dp
  end type demstep_code_contact_c

  !> struct demstep_peer_steps.
  type, bind(C), public :: demstep_peer_steps_c
    real(c_double) :: rayleigh = 0.0_dp, rayleigh_yade = 0.0_dp, hertz_duration = 0.0_dp, &
      hertz_liggghts = 0.0_dp
    real(c_double) :: dt(n_peer_rules) = 0.0_dp
  end type demstep_peer_steps_c

  public :: c_contact_with_onset, c_n_for_tolerance
  public :: c_spring_new, c_spring_step, c_critical_time_step, c_harmonic_error, c_n_roots, &
    c_simulated_stiffness
  public :: c_scene_set_bond_model, c_scene_set_bodies, c_scene_body_peer_steps
  public :: c_scene_create, c_scene_free, c_scene_set_particles, c_scene_add_bonds, &
    c_scene_set_bond_stiffness, c_scene_set_contact_law, c_scene_set_types, c_scene_set_hertz_types, &
    c_scene_add_walls, c_scene_set_contacts, c_scene_set_effects, c_scene_set_cell, c_scene_set_damping, &
    c_scene_set_dashpots, c_scene_set_rolling, c_scene_set_materials, &
    c_scene_set_gravity, c_scene_compute, c_scene_set_eigen_solver, c_solver_compute, &
    c_solver_participation
  public :: c_snapshot_read, c_snapshot_get, c_snapshot_free
  public :: c_contact_parameters, c_peer_time_steps

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
    e%where = c_null_char
    e%index = int(status%index - 1, c_int)
    if (allocated(status%where)) then
      n = min(len(status%where), capi_where_length - 1)
      do i = 1, n
        e%where(i) = status%where(i:i)
      end do
    end if
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
      call set_status(status, stat, "a pole, S(2 pi lambda/N, n) = 0", where="demstep_harmonic_error")
      code = report(err, status)
    else
      call set_status(status, stat, "N, lambda must be finite and > 0, " &
        //"1 <= n_steps <= 1e12", where="demstep_harmonic_error")
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
      ! the library names `steps:` for an unknown kind, the value's name otherwise
      if (status%where == "steps") then
        code = invalid(err, "steps_kind: "//int_text(steps_kind)//" is not DEMSTEP_STEPS_FIXED (" &
          //int_text(step_kind%fixed)//"), DEMSTEP_STEPS_FRACTION ("//int_text(step_kind%fraction) &
          //") or DEMSTEP_STEPS_ROUNDED ("//int_text(step_kind%rounded)//")")
      else
        code = invalid(err, "steps_value: step policy kind 1 (fixed, 1 <= n <= 1e12), 2 (fraction " &
          //"f > 0) or 3 (rounded f > 0)")
      end if
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

  !> The live handle behind `scene`, or .false. with the error reported: NULL,
  !> not a handle, a handle left unusable by a failed builder call, or (when
  !> `particles`) no particles yet.
  logical function live(scene, name, h, err, code, particles)
    type(c_ptr), intent(in) :: scene, err
    character(len=*), intent(in) :: name
    type(capi_scene_type), pointer, intent(out) :: h
    integer(c_int), intent(out) :: code
    logical, intent(in) :: particles
    live = .false.
    h => null()
    code = demstep_stat%ok
    if (.not. c_associated(scene)) then
      code = invalid(err, name//": scene is NULL")
      return
    end if
    call c_f_pointer(scene, h)
    if (h%tag /= scene_tag) then
      code = invalid(err, name//": scene is not a live handle of demstep_scene_create")
      h => null()
      return
    end if
    if (allocated(h%failure)) then
      code = invalid(err, name//": the scene is unusable since a call failed ("//h%failure// &
        "): free it and build it again")
      return
    end if
    if (particles .and. .not. h%has_particles) then
      code = invalid(err, name//": the scene has no particles yet: call demstep_scene_set_particles first")
      return
    end if
    live = .true.
  end function live

  !> Report the status of a builder call on `h`; a failure leaves the handle unusable.
  function built(h, name, status, err) result(code)
    type(capi_scene_type), intent(inout) :: h
    character(len=*), intent(in) :: name
    type(demstep_status_type), intent(inout) :: status
    type(c_ptr), intent(in) :: err
    integer(c_int) :: code
    if (status%stat /= demstep_stat%ok) then
      status%message = name//": "//status%message
      h%failure = status%message
    end if
    code = report(err, status)
  end function built

  !> A builder's own refusal (a NULL array, a bad count): reported, and the handle unusable.
  function refused(h, name, message, err) result(code)
    type(capi_scene_type), intent(inout) :: h
    character(len=*), intent(in) :: name, message
    type(c_ptr), intent(in) :: err
    integer(c_int) :: code
    type(demstep_status_type) :: status
    call set_status(status, demstep_stat%invalid_input, message)
    code = built(h, name, status, err)
  end function refused

  !> int demstep_scene_create(int dim, demstep_scene **scene, demstep_error *err)
  function c_scene_create(dim, scene, err) result(code) bind(C, name="demstep_scene_create")
    integer(c_int), value :: dim
    type(c_ptr), value :: scene, err
    integer(c_int) :: code
    type(c_ptr), pointer :: out
    type(capi_scene_type), pointer :: h
    type(demstep_status_type) :: status
    real(dp), allocatable :: none(:, :)
    if (.not. c_associated(scene)) then
      code = invalid(err, "demstep_scene_create: scene is NULL")
      return
    end if
    call c_f_pointer(scene, out)
    out = c_null_ptr
    ! the library checks dim (a scene without particles)
    allocate(none(max(0, int(dim)), 0))
    allocate(h)
    call new_scene(h%scene, int(dim), none, [real(dp) ::], [real(dp) ::], status)
    if (status%stat /= demstep_stat%ok) then
      status%message = "demstep_scene_create: "//status%message
      code = report(err, status)
      deallocate(h)
      return
    end if
    h%tag = scene_tag
    out = c_loc(h)
    code = ok(err)
  end function c_scene_create

  !> int demstep_scene_free(demstep_scene **scene, demstep_error *err)
  function c_scene_free(scene, err) result(code) bind(C, name="demstep_scene_free")
    type(c_ptr), value :: scene, err
    integer(c_int) :: code
    type(c_ptr), pointer :: handle
    type(capi_scene_type), pointer :: h
    code = ok(err)
    if (.not. c_associated(scene)) return
    call c_f_pointer(scene, handle)
    if (.not. c_associated(handle)) return
    call c_f_pointer(handle, h)
    if (h%tag /= scene_tag) then
      code = invalid(err, "demstep_scene_free: *scene is not a live handle of demstep_scene_create")
      return
    end if
    h%tag = 0
    deallocate(h)
    handle = c_null_ptr
  end function c_scene_free

  !> int demstep_scene_set_particles(demstep_scene *scene, int n, const double *x,
  !>   const double *mass, const double *radius, const int *fixed, const double *inertia,
  !>   const double *velocity, demstep_error *err)
  function c_scene_set_particles(scene, n, x, mass, radius, fixed, inertia, velocity, err) result(code) &
      bind(C, name="demstep_scene_set_particles")
    type(c_ptr), value :: scene, x, mass, radius, fixed, inertia, velocity, err
    integer(c_int), value :: n
    integer(c_int) :: code
    character(len=*), parameter :: name = "demstep_scene_set_particles"
    type(capi_scene_type), pointer :: h
    real(c_double), pointer :: px(:, :), pm(:), pr(:), pin(:), pv(:, :)
    integer(c_int), pointer :: pf(:)
    logical, allocatable :: is_fixed(:)
    real(dp), allocatable :: v(:, :), inert(:)
    type(demstep_status_type) :: status
    integer :: dim
    if (.not. live(scene, name, h, err, code, particles=.false.)) return
    if (h%has_particles) then
      code = refused(h, name, "the particles are already set (once per scene)", err)
      return
    end if
    if (n < 1) then
      code = refused(h, name, "n: must be >= 1", err)
      return
    end if
    if (.not. (c_associated(x) .and. c_associated(mass) .and. c_associated(radius))) then
      code = refused(h, name, "x, mass or radius is NULL", err)
      return
    end if
    dim = h%scene%dim
    call c_f_pointer(x, px, [dim, int(n)])
    call c_f_pointer(mass, pm, [n])
    call c_f_pointer(radius, pr, [n])
    allocate(is_fixed(n), source=.false.)
    if (c_associated(fixed)) then
      call c_f_pointer(fixed, pf, [n])
      is_fixed = pf /= 0
    end if
    allocate(v(dim, n), source=0.0_dp)
    if (c_associated(velocity)) then
      call c_f_pointer(velocity, pv, [dim, int(n)])
      v = pv
    end if
    if (c_associated(inertia)) then
      call c_f_pointer(inertia, pin, [n])
      inert = pin
      call new_scene(h%scene, dim, px, pm, pr, status, v=v, fixed=is_fixed, inertia=inert)
    else
      call new_scene(h%scene, dim, px, pm, pr, status, v=v, fixed=is_fixed)
    end if
    h%has_particles = status%stat == demstep_stat%ok
    code = built(h, name, status, err)
  end function c_scene_set_particles

  !> int demstep_scene_add_bonds(demstep_scene *scene, int n_bonds, const int *bonds,
  !>   demstep_error *err)
  function c_scene_add_bonds(scene, n_bonds, bonds, err) result(code) bind(C, name="demstep_scene_add_bonds")
    type(c_ptr), value :: scene, bonds, err
    integer(c_int), value :: n_bonds
    integer(c_int) :: code
    character(len=*), parameter :: name = "demstep_scene_add_bonds"
    type(capi_scene_type), pointer :: h
    integer(c_int), pointer :: pb(:, :)
    type(demstep_status_type) :: status
    if (.not. live(scene, name, h, err, code, particles=.true.)) return
    if (n_bonds < 1 .or. .not. c_associated(bonds)) then
      code = refused(h, name, "n_bonds must be >= 1 and bonds not NULL", err)
      return
    end if
    call c_f_pointer(bonds, pb, [2, int(n_bonds)])
    call scene_add_bonds(h%scene, pb + 1, status)
    code = built(h, name, status, err)
  end function c_scene_add_bonds

  !> int demstep_scene_set_bond_stiffness(demstep_scene *scene, double k_bond,
  !>   double k_bond_tangential, demstep_error *err)
  function c_scene_set_bond_stiffness(scene, k_bond, k_bond_tangential, err) result(code) &
      bind(C, name="demstep_scene_set_bond_stiffness")
    type(c_ptr), value :: scene, err
    real(c_double), value :: k_bond, k_bond_tangential
    integer(c_int) :: code
    character(len=*), parameter :: name = "demstep_scene_set_bond_stiffness"
    type(capi_scene_type), pointer :: h
    type(demstep_status_type) :: status
    if (.not. live(scene, name, h, err, code, particles=.false.)) return
    call scene_set_bond_stiffness(h%scene, k_bond, k_bond_tangential, status)
    code = built(h, name, status, err)
  end function c_scene_set_bond_stiffness

  !> int demstep_scene_set_contact_law(demstep_scene *scene, int law, double normal,
  !>   double tangential, demstep_error *err)
  function c_scene_set_contact_law(scene, law, normal, tangential, err) result(code) &
      bind(C, name="demstep_scene_set_contact_law")
    type(c_ptr), value :: scene, err
    integer(c_int), value :: law
    real(c_double), value :: normal, tangential
    integer(c_int) :: code
    character(len=*), parameter :: name = "demstep_scene_set_contact_law"
    type(capi_scene_type), pointer :: h
    type(demstep_status_type) :: status
    if (.not. live(scene, name, h, err, code, particles=.false.)) return
    call scene_set_law(h%scene, int(law), normal, tangential, status)
    if (status%stat == demstep_stat%ok .and. h%types_law /= 0 .and. h%types_law /= law) &
      call set_status(status, demstep_stat%invalid_input, "must be the law of the per-type materials", where="law")
    if (status%stat == demstep_stat%ok) h%law_given = int(law)
    code = built(h, name, status, err)
  end function c_scene_set_contact_law

  !> Per-type materials from C: `law` for the types of n particles (0-based).
  logical function types_from_c(h, name, law, n_types, types, ptypes, err, code)
    type(capi_scene_type), intent(inout) :: h
    character(len=*), intent(in) :: name
    integer, intent(in) :: law
    integer(c_int), intent(in) :: n_types
    type(c_ptr), intent(in) :: types, err
    integer, allocatable, intent(out) :: ptypes(:)
    integer(c_int), intent(out) :: code
    integer(c_int), pointer :: pt(:)
    types_from_c = .false.
    code = demstep_stat%ok
    if (h%law_given /= 0 .and. h%law_given /= law) then
      code = refused(h, name, "law: the scene's contact law (demstep_scene_set_contact_law) is " &
        //"another one", err)
      return
    end if
    if (n_types < 1 .or. .not. c_associated(types)) then
      code = refused(h, name, "n_types must be >= 1 and types not NULL", err)
      return
    end if
    call c_f_pointer(types, pt, [h%scene%n])
    ptypes = pt + 1
    types_from_c = .true.
  end function types_from_c

  !> int demstep_scene_set_types(demstep_scene *scene, int n_types, const int *types,
  !>   const double *k_normal, const double *k_tangential, demstep_error *err)
  function c_scene_set_types(scene, n_types, types, k_normal, k_tangential, err) result(code) &
      bind(C, name="demstep_scene_set_types")
    type(c_ptr), value :: scene, types, k_normal, k_tangential, err
    integer(c_int), value :: n_types
    integer(c_int) :: code
    character(len=*), parameter :: name = "demstep_scene_set_types"
    type(capi_scene_type), pointer :: h
    real(c_double), pointer :: kn(:, :), kt(:, :)
    integer, allocatable :: ptypes(:)
    real(dp), allocatable :: k(:, :, :)
    type(demstep_status_type) :: status
    integer :: fail
    if (.not. live(scene, name, h, err, code, particles=.true.)) return
    if (.not. types_from_c(h, name, contact_law%linear, n_types, types, ptypes, err, code)) return
    if (.not. c_associated(k_normal)) then
      code = refused(h, name, "k_normal is NULL", err)
      return
    end if
    ! n_types^2 pairs: a count beyond memory is refused, not a crash
    allocate(k(2, n_types, n_types), source=0.0_dp, stat=fail)
    if (fail /= 0) then
      code = refused(h, name, "n_types: "//int_text(n_types)//" types need "//int_text(n_types)// &
        "^2 type pairs: more than the memory holds", err)
      return
    end if
    call c_f_pointer(k_normal, kn, [n_types, n_types])
    k(1, :, :) = kn
    if (c_associated(k_tangential)) then
      call c_f_pointer(k_tangential, kt, [n_types, n_types])
      k(2, :, :) = kt
    end if
    call scene_set_types(h%scene, ptypes, k, status)
    if (status%stat == demstep_stat%ok) then
      h%scene%law = contact_law%linear
      h%types_law = contact_law%linear
    end if
    code = built(h, name, status, err)
  end function c_scene_set_types

  !> int demstep_scene_set_hertz_types(demstep_scene *scene, int n_types, const int *types,
  !>   const double *young, const double *poisson, demstep_error *err)
  function c_scene_set_hertz_types(scene, n_types, types, young, poisson, err) result(code) &
      bind(C, name="demstep_scene_set_hertz_types")
    type(c_ptr), value :: scene, types, young, poisson, err
    integer(c_int), value :: n_types
    integer(c_int) :: code
    character(len=*), parameter :: name = "demstep_scene_set_hertz_types"
    type(capi_scene_type), pointer :: h
    real(c_double), pointer :: py(:), pp(:)
    integer, allocatable :: ptypes(:)
    type(demstep_status_type) :: status
    if (.not. live(scene, name, h, err, code, particles=.true.)) return
    if (.not. types_from_c(h, name, contact_law%hertz, n_types, types, ptypes, err, code)) return
    if (.not. (c_associated(young) .and. c_associated(poisson))) then
      code = refused(h, name, "young or poisson is NULL", err)
      return
    end if
    call c_f_pointer(young, py, [n_types])
    call c_f_pointer(poisson, pp, [n_types])
    call scene_set_hertz_types(h%scene, ptypes, py, pp, status)
    if (status%stat == demstep_stat%ok) then
      h%scene%law = contact_law%hertz
      h%types_law = contact_law%hertz
    end if
    code = built(h, name, status, err)
  end function c_scene_set_hertz_types

  !> int demstep_scene_set_materials(demstep_scene *scene, int n_types, const int *types,
  !>   const double *young, const double *poisson, const double *density, const double *radius,
  !>   int convention, double restitution, double impact_velocity, int wall_type,
  !>   int tangential_damping, demstep_error *err)
  !> Materials per type (0-based types) in one code's convention into the
  !> scene's contacts and walls (`scene_set_materials`); wall_type -1: each
  !> particle's own type.
  function c_scene_set_materials(scene, n_types, types, young, poisson, density, radius, convention, &
      restitution, impact_velocity, wall_type, tangential_damping, err) result(code) &
      bind(C, name="demstep_scene_set_materials")
    type(c_ptr), value :: scene, types, young, poisson, density, radius, err
    integer(c_int), value :: n_types, convention, wall_type, tangential_damping
    real(c_double), value :: restitution, impact_velocity
    integer(c_int) :: code
    character(len=*), parameter :: name = "demstep_scene_set_materials"
    type(capi_scene_type), pointer :: h
    real(c_double), pointer :: py(:), pp(:), pd(:), pr(:)
    type(material_type), allocatable :: mats(:)
    integer, allocatable :: ptypes(:)
    type(demstep_status_type) :: status
    integer :: i
    if (.not. live(scene, name, h, err, code, particles=.true.)) return
    if (.not. types_from_c(h, name, h%law_given, n_types, types, ptypes, err, code)) return
    if (.not. (c_associated(young) .and. c_associated(poisson) .and. c_associated(density) .and. &
        c_associated(radius))) then
      code = refused(h, name, "young, poisson, density or radius is NULL", err)
      return
    end if
    if (tangential_damping /= 0 .and. tangential_damping /= 1) then
      code = refused(h, name, "tangential_damping: "//int_text(tangential_damping)//" is not 0 (off) or 1 (on)", &
        err)
      return
    end if
    call c_f_pointer(young, py, [n_types])
    call c_f_pointer(poisson, pp, [n_types])
    call c_f_pointer(density, pd, [n_types])
    call c_f_pointer(radius, pr, [n_types])
    allocate(mats(n_types))
    do i = 1, n_types
      mats(i) = material_type(young=py(i), poisson=pp(i), density=pd(i), radius=pr(i))
    end do
    call scene_set_materials(h%scene, ptypes, mats, int(convention), restitution, status, &
      impact_velocity=impact_velocity, wall_type=int(wall_type) + 1, tangential_damping=tangential_damping == 1)
    if (status%stat == demstep_stat%ok) h%types_law = h%scene%law
    code = built(h, name, status, err)
  end function c_scene_set_materials

  !> int demstep_scene_add_walls(demstep_scene *scene, int n_walls, const double *points,
  !>   const double *normals, demstep_error *err)
  function c_scene_add_walls(scene, n_walls, points, normals, err) result(code) &
      bind(C, name="demstep_scene_add_walls")
    type(c_ptr), value :: scene, points, normals, err
    integer(c_int), value :: n_walls
    integer(c_int) :: code
    character(len=*), parameter :: name = "demstep_scene_add_walls"
    type(capi_scene_type), pointer :: h
    real(c_double), pointer :: pp(:, :), pn(:, :)
    type(demstep_status_type) :: status
    if (.not. live(scene, name, h, err, code, particles=.true.)) return
    if (n_walls < 1 .or. .not. (c_associated(points) .and. c_associated(normals))) then
      code = refused(h, name, "n_walls must be >= 1 and points, normals not NULL", err)
      return
    end if
    call c_f_pointer(points, pp, [h%scene%dim, int(n_walls)])
    call c_f_pointer(normals, pn, [h%scene%dim, int(n_walls)])
    call scene_add_walls(h%scene, pp, pn, status)
    code = built(h, name, status, err)
  end function c_scene_add_walls

  !> int demstep_scene_set_contacts(demstep_scene *scene, int n_contacts, const int *pairs,
  !>   const double *k, demstep_error *err)
  function c_scene_set_contacts(scene, n_contacts, pairs, k, err) result(code) &
      bind(C, name="demstep_scene_set_contacts")
    type(c_ptr), value :: scene, pairs, k, err
    integer(c_int), value :: n_contacts
    integer(c_int) :: code
    character(len=*), parameter :: name = "demstep_scene_set_contacts"
    type(capi_scene_type), pointer :: h
    integer(c_int), pointer :: pp(:, :)
    real(c_double), pointer :: pk(:, :)
    type(demstep_status_type) :: status
    if (.not. live(scene, name, h, err, code, particles=.true.)) return
    if (n_contacts < 1 .or. .not. (c_associated(pairs) .and. c_associated(k))) then
      code = refused(h, name, "n_contacts must be >= 1 and pairs, k not NULL", err)
      return
    end if
    call c_f_pointer(pairs, pp, [2, int(n_contacts)])
    call c_f_pointer(k, pk, [2, int(n_contacts)])
    call scene_set_contacts(h%scene, pp + 1, pk, status)
    code = built(h, name, status, err)
  end function c_scene_set_contacts

  !> int demstep_scene_set_effects(demstep_scene *scene, int effects, demstep_error *err)
  function c_scene_set_effects(scene, effects, err) result(code) bind(C, name="demstep_scene_set_effects")
    type(c_ptr), value :: scene, err
    integer(c_int), value :: effects
    integer(c_int) :: code
    character(len=*), parameter :: name = "demstep_scene_set_effects"
    type(capi_scene_type), pointer :: h
    character(len=:), allocatable :: known
    integer :: b, k
    if (.not. live(scene, name, h, err, code, particles=.false.)) return
    do b = 0, bit_size(effects) - 1
      if (.not. btest(effects, b)) cycle
      if (any(capi_effect_map(1, :) == ishft(1_i8, b))) cycle
      known = ""
      do k = 1, n_effects
        known = known//", "//trim(scene_effect_names(capi_effect_map(2, k)))//" "//int_text(capi_effect_map(1, k))
      end do
      code = refused(h, name, "effects: bit "//int_text(b)//" (value "//int_text(ishft(1_i8, b))// &
        ") is not a DEMSTEP_EFFECT_* flag ("//known(3:)//")", err)
      return
    end do
    do k = 1, n_effects
      h%scene%effects(capi_effect_map(2, k)) = iand(effects, capi_effect_map(1, k)) /= 0
    end do
    code = ok(err)
  end function c_scene_set_effects

  !> int demstep_scene_set_cell(demstep_scene *scene, const int *periodic, const double *lo,
  !>   const double *hi, demstep_error *err)
  function c_scene_set_cell(scene, periodic, lo, hi, err) result(code) bind(C, name="demstep_scene_set_cell")
    type(c_ptr), value :: scene, periodic, lo, hi, err
    integer(c_int) :: code
    character(len=*), parameter :: name = "demstep_scene_set_cell"
    type(capi_scene_type), pointer :: h
    integer(c_int), pointer :: pp(:)
    real(c_double), pointer :: plo(:), phi(:)
    logical :: axes(3)
    real(dp) :: cell_lo(3), cell_hi(3)
    type(demstep_status_type) :: status
    integer :: dim
    if (.not. live(scene, name, h, err, code, particles=.true.)) return
    if (.not. (c_associated(periodic) .and. c_associated(lo) .and. c_associated(hi))) then
      code = refused(h, name, "periodic, lo or hi is NULL", err)
      return
    end if
    dim = h%scene%dim
    call c_f_pointer(periodic, pp, [dim])
    call c_f_pointer(lo, plo, [dim])
    call c_f_pointer(hi, phi, [dim])
    axes = .false.
    cell_lo = 0.0_dp
    cell_hi = 0.0_dp
    axes(:dim) = pp /= 0
    cell_lo(:dim) = plo
    cell_hi(:dim) = phi
    call scene_set_cell(h%scene, axes, cell_lo, cell_hi, status)
    code = built(h, name, status, err)
  end function c_scene_set_cell

  !> int demstep_scene_set_damping(demstep_scene *scene, double damping_ratio, demstep_error *err)
  function c_scene_set_damping(scene, damping_ratio, err) result(code) bind(C, name="demstep_scene_set_damping")
    type(c_ptr), value :: scene, err
    real(c_double), value :: damping_ratio
    integer(c_int) :: code
    type(capi_scene_type), pointer :: h
    type(demstep_status_type) :: status
    logical :: on
    if (.not. live(scene, "demstep_scene_set_damping", h, err, code, particles=.false.)) return
    ! the library's setter checks the range; the effect stays as the effects bits set it
    on = h%scene%effects(scene_effect%damping)
    call scene_set_damping(h%scene, damping_ratio, status)
    h%scene%effects(scene_effect%damping) = on
    code = built(h, "demstep_scene_set_damping", status, err)
  end function c_scene_set_damping

  !> int demstep_scene_set_dashpots(demstep_scene *scene, double tangential, double rolling,
  !>   double drag, demstep_error *err)
  function c_scene_set_dashpots(scene, tangential, rolling, drag, err) result(code) &
      bind(C, name="demstep_scene_set_dashpots")
    type(c_ptr), value :: scene, err
    real(c_double), value :: tangential, rolling, drag
    integer(c_int) :: code
    type(capi_scene_type), pointer :: h
    type(demstep_status_type) :: status
    logical :: on
    if (.not. live(scene, "demstep_scene_set_dashpots", h, err, code, particles=.false.)) return
    on = h%scene%effects(scene_effect%damping)
    call scene_set_damping(h%scene, h%scene%damping_ratio, status, tangential=tangential, rolling=rolling, &
      drag=drag)
    h%scene%effects(scene_effect%damping) = on
    code = built(h, "demstep_scene_set_dashpots", status, err)
  end function c_scene_set_dashpots

  !> int demstep_scene_set_rolling(demstep_scene *scene, double rolling_ratio, double twisting_ratio,
  !>   demstep_error *err)
  function c_scene_set_rolling(scene, rolling_ratio, twisting_ratio, err) result(code) &
      bind(C, name="demstep_scene_set_rolling")
    type(c_ptr), value :: scene, err
    real(c_double), value :: rolling_ratio, twisting_ratio
    integer(c_int) :: code
    type(capi_scene_type), pointer :: h
    type(demstep_status_type) :: status
    if (.not. live(scene, "demstep_scene_set_rolling", h, err, code, particles=.false.)) return
    call scene_set_rolling(h%scene, rolling_ratio, twisting_ratio, status)
    code = built(h, "demstep_scene_set_rolling", status, err)
  end function c_scene_set_rolling

  !> int demstep_scene_set_gravity(demstep_scene *scene, const double *gravity, demstep_error *err)
  function c_scene_set_gravity(scene, gravity, err) result(code) bind(C, name="demstep_scene_set_gravity")
    type(c_ptr), value :: scene, gravity, err
    integer(c_int) :: code
    character(len=*), parameter :: name = "demstep_scene_set_gravity"
    type(capi_scene_type), pointer :: h
    real(c_double), pointer :: pg(:)
    type(demstep_status_type) :: status
    if (.not. live(scene, name, h, err, code, particles=.false.)) return
    if (.not. c_associated(gravity)) then
      code = refused(h, name, "gravity is NULL", err)
      return
    end if
    call c_f_pointer(gravity, pg, [h%scene%dim])
    call scene_set_gravity(h%scene, pg, status)
    code = built(h, name, status, err)
  end function c_scene_set_gravity

  !> int demstep_scene_set_eigen_solver(demstep_scene *scene, int solver, double tolerance,
  !>   demstep_error *err)
  !>
  !> The eigensolver of later computes (DEMSTEP_EIGEN_AUTO, _DENSE, _LANCZOS,
  !> _NONE) and the Lanczos relative tolerance (<= 0: the default 1e-6). A
  !> refused option leaves the scene and its options as they were.
  function c_scene_set_eigen_solver(scene, solver, tolerance, err) result(code) &
      bind(C, name="demstep_scene_set_eigen_solver")
    type(c_ptr), value :: scene, err
    integer(c_int), value :: solver
    real(c_double), value :: tolerance
    integer(c_int) :: code
    character(len=*), parameter :: name = "demstep_scene_set_eigen_solver"
    type(capi_scene_type), pointer :: h
    type(demstep_status_type) :: status
    real(dp) :: tol
    if (.not. live(scene, name, h, err, code, particles=.false.)) return
    if (solver < eigen_solver%auto .or. solver > eigen_solver%none) then
      code = invalid(err, name//": solver: "//int_text(solver)//" is not DEMSTEP_EIGEN_AUTO (" &
        //int_text(eigen_solver%auto)//"), _DENSE, _LANCZOS or _NONE ("//int_text(eigen_solver%none)//")")
      return
    end if
    tol = lanczos_tolerance_default
    if (tolerance > 0.0_dp .or. ieee_is_nan(tolerance)) tol = tolerance
    call check_lanczos_options(name, tol, 1, 2, 1, status)
    if (status%stat /= demstep_stat%ok) then
      code = report(err, status)
      return
    end if
    h%solver = solver
    h%tolerance = tol
    code = ok(err)
  end function c_scene_set_eigen_solver

  !> int demstep_scene_set_bond_model(demstep_scene *scene, int model, int n_parameters,
  !>   const double *parameters, demstep_error *err)
  !>
  !> Every bond's law as a DEM code makes it (`scene_set_bond_model`:
  !> DEMSTEP_BOND_PFC, _MUSEN, _YADE, _LAMMPS) from its n_parameters inputs.
  function c_scene_set_bond_model(scene, model, n_parameters, parameters, err) result(code) &
      bind(C, name="demstep_scene_set_bond_model")
    type(c_ptr), value :: scene, parameters, err
    integer(c_int), value :: model, n_parameters
    integer(c_int) :: code
    character(len=*), parameter :: name = "demstep_scene_set_bond_model"
    type(capi_scene_type), pointer :: h
    real(c_double), pointer :: pp(:)
    type(demstep_status_type) :: status
    if (.not. live(scene, name, h, err, code, particles=.false.)) return
    if (n_parameters < 0 .or. (n_parameters > 0 .and. .not. c_associated(parameters))) then
      code = refused(h, name, "n_parameters must be >= 0 and parameters not NULL", err)
      return
    end if
    if (n_parameters > 0) then
      call c_f_pointer(parameters, pp, [n_parameters])
      call scene_set_bond_model(h%scene, int(model), pp, status)
    else
      call scene_set_bond_model(h%scene, int(model), [real(dp) ::], status)
    end if
    code = built(h, name, status, err)
  end function c_scene_set_bond_model

  !> int demstep_scene_set_bodies(demstep_scene *scene, const int *body_of, double density,
  !>   int n_bodies, const double *mass, const double *com, const double *inertia,
  !>   demstep_error *err)
  !>
  !> Rigid bodies of the particles (once per scene, after the particles): a
  !> body id per particle (0: alone). mass NULL: mass and tensor from the
  !> members (`bodies_from_members`; density > 0: the members' masses from
  !> it); else n_bodies bodies with ids 1..n_bodies given by mass, com (3 per
  !> body) and inertia (9 per body) (`bodies_given`).
  function c_scene_set_bodies(scene, body_of, density, n_bodies, mass, com, inertia, err) result(code) &
      bind(C, name="demstep_scene_set_bodies")
    type(c_ptr), value :: scene, body_of, mass, com, inertia, err
    real(c_double), value :: density
    integer(c_int), value :: n_bodies
    integer(c_int) :: code
    character(len=*), parameter :: name = "demstep_scene_set_bodies"
    type(capi_scene_type), pointer :: h
    integer(c_int), pointer :: pb(:)
    real(c_double), pointer :: pm(:), pc(:, :), pj(:, :, :)
    type(demstep_status_type) :: status
    if (.not. live(scene, name, h, err, code, particles=.true.)) return
    if (h%has_bodies) then
      code = refused(h, name, "the bodies are already set (once per scene)", err)
      return
    end if
    if (.not. c_associated(body_of)) then
      code = refused(h, name, "body_of is NULL", err)
      return
    end if
    call c_f_pointer(body_of, pb, [h%scene%n])
    if (.not. c_associated(mass)) then
      if (density > 0.0_dp .or. ieee_is_nan(density)) then
        call bodies_from_members(h%scene, pb, h%bodies, status, density=density)
      else
        call bodies_from_members(h%scene, pb, h%bodies, status)
      end if
    else
      if (n_bodies < 1 .or. .not. (c_associated(com) .and. c_associated(inertia))) then
        code = refused(h, name, "with mass: n_bodies must be >= 1 and com, inertia not NULL", err)
        return
      end if
      call c_f_pointer(mass, pm, [n_bodies])
      call c_f_pointer(com, pc, [3, int(n_bodies)])
      call c_f_pointer(inertia, pj, [3, 3, int(n_bodies)])
      call bodies_given(h%scene, pb, pm, pc, pj, h%bodies, status)
    end if
    h%has_bodies = status%stat == demstep_stat%ok
    code = built(h, name, status, err)
  end function c_scene_set_bodies

  !> int demstep_scene_body_peer_steps(const demstep_scene *scene, double *yade_gst,
  !>   double *exadem, demstep_error *err)
  !>
  !> The peers' rules on the scene's bodies, raw: Yade's
  !> GlobalStiffnessTimeStepper (`body_gst_step`) and exaDEM's
  !> (`body_exadem_step`).
  function c_scene_body_peer_steps(scene, yade_gst, exadem, err) result(code) &
      bind(C, name="demstep_scene_body_peer_steps")
    type(c_ptr), value :: scene, yade_gst, exadem, err
    integer(c_int) :: code
    character(len=*), parameter :: name = "demstep_scene_body_peer_steps"
    type(capi_scene_type), pointer :: h
    real(c_double), pointer :: pg, px
    type(demstep_status_type) :: status
    real(dp) :: dt(2)
    if (.not. live(scene, name, h, err, code, particles=.true.)) return
    if (.not. c_associated(yade_gst)) then
      code = invalid(err, name//": yade_gst is NULL")
      return
    end if
    if (.not. c_associated(exadem)) then
      code = invalid(err, name//": exadem is NULL")
      return
    end if
    if (.not. h%has_bodies) then
      code = invalid(err, name//": the scene has no bodies: call demstep_scene_set_bodies first")
      return
    end if
    call body_gst_step(h%scene, h%bodies, dt(1), status)
    if (status%stat == demstep_stat%ok) call body_exadem_step(h%scene, h%bodies, dt(2), status)
    if (status%stat /= demstep_stat%ok) status%message = name//": "//status%message
    code = report(err, status)
    call guard_finite(dt, name, err, code)
    if (code /= demstep_stat%ok) return
    call c_f_pointer(yade_gst, pg)
    call c_f_pointer(exadem, px)
    pg = dt(1)
    px = dt(2)
  end function c_scene_body_peer_steps

  !> int demstep_scene_compute(const demstep_scene *scene, int hertz_linearization,
  !>   double impact_velocity, int prestress, int max_eigen_dof, demstep_scene_result *result,
  !>   size_t result_size, demstep_error *err)
  !>
  !> The first min(result_size, sizeof) bytes of the result are written (any
  !> more are zeroed), so a program built against an older header, whose struct
  !> lacks fields appended since, gets the fields it knows.
  function c_scene_compute(scene, hertz_mode, impact_velocity, prestress, max_eigen_dof, result, &
      result_size, err) result(code) bind(C, name="demstep_scene_compute")
    type(c_ptr), value :: scene, result, err
    integer(c_int), value :: hertz_mode, prestress, max_eigen_dof
    real(c_double), value :: impact_velocity
    integer(c_size_t), value :: result_size
    integer(c_int) :: code
    character(len=*), parameter :: name = "demstep_scene_compute"
    type(capi_scene_type), pointer :: h
    type(critical_step_type) :: c
    type(demstep_status_type) :: status
    integer :: limit
    if (.not. live(scene, name, h, err, code, particles=.true.)) return
    if (result_refused(result, result_size, name, err, code)) return
    if (hertz_mode /= hertz_linearization%current .and. hertz_mode /= hertz_linearization%impact) then
      code = invalid(err, name//": hertz_linearization: "//int_text(hertz_mode)//" is not " &
        //"DEMSTEP_HERTZ_CURRENT ("//int_text(hertz_linearization%current)//") or DEMSTEP_HERTZ_IMPACT (" &
        //int_text(hertz_linearization%impact)//")")
      return
    end if
    if (prestress /= 0 .and. prestress /= 1) then
      code = invalid(err, name//": prestress: "//int_text(prestress)//" is not 0 (no) or 1 (yes)")
      return
    end if
    limit = default_max_eigen_dof
    if (max_eigen_dof > 0) limit = max_eigen_dof
    if (h%has_bodies) then
      ! rigid bodies: contacts at their current overlap, no pre-stress
      if (hertz_mode /= hertz_linearization%current .or. prestress /= 0) then
        code = invalid(err, name//": with bodies only DEMSTEP_HERTZ_CURRENT and prestress 0 are offered")
        return
      end if
      call body_critical_steps(h%scene, h%bodies, c, status, solver=h%solver, tolerance=h%tolerance, &
        max_eigen_dof=limit)
    else
      call assembly_critical_steps(h%scene, c, status, hertz_mode=int(hertz_mode), &
        impact_velocity=impact_velocity, max_eigen_dof=limit, prestress=prestress == 1, &
        solver=h%solver, tolerance=h%tolerance)
    end if
    if (status%stat /= demstep_stat%ok) status%message = name//": "//status%message
    code = report(err, status)
    call write_result(c, name, err, code, result, result_size)
  end function c_scene_compute

  !> Whether a result pointer and size are refused (NULL, or smaller than the
  !> first version's struct): the refusal is then reported in `code`.
  logical function result_refused(result, result_size, name, err, code) result(refused)
    type(c_ptr), intent(in) :: result, err
    integer(c_size_t), intent(in) :: result_size
    character(len=*), intent(in) :: name
    integer(c_int), intent(out) :: code
    refused = .true.
    code = demstep_stat%ok
    if (.not. c_associated(result)) then
      code = invalid(err, name//": result is NULL")
    else if (result_size < capi_scene_result_size_v1) then
      code = invalid(err, name//": result_size: must be sizeof(demstep_scene_result), at least "// &
        int_text(int(capi_scene_result_size_v1, i8)))
    else
      refused = .false.
    end if
  end function result_refused

  !> The first result_size bytes of a `demstep_scene_result` at `result` from
  !> the critical steps (any more zeroed), when `code` is DEMSTEP_OK and every
  !> value is finite (`guard_finite`; nothing is written otherwise).
  subroutine write_result(c, name, err, code, result, result_size)
    type(critical_step_type), intent(in) :: c
    character(len=*), intent(in) :: name
    type(c_ptr), intent(in) :: err
    integer(c_int), intent(inout) :: code
    type(c_ptr), intent(in) :: result
    integer(c_size_t), intent(in) :: result_size
    type(demstep_scene_result_c) :: row
    character(kind=c_char), pointer :: to(:)
    character(kind=c_char), allocatable :: bytes(:)
    integer :: n_row
    call guard_finite([c%omega_max, c%dt_critical_eigen, c%omega_bound, c%dt_critical_bound, &
      c%dt_contact_rule, c%damping_ratio_top, c%dt_critical_damped, c%omega_upper, c%dt_critical_safe, &
      c%eigen_residual, c%dt_critical_damped_bound], name, err, code)
    if (code /= demstep_stat%ok) return
    row = demstep_scene_result_c(c%omega_max, c%dt_critical_eigen, c%omega_bound, c%dt_critical_bound, &
      c%dt_contact_rule, c%damping_ratio_top, c%dt_critical_damped, c%n_dof, c%n_springs, &
      c%dof_per_particle, flag(c%eigen_computed), flag(c%rotation), flag(c%tangential), &
      flag(c%periodic), flag(c%prestress), c%eigen_tolerance, c%eigen_residual, c%omega_upper, &
      c%dt_critical_safe, c%eigen_products, c%solver, flag(c%eigen_converged), c%dt_critical_damped_bound, &
      flag(c%damped_exact), c%damped_solves)
    ! the struct's bytes by transfer (no pointer to a local of another type:
    ! optimisers may drop stores they cannot see read)
    bytes = transfer(row, [c_null_char])
    n_row = size(bytes)
    call c_f_pointer(result, to, [result_size])
    to = c_null_char
    to(:min(n_row, size(to))) = bytes(:min(n_row, size(to)))
  end subroutine write_result

  !> int demstep_solver_compute(int dim, int n, const double *x, const double *mass,
  !>   const double *radius, const double *inertia, int n_contacts, const int *pairs,
  !>   int n_values, const double *k_n, const double *k_t, const double *c_n, const double *c_t,
  !>   int n_walls, const double *wall_point, const double *wall_normal, const double *wall_k,
  !>   const double *wall_damping, const int *periodic, const double *cell_lo,
  !>   const double *cell_hi, int solver, double tolerance, demstep_scene_result *result,
  !>   size_t result_size, demstep_error *err)
  !>
  !> The critical steps of a solver's own arrays (`solver_critical_steps`): no
  !> scene, no contact search; pairs 0-based; n_values 1 (every contact) or
  !> n_contacts; NULL for inertia (2/5 m r^2), k_t, c_n, c_t, the walls
  !> (n_walls 0) and periodic (no cell); tolerance <= 0: the default.
  function c_solver_compute(dim, n, x, mass, radius, inertia, n_contacts, pairs, n_values, k_n, k_t, &
      c_n, c_t, n_walls, wall_point, wall_normal, wall_k, wall_damping, periodic, cell_lo, cell_hi, &
      solver, tolerance, result, result_size, err) result(code) bind(C, name="demstep_solver_compute")
    integer(c_int), value :: dim, n, n_contacts, n_values, n_walls, solver
    type(c_ptr), value :: x, mass, radius, inertia, pairs, k_n, k_t, c_n, c_t, wall_point, wall_normal, &
      wall_k, wall_damping, periodic, cell_lo, cell_hi, result, err
    real(c_double), value :: tolerance
    integer(c_size_t), value :: result_size
    integer(c_int) :: code
    type(step_monitor_type) :: monitor
    call solver_from_c("demstep_solver_compute", dim, n, x, mass, radius, inertia, n_contacts, pairs, &
      n_values, k_n, k_t, c_n, c_t, n_walls, wall_point, wall_normal, wall_k, wall_damping, periodic, &
      cell_lo, cell_hi, solver, tolerance, result, result_size, err, code, monitor)
  end function c_solver_compute

  !> int demstep_solver_participation(<demstep_solver_compute's arguments up to
  !>   result_size>, double *particle_share, double *contact_share, double *wall_share,
  !>   demstep_error *err)
  !>
  !> The same solve (`demstep_solver_compute`, result filled) and which
  !> particles and contacts carry its top undamped mode (`mode_participation`):
  !> particle_share (n), contact_share (n_contacts; NULL when 0) and
  !> wall_share (n, each particle's wall contacts summed). Status invalid_input
  !> for NULL shares or without an eigensolver (solver none).
  function c_solver_participation(dim, n, x, mass, radius, inertia, n_contacts, pairs, n_values, k_n, k_t, &
      c_n, c_t, n_walls, wall_point, wall_normal, wall_k, wall_damping, periodic, cell_lo, cell_hi, &
      solver, tolerance, result, result_size, particle_share, contact_share, wall_share, err) result(code) &
      bind(C, name="demstep_solver_participation")
    integer(c_int), value :: dim, n, n_contacts, n_values, n_walls, solver
    type(c_ptr), value :: x, mass, radius, inertia, pairs, k_n, k_t, c_n, c_t, wall_point, wall_normal, &
      wall_k, wall_damping, periodic, cell_lo, cell_hi, result, particle_share, contact_share, wall_share, err
    real(c_double), value :: tolerance
    integer(c_size_t), value :: result_size
    integer(c_int) :: code
    character(len=*), parameter :: name = "demstep_solver_participation"
    type(step_monitor_type) :: monitor
    real(dp), allocatable :: ps(:), cs(:), ws(:)
    real(c_double), pointer :: to(:)
    type(demstep_status_type) :: status
    if (.not. (c_associated(particle_share) .and. c_associated(wall_share) .and. &
        (n_contacts <= 0 .or. c_associated(contact_share)))) then
      code = invalid(err, name//": particle_share, wall_share (and contact_share with contacts) must " &
        //"not be NULL")
      return
    end if
    call solver_from_c(name, dim, n, x, mass, radius, inertia, n_contacts, pairs, n_values, k_n, k_t, &
      c_n, c_t, n_walls, wall_point, wall_normal, wall_k, wall_damping, periodic, cell_lo, cell_hi, &
      solver, tolerance, result, result_size, err, code, monitor)
    if (code /= demstep_stat%ok) return
    call mode_participation(monitor, int(n_contacts), ps, cs, ws, status)
    if (status%stat /= demstep_stat%ok) then
      status%message = name//": "//status%message
      code = report(err, status)
      return
    end if
    call c_f_pointer(particle_share, to, [int(n)])
    to = ps
    call c_f_pointer(wall_share, to, [int(n)])
    to = ws
    if (n_contacts > 0) then
      call c_f_pointer(contact_share, to, [int(n_contacts)])
      to = cs
    end if
  end function c_solver_participation

  !> The solver-facing C calls' common part: the counts and pointers checked,
  !> the arrays viewed in place and solved (`solver_critical_steps`, its
  !> monitor returned), the result written; `name` starts the messages.
  subroutine solver_from_c(name, dim, n, x, mass, radius, inertia, n_contacts, pairs, n_values, k_n, &
      k_t, c_n, c_t, n_walls, wall_point, wall_normal, wall_k, wall_damping, periodic, cell_lo, cell_hi, &
      solver, tolerance, result, result_size, err, code, monitor)
    character(len=*), intent(in) :: name
    integer(c_int), intent(in) :: dim, n, n_contacts, n_values, n_walls, solver
    type(c_ptr), intent(in) :: x, mass, radius, inertia, pairs, k_n, k_t, c_n, c_t, wall_point, &
      wall_normal, wall_k, wall_damping, periodic, cell_lo, cell_hi, result, err
    real(c_double), intent(in) :: tolerance
    integer(c_size_t), intent(in) :: result_size
    integer(c_int), intent(out) :: code
    type(step_monitor_type), intent(out) :: monitor
    real(c_double), pointer :: px(:, :), pm(:), pr(:), pkn(:), plo(:), phi(:)
    real(c_double), pointer :: pi(:), pkt(:), pcn(:), pct(:), pwp(:, :), pwn(:, :), pwk(:), pwd(:)
    integer(c_int), pointer :: pp(:, :), pper(:)
    integer(c_int), target :: no_pairs(2, 0)
    real(dp) :: tol, lo(3), hi(3)
    logical :: axes(3)
    type(critical_step_type) :: c
    type(demstep_status_type) :: status
    ! (no initialisation in the declaration: that would SAVE them)
    nullify(pi, pkt, pcn, pct, pwp, pwn, pwk, pwd)
    if (dim < 1 .or. dim > 3 .or. n < 1 .or. n_contacts < 0 .or. n_walls < 0 .or. &
        .not. (n_values == 1 .or. n_values == n_contacts .and. n_contacts > 0)) then
      code = invalid(err, name//": dim 1 to 3, n >= 1, n_contacts >= 0, n_walls >= 0 and n_values " &
        //"1 or n_contacts")
      return
    end if
    if (.not. (c_associated(x) .and. c_associated(mass) .and. c_associated(radius) .and. &
        c_associated(k_n) .and. (n_contacts == 0 .or. c_associated(pairs)))) then
      code = invalid(err, name//": x, mass, radius, k_n (and pairs with contacts) must not be NULL")
      return
    end if
    if (n_walls > 0 .and. .not. (c_associated(wall_point) .and. c_associated(wall_normal) .and. &
        c_associated(wall_k))) then
      code = invalid(err, name//": wall_point, wall_normal and wall_k must not be NULL with walls")
      return
    end if
    if (c_associated(periodic) .and. .not. (c_associated(cell_lo) .and. c_associated(cell_hi))) then
      code = invalid(err, name//": cell_lo and cell_hi must not be NULL with periodic")
      return
    end if
    if (result_refused(result, result_size, name, err, code)) return
    call c_f_pointer(x, px, [int(dim), int(n)])
    call c_f_pointer(mass, pm, [int(n)])
    call c_f_pointer(radius, pr, [int(n)])
    pp => no_pairs
    if (n_contacts > 0) call c_f_pointer(pairs, pp, [2, int(n_contacts)])
    call c_f_pointer(k_n, pkn, [int(n_values)])
    ! a NULL array stays a disassociated pointer: an absent optional argument
    if (c_associated(inertia)) call c_f_pointer(inertia, pi, [int(n)])
    if (c_associated(k_t)) call c_f_pointer(k_t, pkt, [int(n_values)])
    if (c_associated(c_n)) call c_f_pointer(c_n, pcn, [int(n_values)])
    if (c_associated(c_t)) call c_f_pointer(c_t, pct, [int(n_values)])
    if (n_walls > 0) then
      call c_f_pointer(wall_point, pwp, [int(dim), int(n_walls)])
      call c_f_pointer(wall_normal, pwn, [int(dim), int(n_walls)])
      call c_f_pointer(wall_k, pwk, [2])
      if (c_associated(wall_damping)) call c_f_pointer(wall_damping, pwd, [2])
    end if
    tol = lanczos_tolerance_default
    if (tolerance > 0.0_dp .or. ieee_is_nan(tolerance)) tol = tolerance
    if (c_associated(periodic)) then
      call c_f_pointer(periodic, pper, [int(dim)])
      call c_f_pointer(cell_lo, plo, [int(dim)])
      call c_f_pointer(cell_hi, phi, [int(dim)])
      axes = .false.
      lo = 0.0_dp
      hi = 0.0_dp
      axes(:dim) = pper /= 0
      lo(:dim) = plo
      hi(:dim) = phi
      ! (pairs + 1: the library's particle numbers are 1-based)
      call solver_critical_steps(px, pm, pr, pp + 1, pkn, c, status, k_t=pkt, c_n=pcn, c_t=pct, &
        inertia=pi, wall_point=pwp, wall_normal=pwn, wall_k=pwk, wall_damping=pwd, periodic=axes, &
        cell_lo=lo, cell_hi=hi, solver=int(solver), tolerance=tol, solved=monitor)
    else
      call solver_critical_steps(px, pm, pr, pp + 1, pkn, c, status, k_t=pkt, c_n=pcn, c_t=pct, &
        inertia=pi, wall_point=pwp, wall_normal=pwn, wall_k=pwk, wall_damping=pwd, solver=int(solver), &
        tolerance=tol, solved=monitor)
    end if
    if (status%stat /= demstep_stat%ok) status%message = name//": "//status%message
    code = report(err, status)
    call write_result(c, name, err, code, result, result_size)
  end subroutine solver_from_c

  !> A logical as a C int (1 or 0).
  elemental integer(c_int) function flag(value)
    logical, intent(in) :: value
    flag = merge(1_c_int, 0_c_int, value)
  end function flag

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

  !> int demstep_snapshot_read(const char *path, int format, int frame, int n_types,
  !>   const double *type_density, demstep_snapshot **snapshot, demstep_snapshot_info *info,
  !>   demstep_error *err)
  !>
  !> The library's read_snapshot into a new handle (*snapshot; NULL on failure).
  function c_snapshot_read(path, format, frame, n_types, type_density, snapshot, info, err) result(code) &
      bind(C, name="demstep_snapshot_read")
    type(c_ptr), value :: path, type_density, snapshot, info, err
    integer(c_int), value :: format, frame, n_types
    integer(c_int) :: code
    character(len=*), parameter :: name = "demstep_snapshot_read"
    character(kind=c_char), pointer :: chars(:)
    character(len=:), allocatable :: file
    type(c_ptr), pointer :: out
    real(c_double), pointer :: pd(:)
    type(demstep_snapshot_info_c), pointer :: p_info
    type(capi_snapshot_type), pointer :: h
    type(demstep_status_type) :: status
    integer :: k
    if (.not. (c_associated(path) .and. c_associated(snapshot) .and. c_associated(info))) then
      code = invalid(err, name//": path, snapshot or info is NULL")
      return
    end if
    call c_f_pointer(snapshot, out)
    out = c_null_ptr
    if (format < snapshot_format%auto .or. format > snapshot_format%yade_text) then
      code = invalid(err, name//": format: "//int_text(format)//" is not a DEMSTEP_SNAPSHOT_* value (" &
        //int_text(snapshot_format%auto)//" to "//int_text(snapshot_format%yade_text)//")")
      return
    end if
    if (n_types < 0 .or. (n_types > 0 .and. .not. c_associated(type_density))) then
      code = invalid(err, name//": n_types must be >= 0, and type_density not NULL when it is > 0")
      return
    end if
    ! the path up to its NUL, read no further
    call c_f_pointer(path, chars, [capi_path_length])
    k = 0
    do while (k < capi_path_length)
      if (chars(k + 1) == c_null_char) exit
      k = k + 1
    end do
    if (k == 0 .or. k == capi_path_length) then
      code = invalid(err, name//": path: empty, or not NUL-terminated within "//int_text(capi_path_length)// &
        " characters")
      return
    end if
    allocate(character(len=k) :: file)
    do k = 1, len(file)
      file(k:k) = chars(k)
    end do
    allocate(h)
    if (n_types > 0) then
      call c_f_pointer(type_density, pd, [n_types])
      call read_snapshot(file, h%snapshot, status, format=int(format), frame=int(frame), type_density=pd)
    else
      call read_snapshot(file, h%snapshot, status, format=int(format), frame=int(frame))
    end if
    if (status%stat /= demstep_stat%ok) then
      status%message = name//": "//status%message
      code = report(err, status)
      deallocate(h)
      return
    end if
    h%tag = snapshot_tag
    call c_f_pointer(info, p_info)
    associate(d => h%snapshot)
      p_info = demstep_snapshot_info_c(d%n, d%format, d%frame, d%n_frames, int(d%timestep, c_int64_t), &
        flag(d%has_velocity), flag(d%has_omega), flag(d%has_mass), flag(d%has_density), flag(d%has_box), &
        flag(d%periodic), d%lo, d%hi)
    end associate
    out = c_loc(h)
    code = ok(err)
  end function c_snapshot_read

  !> int demstep_snapshot_get(const demstep_snapshot *snapshot, int64_t *id, int *type,
  !>   double *x, double *v, double *omega, double *radius, double *mass, double *density,
  !>   demstep_error *err)
  !>
  !> Copies the snapshot's arrays (n each; x, v, omega 3 per particle); a NULL
  !> array is skipped. Types are 0-based (the file's minus 1).
  function c_snapshot_get(snapshot, id, types, x, v, omega, radius, mass, density, err) result(code) &
      bind(C, name="demstep_snapshot_get")
    type(c_ptr), value :: snapshot, id, types, x, v, omega, radius, mass, density, err
    integer(c_int) :: code
    type(capi_snapshot_type), pointer :: h
    integer(c_int64_t), pointer :: p_id(:)
    integer(c_int), pointer :: p_type(:)
    if (.not. live_snapshot(snapshot, "demstep_snapshot_get", h, err, code)) return
    associate(d => h%snapshot)
      if (c_associated(id)) then
        call c_f_pointer(id, p_id, [d%n])
        p_id = int(d%id, c_int64_t)
      end if
      if (c_associated(types)) then
        call c_f_pointer(types, p_type, [d%n])
        p_type = int(d%type - 1, c_int)
      end if
      call put_rows(x, d%x)
      call put_rows(v, d%v)
      call put_rows(omega, d%omega)
      call put_rows(radius, reshape(d%radius, [1, d%n]))
      call put_rows(mass, reshape(d%mass, [1, d%n]))
      call put_rows(density, reshape(d%density, [1, d%n]))
    end associate
    code = ok(err)
  end function c_snapshot_get

  !> Copy values (rows by particles) to a caller's array, unless it is NULL.
  subroutine put_rows(to, values)
    type(c_ptr), intent(in) :: to
    real(dp), intent(in) :: values(:, :)
    real(c_double), pointer :: p(:, :)
    if (.not. c_associated(to)) return
    call c_f_pointer(to, p, shape(values))
    p = values
  end subroutine put_rows

  !> int demstep_snapshot_free(demstep_snapshot **snapshot, demstep_error *err)
  function c_snapshot_free(snapshot, err) result(code) bind(C, name="demstep_snapshot_free")
    type(c_ptr), value :: snapshot, err
    integer(c_int) :: code
    type(c_ptr), pointer :: handle
    type(capi_snapshot_type), pointer :: h
    code = ok(err)
    if (.not. c_associated(snapshot)) return
    call c_f_pointer(snapshot, handle)
    if (.not. c_associated(handle)) return
    call c_f_pointer(handle, h)
    if (h%tag /= snapshot_tag) then
      code = invalid(err, "demstep_snapshot_free: *snapshot is not a live handle of demstep_snapshot_read")
      return
    end if
    h%tag = 0
    deallocate(h)
    handle = c_null_ptr
  end function c_snapshot_free

  !> Whether `snapshot` is a live handle (h points to it); otherwise the error is reported.
  logical function live_snapshot(snapshot, name, h, err, code)
    type(c_ptr), intent(in) :: snapshot, err
    character(len=*), intent(in) :: name
    type(capi_snapshot_type), pointer, intent(out) :: h
    integer(c_int), intent(out) :: code
    live_snapshot = .false.
    h => null()
    code = demstep_stat%ok
    if (.not. c_associated(snapshot)) then
      code = invalid(err, name//": snapshot is NULL")
      return
    end if
    call c_f_pointer(snapshot, h)
    if (h%tag /= snapshot_tag) then
      code = invalid(err, name//": snapshot is not a live handle of demstep_snapshot_read")
      h => null()
      return
    end if
    live_snapshot = .true.
  end function live_snapshot

  !> The library's pair of a struct demstep_material_pair.
  pure function pair_of(c) result(pair)
    type(demstep_material_pair_c), intent(in) :: c
    type(material_pair_type) :: pair
    pair%a = material_type(c%a%young, c%a%poisson, c%a%density, c%a%radius)
    pair%b = material_type(c%b%young, c%b%poisson, c%b%density, c%b%radius)
    pair%restitution = c%restitution
    pair%restitution_t = c%restitution_t
    pair%impact_velocity = c%impact_velocity
    pair%contact_time = c%contact_time
    pair%stiffness = c%stiffness
  end function pair_of

  !> int demstep_contact_parameters(const demstep_material_pair *pair, int convention,
  !>   demstep_code_contact *params, demstep_error *err)
  !>
  !> The library's contact_parameters of a pair in one code's convention, with
  !> m* and the exact limit of the contact as that code steps it (convention_limit).
  function c_contact_parameters(pair, convention, params, err) result(code) &
      bind(C, name="demstep_contact_parameters")
    type(c_ptr), value :: pair, params, err
    integer(c_int), value :: convention
    integer(c_int) :: code
    character(len=*), parameter :: name = "demstep_contact_parameters"
    type(demstep_material_pair_c), pointer :: pc
    type(demstep_code_contact_c), pointer :: out
    type(material_pair_type) :: p
    type(effective_pair_type) :: eff
    type(contact_parameters_type) :: cp
    type(demstep_status_type) :: status
    real(dp) :: dt
    if (.not. (c_associated(pair) .and. c_associated(params))) then
      code = invalid(err, name//": pair or params is NULL")
      return
    end if
    if (convention < code_convention%liggghts_hooke .or. convention > code_convention%lammps_hertz_material) then
      code = invalid(err, name//": convention: "//int_text(convention)//" is not a DEMSTEP_CODE_* value (" &
        //int_text(code_convention%liggghts_hooke)//" to "//int_text(code_convention%lammps_hertz_material)//")")
      return
    end if
    call c_f_pointer(pair, pc)
    p = pair_of(pc)
    call contact_parameters(p, int(convention), cp, status)
    if (status%stat == demstep_stat%ok) call effective_pair(p%a, p%b, eff, status)
    if (status%stat == demstep_stat%ok) call convention_limit(cp, eff%m_star, dt, status)
    if (status%stat /= demstep_stat%ok) status%message = name//": "//status%message
    code = report(err, status)
    call guard_finite([cp%k_n, cp%k_t, cp%gamma_n, cp%gamma_t, cp%overlap, cp%t_contact, &
      cp%code_collision_time, eff%m_star, dt], name, err, code)
    if (code /= demstep_stat%ok) return
    call c_f_pointer(params, out)
    out = demstep_code_contact_c(cp%k_n, cp%k_t, cp%gamma_n, cp%gamma_t, cp%overlap, cp%t_contact, &
      cp%code_collision_time, eff%m_star, dt)
  end function c_contact_parameters

  !> int demstep_peer_time_steps(const demstep_material_pair *pair, demstep_peer_steps *steps,
  !>   demstep_error *err)
  !>
  !> The library's peer_time_steps: the pair's time scales and each peer's rule.
  function c_peer_time_steps(pair, steps, err) result(code) bind(C, name="demstep_peer_time_steps")
    type(c_ptr), value :: pair, steps, err
    integer(c_int) :: code
    character(len=*), parameter :: name = "demstep_peer_time_steps"
    type(demstep_material_pair_c), pointer :: pc
    type(demstep_peer_steps_c), pointer :: out
    type(peer_steps_type) :: ps
    type(demstep_status_type) :: status
    if (.not. (c_associated(pair) .and. c_associated(steps))) then
      code = invalid(err, name//": pair or steps is NULL")
      return
    end if
    call c_f_pointer(pair, pc)
    call peer_time_steps(pair_of(pc), ps, status)
    if (status%stat /= demstep_stat%ok) status%message = name//": "//status%message
    code = report(err, status)
    call guard_finite([ps%rayleigh, ps%rayleigh_yade, ps%hertz_duration, ps%hertz_liggghts, ps%dt], name, &
      err, code)
    if (code /= demstep_stat%ok) return
    call c_f_pointer(steps, out)
    out = demstep_peer_steps_c(ps%rayleigh, ps%rayleigh_yade, ps%hertz_duration, ps%hertz_liggghts, ps%dt)
  end function c_peer_time_steps

end module demstep_capi
