!> Particles and their contacts as a legacy VTK file (ASCII
!> UNSTRUCTURED_GRID) that ParaView and VisIt open: one point per particle
!> with point fields (radius, the top mode's participation, ...), one vertex
!> cell (VTK type 1) per particle and one line cell (type 3) per contact, with
!> cell fields (a contact's participation; the vertex cells carry 0 there).
!>
!> The only I/O of the monitor: the numbers come from `demstep_monitor`.
module demstep_vtk
  use demstep_kinds, only: dp
  use demstep_status, only: demstep_status_type, demstep_stat, set_status
  use demstep_scene_data, only: scene_type
  use demstep_monitor, only: participation_type
  use, intrinsic :: ieee_arithmetic, only: ieee_is_finite
  implicit none
  private

  public :: write_vtk_particles, write_participation_vtk

  !> A named field: one value per point (particle) or per contact.
  type, public :: vtk_field_type
    character(len=:), allocatable :: name
    real(dp), allocatable :: values(:)
  end type vtk_field_type

contains

  !> A scene's top-mode participation (`scene_participation`) as a legacy
  !> VTK file: point fields radius, mass, type (0 without types),
  !> participation and wall_participation (the particle's wall and ground
  !> springs' share of the mode's energy), and one line per spring between
  !> two particles with cell fields contact_participation and k_n. Status
  !> invalid_input naming `part` (no mode), or as `write_vtk_particles`.
  subroutine write_participation_vtk(path, scene, part, status)
    character(len=*), intent(in) :: path
    type(scene_type), intent(in) :: scene
    type(participation_type), intent(in) :: part
    type(demstep_status_type), intent(out) :: status
    type(vtk_field_type) :: pf(5), cf(2)
    real(dp), allocatable :: wall(:)
    logical, allocatable :: between(:)
    integer, allocatable :: pairs(:, :)
    integer :: s
    if (.not. part%computed) then
      call set_status(status, demstep_stat%invalid_input, "has no top mode (no eigensolver ran)", where="part")
      return
    end if
    allocate(wall(scene%n), source=0.0_dp)
    between = part%spring_a > 0 .and. part%spring_b > 0
    do s = 1, size(between)
      if (.not. between(s) .and. part%spring_b(s) > 0) wall(part%spring_b(s)) = wall(part%spring_b(s)) + &
        part%spring_share(s)
    end do
    allocate(pairs(2, count(between)))
    pairs(1, :) = pack(part%spring_a, between)
    pairs(2, :) = pack(part%spring_b, between)
    pf(1) = vtk_field_type("radius", scene%radius)
    pf(2) = vtk_field_type("mass", scene%mass)
    pf(3) = vtk_field_type("type", [(0.0_dp, s = 1, scene%n)])
    if (allocated(scene%ptype)) pf(3)%values = real(scene%ptype, dp)
    pf(4) = vtk_field_type("participation", part%particle_share)
    pf(5) = vtk_field_type("wall_participation", wall)
    cf(1) = vtk_field_type("contact_participation", pack(part%spring_share, between))
    cf(2) = vtk_field_type("k_n", pack(part%spring_k(1, :), between))
    call write_vtk_particles(path, scene%x, pf, status, pairs=pairs, contact_fields=cf, &
      title="demstep: the top mode's participation")
  end subroutine write_participation_vtk

  !> Write particles x(dim, n) (dim 1 to 3; padded with zeros to 3D) with
  !> point fields (each n values) and, optionally, contacts pairs(2, nc)
  !> (1-based) with contact fields (each nc values) to `path` as legacy VTK.
  !> Non-finite values are written as 0. On a write error the file is
  !> removed. Status invalid_input naming the argument (sizes, a field name
  !> with blanks, a pair out of range) or io_error naming `path`.
  subroutine write_vtk_particles(path, x, point_fields, status, pairs, contact_fields, title)
    character(len=*), intent(in) :: path
    real(dp), intent(in) :: x(:, :)
    type(vtk_field_type), intent(in) :: point_fields(:)
    type(demstep_status_type), intent(out) :: status
    integer, intent(in), optional :: pairs(:, :)
    type(vtk_field_type), intent(in), optional :: contact_fields(:)
    !> The file's title line (default "demstep particles").
    character(len=*), intent(in), optional :: title
    integer :: n, nc, dim, unit, ios, i, f
    real(dp) :: p(3)
    character(len=:), allocatable :: head
    n = size(x, 2)
    dim = size(x, 1)
    nc = 0
    if (present(pairs)) nc = size(pairs, 2)
    if (dim < 1 .or. dim > 3) then
      call set_status(status, demstep_stat%invalid_input, "must be (dim, n) with dim 1 to 3", where="x")
      return
    end if
    do f = 1, size(point_fields)
      if (size(point_fields(f)%values) /= n .or. .not. field_name_ok(point_fields(f)%name)) then
        call set_status(status, demstep_stat%invalid_input, "one value per particle and a name without " &
          //"blanks", where="point_fields", index=f, subscript=.true.)
        return
      end if
    end do
    if (present(pairs)) then
      if (size(pairs, 1) /= 2) then
        call set_status(status, demstep_stat%invalid_input, "must be (2, contacts)", where="pairs")
        return
      end if
      do i = 1, nc
        if (any(pairs(:, i) < 1 .or. pairs(:, i) > n)) then
          call set_status(status, demstep_stat%invalid_input, "names a particle outside 1 to n", &
            where="pairs", index=i, subscript=.true.)
          return
        end if
      end do
    end if
    if (present(contact_fields)) then
      do f = 1, size(contact_fields)
        if (size(contact_fields(f)%values) /= nc .or. .not. field_name_ok(contact_fields(f)%name)) then
          call set_status(status, demstep_stat%invalid_input, "one value per contact and a name without " &
            //"blanks", where="contact_fields", index=f, subscript=.true.)
          return
        end if
      end do
    end if
    head = "demstep particles"
    if (present(title)) head = title(:min(len(title), 255))
    open(newunit=unit, file=path, status="replace", action="write", iostat=ios)
    if (ios /= 0) then
      call set_status(status, demstep_stat%io_error, "cannot be opened for writing", where=path)
      return
    end if
    write(unit, '(a)', iostat=ios) "# vtk DataFile Version 3.0"
    if (ios == 0) write(unit, '(a)', iostat=ios) head
    if (ios == 0) write(unit, '(a)', iostat=ios) "ASCII"
    if (ios == 0) write(unit, '(a)', iostat=ios) "DATASET UNSTRUCTURED_GRID"
    if (ios == 0) write(unit, '(a, i0, a)', iostat=ios) "POINTS ", n, " double"
    do i = 1, n
      if (ios /= 0) exit
      p = 0.0_dp
      p(:dim) = x(:, i)
      write(unit, '(3(es24.16e3, 1x))', iostat=ios) finite(p)
    end do
    if (ios == 0) write(unit, '(a, i0, 1x, i0)', iostat=ios) "CELLS ", n + nc, 2*n + 3*nc
    do i = 1, n
      if (ios /= 0) exit
      write(unit, '(a, i0)', iostat=ios) "1 ", i - 1
    end do
    do i = 1, nc
      if (ios /= 0) exit
      write(unit, '(a, i0, 1x, i0)', iostat=ios) "2 ", pairs(1, i) - 1, pairs(2, i) - 1
    end do
    if (ios == 0) write(unit, '(a, i0)', iostat=ios) "CELL_TYPES ", n + nc
    do i = 1, n + nc
      if (ios /= 0) exit
      write(unit, '(i0)', iostat=ios) merge(1, 3, i <= n)
    end do
    if (size(point_fields) > 0 .and. ios == 0) write(unit, '(a, i0)', iostat=ios) "POINT_DATA ", n
    do f = 1, size(point_fields)
      if (ios /= 0) exit
      call write_scalars(unit, point_fields(f)%name, point_fields(f)%values, 0, ios)
    end do
    if (present(contact_fields)) then
      if (size(contact_fields) > 0 .and. ios == 0) write(unit, '(a, i0)', iostat=ios) "CELL_DATA ", n + nc
      do f = 1, size(contact_fields)
        if (ios /= 0) exit
        ! the vertex cells first (0), then the lines
        call write_scalars(unit, contact_fields(f)%name, contact_fields(f)%values, n, ios)
      end do
    end if
    if (ios /= 0) then
      close(unit, status="delete")
      call set_status(status, demstep_stat%io_error, "write failed (the file is removed)", where=path)
      return
    end if
    close(unit, iostat=ios)
    if (ios /= 0) then
      call set_status(status, demstep_stat%io_error, "close failed", where=path)
      return
    end if
    status%stat = demstep_stat%ok
  end subroutine write_vtk_particles

  !> One SCALARS block: `zeros` zeros, then the values.
  subroutine write_scalars(unit, name, values, zeros, ios)
    integer, intent(in) :: unit, zeros
    character(len=*), intent(in) :: name
    real(dp), intent(in) :: values(:)
    integer, intent(inout) :: ios
    integer :: i
    if (ios == 0) write(unit, '(a)', iostat=ios) "SCALARS "//name//" double 1"
    if (ios == 0) write(unit, '(a)', iostat=ios) "LOOKUP_TABLE default"
    do i = 1, zeros
      if (ios /= 0) return
      write(unit, '(a)', iostat=ios) "0"
    end do
    do i = 1, size(values)
      if (ios /= 0) return
      write(unit, '(es24.16e3)', iostat=ios) finite(values(i:i))
    end do
  end subroutine write_scalars

  !> Values with non-finite entries replaced by 0 (VTK readers reject NaN text).
  pure function finite(v) result(w)
    real(dp), intent(in) :: v(:)
    real(dp) :: w(size(v))
    w = merge(v, 0.0_dp, ieee_is_finite(v))
  end function finite

  !> A VTK array name: non-empty, printable, no blanks.
  pure logical function field_name_ok(name)
    character(len=*), intent(in) :: name
    integer :: i
    field_name_ok = len(name) > 0 .and. len(name) <= 64
    do i = 1, len(name)
      if (iachar(name(i:i)) <= 32 .or. iachar(name(i:i)) >= 127) field_name_ok = .false.
    end do
  end function field_name_ok

end module demstep_vtk
