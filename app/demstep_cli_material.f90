!> Group `&material`: particle types (E, nu, density, radius), restitution and
!> impact velocity; per pair of types the contact parameters in each DEM code's
!> convention, the time scales, the peers' time-step rules beside demstep's
!> exact limit, and one recommended step.
module demstep_cli_material
  use demstep, only: dp, i8, demstep_status_type, demstep_stat, nml_group_type, material_type, &
    material_pair_type, effective_pair_type, contact_parameters_type, peer_steps_type, effective_pair, &
    contact_parameters, peer_time_steps, code_convention, convention_names, peer_rule_names, &
    recommended_step, step_governs, default_safety, contact_assessment_type
  use demstep_material, only: convention_limit, n_conventions, n_peer_rules, liggghts_velocity_factor, &
    check_pair
  use demstep_recommend, only: assess_material_pair
  use demstep_cost, only: default_cost_n_max
  use demstep_status, only: set_status
  use demstep_text, only: lowercase
  use demstep_cli, only: record_step, var_spec, var, given, begin_group, fmt_real, fmt_int, cli_context, &
    next_assignment, group_reading, &
    new_array, array_length, common_length, broadcast, capacity_of, word_list, report_row
  implicit none
  private

  public :: material_specs, material_doc, handle_material, read_material

  character(len=*), parameter :: material_doc = &
    "Particle types (E, nu, density, radius): per pair the contact parameters in each code's " &
    //"convention, Rayleigh/Hertz/linear times, the peers' rules beside demstep's exact limit."

  !> Most particle types.
  integer, parameter :: max_types = 100

contains

  !> The variables of `&material`.
  function material_specs() result(specs)
    type(var_spec), allocatable :: specs(:)
    specs = [ &
      var("young", "a list of real numbers", "Young's modulus E per particle type (> 0)", "7.0e10", &
        capacity=max_types, required=.true.), &
      var("poisson", "a list of real numbers", "Poisson's ratio per type, in (-1, 0.5]", "0.25", &
        capacity=max_types, required=.true.), &
      var("density", "a list of real numbers", "density per type (> 0)", "2500.0", capacity=max_types, &
        required=.true.), &
      var("radius", "a list of real numbers", "radius per type (> 0)", "0.5e-3", capacity=max_types, &
        required=.true.), &
      var("restitution", "a real number", "normal restitution coefficient, in (0, 1]", "0.9", required=.true.), &
      var("restitution_t", "a real number", "tangential restitution (0: the normal one)", "0.0", &
        default="0"), &
      var("impact_velocity", "a real number", "characteristic impact velocity (> 0): Hertz " &
        //"linearisation and durations", "1.0", required=.true.), &
      var("code", "a quoted word", "'all' or one of: "//names_list(), "'all'", default="'all'"), &
      var("tolerance", "a real number", "tolerance on the restitution error, in (0, 1); gives the " &
        //"accuracy step", "!1.0e-2") ]
  end function material_specs

  pure function names_list() result(text)
    character(len=:), allocatable :: text
    text = word_list(convention_names(:n_conventions), quote="'")
  end function names_list

  !> Read, check and evaluate one `&material` group.
  subroutine handle_material(ctx, group, status)
    type(cli_context), intent(in) :: ctx
    type(nml_group_type), intent(in) :: group
    type(demstep_status_type), intent(out) :: status
    type(material_type), allocatable :: types(:)
    real(dp) :: restitution, restitution_t, impact_velocity, tolerance
    integer :: first, last
    call read_material(group, types, restitution, restitution_t, impact_velocity, first, last, &
      tolerance, status)
    if (status%stat /= demstep_stat%ok) return
    call evaluate(ctx, group, types, restitution, restitution_t, impact_velocity, first, last, &
      given(group, "tolerance"), tolerance, status)
    if (status%stat /= demstep_stat%ok) status%message = "&material: "//status%message
  end subroutine handle_material

  !> Read and check one `&material` group: the types, the loading, the
  !> conventions `first` to `last` (`code`) and the tolerance (0 when not given).
  !> Messages start with `&material: `. Also used by `&scene` for a snapshot's types.
  subroutine read_material(group, types, restitution, restitution_t, impact_velocity, first, last, &
      tolerance, status)
    type(nml_group_type), intent(in) :: group
    type(material_type), allocatable, intent(out) :: types(:)
    real(dp), intent(out) :: restitution, restitution_t, impact_velocity, tolerance
    integer, intent(out) :: first, last
    type(demstep_status_type), intent(out) :: status
    type(group_reading) :: reading
    real(dp), allocatable :: young(:), poisson(:), density(:), radius(:)
    character(len=32) :: code
    namelist /material/ young, poisson, density, radius, restitution, restitution_t, impact_velocity, &
      code, tolerance
    type(var_spec), allocatable :: specs(:)
    integer :: lengths(4), n, k
    character(len=*), parameter :: g = "material"

    first = 0
    last = -1
    specs = material_specs()
    young = new_array(capacity_of(specs, "young"))
    poisson = new_array(capacity_of(specs, "poisson"))
    density = new_array(capacity_of(specs, "density"))
    radius = new_array(capacity_of(specs, "radius"))
    tolerance = 0.0_dp
    call begin_group(reading, group, specs, status)
    do while (next_assignment(reading, group, status))
      read(reading%text, nml=material, iostat=reading%ios)
    end do
    if (status%stat /= demstep_stat%ok) return
    call array_length(g, "young", young, lengths(1), status)
    call array_length(g, "poisson", poisson, lengths(2), status)
    call array_length(g, "density", density, lengths(3), status)
    call array_length(g, "radius", radius, lengths(4), status)
    call common_length(g, [character(len=8) :: "young", "poisson", "density", "radius"], lengths, n, status)
    if (status%stat /= demstep_stat%ok) return
    allocate(types(n))
    types%young = broadcast(young, lengths(1), n)
    types%poisson = broadcast(poisson, lengths(2), n)
    types%density = broadcast(density, lengths(3), n)
    types%radius = broadcast(radius, lengths(4), n)
    select case (lowercase(trim(adjustl(code))))
    case ("all")
      first = 1
      last = n_conventions
    case default
      first = findloc([(lowercase(trim(adjustl(code))) == trim(convention_names(k)), k = 1, n_conventions)], &
        .true., dim=1)
      if (first == 0) then
        call set_status(status, demstep_stat%invalid_input, "&material: code: must be 'all' or one of " &
          //names_list()//", got '"//trim(code)//"'")
        return
      end if
      last = first
    end select
    ! the loading, checked here for every reader of the group (a &scene too)
    call check_pair(material_pair_type(types(1), types(1), restitution, restitution_t, impact_velocity), status)
    if (status%stat /= demstep_stat%ok) then
      status%message = "&material: "//status%message
      return
    end if
    if (given(group, "tolerance")) then
      if (.not. (tolerance > 0.0_dp .and. tolerance < 1.0_dp)) then
        call set_status(status, demstep_stat%invalid_input, "&material: tolerance: must lie in (0, 1), got " &
          //fmt_real(tolerance))
        return
      end if
    end if
  end subroutine read_material

  !> Per pair of types: conventions, time scales, rules and limits; then the
  !> recommended step over all pairs.
  subroutine evaluate(ctx, group, types, restitution, restitution_t, velocity, first, last, &
      have_tolerance, tolerance, status)
    type(cli_context), intent(in) :: ctx
    type(nml_group_type), intent(in) :: group
    type(material_type), intent(in) :: types(:)
    real(dp), intent(in) :: restitution, restitution_t, velocity, tolerance
    integer, intent(in) :: first, last
    logical, intent(in) :: have_tolerance
    type(demstep_status_type), intent(out) :: status
    type(material_pair_type) :: pair
    type(effective_pair_type) :: eff
    type(contact_parameters_type) :: params
    type(peer_steps_type) :: steps
    type(contact_assessment_type) :: exact
    integer :: n, np, i, j, p, c, u, nc, governs
    integer, allocatable :: type_i(:), type_j(:)
    real(dp), allocatable :: k_n(:, :), k_t(:, :), gamma_n(:, :), gamma_t(:, :), dt_code(:, :), &
      peer_dt(:, :), m_star(:), rayleigh(:), hertz_duration(:), linear_duration(:), dt_critical(:), &
      dt_accuracy(:), k_linear(:)
    real(dp) :: dt_recommended, dt_stability
    character(len=:), allocatable :: who
    u = ctx%report
    n = size(types)
    np = n*(n + 1)/2
    nc = last - first + 1
    allocate(type_i(np), type_j(np), k_n(nc, np), k_t(nc, np), gamma_n(nc, np), gamma_t(nc, np), &
      dt_code(nc, np), peer_dt(n_peer_rules, np), m_star(np), rayleigh(np), hertz_duration(np), &
      linear_duration(np), dt_critical(np), dt_accuracy(np), k_linear(np))
    dt_accuracy = 0.0_dp
    write(u, '(a)') "&material (line "//fmt_int(int(group%line, i8))//"): "//fmt_int(int(n, i8))// &
      " particle type"//trim(merge("s", " ", n > 1))//", restitution "//fmt_real(restitution)// &
      ", impact velocity "//fmt_real(velocity)
    if (ctx%material_in_scene) write(u, '(2x, a)') "(single contacts of each pair of types; the " &
      //"&scene packing made of them gives the recommended dt)"
    p = 0
    do i = 1, n
      do j = i, n
        p = p + 1
        type_i(p) = i
        type_j(p) = j
        who = "types "//fmt_int(int(i, i8))//" and "//fmt_int(int(j, i8))//": "
        pair = material_pair_type(types(i), types(j), restitution, restitution_t, velocity)
        call effective_pair(pair%a, pair%b, eff, status)
        if (status%stat /= demstep_stat%ok) then
          status%message = fix_label(status%message, i, j)
          return
        end if
        m_star(p) = eff%m_star
        call peer_time_steps(pair, steps, status)
        if (status%stat /= demstep_stat%ok) return
        if (have_tolerance) then
          call assess_material_pair(pair, exact, status, tolerance=tolerance, stiffness=k_linear(p))
        else
          call assess_material_pair(pair, exact, status, stiffness=k_linear(p))
        end if
        if (status%stat == demstep_stat%not_found) then
          call set_status(status, demstep_stat%invalid_input, "tolerance: "//fmt_real(tolerance)// &
            " is not met below "//fmt_real(default_cost_n_max)//" steps per period ("//who(:len(who)-2)//"); use a larger one")
          return
        else if (status%stat /= demstep_stat%ok) then
          status%message = pair_message(who, status%message)
          return
        end if
        dt_critical(p) = exact%dt_critical
        dt_accuracy(p) = exact%dt_accuracy
        rayleigh(p) = steps%rayleigh
        hertz_duration(p) = steps%hertz_duration
        peer_dt(:, p) = steps%dt
        call contact_parameters(pair, code_convention%liggghts_hooke, params, status)
        if (status%stat /= demstep_stat%ok) return
        linear_duration(p) = params%t_contact
        write(u, '(2x, a)') "pair of types "//fmt_int(int(i, i8))//"-"//fmt_int(int(j, i8))//": m* = " &
          //fmt_real(eff%m_star)//", R* = "//fmt_real(eff%r_star)//", E* = "//fmt_real(eff%e_star)// &
          ", G* = "//fmt_real(eff%g_star)
        write(u, '(4x, a22, 5a16)') "convention", "k_n", "k_t", "gamma_n", "gamma_t", "exact limit"
        do c = first, last
          call contact_parameters(pair, c, params, status)
          if (status%stat /= demstep_stat%ok) then
            status%message = pair_message(who//trim(convention_names(c))//": ", status%message)
            return
          end if
          call convention_limit(params, eff%m_star, dt_code(c - first + 1, p), status)
          if (status%stat /= demstep_stat%ok) then
            status%message = pair_message(who//trim(convention_names(c))//": ", status%message)
            return
          end if
          k_n(c - first + 1, p) = params%k_n
          k_t(c - first + 1, p) = params%k_t
          gamma_n(c - first + 1, p) = params%gamma_n
          gamma_t(c - first + 1, p) = params%gamma_t
          write(u, '(4x, a22, 5a16)') trim(convention_names(c)), fmt_real(params%k_n), fmt_real(params%k_t), &
            fmt_real(params%gamma_n), fmt_real(params%gamma_t), fmt_real(dt_code(c - first + 1, p))
        end do
        write(u, '(4x, a)') "(Hertz conventions: secant k_n, k_t and gamma at the impact's largest " &
          //"overlap; their limit uses the tangent stiffness, 3/2 k_n)"
        call report_row(u, 4, "Rayleigh time", fmt_real(steps%rayleigh)//"  (0.8766 factor; Yade's: " &
          //fmt_real(steps%rayleigh_yade)//")")
        call report_row(u, 4, "Hertz contact duration", fmt_real(steps%hertz_duration)//"  (at the impact velocity; " &
          //"LIGGGHTS' estimate "//fmt_real(steps%hertz_liggghts)//" at relative velocity " &
          //fmt_real(liggghts_velocity_factor)//" x "//fmt_real(velocity)//", as check/timestep/gran)")
        call report_row(u, 4, "linear contact duration", fmt_real(linear_duration(p))//"  (LIGGGHTS Hooke spring)")
        call report_row(u, 4, "demstep exact limit", fmt_real(exact%dt_critical)//"  (Hertz linearised at the " &
          //"impact's largest overlap, k = "//fmt_real(k_linear(p))//", lagged dashpot, damping ratio " &
          //fmt_real(exact%damping_ratio)//")")
        write(u, '(4x, a22, 2a16)') "peer rule", "dt", "dt/exact limit"
        do c = 1, n_peer_rules
          write(u, '(4x, a22, 2a16)') trim(peer_rule_names(c)), fmt_real(steps%dt(c)), &
            fmt_real(steps%dt(c)/exact%dt_critical)
        end do
        if (have_tolerance) call report_row(u, 4, "accuracy step", fmt_real(exact%dt_accuracy)// &
          "  (restitution error <= "//fmt_real(tolerance)//", linearised contact)")
      end do
    end do
    ! one code chosen: its own contact (say Yade's stiff linear spring) may be stiffer
    dt_stability = minval(dt_critical)
    if (first == last) dt_stability = min(dt_stability, minval(dt_code))
    if (first == last) then
      call report_row(u, 4, "stability limit", fmt_real(dt_stability)//"  (smallest over the pairs, with " &
        //trim(convention_names(first))//"'s own contact)")
    else
      call report_row(u, 4, "stability limit", fmt_real(dt_stability)//"  (smallest over the pairs)")
    end if
    if (have_tolerance) then
      call recommended_step(dt_stability, dt_recommended, governs, status, dt_accuracy=minval(dt_accuracy))
    else
      call recommended_step(dt_stability, dt_recommended, governs, status)
    end if
    if (status%stat /= demstep_stat%ok) return
    if (governs == step_governs%accuracy) then
      call report_row(u, 4, "governs", "accuracy (tolerance "//fmt_real(tolerance)//" on the restitution)")
    else
      call report_row(u, 4, "governs", "stability ("//fmt_real(default_safety)//" of the smallest exact limit)")
      if (.not. have_tolerance) write(u, '(4x, a)') "(stability only: give tolerance for accuracy)"
    end if
    if (ctx%material_in_scene) then
      ! the deck's recommended dt is the packing's (&scene)
      call report_row(u, 4, "single-contact step", fmt_real(dt_recommended)//" s  (not for the packing)")
    else
      call report_row(u, 4, "single-contact step", fmt_real(dt_recommended)//" s")
    end if
    write(u, '(a)') ""
    call record_step(ctx, "single-contact step", dt_recommended, .false., group)
    call write_result(ctx%results, [(convention_names(c), c = first, last)], peer_rule_names, type_i, type_j, &
      m_star, k_n, k_t, gamma_n, gamma_t, dt_code, rayleigh, hertz_duration, linear_duration, dt_critical, &
      peer_dt, dt_accuracy, dt_recommended, trim(merge("stability", "accuracy ", &
      governs == step_governs%stability)))
    status%stat = demstep_stat%ok
  end subroutine evaluate

  !> The library names a pair's types a and b; the report numbers them.
  !> A library message about one pair (`who`: "types i and j: " and maybe the
  !> code) as the deck's `variable: what`: the `&material` variable it names comes
  !> first (`poisson: types 1 and 1: yade_frictphys: ...`); the contact stiffness
  !> `k_n`, no deck variable, is named by `young`, from which the codes derive it.
  function pair_message(who, message) result(text)
    character(len=*), intent(in) :: who, message
    character(len=:), allocatable :: text
    type(var_spec), allocatable :: specs(:)
    integer :: i
    if (index(message, "k_n: ") == 1) then
      text = "young: "//who//"the contact stiffness k_n it gives (with poisson, radius and " &
        //"impact_velocity) "//message(6:)
      return
    end if
    text = who//message
    allocate(specs, source=material_specs())
    do i = 1, size(specs)
      if (index(message, specs(i)%name//": ") == 1) then
        text = specs(i)%name//": "//who//message(len(specs(i)%name) + 3:)
        exit
      end if
    end do
  end function pair_message

  pure function fix_label(message, i, j) result(text)
    character(len=*), intent(in) :: message
    integer, intent(in) :: i, j
    character(len=:), allocatable :: text
    integer :: k
    text = message
    k = index(text, "(particle type a)")
    if (k > 0) text = text(:k-1)//"(particle type "//fmt_int(int(i, i8))//")"//text(k+17:)
    k = index(text, "(particle type b)")
    if (k > 0) text = text(:k-1)//"(particle type "//fmt_int(int(j, i8))//")"//text(k+17:)
  end function fix_label


  subroutine write_result(unit, conventions, peer_rules, type_i, type_j, m_star, k_n, k_t, gamma_n, &
      gamma_t, dt_code, rayleigh_time, hertz_duration, linear_duration, dt_critical, peer_dt, &
      dt_accuracy, dt_recommended, governs)
    integer, intent(in) :: unit
    character(len=*), intent(in) :: conventions(:), peer_rules(:), governs
    integer, intent(in) :: type_i(:), type_j(:)
    real(dp), intent(in) :: m_star(:), k_n(:, :), k_t(:, :), gamma_n(:, :), gamma_t(:, :), dt_code(:, :), &
      rayleigh_time(:), hertz_duration(:), linear_duration(:), dt_critical(:), peer_dt(:, :), &
      dt_accuracy(:), dt_recommended
    namelist /material_result/ conventions, peer_rules, type_i, type_j, m_star, k_n, k_t, gamma_n, &
      gamma_t, dt_code, rayleigh_time, hertz_duration, linear_duration, dt_critical, peer_dt, &
      dt_accuracy, dt_recommended, governs
    write(unit, nml=material_result)
  end subroutine write_result

end module demstep_cli_material
