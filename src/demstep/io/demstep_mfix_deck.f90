!> Reader of MFiX input decks (`.mfx` and `mfix.dat`).
!>
!> MFiX reads each line of its deck as one Fortran namelist record: keyword
!> assignments `KEY = v`, `KEY(i) = v`, `KEY(i:j) = v1 v2`, `KEY(i,j) = v`, several
!> on a line, case-insensitive keys, repeat counts `3*0.9`, logicals `.True.`/`.T.`,
!> reals `1.0d-3`, quoted strings, `#` and `!` comments (which also cover the GUI's
!> `#!MFIX-GUI` lines). This module splits a deck into such assignments, keeping
!> each value as text with its line, and converts on request, reporting a bad
!> value by line and keyword. MFiX's `@(...)` arithmetic is evaluated as MFiX
!> evaluates it ([[demstep_mfix_expression]]) when the line is read, as MFiX
!> does (model/read_namelist.f:345); the value keeps the expression as written.
!> Reaction blocks (`@(RXNS)` ... `@(END)`, `@(DES_RXNS)` ... `@(END)`) and the
!> `THERMO DATA` section are skipped, as MFiX's own keyword reader does.
module demstep_mfix_deck
  use demstep_kinds, only: dp
  use demstep_status, only: demstep_status_type, demstep_stat, set_status
  use demstep_text, only: int_text, comment_start, read_text_file, lowercase, uppercase, is_blank, is_letter, &
    is_name_char
  use demstep_mfix_expression, only: mfix_evaluate_expression
  use, intrinsic :: ieee_arithmetic, only: ieee_is_finite
  implicit none
  private

  public :: read_mfix_deck, parse_mfix_deck, mfix_get_real, mfix_get_integer, mfix_get_string, &
    mfix_get_real_array, mfix_get_string_array, mfix_has_keyword, mfix_min_by_second_index, &
    mfix_looks_like_deck, mfix_upper

  !> Largest repeat count `r*value` accepted.
  integer, parameter, public :: mfix_max_repeat = 100000

  !> One value as written.
  type, public :: mfix_value_type
    !> The text (a quoted string without its quotes; for `@(...)` the value as
    !> MFiX writes it, 15 significant digits).
    character(len=:), allocatable :: text
    !> True for MFiX's `@(...)` arithmetic.
    logical :: arithmetic = .false.
    !> The arithmetic as written, `@(...)` (unallocated for other values).
    character(len=:), allocatable :: expression
    !> True for a quoted string.
    logical :: quoted = .false.
  end type mfix_value_type

  !> One keyword assignment.
  type, public :: mfix_item_type
    !> Keyword, lower case.
    character(len=:), allocatable :: name
    !> Number of subscripts (0 to 3; MFiX's species keywords such as
    !> `IC_X_S(ic, m, n)` have three).
    integer :: n_sub = 0
    !> Subscript ranges: `KEY(lo:hi)`; a single subscript has `lo = hi`.
    integer :: lo(3) = 1, hi(3) = 1
    !> The values, repeat counts expanded.
    type(mfix_value_type), allocatable :: values(:)
    !> Line in the deck.
    integer :: line = 0
  end type mfix_item_type

  !> A parsed deck.
  type, public :: mfix_deck_type
    !> The assignments in deck order.
    type(mfix_item_type), allocatable :: items(:)
    !> How many of `items` are used.
    integer :: n_items = 0
  end type mfix_deck_type

  character(len=*), parameter :: lf = achar(10), cr = achar(13)
  !> Keywords that mark a text as an MFiX deck.
  character(len=*), parameter :: mfix_marks(10) = [character(len=16) :: "units", "mmax", &
    "solids_model", "d_p0", "ro_s0", "des_en_input", "des_coll_model", "kn", "e_young", "run_name"]
  !> Marker of a keyword written without a subscript, for messages.
  integer, parameter :: no_sub = -huge(1)

contains

  !> Read and parse an MFiX deck. Status `io_error` for an unreadable file and
  !> `invalid_input` for a line that is not keyword assignments; the message
  !> starts with the file name and the line: `FILE: line N: KEY: what is wrong`.
  subroutine read_mfix_deck(path, deck, status)
    !> File name.
    character(len=*), intent(in) :: path
    !> The deck.
    type(mfix_deck_type), intent(out) :: deck
    type(demstep_status_type), intent(out) :: status
    character(len=:), allocatable :: text
    call read_text_file(path, text, status)
    if (status%stat /= demstep_stat%ok) then
      status%message = path//": "//status%message
      return
    end if
    call parse_mfix_deck(text, deck, status)
    if (status%stat /= demstep_stat%ok) status%message = path//": "//status%message
  end subroutine read_mfix_deck

  !> Parse the text of an MFiX deck into keyword assignments, in time linear in
  !> its length. Status `invalid_input` with `line N: KEY: what is wrong`.
  pure subroutine parse_mfix_deck(text, deck, status)
    !> The deck's text.
    character(len=*), intent(in) :: text
    !> The assignments.
    type(mfix_deck_type), intent(out) :: deck
    type(demstep_status_type), intent(out) :: status
    integer :: start, finish, line, n, last
    logical :: in_block
    character(len=:), allocatable :: low
    allocate(deck%items(16))
    deck%n_items = 0
    n = len(text)
    start = 1
    line = 0
    in_block = .false.
    status%stat = demstep_stat%ok
    do while (start <= n)
      finish = line_end(text, start)
      line = line + 1
      last = finish - 1
      if (last >= start) then
        if (text(last:last) == cr) last = last - 1
      end if
      low = lowercase(adjustl(text(start:max(start, last)))//" ")
      if (last < start) low = " "
      if (in_block) then
        if (block_mark(low, "end")) in_block = .false.
      else if (block_mark(low, "rxns")) then
        in_block = .true.
      else if (index(low, "thermo data") == 1) then
        exit
      else if (last >= start) then
        call parse_line(text(start:last), line, deck, status)
        if (status%stat /= demstep_stat%ok) return
      end if
      start = finish + 1
    end do
  end subroutine parse_mfix_deck

  !> MFiX's reaction block marks (model/parse_line.f, PARSE_LINE and its
  !> START_RXN/END_RXN; the words in parse_mod.f:19-21): the line's first
  !> `@(` ... `)` outside a comment contains `word` (`@(RXNS)`, `@(DES_RXNS)`
  !> start a block; `@(END)`, `@(DES_END)` end it).
  pure logical function block_mark(low, word)
    character(len=*), intent(in) :: low, word
    integer :: a, b, c
    block_mark = .false.
    c = comment_start(low, "#!")
    a = index(low(1:c-1), "@(")
    if (a == 0) return
    b = index(low(a:c-1), ")")
    if (b == 0) return
    block_mark = index(low(a:a+b-1), word) > 0
  end function block_mark

  !> Position of the newline ending the line that starts at `start` (len + 1 for the last).
  pure integer function line_end(text, start) result(finish)
    character(len=*), intent(in) :: text
    integer, intent(in) :: start
    finish = index(text(start:), lf)
    if (finish == 0) then
      finish = len(text) + 1
    else
      finish = start + finish - 1
    end if
  end function line_end

  !> Does an assignment `NAME[(...)] =` start at position p?
  pure logical function assignment_at(s, p)
    character(len=*), intent(in) :: s
    integer, intent(in) :: p
    integer :: q, depth
    assignment_at = .false.
    if (p > len(s)) return
    if (.not. is_letter(s(p:p))) return
    q = p
    do while (q <= len(s))
      if (.not. is_name_char(s(q:q))) exit
      q = q + 1
    end do
    do while (q <= len(s))
      if (.not. is_blank(s(q:q))) exit
      q = q + 1
    end do
    if (q <= len(s)) then
      if (s(q:q) == "(") then
        depth = 0
        do while (q <= len(s))
          if (s(q:q) == "(") depth = depth + 1
          if (s(q:q) == ")") depth = depth - 1
          q = q + 1
          if (depth == 0) exit
        end do
        do while (q <= len(s))
          if (.not. is_blank(s(q:q))) exit
          q = q + 1
        end do
      end if
    end if
    if (q <= len(s)) assignment_at = s(q:q) == "="
  end function assignment_at

  !> Parse the assignments of one line.
  pure subroutine parse_line(s, line, deck, status)
    character(len=*), intent(in) :: s
    integer, intent(in) :: line
    type(mfix_deck_type), intent(inout) :: deck
    type(demstep_status_type), intent(out) :: status
    integer :: p, n, q, name_start, name_end
    type(mfix_item_type) :: item
    character(len=:), allocatable :: loc
    status%stat = demstep_stat%ok
    n = comment_start(s, "#!") - 1
    p = 1
    do
      do while (p <= n)
        if (.not. (is_blank(s(p:p)) .or. s(p:p) == ",")) exit
        p = p + 1
      end do
      if (p > n) exit
      loc = "line "//int_text(line)//": "
      if (.not. is_letter(s(p:p))) then
        call set_status(status, demstep_stat%invalid_input, loc// &
          "expected a keyword assignment KEY = value, found '"//clip(s(p:n))//"'")
        return
      end if
      name_start = p
      do while (p <= n)
        if (.not. is_name_char(s(p:p))) exit
        p = p + 1
      end do
      name_end = p - 1
      item%name = lowercase(s(name_start:p-1))
      item%line = line
      item%n_sub = 0
      item%lo = 1
      item%hi = 1
      loc = loc//s(name_start:p-1)
      do while (p <= n)
        if (.not. is_blank(s(p:p))) exit
        p = p + 1
      end do
      if (p <= n) then
        if (s(p:p) == "(") then
          q = index(s(p:n), ")")
          if (q == 0) then
            call set_status(status, demstep_stat%invalid_input, loc//": subscript without ')'")
            return
          end if
          call parse_subscripts(s(p+1:p+q-2), item, loc, status)
          if (status%stat /= demstep_stat%ok) return
          p = p + q
          do while (p <= n)
            if (.not. is_blank(s(p:p))) exit
            p = p + 1
          end do
        end if
      end if
      if (p > n) then
        call set_status(status, demstep_stat%invalid_input, loc//": expected '=' and a value")
        return
      else if (s(p:p) /= "=") then
        call set_status(status, demstep_stat%invalid_input, loc//": expected '=', found '"// &
          clip(s(p:n))//"'")
        return
      end if
      p = p + 1
      call parse_values(s(1:n), p, item, loc, s(name_start:name_end), status)
      if (status%stat /= demstep_stat%ok) return
      if (size(item%values) == 0) then
        call set_status(status, demstep_stat%invalid_input, loc//": no value after '='")
        return
      end if
      call append_item(deck, item)
    end do
  end subroutine parse_line

  !> At most 40 characters of text for a message.
  pure function clip(s) result(t)
    character(len=*), intent(in) :: s
    character(len=:), allocatable :: t
    t = trim(s)
    if (len(t) > 40) t = t(1:37)//"..."
  end function clip

  !> `i`, `i:j` or `i,j` subscripts.
  pure subroutine parse_subscripts(s, item, loc, status)
    character(len=*), intent(in) :: s
    type(mfix_item_type), intent(inout) :: item
    character(len=*), intent(in) :: loc
    type(demstep_status_type), intent(out) :: status
    integer :: comma, k, colon, ios, a, b
    character(len=:), allocatable :: part, rest
    rest = s
    item%n_sub = 0
    status%stat = demstep_stat%ok
    do
      comma = index(rest, ",")
      if (comma > 0) then
        part = rest(1:comma-1)
        rest = rest(comma+1:)
      else
        part = rest
      end if
      item%n_sub = item%n_sub + 1
      k = item%n_sub
      if (k > 3) then
        call set_status(status, demstep_stat%invalid_input, loc//": more than three subscripts")
        return
      end if
      colon = index(part, ":")
      if (colon > 0) then
        read(part(1:colon-1), *, iostat=ios) a
        if (ios == 0) read(part(colon+1:), *, iostat=ios) b
      else
        read(part, *, iostat=ios) a
        b = a
      end if
      if (ios /= 0 .or. len_trim(part) == 0 .or. verify(trim(adjustl(part)), "0123456789:+- ") > 0) then
        call set_status(status, demstep_stat%invalid_input, loc//": bad subscript '("//trim(s)//")'")
        return
      end if
      if (b < a) then
        call set_status(status, demstep_stat%invalid_input, loc//": empty subscript range '("// &
          trim(s)//")'")
        return
      end if
      item%lo(k) = a
      item%hi(k) = b
      if (comma == 0) exit
    end do
  end subroutine parse_subscripts

  !> The values of one assignment, from position p up to the next assignment.
  pure subroutine parse_values(s, p, item, loc, key, status)
    character(len=*), intent(in) :: s
    integer, intent(inout) :: p
    type(mfix_item_type), intent(inout) :: item
    !> `line N: KEY` and the keyword as written.
    character(len=*), intent(in) :: loc, key
    type(demstep_status_type), intent(out) :: status
    type(mfix_value_type), allocatable :: vals(:)
    type(mfix_value_type) :: v
    integer :: n, count, q, repeat, ios, k, column
    real(dp) :: x
    n = len(s)
    allocate(vals(4))
    count = 0
    status%stat = demstep_stat%ok
    do
      do while (p <= n)
        if (.not. (is_blank(s(p:p)) .or. s(p:p) == ",")) exit
        p = p + 1
      end do
      if (p > n) exit
      if (assignment_at(s, p)) exit
      repeat = 1
      ! repeat count r*value
      q = p
      do while (q <= n)
        if (s(q:q) < "0" .or. s(q:q) > "9") exit
        q = q + 1
      end do
      if (q > p .and. q <= n) then
        if (s(q:q) == "*") then
          read(s(p:q-1), *, iostat=ios) repeat
          if (ios /= 0 .or. repeat < 1 .or. repeat > mfix_max_repeat) then
            call set_status(status, demstep_stat%invalid_input, loc//": repeat count '"// &
              s(p:q-1)//"*' must lie in [1, "//int_text(mfix_max_repeat)//"]")
            return
          end if
          p = q + 1
          if (p > n) then
            call set_status(status, demstep_stat%invalid_input, loc//": no value after the repeat count")
            return
          end if
        end if
      end if
      v%text = ""
      v%arithmetic = .false.
      v%quoted = .false.
      if (allocated(v%expression)) deallocate(v%expression)
      if (s(p:min(n, p+1)) == "@(") then
        ! MFiX: the first ')' closes it (model/parse_line.f:508)
        q = index(s(p:n), ")")
        if (q == 0) then
          call set_status(status, demstep_stat%invalid_input, loc//": '@(' without ')'")
          return
        end if
        q = p + q - 1
        if (repeat > 1 .or. s(max(1, p-1):max(1, p-1)) == "*") then
          ! MFiX writes the value with a leading blank: 'r* ' is r null values
          call set_status(status, demstep_stat%invalid_input, "'"//s(p-1:p-1)//"' before '@(': MFiX writes " &
            //"the value with a leading blank, so its namelist read takes 'r*' as r null values; write " &
            //"the expression r times", where=mfix_upper(key))
          status%message = "line "//int_text(item%line)//", column "//int_text(p)//": "//status%message
          return
        end if
        call mfix_evaluate_expression(s(p+2:q-1), x, v%text, column, status)
        if (status%stat /= demstep_stat%ok) then
          call set_status(status, demstep_stat%invalid_input, s(p:q)//": "//status%detail, where=mfix_upper(key))
          status%message = "line "//int_text(item%line)//", column "//int_text(p + 1 + column)//": " &
            //status%message
          return
        end if
        v%expression = s(p:q)
        v%arithmetic = .true.
        p = q + 1
      else if (s(p:p) == "'" .or. s(p:p) == '"') then
        q = index(s(p+1:), s(p:p))
        if (q == 0) then
          call set_status(status, demstep_stat%invalid_input, loc//": string without a closing quote")
          return
        end if
        v%text = s(p+1:p+q-1)
        v%quoted = .true.
        p = p + q + 1
      else
        q = p
        do while (q <= n)
          if (is_blank(s(q:q)) .or. s(q:q) == ",") exit
          q = q + 1
        end do
        v%text = s(p:q-1)
        p = q
      end if
      do k = 1, repeat
        if (count == size(vals)) call grow_values(vals)
        count = count + 1
        vals(count) = v
      end do
    end do
    item%values = vals(1:count)
  end subroutine parse_values

  pure subroutine grow_values(vals)
    type(mfix_value_type), allocatable, intent(inout) :: vals(:)
    type(mfix_value_type), allocatable :: tmp(:)
    allocate(tmp(2*size(vals)))
    tmp(1:size(vals)) = vals
    call move_alloc(tmp, vals)
  end subroutine grow_values

  pure subroutine append_item(deck, item)
    type(mfix_deck_type), intent(inout) :: deck
    type(mfix_item_type), intent(in) :: item
    type(mfix_item_type), allocatable :: tmp(:)
    if (deck%n_items == size(deck%items)) then
      allocate(tmp(2*size(deck%items)))
      tmp(1:deck%n_items) = deck%items(1:deck%n_items)
      call move_alloc(tmp, deck%items)
    end if
    deck%n_items = deck%n_items + 1
    deck%items(deck%n_items) = item
  end subroutine append_item

  !> The recognition rule of an MFiX deck: some line starts (after blanks)
  !> with one of MFiX's keywords `UNITS`, `MMAX`, `SOLIDS_MODEL`, `D_P0`,
  !> `RO_S0`, `DES_EN_INPUT`, `DES_COLL_MODEL`, `KN`, `E_YOUNG`, `RUN_NAME`
  !> (any case) followed by `=` or a subscript. A deck with bad lines is still
  !> recognised, so that the reader can name the bad line.
  pure logical function mfix_looks_like_deck(text) result(yes)
    !> The file's text.
    character(len=*), intent(in) :: text
    integer :: start, finish, k, p, n
    character(len=:), allocatable :: low
    yes = .false.
    n = len(text)
    start = 1
    do while (start <= n)
      finish = line_end(text, start)
      low = lowercase(adjustl(text(start:finish - 1)))//" "
      do k = 1, size(mfix_marks)
        p = len_trim(mfix_marks(k))
        if (low(1:min(p, len(low))) /= mfix_marks(k)(1:p)) cycle
        if (verify(low(p+1:), " ") == 0) cycle
        associate (c => low(p + verify(low(p+1:), " "):p + verify(low(p+1:), " ")))
          if ((c == "=" .or. c == "(") .and. (low(p+1:p+1) == " " .or. low(p+1:p+1) == "=" &
            .or. low(p+1:p+1) == "(")) then
            yes = .true.
            return
          end if
        end associate
      end do
      start = finish + 1
    end do
  end function mfix_looks_like_deck

  !> True when the deck assigns the keyword (any subscript).
  pure logical function mfix_has_keyword(deck, name) result(has)
    !> The deck.
    type(mfix_deck_type), intent(in) :: deck
    !> Keyword, any case.
    character(len=*), intent(in) :: name
    integer :: i
    has = .false.
    do i = 1, deck%n_items
      if (deck%items(i)%name == lowercase(name)) then
        has = .true.
        return
      end if
    end do
  end function mfix_has_keyword

  !> Message prefix `line N: KEY(i): ` (upper case keyword, as MFiX writes it).
  pure function key_where(name, line, idx) result(w)
    character(len=*), intent(in) :: name
    integer, intent(in) :: line, idx
    character(len=:), allocatable :: w
    w = "line "//int_text(line)//": "//mfix_upper(name)
    if (idx /= no_sub) w = w//"("//int_text(idx)//")"
    w = w//": "
  end function key_where

  !> A keyword or word as MFiX writes it: upper case, without surrounding blanks.
  pure function mfix_upper(s) result(t)
    !> The word.
    character(len=*), intent(in) :: s
    character(len=:), allocatable :: t
    t = uppercase(trim(adjustl(s)))
  end function mfix_upper

  !> Status `invalid_input` for MFiX's `@(...)` arithmetic in an integer
  !> keyword (MFiX writes the value as a real, which its namelist read of an
  !> integer refuses), ok otherwise.
  pure subroutine refuse_arithmetic(v, loc, status)
    type(mfix_value_type), intent(in) :: v
    character(len=*), intent(in) :: loc
    type(demstep_status_type), intent(out) :: status
    status%stat = demstep_stat%ok
    if (v%arithmetic) call set_status(status, demstep_stat%invalid_input, loc//clip(v%expression)// &
      " gives the real "//v%text//", which MFiX's namelist read of an integer keyword refuses; write the integer")
  end subroutine refuse_arithmetic

  !> Convert a value to a real (`1.0`, `1.0d-3`, `2E5`, `3`).
  pure subroutine value_real(v, loc, x, status)
    type(mfix_value_type), intent(in) :: v
    character(len=*), intent(in) :: loc
    real(dp), intent(out) :: x
    type(demstep_status_type), intent(out) :: status
    integer :: ios
    x = 0.0_dp
    if (v%quoted .or. len_trim(v%text) == 0 .or. verify(trim(v%text), "0123456789.+-eEdD") > 0) then
      call set_status(status, demstep_stat%invalid_input, loc//"'"//clip(v%text)//"' is not a number")
      return
    end if
    read(v%text, *, iostat=ios) x
    if (ios /= 0 .or. .not. ieee_is_finite(x)) then
      call set_status(status, demstep_stat%invalid_input, loc//"'"//clip(v%text)//"' is not a number")
      x = 0.0_dp
      return
    end if
    status%stat = demstep_stat%ok
  end subroutine value_real

  !> The last assignment of a scalar keyword, or `found = .false.`.
  pure subroutine last_scalar(deck, name, k, found, line, status)
    type(mfix_deck_type), intent(in) :: deck
    character(len=*), intent(in) :: name
    integer, intent(out) :: k
    !> Whether the deck assigns it, and the line of the last assignment (0: none).
    logical, intent(out) :: found
    integer, intent(out) :: line
    type(demstep_status_type), intent(out) :: status
    integer :: i
    k = 0
    line = 0
    status%stat = demstep_stat%ok
    do i = 1, deck%n_items
      if (deck%items(i)%name == lowercase(name)) k = i
    end do
    found = k > 0
    if (k == 0) return
    line = deck%items(k)%line
    associate (it => deck%items(k))
      if (it%n_sub > 0) then
        call set_status(status, demstep_stat%invalid_input, key_where(name, it%line, no_sub)// &
          "takes no subscript")
      else if (size(it%values) /= 1) then
        call set_status(status, demstep_stat%invalid_input, key_where(name, it%line, no_sub)// &
          "expects one value, found "//int_text(size(it%values)))
      end if
    end associate
  end subroutine last_scalar

  !> A real scalar keyword. `found` false when absent; `line` its line.
  pure subroutine mfix_get_real(deck, name, x, found, line, status)
    !> The deck.
    type(mfix_deck_type), intent(in) :: deck
    !> Keyword.
    character(len=*), intent(in) :: name
    !> Its value (unchanged when absent).
    real(dp), intent(inout) :: x
    !> Whether the deck assigns it.
    logical, intent(out) :: found
    !> Its line (0 when absent).
    integer, intent(out) :: line
    type(demstep_status_type), intent(out) :: status
    integer :: k
    call last_scalar(deck, name, k, found, line, status)
    if (status%stat /= demstep_stat%ok .or. .not. found) return
    call value_real(deck%items(k)%values(1), key_where(name, line, no_sub), x, status)
  end subroutine mfix_get_real

  !> An integer scalar keyword.
  pure subroutine mfix_get_integer(deck, name, i, found, line, status)
    !> The deck.
    type(mfix_deck_type), intent(in) :: deck
    !> Keyword.
    character(len=*), intent(in) :: name
    !> Its value (unchanged when absent).
    integer, intent(inout) :: i
    !> Whether the deck assigns it.
    logical, intent(out) :: found
    !> Its line.
    integer, intent(out) :: line
    type(demstep_status_type), intent(out) :: status
    integer :: k, ios
    call last_scalar(deck, name, k, found, line, status)
    if (status%stat /= demstep_stat%ok .or. .not. found) return
    associate (v => deck%items(k)%values(1))
      call refuse_arithmetic(v, key_where(name, line, no_sub), status)
      if (status%stat /= demstep_stat%ok) return
      ios = 1
      if (.not. v%quoted .and. len_trim(v%text) > 0 .and. verify(trim(v%text), "0123456789+-") == 0) &
        read(v%text, *, iostat=ios) i
      if (ios /= 0) call set_status(status, demstep_stat%invalid_input, key_where(name, line, no_sub)// &
        "'"//clip(v%text)//"' is not an integer")
    end associate
  end subroutine mfix_get_integer

  !> A string scalar keyword (quoted or not), as written.
  pure subroutine mfix_get_string(deck, name, s, found, line, status)
    !> The deck.
    type(mfix_deck_type), intent(in) :: deck
    !> Keyword.
    character(len=*), intent(in) :: name
    !> Its value (unallocated when absent).
    character(len=:), allocatable, intent(out) :: s
    !> Whether the deck assigns it.
    logical, intent(out) :: found
    !> Its line.
    integer, intent(out) :: line
    type(demstep_status_type), intent(out) :: status
    integer :: k
    call last_scalar(deck, name, k, found, line, status)
    if (status%stat /= demstep_stat%ok .or. .not. found) return
    s = trim(adjustl(deck%items(k)%values(1)%text))
  end subroutine mfix_get_string

  !> Visit the elements of a one-subscript keyword in deck order: element
  !> indices, values and lines. `KEY = v1 v2` starts at 1, `KEY(i) = v1 v2` at i,
  !> `KEY(i:j)` takes at most j - i + 1 values. Indices outside [1, n] refused.
  pure subroutine array_elements(deck, name, n, idx, vals, lines, count, status)
    type(mfix_deck_type), intent(in) :: deck
    character(len=*), intent(in) :: name
    integer, intent(in) :: n
    integer, allocatable, intent(out) :: idx(:), lines(:)
    type(mfix_value_type), allocatable, intent(out) :: vals(:)
    integer, intent(out) :: count
    type(demstep_status_type), intent(out) :: status
    integer :: i, k, total, j
    total = 0
    do i = 1, deck%n_items
      if (deck%items(i)%name == lowercase(name)) total = total + size(deck%items(i)%values)
    end do
    allocate(idx(total), lines(total), vals(total))
    count = 0
    status%stat = demstep_stat%ok
    do i = 1, deck%n_items
      if (deck%items(i)%name /= lowercase(name)) cycle
      associate (it => deck%items(i))
        if (it%n_sub > 1) then
          call set_status(status, demstep_stat%invalid_input, key_where(name, it%line, no_sub)// &
            "takes one subscript")
          return
        end if
        if (it%n_sub == 1 .and. it%hi(1) > it%lo(1) .and. size(it%values) > it%hi(1) - it%lo(1) + 1) then
          call set_status(status, demstep_stat%invalid_input, key_where(name, it%line, no_sub)// &
            int_text(size(it%values))//" values for "//int_text(it%hi(1) - it%lo(1) + 1)//" elements")
          return
        end if
        do k = 1, size(it%values)
          j = merge(it%lo(1), 1, it%n_sub == 1) + k - 1
          if (j < 1 .or. j > n) then
            call set_status(status, demstep_stat%invalid_input, key_where(name, it%line, j)// &
              "index out of range [1, "//int_text(n)//"]")
            return
          end if
          count = count + 1
          idx(count) = j
          lines(count) = it%line
          vals(count) = it%values(k)
        end do
      end associate
    end do
  end subroutine array_elements

  !> A real array keyword of n elements: `x(i)` and `set(i)` for the elements
  !> the deck assigns (the last assignment wins), `lines(i)` their lines.
  pure subroutine mfix_get_real_array(deck, name, n, x, set, lines, status)
    !> The deck.
    type(mfix_deck_type), intent(in) :: deck
    !> Keyword.
    character(len=*), intent(in) :: name
    !> Number of elements.
    integer, intent(in) :: n
    !> Values (unchanged loc not set).
    real(dp), intent(inout) :: x(n)
    !> Which elements the deck sets.
    logical, intent(out) :: set(n)
    !> Line of each set element (0 elsewhere).
    integer, intent(out) :: lines(n)
    type(demstep_status_type), intent(out) :: status
    integer, allocatable :: idx(:), ln(:)
    type(mfix_value_type), allocatable :: vals(:)
    integer :: count, k
    set = .false.
    lines = 0
    call array_elements(deck, name, n, idx, vals, ln, count, status)
    if (status%stat /= demstep_stat%ok) return
    do k = 1, count
      call value_real(vals(k), key_where(name, ln(k), idx(k)), x(idx(k)), status)
      if (status%stat /= demstep_stat%ok) return
      set(idx(k)) = .true.
      lines(idx(k)) = ln(k)
    end do
  end subroutine mfix_get_real_array

  !> The smallest value a two-subscript real keyword (`KEY(i, j)`, such as
  !> `BC_PSD_MIN_DP(bc, phase)`) assigns for each second subscript j in [1, n]:
  !> `x(j)` and its line, `set(j)` false where the deck assigns none.
  pure subroutine mfix_min_by_second_index(deck, name, n, x, set, lines, status)
    !> The deck.
    type(mfix_deck_type), intent(in) :: deck
    !> Keyword.
    character(len=*), intent(in) :: name
    !> Range of the second subscript.
    integer, intent(in) :: n
    !> Smallest value per second subscript.
    real(dp), intent(out) :: x(n)
    !> Which second subscripts the deck assigns.
    logical, intent(out) :: set(n)
    !> Line of each smallest value (0 elsewhere).
    integer, intent(out) :: lines(n)
    type(demstep_status_type), intent(out) :: status
    integer :: i, j, k
    real(dp) :: v
    x = 0.0_dp
    set = .false.
    lines = 0
    status%stat = demstep_stat%ok
    do i = 1, deck%n_items
      if (deck%items(i)%name /= lowercase(name)) cycle
      associate (it => deck%items(i))
        if (it%n_sub /= 2) then
          call set_status(status, demstep_stat%invalid_input, key_where(name, it%line, no_sub)// &
            "takes two subscripts")
          return
        end if
        ! the second subscript is the phase: as D_P0's index, refused outside [1, n]
        if (min(it%lo(1), it%lo(2)) < 1 .or. it%hi(2) > n) then
          call set_status(status, demstep_stat%invalid_input, "line "//int_text(it%line)//": " &
            //mfix_upper(name)//"("//int_text(it%lo(1))//","//int_text(merge(it%lo(2), it%hi(2), &
            it%lo(2) < 1))//"): index out of range (the first >= 1, the second, the phase, in [1, " &
            //int_text(n)//"])")
          return
        end if
        do k = 1, size(it%values)
          call value_real(it%values(k), key_where(name, it%line, no_sub), v, status)
          if (status%stat /= demstep_stat%ok) return
          do j = it%lo(2), it%hi(2)
            if (.not. set(j) .or. v < x(j)) then
              x(j) = v
              lines(j) = it%line
            end if
            set(j) = .true.
          end do
        end do
      end associate
    end do
  end subroutine mfix_min_by_second_index

  !> A string array keyword of n elements (values upper case, blank loc not set).
  pure subroutine mfix_get_string_array(deck, name, n, s, set, lines, status)
    !> The deck.
    type(mfix_deck_type), intent(in) :: deck
    !> Keyword.
    character(len=*), intent(in) :: name
    !> Number of elements.
    integer, intent(in) :: n
    !> Values, upper case, at most 32 characters.
    character(len=32), intent(out) :: s(n)
    !> Which elements the deck sets.
    logical, intent(out) :: set(n)
    !> Line of each set element.
    integer, intent(out) :: lines(n)
    type(demstep_status_type), intent(out) :: status
    integer, allocatable :: idx(:), ln(:)
    type(mfix_value_type), allocatable :: vals(:)
    integer :: count, k
    s = " "
    set = .false.
    lines = 0
    call array_elements(deck, name, n, idx, vals, ln, count, status)
    if (status%stat /= demstep_stat%ok) return
    do k = 1, count
      s(idx(k)) = mfix_upper(trim(adjustl(vals(k)%text)))
      set(idx(k)) = .true.
      lines(idx(k)) = ln(k)
    end do
  end subroutine mfix_get_string_array

end module demstep_mfix_deck
