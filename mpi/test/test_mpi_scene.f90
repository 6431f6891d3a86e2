!> A progress sink that counts what it is told (for test_mpi_scene).
module test_mpi_scene_progress
  use demstep_kinds, only: i8
  use demstep_progress, only: progress_type
  implicit none
  private

  !> Counts what it is told.
  type, extends(progress_type), public :: counting_progress
    integer :: starts = 0, finishes = 0
    integer(i8) :: last = 0
  contains
    procedure :: start => counting_start
    procedure :: update => counting_update
    procedure :: finish => counting_finish
  end type counting_progress

contains

  !> Count a start.
  subroutine counting_start(self, what, total)
    class(counting_progress), intent(inout) :: self
    character(len=*), intent(in) :: what
    integer(i8), intent(in) :: total
    self%starts = self%starts + 1
  end subroutine counting_start

  !> Keep the count told.
  subroutine counting_update(self, done)
    class(counting_progress), intent(inout) :: self
    integer(i8), intent(in) :: done
    self%last = done
  end subroutine counting_update

  !> Count a finish.
  subroutine counting_finish(self)
    class(counting_progress), intent(inout) :: self
    self%finishes = self%finishes + 1
  end subroutine counting_finish

end module test_mpi_scene_progress

!> The MPI scene path (`mpi_scene_critical_steps`) against the serial
!> `assembly_critical_steps` with the Lanczos and the dense solver, on every
!> rank count (CI runs it under `mpirun -np 2`): random periodic packings with
!> rotations and tangential springs (3D with damping, 2D with pre-stress), a
!> cubic lattice (degenerate top), a box with walls and fixed particles, and
!> the refusals. Prints one PASS/FAIL line per check (rank 0) and exits
!> non-zero on a failure.
program test_mpi_scene
  use mpi_f08
  use mpi_test_support, only: test_start, test_finish, report, uniform, random_particles, num, close, &
    same_everywhere, msg, same_status, rank, nranks
  use demstep_kinds, only: dp, i8
  use demstep_status, only: demstep_status_type, demstep_stat
  use demstep_scene_data, only: scene_type, scene_effect
  use demstep_scene_builders, only: new_scene, scene_set_cell, scene_add_walls, cubic_lattice
  use demstep_assembly, only: critical_step_type, assembly_critical_steps, eigen_solver, safe_basis
  use demstep_mpi_scene, only: mpi_scene_critical_steps
  use test_mpi_scene_progress, only: counting_progress
  implicit none


  type(scene_type) :: scene
  type(demstep_status_type) :: status

  call test_start(2718_i8)

  call random_packing(scene, 300, 3, 0.3_dp, 1.0_dp)
  scene%effects(scene_effect%damping) = .true.
  scene%damping_ratio = 0.2_dp
  call compare("3D periodic packing, 300 particles, rotations, k_t, damping", scene, .false.)
  call random_packing(scene, 400, 2, 0.5_dp, 0.9_dp)
  call compare("2D periodic packing, 400 particles, rotations, k_t, pre-stress", scene, .true.)
  call cubic_lattice(scene, 8, 0.4_dp, 50.0_dp, status)
  call compare("cubic lattice 8^3 (degenerate top)", scene, .false.)
  call box_with_walls(scene)
  call compare("box with walls and fixed particles, damping", scene, .false.)
  call check_refusals()
  call check_progress()
  call check_not_converged()

  call test_finish("test_mpi_scene")

contains

  !> n particles (radii 0.4..0.7, masses 1..2, inertia of spheres) at random in
  !> a periodic box of n fill unit volumes, linear contacts k_n = 100,
  !> k_t = kt_ratio k_n, rotations on.
  subroutine random_packing(scene, n, dim, kt_ratio, fill)
    type(scene_type), intent(out) :: scene
    integer, intent(in) :: n, dim
    real(dp), intent(in) :: kt_ratio, fill
    real(dp), allocatable :: x(:, :), r(:), m(:)
    real(dp) :: box
    type(demstep_status_type) :: st
    box = (real(n, dp)*fill)**(1.0_dp/dim)
    call random_particles(dim, n, box, x, r, m)
    call new_scene(scene, dim, x, m, r, st)
    call scene_set_cell(scene, [.true., .true., dim == 3], [0.0_dp, 0.0_dp, 0.0_dp], &
      spread(box, 1, 3), st)
    scene%k_normal = 100.0_dp
    scene%k_tangential = kt_ratio*100.0_dp
    scene%effects(scene_effect%rotation) = .true.
  end subroutine random_packing

  !> 200 particles in a 2D box 10 x 10 closed by four walls, every tenth one
  !> fixed, rotations and tangential springs, damping ratio 0.3.
  subroutine box_with_walls(scene)
    type(scene_type), intent(out) :: scene
    integer, parameter :: n = 200
    real(dp) :: x(2, n), r(n), m(n)
    logical :: fixed(n)
    type(demstep_status_type) :: st
    integer :: i
    do i = 1, n
      x(:, i) = [10.0_dp*uniform(), 10.0_dp*uniform()]
      r(i) = 0.35_dp + 0.2_dp*uniform()
      m(i) = 0.5_dp + uniform()
      fixed(i) = mod(i, 10) == 0
    end do
    call new_scene(scene, 2, x, m, r, st, fixed=fixed)
    call scene_add_walls(scene, reshape([0.0_dp, 0.0_dp, 0.0_dp, 0.0_dp, 10.0_dp, 10.0_dp, &
      10.0_dp, 10.0_dp], [2, 4]), reshape([1.0_dp, 0.0_dp, 0.0_dp, 1.0_dp, -1.0_dp, 0.0_dp, &
      0.0_dp, -1.0_dp], [2, 4]), st)
    scene%k_normal = 1.0e4_dp
    scene%k_tangential = 0.4e4_dp
    scene%effects(scene_effect%walls) = .true.
    scene%effects(scene_effect%rotation) = .true.
    scene%effects(scene_effect%damping) = .true.
    scene%damping_ratio = 0.3_dp
  end subroutine box_with_walls

  !> Out of restarts (an open chain of 3000: top eigenvalues 1e-6 apart
  !> relative, far below a 1e-13 tolerance): not an error, on every rank; the
  !> bracket [omega_max, omega_upper] holds the closed form
  !> 2 sqrt(k/m) sin(pi (N-1)/(2N)), as the serial path's.
  subroutine check_not_converged()
    integer, parameter :: n = 3000
    type(scene_type) :: chain
    type(critical_step_type) :: par
    type(demstep_status_type) :: st
    real(dp) :: x(1, n), exact
    integer :: i
    do i = 1, n
      x(1, i) = real(i - 1, dp)
    end do
    call new_scene(chain, 1, x, spread(1.0_dp, 1, n), spread(0.55_dp, 1, n), st)
    chain%k_normal = 1.0e4_dp
    call mpi_scene_critical_steps(MPI_COMM_WORLD, chain, par, st, tolerance=1.0e-13_dp)
    exact = 2.0_dp*sqrt(1.0e4_dp)*sin(acos(-1.0_dp)*(n - 1)/(2.0_dp*n))
    call report("out of restarts: ok and not converged", st%stat == demstep_stat%ok .and. &
      par%eigen_computed .and. .not. par%eigen_converged .and. par%eigen_residual > 1.0e-13_dp, msg(st))
    call report("out of restarts: the bracket holds the closed form", &
      par%omega_max <= exact*(1.0_dp + 1.0e-14_dp) .and. par%omega_upper >= exact*(1.0_dp - 1.0e-14_dp) &
      .and. par%dt_critical_safe <= 2.0_dp/exact .and. par%dt_critical_safe >= par%dt_critical_bound, &
      num(par%omega_max)//num(par%omega_upper)//num(exact))
    call report("out of restarts: the same on every rank", same_everywhere(par%omega_max) .and. &
      same_everywhere(par%omega_upper), "")
  end subroutine check_not_converged

  !> The MPI result against the serial Lanczos and dense results.
  subroutine compare(name, scene, prestress)
    character(len=*), intent(in) :: name
    type(scene_type), intent(in) :: scene
    logical, intent(in) :: prestress
    type(critical_step_type) :: par, lan, den
    type(demstep_status_type) :: st_par, st_lan, st_den
    real(dp) :: bar
    ! (at 1e-10, not the default 1e-6)
    call mpi_scene_critical_steps(MPI_COMM_WORLD, scene, par, st_par, prestress=prestress, &
      tolerance=1.0e-10_dp)
    call assembly_critical_steps(scene, lan, st_lan, prestress=prestress, &
      solver=eigen_solver%lanczos, tolerance=1.0e-10_dp)
    call assembly_critical_steps(scene, den, st_den, prestress=prestress, solver=eigen_solver%dense)
    call report(name//": status ok", st_par%stat == demstep_stat%ok .and. &
      st_lan%stat == demstep_stat%ok .and. st_den%stat == demstep_stat%ok, msg(st_par))
    if (st_par%stat /= demstep_stat%ok .or. st_lan%stat /= demstep_stat%ok .or. &
      st_den%stat /= demstep_stat%ok) return
    call report(name//": model as serial", par%n_dof == lan%n_dof .and. par%n_springs == &
      lan%n_springs .and. par%dof_per_particle == lan%dof_per_particle .and. &
      (par%rotation .eqv. lan%rotation) .and. (par%tangential .eqv. lan%tangential) .and. &
      (par%periodic .eqv. lan%periodic) .and. (par%prestress .eqv. lan%prestress) .and. &
      par%solver == eigen_solver%lanczos .and. par%eigen_computed .and. par%eigen_converged, &
      "n_dof "//num(real(par%n_dof, dp)))
    ! both Lanczos results meet the residual tolerance 1e-10 of omega^2, so
    ! each omega is within 5e-11 of the true one (Weinstein) plus rounding
    call report(name//": omega_max as serial Lanczos (1e-10)", &
      close(par%omega_max, lan%omega_max, 1.0e-10_dp), num(par%omega_max)//num(lan%omega_max))
    call report(name//": omega_max as dense (1e-10)", &
      close(par%omega_max, den%omega_max, 1.0e-10_dp), num(par%omega_max)//num(den%omega_max))
    ! the error bar contains the dense value: the Rayleigh quotient is below
    ! lambda_max and the bar above, up to the rounding of both (a few tens of
    ! ulps of lambda from row sums of up to ~100 terms; 1e-14 as the serial test)
    bar = 1.0e-14_dp*den%omega_max
    call report(name//": error bar contains dense", par%omega_max <= den%omega_max + bar .and. &
      den%omega_max <= par%omega_upper + bar .and. par%dt_critical_safe <= par%dt_critical_eigen &
      .and. par%eigen_residual <= 1.0e-10_dp, num(par%omega_upper))
    call report(name//": dt_critical_eigen as dense", close(par%dt_critical_eigen, &
      den%dt_critical_eigen, 1.0e-10_dp), num(par%dt_critical_eigen))
    ! the safe step certified (randomised, or the bound where lower) and at or
    ! below the exact limit
    call report(name//": safe step certified and safe", (par%safe_basis == safe_basis%randomised &
      .or. par%safe_basis == safe_basis%bound) .and. par%dt_critical_safe <= den%dt_critical_eigen &
      *(1.0_dp + 1.0e-14_dp), num(par%dt_critical_safe))
    ! the same sums of the same entries, in another order: rounding only
    call report(name//": bound as serial (1e-13)", close(par%omega_bound, lan%omega_bound, &
      1.0e-13_dp) .and. close(par%dt_critical_bound, lan%dt_critical_bound, 1.0e-13_dp), &
      num(par%omega_bound)//num(lan%omega_bound))
    call report(name//": contact rule as serial (1e-13)", close(par%dt_contact_rule, &
      lan%dt_contact_rule, 1.0e-13_dp), num(par%dt_contact_rule)//num(lan%dt_contact_rule))
    ! the damping ratio is a Rayleigh quotient of the mode: its error is of the
    ! order of the mode's, residual/gap, far below 1e-6 with a residual of 1e-10
    call report(name//": damping ratio and damped limit as dense (1e-6)", &
      close(par%damping_ratio_top, den%damping_ratio_top, 1.0e-6_dp) .and. &
      close(par%dt_critical_damped, den%dt_critical_damped, 1.0e-6_dp), &
      num(par%damping_ratio_top)//num(den%damping_ratio_top))
    call report(name//": the same result on every rank", same_everywhere(par%omega_max) .and. &
      same_everywhere(par%omega_upper) .and. same_everywhere(par%omega_bound) .and. &
      same_everywhere(par%dt_contact_rule) .and. same_everywhere(par%damping_ratio_top) .and. &
      same_everywhere(real(par%eigen_products, dp)), "")
  end subroutine compare

  !> Bad scenes and options: the serial status, the same on every rank.
  subroutine check_refusals()
    type(scene_type) :: scene
    type(critical_step_type) :: par, ser
    type(demstep_status_type) :: st_par, st_ser, st
    real(dp) :: x(2, 3)
    x = reshape([0.0_dp, 0.0_dp, 0.9_dp, 0.0_dp, 1.8_dp, 0.0_dp], [2, 3])
    call new_scene(scene, 2, x, [1.0_dp, 1.0_dp, 1.0_dp], [0.5_dp, 0.5_dp, 0.5_dp], st, &
      fixed=[.true., .true., .true.])
    scene%k_normal = 10.0_dp
    call mpi_scene_critical_steps(MPI_COMM_WORLD, scene, par, st_par)
    call assembly_critical_steps(scene, ser, st_ser, solver=eigen_solver%lanczos)
    call report("every particle fixed: the serial status", st_par%stat == st_ser%stat .and. &
      msg(st_par) == msg(st_ser) .and. index(msg(st_par), "fixed:") == 1 .and. &
      same_status(st_par), msg(st_par))
    ! one free particle between two fixed ones
    call new_scene(scene, 2, x, [1.0_dp, 1.0_dp, 1.0_dp], [0.5_dp, 0.5_dp, 0.5_dp], st, &
      fixed=[.true., .false., .true.])
    scene%k_normal = 10.0_dp
    call mpi_scene_critical_steps(MPI_COMM_WORLD, scene, par, st_par)
    if (nranks > 1) then
      call report("fewer free particles than ranks: refused", st_par%stat == &
        demstep_stat%invalid_input .and. index(msg(st_par), "comm:") == 1 .and. &
        same_status(st_par), msg(st_par))
    else
      ! two springs k on a unit mass: omega = sqrt(2k/m)
      call report("one free particle on one rank: sqrt(2 k/m)", st_par%stat == demstep_stat%ok &
        .and. close(par%omega_max, sqrt(20.0_dp), 1.0e-14_dp), num(par%omega_max))
    end if
    call random_packing(scene, 50, 2, 0.3_dp, 1.0_dp)
    call mpi_scene_critical_steps(MPI_COMM_WORLD, scene, par, st_par, tolerance=0.5_dp)
    call assembly_critical_steps(scene, ser, st_ser, solver=eigen_solver%lanczos, tolerance=0.5_dp)
    call report("tolerance out of range: the serial status", st_par%stat == st_ser%stat .and. &
      msg(st_par) == msg(st_ser) .and. st_par%stat == demstep_stat%invalid_input .and. &
      same_status(st_par), msg(st_par))
    scene%effects(scene_effect%damping) = .true.
    scene%damping_ratio = -1.0_dp
    call mpi_scene_critical_steps(MPI_COMM_WORLD, scene, par, st_par)
    call assembly_critical_steps(scene, ser, st_ser, solver=eigen_solver%lanczos)
    call report("negative damping ratio: the serial status", st_par%stat == st_ser%stat .and. &
      msg(st_par) == msg(st_ser) .and. index(msg(st_par), "damping_ratio:") == 1 .and. &
      same_status(st_par), msg(st_par))
    scene%damping_ratio = 0.1_dp
    call mpi_scene_critical_steps(MPI_COMM_WORLD, scene, par, st_par, hertz_mode=2)
    call assembly_critical_steps(scene, ser, st_ser, solver=eigen_solver%lanczos, hertz_mode=2)
    call report("impact linearisation without a speed: the serial status", st_par%stat == &
      st_ser%stat .and. msg(st_par) == msg(st_ser) .and. st_par%stat /= demstep_stat%ok &
      .and. same_status(st_par), msg(st_par))
  end subroutine check_refusals

  !> Progress on rank 0 only: one start, updates up to the products, one finish.
  subroutine check_progress()
    type(scene_type) :: scene
    type(critical_step_type) :: par
    type(demstep_status_type) :: st
    type(counting_progress) :: counter
    call random_packing(scene, 100, 3, 0.3_dp, 1.0_dp)
    if (rank == 0) then
      call mpi_scene_critical_steps(MPI_COMM_WORLD, scene, par, st, progress=counter)
    else
      call mpi_scene_critical_steps(MPI_COMM_WORLD, scene, par, st)
    end if
    call report("progress told on rank 0", st%stat == demstep_stat%ok .and. (rank /= 0 .or. &
      (counter%starts == 1 .and. counter%finishes == 1 .and. counter%last == par%eigen_products &
      .and. par%eigen_products > 0)), msg(st))
  end subroutine check_progress

end program test_mpi_scene
