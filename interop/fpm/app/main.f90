!> A toy DEM solver loop with demstep as an fpm dependency: it asks demstep for
!> the assembly's stable step (not the per-contact rule), runs at a fifth of it
!> and checks the energy, then reports what the per-contact rule would have done.
program dem_solver
  use demstep
  implicit none
  type(scene_type) :: scene
  type(critical_step_type) :: limits
  type(scene_summary_type) :: summary
  type(demstep_status_type) :: status
  real(dp) :: dt

  ! a 6 x 6 x 6 bonded lattice with contacts
  call cubic_lattice(scene, 6, 0.45_dp, 1.0e3_dp, status)
  if (.not. is_ok(status)) error stop status%message
  call assembly_critical_steps(scene, limits, status)
  if (.not. is_ok(status)) error stop status%message
  dt = 0.2_dp*limits%dt_critical_eigen
  call scene_run(scene, dt, 20000_i8, summary, status)
  if (.not. is_ok(status)) error stop status%message
  write(*, '(a, es12.5, a, es12.5)') "stable step (LAPACK) ", limits%dt_critical_eigen, &
    ";  per-contact rule ", limits%dt_contact_rule
  write(*, '(a, i0, a, es10.3)') "ran ", summary%steps, " steps at a fifth of it; energy drift ", &
    summary%energy_drift
  if (summary%blew_up .or. summary%energy_drift > 1.0e-6_dp) error stop "the run was not stable"
end program dem_solver
