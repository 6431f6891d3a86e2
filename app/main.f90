!> demstep: read a Fortran namelist deck, process the groups demstep knows, print a
!> report and write a result namelist that a Fortran program can read back.
!>
!> Exit status: 0 success, 2 bad input or usage, 1 failure to write the output.
program demstep_main
  use, intrinsic :: iso_fortran_env, only: output_unit, error_unit
  use demstep_kinds, only: i8, dp
  use demstep_status, only: demstep_status_type, demstep_stat
  use demstep_version, only: demstep_version_string
  use demstep_mfix_deck, only: mfix_looks_like_deck
  use demstep_namelist, only: nml_group_type, scan_namelist
  use demstep_text, only: read_text_file
  use demstep_cli, only: cli_context, write_template, fmt_int, group_spec, deck_recommendation
  use demstep_cli_files, only: output_file_type, open_output, commit_output, discard_output, &
    refuse_input
  use demstep_cli_registry, only: cli_groups, find_group, group_list, deck_inputs
  use demstep_cli_mfix, only: run_mfix, mfix_default_tolerance
  use demstep_cli_scene, only: scene_takes_material
  implicit none

  character(len=:), allocatable :: input, output, arg, text, skipped, format, value
  type(output_file_type) :: out_file
  logical :: namelist_only
  type(nml_group_type), allocatable :: groups(:)
  type(demstep_status_type) :: status
  type(cli_context) :: ctx
  type(group_spec), allocatable :: registry(:)
  integer :: i, k, nargs, known, ios, n_skipped
  real(dp) :: tolerance, velocity
  logical :: tolerance_given, is_mfix
  !> Skipped groups listed by name in the report; the rest are counted.
  integer, parameter :: max_listed = 20

  registry = cli_groups()

  namelist_only = .false.
  format = "auto"
  tolerance = mfix_default_tolerance
  tolerance_given = .false.
  velocity = 0.0_dp
  nargs = command_argument_count()
  i = 0
  do while (i < nargs)
    i = i + 1
    call argument(i, arg)
    select case (arg)
    case ("-h", "--help")
      call print_help()
      stop
    case ("-V", "--version")
      write(output_unit, '(a)') "demstep "//demstep_version_string
      stop
    case ("--template")
      call print_template()
      stop
    case ("--namelist")
      namelist_only = .true.
    case ("-q", "--quiet")
      ctx%quiet = .true.
    case ("-o", "--output")
      if (i == nargs) call usage_error("option "//arg//" needs a file name")
      i = i + 1
      call argument(i, output)
    case ("--format", "--tolerance", "--velocity")
      if (i == nargs) call usage_error("option "//arg//" needs a value")
      i = i + 1
      call argument(i, value)
      call option_value(arg, value)
    case default
      if (index(arg, "--output=") == 1) then
        output = arg(10:)
      else if (index(arg, "--format=") == 1) then
        call option_value("--format", arg(10:))
      else if (index(arg, "--tolerance=") == 1) then
        call option_value("--tolerance", arg(13:))
      else if (index(arg, "--velocity=") == 1) then
        call option_value("--velocity", arg(12:))
      else if (len(arg) > 1 .and. arg(1:1) == "-") then
        call usage_error("unknown option '"//arg//"'")
      else if (allocated(input)) then
        call usage_error("more than one input file ('"//input//"', '"//arg//"')")
      else
        input = arg
      end if
    end select
  end do
  if (.not. allocated(input)) call usage_error("no input file")
  ctx%deck = input
  if (allocated(output)) then
    if (len(output) == 0) call usage_error("empty output file name")
  end if

  call read_text_file(input, text, status)
  if (status%stat /= demstep_stat%ok) call fail(input//": "//status%message, 2)
  ! which kind of deck: namelist groups, or MFiX keyword lines (no group)
  select case (format)
  case ("mfix")
    is_mfix = .true.
  case ("namelist")
    is_mfix = .false.
    call scan_namelist(text, groups, status)
  case default
    call scan_namelist(text, groups, status)
    is_mfix = .false.
    if (status%stat /= demstep_stat%ok) then
      is_mfix = mfix_looks_like_deck(text)
    else if (size(groups) == 0) then
      is_mfix = mfix_looks_like_deck(text)
    end if
  end select
  if (.not. is_mfix .and. status%stat /= demstep_stat%ok) call fail(input//": "//status%message, 2)
  if (is_mfix) then
    if (allocated(groups)) deallocate(groups)
    allocate(groups(0))
  end if
  ! no output may replace a file the deck reads (the deck, the files it names)
  ctx%inputs = deck_inputs(input, groups)
  if (allocated(output)) then
    call refuse_input(ctx%inputs, output, status)
    if (status%stat /= demstep_stat%ok) call fail(output//": "//status%message//"; the results " &
      //"would replace it (choose another -o file)", 2)
  end if
  if (.not. is_mfix .and. (tolerance_given .or. velocity > 0.0_dp)) call usage_error("--tolerance " &
    //"and --velocity apply to MFiX decks (namelist groups take their own variables)")

  open(newunit=ctx%report, status="scratch", action="readwrite", form="formatted")
  open(newunit=ctx%results, status="scratch", action="readwrite", form="formatted")
  open(newunit=ctx%steps, status="scratch", action="readwrite", form="formatted")
  write(ctx%report, '(a)') "demstep "//demstep_version_string//": "//input
  write(ctx%report, '(a)') ""
  known = 0
  n_skipped = 0
  skipped = ""
  if (is_mfix) then
    call run_mfix(ctx, text, tolerance, tolerance_given, velocity, status)
    if (status%stat /= demstep_stat%ok) call fail(input//": "//status%message, 2)
    known = 1
  end if
  ! a packing's &material reports single contacts (whichever group comes first)
  ctx%material_in_scene = scene_takes_material(groups, input)
  ctx%groups = groups
  do i = 1, size(groups)
    k = find_group(registry, groups(i)%name)
    if (k == 0) then
      ! list the first few by name, count the rest: linear in the number of groups
      n_skipped = n_skipped + 1
      if (n_skipped <= max_listed) skipped = skipped//" &"//groups(i)%name//" (line " &
        //fmt_int(int(groups(i)%line, i8))//")"
      cycle
    end if
    call registry(k)%handler(ctx, groups(i), status)
    if (status%stat /= demstep_stat%ok) call fail(input//": "//status%message, 2)
    known = known + 1
  end do
  if (known == 0) call fail(input//": no demstep group in the file (known: "//group_list(registry) &
    //"; see demstep --template)", 2)
  if (n_skipped > max_listed) skipped = skipped//" and "//fmt_int(int(n_skipped - max_listed, i8)) &
    //" more"
  if (n_skipped > 0) write(ctx%report, '(a)') "skipped groups (not demstep's):"//skipped

  if (allocated(output)) then
    call open_output(output, out_file, status)
    if (status%stat /= demstep_stat%ok) call fail(output//": "//status%message, 1)
    call copy_unit(ctx%results, out_file%unit, ios)
    if (ios /= 0) then
      call discard_output(out_file)
      call fail(output//": cannot write the results", 1)
    end if
    call commit_output(out_file, status)
    if (status%stat /= demstep_stat%ok) call fail(output//": "//status%message, 1)
    write(ctx%report, '(a)') "results written to "//output
  end if
  ! the deck's one recommended dt: the report's last line
  call deck_recommendation(ctx)
  if (namelist_only) then
    call copy_unit(ctx%results, output_unit, ios)
  else
    call copy_unit(ctx%report, output_unit, ios)
  end if
  close(ctx%report)
  close(ctx%results)
  close(ctx%steps)

contains

  !> Print one line on stderr and end with the given exit status.
  subroutine fail(message, code)
    character(len=*), intent(in) :: message
    integer, intent(in) :: code
    write(error_unit, '(a)') "demstep: "//message
    select case (code)
    case (1)
      stop 1, quiet=.true.
    case default
      stop 2, quiet=.true.
    end select
  end subroutine fail

  !> The value of --format, --tolerance or --velocity.
  subroutine option_value(name, text)
    character(len=*), intent(in) :: name, text
    integer :: io
    real(dp) :: x
    select case (name)
    case ("--format")
      select case (text)
      case ("auto", "mfix", "namelist")
        format = text
      case default
        call usage_error("--format: must be 'auto', 'mfix' or 'namelist', got '"//text//"'")
      end select
    case default
      read(text, *, iostat=io) x
      if (io /= 0 .or. len_trim(text) == 0 .or. verify(trim(text), "0123456789.+-eEdD") > 0) &
        call usage_error(name//": '"//text//"' is not a number")
      if (name == "--tolerance") then
        if (.not. (x > 0.0_dp .and. x < 1.0_dp)) call usage_error("--tolerance: must lie in (0, 1), got " &
          //text)
        tolerance = x
        tolerance_given = .true.
      else
        if (.not. (x > 0.0_dp .and. x <= huge(1.0_dp))) call usage_error("--velocity: must be a finite " &
          //"number > 0, got "//text)
        velocity = x
      end if
    end select
  end subroutine option_value

  subroutine usage_error(message)
    character(len=*), intent(in) :: message
    call fail(message//" (usage: demstep [options] FILE.nml; see demstep --help)", 2)
  end subroutine usage_error

  subroutine argument(i, value)
    integer, intent(in) :: i
    character(len=:), allocatable, intent(out) :: value
    integer :: length
    call get_command_argument(i, length=length)
    allocate(character(len=length) :: value)
    if (length > 0) call get_command_argument(i, value)
  end subroutine argument

  !> Copy a buffered scratch unit, from its start, to another unit.
  subroutine copy_unit(from, to, ios)
    integer, intent(in) :: from, to
    integer, intent(out) :: ios
    character(len=4096) :: chunk
    character(len=:), allocatable :: line
    integer :: got
    rewind(from)
    do
      line = ""
      do
        read(from, '(a)', advance="no", iostat=ios, size=got) chunk
        line = line//chunk(1:got)
        if (ios /= 0) exit
      end do
      if (is_iostat_end(ios)) exit
      write(to, '(a)', iostat=ios) line
      if (ios /= 0) return
    end do
    ios = 0
  end subroutine copy_unit

  subroutine print_help()
    write(output_unit, '(a)') &
      "usage: demstep [options] FILE.nml", &
      "       demstep [options] DECK.mfx   (an MFiX deck: keyword lines, no &group)", &
      "", &
      "Reads the namelist groups demstep knows from FILE.nml (other groups, such as a", &
      "DEM solver's own, are skipped and listed), prints a report, and optionally", &
      "writes a result namelist (&<group>_result) that Fortran can read back.", &
      "", &
      "options:", &
      "  -o FILE, --output FILE   write the result namelist to FILE (atomically)", &
      "  --namelist               print the result namelist instead of the report", &
      "  --format F               'auto' (default), 'mfix' or 'namelist': the kind of deck", &
      "  --tolerance X            MFiX decks: tolerance on the restitution error (default 0.01)", &
      "  --velocity V             MFiX Hertzian decks: impact velocity (deck units)", &
      "  -q, --quiet              no up-front estimates or progress on stderr", &
      "  --template               print a commented input with every group", &
      "  -V, --version            print the version", &
      "  -h, --help               print this help", &
      "", &
      "groups: "//group_list(registry), &
      "exit status: 0 ok, 2 bad input or usage, 1 output not written"
  end subroutine print_help

  subroutine print_template()
    integer :: j
    write(output_unit, '(a)') "! demstep input template: every group demstep knows.", &
      "! Values shown are examples; give only the variables you need."
    do j = 1, size(registry)
      write(output_unit, '(a)') ""
      call write_template(output_unit, registry(j))
    end do
  end subroutine print_template

end program demstep_main
