!> Group `&material`: particle types (E, nu, density, radius), restitution and
!> impact velocity; per pair of types the contact parameters in each DEM code's
!> convention, the time scales, the peers' time-step rules beside demstep's
!> exact limit, and one recommended step.
module demstep_cli_material
  use demstep_kinds, only: dp, i8
  use demstep_material, only: material_type, material_pair_type, effective_pair_type, &
    contact_parameters_type, peer_steps_type, effective_pair, contact_parameters, peer_time_steps, &
    code_convention, code_convention_names, code_convention_from_name, peer_rule_names, convention_limit, &
    n_conventions, n_peer_rules, liggghts_velocity_factor, check_pair
  use demstep_recommend, only: recommended_step, contact_assessment_type, step_governs, default_safety, &
    assess_material_pair
  use demstep_status, only: demstep_status_type, demstep_stat, set_status, status_restate
  use demstep_namelist, only: nml_group_type
  use demstep_cost, only: default_cost_n_max
  use demstep_cli, only: record_step, var_spec, var, given, begin_group, fmt_real, fmt_int, cli_context, &
    next_assignment, group_reading, new_array, array_length, common_length, broadcast, capacity_of, &
    report_row, in_group
  use demstep_words, only: word_list, word_index
  use demstep_results, only: write_material_result
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
    text = word_list(code_convention_names(:n_conventions), quote="'")
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
    if (status%stat /= demstep_stat%ok) call in_group(status, "material")
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
    integer :: lengths(4), n
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
    if (word_index(["all"], code) == 1) then
      first = 1
      last = n_conventions
    else
      first = code_convention_from_name(code)
      if (first == 0) then
        call set_status(status, demstep_stat%invalid_input, "must be 'all' or one of "//names_list()// &
          ", got '"//trim(code)//"'", where="code")
        call in_group(status, g)
        return
      end if
      last = first
    end if
    ! the loading, checked here for every reader of the group (a &scene too)
    call check_pair(material_pair_type(types(1), types(1), restitution, restitution_t, impact_velocity), status)
    if (status%stat /= demstep_stat%ok) then
      call in_group(status, "material")
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
          call fix_label(status, i, j)
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
          call pair_message(status, who)
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
            call pair_message(status, who//trim(code_convention_names(c))//": ")
            return
          end if
          call convention_limit(params, eff%m_star, dt_code(c - first + 1, p), status)
          if (status%stat /= demstep_stat%ok) then
            call pair_message(status, who//trim(code_convention_names(c))//": ")
            return
          end if
          k_n(c - first + 1, p) = params%k_n
          k_t(c - first + 1, p) = params%k_t
          gamma_n(c - first + 1, p) = params%gamma_n
          gamma_t(c - first + 1, p) = params%gamma_t
          write(u, '(4x, a22, 5a16)') trim(code_convention_names(c)), fmt_real(params%k_n), fmt_real(params%k_t), &
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
        //trim(code_convention_names(first))//"'s own contact)")
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
    call write_material_result(ctx%results, [(code_convention_names(c), c = first, last)], peer_rule_names, type_i, type_j, &
      m_star, k_n, k_t, gamma_n, gamma_t, dt_code, rayleigh, hertz_duration, linear_duration, dt_critical, &
      peer_dt, dt_accuracy, dt_recommended, trim(merge("stability", "accuracy ", &
      governs == step_governs%stability)))
    status%stat = demstep_stat%ok
  end subroutine evaluate

  !> A pair's library fault restated for the deck: the pair (`who`) leads the
  !> detail; a stiffness k_n the material gives is named by `young`.
  subroutine pair_message(status, who)
    type(demstep_status_type), intent(inout) :: status
    character(len=*), intent(in) :: who
    type(var_spec), allocatable :: specs(:)
    character(len=:), allocatable :: name, detail
    integer :: i
    name = ""
    detail = status%message
    if (allocated(status%where)) then
      if (status%where == "k_n") then
        call status_restate(status, "young", who//"the contact stiffness k_n it gives (with poisson, " &
          //"radius and impact_velocity) "//status%detail)
        return
      end if
      allocate(specs, source=material_specs())
      do i = 1, size(specs)
        if (status%where == specs(i)%name) then
          name = status%where
          detail = status%detail
          exit
        end if
      end do
    end if
    call status_restate(status, name, who//detail)
  end subroutine pair_message

  !> The library's generic particle types a and b named by the deck's types i and j.
  pure subroutine fix_label(status, i, j)
    type(demstep_status_type), intent(inout) :: status
    integer, intent(in) :: i, j
    character(len=:), allocatable :: where, detail
    where = ""
    if (allocated(status%where)) where = status%where
    detail = status%message
    if (allocated(status%detail)) detail = status%detail
    call status_restate(status, where, relabel(relabel(detail, "a", i), "b", j))
  contains
    pure function relabel(text, letter, k) result(out)
      character(len=*), intent(in) :: text, letter
      integer, intent(in) :: k
      character(len=:), allocatable :: out
      integer :: at
      out = text
      at = index(out, "(particle type "//letter//")")
      if (at > 0) out = out(:at-1)//"(particle type "//fmt_int(int(k, i8))//")"//out(at+17:)
    end function relabel
  end subroutine fix_label

end module demstep_cli_material
