!> Particle snapshots from the files DEM codes write: LAMMPS/LIGGGHTS dump
!> files, LAMMPS/LIGGGHTS data files of the `sphere` atom style, and Yade's
!> text export.
!>
!> - Dump (`lammps_dump`): frames of `ITEM: TIMESTEP`, `ITEM: NUMBER OF ATOMS`,
!>   `ITEM: BOX BOUNDS xx yy zz` (`pp` marks a periodic axis; `ff`, `fs`, `fm`,
!>   `ss`, ... do not), `ITEM: ATOMS <columns>` and one row per atom. Columns in
!>   any order: `id`, `type`, `x y z` (or scaled `xs ys zs`, or unwrapped `xu yu
!>   zu`), `vx vy vz`, `radius` or `diameter`, `mass`, `density`, `omegax omegay
!>   omegaz`, `mol`; LAMMPS' other per-atom columns (`fx`, `tqx`, `ix`, `q`, `c_*`,
!>   `f_*`, `v_*`, ...) are skipped; any other name is refused. The last frame is
!>   read unless another is asked for. `mol` is read as LIGGGHTS `fix
!>   multisphere` writes it: the atom's rigid body (`atom->molecule` is the
!>   fix's body id, fix_multisphere.cpp:1343 in CFDEMproject/LIGGGHTS-PUBLIC
!>   3d5c00f; -1 or 0 for a sphere on its own), and then the `mass` column is
!>   the whole body's mass on each member (`body_mass`; the template's mass,
!>   every member's rmass at insertion, particleToInsert_multisphere.cpp:203),
!>   which must be the same on all of a body's members.
!> - Data file (`lammps_data`): the header counts (`N atoms`, `xlo xhi`, ...),
!>   the `Atoms` section of atom style sphere (`id type diameter density x y z`,
!>   optionally `ix iy iz`) and the optional `Velocities` section (`id vx vy vz
!>   wx wy wz`); other sections are skipped. A data file does not say which axes
!>   are periodic (the input script does): all are marked non-periodic.
!> - Yade text (`yade_text`): `#format x_y_z_r` (the default), `x_y_z_r_matId`
!>   (the type is the material id plus 1: Yade counts its materials from 0) or
!>   `x_y_z_r_attrs` (extra columns skipped; a column `clumpId` or
!>   `b.clumpId`, named in the comment line `# x y z r NAMES` that Yade's
!>   `export.textExt(..., comment='NAMES', attrs=[...])` writes, gives each
!>   sphere's clump: `body` = clumpId + 1, 0 for Yade's -1, a sphere on its own);
!>   `#` lines are comments.
!>
!> Masses: a `mass` column, else `4/3 pi r^3 density` from a `density` column
!> (or the data file's), else from a density per type given by the caller; with
!> none of them `has_mass` is false. Every reader passes over the text a fixed
!> number of times (linear in its size) and reports a bad file in one line as
!> `FILE: line N: what is wrong` (`line N: column 'type': ...` for a value).
!>
!> Bounded by the text: a header's atom count is compared with the rows
!> present (without arithmetic that could overflow), and every row's field
!> count is checked, before anything is allocated; the arrays then take at
!> most about 14 bytes per byte of rows. Ids and types (a dump's `id`, `type`;
!> a data file's; Yade's `matId`) are read as integers, never rounded: ids in
!> [1, 2^63-1], types in [1, 2^31-1], matIds in [0, 2^31-2]; an id met twice
!> (in a frame, in `Atoms`, in `Velocities`) is refused at its second line.
module demstep_snapshot
  use demstep_kinds, only: dp, i8, pi
  use demstep_status, only: demstep_status_type, demstep_stat, set_status
  use demstep_text, only: int_text, real_text, integer_of, printable, read_text_file, lowercase, is_letter
  use demstep_decimal, only: real_of
  use, intrinsic :: ieee_arithmetic, only: ieee_is_finite
  use demstep_words, only: word_index, word_of
  implicit none
  private

  public :: read_snapshot, parse_snapshot, snapshot_format_of, snapshot_masses_from_types

  !> The formats, as components of a parameter.
  type, public :: snapshot_format_enum
    !> Decide from the text (see [[snapshot_format_of]]).
    integer :: auto = 0
    !> LAMMPS/LIGGGHTS dump file.
    integer :: lammps_dump = 1
    !> LAMMPS/LIGGGHTS data file, atom style sphere.
    integer :: lammps_data = 2
    !> Yade `export.text`/`textExt`.
    integer :: yade_text = 3
  end type snapshot_format_enum
  !> The formats by name.
  type(snapshot_format_enum), parameter, public :: snapshot_format = snapshot_format_enum()
  !> Their words, indexed by code (`snapshot_format_from_name`, `snapshot_format_name`).
  character(len=*), parameter, public :: snapshot_format_names(0:3) = [character(len=11) :: &
    "auto", "lammps_dump", "lammps_data", "yade_text"]
  public :: snapshot_format_from_name, snapshot_format_name

  !> Particles read from a snapshot.
  type, public :: snapshot_type
    !> The format read (`snapshot_format%...`).
    integer :: format = 0
    !> Number of particles.
    integer :: n = 0
    !> Identifiers and types (1 and 1..n when the file has none).
    integer(i8), allocatable :: id(:)
    integer, allocatable :: type(:)
    !> Positions, velocities and angular velocities, 3 by n (0 where absent).
    real(dp), allocatable :: x(:, :), v(:, :), omega(:, :)
    !> Radii.
    real(dp), allocatable :: radius(:)
    !> Masses and densities (0 where unknown).
    real(dp), allocatable :: mass(:), density(:)
    !> Rigid body (clump) of each particle, 0 for none (`has_body`: the file
    !> gave them; for `bodies_from_members`).
    integer, allocatable :: body(:)
    logical :: has_body = .false.
    !> The `mass` of a body's members is the body's mass (a LIGGGHTS
    !> multisphere dump's `mol` and `mass` columns).
    logical :: body_mass = .false.
    !> Which optional data the file had.
    logical :: has_velocity = .false., has_omega = .false., has_mass = .false., has_density = .false.
    !> Box bounds (0 for Yade, which writes none) and periodic axes.
    real(dp) :: lo(3) = 0.0_dp, hi(3) = 0.0_dp
    logical :: has_box = .false.
    logical :: periodic(3) = .false.
    !> Dump: the timestep and frame read (1-based) and the number of frames.
    integer(i8) :: timestep = 0_i8
    integer :: frame = 0, n_frames = 0
  end type snapshot_type

  character(len=*), parameter :: lf = achar(10), cr = achar(13), tab = achar(9)

  !> The lines of a text: start and end (exclusive of the newline) of each.
  !> The low 32 bits of a 64-bit integer; each of its four bytes' top bit;
  !> four newlines (for `byte_mask`).
  integer(i8), parameter :: low_half = int(z'FFFFFFFF', i8), top_bits = int(z'80808080', i8), &
    newlines = int(z'0A0A0A0A', i8)

  type :: lines_type
    integer :: n = 0
    integer, allocatable :: first(:), last(:)
  end type lines_type

contains

  !> Read a snapshot file. `format` (default auto), `frame` (dump: 1-based,
  !> default 0 = the last; negative counts from the end) and `type_density`
  !> (density per type, for masses) as for [[parse_snapshot]]. Status
  !> `io_error` for an unreadable file, `invalid_input` for a bad one; the
  !> message starts with `path: `.
  subroutine read_snapshot(path, snapshot, status, format, frame, type_density)
    !> File name.
    character(len=*), intent(in) :: path
    type(snapshot_type), intent(out) :: snapshot
    type(demstep_status_type), intent(out) :: status
    integer, intent(in), optional :: format, frame
    real(dp), intent(in), optional :: type_density(:)
    character(len=:), allocatable :: text
    call read_text_file(path, text, status)
    if (status%stat == demstep_stat%ok) call parse_snapshot(text, snapshot, status, format, frame, type_density)
    if (status%stat /= demstep_stat%ok) status%message = path//": "//status%message
  end subroutine read_snapshot

  !> The format of a snapshot's text: a dump starts with `ITEM:`, a Yade export
  !> with `#format`; a data file has a header line `N atoms`; Yade's default
  !> layout is also recognised by rows of 4 numbers. 0 (auto) when none fits.
  pure integer function snapshot_format_of(text) result(format)
    !> The file's text.
    character(len=*), intent(in) :: text
    character(len=:), allocatable :: s
    integer :: k, nf, first, last, next
    integer :: a(64), b(64)
    format = snapshot_format%auto
    ! line by line (as split_lines cuts them) up to the first line that decides
    next = 1
    k = 0
    do while (next <= len(text))
      first = next
      last = index(text(first:), lf) + first - 2
      if (last < first - 1) last = len(text)
      next = last + 2
      if (last >= first) then
        if (text(last:last) == cr) last = last - 1
      end if
      k = k + 1
      s = lowercase(trim(adjustl(text(first:last))))
      if (len(s) == 0) cycle
      if (index(s, "item:") == 1) then
        format = snapshot_format%lammps_dump
      else if (index(s, "#format") == 1) then
        format = snapshot_format%yade_text
      else if (k == 1) then
        ! a data file's first line is a title; look for the atoms count
        cycle
      else
        call fields(s, a, b, nf)
        if (nf == 2) then
          if (s(a(2):b(2)) == "atoms") format = snapshot_format%lammps_data
        end if
        if (format == snapshot_format%auto .and. nf == 4 .and. s(1:1) /= "#") &
          format = snapshot_format%yade_text
      end if
      if (format /= snapshot_format%auto) return
      if (k > 50) return
    end do
  end function snapshot_format_of

  !> Parse a snapshot's text (see the module's notes). Status `invalid_input`
  !> with `line N: what is wrong` (or `what is wrong` for the file as a whole).
  subroutine parse_snapshot(text, snapshot, status, format, frame, type_density)
    !> The file's text.
    character(len=*), intent(in) :: text
    type(snapshot_type), intent(out) :: snapshot
    type(demstep_status_type), intent(out) :: status
    !> `snapshot_format%...` (default auto).
    integer, intent(in), optional :: format
    !> Dump frame: 1-based, 0 (default) the last, -1 the one before, ...
    integer, intent(in), optional :: frame
    !> Density of each particle type (index = type), for the masses.
    real(dp), intent(in), optional :: type_density(:)
    type(lines_type) :: lines
    integer :: f, fr
    f = snapshot_format%auto
    if (present(format)) f = format
    fr = 0
    if (present(frame)) fr = frame
    if (f == snapshot_format%auto) f = snapshot_format_of(text)
    call split_lines(text, lines)
    select case (f)
    case (snapshot_format%lammps_dump)
      call parse_dump(text, lines, fr, snapshot, status)
    case (snapshot_format%lammps_data)
      call parse_data(text, lines, snapshot, status)
    case (snapshot_format%yade_text)
      call parse_yade(text, lines, snapshot, status)
    case (snapshot_format%auto)
      call set_status(status, demstep_stat%invalid_input, "cannot tell the format (not a LAMMPS " &
        //"dump, data file or Yade text export); name it")
      return
    case default
      call set_status(status, demstep_stat%invalid_input, "unknown snapshot format code "//int_text(f))
      return
    end select
    if (status%stat /= demstep_stat%ok) return
    snapshot%format = f
    if (present(type_density)) then
      call snapshot_masses_from_types(snapshot, type_density, status)
    else
      call snapshot_masses_from_types(snapshot, [real(dp) ::], status)
    end if
  end subroutine parse_snapshot

  !> Masses of a snapshot that has none: `4/3 pi r^3 density` from its density
  !> column, else from `type_density` (index = type) when that is not empty.
  !> Leaves `has_mass` false when neither is there. Status `invalid_input`:
  !> `type_density: no density for particle type T (particle ID)`,
  !> `density: must be > 0 for every particle`, or `particle ID: the mass ...
  !> is not a finite number > 0` (r^3 beyond the double range).
  pure subroutine snapshot_masses_from_types(snapshot, type_density, status)
    type(snapshot_type), intent(inout) :: snapshot
    !> Density of each particle type; empty: none.
    real(dp), intent(in) :: type_density(:)
    type(demstep_status_type), intent(out) :: status
    integer :: i
    status%stat = demstep_stat%ok
    if (snapshot%has_mass) return
    if (.not. snapshot%has_density .and. size(type_density) > 0) then
      do i = 1, snapshot%n
        if (snapshot%type(i) < 1 .or. snapshot%type(i) > size(type_density)) then
          call set_status(status, demstep_stat%invalid_input, "no density for particle " &
            //"type "//int_text(snapshot%type(i))//" (particle "//int_text(snapshot%id(i))//")", where="type_density")
          return
        end if
        snapshot%density(i) = type_density(snapshot%type(i))
      end do
      snapshot%has_density = .true.
    end if
    if (snapshot%has_density) then
      if (.not. all(snapshot%density > 0.0_dp)) then
        call set_status(status, demstep_stat%invalid_input, "must be > 0 for every particle", where="density")
        return
      end if
      snapshot%mass = (4.0_dp*pi/3.0_dp)*snapshot%radius**3*snapshot%density
      ! a radius near the double range's edge: r^3 overflows or underflows
      do i = 1, snapshot%n
        if (.not. (ieee_is_finite(snapshot%mass(i)) .and. snapshot%mass(i) > 0.0_dp)) then
          call set_status(status, demstep_stat%invalid_input, "particle "//int_text(snapshot%id(i))//": the " &
            //"mass 4/3 pi r^3 density of r = "//real_text(snapshot%radius(i))//" and density "// &
            real_text(snapshot%density(i))//" is not a finite number > 0")
          return
        end if
      end do
      snapshot%has_mass = .true.
    end if
  end subroutine snapshot_masses_from_types

  ! ---------------------------------------------------------------- dump files

  subroutine parse_dump(text, lines, frame, s, status)
    character(len=*), intent(in) :: text
    type(lines_type), intent(in) :: lines
    integer, intent(in) :: frame
    type(snapshot_type), intent(out) :: s
    type(demstep_status_type), intent(out) :: status
    integer, allocatable :: starts(:)
    integer :: k, n_frames, natoms, want
    character(len=:), allocatable :: l
    ! one pass: the frames' first lines, each frame's rows skipped by count
    allocate(starts(16))
    n_frames = 0
    k = 1
    do while (k <= lines%n)
      l = trim(adjustl(line_of(text, lines, k)))
      if (len(l) == 0) then
        k = k + 1
        cycle
      end if
      if (l /= "ITEM: TIMESTEP") then
        call fail_at(status, k, "expected 'ITEM: TIMESTEP' (the start of a frame), found '"//clipped(l)//"'")
        return
      end if
      n_frames = n_frames + 1
      if (n_frames > size(starts)) call grow(starts)
      starts(n_frames) = k
      call frame_size(k, natoms)
      if (status%stat /= demstep_stat%ok) return
      ! TIMESTEP, value, NUMBER OF ATOMS, value, BOX BOUNDS, 3 lines, ATOMS, rows
      ! (compared without adding to the count: a huge count cannot wrap around)
      if (natoms > lines%n - (k + 8)) then
        call fail_at(status, lines%n, "truncated: frame "//int_text(n_frames)//" declares "//int_text(natoms)// &
          " atoms, the file ends after "//int_text(max(0, lines%n - (k + 8)))//" of their rows")
        return
      end if
      k = k + 9 + natoms
    end do
    if (n_frames == 0) then
      call set_status(status, demstep_stat%invalid_input, "no frame (empty dump file)")
      return
    end if
    want = frame
    if (want <= 0) want = n_frames + frame
    if (want < 1 .or. want > n_frames) then
      call set_status(status, demstep_stat%invalid_input, "the file has "//int_text(n_frames)// &
        " frames (1 to "//int_text(n_frames)//", 0 the last), asked for "//int_text(frame), where="frame")
      return
    end if
    s%n_frames = n_frames
    s%frame = want
    call read_frame(starts(want))
  contains


    !> Check a frame's header from its TIMESTEP line; the atom count.
    subroutine frame_size(k0, count)
      integer, intent(in) :: k0
      integer, intent(out) :: count
      integer(i8) :: c
      count = 0
      status%stat = demstep_stat%ok
      call expect_item(k0 + 2, "ITEM: NUMBER OF ATOMS")
      if (status%stat /= demstep_stat%ok) return
      call integer_line(k0 + 3, "the number of atoms", c)
      if (status%stat /= demstep_stat%ok) return
      if (c < 0 .or. c > huge(1)) then
        call fail_at(status, k0 + 3, "the number of atoms must lie in [0, "//int_text(huge(1))//"]")
        return
      end if
      count = int(c)
      call expect_item(k0 + 4, "ITEM: BOX BOUNDS")
      if (status%stat /= demstep_stat%ok) return
      call expect_item(k0 + 8, "ITEM: ATOMS")
    end subroutine frame_size

    subroutine expect_item(k0, item)
      integer, intent(in) :: k0
      character(len=*), intent(in) :: item
      if (k0 > lines%n) then
        call fail_at(status, lines%n, "truncated: the file ends before '"//item//"'")
      else if (index(adjustl(line_of(text, lines, k0)), item) /= 1) then
        call fail_at(status, k0, "expected '"//item//"', found '"//clipped(trim(adjustl(line_of(text, lines, k0))))//"'")
      else
        status%stat = demstep_stat%ok
      end if
    end subroutine expect_item

    subroutine integer_line(k0, what, value)
      integer, intent(in) :: k0
      character(len=*), intent(in) :: what
      integer(i8), intent(out) :: value
      character(len=:), allocatable :: t
      logical :: ok, too_large
      value = 0
      if (k0 > lines%n) then
        call fail_at(status, lines%n, "truncated: the file ends before "//what)
        return
      end if
      t = trim(adjustl(line_of(text, lines, k0)))
      call integer_of(t, value, ok, too_large)
      if (too_large) then
        call fail_at(status, k0, what//": '"//clipped(t)//"' lies beyond the 64-bit integer range")
        return
      else if (.not. ok) then
        call fail_at(status, k0, what//": '"//clipped(t)//"' is not an integer")
        return
      end if
      status%stat = demstep_stat%ok
    end subroutine integer_line

    !> Read the frame starting at line k0 into s.
    subroutine read_frame(k0)
      integer, intent(in) :: k0
      integer :: a(64), b(64), nf, j, c, i, ncol, row, first, second, nf_row
      integer(i8) :: count, ints(3)
      integer(i8), allocatable :: table(:)
      integer, allocatable :: slot(:)
      integer :: col_id, col_type, col_x(3), col_v(3), col_w(3), col_r, col_d, col_m, col_rho, col_mol
      logical :: scaled
      real(dp) :: vals(64)
      character(len=:), allocatable :: h, name
      call integer_line(k0 + 3, "the number of atoms", count)
      s%n = int(count)
      call integer_line(k0 + 1, "the timestep", s%timestep)
      if (status%stat /= demstep_stat%ok) return
      ! box
      h = lowercase(trim(adjustl(line_of(text, lines, k0 + 4))))
      call fields(h, a, b, nf)
      if (nf /= 6) then
        if (nf == 9) then
          call fail_at(status, k0 + 4, "a triclinic box (xy xz yz) is not supported")
        else
          call fail_at(status, k0 + 4, "expected 'ITEM: BOX BOUNDS' and three boundary words (pp, ff, fs, ...), " &
            //"found "//int_text(nf - 3)//" words")
        end if
        return
      end if
      do j = 1, 3
        s%periodic(j) = h(a(3 + j):b(3 + j)) == "pp"
        call line_numbers(text, lines, k0 + 4 + j, 2, vals, status)
        if (status%stat /= demstep_stat%ok) return
        s%lo(j) = vals(1)
        s%hi(j) = vals(2)
        if (.not. s%hi(j) > s%lo(j)) then
          call fail_at(status, k0 + 4 + j, "the box's upper bound must exceed its lower bound")
          return
        end if
      end do
      s%has_box = .true.
      ! columns
      h = trim(adjustl(line_of(text, lines, k0 + 8)))
      call fields(h, a, b, nf)
      ncol = nf - 2
      if (ncol < 1) then
        call fail_at(status, k0 + 8, "'ITEM: ATOMS' names no column")
        return
      end if
      if (nf > size(a)) then
        call fail_at(status, k0 + 8, "more than "//int_text(size(a) - 2)//" columns")
        return
      end if
      col_id = 0; col_type = 0; col_x = 0; col_v = 0; col_w = 0; col_r = 0; col_d = 0; col_m = 0; col_rho = 0
      col_mol = 0
      scaled = .false.
      do c = 1, ncol
        name = h(a(c + 2):b(c + 2))
        select case (name)
        case ("id")
          col_id = c
        case ("type")
          col_type = c
        case ("x", "xu")
          col_x(1) = c
        case ("y", "yu")
          col_x(2) = c
        case ("z", "zu")
          col_x(3) = c
        case ("xs", "xsu")
          col_x(1) = c
          scaled = .true.
        case ("ys", "ysu")
          col_x(2) = c
          scaled = .true.
        case ("zs", "zsu")
          col_x(3) = c
          scaled = .true.
        case ("vx")
          col_v(1) = c
        case ("vy")
          col_v(2) = c
        case ("vz")
          col_v(3) = c
        case ("omegax")
          col_w(1) = c
        case ("omegay")
          col_w(2) = c
        case ("omegaz")
          col_w(3) = c
        case ("radius")
          col_r = c
        case ("diameter")
          col_d = c
        case ("mass")
          col_m = c
        case ("density")
          col_rho = c
        case ("mol")
          col_mol = c
        case ("q", "fx", "fy", "fz", "tqx", "tqy", "tqz", "ix", "iy", "iz", "angmomx", "angmomy", &
          "angmomz", "mux", "muy", "muz", "mu", "proc", "procp1", "element", "ke", "pe")
        case default
          if (.not. (index(name, "c_") == 1 .or. index(name, "f_") == 1 .or. index(name, "v_") == 1 &
            .or. index(name, "i_") == 1 .or. index(name, "d_") == 1 .or. index(name, "i2_") == 1 &
            .or. index(name, "d2_") == 1)) then
            call fail_at(status, k0 + 8, "unknown column '"//clipped(name)//"' (known: id type x y z xs ys zs xu yu " &
              //"zu vx vy vz radius diameter mass density omegax omegay omegaz mol, LAMMPS' others skipped)")
            return
          end if
        end select
      end do
      if (any(col_x == 0)) then
        call fail_at(status, k0 + 8, "the columns need x y z (or xs ys zs)")
        return
      else if (col_r == 0 .and. col_d == 0) then
        call fail_at(status, k0 + 8, "the columns need radius or diameter")
        return
      else if (col_r > 0 .and. col_d > 0) then
        call fail_at(status, k0 + 8, "give radius or diameter, not both")
        return
      end if
      s%has_velocity = all(col_v > 0)
      s%has_omega = all(col_w > 0)
      s%has_mass = col_m > 0
      s%has_density = col_rho > 0
      ! every row's field count first: the arrays are then bounded by the rows'
      ! bytes (2 ncol or more each), not by the header's count
      do i = 1, s%n
        row = k0 + 8 + i
        nf_row = field_count(text(lines%first(row):lines%last(row)))
        if (nf_row /= ncol) then
          call line_numbers(text, lines, row, ncol, vals, status)
          return
        end if
      end do
      call allocate_snapshot(s, s%n)
      do i = 1, s%n
        row = k0 + 8 + i
        ! ids and types: integers from 1 (LAMMPS numbers both from 1)
        ! mol: LIGGGHTS writes -1 for a sphere in no body
        call line_numbers(text, lines, row, ncol, vals, status, columns=h(a(3):b(nf)), &
          whole=[col_id, col_type, col_mol], low=[1_i8, 1_i8, -1_i8], &
          high=[huge(1_i8), int(huge(1), i8), int(huge(1), i8)], ints=ints)
        if (status%stat /= demstep_stat%ok) return
        s%id(i) = i
        if (col_id > 0) s%id(i) = ints(1)
        s%type(i) = 1
        if (col_type > 0) s%type(i) = int(ints(2))
        if (col_mol > 0) s%body(i) = max(0, int(ints(3)))
        s%x(:, i) = vals(col_x)
        if (scaled) s%x(:, i) = s%lo + vals(col_x)*(s%hi - s%lo)
        if (s%has_velocity) s%v(:, i) = vals(col_v)
        if (s%has_omega) s%omega(:, i) = vals(col_w)
        if (col_r > 0) s%radius(i) = vals(col_r)
        if (col_d > 0) s%radius(i) = 0.5_dp*vals(col_d)
        if (.not. s%radius(i) > 0.0_dp) then
          call fail_at(status, row, trim(merge("radius  ", "diameter", col_r > 0))//" must be > 0")
          return
        end if
        if (s%has_mass) s%mass(i) = vals(col_m)
        if (s%has_density) s%density(i) = vals(col_rho)
        if (s%has_mass .and. .not. s%mass(i) > 0.0_dp) then
          call fail_at(status, row, "mass must be > 0")
          return
        end if
        if (s%has_density .and. .not. s%density(i) > 0.0_dp) then
          call fail_at(status, row, "density must be > 0")
          return
        end if
      end do
      if (col_id > 0) then
        call id_table(s%id, table, slot, first, second)
        if (second > 0) then
          call fail_at(status, k0 + 8 + second, "atom id "//int_text(s%id(second))//" appears twice (first on " &
            //"line "//int_text(k0 + 8 + first)//")")
          return
        end if
      end if
      ! LIGGGHTS' bodies: the mass column is each member's body's mass
      s%has_body = any(s%body > 0)
      s%body_mass = s%has_body .and. s%has_mass
      status%stat = demstep_stat%ok
    end subroutine read_frame

  end subroutine parse_dump

  ! ---------------------------------------------------------------- data files

  subroutine parse_data(text, lines, s, status)
    character(len=*), intent(in) :: text
    type(lines_type), intent(in) :: lines
    type(snapshot_type), intent(out) :: s
    type(demstep_status_type), intent(out) :: status
    integer :: k, a(64), b(64), nf, j, i, atoms_line, vel_line, n_atoms, pos, count_line, first, second, &
      rows, next
    character(len=:), allocatable :: l, word
    real(dp) :: vals(64)
    integer(i8) :: ints(2)
    logical :: have_count
    integer(i8), allocatable :: table(:)
    integer, allocatable :: slot(:), vel_row(:)
    ! header: from line 2 up to the first section keyword
    have_count = .false.
    atoms_line = 0
    vel_line = 0
    n_atoms = 0
    count_line = 0
    k = 2
    do while (k <= lines%n)
      l = lowercase(strip_comment(line_of(text, lines, k)))
      call fields(l, a, b, nf)
      if (nf == 0) then
        k = k + 1
        cycle
      end if
      word = section_word(l)
      if (len(word) > 0) exit
      if (nf == 2 .and. word_at(2) == "atoms") then
        call count_of(k, l(a(1):b(1)), n_atoms)
        if (status%stat /= demstep_stat%ok) return
        have_count = .true.
        count_line = k
      else if (nf == 4 .and. word_at(3) == "xlo") then
        call bounds(1)
      else if (nf == 4 .and. word_at(3) == "ylo") then
        call bounds(2)
      else if (nf == 4 .and. word_at(3) == "zlo") then
        call bounds(3)
      else if (nf == 6 .and. word_at(4) == "xy") then
        call fail_at(status, k, "a triclinic box (xy xz yz) is not supported")
      end if
      if (status%stat /= demstep_stat%ok) return
      k = k + 1
    end do
    if (.not. have_count) then
      call set_status(status, demstep_stat%invalid_input, "no 'N atoms' line in the header")
      return
    end if
    s%has_box = .true.
    ! sections: Atoms and Velocities read, others skipped to the next keyword
    do while (k <= lines%n)
      l = strip_comment(line_of(text, lines, k))
      word = section_word(lowercase(l))
      if (len(word) == 0) then
        call fields(l, a, b, nf)
        if (nf > 0) then
          call fail_at(status, k, "expected a section keyword (Atoms, Velocities, Masses, ...), found '" &
            //clipped(trim(adjustl(l)))//"'")
          return
        end if
        k = k + 1
        cycle
      end if
      ! the rows start after the keyword and one blank line
      j = k + 1
      do while (j <= lines%n)
        if (first_nonblank(text, lines, j) > 0) exit
        j = j + 1
      end do
      select case (word)
      case ("atoms")
        if (atoms_line > 0) then
          call fail_at(status, k, "a second Atoms section (the first on line "//int_text(atoms_line)//")")
          return
        end if
        atoms_line = k
        if (index(lowercase(line_of(text, lines, k)), "#") > 0 .and. &
          index(lowercase(line_of(text, lines, k)), "sphere") == 0) then
          call fail_at(status, k, "atom style '"//clipped(trim(adjustl(line_of(text, lines, k))))// &
            "': only the sphere style (id type diameter density x y z) is read")
          return
        end if
        ! the header's count against the rows present, before anything is allocated
        call rows_present(j, rows, next)
        if (n_atoms > rows) then
          if (next > lines%n) then
            call fail_at(status, lines%n, "truncated: the Atoms section has "//int_text(rows)//" of the " &
              //int_text(n_atoms)//" rows the header declares (line "//int_text(count_line)//")")
          else
            call fail_at(status, next, "the Atoms section has "//int_text(rows)//" rows, the header declares " &
              //int_text(n_atoms)//" atoms (line "//int_text(count_line)//")")
          end if
          return
        end if
        ! one pass over the rows: a row of 7 or more fields has 14 bytes or
        ! more (with its newline; the last 13), so the arrays are bounded by
        ! the text's bytes; more rows than fit means a short row, which
        ! `atoms_count_error` finds. A row's field count is checked before
        ! its numbers, and a later row's wrong count is reported before an
        ! earlier row's bad value (as a pass over the counts first would)
        if (n_atoms > len(text)/14 + 1) then
          if (.not. atoms_count_error(1)) call fail_at(status, j, "an Atoms row shorter than 7 values")
          return
        end if
        s%n = n_atoms
        call allocate_snapshot(s, n_atoms)
        s%has_density = .true.
        do i = 1, n_atoms
          ! ids and types: integers from 1, as LAMMPS requires
          call line_numbers(text, lines, j + i - 1, 7, vals, status, &
            columns="id type diameter density x y z ix iy iz", strip=.true., whole=[1, 2], low=[1_i8, 1_i8], &
            high=[huge(1_i8), int(huge(1), i8)], ints=ints, found=nf, alternative=10)
          if (nf >= 0 .and. nf /= 10) then
            call atoms_count_message(j + i - 1, nf)
            return
          end if
          if (status%stat /= demstep_stat%ok) then
            if (atoms_count_error(i + 1)) return
            return
          end if
          s%id(i) = ints(1)
          s%type(i) = int(ints(2))
          s%radius(i) = 0.5_dp*vals(3)
          s%density(i) = vals(4)
          s%x(:, i) = vals(5:7)
          if (.not. s%radius(i) > 0.0_dp) then
            if (atoms_count_error(i + 1)) return
            call fail_at(status, j + i - 1, "diameter must be > 0 (a point particle has no contact)")
            return
          end if
          if (.not. s%density(i) > 0.0_dp) then
            if (atoms_count_error(i + 1)) return
            call fail_at(status, j + i - 1, "density must be > 0")
            return
          end if
        end do
        call id_table(s%id, table, slot, first, second)
        if (second > 0) then
          call fail_at(status, j + second - 1, "atom id "//int_text(s%id(second))//" appears twice (first on " &
            //"line "//int_text(j + first - 1)//")")
          return
        end if
        k = j + n_atoms
      case ("velocities")
        if (vel_line > 0) then
          call fail_at(status, k, "a second Velocities section (the first on line "//int_text(vel_line)//")")
          return
        end if
        vel_line = k
        if (atoms_line == 0) then
          call fail_at(status, k, "the Velocities section must follow the Atoms section")
          return
        end if
        allocate(vel_row(n_atoms), source=0)
        do i = 1, n_atoms
          if (j + i - 1 > lines%n) then
            call fail_at(status, lines%n, "truncated: the Velocities section has "//int_text(i - 1)//" of the " &
              //int_text(n_atoms)//" rows")
            return
          end if
          call line_numbers(text, lines, j + i - 1, 7, vals, status, columns="id vx vy vz wx wy wz", &
            strip=.true., whole=[1], low=[1_i8], high=[huge(1_i8)], ints=ints)
          if (status%stat /= demstep_stat%ok) return
          pos = find_id(table, slot, ints(1))
          if (pos == 0) then
            call fail_at(status, j + i - 1, "atom id "//int_text(ints(1))//" is not in the Atoms section")
            return
          end if
          if (vel_row(pos) > 0) then
            call fail_at(status, j + i - 1, "atom id "//int_text(ints(1))//" appears twice in the Velocities " &
              //"section (first on line "//int_text(vel_row(pos))//")")
            return
          end if
          vel_row(pos) = j + i - 1
          s%v(:, pos) = vals(2:4)
          s%omega(:, pos) = vals(5:7)
        end do
        s%has_velocity = .true.
        s%has_omega = .true.
        k = j + n_atoms
      case default
        ! skip the section's rows: up to the next keyword
        k = j
        do while (k <= lines%n)
          if (len(section_at(text, lines, k)) > 0) exit
          k = k + 1
        end do
      end select
    end do
    if (atoms_line == 0) then
      call set_status(status, demstep_stat%invalid_input, "no Atoms section")
      return
    end if
    status%stat = demstep_stat%ok
  contains

    !> The message of the Atoms row on line `line` with `nf` fields.
    subroutine atoms_count_message(line, nf)
      integer, intent(in) :: line, nf
      call fail_at(status, line, "an Atoms row of style sphere has 7 values (id type diameter density " &
        //"x y z) or 10 (with ix iy iz), found "//int_text(nf))
    end subroutine atoms_count_message

    !> Whether an Atoms row from row i0 on (of n_atoms from line j) has a
    !> field count other than 7 or 10 (status set for the first such row).
    logical function atoms_count_error(i0) result(found_one)
      integer, intent(in) :: i0
      integer :: ii, nff
      found_one = .false.
      do ii = i0, n_atoms
        nff = field_count(text(lines%first(j + ii - 1):uncommented_last(text, lines, j + ii - 1)))
        if (nff /= 7 .and. nff /= 10) then
          call atoms_count_message(j + ii - 1, nff)
          found_one = .true.
          return
        end if
      end do
    end function atoms_count_error

    !> Field i of the current header line ('' beyond the last).
    function word_at(i) result(w)
      integer, intent(in) :: i
      character(len=:), allocatable :: w
      w = ""
      if (i <= nf) w = l(a(i):b(i))
    end function word_at


    !> The non-blank lines from line j0 up to the next section keyword (or the
    !> end), and the line of that keyword (lines%n + 1 at the end).
    subroutine rows_present(j0, rows, next)
      integer, intent(in) :: j0
      integer, intent(out) :: rows, next
      rows = 0
      next = j0
      do while (next <= lines%n)
        if (len(section_at(text, lines, next)) > 0) exit
        if (first_nonblank(text, lines, next) > 0) rows = rows + 1
        next = next + 1
      end do
    end subroutine rows_present

    subroutine count_of(line, t, n)
      integer, intent(in) :: line
      character(len=*), intent(in) :: t
      integer, intent(out) :: n
      integer(i8) :: c
      logical :: ok
      n = 0
      call integer_of(t, c, ok)
      if (.not. ok .or. c < 0 .or. c > huge(1)) then
        call fail_at(status, line, "the atom count '"//clipped(t)//"' is not an integer in [0, "//int_text(huge(1))//"]")
        return
      end if
      n = int(c)
      status%stat = demstep_stat%ok
    end subroutine count_of

    subroutine bounds(axis)
      integer, intent(in) :: axis
      call line_numbers(text, lines, k, 2, vals, status, strip=.true., words=2)
      if (status%stat /= demstep_stat%ok) return
      s%lo(axis) = vals(1)
      s%hi(axis) = vals(2)
      if (.not. s%hi(axis) > s%lo(axis)) call fail_at(status, k, "the box's upper bound must exceed its lower bound")
    end subroutine bounds

  end subroutine parse_data

  !> The section keyword a data-file line holds ('' for none), lower case.
  pure function section_word(l) result(word)
    character(len=*), intent(in) :: l
    character(len=:), allocatable :: word
    character(len=:), allocatable :: t
    integer :: k
    character(len=*), parameter :: known(14) = [character(len=20) :: "atoms", "velocities", "masses", &
      "ellipsoids", "lines", "triangles", "bodies", "bonds", "angles", "dihedrals", "impropers", &
      "pair coeffs", "bond coeffs", "pairij coeffs"]
    t = trim(adjustl(l))
    k = index(t, "#")
    if (k > 0) t = trim(t(:k-1))
    word = ""
    do k = 1, size(known)
      if (t == trim(known(k))) word = trim(known(k))
    end do
  end function section_word

  pure function strip_comment(l) result(t)
    character(len=*), intent(in) :: l
    character(len=:), allocatable :: t
    integer :: k
    k = index(l, "#")
    if (k > 0) then
      t = l(:k-1)
    else
      t = l
    end if
  end function strip_comment

  !> The section keyword line k holds ('' for none): `section_word` of it,
  !> looked up only when the line starts (after blanks) with a letter.
  pure function section_at(text, lines, k) result(word)
    character(len=*), intent(in) :: text
    type(lines_type), intent(in) :: lines
    integer, intent(in) :: k
    character(len=:), allocatable :: word
    integer :: j
    word = ""
    j = first_nonblank(text, lines, k)
    if (j == 0) return
    if (.not. is_letter(text(lines%first(k)+j-1:lines%first(k)+j-1))) return
    word = section_word(lowercase(strip_comment(line_of(text, lines, k))))
  end function section_at

  !> The last character of line k before a `#` comment.
  pure integer function uncommented_last(text, lines, k) result(last)
    character(len=*), intent(in) :: text
    type(lines_type), intent(in) :: lines
    integer, intent(in) :: k
    integer :: i, n
    last = lines%last(k)
    ! most lines have no comment: counted without a branch, looked for if any
    n = 0
    do i = lines%first(k), last
      n = n + merge(1, 0, iachar(text(i:i)) == 35)
    end do
    if (n == 0) return
    do i = lines%first(k), last
      if (iachar(text(i:i)) == 35) then
        last = i - 1
        return
      end if
    end do
  end function uncommented_last

  ! ------------------------------------------------------------- Yade exports

  subroutine parse_yade(text, lines, s, status)
    character(len=*), intent(in) :: text
    type(lines_type), intent(in) :: lines
    type(snapshot_type), intent(out) :: s
    type(demstep_status_type), intent(out) :: status
    integer :: k, n, nf, ncol, i, min_col, j, expect, found, cap, clump_col, hk
    character(len=:), allocatable :: l, layout, names
    real(dp) :: vals(64)
    integer(i8) :: ints(1)
    logical :: with_mat, attrs
    integer :: ha(64), hb(64), nh
    layout = "x_y_z_r"
    names = ""
    hk = 0
    ! the layout, and the rows counted
    n = 0
    ncol = 0
    do k = 1, lines%n
      j = first_nonblank(text, lines, k)
      if (j == 0) cycle
      if (text(lines%first(k)+j-1:lines%first(k)+j-1) == "#") then
        l = trim(adjustl(line_of(text, lines, k)))
        if (index(lowercase(l), "#format") == 1) then
          layout = trim(adjustl(l(8:)))
          select case (layout)
          case ("x_y_z_r", "x_y_z_r_matId", "x_y_z_r_attrs")
          case default
            call fail_at(status, k, "unknown Yade format '"//clipped(layout)//"' (x_y_z_r, x_y_z_r_matId, x_y_z_r_attrs)")
            return
          end select
        else if (index(lowercase(l), "# x y z r ") == 1) then
          ! the attributes' names (textExt's comment): the last such line
          names = trim(adjustl(l(10:)))
          hk = k
        end if
        cycle
      end if
      n = n + 1
    end do
    with_mat = layout == "x_y_z_r_matId"
    attrs = layout == "x_y_z_r_attrs"
    min_col = merge(5, 4, with_mat)
    ! a clumpId among the attributes' names: its column
    clump_col = 0
    if (attrs) then
      call fields(names, ha, hb, nh)
      do j = 1, min(nh, size(ha))
        if (lowercase(names(ha(j):hb(j))) == "clumpid" .or. lowercase(names(ha(j):hb(j))) == "b.clumpid") &
          clump_col = 4 + j
      end do
    end if
    ! one pass over the rows: a row of 4 or more fields has 8 bytes or more
    ! (with its newline; the last 7), so the arrays are bounded by the text's
    ! bytes, not by the rows' count; more rows than fit means a short row,
    ! which `count_error` finds. A row's field count is checked before its
    ! numbers, and a later row's wrong count is reported before an earlier
    ! row's bad number (as a pass over the counts first would)
    cap = min(n, len(text)/8 + 1)
    s%n = cap
    call allocate_snapshot(s, cap)
    expect = min_col
    ncol = 0
    i = 0
    do k = 1, lines%n
      j = first_nonblank(text, lines, k)
      if (j == 0) cycle
      if (text(lines%first(k)+j-1:lines%first(k)+j-1) == "#") cycle
      i = i + 1
      if (i == 1 .and. attrs) then
        ncol = field_count(text(lines%first(k):lines%last(k)))
        expect = ncol
        if (ncol < 4) then
          call count_message(k, ncol)
          return
        end if
        if (ncol > size(vals)) then
          call fail_at(status, k, "more than "//int_text(size(vals))//" values")
          return
        end if
        if (clump_col > 0 .and. ncol /= 4 + nh) then
          call fail_at(status, k, "the names line "//int_text(hk)//" (# x y z r ...) names "// &
            int_text(4 + nh)//" columns, the rows have "//int_text(ncol)//": which is clumpId?")
          return
        end if
      end if
      if (i > cap) then
        if (.not. count_error(k)) call fail_at(status, k, "a row shorter than 4 values")
        return
      end if
      ! Yade numbers the materials of O.materials from 0; a type is an integer
      if (with_mat) then
        call line_numbers(text, lines, k, expect, vals, status, columns="x y z r matId", whole=[5], low=[0_i8], &
          high=[int(huge(1), i8) - 1], ints=ints, found=found)
      else if (clump_col > 0) then
        ! Yade's clump ids: -1 (none) or a body id
        call line_numbers(text, lines, k, expect, vals, status, columns="x y z r "//names, whole=[clump_col], &
          low=[-1_i8], high=[int(huge(1), i8) - 1], ints=ints, found=found)
      else
        call line_numbers(text, lines, k, expect, vals, status, columns="x y z r", found=found)
      end if
      if (found >= 0) then
        call count_message(k, found)
        return
      end if
      if (status%stat /= demstep_stat%ok) then
        if (count_error(k + 1)) return
        return
      end if
      s%id(i) = i
      s%x(:, i) = vals(1:3)
      s%radius(i) = vals(4)
      s%type(i) = 1
      ! Yade numbers its materials from 0 (O.materials ids): type = matId + 1
      if (with_mat) s%type(i) = int(ints(1)) + 1
      if (clump_col > 0) s%body(i) = int(ints(1)) + 1
      if (.not. s%radius(i) > 0.0_dp) then
        if (count_error(k + 1)) return
        call fail_at(status, k, "r must be > 0")
        return
      end if
    end do
    s%has_body = clump_col > 0
    status%stat = demstep_stat%ok
  contains

    !> The message of a row with `nf` fields where another count was due.
    subroutine count_message(k, nf)
      integer, intent(in) :: k, nf
      if (attrs) then
        call fail_at(status, k, "expected "//int_text(max(ncol, 4))//" values (x y z r and the attributes), " &
          //"found "//int_text(nf))
      else
        call fail_at(status, k, "expected "//int_text(min_col)//" values ("//layout//"), found "//int_text(nf))
      end if
    end subroutine count_message

    !> Whether a row from line k0 on has a wrong field count (status set for
    !> the first such row).
    logical function count_error(k0) result(found_one)
      integer, intent(in) :: k0
      integer :: kk, jj, nff
      found_one = .false.
      do kk = k0, lines%n
        jj = first_nonblank(text, lines, kk)
        if (jj == 0) cycle
        if (text(lines%first(kk)+jj-1:lines%first(kk)+jj-1) == "#") cycle
        nff = field_count(text(lines%first(kk):lines%last(kk)))
        if ((.not. attrs .and. nff /= min_col) .or. (attrs .and. (nff < 4 .or. nff /= ncol))) then
          call count_message(kk, nff)
          found_one = .true.
          return
        end if
      end do
    end function count_error
  end subroutine parse_yade

  ! ------------------------------------------------------------------ helpers

  !> Status `invalid_input` with `line N: what`.
  pure subroutine fail_at(status, line, what)
    type(demstep_status_type), intent(inout) :: status
    integer, intent(in) :: line
    character(len=*), intent(in) :: what
    call set_status(status, demstep_stat%invalid_input, "line "//int_text(line)//": "//what)
  end subroutine fail_at

  pure subroutine allocate_snapshot(s, n)
    type(snapshot_type), intent(inout) :: s
    integer, intent(in) :: n
    allocate(s%id(n), s%type(n), s%x(3, n), s%v(3, n), s%omega(3, n), s%radius(n), s%mass(n), s%density(n), &
      s%body(n))
    s%id = 0
    s%body = 0
    s%type = 1
    s%x = 0.0_dp
    s%v = 0.0_dp
    s%omega = 0.0_dp
    s%radius = 0.0_dp
    s%mass = 0.0_dp
    s%density = 0.0_dp
  end subroutine allocate_snapshot

  !> Double the capacity of an integer list, keeping its values.
  pure subroutine grow(list)
    integer, allocatable, intent(inout) :: list(:)
    integer, allocatable :: bigger(:)
    allocate(bigger(2*size(list)))
    bigger(:size(list)) = list
    bigger(size(list)+1:) = 0
    call move_alloc(bigger, list)
  end subroutine grow

  !> Line starts and ends (lines counted first, arrays allocated once). The
  !> newlines are found four bytes at a time without a branch per byte
  !> (`byte_mask`): a third of a 26 MB file's reading time went to a byte
  !> loop here.
  pure subroutine split_lines(text, lines)
    character(len=*), intent(in) :: text
    type(lines_type), intent(out) :: lines
    integer :: i, n, start, words, w, half, base
    integer(i8) :: word, mask
    words = len(text)/8
    n = 0
    do w = 0, words - 1
      word = transfer(text(8*w + 1:8*w + 8), 0_i8)
      n = n + flags_of(byte_mask(iand(word, low_half), newlines)) + flags_of(byte_mask(ishft(word, -32), newlines))
    end do
    do i = 8*words + 1, len(text)
      if (iachar(text(i:i)) == 10) n = n + 1
    end do
    if (len(text) > 0) then
      if (text(len(text):len(text)) /= lf) n = n + 1
    end if
    allocate(lines%first(n), lines%last(n))
    lines%n = n
    start = 1
    n = 0
    do w = 0, words - 1
      word = transfer(text(8*w + 1:8*w + 8), 0_i8)
      do half = 0, 1
        mask = byte_mask(iand(ishft(word, -32*half), low_half), newlines)
        base = 8*w + 4*half
        do while (mask /= 0)
          ! (the mask's bit 8 j + 7 marks byte j of the half word)
          i = base + trailz(mask)/8 + 1
          n = n + 1
          lines%first(n) = start
          lines%last(n) = i - 1
          start = i + 1
          mask = iand(mask, mask - 1)
        end do
      end do
    end do
    do i = 8*words + 1, len(text)
      if (iachar(text(i:i)) == 10) then
        n = n + 1
        lines%first(n) = start
        lines%last(n) = i - 1
        start = i + 1
      end if
    end do
    if (start <= len(text)) then
      n = n + 1
      lines%first(n) = start
      lines%last(n) = len(text)
    end if
    ! a carriage return before the newline is not part of the line
    do i = 1, n
      if (lines%last(i) >= lines%first(i)) then
        if (text(lines%last(i):lines%last(i)) == cr) lines%last(i) = lines%last(i) - 1
      end if
    end do
  end subroutine split_lines

  !> Of four bytes (the low 32 bits of `word`), bit 8 j + 7 set where byte j
  !> equals the byte repeated in `pattern` and no other bit: the exact
  !> zero-byte test of x = word xor pattern (y = (x and 0x7f..) + 0x7f.. sets
  !> a byte's top bit unless its low 7 bits are 0; or x adds its own top bit;
  !> not and 0x80.. keeps the zero bytes). In 64-bit integers: no sum overflows.
  elemental integer(i8) function byte_mask(word, pattern) result(mask)
    integer(i8), intent(in) :: word, pattern
    integer(i8), parameter :: low7 = int(z'7F7F7F7F', i8)
    integer(i8) :: x
    x = ieor(word, pattern)
    mask = iand(not(ior(iand(x, low7) + low7, x)), top_bits)
  end function byte_mask

  !> The column of the first character of line k that is not a blank (' '),
  !> 0 for a line of blanks: `verify(line, " ")` without a library call per line.
  pure integer function first_nonblank(text, lines, k) result(j)
    character(len=*), intent(in) :: text
    type(lines_type), intent(in) :: lines
    integer, intent(in) :: k
    integer :: i
    j = 0
    do i = lines%first(k), lines%last(k)
      if (iachar(text(i:i)) /= 32) then
        j = i - lines%first(k) + 1
        return
      end if
    end do
  end function first_nonblank

  pure function line_of(text, lines, k) result(l)
    character(len=*), intent(in) :: text
    type(lines_type), intent(in) :: lines
    integer, intent(in) :: k
    character(len=:), allocatable :: l
    l = text(lines%first(k):lines%last(k))
  end function line_of

  !> Blank- or tab-separated fields of s: a(i):b(i), at most size(a) (nf counts all).
  pure subroutine fields(s, a, b, nf)
    character(len=*), intent(in) :: s
    integer, intent(out) :: a(:), b(:)
    integer, intent(out) :: nf
    integer :: i, c
    logical :: in_field
    nf = 0
    in_field = .false.
    do i = 1, len(s)
      c = iachar(s(i:i))
      if (c == 32 .or. c == 9) then
        if (in_field) then
          if (nf <= size(b)) b(nf) = i - 1
          in_field = .false.
        end if
      else if (.not. in_field) then
        nf = nf + 1
        if (nf <= size(a)) a(nf) = i
        in_field = .true.
      end if
    end do
    if (in_field .and. nf <= size(b)) b(nf) = len(s)
  end subroutine fields

  !> The number of blank- or tab-separated fields of s (as `fields` counts
  !> them): the bytes that start a field, four at a time (`blank_mask`).
  pure integer function field_count(s) result(nf)
    character(len=*), intent(in) :: s
    integer :: i, c, w, half
    integer(i8) :: word, bm, bit
    logical :: blank
    nf = 0
    bit = 1
    do w = 0, len(s)/8 - 1
      word = transfer(s(8*w + 1:8*w + 8), 0_i8)
      do half = 0, 1
        bm = blank_mask(iand(ishft(word, -32*half), low_half))
        nf = nf + flags_of(iand(iand(not(bm), top_bits), ior(iand(ishft(bm, 8), top_bits), ishft(bit, 7))))
        bit = iand(ishft(bm, -31), 1_i8)
      end do
    end do
    do i = 8*(len(s)/8) + 1, len(s)
      c = iachar(s(i:i))
      blank = c == 32 .or. c == 9
      if (.not. blank .and. bit == 1) nf = nf + 1
      bit = merge(1_i8, 0_i8, blank)
    end do
  end function field_count

  !> The number of bytes flagged in a mask of `byte_mask`'s form (bits 8 j + 7
  !> only): the flags moved to the bytes' low bits and summed into the top
  !> byte by one multiplication (no population count instruction is assumed).
  elemental integer function flags_of(mask) result(n)
    integer(i8), intent(in) :: mask
    integer(i8), parameter :: ones = int(z'01010101', i8)
    n = int(iand(ishft(ishft(mask, -7)*ones, -24), 255_i8))
  end function flags_of

  !> Of four bytes (the low 32 bits of `word`), bit 8 j + 7 set where byte j
  !> is a blank or a tab, no other bit (`byte_mask`).
  elemental integer(i8) function blank_mask(word) result(mask)
    integer(i8), intent(in) :: word
    mask = ior(byte_mask(word, int(z'20202020', i8)), byte_mask(word, int(z'09090909', i8)))
  end function blank_mask

  !> Exactly `count` finite numbers at the start of line k, followed by exactly
  !> `words` words (default 0; `xlo xhi` lines have 2). `columns` names the
  !> values for messages; `strip` drops a `#` comment first. The values at the
  !> positions `whole` (0: none) must be integers (see [[integer_of]]) within
  !> [`low`, `high`]: returned in `ints` (and in `vals`, as reals). With
  !> `found`, the fields the line has (the caller's message when it is not
  !> `count`; -1 when the count was right). With `alternative`, a line of
  !> that many numbers is read too (`found` tells which).
  pure subroutine line_numbers(text, lines, k, count, vals, status, columns, strip, words, whole, low, high, ints, &
      found, alternative)
    character(len=*), intent(in) :: text
    type(lines_type), intent(in) :: lines
    integer, intent(in) :: k, count
    real(dp), intent(out) :: vals(:)
    type(demstep_status_type), intent(out) :: status
    character(len=*), intent(in), optional :: columns
    logical, intent(in), optional :: strip
    integer, intent(in), optional :: words
    integer, intent(in), optional :: whole(:)
    integer(i8), intent(in), optional :: low(:), high(:)
    integer(i8), intent(out), optional :: ints(:)
    integer, intent(out), optional :: found
    integer, intent(in), optional :: alternative
    integer :: a(64), b(64), nf, i, j, expect, w, first, last, numbers
    logical :: ok, too_large
    first = lines%first(k)
    last = lines%last(k)
    if (present(strip)) then
      if (strip) last = uncommented_last(text, lines, k)
    end if
    call fields(text(first:last), a, b, nf)
    a(:min(nf, size(a))) = a(:min(nf, size(a))) + first - 1
    b(:min(nf, size(b))) = b(:min(nf, size(b))) + first - 1
    expect = count
    if (present(words)) expect = count + words
    if (present(found)) found = -1
    numbers = count
    if (present(alternative)) then
      if (nf == alternative) then
        expect = alternative
        numbers = alternative
        if (present(found)) found = nf
      end if
    end if
    if (nf /= expect .and. present(found)) then
      found = nf
      status%stat = demstep_stat%invalid_input
      return
    end if
    if (nf /= expect) then
      call set_status(status, demstep_stat%invalid_input, "line "//int_text(k)//": expected "// &
        int_text(expect)//" values, found "//int_text(nf))
      return
    end if
    if (present(ints)) ints = 0
    do j = 1, numbers
      w = 0
      if (present(whole)) then
        do i = 1, size(whole)
          if (whole(i) == j) then
            w = i
            exit
          end if
        end do
      end if
      if (w > 0) then
        call integer_of(text(a(j):b(j)), ints(w), ok, too_large)
        if (.not. ok .and. .not. too_large) then
          call set_status(status, demstep_stat%invalid_input, "line "//int_text(k)//": "//column_name(j)// &
            ": '"//clipped(text(a(j):b(j)))//"' is not an integer")
          return
        end if
        if (too_large .or. ints(w) < low(w) .or. ints(w) > high(w)) then
          call set_status(status, demstep_stat%invalid_input, "line "//int_text(k)//": "//column_name(j)// &
            ": '"//clipped(text(a(j):b(j)))//"' must lie in ["//int_text(low(w))//", "//int_text(high(w))//"]")
          return
        end if
        vals(j) = real(ints(w), dp)
        cycle
      end if
      call real_of(text(a(j):b(j)), vals(j), ok)
      if (ok) ok = ieee_is_finite(vals(j))
      if (.not. ok) then
        call set_status(status, demstep_stat%invalid_input, "line "//int_text(k)//": "//column_name(j)//": '"// &
          clipped(text(a(j):b(j)))//"' is not a number")
        return
      end if
    end do
    status%stat = demstep_stat%ok
  contains
    !> "column 'NAME'" from `columns`, else "value J".
    pure function column_name(j) result(name)
      integer, intent(in) :: j
      character(len=:), allocatable :: name
      integer :: ca(64), cb(64), nc
      name = "value "//int_text(j)
      if (present(columns)) then
        call fields(columns, ca, cb, nc)
        if (j <= min(nc, size(ca))) name = "column '"//columns(ca(j):cb(j))//"'"
      end if
    end function column_name
  end subroutine line_numbers

  !> At most 40 characters of a text, for messages (see [[printable]]).
  pure function clipped(t) result(c)
    character(len=*), intent(in) :: t
    character(len=:), allocatable :: c
    if (len(t) > 40) then
      c = printable(t(:37))//"..."
    else
      c = printable(t)
    end if
  end function clipped

  !> An open-addressing table of the ids (size a power of two >= 2 n):
  !> `table` holds the ids, `slot` their positions (0: empty). The first id
  !> met twice: its positions `first` and `second` (0 and 0 when all differ);
  !> the table then holds the ids before `second`.
  pure subroutine id_table(ids, table, slot, first, second)
    integer(i8), intent(in) :: ids(:)
    integer(i8), allocatable, intent(out) :: table(:)
    integer, allocatable, intent(out) :: slot(:)
    integer, intent(out) :: first, second
    integer :: m, i, h
    first = 0
    second = 0
    m = 16
    do while (m < 2*size(ids))
      m = 2*m
    end do
    allocate(table(0:m-1), slot(0:m-1))
    table = 0
    slot = 0
    do i = 1, size(ids)
      h = hash(ids(i), m)
      do while (slot(h) /= 0)
        if (table(h) == ids(i)) then
          first = slot(h)
          second = i
          return
        end if
        h = iand(h + 1, m - 1)
      end do
      table(h) = ids(i)
      slot(h) = i
    end do
  end subroutine id_table

  pure integer function find_id(table, slot, id) result(pos)
    integer(i8), intent(in) :: table(0:)
    integer, intent(in) :: slot(0:)
    integer(i8), intent(in) :: id
    integer :: h, m
    m = size(table)
    h = hash(id, m)
    pos = 0
    do while (slot(h) /= 0)
      if (table(h) == id) then
        pos = slot(h)
        return
      end if
      h = iand(h + 1, m - 1)
    end do
  end function find_id

  pure integer function hash(id, m) result(h)
    integer(i8), intent(in) :: id
    integer, intent(in) :: m
    ! mix the high bits in; consecutive ids land in consecutive slots
    h = int(modulo(ieor(id, ishft(id, -20)), int(m, i8)))
  end function hash

  !> The `snapshot_format` code of a word (case ignored); `-huge(0)` for another word.
  pure integer function snapshot_format_from_name(name) result(code)
    !> The word, one of `snapshot_format_names`.
    character(len=*), intent(in) :: name
    code = word_index(snapshot_format_names, name)
    if (code == 0) then
      code = -huge(code)
    else
      code = code - 1
    end if
  end function snapshot_format_from_name

  !> The word of a `snapshot_format` code (`?` for another value).
  pure function snapshot_format_name(code) result(name)
    !> A code of `snapshot_format`.
    integer, intent(in) :: code
    character(len=:), allocatable :: name
    name = word_of(snapshot_format_names, code + 1)
  end function snapshot_format_name

end module demstep_snapshot
