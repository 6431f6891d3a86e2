!> Numbers as text for messages, and integers read from text.
module demstep_text
  use, intrinsic :: iso_fortran_env, only: int32, int64, real64
  implicit none
  private

  public :: int_text, real_text, integer_of, printable, comment_start

  !> An integer as text, without blanks.
  interface int_text
    module procedure :: int32_text, int64_text
  end interface int_text

contains

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

  !> A real as short text for messages: 4 significant digits, trailing zeros
  !> dropped; fixed notation for magnitudes 1e-3 .. 1e5 (`0.25`), else `1.5e-8`.
  pure function real_text(x) result(text)
    real(real64), intent(in) :: x
    character(len=:), allocatable :: text
    character(len=40) :: buf
    character(len=12) :: form
    integer :: k, e, last
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
    write(buf, '(es12.3e3)') x
    k = index(buf, "E")
    read(buf(k+1:), *) e
    if (e >= -3 .and. e <= 4) then
      write(form, '(a, i0, a)') "(f0.", max(0, 3 - e), ")"
      write(buf, form) x
      text = trim(adjustl(buf))
      if (text(1:1) == ".") text = "0"//text
      if (text(1:2) == "-.") text = "-0"//text(2:)
    else
      text = trim(adjustl(buf(1:k-1)))
    end if
    if (index(text, ".") > 0) then
      last = verify(text, "0", back=.true.)
      if (text(last:last) == ".") last = last - 1
      text = text(1:last)
    end if
    if (e < -3 .or. e > 4) text = text//"e"//int64_text(int(e, int64))
  end function real_text

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
      d = index("0123456789", text(i:i)) - 1
      if (d < 0) then
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

end module demstep_text
