!> The demstep library: time step and contact stiffness for Discrete Element Method codes.
!>
!> The facade: `use demstep` gives the whole public API.
module demstep
  use demstep_kinds, only: dp, i8, pi
  use demstep_version, only: demstep_version_string
  use demstep_status, only: demstep_status_type, demstep_stat_codes, demstep_stat, &
    set_status, is_ok
  use demstep_spring, only: spring_type, spring_state_type, discrete_contact_type, &
    dashpot_lagged, dashpot_centred, new_spring, spring_step, spring_run, &
    spring_omega, spring_period, spring_damping_ratio, critical_time_step, &
    numerical_phase, numerical_period, growth_factor, exact_discrete_state, &
    paper_closed_form_velocity, discrete_contact, simulate_contact, check_time_step, &
    step_for_n_per_period, saturated_count, ceiling_real, spring_omega_min, spring_omega_max, &
    spring_h_max
  use demstep_harmonic, only: step_policy_type, steps_fixed, steps_fraction, steps_rounded, &
    harmonic_n_max, new_step_policy, policy_steps, harmonic_sum, harmonic_error, &
    harmonic_error_steps, harmonic_error_check, harmonic_phase_max, harmonic_phase_min
  use demstep_roots, only: root_context_type, root_function, find_root, scan_roots, &
    geometric_grid, sort_ascending
  use demstep_stiffness, only: nroots_options_type, nroots_type, stiffness_input_type, &
    stiffness_result_type, n_roots, aggregate_picks, simulated_stiffness, error_limit, &
    pick_largest_step, pick_zero, aggregate_mean, aggregate_weighted, aggregate_median, &
    aggregate_min, aggregate_max, interval_bounded, interval_unbounded, interval_truncated, &
    n_scan_start, default_n_max, default_resolution
  use demstep_scene, only: scene_type, scene_summary_type, cubic_lattice, new_scene, scene_add_bonds, &
    scene_add_walls, scene_set_contacts, scene_set_cell, scene_run, contact_list, effect_index, &
    restitution_to_damping_ratio, contact_law_enum, contact_law, scene_effect_enum, scene_effect, &
    n_effects, effect_names, max_coordinate, contact_limit, max_damping_ratio
  use demstep_assembly, only: critical_step_type, assembly_critical_steps, hertz_linearization_enum, &
    hertz_linearization, default_max_eigen_dof
  use demstep_scene, only: has_tangential, branch_vector, effective_mass, scene_set_types, &
    scene_set_hertz_types
  use demstep_contact, only: onset_contact_type, contact_with_onset, contact_worst_case, &
    exact_contact, contact_error_of, period_error, quantity_restitution, &
    quantity_contact_time, quantity_overlap, quantity_period, n_quantities, quantity_names, &
    worst_case_samples, check_contact_damping
  use demstep_cost, only: worst_error, n_for_tolerance, measure_step_cost, default_cost_n_max, &
    tolerance_grid_ratio, cost_n_max_limit, run_prediction_type, predict_run
  ! the C API lives in the same library (its names are bind(C), not re-exported)
  use demstep_capi, only: capi_message_length
  use demstep_progress, only: progress_type, text_progress_type
  use demstep_namelist, only: nml_group_type, nml_item_type, read_text_file, &
    scan_namelist, lowercase
  implicit none
  public
end module demstep
