!> A LIGGGHTS input script turned into a scene's contacts: the scene's
!> particles come from a snapshot (a LIGGGHTS dump or data file), everything
!> else from the script as LIGGGHTS reads it ([[demstep_liggghts_script]]):
!> the materials per type in LIGGGHTS' own convention, the contact model and
!> its options, the primitive walls, the rolling springs, friction, gravity,
!> and the checks that script and snapshot agree (dimension, types, periodic
!> axes). What cannot be reproduced is refused naming the script's file,
!> line and command; nothing is taken by default.
!>
!> Each contact's stiffness is LIGGGHTS': Hertz from the pair's E*, G* at its
!> own overlap and R*; Hooke from the pair's own R* and m* (LIGGGHTS computes
!> k_n per contact, normal_model_hooke.h:269), so a snapshot whose particles
!> of one type have several radii needs no splitting into types.
module demstep_liggghts_scene
  use demstep_kinds, only: dp, pi
  use demstep_status, only: demstep_status_type, demstep_stat, set_status
  use demstep_text, only: int_text
  use demstep_material, only: material_type
  use demstep_scene_data, only: scene_type, scene_effect
  use demstep_scene_builders, only: scene_add_walls, scene_set_gravity, scene_set_friction, scene_set_rolling
  use demstep_scene_materials, only: scene_set_materials
  use demstep_snapshot, only: snapshot_type
  use demstep_liggghts_script, only: liggghts_script_type, liggghts_contacts_type, read_liggghts_script, &
    liggghts_script_contacts
  implicit none
  private

  public :: scene_from_liggghts_script, script_timestep_ratio

  !> What a script gave a scene, for the report.
  type, public :: liggghts_scene_type
    !> The script as read and its contacts in demstep's terms.
    type(liggghts_script_type) :: script
    type(liggghts_contacts_type) :: contacts
    !> The script's file name.
    character(len=:), allocatable :: file
    !> The script's `timestep` (0 when it has none), its file (the script's
    !> or an included one) and line.
    real(dp) :: timestep = 0.0_dp
    character(len=:), allocatable :: timestep_file
    integer :: timestep_line = 0
  end type liggghts_scene_type

contains

  !> The script's `timestep` over a limit `dt_limit` (> 0): 0 when the
  !> script states no timestep.
  pure real(dp) function script_timestep_ratio(info, dt_limit) result(ratio)
    type(liggghts_scene_type), intent(in) :: info
    real(dp), intent(in) :: dt_limit
    ratio = 0.0_dp
    if (info%timestep_line > 0 .and. dt_limit > 0.0_dp) ratio = info%timestep/dt_limit
  end function script_timestep_ratio

  !> Give `scene` (its particles, types and periodic cell already from
  !> `snapshot`) the contacts of the LIGGGHTS script `path`: materials per
  !> type (`scene_set_materials` in the script's convention, Hooke per
  !> contact), walls (a lone plane's side: the particles'), rolling springs,
  !> friction and gravity, with the effects they imply (`contacts`, `rotation`, `damping` when the restitution is
  !> below 1, `walls`, `gravity`). Status `io_error` for an unreadable file,
  !> `invalid_input` for what cannot be read or reproduced, or where the
  !> script and the snapshot disagree: `FILE: line N: command: what`.
  subroutine scene_from_liggghts_script(scene, path, snapshot, info, status)
    type(scene_type), intent(inout) :: scene
    !> The script's file name (included files relative to its directory).
    character(len=*), intent(in) :: path
    !> The snapshot the scene's particles came from (types, one per particle).
    type(snapshot_type), intent(in) :: snapshot
    type(liggghts_scene_type), intent(out) :: info
    type(demstep_status_type), intent(out) :: status
    type(material_type), allocatable :: mats(:)
    real(dp), allocatable :: points(:, :), normals(:, :)
    integer :: nt, t, k, dim
    call read_liggghts_script(path, info%script, status)
    if (status%stat /= demstep_stat%ok) return
    call side_from_particles(info%script)
    call liggghts_script_contacts(info%script, info%contacts, status, file=path)
    if (status%stat /= demstep_stat%ok) return
    associate (s => info%script, c => info%contacts)
      dim = scene%dim
      if (s%dimension /= dim) then
        call fault(s%dimension_line, "dimension", "the script is "//int_text(s%dimension)//"D, the scene " &
          //int_text(dim)//"D")
        return
      end if
      if (size(snapshot%type) /= scene%n) then
        call set_status(status, demstep_stat%invalid_input, "the snapshot has "//int_text(size(snapshot%type)) &
          //" particles, the scene "//int_text(scene%n), where="snapshot")
        return
      end if
      nt = size(c%young)
      if (maxval(snapshot%type) > nt) then
        k = maxloc(snapshot%type, dim=1)
        call fault(s%young_line, "fix property/global", "youngsModulus gives "//int_text(nt)//" atom type"// &
          trim(merge("s", " ", nt > 1))//", the snapshot's particle "//int_text(snapshot%id(k))// &
          " is of type "//int_text(snapshot%type(k)))
        return
      end if
      if (s%boundary_line > 0 .and. any(s%periodic(:dim) .neqv. scene%periodic(:dim))) then
        call fault(s%boundary_line, "boundary", "the periodic axes differ from the snapshot's box ("// &
          axes(scene%periodic(:dim))//")")
        return
      end if
      ! the types' materials; radius and density of a particle of the type
      ! (only rounding depends on them: Hertz takes each contact's R*, Hooke
      ! its R* and m*)
      allocate(mats(nt))
      do t = 1, nt
        k = findloc(snapshot%type, t, dim=1)
        if (k == 0) k = 1
        mats(t) = material_type(young=c%young(t), poisson=c%poisson(t), radius=scene%radius(k), &
          density=scene%mass(k)/(4.0_dp/3.0_dp*pi*scene%radius(k)**3))
      end do
      if (c%impact_velocity > 0.0_dp) then
        call scene_set_materials(scene, snapshot%type, mats, c%convention, c%restitution, status, &
          impact_velocity=c%impact_velocity, wall_type=c%wall_type, tangential_damping=c%tangential_damping, &
          per_contact=.true.)
      else
        call scene_set_materials(scene, snapshot%type, mats, c%convention, c%restitution, status, &
          wall_type=c%wall_type, tangential_damping=c%tangential_damping, per_contact=.true.)
      end if
      if (status%stat /= demstep_stat%ok) then
        ! the library names the material's variable: the script's command that gave it
        select case (status%where)
        case ("young")
          call fault(s%young_line, "fix property/global", "youngsModulus: "//(status%message))
        case ("poisson")
          call fault(s%poisson_line, "fix property/global", "poissonsRatio: "//(status%message))
        case ("restitution")
          call fault(s%restitution_line, "fix property/global", "coefficientRestitution: "//(status%message))
        case ("wall_type")
          call fault(s%walls(1)%line, "fix wall/gran", "primitive type: "//(status%message), s%walls(1)%file)
        case ("impact_velocity")
          call fault(s%velocity_line, "fix property/global", "characteristicVelocity: "//(status%message))
        case default
          call fault(s%pair%line, "pair_style", (status%message), s%pair%file)
        end select
        return
      end if
      scene%effects(scene_effect%contacts) = .true.
      if (s%n_walls > 0) then
        if (any(c%wall_normals(dim + 1:, :) /= 0.0_dp)) then
          k = findloc(any(c%wall_normals(dim + 1:, :) /= 0.0_dp, dim=1), .true., dim=1)
          call fault(s%walls(k)%line, "fix wall/gran", "wall '"//s%walls(k)%id//"' is normal to an axis " &
            //"beyond the scene's "//int_text(dim)//"D", s%walls(k)%file)
          return
        end if
        points = c%wall_points(:dim, :)
        normals = c%wall_normals(:dim, :)
        call scene_add_walls(scene, points, normals, status)
        if (status%stat /= demstep_stat%ok) then
          call fault(s%walls(1)%line, "fix wall/gran", (status%message), s%walls(1)%file)
          return
        end if
        scene%effects(scene_effect%walls) = .true.
      end if
      call scene_set_rolling(scene, c%rolling_ratio, 0.0_dp, status)
      if (status%stat == demstep_stat%ok) call scene_set_friction(scene, c%friction, status, &
        rolling_friction=c%rolling_friction)
      if (status%stat /= demstep_stat%ok) then
        call fault(s%friction_line, "fix property/global", (status%message))
        return
      end if
      if (any(s%gravity /= 0.0_dp)) then
        if (any(s%gravity(dim + 1:) /= 0.0_dp)) then
          call fault(s%gravity_line, "fix gravity", "points out of the scene's "//int_text(dim)//"D")
          return
        end if
        call scene_set_gravity(scene, s%gravity(:dim), status)
        if (status%stat /= demstep_stat%ok) then
          call fault(s%gravity_line, "fix gravity", (status%message))
          return
        end if
        scene%effects(scene_effect%gravity) = .true.
      end if
      info%timestep = s%timestep
      info%timestep_line = s%timestep_line
      info%timestep_file = path
      if (allocated(s%timestep_file)) info%timestep_file = s%timestep_file
    end associate
    info%file = path
    status%stat = demstep_stat%ok
  contains
    !> `FILE: line N: command: what` (the script's file unless another is given).
    subroutine fault(line, command, what, where_file)
      integer, intent(in) :: line
      character(len=*), intent(in) :: command, what
      character(len=:), allocatable, intent(in), optional :: where_file
      character(len=:), allocatable :: name, detail
      name = path
      if (present(where_file)) then
        if (allocated(where_file)) name = where_file
      end if
      detail = what
      call set_status(status, demstep_stat%invalid_input, detail, where=command)
      if (line > 0) then
        status%message = name//": line "//int_text(line)//": "//status%message
      else
        status%message = name//": "//status%message
      end if
    end subroutine fault
    !> A wall whose side the script does not tell (no `create_box` block, a
    !> lone plane on its axis): the side all the snapshot's particles are on.
    pure subroutine side_from_particles(script)
      type(liggghts_script_type), intent(inout) :: script
      integer :: w, axis
      do w = 1, script%n_walls
        if (any(script%walls(w)%normal /= 0.0_dp)) cycle
        axis = script%walls(w)%axis
        if (all(scene%x(axis, :) > script%walls(w)%position)) script%walls(w)%normal(axis) = 1.0_dp
        if (all(scene%x(axis, :) < script%walls(w)%position)) script%walls(w)%normal(axis) = -1.0_dp
      end do
    end subroutine side_from_particles
    !> The periodic axes as words (`x y`, `none`).
    pure function axes(periodic) result(text)
      logical, intent(in) :: periodic(:)
      character(len=:), allocatable :: text
      integer :: a
      text = ""
      do a = 1, size(periodic)
        if (periodic(a)) text = text//" "//achar(iachar("x") + a - 1)
      end do
      if (len(text) == 0) text = " none"
      text = "periodic:"//text
    end function axes
  end subroutine scene_from_liggghts_script

end module demstep_liggghts_scene
