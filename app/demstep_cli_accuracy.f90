!> Groups `&contact_error` and `&accuracy_cost`: exact discrete contact errors,
!> and what a tolerance costs in steps and run time (table, CSV, figure).
module demstep_cli_accuracy
  use demstep_contact, only: discrete_contact_type, contact_with_onset, contact_worst_case, &
    quantity_kind, n_quantities, quantity_kind_names, quantity_kind_from_name, check_contact_damping
  use demstep_cost, only: n_for_tolerance, run_prediction_type, predict_run, worst_error, &
    n_for_harmonic_tolerance, default_cost_n_max, accuracy_cost_table, quantity_harmonic
  use demstep_step_cost, only: measure_step_cost
  use demstep_harmonic, only: harmonic_error
  use demstep_kinds, only: dp, i8, pi
  use demstep_progress, only: text_progress_type
  use demstep_recommend, only: recommended_step, step_governs, default_safety
  use demstep_spring, only: spring_type, new_spring, spring_period, critical_time_step
  use demstep_status, only: demstep_status_type, demstep_stat, set_status
  use demstep_namelist, only: nml_group_type
  use demstep_cli, only: record_step, var_spec, var, given, begin_group, fmt_real, fmt_int, cli_context, &
    next_assignment, group_reading, check_real, new_array, array_length, broadcast, common_length, &
    default_text, max_values, capacity_of, in_group
  use demstep_words, only: unknown_word, word_index, word_choice
  use demstep_cli_files, only: output_file_type, open_output, commit_output, discard_output, rename_file, &
    process_id, refuse_input
  use demstep_results, only: write_contact_error_result, write_accuracy_cost_result
  use, intrinsic :: iso_fortran_env, only: error_unit
  implicit none
  private

  public :: contact_error_specs, contact_error_doc, handle_contact_error
  public :: accuracy_cost_specs, accuracy_cost_doc, handle_accuracy_cost

  character(len=*), parameter :: contact_error_doc = &
    "Exact discrete contact of the central-difference scheme: steps in contact, contact time, " &
    //"restitution, largest overlap at N = T/dt and an onset (omitted: the worst onset)."
  character(len=*), parameter :: accuracy_cost_doc = &
    "What accuracy costs: for each tolerance the smallest N meeting it (worst onset), dt, steps " &
    //"for the duration and the predicted run time; a CSV file and a figure."

  !> The quantity 'harmonic': the paper's E (half-period steps) at a given lambda.
  !> The curves start at N = 4 (just above the stability limit pi).
  real(dp), parameter :: curve_n_min = 4.0_dp

contains

  function contact_error_specs() result(specs)
    type(var_spec), allocatable :: specs(:)
    specs = [ &
      var("n_per_period", "a list of real numbers", "N = T/dt (> 0; <= pi is flagged unstable)", &
        "10.0, 20.0, 50.0", capacity=max_values, required=.true.), &
      var("onset", "a list of real numbers", "overlap at the first force evaluation over v0 dt, " &
        //"in (0, 1]; omit for the worst case", "!1.0", capacity=max_values), &
      var("damping_ratio", "a real number", "viscous damping ratio (>= 0; < 1 for the worst case) " &
        //"of a lagged dashpot", "0.0", default="0") ]
  end function contact_error_specs

  function accuracy_cost_specs() result(specs)
    type(var_spec), allocatable :: specs(:)
    specs = [ &
      var("quantity", "a quoted word", word_choice([character(len=12) :: quantity_kind_names, "harmonic"], &
        [character(len=24) :: "", "", "", "", "the paper's E at lambda"]), "'restitution'", required=.true.), &
      var("tolerances", "a list of real numbers", "relative errors to meet (> 0)", "1e-2, 1e-3, 1e-4", &
        capacity=max_values, required=.true.), &
      var("duration", "a real number", "simulated time (> 0)", "1.0", required=.true.), &
      var("n_particles", "a real number", "particles in the simulation (>= 1)", "1.0e5", required=.true.), &
      var("mass", "a real number", "particle mass of the stiffest contact (> 0)", "0.01", required=.true.), &
      var("stiffness", "a real number", "its contact stiffness (> 0)", "1.0e5", required=.true.), &
      var("damping_ratio", "a real number", "viscous damping ratio in [0, 1)", "0.0", default="0"), &
      var("lambda", "a real number", "for 'harmonic': sqrt(K'/K*) in (0, 1]", "!0.95"), &
      var("cost_per_particle_step", "a real number", "seconds per particle-step (> 0); omit to " &
        //"measure the stepper on the spot", "!1.5e-7"), &
      var("n_max", "a real number", "largest N searched (at most 1e15)", "!"//default_text(default_cost_n_max), &
        default=default_text(default_cost_n_max)), &
      var("csv", "a quoted file name", "curve data", "'accuracy_cost.csv'", &
        default="'accuracy_cost.csv'"), &
      var("figure", "a quoted file name", "figure base name, .png and .svg added ('none' for no " &
        //"figure)", "'accuracy_cost'", default="'accuracy_cost'") ]
  end function accuracy_cost_specs

  !> Read, check and evaluate one `&contact_error` group.
  subroutine handle_contact_error(ctx, group, status)
    type(cli_context), intent(in) :: ctx
    type(nml_group_type), intent(in) :: group
    type(demstep_status_type), intent(out) :: status
    type(group_reading) :: reading
    real(dp), allocatable :: n_per_period(:), onset(:)
    real(dp) :: damping_ratio
    namelist /contact_error/ n_per_period, onset, damping_ratio
    type(var_spec), allocatable :: specs(:)
    character(len=*), parameter :: g = "contact_error"
    real(dp), allocatable :: big_n(:), s(:), onset_q(:, :), value(:, :)
    integer(i8), allocatable :: steps(:)
    logical, allocatable :: stable(:), saturated(:)
    integer :: i, lengths(2), length, q
    logical :: worst
    type(discrete_contact_type) :: c
    real(dp) :: e
    integer, parameter :: columns(3) = [quantity_kind%contact_time, quantity_kind%restitution, quantity_kind%overlap]

    specs = contact_error_specs()
    n_per_period = new_array(capacity_of(specs, "n_per_period"))
    onset = new_array(capacity_of(specs, "onset"))
    call begin_group(reading, group, specs, status)
    do while (next_assignment(reading, group, status))
      read(reading%text, nml=contact_error, iostat=reading%ios)
    end do
    if (status%stat /= demstep_stat%ok) return
    call array_length(g, "n_per_period", n_per_period, lengths(1), status)
    call array_length(g, "onset", onset, lengths(2), status)
    if (status%stat /= demstep_stat%ok) return
    call common_length(g, [character(len=12) :: "n_per_period", "onset"], lengths, length, status)
    if (status%stat /= demstep_stat%ok) return
    ! n_per_period, onset and damping_ratio: the library checks them (name_element)
    worst = lengths(2) == 0
    big_n = broadcast(n_per_period, lengths(1), length)
    if (.not. worst) s = broadcast(onset, lengths(2), length)

    ! value(:, q): steps-in-contact time, restitution, overlap; onset_q: where
    allocate(value(length, 3), onset_q(length, 3), steps(length), stable(length), saturated(length))
    do i = 1, length
      if (worst) then
        do q = 1, 3
          call contact_worst_case(big_n(i), columns(q), c, e, status, damping_ratio)
          if (status%stat /= demstep_stat%ok) then
            call name_element(status, i, big_n(i), 1.0_dp)
            return
          end if
          select case (q)
          case (1)
            value(i, q) = c%contact_time
          case (2)
            value(i, q) = c%restitution
          case (3)
            value(i, q) = c%max_overlap
          end select
          onset_q(i, q) = c%onset
          if (q == 1) steps(i) = c%steps
          if (q == 1) saturated(i) = c%steps_saturated
          stable(i) = c%stable
        end do
      else
        call contact_with_onset(big_n(i), s(i), c, status, damping_ratio)
        if (status%stat /= demstep_stat%ok) then
          call name_element(status, i, big_n(i), s(i))
          return
        end if
        value(i, :) = [c%contact_time, c%restitution, c%max_overlap]
        onset_q(i, :) = s(i)
        steps(i) = c%steps
        saturated(i) = c%steps_saturated
        stable(i) = c%stable
      end if
    end do
    call report_contact(ctx%report, group, worst, damping_ratio, big_n, steps, value, onset_q, stable, &
      saturated)
    if (worst) then
      call write_contact_error_result(ctx%results, big_n, steps, value, onset_q, stable)
    else
      call write_contact_error_result(ctx%results, big_n, s, steps, value, stable)
    end if
  contains
    !> The library's location and detail as "&contact_error: variable: element i is x; what".
    subroutine name_element(st, element, n_value, onset_value)
      type(demstep_status_type), intent(inout) :: st
      integer, intent(in) :: element
      real(dp), intent(in) :: n_value, onset_value
      character(len=:), allocatable :: name, what
      name = st%where
      what = st%detail
      select case (name)
      case ("n_per_period")
        what = "element "//fmt_int(int(element, i8))//" is "//fmt_real(n_value)//"; "//what
      case ("onset")
        what = "element "//fmt_int(int(element, i8))//" is "//fmt_real(onset_value)//"; "//what
      end select
      call set_status(st, demstep_stat%invalid_input, what, where=name)
      call in_group(st, g)
    end subroutine name_element
  end subroutine handle_contact_error

  subroutine report_contact(u, group, worst, zeta, big_n, steps, value, onset_q, stable, saturated)
    integer, intent(in) :: u
    type(nml_group_type), intent(in) :: group
    logical, intent(in) :: worst
    real(dp), intent(in) :: zeta, big_n(:), value(:, :), onset_q(:, :)
    integer(i8), intent(in) :: steps(:)
    logical, intent(in) :: stable(:), saturated(:)
    integer :: i
    write(u, '(a)') "&contact_error (line "//fmt_int(int(group%line, i8))//")"
    if (worst) then
      write(u, '(2x, a)') "worst case over the onset (the onset attaining it in brackets)"
    end if
    if (zeta > 0.0_dp) write(u, '(2x, a)') "lagged dashpot, damping ratio "//fmt_real(zeta)
    write(u, '(2x, a)') "contact time in T/2, overlap in v0/omega; exact undamped values are 1"
    write(u, '(2x, a12, a8, 3a26, 2x, a)') "N = T/dt", "steps", "contact time", "restitution", &
      "max overlap", ""
    do i = 1, size(big_n)
      write(u, '(2x, a12, a, 3a26, 2x, a)') fmt_real(big_n(i)), steps_cell(steps(i)), &
        cell(value(i, 1), onset_q(i, 1)), cell(value(i, 2), onset_q(i, 2)), &
        cell(value(i, 3), onset_q(i, 3)), merge("beyond the stability limit", "                          ", &
        .not. stable(i))
    end do
    if (any(saturated)) write(u, '(2x, a)') "steps 9223372036854775807: saturated, the count is " &
      //"above 2^63 - 1"
    write(u, '(a)') ""
  contains
    !> A count right-aligned in 8 columns (wider, after a blank, when it needs more).
    function steps_cell(n) result(text)
      integer(i8), intent(in) :: n
      character(len=:), allocatable :: text
      text = fmt_int(n)
      text = repeat(" ", max(1, 8 - len(text)))//text
    end function steps_cell
    function cell(x, s) result(text)
      real(dp), intent(in) :: x, s
      character(len=26) :: text
      text = fmt_real(x)//" ["//fmt_real(s)//"]"
      text = adjustr(text)
    end function cell
  end subroutine report_contact

  !> Read, check and evaluate one `&accuracy_cost` group.
  subroutine handle_accuracy_cost(ctx, group, status)
    type(cli_context), intent(in) :: ctx
    type(nml_group_type), intent(in) :: group
    type(demstep_status_type), intent(out) :: status
    type(group_reading) :: reading
    type(text_progress_type) :: progress
    character(len=32) :: quantity
    real(dp), allocatable :: tolerances(:)
    real(dp) :: duration, n_particles, mass, stiffness, damping_ratio, lambda, &
      cost_per_particle_step, n_max
    character(len=512) :: csv, figure
    namelist /accuracy_cost/ quantity, tolerances, duration, n_particles, mass, stiffness, &
      damping_ratio, lambda, cost_per_particle_step, n_max, csv, figure
    type(var_spec), allocatable :: specs(:)
    character(len=*), parameter :: g = "accuracy_cost"
    integer :: i, nt, q
    real(dp) :: period, cost, n_top
    real(dp), allocatable :: n(:), dt(:), predicted_seconds(:)
    integer(i8), allocatable :: steps(:)
    integer, allocatable :: stat(:)
    logical, allocatable :: saturated(:)
    logical :: measured
    type(spring_type) :: spring, damped
    type(run_prediction_type) :: prediction
    type(run_prediction_type), allocatable :: rows(:)
    real(dp) :: dt_recommended
    integer :: governs

    specs = accuracy_cost_specs()
    tolerances = new_array(capacity_of(specs, "tolerances"))
    call begin_group(reading, group, specs, status)
    do while (next_assignment(reading, group, status))
      read(reading%text, nml=accuracy_cost, iostat=reading%ios)
    end do
    if (status%stat /= demstep_stat%ok) return
    if (word_index(["harmonic"], quantity) == 1) then
      q = quantity_harmonic
    else
      q = quantity_kind_from_name(quantity)
    end if
    if (q == 0) then
      call unknown_word(status, "quantity", quantity, [character(len=12) :: quantity_kind_names, "harmonic"])
      call in_group(status, g)
      return
    end if
    call array_length(g, "tolerances", tolerances, nt, status)
    if (status%stat /= demstep_stat%ok) return
    ! tolerances, n_max (n_needed), mass, stiffness (new_spring) and damping_ratio
    ! (check_contact_damping) are the library's to check; predict_run takes the
    ! run's sizes as given, so their signs are checked here
    call check_real(g, "duration", duration, status)
    call check_real(g, "n_particles", n_particles, status, lower=1.0_dp, inclusive=.true.)
    if (given(group, "cost_per_particle_step")) call check_real(g, "cost_per_particle_step", &
      cost_per_particle_step, status)
    if (status%stat /= demstep_stat%ok) return
    if (q == quantity_harmonic .and. .not. given(group, "lambda")) then
      call set_status(status, demstep_stat%invalid_input, "&"//g//": lambda: required with " &
        //"quantity = 'harmonic'")
      return
    end if

    call check_file_name(g, "csv", trim(csv), .false., status)
    call check_not_input(ctx, g, "csv", trim(csv), [" "], status)
    if (trim(figure) /= "none" .and. len_trim(figure) > 0) then
      call check_file_name(g, "figure", trim(figure), .true., status)
      ! gnuplot writes the .tmp files, renamed over the figures
      call check_not_input(ctx, g, "figure", trim(figure), [character(len=8) :: ".png", ".svg", &
        ".png.tmp", ".svg.tmp"], status)
    end if
    if (status%stat /= demstep_stat%ok) return
    call new_spring(spring, mass, stiffness, status)
    if (status%stat == demstep_stat%ok) call check_contact_damping(damping_ratio, status)
    if (status%stat /= demstep_stat%ok) then
      call in_group(status, g)
      return
    end if
    period = spring_period(spring)
    measured = .not. given(group, "cost_per_particle_step")
    if (measured) then
      call measure_step_cost(cost, status)
      if (status%stat /= demstep_stat%ok) then
        status%message = "&"//g//": cost_per_particle_step: "//status%message
        return
      end if
    else
      cost = cost_per_particle_step
    end if

    allocate(n(nt), rows(nt), stat(nt))
    ! one root per tolerance: a long list shows its progress on stderr
    progress = text_progress_type(unit=error_unit, label="demstep: &"//g)
    ! --quiet: no line, however long
    if (ctx%quiet) progress%delay = huge(1.0_dp)
    call accuracy_cost_table(q, tolerances(:nt), period, duration, n_particles, cost, n, rows, stat, status, &
      damping_ratio=damping_ratio, lambda=lambda, n_max=n_max, progress=progress)
    if (status%stat /= demstep_stat%ok) then
      call in_group(status, g)
      return
    end if
    dt = rows%dt
    steps = rows%steps
    saturated = rows%steps_saturated
    predicted_seconds = rows%seconds
    ! the curves run from N = 4 to n_top: their predictions must hold as well
    n_top = max(1.0e3_dp, 4.0_dp*maxval(n, mask=stat == demstep_stat%ok .and. n < 1.0e6_dp))
    call predict_run(period, curve_n_min, duration, n_particles, cost, prediction, status)
    if (status%stat == demstep_stat%ok) call predict_run(period, n_top, duration, n_particles, cost, &
      prediction, status)
    if (status%stat /= demstep_stat%ok) then
      status%message = "&"//g//": "//status%message//" (for the curves, N from 4 to " &
        //fmt_real(n_top)//")"
      return
    end if
    call report_cost(ctx%report, group, q, tolerances(:nt), n, dt, steps, predicted_seconds, stat, &
      cost, measured, duration, n_particles, period, saturated)
    ! the recommended step: the tightest tolerance met, and the damped spring's limit
    call new_spring(damped, mass, stiffness, status, damping_ratio=damping_ratio)
    if (status%stat == demstep_stat%ok) then
      if (any(stat == demstep_stat%ok)) then
        call recommended_step(critical_time_step(damped), dt_recommended, governs, status, &
          dt_accuracy=minval(dt, mask=stat == demstep_stat%ok))
      else
        call recommended_step(critical_time_step(damped), dt_recommended, governs, status)
      end if
    end if
    if (status%stat /= demstep_stat%ok) then
      call in_group(status, g)
      return
    end if
    call write_accuracy_cost_result(ctx%results, tolerances(:nt), n, dt, steps, saturated, predicted_seconds, stat, cost, &
      period, dt_recommended)
    call write_curves(ctx%report, q, damping_ratio, lambda, period, duration, n_particles, cost, &
      n_top, trim(csv), trim(figure), status)
    if (status%stat /= demstep_stat%ok) then
      status%message = "&"//g//": csv: "//status%message
      return
    end if
    write(ctx%report, '(2x, a, t28, a)') "critical step", fmt_real(critical_time_step(damped))// &
      "  (lagged dashpot)"
    if (governs == step_governs%accuracy) then
      write(ctx%report, '(2x, a, t28, a)') "governs", "accuracy (the tightest tolerance met, " &
        //fmt_real(minval(tolerances(:nt), mask=stat == demstep_stat%ok))//")"
    else
      write(ctx%report, '(2x, a, t28, a)') "governs", "stability ("//fmt_real(default_safety)// &
        " of the critical step)"
    end if
    write(ctx%report, '(2x, a, t28, a)') "single-contact step", fmt_real(dt_recommended)//" s"
    write(ctx%report, '(a)') ""
    call record_step(ctx, "single-contact step", dt_recommended, .false., group)
  end subroutine handle_accuracy_cost

  subroutine report_cost(u, group, q, tolerances, n, dt, steps, seconds, stat, cost, measured, &
      duration, n_particles, period, saturated)
    integer, intent(in) :: u, q
    type(nml_group_type), intent(in) :: group
    real(dp), intent(in) :: tolerances(:), n(:), dt(:), seconds(:), cost, duration, n_particles, period
    integer(i8), intent(in) :: steps(:)
    integer, intent(in) :: stat(:)
    logical, intent(in) :: measured, saturated(:)
    integer :: i
    character(len=:), allocatable :: name
    if (q == quantity_harmonic) then
      name = "harmonic"
    else
      name = trim(quantity_kind_names(q))
    end if
    write(u, '(a)') "&accuracy_cost (line "//fmt_int(int(group%line, i8))//")"
    write(u, '(2x, a)') "quantity: "//name//" (worst case over the onset); T = "//fmt_real(period)// &
      ", duration "//fmt_real(duration)//", "//fmt_real(n_particles)//" particles"
    if (measured) then
      write(u, '(2x, a)') "cost per particle-step: "//fmt_real(cost)//" s (measured now: this build's " &
        //"stepper on 8000 particles with bonds and contacts)"
    else
      write(u, '(2x, a)') "cost per particle-step: "//fmt_real(cost)//" s (given)"
    end if
    write(u, '(2x, a12, a14, a14, a16, a21, a18)') "tolerance", "N = T/dt", "per contact", "dt", "steps", &
      "predicted time"
    do i = 1, size(tolerances)
      if (stat(i) /= demstep_stat%ok) then
        write(u, '(2x, a12, 2x, a)') fmt_real(tolerances(i)), "not met up to n_max"
      else
        ! steps: up to 19 digits, and a blank before them
        write(u, '(2x, a12, a14, a14, a16, a21, a18)') fmt_real(tolerances(i)), fmt_real(n(i)), &
          fmt_real(0.5_dp*n(i)), fmt_real(dt(i)), fmt_int(steps(i)), human_time(seconds(i))
      end if
    end do
    if (any(saturated)) write(u, '(2x, a)') "steps 9223372036854775807: saturated, the count is " &
      //"above 2^63 - 1 (the predicted time uses the exact count)"

  end subroutine report_cost

  !> Seconds as a readable duration.
  pure function human_time(t) result(text)
    real(dp), intent(in) :: t
    character(len=:), allocatable :: text
    if (t < 120.0_dp) then
      text = fmt_real(t)//" s"
    else if (t < 7200.0_dp) then
      text = fmt_real(t/60.0_dp)//" min"
    else if (t < 172800.0_dp) then
      text = fmt_real(t/3600.0_dp)//" h"
    else
      text = fmt_real(t/86400.0_dp)//" d"
    end if
  end function human_time

  !> A file name from the deck: not empty, no control characters, not a directory
  !> (for a figure base name: not ending in '/'; '.png' and '.svg' are added).
  subroutine check_file_name(group, variable, name, base, status)
    character(len=*), intent(in) :: group, variable, name
    !> True for a base name to which extensions are added.
    logical, intent(in) :: base
    type(demstep_status_type), intent(inout) :: status
    character(len=:), allocatable :: what
    integer :: i
    if (status%stat /= demstep_stat%ok) return
    what = "&"//group//": "//variable//": "
    if (len(name) == 0) then
      call set_status(status, demstep_stat%invalid_input, what//"must name a file, got ''")
      return
    end if
    do i = 1, len(name)
      if (iachar(name(i:i)) < 32 .or. iachar(name(i:i)) == 127) then
        call set_status(status, demstep_stat%invalid_input, what//"contains a control character " &
          //"(code "//fmt_int(int(iachar(name(i:i)), i8))//" at position "//fmt_int(int(i, i8))//")")
        return
      end if
    end do
    if (name(len(name):len(name)) == "/" .or. name == "." .or. name == ".." .or. &
        (.not. base .and. is_directory(name))) then
      call set_status(status, demstep_stat%invalid_input, what//"'"//name//"' is a directory; " &
        //"give a file name")
    end if
  end subroutine check_file_name

  !> An output file the deck names (`name` with each of the `suffixes`, blank for
  !> none) must not replace a file the deck reads: `&group: variable: 'file' is
  !> WHAT (an input; choose another name)`. Does nothing after an error.
  subroutine check_not_input(ctx, group, variable, name, suffixes, status)
    type(cli_context), intent(in) :: ctx
    character(len=*), intent(in) :: group, variable, name
    character(len=*), intent(in) :: suffixes(:)
    type(demstep_status_type), intent(inout) :: status
    type(demstep_status_type) :: refused
    integer :: i
    if (status%stat /= demstep_stat%ok .or. .not. allocated(ctx%inputs)) return
    do i = 1, size(suffixes)
      call refuse_input(ctx%inputs, name//trim(suffixes(i)), refused)
      if (refused%stat /= demstep_stat%ok) then
        call set_status(status, demstep_stat%invalid_input, "&"//group//": "//variable//": '" &
          //name//trim(suffixes(i))//"' "//refused%message//"; the output would replace it (choose another name)")
        return
      end if
    end do
  end subroutine check_not_input

  !> True when `path` names a directory (`path/.` then exists).
  logical function is_directory(path)
    character(len=*), intent(in) :: path
    inquire(file=path//"/.", exist=is_directory)
  end function is_directory

  !> The curves: worst errors of every quantity against N (and steps per contact
  !> N/2), with dt, steps and predicted time, as CSV; and a figure by gnuplot.
  !> Errors that cannot be computed (a discrete contact that never ends) are -1.
  !> No temporary file is left behind on any path.
  subroutine write_curves(u, q, zeta, lambda, period, duration, n_particles, cost, top, csv, figure, status)
    integer, intent(in) :: u, q
    real(dp), intent(in) :: zeta, lambda, period, duration, n_particles, cost, top
    character(len=*), intent(in) :: csv, figure
    type(demstep_status_type), intent(out) :: status
    real(dp) :: big_n, e(n_quantities + 1)
    real(dp), allocatable :: rows(:, :)
    integer :: unit, ios, k, j, m, rc, cs
    character(len=:), allocatable :: script, fig
    type(output_file_type) :: csv_file
    type(demstep_status_type) :: st
    type(run_prediction_type) :: prediction
    m = 120
    allocate(rows(11, 0:m))
    do k = 0, m
      big_n = curve_n_min*(top/curve_n_min)**(real(k, dp)/real(m, dp))
      do j = 1, n_quantities
        call worst_error(big_n, j, e(j), st, damping_ratio=zeta)
        if (st%stat /= demstep_stat%ok) e(j) = -1.0_dp
      end do
      e(n_quantities + 1) = 0.0_dp
      if (q == quantity_harmonic) then
        call harmonic_error(big_n, lambda, 0.5_dp*big_n, e(n_quantities + 1), j)
        e(n_quantities + 1) = abs(e(n_quantities + 1))
      end if
      ! checked at both ends of the curve by the caller
      call predict_run(period, big_n, duration, n_particles, cost, prediction, st)
      rows(:10, k) = [big_n, 0.5_dp*big_n, e, prediction%dt, prediction%steps_real, prediction%seconds]
    end do
    ! the guaranteed error at N: the chosen quantity's largest error at N or above
    rows(11, m) = rows(2 + min(q, n_quantities + 1), m)
    do k = m - 1, 0, -1
      rows(11, k) = max(rows(11, k + 1), rows(2 + min(q, n_quantities + 1), k))
    end do
    call open_output(csv, csv_file, status)
    if (status%stat /= demstep_stat%ok) then
      call set_status(status, demstep_stat%io_error, "'"//csv//"': "//status%message)
      return
    end if
    write(csv_file%unit, '(a)', iostat=ios) "n_per_period,steps_per_contact,restitution_error," &
      //"contact_time_error,overlap_error,period_error,harmonic_error,dt,steps,predicted_seconds," &
      //"guaranteed_error"
    do k = 0, m
      if (ios == 0) write(csv_file%unit, '(es16.8, *(",", es16.8))', iostat=ios) rows(:, k)
    end do
    if (ios /= 0) then
      call discard_output(csv_file)
      call set_status(status, demstep_stat%io_error, "'"//csv//"': cannot write")
      return
    end if
    call commit_output(csv_file, status)
    if (status%stat /= demstep_stat%ok) then
      call set_status(status, demstep_stat%io_error, "'"//csv//"': "//status%message)
      return
    end if
    status%stat = demstep_stat%ok
    write(u, '(2x, a)') "curves written to "//csv
    if (figure == "none" .or. len(figure) == 0) then
      write(u, '(a)') ""
      return
    end if
    ! (cmdstat: without a usable shell the runtime would stop the program)
    call execute_command_line("command -v gnuplot > /dev/null 2>&1", exitstat=rc, cmdstat=cs)
    if (rc /= 0 .or. cs /= 0) then
      write(u, '(2x, a)') "gnuplot not found: no figure (install gnuplot-nox); the CSV is written"
      write(u, '(a)') ""
      return
    end if
    fig = figure
    ! the shell sees only this fixed name; the user's names live inside the script,
    ! quoted by gnuplot's rules
    script = "demstep-figure-"//fmt_int(int(process_id(), i8))//".gp"
    ! (status "new": a file of that name is never replaced)
    open(newunit=unit, file=script, status="new", action="write", iostat=ios)
    if (ios /= 0) then
      write(u, '(2x, a)') "cannot write the gnuplot script in the current directory: no figure"
      write(u, '(a)') ""
      return
    end if
    call gnuplot_script(unit, csv, fig, q, ios)
    if (ios == 0) then
      close(unit, iostat=ios)
    else
      close(unit)
    end if
    rc = 1
    cs = 0
    if (ios == 0) call execute_command_line("gnuplot "//script//" > /dev/null 2>&1", exitstat=rc, &
      cmdstat=cs)
    call delete_file(script)
    if (rc /= 0 .or. cs /= 0) then
      call delete_file(fig//".png.tmp")
      call delete_file(fig//".svg.tmp")
      write(u, '(2x, a)') "gnuplot failed: no figure"
    else
      call rename_file(fig//".png.tmp", fig//".png", st)
      if (st%stat == demstep_stat%ok) call rename_file(fig//".svg.tmp", fig//".svg", st)
      if (st%stat == demstep_stat%ok) then
        write(u, '(2x, a)') "figure written to "//fig//".png and "//fig//".svg"
      else
        call delete_file(fig//".png.tmp")
        call delete_file(fig//".svg.tmp")
        write(u, '(2x, a)') "cannot rename the figure files: no figure"
      end if
    end if
    write(u, '(a)') ""
  end subroutine write_curves

  !> A file name as a gnuplot string literal: single quotes (no escapes, no
  !> backquote or macro substitution), a quote doubled, and relative names
  !> prefixed with './' so that a leading '<' or '|' is never a pipe.
  pure function gnuplot_quoted(name) result(text)
    character(len=*), intent(in) :: name
    character(len=:), allocatable :: text
    integer :: i, n
    character(len=:), allocatable :: path
    if (len(name) > 0 .and. name(1:1) == "/") then
      path = name
    else
      path = "./"//name
    end if
    n = len(path)
    do i = 1, len(path)
      if (path(i:i) == "'") n = n + 1
    end do
    allocate(character(len=n + 2) :: text)
    text(1:1) = "'"
    n = 1
    do i = 1, len(path)
      n = n + 1
      text(n:n) = path(i:i)
      if (path(i:i) == "'") then
        n = n + 1
        text(n:n) = "'"
      end if
    end do
    text(n+1:n+1) = "'"
  end function gnuplot_quoted

  subroutine delete_file(path)
    character(len=*), intent(in) :: path
    integer :: unit, ios
    open(newunit=unit, file=path, status="old", iostat=ios)
    if (ios == 0) close(unit, status="delete")
  end subroutine delete_file

  !> Two panels: worst error against steps per contact (log-log), and predicted
  !> run time against the chosen quantity's error.
  subroutine gnuplot_script(unit, csv, fig, q, ios)
    integer, intent(in) :: unit, q
    character(len=*), intent(in) :: csv, fig
    !> Nonzero when a write failed.
    integer, intent(out) :: ios
    integer :: t
    character(len=*), parameter :: terms(2) = [character(len=64) :: &
      "pngcairo size 1200,520 font 'sans,10'", "svg size 1200,520 font 'sans,10'"]
    character(len=*), parameter :: ext(2) = [".png.tmp", ".svg.tmp"]
    character(len=:), allocatable :: data
    data = gnuplot_quoted(csv)
    write(unit, '(a)', iostat=ios) "set datafile separator ','"
    do t = 1, 2
      if (ios /= 0) return
      write(unit, '(a)', iostat=ios) "set terminal "//trim(terms(t)), &
        "set output "//gnuplot_quoted(fig//trim(ext(t))), &
        "set multiplot layout 1,2", &
        "set logscale xy", "set grid", "set key top right", &
        "set format x '10^{%L}'", "set format y '10^{%L}'", &
        "set xlabel 'steps per contact (N/2)'", "set ylabel 'relative error, worst onset'", &
        "set title 'Central-difference contact: error against resolution'", &
        "plot "//data//" every ::1 using 2:3 with lines lw 2 title 'restitution', \", &
        "     '' every ::1 using 2:4 with lines lw 2 title 'contact time', \", &
        "     '' every ::1 using 2:5 with lines lw 2 title 'max overlap', \"
      if (ios /= 0) return
      if (q == quantity_harmonic) then
        write(unit, '(a)', iostat=ios) "     '' every ::1 using 2:6 with lines lw 2 title 'period', \", &
          "     '' every ::1 using 2:7 with lines lw 2 title '|E| (paper)'"
      else
        write(unit, '(a)', iostat=ios) "     '' every ::1 using 2:6 with lines lw 2 title 'period'"
      end if
      if (ios /= 0) return
      write(unit, '(a)', iostat=ios) "set xlabel 'guaranteed relative error (at this N and above)'", &
        "set ylabel 'predicted run time (s)'", "set title 'What accuracy costs'", "set key off", &
        "plot "//data//" every ::1 using 11:10 with steps lw 2", "unset multiplot", "set output"
    end do
  end subroutine gnuplot_script

end module demstep_cli_accuracy
