!> Tests of the MFiX deck reader and of MFiX's DEM collision arithmetic:
!> each syntax feature, each malformed input reported by line and keyword,
!> the packed restitution order, a CGS deck against the same deck in SI, and
!> m_eff, k_n, eta_n, TCOLL, DTSOLID against MFiX's formulas re-evaluated in
!> quad precision, on tutorial decks of MFiX 21.3 (keyword values copied into
!> small fixtures under test/data/mfix).
module test_mfix
  use testdrive, only: new_unittest, unittest_type, error_type, check, test_failed
  use demstep
  use demstep_mfix_deck
  use demstep_mfix_input
  use demstep_mfix
  use demstep_mfix_assess
  use, intrinsic :: iso_fortran_env, only: qp => real128
  implicit none
  private
  public :: collect_mfix

  real(qp), parameter :: pq = 3.14159265358979323846264338327950288_qp
  character(len=*), parameter :: nl = new_line("a")
  character(len=*), parameter :: data_dir = "test/data/mfix/"

contains

  subroutine collect_mfix(testsuite)
    type(unittest_type), allocatable, intent(out) :: testsuite(:)
    testsuite = [ &
      new_unittest("namelist syntax of keyword lines", test_syntax), &
      new_unittest("malformed lines reported by line and keyword", test_bad_lines), &
      new_unittest("reaction blocks end at MFiX's marks; three subscripts", test_blocks), &
      new_unittest("MFiX's @( ) arithmetic: operators, order, PI, 15 digits", test_arithmetic), &
      new_unittest("MFiX's @( ) arithmetic: errors by line and column", test_arithmetic_errors), &
      new_unittest("bad values and missing phases reported by keyword", test_bad_values), &
      new_unittest("packed restitution in MFiX's pair order", test_packed_order), &
      new_unittest("LSD: m_eff, k_n, eta_n, TCOLL, DTSOLID by hand", test_lsd_hand), &
      new_unittest("Hertzian (CGS deck): MFiX's arithmetic by hand", test_hertz_hand), &
      new_unittest("the same deck in CGS and SI", test_cgs_si), &
      new_unittest("tutorial decks: MFiX's DTSOLID", test_tutorials), &
      new_unittest("walls are left out of TCOLL", test_walls), &
      new_unittest("CGP: MFiX's scaling of D_P0 and its size distributions", test_cgp), &
      new_unittest("CGP: MFiX's errors 400, 410, 440, 500 by keyword", test_cgp_errors) &
      ]
  end subroutine collect_mfix

  !> MFiX's arithmetic agrees with the quad evaluation of its formulas to a few
  !> roundings; 1e-12 relative is the issue's requirement.
  subroutine check_rel(error, got, want, what)
    type(error_type), allocatable, intent(out) :: error
    real(dp), intent(in) :: got
    real(qp), intent(in) :: want
    character(len=*), intent(in) :: what
    if (.not. (abs((got - want)/want) <= 1.0e-12_qp)) call test_failed(error, what//": relative error > 1e-12")
  end subroutine check_rel

  subroutine parse_ok(text, deck, error)
    character(len=*), intent(in) :: text
    type(mfix_deck_type), intent(out) :: deck
    type(error_type), allocatable, intent(out) :: error
    type(demstep_status_type) :: status
    call parse_mfix_deck(text, deck, status)
    if (status%stat /= demstep_stat%ok) call test_failed(error, "parse failed: "//status%message)
  end subroutine parse_ok

  subroutine compute_text(text, input, result, status)
    character(len=*), intent(in) :: text
    type(mfix_input_type), intent(out) :: input
    type(mfix_result_type), intent(out) :: result
    type(demstep_status_type), intent(out) :: status
    type(mfix_deck_type) :: deck
    call parse_mfix_deck(text, deck, status)
    if (status%stat /= demstep_stat%ok) return
    call mfix_input_from_deck(deck, input, status)
    if (status%stat /= demstep_stat%ok) return
    call mfix_compute(input, result, status)
  end subroutine compute_text

  subroutine compute_file(path, input, result, error)
    character(len=*), intent(in) :: path
    type(mfix_input_type), intent(out) :: input
    type(mfix_result_type), intent(out) :: result
    type(error_type), allocatable, intent(out) :: error
    type(mfix_deck_type) :: deck
    type(demstep_status_type) :: status
    call read_mfix_deck(path, deck, status)
    if (status%stat == demstep_stat%ok) call mfix_input_from_deck(deck, input, status)
    if (status%stat == demstep_stat%ok) call mfix_compute(input, result, status)
    if (status%stat /= demstep_stat%ok) call test_failed(error, path//": "//status%message)
  end subroutine compute_file

  subroutine test_syntax(error)
    type(error_type), allocatable, intent(out) :: error
    type(mfix_deck_type) :: deck
    type(demstep_status_type) :: status
    real(dp) :: x, arr(6)
    integer :: i, line, lines(6)
    logical :: found, set(6)
    character(len=:), allocatable :: s
    character(len=32) :: strs(6)
    call parse_ok( &
      "#!MFIX-GUI gui_version = 21.3" // nl // &
      "  Kn = 1.5d3  ! a comment" // nl // &
      "KN_W=2.0D-3 # another" // nl // &
      "  des_en_input(1:3) = 3*0.9" // nl // &
      "des_en_input(4) = 0.7, 0.6" // nl // &
      "ic_x(2,3) = 1.0   MMAX = 2   run_name = 'a#b!c'" // nl // &
      "flag = .True.  other = .T.  ys = F" // nl // &
      "" // nl // &
      "kt_fac = @(1.48/1.72)" // nl // &
      "@(RXNS)" // nl // &
      "  nonsense inside a reaction block" // nl // &
      "@(END)" // nl // &
      "Species_Eq(0:2) = .F. .F. .F." // nl // &
      "THERMO DATA" // nl // &
      "not a keyword line", deck, error)
    if (allocated(error)) return
    call mfix_get_real(deck, "KN", x, found, line, status)
    call check(error, found .and. x == 1.5e3_dp .and. line == 2, "case-insensitive key, d exponent")
    if (allocated(error)) return
    call mfix_get_real(deck, "kn_w", x, found, line, status)
    call check(error, x == 2.0e-3_dp .and. line == 3, "D exponent, # comment")
    if (allocated(error)) return
    call mfix_get_real_array(deck, "des_en_input", 6, arr, set, lines, status)
    call check(error, status%stat, demstep_stat%ok)
    if (allocated(error)) return
    call check(error, all(arr(1:5) == [0.9_dp, 0.9_dp, 0.9_dp, 0.7_dp, 0.6_dp]) .and. all(set(1:5)) &
      .and. .not. set(6) .and. lines(3) == 4 .and. lines(5) == 5, "range, repeat count, consecutive values")
    if (allocated(error)) return
    ! two subscripts kept; several assignments on one line
    do i = 1, deck%n_items
      if (deck%items(i)%name == "ic_x") exit
    end do
    call check(error, deck%items(i)%n_sub == 2 .and. deck%items(i)%lo(1) == 2 .and. deck%items(i)%lo(2) == 3, &
      "KEY(i,j)")
    if (allocated(error)) return
    call mfix_get_integer(deck, "mmax", i, found, line, status)
    call check(error, found .and. i == 2 .and. line == 6, "MMAX on a shared line")
    if (allocated(error)) return
    call mfix_get_string(deck, "run_name", s, found, line, status)
    call check(error, s == "a#b!c", "comment characters inside quotes")
    if (allocated(error)) return
    call mfix_get_string(deck, "flag", s, found, line, status)
    call check(error, s == ".True.", "logical kept as text")
    if (allocated(error)) return
    call mfix_get_string_array(deck, "species_eq", 6, strs, set, lines, status)
    ! Species_Eq(0:2) starts at index 0, outside [1, 6]: refused by index
    call check(error, status%stat == demstep_stat%invalid_input .and. index(status%message, "line 13: SPECIES_EQ(0)") == 1, &
      "index out of range named")
    if (allocated(error)) return
    ! MFiX's arithmetic (tests/dem/DEM05's KT_FAC): 1.48/1.72 to 15 digits
    call mfix_get_real(deck, "kt_fac", x, found, line, status)
    call check(error, status%stat == demstep_stat%ok .and. x == 0.860465116279070_dp .and. line == 9, &
      "@(1.48/1.72) evaluated as MFiX does")
    if (allocated(error)) return
    ! reaction block and THERMO DATA skipped
    call check(error, .not. mfix_has_keyword(deck, "nonsense") .and. .not. mfix_has_keyword(deck, "not"), &
      "blocks skipped")
  end subroutine test_syntax

  !> `kt_fac = expr` read back: exactly the double nearest `want`, a decimal
  !> of 15 significant digits (MFiX's G22.15 text, parse_line.f:562), so the
  !> comparison is exact.
  subroutine check_arithmetic(error, expr, want)
    type(error_type), allocatable, intent(out) :: error
    character(len=*), intent(in) :: expr
    real(dp), intent(in) :: want
    type(mfix_deck_type) :: deck
    type(demstep_status_type) :: status
    real(dp) :: x
    logical :: found
    integer :: line
    call parse_ok("kt_fac = "//expr, deck, error)
    if (allocated(error)) return
    call mfix_get_real(deck, "kt_fac", x, found, line, status)
    call check(error, status%stat == demstep_stat%ok .and. x == want, expr//": value")
    if (allocated(error)) return
    call check(error, deck%items(1)%values(1)%arithmetic .and. deck%items(1)%values(1)%expression == expr, &
      expr//": the expression is kept for the report")
  end subroutine check_arithmetic

  subroutine test_arithmetic(error)
    type(error_type), allocatable, intent(out) :: error
    type(mfix_deck_type) :: deck
    type(demstep_status_type) :: status
    real(dp) :: arr(4)
    logical :: set(4)
    integer :: lines(4)
    call check_arithmetic(error, "@(1.48/1.72)", 0.860465116279070_dp)
    if (allocated(error)) return
    ! one precedence, left to right: (6/2)*3, not 6/(2*3)
    call check_arithmetic(error, "@(6/2*3)", 9.0_dp)
    if (allocated(error)) return
    call check_arithmetic(error, "@(1/4/2)", 0.125_dp)
    if (allocated(error)) return
    ! PI in any case, blanks skipped
    call check_arithmetic(error, "@(2*PI)", 6.28318530717959_dp)
    if (allocated(error)) return
    call check_arithmetic(error, "@( pi / 4 )", 0.785398163397448_dp)
    if (allocated(error)) return
    ! 15 significant digits, not the double 1/3
    call check_arithmetic(error, "@(1/3)", 0.333333333333333_dp)
    if (allocated(error)) return
    call check(error, 0.333333333333333_dp /= 1.0_dp/3.0_dp, "the rounding is visible")
    if (allocated(error)) return
    ! signed operands, Fortran exponents, one operand
    call check_arithmetic(error, "@(-2.5d-1*4)", -1.0_dp)
    if (allocated(error)) return
    call check_arithmetic(error, "@(7)", 7.0_dp)
    if (allocated(error)) return
    call check_arithmetic(error, "@(1.0E+20*3)", 3.0e20_dp)
    if (allocated(error)) return
    ! among other values of an array keyword
    call parse_ok("des_en_input = 0.9 @(0.8) 0.7", deck, error)
    if (allocated(error)) return
    call mfix_get_real_array(deck, "des_en_input", 4, arr, set, lines, status)
    call check(error, status%stat == demstep_stat%ok .and. all(arr(1:3) == [0.9_dp, 0.8_dp, 0.7_dp]) &
      .and. .not. set(4), "an array element")
  end subroutine test_arithmetic

  subroutine test_arithmetic_errors(error)
    type(error_type), allocatable, intent(out) :: error
    type(mfix_deck_type) :: deck
    type(demstep_status_type) :: status
    integer :: i, line
    logical :: found
    ! MFiX's READ would take 1+2 as 1e+2 = 100: refused at the '+'
    call expect_parse_error(error, "kn = @(1+2)", "line 1, column 9: KN: @(1+2): '1+2': MFiX's @( ) has no '+'")
    if (allocated(error)) return
    call parse_mfix_deck("units = 'SI'"//nl//"  kn = @(1+2)", deck, status)
    call check(error, status%where == "KN" .and. status%index == 0 .and. index(status%message, "line 2, column 11:") &
      == 1, "structured location: "//status%message)
    if (allocated(error)) return
    call expect_parse_error(error, "kn = @(2-1)", "line 1, column 9: KN: @(2-1): '2-1': MFiX's @( ) has no '+'")
    if (allocated(error)) return
    ! no parentheses inside: the first ')' closes
    call expect_parse_error(error, "kn = @((1/2))", "line 1, column 8: KN: @((1/2): '(': MFiX's @( ) ends at " &
      //"the first ')'")
    if (allocated(error)) return
    ! no functions
    call expect_parse_error(error, "kn = @(sqrt(2))", "line 1, column 8: KN: @(sqrt(2): 'sqrt(2' is neither a " &
      //"number nor PI")
    if (allocated(error)) return
    ! missing operands (MFiX's "Invalid operator")
    call expect_parse_error(error, "kn = @(2**3)", "line 1, column 10: KN: @(2**3): an operand is missing " &
      //"before '*'")
    if (allocated(error)) return
    call expect_parse_error(error, "kn = @(*3)", "line 1, column 8: KN: @(*3): an operand is missing before '*'")
    if (allocated(error)) return
    call expect_parse_error(error, "kn = @(3/)", "line 1, column 10: KN: @(3/): an operand is missing before ')'")
    if (allocated(error)) return
    call expect_parse_error(error, "kn = @()", "line 1, column 8: KN: @(): an operand is missing before ')'")
    if (allocated(error)) return
    call expect_parse_error(error, "kn = @(1/0)", "line 1, column 10: KN: @(1/0): division by zero")
    if (allocated(error)) return
    call expect_parse_error(error, "kn = @(1e300*1e300)", "line 1, column 14: KN: @(1e300*1e300): the value " &
      //"leaves the double range")
    if (allocated(error)) return
    call expect_parse_error(error, "kn = @(1.5e)", "line 1, column 11: KN: @(1.5e): '1.5e' is neither")
    if (allocated(error)) return
    call expect_parse_error(error, nl//"kn = @(1", "line 2: kn: '@(' without ')'")
    if (allocated(error)) return
    ! 'r*@( )': MFiX's leading blank makes r null values
    call expect_parse_error(error, "des_en_input = 3*@(1/2)", "line 1, column 18: DES_EN_INPUT: '*' before '@('")
    if (allocated(error)) return
    ! an integer keyword: MFiX's namelist read refuses the real it writes
    call parse_ok("mmax = @(2)", deck, error)
    if (allocated(error)) return
    i = 0
    call mfix_get_integer(deck, "mmax", i, found, line, status)
    call check(error, status%stat == demstep_stat%invalid_input .and. index(status%message, &
      "line 1: MMAX: @(2) gives the real 2.00000000000000") == 1, "integer keyword: "//status%message)
  end subroutine test_arithmetic_errors

  !> MFiX ends a reaction block at any `@( )` holding END (parse_line.f,
  !> END_RXN), so `@(DES_END)` too; species keywords take three subscripts
  !> (the legacy dem-tests condensation, evaporation and reactive-chemistry decks).
  subroutine test_blocks(error)
    type(error_type), allocatable, intent(out) :: error
    type(mfix_deck_type) :: deck
    type(demstep_status_type) :: status
    real(dp) :: x
    logical :: found
    integer :: line
    call parse_ok("@(DES_RXNS)"//nl//"  Drying { chem_eq = 'x --> y' }"//nl//"@(DES_END)"//nl// &
      "kn = 10.0"//nl//"ic_x_s(1,1,1) = 1.0   ! liquid water"//nl//"  ! @(RXNS) in a comment"//nl// &
      "kn_w = 20.0", deck, error)
    if (allocated(error)) return
    call mfix_get_real(deck, "kn", x, found, line, status)
    call check(error, found .and. x == 10.0_dp .and. line == 4, "@(DES_END) ends the block")
    if (allocated(error)) return
    call mfix_get_real(deck, "kn_w", x, found, line, status)
    call check(error, found .and. x == 20.0_dp .and. line == 7, "a mark in a comment starts no block")
    if (allocated(error)) return
    call check(error, deck%items(2)%n_sub == 3 .and. deck%items(2)%lo(3) == 1, "three subscripts")
    if (allocated(error)) return
    call expect_parse_error(error, "x(1,2,3,4) = 1", "line 1: x: more than three subscripts")
  end subroutine test_blocks

  subroutine expect_parse_error(error, text, prefix)
    type(error_type), allocatable, intent(out) :: error
    character(len=*), intent(in) :: text, prefix
    type(mfix_deck_type) :: deck
    type(demstep_status_type) :: status
    call parse_mfix_deck(text, deck, status)
    call check(error, status%stat == demstep_stat%invalid_input, "refused: "//text)
    if (allocated(error)) return
    call check(error, index(status%message, prefix) == 1, "'"//status%message//"' starts with '"//prefix//"'")
  end subroutine expect_parse_error

  subroutine test_bad_lines(error)
    type(error_type), allocatable, intent(out) :: error
    type(mfix_deck_type) :: deck
    type(demstep_status_type) :: status
    call expect_parse_error(error, "kn = 1" // nl // "= 3", "line 2: expected a keyword assignment")
    if (allocated(error)) return
    call expect_parse_error(error, "units = 'SI'" // nl // "kn 1000", "line 2: kn: expected '='")
    if (allocated(error)) return
    call expect_parse_error(error, "kn =", "line 1: kn: no value after '='")
    if (allocated(error)) return
    call expect_parse_error(error, "run_name = 'abc", "line 1: run_name: string without a closing quote")
    if (allocated(error)) return
    call expect_parse_error(error, "d_p0(x) = 1", "line 1: d_p0: bad subscript '(x)'")
    if (allocated(error)) return
    call expect_parse_error(error, "d_p0(3:1) = 1", "line 1: d_p0: empty subscript range")
    if (allocated(error)) return
    call expect_parse_error(error, "d_p0(1 = 1", "line 1: d_p0: subscript without ')'")
    if (allocated(error)) return
    call expect_parse_error(error, nl // "kt_fac = @(1.48/1.72", "line 2: kt_fac: '@(' without ')'")
    if (allocated(error)) return
    call expect_parse_error(error, "x = 0*1.0", "line 1: x: repeat count '0*' must lie in")
    if (allocated(error)) return
    ! a missing file is reported with its name
    call read_mfix_deck(data_dir//"no_such_deck.mfx", deck, status)
    call check(error, status%stat == demstep_stat%io_error .and. &
      index(status%message, data_dir//"no_such_deck.mfx: no such file") == 1, "missing file named")
  end subroutine test_bad_lines

  !> A two-phase LSD deck with one line replaced.
  function lsd_deck(replace_key, replacement) result(text)
    character(len=*), intent(in) :: replace_key, replacement
    character(len=:), allocatable :: text
    character(len=40), parameter :: lines(13) = [character(len=40) :: &
      "units = 'SI'", "mmax = 2", "solids_model(1:2) = 'DEM' 'DEM'", &
      "d_p0(1) = 2.0e-3", "d_p0(2) = 4.0e-3", "ro_s0(1) = 2500.0", "ro_s0(2) = 1000.0", &
      "kn = 1000.0", "kn_w = 5000.0", "des_en_input = 0.9 0.8 0.7", &
      "des_en_wall_input = 0.6 0.5", "des_etat_fac = 0.5", "dtsolid_factor = 50"]
    integer :: i
    text = ""
    do i = 1, size(lines)
      if (len(replace_key) > 0 .and. index(lines(i), replace_key) == 1) then
        text = text//replacement//nl
      else
        text = text//trim(lines(i))//nl
      end if
    end do
  end function lsd_deck

  subroutine expect_deck_error(error, text, prefix)
    type(error_type), allocatable, intent(out) :: error
    character(len=*), intent(in) :: text, prefix
    type(mfix_input_type) :: input
    type(mfix_result_type) :: result
    type(demstep_status_type) :: status
    call compute_text(text, input, result, status)
    call check(error, status%stat == demstep_stat%invalid_input, "refused: "//prefix)
    if (allocated(error)) return
    call check(error, index(status%message, prefix) == 1, "'"//status%message//"' starts with '"//prefix//"'")
  end subroutine expect_deck_error

  subroutine test_bad_values(error)
    type(error_type), allocatable, intent(out) :: error
    type(mfix_input_type) :: input
    type(mfix_result_type) :: result
    type(demstep_status_type) :: status
    call compute_text(lsd_deck("", ""), input, result, status)
    call check(error, status%stat, demstep_stat%ok, "the base deck is valid")
    if (allocated(error)) return
    call expect_deck_error(error, lsd_deck("kn =", "kn = abc"), "line 8: KN: 'abc' is not a number")
    if (allocated(error)) return
    call expect_deck_error(error, lsd_deck("kn =", "kn = 1.0 2.0"), "line 8: KN: expects one value, found 2")
    if (allocated(error)) return
    call expect_deck_error(error, lsd_deck("kn =", "kn = -1.0"), "line 8: KN: must be > 0")
    if (allocated(error)) return
    call expect_deck_error(error, lsd_deck("kn =", "mew = 0.1"), "KN: missing (DES_COLL_MODEL = 'LSD')")
    if (allocated(error)) return
    call expect_deck_error(error, lsd_deck("d_p0(2)", "d_p0(1) = 2.0e-3"), "D_P0(2): missing for DEM solids phase 2")
    if (allocated(error)) return
    call expect_deck_error(error, lsd_deck("ro_s0(2)", "ro_s0(2) = 0"), "line 7: RO_S0(2): must be > 0")
    if (allocated(error)) return
    call expect_deck_error(error, lsd_deck("des_en_input", "des_en_input = 0.9 0.8"), &
      "DES_EN_INPUT(3): missing (the pair of DEM phases 2 and 2)")
    if (allocated(error)) return
    call expect_deck_error(error, lsd_deck("des_en_input", "des_en_input = 0.9 1.2 0.7"), &
      "line 10: DES_EN_INPUT(2): must lie in [0, 1]")
    if (allocated(error)) return
    call expect_deck_error(error, lsd_deck("des_en_wall", "des_en_wall_input(1) = 0.6"), &
      "DES_EN_WALL_INPUT(2): missing")
    if (allocated(error)) return
    call expect_deck_error(error, lsd_deck("dtsolid_factor", "dtsolid_factor = 5"), &
      "line 13: DTSOLID_FACTOR: MFiX requires >= 10")
    if (allocated(error)) return
    call expect_deck_error(error, lsd_deck("units", "units = 'MKS'"), "line 1: UNITS: 'MKS' is neither")
    if (allocated(error)) return
    call expect_deck_error(error, lsd_deck("units", "mew = 0.1"), "UNITS: missing")
    if (allocated(error)) return
    call expect_deck_error(error, lsd_deck("solids_model", "solids_model(1:2) = 'DEM' 'XYZ'"), &
      "line 3: SOLIDS_MODEL(2): unknown solids model 'XYZ'")
    if (allocated(error)) return
    call expect_deck_error(error, lsd_deck("solids_model", "solids_model(1:2) = 'DEM' 'TFM'"), &
      "line 3: SOLIDS_MODEL(2): MFiX requires the TFM phases before the DEM phases")
    if (allocated(error)) return
    ! an evaluated value is checked as a written one
    call expect_deck_error(error, lsd_deck("des_etat_fac", "des_etat_fac = @(3/2)"), &
      "line 12: DES_ETAT_FAC: must lie in [0, 1]")
    if (allocated(error)) return
    call expect_deck_error(error, lsd_deck("kn_w", "des_coll_model = 'hertzian'"), &
      "DES_ET_INPUT(1): missing")
  end subroutine test_bad_values

  subroutine test_packed_order(error)
    type(error_type), allocatable, intent(out) :: error
    type(mfix_input_type) :: input
    type(mfix_result_type) :: result
    type(demstep_status_type) :: status
    real(dp), parameter :: en(6) = [0.91_dp, 0.82_dp, 0.73_dp, 0.64_dp, 0.55_dp, 0.46_dp]
    integer, parameter :: pi_(9) = [1, 1, 1, 2, 2, 3, 1, 2, 3], pj(9) = [1, 2, 3, 2, 3, 3, 0, 0, 0]
    integer :: k, i, j
    real(qp) :: m(3), meff, eta, d(3), ln
    call compute_text("units='SI'" // nl // "mmax=3 solids_model = 3*'DEM'" // nl // &
      "d_p0 = 1e-3 2e-3 3e-3" // nl // "ro_s0 = 3*2000" // nl // "kn = 100" // nl // "kn_w = 100" // nl // &
      "des_en_input = 0.91 0.82 0.73 0.64 0.55 0.46" // nl // "des_en_wall_input = 3*0.5", input, result, status)
    call check(error, status%stat, demstep_stat%ok)
    if (allocated(error)) return
    call check(error, all(result%phase_i == pi_) .and. all(result%phase_j == pj), "pairs 11 12 13 22 23 33 1W 2W 3W")
    if (allocated(error)) return
    ! each pair's damping uses its own restitution: DES_EN_INPUT(k) for the k-th pair
    d = [1.0e-3_qp, 2.0e-3_qp, 3.0e-3_qp]
    m = pq/6*d**3*2000
    k = 0
    do i = 1, 3
      do j = i, 3
        k = k + 1
        call check(error, mfix_pair_index(i, j, 3) == k, "pair index")
        if (allocated(error)) return
        meff = m(i)*m(j)/(m(i) + m(j))
        ln = log(real(en(k), qp))
        eta = 2*sqrt(100*meff)*abs(ln)/sqrt(pq**2 + ln**2)
        call check_rel(error, result%eta_n(k), eta, "eta_n of the packed pair")
        if (allocated(error)) return
      end do
    end do
  end subroutine test_packed_order

  !> Quad reference of one LSD pair.
  subroutine lsd_ref(d1, r1, d2, r2, kn, en, meff, eta, t)
    real(qp), intent(in) :: d1, r1, d2, r2, kn, en
    real(qp), intent(out) :: meff, eta, t
    real(qp) :: m1, m2
    m1 = pq/6*d1**3*r1
    m2 = pq/6*d2**3*r2
    meff = m1*m2/(m1 + m2)
    eta = 2*sqrt(kn*meff)*abs(log(en))/sqrt(pq**2 + log(en)**2)
    t = pq/sqrt(kn/meff - (eta/meff)**2/4)
  end subroutine lsd_ref

  subroutine test_lsd_hand(error)
    type(error_type), allocatable, intent(out) :: error
    type(mfix_input_type) :: input
    type(mfix_result_type) :: result
    type(demstep_status_type) :: status
    real(qp) :: meff(5), eta(5), t(5), tcoll
    integer :: k
    call compute_text(lsd_deck("", ""), input, result, status)
    call check(error, status%stat, demstep_stat%ok)
    if (allocated(error)) return
    call lsd_ref(2.0e-3_qp, 2500.0_qp, 2.0e-3_qp, 2500.0_qp, 1000.0_qp, 0.9_qp, meff(1), eta(1), t(1))
    call lsd_ref(2.0e-3_qp, 2500.0_qp, 4.0e-3_qp, 1000.0_qp, 1000.0_qp, 0.8_qp, meff(2), eta(2), t(2))
    call lsd_ref(4.0e-3_qp, 1000.0_qp, 4.0e-3_qp, 1000.0_qp, 1000.0_qp, 0.7_qp, meff(3), eta(3), t(3))
    ! walls: MASS_EFF = the particle mass; lsd_ref with an infinitely heavy
    ! partner is the same, written out here
    meff(4) = pq/6*(2.0e-3_qp)**3*2500
    meff(5) = pq/6*(4.0e-3_qp)**3*1000
    eta(4) = 2*sqrt(5000*meff(4))*abs(log(0.6_qp))/sqrt(pq**2 + log(0.6_qp)**2)
    eta(5) = 2*sqrt(5000*meff(5))*abs(log(0.5_qp))/sqrt(pq**2 + log(0.5_qp)**2)
    t(4) = pq/sqrt(5000/meff(4) - (eta(4)/meff(4))**2/4)
    t(5) = pq/sqrt(5000/meff(5) - (eta(5)/meff(5))**2/4)
    do k = 1, 5
      call check_rel(error, result%m_eff(k), meff(k), "m_eff")
      if (allocated(error)) return
      call check_rel(error, result%eta_n(k), eta(k), "eta_n")
      if (allocated(error)) return
      call check_rel(error, result%t_coll(k), t(k), "t_coll")
      if (allocated(error)) return
    end do
    call check(error, all(result%k_n == [1000.0_dp, 1000.0_dp, 1000.0_dp, 5000.0_dp, 5000.0_dp]), "k_n")
    if (allocated(error)) return
    ! KT_FAC not in the deck: MFiX's default literal is single precision
    call check(error, result%k_t(1) == 1000.0_dp*real(0.28571428571429, dp) .and. &
      result%k_t(1) /= 1000.0_dp*(2.0_dp/7.0_dp), "KT = KT_FAC KN with MFiX's single-precision default")
    if (allocated(error)) return
    call check(error, result%eta_t(1) == 0.5_dp*result%eta_n(1), "DES_ETAT = DES_ETAT_FAC DES_ETAN")
    if (allocated(error)) return
    tcoll = minval(t(1:3))
    call check_rel(error, result%tcoll, tcoll, "TCOLL")
    if (allocated(error)) return
    call check_rel(error, result%dtsolid, tcoll/50, "DTSOLID")
  end subroutine test_lsd_hand

  subroutine test_hertz_hand(error)
    type(error_type), allocatable, intent(out) :: error
    type(mfix_input_type) :: input
    type(mfix_result_type) :: result
    real(qp) :: d(2), ro(2), e(2), nu(2), g(2), m(2), r(2), meff, reff, eeff, geff, kn, kt, eta, etat, t
    real(qp) :: en(3), tcoll, ew, nuw, gw
    integer :: i, j, k
    call compute_file(data_dir//"hertz_cgs.dat", input, result, error)
    if (allocated(error)) return
    call check(error, input%units == mfix_units%cgs .and. input%model == mfix_model%hertzian .and. &
      input%integrator == mfix_integrator%adams_bashforth, "units, model, integrator")
    if (allocated(error)) return
    d = [0.2_qp, 0.5_qp]; ro = [2.5_qp, 7.8_qp]; e = [6.3e11_qp, 2.1e12_qp]; nu = [0.22_qp, 0.30_qp]
    en = [0.9_qp, 0.8_qp, 0.7_qp]
    g = e/(2*(1 + nu))
    m = pq/6*d**3*ro
    r = d/2
    tcoll = huge(1.0_qp)
    k = 0
    do i = 1, 2
      do j = i, 2
        k = k + 1
        meff = m(i)*m(j)/(m(i) + m(j))
        reff = r(i)*r(j)/(r(i) + r(j))
        eeff = 1/((1 - nu(i)**2)/e(i) + (1 - nu(j)**2)/e(j))
        geff = g(i)*g(j)/(g(i)*(2 - nu(j)) + g(j)*(2 - nu(i)))
        kn = 4*sqrt(reff)*eeff/3
        kt = 8*sqrt(reff)*geff
        eta = 2*sqrt(kn*meff)*abs(log(en(k)))/sqrt(pq**2 + log(en(k))**2)
        etat = 2*sqrt(kt*2*meff/7)*abs(log(0.6_qp))/sqrt(pq**2 + log(0.6_qp)**2)
        t = pq/sqrt(kn/meff - (eta/meff)**2/4)
        tcoll = min(tcoll, t)
        call check_rel(error, result%k_n(k), kn, "HERT_KN")
        if (allocated(error)) return
        call check_rel(error, result%k_t(k), kt, "HERT_KT")
        if (allocated(error)) return
        call check_rel(error, result%eta_n(k), eta, "DES_ETAN")
        if (allocated(error)) return
        call check_rel(error, result%eta_t(k), etat, "DES_ETAT")
        if (allocated(error)) return
        call check_rel(error, result%t_coll(k), t, "TCOLL_TMP")
        if (allocated(error)) return
      end do
    end do
    call check_rel(error, result%tcoll, tcoll, "TCOLL")
    if (allocated(error)) return
    call check_rel(error, result%dtsolid, tcoll/40, "DTSOLID with DTSOLID_FACTOR = 40")
    if (allocated(error)) return
    ! the steel-wall pair
    ew = 2.1e12_qp; nuw = 0.3_qp; gw = ew/(2*(1 + nuw))
    eeff = e(2)*ew/(e(2)*(1 - nuw**2) + ew*(1 - nu(2)**2))
    kn = 4*sqrt(r(2))*eeff/3
    eta = 2*sqrt(kn*m(2))*abs(log(0.75_qp))/sqrt(pq**2 + log(0.75_qp)**2)
    call check_rel(error, result%k_n(5), kn, "HERT_KWN")
    if (allocated(error)) return
    geff = g(2)*gw/(g(2)*(2 - nuw) + gw*(2 - nu(2)))
    call check_rel(error, result%k_t(5), 8*sqrt(r(2))*geff, "HERT_KWT")
    if (allocated(error)) return
    call check_rel(error, result%t_coll(5), pq/sqrt(kn/m(2) - (eta/m(2))**2/4), "wall TCOLL_TMP")
  end subroutine test_hertz_hand

  subroutine test_cgs_si(error)
    type(error_type), allocatable, intent(out) :: error
    type(mfix_input_type) :: input
    type(mfix_result_type) :: si, cgs
    type(demstep_status_type) :: status
    ! LSD: the same physics in both unit systems gives the same times (the
    ! damping and mass scale together); 1e-14 covers the unit conversions
    call compute_text(lsd_deck("", ""), input, si, status)
    call check(error, status%stat, demstep_stat%ok)
    if (allocated(error)) return
    call compute_text("units = 'CGS'" // nl // "mmax = 2" // nl // "solids_model(1:2) = 2*'DEM'" // nl // &
      "d_p0 = 0.2 0.4" // nl // "ro_s0 = 2.5 1.0" // nl // "kn = 1.0d6" // nl // "kn_w = 5.0d6" // nl // &
      "des_en_input = 0.9 0.8 0.7" // nl // "des_en_wall_input = 0.6 0.5", input, cgs, status)
    call check(error, status%stat, demstep_stat%ok)
    if (allocated(error)) return
    call check(error, maxval(abs(cgs%t_coll - si%t_coll)/si%t_coll) < 1.0e-14_dp, "LSD collision times agree")
    if (allocated(error)) return
    call check(error, abs(cgs%dtsolid - si%dtsolid)/si%dtsolid < 1.0e-14_dp, "LSD DTSOLID agrees")
    if (allocated(error)) return
    call check(error, maxval(abs(cgs%m_eff/si%m_eff - 1000.0_dp))/1000.0_dp < 1.0e-14_dp, "m_eff in g")
    if (allocated(error)) return
    ! Hertzian: MFiX's TCOLL uses HERT_KN (force/length^1.5) as a stiffness, so
    ! the same deck in CGS gives sqrt(10) times the SI value
    call compute_file(data_dir//"hertz_cgs.dat", input, cgs, error)
    if (allocated(error)) return
    call compute_text("UNITS = 'SI'" // nl // "MMAX = 2   SOLIDS_MODEL(1:2) = 2*'DEM'" // nl // &
      "D_P0 = 0.002 0.005   RO_S0 = 2500 7800" // nl // "DES_COLL_MODEL = 'HERTZIAN'" // nl // &
      "E_YOUNG = 6.3d10 2.1d11   V_POISSON = 0.22 0.30   EW_YOUNG = 2.1d11   VW_POISSON = 0.3" // nl // &
      "DES_EN_INPUT = 0.9 0.8 0.7   DES_ET_INPUT = 3*0.6" // nl // &
      "DES_EN_WALL_INPUT = 0.85 0.75   DES_ET_WALL_INPUT = 2*0.5   DTSOLID_FACTOR = 40", input, si, status)
    call check(error, status%stat, demstep_stat%ok)
    if (allocated(error)) return
    call check(error, maxval(abs(cgs%t_coll/si%t_coll - sqrt(10.0_dp)))/sqrt(10.0_dp) < 1.0e-13_dp, &
      "Hertzian TCOLL: CGS = sqrt(10) SI")
  end subroutine test_cgs_si

  subroutine test_tutorials(error)
    type(error_type), allocatable, intent(out) :: error
    type(mfix_input_type) :: input
    type(mfix_result_type) :: result
    real(qp) :: meff, eta, t(3), tw
    ! hopper_massinflow_psd: phases 2 mm / 2500 and 4 mm / 1000, KN = 1000, e = 0.5
    call compute_file(data_dir//"hopper_two_phase.mfx", input, result, error)
    if (allocated(error)) return
    call lsd_ref(2.0e-3_qp, 2500.0_qp, 2.0e-3_qp, 2500.0_qp, 1000.0_qp, 0.5_qp, meff, eta, t(1))
    call lsd_ref(2.0e-3_qp, 2500.0_qp, 4.0e-3_qp, 1000.0_qp, 1000.0_qp, 0.5_qp, meff, eta, t(2))
    call lsd_ref(4.0e-3_qp, 1000.0_qp, 4.0e-3_qp, 1000.0_qp, 1000.0_qp, 0.5_qp, meff, eta, t(3))
    call check_rel(error, result%tcoll, minval(t), "hopper TCOLL")
    if (allocated(error)) return
    call check_rel(error, result%dtsolid, minval(t)/50, "hopper DTSOLID")
    if (allocated(error)) return
    ! and in figures (hand arithmetic, the 11 pair governs): TCOLL = 2.32793e-4 s,
    ! DTSOLID = 4.65587e-6 s
    call check(error, abs(result%dtsolid - 4.65587e-6_dp) < 5.0e-12_dp, "hopper DTSOLID = 4.65587e-6 s")
    if (allocated(error)) return
    ! fluid_bed_2d: 4 mm, 2700 kg/m^3, KN = 1000, e = 0.9, walls e = 1
    call compute_file(data_dir//"fluid_bed_2d.mfx", input, result, error)
    if (allocated(error)) return
    call lsd_ref(4.0e-3_qp, 2700.0_qp, 4.0e-3_qp, 2700.0_qp, 1000.0_qp, 0.9_qp, meff, eta, t(1))
    call check_rel(error, result%dtsolid, t(1)/50, "fluid bed DTSOLID")
    if (allocated(error)) return
    ! in figures: TCOLL = 6.68575e-4 s, DTSOLID = 1.33715e-5 s
    call check(error, abs(result%dtsolid - 1.33715e-5_dp) < 5.0e-11_dp, "fluid bed DTSOLID = 1.33715e-5 s")
    if (allocated(error)) return
    ! e = 1 at the wall: no damping, the undamped half period
    tw = pq*sqrt(pq/6*(4.0e-3_qp)**3*2700/1000)
    call check(error, result%eta_n(2) == 0.0_dp, "e = 1: no wall damping")
    if (allocated(error)) return
    call check_rel(error, result%t_coll(2), tw, "fluid bed wall t_coll")
  end subroutine test_tutorials

  subroutine test_walls(error)
    type(error_type), allocatable, intent(out) :: error
    type(mfix_input_type) :: input
    type(mfix_result_type) :: result
    type(demstep_status_type) :: status
    ! KN_W = 100 KN: the wall contact is 10 times shorter, yet TCOLL ignores it
    call compute_text(lsd_deck("kn_w", "kn_w = 1.0d5"), input, result, status)
    call check(error, status%stat, demstep_stat%ok)
    if (allocated(error)) return
    call check(error, minval(result%t_coll(4:5)) < 0.2_dp*result%tcoll, "the wall pairs are faster")
    if (allocated(error)) return
    call check(error, result%tcoll == minval(result%t_coll(1:3)), "TCOLL from particle pairs only")
  end subroutine test_walls

  !> A two-phase deck, phase 1 'CGP' and phase 2 'DEM', with extra lines.
  function cgp_deck(extra) result(text)
    character(len=*), intent(in) :: extra
    character(len=:), allocatable :: text
    text = "units = 'SI'"//nl//"mmax = 2"//nl//"solids_model(1:2) = 'CGP' 'DEM'"//nl// &
      "d_p0 = 1.0e-3 2.0e-3"//nl//"ro_s0 = 2500.0 1000.0"//nl//"kn = 1000.0"//nl//"kn_w = 1000.0"//nl// &
      "des_en_input = 3*0.9"//nl//"des_en_wall_input = 2*0.9"//nl//extra
  end function cgp_deck

  subroutine test_cgp(error)
    type(error_type), allocatable, intent(out) :: error
    type(mfix_input_type) :: input
    type(mfix_result_type) :: result
    type(demstep_status_type) :: status
    ! weight 27 (check_solids_common_discrete.f:147): the same double operations
    call compute_text(cgp_deck("cgp_stat_wt = 27.0 1.0"//nl//"ic_psd_min_dp(1,1) = 0.5e-3"//nl// &
      "bc_psd_min_dp(2,2) = 1.0e-3"), input, result, status)
    call check(error, status%stat, demstep_stat%ok, "weights: "//status%message)
    if (allocated(error)) return
    call check(error, input%coarse_grained .and. input%d_p0(1) == 1.0e-3_dp*27.0_dp**(1.0_dp/3.0_dp) .and. &
      input%d_p0(2) == 2.0e-3_dp .and. all(input%d_p0_real == [1.0e-3_dp, 2.0e-3_dp]) .and. &
      all(input%cgp_stat_wt == [27.0_dp, 1.0_dp]), "D_P0 := D_P0 CGP_STAT_WT^(1/3), every discrete phase")
    if (allocated(error)) return
    ! the size distributions scale with the weight (check_solids_common_discrete.f:191, check_bc_dem.f:159)
    call check(error, input%d_min(1) == 0.5e-3_dp*27.0_dp**(1.0_dp/3.0_dp) .and. input%d_min(2) == 1.0e-3_dp, &
      "PSD_MIN_DP scaled by the weight")
    if (allocated(error)) return
    ! the coarse-grained particles' mass: 27 times the real one's
    call check_rel(error, result%m_eff(1), pq/6*(1.0e-3_qp*3)**3*2500/2, "m_eff 1-1")
    if (allocated(error)) return
    ! CGP_D_P0 alone: weight (CGP_D_P0/D_P0)^3 (:132), the size distribution not scaled
    call compute_text(cgp_deck("cgp_d_p0(1) = 3.0e-3"//nl//"cgp_stat_wt(2) = 1.0"//nl// &
      "ic_psd_min_dp(1,1) = 0.5e-3"), input, result, status)
    call check(error, status%stat, demstep_stat%ok, "CGP_D_P0: "//status%message)
    if (allocated(error)) return
    call check(error, input%cgp_stat_wt(1) == (3.0e-3_dp/1.0e-3_dp)**3 .and. &
      input%d_p0(1) == 1.0e-3_dp*((3.0e-3_dp/1.0e-3_dp)**3)**(1.0_dp/3.0_dp) .and. &
      input%d_min(1) == 0.5e-3_dp, "CGP_D_P0 gives the weight")
    if (allocated(error)) return
    ! 1e-15: MFiX's cube and cube root of 3 round twice
    call check(error, abs(input%d_p0(1) - 3.0e-3_dp) < 1.0e-15_dp*3.0e-3_dp, "CGP_D_P0 is the diameter used")
    if (allocated(error)) return
    ! without a 'CGP' phase the keywords do nothing (MFiX's CGDEM is false)
    call compute_text(lsd_deck("", "")//"cgp_stat_wt = 8.0 8.0"//nl, input, result, status)
    call check(error, status%stat == demstep_stat%ok .and. .not. input%coarse_grained .and. &
      all(input%d_p0 == input%d_p0_real) .and. all(input%cgp_stat_wt == 1.0_dp), "DEM only: not scaled")
  end subroutine test_cgp

  subroutine test_cgp_errors(error)
    type(error_type), allocatable, intent(out) :: error
    type(mfix_input_type) :: input
    type(mfix_result_type) :: result
    type(demstep_status_type) :: status
    ! 410: the 'DEM' phase needs a weight too
    call compute_text(cgp_deck("cgp_stat_wt(1) = 8.0"), input, result, status)
    call check(error, status%stat == demstep_stat%invalid_input .and. status%where == "CGP_STAT_WT" .and. &
      status%index == 2 .and. index(status%message, "CGP_STAT_WT(2): missing: with a 'CGP' phase") == 1, &
      "error 410: "//status%message)
    if (allocated(error)) return
    ! 400: both
    call compute_text(cgp_deck("cgp_stat_wt = 8.0 1.0"//nl//"cgp_d_p0(1) = 2.0e-3"), input, result, status)
    call check(error, status%where == "CGP_D_P0" .and. status%index == 1 .and. &
      index(status%message, "line 11: CGP_D_P0(1): not allowed together with CGP_STAT_WT(1)") == 1, &
      "error 400: "//status%message)
    if (allocated(error)) return
    ! 440: coarse-grained smaller than real
    call compute_text(cgp_deck("cgp_d_p0(1) = 0.5e-3"//nl//"cgp_stat_wt(2) = 1.0"), input, result, status)
    call check(error, status%where == "CGP_D_P0" .and. &
      index(status%message, "line 10: CGP_D_P0(1): must be >= D_P0(1) = 0.001") == 1, "error 440: "//status%message)
    if (allocated(error)) return
    ! 500: a weight below 1
    call compute_text(cgp_deck("cgp_stat_wt = 0.5 1.0"), input, result, status)
    call check(error, status%where == "CGP_STAT_WT" .and. status%index == 1 .and. &
      index(status%message, "line 10: CGP_STAT_WT(1): must be >= 1") == 1, "error 500: "//status%message)
  end subroutine test_cgp_errors

end module test_mfix
