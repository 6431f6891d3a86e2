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
  use demstep_status, only: demstep_status_type, demstep_stat, set_status
  use demstep_interaction, only: contact_law, reduced_mass, reduced_radius, normal_force, &
    normal_stiffness, tangential_stiffness, dashpot_coefficient, hooke_size_factor
  use demstep_words, only: word_index, word_of
  implicit none
  private

  public :: effective_mass, effective_inertia, branch_vector, contact_values, wall_values, contact_dashpots, &
    has_tangential, has_rolling, check_scene_damping, wrap_positions, law_parameters

  !> Effects, by index into `scene_type`%effects: `scene_effect%gravity`.
  type, public :: scene_effect_enum
    !> Particle-particle contacts (detected, or the explicit contact list).
    integer :: contacts = 1
    !> A uniform gravity field.
    integer :: gravity = 2
    !> Viscous dashpots on every contact, wall contact and bond (normal,
    !> tangential, rolling and twisting), and the drag to ground.
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
  public :: scene_effect_from_name, scene_effect_name
  !> Largest viscous damping ratio: the damped limit, about dt/(2 zeta), stays a
  !> normal number for every dt above 1e-200.
  real(dp), parameter, public :: max_damping_ratio = 1.0e100_dp

  !> Number of effects.
  integer, parameter, public :: n_effects = 6
  !> Their names, as the namelist input spells them.
  character(len=*), parameter, public :: scene_effect_names(n_effects) = [character(len=13) :: &
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
    !> With materials per type (`scene_set_materials`): per type pair the
    !> normal damping ratio and the tangential dashpot over the normal one,
    !> pair_damping(:, a, b) = (zeta_n, c_t/c_n); for a particle of type t on a
    !> wall the law's parameters wall_law(:, t) (as pair_law) and
    !> wall_damping(:, t). They replace the scene's values where allocated.
    real(dp), allocatable :: pair_damping(:, :, :), wall_law(:, :), wall_damping(:, :)
    !> LIGGGHTS' Hooke stiffness per contact (`scene_set_materials` with
    !> `per_contact`): k_n and k_t of pair_law and wall_law are then those of
    !> R* = m* = 1, and each detected contact's are k R*^(2/5) m*^(1/5) with its
    !> own R* and m* (`hooke_size_factor`), as LIGGGHTS computes them per contact.
    logical :: hooke_per_contact = .false.
    !> Coulomb friction coefficient of the tangential springs (< 0: no sliding).
    real(dp) :: friction = -1.0_dp
    !> Bonds (2, nb): particle pairs; rest(3, nb) = initial x_j - x_i and its
    !> unit vector bond_normal(3, nb).
    integer, allocatable :: bonds(:, :)
    real(dp), allocatable :: bond_rest(:, :), bond_normal(:, :)
    !> Bond stiffness, normal and tangential.
    real(dp) :: k_bond = 0.0_dp, k_bond_tangential = 0.0_dp
    !> The bonds' model (`bond_model` of demstep_bonds: each code's bond with
    !> normal, shear, bending and twisting springs; `scene_set_bond_model`) and
    !> its parameters; 0: central springs k_bond, k_bond_tangential.
    integer :: bond_model = 0
    real(dp) :: bond_parameters(8) = 0.0_dp
    !> Walls: a point and the unit normal pointing into the domain (3, nw).
    real(dp), allocatable :: wall_point(:, :), wall_normal(:, :)
    !> An explicit contact list (2, nc) with per contact its stiffness
    !> contact_k(1:4, c) = (k_n, k_t, k_r, k_w) and, when `given_dashpots`, its
    !> dashpots contact_k(5:8, c) = (c_n, c_t, c_r, c_w) (else they follow from
    !> the damping ratios): it replaces the detection of contacts when
    !> `given_contacts`.
    logical :: given_contacts = .false., given_dashpots = .false.
    integer, allocatable :: contact_pairs(:, :)
    real(dp), allocatable :: contact_k(:, :)
    !> Periodic axes and the cell [cell_lo, cell_hi) (orthorhombic).
    logical :: periodic(3) = .false.
    real(dp) :: cell_lo(3) = 0.0_dp, cell_hi(3) = 0.0_dp
    !> Effects switched on (indexed by scene_effect%...).
    logical :: effects(n_effects) = [.true., .false., .false., .false., .false., .false.]
    !> Gravity vector; components beyond dim must be zero.
    real(dp) :: gravity(3) = [0.0_dp, 0.0_dp, 0.0_dp]
    !> Viscous damping ratio zeta (normal dashpots c_n = 2 zeta sqrt(m* k_n)) and
    !> local damping coefficient alpha.
    real(dp) :: damping_ratio = 0.0_dp, local_damping = 0.0_dp
    !> Tangential damping ratio: c_t = 2 zeta_t sqrt(m* k_t); < 0 (default): the
    !> normal ratio, as LIGGGHTS' default `tangential_damping on` (Hertz).
    real(dp) :: damping_ratio_tangential = -1.0_dp
    !> Rolling and twisting springs of detected contacts and wall contacts,
    !> k_r = rolling_ratio k_t R*^2 and k_w = twisting_ratio k_t R*^2 (0: none;
    !> LIGGGHTS' `epsd2`: rolling_ratio 1, rolling_model_epsd2.h:193),
    !> with the dashpots c = 2 zeta_r sqrt(I* k) (I* the pair's reduced moment of
    !> inertia; a wall: the particle's) and the rolling moment capped at
    !> rolling_friction R* F_n in the stepper (< 0: no cap).
    real(dp) :: rolling_ratio = 0.0_dp, twisting_ratio = 0.0_dp, damping_ratio_rolling = 0.0_dp
    real(dp) :: rolling_friction = -1.0_dp
    !> Viscous drag of every free particle to the ground, F = -drag v (force per
    !> velocity; LIGGGHTS/LAMMPS `fix viscous` gamma), with the damping effect.
    real(dp) :: drag = 0.0_dp
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

  !> Wrap the positions along the periodic axes into [cell_lo, cell_hi):
  !> cell_lo + modulo(x - cell_lo, box).
  pure subroutine wrap_positions(scene)
    type(scene_type), intent(inout) :: scene
    integer :: ax, i
    real(dp) :: box, lo, t
    do ax = 1, 3
      if (.not. scene%periodic(ax)) cycle
      lo = scene%cell_lo(ax)
      box = scene%cell_hi(ax) - lo
      do i = 1, size(scene%x, 2)
        t = scene%x(ax, i) - lo
        ! (modulo is t itself for t in [0, box): the remainder is exact)
        if (.not. (t >= 0.0_dp .and. t < box)) t = modulo(t, box)
        scene%x(ax, i) = lo + t
      end do
    end do
  end subroutine wrap_positions

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
      ! (well inside half a box the image is the pair itself: anint gives 0
      ! and d is kept as it is; 0 and -0 still go through the formula)
      if (abs(d(ax)) < 0.25_dp*box .and. d(ax) /= 0.0_dp) cycle
      d(ax) = d(ax) - box*anint(d(ax)/box)
    end do
  end function branch_vector

  !> m* I-analogue of a pair: the reduced moment of inertia (j = 0 or fixed:
  !> infinitely heavy).
  pure real(dp) function effective_inertia(scene, i, j) result(m)
    type(scene_type), intent(in) :: scene
    integer, intent(in) :: i, j
    real(dp) :: mi, mj
    mi = huge(1.0_dp)
    mj = huge(1.0_dp)
    if (.not. scene%fixed(i)) mi = scene%inertia(i)
    if (j > 0) then
      if (.not. scene%fixed(j)) mj = scene%inertia(j)
    end if
    if (mi >= huge(1.0_dp) .and. mj >= huge(1.0_dp)) mi = scene%inertia(i)
    m = reduced_mass(mi, mj)
  end function effective_inertia

  !> The law's values for a particle contact (i, j) at overlap d: normal force
  !> and the stiffnesses k = (k_n, k_t, k_r, k_w) (normal and tangential tangent
  !> stiffness, rolling and twisting). `c` > 0 names a row of the explicit
  !> contact list (its values, linear); 0 a detected contact (the scene's law).
  pure subroutine contact_values(scene, c, i, j, d, f_n, k)
    type(scene_type), intent(in) :: scene
    integer, intent(in) :: c, i, j
    real(dp), intent(in) :: d
    real(dp), intent(out) :: f_n, k(4)
    real(dp) :: rs, p(4)
    if (c > 0) then
      k = scene%contact_k(1:4, c)
      f_n = k(1)*d
      return
    end if
    rs = reduced_radius(scene%radius(i), scene%radius(j))
    p = law_parameters(scene, i, j)
    call law_values(scene, p, d, rs, f_n, k)
  end subroutine contact_values

  !> The law's parameters (k_n, k_t, E*, G*) of a detected contact between i
  !> and j (j = 0: a wall): the pair's (the wall's) per-type values where set,
  !> else the scene's; LIGGGHTS' Hooke springs scaled to the contact's own R*
  !> and m* (`hooke_per_contact`).
  pure function law_parameters(scene, i, j) result(p)
    type(scene_type), intent(in) :: scene
    integer, intent(in) :: i, j
    real(dp) :: p(4)
    p = [scene%k_normal, scene%k_tangential, scene%e_star, scene%g_star]
    if (j > 0) then
      if (allocated(scene%ptype)) p = scene%pair_law(:, scene%ptype(i), scene%ptype(j))
      if (scene%hooke_per_contact) p(1:2) = p(1:2)*hooke_size_factor(reduced_radius(scene%radius(i), &
        scene%radius(j)), effective_mass(scene, i, j))
    else
      if (allocated(scene%wall_law)) p = scene%wall_law(:, scene%ptype(i))
      if (scene%hooke_per_contact) p(1:2) = p(1:2)*hooke_size_factor(scene%radius(i), effective_mass(scene, i, 0))
    end if
  end function law_parameters

  !> The law's values for particle i on a wall at overlap d (R* = r_i, the
  !> scene's law): normal force and k = (k_n, k_t, k_r, k_w).
  pure subroutine wall_values(scene, i, d, f_n, k)
    type(scene_type), intent(in) :: scene
    integer, intent(in) :: i
    real(dp), intent(in) :: d
    real(dp), intent(out) :: f_n, k(4)
    real(dp) :: r, p(4)
    r = scene%radius(i)
    p = law_parameters(scene, i, 0)
    call law_values(scene, p, d, r, f_n, k)
  end subroutine wall_values

  !> The scene's law with parameters p = (k_n, k_t, E*, G*) at overlap d and
  !> reduced radius rs: normal force and k = (k_n, k_t, k_r, k_w), the rolling
  !> and twisting springs from the scene's ratios of k_t rs^2.
  pure subroutine law_values(scene, p, d, rs, f_n, k)
    type(scene_type), intent(in) :: scene
    real(dp), intent(in) :: p(4), d, rs
    real(dp), intent(out) :: f_n, k(4)
    f_n = normal_force(scene%law, p(1), p(3), d, rs)
    k(1) = normal_stiffness(scene%law, p(1), p(3), d, rs)
    k(2) = tangential_stiffness(scene%law, p(2), p(4), d, rs)
    k(3) = scene%rolling_ratio*k(2)*rs**2
    k(4) = scene%twisting_ratio*k(2)*rs**2
  end subroutine law_values

  !> The dashpots (c_n, c_t, c_r, c_w) of an interaction between i and j (0: a
  !> wall) of stiffness k (0 without the damping effect): the explicit list's
  !> row `c` > 0 when it gives them, else the materials' per-pair (per-wall)
  !> values where set, else the scene's damping ratios.
  pure function contact_dashpots(scene, c, i, j, k) result(cd)
    type(scene_type), intent(in) :: scene
    integer, intent(in) :: c, i, j
    real(dp), intent(in) :: k(4)
    real(dp) :: cd(4)
    real(dp) :: m, mi, zt, p(2)
    cd = 0.0_dp
    if (.not. scene%effects(scene_effect%damping)) return
    if (c > 0 .and. scene%given_dashpots) then
      cd = scene%contact_k(5:8, c)
      return
    end if
    m = effective_mass(scene, i, j)
    mi = effective_inertia(scene, i, j)
    zt = scene%damping_ratio_tangential
    if (zt < 0.0_dp) zt = scene%damping_ratio
    if (c == 0 .and. (allocated(scene%pair_damping) .and. j > 0 .or. allocated(scene%wall_damping) &
        .and. j == 0)) then
      ! the code's own dashpots: zeta_n on the normal spring, c_t a multiple of c_n
      if (j > 0) then
        p = scene%pair_damping(:, scene%ptype(i), scene%ptype(j))
      else
        p = scene%wall_damping(:, scene%ptype(i))
      end if
      cd(1) = dashpot_coefficient(p(1), m, k(1))
      cd(2) = p(2)*cd(1)
    else
      cd(1) = dashpot_coefficient(scene%damping_ratio, m, k(1))
      cd(2) = dashpot_coefficient(zt, m, k(2))
    end if
    cd(3) = dashpot_coefficient(scene%damping_ratio_rolling, mi, k(3))
    cd(4) = dashpot_coefficient(scene%damping_ratio_rolling, mi, k(4))
  end function contact_dashpots

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

  !> Whether the scene's contacts have rolling or twisting springs.
  pure logical function has_rolling(scene)
    type(scene_type), intent(in) :: scene
    if (scene%given_contacts) then
      has_rolling = any(scene%contact_k(3:4, :) > 0.0_dp)
    else
      has_rolling = scene%rolling_ratio > 0.0_dp .or. scene%twisting_ratio > 0.0_dp
    end if
  end function has_rolling

  !> The scene's damping values, as every user of a scene checks them: the
  !> ratios in [0, max_damping_ratio] (the tangential one < 0: as the normal
  !> one) and the drag >= 0, with the damping effect on. Status invalid_input
  !> naming `damping_ratio`, `damping_ratio_tangential`, `damping_ratio_rolling`
  !> or `drag`.
  pure subroutine check_scene_damping(scene, status)
    type(scene_type), intent(in) :: scene
    type(demstep_status_type), intent(out) :: status
    real(dp) :: zt
    status%stat = demstep_stat%ok
    if (.not. scene%effects(scene_effect%damping)) return
    zt = scene%damping_ratio_tangential
    if (zt < 0.0_dp) zt = 0.0_dp
    if (.not. (scene%damping_ratio >= 0.0_dp .and. scene%damping_ratio <= max_damping_ratio)) then
      call set_status(status, demstep_stat%invalid_input, "must be in [0, 1e100]", where="damping_ratio")
    else if (.not. (zt >= 0.0_dp .and. zt <= max_damping_ratio)) then
      call set_status(status, demstep_stat%invalid_input, "must be in [0, 1e100]", where="damping_ratio_tangential")
    else if (.not. (scene%damping_ratio_rolling >= 0.0_dp .and. &
        scene%damping_ratio_rolling <= max_damping_ratio)) then
      call set_status(status, demstep_stat%invalid_input, "must be in [0, 1e100]", where="damping_ratio_rolling")
    else if (.not. (scene%drag >= 0.0_dp .and. scene%drag <= huge(1.0_dp))) then
      call set_status(status, demstep_stat%invalid_input, "must be >= 0 and finite", where="drag")
    end if
  end subroutine check_scene_damping

  !> The `scene_effect` code of a word (case ignored); 0 for another word.
  pure integer function scene_effect_from_name(name) result(code)
    !> The word, one of `scene_effect_names`.
    character(len=*), intent(in) :: name
    code = word_index(scene_effect_names, name)
  end function scene_effect_from_name

  !> The word of a `scene_effect` code (`?` for another value).
  pure function scene_effect_name(code) result(name)
    !> A code of `scene_effect`.
    integer, intent(in) :: code
    character(len=:), allocatable :: name
    name = word_of(scene_effect_names, code)
  end function scene_effect_name

end module demstep_scene_data
