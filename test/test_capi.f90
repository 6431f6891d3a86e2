!> Tests of the C API through its bind(C) entry points: the same numbers as the
!> Fortran API, and bad input (NULL pointers, empty arrays, NaN) as statuses with
!> messages, never a crash.
module test_capi
  use, intrinsic :: iso_c_binding, only: c_int, c_double, c_loc, c_null_ptr, c_null_char, c_ptr, &
    c_associated, c_f_pointer, c_sizeof, c_size_t, c_char, c_int64_t
  use testdrive, only: new_unittest, unittest_type, error_type, check, test_failed
  use demstep
  use demstep_material, only: convention_limit, code_convention_names
  use demstep_scene_data, only: scene_effect_names, n_effects
  use demstep_kinds, only: pi
  use demstep_lanczos, only: lanczos_tolerance_default
  use demstep_capi, only: demstep_error_c, demstep_spring_c, demstep_spring_state_c, demstep_nroots_c, &
    demstep_stiffness_result_c, c_spring_new, c_spring_step, c_critical_time_step, c_harmonic_error, &
    c_n_roots, c_simulated_stiffness, demstep_contact_c, c_contact_with_onset, c_n_for_tolerance, &
    capi_scene_type, capi_effect, capi_effect_map, demstep_scene_result_c, capi_scene_result_size_v1, &
    c_scene_create, c_scene_free, c_scene_set_particles, c_scene_add_bonds, c_scene_set_bond_stiffness, &
    c_scene_set_contact_law, c_scene_set_types, c_scene_set_hertz_types, c_scene_add_walls, &
    c_scene_set_contacts, c_scene_set_effects, c_scene_set_cell, c_scene_set_damping, &
    c_scene_set_gravity, c_scene_compute, c_scene_set_dashpots, c_scene_set_rolling, &
    c_scene_set_materials, c_scene_set_eigen_solver, demstep_snapshot_info_c, c_snapshot_read, &
    c_snapshot_get, c_snapshot_free, demstep_material_c, demstep_material_pair_c, demstep_code_contact_c, &
    demstep_peer_steps_c, c_contact_parameters, c_peer_time_steps, c_scene_set_bond_model, c_scene_set_bodies, &
    c_scene_body_peer_steps
  use test_support, only: ieee_nan, read_file
  implicit none
  private
  public :: collect_capi

contains

  subroutine collect_capi(testsuite)
    type(unittest_type), allocatable, intent(out) :: testsuite(:)
    testsuite = [ &
      new_unittest("C API gives the Fortran numbers bit for bit", test_same_numbers), &
      new_unittest("NULL pointers, empty arrays, NaN: statuses and messages", test_bad_input), &
      new_unittest("n_roots and the procedure: NaN options, extreme weights and n, fine scans", &
        test_stiffness_limits), &
      new_unittest("include/demstep.h: every enum value equals the Fortran one", test_header_enums), &
      new_unittest("materials in a code's convention: the library's numbers bit for bit", test_scene_materials), &
      new_unittest("rigid bodies and bond models: the library's numbers bit for bit; refusals", test_scene_bodies), &
      new_unittest("every enum argument out of range: a status naming it", test_bad_enums), &
      new_unittest("scene handle: a chain bit for bit as Fortran and against the closed form", &
        test_scene_chain), &
      new_unittest("scene handle: wall, periodic cell, Hertz impact, types: closed forms", test_scene_models), &
      new_unittest("scene handle: each C effect flag switches its library effect", test_scene_effects), &
      new_unittest("scene handle: NULL pointers, bad enums, use after a failed call, free", &
        test_scene_bad_input), &
      new_unittest("snapshot handle: read_snapshot's arrays bit for bit; bad input as statuses", &
        test_snapshot), &
      new_unittest("a pair's contact per convention and the peers' rules: the library's numbers", &
        test_pair_and_peers) &
      ]
  end subroutine collect_capi

  !> Every `DEMSTEP_NAME = value` of the C header is parsed and compared with the
  !> Fortran constant of the same meaning; a header constant missing from the
  !> table, or a table entry missing from the header, fails too.
  subroutine test_header_enums(error)
    type(error_type), allocatable, intent(out) :: error
    character(len=32), allocatable :: names(:)
    integer, allocatable :: values(:)
    logical, allocatable :: seen(:)
    character(len=:), allocatable :: text, name
    integer :: i, j, k, value, ios, found
    names = [character(len=32) :: "OK", "INVALID_INPUT", "UNSTABLE", "POLE", "NOT_CONVERGED", &
      "NOT_FOUND", "LAPACK_FAILURE", "IO_ERROR", "BLOW_UP", "AT_STABILITY_LIMIT", "DISCONTINUOUS", &
      "EIGENSOLVER_FAILURE", "BUSY", &
      "DASHPOT_LAGGED", "DASHPOT_CENTRED", "STEPS_FIXED", "STEPS_FRACTION", "STEPS_ROUNDED", &
      "PICK_LARGEST_STEP", "PICK_ZERO", "AGGREGATE_MEAN", "AGGREGATE_WEIGHTED", "AGGREGATE_MEDIAN", &
      "AGGREGATE_MIN", "AGGREGATE_MAX", "QUANTITY_RESTITUTION", "QUANTITY_CONTACT_TIME", &
      "QUANTITY_OVERLAP", "QUANTITY_PERIOD", "LAW_LINEAR", "LAW_HERTZ", "EFFECT_CONTACTS", &
      "EFFECT_GRAVITY", "EFFECT_DAMPING", "EFFECT_LOCAL_DAMPING", "EFFECT_WALLS", "EFFECT_ROTATION", &
      "HERTZ_CURRENT", "HERTZ_IMPACT", "EIGEN_AUTO", "EIGEN_DENSE", "EIGEN_LANCZOS", "EIGEN_NONE", &
      "CODE_LIGGGHTS_HOOKE", "CODE_LIGGGHTS_HERTZ", "CODE_YADE_FRICTPHYS", "CODE_YADE_VISCELPHYS", &
      "CODE_MFIX_LSD", "CODE_MFIX_HERTZIAN", "CODE_MERCURYDPM_LINEAR", "CODE_LAMMPS_HOOKE", &
      "CODE_LAMMPS_HERTZ_MATERIAL", "SNAPSHOT_AUTO", "SNAPSHOT_LAMMPS_DUMP", "SNAPSHOT_LAMMPS_DATA", &
      "SNAPSHOT_YADE_TEXT", "PEER_EDEM_RAYLEIGH_20", "PEER_EDEM_RAYLEIGH_40", "PEER_LIGGGHTS_RAYLEIGH_10", &
      "PEER_LIGGGHTS_HERTZ_10", "PEER_MFIX_LSD_TC50", "PEER_MFIX_HERTZIAN_TC50", "PEER_MERCURYDPM_TC50", &
      "PEER_YADE_PWAVE", "PEER_YADE_PWAVE_30", "BOND_PFC", "BOND_MUSEN", "BOND_YADE", "BOND_LAMMPS"]
    values = [demstep_stat%ok, demstep_stat%invalid_input, demstep_stat%unstable, demstep_stat%pole, &
      demstep_stat%not_converged, demstep_stat%not_found, demstep_stat%lapack_failure, &
      demstep_stat%io_error, demstep_stat%blow_up, demstep_stat%at_stability_limit, &
      demstep_stat%discontinuous, demstep_stat%eigensolver_failure, demstep_stat%busy, &
      dashpot_kind%lagged, dashpot_kind%centred, step_kind%fixed, &
      step_kind%fraction, step_kind%rounded, pick_kind%largest_step, pick_kind%zero, &
      aggregate_kind%mean, aggregate_kind%weighted, aggregate_kind%median, aggregate_kind%min, &
      aggregate_kind%max, quantity_kind%restitution, quantity_kind%contact_time, &
      quantity_kind%overlap, quantity_kind%period, contact_law%linear, contact_law%hertz, &
      ! effects are the C API's own bit flags (test_scene_effects checks their map)
      capi_effect%contacts, capi_effect%gravity, capi_effect%damping, capi_effect%local_damping, &
      capi_effect%walls, capi_effect%rotation, hertz_linearization%current, hertz_linearization%impact, &
      eigen_solver%auto, eigen_solver%dense, eigen_solver%lanczos, eigen_solver%none, &
      code_convention%liggghts_hooke, code_convention%liggghts_hertz, code_convention%yade_frictphys, &
      code_convention%yade_viscelphys, code_convention%mfix_lsd, code_convention%mfix_hertzian, &
      code_convention%mercurydpm_linear, code_convention%lammps_hooke, code_convention%lammps_hertz_material, &
      snapshot_format%auto, snapshot_format%lammps_dump, snapshot_format%lammps_data, snapshot_format%yade_text, &
      peer_rule%edem_rayleigh_20, peer_rule%edem_rayleigh_40, peer_rule%liggghts_rayleigh_10, &
      peer_rule%liggghts_hertz_10, peer_rule%mfix_lsd_tc50, peer_rule%mfix_hertzian_tc50, &
      peer_rule%mercurydpm_tc50, peer_rule%yade_pwave, peer_rule%yade_pwave_30, bond_model%pfc, &
      bond_model%musen, bond_model%yade, bond_model%lammps]
    allocate(seen(size(names)), source=.false.)
    call read_file("include/demstep.h", text)
    call check(error, len(text) > 0, "include/demstep.h read")
    if (allocated(error)) return
    found = 0
    i = 1
    do
      k = index(text(i:), "DEMSTEP_")
      if (k == 0) exit
      i = i + k - 1 + len("DEMSTEP_")
      ! a name of capitals, digits and underscores, then " = value"
      j = i
      do while (j <= len(text))
        if (index("ABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789_", text(j:j)) == 0) exit
        j = j + 1
      end do
      name = text(i:j-1)
      k = j
      do while (k <= len(text))
        if (text(k:k) /= " ") exit
        k = k + 1
      end do
      if (k > len(text) .or. len(name) == 0) cycle
      if (text(k:k) /= "=") cycle
      read(text(k+1:min(len(text), k+12)), *, iostat=ios) value
      if (ios /= 0) then
        ! a value followed by a comment or a brace: read up to it
        j = k + 1
        do while (j <= len(text))
          if (index(",}/ ", text(j:j)) > 0 .and. j > k + 2) exit
          j = j + 1
        end do
        read(text(k+1:j-1), *, iostat=ios) value
      end if
      call check(error, ios == 0, "DEMSTEP_"//name//": value not read")
      if (allocated(error)) return
      found = found + 1
      do j = 1, size(names)
        if (trim(names(j)) == name) exit
      end do
      call check(error, j <= size(names), "DEMSTEP_"//name//" has no Fortran counterpart in the test")
      if (allocated(error)) return
      call check(error, value, values(j), message="DEMSTEP_"//name)
      if (allocated(error)) return
      seen(j) = .true.
    end do
    call check(error, all(seen), "every Fortran constant has its DEMSTEP_ value in the header")
    if (allocated(error)) return
    call check(error, found, size(names), message="one header value per name")
  end subroutine test_header_enums

  !> The location (`where`) of a C error struct as a Fortran string.
  function where_of(e) result(text)
    type(demstep_error_c), intent(in) :: e
    character(len=:), allocatable :: text
    text = c_text(e%where)
  end function where_of

  !> The message of a C error struct as a Fortran string.
  function message_of(e) result(text)
    type(demstep_error_c), intent(in) :: e
    character(len=:), allocatable :: text
    text = c_text(e%message)
  end function message_of

  !> A NUL-terminated C character array as a Fortran string.
  function c_text(chars) result(text)
    character(kind=c_char), intent(in) :: chars(:)
    character(len=:), allocatable :: text
    integer :: i
    text = ""
    do i = 1, size(chars)
      if (chars(i) == c_null_char) exit
      text = text//chars(i)
    end do
  end function c_text

  subroutine test_same_numbers(error)
    type(error_type), allocatable, intent(out) :: error
    type(demstep_error_c), target :: e
    type(demstep_spring_c), target :: cs
    type(demstep_spring_state_c), target :: cst
    type(demstep_nroots_c), target :: cr
    real(c_double), target :: dt, value
    type(spring_type) :: fs
    type(spring_state_type) :: fst
    type(demstep_status_type) :: status
    type(nroots_options_type) :: options
    type(nroots_type) :: r
    real(dp) :: ev
    integer :: i, stat
    call check(error, int(c_spring_new(0.01_dp, 1.0e5_dp, 0.1_dp, 1, 1, c_loc(cs), c_loc(e))), 0)
    if (allocated(error)) return
    call new_spring(fs, 0.01_dp, 1.0e5_dp, status, damping_ratio=0.1_dp)
    call check(error, int(c_critical_time_step(c_loc(cs), c_loc(dt), c_loc(e))), 0)
    if (allocated(error)) return
    call check(error, dt, critical_time_step(fs), thr=0.0_dp, message="critical step")
    if (allocated(error)) return
    cst = demstep_spring_state_c(0.0_dp, 1.0_dp, 0_i8)
    fst = spring_state_type(x=0.0_dp, v=1.0_dp)
    do i = 1, 500
      call check(error, int(c_spring_step(c_loc(cs), 0.3_dp*dt, c_loc(cst), c_loc(e))), 0)
      if (allocated(error)) return
      call spring_step(fs, 0.3_dp*dt, fst)
    end do
    call check(error, cst%x == fst%x .and. cst%v == fst%v .and. cst%step == fst%step, "500 steps")
    if (allocated(error)) return
    call check(error, int(c_harmonic_error(1000.0_dp, 0.97_dp, 1.0e7_dp + 1.0_dp, c_loc(value), c_loc(e))), 0)
    if (allocated(error)) return
    call harmonic_error(1000.0_dp, 0.97_dp, 1.0e7_dp + 1.0_dp, ev, stat)
    call check(error, value, ev, thr=0.0_dp, message="E")
    if (allocated(error)) return
    call check(error, int(c_n_roots(0.9_dp, 1.0e-3_dp, 2, 0.5_dp, 1, 0.0_dp, 0.0_dp, c_loc(cr), &
      c_loc(e))), 0)
    if (allocated(error)) return
    options%tolerance = 1.0e-3_dp
    call n_roots(0.9_dp, options, r, status)
    call check(error, cr%n_pick == r%n_pick .and. cr%n_zero == r%roots(1) .and. cr%n_lower == r%lower(1), &
      "n_roots")
  end subroutine test_same_numbers

  subroutine test_bad_input(error)
    type(error_type), allocatable, intent(out) :: error
    type(demstep_error_c), target :: e
    type(demstep_spring_c), target :: cs
    type(demstep_stiffness_result_c), target :: res
    type(demstep_contact_c), target :: contact
    real(c_double), target :: value, lambdas(2)
    integer :: code
    code = c_spring_new(1.0_dp, 1.0_dp, 0.0_dp, 1, 1, c_null_ptr, c_loc(e))
    call check(error, code == 1 .and. e%stat == 1 .and. index(message_of(e), "NULL") > 0, &
      "NULL spring: "//message_of(e))
    if (allocated(error)) return
    code = c_spring_new(ieee_nan(), 1.0_dp, 0.0_dp, 1, 1, c_loc(cs), c_loc(e))
    call check(error, code == 1 .and. index(message_of(e), "mass") > 0, "NaN mass: "//message_of(e))
    if (allocated(error)) return
    code = c_critical_time_step(c_null_ptr, c_loc(value), c_loc(e))
    call check(error, code, 1, message="NULL spring to critical_time_step")
    if (allocated(error)) return
    code = c_harmonic_error(10.0_dp, ieee_nan(), 5.0_dp, c_loc(value), c_loc(e))
    call check(error, code == 1 .and. len(message_of(e)) > 0, "NaN lambda")
    if (allocated(error)) return
    code = c_harmonic_error(10.0_dp, 0.5_dp, 20.0_dp, c_loc(value), c_null_ptr)
    call check(error, code, 3, message="a pole, no error struct")
    if (allocated(error)) return
    lambdas = [0.9_dp, 0.95_dp]
    code = c_simulated_stiffness(0.01_dp, 1.0e5_dp, 1.0e-3_dp, c_loc(lambdas), 0, 2, 0.5_dp, 1, 1, &
      c_null_ptr, c_null_ptr, c_null_ptr, c_loc(res), c_loc(e))
    call check(error, code == 1 .and. index(message_of(e), "n_lambdas") > 0, "empty lambda set")
    if (allocated(error)) return
    code = c_simulated_stiffness(0.01_dp, 1.0e5_dp, 1.0e-3_dp, c_null_ptr, 2, 2, 0.5_dp, 1, 1, &
      c_null_ptr, c_null_ptr, c_null_ptr, c_loc(res), c_loc(e))
    call check(error, code, 1, message="NULL lambdas")
    if (allocated(error)) return
    lambdas = [0.9_dp, ieee_nan()]
    code = c_simulated_stiffness(0.01_dp, 1.0e5_dp, 1.0e-3_dp, c_loc(lambdas), 2, 2, 0.5_dp, 1, 1, &
      c_null_ptr, c_null_ptr, c_null_ptr, c_loc(res), c_loc(e))
    call check(error, code, 1, message="NaN lambda in the set")
    if (allocated(error)) return
    code = c_contact_with_onset(20.0_dp, 1.5_dp, 0.0_dp, c_loc(contact), c_loc(e))
    call check(error, code == 1 .and. index(message_of(e), "onset") > 0, "onset 1.5: "//message_of(e))
    if (allocated(error)) return
    code = c_contact_with_onset(20.0_dp, 0.5_dp, ieee_nan(), c_loc(contact), c_loc(e))
    call check(error, code, 1, message="NaN damping")
    if (allocated(error)) return
    code = c_contact_with_onset(20.0_dp, 0.5_dp, 0.0_dp, c_null_ptr, c_loc(e))
    call check(error, code, 1, message="NULL contact")
    if (allocated(error)) return
    code = c_n_for_tolerance(1, ieee_nan(), 0.0_dp, 0.0_dp, c_loc(value), c_loc(e))
    call check(error, code, 1, message="NaN tolerance")
    if (allocated(error)) return
    code = c_n_for_tolerance(9, 1.0e-3_dp, 0.0_dp, 0.0_dp, c_loc(value), c_loc(e))
    call check(error, code, 1, message="unknown quantity")
  end subroutine test_bad_input

  subroutine test_stiffness_limits(error)
    type(error_type), allocatable, intent(out) :: error
    type(demstep_error_c), target :: e
    type(demstep_nroots_c), target :: cr
    type(demstep_stiffness_result_c), target :: res
    type(demstep_spring_c), target :: cs
    type(demstep_spring_state_c), target :: cst
    real(c_double), target :: lambdas(2), weights(2)
    integer :: code
    code = c_n_roots(0.9_dp, 1.0e-3_dp, 2, 0.5_dp, 1, ieee_nan(), 0.0_dp, c_loc(cr), c_loc(e))
    call check(error, code == 1 .and. index(message_of(e), "n_max") > 0, "n_max NaN: "//message_of(e))
    if (allocated(error)) return
    code = c_n_roots(0.9_dp, 1.0e-3_dp, 2, 0.5_dp, 1, 0.0_dp, ieee_nan(), c_loc(cr), c_loc(e))
    call check(error, code == 1 .and. index(message_of(e), "resolution") > 0, "resolution NaN: "//message_of(e))
    if (allocated(error)) return
    code = c_n_roots(0.9_dp, 1.0e-3_dp, 1, 1.0e9_dp, 1, 0.0_dp, 1.0e-9_dp, c_loc(cr), c_loc(e))
    call check(error, code == 1 .and. index(message_of(e), "resolution") > 0, "resolution 1e-9: "//message_of(e))
    if (allocated(error)) return
    ! n = 1e9 and 1e12 fixed steps: the scan stops at the first root, next to pi
    code = c_n_roots(0.9_dp, 1.0e-3_dp, 1, 1.0e9_dp, 1, 0.0_dp, 0.0_dp, c_loc(cr), c_loc(e))
    call check(error, code == 0 .and. cr%n_zero > pi .and. cr%n_zero < pi*(1.0_dp + 1.0e-6_dp), "n = 1e9")
    if (allocated(error)) return
    code = c_n_roots(0.9_dp, 1.0e-3_dp, 1, 1.0e12_dp, 1, 0.0_dp, 0.0_dp, c_loc(cr), c_loc(e))
    call check(error, code == 0 .and. cr%n_zero > pi .and. cr%n_zero < pi*(1.0_dp + 1.0e-6_dp), "n = 1e12")
    if (allocated(error)) return
    lambdas = [0.9_dp, 0.95_dp]
    weights = [1.0e308_dp, 1.0_dp]
    code = c_simulated_stiffness(1.0_dp, 1.0_dp, 1.0e-3_dp, c_loc(lambdas), 2, 2, 0.5_dp, 1, 2, &
      c_loc(weights), c_null_ptr, c_null_ptr, c_loc(res), c_loc(e))
    call check(error, code == 0 .and. res%n_star > 18.0_dp .and. res%n_star < 19.0_dp, &
      "weights 1e308, 1: N* finite")
    if (allocated(error)) return
    ! the finite-output guard: a step that overflows is an error, not Infinity
    code = c_spring_new(1.0_dp, 1.0_dp, 0.0_dp, 0, 1, c_loc(cs), c_loc(e))
    cst = demstep_spring_state_c(1.0e300_dp, 1.0e300_dp, 0_8)
    code = c_spring_step(c_loc(cs), 1.0e300_dp, c_loc(cst), c_loc(e))
    call check(error, code == 1 .and. cst%x == 1.0e300_dp .and. index(message_of(e), "not finite") > 0, &
      "overflowing step: "//message_of(e))
  end subroutine test_stiffness_limits

  !> A 1D chain through the handle: 12 unit masses at x = 1..12 (radius 0.3, no
  !> contacts), ends fixed, 11 bonds k = 100, no effects.
  subroutine chain_handle(handle, e, code)
    type(c_ptr), intent(out), target :: handle
    type(demstep_error_c), intent(inout), target :: e
    integer, intent(out) :: code
    real(c_double), target :: x(12), m(12), r(12)
    integer(c_int), target :: fixed(12), bonds(2, 11)
    integer :: i
    x = [(real(i, dp), i = 1, 12)]
    m = 1.0_dp
    r = 0.3_dp
    fixed = 0
    fixed([1, 12]) = 1
    bonds = reshape([(i - 1, i, i = 1, 11)], [2, 11])
    code = c_scene_create(1, c_loc(handle), c_loc(e))
    if (code /= 0) return
    code = c_scene_set_particles(handle, 12, c_loc(x), c_loc(m), c_loc(r), c_loc(fixed), c_null_ptr, &
      c_null_ptr, c_loc(e))
    if (code /= 0) return
    code = c_scene_add_bonds(handle, 11, c_loc(bonds), c_loc(e))
    if (code /= 0) return
    code = c_scene_set_bond_stiffness(handle, 100.0_dp, 0.0_dp, c_loc(e))
    if (code /= 0) return
    code = c_scene_set_effects(handle, 0, c_loc(e))
  end subroutine chain_handle

  !> Three beads in a row on a floor, materials in LIGGGHTS' Hertz convention
  !> (restitution 0.5, walls of type 1): the handle gives the library's
  !> `scene_set_materials` numbers bit for bit; bad arguments refused.
  subroutine test_scene_materials(error)
    type(error_type), allocatable, intent(out) :: error
    type(c_ptr), target :: handle
    type(demstep_error_c), target :: e
    type(demstep_scene_result_c), target :: res
    real(c_double), target :: x(9), m(3), r(3), young(2), poisson(2), density(2), radius(2), point(3), normal(3)
    integer(c_int), target :: types(3)
    type(scene_type) :: scene
    type(critical_step_type) :: c
    type(demstep_status_type) :: status
    integer :: code
    x = [0.0_dp, 0.0_dp, 0.99e-3_dp, 1.98e-3_dp, 0.0_dp, 0.99e-3_dp, 3.96e-3_dp, 0.0_dp, 0.99e-3_dp]
    m = [1.0e-5_dp, 1.2e-5_dp, 1.0e-5_dp]
    r = 1.0e-3_dp
    types = [0, 1, 0]
    young = [1.0e7_dp, 2.0e7_dp]
    poisson = [0.3_dp, 0.25_dp]
    density = 2500.0_dp
    radius = 1.0e-3_dp
    point = 0.0_dp
    normal = [0.0_dp, 0.0_dp, 1.0_dp]
    code = c_scene_create(3, c_loc(handle), c_loc(e))
    code = c_scene_set_particles(handle, 3, c_loc(x), c_loc(m), c_loc(r), c_null_ptr, c_null_ptr, &
      c_null_ptr, c_loc(e))
    code = c_scene_add_walls(handle, 1, c_loc(point), c_loc(normal), c_loc(e))
    code = c_scene_set_materials(handle, 2, c_loc(types), c_loc(young), c_loc(poisson), c_loc(density), &
      c_loc(radius), code_convention%liggghts_hertz, 0.5_dp, 1.0_dp, 0, 1, c_loc(e))
    call check(error, code == 0, "materials: "//message_of(e))
    if (allocated(error)) return
    code = c_scene_set_effects(handle, ior(ior(capi_effect%contacts, capi_effect%walls), &
      ior(capi_effect%damping, capi_effect%rotation)), c_loc(e))
    code = compute(handle, res, e)
    call check(error, code == 0 .and. res%damped_exact == 1, "compute: "//message_of(e))
    if (allocated(error)) return
    call new_scene(scene, 3, reshape(x, [3, 3]), m, r, status)
    call scene_add_walls(scene, reshape(point, [3, 1]), reshape(normal, [3, 1]), status)
    call scene_set_materials(scene, [1, 2, 1], [(material_type(young(code), poisson(code), density(code), &
      radius(code)), code = 1, 2)], code_convention%liggghts_hertz, 0.5_dp, status, impact_velocity=1.0_dp, &
      wall_type=1)
    call assembly_critical_steps(scene, c, status)
    call check(error, status%stat == demstep_stat%ok .and. res%dt_critical_damped == c%dt_critical_damped .and. &
      res%omega_max == c%omega_max, "the library's numbers bit for bit")
    if (allocated(error)) return
    code = c_scene_set_materials(handle, 2, c_loc(types), c_loc(young), c_loc(poisson), c_loc(density), &
      c_loc(radius), code_convention%liggghts_hertz, 0.5_dp, 1.0_dp, 0, 2, c_loc(e))
    call check(error, code == demstep_stat%invalid_input .and. index(message_of(e), "tangential_damping") > 0, &
      "tangential_damping 2 refused")
    if (allocated(error)) return
    code = c_scene_free(c_loc(handle), c_loc(e))
  end subroutine test_scene_materials

  !> Rigid bodies and a code's bonds through the handle. A clump packing
  !> (12 clumps over a floor, linear law with rolling and twisting springs):
  !> the bodies from their members, and the same bodies given by mass, centre
  !> and tensor, give `body_critical_steps`' numbers bit for bit, and the
  !> peers' rules `body_gst_step`'s and `body_exadem_step`'s. A bonded pair
  !> with Yade's CohFrictPhys bond gives `assembly_critical_steps`' numbers.
  !> Refused, by name: bodies before the particles, bodies set twice, a
  !> singular tensor (where "inertia", the body's 0-based index), a negative
  !> bond parameter (where "bond_parameters"), HERTZ_IMPACT or pre-stress
  !> with bodies, the peers' rules without bodies.
  subroutine test_scene_bodies(error)
    type(error_type), allocatable, intent(out) :: error
    type(c_ptr), target :: handle
    type(demstep_error_c), target :: e
    type(demstep_scene_result_c), target :: res
    type(scene_type) :: scene
    type(body_set_type) :: bodies
    type(critical_step_type) :: c
    type(demstep_status_type) :: status
    integer, allocatable :: body_of(:)
    integer(c_int), allocatable, target :: ids(:)
    integer(c_int), target :: pair(2)
    real(c_double), allocatable, target :: x(:), m(:), r(:), mass(:), com(:), inertia(:)
    real(c_double), target :: point(3), normal(3), p(4), gst, exa, x2(6), m2(2), r2(2)
    real(dp) :: dt_gst, dt_exa
    integer :: code, given
    call random_clump_packing(scene, body_of, 12, status, seed=3)
    call check(error, status%stat, demstep_stat%ok, status%message)
    if (allocated(error)) return
    x = reshape(scene%x, [3*scene%n])
    m = scene%mass
    r = scene%radius
    ids = body_of
    point = scene%wall_point(:, 1)
    normal = scene%wall_normal(:, 1)
    do given = 0, 1
      call bodies_from_members(scene, body_of, bodies, status)
      if (given == 1) then
        mass = bodies%mass
        com = reshape(bodies%com, [3*bodies%n])
        inertia = reshape(bodies%inertia, [9*bodies%n])
        call bodies_given(scene, body_of, mass, reshape(com, [3, size(mass)]), &
          reshape(inertia, [3, 3, size(mass)]), bodies, status)
      end if
      call body_critical_steps(scene, bodies, c, status)
      call check(error, status%stat, demstep_stat%ok, status%message)
      if (allocated(error)) return
      code = c_scene_create(3, c_loc(handle), c_loc(e))
      code = c_scene_set_particles(handle, scene%n, c_loc(x), c_loc(m), c_loc(r), c_null_ptr, c_null_ptr, &
        c_null_ptr, c_loc(e))
      code = c_scene_set_contact_law(handle, contact_law%linear, 1.0e3_dp, 400.0_dp, c_loc(e))
      code = c_scene_set_rolling(handle, 0.1_dp, 0.05_dp, c_loc(e))
      code = c_scene_add_walls(handle, 1, c_loc(point), c_loc(normal), c_loc(e))
      code = c_scene_set_effects(handle, ior(ior(capi_effect%contacts, capi_effect%walls), capi_effect%rotation), &
        c_loc(e))
      if (given == 0) then
        code = c_scene_set_bodies(handle, c_loc(ids), 0.0_dp, 0, c_null_ptr, c_null_ptr, c_null_ptr, c_loc(e))
      else
        code = c_scene_set_bodies(handle, c_loc(ids), 0.0_dp, bodies%n, c_loc(mass), c_loc(com), c_loc(inertia), &
          c_loc(e))
      end if
      call check(error, code == 0, "set_bodies: "//message_of(e))
      if (allocated(error)) return
      code = compute(handle, res, e)
      call check(error, code == 0 .and. res%omega_max == c%omega_max .and. res%dt_critical_eigen == &
        c%dt_critical_eigen .and. res%dt_critical_bound == c%dt_critical_bound .and. res%dt_contact_rule == &
        c%dt_contact_rule .and. res%n_dof == c%n_dof .and. res%dof_per_particle == 6, &
        "bodies: the library's numbers bit for bit: "//message_of(e))
      if (allocated(error)) return
      code = c_scene_body_peer_steps(handle, c_loc(gst), c_loc(exa), c_loc(e))
      call body_gst_step(scene, bodies, dt_gst, status)
      call body_exadem_step(scene, bodies, dt_exa, status)
      call check(error, code == 0 .and. gst == dt_gst .and. exa == dt_exa, "peers' rules: "//message_of(e))
      if (allocated(error)) return
      ! the impact linearisation and the pre-stress are not offered for bodies
      code = c_scene_compute(handle, hertz_linearization%impact, 1.0_dp, 0, 0, c_loc(res), c_sizeof(res), c_loc(e))
      call check(error, code == demstep_stat%invalid_input .and. index(message_of(e), "with bodies") > 0, &
        "HERTZ_IMPACT with bodies: "//message_of(e))
      if (allocated(error)) return
      code = c_scene_compute(handle, hertz_linearization%current, 0.0_dp, 1, 0, c_loc(res), c_sizeof(res), c_loc(e))
      call check(error, code == demstep_stat%invalid_input, "prestress with bodies: "//message_of(e))
      if (allocated(error)) return
      code = c_scene_set_bodies(handle, c_loc(ids), 0.0_dp, 0, c_null_ptr, c_null_ptr, c_null_ptr, c_loc(e))
      call check(error, code == demstep_stat%invalid_input .and. index(message_of(e), "already set") > 0, &
        "bodies twice: "//message_of(e))
      if (allocated(error)) return
      code = c_scene_free(c_loc(handle), c_loc(e))
    end do
    ! a singular tensor (body 2 of 12), by name and 0-based index
    inertia(10:18) = 0.0_dp
    code = c_scene_create(3, c_loc(handle), c_loc(e))
    code = c_scene_set_bodies(handle, c_loc(ids), 0.0_dp, 0, c_null_ptr, c_null_ptr, c_null_ptr, c_loc(e))
    call check(error, code == demstep_stat%invalid_input .and. index(message_of(e), "no particles") > 0, &
      "bodies before the particles: "//message_of(e))
    if (allocated(error)) return
    code = c_scene_set_particles(handle, scene%n, c_loc(x), c_loc(m), c_loc(r), c_null_ptr, c_null_ptr, &
      c_null_ptr, c_loc(e))
    code = c_scene_body_peer_steps(handle, c_loc(gst), c_loc(exa), c_loc(e))
    call check(error, code == demstep_stat%invalid_input .and. index(message_of(e), "no bodies") > 0, &
      "peers' rules without bodies: "//message_of(e))
    if (allocated(error)) return
    code = c_scene_set_bodies(handle, c_loc(ids), 0.0_dp, bodies%n, c_loc(mass), c_loc(com), c_loc(inertia), &
      c_loc(e))
    call check(error, code == demstep_stat%invalid_input .and. where_of(e) == "inertia" .and. e%index == 1, &
      "singular tensor: "//where_of(e)//" "//message_of(e))
    if (allocated(error)) return
    code = c_scene_free(c_loc(handle), c_loc(e))
    ! a bonded pair (a 0.1 gap: no contact), Yade's CohFrictPhys bond
    x2 = [0.0_dp, 0.0_dp, 0.0_dp, 1.2_dp, 1.1_dp, 0.9_dp]
    m2 = [1.0_dp, 1.5_dp]
    r2 = [1.0_dp, 0.9_dp]
    pair = [0, 1]
    p = [1.0e5_dp, 0.3_dp, 2.0_dp, 2.0_dp]
    code = c_scene_create(3, c_loc(handle), c_loc(e))
    code = c_scene_set_particles(handle, 2, c_loc(x2), c_loc(m2), c_loc(r2), c_null_ptr, c_null_ptr, &
      c_null_ptr, c_loc(e))
    code = c_scene_add_bonds(handle, 1, c_loc(pair), c_loc(e))
    code = c_scene_set_bond_model(handle, bond_model%yade, 4, c_loc(p), c_loc(e))
    call check(error, code == 0, "bond model: "//message_of(e))
    if (allocated(error)) return
    code = compute(handle, res, e)
    call new_scene(scene, 3, reshape(x2, [3, 2]), m2, r2, status)
    call scene_add_bonds(scene, reshape([1, 2], [2, 1]), status)
    call scene_set_bond_model(scene, bond_model%yade, p, status)
    call assembly_critical_steps(scene, c, status)
    call check(error, code == 0 .and. status%stat == demstep_stat%ok .and. res%omega_max == c%omega_max .and. &
      res%dt_critical_eigen == c%dt_critical_eigen .and. res%dof_per_particle == 6, &
      "bonds: the library's numbers bit for bit: "//message_of(e))
    if (allocated(error)) return
    code = c_scene_free(c_loc(handle), c_loc(e))
    p(2) = -0.3_dp
    code = c_scene_create(3, c_loc(handle), c_loc(e))
    code = c_scene_set_particles(handle, 2, c_loc(x2), c_loc(m2), c_loc(r2), c_null_ptr, c_null_ptr, &
      c_null_ptr, c_loc(e))
    code = c_scene_set_bond_model(handle, bond_model%yade, 4, c_loc(p), c_loc(e))
    call check(error, code == demstep_stat%invalid_input .and. where_of(e) == "bond_parameters" .and. &
      e%index == 1, "negative bond parameter: "//where_of(e)//" "//message_of(e))
    if (allocated(error)) return
    code = c_scene_free(c_loc(handle), c_loc(e))
  end subroutine test_scene_bodies

  !> Compute with the defaults (current overlap, no pre-stress, default eigen limit).
  integer function compute(handle, res, e) result(code)
    type(c_ptr), intent(in) :: handle
    type(demstep_scene_result_c), intent(inout), target :: res
    type(demstep_error_c), intent(inout), target :: e
    code = c_scene_compute(handle, hertz_linearization%current, 0.0_dp, 0, 0, c_loc(res), &
      c_sizeof(res), c_loc(e))
  end function compute

  !> The chain built through the handle gives the Fortran API's numbers bit for
  !> bit, and omega_max of the fixed-fixed chain of 10 free masses is
  !> 2 sqrt(k/m) sin(10 pi/22) (the largest of 2 sqrt(k/m) sin(j pi/(2 (N+1))));
  !> 1e-12 relative: dsyevr's eigenvalue of this 10 x 10 matrix is within a few
  !> eps of ||A|| = 4 k/m.
  subroutine test_scene_chain(error)
    type(error_type), allocatable, intent(out) :: error
    !> A result struct of a later version: this one's fields, then more.
    type, bind(C) :: newer_result_c
      type(demstep_scene_result_c) :: res
      real(c_double) :: appended
    end type newer_result_c
    type(c_ptr), target :: handle
    type(demstep_error_c), target :: e
    type(demstep_scene_result_c), target :: res, res2
    type(newer_result_c), target :: newer
    type(scene_type) :: scene
    type(critical_step_type) :: c
    type(demstep_status_type) :: status
    real(dp) :: x(1, 12), exact
    integer :: i, code
    call chain_handle(handle, e, code)
    call check(error, code == 0 .and. c_associated(handle), "chain built: "//message_of(e))
    if (allocated(error)) return
    code = compute(handle, res, e)
    call check(error, code, 0, message="compute: "//message_of(e))
    if (allocated(error)) return
    x(1, :) = [(real(i, dp), i = 1, 12)]
    call new_scene(scene, 1, x, spread(1.0_dp, 1, 12), spread(0.3_dp, 1, 12), status, &
      fixed=[.true., (.false., i = 2, 11), .true.])
    call scene_add_bonds(scene, reshape([(i, i + 1, i = 1, 11)], [2, 11]), status)
    scene%k_bond = 100.0_dp
    scene%effects = .false.
    call assembly_critical_steps(scene, c, status)
    call check(error, res%omega_max == c%omega_max .and. res%dt_critical_eigen == c%dt_critical_eigen &
      .and. res%omega_bound == c%omega_bound .and. res%dt_critical_bound == c%dt_critical_bound .and. &
      res%dt_contact_rule == c%dt_contact_rule .and. res%damping_ratio_top == c%damping_ratio_top .and. &
      res%dt_critical_damped == c%dt_critical_damped, "the Fortran numbers bit for bit")
    if (allocated(error)) return
    call check(error, res%n_dof == 10 .and. res%n_springs == 11 .and. res%dof_per_particle == 1 .and. &
      res%eigen_computed == 1 .and. res%rotation == 0 .and. res%tangential == 0 .and. res%periodic == 0 &
      .and. res%prestress == 0, "counts and flags")
    if (allocated(error)) return
    exact = 2.0_dp*sqrt(100.0_dp)*sin(10.0_dp*pi/22.0_dp)
    call check(error, res%omega_max, exact, rel=.true., thr=1.0e-12_dp, message="omega_max closed form")
    if (allocated(error)) return
    ! above max_eigen_dof Lanczos: the same omega_max to its tolerance
    code = c_scene_compute(handle, hertz_linearization%current, 0.0_dp, 0, 5, c_loc(res), c_sizeof(res), &
      c_loc(e))
    call check(error, code == 0 .and. res%eigen_computed == 1 .and. res%eigen_solver == eigen_solver%lanczos &
      .and. res%eigen_converged == 1 .and. res%eigen_tolerance == lanczos_tolerance_default .and. &
      res%eigen_residual <= lanczos_tolerance_default .and. res%eigen_products > 0, &
      "max_eigen_dof 5 < 10 dof: Lanczos")
    if (allocated(error)) return
    ! (omega to half the default tolerance on omega^2)
    call check(error, res%omega_max, exact, rel=.true., thr=0.5_dp*lanczos_tolerance_default, &
      message="Lanczos omega_max")
    if (allocated(error)) return
    call check(error, res%omega_upper >= exact*(1.0_dp - 1.0e-15_dp) .and. &
      res%dt_critical_safe <= 2.0_dp/exact*(1.0_dp + 1.0e-15_dp), "the error bar holds the closed form")
    if (allocated(error)) return
    ! eigen solver 'none': only the bound, the exact fields stay 0
    code = c_scene_set_eigen_solver(handle, eigen_solver%none, 0.0_dp, c_loc(e))
    call check(error, code, 0, message="set_eigen_solver none")
    if (allocated(error)) return
    code = c_scene_compute(handle, hertz_linearization%current, 0.0_dp, 0, 0, c_loc(res), c_sizeof(res), &
      c_loc(e))
    call check(error, code == 0 .and. res%eigen_computed == 0 .and. res%omega_max == 0.0_dp .and. &
      res%eigen_solver == eigen_solver%none .and. res%dt_critical_bound == c%dt_critical_bound .and. &
      res%dt_critical_damped == c%dt_critical_bound, "eigen solver none: the bound only")
    if (allocated(error)) return
    ! bad options refused by name, the options kept
    code = c_scene_set_eigen_solver(handle, 5, 0.0_dp, c_loc(e))
    call check(error, code == demstep_stat%invalid_input .and. index(message_of(e), "solver: 5") > 0, &
      "solver 5 refused")
    if (allocated(error)) return
    code = c_scene_set_eigen_solver(handle, eigen_solver%lanczos, 0.5_dp, c_loc(e))
    call check(error, code == demstep_stat%invalid_input .and. index(message_of(e), "tolerance") > 0, &
      "tolerance 0.5 refused")
    if (allocated(error)) return
    code = c_scene_set_eigen_solver(handle, eigen_solver%auto, 0.0_dp, c_loc(e))
    if (allocated(error)) return
    ! a caller's struct with a field appended after this version's: filled up to
    ! this version's size, the rest zeroed
    newer%res%omega_max = -1.0_dp
    newer%appended = -1.0_dp
    code = c_scene_compute(handle, hertz_linearization%current, 0.0_dp, 0, 0, c_loc(newer), &
      c_sizeof(newer), c_loc(e))
    call check(error, code == 0 .and. newer%res%omega_max == c%omega_max .and. newer%appended == 0.0_dp, &
      "a larger result_size")
    if (allocated(error)) return
    ! the dashpot effect through its flag and the ratio through its setter
    code = c_scene_set_damping(handle, 0.2_dp, c_loc(e))
    code = c_scene_set_effects(handle, capi_effect%damping, c_loc(e))
    code = compute(handle, res, e)
    call check(error, code == 0 .and. res%damping_ratio_top > 0.0_dp .and. &
      res%dt_critical_damped < res%dt_critical_eigen .and. res%damped_exact == 1 .and. &
      res%dt_critical_damped_bound <= res%dt_critical_damped .and. res%damped_solves > 0, &
      "damped chain, exact: "//message_of(e))
    if (allocated(error)) return
    ! the other dashpots and the rolling springs through their setters; bad values refused
    code = c_scene_set_dashpots(handle, 0.1_dp, 0.0_dp, 0.5_dp, c_loc(e))
    call check(error, code == 0, "dashpots: "//message_of(e))
    if (allocated(error)) return
    code = compute(handle, res2, e)
    call check(error, code == 0 .and. res2%dt_critical_damped < res%dt_critical_damped, &
      "a drag lowers the damped limit: "//message_of(e))
    if (allocated(error)) return
    code = c_scene_set_rolling(handle, -1.0_dp, 0.0_dp, c_loc(e))
    call check(error, code == demstep_stat%invalid_input .and. index(message_of(e), "rolling_ratio") > 0, &
      "rolling_ratio -1 refused")
    if (allocated(error)) return
    code = c_scene_free(c_loc(handle), c_loc(e))
    call check(error, code == 0 .and. .not. c_associated(handle), "free sets the handle to NULL")
  end subroutine test_scene_chain

  !> Closed forms, 1e-12 relative (eigenvalues of 1 x 1 to 2 x 2 matrices, a few
  !> eps): a particle of mass m pressed on a wall, omega = sqrt(k/m); two unit
  !> masses touching through a periodic boundary, omega = sqrt(2 k); a Hertz
  !> wall contact linearised at the current overlap d0, k = 2 E* sqrt(R d0), and
  !> at an impact at v, d = (15 m v^2/(16 E* sqrt(R)))^(2/5); per-type materials.
  subroutine test_scene_models(error)
    type(error_type), allocatable, intent(out) :: error
    type(c_ptr), target :: handle
    type(demstep_error_c), target :: e
    type(demstep_scene_result_c), target :: res
    real(c_double), target :: x2(2), m2(2), r2(2), p1(1), one(1), lo(1), hi(1), pt(2), nm(2), &
      kk(2, 2), young(2), poisson(2)
    integer(c_int), target :: periodic(1), types(2)
    real(dp) :: d, k, e_star
    integer :: code
    ! a 2D particle of mass 2 on the wall y = 0: overlap 0.1, k = 1e4
    x2 = [0.0_dp, 0.9_dp]
    m2(1) = 2.0_dp
    r2(1) = 1.0_dp
    pt = 0.0_dp
    nm = [0.0_dp, 1.0_dp]
    code = c_scene_create(2, c_loc(handle), c_loc(e))
    code = c_scene_set_particles(handle, 1, c_loc(x2), c_loc(m2), c_loc(r2), c_null_ptr, c_null_ptr, &
      c_null_ptr, c_loc(e))
    code = c_scene_add_walls(handle, 1, c_loc(pt), c_loc(nm), c_loc(e))
    code = c_scene_set_contact_law(handle, contact_law%linear, 1.0e4_dp, 0.0_dp, c_loc(e))
    code = c_scene_set_effects(handle, capi_effect%walls, c_loc(e))
    code = compute(handle, res, e)
    call check(error, code == 0 .and. res%n_dof == 2 .and. res%n_springs == 1, "wall: "//message_of(e))
    if (allocated(error)) return
    call check(error, res%omega_max, sqrt(1.0e4_dp/2.0_dp), rel=.true., thr=1.0e-12_dp, message="wall omega")
    if (allocated(error)) return
    call check(error, res%dt_contact_rule, 2.0_dp*sqrt(2.0_dp/1.0e4_dp), rel=.true., thr=1.0e-12_dp, &
      message="wall contact rule")
    if (allocated(error)) return
    code = c_scene_free(c_loc(handle), c_loc(e))

    ! 1D, cell [0, 4): particles at 0.5 and 3.6 (radius 0.5) touch through the
    ! boundary, overlap 0.1; without the cell they are 3.1 apart
    x2 = [0.5_dp, 3.6_dp]
    m2 = 1.0_dp
    r2 = 0.5_dp
    code = c_scene_create(1, c_loc(handle), c_loc(e))
    code = c_scene_set_particles(handle, 2, c_loc(x2), c_loc(m2), c_loc(r2), c_null_ptr, c_null_ptr, &
      c_null_ptr, c_loc(e))
    code = c_scene_set_contact_law(handle, contact_law%linear, 1.0e4_dp, 0.0_dp, c_loc(e))
    code = compute(handle, res, e)
    call check(error, code == 1 .and. index(message_of(e), "position:") > 0, "no cell, no contact: " &
      //message_of(e))
    if (allocated(error)) return
    periodic = 1
    lo = 0.0_dp
    hi = 4.0_dp
    code = c_scene_set_cell(handle, c_loc(periodic), c_loc(lo), c_loc(hi), c_loc(e))
    call check(error, code, 0, message="cell: "//message_of(e))
    if (allocated(error)) return
    code = compute(handle, res, e)
    call check(error, code == 0 .and. res%periodic == 1 .and. res%n_springs == 1, "periodic: "//message_of(e))
    if (allocated(error)) return
    call check(error, res%omega_max, sqrt(2.0e4_dp), rel=.true., thr=1.0e-12_dp, message="periodic omega")
    if (allocated(error)) return
    code = c_scene_free(c_loc(handle), c_loc(e))

    ! Hertz on a wall in 1D: mass 1, R 0.5, overlap 0.05, E* = 1e7
    p1 = 0.45_dp
    one = 1.0_dp
    r2(1) = 0.5_dp
    code = c_scene_create(1, c_loc(handle), c_loc(e))
    code = c_scene_set_particles(handle, 1, c_loc(p1), c_loc(one), c_loc(r2), c_null_ptr, c_null_ptr, &
      c_null_ptr, c_loc(e))
    lo = 0.0_dp
    hi = 1.0_dp
    code = c_scene_add_walls(handle, 1, c_loc(lo), c_loc(hi), c_loc(e))
    code = c_scene_set_contact_law(handle, contact_law%hertz, 1.0e7_dp, 0.0_dp, c_loc(e))
    code = c_scene_set_effects(handle, capi_effect%walls, c_loc(e))
    code = compute(handle, res, e)
    k = 2.0e7_dp*sqrt(0.5_dp*0.05_dp)
    call check(error, code, 0, message="Hertz current: "//message_of(e))
    if (allocated(error)) return
    call check(error, res%omega_max, sqrt(k), rel=.true., thr=1.0e-12_dp, message="Hertz current omega")
    if (allocated(error)) return
    code = c_scene_compute(handle, hertz_linearization%impact, 2.0_dp, 0, 0, c_loc(res), c_sizeof(res), &
      c_loc(e))
    d = (15.0_dp*4.0_dp/(16.0_dp*1.0e7_dp*sqrt(0.5_dp)))**0.4_dp
    k = 2.0e7_dp*sqrt(0.5_dp*d)
    call check(error, code, 0, message="Hertz impact: "//message_of(e))
    if (allocated(error)) return
    call check(error, res%omega_max, sqrt(k), rel=.true., thr=1.0e-12_dp, message="Hertz impact omega")
    if (allocated(error)) return
    code = c_scene_compute(handle, hertz_linearization%impact, 0.0_dp, 0, 0, c_loc(res), c_sizeof(res), &
      c_loc(e))
    call check(error, code == 1 .and. index(message_of(e), "impact_velocity") > 0, "impact at v = 0: " &
      //message_of(e))
    if (allocated(error)) return
    code = c_scene_compute(handle, hertz_linearization%current, 0.0_dp, 1, 0, c_loc(res), c_sizeof(res), &
      c_loc(e))
    call check(error, code == 0 .and. res%prestress == 1, "prestress flag: "//message_of(e))
    if (allocated(error)) return
    code = c_scene_free(c_loc(handle), c_loc(e))

    ! per-type materials, 1D: particles 0 and 0.9 (radius 0.5) of types 0 and 1,
    ! overlap 0.1; linear k(0, 1) = 3e4, omega^2 = 2 k; Hertz with E = 1e9, nu = 0.25
    ! for both: E* = E/(2 (1 - nu^2)), k = 2 E* sqrt(R* d) with R* = 0.25
    x2 = [0.0_dp, 0.9_dp]
    types = [0, 1]
    kk = reshape([1.0e4_dp, 3.0e4_dp, 3.0e4_dp, 5.0e4_dp], [2, 2])
    code = c_scene_create(1, c_loc(handle), c_loc(e))
    code = c_scene_set_particles(handle, 2, c_loc(x2), c_loc(m2), c_loc(r2), c_null_ptr, c_null_ptr, &
      c_null_ptr, c_loc(e))
    code = c_scene_set_types(handle, 2, c_loc(types), c_loc(kk), c_null_ptr, c_loc(e))
    call check(error, code, 0, message="types: "//message_of(e))
    if (allocated(error)) return
    code = compute(handle, res, e)
    call check(error, code, 0, message="types compute: "//message_of(e))
    if (allocated(error)) return
    call check(error, res%omega_max, sqrt(6.0e4_dp), rel=.true., thr=1.0e-12_dp, message="types omega")
    if (allocated(error)) return
    code = c_scene_free(c_loc(handle), c_loc(e))
    young = 1.0e9_dp
    poisson = 0.25_dp
    code = c_scene_create(1, c_loc(handle), c_loc(e))
    code = c_scene_set_particles(handle, 2, c_loc(x2), c_loc(m2), c_loc(r2), c_null_ptr, c_null_ptr, &
      c_null_ptr, c_loc(e))
    code = c_scene_set_hertz_types(handle, 2, c_loc(types), c_loc(young), c_loc(poisson), c_loc(e))
    call check(error, code, 0, message="Hertz types: "//message_of(e))
    if (allocated(error)) return
    code = compute(handle, res, e)
    e_star = 1.0e9_dp/(2.0_dp*(1.0_dp - 0.25_dp**2))
    k = 2.0_dp*e_star*sqrt(0.25_dp*0.1_dp)
    call check(error, code, 0, message="Hertz types compute: "//message_of(e))
    if (allocated(error)) return
    call check(error, res%omega_max, sqrt(2.0_dp*k), rel=.true., thr=1.0e-12_dp, message="Hertz types omega")
    if (allocated(error)) return
    code = c_scene_free(c_loc(handle), c_loc(e))
  end subroutine test_scene_models

  !> Each DEMSTEP_EFFECT_* flag, by name, switches on exactly the library effect
  !> of that name; 0 switches all off; the sum all on.
  subroutine test_scene_effects(error)
    type(error_type), allocatable, intent(out) :: error
    type(c_ptr), target :: handle
    type(demstep_error_c), target :: e
    type(capi_scene_type), pointer :: h
    integer :: pairs(2, 6), k, code
    pairs = reshape([capi_effect%contacts, scene_effect%contacts, capi_effect%gravity, scene_effect%gravity, &
      capi_effect%damping, scene_effect%damping, capi_effect%local_damping, scene_effect%local_damping, &
      capi_effect%walls, scene_effect%walls, capi_effect%rotation, scene_effect%rotation], [2, 6])
    call check(error, n_effects, 6, message="every library effect has a C flag here")
    if (allocated(error)) return
    call check(error, size(capi_effect_map, 2), n_effects, message="the C API maps every effect")
    if (allocated(error)) return
    code = c_scene_create(2, c_loc(handle), c_loc(e))
    call c_f_pointer(handle, h)
    do k = 1, 6
      code = c_scene_set_effects(handle, pairs(1, k), c_loc(e))
      call check(error, code == 0 .and. h%scene%effects(pairs(2, k)) .and. count(h%scene%effects) == 1, &
        "flag "//trim(scene_effect_names(pairs(2, k))))
      if (allocated(error)) return
    end do
    code = c_scene_set_effects(handle, 0, c_loc(e))
    call check(error, code == 0 .and. .not. any(h%scene%effects), "0: no effect")
    if (allocated(error)) return
    code = c_scene_set_effects(handle, sum(pairs(1, :)), c_loc(e))
    call check(error, code == 0 .and. all(h%scene%effects), "every flag: every effect")
    if (allocated(error)) return
    code = c_scene_free(c_loc(handle), c_loc(e))
  end subroutine test_scene_effects

  subroutine test_scene_bad_input(error)
    type(error_type), allocatable, intent(out) :: error
    type(c_ptr), target :: handle, none
    type(demstep_error_c), target :: e
    type(demstep_scene_result_c), target :: res
    type(capi_scene_type), target :: stranger
    real(c_double), target :: x(2), m(2), rad(2)
    integer(c_int), target :: bonds(2), chain_types(12)
    integer :: code, i
    character(len=:), allocatable :: first
    x = [0.0_dp, 1.0_dp]
    m = [1.0_dp, 1.0_dp]
    rad = [0.3_dp, 0.3_dp]
    ! create: NULL out pointer, dim out of range (the library's message)
    code = c_scene_create(1, c_null_ptr, c_loc(e))
    call check(error, code == 1 .and. index(message_of(e), "NULL") > 0, "create into NULL")
    if (allocated(error)) return
    do i = 0, 4, 4
      handle = c_loc(e)
      code = c_scene_create(i, c_loc(handle), c_loc(e))
      call check(error, code == 1 .and. index(message_of(e), "dim:") > 0 .and. .not. c_associated(handle), &
        "dim out of range: "//message_of(e))
      if (allocated(error)) return
    end do
    ! a NULL or foreign handle
    code = c_scene_set_effects(c_null_ptr, 1, c_loc(e))
    call check(error, code == 1 .and. index(message_of(e), "scene is NULL") > 0, "NULL handle")
    if (allocated(error)) return
    code = c_scene_compute(c_loc(stranger), 1, 0.0_dp, 0, 0, c_loc(res), c_sizeof(res), c_loc(e))
    call check(error, code == 1 .and. index(message_of(e), "not a live handle") > 0, "foreign handle: " &
      //message_of(e))
    if (allocated(error)) return
    ! no particles (n = 0), NULL positions; a scene without particles computes nothing
    code = c_scene_create(1, c_loc(handle), c_loc(e))
    code = compute(handle, res, e)
    call check(error, code == 1 .and. index(message_of(e), "no particles") > 0, "compute without particles")
    if (allocated(error)) return
    code = c_scene_set_particles(handle, 0, c_loc(x), c_loc(m), c_loc(rad), c_null_ptr, c_null_ptr, &
      c_null_ptr, c_loc(e))
    call check(error, code, 1, message="no particles")
    if (allocated(error)) return
    code = c_scene_free(c_loc(handle), c_loc(e))
    code = c_scene_create(1, c_loc(handle), c_loc(e))
    code = c_scene_set_particles(handle, 2, c_null_ptr, c_loc(m), c_loc(rad), c_null_ptr, c_null_ptr, &
      c_null_ptr, c_loc(e))
    call check(error, code, 1, message="NULL positions")
    if (allocated(error)) return
    code = c_scene_free(c_loc(handle), c_loc(e))
    ! a bond to a missing particle; then the scene is unusable, quoting it
    code = c_scene_create(1, c_loc(handle), c_loc(e))
    code = c_scene_set_particles(handle, 2, c_loc(x), c_loc(m), c_loc(rad), c_null_ptr, c_null_ptr, &
      c_null_ptr, c_loc(e))
    call check(error, code, 0, message="two particles: "//message_of(e))
    if (allocated(error)) return
    code = c_scene_set_particles(handle, 2, c_loc(x), c_loc(m), c_loc(rad), c_null_ptr, c_null_ptr, &
      c_null_ptr, c_loc(e))
    call check(error, code == 1 .and. index(message_of(e), "already") > 0, "particles twice: "//message_of(e))
    if (allocated(error)) return
    code = c_scene_free(c_loc(handle), c_loc(e))
    code = c_scene_create(1, c_loc(handle), c_loc(e))
    code = c_scene_set_particles(handle, 2, c_loc(x), c_loc(m), c_loc(rad), c_null_ptr, c_null_ptr, &
      c_null_ptr, c_loc(e))
    code = c_scene_add_bonds(handle, 1, c_null_ptr, c_loc(e))
    call check(error, code == 1 .and. index(message_of(e), "NULL") > 0, "NULL bonds")
    if (allocated(error)) return
    code = c_scene_free(c_loc(handle), c_loc(e))
    code = c_scene_create(1, c_loc(handle), c_loc(e))
    code = c_scene_set_particles(handle, 2, c_loc(x), c_loc(m), c_loc(rad), c_null_ptr, c_null_ptr, &
      c_null_ptr, c_loc(e))
    bonds = [0, 5]
    code = c_scene_add_bonds(handle, 1, c_loc(bonds), c_loc(e))
    call check(error, code == 1 .and. index(message_of(e), "missing") > 0, "bond to a missing particle: " &
      //message_of(e))
    if (allocated(error)) return
    first = message_of(e)
    code = c_scene_set_bond_stiffness(handle, 1.0_dp, 0.0_dp, c_loc(e))
    call check(error, code == 1 .and. index(message_of(e), "unusable") > 0 .and. index(message_of(e), &
      "missing") > 0, "a builder after the failure: "//message_of(e))
    if (allocated(error)) return
    code = compute(handle, res, e)
    call check(error, code == 1 .and. index(message_of(e), first) > 0, "compute after the failure quotes it: " &
      //message_of(e))
    if (allocated(error)) return
    code = c_scene_free(c_loc(handle), c_loc(e))
    call check(error, code == 0 .and. .not. c_associated(handle), "free after the failure")
    if (allocated(error)) return
    ! free: NULL, a NULL handle, twice
    code = c_scene_free(c_null_ptr, c_null_ptr)
    call check(error, code, 0, message="free(NULL)")
    if (allocated(error)) return
    none = c_null_ptr
    code = c_scene_free(c_loc(none), c_loc(e))
    call check(error, code, 0, message="free of a NULL handle (a second free)")
    if (allocated(error)) return

    ! bad enums and flags, each named; a scene that computes without them
    call chain_handle(handle, e, code)
    code = c_scene_compute(handle, 0, 0.0_dp, 0, 0, c_loc(res), c_sizeof(res), c_loc(e))
    call check(error, code == 1 .and. index(message_of(e), "hertz_linearization: 0") > 0, &
      "hertz_linearization 0: "//message_of(e))
    if (allocated(error)) return
    code = c_scene_compute(handle, 3, 1.0_dp, 0, 0, c_loc(res), c_sizeof(res), c_loc(e))
    call check(error, code == 1 .and. index(message_of(e), "hertz_linearization: 3") > 0, &
      "hertz_linearization 3")
    if (allocated(error)) return
    code = c_scene_compute(handle, 1, 0.0_dp, 2, 0, c_loc(res), c_sizeof(res), c_loc(e))
    call check(error, code == 1 .and. index(message_of(e), "prestress: 2") > 0, "prestress 2")
    if (allocated(error)) return
    code = c_scene_compute(handle, 1, 0.0_dp, 0, 0, c_null_ptr, c_sizeof(res), c_loc(e))
    call check(error, code == 1 .and. index(message_of(e), "result is NULL") > 0, "NULL result")
    if (allocated(error)) return
    code = c_scene_compute(handle, 1, 0.0_dp, 0, 0, c_loc(res), capi_scene_result_size_v1 - 1_c_size_t, c_loc(e))
    call check(error, code == 1 .and. index(message_of(e), "result_size") > 0, "result_size too small")
    if (allocated(error)) return
    call check(error, c_sizeof(res) >= capi_scene_result_size_v1, "the struct holds the first version")
    if (allocated(error)) return
    ! compute failures leave the scene usable
    code = compute(handle, res, e)
    call check(error, code, 0, message="compute after refused options: "//message_of(e))
    if (allocated(error)) return
    code = c_scene_set_contact_law(handle, 3, 1.0_dp, 0.0_dp, c_loc(e))
    call check(error, code == 1 .and. index(message_of(e), "law: 3") > 0 .and. index(message_of(e), &
      "hertz") > 0, "law 3: "//message_of(e))
    if (allocated(error)) return
    code = c_scene_free(c_loc(handle), c_loc(e))
    call chain_handle(handle, e, code)
    code = c_scene_set_contact_law(handle, 0, 1.0_dp, 0.0_dp, c_loc(e))
    call check(error, code == 1 .and. index(message_of(e), "law: 0") > 0, "law 0")
    if (allocated(error)) return
    code = c_scene_free(c_loc(handle), c_loc(e))
    call chain_handle(handle, e, code)
    code = c_scene_set_contact_law(handle, contact_law%linear, ieee_nan(), 0.0_dp, c_loc(e))
    call check(error, code == 1 .and. index(message_of(e), "k_normal") > 0, "NaN k_normal")
    if (allocated(error)) return
    code = c_scene_free(c_loc(handle), c_loc(e))
    call chain_handle(handle, e, code)
    code = c_scene_set_effects(handle, capi_effect%walls + 64, c_loc(e))
    call check(error, code == 1 .and. index(message_of(e), "bit 6 (value 64)") > 0 .and. &
      index(message_of(e), "walls 16") > 0, "effect bit 64: "//message_of(e))
    if (allocated(error)) return
    code = c_scene_free(c_loc(handle), c_loc(e))
    call chain_handle(handle, e, code)
    code = c_scene_set_effects(handle, -1, c_loc(e))
    call check(error, code == 1 .and. index(message_of(e), "bit 6") > 0, "effects -1: "//message_of(e))
    if (allocated(error)) return
    code = c_scene_free(c_loc(handle), c_loc(e))
    call chain_handle(handle, e, code)
    code = c_scene_set_bond_stiffness(handle, -1.0_dp, 0.0_dp, c_loc(e))
    call check(error, code == 1 .and. index(message_of(e), "k_bond:") > 0, "negative k_bond")
    if (allocated(error)) return
    code = c_scene_free(c_loc(handle), c_loc(e))
    ! a Hertz law, then linear per-type materials: refused, naming the law
    call chain_handle(handle, e, code)
    code = c_scene_set_contact_law(handle, contact_law%hertz, 1.0e7_dp, 0.0_dp, c_loc(e))
    chain_types = 0
    code = c_scene_set_types(handle, 1, c_loc(chain_types), c_loc(x), c_null_ptr, c_loc(e))
    call check(error, code == 1 .and. index(message_of(e), "law:") > 0, "Hertz law, linear types: " &
      //message_of(e))
    if (allocated(error)) return
    code = c_scene_free(c_loc(handle), c_loc(e))
    ! 2e9 types: 8e18 pair values, refused before any is read
    call chain_handle(handle, e, code)
    chain_types = 0
    code = c_scene_set_types(handle, 2000000000, c_loc(chain_types), c_loc(x), c_null_ptr, c_loc(e))
    call check(error, code == 1 .and. index(message_of(e), "n_types: 2000000000") > 0, "2e9 types: " &
      //message_of(e))
    if (allocated(error)) return
    code = c_scene_free(c_loc(handle), c_loc(e))
    ! a NULL array to each builder that takes one: refused, naming it
    do i = 1, 6
      call chain_handle(handle, e, code)
      select case (i)
      case (1)
        code = c_scene_set_types(handle, 1, c_null_ptr, c_loc(x), c_null_ptr, c_loc(e))
      case (2)
        code = c_scene_set_hertz_types(handle, 1, c_loc(chain_types), c_null_ptr, c_loc(x), c_loc(e))
      case (3)
        code = c_scene_add_walls(handle, 1, c_null_ptr, c_loc(x), c_loc(e))
      case (4)
        code = c_scene_set_contacts(handle, 1, c_loc(bonds), c_null_ptr, c_loc(e))
      case (5)
        code = c_scene_set_cell(handle, c_loc(chain_types), c_null_ptr, c_loc(x), c_loc(e))
      case (6)
        code = c_scene_set_gravity(handle, c_null_ptr, c_loc(e))
      end select
      call check(error, code == 1 .and. index(message_of(e), "NULL") > 0, "a NULL array: "//message_of(e))
      if (allocated(error)) return
      code = c_scene_free(c_loc(handle), c_loc(e))
    end do
    ! an optional array with a bad value: the library's message
    code = c_scene_create(1, c_loc(handle), c_loc(e))
    rad = [0.3_dp, ieee_nan()]
    code = c_scene_set_particles(handle, 2, c_loc(x), c_loc(m), c_loc(m), c_null_ptr, c_loc(rad), &
      c_null_ptr, c_loc(e))
    call check(error, code == 1 .and. index(message_of(e), "inertia: particle 2") > 0, "NaN inertia: " &
      //message_of(e))
    if (allocated(error)) return
    code = c_scene_free(c_loc(handle), c_loc(e))
    ! gravity and damping: the library's checks
    call chain_handle(handle, e, code)
    x = [ieee_nan(), 0.0_dp]
    code = c_scene_set_gravity(handle, c_loc(x), c_loc(e))
    call check(error, code == 1 .and. index(message_of(e), "gravity:") > 0, "NaN gravity")
    if (allocated(error)) return
    code = c_scene_free(c_loc(handle), c_loc(e))
    call chain_handle(handle, e, code)
    ! refused by the setter itself (NaN was once accepted with DEMSTEP_OK)
    code = c_scene_set_damping(handle, -1.0_dp, c_loc(e))
    call check(error, code == 1 .and. index(message_of(e), "damping_ratio:") > 0, "negative damping: " &
      //message_of(e))
    if (allocated(error)) return
    code = c_scene_free(c_loc(handle), c_loc(e))
    call chain_handle(handle, e, code)
    code = c_scene_set_damping(handle, ieee_nan(), c_loc(e))
    call check(error, code == 1 .and. index(message_of(e), "damping_ratio:") > 0, "NaN damping: " &
      //message_of(e))
    if (allocated(error)) return
    code = c_scene_free(c_loc(handle), c_loc(e))
    call chain_handle(handle, e, code)
    code = c_scene_set_dashpots(handle, 0.1_dp, 0.0_dp, ieee_nan(), c_loc(e))
    call check(error, code == 1 .and. index(message_of(e), "drag:") > 0, "NaN drag: "//message_of(e))
    if (allocated(error)) return
    code = c_scene_free(c_loc(handle), c_loc(e))
  end subroutine test_scene_bad_input

  !> Every enum argument of the scalar functions, one below and one above its
  !> range: DEMSTEP_INVALID_INPUT with a message, never a silent default.
  subroutine test_bad_enums(error)
    type(error_type), allocatable, intent(out) :: error
    type(demstep_error_c), target :: e
    type(demstep_spring_c), target :: cs
    type(demstep_nroots_c), target :: cr
    type(demstep_stiffness_result_c), target :: res
    real(c_double), target :: value, lambdas(2)
    integer :: code, k, bad(2)
    character(len=8) :: which
    lambdas = [0.9_dp, 0.95_dp]
    do k = 1, 2
      write(which, '(i0)') k
      bad = [dashpot_kind%lagged - 1, dashpot_kind%centred + 1]
      code = c_spring_new(1.0_dp, 1.0_dp, 0.0_dp, 1, bad(k), c_loc(cs), c_loc(e))
      call check(error, code == 1 .and. index(message_of(e), "dashpot") > 0, "dashpot "//which//": " &
        //message_of(e))
      if (allocated(error)) return
      bad = [step_kind%fixed - 1, step_kind%rounded + 1]
      code = c_n_roots(0.9_dp, 1.0e-3_dp, bad(k), 0.5_dp, 1, 0.0_dp, 0.0_dp, c_loc(cr), c_loc(e))
      call check(error, code == 1 .and. index(message_of(e), "steps_kind: ") > 0, "steps_kind "//which//": " &
        //message_of(e))
      if (allocated(error)) return
      bad = [pick_kind%largest_step - 1, pick_kind%zero + 1]
      code = c_n_roots(0.9_dp, 1.0e-3_dp, 2, 0.5_dp, bad(k), 0.0_dp, 0.0_dp, c_loc(cr), c_loc(e))
      call check(error, code == 1 .and. index(message_of(e), "pick") > 0, "pick "//which//": "//message_of(e))
      if (allocated(error)) return
      bad = [aggregate_kind%mean - 1, aggregate_kind%max + 1]
      code = c_simulated_stiffness(0.01_dp, 1.0e5_dp, 1.0e-3_dp, c_loc(lambdas), 2, 2, 0.5_dp, 1, bad(k), &
        c_null_ptr, c_null_ptr, c_null_ptr, c_loc(res), c_loc(e))
      call check(error, code == 1 .and. index(message_of(e), "aggregate") > 0, "aggregate "//which//": " &
        //message_of(e))
      if (allocated(error)) return
      bad = [quantity_kind%restitution - 1, quantity_kind%period + 1]
      code = c_n_for_tolerance(bad(k), 1.0e-3_dp, 0.0_dp, 0.0_dp, c_loc(value), c_loc(e))
      call check(error, code == 1 .and. index(message_of(e), "quantity") > 0, "quantity "//which//": " &
        //message_of(e))
      if (allocated(error)) return
    end do
  end subroutine test_bad_enums

  !> demstep_snapshot_read/_get/_free on LIGGGHTS' own dump and data file: the
  !> arrays read_snapshot gives (types 0-based), masses from a density per type;
  !> a missing file, a bad format, NULLs and a dead handle as statuses.
  subroutine test_snapshot(error)
    type(error_type), allocatable, intent(out) :: error
    type(demstep_error_c), target :: e
    type(demstep_snapshot_info_c), target :: info
    type(c_ptr), target :: handle
    type(snapshot_type) :: f
    type(demstep_status_type) :: status
    character(kind=c_char, len=:), allocatable, target :: path
    integer(c_int64_t), allocatable, target :: ids(:)
    integer(c_int), allocatable, target :: types(:)
    real(c_double), allocatable, target :: x(:, :), mass(:), density(:)
    real(c_double), target :: rho(2)
    integer(c_int) :: code
    path = "test/data/liggghts/dump.liggghts"//c_null_char
    call read_snapshot(path(:len(path) - 1), f, status)
    call check(error, is_ok(status), "read_snapshot")
    if (allocated(error)) return
    code = c_snapshot_read(c_loc(path), snapshot_format%auto, 0, 0, c_null_ptr, c_loc(handle), c_loc(info), &
      c_loc(e))
    call check(error, code, demstep_stat%ok, message=message_of(e))
    if (allocated(error)) return
    call check(error, info%n == f%n .and. info%format == f%format .and. info%frame == f%frame .and. &
      info%n_frames == f%n_frames .and. info%timestep == f%timestep, "info counts")
    if (allocated(error)) return
    call check(error, all(info%lo == f%lo) .and. all(info%hi == f%hi) .and. &
      all((info%periodic == 1) .eqv. f%periodic) .and. (info%has_mass == 1 .eqv. f%has_mass), "info box")
    if (allocated(error)) return
    allocate(ids(f%n), types(f%n), x(3, f%n), mass(f%n))
    code = c_snapshot_get(handle, c_loc(ids), c_loc(types), c_loc(x), c_null_ptr, c_null_ptr, c_null_ptr, &
      c_loc(mass), c_null_ptr, c_loc(e))
    call check(error, code, demstep_stat%ok, message=message_of(e))
    if (allocated(error)) return
    call check(error, all(ids == f%id) .and. all(types == f%type - 1) .and. all(x == f%x) .and. &
      all(mass == f%mass), "arrays equal read_snapshot's")
    if (allocated(error)) return
    code = c_snapshot_free(c_loc(handle), c_loc(e))
    call check(error, code == demstep_stat%ok .and. .not. c_associated(handle), "free sets the handle to NULL")
    if (allocated(error)) return
    code = c_snapshot_free(c_loc(handle), c_loc(e))
    call check(error, code, demstep_stat%ok, message="a second free does nothing")
    if (allocated(error)) return
    ! a data file with masses from the densities per type given
    path = "test/data/liggghts/data.liggghts"//c_null_char
    rho = [1000.0_dp, 3000.0_dp]
    call read_snapshot(path(:len(path) - 1), f, status, type_density=rho)
    code = c_snapshot_read(c_loc(path), snapshot_format%lammps_data, 0, 2, c_loc(rho), c_loc(handle), &
      c_loc(info), c_loc(e))
    call check(error, code, demstep_stat%ok, message=message_of(e))
    if (allocated(error)) return
    allocate(density(info%n))
    deallocate(mass)
    allocate(mass(info%n))
    code = c_snapshot_get(handle, c_null_ptr, c_null_ptr, c_null_ptr, c_null_ptr, c_null_ptr, c_null_ptr, &
      c_loc(mass), c_loc(density), c_loc(e))
    call check(error, code == demstep_stat%ok .and. all(mass == f%mass) .and. all(density == f%density), &
      "data file: masses and densities")
    if (allocated(error)) return
    code = c_snapshot_free(c_loc(handle), c_loc(e))
    ! bad input
    path = "test/data/liggghts/no_such_file"//c_null_char
    code = c_snapshot_read(c_loc(path), snapshot_format%auto, 0, 0, c_null_ptr, c_loc(handle), c_loc(info), &
      c_loc(e))
    call check(error, code == demstep_stat%io_error .and. .not. c_associated(handle) .and. &
      index(message_of(e), "demstep_snapshot_read: test/data/liggghts/no_such_file") == 1, message_of(e))
    if (allocated(error)) return
    code = c_snapshot_read(c_loc(path), 7, 0, 0, c_null_ptr, c_loc(handle), c_loc(info), c_loc(e))
    call check(error, code == demstep_stat%invalid_input .and. index(message_of(e), "format: 7 is not") > 0, &
      message_of(e))
    if (allocated(error)) return
    code = c_snapshot_read(c_loc(path), 0, 0, 2, c_null_ptr, c_loc(handle), c_loc(info), c_loc(e))
    call check(error, code == demstep_stat%invalid_input .and. index(message_of(e), "type_density") > 0, &
      message_of(e))
    if (allocated(error)) return
    code = c_snapshot_read(c_null_ptr, 0, 0, 0, c_null_ptr, c_loc(handle), c_loc(info), c_loc(e))
    call check(error, code == demstep_stat%invalid_input .and. index(message_of(e), "is NULL") > 0, &
      message_of(e))
    if (allocated(error)) return
    code = c_snapshot_get(c_null_ptr, c_null_ptr, c_null_ptr, c_null_ptr, c_null_ptr, c_null_ptr, &
      c_null_ptr, c_null_ptr, c_null_ptr, c_loc(e))
    call check(error, code == demstep_stat%invalid_input .and. index(message_of(e), "snapshot is NULL") > 0, &
      message_of(e))
  end subroutine test_snapshot

  !> demstep_contact_parameters and demstep_peer_time_steps on example/material.nml's
  !> glass pair (1 and 2 mm beads, e = 0.9, 1 m/s): the library's numbers bit for
  !> bit in every convention; a bad convention, a bad Poisson ratio and NULLs as statuses.
  subroutine test_pair_and_peers(error)
    type(error_type), allocatable, intent(out) :: error
    type(demstep_error_c), target :: e
    type(demstep_material_pair_c), target :: cp
    type(demstep_code_contact_c), target :: out
    type(demstep_peer_steps_c), target :: peers
    type(material_pair_type) :: p
    type(effective_pair_type) :: eff
    type(contact_parameters_type) :: params
    type(peer_steps_type) :: steps
    type(demstep_status_type) :: status
    real(dp) :: dt
    integer(c_int) :: code
    integer :: convention
    cp%a = demstep_material_c(6.3e10_dp, 0.22_dp, 2500.0_dp, 0.5e-3_dp)
    cp%b = demstep_material_c(6.3e10_dp, 0.22_dp, 2500.0_dp, 1.0e-3_dp)
    cp%restitution = 0.9_dp
    cp%impact_velocity = 1.0_dp
    p%a = material_type(6.3e10_dp, 0.22_dp, 2500.0_dp, 0.5e-3_dp)
    p%b = material_type(6.3e10_dp, 0.22_dp, 2500.0_dp, 1.0e-3_dp)
    p%restitution = 0.9_dp
    p%impact_velocity = 1.0_dp
    call effective_pair(p%a, p%b, eff, status)
    do convention = code_convention%liggghts_hooke, code_convention%lammps_hertz_material
      call contact_parameters(p, convention, params, status)
      call convention_limit(params, eff%m_star, dt, status)
      code = c_contact_parameters(c_loc(cp), convention, c_loc(out), c_loc(e))
      call check(error, code, demstep_stat%ok, message=message_of(e))
      if (allocated(error)) return
      call check(error, out%k_n == params%k_n .and. out%k_t == params%k_t .and. out%gamma_n == params%gamma_n &
        .and. out%gamma_t == params%gamma_t .and. out%overlap == params%overlap .and. &
        out%t_contact == params%t_contact .and. out%code_collision_time == params%code_collision_time .and. &
        out%m_star == eff%m_star .and. out%dt_code == dt .and. dt > 0.0_dp, &
        "convention "//code_convention_names(convention))
      if (allocated(error)) return
    end do
    call peer_time_steps(p, steps, status)
    code = c_peer_time_steps(c_loc(cp), c_loc(peers), c_loc(e))
    call check(error, code == demstep_stat%ok .and. peers%rayleigh == steps%rayleigh .and. &
      peers%rayleigh_yade == steps%rayleigh_yade .and. peers%hertz_duration == steps%hertz_duration .and. &
      peers%hertz_liggghts == steps%hertz_liggghts .and. all(peers%dt == steps%dt) .and. &
      all(peers%dt > 0.0_dp), "peer rules")
    if (allocated(error)) return
    code = c_contact_parameters(c_loc(cp), 10, c_loc(out), c_loc(e))
    call check(error, code == demstep_stat%invalid_input .and. index(message_of(e), "convention: 10 is not") > 0, &
      message_of(e))
    if (allocated(error)) return
    cp%b%poisson = 0.7_dp
    code = c_peer_time_steps(c_loc(cp), c_loc(peers), c_loc(e))
    call check(error, code == demstep_stat%invalid_input .and. &
      index(message_of(e), "demstep_peer_time_steps: ") == 1, message_of(e))
    if (allocated(error)) return
    code = c_peer_time_steps(c_null_ptr, c_loc(peers), c_loc(e))
    call check(error, code == demstep_stat%invalid_input .and. index(message_of(e), "is NULL") > 0, &
      message_of(e))
  end subroutine test_pair_and_peers

end module test_capi
