!> Tests of bonds in each code's convention (`demstep_bonds`): the laws from
!> each code's inputs, the stepper's bond forces against the analysis'
!> operator, a bonded pair's four modes and a straight chain's dispersion in
!> closed form, stepper runs just below and above the undamped and damped
!> limits, the peers' rules as ratios to the exact limit, and refusals.
module test_bonds
  use testdrive, only: new_unittest, unittest_type, error_type, check
  use demstep_kinds, only: dp, i8, pi
  use demstep_status, only: demstep_status_type, demstep_stat
  use demstep_scene_data, only: scene_type, scene_summary_type, scene_effect
  use demstep_scene_builders, only: new_scene, scene_add_bonds, scene_set_cell
  use demstep_scene_bonds, only: scene_set_bond_model, scene_bond_law
  use demstep_bonds, only: bond_model, bond_law_type, bond_law, bond_pair_modes, musen_bond_time, &
    musen_recommended_step, kratos_step, exadem_step, musen_step_factor, bond_parameter_count, bond_model_from_name, bond_model_name
  use demstep_assembly, only: assembly_critical_steps, critical_step_type, assembly_operator, &
    assembly_operator_type, assembly_matrix, eigen_solver
  use demstep_csr, only: csr_matrix_type, csr_to_dense
  use demstep_stepper, only: scene_run
  use demstep_packing, only: random_periodic_packing
  use demstep_neighbours, only: contact_list
  use test_support, only: real_str, seed_fixed, ieee_nan, run_app, write_file, work_dir, read_group, take, &
    file_exists
  use demstep_results, only: result_group_type
  use test_yade, only: json_number
  use test_support, only: read_file
  implicit none
  private
  public :: collect_bonds

  interface
    subroutine dsyev(jobz, uplo, n, a, lda, w, work, lwork, info)
      import :: dp
      character, intent(in) :: jobz, uplo
      integer, intent(in) :: n, lda, lwork
      real(dp), intent(inout) :: a(lda, *)
      real(dp), intent(out) :: w(*), work(*)
      integer, intent(out) :: info
    end subroutine dsyev
  end interface

  !> One parameter set per model (pfc, musen, yade, lammps) for spheres of
  !> radius about 1: stiffness of order 1e3 to 1e4.
  real(dp), parameter :: params(8, 4) = reshape([ &
    2.0e3_dp, 8.0e2_dp, 0.7_dp, 0.0_dp, 0.0_dp, 0.0_dp, 0.0_dp, 0.0_dp, &
    5.0e4_dp, 1.9e4_dp, 1.0_dp, 0.0_dp, 0.0_dp, 0.0_dp, 0.0_dp, 0.0_dp, &
    3.0e3_dp, 0.4_dp, 0.6_dp, 0.3_dp, 0.0_dp, 0.0_dp, 0.0_dp, 0.0_dp, &
    4.0e3_dp, 1.5e3_dp, 300.0_dp, 500.0_dp, 0.0_dp, 0.0_dp, 0.0_dp, 0.0_dp], [8, 4])

contains

  subroutine collect_bonds(testsuite)
    type(unittest_type), allocatable, intent(out) :: testsuite(:)
    testsuite = [ &
      new_unittest("each code's inputs -> (k_n, k_t, k_r, k_w), arms, dashpots", test_laws), &
      new_unittest("stepper's bond forces: finite differences = the operator", test_tangent_fd), &
      new_unittest("bonded pair: the four modes in closed form", test_pair_modes), &
      new_unittest("straight periodic chain: the dispersion, whole spectrum", test_chain_dispersion), &
      new_unittest("stepper at 0.99/1.01 of the undamped and damped limits", test_stability), &
      new_unittest("peers' rules: MUSEN 1.64, k_n = k_s 0.535, Kratos", test_peer_rules), &
      new_unittest("peers' rules on chains and a cemented packing", test_peer_rules_chain), &
      new_unittest("Lanczos = dense, undamped and damped, on a cemented packing", test_lanczos_bonds), &
      new_unittest("bonded packings (PFC, Yade) = a dense numpy assembly, every eigenvalue", test_numpy_bonds), &
      new_unittest("bad input refused by name", test_refusals), &
      new_unittest("the app's &scene: bond_model, bond_parameters", test_app_input), &
      new_unittest("Yade cemented samples (CohFrictPhys bonds): the exact limit at Yade's measured one", &
        test_yade_bonded) &
      ]
  end subroutine collect_bonds

  !> A scene of equal or given spheres with bonds between the listed pairs,
  !> contacts off, the model's law on every bond.
  subroutine bonded_scene(scene, x, r, m, pairs, model, p, status)
    type(scene_type), intent(out) :: scene
    real(dp), intent(in) :: x(:, :), r(:), m(:)
    integer, intent(in) :: pairs(:, :), model
    real(dp), intent(in) :: p(:)
    type(demstep_status_type), intent(out) :: status
    call new_scene(scene, 3, x, m, r, status, search=.false.)
    if (status%stat /= demstep_stat%ok) return
    scene%effects(scene_effect%contacts) = .false.
    call scene_add_bonds(scene, pairs, status)
    if (status%stat /= demstep_stat%ok) return
    call scene_set_bond_model(scene, model, p, status)
  end subroutine bonded_scene

  subroutine test_laws(error)
    type(error_type), allocatable, intent(out) :: error
    type(bond_law_type) :: law
    real(dp) :: r, a, i2
    integer :: model
    r = 1.0e-3_dp
    ! PFC, 3D: Rbar = lambda min(r) = 0.5 mm, A = pi Rbar^2, I = pi Rbar^4/4, J = 2 I;
    ! a gap of 0.1 mm: the bond sits in its middle, r + 0.05 mm from each centre
    law = bond_law(bond_model%pfc, [1.0e12_dp, 4.0e11_dp, 0.5_dp], r, r, 2.1e-3_dp, 3)
    a = pi*0.25e-6_dp
    i2 = pi*0.5e-3_dp**4/4.0_dp
    call check(error, near(law%k, [1.0e12_dp*a, 4.0e11_dp*a, 1.0e12_dp*i2, 4.0e11_dp*2.0_dp*i2], 1.0e-14_dp) &
      .and. near(law%arm, [1.05e-3_dp, 1.05e-3_dp], 1.0e-14_dp) .and. all(law%c == 0.0_dp), "pfc 3D")
    if (allocated(error)) return
    ! PFC 2D discs of unit thickness: A = 2 Rbar, I = 2 Rbar^3/3, no twisting;
    ! unequal radii touching: arms are the radii
    law = bond_law(bond_model%pfc, [1.0e9_dp, 4.0e8_dp, 1.0_dp], 1.0e-3_dp, 2.0e-3_dp, 3.0e-3_dp, 2)
    call check(error, near(law%k, [2.0e6_dp, 8.0e5_dp, 1.0e9_dp*2.0e-9_dp/3.0_dp, 0.0_dp], 1.0e-14_dp) .and. &
      near(law%arm, [1.0e-3_dp, 2.0e-3_dp], 1.0e-14_dp), "pfc 2D")
    if (allocated(error)) return
    ! MUSEN: E A/L, G A/L, E I/L, G J/L with A = pi d^2/4, I = pi d^4/64, arms L/2
    law = bond_law(bond_model%musen, [7.0e10_dp, 2.6e10_dp, 1.0e-3_dp], r, r, 2.0e-3_dp, 3)
    a = pi*1.0e-6_dp/4.0_dp
    i2 = pi*1.0e-12_dp/64.0_dp
    call check(error, near(law%k, [7.0e10_dp*a, 2.6e10_dp*a, 7.0e10_dp*i2, 2.6e10_dp*2.0_dp*i2]/2.0e-3_dp, &
      1.0e-14_dp) .and. near(law%arm, [1.0e-3_dp, 1.0e-3_dp], 1.0e-14_dp), "musen")
    if (allocated(error)) return
    ! Yade, equal spheres touching: kn = E r, ks = nu kn, kr = r^2 ks alpha_kr,
    ! ktw = r^2 ks alpha_ktw, arms r; with a gap the shear is alpha = 2r/L
    ! times ks (ScGeom's alpha on the translations)
    law = bond_law(bond_model%yade, [1.0e8_dp, 0.3_dp, 2.0_dp, 0.5_dp], r, r, 2.0e-3_dp, 3)
    call check(error, near(law%k, [1.0e5_dp, 3.0e4_dp, 3.0e4_dp*1.0e-6_dp*2.0_dp, 3.0e4_dp*1.0e-6_dp*0.5_dp], &
      1.0e-14_dp) .and. near(law%arm, [r, r], 1.0e-14_dp), "yade touching")
    if (allocated(error)) return
    law = bond_law(bond_model%yade, [1.0e8_dp, 0.3_dp, 2.0_dp, 0.5_dp], r, r, 2.5e-3_dp, 3)
    call check(error, near(law%k(1:2), [1.0e5_dp, 3.0e4_dp*0.8_dp], 1.0e-14_dp) .and. &
      near(law%arm, [1.25e-3_dp, 1.25e-3_dp], 1.0e-14_dp), "yade with a gap")
    if (allocated(error)) return
    ! Yade's kn: 2 E_a r_a E_b r_b/(E_a r_a + E_b r_b), the harmonic mean of E r_a and E r_b
    law = bond_law(bond_model%yade, [1.0e8_dp, 0.3_dp, 0.0_dp, 0.0_dp], 1.0e-3_dp, 3.0e-3_dp, 4.0e-3_dp, 3)
    call check(error, near(law%k(1:1), [2.0_dp/(1.0_dp/1.0e5_dp + 1.0_dp/3.0e5_dp)], 1.0e-14_dp), &
      "yade kn "//real_str(law%k(1)))
    if (allocated(error)) return
    ! LAMMPS: (K_r, K_s, K_b, K_t), arms r0/2; dashpots (g_n, g_s, g_r r0/2, g_t/2)
    law = bond_law(bond_model%lammps, [1.0_dp, 2.0_dp, 3.0_dp, 4.0_dp, 5.0_dp, 6.0_dp, 7.0_dp, 8.0_dp], &
      r, r, 3.0_dp, 3)
    call check(error, near(law%k, [1.0_dp, 2.0_dp, 4.0_dp, 3.0_dp], 1.0e-15_dp) .and. &
      near(law%c, [5.0_dp, 6.0_dp, 10.5_dp, 4.0_dp], 1.0e-15_dp) .and. near(law%arm, [1.5_dp, 1.5_dp], &
      1.0e-15_dp), "lammps")
    if (allocated(error)) return
    ! the names table
    do model = 1, 4
      call check(error, bond_model_from_name(bond_model_name(model)) == model .and. &
        bond_parameter_count(model) == merge(3, merge(4, 8, model == 3), model <= 2), "names "//bond_model_name(model))
      if (allocated(error)) return
    end do
    call check(error, bond_model_from_name("MUSEN") == bond_model%musen .and. bond_model_from_name("pfc2") == 0, &
      "case folded; unknown word 0")
  end subroutine test_laws

  !> The stepper's generalised forces at the displacement q of a two-particle
  !> scene at rest: one step of length 1 from v = q(1:3), w = q(4:6) (per
  !> particle) moves the particles by q and turns them by q, and the step's
  !> velocity change is the force over the mass.
  function stepper_forces(start, q) result(g)
    type(scene_type), intent(in) :: start
    real(dp), intent(in) :: q(:)
    real(dp) :: g(size(q))
    type(scene_type) :: scene
    type(scene_summary_type) :: summary
    type(demstep_status_type) :: status
    integer :: i
    scene = start
    do i = 1, scene%n
      scene%v(:, i) = q(6*i - 5:6*i - 3)
      scene%w(:, i) = q(6*i - 2:6*i)
    end do
    call scene_run(scene, 1.0_dp, 1_i8, summary, status)
    do i = 1, scene%n
      g(6*i - 5:6*i - 3) = (scene%v(:, i) - q(6*i - 5:6*i - 3))*scene%mass(i)
      g(6*i - 2:6*i) = (scene%w(:, i) - q(6*i - 2:6*i))*scene%inertia(i)
    end do
  end function stepper_forces

  !> For each model on a randomly oriented pair of unequal spheres (with a gap
  !> or an overlap), -dF/dq of the stepper by central differences, mass
  !> scaled, equals rate^2 A' of the analysis' operator. The bond forces are
  !> linear in q, so the differences are exact to rounding: 1e-9 of the
  !> largest entry.
  subroutine test_tangent_fd(error)
    type(error_type), allocatable, intent(out) :: error
    type(scene_type) :: scene
    type(assembly_operator_type) :: op
    type(csr_matrix_type) :: csr
    type(demstep_status_type) :: status
    real(dp), allocatable :: a(:, :)
    real(dp) :: kfd(12, 12), q(12), u(3), x(3, 2), rate, h, w(12), err, g(12)
    integer :: model, c, trial
    integer, parameter :: comp2(6) = [1, 2, 6, 7, 8, 12]
    call seed_fixed(7)
    do trial = 1, 2
      do model = 1, 4
        call random_number(u)
        u = u - 0.5_dp
        x(:, 1) = [0.3_dp, -0.2_dp, 0.1_dp]
        x(:, 2) = x(:, 1) + (2.2_dp + 0.3_dp*(trial - 1.5_dp))*u/norm2(u)
        call bonded_scene(scene, x, [0.9_dp, 1.3_dp], [1.0_dp, 2.5_dp], reshape([1, 2], [2, 1]), model, &
          params(:bond_parameter_count(model), model), status)
        call check(error, status%stat, demstep_stat%ok, status%message)
        if (allocated(error)) return
        h = 1.0e-4_dp
        do c = 1, 12
          q = 0.0_dp
          q(c) = h
          kfd(:, c) = -(stepper_forces(scene, q) - stepper_forces(scene, -q))/(2.0_dp*h)
        end do
        w = 1.0_dp/sqrt([spread(scene%mass(1), 1, 3), spread(scene%inertia(1), 1, 3), &
          spread(scene%mass(2), 1, 3), spread(scene%inertia(2), 1, 3)])
        kfd = kfd*spread(w, 1, 12)*spread(w, 2, 12)
        call assembly_operator(scene, op, rate, status)
        call check(error, status%stat, demstep_stat%ok, status%message)
        if (allocated(error)) return
        call assembly_matrix(op, csr)
        call csr_to_dense(csr, a)
        a = rate**2*a
        err = maxval(abs(kfd - a))/maxval(abs(a))
        call check(error, err < 1.0e-9_dp, bond_model_name(model)//": stepper vs operator, relative "// &
          real_str(err))
        if (allocated(error)) return
        ! and symmetric (the kernel's block)
        call check(error, maxval(abs(kfd - transpose(kfd)))/maxval(abs(kfd)) < 1.0e-9_dp, &
          bond_model_name(model)//": symmetric")
        if (allocated(error)) return
      end do
    end do
    ! 2D (PFC's discs of unit thickness: no twisting): the dof are x, y, theta_z
    do model = 1, 4
      call new_scene(scene, 2, reshape([0.3_dp, -0.2_dp, 1.9_dp, 1.2_dp], [2, 2]), [1.0_dp, 2.5_dp], &
        [0.9_dp, 1.3_dp], status, search=.false.)
      scene%effects(scene_effect%contacts) = .false.
      call scene_add_bonds(scene, reshape([1, 2], [2, 1]), status)
      call scene_set_bond_model(scene, model, params(:bond_parameter_count(model), model), status)
      call check(error, status%stat, demstep_stat%ok, status%message)
      if (allocated(error)) return
      h = 1.0e-4_dp
      kfd = 0.0_dp
      do c = 1, 6
        q = 0.0_dp
        q(comp2(c)) = h
        g = -(stepper_forces(scene, q) - stepper_forces(scene, -q))/(2.0_dp*h)
        kfd(1:6, c) = g(comp2)
      end do
      w(1:6) = 1.0_dp/sqrt([scene%mass(1), scene%mass(1), scene%inertia(1), scene%mass(2), scene%mass(2), &
        scene%inertia(2)])
      kfd(1:6, 1:6) = kfd(1:6, 1:6)*spread(w(1:6), 1, 6)*spread(w(1:6), 2, 6)
      call assembly_operator(scene, op, rate, status)
      call check(error, status%stat == demstep_stat%ok .and. op%n == 6, "2D operator: "//status%message)
      if (allocated(error)) return
      call assembly_matrix(op, csr)
      call csr_to_dense(csr, a)
      a = rate**2*a
      err = maxval(abs(kfd(1:6, 1:6) - a))/maxval(abs(a))
      call check(error, err < 1.0e-9_dp, bond_model_name(model)//" 2D: stepper vs operator, relative "// &
        real_str(err))
      if (allocated(error)) return
    end do
  end subroutine test_tangent_fd

  !> Every eigenvalue of the dense A' of a scene, times rate^2 (ascending).
  subroutine spectrum(scene, lam, status)
    type(scene_type), intent(in) :: scene
    real(dp), allocatable, intent(out) :: lam(:)
    type(demstep_status_type), intent(out) :: status
    type(assembly_operator_type) :: op
    type(csr_matrix_type) :: csr
    real(dp), allocatable :: a(:, :), work(:)
    real(dp) :: rate
    integer :: n, info
    call assembly_operator(scene, op, rate, status)
    if (status%stat /= demstep_stat%ok) return
    call assembly_matrix(op, csr)
    call csr_to_dense(csr, a)
    n = size(a, 1)
    allocate(lam(n), work(max(1, 3*n)*4))
    call dsyev("N", "U", n, a, n, lam, work, size(work), info)
    if (info /= 0) status%stat = demstep_stat%invalid_input
    lam = rate**2*lam
  end subroutine spectrum

  !> An equal-sphere pair (m = 2, r = 1, I = 0.8), each model: the 12
  !> eigenvalues are 0 (six rigid motions), the axial k_n/m*, twice the
  !> shear-rotation k_t (2/m + 2 a^2/I), twice the bending k_r/I* and the
  !> twisting k_w/I* (`bond_pair_modes`); dsyev: to 1e-12 of the largest.
  subroutine test_pair_modes(error)
    type(error_type), allocatable, intent(out) :: error
    type(scene_type) :: scene
    type(demstep_status_type) :: status
    type(critical_step_type) :: crit
    real(dp), allocatable :: lam(:)
    real(dp) :: w2(4), want(12), x(3, 2), u(3)
    integer :: model
    call seed_fixed(3)
    do model = 1, 4
      call random_number(u)
      u = u - 0.5_dp
      x(:, 1) = 0.0_dp
      x(:, 2) = 2.0_dp*u/norm2(u)
      call bonded_scene(scene, x, [1.0_dp, 1.0_dp], [2.0_dp, 2.0_dp], reshape([1, 2], [2, 1]), model, &
        params(:bond_parameter_count(model), model), status)
      call check(error, status%stat, demstep_stat%ok, status%message)
      if (allocated(error)) return
      w2 = bond_pair_modes(scene_bond_law(scene, 1), 2.0_dp, 2.0_dp, 0.8_dp, 0.8_dp)
      want = [0.0_dp, 0.0_dp, 0.0_dp, 0.0_dp, 0.0_dp, 0.0_dp, w2(1), w2(2), w2(2), w2(3), w2(3), w2(4)]
      call sort(want)
      call spectrum(scene, lam, status)
      call check(error, status%stat, demstep_stat%ok, "dsyev")
      if (allocated(error)) return
      call check(error, maxval(abs(lam - want)) <= 1.0e-12_dp*maxval(want), bond_model_name(model)// &
        ": spectrum "//real_str(lam(12))//" vs "//real_str(want(12)))
      if (allocated(error)) return
      ! and the exact limit 2/omega_max through the solver
      call assembly_critical_steps(scene, crit, status, solver=eigen_solver%dense)
      call check(error, status%stat == demstep_stat%ok .and. abs(crit%dt_critical_eigen*sqrt(maxval(w2))/2.0_dp &
        - 1.0_dp) < 1.0e-12_dp, bond_model_name(model)//": limit")
      if (allocated(error)) return
    end do
  end subroutine test_pair_modes

  !> A straight periodic chain of N = 8 equal spheres (m, r = 1, I = 2/5 m r^2)
  !> bonded to their neighbours, spacing L: per wavenumber phi = 2 pi j/N the
  !> axial 2 k_n (1 - cos phi)/m, the twisting 2 k_w (1 - cos phi)/I and, in
  !> each of the two bending planes, the two roots of
  !> [[2 k_t (1 - c)/m, i 2 k_t a sin phi/sqrt(m I)], [., (2 k_t a^2 (1 + c) +
  !> 2 k_r (1 - c))/I]] (shear s = u_{p+1} - u_p - a(theta_p + theta_{p+1}),
  !> bending theta_{p+1} - theta_p). The 48 eigenvalues match to 1e-11 of the
  !> largest (dsyev and the closed form's rounding).
  subroutine test_chain_dispersion(error)
    type(error_type), allocatable, intent(out) :: error
    integer, parameter :: n = 8
    type(scene_type) :: scene
    type(demstep_status_type) :: status
    type(bond_law_type) :: law
    real(dp), allocatable :: lam(:)
    real(dp) :: x(3, n), want(6*n), m, inertia, span, c, s, a11, a22, a12, tr, det
    integer :: pairs(2, n), j, model, k
    m = 1.5_dp
    inertia = 0.4_dp*m
    span = 2.1_dp
    do j = 1, n
      x(:, j) = [(j - 0.5_dp)*span, 0.0_dp, 0.0_dp]
      pairs(:, j) = [j, modulo(j, n) + 1]
    end do
    do model = 1, 4
      call new_scene(scene, 3, x, spread(m, 1, n), spread(1.0_dp, 1, n), status, search=.false.)
      scene%effects(scene_effect%contacts) = .false.
      call scene_set_cell(scene, [.true., .false., .false.], [0.0_dp, -10.0_dp, -10.0_dp], &
        [n*span, 10.0_dp, 10.0_dp], status, search=.false.)
      call check(error, status%stat, demstep_stat%ok, status%message)
      if (allocated(error)) return
      call scene_add_bonds(scene, pairs, status)
      call scene_set_bond_model(scene, model, params(:bond_parameter_count(model), model), status)
      call check(error, status%stat, demstep_stat%ok, status%message)
      if (allocated(error)) return
      law = scene_bond_law(scene, 1)
      k = 0
      do j = 0, n - 1
        c = cos(2.0_dp*pi*j/n)
        s = sin(2.0_dp*pi*j/n)
        a11 = 2.0_dp*law%k(2)*(1.0_dp - c)/m
        a22 = (2.0_dp*law%k(2)*law%arm(1)**2*(1.0_dp + c) + 2.0_dp*law%k(3)*(1.0_dp - c))/inertia
        a12 = 2.0_dp*law%k(2)*law%arm(1)*s/sqrt(m*inertia)
        tr = a11 + a22
        det = a11*a22 - a12**2
        want(k + 1:k + 6) = [2.0_dp*law%k(1)*(1.0_dp - c)/m, 2.0_dp*law%k(4)*(1.0_dp - c)/inertia, &
          0.5_dp*tr - sqrt(max(0.0_dp, 0.25_dp*tr**2 - det)), 0.5_dp*tr + sqrt(max(0.0_dp, 0.25_dp*tr**2 - det)), &
          0.5_dp*tr - sqrt(max(0.0_dp, 0.25_dp*tr**2 - det)), 0.5_dp*tr + sqrt(max(0.0_dp, 0.25_dp*tr**2 - det))]
        k = k + 6
      end do
      call sort(want)
      call spectrum(scene, lam, status)
      call check(error, status%stat, demstep_stat%ok, "dsyev")
      if (allocated(error)) return
      call check(error, maxval(abs(lam - want)) <= 1.0e-11_dp*maxval(want), bond_model_name(model)// &
        ": chain spectrum, top "//real_str(lam(6*n))//" vs "//real_str(want(6*n)))
      if (allocated(error)) return
    end do
  end subroutine test_chain_dispersion

  !> An open chain of 12 bonded spheres of random masses along a bent line,
  !> random small velocities and spins: at 0.99 of the exact limit the
  !> leapfrog's energy (kinetic from the half-step velocities' product), the
  !> scheme's exact invariant for linear springs, stays within 1e-7 of its
  !> start (measured 0.8e-9 to 1.5e-9: rounding, amplified near the limit where
  !> the kinetic product nearly cancels the elastic energy); at 1.01 the top mode grows past 1e6 (blow-up) or to more than
  !> twice the start within 4000 steps (measured growth per step at 1.01:
  !> |lambda| about 1.3). With LAMMPS' dashpots the same at the damped limit:
  !> below, the energy never rises.
  subroutine test_stability(error)
    type(error_type), allocatable, intent(out) :: error
    integer, parameter :: n = 12
    type(scene_type) :: start, scene
    type(scene_summary_type) :: summary
    type(demstep_status_type) :: status
    type(critical_step_type) :: crit
    real(dp) :: x(3, n), m(n), r(n), v(3, n), u(3), dt
    real(dp) :: p(8)
    integer :: pairs(2, n - 1), j, model
    logical :: damped
    call seed_fixed(11)
    x(:, 1) = 0.0_dp
    do j = 2, n
      call random_number(u)
      x(:, j) = x(:, j - 1) + 2.0_dp*[1.0_dp, 0.3_dp*(u(2) - 0.5_dp), 0.3_dp*(u(3) - 0.5_dp)]
      pairs(:, j - 1) = [j - 1, j]
    end do
    call random_number(m)
    m = 1.0_dp + m
    r = 1.0_dp
    do model = 1, 5
      damped = model == 5
      p = params(:, min(model, 4))
      if (damped) p(5:8) = [20.0_dp, 10.0_dp, 6.0_dp, 4.0_dp]
      call bonded_scene(start, x, r, m, pairs, min(model, 4), p(:bond_parameter_count(min(model, 4))), status)
      call check(error, status%stat, demstep_stat%ok, status%message)
      if (allocated(error)) return
      call random_number(v)
      start%v = 1.0e-3_dp*(v - 0.5_dp)
      call random_number(v)
      start%w = 1.0e-3_dp*(v - 0.5_dp)
      call assembly_critical_steps(start, crit, status, solver=eigen_solver%dense)
      call check(error, status%stat == demstep_stat%ok .and. (crit%dashpots(5) .eqv. damped), status%message)
      if (allocated(error)) return
      dt = crit%dt_critical_eigen
      if (damped) then
        call check(error, crit%damped_exact .and. crit%dt_critical_damped < 0.99_dp*dt, "damped limit")
        if (allocated(error)) return
        dt = crit%dt_critical_damped
      end if
      scene = start
      call scene_run(scene, 0.99_dp*dt, 4000_i8, summary, status)
      if (damped) then
        call check(error, .not. summary%blew_up .and. summary%energy_final <= summary%energy_initial, &
          "damped: bounded at 0.99, energy "//real_str(summary%energy_initial)//" -> "// &
          real_str(summary%energy_final))
      else
        call check(error, .not. summary%blew_up .and. summary%energy_drift < 1.0e-7_dp, &
          bond_model_name(model)//": bounded at 0.99, drift "//real_str(summary%energy_drift))
      end if
      if (allocated(error)) return
      scene = start
      call scene_run(scene, 1.01_dp*dt, 4000_i8, summary, status)
      call check(error, summary%blew_up .or. summary%energy_final > 2.0_dp*summary%energy_initial, &
        bond_model_name(min(model, 4))//": grows at 1.01, energy "//real_str(summary%energy_initial)// &
        " -> "//real_str(summary%energy_final))
      if (allocated(error)) return
    end do
  end subroutine test_stability

  !> The peers' rules beside the exact limit on a bonded equal-sphere pair
  !> (r = 1, m = 1, I = 2/5): MUSEN's bond of diameter r (= the sphere radius)
  !> with G = E/(2 (1 + 0.3)): the shear-rotation mode omega^2 = 7 k_t/m tops
  !> the axial 2 k_n/m, and MUSEN's T_bond = 2 sqrt(m/(E A/L)) is
  !> sqrt(7/2.6) = 1.6408 times the exact limit (its recommended step 0.1 of
  !> that); Kratos' sqrt(m/k_n) is half of it, 0.8204, and exaDEM's
  !> pi sqrt(m/k_n) pi times Kratos', 2.5775. With k_n = k_s (LAMMPS,
  !> arms r) the exact limit is sqrt(2/7) = 0.5345 of the normal-only one.
  !> On a 20-sphere open chain the rules' ratios grow (measured here against
  !> the operator, the chain's values in the comments of the report).
  subroutine test_peer_rules(error)
    type(error_type), allocatable, intent(out) :: error
    type(scene_type) :: scene
    type(demstep_status_type) :: status
    type(critical_step_type) :: crit
    type(bond_law_type) :: law
    real(dp) :: x(3, 2), e, g, t_bond, ratio, k_n
    e = 1.0e5_dp
    g = e/(2.0_dp*1.3_dp)
    x(:, 1) = 0.0_dp
    x(:, 2) = [2.0_dp, 0.0_dp, 0.0_dp]
    call bonded_scene(scene, x, [1.0_dp, 1.0_dp], [1.0_dp, 1.0_dp], reshape([1, 2], [2, 1]), bond_model%musen, &
      [e, g, 1.0_dp], status)
    call assembly_critical_steps(scene, crit, status, solver=eigen_solver%dense)
    call check(error, status%stat, demstep_stat%ok, status%message)
    if (allocated(error)) return
    t_bond = musen_bond_time(1.0_dp, 1.0_dp, e, 0.3_dp, 1.0_dp, 2.0_dp)
    ratio = t_bond/crit%dt_critical_eigen
    call check(error, abs(ratio - sqrt(7.0_dp/2.6_dp)) < 1.0e-12_dp .and. abs(ratio - 1.6408_dp) < 1.0e-4_dp, &
      "MUSEN T_bond / exact = "//real_str(ratio))
    if (allocated(error)) return
    call check(error, abs(musen_recommended_step(huge(1.0_dp), t_bond)/crit%dt_critical_eigen - 0.1_dp*ratio) &
      < 1.0e-12_dp, "MUSEN recommended = 0.1 T_bond here")
    if (allocated(error)) return
    law = scene_bond_law(scene, 1)
    k_n = law%k(1)
    ratio = kratos_step(1.0_dp, k_n, 1.0_dp)/crit%dt_critical_eigen
    call check(error, abs(ratio - 0.5_dp*sqrt(7.0_dp/2.6_dp)) < 1.0e-12_dp, "Kratos / exact = "//real_str(ratio))
    if (allocated(error)) return
    ! exaDEM: pi sqrt(m_min/k_n,max), pi times Kratos' here: 2.5775
    ratio = exadem_step(1.0_dp, k_n)/crit%dt_critical_eigen
    call check(error, abs(ratio - 0.5_dp*pi*sqrt(7.0_dp/2.6_dp)) < 1.0e-12_dp .and. abs(ratio - 2.5775_dp) &
      < 1.0e-4_dp, "exaDEM / exact = "//real_str(ratio))
    if (allocated(error)) return
    ! k_n = k_s, the shear spring at the contact point (arms r): LAMMPS' bond
    call bonded_scene(scene, x, [1.0_dp, 1.0_dp], [1.0_dp, 1.0_dp], reshape([1, 2], [2, 1]), bond_model%lammps, &
      [1.0e4_dp, 1.0e4_dp, 0.0_dp, 0.0_dp, 0.0_dp, 0.0_dp, 0.0_dp, 0.0_dp], status)
    call assembly_critical_steps(scene, crit, status, solver=eigen_solver%dense)
    call check(error, status%stat, demstep_stat%ok, status%message)
    if (allocated(error)) return
    ratio = crit%dt_critical_eigen/(2.0_dp/sqrt(2.0_dp*1.0e4_dp/1.0_dp))
    call check(error, abs(ratio - sqrt(2.0_dp/7.0_dp)) < 1.0e-12_dp .and. abs(ratio - 0.5345_dp) < 1.0e-4_dp, &
      "k_n = k_s: exact / normal-only = "//real_str(ratio))
  end subroutine test_peer_rules

  !> MUSEN's, Kratos' and exaDEM's rules (bond diameter = the mean sphere
  !> radius, nu = 0.3) on a straight periodic chain of 20 equal spheres
  !> (closed form: the axial branch's 4 k_n/m tops the shear-rotation's
  !> 4 k_t a^2/I = 3.85 k_n/m, so T_bond/exact = 2, Kratos 1 and exaDEM pi),
  !> an open chain of 20 and a cemented
  !> random packing of 64 spheres (radii 1 +- 15 %, a bond on every contact).
  subroutine test_peer_rules_chain(error)
    type(error_type), allocatable, intent(out) :: error
    integer, parameter :: n = 20
    type(scene_type) :: scene
    type(demstep_status_type) :: status
    type(critical_step_type) :: crit
    type(bond_law_type) :: law
    integer, allocatable :: pi_(:), pj(:)
    real(dp), allocatable :: pn(:, :), pd(:)
    real(dp) :: x(3, n), e, g, t_bond, k_min, r_musen, r_kratos, k_max, r_exadem
    integer :: pairs(2, n), j, k, shape_
    logical :: ok
    e = 1.0e5_dp
    g = e/2.6_dp
    do shape_ = 1, 3
      if (shape_ <= 2) then
        do j = 1, n
          x(:, j) = [(j - 0.5_dp)*2.0_dp, 0.0_dp, 0.0_dp]
          pairs(:, j) = [j, modulo(j, n) + 1]
        end do
        call new_scene(scene, 3, x, spread(1.0_dp, 1, n), spread(1.0_dp, 1, n), status, search=.false.)
        if (shape_ == 1) then
          call scene_set_cell(scene, [.true., .false., .false.], [0.0_dp, -5.0_dp, -5.0_dp], &
            [2.0_dp*n, 5.0_dp, 5.0_dp], status, search=.false.)
          call scene_add_bonds(scene, pairs, status)
        else
          call scene_add_bonds(scene, pairs(:, :n - 1), status)
        end if
      else
        call random_periodic_packing(scene, 64, status, seed=5)
        call check(error, status%stat, demstep_stat%ok, status%message)
        if (allocated(error)) return
        call contact_list(scene, pi_, pj, pn, pd, status)
        call scene_add_bonds(scene, reshape([(pi_(k), pj(k), k = 1, size(pi_))], [2, size(pi_)]), status)
      end if
      scene%effects(scene_effect%contacts) = .false.
      call scene_set_bond_model(scene, bond_model%musen, [e, g, 1.0_dp], status)
      call assembly_critical_steps(scene, crit, status, solver=eigen_solver%dense)
      call check(error, status%stat, demstep_stat%ok, status%message)
      if (allocated(error)) return
      t_bond = huge(1.0_dp)
      do k = 1, size(scene%bonds, 2)
        t_bond = min(t_bond, musen_bond_time(scene%mass(scene%bonds(1, k)), scene%mass(scene%bonds(2, k)), e, &
          0.3_dp, 1.0_dp, norm2(scene%bond_rest(:, k))))
      end do
      ! Kratos: the smallest particle bonded to itself (rest length 2 r_min)
      j = minloc(scene%radius, 1)
      law = bond_law(bond_model%musen, [e, g, 1.0_dp], scene%radius(j), scene%radius(j), 2.0_dp*scene%radius(j), 3)
      k_min = law%k(1)
      r_musen = t_bond/crit%dt_critical_eigen
      r_kratos = kratos_step(minval(scene%mass), k_min, 1.0_dp)/crit%dt_critical_eigen
      ! exaDEM: the lightest particle and the stiffest bond
      k_max = 0.0_dp
      do k = 1, size(scene%bonds, 2)
        law = scene_bond_law(scene, k)
        k_max = max(k_max, law%k(1))
      end do
      r_exadem = exadem_step(minval(scene%mass), k_max)/crit%dt_critical_eigen
      select case (shape_)
      case (1)
        ok = abs(r_musen - 2.0_dp) < 1.0e-12_dp .and. abs(r_kratos - 1.0_dp) < 1.0e-12_dp .and. &
          abs(r_exadem - pi) < 1.0e-12_dp
      case (2)
        ! an open chain's top lies below the infinite chain's (measured 1.9938, 0.9969, 3.1319)
        ok = r_musen > 1.99_dp .and. r_musen <= 2.0_dp .and. abs(r_kratos - 0.5_dp*r_musen) < 1.0e-12_dp .and. &
          abs(r_exadem - pi*r_kratos) < 1.0e-12_dp
      case default
        ! measured 2.886, 1.427 and 4.512 (207 bonds): MUSEN's 0.1 T_bond is safe, Kratos' factor 1
        ! and exaDEM's (at its default threshold 1) are not
        ok = r_musen > 2.0_dp .and. musen_step_factor*r_musen < 1.0_dp .and. r_kratos > 1.0_dp .and. &
          r_exadem > 1.0_dp
      end select
      call check(error, ok, "case "//real_str(real(shape_, dp))//": MUSEN T_bond/exact "//real_str(r_musen)// &
        ", Kratos/exact "//real_str(r_kratos)//", exaDEM/exact "//real_str(r_exadem))
      if (allocated(error)) return
    end do
  end subroutine test_peer_rules_chain

  !> A cemented random packing of 64 spheres (a LAMMPS bond with all four
  !> dashpots on every contact): the matrix-free Lanczos solve gives the dense
  !> solver's undamped and damped limits to its tolerance (1e-10 asked; both
  !> agree to 1e-8 here, the damped Newton steps each to the eigensolver's
  !> tolerance).
  subroutine test_lanczos_bonds(error)
    type(error_type), allocatable, intent(out) :: error
    type(scene_type) :: scene
    type(demstep_status_type) :: status
    type(critical_step_type) :: dense, lanczos
    integer, allocatable :: pi_(:), pj(:)
    real(dp), allocatable :: pn(:, :), pd(:)
    integer :: k
    call random_periodic_packing(scene, 64, status, seed=9)
    call check(error, status%stat, demstep_stat%ok, status%message)
    if (allocated(error)) return
    call contact_list(scene, pi_, pj, pn, pd, status)
    call scene_add_bonds(scene, reshape([(pi_(k), pj(k), k = 1, size(pi_))], [2, size(pi_)]), status)
    scene%effects(scene_effect%contacts) = .false.
    call scene_set_bond_model(scene, bond_model%lammps, [1.0_dp, 0.4_dp, 0.05_dp, 0.08_dp, 0.05_dp, 0.02_dp, &
      0.01_dp, 0.01_dp], status)
    call check(error, status%stat, demstep_stat%ok, status%message)
    if (allocated(error)) return
    call assembly_critical_steps(scene, dense, status, solver=eigen_solver%dense)
    call check(error, status%stat == demstep_stat%ok .and. dense%damped_exact, "dense: "//status%message)
    if (allocated(error)) return
    call assembly_critical_steps(scene, lanczos, status, solver=eigen_solver%lanczos, tolerance=1.0e-10_dp)
    call check(error, status%stat == demstep_stat%ok .and. lanczos%damped_exact, "lanczos: "//status%message)
    if (allocated(error)) return
    call check(error, abs(lanczos%dt_critical_eigen/dense%dt_critical_eigen - 1.0_dp) < 1.0e-8_dp .and. &
      abs(lanczos%dt_critical_damped/dense%dt_critical_damped - 1.0_dp) < 1.0e-8_dp .and. &
      dense%dt_critical_damped < dense%dt_critical_eigen, "undamped "//real_str(lanczos%dt_critical_eigen)// &
      " vs "//real_str(dense%dt_critical_eigen)//", damped "//real_str(lanczos%dt_critical_damped)//" vs "// &
      real_str(dense%dt_critical_damped))
  end subroutine test_lanczos_bonds

  !> Two bonded packings of 27 spheres on a jittered lattice (radii 1 +- 15 %,
  !> gaps and overlaps, 44 and more bonds; PFC parallel bonds and Yade
  !> CohFrictPhys bonds) against the dense numpy assembly of
  !> test/data/numpy_operator/make_reference.py (its own bond laws, blocks and
  !> eigvalsh): every eigenvalue of the operator (times rate^2) to 1e-10 of
  !> the largest (measured 3.5e-15 on the first).
  subroutine test_numpy_bonds(error)
    type(error_type), allocatable, intent(out) :: error
    type(scene_type) :: scene
    type(demstep_status_type) :: status
    character(len=*), parameter :: dir = "test/data/numpy_operator/"
    character(len=256) :: line
    character(len=8) :: name
    real(dp), allocatable :: x(:, :), m(:), r(:), lam(:), lam_ref(:)
    integer, allocatable :: pairs(:, :)
    real(dp) :: p(8)
    integer :: t, u, n, nb, i, model, np
    do t = 1, 2
      open(newunit=u, file=dir//"bonds_"//achar(48 + t)//".txt", status="old", action="read")
      read(u, '(a)') line
      read(line, *) n, nb, name
      model = bond_model_from_name(name)
      np = bond_parameter_count(model)
      read(line, *) n, nb, name, p(:np)
      allocate(x(3, n), m(n), r(n), pairs(2, nb), lam_ref(6*n))
      do i = 1, n
        read(u, *) x(:, i), m(i), r(i)
      end do
      read(u, *) pairs
      read(u, *) lam_ref
      close(u)
      call new_scene(scene, 3, x, m, r, status, search=.false.)
      scene%effects(scene_effect%contacts) = .false.
      call scene_add_bonds(scene, pairs, status)
      if (status%stat == demstep_stat%ok) call scene_set_bond_model(scene, model, p(:np), status)
      if (status%stat == demstep_stat%ok) call spectrum(scene, lam, status)
      call check(error, status%stat, demstep_stat%ok, status%message)
      if (allocated(error)) return
      call check(error, size(lam), size(lam_ref))
      if (allocated(error)) return
      call check(error, maxval(abs(lam - lam_ref)) <= 1.0e-10_dp*maxval(lam_ref), name//": eigenvalues differ by " &
        //real_str(maxval(abs(lam - lam_ref)))//" of "//real_str(maxval(lam_ref)))
      if (allocated(error)) return
      deallocate(x, m, r, pairs, lam_ref)
    end do
  end subroutine test_numpy_bonds

  subroutine test_refusals(error)
    type(error_type), allocatable, intent(out) :: error
    type(scene_type) :: scene
    type(demstep_status_type) :: status
    real(dp) :: x(3, 3)
    x = reshape([0.0_dp, 0.0_dp, 0.0_dp, 2.0_dp, 0.0_dp, 0.0_dp, 4.0_dp, 0.0_dp, 0.0_dp], [3, 3])
    call new_scene(scene, 3, x, [1.0_dp, 1.0_dp, 1.0_dp], [1.0_dp, 1.0_dp, 1.0_dp], status)
    call check(error, status%stat, demstep_stat%ok, status%message)
    if (allocated(error)) return
    ! a negative stiffness, by the parameter's place and name
    call scene_set_bond_model(scene, bond_model%pfc, [1.0e3_dp, -1.0_dp, 1.0_dp], status)
    call check(error, status%stat == demstep_stat%invalid_input .and. status%where == "bond_parameters" .and. &
      status%index == 2 .and. status%message == "bond_parameters(2): kbar_s must be >= 0 and finite", &
      status%message)
    if (allocated(error)) return
    call check(error, scene%bond_model == 0, "scene unchanged")
    if (allocated(error)) return
    call scene_set_bond_model(scene, bond_model%musen, [1.0e3_dp, 1.0_dp, 0.0_dp], status)
    call check(error, status%where == "bond_parameters" .and. status%index == 3 .and. &
      index(status%message, "diameter must be > 0") > 0, status%message)
    if (allocated(error)) return
    call scene_set_bond_model(scene, bond_model%yade, [1.0e3_dp, 0.3_dp], status)
    call check(error, status%where == "bond_parameters" .and. index(status%message, &
      "the yade bond takes 4 values (young, poisson, alpha_kr, alpha_ktw)") > 0, status%message)
    if (allocated(error)) return
    call scene_set_bond_model(scene, 5, [1.0_dp], status)
    call check(error, status%stat == demstep_stat%invalid_input .and. status%where == "bond_model", status%message)
    if (allocated(error)) return
    call scene_set_bond_model(scene, bond_model%lammps, [1.0_dp, 1.0_dp, 1.0_dp, 1.0_dp, ieee_nan(), &
      0.0_dp, 0.0_dp, 0.0_dp], status)
    call check(error, status%where == "bond_parameters" .and. status%index == 5, status%message)
    if (allocated(error)) return
    ! a bond between a particle and itself; an index out of range
    call scene_add_bonds(scene, reshape([1, 2, 3, 3], [2, 2]), status)
    call check(error, status%stat == demstep_stat%invalid_input .and. status%where == "bonds" .and. &
      status%index == 2 .and. index(status%message, "joins particle 3 to itself") > 0, status%message)
    if (allocated(error)) return
    call scene_add_bonds(scene, reshape([1, 4], [2, 1]), status)
    call check(error, status%where == "bonds" .and. status%index == 1 .and. &
      index(status%message, "names a missing particle (1, 4)") > 0, status%message)
    if (allocated(error)) return
    call scene_add_bonds(scene, reshape([0, 1], [2, 1]), status)
    call check(error, status%where == "bonds" .and. index(status%message, "missing particle (0, 1)") > 0, &
      status%message)
  end subroutine test_refusals

  !> The app on a deck of three bonded spheres with each code's bond: its exact
  !> limit is the library's for the same scene (to the 10 digits the result
  !> file keeps, 1e-9); a negative parameter and a bond of a particle to
  !> itself are refused with exit 2 and one line naming the variable.
  subroutine test_app_input(error)
    type(error_type), allocatable, intent(out) :: error
    character(len=*), parameter :: deck = work_dir//"/bonds_deck.nml", out = work_dir//"/bonds_out.nml"
    character(len=*), parameter :: head = "&scene dim = 3, position = 0, 0, 0,  2.1, 0, 0,  4.0, 0.5, 0, " &
      //"mass = 1.0, 1.5, 2.0, radius = 1.0, effects = 'rotation', "
    character(len=*), parameter :: words(4) = [character(len=6) :: "pfc", "musen", "yade", "lammps"]
    type(scene_type) :: scene
    type(critical_step_type) :: crit
    type(demstep_status_type) :: status
    type(result_group_type) :: fields
    character(len=:), allocatable :: stdout, stderr, values
    real(dp) :: dt
    integer :: model, rc, unit, ios, q
    do model = 1, 4
      values = ""
      do q = 1, bond_parameter_count(model)
        values = values//real_str(params(q, model))//", "
      end do
      call write_file(deck, [head//"bonds = 1, 2, 2, 3, bond_model = '"//trim(words(model))//"', " &
        //"bond_parameters = "//values//"/"])
      call run_app("-q "//deck//" -o "//out, rc, stdout, stderr)
      call check(error, rc, 0, message=trim(words(model))//": exit status; stderr: "//stderr)
      if (allocated(error)) return
      open(newunit=unit, file=out, status="old", action="read", iostat=ios)
      if (ios == 0) call read_group(unit, "scene_result", fields, ios)
      if (ios == 0) call take(fields, "dt_critical_eigen", dt, ios)
      if (ios == 0) close(unit)
      call check(error, ios, 0, message="result file")
      if (allocated(error)) return
      call bonded_scene(scene, reshape([0.0_dp, 0.0_dp, 0.0_dp, 2.1_dp, 0.0_dp, 0.0_dp, 4.0_dp, 0.5_dp, &
        0.0_dp], [3, 3]), [1.0_dp, 1.0_dp, 1.0_dp], [1.0_dp, 1.5_dp, 2.0_dp], reshape([1, 2, 2, 3], [2, 2]), &
        model, params(:bond_parameter_count(model), model), status)
      call assembly_critical_steps(scene, crit, status)
      call check(error, status%stat == demstep_stat%ok .and. abs(dt/crit%dt_critical_eigen - 1.0_dp) < 1.0e-9_dp, &
        trim(words(model))//": app "//real_str(dt)//", library "//real_str(crit%dt_critical_eigen))
      if (allocated(error)) return
    end do
    call write_file(deck, [head//"bonds = 1, 2, 2, 3, bond_model = 'pfc', bond_parameters = 1e3, -1, 1 /"])
    call run_app("-q "//deck//" -o "//out, rc, stdout, stderr)
    call check(error, rc == 2 .and. index(stderr, "demstep: "//deck//": &scene: bond_parameters: kbar_s must be " &
      //">= 0 and finite") == 1 .and. count(transfer(stderr, "a", len(stderr)) == new_line("a")) == 1, &
      "negative kbar_s: "//stderr)
    if (allocated(error)) return
    call write_file(deck, [head//"bonds = 1, 2, 2, 2, bond_model = 'musen', bond_parameters = 1e5, 4e4, 1 /"])
    call run_app("-q "//deck//" -o "//out, rc, stdout, stderr)
    call check(error, rc == 2 .and. index(stderr, "demstep: "//deck//": &scene: bonds: bond 2 joins particle 2 " &
      //"to itself") == 1, "self bond: "//stderr)
  end subroutine test_app_input

  !> The cemented Yade samples of validation/yade (yade_bonds.py: 108
  !> spheres, 450 CohFrictPhys bonds with bending and twisting, gaps and
  !> overlaps; equal radii, and radii 1 +- 10 %) through the app with the
  !> 'yade' bond model from Yade's own material inputs: the exact limit lies
  !> within the issue's goal of Yade's measured limit (not above it by more
  !> than 0.5 %, not below by more than 2 %; measured: 1.00001 and 0.99984 of
  !> the brackets' midpoints, brackets of relative width 1e-4). Yade is not
  !> needed: the data are committed.
  subroutine test_yade_bonded(error)
    type(error_type), allocatable, intent(out) :: error
    character(len=*), parameter :: out = work_dir//"/bonded_out.nml"
    character(len=*), parameter :: cases(2) = [character(len=11) :: "bonded", "bonded_poly"]
    type(result_group_type) :: fields
    character(len=:), allocatable :: stdout, stderr, summary
    real(dp) :: dt, lo, hi
    integer :: rc, unit, ios, c
    do c = 1, size(cases)
      call run_app("-q validation/yade/demstep/"//trim(cases(c))//".nml -o "//out, rc, stdout, stderr)
      call check(error, rc, 0, message=trim(cases(c))//": exit status; stderr: "//stderr)
      if (allocated(error)) return
      open(newunit=unit, file=out, status="old", action="read", iostat=ios)
      if (ios == 0) call read_group(unit, "scene_result", fields, ios)
      if (ios == 0) call take(fields, "dt_critical_eigen", dt, ios)
      if (ios == 0) close(unit)
      call check(error, ios, 0, message="result file")
      if (allocated(error)) return
      call read_file("validation/yade/data/"//trim(cases(c))//"/summary.json", summary)
      lo = json_number(summary, "measured_dt_lo", 1)
      hi = json_number(summary, "measured_dt_hi", 1)
      call check(error, lo > 0.0_dp .and. hi > lo, "summary.json read")
      if (allocated(error)) return
      call check(error, dt <= 1.005_dp*hi .and. dt >= 0.98_dp*lo, trim(cases(c))//": exact "//real_str(dt)// &
        " vs measured ["//real_str(lo)//", "//real_str(hi)//"]")
      if (allocated(error)) return
    end do
  end subroutine test_yade_bonded

  !> Whether a and b agree to rel of the largest |b|.
  pure logical function near(a, b, rel)
    real(dp), intent(in) :: a(:), b(:), rel
    near = maxval(abs(a - b)) <= rel*maxval(abs(b))
  end function near

  !> Sort ascending (insertion; short lists).
  pure subroutine sort(a)
    real(dp), intent(inout) :: a(:)
    integer :: i, j
    real(dp) :: t
    do i = 2, size(a)
      t = a(i)
      j = i - 1
      do while (j >= 1)
        if (a(j) <= t) exit
        a(j + 1) = a(j)
        j = j - 1
      end do
      a(j + 1) = t
    end do
  end subroutine sort

end module test_bonds
