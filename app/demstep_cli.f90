!> Shared machinery of the demstep command line: variable specifications,
!> reading a group's assignments into a namelist one at a time (so that an error
!> names the variable), number formatting and checks.
module demstep_cli
  use demstep_kinds, only: dp, i8
  use demstep_status, only: demstep_status_type, demstep_stat, set_status
  use demstep_namelist, only: nml_group_type, nml_item_type, excerpt
  use, intrinsic :: ieee_arithmetic, only: ieee_is_finite, ieee_is_nan
  implicit none
  private

  public :: var, check_names, given, item_text, read_failed, check_real, fmt_real, fmt_int, write_template, cli_context, &
    fmt_real_column, &
    new_array, array_length, broadcast, common_length, new_int_array, int_array_length

  !> Most values one array variable of a group may hold.
  integer, parameter, public :: max_values = 100000
  !> Marks array elements the input did not set.
  real(dp), parameter, public :: unset = -huge(1.0_dp)
  !> Marks integer array elements the input did not set.
  integer, parameter, public :: unset_int = -huge(1)

  !> Where a group handler writes: the human report and the result namelist.
  type :: cli_context
    !> Unit of the report (buffered; printed at the end on success).
    integer :: report = -1
    !> Unit of the result namelist (buffered; file or stdout at the end).
    integer :: results = -1
    !> No progress or up-front estimates on stderr (`--quiet`).
    logical :: quiet = .false.
  end type cli_context

  !> One input variable of a group: name, what its value must be, documentation,
  !> and an example value for the template (a leading '!' comments it out there).
  type, public :: var_spec
    character(len=:), allocatable :: name, what, doc, example
  end type var_spec

contains

  !> Build a variable specification.
  pure function var(name, what, doc, example) result(spec)
    character(len=*), intent(in) :: name, what, doc, example
    type(var_spec) :: spec
    spec%name = name
    spec%what = what
    spec%doc = doc
    spec%example = example
  end function var

  !> Every assignment must name a known variable and have a value.
  pure subroutine check_names(group, specs, status)
    type(nml_group_type), intent(in) :: group
    type(var_spec), intent(in) :: specs(:)
    type(demstep_status_type), intent(out) :: status
    integer :: i, j
    do i = 1, size(group%items)
      associate(item => group%items(i))
        j = find(specs, item%name)
        if (j == 0) then
          call set_status(status, demstep_stat%invalid_input, "&"//group%name//": " &
            //item%name//": unknown variable (known: "//names_of(specs)//")")
          return
        end if
        if (len(item%value) == 0) then
          call set_status(status, demstep_stat%invalid_input, "&"//group%name//": " &
            //item%name//": no value given")
          return
        end if
      end associate
    end do
    status%stat = demstep_stat%ok
  end subroutine check_names

  !> True when the group assigns variable `name`.
  pure logical function given(group, name)
    type(nml_group_type), intent(in) :: group
    character(len=*), intent(in) :: name
    integer :: i
    given = .false.
    do i = 1, size(group%items)
      if (group%items(i)%name == name) given = .true.
    end do
  end function given

  !> The single assignment `item` as namelist input of `group`.
  pure function item_text(group, item) result(text)
    type(nml_group_type), intent(in) :: group
    type(nml_item_type), intent(in) :: item
    character(len=:), allocatable :: text
    text = "&"//group%name//" "//item%designator//" = "//item%value//" /"
  end function item_text

  !> The status for a value the runtime could not read.
  pure subroutine read_failed(group, item, specs, status)
    type(nml_group_type), intent(in) :: group
    type(nml_item_type), intent(in) :: item
    type(var_spec), intent(in) :: specs(:)
    type(demstep_status_type), intent(out) :: status
    integer :: j
    j = find(specs, item%name)
    call set_status(status, demstep_stat%invalid_input, "&"//group%name//": "//item%name// &
      ": cannot read '"//excerpt(item%value)//"' as "//specs(max(j, 1))%what)
  end subroutine read_failed

  !> Status `invalid_input` unless x is finite and > `lower` (>= with `inclusive`);
  !> `element` names the array element checked. Does nothing after an error.
  pure subroutine check_real(group, name, x, status, lower, inclusive, element)
    character(len=*), intent(in) :: group, name
    real(dp), intent(in) :: x
    type(demstep_status_type), intent(inout) :: status
    !> Lower bound (default 0).
    real(dp), intent(in), optional :: lower
    logical, intent(in), optional :: inclusive
    integer, intent(in), optional :: element
    real(dp) :: bound
    logical :: closed
    character(len=:), allocatable :: what
    if (status%stat /= demstep_stat%ok) return
    bound = 0.0_dp
    if (present(lower)) bound = lower
    closed = .false.
    if (present(inclusive)) closed = inclusive
    if (ieee_is_finite(x)) then
      if (closed .and. .not. x < bound) return
      if (.not. closed .and. x > bound) return
    end if
    ! the message is built only for a value that fails (this runs once per array element)
    what = "&"//group//": "//name//": "
    if (present(element)) what = what//"element "//fmt_int(int(element, i8))//" is "//fmt_real(x)//"; "
    if (.not. ieee_is_finite(x)) then
      call set_status(status, demstep_stat%invalid_input, what//"must be a finite number, not " &
        //fmt_real(x))
    else if (closed .and. x < bound) then
      call set_status(status, demstep_stat%invalid_input, what//"must be >= "//fmt_real(bound)// &
        ", got "//fmt_real(x))
    else if (.not. closed .and. .not. x > bound) then
      call set_status(status, demstep_stat%invalid_input, what//"must be > "//fmt_real(bound)// &
        ", got "//fmt_real(x))
    end if
  end subroutine check_real

  !> A real with 10 significant digits, trailing zeros dropped: fixed notation for
  !> magnitudes 1e-3 .. 1e7, else `1.25e-8`.
  pure function fmt_real(x) result(text)
    real(dp), intent(in) :: x
    character(len=:), allocatable :: text
    character(len=24) :: cell
    cell = ""
    if (ieee_is_finite(x) .and. x /= 0.0_dp) write(cell, '(es24.9e3)') x
    text = real_text(x, cell)
  end function fmt_real

  !> [[fmt_real]] of each element, left-adjusted in cells of 24 characters, with one
  !> formatted write for the whole array (long tables: the per-statement cost of
  !> formatted output would dominate).
  pure function fmt_real_column(x) result(cells)
    real(dp), intent(in) :: x(:)
    character(len=24), allocatable :: cells(:)
    character(len=24), allocatable :: es(:)
    integer :: i
    allocate(es(size(x)), cells(size(x)))
    if (size(x) > 0) write(es, '(es24.9e3)') x
    do i = 1, size(x)
      cells(i) = real_text(x(i), es(i))
    end do
  end function fmt_real_column

  !> The text of [[fmt_real]] from x and its `es24.9e3` edit (used when x is
  !> finite and nonzero).
  pure function real_text(x, cell) result(text)
    real(dp), intent(in) :: x
    character(len=24), intent(in) :: cell
    character(len=:), allocatable :: text
    character(len=10) :: digits
    character :: sign
    integer :: e, k, m
    if (ieee_is_nan(x)) then
      text = "NaN"
      return
    else if (.not. ieee_is_finite(x)) then
      text = merge("+Inf", "-Inf", x > 0.0_dp)
      return
    else if (x == 0.0_dp) then
      text = "0"
      return
    end if
    ! the es edit gives the 10 rounded significant digits and the exponent of the
    ! rounded value; the fixed notation places the decimal point in those same
    ! digits (rounding at 10 digits lands on the same decimal place there)
    k = index(cell, "E")
    e = exponent_value(cell(k+1:))
    if (e >= -3 .and. e <= 6) then
      m = verify(cell, " ")
      sign = merge("-", " ", cell(m:m) == "-")
      if (sign == "-") m = m + 1
      digits = cell(m:m)//cell(m+2:k-1)
      if (e >= 0) then
        text = drop_zeros(trim(sign)//digits(1:e+1)//"."//digits(e+2:))
      else
        text = drop_zeros(trim(sign)//"0."//repeat("0", -e-1)//digits)
      end if
    else
      text = drop_zeros(trim(adjustl(cell(1:k-1))))//"e"//fmt_int(int(e, i8))
    end if
  end function real_text

  !> The exponent field of an `es` edit (`+005`, `-012`) as an integer.
  pure integer function exponent_value(field) result(e)
    character(len=*), intent(in) :: field
    integer :: i
    e = 0
    do i = 2, len_trim(field)
      e = 10*e + (iachar(field(i:i)) - iachar("0"))
    end do
    if (field(1:1) == "-") e = -e
  end function exponent_value

  pure function drop_zeros(number) result(text)
    character(len=*), intent(in) :: number
    character(len=:), allocatable :: text
    integer :: last
    text = number
    if (index(text, ".") == 0) return
    last = verify(text, "0", back=.true.)
    if (text(last:last) == ".") last = last - 1
    text = text(1:last)
  end function drop_zeros

  !> An integer as text.
  pure function fmt_int(i) result(text)
    integer(i8), intent(in) :: i
    character(len=:), allocatable :: text
    character(len=24) :: buf
    write(buf, '(i0)') i
    text = trim(buf)
  end function fmt_int

  !> Write a commented input group for the template.
  subroutine write_template(unit, group, doc, specs)
    integer, intent(in) :: unit
    character(len=*), intent(in) :: group, doc
    type(var_spec), intent(in) :: specs(:)
    integer :: i
    character(len=:), allocatable :: line
    write(unit, '(a)') "! "//doc
    write(unit, '(a)') "&"//group
    do i = 1, size(specs)
      if (specs(i)%example(1:1) == "!") then
        ! an alternative to another variable: shown commented out
        line = "  ! "//specs(i)%name//" = "//specs(i)%example(2:)//","
      else
        line = "  "//specs(i)%name//" = "//specs(i)%example//","
      end if
      write(unit, '(a)') line//repeat(" ", max(1, 40 - len(line)))//"! "//specs(i)%doc
    end do
    write(unit, '(a)') "/"
  end subroutine write_template

  !> An input array of max_values elements (or `capacity`), all unset.
  pure function new_array(capacity) result(x)
    integer, intent(in), optional :: capacity
    real(dp), allocatable :: x(:)
    if (present(capacity)) then
      allocate(x(capacity))
    else
      allocate(x(max_values))
    end if
    x = unset
  end function new_array

  !> An integer input array of `capacity` elements, all unset.
  pure function new_int_array(capacity) result(x)
    integer, intent(in) :: capacity
    integer, allocatable :: x(:)
    allocate(x(capacity))
    x = unset_int
  end function new_int_array

  !> Number of values given for an integer array, as [[array_length]].
  pure subroutine int_array_length(group, name, x, length, status)
    character(len=*), intent(in) :: group, name
    integer, intent(in) :: x(:)
    integer, intent(out) :: length
    type(demstep_status_type), intent(inout) :: status
    call array_length(group, name, merge(0.0_dp, unset, x /= unset_int), length, status)
  end subroutine int_array_length

  !> Number of values given for an array (0 if none): the last set element;
  !> an unset element before it is an error naming the index.
  pure subroutine array_length(group, name, x, length, status)
    character(len=*), intent(in) :: group, name
    real(dp), intent(in) :: x(:)
    integer, intent(out) :: length
    type(demstep_status_type), intent(inout) :: status
    integer :: i
    length = 0
    if (status%stat /= demstep_stat%ok) return
    do i = size(x), 1, -1
      if (x(i) /= unset) then
        length = i
        exit
      end if
    end do
    do i = 1, length
      if (x(i) == unset) then
        call set_status(status, demstep_stat%invalid_input, "&"//group//": "//name//"(" &
          //fmt_int(int(i, i8))//"): no value (values must be given without gaps)")
        return
      end if
    end do
  end subroutine array_length

  !> The common length of arrays that broadcast: each has 1 value or the
  !> same number; lengths of 0 (absent) are ignored.
  pure subroutine common_length(group, names, lengths, length, status)
    character(len=*), intent(in) :: group
    character(len=*), intent(in) :: names(:)
    integer, intent(in) :: lengths(:)
    integer, intent(out) :: length
    type(demstep_status_type), intent(inout) :: status
    integer :: i, bad
    character(len=:), allocatable :: listing
    length = maxval(lengths)
    if (status%stat /= demstep_stat%ok) return
    if (all(lengths == 0 .or. lengths == 1 .or. lengths == length)) return
    bad = findloc(lengths == 0 .or. lengths == 1 .or. lengths == length, .false., dim=1)
    listing = ""
    do i = 1, size(names)
      if (lengths(i) == 0) cycle
      if (len(listing) > 0) listing = listing//", "
      listing = listing//trim(names(i))//": "//fmt_int(int(lengths(i), 8))
    end do
    call set_status(status, demstep_stat%invalid_input, "&"//group//": "//trim(names(bad))// &
      ": arrays of different lengths ("//listing//"); give 1 value or the same number")
  end subroutine common_length

  !> The first `length` values of an array, a single value repeated.
  pure function broadcast(x, given_length, length) result(y)
    real(dp), intent(in) :: x(:)
    integer, intent(in) :: given_length, length
    real(dp) :: y(length)
    if (given_length == 1) then
      y = x(1)
    else
      y = x(1:length)
    end if
  end function broadcast

  pure integer function find(specs, name)
    type(var_spec), intent(in) :: specs(:)
    character(len=*), intent(in) :: name
    do find = 1, size(specs)
      if (specs(find)%name == name) return
    end do
    find = 0
  end function find

  pure function names_of(specs) result(text)
    type(var_spec), intent(in) :: specs(:)
    character(len=:), allocatable :: text
    integer :: i
    text = ""
    do i = 1, size(specs)
      if (i > 1) text = text//", "
      text = text//specs(i)%name
    end do
  end function names_of

end module demstep_cli
