!> Benchmark (and check at sizes `fpm test` does not reach) of the scene
!> Lanczos solve on crowded spectra: random periodic packings (64 particles,
!> rotations and tangential springs, 6 DOF per particle) tiled K x K x K,
!> (default K = 4, 6, 8, 12 and seeds 1, 2; Lanczos at the default tolerance
!> unless TOL is given) against the exact top by Bloch's theorem (`bloch_top`). Per case, one run:
!> the reference's and the solve's seconds, the solve's products (the
!> certificate's included), omega_max's relative deficit below the reference
!> (at most half the tolerance is the claim), whether it converged, and
!> whether dt_critical_safe is at or below the exact limit 2/omega and
!> certified (`safe_basis`).
!>
!>   OPENBLAS_NUM_THREADS=1 fpm run --example bench_tiling_top --profile release [-- K_MAX [SEEDS [TOL [K_MIN]]]]
program bench_tiling_top
  use, intrinsic :: iso_fortran_env, only: output_unit
  use demstep_kinds, only: dp
  use demstep_status, only: demstep_status_type, demstep_stat
  use demstep_progress, only: progress_seconds
  use demstep_scene_data, only: scene_type
  use demstep_packing, only: random_periodic_packing, tile_scene
  use demstep_assembly, only: assembly_critical_steps, critical_step_type, eigen_solver, safe_basis_name
  use demstep_lanczos, only: lanczos_tolerance_default
  use demstep_bloch, only: bloch_top
  use demstep_text, only: int_text
  implicit none
  integer, parameter :: ks(6) = [4, 6, 8, 12, 16, 25]
  type(scene_type) :: base, tiled
  type(critical_step_type) :: r
  type(demstep_status_type) :: status
  character(len=32) :: arg
  character(len=24) :: buf(4)
  integer :: k_max, k_min, seeds, seed, c, k, ios
  real(dp) :: lam, rate, omega, t0, t_ref, t_solve, tol
  logical :: safe

  k_max = 12
  seeds = 2
  call get_command_argument(1, arg)
  if (arg /= "") read(arg, *, iostat=ios) k_max
  call get_command_argument(2, arg)
  if (arg /= "") read(arg, *, iostat=ios) seeds
  tol = lanczos_tolerance_default
  call get_command_argument(3, arg)
  if (arg /= "") read(arg, *, iostat=ios) tol
  k_min = 1
  call get_command_argument(4, arg)
  if (arg /= "") read(arg, *, iostat=ios) k_min
  write(output_unit, '(a, es8.1, a)') "# random periodic packings of 64 (seed) tiled K^3; Lanczos at tolerance ", &
    tol, "; one run each; times in seconds"
  write(output_unit, '(a)') "| seed | K | particles | Bloch s | Lanczos s | products | deficit | " &
    //"converged | safe <= exact | safe basis |"
  write(output_unit, '(a)') "|---:|---:|---:|---:|---:|---:|---:|---|---|---|"
  do seed = 1, seeds
    call random_periodic_packing(base, 64, status, seed=seed)
    call require("random_periodic_packing")
    do c = 1, size(ks)
      k = ks(c)
      if (k > k_max .or. k < k_min) cycle
      call tile_scene(base, [k, k, k], tiled, status)
      call require("tile_scene")
      t0 = progress_seconds()
      call bloch_top(base, [k, k, k], lam, rate, status)
      call require("bloch_top")
      t_ref = progress_seconds() - t0
      omega = rate*sqrt(lam)
      t0 = progress_seconds()
      call assembly_critical_steps(tiled, r, status, solver=eigen_solver%lanczos, tolerance=tol)
      call require("assembly_critical_steps")
      t_solve = progress_seconds() - t0
      safe = r%dt_critical_safe <= 2.0_dp/omega*(1.0_dp + 1.0e-12_dp)
      write(buf(1), '(f0.2)') t_ref
      write(buf(2), '(f0.2)') t_solve
      write(buf(3), '(es9.2)') (omega - r%omega_max)/omega
      write(output_unit, '(a)') "| "//int_text(seed)//" | "//int_text(k)//" | "//int_text(tiled%n) &
        //" | "//trim(buf(1))//" | "//trim(buf(2))//" | "//int_text(int(r%eigen_products))//" | " &
        //trim(adjustl(buf(3)))//" | "//trim(merge("yes", "no ", r%eigen_converged))//" | " &
        //trim(merge("yes", "NO ", safe))//" | "//safe_basis_name(r%safe_basis)//" |"
      flush(output_unit)
      if ((omega - r%omega_max)/omega > 0.5_dp*tol + 1.0e-12_dp) &
        write(output_unit, '(a)') "# the top was missed by more than the tolerance"
    end do
  end do

contains

  subroutine require(what)
    character(len=*), intent(in) :: what
    if (status%stat /= demstep_stat%ok) then
      write(output_unit, '(a)') "# "//what//": "//status%message
      error stop 1
    end if
  end subroutine require

end program bench_tiling_top
