program minimal
  use demstep
  implicit none
  type(spring_type) :: contact
  type(demstep_status_type) :: status
  type(discrete_contact_type) :: c
  call new_spring(contact, mass=0.01_dp, stiffness=1.0e5_dp, status=status)
  if (.not. is_ok(status)) error stop status%message
  print *, "critical step", critical_time_step(contact)       ! 2 sqrt(M/K)
  call spring_contact(contact, spring_period(contact)/10, c, status)
  print *, "restitution at N = 10:", c%restitution            ! 1.0164...
end program minimal
