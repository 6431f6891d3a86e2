!> Benchmark of the scene operator's product y = A' x at DEM scale: the
!> random periodic packing of `bench_scene_eigen` (1000 particles, seed 1,
!> rotations and tangential springs, 6 DOF per particle) tiled k x k x k
!> (default 10: 1e6 particles), the operator built by `assembly_operator`,
!> and the product timed over 10 products, the median of 5 such runs, with
!> 1 and 2 OpenMP threads (the two results compared bit for bit). Prints the
!> build time, the product's wall milliseconds and nanoseconds per spring,
!> its CPU milliseconds (all threads; on a shared machine the 1-thread CPU
!> time is the steadier figure) and x'A'x as a checksum; then the same for
!> the absolute product |A'| v of the bound (`operator_abs_product`, v > 0,
!> its diagonal blocks known; the bound makes three, the first summing the
!> blocks) with the sum of r as its checksum; then the whole
!> bound (`operator_bound`: its products and the Collatz-Wielandt steps; on
!> 2 threads, median of 5 runs) with its value.
!>
!> A second argument sets the product's block size (`operator_set_blocks`;
!> default `product_block_bodies`); the springs that cross blocks are counted.
!> A third, 0, leaves out the absolute product (the product alone, faster).
!>
!>   OPENBLAS_NUM_THREADS=1 fpm run --example bench_product --profile release [-- K [block_bodies [abs]]]
program bench_product
  use, intrinsic :: iso_fortran_env, only: output_unit
  use demstep_kinds, only: dp
  use demstep_status, only: demstep_status_type, demstep_stat
  use demstep_progress, only: progress_seconds
  use demstep_scene_data, only: scene_type
  use demstep_packing, only: random_periodic_packing, tile_scene
  use demstep_assembly, only: assembly_operator, assembly_operator_type, assembly_operator_apply, &
    operator_abs_product, operator_set_blocks, product_block_bodies, operator_bound
  use demstep_sort, only: sort_ascending
  use demstep_text, only: int_text
  !$ use omp_lib, only: omp_set_num_threads
  implicit none
  integer, parameter :: products = 10, runs = 5
  type(scene_type) :: packing, scene
  type(assembly_operator_type) :: op
  type(demstep_status_type) :: status
  real(dp), allocatable :: x(:), y(:, :), v(:), dsum(:, :)
  real(dp) :: t0, t_build, t(runs), tc(runs), rate, ms(2), cpu_ms(2), c0, c1, bound
  integer :: k, j, r, threads, ios, block_bodies, with_abs
  character(len=32) :: arg

  k = 10
  call get_command_argument(1, arg)
  if (arg /= "") read(arg, *, iostat=ios) k
  block_bodies = product_block_bodies
  call get_command_argument(2, arg)
  if (arg /= "") read(arg, *, iostat=ios) block_bodies
  with_abs = 1
  call get_command_argument(3, arg)
  if (arg /= "") read(arg, *, iostat=ios) with_abs
  call random_periodic_packing(packing, 1000, status, seed=1)
  if (status%stat /= demstep_stat%ok) error stop status%message
  call tile_scene(packing, [k, k, k], scene, status)
  if (status%stat /= demstep_stat%ok) error stop status%message
  t0 = progress_seconds()
  call assembly_operator(scene, op, rate, status)
  if (status%stat /= demstep_stat%ok) error stop status%message
  call operator_set_blocks(op, block_bodies)
  t_build = progress_seconds() - t0
  allocate(x(op%n), y(op%n, 2))
  do j = 1, op%n
    x(j) = sin(real(j, dp))
  end do
  call time_products(.false.)
  write(output_unit, '(a, i0, a, i0, a, f0.3, a)') "# particles ", scene%n, ", springs ", op%n_springs, &
    ", build ", t_build, " s"
  write(output_unit, '(a, i0, a, i0, a, f0.2, a)') "# blocks of ", op%block_bodies, " bodies: ", size(op%cross), &
    " springs cross blocks (", 100.0_dp*size(op%cross)/op%n_springs, " %)"
  write(output_unit, '(a, 2(f0.2, a), 2(f0.1, a), l1)') "product ms (1, 2 threads): ", ms(1), " ", ms(2), &
    "; ns per spring: ", 1.0e6_dp*ms(1)/op%n_springs, " ", 1.0e6_dp*ms(2)/op%n_springs, &
    "; same bits: ", all(y(:, 1) == y(:, 2))
  write(output_unit, '(a, 2(f0.2, a))') "product CPU ms (1, 2 threads: all threads' time): ", cpu_ms(1), " ", &
    cpu_ms(2), ""
  write(output_unit, '(a, es24.16)') "checksum ", sum(y(:, 1)*x)
  if (with_abs /= 0) then
    ! the bound's absolute product on a positive vector
    v = 1.0_dp + abs(x)
    allocate(dsum(18, op%n_bodies))
    call operator_abs_product(op, v, y(:, 1), dsum, .false.)
    call time_products(.true.)
    write(output_unit, '(4(a, f0.2), a, l1)') "abs product ms (1, 2 threads): ", ms(1), " ", ms(2), &
      "; CPU ms: ", cpu_ms(1), " ", cpu_ms(2), "; same bits: ", all(y(:, 1) == y(:, 2))
    write(output_unit, '(a, es24.16)') "abs checksum ", sum(y(:, 1))
    do r = 1, runs
      t0 = progress_seconds()
      call cpu_time(c0)
      bound = operator_bound(op)
      call cpu_time(c1)
      t(r) = progress_seconds() - t0
      tc(r) = c1 - c0
    end do
    call sort_ascending(t)
    call sort_ascending(tc)
    write(output_unit, '(2(a, f0.2), a, es24.16)') "bound ms (2 threads): ", 1.0e3_dp*t((runs + 1)/2), &
      "; CPU ms: ", 1.0e3_dp*tc((runs + 1)/2), "; bound ", bound
  end if
contains
  !> ms and cpu_ms for 1 and 2 threads (medians of the runs) of the product
  !> into y (absolute: |A'| v, else A' x).
  subroutine time_products(absolute)
    logical, intent(in) :: absolute
    do threads = 1, 2
      !$ call omp_set_num_threads(threads)
      do r = 1, runs
        t0 = progress_seconds()
        call cpu_time(c0)
        do j = 1, products
          if (absolute) then
            call operator_abs_product(op, v, y(:, threads), dsum, .true.)
          else
            call assembly_operator_apply(op, x, y(:, threads))
          end if
        end do
        call cpu_time(c1)
        t(r) = (progress_seconds() - t0)/products
        tc(r) = (c1 - c0)/products
      end do
      call sort_ascending(t)
      call sort_ascending(tc)
      ms(threads) = 1.0e3_dp*t((runs + 1)/2)
      cpu_ms(threads) = 1.0e3_dp*tc((runs + 1)/2)
    end do
  end subroutine time_products
end program bench_product
