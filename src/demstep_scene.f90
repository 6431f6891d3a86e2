!> Particle scenes, in one `use`: the scene data (`demstep_scene_data`), its
!> builders (`demstep_scene_builders`), the neighbour search
!> (`demstep_neighbours`) and the stepper (`demstep_stepper`).
module demstep_scene
  use demstep_scene_data, only: scene_type, scene_summary_type, scene_effect_enum, scene_effect, &
    n_effects, scene_effect_names, scene_effect_from_name, scene_effect_name, effective_mass, branch_vector, has_tangential, &
    has_rolling, max_damping_ratio
  use demstep_scene_builders, only: new_scene, scene_add_bonds, scene_add_walls, scene_set_contacts, &
    scene_set_cell, scene_set_types, scene_set_hertz_types, scene_set_law, &
    scene_set_bond_stiffness, scene_set_gravity, cubic_lattice, restitution_to_damping_ratio, max_coordinate, &
    random_periodic_packing, tile_scene, scene_set_damping, scene_set_friction, scene_set_local_damping, &
    scene_set_rolling, scene_set_effects
  use demstep_neighbours, only: contact_list, contact_limit
  use demstep_stepper, only: scene_run
  use demstep_interaction, only: contact_law_enum, contact_law, contact_law_names, contact_law_from_name, &
    contact_law_name
  implicit none
  private
  public :: scene_type, scene_summary_type, scene_effect_enum, scene_effect, n_effects, scene_effect_names, &
    scene_effect_from_name, scene_effect_name, effective_mass, branch_vector, has_tangential, has_rolling, new_scene, &
    scene_set_damping, scene_set_friction, scene_set_local_damping, scene_set_rolling, scene_set_effects, scene_add_bonds, &
    scene_add_walls, scene_set_contacts, scene_set_cell, scene_set_types, scene_set_hertz_types, &
    scene_set_law, scene_set_bond_stiffness, scene_set_gravity, random_periodic_packing, tile_scene, &
    cubic_lattice, restitution_to_damping_ratio, max_coordinate, contact_list, contact_limit, &
    scene_run, max_damping_ratio, contact_law_enum, contact_law, contact_law_names, contact_law_from_name, &
    contact_law_name
end module demstep_scene
