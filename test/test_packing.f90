!> Tests of the random periodic packing builder and of tiling a periodic scene:
!> determinism, the contact network's statistics (counted here from the
!> neighbour search), contacts, bonds and explicit contacts of the tiled scene
!> against the original's, its spectrum against the original's (a tiled
!> periodic system has the original's modes) and the refusals.
module test_packing
  use testdrive, only: new_unittest, unittest_type, error_type, check, test_failed
  use demstep_kinds, only: dp, pi
  use demstep_status, only: demstep_status_type, demstep_stat
  use demstep_scene_data, only: scene_type, scene_effect, branch_vector
  use demstep_scene_builders, only: cubic_lattice, scene_add_bonds, scene_set_contacts
  use demstep_packing, only: random_periodic_packing, tile_scene, packing_min_particles, packing_max_particles
  use demstep_neighbours, only: contact_list
  use demstep_interaction, only: contact_law
  use demstep_assembly, only: assembly_critical_steps, critical_step_type, eigen_solver, &
    assembly_operator, assembly_operator_type, assembly_matrix
  use demstep_csr, only: csr_matrix_type, csr_to_dense
  use demstep_lapack, only: largest_eigenpair
  use test_support, only: real_str, ieee_nan
  implicit none
  private
  public :: collect_packing

contains

  subroutine collect_packing(testsuite)
    type(unittest_type), allocatable, intent(out) :: testsuite(:)
    testsuite = [ &
      new_unittest("a seed gives the same packing, another seed another", test_determinism), &
      new_unittest("coordination, overlaps, radii: a dense packing, all in contact", test_statistics), &
      new_unittest("the packing's scene: law, springs, effects, cell", test_scene_settings), &
      new_unittest("tiled: reps product times the contacts, copies shifted", test_tiled_contacts), &
      new_unittest("tiled: bonds and explicit contacts through the images", test_tiled_pairs), &
      new_unittest("tiled 2x1x1: the original's modes; its limit the in- or anti-phase top", test_tiled_limit), &
      new_unittest("bad arguments are refused by name", test_bad_arguments) &
      ]
  end subroutine collect_packing

  !> Contacts per particle and the overlaps over the pair's mean radius.
  subroutine network(scene, count, overlap, status)
    type(scene_type), intent(in) :: scene
    integer, allocatable, intent(out) :: count(:)
    real(dp), allocatable, intent(out) :: overlap(:)
    type(demstep_status_type), intent(out) :: status
    integer, allocatable :: i(:), j(:)
    real(dp), allocatable :: n(:, :), d(:)
    integer :: k
    call contact_list(scene, i, j, n, d, status)
    allocate(count(scene%n), source=0)
    do k = 1, size(i)
      count(i(k)) = count(i(k)) + 1
      count(j(k)) = count(j(k)) + 1
    end do
    overlap = d/(0.5_dp*(scene%radius(i) + scene%radius(j)))
  end subroutine network

  subroutine test_determinism(error)
    type(error_type), allocatable, intent(out) :: error
    type(scene_type) :: a, b, c
    type(demstep_status_type) :: status
    call random_periodic_packing(a, 100, status, seed=7)
    call check(error, status%stat, demstep_stat%ok, status%message)
    if (allocated(error)) return
    call random_periodic_packing(b, 100, status, seed=7)
    call check(error, status%stat, demstep_stat%ok, status%message)
    if (allocated(error)) return
    call check(error, all(a%x == b%x) .and. all(a%radius == b%radius) .and. all(a%mass == b%mass) &
      .and. all(a%cell_hi == b%cell_hi), "seed 7 twice: bit-identical positions, radii, masses, cell")
    if (allocated(error)) return
    call random_periodic_packing(c, 100, status, seed=8)
    call check(error, status%stat, demstep_stat%ok, status%message)
    if (allocated(error)) return
    call check(error, any(c%radius /= a%radius) .and. any(c%x /= a%x), "seed 8 differs from seed 7")
  end subroutine test_determinism

  !> The ranges the builder documents, for three seeds and two sizes.
  subroutine test_statistics(error)
    type(error_type), allocatable, intent(out) :: error
    type(scene_type) :: scene
    type(demstep_status_type) :: status
    integer, allocatable :: count(:)
    real(dp), allocatable :: overlap(:)
    real(dp) :: z, mean_overlap, fraction, r_mean
    integer :: seed, size_case, n
    integer, parameter :: sizes(2) = [100, 300]
    do size_case = 1, 2
      do seed = 1, 3
        n = sizes(size_case)
        call random_periodic_packing(scene, n, status, seed=seed, radius=2.0e-3_dp)
        call check(error, status%stat, demstep_stat%ok, status%message)
        if (allocated(error)) return
        call check(error, scene%n, n, "particle count")
        if (allocated(error)) return
        ! contact_list refuses coincident particles; every particle touches one
        call network(scene, count, overlap, status)
        call check(error, status%stat, demstep_stat%ok, "no coincident particles: "//status%message)
        if (allocated(error)) return
        call check(error, minval(count) >= 1, "every particle in contact (seed "//real_str(real(seed, dp)) &
          //", n "//real_str(real(n, dp))//")")
        if (allocated(error)) return
        z = 2.0_dp*size(overlap)/n
        call check(error, z >= 5.0_dp .and. z <= 7.0_dp, "mean coordination "//real_str(z)//" in [5, 7]")
        if (allocated(error)) return
        mean_overlap = sum(overlap)/size(overlap)
        call check(error, mean_overlap >= 1.0e-3_dp .and. mean_overlap <= 1.0e-2_dp, &
          "mean overlap "//real_str(mean_overlap)//" of the radius in [1e-3, 1e-2]")
        if (allocated(error)) return
        call check(error, maxval(overlap) <= 5.0e-2_dp, "largest overlap "//real_str(maxval(overlap)) &
          //" of the radius below 5e-2")
        if (allocated(error)) return
        ! radii uniform in 1 +- 0.15 before the mean is set to `radius`
        r_mean = sum(scene%radius)/n
        call check(error, abs(r_mean/2.0e-3_dp - 1.0_dp) < 1.0e-12_dp, "mean radius is the one asked")
        if (allocated(error)) return
        call check(error, maxval(scene%radius)/minval(scene%radius) <= 1.15_dp/0.85_dp*(1.0_dp + 1.0e-12_dp), &
          "radii within 1 +- 0.15")
        if (allocated(error)) return
        fraction = sum(4.0_dp/3.0_dp*pi*scene%radius**3)/product(scene%cell_hi - scene%cell_lo)
        call check(error, fraction > 0.62_dp .and. fraction < 0.68_dp, "packing fraction " &
          //real_str(fraction)//" near random close packing")
        if (allocated(error)) return
      end do
    end do
  end subroutine test_statistics

  subroutine test_scene_settings(error)
    type(error_type), allocatable, intent(out) :: error
    type(scene_type) :: scene
    type(demstep_status_type) :: status
    call random_periodic_packing(scene, 64, status, seed=3, k_normal=1.0e6_dp, density=2500.0_dp, &
      radius=1.0e-3_dp)
    call check(error, status%stat, demstep_stat%ok, status%message)
    if (allocated(error)) return
    call check(error, scene%law == contact_law%linear .and. scene%k_normal == 1.0e6_dp .and. &
      abs(scene%k_tangential/(2.0_dp/7.0_dp*1.0e6_dp) - 1.0_dp) < 1.0e-15_dp, "linear, k_t = 2/7 k_n")
    if (allocated(error)) return
    call check(error, scene%effects(scene_effect%contacts) .and. scene%effects(scene_effect%rotation) &
      .and. count(scene%effects) == 2, "contacts and rotation on, nothing else")
    if (allocated(error)) return
    call check(error, all(scene%periodic) .and. all(scene%cell_lo == 0.0_dp) .and. &
      all(scene%cell_hi == scene%cell_hi(1)), "a cubic periodic cell from 0")
    if (allocated(error)) return
    ! mass 4/3 pi r^3 rho, inertia 2/5 m r^2 (to rounding)
    call check(error, maxval(abs(scene%mass/(4.0_dp/3.0_dp*pi*scene%radius**3*2500.0_dp) - 1.0_dp)) < 1.0e-14_dp &
      .and. maxval(abs(scene%inertia/(0.4_dp*scene%mass*scene%radius**2) - 1.0_dp)) < 1.0e-14_dp, &
      "masses and inertia of solid spheres")
    if (allocated(error)) return
    call random_periodic_packing(scene, 64, status, seed=3, k_tangential=0.5_dp, damping_ratio=0.3_dp)
    call check(error, status%stat, demstep_stat%ok, status%message)
    if (allocated(error)) return
    call check(error, scene%k_tangential == 0.5_dp .and. scene%effects(scene_effect%damping) .and. &
      scene%damping_ratio == 0.3_dp, "k_t and damping as given")
  end subroutine test_scene_settings

  subroutine test_tiled_contacts(error)
    type(error_type), allocatable, intent(out) :: error
    type(scene_type) :: scene, tiled
    type(demstep_status_type) :: status
    integer, allocatable :: count(:), count_t(:)
    real(dp), allocatable :: overlap(:), overlap_t(:)
    real(dp) :: box(3)
    integer :: r, t, k, copies
    integer, parameter :: reps(3, 3) = reshape([2, 1, 1, 2, 3, 1, 1, 1, 2], [3, 3])
    call random_periodic_packing(scene, 100, status, seed=5)
    call check(error, status%stat, demstep_stat%ok, status%message)
    if (allocated(error)) return
    call network(scene, count, overlap, status)
    box = scene%cell_hi - scene%cell_lo
    do r = 1, size(reps, 2)
      call tile_scene(scene, reps(:, r), tiled, status)
      call check(error, status%stat, demstep_stat%ok, status%message)
      if (allocated(error)) return
      copies = product(reps(:, r))
      call check(error, tiled%n, copies*scene%n, "particles")
      if (allocated(error)) return
      call check(error, all(tiled%cell_hi == scene%cell_lo + reps(:, r)*box), "the cell grows reps times")
      if (allocated(error)) return
      call network(tiled, count_t, overlap_t, status)
      call check(error, status%stat, demstep_stat%ok, status%message)
      if (allocated(error)) return
      ! every contact, those across the cell boundary included, once per copy
      call check(error, size(overlap_t), copies*size(overlap), "contacts: reps product times the original's")
      if (allocated(error)) return
      do t = 0, copies - 1
        call check(error, all(count_t(t*scene%n + 1:(t + 1)*scene%n) == count), &
          "each copy's particles keep their contact counts")
        if (allocated(error)) return
        call check(error, all(tiled%radius(t*scene%n + 1:(t + 1)*scene%n) == scene%radius) .and. &
          all(tiled%mass(t*scene%n + 1:(t + 1)*scene%n) == scene%mass), "radii and masses repeated")
        if (allocated(error)) return
      end do
      ! copy (1, 0, 0) is shifted by one cell length along x
      if (reps(1, r) > 1) then
        do k = 1, scene%n
          if (any(abs(tiled%x(:, scene%n + k) - scene%x(:, k) - [box(1), 0.0_dp, 0.0_dp]) > 1.0e-12_dp*box(1))) then
            call test_failed(error, "copy (1, 0, 0) is not the original shifted by the cell along x")
            return
          end if
        end do
      end if
    end do
  end subroutine test_tiled_contacts

  !> Bonds and an explicit contact list made from the packing's contacts: in
  !> the tiled scene each bond's branch vector is still its rest vector, and
  !> every explicit contact still overlaps.
  subroutine test_tiled_pairs(error)
    type(error_type), allocatable, intent(out) :: error
    type(scene_type) :: scene, tiled
    type(demstep_status_type) :: status
    integer, allocatable :: i(:), j(:)
    real(dp), allocatable :: n(:, :), d(:), k(:, :)
    integer :: b, nc
    call random_periodic_packing(scene, 80, status, seed=2)
    call check(error, status%stat, demstep_stat%ok, status%message)
    if (allocated(error)) return
    call contact_list(scene, i, j, n, d, status)
    nc = size(i)
    call scene_add_bonds(scene, reshape([i, j], [2, nc], order=[2, 1]), status)
    call check(error, status%stat, demstep_stat%ok, status%message)
    if (allocated(error)) return
    allocate(k(2, nc), source=1.0_dp)
    call scene_set_contacts(scene, reshape([i, j], [2, nc], order=[2, 1]), k, status)
    call check(error, status%stat, demstep_stat%ok, status%message)
    if (allocated(error)) return
    call tile_scene(scene, [2, 2, 1], tiled, status)
    call check(error, status%stat, demstep_stat%ok, status%message)
    if (allocated(error)) return
    call check(error, size(tiled%bonds, 2) == 4*nc .and. size(tiled%contact_pairs, 2) == 4*nc, &
      "bonds and explicit contacts repeated 4 times")
    if (allocated(error)) return
    do b = 1, size(tiled%bonds, 2)
      if (norm2(branch_vector(tiled, tiled%bonds(1, b), tiled%bonds(2, b)) - tiled%bond_rest(:, b)) &
          > 1.0e-12_dp*norm2(tiled%bond_rest(:, b))) then
        call test_failed(error, "tiled bond "//real_str(real(b, dp))//" does not join the nearest image")
        return
      end if
    end do
    call contact_list(tiled, i, j, n, d, status)
    call check(error, size(i), 4*nc, "every explicit contact of the tiled scene overlaps")
  end subroutine test_tiled_pairs

  !> A tiled periodic system has the original's modes: with the 2x1x1 tiled
  !> matrix in blocks [[B11, B12], [B21, B22]] (copy 0, copy 1), translation
  !> makes B22 = B11 and B21 = B12, so its spectrum is that of B11 + B12
  !> (in-phase modes (u, u)) and of B11 - B12 (anti-phase (u, -u)). The test
  !> checks that B11 + B12 is the original's matrix, that the tiled top is the
  !> larger of the two tops, and that assembly_critical_steps reports these
  !> (dense) limits; the tiled limit equals the original's exactly when the
  !> in-phase top is the larger (seeds 2 and 3 here), and exceeds it otherwise
  !> (seed 1: an anti-phase mode 2.5e-5 higher).
  subroutine test_tiled_limit(error)
    type(error_type), allocatable, intent(out) :: error
    type(scene_type) :: scene, tiled
    type(demstep_status_type) :: status
    type(critical_step_type) :: r1, r2
    type(assembly_operator_type) :: op
    type(csr_matrix_type) :: m
    real(dp), allocatable :: a1(:, :), a2(:, :), work(:, :), v(:)
    real(dp) :: rate1, rate2, lam1, lam2, lam_in, lam_anti, scale
    integer :: seed, nd
    do seed = 1, 3
      call random_periodic_packing(scene, 100, status, seed=seed)
      call check(error, status%stat, demstep_stat%ok, status%message)
      if (allocated(error)) return
      call tile_scene(scene, [2, 1, 1], tiled, status)
      call check(error, status%stat, demstep_stat%ok, status%message)
      if (allocated(error)) return
      call assembly_operator(scene, op, rate1, status)
      call check(error, status%stat, demstep_stat%ok, status%message)
      if (allocated(error)) return
      call assembly_matrix(op, m)
      call csr_to_dense(m, a1)
      call assembly_operator(tiled, op, rate2, status)
      call check(error, status%stat, demstep_stat%ok, status%message)
      if (allocated(error)) return
      call assembly_matrix(op, m)
      call csr_to_dense(m, a2)
      nd = size(a1, 1)
      call check(error, nd == 600 .and. size(a2, 1) == 2*nd, "600 and 1200 dof")
      if (allocated(error)) return
      call check(error, rate1 == rate2, "the same scaling")
      if (allocated(error)) return
      ! coordinates up to 2 cells (17 radii) carry 17 eps of rounding into branch
      ! vectors of length ~2, normals and entries to ~1e-15 of the largest entry
      scale = maxval(abs(a1))
      call check(error, maxval(abs(a2(nd+1:, nd+1:) - a2(:nd, :nd))) <= 1.0e-13_dp*scale .and. &
        maxval(abs(a2(nd+1:, :nd) - a2(:nd, nd+1:))) <= 1.0e-13_dp*scale, "copies are translates")
      if (allocated(error)) return
      call check(error, maxval(abs(a2(:nd, :nd) + a2(:nd, nd+1:) - a1)) <= 1.0e-13_dp*scale, &
        "in-phase modes: B11 + B12 is the original's matrix")
      if (allocated(error)) return
      allocate(v(2*nd))
      work = a1
      call largest_eigenpair(work, lam1, v(:nd), status)
      work = a2(:nd, :nd) + a2(:nd, nd+1:)
      call largest_eigenpair(work, lam_in, v(:nd), status)
      work = a2(:nd, :nd) - a2(:nd, nd+1:)
      call largest_eigenpair(work, lam_anti, v(:nd), status)
      work = a2
      call largest_eigenpair(work, lam2, v, status)
      deallocate(v)
      call check(error, status%stat, demstep_stat%ok, status%message)
      if (allocated(error)) return
      ! dsyevr: eigenvalues to a few eps of the norm
      call check(error, abs(lam_in/lam1 - 1.0_dp) <= 1.0e-12_dp, "original's top is an in-phase mode")
      if (allocated(error)) return
      call check(error, abs(lam2/max(lam_in, lam_anti) - 1.0_dp) <= 1.0e-12_dp, &
        "tiled top is the larger of the in-phase and anti-phase tops")
      if (allocated(error)) return
      call assembly_critical_steps(scene, r1, status, solver=eigen_solver%dense)
      call check(error, status%stat, demstep_stat%ok, status%message)
      if (allocated(error)) return
      call assembly_critical_steps(tiled, r2, status, solver=eigen_solver%dense)
      call check(error, status%stat, demstep_stat%ok, status%message)
      if (allocated(error)) return
      call check(error, abs(r1%omega_max/(rate1*sqrt(lam1)) - 1.0_dp) <= 1.0e-12_dp .and. &
        abs(r2%omega_max/(rate2*sqrt(lam2)) - 1.0_dp) <= 1.0e-12_dp, "reported limits are these tops")
      if (allocated(error)) return
      if (lam_in >= lam_anti) then
        call check(error, abs(r2%omega_max/r1%omega_max - 1.0_dp) <= 1.0e-12_dp, "in-phase top: " &
          //"the tiled limit is the original's, "//real_str(r2%omega_max)//" vs "//real_str(r1%omega_max))
      else
        call check(error, r2%omega_max > r1%omega_max, "anti-phase top: the tiled limit is higher")
      end if
      if (allocated(error)) return
      call check(error, r2%n_springs, 2*r1%n_springs, "twice the springs")
      if (allocated(error)) return
      ! the bound takes the largest row sum: the same rows in both copies
      call check(error, abs(r2%omega_bound/r1%omega_bound - 1.0_dp) <= 1.0e-12_dp, "same bound")
      if (allocated(error)) return
    end do
  end subroutine test_tiled_limit

  subroutine test_bad_arguments(error)
    type(error_type), allocatable, intent(out) :: error
    type(scene_type) :: scene, tiled
    type(demstep_status_type) :: status
    call random_periodic_packing(scene, packing_min_particles - 1, status)
    call expect(error, status, "n:")
    if (allocated(error)) return
    call random_periodic_packing(scene, packing_max_particles + 1, status)
    call expect(error, status, "n:")
    if (allocated(error)) return
    call random_periodic_packing(scene, 100, status, radius=-1.0_dp)
    call expect(error, status, "radius:")
    if (allocated(error)) return
    call random_periodic_packing(scene, 100, status, radius=ieee_nan())
    call expect(error, status, "radius:")
    if (allocated(error)) return
    call random_periodic_packing(scene, 100, status, polydispersity=0.6_dp)
    call expect(error, status, "polydispersity:")
    if (allocated(error)) return
    call random_periodic_packing(scene, 100, status, polydispersity=ieee_nan())
    call expect(error, status, "polydispersity:")
    if (allocated(error)) return
    call random_periodic_packing(scene, 100, status, density=0.0_dp)
    call expect(error, status, "density:")
    if (allocated(error)) return
    call random_periodic_packing(scene, 100, status, k_normal=0.0_dp)
    call expect(error, status, "k_normal:")
    if (allocated(error)) return
    call random_periodic_packing(scene, 100, status, k_tangential=-1.0_dp)
    call expect(error, status, "k_tangential:")
    if (allocated(error)) return
    call random_periodic_packing(scene, 100, status, damping_ratio=-0.1_dp)
    call expect(error, status, "damping_ratio:")
    if (allocated(error)) return
    call random_periodic_packing(scene, 64, status)
    call check(error, status%stat, demstep_stat%ok, status%message)
    if (allocated(error)) return
    call tile_scene(scene, [0, 1, 1], tiled, status)
    call expect(error, status, "reps:")
    if (allocated(error)) return
    ! 64 particles times 1e8: above 2147483647, refused before allocating
    call tile_scene(scene, [1000, 1000, 100], tiled, status)
    call expect(error, status, "reps:")
    if (allocated(error)) return
    call cubic_lattice(scene, 3, 0.4_dp, 1.0_dp, status)
    call check(error, status%stat, demstep_stat%ok, status%message)
    if (allocated(error)) return
    call tile_scene(scene, [2, 1, 1], tiled, status)
    call expect(error, status, "reps: axis 1 is not periodic")
    if (allocated(error)) return
    ! reps 1 on a non-periodic axis is a copy
    call tile_scene(scene, [1, 1, 1], tiled, status)
    call check(error, status%stat == demstep_stat%ok .and. tiled%n == scene%n .and. &
      size(tiled%bonds, 2) == size(scene%bonds, 2), "reps 1: the same scene")
  end subroutine test_bad_arguments

  !> An invalid_input status whose message starts with `start`.
  subroutine expect(error, status, start)
    type(error_type), allocatable, intent(out) :: error
    type(demstep_status_type), intent(in) :: status
    character(len=*), intent(in) :: start
    call check(error, status%stat, demstep_stat%invalid_input, "expected a refusal starting '"//start//"'")
    if (allocated(error)) return
    call check(error, index(status%message, start) == 1, "message '"//status%message//"' should start '" &
      //start//"'")
  end subroutine expect

end module test_packing
