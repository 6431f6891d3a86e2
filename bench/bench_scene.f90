!> Benchmark of scenes: nanoseconds per particle-step with effects off and each
!> effect on, beside a plain spring loop over the same bonds; time of the exact
!> eigen analysis against degrees of freedom; time of the bound against springs.
!> Run: fpm run --profile release --example bench_scene
program bench_scene
  use demstep
  use demstep_sort, only: sort_ascending
  implicit none
  integer, parameter :: sizes(4) = [1000, 10000, 100000, 1000000]
  character(len=16), parameter :: labels(7) = [character(len=16) :: "plain loop", "bonds only", &
    "+ contacts", "+ gravity", "+ damping", "+ local_damping", "+ walls"]
  real(dp) :: t(7)
  integer :: i, k
  character(len=16) :: part, arg
  integer :: n_max, ios
  ! an argument picks one part: steps, eigen or bound (default: all three).
  ! The program ends at `end program`, never at `stop`: gfortran's STOP lists the
  ! IEEE flags raised so far, and dsyevr sets divide-by-zero and invalid on
  ! purpose (LAPACK's ieeeck divides by zero to probe IEEE arithmetic), which
  ! would read like a fault of the benchmark or of demstep.
  call get_command_argument(1, part)
  ! a second argument limits the particle counts of `steps` (say 10000)
  call get_command_argument(2, arg)
  n_max = huge(1)
  if (arg /= "") read(arg, *, iostat=ios) n_max
  if (part == "" .or. part == "steps") then
    write(*, '(a)') "ns per particle-step (3D cubic lattice, 3 bonds per particle; median of 3):"
    write(*, '("| particles |", 7(1x, a, " |"))') (trim(labels(k)), k = 1, 7)
    write(*, '(a)') "|---:|---:|---:|---:|---:|---:|---:|---:|"
    do i = 1, size(sizes)
      if (sizes(i) > n_max) exit
      do k = 1, 7
        t(k) = step_time(sizes(i), k)
      end do
      write(*, '("| ", i0, " |", 7(1x, f8.1, " |"))') sizes(i), t
    end do
  end if
  if (part == "" .or. part == "eigen") call eigen_times()
  if (part == "" .or. part == "bound") call bound_times()

contains

  !> A cubic lattice of about n particles, radius 0.45 (no contacts at rest),
  !> every effect off.
  subroutine lattice(n, scene)
    integer, intent(in) :: n
    type(scene_type), intent(out) :: scene
    type(demstep_status_type) :: status
    call cubic_lattice(scene, max(2, nint(real(n, dp)**(1.0_dp/3.0_dp))), 0.45_dp, 100.0_dp, status)
    scene%effects = .false.
  end subroutine lattice

  !> Median ns per particle-step of configuration k (1: the plain loop).
  real(dp) function step_time(n, k) result(ns)
    integer, intent(in) :: n, k
    type(scene_type) :: scene, start
    type(scene_summary_type) :: summary
    type(demstep_status_type) :: status
    integer(8) :: c0, c1, rate, steps
    real(dp) :: times(3)
    integer :: r
    call lattice(n, start)
    if (k >= 3) start%effects(scene_effect%contacts) = .true.
    if (k >= 4) start%effects(scene_effect%gravity) = .true.
    if (k >= 4) start%gravity = [0.0_dp, 0.0_dp, -1.0e-3_dp]
    if (k >= 5) start%effects(scene_effect%damping) = .true.
    if (k >= 5) start%damping_ratio = 0.05_dp
    if (k >= 6) start%effects(scene_effect%local_damping) = .true.
    if (k >= 6) start%local_damping = 0.1_dp
    if (k >= 7) then
      start%effects(scene_effect%walls) = .true.
      call scene_add_walls(start, reshape([0.0_dp, 0.0_dp, 0.5_dp], [3, 1]), &
        reshape([0.0_dp, 0.0_dp, 1.0_dp], [3, 1]), status)
    end if
    steps = max(5_8, 20000000_8/start%n)
    do r = 1, 3
      scene = start
      call system_clock(c0, rate)
      if (k == 1) then
        call plain_loop(scene, 0.01_dp, steps)
      else
        call scene_run(scene, 0.01_dp, steps, summary, status, sample_every=steps)
      end if
      call system_clock(c1)
      times(r) = real(c1 - c0, dp)/real(rate, dp)*1.0e9_dp/real(steps*start%n, dp)
    end do
    call sort_ascending(times)
    ns = times(2)
  end function step_time

  !> The same bonds stepped by a loop written for them alone.
  subroutine plain_loop(scene, dt, steps)
    type(scene_type), intent(inout) :: scene
    real(dp), intent(in) :: dt
    integer(8), intent(in) :: steps
    real(dp), allocatable :: f(:, :)
    real(dp) :: u(3), fb(3)
    integer(8) :: s
    integer :: b, i, j
    allocate(f(3, scene%n))
    do s = 1, steps
      scene%x = scene%x + scene%v*dt
      f = 0.0_dp
      do b = 1, size(scene%bonds, 2)
        i = scene%bonds(1, b)
        j = scene%bonds(2, b)
        u = scene%x(:, j) - scene%x(:, i) - scene%bond_rest(:, b)
        fb = scene%k_bond*dot_product(scene%bond_normal(:, b), u)*scene%bond_normal(:, b)
        f(:, i) = f(:, i) + fb
        f(:, j) = f(:, j) - fb
      end do
      do i = 1, scene%n
        scene%v(:, i) = scene%v(:, i) + f(:, i)*(dt/scene%mass(i))
      end do
    end do
  end subroutine plain_loop

  subroutine eigen_times()
    integer, parameter :: dofs(5) = [300, 750, 1500, 2250, 3000]
    type(scene_type) :: scene
    type(critical_step_type) :: c
    type(demstep_status_type) :: status
    integer(8) :: c0, c1, rate
    integer :: i
    write(*, '(a)') "", "exact omega_max (dsyevr on the dense mass-scaled stiffness), one run each:"
    write(*, '(a)') "| degrees of freedom | seconds |", "|---:|---:|"
    do i = 1, size(dofs)
      call lattice(dofs(i)/3, scene)
      call system_clock(c0, rate)
      call assembly_critical_steps(scene, c, status, solver=eigen_solver%dense)
      call system_clock(c1)
      write(*, '("| ", i0, " | ", f8.3, " |")') c%n_dof, real(c1 - c0, dp)/real(rate, dp)
    end do
  end subroutine eigen_times

  subroutine bound_times()
    integer, parameter :: counts(4) = [1000, 10000, 100000, 1000000]
    type(scene_type) :: scene
    type(critical_step_type) :: c
    type(demstep_status_type) :: status
    integer(8) :: c0, c1, rate
    integer :: i
    write(*, '(a)') "", "Gershgorin bound and per-contact rule (no eigen analysis), one run each:"
    write(*, '(a)') "| springs | seconds | ns per spring |", "|---:|---:|---:|"
    do i = 1, size(counts)
      call lattice(counts(i)/3, scene)
      call system_clock(c0, rate)
      call assembly_critical_steps(scene, c, status, solver=eigen_solver%none)
      call system_clock(c1)
      write(*, '("| ", i0, " | ", f8.4, " | ", f8.1, " |")') c%n_springs, real(c1 - c0, dp)/real(rate, dp), &
        real(c1 - c0, dp)/real(rate, dp)*1.0e9_dp/c%n_springs
    end do
  end subroutine bound_times

end program bench_scene
