!> Time the distributed Lanczos solve on a random spring network of L**3
!> degrees of freedom: a periodic cubic grid, each node joined to its 6
!> neighbours with random stiffness and carrying a random mass, mass-scaled as
!> demstep's operator. Nodes are numbered by z slab, so a row block is a region
!> of space and its halo is one L x L layer on each side. Every rank builds
!> only its own rows.
!>   mpirun -np 2 build/.../mpi_network [L [tolerance [ncv]]]   (default 46, 1e-6, 24)
program mpi_network
  use mpi_f08
  use demstep_kinds, only: dp, i8
  use demstep_status, only: demstep_status_type, demstep_stat
  use demstep_lanczos, only: eigen_result_type
  use demstep_mpi_lanczos, only: dist_csr_type, dist_csr_create, parallel_lanczos_largest, &
    dist_gershgorin_bound, dist_csr_bytes, dist_csr_free
  implicit none
  integer, parameter :: reach = 3
  integer :: rank, nranks, n, side, ncv, first, nl, i, d, j, q, arg_status
  integer(i8), allocatable :: row_start(:)
  integer, allocatable :: col(:)
  real(dp), allocatable :: val(:)
  type(dist_csr_type) :: a
  type(eigen_result_type) :: result
  type(demstep_status_type) :: status
  real(dp) :: tol, t0, t1, t2, bound, k
  integer(i8) :: lanczos_bytes, csr_bytes, hwm
  character(len=64) :: arg

  call MPI_Init()
  call MPI_Comm_rank(MPI_COMM_WORLD, rank)
  call MPI_Comm_size(MPI_COMM_WORLD, nranks)
  side = 46
  tol = 1.0e-6_dp
  ncv = 24
  call get_command_argument(1, arg, status=arg_status)
  if (arg_status == 0 .and. len_trim(arg) > 0) read (arg, *) side
  call get_command_argument(2, arg, status=arg_status)
  if (arg_status == 0 .and. len_trim(arg) > 0) read (arg, *) tol
  call get_command_argument(3, arg, status=arg_status)
  if (arg_status == 0 .and. len_trim(arg) > 0) read (arg, *) ncv
  n = side**3
  ! equal contiguous blocks
  first = 1 + rank*(n/nranks) + min(rank, mod(n, nranks))
  nl = n/nranks
  if (rank < mod(n, nranks)) nl = nl + 1

  t0 = MPI_Wtime()
  ! row i: the diagonal, then the springs to its 6 grid neighbours (a graph Laplacian)
  allocate(row_start(nl + 1), col(nl*(2*reach + 1)), val(nl*(2*reach + 1)))
  q = 0
  do i = first, first + nl - 1
    row_start(i - first + 1) = q + 1
    q = q + 1
    col(q) = i
    val(q) = 0.0_dp
    do d = 1, 2*reach
      j = neighbour(i, d)
      k = stiffness(min(i, j), max(i, j))
      val(row_start(i - first + 1)) = val(row_start(i - first + 1)) + k
      q = q + 1
      col(q) = j
      val(q) = -k
    end do
  end do
  row_start(nl + 1) = q + 1
  ! mass scaling M^-1/2 K M^-1/2
  do i = 1, nl
    do q = int(row_start(i)), int(row_start(i + 1)) - 1
      val(q) = val(q)/sqrt(mass(first + i - 1)*mass(col(q)))
    end do
  end do
  call dist_csr_create(MPI_COMM_WORLD, n, first, row_start, col, val, a, status)
  deallocate(row_start, col, val)
  if (status%stat /= demstep_stat%ok) then
    if (rank == 0) write (*, '(a)') status%message
    call MPI_Abort(MPI_COMM_WORLD, 1)
  end if
  t1 = MPI_Wtime()
  call dist_gershgorin_bound(a, bound)
  call parallel_lanczos_largest(a, result, status, tolerance=tol, ncv=ncv)
  t2 = MPI_Wtime()
  csr_bytes = dist_csr_bytes(a)
  ! PARPACK's arrays: v(n_local, ncv), workd 3 n_local, resid, z(n_local, nev), y
  lanczos_bytes = 8_i8*a%n_local*(result%ncv + 3 + 1 + result%nev + 1)
  hwm = peak_kib()
  call MPI_Allreduce(MPI_IN_PLACE, hwm, 1, MPI_INTEGER8, MPI_MAX, MPI_COMM_WORLD)
  if (rank == 0) then
    write (*, '(a, i0, a, i0, a, es8.1)') "dof ", n, "  ranks ", nranks, "  tolerance ", tol
    write (*, '(a, es22.14, a, es9.2, a, l1)') "lambda_max ", result%eigenvalue, &
      "  error bar ", result%error_bound, "  converged ", result%converged
    if (status%stat /= demstep_stat%ok) write (*, '(a)') status%message
    write (*, '(a, es22.14)') "Gershgorin bound ", bound
    write (*, '(a, i0, a, i0)') "restarts ", result%iterations, "  products ", result%applications
    write (*, '(a, f9.3, a, f9.3, a)') "build ", t1 - t0, " s  solve ", t2 - t1, " s"
    write (*, '(a, f7.1, a, f7.1, a, i0, a)') "bytes per dof on rank 0: CSR + halo ", &
      real(csr_bytes, dp)/a%n_local, ", Lanczos ", real(lanczos_bytes, dp)/a%n_local, &
      "  (halo ", a%n_halo, " entries)"
    write (*, '(a, f9.1, a)') "peak resident memory, largest rank ", hwm/1024.0_dp, " MiB"
  end if
  call dist_csr_free(a)
  call MPI_Finalize()

contains

  !> Stiffness in [0.1, 1.1) of the spring between nodes i < j, from a few
  !> Park-Miller steps seeded by the pair (the same on every rank).
  pure function stiffness(i, j) result(s)
    integer, intent(in) :: i, j
    real(dp) :: s
    integer(i8), parameter :: m = 2147483647_i8
    integer(i8) :: state
    state = mod(int(i, i8)*9_i8 + int(modulo(j - i, n), i8), m - 1_i8) + 1_i8
    state = mod(48271_i8*state, m)
    state = mod(48271_i8*state, m)
    state = mod(48271_i8*state, m)
    s = 0.1_dp + real(state, dp)/real(m, dp)
  end function stiffness

  !> The d-th grid neighbour (-x, +x, -y, +y, -z, +z) of node i, periodic.
  pure function neighbour(i, d) result(j)
    integer, intent(in) :: i, d
    integer :: j
    integer :: x(3), axis
    x = [mod(i - 1, side), mod((i - 1)/side, side), (i - 1)/(side*side)]
    axis = (d + 1)/2
    x(axis) = modulo(x(axis) + merge(-1, 1, mod(d, 2) == 1), side)
    j = 1 + x(1) + side*(x(2) + side*x(3))
  end function neighbour

  !> Mass in [0.5, 1.5) of node i (the same on every rank).
  pure function mass(i) result(w)
    integer, intent(in) :: i
    real(dp) :: w
    w = stiffness(i, i) + 0.4_dp
  end function mass

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

end program mpi_network
