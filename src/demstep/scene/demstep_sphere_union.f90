!> Volume, centroid and inertia tensor of the union of overlapping spheres
!> (a LIGGGHTS multisphere template's body, the overlap counted once).
!>
!> LIGGGHTS estimates these by Monte Carlo when a template states no `mass`
!> (fix_template_multiplespheres.cpp:458-503, CFDEMproject/LIGGGHTS-PUBLIC
!> 3d5c00f), with a relative noise of about 1/sqrt(ntry). Here they are
!> integrated deterministically: along x exactly (a line at (y, z) cuts each
!> sphere in an interval; the intervals are merged and 1, x, x^2 integrated
!> over them in closed form), over y and z by Gauss-Legendre on panels. The
!> panels break where the integrand is not smooth: in y at each sphere's
!> extent and at the y-extent of each pair's intersection circle; in z, for
!> each y, at the edges of each sphere's slice and where the slice plane
!> crosses a pair's intersection circle (the merged length has a kink there).
!> In each panel the nodes are mapped by s = m - h cos(theta), which removes
!> the square-root ends of a slice's chord. A single sphere is then exact to
!> rounding; the test suite `bodies` states the error on overlapping spheres.
module demstep_sphere_union
  use demstep_sort, only: sort_ascending
  use demstep_kinds, only: dp, pi
  use demstep_status, only: demstep_status_type, demstep_stat, set_status
  use, intrinsic :: ieee_arithmetic, only: ieee_is_finite
  implicit none
  private

  public :: sphere_union_moments

  !> Default Gauss-Legendre points per panel in y and in z.
  integer, parameter, public :: union_points = 16

contains

  !> Volume, centroid and inertia tensor per unit density (about the
  !> centroid, the axes of `centre`) of the union of spheres `centre(:, i)`,
  !> `radius(i)`. `points` Gauss points per panel (default `union_points`).
  !> Cost: at most (2 n + n (n - 1))^2 points^2 lines for n spheres, each
  !> O(n^2) in the worst case (an insertion sort of n intervals), so meant
  !> for bodies of a few to tens of spheres. Status invalid_input naming
  !> `centre` (not 3 x n, not finite), `radius` (none, not finite and > 0)
  !> or `points` (below 2).
  pure subroutine sphere_union_moments(centre, radius, volume, centroid, inertia, status, points)
    real(dp), intent(in) :: centre(:, :), radius(:)
    real(dp), intent(out) :: volume, centroid(3), inertia(3, 3)
    type(demstep_status_type), intent(out) :: status
    integer, intent(in), optional :: points
    real(dp), allocatable :: c(:, :), t(:), w(:), yb(:), zb(:), cc(:, :), ca(:), cu(:, :), cv(:, :)
    real(dp), allocatable :: lo(:), hi(:)
    real(dp) :: s(10), y, wy, z, wz, d(3), dist, along, h2, sc(3, 3), eye(3, 3)
    integer :: n, q, i, j, k, ny, nz, np, iy, iz, ky, kz
    volume = 0.0_dp
    centroid = 0.0_dp
    inertia = 0.0_dp
    n = size(radius)
    q = union_points
    if (present(points)) q = points
    if (n < 1) then
      call set_status(status, demstep_stat%invalid_input, "needs at least one sphere", where="radius")
      return
    end if
    if (size(centre, 1) /= 3 .or. size(centre, 2) /= n) then
      call set_status(status, demstep_stat%invalid_input, "must be 3 x size(radius)", where="centre")
      return
    end if
    do i = 1, n
      if (.not. (ieee_is_finite(radius(i)) .and. radius(i) > 0.0_dp)) then
        call set_status(status, demstep_stat%invalid_input, "must be finite and > 0", where="radius", &
          index=i, subscript=.true.)
        return
      end if
      if (.not. all(ieee_is_finite(centre(:, i)))) then
        call set_status(status, demstep_stat%invalid_input, "must be finite", where="centre", index=i)
        return
      end if
    end do
    if (q < 2) then
      call set_status(status, demstep_stat%invalid_input, "must be at least 2", where="points")
      return
    end if
    ! coordinates from the first centre (the moments' rounding stays relative)
    c = centre - spread(centre(:, 1), 2, n)
    call gauss_legendre(q, t, w)
    ! each overlapping pair's intersection circle: centre, radius, in-plane axes
    allocate(cc(3, n*(n - 1)/2), ca(n*(n - 1)/2), cu(3, n*(n - 1)/2), cv(3, n*(n - 1)/2))
    np = 0
    do i = 1, n - 1
      do j = i + 1, n
        d = c(:, j) - c(:, i)
        dist = norm2(d)
        if (dist >= radius(i) + radius(j) .or. dist <= abs(radius(i) - radius(j))) cycle
        d = d/dist
        along = (dist**2 + radius(i)**2 - radius(j)**2)/(2.0_dp*dist)
        np = np + 1
        cc(:, np) = c(:, i) + along*d
        ca(np) = sqrt(max(radius(i)**2 - along**2, 0.0_dp))
        call plane_axes(d, cu(:, np), cv(:, np))
      end do
    end do
    allocate(yb(2*n + 2*np), zb(2*n + 2*np), lo(n), hi(n))
    ny = 0
    do i = 1, n
      yb(ny + 1:ny + 2) = [c(2, i) - radius(i), c(2, i) + radius(i)]
      ny = ny + 2
    end do
    do k = 1, np
      ! y-extent of the circle cc + a (cos phi u + sin phi v)
      h2 = ca(k)*hypot(cu(2, k), cv(2, k))
      yb(ny + 1:ny + 2) = [cc(2, k) - h2, cc(2, k) + h2]
      ny = ny + 2
    end do
    call sort_ascending(yb(:ny))
    s = 0.0_dp
    do iy = 1, ny - 1
      if (yb(iy + 1) <= yb(iy)) cycle
      do ky = 1, q
        call mapped_node(yb(iy), yb(iy + 1), t(ky), w(ky), y, wy)
        call slice_breaks(c, radius, cc(:, :np), ca(:np), cu(:, :np), cv(:, :np), y, zb, nz)
        do iz = 1, nz - 1
          if (zb(iz + 1) <= zb(iz)) cycle
          do kz = 1, q
            call mapped_node(zb(iz), zb(iz + 1), t(kz), w(kz), z, wz)
            call add_line(c, radius, y, z, wy*wz, lo, hi, s)
          end do
        end do
      end do
    end do
    volume = s(1)
    centroid = s(2:4)/volume
    ! second moments about the origin: xx yy zz xy xz yz
    sc(1, 1) = s(5)
    sc(2, 2) = s(6)
    sc(3, 3) = s(7)
    sc(1, 2) = s(8)
    sc(1, 3) = s(9)
    sc(2, 3) = s(10)
    sc(2, 1) = sc(1, 2)
    sc(3, 1) = sc(1, 3)
    sc(3, 2) = sc(2, 3)
    sc = sc - volume*spread(centroid, 2, 3)*spread(centroid, 1, 3)
    eye = reshape([1.0_dp, 0.0_dp, 0.0_dp, 0.0_dp, 1.0_dp, 0.0_dp, 0.0_dp, 0.0_dp, 1.0_dp], [3, 3])
    inertia = (sc(1, 1) + sc(2, 2) + sc(3, 3))*eye - sc
    centroid = centroid + centre(:, 1)
    status%stat = demstep_stat%ok
  end subroutine sphere_union_moments


  !> The z breakpoints of the slice at y: its circles' edges and where it
  !> crosses the pairs' intersection circles (centre cc, radius ca, in-plane
  !> axes cu, cv), sorted in zb(:nz).
  pure subroutine slice_breaks(c, radius, cc, ca, cu, cv, y, zb, nz)
    real(dp), intent(in) :: c(:, :), radius(:), cc(:, :), ca(:), cu(:, :), cv(:, :), y
    real(dp), intent(inout) :: zb(:)
    integer, intent(out) :: nz
    real(dp) :: r2, big, alpha, phi, cosd
    integer :: m, sgn, n, np
    n = size(radius)
    np = size(ca)
    nz = 0
    do m = 1, n
      r2 = radius(m)**2 - (y - c(2, m))**2
      if (r2 <= 0.0_dp) cycle
      zb(nz + 1:nz + 2) = [c(3, m) - sqrt(r2), c(3, m) + sqrt(r2)]
      nz = nz + 2
    end do
    do m = 1, np
      ! a (u_y cos phi + v_y sin phi) = y - cc_y
      big = ca(m)*hypot(cu(2, m), cv(2, m))
      if (big <= 0.0_dp) cycle
      cosd = (y - cc(2, m))/big
      if (abs(cosd) >= 1.0_dp) cycle
      alpha = atan2(cv(2, m), cu(2, m))
      do sgn = -1, 1, 2
        phi = alpha + sgn*acos(cosd)
        nz = nz + 1
        zb(nz) = cc(3, m) + ca(m)*(cu(3, m)*cos(phi) + cv(3, m)*sin(phi))
      end do
    end do
    call sort_ascending(zb(:nz))
  end subroutine slice_breaks

  !> The line at (y, z): its merged intervals' moments, weight wt, added to
  !> s (lo, hi: workspace of size(radius)).
  pure subroutine add_line(c, radius, y, z, wt, lo, hi, s)
    real(dp), intent(in) :: c(:, :), radius(:), y, z, wt
    real(dp), intent(inout) :: lo(:), hi(:), s(10)
    real(dp) :: r2, a, b, one, xm, xx
    integer :: m, nl, n
    n = size(radius)
    nl = 0
    do m = 1, n
      r2 = radius(m)**2 - (y - c(2, m))**2 - (z - c(3, m))**2
      if (r2 <= 0.0_dp) cycle
      nl = nl + 1
      lo(nl) = c(1, m) - sqrt(r2)
      hi(nl) = c(1, m) + sqrt(r2)
    end do
    if (nl == 0) return
    call sort_pairs(lo(:nl), hi(:nl))
    one = 0.0_dp
    xm = 0.0_dp
    xx = 0.0_dp
    a = lo(1)
    b = hi(1)
    do m = 2, nl + 1
      if (m <= nl) then
        if (lo(m) <= b) then
          b = max(b, hi(m))
          cycle
        end if
      end if
      one = one + (b - a)
      xm = xm + 0.5_dp*(b - a)*(b + a)
      xx = xx + (b - a)*(b*b + a*b + a*a)/3.0_dp
      if (m <= nl) then
        a = lo(m)
        b = hi(m)
      end if
    end do
    s = s + wt*[one, xm, y*one, z*one, xx, y*y*one, z*z*one, y*xm, z*xm, y*z*one]
  end subroutine add_line

  !> Node and weight on [a, b] of Gauss node t, weight w on [-1, 1] after
  !> the map s = m - h cos(pi (t + 1) / 2).
  pure subroutine mapped_node(a, b, t, w, x, wx)
    real(dp), intent(in) :: a, b, t, w
    real(dp), intent(out) :: x, wx
    real(dp) :: theta
    theta = 0.5_dp*pi*(t + 1.0_dp)
    x = 0.5_dp*(a + b) - 0.5_dp*(b - a)*cos(theta)
    wx = w*0.5_dp*pi*0.5_dp*(b - a)*sin(theta)
  end subroutine mapped_node

  !> Two unit vectors u, v with (u, v, n) orthonormal.
  pure subroutine plane_axes(n, u, v)
    real(dp), intent(in) :: n(3)
    real(dp), intent(out) :: u(3), v(3)
    real(dp) :: e(3)
    e = 0.0_dp
    e(minloc(abs(n), 1)) = 1.0_dp
    u = e - dot_product(e, n)*n
    u = u/norm2(u)
    v = [n(2)*u(3) - n(3)*u(2), n(3)*u(1) - n(1)*u(3), n(1)*u(2) - n(2)*u(1)]
  end subroutine plane_axes

  !> Gauss-Legendre nodes and weights on [-1, 1] (Newton on P_q from the
  !> Chebyshev guesses).
  pure subroutine gauss_legendre(q, t, w)
    integer, intent(in) :: q
    real(dp), allocatable, intent(out) :: t(:), w(:)
    real(dp) :: x, p0, p1, p2, dp1, dx
    integer :: i, k, it
    allocate(t(q), w(q))
    do i = 1, q
      x = cos(pi*(i - 0.25_dp)/(q + 0.5_dp))
      do it = 1, 100
        p0 = 1.0_dp
        p1 = x
        do k = 2, q
          p2 = ((2*k - 1)*x*p1 - (k - 1)*p0)/k
          p0 = p1
          p1 = p2
        end do
        dp1 = q*(x*p1 - p0)/(x*x - 1.0_dp)
        dx = p1/dp1
        x = x - dx
        if (abs(dx) < 1.0e-15_dp) exit
      end do
      p0 = 1.0_dp
      p1 = x
      do k = 2, q
        p2 = ((2*k - 1)*x*p1 - (k - 1)*p0)/k
        p0 = p1
        p1 = p2
      end do
      dp1 = q*(x*p1 - p0)/(x*x - 1.0_dp)
      t(q + 1 - i) = x
      w(q + 1 - i) = 2.0_dp/((1.0_dp - x*x)*dp1*dp1)
    end do
  end subroutine gauss_legendre

  !> Insertion sort of intervals by their start.
  pure subroutine sort_pairs(a, b)
    real(dp), intent(inout) :: a(:), b(:)
    real(dp) :: va, vb
    integer :: i, j
    do i = 2, size(a)
      va = a(i)
      vb = b(i)
      j = i - 1
      do while (j >= 1)
        if (a(j) <= va) exit
        a(j + 1) = a(j)
        b(j + 1) = b(j)
        j = j - 1
      end do
      a(j + 1) = va
      b(j + 1) = vb
    end do
  end subroutine sort_pairs
end module demstep_sphere_union
