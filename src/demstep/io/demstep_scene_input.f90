!> A scene from typed input: what a `&scene` group (or any caller) gives, as
!> values, turned into a checked [[scene_type]]. The particles come from
!> arrays, a particles table or a DEM code's snapshot (masses from the file or
!> from a material set's densities per type); the springs from one law, per
!> type tables, listed contacts or a material set in a code's convention; then
!> bonds, walls, effects, gravity and dashpots.
!>
!> Optional inputs are allocatable components: allocated means given. Every
!> fault names the input's component (`status%where`, the `&scene` variable
!> of the same name) and the part of the input that holds it
!> (`scene_input_part%scene` or `%material`, for the material set).
module demstep_scene_input
  use demstep_kinds, only: dp
  use demstep_status, only: demstep_status_type, demstep_stat, set_status, status_restate
  use demstep_text, only: int_text, real_text, check_lower
  use demstep_table_io, only: read_table
  use demstep_spring, only: restitution_to_damping_ratio
  use demstep_interaction, only: contact_law
  use demstep_material, only: material_set_type
  use demstep_scene_data, only: scene_type, scene_effect, has_tangential, n_effects
  use demstep_scene_builders, only: parallel_rows, new_scene, scene_add_bonds, scene_add_walls, scene_set_contacts, &
    scene_set_cell, scene_set_law, scene_set_bond_stiffness, scene_set_gravity, scene_set_types, &
    scene_set_hertz_types, scene_set_damping, scene_set_friction, scene_set_rolling, &
    scene_set_local_damping
  use demstep_scene_materials, only: scene_set_material_set, material_set_law, material_set_damped
  use demstep_scene_bonds, only: scene_set_bond_model
  use demstep_bodies, only: body_set_type, bodies_from_members
  use demstep_body_table, only: read_body_table
  use demstep_liggghts_scene, only: liggghts_scene_type, scene_from_liggghts_script
  use demstep_assembly, only: hertz_linearization, eigen_solver, default_max_eigen_dof
  use demstep_lanczos, only: lanczos_tolerance_default
  use demstep_snapshot, only: snapshot_type, read_snapshot, snapshot_format, snapshot_masses_from_types
  implicit none
  private

  public :: scene_from_input, scene_input_own_stiffness, scene_input_takes_material, particle_columns, &
    particles_from_rows, scene_input_effects, scene_input_damping, scene_input_check_dim

  !> The parts of a scene's input a fault can lie in.
  type, public :: scene_input_part_enum
    !> The scene's own variables.
    integer :: scene = 1
    !> The material set.
    integer :: material = 2
  end type scene_input_part_enum
  !> The parts by name.
  type(scene_input_part_enum), parameter, public :: scene_input_part = scene_input_part_enum()

  !> The column counts a contacts table may have: i j k_n k_t [k_r k_w [c_n
  !> c_t c_r c_w]] (the particle numbers are columns 1 and 2).
  integer, parameter, public :: contact_columns(3) = [4, 6, 10]

  !> Most particle types of a snapshot (per-type tables are nt x nt).
  integer, parameter, public :: max_snapshot_types = 1000

  !> Everything one scene is made of. Files are paths as the caller resolved
  !> them; arrays are as given (zero-sized or unallocated: not given).
  type, public :: scene_input_type
    !> Dimension: 1, 2 or 3.
    integer :: dim = 0
    !> Particles as arrays: dim coordinates and velocities per particle, one
    !> mass and radius per particle or one for all, fixed particles' numbers.
    real(dp), allocatable :: position(:), velocity(:), mass(:), radius(:)
    integer, allocatable :: fixed(:)
    !> Particles as a table: per row dim positions, dim velocities, mass,
    !> radius, fixed (0/1), optionally the moment of inertia.
    character(len=:), allocatable :: particles_file
    !> Particles from a DEM code's file, its format (`snapshot_format%...`) and
    !> dump frame (0 the last, negative from the end).
    character(len=:), allocatable :: snapshot_file
    integer :: snapshot_format = 0, snapshot_frame = 0
    !> The LIGGGHTS input script that made the snapshot: its contacts, walls,
    !> gravity and effects as LIGGGHTS computes them (no material set needed).
    character(len=:), allocatable :: liggghts_script
    !> Explicit contacts: per row i j k_n k_t [k_r k_w [c_n c_t c_r c_w]].
    character(len=:), allocatable :: contacts_file
    !> Bonds: pairs of particle numbers, or a table of them.
    integer, allocatable :: bonds(:)
    character(len=:), allocatable :: bonds_file
    real(dp) :: k_bond = 0.0_dp, k_bond_tangential = 0.0_dp
    !> Or bonds as a DEM code makes them (`bond_model%...`) and that model's
    !> parameters in its code's units.
    integer, allocatable :: bond_model
    real(dp), allocatable :: bond_parameters(:)
    !> Rigid bodies (clumps): a table of particle and body id per row (else
    !> the clumps a snapshot names), and the members' density for the bodies'
    !> masses and inertias (default the particles' own).
    character(len=:), allocatable :: bodies_file
    real(dp), allocatable :: body_density
    !> A LIGGGHTS multisphere dump's bodies (body mass per member): the
    !> union of the members (overlap once, LIGGGHTS' Monte Carlo template),
    !> else (the default) the members' sum (a template stating the sum): the
    !> sum is the conservative one on the validation scenes (the union is
    !> above the measured limit where the template states the sum).
    logical :: body_union = .false.
    !> The periodic cell (the snapshot's box and axes when not given).
    logical, allocatable :: periodic(:)
    real(dp) :: cell_lo(3) = 0.0_dp
    real(dp), allocatable :: cell_hi(:)
    !> The contact law (`contact_law%...`; default the material set's, else linear).
    integer, allocatable :: law
    real(dp), allocatable :: k_normal, k_tangential, kt_ratio, e_star, g_star
    !> Per-type stiffness: the particles' types and the tables.
    integer, allocatable :: types(:)
    real(dp), allocatable :: type_k_normal(:), type_k_tangential(:), young(:), poisson(:)
    !> Friction and rolling friction (default none: no sliding, no cap).
    real(dp), allocatable :: friction, rolling_friction
    real(dp) :: rolling_ratio = 0.0_dp, twisting_ratio = 0.0_dp
    !> Walls: per wall dim coordinates of a point, dim of the inward normal.
    real(dp), allocatable :: walls(:)
    !> The walls' material type (0: each particle's own) and the code's
    !> tangential dashpots, with a material set.
    integer :: wall_type = 0
    logical :: tangential_damping = .true.
    !> The effects switched on (`scene_effect%...`; default: contacts, and
    !> rotation with tangential springs).
    integer, allocatable :: effects(:)
    !> Gravity (default -9.81 along the last axis).
    real(dp), allocatable :: gravity(:)
    !> The dashpots: the normal damping ratio or the restitution giving it, the
    !> tangential (default the normal) and rolling ratios, drag.
    real(dp), allocatable :: damping_ratio, restitution, damping_ratio_tangential, &
      damping_ratio_rolling, drag
    real(dp) :: local_damping = 0.0_dp
    !> Hertz linearisation (`hertz_linearization%...`) and impact velocity
    !> (defaults: current, 0; with a material set: larger, its impact velocity).
    integer, allocatable :: hertz_linearization
    real(dp), allocatable :: impact_velocity
    !> The analysis: eigensolver, Lanczos tolerance, dense limit, pre-stress.
    integer :: eigen_solver = eigen_solver%auto
    real(dp) :: eigen_tolerance = lanczos_tolerance_default
    integer :: max_eigen_dof = default_max_eigen_dof
    logical :: prestress = .false.
  end type scene_input_type

  !> What the input resolved to beside the scene.
  type, public :: scene_setup_type
    !> The snapshot read (empty without one).
    type(snapshot_type) :: snapshot
    !> Whether the springs came from the material set.
    logical :: from_material = .false.
    !> The Hertz linearisation and impact velocity for the analysis.
    integer :: hertz_mode = 1
    real(dp) :: impact_velocity = 0.0_dp
    !> What a LIGGGHTS script gave (with `liggghts_script`), for the report.
    type(liggghts_scene_type) :: script
    !> The rigid bodies, when the scene has them (analyse and run with them).
    type(body_set_type), allocatable :: bodies
  end type scene_setup_type

contains

  !> Whether the input gives the contact stiffness itself (one law, or per type).
  pure logical function scene_input_own_stiffness(input) result(own)
    type(scene_input_type), intent(in) :: input
    own = allocated(input%k_normal) .or. allocated(input%e_star) .or. given_real(input%type_k_normal) &
      .or. given_real(input%young) .or. allocated(input%liggghts_script)
  end function scene_input_own_stiffness

  !> The input's `dim`: 1, 2 or 3, else invalid_input at `dim`.
  pure subroutine scene_input_check_dim(input, status)
    type(scene_input_type), intent(in) :: input
    type(demstep_status_type), intent(out) :: status
    status%stat = demstep_stat%ok
    if (input%dim < 1 .or. input%dim > 3) call set_status(status, demstep_stat%invalid_input, &
      "must be 1, 2 or 3, got "//int_text(input%dim), where="dim")
  end subroutine scene_input_check_dim

  !> Whether the input takes its particle types' stiffness from a material
  !> set: a snapshot without stiffness of its own.
  pure logical function scene_input_takes_material(input) result(takes)
    type(scene_input_type), intent(in) :: input
    takes = allocated(input%snapshot_file) .and. .not. scene_input_own_stiffness(input)
  end function scene_input_takes_material

  !> Build the scene an input describes. `materials` (broadcast to the
  !> snapshot's types on return) gives a snapshot's masses and, unless the input
  !> has stiffness of its own, its springs and dashpots. Status invalid_input
  !> or io_error naming the input's component; `part` the part holding it.
  subroutine scene_from_input(input, materials, scene, setup, status, part)
    type(scene_input_type), intent(in) :: input
    type(material_set_type), intent(inout) :: materials
    type(scene_type), intent(out) :: scene
    type(scene_setup_type), intent(out) :: setup
    type(demstep_status_type), intent(out) :: status
    integer, intent(out) :: part
    real(dp), allocatable :: x(:, :), v(:, :), m(:), r(:), inertia(:), contact_k(:, :), kk(:, :, :)
    real(dp) :: law_values(2), k_tangential
    integer, allocatable :: contact_pairs(:, :), contact_lines(:), pairs(:, :), ptypes(:)
    logical, allocatable :: is_fixed(:)
    logical :: periodic(3), typed, law_given, search, in_set, effects(n_effects)
    real(dp) :: cell_lo(3), cell_hi(3)
    integer :: i, n, np, dim, law, nt, nw
    part = scene_input_part%scene
    dim = input%dim
    call scene_input_check_dim(input, status)
    if (status%stat /= demstep_stat%ok) return
    search = .not. allocated(input%contacts_file)

    ! particles: a snapshot, a table file or the arrays
    if (allocated(input%snapshot_file)) then
      call snapshot_particles(input, materials, setup%snapshot, x, v, m, r, status, part)
      if (status%stat /= demstep_stat%ok) return
      n = size(m)
      allocate(is_fixed(n), source=.false.)
      ptypes = setup%snapshot%type
      setup%from_material = materials%found .and. scene_input_takes_material(input)
      if (.not. (setup%from_material .or. scene_input_own_stiffness(input))) then
        call set_status(status, demstep_stat%invalid_input, "required with snapshot_file (or e_star, " &
          //"type_k_normal, young and poisson per type, liggghts_script, or a &material group in the deck)", where="k_normal")
        return
      end if
    else if (allocated(input%particles_file)) then
      call read_particles(input%particles_file, dim, x, v, m, r, is_fixed, inertia, status)
      if (status%stat /= demstep_stat%ok) then
        call status_restate(status, "particles_file", status%message)
        return
      end if
      n = size(m)
    else
      np = length(input%position)
      if (np == 0) then
        call fail("position", "give either position, particles_file or snapshot_file (one of them is required)")
        return
      end if
      if (mod(np, dim) /= 0) then
        call fail("position", int_text(np)//" values are not "//int_text(dim)//" per particle")
        return
      end if
      n = np/dim
      if (length(input%velocity) /= 0 .and. length(input%velocity) /= np) then
        call fail("velocity", "needs "//int_text(np)//" values, got "//int_text(length(input%velocity)))
        return
      end if
      if (length(input%mass) /= 1 .and. length(input%mass) /= n) then
        call fail("mass", "needs 1 or "//int_text(n)//" values, got "//int_text(length(input%mass)))
        return
      end if
      if (length(input%radius) /= 1 .and. length(input%radius) /= n) then
        call fail("radius", "needs 1 or "//int_text(n)//" values, got "//int_text(length(input%radius)))
        return
      end if
      x = reshape(input%position(:np), [dim, n])
      allocate(v(dim, n), source=0.0_dp)
      if (length(input%velocity) > 0) v = reshape(input%velocity(:np), [dim, n])
      m = broadcast(input%mass, n)
      r = broadcast(input%radius, n)
      allocate(is_fixed(n), source=.false.)
      if (allocated(input%fixed)) then
        do i = 1, size(input%fixed)
          if (input%fixed(i) < 1 .or. input%fixed(i) > n) then
            call fail("fixed", "particle "//int_text(input%fixed(i))//" does not exist (1 to "// &
              int_text(n)//")")
            return
          end if
          is_fixed(input%fixed(i)) = .true.
        end do
      end if
    end if
    ! new_scene checks the masses, radii, positions and inertias (no contact
    ! search when the contacts are given: only listed pairs are contacts)
    if (allocated(inertia)) then
      call new_scene(scene, dim, x, m, r, status, v=v, fixed=is_fixed, inertia=inertia, search=search)
      if (status%stat /= demstep_stat%ok .and. status%where == "inertia") then
        call status_restate(status, "particles_file", input%particles_file//": "//status%message)
        return
      end if
    else
      call new_scene(scene, dim, x, m, r, status, v=v, fixed=is_fixed, search=search)
    end if
    if (status%stat /= demstep_stat%ok) return

    ! the periodic cell (before bonds: their rest vectors go through the nearest image)
    periodic = .false.
    cell_lo = input%cell_lo
    cell_hi = 0.0_dp
    if (allocated(input%periodic)) periodic(:size(input%periodic)) = input%periodic
    if (allocated(input%cell_hi)) cell_hi(:size(input%cell_hi)) = input%cell_hi
    if (allocated(input%snapshot_file)) then
      ! the file's box and periodic axes, unless the input gives them
      if (.not. allocated(input%periodic)) periodic = setup%snapshot%periodic
      periodic(dim+1:) = .false.
      if (setup%snapshot%has_box .and. .not. allocated(input%cell_hi)) then
        cell_lo = setup%snapshot%lo
        cell_hi = setup%snapshot%hi
      end if
    end if
    if (any(periodic)) then
      if (.not. (allocated(input%cell_hi) .or. (allocated(input%snapshot_file) .and. &
          setup%snapshot%has_box))) then
        call fail("cell_hi", "required with periodic axes")
        return
      end if
      call scene_set_cell(scene, periodic, cell_lo, cell_hi, status, search=search)
      if (status%stat /= demstep_stat%ok) return
    end if

    ! an explicit contact list
    if (allocated(input%contacts_file)) then
      call read_contacts(input%contacts_file, contact_pairs, contact_k, contact_lines, status)
      if (status%stat == demstep_stat%ok) then
        call scene_set_contacts(scene, contact_pairs, contact_k, status)
        ! a row's fault at its line in the file
        if (status%stat /= demstep_stat%ok .and. status%index > 0 .and. status%index <= size(contact_lines)) &
          call status_restate(status, "contacts_file", input%contacts_file//": line "// &
            int_text(contact_lines(status%index))//": "//status%detail)
      end if
      if (status%stat /= demstep_stat%ok) then
        if (status%where /= "contacts_file") call status_restate(status, "contacts_file", status%message)
        return
      end if
    end if

    ! bonds: a table file or the array
    if (allocated(input%bonds_file)) then
      call read_bonds(input%bonds_file, pairs, status)
      if (status%stat /= demstep_stat%ok) then
        call status_restate(status, "bonds_file", status%message)
        return
      end if
    else if (allocated(input%bonds)) then
      np = length_int(input%bonds)
      if (mod(np, 2) /= 0) then
        call fail("bonds", "pairs of particle numbers: got an odd count "//int_text(np))
        return
      end if
      pairs = reshape(input%bonds(:np), [2, np/2])
    else
      allocate(pairs(2, 0))
    end if
    if (size(pairs, 2) > 0) then
      call scene_add_bonds(scene, pairs, status)
      if (status%stat /= demstep_stat%ok) return
      if (allocated(input%bond_model)) then
        if (allocated(input%bond_parameters)) then
          call scene_set_bond_model(scene, input%bond_model, input%bond_parameters, status)
        else
          call scene_set_bond_model(scene, input%bond_model, [real(dp) ::], status)
        end if
      else
        call scene_set_bond_stiffness(scene, input%k_bond, input%k_bond_tangential, status)
      end if
      if (status%stat /= demstep_stat%ok) return
    end if

    ! effects
    call scene_input_effects(input, scene, status)
    if (status%stat /= demstep_stat%ok) return
    ! per-type materials: the types array, or a snapshot's types with per-type stiffness
    typed = allocated(input%types) .or. (allocated(input%snapshot_file) .and. (setup%from_material .or. &
      given_real(input%type_k_normal) .or. given_real(input%young)))
    law = contact_law%linear
    if (setup%from_material) law = material_set_law(materials)
    if (allocated(input%law)) law = input%law
    if (law == contact_law%linear) then
      if (allocated(input%k_tangential) .and. allocated(input%kt_ratio)) then
        call fail("kt_ratio", "give either k_tangential or kt_ratio, not both")
        return
      end if
      k_tangential = 0.0_dp
      if (allocated(input%k_tangential)) k_tangential = input%k_tangential
      if (allocated(input%kt_ratio)) then
        call check_lower(input%kt_ratio, "kt_ratio", status, inclusive=.true.)
        if (status%stat /= demstep_stat%ok) return
        k_tangential = input%kt_ratio*value_or_zero(input%k_normal)
      end if
      law_values = [value_or_zero(input%k_normal), k_tangential]
      law_given = allocated(input%k_normal) .or. allocated(input%k_tangential)
    else
      law_values = [value_or_zero(input%e_star), value_or_zero(input%g_star)]
      law_given = allocated(input%e_star) .or. allocated(input%g_star)
    end if
    if (law_given .or. (scene%effects(scene_effect%contacts) .and. .not. (scene%given_contacts .or. typed .or. &
      allocated(input%liggghts_script))) &
      .or. (scene%effects(scene_effect%walls) .and. .not. setup%from_material)) then
      call scene_set_law(scene, law, law_values(1), law_values(2), status)
      if (status%stat /= demstep_stat%ok) return
    else
      ! per-type or listed stiffness, or no contacts: the law's own values go unused
      scene%law = law
    end if
    if (setup%from_material) then
      effects = scene%effects
      call scene_set_material_set(scene, materials, ptypes, input%wall_type, input%tangential_damping, &
        status, in_set)
      if (status%stat /= demstep_stat%ok) then
        if (in_set) part = scene_input_part%material
        return
      end if
      ! the input's effects list, where given, has the last word
      if (allocated(input%effects)) scene%effects = effects
    else if (typed) then
      call type_materials()
      if (status%stat /= demstep_stat%ok) return
    end if
    if (allocated(input%friction)) call check_lower(input%friction, "friction", status, inclusive=.true.)
    if (allocated(input%rolling_friction)) call check_lower(input%rolling_friction, "rolling_friction", &
      status, inclusive=.true.)
    if (status%stat /= demstep_stat%ok) return
    call scene_set_friction(scene, value_or(input%friction, -1.0_dp), status, &
      rolling_friction=value_or(input%rolling_friction, -1.0_dp))
    if (status%stat == demstep_stat%ok) call scene_set_rolling(scene, input%rolling_ratio, &
      input%twisting_ratio, status)
    if (status%stat /= demstep_stat%ok) return
    ! rotations come with tangential springs unless the effects say otherwise
    if (.not. allocated(input%effects) .and. has_tangential(scene)) scene%effects(scene_effect%rotation) = .true.
    nw = length(input%walls)
    if (scene%effects(scene_effect%walls) .neqv. nw > 0) then
      call fail("walls", "the 'walls' effect and the walls array go together")
      return
    end if
    if (nw > 0) then
      if (mod(nw, 2*dim) /= 0) then
        call fail("walls", "each wall is "//int_text(2*dim)//" values (a point, a normal)")
        return
      end if
      call scene_add_walls(scene, reshape([(input%walls(2*dim*(i-1)+1:2*dim*(i-1)+dim), i = 1, nw/(2*dim))], &
        [dim, nw/(2*dim)]), reshape([(input%walls(2*dim*(i-1)+dim+1:2*dim*i), i = 1, nw/(2*dim))], &
        [dim, nw/(2*dim)]), status)
      if (status%stat /= demstep_stat%ok) then
        call status_restate(status, "walls", status%message)
        return
      end if
    end if
    if (scene%effects(scene_effect%gravity)) then
      if (length(input%gravity) == 0) then
        ! the default: standard gravity along the last axis
        call scene_set_gravity(scene, [(merge(-9.81_dp, 0.0_dp, i == dim), i = 1, dim)], status)
      else
        call scene_set_gravity(scene, input%gravity, status)
      end if
      if (status%stat /= demstep_stat%ok) return
    end if
    call scene_input_damping(input, scene, status)
    if (status%stat /= demstep_stat%ok) return
    if (setup%from_material .and. .not. (allocated(input%effects) .or. allocated(input%damping_ratio) .or. &
        allocated(input%restitution))) then
      ! the code damps its contacts to the set's restitution (unless its
      ! convention has no contact damping, as Yade's FrictPhys)
      if (material_set_damped(materials)) then
        call scene_set_damping(scene, restitution_to_damping_ratio(materials%restitution), status)
        if (status%stat /= demstep_stat%ok) then
          call status_restate(status, "restitution", status%message)
          part = scene_input_part%material
          return
        end if
      end if
    end if
    if (scene%effects(scene_effect%local_damping)) then
      call check_lower(input%local_damping, "local_damping", status, inclusive=.true.)
      if (status%stat /= demstep_stat%ok) return
      call scene_set_local_damping(scene, input%local_damping, status)
      if (status%stat /= demstep_stat%ok) return
    end if
    if (allocated(input%liggghts_script)) then
      ! the script gives the contacts, walls, gravity and effects (after the
      ! input's own: the script's have the last word)
      call scene_from_liggghts_script(scene, input%liggghts_script, setup%snapshot, setup%script, status)
      if (status%stat /= demstep_stat%ok) then
        call status_restate(status, "liggghts_script", status%message)
        return
      end if
    end if
    ! the Hertz linearisation: with a material set, the larger of the current
    ! overlap and the impact's (a settled contact may be struck)
    setup%hertz_mode = hertz_linearization%current
    if (setup%from_material) then
      setup%hertz_mode = hertz_linearization%larger
      setup%impact_velocity = materials%impact_velocity
    end if
    if (allocated(input%hertz_linearization)) setup%hertz_mode = input%hertz_linearization
    if (allocated(input%impact_velocity)) setup%impact_velocity = input%impact_velocity
    call rigid_bodies()
    if (status%stat /= demstep_stat%ok) return
    status%stat = demstep_stat%ok

  contains

    !> Rigid bodies: a body table, or the clumps a snapshot names.
    subroutine rigid_bodies()
      character(len=:), allocatable :: from
      integer, allocatable :: body_of(:)
      from = ""
      if (allocated(input%bodies_file)) then
        from = "bodies_file"
      else if (allocated(input%snapshot_file)) then
        if (setup%snapshot%has_body) from = "snapshot_file"
      end if
      if (len(from) == 0) return
      ! linearised at the current overlap (a material set's implied impact
      ! linearisation is not taken)
      if ((allocated(input%hertz_linearization) .and. setup%hertz_mode /= hertz_linearization%current) &
          .or. input%prestress) then
        call fail(from, "rigid bodies are analysed at the current overlap, without pre-stress " &
          //"(hertz_linearization 'current', prestress F)")
        return
      end if
      setup%hertz_mode = hertz_linearization%current
      if (allocated(input%bodies_file)) then
        call read_body_table(input%bodies_file, scene%n, body_of, status)
        if (status%stat /= demstep_stat%ok) then
          call status_restate(status, "bodies_file", status%message)
          return
        end if
      else
        body_of = setup%snapshot%body
      end if
      allocate(setup%bodies)
      if (from == "snapshot_file" .and. setup%snapshot%body_mass .and. .not. allocated(input%body_density)) then
        ! LIGGGHTS' multisphere: each member's mass is its body's
        call bodies_from_members(scene, body_of, setup%bodies, status, body_mass=setup%snapshot%mass, &
          union=input%body_union)
      else
        call bodies_from_members(scene, body_of, setup%bodies, status, density=input%body_density)
      end if
      if (status%stat /= demstep_stat%ok) then
        if (status%where == "density") call status_restate(status, "body_density", status%detail)
        if (status%where == "body_of") call status_restate(status, from, status%detail)
        ! the particle's index: "body_mass(i): ..." (the dump's mass column)
        if (status%where == "body_mass") call status_restate(status, from, "mass column: "//status%message)
        if (status%where == "body_union") call status_restate(status, "body_union", status%detail)
        deallocate(setup%bodies)
      end if
    end subroutine rigid_bodies

    subroutine fail(where, what)
      character(len=*), intent(in) :: where, what
      call set_status(status, demstep_stat%invalid_input, what, where=where)
    end subroutine fail

    !> Materials per particle type: the tables, checked by the library.
    subroutine type_materials()
      integer :: nkn, nkt
      if (.not. allocated(input%snapshot_file)) then
        if (length_int(input%types) /= n) then
          call fail("types", "needs one type per particle ("//int_text(n)//"), got "// &
            int_text(length_int(input%types)))
          return
        end if
        ptypes = input%types
      end if
      if (scene%law == contact_law%linear) then
        nkn = length(input%type_k_normal)
        nkt = length(input%type_k_tangential)
        nt = nint(sqrt(real(nkn, dp)))
        if (nkn == 0 .or. nt*nt /= nkn) then
          call fail("type_k_normal", "needs nt x nt values (nt types, row by row), got "//int_text(nkn))
          return
        end if
        allocate(kk(2, nt, nt), source=0.0_dp)
        kk(1, :, :) = reshape(input%type_k_normal, [nt, nt])
        if (nkt > 0) then
          if (nkt /= nkn) then
            call fail("type_k_tangential", "needs as many values as type_k_normal ("//int_text(nkn)// &
              "), got "//int_text(nkt))
            return
          end if
          kk(2, :, :) = reshape(input%type_k_tangential, [nt, nt])
        else if (allocated(input%kt_ratio)) then
          kk(2, :, :) = input%kt_ratio*kk(1, :, :)
        end if
        call scene_set_types(scene, ptypes, kk, status)
      else
        if (length(input%young) == 0) then
          call fail("young", "required with types and the Hertz law (one per type)")
          return
        end if
        if (allocated(input%poisson)) then
          call scene_set_hertz_types(scene, ptypes, input%young, input%poisson, status)
        else
          call scene_set_hertz_types(scene, ptypes, input%young, [real(dp) ::], status)
        end if
      end if
    end subroutine type_materials

  end subroutine scene_from_input

  !> The effects an input lists (when it lists them) switched on in the
  !> scene, all others off. Status invalid_input naming `effects`.
  pure subroutine scene_input_effects(input, scene, status)
    type(scene_input_type), intent(in) :: input
    type(scene_type), intent(inout) :: scene
    type(demstep_status_type), intent(out) :: status
    integer :: i
    status%stat = demstep_stat%ok
    if (.not. allocated(input%effects)) return
    scene%effects = .false.
    do i = 1, size(input%effects)
      if (input%effects(i) < 1 .or. input%effects(i) > n_effects) then
        call set_status(status, demstep_stat%invalid_input, "element "//int_text(i)//": "// &
          int_text(input%effects(i))//" is not an effect (1 to "//int_text(n_effects)//")", where="effects")
        return
      end if
      scene%effects(input%effects(i)) = .true.
    end do
  end subroutine scene_input_effects

  !> The input's dashpots on the scene: with the 'damping' effect, the
  !> damping ratio (or the restitution giving it), tangential, rolling and
  !> drag (unless a material set gave the scene its own and the input gives
  !> no ratio); without it, none may be given. Status invalid_input naming
  !> the variable.
  subroutine scene_input_damping(input, scene, status)
    type(scene_input_type), intent(in) :: input
    type(scene_type), intent(inout) :: scene
    type(demstep_status_type), intent(out) :: status
    real(dp) :: damping_ratio
    status%stat = demstep_stat%ok
    if (scene%effects(scene_effect%damping) .and. (allocated(input%damping_ratio) .or. &
        allocated(input%restitution) .or. .not. allocated(scene%pair_damping))) then
      ! (a code's material set gives its own dashpots: nothing more is needed)
      if (.not. (allocated(input%damping_ratio) .or. allocated(input%restitution))) then
        call set_status(status, demstep_stat%invalid_input, "the 'damping' effect needs damping_ratio " &
          //"or restitution (one)", where="damping_ratio")
        return
      end if
      damping_ratio = value_or_zero(input%damping_ratio)
      if (allocated(input%restitution)) then
        call check_lower(input%restitution, "restitution", status)
        if (status%stat == demstep_stat%ok .and. input%restitution > 1.0_dp) call set_status(status, &
          demstep_stat%invalid_input, "must be in (0, 1], got "//real_text(input%restitution, 10), where="restitution")
        if (status%stat /= demstep_stat%ok) return
        damping_ratio = restitution_to_damping_ratio(input%restitution)
      end if
      call scene_set_damping(scene, damping_ratio, status, tangential=value_or(input%damping_ratio_tangential, &
        damping_ratio), rolling=value_or_zero(input%damping_ratio_rolling), drag=value_or_zero(input%drag))
      if (status%stat /= demstep_stat%ok) return
    else if (allocated(input%damping_ratio_tangential) .or. allocated(input%damping_ratio_rolling) .or. &
        allocated(input%drag)) then
      call set_status(status, demstep_stat%invalid_input, "dashpots (damping_ratio_tangential, " &
        //"damping_ratio_rolling, drag) need the 'damping' effect", where="effects")
      return
    end if
  end subroutine scene_input_damping

  !> A snapshot's particles as the scene's arrays: masses from the file, else
  !> from the material set's densities per type (the set broadcast to the
  !> file's types when it gives one material for all).
  subroutine snapshot_particles(input, materials, snap, x, v, m, r, status, part)
    type(scene_input_type), intent(in) :: input
    type(material_set_type), intent(inout) :: materials
    type(snapshot_type), intent(out) :: snap
    real(dp), allocatable, intent(out) :: x(:, :), v(:, :), m(:), r(:)
    type(demstep_status_type), intent(out) :: status
    integer, intent(inout) :: part
    integer :: k, nt
    real(dp), allocatable :: rho(:)
    character(len=:), allocatable :: path
    path = input%snapshot_file
    if (input%dim < 2) then
      call set_status(status, demstep_stat%invalid_input, "a snapshot holds 3D positions: dim must be 3 " &
        //"(or 2, the z coordinates dropped)", where="dim")
      return
    end if
    call read_snapshot(path, snap, status, format=input%snapshot_format, frame=input%snapshot_frame)
    if (status%stat /= demstep_stat%ok) then
      if (status%where == "frame") then
        call status_restate(status, "snapshot_frame", path//": "//status%detail)
      else
        call status_restate(status, "snapshot_file", status%message)
      end if
      return
    end if
    if (snap%n == 0) then
      call set_status(status, demstep_stat%invalid_input, path//": no particles", where="snapshot_file")
      return
    end if
    if (minval(snap%type) < 1 .or. maxval(snap%type) > max_snapshot_types) then
      k = merge(minloc(snap%type, dim=1), maxloc(snap%type, dim=1), minval(snap%type) < 1)
      call set_status(status, demstep_stat%invalid_input, path//": particle "//int_text(snap%id(k))// &
        " has type "//int_text(snap%type(k))//"; types count from 1 to at most "// &
        int_text(max_snapshot_types), where="snapshot_file")
      return
    end if
    nt = maxval(snap%type)
    if (materials%found) then
      ! one material for all types, or one per type
      if (size(materials%types) == 1) then
        materials%types = spread(materials%types(1), 1, nt)
      else if (size(materials%types) < nt) then
        call set_status(status, demstep_stat%invalid_input, "one value per particle type (or one for " &
          //"all): "//path//" has types 1 to "//int_text(nt)//", the materials are "// &
          int_text(size(materials%types)), where="young")
        part = scene_input_part%material
        return
      end if
      rho = materials%types%density
      call snapshot_masses_from_types(snap, rho, status)
    else
      call snapshot_masses_from_types(snap, [real(dp) ::], status)
    end if
    if (status%stat /= demstep_stat%ok) then
      call status_restate(status, "snapshot_file", path//": "//status%message)
      return
    end if
    if (.not. snap%has_mass) then
      call set_status(status, demstep_stat%invalid_input, path//" gives no masses (no mass or density " &
        //"column): add a &material group with density (one per type)", where="snapshot_file")
      return
    end if
    x = snap%x(:input%dim, :)
    v = snap%v(:input%dim, :)
    m = snap%mass
    r = snap%radius
    status%stat = demstep_stat%ok
  end subroutine snapshot_particles

  !> A particles table: per row dim positions, dim velocities, mass, radius and
  !> fixed (0 or 1), optionally the moment of inertia (the same columns on every
  !> row); '#' starts a comment, blank lines are skipped.
  subroutine read_particles(path, dim, x, v, m, r, fixed, inertia, status)
    character(len=*), intent(in) :: path
    integer, intent(in) :: dim
    real(dp), allocatable, intent(out) :: x(:, :), v(:, :), m(:), r(:), inertia(:)
    logical, allocatable, intent(out) :: fixed(:)
    type(demstep_status_type), intent(out) :: status
    real(dp), allocatable :: rows(:, :)
    integer, allocatable :: lines(:)
    ! an optional last column: the moment of inertia
    call read_table(path, particle_columns(dim), rows, status, lines=lines)
    if (status%stat /= demstep_stat%ok) return
    call particles_from_rows(path, dim, rows, lines, x, v, m, r, fixed, inertia, status)
    if (status%stat /= demstep_stat%ok) return
    if (size(m) == 0) call set_status(status, demstep_stat%invalid_input, path//": no particles")
  end subroutine read_particles

  !> The column counts a particles table may have in `dim` dimensions:
  !> 2 dim + 3, or one more with the moment of inertia.
  pure function particle_columns(dim) result(allowed)
    integer, intent(in) :: dim
    integer :: allowed(2)
    allowed = [2*dim + 3, 2*dim + 4]
  end function particle_columns

  !> A particles table's rows (all of them, or a part read elsewhere) as the
  !> scene's arrays; status invalid_input naming `path` and the line of the
  !> first row whose fixed column is not 0 or 1 (`fault_line`, 0 if none).
  pure subroutine particles_from_rows(path, dim, rows, lines, x, v, m, r, fixed, inertia, status, fault_line)
    !> The file's name, for messages.
    character(len=*), intent(in) :: path
    integer, intent(in) :: dim
    !> The rows (`particle_columns(dim)` numbers each) and their file lines.
    real(dp), intent(in) :: rows(:, :)
    integer, intent(in) :: lines(:)
    real(dp), allocatable, intent(out) :: x(:, :), v(:, :), m(:), r(:), inertia(:)
    logical, allocatable, intent(out) :: fixed(:)
    type(demstep_status_type), intent(out) :: status
    integer, intent(out), optional :: fault_line
    integer :: ncol, bad, k, n
    logical :: with_inertia
    ncol = 2*dim + 3
    if (present(fault_line)) fault_line = 0
    n = size(rows, 2)
    with_inertia = size(rows, 1) == ncol + 1
    allocate(x(dim, n), v(dim, n), m(n), r(n), fixed(n))
    if (with_inertia) allocate(inertia(n))
    ! (one pass over the rows, each read once; the first fixed value not 0 or 1)
    bad = 0
    do k = 1, n
      x(:, k) = rows(1:dim, k)
      v(:, k) = rows(dim+1:2*dim, k)
      m(k) = rows(2*dim+1, k)
      r(k) = rows(2*dim+2, k)
      fixed(k) = rows(2*dim+3, k) /= 0.0_dp
      if (with_inertia) inertia(k) = rows(ncol + 1, k)
      if (bad == 0 .and. fixed(k) .and. rows(2*dim+3, k) /= 1.0_dp) bad = k
    end do
    if (bad > 0) then
      call set_status(status, demstep_stat%invalid_input, path//": line "//int_text(lines(bad))// &
        ": column "//int_text(2*dim + 3)//": the fixed column must be 0 or 1")
      if (present(fault_line)) fault_line = lines(bad)
      return
    end if
    status%stat = demstep_stat%ok
  end subroutine particles_from_rows

  !> A bonds table: two particle numbers per row.
  subroutine read_bonds(path, pairs, status)
    character(len=*), intent(in) :: path
    integer, allocatable, intent(out) :: pairs(:, :)
    type(demstep_status_type), intent(out) :: status
    real(dp), allocatable :: rows(:, :)
    call read_table(path, 2, rows, status, index_columns=[1, 2])
    if (status%stat /= demstep_stat%ok) return
    pairs = nint(rows)
  end subroutine read_bonds

  !> A contacts table: per row i j k_n k_t [k_r k_w [c_n c_t c_r c_w]]; the
  !> line of each row is kept for messages.
  subroutine read_contacts(path, pairs, k, lines, status)
    character(len=*), intent(in) :: path
    integer, allocatable, intent(out) :: pairs(:, :), lines(:)
    real(dp), allocatable, intent(out) :: k(:, :)
    type(demstep_status_type), intent(out) :: status
    real(dp), allocatable :: rows(:, :)
    integer :: c
    call read_table(path, contact_columns, rows, status, lines=lines, index_columns=[1, 2])
    if (status%stat /= demstep_stat%ok) return
    allocate(pairs(2, size(rows, 2)), k(size(rows, 1) - 2, size(rows, 2)))
    ! (split in parallel: each thread touches its own pages first)
    !$omp parallel do private(c) schedule(static) if(size(rows, 2) >= parallel_rows)
    do c = 1, size(rows, 2)
      pairs(:, c) = nint(rows(1:2, c))
      k(:, c) = rows(3:, c)
    end do
    !$omp end parallel do
  end subroutine read_contacts

  !> One value for all n, or n values.
  pure function broadcast(x, n) result(y)
    real(dp), intent(in) :: x(:)
    integer, intent(in) :: n
    real(dp) :: y(n)
    if (size(x) == 1) then
      y = x(1)
    else
      y = x(:n)
    end if
  end function broadcast

  pure integer function length(x)
    real(dp), allocatable, intent(in) :: x(:)
    length = 0
    if (allocated(x)) length = size(x)
  end function length

  pure integer function length_int(x)
    integer, allocatable, intent(in) :: x(:)
    length_int = 0
    if (allocated(x)) length_int = size(x)
  end function length_int

  pure logical function given_real(x)
    real(dp), allocatable, intent(in) :: x(:)
    given_real = length(x) > 0
  end function given_real

  pure real(dp) function value_or(x, default)
    real(dp), allocatable, intent(in) :: x
    real(dp), intent(in) :: default
    value_or = default
    if (allocated(x)) value_or = x
  end function value_or

  pure real(dp) function value_or_zero(x)
    real(dp), allocatable, intent(in) :: x
    value_or_zero = value_or(x, 0.0_dp)
  end function value_or_zero

end module demstep_scene_input
