!> Shared machinery of the demstep command line: the table that describes a
!> group (its variables with type, default, capacity and the required and
!> either-or rules), the one generic reader that fills a group's namelist from
!> that table (defaults first, then the deck's assignments one at a time, so that
!> an error names the variable), the one place the rules are checked, the
!> template written from the same table, and number formatting.
module demstep_cli
  use demstep_kinds, only: dp, i8
  use demstep_status, only: demstep_status_type, demstep_stat, set_status
  use demstep_namelist, only: nml_group_type, nml_item_type, excerpt
  use demstep_text, only: fmt_int => int_text, real_text, real_column, check_lower
  use demstep_words, only: word_list
  use demstep_cli_files, only: input_file_type
  use, intrinsic :: ieee_arithmetic, only: ieee_is_finite, ieee_is_nan
  implicit none
  private

  public :: record_step, deck_recommendation, var, given, begin_group, check_real, fmt_real, fmt_int, write_template, cli_context, &
    next_assignment, fmt_real_column, default_text, capacity_of, &
    new_array, array_length, broadcast, common_length, new_int_array, int_array_length, &
    report_row, in_group

  !> Most values a list variable holds unless its table row says otherwise.
  integer, parameter, public :: max_values = 100000
  !> Marks array elements the input did not set.
  real(dp), parameter, public :: unset = -huge(1.0_dp)
  !> Marks integer array elements the input did not set.
  integer, parameter, public :: unset_int = -huge(1)
  !> Significant digits of the numbers the app prints ([[fmt_real]]).
  integer, parameter :: app_digits = 10

  !> Where a group handler writes: the human report and the result namelist.
  type :: cli_context
    !> Unit of the report (buffered; printed at the end on success).
    integer :: report = -1
    !> Unit of the result namelist (buffered; file or stdout at the end).
    integer :: results = -1
    !> No progress or up-front estimates on stderr (`--quiet`).
    logical :: quiet = .false.
    !> The input deck's name (relative table files are read beside it).
    character(len=:), allocatable :: deck
    !> The files the deck reads (itself first): no output may replace one.
    type(input_file_type), allocatable :: inputs(:)
    !> A `&scene` of the deck takes its particle types' materials from the
    !> `&material` group: that group then reports single contacts, and the
    !> recommended dt is the packing's alone.
    logical :: material_in_scene = .false.
    !> The deck's groups, scanned once (none for an MFiX deck).
    type(nml_group_type), allocatable :: groups(:)
    !> Unit of the steps the groups yield (scratch; see [[record_step]]), from
    !> which [[deck_recommendation]] takes the deck's one recommended dt.
    integer :: steps = -1
  end type cli_context

  !> One input variable of a group: name, what its value must be (its type, in
  !> words), documentation, an example value for the template (a leading '!'
  !> comments it out there), the default as namelist value text ('' for none; a
  !> leading '!' marks the initial value of a variable needed only in some cases,
  !> not shown as a default),
  !> the capacity of a list (0 for a scalar), and the rules: `required`, and
  !> `excludes` (blank-separated names that may not be given with it; with
  !> `required`, one of it and them must be given) and `needs` (names that must
  !> be given with it).
  type, public :: var_spec
    character(len=:), allocatable :: name, what, doc, example, default, excludes, needs
    integer :: capacity = 0
    logical :: required = .false.
  end type var_spec

  !> Reads, checks and evaluates one group of a deck.
  abstract interface
    subroutine group_handler(ctx, group, status)
      import :: cli_context, nml_group_type, demstep_status_type
      type(cli_context), intent(in) :: ctx
      type(nml_group_type), intent(in) :: group
      type(demstep_status_type), intent(out) :: status
    end subroutine group_handler
  end interface

  !> One group of the command line: its name, a line of documentation, its
  !> variables and its handler.
  type, public :: group_spec
    character(len=:), allocatable :: name, doc
    type(var_spec), allocatable :: vars(:)
    procedure(group_handler), pointer, nopass :: handler => null()
  end type group_spec

  public :: group_handler

  !> One group being read by its handler (see [[begin_group]]).
  type, public :: group_reading
    !> The namelist text to read next: `&group name = value /`.
    character(len=:), allocatable :: text
    !> The runtime's iostat for `text` (set by the handler's read).
    integer :: ios = 0
    !> The group's table.
    type(var_spec), allocatable, private :: specs(:)
    !> Texts handed out so far: the table's rows first, then the deck's items.
    integer, private :: handed = 0
  end type group_reading

contains

  !> Build a variable specification (see [[var_spec]] for the optional rules).
  pure function var(name, what, doc, example, default, capacity, required, excludes, needs) &
      result(spec)
    character(len=*), intent(in) :: name, what, doc, example
    !> Default as namelist value text (a word quoted).
    character(len=*), intent(in), optional :: default
    !> Most values of a list variable.
    integer, intent(in), optional :: capacity
    logical, intent(in), optional :: required
    !> Blank-separated names that may not be given with this one.
    character(len=*), intent(in), optional :: excludes
    !> Blank-separated names that must be given with this one.
    character(len=*), intent(in), optional :: needs
    type(var_spec) :: spec
    spec%name = name
    spec%what = what
    spec%doc = doc
    spec%example = example
    spec%default = ""
    if (present(default)) spec%default = default
    if (present(capacity)) spec%capacity = capacity
    if (present(required)) spec%required = required
    spec%excludes = ""
    if (present(excludes)) spec%excludes = excludes
    spec%needs = ""
    if (present(needs)) spec%needs = needs
  end function var

  !> A real default as namelist text: the short form of [[fmt_real]] when it reads
  !> back to the same double, else all 17 digits (the template then shows exactly
  !> the value the code uses).
  pure function default_text(x) result(text)
    real(dp), intent(in) :: x
    character(len=:), allocatable :: text
    character(len=32) :: buf
    real(dp) :: back
    integer :: ios
    text = fmt_real(x)
    read(text, *, iostat=ios) back
    if (ios == 0 .and. back == x) return
    write(buf, '(es25.17e3)') x
    text = trim(adjustl(buf))
  end function default_text

  !> The capacity of list variable `name` in `specs` (0 when unknown or scalar).
  pure integer function capacity_of(specs, name) result(capacity)
    type(var_spec), intent(in) :: specs(:)
    character(len=*), intent(in) :: name
    integer :: j
    capacity = 0
    j = find(specs, name)
    if (j > 0) capacity = specs(j)%capacity
  end function capacity_of

  !> The common part of every group handler, begun: check the names. The handler
  !> then reads the group's texts (the table's defaults, then the deck's
  !> assignments one at a time) into its own namelist with
  !> `do while (next_assignment(reading, group, status))` and
  !> `read(reading%text, nml=..., iostat=reading%ios)`; the loop ends at an error
  !> or after the required and either-or rules are checked. (The handler reads,
  !> not a procedure passed here: an internal procedure passed as an argument
  !> would need an executable stack.)
  subroutine begin_group(reading, group, specs, status)
    type(group_reading), intent(out) :: reading
    type(nml_group_type), intent(in) :: group
    !> The group's table.
    type(var_spec), intent(in) :: specs(:)
    type(demstep_status_type), intent(out) :: status
    call check_names(group, specs, status)
    reading%specs = specs
  end subroutine begin_group

  !> The next text of a group reading begun by [[begin_group]] in `reading%text`
  !> (true), or false: at an error (in `status`; a text the runtime could not
  !> read, `reading%ios` /= 0, is named here) or at the end, once the group's
  !> rules are checked.
  logical function next_assignment(reading, group, status) result(more)
    type(group_reading), intent(inout) :: reading
    type(nml_group_type), intent(in) :: group
    type(demstep_status_type), intent(inout) :: status
    integer :: k
    more = .false.
    if (status%stat /= demstep_stat%ok) return
    k = reading%handed
    if (k > 0 .and. reading%ios /= 0) then
      if (k <= size(reading%specs)) then
        call set_status(status, demstep_stat%invalid_input, "&"//group%name//": "//reading%specs(k)%name &
          //": the default '"//reading%specs(k)%default//"' cannot be read (a defect of demstep)")
      else
        call read_failed(group, group%items(k - size(reading%specs)), reading%specs, status)
      end if
      return
    end if
    do k = reading%handed + 1, size(reading%specs)
      if (len(reading%specs(k)%default) == 0) cycle
      reading%handed = k
      reading%text = "&"//group%name//" "//reading%specs(k)%name//" = " &
        //value_of(reading%specs(k)%default)//" /"
      more = .true.
      return
    end do
    k = max(reading%handed, size(reading%specs)) + 1
    if (k - size(reading%specs) <= size(group%items)) then
      reading%handed = k
      call check_value_text(group, group%items(k - size(reading%specs)), reading%specs, status)
      if (status%stat /= demstep_stat%ok) return
      reading%text = item_text(group, group%items(k - size(reading%specs)))
      more = .true.
      return
    end if
    reading%handed = k
    call check_rules(group, reading%specs, status)
  end function next_assignment

  !> A default without its '!' mark.
  pure function value_of(default) result(text)
    character(len=*), intent(in) :: default
    character(len=:), allocatable :: text
    text = default
    if (default(1:1) == "!") text = default(2:)
  end function value_of

  !> The required and either-or rules of a table, in one message style:
  !> `V: required`, `V: give either V or W, not both`, for a required
  !> variable with alternatives `V: give either V or W (one of them is required)`,
  !> and `W: required with V` for names that go together.
  pure subroutine check_rules(group, specs, status)
    type(nml_group_type), intent(in) :: group
    type(var_spec), intent(in) :: specs(:)
    type(demstep_status_type), intent(out) :: status
    integer :: i, start
    character(len=:), allocatable :: other
    logical :: any_other
    do i = 1, size(specs)
      associate(s => specs(i))
        any_other = .false.
        start = 1
        do while (start <= len(s%excludes))
          call next_word(s%excludes, start, other)
          if (len(other) == 0) exit
          if (given(group, other)) then
            any_other = .true.
            if (given(group, s%name)) then
              call set_status(status, demstep_stat%invalid_input, "&"//group%name//": "//s%name// &
                ": give either "//s%name//" or "//other//", not both")
              return
            end if
          end if
        end do
        if (given(group, s%name)) then
          start = 1
          do while (start <= len(s%needs))
            call next_word(s%needs, start, other)
            if (len(other) == 0) exit
            if (.not. given(group, other)) then
              call set_status(status, demstep_stat%invalid_input, "&"//group%name//": "//other// &
                ": required with "//s%name)
              return
            end if
          end do
        end if
        ! a given variable that excludes this one replaces it too
        if (s%required .and. .not. (given(group, s%name) .or. any_other)) any_other = replaced(s%name)
        if (s%required .and. .not. (given(group, s%name) .or. any_other)) then
          if (len_trim(s%excludes) == 0) then
            call set_status(status, demstep_stat%invalid_input, "&"//group%name//": "//s%name// &
              ": required")
          else
            call set_status(status, demstep_stat%invalid_input, "&"//group%name//": "//s%name// &
              ": give either "//s%name//" or "//alternatives(s%excludes)//" (one of them is required)")
          end if
          return
        end if
      end associate
    end do
    status%stat = demstep_stat%ok
  contains
    !> Whether a given variable lists `name` among the ones it excludes.
    pure logical function replaced(name)
      character(len=*), intent(in) :: name
      integer :: j, start
      character(len=:), allocatable :: word
      replaced = .false.
      do j = 1, size(specs)
        if (.not. given(group, specs(j)%name)) cycle
        start = 1
        do while (start <= len(specs(j)%excludes))
          call next_word(specs(j)%excludes, start, word)
          if (len(word) == 0) exit
          if (word == name) replaced = .true.
        end do
      end do
    end function replaced
  end subroutine check_rules

  !> The next blank-separated word of `list` from `start` ('' at the end).
  pure subroutine next_word(list, start, word)
    character(len=*), intent(in) :: list
    integer, intent(inout) :: start
    character(len=:), allocatable, intent(out) :: word
    integer :: first, last
    word = ""
    first = verify(list(start:), " ")
    if (first == 0) then
      start = len(list) + 1
      return
    end if
    first = start + first - 1
    last = index(list(first:), " ")
    if (last == 0) then
      last = len(list)
    else
      last = first + last - 2
    end if
    word = list(first:last)
    start = last + 2
  end subroutine next_word

  !> Blank-separated names as prose: `a`, `a and b`, `a, b and c`.
  pure function alternatives(list) result(text)
    character(len=*), intent(in) :: list
    character(len=:), allocatable :: text, word, last
    integer :: start
    text = ""
    last = ""
    start = 1
    do
      call next_word(list, start, word)
      if (len(word) == 0) exit
      if (len(last) > 0) then
        if (len(text) > 0) text = text//", "
        text = text//last
      end if
      last = word
    end do
    if (len(text) > 0) then
      text = text//" and "//last
    else
      text = last
    end if
  end function alternatives

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
    integer(i8) :: last
    j = find(specs, item%name)
    if (specs(j)%capacity > 0) then
      ! too many values is the likelier cause when the count says so
      last = first_index(item%designator) - 1 + count_values(item%value)
      if (last > specs(j)%capacity) then
        call set_status(status, demstep_stat%invalid_input, "&"//group%name//": "//item%name// &
          ": holds at most "//fmt_int(int(specs(j)%capacity, i8))//" values, got "//fmt_int(last))
        return
      end if
    end if
    call set_status(status, demstep_stat%invalid_input, "&"//group%name//": "//item%name// &
      ": cannot read '"//excerpt(item%value)//"' as "//specs(j)%what)
  end subroutine read_failed

  !> What the runtime would read without a word, refused: a null value (an empty
  !> field between commas, or `r*` without a constant: the variable would keep its
  !> default, or a list a gap), a lone sign (`mass = -`, read as 0), and in a
  !> list the value that marks elements not given ([[unset]], [[unset_int]]).
  pure subroutine check_value_text(group, item, specs, status)
    type(nml_group_type), intent(in) :: group
    type(nml_item_type), intent(in) :: item
    type(var_spec), intent(in) :: specs(:)
    type(demstep_status_type), intent(inout) :: status
    integer :: i, start, last, star, j, ios, iv
    integer(i8) :: element, repeat_count
    character :: quote
    logical :: in_field, after_comma, null
    real(dp) :: x
    character(len=:), allocatable :: what, marked
    j = find(specs, item%name)
    what = "&"//group%name//": "//item%name//": "
    element = first_index(item%designator)
    null = .false.
    in_field = .false.
    after_comma = .true.
    quote = " "
    start = 1
    i = 1
    do while (i <= len(item%value) + 1)
      if (i <= len(item%value)) then
        associate(c => item%value(i:i))
          if (quote /= " ") then
            if (c == quote) quote = " "
            i = i + 1
            cycle
          else if (c == "'" .or. c == '"') then
            quote = c
            if (.not. in_field) start = i
            in_field = .true.
            i = i + 1
            cycle
          else if (.not. (c == "," .or. c == " " .or. c == achar(9) .or. c == achar(10) .or. &
              c == achar(13) .or. c == "/")) then
            if (.not. in_field) start = i
            in_field = .true.
            i = i + 1
            cycle
          end if
          ! a separator: two commas with nothing between them enclose a null
          if (c == "," .and. .not. in_field) then
            null = null .or. after_comma
            after_comma = .true.
          else if (c == ",") then
            after_comma = .true.
          else if (in_field) then
            after_comma = .false.
          end if
        end associate
      end if
      last = i - 1
      if (i <= len(item%value)) then
        if (item%value(i:i) == "/") i = len(item%value) + 1
      end if
      if (in_field) then
        in_field = .false.
        associate(field => item%value(start:last))
          star = index(field, "*")
          repeat_count = 1
          if (star > 1 .and. field(1:1) /= "'" .and. field(1:1) /= '"') then
            if (verify(field(1:star-1), "0123456789") == 0) then
              read(field(1:star-1), *, iostat=ios) repeat_count
              if (ios /= 0) repeat_count = 1
              ! r* alone: r nulls
              if (star == len(field)) null = .true.
            else
              star = 0
            end if
          else
            star = 0
          end if
          associate(constant => field(star+1:))
            if (constant == "+" .or. constant == "-") then
              call set_status(status, demstep_stat%invalid_input, what//"cannot read '"// &
                excerpt(item%value)//"' as "//specs(j)%what//" (a sign without digits)")
              return
            end if
            marked = ""
            if (specs(j)%capacity > 0 .and. len(constant) > 0) then
              if (index(specs(j)%what, "real") > 0) then
                read(constant, *, iostat=ios) x
                if (ios == 0 .and. x == unset) marked = fmt_real(x)
              else if (index(specs(j)%what, "integer") > 0) then
                read(constant, *, iostat=ios) iv
                if (ios == 0 .and. iv == unset_int) marked = fmt_int(int(iv, i8))
              end if
            end if
            if (len(marked) > 0) then
              call set_status(status, demstep_stat%invalid_input, what//"element "//fmt_int(element)// &
                " is "//marked//", the value that marks an element not given: out of range")
              return
            end if
          end associate
        end associate
        element = element + repeat_count
      end if
      if (null) then
        call set_status(status, demstep_stat%invalid_input, what//"'"//excerpt(item%value)// &
          "' holds a null value (an empty field between commas, or r* without a value): give every value")
        return
      end if
      i = i + 1
    end do
  end subroutine check_value_text

  !> The first subscript of a designator (`x(3)`, `x(3:5)`: 3), 1 without one.
  pure integer(i8) function first_index(designator) result(k)
    character(len=*), intent(in) :: designator
    integer :: open, i
    k = 1
    open = index(designator, "(")
    if (open == 0) return
    k = 0
    do i = open + 1, len(designator)
      if (designator(i:i) == " ") cycle
      if (designator(i:i) < "0" .or. designator(i:i) > "9") exit
      if (k > huge(k)/10 - 9) exit
      k = 10*k + (iachar(designator(i:i)) - iachar("0"))
    end do
    k = max(k, 1_i8)
  end function first_index

  !> How many values a list-directed value text holds: fields separated by commas
  !> or blanks outside quotes, `r*c` and `r*` counting r, a null between two
  !> commas counting 1 (only used to word a message; 64-bit so that huge repeat
  !> counts saturate instead of wrapping).
  pure integer(i8) function count_values(text) result(n)
    character(len=*), intent(in) :: text
    integer :: i, start
    character :: quote
    logical :: in_field, after_comma
    n = 0
    i = 1
    in_field = .false.
    after_comma = .true.
    quote = " "
    start = 1
    do while (i <= len(text))
      associate(c => text(i:i))
        if (quote /= " ") then
          if (c == quote) quote = " "
        else if (c == "'" .or. c == '"') then
          quote = c
          if (.not. in_field) start = i
          in_field = .true.
        else if (c == "," .or. c == " " .or. c == achar(9) .or. c == achar(10) .or. c == achar(13)) then
          if (in_field) then
            n = n + field_count(text(start:i-1))
            in_field = .false.
            after_comma = c == ","
          else if (c == ",") then
            if (after_comma) n = n + 1
            after_comma = .true.
          end if
        else if (c == "/") then
          exit
        else if (.not. in_field) then
          in_field = .true.
          start = i
        end if
      end associate
      i = i + 1
    end do
    if (in_field) n = n + field_count(text(start:i-1))
  contains
    pure integer(i8) function field_count(field) result(m)
      character(len=*), intent(in) :: field
      integer :: j, star
      integer(i8) :: r
      m = 1
      star = index(field, "*")
      if (star <= 1) return
      r = 0
      do j = 1, star - 1
        if (field(j:j) < "0" .or. field(j:j) > "9") return
        if (r > huge(r)/10 - 9) then
          m = huge(m)
          return
        end if
        r = 10*r + (iachar(field(j:j)) - iachar("0"))
      end do
      m = r
    end function field_count
  end function count_values

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
    if (status%stat /= demstep_stat%ok) return
    call check_lower(x, name, status, lower, inclusive, element)
    call in_group(status, group)
  end subroutine check_real

  !> A real as the app prints it: the library's [[real_text]] with 10
  !> significant digits (`0.25`, `1234567.5`, `1.25e-8`).
  pure function fmt_real(x) result(text)
    real(dp), intent(in) :: x
    character(len=:), allocatable :: text
    text = real_text(x, app_digits)
  end function fmt_real

  !> [[fmt_real]] of each element, left-adjusted in cells of 24 characters
  !> (one formatted write for the whole array).
  pure function fmt_real_column(x) result(cells)
    real(dp), intent(in) :: x(:)
    character(len=24), allocatable :: cells(:)
    cells = real_column(x, app_digits)
  end function fmt_real_column

  !> Write a commented input group for the template, from the group's table: its
  !> documentation, and per variable the example, the documentation and the
  !> default or the rule.
  subroutine write_template(unit, spec)
    integer, intent(in) :: unit
    type(group_spec), intent(in) :: spec
    integer :: i
    character(len=:), allocatable :: line, note
    write(unit, '(a)') "! "//spec%doc
    write(unit, '(a)') "&"//spec%name
    do i = 1, size(spec%vars)
      associate(s => spec%vars(i))
        if (s%example(1:1) == "!") then
          ! an alternative to another variable: shown commented out
          line = "  ! "//s%name//" = "//s%example(2:)//","
        else
          line = "  "//s%name//" = "//s%example//","
        end if
        note = ""
        if (len(s%default) > 0) then
          if (s%default(1:1) /= "!") note = " (default "//s%default//")"
        end if
        if (s%required .and. len_trim(s%excludes) == 0) note = " (required)"
        if (s%required .and. len_trim(s%excludes) > 0) note = " (this or "// &
          alternatives(s%excludes)//" required)"
        write(unit, '(a)') line//repeat(" ", max(1, 40 - len(line)))//"! "//s%doc//note
      end associate
    end do
    write(unit, '(a)') "/"
  end subroutine write_template

  !> An input array of `capacity` elements (the table's), all unset.
  pure function new_array(capacity) result(x)
    integer, intent(in) :: capacity
    real(dp), allocatable :: x(:)
    allocate(x(capacity))
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
      listing = listing//trim(names(i))//": "//fmt_int(int(lengths(i), i8))
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
    character(len=64) :: names(size(specs))
    integer :: i
    do i = 1, size(specs)
      names(i) = specs(i)%name
    end do
    text = word_list(names)
  end function names_of

  !> A failed library status as the app reports it, `&group: variable: what`:
  !> the library's location (`status%where`) becomes the deck's
  !> variable through `names` (rows: library name, deck name; a name not listed
  !> is the deck's own). A status without a location keeps its message.
  pure subroutine in_group(status, group, names)
    !> The status (a failure), relabelled.
    type(demstep_status_type), intent(inout) :: status
    !> The group, without `&`.
    character(len=*), intent(in) :: group
    !> Library names and the deck's names for them, `names(1,k)` -> `names(2,k)`.
    character(len=*), intent(in), optional :: names(:, :)
    integer :: k
    if (status%stat == demstep_stat%ok) return
    if (.not. allocated(status%where)) status%where = ""
    if (.not. allocated(status%detail)) status%detail = status%message
    if (len(status%where) == 0) then
      status%message = "&"//group//": "//status%message
      return
    end if
    if (present(names)) then
      do k = 1, size(names, 2)
        if (trim(names(1, k)) == status%where) then
          status%where = trim(names(2, k))
          exit
        end if
      end do
    end if
    status%message = "&"//group//": "//status%where//": "//status%detail
  end subroutine in_group

  !> One labelled row of a report: `indent` blanks, the label, the value from
  !> column indent + 26 on.
  subroutine report_row(unit, indent, label, value)
    integer, intent(in) :: unit, indent
    character(len=*), intent(in) :: label, value
    character(len=32) :: form
    write(form, '("(", i0, "x, a, t", i0, ", a)")') indent, indent + 26
    write(unit, form) label, trim(value)
  end subroutine report_row

  !> Record the step a group yields (its report names it in a row `label`), for
  !> the deck's one recommended dt; `scene` marks an assembly's step, which
  !> governs its deck. Without `group` (an MFiX deck) the source is "the deck".
  subroutine record_step(ctx, label, dt, scene, group)
    type(cli_context), intent(in) :: ctx
    character(len=*), intent(in) :: label
    real(dp), intent(in) :: dt
    logical, intent(in) :: scene
    type(nml_group_type), intent(in), optional :: group
    character(len=:), allocatable :: source
    if (ctx%steps == -1) return
    source = "the deck"
    if (present(group)) source = "&"//group%name//" (line "//fmt_int(int(group%line, i8))//")"
    ! 17 digits: the double reads back exactly
    write(ctx%steps, '(es25.17e3, 1x, l1, 1x, a)') dt, scene, source//": "//label
  end subroutine record_step

  !> The end of the deck's report: the one `recommended dt = ... s` line, the
  !> step that governs the whole deck (the smallest of the `&scene` steps when
  !> there is one, else the smallest of all), preceded by a row naming it when
  !> the groups yielded more than one step. Nothing when no group yields a step.
  subroutine deck_recommendation(ctx)
    type(cli_context), intent(in) :: ctx
    real(dp) :: dt, best
    logical :: scene, best_scene
    character(len=512) :: source, best_source
    character(len=:), allocatable :: why
    integer :: ios, n, n_scene
    if (ctx%steps == -1) return
    rewind(ctx%steps)
    n = 0
    n_scene = 0
    best = huge(1.0_dp)
    best_scene = .false.
    best_source = ""
    do
      read(ctx%steps, '(es25.17e3, 1x, l1, 1x, a)', iostat=ios) dt, scene, source
      if (ios /= 0) exit
      n = n + 1
      if (scene) n_scene = n_scene + 1
      ! a scene's step replaces any other; among equals, the smallest
      if ((scene .and. .not. best_scene) .or. ((scene .eqv. best_scene) .and. dt < best)) then
        best = dt
        best_scene = scene
        best_source = source
      end if
    end do
    if (n == 0) return
    if (n_scene > 1) then
      why = "the smallest of the "//fmt_int(int(n_scene, i8))//" &scene steps: an assembly's step is its deck's"
    else if (best_scene) then
      why = "an assembly's step is its deck's"
    else
      why = "the smallest of the "//fmt_int(int(n, i8))//" steps"
    end if
    if (n > 1) write(ctx%report, '(a)') "the deck's step: "//trim(best_source)//" ("//why//")"
    write(ctx%report, '(a)') "recommended dt = "//fmt_real(best)//" s"
  end subroutine deck_recommendation

end module demstep_cli
