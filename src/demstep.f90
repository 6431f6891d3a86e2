!> The demstep library: time step and contact stiffness for Discrete Element Method codes.
!>
!> `use demstep` gives what a DEM-solver author needs, by task. Every call that
!> can fail reports a `demstep_status_type` (`is_ok(status)`, or compare
!> `status%stat` with the codes of `demstep_stat`); options are named constants
!> (`dashpot_kind%lagged`, `step_kind%fraction`, `pick_kind%largest_step`, ...).
!>
!> - Status and kinds: `dp`, `i8`, `demstep_status_type`, `demstep_stat`, `is_ok`,
!>   `demstep_version_string`.
!> - One spring (a contact or a bond) stepped by central differences:
!>   `spring_type`, `new_spring`, `spring_step` (elemental), `spring_run`,
!>   `critical_time_step`, `damped_limit`, `growth_factor`, the exact discrete
!>   solution (`numerical_phase`, `numerical_period`, `exact_discrete_state`).
!> - One contact, exact and discrete: `discrete_contact_type`, `spring_contact`
!>   (a spring at its step), `contact_with_onset` (any N = T/dt and onset),
!>   `simulate_contact` (stepped), `exact_contact`, `contact_worst_case`.
!> - What accuracy costs: `n_for_tolerance`, `n_for_harmonic_tolerance`, `worst_error`,
!>   `predict_run`.
!> - The paper's error and the simulated-stiffness method: `harmonic_error`,
!>   `step_policy_type`, `new_step_policy`, `n_roots`, `simulated_stiffness`.
!> - Roots of any function: `find_root`, `scan_roots` (extend `root_context_type`).
!> - Assemblies: `scene_type`, `new_scene`, `assembly_critical_steps` (dense or
!>   Lanczos: `eigen_solver%...`), `scene_run`, `assembly_step_for_n_per_period`;
!>   test packings: `random_periodic_packing`, `tile_scene`;
!>   the matrix-free operator `assembly_operator` and its matrix `assembly_matrix`.
!> - The largest eigenvalue of a large symmetric operator, matrix-free, with an
!>   error bar: `lanczos_largest` (extend `lanczos_context_type`), `eigen_result_type`,
!>   a sparse operator from springs (`csr_from_springs`, `csr_apply`).
!> - Materials in each DEM code's convention and the peers' step rules:
!>   `material_type`, `effective_pair`, `contact_parameters` (`code_convention%...`),
!>   `rayleigh_time`, `hertz_contact_duration`, `peer_time_steps`.
!> - MFiX decks: `read_mfix_deck`, `mfix_looks_like_deck`, `mfix_input_from_deck`,
!>   `mfix_compute` (what MFiX computes), `mfix_assess` (demstep's exact answers at MFiX's step).
!> - Snapshots from DEM codes' files (LAMMPS/LIGGGHTS dump and data files, Yade text):
!>   `snapshot_type`, `read_snapshot`, `parse_snapshot` (`snapshot_format%...`).
!> - One recommended step: `recommended_step` (safety times the exact limit, or the
!>   accuracy requirement), `assess_contact` (one linear contact's limit, errors at a
!>   step and the step for a tolerance).
!> - Progress of long work, and reading namelist decks and tables of numbers:
!>   `text_progress_type`, `read_text_file`, `scan_namelist`, `read_table`.
!>
!> Internal helpers (limits, formatting, the C binding) stay in their own
!> modules (`demstep_spring`, `demstep_stiffness`, `demstep_text`, `demstep_capi`, ...).
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
  use demstep_spring, only: spring_type, spring_state_type, dashpot_kind, new_spring, &
    spring_step, spring_run, spring_omega, spring_period, spring_damping_ratio, &
    critical_time_step, damped_limit, growth_factor, numerical_phase, numerical_period, &
    exact_discrete_state, paper_closed_form_velocity, check_time_step, step_for_n_per_period
  ! one contact
  use demstep_contact, only: discrete_contact_type, spring_contact, contact_with_onset, &
    simulate_contact, exact_contact, contact_worst_case, contact_error_of, period_error, &
    quantity_kind, n_quantities, quantity_names
  ! what accuracy costs
  use demstep_cost, only: n_for_tolerance, n_for_harmonic_tolerance, worst_error, &
    run_prediction_type, predict_run, measure_step_cost
  ! the paper's error and the simulated-stiffness method
  use demstep_harmonic, only: step_policy_type, step_kind, new_step_policy, policy_steps, &
    harmonic_sum, harmonic_error, harmonic_error_steps, harmonic_error_check
  use demstep_stiffness, only: nroots_options_type, nroots_type, n_roots, pick_kind, &
    interval_kind, stiffness_input_type, stiffness_result_type, simulated_stiffness, &
    aggregate_kind, aggregate_picks, error_limit
  ! roots of any function
  use demstep_roots, only: root_context_type, root_function, find_root, scan_roots, &
    scan_break, scan_cell_type, scan_sample_type
  ! assemblies (the scene modules' public names)
  use demstep_scene, only: scene_type, scene_summary_type, cubic_lattice, new_scene, scene_add_bonds, &
    scene_add_walls, scene_set_contacts, scene_set_cell, scene_set_types, scene_set_hertz_types, &
    scene_set_law, scene_set_bond_stiffness, scene_set_gravity, scene_run, contact_list, effect_index, &
    random_periodic_packing, tile_scene, scene_set_damping, scene_set_friction, scene_set_local_damping, &
    scene_set_rolling, scene_set_effects, restitution_to_damping_ratio, contact_law_enum, &
    contact_law, scene_effect_enum, scene_effect, n_effects, effect_names, max_coordinate, &
    contact_limit, max_damping_ratio
  use demstep_assembly, only: critical_step_type, assembly_critical_steps, hertz_linearization_enum, &
    hertz_linearization, default_max_eigen_dof, assembly_step_for_n_per_period, eigen_solver_enum, &
    eigen_solver, eigen_solver_name, eigen_solver_value, eigen_solver_names, assembly_operator_type, assembly_operator, &
    assembly_operator_apply, assembly_matrix, assembly_matrix_rows, dashpot_names
  ! the largest eigenvalue of a large operator, matrix-free (Lanczos, ARPACK)
  use demstep_lanczos, only: lanczos_context_type, lanczos_operator, lanczos_largest, &
    eigen_result_type, lanczos_tolerance_default, lanczos_ncv_default, lanczos_nev_default, &
    lanczos_restarts_default, lanczos_solver_name
  use demstep_csr, only: csr_matrix_type, csr_from_springs, csr_apply
  ! progress, and reading namelist decks and tables
  use demstep_progress, only: progress_type, text_progress_type
  use demstep_namelist, only: nml_group_type, nml_item_type, read_text_file, scan_namelist
  use demstep_table_io, only: read_table
  ! materials in each code's convention, into a scene's contacts, and the peers' time-step rules
  use demstep_scene_materials, only: scene_set_materials
  use demstep_material, only: code_convention, convention_names, peer_rule, peer_rule_names, &
    material_type, material_pair_type, effective_pair_type, contact_parameters_type, &
    peer_steps_type, effective_pair, contact_parameters, rayleigh_time, hertz_max_overlap, &
    hertz_contact_duration, linear_contact_duration, peer_time_steps, hertz_impact_stiffness, &
    convention_limit
  ! MFiX decks and what MFiX computes for its DEM solids step
  use demstep_mfix_deck, only: mfix_deck_type, read_mfix_deck, parse_mfix_deck, mfix_get_real, &
    mfix_get_integer, mfix_get_string, mfix_get_real_array, mfix_get_string_array, mfix_has_keyword, &
    mfix_min_by_second_index, mfix_looks_like_deck
  use demstep_mfix, only: mfix_input_type, mfix_result_type, mfix_units, mfix_model, &
    mfix_integrator, mfix_input_from_deck, mfix_compute, mfix_assessment_type, mfix_assess, &
    mfix_default_dtsolid_factor
  ! particle snapshots from DEM codes' files
  use demstep_snapshot, only: snapshot_type, snapshot_format, snapshot_format_names, read_snapshot, &
    parse_snapshot, snapshot_format_of
  ! one recommended step
  use demstep_recommend, only: recommended_step, default_safety, step_governs, step_governs_names, &
    contact_assessment_type, assess_contact, assess_material_pair
  implicit none
  public
end module demstep
