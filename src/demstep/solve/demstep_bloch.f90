!> The exact largest eigenvalue of a tiled periodic scene by Bloch's theorem:
!> a K1 x K2 x K3 tiling of a periodic base scene has as its largest
!> eigenvalue the largest over the wave vectors k = 2 pi j / K (j_a = 0 ..
!> K_a - 1) of the top of the base's Hermitian Bloch operator H(k): the base's
!> operator with each block that couples a body to another body's periodic
!> image shifted by s cells multiplied by exp(i k . s). One dense Hermitian
!> eigenvalue problem of the base's order per wave vector (half of them: H(-k)
!> is H(k)'s conjugate; a real symmetric one where every phase is +-1, each
!> j_a 0 or K_a/2), so it is a reference for crowded spectra at any
!> tiling size (the tests' and `bench_tiling_top`'s).
module demstep_bloch
  use demstep_kinds, only: dp, i8, pi
  use demstep_status, only: demstep_status_type, demstep_stat, set_status
  use demstep_scene_data, only: scene_type
  use demstep_assembly, only: assembly_operator, assembly_operator_type, assembly_matrix
  use demstep_csr, only: csr_matrix_type
  use demstep_lapack, only: largest_hermitian_eigenvalue, largest_eigenpair
  implicit none
  private

  public :: bloch_top

contains

  !> The largest eigenvalue `lam` of the scaled operator of `base` tiled
  !> `reps` times, and the operator's rate (omega = rate sqrt(lam), the tiled
  !> scene's too). Status invalid_input naming `base` when a particle is fixed
  !> or the cell is not wider than four largest radii along a periodic axis
  !> (each contact must reach one image only, the nearest), `reps` when one
  !> is < 1; the operator's and LAPACK's statuses.
  subroutine bloch_top(base, reps, lam, rate, status)
    type(scene_type), intent(in) :: base
    integer, intent(in) :: reps(3)
    real(dp), intent(out) :: lam, rate
    type(demstep_status_type), intent(out) :: status
    type(assembly_operator_type) :: op
    type(csr_matrix_type) :: m
    complex(dp), allocatable :: h(:, :)
    complex(dp) :: phase
    real(dp), allocatable :: hr(:, :), vec(:)
    real(dp) :: box(3), kvec(3), shift(3), lam_k
    integer :: j(3), jm(3), r, bi, bj, nc, t
    integer(i8) :: p
    logical :: real_phases
    lam = 0.0_dp
    rate = 0.0_dp
    if (any(reps < 1)) then
      call set_status(status, demstep_stat%invalid_input, "need at least 1 along every axis", where="reps")
      return
    end if
    call assembly_operator(base, op, rate, status)
    if (status%stat /= demstep_stat%ok) return
    box = base%cell_hi - base%cell_lo
    if (any(base%fixed) .or. op%n_bodies /= base%n) then
      call set_status(status, demstep_stat%invalid_input, "a fixed particle: the Bloch operator " &
        //"needs every particle free", where="base")
      return
    end if
    if (any(base%periodic .and. box <= 4.0_dp*maxval(base%radius))) then
      call set_status(status, demstep_stat%invalid_input, "the cell is not wider than four " &
        //"largest radii: a contact's image is not unique", where="base")
      return
    end if
    call assembly_matrix(op, m)
    nc = op%nc
    lam = -huge(1.0_dp)
    do t = 0, product(reps) - 1
      j = [mod(t, reps(1)), mod(t/reps(1), reps(2)), t/(reps(1)*reps(2))]
      ! H(-k) is H(k)'s conjugate, with the same spectrum: one of each pair
      jm = mod(reps - j, reps)
      if (jm(1) + reps(1)*(jm(2) + reps(2)*jm(3)) < t) cycle
      kvec = 2.0_dp*pi*j/reps
      ! (k . shift a multiple of pi for every shift: the phases are +-1 and
      ! H(k) is real symmetric, a quarter of the complex solve's work)
      real_phases = all(mod(2*j, reps) == 0)
      if (real_phases) then
        if (.not. allocated(hr)) allocate(hr(m%n, m%n), vec(m%n))
        hr = 0.0_dp
      else
        if (.not. allocated(h)) allocate(h(m%n, m%n))
        h = (0.0_dp, 0.0_dp)
      end if
      do r = 1, m%n
        bi = (r - 1)/nc + 1
        do p = m%row_start(r), m%row_start(r + 1) - 1
          bj = (m%col(p) - 1)/nc + 1
          ! (1 on the body's own (diagonal) block; else from the cells from
          ! body bi to the image of bj it touches)
          phase = (1.0_dp, 0.0_dp)
          if (p - m%row_start(r) >= nc) then
            shift = 0.0_dp
            where (base%periodic) shift = anint((base%x(:, bi) - base%x(:, bj))/box)
            phase = exp(cmplx(0.0_dp, dot_product(kvec, shift), dp))
          end if
          if (real_phases) then
            ! (the cosine of a multiple of pi, at its extremum: exactly +-1)
            hr(r, m%col(p)) = hr(r, m%col(p)) + m%val(p)*real(phase, dp)
          else
            h(r, m%col(p)) = h(r, m%col(p)) + m%val(p)*phase
          end if
        end do
      end do
      if (real_phases) then
        call largest_eigenpair(hr, lam_k, vec, status)
      else
        call largest_hermitian_eigenvalue(h, lam_k, status)
      end if
      if (status%stat /= demstep_stat%ok) return
      lam = max(lam, lam_k)
    end do
  end subroutine bloch_top

end module demstep_bloch
