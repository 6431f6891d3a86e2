!> Tests of the namelist deck scanner.
module test_namelist
  use testdrive, only: new_unittest, unittest_type, error_type, check
  use demstep, only: nml_group_type, scan_namelist, demstep_status_type, demstep_stat
  implicit none
  private
  public :: collect_namelist

  character(len=*), parameter :: nl = new_line("a")

contains

  subroutine collect_namelist(testsuite)
    type(unittest_type), allocatable, intent(out) :: testsuite(:)
    testsuite = [ &
      new_unittest("groups, lines and assignments", test_groups), &
      new_unittest("strings, comments and old terminators", test_strings_comments), &
      new_unittest("subscripts and value lists", test_subscripts), &
      new_unittest("malformed decks give a status", test_malformed) &
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

end module test_namelist
