!> LIGGGHTS' equal-style variable formulas (`variable a equal 2*${b}+v_c`),
!> evaluated as LIGGGHTS 3.8 evaluates them, for the script reader.
!>
!> The rules, read from LIGGGHTS-PUBLIC's src/variable.cpp (Variable::evaluate
!> and math_function):
!> - operators and precedence (variable.cpp:132-140): `||` 1, `&&` 2, `==` `!=`
!>   3, `<` `<=` `>` `>=` 4, `+` `-` 5, `*` `/` `%` 6, `^` 7, unary `-` and `!` 8;
!>   an operator is applied while the stacked one has a precedence >= its own
!>   (:1567), so every binary operator is left-associative (`2^3^2` is 64) and
!>   the unary minus binds tighter than `^` (`-2^2` is 4);
!> - a number is digits and `.`, then an optional `e`/`E` exponent (:876-889);
!> - `/` and `%` by 0 and `^` with exponent 0 are errors (:1594-1605);
!>   comparisons and logic give 1 or 0 (:1608-1633);
!> - functions sqrt, exp, ln, log (base 10), abs, sin, cos, tan, asin, acos,
!>   atan, atan2, ceil, floor, round, with LIGGGHTS' domain errors
!>   (:2572-2710); `random` and `normal` draw random numbers, which demstep
!>   cannot reproduce, so they are refused; the constant PI (:3596-3607);
!> - `v_name` is the value of variable `name` (:1321), evaluated in turn;
!>   thermo keywords, computes `c_`, fixes `f_` and per-atom values need a
!>   running simulation and are refused, naming the word.
!> A `${name}` substitution of an equal-style variable writes its value with
!> 15 significant digits (`%.15g`, variable.cpp:600-603) and `$(formula)`
!> with 20 (`%.20g`, input.cpp:492): [[liggghts_number_text]].
module demstep_liggghts_formula
  use demstep_kinds, only: dp, i8
  use demstep_status, only: demstep_status_type, demstep_stat, set_status
  use, intrinsic :: ieee_arithmetic, only: ieee_is_finite
  implicit none
  private

  public :: liggghts_evaluate, liggghts_number_text, liggghts_find_variable

  !> A script variable as defined so far.
  type, public :: liggghts_variable_type
    !> Its name.
    character(len=:), allocatable :: name
    !> Its style: `equal`, `index`, `string`, `loop`, `atom` or another.
    character(len=:), allocatable :: style
    !> The formula (`equal`, `atom`) or the current value (others).
    character(len=:), allocatable :: text
    !> Line of its definition.
    integer :: line = 0
  end type liggghts_variable_type

  !> Deepest chain of `v_` references before a circular dependency is assumed.
  integer, parameter :: max_depth = 64
  !> Most `v_` references evaluated for one formula (a chain of variables each
  !> using the previous twice would otherwise take 2^64 evaluations).
  integer, parameter :: max_work = 1000000

  !> LIGGGHTS' PI (math_const.h: 3.14159265358979323846).
  real(dp), parameter :: liggghts_pi = 3.14159265358979323846_dp

contains

  !> The index of the variable named `name` in `vars(1:n)` (the last one so named), 0 for none.
  pure integer function liggghts_find_variable(vars, n, name) result(k)
    !> The variables defined so far.
    type(liggghts_variable_type), intent(in) :: vars(:)
    !> How many of them are defined.
    integer, intent(in) :: n
    !> The name looked for.
    character(len=*), intent(in) :: name
    integer :: i
    k = 0
    do i = n, 1, -1
      if (vars(i)%name == name) then
        k = i
        return
      end if
    end do
  end function liggghts_find_variable

  !> Evaluate an equal-style formula as LIGGGHTS does (see the module's notes).
  !> Status `invalid_input` saying what is wrong and where in the formula.
  pure recursive subroutine liggghts_evaluate(formula, vars, n_vars, value, status, depth, work)
    !> The formula.
    character(len=*), intent(in) :: formula
    !> The variables defined so far, for `v_name`.
    type(liggghts_variable_type), intent(in) :: vars(:)
    integer, intent(in) :: n_vars
    !> Its value.
    real(dp), intent(out) :: value
    type(demstep_status_type), intent(out) :: status
    !> Depth of `v_` references (absent: 0).
    integer, intent(in), optional :: depth
    !> `v_` references evaluated so far in this evaluation (absent: 0).
    integer, intent(inout), optional :: work
    integer :: p, d, w
    d = 0
    if (present(depth)) d = depth
    w = 0
    if (present(work)) w = work
    p = 1
    call expression(formula, p, 1, vars, n_vars, d, w, value, status)
    if (present(work)) work = w
    if (status%stat /= demstep_stat%ok) return
    call skip_blanks(formula, p)
    if (p <= len(formula)) then
      call fail(status, formula, p, "unexpected '"//formula(p:p)//"'")
      value = 0.0_dp
      return
    end if
    if (.not. ieee_is_finite(value)) then
      call fail(status, formula, 1, "the value leaves the double range")
      value = 0.0_dp
    end if
  end subroutine liggghts_evaluate

  !> A value as LIGGGHTS writes it in a substitution, C's `%.15g` (`digits`
  !> 15, `${name}`) or `%.20g` (`digits` 20, `$(formula)`): `digits`
  !> significant digits, fixed notation for decimal exponents in [-4, digits),
  !> else `d.ddde-05`, trailing zeros dropped.
  pure function liggghts_number_text(x, digits) result(text)
    !> The value (finite).
    real(dp), intent(in) :: x
    !> Significant digits (at most 30).
    integer, intent(in) :: digits
    character(len=:), allocatable :: text
    character(len=64) :: buffer, fmt
    character(len=:), allocatable :: mantissa, sign_text
    integer :: e, ios, p, x10
    if (x == 0.0_dp) then
      text = "0"
      return
    end if
    p = min(max(digits, 1), 30)
    write(fmt, '(a, i0, a, i0, a)') "(es", p + 10, ".", p - 1, "e4)"
    write(buffer, fmt) abs(x)
    buffer = adjustl(buffer)
    e = index(buffer, "E")
    read(buffer(e + 1:), *, iostat=ios) x10
    ! the p digits without the point
    mantissa = buffer(1:1)//buffer(3:e - 1)
    sign_text = merge("-", " ", x < 0.0_dp)
    if (x10 >= -4 .and. x10 < p) then
      if (x10 >= 0) then
        text = mantissa(1:x10 + 1)//"."//mantissa(x10 + 2:)
      else
        text = "0."//repeat("0", -x10 - 1)//mantissa
      end if
      text = drop_zeros(text)
    else
      text = drop_zeros(mantissa(1:1)//"."//mantissa(2:))
      ! C: at least two exponent digits
      if (abs(x10) < 10) then
        write(buffer, '(i2.2)') abs(x10)
      else
        write(buffer, '(i0)') abs(x10)
      end if
      text = text//"e"//merge("-", "+", x10 < 0)//trim(buffer)
    end if
    text = trim(sign_text)//text
  end function liggghts_number_text

  !> `1.2300` -> `1.23`, `5.000` -> `5`, `120` unchanged (no point).
  pure function drop_zeros(s) result(t)
    character(len=*), intent(in) :: s
    character(len=:), allocatable :: t
    integer :: k
    t = s
    if (index(t, ".") == 0) return
    k = len(t)
    do while (t(k:k) == "0")
      k = k - 1
    end do
    if (t(k:k) == ".") k = k - 1
    t = t(1:k)
  end function drop_zeros

  !> Binary operators of precedence >= `min_prec`, left to right.
  pure recursive subroutine expression(s, p, min_prec, vars, n_vars, depth, work, value, status)
    character(len=*), intent(in) :: s
    integer, intent(inout) :: p
    integer, intent(in) :: min_prec, n_vars, depth
    integer, intent(inout) :: work
    type(liggghts_variable_type), intent(in) :: vars(:)
    real(dp), intent(out) :: value
    type(demstep_status_type), intent(out) :: status
    character(len=2) :: op
    integer :: width, prec, at
    real(dp) :: rhs
    call unary(s, p, vars, n_vars, depth, work, value, status)
    if (status%stat /= demstep_stat%ok) return
    do
      call skip_blanks(s, p)
      call peek_operator(s, p, op, width, prec)
      if (prec == 0 .or. prec < min_prec) exit
      at = p
      p = p + width
      ! left-associative: the right operand takes only tighter operators
      call expression(s, p, prec + 1, vars, n_vars, depth, work, rhs, status)
      if (status%stat /= demstep_stat%ok) return
      call apply(trim(op), value, rhs, s, at, status)
      if (status%stat /= demstep_stat%ok) return
    end do
  end subroutine expression

  !> Unary `-` and `!` (precedence 8, above `^`), then a primary.
  pure recursive subroutine unary(s, p, vars, n_vars, depth, work, value, status)
    character(len=*), intent(in) :: s
    integer, intent(inout) :: p
    integer, intent(in) :: n_vars, depth
    integer, intent(inout) :: work
    type(liggghts_variable_type), intent(in) :: vars(:)
    real(dp), intent(out) :: value
    type(demstep_status_type), intent(out) :: status
    call skip_blanks(s, p)
    if (p > len(s)) then
      call fail(status, s, p, "a value is missing at the end")
      value = 0.0_dp
      return
    end if
    if (s(p:p) == "-") then
      p = p + 1
      call unary(s, p, vars, n_vars, depth, work, value, status)
      value = -value
    else if (s(p:p) == "!" .and. s(min(p + 1, len(s)):min(p + 1, len(s))) /= "=") then
      p = p + 1
      call unary(s, p, vars, n_vars, depth, work, value, status)
      value = merge(1.0_dp, 0.0_dp, value == 0.0_dp)
    else
      call primary(s, p, vars, n_vars, depth, work, value, status)
    end if
  end subroutine unary

  !> `(formula)`, a number, PI, `v_name` or `function(args)`.
  pure recursive subroutine primary(s, p, vars, n_vars, depth, work, value, status)
    character(len=*), intent(in) :: s
    integer, intent(inout) :: p
    integer, intent(in) :: n_vars, depth
    integer, intent(inout) :: work
    type(liggghts_variable_type), intent(in) :: vars(:)
    real(dp), intent(out) :: value
    type(demstep_status_type), intent(out) :: status
    integer :: start, k, ios, n_args
    character(len=:), allocatable :: word
    real(dp) :: args(3)
    value = 0.0_dp
    start = p
    if (s(p:p) == "(") then
      p = p + 1
      call expression(s, p, 1, vars, n_vars, depth, work, value, status)
      if (status%stat /= demstep_stat%ok) return
      call skip_blanks(s, p)
      if (p > len(s)) then
        call fail(status, s, start, "'(' without ')'")
      else if (s(p:p) /= ")") then
        call fail(status, s, p, "expected ')', found '"//s(p:p)//"'")
      else
        p = p + 1
      end if
    else if (is_digit(s(p:p)) .or. s(p:p) == ".") then
      do while (p <= len(s))
        if (.not. (is_digit(s(p:p)) .or. s(p:p) == ".")) exit
        p = p + 1
      end do
      if (p <= len(s)) then
        if (s(p:p) == "e" .or. s(p:p) == "E") then
          p = p + 1
          if (p <= len(s)) then
            if (s(p:p) == "+" .or. s(p:p) == "-") p = p + 1
          end if
          do while (p <= len(s))
            if (.not. is_digit(s(p:p))) exit
            p = p + 1
          end do
        end if
      end if
      ios = 1
      if (verify(s(start:p - 1), ".") > 0 .and. count_dots(s(start:p - 1)) <= 1) &
        read(s(start:p - 1), *, iostat=ios) value
      if (ios /= 0) then
        call fail(status, s, start, "'"//s(start:p - 1)//"' is not a number")
        value = 0.0_dp
        return
      end if
      status%stat = demstep_stat%ok
    else if (is_letter(s(p:p))) then
      do while (p <= len(s))
        if (.not. (is_letter(s(p:p)) .or. is_digit(s(p:p)) .or. s(p:p) == "_")) exit
        p = p + 1
      end do
      word = s(start:p - 1)
      call skip_blanks(s, p)
      if (word == "PI") then
        value = liggghts_pi
        status%stat = demstep_stat%ok
      else if (index(word, "v_") == 1) then
        k = liggghts_find_variable(vars, n_vars, word(3:))
        if (k == 0) then
          call fail(status, s, start, "'"//word//"': no variable '"//word(3:)//"' is defined before this line")
        else if (depth >= max_depth) then
          call fail(status, s, start, "'"//word//"': circular dependency of variables")
        else if (work >= max_work) then
          call fail(status, s, start, "'"//word//"': more than a million variable references in one formula")
        else if (vars(k)%style == "equal") then
          work = work + 1
          call liggghts_evaluate(vars(k)%text, vars, n_vars, value, status, depth + 1, work)
          if (status%stat /= demstep_stat%ok) then
            call fail(status, s, start, "'"//word//"': "//status%message)
            value = 0.0_dp
          end if
        else if (vars(k)%style == "atom") then
          call fail(status, s, start, "'"//word//"' is an atom-style variable (per particle)")
        else
          ios = 1
          if (len_trim(vars(k)%text) > 0 .and. verify(trim(vars(k)%text), "0123456789.+-eE") == 0) &
            read(vars(k)%text, *, iostat=ios) value
          if (ios /= 0) then
            call fail(status, s, start, "'"//word//"' holds '"//vars(k)%text//"', not a number")
            value = 0.0_dp
          else
            status%stat = demstep_stat%ok
          end if
        end if
      else if (p <= len(s) .and. s(min(p, len(s)):min(p, len(s))) == "(") then
        call arguments(s, p, vars, n_vars, depth, work, args, n_args, status)
        if (status%stat /= demstep_stat%ok) return
        call math_function(word, args, n_args, value, s, start, status)
      else if (index(word, "c_") == 1 .or. index(word, "f_") == 1) then
        call fail(status, s, start, "'"//word//"' needs a running simulation (a compute or fix value)")
      else
        call fail(status, s, start, "'"//word//"' is a thermo keyword or per-atom value, which needs a " &
          //"running simulation")
      end if
    else
      call fail(status, s, p, "unexpected '"//s(p:p)//"'")
    end if
  end subroutine primary

  !> `(a, b, c)`: up to three comma-separated formulas.
  pure recursive subroutine arguments(s, p, vars, n_vars, depth, work, args, n_args, status)
    character(len=*), intent(in) :: s
    integer, intent(inout) :: p
    integer, intent(in) :: n_vars, depth
    integer, intent(inout) :: work
    type(liggghts_variable_type), intent(in) :: vars(:)
    real(dp), intent(out) :: args(3)
    integer, intent(out) :: n_args
    type(demstep_status_type), intent(out) :: status
    integer :: start
    args = 0.0_dp
    n_args = 0
    start = p
    p = p + 1
    do
      if (n_args == size(args)) then
        call fail(status, s, p, "more than three arguments")
        return
      end if
      n_args = n_args + 1
      call expression(s, p, 1, vars, n_vars, depth, work, args(n_args), status)
      if (status%stat /= demstep_stat%ok) return
      call skip_blanks(s, p)
      if (p > len(s)) then
        call fail(status, s, start, "'(' without ')'")
        return
      end if
      if (s(p:p) == ")") exit
      if (s(p:p) /= ",") then
        call fail(status, s, p, "expected ',' or ')', found '"//s(p:p)//"'")
        return
      end if
      p = p + 1
    end do
    p = p + 1
    status%stat = demstep_stat%ok
  end subroutine arguments

  !> LIGGGHTS' math functions (variable.cpp:2572-2710).
  pure subroutine math_function(word, args, n_args, value, s, at, status)
    character(len=*), intent(in) :: word, s
    real(dp), intent(in) :: args(3)
    integer, intent(in) :: n_args, at
    real(dp), intent(out) :: value
    type(demstep_status_type), intent(out) :: status
    integer :: wanted
    value = 0.0_dp
    select case (word)
    case ("sqrt", "exp", "ln", "log", "abs", "sin", "cos", "tan", "asin", "acos", "atan", "ceil", "floor", "round")
      wanted = 1
    case ("atan2")
      wanted = 2
    case ("random", "normal")
      call fail(status, s, at, "'"//word//"' draws random numbers, which demstep cannot reproduce")
      return
    case default
      call fail(status, s, at, "'"//word//"' is not a math function demstep evaluates (LIGGGHTS' " &
        //"time-dependent ones need a run)")
      return
    end select
    if (n_args /= wanted) then
      call fail(status, s, at, "'"//word//"' takes "//merge("one argument ", "two arguments", wanted == 1))
      return
    end if
    associate (x => args(1))
      if ((word == "ceil" .or. word == "floor" .or. word == "round") .and. abs(x) >= 1.0e18_dp) then
        ! already an integer in double precision
        value = x
        status%stat = demstep_stat%ok
        return
      end if
      select case (word)
      case ("sqrt")
        if (x < 0.0_dp) then
          call fail(status, s, at, "sqrt of a negative value")
          return
        end if
        value = sqrt(x)
      case ("exp")
        value = exp(x)
      case ("ln", "log")
        if (x <= 0.0_dp) then
          call fail(status, s, at, word//" of a value <= 0")
          return
        end if
        value = merge(log(x), log10(x), word == "ln")
      case ("abs")
        value = abs(x)
      case ("sin")
        value = sin(x)
      case ("cos")
        value = cos(x)
      case ("tan")
        value = tan(x)
      case ("asin", "acos")
        if (x < -1.0_dp .or. x > 1.0_dp) then
          call fail(status, s, at, word//" of a value outside [-1, 1]")
          return
        end if
        value = merge(asin(x), acos(x), word == "asin")
      case ("atan")
        value = atan(x)
      case ("atan2")
        value = atan2(x, args(2))
      case ("ceil")
        value = real(ceiling(x, i8), dp)
      case ("floor")
        value = real(floor(x, i8), dp)
      case ("round")
        ! MYROUND (variable.cpp:87): halves go up, round(-2.5) is -2
        if (x - real(floor(x, i8), dp) >= 0.5_dp) then
          value = real(ceiling(x, i8), dp)
        else
          value = real(floor(x, i8), dp)
        end if
      end select
    end associate
    status%stat = demstep_stat%ok
  end subroutine math_function

  !> One binary operation as LIGGGHTS applies it (variable.cpp:1583-1633).
  pure subroutine apply(op, a, b, s, at, status)
    character(len=*), intent(in) :: op, s
    real(dp), intent(inout) :: a
    real(dp), intent(in) :: b
    integer, intent(in) :: at
    type(demstep_status_type), intent(out) :: status
    status%stat = demstep_stat%ok
    select case (op)
    case ("+")
      a = a + b
    case ("-")
      a = a - b
    case ("*")
      a = a*b
    case ("/")
      if (b == 0.0_dp) then
        call fail(status, s, at, "divide by 0")
        return
      end if
      a = a/b
    case ("%")
      if (b == 0.0_dp) then
        call fail(status, s, at, "modulo 0")
        return
      end if
      a = mod(a, b)
    case ("^")
      if (b == 0.0_dp) then
        call fail(status, s, at, "power by 0 (LIGGGHTS refuses an exponent of 0)")
        return
      end if
      a = a**b
    case ("==")
      a = merge(1.0_dp, 0.0_dp, a == b)
    case ("!=")
      a = merge(1.0_dp, 0.0_dp, a /= b)
    case ("<")
      a = merge(1.0_dp, 0.0_dp, a < b)
    case ("<=")
      a = merge(1.0_dp, 0.0_dp, a <= b)
    case (">")
      a = merge(1.0_dp, 0.0_dp, a > b)
    case (">=")
      a = merge(1.0_dp, 0.0_dp, a >= b)
    case ("&&")
      a = merge(1.0_dp, 0.0_dp, a /= 0.0_dp .and. b /= 0.0_dp)
    case ("||")
      a = merge(1.0_dp, 0.0_dp, a /= 0.0_dp .or. b /= 0.0_dp)
    end select
  end subroutine apply

  !> The binary operator at p, its width and precedence (0: none).
  pure subroutine peek_operator(s, p, op, width, prec)
    character(len=*), intent(in) :: s
    integer, intent(in) :: p
    character(len=2), intent(out) :: op
    integer, intent(out) :: width, prec
    character(len=2) :: two
    op = " "
    width = 0
    prec = 0
    if (p > len(s)) return
    two = s(p:min(p + 1, len(s)))
    select case (two)
    case ("||")
      prec = 1
    case ("&&")
      prec = 2
    case ("==", "!=")
      prec = 3
    case ("<=", ">=")
      prec = 4
    end select
    if (prec > 0) then
      op = two
      width = 2
      return
    end if
    select case (s(p:p))
    case ("<", ">")
      prec = 4
    case ("+", "-")
      prec = 5
    case ("*", "/", "%")
      prec = 6
    case ("^")
      prec = 7
    end select
    if (prec > 0) then
      op = s(p:p)
      width = 1
    end if
  end subroutine peek_operator

  !> Status `invalid_input`: `'formula' at column c: what`.
  pure subroutine fail(status, s, at, what)
    type(demstep_status_type), intent(out) :: status
    character(len=*), intent(in) :: s, what
    integer, intent(in) :: at
    character(len=12) :: buffer
    write(buffer, '(i0)') min(max(at, 1), len(s) + 1)
    call set_status(status, demstep_stat%invalid_input, "'"//s//"' at column "//trim(buffer)//": "//what)
  end subroutine fail

  pure subroutine skip_blanks(s, p)
    character(len=*), intent(in) :: s
    integer, intent(inout) :: p
    do while (p <= len(s))
      if (s(p:p) /= " " .and. s(p:p) /= achar(9)) exit
      p = p + 1
    end do
  end subroutine skip_blanks

  pure integer function count_dots(s)
    character(len=*), intent(in) :: s
    integer :: i
    count_dots = 0
    do i = 1, len(s)
      if (s(i:i) == ".") count_dots = count_dots + 1
    end do
  end function count_dots

  pure logical function is_digit(c)
    character, intent(in) :: c
    is_digit = c >= "0" .and. c <= "9"
  end function is_digit

  pure logical function is_letter(c)
    character, intent(in) :: c
    is_letter = (c >= "a" .and. c <= "z") .or. (c >= "A" .and. c <= "Z")
  end function is_letter

end module demstep_liggghts_formula
