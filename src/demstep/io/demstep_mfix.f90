!> What MFiX computes for its DEM solids time step, from a deck's DEM inputs
!> ([[demstep_mfix_input]], coarse-grained phases already scaled as MFiX scales them).
!>
!> Re-derived from MFiX 21.3, model/check_data/check_solids_dem.f:
!> GET_REF_PARTICLE_SIZE_AND_MASS (reference radius `D_P0/2` and mass
!> `(PI/6) D_P0^3 RO_S0` of each DEM phase), CHECK_SOLIDS_DEM_COLL_LSD and
!> CHECK_SOLIDS_DEM_COLL_HERTZ (per pair: effective mass, spring, damping
!> `DES_ETAN`, collision time `TCOLL_TMP`; `TCOLL` the smallest over particle
!> pairs, walls left out; `DTSOLID = TCOLL/DTSOLID_FACTOR`). The arithmetic is
!> done in MFiX's order so that the results agree with MFiX's to rounding.
!> Units are the deck's (`UNITS = 'SI'` or `'CGS'`); times are in seconds.
!>
!> Caveats that this module reproduces rather than corrects: walls do not enter
!> `TCOLL` (a stiff `KN_W` is ignored); with particles present at the start MFiX
!> replaces `D_P0` by the smallest particle of the phase (not read here); and
!> the Hertzian `TCOLL` uses `HERT_KN` (force/length^1.5) as if it were a linear
!> stiffness, so it is the linear duration at the secant stiffness of an overlap
!> of ONE length unit (1 m in SI, 1 cm in CGS): it depends on the unit system
!> (CGS gives sqrt(10) times the SI value) and is not the Hertz contact duration.
module demstep_mfix
  use demstep_kinds, only: dp
  use demstep_material, only: mfix_moduli, mfix_pair_springs
  use demstep_status, only: demstep_status_type, demstep_stat, set_status
  use demstep_text, only: int_text
  use demstep_mfix_input, only: mfix_input_type, mfix_model
  use, intrinsic :: ieee_arithmetic, only: ieee_is_finite
  implicit none
  private

  public :: mfix_compute, mfix_pair_name

  !> MFiX's PI (constant_mod.f: 4 atan(1)).
  real(dp), parameter :: mfix_pi = 4.0_dp*atan(1.0_dp)

  !> What MFiX computes, per pair: the particle pairs in MFiX's order (11, 12,
  !> ..., 22, ...), then the phase-wall pairs (1W, 2W, ...).
  type, public :: mfix_result_type
    !> Number of particle pairs and of wall pairs.
    integer :: n_pairs = 0, n_walls = 0
    !> Global phase numbers of each pair; `phase_j = 0` for a wall.
    integer, allocatable :: phase_i(:), phase_j(:)
    !> `MASS_EFF` (mass units).
    real(dp), allocatable :: m_eff(:)
    !> Normal spring: `KN`/`KN_W` (force/length) for LSD, `HERT_KN`/`HERT_KWN`
    !> (force/length^1.5) for Hertzian.
    real(dp), allocatable :: k_n(:)
    !> Tangential spring: `KT_FAC KN` for LSD, `HERT_KT` for Hertzian.
    real(dp), allocatable :: k_t(:)
    !> `DES_ETAN` (force time/length for LSD; MFiX multiplies it by overlap^(1/4) for Hertzian).
    real(dp), allocatable :: eta_n(:)
    !> `DES_ETAT`.
    real(dp), allocatable :: eta_t(:)
    !> MFiX's collision time `TCOLL_TMP` of each pair (s).
    real(dp), allocatable :: t_coll(:)
    !> `TCOLL`: the smallest particle-pair collision time (walls left out).
    real(dp) :: tcoll = 0.0_dp
    !> `DTSOLID = TCOLL/DTSOLID_FACTOR`.
    real(dp) :: dtsolid = 0.0_dp
  end type mfix_result_type

contains

  !> MFiX's per-pair quantities, TCOLL and DTSOLID (see the module's notes).
  !> `invalid_input` when a pair is overdamped or a value leaves the double range.
  pure subroutine mfix_compute(input, result, status)
    !> The deck's DEM inputs.
    type(mfix_input_type), intent(in) :: input
    !> What MFiX computes.
    type(mfix_result_type), intent(out) :: result
    type(demstep_status_type), intent(out) :: status
    integer :: n, m, l, lc, np, w
    real(dp) :: mass(input%n_phases), radius(input%n_phases)
    real(dp) :: mass_eff, e_eff, g_mod_eff
    n = input%n_phases
    np = n + n*(n - 1)/2
    result%n_pairs = np
    result%n_walls = n
    allocate(result%phase_i(np + n), result%phase_j(np + n), result%m_eff(np + n), result%k_n(np + n), &
      result%k_t(np + n), result%eta_n(np + n), result%eta_t(np + n), result%t_coll(np + n))
    ! GET_REF_PARTICLE_SIZE_AND_MASS
    do m = 1, n
      radius(m) = 0.5_dp*input%d_p0(m)
      mass(m) = (mfix_pi/6.0_dp)*(input%d_p0(m)**3)*input%ro_s0(m)
    end do
    result%tcoll = huge(1.0_dp)
    lc = 0
    do m = 1, n
      do l = m, n
        lc = lc + 1
        result%phase_i(lc) = input%phase(m)
        result%phase_j(lc) = input%phase(l)
        mass_eff = mass(m)*mass(l)/(mass(m) + mass(l))
        if (input%model == mfix_model%lsd) then
          call pair(result, status, lc, mass_eff, input%en(lc), input%kn, input%kt_fac, input%etat_fac)
        else
          call mfix_moduli(input%e_young(m), input%v_poisson(m), input%e_young(l), input%v_poisson(l), &
            e_eff, g_mod_eff)
          call pair(result, status, lc, mass_eff, input%en(lc), r_eff=radius(m)*radius(l)/(radius(m) + radius(l)), &
            e_eff=e_eff, g_eff=g_mod_eff, et=input%et(lc))
        end if
        if (status%stat /= demstep_stat%ok) return
        result%tcoll = min(result%t_coll(lc), result%tcoll)
      end do
    end do
    ! walls: computed, but left out of TCOLL (MFiX comments the MIN out)
    do m = 1, n
      w = np + m
      result%phase_i(w) = input%phase(m)
      result%phase_j(w) = 0
      if (input%model == mfix_model%lsd) then
        call pair(result, status, w, mass(m), input%en_wall(m), input%kn_w, input%kt_w_fac, input%etat_w_fac)
      else
        call mfix_moduli(input%e_young(m), input%v_poisson(m), input%ew_young, input%vw_poisson, &
          e_eff, g_mod_eff)
        call pair(result, status, w, mass(m), input%en_wall(m), r_eff=radius(m), e_eff=e_eff, g_eff=g_mod_eff, &
          et=input%et_wall(m))
      end if
      if (status%stat /= demstep_stat%ok) return
    end do
    result%dtsolid = result%tcoll/input%dtsolid_factor
    if (.not. all(ieee_is_finite([result%m_eff, result%k_n, result%k_t, result%eta_n, result%eta_t, &
      result%t_coll, result%dtsolid]))) then
      call set_status(status, demstep_stat%invalid_input, &
        "D_P0: MFiX's quantities leave the double range; rescale the units")
      return
    end if
    status%stat = demstep_stat%ok
  contains
    !> One pair's springs, dashpots and collision time (`status` set when undefined).
    pure subroutine pair(res, st, p, m_eff, en, kn, kt_fac, etat_fac, r_eff, e_eff, g_eff, et)
      type(mfix_result_type), intent(inout) :: res
      type(demstep_status_type), intent(out) :: st
      integer, intent(in) :: p
      real(dp), intent(in) :: m_eff, en
      real(dp), intent(in), optional :: kn, kt_fac, etat_fac, r_eff, e_eff, g_eff, et
      real(dp) :: x
      res%m_eff(p) = m_eff
      call mfix_pair_springs(m_eff, en, res%k_n(p), res%k_t(p), res%eta_n(p), res%eta_t(p), x, &
        kn, kt_fac, etat_fac, r_eff, e_eff, g_eff, et)
      if (.not. ieee_is_finite(x)) then
        call set_status(st, demstep_stat%invalid_input, "D_P0: MFiX's masses, springs or dashpots leave " &
          //"the double range ("//mfix_pair_name(res, p)//"); rescale the units")
        return
      else if (.not. (x > 0.0_dp)) then
        if (res%phase_j(p) == 0) then
          call set_status(st, demstep_stat%invalid_input, "DES_EN_WALL_INPUT("//int_text(p - np)// &
            "): MFiX's wall collision time of phase "//int_text(res%phase_i(p))// &
            " is undefined (overdamped)")
        else
          call set_status(st, demstep_stat%invalid_input, "DES_EN_INPUT("//int_text(p)// &
            "): MFiX's collision time of the pair of phases "//int_text(res%phase_i(p))//" and "// &
            int_text(res%phase_j(p))//" is undefined (overdamped)")
        end if
        return
      end if
      res%t_coll(p) = mfix_pi/sqrt(x)
      st%stat = demstep_stat%ok
    end subroutine pair
  end subroutine mfix_compute

  !> A pair in words: `the pair of phases i and j` or `phase i against walls`.
  pure function mfix_pair_name(result, p) result(name)
    type(mfix_result_type), intent(in) :: result
    integer, intent(in) :: p
    character(len=:), allocatable :: name
    if (result%phase_j(p) == 0) then
      name = "phase "//int_text(result%phase_i(p))//" against walls"
    else
      name = "the pair of phases "//int_text(result%phase_i(p))//" and "//int_text(result%phase_j(p))
    end if
  end function mfix_pair_name

end module demstep_mfix
