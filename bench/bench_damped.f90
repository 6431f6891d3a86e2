!> Benchmark of the exact damped limit against the undamped Lanczos solve on
!> the same scene: random periodic packings (`random_periodic_packing`, 6 DOF
!> per particle, k_t = 0.3 k_n, rolling and twisting springs) tiled to 1e3 ..
!> 1e5 particles, with normal, tangential and rolling dashpots (damping ratio
!> 0.3, as restitution 0.37). Per size, one run each, Lanczos to 1e-6 both
!> times: the undamped solve (the `damping` effect off) and the whole damped
!> computation (the undamped solve, then the Newton steps, each a
!> warm-started solve of h^2 A + 2 h B); the ratio of the two times, the
!> Newton solves and the operator products of each.
!>
!>   OPENBLAS_NUM_THREADS=1 fpm run --example bench_damped --profile release [-- MAX_PARTICLES]
program bench_damped
  use, intrinsic :: iso_fortran_env, only: output_unit
  use demstep_kinds, only: dp
  use demstep_status, only: demstep_status_type, demstep_stat
  use demstep_progress, only: progress_seconds
  use demstep_scene_data, only: scene_type, scene_effect
  use demstep_scene_builders, only: scene_set_damping, scene_set_rolling
  use demstep_packing, only: random_periodic_packing, tile_scene
  use demstep_assembly, only: assembly_critical_steps, critical_step_type, eigen_solver
  implicit none
  integer, parameter :: n_cases = 3
  integer, parameter :: reps(n_cases) = [1, 3, 6]
  real(dp), parameter :: tol = 1.0e-6_dp
  type(scene_type) :: packing, scene
  type(critical_step_type) :: undamped, damped
  type(demstep_status_type) :: status
  character(len=32) :: arg
  integer :: c, n_max, ios
  real(dp) :: t0, t_undamped, t_damped

  n_max = huge(1)
  call get_command_argument(1, arg)
  if (arg /= "") read(arg, *, iostat=ios) n_max
  write(output_unit, '(a)') "# random periodic packing of 500 (seed 1) tiled K x K x K; 6 DOF; Lanczos to 1e-6; " &
    //"one run each; times in seconds"
  write(output_unit, '(a)') "| particles | undamped s | damped s | ratio | Newton solves | products undamped " &
    //"| products damped | dt damped/undamped |"
  write(output_unit, '(a)') "|---:|---:|---:|---:|---:|---:|---:|---:|"
  call random_periodic_packing(packing, 500, status, seed=1, k_normal=1.0e4_dp, k_tangential=3.0e3_dp)
  call require("random_periodic_packing")
  call scene_set_rolling(packing, 0.1_dp, 0.05_dp, status)
  call require("scene_set_rolling")
  call scene_set_damping(packing, 0.3_dp, status, rolling=0.3_dp)
  call require("scene_set_damping")
  do c = 1, n_cases
    if (500*reps(c)**3 > n_max) cycle
    call tile_scene(packing, [reps(c), reps(c), reps(c)], scene, status)
    call require("tile_scene")
    scene%effects(scene_effect%damping) = .false.
    t0 = progress_seconds()
    call assembly_critical_steps(scene, undamped, status, solver=eigen_solver%lanczos, tolerance=tol)
    call require("undamped")
    t_undamped = progress_seconds() - t0
    scene%effects(scene_effect%damping) = .true.
    t0 = progress_seconds()
    call assembly_critical_steps(scene, damped, status, solver=eigen_solver%lanczos, tolerance=tol)
    call require("damped")
    t_damped = progress_seconds() - t0
    write(output_unit, '("| ", i0, " | ", f0.3, " | ", f0.3, " | ", f0.2, " | ", i0, " | ", i0, " | ", i0, &
      & " | ", f0.4, " |")') scene%n, t_undamped, t_damped, t_damped/t_undamped, damped%damped_solves, &
      undamped%eigen_products, damped%eigen_products, damped%dt_critical_damped/undamped%dt_critical_safe
  end do
contains
  subroutine require(what)
    character(len=*), intent(in) :: what
    if (status%stat /= demstep_stat%ok) then
      write(output_unit, '(a)') what//": "//status%message
      error stop 1
    end if
  end subroutine require
end program bench_damped
