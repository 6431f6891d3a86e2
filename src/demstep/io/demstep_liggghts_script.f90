!> Reader of LIGGGHTS input scripts, as they are: what a script says about
!> the contacts, for the scene's materials, walls, periodicity and gravity.
!>
!> A script is read as LIGGGHTS 3.8 reads it (LIGGGHTS-PUBLIC src/input.cpp):
!> a line ending in `&` continues on the next (input.cpp:191-213), `#` starts
!> a comment outside quotes (:351-364), then `$x`, `${name}` and `$(formula)`
!> are substituted outside quotes (Input::substitute, :435-531; values of
!> equal-style variables with 15 significant digits, immediate formulas with
!> 20: [[demstep_liggghts_formula]]), and the line is split into words, a
!> quoted text being one word (:407-430).
!>
!> Read, with their effect: `units` (si, cgs), `dimension`, `boundary`
!> (periodic axes), `variable` (equal, index, string, loop, atom, delete),
!> `include`, `region ... block` with `create_box` (the number of types and
!> the box, whose centre orients the walls' normals), `fix property/global`
!> (youngsModulus, poissonsRatio per type; coefficientRestitution,
!> coefficientFriction, coefficientRollingFriction per type pair, symmetric as
!> fix_property_global.cpp:154-170 demands; characteristicVelocity;
!> cohesionEnergyDensity refused until demstep has cohesion), `pair_style gran`
!> (model, tangential, cohesion, rolling_friction, surface in that order,
!> contact_models.cpp:170-260, then the models' on/off settings
!> tangential_damping, limitForce, ktToKnUser, ...), `fix wall/gran` with a
!> primitive plane (`primitive type T xplane|yplane|zplane position`,
!> fix_wall_gran.cpp:188-226), `fix gravity ... vector` (the direction
!> normalised, fix_gravity.cpp:379-384), `fix particletemplate/sphere`
!> (constant radius and density per type) and `timestep`.
!>
!> Commands that do not bear on the contacts (output, neighbour lists,
!> insertion, integration, runs, control flow, ...) are passed over; control
!> flow (`if`, `jump`, `label`, `next`, `print`) is not followed and its line
!> not substituted. Anything else is refused, naming the file, line and
!> command: never a silent default. Reading files makes this module impure.
module demstep_liggghts_script
  use demstep_kinds, only: dp
  use demstep_status, only: demstep_status_type, demstep_stat, set_status
  use demstep_text, only: int_text, comment_start
  use demstep_text, only: read_text_file
  use demstep_material, only: code_convention
  use demstep_liggghts_formula, only: liggghts_variable_type, liggghts_evaluate, liggghts_number_text, &
    liggghts_find_variable
  implicit none
  private

  public :: read_liggghts_script, parse_liggghts_script, liggghts_script_contacts

  !> Unit systems (`units`).
  type, public :: liggghts_units_codes
    !> Not given.
    integer :: none = 0
    !> `units si`.
    integer :: si = 1
    !> `units cgs`.
    integer :: cgs = 2
  end type liggghts_units_codes
  !> The unit systems by name.
  type(liggghts_units_codes), parameter, public :: liggghts_units = liggghts_units_codes()

  !> A granular contact model, as `pair_style gran` or `fix wall/gran` states it.
  type, public :: liggghts_model_type
    !> True once stated.
    logical :: defined = .false.
    !> `model` (hertz, hooke, hertz/stiffness, hooke/stiffness, ...), `tangential`
    !> (default off), `cohesion` (off), `rolling_friction` (off), `surface` (default).
    character(len=:), allocatable :: model, tangential, cohesion, rolling, surface
    !> The models' settings: `tangential_damping` (default on), `limitForce`,
    !> `ktToKnUser` (default off).
    logical :: tangential_damping = .true., limit_force = .false., kt_to_kn_user = .false.
    !> Where it is stated.
    character(len=:), allocatable :: file
    integer :: line = 0
  end type liggghts_model_type

  !> A primitive plane wall (`fix ID group wall/gran ... primitive type T xplane x`).
  type, public :: liggghts_wall_type
    !> The fix's ID.
    character(len=:), allocatable :: id
    !> Axis of the plane's normal (1, 2, 3 for xplane, yplane, zplane) and its position.
    integer :: axis = 0
    real(dp) :: position = 0.0_dp
    !> The wall's material: atom type T.
    integer :: wall_type = 0
    !> Inward unit normal (see `orient_walls`; zero when the script does not
    !> tell the side).
    real(dp) :: normal(3) = 0.0_dp
    !> Its contact model.
    type(liggghts_model_type) :: model
    !> Where it is stated.
    character(len=:), allocatable :: file
    integer :: line = 0
  end type liggghts_wall_type

  !> A particle template with a constant radius and density
  !> (`fix ID group particletemplate/sphere seed atom_type t density constant rho radius constant r`).
  type, public :: liggghts_template_type
    !> The fix's ID and its atom type.
    character(len=:), allocatable :: id
    integer :: atom_type = 0
    !> Radius and density (0 where not constant).
    real(dp) :: radius = 0.0_dp, density = 0.0_dp
    integer :: line = 0
  end type liggghts_template_type

  !> A `region ID block` (other styles have `known = .false.`).
  type, public :: liggghts_region_type
    character(len=:), allocatable :: id
    logical :: known = .false.
    real(dp) :: lo(3) = 0.0_dp, hi(3) = 0.0_dp
  end type liggghts_region_type

  !> What a script says about the contacts (the state at its end).
  type, public :: liggghts_script_type
    !> `liggghts_units%...`.
    integer :: units = 0
    !> `dimension` (3 unless stated).
    integer :: dimension = 3
    !> Periodic axes (`boundary p ...`).
    logical :: periodic(3) = .false.
    !> Lines of `units`, `dimension` and `boundary` (0 when not given).
    integer :: units_line = 0, dimension_line = 0, boundary_line = 0
    !> Number of atom types (`create_box N`, else the count of the per-type
    !> properties; 0 when neither).
    integer :: n_types = 0
    !> The simulation box, when `create_box` names a `block` region.
    logical :: box_known = .false.
    real(dp) :: box_lo(3) = 0.0_dp, box_hi(3) = 0.0_dp
    !> Per type: `youngsModulus`, `poissonsRatio` (unallocated when not given).
    real(dp), allocatable :: young(:), poisson(:)
    !> Per type pair: `coefficientRestitution`, `coefficientFriction`,
    !> `coefficientRollingFriction` (unallocated when not given).
    real(dp), allocatable :: restitution(:, :), friction(:, :), rolling_friction(:, :)
    !> `characteristicVelocity` (0 when not given; Hooke models need it).
    real(dp) :: characteristic_velocity = 0.0_dp
    !> Lines of the properties (0 when not given), in the order above.
    integer :: young_line = 0, poisson_line = 0, restitution_line = 0, friction_line = 0, &
      rolling_friction_line = 0, velocity_line = 0
    !> `pair_style gran`.
    type(liggghts_model_type) :: pair
    !> The primitive plane walls.
    integer :: n_walls = 0
    type(liggghts_wall_type), allocatable :: walls(:)
    !> `fix gravity`: the acceleration vector (zero without one).
    real(dp) :: gravity(3) = 0.0_dp
    integer :: gravity_line = 0
    !> The last `timestep` (0 when none), its file and line.
    real(dp) :: timestep = 0.0_dp
    character(len=:), allocatable :: timestep_file
    integer :: timestep_line = 0
    !> Particle templates with constant radius and density.
    integer :: n_templates = 0
    type(liggghts_template_type), allocatable :: templates(:)
    !> The variables at the end of the script.
    integer :: n_vars = 0
    type(liggghts_variable_type), allocatable :: vars(:)
    !> The regions seen.
    integer :: n_regions = 0
    type(liggghts_region_type), allocatable :: regions(:)
  end type liggghts_script_type

  !> What a script gives a scene's contacts, in demstep's terms (the arguments
  !> of `scene_set_materials` and the scene's walls, rolling springs and
  !> periodicity); the particles' radii, densities and types come from the snapshot.
  type, public :: liggghts_contacts_type
    !> `code_convention%liggghts_hertz` or `%liggghts_hooke`.
    integer :: convention = 0
    !> Per type: Young's modulus and Poisson's ratio.
    real(dp), allocatable :: young(:), poisson(:)
    !> The restitution, the same for every type pair.
    real(dp) :: restitution = 1.0_dp
    !> Hooke: `characteristicVelocity`; Hertz: 0 (the script has none).
    real(dp) :: impact_velocity = 0.0_dp
    !> LIGGGHTS' `tangential_damping`.
    logical :: tangential_damping = .true.
    !> `rolling_ratio`: 1 for `rolling_friction epsd2` (k_r = k_t R*^2), 0 for
    !> `off` and `cdt` (a constant torque, no stiffness).
    real(dp) :: rolling_ratio = 0.0_dp
    !> The walls' material type (0 without walls) and, per wall, a point and the inward normal.
    integer :: wall_type = 0
    real(dp), allocatable :: wall_points(:, :), wall_normals(:, :)
    !> Coulomb friction and rolling friction, the same for every type pair
    !> (-1 when the script gives none, or `friction_per_pair`: no sliding, no
    !> cap; the limit takes every contact sticking either way).
    real(dp) :: friction = -1.0_dp, rolling_friction = -1.0_dp
    !> The script's friction or rolling friction differs between type pairs
    !> (demstep's scene takes one value: none is taken).
    logical :: friction_per_pair = .false.
    !> Periodic axes as the script's `boundary` states them (after
    !> `read_restart` or `read_data` the restart or data file has them: take
    !> the snapshot's box then).
    logical :: periodic(3) = .false.
  end type liggghts_contacts_type

  !> One word of a command.
  type :: word_type
    character(len=:), allocatable :: text
  end type word_type

  !> Deepest nesting of `include`.
  integer, parameter :: max_include_depth = 16

  !> Commands with no bearing on the contacts.
  character(len=*), parameter :: passed_commands(*) = [character(len=16) :: "atom_style", "atom_modify", &
    "communicate", "comm_modify", "newton", "processors", "neighbor", "neigh_modify", "thermo", &
    "thermo_style", "thermo_modify", "thermo_log", "compute", "compute_modify", "uncompute", "dump", &
    "dump_modify", "undump", "run", "restart", "write_restart", "write_dump", "write_data", "read_restart", &
    "read_data", "read_dump", "group", "create_atoms", "lattice", "set", "velocity", "mass", "unfix", &
    "reset_timestep", "pair_coeff", "soft_particles", "hard_particles", "delete_atoms", "displace_atoms", &
    "fix_modify", "balance", "run_style", "orient", "modify_timing", "partition", "clear"]
  !> Control flow: not followed, not substituted.
  character(len=*), parameter :: control_commands(*) = [character(len=8) :: "if", "jump", "label", "next", &
    "print", "shell", "echo", "log", "quit"]
  !> Fix styles with no bearing on the contacts.
  character(len=*), parameter :: passed_fixes(*) = [character(len=40) :: "nve/sphere", "nve", "nve/limit", &
    "nve/asphere", "insert/pack", "insert/stream", "insert/rate/region", "particledistribution/discrete", &
    "particledistribution/discrete/numberbased", "particledistribution/discrete/massbased", "adapt", &
    "freeze", "mesh/surface", "mesh/surface/stress", "mesh/surface/planar", "move/mesh", &
    "check/timestep/gran", "ave/time", "ave/atom", "ave/euler", "ave/spatial", "print", "enforce2d", &
    "heat/gran", "heat/gran/conduction", "property/atom", "property/atom/tracer", "setforce", "addforce", &
    "momentum", "wall/region/sph", "store/state", "contactproperty/atom/wall"]
  !> `fix property/global` names with no bearing on the mechanical contacts.
  !> (coefficientRollingViscousDamping: the rolling dashpot of epsd and epsd3,
  !> which are refused; epsd2 has none, rolling_model_epsd2.h:226.)
  character(len=*), parameter :: passed_properties(*) = [character(len=32) :: "thermalConductivity", &
    "thermalCapacity", "k_finnie", "coefficientRollingViscousDamping"]
  !> The on/off settings of LIGGGHTS 3.8's granular models without bearing on
  !> the step (normal_model_hertz.h:90-96, normal_model_hooke.h:97-105,
  !> tangential_model_history.h:110-112, rolling_model_epsd2.h:83).
  character(len=*), parameter :: passed_settings(*) = [character(len=28) :: "heating_normal_hertz", &
    "heating_normal_hooke", "heating_tangential_history", "heating_tracking", "computeElasticPotential", &
    "computeDissipatedEnergy", "disableNormalWhenBonded", "torsionTorque"]

contains

  !> Read a LIGGGHTS input script (and the files it includes, relative to its
  !> directory). Status `io_error` for an unreadable file, `invalid_input`
  !> for what the reader cannot read: `FILE: line N: command: what is wrong`,
  !> `where` the command.
  subroutine read_liggghts_script(path, script, status)
    !> The script's file name.
    character(len=*), intent(in) :: path
    !> What it says.
    type(liggghts_script_type), intent(out) :: script
    type(demstep_status_type), intent(out) :: status
    call read_file(path, script, status, 0)
    if (status%stat == demstep_stat%ok) call orient_walls(script)
  end subroutine read_liggghts_script

  !> Read a script's text; `include` names files relative to `directory`
  !> (default: the working directory); messages name `name` as the file
  !> (default `script`). Status as [[read_liggghts_script]].
  subroutine parse_liggghts_script(text, script, status, directory, name)
    !> The script.
    character(len=*), intent(in) :: text
    type(liggghts_script_type), intent(out) :: script
    type(demstep_status_type), intent(out) :: status
    !> Directory of included files and name of the script in messages.
    character(len=*), intent(in), optional :: directory, name
    character(len=:), allocatable :: dir, label
    dir = ""
    if (present(directory)) dir = directory
    label = "script"
    if (present(name)) label = name
    call run_text(text, label, dir, script, status, 0)
    if (status%stat == demstep_stat%ok) call orient_walls(script)
  end subroutine parse_liggghts_script

  !> What the script gives a scene's contacts ([[liggghts_contacts_type]]).
  !> Status `invalid_input` for what demstep's conventions do not cover, naming
  !> the script's command and line (`FILE: line N: command: what`; a missing
  !> property or pair style without a line): a model other than hertz or hooke,
  !> tangential other than history, a surface model, `ktToKnUser on`, rolling
  !> friction epsd or epsd3, a restitution that differs between type pairs,
  !> a wall whose model differs from the pair style's, walls of different types,
  !> a wall whose side the script does not tell, Hooke without
  !> characteristicVelocity.
  subroutine liggghts_script_contacts(script, contacts, status, file)
    !> The script as read.
    type(liggghts_script_type), intent(in) :: script
    type(liggghts_contacts_type), intent(out) :: contacts
    type(demstep_status_type), intent(out) :: status
    !> The script's name in messages (default `script`).
    character(len=*), intent(in), optional :: file
    character(len=:), allocatable :: name
    integer :: k
    name = "script"
    if (present(file)) name = file
    status%stat = demstep_stat%ok
    if (.not. script%pair%defined) then
      call set_status(status, demstep_stat%invalid_input, "missing: the script states no 'pair_style gran'", &
        where="pair_style")
      status%message = name//": "//status%message
      return
    end if
    call check_model(script%pair, "pair_style")
    if (status%stat /= demstep_stat%ok) return
    contacts%convention = merge(code_convention%liggghts_hertz, code_convention%liggghts_hooke, &
      script%pair%model == "hertz")
    contacts%tangential_damping = script%pair%tangential_damping
    contacts%rolling_ratio = merge(1.0_dp, 0.0_dp, script%pair%rolling == "epsd2")
    if (.not. allocated(script%young) .or. .not. allocated(script%poisson)) then
      call set_status(status, demstep_stat%invalid_input, "missing: 'fix property/global " &
        //trim(merge("youngsModulus", "poissonsRatio", .not. allocated(script%young)))//" peratomtype ...'", &
        where=trim(merge("youngsModulus", "poissonsRatio", .not. allocated(script%young))))
      status%message = name//": "//status%message
      return
    end if
    contacts%young = script%young
    contacts%poisson = script%poisson
    if (.not. allocated(script%restitution)) then
      call set_status(status, demstep_stat%invalid_input, "missing: 'fix property/global coefficientRestitution " &
        //"peratomtypepair ...'", where="coefficientRestitution")
      status%message = name//": "//status%message
      return
    end if
    if (any(script%restitution /= script%restitution(1, 1))) then
      call fault(script%restitution_line, "fix property/global", "coefficientRestitution differs between type " &
        //"pairs; demstep's scene takes one restitution")
      return
    end if
    contacts%restitution = script%restitution(1, 1)
    ! friction caps the springs in a run, not the limit (every contact sticks):
    ! one value per scene, none when the type pairs differ (`friction_per_pair`)
    if (allocated(script%friction)) then
      contacts%friction_per_pair = any(script%friction /= script%friction(1, 1))
      if (.not. contacts%friction_per_pair) contacts%friction = script%friction(1, 1)
    end if
    if (allocated(script%rolling_friction) .and. script%pair%rolling /= "off") then
      if (any(script%rolling_friction /= script%rolling_friction(1, 1))) then
        contacts%friction_per_pair = .true.
      else
        contacts%rolling_friction = script%rolling_friction(1, 1)
      end if
    end if
    if (contacts%convention == code_convention%liggghts_hooke) then
      if (.not. (script%characteristic_velocity > 0.0_dp)) then
        call fault(script%pair%line, "pair_style", "model hooke needs 'fix property/global " &
          //"characteristicVelocity scalar v'", script%pair%file)
        return
      end if
      contacts%impact_velocity = script%characteristic_velocity
    end if
    contacts%periodic = script%periodic
    allocate(contacts%wall_points(3, script%n_walls), contacts%wall_normals(3, script%n_walls))
    contacts%wall_points = 0.0_dp
    do k = 1, script%n_walls
      associate (w => script%walls(k))
        call check_model(w%model, "fix wall/gran")
        if (status%stat /= demstep_stat%ok) return
        if (w%model%model /= script%pair%model .or. w%model%tangential /= script%pair%tangential .or. &
          w%model%rolling /= script%pair%rolling .or. (w%model%tangential_damping .neqv. &
          script%pair%tangential_damping)) then
          call fault(w%line, "fix wall/gran", "wall '"//w%id//"': its model differs from the pair style's " &
            //"(line "//int_text(script%pair%line)//"); demstep's walls take the particles' law", w%file)
          return
        end if
        if (k > 1 .and. w%wall_type /= script%walls(1)%wall_type) then
          call fault(w%line, "fix wall/gran", "wall '"//w%id//"' is of type "//int_text(w%wall_type)// &
            ", wall '"//script%walls(1)%id//"' of type "//int_text(script%walls(1)%wall_type)// &
            "; demstep's walls are of one type", w%file)
          return
        end if
        if (all(w%normal == 0.0_dp)) then
          call fault(w%line, "fix wall/gran", "wall '"//w%id//"': the script does not tell its side (no " &
            //"create_box with a block region, no opposite plane)", w%file)
          return
        end if
        contacts%wall_points(w%axis, k) = w%position
        contacts%wall_normals(:, k) = w%normal
      end associate
    end do
    if (script%n_walls > 0) contacts%wall_type = script%walls(1)%wall_type
  contains
    !> A model demstep's LIGGGHTS conventions cover.
    subroutine check_model(model, command)
      type(liggghts_model_type), intent(in) :: model
      character(len=*), intent(in) :: command
      if (model%model /= "hertz" .and. model%model /= "hooke") then
        call fault(model%line, command, "model '"//model%model//"': demstep reproduces LIGGGHTS' hertz and " &
          //"hooke", model%file)
      else if (model%tangential /= "history") then
        call fault(model%line, command, "tangential '"//model%tangential//"': demstep's tangential springs " &
          //"are LIGGGHTS' 'history'", model%file)
      else if (model%surface /= "default") then
        call fault(model%line, command, "surface '"//model%surface//"' is not reproduced", model%file)
      else if (model%kt_to_kn_user) then
        call fault(model%line, command, "ktToKnUser on is not reproduced (demstep's k_t is the model's own)", model%file)
      else if (model%rolling /= "off" .and. model%rolling /= "cdt" .and. model%rolling /= "epsd2") then
        call fault(model%line, command, "rolling_friction '"//model%rolling//"': demstep reproduces off, cdt " &
          //"(no stiffness) and epsd2 (k_r = k_t R*^2)", model%file)
      end if
    end subroutine check_model
    !> `FILE: line N: command: what` (the file where the command is, when known).
    subroutine fault(line, command, what, where_file)
      integer, intent(in) :: line
      character(len=*), intent(in) :: command, what
      character(len=:), allocatable, intent(in), optional :: where_file
      call set_status(status, demstep_stat%invalid_input, what, where=command)
      if (present(where_file)) then
        if (allocated(where_file)) then
          status%message = where_file//": line "//int_text(line)//": "//status%message
          return
        end if
      end if
      status%message = name//": line "//int_text(line)//": "//status%message
    end subroutine fault
  end subroutine liggghts_script_contacts

  !> The walls' inward normals: towards the box's centre when `create_box`
  !> names a block region, else, on an axis with planes at two or more
  !> positions, towards the middle of the outermost two; zero otherwise (a
  !> lone plane without a box: the side is the particles').
  pure subroutine orient_walls(script)
    type(liggghts_script_type), intent(inout) :: script
    integer :: k, axis
    real(dp) :: centre, lo, hi
    do k = 1, script%n_walls
      axis = script%walls(k)%axis
      script%walls(k)%normal = 0.0_dp
      if (script%box_known) then
        centre = 0.5_dp*(script%box_lo(axis) + script%box_hi(axis))
      else
        lo = minval(script%walls(1:script%n_walls)%position, mask=script%walls(1:script%n_walls)%axis == axis)
        hi = maxval(script%walls(1:script%n_walls)%position, mask=script%walls(1:script%n_walls)%axis == axis)
        if (.not. (hi > lo)) cycle
        centre = 0.5_dp*(lo + hi)
      end if
      if (centre /= script%walls(k)%position) &
        script%walls(k)%normal(axis) = sign(1.0_dp, centre - script%walls(k)%position)
    end do
  end subroutine orient_walls

  recursive subroutine read_file(path, script, status, depth)
    character(len=*), intent(in) :: path
    type(liggghts_script_type), intent(inout) :: script
    type(demstep_status_type), intent(out) :: status
    integer, intent(in) :: depth
    character(len=:), allocatable :: text
    integer :: slash
    call read_text_file(path, text, status)
    if (status%stat /= demstep_stat%ok) then
      status%message = path//": "//status%message
      return
    end if
    slash = index(path, "/", back=.true.)
    call run_text(text, path, path(1:slash), script, status, depth)
  end subroutine read_file

  !> Read the commands of one file's text.
  recursive subroutine run_text(text, file, dir, script, status, depth)
    character(len=*), intent(in) :: text, file, dir
    type(liggghts_script_type), intent(inout) :: script
    type(demstep_status_type), intent(out) :: status
    integer, intent(in) :: depth
    integer :: start, finish, line, first_line, m
    character(len=:), allocatable :: statement
    logical :: continued
    status%stat = demstep_stat%ok
    if (.not. allocated(script%vars)) allocate(script%vars(8), script%walls(4), script%templates(4), &
      script%regions(4))
    start = 1
    line = 0
    statement = ""
    continued = .false.
    first_line = 1
    do while (start <= len(text))
      finish = index(text(start:), achar(10))
      if (finish == 0) then
        finish = len(text) + 1
      else
        finish = start + finish - 1
      end if
      line = line + 1
      if (.not. continued) then
        statement = ""
        first_line = line
      end if
      ! a trailing '&' (after blanks) continues the line on the next
      m = finish - 1
      do while (m >= start)
        if (.not. is_space(text(m:m))) exit
        m = m - 1
      end do
      continued = .false.
      if (m >= start) then
        if (text(m:m) == "&") then
          continued = .true.
          statement = statement//text(start:m - 1)
        end if
      end if
      if (.not. continued) then
        if (m >= start) statement = statement//text(start:m)
        call run_statement(statement, file, first_line, dir, script, status, depth)
        if (status%stat /= demstep_stat%ok) return
      end if
      start = finish + 1
    end do
    if (continued) call run_statement(statement, file, first_line, dir, script, status, depth)
  end subroutine run_text

  !> One command: comment stripped, substituted, split, executed.
  recursive subroutine run_statement(raw, file, line, dir, script, status, depth)
    character(len=*), intent(in) :: raw, file, dir
    integer, intent(in) :: line, depth
    type(liggghts_script_type), intent(inout) :: script
    type(demstep_status_type), intent(out) :: status
    character(len=:), allocatable :: s, command
    type(word_type), allocatable :: words(:)
    integer :: n, k
    status%stat = demstep_stat%ok
    s = raw(1:comment_start(raw, "#") - 1)
    ! control flow: neither followed nor substituted
    call split_words(s, words, n, status)
    if (status%stat /= demstep_stat%ok) then
      call locate(status, file, line, "")
      return
    end if
    if (n == 0) return
    if (any(control_commands == words(1)%text)) return
    call substitute(s, script, status)
    if (status%stat /= demstep_stat%ok) then
      call locate(status, file, line, words(1)%text)
      return
    end if
    call split_words(s, words, n, status)
    if (status%stat /= demstep_stat%ok) then
      call locate(status, file, line, "")
      return
    end if
    if (n == 0) return
    command = words(1)%text
    select case (command)
    case ("units")
      call units_command(words, n, script, status)
      script%units_line = line
    case ("dimension")
      script%dimension_line = line
      call count_check(n, 2, status)
      if (status%stat == demstep_stat%ok) then
        if (words(2)%text == "2") then
          script%dimension = 2
        else if (words(2)%text == "3") then
          script%dimension = 3
        else
          call set_status(status, demstep_stat%invalid_input, "must be 2 or 3, got '"//words(2)%text//"'")
        end if
      end if
    case ("boundary")
      script%boundary_line = line
      call count_check(n, 4, status)
      if (status%stat == demstep_stat%ok) then
        do k = 1, 3
          script%periodic(k) = words(k + 1)%text == "p"
          if (verify(words(k + 1)%text, "pfsm") > 0 .or. len(words(k + 1)%text) > 2 .or. &
            (index(words(k + 1)%text, "p") > 0 .and. words(k + 1)%text /= "p")) then
            call set_status(status, demstep_stat%invalid_input, "'"//words(k + 1)%text//"' is not p, f, s, m " &
              //"or a pair of f, s, m")
            exit
          end if
        end do
      end if
    case ("variable")
      call variable_command(words, n, line, script, status)
    case ("include")
      call count_check(n, 2, status)
      if (status%stat == demstep_stat%ok) then
        if (depth >= max_include_depth) then
          call set_status(status, demstep_stat%invalid_input, "more than "//int_text(max_include_depth)// &
            " nested includes")
        else if (words(2)%text(1:1) == "/") then
          call read_file(words(2)%text, script, status, depth + 1)
          return
        else
          call read_file(dir//words(2)%text, script, status, depth + 1)
          return
        end if
      end if
    case ("timestep")
      call count_check(n, 2, status)
      if (status%stat == demstep_stat%ok) call positive_number(words(2)%text, script%timestep, status)
      script%timestep_line = line
      script%timestep_file = file
    case ("region")
      call region_command(words, n, script)
    case ("create_box")
      call create_box_command(words, n, script, status)
    case ("pair_style")
      if (n < 2) then
        call set_status(status, demstep_stat%invalid_input, "no style")
      else if (words(2)%text /= "gran") then
        call set_status(status, demstep_stat%invalid_input, "'"//words(2)%text//"' is not read (demstep " &
          //"reads 'pair_style gran model ...'; the older styles such as gran/hertz/history are not read)")
      else
        k = 3
        call model_words(words, n, k, script%pair, status)
        if (status%stat == demstep_stat%ok .and. k <= n) call set_status(status, demstep_stat%invalid_input, &
          "'"//words(k)%text//"' is not a setting of the granular models")
        script%pair%file = file
        script%pair%line = line
      end if
    case ("fix")
      call fix_command(words, n, file, line, script, status)
      if (status%stat /= demstep_stat%ok .and. n >= 4) command = "fix "//words(4)%text
    case default
      if (.not. any(passed_commands == command)) call set_status(status, demstep_stat%invalid_input, &
        "unknown command (not read by demstep)")
    end select
    if (status%stat /= demstep_stat%ok) call locate(status, file, line, command)
  end subroutine run_statement

  !> `FILE: line N: command: what` with `where` the command (kept when set).
  subroutine locate(status, file, line, command)
    type(demstep_status_type), intent(inout) :: status
    character(len=*), intent(in) :: file, command
    integer, intent(in) :: line
    character(len=:), allocatable :: detail, where
    integer :: code, idx
    if (index(status%message, file//": ") == 1) return
    code = status%stat
    detail = status%message
    where = command
    idx = 0
    if (allocated(status%where)) then
      if (len(status%where) > 0) then
        where = status%where
        idx = status%index
        detail = status%detail
      end if
    end if
    call set_status(status, code, detail, where=where, index=idx, subscript=.true.)
    status%message = file//": line "//int_text(line)//": "//status%message
  end subroutine locate

  subroutine count_check(n, wanted, status)
    integer, intent(in) :: n, wanted
    type(demstep_status_type), intent(out) :: status
    status%stat = demstep_stat%ok
    if (n /= wanted) call set_status(status, demstep_stat%invalid_input, "takes "//int_text(wanted - 1)// &
      " argument"//trim(merge("s", " ", wanted /= 2))//", got "//int_text(n - 1))
  end subroutine count_check

  subroutine units_command(words, n, script, status)
    type(word_type), intent(in) :: words(:)
    integer, intent(in) :: n
    type(liggghts_script_type), intent(inout) :: script
    type(demstep_status_type), intent(out) :: status
    call count_check(n, 2, status)
    if (status%stat /= demstep_stat%ok) return
    select case (words(2)%text)
    case ("si")
      script%units = liggghts_units%si
    case ("cgs")
      script%units = liggghts_units%cgs
    case default
      call set_status(status, demstep_stat%invalid_input, "'"//words(2)%text//"' is not read (demstep reads " &
        //"si and cgs scripts)")
    end select
  end subroutine units_command

  !> `variable name style args` (variable.cpp, Variable::set): `equal` and
  !> `string` replace a variable of their style, `index` and `loop` keep an
  !> existing one (:184-200), `delete` removes it.
  subroutine variable_command(words, n, line, script, status)
    type(word_type), intent(in) :: words(:)
    integer, intent(in) :: n, line
    type(liggghts_script_type), intent(inout) :: script
    type(demstep_status_type), intent(out) :: status
    integer :: k
    type(liggghts_variable_type) :: v
    type(liggghts_variable_type), allocatable :: tmp(:)
    status%stat = demstep_stat%ok
    if (n < 3) then
      call set_status(status, demstep_stat%invalid_input, "needs a name and a style")
      return
    end if
    k = liggghts_find_variable(script%vars, script%n_vars, words(2)%text)
    v%name = words(2)%text
    v%style = words(3)%text
    v%line = line
    select case (v%style)
    case ("delete")
      if (k > 0) script%vars(k)%name = ""
      return
    case ("equal", "atom", "string")
      if (n /= 4) then
        call set_status(status, demstep_stat%invalid_input, "'"//v%name//"': style "//v%style//" takes one " &
          //"formula or text (quote it when it holds blanks), got "//int_text(n - 3))
        return
      end if
      if (k > 0) then
        if (script%vars(k)%style /= v%style) then
          call set_status(status, demstep_stat%invalid_input, "'"//v%name//"': cannot redefine a variable " &
            //"as a different style")
          return
        end if
        script%vars(k)%name = ""
      end if
      v%text = words(4)%text
    case ("index", "loop", "world", "universe", "uloop", "file", "atomfile", "getenv")
      if (k > 0) return
      if (n < 4) then
        call set_status(status, demstep_stat%invalid_input, "'"//v%name//"': no value")
        return
      end if
      v%text = words(4)%text
      if (v%style == "loop") v%text = "1"
      if (v%style == "file" .or. v%style == "atomfile" .or. v%style == "getenv") v%style = "other"
    case default
      call set_status(status, demstep_stat%invalid_input, "'"//v%name//"': style '"//v%style// &
        "' is not read")
      return
    end select
    if (script%n_vars == size(script%vars)) then
      allocate(tmp(2*size(script%vars)))
      tmp(1:script%n_vars) = script%vars(1:script%n_vars)
      call move_alloc(tmp, script%vars)
    end if
    script%n_vars = script%n_vars + 1
    script%vars(script%n_vars) = v
  end subroutine variable_command

  !> `region ID block xlo xhi ylo yhi zlo zhi ...`: kept for `create_box`.
  subroutine region_command(words, n, script)
    type(word_type), intent(in) :: words(:)
    integer, intent(in) :: n
    type(liggghts_script_type), intent(inout) :: script
    type(liggghts_region_type) :: r
    type(demstep_status_type) :: st
    integer :: k
    if (n < 3) return
    r%id = words(2)%text
    r%known = words(3)%text == "block" .and. n >= 9
    if (r%known) then
      do k = 1, 3
        call number(words(2*k + 2)%text, r%lo(k), st)
        if (st%stat == demstep_stat%ok) call number(words(2*k + 3)%text, r%hi(k), st)
        if (st%stat /= demstep_stat%ok) r%known = .false.
      end do
    end if
    script%regions = [script%regions(1:script%n_regions), r]
    script%n_regions = script%n_regions + 1
  end subroutine region_command

  !> `create_box N region-ID`: the number of types and the box.
  subroutine create_box_command(words, n, script, status)
    type(word_type), intent(in) :: words(:)
    integer, intent(in) :: n
    type(liggghts_script_type), intent(inout) :: script
    type(demstep_status_type), intent(out) :: status
    integer :: k, ios, nt
    status%stat = demstep_stat%ok
    if (n < 3) then
      call set_status(status, demstep_stat%invalid_input, "needs the number of types and a region")
      return
    end if
    read(words(2)%text, *, iostat=ios) nt
    if (ios /= 0 .or. verify(words(2)%text, "0123456789") > 0 .or. nt < 1 .or. nt > 10000) then
      call set_status(status, demstep_stat%invalid_input, "'"//words(2)%text//"' is not a number of types " &
        //"in [1, 10000]")
      return
    end if
    if (script%n_types > 0 .and. script%n_types /= nt) then
      call set_status(status, demstep_stat%invalid_input, int_text(nt)//" types, but the properties before " &
        //"it have "//int_text(script%n_types))
      return
    end if
    script%n_types = nt
    do k = script%n_regions, 1, -1
      if (script%regions(k)%id == words(3)%text) then
        script%box_known = script%regions(k)%known
        script%box_lo = script%regions(k)%lo
        script%box_hi = script%regions(k)%hi
        exit
      end if
    end do
  end subroutine create_box_command

  !> `fix ID group style args`.
  subroutine fix_command(words, n, file, line, script, status)
    type(word_type), intent(in) :: words(:)
    integer, intent(in) :: n, line
    character(len=*), intent(in) :: file
    type(liggghts_script_type), intent(inout) :: script
    type(demstep_status_type), intent(out) :: status
    status%stat = demstep_stat%ok
    if (n < 4) then
      call set_status(status, demstep_stat%invalid_input, "needs an ID, a group and a style")
      return
    end if
    select case (words(4)%text)
    case ("property/global")
      call property_command(words, n, line, script, status)
    case ("wall/gran")
      call wall_command(words, n, file, line, script, status)
    case ("gravity")
      call gravity_command(words, n, script, status)
      script%gravity_line = line
    case ("particletemplate/sphere")
      call template_command(words, n, line, script, status)
    case ("particletemplate/multisphere", "multisphere")
      ! a script does not say where the bodies settled; a dump does
      call set_status(status, demstep_stat%invalid_input, "fix style not read by demstep (rigid bodies: " &
        //"give the settled state as a dump with its mol and mass columns, &scene snapshot_file)")
    case default
      if (.not. any(passed_fixes == words(4)%text)) call set_status(status, demstep_stat%invalid_input, &
        "fix style not read by demstep")
    end select
  end subroutine fix_command

  !> `fix ID group property/global name style values`.
  subroutine property_command(words, n, line, script, status)
    type(word_type), intent(in) :: words(:)
    integer, intent(in) :: n, line
    type(liggghts_script_type), intent(inout) :: script
    type(demstep_status_type), intent(out) :: status
    character(len=:), allocatable :: name, style
    real(dp), allocatable :: values(:), matrix(:, :)
    integer :: nt, k, ios
    status%stat = demstep_stat%ok
    if (n < 6) then
      call set_status(status, demstep_stat%invalid_input, "needs a property name, a style and values")
      return
    end if
    name = words(5)%text
    style = words(6)%text
    select case (name)
    case ("youngsModulus", "poissonsRatio")
      if (style /= "peratomtype" .and. style /= "atomtype") then
        call set_status(status, demstep_stat%invalid_input, name//": style '"//style//"' is not peratomtype")
        return
      end if
      call numbers(words(7:n), values, status)
      if (status%stat /= demstep_stat%ok) return
      call type_count(size(values), name, script, status)
      if (status%stat /= demstep_stat%ok) return
      do k = 1, size(values)
        if (name == "youngsModulus" .and. .not. (values(k) > 0.0_dp)) then
          call set_status(status, demstep_stat%invalid_input, "value for type "//int_text(k)//" must be > 0", &
            where=name, index=k, subscript=.true.)
          return
        else if (name == "poissonsRatio" .and. .not. (values(k) > -1.0_dp .and. values(k) <= 0.5_dp)) then
          call set_status(status, demstep_stat%invalid_input, "value for type "//int_text(k)// &
            " must lie in (-1, 0.5]", where=name, index=k, subscript=.true.)
          return
        end if
      end do
      if (name == "youngsModulus") then
        script%young = values
        script%young_line = line
      else
        script%poisson = values
        script%poisson_line = line
      end if
    case ("coefficientRestitution", "coefficientFriction", "coefficientRollingFriction")
      if (style /= "peratomtypepair" .and. style /= "atomtypepair") then
        call set_status(status, demstep_stat%invalid_input, name//": style '"//style// &
          "' is not peratomtypepair")
        return
      end if
      if (n < 8) then
        call set_status(status, demstep_stat%invalid_input, name//": needs the number of types and the values")
        return
      end if
      read(words(7)%text, *, iostat=ios) nt
      if (ios /= 0 .or. verify(words(7)%text, "0123456789") > 0 .or. nt < 1 .or. nt > 10000) then
        call set_status(status, demstep_stat%invalid_input, name//": '"//words(7)%text//"' is not a number of " &
          //"types in [1, 10000]")
        return
      end if
      if (n - 7 /= nt*nt) then
        call set_status(status, demstep_stat%invalid_input, name//": "//int_text(nt)//" types need "// &
          int_text(nt*nt)//" values, got "//int_text(n - 7))
        return
      end if
      call numbers(words(8:n), values, status)
      if (status%stat /= demstep_stat%ok) return
      call type_count(nt, name, script, status)
      if (status%stat /= demstep_stat%ok) return
      matrix = reshape(values, [nt, nt])
      if (any(matrix /= transpose(matrix))) then
        call set_status(status, demstep_stat%invalid_input, name//": the matrix must be symmetric (LIGGGHTS " &
          //"refuses it too)")
        return
      end if
      if (name == "coefficientRestitution" .and. any(.not. (matrix > 0.0_dp .and. matrix <= 1.0_dp))) then
        call set_status(status, demstep_stat%invalid_input, name//": values must lie in (0, 1]")
        return
      else if (any(.not. (matrix >= 0.0_dp))) then
        call set_status(status, demstep_stat%invalid_input, name//": values must be >= 0")
        return
      end if
      select case (name)
      case ("coefficientRestitution")
        script%restitution = matrix
        script%restitution_line = line
      case ("coefficientFriction")
        script%friction = matrix
        script%friction_line = line
      case default
        script%rolling_friction = matrix
        script%rolling_friction_line = line
      end select
    case ("characteristicVelocity")
      if (style /= "scalar" .or. n /= 7) then
        call set_status(status, demstep_stat%invalid_input, name//": expected 'scalar' and one value")
        return
      end if
      call positive_number(words(7)%text, script%characteristic_velocity, status)
      script%velocity_line = line
    case ("cohesionEnergyDensity")
      call set_status(status, demstep_stat%invalid_input, name//": cohesion is not supported by demstep yet")
    case default
      if (.not. any(passed_properties == name)) call set_status(status, demstep_stat%invalid_input, &
        "property '"//name//"' is not read (demstep reads youngsModulus, poissonsRatio, coefficientRestitution, " &
        //"coefficientFriction, coefficientRollingFriction, characteristicVelocity)")
    end select
  end subroutine property_command

  !> The number of types a per-type property has, against the script's.
  subroutine type_count(nt, name, script, status)
    integer, intent(in) :: nt
    character(len=*), intent(in) :: name
    type(liggghts_script_type), intent(inout) :: script
    type(demstep_status_type), intent(out) :: status
    status%stat = demstep_stat%ok
    if (script%n_types == 0) then
      script%n_types = nt
    else if (nt /= script%n_types) then
      call set_status(status, demstep_stat%invalid_input, name//": "//int_text(nt)//" types, but the script " &
        //"has "//int_text(script%n_types))
    end if
  end subroutine type_count

  !> The model selectors in LIGGGHTS' order and the on/off settings, from
  !> words(k); k ends at the first word that is neither.
  subroutine model_words(words, n, k, model, status)
    type(word_type), intent(in) :: words(:)
    integer, intent(in) :: n
    integer, intent(inout) :: k
    type(liggghts_model_type), intent(out) :: model
    type(demstep_status_type), intent(out) :: status
    character(len=*), parameter :: selectors(5) = [character(len=16) :: "model", "tangential", "cohesion", &
      "rolling_friction", "surface"]
    character(len=:), allocatable :: value
    integer :: j
    status%stat = demstep_stat%ok
    model%defined = .true.
    model%model = "off"
    model%tangential = "off"
    model%cohesion = "off"
    model%rolling = "off"
    model%surface = "default"
    ! contact_models.cpp:170-260: each selector once, in this order
    do j = 1, size(selectors)
      if (k + 1 > n) exit
      if (words(k)%text /= trim(selectors(j))) cycle
      value = words(k + 1)%text
      select case (j)
      case (1)
        model%model = value
      case (2)
        model%tangential = value
      case (3)
        model%cohesion = value
      case (4)
        model%rolling = value
      case (5)
        model%surface = value
      end select
      k = k + 2
    end do
    if (model%model == "off") then
      call set_status(status, demstep_stat%invalid_input, "no 'model' (the first keyword, as LIGGGHTS reads it)")
      return
    end if
    if (model%cohesion /= "off") then
      call set_status(status, demstep_stat%invalid_input, "cohesion '"//model%cohesion//"' is not supported by " &
        //"demstep yet")
      return
    end if
    ! on/off settings
    do while (k + 1 <= n)
      if (.not. is_setting(words(k)%text)) exit
      call setting(words(k)%text, words(k + 1)%text, model, status)
      if (status%stat /= demstep_stat%ok) return
      k = k + 2
    end do
  end subroutine model_words

  !> One of the granular models' on/off settings?
  pure logical function is_setting(word)
    character(len=*), intent(in) :: word
    is_setting = any(passed_settings == word) .or. word == "tangential_damping" .or. word == "limitForce" .or. &
      word == "ktToKnUser" .or. word == "viscous"
  end function is_setting

  !> A model's on/off setting `key value`.
  pure subroutine setting(key, value, model, status)
    character(len=*), intent(in) :: key, value
    type(liggghts_model_type), intent(inout) :: model
    type(demstep_status_type), intent(out) :: status
    status%stat = demstep_stat%ok
    if (value /= "on" .and. value /= "off") then
      call set_status(status, demstep_stat%invalid_input, key//": '"//value//"' is neither on nor off")
      return
    end if
    select case (key)
    case ("tangential_damping")
      model%tangential_damping = value == "on"
    case ("limitForce")
      model%limit_force = value == "on"
    case ("ktToKnUser")
      model%kt_to_kn_user = value == "on"
    case ("viscous")
      if (value == "on") call set_status(status, demstep_stat%invalid_input, "viscous on: the viscous Hooke " &
        //"model is not supported by demstep")
    end select
  end subroutine setting

  !> `fix ID group wall/gran model ... primitive type T xplane|yplane|zplane position`.
  subroutine wall_command(words, n, file, line, script, status)
    type(word_type), intent(in) :: words(:)
    integer, intent(in) :: n, line
    character(len=*), intent(in) :: file
    type(liggghts_script_type), intent(inout) :: script
    type(demstep_status_type), intent(out) :: status
    type(liggghts_wall_type) :: w
    integer :: k, ios
    k = 5
    call model_words(words, n, k, w%model, status)
    if (status%stat /= demstep_stat%ok) return
    w%model%file = file
    w%model%line = line
    w%id = words(2)%text
    w%file = file
    w%line = line
    do while (k <= n)
      select case (words(k)%text)
      case ("primitive")
        if (k + 4 > n) then
          call set_status(status, demstep_stat%invalid_input, "primitive: expected 'type T style position'")
          return
        end if
        if (words(k + 1)%text /= "type") then
          call set_status(status, demstep_stat%invalid_input, "primitive: expected 'type', found '"// &
            words(k + 1)%text//"'")
          return
        end if
        read(words(k + 2)%text, *, iostat=ios) w%wall_type
        if (ios /= 0 .or. verify(words(k + 2)%text, "0123456789") > 0 .or. w%wall_type < 1) then
          call set_status(status, demstep_stat%invalid_input, "primitive type: '"//words(k + 2)%text// &
            "' is not an atom type")
          return
        end if
        select case (words(k + 3)%text)
        case ("xplane")
          w%axis = 1
        case ("yplane")
          w%axis = 2
        case ("zplane")
          w%axis = 3
        case default
          call set_status(status, demstep_stat%invalid_input, "primitive '"//words(k + 3)%text//"' is not " &
            //"read (demstep's walls are planes: xplane, yplane, zplane)")
          return
        end select
        call number(words(k + 4)%text, w%position, status)
        if (status%stat /= demstep_stat%ok) return
        k = k + 5
      case ("mesh", "n_meshes", "meshes")
        call set_status(status, demstep_stat%invalid_input, "mesh walls are not read (demstep's walls are " &
          //"primitive planes)")
        return
      case ("shear", "store_force", "store_force_contact", "temperature", "track_energy")
        ! a moving wall's velocity and output: no bearing on the contacts' stiffness
        k = k + 2
        if (words(k - 2)%text == "shear") k = k + 1
      case default
        ! the models' settings may follow the wall (LIGGGHTS passes the rest of the line to them)
        if (is_setting(words(k)%text) .and. k + 1 <= n) then
          call setting(words(k)%text, words(k + 1)%text, w%model, status)
          if (status%stat /= demstep_stat%ok) return
          k = k + 2
          cycle
        end if
        call set_status(status, demstep_stat%invalid_input, "'"//words(k)%text//"' is not read")
        return
      end select
    end do
    if (w%axis == 0) then
      call set_status(status, demstep_stat%invalid_input, "no 'primitive' wall")
      return
    end if
    if (script%n_types > 0 .and. w%wall_type > script%n_types) then
      call set_status(status, demstep_stat%invalid_input, "primitive type "//int_text(w%wall_type)// &
        " is above the "//int_text(script%n_types)//" types")
      return
    end if
    ! a fix with an existing ID replaces it
    do k = 1, script%n_walls
      if (script%walls(k)%id == w%id) then
        script%walls(k) = w
        return
      end if
    end do
    script%walls = [script%walls(1:script%n_walls), w]
    script%n_walls = script%n_walls + 1
    status%stat = demstep_stat%ok
  end subroutine wall_command

  !> `fix ID group gravity magnitude vector x y z` (the direction normalised,
  !> fix_gravity.cpp:379-384); the other styles are refused.
  subroutine gravity_command(words, n, script, status)
    type(word_type), intent(in) :: words(:)
    integer, intent(in) :: n
    type(liggghts_script_type), intent(inout) :: script
    type(demstep_status_type), intent(out) :: status
    real(dp) :: g, d(3)
    integer :: k
    if (n /= 9 .or. words(min(n, 6))%text /= "vector") then
      call set_status(status, demstep_stat%invalid_input, "expected 'gravity magnitude vector x y z' (the " &
        //"chute, spherical and gradient styles are not read)")
      return
    end if
    call variable_or_number(words(5)%text, script, g, status)
    if (status%stat /= demstep_stat%ok) return
    do k = 1, 3
      call variable_or_number(words(6 + k)%text, script, d(k), status)
      if (status%stat /= demstep_stat%ok) return
    end do
    if (norm2(d) == 0.0_dp) then
      call set_status(status, demstep_stat%invalid_input, "the direction vector is zero")
      return
    end if
    script%gravity = g*d/norm2(d)
  end subroutine gravity_command

  !> A number or `v_name` (an equal-style variable's value, as fix gravity takes it).
  subroutine variable_or_number(word, script, x, status)
    character(len=*), intent(in) :: word
    type(liggghts_script_type), intent(in) :: script
    real(dp), intent(out) :: x
    type(demstep_status_type), intent(out) :: status
    if (index(word, "v_") == 1) then
      call liggghts_evaluate(word, script%vars, script%n_vars, x, status)
    else
      call number(word, x, status)
    end if
  end subroutine variable_or_number

  !> `fix ID group particletemplate/sphere seed atom_type t density constant rho radius constant r`.
  subroutine template_command(words, n, line, script, status)
    type(word_type), intent(in) :: words(:)
    integer, intent(in) :: n, line
    type(liggghts_script_type), intent(inout) :: script
    type(demstep_status_type), intent(out) :: status
    type(liggghts_template_type) :: t
    integer :: k, ios
    status%stat = demstep_stat%ok
    t%id = words(2)%text
    t%line = line
    k = 6
    do while (k <= n)
      select case (words(k)%text)
      case ("atom_type")
        if (k + 1 > n) exit
        read(words(k + 1)%text, *, iostat=ios) t%atom_type
        if (ios /= 0 .or. verify(words(k + 1)%text, "0123456789") > 0 .or. t%atom_type < 1) then
          call set_status(status, demstep_stat%invalid_input, "atom_type: '"//words(k + 1)%text// &
            "' is not an atom type")
          return
        end if
        k = k + 2
      case ("density", "radius")
        if (k + 2 > n) exit
        if (words(k + 1)%text == "constant") then
          if (words(k)%text == "density") then
            call positive_number(words(k + 2)%text, t%density, status)
          else
            call positive_number(words(k + 2)%text, t%radius, status)
          end if
          if (status%stat /= demstep_stat%ok) return
        end if
        k = k + 3
      case default
        k = k + 1
      end select
    end do
    script%templates = [script%templates(1:script%n_templates), t]
    script%n_templates = script%n_templates + 1
  end subroutine template_command

  !> Substitute `$x`, `${name}` and `$(formula)` outside quotes (Input::substitute).
  subroutine substitute(s, script, status)
    character(len=:), allocatable, intent(inout) :: s
    type(liggghts_script_type), intent(in) :: script
    type(demstep_status_type), intent(out) :: status
    character(len=:), allocatable :: out, name, value
    character :: quote
    integer :: p, q, depth, k
    real(dp) :: x
    status%stat = demstep_stat%ok
    out = ""
    quote = " "
    p = 1
    do while (p <= len(s))
      if (quote /= " ") then
        if (s(p:p) == quote) quote = " "
      else if (s(p:p) == '"' .or. s(p:p) == "'") then
        quote = s(p:p)
      else if (s(p:p) == "$" .and. p < len(s)) then
        if (s(p + 1:p + 1) == "{") then
          q = index(s(p + 2:), "}")
          if (q == 0) then
            call set_status(status, demstep_stat%invalid_input, "'${' without '}'")
            return
          end if
          name = s(p + 2:p + q)
          p = p + q + 2
        else if (s(p + 1:p + 1) == "(") then
          depth = 0
          q = p + 1
          do while (q <= len(s))
            if (s(q:q) == "(") depth = depth + 1
            if (s(q:q) == ")") depth = depth - 1
            if (depth == 0) exit
            q = q + 1
          end do
          if (q > len(s)) then
            call set_status(status, demstep_stat%invalid_input, "'$(' without ')'")
            return
          end if
          call liggghts_evaluate(s(p + 2:q - 1), script%vars, script%n_vars, x, status)
          if (status%stat /= demstep_stat%ok) then
            status%message = "$("//s(p + 2:q - 1)//"): "//status%message
            return
          end if
          out = out//liggghts_number_text(x, 20)
          p = q + 1
          cycle
        else
          name = s(p + 1:p + 1)
          p = p + 2
        end if
        k = liggghts_find_variable(script%vars, script%n_vars, name)
        if (k == 0) then
          call set_status(status, demstep_stat%invalid_input, "$"//name//": no variable '"//name// &
            "' is defined before this line")
          return
        end if
        select case (script%vars(k)%style)
        case ("equal")
          call liggghts_evaluate(script%vars(k)%text, script%vars, script%n_vars, x, status)
          if (status%stat /= demstep_stat%ok) then
            status%message = "${"//name//"}: variable "//name//" (line "//int_text(script%vars(k)%line)//"): " &
              //status%message
            return
          end if
          value = liggghts_number_text(x, 15)
        case ("atom", "other")
          call set_status(status, demstep_stat%invalid_input, "${"//name//"}: a variable of style " &
            //script%vars(k)%style//" has no value here")
          return
        case default
          value = script%vars(k)%text
        end select
        out = out//value
        cycle
      end if
      out = out//s(p:p)
      p = p + 1
    end do
    s = out
  end subroutine substitute

  !> Words separated by blanks; a quoted text is one word without its quotes.
  pure subroutine split_words(s, words, n, status)
    character(len=*), intent(in) :: s
    type(word_type), allocatable, intent(out) :: words(:)
    integer, intent(out) :: n
    type(demstep_status_type), intent(out) :: status
    type(word_type), allocatable :: tmp(:)
    integer :: p, q
    allocate(words(8))
    n = 0
    p = 1
    status%stat = demstep_stat%ok
    do
      do while (p <= len(s))
        if (.not. is_space(s(p:p))) exit
        p = p + 1
      end do
      if (p > len(s)) exit
      if (n == size(words)) then
        allocate(tmp(2*n))
        tmp(1:n) = words(1:n)
        call move_alloc(tmp, words)
      end if
      n = n + 1
      if (s(p:p) == '"' .or. s(p:p) == "'") then
        q = index(s(p + 1:), s(p:p))
        if (q == 0) then
          call set_status(status, demstep_stat%invalid_input, "unbalanced quotes")
          return
        end if
        words(n)%text = s(p + 1:p + q - 1)
        p = p + q + 1
      else
        q = p
        do while (q <= len(s))
          if (is_space(s(q:q))) exit
          q = q + 1
        end do
        words(n)%text = s(p:q - 1)
        p = q
      end if
    end do
  end subroutine split_words

  pure logical function is_space(c)
    character, intent(in) :: c
    is_space = c == " " .or. c == achar(9) .or. c == achar(13) .or. c == achar(11) .or. c == achar(12)
  end function is_space

  !> A number as LIGGGHTS' `force->numeric` takes it (digits, sign, point, e).
  pure subroutine number(word, x, status)
    character(len=*), intent(in) :: word
    real(dp), intent(out) :: x
    type(demstep_status_type), intent(out) :: status
    integer :: ios
    x = 0.0_dp
    ios = 1
    if (len(word) > 0 .and. verify(word, "0123456789.+-eE") == 0 .and. scan(word, "0123456789") > 0) &
      read(word, *, iostat=ios) x
    if (ios /= 0 .or. x /= x .or. abs(x) > huge(x)) then
      call set_status(status, demstep_stat%invalid_input, "'"//word//"' is not a number")
      x = 0.0_dp
      return
    end if
    status%stat = demstep_stat%ok
  end subroutine number

  pure subroutine positive_number(word, x, status)
    character(len=*), intent(in) :: word
    real(dp), intent(out) :: x
    type(demstep_status_type), intent(out) :: status
    call number(word, x, status)
    if (status%stat == demstep_stat%ok .and. .not. (x > 0.0_dp)) &
      call set_status(status, demstep_stat%invalid_input, "'"//word//"' must be > 0")
  end subroutine positive_number

  !> Numbers of the words.
  pure subroutine numbers(words, values, status)
    type(word_type), intent(in) :: words(:)
    real(dp), allocatable, intent(out) :: values(:)
    type(demstep_status_type), intent(out) :: status
    integer :: k
    allocate(values(size(words)))
    status%stat = demstep_stat%ok
    if (size(words) == 0) then
      call set_status(status, demstep_stat%invalid_input, "no values")
      return
    end if
    do k = 1, size(words)
      call number(words(k)%text, values(k), status)
      if (status%stat /= demstep_stat%ok) return
    end do
  end subroutine numbers

end module demstep_liggghts_script
