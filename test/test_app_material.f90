!> End-to-end tests of `&material`: the result group read back and checked
!> against the formulas evaluated independently in quad precision (Hertz
!> overlap and stiffness, Rayleigh time, the lagged dashpot's limit), the
!> peers' rules as fractions of their time scales, the recommended step, and
!> each bad input in one line.
module test_app_material
  use testdrive, only: new_unittest, unittest_type, error_type, check
  use demstep, only: dp
  use test_support, only: run_app, write_file, work_dir, file_exists
  use, intrinsic :: iso_fortran_env, only: qp => real128
  use demstep_results, only: result_group_type
  use test_support, only: read_group, take
  implicit none
  private
  public :: collect_app_material

  real(qp), parameter :: pq = 3.14159265358979323846264338327950288_qp
  character(len=*), parameter :: out = work_dir//"/material_out.nml"
  character(len=*), parameter :: deck = work_dir//"/material.nml"
  integer, parameter :: nc = 9, np_max = 6

contains

  subroutine collect_app_material(testsuite)
    type(unittest_type), allocatable, intent(out) :: testsuite(:)
    testsuite = [ &
      new_unittest("example: conventions, time scales, rules and limit read back", test_example), &
      new_unittest("one code: its own contact enters the stability limit", test_one_code), &
      new_unittest("each bad input in one line", test_bad) &
      ]
  end subroutine collect_app_material

  subroutine test_example(error)
    type(error_type), allocatable, intent(out) :: error
    integer :: rc, unit, ios, type_i(np_max), type_j(np_max)
    character(len=:), allocatable :: stdout, stderr
    character(len=24) :: conventions(nc), peer_rules(nc), governs
    real(dp) :: m_star(np_max), k_n(nc, np_max), k_t(nc, np_max), gamma_n(nc, np_max), gamma_t(nc, np_max), &
      dt_code(nc, np_max), rayleigh_time(np_max), hertz_duration(np_max), linear_duration(np_max), &
      dt_critical(np_max), peer_dt(nc, np_max), dt_accuracy(np_max), dt_recommended
    type(result_group_type) :: material_result_fields
    real(qp) :: e_star, r_star, m, delta, k, z, dt, g, t_r
    call execute_command_line("rm -f "//out, cmdstat=ios)
    call run_app("example/material.nml -o "//out, rc, stdout, stderr)
    call check(error, rc == 0 .and. len(stderr) == 0, "runs cleanly: "//stderr)
    if (allocated(error)) return
    type_i = -1
    open(newunit=unit, file=out, status="old", action="read", iostat=ios)
    if (ios == 0) call read_group(unit, "material_result", material_result_fields, ios)
    if (ios == 0) call take(material_result_fields, "conventions", conventions, ios)
    if (ios == 0) call take(material_result_fields, "peer_rules", peer_rules, ios)
    if (ios == 0) call take(material_result_fields, "type_i", type_i, ios)
    if (ios == 0) call take(material_result_fields, "type_j", type_j, ios)
    if (ios == 0) call take(material_result_fields, "m_star", m_star, ios)
    if (ios == 0) call take(material_result_fields, "k_n", k_n, ios)
    if (ios == 0) call take(material_result_fields, "k_t", k_t, ios)
    if (ios == 0) call take(material_result_fields, "gamma_n", gamma_n, ios)
    if (ios == 0) call take(material_result_fields, "gamma_t", gamma_t, ios)
    if (ios == 0) call take(material_result_fields, "dt_code", dt_code, ios)
    if (ios == 0) call take(material_result_fields, "rayleigh_time", rayleigh_time, ios)
    if (ios == 0) call take(material_result_fields, "hertz_duration", hertz_duration, ios)
    if (ios == 0) call take(material_result_fields, "linear_duration", linear_duration, ios)
    if (ios == 0) call take(material_result_fields, "dt_critical", dt_critical, ios)
    if (ios == 0) call take(material_result_fields, "peer_dt", peer_dt, ios)
    if (ios == 0) call take(material_result_fields, "dt_accuracy", dt_accuracy, ios)
    if (ios == 0) call take(material_result_fields, "dt_recommended", dt_recommended, ios)
    if (ios == 0) call take(material_result_fields, "governs", governs, ios)
    call check(error, ios, 0, message="&material_result reads back")
    if (allocated(error)) return
    close(unit)
    call check(error, all(type_i(:3) == [1, 1, 2]) .and. all(type_j(:3) == [1, 2, 2]) .and. type_i(4) == -1, &
      "pairs 11, 12, 22")
    if (allocated(error)) return
    ! pair 1-1: glass, E = 6.3e10, nu = 0.22, rho = 2500, R = 0.5 mm, v = 1
    e_star = 6.3e10_qp/(2*(1 - 0.22_qp**2))
    r_star = 0.25e-3_qp
    m = 4*pq/3*0.5e-3_qp**3*2500/2
    delta = (15*m/(16*e_star*sqrt(r_star)))**0.4_qp
    ! LIGGGHTS Hertz: k_n = 4/3 E* sqrt(R* delta) (the secant at delta)
    call rel(k_n(2, 1), 4*e_star*sqrt(r_star*delta)/3, "liggghts_hertz k_n")
    if (allocated(error)) return
    ! the exact limit: tangent 2 E* sqrt(R* delta), lagged dashpot of e = 0.9
    k = 2*e_star*sqrt(r_star*delta)
    z = abs(log(0.9_qp))/sqrt(pq**2 + log(0.9_qp)**2)
    dt = 2*sqrt(m/k)*(sqrt(1 + z**2) - z)
    call rel(dt_critical(1), dt, "demstep's exact limit")
    if (allocated(error)) return
    ! Rayleigh time pi R sqrt(rho/G)/(0.1631 nu + 0.8766), and EDEM's 20 % of it
    g = 6.3e10_qp/(2*1.22_qp)
    t_r = pq*0.5e-3_qp*sqrt(2500/g)/(0.1631_qp*0.22_qp + 0.8766_qp)
    call rel(rayleigh_time(1), t_r, "Rayleigh time")
    if (allocated(error)) return
    call rel(peer_dt(1, 1), t_r/5, "EDEM 20 %")
    if (allocated(error)) return
    ! the recommendation: min(0.9 smallest limit, smallest accuracy step)
    call check(error, dt_recommended == min(0.9_dp*minval(dt_critical(:3)), minval(dt_accuracy(:3))) .and. &
      governs == "accuracy", "recommended step and what governs")
    if (allocated(error)) return
    call check(error, index(stdout, "recommended dt = ") > 0 .and. index(stdout, "dt/exact limit") > 0, &
      "report shows the rules' ratios and the recommendation")
  contains
    !> 1e-13 relative: a handful of roundings in double against quad.
    subroutine rel(got, want, what)
      real(dp), intent(in) :: got
      real(qp), intent(in) :: want
      character(len=*), intent(in) :: what
      call check(error, abs(real(got, qp) - want) <= 1.0e-13_qp*abs(want), what)
    end subroutine rel
  end subroutine test_example

  subroutine test_one_code(error)
    type(error_type), allocatable, intent(out) :: error
    integer :: rc
    character(len=:), allocatable :: stdout, stderr
    call write_file(deck, [character(len=60) :: "&material", "young = 6.3e10, poisson = 0.22,", &
      "density = 2500, radius = 0.5e-3,", "restitution = 0.9, impact_velocity = 1.0,", &
      "code = 'yade_frictphys' /"])
    call run_app(deck, rc, stdout, stderr)
    call check(error, rc == 0, "runs: "//stderr)
    if (allocated(error)) return
    call check(error, index(stdout, "liggghts_hooke") == 0 .and. index(stdout, "yade_frictphys") > 0, &
      "only the chosen code")
    if (allocated(error)) return
    ! Yade's linear spring E R is far stiffer than the Hertz contact at 1 m/s:
    ! 2 sqrt(m/(E R)) = 2.88e-7 s governs, times 0.9
    call check(error, index(stdout, "with yade_frictphys's own contact") > 0 .and. &
      index(stdout, "recommended dt = 2.59460676") > 0, "the code's own limit governs: "//stdout)
  end subroutine test_one_code

  subroutine test_bad(error)
    type(error_type), allocatable, intent(out) :: error
    call expect("code = 'edem'", "demstep: "//deck//": &material: code: must be 'all' or one of")
    if (allocated(error)) return
    call expect("poisson = 0.7", "demstep: "//deck//": &material: poisson: must lie in (-1, 0.5] (particle type 1)")
    if (allocated(error)) return
    call expect("radius = 1e-3, 2e-3, density = 1, 2, 3", &
      "demstep: "//deck//": &material: radius: arrays of different lengths")
    if (allocated(error)) return
    call expect("tolerance = 2", "demstep: "//deck//": &material: tolerance: must lie in (0, 1)")
    if (allocated(error)) return
    call expect("restitution = 0", "demstep: "//deck//": &material: ")
    if (allocated(error)) return
    call expect("impact_velocity = -1", "demstep: "//deck//": &material: ")
  contains
    subroutine expect(change, start)
      character(len=*), intent(in) :: change, start
      integer :: rc, ios
      character(len=:), allocatable :: stdout, stderr
      call write_file(deck, [character(len=80) :: "&material", "young = 6.3e10, poisson = 0.22,", &
        "density = 2500, radius = 0.5e-3,", "restitution = 0.9, impact_velocity = 1.0,", change, "/"])
      call execute_command_line("rm -f "//out, cmdstat=ios)
      call run_app(deck//" -o "//out, rc, stdout, stderr)
      call check(error, rc == 2 .and. index(stderr, start) == 1 .and. &
        index(stderr, new_line("a")) == len(stderr), "one line starting '"//start//"', got: "//stderr)
      if (allocated(error)) return
      call check(error, .not. file_exists(out), "no output file")
    end subroutine expect
  end subroutine test_bad

end module test_app_material
