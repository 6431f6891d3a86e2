!> MFiX's `@( )` deck arithmetic, evaluated as MFiX 21.3 evaluates it.
!>
!> The rules, read from MFiX 21.3's source (model/parse_line.f, PARSE_ARITH;
!> model/read_namelist.f, SET_KEYWORD; model/parse_mod.f):
!>
!> - `@(` opens an expression and the FIRST `)` after it closes it
!>   (parse_mod.f:15-16, parse_line.f:508): there are no parentheses inside,
!>   so `@((1/2))` fails (the `(` reaches MFiX's READ, parse_line.f:528).
!> - The operators are `*` and `/` only, applied left to right as they come,
!>   starting from 1 (parse_line.f:516-535): one precedence, left associative;
!>   `@(6/2*3)` is 9. An operator with no operand before it is MFiX's error
!>   "Invalid operator" (parse_line.f:521-523).
!> - An operand is a number read by a list-directed READ, or the word `PI`
!>   (4 atan(1), parse_line.f:497, :525-528); the line is upper-cased first
!>   (read_namelist.f:333), so `pi` works too. Blanks are skipped
!>   (parse_line.f:537). There are no functions and no `+`/`-` operators:
!>   MFiX's READ takes `1+2` as the number 1e+2, so demstep refuses a sign
!>   inside an operand other than in its exponent instead of reading 100.
!> - The value replaces the expression as the text `G22.15` (parse_line.f:562),
!>   which the namelist read then reads: the keyword gets the value rounded to
!>   15 significant digits (`@(1/3)` is 0.333333333333333, not 1/3).
!>
!> Everything here is pure; errors give the column of the fault.
module demstep_mfix_expression
  use demstep_kinds, only: dp
  use demstep_status, only: demstep_status_type, demstep_stat, set_status
  use demstep_text, only: lowercase
  use, intrinsic :: ieee_arithmetic, only: ieee_is_finite
  implicit none
  private

  public :: mfix_evaluate_expression

  !> MFiX's PI (parse_line.f:497).
  real(dp), parameter :: mfix_pi = 4.0_dp*atan(1.0_dp)

contains

  !> Evaluate the text between `@(` and its `)` as MFiX does (see the module's
  !> notes): `value` is the number the keyword receives, `digits` its text as
  !> MFiX writes it (15 significant digits). Status `invalid_input` with
  !> `column`, the 1-based position in `text` of the fault (`len(text) + 1`
  !> for the closing parenthesis), and the message saying what is wrong.
  pure subroutine mfix_evaluate_expression(text, value, digits, column, status)
    !> The expression without `@(` and `)`.
    character(len=*), intent(in) :: text
    !> Its value, rounded to 15 significant digits as MFiX's namelist read gets it.
    real(dp), intent(out) :: value
    !> The value's text as MFiX writes it into the line (`G22.15`, trimmed).
    character(len=:), allocatable, intent(out) :: digits
    !> Column of the fault in `text` (0 on success).
    integer, intent(out) :: column
    type(demstep_status_type), intent(out) :: status
    character(len=22) :: buffer
    character :: operation
    integer :: p, start, n, ios
    real(dp) :: x, acc
    value = 0.0_dp
    digits = ""
    column = 0
    n = len(text)
    acc = 1.0_dp
    operation = "*"
    p = 1
    do
      ! one operand, up to the next operator or the end
      start = p
      do while (p <= n)
        if (text(p:p) == "*" .or. text(p:p) == "/") exit
        p = p + 1
      end do
      if (verify(text(start:p - 1), " "//achar(9)) == 0) then
        ! MFiX's "Invalid operator" (parse_line.f:521-523)
        column = p
        if (p <= n) then
          call set_status(status, demstep_stat%invalid_input, "an operand is missing before '"//text(p:p) &
            //"' (MFiX's @( ) is numbers and PI joined by * and /)")
        else
          call set_status(status, demstep_stat%invalid_input, "an operand is missing before ')' " &
            //"(MFiX's @( ) is numbers and PI joined by * and /)")
        end if
        return
      end if
      call operand(text(start:p - 1), start, x, column, status)
      if (status%stat /= demstep_stat%ok) return
      if (operation == "*") then
        acc = acc*x
      else
        if (x == 0.0_dp) then
          column = start
          call set_status(status, demstep_stat%invalid_input, "division by zero")
          return
        end if
        acc = acc/x
      end if
      if (.not. ieee_is_finite(acc)) then
        column = start
        call set_status(status, demstep_stat%invalid_input, "the value leaves the double range")
        return
      end if
      if (p > n) exit
      operation = text(p:p)
      p = p + 1
    end do
    ! MFiX writes G22.15 into the line and the namelist read reads it back
    write(buffer, '(g22.15)') acc
    read(buffer, *, iostat=ios) value
    if (ios /= 0 .or. .not. ieee_is_finite(value)) then
      column = 1
      call set_status(status, demstep_stat%invalid_input, "the value leaves the double range")
      value = 0.0_dp
      return
    end if
    digits = trim(adjustl(buffer))
    status%stat = demstep_stat%ok
  end subroutine mfix_evaluate_expression

  !> One operand, not blank (blanks skipped): `PI` or a number
  !> `[sign]digits[.digits][(e|d)[sign]digits]`.
  pure subroutine operand(s, offset, x, column, status)
    character(len=*), intent(in) :: s
    !> Column of s(1:1) in the expression.
    integer, intent(in) :: offset
    real(dp), intent(out) :: x
    integer, intent(out) :: column
    type(demstep_status_type), intent(out) :: status
    character(len=len(s)) :: packed
    integer :: map(len(s)), i, k, ios, bad
    x = 0.0_dp
    column = 0
    ! MFiX skips blanks (parse_line.f:537); keep each character's column
    k = 0
    do i = 1, len(s)
      if (s(i:i) == " " .or. s(i:i) == achar(9)) cycle
      k = k + 1
      packed(k:k) = s(i:i)
      map(k) = offset + i - 1
    end do
    if (lowercase(packed(1:k)) == "pi") then
      x = mfix_pi
      status%stat = demstep_stat%ok
      return
    end if
    bad = number_fault(packed(1:k))
    if (bad > 0) then
      column = map(bad)
      if (packed(bad:bad) == "(" .or. packed(bad:bad) == ")") then
        call set_status(status, demstep_stat%invalid_input, "'"//packed(bad:bad)//"': MFiX's @( ) ends at " &
          //"the first ')' and takes no parentheses inside")
      else if ((packed(bad:bad) == "+" .or. packed(bad:bad) == "-") .and. bad > 1) then
        call set_status(status, demstep_stat%invalid_input, "'"//packed(1:k)//"': MFiX's @( ) has no '+' or " &
          //"'-' operator (its READ would take this as a number with exponent "//packed(bad:k)//")")
      else
        call set_status(status, demstep_stat%invalid_input, "'"//packed(1:k)//"' is neither a number nor PI " &
          //"(MFiX's @( ) has no functions or names but PI)")
      end if
      return
    end if
    read(packed(1:k), *, iostat=ios) x
    if (ios /= 0 .or. .not. ieee_is_finite(x)) then
      column = map(1)
      call set_status(status, demstep_stat%invalid_input, "'"//packed(1:k)//"' is not a finite number")
      x = 0.0_dp
      return
    end if
    status%stat = demstep_stat%ok
  end subroutine operand

  !> Position of the first character that breaks `[sign]digits[.digits][(e|d)[sign]digits]`
  !> (at least one mantissa digit; 0 when the text is such a number).
  pure integer function number_fault(s) result(bad)
    character(len=*), intent(in) :: s
    integer :: p, n, mantissa, exponent
    n = len(s)
    p = 1
    if (s(1:1) == "+" .or. s(1:1) == "-") p = 2
    mantissa = 0
    do while (p <= n)
      if (.not. is_digit(s(p:p))) exit
      p = p + 1
      mantissa = mantissa + 1
    end do
    if (p <= n) then
      if (s(p:p) == ".") then
        p = p + 1
        do while (p <= n)
          if (.not. is_digit(s(p:p))) exit
          p = p + 1
          mantissa = mantissa + 1
        end do
      end if
    end if
    if (mantissa == 0) then
      bad = min(p, n)
      return
    end if
    if (p <= n) then
      if (index("eEdD", s(p:p)) > 0) then
        p = p + 1
        if (p <= n) then
          if (s(p:p) == "+" .or. s(p:p) == "-") p = p + 1
        end if
        exponent = 0
        do while (p <= n)
          if (.not. is_digit(s(p:p))) exit
          p = p + 1
          exponent = exponent + 1
        end do
        if (exponent == 0) then
          bad = min(p, n)
          return
        end if
      end if
    end if
    bad = 0
    if (p <= n) bad = p
  end function number_fault

  pure logical function is_digit(c)
    character, intent(in) :: c
    is_digit = c >= "0" .and. c <= "9"
  end function is_digit

end module demstep_mfix_expression
