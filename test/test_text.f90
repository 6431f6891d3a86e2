!> Tests of demstep_text and demstep_decimal: numbers as text (the formats the
!> messages and reports print), case folding, and numbers read from text bit for
!> bit as the Fortran runtime's list-directed read gives them.
module test_text
  use testdrive, only: new_unittest, unittest_type, error_type, check, test_failed
  use demstep_kinds, only: dp, i8
  use demstep_text, only: real_text, real_column, lowercase, uppercase, is_blank, is_name_char
  use demstep_decimal, only: real_of
  use, intrinsic :: ieee_arithmetic, only: ieee_value, ieee_quiet_nan, ieee_positive_inf, &
    ieee_negative_inf
  use, intrinsic :: iso_fortran_env, only: real128
  implicit none
  private
  public :: collect_text

contains

  subroutine collect_text(testsuite)
    type(unittest_type), allocatable, intent(out) :: testsuite(:)
    testsuite = [ &
      new_unittest("real_text: 4 digits for messages, 10 for reports", test_real_text), &
      new_unittest("real_column equals real_text element by element", test_real_column), &
      new_unittest("case folding and character classes", test_case), &
      new_unittest("real_of: fields of every shape, as read(*,*)", test_real_of_shapes), &
      new_unittest("real_of: random doubles printed 1 to 20 digits, as read(*,*)", test_real_of_random), &
      new_unittest("real_of: random digit strings, as read(*,*)", test_real_of_digits), &
      new_unittest("real_of: near halfway between doubles, as read(*,*)", test_real_of_halfway) &
      ]
  end subroutine collect_text

  subroutine test_real_text(error)
    type(error_type), allocatable, intent(out) :: error
    ! the 4-digit texts messages have always printed
    call expect(error, real_text(0.25_dp), "0.25")
    call expect(error, real_text(1.0_dp), "1")
    call expect(error, real_text(-1.5e-8_dp), "-1.5e-8")
    call expect(error, real_text(12345.6_dp), "12346")
    call expect(error, real_text(123456.0_dp), "1.235e5")
    call expect(error, real_text(9.9996_dp), "10")
    call expect(error, real_text(0.00099996_dp), "0.001")
    call expect(error, real_text(-0.00123456_dp), "-0.001235")
    call expect(error, real_text(2.0e12_dp), "2e12")
    call expect(error, real_text(0.0_dp), "0")
    call expect(error, real_text(-0.0_dp), "0")
    call expect(error, real_text(ieee_value(1.0_dp, ieee_quiet_nan)), "NaN")
    call expect(error, real_text(ieee_value(1.0_dp, ieee_positive_inf)), "+Inf")
    call expect(error, real_text(ieee_value(1.0_dp, ieee_negative_inf)), "-Inf")
    call expect(error, real_text(tiny(1.0_dp)*2.0_dp**(-52)), "4.941e-324")
    ! the app's 10 digits
    call expect(error, real_text(1234567.5_dp, 10), "1234567.5")
    call expect(error, real_text(12345678.0_dp, 10), "1.2345678e7")
    call expect(error, real_text(5.692099788e-4_dp, 10), "5.692099788e-4")
    call expect(error, real_text(-1.7976931348623157e308_dp, 10), "-1.797693135e308")
    call expect(error, real_text(0.1_dp, 17), "0.10000000000000001")
    call expect(error, real_text(3.14159265358979_dp, 15), "3.14159265358979")
  end subroutine test_real_text

  subroutine expect(error, got, want)
    type(error_type), allocatable, intent(inout) :: error
    character(len=*), intent(in) :: got, want
    if (allocated(error)) return
    if (got /= want) call test_failed(error, "got '"//got//"', want '"//want//"'")
  end subroutine expect

  subroutine test_real_column(error)
    type(error_type), allocatable, intent(out) :: error
    real(dp) :: x(9)
    character(len=24), allocatable :: cells(:)
    integer :: i, d
    x = [0.25_dp, -1.0e-300_dp, 12345.6_dp, 0.0_dp, ieee_value(1.0_dp, ieee_quiet_nan), &
      ieee_value(1.0_dp, ieee_negative_inf), 7.0e22_dp, -3.3333333333333335_dp, tiny(1.0_dp)*2.0_dp**(-52)]
    do d = 1, 17
      cells = real_column(x, d)
      do i = 1, size(x)
        call expect(error, trim(cells(i)), real_text(x(i), d))
      end do
    end do
  end subroutine test_real_column

  subroutine test_case(error)
    type(error_type), allocatable, intent(out) :: error
    call expect(error, lowercase("Young_Modulus(2) = 1E9"), "young_modulus(2) = 1e9")
    call expect(error, uppercase("des_en_input(1)"), "DES_EN_INPUT(1)")
    call check(error, all(is_blank([" ", achar(9), achar(10), achar(13)])) .and. .not. is_blank("a"), "blanks")
    if (allocated(error)) return
    call check(error, is_name_char("_") .and. is_name_char("Z") .and. is_name_char("0") .and. &
      .not. is_name_char("%"), "name characters")
  end subroutine test_case

  !> real_of and the runtime agree on one field: the same refusal, or the
  !> same bits.
  subroutine agree(error, field)
    type(error_type), allocatable, intent(inout) :: error
    character(len=*), intent(in) :: field
    real(dp) :: mine, runtime
    logical :: ok
    integer :: ios
    if (allocated(error)) return
    call real_of(field, mine, ok)
    runtime = 0.0_dp
    ios = 1
    if (len(field) > 0) then
      if (verify(field, "0123456789+-.eEdD") == 0) read(field, *, iostat=ios) runtime
    end if
    if (ok .neqv. ios == 0) then
      call test_failed(error, "'"//field//"': real_of says "//merge("a number    ", "not a number", ok) &
        //", read(*,*) the opposite")
    else if (ok .and. transfer(mine, 0_i8) /= transfer(runtime, 0_i8)) then
      call test_failed(error, "'"//field//"': real_of gives "//real_text(mine, 17)//", read(*,*) "// &
        real_text(runtime, 17))
    end if
  end subroutine agree

  subroutine test_real_of_shapes(error)
    type(error_type), allocatable, intent(out) :: error
    character(len=32), parameter :: fields(*) = [character(len=32) :: "0", "-0", "+0", "-0.0e5", "1", &
      "-1", "+7", "1.", ".5", "-.5e-3", "1.5d3", "1.5D-3", "2E+2", "1e0005", "1e00005", "1e", "1e+", "e5", &
      ".", "+", "-", "+-1", "1.2.3", "1+5", "1-5", "1.5e3.2", "1e999", "-1e999", "1e-999", "4.9e-324", &
      "2.4e-324", "2.5e-324", "1e-320", "2.2250738585072014e-308", "2.2250738585072011e-308", &
      "1.7976931348623157e308", "1.7976931348623159e308", "9007199254740993", "9007199254740992", &
      "9007199254740994", "123456789012345678", "1234567890123456789", "12345678901234567890123", &
      "0.000000000000000000000000000001", "00000000000000000000001.5", "1e22", "1e23", "8.9e15", &
      "3.0e-279", "3.0e-281", "9.99999999999999999e279", "1e280", "1x", "nan", "inf", "1,5", " 1", "1 ", &
      "0x10", "1e-0", "1E-00", "5e-324", "1e308", "1e309", "0.1", "0.30000000000000004"]
    integer :: i
    do i = 1, size(fields)
      call agree(error, trim(fields(i)))
    end do
    call agree(error, "")
  end subroutine test_real_of_shapes

  !> Doubles of every magnitude (random bit patterns: subnormals included),
  !> printed with 1 to 20 significant digits in es, e and d forms and fixed
  !> notation.
  subroutine test_real_of_random(error)
    type(error_type), allocatable, intent(out) :: error
    integer, parameter :: n = 20000
    integer :: i, d, k
    integer(i8) :: bits
    real(dp) :: u(3), x
    character(len=64) :: buf
    character(len=16) :: form
    call seed(271)
    do i = 1, n
      call random_number(u)
      ! a random exponent field (0: subnormal; 2047 skipped) and mantissa
      bits = ior(ishft(int(u(1)*2047.0_dp, i8), 52), int(u(2)*4503599627370496.0_dp, i8))
      x = transfer(bits, 1.0_dp)
      if (u(3) < 0.5_dp) x = -x
      ! and a random value of ordinary size
      if (mod(i, 2) == 0) x = (u(2) - 0.5_dp)*10.0_dp**(int(u(1)*40.0_dp) - 20)
      d = 1 + mod(i, 20)
      k = mod(i/20, 4)
      select case (k)
      case (0)
        write(form, '(a, i0, a)') "(es40.", d - 1, "e3)"
      case (1)
        write(form, '(a, i0, a)') "(e40.", d, "e3)"
      case (2)
        write(form, '(a, i0, a)') "(d40.", d, ")"
      case default
        write(form, '(a, i0, a)') "(f60.", d, ")"
      end select
      write(buf, form) x
      if (index(buf, "*") > 0) cycle
      call agree(error, trim(adjustl(buf)))
      if (allocated(error)) return
    end do
  end subroutine test_real_of_random

  !> Random strings of 1 to 22 digits with a decimal point anywhere and
  !> exponents from -340 to 340: every path and every boundary between them.
  subroutine test_real_of_digits(error)
    type(error_type), allocatable, intent(out) :: error
    integer, parameter :: n = 40000
    integer :: i, nd, j, point, e
    real(dp) :: u(4)
    character(len=64) :: buf
    character(len=24) :: digits
    call seed(314)
    do i = 1, n
      call random_number(u)
      nd = 1 + int(u(1)*22.0_dp)
      do j = 1, nd
        call random_number(u(4))
        digits(j:j) = achar(iachar("0") + int(u(4)*10.0_dp))
      end do
      point = int(u(2)*real(nd + 1, dp))
      e = int(u(3)*681.0_dp) - 340
      if (mod(i, 3) == 0) e = int(u(3)*61.0_dp) - 30
      if (point == 0) then
        buf = "."//digits(:nd)
      else
        buf = digits(:point)//"."//digits(point+1:nd)
      end if
      if (mod(i, 5) /= 0) write(buf, '(a, "e", i0)') trim(buf), e
      if (mod(i, 7) == 0) buf = "-"//buf
      call agree(error, trim(buf))
      if (allocated(error)) return
    end do
  end subroutine test_real_of_digits

  !> Fields within 1e-18 (relative) of the midpoint between two neighbouring
  !> doubles, 16 to 19 digits: the double-double path must round them right or
  !> leave them to the runtime.
  subroutine test_real_of_halfway(error)
    type(error_type), allocatable, intent(out) :: error
    integer, parameter :: n = 20000
    integer :: i, d
    real(dp) :: u(2), x
    real(real128) :: mid
    character(len=64) :: buf
    character(len=16) :: form
    call seed(161)
    do i = 1, n
      call random_number(u)
      x = (0.5_dp + u(1))*10.0_dp**(int(u(2)*520.0_dp) - 260)
      mid = (real(x, real128) + real(nearest(x, 1.0_dp), real128))/2.0_real128
      d = 16 + mod(i, 4)
      write(form, '(a, i0, a)') "(es40.", d - 1, "e3)"
      write(buf, form) mid
      call agree(error, trim(adjustl(buf)))
      if (allocated(error)) return
    end do
  end subroutine test_real_of_halfway

  !> A fixed sequence of the compiler's generator.
  subroutine seed(k)
    integer, intent(in) :: k
    integer :: n, i
    call random_seed(size=n)
    call random_seed(put=[(k + 37*i, i = 1, n)])
  end subroutine seed

end module test_text
