!> Scene data: particles (translation and rotation), contact law and its
!> parameters, bonds, walls, an explicit contact list, a periodic cell and the
!> effects switched on; and the per-interaction values every user of a scene
!> takes from here (branch vector by minimum image, reduced mass, the law's
!> force and stiffnesses of one contact).
!>
!> Storage is 3D whatever `dim` is: the coordinates beyond `dim` are zero and stay
!> zero, so every kernel works on fixed-size vectors. In 2D the rotation is
!> about z (the third component of the angular velocity).
module demstep_scene_data
  use demstep_kinds, only: dp, i8
  use demstep_interaction, only: contact_law, reduced_mass, reduced_radius, normal_force, &
    normal_stiffness, tangential_stiffness
  implicit none
  private

  public :: effective_mass, branch_vector, contact_values, has_tangential, effect_index

  !> Effects, by index into `scene_type`%effects: `scene_effect%gravity`.
  type, public :: scene_effect_enum
    !> Particle-particle contacts (detected, or the explicit contact list).
    integer :: contacts = 1
    !> A uniform gravity field.
    integer :: gravity = 2
    !> Viscous dashpots on every contact, wall contact and bond.
    integer :: damping = 3
    !> Cundall's local damping.
    integer :: local_damping = 4
    !> Planar walls.
    integer :: walls = 5
    !> Rotational degrees of freedom (angular velocity, torques).
    integer :: rotation = 6
  end type scene_effect_enum
  !> The effects by name.
  type(scene_effect_enum), parameter, public :: scene_effect = scene_effect_enum()
  !> Number of effects.
  integer, parameter, public :: n_effects = 6
  !> Their names, as the namelist input spells them.
  character(len=*), parameter, public :: effect_names(n_effects) = [character(len=13) :: &
    "contacts", "gravity", "damping", "local_damping", "walls", "rotation"]

  !> A scene: particles, contact law, bonds, walls, cell and effects.
  type, public :: scene_type
    !> Dimension, 1 to 3.
    integer :: dim = 3
    !> Number of particles.
    integer :: n = 0
    !> Positions, half-step velocities and half-step angular velocities (3, n),
    !> zero beyond dim (2D: the angular velocity about z only).
    real(dp), allocatable :: x(:, :), v(:, :), w(:, :)
    !> Masses, radii and moments of inertia (> 0; default inertia 2/5 m r^2).
    real(dp), allocatable :: mass(:), radius(:), inertia(:)
    !> Fixed particles neither move nor count as degrees of freedom.
    logical, allocatable :: fixed(:)
    !> `contact_law%linear` (k_normal, k_tangential) or `contact_law%hertz`
    !> (e_star, g_star: Mindlin's k_t = 8 G* sqrt(R* d)).
    integer :: law = 1
    real(dp) :: k_normal = 0.0_dp, e_star = 0.0_dp, k_tangential = 0.0_dp, g_star = 0.0_dp
    !> Materials per particle type (when `ptype` is allocated): the type of each
    !> particle (1 to nt) and per type pair the law's parameters
    !> pair_law(:, a, b) = (k_n, k_t, E*, G*), symmetric in a, b; they replace
    !> k_normal, k_tangential, e_star, g_star for particle contacts.
    integer, allocatable :: ptype(:)
    real(dp), allocatable :: pair_law(:, :, :)
    !> Coulomb friction coefficient of the tangential springs (< 0: no sliding).
    real(dp) :: friction = -1.0_dp
    !> Bonds (2, nb): particle pairs; rest(3, nb) = initial x_j - x_i and its
    !> unit vector bond_normal(3, nb).
    integer, allocatable :: bonds(:, :)
    real(dp), allocatable :: bond_rest(:, :), bond_normal(:, :)
    !> Bond stiffness, normal and tangential.
    real(dp) :: k_bond = 0.0_dp, k_bond_tangential = 0.0_dp
    !> Walls: a point and the unit normal pointing into the domain (3, nw).
    real(dp), allocatable :: wall_point(:, :), wall_normal(:, :)
    !> An explicit contact list (2, nc) with its stiffness (k_n, k_t) per contact:
    !> it replaces the detection of contacts when `given_contacts`.
    logical :: given_contacts = .false.
    integer, allocatable :: contact_pairs(:, :)
    real(dp), allocatable :: contact_k(:, :)
    !> Periodic axes and the cell [cell_lo, cell_hi) (orthorhombic).
    logical :: periodic(3) = .false.
    real(dp) :: cell_lo(3) = 0.0_dp, cell_hi(3) = 0.0_dp
    !> Effects switched on (indexed by scene_effect%...).
    logical :: effects(n_effects) = [.true., .false., .false., .false., .false., .false.]
    !> Gravity vector; components beyond dim must be zero.
    real(dp) :: gravity(3) = [0.0_dp, 0.0_dp, 0.0_dp]
    !> Viscous damping ratio zeta and local damping coefficient alpha.
    real(dp) :: damping_ratio = 0.0_dp, local_damping = 0.0_dp
  end type scene_type

  !> What a run reports.
  type, public :: scene_summary_type
    integer(i8) :: steps = 0_i8
    !> Total energy (kinetic + elastic + gravitational) at the start and the end.
    real(dp) :: energy_initial = 0.0_dp, energy_final = 0.0_dp
    !> Largest |E(t) - E(0)| over the samples, relative to the largest energy scale.
    real(dp) :: energy_drift = 0.0_dp
    !> Largest overlap of any contact (particle or wall) seen.
    real(dp) :: max_overlap = 0.0_dp
    !> Largest number of contacts at one step.
    integer :: max_contacts = 0
    !> The run stopped because the state became non-finite or the energy grew
    !> by more than 1e6 of its scale.
    logical :: blew_up = .false.
    !> Energy samples: time and total energy.
    real(dp), allocatable :: sample_time(:), sample_energy(:)
  end type scene_summary_type

contains

  !> m* of a pair (i, j); j = 0 (the ground, a wall) and fixed partners count as
  !> infinitely heavy.
  pure real(dp) function effective_mass(scene, i, j) result(m)
    type(scene_type), intent(in) :: scene
    integer, intent(in) :: i, j
    real(dp) :: mi, mj
    mi = huge(1.0_dp)
    mj = huge(1.0_dp)
    if (.not. scene%fixed(i)) mi = scene%mass(i)
    if (j > 0) then
      if (.not. scene%fixed(j)) mj = scene%mass(j)
    end if
    if (mi >= huge(1.0_dp) .and. mj >= huge(1.0_dp)) mi = scene%mass(i)
    m = reduced_mass(mi, mj)
  end function effective_mass

  !> x_j - x_i, through the nearest periodic image along the periodic axes.
  pure function branch_vector(scene, i, j) result(d)
    type(scene_type), intent(in) :: scene
    integer, intent(in) :: i, j
    real(dp) :: d(3), box
    integer :: ax
    d = scene%x(:, j) - scene%x(:, i)
    do ax = 1, 3
      if (.not. scene%periodic(ax)) cycle
      box = scene%cell_hi(ax) - scene%cell_lo(ax)
      d(ax) = d(ax) - box*anint(d(ax)/box)
    end do
  end function branch_vector

  !> The law's values for a particle contact (i, j) at overlap d: normal force,
  !> normal and tangential tangent stiffness. `c` > 0 names a row of the explicit
  !> contact list (its k_n, k_t, linear); 0 a detected contact (the scene's law).
  pure subroutine contact_values(scene, c, i, j, d, f_n, k_n, k_t)
    type(scene_type), intent(in) :: scene
    integer, intent(in) :: c, i, j
    real(dp), intent(in) :: d
    real(dp), intent(out) :: f_n, k_n, k_t
    real(dp) :: rs, p(4)
    if (c > 0) then
      k_n = scene%contact_k(1, c)
      k_t = scene%contact_k(2, c)
      f_n = k_n*d
    else if (allocated(scene%ptype)) then
      p = scene%pair_law(:, scene%ptype(i), scene%ptype(j))
      rs = reduced_radius(scene%radius(i), scene%radius(j))
      f_n = normal_force(scene%law, p(1), p(3), d, rs)
      k_n = normal_stiffness(scene%law, p(1), p(3), d, rs)
      k_t = tangential_stiffness(scene%law, p(2), p(4), d, rs)
    else
      rs = reduced_radius(scene%radius(i), scene%radius(j))
      f_n = normal_force(scene%law, scene%k_normal, scene%e_star, d, rs)
      k_n = normal_stiffness(scene%law, scene%k_normal, scene%e_star, d, rs)
      k_t = tangential_stiffness(scene%law, scene%k_tangential, scene%g_star, d, rs)
    end if
  end subroutine contact_values

  !> Whether the scene's contacts have tangential springs.
  pure logical function has_tangential(scene)
    type(scene_type), intent(in) :: scene
    if (scene%given_contacts) then
      has_tangential = any(scene%contact_k(2, :) > 0.0_dp)
    else if (allocated(scene%ptype)) then
      has_tangential = any(scene%pair_law(merge(2, 4, scene%law == contact_law%linear), :, :) > 0.0_dp)
    else if (scene%law == contact_law%linear) then
      has_tangential = scene%k_tangential > 0.0_dp
    else
      has_tangential = scene%g_star > 0.0_dp
    end if
  end function has_tangential

  !> Index of an effect by name, 0 if unknown.
  pure integer function effect_index(name)
    character(len=*), intent(in) :: name
    do effect_index = 1, n_effects
      if (trim(effect_names(effect_index)) == name) return
    end do
    effect_index = 0
  end function effect_index

end module demstep_scene_data
