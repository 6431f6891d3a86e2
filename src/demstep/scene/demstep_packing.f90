!> Packings for tests and benchmarks: a random dense periodic packing relaxed
!> by FIRE (`random_periodic_packing`), and a periodic scene repeated along its
!> axes (`tile_scene`), the way larger packings are made.
module demstep_packing
  use demstep_kinds, only: dp, i8, pi
  use demstep_status, only: demstep_status_type, demstep_stat, set_status
  use demstep_text, only: int_text
  use demstep_scene_data, only: scene_type, scene_effect, branch_vector, max_damping_ratio, wrap_positions
  use demstep_interaction, only: contact_law
  use demstep_neighbours, only: search_type, prepare_search, find_contacts
  use demstep_scene_builders, only: new_scene, scene_set_cell, scene_set_law, scene_set_rolling, scene_add_walls
  use, intrinsic :: ieee_arithmetic, only: ieee_is_finite
  implicit none
  private

  public :: random_periodic_packing, tile_scene, random_clump_packing

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
      call set_status(status, demstep_stat%invalid_input, "a random periodic packing needs "// &
        int_text(packing_min_particles)//" to "//int_text(packing_max_particles)//" particles " &
        //"(tile_scene makes larger ones)", where="n")
      return
    end if
    if (.not. (ieee_is_finite(r_mean) .and. r_mean > 0.0_dp .and. r_mean <= 1.0e100_dp)) then
      call set_status(status, demstep_stat%invalid_input, "must be > 0 and at most 1e100", where="radius")
      return
    end if
    if (.not. (poly >= 0.0_dp .and. poly <= 0.5_dp)) then
      call set_status(status, demstep_stat%invalid_input, "must be in [0, 0.5]", where="polydispersity")
      return
    end if
    if (.not. (ieee_is_finite(rho) .and. rho > 0.0_dp)) then
      call set_status(status, demstep_stat%invalid_input, "must be > 0 and finite", where="density")
      return
    end if
    ! the law's own check, before the relaxation
    call scene_set_law(law_only, contact_law%linear, kn, kt, status)
    if (status%stat /= demstep_stat%ok) return
    if (.not. (zeta >= 0.0_dp .and. zeta <= 1.0e100_dp)) then
      call set_status(status, demstep_stat%invalid_input, "must be in [0, 1e100]", where="damping_ratio")
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

  !> A test packing of rigid clumps over a floor: n_bodies clumps of 1 to 3
  !> spheres (radii uniform in 0.7-1, masses r^3 (0.6 + 0.8 u); a clump's
  !> further members 0.5 to 1.1 from its first, so they overlap) at random
  !> orientations, on a cubic grid of spacing `gap` (default 2: neighbouring
  !> clumps touch) jittered by +-0.15, over a floor wall 0.05 into the lowest
  !> sphere; linear law k_n = 1000, k_t = 400, rolling and twisting ratios 0.1
  !> and 0.05. `body_of` is each sphere's clump (for `bodies_from_members`).
  !> The same packing for the same seed (MINSTD, as `random_periodic_packing`).
  !> Status invalid_input naming `n_bodies` (below 1 or above
  !> `packing_max_particles`/3) or `gap` (not finite and > 0).
  subroutine random_clump_packing(scene, body_of, n_bodies, status, seed, gap)
    type(scene_type), intent(out) :: scene
    integer, allocatable, intent(out) :: body_of(:)
    integer, intent(in) :: n_bodies
    type(demstep_status_type), intent(out) :: status
    !> Seed of the generator (any integer); default 1.
    integer, intent(in), optional :: seed
    !> Grid spacing (default 2).
    real(dp), intent(in), optional :: gap
    real(dp), allocatable :: x(:, :), m(:), r(:)
    integer, allocatable :: id(:)
    real(dp) :: u(3), centre(3), q, g
    integer(i8) :: state
    integer :: b, j, k, nm, n, side
    g = 2.0_dp
    if (present(gap)) g = gap
    if (n_bodies < 1 .or. n_bodies > packing_max_particles/3) then
      call set_status(status, demstep_stat%invalid_input, "must be in 1.."//int_text(packing_max_particles/3), &
        where="n_bodies")
      return
    end if
    if (.not. (ieee_is_finite(g) .and. g > 0.0_dp)) then
      call set_status(status, demstep_stat%invalid_input, "must be finite and > 0", where="gap")
      return
    end if
    state = 1_i8
    if (present(seed)) state = 1_i8 + modulo(int(seed, i8), 2147483646_i8)
    allocate(x(3, 3*n_bodies), m(3*n_bodies), r(3*n_bodies), id(3*n_bodies))
    side = ceiling(real(n_bodies, dp)**(1.0_dp/3.0_dp) - 1.0e-9_dp)
    n = 0
    do b = 1, n_bodies
      do k = 1, 3
        call next_uniform(state, u(k))
      end do
      centre = g*[real(mod(b - 1, side), dp), real(mod((b - 1)/side, side), dp), real((b - 1)/side**2, dp)] &
        + 0.3_dp*(u - 0.5_dp)
      call next_uniform(state, q)
      nm = min(3, 1 + int(3.0_dp*q))
      do j = 1, nm
        n = n + 1
        do k = 1, 3
          call next_uniform(state, u(k))
        end do
        u = u - 0.5_dp
        x(:, n) = centre
        if (j > 1) x(:, n) = centre + (0.5_dp + 0.6_dp*abs(u(1)))*u/norm2(u)
        call next_uniform(state, q)
        r(n) = 0.7_dp + 0.3_dp*q
        call next_uniform(state, q)
        m(n) = r(n)**3*(0.6_dp + 0.8_dp*q)
        id(n) = b
      end do
    end do
    call new_scene(scene, 3, x(:, :n), m(:n), r(:n), status)
    if (status%stat /= demstep_stat%ok) return
    call scene_set_law(scene, contact_law%linear, 1.0e3_dp, 400.0_dp, status)
    if (status%stat == demstep_stat%ok) call scene_set_rolling(scene, 0.1_dp, 0.05_dp, status)
    if (status%stat == demstep_stat%ok) call scene_add_walls(scene, reshape([0.0_dp, 0.0_dp, &
      minval(x(3, :n) - r(:n)) + 0.05_dp], [3, 1]), reshape([0.0_dp, 0.0_dp, 1.0_dp], [3, 1]), status)
    body_of = id(:n)
  end subroutine random_clump_packing

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
      call set_status(status, demstep_stat%invalid_input, "must be >= 1 along every axis", where="reps")
      return
    end if
    do ax = 1, 3
      if (reps(ax) > 1 .and. .not. scene%periodic(ax)) then
        call set_status(status, demstep_stat%invalid_input, "axis "//int_text(ax)//" is not " &
          //"periodic: only a periodic cell can be repeated along it", where="reps", index=int(ax))
        return
      end if
    end do
    n = scene%n
    if (n < 1) then
      call set_status(status, demstep_stat%invalid_input, "the scene has no particles", where="n")
      return
    end if
    if (real(n, dp)*real(reps(1), dp)*real(reps(2), dp)*real(reps(3), dp) > real(huge(1), dp)) then
      call set_status(status, demstep_stat%invalid_input, "the tiled scene would hold more " &
        //"than 2147483647 particles", where="reps")
      return
    end if
    if ((real(size(scene%bonds, 2), dp) + real(size(scene%contact_pairs, 2), dp)) &
        *real(reps(1), dp)*real(reps(2), dp)*real(reps(3), dp) > real(huge(1), dp)) then
      call set_status(status, demstep_stat%invalid_input, "the tiled scene would hold more " &
        //"than 2147483647 bonds or contacts", where="reps")
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

end module demstep_packing
