!> Materials into contacts, once: per-type materials in one DEM code's
!> convention (`demstep_material`) turned into a scene's contact law, per
!> type pair, and its dashpots, walls included. The app, the C API and any
!> solver call this one procedure.
!>
!> For each pair of types the code's own parameters at the pair's nominal
!> radii and densities (`contact_parameters`) give: for a Hertz convention
!> its effective moduli E* = k_n/((4/3) a) and G* = k_t/(8 a) at the
!> evaluation overlap (a = sqrt(R* d); the scene's Hertz law then follows
!> each contact's own overlap), for a linear one k_n and k_t; the normal
!> damping ratio zeta_n = gamma_n/(2 sqrt(m* k)) at the tangent stiffness k
!> (3/2 of the secant for Hertz) and the code's tangential dashpot as a
!> multiple of the normal one, gamma_t/gamma_n. Both are the same for every
!> contact of the pair in each supported convention (their dashpots scale as
!> sqrt(m* k)), so each contact's dashpots follow from its own m* and k.
!> Walls: a particle of type t on a wall of type w, R* = r, m* = m.
!>
!> LIGGGHTS' Hooke stiffness depends on each contact's own R* and m*
!> (normal_model_hooke.h:269); with `per_contact` the scene takes it so
!> (`hooke_per_contact`), the types' nominal radii and densities then only
!> carry the rounding: what a snapshot of several radii with one LIGGGHTS type needs.
module demstep_scene_materials
  use demstep_kinds, only: dp
  use demstep_status, only: demstep_status_type, demstep_stat, set_status
  use demstep_text, only: int_text
  use demstep_interaction, only: contact_law, hooke_size_factor
  use demstep_material, only: code_convention
  use demstep_material, only: material_type, material_pair_type, contact_parameters_type, &
    contact_parameters, effective_pair_type, effective_pair, material_set_type, code_convention_names
  use demstep_scene_data, only: scene_type, scene_effect
  use demstep_scene_builders, only: scene_set_types, scene_set_hertz_types
  implicit none
  private

  public :: scene_set_materials, scene_set_material_set, material_set_law, material_set_damped

contains

  !> Set the scene's contacts from materials per type in a code's convention
  !> (`code_convention%...`): `types` (one per particle, 1 to nt), the
  !> materials (nt: Young's modulus, Poisson's ratio, density, nominal
  !> radius), the restitution (and tangential restitution, 0: the normal one)
  !> and impact velocity of the convention. Walls are of type `wall_type`
  !> (0, the default: each particle's own type). Sets the law (Hertz or
  !> linear, as the convention), the per-pair springs and dashpot ratios, the
  !> walls' per-type law and dashpots, and switches on `rotation` (tangential
  !> springs) and `damping` (when the code damps: restitution below 1).
  !> Status invalid_input naming `types`, `wall_type` or, prefixed by the
  !> pair (`types 1 and 2:`, `wall, type 1:`), the material's variable.
  subroutine scene_set_materials(scene, types, materials, convention, restitution, status, &
      restitution_t, impact_velocity, wall_type, tangential_damping, per_contact)
    type(scene_type), intent(inout) :: scene
    integer, intent(in) :: types(:)
    type(material_type), intent(in) :: materials(:)
    integer, intent(in) :: convention
    real(dp), intent(in) :: restitution
    type(demstep_status_type), intent(out) :: status
    real(dp), intent(in), optional :: restitution_t, impact_velocity
    integer, intent(in), optional :: wall_type
    !> The code's tangential dashpots (default on; LIGGGHTS' `tangential_damping
    !> off` drops them, normal_model_hertz.h:238, normal_model_hooke.h:275).
    logical, intent(in), optional :: tangential_damping
    !> LIGGGHTS Hooke: each contact's stiffness from its own R* and m*
    !> (default no: the types' nominal radii and densities).
    logical, intent(in), optional :: per_contact
    type(contact_parameters_type) :: params
    type(material_pair_type) :: pair
    real(dp), allocatable :: k(:, :, :), law(:, :, :), damp(:, :, :), wall_law(:, :), wall_damp(:, :)
    integer :: nt, a, b, w, law_id
    logical :: hertz, first, scaled
    nt = size(materials)
    scaled = .false.
    if (present(per_contact)) scaled = per_contact .and. convention == code_convention%liggghts_hooke
    w = 0
    if (present(wall_type)) w = wall_type
    if (w < 0 .or. w > nt) then
      call set_status(status, demstep_stat%invalid_input, "must be 0 (each particle's own " &
        //"type) or one of the "//int_text(nt)//" materials", where="wall_type")
      return
    end if
    pair%restitution = restitution
    if (present(restitution_t)) pair%restitution_t = restitution_t
    if (present(impact_velocity)) pair%impact_velocity = impact_velocity
    allocate(law(4, nt, nt), damp(2, nt, nt), wall_law(4, nt), wall_damp(2, nt), source=0.0_dp)
    first = .true.
    hertz = .false.
    do a = 1, nt
      do b = a, nt
        pair%a = materials(a)
        pair%b = materials(b)
        call pair_values(.false., "types "//int_text(a)//" and "//int_text(b)//": ", law(:, a, b), &
          damp(:, a, b))
        if (status%stat /= demstep_stat%ok) return
        law(:, b, a) = law(:, a, b)
        damp(:, b, a) = damp(:, a, b)
      end do
    end do
    do a = 1, nt
      pair%a = materials(a)
      pair%b = materials(merge(a, w, w == 0))
      call pair_values(.true., "wall, type "//int_text(a)//": ", wall_law(:, a), wall_damp(:, a))
      if (status%stat /= demstep_stat%ok) return
    end do
    ! the per-type table through the builder's checks (types, symmetry)
    allocate(k(2, nt, nt))
    k(1, :, :) = 1.0_dp
    k(2, :, :) = 0.0_dp
    call scene_set_types(scene, types, k, status)
    if (status%stat /= demstep_stat%ok) return
    ! per-pair dashpots replace the scene's ratios for contacts and walls
    law_id = merge(contact_law%hertz, contact_law%linear, hertz)
    scene%law = law_id
    scene%pair_law = law
    if (present(tangential_damping)) then
      if (.not. tangential_damping) then
        damp(2, :, :) = 0.0_dp
        wall_damp(2, :) = 0.0_dp
      end if
    end if
    scene%pair_damping = damp
    scene%wall_law = wall_law
    scene%wall_damping = wall_damp
    scene%hooke_per_contact = scaled
    scene%effects(scene_effect%rotation) = .true.
    if (any(damp(1, :, :) > 0.0_dp) .or. any(wall_damp(1, :) > 0.0_dp)) &
      scene%effects(scene_effect%damping) = .true.
    status%stat = demstep_stat%ok
  contains
    !> One pair's (or wall's) law row (k_n, k_t, E*, G*) and (zeta_n, gamma_t/gamma_n).
    subroutine pair_values(on_wall, who, row, ratios)
      logical, intent(in) :: on_wall
      character(len=*), intent(in) :: who
      real(dp), intent(out) :: row(4), ratios(2)
      type(effective_pair_type) :: eff
      real(dp) :: a_c, k_tan
      row = 0.0_dp
      ratios = 0.0_dp
      call contact_parameters(pair, convention, params, status, wall=on_wall)
      if (status%stat == demstep_stat%ok) call effective_pair(pair%a, pair%b, eff, status)
      if (status%stat /= demstep_stat%ok) then
        status%message = who//status%message
        return
      end if
      if (on_wall) then
        eff%m_star = eff%m_a
        eff%r_star = pair%a%radius
      end if
      if (first) hertz = params%overlap > 0.0_dp
      first = .false.
      if (hertz) then
        a_c = sqrt(eff%r_star*params%overlap)
        row(3) = params%k_n/((4.0_dp/3.0_dp)*a_c)
        row(4) = params%k_t/(8.0_dp*a_c)
        k_tan = 1.5_dp*params%k_n
      else
        row(1) = params%k_n
        row(2) = params%k_t
        k_tan = params%k_n
      end if
      ratios(1) = params%gamma_n/(2.0_dp*sqrt(eff%m_star*k_tan))
      ! per contact: the springs of R* = m* = 1 (the damping ratio does not depend on them)
      if (scaled) row(1:2) = row(1:2)/hooke_size_factor(eff%r_star, eff%m_star)
      if (params%gamma_n > 0.0_dp) ratios(2) = params%gamma_t/params%gamma_n
    end subroutine pair_values

  end subroutine scene_set_materials

  !> The contact law a material set implies: Hertz for all codes or a Hertz
  !> convention (one evaluated at an overlap), else linear (`contact_law%...`).
  pure integer function material_set_law(set) result(law)
    type(material_set_type), intent(in) :: set
    type(contact_parameters_type) :: params
    type(demstep_status_type) :: status
    law = contact_law%hertz
    if (set%first /= set%last) return
    call contact_parameters(material_pair_type(set%types(1), set%types(1), set%restitution, &
      set%restitution_t, set%impact_velocity), set%first, params, status)
    if (status%stat == demstep_stat%ok .and. params%overlap == 0.0_dp) law = contact_law%linear
  end function material_set_law

  !> Whether the set's code damps its contacts: all codes, or one whose
  !> convention gives a normal dashpot (Yade's FrictPhys has none).
  pure logical function material_set_damped(set) result(damped)
    type(material_set_type), intent(in) :: set
    type(contact_parameters_type) :: params
    type(demstep_status_type) :: status
    damped = .true.
    if (set%first /= set%last) return
    call contact_parameters(material_pair_type(set%types(1), set%types(1), set%restitution, &
      set%restitution_t, set%impact_velocity), set%first, params, status)
    if (status%stat == demstep_stat%ok) damped = params%gamma_n > 0.0_dp
  end function material_set_damped

  !> Per-type springs and dashpots from a material set: one code named, its own
  !> convention ([[scene_set_materials]]); all codes, Hertz E* and G* from each
  !> type's Young's modulus and Poisson's ratio (the scene's law must be Hertz).
  !> `in_set` tells whether a fault lies in the set (else in `types` or
  !> `wall_type`).
  subroutine scene_set_material_set(scene, set, types, wall_type, tangential_damping, status, in_set)
    type(scene_type), intent(inout) :: scene
    type(material_set_type), intent(in) :: set
    !> The particles' types (1 to the set's size).
    integer, intent(in) :: types(:)
    !> The walls' type (0: each particle's own).
    integer, intent(in) :: wall_type
    !> The code's tangential dashpots.
    logical, intent(in) :: tangential_damping
    type(demstep_status_type), intent(out) :: status
    logical, intent(out) :: in_set
    real(dp), allocatable :: young(:), poisson(:)
    in_set = .true.
    if (set%first == set%last) then
      call scene_set_materials(scene, types, set%types, set%first, set%restitution, status, &
        restitution_t=set%restitution_t, impact_velocity=set%impact_velocity, wall_type=wall_type, &
        tangential_damping=tangential_damping)
      if (status%stat /= demstep_stat%ok) in_set = .not. (status%where == "wall_type" .or. &
        status%where == "types")
      return
    end if
    if (scene%law == contact_law%hertz) then
      young = set%types%young
      poisson = set%types%poisson
      call scene_set_hertz_types(scene, types, young, poisson, status)
      return
    end if
    call set_status(status, demstep_stat%invalid_input, "the linear law takes k_n and k_t from one " &
      //"code's convention: name it ("//linear_conventions(set)//")", where="code")
  end subroutine scene_set_material_set

  !> The names of the conventions whose springs are linear (evaluated at no overlap).
  pure function linear_conventions(set) result(names)
    type(material_set_type), intent(in) :: set
    character(len=:), allocatable :: names
    type(contact_parameters_type) :: params
    type(demstep_status_type) :: status
    integer :: c
    names = ""
    do c = 1, size(code_convention_names)
      call contact_parameters(material_pair_type(set%types(1), set%types(1), set%restitution, &
        set%restitution_t, set%impact_velocity), c, params, status)
      if (status%stat /= demstep_stat%ok .or. params%overlap /= 0.0_dp) cycle
      if (len(names) > 0) names = names//", "
      names = names//trim(code_convention_names(c))
    end do
  end function linear_conventions

end module demstep_scene_materials
