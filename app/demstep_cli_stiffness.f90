!> Group `&simulated_stiffness`: the whole simulated-stiffness procedure
!> (paper eqs. 25-29): dt = T*/N* and K' = lambda*^2 K*.
module demstep_cli_stiffness
  use demstep_harmonic, only: step_kind, new_step_policy, step_kind_from_name, step_kind_names
  use demstep_kinds, only: dp, i8
  use demstep_progress, only: text_progress_type
  use demstep_recommend, only: recommended_step, step_governs, default_safety
  use demstep_spring, only: spring_type, new_spring, critical_time_step
  use demstep_status, only: demstep_status_type, demstep_stat, set_status
  use demstep_stiffness, only: stiffness_input_type, stiffness_result_type, &
    run_procedure => simulated_stiffness, pick_kind, aggregate_kind, interval_kind, pick_kind_from_name, &
    pick_kind_names, aggregate_kind_from_name, aggregate_kind_names, default_n_max, default_resolution, &
    procedure_cost, measure_evaluation_cost, max_procedure_evaluations
  use demstep_namelist, only: nml_group_type
  use demstep_cli, only: record_step, var_spec, var, given, begin_group, fmt_real, fmt_int, cli_context, &
    next_assignment, group_reading, new_array, array_length, default_text, max_values, capacity_of, &
    in_group
  use demstep_words, only: unknown_word, word_index, word_choice
  use demstep_results, only: write_simulated_stiffness_result
  use, intrinsic :: iso_fortran_env, only: error_unit
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
      var("steps", "a quoted word", word_choice([character(len=11) :: "half_period", step_kind_names], [character(len=16) :: &
        "", "", "", "nint(f N) steps"]), "'half_period'", default="'half_period'"), &
      var("steps_fraction", "a real number", "f for steps = 'fraction' or 'rounded' (> 0)", "!0.5", &
        default="0.5"), &
      var("n_steps", "a real number", "n for steps = 'fixed' (>= 1)", "!100.0"), &
      var("pick", "a quoted word", word_choice(pick_kind_names, [character(len=25) :: &
        "smallest N with |E| <= E0", ""]), &
        "'largest_step'", default="'largest_step'"), &
      var("aggregate", "a quoted word", word_choice(aggregate_kind_names), &
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
    if (word_index(["half_period"], steps) == 1) then
      call new_step_policy(input%options%policy, step_kind%fraction, 0.5_dp, status)
    else
      kind = step_kind_from_name(steps)
      if (kind == 0) then
        call unknown_word(status, "steps", steps, [character(len=12) :: "half_period", step_kind_names])
        call in_group(status, g)
        return
      end if
      if (kind == step_kind%fixed .and. .not. given(group, "n_steps")) then
        call set_status(status, demstep_stat%invalid_input, "&"//g//": n_steps: required with steps = 'fixed'")
        return
      end if
      call new_step_policy(input%options%policy, kind, merge(n_steps, steps_fraction, kind == step_kind%fixed), &
        status)
    end if
    if (status%stat /= demstep_stat%ok) then
      call in_group(status, g)
      return
    end if
    input%options%pick = pick_kind_from_name(pick)
    if (input%options%pick == 0) then
      call unknown_word(status, "pick", pick, pick_kind_names)
      call in_group(status, g)
      return
    end if
    input%aggregate = aggregate_kind_from_name(aggregate)
    if (input%aggregate == 0) then
      call unknown_word(status, "aggregate", aggregate, aggregate_kind_names)
      call in_group(status, g)
      return
    end if
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
      call in_group(status, g)
      return
    end if
    call recommend(input, result, dt_stability, dt_recommended, governs, status)
    if (status%stat /= demstep_stat%ok) then
      call in_group(status, g)
      return
    end if
    call report(ctx%report, group, input, result, dt_stability, dt_recommended, governs)
    if (dt_recommended > 0.0_dp) call record_step(ctx, "single-contact step", dt_recommended, .false., group)
    call write_simulated_stiffness_result(ctx%results, result, dt_recommended)
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

end module demstep_cli_stiffness
