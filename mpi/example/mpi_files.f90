!> The critical time steps of a 3D periodic scene read in parts from a
!> particles table and a contacts table (distributed input, module
!> `demstep_mpi_dist_scene`), e.g. the tables of `mpi/tools/lattice_tables.py`.
!> Prints the result, the time of the reading and of the solve, and per rank
!> the particles owned and held (halo), the contacts held, the peak resident
!> memory (VmHWM) after the reading and after the solve, and the bytes per
!> owned particle.
!>   mpirun -np 2 build/.../mpi_files PARTICLES CONTACTS BOX [TOLERANCE]
!> BOX: the periodic cell [0, BOX)^3; TOLERANCE default 1e-6.
program mpi_files
  use mpi_f08
  use demstep_kinds, only: dp, i8
  use demstep_status, only: demstep_status_type, demstep_stat
  use demstep_scene_input, only: scene_input_type
  use demstep_assembly, only: critical_step_type
  use demstep_mpi_dist_scene, only: dist_scene_part_type, mpi_read_scene, mpi_part_critical_steps, &
    dist_scene_bytes
  implicit none
  integer :: rank, nranks, ios, r
  integer(i8) :: mine(6)
  integer(i8), allocatable :: all(:, :)
  real(dp) :: box, tol, t0, t1, t2
  character(len=4096) :: arg
  type(scene_input_type) :: input
  type(dist_scene_part_type) :: part
  type(critical_step_type) :: result
  type(demstep_status_type) :: status

  call MPI_Init()
  call MPI_Comm_rank(MPI_COMM_WORLD, rank)
  call MPI_Comm_size(MPI_COMM_WORLD, nranks)
  input%dim = 3
  call get_command_argument(1, arg)
  input%particles_file = trim(arg)
  call get_command_argument(2, arg)
  input%contacts_file = trim(arg)
  call get_command_argument(3, arg)
  read (arg, *, iostat=ios) box
  tol = 1.0e-6_dp
  call get_command_argument(4, arg)
  if (len_trim(arg) > 0 .and. ios == 0) read (arg, *, iostat=ios) tol
  if (ios /= 0 .or. len(input%particles_file) == 0 .or. len(input%contacts_file) == 0) then
    if (rank == 0) write (*, '(a)') "mpi_files PARTICLES CONTACTS BOX [TOLERANCE]"
    call MPI_Abort(MPI_COMM_WORLD, 2)
  end if
  input%periodic = [.true., .true., .true.]
  input%cell_hi = [box, box, box]

  call MPI_Barrier(MPI_COMM_WORLD)
  t0 = MPI_Wtime()
  call mpi_read_scene(MPI_COMM_WORLD, input, part, status)
  call MPI_Barrier(MPI_COMM_WORLD)
  t1 = MPI_Wtime()
  if (status%stat /= demstep_stat%ok) then
    if (rank == 0) write (*, '(a)') status%message
    call MPI_Abort(MPI_COMM_WORLD, 2)
  end if
  mine(1) = part%n_own
  mine(2) = part%scene%n - part%n_own
  mine(3) = size(part%scene%contact_pairs, 2)
  mine(4) = peak_kib()
  mine(6) = dist_scene_bytes(part)
  call mpi_part_critical_steps(MPI_COMM_WORLD, part, result, status, tolerance=tol, release=.true.)
  t2 = MPI_Wtime()
  mine(5) = peak_kib()
  allocate(all(6, 0:nranks - 1))
  call MPI_Gather(mine, 6, MPI_INTEGER8, all, 6, MPI_INTEGER8, 0, MPI_COMM_WORLD)
  if (rank == 0) then
    if (status%stat /= demstep_stat%ok) write (*, '(a)') status%message
    write (*, '(a, i0, a, i0, a, i0, a, i0)') "particles ", part%n_particles, "  dof ", result%n_dof, &
      "  springs ", result%n_springs, "  ranks ", nranks
    write (*, '(a, es22.14, a, es22.14, a, l1)') "omega_max ", result%omega_max, "  upper ", &
      result%omega_upper, "  converged ", result%eigen_converged
    write (*, '(a, es14.6, a, es14.6, a, es14.6)') "dt eigen ", result%dt_critical_eigen, &
      "  bound ", result%dt_critical_bound, "  contact rule ", result%dt_contact_rule
    write (*, '(a, i0, a, i0)') "restarts ", result%eigen_restarts, "  products ", result%eigen_products
    write (*, '(a, f9.3, a, f9.3, a)') "read ", t1 - t0, " s  solve ", t2 - t1, " s"
    write (*, '(a)') "rank  own  halo  contacts  part-arrays-MiB  VmHWM-read-MiB  VmHWM-solve-MiB  " &
      //"bytes/own-particle"
    do r = 0, nranks - 1
      write (*, '(i0, 3(2x, i0), 3(2x, f9.1), 2x, f8.0)') r, all(1:3, r), all(6, r)/1048576.0_dp, &
        all(4, r)/1024.0_dp, all(5, r)/1024.0_dp, 1024.0_dp*all(5, r)/max(all(1, r), 1_i8)
    end do
  end if
  call MPI_Finalize()

contains

  !> VmHWM of this process in KiB (0 where /proc is absent).
  function peak_kib() result(kib)
    integer(i8) :: kib
    integer :: unit, ios2
    character(len=256) :: line
    kib = 0
    open (newunit=unit, file="/proc/self/status", action="read", iostat=ios2)
    if (ios2 /= 0) return
    do
      read (unit, '(a)', iostat=ios2) line
      if (ios2 /= 0) exit
      if (line(1:6) == "VmHWM:") read (line(7:), *, iostat=ios2) kib
    end do
    close (unit)
  end function peak_kib

end program mpi_files
