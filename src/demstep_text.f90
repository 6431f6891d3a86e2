!> Numbers as text for messages.
module demstep_text
  use, intrinsic :: iso_fortran_env, only: int32, int64
  implicit none
  private

  public :: int_text

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

end module demstep_text
