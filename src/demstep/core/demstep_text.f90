!> Files read whole, numbers as text for messages, integers read from
!> text, case folding and the character classes the readers share.
module demstep_text
  use, intrinsic :: iso_fortran_env, only: int32, int64, real64
  use demstep_status, only: demstep_status_type, demstep_stat, set_status
  implicit none
  private

  public :: int_text, real_text, real_column, integer_of, printable, read_text_file, &
    lowercase, uppercase, is_blank, is_letter, is_name_char, comment_start, check_lower

  !> An integer as text, without blanks.
  interface int_text
    module procedure :: int32_text, int64_text
  end interface int_text

  !> Significant digits of [[real_text]] when none are asked for.
  integer, parameter :: default_digits = 4
  !> Width of the cells of [[real_column]]: the longest text of 17 digits
  !> (`-1.2345678901234567e-308`).
  integer, parameter :: cell_width = 24
  !> Significant digits of the numbers in [[check_lower]]'s messages.
  integer, parameter :: check_digits = 10

contains

  !> Status `invalid_input` at `where` unless `x` is finite and above `lower`
  !> (default 0; at or above with `inclusive`); `element` names the array
  !> element checked. Does nothing after an earlier failure (checks chain).
  pure subroutine check_lower(x, where, status, lower, inclusive, element)
    !> The value.
    real(real64), intent(in) :: x
    !> The argument or field it came from.
    character(len=*), intent(in) :: where
    type(demstep_status_type), intent(inout) :: status
    real(real64), intent(in), optional :: lower
    logical, intent(in), optional :: inclusive
    integer, intent(in), optional :: element
    real(real64) :: bound
    logical :: closed
    character(len=:), allocatable :: what
    if (status%stat /= demstep_stat%ok) return
    bound = 0.0_real64
    if (present(lower)) bound = lower
    closed = .false.
    if (present(inclusive)) closed = inclusive
    if (x == x .and. abs(x) <= huge(x)) then
      if (closed .and. .not. x < bound) return
      if (.not. closed .and. x > bound) return
    end if
    ! the message is built only for a value that fails (this runs per array element)
    what = ""
    if (present(element)) what = "element "//int_text(element)//" is "//real_text(x, check_digits)//"; "
    if (.not. (x == x .and. abs(x) <= huge(x))) then
      what = what//"must be a finite number, not "//real_text(x, check_digits)
    else if (closed) then
      what = what//"must be >= "//real_text(bound, check_digits)//", got "//real_text(x, check_digits)
    else
      what = what//"must be > "//real_text(bound, check_digits)//", got "//real_text(x, check_digits)
    end if
    call set_status(status, demstep_stat%invalid_input, what, where=where)
  end subroutine check_lower

  pure function int32_text(i) result(text)
    integer(int32), intent(in) :: i
    character(len=:), allocatable :: text
    text = int64_text(int(i, int64))
  end function int32_text

  pure function int64_text(i) result(text)
    integer(int64), intent(in) :: i
    character(len=:), allocatable :: text
    character(len=24) :: buf
    write(buf, '(i0)') i
    text = trim(buf)
  end function int64_text

  !> A real as text: `digits` significant digits (default 4, at most 17),
  !> trailing zeros dropped; fixed notation for magnitudes from 1e-3 below
  !> 10^(min(digits, 6) + 1) (`0.25`, `12346` with 4 digits, `1234567.5` with
  !> 10), else `1.5e-8`; `NaN`, `+Inf`, `-Inf`, and `0` for either zero.
  pure function real_text(x, digits) result(text)
    !> The number.
    real(real64), intent(in) :: x
    !> Significant digits (1 to 17; default 4).
    integer, intent(in), optional :: digits
    character(len=:), allocatable :: text
    character(len=cell_width) :: cell
    integer :: d
    d = default_digits
    if (present(digits)) d = max(1, min(17, digits))
    cell = ""
    if (x == x .and. abs(x) <= huge(x) .and. x /= 0.0_real64) write(cell, es_format(d)) x
    text = text_of_es(x, cell, d)
  end function real_text

  !> [[real_text]] of each element, left-adjusted in cells of 24 characters,
  !> from one formatted write for the whole array (in long tables the cost per
  !> write statement would dominate).
  pure function real_column(x, digits) result(cells)
    !> The numbers.
    real(real64), intent(in) :: x(:)
    !> Significant digits (1 to 17; default 4).
    integer, intent(in), optional :: digits
    character(len=cell_width), allocatable :: cells(:)
    character(len=cell_width), allocatable :: es(:)
    integer :: i, d
    d = default_digits
    if (present(digits)) d = max(1, min(17, digits))
    allocate(es(size(x)), cells(size(x)))
    ! Inf and NaN print as text, which text_of_es does not read
    if (size(x) > 0) write(es, es_format(d)) x
    do i = 1, size(x)
      cells(i) = text_of_es(x(i), es(i), d)
    end do
  end function real_column

  !> The edit `(esW.De3)` giving `d` significant digits.
  pure function es_format(d) result(form)
    integer, intent(in) :: d
    character(len=16) :: form
    write(form, '(a, i0, a, i0, a)') "(es", cell_width, ".", d - 1, "e3)"
  end function es_format

  !> The text of [[real_text]] from x and its `es_format(d)` edit `cell` (used
  !> when x is finite and nonzero). The es edit gives the rounded significant
  !> digits and the exponent of the rounded value; the fixed notation places
  !> the decimal point in those same digits (rounding at d digits lands on the
  !> same decimal place there), or, with more integer digits than d, shows the
  !> integer part whole.
  pure function text_of_es(x, cell, d) result(text)
    real(real64), intent(in) :: x
    character(len=*), intent(in) :: cell
    integer, intent(in) :: d
    character(len=:), allocatable :: text
    character(len=17) :: digits
    character(len=cell_width) :: buf
    character :: sign
    integer :: e, k, m, i
    if (x /= x) then
      text = "NaN"
      return
    else if (abs(x) > huge(x)) then
      text = merge("+Inf", "-Inf", x > 0.0_real64)
      return
    else if (x == 0.0_real64) then
      text = "0"
      return
    end if
    k = index(cell, "E")
    e = 0
    do i = k + 2, len_trim(cell)
      e = 10*e + (iachar(cell(i:i)) - iachar("0"))
    end do
    if (cell(k+1:k+1) == "-") e = -e
    if (e >= -3 .and. e <= min(d, 6)) then
      m = verify(cell, " ")
      sign = merge("-", " ", cell(m:m) == "-")
      if (sign == "-") m = m + 1
      digits = cell(m:m)//cell(m+2:k-1)
      if (e >= d) then
        write(buf, '(f0.0)') x
        text = trim(adjustl(buf))
      else if (e >= 0) then
        text = trim(sign)//digits(1:e+1)//"."//digits(e+2:d)
      else
        text = trim(sign)//"0."//repeat("0", -e-1)//digits(1:d)
      end if
      text = without_trailing_zeros(text)
    else
      text = without_trailing_zeros(trim(adjustl(cell(1:k-1))))//"e"//int64_text(int(e, int64))
    end if
  end function text_of_es

  !> A decimal number without the zeros that end its fraction, and without a
  !> point that ends it (`1.500` is `1.5`, `2.` is `2`).
  pure function without_trailing_zeros(number) result(text)
    character(len=*), intent(in) :: number
    character(len=:), allocatable :: text
    integer :: last
    text = number
    if (index(text, ".") == 0) return
    last = verify(text, "0", back=.true.)
    if (text(last:last) == ".") last = last - 1
    text = text(1:last)
  end function without_trailing_zeros

  !> A text as it may be quoted in a one-line message: a tab becomes a blank,
  !> every other byte outside printable ASCII (a newline, a carriage return, a
  !> NUL, a byte of a binary file) becomes `?`.
  pure function printable(text) result(out)
    !> The text to quote.
    character(len=*), intent(in) :: text
    character(len=len(text)) :: out
    integer :: i, c
    out = text
    do i = 1, len(text)
      c = iachar(text(i:i))
      if (c == 9) then
        out(i:i) = " "
      else if (c < 32 .or. c > 126) then
        out(i:i) = "?"
      end if
    end do
  end function printable

  !> The integer a text spells: an optional sign and decimal digits, nothing
  !> else (no blanks, no decimal point, no exponent). `ok` is false for any
  !> other text and for a value outside the 64-bit range (value 0 then; and
  !> `too_large` true); no value is rounded, truncated or wrapped around.
  pure subroutine integer_of(text, value, ok, too_large)
    !> The text (one field, without blanks).
    character(len=*), intent(in) :: text
    integer(int64), intent(out) :: value
    logical, intent(out) :: ok
    !> The text is an integer beyond the 64-bit range.
    logical, intent(out), optional :: too_large
    integer :: i, first, d
    logical :: negative, beyond
    value = 0
    ok = .false.
    beyond = .false.
    if (present(too_large)) too_large = .false.
    if (len(text) == 0) return
    negative = text(1:1) == "-"
    first = 1
    if (text(1:1) == "-" .or. text(1:1) == "+") first = 2
    if (first > len(text)) return
    ! accumulated as a negative number: -huge - 1 is in range too
    do i = first, len(text)
      d = iachar(text(i:i)) - iachar("0")
      if (d < 0 .or. d > 9) then
        value = 0
        return
      end if
      if (value < (-huge(value) - 1 + d)/10) then
        beyond = .true.
      else if (.not. beyond) then
        value = 10*value - d
      end if
    end do
    if (.not. negative .and. value < -huge(value)) beyond = .true.
    if (beyond) then
      value = 0
      if (present(too_large)) too_large = .true.
      return
    end if
    if (.not. negative) value = -value
    ok = .true.
  end subroutine integer_of

  !> Position of the first character of `marks` outside single or double
  !> quotes (a comment's start in MFiX decks and LIGGGHTS scripts), len + 1 for none.
  pure integer function comment_start(text, marks) result(k)
    !> A line.
    character(len=*), intent(in) :: text
    !> The comment characters.
    character(len=*), intent(in) :: marks
    character :: quote
    integer :: i
    quote = " "
    k = len(text) + 1
    do i = 1, len(text)
      if (quote /= " ") then
        if (text(i:i) == quote) quote = " "
      else if (text(i:i) == "'" .or. text(i:i) == '"') then
        quote = text(i:i)
      else if (index(marks, text(i:i)) > 0) then
        k = i
        return
      end if
    end do
  end function comment_start
  !> Read a whole file into a string (one unformatted stream read).
  subroutine read_text_file(path, text, status)
    !> File name.
    character(len=*), intent(in) :: path
    !> Its contents.
    character(len=:), allocatable, intent(out) :: text
    !> `io_error` when the file is missing or unreadable.
    type(demstep_status_type), intent(out) :: status
    integer :: unit, ios
    integer(int64) :: length
    logical :: exists
    character(len=256) :: msg
    inquire(file=path, exist=exists)
    if (.not. exists) then
      call set_status(status, demstep_stat%io_error, "no such file")
      return
    end if
    open(newunit=unit, file=path, access="stream", form="unformatted", action="read", &
      status="old", iostat=ios, iomsg=msg)
    if (ios /= 0) then
      call set_status(status, demstep_stat%io_error, "cannot open: "//trim(msg))
      return
    end if
    inquire(unit=unit, size=length)
    if (length < 0) then
      close(unit)
      call set_status(status, demstep_stat%io_error, "cannot determine the size (not a regular file?)")
      return
    end if
    allocate(character(len=length) :: text)
    ios = 0
    if (length > 0) read(unit, iostat=ios, iomsg=msg) text
    close(unit)
    if (ios /= 0) then
      call set_status(status, demstep_stat%io_error, "cannot read: "//trim(msg))
      return
    end if
    status%stat = demstep_stat%ok
  end subroutine read_text_file

  !> ASCII lower case (other bytes unchanged).
  pure function lowercase(text) result(out)
    !> Text to convert.
    character(len=*), intent(in) :: text
    character(len=len(text)) :: out
    out = case_shifted(text, "A", "Z", 32)
  end function lowercase

  !> ASCII upper case (other bytes unchanged).
  pure function uppercase(text) result(out)
    !> Text to convert.
    character(len=*), intent(in) :: text
    character(len=len(text)) :: out
    out = case_shifted(text, "a", "z", -32)
  end function uppercase

  !> The text with the letters `first` .. `last` moved by `shift` codes.
  pure function case_shifted(text, first, last, shift) result(out)
    character(len=*), intent(in) :: text
    character, intent(in) :: first, last
    integer, intent(in) :: shift
    character(len=len(text)) :: out
    integer :: i
    out = text
    do i = 1, len(text)
      if (text(i:i) >= first .and. text(i:i) <= last) out(i:i) = achar(iachar(text(i:i)) + shift)
    end do
  end function case_shifted

  !> A blank, tab, carriage return or line feed.
  elemental logical function is_blank(c)
    !> One character.
    character, intent(in) :: c
    is_blank = c == " " .or. c == achar(9) .or. c == achar(10) .or. c == achar(13)
  end function is_blank

  !> An ASCII letter.
  elemental logical function is_letter(c)
    !> One character.
    character, intent(in) :: c
    is_letter = (c >= "a" .and. c <= "z") .or. (c >= "A" .and. c <= "Z")
  end function is_letter

  !> A character of a Fortran name: letter, digit or underscore.
  elemental logical function is_name_char(c)
    !> One character.
    character, intent(in) :: c
    is_name_char = is_letter(c) .or. (c >= "0" .and. c <= "9") .or. c == "_"
  end function is_name_char

end module demstep_text
