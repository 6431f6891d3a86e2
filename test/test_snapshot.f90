!> Tests of the snapshot readers on small hand-written files: a LAMMPS/LIGGGHTS
!> dump (columns in any order, scaled coordinates, periodic flags, frames), a
!> data file of atom style sphere with velocities, Yade's text exports; and each
!> malformed file reported by name, line and what is wrong.
module test_snapshot
  use testdrive, only: new_unittest, unittest_type, error_type, check
  use demstep_kinds, only: dp, i8, pi
  use demstep_status, only: demstep_status_type, demstep_stat
  use demstep_snapshot
  use test_support, only: write_file, work_dir
  use test_snapshot_hostile, only: test_truncated, test_flipped, test_inflated
  use demstep_text, only: integer_of, printable
  implicit none
  private
  public :: collect_snapshot

  character(len=*), parameter :: nl = new_line("a")

contains

  subroutine collect_snapshot(testsuite)
    type(unittest_type), allocatable, intent(out) :: testsuite(:)
    testsuite = [ &
      new_unittest("dump: columns in any order, box, periodic axes, last frame", test_dump), &
      new_unittest("dump: scaled coordinates, diameter, a chosen frame, type densities", test_dump_scaled), &
      new_unittest("dump: each malformed file", test_dump_bad), &
      new_unittest("data file: atom style sphere with velocities", test_data), &
      new_unittest("data file: each malformed file", test_data_bad), &
      new_unittest("Yade text: x_y_z_r, matId, attrs", test_yade), &
      new_unittest("Yade text: each malformed file; format detection", test_yade_bad), &
      new_unittest("files: the message starts with the file name", test_files), &
      new_unittest("files LIGGGHTS 3.8.0 wrote (test/data/liggghts)", test_liggghts), &
      new_unittest("dump: NUMBER OF ATOMS 2147483647 over 8 rows refused in one line", test_dump_counts), &
      new_unittest("data file: 2147483647 atoms over 2 rows refused before allocating", test_data_counts), &
      new_unittest("ids, types and matIds: integers in range, by line and column", test_integer_columns), &
      new_unittest("duplicate atom ids refused with the lines of both", test_duplicate_ids), &
      new_unittest("integer_of: the 64-bit integers and nothing else; printable", test_integer_of), &
      new_unittest("every example snapshot truncated: a prefix of it or one line", test_truncated), &
      new_unittest("every example snapshot with bytes changed: sound or one line", test_flipped), &
      new_unittest("every example snapshot's counts inflated to 2147483647, 1e8, ...: one line", test_inflated) &
      ]
  end subroutine collect_snapshot

  !> Two frames; the second (the last) is read.
  pure function two_frames() result(t)
    character(len=:), allocatable :: t
    t = "ITEM: TIMESTEP"//nl//"100"//nl//"ITEM: NUMBER OF ATOMS"//nl//"1"//nl// &
      "ITEM: BOX BOUNDS pp ff pp"//nl//"0 1"//nl//"0 2"//nl//"0 3"//nl// &
      "ITEM: ATOMS id type x y z radius mass"//nl//"7 1 0.1 0.2 0.3 0.05 1.0"//nl// &
      "ITEM: TIMESTEP"//nl//"200"//nl//"ITEM: NUMBER OF ATOMS"//nl//"2"//nl// &
      "ITEM: BOX BOUNDS pp ff pp"//nl//"-1 1"//nl//"-2 2"//nl//"0 3"//nl// &
      "ITEM: ATOMS radius z y x vz vy vx type id fx c_stress[1] mass omegax omegay omegaz"//nl// &
      "0.01 3e-1 0.2 0.1 -3 -2 -1 2 11 9 9 0.5 4 5 6"//nl// &
      "0.02 0.6 0.5 0.4 3 2 1 1 12 9 9 0.25 7 8 9"//nl
  end function two_frames

  subroutine test_dump(error)
    type(error_type), allocatable, intent(out) :: error
    type(snapshot_type) :: s
    type(demstep_status_type) :: status
    call parse_snapshot(two_frames(), s, status)
    call check(error, status%stat == demstep_stat%ok, "reads: "//status%message)
    if (allocated(error)) return
    call check(error, s%format == snapshot_format%lammps_dump .and. s%n == 2 .and. s%n_frames == 2 .and. &
      s%frame == 2 .and. s%timestep == 200_i8, "the last of two frames")
    if (allocated(error)) return
    call check(error, all(s%id == [11_i8, 12_i8]) .and. all(s%type == [2, 1]), "ids and types")
    if (allocated(error)) return
    call check(error, all(s%x(:, 1) == [0.1_dp, 0.2_dp, 0.3_dp]) .and. all(s%x(:, 2) == [0.4_dp, 0.5_dp, 0.6_dp]), &
      "x y z from columns in any order")
    if (allocated(error)) return
    call check(error, s%has_velocity .and. all(s%v(:, 1) == [-1.0_dp, -2.0_dp, -3.0_dp]) .and. &
      s%has_omega .and. all(s%omega(:, 2) == [7.0_dp, 8.0_dp, 9.0_dp]), "velocities and omegas")
    if (allocated(error)) return
    call check(error, all(s%radius == [0.01_dp, 0.02_dp]) .and. s%has_mass .and. all(s%mass == [0.5_dp, 0.25_dp]), &
      "radii and masses")
    if (allocated(error)) return
    call check(error, s%has_box .and. all(s%lo == [-1.0_dp, -2.0_dp, 0.0_dp]) .and. &
      all(s%hi == [1.0_dp, 2.0_dp, 3.0_dp]) .and. all(s%periodic .eqv. [.true., .false., .true.]), &
      "box and periodic axes (pp)")
    if (allocated(error)) return
    call parse_snapshot(two_frames(), s, status, frame=1)
    call check(error, status%stat == demstep_stat%ok .and. s%n == 1 .and. s%timestep == 100_i8 .and. &
      s%id(1) == 7_i8 .and. .not. s%has_velocity, "frame 1")
    if (allocated(error)) return
    call parse_snapshot(two_frames(), s, status, frame=-1)
    call check(error, s%frame == 1, "frame -1: the one before the last")
    if (allocated(error)) return
    call parse_snapshot(two_frames(), s, status, frame=3)
    call check(error, status%stat == demstep_stat%invalid_input .and. &
      index(status%message, "frame: the file has 2 frames") == 1, "frame 3 refused: "//status%message)
  end subroutine test_dump

  subroutine test_dump_scaled(error)
    type(error_type), allocatable, intent(out) :: error
    type(snapshot_type) :: s
    type(demstep_status_type) :: status
    character(len=:), allocatable :: t
    t = "ITEM: TIMESTEP"//nl//"0"//nl//"ITEM: NUMBER OF ATOMS"//nl//"1"//nl// &
      "ITEM: BOX BOUNDS ff fs fm"//nl//"0 2"//nl//"-1 1"//nl//"10 20"//nl// &
      "ITEM: ATOMS type xs ys zs diameter"//nl//"2 0.5 0.25 0.1 0.004"//nl
    call parse_snapshot(t, s, status, type_density=[1000.0_dp, 2500.0_dp])
    call check(error, status%stat == demstep_stat%ok, "reads: "//status%message)
    if (allocated(error)) return
    ! x = lo + xs (hi - lo)
    call check(error, all(abs(s%x(:, 1) - [1.0_dp, -0.5_dp, 11.0_dp]) < 1.0e-15_dp*20), "scaled coordinates")
    if (allocated(error)) return
    call check(error, s%radius(1) == 0.002_dp .and. s%id(1) == 1_i8 .and. .not. any(s%periodic), &
      "diameter halved; ids 1..n; ff fs fm not periodic")
    if (allocated(error)) return
    ! mass 4/3 pi r^3 rho with the density of type 2 (1e-15: a few roundings)
    call check(error, s%has_mass .and. abs(s%mass(1) - 4*pi/3*0.002_dp**3*2500)/s%mass(1) < 1.0e-15_dp, &
      "mass from the density of its type")
    if (allocated(error)) return
    call parse_snapshot(t, s, status, type_density=[1000.0_dp])
    call check(error, index(status%message, "type_density: no density for particle type 2") == 1, &
      "a type without a density: "//status%message)
  end subroutine test_dump_scaled

  subroutine test_dump_bad(error)
    type(error_type), allocatable, intent(out) :: error
    character(len=:), allocatable :: head, t
    head = "ITEM: TIMESTEP"//nl//"0"//nl//"ITEM: NUMBER OF ATOMS"//nl//"2"//nl// &
      "ITEM: BOX BOUNDS pp pp pp"//nl//"0 1"//nl//"0 1"//nl//"0 1"//nl
    ! truncated: two atoms declared, one row
    call expect(head//"ITEM: ATOMS id x y z radius"//nl//"1 0.1 0.1 0.1 0.01"//nl, "line 10: truncated: " &
      //"frame 1 declares 2 atoms, the file ends after 1 of their rows")
    if (allocated(error)) return
    ! a row with a missing value
    call expect(head//"ITEM: ATOMS id x y z radius"//nl//"1 0.1 0.1 0.1 0.01"//nl//"2 0.2 0.2 0.01"//nl, &
      "line 11: expected 5 values, found 4")
    if (allocated(error)) return
    ! an unknown column
    call expect(head//"ITEM: ATOMS id x y z radius colour"//nl//"1 0.1 0.1 0.1 0.01 1"//nl// &
      "2 0.2 0.2 0.2 0.01 1"//nl, "line 9: unknown column 'colour'")
    if (allocated(error)) return
    ! no radius
    call expect(head//"ITEM: ATOMS id x y z"//nl//"1 0.1 0.1 0.1"//nl//"2 0.2 0.2 0.2"//nl, &
      "line 9: the columns need radius or diameter")
    if (allocated(error)) return
    ! not a number
    call expect(head//"ITEM: ATOMS id x y z radius"//nl//"1 0.1 0.1 0.1 0.01"//nl//"2 0.2 abc 0.2 0.01"//nl, &
      "line 11: column 'y': 'abc' is not a number")
    if (allocated(error)) return
    ! a negative radius
    call expect(head//"ITEM: ATOMS id x y z radius"//nl//"1 0.1 0.1 0.1 0.01"//nl//"2 0.2 0.2 0.2 -1"//nl, &
      "line 11: radius must be > 0")
    if (allocated(error)) return
    ! a triclinic box
    t = "ITEM: TIMESTEP"//nl//"0"//nl//"ITEM: NUMBER OF ATOMS"//nl//"0"//nl// &
      "ITEM: BOX BOUNDS xy xz yz pp pp pp"//nl//"0 1 0"//nl//"0 1 0"//nl//"0 1 0"//nl//"ITEM: ATOMS x y z radius"
    call expect(t, "line 5: a triclinic box")
    if (allocated(error)) return
    ! a bad atom count, a missing item
    call expect("ITEM: TIMESTEP"//nl//"0"//nl//"ITEM: NUMBER OF ATOMS"//nl//"two"//nl, &
      "line 4: the number of atoms: 'two' is not an integer")
    if (allocated(error)) return
    call expect("ITEM: TIMESTEP"//nl//"0"//nl//"ITEM: BOX BOUNDS pp pp pp"//nl, &
      "line 3: expected 'ITEM: NUMBER OF ATOMS'")
    if (allocated(error)) return
    call expect(head//"ITEM: ATOMS id x y z radius"//nl//"1 0 0 0 1"//nl//"2 0 0 0 1"//nl//"garbage"//nl, &
      "line 12: expected 'ITEM: TIMESTEP'")
  contains
    subroutine expect(text, start)
      character(len=*), intent(in) :: text, start
      type(snapshot_type) :: s
      type(demstep_status_type) :: status
      call parse_snapshot(text, s, status, format=snapshot_format%lammps_dump)
      call check(error, status%stat == demstep_stat%invalid_input .and. index(status%message, start) == 1, &
        "want '"//start//"', got '"//status%message//"'")
    end subroutine expect
  end subroutine test_dump_bad

  pure function data_file() result(t)
    character(len=:), allocatable :: t
    t = "LAMMPS data file written for demstep's tests"//nl//nl//"3 atoms"//nl//"2 atom types"//nl// &
      "0.0 1.0 xlo xhi"//nl//"-1.0 1.0 ylo yhi"//nl//"0.0 2.0 zlo zhi"//nl//nl// &
      "Masses"//nl//nl//"1 1.0"//nl//"2 2.0"//nl//nl// &
      "Atoms # sphere"//nl//nl//"5 1 0.002 2500 0.1 0.2 0.3 0 0 0"//nl//"3 2 0.004 1000 0.4 0.5 0.6 0 0 0"//nl// &
      "9 1 0.002 2500 0.7 0.8 0.9 1 0 0"//nl//nl// &
      "Velocities"//nl//nl//"9 1 2 3 4 5 6"//nl//"5 -1 -2 -3 0 0 0"//nl//"3 0 0 0 0 0 1"//nl
  end function data_file

  subroutine test_data(error)
    type(error_type), allocatable, intent(out) :: error
    type(snapshot_type) :: s
    type(demstep_status_type) :: status
    call parse_snapshot(data_file(), s, status)
    call check(error, status%stat == demstep_stat%ok, "reads: "//status%message)
    if (allocated(error)) return
    call check(error, s%format == snapshot_format%lammps_data .and. s%n == 3 .and. &
      all(s%id == [5_i8, 3_i8, 9_i8]) .and. all(s%type == [1, 2, 1]), "detected; ids and types")
    if (allocated(error)) return
    call check(error, all(s%radius == [0.001_dp, 0.002_dp, 0.001_dp]) .and. all(s%x(:, 3) == [0.7_dp, 0.8_dp, 0.9_dp]), &
      "radius = diameter/2, positions")
    if (allocated(error)) return
    call check(error, all(s%lo == [0.0_dp, -1.0_dp, 0.0_dp]) .and. all(s%hi == [1.0_dp, 1.0_dp, 2.0_dp]) .and. &
      .not. any(s%periodic), "box; periodicity unknown: none")
    if (allocated(error)) return
    ! velocities matched by id, not by order
    call check(error, all(s%v(:, 3) == [1.0_dp, 2.0_dp, 3.0_dp]) .and. all(s%v(:, 1) == [-1.0_dp, -2.0_dp, -3.0_dp]) &
      .and. all(s%omega(:, 2) == [0.0_dp, 0.0_dp, 1.0_dp]), "velocities by id")
    if (allocated(error)) return
    call check(error, s%has_mass .and. abs(s%mass(2) - 4*pi/3*0.002_dp**3*1000)/s%mass(2) < 1.0e-15_dp, &
      "mass from the density column")
  end subroutine test_data

  subroutine test_data_bad(error)
    type(error_type), allocatable, intent(out) :: error
    character(len=:), allocatable :: t
    t = data_file()
    call expect(t(:index(t, "9 1 0.002") - 1), "line 17: truncated: the Atoms section has 2 of the 3 rows")
    if (allocated(error)) return
    call expect(replace(t, "3 2 0.004 1000 0.4 0.5 0.6 0 0 0", "3 2 0.004 0.4 0.5 0.6"), &
      "line 17: an Atoms row of style sphere has 7 values")
    if (allocated(error)) return
    call expect(replace(t, "Atoms # sphere", "Atoms # atomic"), "line 14: atom style 'Atoms # atomic'")
    if (allocated(error)) return
    call expect(replace(t, "9 1 2 3 4 5 6", "8 1 2 3 4 5 6"), "line 22: atom id 8 is not in the Atoms section")
    if (allocated(error)) return
    call expect(replace(t, "3 atoms", "three atoms"), "line 3: the atom count 'three'")
    if (allocated(error)) return
    call expect(replace(t, "0.4 0.5 0.6", "0.4 x 0.6"), "line 17: column 'y': 'x' is not a number")
    if (allocated(error)) return
    call expect(replace(t, "3 2 0.004", "3 2 0"), "line 17: diameter must be > 0")
    if (allocated(error)) return
    call expect("title"//nl//nl//"3 atoms"//nl, "no Atoms section")
  contains
    subroutine expect(text, start)
      character(len=*), intent(in) :: text, start
      type(snapshot_type) :: s
      type(demstep_status_type) :: status
      call parse_snapshot(text, s, status, format=snapshot_format%lammps_data)
      call check(error, status%stat == demstep_stat%invalid_input .and. index(status%message, start) == 1, &
        "want '"//start//"', got '"//status%message//"'")
    end subroutine expect
  end subroutine test_data_bad

  pure function replace(t, old, new) result(r)
    character(len=*), intent(in) :: t, old, new
    character(len=:), allocatable :: r
    integer :: k
    k = index(t, old)
    r = t(:k-1)//new//t(k+len(old):)
  end function replace

  subroutine test_yade(error)
    type(error_type), allocatable, intent(out) :: error
    type(snapshot_type) :: s
    type(demstep_status_type) :: status
    call parse_snapshot("#format x_y_z_r"//nl//"0 0 0 0.5"//nl//"1.0 0 0 0.5"//nl, s, status)
    call check(error, status%stat == demstep_stat%ok .and. s%format == snapshot_format%yade_text .and. &
      s%n == 2 .and. s%x(1, 2) == 1.0_dp .and. all(s%radius == 0.5_dp) .and. .not. s%has_box, "x_y_z_r")
    if (allocated(error)) return
    ! Yade's material ids count from 0 (a real export of two materials holds 0 and 1)
    call parse_snapshot("#format x_y_z_r_matId"//nl//"# a comment"//nl//"0 0 0 0.5 3"//nl, s, status, &
      type_density=[1.0_dp, 1.0_dp, 1.0_dp, 3000.0_dp])
    call check(error, status%stat == demstep_stat%ok .and. s%type(1) == 4 .and. s%has_mass, &
      "matId + 1 is the type")
    if (allocated(error)) return
    call parse_snapshot("#format x_y_z_r_attrs"//nl//"# x y z r attr1 attr2"//nl//"0 0 0 0.5 7 8"//nl// &
      "1 1 1 0.25 7 8"//nl, s, status)
    call check(error, status%stat == demstep_stat%ok .and. s%n == 2 .and. s%radius(2) == 0.25_dp, "attrs skipped")
    if (allocated(error)) return
    ! no header: rows of four numbers
    call parse_snapshot("0 0 0 0.5"//nl//"1 1 1 0.5"//nl, s, status)
    call check(error, status%stat == demstep_stat%ok .and. s%format == snapshot_format%yade_text, &
      "detected without a header")
  end subroutine test_yade

  subroutine test_yade_bad(error)
    type(error_type), allocatable, intent(out) :: error
    call expect("#format x_y_z_r"//nl//"0 0 0 0.5"//nl//"1 1 1"//nl, "line 3: expected 4 values (x_y_z_r), found 3")
    if (allocated(error)) return
    call expect("#format x_y_z_r_matId"//nl//"0 0 0 0.5"//nl, "line 2: expected 5 values (x_y_z_r_matId)")
    if (allocated(error)) return
    call expect("#format x_y_z_r_attrs"//nl//"0 0 0 0.5 1 2"//nl//"0 0 0 0.5 1"//nl, &
      "line 3: expected 6 values (x y z r and the attributes), found 5")
    if (allocated(error)) return
    call expect("#format x_y_z"//nl//"0 0 0"//nl, "line 1: unknown Yade format 'x_y_z'")
    if (allocated(error)) return
    call expect("#format x_y_z_r"//nl//"0 0 zero 0.5"//nl, "line 2: column 'z': 'zero' is not a number")
    if (allocated(error)) return
    call expect("#format x_y_z_r"//nl//"0 0 0 0"//nl, "line 2: r must be > 0")
    if (allocated(error)) return
    block
      type(snapshot_type) :: s
      type(demstep_status_type) :: status
      call parse_snapshot("hello"//nl//"world"//nl, s, status)
      call check(error, index(status%message, "cannot tell the format") == 1, "no format detected")
    end block
  contains
    subroutine expect(text, start)
      character(len=*), intent(in) :: text, start
      type(snapshot_type) :: s
      type(demstep_status_type) :: status
      call parse_snapshot(text, s, status)
      call check(error, status%stat == demstep_stat%invalid_input .and. index(status%message, start) == 1, &
        "want '"//start//"', got '"//status%message//"'")
    end subroutine expect
  end subroutine test_yade_bad

  subroutine test_files(error)
    type(error_type), allocatable, intent(out) :: error
    type(snapshot_type) :: s
    type(demstep_status_type) :: status
    character(len=*), parameter :: path = work_dir//"/snap.yade"
    call write_file(path, [character(len=20) :: "#format x_y_z_r", "0 0 0 0.5", "0 0 0"])
    call read_snapshot(path, s, status)
    call check(error, index(status%message, path//": line 3: expected 4 values") == 1, status%message)
    if (allocated(error)) return
    call read_snapshot(work_dir//"/no_such_file", s, status)
    call check(error, status%stat == demstep_stat%io_error .and. index(status%message, work_dir//"/no_such_file: ") &
      == 1, "missing file: "//status%message)
  end subroutine test_files

  !> The dump and data file LIGGGHTS itself wrote (make_fixtures.sh beside them):
  !> the same three spheres read both ways agree.
  subroutine test_liggghts(error)
    type(error_type), allocatable, intent(out) :: error
    type(snapshot_type) :: d, w
    type(demstep_status_type) :: status
    call read_snapshot("test/data/liggghts/dump.liggghts", d, status)
    call check(error, status%stat == demstep_stat%ok, "dump: "//status%message)
    if (allocated(error)) return
    call check(error, d%format == snapshot_format%lammps_dump .and. d%n_frames == 3 .and. d%timestep == 100_i8 &
      .and. d%n == 3 .and. all(d%periodic .eqv. [.true., .true., .false.]), "dump: last of 3 frames, pp pp ff")
    if (allocated(error)) return
    call read_snapshot("test/data/liggghts/data.liggghts", w, status)
    call check(error, status%stat == demstep_stat%ok, "data: "//status%message)
    if (allocated(error)) return
    call check(error, w%format == snapshot_format%lammps_data .and. all(w%id == d%id) .and. &
      all(w%type == d%type) .and. all(w%radius == d%radius), "same ids, types, radii")
    if (allocated(error)) return
    ! the dump prints 6 significant digits: positions and masses agree to 5e-6 relative
    call check(error, all(abs(w%x - d%x) <= 5.0e-6_dp*0.01_dp) .and. all(abs(w%mass - d%mass) <= 5.0e-6_dp*d%mass), &
      "positions and masses (mass from diameter and density in the data file)")
    if (allocated(error)) return
    call check(error, w%v(1, 1) == 0.5_dp .and. d%v(1, 1) == 0.5_dp .and. w%omega(3, 3) == 10.0_dp .and. &
      d%omega(3, 3) == 10.0_dp, "velocities and angular velocities")
  end subroutine test_liggghts

  !> A dump frame of 8 valid rows whose header declares `count` atoms.
  pure function eight_rows(count) result(t)
    character(len=*), intent(in) :: count
    character(len=:), allocatable :: t
    integer :: i
    character(len=40) :: row
    t = "ITEM: TIMESTEP"//nl//"0"//nl//"ITEM: NUMBER OF ATOMS"//nl//count//nl// &
      "ITEM: BOX BOUNDS ff ff ff"//nl//"0 1"//nl//"0 1"//nl//"0 1"//nl//"ITEM: ATOMS id type x y z radius"//nl
    do i = 1, 8
      write(row, '(i0, a, f3.1, a)') i, " 1 ", 0.1*i, " 0.1 0.1 0.01"
      t = t//trim(row)//nl
    end do
  end function eight_rows

  !> The message of a refused text (format given), checked to be one line.
  subroutine refusal(error, text, format, message)
    type(error_type), allocatable, intent(out) :: error
    character(len=*), intent(in) :: text
    integer, intent(in) :: format
    character(len=:), allocatable, intent(out) :: message
    type(snapshot_type) :: s
    type(demstep_status_type) :: status
    call parse_snapshot(text, s, status, format=format)
    message = ""
    if (allocated(status%message)) message = status%message
    call check(error, status%stat == demstep_stat%invalid_input .and. index(message, nl) == 0, &
      "refused in one line: '"//message//"'")
  end subroutine refusal

  !> Expect the exact message for a refused text.
  subroutine expect_exact(error, text, format, expected)
    type(error_type), allocatable, intent(out) :: error
    character(len=*), intent(in) :: text, expected
    integer, intent(in) :: format
    character(len=:), allocatable :: message
    call refusal(error, text, format, message)
    if (allocated(error)) return
    call check(error, message == expected, "want '"//expected//"', got '"//message//"'")
  end subroutine expect_exact

  !> The count was added to the line number before it was compared (it wrapped
  !> around, the reader went out of bounds): now compared with the lines left.
  subroutine test_dump_counts(error)
    type(error_type), allocatable, intent(out) :: error
    type(snapshot_type) :: s
    type(demstep_status_type) :: status
    integer :: i
    character(len=10), parameter :: counts(3) = ["2147483647", "2147483646", "2147483640"]
    call parse_snapshot(eight_rows("8"), s, status)
    call check(error, status%stat == demstep_stat%ok .and. s%n == 8 .and. s%x(1, 8) == 0.8_dp, &
      "the 8-row dump itself reads")
    if (allocated(error)) return
    do i = 1, size(counts)
      call expect_exact(error, eight_rows(counts(i)), snapshot_format%lammps_dump, "line 17: truncated: frame 1 " &
        //"declares "//counts(i)//" atoms, the file ends after 8 of their rows")
      if (allocated(error)) return
    end do
    call expect_exact(error, eight_rows("2147483648"), snapshot_format%lammps_dump, &
      "line 4: the number of atoms must lie in [0, 2147483647]")
    if (allocated(error)) return
    call expect_exact(error, eight_rows("99999999999999999999"), snapshot_format%lammps_dump, &
      "line 4: the number of atoms: '99999999999999999999' lies beyond the 64-bit integer range")
    if (allocated(error)) return
    ! a huge count in the first of two frames swallows the second: refused too
    call expect_exact(error, eight_rows("2147483647")//eight_rows("8"), snapshot_format%lammps_dump, &
      "line 34: truncated: frame 1 declares 2147483647 atoms, the file ends after 25 of their rows")
  end subroutine test_dump_counts

  !> The count is checked against the rows under Atoms before the snapshot is
  !> allocated (17 GB were asked for 2147483647 atoms before).
  subroutine test_data_counts(error)
    type(error_type), allocatable, intent(out) :: error
    type(snapshot_type) :: s
    type(demstep_status_type) :: status
    character(len=:), allocatable :: t
    integer :: i
    character(len=10), parameter :: counts(3) = [character(len=10) :: "2147483647", "2147483646", "100000000"]
    t = "LAMMPS data file"//nl//nl//"2 atoms"//nl//nl//"0 1 xlo xhi"//nl//"0 1 ylo yhi"//nl//"0 1 zlo zhi"// &
      nl//nl//"Atoms # sphere"//nl//nl//"1 1 0.02 1000 0.1 0.1 0.1"//nl//"2 1 0.02 1000 0.2 0.1 0.1"//nl
    call parse_snapshot(t, s, status)
    call check(error, status%stat == demstep_stat%ok .and. s%n == 2, "the 2-atom file itself reads")
    if (allocated(error)) return
    do i = 1, size(counts)
      call expect_exact(error, replace(t, "2 atoms", trim(counts(i))//" atoms"), snapshot_format%lammps_data, &
        "line 12: truncated: the Atoms section has 2 of the "//trim(counts(i))//" rows the header declares (line 3)")
      if (allocated(error)) return
    end do
    ! another section after the rows: the message is at its keyword
    call expect_exact(error, replace(t, "2 atoms", "5 atoms")//nl//"Velocities"//nl//nl//"1 0 0 0 0 0 0"//nl, &
      snapshot_format%lammps_data, "line 14: the Atoms section has 2 rows, the header declares 5 atoms (line 3)")
    if (allocated(error)) return
    call expect_exact(error, replace(t, "2 atoms", "4294967297 atoms"), snapshot_format%lammps_data, &
      "line 3: the atom count '4294967297' is not an integer in [0, 2147483647]")
    if (allocated(error)) return
    call expect_exact(error, t//nl//"Atoms"//nl//nl//"3 1 0.02 1000 0.3 0.1 0.1"//nl, snapshot_format%lammps_data, &
      "line 14: a second Atoms section (the first on line 9)")
  end subroutine test_data_counts

  !> Ids and types were read as reals and rounded: 4294967297 became type 1,
  !> 1.5 type 2, 0.6 type 1; a matId of 1e300 or 0.4 became material 0.
  subroutine test_integer_columns(error)
    type(error_type), allocatable, intent(out) :: error
    character(len=:), allocatable :: d, y
    integer, parameter :: dump = snapshot_format%lammps_dump, data = snapshot_format%lammps_data, &
      yade = snapshot_format%yade_text
    ! dump, row 2 (line 11): "2 1 0.2 0.1 0.1 0.01"
    d = eight_rows("8")
    call expect_exact(error, replace(d, "2 1 0.2", "2 4294967297 0.2"), dump, &
      "line 11: column 'type': '4294967297' must lie in [1, 2147483647]")
    if (allocated(error)) return
    call expect_exact(error, replace(d, "2 1 0.2", "2 1.5 0.2"), dump, "line 11: column 'type': '1.5' is not an integer")
    if (allocated(error)) return
    call expect_exact(error, replace(d, "2 1 0.2", "2 0.6 0.2"), dump, "line 11: column 'type': '0.6' is not an integer")
    if (allocated(error)) return
    call expect_exact(error, replace(d, "2 1 0.2", "2 0 0.2"), dump, "line 11: column 'type': '0' must lie in " &
      //"[1, 2147483647]")
    if (allocated(error)) return
    call expect_exact(error, replace(d, "2 1 0.2", "1.5 1 0.2"), dump, "line 11: column 'id': '1.5' is not an integer")
    if (allocated(error)) return
    call expect_exact(error, replace(d, "2 1 0.2", "9223372036854775808 1 0.2"), dump, "line 11: column 'id': " &
      //"'9223372036854775808' must lie in [1, 9223372036854775807]")
    if (allocated(error)) return
    ! data file, row 2 (line 17): "3 2 0.004 1000 ..."
    d = data_file()
    call expect_exact(error, replace(d, "3 2 0.004", "3 4294967297 0.004"), data, &
      "line 17: column 'type': '4294967297' must lie in [1, 2147483647]")
    if (allocated(error)) return
    call expect_exact(error, replace(d, "3 2 0.004", "3 1.5 0.004"), data, "line 17: column 'type': '1.5' is not " &
      //"an integer")
    if (allocated(error)) return
    call expect_exact(error, replace(d, "3 2 0.004", "3 0.6 0.004"), data, "line 17: column 'type': '0.6' is not " &
      //"an integer")
    if (allocated(error)) return
    call expect_exact(error, replace(d, "3 2 0.004", "1.5 2 0.004"), data, "line 17: column 'id': '1.5' is not " &
      //"an integer")
    if (allocated(error)) return
    call expect_exact(error, replace(d, "5 -1 -2 -3", "5.0 -1 -2 -3"), data, "line 23: column 'id': '5.0' is not " &
      //"an integer")
    if (allocated(error)) return
    ! Yade: matId counts from 0 (the type is matId + 1, at most huge)
    y = "#format x_y_z_r_matId"//nl//"0 0 0 0.5 1"//nl//"1 0 0 0.5 0"//nl
    call expect_exact(error, replace(y, "0.5 1", "0.5 4294967296"), yade, &
      "line 2: column 'matId': '4294967296' must lie in [0, 2147483646]")
    if (allocated(error)) return
    call expect_exact(error, replace(y, "0.5 1", "0.5 1e300"), yade, "line 2: column 'matId': '1e300' is not an integer")
    if (allocated(error)) return
    call expect_exact(error, replace(y, "0.5 1", "0.5 0.4"), yade, "line 2: column 'matId': '0.4' is not an integer")
    if (allocated(error)) return
    call expect_exact(error, replace(y, "0.5 1", "0.5 -1"), yade, "line 2: column 'matId': '-1' must lie in " &
      //"[0, 2147483646]")
    if (allocated(error)) return
    ! an attribute column is not a matId: any number
    block
      type(snapshot_type) :: s
      type(demstep_status_type) :: status
      call parse_snapshot("#format x_y_z_r_attrs"//nl//"0 0 0 0.5 0.4"//nl, s, status)
      call check(error, status%stat == demstep_stat%ok .and. s%type(1) == 1, "attrs: 0.4 is an attribute")
      if (allocated(error)) return
      call parse_snapshot("#format x_y_z_r_attrs"//nl//"0 0 0 0.5 x"//nl, s, status)
      call check(error, status%message == "line 2: value 5: 'x' is not a number", &
        "attrs: the fifth value is no matId: "//status%message)
    end block
  end subroutine test_integer_columns

  !> The readers' integers: exact to the ends of the 64-bit range, beyond it
  !> flagged, any other text refused.
  subroutine test_integer_of(error)
    type(error_type), allocatable, intent(out) :: error
    integer(i8) :: v
    logical :: ok, big
    integer :: i
    character(len=24), parameter :: good(5) = [character(len=24) :: "0", "+7", "-7", "9223372036854775807", &
      "-9223372036854775808"]
    integer(i8), parameter :: values(5) = [0_i8, 7_i8, -7_i8, huge(1_i8), -huge(1_i8) - 1_i8]
    character(len=24), parameter :: beyond(3) = [character(len=24) :: "9223372036854775808", &
      "-9223372036854775809", "99999999999999999999999"]
    character(len=8), parameter :: bad(9) = [character(len=8) :: "", "+", "-", "1.0", "1e3", " 1", "0x10", "12a", &
      "--1"]
    do i = 1, size(good)
      call integer_of(trim(good(i)), v, ok, big)
      call check(error, ok .and. .not. big .and. v == values(i), "'"//trim(good(i))//"' read exactly")
      if (allocated(error)) return
    end do
    do i = 1, size(beyond)
      call integer_of(trim(beyond(i)), v, ok, big)
      call check(error, .not. ok .and. big .and. v == 0_i8, "'"//trim(beyond(i))//"': beyond the range")
      if (allocated(error)) return
    end do
    do i = 1, size(bad)
      ! (len_trim keeps the leading blank of " 1")
      call integer_of(bad(i)(:len_trim(bad(i))), v, ok, big)
      call check(error, .not. ok .and. .not. big, "'"//trim(bad(i))//"': not an integer")
      if (allocated(error)) return
    end do
    call check(error, printable("a"//achar(13)//"b"//achar(9)//"c"//achar(0)//achar(255)//nl) == "a?b c???", &
      "printable: control and non-ASCII bytes as ?, a tab as a blank")
  end subroutine test_integer_of

  subroutine test_duplicate_ids(error)
    type(error_type), allocatable, intent(out) :: error
    ! dump: rows 1..8 on lines 10..17; row 5 repeats id 3
    call expect_exact(error, replace(eight_rows("8"), "5 1 0.5", "3 1 0.5"), snapshot_format%lammps_dump, &
      "line 14: atom id 3 appears twice (first on line 12)")
    if (allocated(error)) return
    ! data file: Atoms rows on lines 16..18, Velocities rows on 22..24
    call expect_exact(error, replace(data_file(), "9 1 0.002", "5 1 0.002"), snapshot_format%lammps_data, &
      "line 18: atom id 5 appears twice (first on line 16)")
    if (allocated(error)) return
    call expect_exact(error, replace(data_file(), "3 0 0 0 0 0 1", "9 0 0 0 0 0 1"), snapshot_format%lammps_data, &
      "line 24: atom id 9 appears twice in the Velocities section (first on line 22)")
  end subroutine test_duplicate_ids

end module test_snapshot
