!> Result namelists read back by name.
!>
!> demstep writes each result as one namelist group (`&system_result`,
!> `&scene_result`, ...; the README lists their fields). A program that reads a
!> group with its own `namelist` declaration breaks when a field is added;
!> `read_result` reads the group by name instead, so a reader asks only for the
!> fields it uses and ignores the others:
!>
!>```fortran
!> type(result_group_type) :: r
!> call read_result("demstep_result.nml", "system_result", r, status)
!> call result_get(r, "dt", dt, status)
!>```
module demstep_results
  use demstep_kinds, only: dp, i8
  use demstep_status, only: demstep_status_type, demstep_stat, set_status
  use demstep_namelist, only: nml_group_type, read_text_file, scan_namelist, lowercase
  implicit none
  private

  public :: read_result, parse_result, result_get, result_has

  !> Most values one field may hold (a longer list is refused, not allocated).
  integer, parameter :: max_values = 10000000

  !> One result group as read: its fields by name, their values as text.
  type, public :: result_group_type
    !> The group as scanned (names in lower case).
    type(nml_group_type) :: group
  end type result_group_type

  !> A field's value, converted to the type of `value`: a real, an integer (32 or
  !> 64 bit), a logical, a text, an array of reals or integers (allocated to the
  !> field's length), or an array of logicals or fixed-length texts (its leading
  !> elements set, `invalid_input` when the field holds more).
  !> As with a `namelist` read, `value` is left as it was when the group lacks
  !> the field (status `not_found`, naming it) or its text does not convert
  !> (`invalid_input`).
  interface result_get
    module procedure :: get_real, get_int, get_int64, get_logical, get_text, get_reals, get_ints, &
      get_logicals, get_texts, get_int64s
  end interface result_get

contains

  !> Read group `name` (without `&`, any case) of the result file `path`.
  subroutine read_result(path, name, result, status)
    !> The result file (`demstep deck -o path`).
    character(len=*), intent(in) :: path
    !> The group, e.g. `scene_result`.
    character(len=*), intent(in) :: name
    !> The group's fields.
    type(result_group_type), intent(out) :: result
    !> `io_error` naming the file, `not_found` naming the group.
    type(demstep_status_type), intent(out) :: status
    character(len=:), allocatable :: text, what
    integer :: code
    call read_text_file(path, text, status)
    if (status%stat /= demstep_stat%ok) then
      what = status%message
      code = status%stat
      call set_status(status, code, what, where=path)
      return
    end if
    call parse_result(text, name, result, status)
  end subroutine read_result

  !> Find group `name` (without `&`, any case) in result text.
  pure subroutine parse_result(text, name, result, status)
    !> The result namelists, as written.
    character(len=*), intent(in) :: text
    !> The group, e.g. `scene_result`.
    character(len=*), intent(in) :: name
    !> The group's fields.
    type(result_group_type), intent(out) :: result
    !> `not_found` naming the group when the text does not hold it.
    type(demstep_status_type), intent(out) :: status
    type(nml_group_type), allocatable :: groups(:)
    integer :: k
    call scan_namelist(text, groups, status)
    if (status%stat /= demstep_stat%ok) return
    do k = 1, size(groups)
      if (groups(k)%name == lowercase(trim(name))) then
        result%group = groups(k)
        return
      end if
    end do
    call set_status(status, demstep_stat%not_found, "no such group in the result", where=lowercase(trim(name)))
  end subroutine parse_result

  !> True when the group holds field `name`.
  pure logical function result_has(result, name)
    !> The group.
    type(result_group_type), intent(in) :: result
    !> The field, any case.
    character(len=*), intent(in) :: name
    result_has = field_of(result, name) > 0
  end function result_has

  pure integer function field_of(result, name) result(k)
    type(result_group_type), intent(in) :: result
    character(len=*), intent(in) :: name
    integer :: i
    k = 0
    if (.not. allocated(result%group%items)) return
    do i = 1, size(result%group%items)
      if (result%group%items(i)%name == lowercase(trim(name))) k = i
    end do
  end function field_of

  !> The value text of field `name`, or a `not_found` status naming it.
  pure subroutine field_text(result, name, text, status)
    type(result_group_type), intent(in) :: result
    character(len=*), intent(in) :: name
    character(len=:), allocatable, intent(out) :: text
    type(demstep_status_type), intent(out) :: status
    integer :: k
    k = field_of(result, name)
    if (k == 0) then
      text = ""
      call set_status(status, demstep_stat%not_found, "not in &"//result%group%name, where=lowercase(trim(name)))
      return
    end if
    text = result%group%items(k)%value
    status%stat = demstep_stat%ok
  end subroutine field_text

  !> The status for a value its field's type cannot hold.
  pure subroutine bad_value(status, name, text)
    type(demstep_status_type), intent(out) :: status
    character(len=*), intent(in) :: name, text
    call set_status(status, demstep_stat%invalid_input, "cannot read '"//trim(adjustl(text))//"'", &
      where=lowercase(trim(name)))
  end subroutine bad_value

  subroutine get_real(result, name, value, status)
    type(result_group_type), intent(in) :: result
    character(len=*), intent(in) :: name
    real(dp), intent(inout) :: value
    type(demstep_status_type), intent(out) :: status
    character(len=:), allocatable :: text
    real(dp) :: got
    integer :: ios
    call field_text(result, name, text, status)
    if (status%stat /= demstep_stat%ok) return
    read(text, *, iostat=ios) got
    if (ios /= 0) then
      call bad_value(status, name, text)
      return
    end if
    value = got
  end subroutine get_real

  subroutine get_int(result, name, value, status)
    type(result_group_type), intent(in) :: result
    character(len=*), intent(in) :: name
    integer, intent(inout) :: value
    type(demstep_status_type), intent(out) :: status
    character(len=:), allocatable :: text
    integer :: got
    integer :: ios
    call field_text(result, name, text, status)
    if (status%stat /= demstep_stat%ok) return
    read(text, *, iostat=ios) got
    if (ios /= 0) then
      call bad_value(status, name, text)
      return
    end if
    value = got
  end subroutine get_int

  subroutine get_int64(result, name, value, status)
    type(result_group_type), intent(in) :: result
    character(len=*), intent(in) :: name
    integer(i8), intent(inout) :: value
    type(demstep_status_type), intent(out) :: status
    character(len=:), allocatable :: text
    integer(i8) :: got
    integer :: ios
    call field_text(result, name, text, status)
    if (status%stat /= demstep_stat%ok) return
    read(text, *, iostat=ios) got
    if (ios /= 0) then
      call bad_value(status, name, text)
      return
    end if
    value = got
  end subroutine get_int64

  subroutine get_logical(result, name, value, status)
    type(result_group_type), intent(in) :: result
    character(len=*), intent(in) :: name
    logical, intent(inout) :: value
    type(demstep_status_type), intent(out) :: status
    character(len=:), allocatable :: text
    logical :: got
    integer :: ios
    call field_text(result, name, text, status)
    if (status%stat /= demstep_stat%ok) return
    read(text, *, iostat=ios) got
    if (ios /= 0) then
      call bad_value(status, name, text)
      return
    end if
    value = got
  end subroutine get_logical

  !> A text field: one quoted value (blanks the writer padded it with trimmed),
  !> or for a list of texts the value text as written.
  subroutine get_text(result, name, value, status)
    type(result_group_type), intent(in) :: result
    character(len=*), intent(in) :: name
    character(len=:), allocatable, intent(inout) :: value
    type(demstep_status_type), intent(out) :: status
    character(len=:), allocatable :: text
    integer :: n
    call field_text(result, name, text, status)
    if (status%stat /= demstep_stat%ok) return
    text = trim(adjustl(text))
    n = len(text)
    if (n > 0) then
      if (text(n:n) == ",") text = trim(text(:n-1))
    end if
    n = len(text)
    if (n >= 2) then
      if ((text(1:1) == '"' .or. text(1:1) == "'") .and. text(n:n) == text(1:1) .and. &
          index(text(2:n-1), text(1:1)) == 0) then
        value = trim(text(2:n-1))
        return
      end if
    end if
    value = text
  end subroutine get_text

  !> The number of values a list-directed value text holds: commas and blanks
  !> outside quotes separate them, `r*x` stands for r values (the runtime writes
  !> repeats so); -1 for a count beyond `max_values`.
  pure integer function count_values(text) result(n)
    character(len=*), intent(in) :: text
    integer :: i, first, star, r, ios
    character :: quote
    n = 0
    i = 1
    do while (i <= len(text))
      if (is_separator(text(i:i))) then
        i = i + 1
        cycle
      end if
      first = i
      quote = " "
      do while (i <= len(text))
        if (quote /= " ") then
          if (text(i:i) == quote) quote = " "
        else if (text(i:i) == '"' .or. text(i:i) == "'") then
          quote = text(i:i)
        else if (is_separator(text(i:i))) then
          exit
        end if
        i = i + 1
      end do
      star = index(text(first:i-1), "*")
      r = 1
      if (star > 1 .and. verify(text(first:first+star-2), "0123456789") == 0 .and. star <= 10) then
        read(text(first:first+star-2), *, iostat=ios) r
        if (ios /= 0 .or. r < 1) r = 1
      end if
      ! a count beyond any result demstep writes is not a result: refused
      if (r > max_values - n) then
        n = -1
        return
      end if
      n = n + r
    end do
  end function count_values

  elemental logical function is_separator(c)
    character, intent(in) :: c
    is_separator = c == "," .or. c == " " .or. iachar(c) < 32
  end function is_separator

  subroutine get_reals(result, name, value, status)
    type(result_group_type), intent(in) :: result
    character(len=*), intent(in) :: name
    real(dp), allocatable, intent(inout) :: value(:)
    type(demstep_status_type), intent(out) :: status
    character(len=:), allocatable :: text
    real(dp), allocatable :: got(:)
    integer :: ios, n
    call field_text(result, name, text, status)
    if (status%stat /= demstep_stat%ok) return
    n = count_values(text)
    if (n < 0) then
      call bad_value(status, name, text)
      return
    end if
    allocate(got(n))
    read(text, *, iostat=ios) got
    if (ios /= 0) then
      call bad_value(status, name, text)
      return
    end if
    call move_alloc(got, value)
  end subroutine get_reals

  subroutine get_ints(result, name, value, status)
    type(result_group_type), intent(in) :: result
    character(len=*), intent(in) :: name
    integer, allocatable, intent(inout) :: value(:)
    type(demstep_status_type), intent(out) :: status
    character(len=:), allocatable :: text
    integer, allocatable :: got(:)
    integer :: ios, n
    call field_text(result, name, text, status)
    if (status%stat /= demstep_stat%ok) return
    n = count_values(text)
    if (n < 0) then
      call bad_value(status, name, text)
      return
    end if
    allocate(got(n))
    read(text, *, iostat=ios) got
    if (ios /= 0) then
      call bad_value(status, name, text)
      return
    end if
    call move_alloc(got, value)
  end subroutine get_ints

  subroutine get_int64s(result, name, value, status)
    type(result_group_type), intent(in) :: result
    character(len=*), intent(in) :: name
    integer(i8), allocatable, intent(inout) :: value(:)
    type(demstep_status_type), intent(out) :: status
    character(len=:), allocatable :: text
    integer(i8), allocatable :: got(:)
    integer :: ios, n
    call field_text(result, name, text, status)
    if (status%stat /= demstep_stat%ok) return
    n = count_values(text)
    if (n < 0) then
      call bad_value(status, name, text)
      return
    end if
    allocate(got(n))
    read(text, *, iostat=ios) got
    if (ios /= 0) then
      call bad_value(status, name, text)
      return
    end if
    call move_alloc(got, value)
  end subroutine get_int64s

  subroutine get_logicals(result, name, value, status)
    type(result_group_type), intent(in) :: result
    character(len=*), intent(in) :: name
    logical, intent(inout) :: value(:)
    type(demstep_status_type), intent(out) :: status
    character(len=:), allocatable :: text
    logical, allocatable :: got(:)
    integer :: ios, n
    call field_text(result, name, text, status)
    if (status%stat /= demstep_stat%ok) return
    n = count_values(text)
    if (n < 0 .or. n > size(value)) then
      call bad_value(status, name, text)
      return
    end if
    allocate(got(n))
    read(text, *, iostat=ios) got
    if (ios /= 0) then
      call bad_value(status, name, text)
      return
    end if
    value(:n) = got
  end subroutine get_logicals

  subroutine get_texts(result, name, value, status)
    type(result_group_type), intent(in) :: result
    character(len=*), intent(in) :: name
    character(len=*), intent(inout) :: value(:)
    type(demstep_status_type), intent(out) :: status
    character(len=:), allocatable :: text
    character(len=len(value)), allocatable :: got(:)
    integer :: ios, n
    call field_text(result, name, text, status)
    if (status%stat /= demstep_stat%ok) return
    n = count_values(text)
    if (n < 0 .or. n > size(value)) then
      call bad_value(status, name, text)
      return
    end if
    allocate(got(n))
    read(text, *, iostat=ios) got
    if (ios /= 0) then
      call bad_value(status, name, text)
      return
    end if
    value(:n) = got
  end subroutine get_texts

end module demstep_results
