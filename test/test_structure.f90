!> The structural contracts: option enums own their words, library faults carry
!> their location as components (Fortran and C), result groups read back by name.
module test_structure
  use testdrive, only: new_unittest, unittest_type, error_type, check, test_failed
  use, intrinsic :: iso_c_binding, only: c_loc, c_null_char, c_ptr, c_int, c_double, c_null_ptr
  use demstep_kinds, only: dp, i8
  use demstep_text, only: uppercase
  use demstep_status, only: demstep_status_type, demstep_stat, set_status, status_at, status_restate
  use demstep_words, only: word_index, word_list, unknown_word
  use demstep_assembly, only: eigen_solver, eigen_solver_names, eigen_solver_from_name, eigen_solver_name, &
    hertz_linearization_names, hertz_linearization_from_name, hertz_linearization_name
  use demstep_interaction, only: contact_law_names, contact_law_from_name, contact_law_name
  use demstep_spring, only: dashpot_kind, dashpot_kind_names, dashpot_kind_from_name, dashpot_kind_name
  use demstep_stiffness, only: interval_kind, interval_kind_names, interval_kind_from_name, interval_kind_name, &
    aggregate_kind_names, aggregate_kind_from_name, aggregate_kind_name, pick_kind_names, pick_kind_from_name, &
    pick_kind_name
  use demstep_roots, only: scan_break, scan_break_names, scan_break_from_name, scan_break_name
  use demstep_harmonic, only: step_kind_names, step_kind_from_name, step_kind_name
  use demstep_contact, only: quantity_kind_names, quantity_kind_from_name, quantity_kind_name
  use demstep_material, only: code_convention_names, code_convention_from_name, code_convention_name, &
    peer_rule_names, peer_rule_from_name, peer_rule_name, material_type, material_pair_type, &
    peer_steps_type, peer_time_steps, packing_peer_steps, n_peer_rules
  use demstep_recommend, only: step_governs_names, step_governs_from_name, step_governs_name
  use demstep_scene_data, only: scene_effect_names, scene_effect_from_name, scene_effect_name
  use demstep_scene_builders, only: new_scene
  use demstep_scene_data, only: scene_type
  use demstep_snapshot, only: snapshot_format, snapshot_format_names, snapshot_format_from_name, &
    snapshot_format_name
  use demstep_results, only: result_group_type, parse_result, result_get, result_has
  use demstep_scene_input, only: scene_input_type, scene_setup_type, scene_from_input, scene_input_part
  use demstep_scene_builders, only: scene_set_law
  use demstep_assembly, only: critical_step_type, assembly_critical_steps, hertz_linearization
  use demstep_material, only: material_set_type, n_conventions
  use demstep_interaction, only: contact_law
  use demstep_capi, only: demstep_error_c, c_scene_create, c_scene_set_particles, c_scene_free
  implicit none
  private
  public :: collect_structure

contains

  !> The structure suite.
  subroutine collect_structure(testsuite)
    type(unittest_type), allocatable, intent(out) :: testsuite(:)
    testsuite = [ &
      new_unittest("every option enum: word -> code -> word, case and blanks ignored", test_words), &
      new_unittest("an unknown word: invalid input at the variable, the table listed", test_unknown_word), &
      new_unittest("status: where, index and detail; relabelled and restated", test_status_location), &
      new_unittest("library faults name the argument and element as components", test_library_location), &
      new_unittest("C API: demstep_error carries where and the 0-based index", test_c_location), &
      new_unittest("results by name: scalars, lists, repeats, texts, absent fields", test_results), &
      new_unittest("results by name: hostile values refused, never allocated", test_results_hostile), &
      new_unittest("peers' rules of a packing: the minimum over the pairs present", test_packing_peers), &
      new_unittest("scene from typed input: the builders' scene; faults at the component and part", &
        test_scene_input) &
      ]
  end subroutine collect_structure

  !> Round trip of one table: each word gives its code (offset for tables that
  !> start below 1) and the code gives the word back.
  subroutine round_trip(error, names, first, from_name_codes, name_of_codes, label)
    type(error_type), allocatable, intent(out) :: error
    character(len=*), intent(in) :: names(:)
    integer, intent(in) :: first
    integer, intent(in) :: from_name_codes(:)
    character(len=*), intent(in) :: name_of_codes(:)
    character(len=*), intent(in) :: label
    integer :: k
    do k = 1, size(names)
      call check(error, from_name_codes(k), first + k - 1, message=label//": "//trim(names(k)))
      if (allocated(error)) return
      call check(error, trim(name_of_codes(k)), trim(names(k)), message=label//": name of code")
      if (allocated(error)) return
    end do
  end subroutine round_trip

  subroutine test_words(error)
    type(error_type), allocatable, intent(out) :: error
    integer :: k, n, codes(32)
    character(len=32) :: got(32)
    do k = 1, size(eigen_solver_names)
      codes(k) = eigen_solver_from_name("  "//uppercase(eigen_solver_names(k)))
      got(k) = eigen_solver_name(1 + k - 1)
    end do
    n = size(eigen_solver_names)
    call round_trip(error, eigen_solver_names, 1, codes(:n), got(:n), "eigen_solver")
    if (allocated(error)) return
    do k = 1, size(hertz_linearization_names)
      codes(k) = hertz_linearization_from_name("  "//uppercase(hertz_linearization_names(k)))
      got(k) = hertz_linearization_name(1 + k - 1)
    end do
    n = size(hertz_linearization_names)
    call round_trip(error, hertz_linearization_names, 1, codes(:n), got(:n), "hertz_linearization")
    if (allocated(error)) return
    do k = 1, size(contact_law_names)
      codes(k) = contact_law_from_name("  "//uppercase(contact_law_names(k)))
      got(k) = contact_law_name(1 + k - 1)
    end do
    n = size(contact_law_names)
    call round_trip(error, contact_law_names, 1, codes(:n), got(:n), "contact_law")
    if (allocated(error)) return
    do k = 1, size(dashpot_kind_names)
      codes(k) = dashpot_kind_from_name("  "//uppercase(dashpot_kind_names(k)))
      got(k) = dashpot_kind_name(1 + k - 1)
    end do
    n = size(dashpot_kind_names)
    call round_trip(error, dashpot_kind_names, 1, codes(:n), got(:n), "dashpot_kind")
    if (allocated(error)) return
    do k = 1, size(interval_kind_names)
      codes(k) = interval_kind_from_name("  "//uppercase(interval_kind_names(k)))
      got(k) = interval_kind_name(interval_kind%bounded + k - 1)
    end do
    n = size(interval_kind_names)
    call round_trip(error, interval_kind_names, interval_kind%bounded, codes(:n), got(:n), "interval_kind")
    if (allocated(error)) return
    do k = 1, size(scan_break_names)
      codes(k) = scan_break_from_name("  "//uppercase(scan_break_names(k)))
      got(k) = scan_break_name(scan_break%none + k - 1)
    end do
    n = size(scan_break_names)
    call round_trip(error, scan_break_names, scan_break%none, codes(:n), got(:n), "scan_break")
    if (allocated(error)) return
    do k = 1, size(aggregate_kind_names)
      codes(k) = aggregate_kind_from_name("  "//uppercase(aggregate_kind_names(k)))
      got(k) = aggregate_kind_name(1 + k - 1)
    end do
    n = size(aggregate_kind_names)
    call round_trip(error, aggregate_kind_names, 1, codes(:n), got(:n), "aggregate_kind")
    if (allocated(error)) return
    do k = 1, size(pick_kind_names)
      codes(k) = pick_kind_from_name("  "//uppercase(pick_kind_names(k)))
      got(k) = pick_kind_name(1 + k - 1)
    end do
    n = size(pick_kind_names)
    call round_trip(error, pick_kind_names, 1, codes(:n), got(:n), "pick_kind")
    if (allocated(error)) return
    do k = 1, size(step_kind_names)
      codes(k) = step_kind_from_name("  "//uppercase(step_kind_names(k)))
      got(k) = step_kind_name(1 + k - 1)
    end do
    n = size(step_kind_names)
    call round_trip(error, step_kind_names, 1, codes(:n), got(:n), "step_kind")
    if (allocated(error)) return
    do k = 1, size(quantity_kind_names)
      codes(k) = quantity_kind_from_name("  "//uppercase(quantity_kind_names(k)))
      got(k) = quantity_kind_name(1 + k - 1)
    end do
    n = size(quantity_kind_names)
    call round_trip(error, quantity_kind_names, 1, codes(:n), got(:n), "quantity_kind")
    if (allocated(error)) return
    do k = 1, size(code_convention_names)
      codes(k) = code_convention_from_name("  "//uppercase(code_convention_names(k)))
      got(k) = code_convention_name(1 + k - 1)
    end do
    n = size(code_convention_names)
    call round_trip(error, code_convention_names, 1, codes(:n), got(:n), "code_convention")
    if (allocated(error)) return
    do k = 1, size(peer_rule_names)
      codes(k) = peer_rule_from_name("  "//uppercase(peer_rule_names(k)))
      got(k) = peer_rule_name(1 + k - 1)
    end do
    n = size(peer_rule_names)
    call round_trip(error, peer_rule_names, 1, codes(:n), got(:n), "peer_rule")
    if (allocated(error)) return
    do k = 1, size(step_governs_names)
      codes(k) = step_governs_from_name("  "//uppercase(step_governs_names(k)))
      got(k) = step_governs_name(1 + k - 1)
    end do
    n = size(step_governs_names)
    call round_trip(error, step_governs_names, 1, codes(:n), got(:n), "step_governs")
    if (allocated(error)) return
    do k = 1, size(scene_effect_names)
      codes(k) = scene_effect_from_name("  "//uppercase(scene_effect_names(k)))
      got(k) = scene_effect_name(1 + k - 1)
    end do
    n = size(scene_effect_names)
    call round_trip(error, scene_effect_names, 1, codes(:n), got(:n), "scene_effect")
    if (allocated(error)) return
    do k = 1, size(snapshot_format_names)
      codes(k) = snapshot_format_from_name("  "//uppercase(snapshot_format_names(k - 1)))
      got(k) = snapshot_format_name(snapshot_format%auto + k - 1)
    end do
    n = size(snapshot_format_names)
    call round_trip(error, snapshot_format_names, snapshot_format%auto, codes(:n), got(:n), "snapshot_format")
    if (allocated(error)) return
    call check(error, eigen_solver_from_name("LANCZOS") == eigen_solver%lanczos, "case ignored")
    if (allocated(error)) return
    call check(error, dashpot_kind_from_name("Centered") == dashpot_kind%centred, "the American spelling")
    if (allocated(error)) return
    call check(error, interval_kind_from_name("nothing") < interval_kind%bounded .and. &
      scan_break_from_name("nothing") < scan_break%none, "an unknown word is below every code")
    if (allocated(error)) return
    call check(error, eigen_solver_name(0) == "?" .and. eigen_solver_from_name("lanczo") == 0, &
      "no code outside the table, no word for one")
  end subroutine test_words

  subroutine test_unknown_word(error)
    type(error_type), allocatable, intent(out) :: error
    type(demstep_status_type) :: status
    call unknown_word(status, "eigen_solver", " Lanczo ", eigen_solver_names)
    call check(error, status%stat, demstep_stat%invalid_input)
    if (allocated(error)) return
    call check(error, status%where, "eigen_solver")
    if (allocated(error)) return
    call check(error, status%detail, "unknown word 'Lanczo' (auto, dense, lanczos, none)")
    if (allocated(error)) return
    call check(error, status%message, "eigen_solver: "//status%detail)
    if (allocated(error)) return
    call check(error, word_list(contact_law_names, quote="'"), "'linear', 'hertz'")
    if (allocated(error)) return
    call check(error, word_index(contact_law_names, "HERTZ"), 2)
  end subroutine test_unknown_word

  subroutine test_status_location(error)
    type(error_type), allocatable, intent(out) :: error
    type(demstep_status_type) :: status
    call set_status(status, demstep_stat%invalid_input, "particle 3: must be > 0", where="mass", index=3)
    call check(error, status%message == "mass: particle 3: must be > 0" .and. status%where == "mass" &
      .and. status%index == 3 .and. status%detail == "particle 3: must be > 0", "set_status with a location")
    if (allocated(error)) return
    call set_status(status, demstep_stat%pole, "a pole")
    call check(error, status%message == "a pole" .and. status%where == "" .and. status%index == 0, &
      "without a location")
    if (allocated(error)) return
    call set_status(status, demstep_stat%invalid_input, "must be finite", where="tolerance")
    call status_at(status, "eigen_tolerance", lead="Lanczos: ")
    call check(error, status%message == "eigen_tolerance: Lanczos: tolerance: must be finite" .and. &
      status%where == "eigen_tolerance", "status_at: "//status%message)
    if (allocated(error)) return
    call status_restate(status, "young", "types 1 and 2: too large")
    call check(error, status%message == "young: types 1 and 2: too large" .and. &
      status%stat == demstep_stat%invalid_input, "status_restate: "//status%message)
    if (allocated(error)) return
    status%stat = demstep_stat%ok
    call status_at(status, "x")
    call check(error, status%where == "young", "a successful status is left alone")
  end subroutine test_status_location

  !> Two library entry points: the location travels as components, and the
  !> message is still `where: detail`.
  subroutine test_library_location(error)
    type(error_type), allocatable, intent(out) :: error
    type(scene_type) :: scene
    type(demstep_status_type) :: status
    real(dp) :: x(3, 4)
    x = 0.0_dp
    x(1, :) = [0.0_dp, 1.0_dp, 2.0_dp, 3.0_dp]
    call new_scene(scene, 3, x, [1.0_dp, 1.0_dp, -1.0_dp, 1.0_dp], [0.4_dp, 0.4_dp, 0.4_dp, 0.4_dp], status)
    call check(error, status%where == "mass" .and. status%index == 3, "new_scene: "//status%message)
    if (allocated(error)) return
    call check(error, status%message, status%where//": "//status%detail)
    if (allocated(error)) return
    call new_scene(scene, 3, x, [1.0_dp, 1.0_dp, 1.0_dp, 1.0_dp], [0.4_dp, 0.4_dp, 0.4_dp, 0.0_dp], status)
    call check(error, status%where == "radius" .and. status%index == 4, "new_scene: "//status%message)
  end subroutine test_library_location

  subroutine test_c_location(error)
    type(error_type), allocatable, intent(out) :: error
    type(c_ptr), target :: handle
    type(demstep_error_c), target :: e
    real(c_double), target :: x(6), m(2), r(2)
    integer(c_int) :: code
    character(len=:), allocatable :: where
    integer :: i
    x = [0.0_dp, 0.0_dp, 0.0_dp, 1.0_dp, 0.0_dp, 0.0_dp]
    m = [1.0_dp, -1.0_dp]
    r = 0.4_dp
    code = c_scene_create(3, c_loc(handle), c_loc(e))
    call check(error, code, 0)
    if (allocated(error)) return
    call check(error, e%index, -1, message="no location on success")
    if (allocated(error)) return
    code = c_scene_set_particles(handle, 2, c_loc(x), c_loc(m), c_loc(r), c_null_ptr, c_null_ptr, &
      c_null_ptr, c_loc(e))
    where = ""
    do i = 1, size(e%where)
      if (e%where(i) == c_null_char) exit
      where = where//e%where(i)
    end do
    call check(error, code /= 0 .and. where == "mass" .and. e%index == 1, &
      "second particle's mass, 0-based index 1: where '"//where//"'")
    code = c_scene_free(c_loc(handle), c_loc(e))
  end subroutine test_c_location

  subroutine test_results(error)
    type(error_type), allocatable, intent(out) :: error
    type(result_group_type) :: r
    type(demstep_status_type) :: status
    character(len=*), parameter :: text = "&OTHER_RESULT X=1 /"//new_line("a")// &
      "&SCENE_RESULT"//new_line("a")// &
      " N_PARTICLES=48         ,"//new_line("a")// &
      " ROTATION=F,"//new_line("a")// &
      " OMEGA_MAX=  382.15230466927164     ,"//new_line("a")// &
      " EIGEN_SOLVER=""dense   "","//new_line("a")// &
      " STEPS=608                 ,"//new_line("a")// &
      " TOLERANCES= 3*0.1 ,  2.5E-003,"//new_line("a")// &
      " RULES=""edem_rayleigh_20    "",""yade_pwave          "","//new_line("a")// &
      " FUTURE_FIELD=  1.0,"//new_line("a")// &
      " /"
    integer :: n
    integer(i8) :: steps
    logical :: rotation
    real(dp) :: omega
    real(dp), allocatable :: tolerances(:)
    character(len=:), allocatable :: solver
    character(len=20) :: rules(3)
    call parse_result(text, "scene_result", r, status)
    call check(error, status%stat, demstep_stat%ok, message="the group is found among others")
    if (allocated(error)) return
    call result_get(r, "n_particles", n, status)
    call check(error, n, 48)
    if (allocated(error)) return
    call result_get(r, "rotation", rotation, status)
    call check(error, .not. rotation .and. status%stat == demstep_stat%ok, "logical")
    if (allocated(error)) return
    call result_get(r, "OMEGA_MAX", omega, status)
    ! the text written by the runtime reads back to the same double
    call check(error, omega, 382.15230466927164_dp, thr=0.0_dp)
    if (allocated(error)) return
    call result_get(r, "steps", steps, status)
    call check(error, steps == 608_i8, "64-bit integer")
    if (allocated(error)) return
    call result_get(r, "eigen_solver", solver, status)
    call check(error, solver, "dense")
    if (allocated(error)) return
    call result_get(r, "tolerances", tolerances, status)
    call check(error, size(tolerances) == 4 .and. all(tolerances == [0.1_dp, 0.1_dp, 0.1_dp, 2.5e-3_dp]), &
      "a list with a repeat count")
    if (allocated(error)) return
    rules = "x"
    call result_get(r, "rules", rules, status)
    call check(error, rules(1) == "edem_rayleigh_20" .and. rules(2) == "yade_pwave" .and. rules(3) == "x", &
      "a list of texts: the leading elements")
    if (allocated(error)) return
    ! absent: not_found at the field, the value left as it was (a namelist read's rule)
    omega = -7.0_dp
    call result_get(r, "dt_used", omega, status)
    call check(error, status%stat == demstep_stat%not_found .and. status%where == "dt_used" .and. &
      omega == -7.0_dp, "absent field: "//status%message)
    if (allocated(error)) return
    call check(error, result_has(r, "future_field") .and. .not. result_has(r, "dt_used"), "result_has")
    if (allocated(error)) return
    call parse_result(text, "system_result", r, status)
    call check(error, status%stat == demstep_stat%not_found .and. status%where == "system_result", &
      "absent group: "//status%message)
  end subroutine test_results

  subroutine test_results_hostile(error)
    type(error_type), allocatable, intent(out) :: error
    type(result_group_type) :: r
    type(demstep_status_type) :: status
    real(dp), allocatable :: values(:)
    real(dp) :: x
    integer :: n
    call parse_result("&R A=999999999*1.0, B=abc, C=1e999, D=3*2 /", "r", r, status)
    call check(error, status%stat, demstep_stat%ok)
    if (allocated(error)) return
    call result_get(r, "a", values, status)
    call check(error, status%stat == demstep_stat%invalid_input .and. .not. allocated(values), &
      "a repeat count beyond any result is refused, nothing allocated: "//status%message)
    if (allocated(error)) return
    x = 5.0_dp
    call result_get(r, "b", x, status)
    call check(error, status%stat == demstep_stat%invalid_input .and. status%where == "b" .and. x == 5.0_dp, &
      "text that is not a number: "//status%message)
    if (allocated(error)) return
    call result_get(r, "c", x, status)
    call check(error, status%stat == demstep_stat%invalid_input .and. x == 5.0_dp, "beyond the double range")
    if (allocated(error)) return
    n = 0
    call result_get(r, "d", values, status)
    call check(error, status%stat == demstep_stat%ok .and. size(values) == 3, "3*2 is three values")
  end subroutine test_results_hostile

  !> Two types, three particles of type 1 with radii 1e-3, 0.5e-3, 2e-3 and one of
  !> type 2: each rule's step is the smaller of the pairs' steps at the smallest
  !> radius of each type; a type outside the table is refused by name.
  subroutine test_packing_peers(error)
    type(error_type), allocatable, intent(out) :: error
    type(material_type) :: types(3), a, b
    type(peer_steps_type) :: steps, s11, s12, s22
    type(demstep_status_type) :: status
    real(dp), parameter :: e = 0.5_dp, v = 1.0_dp
    types(1) = material_type(young=1.0e8_dp, poisson=0.3_dp, density=2500.0_dp, radius=1.0_dp)
    types(2) = material_type(young=5.0e7_dp, poisson=0.25_dp, density=1200.0_dp, radius=1.0_dp)
    types(3) = material_type(young=1.0e9_dp, poisson=0.2_dp, density=7800.0_dp, radius=1.0_dp)
    call packing_peer_steps(types, [1, 1, 2, 1], [1.0e-3_dp, 0.5e-3_dp, 3.0e-3_dp, 2.0e-3_dp], e, e, v, &
      steps, status)
    call check(error, status%stat, demstep_stat%ok, message=status%message)
    if (allocated(error)) return
    a = types(1)
    a%radius = 0.5e-3_dp
    b = types(2)
    b%radius = 3.0e-3_dp
    call peer_time_steps(material_pair_type(a, a, e, e, v), s11, status)
    call peer_time_steps(material_pair_type(a, b, e, e, v), s12, status)
    call peer_time_steps(material_pair_type(b, b, e, e, v), s22, status)
    ! min of the same doubles: exact; type 3 (absent) plays no part
    call check(error, all(steps%dt == min(s11%dt, s12%dt, s22%dt)), "each rule: the minimum over the pairs")
    if (allocated(error)) return
    call check(error, steps%rayleigh == min(s11%rayleigh, s12%rayleigh, s22%rayleigh) .and. &
      steps%hertz_duration == min(s11%hertz_duration, s12%hertz_duration, s22%hertz_duration), &
      "the time scales too")
    if (allocated(error)) return
    call check(error, size(steps%dt) == n_peer_rules, "one step per rule")
    if (allocated(error)) return
    call packing_peer_steps(types, [1, 4], [1.0e-3_dp, 1.0e-3_dp], e, e, v, steps, status)
    call check(error, status%stat == demstep_stat%invalid_input .and. status%where == "type_of" .and. &
      status%index == 2, "a type without material: "//status%message)
  end subroutine test_packing_peers

  !> The typed-input path builds what the builders build (the same doubles in,
  !> the same limit out, compared exactly); each fault names the input's
  !> component and the part holding it.
  subroutine test_scene_input(error)
    type(error_type), allocatable, intent(out) :: error
    type(scene_input_type) :: input
    type(material_set_type) :: set
    type(scene_setup_type) :: setup
    type(scene_type) :: a, b
    type(critical_step_type) :: ca, cb
    type(demstep_status_type) :: status
    integer :: part
    input%dim = 2
    input%position = [0.0_dp, 0.0_dp, 1.0_dp, 0.0_dp, 2.0_dp, 0.1_dp]
    input%mass = [1.0_dp, 2.0_dp, 3.0_dp]
    input%radius = [0.6_dp]
    input%k_normal = 1.0e4_dp
    call scene_from_input(input, set, a, setup, status, part)
    call check(error, status%stat, demstep_stat%ok, message=status%message)
    if (allocated(error)) return
    call new_scene(b, 2, reshape(input%position, [2, 3]), input%mass, [0.6_dp, 0.6_dp, 0.6_dp], status)
    if (status%stat == demstep_stat%ok) call scene_set_law(b, contact_law%linear, 1.0e4_dp, 0.0_dp, status)
    if (status%stat == demstep_stat%ok) call assembly_critical_steps(a, ca, status)
    if (status%stat == demstep_stat%ok) call assembly_critical_steps(b, cb, status)
    call check(error, status%stat, demstep_stat%ok, message=status%message)
    if (allocated(error)) return
    call check(error, ca%omega_max == cb%omega_max .and. ca%dt_critical_damped == cb%dt_critical_damped .and. &
      ca%n_springs == cb%n_springs .and. ca%n_springs == 2, "the same springs and limit")
    if (allocated(error)) return
    call check(error, .not. setup%from_material .and. setup%hertz_mode == hertz_linearization%current, &
      "no material set: the current overlap")
    if (allocated(error)) return
    ! a broadcast that does not fit: the component, the scene part
    input%mass = [1.0_dp, 2.0_dp]
    call scene_from_input(input, set, a, setup, status, part)
    call check(error, status%stat == demstep_stat%invalid_input .and. status%where == "mass" .and. &
      part == scene_input_part%scene, "mass: "//status%message)
    if (allocated(error)) return
    ! no particles at all: the position is required, by name
    input = scene_input_type(dim=2, k_normal=1.0e4_dp)
    call scene_from_input(input, set, a, setup, status, part)
    call check(error, status%stat == demstep_stat%invalid_input .and. status%where == "position", &
      "no position: "//status%message)
    if (allocated(error)) return
    ! a snapshot's springs from a material set in one code's convention
    input = scene_input_type(dim=3, snapshot_file="example/liggghts_pour.dump")
    set%found = .true.
    set%types = [material_type(young=1.0e7_dp, poisson=0.25_dp, density=2500.0_dp, radius=1.0e-3_dp)]
    set%restitution = 0.9_dp
    set%impact_velocity = 1.0_dp
    set%first = 2
    set%last = 2
    call scene_from_input(input, set, a, setup, status, part)
    call check(error, status%stat, demstep_stat%ok, message=status%message)
    if (allocated(error)) return
    call check(error, setup%from_material .and. setup%hertz_mode == hertz_linearization%larger .and. &
      setup%impact_velocity == 1.0_dp .and. a%law == contact_law%hertz .and. size(set%types) == 2 .and. &
      setup%snapshot%n == 128, "the set's Hertz convention, at the larger overlap, broadcast to 2 types")
    if (allocated(error)) return
    ! all codes with a linear law: the set's fault, at its `code`
    set%first = 1
    set%last = n_conventions
    input%law = contact_law%linear
    call scene_from_input(input, set, a, setup, status, part)
    call check(error, status%stat == demstep_stat%invalid_input .and. status%where == "code" .and. &
      part == scene_input_part%material, "code: "//status%message)
  end subroutine test_scene_input

end module test_structure
