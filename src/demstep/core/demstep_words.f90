!> Option words. Each option enum owns one table of its words in code order
!> (`eigen_solver_names`, `contact_law_names`, ...) and spells it with one
!> `*_from_name` and one `*_name`; these are the lookups they share, and the
!> one message for a word that is not in a table.
module demstep_words
  use demstep_status, only: demstep_status_type, demstep_stat, set_status
  use demstep_text, only: lowercase
  implicit none
  private

  public :: word_index, word_of, word_list, word_choice, unknown_word

contains

  !> Position of `word` in `names` (case and surrounding blanks ignored), 0 when absent.
  pure integer function word_index(names, word) result(k)
    !> The table, in code order.
    character(len=*), intent(in) :: names(:)
    !> The word to look up.
    character(len=*), intent(in) :: word
    integer :: i
    k = 0
    do i = 1, size(names)
      if (lowercase(trim(adjustl(word))) == trim(names(i))) then
        k = i
        return
      end if
    end do
  end function word_index

  !> The word at position `k` of `names`, or `?` when `k` is outside the table.
  pure function word_of(names, k) result(word)
    !> The table, in code order.
    character(len=*), intent(in) :: names(:)
    !> Position in the table.
    integer, intent(in) :: k
    character(len=:), allocatable :: word
    if (k >= 1 .and. k <= size(names)) then
      word = trim(names(k))
    else
      word = "?"
    end if
  end function word_of

  !> The table as text for messages and help: `a, b, c` (each in `quote` if given).
  pure function word_list(names, quote) result(text)
    !> The table.
    character(len=*), intent(in) :: names(:)
    !> Put around each word (`'`).
    character(len=*), intent(in), optional :: quote
    character(len=:), allocatable :: text, q
    integer :: i, n, at
    q = ""
    if (present(quote)) q = quote
    ! the length first, then one fill (no growing concatenation)
    n = max(0, 2*(size(names) - 1))
    do i = 1, size(names)
      n = n + len_trim(names(i)) + 2*len(q)
    end do
    allocate(character(len=n) :: text)
    at = 0
    do i = 1, size(names)
      if (i > 1) then
        text(at+1:at+2) = ", "
        at = at + 2
      end if
      text(at+1:) = q//trim(names(i))//q
      at = at + len_trim(names(i)) + 2*len(q)
    end do
  end function word_list

  !> A table's words as a choice for help texts: each quoted, followed by its
  !> note in parentheses where the note is not blank, `or` before the last
  !> (`'auto', 'dense' (LAPACK) or 'none'`).
  pure function word_choice(names, notes) result(text)
    !> The table.
    character(len=*), intent(in) :: names(:)
    !> One note per word (blank: none).
    character(len=*), intent(in), optional :: notes(:)
    character(len=:), allocatable :: text
    integer :: i
    text = ""
    do i = 1, size(names)
      if (i > 1 .and. i == size(names)) then
        text = text//" or "
      else if (i > 1) then
        text = text//", "
      end if
      text = text//"'"//trim(names(i))//"'"
      if (present(notes)) then
        if (i <= size(notes)) then
          if (len_trim(notes(i)) > 0) text = text//" ("//trim(notes(i))//")"
        end if
      end if
    end do
  end function word_choice

  !> The status for a word outside its table: `where: unknown word 'w' (a, b, c)`.
  pure subroutine unknown_word(status, where, word, names)
    !> Status to set (invalid input).
    type(demstep_status_type), intent(out) :: status
    !> The argument or variable that holds the word.
    character(len=*), intent(in) :: where
    !> The word given.
    character(len=*), intent(in) :: word
    !> The words allowed.
    character(len=*), intent(in) :: names(:)
    call set_status(status, demstep_stat%invalid_input, "unknown word '"//trim(adjustl(word))// &
      "' ("//word_list(names)//")", where=where)
  end subroutine unknown_word

end module demstep_words
