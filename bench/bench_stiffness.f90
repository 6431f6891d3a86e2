!> Benchmark of the simulated-stiffness procedure: evaluations of E per root
!> (roots of E and ends of the admissible intervals) over a lambda grid and a
!> range of tolerances, and the time of a 10 000-lambda procedure run.
!> Run: fpm run --profile release --example bench_stiffness
program bench_stiffness
  use demstep
  use demstep_sort, only: sort_ascending
  use demstep_stiffness, only: n_scan_start
  implicit none
  integer, parameter :: n_lambda_grid = 200, n_big = 10000, repeats = 5
  type(nroots_options_type) :: options
  type(nroots_type) :: r
  type(demstep_status_type) :: status
  type(stiffness_input_type) :: input
  type(stiffness_result_type) :: result
  real(dp) :: lambda, times(repeats), tmin, tmed
  integer(i8) :: evaluations, found, c0, c1, rate
  integer :: i, k, rep

  write(*, '(a)') "evaluations of E per root, half-period steps, lambda in [0.3, 0.999]:"
  write(*, '(a)') "| tolerance | lambdas | roots + interval ends | evaluations | per root |"
  write(*, '(a)') "|---:|---:|---:|---:|---:|"
  do k = 1, 10
    options%tolerance = 10.0_dp**(-k)
    evaluations = 0
    found = 0
    do i = 0, n_lambda_grid - 1
      lambda = 0.3_dp + 0.699_dp*real(i, dp)/real(n_lambda_grid - 1, dp)
      call n_roots(lambda, options, r, status)
      evaluations = evaluations + r%evaluations
      found = found + size(r%roots) + count(r%lower > n_scan_start) + count(r%upper < options%n_max)
    end do
    write(*, '("| ", es7.0, " | ", i0, " | ", i0, " | ", i0, " | ", f6.1, " |")') options%tolerance, &
      n_lambda_grid, found, evaluations, real(evaluations, dp)/real(max(found, 1_8), dp)
  end do

  input%mass = 0.01_dp
  input%stiffness = 1.0e5_dp
  input%options%tolerance = 1.0e-3_dp
  input%lambdas = [(0.3_dp + 0.699_dp*real(i, dp)/real(n_big - 1, dp), i = 0, n_big - 1)]
  do rep = 1, repeats
    call system_clock(c0, rate)
    call simulated_stiffness(input, result, status)
    call system_clock(c1)
    times(rep) = real(c1 - c0, dp)/real(rate, dp)
  end do
  tmin = minval(times)
  call sort_ascending(times)
  tmed = times((repeats + 1)/2)
  write(*, '(a, i0, a, f7.3, a, f7.3, a, i0, a)') "procedure with ", n_big, " lambdas: median ", tmed, &
    " s, min ", tmin, " s (", result%evaluations, " evaluations of E)"
  write(*, '(a, es12.5, a, f10.6, a)') "  (N* = ", result%n_star, ", lambda* = ", result%lambda_star, ")"
end program bench_stiffness
