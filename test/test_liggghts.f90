!> The LIGGGHTS check (validation/liggghts): settled piles poured, settled
!> and bisected in LIGGGHTS 3.8 (walls, gravity, Hertz and Hooke, restitution
!> 0.3 and 0.5, friction, epsd2 rolling, a periodic packing; controls without
!> tangential damping and without damping). The app runs the committed decks
!> (validation/liggghts/demstep/, written by demstep_compare.py from each
!> scene's dump and materials, in LIGGGHTS' convention) and its exact damped
!> limit must lie within [0.90, 1.005] of the measured limit (issue 19's goal:
!> never above by more than 0.5 %, within 10 % below), equal the independent
!> numpy model of the same conventions (reference_damped.py) to 1e-6, and its
!> recommended step must be below the measured bracket. The `fix
!> multisphere` scenes (h, i: rigid bodies read from the dump's `mol` and
!> `mass` columns) have no numpy reference; their exact damped limit must lie
!> within [0.98, 1.005] of the measured limit (issue 22's goal: never above by
!> more than 0.5 %, within 2 % below where no contact slides), j too, whose
!> template LIGGGHTS estimated by Monte Carlo (the union of the members,
!> which the app builds with `body_union = T`; h and i state the members'
!> sum, the default). LIGGGHTS is not needed: the
!> measurements and the reference are committed files.
module test_liggghts
  use testdrive, only: new_unittest, unittest_type, error_type, check
  use demstep, only: dp
  use test_support, only: run_app, read_file, real_str, result_value
  implicit none
  private
  public :: collect_liggghts

  character(len=*), parameter :: out = "build/demstep-test-files/liggghts_result.nml"
  character(len=*), parameter :: data = "validation/liggghts/data/"

contains

  subroutine collect_liggghts(testsuite)
    type(unittest_type), allocatable, intent(out) :: testsuite(:)
    testsuite = [ &
      new_unittest("a: Hertz pile, e 0.5, walls", test_a), &
      new_unittest("b: Hooke pile, e 0.3, walls", test_b), &
      new_unittest("c: Hertz pile with epsd2 rolling friction", test_c), &
      new_unittest("d: periodic Hertz packing", test_d), &
      new_unittest("f: tangential_damping off", test_f), &
      new_unittest("g: Hooke without damping (small kick)", test_g), &
      new_unittest("e: Hertz without damping: the recommended step below the bracket", test_e), &
      new_unittest("h: fix multisphere, 250 two-sphere bodies", test_h), &
      new_unittest("i: fix multisphere, 195 bodies of three unequal spheres", test_i), &
      new_unittest("j: fix multisphere, Monte Carlo template: the union of the members", test_j) &
      ]
  end subroutine collect_liggghts

  subroutine test_a(error)
    type(error_type), allocatable, intent(out) :: error
    call check_scene(error, "a_hertz", "measured.csv")
  end subroutine test_a

  subroutine test_b(error)
    type(error_type), allocatable, intent(out) :: error
    call check_scene(error, "b_hooke", "measured.csv")
  end subroutine test_b

  subroutine test_c(error)
    type(error_type), allocatable, intent(out) :: error
    call check_scene(error, "c_epsd2", "measured.csv")
  end subroutine test_c

  subroutine test_d(error)
    type(error_type), allocatable, intent(out) :: error
    call check_scene(error, "d_periodic", "measured.csv")
  end subroutine test_d

  subroutine test_f(error)
    type(error_type), allocatable, intent(out) :: error
    call check_scene(error, "f_tdoff", "measured.csv")
  end subroutine test_f

  subroutine test_g(error)
    type(error_type), allocatable, intent(out) :: error
    ! the undamped Hooke pile's limit depends on the kick (the larger one
    ! opens and closes contacts): the 1e-6 m/s measurement
    call check_scene(error, "g_hooke_undamped", "measured_kick1e-06.csv")
  end subroutine test_g

  subroutine test_e(error)
    type(error_type), allocatable, intent(out) :: error
    ! LIGGGHTS' undamped Hertz history law gains energy at every step
    ! (validation/liggghts/README.md): no sharp limit to meet, only the
    ! recommendation must stay below the bracket
    call check_scene(error, "e_undamped", "measured.csv", limit_checked=.false.)
  end subroutine test_e

  subroutine test_h(error)
    type(error_type), allocatable, intent(out) :: error
    call check_bodies_scene(error, "h_multisphere", 250)
  end subroutine test_h

  subroutine test_i(error)
    type(error_type), allocatable, intent(out) :: error
    call check_bodies_scene(error, "i_multisphere3", 195)
  end subroutine test_i

  subroutine test_j(error)
    type(error_type), allocatable, intent(out) :: error
    ! LIGGGHTS' Monte Carlo template has the union's tensor, as the app's
    ! bodies (measured 0.9982 of the middle; with the members' sum it was
    ! 0.9602, validation/liggghts/README.md)
    call check_bodies_scene(error, "j_multisphere_mc", 250)
  end subroutine test_j

  !> A multisphere scene: the app's bodies (6 degrees of freedom each), its
  !> exact damped limit against the measured bracket (at least `low`, default
  !> 0.98, of its middle), its recommended step below it.
  subroutine check_bodies_scene(error, scene, n_bodies, low)
    type(error_type), allocatable, intent(out) :: error
    character(len=*), intent(in) :: scene
    integer, intent(in) :: n_bodies
    real(dp), intent(in), optional :: low
    character(len=:), allocatable :: stdout, stderr, text
    real(dp) :: lo, hi, mid, dt_critical_damped, dt_recommended, lowest
    integer :: rc
    call execute_command_line("rm -f "//out, wait=.true., cmdstat=rc)
    call run_app("-q validation/liggghts/demstep/"//scene//".nml -o "//out, rc, stdout, stderr)
    call check(error, rc, 0, message=scene//": exit status; stderr: "//stderr)
    if (allocated(error)) return
    call read_file(out, text)
    dt_critical_damped = result_value(text, "DT_CRITICAL_DAMPED")
    dt_recommended = result_value(text, "DT_RECOMMENDED")
    call measured("measured.csv", scene, lo, hi)
    call check(error, lo > 0.0_dp .and. hi > lo .and. dt_critical_damped > 0.0_dp .and. dt_recommended > 0.0_dp, &
      scene//": the measurement and the result are read")
    if (allocated(error)) return
    call check(error, nint(result_value(text, "N_DOF")), 6*n_bodies, message=scene//": 6 degrees of freedom " &
      //"per body")
    if (allocated(error)) return
    call check(error, dt_recommended < lo, scene//": recommended "//real_str(dt_recommended)// &
      " below the measured bracket's "//real_str(lo))
    if (allocated(error)) return
    mid = 0.5_dp*(lo + hi)
    lowest = 0.98_dp
    if (present(low)) lowest = low
    call check(error, dt_critical_damped <= 1.005_dp*mid .and. dt_critical_damped >= lowest*mid, &
      scene//": exact damped "//real_str(dt_critical_damped)//" vs measured "//real_str(mid))
  end subroutine check_bodies_scene

  !> The measured bracket of a scene from a measurement table.
  subroutine measured(table, scene, lo, hi)
    character(len=*), intent(in) :: table, scene
    real(dp), intent(out) :: lo, hi
    character(len=:), allocatable :: text
    integer :: k, e, ios
    lo = -1.0_dp
    hi = -1.0_dp
    call read_file(data//table, text)
    k = index(text, new_line("a")//scene//",")
    if (k == 0) return
    k = k + len(scene) + 2
    e = index(text(k:), ",")
    read(text(k:k + e - 2), *, iostat=ios) lo
    k = k + e
    e = index(text(k:), ",")
    read(text(k:k + e - 2), *, iostat=ios) hi
  end subroutine measured

  !> The numpy model's exact damped limit of a scene (reference.json, "stick").
  real(dp) function reference(scene) result(dt)
    character(len=*), intent(in) :: scene
    character(len=:), allocatable :: text
    integer :: k, e, ios
    dt = -1.0_dp
    call read_file(data//scene//"/reference.json", text)
    k = index(text, '"stick"')
    if (k == 0) return
    k = k + index(text(k:), '"damped":') + len('"damped":') - 1
    e = scan(text(k:), ",}")
    read(text(k:k + e - 2), *, iostat=ios) dt
    if (ios /= 0) dt = -1.0_dp
  end function reference

  subroutine check_scene(error, scene, table, limit_checked)
    type(error_type), allocatable, intent(out) :: error
    character(len=*), intent(in) :: scene, table
    logical, intent(in), optional :: limit_checked
    character(len=:), allocatable :: stdout, stderr, text
    real(dp) :: lo, hi, mid, ref, dt_critical_damped, dt_recommended
    integer :: rc
    call execute_command_line("rm -f "//out, wait=.true., cmdstat=rc)
    call run_app("-q validation/liggghts/demstep/"//scene//".nml -o "//out, rc, stdout, stderr)
    call check(error, rc, 0, message=scene//": exit status; stderr: "//stderr)
    if (allocated(error)) return
    call read_file(out, text)
    dt_critical_damped = result_value(text, "DT_CRITICAL_DAMPED")
    dt_recommended = result_value(text, "DT_RECOMMENDED")
    call measured(table, scene, lo, hi)
    ref = reference(scene)
    call check(error, lo > 0.0_dp .and. hi > lo .and. ref > 0.0_dp .and. dt_critical_damped > 0.0_dp &
      .and. dt_recommended > 0.0_dp, scene//": the measurement, the reference and the result are read")
    if (allocated(error)) return
    mid = 0.5_dp*(lo + hi)
    call check(error, nint(result_value(text, "DOF_PER_PARTICLE")) == 6 .and. index(text, "ROTATION=T") > 0 &
      .and. index(text, "TANGENTIAL=T") > 0, scene//": the 6-dof model")
    if (allocated(error)) return
    ! the same model in numpy (dense eigensolves, bisection): measured
    ! agreement 1e-10 on a, b, d, e, f, g and 9e-8 on c (epsd2); 1e-6 leaves
    ! room for the Lanczos tolerance
    call check(error, dt_critical_damped, ref, rel=.true., thr=1.0e-6_dp, message=scene// &
      ": vs reference_damped.py")
    if (allocated(error)) return
    call check(error, dt_recommended < lo, scene//": recommended "//real_str(dt_recommended)// &
      " below the measured bracket's "//real_str(lo))
    if (allocated(error)) return
    if (present(limit_checked)) then
      if (.not. limit_checked) return
    end if
    call check(error, dt_critical_damped <= 1.005_dp*mid .and. dt_critical_damped >= 0.90_dp*mid, &
      scene//": exact damped "//real_str(dt_critical_damped)//" vs measured "//real_str(mid))
  end subroutine check_scene

end module test_liggghts
