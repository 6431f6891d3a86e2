!> One interaction kernel for the stepper and the stability analysis.
!>
!> Every interaction of a scene (particle pair, particle and wall, bond) is a
!> contact between two bodies i and j with a unit normal n from i to j, a normal
!> spring and a tangential spring acting at the contact point, which lies at
!> `arm_i n` from the centre of i and at `-arm_j n` from the centre of j (the
!> radii for a particle pair; 0 for a wall (body i, the ground) and for the
!> central bonds of `k_bond`, which join centres; a bond model's own arms, as
!> its code places the bond, in `demstep_bonds`). The relative displacement of the contact point is
!>   u_c = u_j - u_i + arm_j n x theta_j + arm_i n x theta_i,
!> the force on j is f = F_n n - k_t u_s (u_s the tangential part of u_c, kept
!> incrementally with its history) and -f on i; the torques are
!> -arm_i n x f on i and -arm_j n x f on j.
!>
!> The linearisation of exactly this force about a state without shear load is
!> the 12 x 12 block on (u_i, theta_i, u_j, theta_j) of `contact_block`:
!>   K = k_n b_n^T b_n + k_t B_t^T B_t - (F_n/l) B_p^T B_p,
!> b_n = [-n^T, 0, n^T, 0], B_t = [-P, arm_i N, P, arm_j N], B_p = [-P, 0, P, 0],
!> P = I - n n^T, N = [n]x; the last term is the pre-stress (geometric)
!> stiffness of a loaded normal spring of length l whose direction turns.
module demstep_interaction
  use demstep_kinds, only: dp, i8
  use demstep_words, only: word_index, word_of
  implicit none
  private

  public :: reduced_radius, reduced_mass, normal_force, normal_stiffness, tangential_stiffness, &
    normal_energy, dashpot_coefficient, wall_overlap, contact_block, contact_end_blocks, contact_product, &
    contact_product_arms, contact_products, contact_products_listed, contact_products_add, mixed_stiffness, &
    contact_abs_springs, &
    contact_forces, rolling_moments, contact_arm, hooke_size_factor, &
    add_bond_forces, dof_components, hertz_e_star, mindlin_g_star, cross

  !> Contact laws, as components of a parameter: `contact_law%hertz`.
  type, public :: contact_law_enum
    !> F = k_n d, tangential k_t.
    integer :: linear = 1
    !> F = (4/3) E* sqrt(R* d) d, tangential (Mindlin) 8 G* sqrt(R* d).
    integer :: hertz = 2
  end type contact_law_enum
  !> The contact laws by name.
  type(contact_law_enum), parameter, public :: contact_law = contact_law_enum()
  !> Their words, in code order (`contact_law_from_name`, `contact_law_name`).
  character(len=*), parameter, public :: contact_law_names(2) = [character(len=6) :: "linear", "hertz"]
  public :: contact_law_from_name, contact_law_name
  !> Springs per chunk of the kernel's loop (`spring_pass`): measured at
  !> 125 000 spheres (`bench_product`), 8 and 16 were fastest, 4 and 32 slower.
  integer, parameter :: pass_chunk = 8

contains

  !> R* = r_i r_j/(r_i + r_j), without overflow (a wall: pass r_j = huge).
  elemental real(dp) function reduced_radius(ri, rj) result(rs)
    real(dp), intent(in) :: ri, rj
    rs = min(ri, rj)/(1.0_dp + min(ri, rj)/max(ri, rj))
  end function reduced_radius

  !> m* = m_i m_j/(m_i + m_j) as m_a/(1 + m_a/m_b), m_a the lighter (no under- or
  !> overflow); an infinite (fixed, ground) partner is passed as huge.
  elemental real(dp) function reduced_mass(mi, mj) result(m)
    real(dp), intent(in) :: mi, mj
    if (mj >= huge(1.0_dp)) then
      m = mi
    else if (mi >= huge(1.0_dp)) then
      m = mj
    else
      m = min(mi, mj)/(1.0_dp + min(mi, mj)/max(mi, mj))
    end if
  end function reduced_mass

  !> How LIGGGHTS' Hooke stiffness depends on a contact's own R* and m*:
  !> k_n = 16/15 sqrt(R*) Y* (15 m* V^2/(16 sqrt(R*) Y*))^(1/5)
  !> (normal_model_hooke.h:269) is R*^(2/5) m*^(1/5) times a factor of the
  !> materials and V alone; this returns R*^(2/5) m*^(1/5) (in logarithms).
  elemental real(dp) function hooke_size_factor(rs, m) result(f)
    real(dp), intent(in) :: rs, m
    f = exp(0.4_dp*log(rs) + 0.2_dp*log(m))
  end function hooke_size_factor

  !> Normal force magnitude at overlap d: k d (linear) or (4/3) E* sqrt(R*) d^(3/2).
  elemental real(dp) function normal_force(law, k, e_star, d, rs) result(f)
    integer, intent(in) :: law
    real(dp), intent(in) :: k, e_star, d, rs
    if (law == contact_law%linear) then
      f = k*d
    else
      f = (4.0_dp/3.0_dp)*e_star*sqrt(rs)*d**1.5_dp
    end if
  end function normal_force

  !> dF_n/dd at overlap d: k (linear) or 2 E* sqrt(R* d) (Hertz).
  elemental real(dp) function normal_stiffness(law, k, e_star, d, rs) result(kn)
    integer, intent(in) :: law
    real(dp), intent(in) :: k, e_star, d, rs
    if (law == contact_law%linear) then
      kn = k
    else
      kn = 2.0_dp*e_star*sqrt(rs*d)
    end if
  end function normal_stiffness

  !> Tangential stiffness at overlap d: k_t (linear) or Mindlin's 8 G* sqrt(R* d) (Hertz).
  elemental real(dp) function tangential_stiffness(law, kt, g_star, d, rs) result(k)
    integer, intent(in) :: law
    real(dp), intent(in) :: kt, g_star, d, rs
    if (law == contact_law%linear) then
      k = kt
    else
      k = 8.0_dp*g_star*sqrt(rs*max(d, 0.0_dp))
    end if
  end function tangential_stiffness

  !> Hertz's effective modulus of two materials (Young's modulus, Poisson's
  !> ratio): 1/E* = (1 - nu_i^2)/E_i + (1 - nu_j^2)/E_j.
  elemental real(dp) function hertz_e_star(e_i, nu_i, e_j, nu_j) result(e_star)
    real(dp), intent(in) :: e_i, nu_i, e_j, nu_j
    e_star = 1.0_dp/((1.0_dp - nu_i**2)/e_i + (1.0_dp - nu_j**2)/e_j)
  end function hertz_e_star

  !> Mindlin's effective shear modulus of two materials: 1/G* = (2 - nu_i)/G_i +
  !> (2 - nu_j)/G_j with G = E/(2 (1 + nu)).
  elemental real(dp) function mindlin_g_star(e_i, nu_i, e_j, nu_j) result(g_star)
    real(dp), intent(in) :: e_i, nu_i, e_j, nu_j
    g_star = 1.0_dp/(2.0_dp*(2.0_dp - nu_i)*(1.0_dp + nu_i)/e_i + 2.0_dp*(2.0_dp - nu_j)*(1.0_dp + nu_j)/e_j)
  end function mindlin_g_star

  !> Elastic energy of the normal spring at overlap d.
  elemental real(dp) function normal_energy(law, k, e_star, d, rs) result(u)
    integer, intent(in) :: law
    real(dp), intent(in) :: k, e_star, d, rs
    if (law == contact_law%linear) then
      u = 0.5_dp*k*d**2
    else
      u = (8.0_dp/15.0_dp)*e_star*sqrt(rs)*d**2.5_dp
    end if
  end function normal_energy

  !> The normal dashpot c = 2 zeta sqrt(m* k) of a spring of tangent stiffness k.
  elemental real(dp) function dashpot_coefficient(zeta, m, k) result(c)
    real(dp), intent(in) :: zeta, m, k
    c = 2.0_dp*zeta*sqrt(m*k)
  end function dashpot_coefficient

  !> Lever arm from a sphere's centre (radius r) to the contact point at
  !> overlap d: r - d/2, as LIGGGHTS (surface_model_default.h, c_i = r_i -
  !> delta/2) and Yade (ScGeom's contact point) take it, for particle and
  !> wall contacts alike.
  elemental real(dp) function contact_arm(r, d) result(arm)
    real(dp), intent(in) :: r, d
    arm = r - 0.5_dp*max(d, 0.0_dp)
  end function contact_arm

  !> Overlap r - (x - p).n of a sphere (centre x, radius r) with the wall through p
  !> of unit normal n (pointing into the domain).
  pure real(dp) function wall_overlap(x, r, p, n) result(d)
    real(dp), intent(in) :: x(3), r, p(3), n(3)
    d = r - dot_product(x - p, n)
  end function wall_overlap

  !> The tangent stiffness of one interaction applied to a displacement
  !> (u_i, theta_i, u_j, theta_j). k = (k_n, k_t, k_r, k_w): normal k_n along n
  !> (from i to j); tangential k_t on the contact point's slip
  !> s = P du + arm_i n x theta_i + arm_j n x theta_j (du = u_j - u_i,
  !> P = I - n n^T); rolling k_r on the tangential part and twisting k_w on the
  !> normal part of the relative rotation dr = rot_j theta_j - rot_i theta_i;
  !> and the pre-stress term -geo P du (geo = F_n/l, 0 to leave it out). With
  !> f = k_n (n.du) n + k_t s - geo P du, g = k_t s x n and
  !> m = k_r P dr + k_w n (n.dr): y_i = -f, t_i = arm_i g - rot_i m, y_j = f,
  !> t_j = arm_j g + rot_j m. `rot` is 1 for rotations in radians and 1/r for
  !> the scaled coordinate r theta. The same kernel with dashpot coefficients
  !> (c_n, c_t, c_r, c_w) in k and velocities in place of displacements gives
  !> the dashpot forces. This is the one linearised interaction kernel (its
  !> arithmetic is the loop of `contact_products`, here on one spring).
  pure subroutine contact_product(n, k, arm_i, arm_j, rot_i, rot_j, geo, u_i, theta_i, u_j, theta_j, &
      y_i, t_i, y_j, t_j)
    real(dp), intent(in) :: n(3), k(4), arm_i, arm_j, rot_i, rot_j, geo
    real(dp), intent(in) :: u_i(3), theta_i(3), u_j(3), theta_j(3)
    real(dp), intent(out) :: y_i(3), t_i(3), y_j(3), t_j(3)
    real(dp) :: coef(7, 1), x(6, 0:2), f(6, 2)
    real(dp), parameter :: no_dashpots(4, 1) = 0.0_dp
    integer, parameter :: one_pair(2, 1) = reshape([1, 2], [2, 1])
    ! (one spring of `contact_products`, bodies 1 and 2 (x(:, 0), the ground,
    ! is not read): the kernel's arithmetic stays in one loop, which the
    ! compiler optimises as a whole)
    coef(:, 1) = [k(1), k(2), arm_i, arm_j, geo, k(3), k(4)]
    x(1:3, 1) = u_i
    x(4:6, 1) = theta_i
    x(1:3, 2) = u_j
    x(4:6, 2) = theta_j
    call contact_products(1, 1, n, coef, no_dashpots, 1.0_dp, 0.0_dp, one_pair, [0.0_dp, rot_i, rot_j], x, f)
    y_i = f(1:3, 1)
    t_i = f(4:6, 1)
    y_j = f(1:3, 2)
    t_j = f(4:6, 2)
  end subroutine contact_product

  !> `contact_product` over springs first..last of a list (the operator
  !> product's spring pass; the kernel is written out in a loop, where the
  !> compiler can keep it in registers: a call per spring cost a quarter of
  !> the product): spring s joins bodies ends(1, s) and ends(2, s) (0: the ground,
  !> whose x and rinv are 0) along normal(:, s) with coef(:, s) = (k_n, k_t,
  !> arm_i, arm_j, geo, k_r, k_w) mixed as `mixed_stiffness` says; x(1:3, b)
  !> and x(4:6, b) are body b's displacement and rotation, rinv(b) its `rot`.
  !> The forces and torques on its two ends go to f(:, 2s - 1) and f(:, 2s).
  pure subroutine contact_products(first, last, normal, coef, dcoef, alpha, beta, ends, rinv, x, f)
    integer, intent(in) :: first, last
    real(dp), intent(in) :: normal(3, *), coef(7, *), dcoef(4, *), alpha, beta
    integer, intent(in) :: ends(2, *)
    real(dp), intent(in) :: rinv(0:*), x(6, 0:*)
    real(dp), intent(inout) :: f(6, *)
    integer, parameter :: no_list(1) = 0
    real(dp) :: no_acc(6, 1)
    call spring_pass(first, last, .false., .false., no_list, normal, coef, dcoef, alpha, beta, ends, rinv, x, &
      f, 1, 1, no_acc)
  end subroutine contact_products

  !> `contact_products` on the springs list(first..last): the forces and
  !> torques of spring list(p) go to f(:, 2p - 1) and f(:, 2p).
  pure subroutine contact_products_listed(first, last, list, normal, coef, dcoef, alpha, beta, ends, rinv, &
      x, f)
    integer, intent(in) :: first, last, list(*)
    real(dp), intent(in) :: normal(3, *), coef(7, *), dcoef(4, *), alpha, beta
    integer, intent(in) :: ends(2, *)
    real(dp), intent(in) :: rinv(0:*), x(6, 0:*)
    real(dp), intent(inout) :: f(6, *)
    real(dp) :: no_acc(6, 1)
    call spring_pass(first, last, .true., .false., list, normal, coef, dcoef, alpha, beta, ends, rinv, x, &
      f, 1, 1, no_acc)
  end subroutine contact_products_listed

  !> `contact_products` on the springs list(first..last), each end's force
  !> and torque added to acc(:, body) as the springs come (the ground's, body
  !> 0, dropped; every other end's body in lo..hi), none stored: a body's sum
  !> is in the list's order.
  pure subroutine contact_products_add(first, last, list, normal, coef, dcoef, alpha, beta, ends, rinv, x, &
      lo, hi, acc)
    integer, intent(in) :: first, last, list(*), lo, hi
    real(dp), intent(in) :: normal(3, *), coef(7, *), dcoef(4, *), alpha, beta
    integer, intent(in) :: ends(2, *)
    real(dp), intent(in) :: rinv(0:*), x(6, 0:*)
    real(dp), intent(inout) :: acc(6, lo:hi)
    real(dp) :: no_f(6, 1)
    call spring_pass(first, last, .true., .true., list, normal, coef, dcoef, alpha, beta, ends, rinv, x, &
      no_f, lo, hi, acc)
  end subroutine contact_products_add

  !> The loop of `contact_products` (listed: spring list(p), else p, for p in
  !> first..last; add: forces added to acc(:, body), else stored in
  !> f(:, 2p - 1: 2p)). The one place of the kernel's arithmetic; private, so
  !> that it is compiled into each caller's loop with its flags fixed. The
  !> springs go in chunks of `pass_chunk`: each chunk's inputs are gathered
  !> into arrays by spring (q), the kernel runs over q as loops the compiler
  !> vectorises (the same expression per spring as one at a time, so the
  !> same bits; a short chunk, as `contact_product`'s one spring, runs the
  !> loops' scalar remainder), and the forces are stored or added in spring
  !> order.
  pure subroutine spring_pass(first, last, listed, add, list, normal, coef, dcoef, alpha, beta, ends, rinv, &
      x, f, lo, hi, acc)
    integer, intent(in) :: first, last
    logical, intent(in) :: listed, add
    integer, intent(in) :: list(*), lo, hi
    real(dp), intent(in) :: normal(3, *), coef(7, *), dcoef(4, *), alpha, beta
    integer, intent(in) :: ends(2, *)
    real(dp), intent(in) :: rinv(0:*), x(6, 0:*)
    real(dp), intent(inout) :: f(6, *), acc(6, lo:hi)
    integer, parameter :: w = pass_chunk
    ! (by spring q of a chunk: normal, stiffness (k_n, k_t, k_r, k_w), geo,
    ! arms, the ends' x and rinv; the forces on the ends)
    real(dp) :: n(w, 3), k(w, 4), geo(w), arm_i(w), arm_j(w), xa(w, 6), xb(w, 6), ra(w), rb(w)
    real(dp) :: fa(w, 6), fb(w, 6), ma(w, 3), mb(w, 3)
    real(dp) :: nn(3), ta(3), tb(3), du(3), dn, pdu(3), sl(3), fn(3), g(3), dr(3), m(3), kq(4), gq
    integer :: ab(w, 2), p0, p, q, nq, s, a, b, c
    logical :: turn(w)
    do p0 = first, last, w
      nq = min(w, last - p0 + 1)
      ! gather
      do q = 1, nq
        p = p0 + q - 1
        s = p
        if (listed) s = list(p)
        ab(q, 1) = ends(1, s)
        ab(q, 2) = ends(2, s)
        call mix_kernel(coef(:, s), dcoef, s, alpha, beta, kq, gq)
        k(q, :) = kq
        geo(q) = gq
        n(q, :) = normal(:, s)
        arm_i(q) = coef(3, s)
        arm_j(q) = coef(4, s)
      end do
      ! (a gather: vectorised (AVX), it made the pass slower)
!GCC$ novector
      do q = 1, nq
        xa(q, :) = x(:, ab(q, 1))
        xb(q, :) = x(:, ab(q, 2))
      end do
      ! the kernel, as `contact_product` states it
      do q = 1, nq
        nn = n(q, :)
        du = xb(q, 1:3) - xa(q, 1:3)
        dn = nn(1)*du(1) + nn(2)*du(2) + nn(3)*du(3)
        pdu = du - dn*nn
        ta = xa(q, 4:6)
        tb = xb(q, 4:6)
        sl = pdu + arm_i(q)*cross_product(nn, ta) + arm_j(q)*cross_product(nn, tb)
        fn = (k(q, 1)*dn)*nn + k(q, 2)*sl - geo(q)*pdu
        g = k(q, 2)*cross_product(sl, nn)
        fa(q, 1:3) = -fn
        fb(q, 1:3) = fn
        fa(q, 4:6) = arm_i(q)*g
        fb(q, 4:6) = arm_j(q)*g
      end do
      turn(:nq) = k(:nq, 3) /= 0.0_dp .or. k(:nq, 4) /= 0.0_dp
      if (any(turn(:nq))) then
        ! rolling and twisting, on the springs that have them (only they
        ! read the ends' rot: a cache miss saved on the others)
        do q = 1, nq
          ra(q) = rinv(ab(q, 1))
          rb(q) = rinv(ab(q, 2))
        end do
        do q = 1, nq
          nn = n(q, :)
          dr = rb(q)*xb(q, 4:6) - ra(q)*xa(q, 4:6)
          m = rotation_moment(nn, k(q, 3), k(q, 4), dr)
          ma(q, :) = fa(q, 4:6) - ra(q)*m
          mb(q, :) = fb(q, 4:6) + rb(q)*m
        end do
        do c = 1, 3
          fa(:nq, 3 + c) = merge(ma(:nq, c), fa(:nq, 3 + c), turn(:nq))
          fb(:nq, 3 + c) = merge(mb(:nq, c), fb(:nq, 3 + c), turn(:nq))
        end do
      end if
      ! the forces, in spring order
      do q = 1, nq
        p = p0 + q - 1
        if (add) then
          a = ab(q, 1)
          b = ab(q, 2)
          if (a > 0) acc(:, a) = acc(:, a) + fa(q, :)
          if (b > 0) acc(:, b) = acc(:, b) + fb(q, :)
        else
          f(:, 2*p - 1) = fa(q, :)
          f(:, 2*p) = fb(q, :)
        end if
      end do
    end do
  end subroutine spring_pass

  !> The stiffness (k_n, k_t, k_r, k_w) and pre-stress geo of spring s of an
  !> operator mixed as alpha K + beta C: coef = (k_n, k_t, arm_i, arm_j, geo,
  !> k_r, k_w) of the spring, dcoef(:, s) its dashpots (read only when beta
  !> is not 0; no pre-stress in C).
  pure subroutine mixed_stiffness(coef, dcoef, s, alpha, beta, k, geo)
    real(dp), intent(in) :: coef(7), dcoef(4, *)
    integer, intent(in) :: s
    real(dp), intent(in) :: alpha, beta
    real(dp), intent(out) :: k(4), geo
    call mix_kernel(coef, dcoef, s, alpha, beta, k, geo)
  end subroutine mixed_stiffness

  !> The body of `mixed_stiffness` (private: compiled into the loop of
  !> `contact_products`, which a public procedure under -fPIC is not).
  pure subroutine mix_kernel(coef, dcoef, s, alpha, beta, k, geo)
    real(dp), intent(in) :: coef(7), dcoef(4, *)
    integer, intent(in) :: s
    real(dp), intent(in) :: alpha, beta
    real(dp), intent(out) :: k(4), geo
    k(1) = coef(1)
    k(2) = coef(2)
    k(3) = coef(6)
    k(4) = coef(7)
    geo = coef(5)
    ! (K alone, the solves' case: no multiplications)
    if (alpha == 1.0_dp .and. beta == 0.0_dp) return
    k = alpha*k
    geo = alpha*geo
    if (beta /= 0.0_dp) k = k + beta*dcoef(:, s)
  end subroutine mix_kernel

  !> The moment of a relative rotation dr on an interaction of normal n:
  !> rolling k_r on its tangential part, twisting k_w on its normal part,
  !> m = k_r P dr + k_w n (n.dr) (`contact_product`, `contact_product_arms`).
  pure function rotation_moment(n, k_r, k_w, dr) result(m)
    real(dp), intent(in) :: n(3), k_r, k_w, dr(3)
    real(dp) :: m(3)
    real(dp) :: rn
    rn = n(1)*dr(1) + n(2)*dr(2) + n(3)*dr(3)
    m = k_r*(dr - rn*n) + (k_w*rn)*n
  end function rotation_moment

  !> `contact_product` with each end's arm a vector: c_i, c_j from each
  !> end's centre (a rigid body's centre of mass) to the contact point, so a
  !> rigid body's map is fused into the kernel. On the scaled motions
  !> x = (u, l theta) of the two ends: the contact point's relative motion
  !> w = u_j + theta_j x c_j - u_i - theta_i x c_i, the force
  !> f = k_n (n.w) n + k_t (w - (n.w) n) on j (-f on i), the torques
  !> -c_i x f and c_j x f, and the moment (`rotation_moment`) of
  !> rot (theta_j - theta_i) with rot = 1/l. No pre-stress term. With
  !> c_i = arm_i n + d_i, c_j = -arm_j n + d_j it equals `contact_product` on
  !> the members' motions carried back by the rigid map (tested).
  pure subroutine contact_product_arms(n, k, c_i, c_j, rot, x_i, x_j, y_i, y_j)
    real(dp), intent(in) :: n(3), k(4), c_i(3), c_j(3), rot, x_i(6), x_j(6)
    real(dp), intent(out) :: y_i(6), y_j(6)
    real(dp) :: w(3), dn, f(3), m(3)
    w = x_j(1:3) - x_i(1:3) + cross_product(x_j(4:6), c_j) - cross_product(x_i(4:6), c_i)
    dn = n(1)*w(1) + n(2)*w(2) + n(3)*w(3)
    f = k(2)*w + ((k(1) - k(2))*dn)*n
    y_i(1:3) = -f
    y_j(1:3) = f
    y_i(4:6) = cross_product(f, c_i)
    y_j(4:6) = cross_product(c_j, f)
    if (k(3) /= 0.0_dp .or. k(4) /= 0.0_dp) then
      m = rotation_moment(n, k(3), k(4), rot*(x_j(4:6) - x_i(4:6)))
      y_i(4:6) = y_i(4:6) - rot*m
      y_j(4:6) = y_j(4:6) + rot*m
    end if
  end subroutine contact_product_arms

  !> The 12 x 12 tangent stiffness of one interaction on (u_i, theta_i, u_j,
  !> theta_j), column by column from `contact_product` (same arguments;
  !> rot_i, rot_j default 1: rotations in radians): k = (k_n, k_t, k_r, k_w).
  !> K f = -dF/dq for the forces and torques of `contact_forces` and
  !> `rolling_moments`.
  pure function contact_block(n, k, arm_i, arm_j, geo, rot_i, rot_j) result(kb)
    real(dp), intent(in) :: n(3), k(4), arm_i, arm_j, geo
    real(dp), intent(in), optional :: rot_i, rot_j
    real(dp) :: kb(12, 12)
    real(dp) :: e(12), ri, rj
    integer :: c
    ri = 1.0_dp
    rj = 1.0_dp
    if (present(rot_i)) ri = rot_i
    if (present(rot_j)) rj = rot_j
    do c = 1, 12
      e = 0.0_dp
      e(c) = 1.0_dp
      call contact_product(n, k, arm_i, arm_j, ri, rj, geo, e(1:3), e(4:6), e(7:9), e(10:12), &
        kb(1:3, c), kb(4:6, c), kb(7:9, c), kb(10:12, c))
    end do
  end function contact_block

  !> The columns of one end of `contact_block` in closed form (same
  !> arguments; `first`: the end is i, else j): `own` its rows of that end
  !> (6 x 6, u then theta) and `other` the other end's rows. With
  !> Q = k_n n n^T + (k_t - geo) P, N the cross-product matrix of n (N x = n x x),
  !> R = k_r P + k_w n n^T, a and b the end's and the other end's arms, r_a,
  !> r_b their rot and sign +1 for i, -1 for j:
  !> own = [Q, -sign k_t a N; sign k_t a N, k_t a^2 P + r_a^2 R],
  !> other = [-Q, sign k_t a N; sign k_t b N, k_t a b P - r_a r_b R]
  !> (from the kernel with N N = -P and N P = N; equal to `contact_block`'s to
  !> rounding, tested). One evaluation instead of six kernel calls, for the
  !> operator's absolute product (`operator_abs_product`; with 6 components
  !> its entries are formed by `contact_abs_springs`, to the same bits).
  pure subroutine contact_end_blocks(n, k, arm_i, arm_j, rot_i, rot_j, geo, first, own, other)
    real(dp), intent(in) :: n(3), k(4), arm_i, arm_j, rot_i, rot_j, geo
    logical, intent(in) :: first
    real(dp), intent(out) :: own(6, 6), other(6, 6)
    real(dp) :: nn(3, 3), p(3, 3), q(3, 3), r(3, 3), cn(3, 3), a, b, ra, rb, sgn
    integer :: c
    do c = 1, 3
      nn(:, c) = n*n(c)
    end do
    p = -nn
    do c = 1, 3
      p(c, c) = p(c, c) + 1.0_dp
    end do
    q = k(1)*nn + (k(2) - geo)*p
    r = k(3)*p + k(4)*nn
    ! (N entry by entry: an array constructor of variables is a library call per spring)
    cn(1, 1) = 0.0_dp
    cn(2, 1) = n(3)
    cn(3, 1) = -n(2)
    cn(1, 2) = -n(3)
    cn(2, 2) = 0.0_dp
    cn(3, 2) = n(1)
    cn(1, 3) = n(2)
    cn(2, 3) = -n(1)
    cn(3, 3) = 0.0_dp
    if (first) then
      a = arm_i
      b = arm_j
      ra = rot_i
      rb = rot_j
      sgn = 1.0_dp
    else
      a = arm_j
      b = arm_i
      ra = rot_j
      rb = rot_i
      sgn = -1.0_dp
    end if
    own(1:3, 1:3) = q
    own(1:3, 4:6) = (-sgn*k(2)*a)*cn
    own(4:6, 1:3) = (sgn*k(2)*a)*cn
    own(4:6, 4:6) = (k(2)*a*a)*p + (ra*ra)*r
    other(1:3, 1:3) = -q
    other(1:3, 4:6) = (sgn*k(2)*a)*cn
    other(4:6, 1:3) = (sgn*k(2)*b)*cn
    other(4:6, 4:6) = (k(2)*a*b)*p - (ra*rb)*r
  end subroutine contact_end_blocks

  !> The sums of the bound's absolute product (`operator_abs_product`) of a
  !> 6-DOF operator at its free bodies lo..hi, spring by spring (springs
  !> 1..n_springs in order, each end at a body in lo..hi): acc(c, i) += sum_q
  !> |O(q, c)| w(q, j) v(q, j) for the end at body i whose other end j is a
  !> body, and with `diag`, dsum(:, i) += the end's own block (18 distinct
  !> entries, `contact_abs_diag`), the ground's ends too; then
  !> acc(c, i) += sum_q |D(q, c)| w(q, i) v(q, i), D the sum in dsum. O and
  !> the own block are `contact_end_blocks`' (no pre-stress; stiffness `mixed_stiffness`),
  !> formed entry by entry with the same roundings (each symmetric pair once:
  !> n_x n_y = n_y n_x, and a sign flip is exact), each spring's common parts
  !> once for both ends. A body's sums thus come in spring order, the order of
  !> its entries in the operator's `incident`, q = 1..6 within an end: the
  !> blocks' sums to the last bit (tested). The springs' data is read in order
  !> (the arithmetic compiled into the loop).
  pure subroutine contact_abs_springs(lo, hi, n_springs, ends, normal, coef, dcoef, alpha, beta, rinv, &
      w, v, diag, acc, dsum)
    integer, intent(in) :: lo, hi, n_springs
    integer, intent(in) :: ends(2, *)
    real(dp), intent(in) :: normal(3, *), coef(7, *), dcoef(4, *), alpha, beta, rinv(0:*), w(6, *), v(6, *)
    logical, intent(in) :: diag
    real(dp), intent(inout) :: acc(6, lo:hi), dsum(18, lo:hi)
    ! (o(c, q) = |O(q, c)|: the sums over q of all six c at once)
    real(dp) :: o(6, 6), k(4), geo, n(3), nn(6), p(3), q(6), r(6), a, b, ra, rb, t, ta, tb, kab, rab, &
      kaa, raa
    integer :: s, en, i, j, m
    ! (the zeros of O: N's diagonal)
    o(4, 1) = 0.0_dp
    o(5, 2) = 0.0_dp
    o(6, 3) = 0.0_dp
    o(1, 4) = 0.0_dp
    o(2, 5) = 0.0_dp
    o(3, 6) = 0.0_dp
    do s = 1, n_springs
      if ((ends(1, s) < lo .or. ends(1, s) > hi) .and. (ends(2, s) < lo .or. ends(2, s) > hi)) cycle
      call mix_kernel(coef(:, s), dcoef, s, alpha, beta, k, geo)
      n = normal(:, s)
      ! n n^T, P, Q, R (entries 11, 22, 33, 12, 13, 23; P's off the diagonal
      ! are -n n^T's)
      nn(1) = n(1)*n(1)
      nn(2) = n(2)*n(2)
      nn(3) = n(3)*n(3)
      nn(4) = n(1)*n(2)
      nn(5) = n(1)*n(3)
      nn(6) = n(2)*n(3)
      p = -nn(1:3) + 1.0_dp
      q(1:3) = k(1)*nn(1:3) + k(2)*p
      q(4:6) = k(1)*nn(4:6) + k(2)*(-nn(4:6))
      r(1:3) = k(3)*p + k(4)*nn(1:3)
      r(4:6) = k(3)*(-nn(4:6)) + k(4)*nn(4:6)
      o(1, 1) = abs(q(1))
      o(2, 2) = abs(q(2))
      o(3, 3) = abs(q(3))
      o(2, 1) = abs(q(4))
      o(1, 2) = o(2, 1)
      o(3, 1) = abs(q(5))
      o(1, 3) = o(3, 1)
      o(3, 2) = abs(q(6))
      o(2, 3) = o(3, 2)
      do en = 1, 2
        i = ends(en, s)
        if (i < lo .or. i > hi) cycle
        j = ends(3 - en, s)
        ! a, b, r_a, r_b of the end, t = sign k_t a
        a = coef(2 + en, s)
        b = coef(5 - en, s)
        ra = rinv(i)
        rb = rinv(j)
        if (en == 1) then
          t = k(2)*a
        else
          t = (-k(2))*a
        end if
        if (diag) then
          ! own = [Q, -t N; t N, k_t a^2 P + r_a^2 R]: -t N's entries (1,5),
          ! (1,6), (2,4), (2,6), (3,4), (3,5) are t n_3, -t n_2, -t n_3,
          ! t n_1, t n_2, -t n_1 (its diagonal is 0)
          kaa = k(2)*a*a
          raa = ra*ra
          dsum(1:6, i) = dsum(1:6, i) + q
          dsum(7, i) = dsum(7, i) + (-t)*(-n(3))
          dsum(8, i) = dsum(8, i) + (-t)*n(2)
          dsum(9, i) = dsum(9, i) + (-t)*n(3)
          dsum(10, i) = dsum(10, i) + (-t)*(-n(1))
          dsum(11, i) = dsum(11, i) + (-t)*(-n(2))
          dsum(12, i) = dsum(12, i) + (-t)*n(1)
          dsum(13:15, i) = dsum(13:15, i) + (kaa*p + raa*r(1:3))
          dsum(16:18, i) = dsum(16:18, i) + (kaa*(-nn(4:6)) + raa*r(4:6))
        end if
        if (j == 0) cycle
        ! |O|, O = [-Q, t N; sign k_t b N, k_t a b P - r_a r_b R]
        ta = abs(t)
        tb = abs(k(2)*b)
        kab = k(2)*a*b
        rab = ra*rb
        o(5, 1) = ta*abs(n(3))
        o(4, 2) = o(5, 1)
        o(6, 1) = ta*abs(n(2))
        o(4, 3) = o(6, 1)
        o(6, 2) = ta*abs(n(1))
        o(5, 3) = o(6, 2)
        o(2, 4) = tb*abs(n(3))
        o(1, 5) = o(2, 4)
        o(3, 4) = tb*abs(n(2))
        o(1, 6) = o(3, 4)
        o(3, 5) = tb*abs(n(1))
        o(2, 6) = o(3, 5)
        o(4, 4) = abs(kab*p(1) - rab*r(1))
        o(5, 5) = abs(kab*p(2) - rab*r(2))
        o(6, 6) = abs(kab*p(3) - rab*r(3))
        o(5, 4) = abs(kab*(-nn(4)) - rab*r(4))
        o(4, 5) = o(5, 4)
        o(6, 4) = abs(kab*(-nn(5)) - rab*r(5))
        o(4, 6) = o(6, 4)
        o(6, 5) = abs(kab*(-nn(6)) - rab*r(6))
        o(5, 6) = o(6, 5)
        do m = 1, 6
          acc(:, i) = acc(:, i) + o(:, m)*w(m, j)*v(m, j)
        end do
      end do
    end do
    ! then each body's own: acc(c, i) += sum_q |D(q, c)| w(q, i) v(q, i)
    do i = lo, hi
      ! (|D| is symmetric)
      o = contact_abs_diag(dsum(:, i))
      do m = 1, 6
        acc(:, i) = acc(:, i) + o(:, m)*w(m, i)*v(m, i)
      end do
    end do
  end subroutine contact_abs_springs

  !> The magnitudes |D| of a body's diagonal block from the 18 distinct
  !> entries dsum of `contact_abs_springs`: Q's 11, 22, 33, 12, 13, 23; the
  !> upper right part's (1,5), (1,6), (2,4), (2,6), (3,4), (3,5) (its
  !> diagonal and the lower left's are 0); the lower right's 44, 55, 66, 45,
  !> 46, 56. D is symmetric to the last bit: its entries (x, y) and (y, x)
  !> are the same sums of the same terms.
  pure function contact_abs_diag(dsum) result(d)
    real(dp), intent(in) :: dsum(18)
    real(dp) :: d(6, 6)
    d(1, 1) = abs(dsum(1))
    d(2, 2) = abs(dsum(2))
    d(3, 3) = abs(dsum(3))
    d(1, 2) = abs(dsum(4))
    d(1, 3) = abs(dsum(5))
    d(2, 3) = abs(dsum(6))
    d(1, 4) = 0.0_dp
    d(1, 5) = abs(dsum(7))
    d(1, 6) = abs(dsum(8))
    d(2, 4) = abs(dsum(9))
    d(2, 5) = 0.0_dp
    d(2, 6) = abs(dsum(10))
    d(3, 4) = abs(dsum(11))
    d(3, 5) = abs(dsum(12))
    d(3, 6) = 0.0_dp
    d(4, 4) = abs(dsum(13))
    d(5, 5) = abs(dsum(14))
    d(6, 6) = abs(dsum(15))
    d(4, 5) = abs(dsum(16))
    d(4, 6) = abs(dsum(17))
    d(5, 6) = abs(dsum(18))
    d(2, 1) = d(1, 2)
    d(3, 1) = d(1, 3)
    d(3, 2) = d(2, 3)
    d(4:6, 1:3) = transpose(d(1:3, 4:6))
    d(5, 4) = d(4, 5)
    d(6, 4) = d(4, 6)
    d(6, 5) = d(5, 6)
  end function contact_abs_diag

  !> Forces and torques of one interaction in the stepper. The shear displacement
  !> u_s (history, inout) is first turned into the plane normal to the current n
  !> (keeping its length), then incremented by the tangential part of the contact
  !> point's relative displacement since the last step (dx = increment of
  !> x_j - x_i, dtheta the rotation increments), and capped by Coulomb's
  !> |k_t u_s| <= friction F_n (friction < 0: no cap). Returns the force on j
  !> (-f on i) and the torques on i and j.
  pure subroutine contact_forces(n, f_n, k_t, friction, arm_i, arm_j, dx, dtheta_i, dtheta_j, &
      u_s, f, t_i, t_j)
    real(dp), intent(in) :: n(3), f_n, k_t, friction, arm_i, arm_j, dx(3), dtheta_i(3), dtheta_j(3)
    real(dp), intent(inout) :: u_s(3)
    real(dp), intent(out) :: f(3), t_i(3), t_j(3)
    real(dp) :: du(3), len0, len1, cap, ft
    if (k_t > 0.0_dp) then
      len0 = norm2(u_s)
      if (len0 > 0.0_dp) then
        u_s = u_s - dot_product(u_s, n)*n
        len1 = norm2(u_s)
        if (len1 > 0.0_dp) u_s = u_s*(len0/len1)
      end if
      du = dx + arm_j*cross_product(n, dtheta_j) + arm_i*cross_product(n, dtheta_i)
      u_s = u_s + (du - dot_product(du, n)*n)
      if (friction >= 0.0_dp) then
        cap = friction*max(f_n, 0.0_dp)
        ft = k_t*norm2(u_s)
        if (ft > cap) u_s = u_s*(cap/ft)
      end if
      f = f_n*n - k_t*u_s
      t_i = -arm_i*cross_product(n, f)
      t_j = -arm_j*cross_product(n, f)
    else
      f = f_n*n
      t_i = 0.0_dp
      t_j = 0.0_dp
    end if
  end subroutine contact_forces

  !> Rolling and twisting moments of one interaction in the stepper (the
  !> elastic-plastic spring of LIGGGHTS' `epsd2` and Yade's `CohFrictPhys`
  !> moment law). The relative rotation u_r (history, inout) is split into its
  !> twisting part along the current n and its rolling part in the plane normal
  !> to n (a turn of n moves a second-order amount between them); both are
  !> incremented by the relative rotation dtheta = dtheta_j - dtheta_i since
  !> the last step; the rolling moment k_r |u_roll| is capped at `cap` (< 0: no
  !> cap). Returns the moment m on i (-m on j): m = k_r u_roll + k_w u_twist.
  pure subroutine rolling_moments(n, k_r, k_w, cap, dtheta, u_r, m)
    real(dp), intent(in) :: n(3), k_r, k_w, cap, dtheta(3)
    real(dp), intent(inout) :: u_r(3)
    real(dp), intent(out) :: m(3)
    real(dp) :: twist, roll(3), mr
    twist = dot_product(u_r, n)
    roll = u_r - twist*n
    twist = twist + dot_product(dtheta, n)
    roll = roll + (dtheta - dot_product(dtheta, n)*n)
    if (cap >= 0.0_dp .and. k_r > 0.0_dp) then
      mr = k_r*norm2(roll)
      if (mr > cap) roll = roll*(cap/mr)
    end if
    u_r = roll + twist*n
    m = k_r*roll + (k_w*twist)*n
  end subroutine rolling_moments

  !> Add the forces of nb bonds at positions x to f (the stepper's hot loop for
  !> bonds, on plain contiguous arrays). A bond (i, j) with rest vector r0 and
  !> unit direction n0, stretched by u = x_j - x_i - r0, pulls i by
  !> k_n n0 (n0 . u) + k_t (u - n0 (n0 . u)) = (k_n - k_t)(n0 . u) n0 + k_t u
  !> and j by the opposite. With `box` (the periods, 0 along open axes) u is
  !> taken through the nearest image.
  pure subroutine add_bond_forces(nb, n, bonds, x, rest, normal, k_n, k_t, f, box)
    integer, intent(in) :: nb, n, bonds(2, nb)
    real(dp), intent(in) :: x(3, n), rest(3, nb), normal(3, nb), k_n, k_t
    real(dp), intent(inout) :: f(3, n)
    real(dp), intent(in), optional :: box(3)
    integer :: b, i, j
    real(dp) :: fb(3), u(3)
    do b = 1, nb
      i = bonds(1, b)
      j = bonds(2, b)
      u = x(:, j) - x(:, i) - rest(:, b)
      if (present(box)) where (box > 0.0_dp) u = u - box*anint(u/box)
      fb = ((k_n - k_t)*dot_product(normal(:, b), u))*normal(:, b) + k_t*u
      f(:, i) = f(:, i) + fb
      f(:, j) = f(:, j) - fb
    end do
  end subroutine add_bond_forces

  !> a x b.
  pure function cross(a, b) result(c)
    real(dp), intent(in) :: a(3), b(3)
    real(dp) :: c(3)
    c = cross_product(a, b)
  end function cross

  !> `cross` for this module's kernels: private, so that the compiler may
  !> inline it (a public procedure of a position-independent library may be
  !> interposed and is called instead; the kernels then spent a third of
  !> their time in the calls).
  pure function cross_product(a, b) result(c)
    real(dp), intent(in) :: a(3), b(3)
    real(dp) :: c(3)
    c(1) = a(2)*b(3) - a(3)*b(2)
    c(2) = a(3)*b(1) - a(1)*b(3)
    c(3) = a(1)*b(2) - a(2)*b(1)
  end function cross_product

  !> The components (of u(1:3), theta(4:6)) that are degrees of freedom of a
  !> particle in `dim` dimensions: translations up to dim, and with rotations
  !> theta_z in 2D, all three in 3D (none in 1D).
  pure function dof_components(dim, rotation) result(c)
    integer, intent(in) :: dim
    logical, intent(in) :: rotation
    integer, allocatable :: c(:)
    if (.not. rotation .or. dim == 1) then
      c = [1, 2, 3]
      c = c(:dim)
    else if (dim == 2) then
      c = [1, 2, 6]
    else
      c = [1, 2, 3, 4, 5, 6]
    end if
  end function dof_components

  !> The `contact_law` code of a word (case ignored); 0 for another word.
  pure integer function contact_law_from_name(name) result(code)
    !> The word, one of `contact_law_names`.
    character(len=*), intent(in) :: name
    code = word_index(contact_law_names, name)
  end function contact_law_from_name

  !> The word of a `contact_law` code (`?` for another value).
  pure function contact_law_name(code) result(name)
    !> A code of `contact_law`.
    integer, intent(in) :: code
    character(len=:), allocatable :: name
    name = word_of(contact_law_names, code)
  end function contact_law_name

end module demstep_interaction
