!> Tests of rigid bodies (clumps): a dumbbell on a spring against its closed
!> form, one-member bodies against the sphere path, the stepper's clump
!> forces by finite differences against the operator, random clump packings
!> against a dense reference assembled here independently (its own contact
!> search, tangent blocks written out, body mass and inertia summed, the
!> generalised eigenproblem by Cholesky), Lanczos against dense, Yade's
!> GlobalStiffnessTimeStepper rule and exaDEM's on a rod, and bad input refused
!> by name.
module test_bodies
  use testdrive, only: new_unittest, unittest_type, error_type, check, test_failed
  use demstep
  use demstep_assembly, only: critical_step_type, safe_basis
  use demstep_lanczos, only: lanczos_tolerance_default, certificate_failure, certificate_margin
  use demstep_bodies, only: body_set_type, bodies_from_members, bodies_from_lists, bodies_given
  use demstep_body_assembly, only: body_critical_steps, body_operator, body_operator_type, body_matrix, &
    body_operator_apply, body_gst_step, body_exadem_step, inverse_sqrt_inertia, yade_gst_factor
  use demstep_kinds, only: pi, i8
  use demstep_interaction, only: cross
  use demstep_assembly, only: spring_block_type
  use demstep_csr, only: csr_matrix_type, csr_to_dense
  use demstep_lapack, only: symmetric_eigensystem
  use demstep_scene_builders, only: scene_set_effects, scene_add_bonds, scene_set_bond_stiffness
  use test_support, only: real_str, seed_fixed, run_app, write_file, work_dir, read_group, take
  use demstep_results, only: result_group_type
  use demstep_snapshot, only: snapshot_type, read_snapshot
  use demstep_packing, only: random_clump_packing
  use demstep_sphere_union, only: sphere_union_moments
  implicit none
  private
  public :: collect_bodies

contains

  subroutine collect_bodies(testsuite)
    type(unittest_type), allocatable, intent(out) :: testsuite(:)
    testsuite = [ &
      new_unittest("dumbbell on a spring: closed form, undamped and damped", test_dumbbell), &
      new_unittest("one-member bodies = the sphere path (3D, 2D, no rotation)", test_single_spheres), &
      new_unittest("clump contacts: the stepper's forces by finite differences = the operator", test_tangent_fd), &
      new_unittest("random clump packings = independent dense reference", test_random_clumps), &
      new_unittest("random clump packings = a dense numpy assembly, every eigenvalue", test_numpy_clumps), &
      new_unittest("matrix-free product = compressed rows; J^-1/2 squared = J^-1", test_products), &
      new_unittest("Lanczos = dense on a larger clump packing, undamped and damped", test_lanczos), &
      new_unittest("bodies' Lanczos solves certified: 360 and 1260 dof at the default tolerance", &
        test_certified), &
      new_unittest("Yade GST rule on a 5-sphere rod: its formula; ratio to the exact limit", test_gst_rod), &
      new_unittest("bad input refused by name", test_bad_input), &
      new_unittest("body ids: any positive values, bodies in increasing id, lone particles after", test_ids), &
      new_unittest("Yade text export with clumpId: the bodies; a names line that does not fit", test_yade_clumps), &
      new_unittest("LIGGGHTS multisphere dump (mol, the body's mass): the bodies; members' masses differ", &
        test_liggghts_multisphere), &
      new_unittest("union of member spheres (LIGGGHTS' Monte Carlo template): closed forms", test_union), &
      new_unittest("the stepper with rigid bodies: bounded at 0.99, grows at 1.01 of the limit", test_stepper), &
      new_unittest("the app: &scene bodies_file (and body_density), computed or refused", test_app) &
      ]
  end subroutine collect_bodies

  !> A two-sphere dumbbell (radius 1, mass 1, centres 1.6 apart: the members
  !> overlap) tilted by psi = 0.3 above the horizontal along azimuth 0.7, its
  !> lower sphere on a floor (normal spring k, no tangential spring): one
  !> mode, omega^2 = k (1/M + (L/2)^2 cos^2 psi / J_perp) with M = 2 m,
  !> J_perp = 2 (2/5) m r^2 + 2 m (L/2)^2 (Yade's sum, overlap counted
  !> twice); with a dashpot c = 2 zeta sqrt(m k) on the same contact the
  !> damped limit is (2/omega)(sqrt(1 + z^2) - z), z = c omega/(2 k).
  !> Tolerance 1e-12: dense LAPACK on a 6 x 6 operator of rank 1.
  subroutine test_dumbbell(error)
    type(error_type), allocatable, intent(out) :: error
    type(scene_type) :: scene
    type(body_set_type) :: bodies
    type(critical_step_type) :: c
    type(demstep_status_type) :: status
    real(dp), parameter :: k = 1.0e4_dp, half = 0.8_dp, psi = 0.3_dp, phi = 0.7_dp, zeta = 0.3_dp
    real(dp) :: x(3, 2), e(3), omega2, jperp, omega, z, c_n, dt_d
    real(dp), allocatable :: mass(:), com(:, :), inertia(:, :, :)
    e = [cos(phi)*cos(psi), sin(phi)*cos(psi), sin(psi)]
    x(:, 1) = [0.3_dp, -0.2_dp, 2.0_dp] - half*e
    x(:, 2) = [0.3_dp, -0.2_dp, 2.0_dp] + half*e
    call new_scene(scene, 3, x, [1.0_dp, 1.0_dp], [1.0_dp, 1.0_dp], status)
    call check(error, status%stat, demstep_stat%ok, status%message)
    if (allocated(error)) return
    call scene_set_law(scene, contact_law%linear, k, 0.0_dp, status)
    call scene_set_effects(scene, ["rotation"], [.true.], status)
    ! the floor 1e-3 into the lower sphere
    call scene_add_walls(scene, reshape([0.0_dp, 0.0_dp, x(3, 1) - 0.999_dp], [3, 1]), &
      reshape([0.0_dp, 0.0_dp, 1.0_dp], [3, 1]), status)
    call bodies_from_members(scene, [1, 1], bodies, status)
    call check(error, status%stat, demstep_stat%ok, status%message)
    if (allocated(error)) return
    call check(error, bodies%n, 1)
    if (allocated(error)) return
    jperp = 2.0_dp*0.4_dp + 2.0_dp*half**2
    omega2 = k*(1.0_dp/2.0_dp + half**2*cos(psi)**2/jperp)
    call body_critical_steps(scene, bodies, c, status, solver=eigen_solver%dense)
    call check(error, status%stat, demstep_stat%ok, status%message)
    if (allocated(error)) return
    call check(error, c%n_dof, 6)
    if (allocated(error)) return
    call check(error, c%omega_max**2, omega2, rel=.true., thr=1.0e-12_dp, &
      message="omega^2 "//real_str(c%omega_max**2)//" closed form "//real_str(omega2))
    if (allocated(error)) return
    ! the same body given by its mass, centre and tensor
    mass = bodies%mass
    com = bodies%com
    inertia = bodies%inertia
    call bodies_given(scene, [1, 1], mass, com, inertia, bodies, status)
    call check(error, status%stat, demstep_stat%ok, status%message)
    if (allocated(error)) return
    call body_critical_steps(scene, bodies, c, status, solver=eigen_solver%dense)
    call check(error, c%omega_max**2, omega2, rel=.true., thr=1.0e-12_dp)
    if (allocated(error)) return
    ! damped: the same rank-1 direction
    call scene_set_damping(scene, zeta, status)
    call check(error, status%stat, demstep_stat%ok, status%message)
    if (allocated(error)) return
    call body_critical_steps(scene, bodies, c, status, solver=eigen_solver%dense)
    call check(error, status%stat, demstep_stat%ok, status%message)
    if (allocated(error)) return
    omega = sqrt(omega2)
    c_n = 2.0_dp*zeta*sqrt(1.0_dp*k)
    z = c_n*omega/(2.0_dp*k)
    dt_d = (2.0_dp/omega)*(sqrt(1.0_dp + z**2) - z)
    call check(error, c%damped_exact, .true., "damped limit not exact")
    if (allocated(error)) return
    call check(error, c%dt_critical_damped, dt_d, rel=.true., thr=1.0e-12_dp, &
      message="damped "//real_str(c%dt_critical_damped)//" closed form "//real_str(dt_d))
  end subroutine test_dumbbell

  !> The generalised forces (f, t) on the bodies after one stepper step of
  !> dt = 1 from rest with body velocities q = (v, w) per body: the bodies
  !> move by q, and (v' - v) M, J' (w' - w) (J' the tensor turned with the
  !> body) are the forces at the displaced positions.
  function body_forces(start, start_bodies, q) result(g)
    type(scene_type), intent(in) :: start
    type(body_set_type), intent(in) :: start_bodies
    real(dp), intent(in) :: q(:)
    real(dp) :: g(size(q))
    type(scene_type) :: scene
    type(body_set_type) :: bodies
    type(scene_summary_type) :: summary
    type(demstep_status_type) :: status
    real(dp) :: w(3), v(3)
    integer :: i, b, m
    scene = start
    bodies = start_bodies
    do i = 1, scene%n
      b = bodies%body_of(i)
      scene%v(:, i) = q(6*b - 5:6*b - 3) + cross(q(6*b - 2:6*b), bodies%offset(:, i))
      scene%w(:, i) = q(6*b - 2:6*b)
    end do
    call scene_run(scene, 1.0_dp, 1_i8, summary, status, bodies=bodies)
    if (status%stat /= demstep_stat%ok) error stop "body_forces: "//status%message
    do b = 1, bodies%n
      m = findloc(bodies%body_of, b, 1)
      w = scene%w(:, m)
      v = scene%v(:, m) - cross(w, bodies%offset(:, m))
      g(6*b - 5:6*b - 3) = (v - q(6*b - 5:6*b - 3))*bodies%mass(b)
      g(6*b - 2:6*b) = matmul(bodies%inertia(:, :, b), w - q(6*b - 2:6*b))
    end do
  end function body_forces

  !> Two clumps of two unequal spheres each (random masses and offsets: full,
  !> non-diagonal tensors) touching at a random normal, one also on a floor,
  !> linear law with tangential, rolling and twisting springs: -dF/dq of the
  !> stepper's rigid bodies by central differences (h = 1e-9), mass scaled
  !> (M^-1/2, J^-1/2), equals rate^2 A' of the body operator, 12 x 12, for
  !> three random normals. Tolerance 1e-5 of the largest entry: the contacts
  !> are 1e-7 deep, so their preload adds a geometric stiffness of order
  !> F/r = 1e-7 k_n that the operator leaves out (as documented), and the
  !> positions' rounding (1e-16 of 1) over h gives 1e-7 (measured 9e-8).
  subroutine test_tangent_fd(error)
    type(error_type), allocatable, intent(out) :: error
    real(dp), parameter :: depth = 1.0e-7_dp, h = 1.0e-9_dp
    type(scene_type) :: scene
    type(body_set_type) :: bodies
    type(body_operator_type) :: op
    type(csr_matrix_type) :: sparse
    type(spring_block_type), allocatable :: springs(:)
    type(demstep_status_type) :: status
    real(dp), allocatable :: a(:, :)
    real(dp) :: x(3, 4), r(4), m(4), u(3), e(3), d(3), kfd(12, 12), q(12), wm(12, 12), s(3, 3), rate, err
    integer :: trial, c, b
    call seed_fixed(11)
    do trial = 1, 3
      call random_number(m)
      m = 0.5_dp + m
      r = [1.0_dp, 0.8_dp, 0.9_dp, 0.7_dp]
      ! members 1 (on the floor) and 2 of body 1 along d, the normal e from
      ! member 2 to member 3 (body 2) and member 4 beyond, each direction
      ! near the one before: no other contact (checked below)
      x(:, 1) = [0.1_dp, 0.2_dp, 1.0_dp - depth]
      call random_number(u)
      d = u - 0.5_dp + [0.0_dp, 0.0_dp, 1.0_dp]
      d = d/norm2(d)
      x(:, 2) = x(:, 1) + 0.9_dp*d
      call random_number(u)
      e = d + 0.8_dp*(u - 0.5_dp)
      e = e/norm2(e)
      x(:, 3) = x(:, 2) + (r(2) + r(3) - depth)*e
      call random_number(u)
      d = e + 0.4_dp*(u - 0.5_dp)
      x(:, 4) = x(:, 3) + 0.8_dp*d/norm2(d)
      call new_scene(scene, 3, x, m, r, status)
      call scene_set_law(scene, contact_law%linear, 1.0e3_dp, 400.0_dp, status)
      call scene_set_rolling(scene, 0.1_dp, 0.05_dp, status)
      call scene_add_walls(scene, reshape([0.0_dp, 0.0_dp, 0.0_dp], [3, 1]), &
        reshape([0.0_dp, 0.0_dp, 1.0_dp], [3, 1]), status)
      call bodies_from_members(scene, [1, 1, 2, 2], bodies, status)
      call check(error, status%stat, demstep_stat%ok, status%message)
      if (allocated(error)) return
      call body_operator(scene, bodies, op, rate, status, springs)
      call check(error, status%stat, demstep_stat%ok, status%message)
      if (allocated(error)) return
      ! the contact between the bodies and the one on the floor
      call check(error, op%n == 12 .and. size(springs) == 2, "trial "//real_str(real(trial, dp)) &
        //": springs "//real_str(real(size(springs), dp)))
      if (allocated(error)) return
      do c = 1, 12
        q = 0.0_dp
        q(c) = h
        kfd(:, c) = -(body_forces(scene, bodies, q) - body_forces(scene, bodies, -q))/(2.0_dp*h)
      end do
      wm = 0.0_dp
      do b = 1, 2
        do c = 1, 3
          wm(6*b - 6 + c, 6*b - 6 + c) = 1.0_dp/sqrt(bodies%mass(b))
        end do
        call inverse_sqrt_inertia(bodies%inertia(:, :, b), s, status)
        wm(6*b - 2:6*b, 6*b - 2:6*b) = s
      end do
      kfd = matmul(wm, matmul(kfd, wm))
      call body_matrix(op, sparse)
      call csr_to_dense(sparse, a)
      a = rate**2*a
      err = maxval(abs(kfd - a))/maxval(abs(a))
      call check(error, err < 1.0e-5_dp, "trial "//real_str(real(trial, dp))//": stepper vs operator, " &
        //"relative "//real_str(err))
      if (allocated(error)) return
    end do
  end subroutine test_tangent_fd

  !> n unit spheres along a random walk of 1.8-long steps over a floor,
  !> random masses, linear law with k_t, rolling and twisting, damping.
  subroutine walk(scene, n, seed, dim)
    type(scene_type), intent(out) :: scene
    integer, intent(in) :: n, seed, dim
    real(dp), allocatable :: x(:, :), m(:), r(:)
    real(dp) :: u(3)
    type(demstep_status_type) :: status
    integer :: i
    call seed_fixed(seed)
    allocate(x(3, n), m(n), r(n))
    x(:, 1) = 0.0_dp
    do i = 2, n
      call random_number(u)
      u = u - 0.5_dp
      if (dim == 2) u(3) = 0.0_dp
      x(:, i) = x(:, i - 1) + 1.8_dp*u/norm2(u)
    end do
    call random_number(m)
    m = 0.5_dp + m
    r = 1.0_dp
    call new_scene(scene, dim, x(:dim, :), m, r, status)
    call scene_set_law(scene, contact_law%linear, 1.0e3_dp, 400.0_dp, status)
    call scene_set_rolling(scene, 0.1_dp, 0.05_dp, status)
    call scene_set_damping(scene, 0.1_dp, status, tangential=0.2_dp, rolling=0.1_dp)
    if (dim == 3) then
      call scene_add_walls(scene, reshape([0.0_dp, 0.0_dp, minval(x(3, :)) - 0.9_dp], [3, 1]), &
        reshape([0.0_dp, 0.0_dp, 1.0_dp], [3, 1]), status)
    else
      call scene_add_walls(scene, reshape([0.0_dp, minval(x(2, :)) - 0.9_dp], [2, 1]), &
        reshape([0.0_dp, 1.0_dp], [2, 1]), status)
    end if
  end subroutine walk

  !> Every particle a body of its own: the same limits as
  !> `assembly_critical_steps` (bound, exact, damped, per-contact rule) to
  !> 1e-12 (both dense; the operators differ only by their scaling).
  subroutine test_single_spheres(error)
    type(error_type), allocatable, intent(out) :: error
    type(scene_type) :: scene
    type(body_set_type) :: bodies
    type(critical_step_type) :: c, ref
    type(demstep_status_type) :: status
    integer :: trial, dim
    do trial = 1, 3
      dim = 3
      if (trial == 2) dim = 2
      call walk(scene, 9, trial, dim)
      if (trial == 3) call scene_set_effects(scene, ["rotation"], [.false.], status)
      call bodies_from_members(scene, [(0, dim = 1, scene%n)], bodies, status)
      call check(error, status%stat, demstep_stat%ok, status%message)
      if (allocated(error)) return
      call body_critical_steps(scene, bodies, c, status, solver=eigen_solver%dense)
      call check(error, status%stat, demstep_stat%ok, status%message)
      if (allocated(error)) return
      call assembly_critical_steps(scene, ref, status, solver=eigen_solver%dense)
      call check(error, status%stat, demstep_stat%ok, status%message)
      if (allocated(error)) return
      call check(error, c%n_dof, ref%n_dof)
      if (allocated(error)) return
      call check(error, c%dt_critical_eigen, ref%dt_critical_eigen, rel=.true., thr=1.0e-12_dp, &
        message="trial "//real_str(real(trial, dp))//" eigen "//real_str(c%dt_critical_eigen)//" spheres " &
        //real_str(ref%dt_critical_eigen))
      if (allocated(error)) return
      call check(error, c%dt_critical_bound, ref%dt_critical_bound, rel=.true., thr=1.0e-12_dp, &
        message="bound "//real_str(c%dt_critical_bound)//" spheres "//real_str(ref%dt_critical_bound))
      if (allocated(error)) return
      call check(error, c%dt_critical_damped, ref%dt_critical_damped, rel=.true., thr=1.0e-12_dp, &
        message="damped "//real_str(c%dt_critical_damped)//" spheres "//real_str(ref%dt_critical_damped))
      if (allocated(error)) return
      call check(error, c%dt_contact_rule, ref%dt_contact_rule, rel=.true., thr=1.0e-12_dp)
      if (allocated(error)) return
    end do
  end subroutine test_single_spheres

  !> `random_clump_packing` (nb clumps over a floor, linear law with k_t,
  !> rolling and twisting springs); refused packings fail the test.
  subroutine clump_packing(scene, body_of, nb, seed, gap)
    type(scene_type), intent(out) :: scene
    integer, allocatable, intent(out) :: body_of(:)
    integer, intent(in) :: nb, seed
    real(dp), intent(in) :: gap
    type(demstep_status_type) :: status
    call random_clump_packing(scene, body_of, nb, status, seed=seed, gap=gap)
    if (status%stat /= demstep_stat%ok) error stop "random_clump_packing: "//status%message
  end subroutine clump_packing

  !> The reference: every eigenvalue of L^-1 K_b L^-T (L the Cholesky factor
  !> of the body mass matrix) from this test's own assembly: contacts by
  !> brute force between spheres of different bodies and on the floor; each
  !> contact's 12 x 12 block written out (k_n b_n^T b_n + k_t B_t^T B_t +
  !> D^T (k_r P + k_w n n^T) D, arms r - d/2); carried to the bodies by
  !> [I, -[d]x; 0, I]; mass, centre and inertia summed (Steiner).
  subroutine reference_eigenvalues(scene, body_of, lam)
    type(scene_type), intent(in) :: scene
    integer, intent(in) :: body_of(:)
    real(dp), allocatable, intent(out) :: lam(:)
    integer :: nb, n, i, j, b, p, q
    real(dp), allocatable :: kk(:, :), mm(:, :), com(:, :), mass(:), a(:, :), z(:, :), lmat(:, :), linv(:, :)
    real(dp) :: d(3), l, nrm(3), ov, rs, kt, eye(3, 3), off(3)
    type(demstep_status_type) :: status
    nb = maxval(body_of)
    n = 6*nb
    eye = 0.0_dp
    do i = 1, 3
      eye(i, i) = 1.0_dp
    end do
    allocate(kk(n, n), mm(n, n), source=0.0_dp)
    allocate(com(3, nb), mass(nb), source=0.0_dp)
    do i = 1, scene%n
      b = body_of(i)
      mass(b) = mass(b) + scene%mass(i)
      com(:, b) = com(:, b) + scene%mass(i)*scene%x(:, i)
    end do
    do b = 1, nb
      com(:, b) = com(:, b)/mass(b)
      mm(6*b - 5:6*b - 3, 6*b - 5:6*b - 3) = mass(b)*eye
    end do
    do i = 1, scene%n
      b = body_of(i)
      off = scene%x(:, i) - com(:, b)
      mm(6*b - 2:6*b, 6*b - 2:6*b) = mm(6*b - 2:6*b, 6*b - 2:6*b) + scene%inertia(i)*eye &
        + scene%mass(i)*(dot_product(off, off)*eye - spread(off, 2, 3)*spread(off, 1, 3))
    end do
    kt = scene%k_tangential
    do i = 1, scene%n
      do j = i + 1, scene%n
        if (body_of(i) == body_of(j)) cycle
        d = scene%x(:, j) - scene%x(:, i)
        l = norm2(d)
        ov = scene%radius(i) + scene%radius(j) - l
        if (.not. ov > 0.0_dp) cycle
        nrm = d/l
        rs = scene%radius(i)*scene%radius(j)/(scene%radius(i) + scene%radius(j))
        call add_contact(i, j, nrm, scene%radius(i) - ov/2, scene%radius(j) - ov/2, rs)
      end do
      ov = scene%radius(i) - dot_product(scene%x(:, i) - scene%wall_point(:, 1), scene%wall_normal(:, 1))
      if (ov > 0.0_dp) call add_contact(0, i, scene%wall_normal(:, 1), 0.0_dp, scene%radius(i) - ov/2, &
        scene%radius(i))
    end do
    ! L^-1 K L^-T with M = L L^T (Cholesky, by hand)
    allocate(lmat(n, n), source=0.0_dp)
    do j = 1, n
      lmat(j, j) = sqrt(mm(j, j) - sum(lmat(j, :j - 1)**2))
      do i = j + 1, n
        lmat(i, j) = (mm(i, j) - sum(lmat(i, :j - 1)*lmat(j, :j - 1)))/lmat(j, j)
      end do
    end do
    ! L^-1 by forward substitution
    allocate(linv(n, n), source=0.0_dp)
    do q = 1, n
      do p = 1, n
        linv(p, q) = (merge(1.0_dp, 0.0_dp, p == q) - sum(lmat(p, :p - 1)*linv(:p - 1, q)))/lmat(p, p)
      end do
    end do
    a = matmul(linv, matmul(kk, transpose(linv)))
    a = 0.5_dp*(a + transpose(a))
    allocate(lam(n), z(n, n))
    call symmetric_eigensystem(a, lam, z, status)
  contains
    subroutine add_contact(pi_, pj, nv, ai, aj, rstar)
      integer, intent(in) :: pi_, pj
      real(dp), intent(in) :: nv(3), ai, aj, rstar
      real(dp) :: bn(12), bt(3, 12), dr(3, 12), blk(12, 12), g(12, 12), pp(3, 3), nx(3, 3), kr, kw
      integer :: idx(12), e, mem(2), bod(2), c
      pp = eye - spread(nv, 2, 3)*spread(nv, 1, 3)
      nx = reshape([0.0_dp, nv(3), -nv(2), -nv(3), 0.0_dp, nv(1), nv(2), -nv(1), 0.0_dp], [3, 3])
      bn = [-nv, 0.0_dp, 0.0_dp, 0.0_dp, nv, 0.0_dp, 0.0_dp, 0.0_dp]
      bt(:, 1:3) = -pp
      bt(:, 4:6) = ai*nx
      bt(:, 7:9) = pp
      bt(:, 10:12) = aj*nx
      dr = 0.0_dp
      dr(:, 4:6) = -eye
      dr(:, 10:12) = eye
      kr = scene%rolling_ratio*kt*rstar**2
      kw = scene%twisting_ratio*kt*rstar**2
      blk = scene%k_normal*spread(bn, 2, 12)*spread(bn, 1, 12) + kt*matmul(transpose(bt), bt) &
        + matmul(transpose(dr), matmul(kr*pp + kw*spread(nv, 2, 3)*spread(nv, 1, 3), dr))
      ! the rigid map of each end (ground: nothing)
      g = 0.0_dp
      mem = [pi_, pj]
      idx = 0
      do e = 1, 2
        bod(e) = 0
        if (mem(e) == 0) cycle
        bod(e) = body_of(mem(e))
        off = scene%x(:, mem(e)) - com(:, bod(e))
        do c = 1, 6
          g(6*(e - 1) + c, 6*(e - 1) + c) = 1.0_dp
        end do
        ! u_m = u + theta x off = u - [off]x theta
        g(6*(e - 1) + 1:6*(e - 1) + 3, 6*(e - 1) + 4:6*(e - 1) + 6) = &
          -reshape([0.0_dp, off(3), -off(2), -off(3), 0.0_dp, off(1), off(2), -off(1), 0.0_dp], [3, 3])
        idx(6*(e - 1) + 1:6*e) = [(6*(bod(e) - 1) + c, c = 1, 6)]
      end do
      blk = matmul(transpose(g), matmul(blk, g))
      do p = 1, 12
        if (idx(p) == 0) cycle
        do q = 1, 12
          if (idx(q) == 0) cycle
          kk(idx(p), idx(q)) = kk(idx(p), idx(q)) + blk(p, q)
        end do
      end do
    end subroutine add_contact
  end subroutine reference_eigenvalues

  !> Random clump packings: every eigenvalue of the library's body operator
  !> (dense, times rate^2) = the independent reference's, to 1e-10 of the
  !> largest; the exact limit's omega_max^2 = the reference's top, 1e-10.
  subroutine test_random_clumps(error)
    type(error_type), allocatable, intent(out) :: error
    type(scene_type) :: scene
    type(body_set_type) :: bodies
    type(body_operator_type) :: op
    type(critical_step_type) :: c
    type(csr_matrix_type) :: sparse
    type(spring_block_type), allocatable :: springs(:)
    type(demstep_status_type) :: status
    integer, allocatable :: body_of(:)
    real(dp), allocatable :: lam_ref(:), a(:, :), lam(:), z(:, :)
    real(dp) :: rate
    integer :: trial
    do trial = 1, 4
      call clump_packing(scene, body_of, 6 + 3*trial, 10 + trial, 2.0_dp)
      call bodies_from_members(scene, body_of, bodies, status)
      call check(error, status%stat, demstep_stat%ok, status%message)
      if (allocated(error)) return
      call body_operator(scene, bodies, op, rate, status, springs)
      call check(error, status%stat, demstep_stat%ok, status%message)
      if (allocated(error)) return
      ! some contacts between bodies, some inside them (dropped)
      call check(error, size(springs) > 3, "too few contacts between bodies: "//real_str(real(size(springs), dp)))
      if (allocated(error)) return
      call body_matrix(op, sparse)
      call csr_to_dense(sparse, a)
      allocate(lam(op%n), z(op%n, op%n))
      call symmetric_eigensystem(a, lam, z, status)
      lam = lam*rate**2
      call reference_eigenvalues(scene, body_of, lam_ref)
      call check(error, size(lam_ref), op%n)
      if (allocated(error)) return
      call check(error, maxval(abs(lam - lam_ref)) <= 1.0e-10_dp*maxval(lam_ref), &
        "trial "//real_str(real(trial, dp))//": eigenvalues differ by "//real_str(maxval(abs(lam - lam_ref))) &
        //" of "//real_str(maxval(lam_ref)))
      if (allocated(error)) return
      call body_critical_steps(scene, bodies, c, status, solver=eigen_solver%dense)
      call check(error, status%stat, demstep_stat%ok, status%message)
      if (allocated(error)) return
      call check(error, c%omega_max**2, maxval(lam_ref), rel=.true., thr=1.0e-10_dp)
      if (allocated(error)) return
      ! the bound is an upper bound of omega_max
      call check(error, c%omega_bound >= c%omega_max, "bound below omega_max")
      if (allocated(error)) return
      deallocate(lam, z)
    end do
  end subroutine test_random_clumps

  !> Three clump packings (8, 12 and 18 clumps of 1 to 3 overlapping spheres
  !> over a floor, linear law with tangential, rolling and twisting springs)
  !> against the dense numpy assembly of
  !> test/data/numpy_operator/make_reference.py (its own contact search,
  !> blocks, rigid maps and Yade's tensor sum; Cholesky and eigvalsh): the
  !> number of springs between bodies and every eigenvalue of the body
  !> operator (times rate^2) to 1e-10 of the largest (measured 1.4e-15 on
  !> the first).
  subroutine test_numpy_clumps(error)
    type(error_type), allocatable, intent(out) :: error
    type(scene_type) :: scene
    type(body_set_type) :: bodies
    type(body_operator_type) :: op
    type(csr_matrix_type) :: sparse
    type(spring_block_type), allocatable :: springs(:)
    type(demstep_status_type) :: status
    character(len=*), parameter :: dir = "test/data/numpy_operator/"
    real(dp), allocatable :: x(:, :), m(:), r(:), lam(:), lam_ref(:), a(:, :), z(:, :)
    integer, allocatable :: body_of(:)
    real(dp) :: floor_z, k_n, k_t, rolling, twisting, rate
    integer :: t, u, n, nb, ns, i
    do t = 1, 3
      open(newunit=u, file=dir//"clumps_"//achar(48 + t)//".txt", status="old", action="read")
      read(u, *) n, nb, ns, floor_z, k_n, k_t, rolling, twisting
      allocate(x(3, n), m(n), r(n), body_of(n), lam_ref(6*nb))
      do i = 1, n
        read(u, *) x(:, i), m(i), r(i), body_of(i)
      end do
      read(u, *) lam_ref
      close(u)
      call new_scene(scene, 3, x, m, r, status)
      if (status%stat == demstep_stat%ok) call scene_set_law(scene, contact_law%linear, k_n, k_t, status)
      if (status%stat == demstep_stat%ok) call scene_set_rolling(scene, rolling, twisting, status)
      if (status%stat == demstep_stat%ok) call scene_set_effects(scene, ["rotation"], [.true.], status)
      if (status%stat == demstep_stat%ok) call scene_add_walls(scene, reshape([0.0_dp, 0.0_dp, floor_z], [3, 1]), &
        reshape([0.0_dp, 0.0_dp, 1.0_dp], [3, 1]), status)
      if (status%stat == demstep_stat%ok) call bodies_from_members(scene, body_of, bodies, status)
      if (status%stat == demstep_stat%ok) call body_operator(scene, bodies, op, rate, status, springs)
      call check(error, status%stat, demstep_stat%ok, status%message)
      if (allocated(error)) return
      call check(error, size(springs), ns)
      if (allocated(error)) return
      call check(error, op%n, 6*nb)
      if (allocated(error)) return
      call body_matrix(op, sparse)
      call csr_to_dense(sparse, a)
      allocate(lam(op%n), z(op%n, op%n))
      call symmetric_eigensystem(a, lam, z, status)
      lam = rate**2*lam
      call check(error, maxval(abs(lam - lam_ref)) <= 1.0e-10_dp*maxval(lam_ref), "clumps_" &
        //achar(48 + t)//": eigenvalues differ by "//real_str(maxval(abs(lam - lam_ref)))//" of " &
        //real_str(maxval(lam_ref)))
      if (allocated(error)) return
      deallocate(x, m, r, body_of, lam_ref, lam, z)
    end do
  end subroutine test_numpy_clumps

  !> The matrix-free product (the fused kernel, `contact_product_arms`) = the
  !> compressed rows' product (`contact_block` carried by the rigid map) on
  !> random vectors (1e-12 of the norm), undamped and dashpot-mixed, with
  !> rotations (6 dof per body) and without (3); J^-1/2 of a random tensor
  !> squared and times J = I (1e-13).
  subroutine test_products(error)
    type(error_type), allocatable, intent(out) :: error
    type(scene_type) :: scene
    type(body_set_type) :: bodies
    type(body_operator_type) :: op
    type(csr_matrix_type) :: sparse
    type(spring_block_type), allocatable :: springs(:)
    type(demstep_status_type) :: status
    integer, allocatable :: body_of(:)
    real(dp), allocatable :: a(:, :), x(:), y(:)
    real(dp) :: rate, j(3, 3), s(3, 3), q(3, 3), eye(3, 3)
    integer :: mix, i, rot
    do rot = 1, 2
      call clump_packing(scene, body_of, 12, 3, 2.0_dp)
      call scene_set_damping(scene, 0.2_dp, status, tangential=0.1_dp, rolling=0.3_dp, drag=0.05_dp)
      if (rot == 2) call scene_set_effects(scene, ["rotation"], [.false.], status)
      call bodies_from_members(scene, body_of, bodies, status)
      call body_operator(scene, bodies, op, rate, status, springs)
      call check(error, status%stat, demstep_stat%ok, status%message)
      if (allocated(error)) return
      call check(error, op%nc, merge(6, 3, rot == 1))
      if (allocated(error)) return
      x = [(modulo(0.618034_dp*i, 1.0_dp) - 0.5_dp, i = 1, op%n)]
      allocate(y(op%n))
      do mix = 1, 2
        op%alpha = merge(1.0_dp, 0.3_dp, mix == 1)
        op%beta = merge(0.0_dp, 0.7_dp, mix == 1)
        call body_matrix(op, sparse)
        call csr_to_dense(sparse, a)
        call body_operator_apply(op, x, y)
        call check(error, norm2(y - matmul(a, x)) <= 1.0e-12_dp*norm2(y), "product differs: " &
          //real_str(norm2(y - matmul(a, x))/norm2(y)))
        if (allocated(error)) return
        call check(error, maxval(abs(a - transpose(a))) <= 1.0e-13_dp*maxval(abs(a)), "not symmetric")
        if (allocated(error)) return
      end do
      deallocate(y)
    end do
    call random_number(q)
    j = matmul(q, transpose(q)) + 0.1_dp*reshape([1, 0, 0, 0, 1, 0, 0, 0, 1], [3, 3])
    call inverse_sqrt_inertia(j, s, status)
    call check(error, status%stat, demstep_stat%ok, status%message)
    if (allocated(error)) return
    eye = 0.0_dp
    do i = 1, 3
      eye(i, i) = 1.0_dp
    end do
    call check(error, maxval(abs(matmul(matmul(s, s), j) - eye)) <= 1.0e-13_dp*maxval(j)/minval([(j(i, i), &
      i = 1, 3)]), "J^-1/2 J^-1/2 J /= I")
  end subroutine test_products

  !> ~60 clumps (about 360 dof): Lanczos (tolerance 1e-12) = dense for
  !> omega_max (1e-10) and the damped limit (1e-9: each Newton step's
  !> eigensolve to the tolerance).
  subroutine test_lanczos(error)
    type(error_type), allocatable, intent(out) :: error
    type(scene_type) :: scene
    type(body_set_type) :: bodies
    type(critical_step_type) :: cd, cl
    type(demstep_status_type) :: status
    integer, allocatable :: body_of(:)
    call clump_packing(scene, body_of, 60, 21, 2.0_dp)
    call scene_set_damping(scene, 0.2_dp, status, tangential=0.2_dp)
    call bodies_from_members(scene, body_of, bodies, status)
    call body_critical_steps(scene, bodies, cd, status, solver=eigen_solver%dense)
    call check(error, status%stat, demstep_stat%ok, status%message)
    if (allocated(error)) return
    call body_critical_steps(scene, bodies, cl, status, solver=eigen_solver%lanczos, tolerance=1.0e-12_dp)
    call check(error, status%stat, demstep_stat%ok, status%message)
    if (allocated(error)) return
    call check(error, cl%n_dof > 300, "only "//real_str(real(cl%n_dof, dp))//" dof")
    if (allocated(error)) return
    call check(error, cl%omega_max, cd%omega_max, rel=.true., thr=1.0e-10_dp, &
      message="Lanczos "//real_str(cl%omega_max)//" dense "//real_str(cd%omega_max))
    if (allocated(error)) return
    call check(error, cd%damped_exact .and. cl%damped_exact, "damped limits not exact")
    if (allocated(error)) return
    call check(error, cl%dt_critical_damped, cd%dt_critical_damped, rel=.true., thr=1.0e-9_dp, &
      message="damped Lanczos "//real_str(cl%dt_critical_damped)//" dense "//real_str(cd%dt_critical_damped))
    if (allocated(error)) return
    call check(error, cd%dt_critical_damped < cd%dt_critical_eigen, "damping did not lower the limit")
  end subroutine test_lanczos

  !> The bodies' Lanczos solve at the default tolerance carries the sphere
  !> path's randomised certificate: 60 clumps (360 dof: ARPACK, then the
  !> certificate's run) and 210 (1260 dof: one run, `krylov_top`) against the
  !> dense top: omega_max within half the tolerance below it (1e-12 for
  !> rounding), dt_critical_safe certified, at or below the dense limit and
  !> within the certificate's margin of it (omega_upper <= omega_max /
  !> sqrt(1 - eps), rounding aside).
  subroutine test_certified(error)
    type(error_type), allocatable, intent(out) :: error
    type(scene_type) :: scene
    type(body_set_type) :: bodies
    type(critical_step_type) :: cd, cl
    type(demstep_status_type) :: status
    integer, allocatable :: body_of(:)
    integer :: c
    integer, parameter :: counts(2) = [60, 210]
    real(dp) :: tol
    tol = lanczos_tolerance_default
    do c = 1, 2
      call clump_packing(scene, body_of, counts(c), 21, 2.0_dp)
      call bodies_from_members(scene, body_of, bodies, status)
      call body_critical_steps(scene, bodies, cd, status, solver=eigen_solver%dense)
      call check(error, status%stat, demstep_stat%ok, status%message)
      if (allocated(error)) return
      call body_critical_steps(scene, bodies, cl, status, solver=eigen_solver%lanczos)
      call check(error, status%stat, demstep_stat%ok, status%message)
      if (allocated(error)) return
      call check(error, cl%n_dof > merge(300, 1000, c == 1), "only "//real_str(real(cl%n_dof, dp))//" dof")
      if (allocated(error)) return
      call check(error, cl%omega_max >= cd%omega_max*(1.0_dp - 0.5_dp*tol - 1.0e-12_dp) .and. &
        cl%omega_max <= cd%omega_max*(1.0_dp + 1.0e-12_dp), "omega_max "//real_str(cl%omega_max) &
        //" against dense "//real_str(cd%omega_max))
      if (allocated(error)) return
      call check(error, cl%safe_basis == safe_basis%randomised .and. cl%safe_failure == certificate_failure, &
        "not certified: basis "//real_str(real(cl%safe_basis, dp)))
      if (allocated(error)) return
      call check(error, cl%dt_critical_safe <= 2.0_dp/cd%omega_max*(1.0_dp + 1.0e-12_dp) .and. &
        cl%omega_upper <= cl%omega_max/sqrt(1.0_dp - certificate_margin)*(1.0_dp + 1.0e-12_dp), &
        "dt_critical_safe "//real_str(cl%dt_critical_safe)//", exact "//real_str(2.0_dp/cd%omega_max))
      if (allocated(error)) return
    end do
  end subroutine test_certified

  !> A straight rod of 5 unit spheres (mass 1, touching: their contacts are
  !> inside the body) along x, its end sphere 1e-3 into a wall of normal +x.
  !> Exact: omega^2 = max(k_n/M, k_t (1/M + (4 + a)^2/J_perp)) (a = 1 - 5e-4
  !> the contact arm; M = 5, J_perp = 5 (2/5) + 2 (4 + 16) = 42). Yade's rule
  !> (member stiffness about its own centre, principal moments (2, 42, 42)):
  !> 1.41044 sqrt(min(M/max(k_n, k_t), 42/k_t)); exaDEM's pi sqrt(M/k_n).
  !> All three to 1e-12, for k_t/k_n = 0.25, 0.75 and 1.
  subroutine test_gst_rod(error)
    type(error_type), allocatable, intent(out) :: error
    type(scene_type) :: scene
    type(body_set_type) :: bodies
    type(critical_step_type) :: c
    type(demstep_status_type) :: status
    real(dp) :: x(3, 5), dt, ratio, omega2, gst, kt, arm
    real(dp), parameter :: kn = 1.0e4_dp, ratios(3) = [0.25_dp, 0.75_dp, 1.0_dp]
    integer :: i, t
    do i = 1, 5
      x(:, i) = [2.0_dp*real(i - 1, dp), 0.0_dp, 0.0_dp]
    end do
    arm = 1.0_dp - 0.5e-3_dp
    do t = 1, 3
      kt = ratios(t)*kn
      call new_scene(scene, 3, x, [(1.0_dp, i = 1, 5)], [(1.0_dp, i = 1, 5)], status)
      call scene_set_law(scene, contact_law%linear, kn, kt, status)
      call scene_add_walls(scene, reshape([-0.999_dp, 0.0_dp, 0.0_dp], [3, 1]), &
        reshape([1.0_dp, 0.0_dp, 0.0_dp], [3, 1]), status)
      call bodies_from_members(scene, [1, 1, 1, 1, 1], bodies, status)
      call check(error, status%stat, demstep_stat%ok, status%message)
      if (allocated(error)) return
      call body_critical_steps(scene, bodies, c, status, solver=eigen_solver%dense)
      call check(error, status%stat, demstep_stat%ok, status%message)
      if (allocated(error)) return
      omega2 = max(kn/5.0_dp, kt*(0.2_dp + (4.0_dp + arm)**2/42.0_dp))
      call check(error, c%omega_max**2, omega2, rel=.true., thr=1.0e-12_dp, &
        message="rod omega^2 "//real_str(c%omega_max**2)//" closed form "//real_str(omega2))
      if (allocated(error)) return
      call body_gst_step(scene, bodies, dt, status)
      call check(error, status%stat, demstep_stat%ok, status%message)
      if (allocated(error)) return
      gst = yade_gst_factor*sqrt(min(5.0_dp/max(kn, kt), 42.0_dp/kt))
      call check(error, dt, gst, rel=.true., thr=1.0e-12_dp, message="GST "//real_str(dt)//" formula " &
        //real_str(gst))
      if (allocated(error)) return
      ratio = dt/c%dt_critical_eigen
      ! (the ratios, for the record: 0.705, 1.218, 1.406)
      if (t == 3) then
        call check(error, ratio > 1.4_dp, "GST/exact "//real_str(ratio))
        if (allocated(error)) return
      end if
      ! exaDEM: pi sqrt(M/k_n), at least pi/2 of the exact limit (which is at
      ! most 2 sqrt(M/k_n), the rod's axial mode alone); by the closed form
      ! above 1.571, 2.712, 3.132
      call body_exadem_step(scene, bodies, dt, status)
      call check(error, status%stat, demstep_stat%ok, status%message)
      if (allocated(error)) return
      call check(error, dt, pi*sqrt(5.0_dp/kn), rel=.true., thr=1.0e-12_dp, message="exaDEM "//real_str(dt))
      if (allocated(error)) return
      ratio = dt/c%dt_critical_eigen
      call check(error, ratio >= 0.5_dp*pi*(1.0_dp - 1.0e-12_dp), "exaDEM/exact "//real_str(ratio))
      if (allocated(error)) return
    end do
  end subroutine test_gst_rod

  !> A Yade `export.textExt(..., format='x_y_z_r_attrs', comment='mass
  !> clumpId', attrs=['b.state.mass', 'b.clumpId'])`: clumpIds 12, 12, -1, 9
  !> give bodies 13, 13, 0 (alone), 10 and, from the members, bodies 2, 2, 3,
  !> 1; a names line of another width than the rows is refused at the row.
  subroutine test_yade_clumps(error)
    type(error_type), allocatable, intent(out) :: error
    type(snapshot_type) :: snap
    type(scene_type) :: scene
    type(body_set_type) :: bodies
    type(demstep_status_type) :: status
    character(len=*), parameter :: path = work_dir//"/yade_clumps.txt"
    call write_file(path, [character(len=40) :: "#format x_y_z_r_attrs", "# x y z r mass clumpId", &
      "0 0 0 1 1 12", "1.5 0 0 1 1 12", "5 0 0 1 1 -1", "9 0 0 1 1 9"])
    call read_snapshot(path, snap, status)
    call check(error, status%stat, demstep_stat%ok, status%message)
    if (allocated(error)) return
    call check(error, snap%has_body .and. all(snap%body == [13, 13, 0, 10]), "clumpId column")
    if (allocated(error)) return
    call new_scene(scene, 3, snap%x, [1.0_dp, 1.0_dp, 1.0_dp, 1.0_dp], snap%radius, status)
    call bodies_from_members(scene, snap%body, bodies, status)
    call check(error, status%stat, demstep_stat%ok, status%message)
    if (allocated(error)) return
    call check(error, all(bodies%body_of == [2, 2, 3, 1]), "bodies of the clumps")
    if (allocated(error)) return
    call write_file(path, [character(len=40) :: "#format x_y_z_r_attrs", "# x y z r clumpId", &
      "0 0 0 1 1 12"])
    call read_snapshot(path, snap, status)
    call check(error, status%stat, demstep_stat%invalid_input)
    if (allocated(error)) return
    call check(error, index(status%message, "line 3: the names line 2") > 0, status%message)
    if (allocated(error)) return
    ! without a clumpId column: no bodies
    call write_file(path, [character(len=40) :: "#format x_y_z_r_attrs", "# x y z r mass", "0 0 0 1 1"])
    call read_snapshot(path, snap, status)
    call check(error, status%stat == demstep_stat%ok .and. .not. snap%has_body, "no clumpId: no bodies")
  end subroutine test_yade_clumps

  !> A LIGGGHTS dump with `mol` (fix multisphere's bodies 7 and 3, -1 for a
  !> sphere on its own) and each member's `mass` the body's: body 7 of two
  !> r = 1 spheres 1.2 apart, mass 5; body 3 of r = 1 and r = 0.5 spheres,
  !> mass 2.25; the lone sphere keeps its mass 1. The members share the
  !> body's mass in proportion to r^3, so body 7 has J = diag(2, 3.8, 3.8)
  !> (2 x 2/5 2.5 1^2; plus 2 x 2.5 x 0.6^2) and body 3 its centre at the
  !> r^3-weighted mean (closed forms, to 1e-12). A body whose members carry
  !> different masses is refused naming the member.
  subroutine test_liggghts_multisphere(error)
    type(error_type), allocatable, intent(out) :: error
    type(snapshot_type) :: snap
    type(scene_type) :: scene
    type(body_set_type) :: bodies
    type(demstep_status_type) :: status
    character(len=*), parameter :: path = work_dir//"/multisphere.dump"
    character(len=60), parameter :: head(9) = [character(len=60) :: "ITEM: TIMESTEP", "0", &
      "ITEM: NUMBER OF ATOMS", "5", "ITEM: BOX BOUNDS ff ff ff", "-10 10", "-10 10", "-10 10", &
      "ITEM: ATOMS id type mol x y z radius mass"]
    real(dp) :: j7(3, 3), com3(3)
    call write_file(path, [head, [character(len=60) :: "1 1 7 0 0 0 1 5", "2 1 7 1.2 0 0 1 5", &
      "3 1 3 0 4 0 1 2.25", "4 1 3 0 5.2 0 0.5 2.25", "5 1 -1 6 0 0 1 1"]])
    call read_snapshot(path, snap, status)
    call check(error, status%stat, demstep_stat%ok, status%message)
    if (allocated(error)) return
    call check(error, snap%has_body .and. snap%body_mass .and. all(snap%body == [7, 7, 3, 3, 0]), "mol column")
    if (allocated(error)) return
    call new_scene(scene, 3, snap%x, snap%mass, snap%radius, status)
    call bodies_from_members(scene, snap%body, bodies, status, body_mass=snap%mass)
    call check(error, status%stat, demstep_stat%ok, status%message)
    if (allocated(error)) return
    ! ids 3, 7 are bodies 1, 2; the lone sphere body 3
    call check(error, all(bodies%body_of == [2, 2, 1, 1, 3]) .and. &
      all(abs(bodies%mass - [2.25_dp, 5.0_dp, 1.0_dp]) <= 1.0e-12_dp*bodies%mass), "bodies and their masses")
    if (allocated(error)) return
    j7 = 0.0_dp
    j7(1, 1) = 2.0_dp
    j7(2, 2) = 3.8_dp
    j7(3, 3) = 3.8_dp
    call check(error, maxval(abs(bodies%inertia(:, :, 2) - j7)) <= 1.0e-12_dp*3.8_dp .and. &
      maxval(abs(bodies%com(:, 2) - [0.6_dp, 0.0_dp, 0.0_dp])) <= 1.0e-12_dp, "two-sphere body")
    if (allocated(error)) return
    com3 = ([0.0_dp, 4.0_dp, 0.0_dp] + 0.125_dp*[0.0_dp, 5.2_dp, 0.0_dp])/1.125_dp
    call check(error, maxval(abs(bodies%com(:, 1) - com3)) <= 1.0e-12_dp*5.2_dp, "unequal members' centre")
    if (allocated(error)) return
    call write_file(path, [head, [character(len=60) :: "1 1 7 0 0 0 1 5", "2 1 7 1.2 0 0 1 4", &
      "3 1 3 0 4 0 1 2.25", "4 1 3 0 5.2 0 0.5 2.25", "5 1 -1 6 0 0 1 1"]])
    call read_snapshot(path, snap, status)
    call check(error, status%stat, demstep_stat%ok, status%message)
    if (allocated(error)) return
    call new_scene(scene, 3, snap%x, snap%mass, snap%radius, status)
    call bodies_from_members(scene, snap%body, bodies, status, body_mass=snap%mass)
    call check(error, status%stat == demstep_stat%invalid_input .and. status%where == "body_mass" .and. &
      index(status%message, "body_mass(2): differs from body_mass(1)") == 1, status%message)
  end subroutine test_liggghts_multisphere

  !> The union of spheres (`sphere_union_moments`, 16 Gauss points a panel)
  !> against closed forms. One sphere off the origin: volume 4/3 pi r^3,
  !> its centre, tensor 2/5 V r^2 1. A sphere inside another: the larger.
  !> Two unit spheres 1.2 apart along (1, 2, 2)/3, each less the cap of
  !> height h = 0.4 beyond the mid-plane: volume 2 (4/3 pi - pi h^2 (3 - h)
  !> / 3), axial moment 2 (8 pi / 15 - pi h^3 (20 - 15 h + 3 h^2) / 30), the
  !> transverse one half of it plus the integral of x^2 along the axis.
  !> Measured relative errors (gfortran): 4e-16 for the single sphere, 2e-15
  !> for the nested ones, 2.5e-9 for the overlapping pair (volume 1.8e-9,
  !> axial moment 2.5e-9); tolerance 1e-7, far below LIGGGHTS' Monte Carlo noise
  !> (0.3 % at ntry 1e5). Three unequal overlapping spheres (no closed form):
  !> 16 points a panel against 48 agree to 2.7e-12 (8 points against 64:
  !> 6e-7). The app's path: the LIGGGHTS body of two r = 1 spheres 1.2
  !> apart with mass 5 gets 5 / V times the union's tensor. Bad input
  !> refused by name.
  subroutine test_union(error)
    type(error_type), allocatable, intent(out) :: error
    type(scene_type) :: scene
    type(body_set_type) :: bodies
    type(demstep_status_type) :: status
    real(dp) :: v, c(3), t(3, 3), x0(3), e(3), h, v_ref, axial, transverse, err, eye(3, 3), d(3, 2)
    eye = reshape([1.0_dp, 0.0_dp, 0.0_dp, 0.0_dp, 1.0_dp, 0.0_dp, 0.0_dp, 0.0_dp, 1.0_dp], [3, 3])
    ! one sphere
    x0 = [0.3_dp, -0.2_dp, 0.5_dp]
    call sphere_union_moments(reshape(x0, [3, 1]), [1.5_dp], v, c, t, status)
    call check(error, status%stat, demstep_stat%ok, status%message)
    if (allocated(error)) return
    v_ref = 4.0_dp/3.0_dp*pi*1.5_dp**3
    err = max(abs(v/v_ref - 1.0_dp), maxval(abs(c - x0))/1.5_dp, maxval(abs(t - 0.4_dp*v_ref*2.25_dp*eye)) &
      /(0.4_dp*v_ref*2.25_dp))
    call check(error, err <= 1.0e-7_dp, "one sphere: relative error "//real_str(err))
    if (allocated(error)) return
    ! a sphere inside another
    call sphere_union_moments(reshape([x0, x0 + [0.2_dp, 0.1_dp, 0.0_dp]], [3, 2]), [1.5_dp, 0.7_dp], &
      v, c, t, status)
    err = max(abs(v/v_ref - 1.0_dp), maxval(abs(c - x0))/1.5_dp, maxval(abs(t - 0.4_dp*v_ref*2.25_dp*eye)) &
      /(0.4_dp*v_ref*2.25_dp))
    call check(error, status%stat == demstep_stat%ok .and. err <= 1.0e-7_dp, "nested spheres: relative error " &
      //real_str(err))
    if (allocated(error)) return
    ! two unit spheres 1.2 apart
    e = [1.0_dp, 2.0_dp, 2.0_dp]/3.0_dp
    d(:, 1) = x0 - 0.6_dp*e
    d(:, 2) = x0 + 0.6_dp*e
    call sphere_union_moments(d, [1.0_dp, 1.0_dp], v, c, t, status)
    call check(error, status%stat, demstep_stat%ok, status%message)
    if (allocated(error)) return
    h = 0.4_dp
    v_ref = 2.0_dp*(4.0_dp/3.0_dp*pi - pi*h**2*(3.0_dp - h)/3.0_dp)
    axial = 2.0_dp*(8.0_dp*pi/15.0_dp - pi*h**3*(20.0_dp - 15.0_dp*h + 3.0_dp*h**2)/30.0_dp)
    ! x^2 over the right half: u = x - 0.6 from -0.6 to 1, slice area pi (1 - u^2)
    transverse = 0.5_dp*axial + 2.0_dp*(half_moment(1.0_dp) - half_moment(-0.6_dp))
    err = max(abs(v/v_ref - 1.0_dp), maxval(abs(c - x0)), &
      abs(dot_product(e, matmul(t, e))/axial - 1.0_dp), &
      maxval(abs(t - (axial*spread(e, 2, 3)*spread(e, 1, 3) + transverse*(eye - spread(e, 2, 3) &
      *spread(e, 1, 3)))))/axial)
    call check(error, err <= 1.0e-7_dp, "two overlapping spheres: relative error "//real_str(err))
    if (allocated(error)) return
    ! three unequal spheres (validation scene i's template, mm): the default
    ! 16 points against 48, measured 2.7e-12 apart (tolerance 1e-9)
    block
      real(dp) :: c3(3, 3), va, ca(3), ta(3, 3)
      c3 = reshape([-0.30024691358_dp, -0.55555555556_dp, -0.12345679012_dp, 1.59975308642_dp, &
        -0.55555555556_dp, -0.12345679012_dp, -0.30024691358_dp, 1.24444444444_dp, 0.27654320988_dp], [3, 3])
      call sphere_union_moments(c3, [1.5_dp, 1.0_dp, 1.25_dp], va, ca, ta, status, points=48)
      call sphere_union_moments(c3, [1.5_dp, 1.0_dp, 1.25_dp], v, c, t, status)
      err = max(abs(v/va - 1.0_dp), maxval(abs(c - ca))/1.5_dp, maxval(abs(t - ta))/maxval(abs(ta)))
      call check(error, status%stat == demstep_stat%ok .and. err <= 1.0e-9_dp, "three spheres, 16 against " &
        //"48 points: "//real_str(err))
      if (allocated(error)) return
    end block
    ! the LIGGGHTS body: mass 5 on the union
    call new_scene(scene, 3, d, [1.0_dp, 1.0_dp], [1.0_dp, 1.0_dp], status)
    call bodies_from_members(scene, [7, 7], bodies, status, body_mass=[5.0_dp, 5.0_dp], union=.true.)
    call check(error, status%stat, demstep_stat%ok, status%message)
    if (allocated(error)) return
    call check(error, abs(bodies%mass(1) - 5.0_dp) <= 1.0e-12_dp .and. maxval(abs(bodies%com(:, 1) - x0)) &
      <= 1.0e-7_dp .and. abs(dot_product(e, matmul(bodies%inertia(:, :, 1), e))/(5.0_dp/v_ref*axial) - 1.0_dp) &
      <= 1.0e-7_dp .and. maxval(abs(bodies%offset(:, 2) - 0.6_dp*e)) <= 1.0e-7_dp, "the body's union tensor")
    if (allocated(error)) return
    ! bad input
    call sphere_union_moments(d, [1.0_dp, 0.0_dp], v, c, t, status)
    call check(error, status%stat == demstep_stat%invalid_input .and. status%where == "radius" .and. &
      index(status%message, "radius(2)") == 1, "radius 0: "//status%message)
    if (allocated(error)) return
    call sphere_union_moments(d(1:2, :), [1.0_dp, 1.0_dp], v, c, t, status)
    call check(error, status%stat == demstep_stat%invalid_input .and. status%where == "centre", &
      "centre not 3 x n: "//status%message)

  contains

    !> Antiderivative of (u + 0.6)^2 pi (1 - u^2) in u.
    pure real(dp) function half_moment(u) result(f)
      real(dp), intent(in) :: u
      real(dp), parameter :: a = 0.6_dp
      f = pi*(u**3/3.0_dp - u**5/5.0_dp + 2.0_dp*a*(u**2/2.0_dp - u**4/4.0_dp) + a*a*(u - u**3/3.0_dp))
    end function half_moment
  end subroutine test_union

  !> Ids 1000000007, 5, 0, 5, 42, 0 number the bodies 3, 1, 4, 1, 2, 5.
  subroutine test_ids(error)
    type(error_type), allocatable, intent(out) :: error
    type(scene_type) :: scene
    type(body_set_type) :: bodies
    type(demstep_status_type) :: status
    real(dp) :: x(3, 6)
    integer :: i
    x = 0.0_dp
    do i = 1, 6
      x(1, i) = 3.0_dp*real(i, dp)
    end do
    call new_scene(scene, 3, x, [(1.0_dp, i = 1, 6)], [(1.0_dp, i = 1, 6)], status)
    call bodies_from_members(scene, [1000000007, 5, 0, 5, 42, 0], bodies, status)
    call check(error, status%stat, demstep_stat%ok, status%message)
    if (allocated(error)) return
    call check(error, bodies%n, 5)
    if (allocated(error)) return
    call check(error, all(bodies%body_of == [3, 1, 4, 1, 2, 5]), "body numbers")
    if (allocated(error)) return
    call check(error, all(bodies%members == [2, 1, 1, 1, 1]), "members per body")
  end subroutine test_ids

  !> Refusals by name: a particle listed in two bodies (`members`), a
  !> singular inertia tensor and a non-positive mass (`inertia`, `mass`,
  !> with the body), a body_of of the wrong size, mixed fixed members.
  subroutine test_bad_input(error)
    type(error_type), allocatable, intent(out) :: error
    type(scene_type) :: scene
    type(body_set_type) :: bodies
    type(demstep_status_type) :: status
    real(dp) :: x(3, 4), inertia(3, 3, 2), com(3, 2)
    integer :: i
    x = reshape([0.0_dp, 0.0_dp, 0.0_dp, 1.5_dp, 0.0_dp, 0.0_dp, 5.0_dp, 0.0_dp, 0.0_dp, 6.5_dp, 0.0_dp, 0.0_dp], &
      [3, 4])
    call new_scene(scene, 3, x, [(1.0_dp, i = 1, 4)], [(1.0_dp, i = 1, 4)], status)
    call bodies_from_lists(scene, [1, 3, 5], [1, 2, 2, 3], bodies, status)
    call check(error, status%stat, demstep_stat%invalid_input)
    if (allocated(error)) return
    call check(error, status%where, "members")
    if (allocated(error)) return
    call check(error, status%index, 3)
    if (allocated(error)) return
    call check(error, index(status%message, "body 1 and again in body 2") > 0, status%message)
    if (allocated(error)) return
    inertia = 0.0_dp
    do i = 1, 3
      inertia(i, i, :) = 1.0_dp
    end do
    com = reshape([0.75_dp, 0.0_dp, 0.0_dp, 5.75_dp, 0.0_dp, 0.0_dp], [3, 2])
    ! a rod of point masses: no inertia about its axis
    inertia(1, 1, 2) = 0.0_dp
    call bodies_given(scene, [1, 1, 2, 2], [2.0_dp, 2.0_dp], com, inertia, bodies, status)
    call check(error, status%where, "inertia")
    if (allocated(error)) return
    call check(error, status%index, 2)
    if (allocated(error)) return
    call check(error, index(status%message, "inertia(2): ") == 1, status%message)
    if (allocated(error)) return
    inertia(1, 1, 2) = 1.0_dp
    call bodies_given(scene, [1, 1, 2, 2], [2.0_dp, 0.0_dp], com, inertia, bodies, status)
    call check(error, status%where, "mass")
    if (allocated(error)) return
    call check(error, status%index, 2)
    if (allocated(error)) return
    call bodies_given(scene, [1, 1, 2, 2], [-1.0_dp, 2.0_dp], com, inertia, bodies, status)
    call check(error, status%where, "mass")
    if (allocated(error)) return
    call check(error, status%index, 1)
    if (allocated(error)) return
    ! not symmetric
    inertia(1, 2, 1) = 0.5_dp
    call bodies_given(scene, [1, 1, 2, 2], [2.0_dp, 2.0_dp], com, inertia, bodies, status)
    call check(error, status%where, "inertia")
    if (allocated(error)) return
    call bodies_from_members(scene, [1, 1, 2], bodies, status)
    call check(error, status%where, "body_of")
    if (allocated(error)) return
    call bodies_from_members(scene, [1, 1, 2, -2], bodies, status)
    call check(error, status%where, "body_of")
    if (allocated(error)) return
    call check(error, status%index, 4)
    if (allocated(error)) return
    call new_scene(scene, 3, x, [(1.0_dp, i = 1, 4)], [(1.0_dp, i = 1, 4)], status, &
      fixed=[.true., .false., .false., .false.])
    call bodies_from_members(scene, [1, 1, 2, 2], bodies, status)
    call check(error, status%where, "fixed")
  end subroutine test_bad_input

  !> A chain of 6 clumps (1 to 3 members) joined by bonds between members of
  !> neighbouring clumps (two per pair, off the centres: the bonds turn the
  !> bodies), no contacts, members with random velocities of 1e-4. The
  !> stepper's rigid bodies at 0.99 of the exact limit: no blow-up in 1e5
  !> steps and the energy kept to 1e-3 (measured 3e-5: the scheme conserves
  !> a modified energy of the linear system, and the finite rotations and the
  !> gyroscopic term it leaves out add a drift in proportion to the
  !> amplitude, 7e-3 at velocities of 1e-2); at 1.01: blown up. 3D and 2D;
  !> and a clump between two walls, held by its wall contacts.
  subroutine test_stepper(error)
    type(error_type), allocatable, intent(out) :: error
    type(scene_type) :: scene, start
    type(body_set_type) :: bodies, bodies0
    type(critical_step_type) :: c
    type(scene_summary_type) :: summary
    type(demstep_status_type) :: status
    integer, allocatable :: body_of(:), pairs(:, :)
    real(dp), allocatable :: x(:, :), m(:), r(:)
    real(dp) :: u(3), q
    integer :: b, j, n, dim, first(7), a, k, best(2)
    real(dp) :: dmin, dist
    do dim = 3, 2, -1
      call seed_fixed(40 + dim)
      allocate(x(3, 18), m(18), r(18), body_of(18))
      n = 0
      do b = 1, 6
        first(b) = n + 1
        call random_number(q)
        do j = 1, 1 + int(3.0_dp*q)
          n = n + 1
          call random_number(u)
          u = u - 0.5_dp
          if (dim == 2) u(3) = 0.0_dp
          x(:, n) = [2.6_dp*real(b, dp), 0.0_dp, 0.0_dp]
          if (j > 1) x(:, n) = x(:, n) + 0.7_dp*u/norm2(u)
          call random_number(q)
          r(n) = 0.6_dp + 0.2_dp*q
          m(n) = r(n)**3
          body_of(n) = b
        end do
      end do
      first(7) = n + 1
      call new_scene(start, dim, x(:dim, :n), m(:n), r(:n), status)
      call check(error, status%stat, demstep_stat%ok, status%message)
      if (allocated(error)) return
      ! per neighbouring pair: the closest members, and the first members
      allocate(pairs(2, 10))
      k = 0
      do b = 1, 5
        dmin = huge(1.0_dp)
        do a = first(b), first(b + 1) - 1
          do j = first(b + 1), first(b + 2) - 1
            dist = norm2(x(:, j) - x(:, a))
            if (dist < dmin) then
              dmin = dist
              best = [a, j]
            end if
          end do
        end do
        k = k + 1
        pairs(:, k) = best
        k = k + 1
        pairs(:, k) = [first(b + 1) - 1, first(b + 2) - 1]
        if (all(pairs(:, k) == pairs(:, k - 1))) pairs(:, k) = [first(b), first(b + 1)]
      end do
      call scene_add_bonds(start, pairs, status)
      call scene_set_bond_stiffness(start, 1.0e3_dp, 300.0_dp, status)
      call scene_set_effects(start, ["contacts", "rotation"], [.false., .true.], status)
      call check(error, status%stat, demstep_stat%ok, status%message)
      if (allocated(error)) return
      call random_number(start%v(:dim, :))
      start%v = 1.0e-4_dp*(start%v - 0.5_dp)
      call bodies_from_members(start, body_of(:n), bodies0, status)
      call body_critical_steps(start, bodies0, c, status, solver=eigen_solver%dense)
      call check(error, status%stat, demstep_stat%ok, status%message)
      if (allocated(error)) return
      scene = start
      bodies = bodies0
      call scene_run(scene, 0.99_dp*c%dt_critical_eigen, 100000_i8, summary, status, bodies=bodies)
      call check(error, .not. summary%blew_up .and. summary%energy_drift < 1.0e-3_dp, "bounded at 0.99 " &
        //"(dim "//real_str(real(dim, dp))//"), drift "//real_str(summary%energy_drift))
      if (allocated(error)) return
      ! the members stayed a rigid body: their distance to the centre kept
      call check(error, maxval(abs(norm2(bodies%offset, 1) - norm2(bodies0%offset, 1))) < 1.0e-12_dp, &
        "offsets changed length")
      if (allocated(error)) return
      scene = start
      bodies = bodies0
      call scene_run(scene, 1.01_dp*c%dt_critical_eigen, 100000_i8, summary, status, bodies=bodies)
      call check(error, summary%blew_up .and. status%stat == demstep_stat%blow_up, "grows at 1.01 (dim " &
        //real_str(real(dim, dp))//")")
      if (allocated(error)) return
      deallocate(x, m, r, body_of, pairs)
    end do
    ! a three-sphere clump squeezed between a floor and a ceiling (1e-3
    ! overlaps, the two contacts on one vertical: in equilibrium), k_t and
    ! rolling springs on the walls. With its members' contacts on (they
    ! overlap: 3e3 times the wall forces, cancelling in the body's sums)
    ! bounded at 0.99, the energy kept to 1e-9 of their (constant) energy
    ! (measured 2e-12); without them (the energy that moves): kept to 1e-6
    ! at 0.99 (measured 1e-9), grown more than 100-fold at 1.01 (measured
    ! 655: the wall contacts open and cap the growth).
    allocate(x(3, 3), r(3))
    x(:, 1:3) = reshape([0.0_dp, 0.0_dp, 0.0_dp, 0.0_dp, 0.0_dp, 1.5_dp, 0.7_dp, 0.4_dp, 0.6_dp], [3, 3])
    r(1:3) = [1.0_dp, 0.8_dp, 0.5_dp]
    call new_scene(start, 3, x(:, 1:3), r(1:3)**3, r(1:3), status)
    call scene_set_law(start, contact_law%linear, 1.0e4_dp, 3.0e3_dp, status)
    call scene_set_rolling(start, 0.2_dp, 0.1_dp, status)
    call scene_add_walls(start, reshape([0.0_dp, 0.0_dp, -1.0_dp + 1.0e-3_dp, 0.0_dp, 0.0_dp, &
      2.3_dp - 1.0e-3_dp], [3, 2]), reshape([0.0_dp, 0.0_dp, 1.0_dp, 0.0_dp, 0.0_dp, -1.0_dp], [3, 2]), status)
    call check(error, status%stat, demstep_stat%ok, status%message)
    if (allocated(error)) return
    call random_number(start%v)
    start%v = 1.0e-6_dp*(start%v - 0.5_dp)
    call bodies_from_members(start, [1, 1, 1], bodies0, status)
    call body_critical_steps(start, bodies0, c, status, solver=eigen_solver%dense)
    call check(error, status%stat, demstep_stat%ok, status%message)
    if (allocated(error)) return
    scene = start
    bodies = bodies0
    call scene_run(scene, 0.99_dp*c%dt_critical_eigen, 100000_i8, summary, status, bodies=bodies)
    call check(error, .not. summary%blew_up .and. summary%energy_drift < 1.0e-9_dp, "clump between walls, " &
      //"members' contacts on: bounded at 0.99, drift "//real_str(summary%energy_drift))
    if (allocated(error)) return
    call scene_set_effects(start, ["contacts"], [.false.], status)
    scene = start
    bodies = bodies0
    call scene_run(scene, 0.99_dp*c%dt_critical_eigen, 100000_i8, summary, status, bodies=bodies)
    call check(error, .not. summary%blew_up .and. summary%energy_drift < 1.0e-6_dp, "clump between walls: " &
      //"bounded at 0.99, drift "//real_str(summary%energy_drift))
    if (allocated(error)) return
    scene = start
    bodies = bodies0
    call scene_run(scene, 1.01_dp*c%dt_critical_eigen, 100000_i8, summary, status, bodies=bodies)
    call check(error, summary%energy_drift > 100.0_dp, "clump between walls: grows at 1.01, drift " &
      //real_str(summary%energy_drift))
  end subroutine test_stepper

  !> The app reads a body table: the dumbbell (lower sphere at the origin,
  !> the upper at 1.6 (0.8, 0, 0.6)) on a floor 1e-3 into the lower one gives
  !> omega^2 = k (1/2 + 0.8^2 0.8^2/(0.8 + 2 0.8^2)) (1e-12: the result's
  !> 17 digits); bad tables and variables refused on one line by name.
  subroutine test_app(error)
    type(error_type), allocatable, intent(out) :: error
    character(len=*), parameter :: deck = work_dir//"/bodies_deck.nml", out = work_dir//"/bodies_out.nml"
    character(len=*), parameter :: g = "&scene dim = 3, position = 0, 0, 0, 1.28, 0, 0.96, radius = 1.0, " &
      //"mass = 1.0, k_normal = 1e4, effects = 'contacts', 'walls', 'rotation', walls = 0, 0, -0.999, " &
      //"0, 0, 1, bodies_file = 'bodies.txt'"
    character(len=*), parameter :: yade_material = "&material young = 1.0e7, poisson = 0.25, density = " &
      //"2500.0, radius = 1e-3, restitution = 0.9, impact_velocity = 1.0, code = 'yade_frictphys' /"
    character(len=:), allocatable :: stdout, stderr
    real(dp) :: omega_max, expected, drift
    integer :: rc, n_dof
    integer(i8) :: steps
    logical :: blew_up
    call write_file(work_dir//"/bodies.txt", [character(len=20) :: "# particle body", "1 70", "2 70"])
    call computed([g//" /"])
    if (allocated(error)) return
    call check(error, n_dof, 6)
    if (allocated(error)) return
    expected = sqrt(1.0e4_dp*(0.5_dp + 0.8_dp**4/(0.8_dp + 2.0_dp*0.8_dp**2)))
    call check(error, omega_max, expected, rel=.true., thr=1.0e-12_dp)
    if (allocated(error)) return
    ! a run of the body at 20 steps per period: stable
    call computed([g//", duration = 1.0, n_per_period = 20, velocity = 0, 0, -1e-5, 0, 0, -1e-5 /"])
    if (allocated(error)) return
    call check(error, steps > 0_i8 .and. .not. blew_up .and. drift < 1.0e-6_dp, "run: steps " &
      //real_str(real(steps, dp))//", drift "//real_str(drift))
    if (allocated(error)) return
    ! refusals
    call write_file(work_dir//"/bodies.txt", [character(len=20) :: "1 1", "2 1", "1 2"])
    call refused(g//" /", "&scene: bodies_file: "//work_dir//"/bodies.txt: line 3: particle 1 is already " &
      //"in body 1 (line 1)")
    if (allocated(error)) return
    call write_file(work_dir//"/bodies.txt", [character(len=20) :: "1 1", "3 1"])
    call refused(g//" /", "&scene: bodies_file: "//work_dir//"/bodies.txt: line 2: column 1: particle 3 " &
      //"does not exist (1 to 2)")
    if (allocated(error)) return
    call write_file(work_dir//"/bodies.txt", [character(len=20) :: "1 1", "2 1"])
    call refused(g//", body_density = -1 /", "&scene: body_density: must be finite and > 0")
    if (allocated(error)) return
    call refused(g//", body_union = T /", "&scene: snapshot_file: required with body_union")
    if (allocated(error)) return
    call refused(g//", prestress = T /", "&scene: bodies_file: rigid bodies are analysed")
    if (allocated(error)) return
    call refused(g//", fixed = 1 /", "&scene: fixed: body 1 has fixed and free members")
    if (allocated(error)) return
    ! a Yade export with clumpId gives the bodies; the same spheres without it
    ! and a body table give the same limit
    call write_file(work_dir//"/yade_clumps_app.txt", [character(len=60) :: "#format x_y_z_r_attrs", &
      "# x y z r clumpId", "0 0 0 1e-3 4", "1.2e-3 0 0 1e-3 4", "3.15e-3 0.2e-3 0 1e-3 7", &
      "4.35e-3 0.2e-3 0.2e-3 1e-3 7", "1.0e-3 1.95e-3 0 1e-3 -1"])
    call write_file(work_dir//"/yade_spheres_app.txt", [character(len=60) :: "#format x_y_z_r", &
      "0 0 0 1e-3", "1.2e-3 0 0 1e-3", "3.15e-3 0.2e-3 0 1e-3", "4.35e-3 0.2e-3 0.2e-3 1e-3", &
      "1.0e-3 1.95e-3 0 1e-3"])
    call write_file(work_dir//"/bodies.txt", [character(len=20) :: "1 5", "2 5", "3 8", "4 8"])
    call computed([character(len=200) :: "&scene dim = 3, snapshot_file = 'yade_clumps_app.txt' /", &
      yade_material])
    if (allocated(error)) return
    call check(error, n_dof, 18, message="3 bodies")
    if (allocated(error)) return
    expected = omega_max
    call computed([character(len=200) :: "&scene dim = 3, snapshot_file = 'yade_spheres_app.txt', " &
      //"bodies_file = 'bodies.txt' /", yade_material])
    if (allocated(error)) return
    call check(error, omega_max, expected, rel=.true., thr=1.0e-14_dp)
    if (allocated(error)) return
    ! a LIGGGHTS multisphere dump (mol, the body's mass) gives its bodies: two
    ! bodies of two members and a lone sphere, 18 degrees of freedom; members
    ! of one body with different masses are refused
    call write_file(work_dir//"/ms_app.dump", [character(len=60) :: "ITEM: TIMESTEP", "0", &
      "ITEM: NUMBER OF ATOMS", "5", "ITEM: BOX BOUNDS ff ff ff", "-1 1", "-1 1", "-1 1", &
      "ITEM: ATOMS id type mol x y z radius mass", "1 1 4 0 0 0 1e-3 2e-5", "2 1 4 1.2e-3 0 0 1e-3 2e-5", &
      "3 1 9 3.15e-3 0.2e-3 0 1e-3 2e-5", "4 1 9 4.35e-3 0.2e-3 0.2e-3 1e-3 2e-5", &
      "5 1 -1 1.0e-3 1.95e-3 0 1e-3 1e-5"])
    call computed([character(len=200) :: "&scene dim = 3, snapshot_file = 'ms_app.dump' /", yade_material])
    if (allocated(error)) return
    call check(error, n_dof, 18, message="3 bodies from mol")
    if (allocated(error)) return
    call write_file(work_dir//"/ms_app.dump", [character(len=60) :: "ITEM: TIMESTEP", "0", &
      "ITEM: NUMBER OF ATOMS", "2", "ITEM: BOX BOUNDS ff ff ff", "-1 1", "-1 1", "-1 1", &
      "ITEM: ATOMS id type mol x y z radius mass", "1 1 4 0 0 0 1e-3 2e-5", "2 1 4 1.2e-3 0 0 1e-3 3e-5"])
    call refused("&scene dim = 3, snapshot_file = 'ms_app.dump', k_normal = 1e4 /", "&scene: snapshot_file: " &
      //"mass column: body_mass(2): differs from body_mass(1) of the same body")
  contains
    !> Run a deck that computes; its result's omega_max, n_dof, steps,
    !> blew_up, energy_drift.
    subroutine computed(lines)
      character(len=*), intent(in) :: lines(:)
      type(result_group_type) :: fields
      integer :: unit, ios
      call write_file(deck, lines)
      call run_app("-q "//deck//" -o "//out, rc, stdout, stderr)
      call check(error, rc, 0, message="exit status for '"//trim(lines(1))//"'; stderr: "//stderr)
      if (allocated(error)) return
      open(newunit=unit, file=out, status="old", action="read", iostat=ios)
      call read_group(unit, "scene_result", fields, ios)
      if (ios == 0) call take(fields, "omega_max", omega_max, ios)
      if (ios == 0) call take(fields, "n_dof", n_dof, ios)
      if (ios == 0) call take(fields, "steps", steps, ios)
      if (ios == 0) call take(fields, "blew_up", blew_up, ios)
      if (ios == 0) call take(fields, "energy_drift", drift, ios)
      close(unit)
      call check(error, ios, 0, message="scene_result of '"//trim(lines(1))//"'")
    end subroutine computed

    subroutine refused(line, expected)
      character(len=*), intent(in) :: line, expected
      call write_file(deck, [line])
      call run_app(deck//" -o "//out, rc, stdout, stderr)
      call check(error, rc, 2, message="exit status for '"//line//"': "//stderr)
      if (allocated(error)) return
      call check(error, index(stderr, "demstep: "//deck//": "//expected) == 1, "stderr '"//stderr &
        //"' does not start with 'demstep: "//deck//": "//expected//"'")
      if (allocated(error)) return
      call check(error, count(transfer(stderr, "a", len(stderr)) == new_line("a")), 1, &
        message="one line on stderr: "//stderr)
    end subroutine refused
  end subroutine test_app

end module test_bodies
