!> A small covering linear program: minimise c't subject to A t >= r and
!> t >= 0, with A >= 0 (sparse, by rows) and c > 0 (always feasible when
!> every row with r > 0 has a positive entry, and bounded). Solved by a
!> primal-dual interior point method (Mehrotra's predictor-corrector) on the
!> problem with surplus w = A t - r >= 0 and its dual (max r'y subject to
!> A'y + z = c, y, z >= 0). Each iteration factors the m-by-m normal
!> equations A D A' + W/Y (D = T/Z; LAPACK's Cholesky), assembled column by
!> column from each column's entries: suited to a few hundred or thousand
!> rows (cuts) over any number of columns. No I/O.
module demstep_covering_lp
  use demstep_kinds, only: dp
  use demstep_status, only: demstep_status_type, demstep_stat, set_status
  use demstep_lapack, only: cholesky_factor, cholesky_solve
  use, intrinsic :: ieee_arithmetic, only: ieee_is_finite
  implicit none
  private

  public :: covering_lp

  !> Default tolerance of `covering_lp`: the relative primal and dual
  !> residuals and duality gap at the answer.
  real(dp), parameter, public :: covering_lp_tolerance_default = 1.0e-9_dp
  !> Interior point iterations before `covering_lp` gives up (they converge
  !> in 15 to 40).
  integer, parameter, public :: covering_lp_iterations_max = 200
  !> Iterations without a better iterate after which `covering_lp` stops.
  integer, parameter :: stall_iterations = 8
  !> The worst relative residual or gap a stalled answer may have (else
  !> not_converged).
  real(dp), parameter :: stall_tolerance = 1.0e-6_dp
  !> A column whose reduced cost is above this fraction of its cost is set
  !> to 0 in the answer.
  real(dp), parameter :: purify_fraction = 1.0e-3_dp

contains

  !> min c't subject to A t >= r, t >= 0 (see the module notes): A's row k
  !> holds the entries row_start(k) .. row_start(k+1)-1 (columns `col`, values
  !> `val` >= 0; a column may repeat: its entries add). Returns t (size n =
  !> size(c)) and the dual y >= 0 (size m: each row's price; c't = r'y at the
  !> optimum, so r'y is the least objective any feasible t reaches, up to
  !> `tolerance`). Status invalid_input naming `row_start`, `col`, `val`, `r`
  !> or `c` (with the index), or `r` for a row with r > 0 and no positive
  !> entry (infeasible); not_converged after `covering_lp_iterations_max`
  !> iterations.
  subroutine covering_lp(row_start, col, val, r, c, t, y, status, tolerance, iterations, lower)
    integer, intent(in) :: row_start(:), col(:)
    real(dp), intent(in) :: val(:), r(:), c(:)
    real(dp), allocatable, intent(out) :: t(:), y(:)
    type(demstep_status_type), intent(out) :: status
    !> Relative residuals and gap at the answer (default `covering_lp_tolerance_default`).
    real(dp), intent(in), optional :: tolerance
    !> Interior point iterations made.
    integer, intent(out), optional :: iterations
    !> A lower bound of the optimum: r'y with y scaled down until A'y <= c
    !> holds (weak duality), within rounding of the optimum at convergence.
    real(dp), intent(out), optional :: lower
    real(dp), allocatable :: a(:), rs(:), cs(:), x(:), w(:), z(:), rp(:), rd(:), n_mat(:, :), n0(:, :), d(:), &
      dx(:), dy(:), dz(:), dw(:), dxa(:), dya(:), dza(:), dwa(:), rxz(:), rwy(:), rhs(:), best_x(:), best_y(:)
    integer, allocatable :: col_start(:), col_row(:), col_entry(:), fill(:)
    real(dp) :: tol, c_max, mu, mu_aff, sigma, ap, ad, r_norm, c_norm, primal, dual, ridge, merit, best
    integer :: m, n, k, p, i, it, since
    m = size(r)
    n = size(c)
    allocate(t(n), y(m), source=0.0_dp)
    if (present(iterations)) iterations = 0
    if (present(lower)) lower = 0.0_dp
    tol = covering_lp_tolerance_default
    if (present(tolerance)) tol = tolerance
    call check_input(status)
    if (status%stat /= demstep_stat%ok) return
    if (m == 0 .or. all(r <= 0.0_dp)) then
      status%stat = demstep_stat%ok
      return
    end if
    ! scaled problem: each row by its largest entry, the costs by the largest
    allocate(rs(m), source=0.0_dp)
    do k = 1, m
      do p = row_start(k), row_start(k + 1) - 1
        rs(k) = max(rs(k), val(p))
      end do
    end do
    where (rs > 0.0_dp)
      rs = 1.0_dp/rs
    elsewhere
      rs = 1.0_dp
    end where
    c_max = maxval(c)
    cs = c/c_max
    allocate(a(size(val)))
    do k = 1, m
      a(row_start(k):row_start(k + 1) - 1) = val(row_start(k):row_start(k + 1) - 1)*rs(k)
    end do
    ! (rows with r <= 0 hold for every t >= 0: their surplus starts positive and stays)
    rhs = r*rs
    call column_lists()
    r_norm = maxval(abs(rhs))
    c_norm = maxval(cs)
    allocate(x(n), z(n), source=1.0_dp)
    allocate(w(m), source=1.0_dp)
    y = 1.0_dp
    allocate(n_mat(m, m), d(n), dx(n), dz(n), dy(m), dw(m), rxz(n), rwy(m))
    best = huge(1.0_dp)
    since = 0
    do it = 1, covering_lp_iterations_max
      if (present(iterations)) iterations = it
      rp = rhs - a_times(x) + w
      rd = cs - at_times(y) - z
      primal = dot_product(cs, x)
      dual = dot_product(rhs, y)
      ! the iterate's worst relative residual or gap; the best one is kept
      ! (near the answer rounding in the normal equations, whose condition
      ! grows without bound, can stall the residuals above the tolerance)
      merit = max(maxval(abs(rp))/(1.0_dp + r_norm), maxval(abs(rd))/(1.0_dp + c_norm), &
        abs(primal - dual)/(1.0_dp + abs(primal)))
      if (merit < best) then
        best = merit
        best_x = x
        best_y = y
        since = 0
      else
        since = since + 1
      end if
      if (best <= tol .or. since >= stall_iterations) exit
      mu = (dot_product(x, z) + dot_product(w, y))/real(n + m, dp)
      ! the normal equations (A D A' + W/Y), factored once for both solves
      d = x/z
      call normal_matrix()
      if (status%stat /= demstep_stat%ok) return
      ! predictor (affine scaling)
      rxz = -x*z
      rwy = -w*y
      call newton_step(dxa, dya, dza, dwa)
      if (status%stat /= demstep_stat%ok) return
      ap = step_length(x, dxa, w, dwa)
      ad = step_length(z, dza, y, dya)
      mu_aff = (dot_product(x + ap*dxa, z + ad*dza) + dot_product(w + ap*dwa, y + ad*dya))/real(n + m, dp)
      sigma = (mu_aff/mu)**3
      ! corrector (centring and the second-order term)
      rxz = sigma*mu - x*z - dxa*dza
      rwy = sigma*mu - w*y - dwa*dya
      call newton_step(dx, dy, dz, dw)
      if (status%stat /= demstep_stat%ok) return
      ap = min(1.0_dp, 0.995_dp*step_length(x, dx, w, dw))
      ad = min(1.0_dp, 0.995_dp*step_length(z, dz, y, dy))
      x = x + ap*dx
      w = w + ap*dw
      y = y + ad*dy
      z = z + ad*dz
    end do
    t = max(best_x, 0.0_dp)
    y = max(best_y, 0.0_dp)*rs*c_max
    status%stat = demstep_stat%ok
    if (present(lower)) lower = dual_bound()
    ! complementary slackness: a column whose reduced cost c - A'y is clearly
    ! positive is 0 at the optimum (the iterates leave it barely above)
    where (reduced_cost() > purify_fraction*c) t = 0.0_dp
    if (best <= stall_tolerance) return
    call set_status(status, demstep_stat%not_converged, "the interior point iterations did not converge", &
      where="covering_lp")
  contains
    !> r'y with the prices y scaled into dual feasibility (A'y <= c): by weak
    !> duality no t >= 0 with A t >= r costs less.
    real(dp) function dual_bound() result(bound)
      bound = dot_product(r, y)/max(1.0_dp, maxval((c - reduced_cost())/c))
    end function dual_bound
    !> c - A'y with the original A and the prices y.
    function reduced_cost() result(z_y)
      real(dp) :: z_y(n)
      integer :: kk, pp
      z_y = c
      do kk = 1, m
        do pp = row_start(kk), row_start(kk + 1) - 1
          z_y(col(pp)) = z_y(col(pp)) - val(pp)*y(kk)
        end do
      end do
    end function reduced_cost
    !> The arguments' sizes and values.
    subroutine check_input(status)
      type(demstep_status_type), intent(out) :: status
      logical :: positive
      status%stat = demstep_stat%ok
      if (size(row_start) /= m + 1) then
        call set_status(status, demstep_stat%invalid_input, "must have size(r) + 1 entries", where="row_start")
        return
      end if
      if (row_start(1) /= 1 .or. any(row_start(2:) < row_start(:m)) .or. row_start(m + 1) - 1 /= size(col) &
          .or. size(val) /= size(col)) then
        call set_status(status, demstep_stat%invalid_input, "must start at 1, not decrease and end " &
          //"after the last entry of col and val (of one size)", where="row_start")
        return
      end if
      do p = 1, row_start(m + 1) - 1
        if (col(p) < 1 .or. col(p) > n) then
          call set_status(status, demstep_stat%invalid_input, "must be a column in 1..size(c)", where="col", &
            index=p)
          return
        end if
        if (.not. (ieee_is_finite(val(p)) .and. val(p) >= 0.0_dp)) then
          call set_status(status, demstep_stat%invalid_input, "must be >= 0 and finite", where="val", index=p)
          return
        end if
      end do
      do i = 1, n
        if (.not. (ieee_is_finite(c(i)) .and. c(i) > 0.0_dp)) then
          call set_status(status, demstep_stat%invalid_input, "must be > 0 and finite", where="c", index=i)
          return
        end if
      end do
      do k = 1, m
        if (.not. ieee_is_finite(r(k))) then
          call set_status(status, demstep_stat%invalid_input, "must be finite", where="r", index=k)
          return
        end if
        positive = .false.
        do p = row_start(k), row_start(k + 1) - 1
          positive = positive .or. val(p) > 0.0_dp
        end do
        if (r(k) > 0.0_dp .and. .not. positive) then
          call set_status(status, demstep_stat%invalid_input, "is > 0 on a row with no positive entry " &
            //"(infeasible)", where="r", index=k)
          return
        end if
      end do
    end subroutine check_input
    !> Each column's entries (their rows and positions in a), for the normal equations.
    subroutine column_lists()
      integer :: q
      allocate(col_start(n + 1), source=0)
      do p = 1, size(a)
        col_start(col(p) + 1) = col_start(col(p) + 1) + 1
      end do
      col_start(1) = 1
      do i = 1, n
        col_start(i + 1) = col_start(i + 1) + col_start(i)
      end do
      allocate(col_row(size(a)), col_entry(size(a)))
      fill = col_start(:n)
      do k = 1, m
        do p = row_start(k), row_start(k + 1) - 1
          q = fill(col(p))
          col_row(q) = k
          col_entry(q) = p
          fill(col(p)) = q + 1
        end do
      end do
    end subroutine column_lists
    function a_times(v) result(av)
      real(dp), intent(in) :: v(:)
      real(dp) :: av(m)
      integer :: kk, pp
      do kk = 1, m
        av(kk) = 0.0_dp
        do pp = row_start(kk), row_start(kk + 1) - 1
          av(kk) = av(kk) + a(pp)*v(col(pp))
        end do
      end do
    end function a_times
    function at_times(v) result(atv)
      real(dp), intent(in) :: v(:)
      real(dp) :: atv(n)
      integer :: kk, pp
      atv = 0.0_dp
      do kk = 1, m
        do pp = row_start(kk), row_start(kk + 1) - 1
          atv(col(pp)) = atv(col(pp)) + a(pp)*v(kk)
        end do
      end do
    end function at_times
    !> n_mat = A D A' + W/Y, Cholesky-factored (a ridge added when rounding
    !> leaves it not quite positive definite, as the iterates near the answer).
    subroutine normal_matrix()
      integer :: q1, q2, k1, k2, attempt
      n_mat = 0.0_dp
      do i = 1, n
        do q1 = col_start(i), col_start(i + 1) - 1
          k1 = col_row(q1)
          do q2 = col_start(i), col_start(i + 1) - 1
            k2 = col_row(q2)
            if (k2 < k1) cycle
            n_mat(k2, k1) = n_mat(k2, k1) + d(i)*a(col_entry(q1))*a(col_entry(q2))
          end do
        end do
      end do
      do k = 1, m
        n_mat(k, k) = n_mat(k, k) + w(k)/y(k)
      end do
      n0 = n_mat
      ridge = 0.0_dp
      do attempt = 1, 8
        call cholesky_factor(n_mat, status)
        if (status%stat == demstep_stat%ok) return
        ridge = max(10.0_dp*ridge, 1.0e-14_dp*maxval([(n0(k, k), k = 1, m)]))
        n_mat = n0
        do k = 1, m
          n_mat(k, k) = n_mat(k, k) + ridge
        end do
      end do
    end subroutine normal_matrix
    !> The Newton direction for the residuals rp, rd and the complementarity
    !> right-hand sides rxz, rwy (the factored normal equations).
    subroutine newton_step(ddx, ddy, ddz, ddw)
      real(dp), allocatable, intent(out) :: ddx(:), ddy(:), ddz(:), ddw(:)
      real(dp), allocatable :: b0(:), res(:)
      integer :: kk
      b0 = rp + a_times(d*rd - rxz/z) + rwy/y
      ddy = b0
      call cholesky_solve(n_mat, ddy, status)
      if (status%stat /= demstep_stat%ok) return
      ! one step of iterative refinement against the unfactored matrix
      ! (its lower triangle)
      res = b0
      do kk = 1, m
        res(kk) = res(kk) - dot_product(n0(kk:, kk), ddy(kk:))
        res(kk + 1:) = res(kk + 1:) - n0(kk + 1:, kk)*ddy(kk)
      end do
      call cholesky_solve(n_mat, res, status)
      if (status%stat /= demstep_stat%ok) return
      ddy = ddy + res
      ddx = d*(at_times(ddy) - rd) + rxz/z
      ddz = (rxz - z*ddx)/x
      ddw = (rwy - w*ddy)/y
    end subroutine newton_step
  end subroutine covering_lp

  !> The largest step (at most 1) along (du, dv) that keeps u and v >= 0.
  pure real(dp) function step_length(u, du, v, dv) result(alpha)
    real(dp), intent(in) :: u(:), du(:), v(:), dv(:)
    integer :: i
    alpha = 1.0_dp
    do i = 1, size(u)
      if (du(i) < 0.0_dp) alpha = min(alpha, -u(i)/du(i))
    end do
    do i = 1, size(v)
      if (dv(i) < 0.0_dp) alpha = min(alpha, -v(i)/dv(i))
    end do
  end function step_length

end module demstep_covering_lp
