!> The Fortran side of the C/C++ comparison: the numbers example/c and
!> example/cpp print, computed with the Fortran API, in the same form.
program capi_reference
  use demstep
  implicit none
  type(spring_type) :: spring
  type(spring_state_type) :: state
  type(demstep_status_type) :: status
  type(nroots_options_type) :: options
  type(nroots_type) :: r
  type(stiffness_input_type) :: input
  type(stiffness_result_type) :: res
  type(scene_type) :: scene
  type(critical_step_type) :: c
  type(discrete_contact_type) :: contact
  type(body_set_type) :: bodies
  real(dp) :: dt_crit, e, x(1, 12)
  integer :: i, stat, pairs(2, 11)
  type(step_monitor_type) :: solved
  real(dp), allocatable :: shares(:), contact_shares(:), wall_shares(:)
  call new_spring(spring, 0.01_dp, 1.0e5_dp, status)
  dt_crit = critical_time_step(spring)
  call put("dt_critical", dt_crit)
  state = spring_state_type(x=0.0_dp, v=1.0_dp)
  do i = 1, 1000
    call spring_step(spring, 0.1_dp*dt_crit, state)
  end do
  call put("x_1000", state%x)
  call put("v_1000", state%v)
  call harmonic_error(19.316_dp, 0.9_dp, 9.658_dp, e, stat)
  call put("e_half_period", e)
  call harmonic_error(1000.0_dp, 1.0_dp - 1.0e-9_dp, 1.0e7_dp + 1.0_dp, e, stat)
  call put("e_hard", e)
  options%tolerance = 1.0e-3_dp
  call n_roots(0.9_dp, options, r, status)
  call put("n_pick", r%n_pick)
  call put("n_zero", r%roots(1))
  input%mass = 0.01_dp
  input%stiffness = 1.0e5_dp
  input%options%tolerance = 1.0e-3_dp
  input%lambdas = [(0.9_dp + (0.99_dp - 0.9_dp)*real(i, dp)/9.0_dp, i = 0, 9)]
  call simulated_stiffness(input, res, status)
  call put("n_star", res%n_star)
  call put("lambda_star", res%lambda_star)
  call put("dt", res%dt)
  call put("stiffness_actual", res%stiffness_actual)
  x(1, :) = [(real(i, dp), i = 1, 12)]
  call new_scene(scene, 1, x, spread(1.0_dp, 1, 12), spread(0.3_dp, 1, 12), status, &
    fixed=[.true., (.false., i = 2, 11), .true.])
  pairs = reshape([(i, i + 1, i = 1, 11)], [2, 11])
  call scene_add_bonds(scene, pairs, status)
  call scene_set_bond_stiffness(scene, 100.0_dp, 0.0_dp, status)
  scene%effects = .false.
  call assembly_critical_steps(scene, c, status)
  call put("omega_max", c%omega_max)
  call put("dt_critical_bound", c%dt_critical_bound)
  call put("dt_contact_rule", c%dt_contact_rule)
  ! a 2D sphere pressed into the floor, Hertz, linearised at an impact at 2 m/s, damped
  call new_scene(scene, 2, reshape([0.0_dp, 0.0099_dp], [2, 1]), [0.01_dp], [0.01_dp], status)
  call scene_add_walls(scene, reshape([0.0_dp, 0.0_dp], [2, 1]), reshape([0.0_dp, 1.0_dp], [2, 1]), status)
  call scene_set_law(scene, contact_law%hertz, 1.0e8_dp, 4.0e7_dp, status)
  scene%damping_ratio = 0.1_dp
  scene%effects = .false.
  scene%effects([scene_effect%walls, scene_effect%damping]) = .true.
  call assembly_critical_steps(scene, c, status, hertz_mode=hertz_linearization%impact, &
    impact_velocity=2.0_dp)
  call put("wall_omega_max", c%omega_max)
  call put("wall_dt_critical_damped", c%dt_critical_damped)
  ! a rigid clump of two overlapping spheres 1e-3 into a floor, linear k_n = 1e4
  call new_scene(scene, 3, reshape([0.3_dp, -0.2_dp, 1.2_dp, 0.9_dp, 0.2_dp, 1.8_dp], [3, 2]), [1.0_dp, 1.5_dp], &
    [1.0_dp, 1.0_dp], status)
  call scene_add_walls(scene, reshape([0.0_dp, 0.0_dp, 0.201_dp], [3, 1]), reshape([0.0_dp, 0.0_dp, 1.0_dp], &
    [3, 1]), status)
  call scene_set_law(scene, contact_law%linear, 1.0e4_dp, 0.0_dp, status)
  scene%effects = .false.
  scene%effects([scene_effect%contacts, scene_effect%walls, scene_effect%rotation]) = .true.
  call bodies_from_members(scene, [1, 1], bodies, status)
  call body_critical_steps(scene, bodies, c, status)
  call put("clump_omega_max", c%omega_max)
  call put("clump_dt_critical_eigen", c%dt_critical_eigen)
  call body_gst_step(scene, bodies, e, status)
  call put("clump_yade_gst", e)
  call body_exadem_step(scene, bodies, e, status)
  call put("clump_exadem", e)
  ! a pair held by Yade's CohFrictPhys bond
  call new_scene(scene, 3, reshape([0.0_dp, 0.0_dp, 0.0_dp, 1.2_dp, 1.1_dp, 0.9_dp], [3, 2]), [1.0_dp, 1.5_dp], &
    [1.0_dp, 0.9_dp], status)
  call scene_add_bonds(scene, reshape([1, 2], [2, 1]), status)
  call scene_set_bond_model(scene, bond_model%yade, [1.0e5_dp, 0.3_dp, 2.0_dp, 2.0_dp], status)
  call assembly_critical_steps(scene, c, status)
  call put("bond_omega_max", c%omega_max)
  call put("bond_dt_critical_eigen", c%dt_critical_eigen)
  call contact_with_onset(20.0_dp, 0.5_dp, contact, status, 0.1_dp)
  call put("contact_restitution", contact%restitution)
  call n_for_tolerance(quantity_kind%restitution, 1.0e-3_dp, e, status)
  call put("n_for_tolerance", e)
  ! a solver's own arrays: three spheres in a row (1D), the middle one light;
  ! the top mode's shares per particle and contact
  call solver_critical_steps(reshape([0.0_dp, 1.9e-3_dp, 3.8e-3_dp], [1, 3]), [1.0e-3_dp, 2.0e-4_dp, &
    1.0e-3_dp], [1.0e-3_dp, 1.0e-3_dp, 1.0e-3_dp], reshape([1, 2, 2, 3], [2, 2]), [1.0e4_dp], c, status, &
    solved=solved)
  call mode_participation(solved, 2, shares, contact_shares, wall_shares, status)
  call put("solver_dt_critical_eigen", c%dt_critical_eigen)
  call put("solver_share_1", shares(1))
  call put("solver_share_2", shares(2))
  call put("solver_contact_share_1", contact_shares(1))
contains
  subroutine put(name, value)
    character(len=*), intent(in) :: name
    real(dp), intent(in) :: value
    write(*, '(a, 1x, es24.16e3)') name, value
  end subroutine put
end program capi_reference
