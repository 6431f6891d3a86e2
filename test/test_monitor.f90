!> Tests of the solver-facing call and the monitor: the solver's arrays give
!> what `assembly_critical_steps` gives for the same scene, bad arrays are
!> refused by name and index, the warm start converges to the cold value with
!> fewer products, the cheap check flags a stiffened contact, the top mode's
!> participation sums to 1.
module test_monitor
  use testdrive, only: new_unittest, unittest_type, error_type, check, test_failed
  use demstep
  use demstep_assembly, only: assembly_operator_type, assembly_operator, order_min_bodies
  use demstep_packing, only: tile_scene
  use demstep_neighbours, only: contact_list
  use demstep_monitor, only: solver_critical_steps, step_monitor_type, mode_participation, top_shares, &
    monitor_verdict, fresh_pour_estimate, cheap_bound, participation_type, scene_participation
  use demstep_mass_scaling, only: scale_masses
  use demstep_vtk, only: write_vtk_particles, vtk_field_type, write_participation_vtk
  use demstep_lanczos, only: arpack_claim, arpack_release, certificate_steps
  use demstep_capi, only: c_solver_compute, c_solver_participation, demstep_scene_result_c, demstep_error_c
  use test_support, only: real_str, ieee_nan, run_app, write_file, work_dir, read_file, count_lines, int_str, seed_fixed
  use, intrinsic :: iso_c_binding, only: c_int, c_double, c_loc, c_null_ptr, c_sizeof, c_char
  implicit none
  private
  public :: collect_monitor

  !> One packing as a solver holds it: arrays, its contact list and per-contact values.
  type :: solver_arrays_type
    real(dp), allocatable :: x(:, :), mass(:), radius(:), inertia(:)
    integer, allocatable :: pairs(:, :)
    real(dp), allocatable :: k_n(:), k_t(:), c_n(:), c_t(:)
    real(dp) :: lo(3) = 0.0_dp, hi(3) = 0.0_dp
    real(dp) :: wall_point(3, 1) = 0.0_dp, wall_normal(3, 1) = 0.0_dp
    real(dp) :: wall_k(2) = 0.0_dp, wall_damping(2) = 0.0_dp
  end type solver_arrays_type

contains

  subroutine collect_monitor(testsuite)
    type(unittest_type), allocatable, intent(out) :: testsuite(:)
    testsuite = [ &
      new_unittest("solver arrays = assembly_critical_steps on the same scene (dense)", test_equals_dense), &
      new_unittest("solver arrays = assembly_critical_steps on the same scene (Lanczos)", test_equals_lanczos), &
      new_unittest("bad arrays refused by name and index", test_bad_arrays), &
      new_unittest("warm start: same value, fewer products", test_warm_start), &
      new_unittest("warm start with dashpots: the same damped limit, fewer products", test_warm_damped), &
      new_unittest("unchanged packing: the previous modes stand (1 product), below the exact limit; " &
        //"confirm_every runs Lanczos; a stiffened contact's neighbourhood starts it", test_warm_accept), &
      new_unittest("a previous mode that fails: refined in place unconfirmed; a top that moved: confirmed", &
        test_in_place), &
      new_unittest("a confirmation with dashpots: the damped limit's cold solve finds a top that moved", &
        test_deferred_confirmation), &
      new_unittest("scene participation: shares sum to 1, the light particle leads; result and VTK", &
        test_scene_participation), &
      new_unittest("app: participation in the report, the result group and a VTK file; inputs kept", &
        test_app_participation), &
      new_unittest("fresh-pour estimate: the generated packing's limit; bad input refused", test_fresh_pour), &
      new_unittest("the per-body bound holds: above omega_max^2, with rolling springs too", test_cheap_bound), &
      new_unittest("mass scaling reaches its target; the light particle grows most", test_scale_masses), &
      new_unittest("mass scaling on a crowded top (a uniform packing) reaches its target", test_scale_crowded), &
      new_unittest("mass scaling: max_passes below 2 or past the budget refused by name", test_scale_passes), &
      new_unittest("check: safe when unchanged, re-solve on a stiffened contact", test_check), &
      new_unittest("arrays in random order: a locality order kept across updates; the same limit and check", &
        test_locality_monitor), &
      new_unittest("participation sums to 1; a light particle leads", test_participation), &
      new_unittest("C entry point: the Fortran numbers and participation bit for bit; bad counts refused", &
        test_capi_solver), &
      new_unittest("app: no contact search with contacts_file", test_app_no_search), &
      new_unittest("VTK: participation as a point field, contacts as lines; bad fields refused", test_vtk), &
      new_unittest("concurrent solves: refused with busy or correct, never wrong", test_concurrent) &
      ]
  end subroutine collect_monitor

  !> A periodic packing of n spheres as a solver's arrays: its contacts with
  !> per-contact k_n, k_t (random within a factor 2), dashpots, and a floor
  !> wall through the lowest particles.
  subroutine packing_arrays(n, a, error)
    integer, intent(in) :: n
    type(solver_arrays_type), intent(out) :: a
    type(error_type), allocatable, intent(out) :: error
    type(scene_type) :: scene
    type(demstep_status_type) :: status
    integer, allocatable :: ci(:), cj(:)
    real(dp), allocatable :: cn(:, :), cd(:), u(:)
    integer :: nc
    call random_periodic_packing(scene, n, status, seed=7)
    call check(error, is_ok(status), "packing")
    if (allocated(error)) return
    call contact_list(scene, ci, cj, cn, cd, status)
    nc = size(ci)
    a%x = scene%x
    a%mass = scene%mass
    a%radius = scene%radius
    a%inertia = scene%inertia
    a%pairs = reshape([ci, cj], [nc, 2])
    a%pairs = transpose(a%pairs)
    allocate(u(nc))
    call seed_fixed(17)
    call random_number(u)
    a%k_n = 1.0_dp + u
    call random_number(u)
    a%k_t = 0.3_dp*(1.0_dp + u)
    a%c_n = 0.05_dp*sqrt(a%k_n)
    a%c_t = 0.02_dp*sqrt(a%k_t)
    a%lo = scene%cell_lo
    a%hi = scene%cell_hi
    a%wall_point(:, 1) = [0.0_dp, 0.0_dp, minval(scene%x(3, :)) + 0.5_dp]
    a%wall_normal(:, 1) = [0.0_dp, 0.0_dp, 1.0_dp]
    a%wall_k = [1.5_dp, 0.5_dp]
    a%wall_damping = [0.1_dp, 0.05_dp]
  end subroutine packing_arrays

  !> The same arrays as a scene: explicit contacts (8 values each), the cell,
  !> the wall with the scene's law and damping ratios.
  subroutine as_scene(a, scene, error)
    type(solver_arrays_type), intent(in) :: a
    type(scene_type), intent(out) :: scene
    type(error_type), allocatable, intent(out) :: error
    type(demstep_status_type) :: status
    real(dp), allocatable :: k(:, :)
    integer :: nc
    nc = size(a%pairs, 2)
    call new_scene(scene, 3, a%x, a%mass, a%radius, status, inertia=a%inertia)
    if (is_ok(status)) call scene_set_cell(scene, [.true., .true., .true.], a%lo, a%hi, status)
    allocate(k(8, nc), source=0.0_dp)
    k(1, :) = a%k_n
    k(2, :) = a%k_t
    k(5, :) = a%c_n
    k(6, :) = a%c_t
    if (is_ok(status)) call scene_set_contacts(scene, a%pairs, k, status)
    if (is_ok(status)) call scene_add_walls(scene, a%wall_point, a%wall_normal, status)
    if (is_ok(status)) call scene_set_law(scene, contact_law%linear, a%wall_k(1), a%wall_k(2), status)
    if (is_ok(status)) call scene_set_damping(scene, a%wall_damping(1), status, tangential=a%wall_damping(2))
    call check(error, is_ok(status), "scene: "//status_text(status))
    scene%effects(scene_effect%damping) = .true.
  end subroutine as_scene

  pure function status_text(status) result(text)
    type(demstep_status_type), intent(in) :: status
    character(len=:), allocatable :: text
    text = "ok"
    if (allocated(status%message)) text = status%message
  end function status_text

  subroutine compare(n, solver, error)
    integer, intent(in) :: n, solver
    type(error_type), allocatable, intent(out) :: error
    type(solver_arrays_type) :: a
    type(scene_type) :: scene
    type(critical_step_type) :: ref, got
    type(demstep_status_type) :: status
    ! tolerance: both paths build the same springs up to the rounding of the
    ! scene's wrapped positions; the eigensolves then agree to a few ulps
    real(dp), parameter :: tol = 1.0e-12_dp
    call packing_arrays(n, a, error)
    if (allocated(error)) return
    call as_scene(a, scene, error)
    if (allocated(error)) return
    call assembly_critical_steps(scene, ref, status, solver=solver)
    call check(error, is_ok(status), "scene: "//status_text(status))
    if (allocated(error)) return
    call solver_critical_steps(a%x, a%mass, a%radius, a%pairs, a%k_n, got, status, k_t=a%k_t, &
      c_n=a%c_n, c_t=a%c_t, inertia=a%inertia, wall_point=a%wall_point, wall_normal=a%wall_normal, &
      wall_k=a%wall_k, wall_damping=a%wall_damping, periodic=[.true., .true., .true.], cell_lo=a%lo, &
      cell_hi=a%hi, solver=solver)
    call check(error, is_ok(status), "solver arrays: "//status_text(status))
    if (allocated(error)) return
    call check(error, got%n_dof == ref%n_dof .and. got%n_springs == ref%n_springs .and. got%rotation &
      .and. got%damped_exact .and. ref%damped_exact, "same problem")
    if (allocated(error)) return
    call check(error, abs(got%dt_critical_eigen/ref%dt_critical_eigen - 1.0_dp) <= tol, &
      "undamped "//real_str(got%dt_critical_eigen)//" vs "//real_str(ref%dt_critical_eigen))
    if (allocated(error)) return
    call check(error, abs(got%dt_critical_damped/ref%dt_critical_damped - 1.0_dp) <= tol, &
      "damped "//real_str(got%dt_critical_damped)//" vs "//real_str(ref%dt_critical_damped))
    if (allocated(error)) return
    call check(error, abs(got%dt_critical_bound/ref%dt_critical_bound - 1.0_dp) <= tol .and. &
      abs(got%dt_contact_rule/ref%dt_contact_rule - 1.0_dp) <= tol, "bound and contact rule")
  end subroutine compare

  subroutine test_equals_dense(error)
    type(error_type), allocatable, intent(out) :: error
    call compare(100, eigen_solver%dense, error)
  end subroutine test_equals_dense

  subroutine test_equals_lanczos(error)
    type(error_type), allocatable, intent(out) :: error
    call compare(300, eigen_solver%lanczos, error)
  end subroutine test_equals_lanczos

  !> One refusal: status invalid_input with this `where` and `index`.
  subroutine expect(status, where, index, error)
    type(demstep_status_type), intent(in) :: status
    character(len=*), intent(in) :: where
    integer, intent(in) :: index
    type(error_type), allocatable, intent(out) :: error
    character(len=16) :: buf
    write(buf, '(i0)') index
    call check(error, status%stat == demstep_stat%invalid_input, where//": not refused")
    if (allocated(error)) return
    call check(error, status%where == where .and. status%index == index, "expected "//where//"("// &
      trim(buf)//"), got: "//status_text(status))
  end subroutine expect

  subroutine test_bad_arrays(error)
    type(error_type), allocatable, intent(out) :: error
    type(solver_arrays_type) :: a, b
    type(critical_step_type) :: r
    type(demstep_status_type) :: status
    call packing_arrays(64, a, error)
    if (allocated(error)) return
    b = a
    b%x(2, 3) = ieee_nan()
    call solver_critical_steps(b%x, b%mass, b%radius, b%pairs, b%k_n, r, status)
    call expect(status, "x", 3, error)
    if (allocated(error)) return
    call solver_critical_steps(a%x, a%mass, a%radius(2:), a%pairs, a%k_n, r, status)
    call expect(status, "radius", 0, error)
    if (allocated(error)) return
    b = a
    b%mass(5) = -1.0_dp
    call solver_critical_steps(b%x, b%mass, b%radius, b%pairs, b%k_n, r, status)
    call expect(status, "mass", 5, error)
    if (allocated(error)) return
    b = a
    b%pairs(2, 4) = size(a%mass) + 1
    call solver_critical_steps(b%x, b%mass, b%radius, b%pairs, b%k_n, r, status)
    call expect(status, "pairs", 4, error)
    if (allocated(error)) return
    b%pairs(2, 4) = b%pairs(1, 4)
    call solver_critical_steps(b%x, b%mass, b%radius, b%pairs, b%k_n, r, status)
    call expect(status, "pairs", 4, error)
    if (allocated(error)) return
    call solver_critical_steps(a%x, a%mass, a%radius, a%pairs, a%k_n(2:), r, status)
    call expect(status, "k_n", 0, error)
    if (allocated(error)) return
    b = a
    b%k_t(6) = -1.0_dp
    call solver_critical_steps(b%x, b%mass, b%radius, b%pairs, b%k_n, r, status, k_t=b%k_t)
    call expect(status, "k_t", 6, error)
    if (allocated(error)) return
    b%c_n(2) = ieee_nan()
    call solver_critical_steps(a%x, a%mass, a%radius, a%pairs, a%k_n, r, status, c_n=b%c_n)
    call expect(status, "c_n", 2, error)
    if (allocated(error)) return
    call solver_critical_steps(a%x, a%mass, a%radius, a%pairs, [0.0_dp], r, status)
    call expect(status, "k_n", 1, error)
    if (allocated(error)) return
    call solver_critical_steps(a%x, a%mass, a%radius, a%pairs, a%k_n, r, status, inertia=a%inertia(2:))
    call expect(status, "inertia", 0, error)
    if (allocated(error)) return
    call solver_critical_steps(a%x, a%mass, a%radius, a%pairs, a%k_n, r, status, &
      periodic=[.true., .true., .true.], cell_lo=a%lo, cell_hi=a%lo + 3.0_dp*maxval(a%radius))
    call expect(status, "cell_hi", 1, error)
    if (allocated(error)) return
    b = a
    b%wall_normal = 0.0_dp
    call solver_critical_steps(a%x, a%mass, a%radius, a%pairs, a%k_n, r, status, &
      wall_point=b%wall_point, wall_normal=b%wall_normal, wall_k=b%wall_k)
    call expect(status, "wall_normal", 1, error)
    if (allocated(error)) return
    ! two particles at one point, listed as a contact
    b = a
    b%x(:, b%pairs(2, 1)) = b%x(:, b%pairs(1, 1))
    call solver_critical_steps(b%x, b%mass, b%radius, b%pairs(:, 1:1), b%k_n(1:1), r, status)
    call expect(status, "pairs", 1, error)
  end subroutine test_bad_arrays

  !> The arrays moved a little: every particle by up to 2e-4 of its radius.
  subroutine jiggle(a)
    type(solver_arrays_type), intent(inout) :: a
    real(dp), allocatable :: u(:, :)
    allocate(u(3, size(a%mass)))
    call seed_fixed(5)
    call random_number(u)
    a%x = a%x + 4.0e-4_dp*(u - 0.5_dp)*spread(a%radius, 1, 3)
  end subroutine jiggle

  subroutine test_warm_start(error)
    type(error_type), allocatable, intent(out) :: error
    type(solver_arrays_type) :: a
    type(step_monitor_type) :: monitor
    type(critical_step_type) :: cold, exact
    type(demstep_status_type) :: status
    real(dp) :: tol
    call packing_arrays(400, a, error)
    if (allocated(error)) return
    monitor%solver = eigen_solver%lanczos
    tol = monitor%tolerance
    call monitor%update(a%x, a%mass, a%radius, a%pairs, a%k_n, status, k_t=a%k_t, &
      periodic=[.true., .true., .true.], cell_lo=a%lo, cell_hi=a%hi)
    call check(error, is_ok(status), "first update: "//status_text(status))
    if (allocated(error)) return
    call jiggle(a)
    call monitor%update(a%x, a%mass, a%radius, a%pairs, a%k_n, status, k_t=a%k_t, &
      periodic=[.true., .true., .true.], cell_lo=a%lo, cell_hi=a%hi)
    call check(error, is_ok(status), "second update: "//status_text(status))
    if (allocated(error)) return
    call solver_critical_steps(a%x, a%mass, a%radius, a%pairs, a%k_n, cold, status, k_t=a%k_t, &
      periodic=[.true., .true., .true.], cell_lo=a%lo, cell_hi=a%hi, solver=eigen_solver%lanczos, &
      tolerance=monitor%tolerance)
    call check(error, is_ok(status), "cold solve: "//status_text(status))
    if (allocated(error)) return
    call solver_critical_steps(a%x, a%mass, a%radius, a%pairs, a%k_n, exact, status, k_t=a%k_t, &
      periodic=[.true., .true., .true.], cell_lo=a%lo, cell_hi=a%hi, solver=eigen_solver%lanczos, &
      tolerance=1.0e-10_dp)
    call check(error, is_ok(status), "exact solve: "//status_text(status))
    if (allocated(error)) return
    ! the warm Rayleigh quotient lam lies in [lambda - r, lambda] with the
    ! residual r <= tol lam: 2/omega at most tol/2 (to first order) above the
    ! exact 2/omega (tolerance 1e-10), never below it; the step safe to the
    ! error bar (omega_upper^2 >= lambda) never above it
    call check(error, monitor%last%dt_critical_eigen >= exact%dt_critical_eigen*(1.0_dp - 1.0e-9_dp) .and. &
      monitor%last%dt_critical_eigen <= exact%dt_critical_eigen*(1.0_dp + tol), &
      "warm "//real_str(monitor%last%dt_critical_eigen)//" vs exact "//real_str(exact%dt_critical_eigen))
    if (allocated(error)) return
    call check(error, monitor%last%dt_critical_safe <= exact%dt_critical_eigen*(1.0_dp + 1.0e-9_dp), &
      "warm safe step "//real_str(monitor%last%dt_critical_safe)//" above the exact " &
      //real_str(exact%dt_critical_eigen))
    if (allocated(error)) return
    call check(error, monitor%last%eigen_products < cold%eigen_products, "warm products " &
      //real_str(real(monitor%last%eigen_products, dp))//" not below cold " &
      //real_str(real(cold%eigen_products, dp)))
  end subroutine test_warm_start

  subroutine test_warm_damped(error)
    type(error_type), allocatable, intent(out) :: error
    type(solver_arrays_type) :: a
    type(step_monitor_type) :: monitor
    type(critical_step_type) :: cold, exact
    type(demstep_status_type) :: status
    call packing_arrays(400, a, error)
    if (allocated(error)) return
    monitor%solver = eigen_solver%lanczos
    call monitor%update(a%x, a%mass, a%radius, a%pairs, a%k_n, status, k_t=a%k_t, c_n=a%c_n, c_t=a%c_t, &
      periodic=[.true., .true., .true.], cell_lo=a%lo, cell_hi=a%hi)
    call check(error, is_ok(status), "first update: "//status_text(status))
    if (allocated(error)) return
    call jiggle(a)
    call monitor%update(a%x, a%mass, a%radius, a%pairs, a%k_n, status, k_t=a%k_t, c_n=a%c_n, c_t=a%c_t, &
      periodic=[.true., .true., .true.], cell_lo=a%lo, cell_hi=a%hi)
    call check(error, is_ok(status) .and. monitor%last%damped_exact, "second update: "//status_text(status))
    if (allocated(error)) return
    call solver_critical_steps(a%x, a%mass, a%radius, a%pairs, a%k_n, cold, status, k_t=a%k_t, c_n=a%c_n, &
      c_t=a%c_t, periodic=[.true., .true., .true.], cell_lo=a%lo, cell_hi=a%hi, solver=eigen_solver%lanczos, &
      tolerance=monitor%tolerance)
    call check(error, is_ok(status) .and. cold%damped_exact, "cold solve: "//status_text(status))
    if (allocated(error)) return
    call solver_critical_steps(a%x, a%mass, a%radius, a%pairs, a%k_n, exact, status, k_t=a%k_t, c_n=a%c_n, &
      c_t=a%c_t, periodic=[.true., .true., .true.], cell_lo=a%lo, cell_hi=a%hi, solver=eigen_solver%lanczos, &
      tolerance=1.0e-10_dp)
    call check(error, is_ok(status) .and. exact%damped_exact, "exact solve: "//status_text(status))
    if (allocated(error)) return
    ! verified below the root: the last solve's error bar (at most tol of its
    ! eigenvalue 4) puts the safe step within about tol below the exact root
    ! (tolerance 1e-10); 2 tol leaves room for the Newton step's own gap
    call check(error, monitor%last%dt_critical_damped <= exact%dt_critical_damped*(1.0_dp + 1.0e-9_dp) .and. &
      monitor%last%dt_critical_damped >= exact%dt_critical_damped*(1.0_dp - 2.0_dp*monitor%tolerance), &
      "warm "//real_str(monitor%last%dt_critical_damped)//" vs exact "//real_str(exact%dt_critical_damped))
    if (allocated(error)) return
    call check(error, monitor%last%eigen_products < cold%eigen_products, "warm products " &
      //real_str(real(monitor%last%eigen_products, dp))//" not below cold " &
      //real_str(real(cold%eigen_products, dp)))
  end subroutine test_warm_damped

  !> A second update on the same arrays takes the previous modes as they are
  !> (their residuals meet the tolerance: one product for the undamped mode;
  !> the damped one's residual from the products its quotients made), and
  !> the step it certifies stays at or below the
  !> exact damped limit; with confirm_every = 1 the undamped Lanczos solve
  !> runs (with its confirmation) and gives the same limit to the tolerance;
  !> a stiffened contact under the top mode makes the next update look at
  !> its bodies and run Lanczos from their neighbourhood's top: the exact
  !> limit of the stiffened arrays.
  subroutine test_warm_accept(error)
    type(error_type), allocatable, intent(out) :: error
    type(solver_arrays_type) :: a
    type(step_monitor_type) :: monitor
    type(critical_step_type) :: exact
    type(demstep_status_type) :: status
    real(dp), allocatable :: ps(:), cs(:), ws(:)
    integer, allocatable :: top(:)
    integer :: k
    call packing_arrays(400, a, error)
    if (allocated(error)) return
    monitor%solver = eigen_solver%lanczos
    call solver_critical_steps(a%x, a%mass, a%radius, a%pairs, a%k_n, exact, status, k_t=a%k_t, c_n=a%c_n, &
      c_t=a%c_t, periodic=[.true., .true., .true.], cell_lo=a%lo, cell_hi=a%hi, solver=eigen_solver%lanczos, &
      tolerance=1.0e-10_dp)
    call check(error, is_ok(status) .and. exact%damped_exact, "exact solve: "//status_text(status))
    if (allocated(error)) return
    do k = 1, 3
      if (k == 3) monitor%confirm_every = 1
      call monitor%update(a%x, a%mass, a%radius, a%pairs, a%k_n, status, k_t=a%k_t, c_n=a%c_n, c_t=a%c_t, &
        periodic=[.true., .true., .true.], cell_lo=a%lo, cell_hi=a%hi)
      call check(error, is_ok(status) .and. monitor%last%damped_exact, "update "//int_str(int(k, i8))//": " &
        //status_text(status))
      if (allocated(error)) return
      ! (see test_warm_damped for the tolerances)
      call check(error, monitor%last%dt_critical_damped <= exact%dt_critical_damped*(1.0_dp + 1.0e-9_dp) .and. &
        monitor%last%dt_critical_damped >= exact%dt_critical_damped*(1.0_dp - 2.0_dp*monitor%tolerance), &
        "update "//int_str(int(k, i8))//": "//real_str(monitor%last%dt_critical_damped)//" vs exact " &
        //real_str(exact%dt_critical_damped))
      if (allocated(error)) return
    end do
    ! the first update is cold; the third, confirmed, ran Lanczos
    call check(error, .not. monitor%accepted .and. monitor%confirmed .and. monitor%last%eigen_products > 2, &
      "confirm_every = 1: no Lanczos solve")
    if (allocated(error)) return
    monitor%confirm_every = 10
    call monitor%update(a%x, a%mass, a%radius, a%pairs, a%k_n, status, k_t=a%k_t, c_n=a%c_n, c_t=a%c_t, &
      periodic=[.true., .true., .true.], cell_lo=a%lo, cell_hi=a%hi)
    call check(error, is_ok(status) .and. monitor%accepted .and. .not. monitor%confirmed .and. &
      monitor%last%eigen_products == 1 .and. monitor%last%damped_solves == 1, "unchanged: products " &
      //int_str(monitor%last%eigen_products)//", damped solves "//int_str(int(monitor%last%damped_solves, i8)))
    if (allocated(error)) return
    ! the top mode's leading contact 50 % stiffer (normal and tangential):
    ! its bodies' bounds rise, their neighbourhood's own top joins the start
    ! and Lanczos runs from it (not the old modes as they are); the limit is
    ! the exact one of the stiffened arrays, never above it
    call mode_participation(monitor, size(a%pairs, 2), ps, cs, ws, status)
    top = top_shares(cs, 1)
    a%k_n(top(1)) = 1.5_dp*a%k_n(top(1))
    a%k_t(top(1)) = 1.5_dp*a%k_t(top(1))
    call monitor%update(a%x, a%mass, a%radius, a%pairs, a%k_n, status, k_t=a%k_t, c_n=a%c_n, c_t=a%c_t, &
      periodic=[.true., .true., .true.], cell_lo=a%lo, cell_hi=a%hi)
    call check(error, is_ok(status) .and. monitor%flagged >= 2 .and. monitor%local_start .and. &
      .not. monitor%accepted .and. monitor%last%eigen_products > 2, "a stiffened contact: not looked at " &
      //"(flagged "//int_str(int(monitor%flagged, i8))//")")
    if (allocated(error)) return
    call solver_critical_steps(a%x, a%mass, a%radius, a%pairs, a%k_n, exact, status, k_t=a%k_t, c_n=a%c_n, &
      c_t=a%c_t, periodic=[.true., .true., .true.], cell_lo=a%lo, cell_hi=a%hi, solver=eigen_solver%lanczos, &
      tolerance=1.0e-10_dp)
    call check(error, is_ok(status) .and. &
      monitor%last%dt_critical_damped <= exact%dt_critical_damped*(1.0_dp + 1.0e-9_dp) .and. &
      monitor%last%dt_critical_damped >= exact%dt_critical_damped*(1.0_dp - 2.0_dp*monitor%tolerance), &
      "stiffened: "//real_str(monitor%last%dt_critical_damped)//" vs exact "//real_str(exact%dt_critical_damped))
  end subroutine test_warm_accept

  !> The rule for a previous mode whose residual fails (`in_place`): the top
  !> mode's leading contact 2 % stiffer moves the mode a little, in place:
  !> it is refined from itself, with no confirmation run, to the exact limit;
  !> the contacts that carry the top mode softened to a tenth move the top
  !> elsewhere: the refined mode's overlap with the old one falls below
  !> in_place and the confirmed solves run, again to the exact limit. The
  !> neighbourhood guard is switched off (local_margin above 1) so that
  !> the rule alone acts.
  subroutine test_in_place(error)
    type(error_type), allocatable, intent(out) :: error
    type(solver_arrays_type) :: a
    type(step_monitor_type) :: monitor
    type(demstep_status_type) :: status
    real(dp), allocatable :: ps(:), cs(:), ws(:)
    integer, allocatable :: top(:)
    integer :: k
    call packing_arrays(400, a, error)
    if (allocated(error)) return
    monitor%solver = eigen_solver%lanczos
    monitor%local_margin = 2.0_dp
    call update_against_exact(monitor, a, "first", error)
    if (allocated(error)) return
    call mode_participation(monitor, size(a%pairs, 2), ps, cs, ws, status)
    call check(error, is_ok(status), "participation")
    if (allocated(error)) return
    top = top_shares(cs, 1)
    a%k_n(top(1)) = 1.02_dp*a%k_n(top(1))
    a%k_t(top(1)) = 1.02_dp*a%k_t(top(1))
    call update_against_exact(monitor, a, "in place", error)
    if (allocated(error)) return
    call check(error, .not. monitor%accepted .and. .not. monitor%confirmed .and. .not. monitor%local_start, &
      "in place: accepted "//merge("T", "F", monitor%accepted)//", confirmed "//merge("T", "F", monitor%confirmed))
    if (allocated(error)) return
    ! (every contact with a share of the mode's energy above 1 %)
    do k = 1, size(cs)
      if (cs(k) <= 0.01_dp) cycle
      a%k_n(k) = 0.1_dp*a%k_n(k)
      a%k_t(k) = 0.1_dp*a%k_t(k)
    end do
    call update_against_exact(monitor, a, "moved", error)
    if (allocated(error)) return
    call check(error, monitor%confirmed .and. .not. monitor%accepted .and. .not. monitor%local_start, &
      "moved: not confirmed")
    if (allocated(error)) return
    ! (a NaN in_place would take every re-solved top as in place)
    monitor%in_place = ieee_nan()
    call monitor%update(a%x, a%mass, a%radius, a%pairs, a%k_n, status, k_t=a%k_t, c_n=a%c_n, c_t=a%c_t, &
      periodic=[.true., .true., .true.], cell_lo=a%lo, cell_hi=a%hi)
    call check(error, status%stat == demstep_stat%invalid_input .and. status%where == "in_place", &
      "NaN in_place: "//status_text(status))
  contains
    !> An update (scheduled confirmations off) against the exact damped limit
    !> (tolerance 1e-10) on the same arrays: never above it, and within 2 tol
    !> below it (see test_warm_damped).
    subroutine update_against_exact(monitor, a, what, error)
      type(step_monitor_type), intent(inout) :: monitor
      type(solver_arrays_type), intent(in) :: a
      character(len=*), intent(in) :: what
      type(error_type), allocatable, intent(out) :: error
      type(critical_step_type) :: exact
      type(demstep_status_type) :: status
      monitor%confirm_every = 0
      call monitor%update(a%x, a%mass, a%radius, a%pairs, a%k_n, status, k_t=a%k_t, c_n=a%c_n, c_t=a%c_t, &
        periodic=[.true., .true., .true.], cell_lo=a%lo, cell_hi=a%hi)
      call check(error, is_ok(status) .and. monitor%last%damped_exact, what//": "//status_text(status))
      if (allocated(error)) return
      call solver_critical_steps(a%x, a%mass, a%radius, a%pairs, a%k_n, exact, status, k_t=a%k_t, c_n=a%c_n, &
        c_t=a%c_t, periodic=[.true., .true., .true.], cell_lo=a%lo, cell_hi=a%hi, solver=eigen_solver%lanczos, &
        tolerance=1.0e-10_dp)
      call check(error, is_ok(status) .and. &
        monitor%last%dt_critical_damped <= exact%dt_critical_damped*(1.0_dp + 1.0e-9_dp) .and. &
        monitor%last%dt_critical_damped >= exact%dt_critical_damped*(1.0_dp - 2.0_dp*monitor%tolerance), &
        what//": "//real_str(monitor%last%dt_critical_damped)//" vs exact "//real_str(exact%dt_critical_damped))
    end subroutine update_against_exact
  end subroutine test_in_place

  !> A scheduled confirmation with dashpots (`confirm_every` = 1) makes no
  !> undamped confirmation run of its own: the damped limit's cold solve is
  !> the one. One particle, far from the top mode, made half as heavy after
  !> the second update puts the top on it, 1.3 % above the previous one (the
  !> neighbourhood guard off: local_margin above 1). The undamped solve
  !> refined from the previous mode stays on it; the cold solve finds the
  !> higher damped top and the undamped solve is made again, confirmed: the
  !> update lands on the exact damped limit of the new arrays (never above
  !> it, within 2 tol below) and on their undamped top (within tol; without
  !> the second undamped solve 1.3 % below). On the unchanged arrays (the
  !> second update) the confirmation is one cold solve and costs fewer
  !> products than an undamped confirmation run of ncv products plus that
  !> cold solve.
  subroutine test_deferred_confirmation(error)
    type(error_type), allocatable, intent(out) :: error
    type(solver_arrays_type) :: a
    type(step_monitor_type) :: monitor
    type(critical_step_type) :: exact
    type(demstep_status_type) :: status
    integer(i8) :: unchanged
    integer :: light
    call packing_arrays(400, a, error)
    if (allocated(error)) return
    monitor%solver = eigen_solver%lanczos
    monitor%local_margin = 2.0_dp
    monitor%confirm_every = 1
    call update(error)
    if (allocated(error)) return
    call update(error)
    if (allocated(error)) return
    call check(error, monitor%confirmed .and. .not. monitor%accepted .and. &
      monitor%last%damped_confirmations == 1, "unchanged: not confirmed by one cold solve")
    if (allocated(error)) return
    unchanged = monitor%last%eigen_products
    ! (the particle farthest from the top mode's peak)
    light = maxloc(sum((a%x - spread(a%x(:, maxloc(sum(monitor%mode_particles**2, 1), 1)), 2, &
      size(a%mass)))**2, 1), 1)
    a%mass(light) = 0.5_dp*a%mass(light)
    a%inertia(light) = 0.5_dp*a%inertia(light)
    call update(error)
    if (allocated(error)) return
    call solver_critical_steps(a%x, a%mass, a%radius, a%pairs, a%k_n, exact, status, k_t=a%k_t, c_n=a%c_n, &
      c_t=a%c_t, periodic=[.true., .true., .true.], cell_lo=a%lo, cell_hi=a%hi, solver=eigen_solver%lanczos, &
      tolerance=1.0e-10_dp)
    call check(error, is_ok(status) .and. monitor%confirmed .and. monitor%last%damped_exact .and. &
      monitor%last%dt_critical_damped <= exact%dt_critical_damped*(1.0_dp + 1.0e-9_dp) .and. &
      monitor%last%dt_critical_damped >= exact%dt_critical_damped*(1.0_dp - 2.0_dp*monitor%tolerance), &
      "light particle: damped "//real_str(monitor%last%dt_critical_damped)//" vs exact " &
      //real_str(exact%dt_critical_damped))
    if (allocated(error)) return
    call check(error, abs(monitor%last%omega_max/exact%omega_max - 1.0_dp) <= monitor%tolerance, &
      "light particle: omega_max "//real_str(monitor%last%omega_max)//" vs exact "//real_str(exact%omega_max))
    if (allocated(error)) return
    ! (the confirmation on unchanged arrays: the previous modes taken, then
    ! the cold solve of at least the certificate's products; an undamped
    ! confirmation run would add at least ncv)
    call check(error, unchanged < monitor%ncv + certificate_steps(6*size(a%mass)), &
      "unchanged arrays' confirmation: "//int_str(unchanged)//" products")
  contains
    subroutine update(error)
      type(error_type), allocatable, intent(out) :: error
      call monitor%update(a%x, a%mass, a%radius, a%pairs, a%k_n, status, k_t=a%k_t, c_n=a%c_n, c_t=a%c_t, &
        inertia=a%inertia, periodic=[.true., .true., .true.], cell_lo=a%lo, cell_hi=a%hi)
      call check(error, is_ok(status), "update: "//status_text(status))
    end subroutine update
  end subroutine test_deferred_confirmation

  !> `scene_participation` on a packing with one light particle: the steps
  !> are `assembly_critical_steps`' bit for bit, the particle and spring shares
  !> each sum to 1, the light particle leads; the result group lists it first
  !> and the VTK file carries the point and cell fields.
  subroutine test_scene_participation(error)
    type(error_type), allocatable, intent(out) :: error
    character(len=*), parameter :: path = work_dir//"/scene_participation.vtk"
    type(scene_type) :: scene
    type(critical_step_type) :: crit, ref
    type(participation_type) :: part
    type(demstep_status_type) :: status
    character(len=:), allocatable :: text
    integer, allocatable :: top(:)
    integer :: light, cmdstat
    call execute_command_line("mkdir -p "//work_dir, wait=.true., cmdstat=cmdstat)
    call random_periodic_packing(scene, 150, status, seed=11, k_tangential=0.5_dp)
    call check(error, is_ok(status), "packing")
    if (allocated(error)) return
    light = 21
    scene%mass(light) = scene%mass(light)/30.0_dp
    scene%inertia(light) = scene%inertia(light)/30.0_dp
    call scene_participation(scene, crit, part, status)
    call check(error, is_ok(status) .and. part%computed, "participation: "//status_text(status))
    if (allocated(error)) return
    call assembly_critical_steps(scene, ref, status)
    call check(error, is_ok(status) .and. crit%dt_critical_damped == ref%dt_critical_damped .and. &
      crit%dt_critical_eigen == ref%dt_critical_eigen, "not assembly_critical_steps' steps")
    if (allocated(error)) return
    ! sums of a few hundred non-negative terms: rounding of order 1e-14
    call check(error, abs(sum(part%particle_share) - 1.0_dp) <= 1.0e-12_dp .and. &
      abs(sum(part%spring_share) - 1.0_dp) <= 1.0e-12_dp .and. minval(part%spring_share) >= -1.0e-12_dp, &
      "sums "//real_str(sum(part%particle_share))//", "//real_str(sum(part%spring_share)))
    if (allocated(error)) return
    top = top_shares(part%particle_share, 3)
    call check(error, top(1) == light, "the light particle does not lead")
    if (allocated(error)) return
    top = top_shares(part%spring_share, 1)
    call check(error, any([part%spring_a(top(1)), part%spring_b(top(1))] == light) .and. &
      part%spring_kind(top(1)) == 1, "the leading spring is not the light particle's contact")
    if (allocated(error)) return
    call write_participation_vtk(path, scene, part, status)
    call check(error, is_ok(status), "vtk: "//status_text(status))
    if (allocated(error)) return
    call read_file(path, text)
    call check(error, index(text, "POINT_DATA 150") > 0 .and. index(text, "SCALARS participation double") > 0 &
      .and. index(text, "SCALARS contact_participation double") > 0 .and. index(text, "SCALARS k_n double") > 0, &
      "vtk sections")
    if (allocated(error)) return
    ! without a mode (the bound only): nothing to write, refused by name
    call scene_participation(scene, crit, part, status, solver=eigen_solver%none)
    call check(error, is_ok(status) .and. .not. part%computed, "solver none: "//status_text(status))
    if (allocated(error)) return
    call write_participation_vtk(path, scene, part, status)
    call check(error, status%stat == demstep_stat%invalid_input .and. status%where == "part", &
      "no mode, yet written")
  end subroutine test_scene_participation

  !> The app: `participation_file` writes the VTK file beside the deck, the
  !> report lists the particles and springs, the result group has them; a
  !> participation_file naming an input is refused (exit 2, the deck kept).
  subroutine test_app_participation(error)
    type(error_type), allocatable, intent(out) :: error
    character(len=*), parameter :: deck = work_dir//"/participation_deck.nml"
    character(len=:), allocatable :: stdout, stderr, text
    integer :: rc
    ! three spheres in a row, the middle one light: it carries the top mode
    call write_file(work_dir//"/participation_p.txt", [character(len=60) :: "0.0 0 0  0 0 0  1 0.6 0", &
      "1.1 0 0  0 0 0  0.1 0.6 0", "2.2 0 0  0 0 0  1 0.6 0"])
    call write_file(deck, [character(len=120) :: "&scene dim = 3, particles_file = 'participation_p.txt', " &
      //"k_normal = 100, participation_file = 'participation.vtk' /"])
    call run_app(deck, rc, stdout, stderr)
    call check(error, rc, 0, message="stderr: "//stderr)
    if (allocated(error)) return
    call check(error, index(stdout, "the particles that carry most") > 0 .and. index(stdout, "contact") > 0, &
      "report: "//stdout)
    if (allocated(error)) return
    call read_file(work_dir//"/participation.vtk", text)
    call check(error, index(text, "POINT_DATA 3") > 0 .and. index(text, "CELL_DATA 5") > 0, "vtk: "//text)
    if (allocated(error)) return
    call run_app("--namelist "//deck, rc, stdout, stderr)
    call check(error, rc == 0 .and. index(stdout, "PARTICIPATION=T") > 0 .and. &
      index(stdout, "TOP_PARTICLES=2 ") > 0, "result group: "//stdout)
    if (allocated(error)) return
    call write_file(deck, [character(len=120) :: "&scene dim = 3, particles_file = 'participation_p.txt', " &
      //"k_normal = 100, participation_file = 'participation_p.txt' /"])
    call run_app(deck, rc, stdout, stderr)
    call check(error, rc == 2 .and. index(stderr, "participation_file") > 0, "an input overwritten: "//stderr)
    if (allocated(error)) return
    call read_file(work_dir//"/participation_p.txt", text)
    call check(error, index(text, "0.1 0.6 0") > 0, "the particles file changed")
  end subroutine test_app_participation

  !> The estimate is the exact limit of the generated packing (the same call
  !> by hand gives it bit for bit); a bad ratio is refused by name.
  subroutine test_fresh_pour(error)
    type(error_type), allocatable, intent(out) :: error
    type(critical_step_type) :: est, ref
    type(scene_type) :: scene
    type(demstep_status_type) :: status
    call fresh_pour_estimate(1.0e-3_dp, 0.2_dp, 2500.0_dp, 200.0_dp, 60.0_dp, 0.2_dp, 0.0_dp, est, status, n=100)
    call check(error, is_ok(status) .and. est%damped_exact, "estimate: "//status_text(status))
    if (allocated(error)) return
    call random_periodic_packing(scene, 100, status, radius=1.0e-3_dp, polydispersity=0.2_dp, &
      density=2500.0_dp, k_normal=200.0_dp, k_tangential=60.0_dp, damping_ratio=0.2_dp)
    scene%damping_ratio_tangential = 0.0_dp
    call assembly_critical_steps(scene, ref, status)
    call check(error, is_ok(status) .and. est%dt_critical_damped == ref%dt_critical_damped .and. &
      est%dt_critical_damped < est%dt_critical_eigen, "not the packing's damped limit")
    if (allocated(error)) return
    call fresh_pour_estimate(1.0e-3_dp, 0.2_dp, 2500.0_dp, 200.0_dp, 60.0_dp, 0.2_dp, -1.0_dp, est, status, n=100)
    call check(error, status%stat == demstep_stat%invalid_input .and. status%where == &
      "tangential_damping_ratio", "a negative tangential ratio accepted")
  end subroutine test_fresh_pour

  !> The per-body bound of `check` against the exact top eigenvalue (dense)
  !> of a packing with tangential springs, without and with rolling and
  !> twisting springs: it must lie above (it is a bound) and, to be useful,
  !> within a factor 8 of it.
  subroutine test_cheap_bound(error)
    type(error_type), allocatable, intent(out) :: error
    type(scene_type) :: scene
    type(critical_step_type) :: crit
    type(assembly_operator_type) :: op
    type(demstep_status_type) :: status
    real(dp) :: rate, b
    integer :: t
    do t = 1, 2
      call random_periodic_packing(scene, 120, status, seed=3 + t, k_tangential=0.8_dp)
      if (t == 2) call scene_set_rolling(scene, 1.0_dp, 0.5_dp, status)
      call assembly_critical_steps(scene, crit, status, solver=eigen_solver%dense)
      call check(error, is_ok(status), "scene: "//status_text(status))
      if (allocated(error)) return
      call assembly_operator(scene, op, rate, status)
      b = cheap_bound(op)*rate**2
      call check(error, b >= crit%omega_max**2 .and. b <= 8.0_dp*crit%omega_max**2, "bound " &
        //real_str(b)//" against omega_max^2 "//real_str(crit%omega_max**2))
      if (allocated(error)) return
    end do
  end subroutine test_cheap_bound

  !> A monitor's update on the arrays with their moments of inertia (the
  !> mass-scaling tests' start).
  subroutine update_with_inertia(a, monitor, error)
    type(solver_arrays_type), intent(in) :: a
    type(step_monitor_type), intent(inout) :: monitor
    type(error_type), allocatable, intent(out) :: error
    type(demstep_status_type) :: status
    call monitor%update(a%x, a%mass, a%radius, a%pairs, a%k_n, status, k_t=a%k_t, c_n=a%c_n, c_t=a%c_t, &
      inertia=a%inertia, periodic=[.true., .true., .true.], cell_lo=a%lo, cell_hi=a%hi)
    call check(error, is_ok(status), "update: "//status_text(status))
  end subroutine update_with_inertia

  !> A packing with one particle 30 times lighter: a target 1.5 times the
  !> damped limit is reached (checked again by `solver_critical_steps` on the
  !> scaled arrays at tolerance 1e-10), the light particle takes the largest
  !> factor, the added mass stays below 5 % (the light particle grown to an
  !> ordinary one is 0.5 %) and at or above the cutting planes' lower bound
  !> of any scaling's added mass, within 5 % of it.
  subroutine test_scale_masses(error)
    type(error_type), allocatable, intent(out) :: error
    type(solver_arrays_type) :: a
    type(step_monitor_type) :: monitor
    type(critical_step_type) :: scaled, check_result
    type(demstep_status_type) :: status
    real(dp), allocatable :: scale(:)
    real(dp) :: added, target, least
    integer, parameter :: light = 37
    call packing_arrays(200, a, error)
    if (allocated(error)) return
    a%mass(light) = a%mass(light)/30.0_dp
    a%inertia(light) = a%inertia(light)/30.0_dp
    call update_with_inertia(a, monitor, error)
    if (allocated(error)) return
    target = 1.5_dp*monitor%last%dt_critical_damped
    call scale_masses(monitor, target, a%mass, a%radius, scale, added, scaled, status, inertia=a%inertia, &
      least=least)
    call check(error, is_ok(status) .and. scaled%dt_critical_damped >= target, "target not reached: " &
      //status_text(status))
    if (allocated(error)) return
    call check(error, minval(scale) >= 1.0_dp .and. maxloc(scale, 1) == light .and. added < 0.05_dp, &
      "light particle's factor "//real_str(scale(light))//", added mass "//real_str(added))
    if (allocated(error)) return
    ! (the bound holds for any factors reaching the target, these too; the
    ! linear program's tolerance 1e-9 is far inside the 1e-6 allowed)
    call check(error, least > 0.0_dp .and. added >= least - 1.0e-6_dp*added .and. added <= 1.05_dp*least, &
      "added "//real_str(added)//" against the lower bound "//real_str(least))
    if (allocated(error)) return
    ! the scaled arrays through the whole path, at the scene's tolerance
    call solver_critical_steps(a%x, a%mass*scale, a%radius, a%pairs, a%k_n, check_result, status, k_t=a%k_t, &
      c_n=a%c_n, c_t=a%c_t, inertia=a%inertia*scale, periodic=[.true., .true., .true.], cell_lo=a%lo, &
      cell_hi=a%hi, tolerance=1.0e-10_dp)
    ! (the monitor certifies its limit below the exact one: the re-check at
    ! the scene's tolerance 1e-10 is at or above the target)
    call check(error, is_ok(status) .and. check_result%dt_critical_damped >= (1.0_dp - 1.0e-9_dp)*target, &
      "re-check "//real_str(check_result%dt_critical_damped)//" below the target "//real_str(target))
  end subroutine test_scale_masses

  !> A uniform packing has many near-equal localised top modes (a crowded
  !> top): 1.2 and 1.3 times the limit are reached (re-checked at tolerance
  !> 1e-10 on the scaled arrays) with no more added mass than a diagonal rule
  !> needs:
  !> each particle's factor max(1, c (target/h_i)^2), h_i its own limit from
  !> its diagonal stiffness sums (Yade's per-body rule, as example/dem_solver
  !> takes it), with the least c that reaches the target (bisected to 0.1 %
  !> on the exact limit; its added mass is then within 0.1 % of its least).
  !> (`scale_masses` has its own diagonal candidate, h_i from its diagonal
  !> blocks' largest eigenvalues with the dashpots: a different estimate, so
  !> this rule is an independent check; measured 0.110 against 0.137 at 1.2 x,
  !> 0.253 against 0.289 at 1.3 x.)
  subroutine test_scale_crowded(error)
    type(error_type), allocatable, intent(out) :: error
    type(solver_arrays_type) :: a
    type(step_monitor_type) :: monitor
    type(critical_step_type) :: scaled, check_result
    type(demstep_status_type) :: status
    real(dp), allocatable :: scale(:), own(:), kd(:, :), rd(:, :), f(:)
    real(dp) :: added, target, least, nn(3), d(3), box(3), c_lo, c_hi, c, diagonal
    integer :: passes, k, e, i, j
    real(dp), parameter :: ratios(2) = [1.2_dp, 1.3_dp]
    call packing_arrays(200, a, error)
    if (allocated(error)) return
    call update_with_inertia(a, monitor, error)
    if (allocated(error)) return
    ! the diagonal rule: per particle the diagonal stiffness sums per axis,
    ! K = sum (k_n - k_t) n_a^2 + k_t and R = sum k_t (1 - n_a^2) r^2, and
    ! h_i^2 = 2 min(m/max K, I/max R)
    box = a%hi - a%lo
    allocate(kd(3, size(a%mass)), rd(3, size(a%mass)), source=0.0_dp)
    do k = 1, size(a%pairs, 2)
      d = a%x(:, a%pairs(2, k)) - a%x(:, a%pairs(1, k))
      d = d - box*anint(d/box)
      nn = d/norm2(d)
      do e = 1, 2
        i = a%pairs(e, k)
        kd(:, i) = kd(:, i) + (a%k_n(k) - a%k_t(k))*nn**2 + a%k_t(k)
        rd(:, i) = rd(:, i) + a%k_t(k)*(1.0_dp - nn**2)*a%radius(i)**2
      end do
    end do
    own = [(2.0_dp*min(a%mass(i)/maxval(kd(:, i)), a%inertia(i)/maxval(rd(:, i))), i = 1, size(a%mass))]
    do j = 1, size(ratios)
      target = ratios(j)*monitor%last%dt_critical_damped
      call scale_masses(monitor, target, a%mass, a%radius, scale, added, scaled, status, inertia=a%inertia, &
        passes=passes, least=least)
      call check(error, is_ok(status) .and. scaled%dt_critical_damped >= target, "target not reached: " &
        //status_text(status))
      if (allocated(error)) return
      call check(error, minval(scale) >= 1.0_dp .and. added > 0.0_dp .and. added >= least - 1.0e-6_dp*added, &
        "passes "//int_str(int(passes, i8))//", added "//real_str(added)//", bound "//real_str(least))
      if (allocated(error)) return
      ! the monitor certifies its limit below the exact one (tolerance 1e-3):
      ! the scene's solve (1e-10) of the scaled arrays is at or above the target
      call limit_of(scale, check_result)
      if (allocated(error)) return
      call check(error, check_result%dt_critical_damped >= (1.0_dp - 1.0e-9_dp)*target, &
        "re-check "//real_str(check_result%dt_critical_damped)//" below the target "//real_str(target))
      if (allocated(error)) return
      c_lo = 0.0_dp
      c_hi = 1.0_dp
      diagonal = -1.0_dp
      do
        c = c_hi
        if (diagonal >= 0.0_dp) c = 0.5_dp*(c_lo + c_hi)
        f = max(1.0_dp, c*target**2/own)
        call limit_of(f, check_result)
        if (allocated(error)) return
        if (check_result%dt_critical_damped >= target) then
          c_hi = c
          diagonal = sum((f - 1.0_dp)*a%mass)/sum(a%mass)
          if (c_hi - c_lo <= 1.0e-3_dp*c_hi) exit
        else
          c_lo = c
          if (diagonal < 0.0_dp) c_hi = 2.0_dp*c_hi
        end if
      end do
      call check(error, added <= diagonal, "added "//real_str(added) &
        //" above the diagonal rule's "//real_str(diagonal)//" (lower bound "//real_str(least)//") at "//real_str(ratios(j))//" x")
      if (allocated(error)) return
    end do
  contains
    !> The exact damped limit of the arrays with the factors f (tolerance 1e-10).
    subroutine limit_of(f, crit)
      real(dp), intent(in) :: f(:)
      type(critical_step_type), intent(out) :: crit
      call solver_critical_steps(a%x, a%mass*f, a%radius, a%pairs, a%k_n, crit, status, k_t=a%k_t, &
        c_n=a%c_n, c_t=a%c_t, inertia=a%inertia*f, periodic=[.true., .true., .true.], cell_lo=a%lo, &
        cell_hi=a%hi, tolerance=1.0e-10_dp)
      call check(error, is_ok(status), "solve: "//status_text(status))
    end subroutine limit_of
  end subroutine test_scale_crowded

  !> `max_passes` of `scale_masses`: below 2 (a warm solve and its
  !> confirmation: with 1 a target already reached was never confirmed and
  !> mass was added for nothing) and past huge - `diagonal_solves` (the
  !> diagonal candidate's budget overflowed) refused by name, nothing done;
  !> 2 confirms a target the limit already reaches (half of it) with no
  !> added mass in those 2 solves.
  subroutine test_scale_passes(error)
    type(error_type), allocatable, intent(out) :: error
    type(solver_arrays_type) :: a
    type(step_monitor_type) :: monitor
    type(critical_step_type) :: scaled
    type(demstep_status_type) :: status
    real(dp), allocatable :: scale(:)
    real(dp) :: added, target
    integer :: passes, k
    integer, parameter :: bad(4) = [1, 0, -3, huge(1)]
    call packing_arrays(200, a, error)
    if (allocated(error)) return
    call update_with_inertia(a, monitor, error)
    if (allocated(error)) return
    target = 0.5_dp*monitor%last%dt_critical_damped
    do k = 1, size(bad)
      call scale_masses(monitor, target, a%mass, a%radius, scale, added, scaled, status, inertia=a%inertia, &
        max_passes=bad(k), passes=passes)
      call check(error, status%stat == demstep_stat%invalid_input .and. status%where == "max_passes" .and. &
        passes == 0, "max_passes = "//int_str(int(bad(k), i8))//": "//status_text(status)//", passes " &
        //int_str(int(passes, i8)))
      if (allocated(error)) return
    end do
    call scale_masses(monitor, target, a%mass, a%radius, scale, added, scaled, status, inertia=a%inertia, &
      max_passes=2, passes=passes)
    call check(error, is_ok(status) .and. added == 0.0_dp .and. all(scale == 1.0_dp) .and. passes == 2 .and. &
      scaled%dt_critical_damped >= target, "max_passes = 2, target reached already: "//status_text(status) &
      //", added "//real_str(added)//", passes "//int_str(int(passes, i8)))
  end subroutine test_scale_passes

  !> A solver's arrays in random order (a 500-sphere packing tiled 4 x 4 x
  !> 6: 48 000 spheres, permuted, contacts renamed; normal springs only): the
  !> monitor numbers its
  !> operator's bodies in a locality order (`locality_order`) at the first
  !> update and keeps that order at the next one (the arrays jiggled), whose
  !> warm start then takes fewer products than the cold one. omega_max
  !> equals the same arrays' in tile order (no locality order there) to
  !> 1e-6 (both solves meet the relative tolerance 1e-6 on omega^2), and the
  !> check's Rayleigh quotient of the stored mode, computed per particle
  !> from the arrays, is the update's to 1e-12 (the mode mapped to the right
  !> particles).
  subroutine test_locality_monitor(error)
    type(error_type), allocatable, intent(out) :: error
    type(scene_type) :: base, tiled
    type(solver_arrays_type) :: a, b
    type(step_monitor_type) :: monitor, plain
    type(demstep_status_type) :: status
    integer, allocatable :: ci(:), cj(:), perm(:), new_of(:), first_order(:)
    real(dp), allocatable :: cn(:, :), cd(:), u(:)
    integer(i8) :: cold_products
    integer :: n, i, j, k
    logical :: safe
    call random_periodic_packing(base, 500, status, seed=11)
    if (is_ok(status)) call tile_scene(base, [4, 4, 6], tiled, status)
    call check(error, is_ok(status), "packing: "//status_text(status))
    if (allocated(error)) return
    call contact_list(tiled, ci, cj, cn, cd, status)
    n = tiled%n
    call check(error, is_ok(status) .and. n >= order_min_bodies, "contacts")
    if (allocated(error)) return
    ! tile order (b) and a random order (a)
    b%x = tiled%x
    b%mass = tiled%mass
    b%radius = tiled%radius
    b%pairs = transpose(reshape([ci, cj], [size(ci), 2]))
    b%k_n = spread(1.0_dp, 1, size(ci))
    b%lo = tiled%cell_lo
    b%hi = tiled%cell_hi
    call seed_fixed(29)
    allocate(u(n))
    call random_number(u)
    perm = [(i, i = 1, n)]
    do i = n, 2, -1
      j = min(i, int(u(i)*i) + 1)
      k = perm(i)
      perm(i) = perm(j)
      perm(j) = k
    end do
    allocate(new_of(n))
    new_of(perm) = [(i, i = 1, n)]
    a = b
    a%x = b%x(:, perm)
    a%mass = b%mass(perm)
    a%radius = b%radius(perm)
    a%pairs = reshape(new_of(reshape(b%pairs, [size(b%pairs)])), shape(b%pairs))
    monitor%solver = eigen_solver%lanczos
    plain%solver = eigen_solver%lanczos
    call monitor%update(a%x, a%mass, a%radius, a%pairs, a%k_n, status, &
      periodic=[.true., .true., .true.], cell_lo=a%lo, cell_hi=a%hi)
    call check(error, is_ok(status), "first update: "//status_text(status))
    if (allocated(error)) return
    call check(error, allocated(monitor%op%order) .and. size(monitor%order) == n, "random order: reordered")
    if (allocated(error)) return
    first_order = monitor%order
    cold_products = monitor%last%eigen_products
    call plain%update(b%x, b%mass, b%radius, b%pairs, b%k_n, status, &
      periodic=[.true., .true., .true.], cell_lo=b%lo, cell_hi=b%hi)
    call check(error, is_ok(status) .and. .not. allocated(plain%op%order), "tile order: kept")
    if (allocated(error)) return
    call check(error, abs(monitor%last%omega_max - plain%last%omega_max) <= 1.0e-6_dp*plain%last%omega_max, &
      "omega_max "//real_str(monitor%last%omega_max)//" against "//real_str(plain%last%omega_max))
    if (allocated(error)) return
    call monitor%check(0.9_dp*monitor%last%dt_critical_damped, safe, a%x, a%mass, a%radius, a%pairs, a%k_n, &
      status, periodic=[.true., .true., .true.], cell_lo=a%lo, cell_hi=a%hi)
    call check(error, is_ok(status) .and. safe .and. abs(monitor%quotient_ratio - 1.0_dp) < 1.0e-12_dp, &
      "the stored mode's quotient over the update's "//real_str(monitor%quotient_ratio))
    if (allocated(error)) return
    call jiggle(a)
    call monitor%update(a%x, a%mass, a%radius, a%pairs, a%k_n, status, &
      periodic=[.true., .true., .true.], cell_lo=a%lo, cell_hi=a%hi)
    call check(error, is_ok(status), "second update: "//status_text(status))
    if (allocated(error)) return
    call check(error, all(monitor%order == first_order), "the order kept")
    if (allocated(error)) return
    call check(error, monitor%last%eigen_products < cold_products, "warm products " &
      //int_str(monitor%last%eigen_products)//" not below cold "//int_str(cold_products))
  end subroutine test_locality_monitor

  subroutine test_check(error)
    type(error_type), allocatable, intent(out) :: error
    type(solver_arrays_type) :: a
    type(step_monitor_type) :: monitor
    type(demstep_status_type) :: status
    real(dp), allocatable :: ps(:), cs(:), ws(:), k(:)
    integer, allocatable :: top(:)
    real(dp) :: dt
    logical :: safe
    call packing_arrays(200, a, error)
    if (allocated(error)) return
    call monitor%update(a%x, a%mass, a%radius, a%pairs, a%k_n, status, k_t=a%k_t, c_n=a%c_n, &
      c_t=a%c_t, periodic=[.true., .true., .true.], cell_lo=a%lo, cell_hi=a%hi)
    call check(error, is_ok(status), "update: "//status_text(status))
    if (allocated(error)) return
    dt = 0.95_dp*monitor%last%dt_critical_damped
    call monitor%check(dt, safe, a%x, a%mass, a%radius, a%pairs, a%k_n, status, k_t=a%k_t, c_n=a%c_n, &
      c_t=a%c_t, periodic=[.true., .true., .true.], cell_lo=a%lo, cell_hi=a%hi)
    call check(error, is_ok(status) .and. safe .and. abs(monitor%quotient_ratio - 1.0_dp) < 1.0e-12_dp, &
      "unchanged: not safe at 0.95 of the limit")
    if (allocated(error)) return
    ! above the limit: re-solve
    call monitor%check(1.05_dp*monitor%last%dt_critical_damped, safe, a%x, a%mass, a%radius, a%pairs, &
      a%k_n, status, k_t=a%k_t, c_n=a%c_n, c_t=a%c_t, periodic=[.true., .true., .true.], cell_lo=a%lo, &
      cell_hi=a%hi)
    call check(error, .not. safe .and. monitor%verdict == monitor_verdict%resolve, "safe above the limit")
    if (allocated(error)) return
    ! the contact that carries most of the mode, three times stiffer
    call mode_participation(monitor, size(a%pairs, 2), ps, cs, ws, status)
    top = top_shares(cs, 1)
    k = a%k_n
    k(top(1)) = 3.0_dp*k(top(1))
    call monitor%check(dt, safe, a%x, a%mass, a%radius, a%pairs, k, status, k_t=a%k_t, c_n=a%c_n, &
      c_t=a%c_t, periodic=[.true., .true., .true.], cell_lo=a%lo, cell_hi=a%hi)
    call check(error, is_ok(status) .and. .not. safe .and. monitor%verdict == monitor_verdict%resolve, &
      "a stiffened top contact not flagged (quotient ratio "//real_str(monitor%quotient_ratio)//")")
    if (allocated(error)) return
    ! the contact that carries least, a hundred times stiffer: the bound moves
    top = top_shares(-cs, 1)
    k = a%k_n
    k(top(1)) = 100.0_dp*k(top(1))
    call monitor%check(dt, safe, a%x, a%mass, a%radius, a%pairs, k, status, k_t=a%k_t, c_n=a%c_n, &
      c_t=a%c_t, periodic=[.true., .true., .true.], cell_lo=a%lo, cell_hi=a%hi)
    call check(error, is_ok(status) .and. .not. safe, "a contact 100 times stiffer not flagged (bound " &
      //"ratio "//real_str(monitor%bound_ratio)//")")
  end subroutine test_check

  subroutine test_participation(error)
    type(error_type), allocatable, intent(out) :: error
    type(solver_arrays_type) :: a
    type(step_monitor_type) :: monitor
    type(demstep_status_type) :: status
    real(dp), allocatable :: ps(:), cs(:), ws(:)
    integer, allocatable :: top(:)
    logical, allocatable :: outside(:)
    integer :: light, k
    call packing_arrays(200, a, error)
    if (allocated(error)) return
    ! one particle 30 times lighter: the top mode sits on it
    light = 37
    a%mass(light) = a%mass(light)/30.0_dp
    a%inertia(light) = a%inertia(light)/30.0_dp
    call monitor%update(a%x, a%mass, a%radius, a%pairs, a%k_n, status, k_t=a%k_t, &
      wall_point=a%wall_point, wall_normal=a%wall_normal, wall_k=a%wall_k, &
      periodic=[.true., .true., .true.], cell_lo=a%lo, cell_hi=a%hi)
    call check(error, is_ok(status), "update: "//status_text(status))
    if (allocated(error)) return
    call mode_participation(monitor, size(a%pairs, 2), ps, cs, ws, status)
    call check(error, is_ok(status), "participation: "//status_text(status))
    if (allocated(error)) return
    ! sums of a few hundred non-negative terms: rounding of order 1e-14
    call check(error, abs(sum(ps) - 1.0_dp) <= 1.0e-12_dp .and. abs(sum(cs) + sum(ws) - 1.0_dp) <= 1.0e-12_dp, &
      "sums "//real_str(sum(ps))//", "//real_str(sum(cs) + sum(ws)))
    if (allocated(error)) return
    call check(error, all(ps >= 0.0_dp) .and. minval(cs) >= -1.0e-12_dp, "negative shares")
    if (allocated(error)) return
    top = top_shares(ps, 10)
    call check(error, size(top) == 10 .and. top(1) == light, "the light particle does not lead")
    if (allocated(error)) return
    do k = 2, 10
      call check(error, ps(top(k)) <= ps(top(k - 1)), "top 10 not in descending order")
      if (allocated(error)) return
    end do
    ! every particle outside the top 10 carries at most the tenth share
    allocate(outside(size(ps)), source=.true.)
    outside(top) = .false.
    call check(error, maxval(ps, mask=outside) <= ps(top(10)), "a larger share outside the top 10")
  end subroutine test_participation

  subroutine test_capi_solver(error)
    type(error_type), allocatable, intent(out) :: error
    type(solver_arrays_type), target :: a
    type(critical_step_type) :: ref
    type(demstep_status_type) :: status
    type(demstep_scene_result_c), target :: res
    type(demstep_error_c), target :: err
    integer(c_int), allocatable, target :: pairs0(:, :)
    integer(c_int), target :: periodic(3) = [1, 1, 1]
    integer(c_int) :: code
    integer :: nc, n
    real(dp), allocatable, target :: ps_c(:), cs_c(:), ws_c(:)
    real(dp), allocatable :: ps(:), cs(:), ws(:)
    type(step_monitor_type) :: solved
    call packing_arrays(100, a, error)
    if (allocated(error)) return
    nc = size(a%pairs, 2)
    n = size(a%mass)
    pairs0 = a%pairs - 1
    call solver_critical_steps(a%x, a%mass, a%radius, a%pairs, a%k_n, ref, status, k_t=a%k_t, &
      c_n=a%c_n, c_t=a%c_t, wall_point=a%wall_point, wall_normal=a%wall_normal, wall_k=a%wall_k, &
      wall_damping=a%wall_damping, periodic=[.true., .true., .true.], cell_lo=a%lo, cell_hi=a%hi)
    call check(error, is_ok(status), "Fortran: "//status_text(status))
    if (allocated(error)) return
    code = c_solver_compute(3, n, c_loc(a%x), c_loc(a%mass), c_loc(a%radius), c_null_ptr, nc, &
      c_loc(pairs0), nc, c_loc(a%k_n), c_loc(a%k_t), c_loc(a%c_n), c_loc(a%c_t), 1, c_loc(a%wall_point), &
      c_loc(a%wall_normal), c_loc(a%wall_k), c_loc(a%wall_damping), c_loc(periodic), c_loc(a%lo), &
      c_loc(a%hi), eigen_solver%auto, 0.0_dp, c_loc(res), c_sizeof(res), c_loc(err))
    call check(error, code == 0, "C: code not 0")
    if (allocated(error)) return
    call check(error, res%dt_critical_eigen == ref%dt_critical_eigen .and. &
      res%dt_critical_damped == ref%dt_critical_damped .and. res%n_springs == ref%n_springs .and. &
      res%rotation == 1, "C result differs: "//real_str(res%dt_critical_eigen)//" vs "// &
      real_str(ref%dt_critical_eigen))
    if (allocated(error)) return
    ! participation through C: the Fortran monitor's shares bit for bit,
    ! each set summing to 1 (to rounding: 1e-12 over a few hundred terms)
    allocate(ps_c(n), ws_c(n), cs_c(nc))
    code = c_solver_participation(3, n, c_loc(a%x), c_loc(a%mass), c_loc(a%radius), c_null_ptr, nc, &
      c_loc(pairs0), nc, c_loc(a%k_n), c_loc(a%k_t), c_loc(a%c_n), c_loc(a%c_t), 1, c_loc(a%wall_point), &
      c_loc(a%wall_normal), c_loc(a%wall_k), c_loc(a%wall_damping), c_loc(periodic), c_loc(a%lo), &
      c_loc(a%hi), eigen_solver%auto, 0.0_dp, c_loc(res), c_sizeof(res), c_loc(ps_c), c_loc(cs_c), &
      c_loc(ws_c), c_loc(err))
    call check(error, code == 0 .and. res%dt_critical_damped == ref%dt_critical_damped, &
      "C participation: "//c_text(err%message))
    if (allocated(error)) return
    call solver_critical_steps(a%x, a%mass, a%radius, a%pairs, a%k_n, ref, status, k_t=a%k_t, &
      c_n=a%c_n, c_t=a%c_t, wall_point=a%wall_point, wall_normal=a%wall_normal, wall_k=a%wall_k, &
      wall_damping=a%wall_damping, periodic=[.true., .true., .true.], cell_lo=a%lo, cell_hi=a%hi, solved=solved)
    call mode_participation(solved, nc, ps, cs, ws, status)
    call check(error, is_ok(status) .and. all(ps_c == ps) .and. all(cs_c == cs) .and. all(ws_c == ws) .and. &
      abs(sum(ps_c) - 1.0_dp) < 1.0e-12_dp .and. abs(sum(cs_c) + sum(ws_c) - 1.0_dp) < 1.0e-12_dp, &
      "C participation differs from the Fortran monitor's or does not sum to 1")
    if (allocated(error)) return
    code = c_solver_participation(3, n, c_loc(a%x), c_loc(a%mass), c_loc(a%radius), c_null_ptr, nc, &
      c_loc(pairs0), nc, c_loc(a%k_n), c_null_ptr, c_null_ptr, c_null_ptr, 0, c_null_ptr, c_null_ptr, &
      c_null_ptr, c_null_ptr, c_loc(periodic), c_loc(a%lo), c_loc(a%hi), eigen_solver%auto, 0.0_dp, &
      c_loc(res), c_sizeof(res), c_loc(ps_c), c_null_ptr, c_loc(ws_c), c_loc(err))
    call check(error, code == demstep_stat%invalid_input .and. index(c_text(err%message), "contact_share") > 0, &
      "NULL contact_share: "//c_text(err%message))
    if (allocated(error)) return
    ! scalar stiffness (n_values 1), no walls, no cell: a status, not a crash, for bad counts
    code = c_solver_compute(3, n, c_loc(a%x), c_loc(a%mass), c_loc(a%radius), c_null_ptr, nc, &
      c_loc(pairs0), 2, c_loc(a%k_n), c_null_ptr, c_null_ptr, c_null_ptr, 0, c_null_ptr, c_null_ptr, &
      c_null_ptr, c_null_ptr, c_null_ptr, c_null_ptr, c_null_ptr, eigen_solver%auto, 0.0_dp, c_loc(res), &
      c_sizeof(res), c_loc(err))
    call check(error, code == demstep_stat%invalid_input, "n_values 2 accepted")
    if (allocated(error)) return
    pairs0(1, 3) = n
    code = c_solver_compute(3, n, c_loc(a%x), c_loc(a%mass), c_loc(a%radius), c_null_ptr, nc, &
      c_loc(pairs0), 1, c_loc(a%k_n), c_null_ptr, c_null_ptr, c_null_ptr, 0, c_null_ptr, c_null_ptr, &
      c_null_ptr, c_null_ptr, c_null_ptr, c_null_ptr, c_null_ptr, eigen_solver%auto, 0.0_dp, c_loc(res), &
      c_sizeof(res), c_loc(err))
    call check(error, code == demstep_stat%invalid_input .and. index(c_text(err%message), "pairs(3)") > 0, &
      "pair out of range: "//c_text(err%message))
  end subroutine test_capi_solver

  !> Particles 1 and 3 at the same point: a contact search refuses them, but
  !> with a contacts_file that does not list them the deck is computed (the
  !> search is skipped: only listed pairs are contacts); without the file it
  !> is refused.
  subroutine test_app_no_search(error)
    type(error_type), allocatable, intent(out) :: error
    character(len=*), parameter :: deck = work_dir//"/monitor_deck.nml"
    character(len=:), allocatable :: stdout, stderr
    integer :: rc
    call write_file(work_dir//"/monitor_p.txt", [character(len=60) :: "0.1 0 0  0 0 0  1 0.6 0", &
      "1.1 0 0  0 0 0  1 0.6 0", "0.1 0 0  0 0 0  1 0.6 0"])
    call write_file(work_dir//"/monitor_c.txt", [character(len=20) :: "1 2 100 60"])
    call write_file(deck, [character(len=100) :: "&scene dim = 3, particles_file = 'monitor_p.txt', " &
      //"contacts_file = 'monitor_c.txt' /"])
    call run_app(deck, rc, stdout, stderr)
    call check(error, rc, 0, message="with contacts_file; stderr: "//stderr)
    if (allocated(error)) return
    call write_file(deck, [character(len=100) :: "&scene dim = 3, particles_file = 'monitor_p.txt', " &
      //"k_normal = 100 /"])
    call run_app(deck, rc, stdout, stderr)
    call check(error, rc == 2 .and. index(stderr, "same point") > 0, "without contacts_file: " &
      //"not refused: "//stderr)
  end subroutine test_app_no_search

  subroutine test_vtk(error)
    type(error_type), allocatable, intent(out) :: error
    character(len=*), parameter :: path = work_dir//"/monitor.vtk"
    type(solver_arrays_type) :: a
    type(step_monitor_type) :: monitor
    type(demstep_status_type) :: status
    real(dp), allocatable :: ps(:), cs(:), ws(:)
    type(vtk_field_type) :: pf(2), cf(1)
    character(len=:), allocatable :: text
    integer :: n, nc
    call packing_arrays(64, a, error)
    if (allocated(error)) return
    n = size(a%mass)
    nc = size(a%pairs, 2)
    call monitor%update(a%x, a%mass, a%radius, a%pairs, a%k_n, status, k_t=a%k_t, &
      periodic=[.true., .true., .true.], cell_lo=a%lo, cell_hi=a%hi)
    call mode_participation(monitor, nc, ps, cs, ws, status)
    call check(error, is_ok(status), "participation: "//status_text(status))
    if (allocated(error)) return
    pf(1) = vtk_field_type("radius", a%radius)
    pf(2) = vtk_field_type("participation", ps)
    cf(1) = vtk_field_type("contact_participation", cs)
    call write_vtk_particles(path, a%x, pf, status, pairs=a%pairs, contact_fields=cf)
    call check(error, is_ok(status), "write: "//status_text(status))
    if (allocated(error)) return
    call read_file(path, text)
    ! header 4 + points (1 + n) + cells and their types (2 (1 + n + nc)) + point
    ! data (1 + 2 (2 + n)) + cell data (1 + 2 + n + nc)
    call check(error, count_lines(text) == 4 + (1 + n) + 2*(1 + n + nc) + (1 + 2*(2 + n)) + &
      (3 + n + nc), "line count")
    if (allocated(error)) return
    call check(error, index(text, "POINT_DATA "//int_str(int(n, i8))) > 0 .and. index(text, "SCALARS " &
      //"participation double 1") > 0 .and. index(text, "CELL_DATA "//int_str(int(n + nc, i8))) > 0, "sections")
    if (allocated(error)) return
    pf(2) = vtk_field_type("two words", ps)
    call write_vtk_particles(path, a%x, pf, status)
    call check(error, status%stat == demstep_stat%invalid_input .and. status%where == "point_fields" &
      .and. status%index == 2, "a blank in a field name accepted")
  end subroutine test_vtk

  !> ARPACK's state held (as by another thread's solve): a Lanczos solve is
  !> refused with `busy`, a dense one runs; released: it runs. Then four
  !> solves on two threads at once: each is refused with `busy` or gives the
  !> serial answer (the same operator and start vector: the same rounding).
  subroutine test_concurrent(error)
    type(error_type), allocatable, intent(out) :: error
    type(solver_arrays_type) :: a
    type(critical_step_type) :: ref, r(4)
    type(demstep_status_type) :: status, st(4)
    integer :: t, n_ok
    call packing_arrays(300, a, error)
    if (allocated(error)) return
    call arpack_claim(status)
    call check(error, is_ok(status), "claim")
    if (allocated(error)) return
    call solver_critical_steps(a%x, a%mass, a%radius, a%pairs, a%k_n, ref, status, k_t=a%k_t, &
      periodic=[.true., .true., .true.], cell_lo=a%lo, cell_hi=a%hi, solver=eigen_solver%lanczos)
    call check(error, status%stat == demstep_stat%busy .and. status%where == "lanczos_largest", &
      "not refused while ARPACK is held: "//status_text(status))
    if (allocated(error)) then
      call arpack_release()
      return
    end if
    call solver_critical_steps(a%x(:, :100), a%mass(:100), a%radius(:100), a%pairs(:, 1:0), [1.0_dp], &
      ref, status, wall_point=a%wall_point, wall_normal=a%wall_normal, wall_k=a%wall_k, &
      solver=eigen_solver%dense)
    call arpack_release()
    call check(error, is_ok(status), "a dense solve refused: "//status_text(status))
    if (allocated(error)) return
    call solver_critical_steps(a%x, a%mass, a%radius, a%pairs, a%k_n, ref, status, k_t=a%k_t, &
      periodic=[.true., .true., .true.], cell_lo=a%lo, cell_hi=a%hi, solver=eigen_solver%lanczos)
    call check(error, is_ok(status), "released: "//status_text(status))
    if (allocated(error)) return
    !$omp parallel do num_threads(2) schedule(static, 1)
    do t = 1, 4
      call solver_critical_steps(a%x, a%mass, a%radius, a%pairs, a%k_n, r(t), st(t), k_t=a%k_t, &
        periodic=[.true., .true., .true.], cell_lo=a%lo, cell_hi=a%hi, solver=eigen_solver%lanczos)
    end do
    !$omp end parallel do
    n_ok = 0
    do t = 1, 4
      if (st(t)%stat == demstep_stat%busy) cycle
      call check(error, is_ok(st(t)), "solve "//int_str(int(t, i8))//": "//status_text(st(t)))
      if (allocated(error)) return
      ! tolerance: the same products in the same order give the same bits;
      ! 1e-14 leaves room for nothing but rounding
      call check(error, abs(r(t)%dt_critical_eigen/ref%dt_critical_eigen - 1.0_dp) <= 1.0e-14_dp, &
        "solve "//int_str(int(t, i8))//": "//real_str(r(t)%dt_critical_eigen)//" vs "// &
        real_str(ref%dt_critical_eigen))
      if (allocated(error)) return
      n_ok = n_ok + 1
    end do
    call check(error, n_ok >= 1, "every concurrent solve refused")
  end subroutine test_concurrent

  !> A NUL-terminated C message as text.
  pure function c_text(chars) result(text)
    character(kind=c_char), intent(in) :: chars(:)
    character(len=:), allocatable :: text
    integer :: i
    text = ""
    do i = 1, size(chars)
      if (chars(i) == achar(0)) exit
      text = text//chars(i)
    end do
  end function c_text

  !> A fixed seed of the intrinsic generator.

end module test_monitor
