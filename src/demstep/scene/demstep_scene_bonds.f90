!> A scene's bonds in a DEM code's convention (`demstep_bonds`): the setter
!> and each bond's linear law, which the stepper integrates and the stability
!> analysis linearises through the one interaction kernel (`contact_product`).
module demstep_scene_bonds
  use demstep_kinds, only: dp
  use demstep_status, only: demstep_status_type, demstep_stat
  use demstep_bonds, only: bond_law_type, bond_law, check_bond_parameters, bond_parameter_count
  use demstep_scene_data, only: scene_type, scene_effect
  implicit none
  private

  public :: scene_set_bond_model, scene_bond_law, scene_bond_laws, scene_bonds_damped

contains

  !> Give every bond of the scene (those added before and after) the law of a
  !> code's bond model (`bond_model%pfc`, `%musen`, `%yade`, `%lammps`) with
  !> its parameters in that code's convention; switches the rotation effect
  !> on (dim > 1). The bonds' dashpots are the model's own (LAMMPS' gammas;
  !> none for the others), whatever the scene's damping effect. Status
  !> invalid_input naming `bond_model` or `bond_parameters` (index: the
  !> parameter); the scene is unchanged then.
  pure subroutine scene_set_bond_model(scene, model, parameters, status)
    type(scene_type), intent(inout) :: scene
    !> A code of `bond_model`.
    integer, intent(in) :: model
    !> The model's parameters, in its order (`bond_parameter_name`).
    real(dp), intent(in) :: parameters(:)
    type(demstep_status_type), intent(out) :: status
    call check_bond_parameters(model, parameters, status)
    if (status%stat /= demstep_stat%ok) return
    scene%bond_model = model
    scene%bond_parameters = 0.0_dp
    scene%bond_parameters(:size(parameters)) = parameters
    if (scene%dim > 1) scene%effects(scene_effect%rotation) = .true.
  end subroutine scene_set_bond_model

  !> The linear law of bond k of a scene with a bond model: the model's law
  !> for the two particles' radii and the bond's rest length.
  pure function scene_bond_law(scene, k) result(law)
    type(scene_type), intent(in) :: scene
    integer, intent(in) :: k
    type(bond_law_type) :: law
    associate(i => scene%bonds(1, k), j => scene%bonds(2, k))
      law = bond_law(scene%bond_model, scene%bond_parameters(:bond_parameter_count(scene%bond_model)), &
        scene%radius(i), scene%radius(j), norm2(scene%bond_rest(:, k)), scene%dim)
    end associate
  end function scene_bond_law

  !> Every bond's law (a scene with a bond model).
  pure function scene_bond_laws(scene) result(laws)
    type(scene_type), intent(in) :: scene
    type(bond_law_type), allocatable :: laws(:)
    integer :: k
    allocate(laws(size(scene%bonds, 2)))
    do k = 1, size(laws)
      laws(k) = scene_bond_law(scene, k)
    end do
  end function scene_bond_laws

  !> Whether the scene's bonds carry dashpots of their own (a bond model with
  !> a non-zero dashpot).
  pure logical function scene_bonds_damped(scene)
    type(scene_type), intent(in) :: scene
    type(bond_law_type) :: law
    scene_bonds_damped = .false.
    if (scene%bond_model == 0 .or. size(scene%bonds, 2) == 0) return
    law = scene_bond_law(scene, 1)
    ! (the dashpots scale with the rest length at most: one bond tells)
    scene_bonds_damped = any(law%c > 0.0_dp)
  end function scene_bonds_damped

end module demstep_scene_bonds
