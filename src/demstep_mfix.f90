!> What MFiX computes for its DEM solids time step, from an MFiX deck.
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
  use demstep_kinds, only: dp, i8
  use demstep_mfix_deck, only: mfix_min_by_second_index
  use demstep_material, only: effective_pair_type, hertz_impact_stiffness, hertz_contact_duration, &
    mfix_moduli, mfix_pair_springs
  use demstep_recommend, only: contact_assessment_type, assess_contact, recommended_step
  use demstep_spring, only: ceiling_real
  use demstep_cost, only: default_cost_n_max
  use demstep_status, only: demstep_status_type, demstep_stat, set_status
  use demstep_text, only: int_text, real_text, uppercase
  use demstep_mfix_deck, only: mfix_deck_type, mfix_get_real, mfix_get_integer, mfix_get_string, &
    mfix_get_real_array, mfix_get_string_array
  use, intrinsic :: ieee_arithmetic, only: ieee_is_finite
  implicit none
  private

  public :: mfix_input_from_deck, mfix_compute, mfix_pair_index, mfix_assess

  !> Largest number of solids phases MFiX allows (param_mod.f, DIM_M).
  integer, parameter, public :: mfix_dim_m = 10
  !> MFiX's default DTSOLID_FACTOR (des_init_namelist.f).
  real(dp), parameter, public :: mfix_default_dtsolid_factor = 50.0_dp
  !> MFiX's default KT_FAC and KT_W_FAC: the literal `0.28571428571429` of
  !> des_init_namelist.f is a default (single precision) real, so MFiX holds
  !> 0.2857142984867096..., not 2/7.
  real(dp), parameter, public :: mfix_default_kt_fac = real(0.28571428571429, dp)
  !> MFiX's PI (constant_mod.f: 4 atan(1)).
  real(dp), parameter :: mfix_pi = 4.0_dp*atan(1.0_dp)

  !> Unit systems.
  type, public :: mfix_units_codes
    !> `UNITS = 'SI'`.
    integer :: si = 1
    !> `UNITS = 'CGS'`.
    integer :: cgs = 2
  end type mfix_units_codes
  !> The unit systems by name.
  type(mfix_units_codes), parameter, public :: mfix_units = mfix_units_codes()

  !> Collision models (`DES_COLL_MODEL`).
  type, public :: mfix_model_codes
    !> Linear spring-dashpot, `'LSD'` (the default).
    integer :: lsd = 1
    !> `'HERTZIAN'`.
    integer :: hertzian = 2
  end type mfix_model_codes
  !> The collision models by name.
  type(mfix_model_codes), parameter, public :: mfix_model = mfix_model_codes()

  !> Integrators (`DES_INTG_METHOD`).
  type, public :: mfix_integrator_codes
    !> `'EULER'` (the default; cfnewvalues.f): `v += dt a(x_n)`, then
    !> `x += dt v_(n+1)`: the central-difference scheme (symplectic Euler).
    integer :: euler = 1
    !> `'ADAMS_BASHFORTH'` (cfnewvalues.f): velocity by second-order
    !> Adams-Bashforth, `v += dt (3 a_n - a_(n-1))/2`, position by the trapezoid
    !> `x += dt (v_n + v_(n+1))/2`. On an undamped linear contact it gains
    !> energy at every step (measured amplitude growth per period: 1.0008 at
    !> omega dt = 0.1, 1.115 at 0.5): there is no stability limit to meet.
    integer :: adams_bashforth = 2
  end type mfix_integrator_codes
  !> The integrators by name.
  type(mfix_integrator_codes), parameter, public :: mfix_integrator = mfix_integrator_codes()

  !> The DEM inputs of an MFiX deck, in the deck's units.
  type, public :: mfix_input_type
    !> `mfix_units%...`.
    integer :: units = 1
    !> `mfix_model%...`.
    integer :: model = 1
    !> `mfix_integrator%...`.
    integer :: integrator = 1
    !> Number of DEM phases, and their global phase numbers (`SOLIDS_MODEL(m)`
    !> `'DEM'` or `'CGP'`; MFiX requires TFM phases before DEM ones).
    integer :: n_phases = 0
    integer, allocatable :: phase(:)
    !> Per DEM phase: `D_P0`, `RO_S0`, `E_YOUNG`, `V_POISSON`.
    real(dp), allocatable :: d_p0(:), ro_s0(:), e_young(:), v_poisson(:)
    !> Packed upper-triangular restitution over DEM phases (11, 12, ..., 22, ...).
    real(dp), allocatable :: en(:), et(:)
    !> Per DEM phase: wall restitution.
    real(dp), allocatable :: en_wall(:), et_wall(:)
    !> LSD springs and factors.
    real(dp) :: kn = 0.0_dp, kn_w = 0.0_dp, kt_fac = mfix_default_kt_fac, kt_w_fac = mfix_default_kt_fac
    real(dp) :: etat_fac = 0.5_dp, etat_w_fac = 0.5_dp
    !> Hertzian wall material.
    real(dp) :: ew_young = 0.0_dp, vw_poisson = 0.0_dp
    !> `DTSOLID_FACTOR`.
    real(dp) :: dtsolid_factor = mfix_default_dtsolid_factor
  end type mfix_input_type

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

  !> demstep's exact answers for a deck at MFiX's step, per pair in the order of
  !> [[mfix_result_type]], in the deck's units (times in seconds).
  type, public :: mfix_assessment_type
    !> The tolerance on the restitution error and the impact velocity used
    !> (0: none given).
    real(dp) :: tolerance = 0.0_dp, velocity = 0.0_dp
    !> True when the exact answers exist: LSD, or Hertzian with an impact
    !> velocity (the Hertz contact is linearised at its largest overlap).
    logical :: linearised = .false.
    !> Damping ratio of the (linearised) contact: `eta_n/(2 sqrt(k m))`, for
    !> Hertzian `eta_n/(2 sqrt(1.5 HERT_KN m))` at every overlap.
    real(dp), allocatable :: damping_ratio(:)
    !> Linear stiffness: `KN` (LSD), the Hertz tangent stiffness at the largest
    !> overlap of the impact (Hertzian); 0 where undefined.
    real(dp), allocatable :: k_linear(:)
    !> The contact's true duration: the damped linear one (LSD), the Hertz
    !> duration at the impact velocity (Hertzian); 0 where undefined.
    real(dp), allocatable :: t_contact(:)
    !> Exact stability limit of the lagged dashpot (EULER); 0 where undefined.
    real(dp), allocatable :: dt_critical(:)
    !> At DTSOLID: N = T/DTSOLID, force evaluations per contact (onset at a
    !> step), stable, worst relative restitution and overlap errors.
    real(dp), allocatable :: n_per_period(:), restitution_error(:), overlap_error(:)
    integer(i8), allocatable :: steps(:)
    logical, allocatable :: stable(:)
    !> Largest step meeting the tolerance, per pair (0 without a tolerance).
    real(dp), allocatable :: dt_accuracy(:)
    !> Smallest limit and accuracy step over all pairs (walls and the smallest
    !> particles of a size distribution included); the recommended step and
    !> what governs it (`step_governs%...`); the DTSOLID_FACTOR giving a DTSOLID
    !> at most the recommended step (an integer >= 10, MFiX's lower bound).
    real(dp) :: dt_stability = 0.0_dp, dt_accuracy_min = 0.0_dp, dt_recommended = 0.0_dp
    integer :: governs = 0
    real(dp) :: dtsolid_factor = 0.0_dp
    !> True when a wall pair has a smaller limit than every particle pair
    !> (MFiX leaves walls out of TCOLL).
    logical :: walls_govern = .false.
    !> Size distributions: per DEM phase the smallest diameter the deck's
    !> `IC_PSD_MIN_DP`/`BC_PSD_MIN_DP` give (0: none) and its line; MFiX's TCOLL
    !> and demstep's smallest limit with those diameters in place of `D_P0`.
    logical :: psd = .false.
    real(dp), allocatable :: d_min(:)
    integer, allocatable :: d_min_line(:)
    real(dp) :: tcoll_psd = 0.0_dp, dt_stability_psd = 0.0_dp
  end type mfix_assessment_type

contains

  !> Position of the pair (i, j), i <= j among n phases, in MFiX's packed
  !> upper-triangular order 11, 12, ..., 1n, 22, ... (1-based).
  pure integer function mfix_pair_index(i, j, n) result(k)
    !> Phases (1-based DEM phase numbers), i <= j.
    integer, intent(in) :: i, j
    !> Number of DEM phases.
    integer, intent(in) :: n
    k = (i - 1)*n - (i - 1)*(i - 2)/2 + (j - i + 1)
  end function mfix_pair_index

  !> Extract and check the DEM inputs of a parsed deck, by MFiX's rules
  !> (CHECK_SOLIDS_DEM_COLLISION and its LSD/Hertzian parts). Status
  !> `invalid_input` with `line N: KEY(i): what is wrong` (or `KEY(i): ...`
  !> for a keyword the deck lacks).
  pure subroutine mfix_input_from_deck(deck, input, status)
    !> The parsed deck.
    type(mfix_deck_type), intent(in) :: deck
    !> The inputs.
    type(mfix_input_type), intent(out) :: input
    type(demstep_status_type), intent(out) :: status
    character(len=:), allocatable :: text
    character(len=32) :: models(mfix_dim_m)
    logical :: found, set(mfix_dim_m)
    integer :: line, lines(mfix_dim_m), mmax, m, k, n, n_tfm, mmax_line
    real(dp) :: d(mfix_dim_m), ro(mfix_dim_m), e(mfix_dim_m), nu(mfix_dim_m)
    logical :: set_d(mfix_dim_m), set_ro(mfix_dim_m), set_e(mfix_dim_m), set_nu(mfix_dim_m)
    integer :: ld(mfix_dim_m), lro(mfix_dim_m), le(mfix_dim_m), lnu(mfix_dim_m)

    ! UNITS
    call mfix_get_string(deck, "units", text, found, line, status)
    if (status%stat /= demstep_stat%ok) return
    if (.not. found) then
      call set_status(status, demstep_stat%invalid_input, "UNITS: missing ('SI' or 'CGS')")
      return
    end if
    call choice("units", "SI ", "CGS", input%units, status)
    if (status%stat /= demstep_stat%ok) return

    ! phases
    mmax = 1
    call mfix_get_integer(deck, "mmax", mmax, found, mmax_line, status)
    if (status%stat /= demstep_stat%ok) return
    if (mmax < 1 .or. mmax > mfix_dim_m) then
      call set_status(status, demstep_stat%invalid_input, "line "//int_text(mmax_line)// &
        ": MMAX: must lie in [1, "//int_text(mfix_dim_m)//"]")
      return
    end if
    call mfix_get_string_array(deck, "solids_model", mfix_dim_m, models, set, lines, status)
    if (status%stat /= demstep_stat%ok) return
    where (.not. set) models = "TFM"
    n = 0
    n_tfm = 0
    allocate(input%phase(mmax))
    do m = 1, mmax
      select case (trim(models(m)))
      case ("DEM", "CGP")
        n = n + 1
        input%phase(n) = m
      case ("TFM")
        if (n > 0) then
          call set_status(status, demstep_stat%invalid_input, where_key("SOLIDS_MODEL", m, lines(m))// &
            "MFiX requires the TFM phases before the DEM phases")
          return
        end if
        n_tfm = n_tfm + 1
      case ("PIC")
        call set_status(status, demstep_stat%invalid_input, where_key("SOLIDS_MODEL", m, lines(m))// &
          "'PIC' phases have no DEM collision time step (not supported)")
        return
      case default
        call set_status(status, demstep_stat%invalid_input, where_key("SOLIDS_MODEL", m, lines(m))// &
          "unknown solids model '"//trim(models(m))//"'")
        return
      end select
    end do
    if (n == 0) then
      call set_status(status, demstep_stat%invalid_input, &
        "SOLIDS_MODEL: no 'DEM' phase among the MMAX = "//int_text(mmax)//" solids phases")
      return
    end if
    input%n_phases = n
    input%phase = input%phase(1:n)

    ! D_P0, RO_S0 of each DEM phase
    call mfix_get_real_array(deck, "d_p0", mfix_dim_m, d, set_d, ld, status)
    if (status%stat /= demstep_stat%ok) return
    call mfix_get_real_array(deck, "ro_s0", mfix_dim_m, ro, set_ro, lro, status)
    if (status%stat /= demstep_stat%ok) return
    allocate(input%d_p0(n), input%ro_s0(n))
    do k = 1, n
      m = input%phase(k)
      if (.not. set_d(m)) then
        call set_status(status, demstep_stat%invalid_input, "D_P0("//int_text(m)// &
          "): missing for DEM solids phase "//int_text(m))
        return
      else if (.not. (d(m) > 0.0_dp)) then
        call set_status(status, demstep_stat%invalid_input, where_key("D_P0", m, ld(m))//"must be > 0")
        return
      else if (.not. set_ro(m)) then
        call set_status(status, demstep_stat%invalid_input, "RO_S0("//int_text(m)// &
          "): missing for DEM solids phase "//int_text(m)//" (variable solids density is not supported)")
        return
      else if (.not. (ro(m) > 0.0_dp)) then
        call set_status(status, demstep_stat%invalid_input, where_key("RO_S0", m, lro(m))//"must be > 0")
        return
      end if
      input%d_p0(k) = d(m)
      input%ro_s0(k) = ro(m)
    end do

    ! model and integrator
    call choice("des_coll_model", "LSD     ", "HERTZIAN", input%model, status)
    if (status%stat /= demstep_stat%ok) return
    call choice("des_intg_method", "EULER          ", "ADAMS_BASHFORTH", input%integrator, status)
    if (status%stat /= demstep_stat%ok) return
    call mfix_get_real(deck, "dtsolid_factor", input%dtsolid_factor, found, line, status)
    if (status%stat /= demstep_stat%ok) return
    if (.not. (input%dtsolid_factor >= 10.0_dp)) then
      call set_status(status, demstep_stat%invalid_input, "line "//int_text(line)// &
        ": DTSOLID_FACTOR: MFiX requires >= 10, found "//real_text(input%dtsolid_factor))
      return
    end if

    ! restitution: the DEM entries of DES_EN_INPUT come first in the deck and
    ! MFiX shifts them behind the TFM ones (CHECK_SOLIDS_DEM_COLL_LSD)
    k = n + n*(n - 1)/2
    call packed_restitution("des_en_input", k, input%en, status)
    if (status%stat /= demstep_stat%ok) return
    call wall_restitution("des_en_wall_input", input%en_wall, status)
    if (status%stat /= demstep_stat%ok) return

    select case (input%model)
    case (mfix_model%lsd)
      call real_keyword("kn", input%kn, .true., status)
      if (status%stat /= demstep_stat%ok) return
      call real_keyword("kn_w", input%kn_w, .true., status)
      if (status%stat /= demstep_stat%ok) return
      call real_keyword("kt_fac", input%kt_fac, .false., status)
      if (status%stat /= demstep_stat%ok) return
      call real_keyword("kt_w_fac", input%kt_w_fac, .false., status)
      if (status%stat /= demstep_stat%ok) return
      call real_keyword("des_etat_fac", input%etat_fac, .false., status)
      if (status%stat /= demstep_stat%ok) return
      call real_keyword("des_etat_w_fac", input%etat_w_fac, .false., status)
      if (status%stat /= demstep_stat%ok) return
    case (mfix_model%hertzian)
      call packed_restitution("des_et_input", k, input%et, status)
      if (status%stat /= demstep_stat%ok) return
      call wall_restitution("des_et_wall_input", input%et_wall, status)
      if (status%stat /= demstep_stat%ok) return
      call real_keyword("ew_young", input%ew_young, .true., status)
      if (status%stat /= demstep_stat%ok) return
      call mfix_get_real(deck, "vw_poisson", input%vw_poisson, found, line, status)
      if (status%stat /= demstep_stat%ok) return
      if (.not. found) then
        call set_status(status, demstep_stat%invalid_input, "VW_POISSON: missing (DES_COLL_MODEL = 'HERTZIAN')")
        return
      else if (input%vw_poisson > 0.5_dp .or. input%vw_poisson <= -1.0_dp) then
        call set_status(status, demstep_stat%invalid_input, "line "//int_text(line)// &
          ": VW_POISSON: must lie in (-1, 0.5]")
        return
      end if
      call mfix_get_real_array(deck, "e_young", mfix_dim_m, e, set_e, le, status)
      if (status%stat /= demstep_stat%ok) return
      call mfix_get_real_array(deck, "v_poisson", mfix_dim_m, nu, set_nu, lnu, status)
      if (status%stat /= demstep_stat%ok) return
      ! E_YOUNG and V_POISSON, like the restitution arrays, are numbered over the
      ! DEM phases only (MFiX shifts e_young(1:DES_MMAX) behind the TFM phases)
      allocate(input%e_young(n), input%v_poisson(n))
      do k = 1, n
        m = k
        if (.not. set_e(m)) then
          call set_status(status, demstep_stat%invalid_input, "E_YOUNG("//int_text(m)// &
            "): missing for DEM solids phase "//int_text(input%phase(k))//" (DES_COLL_MODEL = 'HERTZIAN')")
          return
        else if (.not. (e(m) > 0.0_dp)) then
          call set_status(status, demstep_stat%invalid_input, where_key("E_YOUNG", m, le(m))//"must be > 0")
          return
        else if (.not. set_nu(m)) then
          call set_status(status, demstep_stat%invalid_input, "V_POISSON("//int_text(m)// &
            "): missing for DEM solids phase "//int_text(input%phase(k))//" (DES_COLL_MODEL = 'HERTZIAN')")
          return
        else if (nu(m) > 0.5_dp .or. nu(m) <= -1.0_dp) then
          call set_status(status, demstep_stat%invalid_input, where_key("V_POISSON", m, lnu(m))// &
            "must lie in (-1, 0.5]")
          return
        end if
        input%e_young(k) = e(k)
        input%v_poisson(k) = nu(k)
      end do
    end select
    status%stat = demstep_stat%ok

  contains

    pure subroutine packed_restitution(name, count, values, st)
      character(len=*), intent(in) :: name
      integer, intent(in) :: count
      real(dp), allocatable, intent(out) :: values(:)
      type(demstep_status_type), intent(out) :: st
      integer :: i, j, lc, lines_pairs(55)
      real(dp) :: en(55)
      logical :: set_pairs(55)
      call mfix_get_real_array(deck, name, 55, en, set_pairs, lines_pairs, st)
      if (st%stat /= demstep_stat%ok) return
      allocate(values(count))
      do i = 1, n
        do j = i, n
          lc = mfix_pair_index(i, j, n)
          call check_restitution(name, lc, en(lc), set_pairs(lc), lines_pairs(lc), "the pair of DEM " &
            //"phases "//int_text(input%phase(i))//" and "//int_text(input%phase(j)), st)
          if (st%stat /= demstep_stat%ok) return
          values(lc) = en(lc)
        end do
      end do
    end subroutine packed_restitution

    pure subroutine wall_restitution(name, values, st)
      character(len=*), intent(in) :: name
      real(dp), allocatable, intent(out) :: values(:)
      type(demstep_status_type), intent(out) :: st
      integer :: i, lines_w(mfix_dim_m)
      real(dp) :: enw(mfix_dim_m)
      logical :: set_w(mfix_dim_m)
      call mfix_get_real_array(deck, name, mfix_dim_m, enw, set_w, lines_w, st)
      if (st%stat /= demstep_stat%ok) return
      allocate(values(n))
      do i = 1, n
        call check_restitution(name, i, enw(i), set_w(i), lines_w(i), "DEM solids phase "// &
          int_text(input%phase(i))//" against walls", st)
        if (st%stat /= demstep_stat%ok) return
        values(i) = enw(i)
      end do
    end subroutine wall_restitution

    !> A keyword naming one of two options (the first the default when absent).
    pure subroutine choice(name, first, second, code, st)
      character(len=*), intent(in) :: name, first, second
      integer, intent(out) :: code
      type(demstep_status_type), intent(out) :: st
      character(len=:), allocatable :: word
      logical :: there
      integer :: ln
      code = 1
      call mfix_get_string(deck, name, word, there, ln, st)
      if (st%stat /= demstep_stat%ok .or. .not. there) return
      if (uppercase(trim(adjustl(word))) == trim(first)) then
        code = 1
      else if (uppercase(trim(adjustl(word))) == trim(second)) then
        code = 2
      else
        call set_status(st, demstep_stat%invalid_input, "line "//int_text(ln)//": " &
          //uppercase(trim(adjustl(name)))// &
          ": '"//word//"' is neither '"//trim(first)//"' nor '"//trim(second)//"'")
      end if
    end subroutine choice

    !> One restitution coefficient: set, in [0, 1], not 0.
    pure subroutine check_restitution(name, idx, e, is_set, ln, what, st)
      character(len=*), intent(in) :: name, what
      integer, intent(in) :: idx, ln
      real(dp), intent(in) :: e
      logical, intent(in) :: is_set
      type(demstep_status_type), intent(out) :: st
      if (.not. is_set) then
        call set_status(st, demstep_stat%invalid_input, uppercase(trim(adjustl(name)))//"("//int_text(idx)// &
          "): missing ("//what//")")
      else if (e > 1.0_dp .or. e < 0.0_dp) then
        call set_status(st, demstep_stat%invalid_input, where_key(name, idx, ln)//"must lie in [0, 1]")
      else if (e == 0.0_dp) then
        call set_status(st, demstep_stat%invalid_input, where_key(name, idx, ln)// &
          "0 makes the contact critically damped: MFiX's collision time pi/sqrt(0) is undefined")
      else
        st%stat = demstep_stat%ok
      end if
    end subroutine check_restitution

    !> A real keyword: `required` ones must be given and > 0 (springs), the
    !> others lie in [0, 1] (factors, keeping their default when absent).
    pure subroutine real_keyword(name, x, required, st)
      character(len=*), intent(in) :: name
      real(dp), intent(inout) :: x
      logical, intent(in) :: required
      type(demstep_status_type), intent(out) :: st
      logical :: there
      integer :: ln
      call mfix_get_real(deck, name, x, there, ln, st)
      if (st%stat /= demstep_stat%ok) return
      if (required .and. .not. there) then
        call set_status(st, demstep_stat%invalid_input, uppercase(trim(adjustl(name))) &
          //": missing (DES_COLL_MODEL = '"// &
          trim(merge("LSD     ", "HERTZIAN", input%model == mfix_model%lsd))//"')")
      else if (required .and. .not. (x > 0.0_dp)) then
        call set_status(st, demstep_stat%invalid_input, "line "//int_text(ln)//": " &
          //uppercase(trim(adjustl(name)))// &
          ": must be > 0")
      else if (.not. required .and. (x > 1.0_dp .or. x < 0.0_dp)) then
        call set_status(st, demstep_stat%invalid_input, "line "//int_text(ln)//": " &
          //uppercase(trim(adjustl(name)))// &
          ": must lie in [0, 1]")
      end if
    end subroutine real_keyword

  end subroutine mfix_input_from_deck

  pure function where_key(name, idx, line) result(w)
    character(len=*), intent(in) :: name
    integer, intent(in) :: idx, line
    character(len=:), allocatable :: w
    w = uppercase(trim(adjustl(name)))//"("//int_text(idx)//"): "
    if (line > 0) w = "line "//int_text(line)//": "//w
  end function where_key

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
          //"the double range ("//pair_name(res, p)//"); rescale the units")
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

  !> demstep's exact answers for a deck at MFiX's step (see
  !> [[mfix_assessment_type]]): per pair the exact limit under MFiX's EULER
  !> scheme (central differences, dashpot on the previous velocity), the contact
  !> at DTSOLID, the step meeting `tolerance` on the restitution; the smallest
  !> particles of a size distribution; the recommended step and DTSOLID_FACTOR.
  !> Status `invalid_input` naming `tolerance` or `velocity`, or the pair.
  pure subroutine mfix_assess(deck, input, result, assessment, status, tolerance, velocity)
    !> The parsed deck (for its size distributions).
    type(mfix_deck_type), intent(in) :: deck
    !> Its DEM inputs and what MFiX computes from them.
    type(mfix_input_type), intent(in) :: input
    type(mfix_result_type), intent(in) :: result
    type(mfix_assessment_type), intent(out) :: assessment
    type(demstep_status_type), intent(out) :: status
    !> Tolerance on the relative restitution error (> 0); absent: stability only.
    real(dp), intent(in), optional :: tolerance
    !> Impact velocity in the deck's units (> 0), needed for Hertzian decks.
    real(dp), intent(in), optional :: velocity
    type(mfix_assessment_type) :: small
    type(mfix_input_type) :: psd_input
    type(mfix_result_type) :: psd_result
    real(dp) :: dmin(mfix_dim_m), dmin2(mfix_dim_m)
    logical :: set(mfix_dim_m), set2(mfix_dim_m)
    integer :: lines(mfix_dim_m), lines2(mfix_dim_m), k, m, np
    if (present(tolerance)) then
      if (.not. (tolerance > 0.0_dp .and. tolerance < 1.0_dp)) then
        call set_status(status, demstep_stat%invalid_input, "tolerance: must lie in (0, 1), got " &
          //real_text(tolerance))
        return
      end if
      assessment%tolerance = tolerance
    end if
    if (present(velocity)) then
      if (.not. (velocity > 0.0_dp .and. ieee_is_finite(velocity))) then
        call set_status(status, demstep_stat%invalid_input, "velocity: must be finite and > 0, got " &
          //real_text(velocity))
        return
      end if
      assessment%velocity = velocity
    end if
    call assess_pairs(input, result, assessment, status)
    if (status%stat /= demstep_stat%ok) return
    np = result%n_pairs

    ! size distributions: the smallest diameter of each DEM phase
    call mfix_min_by_second_index(deck, "ic_psd_min_dp", mfix_dim_m, dmin, set, lines, status)
    if (status%stat /= demstep_stat%ok) return
    call mfix_min_by_second_index(deck, "bc_psd_min_dp", mfix_dim_m, dmin2, set2, lines2, status)
    if (status%stat /= demstep_stat%ok) return
    allocate(assessment%d_min(input%n_phases), assessment%d_min_line(input%n_phases))
    assessment%d_min = 0.0_dp
    assessment%d_min_line = 0
    psd_input = input
    do k = 1, input%n_phases
      m = input%phase(k)
      if (set2(m) .and. (.not. set(m) .or. dmin2(m) < dmin(m))) then
        dmin(m) = dmin2(m)
        lines(m) = lines2(m)
        set(m) = .true.
      end if
      if (.not. set(m)) cycle
      if (.not. (dmin(m) > 0.0_dp)) then
        call set_status(status, demstep_stat%invalid_input, "line "//int_text(lines(m))// &
          ": PSD_MIN_DP: the smallest diameter of phase "//int_text(m)//" must be > 0")
        return
      end if
      assessment%d_min(k) = dmin(m)
      assessment%d_min_line(k) = lines(m)
      if (dmin(m) < input%d_p0(k)) then
        assessment%psd = .true.
        psd_input%d_p0(k) = dmin(m)
      end if
    end do

    assessment%dt_stability = 0.0_dp
    if (assessment%linearised) then
      assessment%dt_stability = minval(assessment%dt_critical)
      assessment%walls_govern = minval(assessment%dt_critical(np+1:)) < minval(assessment%dt_critical(:np))
    end if
    if (present(tolerance) .and. assessment%linearised) assessment%dt_accuracy_min = minval(assessment%dt_accuracy)
    if (assessment%psd) then
      call mfix_compute(psd_input, psd_result, status)
      if (status%stat /= demstep_stat%ok) return
      assessment%tcoll_psd = psd_result%tcoll
      small%tolerance = assessment%tolerance
      small%velocity = assessment%velocity
      call assess_pairs(psd_input, psd_result, small, status)
      if (status%stat /= demstep_stat%ok) return
      if (small%linearised) then
        assessment%dt_stability_psd = minval(small%dt_critical)
        assessment%dt_stability = min(assessment%dt_stability, assessment%dt_stability_psd)
        if (present(tolerance)) assessment%dt_accuracy_min = min(assessment%dt_accuracy_min, &
          minval(small%dt_accuracy))
      end if
    end if

    status%stat = demstep_stat%ok
    if (.not. assessment%linearised) return
    if (present(tolerance)) then
      call recommended_step(assessment%dt_stability, assessment%dt_recommended, assessment%governs, &
        status, dt_accuracy=assessment%dt_accuracy_min)
    else
      call recommended_step(assessment%dt_stability, assessment%dt_recommended, assessment%governs, status)
    end if
    if (status%stat /= demstep_stat%ok) return
    ! DTSOLID = TCOLL/factor <= the recommended step
    assessment%dtsolid_factor = max(10.0_dp, ceiling_real(result%tcoll/assessment%dt_recommended))
  end subroutine mfix_assess

  !> The per-pair part of [[mfix_assess]] for one input (D_P0 or the smallest sizes).
  pure subroutine assess_pairs(input, result, a, status)
    type(mfix_input_type), intent(in) :: input
    type(mfix_result_type), intent(in) :: result
    type(mfix_assessment_type), intent(inout) :: a
    type(demstep_status_type), intent(out) :: status
    type(contact_assessment_type) :: c
    type(effective_pair_type) :: eff
    integer :: p, n, j
    real(dp) :: m, k_lin, t_contact, n_tol(result%n_pairs + result%n_walls)
    n = result%n_pairs + result%n_walls
    allocate(a%damping_ratio(n), a%k_linear(n), a%t_contact(n), a%dt_critical(n), a%n_per_period(n), &
      a%restitution_error(n), a%overlap_error(n), a%steps(n), a%stable(n), a%dt_accuracy(n))
    a%k_linear = 0.0_dp
    a%t_contact = 0.0_dp
    a%dt_critical = 0.0_dp
    a%n_per_period = 0.0_dp
    a%restitution_error = 0.0_dp
    a%overlap_error = 0.0_dp
    a%steps = 0_i8
    a%stable = .true.
    a%dt_accuracy = 0.0_dp
    a%linearised = input%model == mfix_model%lsd .or. a%velocity > 0.0_dp
    status%stat = demstep_stat%ok
    do p = 1, n
      m = result%m_eff(p)
      if (input%model == mfix_model%lsd) then
        a%damping_ratio(p) = result%eta_n(p)/(2.0_dp*sqrt(result%k_n(p)*m))
        k_lin = result%k_n(p)
        t_contact = result%t_coll(p)
      else
        ! force HERT_KN d^(3/2) + eta_n d^(1/4) v: tangent 1.5 HERT_KN d^(1/2), so
        ! the linearised damping ratio does not depend on the overlap
        a%damping_ratio(p) = result%eta_n(p)/(2.0_dp*sqrt(1.5_dp*result%k_n(p)*m))
        if (.not. a%linearised) cycle
        ! HERT_KN = 4/3 E* sqrt(R*): E* sqrt(R*) is all the Hertz law needs
        eff%e_star = 0.75_dp*result%k_n(p)
        eff%r_star = 1.0_dp
        eff%m_star = m
        call hertz_impact_stiffness(eff, a%velocity, k_lin, status)
        if (status%stat == demstep_stat%ok) call hertz_contact_duration(eff, a%velocity, t_contact, status)
        if (status%stat /= demstep_stat%ok) then
          status%message = "velocity: "//pair_name(result, p)//": "//status%message
          return
        end if
      end if
      a%k_linear(p) = k_lin
      a%t_contact(p) = t_contact
      call assess_contact(m, k_lin, a%damping_ratio(p), c, status, dt=result%dtsolid)
      if (status%stat /= demstep_stat%ok) then
        call name_pair(input, result, p, status)
        return
      end if
      a%dt_critical(p) = c%dt_critical
      a%n_per_period(p) = c%n_per_period
      a%steps(p) = c%steps
      a%stable(p) = c%stable
      a%restitution_error(p) = c%restitution_error
      a%overlap_error(p) = c%overlap_error
      if (a%tolerance > 0.0_dp) then
        ! N for a tolerance depends on the damping ratio alone: reuse it
        n_tol(p) = 0.0_dp
        do j = 1, p - 1
          if (a%damping_ratio(j) == a%damping_ratio(p) .and. n_tol(j) > 0.0_dp) n_tol(p) = n_tol(j)
        end do
        if (n_tol(p) == 0.0_dp) then
          call assess_contact(m, k_lin, a%damping_ratio(p), c, status, tolerance=a%tolerance)
          if (status%stat == demstep_stat%not_found) then
            call set_status(status, demstep_stat%invalid_input, "tolerance: "//real_text(a%tolerance)// &
              " is not met below "//real_text(default_cost_n_max)//" steps per period ("// &
              pair_name(result, p)//"); use a larger one")
            return
          else if (status%stat /= demstep_stat%ok) then
            call name_pair(input, result, p, status)
            return
          end if
          n_tol(p) = c%n_tolerance
        end if
        a%dt_accuracy(p) = c%period/n_tol(p)
      end if
    end do
  end subroutine assess_pairs

  !> A pair's failure, named: `the pair of phases i and j: what`, and a failure of
  !> its steps per period (a damping the discrete contact cannot end with) first
  !> names the keyword that gives the damping, the pair's restitution
  !> (`DES_EN_INPUT(k)` in MFiX's packed order, `DES_EN_WALL_INPUT(i)`).
  pure subroutine name_pair(input, result, p, status)
    type(mfix_input_type), intent(in) :: input
    type(mfix_result_type), intent(in) :: result
    integer, intent(in) :: p
    type(demstep_status_type), intent(inout) :: status
    character(len=*), parameter :: internal = "n_per_period: "
    integer :: i, j
    if (index(status%message, internal) /= 1) then
      status%message = pair_name(result, p)//": "//status%message
      return
    end if
    i = findloc(input%phase, result%phase_i(p), dim=1)
    if (result%phase_j(p) == 0) then
      status%message = "DES_EN_WALL_INPUT("//int_text(i)//"): "//pair_name(result, p)//": " &
        //status%message(len(internal) + 1:)
    else
      j = findloc(input%phase, result%phase_j(p), dim=1)
      status%message = "DES_EN_INPUT("//int_text(mfix_pair_index(min(i, j), max(i, j), input%n_phases)) &
        //"): "//pair_name(result, p)//": "//status%message(len(internal) + 1:)
    end if
  end subroutine name_pair

  !> `the pair of phases i and j` or `phase i against walls`.
  pure function pair_name(result, p) result(name)
    type(mfix_result_type), intent(in) :: result
    integer, intent(in) :: p
    character(len=:), allocatable :: name
    if (result%phase_j(p) == 0) then
      name = "phase "//int_text(result%phase_i(p))//" against walls"
    else
      name = "the pair of phases "//int_text(result%phase_i(p))//" and "//int_text(result%phase_j(p))
    end if
  end function pair_name

end module demstep_mfix
