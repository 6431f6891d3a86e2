!> Group `&simulated_stiffness`: the whole simulated-stiffness procedure
!> (paper eqs. 25-29): dt = T*/N* and K' = lambda*^2 K*.
module demstep_cli_stiffness
  use demstep, only: dp, i8, demstep_status_type, demstep_stat, nml_group_type, &
    stiffness_input_type, stiffness_result_type, run_procedure => simulated_stiffness, step_kind, &
    new_step_policy, pick_kind, aggregate_kind, interval_kind, text_progress_type, spring_type, &
    new_spring, critical_time_step, recommended_step, step_governs, default_safety
  use demstep_status, only: set_status
  use demstep_text, only: lowercase
  use demstep_stiffness, only: default_n_max, default_resolution
  use demstep_stiffness, only: procedure_cost, measure_evaluation_cost, max_procedure_evaluations
  use, intrinsic :: iso_fortran_env, only: error_unit
  use demstep_cli, only: record_step, var_spec, var, given, begin_group, fmt_real, fmt_int, cli_context, &
    next_assignment, group_reading, &
    new_array, array_length, default_text, max_values, capacity_of
  implicit none
  private

  public :: stiffness_specs, stiffness_doc, handle_simulated_stiffness

  character(len=*), parameter :: stiffness_doc = &
    "The simulated-stiffness procedure: for each lambda the N meeting |E| <= tolerance, " &
    //"combined into N*; dt = T*/N*, K' = lambda*^2 K*."

contains

  !> The variables of `&simulated_stiffness`.
  function stiffness_specs() result(specs)
    type(var_spec), allocatable :: specs(:)
    specs = [ &
      var("mass", "a real number", "mass M (> 0)", "0.01", required=.true.), &
      var("stiffness", "a real number", "ideal (simulated) stiffness K* (> 0)", "1.0e5", required=.true.), &
      var("tolerance", "a real number", "tolerance E0 on |E|, in (0, 1)", "1.0e-3", required=.true.), &
      var("lambda", "a list of real numbers", "lambda set, increasing, in (0, 1); or the three below", &
        "!0.9, 0.95, 0.99", capacity=max_values, required=.true., &
        excludes="lambda_min lambda_max lambda_count"), &
      var("lambda_min", "a real number", "smallest lambda of an even set", "0.9", &
        needs="lambda_max lambda_count"), &
      var("lambda_max", "a real number", "largest lambda of an even set", "0.99", &
        needs="lambda_min lambda_count"), &
      var("lambda_count", "an integer", "number of lambdas in the even set (>= 1)", "10", &
        needs="lambda_min lambda_max"), &
      var("steps", "a quoted word", "'half_period', 'fraction', 'rounded' " &
        //"(nint(f N) steps) or 'fixed'", "'half_period'", default="'half_period'"), &
      var("steps_fraction", "a real number", "f for steps = 'fraction' or 'rounded' (> 0)", "!0.5", &
        default="0.5"), &
      var("n_steps", "a real number", "n for steps = 'fixed' (>= 1)", "!100.0"), &
      var("pick", "a quoted word", "'largest_step' (smallest N with |E| <= E0) or 'zero'", &
        "'largest_step'", default="'largest_step'"), &
      var("aggregate", "a quoted word", "'mean', 'weighted', 'median', 'min' or 'max'", &
        "'mean'", default="'mean'"), &
      var("weights", "a list of real numbers", "one weight >= 0 per lambda, for 'weighted'", &
        "!1.0, 2.0, 1.0", capacity=max_values), &
      var("n_max", "a real number", "largest N scanned", default_text(default_n_max), &
        default=default_text(default_n_max)), &
      var("resolution", "a real number", "scan step relative to N, in (0, 1]", &
        default_text(default_resolution), default=default_text(default_resolution)) ]
  end function stiffness_specs

  !> Read, check and run one `&simulated_stiffness` group.
  subroutine handle_simulated_stiffness(ctx, group, status)
    type(cli_context), intent(in) :: ctx
    type(nml_group_type), intent(in) :: group
    type(demstep_status_type), intent(out) :: status
    type(group_reading) :: reading
    real(dp) :: mass, stiffness, tolerance, lambda_min, lambda_max, steps_fraction, n_steps, &
      n_max, resolution
    real(dp), allocatable :: lambda(:), weights(:)
    integer :: lambda_count
    character(len=32) :: steps, pick, aggregate
    namelist /simulated_stiffness/ mass, stiffness, tolerance, lambda, lambda_min, lambda_max, &
      lambda_count, steps, steps_fraction, n_steps, pick, aggregate, weights, n_max, resolution
    type(var_spec), allocatable :: specs(:)
    type(stiffness_input_type) :: input
    type(stiffness_result_type) :: result
    character(len=*), parameter :: g = "simulated_stiffness"
    !> Estimated run times above this many seconds are announced on stderr.
    real(dp), parameter :: announce_seconds = 2.0_dp
    !> Below this many evaluations of E the run is not worth timing up front.
    real(dp), parameter :: measure_above = 1.0e5_dp
    type(text_progress_type) :: progress
    real(dp) :: cost, seconds
    integer :: i, n_lambda, n_weights, kind, governs
    real(dp) :: dt_stability, dt_recommended

    specs = stiffness_specs()
    lambda = new_array(capacity_of(specs, "lambda"))
    weights = new_array(capacity_of(specs, "weights"))
    call begin_group(reading, group, specs, status)
    do while (next_assignment(reading, group, status))
      read(reading%text, nml=simulated_stiffness, iostat=reading%ios)
    end do
    if (status%stat /= demstep_stat%ok) return
    ! mass, stiffness, tolerance, n_max, resolution, the lambdas and weights:
    ! run_procedure checks them all before the scan

    ! the lambda set: a list, or an even set from min, max and count
    call array_length(g, "lambda", lambda, n_lambda, status)
    if (status%stat /= demstep_stat%ok) return
    if (given(group, "lambda")) then
      input%lambdas = lambda(:n_lambda)
    else

      if (lambda_count < 1) then
        call set_status(status, demstep_stat%invalid_input, "&"//g//": lambda_count: must be >= 1, got " &
          //fmt_int(int(lambda_count, i8)))
        return
      end if
      if (lambda_count > 1 .and. .not. lambda_max > lambda_min) then
        call set_status(status, demstep_stat%invalid_input, "&"//g//": lambda_max: must be > lambda_min")
        return
      end if
      if (lambda_count == 1) then
        input%lambdas = [lambda_min]
      else
        input%lambdas = [(lambda_min + (lambda_max - lambda_min)*real(i - 1, dp)/real(lambda_count - 1, dp), &
          i = 1, lambda_count)]
      end if
    end if
    ! step policy, pick and aggregation
    select case (lowercase(trim(adjustl(steps))))
    case ("half_period")
      call new_step_policy(input%options%policy, step_kind%fraction, 0.5_dp, status)
    case ("fraction", "rounded")
      kind = merge(step_kind%fraction, step_kind%rounded, lowercase(trim(adjustl(steps))) == "fraction")
      call new_step_policy(input%options%policy, kind, steps_fraction, status)
    case ("fixed")
      if (.not. given(group, "n_steps")) then
        call set_status(status, demstep_stat%invalid_input, "&"//g//": n_steps: required with steps = 'fixed'")
        return
      end if
      call new_step_policy(input%options%policy, step_kind%fixed, n_steps, status)
    case default
      call set_status(status, demstep_stat%invalid_input, "&"//g//": steps: unknown word '"// &
        trim(steps)//"' (half_period, fraction, rounded, fixed)")
      return
    end select
    if (status%stat /= demstep_stat%ok) then
      status%message = "&"//g//": "//status%message
      return
    end if
    select case (lowercase(trim(adjustl(pick))))
    case ("largest_step")
      input%options%pick = pick_kind%largest_step
    case ("zero")
      input%options%pick = pick_kind%zero
    case default
      call set_status(status, demstep_stat%invalid_input, "&"//g//": pick: unknown word '"// &
        trim(pick)//"' (largest_step, zero)")
      return
    end select
    select case (lowercase(trim(adjustl(aggregate))))
    case ("mean")
      input%aggregate = aggregate_kind%mean
    case ("weighted")
      input%aggregate = aggregate_kind%weighted
    case ("median")
      input%aggregate = aggregate_kind%median
    case ("min")
      input%aggregate = aggregate_kind%min
    case ("max")
      input%aggregate = aggregate_kind%max
    case default
      call set_status(status, demstep_stat%invalid_input, "&"//g//": aggregate: unknown word '"// &
        trim(aggregate)//"' (mean, weighted, median, min, max)")
      return
    end select
    call array_length(g, "weights", weights, n_weights, status)
    if (status%stat /= demstep_stat%ok) return
    if (input%aggregate == aggregate_kind%weighted) then
      input%weights = weights(:n_weights)
    else if (n_weights > 0) then
      call set_status(status, demstep_stat%invalid_input, "&"//g//": weights: only used with " &
        //"aggregate = 'weighted'")
      return
    end if
    input%mass = mass
    input%stiffness = stiffness
    input%options%tolerance = tolerance
    input%options%n_max = n_max
    input%options%resolution = resolution
    ! the report shows the first root and the first interval: the scan stops there
    input%options%first_only = .true.

    if (ctx%quiet) then
      call run_procedure(input, result, status)
    else
      cost = procedure_cost(input)
      if (cost > measure_above .and. cost <= max_procedure_evaluations) then
        ! the time of one evaluation, measured here and now (a few ms)
        call measure_evaluation_cost(input, seconds)
        if (cost*seconds > announce_seconds) write(error_unit, '(a)') "demstep: &"//g// &
          ": up to about "//fmt_real(cost)//" evaluations of E ("// &
          fmt_int(int(size(input%lambdas), i8))//" lambdas, resolution "//fmt_real(resolution)// &
          ", n_max "//fmt_real(n_max)//"), up to roughly "//fmt_real(real(nint(cost*seconds), dp))// &
          " s at the "//fmt_real(real(nint(1.0e9_dp*seconds), dp))//" ns an evaluation takes here"
      end if
      progress = text_progress_type(unit=error_unit, label="demstep: &"//g)
      call run_procedure(input, result, status, progress)
    end if
    if (status%stat /= demstep_stat%ok) then
      status%message = "&"//g//": "//status%message
      return
    end if
    call recommend(input, result, dt_stability, dt_recommended, governs, status)
    if (status%stat /= demstep_stat%ok) then
      status%message = "&"//g//": "//status%message
      return
    end if
    call report(ctx%report, group, input, result, dt_stability, dt_recommended, governs)
    if (dt_recommended > 0.0_dp) call record_step(ctx, "single-contact step", dt_recommended, .false., group)
    call write_result(ctx%results, result, dt_recommended)
  end subroutine handle_simulated_stiffness

  !> The recommended step: the procedure's dt = T*/N* is the accuracy step; the
  !> stability limit is that of the simulated spring K' (0 when N* was not found).
  subroutine recommend(input, result, dt_stability, dt_recommended, governs, status)
    type(stiffness_input_type), intent(in) :: input
    type(stiffness_result_type), intent(in) :: result
    real(dp), intent(out) :: dt_stability, dt_recommended
    integer, intent(out) :: governs
    type(demstep_status_type), intent(out) :: status
    type(spring_type) :: spring
    dt_stability = 0.0_dp
    dt_recommended = 0.0_dp
    governs = 0
    status%stat = demstep_stat%ok
    if (.not. (result%dt > 0.0_dp .and. result%stiffness_actual > 0.0_dp)) return
    call new_spring(spring, input%mass, result%stiffness_actual, status)
    if (status%stat /= demstep_stat%ok) return
    dt_stability = critical_time_step(spring)
    call recommended_step(dt_stability, dt_recommended, governs, status, dt_accuracy=result%dt)
  end subroutine recommend

  subroutine report(u, group, input, result, dt_stability, dt_recommended, governs)
    integer, intent(in) :: u
    type(nml_group_type), intent(in) :: group
    type(stiffness_input_type), intent(in) :: input
    type(stiffness_result_type), intent(in) :: result
    real(dp), intent(in) :: dt_stability, dt_recommended
    integer, intent(in) :: governs
    integer :: i
    character(len=20) :: zero, lower, upper, pick
    write(u, '(a)') "&simulated_stiffness (line "//fmt_int(int(group%line, i8))//")"
    write(u, '(2x, a)') "tolerance |E| <= "//fmt_real(input%options%tolerance)//", N scanned on (pi, " &
      //fmt_real(input%options%n_max)//"]"
    write(u, '(2x, a14, 4a20, 2x, a)') "lambda", "root of E", "N lower", "N upper", "N pick", "status"
    do i = 1, size(result%rows)
      associate(r => result%rows(i))
        zero = "-"
        lower = "-"
        upper = "-"
        pick = "-"
        if (size(r%roots) > 0) zero = fmt_real(r%roots(1))
        if (size(r%lower) > 0) then
          lower = fmt_real(r%lower(1))
          upper = fmt_real(r%upper(1))
          if (size(r%lower) == 1 .and. r%last_interval == interval_kind%unbounded) upper = "unbounded"
          if (size(r%lower) == 1 .and. r%last_interval /= interval_kind%bounded .and. &
            r%last_interval /= interval_kind%unbounded) upper = ">"//fmt_real(r%upper(1))
        end if
        if (r%stat /= demstep_stat%not_found) pick = fmt_real(r%n_pick)
        write(u, '(2x, a14, 4a20, 2x, a)') fmt_real(r%lambda), adjustr(zero), adjustr(lower), &
          adjustr(upper), adjustr(pick), status_word(r%stat)
      end associate
    end do
    if (result%excluded > 0) write(u, '(2x, a)') fmt_int(int(result%excluded, i8))// &
      " lambda(s) without an admissible N up to n_max: left out of N*"
    write(u, '(2x, a, t30, a)') "N*", fmt_real(result%n_star)
    write(u, '(2x, a, t30, a)') "lambda*", fmt_real(result%lambda_star)//"  ("// &
      status_word(result%lambda_star_stat)//")"
    write(u, '(2x, a, t30, a)') "T* = 2 pi sqrt(M/K*)", fmt_real(result%period)
    write(u, '(2x, a, t30, a)') "dt = T*/N*", fmt_real(result%dt)
    write(u, '(2x, a, t30, a)') "K' = lambda*^2 K*", fmt_real(result%stiffness_actual)
    write(u, '(2x, a)') "(E evaluated "//fmt_int(int(result%evaluations, i8))//" times)"
    if (dt_recommended > 0.0_dp) then
      write(u, '(2x, a, t30, a)') "critical step of K'", fmt_real(dt_stability)
      if (governs == step_governs%accuracy) then
        write(u, '(2x, a, t30, a)') "governs", "accuracy (dt = T*/N*, |E| <= tolerance)"
      else
        write(u, '(2x, a, t30, a)') "governs", "stability ("//fmt_real(default_safety)// &
          " of the critical step of K')"
      end if
      write(u, '(2x, a, t30, a)') "single-contact step", fmt_real(dt_recommended)//" s"
    end if
    write(u, '(a)') ""
  end subroutine report

  !> The report's word for a status code.
  pure function status_word(stat) result(word)
    integer, intent(in) :: stat
    character(len=:), allocatable :: word
    if (stat == demstep_stat%ok) then
      word = "ok"
    else if (stat == demstep_stat%at_stability_limit) then
      word = "holds at the stability limit"
    else if (stat == demstep_stat%discontinuous) then
      word = "pick jumps here"
    else if (stat == demstep_stat%not_found) then
      word = "none up to n_max"
    else
      word = "status "//fmt_int(int(stat, i8))
    end if
  end function status_word

  subroutine write_result(unit, result, dt_recommended)
    integer, intent(in) :: unit
    type(stiffness_result_type), intent(in) :: result
    real(dp), intent(in) :: dt_recommended
    real(dp), allocatable :: lambda(:), n_zero(:), n_lower(:), n_upper(:), n_pick(:)
    logical, allocatable :: bounded(:)
    integer, allocatable :: status(:)
    real(dp) :: n_star, lambda_star, period, dt, stiffness_actual
    integer :: lambda_star_status, excluded, i, n
    namelist /simulated_stiffness_result/ lambda, n_zero, n_lower, n_upper, bounded, n_pick, &
      status, n_star, lambda_star, lambda_star_status, period, dt, stiffness_actual, excluded, &
      dt_recommended
    n = size(result%rows)
    allocate(lambda(n), n_zero(n), n_lower(n), n_upper(n), n_pick(n), bounded(n), status(n))
    do i = 1, n
      associate(r => result%rows(i))
        lambda(i) = r%lambda
        n_zero(i) = 0.0_dp
        if (size(r%roots) > 0) n_zero(i) = r%roots(1)
        n_lower(i) = 0.0_dp
        n_upper(i) = 0.0_dp
        bounded(i) = .false.
        if (size(r%lower) > 0) then
          n_lower(i) = r%lower(1)
          n_upper(i) = r%upper(1)
          bounded(i) = size(r%lower) > 1 .or. r%last_interval == interval_kind%bounded
        end if
        n_pick(i) = r%n_pick
        status(i) = r%stat
      end associate
    end do
    n_star = result%n_star
    lambda_star = result%lambda_star
    lambda_star_status = result%lambda_star_stat
    period = result%period
    dt = result%dt
    stiffness_actual = result%stiffness_actual
    excluded = result%excluded
    write(unit, nml=simulated_stiffness_result)
  end subroutine write_result

end module demstep_cli_stiffness
