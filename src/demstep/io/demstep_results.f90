!> Result namelists: each group written in one place, and read back by name.
!>
!> demstep writes each result as one namelist group (`&system_result`,
!> `&scene_result`, ...; the README lists their fields). A program that reads a
!> group with its own `namelist` declaration breaks when a field is added;
!> `read_result` reads the group by name instead, so a reader asks only for the
!> fields it uses and ignores the others:
!>
!>```fortran
!> type(result_group_type) :: r
!> call read_result("demstep_result.nml", "system_result", r, status)
!> call result_get(r, "dt", dt, status)
!>```
module demstep_results
  use demstep_kinds, only: dp, i8
  use, intrinsic :: ieee_arithmetic, only: ieee_is_finite
  use demstep_status, only: demstep_status_type, demstep_stat, set_status
  use demstep_namelist, only: nml_group_type, scan_namelist
  use demstep_text, only: read_text_file, lowercase
  use demstep_scene_data, only: scene_type, scene_summary_type
  use demstep_assembly, only: critical_step_type, eigen_solver_name, safe_basis_name
  use demstep_monitor, only: participation_type, participation_top, spring_kind_names, top_shares
  use demstep_stiffness, only: stiffness_result_type, interval_kind
  use demstep_snapshot, only: snapshot_type, snapshot_format_names
  use demstep_liggghts_scene, only: liggghts_scene_type, script_timestep_ratio
  use demstep_material, only: n_peer_rules, peer_rule_names
  use demstep_mfix_input, only: mfix_input_type
  use demstep_mfix, only: mfix_result_type
  use demstep_mfix_assess, only: mfix_assessment_type
  use demstep_recommend, only: step_governs
  implicit none
  private

  public :: read_result, parse_result, result_get, result_has
  public :: write_system_result, write_contact_error_result, write_accuracy_cost_result, &
    write_harmonic_error_result, write_material_result, write_simulated_stiffness_result, &
    write_scene_result, write_snapshot_result, write_script_result, write_mfix_result

  !> `&system_result`: the spring alone, with a time step beyond the limit, or
  !> with a stable step and its discrete contact (by the arguments given).
  interface write_system_result
    module procedure :: system_result_basic, system_result_unstable, system_result_stable
  end interface write_system_result

  !> `&contact_error_result`: at given onsets, or the worst over the onsets.
  interface write_contact_error_result
    module procedure :: contact_error_result_onset, contact_error_result_worst
  end interface write_contact_error_result

  !> Most values one field may hold (a longer list is refused, not allocated).
  integer, parameter :: max_values = 10000000

  !> One result group as read: its fields by name, their values as text.
  type, public :: result_group_type
    !> The group as scanned (names in lower case).
    type(nml_group_type) :: group
  end type result_group_type

  !> A field's value, converted to the type of `value`: a real, an integer (32 or
  !> 64 bit), a logical, a text, an array of reals or integers (allocated to the
  !> field's length), or an array of logicals or fixed-length texts (its leading
  !> elements set, `invalid_input` when the field holds more).
  !> As with a `namelist` read, `value` is left as it was when the group lacks
  !> the field (status `not_found`, naming it) or its text does not convert
  !> (`invalid_input`; a real must be finite).
  interface result_get
    module procedure :: get_real, get_int, get_int64, get_logical, get_text, get_reals, get_ints, &
      get_logicals, get_texts, get_int64s
  end interface result_get

contains

  !> Read group `name` (without `&`, any case) of the result file `path`.
  subroutine read_result(path, name, result, status)
    !> The result file (`demstep deck -o path`).
    character(len=*), intent(in) :: path
    !> The group, e.g. `scene_result`.
    character(len=*), intent(in) :: name
    !> The group's fields.
    type(result_group_type), intent(out) :: result
    !> `io_error` naming the file, `not_found` naming the group.
    type(demstep_status_type), intent(out) :: status
    character(len=:), allocatable :: text, what
    integer :: code
    call read_text_file(path, text, status)
    if (status%stat /= demstep_stat%ok) then
      what = status%message
      code = status%stat
      call set_status(status, code, what, where=path)
      return
    end if
    call parse_result(text, name, result, status)
  end subroutine read_result

  !> Find group `name` (without `&`, any case) in result text.
  pure subroutine parse_result(text, name, result, status)
    !> The result namelists, as written.
    character(len=*), intent(in) :: text
    !> The group, e.g. `scene_result`.
    character(len=*), intent(in) :: name
    !> The group's fields.
    type(result_group_type), intent(out) :: result
    !> `not_found` naming the group when the text does not hold it.
    type(demstep_status_type), intent(out) :: status
    type(nml_group_type), allocatable :: groups(:)
    integer :: k
    call scan_namelist(text, groups, status)
    if (status%stat /= demstep_stat%ok) return
    do k = 1, size(groups)
      if (groups(k)%name == lowercase(trim(name))) then
        result%group = groups(k)
        return
      end if
    end do
    call set_status(status, demstep_stat%not_found, "no such group in the result", where=lowercase(trim(name)))
  end subroutine parse_result

  !> True when the group holds field `name`.
  pure logical function result_has(result, name)
    !> The group.
    type(result_group_type), intent(in) :: result
    !> The field, any case.
    character(len=*), intent(in) :: name
    result_has = field_of(result, name) > 0
  end function result_has

  pure integer function field_of(result, name) result(k)
    type(result_group_type), intent(in) :: result
    character(len=*), intent(in) :: name
    integer :: i
    k = 0
    if (.not. allocated(result%group%items)) return
    do i = 1, size(result%group%items)
      if (result%group%items(i)%name == lowercase(trim(name))) k = i
    end do
  end function field_of

  !> The value text of field `name`, or a `not_found` status naming it.
  pure subroutine field_text(result, name, text, status)
    type(result_group_type), intent(in) :: result
    character(len=*), intent(in) :: name
    character(len=:), allocatable, intent(out) :: text
    type(demstep_status_type), intent(out) :: status
    integer :: k
    k = field_of(result, name)
    if (k == 0) then
      text = ""
      call set_status(status, demstep_stat%not_found, "not in &"//result%group%name, where=lowercase(trim(name)))
      return
    end if
    text = result%group%items(k)%value
    status%stat = demstep_stat%ok
  end subroutine field_text

  !> The status for a value its field's type cannot hold.
  pure subroutine bad_value(status, name, text)
    type(demstep_status_type), intent(out) :: status
    character(len=*), intent(in) :: name, text
    call set_status(status, demstep_stat%invalid_input, "cannot read '"//trim(adjustl(text))//"'", &
      where=lowercase(trim(name)))
  end subroutine bad_value

  subroutine get_real(result, name, value, status)
    type(result_group_type), intent(in) :: result
    character(len=*), intent(in) :: name
    real(dp), intent(inout) :: value
    type(demstep_status_type), intent(out) :: status
    call get_scalar(result, name, value, status)
  end subroutine get_real

  subroutine get_int(result, name, value, status)
    type(result_group_type), intent(in) :: result
    character(len=*), intent(in) :: name
    integer, intent(inout) :: value
    type(demstep_status_type), intent(out) :: status
    call get_scalar(result, name, value, status)
  end subroutine get_int

  subroutine get_int64(result, name, value, status)
    type(result_group_type), intent(in) :: result
    character(len=*), intent(in) :: name
    integer(i8), intent(inout) :: value
    type(demstep_status_type), intent(out) :: status
    call get_scalar(result, name, value, status)
  end subroutine get_int64

  subroutine get_logical(result, name, value, status)
    type(result_group_type), intent(in) :: result
    character(len=*), intent(in) :: name
    logical, intent(inout) :: value
    type(demstep_status_type), intent(out) :: status
    call get_scalar(result, name, value, status)
  end subroutine get_logical

  !> One scalar field into `value` (a real, 32- or 64-bit integer or logical),
  !> converted as a list-directed read converts it; `value` is left as it was
  !> when the field is absent or does not convert (a real must be finite).
  subroutine get_scalar(result, name, value, status)
    type(result_group_type), intent(in) :: result
    character(len=*), intent(in) :: name
    class(*), intent(inout) :: value
    type(demstep_status_type), intent(out) :: status
    character(len=:), allocatable :: text
    real(dp) :: r
    integer :: k, ios
    integer(i8) :: k8
    logical :: l
    call field_text(result, name, text, status)
    if (status%stat /= demstep_stat%ok) return
    ios = 1
    select type (value)
    type is (real(dp))
      read(text, *, iostat=ios) r
      if (ios == 0 .and. .not. ieee_is_finite(r)) ios = 1
      if (ios == 0) value = r
    type is (integer)
      read(text, *, iostat=ios) k
      if (ios == 0) value = k
    type is (integer(i8))
      read(text, *, iostat=ios) k8
      if (ios == 0) value = k8
    type is (logical)
      read(text, *, iostat=ios) l
      if (ios == 0) value = l
    end select
    if (ios /= 0) call bad_value(status, name, text)
  end subroutine get_scalar

  !> A text field: one quoted value (blanks the writer padded it with trimmed),
  !> or for a list of texts the value text as written.
  subroutine get_text(result, name, value, status)
    type(result_group_type), intent(in) :: result
    character(len=*), intent(in) :: name
    character(len=:), allocatable, intent(inout) :: value
    type(demstep_status_type), intent(out) :: status
    character(len=:), allocatable :: text
    integer :: n
    call field_text(result, name, text, status)
    if (status%stat /= demstep_stat%ok) return
    text = trim(adjustl(text))
    n = len(text)
    if (n > 0) then
      if (text(n:n) == ",") text = trim(text(:n-1))
    end if
    n = len(text)
    if (n >= 2) then
      if ((text(1:1) == '"' .or. text(1:1) == "'") .and. text(n:n) == text(1:1) .and. &
          index(text(2:n-1), text(1:1)) == 0) then
        value = trim(text(2:n-1))
        return
      end if
    end if
    value = text
  end subroutine get_text

  !> The number of values a list-directed value text holds: commas and blanks
  !> outside quotes separate them, `r*x` stands for r values (the runtime writes
  !> repeats so); -1 for a count beyond `max_values`.
  pure integer function count_values(text) result(n)
    character(len=*), intent(in) :: text
    integer :: i, first, star, r, ios
    character :: quote
    n = 0
    i = 1
    do while (i <= len(text))
      if (is_separator(text(i:i))) then
        i = i + 1
        cycle
      end if
      first = i
      quote = " "
      do while (i <= len(text))
        if (quote /= " ") then
          if (text(i:i) == quote) quote = " "
        else if (text(i:i) == '"' .or. text(i:i) == "'") then
          quote = text(i:i)
        else if (is_separator(text(i:i))) then
          exit
        end if
        i = i + 1
      end do
      star = index(text(first:i-1), "*")
      r = 1
      if (star > 1 .and. verify(text(first:first+star-2), "0123456789") == 0 .and. star <= 10) then
        read(text(first:first+star-2), *, iostat=ios) r
        if (ios /= 0 .or. r < 1) r = 1
      end if
      ! a count beyond any result demstep writes is not a result: refused
      if (r > max_values - n) then
        n = -1
        return
      end if
      n = n + r
    end do
  end function count_values

  elemental logical function is_separator(c)
    character, intent(in) :: c
    is_separator = c == "," .or. c == " " .or. iachar(c) < 32
  end function is_separator

  !> The text of a list field and how many values it holds; `invalid_input`
  !> for more than `capacity` (or `max_values`) values.
  subroutine list_text(result, name, text, n, status, capacity)
    type(result_group_type), intent(in) :: result
    character(len=*), intent(in) :: name
    character(len=:), allocatable, intent(out) :: text
    integer, intent(out) :: n
    type(demstep_status_type), intent(out) :: status
    integer, intent(in), optional :: capacity
    n = 0
    call field_text(result, name, text, status)
    if (status%stat /= demstep_stat%ok) return
    n = count_values(text)
    if (present(capacity)) then
      if (n > capacity) n = -1
    end if
    if (n < 0) call bad_value(status, name, text)
  end subroutine list_text

  subroutine get_reals(result, name, value, status)
    type(result_group_type), intent(in) :: result
    character(len=*), intent(in) :: name
    real(dp), allocatable, intent(inout) :: value(:)
    type(demstep_status_type), intent(out) :: status
    character(len=:), allocatable :: text
    real(dp), allocatable :: got(:)
    integer :: ios, n
    call list_text(result, name, text, n, status)
    if (status%stat /= demstep_stat%ok) return
    allocate(got(n))
    read(text, *, iostat=ios) got
    if (ios == 0) then
      if (.not. all(ieee_is_finite(got))) ios = 1
    end if
    if (ios /= 0) then
      call bad_value(status, name, text)
      return
    end if
    call move_alloc(got, value)
  end subroutine get_reals

  subroutine get_ints(result, name, value, status)
    type(result_group_type), intent(in) :: result
    character(len=*), intent(in) :: name
    integer, allocatable, intent(inout) :: value(:)
    type(demstep_status_type), intent(out) :: status
    character(len=:), allocatable :: text
    integer, allocatable :: got(:)
    integer :: ios, n
    call list_text(result, name, text, n, status)
    if (status%stat /= demstep_stat%ok) return
    allocate(got(n))
    read(text, *, iostat=ios) got
    if (ios /= 0) then
      call bad_value(status, name, text)
      return
    end if
    call move_alloc(got, value)
  end subroutine get_ints

  subroutine get_int64s(result, name, value, status)
    type(result_group_type), intent(in) :: result
    character(len=*), intent(in) :: name
    integer(i8), allocatable, intent(inout) :: value(:)
    type(demstep_status_type), intent(out) :: status
    character(len=:), allocatable :: text
    integer(i8), allocatable :: got(:)
    integer :: ios, n
    call list_text(result, name, text, n, status)
    if (status%stat /= demstep_stat%ok) return
    allocate(got(n))
    read(text, *, iostat=ios) got
    if (ios /= 0) then
      call bad_value(status, name, text)
      return
    end if
    call move_alloc(got, value)
  end subroutine get_int64s

  subroutine get_logicals(result, name, value, status)
    type(result_group_type), intent(in) :: result
    character(len=*), intent(in) :: name
    logical, intent(inout) :: value(:)
    type(demstep_status_type), intent(out) :: status
    character(len=:), allocatable :: text
    logical, allocatable :: got(:)
    integer :: ios, n
    call list_text(result, name, text, n, status, capacity=size(value))
    if (status%stat /= demstep_stat%ok) return
    allocate(got(n))
    read(text, *, iostat=ios) got
    if (ios /= 0) then
      call bad_value(status, name, text)
      return
    end if
    value(:n) = got
  end subroutine get_logicals

  subroutine get_texts(result, name, value, status)
    type(result_group_type), intent(in) :: result
    character(len=*), intent(in) :: name
    character(len=*), intent(inout) :: value(:)
    type(demstep_status_type), intent(out) :: status
    character(len=:), allocatable :: text
    character(len=len(value)), allocatable :: got(:)
    integer :: ios, n
    call list_text(result, name, text, n, status, capacity=size(value))
    if (status%stat /= demstep_stat%ok) return
    allocate(got(n))
    read(text, *, iostat=ios) got
    if (ios /= 0) then
      call bad_value(status, name, text)
      return
    end if
    value(:n) = got
  end subroutine get_texts

  ! ------------------------------------------------------------ writers

  !> `&system_result` without a time step.
  subroutine system_result_basic(unit, period, omega, dt_critical, dt_recommended)
    integer, intent(in) :: unit
    real(dp), intent(in) :: period, omega, dt_critical, dt_recommended
    namelist /system_result/ period, omega, dt_critical, dt_recommended
    write(unit, nml=system_result)
  end subroutine system_result_basic

  !> `&system_result` for a time step at or beyond the limit.
  subroutine system_result_unstable(unit, period, omega, dt_critical, dt, n_per_period, growth_factor, &
      dt_recommended)
    integer, intent(in) :: unit
    real(dp), intent(in) :: period, omega, dt_critical, dt, n_per_period, growth_factor, dt_recommended
    logical :: stable
    namelist /system_result/ period, omega, dt_critical, dt_recommended, dt, n_per_period, stable, &
      growth_factor
    stable = .false.
    write(unit, nml=system_result)
  end subroutine system_result_unstable

  !> `&system_result` for a stable time step, with the discrete contact.
  subroutine system_result_stable(unit, period, omega, dt_critical, dt, n_per_period, growth_factor, &
      theta, period_numerical, contact_steps, contact_time, restitution, max_overlap, dt_recommended)
    integer, intent(in) :: unit
    real(dp), intent(in) :: period, omega, dt_critical, dt, n_per_period, growth_factor, theta, &
      period_numerical, contact_time, restitution, max_overlap, dt_recommended
    integer(i8), intent(in) :: contact_steps
    logical :: stable
    namelist /system_result/ period, omega, dt_critical, dt_recommended, dt, n_per_period, stable, &
      growth_factor, theta, period_numerical, contact_steps, contact_time, restitution, &
      max_overlap
    stable = .true.
    write(unit, nml=system_result)
  end subroutine system_result_stable

  !> `&contact_error_result` over the onsets: worst values and where.
  subroutine contact_error_result_worst(unit, n_per_period, steps_in_contact, value, onset_q, stable)
    integer, intent(in) :: unit
    real(dp), intent(in) :: n_per_period(:), value(:, :), onset_q(:, :)
    integer(i8), intent(in) :: steps_in_contact(:)
    logical, intent(in) :: stable(:)
    real(dp), allocatable :: contact_time(:), restitution(:), max_overlap(:), onset_contact_time(:), &
      onset_restitution(:), onset_overlap(:)
    namelist /contact_error_result/ n_per_period, steps_in_contact, contact_time, restitution, &
      max_overlap, onset_contact_time, onset_restitution, onset_overlap, stable
    contact_time = value(:, 1)
    restitution = value(:, 2)
    max_overlap = value(:, 3)
    onset_contact_time = onset_q(:, 1)
    onset_restitution = onset_q(:, 2)
    onset_overlap = onset_q(:, 3)
    write(unit, nml=contact_error_result)
  end subroutine contact_error_result_worst

  !> `&contact_error_result` at given onsets.
  subroutine contact_error_result_onset(unit, n_per_period, onset, steps_in_contact, value, stable)
    integer, intent(in) :: unit
    real(dp), intent(in) :: n_per_period(:), onset(:), value(:, :)
    integer(i8), intent(in) :: steps_in_contact(:)
    logical, intent(in) :: stable(:)
    real(dp), allocatable :: contact_time(:), restitution(:), max_overlap(:)
    namelist /contact_error_result/ n_per_period, onset, steps_in_contact, contact_time, &
      restitution, max_overlap, stable
    contact_time = value(:, 1)
    restitution = value(:, 2)
    max_overlap = value(:, 3)
    write(unit, nml=contact_error_result)
  end subroutine contact_error_result_onset

  !> The result group; `steps_saturated(i)` marks a count above 2^63 - 1, written as
  !> 2^63 - 1 in `steps(i)` (`predicted_seconds` uses the exact count).
  subroutine write_accuracy_cost_result(unit, tolerances, n_per_period, dt, steps, steps_saturated, predicted_seconds, &
      status, cost_per_particle_step, period, dt_recommended)
    integer, intent(in) :: unit
    real(dp), intent(in) :: tolerances(:), n_per_period(:), dt(:), predicted_seconds(:), &
      cost_per_particle_step, period, dt_recommended
    integer(i8), intent(in) :: steps(:)
    logical, intent(in) :: steps_saturated(:)
    integer, intent(in) :: status(:)
    namelist /accuracy_cost_result/ tolerances, n_per_period, dt, steps, steps_saturated, predicted_seconds, &
      status, cost_per_particle_step, period, dt_recommended
    write(unit, nml=accuracy_cost_result)
  end subroutine write_accuracy_cost_result

  !> `&harmonic_error_result`: E per evaluation and its status.
  subroutine write_harmonic_error_result(unit, n_per_period, lambda, n_steps, e, status)
    integer, intent(in) :: unit
    real(dp), intent(in) :: n_per_period(:), lambda(:), n_steps(:), e(:)
    integer, intent(in) :: status(:)
    namelist /harmonic_error_result/ n_per_period, lambda, n_steps, e, status
    write(unit, nml=harmonic_error_result)
  end subroutine write_harmonic_error_result

  !> `&material_result`: each pair of types in each convention, and the peers' steps.
  subroutine write_material_result(unit, conventions, peer_rules, type_i, type_j, m_star, k_n, k_t, gamma_n, &
      gamma_t, dt_code, rayleigh_time, hertz_duration, linear_duration, dt_critical, peer_dt, &
      dt_accuracy, dt_recommended, governs)
    integer, intent(in) :: unit
    character(len=*), intent(in) :: conventions(:), peer_rules(:), governs
    integer, intent(in) :: type_i(:), type_j(:)
    real(dp), intent(in) :: m_star(:), k_n(:, :), k_t(:, :), gamma_n(:, :), gamma_t(:, :), dt_code(:, :), &
      rayleigh_time(:), hertz_duration(:), linear_duration(:), dt_critical(:), peer_dt(:, :), &
      dt_accuracy(:), dt_recommended
    namelist /material_result/ conventions, peer_rules, type_i, type_j, m_star, k_n, k_t, gamma_n, &
      gamma_t, dt_code, rayleigh_time, hertz_duration, linear_duration, dt_critical, peer_dt, &
      dt_accuracy, dt_recommended, governs
    write(unit, nml=material_result)
  end subroutine write_material_result

  !> `&simulated_stiffness_result`: the roots per lambda and the chosen N.
  subroutine write_simulated_stiffness_result(unit, result, dt_recommended)
    integer, intent(in) :: unit
    type(stiffness_result_type), intent(in) :: result
    real(dp), intent(in) :: dt_recommended
    real(dp), allocatable :: lambda(:), n_zero(:), n_lower(:), n_upper(:), n_pick(:)
    logical, allocatable :: bounded(:)
    integer, allocatable :: status(:)
    real(dp) :: n_star, lambda_star, period, dt, stiffness_actual
    integer :: lambda_star_status, excluded, i, n
    namelist /simulated_stiffness_result/ lambda, n_zero, n_lower, n_upper, bounded, n_pick, &
      status, n_star, lambda_star, lambda_star_status, period, dt, stiffness_actual, excluded, &
      dt_recommended
    n = size(result%rows)
    allocate(lambda(n), n_zero(n), n_lower(n), n_upper(n), n_pick(n), bounded(n), status(n))
    do i = 1, n
      associate(r => result%rows(i))
        lambda(i) = r%lambda
        n_zero(i) = 0.0_dp
        if (size(r%roots) > 0) n_zero(i) = r%roots(1)
        n_lower(i) = 0.0_dp
        n_upper(i) = 0.0_dp
        bounded(i) = .false.
        if (size(r%lower) > 0) then
          n_lower(i) = r%lower(1)
          n_upper(i) = r%upper(1)
          bounded(i) = size(r%lower) > 1 .or. r%last_interval == interval_kind%bounded
        end if
        n_pick(i) = r%n_pick
        status(i) = r%stat
      end associate
    end do
    n_star = result%n_star
    lambda_star = result%lambda_star
    lambda_star_status = result%lambda_star_stat
    period = result%period
    dt = result%dt
    stiffness_actual = result%stiffness_actual
    excluded = result%excluded
    write(unit, nml=simulated_stiffness_result)
  end subroutine write_simulated_stiffness_result

  !> `&scene_result`: the assembly's sizes, limits and run, and (with `part`)
  !> the `participation_top` particles and springs that carry most of the top
  !> mode, largest first (fewer: the rest 0 and blank; a spring's particle i
  !> is 0 on a wall or the ground; types 0 when the scene has none).
  subroutine write_scene_result(unit, sc, crit, dt_used, summary, dt_recommended, part)
    integer, intent(in) :: unit
    type(scene_type), intent(in) :: sc
    type(critical_step_type), intent(in) :: crit
    real(dp), intent(in) :: dt_used
    type(scene_summary_type), intent(in) :: summary
    real(dp), intent(in) :: dt_recommended
    type(participation_type), intent(in), optional :: part
    logical :: participation
    integer, dimension(participation_top) :: top_particles, top_particle_types, top_contact_i, top_contact_j
    real(dp), dimension(participation_top) :: top_particle_shares, top_particle_radii, top_particle_masses, &
      top_contact_shares, top_contact_k_n, top_contact_k_t
    character(len=len(spring_kind_names)) :: top_contact_kinds(participation_top)
    integer, allocatable :: top(:)
    integer :: k
    integer :: n_particles, n_dof, n_springs, max_contacts, dof_per_particle
    logical :: rotation, tangential, periodic, prestress
    real(dp) :: omega_max, dt_critical_eigen, dt_critical_bound, dt_contact_rule, &
      dt_critical_damped, damping_ratio_top, energy_drift, max_overlap
    integer(i8) :: steps
    logical :: eigen_computed, blew_up
    character(len=8) :: eigen_solver
    real(dp) :: eigen_tolerance, eigen_residual, omega_upper, dt_critical_safe, dt_critical_damped_bound
    logical :: eigen_converged, damped_exact
    ! what dt_critical_safe rests on (safe_basis_names) and its failure probability
    character(len=10) :: safe_basis
    real(dp) :: safe_failure
    ! the Lanczos solve's operator products (the certificate's included)
    integer(i8) :: eigen_products
    namelist /scene_result/ n_particles, n_dof, n_springs, dof_per_particle, rotation, tangential, &
      periodic, prestress, omega_max, eigen_computed, eigen_converged, eigen_solver, eigen_tolerance, eigen_residual, &
      omega_upper, dt_critical_eigen, dt_critical_safe, safe_basis, safe_failure, eigen_products, dt_critical_bound, &
      dt_contact_rule, &
      dt_critical_damped, damping_ratio_top, dt_used, steps, energy_drift, max_overlap, max_contacts, &
      blew_up, dt_recommended, damped_exact, dt_critical_damped_bound, participation, top_particles, &
      top_particle_shares, top_particle_radii, top_particle_masses, top_particle_types, top_contact_i, &
      top_contact_j, top_contact_kinds, top_contact_shares, top_contact_k_n, top_contact_k_t
    participation = .false.
    top_particles = 0
    top_particle_types = 0
    top_particle_shares = 0.0_dp
    top_particle_radii = 0.0_dp
    top_particle_masses = 0.0_dp
    top_contact_i = 0
    top_contact_j = 0
    top_contact_kinds = ""
    top_contact_shares = 0.0_dp
    top_contact_k_n = 0.0_dp
    top_contact_k_t = 0.0_dp
    if (present(part)) participation = part%computed
    if (participation) then
      top = top_shares(part%particle_share, participation_top)
      do k = 1, size(top)
        top_particles(k) = top(k)
        top_particle_shares(k) = part%particle_share(top(k))
        top_particle_radii(k) = sc%radius(top(k))
        top_particle_masses(k) = sc%mass(top(k))
        if (allocated(sc%ptype)) top_particle_types(k) = sc%ptype(top(k))
      end do
      top = top_shares(part%spring_share, participation_top)
      do k = 1, size(top)
        top_contact_i(k) = part%spring_a(top(k))
        top_contact_j(k) = part%spring_b(top(k))
        top_contact_kinds(k) = spring_kind_names(part%spring_kind(top(k)))
        top_contact_shares(k) = part%spring_share(top(k))
        top_contact_k_n(k) = part%spring_k(1, top(k))
        top_contact_k_t(k) = part%spring_k(2, top(k))
      end do
    end if
    n_particles = sc%n
    n_dof = crit%n_dof
    n_springs = crit%n_springs
    dof_per_particle = crit%dof_per_particle
    rotation = crit%rotation
    tangential = crit%tangential
    periodic = crit%periodic
    prestress = crit%prestress
    omega_max = crit%omega_max
    eigen_computed = crit%eigen_computed
    eigen_solver = eigen_solver_name(crit%solver)
    eigen_converged = crit%eigen_converged
    eigen_tolerance = crit%eigen_tolerance
    eigen_residual = crit%eigen_residual
    omega_upper = crit%omega_upper
    dt_critical_safe = crit%dt_critical_safe
    safe_basis = safe_basis_name(crit%safe_basis)
    safe_failure = crit%safe_failure
    eigen_products = crit%eigen_products
    dt_critical_eigen = crit%dt_critical_eigen
    dt_critical_bound = crit%dt_critical_bound
    dt_contact_rule = crit%dt_contact_rule
    dt_critical_damped = crit%dt_critical_damped
    damping_ratio_top = crit%damping_ratio_top
    damped_exact = crit%damped_exact
    dt_critical_damped_bound = crit%dt_critical_damped_bound
    steps = summary%steps
    energy_drift = summary%energy_drift
    max_overlap = summary%max_overlap
    max_contacts = summary%max_contacts
    blew_up = summary%blew_up
    write(unit, nml=scene_result)
  end subroutine write_scene_result

  !> The `&snapshot_result` group: what was read and the peers' rules.
  subroutine write_snapshot_result(unit, snap, have_materials, crit, peer_dt)
    integer, intent(in) :: unit
    type(snapshot_type), intent(in) :: snap
    !> The deck gives the types' materials (the peers' steps are computed).
    logical, intent(in) :: have_materials
    type(critical_step_type), intent(in) :: crit
    real(dp), intent(in) :: peer_dt(n_peer_rules)
    character(len=11) :: format
    integer :: n_particles, n_types, frame, n_frames
    integer(i8) :: timestep
    logical :: periodic(3)
    real(dp) :: box_lo(3), box_hi(3), dt_exact, peer_ratio(n_peer_rules)
    character(len=20) :: peer_rules(n_peer_rules)
    namelist /snapshot_result/ format, n_particles, n_types, frame, n_frames, timestep, periodic, &
      box_lo, box_hi, have_materials, peer_rules, peer_dt, peer_ratio, dt_exact
    format = snapshot_format_names(snap%format)
    n_particles = snap%n
    n_types = maxval(snap%type)
    frame = snap%frame
    n_frames = snap%n_frames
    timestep = snap%timestep
    periodic = snap%periodic
    box_lo = snap%lo
    box_hi = snap%hi
    peer_rules = peer_rule_names
    dt_exact = crit%dt_critical_damped
    peer_ratio = peer_dt/dt_exact
    write(unit, nml=snapshot_result)
  end subroutine write_snapshot_result

  !> The `&script_result` group: a LIGGGHTS script's `timestep` (0 and line 0
  !> when it states none) and its ratio to the scene's damped limit `dt_limit`.
  subroutine write_script_result(unit, info, dt_limit)
    integer, intent(in) :: unit
    type(liggghts_scene_type), intent(in) :: info
    real(dp), intent(in) :: dt_limit
    character(len=512) :: script_file, timestep_file
    integer :: timestep_line
    real(dp) :: timestep, timestep_ratio
    namelist /script_result/ script_file, timestep, timestep_file, timestep_line, timestep_ratio
    script_file = ""
    if (allocated(info%file)) script_file = info%file
    timestep_file = ""
    if (allocated(info%timestep_file)) timestep_file = info%timestep_file
    timestep = info%timestep
    timestep_line = info%timestep_line
    timestep_ratio = script_timestep_ratio(info, dt_limit)
    write(unit, nml=script_result)
  end subroutine write_script_result

  !> The result group `&mfix_result`, per pair in MFiX's order (particle pairs
  !> 11, 12, ..., then phase-wall pairs; `phase_j = 0` for a wall).
  !> `&mfix_result`: MFiX's TCOLL and DTSOLID, demstep's answer at MFiX's step,
  !> per pair of phases.
  subroutine write_mfix_result(unit, input, result, a)
    integer, intent(in) :: unit
    type(mfix_input_type), intent(in) :: input
    type(mfix_result_type), intent(in) :: result
    type(mfix_assessment_type), intent(in) :: a
    call mfix_group(unit, result%tcoll, result%dtsolid, input%dtsolid_factor, a%dtsolid_factor, &
      a%dt_recommended, a%tolerance, a%dt_stability, a%dt_accuracy_min, &
      trim(merge("stability", "accuracy ", a%governs /= step_governs%accuracy)), &
      result%phase_i, result%phase_j, result%m_eff, result%k_n, result%eta_n, a%damping_ratio, &
      result%t_coll, a%dt_critical, a%steps, a%restitution_error, a%overlap_error, a%dt_accuracy)
  end subroutine write_mfix_result

  subroutine mfix_group(unit, tcoll, dtsolid, dtsolid_factor, dtsolid_factor_recommended, &
      dt_recommended, tolerance, dt_stability, dt_accuracy_min, governs, phase_i, phase_j, m_eff, &
      k_n, eta_n, damping_ratio, t_coll, dt_critical, steps_per_contact, restitution_error, &
      overlap_error, dt_accuracy)
    integer, intent(in) :: unit
    real(dp), intent(in) :: tcoll, dtsolid, dtsolid_factor, dtsolid_factor_recommended, &
      dt_recommended, tolerance, dt_stability, dt_accuracy_min
    character(len=*), intent(in) :: governs
    integer, intent(in) :: phase_i(:), phase_j(:)
    real(dp), intent(in) :: m_eff(:), k_n(:), eta_n(:), damping_ratio(:), t_coll(:), dt_critical(:), &
      restitution_error(:), overlap_error(:), dt_accuracy(:)
    integer(i8), intent(in) :: steps_per_contact(:)
    namelist /mfix_result/ tcoll, dtsolid, dtsolid_factor, dtsolid_factor_recommended, dt_recommended, &
      governs, tolerance, dt_stability, dt_accuracy_min, phase_i, phase_j, m_eff, k_n, eta_n, &
      damping_ratio, t_coll, dt_critical, steps_per_contact, restitution_error, overlap_error, dt_accuracy
    write(unit, nml=mfix_result)
  end subroutine mfix_group

end module demstep_results
