!> Group `&scene`: a particle assembly, its critical time steps by four methods,
!> and optionally a run that simulates only the effects it switches on.
module demstep_cli_scene
  use demstep_status, only: set_status, demstep_status_type, demstep_stat
  use demstep_namelist, only: nml_group_type
  use demstep_table_io, only: read_table
  use demstep_scene_data, only: has_tangential, scene_effect_from_name, n_effects, scene_effect_names, &
    scene_type, scene_summary_type, scene_effect
  use demstep_scene_builders, only: new_scene, scene_add_bonds, scene_add_walls, scene_set_contacts, &
    scene_set_cell, scene_set_law, scene_set_bond_stiffness, scene_set_gravity, scene_set_types, &
    scene_set_hertz_types, scene_set_damping, scene_set_friction, scene_set_rolling, &
    scene_set_local_damping
  use demstep_spring, only: restitution_to_damping_ratio
  use demstep_interaction, only: contact_law_from_name, contact_law_names, contact_law
  use demstep_assembly, only: critical_step_type, assembly_critical_steps, &
    assembly_step_for_n_per_period, demstep_eigen_solver => eigen_solver, hertz_linearization_from_name, &
    hertz_linearization_names, dashpot_names, default_max_eigen_dof, eigen_solver_name, &
    eigen_solver_from_name, eigen_solver_names
  use demstep_kinds, only: dp, i8
  use demstep_progress, only: text_progress_type
  use demstep_scene_materials, only: scene_set_materials
  use demstep_stepper, only: scene_run
  use demstep_step_cost, only: measure_step_cost
  use demstep_lanczos, only: lanczos_tolerance_default
  use demstep_recommend, only: recommended_step, default_safety
  use demstep_snapshot, only: snapshot_type, read_snapshot, snapshot_format, snapshot_format_names, &
    snapshot_format_from_name, &
    snapshot_masses_from_types
  use demstep_material, only: material_type, material_pair_type, contact_parameters_type, &
    peer_steps_type, contact_parameters, packing_peer_steps, code_convention_names, peer_rule_names, &
    n_conventions, n_peer_rules
  use demstep_cli_material, only: read_material
  use demstep_liggghts_scene, only: liggghts_scene_type, scene_from_liggghts_script
  use demstep_cli, only: record_step, var_spec, var, given, begin_group, fmt_real, fmt_int, cli_context, &
    next_assignment, group_reading, check_real, new_array, array_length, new_int_array, int_array_length, &
    max_values, capacity_of, in_group
  use demstep_words, only: word_list, unknown_word, word_index
  use demstep_results, only: write_scene_result, write_snapshot_result
  use, intrinsic :: ieee_arithmetic, only: ieee_is_finite
  use, intrinsic :: iso_fortran_env, only: error_unit
  implicit none
  private

  public :: scene_specs, scene_doc, handle_scene, scene_takes_material, beside

  character(len=*), parameter :: scene_doc = &
    "A particle assembly: its critical time step by the per-contact rule, a rigorous bound, " &
    //"the exact limit (LAPACK or Lanczos) and the damped limit; and a run with only the effects " &
    //"switched on."

  !> Most effects one group may list.
  integer, parameter :: max_effects = 16

  !> Most particle types of a snapshot (per-type tables are nt x nt).
  integer, parameter :: max_snapshot_types = 1000

  !> The deck's `&material` group, for a snapshot's particle types.
  type :: deck_material_type
    logical :: found = .false.
    !> Line of the group in the deck.
    integer :: line = 0
    !> One material per particle type (broadcast to the snapshot's types).
    type(material_type), allocatable :: types(:)
    real(dp) :: restitution = 1.0_dp, restitution_t = 0.0_dp, impact_velocity = 0.0_dp, tolerance = 0.0_dp
    !> The conventions named by `code` (first = last: one code).
    integer :: first = 0, last = -1
  end type deck_material_type

contains

  !> The variables of `&scene`.
  function scene_specs() result(specs)
    type(var_spec), allocatable :: specs(:)
    specs = [ &
      var("dim", "an integer", "dimension: 1, 2 or 3", "2", required=.true.), &
      var("position", "a list of real numbers", "dim coordinates per particle", &
        "0.0, 0.0,  1.0, 0.0,  2.0, 0.0", capacity=3*max_values, required=.true., &
        excludes="particles_file"), &
      var("velocity", "a list of real numbers", "dim components per particle (default 0)", &
        "0.0, 0.0,  0.0, 0.0,  0.0, 0.1", capacity=3*max_values), &
      var("mass", "a list of real numbers", "one per particle, or one for all (> 0)", "1.0", &
        capacity=max_values), &
      var("radius", "a list of real numbers", "one per particle, or one for all (> 0)", "0.4", &
        capacity=max_values), &
      var("fixed", "a list of integers", "numbers of the fixed particles", "1", capacity=max_values), &
      var("bonds", "a list of integers", "pairs of particle numbers joined by bonds", "1, 2,  2, 3", &
        capacity=2*max_values), &
      var("particles_file", "a quoted file name", "table instead of the arrays: per row dim " &
        //"positions, dim velocities, mass, radius, fixed (0/1), optionally the moment of inertia; " &
        //"# comments", "!'particles.txt'", excludes="velocity mass radius fixed"), &
      var("snapshot_file", "a quoted file name", "particles (and the periodic box) from a DEM code's " &
        //"file: LAMMPS/LIGGGHTS dump or data file, Yade text export; masses from the file, else " &
        //"from a &material group's density per type", "!'dump.liggghts'", &
        excludes="position particles_file velocity mass radius fixed types"), &
      var("liggghts_script", "a quoted file name", "a LIGGGHTS input script giving the snapshot's " &
        //"contacts as LIGGGHTS computes them (units, boundary, fix property/global materials, pair_style " &
        //"gran, fix wall/gran primitives, fix gravity, timestep, variables, include): no &material needed", &
        "!'in.liggghts'", needs="snapshot_file", excludes="law k_normal e_star k_tangential kt_ratio g_star " &
        //"types type_k_normal type_k_tangential young poisson walls wall_type tangential_damping " &
        //"rolling_ratio twisting_ratio effects gravity damping_ratio restitution damping_ratio_tangential " &
        //"friction rolling_friction"), &
      var("snapshot_format", "a quoted word", "'auto', 'lammps_dump', 'lammps_data' or 'yade_text'", &
        "!'auto'", default="'auto'", needs="snapshot_file"), &
      var("snapshot_frame", "an integer", "dump frame: 1, 2, ... from the first; 0 the last, -1 the " &
        //"one before, ...", "!0", default="0", needs="snapshot_file"), &
      var("contacts_file", "a quoted file name", "explicit contacts instead of detection: per row " &
        //"i j k_n k_t [k_r k_w [c_n c_t c_r c_w]] (particle numbers as in the particle table)", &
        "!'contacts.txt'"), &
      var("periodic", "a list of logicals", "periodic axes", "!T, T, T", capacity=3, &
        default="F, F, F"), &
      var("cell_lo", "a list of real numbers", "lower corner of the periodic cell", &
        "!0.0, 0.0, 0.0", capacity=3, default="0, 0, 0"), &
      var("cell_hi", "a list of real numbers", "upper corner of the periodic cell (with periodic)", &
        "!1.0, 1.0, 1.0", capacity=3, default="!0, 0, 0"), &
      var("bonds_file", "a quoted file name", "table of bonds: per row two particle numbers", &
        "!'bonds.txt'", excludes="bonds"), &
      var("law", "a quoted word", "contact law: 'linear' (k_normal) or 'hertz' (e_star)", &
        "'linear'", default="'linear'"), &
      var("k_normal", "a real number", "linear contact stiffness (> 0)", "1.0e4", default="!0"), &
      var("e_star", "a real number", "Hertz effective modulus E* (> 0)", "!1.0e8", default="!0"), &
      var("k_tangential", "a real number", "linear tangential contact stiffness (>= 0)", &
        "!3.0e3", default="0"), &
      var("kt_ratio", "a real number", "or k_tangential as a ratio of k_normal (>= 0)", "!0.3", &
        default="!0"), &
      var("g_star", "a real number", "Hertz: G* of Mindlin's k_t = 8 G* sqrt(R* d) (>= 0)", "!4.0e7", &
        default="!0"), &
      var("friction", "a real number", "Coulomb friction coefficient of the tangential springs " &
        //"(>= 0; default none: no sliding)", "!0.5", default="!-1"), &
      var("types", "a list of integers", "material type of each particle (1, 2, ...): per-type " &
        //"stiffness instead of one law for all", "!1, 1, 2", capacity=max_values), &
      var("type_k_normal", "a list of real numbers", "linear: k_n per type pair, nt x nt (row " &
        //"by row, symmetric)", "!1.0e4, 2.0e4,  2.0e4, 3.0e4", capacity=10000), &
      var("type_k_tangential", "a list of real numbers", "linear: k_t per type pair, nt x nt " &
        //"(default kt_ratio times type_k_normal, or 0)", "!3.0e3, 6.0e3,  6.0e3, 9.0e3", capacity=10000), &
      var("young", "a list of real numbers", "Hertz: Young's modulus per type (> 0)", "!7.0e10, 2.1e11", &
        capacity=100), &
      var("poisson", "a list of real numbers", "Hertz: Poisson's ratio per type (-1 to 0.5)", &
        "!0.3, 0.25", capacity=100), &
      var("prestress", "a logical", "count the pre-stress stiffness -(F_n/l)(I - n n^T) in the " &
        //"analysis", "!F", default="F"), &
      var("k_bond", "a real number", "bond normal stiffness (> 0 when there are bonds)", "100.0", &
        default="!0"), &
      var("k_bond_tangential", "a real number", "bond tangential stiffness (>= 0)", "0.0", &
        default="0"), &
      var("walls", "a list of real numbers", "per wall: dim coordinates of a point, dim of the " &
        //"normal pointing into the domain", "!0.0, -0.5,  0.0, 1.0", capacity=64), &
      var("effects", "a list of quoted words", "'contacts' (default), 'gravity', 'damping', " &
        //"'local_damping', 'walls', 'rotation' (default with tangential springs); 'none' for " &
        //"bonds only", "'contacts'", capacity=max_effects), &
      var("gravity", "a list of real numbers", "dim components (default -9.81 along the last axis)", &
        "!0.0, -9.81", capacity=3), &
      var("damping_ratio", "a real number", "viscous damping ratio (0 to 1e100) for 'damping'", "!0.1", &
        default="0"), &
      var("restitution", "a real number", "or the restitution coefficient in (0, 1] it gives", "!0.8", &
        excludes="damping_ratio"), &
      var("local_damping", "a real number", "Cundall's alpha in [0, 1) for 'local_damping'", "!0.7", &
        default="0"), &
      var("damping_ratio_tangential", "a real number", "tangential dashpots c_t = 2 zeta_t sqrt(m* k_t) " &
        //"(0 to 1e100; default the normal ratio, as LIGGGHTS' tangential_damping on)", "!0.1", &
        default="!-1"), &
      var("damping_ratio_rolling", "a real number", "rolling and twisting dashpots c = 2 zeta_r " &
        //"sqrt(I* k_r) (0 to 1e100)", "!0.0", default="0"), &
      var("drag", "a real number", "drag of every particle to the ground, F = -drag v (>= 0; " &
        //"LIGGGHTS/LAMMPS fix viscous gamma) with 'damping'", "!0.0", default="0"), &
      var("rolling_ratio", "a real number", "rolling springs k_r = rolling_ratio k_t R*^2 (>= 0; " &
        //"LIGGGHTS epsd2: 1)", &
        "!0.0", default="0"), &
      var("twisting_ratio", "a real number", "twisting springs k_w = twisting_ratio k_t R*^2 (>= 0)", &
        "!0.0", default="0"), &
      var("tangential_damping", "a logical", "with a &material: the code's tangential dashpots " &
        //"(LIGGGHTS' tangential_damping)", "!F", default="T"), &
      var("wall_type", "an integer", "with a &material: the type (1, 2, ...) of the walls' material; " &
        //"0 each particle's own", "!1", default="0"), &
      var("rolling_friction", "a real number", "the rolling moment's cap rolling_friction R* F_n in " &
        //"a run (>= 0; default none)", "!0.1", default="!-1"), &
      var("hertz_linearization", "a quoted word", "'current' overlap, 'impact' or the 'larger' of them " &
        //"(with impact_velocity)", "!'current'", default="'current'"), &
      var("impact_velocity", "a real number", "impact speed for the 'impact' linearization (> 0)", &
        "!1.0", default="!0"), &
      var("duration", "a real number", "simulated time (>= 0; 0: no run)", "10.0", default="0"), &
      var("dt", "a real number", "time step of the run (> 0), or give n_per_period", "!0.01", &
        excludes="n_per_period"), &
      var("n_per_period", "a real number", "steps per smallest period 2 pi/omega_max (> pi " &
        //"to be stable)", "20.0"), &
      var("eigen_solver", "a quoted word", "exact omega_max by 'auto', 'dense' (LAPACK), " &
        //"'lanczos' (ARPACK) or 'none' (the bound only)", "!'auto'", default="'auto'"), &
      var("eigen_tolerance", "a real number", "Lanczos: relative residual on omega_max^2, " &
        //"in [2.2e-16, 0.1]", "!"//fmt_real(lanczos_tolerance_default), &
        default=fmt_real(lanczos_tolerance_default)), &
      var("max_eigen_dof", "an integer", "'auto' takes Lanczos above this, the largest problem " &
        //"for the dense eigensolver", "!"//fmt_int(int(default_max_eigen_dof, i8)), &
        default=fmt_int(int(default_max_eigen_dof, i8))) ]
  end function scene_specs

  !> Read, check and evaluate one `&scene` group.
  subroutine handle_scene(ctx, group, file, status)
    type(cli_context), intent(in) :: ctx
    type(nml_group_type), intent(in) :: group
    !> The input deck's name: relative table file names are relative to its directory.
    character(len=*), intent(in) :: file
    type(demstep_status_type), intent(out) :: status
    type(group_reading) :: reading
    integer :: dim, max_eigen_dof, wall_type
    real(dp), allocatable :: position(:), velocity(:), mass(:), radius(:), walls(:), gravity(:)
    integer, allocatable :: fixed(:), bonds(:), types(:)
    real(dp), allocatable :: type_k_normal(:), type_k_tangential(:), young(:), poisson(:), kk(:, :, :)
    integer :: nty, nkn, nkt, nt
    character(len=512) :: particles_file, bonds_file, contacts_file, snapshot_file, liggghts_script
    type(liggghts_scene_type) :: from_script
    character(len=32) :: snapshot_format
    integer :: snapshot_frame
    type(snapshot_type) :: snap
    type(deck_material_type) :: deck_mat
    integer, allocatable :: ptypes(:)
    logical :: from_material, typed, effects_given(n_effects)
    character(len=200), allocatable :: snapshot_lines(:)
    real(dp) :: peer_dt(n_peer_rules)
    character(len=32) :: law, hertz_linearization, eigen_solver
    character(len=32) :: effects(max_effects)
    real(dp) :: k_normal, e_star, k_bond, k_bond_tangential, damping_ratio, restitution, &
      local_damping, impact_velocity, duration, dt, n_per_period, k_tangential, kt_ratio, g_star, &
      friction, cell_lo(3), cell_hi(3), eigen_tolerance, damping_ratio_tangential, &
      damping_ratio_rolling, drag, rolling_ratio, twisting_ratio, rolling_friction
    logical :: periodic(3), prestress, tangential_damping
    namelist /scene/ dim, position, velocity, mass, radius, fixed, bonds, particles_file, &
      bonds_file, law, k_normal, e_star, k_bond, k_bond_tangential, walls, effects, gravity, &
      damping_ratio, restitution, local_damping, hertz_linearization, impact_velocity, duration, &
      dt, n_per_period, max_eigen_dof, contacts_file, periodic, cell_lo, cell_hi, k_tangential, &
      kt_ratio, g_star, friction, prestress, types, type_k_normal, type_k_tangential, young, poisson, &
      eigen_solver, eigen_tolerance, snapshot_file, snapshot_format, snapshot_frame, &
      damping_ratio_tangential, damping_ratio_rolling, drag, rolling_ratio, twisting_ratio, rolling_friction, &
      wall_type, tangential_damping, liggghts_script
    type(var_spec), allocatable :: specs(:)
    character(len=*), parameter :: g = "scene"
    type(scene_type) :: sc
    type(critical_step_type) :: crit
    type(scene_summary_type) :: summary
    real(dp), allocatable :: x(:, :), v(:, :), m(:), r(:), inertia(:), contact_k(:, :)
    integer, allocatable :: contact_pairs(:, :), contact_lines(:)
    logical, allocatable :: is_fixed(:)
    integer, allocatable :: pairs(:, :)
    integer :: i, n, np, nv, nm, nr, nf, nb, nw, mode, solver, law_id
    real(dp) :: law_values(2)
    logical :: law_given
    real(dp) :: dt_used, dt_recommended
    integer :: governs
    integer(i8) :: steps
    type(text_progress_type) :: progress

    specs = scene_specs()
    position = new_array(capacity_of(specs, "position"))
    velocity = new_array(capacity_of(specs, "velocity"))
    mass = new_array(capacity_of(specs, "mass"))
    radius = new_array(capacity_of(specs, "radius"))
    walls = new_array(capacity_of(specs, "walls"))
    gravity = new_array(capacity_of(specs, "gravity"))
    fixed = new_int_array(capacity_of(specs, "fixed"))
    bonds = new_int_array(capacity_of(specs, "bonds"))
    types = new_int_array(capacity_of(specs, "types"))
    type_k_normal = new_array(capacity_of(specs, "type_k_normal"))
    type_k_tangential = new_array(capacity_of(specs, "type_k_tangential"))
    young = new_array(capacity_of(specs, "young"))
    poisson = new_array(capacity_of(specs, "poisson"))
    effects = ""
    call begin_group(reading, group, specs, status)
    do while (next_assignment(reading, group, status))
      read(reading%text, nml=scene, iostat=reading%ios)
    end do
    if (status%stat /= demstep_stat%ok) return
    if (dim < 1 .or. dim > 3) then
      call fail("dim", "must be 1, 2 or 3, got "//fmt_int(int(dim, i8)))
      return
    end if

    ! particles: a snapshot, a table file or the arrays
    from_material = .false.
    if (given(group, "snapshot_file")) then
      call find_deck_material(ctx%groups, deck_mat, status)
      if (status%stat /= demstep_stat%ok) return
      call snapshot_particles(beside(file, trim(snapshot_file)), snapshot_format, snapshot_frame, dim, &
        deck_mat, snap, x, v, m, r, status)
      if (status%stat /= demstep_stat%ok) return
      n = size(m)
      allocate(is_fixed(n), source=.false.)
      ptypes = snap%type
      ! the materials: the scene's own stiffness variables, else the &material group
      from_material = deck_mat%found .and. .not. own_stiffness(group)
      if (.not. (from_material .or. own_stiffness(group))) then
        call fail("k_normal", "required with snapshot_file (or e_star, type_k_normal, young and poisson " &
          //"per type, liggghts_script, or a &material group in the deck)")
        return
      end if
      if (from_material .and. .not. given(group, "law")) law = material_law(deck_mat)
    else if (given(group, "particles_file")) then
      call read_particles(beside(file, trim(particles_file)), dim, x, v, m, r, is_fixed, inertia, status)
      if (status%stat /= demstep_stat%ok) then
        status%message = "&"//g//": particles_file: "//status%message
        return
      end if
      n = size(m)
    else
      call array_length(g, "position", position, np, status)
      call array_length(g, "velocity", velocity, nv, status)
      call array_length(g, "mass", mass, nm, status)
      call array_length(g, "radius", radius, nr, status)
      call int_array_length(g, "fixed", fixed, nf, status)
      if (status%stat /= demstep_stat%ok) return
      if (mod(np, dim) /= 0) then
        call fail("position", fmt_int(int(np, i8))//" values are not "//fmt_int(int(dim, i8))// &
          " per particle")
        return
      end if
      n = np/dim
      if (nv /= 0 .and. nv /= np) then
        call fail("velocity", "needs "//fmt_int(int(np, i8))//" values, got "//fmt_int(int(nv, i8)))
        return
      end if
      if (nm /= 1 .and. nm /= n) then
        call fail("mass", "needs 1 or "//fmt_int(int(n, i8))//" values, got "//fmt_int(int(nm, i8)))
        return
      end if
      if (nr /= 1 .and. nr /= n) then
        call fail("radius", "needs 1 or "//fmt_int(int(n, i8))//" values, got "//fmt_int(int(nr, i8)))
        return
      end if
      x = reshape(position(:np), [dim, n])
      allocate(v(dim, n), source=0.0_dp)
      if (nv > 0) v = reshape(velocity(:np), [dim, n])
      m = merge(spread(mass(1), 1, n), mass(:n), nm == 1)
      r = merge(spread(radius(1), 1, n), radius(:n), nr == 1)
      allocate(is_fixed(n), source=.false.)
      do i = 1, nf
        if (fixed(i) < 1 .or. fixed(i) > n) then
          call fail("fixed", "particle "//fmt_int(int(fixed(i), i8))//" does not exist (1 to "// &
            fmt_int(int(n, i8))//")")
          return
        end if
        is_fixed(fixed(i)) = .true.
      end do
    end if
    ! new_scene checks the masses, radii, positions and inertias (no contact
    ! search when the contacts are given: only listed pairs are contacts)
    if (allocated(inertia)) then
      call new_scene(sc, dim, x, m, r, status, v=v, fixed=is_fixed, inertia=inertia, &
        search=.not. given(group, "contacts_file"))
    else
      call new_scene(sc, dim, x, m, r, status, v=v, fixed=is_fixed, search=.not. given(group, "contacts_file"))
    end if
    if (status%stat /= demstep_stat%ok) then
      if (allocated(inertia) .and. status%where == "inertia") then
        status%message = "&"//g//": particles_file: "//beside(file, trim(particles_file))//": "// &
          status%message
      else
        call in_group(status, g)
      end if
      return
    end if

    ! the periodic cell (before bonds: their rest vectors go through the nearest image)
    if (given(group, "snapshot_file")) then
      ! the file's box and periodic axes, unless the deck gives them
      if (.not. given(group, "periodic")) periodic = snap%periodic
      periodic(dim+1:) = .false.
      if (snap%has_box .and. .not. given(group, "cell_hi")) then
        cell_lo = snap%lo
        cell_hi = snap%hi
      end if
    end if
    if (any(periodic)) then
      if (.not. (given(group, "cell_hi") .or. (given(group, "snapshot_file") .and. snap%has_box))) then
        call fail("cell_hi", "required with periodic axes")
        return
      end if
      call scene_set_cell(sc, periodic, cell_lo, cell_hi, status, search=.not. given(group, "contacts_file"))
      if (status%stat /= demstep_stat%ok) then
        call in_group(status, g)
        return
      end if
    end if

    ! an explicit contact list
    if (given(group, "contacts_file")) then
      call read_contacts(beside(file, trim(contacts_file)), contact_pairs, contact_k, contact_lines, status)
      if (status%stat == demstep_stat%ok) call scene_set_contacts(sc, contact_pairs, contact_k, status)
      if (status%stat /= demstep_stat%ok) then
        status%message = "&"//g//": contacts_file: "//row_to_line(status%message, &
          beside(file, trim(contacts_file)), contact_lines)
        return
      end if
    end if

    ! bonds: a table file or the array
    if (given(group, "bonds_file")) then
      call read_bonds(beside(file, trim(bonds_file)), pairs, status)
      if (status%stat /= demstep_stat%ok) then
        status%message = "&"//g//": bonds_file: "//status%message
        return
      end if
    else
      call int_array_length(g, "bonds", bonds, nb, status)
      if (status%stat /= demstep_stat%ok) return
      if (mod(nb, 2) /= 0) then
        call fail("bonds", "pairs of particle numbers: got an odd count "//fmt_int(int(nb, i8)))
        return
      end if
      pairs = reshape(bonds(:nb), [2, nb/2])
    end if
    if (size(pairs, 2) > 0) then
      call scene_add_bonds(sc, pairs, status)
      if (status%stat /= demstep_stat%ok) then
        status%message = "&"//g//": bonds: "//status%message
        return
      end if
      call scene_set_bond_stiffness(sc, k_bond, k_bond_tangential, status)
      if (status%stat /= demstep_stat%ok) then
        call in_group(status, g)
        return
      end if
    end if

    ! effects
    if (given(group, "effects")) then
      sc%effects = .false.
      do i = 1, max_effects
        if (len_trim(effects(i)) == 0) cycle
        if (word_index(["none"], effects(i)) == 1) cycle
        if (scene_effect_from_name(effects(i)) == 0) then
          call fail("effects", "unknown effect '"//trim(effects(i))//"' ("//word_list(scene_effect_names(:n_effects))// &
            ", none)")
          return
        end if
        sc%effects(scene_effect_from_name(effects(i))) = .true.
      end do
    end if
    ! per-type materials: the types array, or a snapshot's types with per-type stiffness
    typed = given(group, "types") .or. (given(group, "snapshot_file") .and. (from_material .or. &
      given(group, "type_k_normal") .or. given(group, "young")))
    law_id = contact_law_from_name(law)
    if (law_id == 0) then
      call unknown_word(status, "law", law, contact_law_names)
      call in_group(status, g)
      return
    end if
    if (law_id == contact_law%linear) then
      if (given(group, "k_tangential") .and. given(group, "kt_ratio")) then
        call fail("kt_ratio", "give either k_tangential or kt_ratio, not both")
        return
      end if
      if (given(group, "kt_ratio")) then
        ! the ratio is the app's way to give k_tangential: the library never sees it
        call check_real(g, "kt_ratio", kt_ratio, status, inclusive=.true.)
        if (status%stat /= demstep_stat%ok) return
        k_tangential = kt_ratio*k_normal
      end if
      law_values = [k_normal, k_tangential]
      law_given = given(group, "k_normal") .or. given(group, "k_tangential")
    else
      law_values = [e_star, g_star]
      law_given = given(group, "e_star") .or. given(group, "g_star")
    end if
    if (law_given .or. (sc%effects(scene_effect%contacts) .and. .not. (sc%given_contacts .or. typed .or. &
      given(group, "liggghts_script"))) &
      .or. (sc%effects(scene_effect%walls) .and. .not. from_material)) then
      call scene_set_law(sc, law_id, law_values(1), law_values(2), status)
      if (status%stat /= demstep_stat%ok) then
        call in_group(status, g)
        return
      end if
    else
      ! per-type or listed stiffness, or no contacts: the law's own values go unused
      sc%law = law_id
    end if
    if (from_material) then
      effects_given = sc%effects
      call material_springs(sc, deck_mat, ptypes, wall_type, tangential_damping, status)
      if (status%stat /= demstep_stat%ok) return
      ! the deck's effects list, where given, has the last word
      if (given(group, "effects")) sc%effects = effects_given
    else if (typed) then
      call materials()
      if (status%stat /= demstep_stat%ok) return
    end if
    if (given(group, "friction")) then
      call check_real(g, "friction", friction, status, inclusive=.true.)
      if (status%stat /= demstep_stat%ok) return
    end if
    if (given(group, "rolling_friction")) then
      call check_real(g, "rolling_friction", rolling_friction, status, inclusive=.true.)
      if (status%stat /= demstep_stat%ok) return
    end if
    call scene_set_friction(sc, friction, status, rolling_friction=rolling_friction)
    if (status%stat == demstep_stat%ok) call scene_set_rolling(sc, rolling_ratio, twisting_ratio, status)
    if (status%stat /= demstep_stat%ok) then
      call in_group(status, g)
      return
    end if
    ! rotations come with tangential springs unless the effects say otherwise
    if (.not. given(group, "effects") .and. has_tangential(sc)) sc%effects(scene_effect%rotation) = .true.
    call array_length(g, "walls", walls, nw, status)
    if (status%stat /= demstep_stat%ok) return
    if (sc%effects(scene_effect%walls) .neqv. nw > 0) then
      call fail("walls", "the 'walls' effect and the walls array go together")
      return
    end if
    if (nw > 0) then
      if (mod(nw, 2*dim) /= 0) then
        call fail("walls", "each wall is "//fmt_int(int(2*dim, i8))//" values (a point, a normal)")
        return
      end if
      call scene_add_walls(sc, reshape([(walls(2*dim*(i-1)+1:2*dim*(i-1)+dim), i = 1, nw/(2*dim))], &
        [dim, nw/(2*dim)]), reshape([(walls(2*dim*(i-1)+dim+1:2*dim*i), i = 1, nw/(2*dim))], &
        [dim, nw/(2*dim)]), status)
      if (status%stat /= demstep_stat%ok) then
        status%message = "&"//g//": walls: "//status%message
        return
      end if
    end if
    if (sc%effects(scene_effect%gravity)) then
      call array_length(g, "gravity", gravity, nv, status)
      if (status%stat /= demstep_stat%ok) return
      if (nv == 0) then
        ! the default: standard gravity along the last axis
        gravity(:dim) = 0.0_dp
        gravity(dim) = -9.81_dp
        nv = dim
      end if
      call scene_set_gravity(sc, gravity(:nv), status)
      if (status%stat /= demstep_stat%ok) then
        call in_group(status, g)
        return
      end if
    end if
    if (sc%effects(scene_effect%damping) .and. (given(group, "damping_ratio") .or. &
        given(group, "restitution") .or. .not. allocated(sc%pair_damping))) then
      ! (a code's &material gives its own dashpots: nothing more is needed)
      if (.not. (given(group, "damping_ratio") .or. given(group, "restitution"))) then
        call fail("damping_ratio", "the 'damping' effect needs damping_ratio or restitution (one)")
        return
      end if
      if (given(group, "restitution")) then
        call check_real(g, "restitution", restitution, status)
        if (status%stat == demstep_stat%ok .and. restitution > 1.0_dp) call fail("restitution", &
          "must be in (0, 1], got "//fmt_real(restitution))
        if (status%stat /= demstep_stat%ok) return
        damping_ratio = restitution_to_damping_ratio(restitution)
      end if
      if (.not. given(group, "damping_ratio_tangential")) damping_ratio_tangential = damping_ratio
      call scene_set_damping(sc, damping_ratio, status, tangential=damping_ratio_tangential, &
        rolling=damping_ratio_rolling, drag=drag)
      if (status%stat /= demstep_stat%ok) then
        call in_group(status, g)
        return
      end if
    else if (given(group, "damping_ratio_tangential") .or. given(group, "damping_ratio_rolling") .or. &
        given(group, "drag")) then
      call fail("effects", "dashpots (damping_ratio_tangential, damping_ratio_rolling, drag) need " &
        //"the 'damping' effect")
      return
    end if
    if (from_material .and. .not. (given(group, "effects") .or. given(group, "damping_ratio") .or. &
      given(group, "restitution"))) then
      ! the code damps its contacts to the &material's restitution (unless its
      ! convention has no contact damping, as Yade's FrictPhys)
      if (material_damped(deck_mat)) then
        call scene_set_damping(sc, restitution_to_damping_ratio(deck_mat%restitution), status)
        if (status%stat /= demstep_stat%ok) then
          status%message = "&material: restitution: "//status%message
          return
        end if
      end if
    end if
    if (sc%effects(scene_effect%local_damping)) then
      call check_real(g, "local_damping", local_damping, status, inclusive=.true.)
      if (status%stat /= demstep_stat%ok) return
      call scene_set_local_damping(sc, local_damping, status)
      if (status%stat /= demstep_stat%ok) then
        call in_group(status, g)
        return
      end if
      sc%effects(scene_effect%local_damping) = .true.
    end if
    if (given(group, "liggghts_script")) then
      ! the script gives the contacts, walls, gravity and effects (the library's conversion)
      call scene_from_liggghts_script(sc, beside(file, trim(liggghts_script)), snap, from_script, status)
      if (status%stat /= demstep_stat%ok) then
        status%message = "&"//g//": liggghts_script: "//status%message
        return
      end if
    end if
    if (from_material .and. .not. given(group, "hertz_linearization")) then
      ! a &material gives the impact velocity: linearise at the larger of the
      ! current overlap and the impact's (a settled contact may be struck)
      hertz_linearization = "larger"
      if (.not. given(group, "impact_velocity")) impact_velocity = deck_mat%impact_velocity
    end if
    ! the library checks impact_velocity where the mode needs it
    mode = hertz_linearization_from_name(hertz_linearization)
    if (mode == 0) then
      call unknown_word(status, "hertz_linearization", hertz_linearization, hertz_linearization_names)
      call in_group(status, g)
      return
    end if
    call check_real(g, "duration", duration, status, inclusive=.true.)
    if (given(group, "dt")) call check_real(g, "dt", dt, status)
    if (status%stat /= demstep_stat%ok) return
    if (duration > 0.0_dp .and. .not. (given(group, "dt") .or. given(group, "n_per_period"))) then
      call fail("dt", "a run (duration > 0) needs dt or n_per_period")
      return
    end if

    solver = eigen_solver_from_name(eigen_solver)
    if (solver == 0) then
      call unknown_word(status, "eigen_solver", eigen_solver, eigen_solver_names)
      call in_group(status, g)
      return
    end if
    if (ctx%quiet) then
      call assembly_critical_steps(sc, crit, status, hertz_mode=mode, impact_velocity=impact_velocity, &
        max_eigen_dof=max_eigen_dof, prestress=prestress, solver=solver, tolerance=eigen_tolerance)
    else
      progress = text_progress_type(unit=error_unit, label="demstep: &"//g)
      call assembly_critical_steps(sc, crit, status, hertz_mode=mode, impact_velocity=impact_velocity, &
        max_eigen_dof=max_eigen_dof, prestress=prestress, solver=solver, tolerance=eigen_tolerance, &
        progress=progress)
    end if
    if (status%stat /= demstep_stat%ok) then
      if (status%where == "effects" .and. given(group, "bonds_file")) then
        ! the empty table is what left the scene without springs
        call fail("bonds_file", beside(file, trim(bonds_file))//": holds no bonds, and neither " &
          //"'contacts' nor 'walls' is in effects: the scene has no stiffness")
      else
        ! the library's Lanczos tolerance is this group's eigen_tolerance
        call in_group(status, g, reshape([character(len=15) :: "tolerance", "eigen_tolerance"], [2, 1]))
      end if
      return
    end if
    dt_used = 0.0_dp
    steps = 0_i8
    if (duration > 0.0_dp) then
      if (given(group, "dt")) then
        dt_used = dt
      else
        call assembly_step_for_n_per_period(crit, n_per_period, dt_used, status)
        if (status%stat /= demstep_stat%ok) then
          call in_group(status, g)
          return
        end if
      end if
      call plan_run(ctx, g, sc%n, crit%n_springs, duration, dt_used, steps, status)
      if (status%stat /= demstep_stat%ok) return
      if (ctx%quiet) then
        call scene_run(sc, dt_used, steps, summary, status)
      else
        progress = text_progress_type(unit=error_unit, label="demstep: &"//g)
        call scene_run(sc, dt_used, steps, summary, status, progress=progress)
      end if
      ! a blow-up is a result to report, not an input error
      if (status%stat == demstep_stat%blow_up) status%stat = demstep_stat%ok
      if (status%stat /= demstep_stat%ok) then
        call in_group(status, g)
        return
      end if
    end if
    ! the damped limit is that of the exact omega_max, or of the bound when the
    ! dense solver was not run: the recommendation is safe either way
    call recommended_step(crit%dt_critical_damped, dt_recommended, governs, status)
    if (status%stat /= demstep_stat%ok) then
      call in_group(status, g)
      return
    end if
    if (given(group, "snapshot_file")) then
      call snapshot_summary(beside(file, trim(snapshot_file)), snap, deck_mat, from_material, sc, crit, &
        snapshot_lines, peer_dt, status)
      if (status%stat /= demstep_stat%ok) return
      if (given(group, "liggghts_script")) snapshot_lines = [snapshot_lines, &
        script_summary(from_script, crit%dt_critical_damped, crit%eigen_computed, dt_recommended)]
      call report(ctx%report, group, sc, crit, duration > 0.0_dp, dt_used, steps, summary, dt_recommended, &
        snapshot_lines)
    else
      call report(ctx%report, group, sc, crit, duration > 0.0_dp, dt_used, steps, summary, dt_recommended)
    end if
    call write_scene_result(ctx%results, sc, crit, dt_used, summary, dt_recommended)
    call record_step(ctx, "assembly step", dt_recommended, .true., group)
    if (given(group, "snapshot_file")) call write_snapshot_result(ctx%results, snap, deck_mat%found, crit, peer_dt)

  contains

    subroutine fail(name, what)
      character(len=*), intent(in) :: name, what
      call set_status(status, demstep_stat%invalid_input, "&"//g//": "//name//": "//what)
    end subroutine fail

    !> Materials per particle type: the tables read, the library checks them.
    subroutine materials()
      if (.not. given(group, "snapshot_file")) then
        call int_array_length(g, "types", types, nty, status)
        if (status%stat /= demstep_stat%ok) return
        if (nty /= n) then
          call fail("types", "needs one type per particle ("//fmt_int(int(n, i8))//"), got "// &
            fmt_int(int(nty, i8)))
          return
        end if
        ptypes = types(:n)
      end if
      if (sc%law == contact_law%linear) then
        call array_length(g, "type_k_normal", type_k_normal, nkn, status)
        call array_length(g, "type_k_tangential", type_k_tangential, nkt, status)
        if (status%stat /= demstep_stat%ok) return
        nt = nint(sqrt(real(nkn, dp)))
        if (nkn == 0 .or. nt*nt /= nkn) then
          call fail("type_k_normal", "needs nt x nt values (nt types, row by row), got "// &
            fmt_int(int(nkn, i8)))
          return
        end if
        allocate(kk(2, nt, nt), source=0.0_dp)
        kk(1, :, :) = reshape(type_k_normal(:nkn), [nt, nt])
        if (nkt > 0) then
          if (nkt /= nkn) then
            call fail("type_k_tangential", "needs as many values as type_k_normal ("// &
              fmt_int(int(nkn, i8))//"), got "//fmt_int(int(nkt, i8)))
            return
          end if
          kk(2, :, :) = reshape(type_k_tangential(:nkt), [nt, nt])
        else if (given(group, "kt_ratio")) then
          kk(2, :, :) = kt_ratio*kk(1, :, :)
        end if
        call scene_set_types(sc, ptypes, kk, status)
      else
        call array_length(g, "young", young, nkn, status)
        call array_length(g, "poisson", poisson, nkt, status)
        if (status%stat /= demstep_stat%ok) return
        if (nkn == 0) then
          call fail("young", "required with types and the Hertz law (one per type)")
          return
        end if
        call scene_set_hertz_types(sc, ptypes, young(:nkn), poisson(:nkt), status)
      end if
      if (status%stat /= demstep_stat%ok) call in_group(status, g)
    end subroutine materials

  end subroutine handle_scene

  !> Whether a `&scene` among `groups` takes its particle types' materials
  !> from the deck's `&material` group: a snapshot without stiffness of its own.
  pure logical function scene_takes_material(groups) result(takes)
    type(nml_group_type), intent(in) :: groups(:)
    integer :: k
    takes = .false.
    do k = 1, size(groups)
      if (groups(k)%name /= "scene") cycle
      if (given(groups(k), "snapshot_file") .and. .not. own_stiffness(groups(k))) takes = .true.
    end do
  end function scene_takes_material

  !> Whether a `&scene` group gives the contact stiffness itself (one law, or per type).
  pure logical function own_stiffness(group)
    type(nml_group_type), intent(in) :: group
    own_stiffness = given(group, "k_normal") .or. given(group, "e_star") .or. &
      given(group, "type_k_normal") .or. given(group, "young") .or. given(group, "liggghts_script")
  end function own_stiffness

  !> The step count of a run, refused when it is absurd, and announced on stderr
  !> (unless quiet) when the run is big enough to matter: the cost per
  !> particle-step is then measured (`measure_step_cost`, about 0.2 s) and the
  !> work counted as max(particles, springs/3) per step (the measured lattice
  !> has about 3 springs per particle). Refused: more than `max_run_steps` steps
  !> or an estimate above `max_run_seconds`, with the duration that fits.
  subroutine plan_run(ctx, g, n, n_springs, duration, dt, steps, status)
    type(cli_context), intent(in) :: ctx
    character(len=*), intent(in) :: g
    integer, intent(in) :: n, n_springs
    real(dp), intent(in) :: duration, dt
    integer(i8), intent(out) :: steps
    type(demstep_status_type), intent(out) :: status
    !> Runs of fewer particle-steps take about a second at most: no estimate.
    real(dp), parameter :: announce_work = 2.0e7_dp
    !> Most steps (int64 holds 9.2e18) and most estimated seconds (30 days).
    real(dp), parameter :: max_run_steps = 1.0e18_dp, max_run_seconds = 30.0_dp*86400.0_dp
    real(dp) :: steps_real, per_step, cost, seconds, longest
    type(demstep_status_type) :: measured
    character(len=:), allocatable :: about
    steps = 0_i8
    steps_real = duration/dt
    per_step = max(real(n, dp), real(n_springs, dp)/3.0_dp)
    cost = 0.0_dp
    if (steps_real*per_step >= announce_work) then
      call measure_step_cost(cost, measured, seconds=0.05_dp)
      if (measured%stat /= demstep_stat%ok) cost = 0.0_dp
    end if
    seconds = steps_real*per_step*cost
    if (.not. (steps_real <= max_run_steps .and. seconds <= max_run_seconds)) then
      ! the longest duration within both limits
      longest = max_run_steps*dt
      if (cost > 0.0_dp) longest = min(longest, max_run_seconds/(per_step*cost)*dt)
      about = ""
      if (cost > 0.0_dp .and. ieee_is_finite(seconds)) about = ", about "//fmt_real(seconds)//" s"
      call set_status(status, demstep_stat%invalid_input, "&"//g//": duration: "// &
        fmt_real(duration)//" at dt = "//fmt_real(dt)//" is "//fmt_real(steps_real)//" steps of "// &
        fmt_int(int(n, i8))//" particles"//about//", more than 1e18 steps or 30 days of work: " &
        //"duration must be at most "//fmt_real(longest))
      return
    end if
    steps = max(1_i8, nint(steps_real, i8))
    if (cost > 0.0_dp .and. .not. ctx%quiet) then
      write(error_unit, '(a)') "demstep: &"//g//": "//fmt_int(steps)//" steps of "// &
        fmt_int(int(n, i8))//" particles, about "//fmt_real(seconds)//" s ("//fmt_real(cost)// &
        " s per particle-step measured)"
      flush(error_unit)
    end if
    status%stat = demstep_stat%ok
  end subroutine plan_run

  !> `name` relative to the directory of `deck` (unless absolute).
  pure function beside(deck, name) result(path)
    character(len=*), intent(in) :: deck, name
    character(len=:), allocatable :: path
    integer :: k
    k = index(deck, "/", back=.true.)
    if (k == 0 .or. name(1:min(1, len(name))) == "/") then
      path = name
    else
      path = deck(:k)//name
    end if
  end function beside

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
    integer :: ncol, bad
    integer, allocatable :: lines(:)
    ncol = 2*dim + 3
    ! an optional last column: the moment of inertia
    call read_table(path, [ncol, ncol + 1], rows, status, lines=lines)
    if (status%stat /= demstep_stat%ok) return
    x = rows(1:dim, :)
    v = rows(dim+1:2*dim, :)
    m = rows(2*dim+1, :)
    r = rows(2*dim+2, :)
    fixed = rows(2*dim+3, :) /= 0.0_dp
    if (size(rows, 1) == ncol + 1) inertia = rows(ncol + 1, :)
    bad = findloc(rows(2*dim+3, :) /= 0.0_dp .and. rows(2*dim+3, :) /= 1.0_dp, .true., dim=1)
    if (bad > 0) then
      call set_status(status, demstep_stat%invalid_input, path//": line "//fmt_int(int(lines(bad), i8))// &
        ": column "//fmt_int(int(2*dim + 3, i8))//": the fixed column must be 0 or 1")
      return
    end if
    if (size(m) == 0) call set_status(status, demstep_stat%invalid_input, path//": no particles")
  end subroutine read_particles

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

  !> A contacts table: per row i j k_n k_t; the line of each row is kept for messages.
  subroutine read_contacts(path, pairs, k, lines, status)
    character(len=*), intent(in) :: path
    integer, allocatable, intent(out) :: pairs(:, :), lines(:)
    real(dp), allocatable, intent(out) :: k(:, :)
    type(demstep_status_type), intent(out) :: status
    real(dp), allocatable :: rows(:, :)
    ! i j, then k_n k_t [k_r k_w [c_n c_t c_r c_w]]
    call read_table(path, [4, 6, 10], rows, status, lines=lines, index_columns=[1, 2])
    if (status%stat /= demstep_stat%ok) return
    pairs = nint(rows(1:2, :))
    k = rows(3:, :)
  end subroutine read_contacts

  !> A library message "contacts: row K: what" as "PATH: line L: what".
  function row_to_line(message, path, lines) result(text)
    character(len=*), intent(in) :: message, path
    integer, intent(in), allocatable :: lines(:)
    character(len=:), allocatable :: text
    integer :: a, b, row, ios
    text = message
    a = index(message, "contacts: row ")
    if (a /= 1 .or. .not. allocated(lines)) return
    b = index(message(15:), ":") + 13
    read(message(15:b), *, iostat=ios) row
    if (ios /= 0 .or. row < 1 .or. row > size(lines)) return
    text = path//": line "//fmt_int(int(lines(row), i8))//message(b+1:)
  end function row_to_line

  subroutine report(u, group, sc, crit, ran, dt_used, steps, summary, dt_recommended, extra)
    integer, intent(in) :: u
    type(nml_group_type), intent(in) :: group
    type(scene_type), intent(in) :: sc
    type(critical_step_type), intent(in) :: crit
    logical, intent(in) :: ran
    real(dp), intent(in) :: dt_used
    integer(i8), intent(in) :: steps
    type(scene_summary_type), intent(in) :: summary
    real(dp), intent(in) :: dt_recommended
    !> Lines written before the recommendation (a snapshot's peers' rules).
    character(len=*), intent(in), optional :: extra(:)
    integer :: i
    character(len=:), allocatable :: on
    on = ""
    do i = 1, n_effects
      if (sc%effects(i)) on = on//" "//trim(scene_effect_names(i))
    end do
    if (len(on) == 0) on = " none (bonds only)"
    write(u, '(a)') "&scene (line "//fmt_int(int(group%line, i8))//")"
    write(u, '(2x, a)') fmt_int(int(sc%n, i8))//" particles in "//fmt_int(int(sc%dim, i8))//"D, "// &
      fmt_int(int(crit%n_dof, i8))//" degrees of freedom, "//fmt_int(int(crit%n_springs, i8))// &
      " springs (bonds and contacts); effects:"//on
    write(u, '(2x, a)') "model: "//fmt_int(int(crit%dof_per_particle, i8))//" degrees of freedom per " &
      //"particle, tangential springs "//trim(merge("counted", "none   ", crit%tangential))// &
      ", periodic "//trim(merge("yes", "no ", crit%periodic))//", pre-stress "// &
      trim(merge("yes", "no ", crit%prestress))
    write(u, '(2x, a)') "critical time step (undamped central differences, 2/omega):"
    write(u, '(4x, a, t40, a)') "per-contact rule 2 sqrt(m*/k)", fmt_real(crit%dt_contact_rule)// &
      "  (not safe in an assembly)"
    write(u, '(4x, a, t40, a)') "Gershgorin bound (safe)", fmt_real(crit%dt_critical_bound)
    if (crit%solver == demstep_eigen_solver%dense) then
      write(u, '(4x, a, t40, a)') "exact, LAPACK dsyevr", fmt_real(crit%dt_critical_eigen)// &
        "  (omega_max = "//fmt_real(crit%omega_max)//")"
    else if (crit%solver == demstep_eigen_solver%lanczos .and. crit%eigen_converged) then
      write(u, '(4x, a, t40, a)') "exact, Lanczos (ARPACK)", fmt_real(crit%dt_critical_eigen)// &
        "  (omega_max = "//fmt_real(crit%omega_max)//", "//fmt_int(crit%eigen_products)//" products)"
    else if (crit%solver == demstep_eigen_solver%lanczos) then
      write(u, '(4x, a, t40, a)') "Lanczos (ARPACK), not converged", "omega_max in ["// &
        fmt_real(crit%omega_max)//", "//fmt_real(crit%omega_upper)//"] after "// &
        fmt_int(crit%eigen_products)//" products"
    else
      write(u, '(4x, a, t40, a)') "exact", "not computed (eigen_solver = 'none')"
    end if
    if (crit%eigen_computed) write(u, '(4x, a, t40, a)') "safe to the error bar", &
      fmt_real(crit%dt_critical_safe)//"  (residual "//fmt_real(crit%eigen_residual)// &
      ", tolerance "//fmt_real(crit%eigen_tolerance)//")"
    if (crit%damped_exact) then
      write(u, '(4x, a, t40, a)') "damped, exact (lagged dashpots)", fmt_real(crit%dt_critical_damped)// &
        "  (as one spring of damping ratio "//fmt_real(crit%damping_ratio_top)//"; "// &
        fmt_int(int(crit%damped_solves, i8))//" solves)"
    else
      write(u, '(4x, a, t40, a)') "damped (lagged dashpots)", fmt_real(crit%dt_critical_damped)// &
        "  (the rigorous lower bound)"
    end if
    if (any(crit%dashpots)) then
      on = ""
      do i = 1, size(crit%dashpots)
        if (crit%dashpots(i)) on = on//" "//trim(dashpot_names(i))
      end do
      write(u, '(4x, a, t40, a)') "dashpots in C", on(2:)//"; lower bound "// &
        fmt_real(crit%dt_critical_damped_bound)
    end if
    if (ran) then
      write(u, '(2x, a)') "run: "//fmt_int(steps)//" steps of "//fmt_real(dt_used)//":"
      write(u, '(4x, a, t40, a)') "energy drift (relative)", fmt_real(summary%energy_drift)
      write(u, '(4x, a, t40, a)') "largest overlap", fmt_real(summary%max_overlap)
      write(u, '(4x, a, t40, a)') "most contacts at once", fmt_int(int(summary%max_contacts, i8))
      if (summary%blew_up) then
        write(u, '(4x, a, t40, a)') "blew up", "YES, stopped after "//fmt_int(summary%steps)//" steps"
      else
        write(u, '(4x, a, t40, a)') "blew up", "no"
      end if
    end if
    if (present(extra)) then
      do i = 1, size(extra)
        write(u, '(a)') trim(extra(i))
      end do
    end if
    if (crit%eigen_computed) then
      write(u, '(2x, a, t28, a)') "governs", "stability ("//fmt_real(default_safety)// &
        " of the damped critical step of omega_max)"
    else
      write(u, '(2x, a, t28, a)') "governs", "stability ("//fmt_real(default_safety)// &
        " of the damped step of the bound)"
    end if
    write(u, '(2x, a, t28, a)') "assembly step", fmt_real(dt_recommended)//" s"
    write(u, '(a)') ""
  end subroutine report

  ! ------------------------------------------------------------ snapshots

  !> The deck's `&material` group, if it has one (read as `&material` reads it).
  subroutine find_deck_material(groups, mat, status)
    !> The deck's groups, as scanned once.
    type(nml_group_type), intent(in) :: groups(:)
    type(deck_material_type), intent(out) :: mat
    type(demstep_status_type), intent(out) :: status
    integer :: k, found
    status%stat = demstep_stat%ok
    found = 0
    do k = 1, size(groups)
      if (groups(k)%name /= "material") cycle
      found = found + 1
      if (found > 1) then
        call set_status(status, demstep_stat%invalid_input, "&scene: snapshot_file: the deck has more " &
          //"than one &material group (lines "//fmt_int(int(mat%line, i8))//" and "// &
          fmt_int(int(groups(k)%line, i8))//"): the snapshot's types take one; merge them")
        return
      end if
      mat%found = .true.
      mat%line = groups(k)%line
      call read_material(groups(k), mat%types, mat%restitution, mat%restitution_t, mat%impact_velocity, &
        mat%first, mat%last, mat%tolerance, status)
      if (status%stat /= demstep_stat%ok) return
    end do
    status%stat = demstep_stat%ok
  end subroutine find_deck_material

  !> Read a snapshot; its particles as the scene's arrays. Masses from the
  !> file, else from the `&material` densities per type.
  subroutine snapshot_particles(path, format_word, frame, dim, mat, snap, x, v, m, r, status)
    character(len=*), intent(in) :: path, format_word
    integer, intent(in) :: frame, dim
    type(deck_material_type), intent(inout) :: mat
    type(snapshot_type), intent(out) :: snap
    real(dp), allocatable, intent(out) :: x(:, :), v(:, :), m(:), r(:)
    type(demstep_status_type), intent(out) :: status
    integer :: code, k, nt
    real(dp), allocatable :: rho(:)
    character(len=*), parameter :: g = "&scene: "
    code = snapshot_format_from_name(format_word)
    if (code < snapshot_format%auto) then
      call unknown_word(status, "snapshot_format", format_word, snapshot_format_names)
      call in_group(status, "scene")
      return
    end if
    if (dim < 2) then
      call set_status(status, demstep_stat%invalid_input, g//"dim: a snapshot holds 3D positions: dim " &
        //"must be 3 (or 2, the z coordinates dropped)")
      return
    end if
    call read_snapshot(path, snap, status, format=code, frame=frame)
    if (status%stat /= demstep_stat%ok) then
      if (status%where == "frame") then
        status%message = g//"snapshot_frame: "//path//": "//status%detail
      else
        status%message = g//"snapshot_file: "//status%message
      end if
      return
    end if
    if (snap%n == 0) then
      call set_status(status, demstep_stat%invalid_input, g//"snapshot_file: "//path//": no particles")
      return
    end if
    if (minval(snap%type) < 1 .or. maxval(snap%type) > max_snapshot_types) then
      k = merge(minloc(snap%type, dim=1), maxloc(snap%type, dim=1), minval(snap%type) < 1)
      call set_status(status, demstep_stat%invalid_input, g//"snapshot_file: "//path//": particle "// &
        fmt_int(snap%id(k))//" has type "//fmt_int(int(snap%type(k), i8))//"; types count from 1 to at " &
        //"most "//fmt_int(int(max_snapshot_types, i8)))
      return
    end if
    nt = maxval(snap%type)
    if (mat%found) then
      ! one material for all types, or one per type
      if (size(mat%types) == 1) then
        mat%types = spread(mat%types(1), 1, nt)
      else if (size(mat%types) < nt) then
        call set_status(status, demstep_stat%invalid_input, "&material: young: one value per particle " &
          //"type (or one for all): "//path//" has types 1 to "//fmt_int(int(nt, i8))//", the group (line " &
          //fmt_int(int(mat%line, i8))//") gives "//fmt_int(int(size(mat%types), i8)))
        return
      end if
      rho = mat%types%density
      call snapshot_masses_from_types(snap, rho, status)
    else
      call snapshot_masses_from_types(snap, [real(dp) ::], status)
    end if
    if (status%stat /= demstep_stat%ok) then
      status%message = g//"snapshot_file: "//path//": "//status%message
      return
    end if
    if (.not. snap%has_mass) then
      call set_status(status, demstep_stat%invalid_input, g//"snapshot_file: "//path//" gives no masses " &
        //"(no mass or density column): add a &material group with density (one per type)")
      return
    end if
    x = snap%x(:dim, :)
    v = snap%v(:dim, :)
    m = snap%mass
    r = snap%radius
    status%stat = demstep_stat%ok
  end subroutine snapshot_particles

  !> The contact law a `&material` code implies: 'hertz' for all codes or a
  !> Hertz convention (one evaluated at an overlap), else 'linear'.
  function material_law(mat) result(law)
    type(deck_material_type), intent(in) :: mat
    character(len=32) :: law
    type(contact_parameters_type) :: params
    type(demstep_status_type) :: status
    law = "hertz"
    if (mat%first /= mat%last) return
    call contact_parameters(material_pair_type(mat%types(1), mat%types(1), mat%restitution, &
      mat%restitution_t, mat%impact_velocity), mat%first, params, status)
    if (status%stat == demstep_stat%ok .and. params%overlap == 0.0_dp) law = "linear"
  end function material_law

  !> Whether the `&material`'s code damps its contacts: all codes, or one whose
  !> convention gives a normal dashpot.
  logical function material_damped(mat) result(damped)
    type(deck_material_type), intent(in) :: mat
    type(contact_parameters_type) :: params
    type(demstep_status_type) :: status
    damped = .true.
    if (mat%first /= mat%last) return
    call contact_parameters(material_pair_type(mat%types(1), mat%types(1), mat%restitution, &
      mat%restitution_t, mat%impact_velocity), mat%first, params, status)
    if (status%stat == demstep_stat%ok) damped = params%gamma_n > 0.0_dp
  end function material_damped

  !> Per-type springs and dashpots from the `&material` group: one code named,
  !> its own convention through the library (`scene_set_materials`: the law,
  !> the per-pair springs and dashpots, the walls' as contacts of type
  !> `wall_type`); all codes, Hertz E* and G* from young and poisson.
  subroutine material_springs(sc, mat, ptypes, wall_type, tangential_damping, status)
    type(scene_type), intent(inout) :: sc
    type(deck_material_type), intent(in) :: mat
    integer, intent(in) :: ptypes(:), wall_type
    logical, intent(in) :: tangential_damping
    type(demstep_status_type), intent(out) :: status
    real(dp), allocatable :: young(:), poisson(:)
    if (mat%first == mat%last) then
      call scene_set_materials(sc, ptypes, mat%types, mat%first, mat%restitution, status, &
        restitution_t=mat%restitution_t, impact_velocity=mat%impact_velocity, wall_type=wall_type, &
        tangential_damping=tangential_damping)
      if (status%stat /= demstep_stat%ok) then
        if (status%where == "wall_type" .or. status%where == "types") then
          call in_group(status, "scene")
        else
          call in_group(status, "material")
        end if
      end if
      return
    end if
    if (sc%law == contact_law%hertz) then
      young = mat%types%young
      poisson = mat%types%poisson
      call scene_set_hertz_types(sc, ptypes, young, poisson, status)
      if (status%stat /= demstep_stat%ok) call in_group(status, "material")
      return
    end if
    call set_status(status, demstep_stat%invalid_input, "&material: code: the linear law of &scene " &
      //"takes k_n and k_t from one code's convention: name it (liggghts_hooke, yade_frictphys, " &
      //"yade_viscelphys, mfix_lsd, mercurydpm_linear, lammps_hooke)")
  end subroutine material_springs

  !> A LIGGGHTS script's part of the report: what it gave, and its `timestep`
  !> against the damped limit `dt_limit` (`exact`, or the safe bound), with
  !> the recommendation.
  function script_summary(info, dt_limit, exact, dt_recommended) result(lines)
    type(liggghts_scene_type), intent(in) :: info
    real(dp), intent(in) :: dt_limit, dt_recommended
    logical, intent(in) :: exact
    character(len=200), allocatable :: lines(:)
    character(len=:), allocatable :: walls, units, where, limit
    real(dp) :: ratio
    associate (s => info%script, c => info%contacts)
      walls = "no walls"
      if (s%n_walls > 0) walls = fmt_int(int(s%n_walls, i8))//" primitive wall"// &
        trim(merge("s", " ", s%n_walls > 1))//" of type "//fmt_int(int(c%wall_type, i8))
      units = "units not stated"
      if (s%units_line > 0) units = "units "//trim(merge("si ", "cgs", s%units == 1))
      lines = [character(len=200) :: "    script: "//info%file//": "// &
        trim(code_convention_names(c%convention))//", "//fmt_int(int(size(c%young), i8))//" atom type"// &
        trim(merge("s", " ", size(c%young) > 1))//", "//walls//", restitution "//fmt_real(c%restitution)// &
        ", tangential_damping "//trim(merge("on ", "off", c%tangential_damping))//", rolling springs "// &
        trim(merge("on ", "off", c%rolling_ratio > 0.0_dp))//"; "//units]
      if (c%friction_per_pair) lines = [character(len=200) :: lines, "    (its friction differs between " &
        //"type pairs, line "//fmt_int(int(merge(s%friction_line, s%rolling_friction_line, c%friction < 0.0_dp &
        .and. s%friction_line > 0), i8))//": not taken; the limit takes every contact sticking)"]
    end associate
    if (info%timestep_line == 0) then
      lines = [character(len=200) :: lines, "    your script states no timestep: use at most "// &
        fmt_real(dt_recommended)//" s"]
      return
    end if
    ratio = info%timestep/dt_limit
    where = " (line "//fmt_int(int(info%timestep_line, i8))//")"
    if (info%timestep_file /= info%file) where = " ("//info%timestep_file//": line "// &
      fmt_int(int(info%timestep_line, i8))//")"
    limit = "exact limit"
    if (.not. exact) limit = "safe bound on the limit"
    lines = [character(len=200) :: lines, "    your script's timestep "//fmt_real(info%timestep)//" s"//where// &
      " is "//fmt_real(ratio)//" times the "//limit//" "//fmt_real(dt_limit)//" s"]
    if (ratio >= 1.0_dp) then
      lines = [character(len=200) :: lines, "    it is not stable: lower it to "//fmt_real(dt_recommended)//" s"]
    else if (info%timestep > dt_recommended) then
      lines = [character(len=200) :: lines, "    it is within "//fmt_real(1.0_dp - ratio)//" of the limit: " &
        //"lower it to "//fmt_real(dt_recommended)//" s"]
    else
      lines = [character(len=200) :: lines, "    it is stable; "//fmt_real(dt_recommended)//" s (" &
        //fmt_real(dt_recommended/info%timestep)//" times it) would be too"]
    end if
  end function script_summary

  !> A snapshot's part of the report: what was read, and with a `&material`
  !> group the peers' rules beside demstep's exact limit (as ratios). The
  !> peers' rules take each type's smallest radius in the file (their codes
  !> check every particle); `peer_dt` 0 without a `&material` group.
  subroutine snapshot_summary(path, snap, mat, from_material, sc, crit, lines, peer_dt, status)
    character(len=*), intent(in) :: path
    type(snapshot_type), intent(in) :: snap
    type(deck_material_type), intent(in) :: mat
    logical, intent(in) :: from_material
    type(scene_type), intent(in) :: sc
    type(critical_step_type), intent(in) :: crit
    character(len=200), allocatable, intent(out) :: lines(:)
    real(dp), intent(out) :: peer_dt(n_peer_rules)
    type(demstep_status_type), intent(out) :: status
    type(peer_steps_type) :: steps
    real(dp) :: rayleigh, hertz, exact
    integer :: nt, i, c, nl
    character(len=:), allocatable :: solver, axes, masses, frame
    peer_dt = 0.0_dp
    nt = maxval(snap%type)
    allocate(lines(20 + n_peer_rules))
    nl = 0
    frame = ""
    if (snap%format == snapshot_format%lammps_dump) frame = ", frame "//fmt_int(int(snap%frame, i8))//" of " &
      //fmt_int(int(snap%n_frames, i8))//", timestep "//fmt_int(snap%timestep)
    call add("  snapshot: "//path//" ("//trim(snapshot_format_names(snap%format))//frame//"), "// &
      fmt_int(int(nt, i8))//" particle type"//trim(merge("s", " ", nt > 1)))
    axes = ""
    do i = 1, sc%dim
      if (sc%periodic(i)) axes = axes//" "//achar(iachar("x") + i - 1)
    end do
    if (len(axes) == 0) axes = " none"
    masses = "from the file"
    if (.not. any(snap%mass > 0.0_dp .and. snap%density == 0.0_dp)) masses = "from the densities"
    call add("    periodic axes:"//axes//"; masses "//masses//"; radii "//fmt_real(minval(snap%radius))// &
      " to "//fmt_real(maxval(snap%radius)))
    if (from_material) then
      call add("    materials: &material (line "//fmt_int(int(mat%line, i8))//"), "//trim(material_note())// &
        ", restitution "//fmt_real(mat%restitution))
    else if (mat%found) then
      call add("    materials: the &scene's stiffness; &material (line "//fmt_int(int(mat%line, i8))// &
        ") for the peers' rules")
    end if
    exact = crit%dt_critical_damped
    solver = "bound"
    if (crit%solver == demstep_eigen_solver%dense) solver = "LAPACK"
    if (crit%solver == demstep_eigen_solver%lanczos) solver = "Lanczos"
    if (.not. mat%found) then
      call add("    peers' rules: add a &material group (young, poisson, density per type) to see them")
      call finish()
      return
    end if
    ! the peers' rules over the types present, each at its smallest radius in the file
    call packing_peer_steps(mat%types, snap%type, snap%radius, mat%restitution, mat%restitution_t, &
      mat%impact_velocity, steps, status)
    if (status%stat /= demstep_stat%ok) then
      call in_group(status, "material")
      return
    end if
    peer_dt = steps%dt
    rayleigh = steps%rayleigh
    hertz = steps%hertz_duration
    call add("    Rayleigh time "//fmt_real(rayleigh)//", Hertz contact duration "//fmt_real(hertz)// &
      " (smallest particle of each type, impact velocity "//fmt_real(mat%impact_velocity)//")")
    write(lines(nl + 1), '(4x, a22, 2a16)') "peer rule", "dt", "dt/exact limit"
    nl = nl + 1
    do c = 1, n_peer_rules
      write(lines(nl + 1), '(4x, a22, 2a16)') trim(peer_rule_names(c)), fmt_real(peer_dt(c)), &
        fmt_real(peer_dt(c)/exact)
      nl = nl + 1
    end do
    write(lines(nl + 1), '(4x, a22, a16, a)') "demstep exact limit", fmt_real(exact), &
      "  (damped, "//trim(solver)//")"
    nl = nl + 1
    call add("    (the limit of this packing; a &material report is for a single contact of each pair of types)")
    call finish()
  contains
    subroutine add(line)
      character(len=*), intent(in) :: line
      nl = nl + 1
      lines(nl) = line
    end subroutine add
    subroutine finish()
      lines = lines(:nl)
      status%stat = demstep_stat%ok
    end subroutine finish
    function material_note() result(text)
      character(len=:), allocatable :: text
      if (mat%first == mat%last) then
        text = trim(code_convention_names(mat%first))//"'s springs and dashpots per pair of types"
        if (sc%law == contact_law%hertz) text = text//" (Hertz)"
      else if (sc%law == contact_law%hertz) then
        text = "Hertz E*, G* from young and poisson"
      else
        text = "linear k_n, k_t of "//trim(code_convention_names(mat%first))//" at each type's radius"
      end if
    end function material_note
  end subroutine snapshot_summary

end module demstep_cli_scene
