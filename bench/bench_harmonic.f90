!> Benchmark of E(N, lambda, n): median time per evaluation of demstep's accurate
!> evaluator, of the naive double-precision closed form, and of a direct sum, for
!> n = 10 .. 1e9. Run: fpm run --profile release --example bench_harmonic
program bench_harmonic
  use demstep, only: dp, i8, harmonic_error
  use demstep_kinds, only: pi
  use demstep_sort, only: sort_ascending
  implicit none
  integer, parameter :: batch = 20000, repeats = 11
  real(dp), parameter :: ns(5) = [10.0_dp, 1.0e3_dp, 1.0e5_dp, 1.0e7_dp, 1.0e9_dp]
  real(dp) :: big_n(batch), lam_far(batch), lam_near(batch), u(3), sink
  real(dp) :: t_acc_far, t_acc_near, t_naive, t_direct
  integer :: i, j

  call random_seed(put=[(12345 + i, i = 1, 64)])
  do i = 1, batch
    call random_number(u)
    big_n(i) = pi*(1.05_dp + 300.0_dp*u(1))
    lam_far(i) = 0.3_dp + 0.69_dp*u(2)
    lam_near(i) = 1.0_dp - 10.0_dp**(-2.0_dp - 10.0_dp*u(3))
  end do
  sink = 0.0_dp
  write(*, '(a)') "median ns per evaluation of E(N, lambda, n); N in (3.3, 945)"
  write(*, '(a)') "| n | accurate, lambda in [0.3, 0.99) | accurate, 1-lambda in [1e-12, 1e-2] " &
    //"| naive closed form | direct sum | accurate / naive (worse case) |"
  write(*, '(a)') "|---:|---:|---:|---:|---:|---:|"
  do j = 1, size(ns)
    t_acc_far = median_time(1, ns(j), lam_far)
    t_acc_near = median_time(1, ns(j), lam_near)
    t_naive = median_time(2, ns(j), lam_far)
    t_direct = direct_time(ns(j))
    write(*, '("| ", es7.0, " | ", f8.1, " | ", f8.1, " | ", f8.1, " | ", es10.3, " | ", f5.2, " |")') &
      ns(j), t_acc_far, t_acc_near, t_naive, t_direct, max(t_acc_far, t_acc_near)/t_naive
  end do
  write(*, '(a, es10.3, a)') "(checksum ", sink, ")"

contains

  !> Median over `repeats` runs of the batch time per evaluation, in ns.
  real(dp) function median_time(which, n, lam) result(t)
    integer, intent(in) :: which
    real(dp), intent(in) :: n, lam(:)
    real(dp) :: times(repeats), e
    integer(i8) :: c0, c1, rate
    integer :: r, i, stat
    do r = 1, repeats
      call system_clock(c0, rate)
      do i = 1, batch
        if (which == 1) then
          call harmonic_error(big_n(i), lam(i), n, e, stat)
        else
          e = naive_error(big_n(i), lam(i), n)
        end if
        sink = sink + e
      end do
      call system_clock(c1)
      times(r) = real(c1 - c0, dp)/real(rate, dp)*1.0e9_dp/batch
    end do
    t = median(times)
  end function median_time

  !> Time of a direct sum (one evaluation of both sums, median of 3 for n <= 1e7).
  real(dp) function direct_time(n) result(t)
    real(dp), intent(in) :: n
    real(dp) :: times(3)
    integer(i8) :: c0, c1, rate
    integer :: r, reps
    reps = merge(3, 1, n <= 1.0e7_dp)
    do r = 1, reps
      call system_clock(c0, rate)
      sink = sink + direct_error(big_n(r), lam_far(r), n)
      call system_clock(c1)
      times(r) = real(c1 - c0, dp)/real(rate, dp)*1.0e9_dp
    end do
    t = median(times(1:reps))
  end function direct_time

  !> The naive closed form: Lagrange's identity with phases 2 pi/N in double.
  pure real(dp) function naive_error(big_n, lam, n) result(e)
    real(dp), intent(in) :: big_n, lam, n
    real(dp) :: p1, p2
    p1 = 2.0_dp*pi/big_n
    p2 = 2.0_dp*pi*lam/big_n
    e = 1.0_dp - (sin(0.5_dp*n*p1)*sin(0.5_dp*(n + 1.0_dp)*p1)/sin(0.5_dp*p1)) &
      /(lam*sin(0.5_dp*n*p2)*sin(0.5_dp*(n + 1.0_dp)*p2)/sin(0.5_dp*p2))
  end function naive_error

  !> The direct sums, term by term.
  pure real(dp) function direct_error(big_n, lam, n) result(e)
    real(dp), intent(in) :: big_n, lam, n
    real(dp) :: s1, s2, p1, p2
    integer(i8) :: k
    p1 = 2.0_dp*pi/big_n
    p2 = 2.0_dp*pi*lam/big_n
    s1 = 0.0_dp
    s2 = 0.0_dp
    do k = 1_i8, int(n, i8)
      s1 = s1 + sin(real(k, dp)*p1)
      s2 = s2 + sin(real(k, dp)*p2)
    end do
    e = 1.0_dp - s1/(lam*s2)
  end function direct_error

  real(dp) function median(x)
    real(dp), intent(in) :: x(:)
    real(dp) :: y(size(x))
    y = x
    call sort_ascending(y)
    median = y((size(y) + 1)/2)
  end function median

end program bench_harmonic
