!> The stability limit of a whole scene at its current configuration.
!>
!> The scene is linearised with the interaction kernel's tangent blocks
!> (`contact_block`): every bond, particle contact and wall contact couples the
!> translations (and, with the `rotation` effect, the rotations) of its two
!> bodies through its normal and tangential springs with their lever arms;
!> fixed particles and walls are ground. Degrees of freedom per particle: dim
!> translations, plus theta_z in 2D or three rotations in 3D with rotations on.
!> The smallest period of the assembly is 2 pi/omega_max with omega_max^2 the
!> largest eigenvalue of A = M^-1/2 K M^-1/2 (M: masses and moments of inertia),
!> and the undamped central-difference limit is dt = 2/omega_max. Four estimates:
!> - the per-contact rule min 2 sqrt(m*/k): NOT safe, a particle held by several
!>   springs vibrates faster than any one of them;
!> - a rigorous bound: Gershgorin's row sums of |A| bound omega_max^2 from above,
!>   so 2/omega_bound <= the true limit; cost linear in interactions. The
!>   pre-stress of compressed contacts only softens K, so the bound (taken
!>   without it) holds for the integrated system as well;
!> - the exact omega_max from LAPACK (dsyevr, largest eigenpair only);
!> - the damped limit of the lagged dashpot, (2/omega)(sqrt(1 + z^2) - z), with z
!>   the modal damping ratio of the top mode (its eigenvector's Rayleigh quotient
!>   of the dashpot matrix).
!> Hertz contacts are linearised with their tangent stiffness 2 E* sqrt(R* d)
!> (tangential 8 G* sqrt(R* d)), at the current overlap d or at the overlap an
!> impact at a given speed would reach, d = (15 m* v^2 / (16 E* sqrt(R*)))^(2/5).
!> The spring list is counted, allocated once and filled: linear in interactions.
module demstep_assembly
  use demstep_kinds, only: dp, pi
  use demstep_status, only: demstep_status_type, demstep_stat, set_status
  use demstep_text, only: int_text, real_text
  use demstep_spring, only: damped_limit
  use demstep_interaction, only: contact_law, contact_block, dashpot_coefficient, &
    normal_stiffness, wall_overlap, reduced_radius, dof_components
  use demstep_scene_data, only: scene_type, scene_effect, effective_mass, contact_values
  use demstep_neighbours, only: contact_list
  use demstep_stepper, only: max_damping_ratio
  use, intrinsic :: ieee_arithmetic, only: ieee_is_finite
  use demstep_lapack, only: largest_eigenpair
  implicit none
  private

  public :: assembly_critical_steps, assembly_step_for_n_per_period

  !> Hertz linearisation at the current overlap, or at an impact's largest
  !> overlap: `hertz_linearization%impact`.
  type, public :: hertz_linearization_enum
    integer :: current = 1
    integer :: impact = 2
  end type hertz_linearization_enum
  !> The Hertz linearisations by name.
  type(hertz_linearization_enum), parameter, public :: hertz_linearization = hertz_linearization_enum()
  !> Most numbers (dof per particle squared times free particles) the bound keeps
  !> for the diagonal blocks (160 MB); above, it sums absolute values of each
  !> spring's entries (looser, equally rigorous).
  real(dp), parameter :: max_bound_memory = 2.0e7_dp
  !> Largest number of degrees of freedom given to the dense eigensolver by default.
  integer, parameter, public :: default_max_eigen_dof = 4000

  !> The four estimates and what they rest on.
  type, public :: critical_step_type
    !> Degrees of freedom (free particles times dof_per_particle) and springs
    !> (bonds + contacts + wall contacts).
    integer :: n_dof = 0, n_springs = 0, dof_per_particle = 0
    !> The model: rotations, tangential springs counted, periodic cell, pre-stress.
    logical :: rotation = .false., tangential = .false., periodic = .false., prestress = .false.
    !> Exact: omega_max and 2/omega_max (0 when not computed).
    real(dp) :: omega_max = 0.0_dp, dt_critical_eigen = 0.0_dp
    logical :: eigen_computed = .false.
    !> Gershgorin bound: omega_bound >= omega_max, 2/omega_bound <= the limit.
    real(dp) :: omega_bound = 0.0_dp, dt_critical_bound = 0.0_dp
    !> The per-contact rule min 2 sqrt(m*/k) (unsafe).
    real(dp) :: dt_contact_rule = 0.0_dp
    !> Modal damping ratio of the top mode and the damped limit (lagged dashpot).
    real(dp) :: damping_ratio_top = 0.0_dp, dt_critical_damped = 0.0_dp
  end type critical_step_type

  !> A linearised interaction between bodies a and b (a = 0: the ground), n from
  !> a to b; lever arms and the pre-stress F_n/l (0 when not asked for).
  type :: spring_block_type
    integer :: a = 0, b = 0
    real(dp) :: k_n = 0.0_dp, k_t = 0.0_dp, arm_a = 0.0_dp, arm_b = 0.0_dp, geo = 0.0_dp
    real(dp) :: n(3) = 0.0_dp
  end type spring_block_type

contains

  !> The critical time steps of a scene at its current configuration.
  !>
  !> The eigenproblem is solved in scaled units (stiffness over the largest
  !> spring stiffness, masses over the smallest free mass or I/r^2, rotations as
  !> r theta), so any finite stiffness and any mass with a finite inverse give
  !> finite results unless omega_max itself overflows.
  !> Status invalid_input, the message starting with the variable to change:
  !> `fixed:` (every particle fixed), `effects:` (no bonds and no contact effect),
  !> `position:` (no free particle touches a spring; coincident particles; too
  !> many contacts), `e_star:` (a Hertz stiffness overflows), `damping_ratio:`
  !> (above `max_damping_ratio`, or a damped limit that underflows), `mass:`
  !> (omega_max overflows), bad Hertz options; lapack_failure.
  subroutine assembly_critical_steps(scene, result, status, hertz_mode, impact_velocity, &
      max_eigen_dof, prestress)
    type(scene_type), intent(in) :: scene
    type(critical_step_type), intent(out) :: result
    type(demstep_status_type), intent(out) :: status
    !> `hertz_linearization%current` (default) or `%impact` with impact_velocity > 0.
    integer, intent(in), optional :: hertz_mode
    real(dp), intent(in), optional :: impact_velocity
    !> Above this many degrees of freedom the eigensolver is skipped (default 4000).
    integer, intent(in), optional :: max_eigen_dof
    !> Count the pre-stress (geometric) stiffness -(F_n/l)(I - n n^T) of the
    !> loaded contacts (default no).
    logical, intent(in), optional :: prestress
    type(spring_block_type), allocatable :: springs(:)
    integer, allocatable :: dof(:), comp(:)
    real(dp), allocatable :: a(:, :), vec(:), rows(:), mdof(:, :), diag(:, :, :)
    real(dp) :: lam, zeta, v_impact, k_scale, m_scale, rate
    integer :: mode, limit, i, nfree, nc, p
    logical :: touches, geo
    mode = hertz_linearization%current
    if (present(hertz_mode)) mode = hertz_mode
    v_impact = 0.0_dp
    if (present(impact_velocity)) v_impact = impact_velocity
    limit = default_max_eigen_dof
    if (present(max_eigen_dof)) limit = max_eigen_dof
    geo = .false.
    if (present(prestress)) geo = prestress
    if (mode == hertz_linearization%impact .and. .not. (v_impact > 0.0_dp .and. ieee_is_finite(v_impact))) then
      call set_status(status, demstep_stat%invalid_input, "impact_velocity: the Hertz linearisation " &
        //"at impact needs a finite impact velocity > 0")
      return
    end if
    zeta = 0.0_dp
    if (scene%effects(scene_effect%damping)) zeta = scene%damping_ratio
    if (.not. (zeta >= 0.0_dp .and. zeta <= max_damping_ratio)) then
      call set_status(status, demstep_stat%invalid_input, "damping_ratio: must be in [0, 1e100]")
      return
    end if
    result%rotation = scene%effects(scene_effect%rotation) .and. scene%dim > 1
    result%periodic = any(scene%periodic)
    result%prestress = geo
    comp = dof_components(scene%dim, result%rotation)
    nc = size(comp)
    result%dof_per_particle = nc
    ! degrees of freedom: nc per free particle, scaled masses per component
    allocate(dof(scene%n), source=0)
    allocate(mdof(6, scene%n), source=1.0_dp)
    nfree = 0
    m_scale = huge(1.0_dp)
    do i = 1, scene%n
      if (scene%fixed(i)) cycle
      nfree = nfree + 1
      dof(i) = (nfree - 1)*nc
      mdof(1:3, i) = scene%mass(i)
      ! a rotation counts as r theta: its mass is I/r^2
      mdof(4:6, i) = (scene%inertia(i)/scene%radius(i))/scene%radius(i)
      m_scale = min(m_scale, minval(mdof(comp, i)))
    end do
    result%n_dof = nfree*nc
    if (nfree == 0) then
      call set_status(status, demstep_stat%invalid_input, "fixed: every particle is fixed: the " &
        //"scene has no stiffness")
      return
    end if
    mdof = mdof/m_scale
    call linearise(scene, mode, v_impact, geo, springs, status)
    if (status%stat /= demstep_stat%ok) return
    result%n_springs = size(springs)
    touches = .false.
    k_scale = 0.0_dp
    do i = 1, size(springs)
      if (springs(i)%a > 0) touches = touches .or. .not. scene%fixed(springs(i)%a)
      touches = touches .or. .not. scene%fixed(springs(i)%b)
      k_scale = max(k_scale, springs(i)%k_n, springs(i)%k_t)
      result%tangential = result%tangential .or. springs(i)%k_t > 0.0_dp
    end do
    if (.not. (touches .and. k_scale > 0.0_dp)) then
      if (size(scene%bonds, 2) == 0 .and. .not. (scene%effects(scene_effect%contacts) .or. &
          scene%effects(scene_effect%walls))) then
        call set_status(status, demstep_stat%invalid_input, "effects: the scene has no stiffness: " &
          //"no bonds, and neither 'contacts' nor 'walls' is switched on")
      else
        call set_status(status, demstep_stat%invalid_input, "position: the scene has no stiffness: " &
          //"no free particle touches a bond, a contact or a wall")
      end if
      return
    end if
    ! omega = rate sqrt(lambda'), lambda' an eigenvalue of the scaled problem
    rate = sqrt(k_scale)/sqrt(m_scale)

    ! per-contact rule and the Gershgorin bound (scaled, without pre-stress):
    ! the diagonal blocks are summed before their absolute values are taken
    ! (contacts of one particle cancel there) when they fit in max_bound_memory
    result%dt_contact_rule = huge(1.0_dp)
    allocate(rows(result%n_dof), source=0.0_dp)
    if (real(nfree, dp)*nc*nc <= max_bound_memory) then
      allocate(diag(nc, nc, nfree), source=0.0_dp)
    else
      allocate(diag(0, 0, 0))
    end if
    do i = 1, size(springs)
      associate(s => springs(i))
        result%dt_contact_rule = min(result%dt_contact_rule, &
          2.0_dp*sqrt(effective_mass(scene, s%b, s%a))/sqrt(max(s%k_n, s%k_t)))
        if (size(diag) > 0) then
          call add_spring(scene, dof, comp, mdof, s, k_scale, .false., rows=rows, diag=diag)
        else
          call add_spring(scene, dof, comp, mdof, s, k_scale, .false., rows=rows)
        end if
      end associate
    end do
    do i = 1, size(diag, 3)
      do p = 1, nc
        rows((i - 1)*nc + p) = rows((i - 1)*nc + p) + sum(abs(diag(p, :, i)))
      end do
    end do
    result%omega_bound = rate*sqrt(maxval(rows))
    if (.not. ieee_is_finite(result%omega_bound)) then
      call set_status(status, demstep_stat%invalid_input, "mass: the bound of omega_max = sqrt(k/m) " &
        //"overflows: the largest stiffness over the smallest mass must stay below about 1e600")
      return
    end if
    result%dt_critical_bound = 2.0_dp/result%omega_bound

    ! exact omega_max from the dense scaled stiffness matrix
    if (result%n_dof <= limit) then
      allocate(a(result%n_dof, result%n_dof), source=0.0_dp)
      do i = 1, size(springs)
        call add_spring(scene, dof, comp, mdof, springs(i), k_scale, geo, a=a)
      end do
      allocate(vec(result%n_dof))
      call largest_eigenpair(a, lam, vec, status)
      if (status%stat /= demstep_stat%ok) return
      if (.not. lam > 0.0_dp) then
        call set_status(status, demstep_stat%invalid_input, "position: the scene has no stiffness")
        return
      end if
      result%omega_max = rate*sqrt(lam)
      result%dt_critical_eigen = 2.0_dp/result%omega_max
      result%eigen_computed = .true.
      if (scene%effects(scene_effect%damping)) then
        zeta = zeta*modal_damping(scene, dof, mdof, springs, k_scale, m_scale, vec)/(2.0_dp*sqrt(lam))
      end if
      result%damping_ratio_top = zeta
      result%dt_critical_damped = damped_limit(result%dt_critical_eigen, zeta)
    else
      ! too large for the dense solver: the damped limit from the bound
      result%damping_ratio_top = zeta
      result%dt_critical_damped = damped_limit(result%dt_critical_bound, zeta)
    end if
    if (.not. (ieee_is_finite(result%damping_ratio_top) .and. result%dt_critical_damped > 0.0_dp)) then
      call set_status(status, demstep_stat%invalid_input, "damping_ratio: the damped limit " &
        //"dt/(sqrt(1 + z^2) + z) is not representable; use a smaller damping_ratio")
      return
    end if
    status%stat = demstep_stat%ok
  end subroutine assembly_critical_steps

  !> Every interaction of the scene, linearised at the current configuration:
  !> counted, allocated once and filled (linear in interactions).
  subroutine linearise(scene, mode, v_impact, geo, springs, status)
    type(scene_type), intent(in) :: scene
    integer, intent(in) :: mode
    real(dp), intent(in) :: v_impact
    logical, intent(in) :: geo
    type(spring_block_type), allocatable, intent(out) :: springs(:)
    type(demstep_status_type), intent(out) :: status
    integer, allocatable :: pi(:), pj(:), pc(:)
    real(dp), allocatable :: pn(:, :), pd(:)
    integer :: k, i, j, w, m, n_contacts, n_walls
    real(dp) :: overlap, d, f_n, k_n, k_t, rs, l, e_pair
    m = size(scene%bonds, 2)
    n_contacts = 0
    n_walls = 0
    if (scene%effects(scene_effect%contacts)) then
      call contact_list(scene, pi, pj, pn, pd, status, pc)
      if (status%stat /= demstep_stat%ok) return
      do k = 1, size(pi)
        if (.not. (scene%fixed(pi(k)) .and. scene%fixed(pj(k)))) n_contacts = n_contacts + 1
      end do
    end if
    if (scene%effects(scene_effect%walls)) then
      do w = 1, size(scene%wall_normal, 2)
        do i = 1, scene%n
          if (.not. scene%fixed(i) .and. wall_overlap(scene%x(:, i), scene%radius(i), &
            scene%wall_point(:, w), scene%wall_normal(:, w)) > 0.0_dp) n_walls = n_walls + 1
        end do
      end do
    end if
    allocate(springs(m + n_contacts + n_walls))
    do k = 1, m
      springs(k) = spring_block_type(a=scene%bonds(1, k), b=scene%bonds(2, k), k_n=scene%k_bond, &
        k_t=scene%k_bond_tangential, n=scene%bond_normal(:, k))
    end do
    if (scene%effects(scene_effect%contacts)) then
      do k = 1, size(pi)
        i = pi(k)
        j = pj(k)
        if (scene%fixed(i) .and. scene%fixed(j)) cycle
        rs = reduced_radius(scene%radius(i), scene%radius(j))
        ! the pair's E* (per-type materials) or the scene's
        e_pair = scene%e_star
        if (allocated(scene%ptype)) e_pair = scene%pair_law(3, scene%ptype(i), scene%ptype(j))
        d = linearisation_overlap(scene, pc(k), pd(k), rs, effective_mass(scene, i, j), mode, v_impact, e_pair)
        call contact_values(scene, pc(k), i, j, d, f_n, k_n, k_t)
        if (.not. (ieee_is_finite(k_n) .and. ieee_is_finite(k_t))) then
          call stiffness_overflow(i, j)
          return
        end if
        m = m + 1
        springs(m) = spring_block_type(a=i, b=j, k_n=k_n, k_t=k_t, n=pn(:, k), &
          arm_a=scene%radius(i), arm_b=scene%radius(j))
        if (geo) then
          ! F_n at the current overlap over the branch length
          call contact_values(scene, pc(k), i, j, pd(k), f_n, k_n, k_t)
          l = scene%radius(i) + scene%radius(j) - pd(k)
          springs(m)%geo = f_n/l
        end if
      end do
    end if
    if (scene%effects(scene_effect%walls)) then
      do w = 1, size(scene%wall_normal, 2)
        do i = 1, scene%n
          if (scene%fixed(i)) cycle
          overlap = wall_overlap(scene%x(:, i), scene%radius(i), scene%wall_point(:, w), scene%wall_normal(:, w))
          if (.not. overlap > 0.0_dp) cycle
          d = linearisation_overlap(scene, 0, overlap, scene%radius(i), scene%mass(i), mode, v_impact, &
            scene%e_star)
          k_n = normal_stiffness(scene%law, scene%k_normal, scene%e_star, d, scene%radius(i))
          if (.not. ieee_is_finite(k_n)) then
            call stiffness_overflow(i, 0)
            return
          end if
          m = m + 1
          springs(m) = spring_block_type(a=0, b=i, k_n=k_n, k_t=0.0_dp, n=scene%wall_normal(:, w), &
            arm_b=scene%radius(i))
        end do
      end do
    end if
    status%stat = demstep_stat%ok
  contains
    subroutine stiffness_overflow(i, j)
      integer, intent(in) :: i, j
      character(len=:), allocatable :: who
      if (j == 0) then
        who = "particle "//int_text(i)//" on a wall"
      else
        who = "particles "//int_text(i)//" and "//int_text(j)
      end if
      if (mode == hertz_linearization%impact) then
        call set_status(status, demstep_stat%invalid_input, "e_star: the Hertz tangent stiffness " &
          //"2 E* sqrt(R* d) of "//who//" overflows (lower e_star or impact_velocity)")
      else
        call set_status(status, demstep_stat%invalid_input, "e_star: the Hertz tangent stiffness " &
          //"2 E* sqrt(R* d) of "//who//" overflows (lower e_star)")
      end if
    end subroutine stiffness_overflow
  end subroutine linearise

  !> The overlap a contact is linearised at: the current one, or (Hertz, detected
  !> contacts) the largest overlap of an impact at v_impact,
  !> d = (15 m* v^2/(16 E* sqrt(R*)))^(2/5) (through logarithms: no overflow).
  pure real(dp) function linearisation_overlap(scene, c, overlap, rs, m_eff, mode, v_impact, e_star) result(d)
    type(scene_type), intent(in) :: scene
    integer, intent(in) :: c, mode
    !> E* of the pair (per-type materials) or of the scene.
    real(dp), intent(in) :: overlap, rs, m_eff, v_impact, e_star
    d = overlap
    if (c == 0 .and. scene%law == contact_law%hertz .and. mode == hertz_linearization%impact) &
      d = exp(0.4_dp*(log(15.0_dp/16.0_dp) + log(m_eff) + 2.0_dp*log(v_impact) - log(e_star) &
        - 0.5_dp*log(rs)))
  end function linearisation_overlap

  !> Add a spring's scaled block A' = M'^-1/2 K' M'^-1/2 (K' = K/k_scale, rotations
  !> as r theta) to the lower triangle of `a`, or the absolute values of its
  !> entries to the row sums `rows` (an upper bound of |A'|'s row sums); with
  !> `diag`, the diagonal blocks go there (by free particle) instead of to `rows`.
  subroutine add_spring(scene, dof, comp, mdof, s, k_scale, geo, a, rows, diag)
    type(scene_type), intent(in) :: scene
    integer, intent(in) :: dof(:), comp(:)
    real(dp), intent(in) :: mdof(:, :)
    type(spring_block_type), intent(in) :: s
    real(dp), intent(in) :: k_scale
    logical, intent(in) :: geo
    real(dp), intent(inout), optional :: a(:, :), rows(:), diag(:, :, :)
    real(dp) :: b(12, 12), arm(2), value, g
    integer :: body(2), sa, sb, p, q, row, col
    logical :: free(2)
    body = [s%a, s%b]
    arm = 0.0_dp
    do sa = 1, 2
      free(sa) = body(sa) > 0
      if (free(sa)) free(sa) = .not. scene%fixed(body(sa))
    end do
    if (s%a > 0) arm(1) = s%arm_a/scene%radius(s%a)
    arm(2) = s%arm_b/scene%radius(s%b)
    g = 0.0_dp
    if (geo) g = s%geo/k_scale
    b = contact_block(s%n, s%k_n/k_scale, s%k_t/k_scale, arm(1), arm(2), g)
    do sa = 1, 2
      if (.not. free(sa)) cycle
      do sb = 1, 2
        if (.not. free(sb)) cycle
        do q = 1, size(comp)
          col = dof(body(sb)) + q
          do p = 1, size(comp)
            row = dof(body(sa)) + p
            value = b(6*(sa - 1) + comp(p), 6*(sb - 1) + comp(q)) &
              /(sqrt(mdof(comp(p), body(sa)))*sqrt(mdof(comp(q), body(sb))))
            if (present(diag) .and. sa == sb) then
              diag(p, q, dof(body(sa))/size(comp) + 1) = diag(p, q, dof(body(sa))/size(comp) + 1) + value
            else if (present(rows)) then
              rows(row) = rows(row) + abs(value)
            end if
            if (present(a) .and. row >= col) a(row, col) = a(row, col) + value
          end do
        end do
      end do
    end do
  end subroutine add_spring

  !> The top mode's damping per unit damping ratio, in scaled units: with the
  !> dashpots 2 zeta sqrt(m* k_n) along n and v a unit vector of the scaled
  !> problem, v^T M^-1/2 C M^-1/2 v = zeta sqrt(k_scale/m_scale) times this sum.
  pure real(dp) function modal_damping(scene, dof, mdof, springs, k_scale, m_scale, v) result(q)
    type(scene_type), intent(in) :: scene
    integer, intent(in) :: dof(:)
    real(dp), intent(in) :: mdof(:, :)
    type(spring_block_type), intent(in) :: springs(:)
    real(dp), intent(in) :: k_scale, m_scale, v(:)
    real(dp) :: rel
    integer :: k, nt
    nt = min(scene%dim, 3)
    q = 0.0_dp
    do k = 1, size(springs)
      associate(s => springs(k))
        rel = 0.0_dp
        if (s%a > 0) then
          if (.not. scene%fixed(s%a)) rel = -dot_product(s%n(:nt), v(dof(s%a)+1:dof(s%a)+nt)) &
            /sqrt(mdof(1, s%a))
        end if
        if (.not. scene%fixed(s%b)) rel = rel + dot_product(s%n(:nt), v(dof(s%b)+1:dof(s%b)+nt)) &
          /sqrt(mdof(1, s%b))
        q = q + dashpot_coefficient(1.0_dp, effective_mass(scene, s%b, s%a)/m_scale, s%k_n/k_scale)*rel**2
      end associate
    end do
  end function modal_damping

  !> The time step of a run at `n_per_period` steps per smallest period
  !> 2 pi/omega_max: the exact omega_max when it was computed, else the safe bound
  !> omega_bound (which gives the smaller step). Status invalid_input naming
  !> `n_per_period` when it is not finite and > 0 or the step overflows.
  pure subroutine assembly_step_for_n_per_period(crit, n_per_period, dt, status)
    !> The critical steps of the assembly.
    type(critical_step_type), intent(in) :: crit
    !> Steps per smallest period.
    real(dp), intent(in) :: n_per_period
    !> The time step.
    real(dp), intent(out) :: dt
    type(demstep_status_type), intent(out) :: status
    real(dp) :: omega
    dt = 0.0_dp
    if (.not. (ieee_is_finite(n_per_period) .and. n_per_period > 0.0_dp)) then
      call set_status(status, demstep_stat%invalid_input, "n_per_period: must be finite and > 0")
      return
    end if
    omega = crit%omega_bound
    if (crit%eigen_computed) omega = crit%omega_max
    dt = 2.0_dp*pi/omega/n_per_period
    if (.not. ieee_is_finite(dt)) then
      dt = 0.0_dp
      call set_status(status, demstep_stat%invalid_input, "n_per_period: the time step 2 pi/(omega_max " &
        //"n_per_period) overflows: n_per_period must be above "// &
        real_text(2.0_dp*pi/crit%omega_bound/huge(1.0_dp)))
      return
    end if
    status%stat = demstep_stat%ok
  end subroutine assembly_step_for_n_per_period

end module demstep_assembly
