!> Benchmark of the solver-facing calls on a solver's arrays listed in tile
!> order and in random order (as a DEM code's arrays hold a settled pile):
!> random periodic packings (`random_periodic_packing`, seed 1, 6 DOF per
!> particle, k_t = 0.3 k_n) tiled to 1e5 and 1e6 particles, the arrays
!> permuted by a fixed random permutation (contacts renamed). Per size and
!> order, one run each: `solver_critical_steps` (a cold certified Lanczos
!> solve to 1e-6, wall time) and then a monitor's second update after every
!> particle moved by up to 2e-4 of its radius (a warm start, wall time), with
!> their operator products and omega_max.
!>
!>   OPENBLAS_NUM_THREADS=1 OMP_WAIT_POLICY=passive fpm run --example bench_solver_order --profile release [-- MAX_PARTICLES]
program bench_solver_order
  use, intrinsic :: iso_fortran_env, only: output_unit
  use demstep_kinds, only: dp
  use demstep_status, only: demstep_status_type, demstep_stat
  use demstep_progress, only: progress_seconds
  use demstep_scene_data, only: scene_type
  use demstep_packing, only: random_periodic_packing, tile_scene
  use demstep_neighbours, only: contact_list
  use demstep_assembly, only: critical_step_type, eigen_solver
  use demstep_monitor, only: solver_critical_steps, step_monitor_type
  implicit none
  integer, parameter :: n_cases = 2
  integer, parameter :: base(n_cases) = [800, 1000]
  integer, parameter :: reps(n_cases) = [5, 10]
  type(scene_type) :: packing, scene
  type(critical_step_type) :: cold
  type(step_monitor_type) :: monitor
  type(demstep_status_type) :: status
  character(len=32) :: arg
  integer, allocatable :: ci(:), cj(:), pairs(:, :), perm(:), new_of(:)
  real(dp), allocatable :: cn(:, :), cd(:), x(:, :), mass(:), radius(:), k_n(:), k_t(:), u(:), xm(:, :)
  integer :: c, n_max, ios, order, n, i, j, k
  real(dp) :: t0, t_cold, t_warm
  character(len=6), parameter :: order_name(2) = ["tile  ", "random"]

  n_max = huge(1)
  call get_command_argument(1, arg)
  if (arg /= "") read(arg, *, iostat=ios) n_max
  write(output_unit, '(a)') "# solver arrays of tiled random periodic packings; 6 DOF; Lanczos to 1e-6; one run each; " &
    //"wall seconds"
  write(output_unit, '(a)') "| particles | order | cold s | cold products | warm s | warm products | omega_max |"
  write(output_unit, '(a)') "|---:|---|---:|---:|---:|---:|---:|"
  do c = 1, n_cases
    if (base(c)*reps(c)**3 > n_max) cycle
    call random_periodic_packing(packing, base(c), status, seed=1)
    call require("random_periodic_packing")
    call tile_scene(packing, [reps(c), reps(c), reps(c)], scene, status)
    call require("tile_scene")
    call contact_list(scene, ci, cj, cn, cd, status)
    call require("contact_list")
    n = scene%n
    ! a fixed permutation (Fisher-Yates on the compiler's generator, seed set)
    call random_seed(size=k)
    call random_seed(put=[(7919*i + 35, i = 1, k)])
    allocate(u(n))
    call random_number(u)
    perm = [(i, i = 1, n)]
    do i = n, 2, -1
      j = min(i, int(u(i)*i) + 1)
      k = perm(i)
      perm(i) = perm(j)
      perm(j) = k
    end do
    allocate(new_of(n))
    new_of(perm) = [(i, i = 1, n)]
    do order = 1, 2
      if (order == 1) then
        x = scene%x
        mass = scene%mass
        radius = scene%radius
        pairs = transpose(reshape([ci, cj], [size(ci), 2]))
      else
        x = scene%x(:, perm)
        mass = scene%mass(perm)
        radius = scene%radius(perm)
        pairs = transpose(reshape([new_of(ci), new_of(cj)], [size(ci), 2]))
      end if
      k_n = spread(scene%k_normal, 1, size(ci))
      k_t = spread(scene%k_tangential, 1, size(ci))
      t0 = progress_seconds()
      call solver_critical_steps(x, mass, radius, pairs, k_n, cold, status, k_t=k_t, &
        periodic=[.true., .true., .true.], cell_lo=scene%cell_lo, cell_hi=scene%cell_hi, &
        solver=eigen_solver%lanczos, solved=monitor)
      call require("solver_critical_steps")
      t_cold = progress_seconds() - t0
      ! every particle moved by up to 2e-4 of its radius
      call random_number(u)
      xm = x
      do i = 1, n
        xm(:, i) = x(:, i) + 4.0e-4_dp*(u(i) - 0.5_dp)*radius(i)
      end do
      t0 = progress_seconds()
      call monitor%update(xm, mass, radius, pairs, k_n, status, k_t=k_t, periodic=[.true., .true., .true.], &
        cell_lo=scene%cell_lo, cell_hi=scene%cell_hi)
      call require("update")
      t_warm = progress_seconds() - t0
      write(output_unit, '(a, i0, a, a, a, f0.3, a, i0, a, f0.3, a, i0, a, es23.16, a)') "| ", n, " | ", &
        trim(order_name(order)), " | ", t_cold, " | ", cold%eigen_products, " | ", t_warm, " | ", &
        monitor%last%eigen_products, " | ", cold%omega_max, " |"
      flush(output_unit)
    end do
    deallocate(u, new_of)
  end do

contains

  !> Stop the benchmark on a failed call.
  subroutine require(what)
    character(len=*), intent(in) :: what
    if (status%stat == demstep_stat%ok) return
    write(output_unit, '(a)') "# "//what//" failed: "//trim(status%message)
    error stop 1
  end subroutine require
end program bench_solver_order
