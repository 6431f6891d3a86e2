!> Scene builders: a scene from particle arrays, its bonds, walls, explicit
!> contact list and periodic cell, each checked on the way in; and a ready
!> cubic lattice for tests and benchmarks.
module demstep_scene_builders
  use demstep_kinds, only: dp, i8, pi
  use demstep_status, only: demstep_status_type, demstep_stat, set_status
  use demstep_text, only: int_text
  use demstep_scene_data, only: scene_type, scene_effect, branch_vector, effect_index, n_effects, &
    max_damping_ratio
  use demstep_interaction, only: hertz_e_star, mindlin_g_star, contact_law
  use demstep_neighbours, only: search_type, prepare_search, find_contacts, search_trouble
  use, intrinsic :: ieee_arithmetic, only: ieee_is_finite
  implicit none
  private

  public :: new_scene, scene_add_bonds, scene_add_walls, scene_set_contacts, scene_set_cell, &
    scene_set_types, scene_set_hertz_types, scene_set_law, scene_set_bond_stiffness, scene_set_gravity, &
    scene_set_damping, scene_set_friction, scene_set_local_damping, scene_set_rolling, scene_set_effects, &
    cubic_lattice, restitution_to_damping_ratio, wrap_positions, random_periodic_packing, tile_scene

  !> Largest |coordinate| and radius of a scene: squared distances stay finite.
  real(dp), parameter, public :: max_coordinate = 1.0e150_dp
  !> Fewest and most particles of `random_periodic_packing` (the cell must be at
  !> least two contacts across; larger packings come from `tile_scene`).
  integer, parameter, public :: packing_min_particles = 64, packing_max_particles = 1000000
  !> The packing's mean overlap over the pair's mean radius, and the packing
  !> fraction it starts from (above jamming).
  real(dp), parameter, public :: packing_overlap = 4.0e-3_dp
  real(dp), parameter :: packing_start_fraction = 0.68_dp
  !> FIRE (unit masses and stiffness): first and largest step, mixing, steps per relaxation.
  real(dp), parameter :: fire_dt_start = 0.05_dp, fire_dt_max = 0.25_dp, fire_alpha_start = 0.1_dp
  integer, parameter :: fire_max_steps = 20000
  !> Skin of the relaxation's Verlet list, in mean radii.
  real(dp), parameter :: verlet_skin = 0.2_dp

contains

  !> Build a scene from particle arrays. Defaults: only the `contacts` effect
  !> on, no damping, no friction cap, no gravity, inertia 2/5 m r^2; the
  !> builders then switch on what they add (`rotation` with any tangential,
  !> rolling or twisting stiffness, `walls` with walls, `damping` with
  !> dashpots). Status `invalid_input` names the first
  !> bad value, its message starting with the variable (`mass:`, `radius:`,
  !> `inertia:`, `position:`, `velocity:`, `fixed:`): non-positive or too small
  !> mass (1/m must be finite), non-positive inertia, radius or coordinates
  !> beyond `max_coordinate`, wrong sizes, non-finite values, two particles at the
  !> same point (their contact normal is undefined), overlapping fixed particles,
  !> more than `contact_limit` contacts. `search = .false.` skips the contact
  !> search behind the last three (for a caller that gives its own contact
  !> list with `scene_set_contacts`: only listed pairs are ever contacts).
  subroutine new_scene(scene, dim, x, mass, radius, status, v, fixed, inertia, search)
    type(scene_type), intent(out) :: scene
    integer, intent(in) :: dim
    !> Positions (dim, n).
    real(dp), intent(in) :: x(:, :)
    real(dp), intent(in) :: mass(:), radius(:)
    type(demstep_status_type), intent(out) :: status
    !> Velocities (dim, n), default 0.
    real(dp), intent(in), optional :: v(:, :)
    !> Fixed flags, default none.
    logical, intent(in), optional :: fixed(:)
    !> Moments of inertia (> 0), default 2/5 m r^2 (a solid sphere).
    real(dp), intent(in), optional :: inertia(:)
    !> Search the contacts for the refusals above (default true).
    logical, intent(in), optional :: search
    integer :: n, i
    scene%gravity = 0.0_dp
    if (dim < 1 .or. dim > 3) then
      call set_status(status, demstep_stat%invalid_input, "dim: must be 1, 2 or 3")
      return
    end if
    n = size(mass)
    if (size(x, 1) /= dim .or. size(x, 2) /= n .or. size(radius) /= n) then
      call set_status(status, demstep_stat%invalid_input, "position: positions, masses and radii " &
        //"must describe the same particles")
      return
    end if
    do i = 1, n
      if (.not. (ieee_is_finite(mass(i)) .and. mass(i) > 0.0_dp)) then
        call set_status(status, demstep_stat%invalid_input, "mass: particle "//int_text(i)//": must be > 0")
        return
      end if
      if (.not. ieee_is_finite(1.0_dp/mass(i))) then
        call set_status(status, demstep_stat%invalid_input, "mass: particle "//int_text(i)//": must be " &
          //"at least 5.6e-309 (1/mass must be finite)")
        return
      end if
      if (.not. (ieee_is_finite(radius(i)) .and. radius(i) > 0.0_dp)) then
        call set_status(status, demstep_stat%invalid_input, "radius: particle "//int_text(i)//": must be > 0")
        return
      end if
      if (radius(i) > max_coordinate) then
        call set_status(status, demstep_stat%invalid_input, "radius: particle "//int_text(i)//": must be " &
          //"at most 1e150 (squared distances must be representable)")
        return
      end if
      if (.not. all(ieee_is_finite(x(:, i)))) then
        call set_status(status, demstep_stat%invalid_input, "position: particle "//int_text(i)//" is not finite")
        return
      end if
      if (any(abs(x(:, i)) > max_coordinate)) then
        call set_status(status, demstep_stat%invalid_input, "position: particle "//int_text(i)//": every " &
          //"coordinate must be within +-1e150 (squared distances must be representable)")
        return
      end if
    end do
    scene%dim = dim
    scene%n = n
    allocate(scene%x(3, n), source=0.0_dp)
    scene%x(:dim, :) = x
    scene%mass = mass
    scene%radius = radius
    if (present(inertia)) then
      if (size(inertia) /= n) then
        call set_status(status, demstep_stat%invalid_input, "inertia: one per particle")
        return
      end if
      do i = 1, n
        if (.not. (ieee_is_finite(inertia(i)) .and. inertia(i) > 0.0_dp)) then
          call set_status(status, demstep_stat%invalid_input, "inertia: particle "//int_text(i)// &
            ": must be > 0 and finite")
          return
        end if
      end do
      scene%inertia = inertia
    else
      ! 2/5 m r^2, saturated (only rotations use it)
      scene%inertia = min(0.4_dp*mass*radius, huge(1.0_dp)/max(1.0_dp, radius))*radius
    end if
    allocate(scene%v(3, n), scene%w(3, n), source=0.0_dp)
    if (present(v)) then
      if (size(v, 1) /= dim .or. size(v, 2) /= n .or. .not. all(ieee_is_finite(v))) then
        call set_status(status, demstep_stat%invalid_input, "velocity: must be finite, one per particle")
        return
      end if
      scene%v(:dim, :) = v
    end if
    allocate(scene%fixed(n), source=.false.)
    if (present(fixed)) then
      if (size(fixed) /= n) then
        call set_status(status, demstep_stat%invalid_input, "fixed: one fixed flag per particle")
        return
      end if
      scene%fixed = fixed
    end if
    do i = 1, 3
      where (scene%fixed) scene%v(i, :) = 0.0_dp
    end do
    allocate(scene%bonds(2, 0), scene%bond_rest(3, 0), scene%bond_normal(3, 0), &
      scene%wall_point(3, 0), scene%wall_normal(3, 0), scene%contact_pairs(2, 0), scene%contact_k(8, 0))
    status%stat = demstep_stat%ok
    if (present(search)) then
      if (.not. search) return
    end if
    call check_contacts(scene, status)
  end subroutine new_scene

  !> The contact search's refusals for the current configuration: coincident
  !> particles, too many contacts, overlapping fixed particles.
  subroutine check_contacts(scene, status)
    type(scene_type), intent(in) :: scene
    type(demstep_status_type), intent(out) :: status
    type(search_type) :: s
    integer :: i
    call prepare_search(scene, s)
    call find_contacts(scene, s)
    call search_trouble(s, status)
    if (status%stat /= demstep_stat%ok) return
    ! two fixed particles may not overlap: their contact could never resolve
    do i = 1, s%n_pairs
      if (scene%fixed(s%pair_i(i)) .and. scene%fixed(s%pair_j(i))) then
        call set_status(status, demstep_stat%invalid_input, "position: fixed particles "// &
          int_text(s%pair_i(i))//" and "//int_text(s%pair_j(i))//" overlap")
        return
      end if
    end do
    status%stat = demstep_stat%ok
  end subroutine check_contacts

  !> Make axes periodic with the orthorhombic cell [lo, hi): positions are
  !> wrapped into it, contacts and bonds then go through the nearest image.
  !> Status `invalid_input`: `cell_hi:` a periodic length not above 0 or shorter
  !> than twice the longest possible contact (2 (r_i + r_j), so that the nearest
  !> image is the only one in contact) or bond; `periodic:` a periodic axis
  !> beyond dim; call it before adding bonds. `search = .false.`: no contact
  !> search for coincident particles and too many contacts (as `new_scene`).
  subroutine scene_set_cell(scene, periodic, lo, hi, status, search)
    type(scene_type), intent(inout) :: scene
    logical, intent(in) :: periodic(3)
    real(dp), intent(in) :: lo(3), hi(3)
    type(demstep_status_type), intent(out) :: status
    !> Search the contacts for the refusals (default true).
    logical, intent(in), optional :: search
    real(dp) :: longest
    integer :: ax
    if (any(periodic(scene%dim+1:))) then
      call set_status(status, demstep_stat%invalid_input, "periodic: only the first dim axes can be periodic")
      return
    end if
    longest = 2.0_dp*maxval(scene%radius)
    if (size(scene%bonds, 2) > 0) longest = max(longest, maxval(norm2(scene%bond_rest, dim=1)))
    do ax = 1, 3
      if (.not. (ieee_is_finite(lo(ax)) .and. ieee_is_finite(hi(ax)) .and. &
          abs(lo(ax)) <= max_coordinate .and. abs(hi(ax)) <= max_coordinate)) then
        call set_status(status, demstep_stat%invalid_input, "cell_hi: axis "//int_text(ax)//": cell_lo " &
          //"and cell_hi must be finite within +-1e150")
        return
      end if
      if (.not. periodic(ax)) cycle
      if (.not. hi(ax) - lo(ax) > 0.0_dp) then
        call set_status(status, demstep_stat%invalid_input, "cell_hi: axis "//int_text(ax)//": cell_hi " &
          //"must be above cell_lo")
        return
      end if
      if (hi(ax) - lo(ax) < 2.0_dp*longest) then
        call set_status(status, demstep_stat%invalid_input, "cell_hi: axis "//int_text(ax)//": the " &
          //"periodic cell must be at least twice the longest contact or bond ("// &
          trim(real_text(2.0_dp*longest))//") long")
        return
      end if
    end do
    scene%periodic = periodic
    scene%cell_lo = lo
    scene%cell_hi = hi
    call wrap_positions(scene)
    status%stat = demstep_stat%ok
    if (present(search)) then
      if (.not. search) return
    end if
    call check_contacts(scene, status)
  end subroutine scene_set_cell

  !> Wrap the positions along the periodic axes into [cell_lo, cell_hi).
  pure subroutine wrap_positions(scene)
    type(scene_type), intent(inout) :: scene
    integer :: ax
    real(dp) :: box
    do ax = 1, 3
      if (.not. scene%periodic(ax)) cycle
      box = scene%cell_hi(ax) - scene%cell_lo(ax)
      scene%x(ax, :) = scene%cell_lo(ax) + modulo(scene%x(ax, :) - scene%cell_lo(ax), box)
    end do
  end subroutine wrap_positions

  !> A real number as text (for messages).
  pure function real_text(x) result(text)
    real(dp), intent(in) :: x
    character(len=24) :: text
    write(text, '(es12.5)') x
    text = adjustl(text)
  end function real_text

  !> Replace contact detection by an explicit list: pairs (2, nc) of particle
  !> numbers and per contact k (m, nc) with m = 2 (k_n, k_t), 4 (and the
  !> rolling and twisting stiffness k_r, k_w) or 8 (and the dashpots c_n, c_t,
  !> c_r, c_w, which then replace those of the damping ratios); linear springs,
  !> a pair acts while it overlaps, through the nearest periodic image.
  !> Switches `rotation` on when any k_t, k_r or k_w is > 0. Status
  !> `invalid_input` starting `contacts: row K:` for a missing particle, a
  !> particle paired with itself, k_n <= 0, another value < 0 or not finite.
  subroutine scene_set_contacts(scene, pairs, k, status)
    type(scene_type), intent(inout) :: scene
    integer, intent(in) :: pairs(:, :)
    real(dp), intent(in) :: k(:, :)
    type(demstep_status_type), intent(out) :: status
    character(len=*), parameter :: names(8) = [character(len=3) :: "k_n", "k_t", "k_r", "k_w", &
      "c_n", "c_t", "c_r", "c_w"]
    integer :: c, m, q
    m = size(k, 1)
    if (size(pairs, 1) /= 2 .or. .not. (m == 2 .or. m == 4 .or. m == 8) .or. size(k, 2) /= size(pairs, 2)) then
      call set_status(status, demstep_stat%invalid_input, "contacts: each contact is two particle " &
        //"numbers and 2, 4 or 8 values (k_n, k_t, k_r, k_w, c_n, c_t, c_r, c_w)")
      return
    end if
    do c = 1, size(pairs, 2)
      if (any(pairs(:, c) < 1) .or. any(pairs(:, c) > scene%n)) then
        call set_status(status, demstep_stat%invalid_input, "contacts: row "//int_text(c)//": names a " &
          //"missing particle ("//int_text(pairs(1, c))//", "//int_text(pairs(2, c))//"; there are " &
          //int_text(scene%n)//")")
        return
      end if
      if (pairs(1, c) == pairs(2, c)) then
        call set_status(status, demstep_stat%invalid_input, "contacts: row "//int_text(c)//": pairs " &
          //"particle "//int_text(pairs(1, c))//" with itself")
        return
      end if
      if (.not. (ieee_is_finite(k(1, c)) .and. k(1, c) > 0.0_dp)) then
        call set_status(status, demstep_stat%invalid_input, "contacts: row "//int_text(c)//": k_n " &
          //"must be > 0 and finite")
        return
      end if
      do q = 2, m
        if (.not. (ieee_is_finite(k(q, c)) .and. k(q, c) >= 0.0_dp)) then
          call set_status(status, demstep_stat%invalid_input, "contacts: row "//int_text(c)//": " &
            //trim(names(q))//" must be >= 0 and finite")
          return
        end if
      end do
    end do
    scene%contact_pairs = pairs
    deallocate(scene%contact_k)
    allocate(scene%contact_k(8, size(pairs, 2)), source=0.0_dp)
    scene%contact_k(:m, :) = k
    scene%given_dashpots = m == 8
    scene%given_contacts = .true.
    if (any(scene%contact_k(2:4, :) > 0.0_dp)) scene%effects(scene_effect%rotation) = .true.
    status%stat = demstep_stat%ok
  end subroutine scene_set_contacts

  !> Linear materials per particle type: the type of each particle (1 to nt) and
  !> per type pair k(:, a, b) = (k_n, k_t), symmetric; `rotation` on when any
  !> k_t > 0. Status `invalid_input`:
  !> `types:` a type outside 1 to nt, a count other than one per particle;
  !> `type_k_normal:` k_n <= 0 or not symmetric; `type_k_tangential:` k_t < 0 or
  !> not symmetric.
  subroutine scene_set_types(scene, types, k, status)
    type(scene_type), intent(inout) :: scene
    integer, intent(in) :: types(:)
    real(dp), intent(in) :: k(:, :, :)
    type(demstep_status_type), intent(out) :: status
    integer :: nt
    nt = size(k, 2)
    call check_types(scene, types, nt, status)
    if (status%stat /= demstep_stat%ok) return
    if (size(k, 1) /= 2 .or. size(k, 3) /= nt) then
      call set_status(status, demstep_stat%invalid_input, "type_k_normal: one value per type pair")
      return
    end if
    if (.not. all(ieee_is_finite(k(1, :, :)) .and. k(1, :, :) > 0.0_dp)) then
      call set_status(status, demstep_stat%invalid_input, "type_k_normal: must be > 0 and finite")
      return
    end if
    if (.not. all(ieee_is_finite(k(2, :, :)) .and. k(2, :, :) >= 0.0_dp)) then
      call set_status(status, demstep_stat%invalid_input, "type_k_tangential: must be >= 0 and finite")
      return
    end if
    if (any(k(1, :, :) /= transpose(k(1, :, :)))) then
      call set_status(status, demstep_stat%invalid_input, "type_k_normal: must be symmetric (a-b as b-a)")
      return
    end if
    if (any(k(2, :, :) /= transpose(k(2, :, :)))) then
      call set_status(status, demstep_stat%invalid_input, "type_k_tangential: must be symmetric (a-b as b-a)")
      return
    end if
    scene%ptype = types
    call clear_types(scene)
    allocate(scene%pair_law(4, nt, nt), source=0.0_dp)
    scene%pair_law(1:2, :, :) = k
    if (any(k(2, :, :) > 0.0_dp)) scene%effects(scene_effect%rotation) = .true.
    status%stat = demstep_stat%ok
  end subroutine scene_set_types

  !> Hertz materials per particle type: Young's modulus and Poisson's ratio per
  !> type; E* and Mindlin's G* of each type pair follow (`rotation` on). Status `invalid_input`:
  !> `types:` as `scene_set_types`; `young:` not > 0 and finite; `poisson:`
  !> outside (-1, 0.5].
  subroutine scene_set_hertz_types(scene, types, young, poisson, status)
    type(scene_type), intent(inout) :: scene
    integer, intent(in) :: types(:)
    real(dp), intent(in) :: young(:), poisson(:)
    type(demstep_status_type), intent(out) :: status
    integer :: nt, a
    nt = size(young)
    call check_types(scene, types, nt, status)
    if (status%stat /= demstep_stat%ok) return
    if (size(poisson) /= nt) then
      call set_status(status, demstep_stat%invalid_input, "poisson: one per type, as young")
      return
    end if
    if (.not. all(ieee_is_finite(young) .and. young > 0.0_dp)) then
      call set_status(status, demstep_stat%invalid_input, "young: must be > 0 and finite")
      return
    end if
    if (.not. all(poisson > -1.0_dp .and. poisson <= 0.5_dp)) then
      call set_status(status, demstep_stat%invalid_input, "poisson: must be in (-1, 0.5]")
      return
    end if
    scene%ptype = types
    call clear_types(scene)
    allocate(scene%pair_law(4, nt, nt), source=0.0_dp)
    do a = 1, nt
      scene%pair_law(3, :, a) = hertz_e_star(young, poisson, young(a), poisson(a))
      scene%pair_law(4, :, a) = mindlin_g_star(young, poisson, young(a), poisson(a))
    end do
    ! Mindlin's tangential springs
    scene%effects(scene_effect%rotation) = .true.
    status%stat = demstep_stat%ok
  end subroutine scene_set_hertz_types

  !> Drop the per-type tables of an earlier call (materials included).
  pure subroutine clear_types(scene)
    type(scene_type), intent(inout) :: scene
    if (allocated(scene%pair_law)) deallocate(scene%pair_law)
    if (allocated(scene%pair_damping)) deallocate(scene%pair_damping)
    if (allocated(scene%wall_law)) deallocate(scene%wall_law)
    if (allocated(scene%wall_damping)) deallocate(scene%wall_damping)
  end subroutine clear_types

  !> One type in 1 to nt per particle.
  subroutine check_types(scene, types, nt, status)
    type(scene_type), intent(in) :: scene
    integer, intent(in) :: types(:), nt
    type(demstep_status_type), intent(out) :: status
    integer :: i
    if (size(types) /= scene%n .or. nt < 1) then
      call set_status(status, demstep_stat%invalid_input, "types: one type per particle ("// &
        int_text(scene%n)//"), and at least one material")
      return
    end if
    do i = 1, scene%n
      if (types(i) < 1 .or. types(i) > nt) then
        call set_status(status, demstep_stat%invalid_input, "types: particle "//int_text(i)//": type "// &
          int_text(types(i))//" is not one of the "//int_text(nt)//" materials")
        return
      end if
    end do
    status%stat = demstep_stat%ok
  end subroutine check_types

  !> A cubic lattice of m^3 particles 1 apart (unit masses, radius r) with bonds of
  !> stiffness k_bond to the +x, +y, +z neighbours, and random velocities of size
  !> `speed` (default 1e-3); linear contacts of stiffness k_bond, only the
  !> `contacts` effect on. A ready test and benchmark load.
  subroutine cubic_lattice(scene, m, radius, k_bond, status, speed)
    type(scene_type), intent(out) :: scene
    integer, intent(in) :: m
    real(dp), intent(in) :: radius, k_bond
    type(demstep_status_type), intent(out) :: status
    real(dp), intent(in), optional :: speed
    real(dp), allocatable :: x(:, :), v(:, :)
    integer, allocatable :: pairs(:, :)
    integer :: i, j, k, p, nb
    real(dp) :: size_v
    if (m < 2) then
      call set_status(status, demstep_stat%invalid_input, "a lattice needs m >= 2")
      return
    end if
    size_v = 1.0e-3_dp
    if (present(speed)) size_v = speed
    allocate(x(3, m**3), v(3, m**3), pairs(2, 3*m**3))
    call random_number(v)
    v = size_v*(v - 0.5_dp)
    nb = 0
    do k = 1, m
      do j = 1, m
        do i = 1, m
          p = i + m*(j - 1 + m*(k - 1))
          x(:, p) = [real(i, dp), real(j, dp), real(k, dp)]
          if (i < m) then
            nb = nb + 1
            pairs(:, nb) = [p, p + 1]
          end if
          if (j < m) then
            nb = nb + 1
            pairs(:, nb) = [p, p + m]
          end if
          if (k < m) then
            nb = nb + 1
            pairs(:, nb) = [p, p + m*m]
          end if
        end do
      end do
    end do
    call new_scene(scene, 3, x, spread(1.0_dp, 1, m**3), spread(radius, 1, m**3), status, v=v)
    if (status%stat /= demstep_stat%ok) return
    call scene_add_bonds(scene, pairs(:, :nb), status)
    scene%k_bond = k_bond
    scene%k_normal = k_bond
    scene%effects = .false.
    scene%effects(scene_effect%contacts) = .true.
  end subroutine cubic_lattice

  !> Add bonds between particle pairs (2, nb); rest vectors from the current
  !> positions (nearest image in a periodic cell).
  subroutine scene_add_bonds(scene, pairs, status)
    type(scene_type), intent(inout) :: scene
    integer, intent(in) :: pairs(:, :)
    type(demstep_status_type), intent(out) :: status
    integer :: k, nb0, nb
    integer, allocatable :: bonds(:, :)
    real(dp), allocatable :: rest(:, :), normal(:, :)
    if (size(pairs, 1) /= 2) then
      call set_status(status, demstep_stat%invalid_input, "bonds are pairs of particle numbers")
      return
    end if
    nb0 = size(scene%bonds, 2)
    nb = nb0 + size(pairs, 2)
    allocate(bonds(2, nb), rest(3, nb), normal(3, nb))
    bonds(:, :nb0) = scene%bonds
    rest(:, :nb0) = scene%bond_rest
    normal(:, :nb0) = scene%bond_normal
    do k = 1, size(pairs, 2)
      if (any(pairs(:, k) < 1) .or. any(pairs(:, k) > scene%n)) then
        call set_status(status, demstep_stat%invalid_input, "bond "//int_text(k)//" names a missing " &
          //"particle ("//int_text(pairs(1, k))//", "//int_text(pairs(2, k))//")")
        return
      end if
      if (pairs(1, k) == pairs(2, k)) then
        call set_status(status, demstep_stat%invalid_input, "bond "//int_text(k)//" joins particle " &
          //int_text(pairs(1, k))//" to itself")
        return
      end if
      bonds(:, nb0 + k) = pairs(:, k)
      rest(:, nb0 + k) = branch_vector(scene, pairs(1, k), pairs(2, k))
      if (.not. norm2(rest(:, nb0 + k)) > 0.0_dp) then
        call set_status(status, demstep_stat%invalid_input, "bond "//int_text(k)//" joins particles " &
          //"at the same position")
        return
      end if
      normal(:, nb0 + k) = rest(:, nb0 + k)/norm2(rest(:, nb0 + k))
    end do
    call move_alloc(bonds, scene%bonds)
    call move_alloc(rest, scene%bond_rest)
    call move_alloc(normal, scene%bond_normal)
    status%stat = demstep_stat%ok
  end subroutine scene_add_bonds

  !> Add walls: points (dim, nw) and normals (dim, nw) pointing into the
  !> domain; switches the `walls` effect on. Walls take the scene's law
  !> (normal, tangential, rolling springs and dashpots with R* = r, m* = m).
  subroutine scene_add_walls(scene, points, normals, status)
    type(scene_type), intent(inout) :: scene
    real(dp), intent(in) :: points(:, :), normals(:, :)
    type(demstep_status_type), intent(out) :: status
    real(dp), allocatable :: unit(:, :), point(:, :)
    integer :: k
    if (size(points, 1) /= scene%dim .or. any(shape(normals) /= shape(points))) then
      call set_status(status, demstep_stat%invalid_input, "a wall is a point and a normal of dim values each")
      return
    end if
    allocate(unit(3, size(normals, 2)), point(3, size(points, 2)), source=0.0_dp)
    point(:scene%dim, :) = points
    do k = 1, size(normals, 2)
      if (.not. (all(ieee_is_finite(points(:, k))) .and. norm2(normals(:, k)) > 0.0_dp)) then
        call set_status(status, demstep_stat%invalid_input, "wall "//int_text(k)//" needs a finite " &
          //"point and a non-zero normal")
        return
      end if
      unit(:scene%dim, k) = normals(:, k)/norm2(normals(:, k))
    end do
    scene%wall_point = reshape([scene%wall_point, point], [3, size(scene%wall_point, 2) + size(point, 2)])
    scene%wall_normal = reshape([scene%wall_normal, unit], [3, size(scene%wall_normal, 2) + size(unit, 2)])
    scene%effects(scene_effect%walls) = .true.
    status%stat = demstep_stat%ok
  end subroutine scene_add_walls

  !> The contact law of detected particle contacts and of wall contacts:
  !> `contact_law%linear` with normal = k_normal (> 0) and tangential =
  !> k_tangential (>= 0), or `contact_law%hertz` with normal = e_star (E* > 0)
  !> and tangential = g_star (Mindlin's G* >= 0); `rotation` on when
  !> tangential > 0. Status `invalid_input` naming
  !> `law:` (not one of `contact_law`) or the parameter (not finite, out of range);
  !> the scene is unchanged then.
  subroutine scene_set_law(scene, law, normal, tangential, status)
    type(scene_type), intent(inout) :: scene
    integer, intent(in) :: law
    real(dp), intent(in) :: normal, tangential
    type(demstep_status_type), intent(out) :: status
    character(len=:), allocatable :: name_n, name_t
    if (law == contact_law%linear) then
      name_n = "k_normal"
      name_t = "k_tangential"
    else if (law == contact_law%hertz) then
      name_n = "e_star"
      name_t = "g_star"
    else
      call set_status(status, demstep_stat%invalid_input, "law: "//int_text(law)//" is not a contact " &
        //"law (linear "//int_text(contact_law%linear)//", hertz "//int_text(contact_law%hertz)//")")
      return
    end if
    if (.not. (ieee_is_finite(normal) .and. normal > 0.0_dp)) then
      call set_status(status, demstep_stat%invalid_input, name_n//": must be > 0 and finite")
      return
    end if
    if (.not. (ieee_is_finite(tangential) .and. tangential >= 0.0_dp)) then
      call set_status(status, demstep_stat%invalid_input, name_t//": must be >= 0 and finite")
      return
    end if
    scene%law = law
    if (law == contact_law%linear) then
      scene%k_normal = normal
      scene%k_tangential = tangential
    else
      scene%e_star = normal
      scene%g_star = tangential
    end if
    if (tangential > 0.0_dp) scene%effects(scene_effect%rotation) = .true.
    status%stat = demstep_stat%ok
  end subroutine scene_set_law

  !> The stiffness of every bond: normal k_bond (> 0) and tangential
  !> k_bond_tangential (>= 0). Status `invalid_input` naming the one that is out
  !> of range or not finite; the scene is unchanged then.
  subroutine scene_set_bond_stiffness(scene, k_bond, k_bond_tangential, status)
    type(scene_type), intent(inout) :: scene
    real(dp), intent(in) :: k_bond, k_bond_tangential
    type(demstep_status_type), intent(out) :: status
    if (.not. (ieee_is_finite(k_bond) .and. k_bond > 0.0_dp)) then
      call set_status(status, demstep_stat%invalid_input, "k_bond: must be > 0 and finite")
      return
    end if
    if (.not. (ieee_is_finite(k_bond_tangential) .and. k_bond_tangential >= 0.0_dp)) then
      call set_status(status, demstep_stat%invalid_input, "k_bond_tangential: must be >= 0 and finite")
      return
    end if
    scene%k_bond = k_bond
    scene%k_bond_tangential = k_bond_tangential
    status%stat = demstep_stat%ok
  end subroutine scene_set_bond_stiffness

  !> The gravity vector: dim finite components (those beyond dim stay zero).
  !> Status `invalid_input` starting `gravity:`; the scene is unchanged then.
  subroutine scene_set_gravity(scene, gravity, status)
    type(scene_type), intent(inout) :: scene
    real(dp), intent(in) :: gravity(:)
    type(demstep_status_type), intent(out) :: status
    if (size(gravity) /= scene%dim .or. .not. all(ieee_is_finite(gravity))) then
      call set_status(status, demstep_stat%invalid_input, "gravity: needs "//int_text(scene%dim)// &
        " finite components")
      return
    end if
    scene%gravity = 0.0_dp
    scene%gravity(:scene%dim) = gravity
    status%stat = demstep_stat%ok
  end subroutine scene_set_gravity

  !> Viscous damping: the normal damping ratio (c_n = 2 zeta sqrt(m* k_n)), and
  !> optionally the tangential one (c_t = 2 zeta_t sqrt(m* k_t); default: the
  !> normal ratio, as LIGGGHTS' `tangential_damping on`; 0 for none), the
  !> rolling and twisting one (c = 2 zeta_r sqrt(I* k), default 0) and a drag of
  !> every particle to the ground (F = -drag v, default 0). Switches the
  !> `damping` effect on. Status `invalid_input` naming `damping_ratio`,
  !> `damping_ratio_tangential`, `damping_ratio_rolling` (each in [0, 1e100])
  !> or `drag` (>= 0, finite); the scene is unchanged then.
  subroutine scene_set_damping(scene, ratio, status, tangential, rolling, drag)
    type(scene_type), intent(inout) :: scene
    real(dp), intent(in) :: ratio
    type(demstep_status_type), intent(out) :: status
    real(dp), intent(in), optional :: tangential, rolling, drag
    real(dp) :: zt, zr, g
    zt = ratio
    if (present(tangential)) zt = tangential
    zr = 0.0_dp
    if (present(rolling)) zr = rolling
    g = 0.0_dp
    if (present(drag)) g = drag
    if (.not. damping_ratio_ok(ratio)) then
      call set_status(status, demstep_stat%invalid_input, "damping_ratio: must be in [0, 1e100]")
    else if (.not. damping_ratio_ok(zt)) then
      call set_status(status, demstep_stat%invalid_input, "damping_ratio_tangential: must be in [0, 1e100]")
    else if (.not. damping_ratio_ok(zr)) then
      call set_status(status, demstep_stat%invalid_input, "damping_ratio_rolling: must be in [0, 1e100]")
    else if (.not. (ieee_is_finite(g) .and. g >= 0.0_dp)) then
      call set_status(status, demstep_stat%invalid_input, "drag: must be >= 0 and finite")
    else
      scene%damping_ratio = ratio
      scene%damping_ratio_tangential = zt
      scene%damping_ratio_rolling = zr
      scene%drag = g
      scene%effects(scene_effect%damping) = .true.
      status%stat = demstep_stat%ok
    end if
  end subroutine scene_set_damping

  !> Whether a damping ratio is in [0, max_damping_ratio].
  elemental logical function damping_ratio_ok(zeta)
    real(dp), intent(in) :: zeta
    damping_ratio_ok = zeta >= 0.0_dp .and. zeta <= max_damping_ratio
  end function damping_ratio_ok

  !> Coulomb friction of the tangential springs (>= 0; a negative value: no
  !> sliding) and optionally the rolling friction that caps the rolling moment
  !> at rolling_friction R* F_n (>= 0; negative: no cap). Status
  !> `invalid_input` naming `friction` or `rolling_friction` (not finite).
  subroutine scene_set_friction(scene, friction, status, rolling_friction)
    type(scene_type), intent(inout) :: scene
    real(dp), intent(in) :: friction
    type(demstep_status_type), intent(out) :: status
    real(dp), intent(in), optional :: rolling_friction
    if (.not. ieee_is_finite(friction)) then
      call set_status(status, demstep_stat%invalid_input, "friction: must be finite")
      return
    end if
    if (present(rolling_friction)) then
      if (.not. ieee_is_finite(rolling_friction)) then
        call set_status(status, demstep_stat%invalid_input, "rolling_friction: must be finite")
        return
      end if
      scene%rolling_friction = rolling_friction
    end if
    scene%friction = friction
    status%stat = demstep_stat%ok
  end subroutine scene_set_friction

  !> Cundall's local damping coefficient alpha in [0, 1); switches the
  !> `local_damping` effect on (off for alpha = 0). Status `invalid_input`
  !> naming `local_damping`.
  subroutine scene_set_local_damping(scene, alpha, status)
    type(scene_type), intent(inout) :: scene
    real(dp), intent(in) :: alpha
    type(demstep_status_type), intent(out) :: status
    if (.not. (alpha >= 0.0_dp .and. alpha < 1.0_dp)) then
      call set_status(status, demstep_stat%invalid_input, "local_damping: must be in [0, 1)")
      return
    end if
    scene%local_damping = alpha
    scene%effects(scene_effect%local_damping) = alpha > 0.0_dp
    status%stat = demstep_stat%ok
  end subroutine scene_set_local_damping

  !> Rolling and twisting springs of detected and wall contacts:
  !> k_r = rolling_ratio k_t R*^2, k_w = twisting_ratio k_t R*^2 (each >= 0,
  !> finite); `rotation` on when either is > 0. Status `invalid_input` naming
  !> `rolling_ratio` or `twisting_ratio`.
  subroutine scene_set_rolling(scene, rolling_ratio, twisting_ratio, status)
    type(scene_type), intent(inout) :: scene
    real(dp), intent(in) :: rolling_ratio, twisting_ratio
    type(demstep_status_type), intent(out) :: status
    if (.not. (ieee_is_finite(rolling_ratio) .and. rolling_ratio >= 0.0_dp)) then
      call set_status(status, demstep_stat%invalid_input, "rolling_ratio: must be >= 0 and finite")
      return
    end if
    if (.not. (ieee_is_finite(twisting_ratio) .and. twisting_ratio >= 0.0_dp)) then
      call set_status(status, demstep_stat%invalid_input, "twisting_ratio: must be >= 0 and finite")
      return
    end if
    scene%rolling_ratio = rolling_ratio
    scene%twisting_ratio = twisting_ratio
    if (rolling_ratio > 0.0_dp .or. twisting_ratio > 0.0_dp) scene%effects(scene_effect%rotation) = .true.
    status%stat = demstep_stat%ok
  end subroutine scene_set_rolling

  !> Switch effects on or off by name (`effect_names`: 'contacts', 'gravity',
  !> 'damping', 'local_damping', 'walls', 'rotation'), each `on(k)` for
  !> `names(k)`. Status `invalid_input` naming `effects` for an unknown name or
  !> sizes that differ; the scene is unchanged then.
  subroutine scene_set_effects(scene, names, on, status)
    type(scene_type), intent(inout) :: scene
    character(len=*), intent(in) :: names(:)
    logical, intent(in) :: on(:)
    type(demstep_status_type), intent(out) :: status
    logical :: effects(n_effects)
    integer :: k, e
    if (size(on) /= size(names)) then
      call set_status(status, demstep_stat%invalid_input, "effects: one on/off flag per name")
      return
    end if
    effects = scene%effects
    do k = 1, size(names)
      e = effect_index(trim(names(k)))
      if (e == 0) then
        call set_status(status, demstep_stat%invalid_input, "effects: '"//trim(names(k))//"' is not " &
          //"an effect")
        return
      end if
      effects(e) = on(k)
    end do
    scene%effects = effects
    status%stat = demstep_stat%ok
  end subroutine scene_set_effects

  !> Damping ratio of a linear spring-dashpot whose restitution coefficient is e:
  !> zeta = -ln e / sqrt(pi^2 + ln^2 e).
  elemental real(dp) function restitution_to_damping_ratio(e) result(zeta)
    real(dp), intent(in) :: e
    zeta = -log(e)/sqrt(pi**2 + log(e)**2)
  end function restitution_to_damping_ratio

  !> A random dense packing of n spheres in a cubic periodic cell: a contact
  !> network like a DEM packing at rest, with the `contacts` and `rotation`
  !> effects on and linear normal and tangential springs.
  !>
  !> Radii are uniform in radius (1 +- polydispersity). The spheres start on a
  !> jittered simple cubic lattice (numbered in lattice order, so neighbours have
  !> near numbers) at packing fraction 0.68, and are relaxed with unit harmonic
  !> repulsion by FIRE to force balance; the radii are then shrunk step by step
  !> (secant on the mean overlap, re-relaxed each time) until the mean overlap is
  !> about 4e-3 of the pair's mean radius, just above jamming. A particle left
  !> without contact (a rattler, a few per cent) is moved straight to its
  !> nearest neighbour until it touches it with the same small overlap, so every
  !> particle is in contact. Measured (seeds 1 to 3, n = 100 to 1000): mean
  !> coordination 6.4 to 6.6 (every particle at least 1), mean overlap 4.5e-3 to
  !> 5e-3 of the pair's mean radius, largest 1.5e-2 to 2.6e-2, packing fraction
  !> 0.645 to 0.652. The numbers come from a MINSTD generator (exact in 64-bit
  !> integers), so a seed gives the same packing wherever the floating point is
  !> the same. Cost: O(n) per relaxation step and a bounded number of steps
  !> (1.6 s at n = 1000, release build, about 1e4 steps);
  !> larger packings are made by `tile_scene`.
  !>
  !> Status `invalid_input` naming the argument: `n:` below
  !> `packing_min_particles` or above `packing_max_particles`; `radius:`,
  !> `density:`, `k_normal:` not > 0 and finite; `k_tangential:` not >= 0 and
  !> finite; `polydispersity:` outside [0, 0.5]; `damping_ratio:` outside
  !> [0, 1e100].
  subroutine random_periodic_packing(scene, n, status, seed, radius, polydispersity, density, &
      k_normal, k_tangential, damping_ratio)
    type(scene_type), intent(out) :: scene
    !> Number of particles.
    integer, intent(in) :: n
    type(demstep_status_type), intent(out) :: status
    !> Seed of the generator (any integer); default 1.
    integer, intent(in), optional :: seed
    !> Mean radius (default 1) and relative spread of the radii (default 0.15).
    real(dp), intent(in), optional :: radius, polydispersity
    !> Density of the spheres (default 1): mass 4/3 pi r^3 density, inertia 2/5 m r^2.
    real(dp), intent(in), optional :: density
    !> Normal stiffness (default 1) and tangential stiffness (default 2/7 k_normal).
    real(dp), intent(in), optional :: k_normal, k_tangential
    !> Viscous damping ratio of every contact; present: the `damping` effect is on.
    real(dp), intent(in), optional :: damping_ratio
    real(dp) :: r_mean, poly, rho, kn, kt, zeta, box
    real(dp), allocatable :: x(:, :), r(:)
    integer(i8) :: state
    type(scene_type) :: law_only
    r_mean = 1.0_dp
    if (present(radius)) r_mean = radius
    poly = 0.15_dp
    if (present(polydispersity)) poly = polydispersity
    rho = 1.0_dp
    if (present(density)) rho = density
    kn = 1.0_dp
    if (present(k_normal)) kn = k_normal
    kt = 2.0_dp/7.0_dp*kn
    if (present(k_tangential)) kt = k_tangential
    zeta = 0.0_dp
    if (present(damping_ratio)) zeta = damping_ratio
    if (n < packing_min_particles .or. n > packing_max_particles) then
      call set_status(status, demstep_stat%invalid_input, "n: a random periodic packing needs "// &
        int_text(packing_min_particles)//" to "//int_text(packing_max_particles)//" particles " &
        //"(tile_scene makes larger ones)")
      return
    end if
    if (.not. (ieee_is_finite(r_mean) .and. r_mean > 0.0_dp .and. r_mean <= 1.0e100_dp)) then
      call set_status(status, demstep_stat%invalid_input, "radius: must be > 0 and at most 1e100")
      return
    end if
    if (.not. (poly >= 0.0_dp .and. poly <= 0.5_dp)) then
      call set_status(status, demstep_stat%invalid_input, "polydispersity: must be in [0, 0.5]")
      return
    end if
    if (.not. (ieee_is_finite(rho) .and. rho > 0.0_dp)) then
      call set_status(status, demstep_stat%invalid_input, "density: must be > 0 and finite")
      return
    end if
    ! the law's own check, before the relaxation
    call scene_set_law(law_only, contact_law%linear, kn, kt, status)
    if (status%stat /= demstep_stat%ok) return
    if (.not. (zeta >= 0.0_dp .and. zeta <= 1.0e100_dp)) then
      call set_status(status, demstep_stat%invalid_input, "damping_ratio: must be in [0, 1e100]")
      return
    end if
    state = 1_i8
    if (present(seed)) state = 1_i8 + modulo(int(seed, i8), 2147483646_i8)
    call jammed_packing(n, poly, state, x, r, box)
    ! from unit mean radius to the asked one
    call new_scene(scene, 3, r_mean*x, rho*(4.0_dp/3.0_dp*pi)*(r_mean*r)**3, r_mean*r, status)
    if (status%stat /= demstep_stat%ok) return
    call scene_set_cell(scene, [.true., .true., .true.], [0.0_dp, 0.0_dp, 0.0_dp], &
      spread(r_mean*box, 1, 3), status)
    if (status%stat /= demstep_stat%ok) return
    call scene_set_law(scene, contact_law%linear, kn, kt, status)
    if (status%stat /= demstep_stat%ok) return
    scene%effects = .false.
    scene%effects(scene_effect%contacts) = .true.
    scene%effects(scene_effect%rotation) = .true.
    if (present(damping_ratio)) then
      scene%effects(scene_effect%damping) = .true.
      scene%damping_ratio = zeta
    end if
  end subroutine random_periodic_packing

  !> The packing in units of the mean radius: positions x(3, n) in the cell
  !> [0, box)^3 and radii r(n).
  subroutine jammed_packing(n, poly, state, x, r, box)
    integer, intent(in) :: n
    real(dp), intent(in) :: poly
    integer(i8), intent(inout) :: state
    real(dp), allocatable, intent(out) :: x(:, :), r(:)
    real(dp), intent(out) :: box
    type(scene_type) :: work
    real(dp), allocatable :: r0(:)
    real(dp) :: g, g_lo, g_hi, m, m_lo, m_hi, u, c
    integer :: i, iter
    logical :: have_lo
    allocate(r0(n))
    do i = 1, n
      call next_uniform(state, u)
      r0(i) = 1.0_dp + poly*(2.0_dp*u - 1.0_dp)
    end do
    box = (sum(4.0_dp/3.0_dp*pi*r0**3)/packing_start_fraction)**(1.0_dp/3.0_dp)
    work%dim = 3
    work%n = n
    work%periodic = .true.
    work%cell_lo = 0.0_dp
    work%cell_hi = box
    call jittered_lattice(n, box, state, work%x)
    work%radius = r0
    ! shrink the radii (factor g) until the relaxed mean overlap is near target
    g = 1.0_dp
    call relax(work, r0, g, m)
    do iter = 1, 20
      if (m > packing_overlap) exit
      g = 1.02_dp*g
      call relax(work, r0, g, m)
    end do
    g_hi = g
    m_hi = m
    g_lo = 0.0_dp
    m_lo = 0.0_dp
    have_lo = .false.
    do iter = 1, 40
      if (abs(m - packing_overlap) <= 0.25_dp*packing_overlap) exit
      if (have_lo .and. m_lo > 0.0_dp) then
        ! regula falsi between a jammed state above and one below the target
        g = g_lo + (packing_overlap - m_lo)*(g_hi - g_lo)/(m_hi - m_lo)
      else if (have_lo) then
        ! below jamming at g_lo: bisect
        g = 0.5_dp*(g_lo + g_hi)
      else
        ! relaxed overlaps shrink at most about twice as fast as the radii
        g = g_hi*(1.0_dp - 0.5_dp*(m_hi - packing_overlap))
      end if
      call relax(work, r0, g, m)
      if (m > packing_overlap) then
        g_hi = g
        m_hi = m
      else
        g_lo = g
        m_lo = m
        have_lo = .true.
      end if
    end do
    call attach_rattlers(work)
    call wrap_positions(work)
    ! back to unit mean radius
    c = real(n, dp)/sum(work%radius)
    x = c*work%x
    r = c*work%radius
    box = c*box
  end subroutine jammed_packing

  !> n sites of an m^3 simple cubic lattice in [0, box)^3 (m^3 >= n, the empty
  !> sites drawn at random), each jittered by up to 0.2 of the spacing, numbered
  !> in lattice order.
  subroutine jittered_lattice(n, box, state, x)
    integer, intent(in) :: n
    real(dp), intent(in) :: box
    integer(i8), intent(inout) :: state
    real(dp), allocatable, intent(out) :: x(:, :)
    integer, allocatable :: site(:)
    logical, allocatable :: empty(:)
    integer :: m, k, j, p, a, b, c
    real(dp) :: u, h, jitter(3)
    m = max(1, nint(real(n, dp)**(1.0_dp/3.0_dp)))
    do while (m**3 < n)
      m = m + 1
    end do
    ! the m^3 - n empty sites: a partial Fisher-Yates shuffle
    site = [(k, k = 1, m**3)]
    allocate(empty(m**3), source=.false.)
    do k = 1, m**3 - n
      call next_uniform(state, u)
      j = k + min(m**3 - k, int(u*(m**3 - k + 1)))
      p = site(j)
      site(j) = site(k)
      site(k) = p
      empty(p) = .true.
    end do
    h = box/m
    allocate(x(3, n))
    p = 0
    do k = 1, m**3
      if (empty(k)) cycle
      p = p + 1
      a = mod(k - 1, m)
      b = mod((k - 1)/m, m)
      c = (k - 1)/(m*m)
      do j = 1, 3
        call next_uniform(state, u)
        jitter(j) = 0.4_dp*(u - 0.5_dp)
      end do
      x(:, p) = h*([real(a, dp), real(b, dp), real(c, dp)] + 0.5_dp + jitter)
    end do
  end subroutine jittered_lattice

  !> Relax the spheres of radii g r0 to force balance (unit harmonic repulsion,
  !> FIRE); m is then the mean overlap over the pair's mean radius. The pairs
  !> are taken from a Verlet list (the cell list's pairs within a skin),
  !> rebuilt when a particle has moved half the skin.
  subroutine relax(work, r0, g, m)
    type(scene_type), intent(inout) :: work
    real(dp), intent(in) :: r0(:), g
    real(dp), intent(out) :: m
    type(scene_type) :: probe
    type(search_type) :: s
    real(dp), allocatable :: v(:, :), f(:, :), moved(:, :)
    integer, allocatable :: ci(:), cj(:)
    real(dp) :: dt, alpha, p, vn, fn, f_tol, d(3), dist2, reach, overlap
    integer :: step, k, n_positive, i, j, n_pairs
    work%radius = g*r0
    probe = work
    probe%radius = work%radius + 0.5_dp*verlet_skin
    call prepare_search(probe, s)
    allocate(v(3, work%n), source=0.0_dp)
    allocate(f(3, work%n), moved(3, work%n))
    ! net force per particle below 2 % of a typical contact force
    f_tol = 0.02_dp*packing_overlap
    dt = fire_dt_start
    alpha = fire_alpha_start
    n_positive = 0
    moved = huge(1.0_dp)
    do step = 1, fire_max_steps
      if (maxval(moved(1, :)**2 + moved(2, :)**2 + moved(3, :)**2) > (0.5_dp*verlet_skin)**2) then
        call wrap_positions(work)
        probe%x = work%x
        call find_contacts(probe, s)
        ci = s%pair_i(:s%n_pairs)
        cj = s%pair_j(:s%n_pairs)
        moved = 0.0_dp
      end if
      f = 0.0_dp
      m = 0.0_dp
      n_pairs = 0
      do k = 1, size(ci)
        i = ci(k)
        j = cj(k)
        d = branch_vector(work, i, j)
        dist2 = d(1)**2 + d(2)**2 + d(3)**2
        reach = work%radius(i) + work%radius(j)
        if (dist2 >= reach**2) cycle
        overlap = reach - sqrt(dist2)
        d = (overlap/sqrt(dist2))*d
        f(:, i) = f(:, i) - d
        f(:, j) = f(:, j) + d
        m = m + overlap/(0.5_dp*reach)
        n_pairs = n_pairs + 1
      end do
      if (maxval(f(1, :)**2 + f(2, :)**2 + f(3, :)**2) <= f_tol**2) exit
      p = sum(f*v)
      if (p > 0.0_dp) then
        n_positive = n_positive + 1
        if (n_positive > 5) then
          dt = min(1.1_dp*dt, fire_dt_max)
          alpha = 0.99_dp*alpha
        end if
      else
        n_positive = 0
        dt = max(0.5_dp*dt, 0.02_dp*fire_dt_max)
        alpha = fire_alpha_start
        v = 0.0_dp
      end if
      v = v + dt*f
      vn = sqrt(sum(v**2))
      fn = sqrt(sum(f**2))
      if (fn > 0.0_dp) v = (1.0_dp - alpha)*v + (alpha*vn/fn)*f
      work%x = work%x + dt*v
      moved = moved + dt*v
    end do
    call wrap_positions(work)
    if (n_pairs > 0) m = m/n_pairs
  end subroutine relax

  !> Move each particle without contact (a rattler) straight towards its
  !> nearest neighbour (smallest gap) until they overlap by packing_overlap of
  !> their mean radius. Other gaps were at least as large, so no new overlap
  !> exceeds that.
  subroutine attach_rattlers(work)
    type(scene_type), intent(inout) :: work
    type(scene_type) :: probe
    type(search_type) :: s
    integer, allocatable :: contacts(:), partner(:)
    real(dp), allocatable :: best(:)
    real(dp) :: h, d(3), gap, dist
    integer :: k, i, j, a, pass
    call wrap_positions(work)
    call prepare_search(work, s)
    call find_contacts(work, s)
    allocate(contacts(work%n), source=0)
    do k = 1, s%n_pairs
      contacts(s%pair_i(k)) = contacts(s%pair_i(k)) + 1
      contacts(s%pair_j(k)) = contacts(s%pair_j(k)) + 1
    end do
    if (all(contacts > 0)) return
    ! candidates: the rattlers' radii grown by 2h find the neighbours within gap 2h
    allocate(partner(work%n), best(work%n))
    partner = 0
    best = huge(1.0_dp)
    h = 0.25_dp
    do pass = 1, 6
      probe = work
      where (contacts == 0) probe%radius = probe%radius + 2.0_dp*h
      call prepare_search(probe, s)
      call find_contacts(probe, s)
      do k = 1, s%n_pairs
        do a = 1, 2
          i = merge(s%pair_i(k), s%pair_j(k), a == 1)
          j = merge(s%pair_j(k), s%pair_i(k), a == 1)
          if (contacts(i) > 0) cycle
          gap = s%pair_l(k) - work%radius(i) - work%radius(j)
          if (gap < best(i)) then
            best(i) = gap
            partner(i) = j
          end if
        end do
      end do
      if (all(contacts > 0 .or. partner > 0)) exit
      h = 2.0_dp*h
    end do
    do i = 1, work%n
      if (contacts(i) > 0 .or. partner(i) == 0) cycle
      j = partner(i)
      d = branch_vector(work, i, j)
      dist = norm2(d)
      gap = dist - work%radius(i) - work%radius(j)
      work%x(:, i) = work%x(:, i) + (gap + packing_overlap*0.5_dp*(work%radius(i) + work%radius(j)))*d/dist
      contacts(i) = contacts(i) + 1
      contacts(j) = contacts(j) + 1
    end do
  end subroutine attach_rattlers

  !> MINSTD (Park and Miller, multiplier 48271) uniform in (0, 1): exact in
  !> 64-bit integers, so the same sequence with every compiler.
  pure subroutine next_uniform(state, u)
    integer(i8), intent(inout) :: state
    real(dp), intent(out) :: u
    state = mod(48271_i8*state, 2147483647_i8)
    u = real(state, dp)/2147483647.0_dp
  end subroutine next_uniform

  !> Repeat a periodic scene reps(ax) times along each axis: copy t = (a, b, c)
  !> (0-based) holds particles t_index n + 1 .. (t_index + 1) n, t_index = a +
  !> reps(1) (b + reps(2) c), shifted by (a, b, c) cell lengths; radii, masses,
  !> inertia, velocities, fixed flags and types are repeated, the law, materials,
  !> effects and walls kept; bonds and explicit contacts are repeated with each
  !> partner taken in the copy its nearest image lies in. The cell grows to
  !> cell_lo + reps (cell_hi - cell_lo). O(particles + bonds + contacts out).
  !> Status `invalid_input`: `reps:` below 1, above 1 along an axis that is not
  !> periodic, or more than 2147483647 particles out; `n:` an empty scene.
  subroutine tile_scene(scene, reps, tiled, status)
    type(scene_type), intent(in) :: scene
    integer, intent(in) :: reps(3)
    type(scene_type), intent(out) :: tiled
    type(demstep_status_type), intent(out) :: status
    real(dp) :: box(3), shift(3)
    integer :: ax, n, copies, t, a, b, c, lo, k
    if (any(reps < 1)) then
      call set_status(status, demstep_stat%invalid_input, "reps: must be >= 1 along every axis")
      return
    end if
    do ax = 1, 3
      if (reps(ax) > 1 .and. .not. scene%periodic(ax)) then
        call set_status(status, demstep_stat%invalid_input, "reps: axis "//int_text(ax)//" is not " &
          //"periodic: only a periodic cell can be repeated along it")
        return
      end if
    end do
    n = scene%n
    if (n < 1) then
      call set_status(status, demstep_stat%invalid_input, "n: the scene has no particles")
      return
    end if
    if (real(n, dp)*real(reps(1), dp)*real(reps(2), dp)*real(reps(3), dp) > real(huge(1), dp)) then
      call set_status(status, demstep_stat%invalid_input, "reps: the tiled scene would hold more " &
        //"than 2147483647 particles")
      return
    end if
    if ((real(size(scene%bonds, 2), dp) + real(size(scene%contact_pairs, 2), dp)) &
        *real(reps(1), dp)*real(reps(2), dp)*real(reps(3), dp) > real(huge(1), dp)) then
      call set_status(status, demstep_stat%invalid_input, "reps: the tiled scene would hold more " &
        //"than 2147483647 bonds or contacts")
      return
    end if
    copies = product(reps)
    box = scene%cell_hi - scene%cell_lo
    tiled = scene
    tiled%n = n*copies
    deallocate(tiled%x, tiled%v, tiled%w, tiled%mass, tiled%radius, tiled%inertia, tiled%fixed)
    allocate(tiled%x(3, tiled%n), tiled%v(3, tiled%n), tiled%w(3, tiled%n), tiled%mass(tiled%n), &
      tiled%radius(tiled%n), tiled%inertia(tiled%n), tiled%fixed(tiled%n))
    if (allocated(scene%ptype)) then
      deallocate(tiled%ptype)
      allocate(tiled%ptype(tiled%n))
    end if
    do t = 0, copies - 1
      call copy_index(t, reps, a, b, c)
      shift = 0.0_dp
      where (scene%periodic) shift = [a, b, c]*box
      lo = t*n
      do k = 1, n
        tiled%x(:, lo + k) = scene%x(:, k) + shift
      end do
      tiled%v(:, lo + 1:lo + n) = scene%v
      tiled%w(:, lo + 1:lo + n) = scene%w
      tiled%mass(lo + 1:lo + n) = scene%mass
      tiled%radius(lo + 1:lo + n) = scene%radius
      tiled%inertia(lo + 1:lo + n) = scene%inertia
      tiled%fixed(lo + 1:lo + n) = scene%fixed
      if (allocated(scene%ptype)) tiled%ptype(lo + 1:lo + n) = scene%ptype
    end do
    where (scene%periodic) tiled%cell_hi = scene%cell_lo + reps*box
    call tile_pairs(scene, reps, scene%bonds, tiled%bonds)
    deallocate(tiled%bond_rest, tiled%bond_normal)
    allocate(tiled%bond_rest(3, size(tiled%bonds, 2)), tiled%bond_normal(3, size(tiled%bonds, 2)))
    k = size(scene%bonds, 2)
    do t = 0, copies - 1
      tiled%bond_rest(:, t*k + 1:(t + 1)*k) = scene%bond_rest
      tiled%bond_normal(:, t*k + 1:(t + 1)*k) = scene%bond_normal
    end do
    call tile_pairs(scene, reps, scene%contact_pairs, tiled%contact_pairs)
    deallocate(tiled%contact_k)
    k = size(scene%contact_pairs, 2)
    allocate(tiled%contact_k(8, k*copies))
    do t = 0, copies - 1
      tiled%contact_k(:, t*k + 1:(t + 1)*k) = scene%contact_k
    end do
    status%stat = demstep_stat%ok
  end subroutine tile_scene

  !> The copy (a, b, c) of copy number t (0-based, a fastest).
  pure subroutine copy_index(t, reps, a, b, c)
    integer, intent(in) :: t, reps(3)
    integer, intent(out) :: a, b, c
    a = mod(t, reps(1))
    b = mod(t/reps(1), reps(2))
    c = t/(reps(1)*reps(2))
  end subroutine copy_index

  !> Pairs (2, m) of particle numbers repeated in every copy; the second of a
  !> pair is taken in the copy its nearest image (from the first) lies in.
  subroutine tile_pairs(scene, reps, pairs, tiled)
    type(scene_type), intent(in) :: scene
    integer, intent(in) :: reps(3), pairs(:, :)
    integer, allocatable, intent(out) :: tiled(:, :)
    integer :: m, t, k, abc(3), image(3), partner(3), i, j
    real(dp) :: box(3), d(3), raw(3)
    m = size(pairs, 2)
    allocate(tiled(2, m*product(reps)))
    box = scene%cell_hi - scene%cell_lo
    do k = 1, m
      i = pairs(1, k)
      j = pairs(2, k)
      d = branch_vector(scene, i, j)
      raw = scene%x(:, j) - scene%x(:, i)
      image = 0
      where (scene%periodic) image = nint((d - raw)/box)
      do t = 0, product(reps) - 1
        call copy_index(t, reps, abc(1), abc(2), abc(3))
        partner = modulo(abc + image, reps)
        tiled(:, t*m + k) = [t*scene%n + i, &
          (partner(1) + reps(1)*(partner(2) + reps(2)*partner(3)))*scene%n + j]
      end do
    end do
  end subroutine tile_pairs

end module demstep_scene_builders
