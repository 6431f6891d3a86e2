!> The stepper: a scene integrated with the central-difference (leapfrog)
!> scheme, translations and (with the `rotation` effect) rotations.
!>
!> Physics on demand: the effects a scene switches on each become one force term,
!> assembled once by `scene_run`; nothing in the step loop tests which effects
!> are on. Bonds are always on (a scene without bonds has none). Every contact
!> force comes from the interaction kernel (`demstep_interaction`), the one the
!> stability analysis linearises.
!>
!> Conventions:
!> - leapfrog: x_n = x_{n-1} + v_{n-1/2} dt, forces at x_n, v_{n+1/2} = v_{n-1/2} + F/m dt,
!>   and w_{n+1/2} = w_{n-1/2} + T/I dt; periodic positions are wrapped each step;
!> - contacts: overlap d = r_i + r_j - |x_j - x_i| > 0 (nearest image); normal force
!>   from the law, tangential spring incremental (history kept while in contact,
!>   turned with the contact plane, Coulomb cap when friction >= 0);
!> - bonds: linear about the initial configuration (small strain), normal stiffness
!>   k_n along the initial direction and optional tangential stiffness k_t; with
!>   a bond model (`scene_set_bond_model`) the kernel's springs (normal, shear at
!>   the model's lever arms, bending, twisting) on the stretch and the rotations
!>   accumulated since the start, and the model's dashpots;
!> - rolling and twisting springs (contacts and walls): incremental on the
!>   relative rotation, the rolling moment capped at rolling_friction R* F_n;
!> - viscous damping: dashpots on every contact and wall contact (normal,
!>   tangential on the contact point's slip velocity, rolling and twisting on
!>   the relative angular velocity; `contact_dashpots`), on bonds (normal), and
!>   a drag of each particle to the ground, all acting on the velocities of the
!>   previous half step (lagged: one spring's limit becomes
!>   (2/omega)(sqrt(1 + zeta^2) - zeta); an assembly's is `assembly_critical_steps`');
!> - local (Cundall) damping: F <- F - alpha |F| sign(v_{n-1/2}) per component
!>   (torques likewise);
!> - rigid bodies (`bodies`, clumps): each member's force f and torque t act on
!>   its body as f and t + d x f (d = x_member - x_com), the body's velocity
!>   and angular velocity are stepped with its mass and inertia tensor J
!>   (global axes, turned with the body), members move rigidly: x_com by v dt,
!>   offsets and J by the rotation exp([w dt]x) (Rodrigues), member velocities
!>   v + w x d. The gyroscopic term w x J w is left out (second order in the
!>   amplitude: the linearised stability limit is the same). Forces between
!>   members of one body cancel in the sums.
module demstep_stepper
  use demstep_kinds, only: dp, i8
  use demstep_status, only: demstep_status_type, demstep_stat, set_status
  use demstep_text, only: int_text
  use demstep_progress, only: progress_type
  use demstep_interaction, only: contact_law, reduced_radius, normal_force, &
    normal_energy, dashpot_coefficient, contact_forces, rolling_moments, contact_product, add_bond_forces, &
    contact_arm, cross
  use demstep_scene_data, only: scene_type, scene_summary_type, scene_effect, effective_mass, law_parameters, &
    contact_values, wall_values, contact_dashpots, has_tangential, has_rolling, check_scene_damping, &
    wrap_positions
  use demstep_scene_bonds, only: scene_bond_laws, scene_bonds_damped
  use demstep_bonds, only: bond_law_type
  use demstep_neighbours, only: search_type, prepare_search, find_contacts, find_wall_contacts, &
    contact_limit, history_size
  use demstep_bodies, only: body_set_type, check_bodies
  use, intrinsic :: ieee_arithmetic, only: ieee_is_finite
  implicit none
  private

  public :: scene_run

  !> Scratch of a run: forces, torques, inverse masses, contact lists, shear history.
  type :: work_type
    real(dp), allocatable :: f(:, :), t(:, :), inv_mass(:), inv_inertia(:), v_old(:, :), w_old(:, :)
    type(search_type) :: s
    !> Shear history of the previous step's detected contacts, by particle i
    !> (CSR: hist_start(i) to hist_start(i+1) - 1), and of the explicit list's rows.
    integer, allocatable :: hist_start(:), hist_j(:)
    real(dp), allocatable :: hist_us(:, :), row_us(:, :)
    !> History of each (wall, particle) pair (history_size, walls, n) and
    !> whether it was in contact at the last step.
    real(dp), allocatable :: wall_us(:, :, :)
    logical, allocatable :: wall_on(:, :)
    !> Time over which the velocities moved the contacts since the last force
    !> evaluation (0 at the first).
    real(dp) :: shear_dt = 0.0_dp
    !> With a bond model: each particle's rotation since the start (3, n) and
    !> each bond's law.
    real(dp), allocatable :: theta(:, :)
    type(bond_law_type), allocatable :: bond_laws(:)
    !> Rigid bodies: whether the run has them; per body its mass, centre,
    !> inertia tensor and its inverse (global axes), velocity and angular
    !> velocity (half steps, and the previous ones for the energy), fixed.
    logical :: rigid = .false.
    real(dp), allocatable :: b_mass(:), b_com(:, :), b_j(:, :, :), b_jinv(:, :, :), b_v(:, :), b_w(:, :), &
      b_v_old(:, :), b_w_old(:, :)
    logical, allocatable :: b_fixed(:)
  end type work_type

  abstract interface
    !> One force term: adds its forces (and torques) to work%f (work%t).
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

contains

  !> Step a scene `steps` times with time step dt, recording energy every
  !> `sample_every` steps (default: about 1000 samples). Status `blow_up` when the
  !> state became non-finite, the energy grew 1e6-fold or the contacts passed
  !> `contact_limit` (the summary says when); `invalid_input` for a bad dt or
  !> step count, a damping ratio above `max_damping_ratio`, or an initial energy
  !> that overflows. `progress` (optional) is told the steps done every few
  !> thousand particle-steps. With `bodies` (made for this scene) the
  !> particles move as those rigid bodies, their velocities first projected
  !> on the bodies' (momentum and angular momentum kept); the bodies' centres,
  !> tensors and offsets follow the run. Status invalid_input naming `bodies`
  !> when they were made for another scene.
  subroutine scene_run(scene, dt, steps, summary, status, sample_every, progress, bodies)
    type(scene_type), intent(inout) :: scene
    real(dp), intent(in) :: dt
    integer(i8), intent(in) :: steps
    type(scene_summary_type), intent(out) :: summary
    type(demstep_status_type), intent(out) :: status
    integer(i8), intent(in), optional :: sample_every
    class(progress_type), intent(inout), optional :: progress
    type(body_set_type), intent(inout), optional :: bodies
    type(term_type), allocatable :: terms(:)
    type(work_type) :: work
    integer(i8) :: step, every, report_every
    integer :: t, ns, i
    real(dp) :: e, scale
    logical :: rotation, periodic, torques
    if (.not. (ieee_is_finite(dt) .and. dt > 0.0_dp) .or. steps < 0_i8) then
      call set_status(status, demstep_stat%invalid_input, "dt must be > 0 and steps >= 0")
      return
    end if
    call check_scene_damping(scene, status)
    if (status%stat /= demstep_stat%ok) return
    rotation = scene%effects(scene_effect%rotation) .and. scene%dim > 1
    periodic = any(scene%periodic)
    ! only tangential, rolling and twisting springs make torques
    torques = (has_tangential(scene) .or. has_rolling(scene)) .and. (scene%effects(scene_effect%contacts) &
      .or. scene%effects(scene_effect%walls)) .or. (scene%bond_model > 0 .and. size(scene%bonds, 2) > 0)
    every = max(1_i8, steps/1000_i8)
    if (present(sample_every)) every = max(1_i8, sample_every)
    ! progress every 1e5 particle-steps or so: a clock read is then negligible
    report_every = max(1_i8, 100000_i8/max(1_i8, int(scene%n, i8)))
    call prepare(scene, work)
    if (present(bodies)) then
      call prepare_bodies(scene, bodies, rotation, work, status)
      if (status%stat /= demstep_stat%ok) return
      ! lever arms make torques of every force
      torques = .true.
    end if
    terms = assemble(scene)
    allocate(summary%sample_time(steps/every + 2), summary%sample_energy(steps/every + 2))
    ! energy at the start: forces at x_0 give the first half-step pair v_{-1/2}, v_{1/2}
    work%shear_dt = 0.0_dp
    summary%energy_initial = scene_energy(scene, work, terms, dt, rotation, advance=.false., bodies=bodies)
    if (.not. ieee_is_finite(summary%energy_initial)) then
      call set_status(status, demstep_stat%invalid_input, "the initial energy (kinetic " &
        //"+ elastic + gravitational) overflows: velocities, masses, stiffness or overlaps too large", where="velocity")
      return
    end if
    work%shear_dt = dt
    ns = 1
    summary%sample_time(1) = 0.0_dp
    summary%sample_energy(1) = summary%energy_initial
    scale = max(abs(summary%energy_initial), tiny(1.0_dp))
    status%stat = demstep_stat%ok
    if (present(progress)) call progress%start("steps", steps)
    do step = 1_i8, steps
      if (work%rigid) then
        call rigid_positions(scene, bodies, work, dt, rotation)
      else
        scene%x = scene%x + scene%v*dt
      end if
      if (periodic) call wrap_positions(scene)
      if (mod(step, every) == 0_i8 .or. step == steps .or. work%s%too_many) then
        ! a sample: E = kinetic (v_{n-1/2} . v_{n+1/2}) + potential at x_n
        e = scene_energy(scene, work, terms, dt, rotation, advance=.true., bodies=bodies)
        summary%steps = step
        if (ieee_is_finite(e)) then
          ns = ns + 1
          summary%sample_time(ns) = real(step, dp)*dt
          summary%sample_energy(ns) = e
          summary%energy_drift = max(summary%energy_drift, min(huge(1.0_dp), abs(e - summary%energy_initial)/scale))
        end if
        if (.not. (ieee_is_finite(e) .and. all(ieee_is_finite(scene%x))) .or. &
            abs(e - summary%energy_initial) > blow_up_factor*scale .or. work%s%too_many) then
          ! (a non-finite energy is not sampled: the drift stays finite)
          summary%blew_up = .true.
          if (work%s%too_many) then
            call set_status(status, demstep_stat%blow_up, "the scene blew up at step "// &
              int_text(step)//": more than "//int_text(contact_limit)//" contacts")
          else
            call set_status(status, demstep_stat%blow_up, "the scene blew up at step "// &
              int_text(step))
          end if
          exit
        end if
      else
        work%f = 0.0_dp
        if (torques) work%t = 0.0_dp
        do t = 1, size(terms)
          call terms(t)%add(scene, work)
        end do
        if (work%rigid) then
          call rigid_velocities(scene, bodies, work, dt, rotation)
          work%b_v = work%b_v_old
          work%b_w = work%b_w_old
          call member_velocities(scene, bodies, work, rotation)
        else
          do i = 1, scene%n
            scene%v(:, i) = scene%v(:, i) + work%f(:, i)*(work%inv_mass(i)*dt)
          end do
          if (rotation) then
            do i = 1, scene%n
              scene%w(:, i) = scene%w(:, i) + work%t(:, i)*(work%inv_inertia(i)*dt)
            end do
          end if
        end if
        summary%steps = step
      end if
      if (present(progress) .and. mod(step, report_every) == 0_i8) call progress%update(step)
    end do
    if (present(progress)) call progress%finish()
    summary%energy_final = summary%sample_energy(ns)
    summary%sample_time = summary%sample_time(:ns)
    summary%sample_energy = summary%sample_energy(:ns)
    summary%max_overlap = work%s%max_overlap
    summary%max_contacts = work%s%max_contacts
  end subroutine scene_run

  !> Total energy at the current positions: elastic + gravitational, and kinetic
  !> as the product of the half-step velocities around x_n (for the undamped
  !> linear scheme this energy is exactly conserved). With `advance` the velocity
  !> step is taken (scene%v holds v_{n-1/2} and becomes v_{n+1/2}); without, scene%v
  !> is taken as v_{1/2} at the start and v_{-1/2} is reconstructed.
  function scene_energy(scene, work, terms, dt, rotation, advance, bodies) result(energy)
    type(scene_type), intent(inout) :: scene
    type(work_type), intent(inout) :: work
    !> The run's bodies (with work%rigid).
    type(body_set_type), intent(in), optional :: bodies
    type(term_type), intent(in) :: terms(:)
    real(dp), intent(in) :: dt
    logical, intent(in) :: rotation, advance
    real(dp) :: energy, sgn
    integer :: t, i
    work%f = 0.0_dp
    work%t = 0.0_dp
    do t = 1, size(terms)
      call terms(t)%add(scene, work)
    end do
    sgn = merge(1.0_dp, -1.0_dp, advance)
    if (work%rigid) then
      ! the bodies' kinetic energy, as for particles: M v.v' + w.J w'
      call rigid_velocities(scene, bodies, work, sgn*dt, rotation)
      energy = 0.0_dp
      do i = 1, size(work%b_mass)
        if (work%b_fixed(i)) cycle
        energy = energy + 0.5_dp*work%b_mass(i)*dot_product(work%b_v(:, i), work%b_v_old(:, i)) &
          + 0.5_dp*dot_product(work%b_w(:, i), matmul(work%b_j(:, :, i), work%b_w_old(:, i)))
      end do
      energy = energy + potential_energy(scene, work)
      if (advance) then
        work%b_v = work%b_v_old
        work%b_w = work%b_w_old
        call member_velocities(scene, bodies, work, rotation)
      end if
      return
    end if
    do i = 1, scene%n
      work%v_old(:, i) = scene%v(:, i) + sgn*work%f(:, i)*(work%inv_mass(i)*dt)
    end do
    energy = 0.0_dp
    do i = 1, scene%n
      energy = energy + 0.5_dp*scene%mass(i)*dot_product(scene%v(:, i), work%v_old(:, i))
    end do
    if (rotation) then
      do i = 1, scene%n
        work%w_old(:, i) = scene%w(:, i) + sgn*work%t(:, i)*(work%inv_inertia(i)*dt)
        energy = energy + 0.5_dp*scene%inertia(i)*dot_product(scene%w(:, i), work%w_old(:, i))
      end do
    end if
    energy = energy + potential_energy(scene, work)
    if (advance) then
      scene%v = work%v_old
      if (rotation) scene%w = work%w_old
    end if
  end function scene_energy

  !> Elastic and gravitational energy at the current positions (contact lists current).
  function potential_energy(scene, work) result(u)
    type(scene_type), intent(in) :: scene
    type(work_type), intent(in) :: work
    real(dp) :: u, d(3), f_n, kc(4), dn
    integer :: k, i, j, w
    u = 0.0_dp
    if (scene%bond_model > 0) u = model_bonds_energy(scene, work)
    do k = 1, size(scene%bonds, 2)
      if (scene%bond_model > 0) exit
      i = scene%bonds(1, k)
      j = scene%bonds(2, k)
      d = scene%x(:, j) - scene%x(:, i) - scene%bond_rest(:, k)
      if (any(scene%periodic)) d = bond_stretch(scene, k)
      dn = dot_product(scene%bond_normal(:, k), d)
      u = u + 0.5_dp*(scene%k_bond*dn**2 + scene%k_bond_tangential*(dot_product(d, d) - dn**2))
    end do
    if (scene%effects(scene_effect%contacts)) then
      associate(s => work%s)
        do k = 1, s%n_pairs
          i = s%pair_i(k)
          j = s%pair_j(k)
          call contact_values(scene, s%pair_c(k), i, j, s%pair_d(k), f_n, kc)
          u = u + pair_energy(scene, s%pair_c(k), i, j, s%pair_d(k)) + history_energy(kc, s%pair_n(:, k), &
            s%pair_us(:, k))
        end do
      end associate
    end if
    if (scene%effects(scene_effect%walls)) then
      do k = 1, work%s%n_walls
        i = work%s%wall_i(k)
        w = work%s%wall_k(k)
        call wall_values(scene, i, work%s%wall_d(k), f_n, kc)
        u = u + normal_energy(scene%law, scene%k_normal, scene%e_star, work%s%wall_d(k), &
          scene%radius(i)) + history_energy(kc, scene%wall_normal(:, w), work%wall_us(:, w, i))
      end do
    end if
    if (scene%effects(scene_effect%gravity)) then
      do i = 1, scene%n
        if (.not. scene%fixed(i)) u = u - scene%mass(i)*dot_product(scene%gravity, scene%x(:, i))
      end do
    end if
  end function potential_energy

  !> Elastic energy of the bonds of a bond model, q^T K q/2 with the kernel's
  !> block of each bond on (0, theta_i, stretch, theta_j).
  pure real(dp) function model_bonds_energy(scene, work) result(u)
    type(scene_type), intent(in) :: scene
    type(work_type), intent(in) :: work
    integer :: k, i, j
    real(dp) :: d(3), y_i(3), y_j(3), t_i(3), t_j(3)
    u = 0.0_dp
    do k = 1, size(scene%bonds, 2)
      i = scene%bonds(1, k)
      j = scene%bonds(2, k)
      call bond_kernel(scene, work, k, d, y_i, t_i, y_j, t_j)
      u = u + 0.5_dp*(dot_product(y_j, d) + dot_product(t_i, work%theta(:, i)) + &
        dot_product(t_j, work%theta(:, j)))
    end do
  end function model_bonds_energy

  !> Elastic energy of a particle contact's normal spring at overlap d.
  pure real(dp) function pair_energy(scene, c, i, j, d) result(u)
    type(scene_type), intent(in) :: scene
    integer, intent(in) :: c, i, j
    real(dp), intent(in) :: d
    real(dp) :: p(4)
    if (c > 0) then
      u = normal_energy(contact_law%linear, scene%contact_k(1, c), 0.0_dp, d, 0.0_dp)
      return
    end if
    p = law_parameters(scene, i, j)
    u = normal_energy(scene%law, p(1), p(3), d, reduced_radius(scene%radius(i), scene%radius(j)))
  end function pair_energy

  !> Elastic energy of a contact's history: shear (k_t), rolling (k_r) and
  !> twisting (k_w) springs; kc = (k_n, k_t, k_r, k_w), n the normal.
  pure real(dp) function history_energy(kc, n, us) result(u)
    real(dp), intent(in) :: kc(4), n(3), us(history_size)
    real(dp) :: tw
    tw = dot_product(us(4:6), n)
    u = 0.5_dp*(kc(2)*dot_product(us(1:3), us(1:3)) + kc(3)*(dot_product(us(4:6), us(4:6)) - tw**2) &
      + kc(4)*tw**2)
  end function history_energy

  !> x_j - x_i - rest of bond k (nearest image).
  !> The kernel's block of bond k of a bond model on (0, theta_i, stretch d,
  !> theta_j): the forces and torques y_i, t_i on i and y_j, t_j on j, for the
  !> stepper's forces and its energy alike.
  pure subroutine bond_kernel(scene, work, k, d, y_i, t_i, y_j, t_j)
    type(scene_type), intent(in) :: scene
    type(work_type), intent(in) :: work
    integer, intent(in) :: k
    real(dp), intent(out) :: d(3), y_i(3), t_i(3), y_j(3), t_j(3)
    real(dp), parameter :: zero(3) = 0.0_dp
    integer :: i, j
    i = scene%bonds(1, k)
    j = scene%bonds(2, k)
    d = bond_stretch(scene, k)
    associate(law => work%bond_laws(k))
      call contact_product(scene%bond_normal(:, k), law%k, law%arm(1), law%arm(2), 1.0_dp, 1.0_dp, &
        0.0_dp, zero, work%theta(:, i), d, work%theta(:, j), y_i, t_i, y_j, t_j)
    end associate
  end subroutine bond_kernel

  pure function bond_stretch(scene, k) result(u)
    type(scene_type), intent(in) :: scene
    integer, intent(in) :: k
    real(dp) :: u(3), box(3)
    u = scene%x(:, scene%bonds(2, k)) - scene%x(:, scene%bonds(1, k))
    if (any(scene%periodic)) then
      box = scene%cell_hi - scene%cell_lo
      where (scene%periodic) u = u - box*anint((u - scene%bond_rest(:, k))/box)
    end if
    u = u - scene%bond_rest(:, k)
  end function bond_stretch

  ! ---- force terms ---------------------------------------------------------

  !> The contact list of the current configuration, with each continuing
  !> contact's shear history.
  subroutine detect_contacts(scene, work)
    type(scene_type), intent(in) :: scene
    type(work_type), intent(inout) :: work
    integer :: k, i, j, p
    call find_contacts(scene, work%s)
    associate(s => work%s)
      if (scene%given_contacts) then
        do k = 1, s%n_pairs
          s%pair_us(:, k) = work%row_us(:, s%pair_c(k))
        end do
      else
        do k = 1, s%n_pairs
          i = s%pair_i(k)
          j = s%pair_j(k)
          do p = work%hist_start(i), work%hist_start(i + 1) - 1
            if (work%hist_j(p) == j) then
              s%pair_us(:, k) = work%hist_us(:, p)
              exit
            end if
          end do
        end do
      end if
    end associate
  end subroutine detect_contacts

  !> Keep the shear displacements of this step's contacts for the next step
  !> (counting sort by the first particle: linear in contacts).
  subroutine save_history(scene, work)
    type(scene_type), intent(in) :: scene
    type(work_type), intent(inout) :: work
    integer :: k, i, p
    associate(s => work%s)
      if (scene%given_contacts) then
        work%row_us = 0.0_dp
        do k = 1, s%n_pairs
          work%row_us(:, s%pair_c(k)) = s%pair_us(:, k)
        end do
        return
      end if
      if (size(work%hist_j) < s%n_pairs) then
        deallocate(work%hist_j, work%hist_us)
        allocate(work%hist_j(size(s%pair_i)), work%hist_us(history_size, size(s%pair_i)))
      end if
      work%hist_start = 0
      do k = 1, s%n_pairs
        i = s%pair_i(k)
        work%hist_start(i + 1) = work%hist_start(i + 1) + 1
      end do
      work%hist_start(1) = 1
      do i = 2, scene%n + 1
        work%hist_start(i) = work%hist_start(i) + work%hist_start(i - 1)
      end do
      do k = 1, s%n_pairs
        i = s%pair_i(k)
        p = work%hist_start(i)
        work%hist_j(p) = s%pair_j(k)
        work%hist_us(:, p) = s%pair_us(:, k)
        work%hist_start(i) = p + 1
      end do
      do i = scene%n, 1, -1
        work%hist_start(i + 1) = work%hist_start(i)
      end do
      work%hist_start(1) = 1
    end associate
  end subroutine save_history

  !> Normal forces only (no tangential springs): the kernel's law along n.
  subroutine contacts_normal(scene, work)
    type(scene_type), intent(in) :: scene
    type(work_type), intent(inout) :: work
    integer :: k, i, j
    real(dp) :: f(3), f_n, kc(4)
    associate(s => work%s)
      do k = 1, s%n_pairs
        i = s%pair_i(k)
        j = s%pair_j(k)
        call contact_values(scene, s%pair_c(k), i, j, s%pair_d(k), f_n, kc)
        f = f_n*s%pair_n(:, k)
        work%f(:, i) = work%f(:, i) - f
        work%f(:, j) = work%f(:, j) + f
      end do
    end associate
  end subroutine contacts_normal

  !> Normal, tangential, rolling and twisting springs with torques, from the
  !> kernel; then the history is kept.
  subroutine contacts_full(scene, work)
    type(scene_type), intent(in) :: scene
    type(work_type), intent(inout) :: work
    integer :: k, i, j
    real(dp) :: f(3), t_i(3), t_j(3), f_n, kc(4), us(history_size), h
    h = work%shear_dt
    associate(s => work%s)
      do k = 1, s%n_pairs
        i = s%pair_i(k)
        j = s%pair_j(k)
        call contact_values(scene, s%pair_c(k), i, j, s%pair_d(k), f_n, kc)
        us = s%pair_us(:, k)
        call interaction_forces(scene, s%pair_n(:, k), f_n, kc, contact_arm(scene%radius(i), s%pair_d(k)), &
          contact_arm(scene%radius(j), s%pair_d(k)), &
          reduced_radius(scene%radius(i), scene%radius(j)), (scene%v(:, j) - scene%v(:, i))*h, &
          scene%w(:, i)*h, scene%w(:, j)*h, us, f, t_i, t_j)
        s%pair_us(:, k) = us
        work%f(:, i) = work%f(:, i) - f
        work%f(:, j) = work%f(:, j) + f
        work%t(:, i) = work%t(:, i) + t_i
        work%t(:, j) = work%t(:, j) + t_j
      end do
    end associate
    call save_history(scene, work)
  end subroutine contacts_full

  !> One interaction's elastic force on j (-f on i) and torques, history us
  !> (shear, relative rotation) updated: the kernel's tangential spring with
  !> Coulomb's cap, and the rolling and twisting springs with the rolling cap
  !> rolling_friction R* F_n. dx, dtheta_i, dtheta_j: increments since the
  !> last step (i = 0, the ground, passes zeros).
  pure subroutine interaction_forces(scene, n, f_n, kc, arm_i, arm_j, rs, dx, dtheta_i, dtheta_j, &
      us, f, t_i, t_j)
    type(scene_type), intent(in) :: scene
    real(dp), intent(in) :: n(3), f_n, kc(4), arm_i, arm_j, rs, dx(3), dtheta_i(3), dtheta_j(3)
    real(dp), intent(inout) :: us(history_size)
    real(dp), intent(out) :: f(3), t_i(3), t_j(3)
    real(dp) :: m(3), cap
    call contact_forces(n, f_n, kc(2), scene%friction, arm_i, arm_j, dx, dtheta_i, dtheta_j, us(1:3), &
      f, t_i, t_j)
    if (kc(3) > 0.0_dp .or. kc(4) > 0.0_dp) then
      cap = -1.0_dp
      if (scene%rolling_friction >= 0.0_dp) cap = scene%rolling_friction*rs*max(f_n, 0.0_dp)
      call rolling_moments(n, kc(3), kc(4), cap, dtheta_j - dtheta_i, us(4:6), m)
      t_i = t_i + m
      t_j = t_j - m
    end if
  end subroutine interaction_forces

  !> Dashpots (`contact_dashpots`: normal, tangential, rolling, twisting) on the
  !> relative velocities of the previous half step, through the kernel.
  subroutine contacts_damping(scene, work)
    type(scene_type), intent(in) :: scene
    type(work_type), intent(inout) :: work
    integer :: k, i, j
    real(dp) :: f_n, kc(4), cd(4), y_i(3), y_j(3), t_i(3), t_j(3)
    associate(s => work%s)
      do k = 1, s%n_pairs
        i = s%pair_i(k)
        j = s%pair_j(k)
        call contact_values(scene, s%pair_c(k), i, j, s%pair_d(k), f_n, kc)
        cd = contact_dashpots(scene, s%pair_c(k), i, j, kc)
        call contact_product(s%pair_n(:, k), cd, contact_arm(scene%radius(i), s%pair_d(k)), &
          contact_arm(scene%radius(j), s%pair_d(k)), 1.0_dp, 1.0_dp, &
          0.0_dp, scene%v(:, i), scene%w(:, i), scene%v(:, j), scene%w(:, j), y_i, t_i, y_j, t_j)
        work%f(:, i) = work%f(:, i) - y_i
        work%f(:, j) = work%f(:, j) - y_j
        work%t(:, i) = work%t(:, i) - t_i
        work%t(:, j) = work%t(:, j) - t_j
      end do
    end associate
  end subroutine contacts_damping

  !> The wall contact list: particles overlapping a wall, with the history of
  !> each continuing (wall, particle) contact (a new one starts from zero).
  subroutine detect_walls(scene, work)
    type(scene_type), intent(in) :: scene
    type(work_type), intent(inout) :: work
    integer :: k
    call find_wall_contacts(scene, work%s)
    associate(s => work%s)
      do k = 1, s%n_walls
        if (.not. work%wall_on(s%wall_k(k), s%wall_i(k))) work%wall_us(:, s%wall_k(k), s%wall_i(k)) = 0.0_dp
      end do
      work%wall_on = .false.
      do k = 1, s%n_walls
        work%wall_on(s%wall_k(k), s%wall_i(k)) = .true.
      end do
    end associate
  end subroutine detect_walls

  !> Wall forces (the wall is the ground end, n into the domain, R* = r): the
  !> law's normal force, and the tangential, rolling and twisting springs.
  subroutine walls_full(scene, work)
    type(scene_type), intent(in) :: scene
    type(work_type), intent(inout) :: work
    integer :: k, i, w
    real(dp) :: f(3), t_i(3), t_j(3), f_n, kc(4), h
    real(dp), parameter :: zero(3) = 0.0_dp
    h = work%shear_dt
    associate(s => work%s)
      do k = 1, s%n_walls
        i = s%wall_i(k)
        w = s%wall_k(k)
        call wall_values(scene, i, s%wall_d(k), f_n, kc)
        call interaction_forces(scene, scene%wall_normal(:, w), f_n, kc, 0.0_dp, &
          contact_arm(scene%radius(i), s%wall_d(k)), &
          scene%radius(i), scene%v(:, i)*h, zero, scene%w(:, i)*h, work%wall_us(:, w, i), f, t_i, t_j)
        work%f(:, i) = work%f(:, i) + f
        work%t(:, i) = work%t(:, i) + t_j
      end do
    end associate
  end subroutine walls_full

  !> Wall dashpots, through the kernel with the wall as the ground end.
  subroutine walls_damping(scene, work)
    type(scene_type), intent(in) :: scene
    type(work_type), intent(inout) :: work
    integer :: k, i
    real(dp) :: f_n, kc(4), cd(4), y_i(3), y_j(3), t_i(3), t_j(3)
    real(dp), parameter :: zero(3) = 0.0_dp
    associate(s => work%s)
      do k = 1, s%n_walls
        i = s%wall_i(k)
        call wall_values(scene, i, s%wall_d(k), f_n, kc)
        cd = contact_dashpots(scene, 0, i, 0, kc)
        call contact_product(scene%wall_normal(:, s%wall_k(k)), cd, 0.0_dp, &
          contact_arm(scene%radius(i), s%wall_d(k)), 1.0_dp, &
          1.0_dp, 0.0_dp, zero, zero, scene%v(:, i), scene%w(:, i), y_i, t_i, y_j, t_j)
        work%f(:, i) = work%f(:, i) - y_j
        work%t(:, i) = work%t(:, i) - t_j
      end do
    end associate
  end subroutine walls_damping

  !> Drag of every free particle to the ground, F = -drag v (previous half step).
  subroutine drag_term(scene, work)
    type(scene_type), intent(in) :: scene
    type(work_type), intent(inout) :: work
    work%f = work%f - scene%drag*scene%v
  end subroutine drag_term

  !> Bonds: the kernel's bond forces (nearest image in a periodic cell).
  subroutine bonds_term(scene, work)
    type(scene_type), intent(in) :: scene
    type(work_type), intent(inout) :: work
    if (any(scene%periodic)) then
      call add_bond_forces(size(scene%bonds, 2), scene%n, scene%bonds, scene%x, scene%bond_rest, &
        scene%bond_normal, scene%k_bond, scene%k_bond_tangential, work%f, &
        box=merge(scene%cell_hi - scene%cell_lo, 0.0_dp, scene%periodic))
    else
      call add_bond_forces(size(scene%bonds, 2), scene%n, scene%bonds, scene%x, scene%bond_rest, &
        scene%bond_normal, scene%k_bond, scene%k_bond_tangential, work%f)
    end if
  end subroutine bonds_term

  !> Bond dashpots along the bond's initial direction (normal ratio).
  subroutine bonds_damping(scene, work)
    type(scene_type), intent(in) :: scene
    type(work_type), intent(inout) :: work
    integer :: k, i, j
    real(dp) :: n0(3), c, vn
    do k = 1, size(scene%bonds, 2)
      i = scene%bonds(1, k)
      j = scene%bonds(2, k)
      n0 = scene%bond_normal(:, k)
      c = dashpot_coefficient(scene%damping_ratio, effective_mass(scene, i, j), scene%k_bond)
      vn = dot_product(scene%v(:, j) - scene%v(:, i), n0)
      work%f(:, i) = work%f(:, i) + c*vn*n0
      work%f(:, j) = work%f(:, j) - c*vn*n0
    end do
  end subroutine bonds_damping

  !> Bonds of a bond model: the kernel's forces -K q on q = (0, theta_i,
  !> stretch, theta_j), the rotations first advanced by the last half step's
  !> spins (rotation effect on).
  subroutine model_bonds_term(scene, work)
    type(scene_type), intent(in) :: scene
    type(work_type), intent(inout) :: work
    integer :: k, i, j
    real(dp) :: d(3), y_i(3), y_j(3), t_i(3), t_j(3)
    if (scene%effects(scene_effect%rotation) .and. scene%dim > 1) work%theta = work%theta + scene%w*work%shear_dt
    do k = 1, size(scene%bonds, 2)
      i = scene%bonds(1, k)
      j = scene%bonds(2, k)
      call bond_kernel(scene, work, k, d, y_i, t_i, y_j, t_j)
      work%f(:, i) = work%f(:, i) - y_i
      work%f(:, j) = work%f(:, j) - y_j
      work%t(:, i) = work%t(:, i) - t_i
      work%t(:, j) = work%t(:, j) - t_j
    end do
  end subroutine model_bonds_term

  !> The dashpots of a bond model's bonds on the previous half step's
  !> velocities, through the kernel.
  subroutine model_bonds_damping(scene, work)
    type(scene_type), intent(in) :: scene
    type(work_type), intent(inout) :: work
    integer :: k, i, j
    real(dp) :: y_i(3), y_j(3), t_i(3), t_j(3)
    do k = 1, size(scene%bonds, 2)
      i = scene%bonds(1, k)
      j = scene%bonds(2, k)
      associate(law => work%bond_laws(k))
        call contact_product(scene%bond_normal(:, k), law%c, law%arm(1), law%arm(2), 1.0_dp, 1.0_dp, &
          0.0_dp, scene%v(:, i), scene%w(:, i), scene%v(:, j), scene%w(:, j), y_i, t_i, y_j, t_j)
      end associate
      work%f(:, i) = work%f(:, i) - y_i
      work%f(:, j) = work%f(:, j) - y_j
      work%t(:, i) = work%t(:, i) - t_i
      work%t(:, j) = work%t(:, j) - t_j
    end do
  end subroutine model_bonds_damping

  subroutine gravity_term(scene, work)
    type(scene_type), intent(in) :: scene
    type(work_type), intent(inout) :: work
    integer :: i
    do i = 1, scene%n
      work%f(:, i) = work%f(:, i) + scene%mass(i)*scene%gravity
    end do
  end subroutine gravity_term

  !> Cundall's local damping: each force (and torque) component reduced by
  !> alpha |F| against the half-step velocity.
  subroutine local_damping_term(scene, work)
    type(scene_type), intent(in) :: scene
    type(work_type), intent(inout) :: work
    ! sign of v, and 0 for a particle at rest
    work%f = work%f - scene%local_damping*abs(work%f)*(merge(1.0_dp, 0.0_dp, scene%v > 0.0_dp) &
      - merge(1.0_dp, 0.0_dp, scene%v < 0.0_dp))
    if (scene%effects(scene_effect%rotation)) work%t = work%t - scene%local_damping*abs(work%t) &
      *(merge(1.0_dp, 0.0_dp, scene%w > 0.0_dp) - merge(1.0_dp, 0.0_dp, scene%w < 0.0_dp))
  end subroutine local_damping_term

  !> The force terms of a scene's effects, in order; local damping last.
  function assemble(scene) result(terms)
    type(scene_type), intent(in) :: scene
    type(term_type), allocatable :: terms(:)
    type(term_type) :: list(12)
    integer :: n
    n = 0
    if (size(scene%bonds, 2) > 0 .and. scene%bond_model > 0) then
      call push(model_bonds_term)
      if (scene_bonds_damped(scene)) call push(model_bonds_damping)
    else if (size(scene%bonds, 2) > 0) then
      call push(bonds_term)
      if (scene%effects(scene_effect%damping)) call push(bonds_damping)
    end if
    if (scene%effects(scene_effect%contacts)) then
      call push(detect_contacts)
      if (has_tangential(scene) .or. has_rolling(scene)) then
        call push(contacts_full)
      else
        call push(contacts_normal)
      end if
      if (scene%effects(scene_effect%damping)) call push(contacts_damping)
    end if
    if (scene%effects(scene_effect%walls)) then
      call push(detect_walls)
      call push(walls_full)
      if (scene%effects(scene_effect%damping)) call push(walls_damping)
    end if
    if (scene%effects(scene_effect%damping) .and. scene%drag > 0.0_dp) call push(drag_term)
    if (scene%effects(scene_effect%gravity)) call push(gravity_term)
    if (scene%effects(scene_effect%local_damping)) call push(local_damping_term)
    terms = list(:n)
  contains
    subroutine push(term)
      procedure(force_term) :: term
      n = n + 1
      list(n)%add => term
    end subroutine push
  end function assemble

  ! ---- rigid bodies ----------------------------------------------------------

  !> The run's body data from `bodies`: inverse tensors, and the bodies'
  !> velocities from their members' momentum and angular momentum (members'
  !> velocities then set to the rigid ones). Status invalid_input naming
  !> `bodies` when they were made for another scene.
  subroutine prepare_bodies(scene, bodies, rotation, work, status)
    type(scene_type), intent(inout) :: scene
    type(body_set_type), intent(in) :: bodies
    logical, intent(in) :: rotation
    type(work_type), intent(inout) :: work
    type(demstep_status_type), intent(out) :: status
    real(dp), allocatable :: p(:, :), l(:, :), ms(:)
    integer :: i, b, nb
    call check_bodies(scene, bodies, status)
    if (status%stat /= demstep_stat%ok) return
    nb = bodies%n
    work%rigid = .true.
    work%b_mass = bodies%mass
    work%b_com = bodies%com
    work%b_j = bodies%inertia
    work%b_fixed = bodies%fixed
    allocate(work%b_jinv(3, 3, nb))
    do b = 1, nb
      work%b_jinv(:, :, b) = inverse3(bodies%inertia(:, :, b), scene%dim)
    end do
    allocate(p(3, nb), l(3, nb), ms(nb), source=0.0_dp)
    do i = 1, scene%n
      b = bodies%body_of(i)
      ms(b) = ms(b) + scene%mass(i)
      p(:, b) = p(:, b) + scene%mass(i)*scene%v(:, i)
      l(:, b) = l(:, b) + scene%mass(i)*cross(bodies%offset(:, i), scene%v(:, i)) + scene%inertia(i)*scene%w(:, i)
    end do
    allocate(work%b_v(3, nb), work%b_w(3, nb), work%b_v_old(3, nb), work%b_w_old(3, nb), source=0.0_dp)
    do b = 1, nb
      if (bodies%fixed(b)) cycle
      work%b_v(:, b) = p(:, b)/ms(b)
      ! (the members' angular momentum about the centre, less the translation's)
      if (rotation) work%b_w(:, b) = matmul(work%b_jinv(:, :, b), l(:, b))
    end do
    call member_velocities(scene, bodies, work, rotation)
    status%stat = demstep_stat%ok
  end subroutine prepare_bodies

  !> The bodies' velocities a step dt on (dt < 0: back), into b_v_old and
  !> b_w_old, from the members' forces and torques (f, t + d x f).
  subroutine rigid_velocities(scene, bodies, work, dt, rotation)
    type(scene_type), intent(in) :: scene
    type(body_set_type), intent(in) :: bodies
    type(work_type), intent(inout) :: work
    real(dp), intent(in) :: dt
    logical, intent(in) :: rotation
    real(dp), allocatable :: f(:, :), t(:, :)
    integer :: i, b
    allocate(f(3, size(work%b_mass)), t(3, size(work%b_mass)), source=0.0_dp)
    do i = 1, scene%n
      b = bodies%body_of(i)
      f(:, b) = f(:, b) + work%f(:, i)
      t(:, b) = t(:, b) + work%t(:, i) + cross(bodies%offset(:, i), work%f(:, i))
    end do
    do b = 1, size(work%b_mass)
      if (work%b_fixed(b)) then
        work%b_v_old(:, b) = 0.0_dp
        work%b_w_old(:, b) = 0.0_dp
        cycle
      end if
      work%b_v_old(:, b) = work%b_v(:, b) + f(:, b)*(dt/work%b_mass(b))
      work%b_w_old(:, b) = work%b_w(:, b)
      if (rotation) work%b_w_old(:, b) = work%b_w(:, b) + matmul(work%b_jinv(:, :, b), t(:, b))*dt
    end do
  end subroutine rigid_velocities

  !> Members' velocities from their bodies': v + w x d, and w.
  subroutine member_velocities(scene, bodies, work, rotation)
    type(scene_type), intent(inout) :: scene
    type(body_set_type), intent(in) :: bodies
    type(work_type), intent(in) :: work
    logical, intent(in) :: rotation
    integer :: i, b
    do i = 1, scene%n
      b = bodies%body_of(i)
      scene%v(:, i) = work%b_v(:, b) + cross(work%b_w(:, b), bodies%offset(:, i))
      if (rotation) scene%w(:, i) = work%b_w(:, b)
    end do
  end subroutine member_velocities

  !> Move the bodies a step: centres by v dt, offsets and tensors turned by
  !> exp([w dt]x); members placed at centre + offset.
  subroutine rigid_positions(scene, bodies, work, dt, rotation)
    type(scene_type), intent(inout) :: scene
    type(body_set_type), intent(inout) :: bodies
    type(work_type), intent(inout) :: work
    real(dp), intent(in) :: dt
    logical, intent(in) :: rotation
    real(dp), allocatable :: q(:, :, :)
    integer :: i, b
    allocate(q(3, 3, size(work%b_mass)))
    do b = 1, size(work%b_mass)
      q(:, :, b) = rotation_matrix(work%b_w(:, b)*dt)
      if (work%b_fixed(b)) cycle
      work%b_com(:, b) = work%b_com(:, b) + work%b_v(:, b)*dt
      if (rotation) then
        work%b_j(:, :, b) = matmul(q(:, :, b), matmul(work%b_j(:, :, b), transpose(q(:, :, b))))
        work%b_jinv(:, :, b) = matmul(q(:, :, b), matmul(work%b_jinv(:, :, b), transpose(q(:, :, b))))
      end if
    end do
    do i = 1, scene%n
      b = bodies%body_of(i)
      if (work%b_fixed(b)) cycle
      if (rotation) bodies%offset(:, i) = matmul(q(:, :, b), bodies%offset(:, i))
      scene%x(:, i) = work%b_com(:, b) + bodies%offset(:, i)
    end do
    bodies%com = work%b_com
    bodies%inertia = work%b_j
  end subroutine rigid_positions

  !> The rotation by the vector p (angle |p| about p/|p|), Rodrigues'
  !> formula (its coefficients by their series below 1e-4 rad).
  pure function rotation_matrix(p) result(q)
    real(dp), intent(in) :: p(3)
    real(dp) :: q(3, 3), a, s, c, k(3, 3)
    integer :: i
    a = norm2(p)
    if (a < 1.0e-4_dp) then
      s = 1.0_dp - a**2/6.0_dp
      c = 0.5_dp - a**2/24.0_dp
    else
      s = sin(a)/a
      c = (1.0_dp - cos(a))/a**2
    end if
    k = reshape([0.0_dp, p(3), -p(2), -p(3), 0.0_dp, p(1), p(2), -p(1), 0.0_dp], [3, 3])
    q = s*k + c*matmul(k, k)
    do i = 1, 3
      q(i, i) = q(i, i) + 1.0_dp
    end do
  end function rotation_matrix

  !> The inverse of an inertia tensor as the rotations of a `dim`-dimensional
  !> body see it (3D: the whole tensor, by its adjugate; 2D: 1/J_zz alone).
  pure function inverse3(j, dim) result(v)
    real(dp), intent(in) :: j(3, 3)
    integer, intent(in) :: dim
    real(dp) :: v(3, 3), det
    v = 0.0_dp
    if (dim == 2) then
      v(3, 3) = 1.0_dp/j(3, 3)
    else if (dim == 3) then
      v(1, :) = cross(j(:, 2), j(:, 3))
      v(2, :) = cross(j(:, 3), j(:, 1))
      v(3, :) = cross(j(:, 1), j(:, 2))
      det = dot_product(j(:, 1), v(1, :))
      v = v/det
    end if
  end function inverse3

  !> Allocate the scratch of a run.
  subroutine prepare(scene, work)
    type(scene_type), intent(in) :: scene
    type(work_type), intent(out) :: work
    allocate(work%f(3, scene%n), work%t(3, scene%n), work%v_old(3, scene%n), &
      work%w_old(3, scene%n), source=0.0_dp)
    allocate(work%inv_mass(scene%n), work%inv_inertia(scene%n))
    work%inv_mass = merge(0.0_dp, 1.0_dp/scene%mass, scene%fixed)
    work%inv_inertia = merge(0.0_dp, 1.0_dp/scene%inertia, scene%fixed)
    allocate(work%hist_start(scene%n + 1), source=1)
    allocate(work%hist_j(64), work%hist_us(history_size, 64))
    allocate(work%row_us(history_size, size(scene%contact_pairs, 2)), source=0.0_dp)
    allocate(work%wall_us(history_size, size(scene%wall_normal, 2), scene%n), source=0.0_dp)
    allocate(work%wall_on(size(scene%wall_normal, 2), scene%n), source=.false.)
    allocate(work%theta(3, scene%n), source=0.0_dp)
    if (scene%bond_model > 0) work%bond_laws = scene_bond_laws(scene)
    call prepare_search(scene, work%s)
  end subroutine prepare

end module demstep_stepper
