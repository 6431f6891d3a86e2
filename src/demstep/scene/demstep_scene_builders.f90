!> Scene builders: a scene from particle arrays, its bonds, walls, explicit
!> contact list and periodic cell, each checked on the way in; and a ready
!> cubic lattice for tests and benchmarks.
module demstep_scene_builders
  use demstep_kinds, only: dp, i8
  use demstep_status, only: demstep_status_type, demstep_stat, set_status
  use demstep_text, only: int_text, real_text
  use demstep_scene_data, only: scene_type, scene_effect, branch_vector, scene_effect_from_name, n_effects, &
    max_damping_ratio, wrap_positions
  use demstep_interaction, only: hertz_e_star, mindlin_g_star, contact_law
  use demstep_neighbours, only: search_type, prepare_search, find_contacts, search_trouble
  use, intrinsic :: ieee_arithmetic, only: ieee_is_finite
  implicit none
  private

  public :: new_scene, scene_add_bonds, scene_add_walls, scene_set_contacts, contact_rows_check, scene_set_cell, &
    scene_set_types, scene_set_hertz_types, scene_set_law, scene_set_bond_stiffness, scene_set_gravity, &
    scene_set_damping, scene_set_friction, scene_set_local_damping, scene_set_rolling, scene_set_effects, &
    cubic_lattice

  !> Largest |coordinate| and radius of a scene: squared distances stay finite.
  real(dp), parameter, public :: max_coordinate = 1.0e150_dp
  !> Rows (particles, contacts) from which the builders' checks and copies run
  !> in parallel (the results do not depend on it).
  integer, parameter, public :: parallel_rows = 65536

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
  subroutine new_scene(scene, dim, x, mass, radius, status, v, fixed, inertia, search, first_number)
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
    !> The number of particle 1 in messages and `status%index` (default 1:
    !> a caller holding one part of a larger scene gives its first particle's).
    integer, intent(in), optional :: first_number
    integer :: n, i, k, bad
    scene%gravity = 0.0_dp
    if (dim < 1 .or. dim > 3) then
      call set_status(status, demstep_stat%invalid_input, "must be 1, 2 or 3", where="dim")
      return
    end if
    n = size(mass)
    if (size(x, 1) /= dim .or. size(x, 2) /= n .or. size(radius) /= n) then
      call set_status(status, demstep_stat%invalid_input, "positions, masses and radii " &
        //"must describe the same particles", where="position")
      return
    end if
    ! (the particles checked in parallel: the first faulty one in order)
    bad = huge(bad)
    !$omp parallel do private(i) reduction(min:bad) schedule(static) if(n >= parallel_rows)
    do i = 1, n
      if (particle_fault(mass(i), radius(i), x(:, i)) /= 0) bad = min(bad, i)
    end do
    !$omp end parallel do
    if (bad <= n) then
      i = bad
      k = i
      if (present(first_number)) k = first_number + i - 1
      select case (particle_fault(mass(i), radius(i), x(:, i)))
      case (1)
        call set_status(status, demstep_stat%invalid_input, "particle "//int_text(k)//": must be > 0", &
          where="mass", index=k)
      case (2)
        call set_status(status, demstep_stat%invalid_input, "particle "//int_text(k)//": must be " &
          //"at least 5.6e-309 (1/mass must be finite)", where="mass", index=k)
      case (3)
        call set_status(status, demstep_stat%invalid_input, "particle "//int_text(k)//": must be > 0", &
          where="radius", index=k)
      case (4)
        call set_status(status, demstep_stat%invalid_input, "particle "//int_text(k)//": must be " &
          //"at most 1e150 (squared distances must be representable)", where="radius", index=k)
      case (5)
        call set_status(status, demstep_stat%invalid_input, "particle "//int_text(k)//" is not finite", &
          where="position", index=k)
      case default
        call set_status(status, demstep_stat%invalid_input, "particle "//int_text(k)//": every " &
          //"coordinate must be within +-1e150 (squared distances must be representable)", &
          where="position", index=k)
      end select
      return
    end if
    scene%dim = dim
    scene%n = n
    if (present(inertia)) then
      if (size(inertia) /= n) then
        call set_status(status, demstep_stat%invalid_input, "one per particle", where="inertia")
        return
      end if
      bad = huge(bad)
      !$omp parallel do private(i) reduction(min:bad) schedule(static) if(n >= parallel_rows)
      do i = 1, n
        if (.not. (ieee_is_finite(inertia(i)) .and. inertia(i) > 0.0_dp)) bad = min(bad, i)
      end do
      !$omp end parallel do
      if (bad <= n) then
        k = bad
        if (present(first_number)) k = first_number + bad - 1
        call set_status(status, demstep_stat%invalid_input, "particle "//int_text(k)// &
          ": must be > 0 and finite", where="inertia", index=k)
        return
      end if
    end if
    if (present(v)) then
      if (size(v, 1) /= dim .or. size(v, 2) /= n .or. .not. all(ieee_is_finite(v))) then
        call set_status(status, demstep_stat%invalid_input, "must be finite, one per particle", where="velocity")
        return
      end if
    end if
    if (present(fixed)) then
      if (size(fixed) /= n) then
        call set_status(status, demstep_stat%invalid_input, "one fixed flag per particle", where="fixed")
        return
      end if
    end if
    allocate(scene%x(3, n), scene%v(3, n), scene%w(3, n), scene%mass(n), scene%radius(n), scene%inertia(n), &
      scene%fixed(n))
    ! (one pass in parallel: each thread touches its own pages first)
    !$omp parallel do private(i) schedule(static) if(n >= parallel_rows)
    do i = 1, n
      scene%x(:, i) = 0.0_dp
      scene%x(:dim, i) = x(:, i)
      scene%mass(i) = mass(i)
      scene%radius(i) = radius(i)
      if (present(inertia)) then
        scene%inertia(i) = inertia(i)
      else
        ! 2/5 m r^2, saturated (only rotations use it)
        scene%inertia(i) = min(0.4_dp*mass(i)*radius(i), huge(1.0_dp)/max(1.0_dp, radius(i)))*radius(i)
      end if
      scene%fixed(i) = .false.
      if (present(fixed)) scene%fixed(i) = fixed(i)
      scene%v(:, i) = 0.0_dp
      ! (a fixed particle does not move)
      if (present(v) .and. .not. scene%fixed(i)) scene%v(:dim, i) = v(:, i)
      scene%w(:, i) = 0.0_dp
    end do
    !$omp end parallel do
    allocate(scene%bonds(2, 0), scene%bond_rest(3, 0), scene%bond_normal(3, 0), &
      scene%wall_point(3, 0), scene%wall_normal(3, 0), scene%contact_pairs(2, 0), scene%contact_k(8, 0))
    status%stat = demstep_stat%ok
    if (present(search)) then
      if (.not. search) return
    end if
    call check_contacts(scene, status)
  end subroutine new_scene

  !> What is wrong with one particle for `new_scene` (the first fault in this
  !> order): 0 nothing, 1 mass not finite and > 0, 2 1/mass not finite, 3
  !> radius not finite and > 0, 4 radius above `max_coordinate`, 5 a position
  !> not finite, 6 a coordinate beyond +-`max_coordinate`.
  pure integer function particle_fault(mass, radius, x) result(fault)
    real(dp), intent(in) :: mass, radius, x(:)
    if (.not. (ieee_is_finite(mass) .and. mass > 0.0_dp)) then
      fault = 1
    else if (.not. ieee_is_finite(1.0_dp/mass)) then
      fault = 2
    else if (.not. (ieee_is_finite(radius) .and. radius > 0.0_dp)) then
      fault = 3
    else if (radius > max_coordinate) then
      fault = 4
    else if (.not. all(ieee_is_finite(x))) then
      fault = 5
    else if (any(abs(x) > max_coordinate)) then
      fault = 6
    else
      fault = 0
    end if
  end function particle_fault

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
        call set_status(status, demstep_stat%invalid_input, "fixed particles "// &
          int_text(s%pair_i(i))//" and "//int_text(s%pair_j(i))//" overlap", where="position")
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
      call set_status(status, demstep_stat%invalid_input, "only the first dim axes can be periodic", where="periodic")
      return
    end if
    longest = 2.0_dp*maxval(scene%radius)
    if (size(scene%bonds, 2) > 0) longest = max(longest, maxval(norm2(scene%bond_rest, dim=1)))
    do ax = 1, 3
      if (.not. (ieee_is_finite(lo(ax)) .and. ieee_is_finite(hi(ax)) .and. &
          abs(lo(ax)) <= max_coordinate .and. abs(hi(ax)) <= max_coordinate)) then
        call set_status(status, demstep_stat%invalid_input, "axis "//int_text(ax)//": cell_lo " &
          //"and cell_hi must be finite within +-1e150", where="cell_hi", index=int(ax))
        return
      end if
      if (.not. periodic(ax)) cycle
      if (.not. hi(ax) - lo(ax) > 0.0_dp) then
        call set_status(status, demstep_stat%invalid_input, "axis "//int_text(ax)//": cell_hi " &
          //"must be above cell_lo", where="cell_hi", index=int(ax))
        return
      end if
      if (hi(ax) - lo(ax) < 2.0_dp*longest) then
        call set_status(status, demstep_stat%invalid_input, "axis "//int_text(ax)//": the " &
          //"periodic cell must be at least twice the longest contact or bond ("// &
          real_text(2.0_dp*longest, 6)//") long", where="cell_hi", index=int(ax))
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
    integer :: c, m, nc
    logical :: turning
    call contact_rows_check(scene%n, pairs, k, status)
    if (status%stat /= demstep_stat%ok) return
    m = size(k, 1)
    nc = size(pairs, 2)
    if (allocated(scene%contact_pairs)) deallocate(scene%contact_pairs)
    if (allocated(scene%contact_k)) deallocate(scene%contact_k)
    allocate(scene%contact_pairs(2, nc), scene%contact_k(8, nc))
    ! (copied in parallel: each thread touches its own pages first)
    turning = .false.
    !$omp parallel do private(c) reduction(.or.:turning) schedule(static) if(nc >= parallel_rows)
    do c = 1, nc
      scene%contact_pairs(:, c) = pairs(:, c)
      scene%contact_k(:m, c) = k(:, c)
      scene%contact_k(m+1:, c) = 0.0_dp
      turning = turning .or. any(scene%contact_k(2:4, c) > 0.0_dp)
    end do
    !$omp end parallel do
    scene%given_dashpots = m == 8
    scene%given_contacts = .true.
    if (turning) scene%effects(scene_effect%rotation) = .true.
    status%stat = demstep_stat%ok
  end subroutine scene_set_contacts

  !> The checks of `scene_set_contacts` on an explicit contact list for a
  !> scene of n particles (the same statuses), without the scene. The rows
  !> are checked in parallel; the first faulty one in list order is named.
  subroutine contact_rows_check(n, pairs, k, status)
    integer, intent(in) :: n
    integer, intent(in) :: pairs(:, :)
    real(dp), intent(in) :: k(:, :)
    type(demstep_status_type), intent(out) :: status
    character(len=*), parameter :: names(8) = [character(len=3) :: "k_n", "k_t", "k_r", "k_w", &
      "c_n", "c_t", "c_r", "c_w"]
    integer :: c, m, q, nc, bad
    m = size(k, 1)
    nc = size(pairs, 2)
    if (size(pairs, 1) /= 2 .or. .not. (m == 2 .or. m == 4 .or. m == 8) .or. size(k, 2) /= nc) then
      call set_status(status, demstep_stat%invalid_input, "each contact is two particle " &
        //"numbers and 2, 4 or 8 values (k_n, k_t, k_r, k_w, c_n, c_t, c_r, c_w)", where="contacts")
      return
    end if
    bad = huge(bad)
    !$omp parallel do private(c) reduction(min:bad) schedule(static) if(nc >= parallel_rows)
    do c = 1, nc
      if (contact_fault(pairs(:, c), k(:, c), n) /= 0) bad = min(bad, c)
    end do
    !$omp end parallel do
    if (bad <= nc) then
      c = bad
      q = contact_fault(pairs(:, c), k(:, c), n)
      if (q == -2) then
        call set_status(status, demstep_stat%invalid_input, "names a " &
          //"missing particle ("//int_text(pairs(1, c))//", "//int_text(pairs(2, c))//"; there are " &
          //int_text(n)//")", where="contacts", index=int(c), subscript=.true.)
      else if (q == -1) then
        call set_status(status, demstep_stat%invalid_input, "pairs " &
          //"particle "//int_text(pairs(1, c))//" with itself", where="contacts", index=int(c), subscript=.true.)
      else if (q == 1) then
        call set_status(status, demstep_stat%invalid_input, "k_n " &
          //"must be > 0 and finite", where="contacts", index=int(c), subscript=.true.)
      else
        call set_status(status, demstep_stat%invalid_input, trim(names(q)) &
          //" must be >= 0 and finite", where="contacts", index=int(c), subscript=.true.)
      end if
      return
    end if
    status%stat = demstep_stat%ok
  end subroutine contact_rows_check

  !> What is wrong with one row of an explicit contact list (`scene_set_contacts`)
  !> of particles 1 to n: 0 nothing, -2 a missing particle, -1 a particle paired
  !> with itself, q > 0 the value k(q) (k_n must be > 0, the others >= 0, all
  !> finite).
  pure integer function contact_fault(pair, k, n) result(fault)
    integer, intent(in) :: pair(2), n
    real(dp), intent(in) :: k(:)
    integer :: q
    fault = 0
    if (any(pair < 1) .or. any(pair > n)) then
      fault = -2
    else if (pair(1) == pair(2)) then
      fault = -1
    else if (.not. (ieee_is_finite(k(1)) .and. k(1) > 0.0_dp)) then
      fault = 1
    else
      do q = 2, size(k)
        if (.not. (ieee_is_finite(k(q)) .and. k(q) >= 0.0_dp)) then
          fault = q
          return
        end if
      end do
    end if
  end function contact_fault

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
      call set_status(status, demstep_stat%invalid_input, "one value per type pair", where="type_k_normal")
      return
    end if
    if (.not. all(ieee_is_finite(k(1, :, :)) .and. k(1, :, :) > 0.0_dp)) then
      call set_status(status, demstep_stat%invalid_input, "must be > 0 and finite", where="type_k_normal")
      return
    end if
    if (.not. all(ieee_is_finite(k(2, :, :)) .and. k(2, :, :) >= 0.0_dp)) then
      call set_status(status, demstep_stat%invalid_input, "must be >= 0 and finite", where="type_k_tangential")
      return
    end if
    if (any(k(1, :, :) /= transpose(k(1, :, :)))) then
      call set_status(status, demstep_stat%invalid_input, "must be symmetric (a-b as b-a)", where="type_k_normal")
      return
    end if
    if (any(k(2, :, :) /= transpose(k(2, :, :)))) then
      call set_status(status, demstep_stat%invalid_input, "must be symmetric (a-b as b-a)", where="type_k_tangential")
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
      call set_status(status, demstep_stat%invalid_input, "one per type, as young", where="poisson")
      return
    end if
    if (.not. all(ieee_is_finite(young) .and. young > 0.0_dp)) then
      call set_status(status, demstep_stat%invalid_input, "must be > 0 and finite", where="young")
      return
    end if
    if (.not. all(poisson > -1.0_dp .and. poisson <= 0.5_dp)) then
      call set_status(status, demstep_stat%invalid_input, "must be in (-1, 0.5]", where="poisson")
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
    scene%hooke_per_contact = .false.
  end subroutine clear_types

  !> One type in 1 to nt per particle.
  subroutine check_types(scene, types, nt, status)
    type(scene_type), intent(in) :: scene
    integer, intent(in) :: types(:), nt
    type(demstep_status_type), intent(out) :: status
    integer :: i
    if (size(types) /= scene%n .or. nt < 1) then
      call set_status(status, demstep_stat%invalid_input, "one type per particle ("// &
        int_text(scene%n)//"), and at least one material", where="types")
      return
    end if
    do i = 1, scene%n
      if (types(i) < 1 .or. types(i) > nt) then
        call set_status(status, demstep_stat%invalid_input, "particle "//int_text(i)//": type "// &
          int_text(types(i))//" is not one of the "//int_text(nt)//" materials", where="types", index=int(i))
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
          //"particle ("//int_text(pairs(1, k))//", "//int_text(pairs(2, k))//")", where="bonds", index=k)
        return
      end if
      if (pairs(1, k) == pairs(2, k)) then
        call set_status(status, demstep_stat%invalid_input, "bond "//int_text(k)//" joins particle " &
          //int_text(pairs(1, k))//" to itself", where="bonds", index=k)
        return
      end if
      bonds(:, nb0 + k) = pairs(:, k)
      rest(:, nb0 + k) = branch_vector(scene, pairs(1, k), pairs(2, k))
      if (.not. norm2(rest(:, nb0 + k)) > 0.0_dp) then
        call set_status(status, demstep_stat%invalid_input, "bond "//int_text(k)//" joins particles " &
          //"at the same position", where="bonds", index=k)
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
      call set_status(status, demstep_stat%invalid_input, int_text(law)//" is not a contact " &
        //"law (linear "//int_text(contact_law%linear)//", hertz "//int_text(contact_law%hertz)//")", where="law")
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
      call set_status(status, demstep_stat%invalid_input, "must be > 0 and finite", where="k_bond")
      return
    end if
    if (.not. (ieee_is_finite(k_bond_tangential) .and. k_bond_tangential >= 0.0_dp)) then
      call set_status(status, demstep_stat%invalid_input, "must be >= 0 and finite", where="k_bond_tangential")
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
      call set_status(status, demstep_stat%invalid_input, "needs "//int_text(scene%dim)// &
        " finite components", where="gravity")
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
      call set_status(status, demstep_stat%invalid_input, "must be in [0, 1e100]", where="damping_ratio")
    else if (.not. damping_ratio_ok(zt)) then
      call set_status(status, demstep_stat%invalid_input, "must be in [0, 1e100]", where="damping_ratio_tangential")
    else if (.not. damping_ratio_ok(zr)) then
      call set_status(status, demstep_stat%invalid_input, "must be in [0, 1e100]", where="damping_ratio_rolling")
    else if (.not. (ieee_is_finite(g) .and. g >= 0.0_dp)) then
      call set_status(status, demstep_stat%invalid_input, "must be >= 0 and finite", where="drag")
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
      call set_status(status, demstep_stat%invalid_input, "must be finite", where="friction")
      return
    end if
    if (present(rolling_friction)) then
      if (.not. ieee_is_finite(rolling_friction)) then
        call set_status(status, demstep_stat%invalid_input, "must be finite", where="rolling_friction")
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
      call set_status(status, demstep_stat%invalid_input, "must be in [0, 1)", where="local_damping")
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
      call set_status(status, demstep_stat%invalid_input, "must be >= 0 and finite", where="rolling_ratio")
      return
    end if
    if (.not. (ieee_is_finite(twisting_ratio) .and. twisting_ratio >= 0.0_dp)) then
      call set_status(status, demstep_stat%invalid_input, "must be >= 0 and finite", where="twisting_ratio")
      return
    end if
    scene%rolling_ratio = rolling_ratio
    scene%twisting_ratio = twisting_ratio
    if (rolling_ratio > 0.0_dp .or. twisting_ratio > 0.0_dp) scene%effects(scene_effect%rotation) = .true.
    status%stat = demstep_stat%ok
  end subroutine scene_set_rolling

  !> Switch effects on or off by name (`scene_effect_names`: 'contacts', 'gravity',
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
      call set_status(status, demstep_stat%invalid_input, "one on/off flag per name", where="effects")
      return
    end if
    effects = scene%effects
    do k = 1, size(names)
      e = scene_effect_from_name(trim(names(k)))
      if (e == 0) then
        call set_status(status, demstep_stat%invalid_input, "'"//trim(names(k))//"' is not " &
          //"an effect", where="effects")
        return
      end if
      effects(e) = on(k)
    end do
    scene%effects = effects
    status%stat = demstep_stat%ok
  end subroutine scene_set_effects

end module demstep_scene_builders
