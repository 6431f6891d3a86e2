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
  use demstep_kinds, only: dp, i8, pi
  use demstep_status, only: demstep_status_type, demstep_stat
  use demstep_scene_data, only: scene_type, scene_effect
  use demstep_packing, only: tile_scene
  use demstep_packing, only: random_periodic_packing
  use demstep_assembly, only: assembly_critical_steps, critical_step_type, eigen_solver, &
    assembly_operator, assembly_operator_type, assembly_matrix
  use demstep_lanczos, only: lanczos_tolerance_default
  use demstep_text, only: int_text
  use demstep_csr, only: csr_matrix_type
  use demstep_lapack, only: largest_hermitian_eigenvalue
  use test_support, only: real_str
  implicit none
  private
  public :: collect_lanczos_top, bloch_top

contains

  subroutine collect_lanczos_top(testsuite)
    type(unittest_type), allocatable, intent(out) :: testsuite(:)
    testsuite = [ &
      new_unittest("Bloch reference: the dense top of small tilings", test_reference), &
      new_unittest("random packings tiled K = 3, 4: the top within tolerance", test_tilings), &
      new_unittest("a light needle near the band's top, tiled: its cluster found", test_needle) &
      ]
  end subroutine collect_lanczos_top

  !> The largest eigenvalue of the scaled operator of `base` tiled `reps`
  !> times, by Bloch's theorem (see the module notes), and the operator's
  !> rate (omega = rate sqrt(lambda), the tiled scene's too). The base must
  !> have no fixed particle and a cell wider than twice the longest contact
  !> along each periodic axis (so each contact's image shift is the nearest
  !> image's).
  subroutine bloch_top(base, reps, lam, rate, status)
    type(scene_type), intent(in) :: base
    integer, intent(in) :: reps(3)
    real(dp), intent(out) :: lam, rate
    type(demstep_status_type), intent(out) :: status
    type(assembly_operator_type) :: op
    type(csr_matrix_type) :: m
    complex(dp), allocatable :: h(:, :)
    real(dp) :: box(3), kvec(3), shift(3), lam_k
    integer :: j(3), jm(3), r, bi, bj, nc, t
    integer(i8) :: p
    lam = 0.0_dp
    call assembly_operator(base, op, rate, status)
    if (status%stat /= demstep_stat%ok) return
    if (any(base%fixed) .or. op%n_bodies /= base%n) error stop "bloch_top: a fixed particle"
    box = base%cell_hi - base%cell_lo
    if (any(base%periodic .and. box <= 4.0_dp*maxval(base%radius))) &
      error stop "bloch_top: the cell is too small for unique images"
    call assembly_matrix(op, m)
    nc = op%nc
    allocate(h(m%n, m%n))
    lam = -huge(1.0_dp)
    do t = 0, product(reps) - 1
      j = [mod(t, reps(1)), mod(t/reps(1), reps(2)), t/(reps(1)*reps(2))]
      ! H(-k) is H(k)'s conjugate, with the same spectrum: one of each pair
      jm = mod(reps - j, reps)
      if (jm(1) + reps(1)*(jm(2) + reps(2)*jm(3)) < t) cycle
      kvec = 2.0_dp*pi*j/reps
      h = (0.0_dp, 0.0_dp)
      do r = 1, m%n
        bi = (r - 1)/nc + 1
        do p = m%row_start(r), m%row_start(r + 1) - 1
          bj = (m%col(p) - 1)/nc + 1
          if (p - m%row_start(r) < nc) then
            ! the body's own (diagonal) block
            h(r, m%col(p)) = h(r, m%col(p)) + m%val(p)
          else
            ! the cells from body bi to the image of bj it touches
            shift = 0.0_dp
            where (base%periodic) shift = anint((base%x(:, bi) - base%x(:, bj))/box)
            h(r, m%col(p)) = h(r, m%col(p)) + m%val(p)*exp(cmplx(0.0_dp, dot_product(kvec, shift), dp))
          end if
        end do
      end do
      call largest_hermitian_eigenvalue(h, lam_k, status)
      if (status%stat /= demstep_stat%ok) return
      lam = max(lam, lam_k)
    end do
  end subroutine bloch_top

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
    ! (seed, K): two bases, each tiling's top a cluster of copies of the base's bands
    integer, parameter :: cases(2, 2) = reshape([2, 3, 3, 4], [2, 2])
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
  !> tolerance, plus 1e-12 for the reference's own rounding), the error bar's
  !> upper end at or above it (dt_critical_safe is safe) and converged; at the
  !> default tolerance and at 1e-6.
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
      tol = merge(lanczos_tolerance_default, 1.0e-6_dp, t == 1)
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
    end do
  end subroutine check_top


end module test_lanczos_top
