!> Group `&system`: one mass on a contact spring (the seed's model).
module demstep_cli_system
  use demstep_contact, only: discrete_contact_type, spring_contact
  use demstep_kinds, only: dp, i8, pi
  use demstep_recommend, only: recommended_step, default_safety
  use demstep_spring, only: spring_type, new_spring, spring_period, critical_time_step, growth_factor, &
    dashpot_kind, check_time_step, step_for_n_per_period, spring_omega, spring_damping_ratio, &
    numerical_phase, dashpot_kind_from_name, dashpot_kind_names
  use demstep_status, only: demstep_status_type, demstep_stat, set_status
  use demstep_namelist, only: nml_group_type
  use demstep_words, only: unknown_word, word_choice
  use demstep_cli, only: report_row, record_step, var_spec, var, given, begin_group, check_real, &
    next_assignment, group_reading, fmt_real, fmt_int, in_group, cli_context
  use demstep_results, only: write_system_result
  implicit none
  private

  public :: system_specs, system_doc, handle_system

  !> One line on what the group is for.
  character(len=*), parameter :: system_doc = &
    "One mass M hitting a contact spring K at speed v0 (the seed's model): period, " &
    //"stability limit and, for a step dt, the discrete contact."

contains

  !> The variables of `&system`.
  function system_specs() result(specs)
    type(var_spec), allocatable :: specs(:)
    specs = [ &
      var("mass", "a real number", "mass M (> 0)", "0.01", required=.true.), &
      var("stiffness", "a real number", "normal stiffness K (> 0)", "1.0e5", required=.true.), &
      var("damping_ratio", "a real number", "viscous damping ratio zeta >= 0", "0.0", default="0"), &
      var("dashpot", "a quoted word", word_choice(dashpot_kind_names, [character(len=22) :: &
        "half-step-old velocity", ""]), &
        "'lagged'", default="'lagged'"), &
      var("velocity", "a real number", "impact speed v0 > 0, scales overlaps", "1.0", default="1"), &
      var("dt", "a real number", "time step to assess (> 0), or give n_per_period", "!2.0e-4", &
        excludes="n_per_period"), &
      var("n_per_period", "a real number", "steps per natural period N = T/dt (> 0), or give dt", &
        "10.0") ]
  end function system_specs

  !> Read, check and evaluate one `&system` group.
  subroutine handle_system(ctx, group, status)
    type(cli_context), intent(in) :: ctx
    type(nml_group_type), intent(in) :: group
    type(demstep_status_type), intent(out) :: status
    type(group_reading) :: reading
    real(dp) :: mass, stiffness, damping_ratio, velocity, dt, n_per_period
    character(len=32) :: dashpot
    namelist /system/ mass, stiffness, damping_ratio, dashpot, velocity, dt, n_per_period
    type(spring_type) :: spring
    integer :: kind
    character(len=*), parameter :: g = "system"

    call begin_group(reading, group, system_specs(), status)
    do while (next_assignment(reading, group, status))
      read(reading%text, nml=system, iostat=reading%ios)
    end do
    if (status%stat /= demstep_stat%ok) return
    ! mass, stiffness, damping_ratio (new_spring), dt and n_per_period
    ! (check_time_step, step_for_n_per_period) are the library's to check;
    ! the impact velocity is the report's own
    call check_real(g, "velocity", velocity, status)
    if (status%stat /= demstep_stat%ok) return
    kind = dashpot_kind_from_name(dashpot)
    if (kind == 0) then
      call unknown_word(status, "dashpot", dashpot, dashpot_kind_names)
      call in_group(status, "system")
      return
    end if

    call new_spring(spring, mass, stiffness, status, damping_ratio=damping_ratio, dashpot=kind)
    if (status%stat /= demstep_stat%ok) then
      call in_group(status, "system")
      return
    end if
    if (given(group, "n_per_period")) then
      call step_for_n_per_period(spring, n_per_period, dt, status)
    else if (given(group, "dt")) then
      call check_time_step(spring, dt, status)
    end if
    if (status%stat /= demstep_stat%ok) then
      call in_group(status, "system")
      return
    end if
    call evaluate(ctx, group, spring, velocity, given(group, "dt") .or. given(group, "n_per_period"), &
      dt, merge("n_per_period", "dt          ", given(group, "n_per_period")), status)
  end subroutine handle_system

  !> Compute, report and write the result group.
  subroutine evaluate(ctx, group, spring, velocity, have_dt, dt, step_name, status)
    type(cli_context), intent(in) :: ctx
    type(nml_group_type), intent(in) :: group
    type(spring_type), intent(in) :: spring
    real(dp), intent(in) :: velocity, dt
    logical, intent(in) :: have_dt
    !> The variable that gave the step: dt or n_per_period.
    character(len=*), intent(in) :: step_name
    type(demstep_status_type), intent(out) :: status
    real(dp) :: period, omega, dt_critical, n_per_period, theta, period_numerical, rho
    real(dp) :: zeta, overlap, dt_recommended
    integer :: governs
    type(discrete_contact_type) :: contact
    type(demstep_status_type) :: phase_status
    logical :: stable
    integer :: u

    u = ctx%report
    period = spring_period(spring)
    omega = spring_omega(spring)
    dt_critical = critical_time_step(spring)
    zeta = spring_damping_ratio(spring)
    write(u, '(a)') "&system (line "//fmt_int(int(group%line, i8))//")"
    call report_row(u, 2, "mass M", fmt_real(spring%mass))
    call report_row(u, 2, "stiffness K", fmt_real(spring%stiffness))
    if (zeta > 0.0_dp) call report_row(u, 2, "damping ratio", fmt_real(zeta)//merge(" (lagged dashpot) ", &
      " (centred dashpot)", spring%dashpot == dashpot_kind%lagged))
    call report_row(u, 2, "natural period T", fmt_real(period)//"  (2 pi sqrt(M/K))")
    call report_row(u, 2, "omega", fmt_real(omega))
    call report_row(u, 2, "critical step", fmt_real(dt_critical)//"  (T/"//fmt_real(period/dt_critical)//")")
    call recommended_step(dt_critical, dt_recommended, governs, status)
    if (status%stat /= demstep_stat%ok) then
      call in_group(status, "system")
      return
    end if
    if (.not. have_dt) then
      call write_system_result(ctx%results, period, omega, dt_critical, dt_recommended)
      call recommend_line(ctx, group, dt_recommended)
      return
    end if

    n_per_period = period/dt
    stable = dt < dt_critical
    rho = growth_factor(spring, dt)
    call report_row(u, 2, "time step dt", fmt_real(dt)//"  (N = T/dt = "//fmt_real(n_per_period)//")")
    if (.not. stable) then
      call report_row(u, 2, "stable", "NO: dt >= critical step; amplitude grows by "//fmt_real(rho)// &
        " per step")
      call write_system_result(ctx%results, period, omega, dt_critical, dt, n_per_period, rho, dt_recommended)
      call recommend_line(ctx, group, dt_recommended)
      return
    end if
    call numerical_phase(omega*dt, theta, phase_status)
    ! 2 pi dt/theta, formed as T (omega dt/theta) so that nothing underflows
    period_numerical = period*(omega*dt/theta)
    ! the contact in closed form (onset at a step), either dashpot
    call spring_contact(spring, dt, contact, status)
    if (status%stat /= demstep_stat%ok) then
      ! the library speaks of N; the deck may have given dt
      call in_group(status, "system", reshape([character(len=12) :: "n_per_period", step_name], [2, 1]))
      status%stat = demstep_stat%invalid_input
      return
    end if
    ! the overlap v0/omega x ratio must be a normal double
    overlap = (velocity/omega)*contact%max_overlap
    if (.not. (overlap >= tiny(1.0_dp) .and. overlap <= huge(1.0_dp))) then
      call set_status(status, demstep_stat%invalid_input, "&system: velocity: must be in [" &
        //fmt_real(1.001_dp*(tiny(1.0_dp)/contact%max_overlap)*omega)//", " &
        //fmt_real(min(huge(1.0_dp), 0.999_dp*(huge(1.0_dp)/contact%max_overlap)*omega)) &
        //"] here (the largest overlap velocity/omega x "//fmt_real(contact%max_overlap) &
        //" must stay in the double range), got "//fmt_real(velocity))
      return
    end if
    call report_row(u, 2, "stable", "yes (dt/dt_critical = "//fmt_real(dt/dt_critical)//")")
    call report_row(u, 2, "phase per step theta", fmt_real(theta)//"  (2 asin(omega dt/2), undamped)")
    call report_row(u, 2, "numerical period", fmt_real(period_numerical)//"  (error " &
      //fmt_real(100.0_dp*(period_numerical/period - 1.0_dp))//" %)")
    write(u, '(2x, a)') "discrete contact, onset at a step, impact speed "//fmt_real(velocity)//":"
    if (contact%steps_saturated) then
      call report_row(u, 2, "  steps in contact", "more than "//fmt_int(contact%steps)//" (saturated at 2^63 - 1)")
    else
      call report_row(u, 2, "  steps in contact", fmt_int(contact%steps))
    end if
    call report_row(u, 2, "  contact time", fmt_real(contact%contact_time*(0.5_dp*period))//"  (exact T/2 = " &
      //fmt_real(0.5_dp*period)//")")
    call report_row(u, 2, "  restitution", fmt_real(contact%restitution)//merge(" (gains energy)", &
      "               ", contact%restitution > 1.0_dp))
    call report_row(u, 2, "  max overlap", fmt_real(overlap)// &
      "  (exact v0/omega = "//fmt_real(velocity/omega)//")")
    call recommend_line(ctx, group, dt_recommended)
    call write_system_result(ctx%results, period, omega, dt_critical, dt, n_per_period, rho, theta, &
      period_numerical, contact%steps, contact%contact_time*(0.5_dp*period), contact%restitution, &
      overlap, dt_recommended)
  end subroutine evaluate

  !> The closing rows: the contact's step (no tolerance here: stability governs),
  !> recorded for the deck's recommended dt.
  subroutine recommend_line(ctx, group, dt_recommended)
    type(cli_context), intent(in) :: ctx
    type(nml_group_type), intent(in) :: group
    real(dp), intent(in) :: dt_recommended
    call report_row(ctx%report, 2, "governs", "stability ("//fmt_real(default_safety)//" of the critical step; " &
      //"&accuracy_cost gives the step for a tolerance)")
    call report_row(ctx%report, 2, "single-contact step", fmt_real(dt_recommended)//" s")
    write(ctx%report, '(a)') ""
    call record_step(ctx, "single-contact step", dt_recommended, .false., group)
  end subroutine recommend_line

end module demstep_cli_system
