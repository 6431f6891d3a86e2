!> Particle scenes: spheres in 1, 2 or 3 dimensions with compression-only normal
!> contacts (with each other and with planar walls) and bonds, stepped with the
!> central-difference (leapfrog / velocity-Verlet) scheme.
!>
!> Physics on demand: the effects a scene switches on (`contacts`, `gravity`,
!> viscous `damping`, `local_damping`, `walls`) each become one force term of the
!> stepper, assembled once by `scene_run`; nothing in the step loop tests which
!> effects are on. Bonds are always on (a scene without bonds has none).
!>
!> Conventions:
!> - leapfrog: x_{n} = x_{n-1} + v_{n-1/2} dt, forces at x_n, v_{n+1/2} = v_{n-1/2} + F/m dt;
!> - contacts: overlap d = r_i + r_j - |x_i - x_j| > 0; linear law F = k d, Hertz
!>   F = (4/3) E* sqrt(R*) d^(3/2) with R* = r_i r_j/(r_i + r_j) (a wall: R* = r);
!> - bonds: linear about the initial configuration (small strain), normal stiffness
!>   k_n along the initial direction and optional tangential stiffness k_t;
!> - viscous damping: a dashpot c = 2 zeta sqrt(m* k) on every contact, wall contact
!>   and bond (normal direction), k the tangent stiffness, acting on the relative
!>   normal velocity of the previous half step v_{n-1/2} (the only one available
!>   in an explicit step: this lags the force and lowers the stability limit to
!>   (2/omega)(sqrt(1 + zeta^2) - zeta));
!> - local (Cundall) damping: F <- F - alpha |F| sign(v_{n-1/2}) per component.
!>
!> Storage is 3D whatever `dim` is: the coordinates beyond `dim` are zero and stay
!> zero, so every kernel works on fixed-size vectors.
module demstep_scene
  use demstep_kinds, only: dp, i8, pi
  use demstep_status, only: demstep_status_type, demstep_stat, set_status
  use demstep_text, only: int_text
  use demstep_progress, only: progress_type
  use, intrinsic :: ieee_arithmetic, only: ieee_is_finite
  implicit none
  private

  public :: effective_mass, tangent_stiffness
  public :: cubic_lattice, new_scene, scene_add_bonds, scene_add_walls, scene_run, contact_list, &
    effect_index, restitution_to_damping_ratio

  !> Contact laws.
  integer, parameter, public :: law_linear = 1, law_hertz = 2
  !> Effects, by index into `scene_type`%effects.
  integer, parameter, public :: effect_contacts = 1, effect_gravity = 2, effect_damping = 3, &
    effect_local_damping = 4, effect_walls = 5, n_effects = 5
  !> Their names, as the namelist input spells them.
  character(len=*), parameter, public :: effect_names(n_effects) = [character(len=13) :: &
    "contacts", "gravity", "damping", "local_damping", "walls"]

  !> A scene: particles, contact law, bonds, walls and effects.
  type, public :: scene_type
    !> Dimension, 1 to 3.
    integer :: dim = 3
    !> Number of particles.
    integer :: n = 0
    !> Positions and velocities (3, n), zero beyond dim; velocities are half-step
    !> velocities.
    real(dp), allocatable :: x(:, :), v(:, :)
    !> Masses and radii (> 0).
    real(dp), allocatable :: mass(:), radius(:)
    !> Fixed particles neither move nor count as degrees of freedom.
    logical, allocatable :: fixed(:)
    !> `law_linear` (stiffness k_normal) or `law_hertz` (modulus e_star).
    integer :: law = law_linear
    real(dp) :: k_normal = 0.0_dp, e_star = 0.0_dp
    !> Bonds (2, nb): particle pairs; rest(3, nb) = initial x_j - x_i and its
    !> unit vector bond_normal(3, nb).
    integer, allocatable :: bonds(:, :)
    real(dp), allocatable :: bond_rest(:, :), bond_normal(:, :)
    !> Bond stiffness, normal and tangential.
    real(dp) :: k_bond = 0.0_dp, k_bond_tangential = 0.0_dp
    !> Walls: a point and the unit normal pointing into the domain (3, nw).
    real(dp), allocatable :: wall_point(:, :), wall_normal(:, :)
    !> Effects switched on (indexed by effect_*).
    logical :: effects(n_effects) = [.true., .false., .false., .false., .false.]
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

  !> Scratch of a run: forces, inverse masses, contact lists, cell list.
  type :: work_type
    real(dp), allocatable :: f(:, :), inv_mass(:), v_old(:, :)
    integer :: n_pairs = 0, n_walls = 0
    integer, allocatable :: pair_i(:), pair_j(:), wall_i(:), wall_k(:)
    real(dp), allocatable :: pair_n(:, :), pair_d(:), wall_d(:)
    integer, allocatable :: cell_start(:), cell_particle(:), cell_of(:)
    real(dp) :: max_overlap = 0.0_dp
    integer :: max_contacts = 0
    !> Cell width before coarsening: twice the largest radius of a non-giant.
    real(dp) :: cell_width = 0.0_dp
    !> Giants: particles searched against all others, not put into cells.
    integer, allocatable :: giants(:)
    logical, allocatable :: is_giant(:)
    !> The first pair found at the same point, and whether contact_limit was hit.
    integer :: coincident(2) = 0
    logical :: too_many = .false.
  end type work_type

  abstract interface
    !> One force term: adds its forces to work%f.
    subroutine force_term(scene, work)
      import :: scene_type, work_type
      type(scene_type), intent(in) :: scene
      type(work_type), intent(inout) :: work
    end subroutine force_term
  end interface

  type :: term_type
    procedure(force_term), pointer, nopass :: add => null()
  end type term_type

  !> Energy growth that counts as blowing up.
  real(dp), parameter :: blow_up_factor = 1.0e6_dp
  !> Largest |coordinate| and radius of a scene: squared distances stay finite.
  real(dp), parameter, public :: max_coordinate = 1.0e150_dp
  !> Most particle contacts a scene may have at once (about 1 GB of contact data
  !> in the analysis; a DEM packing has a few per particle).
  integer, parameter, public :: contact_limit = 10000000
  !> Largest viscous damping ratio: the damped limit, about dt/(2 zeta), stays a
  !> normal number for every dt above 1e-200.
  real(dp), parameter, public :: max_damping_ratio = 1.0e100_dp
  !> At most this many of the largest particles are searched against every
  !> particle instead of sizing the cells (a few giants must not put every
  !> particle into one cell).
  integer, parameter :: n_giants = 16

contains

  !> Build a scene from particle arrays. Status `invalid_input` names the first
  !> bad value, its message starting with the variable (`mass:`, `radius:`,
  !> `position:`, `velocity:`, `fixed:`): non-positive or too small mass (1/m must
  !> be finite), radius or coordinates beyond `max_coordinate`, wrong sizes,
  !> non-finite values, two particles at the same point (their contact normal is
  !> undefined), overlapping fixed particles, more than `contact_limit` contacts.
  subroutine new_scene(scene, dim, x, mass, radius, status, v, fixed)
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
    integer :: n, i
    type(work_type) :: work
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
    allocate(scene%v(3, n), source=0.0_dp)
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
      scene%wall_point(3, 0), scene%wall_normal(3, 0))
    call prepare(scene, work)
    call find_contacts(scene, work)
    call contact_trouble(work, status)
    if (status%stat /= demstep_stat%ok) return
    ! two fixed particles may not overlap: their contact could never resolve
    do i = 1, work%n_pairs
      if (scene%fixed(work%pair_i(i)) .and. scene%fixed(work%pair_j(i))) then
        call set_status(status, demstep_stat%invalid_input, "position: fixed particles "// &
          int_text(work%pair_i(i))//" and "//int_text(work%pair_j(i))//" overlap")
        return
      end if
    end do
    status%stat = demstep_stat%ok
  end subroutine new_scene

  !> The contact search's refusals as a status: coincident particles, too many contacts.
  subroutine contact_trouble(work, status)
    type(work_type), intent(in) :: work
    type(demstep_status_type), intent(out) :: status
    if (work%coincident(1) > 0) then
      call set_status(status, demstep_stat%invalid_input, "position: particles "// &
        int_text(work%coincident(1))//" and "//int_text(work%coincident(2))//" are at the same " &
        //"point (their contact normal is undefined)")
    else if (work%too_many) then
      call set_status(status, demstep_stat%invalid_input, "position: more than "// &
        int_text(contact_limit)//" particle contacts (the limit; the particles overlap far more than " &
        //"in a DEM packing)")
    else
      status%stat = demstep_stat%ok
    end if
  end subroutine contact_trouble

  !> The overlapping particle pairs of the current configuration: particles
  !> i(k) < j(k), unit normal n(:, k) from i to j, overlap d(k). Status (when
  !> present) `invalid_input` for coincident particles or more than
  !> `contact_limit` contacts (the lists then hold what was found).
  subroutine contact_list(scene, i, j, n, d, status)
    type(scene_type), intent(in) :: scene
    integer, allocatable, intent(out) :: i(:), j(:)
    real(dp), allocatable, intent(out) :: n(:, :), d(:)
    type(demstep_status_type), intent(out), optional :: status
    type(work_type) :: work
    call prepare(scene, work)
    call find_contacts(scene, work)
    i = work%pair_i(:work%n_pairs)
    j = work%pair_j(:work%n_pairs)
    n = work%pair_n(:, :work%n_pairs)
    d = work%pair_d(:work%n_pairs)
    if (present(status)) call contact_trouble(work, status)
  end subroutine contact_list

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
    scene%effects(effect_contacts) = .true.
  end subroutine cubic_lattice

  !> Add bonds between particle pairs (2, nb); rest vectors from the current positions.
  subroutine scene_add_bonds(scene, pairs, status)
    type(scene_type), intent(inout) :: scene
    integer, intent(in) :: pairs(:, :)
    type(demstep_status_type), intent(out) :: status
    integer :: k
    real(dp), allocatable :: rest(:, :)
    if (size(pairs, 1) /= 2) then
      call set_status(status, demstep_stat%invalid_input, "bonds are pairs of particle numbers")
      return
    end if
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
    end do
    rest = scene%x(:, pairs(2, :)) - scene%x(:, pairs(1, :))
    do k = 1, size(pairs, 2)
      if (.not. norm2(rest(:, k)) > 0.0_dp) then
        call set_status(status, demstep_stat%invalid_input, "bond "//int_text(k)//" joins particles " &
          //"at the same position")
        return
      end if
    end do
    scene%bonds = reshape([scene%bonds, pairs], [2, size(scene%bonds, 2) + size(pairs, 2)])
    scene%bond_rest = reshape([scene%bond_rest, rest], [3, size(scene%bonds, 2)])
    scene%bond_normal = reshape([scene%bond_normal, rest/spread(norm2(rest, dim=1), 1, 3)], &
      [3, size(scene%bonds, 2)])
    status%stat = demstep_stat%ok
  end subroutine scene_add_bonds

  !> Add walls: points (dim, nw) and normals (dim, nw) pointing into the domain.
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
    status%stat = demstep_stat%ok
  end subroutine scene_add_walls

  !> Index of an effect by name, 0 if unknown.
  pure integer function effect_index(name)
    character(len=*), intent(in) :: name
    do effect_index = 1, n_effects
      if (trim(effect_names(effect_index)) == name) return
    end do
    effect_index = 0
  end function effect_index

  !> Damping ratio of a linear spring-dashpot whose restitution coefficient is e:
  !> zeta = -ln e / sqrt(pi^2 + ln^2 e).
  elemental real(dp) function restitution_to_damping_ratio(e) result(zeta)
    real(dp), intent(in) :: e
    zeta = -log(e)/sqrt(pi**2 + log(e)**2)
  end function restitution_to_damping_ratio

  !> Step a scene `steps` times with time step dt, recording energy every
  !> `sample_every` steps (default: about 1000 samples). Status `blow_up` when the
  !> state became non-finite, the energy grew 1e6-fold or the contacts passed
  !> `contact_limit` (the summary says when); `invalid_input` for a bad dt or
  !> step count, a damping ratio above `max_damping_ratio`, or an initial energy
  !> that overflows. `progress` (optional) is told the steps done every few
  !> thousand particle-steps.
  subroutine scene_run(scene, dt, steps, summary, status, sample_every, progress)
    type(scene_type), intent(inout) :: scene
    real(dp), intent(in) :: dt
    integer(i8), intent(in) :: steps
    type(scene_summary_type), intent(out) :: summary
    type(demstep_status_type), intent(out) :: status
    integer(i8), intent(in), optional :: sample_every
    class(progress_type), intent(inout), optional :: progress
    type(term_type), allocatable :: terms(:)
    type(work_type) :: work
    integer(i8) :: step, every, report_every
    integer :: t, ns, i
    real(dp) :: e, scale
    if (.not. (ieee_is_finite(dt) .and. dt > 0.0_dp) .or. steps < 0_i8) then
      call set_status(status, demstep_stat%invalid_input, "dt must be > 0 and steps >= 0")
      return
    end if
    if (scene%effects(effect_damping) .and. .not. (scene%damping_ratio >= 0.0_dp .and. &
        scene%damping_ratio <= max_damping_ratio)) then
      call set_status(status, demstep_stat%invalid_input, "damping_ratio: must be in [0, 1e100]")
      return
    end if
    every = max(1_i8, steps/1000_i8)
    if (present(sample_every)) every = max(1_i8, sample_every)
    ! progress every 1e5 particle-steps or so: a clock read is then negligible
    report_every = max(1_i8, 100000_i8/max(1_i8, int(scene%n, i8)))
    call prepare(scene, work)
    terms = assemble(scene)
    allocate(summary%sample_time(steps/every + 2), summary%sample_energy(steps/every + 2))
    ! energy at the start: forces at x_0 give the first half-step pair v_{-1/2}, v_{1/2}
    summary%energy_initial = scene_energy(scene, work, terms, dt, advance=.false.)
    if (.not. ieee_is_finite(summary%energy_initial)) then
      call set_status(status, demstep_stat%invalid_input, "velocity: the initial energy (kinetic " &
        //"+ elastic + gravitational) overflows: velocities, masses, stiffness or overlaps too large")
      return
    end if
    ns = 1
    summary%sample_time(1) = 0.0_dp
    summary%sample_energy(1) = summary%energy_initial
    scale = max(abs(summary%energy_initial), tiny(1.0_dp))
    status%stat = demstep_stat%ok
    if (present(progress)) call progress%start("steps", steps)
    do step = 1_i8, steps
      scene%x = scene%x + scene%v*dt
      work%f = 0.0_dp
      if (mod(step, every) == 0_i8 .or. step == steps .or. work%too_many) then
        ! a sample: E = kinetic (v_{n-1/2} . v_{n+1/2}) + potential at x_n
        e = scene_energy(scene, work, terms, dt, advance=.true.)
        summary%steps = step
        if (ieee_is_finite(e)) then
          ns = ns + 1
          summary%sample_time(ns) = real(step, dp)*dt
          summary%sample_energy(ns) = e
          summary%energy_drift = max(summary%energy_drift, min(huge(1.0_dp), abs(e - summary%energy_initial)/scale))
        end if
        if (.not. (ieee_is_finite(e) .and. all(ieee_is_finite(scene%x))) .or. &
            abs(e - summary%energy_initial) > blow_up_factor*scale .or. work%too_many) then
          ! (a non-finite energy is not sampled: the drift stays finite)
          summary%blew_up = .true.
          if (work%too_many) then
            call set_status(status, demstep_stat%blow_up, "the scene blew up at step "// &
              int_text(step)//": more than "//int_text(contact_limit)//" contacts")
          else
            call set_status(status, demstep_stat%blow_up, "the scene blew up at step "// &
              int_text(step))
          end if
          exit
        end if
      else
        do t = 1, size(terms)
          call terms(t)%add(scene, work)
        end do
        do i = 1, scene%n
          scene%v(:, i) = scene%v(:, i) + work%f(:, i)*(work%inv_mass(i)*dt)
        end do
        summary%steps = step
      end if
      if (present(progress) .and. mod(step, report_every) == 0_i8) call progress%update(step)
    end do
    if (present(progress)) call progress%finish()
    summary%energy_final = summary%sample_energy(ns)
    summary%sample_time = summary%sample_time(:ns)
    summary%sample_energy = summary%sample_energy(:ns)
    summary%max_overlap = work%max_overlap
    summary%max_contacts = work%max_contacts
  end subroutine scene_run

  !> Total energy at the current positions: elastic + gravitational, and kinetic
  !> as the product of the half-step velocities around x_n (for the undamped
  !> linear scheme this energy is exactly conserved). With `advance` the velocity
  !> step is taken (scene%v holds v_{n-1/2} and becomes v_{n+1/2}); without, scene%v
  !> is taken as v_{1/2} at the start and v_{-1/2} is reconstructed.
  function scene_energy(scene, work, terms, dt, advance) result(energy)
    type(scene_type), intent(inout) :: scene
    type(work_type), intent(inout) :: work
    type(term_type), intent(in) :: terms(:)
    real(dp), intent(in) :: dt
    logical, intent(in) :: advance
    real(dp) :: energy, sgn
    integer :: t, i
    work%f = 0.0_dp
    do t = 1, size(terms)
      call terms(t)%add(scene, work)
    end do
    sgn = merge(1.0_dp, -1.0_dp, advance)
    do i = 1, scene%n
      work%v_old(:, i) = scene%v(:, i) + sgn*work%f(:, i)*(work%inv_mass(i)*dt)
    end do
    energy = 0.0_dp
    do i = 1, scene%n
      energy = energy + 0.5_dp*scene%mass(i)*dot_product(scene%v(:, i), work%v_old(:, i))
    end do
    energy = energy + potential_energy(scene, work)
    if (advance) scene%v = work%v_old
  end function scene_energy

  !> Elastic and gravitational energy at the current positions (contact lists current).
  function potential_energy(scene, work) result(u)
    type(scene_type), intent(in) :: scene
    type(work_type), intent(in) :: work
    real(dp) :: u, d(3), rs
    integer :: k, i, j
    u = 0.0_dp
    do k = 1, size(scene%bonds, 2)
      i = scene%bonds(1, k)
      j = scene%bonds(2, k)
      d = scene%x(:, j) - scene%x(:, i) - scene%bond_rest(:, k)
      u = u + 0.5_dp*bond_quadratic(scene, k, d)
    end do
    if (scene%effects(effect_contacts)) then
      do k = 1, work%n_pairs
        rs = scene%radius(work%pair_i(k))*scene%radius(work%pair_j(k)) &
          /(scene%radius(work%pair_i(k)) + scene%radius(work%pair_j(k)))
        u = u + contact_energy(scene, work%pair_d(k), rs)
      end do
    end if
    if (scene%effects(effect_walls)) then
      do k = 1, work%n_walls
        u = u + contact_energy(scene, work%wall_d(k), scene%radius(work%wall_i(k)))
      end do
    end if
    if (scene%effects(effect_gravity)) then
      do i = 1, scene%n
        if (.not. scene%fixed(i)) u = u - scene%mass(i)*dot_product(scene%gravity, scene%x(:, i))
      end do
    end if
  end function potential_energy

  pure real(dp) function contact_energy(scene, d, rs) result(u)
    type(scene_type), intent(in) :: scene
    real(dp), intent(in) :: d, rs
    if (scene%law == law_linear) then
      u = 0.5_dp*scene%k_normal*d**2
    else
      u = (8.0_dp/15.0_dp)*scene%e_star*sqrt(rs)*d**2.5_dp
    end if
  end function contact_energy

  !> d^T K_bond d for bond k.
  pure real(dp) function bond_quadratic(scene, k, d) result(q)
    type(scene_type), intent(in) :: scene
    integer, intent(in) :: k
    real(dp), intent(in) :: d(:)
    real(dp) :: dn
    dn = dot_product(scene%bond_normal(:, k), d)
    q = scene%k_bond*dn**2 + scene%k_bond_tangential*(dot_product(d, d) - dn**2)
  end function bond_quadratic

  !> The force terms of a scene's effects, in order; local damping last.
  function assemble(scene) result(terms)
    type(scene_type), intent(in) :: scene
    type(term_type), allocatable :: terms(:)
    allocate(terms(0))
    if (size(scene%bonds, 2) > 0) then
      if (scene%k_bond_tangential > 0.0_dp) then
        call push(terms, bonds_full)
      else
        call push(terms, bonds_normal)
      end if
      if (scene%effects(effect_damping)) call push(terms, bonds_damping)
    end if
    if (scene%effects(effect_contacts)) then
      call push(terms, detect_contacts)
      if (scene%law == law_linear) then
        call push(terms, contacts_linear)
      else
        call push(terms, contacts_hertz)
      end if
      if (scene%effects(effect_damping)) call push(terms, contacts_damping)
    end if
    if (scene%effects(effect_walls)) then
      call push(terms, detect_walls)
      if (scene%law == law_linear) then
        call push(terms, walls_linear)
      else
        call push(terms, walls_hertz)
      end if
      if (scene%effects(effect_damping)) call push(terms, walls_damping)
    end if
    if (scene%effects(effect_gravity)) call push(terms, gravity_term)
    if (scene%effects(effect_local_damping)) call push(terms, local_damping_term)
  contains
    subroutine push(list, term)
      type(term_type), allocatable, intent(inout) :: list(:)
      procedure(force_term) :: term
      type(term_type) :: item
      item%add => term
      list = [list, item]
    end subroutine push
  end function assemble

  !> Allocate the scratch of a run; split off the giants (radius above twice the
  !> (n_giants+1)-th largest) and size the cells for the rest.
  subroutine prepare(scene, work)
    type(scene_type), intent(in) :: scene
    type(work_type), intent(out) :: work
    real(dp) :: top(n_giants + 1)
    integer :: i, k, m
    allocate(work%f(3, scene%n), source=0.0_dp)
    allocate(work%v_old(3, scene%n), source=0.0_dp)
    allocate(work%inv_mass(scene%n))
    work%inv_mass = merge(0.0_dp, 1.0_dp/scene%mass, scene%fixed)
    allocate(work%pair_i(64), work%pair_j(64), work%pair_n(3, 64), work%pair_d(64))
    allocate(work%wall_i(16), work%wall_k(16), work%wall_d(16))
    ! the m largest radii, descending (insertion into a short list: linear in n)
    m = min(scene%n, n_giants + 1)
    top = -1.0_dp
    do i = 1, scene%n
      if (scene%radius(i) <= top(max(m, 1))) cycle
      k = m
      do while (k > 1)
        if (top(k - 1) >= scene%radius(i)) exit
        top(k) = top(k - 1)
        k = k - 1
      end do
      top(k) = scene%radius(i)
    end do
    allocate(work%is_giant(scene%n))
    if (m > n_giants) then
      work%is_giant = scene%radius > 2.0_dp*top(m)
    else
      work%is_giant = .false.
    end if
    work%giants = pack([(i, i = 1, scene%n)], work%is_giant)
    work%cell_width = 0.0_dp
    do i = 1, scene%n
      if (.not. work%is_giant(i)) work%cell_width = max(work%cell_width, 2.0_dp*scene%radius(i))
    end do
  end subroutine prepare

  !> The contact list: every pair of overlapping particles, found with a cell list
  !> (cells at least one non-giant diameter wide, at most about 4 per particle)
  !> and the giants against every particle, in time linear in n plus the pairs
  !> of neighbouring cells. Pairs at the same point are not contacts (the normal
  !> is undefined): the first is recorded in work%coincident. The search stops at
  !> `contact_limit` contacts (work%too_many).
  subroutine find_contacts(scene, work)
    type(scene_type), intent(in) :: scene
    type(work_type), intent(inout) :: work
    integer :: dim, n, i, j, c, k, ncell(3), idx(3), lo(3), hi(3), a, b, cc, p, g, n_cells
    real(dp) :: xmin(3), xmax(3), h, d(3)
    dim = scene%dim
    n = scene%n
    work%n_pairs = 0
    work%coincident = 0
    work%too_many = .false.
    if (n < 2) return
    xmin = 0.0_dp
    xmax = 0.0_dp
    xmin(:dim) = minval(scene%x(:dim, :), dim=2)
    xmax(:dim) = maxval(scene%x(:dim, :), dim=2)
    ! a blown-up state has no contacts to find; the run's energy check reports it
    if (.not. all(ieee_is_finite(xmax(:dim) - xmin(:dim)))) return
    h = work%cell_width
    ! no more cells than about 4 per particle: coarser cells only cost more pairs
    do while (product(max(1.0_dp, (xmax(:dim) - xmin(:dim))/h + 1.0_dp)) > 4.0_dp*n + 64.0_dp)
      h = 2.0_dp*h
    end do
    ncell = 1
    ncell(:dim) = max(1, int((xmax(:dim) - xmin(:dim))/h) + 1)
    n_cells = product(ncell)
    if (.not. allocated(work%cell_of)) allocate(work%cell_of(n), work%cell_particle(n))
    if (allocated(work%cell_start)) then
      if (size(work%cell_start) < n_cells + 1) deallocate(work%cell_start)
    end if
    if (.not. allocated(work%cell_start)) allocate(work%cell_start(n_cells + 1))
    ! counting sort of the non-giants by cell
    work%cell_start(:n_cells + 1) = 0
    do i = 1, n
      if (work%is_giant(i)) cycle
      idx = 0
      idx(:dim) = min(ncell(:dim) - 1, int((scene%x(:dim, i) - xmin(:dim))/h))
      c = 1 + idx(1) + ncell(1)*(idx(2) + ncell(2)*idx(3))
      work%cell_of(i) = c
      work%cell_start(c + 1) = work%cell_start(c + 1) + 1
    end do
    work%cell_start(1) = 1
    do c = 2, n_cells + 1
      work%cell_start(c) = work%cell_start(c) + work%cell_start(c - 1)
    end do
    do i = 1, n
      if (work%is_giant(i)) cycle
      c = work%cell_of(i)
      work%cell_particle(work%cell_start(c)) = i
      work%cell_start(c) = work%cell_start(c) + 1
    end do
    do c = n_cells, 1, -1
      work%cell_start(c + 1) = work%cell_start(c)
    end do
    work%cell_start(1) = 1
    ! every non-giant against the non-giants of its own and the neighbouring cells
    particles: do i = 1, n
      if (work%is_giant(i)) cycle
      c = work%cell_of(i) - 1
      idx(1) = mod(c, ncell(1))
      idx(2) = mod(c/ncell(1), ncell(2))
      idx(3) = c/(ncell(1)*ncell(2))
      lo = max(0, idx - 1)
      hi = min(ncell - 1, idx + 1)
      do a = lo(3), hi(3)
        do b = lo(2), hi(2)
          do cc = lo(1), hi(1)
            k = 1 + cc + ncell(1)*(b + ncell(2)*a)
            do p = work%cell_start(k), work%cell_start(k + 1) - 1
              j = work%cell_particle(p)
              if (j <= i) cycle
              ! the distance test inline (the hot loop); try_pair for the hits
              d = scene%x(:, j) - scene%x(:, i)
              if (d(1)**2 + d(2)**2 + d(3)**2 >= (scene%radius(i) + scene%radius(j))**2) cycle
              call try_pair(scene, work, i, j)
              if (work%too_many) exit particles
            end do
          end do
        end do
      end do
    end do particles
    ! every giant against every other particle (a pair of giants once)
    giants: do g = 1, size(work%giants)
      i = work%giants(g)
      do j = 1, n
        if (j == i) cycle
        if (work%is_giant(j) .and. j < i) cycle
        call try_pair(scene, work, min(i, j), max(i, j))
        if (work%too_many) exit giants
      end do
    end do giants
    work%max_contacts = max(work%max_contacts, work%n_pairs + work%n_walls)
  end subroutine find_contacts

  !> Add the pair (i, j), i < j, to the contact list if the particles overlap.
  subroutine try_pair(scene, work, i, j)
    type(scene_type), intent(in) :: scene
    type(work_type), intent(inout) :: work
    integer, intent(in) :: i, j
    real(dp) :: d(3), reach, dist
    d = scene%x(:, j) - scene%x(:, i)
    reach = scene%radius(i) + scene%radius(j)
    if (d(1)**2 + d(2)**2 + d(3)**2 >= reach**2) return
    dist = norm2(d)
    if (.not. dist > 0.0_dp) then
      if (work%coincident(1) == 0) work%coincident = [i, j]
      return
    end if
    call add_pair(work, i, j, d/dist, reach - dist)
  end subroutine try_pair

  subroutine add_pair(work, i, j, normal, overlap)
    type(work_type), intent(inout) :: work
    integer, intent(in) :: i, j
    real(dp), intent(in) :: normal(3), overlap
    integer :: m
    integer, allocatable :: ti(:), tj(:)
    real(dp), allocatable :: td(:), tn(:, :)
    if (work%n_pairs == contact_limit) then
      work%too_many = .true.
      return
    end if
    if (work%n_pairs == size(work%pair_i)) then
      ! double the capacity: amortised constant cost per pair
      m = min(2*size(work%pair_i), contact_limit)
      allocate(ti(m), tj(m), td(m), tn(3, m))
      ti(:work%n_pairs) = work%pair_i
      tj(:work%n_pairs) = work%pair_j
      td(:work%n_pairs) = work%pair_d
      tn(:, :work%n_pairs) = work%pair_n
      call move_alloc(ti, work%pair_i)
      call move_alloc(tj, work%pair_j)
      call move_alloc(td, work%pair_d)
      call move_alloc(tn, work%pair_n)
    end if
    work%n_pairs = work%n_pairs + 1
    work%pair_i(work%n_pairs) = i
    work%pair_j(work%n_pairs) = j
    work%pair_n(:, work%n_pairs) = normal
    work%pair_d(work%n_pairs) = overlap
    work%max_overlap = max(work%max_overlap, overlap)
  end subroutine add_pair

  ! ---- force terms ---------------------------------------------------------

  subroutine detect_contacts(scene, work)
    type(scene_type), intent(in) :: scene
    type(work_type), intent(inout) :: work
    call find_contacts(scene, work)
  end subroutine detect_contacts

  !> F = k d along the contact normal, on both particles.
  subroutine contacts_linear(scene, work)
    type(scene_type), intent(in) :: scene
    type(work_type), intent(inout) :: work
    integer :: k, i, j
    real(dp) :: fn(3)
    do k = 1, work%n_pairs
      i = work%pair_i(k)
      j = work%pair_j(k)
      fn = scene%k_normal*work%pair_d(k)*work%pair_n(:, k)
      work%f(:, i) = work%f(:, i) - fn
      work%f(:, j) = work%f(:, j) + fn
    end do
  end subroutine contacts_linear

  !> F = (4/3) E* sqrt(R*) d^(3/2) along the contact normal.
  subroutine contacts_hertz(scene, work)
    type(scene_type), intent(in) :: scene
    type(work_type), intent(inout) :: work
    integer :: k, i, j
    real(dp) :: fn(3), rs
    do k = 1, work%n_pairs
      i = work%pair_i(k)
      j = work%pair_j(k)
      rs = scene%radius(i)*scene%radius(j)/(scene%radius(i) + scene%radius(j))
      fn = (4.0_dp/3.0_dp)*scene%e_star*sqrt(rs)*work%pair_d(k)**1.5_dp*work%pair_n(:, k)
      work%f(:, i) = work%f(:, i) - fn
      work%f(:, j) = work%f(:, j) + fn
    end do
  end subroutine contacts_hertz

  !> Dashpot on the relative normal velocity of the previous half step.
  subroutine contacts_damping(scene, work)
    type(scene_type), intent(in) :: scene
    type(work_type), intent(inout) :: work
    integer :: k, i, j
    real(dp) :: fd(3), c, vn
    do k = 1, work%n_pairs
      i = work%pair_i(k)
      j = work%pair_j(k)
      c = 2.0_dp*scene%damping_ratio*sqrt(effective_mass(scene, i, j)*tangent_stiffness(scene, &
        work%pair_d(k), scene%radius(i)*scene%radius(j)/(scene%radius(i) + scene%radius(j))))
      vn = dot_product(scene%v(:, j) - scene%v(:, i), work%pair_n(:, k))
      fd = c*vn*work%pair_n(:, k)
      work%f(:, i) = work%f(:, i) + fd
      work%f(:, j) = work%f(:, j) - fd
    end do
  end subroutine contacts_damping

  !> The wall contact list: particles overlapping a wall.
  subroutine detect_walls(scene, work)
    type(scene_type), intent(in) :: scene
    type(work_type), intent(inout) :: work
    integer :: i, w
    real(dp) :: overlap
    work%n_walls = 0
    do w = 1, size(scene%wall_normal, 2)
      do i = 1, scene%n
        overlap = scene%radius(i) - dot_product(scene%x(:, i) - scene%wall_point(:, w), scene%wall_normal(:, w))
        ! (a NaN overlap, after a blow-up, is no contact)
        if (overlap > 0.0_dp) then
          if (work%n_walls == size(work%wall_i)) call grow_walls(work)
          work%n_walls = work%n_walls + 1
          work%wall_i(work%n_walls) = i
          work%wall_k(work%n_walls) = w
          work%wall_d(work%n_walls) = overlap
          work%max_overlap = max(work%max_overlap, overlap)
        end if
      end do
    end do
    work%max_contacts = max(work%max_contacts, work%n_pairs + work%n_walls)
  end subroutine detect_walls

  !> Double the capacity of the wall contact list (amortised constant cost).
  subroutine grow_walls(work)
    type(work_type), intent(inout) :: work
    integer, allocatable :: ti(:), tk(:)
    real(dp), allocatable :: td(:)
    integer :: m
    m = 2*size(work%wall_i)
    allocate(ti(m), tk(m), td(m))
    ti(:work%n_walls) = work%wall_i(:work%n_walls)
    tk(:work%n_walls) = work%wall_k(:work%n_walls)
    td(:work%n_walls) = work%wall_d(:work%n_walls)
    call move_alloc(ti, work%wall_i)
    call move_alloc(tk, work%wall_k)
    call move_alloc(td, work%wall_d)
  end subroutine grow_walls

  subroutine walls_linear(scene, work)
    type(scene_type), intent(in) :: scene
    type(work_type), intent(inout) :: work
    integer :: k, i
    do k = 1, work%n_walls
      i = work%wall_i(k)
      work%f(:, i) = work%f(:, i) + scene%k_normal*work%wall_d(k)*scene%wall_normal(:, work%wall_k(k))
    end do
  end subroutine walls_linear

  subroutine walls_hertz(scene, work)
    type(scene_type), intent(in) :: scene
    type(work_type), intent(inout) :: work
    integer :: k, i
    do k = 1, work%n_walls
      i = work%wall_i(k)
      work%f(:, i) = work%f(:, i) + (4.0_dp/3.0_dp)*scene%e_star*sqrt(scene%radius(i)) &
        *work%wall_d(k)**1.5_dp*scene%wall_normal(:, work%wall_k(k))
    end do
  end subroutine walls_hertz

  subroutine walls_damping(scene, work)
    type(scene_type), intent(in) :: scene
    type(work_type), intent(inout) :: work
    integer :: k, i
    real(dp) :: c, vn
    do k = 1, work%n_walls
      i = work%wall_i(k)
      c = 2.0_dp*scene%damping_ratio*sqrt(scene%mass(i)*tangent_stiffness(scene, work%wall_d(k), &
        scene%radius(i)))
      vn = dot_product(scene%v(:, i), scene%wall_normal(:, work%wall_k(k)))
      work%f(:, i) = work%f(:, i) - c*vn*scene%wall_normal(:, work%wall_k(k))
    end do
  end subroutine walls_damping

  !> Bonds with normal stiffness only: F = k_n n0 (n0 . (d - d0)).
  subroutine bonds_normal(scene, work)
    type(scene_type), intent(in) :: scene
    type(work_type), intent(inout) :: work
    call bond_normal_forces(size(scene%bonds, 2), scene%n, scene%bonds, scene%x, scene%bond_rest, &
      scene%bond_normal, scene%k_bond, work%f)
  end subroutine bonds_normal

  !> The kernel of `bonds_normal` on plain contiguous arrays.
  pure subroutine bond_normal_forces(nb, n, bonds, x, rest, normal, k, f)
    integer, intent(in) :: nb, n, bonds(2, nb)
    real(dp), intent(in) :: x(3, n), rest(3, nb), normal(3, nb), k
    real(dp), intent(inout) :: f(3, n)
    integer :: b, i, j
    real(dp) :: u(3), fb(3)
    do b = 1, nb
      i = bonds(1, b)
      j = bonds(2, b)
      u = x(:, j) - x(:, i) - rest(:, b)
      fb = k*dot_product(normal(:, b), u)*normal(:, b)
      f(:, i) = f(:, i) + fb
      f(:, j) = f(:, j) - fb
    end do
  end subroutine bond_normal_forces

  !> Bonds with normal and tangential stiffness.
  subroutine bonds_full(scene, work)
    type(scene_type), intent(in) :: scene
    type(work_type), intent(inout) :: work
    integer :: k, i, j
    real(dp) :: u(3), n0(3), fb(3), un
    do k = 1, size(scene%bonds, 2)
      i = scene%bonds(1, k)
      j = scene%bonds(2, k)
      u = scene%x(:, j) - scene%x(:, i) - scene%bond_rest(:, k)
      n0 = scene%bond_normal(:, k)
      un = dot_product(n0, u)
      fb = scene%k_bond*un*n0 + scene%k_bond_tangential*(u - un*n0)
      work%f(:, i) = work%f(:, i) + fb
      work%f(:, j) = work%f(:, j) - fb
    end do
  end subroutine bonds_full

  !> Bond dashpots along the bond's initial direction.
  subroutine bonds_damping(scene, work)
    type(scene_type), intent(in) :: scene
    type(work_type), intent(inout) :: work
    integer :: k, i, j
    real(dp) :: n0(3), c, vn
    do k = 1, size(scene%bonds, 2)
      i = scene%bonds(1, k)
      j = scene%bonds(2, k)
      n0 = scene%bond_normal(:, k)
      c = 2.0_dp*scene%damping_ratio*sqrt(effective_mass(scene, i, j)*scene%k_bond)
      vn = dot_product(scene%v(:, j) - scene%v(:, i), n0)
      work%f(:, i) = work%f(:, i) + c*vn*n0
      work%f(:, j) = work%f(:, j) - c*vn*n0
    end do
  end subroutine bonds_damping

  subroutine gravity_term(scene, work)
    type(scene_type), intent(in) :: scene
    type(work_type), intent(inout) :: work
    integer :: i
    do i = 1, scene%n
      work%f(:, i) = work%f(:, i) + scene%mass(i)*scene%gravity
    end do
  end subroutine gravity_term

  !> Cundall's local damping: each force component reduced by alpha |F| against
  !> the half-step velocity.
  subroutine local_damping_term(scene, work)
    type(scene_type), intent(in) :: scene
    type(work_type), intent(inout) :: work
    ! sign of v, and 0 for a particle at rest
    work%f = work%f - scene%local_damping*abs(work%f)*(merge(1.0_dp, 0.0_dp, scene%v > 0.0_dp) &
      - merge(1.0_dp, 0.0_dp, scene%v < 0.0_dp))
  end subroutine local_damping_term

  !> m* of a pair (i, j); j = 0 (the ground, a wall) and fixed partners count as
  !> infinitely heavy.
  pure real(dp) function effective_mass(scene, i, j) result(m)
    type(scene_type), intent(in) :: scene
    integer, intent(in) :: i, j
    if (j == 0) then
      m = scene%mass(i)
    else if (scene%fixed(j)) then
      m = scene%mass(i)
    else if (scene%fixed(i)) then
      m = scene%mass(j)
    else
      ! m_a m_b/(m_a + m_b) as m_a/(1 + m_a/m_b), m_a the lighter: no under- or overflow
      m = min(scene%mass(i), scene%mass(j))/(1.0_dp + min(scene%mass(i), scene%mass(j)) &
        /max(scene%mass(i), scene%mass(j)))
    end if
  end function effective_mass

  !> dF/dd of the contact law at overlap d: k (linear) or 2 E* sqrt(R* d) (Hertz).
  pure real(dp) function tangent_stiffness(scene, d, rs) result(k)
    type(scene_type), intent(in) :: scene
    real(dp), intent(in) :: d, rs
    if (scene%law == law_linear) then
      k = scene%k_normal
    else
      k = 2.0_dp*scene%e_star*sqrt(rs*d)
    end if
  end function tangent_stiffness

end module demstep_scene
