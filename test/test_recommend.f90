!> Tests of the one recommended step: the library routine (safety factor,
!> which requirement governs, refusals), the single-contact assessment against
!> closed forms in quad precision, and the `recommended dt` line and
!> `dt_recommended` of &system, &simulated_stiffness and &accuracy_cost.
module test_recommend
  use testdrive, only: new_unittest, unittest_type, error_type, check
  use demstep
  use demstep_cost, only: worst_error
  use demstep_recommend, only: default_safety, step_governs
  use demstep_kinds, only: pi
  use test_support, only: run_app, write_file, work_dir
  use, intrinsic :: iso_fortran_env, only: qp => real128
  use demstep_results, only: result_group_type
  use test_support, only: read_group, take
  implicit none
  private
  public :: collect_recommend

  real(qp), parameter :: pq = 3.14159265358979323846264338327950288_qp
  character(len=*), parameter :: out = work_dir//"/recommend_out.nml"
  character(len=*), parameter :: deck = work_dir//"/recommend.nml"

contains

  subroutine collect_recommend(testsuite)
    type(unittest_type), allocatable, intent(out) :: testsuite(:)
    testsuite = [ &
      new_unittest("recommended_step: safety, what governs, refusals", test_routine), &
      new_unittest("assess_contact: limit and contact against closed forms", test_assess), &
      new_unittest("&system, &simulated_stiffness, &accuracy_cost end with it", test_groups) &
      ]
  end subroutine collect_recommend

  subroutine test_routine(error)
    type(error_type), allocatable, intent(out) :: error
    type(demstep_status_type) :: status
    real(dp) :: dt
    integer :: governs
    call recommended_step(1.0e-3_dp, dt, governs, status)
    call check(error, is_ok(status) .and. dt == default_safety*1.0e-3_dp .and. &
      governs == step_governs%stability .and. default_safety == 0.9_dp, "stability alone: 0.9 of the limit")
    if (allocated(error)) return
    call recommended_step(1.0e-3_dp, dt, governs, status, dt_accuracy=2.0e-4_dp)
    call check(error, is_ok(status) .and. dt == 2.0e-4_dp .and. governs == step_governs%accuracy, &
      "a smaller accuracy step governs")
    if (allocated(error)) return
    call recommended_step(1.0e-3_dp, dt, governs, status, dt_accuracy=0.95e-3_dp)
    call check(error, is_ok(status) .and. dt == 0.9_dp*1.0e-3_dp .and. governs == step_governs%stability, &
      "an accuracy step between 0.9 and 1 of the limit: stability governs")
    if (allocated(error)) return
    call recommended_step(1.0e-3_dp, dt, governs, status, safety=0.5_dp)
    call check(error, dt == 0.5e-3_dp, "a given safety factor")
    if (allocated(error)) return
    call recommended_step(0.0_dp, dt, governs, status)
    call check(error, status%stat == demstep_stat%invalid_input .and. index(status%message, "dt_stability:") == 1 &
      .and. dt == 0, "limit 0 refused")
    if (allocated(error)) return
    call recommended_step(1.0_dp, dt, governs, status, safety=1.5_dp)
    call check(error, index(status%message, "safety: must lie in (0, 1]") == 1, "safety > 1 refused")
    if (allocated(error)) return
    call recommended_step(1.0_dp, dt, governs, status, dt_accuracy=-1.0_dp)
    call check(error, index(status%message, "dt_accuracy:") == 1 .and. dt == 0, "negative accuracy step refused")
    if (allocated(error)) return
    call recommended_step(tiny(1.0_dp), dt, governs, status, safety=0.5_dp)
    call check(error, index(status%message, "dt_stability: the recommended step underflows") == 1, &
      "underflow refused")
  end subroutine test_routine

  subroutine test_assess(error)
    type(error_type), allocatable, intent(out) :: error
    type(demstep_status_type) :: status
    type(contact_assessment_type) :: a
    type(discrete_contact_type) :: c
    real(qp) :: z, w
    real(dp) :: n, e
    ! m = 2, k = 8: omega = 2, T = pi; zeta = 0.1: limit (2/omega)(sqrt(1 + z^2) - z)
    call assess_contact(2.0_dp, 8.0_dp, 0.1_dp, a, status, dt=0.05_dp, tolerance=1.0e-2_dp)
    call check(error, is_ok(status), "assesses: "//status%message)
    if (allocated(error)) return
    z = 0.1_qp
    w = sqrt(1 + z**2) - z
    call check(error, abs(real(a%dt_critical, qp) - w) < 1.0e-15_qp, "lagged limit (1e-15: one rounding)")
    if (allocated(error)) return
    call check(error, abs(real(a%period, qp) - pq) < 1.0e-15_qp*pq .and. abs(a%n_per_period - pi/0.05_dp) < &
      1.0e-12_dp*a%n_per_period, "period and N = T/dt")
    if (allocated(error)) return
    ! the same answers as the contact routines called directly
    call contact_with_onset(a%n_per_period, 1.0_dp, c, status, 0.1_dp)
    call check(error, a%steps == c%steps .and. a%stable, "steps per contact, stable")
    if (allocated(error)) return
    call worst_error(a%n_per_period, quantity_kind%restitution, e, status, damping_ratio=0.1_dp)
    call check(error, a%restitution_error == e, "worst restitution error")
    if (allocated(error)) return
    call n_for_tolerance(quantity_kind%restitution, 1.0e-2_dp, n, status, damping_ratio=0.1_dp)
    call check(error, a%n_tolerance == n .and. a%dt_accuracy == a%period/n, "accuracy step T/N")
    if (allocated(error)) return
    call assess_contact(2.0_dp, 8.0_dp, 1.0_dp, a, status)
    call check(error, index(status%message, "damping_ratio: must lie in [0, 1)") == 1, "overdamped refused")
  end subroutine test_assess

  subroutine test_groups(error)
    type(error_type), allocatable, intent(out) :: error
    integer :: rc, unit, ios
    character(len=:), allocatable :: stdout, stderr
    real(dp) :: period, omega, dt_critical, dt_recommended
    type(result_group_type) :: system_result_fields
    real(dp) :: tolerances(2), n_per_period(2), dt(2), predicted_seconds(2), cost_per_particle_step
    integer(i8) :: steps(2)
    logical :: steps_saturated(2)
    integer :: status(2)
    type(result_group_type) :: accuracy_cost_result_fields
    ! &system without a step: 0.9 of the critical step
    call write_file(deck, [character(len=60) :: "&system mass = 0.01, stiffness = 1.0e5 /"])
    call run_app(deck//" -o "//out, rc, stdout, stderr)
    call check(error, rc == 0, "runs: "//stderr)
    if (allocated(error)) return
    dt_recommended = -1
    open(newunit=unit, file=out, status="old", action="read", iostat=ios)
    if (ios == 0) call read_group(unit, "system_result", system_result_fields, ios)
    if (ios == 0) call take(system_result_fields, "period", period, ios)
    if (ios == 0) call take(system_result_fields, "omega", omega, ios)
    if (ios == 0) call take(system_result_fields, "dt_critical", dt_critical, ios)
    if (ios == 0) call take(system_result_fields, "dt_recommended", dt_recommended, ios)
    close(unit)
    call check(error, ios == 0 .and. dt_recommended == 0.9_dp*dt_critical, "&system: 0.9 dt_critical")
    if (allocated(error)) return
    call check(error, index(stdout, "recommended dt = 5.692099788e-4 s") > 0 .and. &
      index(stdout, "stability (0.9") > 0, "&system: the line and what governs")
    if (allocated(error)) return
    ! &accuracy_cost: the tightest tolerance met governs when below 0.9 of the limit
    call write_file(deck, [character(len=80) :: "&accuracy_cost quantity = 'restitution',", &
      "tolerances = 1e-2, 1e-3, duration = 1, n_particles = 100, mass = 0.01,", &
      "stiffness = 1e5, damping_ratio = 0.1, cost_per_particle_step = 1e-7,", &
      "csv = '"//work_dir//"/rec.csv', figure = 'none' /"])
    call run_app(deck//" -o "//out, rc, stdout, stderr)
    call check(error, rc == 0, "runs: "//stderr)
    if (allocated(error)) return
    open(newunit=unit, file=out, status="old", action="read", iostat=ios)
    if (ios == 0) call read_group(unit, "accuracy_cost_result", accuracy_cost_result_fields, ios)
    if (ios == 0) call take(accuracy_cost_result_fields, "tolerances", tolerances, ios)
    if (ios == 0) call take(accuracy_cost_result_fields, "n_per_period", n_per_period, ios)
    if (ios == 0) call take(accuracy_cost_result_fields, "dt", dt, ios)
    if (ios == 0) call take(accuracy_cost_result_fields, "steps", steps, ios)
    if (ios == 0) call take(accuracy_cost_result_fields, "steps_saturated", steps_saturated, ios)
    if (ios == 0) call take(accuracy_cost_result_fields, "predicted_seconds", predicted_seconds, ios)
    if (ios == 0) call take(accuracy_cost_result_fields, "status", status, ios)
    if (ios == 0) call take(accuracy_cost_result_fields, "cost_per_particle_step", cost_per_particle_step, ios)
    if (ios == 0) call take(accuracy_cost_result_fields, "period", period, ios)
    if (ios == 0) call take(accuracy_cost_result_fields, "dt_recommended", dt_recommended, ios)
    close(unit)
    call check(error, ios == 0 .and. dt_recommended == dt(2) .and. index(stdout, "governs                  " &
      //"accuracy (the tightest tolerance met, 0.001)") > 0, "&accuracy_cost: the 1e-3 step")
    if (allocated(error)) return
    call check(error, index(stdout, "recommended dt = ", back=.true.) > index(stdout, "curves written"), &
      "the line closes the group's report")
  end subroutine test_groups

end module test_recommend
