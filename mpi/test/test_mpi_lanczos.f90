!> The distributed Lanczos path against the serial one, on every rank count
!> (CI runs it under `mpirun -np 2`): random sparse networks, a periodic
!> lattice with a degenerate top, an uneven partition, Gershgorin's bound, the
!> start vector, refused partitions and PARPACK's status messages. Prints one
!> PASS/FAIL line per check (rank 0) and exits non-zero on a failure.
program test_mpi_lanczos
  use mpi_f08
  use mpi_test_support, only: test_start, test_finish, report, uniform, rank, nranks
  use demstep_kinds, only: dp, i8
  use demstep_status, only: demstep_status_type, demstep_stat
  use demstep_arpack, only: dsaupd_status, dseupd_status
  use demstep_parpack, only: pdsaupd_status, pdseupd_status
  use demstep_lanczos, only: lanczos_largest, eigen_result_type, lanczos_start_vector
  use demstep_csr, only: csr_matrix_type, csr_from_springs, csr_apply
  use demstep_mpi_lanczos, only: dist_csr_type, dist_csr_create, parallel_lanczos_largest, &
    dist_gershgorin_bound, dist_start_vector, dist_csr_free
  implicit none

  call test_start(12345_i8)

  call check_network("random network, 400 nodes", 400, 2400, .false.)
  call check_network("random network, 6000 nodes, masses and ground", 6000, 30000, .true.)
  call check_network("random network, 6000 nodes, uneven blocks", 6000, 24000, .true., &
    uneven=.true.)
  call check_lattice("periodic square lattice 48 x 48 (degenerate top)", 48)
  call check_start_vector()
  call check_bad_partition()
  call check_status_messages()

  call test_finish("test_mpi_lanczos")

contains

  !> Rows of rank r: equal blocks, or rank 0 with a third of its share.
  subroutine my_block(n, uneven, first, count_rows)
    integer, intent(in) :: n
    logical, intent(in) :: uneven
    integer, intent(out) :: first, count_rows
    integer :: r, f, c, share
    f = 1
    do r = 0, nranks - 1
      share = n/nranks
      if (r < mod(n, nranks)) share = share + 1
      c = share
      if (uneven .and. nranks > 1) then
        if (r == 0) c = max(1, share/3)
        if (r == nranks - 1) c = n - f + 1
      end if
      if (r == rank) then
        first = f
        count_rows = c
      end if
      f = f + c
    end do
  end subroutine my_block

  !> Serial and distributed answers on the same global matrix.
  subroutine compare(name, a, uneven, value)
    character(len=*), intent(in) :: name
    type(csr_matrix_type), intent(in) :: a
    logical, intent(in) :: uneven
    !> The distributed eigenvalue.
    real(dp), intent(out), optional :: value
    type(dist_csr_type) :: d
    type(eigen_result_type) :: serial, parallel
    type(demstep_status_type) :: st_serial, st_parallel
    type(csr_matrix_type) :: work
    integer :: first, nl, i
    integer(i8) :: p0, p1
    real(dp) :: bound, serial_bound, rel
    real(dp), allocatable :: zl(:)
    character(len=200) :: detail

    work = a
    call lanczos_largest(csr_apply, work, a%n, serial, st_serial, tolerance=1.0e-10_dp)
    call my_block(a%n, uneven, first, nl)
    p0 = a%row_start(first)
    p1 = a%row_start(first + nl) - 1
    call dist_csr_create(MPI_COMM_WORLD, a%n, first, a%row_start(first:first + nl) - p0 + 1, &
      a%col(p0:p1), a%val(p0:p1), d, st_parallel)
    call report(name//": partition accepted", st_parallel%stat == demstep_stat%ok, "")
    if (st_parallel%stat /= demstep_stat%ok) return
    allocate(zl(nl))
    call parallel_lanczos_largest(d, parallel, st_parallel, eigenvector=zl, tolerance=1.0e-10_dp)
    if (present(value)) value = parallel%eigenvalue
    ! both asked for 1e-10 (the default is 1e-6): they stop at a residual <=
    ! 1e-10 * theta; a Rayleigh quotient is then within residual**2/gap of the
    ! eigenvalue, far below 1e-10 relative
    rel = abs(parallel%eigenvalue - serial%eigenvalue)/serial%eigenvalue
    write (detail, '(a, es23.15, a, es23.15, a, es9.2)') "(serial ", serial%eigenvalue, &
      ", ranks ", parallel%eigenvalue, ", relative difference ", rel
    call report(name//": eigenvalue to 1e-10", st_serial%stat == demstep_stat%ok .and. &
      st_parallel%stat == demstep_stat%ok .and. parallel%converged .and. rel <= 1.0e-10_dp, &
      trim(detail)//")")
    ! the error bar of each holds the other's lower bound: both bracket lambda_max
    call report(name//": error bars overlap", serial%eigenvalue <= parallel%eigenvalue &
      + parallel%error_bound .and. parallel%eigenvalue <= serial%eigenvalue &
      + serial%error_bound .and. parallel%residual <= 1.0e-10_dp*parallel%eigenvalue, "")
    ! Gershgorin: the serial row sums over the whole matrix, exactly (same sums)
    serial_bound = 0.0_dp
    do i = 1, a%n
      serial_bound = max(serial_bound, sum(abs(a%val(a%row_start(i):a%row_start(i + 1) - 1))))
    end do
    call dist_gershgorin_bound(d, bound)
    ! and it bounds the Rayleigh quotient (a lower bound of lambda_max up to its
    ! rounding, a few ulps: 8 allowed, as the error bar's allowance)
    call report(name//": Gershgorin bound", bound == serial_bound .and. &
      bound*(1.0_dp + 8.0_dp*epsilon(1.0_dp)) >= parallel%eigenvalue, "")
    call dist_csr_free(d)
  end subroutine compare

  subroutine check_network(name, n, springs, scaled, uneven)
    character(len=*), intent(in) :: name
    integer, intent(in) :: n, springs
    logical, intent(in) :: scaled
    logical, intent(in), optional :: uneven
    integer, allocatable :: first(:), second(:)
    real(dp), allocatable :: k(:), mass(:), ground(:)
    type(csr_matrix_type) :: a
    type(demstep_status_type) :: st
    integer :: e
    allocate(first(springs), second(springs), k(springs), mass(n), ground(n))
    do e = 1, springs
      first(e) = 1 + int(uniform()*n)
      do
        second(e) = 1 + int(uniform()*n)
        if (second(e) /= first(e)) exit
      end do
      k(e) = 0.1_dp + uniform()
    end do
    if (scaled) then
      do e = 1, n
        mass(e) = 0.5_dp + uniform()
        ground(e) = 0.01_dp*uniform()
      end do
      call csr_from_springs(n, first, second, k, a, st, ground=ground, mass=mass)
    else
      call csr_from_springs(n, first, second, k, a, st)
    end if
    call compare(name, a, present(uneven))
  end subroutine check_network

  !> An L x L periodic square lattice of unit springs, numbered row by row
  !> (so row blocks are slabs of the cell, as a spatial partition gives).
  subroutine check_lattice(name, l)
    character(len=*), intent(in) :: name
    integer, intent(in) :: l
    integer, allocatable :: first(:), second(:)
    real(dp), allocatable :: k(:)
    type(csr_matrix_type) :: a
    type(demstep_status_type) :: st
    integer :: i, j, e
    real(dp) :: value
    value = 0.0_dp
    allocate(first(2*l*l), second(2*l*l), k(2*l*l))
    k = 1.0_dp
    e = 0
    do j = 0, l - 1
      do i = 0, l - 1
        e = e + 1
        first(e) = 1 + i + l*j
        second(e) = 1 + mod(i + 1, l) + l*j
        e = e + 1
        first(e) = 1 + i + l*j
        second(e) = 1 + i + l*mod(j + 1, l)
      end do
    end do
    call csr_from_springs(l*l, first, second, k, a, st)
    call compare(name, a, .false., value)
    ! the closed form: 8 for even L (the checkerboard mode, 2 + 2 per axis)
    call report(name//": closed form 8", abs(value - 8.0_dp) <= 1.0e-10_dp*8.0_dp, "")
  end subroutine check_lattice

  subroutine check_start_vector()
    real(dp), allocatable :: whole(:), part(:)
    allocate(whole(1000), part(300))
    call lanczos_start_vector(whole)
    call dist_start_vector(701, part)
    call report("start vector block equals the serial one", all(part == whole(701:1000)), "")
  end subroutine check_start_vector

  subroutine check_bad_partition()
    type(dist_csr_type) :: d
    type(demstep_status_type) :: st
    integer(i8), allocatable :: rs(:)
    ! every rank claims row 1: overlapping blocks (on one rank: a block that
    ! misses row 2 of n_global = 2)
    rs = [1_i8, 2_i8]
    call dist_csr_create(MPI_COMM_WORLD, 2*nranks + merge(1, 0, nranks == 1), 1, rs, [1], &
      [1.0_dp], d, st)
    call report("overlapping or short row blocks refused", st%stat == demstep_stat%invalid_input &
      .and. index(st%message, "tile") > 0, "")
    ! a column outside 1..n_global
    call dist_csr_create(MPI_COMM_WORLD, nranks, rank + 1, rs, [nranks + 1], [1.0_dp], d, st)
    call report("column out of range refused", st%stat == demstep_stat%invalid_input, "")
    ! an unbuilt matrix is refused, not used
    block
      type(eigen_result_type) :: r
      call parallel_lanczos_largest(d, r, st)
      call report("unbuilt matrix refused", st%stat == demstep_stat%invalid_input, "")
    end block
  end subroutine check_bad_partition

  subroutine check_status_messages()
    integer, parameter :: codes(*) = [0, 1, 2, 3, -1, -2, -3, -4, -5, -6, -7, -8, -9, -10, &
      -11, -12, -13, -14, -15, -16, -17, -9999, 77]
    type(demstep_status_type) :: a, b
    logical :: ok
    integer :: i
    ok = .true.
    do i = 1, size(codes)
      a = pdsaupd_status(codes(i))
      b = dsaupd_status(codes(i))
      ok = ok .and. a%stat == b%stat
      if (codes(i) /= 0) ok = ok .and. index(a%message, "PARPACK pdsaupd: ") == 1 &
        .and. a%message(18:) == b%message(16:)
      a = pdseupd_status(codes(i))
      b = dseupd_status(codes(i))
      ok = ok .and. a%stat == b%stat
      if (codes(i) /= 0) ok = ok .and. index(a%message, "PARPACK pdseupd: ") == 1 &
        .and. a%message(18:) == b%message(16:)
    end do
    call report("every PARPACK info code is ARPACK's status, named after PARPACK", ok, "")
  end subroutine check_status_messages

end program test_mpi_lanczos
