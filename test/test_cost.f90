!> Tests of demstep_cost: worst errors over the onset, tolerance -> N, and the
!> run-time prediction.
module test_cost
  use testdrive, only: new_unittest, unittest_type, error_type, check, test_failed
  use demstep
  use demstep_contact, only: quantity_kind_names
  use demstep_cost, only: worst_error, accuracy_cost_table, quantity_harmonic
  use demstep_contact, only: n_quantities
  use test_support, only: real_str
  implicit none
  private
  public :: collect_cost

contains

  subroutine collect_cost(testsuite)
    type(unittest_type), allocatable, intent(out) :: testsuite(:)
    testsuite = [ &
      new_unittest("errors vanish at the stated rates", test_rates), &
      new_unittest("tolerance -> N inverts the error curves", test_tolerance), &
      new_unittest("tolerance -> N: bad tolerances, beyond n_max, unknown quantity", test_refusals), &
      new_unittest("run prediction: dt, steps and time in closed form, saturation", test_prediction), &
      new_unittest("the accuracy-cost table: each row as its own calls; faults by element", test_table) &
      ]
  end subroutine collect_cost

  !> Worst errors over the onset against N: O(1/N^2) for restitution, overlap and
  !> period, O(1/N) for the contact time (the force count can be one step off).
  !> The errors oscillate with N (period about 2: they follow the fraction of a
  !> step at which the contact ends), so the rate is read from the envelope: the
  !> largest error over N = 100..110 and over N = 1000..1010, in steps of 0.05.
  subroutine test_rates(error)
    type(error_type), allocatable, intent(out) :: error
    integer, parameter :: quantities(4) = [quantity_kind%restitution, quantity_kind%contact_time, &
      quantity_kind%overlap, quantity_kind%period]
    real(dp), parameter :: rates(4) = [-2.0_dp, -1.0_dp, -2.0_dp, -2.0_dp]
    type(demstep_status_type) :: status
    real(dp) :: e, top(2), slope
    integer :: q, i, band
    do q = 1, size(quantities)
      do band = 1, 2
        top(band) = 0.0_dp
        do i = 0, 200
          call worst_error(100.0_dp*10.0_dp**(band - 1) + 0.05_dp*real(i, dp), quantities(q), e, status)
          top(band) = max(top(band), e)
        end do
      end do
      slope = log10(top(2)/top(1))
      call check(error, slope, rates(q), thr=0.15_dp, message="rate of "//trim(quantity_kind_names(quantities(q))))
      if (allocated(error)) return
    end do
  end subroutine test_rates

  subroutine test_tolerance(error)
    type(error_type), allocatable, intent(out) :: error
    type(demstep_status_type) :: status
    real(dp) :: n, e, probe
    integer :: q, k, j
    logical :: failed_below
    do q = 1, n_quantities
      do k = 1, 3
        call n_for_tolerance(q, 10.0_dp**(-k), n, status)
        call check(error, status%stat, demstep_stat%ok)
        if (allocated(error)) return
        ! the tolerance holds at N, and above it (probed on another grid) to within
        ! the error's variation over one cell of the search grid (2 %)
        call worst_error(n, q, e, status)
        call check(error, e <= 10.0_dp**(-k), trim(quantity_kind_names(q))//": error above the tolerance at N")
        if (allocated(error)) return
        do j = 1, 200
          call worst_error(n*1.0013_dp**j, q, e, status)
          call check(error, e <= 1.02_dp*10.0_dp**(-k), trim(quantity_kind_names(q))//": error "// &
            real_str(e)//" above the tolerance at N = "//real_str(n*1.0013_dp**j))
          if (allocated(error)) return
        end do
        ! ... and fails just below it (within the bisection's 1e-6)
        failed_below = .false.
        do j = 1, 20
          probe = n*(1.0_dp - 1.0e-6_dp*real(j, dp)/20.0_dp)
          call worst_error(probe, q, e, status)
          if (e > 10.0_dp**(-k)) failed_below = .true.
        end do
        call check(error, failed_below, trim(quantity_kind_names(q))//": not the smallest N")
        if (allocated(error)) return
      end do
    end do
  end subroutine test_tolerance

  subroutine test_refusals(error)
    type(error_type), allocatable, intent(out) :: error
    type(demstep_status_type) :: status
    real(dp) :: n, e
    call n_for_tolerance(quantity_kind%restitution, 0.0_dp, n, status)
    call check(error, status%stat, demstep_stat%invalid_input, message="tolerance 0")
    if (allocated(error)) return
    call n_for_tolerance(quantity_kind%contact_time, 1.0e-9_dp, n, status)
    call check(error, status%stat, demstep_stat%not_found, message="1e-9 needs more than n_max")
    if (allocated(error)) return
    call worst_error(100.0_dp, n_quantities + 1, e, status)
    call check(error, status%stat, demstep_stat%invalid_input, message="unknown quantity")
    if (allocated(error)) return
    call check(error, index(status%message, "quantity: ") == 1, "names quantity")
  end subroutine test_refusals

  !> dt = T/N, steps = ceiling(duration/dt), seconds = steps x particles x cost:
  !> exact in binary for these inputs (powers of two), and the 64-bit count
  !> saturating with a flag where steps exceed 2^63 - 1.
  subroutine test_prediction(error)
    type(error_type), allocatable, intent(out) :: error
    type(run_prediction_type) :: p
    type(demstep_status_type) :: status
    call predict_run(1.0_dp, 64.0_dp, 10.0_dp, 1024.0_dp, 2.0_dp**(-20), p, status)
    call check(error, status%stat, demstep_stat%ok)
    if (allocated(error)) return
    call check(error, p%dt, 1.0_dp/64.0_dp, thr=0.0_dp, message="dt = T/N")
    if (allocated(error)) return
    call check(error, p%steps == 640_i8 .and. .not. p%steps_saturated, "steps = duration/dt")
    if (allocated(error)) return
    call check(error, p%seconds, 640.0_dp*1024.0_dp*2.0_dp**(-20), thr=0.0_dp, message="seconds")
    if (allocated(error)) return
    ! a fraction of a step counts as a whole one
    call predict_run(1.0_dp, 64.0_dp, 10.001_dp, 1.0_dp, 1.0_dp, p, status)
    call check(error, p%steps == 641_i8, "ceiling of duration/dt")
    if (allocated(error)) return
    ! 2^70 steps: the count saturates, the real count and the time stay exact
    call predict_run(1.0_dp, 2.0_dp**70, 1.0_dp, 1.0_dp, 1.0_dp, p, status)
    call check(error, status%stat, demstep_stat%ok)
    if (allocated(error)) return
    call check(error, p%steps == huge(1_i8) .and. p%steps_saturated, "steps saturate")
    if (allocated(error)) return
    call check(error, p%steps_real, 2.0_dp**70, thr=0.0_dp, message="steps as a real")
    if (allocated(error)) return
    call check(error, p%seconds, 2.0_dp**70, thr=0.0_dp, message="seconds beyond 2^63 steps")
    if (allocated(error)) return
    call predict_run(1.0_dp, 10.0_dp, 1.0e300_dp, 1.0e300_dp, 1.0_dp, p, status)
    call check(error, status%stat, demstep_stat%invalid_input, message="time beyond the double range")
    if (allocated(error)) return
    call check(error, index(status%message, "n_particles: ") == 1, "names n_particles: "//status%message)
  end subroutine test_prediction

  !> The table's rows are the single calls' results (the same doubles); a
  !> tolerance beyond n_max keeps its code in its row; a bad tolerance is
  !> named with its element, a bad lambda as lambda.
  subroutine test_table(error)
    type(error_type), allocatable, intent(out) :: error
    real(dp), parameter :: tol(3) = [1.0e-2_dp, 1.0e-3_dp, 1.0e-12_dp], period = 1.0e-3_dp
    real(dp) :: n(3), nn
    type(run_prediction_type) :: rows(3), one
    integer :: stat(3), i
    type(demstep_status_type) :: status, st
    call accuracy_cost_table(quantity_kind%restitution, tol, period, 1.0_dp, 1.0e4_dp, 1.0e-7_dp, n, rows, &
      stat, status, damping_ratio=0.1_dp, n_max=1.0e5_dp)
    call check(error, status%stat, demstep_stat%ok, message=status%message)
    if (allocated(error)) return
    do i = 1, 3
      call n_for_tolerance(quantity_kind%restitution, tol(i), nn, st, damping_ratio=0.1_dp, n_max=1.0e5_dp)
      call check(error, stat(i), st%stat, "row "//real_str(tol(i))//": the single call's code")
      if (allocated(error)) return
      if (st%stat /= demstep_stat%ok) then
        call check(error, n(i) == 0.0_dp .and. rows(i)%steps == 0, "an unmet tolerance: a zero row")
        if (allocated(error)) return
        cycle
      end if
      call predict_run(period, nn, 1.0_dp, 1.0e4_dp, 1.0e-7_dp, one, st)
      call check(error, n(i) == nn .and. rows(i)%dt == one%dt .and. rows(i)%seconds == one%seconds, &
        "row "//real_str(tol(i))//": the single calls' doubles")
      if (allocated(error)) return
    end do
    call check(error, stat(1) == demstep_stat%ok .and. stat(3) /= demstep_stat%ok, &
      "1e-2 met, 1e-12 not within n_max = 1e5")
    if (allocated(error)) return
    call accuracy_cost_table(quantity_kind%restitution, [1.0e-2_dp, -1.0_dp], period, 1.0_dp, 1.0e4_dp, &
      1.0e-7_dp, n(:2), rows(:2), stat(:2), status)
    call check(error, status%stat == demstep_stat%invalid_input .and. status%where == "tolerances" .and. &
      status%index == 2, "a bad tolerance at its element: "//status%message)
    if (allocated(error)) return
    call accuracy_cost_table(quantity_harmonic, [1.0e-3_dp], period, 1.0_dp, 1.0e4_dp, 1.0e-7_dp, n(:1), &
      rows(:1), stat(:1), status, lambda=-0.5_dp)
    call check(error, status%stat == demstep_stat%invalid_input .and. status%where == "lambda", &
      "a bad lambda: "//status%message)
  end subroutine test_table

end module test_cost
