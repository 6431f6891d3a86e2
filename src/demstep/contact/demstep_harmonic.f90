!> The paper's harmonic sums and its relative velocity error (eqs. 15, 20, 23).
!>
!>     S(phi, n)    = sum_{k=1..n} sin(k phi) = sin(n phi/2) sin((n+1) phi/2) / sin(phi/2)
!>     E(N, lambda, n) = 1 - S(2 pi/N, n) / (lambda S(2 pi lambda/N, n))
!>
!> Real `n` uses the closed form (Lagrange's identity), which continues the sum
!> smoothly in `n`; for integer `n` it is the sum itself.
!>
!> Accuracy at the exact binary inputs, for every `n` up to 1e12:
!> - every phase `pi m c / den` (m = n or n+1, c = 1, lambda, 1-lambda or 1+lambda,
!>   den = N or 2N) is reduced exactly: `m c` is formed as an unevaluated sum of two
!>   doubles (Dekker's product), its remainder modulo `den` is taken exactly, and
!>   only the reduced phase in [-1/2, 1/2] is rounded; so each sine is correct to a
!>   few ulps relative to itself, even next to its zeros;
!> - near `lambda = 1`, where E cancels, E is assembled from the differences
!>   `sin x - sin y = 2 cos((x+y)/2) sin((x-y)/2)` with `1 - lambda` and
!>   `1 + lambda` carried exactly, so E is accurate relative to `|E| + (1 - lambda)`.
!> Cost is O(1) in `n`.
!>
!> The evaluators `harmonic_sum`, `harmonic_error` and `harmonic_error_steps` are
!> elemental kernels called millions of times by the scans: they report through
!> an integer `stat` holding a code of `demstep_stat` (`ok`, `invalid_input`,
!> `pole`) instead of a `demstep_status_type` with a message;
!> `harmonic_error_check` gives the message naming the argument.
module demstep_harmonic
  use demstep_kinds, only: dp, pi
  use demstep_status, only: demstep_stat, demstep_status_type, set_status
  use demstep_text, only: real_text, int_text
  use demstep_double_double, only: dd_type, dd, two_sum, two_prod, dd_add, dd_mul, &
    dd_div, dd_div_d, dd_neg, dd_sinpi, dd_cospi
  use, intrinsic :: ieee_arithmetic, only: ieee_is_finite
  use demstep_words, only: word_index, word_of
  implicit none
  private

  public :: harmonic_sum, harmonic_error, harmonic_error_steps, policy_steps
  public :: new_step_policy, harmonic_error_check

  !> The kinds of step policy, by name: `step_kind%fraction`.
  type, public :: step_kind_enum
    !> A fixed number of steps `n`.
    integer :: fixed = 1
    !> A fraction `f` of the simulated period, `n = f N`.
    integer :: fraction = 2
    !> Whole steps, `n = max(1, nint(f N))`: E jumps where f N crosses a half-integer.
    integer :: rounded = 3
  end type step_kind_enum
  !> The step policy kinds by name.
  type(step_kind_enum), parameter, public :: step_kind = step_kind_enum()
  !> Their words, in code order (`step_kind_from_name`, `step_kind_name`).
  character(len=*), parameter, public :: step_kind_names(3) = [character(len=8) :: "fixed", "fraction", "rounded"]
  public :: step_kind_from_name, step_kind_name
  !> Largest supported number of steps.
  real(dp), parameter, public :: harmonic_n_max = 1.0e12_dp
  !> Largest phase (n + 1) max(1, lambda)/N in turns: below 2^50 every phase is
  !> reduced exactly (the multiple is found by the 1.5 2^52 shift).
  real(dp), parameter, public :: harmonic_phase_max = 1125899906842624.0_dp
  !> Smallest min(1, lambda)/N: the step phases pi lambda/N and pi/N stay normal
  !> doubles, far from underflow.
  real(dp), parameter, public :: harmonic_phase_min = 1.0e-300_dp

  !> How many steps `n` the error E compares, as a function of N = T/dt.
  !>
  !> - `step_kind%fixed`, `value = n`: the same `n` for every N. E is smooth in N
  !>   (between its poles).
  !> - `step_kind%fraction`, `value = f`: `n = f N` (real), by default `f = 1/2`: half a
  !>   simulated period, the duration of a compression-only contact. E is smooth in N
  !>   because the closed form is smooth in real `n`.
  !>
  !> - `step_kind%rounded`, `value = f`: `n = max(1, nint(f N))`, the whole steps a DEM
  !>   run takes. E then jumps wherever `f N` crosses a half-integer; root finders
  !>   must not take those jumps for roots.
  type, public :: step_policy_type
    !> `step_kind%fixed`, `step_kind%fraction` or `step_kind%rounded`.
    integer :: kind = step_kind%fraction
    !> `n` (fixed) or `f` (fraction, rounded).
    real(dp) :: value = 0.5_dp
  end type step_policy_type

  !> The fast double-precision difference form is kept when its rounding-error
  !> bound is below this fraction of the guaranteed accuracy 1e-12 (|E| + |1 - lambda|);
  !> otherwise E is re-evaluated in double-double.
  real(dp), parameter :: fast_path_share = 0.5_dp
  !> 1.5 2^52: adding and subtracting it rounds a double to the nearest integer.
  real(dp), parameter :: round_shift = 6755399441055744.0_dp
  !> Guaranteed accuracy, relative to |E| + |1 - lambda|.
  real(dp), parameter :: target_accuracy = 1.0e-12_dp
  !> Relative rounding error of one difference term d_k of the fast path, in ulps
  !> (reduction 1, pi t 1, sin 1, cos 1, two products and a quotient 3, margin).
  real(dp), parameter :: term_ulps = 16.0_dp
  !> Below this `1 - lambda` E is assembled from differences (it cancels there);
  !> above it the plain quotient is accurate to the required `|E| + (1 - lambda)`.
  real(dp), parameter :: difference_form_below = 0.0625_dp

  !> A phase `pi ((r + lo)/den + q)` with |r| <~ den/2 and `odd` = q odd;
  !> `pi_den` = pi/den, rounded.
  type :: phase_type
    real(dp) :: r = 0.0_dp, lo = 0.0_dp, den = 1.0_dp, pi_den = pi
    logical :: odd = .false.
    !> |m c|: the unreduced numerator, for the pole test.
    real(dp) :: size = 0.0_dp
  end type phase_type

contains

  !> Build a validated step policy. Status invalid_input, the message naming
  !> `steps` (an unknown kind), `n_steps` (fixed) or `steps_fraction`.
  pure subroutine new_step_policy(policy, kind, value, status)
    type(step_policy_type), intent(out) :: policy
    !> `step_kind%fixed`, `step_kind%fraction` or `step_kind%rounded`.
    integer, intent(in) :: kind
    !> `n` in [1, 1e12] (fixed) or `f` > 0 (fraction, rounded).
    real(dp), intent(in) :: value
    type(demstep_status_type), intent(out) :: status
    if (kind == step_kind%fixed) then
      if (.not. (ieee_is_finite(value) .and. value >= 1.0_dp .and. value <= harmonic_n_max)) then
        call set_status(status, demstep_stat%invalid_input, "must be in [1, 1e12], got " &
          //real_text(value), where="n_steps")
        return
      end if
    else if (kind == step_kind%fraction .or. kind == step_kind%rounded) then
      if (.not. (ieee_is_finite(value) .and. value > 0.0_dp)) then
        call set_status(status, demstep_stat%invalid_input, "must be finite and > 0, " &
          //"got "//real_text(value), where="steps_fraction")
        return
      end if
    else
      call set_status(status, demstep_stat%invalid_input, "unknown step policy kind "// &
        int_text(kind)//" (step_kind%fixed, %fraction or %rounded)", where="steps")
      return
    end if
    policy%kind = kind
    policy%value = value
    status%stat = demstep_stat%ok
  end subroutine new_step_policy

  !> The number of steps `n` a policy gives at N steps per period.
  elemental function policy_steps(policy, n_per_period) result(n)
    type(step_policy_type), intent(in) :: policy
    real(dp), intent(in) :: n_per_period
    real(dp) :: n
    select case (policy%kind)
    case (step_kind%fixed)
      n = policy%value
    case (step_kind%rounded)
      n = max(1.0_dp, anint(policy%value*n_per_period))
    case default
      n = policy%value*n_per_period
    end select
  end function policy_steps

  !> S(2 pi c/N, n) = sum_{k=1..n} sin(2 pi k c/N) for real n >= 0 (closed form).
  !> `stat`: ok, or invalid_input (N <= 0, n < 0, n > 1e12, c not finite).
  elemental subroutine harmonic_sum(cycles, n_per_period, n, s, stat)
    !> c: the sum's phase per step is 2 pi c / N (c = 1 or lambda in the paper).
    real(dp), intent(in) :: cycles
    !> N = T/dt, finite and > 0.
    real(dp), intent(in) :: n_per_period
    !> Number of terms, 0 <= n <= 1e12 (real: the analytic continuation).
    real(dp), intent(in) :: n
    !> The sum; 0 when not ok.
    real(dp), intent(out) :: s
    integer, intent(out) :: stat
    type(phase_type) :: a, b, c
    real(dp) :: n1, n1_lo, inv_n
    s = 0.0_dp
    stat = demstep_stat%invalid_input
    if (.not. (ieee_is_finite(cycles) .and. ieee_is_finite(n_per_period) .and. ieee_is_finite(n))) return
    if (.not. n_per_period > 0.0_dp .or. n < 0.0_dp .or. n > harmonic_n_max) return
    stat = demstep_stat%ok
    if (n == 0.0_dp .or. cycles == 0.0_dp) return
    call two_sum(n, 1.0_dp, n1, n1_lo)
    inv_n = 1.0_dp/n_per_period
    a = reduce(n, 0.0_dp, cycles, 0.0_dp, n_per_period, inv_n)
    b = reduce(n1, n1_lo, cycles, 0.0_dp, n_per_period, inv_n)
    c = reduce(1.0_dp, 0.0_dp, cycles, 0.0_dp, n_per_period, inv_n)
    if (is_zero(c)) then
      ! c/N an integer: every term sin(2 pi k c/N) is zero
      return
    end if
    s = sin_phase(a)*sin_phase(b)/sin_phase(c)
  end subroutine harmonic_sum

  !> The paper's relative error E(N, lambda, n) = 1 - S(2pi/N, n)/(lambda S(2pi lambda/N, n)).
  !>
  !> `stat`: ok; pole when S(2 pi lambda/N, n) vanishes to working precision (its
  !> zero lies within 4 ulps of the phase n lambda/N; `e` is then huge(1.0_dp));
  !> invalid_input for N <= 0, lambda <= 0, n < 1, n > 1e12, non-finite input,
  !> phases (n + 1) max(1, lambda)/N above 2^50 or min(1, lambda)/N below 1e-300,
  !> or |E| beyond the double range (`e` = 0; `harmonic_error_check` says which).
  !> lambda = 1 gives exactly 0; S(2 pi/N, n) = 0 gives exactly 1.
  elemental subroutine harmonic_error(n_per_period, lambda, n, e, stat)
    !> N = T/dt, finite and > 0 (the method uses N > pi).
    real(dp), intent(in) :: n_per_period
    !> lambda = sqrt(K'/K), finite and > 0 (the method uses 0 < lambda <= 1).
    real(dp), intent(in) :: lambda
    !> Steps compared, 1 <= n <= 1e12; real n continues the sum smoothly.
    real(dp), intent(in) :: n
    !> E.
    real(dp), intent(out) :: e
    integer, intent(out) :: stat
    e = 0.0_dp
    stat = demstep_stat%invalid_input
    if (domain_code(n_per_period, lambda, n) /= 0) return
    call evaluate_e(n_per_period, lambda, n, e, stat)
    if (stat == demstep_stat%ok .and. .not. abs(e) <= huge(1.0_dp)) then
      e = 0.0_dp
      stat = demstep_stat%invalid_input
    end if
  end subroutine harmonic_error

  !> Why E(N, lambda, n) is not evaluated: 0 inside the domain, else the first
  !> failed rule (1 N, 2 lambda, 3 n, 4 phase too large, 5 phase too small).
  elemental integer function domain_code(n_per_period, lambda, n) result(code)
    real(dp), intent(in) :: n_per_period, lambda, n
    code = 1
    if (.not. (ieee_is_finite(n_per_period) .and. n_per_period > 0.0_dp)) return
    code = 2
    if (.not. (ieee_is_finite(lambda) .and. lambda > 0.0_dp)) return
    code = 3
    if (.not. (n >= 1.0_dp .and. n <= harmonic_n_max)) return
    code = 4
    if (.not. ((n + 1.0_dp)*max(1.0_dp, lambda)/n_per_period <= harmonic_phase_max)) return
    code = 5
    if (.not. min(1.0_dp, lambda)/n_per_period >= harmonic_phase_min) return
    code = 0
  end function domain_code

  !> The status of E(N, lambda, n) with a message naming the argument to change
  !> (`n_per_period`, `lambda`, `n_steps`) and the range that works there; ok,
  !> or pole (as `harmonic_error`).
  pure subroutine harmonic_error_check(n_per_period, lambda, n, status)
    !> N = T/dt, lambda and n, as for `harmonic_error`.
    real(dp), intent(in) :: n_per_period, lambda, n
    type(demstep_status_type), intent(out) :: status
    real(dp) :: e, bound
    integer :: stat
    select case (domain_code(n_per_period, lambda, n))
    case (1)
      call set_status(status, demstep_stat%invalid_input, "must be finite and > 0", where="n_per_period")
    case (2)
      call set_status(status, demstep_stat%invalid_input, "must be finite and > 0", where="lambda")
    case (3)
      call set_status(status, demstep_stat%invalid_input, "n must be in [1, 1e12], got " &
        //real_text(n), where="n_steps")
    case (4)
      bound = (n + 1.0_dp)*max(1.0_dp, lambda)/harmonic_phase_max
      if (lambda > 1.0_dp) then
        call set_status(status, demstep_stat%invalid_input, "must be <= " &
          //real_text(0.999_dp*harmonic_phase_max*n_per_period/(n + 1.0_dp))//" at this N and n " &
          //"(phases (n + 1) lambda/N above 2^50 turns keep no digit)", where="lambda")
      else
        call set_status(status, demstep_stat%invalid_input, "must be >= " &
          //real_text(1.001_dp*bound)//" at this n (phases (n + 1)/N above 2^50 turns keep no digit)", &
          where="n_per_period")
      end if
    case (5)
      if (lambda < 1.0_dp .and. harmonic_phase_min*n_per_period < 1.0_dp) then
        call set_status(status, demstep_stat%invalid_input, "must be >= " &
          //real_text(1.001_dp*max(harmonic_phase_min*n_per_period, lambda_floor(n_per_period, n))) &
          //" at this N and n (lambda/N must be >= 1e-300 and |E| within the double range)", where="lambda")
      else
        call set_status(status, demstep_stat%invalid_input, "must be <= " &
          //real_text(0.999_dp*min(1.0_dp, lambda)/harmonic_phase_min)//" at this lambda " &
          //"(the phase min(1, lambda)/N must be >= 1e-300)", where="n_per_period")
      end if
    case default
      call harmonic_error(n_per_period, lambda, n, e, stat)
      if (stat == demstep_stat%invalid_input) then
        call set_status(status, demstep_stat%invalid_input, "|E| exceeds the double " &
          //"range at this N and n; lambda must be >= "//real_text(1.001_dp*max(lambda, &
          lambda_floor(n_per_period, n))), where="lambda")
      else if (stat == demstep_stat%pole) then
        call set_status(status, demstep_stat%pole, "a pole of E, S(2 pi lambda/N, n) = 0", where="lambda")
      else
        status%stat = demstep_stat%ok
      end if
    end select
  contains
    !> For small lambda, E ~ -S(2 pi/N, n) N/(pi lambda^2 n (n + 1)): the lambda
    !> at which |E| reaches huge/2.
    pure real(dp) function lambda_floor(big_n, steps)
      real(dp), intent(in) :: big_n, steps
      real(dp) :: s1
      integer :: st
      call harmonic_sum(1.0_dp, big_n, steps, s1, st)
      lambda_floor = sqrt(2.0_dp*abs(s1)*(big_n/(pi*steps*(steps + 1.0_dp)))) &
        *(1.0_dp/sqrt(huge(1.0_dp)))
    end function lambda_floor
  end subroutine harmonic_error_check

  !> E inside the domain (see harmonic_error).
  elemental subroutine evaluate_e(n_per_period, lambda, n, e, stat)
    real(dp), intent(in) :: n_per_period, lambda, n
    real(dp), intent(out) :: e
    integer, intent(out) :: stat
    type(phase_type) :: yn, yn1, xn, xn1, x1, y1, ph(9)
    real(dp) :: big_n, inv_n, two_n, inv_two_n, n1, n1_lo, mu, mu_lo, sg, sg_lo, d(4), acc, bound
    integer :: k
    e = 0.0_dp
    big_n = n_per_period
    inv_n = 1.0_dp/big_n
    two_n = 2.0_dp*big_n
    inv_two_n = 0.5_dp*inv_n
    call two_sum(n, 1.0_dp, n1, n1_lo)

    ! the denominator S(2 pi lambda/N, n) and its zeros
    yn = reduce(n, 0.0_dp, lambda, 0.0_dp, big_n, inv_n)
    yn1 = reduce(n1, n1_lo, lambda, 0.0_dp, big_n, inv_n)
    y1 = reduce(1.0_dp, 0.0_dp, lambda, 0.0_dp, big_n, inv_n)
    if (near_zero(yn) .or. near_zero(yn1) .or. is_zero(y1)) then
      e = huge(1.0_dp)
      stat = demstep_stat%pole
      return
    end if
    stat = demstep_stat%ok
    if (lambda == 1.0_dp) return
    ! the numerator S(2 pi/N, n): exactly zero when n/N, (n+1)/N or 1/N is an integer
    xn = reduce(n, 0.0_dp, 1.0_dp, 0.0_dp, big_n, inv_n)
    xn1 = reduce(n1, n1_lo, 1.0_dp, 0.0_dp, big_n, inv_n)
    x1 = reduce(1.0_dp, 0.0_dp, 1.0_dp, 0.0_dp, big_n, inv_n)
    if (is_zero(xn) .or. is_zero(xn1) .or. is_zero(x1)) then
      e = 1.0_dp
      return
    end if

    call two_sum(1.0_dp, -lambda, mu, mu_lo)
    if (abs(mu) >= difference_form_below) then
      e = 1.0_dp - (sin_phase(xn)/sin_phase(yn))*(sin_phase(xn1)/sin_phase(yn1)) &
        *(sin_phase(y1)/sin_phase(x1))/lambda
      return
    end if

    ! E = 1 - (1+d1)(1+d2)(1+d3)(1+d4) with each d_i = (ratio - 1) formed without
    ! cancellation:  sin x/sin y - 1 = 2 cos((x+y)/2) sin((x-y)/2) / sin y
    call two_sum(1.0_dp, lambda, sg, sg_lo)
    ph(1) = reduce(1.0_dp, 0.0_dp, sg, sg_lo, two_n, inv_two_n)
    ph(2) = reduce(1.0_dp, 0.0_dp, mu, mu_lo, two_n, inv_two_n)
    ph(3) = x1
    ph(4) = reduce(n, 0.0_dp, sg, sg_lo, two_n, inv_two_n)
    ph(5) = reduce(n, 0.0_dp, mu, mu_lo, two_n, inv_two_n)
    ph(6) = yn
    ph(7) = reduce(n1, n1_lo, sg, sg_lo, two_n, inv_two_n)
    ph(8) = reduce(n1, n1_lo, mu, mu_lo, two_n, inv_two_n)
    ph(9) = yn1
    d(1) = (mu + mu_lo)/lambda
    d(2) = -2.0_dp*cos_phase(ph(1))*sin_phase(ph(2))/sin_phase(ph(3))
    d(3) = 2.0_dp*cos_phase(ph(4))*sin_phase(ph(5))/sin_phase(ph(6))
    d(4) = 2.0_dp*cos_phase(ph(7))*sin_phase(ph(8))/sin_phase(ph(9))
    acc = 0.0_dp
    bound = 0.0_dp
    do k = 1, 4
      bound = bound*abs(1.0_dp + d(k)) + term_ulps*epsilon(1.0_dp)*abs(d(k))*abs(1.0_dp + acc)
      acc = acc + d(k) + acc*d(k)
      bound = bound + 2.0_dp*epsilon(1.0_dp)*abs(acc)
    end do
    e = -acc
    ! near a root of E with many steps the terms are large and cancel: use double-double
    if (bound > fast_path_share*target_accuracy*(abs(e) + abs(mu))) &
      e = error_double_double(lambda, mu, mu_lo, ph)
  end subroutine evaluate_e

  !> E(N, lambda, n) with n from a step policy (see `step_policy_type`).
  elemental subroutine harmonic_error_steps(n_per_period, lambda, policy, e, stat)
    real(dp), intent(in) :: n_per_period, lambda
    type(step_policy_type), intent(in) :: policy
    real(dp), intent(out) :: e
    integer, intent(out) :: stat
    call harmonic_error(n_per_period, lambda, policy_steps(policy, n_per_period), e, stat)
  end subroutine harmonic_error_steps

  !> The difference form of E in double-double, from the same exact phases.
  pure function error_double_double(lambda, mu, mu_lo, ph) result(e)
    real(dp), intent(in) :: lambda, mu, mu_lo
    type(phase_type), intent(in) :: ph(9)
    real(dp) :: e
    type(dd_type) :: d(4), acc, two
    integer :: k
    two = dd_type(2.0_dp, 0.0_dp)
    d(1) = dd_div_d(dd(mu, mu_lo), lambda)
    d(2) = dd_neg(dd_div(dd_mul(dd_mul(two, dd_cos_phase(ph(1))), dd_sin_phase(ph(2))), &
      dd_sin_phase(ph(3))))
    d(3) = dd_div(dd_mul(dd_mul(two, dd_cos_phase(ph(4))), dd_sin_phase(ph(5))), dd_sin_phase(ph(6)))
    d(4) = dd_div(dd_mul(dd_mul(two, dd_cos_phase(ph(7))), dd_sin_phase(ph(8))), dd_sin_phase(ph(9)))
    acc = dd_type(0.0_dp, 0.0_dp)
    do k = 1, 4
      acc = dd_add(dd_add(acc, d(k)), dd_mul(acc, d(k)))
    end do
    e = -(acc%hi + acc%lo)
  end function error_double_double

  !> The reduced phase t = (r + lo)/den in double-double.
  elemental function dd_turns(phase) result(t)
    type(phase_type), intent(in) :: phase
    type(dd_type) :: t
    t = dd_div_d(dd(phase%r, phase%lo), phase%den)
  end function dd_turns

  elemental function dd_sin_phase(phase) result(s)
    type(phase_type), intent(in) :: phase
    type(dd_type) :: s
    s = dd_sinpi(dd_turns(phase))
    if (phase%odd) s = dd_neg(s)
  end function dd_sin_phase

  elemental function dd_cos_phase(phase) result(c)
    type(phase_type), intent(in) :: phase
    type(dd_type) :: c
    c = dd_cospi(dd_turns(phase))
    if (phase%odd) c = dd_neg(c)
  end function dd_cos_phase

  !> Reduce the phase pi (m_hi + m_lo)(c_hi + c_lo)/den exactly to pi((r + lo)/den + q).
  !> `inv` is 1/den, rounded: it only chooses the multiple q, so |r| may exceed
  !> den/2 by a rounding, which sin and cos do not mind.
  elemental function reduce(m_hi, m_lo, c_hi, c_lo, den, inv) result(phase)
    real(dp), intent(in) :: m_hi, m_lo, c_hi, c_lo, den, inv
    type(phase_type) :: phase
    real(dp) :: p, e, q, h, l
    call two_prod(m_hi, c_hi, p, e)
    e = e + (m_hi*c_lo + m_lo*c_hi)
    phase%size = abs(p)
    phase%den = den
    phase%pi_den = pi*inv
    ! round to the nearest integer by the 1.5 2^52 shift: exact for |p/den| < 2^51
    q = (p*inv + round_shift) - round_shift
    if (q /= 0.0_dp) then
      ! p - q den is a double and (p - h) is exact (Sterbenz), so r is exact
      call two_prod(q, den, h, l)
      p = (p - h) - l
      phase%odd = aint(0.5_dp*q) /= 0.5_dp*q
    end if
    phase%r = p
    phase%lo = e
  end function reduce

  !> sin of a reduced phase, accurate relative to itself.
  elemental function sin_phase(phase) result(s)
    type(phase_type), intent(in) :: phase
    real(dp) :: s
    s = sin(phase%pi_den*(phase%r + phase%lo))
    if (phase%odd) s = -s
  end function sin_phase

  !> cos of a reduced phase, accurate relative to itself: near its zeros it is
  !> sin(pi (den/2 - |r + lo|)/den), and den/2 - |r| is exact there (Sterbenz).
  elemental function cos_phase(phase) result(c)
    type(phase_type), intent(in) :: phase
    real(dp) :: c, ar
    ar = abs(phase%r)
    if (ar <= 0.25_dp*phase%den) then
      c = cos(phase%pi_den*(phase%r + phase%lo))
    else
      c = sin(phase%pi_den*((0.5_dp*phase%den - ar) - sign(1.0_dp, phase%r)*phase%lo))
    end if
    if (phase%odd) c = -c
  end function cos_phase

  elemental logical function is_zero(phase)
    type(phase_type), intent(in) :: phase
    is_zero = phase%r + phase%lo == 0.0_dp
  end function is_zero

  !> The phase lies within 4 ulps of a multiple of pi: a zero to working precision.
  elemental logical function near_zero(phase)
    type(phase_type), intent(in) :: phase
    near_zero = abs(phase%r + phase%lo) <= 4.0_dp*epsilon(1.0_dp)*phase%size
  end function near_zero

  !> The `step_kind` code of a word (case ignored); 0 for another word.
  pure integer function step_kind_from_name(name) result(code)
    !> The word, one of `step_kind_names`.
    character(len=*), intent(in) :: name
    code = word_index(step_kind_names, name)
  end function step_kind_from_name

  !> The word of a `step_kind` code (`?` for another value).
  pure function step_kind_name(code) result(name)
    !> A code of `step_kind`.
    integer, intent(in) :: code
    character(len=:), allocatable :: name
    name = word_of(step_kind_names, code)
  end function step_kind_name

end module demstep_harmonic
