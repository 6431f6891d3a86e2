!> The README's "Inside your solver" example: a solver's own arrays given to
!> demstep as they are (no scene, no contact search), a monitor that keeps its
!> mode between updates, the cheap check, and what governs the limit.
!> Run: fpm run --example inside_solver
program inside_solver
  use demstep
  implicit none
  integer, parameter :: n = 4
  ! the solver's state: four spheres in a row resting on a floor at z = 0
  real(dp) :: x(3, n), mass(n), radius(n)
  integer :: pairs(2, 3)
  real(dp) :: c_n(3)
  type(step_monitor_type) :: monitor
  type(critical_step_type) :: crit
  type(demstep_status_type) :: status
  real(dp), allocatable :: particle_share(:), contact_share(:), wall_share(:)
  real(dp) :: dt
  logical :: safe
  integer :: i
  radius = 1.0e-3_dp
  mass = 2500.0_dp*4.0_dp/3.0_dp*3.14159265358979_dp*radius**3
  do i = 1, n
    x(:, i) = [1.9e-3_dp*(i - 1), 0.0_dp, 0.99e-3_dp]
  end do
  mass(2) = 0.25_dp*mass(2)                        ! one light particle
  pairs = reshape([1, 2, 2, 3, 3, 4], [2, 3])      ! the solver's contact list
  c_n = 2.0_dp*0.2_dp*sqrt(0.5_dp*mass(1)*200.0_dp) ! its normal dashpots

  ! one call on the arrays: k_n, k_t scalar (size 1) or per contact (size nc)
  call solver_critical_steps(x, mass, radius, pairs, [200.0_dp], crit, status, k_t=[60.0_dp], &
    c_n=c_n, wall_point=reshape([0.0_dp, 0.0_dp, 0.0_dp], [3, 1]), &
    wall_normal=reshape([0.0_dp, 0.0_dp, 1.0_dp], [3, 1]), wall_k=[200.0_dp, 60.0_dp], &
    wall_damping=[0.2_dp, 0.0_dp])
  if (.not. is_ok(status)) error stop status%message
  print '(a, es12.5, a, es12.5)', "damped limit ", crit%dt_critical_damped, "  undamped ", crit%dt_critical_eigen

  ! a monitor: update every few hundred steps, check in between
  call monitor%update(x, mass, radius, pairs, [200.0_dp], status, k_t=[60.0_dp], c_n=c_n, &
    wall_point=reshape([0.0_dp, 0.0_dp, 0.0_dp], [3, 1]), wall_normal=reshape([0.0_dp, 0.0_dp, 1.0_dp], [3, 1]), &
    wall_k=[200.0_dp, 60.0_dp], wall_damping=[0.2_dp, 0.0_dp])
  if (.not. is_ok(status)) error stop status%message
  dt = 0.9_dp*monitor%last%dt_critical_damped
  x(3, 2) = x(3, 2) - 0.05e-3_dp                   ! the light particle sinks into the floor
  call monitor%check(dt, safe, x, mass, radius, pairs, [200.0_dp], status, k_t=[60.0_dp], c_n=c_n, &
    wall_point=reshape([0.0_dp, 0.0_dp, 0.0_dp], [3, 1]), wall_normal=reshape([0.0_dp, 0.0_dp, 1.0_dp], [3, 1]), &
    wall_k=[200.0_dp, 60.0_dp], wall_damping=[0.2_dp, 0.0_dp])
  if (.not. is_ok(status)) error stop status%message
  print '(a, l1, a, i0, a, f6.3)', "still safe at 0.9 of the limit: ", safe, "  verdict ", monitor%verdict, &
    "  quotient ratio ", monitor%quotient_ratio

  ! what governs it: each particle's and contact's share of the top mode
  call mode_participation(monitor, size(pairs, 2), particle_share, contact_share, wall_share, status)
  if (.not. is_ok(status)) error stop status%message
  print '(a, 4f7.3)', "particle shares ", particle_share
  print '(a, 3f7.3, a, 4f7.3)', "contact shares  ", contact_share, "  floor ", wall_share
end program inside_solver
