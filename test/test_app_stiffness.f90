!> End-to-end tests of `&simulated_stiffness` at its limits: extreme but valid
!> values complete with finite results, invalid ones give exit status 2 and one
!> line `demstep: FILE: &simulated_stiffness: VARIABLE: ...` naming the variable
!> (and the range that works). No result namelist or report holds NaN or Infinity.
module test_app_stiffness
  use, intrinsic :: iso_fortran_env, only: qp => real128
  use, intrinsic :: ieee_arithmetic, only: ieee_is_finite
  use testdrive, only: new_unittest, unittest_type, error_type, check, test_failed
  use demstep
  use demstep_kinds, only: pi
  use demstep_text, only: lowercase
  use test_support, only: count_lines, remove, run_app, write_file, read_file, file_exists, work_dir, real_str
  use demstep_results, only: result_group_type
  use test_support, only: read_group, take
  implicit none
  private
  public :: collect_app_stiffness

  character(len=*), parameter :: deck = work_dir//"/stiffness_limits.nml"
  character(len=*), parameter :: out = work_dir//"/stiffness_limits_out.nml"
  !> The start of every deck: the group with its required physics.
  character(len=*), parameter :: g = "&simulated_stiffness mass = 0.01, stiffness = 1e5, "
  !> The start of every error line.
  character(len=*), parameter :: head = "demstep: "//deck//": &simulated_stiffness: "

  !> The result namelist of a run with two lambdas.
  type :: result_two_type
    real(dp) :: lambda(2) = 0.0_dp, n_zero(2) = 0.0_dp, n_lower(2) = 0.0_dp, n_upper(2) = 0.0_dp, &
      n_pick(2) = 0.0_dp
    logical :: bounded(2) = .false.
    integer :: status(2) = -1
    real(dp) :: n_star = 0.0_dp, lambda_star = 0.0_dp, period = 0.0_dp, dt = 0.0_dp, &
      stiffness_actual = 0.0_dp
    integer :: lambda_star_status = -1, excluded = -1
  end type result_two_type

contains

  subroutine collect_app_stiffness(testsuite)
    type(unittest_type), allocatable, intent(out) :: testsuite(:)
    testsuite = [ &
      new_unittest("n_steps = 1e12 and 2147483648: finite results, picks meet the tolerance", &
        test_huge_n_steps), &
      new_unittest("n_steps = 1e12, tolerance 1e-5: refused naming tolerance and what works", &
        test_unresolvable_tolerance), &
      new_unittest("resolution = 1e-308, tolerance = 1e-308: refused with the range", test_tiny_values), &
      new_unittest("weights = 1e308, 1.0 and 1e308, 5e307: the weighted mean, finite", test_huge_weights), &
      new_unittest("n_max = 1e13 refused; n_max = 2e12 gives an unbounded interval", test_n_max), &
      new_unittest("no admissible N, no root, empty lambda set: the variable named", test_messages) &
      ]
  end subroutine collect_app_stiffness

  !> Run the deck `line`; expect exit 0, a result file and no NaN/Infinity in it
  !> or in the report; return the result namelist (two lambdas).
  subroutine run_ok(error, line, res)
    type(error_type), allocatable, intent(out) :: error
    character(len=*), intent(in) :: line
    type(result_two_type), intent(out) :: res
    integer :: rc
    character(len=:), allocatable :: stdout, stderr
    call remove(out)
    call write_file(deck, [line])
    call run_app(deck//" -q -o "//out, rc, stdout, stderr)
    call check(error, rc, 0, message="exit status for '"//line//"'; stderr: "//stderr)
    if (allocated(error)) return
    call check(error, file_exists(out), "result file written")
    if (allocated(error)) return
    call check_finite_text(error, stdout, "the report")
    if (allocated(error)) return
    call read_stiffness_result(error, res)
  end subroutine run_ok

  !> Run the deck `line`; expect exit 2, one stderr line starting with
  !> head//expected, each of `also` in it, and no result file.
  subroutine run_bad(error, line, expected, also)
    type(error_type), allocatable, intent(out) :: error
    character(len=*), intent(in) :: line, expected
    character(len=*), intent(in), optional :: also
    integer :: rc
    character(len=:), allocatable :: stdout, stderr
    call remove(out)
    call write_file(deck, [line])
    call run_app(deck//" -o "//out, rc, stdout, stderr)
    call check(error, rc, 2, message="exit status for '"//line//"'; stderr: "//stderr)
    if (allocated(error)) return
    if (index(stderr, head//expected) /= 1) then
      call test_failed(error, "stderr '"//stderr//"' does not start with '"//head//expected//"'")
      return
    end if
    call check(error, count_lines(stderr), 1, message="one line on stderr: "//stderr)
    if (allocated(error)) return
    if (present(also)) then
      call check(error, index(stderr, also) > 0, "stderr '"//stderr//"' says '"//also//"'")
      if (allocated(error)) return
    end if
    call check(error, .not. file_exists(out), "no result file")
  end subroutine run_bad

  !> Read the result file: the namelist with two lambdas, and no NaN/Infinity text.
  subroutine read_stiffness_result(error, res)
    type(error_type), allocatable, intent(out) :: error
    type(result_two_type), intent(out) :: res
    real(dp) :: lambda(2), n_zero(2), n_lower(2), n_upper(2), n_pick(2)
    logical :: bounded(2)
    integer :: status(2), lambda_star_status, excluded, unit, ios
    real(dp) :: n_star, lambda_star, period, dt, stiffness_actual
    character(len=:), allocatable :: text
    real(dp) :: dt_recommended
    type(result_group_type) :: simulated_stiffness_result_fields
    call read_file(out, text)
    call check_finite_text(error, text, "the result namelist")
    if (allocated(error)) return
    lambda = res%lambda
    n_zero = res%n_zero
    n_lower = res%n_lower
    n_upper = res%n_upper
    n_pick = res%n_pick
    bounded = res%bounded
    status = res%status
    n_star = res%n_star
    lambda_star = res%lambda_star
    period = res%period
    dt = res%dt
    stiffness_actual = res%stiffness_actual
    lambda_star_status = res%lambda_star_status
    excluded = res%excluded
    open(newunit=unit, file=out, status="old", action="read")
    call read_group(unit, "simulated_stiffness_result", simulated_stiffness_result_fields, ios)
    if (ios == 0) call take(simulated_stiffness_result_fields, "dt_recommended", dt_recommended, ios)
    if (ios == 0) call take(simulated_stiffness_result_fields, "lambda", lambda, ios)
    if (ios == 0) call take(simulated_stiffness_result_fields, "n_zero", n_zero, ios)
    if (ios == 0) call take(simulated_stiffness_result_fields, "n_lower", n_lower, ios)
    if (ios == 0) call take(simulated_stiffness_result_fields, "n_upper", n_upper, ios)
    if (ios == 0) call take(simulated_stiffness_result_fields, "bounded", bounded, ios)
    if (ios == 0) call take(simulated_stiffness_result_fields, "n_pick", n_pick, ios)
    if (ios == 0) call take(simulated_stiffness_result_fields, "status", status, ios)
    if (ios == 0) call take(simulated_stiffness_result_fields, "n_star", n_star, ios)
    if (ios == 0) call take(simulated_stiffness_result_fields, "lambda_star", lambda_star, ios)
    if (ios == 0) call take(simulated_stiffness_result_fields, "lambda_star_status", lambda_star_status, ios)
    if (ios == 0) call take(simulated_stiffness_result_fields, "period", period, ios)
    if (ios == 0) call take(simulated_stiffness_result_fields, "dt", dt, ios)
    if (ios == 0) call take(simulated_stiffness_result_fields, "stiffness_actual", stiffness_actual, ios)
    if (ios == 0) call take(simulated_stiffness_result_fields, "excluded", excluded, ios)
    close(unit)
    call check(error, ios, 0, message="read(nml=simulated_stiffness_result)")
    if (allocated(error)) return
    res = result_two_type(lambda, n_zero, n_lower, n_upper, n_pick, bounded, status, n_star, &
      lambda_star, period, dt, stiffness_actual, lambda_star_status, excluded)
    call check(error, all(ieee_is_finite([n_zero, n_lower, n_upper, n_pick, n_star, lambda_star, &
      period, dt, stiffness_actual])), "every result is finite")
  end subroutine read_stiffness_result

  !> No NaN or Infinity (any case) in a text.
  subroutine check_finite_text(error, text, what)
    type(error_type), allocatable, intent(out) :: error
    character(len=*), intent(in) :: text, what
    character(len=:), allocatable :: low
    low = lowercase(text)
    call check(error, index(low, "nan") == 0 .and. index(low, "inf") == 0, what//" holds no NaN or Infinity")
  end subroutine check_finite_text

  subroutine test_huge_n_steps(error)
    type(error_type), allocatable, intent(out) :: error
    real(dp), parameter :: ns(2) = [1.0e12_dp, 2147483648.0_dp]
    character(len=*), parameter :: texts(2) = [character(len=10) :: "1e12", "2147483648"]
    type(result_two_type) :: res
    real(dp) :: e
    integer :: i, k, stat
    do i = 1, size(ns)
      call run_ok(error, g//"tolerance = 1e-3, lambda = 0.9, 0.95, steps = 'fixed', n_steps = "// &
        trim(texts(i))//" /", res)
      if (allocated(error)) return
      ! the picks meet the tolerance as the library evaluates E
      do k = 1, 2
        call check(error, res%status(k), demstep_stat%ok, message="status of lambda "//real_str(res%lambda(k)))
        if (allocated(error)) return
        call harmonic_error(res%n_pick(k), res%lambda(k), ns(i), e, stat)
        call check(error, stat == demstep_stat%ok .and. abs(e) <= 1.0e-3_dp, "n = "//trim(texts(i))// &
          ", lambda = "//real_str(res%lambda(k))//": |E(pick)| = "//real_str(e))
        if (allocated(error)) return
      end do
      call check(error, res%n_star, 0.5_dp*(res%n_pick(1) + res%n_pick(2)), thr=4*epsilon(1.0_dp), rel=.true., &
        message="N* is the mean of the picks")
      if (allocated(error)) return
    end do
  end subroutine test_huge_n_steps

  subroutine test_unresolvable_tolerance(error)
    type(error_type), allocatable, intent(out) :: error
    ! next to the first root (N just above pi) E changes by about 8e-4 between
    ! neighbouring doubles when n = 1e12: no double meets 1e-5 (the smallest |E|
    ! there is 8.9e-5)
    call run_bad(error, g//"tolerance = 1e-5, lambda = 0.9, steps = 'fixed', n_steps = 1e12 /", &
      "tolerance: ", "use tolerance >= ")
  end subroutine test_unresolvable_tolerance

  subroutine test_tiny_values(error)
    type(error_type), allocatable, intent(out) :: error
    call run_bad(error, g//"tolerance = 1e-3, lambda = 0.9, resolution = 1e-308 /", "resolution: ", &
      "use resolution >= ")
    if (allocated(error)) return
    call run_bad(error, g//"tolerance = 1e-308, lambda = 0.9 /", "tolerance: ", "at least 1e-10")
  end subroutine test_tiny_values

  !> The weighted mean in quad (range to 1e4932, so w p cannot overflow), against
  !> the app's N*: 4 eps relative covers the double sums of two terms.
  subroutine test_huge_weights(error)
    type(error_type), allocatable, intent(out) :: error
    character(len=*), parameter :: texts(2) = [character(len=12) :: "1.0", "5e307"]
    real(dp), parameter :: w2(2) = [1.0_dp, 5.0e307_dp]
    type(result_two_type) :: res
    real(qp) :: mean
    integer :: i
    do i = 1, size(texts)
      call run_ok(error, g//"tolerance = 1e-3, lambda = 0.9, 0.95, aggregate = 'weighted', weights = 1e308, " &
        //trim(texts(i))//" /", res)
      if (allocated(error)) return
      mean = (1.0e308_qp*res%n_pick(1) + real(w2(i), qp)*res%n_pick(2))/(1.0e308_qp + real(w2(i), qp))
      call check(error, res%n_star, real(mean, dp), thr=4*epsilon(1.0_dp), rel=.true., &
        message="N* with weights 1e308, "//trim(texts(i)))
      if (allocated(error)) return
    end do
    ! with 1e308, 5e307 N* lies strictly between the picks: (2 p1 + p2)/3
    call check(error, res%n_star > res%n_pick(1) .and. res%n_star < res%n_pick(2), "N* between the picks")
  end subroutine test_huge_weights

  subroutine test_n_max(error)
    type(error_type), allocatable, intent(out) :: error
    type(result_two_type) :: res
    call run_bad(error, g//"tolerance = 1e-3, lambda = 0.9, n_max = 1e13 /", "n_max: ", "2e12]")
    if (allocated(error)) return
    ! lambda = 0.9, E0 = 0.1: E tends to -0.0251 as N grows, the interval is
    ! unbounded; it must not end at the evaluator's limit 2.467e12
    call run_ok(error, g//"tolerance = 0.1, lambda = 0.9, 0.95, n_max = 2e12 /", res)
    if (allocated(error)) return
    call check(error, .not. res%bounded(1), "lambda 0.9: unbounded")
    if (allocated(error)) return
    call check(error, res%n_upper(1) <= 2.0e12_dp, "no end beyond n_max: "//real_str(res%n_upper(1)))
  end subroutine test_n_max

  subroutine test_messages(error)
    type(error_type), allocatable, intent(out) :: error
    call run_bad(error, g//"tolerance = 1e-3, lambda = 0.3 /", "tolerance: no lambda has an admissible N")
    if (allocated(error)) return
    call run_bad(error, g//"tolerance = 1e-3, lambda = 0.3, pick = 'zero' /", "n_max: no lambda has a root")
    if (allocated(error)) return
    call run_bad(error, g//"tolerance = 1e-3 /", "lambda: give either lambda or lambda_min, lambda_max and lambda_count")
  end subroutine test_messages

end module test_app_stiffness
