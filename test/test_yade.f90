!> The Yade check (validation/yade): three periodic assemblies whose largest
!> stable step was measured in Yade by bisection. The app runs the example decks
!> on the exported particle and contact tables; its dt_critical_eigen must lie
!> within 0.5 % of the measured limit and never above it by more than 0.1 %,
!> and equal the independent numpy reference of the same model
!> (reference_6dof.py, "sym6_contact_point_arms": lever arms to the contact
!> point, r - delta/2, as Yade's ScGeom) to 1e-10, and its bound the
!> reference's Collatz-Wielandt bound. Yade is not needed: the
!> measurements and the reference are committed JSON files.
module test_yade
  use testdrive, only: new_unittest, unittest_type, error_type, check, test_failed
  use demstep, only: dp, i8
  use test_support, only: run_app, read_file, work_dir, real_str, result_value
  use demstep_results, only: result_group_type
  use test_support, only: read_group, take
  implicit none
  private
  public :: collect_yade, json_number

  character(len=*), parameter :: out = work_dir//"/yade_out.nml"

contains

  subroutine collect_yade(testsuite)
    type(unittest_type), allocatable, intent(out) :: testsuite(:)
    testsuite = [ &
      new_unittest("simple cubic: Yade's measured limit and the numpy reference", test_sc), &
      new_unittest("FCC: Yade's measured limit and the numpy reference", test_fcc), &
      new_unittest("random packing: Yade's measured limit and the numpy reference", test_random), &
      new_unittest("ViscElPhys pile: the exact damped limit in Yade's bracket", test_viscel), &
      new_unittest("CohFrictPhys pile (rolling, twisting): the exact limit in Yade's bracket", test_cohfrict) &
      ]
  end subroutine collect_yade

  subroutine test_sc(error)
    type(error_type), allocatable, intent(out) :: error
    call check_case(error, "sc")
  end subroutine test_sc

  subroutine test_fcc(error)
    type(error_type), allocatable, intent(out) :: error
    call check_case(error, "fcc")
  end subroutine test_fcc

  subroutine test_random(error)
    type(error_type), allocatable, intent(out) :: error
    call check_case(error, "random")
  end subroutine test_random

  !> The number after `"key": ` in a JSON text, from position `from` on.
  subroutine test_viscel(error)
    type(error_type), allocatable, intent(out) :: error
    call check_damped(error, "viscel", "per_sphere")
  end subroutine test_viscel

  subroutine test_cohfrict(error)
    type(error_type), allocatable, intent(out) :: error
    call check_damped(error, "cohfrict", "total")
  end subroutine test_cohfrict

  !> A damped pile (validation/yade/demstep/, written by
  !> demstep_compare_damped.py): the exact damped limit within [0.90, 1.005]
  !> of Yade's measured limit (issue 19's goal) and equal to the numpy model
  !> of Yade's conventions (reference_damped.py) to 1e-5 (measured: 2e-11 and
  !> 5e-6; the model keeps Yade's sphere-sphere shear factor alpha, demstep
  !> the symmetric form).
  subroutine check_damped(error, name, criterion)
    type(error_type), allocatable, intent(out) :: error
    character(len=*), intent(in) :: name, criterion
    character(len=:), allocatable :: stdout, stderr, reference, text
    real(dp) :: lo, hi, mid, ref, dt
    integer :: rc, k
    call execute_command_line("rm -f "//out, wait=.true., cmdstat=rc)
    call run_app("-q validation/yade/demstep/"//name//".nml -o "//out, rc, stdout, stderr)
    call check(error, rc, 0, message=name//": exit status; stderr: "//stderr)
    if (allocated(error)) return
    call read_file(out, text)
    dt = result_value(text, "DT_CRITICAL_DAMPED")
    call read_file("validation/yade/data/"//name//"/reference.json", reference)
    ! the measurement of the criterion named, at the small kick (1e-7 m/s)
    k = index(reference, '"v0": 1e-07')
    if (k > 0) k = k - 1 + index(reference(k:), '"criterion": "'//criterion//'"')
    lo = json_number(reference, "lo", max(1, k))
    hi = json_number(reference, "hi", max(1, k))
    ref = json_number(reference, "damped_limit", max(1, index(reference, '"yade":')))
    call check(error, k > 0 .and. lo > 0.0_dp .and. hi > lo .and. ref > 0.0_dp .and. dt > 0.0_dp, &
      name//": the measurement, the reference and the result are read")
    if (allocated(error)) return
    mid = 0.5_dp*(lo + hi)
    call check(error, dt <= 1.005_dp*mid .and. dt >= 0.90_dp*mid, name//": exact damped "//real_str(dt)// &
      " vs measured "//real_str(mid))
    if (allocated(error)) return
    call check(error, dt, ref, rel=.true., thr=1.0e-5_dp, message=name//": vs reference_damped.py")
  end subroutine check_damped

  real(dp) function json_number(text, key, from) result(x)
    character(len=*), intent(in) :: text, key
    integer, intent(in) :: from
    integer :: k, e, ios
    x = -1.0_dp
    k = index(text(from:), '"'//key//'":')
    if (k == 0) return
    k = from + k - 1 + len(key) + 3
    e = scan(text(k:), ",}"//new_line("a"))
    read(text(k:k + e - 2), *, iostat=ios) x
    if (ios /= 0) x = -1.0_dp
  end function json_number

  subroutine check_case(error, name)
    type(error_type), allocatable, intent(out) :: error
    character(len=*), intent(in) :: name
    character(len=:), allocatable :: stdout, stderr, summary, reference
    real(dp) :: lo, hi, mid, ref, ref_bound, ref_gershgorin
    integer :: rc, unit, ios
    integer :: n_particles, n_dof, n_springs, max_contacts, dof_per_particle
    real(dp) :: omega_max, dt_critical_eigen, dt_critical_bound, dt_contact_rule, &
      dt_critical_damped, damping_ratio_top, dt_used, energy_drift, max_overlap, dt_recommended
    integer(i8) :: steps
    logical :: eigen_computed, blew_up, rotation, tangential, periodic, prestress
    logical :: eigen_converged
    character(len=8) :: eigen_solver
    real(dp) :: eigen_tolerance, eigen_residual, omega_upper, dt_critical_safe
    logical :: damped_exact
    real(dp) :: dt_critical_damped_bound
    integer :: cmdstat
    type(result_group_type) :: scene_result_fields
    call execute_command_line("rm -f "//out, wait=.true., cmdstat=cmdstat)
    call run_app("-q example/yade_"//name//".nml -o "//out, rc, stdout, stderr)
    call check(error, rc, 0, message="exit status; stderr: "//stderr)
    if (allocated(error)) return
    open(newunit=unit, file=out, status="old", action="read", iostat=ios)
    call check(error, ios, 0, message="result file")
    if (allocated(error)) return
    call read_group(unit, "scene_result", scene_result_fields, ios)
    if (ios == 0) call take(scene_result_fields, "n_particles", n_particles, ios)
    if (ios == 0) call take(scene_result_fields, "n_dof", n_dof, ios)
    if (ios == 0) call take(scene_result_fields, "n_springs", n_springs, ios)
    if (ios == 0) call take(scene_result_fields, "dof_per_particle", dof_per_particle, ios)
    if (ios == 0) call take(scene_result_fields, "rotation", rotation, ios)
    if (ios == 0) call take(scene_result_fields, "tangential", tangential, ios)
    if (ios == 0) call take(scene_result_fields, "periodic", periodic, ios)
    if (ios == 0) call take(scene_result_fields, "prestress", prestress, ios)
    if (ios == 0) call take(scene_result_fields, "omega_max", omega_max, ios)
    if (ios == 0) call take(scene_result_fields, "eigen_computed", eigen_computed, ios)
    if (ios == 0) call take(scene_result_fields, "eigen_converged", eigen_converged, ios)
    if (ios == 0) call take(scene_result_fields, "eigen_solver", eigen_solver, ios)
    if (ios == 0) call take(scene_result_fields, "eigen_tolerance", eigen_tolerance, ios)
    if (ios == 0) call take(scene_result_fields, "eigen_residual", eigen_residual, ios)
    if (ios == 0) call take(scene_result_fields, "omega_upper", omega_upper, ios)
    if (ios == 0) call take(scene_result_fields, "dt_critical_safe", dt_critical_safe, ios)
    if (ios == 0) call take(scene_result_fields, "dt_critical_eigen", dt_critical_eigen, ios)
    if (ios == 0) call take(scene_result_fields, "dt_critical_bound", dt_critical_bound, ios)
    if (ios == 0) call take(scene_result_fields, "dt_contact_rule", dt_contact_rule, ios)
    if (ios == 0) call take(scene_result_fields, "dt_critical_damped", dt_critical_damped, ios)
    if (ios == 0) call take(scene_result_fields, "damping_ratio_top", damping_ratio_top, ios)
    if (ios == 0) call take(scene_result_fields, "dt_used", dt_used, ios)
    if (ios == 0) call take(scene_result_fields, "steps", steps, ios)
    if (ios == 0) call take(scene_result_fields, "energy_drift", energy_drift, ios)
    if (ios == 0) call take(scene_result_fields, "max_overlap", max_overlap, ios)
    if (ios == 0) call take(scene_result_fields, "max_contacts", max_contacts, ios)
    if (ios == 0) call take(scene_result_fields, "blew_up", blew_up, ios)
    if (ios == 0) call take(scene_result_fields, "dt_recommended", dt_recommended, ios)
    if (ios == 0) call take(scene_result_fields, "damped_exact", damped_exact, ios)
    if (ios == 0) call take(scene_result_fields, "dt_critical_damped_bound", dt_critical_damped_bound, ios)
    close(unit)
    call check(error, ios, 0, message="read(nml=scene_result)")
    if (allocated(error)) return
    call read_file("validation/yade/data/"//name//"/summary.json", summary)
    call read_file("validation/yade/data/"//name//"/reference.json", reference)
    lo = json_number(summary, "measured_dt_lo", 1)
    hi = json_number(summary, "measured_dt_hi", 1)
    ref = json_number(reference, "dt", max(1, index(reference, '"sym6_contact_point_arms"')))
    ref_bound = json_number(reference, "dt", max(1, index(reference, '"collatz_sym6"')))
    ref_gershgorin = json_number(reference, "dt", max(1, index(reference, '"gershgorin_sym6"')))
    call check(error, lo > 0.0_dp .and. hi > lo .and. ref > 0.0_dp, "the JSON files are read")
    if (allocated(error)) return
    mid = 0.5_dp*(lo + hi)
    call check(error, eigen_computed .and. dof_per_particle == 6 .and. rotation .and. tangential .and. &
      periodic .and. .not. prestress, "the 6-dof periodic model with tangential springs")
    if (allocated(error)) return
    ! the issue's goal: within 0.5 % of the measured limit, never above it by 0.1 %
    call check(error, abs(dt_critical_eigen/mid - 1.0_dp) <= 5.0e-3_dp, name//": "// &
      real_str(dt_critical_eigen)//" vs measured "//real_str(mid))
    if (allocated(error)) return
    call check(error, dt_critical_eigen <= 1.001_dp*hi, name//": above the measured bracket")
    if (allocated(error)) return
    ! the same model in numpy (dense eigvalsh, order up to 3600): both solvers
    ! reach a few ulps of the matrix norm, far below 1e-10
    call check(error, dt_critical_eigen, ref, rel=.true., thr=1.0e-10_dp, message=name//": vs reference_6dof.py")
    if (allocated(error)) return
    call check(error, dt_critical_bound <= dt_critical_eigen, name//": the bound is below the limit")
    if (allocated(error)) return
    ! the bound is Collatz-Wielandt's on |A| of the same matrix, v = 1 then two
    ! steps v <- |A| v, as the reference computes it with numpy (rounding of the
    ! sums and demstep's 1024-ulp allowance: far below 1e-10); never looser
    ! than Gershgorin's largest absolute row sum
    call check(error, dt_critical_bound, ref_bound, rel=.true., thr=1.0e-10_dp, message=name// &
      ": bound vs reference_6dof.py's Collatz-Wielandt")
    if (allocated(error)) return
    call check(error, dt_critical_bound >= ref_gershgorin*(1.0_dp - 1.0e-10_dp), name// &
      ": the bound is at least Gershgorin's")
  end subroutine check_case

end module test_yade
