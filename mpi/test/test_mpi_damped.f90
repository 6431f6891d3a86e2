!> The MPI paths' exact damped limit on the stored states of a pour
!> (test/data/damped, see its README and test_damping's `test_pour_states`:
!> 300 spheres, 1800 unknowns, normal dashpots, tangential springs, a damped
!> floor, a cell periodic in x and y), each with its dense exact damped
!> limit: `mpi_scene_critical_steps` on the scene with its floor, and
!> `mpi_files_critical_steps` on the same scene written as tables (the
!> distributed reader reads no walls: each floor contact is a contact with
!> a fixed sphere of the same radius centred at z = -r, whose overlap,
!> normal and lever arm are the floor's, with the floor's dashpot given),
!> against the serial `assembly_critical_steps` (Lanczos; its damped Newton
!> steps confirmed by a cold solve) and the exact limit, on every rank
!> count (CI runs it under `mpirun -np 2`). Each state also with an
!> undamped stiff pair of spheres far above the pour whose limit 2/omega is
!> the exact one times 1 + 1e-6 or 1 + 3e-6: the undamped top is the pair's,
!> the damped top the pour's, and the warm Newton steps from the pair's mode
!> stop on it. Without the cold confirmation (at c8ea84a) the MPI damped
!> limits came out above the exact one in 7 of these 12 cases (path, state,
!> pair): 1.0000004 to 1.0000005 of it, 1.0000025 on state 1200 with the
!> 3e-6 pair (MPI scene), and with 2 or 3 damped solves. Prints one
!> PASS/FAIL line per check (rank 0) and exits non-zero on a failure.
program test_mpi_damped
  use mpi_f08
  use mpi_test_support, only: test_start, test_finish, report, num, close, same_everywhere, msg, rank, delete
  use demstep_kinds, only: dp, i8
  use demstep_status, only: demstep_status_type, demstep_stat
  use demstep_scene_data, only: scene_type, scene_effect
  use demstep_scene_builders, only: new_scene, scene_set_cell, scene_set_contacts, scene_add_walls, &
    scene_set_law, scene_set_damping
  use demstep_interaction, only: contact_law, dashpot_coefficient
  use demstep_scene_input, only: scene_input_type
  use demstep_assembly, only: critical_step_type, assembly_critical_steps, eigen_solver
  use demstep_lanczos, only: lanczos_tolerance_default
  use demstep_mpi_scene, only: mpi_scene_critical_steps
  use demstep_mpi_dist_scene, only: mpi_files_critical_steps
  implicit none
  integer, parameter :: steps(3) = [1200, 1380, 1400]
  !> The pair's limit over the exact one, minus 1.
  real(dp), parameter :: margins(2) = [1.0e-6_dp, 3.0e-6_dp]
  character(len=*), parameter :: stem = "build/test_mpi_damped_"
  !> The pour's state: spheres, contacts (with their c_n), the cell's side,
  !> the springs, the floor's damping ratio and the exact damped limit.
  integer :: n, nc
  real(dp), allocatable :: x(:, :), mass(:), radius(:), inertia(:), c_n(:), kn_c(:), kt_c(:)
  integer, allocatable :: pairs(:, :)
  real(dp) :: box, k_n, k_t, zeta, exact
  character(len=:), allocatable :: pfile, cfile
  character(len=64) :: path
  character(len=24) :: label
  integer :: s, p

  call test_start(1400_i8)
  if (rank == 0) call execute_command_line("mkdir -p build")
  call MPI_Barrier(MPI_COMM_WORLD)
  pfile = stem//"particles.txt"
  cfile = stem//"contacts.txt"
  do s = 1, size(steps)
    write (path, '(a, i0, a)') "../test/data/damped/pour_state_", steps(s), ".txt"
    if (.not. read_state(trim(path))) then
      call report(trim(path)//": read", .false., "cannot read it (run from mpi/)")
      cycle
    end if
    call compare(trim(path))
    do p = 1, size(margins)
      if (.not. read_state(trim(path))) exit
      call add_pair(margins(p))
      write (label, '(a, es7.1)') " + pair ", margins(p)
      call compare(trim(path)//trim(label), margins(p))
    end do
  end do
  if (rank == 0) then
    call delete(pfile)
    call delete(cfile)
  end if
  call test_finish("test_mpi_damped")

contains

  !> Read a state (the format of test/data/damped/README.md); false when the
  !> file cannot be read.
  logical function read_state(file) result(ok)
    character(len=*), intent(in) :: file
    integer :: u, k, ios
    ok = .false.
    open (newunit=u, file=file, status="old", action="read", iostat=ios)
    if (ios /= 0) return
    read (u, *, iostat=ios) n, nc, box, k_n, k_t, zeta, exact
    if (ios /= 0) return
    if (allocated(x)) deallocate(x, mass, radius, inertia, c_n, pairs)
    allocate(x(3, n), mass(n), radius(n), inertia(n), c_n(nc), pairs(2, nc))
    kn_c = spread(k_n, 1, nc)
    kt_c = spread(k_t, 1, nc)
    do k = 1, n
      read (u, *, iostat=ios) x(:, k), mass(k), radius(k), inertia(k)
      if (ios /= 0) return
    end do
    do k = 1, nc
      read (u, *, iostat=ios) pairs(:, k), c_n(k)
      if (ios /= 0) return
    end do
    close (u)
    ok = .true.
  end function read_state

  !> Two more spheres far above the pour, one undamped normal spring between
  !> them whose limit 2/omega is the exact damped one times 1 + margin.
  subroutine add_pair(margin)
    real(dp), intent(in) :: margin
    real(dp) :: m, r, k
    m = 1.0e-5_dp
    r = 1.0e-3_dp
    k = 0.5_dp*m*(2.0_dp/(exact*(1.0_dp + margin)))**2
    x = reshape([x, [0.5_dp*box, 0.5_dp*box, 0.1_dp], [0.5_dp*box, 0.5_dp*box, 0.1_dp + 2.0_dp*r - 1.0e-5_dp]], &
      [3, n + 2])
    mass = [mass, m, m]
    radius = [radius, r, r]
    inertia = [inertia, 0.4_dp*m*r**2, 0.4_dp*m*r**2]
    pairs = reshape([pairs, [n + 1, n + 2]], [2, nc + 1])
    kn_c = [kn_c, k]
    kt_c = [kt_c, 0.0_dp]
    c_n = [c_n, 0.0_dp]
    n = n + 2
    nc = nc + 1
  end subroutine add_pair

  !> The state as a scene: its contacts with their springs and c_n, the
  !> floor z = 0 with the springs and its normal damping ratio, the cell.
  subroutine floor_scene(scene, status)
    type(scene_type), intent(out) :: scene
    type(demstep_status_type), intent(out) :: status
    real(dp), allocatable :: k(:, :)
    call new_scene(scene, 3, x, mass, radius, status, inertia=inertia)
    if (status%stat == demstep_stat%ok) call scene_set_cell(scene, [.true., .true., .false.], &
      [0.0_dp, 0.0_dp, 0.0_dp], [box, box, 0.0_dp], status)
    allocate(k(8, nc), source=0.0_dp)
    k(1, :) = kn_c
    k(2, :) = kt_c
    k(5, :) = c_n
    if (status%stat == demstep_stat%ok) call scene_set_contacts(scene, pairs, k, status)
    if (status%stat == demstep_stat%ok) call scene_add_walls(scene, reshape([0.0_dp, 0.0_dp, 0.0_dp], [3, 1]), &
      reshape([0.0_dp, 0.0_dp, 1.0_dp], [3, 1]), status)
    if (status%stat == demstep_stat%ok) call scene_set_law(scene, contact_law%linear, k_n, k_t, status)
    if (status%stat == demstep_stat%ok) call scene_set_damping(scene, zeta, status, tangential=0.0_dp)
  end subroutine floor_scene

  !> The state as tables for the distributed reader (rank 0 writes): the
  !> spheres, then per floor contact a fixed sphere of the same radius at
  !> (x, y, -r) (its overlap with the sphere is the floor's, r - z, so its
  !> lever arm r - overlap/2 and normal are the floor's); the contacts with
  !> (k_n, k_t, 0, 0, c_n, 0, 0, 0), the floor's c_n = 2 zeta sqrt(m k_n).
  subroutine write_tables()
    integer :: u, i, c, extra
    character(len=*), parameter :: row = '(*(es24.16, 1x))'
    if (rank == 0) then
      open (newunit=u, file=pfile, status="replace", action="write")
      write (u, '(a)') "# x y z vx vy vz mass radius fixed inertia"
      do i = 1, n
        write (u, row) x(:, i), 0.0_dp, 0.0_dp, 0.0_dp, mass(i), radius(i), 0.0_dp, inertia(i)
      end do
      do i = 1, n
        if (x(3, i) < radius(i)) write (u, row) x(1:2, i), -radius(i), 0.0_dp, 0.0_dp, 0.0_dp, mass(i), &
          radius(i), 1.0_dp, inertia(i)
      end do
      close (u)
      open (newunit=u, file=cfile, status="replace", action="write")
      write (u, '(a)') "# i j k_n k_t k_r k_w c_n c_t c_r c_w"
      do c = 1, nc
        write (u, '(2(i0, 1x), 8(es24.16, 1x))') pairs(:, c), kn_c(c), kt_c(c), 0.0_dp, 0.0_dp, c_n(c), 0.0_dp, &
          0.0_dp, 0.0_dp
      end do
      extra = 0
      do i = 1, n
        if (.not. x(3, i) < radius(i)) cycle
        extra = extra + 1
        write (u, '(2(i0, 1x), 8(es24.16, 1x))') i, n + extra, k_n, k_t, 0.0_dp, 0.0_dp, &
          dashpot_coefficient(zeta, mass(i), k_n), 0.0_dp, 0.0_dp, 0.0_dp
      end do
      close (u)
    end if
    call MPI_Barrier(MPI_COMM_WORLD)
  end subroutine write_tables

  !> The MPI paths' damped limits on one state (with a pair of the given
  !> margin) against the serial one and the exact one.
  subroutine compare(name, margin)
    character(len=*), intent(in) :: name
    real(dp), intent(in), optional :: margin
    type(scene_type) :: scene
    type(scene_input_type) :: input
    type(critical_step_type) :: ser, par, fil
    type(demstep_status_type) :: st_ser, st_par, st_fil
    real(dp) :: tol
    tol = lanczos_tolerance_default
    call floor_scene(scene, st_ser)
    if (st_ser%stat == demstep_stat%ok) call assembly_critical_steps(scene, ser, st_ser, &
      solver=eigen_solver%lanczos)
    call mpi_scene_critical_steps(MPI_COMM_WORLD, scene, par, st_par)
    call write_tables()
    input%dim = 3
    input%particles_file = pfile
    input%contacts_file = cfile
    input%periodic = [.true., .true., .false.]
    input%cell_hi = [box, box, 0.0_dp]
    input%effects = [scene_effect%contacts, scene_effect%damping, scene_effect%rotation]
    input%damping_ratio = zeta
    call mpi_files_critical_steps(MPI_COMM_WORLD, input, fil, st_fil)
    call report(name//": status ok", st_ser%stat == demstep_stat%ok .and. st_par%stat == demstep_stat%ok &
      .and. st_fil%stat == demstep_stat%ok, msg(st_ser)//" | "//msg(st_par)//" | "//msg(st_fil))
    if (st_ser%stat /= demstep_stat%ok .or. st_par%stat /= demstep_stat%ok .or. st_fil%stat /= demstep_stat%ok) &
      return
    if (present(margin)) then
      ! (the undamped top is the pair's, omega = 2/(exact (1 + margin)): both
      ! solves to tol on omega^2, so within tol of it)
      call report(name//": the undamped top is the pair's", close(par%omega_max*exact*(1.0_dp + margin), &
        2.0_dp, tol) .and. close(fil%omega_max*exact*(1.0_dp + margin), 2.0_dp, tol), num(par%omega_max))
    end if
    call check_limit(name//": MPI scene", par, ser)
    call check_limit(name//": MPI files", fil, ser)
    ! the files path makes the serial path's solves (the same operator and
    ! start vectors, rounding only): the same Newton steps and the same cold
    ! confirmation (without it, one solve fewer)
    call report(name//": MPI files: the serial path's damped solves and cold confirmations", &
      fil%damped_solves == ser%damped_solves .and. fil%damped_confirmations == ser%damped_confirmations, &
      num(real(fil%damped_solves, dp))//num(real(ser%damped_solves, dp)))
  end subroutine compare

  !> One MPI path's damped limit `c`: exact, confirmed by at least one cold
  !> solve (`damped_confirmations`, counted by the Newton steps: a
  !> damped_solves count alone does not tell a cold solve from a third warm
  !> one), at or below the
  !> exact limit (1e-9: the dense reference's rounding; a step 4 tau/U from
  !> an upper end U of the true top is below the root) and within 2 tol of
  !> it (as test_damping's test_pour_states), within tol of the serial one
  !> `ser` (each stops within tol/2 of the root plus its solve's error bar,
  !> below it), the same on every rank.
  subroutine check_limit(what, c, ser)
    character(len=*), intent(in) :: what
    type(critical_step_type), intent(in) :: c, ser
    real(dp) :: got, tol
    tol = lanczos_tolerance_default
    got = c%dt_critical_damped
    call report(what//": damped exact, confirmed by a cold solve (at least a loose warm solve, one to " &
      //"the tolerance and the cold one)", c%damped_exact .and. c%damped_confirmations >= 1 .and. &
      c%damped_solves >= 2 + c%damped_confirmations .and. same_everywhere(real(c%damped_confirmations, dp)), &
      num(real(c%damped_confirmations, dp))//num(real(c%damped_solves, dp)))
    call report(what//": damped limit at or below the exact one, within 2 tol", got <= exact*(1.0_dp + &
      1.0e-9_dp) .and. got >= exact*(1.0_dp - 2.0_dp*tol), "ratio "//num(got/exact))
    call report(what//": damped limit as the serial one (tol)", close(got, ser%dt_critical_damped, tol), &
      num(got)//num(ser%dt_critical_damped))
    call report(what//": the same on every rank", same_everywhere(got), "")
  end subroutine check_limit

end program test_mpi_damped
