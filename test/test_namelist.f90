!> Tests of the namelist deck scanner.
module test_namelist
  use testdrive, only: new_unittest, unittest_type, error_type, check
  use demstep, only: demstep_status_type, demstep_stat
  use demstep_namelist, only: nml_group_type, scan_namelist, excerpt
  implicit none
  private
  public :: collect_namelist

  character(len=*), parameter :: nl = new_line("a")
  integer, parameter :: big = 100000, mega = 1000000

contains

  subroutine collect_namelist(testsuite)
    type(unittest_type), allocatable, intent(out) :: testsuite(:)
    testsuite = [ &
      new_unittest("groups, lines and assignments", test_groups), &
      new_unittest("strings, comments and old terminators", test_strings_comments), &
      new_unittest("subscripts and value lists", test_subscripts), &
      new_unittest("malformed decks give a status", test_malformed), &
      new_unittest("large decks: 1e5 values, items and groups; 1 MB lines", test_large), &
      new_unittest("names over 63 characters refused; messages quote in short", test_long_names) &
      ]
  end subroutine collect_namelist

  subroutine test_groups(error)
    type(error_type), allocatable, intent(out) :: error
    type(nml_group_type), allocatable :: groups(:)
    type(demstep_status_type) :: status
    call scan_namelist("! deck"//nl//"&Solver n = 3 /"//nl//nl//"&SYSTEM"//nl// &
      "  Mass = 1.5,"//nl//"  stiffness=2e3 /"//nl, groups, status)
    call check(error, status%stat, demstep_stat%ok)
    if (allocated(error)) return
    call check(error, size(groups), 2)
    if (allocated(error)) return
    call check(error, groups(1)%name, "solver")
    if (allocated(error)) return
    call check(error, groups(2)%name, "system")
    if (allocated(error)) return
    call check(error, groups(2)%line, 4)
    if (allocated(error)) return
    call check(error, size(groups(2)%items), 2)
    if (allocated(error)) return
    call check(error, groups(2)%items(1)%name, "mass")
    if (allocated(error)) return
    call check(error, groups(2)%items(1)%value, "1.5")
    if (allocated(error)) return
    call check(error, groups(2)%items(2)%line, 6)
    if (allocated(error)) return
    call check(error, groups(2)%items(2)%value, "2e3")
  end subroutine test_groups

  subroutine test_strings_comments(error)
    type(error_type), allocatable, intent(out) :: error
    type(nml_group_type), allocatable :: groups(:)
    type(demstep_status_type) :: status
    call scan_namelist("&a path = 'x/y = z', q = ""it's"" ! c = 3 /"//nl// &
      "  r = 1 /"//nl//"$b s = 2 $end"//nl//"&c t = 'a''b' &end", groups, status)
    call check(error, status%stat, demstep_stat%ok)
    if (allocated(error)) return
    call check(error, size(groups), 3)
    if (allocated(error)) return
    call check(error, size(groups(1)%items), 3)
    if (allocated(error)) return
    call check(error, groups(1)%items(1)%value, "'x/y = z'")
    if (allocated(error)) return
    call check(error, groups(1)%items(2)%value, """it's""")
    if (allocated(error)) return
    call check(error, groups(1)%items(3)%name, "r")
    if (allocated(error)) return
    call check(error, groups(2)%items(1)%value, "2")
    if (allocated(error)) return
    call check(error, groups(3)%items(1)%value, "'a''b'")
  end subroutine test_strings_comments

  subroutine test_subscripts(error)
    type(error_type), allocatable, intent(out) :: error
    type(nml_group_type), allocatable :: groups(:)
    type(demstep_status_type) :: status
    call scan_namelist("&g lambda(2:3) = 0.5, 0.6"//nl//"  z = (1.0, 2.0), n=3*1.0 w%k = 1 /", &
      groups, status)
    call check(error, status%stat, demstep_stat%ok)
    if (allocated(error)) return
    call check(error, size(groups(1)%items), 4)
    if (allocated(error)) return
    call check(error, groups(1)%items(1)%designator, "lambda(2:3)")
    if (allocated(error)) return
    call check(error, groups(1)%items(1)%name, "lambda")
    if (allocated(error)) return
    call check(error, groups(1)%items(1)%value, "0.5, 0.6")
    if (allocated(error)) return
    call check(error, groups(1)%items(2)%value, "(1.0, 2.0)")
    if (allocated(error)) return
    call check(error, groups(1)%items(3)%value, "3*1.0")
    if (allocated(error)) return
    call check(error, groups(1)%items(4)%name, "w")
  end subroutine test_subscripts

  subroutine test_malformed(error)
    type(error_type), allocatable, intent(out) :: error
    type(nml_group_type), allocatable :: groups(:)
    type(demstep_status_type) :: status
    call scan_namelist("&g a = 1", groups, status)
    call check(error, status%stat, demstep_stat%invalid_input, message="no closing /")
    if (allocated(error)) return
    call check(error, index(status%message, "&g") == 1, "message names the group: "//status%message)
    if (allocated(error)) return
    call scan_namelist("&g a = 'open /", groups, status)
    call check(error, status%stat, demstep_stat%invalid_input, message="unterminated string")
    if (allocated(error)) return
    call scan_namelist("&g junk a = 1 /", groups, status)
    call check(error, status%stat, demstep_stat%invalid_input, message="text before assignment")
    if (allocated(error)) return
    call scan_namelist("&g 1.0 /", groups, status)
    call check(error, status%stat, demstep_stat%invalid_input, message="no assignment")
    if (allocated(error)) return
    call scan_namelist("& a = 1 /", groups, status)
    call check(error, status%stat, demstep_stat%invalid_input, message="no group name")
    if (allocated(error)) return
    call scan_namelist("&g a = 1 &h b = 2 /", groups, status)
    call check(error, status%stat, demstep_stat%invalid_input, message="nested group")
  end subroutine test_malformed

  subroutine test_large(error)
    type(error_type), allocatable, intent(out) :: error
    type(nml_group_type), allocatable :: groups(:)
    type(demstep_status_type) :: status
    ! one list of 1e5 values: the value text is kept whole, trailing ", " dropped
    call scan_namelist("&g x = "//repeat("1.5, ", big)//"/", groups, status)
    call check(error, status%stat, demstep_stat%ok, message="1e5 values")
    if (allocated(error)) return
    call check(error, size(groups(1)%items), 1)
    if (allocated(error)) return
    call check(error, len(groups(1)%items(1)%value), 5*big - 2, message="the whole list")
    if (allocated(error)) return
    call check(error, groups(1)%items(1)%value(5*big-4:), "1.5")
    if (allocated(error)) return
    ! 1e5 assignments, one a line
    call scan_namelist("&g"//nl//repeat("a = 1"//nl, big)//" b = 2 /", groups, status)
    call check(error, status%stat, demstep_stat%ok, message="1e5 assignments")
    if (allocated(error)) return
    call check(error, size(groups(1)%items), big + 1)
    if (allocated(error)) return
    call check(error, groups(1)%items(big)%line, big + 1)
    if (allocated(error)) return
    call check(error, groups(1)%items(big)%value, "1")
    if (allocated(error)) return
    call check(error, groups(1)%items(big+1)%name, "b")
    if (allocated(error)) return
    ! 1e5 groups
    call scan_namelist(repeat("&s n = 1 /"//nl, big)//"&T m = 2 /", groups, status)
    call check(error, status%stat, demstep_stat%ok, message="1e5 groups")
    if (allocated(error)) return
    call check(error, size(groups), big + 1)
    if (allocated(error)) return
    call check(error, groups(big)%name, "s")
    if (allocated(error)) return
    call check(error, groups(big+1)%name, "t")
    if (allocated(error)) return
    call check(error, groups(big+1)%line, big + 1)
    if (allocated(error)) return
    call check(error, groups(big+1)%items(1)%value, "2")
    if (allocated(error)) return
    ! 1 MB of line breaks before and inside a group, and a 1 MB string value
    call scan_namelist(repeat(nl, mega)//"&g a = 1"//repeat(nl, mega)//" b = '"// &
      repeat("x", mega)//"' /", groups, status)
    call check(error, status%stat, demstep_stat%ok, message="1 MB blank lines and string")
    if (allocated(error)) return
    call check(error, groups(1)%line, mega + 1)
    if (allocated(error)) return
    call check(error, groups(1)%items(1)%value, "1")
    if (allocated(error)) return
    call check(error, groups(1)%items(2)%line, 2*mega + 1)
    if (allocated(error)) return
    call check(error, len(groups(1)%items(2)%value), mega + 2)
  end subroutine test_large

  subroutine test_long_names(error)
    type(error_type), allocatable, intent(out) :: error
    type(nml_group_type), allocatable :: groups(:)
    type(demstep_status_type) :: status
    call check(error, excerpt("abc"), "abc")
    if (allocated(error)) return
    call check(error, excerpt(repeat("x", 60)), repeat("x", 60))
    if (allocated(error)) return
    call check(error, excerpt(repeat("x", 61)), repeat("x", 60)//"...")
    if (allocated(error)) return
    ! 63 characters is the Fortran limit: accepted, with a subscript too
    call scan_namelist("&"//repeat("g", 63)//" "//repeat("A", 63)//"(2) = 1 /", groups, status)
    call check(error, status%stat, demstep_stat%ok, message="63-character names")
    if (allocated(error)) return
    call check(error, groups(1)%items(1)%name, repeat("a", 63))
    if (allocated(error)) return
    call scan_namelist("&g "//repeat("a", 64)//" = 1 /", groups, status)
    call check(error, status%stat, demstep_stat%invalid_input, message="64-character variable")
    if (allocated(error)) return
    call check(error, status%message, "&g: line 1: variable name '"//repeat("a", 60)// &
      "...' has 64 characters (at most 63)")
    if (allocated(error)) return
    call scan_namelist("&g "//repeat("a", mega)//" = 1 /", groups, status)
    call check(error, status%stat, demstep_stat%invalid_input, message="1 MB variable name")
    if (allocated(error)) return
    call check(error, len(status%message) < 160, "short message: "//status%message)
    if (allocated(error)) return
    call scan_namelist("&"//repeat("g", 64)//" a = 1 /", groups, status)
    call check(error, status%stat, demstep_stat%invalid_input, message="64-character group")
    if (allocated(error)) return
    call check(error, status%message, "line 1: group name '"//repeat("g", 60)// &
      "...' has 64 characters (at most 63)")
    if (allocated(error)) return
    call scan_namelist("&g "//repeat("j", mega)//" a = 1 /", groups, status)
    call check(error, status%stat, demstep_stat%invalid_input, message="1 MB of text before")
    if (allocated(error)) return
    call check(error, status%message, "&g: line 1: text before the first assignment: '"// &
      repeat("j", 60)//"...'")
    if (allocated(error)) return
    call scan_namelist("&g "//repeat("7", mega)//" /", groups, status)
    call check(error, status%stat, demstep_stat%invalid_input, message="1 MB without assignment")
    if (allocated(error)) return
    call check(error, status%message, "&g: line 1: no assignment in '"//repeat("7", 60)//"...'")
  end subroutine test_long_names

end module test_namelist
