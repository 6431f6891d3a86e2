!> Tests of the interaction kernel and of the assembly physics built on it:
!> the tangent block against finite differences of the kernel's forces and
!> torques, rotating pairs, rings and lattices (periodic) against their
!> hand-derived spectra, and the bound against the exact value with rotations.
module test_interaction
  use testdrive, only: new_unittest, unittest_type, error_type, check, test_failed
  use demstep
  use demstep_neighbours, only: contact_list, spatial_order
  use demstep_assembly, only: assembly_matrix, eigen_solver_name, assembly_operator_apply, &
    assembly_operator, assembly_operator_type, assembly_matrix_rows, operator_set_blocks, operator_spring_energies, &
    product_block_bodies, order_min_bodies, operator_products, operator_from_springs, linearise, &
    spring_block_type, hertz_linearization
  use demstep_assembly, only: operator_abs_product, operator_bound, operator_mix, bound_iterations
  use demstep_interaction, only: mixed_stiffness
  use demstep_kinds, only: pi
  use demstep_interaction, only: contact_block, contact_end_blocks, contact_forces, normal_force, normal_stiffness, &
    tangential_stiffness, reduced_radius, contact_product, contact_products, contact_products_listed, &
    contact_products_add, mixed_stiffness
  use demstep_csr, only: csr_matrix_type, csr_to_dense, csr_apply, csr_abs_product
  use demstep_lapack, only: largest_eigenpair
  use test_support, only: real_str
  use demstep_text, only: int_text
  !$ use omp_lib, only: omp_set_num_threads, omp_get_max_threads
  implicit none
  private
  public :: collect_interaction

contains

  subroutine collect_interaction(testsuite)
    type(unittest_type), allocatable, intent(out) :: testsuite(:)
    testsuite = [ &
      new_unittest("tangent block = finite differences of force and torque", test_block_fd), &
      new_unittest("spring pass in chunks = the kernel spring by spring, bit for bit", test_spring_pass), &
      new_unittest("one end's columns in closed form = the kernel's block", test_end_blocks), &
      new_unittest("Coulomb friction caps the tangential force at friction F_n", test_friction), &
      new_unittest("rotating pair: omega^2 = k_t (1/m_i + 1/m_j + c_i^2/I_i + c_j^2/I_j), c = r - d/2", test_pair), &
      new_unittest("periodic ring with rotations vs its dispersion relation", test_ring), &
      new_unittest("periodic simple cubic lattice vs its dispersion relation", test_sc_lattice), &
      new_unittest("the bound is never below the exact value with rotations", test_bound_rotations), &
      new_unittest("the bound is never below the exact value with rolling and twisting springs", &
        test_bound_rolling), &
      new_unittest("the bound's |A'| v = its blocks' sums bit for bit; the bound >= the dense top", &
        test_abs_product), &
      new_unittest("pre-stress: -(F_n/l)(I - n n^T) on a loaded ring", test_prestress), &
      new_unittest("periodic cell and contact list refusals", test_refusals), &
      new_unittest("materials per type: linear k_n, k_t per pair; Hertz E, nu", test_materials), &
      new_unittest("stepper at 0.99/1.01 of the 6-dof limit: periodic packings", test_stability_full), &
      new_unittest("matrix-free operator = its matrix; its top = the dense omega_max", test_operator), &
      new_unittest("matrix rows of listed bodies renumbered; a bad body or map entry refused", test_matrix_rows), &
      new_unittest("Lanczos vs dense on packings, lattices, rings; the error bar", test_lanczos_vs_dense), &
      new_unittest("eigen_solver: auto, dense, lanczos, none; bad values", test_solver_choice), &
      new_unittest("operator product: 1 and 2 threads agree bit for bit", test_threads), &
      new_unittest("operator product in blocks = its matrix times x; threads agree; spring energies", &
        test_product_blocks), &
      new_unittest("operator in a locality order: products, energies, matrix, bound and mode in the caller's order", &
        test_locality_order), &
      new_unittest("operator_from_springs with a given order: its vectors in it; bad orders refused by name", &
        test_given_order), &
      new_unittest("springs linearised in parallel: the first overflowing contact in list order", &
        test_overflow_first), &
      new_unittest("Lanczos out of restarts: the bracket holds the chain's closed form", test_not_converged) &
      ]
  end subroutine collect_interaction

  !> The operator's spring pass (`contact_products`, `contact_products_listed`,
  !> `contact_products_add`; it runs in chunks of springs) against
  !> `contact_product` called spring by spring: 37 springs (not a multiple
  !> of a chunk) among 6 bodies and the ground (body 0: x and rot 0), some with
  !> rolling and twisting springs, some with pre-stress, mixed alpha K + beta C
  !> and K alone. The arithmetic per spring is the same expression, so the
  !> forces, and the sums added in list order, are equal bit for bit.
  subroutine test_spring_pass(error)
    type(error_type), allocatable, intent(out) :: error
    integer, parameter :: ns = 37, nb = 6
    real(dp) :: normal(3, ns), coef(7, ns), dcoef(4, ns), rinv(0:nb), x(6, 0:nb)
    real(dp) :: f(6, 2*ns), ref(6, 2*ns), acc(6, nb), acc_ref(6, nb), k(4), geo, mix(2, 2)
    integer :: ends(2, ns), list(ns), s, p, j, a, b
    logical :: same
    call random_seed_fixed(41)
    call random_number(x)
    x = x - 0.5_dp
    x(:, 0) = 0.0_dp
    call random_number(rinv)
    rinv = 1.0_dp + rinv
    rinv(0) = 0.0_dp
    call random_number(coef)
    call random_number(dcoef)
    call random_number(normal)
    do s = 1, ns
      normal(:, s) = normal(:, s) - 0.5_dp
      normal(:, s) = normal(:, s)/norm2(normal(:, s))
      ! bodies 1..nb and the ground (every fifth spring's first end, every seventh's second)
      ends(1, s) = mod(3*s, nb) + 1
      ends(2, s) = mod(5*s + 1, nb) + 1
      if (ends(2, s) == ends(1, s)) ends(2, s) = mod(ends(2, s), nb) + 1
      if (mod(s, 5) == 0) ends(1, s) = 0
      if (mod(s, 7) == 0) ends(2, s) = 0
      ! rolling and twisting on every third spring, pre-stress on every other
      if (mod(s, 3) /= 0) coef(6:7, s) = 0.0_dp
      if (mod(s, 2) == 0) coef(5, s) = 0.0_dp
      ! the list: the springs reversed
      list(s) = ns + 1 - s
    end do
    mix = reshape([1.0_dp, 0.0_dp, 0.7_dp, 0.3_dp], [2, 2])
    do j = 1, 2
      ! spring by spring
      do s = 1, ns
        a = ends(1, s)
        b = ends(2, s)
        call mixed_stiffness(coef(:, s), dcoef, s, mix(1, j), mix(2, j), k, geo)
        call contact_product(normal(:, s), k, coef(3, s), coef(4, s), rinv(a), rinv(b), geo, x(1:3, a), &
          x(4:6, a), x(1:3, b), x(4:6, b), ref(1:3, 2*s - 1), ref(4:6, 2*s - 1), ref(1:3, 2*s), ref(4:6, 2*s))
      end do
      call check(error, count(coef(6, :) /= 0.0_dp) > 0 .and. count(ends == 0) > 0, "rolling springs and ground ends")
      if (allocated(error)) return
      ! all springs, stored
      f = -1.0_dp
      call contact_products(1, ns, normal, coef, dcoef, mix(1, j), mix(2, j), ends, rinv, x, f)
      call check(error, all(f == ref), "contact_products = contact_product per spring, mix " // int_text(j))
      if (allocated(error)) return
      ! listed, from the third entry: spring list(p)'s forces in columns 2p - 1, 2p
      f = -1.0_dp
      call contact_products_listed(3, ns, list, normal, coef, dcoef, mix(1, j), mix(2, j), ends, rinv, x, f)
      same = all(f(:, 1:4) == -1.0_dp)
      do p = 3, ns
        same = same .and. all(f(:, 2*p - 1) == ref(:, 2*list(p) - 1)) .and. all(f(:, 2*p) == ref(:, 2*list(p)))
      end do
      call check(error, same, "contact_products_listed = contact_product per spring, mix " // int_text(j))
      if (allocated(error)) return
      ! added to the bodies in list order (the ground's dropped)
      acc = 0.5_dp
      acc_ref = 0.5_dp
      do p = 2, ns - 1
        s = list(p)
        if (ends(1, s) > 0) acc_ref(:, ends(1, s)) = acc_ref(:, ends(1, s)) + ref(:, 2*s - 1)
        if (ends(2, s) > 0) acc_ref(:, ends(2, s)) = acc_ref(:, ends(2, s)) + ref(:, 2*s)
      end do
      call contact_products_add(2, ns - 1, list, normal, coef, dcoef, mix(1, j), mix(2, j), ends, rinv, x, &
        1, nb, acc)
      call check(error, all(acc == acc_ref), "contact_products_add = contact_product's sums, mix " // int_text(j))
      if (allocated(error)) return
    end do
  end subroutine test_spring_pass

  !> Generalised forces (-f, t_i, f, t_j) of a pair displaced by q from x_i, x_j
  !> (one kernel step from a state without shear load).
  function pair_forces(law, xi, xj, ri, rj, k, e_star, kt, g_star, q) result(g)
    integer, intent(in) :: law
    real(dp), intent(in) :: xi(3), xj(3), ri, rj, k, e_star, kt, g_star, q(12)
    real(dp) :: g(12), br(3), l, n(3), d, rs, f_n, k_t, us(3), f(3), t_i(3), t_j(3)
    br = xj + q(7:9) - xi - q(1:3)
    l = norm2(br)
    n = br/l
    d = ri + rj - l
    rs = reduced_radius(ri, rj)
    f_n = normal_force(law, k, e_star, d, rs)
    k_t = tangential_stiffness(law, kt, g_star, d, rs)
    us = 0.0_dp
    call contact_forces(n, f_n, k_t, -1.0_dp, ri, rj, q(7:9) - q(1:3), q(4:6), q(10:12), us, f, t_i, t_j)
    g(1:3) = -f
    g(4:6) = t_i
    g(7:9) = f
    g(10:12) = t_j
  end function pair_forces

  !> contact_end_blocks against contact_block's columns (12 kernel calls) on
  !> random normals, stiffnesses (rolling and twisting included), arms, rot
  !> and pre-stress, both ends: equal to 1e-14 of the block's largest entry
  !> (a few roundings of entries of order one).
  subroutine test_end_blocks(error)
    type(error_type), allocatable, intent(out) :: error
    real(dp) :: u(12), n(3), k(4), kb(12, 12), own(6, 6), other(6, 6), err
    integer :: trial
    call random_seed_fixed(7)
    err = 0.0_dp
    do trial = 1, 50
      call random_number(u)
      n = u(1:3) - 0.5_dp
      n = n/norm2(n)
      k = [1.0_dp, u(4), 0.3_dp*u(5), 0.2_dp*u(6)]
      if (mod(trial, 3) == 0) k(3:4) = 0.0_dp
      kb = contact_block(n, k, 0.5_dp + u(7), 0.2_dp + u(8), 0.1_dp*u(9), 0.5_dp + u(10), 1.0_dp + u(11))
      call contact_end_blocks(n, k, 0.5_dp + u(7), 0.2_dp + u(8), 0.5_dp + u(10), 1.0_dp + u(11), &
        0.1_dp*u(9), .true., own, other)
      err = max(err, max(maxval(abs(own - kb(1:6, 1:6))), maxval(abs(other - kb(7:12, 1:6))))/maxval(abs(kb)))
      call contact_end_blocks(n, k, 0.5_dp + u(7), 0.2_dp + u(8), 0.5_dp + u(10), 1.0_dp + u(11), &
        0.1_dp*u(9), .false., own, other)
      err = max(err, max(maxval(abs(own - kb(7:12, 7:12))), maxval(abs(other - kb(1:6, 7:12))))/maxval(abs(kb)))
    end do
    call check(error, err <= 1.0e-14_dp, "closed-form end blocks vs contact_block: largest " &
      //"difference "//real_str(err)//" of the block's largest entry")
  end subroutine test_end_blocks

  subroutine test_block_fd(error)
    type(error_type), allocatable, intent(out) :: error
    real(dp) :: xi(3), xj(3), ri, rj, u(3), kb(12, 12), fd(12, 12), q(12), h, l, d, rs, scale
    integer :: trial, law, c
    call random_seed_fixed(5)
    do trial = 1, 20
      law = merge(contact_law%linear, contact_law%hertz, mod(trial, 2) == 0)
      call random_number(u)
      ri = 0.5_dp + u(1)
      rj = 0.3_dp + u(2)
      call random_number(u)
      u = u - 0.5_dp
      u = u/norm2(u)
      xi = [0.1_dp, -0.2_dp, 0.3_dp]
      ! an overlap of 1 to 5 % of the reach
      xj = xi + u*(ri + rj)*(0.95_dp + 0.02_dp*mod(trial, 3))
      l = norm2(xj - xi)
      d = ri + rj - l
      rs = reduced_radius(ri, rj)
      kb = contact_block((xj - xi)/l, [normal_stiffness(law, 1.0e3_dp, 2.0e4_dp, d, rs), &
        tangential_stiffness(law, 400.0_dp, 9.0e3_dp, d, rs), 0.0_dp, 0.0_dp], ri, rj, &
        normal_force(law, 1.0e3_dp, 2.0e4_dp, d, rs)/l)
      ! central differences, step 1e-6 of the size: truncation ~1e-12, rounding ~1e-10
      h = 1.0e-6_dp*l
      do c = 1, 12
        q = 0.0_dp
        q(c) = h
        fd(:, c) = pair_forces(law, xi, xj, ri, rj, 1.0e3_dp, 2.0e4_dp, 400.0_dp, 9.0e3_dp, q)
        q(c) = -h
        fd(:, c) = -(fd(:, c) - pair_forces(law, xi, xj, ri, rj, 1.0e3_dp, 2.0e4_dp, 400.0_dp, &
          9.0e3_dp, q))/(2.0_dp*h)
      end do
      scale = maxval(abs(kb))
      call check(error, maxval(abs(fd - kb))/scale < 1.0e-7_dp, "trial "//real_str(real(trial, dp))// &
        ": |K - FD|/|K| = "//real_str(maxval(abs(fd - kb))/scale))
      if (allocated(error)) return
      ! symmetric
      call check(error, maxval(abs(kb - transpose(kb))) <= 1.0e-14_dp*scale, "block symmetric")
      if (allocated(error)) return
    end do
  end subroutine test_block_fd

  subroutine test_friction(error)
    type(error_type), allocatable, intent(out) :: error
    real(dp) :: us(3), f(3), t_i(3), t_j(3), n(3)
    n = [0.6_dp, 0.8_dp, 0.0_dp]
    us = 0.0_dp
    ! a tangential step of 1 at k_t = 10 would be 10; the cap is 0.5 x 4 = 2
    call contact_forces(n, 4.0_dp, 10.0_dp, 0.5_dp, 1.0_dp, 1.0_dp, [0.0_dp, 0.0_dp, 1.0_dp], &
      [0.0_dp, 0.0_dp, 0.0_dp], [0.0_dp, 0.0_dp, 0.0_dp], us, f, t_i, t_j)
    call check(error, norm2(f - dot_product(f, n)*n), 2.0_dp, rel=.true., thr=1.0e-15_dp, message="capped")
    if (allocated(error)) return
    call check(error, dot_product(f, n), 4.0_dp, rel=.true., thr=1.0e-15_dp, message="normal kept")
    if (allocated(error)) return
    ! the history holds the slipped spring: a step back unloads by k_t du
    call contact_forces(n, 4.0_dp, 10.0_dp, 0.5_dp, 1.0_dp, 1.0_dp, [0.0_dp, 0.0_dp, -0.1_dp], &
      [0.0_dp, 0.0_dp, 0.0_dp], [0.0_dp, 0.0_dp, 0.0_dp], us, f, t_i, t_j)
    call check(error, f(3), -1.0_dp, rel=.true., thr=1.0e-14_dp, message="unloading from the cap")
    if (allocated(error)) return
    ! torques: -r n x f on each body
    call check(error, maxval(abs(t_i + [n(2)*f(3), -n(1)*f(3), 0.0_dp])), 0.0_dp, thr=1.0e-15_dp, &
      message="torque on i")
  end subroutine test_friction

  subroutine random_seed_fixed(k)
    integer, intent(in) :: k
    integer :: n
    integer, allocatable :: s(:)
    call random_seed(size=n)
    allocate(s(n))
    s = 7919*k + [(n, n = 1, size(s))]
    call random_seed(put=s)
  end subroutine random_seed_fixed

  subroutine test_pair(error)
    type(error_type), allocatable, intent(out) :: error
    type(scene_type) :: scene
    type(critical_step_type) :: c
    type(demstep_status_type) :: status
    real(dp) :: expected, kt
    integer :: dim
    do dim = 2, 3
      kt = 70.0_dp
      ! centres 1 apart, reach 1.1
      if (dim == 2) then
        call new_scene(scene, 2, reshape([0.0_dp, 0.0_dp, 0.6_dp, 0.8_dp], [2, 2]), &
          [2.0_dp, 3.0_dp], [0.6_dp, 0.5_dp], status, inertia=[0.25_dp, 0.4_dp])
      else
        call new_scene(scene, 3, reshape([0.0_dp, 0.0_dp, 0.0_dp, 0.0_dp, 0.8_dp, 0.6_dp], [3, 2]), &
          [2.0_dp, 3.0_dp], [0.6_dp, 0.5_dp], status, inertia=[0.25_dp, 0.4_dp])
      end if
      call check(error, status%stat, demstep_stat%ok, "new_scene")
      if (allocated(error)) return
      scene%k_normal = 10.0_dp
      scene%k_tangential = kt
      scene%effects(scene_effect%rotation) = .true.
      call assembly_critical_steps(scene, c, status)
      call check(error, status%stat, demstep_stat%ok, "analysis: "//status%message)
      if (allocated(error)) return
      ! tangential-rotational mode (the normal one, 10 (1/2 + 1/3), is below);
      ! the lever arms reach the contact point, r - d/2 (overlap d = 0.1)
      expected = kt*(1.0_dp/2.0_dp + 1.0_dp/3.0_dp + 0.55_dp**2/0.25_dp + 0.45_dp**2/0.4_dp)
      call check(error, c%omega_max**2, expected, rel=.true., thr=1.0e-12_dp, message="pair in "// &
        real_str(real(dim, dp))//"D")
      if (allocated(error)) return
      call check(error, c%dof_per_particle == merge(3, 6, dim == 2) .and. c%tangential .and. c%rotation, &
        "the model reported")
      if (allocated(error)) return
    end do
  end subroutine test_pair

  !> A ring of n spheres along x in a periodic 2D cell (spacing 1.98 r).
  subroutine ring(scene, n, m, r, kn, kt)
    type(scene_type), intent(out) :: scene
    integer, intent(in) :: n
    real(dp), intent(in) :: m, r, kn, kt
    real(dp) :: x(2, n)
    integer :: i
    type(demstep_status_type) :: status
    do i = 1, n
      x(:, i) = [(i - 1)*1.98_dp*r, 0.0_dp]
    end do
    call new_scene(scene, 2, x, spread(m, 1, n), spread(r, 1, n), status)
    call scene_set_cell(scene, [.true., .false., .false.], [-0.99_dp*r, 0.0_dp, 0.0_dp], &
      [(n - 0.5_dp)*1.98_dp*r, 0.0_dp, 0.0_dp], status)
    scene%k_normal = kn
    scene%k_tangential = kt
    scene%effects(scene_effect%rotation) = .true.
  end subroutine ring

  subroutine test_ring(error)
    type(error_type), allocatable, intent(out) :: error
    type(scene_type) :: scene
    type(critical_step_type) :: c
    type(demstep_status_type) :: status
    integer, parameter :: sizes(3) = [7, 8, 15]
    integer :: k, n
    real(dp) :: expected
    do k = 1, size(sizes)
      n = sizes(k)
      ! longitudinal branch on top: omega^2 = (4 k_n/m) sin^2(q/2), q = 2 pi j/n
      call ring(scene, n, 2.0_dp, 0.5_dp, 50.0_dp, 1.0_dp)
      call assembly_critical_steps(scene, c, status)
      call check(error, status%stat, demstep_stat%ok, "ring: "//status%message)
      if (allocated(error)) return
      call check(error, c%n_springs, n, "ring contacts")
      if (allocated(error)) return
      expected = 4.0_dp*50.0_dp/2.0_dp*sin(pi*(n/2)/real(n, dp))**2
      call check(error, c%omega_max**2, expected, rel=.true., thr=1.0e-12_dp, message="longitudinal, n = "// &
        real_str(real(n, dp)))
      if (allocated(error)) return
      ! transverse-rotational branch on top: omega^2 = 4 k_t (sin^2(q/2)/m + c^2 cos^2(q/2)/I),
      ! largest at q = 0 (every sphere turning the same way): 10 k_t/m (c/r)^2 with
      ! I = 2/5 m r^2 and the lever arm to the contact point c = r - d/2 = 0.99 r
      call ring(scene, n, 2.0_dp, 0.5_dp, 50.0_dp, 30.0_dp)
      call assembly_critical_steps(scene, c, status)
      call check(error, c%omega_max**2, 10.0_dp*30.0_dp/2.0_dp*0.99_dp**2, rel=.true., thr=1.0e-12_dp, &
        message="rotational, n = "//real_str(real(n, dp)))
      if (allocated(error)) return
      ! without rotations the transverse branch is 4 k_t sin^2(q/2)/m
      scene%effects(scene_effect%rotation) = .false.
      call assembly_critical_steps(scene, c, status)
      call check(error, c%omega_max**2, 4.0_dp*max(50.0_dp, 30.0_dp)/2.0_dp*sin(pi*(n/2)/real(n, dp))**2, &
        rel=.true., thr=1.0e-12_dp, message="translations only, n = "//real_str(real(n, dp)))
      if (allocated(error)) return
    end do
  end subroutine test_ring

  !> A periodic simple cubic lattice of m^3 spheres (spacing 1.98 r, mass 1).
  subroutine sc_lattice(scene, m, kn, kt)
    type(scene_type), intent(out) :: scene
    integer, intent(in) :: m
    real(dp), intent(in) :: kn, kt
    real(dp), allocatable :: x(:, :)
    integer :: i, j, k, p
    real(dp), parameter :: a = 1.98_dp*0.5_dp
    type(demstep_status_type) :: status
    allocate(x(3, m**3))
    p = 0
    do k = 1, m
      do j = 1, m
        do i = 1, m
          p = p + 1
          x(:, p) = a*[i - 1, j - 1, k - 1]
        end do
      end do
    end do
    call new_scene(scene, 3, x, spread(1.0_dp, 1, m**3), spread(0.5_dp, 1, m**3), status)
    call scene_set_cell(scene, [.true., .true., .true.], spread(-0.5_dp*a, 1, 3), &
      spread((m - 0.5_dp)*a, 1, 3), status)
    scene%k_normal = kn
    scene%k_tangential = kt
    scene%effects(scene_effect%rotation) = .true.
  end subroutine sc_lattice

  subroutine test_sc_lattice(error)
    type(error_type), allocatable, intent(out) :: error
    type(scene_type) :: scene
    type(critical_step_type) :: c
    type(demstep_status_type) :: status
    ! checkerboard translation: each sphere pushes 2 normal and 4 tangential
    ! springs on both sides: omega^2 = (4 k_n + 8 k_t)/m; the rotational branch
    ! tops at 4 x 2 k_t c^2/I = 20 k_t/m (c/r)^2 (all neighbours turning
    ! oppositely; lever arm c = r - d/2 = 0.99 r)
    call sc_lattice(scene, 4, 1.0e3_dp, 300.0_dp)
    call assembly_critical_steps(scene, c, status)
    call check(error, status%stat, demstep_stat%ok, "sc: "//status%message)
    if (allocated(error)) return
    call check(error, c%n_springs, 3*64, "sc contacts")
    if (allocated(error)) return
    call check(error, c%omega_max**2, 4.0e3_dp + 8.0_dp*300.0_dp, rel=.true., thr=1.0e-12_dp, message="sc")
    if (allocated(error)) return
    call check(error, c%periodic .and. c%dof_per_particle == 6, "the model reported")
    if (allocated(error)) return
    call sc_lattice(scene, 4, 1.0e3_dp, 900.0_dp)
    call assembly_critical_steps(scene, c, status)
    call check(error, c%omega_max**2, max(4.0e3_dp + 8.0_dp*900.0_dp, 20.0_dp*900.0_dp*0.99_dp**2), rel=.true., &
      thr=1.0e-12_dp, message="sc, rotations on top")
  end subroutine test_sc_lattice

  !> A random polydisperse packing in a periodic box: n spheres placed at random
  !> and shrunk to a typical overlap, with rotations and tangential springs.
  subroutine random_packing(scene, n, dim, kt_ratio, fill)
    type(scene_type), intent(out) :: scene
    integer, intent(in) :: n, dim
    real(dp), intent(in) :: kt_ratio, fill
    real(dp), allocatable :: x(:, :), r(:), m(:)
    real(dp) :: box
    type(demstep_status_type) :: status
    allocate(x(dim, n), r(n), m(n))
    call random_number(x)
    call random_number(r)
    r = 0.4_dp + 0.3_dp*r
    call random_number(m)
    m = 1.0_dp + m
    box = (real(n, dp)*fill)**(1.0_dp/dim)
    x = box*x
    call new_scene(scene, dim, x, m, r, status)
    call scene_set_cell(scene, [.true., .true., dim == 3], [0.0_dp, 0.0_dp, 0.0_dp], spread(box, 1, 3), status)
    scene%k_normal = 100.0_dp
    scene%k_tangential = kt_ratio*100.0_dp
    scene%effects(scene_effect%rotation) = .true.
  end subroutine random_packing

  subroutine test_bound_rotations(error)
    type(error_type), allocatable, intent(out) :: error
    type(scene_type) :: scene
    type(critical_step_type) :: c
    type(demstep_status_type) :: status
    integer :: trial
    call random_seed_fixed(11)
    do trial = 1, 30
      call random_packing(scene, 30 + trial, 2 + mod(trial, 2), 0.2_dp + 0.03_dp*trial, 1.0_dp)
      call assembly_critical_steps(scene, c, status, prestress=mod(trial, 3) == 0)
      if (status%stat /= demstep_stat%ok) cycle
      ! LAPACK's eigenvalue is accurate to a few ulps of the matrix norm
      call check(error, c%omega_bound >= c%omega_max*(1.0_dp - 1.0e-13_dp), "bound "// &
        real_str(c%omega_bound)//" below exact "//real_str(c%omega_max))
      if (allocated(error)) return
      call check(error, c%tangential .and. c%rotation, "rotations and tangential springs counted")
      if (allocated(error)) return
    end do
  end subroutine test_bound_rotations

  !> `omega_bound` (the rigorous Collatz-Wielandt bound) against the exact top `omega_max`
  !> (dense LAPACK) on 12 random 3D periodic packings (masses 1 to 2, radii
  !> 0.4 to 0.7, k_t/k_n from 0.2 to 1.85) with rolling and twisting
  !> stiffness ratios each from 0 to 3 and pre-stress in every other one:
  !> never below, to 1e-13 relative (LAPACK's eigenvalue is accurate to a
  !> few ulps of the matrix norm). The rolling and twisting springs enter the
  !> exact top: in the trials with both ratios > 0 (k_r, k_w > 0), the top
  !> differs from the same packing's without them. Measured: the smallest
  !> omega_bound/omega_max over the 12 is 1.133 (trial 8); the bound without
  !> the rolling and twisting terms falls below the exact top there.
  subroutine test_bound_rolling(error)
    type(error_type), allocatable, intent(out) :: error
    type(scene_type) :: scene
    type(critical_step_type) :: c, bare
    type(demstep_status_type) :: status
    integer :: trial, solved, raised
    real(dp) :: rolling, twisting
    logical :: prestress
    call random_seed_fixed(23)
    solved = 0
    raised = 0
    do trial = 1, 12
      rolling = real(mod(trial - 1, 4), dp)
      twisting = 1.5_dp*real(mod(trial - 1, 3), dp)
      prestress = mod(trial, 2) == 0
      call random_packing(scene, 30 + 2*trial, 3, 0.05_dp + 0.15_dp*trial, 0.5_dp + 0.03_dp*trial)
      call assembly_critical_steps(scene, bare, status, prestress=prestress)
      call check(error, status%stat, demstep_stat%ok, "trial "//int_text(trial)//" without rolling: " &
        //status%message)
      if (allocated(error)) return
      call scene_set_rolling(scene, rolling, twisting, status)
      call check(error, status%stat, demstep_stat%ok, "rolling")
      if (allocated(error)) return
      call assembly_critical_steps(scene, c, status, prestress=prestress)
      call check(error, status%stat, demstep_stat%ok, "trial "//int_text(trial)//": "//status%message)
      if (allocated(error)) return
      call check(error, c%eigen_computed .and. c%n_springs > 0 .and. c%rotation .and. c%tangential, &
        "trial "//int_text(trial)//": a dense top with contacts, rotations and tangential springs")
      if (allocated(error)) return
      call check(error, c%omega_bound >= c%omega_max*(1.0_dp - 1.0e-13_dp), "trial "//int_text(trial) &
        //" (rolling "//real_str(rolling)//", twisting "//real_str(twisting)//"): bound " &
        //real_str(c%omega_bound)//" below exact "//real_str(c%omega_max))
      if (allocated(error)) return
      solved = solved + 1
      if (rolling > 0.0_dp .and. twisting > 0.0_dp .and. c%omega_max /= bare%omega_max) raised = raised + 1
    end do
    call check(error, solved == 12 .and. raised == count([(mod(trial - 1, 4) > 0 .and. mod(trial - 1, 3) > 0, &
      trial = 1, 12)]), int_text(raised)//" trials with rolling and twisting changed the top")
  end subroutine test_bound_rolling

  !> The bound's absolute product (`operator_abs_product`) and the bound
  !> itself (`operator_bound`) against their definition computed here, body by
  !> body: each body's own blocks (`contact_end_blocks`) summed in its
  !> `incident` order before they are taken, the other ends' blocks' absolute
  !> values times w v summed spring by spring (q inner), the row scaled and
  !> raised by its rounding allowance; the bound the smallest max r/v of v = 1
  !> and `bound_iterations` steps v <- max(r/max r, 1e-3). On 8 random
  !> periodic packings: 3D (6 components) with fixed particles (springs to the
  !> ground), rolling and twisting springs, the operator mixed (alpha = 0.7),
  !> and 2D (3 components). Exact: the same roundings in the same order, so
  !> the same bits (the products on 1 and 2 threads alike, the blocks of the
  !> first product kept for the second). And the bound (v = 1 alone too: the
  !> Gershgorin row sums) is never below the top eigenvalue of the assembled
  !> matrix (dense LAPACK, accurate to a few ulps of its norm: 1e-13).
  subroutine test_abs_product(error)
    type(error_type), allocatable, intent(out) :: error
    type(scene_type) :: scene
    type(assembly_operator_type) :: op
    type(csr_matrix_type) :: matrix
    type(demstep_status_type) :: status
    real(dp), allocatable :: v(:), u(:), r(:), ref(:), dsum(:, :), a(:, :), z(:)
    real(dp) :: rate, bound, ref_bound, lam, gershgorin
    integer :: trial, dim, step, threads
    call random_seed_fixed(29)
    do trial = 1, 8
      dim = 3
      if (trial == 8) dim = 2
      call random_packing(scene, 24 + 2*trial, dim, 0.3_dp, 0.4_dp + 0.2_dp*trial)
      if (mod(trial, 3) == 1) scene%fixed(1:3) = .true.
      if (mod(trial, 2) == 0 .and. dim == 3) then
        call scene_set_rolling(scene, 0.3_dp*trial, 0.2_dp*trial, status)
        call check(error, status%stat, demstep_stat%ok, "rolling")
        if (allocated(error)) return
      end if
      call assembly_operator(scene, op, rate, status)
      call check(error, status%stat, demstep_stat%ok, "trial "//int_text(trial)//": "//status%message)
      if (allocated(error)) return
      call check(error, op%nc == 3*(dim - 1), "trial "//int_text(trial)//": rotations")
      if (allocated(error)) return
      allocate(v(op%n), u(op%n), r(op%n), ref(op%n), dsum(18, op%n_bodies), z(op%n))
      ! the bound of A' against the dense top of its matrix
      call assembly_matrix(op, matrix)
      call csr_to_dense(matrix, a)
      call largest_eigenpair(a, lam, z, status)
      call check(error, status%stat, demstep_stat%ok, "LAPACK")
      if (allocated(error)) return
      v = 1.0_dp
      call abs_product_reference(op, v, ref)
      gershgorin = maxval(ref)
      bound = operator_bound(op)
      call check(error, bound >= lam*(1.0_dp - 1.0e-13_dp) .and. gershgorin >= bound, "trial " &
        //int_text(trial)//": bound "//real_str(bound)//", Gershgorin "//real_str(gershgorin) &
        //", dense top "//real_str(lam))
      if (allocated(error)) return
      if (trial == 5) call operator_mix(op, 0.7_dp, 0.0_dp)
      ! the products: the first sums the diagonal blocks, the second reuses them
      call random_number(v)
      v = 0.01_dp + v
      call random_number(u)
      do threads = 1, 2
        !$ call omp_set_num_threads(threads)
        call operator_abs_product(op, v, r, dsum, .false.)
        call abs_product_reference(op, v, ref)
        call check(error, all(r == ref), "trial "//int_text(trial)//", "//int_text(threads) &
          //" threads: the product differs by "//real_str(maxval(abs(r - ref)/ref)))
        if (allocated(error)) return
        call operator_abs_product(op, u, r, dsum, .true.)
        call abs_product_reference(op, u, ref)
        call check(error, all(r == ref), "trial "//int_text(trial)//": the second product (blocks kept)")
        if (allocated(error)) return
      end do
      !$ call omp_set_num_threads(omp_get_max_threads())
      ! the bound: Collatz-Wielandt steps on the reference product
      ref_bound = huge(1.0_dp)
      v = 1.0_dp
      do step = 0, bound_iterations
        call abs_product_reference(op, v, ref)
        ref_bound = min(ref_bound, maxval(ref/v))
        v = max(ref/maxval(ref), 1.0e-3_dp)
      end do
      call check(error, operator_bound(op) == ref_bound, "trial "//int_text(trial)//": bound " &
        //real_str(operator_bound(op))//" reference "//real_str(ref_bound))
      if (allocated(error)) return
      deallocate(v, u, r, ref, dsum, z)
    end do
  end subroutine test_abs_product

  !> The bound's absolute product r = |A'| v by its definition (the body-wise
  !> sums of `test_abs_product`).
  subroutine abs_product_reference(op, v, r)
    type(assembly_operator_type), intent(in) :: op
    real(dp), intent(in) :: v(:)
    real(dp), intent(out) :: r(:)
    real(dp) :: d(6, 6), off(6), own(6, 6), other(6, 6), row, k(4), geo
    integer :: i, s, en, j, c, q, nc
    integer(i8) :: p
    nc = op%nc
    do i = 1, op%n_bodies
      d = 0.0_dp
      off = 0.0_dp
      do p = op%first(i), op%first(i + 1) - 1
        s = (op%incident(p) + 1)/2
        en = op%incident(p) - 2*(s - 1)
        call mixed_stiffness(op%coef(:, s), op%dcoef, s, op%alpha, op%beta, k, geo)
        call contact_end_blocks(op%normal(:, s), k, op%coef(3, s), op%coef(4, s), &
          op%rinv(op%ends(1, s)), op%rinv(op%ends(2, s)), 0.0_dp, en == 1, own, other)
        do c = 1, nc
          d(:, c) = d(:, c) + own(:, op%comp(c))
        end do
        j = op%ends(3 - en, s)
        if (j == 0) cycle
        do c = 1, nc
          do q = 1, nc
            off(c) = off(c) + abs(other(op%comp(q), op%comp(c)))*op%w(op%comp(q), j)*v((j - 1)*nc + q)
          end do
        end do
      end do
      do c = 1, nc
        row = off(c)
        do q = 1, nc
          row = row + abs(d(op%comp(q), c))*op%w(op%comp(q), i)*v((i - 1)*nc + q)
        end do
        r((i - 1)*nc + c) = row*op%w(op%comp(c), i)*(1.0_dp + real(nc*(op%first(i + 1) - op%first(i) + 1) &
          + 4, dp)*epsilon(1.0_dp))
      end do
    end do
  end subroutine abs_product_reference

  subroutine test_prestress(error)
    type(error_type), allocatable, intent(out) :: error
    type(scene_type) :: scene
    type(critical_step_type) :: c
    type(demstep_status_type) :: status
    real(dp) :: fl
    ! ring of 8 without tangential springs: the transverse branch is only the
    ! pre-stress, -(F_n/l) 4 sin^2(q/2)/m (negative), so the top is unchanged,
    ! while with k_t it becomes 4 (k_t - F_n/l) sin^2(q/2)/m
    call ring(scene, 8, 2.0_dp, 0.5_dp, 10.0_dp, 30.0_dp)
    scene%effects(scene_effect%rotation) = .false.
    call assembly_critical_steps(scene, c, status, prestress=.true.)
    call check(error, status%stat, demstep_stat%ok, "prestress: "//status%message)
    if (allocated(error)) return
    ! F_n = k_n d, d = 2 r - 1.98 r, l = 1.98 r
    fl = 10.0_dp*0.02_dp*0.5_dp/(1.98_dp*0.5_dp)
    call check(error, c%omega_max**2, 4.0_dp*(30.0_dp - fl)/2.0_dp, rel=.true., thr=1.0e-12_dp, &
      message="transverse with pre-stress")
    if (allocated(error)) return
    call check(error, c%prestress, "reported")
  end subroutine test_prestress

  subroutine test_refusals(error)
    type(error_type), allocatable, intent(out) :: error
    type(scene_type) :: scene
    type(demstep_status_type) :: status
    real(dp) :: x(2, 3)
    x = reshape([0.0_dp, 0.0_dp, 1.0_dp, 0.0_dp, 5.5_dp, 0.0_dp], [2, 3])
    call new_scene(scene, 2, x, [1.0_dp, 1.0_dp, 1.0_dp], [0.6_dp, 0.6_dp, 0.6_dp], status)
    call check(error, status%stat, demstep_stat%ok)
    if (allocated(error)) return
    ! a cell shorter than twice the longest contact (2 x 1.2)
    call scene_set_cell(scene, [.true., .false., .false.], [0.0_dp, 0.0_dp, 0.0_dp], &
      [2.0_dp, 0.0_dp, 0.0_dp], status)
    call check(error, status%stat == demstep_stat%invalid_input .and. index(status%message, "cell_hi:") == 1, &
      "short cell: "//status%message)
    if (allocated(error)) return
    ! positions outside are wrapped
    call scene_set_cell(scene, [.true., .false., .false.], [0.0_dp, 0.0_dp, 0.0_dp], &
      [4.0_dp, 0.0_dp, 0.0_dp], status)
    call check(error, status%stat, demstep_stat%ok, "cell: "//status%message)
    if (allocated(error)) return
    call check(error, scene%x(1, 3), 1.5_dp, thr=1.0e-15_dp, message="wrapped")
    if (allocated(error)) return
    call scene_set_contacts(scene, reshape([1, 4], [2, 1]), reshape([1.0_dp, 1.0_dp], [2, 1]), status)
    call check(error, status%stat == demstep_stat%invalid_input .and. index(status%message, "missing") > 0, &
      "missing particle: "//status%message)
    if (allocated(error)) return
    call scene_set_contacts(scene, reshape([1, 2], [2, 1]), reshape([1.0_dp, -1.0_dp], [2, 1]), status)
    call check(error, status%stat == demstep_stat%invalid_input .and. index(status%message, "k_t") > 0, &
      "negative k_t: "//status%message)
    if (allocated(error)) return
    call new_scene(scene, 2, x, [1.0_dp, 1.0_dp, 1.0_dp], [0.6_dp, 0.6_dp, 0.6_dp], status, &
      inertia=[1.0_dp, 0.0_dp, 1.0_dp])
    call check(error, status%stat == demstep_stat%invalid_input .and. index(status%message, "inertia:") == 1, &
      "inertia 0: "//status%message)
  end subroutine test_refusals

  subroutine test_materials(error)
    type(error_type), allocatable, intent(out) :: error
    type(scene_type) :: scene
    type(critical_step_type) :: c
    type(demstep_status_type) :: status
    real(dp) :: k(2, 2, 2), d, rs, e_star, g_star, kn, kt, mm, rot
    ! three particles in a row: types 1, 2, 1; only the 1-2 pairs touch
    call new_scene(scene, 2, reshape([0.0_dp, 0.0_dp, 1.0_dp, 0.0_dp, 2.0_dp, 0.0_dp], [2, 3]), &
      [1.0_dp, 2.0_dp, 1.0_dp], [0.55_dp, 0.5_dp, 0.55_dp], status)
    k(1, :, :) = reshape([1.0_dp, 40.0_dp, 40.0_dp, 9.0_dp], [2, 2])
    k(2, :, :) = reshape([0.0_dp, 25.0_dp, 25.0_dp, 0.0_dp], [2, 2])
    call scene_set_types(scene, [1, 2, 1], k, status)
    call check(error, status%stat, demstep_stat%ok, "types: "//status%message)
    if (allocated(error)) return
    scene%effects(scene_effect%rotation) = .true.
    call assembly_critical_steps(scene, c, status)
    call check(error, status%stat, demstep_stat%ok, "analysis: "//status%message)
    if (allocated(error)) return
    ! a chain 1-2-1 with the pair's k_n = 40, k_t = 25 (the types' own values
    ! would give other numbers): longitudinally the middle moves against both
    ! ends, omega^2 = k_n (1/m_1 + 2/m_2) = 80; the transverse-rotational top
    ! comes from its 6 x 6 problem, solved here independently
    rot = tri_top(25.0_dp)
    call check(error, c%omega_max**2, max(40.0_dp*(1.0_dp/1.0_dp + 2.0_dp/2.0_dp), rot), rel=.true., &
      thr=1.0e-12_dp, message="linear types")
    if (allocated(error)) return
    ! Hertz: E*, G* of the pair from the types' E and nu
    call new_scene(scene, 3, reshape([0.0_dp, 0.0_dp, 0.0_dp, 1.0_dp, 0.0_dp, 0.0_dp], [3, 2]), &
      [1.0_dp, 2.0_dp], [0.52_dp, 0.5_dp], status)
    scene%law = contact_law%hertz
    call scene_set_hertz_types(scene, [1, 2], [70.0_dp, 210.0_dp], [0.3_dp, 0.25_dp], status)
    call check(error, status%stat, demstep_stat%ok, "hertz types: "//status%message)
    if (allocated(error)) return
    scene%effects(scene_effect%rotation) = .true.
    call assembly_critical_steps(scene, c, status)
    d = 0.02_dp
    rs = 0.52_dp*0.5_dp/1.02_dp
    e_star = 1.0_dp/((1.0_dp - 0.09_dp)/70.0_dp + (1.0_dp - 0.0625_dp)/210.0_dp)
    g_star = 1.0_dp/((2.0_dp - 0.3_dp)/(70.0_dp/2.6_dp) + (2.0_dp - 0.25_dp)/(210.0_dp/2.5_dp))
    kn = 2.0_dp*e_star*sqrt(rs*d)
    kt = 8.0_dp*g_star*sqrt(rs*d)
    mm = 1.0_dp/1.0_dp + 1.0_dp/2.0_dp
    ! lever arms to the contact point: 0.52 - 0.01, 0.5 - 0.01
    call check(error, c%omega_max**2, max(kn*mm, kt*(mm + 0.51_dp**2/(0.4_dp*1.0_dp*0.52_dp**2) + &
      0.49_dp**2/(0.4_dp*2.0_dp*0.5_dp**2))), &
      rel=.true., thr=1.0e-12_dp, message="Hertz types")
    if (allocated(error)) return
    call scene_set_types(scene, [1, 3], k, status)
    call check(error, status%stat == demstep_stat%invalid_input .and. index(status%message, "types:") == 1, &
      "type out of range: "//status%message)
  contains
    !> The top of the rotational-transverse problem of the 1-2-1 chain along x:
    !> dofs (u_y, theta) of each particle, s_c = u_j - u_i - r_i theta_i - r_j theta_j
    !> per contact, by the largest eigenvalue of M^-1/2 K M^-1/2 (6 x 6), found
    !> by power iteration on the shifted matrix (an independent small solver).
    real(dp) function tri_top(kt) result(top)
      real(dp), intent(in) :: kt
      real(dp) :: kmat(6, 6), b(6), m(6), x(6), y(6)
      integer :: e, it
      integer, parameter :: pairs(2, 2) = reshape([1, 2, 2, 3], [2, 2])
      real(dp), parameter :: r(3) = [0.55_dp, 0.5_dp, 0.55_dp], ms(3) = [1.0_dp, 2.0_dp, 1.0_dp]
      ! lever arms to the contact points (both overlaps 0.05): r - 0.025
      real(dp), parameter :: arm(3) = r - 0.025_dp
      kmat = 0.0_dp
      do e = 1, 2
        b = 0.0_dp
        b(2*pairs(1, e) - 1) = -1.0_dp
        b(2*pairs(1, e)) = -arm(pairs(1, e))
        b(2*pairs(2, e) - 1) = 1.0_dp
        b(2*pairs(2, e)) = -arm(pairs(2, e))
        kmat = kmat + kt*spread(b, 2, 6)*spread(b, 1, 6)
      end do
      m = [(ms((e + 1)/2)*merge(1.0_dp, 0.4_dp*r((e + 1)/2)**2, mod(e, 2) == 1), e = 1, 6)]
      kmat = kmat/sqrt(spread(m, 2, 6)*spread(m, 1, 6))
      ! a start with no symmetry (the chain's mirror symmetry could hide the top)
      x = [1.0_dp, 0.3_dp, -0.7_dp, 0.2_dp, 0.5_dp, -0.1_dp]
      do it = 1, 20000
        y = matmul(kmat, x)
        x = y/norm2(y)
      end do
      top = dot_product(x, matmul(kmat, x))
    end function tri_top
  end subroutine test_materials

  !> Runs with the full physics (rotations, tangential springs; per-contact
  !> stiffness from a contact list) at 0.99 and 1.01 of dt_critical_eigen.
  subroutine test_stability_full(error)
    type(error_type), allocatable, intent(out) :: error
    type(scene_type) :: start, scene
    type(critical_step_type) :: c
    type(scene_summary_type) :: summary
    type(demstep_status_type) :: status
    integer, allocatable :: ci(:), cj(:)
    real(dp), allocatable :: cn(:, :), cd(:), k(:, :), v(:, :)
    integer :: which
    call random_seed_fixed(3)
    do which = 1, 3
      select case (which)
      case (1)
        call sc_lattice(start, 3, 1.0e3_dp, 300.0_dp)
      case (2)
        call fcc_lattice(start, 2, 1.0e3_dp, 300.0_dp)
      case (3)
        call random_packing(start, 30, 3, 0.3_dp, 0.9_dp)
        call relax(start)
        ! per-contact stiffness: the contacts of the relaxed packing with k_t
        ! from 0.2 to 0.6 k_n (k_n as relaxed: the packing stays in equilibrium)
        call contact_list(start, ci, cj, cn, cd, status)
        allocate(k(2, size(ci)))
        call random_number(k(2, :))
        k(1, :) = start%k_normal
        k(2, :) = (0.2_dp + 0.4_dp*k(2, :))*start%k_normal
        call scene_set_contacts(start, reshape([ci, cj], [2, size(ci)], order=[2, 1]), k, status)
        call check(error, status%stat, demstep_stat%ok, "contacts: "//status%message)
        if (allocated(error)) return
      end select
      ! small random velocities and angular velocities: the run stays linear
      allocate(v(3, start%n))
      call random_number(v)
      start%v(:start%dim, :) = 1.0e-9_dp*(v(:start%dim, :) - 0.5_dp)
      call random_number(v)
      start%w = 1.0e-9_dp*(v - 0.5_dp)
      deallocate(v)
      ! the stepper's normal force turns with the contact: pre-stress counted
      call assembly_critical_steps(start, c, status, prestress=.true.)
      call check(error, status%stat, demstep_stat%ok, "analysis: "//status%message)
      if (allocated(error)) return
      scene = start
      ! the perturbation's energy is 1e-18 of the elastic energy: bounded, the
      ! total stays to rounding (1e-15 measured); growing, it leaves 1e-6 within
      ! a few hundred steps (it may then saturate as weak contacts open, short of
      ! the stepper's blow-up)
      call scene_run(scene, 0.99_dp*c%dt_critical_eigen, 100000_i8, summary, status)
      call check(error, .not. summary%blew_up .and. summary%energy_drift < 1.0e-9_dp, &
        "bounded at 0.99 (case "//real_str(real(which, dp))//"), drift "//real_str(summary%energy_drift))
      if (allocated(error)) return
      scene = start
      call scene_run(scene, 1.01_dp*c%dt_critical_eigen, 5000_i8, summary, status)
      call check(error, summary%blew_up .or. summary%energy_drift > 1.0e-6_dp, "grows at 1.01 (case "// &
        real_str(real(which, dp))//")")
      if (allocated(error)) return
    end do
  end subroutine test_stability_full

  !> Relax a packing to equilibrium (normal springs only, local damping), then
  !> stop it.
  subroutine relax(scene)
    type(scene_type), intent(inout) :: scene
    type(scene_type) :: soft
    type(critical_step_type) :: c
    type(scene_summary_type) :: summary
    type(demstep_status_type) :: status
    soft = scene
    soft%k_tangential = 0.0_dp
    soft%effects = .false.
    soft%effects(scene_effect%contacts) = .true.
    soft%effects(scene_effect%local_damping) = .true.
    soft%local_damping = 0.7_dp
    call assembly_critical_steps(soft, c, status)
    call scene_run(soft, 0.5_dp*c%dt_critical_eigen, 30000_i8, summary, status)
    scene%x = soft%x
    scene%v = 0.0_dp
    scene%w = 0.0_dp
  end subroutine relax

  !> A periodic FCC lattice of 4 m^3 spheres (nearest-neighbour distance 1.98 r).
  subroutine fcc_lattice(scene, m, kn, kt)
    type(scene_type), intent(out) :: scene
    integer, intent(in) :: m
    real(dp), intent(in) :: kn, kt
    real(dp), allocatable :: x(:, :)
    real(dp), parameter :: basis(3, 4) = reshape([0.0_dp, 0.0_dp, 0.0_dp, 0.5_dp, 0.5_dp, 0.0_dp, &
      0.5_dp, 0.0_dp, 0.5_dp, 0.0_dp, 0.5_dp, 0.5_dp], [3, 4])
    real(dp) :: a
    integer :: i, j, k, b, p
    type(demstep_status_type) :: status
    a = 1.98_dp*0.5_dp*sqrt(2.0_dp)
    allocate(x(3, 4*m**3))
    p = 0
    do k = 0, m - 1
      do j = 0, m - 1
        do i = 0, m - 1
          do b = 1, 4
            p = p + 1
            x(:, p) = a*([real(i, dp), real(j, dp), real(k, dp)] + basis(:, b))
          end do
        end do
      end do
    end do
    call new_scene(scene, 3, x, spread(1.0_dp, 1, p), spread(0.5_dp, 1, p), status)
    call scene_set_cell(scene, [.true., .true., .true.], spread(-0.25_dp*a, 1, 3), &
      spread((m - 0.25_dp)*a, 1, 3), status)
    scene%k_normal = kn
    scene%k_tangential = kt
    scene%effects(scene_effect%rotation) = .true.
  end subroutine fcc_lattice


  !> The matrix-free operator against the dense path: its matrix (assembly_matrix)
  !> equals its products with unit vectors, and its largest eigenvalue (times
  !> rate^2) is the dense solver's omega_max^2.
  subroutine test_operator(error)
    type(error_type), allocatable, intent(out) :: error
    type(scene_type) :: scene
    type(critical_step_type) :: c
    type(assembly_operator_type) :: op
    type(csr_matrix_type) :: matrix
    type(demstep_status_type) :: status
    real(dp), allocatable :: a(:, :), e(:), y(:), z(:)
    real(dp) :: rate, lam
    integer :: trial, j
    call random_seed_fixed(5)
    do trial = 1, 6
      call random_packing(scene, 20 + 3*trial, 2 + mod(trial, 2), 0.3_dp, 1.0_dp)
      if (trial == 3) scene%fixed(1:2) = .true.
      call assembly_operator(scene, op, rate, status, prestress=mod(trial, 2) == 0)
      call check(error, status%stat, demstep_stat%ok, "operator: "//status%message)
      if (allocated(error)) return
      call assembly_matrix(op, matrix)
      call csr_to_dense(matrix, a)
      allocate(e(op%n), y(op%n), z(op%n))
      do j = 1, op%n
        e = 0.0_dp
        e(j) = 1.0_dp
        call assembly_operator_apply(op, e, y)
        ! the same sums in another order: rounding of the entries only
        call check(error, maxval(abs(y - a(:, j))) <= 1.0e-14_dp*maxval(abs(a)), &
          "column "//real_str(real(j, dp))//" of the matrix")
        if (allocated(error)) return
      end do
      call check(error, maxval(abs(a - transpose(a))) <= 1.0e-14_dp*maxval(abs(a)), "symmetric")
      if (allocated(error)) return
      call largest_eigenpair(a, lam, z, status)
      call assembly_critical_steps(scene, c, status, prestress=mod(trial, 2) == 0, &
        solver=eigen_solver%dense)
      ! both are LAPACK on the same numbers up to summation order: a few ulps
      ! of the norm (eigenvalues are well conditioned)
      call check(error, rate**2*lam, c%omega_max**2, rel=.true., thr=1.0e-12_dp, &
        message="operator eigenvalue, trial "//real_str(real(trial, dp)))
      if (allocated(error)) return
      deallocate(e, y, z)
    end do
  end subroutine test_operator

  !> `assembly_matrix_rows` on a 3D packing with rotations and two fixed
  !> particles: the rows of three listed bodies, renumbered by a reversal,
  !> are the matrix's rows (`assembly_matrix`) with the columns renumbered
  !> (the same entries: exact); a listed body out of range, a map of the
  !> wrong size and a new number out of range for a listed body or for a
  !> partner of one are refused; a bad entry for a body the rows do not
  !> touch is not read (the check is O(rows asked)): the rows as before.
  subroutine test_matrix_rows(error)
    type(error_type), allocatable, intent(out) :: error
    type(scene_type) :: scene
    type(assembly_operator_type) :: op
    type(csr_matrix_type) :: matrix
    type(demstep_status_type) :: status
    integer(i8), allocatable :: row_start(:)
    integer, allocatable :: col(:), new_index(:), map(:), partner(:)
    real(dp), allocatable :: val(:), a(:, :), rows(:, :), expected(:, :)
    real(dp) :: rate
    integer :: nb, nc, k, r, u, far, near
    integer, parameter :: bodies(3) = [5, 1, 12]
    call random_seed_fixed(17)
    call random_packing(scene, 40, 3, 0.3_dp, 1.0_dp)
    scene%fixed(2:3) = .true.
    call assembly_operator(scene, op, rate, status)
    call check(error, status%stat, demstep_stat%ok, "operator: "//status%message)
    if (allocated(error)) return
    call assembly_matrix(op, matrix)
    call csr_to_dense(matrix, a)
    nb = op%n_bodies
    nc = op%nc
    new_index = [(nb + 1 - u, u = 1, nb)]
    ! the listed bodies' rows of the matrix, columns renumbered
    allocate(expected(nc*size(bodies), op%n), source=0.0_dp)
    do k = 1, size(bodies)
      do u = 1, nb
        expected((k - 1)*nc + 1:k*nc, (new_index(u) - 1)*nc + 1:new_index(u)*nc) = &
          a((bodies(k) - 1)*nc + 1:bodies(k)*nc, (u - 1)*nc + 1:u*nc)
      end do
    end do
    call rows_of(bodies, new_index)
    if (allocated(error)) return
    call check(error, status%stat, demstep_stat%ok, "rows: "//msg())
    if (allocated(error)) return
    call check(error, all(rows == expected), "the rows are the matrix's, renumbered")
    if (allocated(error)) return
    ! the bodies the rows touch: the listed ones and their partners
    ! (0: untouched, 1: a partner, 2: listed)
    allocate(partner(nb), source=0)
    do u = 1, nb
      do k = 1, size(bodies)
        if (any(a((bodies(k) - 1)*nc + 1:bodies(k)*nc, (u - 1)*nc + 1:u*nc) /= 0.0_dp)) partner(u) = 1
      end do
    end do
    partner(bodies) = 2
    near = findloc(partner, 1, dim=1)
    far = findloc(partner, 0, dim=1)
    call check(error, near > 0 .and. far > 0, "a partner and an untouched body in the packing")
    if (allocated(error)) return
    call rows_of([bodies(1), 0], new_index)
    call refused("listed body 0")
    if (allocated(error)) return
    call rows_of([bodies(1), nb + 1], new_index)
    call refused("listed body n_bodies + 1")
    if (allocated(error)) return
    call rows_of(bodies, new_index(:nb - 1))
    call refused("a map of n_bodies - 1 entries")
    if (allocated(error)) return
    map = new_index
    map(bodies(2)) = 0
    call rows_of(bodies, map)
    call refused("a listed body's new number 0")
    if (allocated(error)) return
    map = new_index
    map(near) = nb + 1
    call rows_of(bodies, map)
    call refused("a partner's new number n_bodies + 1")
    if (allocated(error)) return
    map = new_index
    map(far) = -7
    call rows_of(bodies, map)
    call check(error, status%stat == demstep_stat%ok .and. all(rows == expected), &
      "a bad entry the rows do not read: the rows as before; "//msg())
  contains
    !> The rows as a dense block (nc per listed body, op%n columns).
    subroutine rows_of(list, index)
      integer, intent(in) :: list(:), index(:)
      integer(i8) :: p
      call assembly_matrix_rows(op, list, index, row_start, col, val, status)
      if (allocated(rows)) deallocate(rows)
      allocate(rows(nc*size(list), op%n), source=0.0_dp)
      if (status%stat /= demstep_stat%ok) return
      call check(error, size(row_start) == nc*size(list) + 1, "row starts")
      if (allocated(error)) return
      do r = 1, nc*size(list)
        do p = row_start(r), row_start(r + 1) - 1
          rows(r, col(p)) = rows(r, col(p)) + val(p)
        end do
      end do
    end subroutine rows_of
    !> The last call refused, with no entries.
    subroutine refused(what)
      character(len=*), intent(in) :: what
      call check(error, status%stat == demstep_stat%invalid_input .and. size(col) == 0 .and. &
        size(val) == 0 .and. all(row_start == 1), what//": "//msg())
    end subroutine refused
    function msg() result(text)
      character(len=:), allocatable :: text
      text = "ok"
      if (allocated(status%message)) text = status%message
    end function msg
  end subroutine test_matrix_rows

  !> Lanczos against dense on random periodic packings (2D, 3D, rotations,
  !> pre-stress, damping), a degenerate lattice top and a ring: 1e-10 relative,
  !> and the error bar holds the dense value.
  subroutine test_lanczos_vs_dense(error)
    type(error_type), allocatable, intent(out) :: error
    type(scene_type) :: scene
    type(critical_step_type) :: d, l
    type(demstep_status_type) :: status
    integer :: trial
    call random_seed_fixed(7)
    do trial = 1, 8
      select case (trial)
      case (7)
        ! the simple cubic top is 4 k_n + 8 k_t at the checkerboard: degenerate
        ! with its rotations and three polarisations
        call sc_lattice(scene, 6, 1.0e3_dp, 300.0_dp)
      case (8)
        call ring(scene, 15, 2.0_dp, 0.5_dp, 50.0_dp, 30.0_dp)
      case default
        call random_packing(scene, 60 + 20*trial, 2 + mod(trial, 2), 0.2_dp + 0.05_dp*trial, 1.0_dp)
        scene%effects(scene_effect%damping) = trial > 4
        scene%damping_ratio = 0.1_dp
      end select
      call assembly_critical_steps(scene, d, status, prestress=trial == 2, solver=eigen_solver%dense)
      call check(error, status%stat, demstep_stat%ok, "dense: "//status%message)
      if (allocated(error)) return
      call assembly_critical_steps(scene, l, status, prestress=trial == 2, solver=eigen_solver%lanczos, &
        tolerance=1.0e-10_dp)
      call check(error, status%stat, demstep_stat%ok, "lanczos: "//status%message)
      if (allocated(error)) return
      ! the tolerance 1e-10 bounds the residual; the Rayleigh quotient's
      ! error is below it
      call check(error, l%omega_max**2, d%omega_max**2, rel=.true., thr=1.0e-10_dp, &
        message="lanczos vs dense, trial "//real_str(real(trial, dp)))
      if (allocated(error)) return
      ! the Rayleigh quotient is below lambda_max (up to rounding), the bar above
      call check(error, l%omega_max <= d%omega_max*(1.0_dp + 1.0e-14_dp) .and. &
        l%omega_upper >= d%omega_max*(1.0_dp - 1.0e-14_dp), "the error bar [" // &
        real_str(l%omega_max)//", "//real_str(l%omega_upper)//"] holds "//real_str(d%omega_max))
      if (allocated(error)) return
      call check(error, l%solver == eigen_solver%lanczos .and. d%solver == eigen_solver%dense .and. &
        l%eigen_residual <= 1.0e-10_dp .and. l%eigen_tolerance == 1.0e-10_dp .and. &
        l%eigen_products > 0 .and. l%dt_critical_safe <= l%dt_critical_eigen, "the report")
      if (allocated(error)) return
      ! the damped limit from the top mode: its damping ratio is a smooth function
      ! of the mode (first-order error in the vector, 1e-5 at a 1e-10 residual)
      call check(error, l%dt_critical_damped, d%dt_critical_damped, rel=.true., thr=1.0e-6_dp, &
        message="damped limit, trial "//real_str(real(trial, dp)))
      if (allocated(error)) return
    end do
  end subroutine test_lanczos_vs_dense

  !> The solver choice: auto takes dense up to max_eigen_dof, Lanczos above; none
  !> gives the bound only; bad values are refused by name.
  subroutine test_solver_choice(error)
    type(error_type), allocatable, intent(out) :: error
    type(scene_type) :: scene
    type(critical_step_type) :: c, d
    type(demstep_status_type) :: status
    call random_seed_fixed(9)
    call random_packing(scene, 50, 3, 0.3_dp, 1.0_dp)
    call assembly_critical_steps(scene, d, status)
    call check(error, d%solver == eigen_solver%dense .and. d%eigen_computed .and. &
      d%eigen_tolerance == epsilon(1.0_dp), "auto: dense for 300 dof")
    if (allocated(error)) return
    call assembly_critical_steps(scene, c, status, max_eigen_dof=100, tolerance=1.0e-6_dp)
    call check(error, c%solver == eigen_solver%lanczos .and. c%eigen_computed .and. &
      c%eigen_tolerance == 1.0e-6_dp .and. c%eigen_residual <= 1.0e-6_dp, "auto: Lanczos above max_eigen_dof")
    if (allocated(error)) return
    ! a residual r of the unit mode puts lambda_max within r of theta
    call check(error, c%omega_upper >= d%omega_max*(1.0_dp - 1.0e-14_dp), "1e-6 error bar holds it")
    if (allocated(error)) return
    call check(error, eigen_solver_name(c%solver), "lanczos", "name")
    if (allocated(error)) return
    call assembly_critical_steps(scene, c, status, solver=eigen_solver%none)
    call check(error, status%stat == demstep_stat%ok .and. c%solver == eigen_solver%none .and. &
      .not. c%eigen_computed .and. c%dt_critical_bound == d%dt_critical_bound, "none: the bound only")
    if (allocated(error)) return
    call assembly_critical_steps(scene, c, status, solver=7)
    call check(error, status%stat == demstep_stat%invalid_input .and. &
      index(status%message, "eigen_solver:") == 1, "bad solver: "//status%message)
    if (allocated(error)) return
    call assembly_critical_steps(scene, c, status, solver=eigen_solver%lanczos, tolerance=1.0_dp)
    call check(error, status%stat == demstep_stat%invalid_input .and. &
      index(status%message, "tolerance:") == 1, "bad tolerance: "//status%message)
  end subroutine test_solver_choice

  !> The operator's product is the same for 1 and 2 threads, bit for bit (above
  !> the size where it runs in parallel).
  subroutine test_threads(error)
    type(error_type), allocatable, intent(out) :: error
    type(scene_type) :: scene
    type(assembly_operator_type) :: op
    type(demstep_status_type) :: status
    real(dp), allocatable :: x(:), y1(:), y2(:)
    real(dp) :: rate
    integer :: threads
    call random_seed_fixed(13)
    call random_packing(scene, 3000, 3, 0.3_dp, 1.0_dp)
    call assembly_operator(scene, op, rate, status)
    call check(error, status%stat == demstep_stat%ok .and. op%n_springs > 4096, "a large operator")
    if (allocated(error)) return
    allocate(x(op%n), y1(op%n), y2(op%n))
    call random_number(x)
    threads = 1
    !$ threads = omp_get_max_threads()
    !$ call omp_set_num_threads(1)
    call assembly_operator_apply(op, x, y1)
    !$ call omp_set_num_threads(2)
    call assembly_operator_apply(op, x, y2)
    !$ call omp_set_num_threads(threads)
    call check(error, all(y1 == y2), "1 and 2 threads agree bit for bit")
  end subroutine test_threads

  !> The product in blocks of bodies (`operator_set_blocks`) against the
  !> operator's matrix (`assembly_matrix`, its entries from `contact_block`):
  !> a 3D packing of 3000 spheres (rotations, rolling and twisting springs,
  !> pre-stress, 20 particles fixed: springs to the ground) and a 2D one of
  !> 1500 (3 dof a body), blocks of 1, 7, 64 and 1000 bodies and the
  !> default (one block here). With blocks of 1 body every spring between
  !> two free bodies crosses, with the default none does. y = A'x equals the
  !> matrix times x to 1e-13 of (|A'||x|)_i in every entry i: both are sums
  !> of the same terms (at most 6 (springs + 1) per row, each rounded a few
  !> times) in other orders, so they differ by a few hundred ulps of the
  !> sum of magnitudes at most. On 3D, 1 and 2 threads give the same bits
  !> (above 4096 springs the passes run in parallel), and the springs'
  !> energies (`operator_spring_energies`) sum to x'A'x to 1e-12 of x'|A'||x|.
  subroutine test_product_blocks(error)
    type(error_type), allocatable, intent(out) :: error
    type(scene_type) :: scene
    type(assembly_operator_type) :: op
    type(csr_matrix_type) :: matrix
    type(demstep_status_type) :: status
    real(dp), allocatable :: x(:), y(:), y2(:), ref(:), mag(:), energy(:)
    real(dp) :: rate
    integer :: dim, k, threads, both
    integer, parameter :: sizes(5) = [1, 7, 64, 1000, product_block_bodies]
    call random_seed_fixed(17)
    do dim = 2, 3
      call random_packing(scene, merge(3000, 1500, dim == 3), dim, 0.3_dp, 1.0_dp)
      scene%fixed(1:20) = .true.
      if (dim == 3) then
        call scene_set_rolling(scene, 0.5_dp, 0.7_dp, status)
        call check(error, status%stat, demstep_stat%ok, "rolling")
        if (allocated(error)) return
      end if
      call assembly_operator(scene, op, rate, status, prestress=.true.)
      call check(error, status%stat == demstep_stat%ok .and. (dim == 2 .or. op%n_springs > 4096), &
        "operator, dim "//int_text(dim)//": "//status%message)
      if (allocated(error)) return
      both = count(op%ends(1, :) > 0 .and. op%ends(2, :) > 0)
      call check(error, both > 0 .and. both < op%n_springs, "springs between free bodies and to the ground")
      if (allocated(error)) return
      call assembly_matrix(op, matrix)
      allocate(x(op%n), y(op%n), y2(op%n), ref(op%n), mag(op%n))
      call random_number(x)
      x = x - 0.5_dp
      call csr_apply(matrix, x, ref)
      call csr_abs_product(matrix, abs(x), mag)
      do k = 1, size(sizes)
        call operator_set_blocks(op, sizes(k))
        if (k == 1) then
          call check(error, size(op%cross), both, "blocks of 1 body: every spring between free bodies crosses")
        else if (k == size(sizes)) then
          call check(error, size(op%cross), 0, "one block: no spring crosses")
        end if
        if (allocated(error)) return
        threads = 1
        !$ threads = omp_get_max_threads()
        !$ call omp_set_num_threads(1)
        call assembly_operator_apply(op, x, y)
        !$ call omp_set_num_threads(2)
        call assembly_operator_apply(op, x, y2)
        !$ call omp_set_num_threads(threads)
        call check(error, all(abs(y - ref) <= 1.0e-13_dp*mag), "dim "//int_text(dim)//", blocks of " &
          //int_text(sizes(k))//": A'x = matrix x, largest difference over |A'||x| " &
          //real_str(maxval(abs(y - ref)/max(mag, tiny(1.0_dp)))))
        if (allocated(error)) return
        call check(error, all(y == y2), "dim "//int_text(dim)//", blocks of "//int_text(sizes(k)) &
          //": 1 and 2 threads agree bit for bit")
        if (allocated(error)) return
      end do
      allocate(energy(op%n_springs))
      call operator_spring_energies(op, x, energy)
      call check(error, abs(sum(energy) - dot_product(x, y)) <= 1.0e-12_dp*dot_product(abs(x), mag), &
        "spring energies sum to x'A'x")
      if (allocated(error)) return
      deallocate(x, y, y2, ref, mag, energy)
    end do
  end subroutine test_product_blocks

  !> An operator numbered in a locality order (`spatial_order`, chosen by
  !> `assembly_critical_steps` when most springs would cross the product's
  !> blocks) against the same scene's operator in the given order
  !> (`assembly_operator`, never reordered): a random 3D packing of 60 000
  !> spheres (random positions, so random order: about half the springs
  !> cross the two blocks), rotations, rolling and twisting, 30 fixed. Its products (one
  !> and several at once), springs' energies (per spring, in the caller's
  !> order), matrix and |A'| v are the plain operator's to 1e-13 of the sums
  !> of magnitudes (the same terms summed in other orders, as in
  !> `test_product_blocks`); its bound to 1e-12. The mode returned in the
  !> caller's numbering is an eigenvector of the plain operator: its
  !> measured residual there meets the tolerance, and rate sqrt(its
  !> Rayleigh quotient) is omega_max to 1e-12. The same packing sorted by
  !> position (few springs cross) keeps the given order. A 2D packing with
  !> dashpots (three components a body): 0.5 A' + 2 B' and its matrix the
  !> same to 1e-13.
  subroutine test_locality_order(error)
    type(error_type), allocatable, intent(out) :: error
    integer, parameter :: n = 60000
    type(scene_type) :: scene, sorted
    type(assembly_operator_type) :: op, plain
    type(critical_step_type) :: c
    type(csr_matrix_type) :: matrix
    type(demstep_status_type) :: status
    real(dp), allocatable :: x(:, :), y(:, :), ref(:, :), mag(:), e1(:), e2(:), mode(:), r1(:), r2(:), &
      dsum(:, :), ym(:)
    integer, allocatable :: perm(:)
    real(dp) :: rate, theta, res, scale
    integer :: k, threads
    call random_seed_fixed(23)
    call random_packing(scene, n, 3, 0.3_dp, 1.0_dp)
    scene%fixed(1:30) = .true.
    call scene_set_rolling(scene, 0.5_dp, 0.7_dp, status)
    call check(error, status%stat, demstep_stat%ok, "rolling")
    if (allocated(error)) return
    call check(error, n - 30 >= order_min_bodies, "enough free bodies to be reordered")
    if (allocated(error)) return
    call assembly_critical_steps(scene, c, status, mode=mode, operator_out=op)
    call check(error, status%stat == demstep_stat%ok .and. c%eigen_converged .and. size(mode) == op%n, &
      "steps: "//status%message)
    if (allocated(error)) return
    call check(error, allocated(op%order) .and. allocated(op%spring_order), "random order: the operator reorders")
    if (allocated(error)) return
    call assembly_operator(scene, plain, rate, status)
    call check(error, status%stat, demstep_stat%ok, status%message)
    if (allocated(error)) return
    call check(error, .not. allocated(plain%order) .and. plain%n == op%n .and. plain%n_springs == op%n_springs, &
      "assembly_operator keeps the given order")
    if (allocated(error)) return
    ! products, one and three at once (mixed with the dashpots' 0)
    allocate(x(op%n, 3), y(op%n, 3), ref(op%n, 3), mag(op%n))
    call random_number(x)
    x = x - 0.5_dp
    call assembly_matrix(plain, matrix)
    do k = 1, 3
      call csr_apply(matrix, x(:, k), ref(:, k))
    end do
    call csr_abs_product(matrix, abs(x(:, 1)), mag)
    call assembly_operator_apply(op, x(:, 1), y(:, 1))
    call check(error, all(abs(y(:, 1) - ref(:, 1)) <= 1.0e-13_dp*mag), "A'x, largest difference over |A'||x| " &
      //real_str(maxval(abs(y(:, 1) - ref(:, 1))/max(mag, tiny(1.0_dp)))))
    if (allocated(error)) return
    ! (on one thread: the one-pass path, which several threads leave to the
    ! product one at a time)
    threads = 1
    !$ threads = omp_get_max_threads()
    !$ call omp_set_num_threads(1)
    call operator_products(op, x, [1, 2, 3], [1.0_dp, 2.0_dp, 0.5_dp], [0.0_dp, 0.0_dp, 0.0_dp], y, &
      one_pass=.true.)
    !$ call omp_set_num_threads(threads)
    call check(error, all(abs(y(:, 1) - ref(:, 1)) <= 1.0e-13_dp*mag) .and. &
      maxval(abs(y(:, 2) - 2.0_dp*ref(:, 2))) <= 1.0e-12_dp*maxval(abs(ref(:, 2))) .and. &
      maxval(abs(y(:, 3) - 0.5_dp*ref(:, 3))) <= 1.0e-12_dp*maxval(abs(ref(:, 3))), "several products in one pass")
    if (allocated(error)) return
    ! the operator's own matrix, in the caller's numbering
    call assembly_matrix(op, matrix)
    allocate(ym(op%n))
    call csr_apply(matrix, x(:, 1), ym)
    call check(error, all(abs(ym - ref(:, 1)) <= 1.0e-13_dp*mag), "its matrix")
    if (allocated(error)) return
    ! each spring's energy, in the caller's spring order
    allocate(e1(op%n_springs), e2(op%n_springs))
    call operator_spring_energies(op, x(:, 1), e1)
    call operator_spring_energies(plain, x(:, 1), e2)
    scale = maxval(abs(e2))
    call check(error, maxval(abs(e1 - e2)) <= 1.0e-13_dp*scale, "springs' energies, largest difference " &
      //real_str(maxval(abs(e1 - e2))/scale))
    if (allocated(error)) return
    ! |A'| v and the bound
    allocate(r1(op%n), r2(op%n), dsum(18, op%n_bodies))
    call operator_abs_product(op, abs(x(:, 1)), r1, dsum, .false.)
    call operator_abs_product(plain, abs(x(:, 1)), r2, dsum, .false.)
    call check(error, all(abs(r1 - r2) <= 1.0e-13_dp*r2), "|A'| v")
    if (allocated(error)) return
    call check(error, abs(operator_bound(op) - operator_bound(plain)) <= 1.0e-12_dp*operator_bound(plain), &
      "the bound")
    if (allocated(error)) return
    ! the mode: an eigenvector of the plain operator
    call assembly_operator_apply(plain, mode, ym)
    theta = dot_product(mode, ym)/dot_product(mode, mode)
    res = norm2(ym - theta*mode)/norm2(mode)
    call check(error, res <= c%eigen_tolerance*theta*(1.0_dp + 1.0e-6_dp), "the mode's residual on the plain " &
      //"operator "//real_str(res/theta))
    if (allocated(error)) return
    call check(error, abs(rate*sqrt(theta) - c%omega_max) <= 1.0e-12_dp*c%omega_max, "omega_max from the mode")
    if (allocated(error)) return
    ! sorted by position: few springs cross, the given order is kept
    perm = spatial_order(scene%x)
    sorted = scene
    sorted%x = scene%x(:, perm)
    sorted%mass = scene%mass(perm)
    sorted%radius = scene%radius(perm)
    sorted%inertia = scene%inertia(perm)
    sorted%fixed = scene%fixed(perm)
    call assembly_critical_steps(sorted, c, status, solver=eigen_solver%none, operator_out=op)
    call check(error, status%stat, demstep_stat%ok, status%message)
    if (allocated(error)) return
    call check(error, .not. allocated(op%order), "sorted by position: the given order kept")
    if (allocated(error)) return
    ! 2D (three components a body) with dashpots: alpha A' + beta B'
    call random_packing(scene, n, 2, 0.3_dp, 1.0_dp)
    call scene_set_damping(scene, 0.3_dp, status)
    call check(error, status%stat, demstep_stat%ok, "damping")
    if (allocated(error)) return
    call assembly_critical_steps(scene, c, status, solver=eigen_solver%none, operator_out=op)
    call check(error, status%stat == demstep_stat%ok .and. allocated(op%order) .and. op%nc == 3 .and. &
      size(op%dcoef, 2) > 0, "2D with dashpots, reordered: "//status%message)
    if (allocated(error)) return
    call assembly_operator(scene, plain, rate, status)
    call check(error, status%stat, demstep_stat%ok, status%message)
    if (allocated(error)) return
    call operator_mix(op, 0.5_dp, 2.0_dp)
    call operator_mix(plain, 0.5_dp, 2.0_dp)
    deallocate(x, y, ref, mag, ym)
    allocate(x(op%n, 1), y(op%n, 1), ref(op%n, 1), mag(op%n), ym(op%n))
    call random_number(x)
    x = x - 0.5_dp
    call assembly_matrix(plain, matrix)
    call csr_apply(matrix, x(:, 1), ref(:, 1))
    call csr_abs_product(matrix, abs(x(:, 1)), mag)
    call assembly_operator_apply(op, x(:, 1), y(:, 1))
    call assembly_matrix(op, matrix)
    call csr_apply(matrix, x(:, 1), ym)
    call check(error, all(abs(y(:, 1) - ref(:, 1)) <= 1.0e-13_dp*mag) .and. all(abs(ym - ref(:, 1)) <= &
      1.0e-13_dp*mag), "2D, 0.5 A' + 2 B': product and matrix, largest difference over |A'||x| " &
      //real_str(maxval(abs(y(:, 1) - ref(:, 1))/max(mag, tiny(1.0_dp)))))
  end subroutine test_locality_order

  !> `operator_from_springs` with the order given (a random 3D packing of
  !> 40 spheres, 2 fixed, rotations): the free particles reversed give an
  !> operator whose vectors are in that order: its A'x equals the given-order
  !> operator's product of the same displacements, block for block, to 1e-13
  !> of the sums of magnitudes; an order of size 0 keeps the given order.
  !> Refused, invalid_input naming `order`: a free particle missing, one
  !> listed twice, a fixed particle listed, a number out of range (0, n + 1).
  subroutine test_given_order(error)
    type(error_type), allocatable, intent(out) :: error
    integer, parameter :: n = 40
    type(scene_type) :: scene
    type(spring_block_type), allocatable :: springs(:)
    type(assembly_operator_type) :: plain, op
    type(csr_matrix_type) :: matrix
    type(demstep_status_type) :: status
    real(dp), allocatable :: x(:), y(:), x_own(:), y_own(:), mag(:)
    integer, allocatable :: order(:), ext(:), bad(:, :)
    real(dp) :: rate
    integer :: i, b, k, nc
    call random_seed_fixed(31)
    call random_packing(scene, n, 3, 0.3_dp, 0.6_dp)
    scene%fixed(1:2) = .true.
    call linearise(scene, hertz_linearization%current, 0.0_dp, .false., springs, status)
    call check(error, status%stat, demstep_stat%ok, "linearise: "//status%message)
    if (allocated(error)) return
    call operator_from_springs(3, .true., scene%mass, scene%inertia, scene%radius, springs, .false., plain, &
      rate, status, scene%fixed)
    call check(error, status%stat == demstep_stat%ok .and. .not. allocated(plain%order), "the given order")
    if (allocated(error)) return
    ! the free particles reversed; ext(p): particle p's free number
    order = [(i, i = n, 3, -1)]
    allocate(ext(n))
    ext = [(i - 2, i = 1, n)]
    call operator_from_springs(3, .true., scene%mass, scene%inertia, scene%radius, springs, .false., op, &
      rate, status, scene%fixed, order=order)
    call check(error, status%stat == demstep_stat%ok .and. allocated(op%order) .and. op%own_vectors, &
      "a given order taken: "//status%message)
    if (allocated(error)) return
    nc = op%nc
    allocate(x(plain%n), y(plain%n), x_own(op%n), y_own(op%n), mag(plain%n))
    call random_number(x)
    x = x - 0.5_dp
    do b = 1, size(order)
      k = ext(order(b))
      x_own((b - 1)*nc + 1:b*nc) = x((k - 1)*nc + 1:k*nc)
    end do
    call assembly_operator_apply(plain, x, y)
    call assembly_operator_apply(op, x_own, y_own)
    call assembly_matrix(plain, matrix)
    call csr_abs_product(matrix, abs(x), mag)
    do b = 1, size(order)
      k = ext(order(b))
      call check(error, all(abs(y_own((b - 1)*nc + 1:b*nc) - y((k - 1)*nc + 1:k*nc)) <= &
        1.0e-13_dp*mag((k - 1)*nc + 1:k*nc)), "A'x in the given order, body "//int_text(b))
      if (allocated(error)) return
    end do
    call operator_from_springs(3, .true., scene%mass, scene%inertia, scene%radius, springs, .false., op, &
      rate, status, scene%fixed, order=[integer ::])
    call check(error, status%stat == demstep_stat%ok .and. .not. allocated(op%order) .and. .not. op%own_vectors, &
      "an empty order: the given one")
    if (allocated(error)) return
    ! missing one, one twice, a fixed one, out of range (low, high)
    allocate(bad(n - 2, 2:5))
    do k = 2, 5
      bad(:, k) = order
    end do
    bad(1, 2) = bad(2, 2)
    bad(1, 3) = 1
    bad(1, 4) = 0
    bad(1, 5) = n + 1
    call operator_from_springs(3, .true., scene%mass, scene%inertia, scene%radius, springs, .false., op, &
      rate, status, scene%fixed, order=order(2:))
    call check(error, status%stat == demstep_stat%invalid_input .and. status%where == "order", &
      "a free particle missing: "//status%message)
    if (allocated(error)) return
    do k = 2, 5
      call operator_from_springs(3, .true., scene%mass, scene%inertia, scene%radius, springs, .false., op, &
        rate, status, scene%fixed, order=bad(:, k))
      call check(error, status%stat == demstep_stat%invalid_input .and. status%where == "order", &
        "bad order "//int_text(k)//" refused: "//status%message)
      if (allocated(error)) return
    end do
  end subroutine test_given_order

  !> The contacts are linearised in parallel (above 4096 of them): a Hertz
  !> tangent stiffness that overflows (E* = 0.4 huge, sqrt(R* d) above 1.25)
  !> is refused naming the first such contact in the contact list's order,
  !> on 1 and 2 threads; the same chain without the two deep overlaps
  !> linearises. A chain of 6000 spheres of radius 10 overlapping by 1e-6,
  !> two pairs far apart by 0.5.
  subroutine test_overflow_first(error)
    type(error_type), allocatable, intent(out) :: error
    integer, parameter :: n = 6000
    type(scene_type) :: scene
    type(critical_step_type) :: c
    type(demstep_status_type) :: status
    integer, allocatable :: pi(:), pj(:)
    real(dp), allocatable :: pn(:, :), pd(:)
    real(dp) :: x(1, n), gap(n)
    integer :: i, k, first, threads, t
    gap = 1.0e-6_dp
    gap(3000) = 0.5_dp
    gap(5000) = 0.5_dp
    x(1, 1) = 0.0_dp
    do i = 2, n
      x(1, i) = x(1, i - 1) + 20.0_dp - gap(i - 1)
    end do
    call new_scene(scene, 1, x, spread(1.0_dp, 1, n), spread(10.0_dp, 1, n), status)
    call check(error, status%stat, demstep_stat%ok, status%message)
    if (allocated(error)) return
    scene%law = contact_law%hertz
    ! (2 E* stays finite: the deep pairs' sqrt(R* d) = 1.58 overflows it)
    scene%e_star = 0.4_dp*huge(1.0_dp)
    ! the first deep pair in the list's order
    call contact_list(scene, pi, pj, pn, pd)
    first = 0
    do k = 1, size(pi)
      if (pd(k) > 0.25_dp) then
        first = k
        exit
      end if
    end do
    call check(error, size(pi) == n - 1 .and. first > 0, "the chain's contacts")
    if (allocated(error)) return
    threads = 1
    !$ threads = omp_get_max_threads()
    do t = 1, 2
      !$ call omp_set_num_threads(t)
      call assembly_critical_steps(scene, c, status, solver=eigen_solver%none)
      call check(error, status%stat == demstep_stat%invalid_input .and. status%where == "e_star" .and. &
        index(status%message, "of particles "//int_text(pi(first))//" and "//int_text(pj(first)) &
        //" overflows") > 0, "threads "//int_text(t)//": "//status%message)
      if (allocated(error)) exit
    end do
    !$ call omp_set_num_threads(threads)
    if (allocated(error)) return
    scene%e_star = 1.0e6_dp
    call assembly_critical_steps(scene, c, status, solver=eigen_solver%none)
    call check(error, status%stat == demstep_stat%ok .and. c%n_springs == n - 1, "a finite E*: "//status%message)
  end subroutine test_overflow_first

  !> Lanczos out of restarts (an open chain of 3000: its top eigenvalues are
  !> 1e-6 apart relative, far below a 1e-13 tolerance): not an error, the bracket
  !> [omega_max, omega_upper] holds the closed form 2 sqrt(k/m) sin(pi (N-1)/(2N)).
  subroutine test_not_converged(error)
    type(error_type), allocatable, intent(out) :: error
    type(scene_type) :: scene
    type(critical_step_type) :: c
    type(demstep_status_type) :: status
    integer, parameter :: n = 3000
    real(dp) :: x(1, n), exact
    integer :: i
    do i = 1, n
      x(1, i) = real(i - 1, dp)
    end do
    call new_scene(scene, 1, x, spread(1.0_dp, 1, n), spread(0.55_dp, 1, n), status)
    scene%k_normal = 1.0e4_dp
    call assembly_critical_steps(scene, c, status, solver=eigen_solver%lanczos, tolerance=1.0e-13_dp)
    call check(error, status%stat, demstep_stat%ok, "not converged is not an error: "//status%message)
    if (allocated(error)) return
    exact = 2.0_dp*sqrt(1.0e4_dp)*sin(pi*(n - 1)/(2.0_dp*n))
    call check(error, .not. c%eigen_converged .and. c%eigen_computed .and. c%eigen_residual > 1.0e-13_dp, &
      "reported as not converged")
    if (allocated(error)) return
    call check(error, c%omega_max <= exact*(1.0_dp + 1.0e-14_dp) .and. c%omega_upper >= exact*(1.0_dp - 1.0e-14_dp), &
      "the bracket ["//real_str(c%omega_max)//", "//real_str(c%omega_upper)//"] holds "//real_str(exact))
    if (allocated(error)) return
    call check(error, c%dt_critical_safe <= 2.0_dp/exact .and. c%dt_critical_damped == c%dt_critical_safe .and. &
      c%dt_critical_safe >= c%dt_critical_bound, "the safe step")
  end subroutine test_not_converged

end module test_interaction
