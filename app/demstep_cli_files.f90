!> Output files of the command line, written atomically: a temporary with a short
!> fixed-pattern name in the target's directory, renamed over the target when it is
!> complete, removed on every failure path.
!>
!> An existing target that is a symbolic link keeps its link: the file it points to
!> is replaced. A target that is a file the deck reads (the deck itself, a file it
!> names), by any path or link, is refused: [[refuse_input]].
module demstep_cli_files
  use, intrinsic :: iso_c_binding, only: c_char, c_int, c_null_char, c_ptr, c_associated
  use demstep_status, only: demstep_status_type, demstep_stat, set_status
  use demstep_text, only: int_text
  implicit none
  private

  public :: resolve_path, same_file, open_output, commit_output, discard_output, rename_file, &
    process_id, refuse_input

  !> A file the deck reads: its name (as it is opened) and what it is, in words
  !> ("the input deck", "the deck's &scene snapshot_file").
  type, public :: input_file_type
    character(len=:), allocatable :: path, what
  end type input_file_type

  !> An output being written: the unit, its temporary and the final name.
  type, public :: output_file_type
    integer :: unit = -1
    character(len=:), allocatable :: temp, target
  end type output_file_type

  !> Longest path realpath(3) writes (PATH_MAX on Linux).
  integer, parameter :: path_max = 4096

  interface
    function c_realpath(path, resolved) result(p) bind(c, name="realpath")
      import :: c_char, c_ptr
      character(kind=c_char), intent(in) :: path(*)
      character(kind=c_char), intent(out) :: resolved(*)
      type(c_ptr) :: p
    end function c_realpath
    function c_rename(old, new) result(rc) bind(c, name="rename")
      import :: c_char, c_int
      character(kind=c_char), intent(in) :: old(*), new(*)
      integer(c_int) :: rc
    end function c_rename
    function c_getpid() result(pid) bind(c, name="getpid")
      import :: c_int
      integer(c_int) :: pid
    end function c_getpid
  end interface

contains

  !> The canonical absolute path of an existing file (symbolic links resolved);
  !> the path itself when it does not exist or cannot be resolved.
  function resolve_path(path) result(resolved)
    !> A file name.
    character(len=*), intent(in) :: path
    character(len=:), allocatable :: resolved
    character(kind=c_char, len=path_max) :: buffer
    integer :: k
    if (.not. c_associated(c_realpath(path//c_null_char, buffer))) then
      resolved = path
      return
    end if
    k = index(buffer, c_null_char)
    if (k == 0) k = len(buffer) + 1
    resolved = buffer(1:k-1)
  end function resolve_path

  !> True when both names exist and are the same file (after resolving links).
  function same_file(a, b) result(same)
    !> File names.
    character(len=*), intent(in) :: a, b
    logical :: same
    logical :: exists_a, exists_b
    inquire(file=a, exist=exists_a)
    inquire(file=b, exist=exists_b)
    same = .false.
    if (exists_a .and. exists_b) same = resolve_path(a) == resolve_path(b)
  end function same_file

  !> Status `invalid_input` with the message "is WHAT" when `target` is one of
  !> `inputs` (after resolving links: the output would replace a file the deck
  !> reads); `ok` otherwise (a `target` that does not exist is none of them).
  subroutine refuse_input(inputs, target, status)
    type(input_file_type), intent(in) :: inputs(:)
    !> The name an output would be written to.
    character(len=*), intent(in) :: target
    type(demstep_status_type), intent(out) :: status
    integer :: i
    status%stat = demstep_stat%ok
    do i = 1, size(inputs)
      if (same_file(inputs(i)%path, target)) then
        call set_status(status, demstep_stat%invalid_input, "is "//inputs(i)%what)
        return
      end if
    end do
  end subroutine refuse_input

  !> Open a temporary for `target` in the target's directory (that of the file a
  !> link points to). Status `io_error` when it cannot be created; nothing is left.
  subroutine open_output(target, file, status)
    !> The final name.
    character(len=*), intent(in) :: target
    !> The open temporary (formatted, sequential).
    type(output_file_type), intent(out) :: file
    type(demstep_status_type), intent(out) :: status
    character(len=:), allocatable :: dir
    logical :: is_dir
    integer :: ios, k, attempt
    file%target = resolve_path(target)
    inquire(file=file%target//"/.", exist=is_dir)
    if (is_dir) then
      call set_status(status, demstep_stat%io_error, "is a directory")
      return
    end if
    k = index(file%target, "/", back=.true.)
    dir = file%target(1:k)
    if (k == 0) dir = "./"
    do attempt = 0, 99
      ! a short name, so that a target name of the longest length still gets one
      file%temp = dir//".demstep-"//int_text(process_id())//"-"//int_text(attempt)//".tmp"
      open(newunit=file%unit, file=file%temp, status="new", action="write", form="formatted", &
        iostat=ios)
      if (ios == 0) exit
      if (.not. exists(file%temp)) exit
    end do
    if (ios /= 0) then
      file%unit = -1
      if (exists(dir//".")) then
        call set_status(status, demstep_stat%io_error, "cannot write in directory '"//dir//"'")
      else
        call set_status(status, demstep_stat%io_error, "cannot write: no directory '"//dir//"'")
      end if
      return
    end if
    status%stat = demstep_stat%ok
  end subroutine open_output

  !> Close the temporary and rename it over the target; on failure it is removed.
  subroutine commit_output(file, status)
    type(output_file_type), intent(inout) :: file
    type(demstep_status_type), intent(out) :: status
    integer :: ios
    close(file%unit, iostat=ios)
    file%unit = -1
    if (ios /= 0) then
      call discard_output(file)
      call set_status(status, demstep_stat%io_error, "cannot write (close failed)")
      return
    end if
    if (c_rename(file%temp//c_null_char, file%target//c_null_char) /= 0) then
      call discard_output(file)
      call set_status(status, demstep_stat%io_error, "cannot replace the file")
      return
    end if
    status%stat = demstep_stat%ok
  end subroutine commit_output

  !> Close (if open) and remove the temporary.
  subroutine discard_output(file)
    type(output_file_type), intent(inout) :: file
    integer :: unit, ios
    if (file%unit /= -1) then
      close(file%unit, status="delete", iostat=ios)
      file%unit = -1
      return
    end if
    if (.not. allocated(file%temp)) return
    open(newunit=unit, file=file%temp, status="old", iostat=ios)
    if (ios == 0) close(unit, status="delete", iostat=ios)
  end subroutine discard_output

  !> Atomically rename `source` over `target` (POSIX rename).
  subroutine rename_file(source, target, status)
    !> Existing file, in the target's directory.
    character(len=*), intent(in) :: source
    !> Final name.
    character(len=*), intent(in) :: target
    type(demstep_status_type), intent(out) :: status
    if (c_rename(source//c_null_char, target//c_null_char) /= 0) then
      call set_status(status, demstep_stat%io_error, "cannot rename "//source//" to "//target)
    else
      status%stat = demstep_stat%ok
    end if
  end subroutine rename_file

  !> This process's id, for names of temporary files.
  integer function process_id()
    process_id = int(c_getpid())
  end function process_id

  logical function exists(path)
    character(len=*), intent(in) :: path
    inquire(file=path, exist=exists)
  end function exists

end module demstep_cli_files
