!> Group `&scene`: a particle assembly, its critical time steps by four methods,
!> and optionally a run that simulates only the effects it switches on.
module demstep_cli_scene
  use demstep_status, only: set_status, demstep_status_type, demstep_stat
  use demstep_namelist, only: nml_group_type
  use demstep_scene_data, only: scene_effect_from_name, n_effects, scene_effect_names, scene_type, &
    scene_summary_type
  use demstep_interaction, only: contact_law_from_name, contact_law_names, contact_law
  use demstep_assembly, only: critical_step_type, assembly_critical_steps, &
    assembly_step_for_n_per_period, demstep_eigen_solver => eigen_solver, hertz_linearization_from_name, &
    hertz_linearization_names, dashpot_names, default_max_eigen_dof, eigen_solver_from_name, &
    eigen_solver_names, safe_basis_name, safe_basis_note
  use demstep_kinds, only: dp, i8
  use demstep_progress, only: text_progress_type
  use demstep_stepper, only: scene_run
  use demstep_step_cost, only: measure_step_cost
  use demstep_lanczos, only: lanczos_tolerance_default
  use demstep_recommend, only: recommended_step, default_safety
  use demstep_snapshot, only: snapshot_type, snapshot_format_code => snapshot_format, &
    snapshot_format_names, snapshot_format_from_name
  use demstep_material, only: material_set_type, peer_steps_type, packing_peer_steps, &
    code_convention_names, peer_rule_names, n_peer_rules
  use demstep_liggghts_scene, only: liggghts_scene_type, script_timestep_ratio
  use demstep_scene_input, only: scene_input_type, scene_setup_type, scene_from_input, scene_input_part, &
    scene_input_takes_material
  use demstep_cli_material, only: read_material
  use demstep_cli, only: record_step, var_spec, var, given, begin_group, fmt_real, fmt_int, cli_context, &
    next_assignment, group_reading, check_real, new_array, array_length, new_int_array, int_array_length, &
    max_values, capacity_of, in_group
  use demstep_words, only: word_list, unknown_word, word_index, word_choice
  use demstep_body_assembly, only: body_critical_steps
  use demstep_bonds, only: bond_model_from_name, bond_model_names, max_bond_parameters
  use demstep_results, only: write_scene_result, write_snapshot_result, write_script_result
  use demstep_monitor, only: participation_type, scene_participation, top_shares, participation_top, &
    spring_kind_names
  use demstep_vtk, only: write_participation_vtk
  use demstep_cli_files, only: output_file_type, open_output, discard_output, rename_file, refuse_input
  use, intrinsic :: ieee_arithmetic, only: ieee_is_finite
  use, intrinsic :: iso_fortran_env, only: error_unit
  implicit none
  private

  public :: scene_specs, scene_doc, handle_scene, scene_takes_material, beside

  !> The `&scene` variable that names a file the group writes (not an input).
  character(len=*), parameter, public :: scene_output_file = "participation_file"

  character(len=*), parameter :: scene_doc = &
    "A particle assembly: its critical time step by the per-contact rule, a rigorous bound, " &
    //"the exact limit (LAPACK or Lanczos) and the damped limit; and a run with only the effects " &
    //"switched on."

  !> Most effects one group may list.
  integer, parameter :: max_effects = 16

  !> The deck's `&material` group, for a snapshot's particle types.
  type, extends(material_set_type) :: deck_material_type
    !> Line of the group in the deck.
    integer :: line = 0
    real(dp) :: tolerance = 0.0_dp
  end type deck_material_type

  !> What a `&scene` group asks of the app beside its scene: the run (its
  !> duration, the step, given or from n_per_period, and the step count) and
  !> the top mode's participation in the report and a VTK file.
  type :: scene_run_type
    real(dp) :: duration = 0.0_dp, dt = 0.0_dp, n_per_period = 0.0_dp
    logical :: dt_given = .false.
    integer(i8) :: steps = 0_i8
    logical :: participation = .false.
    character(len=:), allocatable :: participation_file
  end type scene_run_type

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
      var("snapshot_format", "a quoted word", word_choice(snapshot_format_names), &
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
      var("bodies_file", "a quoted file name", "rigid bodies (clumps, multispheres): per row a " &
        //"particle number and its body id (a positive integer); particles not listed move alone", &
        "!'clumps.txt'"), &
      var("body_density", "a real number", "clump members' density: body mass and inertia from their " &
        //"volumes (Yade's sum, overlaps counted twice); default the particles' masses and inertias", &
        "!2600.0", default="!0", needs="bodies_file"), &
      var("body_union", "a logical", "a LIGGGHTS dump's multisphere bodies (mol, mass columns): T, the " &
        //"centre of mass and inertia of the union of the members (overlap counted once, as LIGGGHTS' " &
        //"Monte Carlo template when it states no mass); F, the members' sum (a template stating " &
        //"mass and inertia_tensor as the sum; the conservative default)", "!T", default="F", &
        needs="snapshot_file"), &
      var("law", "a quoted word", "contact law: "//word_choice(contact_law_names, [character(len=8) :: &
        "k_normal", "e_star"]), &
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
      var("participation", "a logical", "report the particles and springs that carry the top mode " &
        //"(the result group has them always)", "!T", default="F"), &
      var("participation_file", "a quoted file name", "write the top mode's participation per " &
        //"particle and contact as a legacy VTK file (ParaView)", "!'top.vtk'"), &
      var("k_bond", "a real number", "bond normal stiffness (> 0 when there are bonds)", "100.0", &
        default="!0"), &
      var("k_bond_tangential", "a real number", "bond tangential stiffness (>= 0)", "0.0", &
        default="0"), &
      var("bond_model", "a quoted word", "bonds as a DEM code makes them, with normal, shear, " &
        //"bending and twisting springs: "//word_choice(bond_model_names, [character(len=15) :: &
        "parallel bond", "solid bond", "CohFrictPhys", "bpm/rotational"])//"; instead of k_bond", "!'musen'", &
        excludes="k_bond k_bond_tangential", needs="bond_parameters"), &
      var("bond_parameters", "a list of real numbers", "the bond model's inputs in its code's " &
        //"units: pfc kbar_n, kbar_s, lambda; musen E, G, diameter; yade young, poisson, alpha_kr, " &
        //"alpha_ktw; lammps K_r, K_s, K_t, K_b, gamma_n, gamma_s, gamma_r, gamma_t", &
        "!7.0e10, 2.7e10, 1.0e-3", capacity=max_bond_parameters, needs="bond_model"), &
      var("walls", "a list of real numbers", "per wall: dim coordinates of a point, dim of the " &
        //"normal pointing into the domain", "!0.0, -0.5,  0.0, 1.0", capacity=64), &
      var("effects", "a list of quoted words", word_choice(scene_effect_names, [character(len=32) :: &
        "default", "", "", "", "", "default with tangential springs"])//"; 'none' for bonds only", &
        "'contacts'", capacity=max_effects), &
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
      var("hertz_linearization", "a quoted word", "the overlap: "//word_choice(hertz_linearization_names, &
        [character(len=18) :: "", "at impact_velocity", "of the two"]), "!'current'", default="'current'"), &
      var("impact_velocity", "a real number", "impact speed for the 'impact' linearization (> 0)", &
        "!1.0", default="!0"), &
      var("duration", "a real number", "simulated time (>= 0; 0: no run)", "10.0", default="0"), &
      var("dt", "a real number", "time step of the run (> 0), or give n_per_period", "!0.01", &
        excludes="n_per_period"), &
      var("n_per_period", "a real number", "steps per smallest period 2 pi/omega_max (> pi " &
        //"to be stable)", "20.0"), &
      var("eigen_solver", "a quoted word", "exact omega_max by "//word_choice(eigen_solver_names, &
        [character(len=14) :: "", "LAPACK", "ARPACK", "the bound only"]), "!'auto'", default="'auto'"), &
      var("eigen_tolerance", "a real number", "Lanczos: relative residual on omega_max^2, " &
        //"in [2.2e-16, 0.1]", "!"//fmt_real(lanczos_tolerance_default), &
        default=fmt_real(lanczos_tolerance_default)), &
      var("max_eigen_dof", "an integer", "'auto' takes Lanczos above this, the largest problem " &
        //"for the dense eigensolver", "!"//fmt_int(int(default_max_eigen_dof, i8)), &
        default=fmt_int(int(default_max_eigen_dof, i8))) ]
  end function scene_specs

  !> Read one `&scene` group into a typed input, build its scene (the
  !> library), analyse it, run it when asked, and report.
  subroutine handle_scene(ctx, group, file, status)
    type(cli_context), intent(in) :: ctx
    type(nml_group_type), intent(in) :: group
    !> The input deck's name: relative table file names are relative to its directory.
    character(len=*), intent(in) :: file
    type(demstep_status_type), intent(out) :: status
    character(len=*), parameter :: g = "scene"
    type(scene_input_type) :: input
    type(scene_run_type) :: run
    type(deck_material_type) :: deck_mat
    type(scene_setup_type) :: setup
    type(participation_type) :: modal
    type(scene_type) :: sc
    type(critical_step_type) :: crit
    type(scene_summary_type) :: summary
    type(text_progress_type) :: progress
    character(len=200), allocatable :: snapshot_lines(:)
    real(dp) :: peer_dt(n_peer_rules), dt_recommended
    integer :: part, governs

    call read_scene_input(group, file, input, run, status)
    if (status%stat /= demstep_stat%ok) return
    if (allocated(input%snapshot_file)) then
      call find_deck_material(ctx%groups, deck_mat, status)
      if (status%stat /= demstep_stat%ok) return
    end if
    call scene_from_input(input, deck_mat%material_set_type, sc, setup, status, part)
    if (status%stat /= demstep_stat%ok) then
      if (part == scene_input_part%material) then
        call in_group(status, "material")
      else
        call in_group(status, g)
      end if
      return
    end if

    progress = text_progress_type(unit=error_unit, label="demstep: &"//g)
    if (allocated(setup%bodies)) then
      call body_critical_steps(sc, setup%bodies, crit, status, solver=input%eigen_solver, &
        tolerance=input%eigen_tolerance, max_eigen_dof=input%max_eigen_dof)
    else if (ctx%quiet) then
      call scene_participation(sc, crit, modal, status, hertz_mode=setup%hertz_mode, &
        impact_velocity=setup%impact_velocity, max_eigen_dof=input%max_eigen_dof, prestress=input%prestress, &
        solver=input%eigen_solver, tolerance=input%eigen_tolerance)
    else
      call scene_participation(sc, crit, modal, status, hertz_mode=setup%hertz_mode, &
        impact_velocity=setup%impact_velocity, max_eigen_dof=input%max_eigen_dof, prestress=input%prestress, &
        solver=input%eigen_solver, tolerance=input%eigen_tolerance, progress=progress)
    end if
    if (status%stat /= demstep_stat%ok) then
      if (status%where == "effects" .and. allocated(input%bonds_file)) then
        ! the empty table is what left the scene without springs
        call set_status(status, demstep_stat%invalid_input, input%bonds_file//": holds no bonds, and " &
          //"neither 'contacts' nor 'walls' is in effects: the scene has no stiffness", where="bonds_file")
      end if
      ! the library's Lanczos tolerance is this group's eigen_tolerance
      call in_group(status, g, reshape([character(len=15) :: "tolerance", "eigen_tolerance"], [2, 1]))
      return
    end if
    if (run%duration > 0.0_dp) then
      if (.not. run%dt_given) then
        call assembly_step_for_n_per_period(crit, run%n_per_period, run%dt, status)
        if (status%stat /= demstep_stat%ok) then
          call in_group(status, g)
          return
        end if
      end if
      call plan_run(ctx, g, sc%n, crit%n_springs, run%duration, run%dt, run%steps, status)
      if (status%stat /= demstep_stat%ok) return
      if (ctx%quiet) then
        call scene_run(sc, run%dt, run%steps, summary, status, bodies=setup%bodies)
      else
        call scene_run(sc, run%dt, run%steps, summary, status, progress=progress, bodies=setup%bodies)
      end if
      ! a blow-up is a result to report, not an input error
      if (status%stat == demstep_stat%blow_up) status%stat = demstep_stat%ok
      if (status%stat /= demstep_stat%ok) then
        call in_group(status, g)
        return
      end if
    else
      run%dt = 0.0_dp
    end if
    ! the damped limit is that of the exact omega_max, or of the bound when the
    ! dense solver was not run: the recommendation is safe either way
    call recommended_step(crit%dt_critical_damped, dt_recommended, governs, status)
    if (status%stat /= demstep_stat%ok) then
      call in_group(status, g)
      return
    end if
    if (allocated(input%snapshot_file)) then
      call snapshot_summary(input%snapshot_file, setup%snapshot, deck_mat, setup%from_material, sc, crit, &
        snapshot_lines, peer_dt, status)
      if (status%stat /= demstep_stat%ok) return
      if (allocated(input%liggghts_script)) snapshot_lines = [snapshot_lines, script_summary(setup%script, &
        crit%dt_critical_damped, crit%eigen_computed, dt_recommended)]
      call report(ctx%report, group, sc, crit, run%duration > 0.0_dp, run%dt, run%steps, summary, &
        dt_recommended, snapshot_lines)
    else
      call report(ctx%report, group, sc, crit, run%duration > 0.0_dp, run%dt, run%steps, summary, &
        dt_recommended)
    end if
    call participation_output(ctx, group, sc, modal, run, status)
    if (status%stat /= demstep_stat%ok) return
    call write_scene_result(ctx%results, sc, crit, run%dt, summary, dt_recommended, modal)
    call record_step(ctx, "assembly step", dt_recommended, .true., group)
    if (allocated(input%snapshot_file)) call write_snapshot_result(ctx%results, setup%snapshot, &
      deck_mat%found, crit, peer_dt)
    if (allocated(input%liggghts_script)) call write_script_result(ctx%results, setup%script, &
      crit%dt_critical_damped)
  end subroutine handle_scene

  !> Read a `&scene` group into the library's typed input (words to codes,
  !> files beside the deck) and the run's settings.
  subroutine read_scene_input(group, file, input, run, status)
    type(nml_group_type), intent(in) :: group
    character(len=*), intent(in) :: file
    type(scene_input_type), intent(out) :: input
    type(scene_run_type), intent(out) :: run
    type(demstep_status_type), intent(out) :: status
    type(group_reading) :: reading
    integer :: dim, max_eigen_dof, wall_type, snapshot_frame, i, k
    real(dp), allocatable :: position(:), velocity(:), mass(:), radius(:), walls(:), gravity(:), &
      type_k_normal(:), type_k_tangential(:), young(:), poisson(:), bond_parameters(:)
    integer, allocatable :: fixed(:), bonds(:), types(:)
    character(len=512) :: particles_file, bonds_file, contacts_file, snapshot_file, bodies_file, liggghts_script
    character(len=32) :: snapshot_format, law, hertz_linearization, eigen_solver, bond_model
    character(len=32) :: effects(max_effects)
    real(dp) :: k_normal, e_star, k_bond, k_bond_tangential, damping_ratio, restitution, &
      local_damping, impact_velocity, duration, dt, n_per_period, k_tangential, kt_ratio, g_star, &
      friction, cell_lo(3), cell_hi(3), eigen_tolerance, damping_ratio_tangential, &
      damping_ratio_rolling, drag, rolling_ratio, twisting_ratio, rolling_friction, body_density
    logical :: periodic(3), prestress, tangential_damping, participation, body_union
    character(len=512) :: participation_file
    namelist /scene/ dim, position, velocity, mass, radius, fixed, bonds, particles_file, &
      bonds_file, law, k_normal, e_star, k_bond, k_bond_tangential, walls, effects, gravity, &
      damping_ratio, restitution, local_damping, hertz_linearization, impact_velocity, duration, &
      dt, n_per_period, max_eigen_dof, contacts_file, periodic, cell_lo, cell_hi, k_tangential, &
      kt_ratio, g_star, friction, prestress, types, type_k_normal, type_k_tangential, young, poisson, &
      eigen_solver, eigen_tolerance, snapshot_file, snapshot_format, snapshot_frame, &
      damping_ratio_tangential, damping_ratio_rolling, drag, rolling_ratio, twisting_ratio, rolling_friction, &
      wall_type, tangential_damping, bond_model, bond_parameters, bodies_file, body_density, &
      body_union, participation, participation_file, liggghts_script
    type(var_spec), allocatable :: specs(:)
    character(len=*), parameter :: g = "scene"

    specs = scene_specs()
    bond_parameters = new_array(capacity_of(specs, "bond_parameters"))
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

    ! arrays: as many values as given, without gaps
    call take_array("position", position, input%position)
    call take_array("velocity", velocity, input%velocity)
    call take_array("mass", mass, input%mass)
    call take_array("radius", radius, input%radius)
    call take_array("walls", walls, input%walls)
    call take_array("gravity", gravity, input%gravity)
    call take_array("type_k_normal", type_k_normal, input%type_k_normal)
    call take_array("type_k_tangential", type_k_tangential, input%type_k_tangential)
    call take_array("young", young, input%young)
    call take_array("poisson", poisson, input%poisson)
    call take_array("bond_parameters", bond_parameters, input%bond_parameters)
    call take_int_array("fixed", fixed, input%fixed)
    call take_int_array("bonds", bonds, input%bonds)
    if (given(group, "types")) call take_int_array("types", types, input%types)
    if (status%stat /= demstep_stat%ok) return

    ! files, beside the deck
    if (given(group, "particles_file")) input%particles_file = beside(file, trim(particles_file))
    if (given(group, "snapshot_file")) input%snapshot_file = beside(file, trim(snapshot_file))
    if (given(group, "contacts_file")) input%contacts_file = beside(file, trim(contacts_file))
    if (given(group, "bonds_file")) input%bonds_file = beside(file, trim(bonds_file))
    if (given(group, "bodies_file")) input%bodies_file = beside(file, trim(bodies_file))
    if (given(group, "liggghts_script")) input%liggghts_script = beside(file, trim(liggghts_script))

    ! words
    input%snapshot_format = snapshot_format_from_name(snapshot_format)
    if (input%snapshot_format < snapshot_format_code%auto) then
      call unknown_word(status, "snapshot_format", snapshot_format, snapshot_format_names)
    else if (given(group, "law")) then
      input%law = contact_law_from_name(law)
      if (input%law == 0) call unknown_word(status, "law", law, contact_law_names)
    end if
    if (status%stat == demstep_stat%ok .and. given(group, "hertz_linearization")) then
      input%hertz_linearization = hertz_linearization_from_name(hertz_linearization)
      if (input%hertz_linearization == 0) call unknown_word(status, "hertz_linearization", &
        hertz_linearization, hertz_linearization_names)
    end if
    if (status%stat == demstep_stat%ok .and. given(group, "bond_model")) then
      input%bond_model = bond_model_from_name(bond_model)
      if (input%bond_model == 0) call unknown_word(status, "bond_model", bond_model, bond_model_names)
    end if
    if (status%stat == demstep_stat%ok) then
      input%eigen_solver = eigen_solver_from_name(eigen_solver)
      if (input%eigen_solver == 0) call unknown_word(status, "eigen_solver", eigen_solver, eigen_solver_names)
    end if
    if (status%stat /= demstep_stat%ok) then
      call in_group(status, g)
      return
    end if
    if (given(group, "effects")) then
      ! 'none' is no effect: the list may end up empty (bonds only)
      allocate(input%effects(max_effects))
      k = 0
      do i = 1, max_effects
        if (len_trim(effects(i)) == 0 .or. word_index(["none"], effects(i)) == 1) cycle
        k = k + 1
        input%effects(k) = scene_effect_from_name(effects(i))
        if (input%effects(k) == 0) then
          call set_status(status, demstep_stat%invalid_input, "unknown effect '"//trim(effects(i))//"' (" &
            //word_list(scene_effect_names(:n_effects))//", none)", where="effects")
          call in_group(status, g)
          return
        end if
      end do
      input%effects = input%effects(:k)
    end if

    ! scalars: the optional ones only when given
    input%dim = dim
    input%snapshot_frame = snapshot_frame
    if (given(group, "periodic")) input%periodic = periodic
    input%cell_lo = cell_lo
    if (given(group, "cell_hi")) input%cell_hi = cell_hi
    if (given(group, "k_normal")) input%k_normal = k_normal
    if (given(group, "k_tangential")) input%k_tangential = k_tangential
    if (given(group, "kt_ratio")) input%kt_ratio = kt_ratio
    if (given(group, "e_star")) input%e_star = e_star
    if (given(group, "g_star")) input%g_star = g_star
    if (given(group, "friction")) input%friction = friction
    if (given(group, "rolling_friction")) input%rolling_friction = rolling_friction
    if (given(group, "damping_ratio")) input%damping_ratio = damping_ratio
    if (given(group, "restitution")) input%restitution = restitution
    if (given(group, "damping_ratio_tangential")) input%damping_ratio_tangential = damping_ratio_tangential
    if (given(group, "damping_ratio_rolling")) input%damping_ratio_rolling = damping_ratio_rolling
    if (given(group, "drag")) input%drag = drag
    if (given(group, "impact_velocity")) input%impact_velocity = impact_velocity
    if (given(group, "body_density")) input%body_density = body_density
    input%k_bond = k_bond
    input%k_bond_tangential = k_bond_tangential
    input%rolling_ratio = rolling_ratio
    input%twisting_ratio = twisting_ratio
    input%local_damping = local_damping
    input%wall_type = wall_type
    input%tangential_damping = tangential_damping
    input%prestress = prestress
    input%body_union = body_union
    input%eigen_tolerance = eigen_tolerance
    input%max_eigen_dof = max_eigen_dof

    ! the run
    call check_real(g, "duration", duration, status, inclusive=.true.)
    if (given(group, "dt")) call check_real(g, "dt", dt, status)
    if (status%stat /= demstep_stat%ok) return
    if (duration > 0.0_dp .and. .not. (given(group, "dt") .or. given(group, "n_per_period"))) then
      call set_status(status, demstep_stat%invalid_input, "&"//g//": dt: a run (duration > 0) needs dt " &
        //"or n_per_period")
      return
    end if
    run%duration = duration
    run%dt = dt
    run%dt_given = given(group, "dt")
    run%n_per_period = n_per_period
    run%participation = participation
    if (given(group, "participation_file")) run%participation_file = beside(file, trim(participation_file))

  contains

    subroutine take_array(name, x, into)
      character(len=*), intent(in) :: name
      real(dp), intent(in) :: x(:)
      real(dp), allocatable, intent(out) :: into(:)
      integer :: length
      call array_length(g, name, x, length, status)
      if (status%stat == demstep_stat%ok .and. length > 0) into = x(:length)
    end subroutine take_array

    subroutine take_int_array(name, x, into)
      character(len=*), intent(in) :: name
      integer, intent(in) :: x(:)
      integer, allocatable, intent(out) :: into(:)
      integer :: length
      call int_array_length(g, name, x, length, status)
      if (status%stat == demstep_stat%ok) into = x(:length)
    end subroutine take_int_array

  end subroutine read_scene_input

  !> The top mode's participation: the report's lines (with `participation`
  !> or a file) and the VTK file (`participation_file`, never over an input;
  !> written to a temporary beside it and renamed).
  subroutine participation_output(ctx, group, sc, part, run, status)
    type(cli_context), intent(in) :: ctx
    type(nml_group_type), intent(in) :: group
    type(scene_type), intent(in) :: sc
    type(participation_type), intent(in) :: part
    type(scene_run_type), intent(in) :: run
    type(demstep_status_type), intent(out) :: status
    type(output_file_type) :: out
    character(len=:), allocatable :: kind
    integer, allocatable :: top(:)
    integer :: k, ptype
    status%stat = demstep_stat%ok
    if (.not. (run%participation .or. allocated(run%participation_file))) return
    if (.not. part%computed) then
      if (allocated(run%participation_file)) then
        call set_status(status, demstep_stat%invalid_input, "&scene: participation_file: needs the top " &
          //"mode, which no eigensolver returned (eigen_solver = 'none', or Lanczos did not converge)")
      else
        write(ctx%report, '(2x, a)') "participation: no top mode (no eigensolver returned one)"
      end if
      return
    end if
    top = top_shares(part%particle_share, participation_top)
    write(ctx%report, '(2x, a)') "the top mode: the particles that carry most of it"
    write(ctx%report, '(4x, a)') "particle     share         radius          mass  type"
    do k = 1, size(top)
      ptype = 0
      if (allocated(sc%ptype)) ptype = sc%ptype(top(k))
      write(ctx%report, '(4x, i8, f10.4, 2es15.6, i6)') top(k), part%particle_share(top(k)), &
        sc%radius(top(k)), sc%mass(top(k)), ptype
    end do
    top = top_shares(part%spring_share, participation_top)
    write(ctx%report, '(2x, a)') "the top mode: the springs that carry most of its energy (particle 0: a wall)"
    write(ctx%report, '(4x, a)') "   i        j  kind         share            k_n            k_t"
    do k = 1, size(top)
      kind = trim(spring_kind_names(part%spring_kind(top(k))))
      write(ctx%report, '(4x, 2i8, 2x, a7, f10.4, 2es15.6)') part%spring_a(top(k)), part%spring_b(top(k)), &
        kind, part%spring_share(top(k)), part%spring_k(:, top(k))
    end do
    if (.not. allocated(run%participation_file)) return
    associate(target => run%participation_file)
      if (allocated(ctx%inputs)) then
        call refuse_input(ctx%inputs, target, status)
        if (status%stat /= demstep_stat%ok) then
          status%message = "&scene: participation_file: '"//target//"' "//status%message
          return
        end if
      end if
      call open_output(target, out, status)
      if (status%stat == demstep_stat%ok) then
        close(out%unit)
        out%unit = -1
        call write_participation_vtk(out%temp, sc, part, status)
        if (status%stat == demstep_stat%ok) call rename_file(out%temp, out%target, status)
        if (status%stat /= demstep_stat%ok) call discard_output(out)
      end if
      if (status%stat /= demstep_stat%ok) then
        status%message = "&scene: participation_file: '"//target//"': "//status%message
        status%stat = demstep_stat%io_error
        return
      end if
      write(ctx%report, '(2x, a)') "wrote the top mode's participation to "//target
    end associate
  end subroutine participation_output

  !> Whether a `&scene` among `groups` (of deck `file`) takes its particle
  !> types' materials from the deck's `&material` group (the library's rule,
  !> `scene_input_takes_material`). A group that cannot be read takes none:
  !> its handler reports the fault.
  logical function scene_takes_material(groups, file) result(takes)
    type(nml_group_type), intent(in) :: groups(:)
    character(len=*), intent(in) :: file
    type(scene_input_type) :: input
    type(scene_run_type) :: run
    type(demstep_status_type) :: status
    integer :: k
    takes = .false.
    do k = 1, size(groups)
      if (groups(k)%name /= "scene") cycle
      call read_scene_input(groups(k), file, input, run, status)
      if (status%stat /= demstep_stat%ok) cycle
      if (scene_input_takes_material(input)) takes = .true.
    end do
  end function scene_takes_material

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
      write(u, '(4x, a, t40, a)') "exact, Lanczos", fmt_real(crit%dt_critical_eigen)// &
        "  (omega_max = "//fmt_real(crit%omega_max)//", "//fmt_int(crit%eigen_products)//" products)"
    else if (crit%solver == demstep_eigen_solver%lanczos) then
      write(u, '(4x, a, t40, a)') "Lanczos, not converged", "omega_max in ["// &
        fmt_real(crit%omega_max)//", "//fmt_real(crit%omega_upper)//"] after "// &
        fmt_int(crit%eigen_products)//" products"
    else
      write(u, '(4x, a, t40, a)') "exact", "not computed (eigen_solver = 'none')"
    end if
    if (crit%eigen_computed) write(u, '(4x, a, t40, a)') "safe ("//safe_basis_name(crit%safe_basis)//")", &
      fmt_real(crit%dt_critical_safe)//"  ("//safe_basis_note(crit)//"; residual "// &
      fmt_real(crit%eigen_residual)//")"
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
    ratio = script_timestep_ratio(info, dt_limit)
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
    if (snap%format == snapshot_format_code%lammps_dump) frame = ", frame "//fmt_int(int(snap%frame, i8))//" of " &
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
