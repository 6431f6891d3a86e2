!> The demstep library: time step and contact stiffness for Discrete Element Method codes.
!>
!> `use demstep` gives the tasks a DEM-solver author meets; everything else
!> (option words, limits, formatting, the readers' parts, the operator's
!> internals, the C binding) stays in its own module (`demstep_spring`,
!> `demstep_assembly`, `demstep_text`, `demstep_capi`, ...). Every call that can
!> fail reports a `demstep_status_type` (`is_ok(status)`; `status%where` names
!> the argument at fault); options are named constants (`eigen_solver%lanczos`,
!> `contact_law%hertz`, ...) whose words their modules spell (`*_from_name`).
!>
!> - Status and kinds: `dp`, `i8`, `demstep_status_type`, `demstep_stat`, `is_ok`,
!>   `demstep_version_string`.
!> - One spring (a contact or a bond) stepped by central differences:
!>   `spring_type`, `new_spring`, `spring_step` (elemental), `spring_run`,
!>   `critical_time_step`, `damped_limit`, `growth_factor`, `check_time_step`,
!>   `step_for_n_per_period`.
!> - One contact, exact and discrete: `discrete_contact_type`, `spring_contact`,
!>   `contact_with_onset`, `exact_contact`, `contact_worst_case`.
!> - What accuracy costs: `n_for_tolerance`, `predict_run`.
!> - The paper's error and the simulated-stiffness method: `harmonic_error`,
!>   `step_policy_type`, `new_step_policy`, `n_roots`, `simulated_stiffness`.
!> - Roots of any function: `find_root`, `scan_roots` (extend `root_context_type`).
!> - Assemblies: `scene_type`, `new_scene` and the `scene_set_*` builders,
!>   `assembly_critical_steps` (dense or Lanczos: `eigen_solver%...`), `scene_run`;
!>   test packings: `cubic_lattice`, `random_periodic_packing`, `tile_scene`,
!>   `random_clump_packing`.
!> - Rigid bodies (clumps, multispheres) of the scene's spheres: `body_set_type`,
!>   `bodies_from_members` (Yade's mass and inertia sum), `bodies_from_lists`,
!>   `bodies_given`, `body_critical_steps` (the same estimates per body, full
!>   inertia tensor), `body_gst_step` (Yade's GlobalStiffnessTimeStepper rule),
!>   `body_exadem_step` (exaDEM's rule).
!> - The largest eigenvalue of a large symmetric operator, matrix-free, with an
!>   error bar: `lanczos_largest` (extend `lanczos_context_type`).
!> - Bonds as each DEM code makes them (PFC parallel bond, MUSEN solid bond, Yade
!>   CohFrictPhys, LAMMPS bpm/rotational): `scene_set_bond_model` (`bond_model%...`),
!>   `bond_law`, `bond_pair_modes`, and the peers' bond rules `musen_bond_time`,
!>   `musen_recommended_step`, `kratos_step`, `exadem_step`.
!> - Materials in each DEM code's convention and the peers' step rules:
!>   `material_type`, `effective_pair`, `contact_parameters` (`code_convention%...`),
!>   `rayleigh_time`, `hertz_contact_duration`, `peer_time_steps`.
!> - MFiX decks: `read_mfix_deck`, `mfix_input_from_deck` (`@( )` arithmetic and
!>   CGP as MFiX does them), `mfix_compute` (what MFiX computes), `mfix_assess`.
!> - LIGGGHTS input scripts as they are: `read_liggghts_script`,
!>   `liggghts_script_contacts`, and with a snapshot a scene's contacts:
!>   `scene_from_liggghts_script`.
!> - Snapshots from DEM codes' files: `snapshot_type`, `read_snapshot`.
!> - Inside a running DEM solver: `solver_critical_steps` (the solver's own arrays
!>   and contact list, no scene, no search), `step_monitor_type` (`update`
!>   warm-started, `check` in O(contacts)), `mode_participation`, `top_shares`,
!>   `fresh_pour_estimate`, `scale_masses`, `write_vtk_particles` (ParaView);
!>   a scene's top-mode participation: `scene_participation`,
!>   `write_participation_vtk`.
!> - One recommended step: `recommended_step`, `assess_contact`.
!> - Results read back by name: `read_result`, `result_get`.
!> - Progress of long work: `text_progress_type`.
!>
!> A contact spring, its critical step and the restitution it gives at N = 10:
!>
!>```fortran
!> use demstep
!> type(spring_type) :: contact
!> type(discrete_contact_type) :: c
!> type(demstep_status_type) :: status
!> call new_spring(contact, mass=0.01_dp, stiffness=1.0e5_dp, status=status)
!> if (.not. is_ok(status)) error stop status%message
!> print *, critical_time_step(contact)                   ! 2 sqrt(M/K)
!> call spring_contact(contact, spring_period(contact)/10, c, status)
!> print *, c%restitution                                 ! 1.0164...
!>```
module demstep
  ! status and kinds
  use demstep_kinds, only: dp, i8
  use demstep_version, only: demstep_version_string
  use demstep_status, only: demstep_status_type, demstep_stat, is_ok
  ! one spring
  use demstep_spring, only: spring_type, spring_state_type, dashpot_kind, new_spring, spring_step, &
    spring_run, spring_period, critical_time_step, damped_limit, growth_factor, check_time_step, &
    step_for_n_per_period
  ! one contact
  use demstep_contact, only: discrete_contact_type, spring_contact, contact_with_onset, exact_contact, &
    contact_worst_case, quantity_kind
  ! what accuracy costs
  use demstep_cost, only: n_for_tolerance, run_prediction_type, predict_run
  ! the paper's error and the simulated-stiffness method
  use demstep_harmonic, only: harmonic_error, step_policy_type, step_kind, new_step_policy
  use demstep_stiffness, only: nroots_options_type, nroots_type, n_roots, pick_kind, aggregate_kind, &
    stiffness_input_type, stiffness_result_type, simulated_stiffness
  ! roots of any function
  use demstep_roots, only: root_context_type, find_root, scan_roots
  ! assemblies: a scene built from a solver's arrays, its exact limits, a run
  use demstep_scene_data, only: scene_type, scene_summary_type, scene_effect
  use demstep_interaction, only: contact_law
  use demstep_scene_builders, only: new_scene, scene_add_bonds, scene_add_walls, scene_set_contacts, &
    scene_set_cell, scene_set_law, scene_set_types, scene_set_hertz_types, scene_set_bond_stiffness, &
    scene_set_gravity, scene_set_damping, scene_set_friction, scene_set_rolling, scene_set_local_damping, &
    scene_set_effects, cubic_lattice
  use demstep_packing, only: random_periodic_packing, tile_scene, random_clump_packing
  use demstep_scene_materials, only: scene_set_materials
  ! bonds in each code's convention (normal, shear, bending, twisting) and the peers' bond rules
  use demstep_scene_bonds, only: scene_set_bond_model
  use demstep_bonds, only: bond_model, bond_law_type, bond_law, bond_pair_modes, musen_bond_time, &
    musen_recommended_step, kratos_step, exadem_step
  use demstep_stepper, only: scene_run
  use demstep_assembly, only: critical_step_type, assembly_critical_steps, assembly_step_for_n_per_period, &
    eigen_solver, hertz_linearization
  ! rigid bodies (clumps, multispheres): members, mass, inertia tensor, exact limits
  use demstep_bodies, only: body_set_type, bodies_from_members, bodies_from_lists, bodies_given
  use demstep_body_assembly, only: body_critical_steps, body_gst_step, body_exadem_step
  ! the largest eigenvalue of a large operator, matrix-free (Lanczos, ARPACK)
  use demstep_lanczos, only: lanczos_context_type, lanczos_largest, eigen_result_type
  ! materials in each code's convention and the peers' time-step rules
  use demstep_material, only: material_type, material_pair_type, effective_pair_type, effective_pair, &
    contact_parameters_type, contact_parameters, code_convention, peer_steps_type, peer_time_steps, &
    peer_rule, rayleigh_time, hertz_contact_duration, material_set_type
  ! MFiX decks: what MFiX computes for its DEM solids step, and demstep's answer
  use demstep_mfix_deck, only: mfix_deck_type, read_mfix_deck
  use demstep_mfix_input, only: mfix_input_type, mfix_input_from_deck
  use demstep_mfix, only: mfix_result_type, mfix_compute
  use demstep_mfix_assess, only: mfix_assessment_type, mfix_assess
  ! LIGGGHTS input scripts as they are, and the contacts they define
  use demstep_liggghts_script, only: liggghts_script_type, read_liggghts_script, liggghts_contacts_type, &
    liggghts_script_contacts
  use demstep_liggghts_scene, only: liggghts_scene_type, scene_from_liggghts_script
  ! particle snapshots from DEM codes' files
  use demstep_snapshot, only: snapshot_type, snapshot_format, read_snapshot
  ! a whole scene from typed input (arrays, tables or a snapshot, and a material set)
  use demstep_scene_input, only: scene_input_type, scene_setup_type, scene_from_input, scene_input_part
  ! inside a running solver: its own arrays, a persistent monitor, what governs the limit
  use demstep_monitor, only: solver_critical_steps, step_monitor_type, monitor_verdict, &
    mode_participation, top_shares, fresh_pour_estimate, scene_participation, participation_type
  use demstep_mass_scaling, only: scale_masses
  use demstep_vtk, only: write_vtk_particles, vtk_field_type, write_participation_vtk
  ! one recommended step
  use demstep_recommend, only: recommended_step, contact_assessment_type, assess_contact
  ! results read back by name
  use demstep_results, only: result_group_type, read_result, result_get
  ! progress of long work
  use demstep_progress, only: progress_type, text_progress_type
  implicit none
  public
end module demstep
