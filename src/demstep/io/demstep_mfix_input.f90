!> MFiX deck -> demstep's MFiX input: the DEM keywords of a parsed deck,
!> checked by MFiX's rules, with coarse-grained (CGP) phases scaled as MFiX
!> scales them and the smallest diameters of the size distributions.
!>
!> Re-derived from MFiX 21.3: model/check_data/check_solids_model_prereqs.f
!> (phase counting; any 'CGP' phase sets CGDEM, :196), check_solids_common_discrete.f
!> (CGP scaling, :99-148), check_solids_dem.f (collision keywords),
!> des_init_namelist.f (defaults).
module demstep_mfix_input
  use demstep_kinds, only: dp
  use demstep_status, only: demstep_status_type, demstep_stat, set_status
  use demstep_text, only: int_text, real_text
  use demstep_mfix_deck, only: mfix_deck_type, mfix_get_real, mfix_get_integer, mfix_get_string, &
    mfix_get_real_array, mfix_get_string_array, mfix_min_by_second_index, mfix_upper
  implicit none
  private

  public :: mfix_input_from_deck, mfix_pair_index

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
  type, public :: mfix_units_enum
    !> `UNITS = 'SI'`.
    integer :: si = 1
    !> `UNITS = 'CGS'`.
    integer :: cgs = 2
  end type mfix_units_enum
  !> The unit systems by name.
  type(mfix_units_enum), parameter, public :: mfix_units = mfix_units_enum()

  !> Collision models (`DES_COLL_MODEL`).
  type, public :: mfix_model_enum
    !> Linear spring-dashpot, `'LSD'` (the default).
    integer :: lsd = 1
    !> `'HERTZIAN'`.
    integer :: hertzian = 2
  end type mfix_model_enum
  !> The collision models by name.
  type(mfix_model_enum), parameter, public :: mfix_model = mfix_model_enum()

  !> Integrators (`DES_INTG_METHOD`).
  type, public :: mfix_integrator_enum
    !> `'EULER'` (the default; cfnewvalues.f): `v += dt a(x_n)`, then
    !> `x += dt v_(n+1)`: the central-difference scheme (symplectic Euler).
    integer :: euler = 1
    !> `'ADAMS_BASHFORTH'` (cfnewvalues.f): velocity by second-order
    !> Adams-Bashforth, `v += dt (3 a_n - a_(n-1))/2`, position by the trapezoid
    !> `x += dt (v_n + v_(n+1))/2`. On an undamped linear contact it gains
    !> energy at every step (measured amplitude growth per period: 1.0008 at
    !> omega dt = 0.1, 1.115 at 0.5): there is no stability limit to meet.
    integer :: adams_bashforth = 2
  end type mfix_integrator_enum
  !> The integrators by name.
  type(mfix_integrator_enum), parameter, public :: mfix_integrator = mfix_integrator_enum()

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
    !> Per DEM phase: `D_P0` (of the coarse-grained particles when CGP scales
    !> it, as MFiX uses it), `RO_S0`, `E_YOUNG`, `V_POISSON`.
    real(dp), allocatable :: d_p0(:), ro_s0(:), e_young(:), v_poisson(:)
    !> Coarse graining: true when a phase is `'CGP'`, and then per DEM phase the
    !> statistical weight MFiX uses (given, or `(CGP_D_P0/D_P0)^3`) and the
    !> deck's `D_P0` (the real particles); weight 1 and `d_p0` otherwise.
    logical :: coarse_grained = .false.
    real(dp), allocatable :: cgp_stat_wt(:), d_p0_real(:)
    !> Size distributions: per DEM phase the smallest diameter the deck's
    !> `IC_PSD_MIN_DP`/`BC_PSD_MIN_DP` give (scaled as MFiX scales them for
    !> CGP), 0 for none, and its line.
    real(dp), allocatable :: d_min(:)
    integer, allocatable :: d_min_line(:)
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
          call key_fault(status, "SOLIDS_MODEL", m, lines(m), &
            "MFiX requires the TFM phases before the DEM phases")
          return
        end if
        n_tfm = n_tfm + 1
      case ("PIC")
        call key_fault(status, "SOLIDS_MODEL", m, lines(m), &
          "'PIC' phases have no DEM collision time step (not supported)")
        return
      case default
        call key_fault(status, "SOLIDS_MODEL", m, lines(m), &
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
        call key_fault(status, "D_P0", m, ld(m), "must be > 0")
        return
      else if (.not. set_ro(m)) then
        call set_status(status, demstep_stat%invalid_input, "RO_S0("//int_text(m)// &
          "): missing for DEM solids phase "//int_text(m)//" (variable solids density is not supported)")
        return
      else if (.not. (ro(m) > 0.0_dp)) then
        call key_fault(status, "RO_S0", m, lro(m), "must be > 0")
        return
      end if
      input%d_p0(k) = d(m)
      input%ro_s0(k) = ro(m)
    end do

    call coarse_graining(input, status)
    if (status%stat /= demstep_stat%ok) return
    call size_distributions(input, status)
    if (status%stat /= demstep_stat%ok) return

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
          call key_fault(status, "E_YOUNG", m, le(m), "must be > 0")
          return
        else if (.not. set_nu(m)) then
          call set_status(status, demstep_stat%invalid_input, "V_POISSON("//int_text(m)// &
            "): missing for DEM solids phase "//int_text(input%phase(k))//" (DES_COLL_MODEL = 'HERTZIAN')")
          return
        else if (nu(m) > 0.5_dp .or. nu(m) <= -1.0_dp) then
          call key_fault(status, "V_POISSON", m, lnu(m), &
            "must lie in (-1, 0.5]")
          return
        end if
        input%e_young(k) = e(k)
        input%v_poisson(k) = nu(k)
      end do
    end select
    status%stat = demstep_stat%ok

  contains

    !> Coarse-grained phases as MFiX 21.3 scales them: any 'CGP' phase sets
    !> CGDEM (check_solids_model_prereqs.f:89, :196) and then EVERY discrete
    !> phase M is scaled (check_solids_common_discrete.f:99-148): CGP_STAT_WT(M)
    !> and CGP_D_P0(M) (both default 0, des_init_namelist.f:1725, :1739) not
    !> both (error 400) and not neither (error 410); with CGP_D_P0 alone it must
    !> be >= D_P0 (error 440) and CGP_STAT_WT := (CGP_D_P0/D_P0)^3 (:132); the
    !> weight must be >= 1 (error 500); then D_P0 := D_P0 CGP_STAT_WT^(1/3) (:147).
    pure subroutine coarse_graining(inp, st)
      type(mfix_input_type), intent(inout) :: inp
      type(demstep_status_type), intent(out) :: st
      real(dp) :: wt(mfix_dim_m), dcg(mfix_dim_m)
      logical :: set_wt(mfix_dim_m), set_dcg(mfix_dim_m)
      integer :: lwt(mfix_dim_m), ldcg(mfix_dim_m), i, mm
      allocate(inp%cgp_stat_wt(n), inp%d_p0_real(n))
      inp%d_p0_real = inp%d_p0
      inp%cgp_stat_wt = 1.0_dp
      st%stat = demstep_stat%ok
      inp%coarse_grained = any(models(1:mmax) == "CGP")
      if (.not. inp%coarse_grained) return
      wt = 0.0_dp
      dcg = 0.0_dp
      call mfix_get_real_array(deck, "cgp_stat_wt", mfix_dim_m, wt, set_wt, lwt, st)
      if (st%stat /= demstep_stat%ok) return
      call mfix_get_real_array(deck, "cgp_d_p0", mfix_dim_m, dcg, set_dcg, ldcg, st)
      if (st%stat /= demstep_stat%ok) return
      do i = 1, n
        mm = inp%phase(i)
        if (wt(mm) >= 1.0_dp .and. dcg(mm) > 0.0_dp) then
          call key_fault(st, "CGP_D_P0", mm, ldcg(mm), "not allowed together with CGP_STAT_WT("// &
            int_text(mm)//") (MFiX's error 400: give one of the two)")
          return
        else if (wt(mm) == 0.0_dp .and. dcg(mm) == 0.0_dp) then
          call key_fault(st, "CGP_STAT_WT", mm, 0, "missing: with a 'CGP' phase, MFiX needs CGP_STAT_WT or " &
            //"CGP_D_P0 for every discrete phase (its error 410; 1 for a phase of real particles)")
          return
        else if (wt(mm) == 0.0_dp) then
          if (.not. (dcg(mm) >= inp%d_p0(i))) then
            call key_fault(st, "CGP_D_P0", mm, ldcg(mm), "must be >= D_P0("//int_text(mm)//") = " &
              //real_text(inp%d_p0(i))//" (MFiX's error 440)")
            return
          end if
          wt(mm) = (dcg(mm)/inp%d_p0(i))**3
        else if (.not. (wt(mm) >= 1.0_dp)) then
          call key_fault(st, "CGP_STAT_WT", mm, lwt(mm), "must be >= 1 (MFiX's error 500)")
          return
        end if
        inp%cgp_stat_wt(i) = wt(mm)
        inp%d_p0(i) = inp%d_p0(i)*wt(mm)**(1.0_dp/3.0_dp)
      end do
    end subroutine coarse_graining

    !> The smallest diameter of each DEM phase over the deck's
    !> `IC_PSD_MIN_DP(ic, M)` and `BC_PSD_MIN_DP(bc, M)`; for a phase whose
    !> weight CGP_STAT_WT gives, MFiX scales them by CGP_STAT_WT^(1/3) as D_P0
    !> (check_solids_common_discrete.f:188-192, check_bc_dem.f:156-160).
    pure subroutine size_distributions(inp, st)
      type(mfix_input_type), intent(inout) :: inp
      type(demstep_status_type), intent(out) :: st
      real(dp) :: dmin(mfix_dim_m), dmin2(mfix_dim_m), wt(mfix_dim_m)
      logical :: set(mfix_dim_m), set2(mfix_dim_m), set_wt(mfix_dim_m)
      integer :: lmin(mfix_dim_m), lmin2(mfix_dim_m), lwt(mfix_dim_m), i, mm
      call mfix_min_by_second_index(deck, "ic_psd_min_dp", mfix_dim_m, dmin, set, lmin, st)
      if (st%stat /= demstep_stat%ok) return
      call mfix_min_by_second_index(deck, "bc_psd_min_dp", mfix_dim_m, dmin2, set2, lmin2, st)
      if (st%stat /= demstep_stat%ok) return
      wt = 0.0_dp
      if (inp%coarse_grained) then
        call mfix_get_real_array(deck, "cgp_stat_wt", mfix_dim_m, wt, set_wt, lwt, st)
        if (st%stat /= demstep_stat%ok) return
      end if
      allocate(inp%d_min(n), inp%d_min_line(n))
      inp%d_min = 0.0_dp
      inp%d_min_line = 0
      do i = 1, n
        mm = inp%phase(i)
        if (set2(mm) .and. (.not. set(mm) .or. dmin2(mm) < dmin(mm))) then
          dmin(mm) = dmin2(mm)
          lmin(mm) = lmin2(mm)
          set(mm) = .true.
        end if
        if (.not. set(mm)) cycle
        if (.not. (dmin(mm) > 0.0_dp)) then
          call set_status(st, demstep_stat%invalid_input, "the smallest diameter of phase "//int_text(mm)// &
            " must be > 0", where="PSD_MIN_DP")
          st%message = "line "//int_text(lmin(mm))//": "//st%message
          return
        end if
        ! scaled when the weight is given (MFiX's CGP_SCALING_METHOD 1)
        if (wt(mm) >= 1.0_dp) dmin(mm) = dmin(mm)*wt(mm)**(1.0_dp/3.0_dp)
        inp%d_min(i) = dmin(mm)
        inp%d_min_line(i) = lmin(mm)
      end do
      st%stat = demstep_stat%ok
    end subroutine size_distributions

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
      if (mfix_upper(word) == trim(first)) then
        code = 1
      else if (mfix_upper(word) == trim(second)) then
        code = 2
      else
        call set_status(st, demstep_stat%invalid_input, "line "//int_text(ln)//": "//mfix_upper(name)// &
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
        call set_status(st, demstep_stat%invalid_input, mfix_upper(name)//"("//int_text(idx)// &
          "): missing ("//what//")")
      else if (e > 1.0_dp .or. e < 0.0_dp) then
        call key_fault(st, name, idx, ln, "must lie in [0, 1]")
      else if (e == 0.0_dp) then
        call key_fault(st, name, idx, ln, &
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
        call set_status(st, demstep_stat%invalid_input, mfix_upper(name)//": missing (DES_COLL_MODEL = '"// &
          trim(merge("LSD     ", "HERTZIAN", input%model == mfix_model%lsd))//"')")
      else if (required .and. .not. (x > 0.0_dp)) then
        call set_status(st, demstep_stat%invalid_input, "line "//int_text(ln)//": "//mfix_upper(name)// &
          ": must be > 0")
      else if (.not. required .and. (x > 1.0_dp .or. x < 0.0_dp)) then
        call set_status(st, demstep_stat%invalid_input, "line "//int_text(ln)//": "//mfix_upper(name)// &
          ": must lie in [0, 1]")
      end if
    end subroutine real_keyword

  end subroutine mfix_input_from_deck

  !> Status `invalid_input` at the keyword `name(idx)` (`idx` 0: no subscript),
  !> the message `line N: NAME(idx): detail` (no line when `line` is 0).
  pure subroutine key_fault(status, name, idx, line, detail)
    type(demstep_status_type), intent(out) :: status
    character(len=*), intent(in) :: name, detail
    integer, intent(in) :: idx, line
    call set_status(status, demstep_stat%invalid_input, detail, where=mfix_upper(name), index=idx, &
      subscript=.true.)
    if (line > 0) status%message = "line "//int_text(line)//": "//status%message
  end subroutine key_fault


end module demstep_mfix_input
