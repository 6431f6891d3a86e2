!> The stepper's cost on this machine, measured on the spot (for the
!> accuracy-cost predictions of `demstep_cost`).
module demstep_step_cost
  use demstep_kinds, only: dp, i8
  use demstep_status, only: demstep_status_type, demstep_stat
  use demstep_scene_data, only: scene_type, scene_summary_type
  use demstep_scene_builders, only: cubic_lattice
  use demstep_stepper, only: scene_run
  implicit none
  private

  public :: measure_step_cost

contains

  !> Measure the stepper's cost on the spot: a 3D cubic lattice of about 8000
  !> particles, bonds and contacts on (a typical DEM load), stepped for about
  !> `seconds` (default 0.2) three times; the median, in seconds per
  !> particle-step.
  subroutine measure_step_cost(cost, status, seconds)
    !> Seconds per particle-step.
    real(dp), intent(out) :: cost
    type(demstep_status_type), intent(out) :: status
    !> Time to spend on each of the three measured runs (default 0.2 s).
    real(dp), intent(in), optional :: seconds
    type(scene_type) :: start, scene
    type(scene_summary_type) :: summary
    integer, parameter :: m = 20
    real(dp) :: budget, times(3), t
    integer :: r
    integer(i8) :: c0, c1, rate, steps
    budget = 0.2_dp
    if (present(seconds)) budget = seconds
    cost = 0.0_dp
    call cubic_lattice(start, m, 0.5_dp, 100.0_dp, status)
    if (status%stat /= demstep_stat%ok) return
    ! a first short run sizes the measured ones
    steps = 5_i8
    do r = 0, 3
      scene = start
      call system_clock(c0, rate)
      call scene_run(scene, 0.01_dp, steps, summary, status, sample_every=steps)
      call system_clock(c1)
      t = real(c1 - c0, dp)/real(rate, dp)
      if (r == 0) then
        steps = max(5_i8, int(steps*budget/max(t, 1.0e-6_dp)/3.0_dp, i8))
      else
        times(r) = t/real(steps*start%n, dp)
      end if
    end do
    cost = times(1) + times(2) + times(3) - maxval(times) - minval(times)
    status%stat = demstep_stat%ok
  end subroutine measure_step_cost

end module demstep_step_cost
