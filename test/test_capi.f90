!> Tests of the C API through its bind(C) entry points: the same numbers as the
!> Fortran API, and bad input (NULL pointers, empty arrays, NaN) as statuses with
!> messages, never a crash.
module test_capi
  use, intrinsic :: iso_c_binding, only: c_int, c_double, c_loc, c_null_ptr, c_null_char, c_ptr
  use testdrive, only: new_unittest, unittest_type, error_type, check, test_failed
  use demstep
  use demstep_kinds, only: pi
  use demstep_capi, only: demstep_error_c, demstep_spring_c, demstep_spring_state_c, &
    demstep_nroots_c, demstep_stiffness_result_c, demstep_critical_step_c, c_spring_new, &
    c_spring_step, c_critical_time_step, c_harmonic_error, c_n_roots, c_simulated_stiffness, &
    c_scene_critical_step, demstep_contact_c, c_contact_with_onset, c_n_for_tolerance
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
      new_unittest("include/demstep.h: every enum value equals the Fortran one", test_header_enums) &
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
      "EIGENSOLVER_FAILURE", &
      "DASHPOT_LAGGED", "DASHPOT_CENTRED", "STEPS_FIXED", "STEPS_FRACTION", "STEPS_ROUNDED", &
      "PICK_LARGEST_STEP", "PICK_ZERO", "AGGREGATE_MEAN", "AGGREGATE_WEIGHTED", "AGGREGATE_MEDIAN", &
      "AGGREGATE_MIN", "AGGREGATE_MAX", "QUANTITY_RESTITUTION", "QUANTITY_CONTACT_TIME", &
      "QUANTITY_OVERLAP", "QUANTITY_PERIOD", "LAW_LINEAR", "LAW_HERTZ", "EFFECT_CONTACTS", &
      "EFFECT_GRAVITY", "EFFECT_DAMPING", "EFFECT_LOCAL_DAMPING", "EFFECT_WALLS", "EFFECT_ROTATION"]
    values = [demstep_stat%ok, demstep_stat%invalid_input, demstep_stat%unstable, demstep_stat%pole, &
      demstep_stat%not_converged, demstep_stat%not_found, demstep_stat%lapack_failure, &
      demstep_stat%io_error, demstep_stat%blow_up, demstep_stat%at_stability_limit, &
      demstep_stat%discontinuous, demstep_stat%eigensolver_failure, dashpot_kind%lagged, dashpot_kind%centred, step_kind%fixed, &
      step_kind%fraction, step_kind%rounded, pick_kind%largest_step, pick_kind%zero, &
      aggregate_kind%mean, aggregate_kind%weighted, aggregate_kind%median, aggregate_kind%min, &
      aggregate_kind%max, quantity_kind%restitution, quantity_kind%contact_time, &
      quantity_kind%overlap, quantity_kind%period, contact_law%linear, contact_law%hertz, &
      ! effects are bit flags: bit (index - 1) of the Fortran effect index
      2**(scene_effect%contacts - 1), 2**(scene_effect%gravity - 1), 2**(scene_effect%damping - 1), &
      2**(scene_effect%local_damping - 1), 2**(scene_effect%walls - 1), 2**(scene_effect%rotation - 1)]
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
      ! a name of capitals and underscores, then " = value"
      j = i
      do while (j <= len(text))
        if (index("ABCDEFGHIJKLMNOPQRSTUVWXYZ_", text(j:j)) == 0) exit
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

  !> The message of a C error struct as a Fortran string.
  function message_of(e) result(text)
    type(demstep_error_c), intent(in) :: e
    character(len=:), allocatable :: text
    integer :: i
    text = ""
    do i = 1, size(e%message)
      if (e%message(i) == c_null_char) exit
      text = text//e%message(i)
    end do
  end function message_of

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
    type(demstep_critical_step_c), target :: crit
    type(demstep_contact_c), target :: contact
    real(c_double), target :: value, lambdas(2), x(2), m(2), rad(2)
    integer(c_int), target :: bonds(2)
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
    x = [0.0_dp, 1.0_dp]
    m = [1.0_dp, 1.0_dp]
    rad = [0.3_dp, 0.3_dp]
    bonds = [0, 5]
    code = c_scene_critical_step(1, 2, c_loc(x), c_loc(m), c_loc(rad), c_null_ptr, 1, c_loc(bonds), &
      1.0_dp, 0.0_dp, 1, 0.0_dp, 0.0_dp, 0, 0.0_dp, c_loc(crit), c_loc(e))
    call check(error, code == 1 .and. index(message_of(e), "missing") > 0, "bond to a missing particle: " &
      //message_of(e))
    if (allocated(error)) return
    code = c_scene_critical_step(1, 0, c_loc(x), c_loc(m), c_loc(rad), c_null_ptr, 0, c_null_ptr, &
      1.0_dp, 0.0_dp, 1, 0.0_dp, 0.0_dp, 0, 0.0_dp, c_loc(crit), c_loc(e))
    call check(error, code, 1, message="no particles")
    if (allocated(error)) return
    code = c_scene_critical_step(1, 2, c_null_ptr, c_loc(m), c_loc(rad), c_null_ptr, 0, c_null_ptr, &
      1.0_dp, 0.0_dp, 1, 0.0_dp, 0.0_dp, 0, 0.0_dp, c_loc(crit), c_loc(e))
    call check(error, code, 1, message="NULL positions")
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

end module test_capi
