!> Group `&harmonic_error`: the paper's error E(N, lambda, n) for arrays of inputs.
module demstep_cli_harmonic
  use demstep_harmonic, only: evaluate_error => harmonic_error, harmonic_error_check
  use demstep_kinds, only: dp, i8
  use demstep_status, only: demstep_status_type, demstep_stat, set_status
  use demstep_namelist, only: nml_group_type
  use demstep_cli, only: var_spec, var, given, begin_group, fmt_real, fmt_real_column, fmt_int, &
    next_assignment, group_reading, cli_context, new_array, array_length, broadcast, common_length, &
    max_values, capacity_of, in_group
  use demstep_results, only: write_harmonic_error_result
  implicit none
  private

  public :: harmonic_specs, harmonic_doc, handle_harmonic_error

  character(len=*), parameter :: harmonic_doc = &
    "The paper's relative velocity error E(N, lambda, n) (eq. 23); arrays broadcast " &
    //"(one value, or the same number of values each)."

contains

  !> The variables of `&harmonic_error`.
  function harmonic_specs() result(specs)
    type(var_spec), allocatable :: specs(:)
    specs = [ &
      var("n_per_period", "a list of real numbers", "N = T/dt (> 0), one or more", "10.0, 20.0, 40.0", &
        capacity=max_values, required=.true.), &
      var("lambda", "a list of real numbers", "lambda = sqrt(K'/K*) (> 0), one or more", "0.9", &
        capacity=max_values, required=.true.), &
      var("steps_fraction", "a list of real numbers", &
        "n = f N steps (f > 0; 0.5 = half a period), or give n_steps", "0.5", capacity=max_values), &
      var("n_steps", "a list of real numbers", "n steps, 1 <= n <= 1e12", &
        "!100.0", capacity=max_values, required=.true., excludes="steps_fraction") ]
  end function harmonic_specs

  !> Read, check and evaluate one `&harmonic_error` group.
  subroutine handle_harmonic_error(ctx, group, status)
    type(cli_context), intent(in) :: ctx
    type(nml_group_type), intent(in) :: group
    type(demstep_status_type), intent(out) :: status
    type(group_reading) :: reading
    real(dp), allocatable :: n_per_period(:), lambda(:), steps_fraction(:), n_steps(:)
    namelist /harmonic_error/ n_per_period, lambda, steps_fraction, n_steps
    real(dp), allocatable :: big_n(:), lam(:), n(:), e(:)
    integer, allocatable :: stat(:)
    type(var_spec), allocatable :: specs(:)
    character(len=*), parameter :: g = "harmonic_error"
    integer :: i, lengths(3), length
    logical :: fraction
    character(len=:), allocatable :: name, what

    specs = harmonic_specs()
    n_per_period = new_array(capacity_of(specs, "n_per_period"))
    lambda = new_array(capacity_of(specs, "lambda"))
    steps_fraction = new_array(capacity_of(specs, "steps_fraction"))
    n_steps = new_array(capacity_of(specs, "n_steps"))
    call begin_group(reading, group, specs, status)
    do while (next_assignment(reading, group, status))
      read(reading%text, nml=harmonic_error, iostat=reading%ios)
    end do
    if (status%stat /= demstep_stat%ok) return
    fraction = given(group, "steps_fraction")
    call array_length(g, "n_per_period", n_per_period, lengths(1), status)
    call array_length(g, "lambda", lambda, lengths(2), status)
    if (fraction) then
      call array_length(g, "steps_fraction", steps_fraction, lengths(3), status)
    else
      call array_length(g, "n_steps", n_steps, lengths(3), status)
    end if
    if (status%stat /= demstep_stat%ok) return
    call common_length(g, [character(len=16) :: "n_per_period", "lambda", &
      merge("steps_fraction", "n_steps       ", fraction)], lengths, length, status)
    if (status%stat /= demstep_stat%ok) return

    big_n = broadcast(n_per_period, lengths(1), length)
    lam = broadcast(lambda, lengths(2), length)
    if (fraction) then
      ! a fraction of the period: n = steps_fraction N steps
      n = broadcast(steps_fraction, lengths(3), length)*big_n
    else
      n = broadcast(n_steps, lengths(3), length)
    end if

    allocate(e(length), stat(length))
    call evaluate_error(big_n, lam, n, e, stat)
    ! outside the evaluator's domain: the library says which variable and its range
    i = findloc(stat, demstep_stat%invalid_input, dim=1)
    if (i > 0) then
      call harmonic_error_check(big_n(i), lam(i), n(i), status)
      name = status%where
      what = status%detail
      if (name == "n_steps" .and. fraction) name = "steps_fraction"
      call set_status(status, demstep_stat%invalid_input, "element " &
        //fmt_int(int(i, i8))//" (n_per_period = "//fmt_real(big_n(i))//", lambda = " &
        //fmt_real(lam(i))//", n = "//fmt_real(n(i))//"): "//what, where=name)
      call in_group(status, g)
      return
    end if
    call report(ctx%report, group, big_n, lam, n, e, stat)
    call write_harmonic_error_result(ctx%results, big_n, lam, n, e, stat)
  end subroutine handle_harmonic_error

  subroutine report(u, group, big_n, lam, n, e, stat)
    integer, intent(in) :: u
    type(nml_group_type), intent(in) :: group
    real(dp), intent(in) :: big_n(:), lam(:), n(:), e(:)
    integer, intent(in) :: stat(:)
    integer :: i
    character(len=24) :: value
    character(len=24), allocatable :: n_text(:), lam_text(:), steps_text(:), e_text(:)
    write(u, '(a)') "&harmonic_error (line "//fmt_int(int(group%line, i8))//")"
    write(u, '(2x, a16, a16, a16, a24, 2x, a)') "N = T/dt", "lambda", "n steps", "E", "status"
    ! whole columns at once: up to 1e5 rows
    n_text = fmt_real_column(big_n)
    lam_text = fmt_real_column(lam)
    steps_text = fmt_real_column(n)
    e_text = fmt_real_column(e)
    do i = 1, size(e)
      if (stat(i) == demstep_stat%pole) then
        value = "pole"
      else
        value = e_text(i)
      end if
      write(u, '(2x, a16, a16, a16, a24, 2x, i0)') trim(n_text(i)), trim(lam_text(i)), &
        trim(steps_text(i)), adjustr(value), stat(i)
    end do
    write(u, '(2x, a)') "status: 0 ok, 3 pole (S(2 pi lambda/N, n) = 0; e = huge)"
    write(u, '(a)') ""
  end subroutine report

end module demstep_cli_harmonic
