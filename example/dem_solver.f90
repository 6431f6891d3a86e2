!> A small 3D DEM solver that watches its own stability limit with demstep's
!> monitor and adapts its step to it.
!>
!> 3000 polydisperse spheres (radii uniform in 0.8 to 1.2 mm, 2500 kg/m^3) are
!> poured under gravity onto a floor in a cell periodic in x and y and settle.
!> Contacts: linear spring-dashpot normal force (k_n, restitution 0.5), linear
!> tangential springs with Coulomb friction (mu 0.5) and rotations; velocity
!> Verlet (the dashpots see the half-step velocity, the scheme demstep's damped
!> limit is exact for); a cell list each step.
!>
!> Before the first contact the step is demstep's fresh-pour estimate (the
!> exact limit of a generated packing of the same spheres). From then on every
!> `check_every` steps the monitor's cheap check is asked whether the step is
!> still safe; on "re-solve now", and every `update_every` steps, the exact
!> (damped) limit is re-solved, warm-started, and the step set to `safety`
!> times it. The run ends with the mean wall time of a warm-started update and
!> of a check on the settled bed (the second half of the run, the measured
!> window), each over the mean time of one solver step there, measured here:
!>
!>   monitor: update U solver steps, check C solver steps, particles P
!>
!> Run: fpm run --profile release --example dem_solver [-- options] with
!>   steps=N          steps (default 12000);
!>   particles=N      spheres poured (default 3000; the cell's side scaled
!>                    to keep the pour's layers 2.5 mm apart);
!>   safety=S         the step over the damped limit (default 0.9);
!>   settle=N         the step the bed counts as settled (default 3000): from
!>                    there the kinetic energy is watched (the first step at
!>                    which it exceeds 100 times its least value since is
!>                    reported as growth), and tile, probe and kick act;
!>   tile=T           T x T copies of the settled bed in x and y (its contact
!>                    list and tangential springs mapped to the copies: the
!>                    bed as it was, repeated), measured over the second half
!>                    of the steps after it; tile=6 makes 108 000 spheres;
!>   probe=S          from settle on, the step is S times the damped limit;
!>   kick=V           random velocities of V m/s at settle;
!>   kick_mode=V      velocities along the damped limit's mode at settle (the
!>                    fastest particle at V m/s); that mode's own kinetic
!>                    energy is then watched (growth: 100 times its value
!>                    at the kick);
!>   update_every=N   steps between scheduled updates (default 500);
!>   confirm_every=N  the monitor's confirmed Lanczos solve every N-th update;
!>   in_place=X       the monitor's in_place (a refined top mode overlapping
!>                    the previous one by at least X stayed in place);
!>   trace            one line per measured update: its kind, products and
!>                    wall time over the mean solver step of the measured
!>                    window so far (with tile=T the steps after tiling);
!>   verify           each measured update against a cold one on the same
!>                    arrays (damped and undamped limits);
!>   reference        each update and a cold one against the dense exact
!>                    damped limit (one `reference:` line an update; a state
!>                    where either came out above it is written to
!>                    dem_solver_state_STEP.txt; a few hundred particles: a
!>                    dense eigensolve of 6 N unknowns);
!>   scaling=F        mass scaling of the settled bed to F times its damped
!>                    limit, demstep's `scale_masses` against Yade's per-body
!>                    density scaling rule;
!>   a file name      the settled bed's top mode as a VTK file.
!> The solver is serial: the library runs on one OpenMP thread too unless
!> OMP_NUM_THREADS is set (OpenBLAS's own threads: OPENBLAS_NUM_THREADS=1).
program dem_solver
  use demstep, only: dp, i8, demstep_status_type, is_ok, critical_step_type, eigen_solver
  use demstep_monitor, only: step_monitor_type, fresh_pour_estimate, mode_participation, top_shares, &
    monitor_verdict, solver_critical_steps
  use demstep_mass_scaling, only: scale_masses
  use demstep_vtk, only: write_vtk_particles, vtk_field_type
  use omp_lib, only: omp_set_num_threads, omp_get_max_threads
  implicit none

  !> Spheres poured (particles=N; tile=T makes T x T copies of the settled bed).
  integer :: n = 3000
  real(dp), parameter :: pi = 3.14159265358979323846_dp
  real(dp), parameter :: r_mean = 1.0e-3_dp, poly = 0.2_dp, rho = 2500.0_dp
  real(dp), parameter :: k_n = 200.0_dp, k_t = 2.0_dp/7.0_dp*k_n, mu = 0.5_dp, restitution = 0.5_dp
  real(dp), parameter :: g(3) = [0.0_dp, 0.0_dp, -9.81_dp]
  !> The periodic cell's side (x and y), T times the pour's after tiling.
  real(dp) :: box = 30.0e-3_dp
  !> The pour's grid: m x m spheres a layer, 2.5 mm apart (12 for 3000).
  integer :: grid = 12
  integer, parameter :: check_every = 20, report_every = 1000
  !> The step from which the bed counts as settled (settle=N): tiling, the
  !> probe and the kick happen there, and the kinetic energy is watched.
  integer :: settled_step = 3000
  integer :: n_steps = 12000, update_every = 500, tile = 1
  real(dp) :: safety = 0.9_dp, scaling = 0.0_dp
  !> From step settled_step on: the step over the limit (probe=S, 0: safety
  !> throughout), and the velocity kick (m/s) at that step, random or along
  !> the top mode (kick=V, kick_mode=V).
  real(dp) :: probe = 0.0_dp, kick = 0.0_dp, kick_mode = 0.0_dp
  !> kick_mode: the kicked mode (6, n) and its energy's least and largest
  !> values since, at the kick, and the step it first exceeded 100 times its
  !> value at the kick (0: never).
  real(dp), allocatable :: probe_mode(:, :)
  real(dp) :: mode_min = huge(1.0_dp), mode_max = 0.0_dp, mode_kick = 0.0_dp
  integer :: mode_grew_at = 0
  !> The measured window: the steps after measure_from (the run's second
  !> half; with tile=T the second half of the steps after the tiling).
  integer :: measure_from
  integer, parameter :: max_history = 16
  !> The floor z = 0 as the monitor takes walls: a point and the normal into the domain.
  real(dp), parameter :: floor_point(3, 1) = reshape([0.0_dp, 0.0_dp, 0.0_dp], [3, 1])
  real(dp), parameter :: floor_normal(3, 1) = reshape([0.0_dp, 0.0_dp, 1.0_dp], [3, 1])

  real(dp), allocatable :: x(:, :), v(:, :), w(:, :), f(:, :), tq(:, :), mass(:), radius(:), inertia(:)
  ! tangential history: partners (j > i) and spring displacements per particle; the floor's
  integer, allocatable :: h_count(:), h_partner(:, :), new_count(:), new_partner(:, :)
  real(dp), allocatable :: h_xi(:, :, :), new_xi(:, :, :), wall_xi(:, :)
  integer, allocatable :: pairs(:, :)
  real(dp), allocatable :: c_n(:)
  integer :: nc
  ! cell list
  integer, allocatable :: cell_start(:), cell_next(:)
  integer :: ncell(3)
  real(dp) :: cell_w(3)

  real(dp) :: zeta, dt, t, dt_limit, ke
  type(step_monitor_type) :: monitor
  type(critical_step_type) :: estimate
  type(demstep_status_type) :: status
  integer :: step, i, n_updates, n_checks, n_resolves
  integer(i8) :: c0, c1, rate, t_steps, t_updates, t_checks
  ! the second half of the run (a settled bed): its updates, checks and steps
  integer(i8) :: t2_steps, t2_updates, t2_checks
  ! (and their CPU times, s: on a shared machine the wall times wait for the
  ! other processes, the CPU times much less)
  real(dp) :: cpu0, cpu1, cpu2_steps = 0.0_dp, cpu2_updates = 0.0_dp
  integer :: n2_updates, n2_checks, n2_accepted, n2_confirmed, n2_local = 0
  !> verify: each measured update against a cold one (a new monitor) on the
  !> same arrays; the largest and least ratio of their damped limits.
  logical :: verify = .false.
  !> trace: one line per measured update (its kind, products, solver steps).
  logical :: trace = .false.
  real(dp) :: verify_max = 0.0_dp, verify_min = huge(1.0_dp)
  !> verify: the same for the undamped limits.
  real(dp) :: verify_max_u = 0.0_dp, verify_min_u = huge(1.0_dp)
  !> reference: each update (warm) and a cold one against the dense exact
  !> damped limit on the same arrays (one line each, `reference:`).
  logical :: reference = .false.
  ! the kinetic energy's least and largest values since the bed settled (every
  ! 10th step), and the step it grew 100 times
  real(dp) :: ke_min, ke_max
  integer :: grew_at
  ! the first (cold) update's products and time, and the warm ones' products
  integer(i8) :: cold_products, warm_products, t_cold
  logical :: safe, have_limit
  character(len=256) :: vtk_path
  ! Yade's per-body mass factors at sf = 1 (compare_scaling)
  real(dp), allocatable :: yade_base(:)

  zeta = -log(restitution)/sqrt(pi**2 + log(restitution)**2)
  vtk_path = ""
  call arguments()
  if (n_steps < settled_step + 1000) error stop "dem_solver: steps= must be at least settle= + 1000"
  measure_from = n_steps/2
  if (tile > 1) measure_from = (settled_step + n_steps)/2
  call one_thread()
  call setup()

  ! before any contact: the estimate from a generated packing of the same spheres
  call fresh_pour_estimate(r_mean, poly, rho, k_n, k_t, zeta, 0.0_dp, estimate, status)
  if (.not. is_ok(status)) error stop status%message
  dt = safety*estimate%dt_critical_damped
  print '(a, es12.5, a)', "fresh-pour estimate (a generated packing, ESTIMATE): damped limit ", &
    estimate%dt_critical_damped, " s"
  have_limit = .false.
  dt_limit = estimate%dt_critical_damped

  t = 0.0_dp
  t_steps = 0
  t_updates = 0
  t_checks = 0
  t2_steps = 0
  t2_updates = 0
  t2_checks = 0
  n2_updates = 0
  n2_checks = 0
  n2_accepted = 0
  n2_confirmed = 0
  ke_min = huge(1.0_dp)
  ke_max = 0.0_dp
  grew_at = 0
  n_updates = 0
  n_checks = 0
  warm_products = 0
  n_resolves = 0
  call system_clock(count_rate=rate)
  call forces()
  do step = 1, n_steps
    call cpu_time(cpu0)
    call system_clock(c0)
    call verlet_step()
    call system_clock(c1)
    call cpu_time(cpu1)
    t_steps = t_steps + (c1 - c0)
    if (step > measure_from) then
      t2_steps = t2_steps + (c1 - c0)
      cpu2_steps = cpu2_steps + (cpu1 - cpu0)
    end if
    t = t + dt

    if (step == settled_step) call settled()
    if (nc == 0) cycle
    if (.not. have_limit .or. mod(step, update_every) == 0) then
      call update(step)
    else if (mod(step, check_every) == 0) then
      call system_clock(c0)
      call monitor%check(dt, safe, x, mass, radius, pairs(:, :nc), [k_n], status, k_t=[k_t], &
        c_n=c_n(:nc), inertia=inertia, wall_point=floor_point, wall_normal=floor_normal, wall_k=[k_n, k_t], &
        wall_damping=[zeta, 0.0_dp], periodic=[.true., .true., .false.], cell_lo=[0.0_dp, 0.0_dp, 0.0_dp], &
        cell_hi=[box, box, 0.0_dp])
      call system_clock(c1)
      if (.not. is_ok(status)) error stop status%message
      t_checks = t_checks + (c1 - c0)
      n_checks = n_checks + 1
      if (step > measure_from) then
        t2_checks = t2_checks + (c1 - c0)
        n2_checks = n2_checks + 1
      end if
      if (.not. safe) then
        n_resolves = n_resolves + 1
        call update(step)
      end if
    end if
    if (allocated(probe_mode) .and. step >= settled_step .and. mod(step, 10) == 0) then
      ke = mode_energy()
      mode_min = min(mode_min, ke)
      mode_max = max(mode_max, ke)
      ! (against its value at the kick: decayed, it sinks to the bed's
      ! background, from which any noise is a hundredfold)
      if (mode_grew_at == 0 .and. ke > 100.0_dp*mode_kick) then
        mode_grew_at = step
        print '(a, i0, a, es10.3, a, es10.3, a)', "top-mode energy grew 100 times at step ", step, " (", ke, &
          " J, at the kick ", mode_kick, " J)"
      end if
    end if
    if (step >= settled_step .and. mod(step, 10) == 0) then
      ke = kinetic()
      ke_min = min(ke_min, ke)
      ke_max = max(ke_max, ke)
      if (grew_at == 0 .and. (ke > 100.0_dp*ke_min .or. .not. ke <= huge(1.0_dp))) then
        grew_at = step
        print '(a, i0, a, es10.3, a, i0, a, es10.3, a)', "kinetic energy grew 100 times at step ", step, " (", ke, &
          " J, least since step ", settled_step, " ", ke_min, " J)"
      end if
      ! far beyond growth: stop before the cell list sees non-finite positions
      if (.not. ke <= 1.0e6_dp*ke_min) exit
    end if
    if (mod(step, report_every) == 0) then
      ke = kinetic()
      print '(a, i6, a, f7.4, a, es10.3, a, es10.3, a, i6, a, es10.3)', "step ", step, "  t ", t, &
        " s  dt ", dt, " s  limit ", dt_limit, " s  contacts ", nc, "  kinetic ", ke
    end if
  end do

  if (step <= n_steps) print '(a, i0, a)', "stopped at step ", step, ": the kinetic energy grew a million times"
  if (allocated(probe_mode)) print '(a, es10.3, a, es10.3, a, es10.3, a, i0)', "top-mode energy: at the kick ", &
    mode_kick, " J, least ", mode_min, " J, largest ", mode_max, " J, grew 100 times at step ", mode_grew_at
  if (grew_at == 0) print '(a, i0, a, es10.3, a)', "kinetic energy never grew 100 times over its least since step ", &
    settled_step, " (least ", ke_min, " J)"
  print '(a, i0, a, i0, a, es10.3, a, es10.3, a)', "kinetic energy from step ", settled_step, " to ", &
    min(step, n_steps), " (every 10th step): least ", ke_min, " J, largest ", ke_max, " J"
  print '(a, i0, a, i0, a, i0, a)', "updates ", n_updates, " (", n_resolves, " asked for by a check), checks ", &
    n_checks, ""
  print '(a, es12.5, a, es12.5, a, f6.3)', "settled bed: exact damped limit ", monitor%last%dt_critical_damped, &
    " s (undamped ", monitor%last%dt_critical_eigen, " s); fresh-pour estimate / exact ", &
    estimate%dt_critical_damped/monitor%last%dt_critical_damped
  print '(a, i0, a, i0, a, i0)', "last update: Lanczos products ", monitor%last%eigen_products, &
    ", damped solves ", monitor%last%damped_solves, ", contacts ", nc
  print '(a, i0, a, f0.1, a, f0.1, a)', "cold first update: ", cold_products, " products, ", &
    (real(t_cold, dp)/rate)/(real(t_steps, dp)/rate/n_steps), " solver steps; warm updates: ", &
    real(warm_products, dp)/max(1, n_updates - 1), " products on average"

  print '(a, f0.3, a, f0.3, a, f0.3, a)', "mean wall time: solver step ", &
    1.0e3_dp*real(t_steps, dp)/rate/n_steps, " ms, warm update ", &
    1.0e3_dp*real(t_updates, dp)/rate/max(1, n_updates - 1), " ms, check ", &
    1.0e3_dp*real(t_checks, dp)/rate/max(1, n_checks), " ms"
  print '(a, i0, a, f0.2, a, i0, a, i0, a, i0, a, i0, a, f0.2, a)', "settled bed (measured window): ", &
    n2_updates, &
    " updates of ", (real(t2_updates, dp)/max(1, n2_updates))/(real(t2_steps, dp)/(n_steps - measure_from)), &
    " solver steps each (", n2_accepted, " took the previous modes, ", n2_local, " started from a neighbourhood, ", &
    n2_confirmed, " confirmed by Lanczos), ", &
    n2_checks, " checks of ", &
    (real(t2_checks, dp)/max(1, n2_checks))/(real(t2_steps, dp)/(n_steps - measure_from)), " solver steps each"
  if (verify) print '(a, i0, a, f0.6, a, f0.6)', "verify: ", n2_updates, " warm updates against cold ones: "// &
    "damped limit warm/cold from ", verify_min, " to ", verify_max
  if (verify) print '(a, f0.6, a, f0.6)', "verify: undamped limit warm/cold from ", verify_min_u, " to ", verify_max_u
  print '(a, f0.3, a, f0.3, a, f0.2, a)', "measured window: solver step ", &
    1.0e3_dp*real(t2_steps, dp)/rate/(n_steps - measure_from), " ms wall, ", &
    1.0e3_dp*cpu2_steps/(n_steps - measure_from), " ms CPU; updates of ", &
    (cpu2_updates/max(1, n2_updates))/(cpu2_steps/(n_steps - measure_from)), " solver steps in CPU time"
  print '(a, f0.2, a, f0.2, a)', "whole run (pour and settled): warm updates of ", &
    (real(t_updates, dp)/max(1, n_updates - 1))/(real(t_steps, dp)/n_steps), " solver steps, checks of ", &
    (real(t_checks, dp)/max(1, n_checks))/(real(t_steps, dp)/n_steps), " solver steps"
  if (step <= n_steps) stop 1
  call cold_and_warm()
  call governing()
  if (len_trim(vtk_path) > 0) call write_mode(trim(vtk_path))
  if (scaling > 0.0_dp) call compare_scaling(scaling*monitor%last%dt_critical_damped)
  ! the settled bed: the second half of the run, its own solver steps
  print '(a, f0.2, a, f0.2, a, i0)', "monitor: update ", &
    (real(t2_updates, dp)/max(1, n2_updates))/(real(t2_steps, dp)/(n_steps - measure_from)), " solver steps, check ", &
    (real(t2_checks, dp)/max(1, n2_checks))/(real(t2_steps, dp)/(n_steps - measure_from)), " solver steps, particles ", n

contains

  !> steps=N, safety=S and a VTK file name from the command line.
  subroutine arguments()
    character(len=256) :: arg
    integer :: k, ios
    do k = 1, command_argument_count()
      call get_command_argument(k, arg)
      if (index(arg, "steps=") == 1) then
        read(arg(7:), *, iostat=ios) n_steps
        if (ios /= 0 .or. n_steps < 2) error stop "dem_solver: steps= needs an integer >= 2"
      else if (index(arg, "scaling=") == 1) then
        read(arg(9:), *, iostat=ios) scaling
        if (ios /= 0 .or. .not. (scaling > 1.0_dp .and. scaling < 100.0_dp)) &
          error stop "dem_solver: scaling= needs a number in (1, 100)"
      else if (index(arg, "confirm_every=") == 1) then
        read(arg(15:), *, iostat=ios) monitor%confirm_every
        if (ios /= 0 .or. monitor%confirm_every < 0) error stop "dem_solver: confirm_every= needs an integer >= 0"
      else if (index(arg, "in_place=") == 1) then
        read(arg(10:), *, iostat=ios) monitor%in_place
        if (ios /= 0 .or. .not. monitor%in_place >= 0.0_dp) error stop "dem_solver: in_place= needs a number >= 0"
      else if (arg == "verify") then
        verify = .true.
      else if (arg == "reference") then
        reference = .true.
      else if (arg == "trace") then
        trace = .true.
      else if (index(arg, "particles=") == 1) then
        read(arg(11:), *, iostat=ios) n
        if (ios /= 0 .or. n < 10 .or. n > 100000) error stop "dem_solver: particles= needs an integer in 10 to 100000"
        grid = max(3, nint(12.0_dp*sqrt(n/3000.0_dp)))
        box = grid*2.5e-3_dp
      else if (index(arg, "settle=") == 1) then
        read(arg(8:), *, iostat=ios) settled_step
        if (ios /= 0 .or. settled_step < 1000) error stop "dem_solver: settle= needs an integer >= 1000"
      else if (index(arg, "tile=") == 1) then
        read(arg(6:), *, iostat=ios) tile
        if (ios /= 0 .or. tile < 1 .or. tile > 10) error stop "dem_solver: tile= needs an integer in 1 to 10"
      else if (index(arg, "update_every=") == 1) then
        read(arg(14:), *, iostat=ios) update_every
        if (ios /= 0 .or. update_every < check_every) error stop "dem_solver: update_every= needs an integer >= 20"
      else if (index(arg, "probe=") == 1) then
        read(arg(7:), *, iostat=ios) probe
        if (ios /= 0 .or. .not. (probe > 0.0_dp .and. probe < 3.0_dp)) &
          error stop "dem_solver: probe= needs a number in (0, 3)"
      else if (index(arg, "kick=") == 1) then
        read(arg(6:), *, iostat=ios) kick
        if (ios /= 0 .or. .not. (kick >= 0.0_dp .and. kick < 1.0_dp)) &
          error stop "dem_solver: kick= needs a speed in [0, 1) m/s"
      else if (index(arg, "kick_mode=") == 1) then
        read(arg(11:), *, iostat=ios) kick_mode
        if (ios /= 0 .or. .not. (kick_mode >= 0.0_dp .and. kick_mode < 1.0_dp)) &
          error stop "dem_solver: kick_mode= needs a speed in [0, 1) m/s"
      else if (index(arg, "safety=") == 1) then
        read(arg(8:), *, iostat=ios) safety
        if (ios /= 0 .or. .not. (safety > 0.0_dp .and. safety < 2.0_dp)) &
          error stop "dem_solver: safety= needs a number in (0, 2)"
      else
        vtk_path = arg
      end if
    end do
  end subroutine arguments

  !> A serial solver: the library's products run on its one thread too
  !> (OpenMP), unless OMP_NUM_THREADS says otherwise; U and C compare
  !> like with like.
  subroutine one_thread()
    integer :: length, st
    call get_environment_variable("OMP_NUM_THREADS", length=length, status=st)
    if (st /= 0 .or. length == 0) call omp_set_num_threads(1)
    print '(a, i0, a)', "threads: ", omp_get_max_threads(), " (the solver is serial; OMP_NUM_THREADS to change)"
  end subroutine one_thread

  !> At step settled_step: tile the bed (tile=T), switch to the probed step
  !> (probe=S) and kick the particles (kick=V, kick_mode=V).
  subroutine settled()
    real(dp), allocatable :: u(:, :)
    real(dp) :: top
    integer :: k
    if (tile > 1) then
      call tile_bed()
      ! a new bed: the next update is cold
      have_limit = .false.
    end if
    if (probe > 0.0_dp) then
      safety = probe
      dt = safety*dt_limit
      print '(a, f0.4, a, es12.5, a)', "probe: the step is now ", probe, " x the monitored damped limit (", &
        dt, " s)"
    end if
    if (kick > 0.0_dp) then
      ! random directions, each particle's speed kick (translation only)
      allocate(u(3, n))
      call random_number(u)
      u = u - 0.5_dp
      do k = 1, n
        v(:, k) = v(:, k) + kick*u(:, k)/norm2(u(:, k))
      end do
      print '(a, es10.3, a)', "kick: random velocities of ", kick, " m/s"
    end if
    if (kick_mode > 0.0_dp .and. monitor%ready .and. size(monitor%mode_particles, 2) == n) then
      ! along the last update's damped limit's mode (the top undamped one
      ! without dashpots): its displacement and r theta per particle as
      ! velocities, the fastest particle at kick_mode
      probe_mode = monitor%damped_particles
      if (.not. any(probe_mode /= 0.0_dp)) probe_mode = monitor%mode_particles
      top = maxval(norm2(probe_mode(1:3, :), dim=1))
      do k = 1, n
        v(:, k) = v(:, k) + kick_mode*probe_mode(1:3, k)/top
        w(:, k) = w(:, k) + kick_mode*probe_mode(4:6, k)/(top*radius(k))
      end do
      mode_kick = mode_energy()
      print '(a, es10.3, a, es10.3, a)', "kick: along the top mode, fastest particle ", kick_mode, &
        " m/s, its energy ", mode_kick, " J"
    end if
  end subroutine settled

  !> T x T copies of the bed in x and y (tile=T): positions, velocities,
  !> forces, the contact list and the tangential springs (each pair's partner
  !> in the copy its nearest image lies in), so the tiled bed is the settled
  !> one repeated, in equilibrium as it was.
  subroutine tile_bed()
    real(dp), allocatable :: x2(:, :), v2(:, :), w2(:, :), f2(:, :), tq2(:, :), wx2(:, :), c2(:), hx2(:, :, :)
    integer, allocatable :: hc2(:), hp2(:, :), p2(:, :)
    integer :: a, b, k, h, m, off, n2, nc2, ii, jj
    real(dp) :: sg
    n2 = n*tile*tile
    allocate(x2(3, n2), v2(3, n2), w2(3, n2), f2(3, n2), tq2(3, n2), wx2(3, n2))
    allocate(hc2(n2), hp2(max_history, n2), source=0)
    allocate(hx2(3, max_history, n2), source=0.0_dp)
    allocate(p2(2, 8*n2), c2(8*n2))
    nc2 = 0
    do b = 0, tile - 1
      do a = 0, tile - 1
        off = n*(a + tile*b)
        do k = 1, n
          x2(:, k + off) = x(:, k) + [a*box, b*box, 0.0_dp]
          v2(:, k + off) = v(:, k)
          w2(:, k + off) = w(:, k)
          f2(:, k + off) = f(:, k)
          tq2(:, k + off) = tq(:, k)
          wx2(:, k + off) = wall_xi(:, k)
          do h = 1, h_count(k)
            call partner(k, h_partner(h, k), a, b, ii, jj, sg)
            m = hc2(ii) + 1
            if (m > max_history) cycle
            hc2(ii) = m
            hp2(m, ii) = jj
            hx2(:, m, ii) = sg*h_xi(:, h, k)
          end do
        end do
        do m = 1, nc
          call partner(pairs(1, m), pairs(2, m), a, b, ii, jj, sg)
          nc2 = nc2 + 1
          p2(:, nc2) = [ii, jj]
          c2(nc2) = c_n(m)
        end do
      end do
    end do
    n = n2
    box = tile*box
    call move_alloc(x2, x)
    call move_alloc(v2, v)
    call move_alloc(w2, w)
    call move_alloc(f2, f)
    call move_alloc(tq2, tq)
    call move_alloc(wx2, wall_xi)
    call move_alloc(hc2, h_count)
    call move_alloc(hp2, h_partner)
    call move_alloc(hx2, h_xi)
    call move_alloc(p2, pairs)
    call move_alloc(c2, c_n)
    nc = nc2
    mass = [(mass, k = 1, tile*tile)]
    radius = [(radius, k = 1, tile*tile)]
    inertia = [(inertia, k = 1, tile*tile)]
    deallocate(new_count, new_partner, new_xi, cell_next)
    allocate(new_count(n), new_partner(max_history, n), new_xi(3, max_history, n), cell_next(n))
    ncell(1:2) = max(3, int(box/(2.0_dp*maxval(radius))))
    cell_w(1:2) = box/ncell(1:2)
    if (allocated(cell_start)) deallocate(cell_start)
    print '(a, i0, a, i0, a, f0.1, a, i0, a)', "tiled: ", tile, " x ", tile, " copies of the settled bed, cell ", &
      1.0e3_dp*box, " mm, ", n, " particles"
  end subroutine tile_bed

  !> The pair (i, j) (j > i) of copy (a, b) in the tiled numbering (before
  !> n and box change): j's copy is the one its nearest image lies in; (ii,
  !> jj) with jj > ii, and sg = -1 when the order turned (the spring's sense
  !> with it).
  subroutine partner(i, j, a, b, ii, jj, sg)
    integer, intent(in) :: i, j, a, b
    integer, intent(out) :: ii, jj
    real(dp), intent(out) :: sg
    integer :: i2, j2, s(2)
    s = nint((x(1:2, j) - x(1:2, i))/box)
    i2 = i + n*(a + tile*b)
    j2 = j + n*(modulo(a - s(1), tile) + tile*modulo(b - s(2), tile))
    ii = min(i2, j2)
    jj = max(i2, j2)
    sg = merge(1.0_dp, -1.0_dp, j2 > i2)
  end subroutine partner

  !> The kinetic energy in the kicked top mode: the velocities' component
  !> along it in the mass norm (translations, and rotations as r theta).
  real(dp) function mode_energy()
    real(dp) :: a, b
    integer :: k
    a = 0.0_dp
    b = 0.0_dp
    do k = 1, n
      a = a + mass(k)*dot_product(probe_mode(1:3, k), v(:, k)) + &
        (inertia(k)/radius(k))*dot_product(probe_mode(4:6, k), w(:, k))
      b = b + mass(k)*sum(probe_mode(1:3, k)**2) + (inertia(k)/radius(k)**2)*sum(probe_mode(4:6, k)**2)
    end do
    mode_energy = 0.5_dp*a**2/b
  end function mode_energy

  !> Translational and rotational kinetic energy.
  real(dp) function kinetic()
    kinetic = 0.5_dp*sum(spread(mass, 1, 3)*v**2) + 0.5_dp*sum(spread(inertia, 1, 3)*w**2)
  end function kinetic

  !> Radii, masses, a loose lattice above the floor with small random velocities.
  subroutine setup()
    integer :: k, a, b, c, m, seed_size
    integer, allocatable :: seed(:)
    real(dp) :: u(3), spacing
    call random_seed(size=seed_size)
    allocate(seed(seed_size))
    seed = [(12345 + 7*k, k = 1, seed_size)]
    call random_seed(put=seed)
    allocate(x(3, n), v(3, n), w(3, n), f(3, n), tq(3, n), mass(n), radius(n), inertia(n))
    allocate(h_count(n), h_partner(max_history, n), new_count(n), new_partner(max_history, n))
    allocate(h_xi(3, max_history, n), new_xi(3, max_history, n), wall_xi(3, n))
    do i = 1, n
      call random_number(u(1))
      radius(i) = r_mean*(1.0_dp + poly*(2.0_dp*u(1) - 1.0_dp))
    end do
    mass = rho*4.0_dp/3.0_dp*pi*radius**3
    inertia = 0.4_dp*mass*radius**2
    m = grid
    spacing = box/m
    k = 0
    do c = 0, n
      do b = 0, m - 1
        do a = 0, m - 1
          k = k + 1
          if (k > n) exit
          call random_number(u)
          x(:, k) = [(a + 0.5_dp)*spacing, (b + 0.5_dp)*spacing, (c + 0.6_dp)*spacing] + 0.1_dp*spacing*(u - 0.5_dp)
          call random_number(u)
          v(:, k) = 0.05_dp*(u - 0.5_dp)
        end do
      end do
      if (k > n) exit
    end do
    w = 0.0_dp
    h_count = 0
    wall_xi = 0.0_dp
    ncell(1:2) = max(3, int(box/(2.0_dp*maxval(radius))))
    cell_w(1:2) = box/ncell(1:2)
    cell_w(3) = 2.0_dp*maxval(radius)
    allocate(cell_next(n), pairs(2, 8*n), c_n(8*n))
    nc = 0
  end subroutine setup

  !> One velocity-Verlet step: half kick, drift, forces at the half-step
  !> velocities, half kick.
  subroutine verlet_step()
    integer :: k
    do k = 1, 3
      v(k, :) = v(k, :) + 0.5_dp*dt*f(k, :)/mass
      w(k, :) = w(k, :) + 0.5_dp*dt*tq(k, :)/inertia
    end do
    x = x + dt*v
    x(1:2, :) = modulo(x(1:2, :), box)
    call forces()
    do k = 1, 3
      v(k, :) = v(k, :) + 0.5_dp*dt*f(k, :)/mass
      w(k, :) = w(k, :) + 0.5_dp*dt*tq(k, :)/inertia
    end do
  end subroutine verlet_step

  !> Gravity, the floor and every particle contact found with the cell list.
  subroutine forces()
    integer :: j, c, a, b, cc, ia(3), ja(3)
    real(dp) :: zmax
    do i = 1, n
      f(:, i) = mass(i)*g
    end do
    tq = 0.0_dp
    ! cell list: x and y periodic, z from the floor up
    zmax = maxval(x(3, :))
    ncell(3) = max(1, int(zmax/cell_w(3)) + 1)
    if (allocated(cell_start)) then
      if (size(cell_start) < product(ncell)) deallocate(cell_start)
    end if
    if (.not. allocated(cell_start)) allocate(cell_start(2*product(ncell)))
    cell_start = 0
    do i = 1, n
      c = cell_index(cell_of(x(:, i)))
      cell_next(i) = cell_start(c)
      cell_start(c) = i
    end do
    new_count = 0
    nc = 0
    do i = 1, n
      ia = cell_of(x(:, i))
      do a = -1, 1
        do b = -1, 1
          do cc = -1, 1
            ja = [modulo(ia(1) + a, ncell(1)), modulo(ia(2) + b, ncell(2)), ia(3) + cc]
            if (ja(3) < 0 .or. ja(3) >= ncell(3)) cycle
            j = cell_start(cell_index(ja))
            do while (j > 0)
              if (j > i) call pair_force(i, j)
              j = cell_next(j)
            end do
          end do
        end do
      end do
      call floor_force(i)
    end do
    h_count = new_count
    h_partner = new_partner
    h_xi = new_xi
  end subroutine forces

  pure function cell_of(p) result(idx)
    real(dp), intent(in) :: p(3)
    integer :: idx(3)
    idx = int(p/cell_w)
    idx(1:2) = min(max(idx(1:2), 0), ncell(1:2) - 1)
    idx(3) = min(max(idx(3), 0), ncell(3) - 1)
  end function cell_of

  pure integer function cell_index(idx)
    integer, intent(in) :: idx(3)
    cell_index = 1 + idx(1) + ncell(1)*(idx(2) + ncell(2)*idx(3))
  end function cell_index

  !> The contact of i and j (j > i) if they overlap: spring-dashpot normal
  !> force, tangential spring with Coulomb's cap, torques; the pair joins the
  !> contact list with its normal dashpot.
  subroutine pair_force(i, j)
    integer, intent(in) :: i, j
    real(dp) :: d(3), dist, delta, nn(3), ai, aj, vr(3), vn, vt(3), fn, xi(3), ft(3), m_eff, cn, fmax
    integer :: h
    d = x(:, j) - x(:, i)
    d(1:2) = d(1:2) - box*anint(d(1:2)/box)
    dist = norm2(d)
    delta = radius(i) + radius(j) - dist
    if (delta <= 0.0_dp) return
    nn = d/dist
    ai = radius(i) - 0.5_dp*delta
    aj = radius(j) - 0.5_dp*delta
    vr = (v(:, j) + cross(w(:, j), -aj*nn)) - (v(:, i) + cross(w(:, i), ai*nn))
    vn = dot_product(vr, nn)
    vt = vr - vn*nn
    m_eff = mass(i)*mass(j)/(mass(i) + mass(j))
    cn = 2.0_dp*zeta*sqrt(m_eff*k_n)
    fn = k_n*delta - cn*vn
    ! the spring's history, turned into the current tangent plane
    xi = 0.0_dp
    do h = 1, h_count(i)
      if (h_partner(h, i) == j) then
        xi = h_xi(:, h, i)
        exit
      end if
    end do
    xi = xi - dot_product(xi, nn)*nn + dt*vt
    fmax = mu*max(fn, 0.0_dp)
    if (k_t*norm2(xi) > fmax) xi = xi*(fmax/(k_t*norm2(xi)))
    ft = -k_t*xi
    f(:, j) = f(:, j) + fn*nn + ft
    f(:, i) = f(:, i) - fn*nn - ft
    tq(:, i) = tq(:, i) + cross(ai*nn, -ft)
    tq(:, j) = tq(:, j) + cross(-aj*nn, ft)
    if (new_count(i) < max_history) then
      new_count(i) = new_count(i) + 1
      new_partner(new_count(i), i) = j
      new_xi(:, new_count(i), i) = xi
    end if
    if (nc == size(pairs, 2)) call grow()
    nc = nc + 1
    pairs(:, nc) = [i, j]
    c_n(nc) = cn
  end subroutine pair_force

  !> The floor z = 0: the same law, m* = m.
  subroutine floor_force(i)
    integer, intent(in) :: i
    real(dp) :: delta, a, vc(3), vn, vt(3), fn, ft(3), fmax
    real(dp), parameter :: ez(3) = [0.0_dp, 0.0_dp, 1.0_dp]
    delta = radius(i) - x(3, i)
    if (delta <= 0.0_dp) then
      wall_xi(:, i) = 0.0_dp
      return
    end if
    a = radius(i) - 0.5_dp*delta
    vc = v(:, i) + cross(w(:, i), -a*ez)
    vn = vc(3)
    vt = vc - vn*ez
    fn = k_n*delta - 2.0_dp*zeta*sqrt(mass(i)*k_n)*vn
    wall_xi(:, i) = wall_xi(:, i) - wall_xi(3, i)*ez + dt*vt
    fmax = mu*max(fn, 0.0_dp)
    if (k_t*norm2(wall_xi(:, i)) > fmax) wall_xi(:, i) = wall_xi(:, i)*(fmax/(k_t*norm2(wall_xi(:, i))))
    ft = -k_t*wall_xi(:, i)
    f(:, i) = f(:, i) + fn*ez + ft
    tq(:, i) = tq(:, i) + cross(-a*ez, ft)
  end subroutine floor_force

  subroutine grow()
    integer, allocatable :: p2(:, :)
    real(dp), allocatable :: c2(:)
    allocate(p2(2, 2*size(pairs, 2)), c2(2*size(pairs, 2)))
    p2(:, :nc) = pairs(:, :nc)
    c2(:nc) = c_n(:nc)
    call move_alloc(p2, pairs)
    call move_alloc(c2, c_n)
  end subroutine grow

  pure function cross(a, b) result(c)
    real(dp), intent(in) :: a(3), b(3)
    real(dp) :: c(3)
    c = [a(2)*b(3) - a(3)*b(2), a(3)*b(1) - a(1)*b(3), a(1)*b(2) - a(2)*b(1)]
  end function cross

  !> The exact (damped) limit, warm-started; the step becomes safety times it.
  subroutine update(step)
    integer, intent(in) :: step
    call cpu_time(cpu0)
    call system_clock(c0)
    call solve(monitor)
    call system_clock(c1)
    call cpu_time(cpu1)
    if (.not. is_ok(status)) then
      print '(a, i0, a)', "step ", step, ": "//status%message
      error stop 1
    end if
    ! (the first, cold, update is not counted in the mean)
    if (have_limit) then
      t_updates = t_updates + (c1 - c0)
      warm_products = warm_products + monitor%last%eigen_products
    else
      t_cold = c1 - c0
      cold_products = monitor%last%eigen_products
    end if
    n_updates = n_updates + 1
    if (step > measure_from) then
      t2_updates = t2_updates + (c1 - c0)
      cpu2_updates = cpu2_updates + (cpu1 - cpu0)
      n2_updates = n2_updates + 1
      if (monitor%accepted) n2_accepted = n2_accepted + 1
      if (monitor%confirmed) n2_confirmed = n2_confirmed + 1
      if (monitor%local_start) n2_local = n2_local + 1
      if (verify) call verify_update()
      if (trace) print '(a, i0, a, l1, a, l1, a, l1, a, i0, a, f0.2, a)', "update at ", step, ": accepted ", &
        monitor%accepted, ", confirmed ", monitor%confirmed, ", local ", monitor%local_start, ", ", &
        monitor%last%eigen_products, " products, ", real(c1 - c0, dp)/(real(t2_steps, dp)/(step - measure_from)), &
        " solver steps"
    end if
    if (reference) call reference_update(step)
    have_limit = .true.
    dt_limit = monitor%last%dt_critical_damped
    dt = safety*dt_limit
  end subroutine update

  !> The update just made against a cold one on the same arrays (verify).
  subroutine verify_update()
    type(step_monitor_type) :: fresh
    type(demstep_status_type) :: st
    call fresh%update(x, mass, radius, pairs(:, :nc), [k_n], st, k_t=[k_t], c_n=c_n(:nc), &
      inertia=inertia, wall_point=floor_point, wall_normal=floor_normal, wall_k=[k_n, k_t], &
      wall_damping=[zeta, 0.0_dp], periodic=[.true., .true., .false.], cell_lo=[0.0_dp, 0.0_dp, 0.0_dp], &
      cell_hi=[box, box, 0.0_dp])
    if (.not. is_ok(st)) error stop st%message
    verify_max = max(verify_max, monitor%last%dt_critical_damped/fresh%last%dt_critical_damped)
    verify_min = min(verify_min, monitor%last%dt_critical_damped/fresh%last%dt_critical_damped)
    verify_max_u = max(verify_max_u, monitor%last%dt_critical_eigen/fresh%last%dt_critical_eigen)
    verify_min_u = min(verify_min_u, monitor%last%dt_critical_eigen/fresh%last%dt_critical_eigen)
  end subroutine verify_update

  !> The update just made and a cold one against the dense exact damped limit
  !> on the same arrays (reference): one line, the ratios to the exact one.
  subroutine reference_update(step)
    integer, intent(in) :: step
    type(step_monitor_type) :: fresh
    type(critical_step_type) :: exact
    type(demstep_status_type) :: st
    call solve(fresh)
    if (.not. is_ok(status)) error stop status%message
    call solver_critical_steps(x, mass, radius, pairs(:, :nc), [k_n], exact, st, k_t=[k_t], c_n=c_n(:nc), &
      inertia=inertia, wall_point=floor_point, wall_normal=floor_normal, wall_k=[k_n, k_t], &
      wall_damping=[zeta, 0.0_dp], periodic=[.true., .true., .false.], cell_lo=[0.0_dp, 0.0_dp, 0.0_dp], &
      cell_hi=[box, box, 0.0_dp], solver=eigen_solver%dense)
    if (.not. is_ok(st)) error stop st%message
    print '(a, i0, a, i0, a, es14.7, a, f11.8, a, f11.8, a, f11.8, a, l1, a, l1)', "reference: step ", step, &
      " contacts ", nc, " exact ", exact%dt_critical_damped, " warm/exact ", &
      monitor%last%dt_critical_damped/exact%dt_critical_damped, " cold/exact ", &
      fresh%last%dt_critical_damped/exact%dt_critical_damped, " undamped warm/exact ", &
      monitor%last%dt_critical_eigen/exact%dt_critical_eigen, " accepted ", monitor%accepted, " confirmed ", &
      monitor%confirmed
    if (max(monitor%last%dt_critical_damped, fresh%last%dt_critical_damped) > exact%dt_critical_damped) &
      call write_state(step, exact%dt_critical_damped)
  end subroutine reference_update

  !> The solver's arrays at `step` (a state whose warm or cold damped limit
  !> came out above the exact one, `exact`) as a text file
  !> `dem_solver_state_STEP.txt`: the constants, then one line a particle
  !> (x, mass, radius, inertia) and one a contact (pair, c_n).
  subroutine write_state(step, exact)
    integer, intent(in) :: step
    real(dp), intent(in) :: exact
    character(len=64) :: path
    integer :: u, k
    write(path, '(a, i0, a)') "dem_solver_state_", step, ".txt"
    open(newunit=u, file=trim(path), status="replace", action="write")
    write(u, '(2i8, 5es25.17)') n, nc, box, k_n, k_t, zeta, exact
    do k = 1, n
      write(u, '(6es25.17)') x(:, k), mass(k), radius(k), inertia(k)
    end do
    do k = 1, nc
      write(u, '(2i8, es25.17)') pairs(:, k), c_n(k)
    end do
    close(u)
  end subroutine write_state

  !> One update of a monitor on the solver's current arrays: the contact
  !> list with its dashpots, scalar stiffness, the floor and the cell.
  subroutine solve(m)
    type(step_monitor_type), intent(inout) :: m
    call m%update(x, mass, radius, pairs(:, :nc), [k_n], status, k_t=[k_t], c_n=c_n(:nc), &
      inertia=inertia, wall_point=floor_point, wall_normal=floor_normal, wall_k=[k_n, k_t], &
      wall_damping=[zeta, 0.0_dp], periodic=[.true., .true., .false.], cell_lo=[0.0_dp, 0.0_dp, 0.0_dp], &
      cell_hi=[box, box, 0.0_dp])
  end subroutine solve

  !> On the settled bed: a cold update (a new monitor) against a warm one,
  !> products and wall time in solver steps.
  subroutine cold_and_warm()
    type(step_monitor_type) :: fresh
    integer(i8) :: tc, tw
    real(dp) :: step_time
    step_time = real(t_steps, dp)/n_steps
    call system_clock(c0)
    call solve(fresh)
    call system_clock(c1)
    if (.not. is_ok(status)) error stop status%message
    tc = c1 - c0
    call system_clock(c0)
    call solve(monitor)
    call system_clock(c1)
    if (.not. is_ok(status)) error stop status%message
    tw = c1 - c0
    print '(a, i0, a, f0.1, a, i0, a, f0.1, a, es12.5, a, es12.5)', "settled bed, one state: cold update ", &
      fresh%last%eigen_products, " products ", real(tc, dp)/step_time, " solver steps; warm ", &
      monitor%last%eigen_products, " products ", real(tw, dp)/step_time, " solver steps; damped limits ", &
      fresh%last%dt_critical_damped, " and ", monitor%last%dt_critical_damped
  end subroutine cold_and_warm

  !> The ten particles and contacts that carry most of the top mode.
  subroutine governing()
    real(dp), allocatable :: ps(:), cs(:), ws(:)
    integer, allocatable :: top(:)
    integer :: k
    call mode_participation(monitor, nc, ps, cs, ws, status)
    if (.not. is_ok(status)) error stop status%message
    top = top_shares(ps, 10)
    print '(a)', "top mode: the 10 particles that carry most (share, radius mm, mass mg, contacts)"
    do k = 1, size(top)
      print '(i6, f8.4, f8.4, f8.4, i4)', top(k), ps(top(k)), 1.0e3_dp*radius(top(k)), 1.0e6_dp*mass(top(k)), &
        count(pairs(1, :nc) == top(k) .or. pairs(2, :nc) == top(k)) + merge(1, 0, x(3, top(k)) < radius(top(k)))
    end do
    top = top_shares(cs, 10)
    print '(a)', "top mode: the 10 contacts that carry most (share, particles, k_n N/m)"
    do k = 1, size(top)
      print '(i6, f8.4, 2i6, f8.1)', top(k), cs(top(k)), pairs(:, top(k)), k_n
    end do
  end subroutine governing

  !> Mass scaling of the settled bed to `target`: demstep's exact scaling
  !> (`scale_masses`) and Yade's per-body density scaling rule on the same
  !> arrays, each scaled system's exact damped limit by `solver_critical_steps`.
  !> Yade's rule (GlobalStiffnessTimeStepper, pkg/dem/GlobalStiffnessTimeStepper.cpp
  !> of yade-mpi at 593a4d6ab, lines 177-198, 62-73 and 104-106; NewtonIntegrator.cpp
  !> line 172 divides the inertia by it): per body the diagonal stiffness sums
  !> K = sum (k_n - k_t) n_a^2 + k_t per axis a and R = sum k_t (1 - n_a^2) r^2,
  !> dt_i = sqrt(2) sf sqrt(min(m/max K, I/max R)) and the factor
  !> densityScaling = (dt_i/target)^2 on the accelerations: a mass factor
  !> (target/dt_i)^2, below 1 where dt_i > target (kept as "net", and clipped
  !> at 1 as "added only"); sf = 0.8, Yade's default timestepSafetyCoefficient,
  !> and the largest sf (bisected to 0.5 %) with which each version reaches
  !> the target by the exact limit.
  subroutine compare_scaling(target)
    real(dp), intent(in) :: target
    real(dp), allocatable :: factor(:), kd(:, :), rd(:, :)
    real(dp) :: added, nn(3), d(3), sf, lo, hi, least
    type(critical_step_type) :: scaled, verify, verify_y
    integer :: c, k, passes, version
    integer(i8) :: t0, t1, rate
    call system_clock(t0, rate)
    call scale_masses(monitor, target, mass, radius, factor, added, scaled, status, inertia=inertia, &
      passes=passes, least=least)
    call system_clock(t1)
    if (.not. is_ok(status)) then
      print '(a)', "scale_masses: "//status%message
    end if
    call verify_limit(factor, verify)
    print '(a, es12.5, a, f0.2, a, es11.4, a, i0, a, f0.4, a, i0, a, f0.1, a)', "mass scaling to ", target, &
      " s (", target/monitor%last%dt_critical_damped, " x the limit): demstep added mass ", added, &
      " of the total, ", count(factor > 1.0_dp), " particles scaled, exact damped limit / target ", &
      verify%dt_critical_damped/target, " (", passes, " exact solves, ", real(t1 - t0, dp)/real(rate, dp), " s)"
    print '(a, es11.4, a)', "  no factors >= 1 reaching the target add less than ", least, &
      " of the mass (the cutting planes' lower bound)"
    ! Yade's per-body rule on the same contacts (and the floor)
    allocate(kd(3, n), rd(3, n), source=0.0_dp)
    do c = 1, nc
      d = x(:, pairs(2, c)) - x(:, pairs(1, c))
      d(1:2) = d(1:2) - box*anint(d(1:2)/box)
      nn = d/norm2(d)
      do k = 1, 2
        kd(:, pairs(k, c)) = kd(:, pairs(k, c)) + (k_n - k_t)*nn**2 + k_t
        rd(:, pairs(k, c)) = rd(:, pairs(k, c)) + k_t*(1.0_dp - nn**2)*radius(pairs(k, c))**2
      end do
    end do
    do i = 1, n
      if (x(3, i) >= radius(i)) cycle
      kd(:, i) = kd(:, i) + (k_n - k_t)*[0.0_dp, 0.0_dp, 1.0_dp] + k_t
      rd(:, i) = rd(:, i) + k_t*[1.0_dp, 1.0_dp, 0.0_dp]*radius(i)**2
    end do
    ! the factor at sf = 1: (target/dt_i)^2 scales as 1/sf^2
    allocate(yade_base(n), source=1.0_dp)
    do i = 1, n
      if (maxval(kd(:, i)) <= 0.0_dp) cycle
      yade_base(i) = target**2/(2.0_dp*min(mass(i)/maxval(kd(:, i)), inertia(i)/maxval(rd(:, i))))
    end do
    do version = 1, 2
      call report_yade(target, version, 0.8_dp, verify_y)
      lo = 0.05_dp
      hi = 0.8_dp
      if (verify_y%dt_critical_damped >= target) lo = hi
      do while (hi > 1.005_dp*lo)
        sf = sqrt(lo*hi)
        call verify_limit(yade_factors(version, sf), verify_y)
        if (verify_y%dt_critical_damped >= target) then
          lo = sf
        else
          hi = sf
        end if
      end do
      call report_yade(target, version, lo, verify_y)
    end do
  end subroutine compare_scaling

  !> Yade's factors at safety coefficient sf: net (version 1) or clipped at 1.
  function yade_factors(version, sf) result(f)
    integer, intent(in) :: version
    real(dp), intent(in) :: sf
    real(dp) :: f(n)
    f = yade_base/sf**2
    if (version == 2) f = max(f, 1.0_dp)
  end function yade_factors

  !> One line: Yade's rule at sf, its mass change and exact damped limit.
  subroutine report_yade(target, version, sf, crit)
    real(dp), intent(in) :: target, sf
    integer, intent(in) :: version
    type(critical_step_type), intent(out) :: crit
    real(dp) :: f(n)
    f = yade_factors(version, sf)
    call verify_limit(f, crit)
    print '(a, a, a, f0.4, a, es10.3, a, f0.4, a, i0, a)', "Yade's per-body rule (", &
      trim(merge("net       ", "added only", version == 1)), ", sf ", sf, "): mass change ", &
      sum((f - 1.0_dp)*mass)/sum(mass), ", exact damped limit / target ", &
      crit%dt_critical_damped/target, ", ", count(f > 1.0_dp), " particles scaled"
  end subroutine report_yade

  !> The exact damped limit of the settled bed with masses and inertia scaled.
  subroutine verify_limit(factor, crit)
    real(dp), intent(in) :: factor(:)
    type(critical_step_type), intent(out) :: crit
    call solver_critical_steps(x, mass*factor, radius, pairs(:, :nc), [k_n], crit, status, k_t=[k_t], &
      c_n=c_n(:nc), inertia=inertia*factor, wall_point=floor_point, wall_normal=floor_normal, &
      wall_k=[k_n, k_t], wall_damping=[zeta, 0.0_dp], periodic=[.true., .true., .false.], &
      cell_lo=[0.0_dp, 0.0_dp, 0.0_dp], cell_hi=[box, box, 0.0_dp])
    if (.not. is_ok(status)) error stop status%message
  end subroutine verify_limit

  !> The settled bed's top mode as a VTK file (participation per particle and contact).
  subroutine write_mode(path)
    character(len=*), intent(in) :: path
    real(dp), allocatable :: ps(:), cs(:), ws(:)
    type(vtk_field_type) :: pf(2), cf(1)
    call mode_participation(monitor, nc, ps, cs, ws, status)
    if (.not. is_ok(status)) error stop status%message
    pf(1) = vtk_field_type("radius", radius)
    pf(2) = vtk_field_type("participation", ps)
    cf(1) = vtk_field_type("contact_participation", cs)
    call write_vtk_particles(path, x, pf, status, pairs=pairs(:, :nc), contact_fields=cf, &
      title="dem_solver: the settled bed's top mode")
    if (.not. is_ok(status)) error stop status%message
    print '(a)', "wrote "//path
  end subroutine write_mode

end program dem_solver
