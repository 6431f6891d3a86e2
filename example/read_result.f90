!> A legacy-style solver start-up: take the time step from demstep's result file.
!>   demstep example/paper.nml -o demstep_result.nml
!>   fpm run --example read_result -- demstep_result.nml
!> The group is read by name (`read_result`, `result_get`): fields demstep adds
!> later do not break this reader, as they would a `namelist` declaration.
program read_result_example
  use demstep, only: dp, demstep_status_type, is_ok, result_group_type, read_result, result_get
  implicit none
  type(result_group_type) :: result
  type(demstep_status_type) :: status
  character(len=512) :: path
  real(dp) :: dt, n_per_period, restitution
  logical :: stable

  call get_command_argument(1, path)
  if (len_trim(path) == 0) path = "demstep_result.nml"
  call read_result(trim(path), "system_result", result, status)
  if (.not. is_ok(status)) error stop status%message
  call result_get(result, "dt", dt, status)
  if (.not. is_ok(status)) error stop "the result has no time step (give dt or n_per_period)"
  call result_get(result, "n_per_period", n_per_period, status)
  if (is_ok(status)) call result_get(result, "stable", stable, status)
  if (is_ok(status)) call result_get(result, "restitution", restitution, status)
  if (.not. is_ok(status)) error stop status%message
  write(*, '(a, es14.7, a, f8.3, a)') "solver dt = ", dt, " s (", n_per_period, &
    " steps per period)"
  write(*, '(a, l1, a, f10.7)') "stable: ", stable, ", contact restitution: ", restitution
end program read_result_example
