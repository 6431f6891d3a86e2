!> The largest eigenvalue on crowded spectra, against exact references: a
!> K1 x K2 x K3 tiling of a periodic base scene has, by Bloch's theorem, as
!> its largest eigenvalue the largest over the wave vectors k = 2 pi j / K
!> (j_a = 0 .. K_a - 1) of the top of the base's Hermitian Bloch operator
!> H(k), the base's operator with each block that couples a body to another
!> body's periodic image shifted by s cells multiplied by exp(i k . s). The
!> tiled tops sit in clusters (K^3 copies of each base band, nearly equal near
!> the band's top), which a short Krylov space does not separate: before the
!> driver confirmed its top by a second run (and the scene's Krylov size was
!> 16), the scene solve ran out of restarts on the K = 3, 4 tilings of seeds
!> 1 to 3 in 5 of 6 cases at tolerance 1e-6 and in all at 1e-10, omega_max up
!> to 4.4e-6 below the reference (its bracket still holding it).
module test_lanczos_top
  use testdrive, only: new_unittest, unittest_type, error_type, check, test_failed
  use demstep_kinds, only: dp
  use demstep_status, only: demstep_status_type, demstep_stat
  use demstep_scene_data, only: scene_type, scene_effect
  use demstep_packing, only: tile_scene
  use demstep_packing, only: random_periodic_packing
  use demstep_assembly, only: assembly_critical_steps, critical_step_type, eigen_solver, safe_basis
  use demstep_lanczos, only: lanczos_tolerance_default, certificate_failure
  use demstep_text, only: int_text
  use demstep_bloch, only: bloch_top
  use demstep_scene_builders, only: new_scene, scene_set_cell, scene_set_law
  use demstep_interaction, only: contact_law
  use demstep_scene_input, only: scene_input_type, scene_setup_type, scene_from_input
  use demstep_material, only: material_set_type
  use test_support, only: real_str
  implicit none
  private
  public :: collect_lanczos_top

contains

  subroutine collect_lanczos_top(testsuite)
    type(unittest_type), allocatable, intent(out) :: testsuite(:)
    testsuite = [ &
      new_unittest("Bloch reference: the dense top of small tilings", test_reference), &
      new_unittest("Yade's periodic packing from its tables, tiled 2 x 2 x 2: the top within tolerance", &
        test_yade_tiling), &
      new_unittest("random packings tiled K = 3, 4, 6: the top within tolerance", test_tilings), &
      new_unittest("a light needle near the band's top, tiled: its cluster found", test_needle), &
      new_unittest("simple cubic lattices: a degenerate top found and certified", test_lattice) &
      ]
  end subroutine collect_lanczos_top

  !> The reference itself: on tilings small enough for a dense solve of the
  !> tiled scene, Bloch's top equals the dense one to rounding (1e-12: both
  !> are backward stable, ~n eps of the norm, n ~ 1e3).
  subroutine test_reference(error)
    type(error_type), allocatable, intent(out) :: error
    type(scene_type) :: base, tiled
    type(demstep_status_type) :: status
    type(critical_step_type) :: dense
    real(dp) :: lam, rate
    integer :: c
    integer, parameter :: reps(3, 2) = reshape([2, 1, 1, 1, 2, 1], [3, 2])
    call random_periodic_packing(base, 64, status, seed=1)
    call check(error, status%stat, demstep_stat%ok, status%message)
    if (allocated(error)) return
    do c = 1, size(reps, 2)
      call tile_scene(base, reps(:, c), tiled, status)
      call check(error, status%stat, demstep_stat%ok, status%message)
      if (allocated(error)) return
      call assembly_critical_steps(tiled, dense, status, solver=eigen_solver%dense)
      call check(error, status%stat, demstep_stat%ok, status%message)
      if (allocated(error)) return
      call bloch_top(base, reps(:, c), lam, rate, status)
      call check(error, status%stat, demstep_stat%ok, status%message)
      if (allocated(error)) return
      call check(error, rate*sqrt(lam), dense%omega_max, thr=1.0e-12_dp, rel=.true., &
        message="Bloch's omega_max against the dense one")
      if (allocated(error)) return
    end do
  end subroutine test_reference

  !> Tilings of random packings (rotations and tangential springs, 6 dof per
  !> particle) against Bloch's top, at the default tolerance and at 1e-6.
  subroutine test_tilings(error)
    type(error_type), allocatable, intent(out) :: error
    type(scene_type) :: base, tiled
    type(demstep_status_type) :: status
    integer :: c, seed, k
    ! (seed, K): three bases, each tiling's top a cluster of copies of the
    ! base's bands; K = 6 with rotations is 13 824 particles, 82 944 dof (the
    ! largest that keeps this suite near a minute)
    integer, parameter :: cases(2, 3) = reshape([2, 3, 3, 4, 1, 6], [2, 3])
    do c = 1, size(cases, 2)
      seed = cases(1, c)
      k = cases(2, c)
      call random_periodic_packing(base, 64, status, seed=seed)
      call check(error, status%stat, demstep_stat%ok, status%message)
      if (allocated(error)) return
      ! (K = 4 without rotations: 3 dof per particle, a quarter of the work)
      if (k == 4) base%effects(scene_effect%rotation) = .false.
      call tile_scene(base, [k, k, k], tiled, status)
      call check(error, status%stat, demstep_stat%ok, status%message)
      if (allocated(error)) return
      call check_top(error, base, tiled, [k, k, k], "seed "//int_text(seed)//", K = "//int_text(k))
      if (allocated(error)) return
    end do
  end subroutine test_tilings

  !> The issue's case on a packing made elsewhere: Yade's periodic "random"
  !> assembly (validation/yade: 600 spheres, the 1899 contacts Yade
  !> integrated with their own k_n and k_t, rotations), read from its tables
  !> as the app reads them and tiled 2 x 2 x 2 (4 800 spheres, 28 800 dof):
  !> its top is a cluster of copies of the base's bands. (Bloch's reference
  !> solves a dense 3600 x 3600 problem per wave vector: K = 3 takes 27 of
  !> them, 100 s in the debug build, so K = 2.)
  subroutine test_yade_tiling(error)
    type(error_type), allocatable, intent(out) :: error
    type(scene_input_type) :: input
    type(material_set_type) :: set
    type(scene_setup_type) :: setup
    type(scene_type) :: base, tiled
    type(demstep_status_type) :: status
    integer :: part
    input%dim = 3
    input%particles_file = "validation/yade/data/random/particles.txt"
    input%contacts_file = "validation/yade/data/random/contacts.txt"
    input%periodic = [.true., .true., .true.]
    input%cell_hi = spread(0.16332048070942493_dp, 1, 3)
    call scene_from_input(input, set, base, setup, status, part)
    call check(error, status%stat, demstep_stat%ok, status%message)
    if (allocated(error)) return
    call check(error, base%n == 600 .and. base%effects(scene_effect%rotation), "Yade's 600 spheres, rotations")
    if (allocated(error)) return
    call tile_scene(base, [2, 2, 2], tiled, status)
    call check(error, status%stat, demstep_stat%ok, status%message)
    if (allocated(error)) return
    call check_top(error, base, tiled, [2, 2, 2], "Yade's packing, K = 2")
  end subroutine test_yade_tiling

  !> A light particle ("needle") whose own mode sits near the top of the
  !> bulk's band: tiled, its K^3 copies make a cluster of nearly equal
  !> eigenvalues (coupled only through the bulk) at or near the top.
  subroutine test_needle(error)
    type(error_type), allocatable, intent(out) :: error
    type(scene_type) :: base, tiled
    type(demstep_status_type) :: status
    real(dp) :: lam, rate, omega_bulk, omega
    integer :: c
    real(dp), parameter :: factors(1) = [0.8_dp]
    call random_periodic_packing(base, 64, status, seed=3)
    call check(error, status%stat, demstep_stat%ok, status%message)
    if (allocated(error)) return
    call bloch_top(base, [1, 1, 1], lam, rate, status)
    omega_bulk = rate*sqrt(lam)
    do c = 1, size(factors)
      base%mass(1) = base%mass(1)*factors(c)
      base%inertia(1) = base%inertia(1)*factors(c)
      call bloch_top(base, [1, 1, 1], lam, rate, status)
      call check(error, status%stat, demstep_stat%ok, status%message)
      if (allocated(error)) return
      ! (the needle's mode above the bulk's top, by 1 % to 30 % in omega)
      omega = rate*sqrt(lam)
      call check(error, omega > 1.01_dp*omega_bulk .and. omega < 1.3_dp*omega_bulk, "the needle's " &
        //"top "//real_str(omega/omega_bulk)//" times the bulk's")
      if (allocated(error)) return
      call tile_scene(base, [3, 3, 3], tiled, status)
      call check(error, status%stat, demstep_stat%ok, status%message)
      if (allocated(error)) return
      call check_top(error, base, tiled, [3, 3, 3], "needle x "//real_str(factors(c)))
      if (allocated(error)) return
    end do
  end subroutine test_needle

  !> The tiled scene's Lanczos limit against Bloch's top: omega_max within the
  !> tolerance below it (omega is the root of the eigenvalue: half the relative
  !> tolerance, plus 1e-12 for the reference's own rounding), converged, and
  !> dt_critical_safe certified (the randomised bound, failure probability
  !> `certificate_failure`, or the rigorous bound) and at or below the exact limit; at the default
  !> tolerance (1e-6) and at 1e-10.
  subroutine check_top(error, base, tiled, reps, label)
    type(error_type), allocatable, intent(out) :: error
    type(scene_type), intent(in) :: base, tiled
    integer, intent(in) :: reps(3)
    character(len=*), intent(in) :: label
    type(demstep_status_type) :: status
    type(critical_step_type) :: r
    real(dp) :: lam, rate, omega, tol
    integer :: t
    call bloch_top(base, reps, lam, rate, status)
    call check(error, status%stat, demstep_stat%ok, status%message)
    if (allocated(error)) return
    omega = rate*sqrt(lam)
    do t = 1, 2
      tol = merge(lanczos_tolerance_default, 1.0e-10_dp, t == 1)
      call assembly_critical_steps(tiled, r, status, solver=eigen_solver%lanczos, tolerance=tol)
      call check(error, status%stat, demstep_stat%ok, status%message)
      if (allocated(error)) return
      call check(error, r%eigen_converged, label//": converged at "//real_str(tol))
      if (allocated(error)) return
      call check(error, r%omega_max >= omega*(1.0_dp - 0.5_dp*tol - 1.0e-12_dp) .and. &
        r%omega_max <= omega*(1.0_dp + 1.0e-12_dp), label//": omega_max "//real_str(r%omega_max) &
        //" against Bloch's "//real_str(omega)//" at "//real_str(tol))
      if (allocated(error)) return
      call check(error, r%dt_critical_safe <= 2.0_dp/omega*(1.0_dp + 1.0e-12_dp), label &
        //": dt_critical_safe "//real_str(r%dt_critical_safe)//" above the limit " &
        //real_str(2.0_dp/omega)//" at "//real_str(tol))
      if (allocated(error)) return
      ! (certified, or the rigorous bound where it is lower: a regular lattice's
      ! bound is its exact top)
      call check(error, (r%safe_basis == safe_basis%randomised .and. r%safe_failure == certificate_failure) &
        .or. (r%safe_basis == safe_basis%bound .and. r%safe_failure == 0.0_dp), label &
        //": the safe step certified")
      if (allocated(error)) return
    end do
  end subroutine check_top

  !> Simple cubic lattices in a periodic cell (spacing 2, radius 1.01: six
  !> contacts each), 4 x 4 x 4 particles tiled 2 and 3 times: by symmetry
  !> every eigenvalue of the tiling is (at least) three-fold, and without
  !> rotations (central springs) the top is k/m (2 - 2 cos q) at the
  !> zone-boundary wave number q nearest pi along one axis for any wave
  !> numbers along the others: a top of multiplicity 3 (K 4)^2 when K 4 is
  !> even. With rotations and tangential springs (6 dof) and without.
  subroutine test_lattice(error)
    type(error_type), allocatable, intent(out) :: error
    type(scene_type) :: base, tiled
    type(demstep_status_type) :: status
    real(dp) :: x(3, 64), lam, rate
    integer :: i, c, k
    logical :: rotation
    do i = 1, 64
      x(:, i) = 2.0_dp*[mod(i - 1, 4), mod((i - 1)/4, 4), (i - 1)/16] + 1.0_dp
    end do
    do c = 1, 3
      k = merge(2, 3, c /= 2)
      rotation = c == 3
      call new_scene(base, 3, x, spread(1.0_dp, 1, 64), spread(1.01_dp, 1, 64), status)
      call check(error, status%stat, demstep_stat%ok, status%message)
      if (allocated(error)) return
      call scene_set_cell(base, [.true., .true., .true.], [0.0_dp, 0.0_dp, 0.0_dp], &
        [8.0_dp, 8.0_dp, 8.0_dp], status)
      call check(error, status%stat, demstep_stat%ok, status%message)
      if (allocated(error)) return
      call scene_set_law(base, contact_law%linear, 1.0_dp, merge(0.3_dp, 0.0_dp, rotation), status)
      call check(error, status%stat, demstep_stat%ok, status%message)
      if (allocated(error)) return
      base%effects = .false.
      base%effects(scene_effect%contacts) = .true.
      base%effects(scene_effect%rotation) = rotation
      call tile_scene(base, [k, k, k], tiled, status)
      call check(error, status%stat, demstep_stat%ok, status%message)
      if (allocated(error)) return
      if (.not. rotation) then
        ! the closed form (4 k/m at an even period), to the reference's rounding
        call bloch_top(base, [k, k, k], lam, rate, status)
        call check(error, status%stat, demstep_stat%ok, status%message)
        if (allocated(error)) return
        ! (k = m = 1: omega_max = 2 sqrt(k/m) = 2)
        call check(error, rate*sqrt(lam), 2.0_dp, thr=1.0e-12_dp, rel=.true., message="Bloch's top of the lattice")
        if (allocated(error)) return
      end if
      call check_top(error, base, tiled, [k, k, k], "lattice x "//int_text(k)//merge(" rotations", &
        "          ", rotation))
      if (allocated(error)) return
    end do
  end subroutine test_lattice


end module test_lanczos_top
