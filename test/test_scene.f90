!> Tests of scenes and their critical time steps: LAPACK against closed-form
!> spectra, the bound against LAPACK, stability by simulation, and each effect
!> against an analytic or independently computed case.
module test_scene
  use testdrive, only: new_unittest, unittest_type, error_type, check, test_failed
  use demstep
  use demstep_spring, only: restitution_to_damping_ratio
  use demstep_neighbours, only: contact_list, search_type, prepare_search, find_contacts
  use demstep_scene_data, only: n_effects
  use demstep_kinds, only: pi
  use test_support, only: real_str
  implicit none
  private
  public :: collect_scene

  logical, parameter :: no_effects(n_effects) = .false.

  !> Counts what a run tells its progress object.
  type, extends(progress_type) :: counting_progress_type
    integer :: starts = 0, updates = 0, finishes = 0
    integer(i8) :: total = 0, last = 0
    logical :: increasing = .true.
  contains
    procedure :: start => counting_start
    procedure :: update => counting_update
    procedure :: finish => counting_finish
  end type counting_progress_type

contains

  subroutine collect_scene(testsuite)
    type(unittest_type), allocatable, intent(out) :: testsuite(:)
    testsuite = [ &
      new_unittest("omega_max of chains and a ring vs closed forms", test_spectra), &
      new_unittest("the bound is never below the exact omega_max", test_bound_random), &
      new_unittest("stable at 0.99, blows up at 1.01 of the limit", test_stability), &
      new_unittest("the per-contact rule is unsafe on a chain", test_contact_rule_unsafe), &
      new_unittest("gravity: free fall is exact", test_free_fall), &
      new_unittest("damping: lagged dashpot vs its recurrence and the damped limit", test_damped), &
      new_unittest("walls: an undamped bounce is the exact discrete contact", test_wall_bounce), &
      new_unittest("walls + damping: restitution from the damping ratio", test_wall_restitution), &
      new_unittest("local damping removes energy; off, energy is kept", test_local_damping), &
      new_unittest("contacts: a Hertz pair conserves energy, max overlap", test_hertz_pair), &
      new_unittest("bad scenes give a status", test_bad_scenes), &
      new_unittest("contact search with giants equals brute force", test_giants_brute_force), &
      new_unittest("a given contact list: contact_list equals the search, in blocks", test_listed_contacts), &
      new_unittest("coincident particles are refused by number", test_coincident), &
      new_unittest("extreme mass and stiffness: omega_max scaled, vs closed form", test_scaled_eigen), &
      new_unittest("extreme damping ratio: computed to 1e100, refused above", test_extreme_damping), &
      new_unittest("extreme radius, position and mass are refused with the range", test_extreme_geometry), &
      new_unittest("no stiffness: the message names the variable", test_no_stiffness), &
      new_unittest("scene_run reports progress every so often", test_run_progress) &
      ]
  end subroutine collect_scene

  !> A 1D chain of n particles 1 apart (mass m, bonds k), optionally fixed ends
  !> and a closing bond from the last to the first (a ring).
  subroutine chain(scene, n, m, k, fixed_ends, ring)
    type(scene_type), intent(out) :: scene
    integer, intent(in) :: n
    real(dp), intent(in) :: m, k
    logical, intent(in) :: fixed_ends, ring
    real(dp) :: x(1, n), v(1, n)
    logical :: fixed(n)
    integer :: i, pairs(2, n)
    type(demstep_status_type) :: status
    do i = 1, n
      x(1, i) = real(i, dp)
      v(1, i) = 0.01_dp*sin(2.7_dp*i)
    end do
    fixed = .false.
    if (fixed_ends) then
      fixed(1) = .true.
      fixed(n) = .true.
      v(1, 1) = 0.0_dp
      v(1, n) = 0.0_dp
    end if
    call new_scene(scene, 1, x, spread(m, 1, n), spread(0.3_dp, 1, n), status, v=v, fixed=fixed)
    do i = 1, n - 1
      pairs(:, i) = [i, i + 1]
    end do
    pairs(:, n) = [n, 1]
    call scene_add_bonds(scene, pairs(:, :merge(n, n - 1, ring)), status)
    scene%k_bond = k
    scene%effects = no_effects
  end subroutine chain

  !> A 2D square lattice (n x n) with nearest and diagonal bonds, normal and
  !> tangential stiffness, one corner row fixed, random masses.
  subroutine lattice(scene, n)
    type(scene_type), intent(out) :: scene
    integer, intent(in) :: n
    real(dp) :: x(2, n*n), v(2, n*n), m(n*n), u(2)
    logical :: fixed(n*n)
    integer, allocatable :: pairs(:, :)
    integer :: i, j, p
    type(demstep_status_type) :: status
    call seed(5)
    allocate(pairs(2, 0))
    do j = 1, n
      do i = 1, n
        p = i + (j - 1)*n
        x(:, p) = [real(i, dp), real(j, dp)]
        call random_number(u)
        m(p) = 0.5_dp + u(1)
        v(:, p) = 0.01_dp*(u - 0.5_dp)
        if (i < n) pairs = reshape([pairs, p, p + 1], [2, size(pairs, 2) + 1])
        if (j < n) pairs = reshape([pairs, p, p + n], [2, size(pairs, 2) + 1])
        if (i < n .and. j < n) pairs = reshape([pairs, p, p + n + 1], [2, size(pairs, 2) + 1])
      end do
    end do
    fixed = .false.
    fixed(1:n) = .true.
    where (fixed) v(1, :) = 0.0_dp
    where (fixed) v(2, :) = 0.0_dp
    call new_scene(scene, 2, x, m, spread(0.3_dp, 1, n*n), status, v=v, fixed=fixed)
    call scene_add_bonds(scene, pairs, status)
    scene%k_bond = 100.0_dp
    scene%k_bond_tangential = 30.0_dp
    scene%effects = no_effects
  end subroutine lattice

  !> A random 3D packing: n particles in a box, bonds between neighbours closer
  !> than `reach`, random masses and stiffness-free radii (no contacts).
  subroutine packing(scene, n, reach, with_fixed)
    type(scene_type), intent(out) :: scene
    integer, intent(in) :: n
    real(dp), intent(in) :: reach
    logical, intent(in) :: with_fixed
    real(dp) :: x(3, n), v(3, n), m(n), u(3)
    logical :: fixed(n)
    integer, allocatable :: pairs(:, :)
    integer :: i, j
    type(demstep_status_type) :: status
    allocate(pairs(2, 0))
    do i = 1, n
      call random_number(u)
      x(:, i) = 4.0_dp*u
      call random_number(u)
      v(:, i) = 0.01_dp*(u - 0.5_dp)
      m(i) = 0.2_dp + 2.0_dp*u(1)
    end do
    fixed = .false.
    if (with_fixed) fixed(1:3) = .true.
    do i = 1, n
      if (fixed(i)) v(:, i) = 0.0_dp
      do j = i + 1, n
        if (norm2(x(:, i) - x(:, j)) < reach) pairs = reshape([pairs, i, j], [2, size(pairs, 2) + 1])
      end do
    end do
    call new_scene(scene, 3, x, m, spread(1.0e-3_dp, 1, n), status, v=v, fixed=fixed)
    call scene_add_bonds(scene, pairs, status)
    scene%k_bond = 10.0_dp
    scene%k_bond_tangential = 4.0_dp
    scene%effects = no_effects
  end subroutine packing

  subroutine test_spectra(error)
    type(error_type), allocatable, intent(out) :: error
    type(scene_type) :: scene
    type(critical_step_type) :: c
    type(demstep_status_type) :: status
    integer, parameter :: sizes(3) = [5, 24, 61]
    integer :: i, n
    do i = 1, size(sizes)
      n = sizes(i)
      ! fixed ends: n - 2 free masses, omega_k = 2 sqrt(k/m) sin(k pi/(2(n-1)))
      call chain(scene, n, 2.0_dp, 50.0_dp, .true., .false.)
      call assembly_critical_steps(scene, c, status)
      call check(error, status%stat, demstep_stat%ok)
      if (allocated(error)) return
      call check(error, c%omega_max, 10.0_dp*sin((n - 2)*pi/(2.0_dp*(n - 1))), thr=1.0e-13_dp, &
        rel=.true., message="fixed chain of "//real_str(real(n, dp)))
      if (allocated(error)) return
      ! free ends: omega_k = 2 sqrt(k/m) sin(k pi/(2n)), k = 0..n-1
      call chain(scene, n, 2.0_dp, 50.0_dp, .false., .false.)
      call assembly_critical_steps(scene, c, status)
      call check(error, c%omega_max, 10.0_dp*sin((n - 1)*pi/(2.0_dp*n)), thr=1.0e-13_dp, &
        rel=.true., message="free chain of "//real_str(real(n, dp)))
      if (allocated(error)) return
      ! ring: omega_k = 2 sqrt(k/m) |sin(pi k/n)|
      call chain(scene, n, 2.0_dp, 50.0_dp, .false., .true.)
      call assembly_critical_steps(scene, c, status)
      call check(error, c%omega_max, 10.0_dp*sin(pi*(n/2)/real(n, dp)), thr=1.0e-13_dp, &
        rel=.true., message="ring of "//real_str(real(n, dp)))
      if (allocated(error)) return
    end do
  end subroutine test_spectra

  subroutine test_bound_random(error)
    type(error_type), allocatable, intent(out) :: error
    type(scene_type) :: scene
    type(critical_step_type) :: c
    type(demstep_status_type) :: status
    integer :: trial
    call seed(9)
    do trial = 1, 40
      call packing(scene, 10 + trial, 1.2_dp + 0.02_dp*trial, mod(trial, 2) == 0)
      if (size(scene%bonds, 2) == 0) cycle
      call assembly_critical_steps(scene, c, status)
      if (status%stat /= demstep_stat%ok) cycle
      ! LAPACK's eigenvalue is accurate to a few ulps of the matrix norm
      call check(error, c%omega_bound >= c%omega_max*(1.0_dp - 1.0e-13_dp), "bound "// &
        real_str(c%omega_bound)//" below exact "//real_str(c%omega_max))
      if (allocated(error)) return
      call check(error, c%dt_critical_bound <= c%dt_critical_eigen*(1.0_dp + 1.0e-13_dp), "dt bound safe")
      if (allocated(error)) return
    end do
  end subroutine test_bound_random

  subroutine test_stability(error)
    type(error_type), allocatable, intent(out) :: error
    type(scene_type) :: scene, start
    type(critical_step_type) :: c
    type(scene_summary_type) :: summary
    type(demstep_status_type) :: status
    integer :: which
    call seed(21)
    do which = 1, 3
      select case (which)
      case (1)
        call chain(start, 30, 1.0_dp, 1.0_dp, .true., .false.)
      case (2)
        call lattice(start, 5)
      case (3)
        call packing(start, 25, 1.5_dp, .true.)
      end select
      call assembly_critical_steps(start, c, status)
      call check(error, status%stat, demstep_stat%ok)
      if (allocated(error)) return
      scene = start
      call scene_run(scene, 0.99_dp*c%dt_critical_eigen, 100000_i8, summary, status)
      ! the leapfrog energy of an undamped linear system is conserved to rounding
      call check(error, .not. summary%blew_up .and. summary%energy_drift < 1.0e-6_dp, &
        "bounded at 0.99 (scene "//real_str(real(which, dp))//"), drift "//real_str(summary%energy_drift))
      if (allocated(error)) return
      scene = start
      call scene_run(scene, 1.01_dp*c%dt_critical_eigen, 100000_i8, summary, status)
      call check(error, summary%blew_up .and. status%stat == demstep_stat%blow_up, &
        "grows at 1.01 (scene "//real_str(real(which, dp))//")")
      if (allocated(error)) return
    end do
  end subroutine test_stability

  subroutine test_contact_rule_unsafe(error)
    type(error_type), allocatable, intent(out) :: error
    type(scene_type) :: scene
    type(critical_step_type) :: c
    type(scene_summary_type) :: summary
    type(demstep_status_type) :: status
    call chain(scene, 30, 1.0_dp, 1.0_dp, .true., .false.)
    call assembly_critical_steps(scene, c, status)
    ! 2 sqrt(m*/k) with m* = m/2 is sqrt(2) while the chain's limit tends to 1
    call check(error, c%dt_contact_rule, sqrt(2.0_dp), thr=1.0e-14_dp, rel=.true., message="rule")
    if (allocated(error)) return
    call check(error, c%dt_contact_rule > c%dt_critical_eigen, "the rule exceeds the true limit")
    if (allocated(error)) return
    call scene_run(scene, c%dt_contact_rule, 100000_i8, summary, status)
    call check(error, summary%blew_up, "a run at the per-contact rule blows up")
  end subroutine test_contact_rule_unsafe

  subroutine test_free_fall(error)
    type(error_type), allocatable, intent(out) :: error
    type(scene_type) :: scene
    type(scene_summary_type) :: summary
    type(demstep_status_type) :: status
    real(dp) :: dt, t, g(3), x0(3), v0(3)
    dt = 1.0e-3_dp
    g = [0.5_dp, 0.0_dp, -9.81_dp]
    x0 = [1.0_dp, 2.0_dp, 30.0_dp]
    v0 = [0.3_dp, -0.2_dp, 1.0_dp]
    ! the half-step velocity v(dt/2) makes leapfrog exact for a constant force
    call new_scene(scene, 3, reshape(x0, [3, 1]), [2.0_dp], [0.1_dp], status, &
      v=reshape(v0 + 0.5_dp*g*dt, [3, 1]))
    scene%effects = no_effects
    scene%effects(scene_effect%gravity) = .true.
    scene%gravity = g
    call scene_run(scene, dt, 2000_i8, summary, status)
    t = 2000*dt
    call check(error, norm2(scene%x(:, 1) - (x0 + v0*t + 0.5_dp*g*t**2)) < 1.0e-11_dp*norm2(x0), &
      "position after 2 s of free fall")
    if (allocated(error)) return
    ! gravitational + kinetic energy is kept
    call check(error, summary%energy_drift < 1.0e-12_dp, "energy drift "//real_str(summary%energy_drift))
  end subroutine test_free_fall

  subroutine test_damped(error)
    type(error_type), allocatable, intent(out) :: error
    type(scene_type) :: scene
    type(critical_step_type) :: c
    type(scene_summary_type) :: summary
    type(demstep_status_type) :: status
    real(dp) :: dt, h, zeta, xm, x, xp, omega
    integer :: n
    ! one particle (m = 1) on a bond (k = 4) to a fixed particle, zeta = 0.1
    call new_scene(scene, 1, reshape([0.0_dp, 1.0_dp], [1, 2]), [1.0_dp, 1.0_dp], [0.1_dp, 0.1_dp], &
      status, v=reshape([0.0_dp, 0.5_dp], [1, 2]), fixed=[.true., .false.])
    call scene_add_bonds(scene, reshape([1, 2], [2, 1]), status)
    scene%k_bond = 4.0_dp
    scene%effects = no_effects
    scene%effects(scene_effect%damping) = .true.
    zeta = 0.1_dp
    scene%damping_ratio = zeta
    omega = 2.0_dp
    dt = 0.05_dp
    call scene_run(scene, dt, 400_i8, summary, status)
    ! independent reference: the lagged-dashpot recurrence of the displacement
    ! x_{n+1} - x_n = (1 - 2 zeta h)(x_n - x_{n-1}) - h^2 x_n, h = omega dt
    h = omega*dt
    xm = 0.0_dp
    x = 0.5_dp*dt
    do n = 1, 399
      xp = x + (1.0_dp - 2.0_dp*zeta*h)*(x - xm) - h**2*x
      xm = x
      x = xp
    end do
    call check(error, scene%x(1, 2) - 1.0_dp, x, thr=1.0e-12_dp, message="displacement after 400 steps")
    if (allocated(error)) return
    ! the damped limit of this single mode: (2/omega)(sqrt(1 + zeta^2) - zeta)
    call assembly_critical_steps(scene, c, status)
    call check(error, c%damping_ratio_top, zeta, thr=1.0e-13_dp, rel=.true., message="modal zeta")
    if (allocated(error)) return
    call check(error, c%dt_critical_damped, (sqrt(1.0_dp + zeta**2) - zeta), thr=1.0e-13_dp, &
      rel=.true., message="damped limit")
  end subroutine test_damped

  subroutine test_wall_bounce(error)
    type(error_type), allocatable, intent(out) :: error
    type(scene_type) :: scene
    type(scene_summary_type) :: summary
    type(discrete_contact_type) :: exact
    type(demstep_status_type) :: status
    real(dp) :: dt, omega
    integer :: i
    real(dp), parameter :: ns(4) = [4.0_dp, 7.3_dp, 20.0_dp, 333.0_dp]
    do i = 1, size(ns)
      ! a sphere (r = 0.5) touching the wall x = 0 at step 0, moving in at 1
      call new_scene(scene, 1, reshape([0.5_dp], [1, 1]), [2.0_dp], [0.5_dp], status, &
        v=reshape([-1.0_dp], [1, 1]))
      call scene_add_walls(scene, reshape([0.0_dp], [1, 1]), reshape([1.0_dp], [1, 1]), status)
      scene%effects = no_effects
      scene%effects(scene_effect%walls) = .true.
      scene%k_normal = 800.0_dp
      omega = 20.0_dp
      dt = 2.0_dp*pi/(omega*ns(i))
      call scene_run(scene, dt, int(ns(i), i8) + 2_i8, summary, status)
      call contact_with_onset(2.0_dp*pi/(omega*dt), 1.0_dp, exact, status)
      call check(error, scene%v(1, 1), exact%restitution, thr=1.0e-12_dp, rel=.true., &
        message="rebound at N = "//real_str(ns(i)))
      if (allocated(error)) return
      call check(error, summary%max_overlap, exact%max_overlap/omega, thr=1.0e-12_dp, rel=.true., &
        message="max overlap at N = "//real_str(ns(i)))
      if (allocated(error)) return
    end do
  end subroutine test_wall_bounce

  subroutine test_wall_restitution(error)
    type(error_type), allocatable, intent(out) :: error
    type(scene_type) :: scene
    type(scene_summary_type) :: summary
    type(demstep_status_type) :: status
    real(dp) :: e_target, dt
    e_target = 0.5_dp
    call new_scene(scene, 2, reshape([0.0_dp, 0.5_dp], [2, 1]), [2.0_dp], [0.5_dp], status, &
      v=reshape([0.0_dp, -1.0_dp], [2, 1]))
    call scene_add_walls(scene, reshape([0.0_dp, 0.0_dp], [2, 1]), reshape([0.0_dp, 2.0_dp], [2, 1]), status)
    scene%effects = no_effects
    scene%effects(scene_effect%walls) = .true.
    scene%effects(scene_effect%damping) = .true.
    scene%k_normal = 800.0_dp
    scene%damping_ratio = restitution_to_damping_ratio(e_target)
    ! 1000 steps per period: the continuous restitution to about 1 %
    dt = 2.0_dp*pi/(20.0_dp*1000.0_dp)
    call scene_run(scene, dt, 1000_i8, summary, status)
    call check(error, scene%v(2, 1), e_target, thr=1.0e-2_dp, rel=.true., message="restitution")
  end subroutine test_wall_restitution

  subroutine test_local_damping(error)
    type(error_type), allocatable, intent(out) :: error
    type(scene_type) :: scene, start
    type(scene_summary_type) :: summary
    type(demstep_status_type) :: status
    integer :: k
    call chain(start, 8, 1.0_dp, 1.0_dp, .true., .false.)
    scene = start
    call scene_run(scene, 0.1_dp, 5000_i8, summary, status, sample_every=100_i8)
    ! rounding only: about n eps over n = 5000 steps
    call check(error, summary%energy_drift < 1.0e-10_dp, "undamped chain keeps its energy")
    if (allocated(error)) return
    scene = start
    scene%effects(scene_effect%local_damping) = .true.
    scene%local_damping = 0.1_dp
    call scene_run(scene, 0.1_dp, 5000_i8, summary, status, sample_every=100_i8)
    do k = 2, size(summary%sample_energy)
      ! never grows, but for rounding relative to the initial energy
      call check(error, summary%sample_energy(k) <= summary%sample_energy(k - 1) &
        + 1.0e-12_dp*summary%energy_initial, "energy never grows under local damping")
      if (allocated(error)) return
    end do
    call check(error, summary%energy_final < 0.1_dp*summary%energy_initial, "most energy removed")
  end subroutine test_local_damping

  subroutine test_hertz_pair(error)
    type(error_type), allocatable, intent(out) :: error
    type(scene_type) :: scene
    type(scene_summary_type) :: summary
    type(demstep_status_type) :: status
    real(dp) :: m_eff, rs, v, d_max
    ! two equal spheres approaching head-on, Hertz law
    call new_scene(scene, 3, reshape([0.0_dp, 0.0_dp, 0.0_dp, 2.0e-3_dp, 0.0_dp, 0.0_dp], [3, 2]), &
      [1.0e-3_dp, 1.0e-3_dp], [1.0e-3_dp, 1.0e-3_dp], status, &
      v=reshape([0.5_dp, 0.0_dp, 0.0_dp, -0.5_dp, 0.0_dp, 0.0_dp], [3, 2]))
    scene%law = contact_law%hertz
    scene%e_star = 1.0e8_dp
    scene%effects = no_effects
    scene%effects(scene_effect%contacts) = .true.
    call scene_run(scene, 1.0e-8_dp, 20000_i8, summary, status, sample_every=10_i8)
    ! energy is kept to O(dt^2) and the largest overlap is Hertz's
    ! d = (15 m* v^2/(16 E* sqrt(R*)))^(2/5), v the approach speed
    m_eff = 0.5e-3_dp
    rs = 0.5e-3_dp
    v = 1.0_dp
    d_max = (15.0_dp*m_eff*v**2/(16.0_dp*scene%e_star*sqrt(rs)))**0.4_dp
    call check(error, summary%energy_drift < 1.0e-4_dp, "energy drift "//real_str(summary%energy_drift))
    if (allocated(error)) return
    call check(error, summary%max_overlap, d_max, thr=1.0e-3_dp, rel=.true., message="max overlap")
    if (allocated(error)) return
    call check(error, scene%v(1, 1) < 0.0_dp .and. scene%v(1, 2) > 0.0_dp, "the spheres rebound")
  end subroutine test_hertz_pair

  subroutine test_bad_scenes(error)
    type(error_type), allocatable, intent(out) :: error
    type(scene_type) :: scene
    type(critical_step_type) :: c
    type(demstep_status_type) :: status
    call new_scene(scene, 1, reshape([0.0_dp, 1.0_dp], [1, 2]), [1.0_dp, -1.0_dp], [0.1_dp, 0.1_dp], status)
    call check(error, status%stat == demstep_stat%invalid_input .and. index(status%message, "mass") > 0, &
      "negative mass")
    if (allocated(error)) return
    call new_scene(scene, 1, reshape([0.0_dp, 1.0_dp], [1, 2]), [1.0_dp, 1.0_dp], [0.1_dp, -0.1_dp], status)
    call check(error, status%stat == demstep_stat%invalid_input .and. index(status%message, "radius") > 0, &
      "negative radius")
    if (allocated(error)) return
    call new_scene(scene, 1, reshape([0.0_dp, 0.5_dp], [1, 2]), [1.0_dp, 1.0_dp], [0.3_dp, 0.3_dp], status, &
      fixed=[.true., .true.])
    call check(error, status%stat == demstep_stat%invalid_input .and. index(status%message, "overlap") > 0, &
      "overlapping fixed particles")
    if (allocated(error)) return
    call new_scene(scene, 1, reshape([0.0_dp, 1.0_dp], [1, 2]), [1.0_dp, 1.0_dp], [0.1_dp, 0.1_dp], status)
    call scene_add_bonds(scene, reshape([1, 3], [2, 1]), status)
    call check(error, status%stat == demstep_stat%invalid_input .and. index(status%message, "missing") > 0, &
      "a bond to a missing particle")
    if (allocated(error)) return
    scene%effects = no_effects
    call assembly_critical_steps(scene, c, status)
    call check(error, status%stat, demstep_stat%invalid_input, message="no stiffness")
  end subroutine test_bad_scenes

  !> A polydisperse 2D cloud with a few giants: the contact list equals the
  !> pairs found by checking every pair.
  subroutine test_giants_brute_force(error)
    type(error_type), allocatable, intent(out) :: error
    integer, parameter :: n = 1500
    type(scene_type) :: scene
    type(demstep_status_type) :: status
    real(dp) :: x(2, n), r(n), u(2)
    integer, allocatable :: ci(:), cj(:)
    real(dp), allocatable :: cn(:, :), cd(:)
    logical, allocatable :: found(:, :)
    integer :: i, j, k, brute
    call seed(11)
    do i = 1, n
      call random_number(u)
      x(:, i) = 60.0_dp*u
      r(i) = 0.3_dp + 0.4_dp*u(1)
    end do
    ! giants of radius 5 to 12 (more than twice the 17th largest): searched apart
    r(1:10) = [(5.0_dp + 0.7_dp*k, k = 1, 10)]
    call new_scene(scene, 2, x, spread(1.0_dp, 1, n), r, status)
    call check(error, status%stat, demstep_stat%ok, message="new_scene: "//status%message)
    if (allocated(error)) return
    call contact_list(scene, ci, cj, cn, cd, status)
    call check(error, status%stat, demstep_stat%ok, message="contact_list")
    if (allocated(error)) return
    allocate(found(n, n), source=.false.)
    do k = 1, size(ci)
      call check(error, ci(k) < cj(k) .and. .not. found(ci(k), cj(k)), "pairs ordered and unique")
      if (allocated(error)) return
      found(ci(k), cj(k)) = .true.
      ! overlap as computed from the positions (1e-12: a few roundings of O(10))
      call check(error, cd(k), r(ci(k)) + r(cj(k)) - norm2(x(:, cj(k)) - x(:, ci(k))), thr=1.0e-12_dp)
      if (allocated(error)) return
    end do
    brute = 0
    do i = 1, n
      do j = i + 1, n
        if (norm2(x(:, j) - x(:, i)) < r(i) + r(j)) then
          brute = brute + 1
          call check(error, found(i, j), "pair "//real_str(real(i, dp))//", "//real_str(real(j, dp))//" found")
          if (allocated(error)) return
        end if
      end do
    end do
    call check(error, size(ci), brute, message="number of contacts")
    if (allocated(error)) return
    ! the giants do touch many particles: the test exercises their search
    call check(error, count(ci <= 10 .or. cj <= 10) > 100, "giants have contacts")
  end subroutine test_giants_brute_force

  !> A given contact list of 100 000 rows (several of `contact_list`'s
  !> parallel blocks; about one row in fifteen overlaps, through the periodic
  !> images) with a pair at the same point listed twice: `contact_list` gives
  !> the same rows, normals and overlaps, bit for bit, as the stepper's
  !> search row by row (`find_contacts`), without the coincident rows, and
  !> refuses the first coincident pair of the list by number.
  subroutine test_listed_contacts(error)
    type(error_type), allocatable, intent(out) :: error
    integer, parameter :: n = 2000, rows = 100000
    type(scene_type) :: scene
    type(search_type) :: s
    type(demstep_status_type) :: status
    real(dp) :: x(3, n), r(n), u(2)
    integer :: pairs(2, rows), k, m
    integer, allocatable :: ci(:), cj(:), cc(:)
    real(dp), allocatable :: cn(:, :), cd(:)
    call seed(5)
    call random_number(x)
    x = 6.0_dp*x
    call random_number(r)
    r = 0.5_dp + 0.5_dp*r
    x(:, 1500) = x(:, 17)
    do k = 1, rows
      call random_number(u)
      pairs(1, k) = 1 + int(u(1)*n)
      pairs(2, k) = 1 + modulo(pairs(1, k) + int(u(2)*(n - 1)), n)
    end do
    pairs(:, 80000) = [17, 1500]
    pairs(:, 90000) = [1500, 17]
    call new_scene(scene, 3, x, spread(1.0_dp, 1, n), r, status, search=.false.)
    if (status%stat == demstep_stat%ok) call scene_set_cell(scene, [.true., .true., .true.], &
      [0.0_dp, 0.0_dp, 0.0_dp], [6.0_dp, 6.0_dp, 6.0_dp], status, search=.false.)
    if (status%stat == demstep_stat%ok) call scene_set_contacts(scene, pairs, &
      reshape(spread(1.0_dp, 1, 2*rows), [2, rows]), status)
    call check(error, status%stat, demstep_stat%ok, message="scene: "//status%message)
    if (allocated(error)) return
    call contact_list(scene, ci, cj, cn, cd, status, cc)
    call check(error, status%stat, demstep_stat%invalid_input, message="the coincident pair is refused")
    if (allocated(error)) return
    call check(error, index(status%message, "particles 17 and 1500 are at the same point") > 0, &
      "message: "//status%message)
    if (allocated(error)) return
    call prepare_search(scene, s)
    call find_contacts(scene, s)
    m = s%n_pairs
    call check(error, size(ci), m, message="contacts")
    if (allocated(error)) return
    call check(error, m > rows/50 .and. m < rows - 2, "some rows overlap, some do not: "//real_str(real(m, dp)))
    if (allocated(error)) return
    call check(error, all(ci == s%pair_i(:m)) .and. all(cj == s%pair_j(:m)) .and. all(cc == s%pair_c(:m)), &
      "the same rows")
    if (allocated(error)) return
    call check(error, all(cn == s%pair_n(:, :m)) .and. all(cd == s%pair_d(:m)), "the same normals and overlaps")
    if (allocated(error)) return
    call check(error, s%coincident(1) == 17 .and. s%coincident(2) == 1500, "the search's first coincident pair")
    if (allocated(error)) return
    call check(error, .not. any(cc == 80000 .or. cc == 90000), "coincident rows are not contacts")
    if (allocated(error)) return
    ! the rows are checked in parallel: the first faulty row in list order is refused
    pairs(:, 95000) = [3, n + 1]
    call scene_set_contacts(scene, pairs, reshape([(real(1 - 2*merge(1, 0, k == 2*70000 - 1), dp), &
      k = 1, 2*rows)], [2, rows]), status)
    call check(error, status%stat == demstep_stat%invalid_input .and. status%where == "contacts" .and. &
      status%index == 70000 .and. index(status%message, "k_n") > 0, "the first faulty row: "//status%message)
    if (allocated(error)) return
    ! and the first faulty particle
    r(1900) = -1.0_dp
    x(2, 1950) = huge(1.0_dp)
    call new_scene(scene, 3, x, spread(1.0_dp, 1, n), r, status, search=.false.)
    call check(error, status%stat == demstep_stat%invalid_input .and. status%where == "radius" .and. &
      status%index == 1900, "the first faulty particle: "//status%message)
  end subroutine test_listed_contacts

  !> 1000 particles at one point: refused at once, naming two of them.
  subroutine test_coincident(error)
    type(error_type), allocatable, intent(out) :: error
    type(scene_type) :: scene
    type(demstep_status_type) :: status
    real(dp), allocatable :: x(:, :)
    integer :: k
    allocate(x(3, 1000), source=0.0_dp)
    call new_scene(scene, 3, x, spread(1.0_dp, 1, 1000), spread(0.5_dp, 1, 1000), status)
    call check(error, status%stat, demstep_stat%invalid_input, message="coincident")
    if (allocated(error)) return
    call check(error, index(status%message, "position: particles 1 and 2 are at the same point") == 1, &
      "message: "//status%message)
    if (allocated(error)) return
    ! one coincident pair among separated particles
    x = reshape([(real(modulo(k, 1000), dp), k = 0, 2999)], [3, 1000])
    x(:, 7) = x(:, 500)
    call new_scene(scene, 3, x, spread(1.0_dp, 1, 1000), spread(0.1_dp, 1, 1000), status)
    call check(error, index(status%message, "particles 7 and 500 are at the same point") > 0, &
      "message: "//status%message)
  end subroutine test_coincident

  !> Two free particles on a bond: omega_max = sqrt(2 k/m) exactly. At m = 1e-308
  !> or k = 1e308 the unscaled k/m overflows; the scaled problem gives the closed
  !> form to a few roundings (1e-13 relative), and the other estimates stay
  !> finite: the per-contact rule 2 sqrt(m*/k) and the bound (the pair's
  !> Gershgorin bound is exact, 2k/m per row).
  subroutine test_scaled_eigen(error)
    type(error_type), allocatable, intent(out) :: error
    real(dp), parameter :: masses(3) = [1.0e-308_dp, 1.0_dp, 1.0e-308_dp], &
      stiffness(3) = [1.0e4_dp, 1.0e308_dp, 1.0e308_dp]
    type(scene_type) :: scene
    type(critical_step_type) :: c
    type(demstep_status_type) :: status
    real(dp) :: omega
    integer :: k
    do k = 1, 3
      call new_scene(scene, 1, reshape([0.0_dp, 1.0_dp], [1, 2]), [masses(k), masses(k)], &
        [0.1_dp, 0.1_dp], status)
      call scene_add_bonds(scene, reshape([1, 2], [2, 1]), status)
      scene%k_bond = stiffness(k)
      scene%effects = no_effects
      call assembly_critical_steps(scene, c, status)
      call check(error, status%stat, demstep_stat%ok, message="case "//real_str(real(k, dp))//": "// &
        status%message)
      if (allocated(error)) return
      omega = sqrt(2.0_dp)*(sqrt(stiffness(k))/sqrt(masses(k)))
      call check(error, c%omega_max, omega, thr=1.0e-13_dp, rel=.true., message="omega_max")
      if (allocated(error)) return
      call check(error, c%dt_critical_eigen, 2.0_dp/omega, thr=1.0e-13_dp, rel=.true., message="dt")
      if (allocated(error)) return
      call check(error, c%dt_critical_bound, 2.0_dp/omega, thr=1.0e-13_dp, rel=.true., message="bound")
      if (allocated(error)) return
      call check(error, c%dt_contact_rule, 2.0_dp*sqrt(0.5_dp*masses(k))/sqrt(stiffness(k)), &
        thr=1.0e-13_dp, rel=.true., message="contact rule")
      if (allocated(error)) return
    end do
  end subroutine test_scaled_eigen

  !> One spring, one dashpot: the top mode's damping ratio is the dashpot's own,
  !> and the damped limit (2/omega)/(sqrt(1 + z^2) + z) is 1/(omega z) to 1e-200
  !> relative at z = 1e100 (1e-13: roundings). Above 1e100: refused by name.
  subroutine test_extreme_damping(error)
    type(error_type), allocatable, intent(out) :: error
    type(scene_type) :: scene
    type(critical_step_type) :: c
    type(scene_summary_type) :: summary
    type(demstep_status_type) :: status
    call new_scene(scene, 1, reshape([0.0_dp, 1.0_dp], [1, 2]), [1.0_dp, 1.0_dp], [0.1_dp, 0.1_dp], &
      status, fixed=[.true., .false.])
    call scene_add_bonds(scene, reshape([1, 2], [2, 1]), status)
    scene%k_bond = 4.0_dp
    scene%effects = no_effects
    scene%effects(scene_effect%damping) = .true.
    scene%damping_ratio = 1.0e100_dp
    call assembly_critical_steps(scene, c, status)
    call check(error, status%stat, demstep_stat%ok, message=status%message)
    if (allocated(error)) return
    call check(error, c%damping_ratio_top, 1.0e100_dp, thr=1.0e-13_dp, rel=.true., message="modal zeta")
    if (allocated(error)) return
    ! omega = 2: the limit is 1/(2 z)
    call check(error, c%dt_critical_damped, 0.5e-100_dp, thr=1.0e-13_dp, rel=.true., message="damped")
    if (allocated(error)) return
    scene%damping_ratio = 1.0e308_dp
    call assembly_critical_steps(scene, c, status)
    call check(error, status%stat == demstep_stat%invalid_input .and. &
      index(status%message, "damping_ratio: must be in [0, 1e100]") == 1, "refused: "//status%message)
    if (allocated(error)) return
    call scene_run(scene, 0.01_dp, 10_i8, summary, status)
    call check(error, status%stat == demstep_stat%invalid_input .and. &
      index(status%message, "damping_ratio:") == 1, "run refused: "//status%message)
  end subroutine test_extreme_damping

  !> radius 1e308 (whose overlaps overflow), coordinates beyond 1e150 and a mass
  !> whose inverse overflows are refused, naming the variable and the range.
  subroutine test_extreme_geometry(error)
    type(error_type), allocatable, intent(out) :: error
    type(scene_type) :: scene
    type(demstep_status_type) :: status
    call new_scene(scene, 1, reshape([0.0_dp, 1.0_dp], [1, 2]), [1.0_dp, 1.0_dp], [1.0e308_dp, 1.0_dp], status)
    call check(error, index(status%message, "radius: particle 1: must be at most 1e150") == 1, &
      "radius: "//status%message)
    if (allocated(error)) return
    call new_scene(scene, 1, reshape([0.0_dp, 1.0e200_dp], [1, 2]), [1.0_dp, 1.0_dp], [1.0_dp, 1.0_dp], status)
    call check(error, index(status%message, "position: particle 2: every coordinate must be within +-1e150") &
      == 1, "position: "//status%message)
    if (allocated(error)) return
    call new_scene(scene, 1, reshape([0.0_dp, 1.0_dp], [1, 2]), [1.0e-310_dp, 1.0_dp], [0.1_dp, 0.1_dp], status)
    call check(error, index(status%message, "mass: particle 1: must be at least 5.6e-309") == 1, &
      "mass: "//status%message)
    if (allocated(error)) return
    ! at the edge of the range the overlap is finite
    call new_scene(scene, 1, reshape([0.0_dp, 1.0_dp], [1, 2]), [1.0_dp, 1.0_dp], [1.0e150_dp, 1.0e150_dp], &
      status)
    call check(error, status%stat, demstep_stat%ok, message="radius 1e150: "//status%message)
  end subroutine test_extreme_geometry

  !> "The scene has no stiffness" says which variable to change.
  subroutine test_no_stiffness(error)
    type(error_type), allocatable, intent(out) :: error
    type(scene_type) :: scene
    type(critical_step_type) :: c
    type(demstep_status_type) :: status
    real(dp), parameter :: x(1, 2) = reshape([0.0_dp, 3.0_dp], [1, 2])
    call new_scene(scene, 1, x, [1.0_dp, 1.0_dp], [1.0_dp, 1.0_dp], status, fixed=[.true., .true.])
    scene%k_normal = 1.0_dp
    call assembly_critical_steps(scene, c, status)
    call check(error, index(status%message, "fixed: every particle is fixed") == 1, "all fixed: "//status%message)
    if (allocated(error)) return
    call new_scene(scene, 1, x, [1.0_dp, 1.0_dp], [1.0_dp, 1.0_dp], status)
    scene%effects = no_effects
    call assembly_critical_steps(scene, c, status)
    call check(error, index(status%message, "effects: the scene has no stiffness") == 1, &
      "no effects: "//status%message)
    if (allocated(error)) return
    scene%effects(scene_effect%contacts) = .true.
    scene%k_normal = 1.0_dp
    call assembly_critical_steps(scene, c, status)
    call check(error, index(status%message, "position: the scene has no stiffness") == 1, &
      "apart: "//status%message)
  end subroutine test_no_stiffness

  !> A run tells its progress object the total once, then the steps done every
  !> 1e5 particle-steps or so (not every step), increasing, then that it ended.
  subroutine test_run_progress(error)
    type(error_type), allocatable, intent(out) :: error
    type(scene_type) :: scene
    type(scene_summary_type) :: summary
    type(demstep_status_type) :: status
    type(counting_progress_type) :: progress
    call new_scene(scene, 1, reshape([0.0_dp, 1.0_dp], [1, 2]), [1.0_dp, 1.0_dp], [0.1_dp, 0.1_dp], &
      status, v=reshape([0.0_dp, 0.01_dp], [1, 2]))
    call scene_add_bonds(scene, reshape([1, 2], [2, 1]), status)
    scene%k_bond = 1.0_dp
    scene%effects = no_effects
    call scene_run(scene, 0.01_dp, 200000_i8, summary, status, progress=progress)
    call check(error, status%stat, demstep_stat%ok, message=status%message)
    if (allocated(error)) return
    call check(error, progress%starts == 1 .and. progress%finishes == 1 .and. progress%total == 200000_i8, &
      "one start with the total, one finish")
    if (allocated(error)) return
    ! 2 particles: an update every 5e4 steps, so 4 of them
    call check(error, progress%updates, 4, message="updates")
    if (allocated(error)) return
    call check(error, progress%increasing .and. progress%last == 200000_i8, "increasing, ends at the total")
  end subroutine test_run_progress

  subroutine counting_start(self, what, total)
    class(counting_progress_type), intent(inout) :: self
    character(len=*), intent(in) :: what
    integer(i8), intent(in) :: total
    if (what /= "steps") self%increasing = .false.
    self%starts = self%starts + 1
    self%total = total
  end subroutine counting_start

  subroutine counting_update(self, done)
    class(counting_progress_type), intent(inout) :: self
    integer(i8), intent(in) :: done
    self%updates = self%updates + 1
    if (done <= self%last .or. done > self%total) self%increasing = .false.
    self%last = done
  end subroutine counting_update

  subroutine counting_finish(self)
    class(counting_progress_type), intent(inout) :: self
    self%finishes = self%finishes + 1
  end subroutine counting_finish

  subroutine seed(k)
    integer, intent(in) :: k
    integer :: n, i
    call random_seed(size=n)
    call random_seed(put=[(1000*k + 31*i, i = 1, n)])
  end subroutine seed

end module test_scene
