!> MFiX mode: `demstep deck.mfx` reports what MFiX computes for its DEM solids
!> step, demstep's exact answers at that step, and the DTSOLID_FACTOR that
!> meets a tolerance, written as a line MFiX reads.
module demstep_cli_mfix
  use demstep_kinds, only: dp, i8
  use demstep_mfix, only: mfix_result_type, mfix_compute
  use demstep_mfix_assess, only: mfix_assessment_type, mfix_assess
  use demstep_mfix_deck, only: mfix_deck_type, parse_mfix_deck, mfix_upper
  use demstep_mfix_input, only: mfix_input_type, mfix_input_from_deck, mfix_units, mfix_model, &
    mfix_integrator
  use demstep_status, only: demstep_status_type, demstep_stat
  use demstep_recommend, only: step_governs, default_safety
  use demstep_cli, only: report_row, record_step, cli_context, fmt_real, fmt_int
  use demstep_results, only: write_mfix_result
  implicit none
  private

  public :: run_mfix

  !> Tolerance on the relative restitution error when the command line gives none.
  real(dp), parameter, public :: mfix_default_tolerance = 1.0e-2_dp

contains

  !> Read an MFiX deck's text, report and write `&mfix_result`. `tolerance`
  !> (restitution, relative) and `velocity` (Hertzian impact velocity, deck
  !> units; <= 0: none) come from the command line.
  subroutine run_mfix(ctx, text, tolerance, tolerance_given, velocity, status)
    type(cli_context), intent(in) :: ctx
    character(len=*), intent(in) :: text
    real(dp), intent(in) :: tolerance, velocity
    logical, intent(in) :: tolerance_given
    type(demstep_status_type), intent(out) :: status
    type(mfix_deck_type) :: deck
    type(mfix_input_type) :: input
    type(mfix_result_type) :: result
    type(mfix_assessment_type) :: a
    call parse_mfix_deck(text, deck, status)
    if (status%stat /= demstep_stat%ok) return
    call mfix_input_from_deck(deck, input, status)
    if (status%stat /= demstep_stat%ok) return
    call mfix_compute(input, result, status)
    if (status%stat /= demstep_stat%ok) return
    if (velocity > 0.0_dp) then
      call mfix_assess(input, result, a, status, tolerance=tolerance, velocity=velocity)
    else
      call mfix_assess(input, result, a, status, tolerance=tolerance)
    end if
    if (status%stat /= demstep_stat%ok) then
      ! the command line's names for the library's
      if (allocated(status%where)) then
        if (status%where == "tolerance" .or. status%where == "velocity") &
          status%message = "--"//status%where//": "//status%detail
      end if
      return
    end if
    call report(ctx%report, deck, input, result, a, tolerance_given)
    if (a%linearised) call record_step(ctx, "single-contact step", a%dt_recommended, .false.)
    call write_mfix_result(ctx%results, input, result, a)
  end subroutine run_mfix

  !> The human report.
  subroutine report(u, deck, input, result, a, tolerance_given)
    integer, intent(in) :: u
    type(mfix_deck_type), intent(in) :: deck
    type(mfix_input_type), intent(in) :: input
    type(mfix_result_type), intent(in) :: result
    type(mfix_assessment_type), intent(in) :: a
    logical, intent(in) :: tolerance_given
    character(len=:), allocatable :: mass_unit, k_unit, eta_unit, len_unit, model
    integer :: p, np, k, i
    logical :: si, lsd
    si = input%units == mfix_units%si
    lsd = input%model == mfix_model%lsd
    mass_unit = merge("kg", "g ", si)
    len_unit = merge("m ", "cm", si)
    if (lsd) then
      model = "LSD"
      k_unit = merge("N/m   ", "dyn/cm", si)
    else
      model = "HERTZIAN"
      k_unit = merge("N/m^1.5   ", "dyn/cm^1.5", si)
    end if
    eta_unit = merge("kg/s", "g/s ", si)
    np = result%n_pairs
    write(u, '(a)') "MFiX deck: UNITS = '"//trim(merge("SI ", "CGS", si))//"', DES_COLL_MODEL = '"//model// &
      "', DES_INTG_METHOD = '"//trim(merge("EULER          ", "ADAMS_BASHFORTH", &
      input%integrator == mfix_integrator%euler))//"', "//fmt_int(int(input%n_phases, i8))//" DEM phase" &
      //trim(merge("s", " ", input%n_phases > 1))
    ! MFiX's @( ) arithmetic, as MFiX evaluates it (model/parse_line.f, PARSE_ARITH)
    do i = 1, deck%n_items
      do k = 1, size(deck%items(i)%values)
        if (.not. deck%items(i)%values(k)%arithmetic) cycle
        write(u, '(2x, a)') "line "//fmt_int(int(deck%items(i)%line, i8))//": "//keyword_label(deck, i, k) &
          //" = "//deck%items(i)%values(k)%expression//" = "//deck%items(i)%values(k)%text &
          //"  (MFiX's @( ) arithmetic: * and / left to right, 15 digits)"
      end do
    end do
    if (input%coarse_grained) then
      do k = 1, input%n_phases
        write(u, '(2x, a)') "coarse-grained: phase "//fmt_int(int(input%phase(k), i8))//": D_P0 = " &
          //fmt_real(input%d_p0_real(k))//" x CGP_STAT_WT^(1/3) with CGP_STAT_WT = " &
          //fmt_real(input%cgp_stat_wt(k))//": "//fmt_real(input%d_p0(k))//" "//trim(len_unit) &
          //"  (check_solids_common_discrete.f)"
      end do
    end if
    write(u, '(2x, a)') "what MFiX computes (check_solids_dem.f; mass in "//trim(mass_unit)//", k_n in " &
      //trim(k_unit)//", eta_n in "//trim(eta_unit)//", times in s):"
    write(u, '(2x, a8, 4a18)') "pair", "m_eff", "k_n", "eta_n", "t_coll"
    do p = 1, np + result%n_walls
      write(u, '(2x, a8, 4a18)') pair_label(result, p), fmt_real(result%m_eff(p)), fmt_real(result%k_n(p)), &
        fmt_real(result%eta_n(p)), fmt_real(result%t_coll(p))
    end do
    call report_row(u, 2, "TCOLL", fmt_real(result%tcoll)//" s  (smallest particle pair; walls left out)")
    call report_row(u, 2, "DTSOLID_FACTOR", fmt_real(input%dtsolid_factor))
    call report_row(u, 2, "DTSOLID", fmt_real(result%dtsolid)//" s  (TCOLL/DTSOLID_FACTOR)")

    if (input%integrator == mfix_integrator%adams_bashforth) then
      write(u, '(2x, a)') "ADAMS_BASHFORTH: an undamped contact gains energy at every step (amplitude " &
        //"x1.0008 per period at omega dt = 0.1, x1.115 at 0.5):", &
        "  no step is stable without damping. The exact answers below are for DES_INTG_METHOD = 'EULER'."
    end if
    if (.not. lsd) then
      write(u, '(2x, a)') "Hertzian: MFiX's t_coll uses HERT_KN (force/length^1.5) as a linear stiffness, " &
        //"i.e. the secant", "  stiffness at an overlap of ONE length unit (1 "//trim(len_unit)// &
        "): it depends on the unit system (CGS gives sqrt(10)", &
        "  times the SI value) and is not the Hertz contact duration."
    end if
    if (.not. a%linearised) then
      write(u, '(2x, a)') "demstep's exact answers need the Hertz contact's impact velocity: give " &
        //"--velocity V (in "//trim(len_unit)//"/s).", ""
      return
    end if

    write(u, '(2x, a)') "demstep's exact answers at DTSOLID (EULER = central differences with the " &
      //"dashpot on the previous velocity):"
    if (.not. lsd) write(u, '(2x, a)') "Hertz contacts linearised at the largest overlap of an impact at " &
      //fmt_real(a%velocity)//" "//trim(len_unit)//"/s (tangent stiffness, the stiffest state)"
    write(u, '(2x, a8, 6(1x, a19))') "pair", "damping ratio", "dt_critical", &
      "DTSOLID/dt_c", "steps", "restitution err", "overlap err"
    do p = 1, np + result%n_walls
      write(u, '(2x, a8, 6(1x, a19))') pair_label(result, p), &
        fmt_real(a%damping_ratio(p)), fmt_real(a%dt_critical(p)), &
        fmt_real(result%dtsolid/a%dt_critical(p)), fmt_int(a%steps(p)), &
        fmt_real(a%restitution_error(p)), fmt_real(a%overlap_error(p))
    end do
    if (.not. lsd) then
      write(u, '(2x, a)') "Hertz contact duration at the impact velocity, beside MFiX's t_coll:"
      do p = 1, np + result%n_walls
        write(u, '(2x, a8, a18, a)') pair_label(result, p), fmt_real(a%t_contact(p)), "  (MFiX's t_coll/it = " &
          //fmt_real(result%t_coll(p)/a%t_contact(p))//")"
      end do
    end if
    if (any(.not. a%stable)) write(u, '(2x, a)') "UNSTABLE: DTSOLID is above the exact limit of a pair marked " &
      //"DTSOLID/dt_c >= 1; MFiX would blow up there."
    if (a%walls_govern) write(u, '(2x, a)') "walls: a wall pair has a smaller limit (" &
      //fmt_real(minval(a%dt_critical(np+1:)))//" s) than every particle pair (" &
      //fmt_real(minval(a%dt_critical(:np)))//" s); MFiX leaves walls out of TCOLL."
    if (a%psd) then
      do k = 1, input%n_phases
        if (input%d_min(k) > 0.0_dp .and. input%d_min(k) < input%d_p0(k)) write(u, '(2x, a)') "size " &
          //"distribution: phase "//fmt_int(int(input%phase(k), i8))//" has particles of " &
          //fmt_real(input%d_min(k))//" "//trim(len_unit)//" (line "//fmt_int(int(input%d_min_line(k), i8)) &
          //"), below D_P0 = " &
          //fmt_real(input%d_p0(k))//"; MFiX's TCOLL ignores them."
      end do
      write(u, '(2x, a)') "  with the smallest particles: TCOLL would be "//fmt_real(a%tcoll_psd)// &
        " s, the exact limit "//fmt_real(a%dt_stability_psd)//" s (used below)"
    end if
    if (tolerance_given) then
      write(u, '(2x, a)') "tolerance "//fmt_real(a%tolerance)//" on the restitution error (--tolerance): " &
        //"largest step per pair"
    else
      write(u, '(2x, a)') "tolerance "//fmt_real(a%tolerance)//" on the restitution error (the default; " &
        //"set it with --tolerance X): largest step per pair"
    end if
    write(u, '(2x, a8, a18)') "pair", "dt"
    do p = 1, np + result%n_walls
      write(u, '(2x, a8, a18)') pair_label(result, p), fmt_real(a%dt_accuracy(p))
    end do
    call report_row(u, 2, "exact limit", fmt_real(a%dt_stability)//" s  (smallest over the pairs)")
    call report_row(u, 2, "accuracy step", fmt_real(a%dt_accuracy_min)//" s")
    if (a%governs == step_governs%accuracy) then
      call report_row(u, 2, "governs", "accuracy (tolerance "//fmt_real(a%tolerance)//" on the restitution)")
    else
      call report_row(u, 2, "governs", "stability ("//fmt_real(default_safety)//" of the exact limit)")
    end if
    write(u, '(2x, a)') "for MFiX (DTSOLID = TCOLL/DTSOLID_FACTOR = "// &
      fmt_real(result%tcoll/a%dtsolid_factor)//" s):"
    if (input%integrator == mfix_integrator%adams_bashforth) write(u, '(a)') "des_intg_method = 'EULER'"
    write(u, '(a)') "dtsolid_factor = "//fmt_real(a%dtsolid_factor)
    call report_row(u, 2, "single-contact step", fmt_real(a%dt_recommended)//" s  (the smallest over the pairs)")
    write(u, '(a)') ""
  end subroutine report

  !> The keyword of value k of item i as written in upper case, with the
  !> element's subscript: `KT_FAC`, `SPX_DT(1)`, `IC_X_S(1,2)`.
  pure function keyword_label(deck, i, k) result(label)
    type(mfix_deck_type), intent(in) :: deck
    integer, intent(in) :: i, k
    character(len=:), allocatable :: label
    integer :: j
    associate (it => deck%items(i))
      label = mfix_upper(it%name)
      if (it%n_sub == 1) then
        label = label//"("//fmt_int(int(it%lo(1) + k - 1, i8))//")"
      else if (it%n_sub > 1) then
        label = label//"("//fmt_int(int(it%lo(1), i8))
        do j = 2, it%n_sub
          label = label//","//fmt_int(int(it%lo(j), i8))
        end do
        label = label//")"
      end if
    end associate
  end function keyword_label

  !> `1-2` for particle phases 1 and 2, `1-W` for phase 1 against walls.
  pure function pair_label(result, p) result(label)
    type(mfix_result_type), intent(in) :: result
    integer, intent(in) :: p
    character(len=:), allocatable :: label
    label = fmt_int(int(result%phase_i(p), i8))//"-"
    if (result%phase_j(p) == 0) then
      label = label//"W"
    else
      label = label//fmt_int(int(result%phase_j(p), i8))
    end if
  end function pair_label


end module demstep_cli_mfix
