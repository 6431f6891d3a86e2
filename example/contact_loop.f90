!> A DEM-style loop: many particles hit their contact springs at different speeds,
!> all stepped with demstep's central-difference stepper at dt = T/N.
!> It measures the restitution each particle comes out with and compares it with
!> demstep's exact discrete prediction (the undamped contact gains energy).
program contact_loop
  use demstep
  implicit none
  integer, parameter :: n_particles = 1000
  real(dp), parameter :: n_per_period = 10.0_dp
  type(spring_type) :: contact
  type(spring_state_type) :: state(n_particles)
  type(discrete_contact_type) :: predicted
  type(demstep_status_type) :: status
  real(dp) :: dt, v0(n_particles), v_out(n_particles)
  logical :: touching(n_particles)
  integer :: i, step

  call new_spring(contact, mass=0.01_dp, stiffness=1.0e5_dp, status=status)
  if (.not. is_ok(status)) error stop status%message
  dt = spring_period(contact)/n_per_period
  write(*, '(a, es12.5, a, es12.5)') "dt = T/10 = ", dt, "   critical step = ", &
    critical_time_step(contact)

  ! impact speeds from 0.1 to 2 m/s; every particle touches at step 0
  do i = 1, n_particles
    v0(i) = 0.1_dp + 1.9_dp*real(i - 1, dp)/real(n_particles - 1, dp)
    state(i) = spring_state_type(x=0.0_dp, v=v0(i))
  end do
  touching = .true.
  v_out = 0.0_dp
  do step = 1, 100
    call spring_step(contact, dt, state)          ! elemental: the whole array
    where (touching .and. .not. state%x > 0.0_dp) ! separated during this step
      touching = .false.
    end where
    where (touching) v_out = state%v
    if (.not. any(touching)) exit
  end do

  call spring_contact(contact, dt, predicted, status)
  write(*, '(a, f12.9)') "measured restitution (all particles): ", -v_out(1)/v0(1)
  write(*, '(a, es9.2)') "spread over impact speeds:            ", &
    maxval(-v_out/v0) - minval(-v_out/v0)
  write(*, '(a, f12.9)') "demstep exact discrete prediction:    ", predicted%restitution
end program contact_loop
