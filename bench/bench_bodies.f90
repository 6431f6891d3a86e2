!> Benchmark of the rigid bodies' operator against the spheres' on the same
!> packing: `random_clump_packing` (clumps of 1 to 3 overlapping spheres on a
!> jittered grid over a floor, linear law with tangential, rolling and
!> twisting springs), BODIES clumps (1e5 by default, the issue's benchmark:
!> about 2e5 members). Per operator: the build (body set and operator, or the sphere
!> operator) and the product y = A' x, timed over 10 products, the median of
!> 15 such runs, per spring. The sphere operator also holds the contacts
!> between members of one clump (which the bodies' drops); its product cost
!> per spring is the reference the issue's goal names ("no more per contact
!> than today's sphere contacts"). The bonds' operator is the sphere operator
!> of the same members with a MUSEN solid bond (normal, shear, bending and
!> twisting stiffness) on every contact instead of the contact. The three
!> products are timed in turn within each run. One thread
!> (OMP_NUM_THREADS=1) to compare the kernels, not the scheduling.
!>
!>   OMP_NUM_THREADS=1 fpm run --example bench_bodies --profile release [-- BODIES]
program bench_bodies
  use, intrinsic :: iso_fortran_env, only: output_unit
  use demstep_kinds, only: dp
  use demstep_status, only: demstep_status_type, demstep_stat
  use demstep_progress, only: progress_seconds
  use demstep_scene_data, only: scene_type
  use demstep_packing, only: random_clump_packing
  use demstep_assembly, only: assembly_operator, assembly_operator_type, assembly_operator_apply, &
    spring_block_type
  use demstep_bodies, only: body_set_type, bodies_from_members
  use demstep_body_assembly, only: body_operator, body_operator_type, body_operator_apply
  use demstep_sort, only: sort_ascending
  use demstep_neighbours, only: contact_list
  use demstep_scene_data, only: scene_effect
  use demstep_scene_builders, only: scene_add_bonds
  use demstep_scene_bonds, only: scene_set_bond_model
  use demstep_bonds, only: bond_model
  implicit none
  integer, parameter :: products = 10, runs = 15
  type(scene_type) :: scene, bonded
  type(body_set_type) :: bodies
  type(body_operator_type) :: op_b
  type(assembly_operator_type) :: op_s, op_d
  type(spring_block_type), allocatable :: springs(:)
  type(demstep_status_type) :: status
  real(dp), allocatable :: xb(:), yb(:), xs(:), ys(:), xd(:), yd(:), pn(:, :), pd(:)
  integer, allocatable :: id(:), pi(:), pj(:)
  real(dp) :: t0, t_build_b, t_build_s, t_build_d, t_b(runs), t_s(runs), t_d(runs), rate
  integer :: target, j, k, ios
  character(len=32) :: arg

  target = 100000
  call get_command_argument(1, arg)
  if (arg /= "") read(arg, *, iostat=ios) target
  call random_clump_packing(scene, id, max(1, target), status, seed=7)
  if (status%stat /= demstep_stat%ok) error stop status%message

  t0 = progress_seconds()
  call bodies_from_members(scene, id, bodies, status)
  if (status%stat == demstep_stat%ok) call body_operator(scene, bodies, op_b, rate, status, springs)
  if (status%stat /= demstep_stat%ok) error stop status%message
  t_build_b = progress_seconds() - t0
  t0 = progress_seconds()
  call assembly_operator(scene, op_s, rate, status)
  if (status%stat /= demstep_stat%ok) error stop status%message
  t_build_s = progress_seconds() - t0
  ! the bonded members: a bond (E = 1e5, G = E/2.6, diameter ratio 1) on every contact
  bonded = scene
  call contact_list(bonded, pi, pj, pn, pd, status)
  if (status%stat == demstep_stat%ok) call scene_add_bonds(bonded, reshape([(pi(k), pj(k), k = 1, size(pi))], &
    [2, size(pi)]), status)
  bonded%effects(scene_effect%contacts) = .false.
  if (status%stat == demstep_stat%ok) call scene_set_bond_model(bonded, bond_model%musen, &
    [1.0e5_dp, 1.0e5_dp/2.6_dp, 1.0_dp], status)
  if (status%stat /= demstep_stat%ok) error stop status%message
  t0 = progress_seconds()
  call assembly_operator(bonded, op_d, rate, status)
  if (status%stat /= demstep_stat%ok) error stop status%message
  t_build_d = progress_seconds() - t0

  allocate(xb(op_b%n), yb(op_b%n), xs(op_s%n), ys(op_s%n), xd(op_d%n), yd(op_d%n))
  call random_number(xb)
  call random_number(xs)
  call random_number(xd)
  do k = 1, runs
    t0 = progress_seconds()
    do j = 1, products
      call body_operator_apply(op_b, xb, yb)
      xb(1) = xb(1) + 1.0e-3_dp*yb(1)/max(abs(yb(1)), 1.0_dp)
    end do
    t_b(k) = (progress_seconds() - t0)/products
    t0 = progress_seconds()
    do j = 1, products
      call assembly_operator_apply(op_s, xs, ys)
      xs(1) = xs(1) + 1.0e-3_dp*ys(1)/max(abs(ys(1)), 1.0_dp)
    end do
    t_s(k) = (progress_seconds() - t0)/products
    t0 = progress_seconds()
    do j = 1, products
      call assembly_operator_apply(op_d, xd, yd)
      xd(1) = xd(1) + 1.0e-3_dp*yd(1)/max(abs(yd(1)), 1.0_dp)
    end do
    t_d(k) = (progress_seconds() - t0)/products
  end do
  write(output_unit, '(a, i0, a, i0, a)') "members ", scene%n, ", bodies ", bodies%n, &
    " (one run; the machine may be shared: compare the two columns, not the absolutes)"
  write(output_unit, '(a)') "operator  dof  springs  build (s)  product (s, median of 15 x 10)  ns per spring"
  write(output_unit, '(a, i8, i9, es11.3, es14.4, f10.1)') "bodies  ", op_b%n, op_b%n_springs, t_build_b, &
    median(t_b), 1.0e9_dp*median(t_b)/op_b%n_springs
  write(output_unit, '(a, i8, i9, es11.3, es14.4, f10.1)') "spheres ", op_s%n, op_s%n_springs, t_build_s, &
    median(t_s), 1.0e9_dp*median(t_s)/op_s%n_springs
  write(output_unit, '(a, i8, i9, es11.3, es14.4, f10.1)') "bonds   ", op_d%n, op_d%n_springs, t_build_d, &
    median(t_d), 1.0e9_dp*median(t_d)/op_d%n_springs
  write(output_unit, '(a, f7.3)') "bodies/spheres, per spring: ", (median(t_b)/op_b%n_springs) &
    /(median(t_s)/op_s%n_springs)
  write(output_unit, '(a, f7.3)') "bonds/spheres, per spring: ", (median(t_d)/op_d%n_springs) &
    /(median(t_s)/op_s%n_springs)

contains

  !> The median of a few values.
  real(dp) function median(v)
    real(dp), intent(in) :: v(:)
    real(dp) :: w(size(v))
    w = v
    call sort_ascending(w)
    median = w((size(w) + 1)/2)
  end function median

end program bench_bodies
