!> A legacy-style solver start-up: read demstep's result namelist and take its
!> time step.   demstep example/paper.nml -o demstep_result.nml
!>              fpm run --example read_result -- demstep_result.nml
program read_result
  implicit none
  integer, parameter :: dp = kind(1.0d0), i8 = selected_int_kind(18)
  real(dp) :: period, omega, dt_critical, dt, n_per_period, growth_factor, theta, &
    period_numerical, contact_time, restitution, max_overlap
  integer(i8) :: contact_steps
  logical :: stable
  real(dp) :: dt_recommended
  namelist /system_result/ dt_recommended, period, omega, dt_critical, dt, n_per_period, stable, &
    growth_factor, theta, period_numerical, contact_steps, contact_time, restitution, &
    max_overlap
  character(len=512) :: path
  integer :: unit, ios

  call get_command_argument(1, path)
  if (len_trim(path) == 0) path = "demstep_result.nml"
  dt = -1.0_dp
  open(newunit=unit, file=trim(path), status="old", action="read", iostat=ios)
  if (ios /= 0) error stop "cannot open the result namelist"
  read(unit, nml=system_result, iostat=ios)
  close(unit)
  if (ios /= 0) error stop "cannot read &system_result"
  if (dt <= 0.0_dp) error stop "the result has no time step (give dt or n_per_period)"
  write(*, '(a, es14.7, a, f8.3, a)') "solver dt = ", dt, " s (", n_per_period, &
    " steps per period)"
  write(*, '(a, l1, a, f10.7)') "stable: ", stable, ", contact restitution: ", restitution
end program read_result
