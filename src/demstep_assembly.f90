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
  use demstep_kinds, only: dp
  use demstep_status, only: demstep_status_type, demstep_stat, set_status
  use demstep_scene, only: scene_type, contact_list, law_linear, effect_contacts, &
    effect_walls, effect_damping, effective_mass, tangent_stiffness
  use demstep_lapack, only: largest_eigenpair
  implicit none
  private

  public :: critical_time_steps

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
    real(dp) :: k_n = 0.0_dp, k_t = 0.0_dp, c = 0.0_dp
    real(dp) :: n(3) = 0.0_dp
  end type spring_block_type

contains

  !> The critical time steps of a scene at its current configuration.
  !> Status: invalid_input (no stiffness at all, bad Hertz option); lapack_failure.
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
    real(dp) :: lam, zeta, v_impact
    integer :: mode, limit, i, nfree, d
    mode = hertz_at_current
    if (present(hertz_mode)) mode = hertz_mode
    v_impact = 0.0_dp
    if (present(impact_velocity)) v_impact = impact_velocity
    limit = default_max_eigen_dof
    if (present(max_eigen_dof)) limit = max_eigen_dof
    if (mode == hertz_at_impact .and. .not. v_impact > 0.0_dp) then
      call set_status(status, demstep_stat%invalid_input, "Hertz linearisation at impact needs " &
        //"an impact velocity > 0")
      return
    end if
    d = scene%dim
    springs = linearise(scene, mode, v_impact)
    result%n_springs = size(springs)
    ! degrees of freedom: dim per free particle
    allocate(dof(scene%n), source=0)
    nfree = 0
    do i = 1, scene%n
      if (scene%fixed(i)) cycle
      nfree = nfree + 1
      dof(i) = (nfree - 1)*d
    end do
    result%n_dof = nfree*d
    if (result%n_dof == 0 .or. size(springs) == 0) then
      call set_status(status, demstep_stat%invalid_input, "the scene has no stiffness: no free " &
        //"particle touches a bond, a contact or a wall")
      return
    end if

    ! per-contact rule and the Gershgorin bound
    result%dt_contact_rule = huge(1.0_dp)
    allocate(rows(result%n_dof), source=0.0_dp)
    do i = 1, size(springs)
      associate(s => springs(i))
        result%dt_contact_rule = min(result%dt_contact_rule, &
          2.0_dp*sqrt(effective_mass(scene, s%i, s%j)/max(s%k_n, s%k_t)))
        call add_row_sums(scene, dof, s, rows)
      end associate
    end do
    result%omega_bound = sqrt(maxval(rows))
    result%dt_critical_bound = 2.0_dp/result%omega_bound

    ! exact omega_max from the dense mass-scaled stiffness matrix
    zeta = 0.0_dp
    if (scene%effects(effect_damping)) zeta = scene%damping_ratio
    if (result%n_dof <= limit) then
      allocate(a(result%n_dof, result%n_dof), source=0.0_dp)
      do i = 1, size(springs)
        call add_block(scene, dof, springs(i), a)
      end do
      allocate(vec(result%n_dof))
      call largest_eigenpair(a, lam, vec, status)
      if (status%stat /= demstep_stat%ok) return
      result%omega_max = sqrt(max(lam, 0.0_dp))
      if (.not. result%omega_max > 0.0_dp) then
        call set_status(status, demstep_stat%invalid_input, "the scene has no stiffness")
        return
      end if
      result%dt_critical_eigen = 2.0_dp/result%omega_max
      result%eigen_computed = .true.
      if (scene%effects(effect_damping)) then
        zeta = modal_damping(scene, dof, springs, vec)/(2.0_dp*result%omega_max)
      end if
      result%damping_ratio_top = zeta
      result%dt_critical_damped = result%dt_critical_eigen/(sqrt(1.0_dp + zeta**2) + zeta)
    else
      ! too large for the dense solver: the damped limit from the bound
      result%damping_ratio_top = zeta
      result%dt_critical_damped = result%dt_critical_bound/(sqrt(1.0_dp + zeta**2) + zeta)
    end if
    status%stat = demstep_stat%ok
  end subroutine critical_time_steps

  !> Every spring of the scene, linearised at the current configuration.
  function linearise(scene, mode, v_impact) result(springs)
    type(scene_type), intent(in) :: scene
    integer, intent(in) :: mode
    real(dp), intent(in) :: v_impact
    type(spring_block_type), allocatable :: springs(:)
    integer, allocatable :: pi(:), pj(:)
    real(dp), allocatable :: pn(:, :), pd(:)
    integer :: k, i, j, w, m, d
    real(dp) :: overlap, rs, kk, zeta
    d = scene%dim
    zeta = 0.0_dp
    if (scene%effects(effect_damping)) zeta = scene%damping_ratio
    m = size(scene%bonds, 2)
    allocate(springs(m))
    do k = 1, m
      springs(k)%i = scene%bonds(1, k)
      springs(k)%j = scene%bonds(2, k)
      springs(k)%k_n = scene%k_bond
      springs(k)%k_t = scene%k_bond_tangential
      springs(k)%n = scene%bond_normal(:, k)
      springs(k)%c = 2.0_dp*zeta*sqrt(effective_mass(scene, springs(k)%i, springs(k)%j)*scene%k_bond)
    end do
    if (scene%effects(effect_contacts)) then
        call contact_list(scene, pi, pj, pn, pd)
        do k = 1, size(pi)
          i = pi(k)
          j = pj(k)
          if (scene%fixed(i) .and. scene%fixed(j)) cycle
          rs = scene%radius(i)*scene%radius(j)/(scene%radius(i) + scene%radius(j))
          kk = contact_stiffness(scene, pd(k), rs, effective_mass(scene, i, j), mode, v_impact)
          springs = [springs, spring_block_type(i=i, j=j, k_n=kk, k_t=0.0_dp, &
            c=2.0_dp*zeta*sqrt(effective_mass(scene, i, j)*kk), n=pad(pn(:, k)))]
        end do
    end if
    if (scene%effects(effect_walls)) then
      do w = 1, size(scene%wall_normal, 2)
        do i = 1, scene%n
          if (scene%fixed(i)) cycle
          overlap = scene%radius(i) - dot_product(scene%x(:, i) - scene%wall_point(:, w), scene%wall_normal(:, w))
          if (.not. overlap > 0.0_dp) cycle
          kk = contact_stiffness(scene, overlap, scene%radius(i), scene%mass(i), mode, v_impact)
          springs = [springs, spring_block_type(i=i, j=0, k_n=kk, k_t=0.0_dp, &
            c=2.0_dp*zeta*sqrt(scene%mass(i)*kk), n=pad(scene%wall_normal(:, w)))]
        end do
      end do
    end if
  contains
    pure function pad(v) result(p)
      real(dp), intent(in) :: v(:)
      real(dp) :: p(3)
      p = 0.0_dp
      p(:size(v)) = v
    end function pad
  end function linearise

  !> Tangent stiffness of a contact at the current overlap, or (Hertz) at the
  !> largest overlap of an impact at v_impact.
  pure real(dp) function contact_stiffness(scene, overlap, rs, m_eff, mode, v_impact) result(k)
    type(scene_type), intent(in) :: scene
    real(dp), intent(in) :: overlap, rs, m_eff, v_impact
    integer, intent(in) :: mode
    real(dp) :: d
    d = overlap
    if (scene%law /= law_linear .and. mode == hertz_at_impact) &
      d = (15.0_dp*m_eff*v_impact**2/(16.0_dp*scene%e_star*sqrt(rs)))**0.4_dp
    k = tangent_stiffness(scene, d, rs)
  end function contact_stiffness

  !> The spring's 3x3 block k_n n n^T + k_t (I - n n^T).
  pure function block_of(s) result(b)
    type(spring_block_type), intent(in) :: s
    real(dp) :: b(3, 3)
    integer :: p
    b = (s%k_n - s%k_t)*spread(s%n, 2, 3)*spread(s%n, 1, 3)
    do p = 1, 3
      b(p, p) = b(p, p) + s%k_t
    end do
  end function block_of

  !> Add the spring to the row sums of |A| (an upper bound of A's row sums).
  subroutine add_row_sums(scene, dof, s, rows)
    type(scene_type), intent(in) :: scene
    integer, intent(in) :: dof(:)
    type(spring_block_type), intent(in) :: s
    real(dp), intent(inout) :: rows(:)
    real(dp) :: b(3, 3), colsum(3)
    integer :: d
    d = scene%dim
    b = abs(block_of(s))
    colsum(:d) = sum(b(:d, :d), dim=2)
    if (.not. scene%fixed(s%i)) then
      rows(dof(s%i)+1:dof(s%i)+d) = rows(dof(s%i)+1:dof(s%i)+d) + colsum(:d)/scene%mass(s%i)
      if (s%j > 0) then
        if (.not. scene%fixed(s%j)) rows(dof(s%i)+1:dof(s%i)+d) = rows(dof(s%i)+1:dof(s%i)+d) &
          + colsum(:d)/sqrt(scene%mass(s%i)*scene%mass(s%j))
      end if
    end if
    if (s%j > 0) then
      if (.not. scene%fixed(s%j)) then
        rows(dof(s%j)+1:dof(s%j)+d) = rows(dof(s%j)+1:dof(s%j)+d) + colsum(:d)/scene%mass(s%j)
        if (.not. scene%fixed(s%i)) rows(dof(s%j)+1:dof(s%j)+d) = rows(dof(s%j)+1:dof(s%j)+d) &
          + colsum(:d)/sqrt(scene%mass(s%i)*scene%mass(s%j))
      end if
    end if
  end subroutine add_row_sums

  !> Add the spring's blocks to the lower triangle of A = M^-1/2 K M^-1/2.
  subroutine add_block(scene, dof, s, a)
    type(scene_type), intent(in) :: scene
    integer, intent(in) :: dof(:)
    type(spring_block_type), intent(in) :: s
    real(dp), intent(inout) :: a(:, :)
    real(dp) :: b(3, 3)
    integer :: d, p, q, ri, rj
    logical :: free_i, free_j
    d = scene%dim
    b = block_of(s)
    free_i = .not. scene%fixed(s%i)
    free_j = .false.
    if (s%j > 0) free_j = .not. scene%fixed(s%j)
    if (free_i) then
      ri = dof(s%i)
      a(ri+1:ri+d, ri+1:ri+d) = a(ri+1:ri+d, ri+1:ri+d) + b(:d, :d)/scene%mass(s%i)
    end if
    if (free_j) then
      rj = dof(s%j)
      a(rj+1:rj+d, rj+1:rj+d) = a(rj+1:rj+d, rj+1:rj+d) + b(:d, :d)/scene%mass(s%j)
    end if
    if (free_i .and. free_j) then
      ! off-diagonal block, placed in the lower triangle
      do q = 1, d
        do p = 1, d
          if (ri > rj) then
            a(ri+p, rj+q) = a(ri+p, rj+q) - b(p, q)/sqrt(scene%mass(s%i)*scene%mass(s%j))
          else
            a(rj+q, ri+p) = a(rj+q, ri+p) - b(p, q)/sqrt(scene%mass(s%i)*scene%mass(s%j))
          end if
        end do
      end do
    end if
  end subroutine add_block

  !> v^T M^-1/2 C M^-1/2 v for a unit vector v: the dashpots act along n.
  pure real(dp) function modal_damping(scene, dof, springs, v) result(q)
    type(scene_type), intent(in) :: scene
    integer, intent(in) :: dof(:)
    type(spring_block_type), intent(in) :: springs(:)
    real(dp), intent(in) :: v(:)
    real(dp) :: rel
    integer :: k, d
    d = scene%dim
    q = 0.0_dp
    do k = 1, size(springs)
      associate(s => springs(k))
        rel = 0.0_dp
        if (.not. scene%fixed(s%i)) rel = dot_product(s%n(:d), v(dof(s%i)+1:dof(s%i)+d))/sqrt(scene%mass(s%i))
        if (s%j > 0) then
          if (.not. scene%fixed(s%j)) rel = rel - dot_product(s%n(:d), v(dof(s%j)+1:dof(s%j)+d)) &
            /sqrt(scene%mass(s%j))
        end if
        q = q + s%c*rel**2
      end associate
    end do
  end function modal_damping

end module demstep_assembly
