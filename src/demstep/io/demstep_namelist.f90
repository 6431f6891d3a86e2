!> Namelist input decks as text: read a file, find its groups and their assignments.
!>
!> A legacy DEM deck holds the solver's own groups beside demstep's. This module
!> splits a deck into groups (`&name ... /`, also `&name ... &end` and `$name ... $end`)
!> and each group into assignments `designator = values`, honouring quotes and `!`
!> comments, so that a reader can process only the groups it knows and report an
!> error against the exact variable. Values are left as text for the Fortran
!> runtime to convert (`read(text, nml=...)`).
module demstep_namelist
  use demstep_status, only: demstep_status_type, demstep_stat, set_status
  use demstep_text, only: int_text, lowercase, is_blank, is_letter, is_name_char
  implicit none
  private

  public :: scan_namelist, excerpt

  !> One assignment `designator = values` of a group.
  type, public :: nml_item_type
    !> Designator as written, lower case (`lambda(2)`, `mass`).
    character(len=:), allocatable :: designator
    !> Variable name: the designator without subscript or component.
    character(len=:), allocatable :: name
    !> The value text, as written.
    character(len=:), allocatable :: value
    !> Line of the designator in the file.
    integer :: line = 0
  end type nml_item_type

  !> One namelist group of a deck.
  type, public :: nml_group_type
    !> Group name, lower case, without `&`.
    character(len=:), allocatable :: name
    !> Line of the `&name` in the file.
    integer :: line = 0
    !> The assignments, in order.
    type(nml_item_type), allocatable :: items(:)
  end type nml_group_type


  character(len=*), parameter :: lf = achar(10), cr = achar(13), tab = achar(9)
  !> Longest group or variable name Fortran allows.
  integer, parameter :: max_name_length = 63

contains

  !> Split a namelist deck into groups and assignments, in time linear in the
  !> deck's length (groups and items grow by doubling, text is copied once).
  !> Status `invalid_input` for an unterminated group or string, text that is
  !> not an assignment, or a group or variable name longer than Fortran allows
  !> (63 characters); the message starts with the group (`&name: `) where known
  !> and quotes at most [[excerpt]] of the offending text.
  pure subroutine scan_namelist(text, groups, status)
    !> The deck.
    character(len=*), intent(in) :: text
    !> Its groups in file order.
    type(nml_group_type), allocatable, intent(out) :: groups(:)
    type(demstep_status_type), intent(out) :: status
    type(nml_group_type), allocatable :: found(:)
    integer :: i, n, line, start, body_start, body_end, body_line, count
    n = len(text)
    allocate(found(8))
    count = 0
    i = 1
    line = 1
    do while (i <= n)
      select case (text(i:i))
      case (lf)
        line = line + 1
        i = i + 1
      case ("!")
        call skip_comment(text, i)
      case ("&", "$")
        start = i + 1
        i = start
        do while (i <= n)
          if (.not. is_name_char(text(i:i))) exit
          i = i + 1
        end do
        if (i == start) then
          call set_status(status, demstep_stat%invalid_input, &
            "line "//int_text(line)//": '"//text(start-1:start-1)//"' not followed by a group name")
          return
        end if
        if (i - start > max_name_length) then
          call set_status(status, demstep_stat%invalid_input, "line "//int_text(line)// &
            ": group name '"//excerpt(text(start:i-1))//"' has "//int_text(i - start)// &
            " characters (at most "//int_text(max_name_length)//")")
          return
        end if
        if (count == size(found)) call grow_groups(found, 2*count)
        count = count + 1
        associate(group => found(count))
          group%name = lowercase(text(start:i-1))
          group%line = line
          body_start = i
          body_line = line
          call find_group_end(text, i, line, body_end, status)
          if (status%stat /= demstep_stat%ok) then
            status%message = "&"//group%name//": "//status%message
            return
          end if
          call split_items(text(body_start:body_end), body_line, group%items, status)
          if (status%stat /= demstep_stat%ok) then
            status%message = "&"//group%name//": "//status%message
            return
          end if
        end associate
      case default
        i = i + 1
      end select
    end do
    call grow_groups(found, count)
    call move_alloc(found, groups)
    status%stat = demstep_stat%ok
  end subroutine scan_namelist

  !> Resize a group list to `capacity` (>= the groups kept), moving components.
  pure subroutine grow_groups(list, capacity)
    type(nml_group_type), allocatable, intent(inout) :: list(:)
    integer, intent(in) :: capacity
    type(nml_group_type), allocatable :: moved(:)
    integer :: k
    allocate(moved(capacity))
    do k = 1, min(size(list), capacity)
      if (allocated(list(k)%name)) call move_alloc(list(k)%name, moved(k)%name)
      if (allocated(list(k)%items)) call move_alloc(list(k)%items, moved(k)%items)
      moved(k)%line = list(k)%line
    end do
    call move_alloc(moved, list)
  end subroutine grow_groups

  !> Resize an item list to `capacity` (>= the items kept), moving components.
  pure subroutine grow_items(list, capacity)
    type(nml_item_type), allocatable, intent(inout) :: list(:)
    integer, intent(in) :: capacity
    type(nml_item_type), allocatable :: moved(:)
    integer :: k
    allocate(moved(capacity))
    do k = 1, min(size(list), capacity)
      if (allocated(list(k)%designator)) call move_alloc(list(k)%designator, moved(k)%designator)
      if (allocated(list(k)%name)) call move_alloc(list(k)%name, moved(k)%name)
      if (allocated(list(k)%value)) call move_alloc(list(k)%value, moved(k)%value)
      moved(k)%line = list(k)%line
    end do
    call move_alloc(moved, list)
  end subroutine grow_items

  !> Text quoted in a message: at most 60 characters, then "...".
  pure function excerpt(text) result(out)
    !> The text to quote.
    character(len=*), intent(in) :: text
    character(len=:), allocatable :: out
    integer, parameter :: max_shown = 60
    if (len(text) <= max_shown) then
      out = text
    else
      out = text(1:max_shown)//"..."
    end if
  end function excerpt

  !> From just after a group name, find the group's terminator; `i` moves past it.
  pure subroutine find_group_end(text, i, line, body_end, status)
    character(len=*), intent(in) :: text
    integer, intent(inout) :: i, line
    integer, intent(out) :: body_end
    type(demstep_status_type), intent(out) :: status
    integer :: n, first_line
    n = len(text)
    first_line = line
    do while (i <= n)
      select case (text(i:i))
      case (lf)
        line = line + 1
      case ("'", '"')
        call skip_string(text, i, line, status)
        if (status%stat /= demstep_stat%ok) return
        cycle
      case ("!")
        call skip_comment(text, i)
        cycle
      case ("/")
        body_end = i - 1
        i = i + 1
        status%stat = demstep_stat%ok
        return
      case ("&", "$")
        ! &end, $end or a lone $ close a group in older decks
        body_end = i - 1
        if (i + 3 <= n) then
          if (lowercase(text(i+1:i+3)) == "end") then
            i = i + 4
            status%stat = demstep_stat%ok
            return
          end if
        end if
        if (text(i:i) == "$") then
          i = i + 1
          status%stat = demstep_stat%ok
          return
        end if
        call set_status(status, demstep_stat%invalid_input, &
          "line "//int_text(line)//": a new group starts before this one ends with '/'")
        return
      end select
      i = i + 1
    end do
    call set_status(status, demstep_stat%invalid_input, &
      "line "//int_text(first_line)//": group has no closing '/'")
  end subroutine find_group_end

  !> Split a group body into assignments: each '=' outside strings and parentheses
  !> ends a designator; the values run up to the next designator.
  pure subroutine split_items(body, first_line, items, status)
    character(len=*), intent(in) :: body
    integer, intent(in) :: first_line
    type(nml_item_type), allocatable, intent(out) :: items(:)
    type(demstep_status_type), intent(out) :: status
    integer :: i, n, line, depth, name_start, value_start, k, count
    n = len(body)
    allocate(items(8))
    count = 0
    line = first_line
    depth = 0
    value_start = 0
    i = 1
    do while (i <= n)
      select case (body(i:i))
      case (lf)
        line = line + 1
      case ("'", '"')
        call skip_string(body, i, line, status)
        if (status%stat /= demstep_stat%ok) return
        cycle
      case ("!")
        call skip_comment(body, i)
        cycle
      case ("(")
        depth = depth + 1
      case (")")
        depth = depth - 1
      case ("=")
        if (depth == 0) then
          ! the designator lies after the previous '=': the backward scans cover
          ! disjoint stretches of the body
          call designator_before(body, max(value_start, 1), i, name_start)
          if (name_start == 0) then
            call set_status(status, demstep_stat%invalid_input, &
              "line "//int_text(line)//": '=' without a variable name before it")
            return
          end if
          if (value_start == 0) then
            if (len_trim(strip_separators(body(1:name_start-1))) > 0) then
              call set_status(status, demstep_stat%invalid_input, "line "//int_text(line)// &
                ": text before the first assignment: '"// &
                excerpt(trim(strip_separators(body(1:name_start-1))))//"'")
              return
            end if
          else
            items(count)%value = strip_separators(body(value_start:name_start-1))
          end if
          if (count == size(items)) call grow_items(items, 2*count)
          count = count + 1
          associate(item => items(count))
            item%designator = compact(body(name_start:i-1))
            k = scan(item%designator, "(%")
            if (k == 0) k = len(item%designator) + 1
            if (k - 1 > max_name_length) then
              call set_status(status, demstep_stat%invalid_input, "line "//int_text(line)// &
                ": variable name '"//excerpt(item%designator(1:k-1))//"' has "// &
                int_text(k - 1)//" characters (at most "//int_text(max_name_length)//")")
              return
            end if
            item%designator = lowercase(item%designator)
            item%name = item%designator(1:k-1)
            item%line = line
            item%value = ""
          end associate
          value_start = i + 1
        end if
      end select
      i = i + 1
    end do
    if (value_start == 0) then
      if (len_trim(strip_separators(body)) > 0) then
        call set_status(status, demstep_stat%invalid_input, &
          "line "//int_text(first_line)//": no assignment in '"//excerpt(trim(strip_separators(body)))//"'")
        return
      end if
    else
      items(count)%value = strip_separators(body(value_start:n))
    end if
    call grow_items(items, count)
    status%stat = demstep_stat%ok
  end subroutine split_items

  !> Start of the designator (name, optional subscript and components) ending
  !> just before position `eq`, looking no further back than `lo`; 0 if there is none.
  pure subroutine designator_before(body, lo, eq, start)
    character(len=*), intent(in) :: body
    integer, intent(in) :: lo, eq
    integer, intent(out) :: start
    integer :: j, depth
    start = 0
    j = eq - 1
    do while (j >= lo)
      if (.not. is_blank(body(j:j))) exit
      j = j - 1
    end do
    do while (j >= lo)
      if (body(j:j) == ")") then
        depth = 0
        do while (j >= lo)
          if (body(j:j) == ")") depth = depth + 1
          if (body(j:j) == "(") depth = depth - 1
          j = j - 1
          if (depth == 0) exit
        end do
        do while (j >= lo)
          if (.not. is_blank(body(j:j))) exit
          j = j - 1
        end do
      end if
      if (j < lo) return
      if (.not. (is_name_char(body(j:j)) .or. body(j:j) == "%")) exit
      do while (j >= lo)
        if (.not. (is_name_char(body(j:j)) .or. body(j:j) == "%")) exit
        start = j
        j = j - 1
      end do
      if (j < lo) exit
      if (body(j:j) /= ")") exit
    end do
    if (start > 0) then
      if (.not. is_letter(body(start:start))) start = 0
    end if
  end subroutine designator_before

  !> Move `i` past a quoted string starting at `i` (doubled quotes escape).
  pure subroutine skip_string(text, i, line, status)
    character(len=*), intent(in) :: text
    integer, intent(inout) :: i, line
    type(demstep_status_type), intent(out) :: status
    character :: quote
    integer :: first_line
    quote = text(i:i)
    first_line = line
    i = i + 1
    do while (i <= len(text))
      if (text(i:i) == lf) line = line + 1
      if (text(i:i) == quote) then
        if (i < len(text)) then
          if (text(i+1:i+1) == quote) then
            i = i + 2
            cycle
          end if
        end if
        i = i + 1
        status%stat = demstep_stat%ok
        return
      end if
      i = i + 1
    end do
    call set_status(status, demstep_stat%invalid_input, &
      "line "//int_text(first_line)//": unterminated string")
  end subroutine skip_string

  !> Move `i` to the end of the line (onto the line feed, if any).
  pure subroutine skip_comment(text, i)
    character(len=*), intent(in) :: text
    integer, intent(inout) :: i
    integer :: k
    k = index(text(i:), lf)
    if (k == 0) then
      i = len(text) + 1
    else
      i = i + k - 1
    end if
  end subroutine skip_comment

  !> Value text without comments, with blanks for line breaks, trimmed of
  !> blanks and separating commas at both ends. One pass into one buffer.
  pure function strip_separators(text) result(out)
    character(len=*), intent(in) :: text
    character(len=:), allocatable :: out
    character(len=:), allocatable :: buffer
    integer :: i, j, m, line, first, last
    type(demstep_status_type) :: status
    allocate(character(len=len(text)) :: buffer)
    m = 0
    line = 1
    i = 1
    do while (i <= len(text))
      select case (text(i:i))
      case ("'", '"')
        j = i
        call skip_string(text, i, line, status)
        i = min(i, len(text) + 1)
        buffer(m+1:m+i-j) = text(j:i-1)
        m = m + i - j
      case ("!")
        call skip_comment(text, i)
      case (lf, cr, tab)
        m = m + 1
        buffer(m:m) = " "
        i = i + 1
      case default
        m = m + 1
        buffer(m:m) = text(i:i)
        i = i + 1
      end select
    end do
    first = verify(buffer(1:m), " ,")
    if (first == 0) then
      out = ""
      return
    end if
    last = verify(buffer(1:m), " ,", back=.true.)
    out = buffer(first:last)
  end function strip_separators

  !> Remove all blanks from a designator.
  pure function compact(text) result(out)
    character(len=*), intent(in) :: text
    character(len=:), allocatable :: out
    character(len=:), allocatable :: buffer
    integer :: i, m
    allocate(character(len=len(text)) :: buffer)
    m = 0
    do i = 1, len(text)
      if (.not. is_blank(text(i:i))) then
        m = m + 1
        buffer(m:m) = text(i:i)
      end if
    end do
    out = buffer(1:m)
  end function compact

end module demstep_namelist
