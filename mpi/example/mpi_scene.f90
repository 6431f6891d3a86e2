!> The critical time steps of a scene on MPI ranks: a random periodic packing
!> of N spheres in 3D (radii 0.4..0.7 in a box of N unit volumes, about 5.6
!> contacts per particle, masses 1..2, linear contacts k_n = 100, k_t = 30,
!> rotations on: 6 dof per particle, damping ratio 0.1). Every rank builds the
!> same scene (replicated input); `mpi_scene_critical_steps` partitions it into
!> slabs, one per rank. Prints the result, the time and the peak resident
!> memory (VmHWM) of the largest rank, after the scene and after the solve.
!>   mpirun -np 2 build/.../mpi_scene [N [serial]]   (default N = 10000)
!> With `serial`, rank 0 also runs the serial `assembly_critical_steps`
!> (Lanczos) and prints its time and the relative difference of omega_max.
program mpi_scene
  use mpi_f08
  use demstep_kinds, only: dp, i8
  use demstep_status, only: demstep_status_type, demstep_stat
  use demstep_scene_data, only: scene_type, scene_effect
  use demstep_scene_builders, only: new_scene, scene_set_cell
  use demstep_assembly, only: critical_step_type, assembly_critical_steps, eigen_solver
  use demstep_mpi_scene, only: mpi_scene_critical_steps
  implicit none
  integer :: rank, nranks, n, i, arg_status
  integer(i8) :: seed, hwm_scene, hwm_solve
  real(dp), allocatable :: x(:, :), r(:), m(:)
  real(dp) :: box, t0, t1, t2, t3
  type(scene_type) :: scene
  type(critical_step_type) :: result, serial
  type(demstep_status_type) :: status
  character(len=64) :: arg
  logical :: with_serial

  call MPI_Init()
  call MPI_Comm_rank(MPI_COMM_WORLD, rank)
  call MPI_Comm_size(MPI_COMM_WORLD, nranks)
  n = 10000
  call get_command_argument(1, arg, status=arg_status)
  if (arg_status == 0 .and. len_trim(arg) > 0) read (arg, *, iostat=arg_status) n
  if (arg_status /= 0 .or. n < 1) then
    if (rank == 0) write (*, '(a)') "mpi_scene: N must be a whole number >= 1"
    call MPI_Abort(MPI_COMM_WORLD, 2)
  end if
  call get_command_argument(2, arg, status=arg_status)
  with_serial = arg_status == 0 .and. trim(arg) == "serial"

  ! the same packing on every rank: a Park-Miller sequence
  t0 = MPI_Wtime()
  seed = 20261122_i8
  box = real(n, dp)**(1.0_dp/3.0_dp)
  allocate(x(3, n), r(n), m(n))
  do i = 1, n
    x(:, i) = box*[uniform(), uniform(), uniform()]
    r(i) = 0.4_dp + 0.3_dp*uniform()
    m(i) = 1.0_dp + uniform()
  end do
  call new_scene(scene, 3, x, m, r, status)
  if (status%stat == demstep_stat%ok) call scene_set_cell(scene, [.true., .true., .true.], &
    [0.0_dp, 0.0_dp, 0.0_dp], [box, box, box], status)
  if (status%stat /= demstep_stat%ok) then
    if (rank == 0) write (*, '(a)') status%message
    call MPI_Abort(MPI_COMM_WORLD, 1)
  end if
  deallocate(x, r, m)
  scene%k_normal = 100.0_dp
  scene%k_tangential = 30.0_dp
  scene%effects(scene_effect%rotation) = .true.
  scene%effects(scene_effect%damping) = .true.
  scene%damping_ratio = 0.1_dp
  hwm_scene = largest(peak_kib())

  call MPI_Barrier(MPI_COMM_WORLD)
  t1 = MPI_Wtime()
  call mpi_scene_critical_steps(MPI_COMM_WORLD, scene, result, status, tolerance=1.0e-6_dp)
  t2 = MPI_Wtime()
  hwm_solve = largest(peak_kib())
  if (rank == 0) then
    write (*, '(a, i0, a, i0, a, i0, a, i0)') "particles ", n, "  dof ", result%n_dof, &
      "  springs ", result%n_springs, "  ranks ", nranks
    if (status%stat /= demstep_stat%ok) write (*, '(a)') status%message
    write (*, '(a, es22.14, a, es22.14, a, l1)') "omega_max ", result%omega_max, "  upper ", &
      result%omega_upper, "  converged ", result%eigen_converged
    write (*, '(a, es14.6, a, es14.6, a, es14.6)') "dt eigen ", result%dt_critical_eigen, &
      "  bound ", result%dt_critical_bound, "  contact rule ", result%dt_contact_rule
    write (*, '(a, es14.6, a, es14.6)') "damping ratio of the top mode ", &
      result%damping_ratio_top, "  damped limit ", result%dt_critical_damped
    write (*, '(a, i0, a, i0)') "restarts ", result%eigen_restarts, "  products ", &
      result%eigen_products
    write (*, '(a, f9.3, a, f9.3, a)') "scene ", t1 - t0, " s  mpi_scene_critical_steps ", &
      t2 - t1, " s"
    write (*, '(a, f8.1, a, f8.1, a, f8.0, a)') "peak resident memory of the largest rank: ", &
      hwm_scene/1024.0_dp, " MiB after the scene, ", hwm_solve/1024.0_dp, &
      " MiB after the solve (", 1024.0_dp*hwm_solve/n, " bytes per particle)"
    if (with_serial) then
      t3 = MPI_Wtime()
      call assembly_critical_steps(scene, serial, status, solver=eigen_solver%lanczos, &
        tolerance=1.0e-6_dp)
      write (*, '(a, f9.3, a, es10.2)') "serial assembly_critical_steps ", MPI_Wtime() - t3, &
        " s  omega_max relative difference ", abs(serial%omega_max - result%omega_max) &
        /serial%omega_max
    end if
  end if
  call MPI_Finalize()

contains

  !> Uniform (0,1), the same sequence on every rank.
  function uniform() result(u)
    real(dp) :: u
    seed = mod(48271_i8*seed, 2147483647_i8)
    u = real(seed, dp)/2147483647.0_dp
  end function uniform

  !> The largest value over the ranks.
  function largest(v) result(w)
    integer(i8), intent(in) :: v
    integer(i8) :: w
    call MPI_Allreduce(v, w, 1, MPI_INTEGER8, MPI_MAX, MPI_COMM_WORLD)
  end function largest

  !> VmHWM of this process in KiB (0 where /proc is absent).
  function peak_kib() result(kib)
    integer(i8) :: kib
    integer :: unit, ios
    character(len=256) :: line
    kib = 0
    open (newunit=unit, file="/proc/self/status", action="read", iostat=ios)
    if (ios /= 0) return
    do
      read (unit, '(a)', iostat=ios) line
      if (ios /= 0) exit
      if (line(1:6) == "VmHWM:") read (line(7:), *, iostat=ios) kib
    end do
    close (unit)
  end function peak_kib

end program mpi_scene
