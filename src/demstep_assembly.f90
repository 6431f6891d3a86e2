!> The stability limit of a whole scene at its current configuration.
!>
!> The scene is linearised: every bond, particle contact and wall contact is a
!> spring block B = k_n n n^T + k_t (I - n n^T) between two particles (or one
!> particle and the ground); fixed particles are ground. The smallest period of
!> the assembly is 2 pi/omega_max with omega_max^2 the largest eigenvalue of
!> A = M^-1/2 K M^-1/2, and the undamped central-difference limit is
!> dt = 2/omega_max. Four estimates side by side:
!> - the per-contact rule min 2 sqrt(m*/k): NOT safe, a particle held by several
!>   springs vibrates faster than any one of them;
!> - a rigorous bound: Gershgorin's row sums of |A| bound omega_max^2 from above,
!>   so 2/omega_bound <= the true limit; cost linear in interactions;
!> - the exact omega_max from LAPACK (dsyevr, largest eigenpair only);
!> - the damped limit of the lagged dashpot, (2/omega)(sqrt(1 + z^2) - z), with z
!>   the modal damping ratio of the top mode (its eigenvector's Rayleigh quotient
!>   of the dashpot matrix).
!> Hertz contacts are linearised with their tangent stiffness 2 E* sqrt(R* d), at
!> the current overlap d or at the overlap an impact at a given speed would reach,
!> d = (15 m* v^2 / (16 E* sqrt(R*)))^(2/5).
module demstep_assembly
  use demstep_kinds, only: dp, pi
  use demstep_status, only: demstep_status_type, demstep_stat, set_status
  use demstep_text, only: int_text, real_text
  use demstep_scene, only: scene_type, contact_list, law_linear, effect_contacts, &
    effect_walls, effect_damping, effective_mass, tangent_stiffness, max_damping_ratio
  use, intrinsic :: ieee_arithmetic, only: ieee_is_finite
  use demstep_lapack, only: largest_eigenpair
  implicit none
  private

  public :: critical_time_steps, assembly_step_for_n_per_period

  !> Hertz linearisation at the current overlap, or at an impact's largest overlap.
  integer, parameter, public :: hertz_at_current = 1, hertz_at_impact = 2
  !> Largest number of degrees of freedom given to the dense eigensolver by default.
  integer, parameter, public :: default_max_eigen_dof = 4000

  !> The four estimates and what they rest on.
  type, public :: critical_step_type
    !> Degrees of freedom (dim times free particles) and springs (bonds + contacts).
    integer :: n_dof = 0, n_springs = 0
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

  !> A linearised spring between particles i and j (j = 0: the ground).
  type :: spring_block_type
    integer :: i = 0, j = 0
    real(dp) :: k_n = 0.0_dp, k_t = 0.0_dp
    real(dp) :: n(3) = 0.0_dp
  end type spring_block_type

contains

  !> The critical time steps of a scene at its current configuration.
  !>
  !> The eigenproblem is solved in scaled units (stiffness over the largest
  !> spring stiffness, masses over the smallest free mass), so any finite
  !> stiffness and any mass with a finite inverse give finite results unless
  !> omega_max itself overflows.
  !> Status invalid_input, the message starting with the variable to change:
  !> `fixed:` (every particle fixed), `effects:` (no bonds and no contact effect),
  !> `position:` (no free particle touches a spring; coincident particles; too
  !> many contacts), `e_star:` (a Hertz stiffness overflows), `damping_ratio:`
  !> (above `max_damping_ratio`, or a damped limit that underflows), `mass:`
  !> (omega_max overflows), bad Hertz options; lapack_failure.
  subroutine critical_time_steps(scene, result, status, hertz_mode, impact_velocity, max_eigen_dof)
    type(scene_type), intent(in) :: scene
    type(critical_step_type), intent(out) :: result
    type(demstep_status_type), intent(out) :: status
    !> `hertz_at_current` (default) or `hertz_at_impact` with impact_velocity > 0.
    integer, intent(in), optional :: hertz_mode
    real(dp), intent(in), optional :: impact_velocity
    !> Above this many degrees of freedom the eigensolver is skipped (default 4000).
    integer, intent(in), optional :: max_eigen_dof
    type(spring_block_type), allocatable :: springs(:)
    integer, allocatable :: dof(:)
    real(dp), allocatable :: a(:, :), vec(:), rows(:)
    real(dp) :: lam, zeta, v_impact, k_scale, m_scale, rate
    integer :: mode, limit, i, nfree, d
    logical :: touches
    mode = hertz_at_current
    if (present(hertz_mode)) mode = hertz_mode
    v_impact = 0.0_dp
    if (present(impact_velocity)) v_impact = impact_velocity
    limit = default_max_eigen_dof
    if (present(max_eigen_dof)) limit = max_eigen_dof
    if (mode == hertz_at_impact .and. .not. (v_impact > 0.0_dp .and. ieee_is_finite(v_impact))) then
      call set_status(status, demstep_stat%invalid_input, "impact_velocity: the Hertz linearisation " &
        //"at impact needs a finite impact velocity > 0")
      return
    end if
    zeta = 0.0_dp
    if (scene%effects(effect_damping)) zeta = scene%damping_ratio
    if (.not. (zeta >= 0.0_dp .and. zeta <= max_damping_ratio)) then
      call set_status(status, demstep_stat%invalid_input, "damping_ratio: must be in [0, 1e100]")
      return
    end if
    d = scene%dim
    ! degrees of freedom: dim per free particle
    allocate(dof(scene%n), source=0)
    nfree = 0
    m_scale = huge(1.0_dp)
    do i = 1, scene%n
      if (scene%fixed(i)) cycle
      nfree = nfree + 1
      dof(i) = (nfree - 1)*d
      m_scale = min(m_scale, scene%mass(i))
    end do
    result%n_dof = nfree*d
    if (nfree == 0) then
      call set_status(status, demstep_stat%invalid_input, "fixed: every particle is fixed: the " &
        //"scene has no stiffness")
      return
    end if
    call linearise(scene, mode, v_impact, springs, status)
    if (status%stat /= demstep_stat%ok) return
    result%n_springs = size(springs)
    touches = .false.
    k_scale = 0.0_dp
    do i = 1, size(springs)
      touches = touches .or. .not. scene%fixed(springs(i)%i)
      if (springs(i)%j > 0) touches = touches .or. .not. scene%fixed(springs(i)%j)
      k_scale = max(k_scale, springs(i)%k_n, springs(i)%k_t)
    end do
    if (.not. (touches .and. k_scale > 0.0_dp)) then
      if (size(scene%bonds, 2) == 0 .and. .not. (scene%effects(effect_contacts) .or. &
          scene%effects(effect_walls))) then
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

    ! per-contact rule and the Gershgorin bound (scaled)
    result%dt_contact_rule = huge(1.0_dp)
    allocate(rows(result%n_dof), source=0.0_dp)
    do i = 1, size(springs)
      associate(s => springs(i))
        result%dt_contact_rule = min(result%dt_contact_rule, &
          2.0_dp*sqrt(effective_mass(scene, s%i, s%j))/sqrt(max(s%k_n, s%k_t)))
        call add_row_sums(scene, dof, s, k_scale, m_scale, rows)
      end associate
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
        call add_block(scene, dof, springs(i), k_scale, m_scale, a)
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
      if (scene%effects(effect_damping)) then
        zeta = zeta*modal_damping(scene, dof, springs, k_scale, m_scale, vec)/(2.0_dp*sqrt(lam))
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
  end subroutine critical_time_steps

  !> The lagged dashpot's limit dt/(sqrt(1 + z^2) + z), without overflow for large z.
  pure real(dp) function damped_limit(dt, z) result(limit)
    real(dp), intent(in) :: dt, z
    if (z <= 1.0_dp) then
      limit = dt/(sqrt(1.0_dp + z**2) + z)
    else
      limit = (dt/z)/(sqrt(1.0_dp + (1.0_dp/z)**2) + 1.0_dp)
    end if
  end function damped_limit

  !> Every spring of the scene, linearised at the current configuration: counted,
  !> allocated once and filled (linear in springs).
  subroutine linearise(scene, mode, v_impact, springs, status)
    type(scene_type), intent(in) :: scene
    integer, intent(in) :: mode
    real(dp), intent(in) :: v_impact
    type(spring_block_type), allocatable, intent(out) :: springs(:)
    type(demstep_status_type), intent(out) :: status
    integer, allocatable :: pi(:), pj(:)
    real(dp), allocatable :: pn(:, :), pd(:)
    integer :: k, i, j, w, m, n_contacts, n_walls
    real(dp) :: overlap, rs, kk
    m = size(scene%bonds, 2)
    n_contacts = 0
    n_walls = 0
    if (scene%effects(effect_contacts)) then
      call contact_list(scene, pi, pj, pn, pd, status)
      if (status%stat /= demstep_stat%ok) return
      do k = 1, size(pi)
        if (.not. (scene%fixed(pi(k)) .and. scene%fixed(pj(k)))) n_contacts = n_contacts + 1
      end do
    end if
    if (scene%effects(effect_walls)) then
      do w = 1, size(scene%wall_normal, 2)
        do i = 1, scene%n
          if (.not. scene%fixed(i) .and. wall_overlap(i, w) > 0.0_dp) n_walls = n_walls + 1
        end do
      end do
    end if
    allocate(springs(m + n_contacts + n_walls))
    do k = 1, m
      springs(k)%i = scene%bonds(1, k)
      springs(k)%j = scene%bonds(2, k)
      springs(k)%k_n = scene%k_bond
      springs(k)%k_t = scene%k_bond_tangential
      springs(k)%n = scene%bond_normal(:, k)
    end do
    if (scene%effects(effect_contacts)) then
      do k = 1, size(pi)
        i = pi(k)
        j = pj(k)
        if (scene%fixed(i) .and. scene%fixed(j)) cycle
        rs = scene%radius(i)*scene%radius(j)/(scene%radius(i) + scene%radius(j))
        kk = contact_stiffness(scene, pd(k), rs, effective_mass(scene, i, j), mode, v_impact)
        if (.not. ieee_is_finite(kk)) then
          call stiffness_overflow(i, j)
          return
        end if
        m = m + 1
        springs(m) = spring_block_type(i=i, j=j, k_n=kk, k_t=0.0_dp, n=pn(:, k))
      end do
    end if
    if (scene%effects(effect_walls)) then
      do w = 1, size(scene%wall_normal, 2)
        do i = 1, scene%n
          if (scene%fixed(i)) cycle
          overlap = wall_overlap(i, w)
          if (.not. overlap > 0.0_dp) cycle
          kk = contact_stiffness(scene, overlap, scene%radius(i), scene%mass(i), mode, v_impact)
          if (.not. ieee_is_finite(kk)) then
            call stiffness_overflow(i, 0)
            return
          end if
          m = m + 1
          springs(m) = spring_block_type(i=i, j=0, k_n=kk, k_t=0.0_dp, n=scene%wall_normal(:, w))
        end do
      end do
    end if
    status%stat = demstep_stat%ok
  contains
    pure real(dp) function wall_overlap(i, w)
      integer, intent(in) :: i, w
      wall_overlap = scene%radius(i) - dot_product(scene%x(:, i) - scene%wall_point(:, w), &
        scene%wall_normal(:, w))
    end function wall_overlap
    subroutine stiffness_overflow(i, j)
      integer, intent(in) :: i, j
      character(len=:), allocatable :: who
      if (j == 0) then
        who = "particle "//int_text(i)//" on a wall"
      else
        who = "particles "//int_text(i)//" and "//int_text(j)
      end if
      if (mode == hertz_at_impact) then
        call set_status(status, demstep_stat%invalid_input, "e_star: the Hertz tangent stiffness " &
          //"2 E* sqrt(R* d) of "//who//" overflows (lower e_star or impact_velocity)")
      else
        call set_status(status, demstep_stat%invalid_input, "e_star: the Hertz tangent stiffness " &
          //"2 E* sqrt(R* d) of "//who//" overflows (lower e_star)")
      end if
    end subroutine stiffness_overflow
  end subroutine linearise

  !> Tangent stiffness of a contact at the current overlap, or (Hertz) at the
  !> largest overlap of an impact at v_impact, d = (15 m* v^2/(16 E* sqrt(R*)))^(2/5)
  !> (through logarithms: no overflow on the way).
  pure real(dp) function contact_stiffness(scene, overlap, rs, m_eff, mode, v_impact) result(k)
    type(scene_type), intent(in) :: scene
    real(dp), intent(in) :: overlap, rs, m_eff, v_impact
    integer, intent(in) :: mode
    real(dp) :: d
    d = overlap
    if (scene%law /= law_linear .and. mode == hertz_at_impact) &
      d = exp(0.4_dp*(log(15.0_dp/16.0_dp) + log(m_eff) + 2.0_dp*log(v_impact) - log(scene%e_star) &
        - 0.5_dp*log(rs)))
    k = tangent_stiffness(scene, d, rs)
  end function contact_stiffness

  !> The spring's 3x3 block k_n n n^T + k_t (I - n n^T), stiffness divided by k_scale.
  pure function block_of(s, k_scale) result(b)
    type(spring_block_type), intent(in) :: s
    real(dp), intent(in) :: k_scale
    real(dp) :: b(3, 3), kn, kt
    integer :: p
    kn = s%k_n/k_scale
    kt = s%k_t/k_scale
    b = (kn - kt)*spread(s%n, 2, 3)*spread(s%n, 1, 3)
    do p = 1, 3
      b(p, p) = b(p, p) + kt
    end do
  end function block_of

  !> Add the spring to the row sums of |A'| (an upper bound of A's row sums), A'
  !> the scaled M'^-1/2 K' M'^-1/2 with K' = K/k_scale and M' = M/m_scale.
  subroutine add_row_sums(scene, dof, s, k_scale, m_scale, rows)
    type(scene_type), intent(in) :: scene
    integer, intent(in) :: dof(:)
    type(spring_block_type), intent(in) :: s
    real(dp), intent(in) :: k_scale, m_scale
    real(dp), intent(inout) :: rows(:)
    real(dp) :: b(3, 3), colsum(3), mi, mj
    integer :: d
    d = scene%dim
    b = abs(block_of(s, k_scale))
    colsum(:d) = sum(b(:d, :d), dim=2)
    mi = scene%mass(s%i)/m_scale
    mj = 1.0_dp
    if (s%j > 0) mj = scene%mass(s%j)/m_scale
    if (.not. scene%fixed(s%i)) then
      rows(dof(s%i)+1:dof(s%i)+d) = rows(dof(s%i)+1:dof(s%i)+d) + colsum(:d)/mi
      if (s%j > 0) then
        if (.not. scene%fixed(s%j)) rows(dof(s%i)+1:dof(s%i)+d) = rows(dof(s%i)+1:dof(s%i)+d) &
          + colsum(:d)/(sqrt(mi)*sqrt(mj))
      end if
    end if
    if (s%j > 0) then
      if (.not. scene%fixed(s%j)) then
        rows(dof(s%j)+1:dof(s%j)+d) = rows(dof(s%j)+1:dof(s%j)+d) + colsum(:d)/mj
        if (.not. scene%fixed(s%i)) rows(dof(s%j)+1:dof(s%j)+d) = rows(dof(s%j)+1:dof(s%j)+d) &
          + colsum(:d)/(sqrt(mi)*sqrt(mj))
      end if
    end if
  end subroutine add_row_sums

  !> Add the spring's blocks to the lower triangle of the scaled A'.
  subroutine add_block(scene, dof, s, k_scale, m_scale, a)
    type(scene_type), intent(in) :: scene
    integer, intent(in) :: dof(:)
    type(spring_block_type), intent(in) :: s
    real(dp), intent(in) :: k_scale, m_scale
    real(dp), intent(inout) :: a(:, :)
    real(dp) :: b(3, 3), mi, mj
    integer :: d, p, q, ri, rj
    logical :: free_i, free_j
    d = scene%dim
    b = block_of(s, k_scale)
    free_i = .not. scene%fixed(s%i)
    free_j = .false.
    if (s%j > 0) free_j = .not. scene%fixed(s%j)
    mi = scene%mass(s%i)/m_scale
    mj = 1.0_dp
    if (s%j > 0) mj = scene%mass(s%j)/m_scale
    if (free_i) then
      ri = dof(s%i)
      a(ri+1:ri+d, ri+1:ri+d) = a(ri+1:ri+d, ri+1:ri+d) + b(:d, :d)/mi
    end if
    if (free_j) then
      rj = dof(s%j)
      a(rj+1:rj+d, rj+1:rj+d) = a(rj+1:rj+d, rj+1:rj+d) + b(:d, :d)/mj
    end if
    if (free_i .and. free_j) then
      ! off-diagonal block, placed in the lower triangle
      do q = 1, d
        do p = 1, d
          if (ri > rj) then
            a(ri+p, rj+q) = a(ri+p, rj+q) - b(p, q)/(sqrt(mi)*sqrt(mj))
          else
            a(rj+q, ri+p) = a(rj+q, ri+p) - b(p, q)/(sqrt(mi)*sqrt(mj))
          end if
        end do
      end do
    end if
  end subroutine add_block

  !> The top mode's damping per unit damping ratio, in scaled units: with the
  !> dashpots 2 zeta sqrt(m* k_n) along n and v a unit vector of the scaled
  !> problem, v^T M^-1/2 C M^-1/2 v = zeta sqrt(k_scale/m_scale) times this sum.
  pure real(dp) function modal_damping(scene, dof, springs, k_scale, m_scale, v) result(q)
    type(scene_type), intent(in) :: scene
    integer, intent(in) :: dof(:)
    type(spring_block_type), intent(in) :: springs(:)
    real(dp), intent(in) :: k_scale, m_scale, v(:)
    real(dp) :: rel, c
    integer :: k, d
    d = scene%dim
    q = 0.0_dp
    do k = 1, size(springs)
      associate(s => springs(k))
        rel = 0.0_dp
        if (.not. scene%fixed(s%i)) rel = dot_product(s%n(:d), v(dof(s%i)+1:dof(s%i)+d)) &
          /sqrt(scene%mass(s%i)/m_scale)
        if (s%j > 0) then
          if (.not. scene%fixed(s%j)) rel = rel - dot_product(s%n(:d), v(dof(s%j)+1:dof(s%j)+d)) &
            /sqrt(scene%mass(s%j)/m_scale)
        end if
        c = 2.0_dp*sqrt(effective_mass(scene, s%i, s%j)/m_scale)*sqrt(s%k_n/k_scale)
        q = q + c*rel**2
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
