!> Numbers as text for messages.
module demstep_text
  use, intrinsic :: iso_fortran_env, only: int32, int64, real64
  implicit none
  private

  public :: int_text, real_text

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

end module demstep_text
