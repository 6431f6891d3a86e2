!> Materials and contact time scales in the conventions of the major DEM codes.
!>
!> From Young's modulus, Poisson's ratio, density and radius of two particle
!> types, a restitution coefficient and a characteristic impact velocity, this
!> module gives the contact parameters (`k_n`, `k_t`, `gamma_n`, `gamma_t`) as
!> each code computes them, named by the code (`code_convention%liggghts_hertz`),
!> so that a user can reproduce what the code will do; the Rayleigh time, the
!> Hertz contact duration and the linear contact duration; and the time step
!> each code's rule of thumb would pick (`peer_rule%edem_rayleigh_20`, ...).
!>
!> Units: any consistent set (SI in the comments). The formulas were read in
!> each code's source; the comment on each convention names the file and function.
module demstep_material
  use demstep_kinds, only: dp, pi
  use demstep_status, only: demstep_status_type, demstep_stat, set_status, status_at, status_restate
  use demstep_text, only: real_text, int_text
  use demstep_spring, only: damped_limit
  use demstep_interaction, only: hertz_e_star, mindlin_g_star
  use, intrinsic :: ieee_arithmetic, only: ieee_is_finite
  use demstep_words, only: word_index, word_of
  implicit none
  private

  public :: effective_pair, contact_parameters, rayleigh_time, hertz_max_overlap, &
    hertz_contact_duration, linear_contact_duration, peer_time_steps, packing_peer_steps, hertz_duration_constant, &
    hertz_impact_stiffness, convention_limit, mfix_moduli, mfix_pair_springs, check_pair

  !> The codes whose contact conventions are reproduced, as components of a parameter.
  type, public :: code_convention_enum
    !> LIGGGHTS `model hooke` (normal_model_hooke.h): stiffness from the Hertz impact at v.
    integer :: liggghts_hooke = 1
    !> LIGGGHTS `model hertz` (normal_model_hertz.h): values at the maximum overlap.
    integer :: liggghts_hertz = 2
    !> Yade `Ip2_FrictMat_FrictMat_FrictPhys` (FrictPhys.cpp): no contact damping.
    integer :: yade_frictphys = 3
    !> Yade `Ip2_ViscElMat_ViscElMat_ViscElPhys` with `tc`, `en`, `et` (ViscoelasticPM.cpp).
    integer :: yade_viscelphys = 4
    !> MFiX linear spring-dashpot (check_solids_dem.f, CHECK_SOLIDS_DEM_COLL_LSD).
    integer :: mfix_lsd = 5
    !> MFiX Hertzian (check_solids_dem.f, CHECK_SOLIDS_DEM_COLL_HERTZ; calc_force_dem.f).
    integer :: mfix_hertzian = 6
    !> MercuryDPM linear viscoelastic species from a collision time and restitution.
    integer :: mercurydpm_linear = 7
    !> LAMMPS `pair_style granular`, `normal hooke`, `damping coeff_restitution`.
    integer :: lammps_hooke = 8
    !> LAMMPS `pair_style granular`, `normal hertz/material`, `damping coeff_restitution`,
    !> `tangential mindlin NULL` with `x_gamma_t = 1`.
    integer :: lammps_hertz_material = 9
  end type code_convention_enum

  !> The conventions by name.
  type(code_convention_enum), parameter, public :: code_convention = code_convention_enum()
  public :: code_convention_from_name, code_convention_name
  !> Number of conventions.
  integer, parameter, public :: n_conventions = 9
  !> Names of the conventions, in the order of their codes.
  character(len=*), parameter, public :: code_convention_names(n_conventions) = [character(len=21) :: &
    "liggghts_hooke", "liggghts_hertz", "yade_frictphys", "yade_viscelphys", "mfix_lsd", &
    "mfix_hertzian", "mercurydpm_linear", "lammps_hooke", "lammps_hertz_material"]

  !> The peers' rules of thumb for the time step, as components of a parameter.
  type, public :: peer_rule_enum
    !> EDEM: 20 % of the Rayleigh time (EDEM advises 20 to 40 %).
    integer :: edem_rayleigh_20 = 1
    !> EDEM: 40 % of the Rayleigh time, the upper end of its advice.
    integer :: edem_rayleigh_40 = 2
    !> LIGGGHTS `fix check/timestep/gran` warning threshold on the Rayleigh time
    !> (fraction_r = 0.1, as in its documentation's example and shipped examples).
    integer :: liggghts_rayleigh_10 = 3
    !> LIGGGHTS `fix check/timestep/gran` warning threshold on its Hertz time (fraction_h = 0.1).
    integer :: liggghts_hertz_10 = 4
    !> MFiX LSD: `DTSOLID = TCOLL/50` with the linear stiffness.
    integer :: mfix_lsd_tc50 = 5
    !> MFiX Hertzian: `DTSOLID = TCOLL/50` with MFiX's Hertzian TCOLL (SI units).
    integer :: mfix_hertzian_tc50 = 6
    !> MercuryDPM: `dt = tc/50` (its drivers' `getCollisionTime(mass)/50`).
    integer :: mercurydpm_tc50 = 7
    !> Yade `PWaveTimeStep()`: min over bodies of `r/sqrt(E/rho)`.
    integer :: yade_pwave = 8
    !> Yade: 0.3 of `PWaveTimeStep()`, as its documentation advises.
    integer :: yade_pwave_30 = 9
  end type peer_rule_enum

  !> The peers' rules by name.
  type(peer_rule_enum), parameter, public :: peer_rule = peer_rule_enum()
  public :: peer_rule_from_name, peer_rule_name
  !> Number of peer rules.
  integer, parameter, public :: n_peer_rules = 9
  !> Names of the peer rules, in the order of their codes.
  character(len=*), parameter, public :: peer_rule_names(n_peer_rules) = [character(len=20) :: &
    "edem_rayleigh_20", "edem_rayleigh_40", "liggghts_rayleigh_10", "liggghts_hertz_10", &
    "mfix_lsd_tc50", "mfix_hertzian_tc50", "mercurydpm_tc50", "yade_pwave", "yade_pwave_30"]

  !> Fraction of the Rayleigh time EDEM advises (its range is 0.2 to 0.4).
  real(dp), parameter, public :: edem_fraction_low = 0.2_dp, edem_fraction_high = 0.4_dp
  !> Fractions of `fix check/timestep/gran` in LIGGGHTS' documented example.
  real(dp), parameter, public :: liggghts_fraction_rayleigh = 0.1_dp, liggghts_fraction_hertz = 0.1_dp
  !> The relative velocity of LIGGGHTS' Hertz time over the impact velocity:
  !> `check/timestep/gran` takes `max(2 vmax, vmax + vmax_mesh)` with `vmax` the
  !> largest particle speed (or its `vmax` keyword), i.e. 2 vmax with resting walls.
  real(dp), parameter, public :: liggghts_velocity_factor = 2.0_dp
  !> Collision time over time step of MFiX's default DTSOLID_FACTOR and of MercuryDPM's drivers.
  real(dp), parameter, public :: tc_over_dt_rule = 50.0_dp
  !> Fraction of `PWaveTimeStep()` Yade's documentation advises (formulation.rst).
  real(dp), parameter, public :: yade_pwave_fraction = 0.3_dp

  !> One particle type.
  type, public :: material_type
    !> Young's modulus `E` (> 0).
    real(dp) :: young = 0.0_dp
    !> Poisson's ratio `nu` in (-1, 0.5].
    real(dp) :: poisson = 0.0_dp
    !> Density `rho` (> 0).
    real(dp) :: density = 0.0_dp
    !> Radius `R` (> 0).
    real(dp) :: radius = 0.0_dp
  end type material_type

  !> The materials of a packing's particle types and how its contacts are
  !> loaded, in one code's convention (`first` = `last`) or all of them
  !> (`first` 1 to `last` n_conventions): what a `&material` group gives.
  type, public :: material_set_type
    !> Whether a set was given at all.
    logical :: found = .false.
    !> One material per particle type (one for all types before broadcasting).
    type(material_type), allocatable :: types(:)
    !> Normal and tangential restitution (0: the normal one) and impact velocity.
    real(dp) :: restitution = 1.0_dp, restitution_t = 0.0_dp, impact_velocity = 0.0_dp
    !> The conventions named (`code_convention%...`).
    integer :: first = 0, last = -1
  end type material_set_type

  !> A contact between two particle types and how it is loaded.
  type, public :: material_pair_type
    !> The two types (equal for a contact between like particles).
    type(material_type) :: a, b
    !> Normal restitution coefficient in (0, 1].
    real(dp) :: restitution = 1.0_dp
    !> Tangential restitution in (0, 1] (Yade ViscElPhys `et`, MercuryDPM, MFiX
    !> Hertzian `DES_ET_INPUT`); 0: the normal one.
    real(dp) :: restitution_t = 0.0_dp
    !> Characteristic impact (relative normal) velocity (> 0).
    real(dp) :: impact_velocity = 1.0_dp
    !> Collision time for the codes set from one (Yade ViscElPhys `tc`,
    !> MercuryDPM); 0: the Hertz contact duration at the impact velocity.
    real(dp) :: contact_time = 0.0_dp
    !> Linear normal stiffness for the codes that take one (MFiX `KN`, LAMMPS
    !> `normal hooke`); 0: LIGGGHTS' Hooke stiffness (the linear spring with
    !> the Hertz maximum overlap at the impact velocity).
    real(dp) :: stiffness = 0.0_dp
  end type material_pair_type

  !> Effective quantities of a pair.
  type, public :: effective_pair_type
    !> `E* = 1/((1 - nu_a^2)/E_a + (1 - nu_b^2)/E_b)`.
    real(dp) :: e_star = 0.0_dp
    !> `G* = 1/(2(2 - nu_a)(1 + nu_a)/E_a + 2(2 - nu_b)(1 + nu_b)/E_b)`.
    real(dp) :: g_star = 0.0_dp
    !> `R* = R_a R_b/(R_a + R_b)`.
    real(dp) :: r_star = 0.0_dp
    !> `m* = m_a m_b/(m_a + m_b)`.
    real(dp) :: m_star = 0.0_dp
    !> Particle masses `4/3 pi R^3 rho`.
    real(dp) :: m_a = 0.0_dp, m_b = 0.0_dp
  end type effective_pair_type

  !> Contact parameters in one code's convention.
  type, public :: contact_parameters_type
    !> The convention (`code_convention%...`).
    integer :: convention = 0
    !> Normal and tangential stiffness (force/length); for the Hertz conventions
    !> the secant values at `overlap`.
    real(dp) :: k_n = 0.0_dp, k_t = 0.0_dp
    !> Normal and tangential damping coefficients (force/velocity), at `overlap`
    !> for the Hertz conventions.
    real(dp) :: gamma_n = 0.0_dp, gamma_t = 0.0_dp
    !> Overlap at which a Hertz convention is evaluated: the maximum overlap of
    !> an undamped Hertz impact at the impact velocity; 0 for linear conventions.
    real(dp) :: overlap = 0.0_dp
    !> Contact duration: `pi/sqrt(k_n/m* - (gamma_n/2m*)^2)` for the linear
    !> conventions, the undamped Hertz duration at the impact velocity for the Hertz ones.
    real(dp) :: t_contact = 0.0_dp
    !> The collision time the code itself computes (MFiX TCOLL of the pair,
    !> MercuryDPM `getCollisionTime`, Yade ViscElPhys `tc`); 0 where it computes none.
    real(dp) :: code_collision_time = 0.0_dp
  end type contact_parameters_type

  !> The time scales of a pair and the steps the peers' rules pick.
  type, public :: peer_steps_type
    !> Rayleigh time, smaller of the two types: LIGGGHTS/EDEM/MercuryDPM constant 0.8766.
    real(dp) :: rayleigh = 0.0_dp
    !> Rayleigh time with Yade's constant 0.876605 (Shop::RayleighWaveTimeStep).
    real(dp) :: rayleigh_yade = 0.0_dp
    !> The Hertz contact duration at the impact velocity (exact constant).
    real(dp) :: hertz_duration = 0.0_dp
    !> LIGGGHTS' Hertz time estimate (fix_check_timestep_gran.cpp), at the relative
    !> velocity `liggghts_velocity_factor` times the impact velocity.
    real(dp) :: hertz_liggghts = 0.0_dp
    !> Steps picked by each rule, indexed by `peer_rule%...`.
    real(dp) :: dt(n_peer_rules) = 0.0_dp
  end type peer_steps_type

contains

  !> The exact constant `C` of the Hertz contact duration
  !> `t = C (m*^2/(R* E*^2 v))^(1/5)`: `C = 2 (15/16)^(2/5) (2/5) B(2/5, 1/2)`
  !> = 2.868265... (the folklore rounds it to 2.87). From the energy integral
  !> `t = 2 (delta_max/v) int_0^1 dx/sqrt(1 - x^(5/2))`.
  pure real(dp) function hertz_duration_constant() result(c)
    c = 2.0_dp*(15.0_dp/16.0_dp)**0.4_dp*0.4_dp*gamma(0.4_dp)*sqrt(pi)/gamma(0.9_dp)
  end function hertz_duration_constant

  !> Check one material; the message names the variable and the type.
  pure subroutine check_material(mat, label, status)
    type(material_type), intent(in) :: mat
    character(len=*), intent(in) :: label
    type(demstep_status_type), intent(out) :: status
    if (.not. (mat%young > 0.0_dp .and. ieee_is_finite(mat%young))) then
      call set_status(status, demstep_stat%invalid_input, &
        "must be a finite number > 0"//label, where="young")
    else if (.not. (mat%poisson > -1.0_dp .and. mat%poisson <= 0.5_dp)) then
      call set_status(status, demstep_stat%invalid_input, &
        "must lie in (-1, 0.5]"//label, where="poisson")
    else if (.not. (mat%density > 0.0_dp .and. ieee_is_finite(mat%density))) then
      call set_status(status, demstep_stat%invalid_input, &
        "must be a finite number > 0"//label, where="density")
    else if (.not. (mat%radius > 0.0_dp .and. ieee_is_finite(mat%radius))) then
      call set_status(status, demstep_stat%invalid_input, &
        "must be a finite number > 0"//label, where="radius")
    else
      status%stat = demstep_stat%ok
    end if
  end subroutine check_material

  !> Particle mass `4/3 pi R^3 rho`, formed without intermediate overflow
  !> (`huge` when the mass itself overflows).
  pure real(dp) function particle_mass(mat) result(m)
    type(material_type), intent(in) :: mat
    real(dp) :: lm
    lm = log(4.0_dp*pi/3.0_dp) + 3.0_dp*log(mat%radius) + log(mat%density)
    if (lm > log(huge(1.0_dp))) then
      m = huge(1.0_dp)
    else
      m = exp(lm)
      ! exact product where it cannot overflow: keeps the textbook rounding
      if (lm < 600.0_dp .and. lm > -600.0_dp) m = (4.0_dp*pi/3.0_dp)*mat%radius**3*mat%density
    end if
  end function particle_mass

  !> Effective quantities `E*`, `G*`, `R*`, `m*` of a pair of types.
  !> `invalid_input` (message starting with the variable) for a material out of
  !> its domain or a mass or modulus that overflows.
  pure subroutine effective_pair(a, b, eff, status)
    !> The two types.
    type(material_type), intent(in) :: a, b
    !> Their effective quantities.
    type(effective_pair_type), intent(out) :: eff
    type(demstep_status_type), intent(out) :: status
    call check_material(a, " (particle type a)", status)
    if (status%stat /= demstep_stat%ok) return
    call check_material(b, " (particle type b)", status)
    if (status%stat /= demstep_stat%ok) return
    eff%m_a = particle_mass(a)
    eff%m_b = particle_mass(b)
    if (eff%m_a >= huge(1.0_dp) .or. eff%m_b >= huge(1.0_dp) .or. eff%m_a < tiny(1.0_dp) &
      .or. eff%m_b < tiny(1.0_dp)) then
      call set_status(status, demstep_stat%invalid_input, &
        "the particle mass 4/3 pi radius^3 density leaves the double range; rescale the units", where="radius")
      return
    end if
    ! forms that never overflow: x y/(x + y) = x/(1 + x/y)
    eff%m_star = eff%m_a/(1.0_dp + eff%m_a/eff%m_b)
    eff%r_star = a%radius/(1.0_dp + a%radius/b%radius)
    eff%e_star = hertz_e_star(a%young, a%poisson, b%young, b%poisson)
    eff%g_star = mindlin_g_star(a%young, a%poisson, b%young, b%poisson)
    if (.not. (ieee_is_finite(eff%e_star) .and. ieee_is_finite(eff%g_star) .and. &
      eff%e_star > 0.0_dp .and. eff%g_star > 0.0_dp)) then
      call set_status(status, demstep_stat%invalid_input, &
        "the effective modulus leaves the double range; rescale the units", where="young")
      return
    end if
    status%stat = demstep_stat%ok
  end subroutine effective_pair

  !> Maximum overlap of an undamped Hertz impact at velocity `v`:
  !> `delta = (15 m* v^2/(16 E* sqrt(R*)))^(2/5)` (energy balance).
  pure subroutine hertz_max_overlap(eff, v, delta, status)
    !> The pair.
    type(effective_pair_type), intent(in) :: eff
    !> Impact velocity (> 0).
    real(dp), intent(in) :: v
    !> The overlap.
    real(dp), intent(out) :: delta
    type(demstep_status_type), intent(out) :: status
    real(dp) :: ld
    delta = 0.0_dp
    if (.not. (v > 0.0_dp .and. ieee_is_finite(v))) then
      call set_status(status, demstep_stat%invalid_input, "must be a finite number > 0", where="impact_velocity")
      return
    end if
    ! in logarithms: m* v^2 may overflow although delta does not
    ld = 0.4_dp*(log(15.0_dp/16.0_dp) + log(eff%m_star) + 2.0_dp*log(v) - log(eff%e_star) &
      - 0.5_dp*log(eff%r_star))
    if (ld > log(huge(1.0_dp)) .or. ld < log(tiny(1.0_dp))) then
      call set_status(status, demstep_stat%invalid_input, &
        "the Hertz overlap leaves the double range; rescale the units", where="impact_velocity")
      return
    end if
    delta = exp(ld)
    status%stat = demstep_stat%ok
  end subroutine hertz_max_overlap

  !> The Hertz contact duration of an undamped impact at velocity `v`:
  !> `t = C (m*^2/(R* E*^2 v))^(1/5)` with the exact [[hertz_duration_constant]].
  pure subroutine hertz_contact_duration(eff, v, t, status)
    !> The pair.
    type(effective_pair_type), intent(in) :: eff
    !> Impact velocity (> 0).
    real(dp), intent(in) :: v
    !> The duration.
    real(dp), intent(out) :: t
    type(demstep_status_type), intent(out) :: status
    real(dp) :: delta
    t = 0.0_dp
    call hertz_max_overlap(eff, v, delta, status)
    if (status%stat /= demstep_stat%ok) return
    ! t = 2 (delta/v) int_0^1 (1 - x^(5/2))^(-1/2) dx
    t = hertz_duration_constant()/(15.0_dp/16.0_dp)**0.4_dp*(delta/v)
    if (.not. (ieee_is_finite(t) .and. t > 0.0_dp)) then
      call set_status(status, demstep_stat%invalid_input, &
        "the Hertz contact duration leaves the double range; rescale the units", where="impact_velocity")
      t = 0.0_dp
      return
    end if
  end subroutine hertz_contact_duration

  !> The Hertz contact linearised at the largest overlap `delta` of an impact at
  !> velocity `v`: its tangent stiffness `dF/d delta = 2 E* sqrt(R* delta)`, the
  !> stiffest state the contact reaches, so that the linear contact's stability
  !> limit bounds the step of the whole impact. Hertz quantities depend on E* and
  !> R* only through E* sqrt(R*).
  pure subroutine hertz_impact_stiffness(eff, v, k, status)
    !> The pair.
    type(effective_pair_type), intent(in) :: eff
    !> Impact velocity (> 0).
    real(dp), intent(in) :: v
    !> The tangent stiffness.
    real(dp), intent(out) :: k
    type(demstep_status_type), intent(out) :: status
    real(dp) :: delta
    k = 0.0_dp
    call hertz_max_overlap(eff, v, delta, status)
    if (status%stat /= demstep_stat%ok) return
    k = 2.0_dp*eff%e_star*sqrt(eff%r_star)*sqrt(delta)
    if (.not. (ieee_is_finite(k) .and. k > 0.0_dp)) then
      k = 0.0_dp
      call set_status(status, demstep_stat%invalid_input, &
        "the linearised Hertz stiffness leaves the double range; rescale the units", where="impact_velocity")
    end if
  end subroutine hertz_impact_stiffness

  !> MFiX's effective moduli of two materials, in its order of operations
  !> (check_solids_dem.f, CHECK_SOLIDS_DEM_COLL_HERTZ): `E_eff = Ea Eb/(Ea (1 -
  !> nub^2) + Eb (1 - nua^2))`, `G = E/(2 (1 + nu))`, `G_eff = Ga Gb/(Ga (2 - nub)
  !> + Gb (2 - nua))`.
  pure subroutine mfix_moduli(e_a, nu_a, e_b, nu_b, e_eff, g_eff)
    !> Young's moduli and Poisson's ratios of the two sides.
    real(dp), intent(in) :: e_a, nu_a, e_b, nu_b
    !> The effective moduli.
    real(dp), intent(out) :: e_eff, g_eff
    real(dp) :: g_a, g_b
    g_a = 0.5_dp*e_a/(1.0_dp + nu_a)
    g_b = 0.5_dp*e_b/(1.0_dp + nu_b)
    e_eff = e_a*e_b/(e_a*(1.0_dp - nu_b**2) + e_b*(1.0_dp - nu_a**2))
    g_eff = g_a*g_b/(g_a*(2.0_dp - nu_b) + g_b*(2.0_dp - nu_a))
  end subroutine mfix_moduli

  !> MFiX's springs and dashpots of one pair (particle or wall), in its order
  !> of operations (CHECK_SOLIDS_DEM_COLL_LSD and _HERTZ). LSD: `k_n = KN`,
  !> `k_t = KT_FAC KN`, `eta_n = 2 sqrt(KN m)|ln en|/sqrt(pi^2 + ln^2 en)`,
  !> `eta_t = DES_ETAT_FAC eta_n`. Hertzian (when `r_eff` is present): `k_n =
  !> 4/3 sqrt(R) E_eff`, `k_t = 8 sqrt(R) G_eff`, `eta_n` as LSD with `k_n`,
  !> `eta_t = 2 sqrt(2/7 k_t m)|ln et|/sqrt(pi^2 + ln^2 et)`. `w = k_n/m -
  !> (eta_n/m)^2/4`, whose root gives MFiX's collision time `pi/sqrt(w)`.
  pure subroutine mfix_pair_springs(mass_eff, en, k_n, k_t, eta_n, eta_t, w, kn, kt_fac, etat_fac, &
      r_eff, e_eff, g_eff, et)
    !> Effective mass and normal restitution.
    real(dp), intent(in) :: mass_eff, en
    !> MFiX's springs, dashpots and `w`.
    real(dp), intent(out) :: k_n, k_t, eta_n, eta_t, w
    !> LSD: `KN` (or `KN_W`), `KT_FAC`, `DES_ETAT_FAC`.
    real(dp), intent(in), optional :: kn, kt_fac, etat_fac
    !> Hertzian: effective radius and moduli, tangential restitution.
    real(dp), intent(in), optional :: r_eff, e_eff, g_eff, et
    if (present(r_eff)) then
      k_n = (4.0_dp/3.0_dp)*sqrt(r_eff)*e_eff
      k_t = 8.0_dp*sqrt(r_eff)*g_eff
    else
      k_n = kn
      k_t = kt_fac*kn
    end if
    eta_n = 2.0_dp*sqrt(k_n*mass_eff)*abs(log(en))
    eta_n = eta_n/sqrt(pi*pi + (log(en))**2)
    if (present(r_eff)) then
      eta_t = 2.0_dp*sqrt(k_t*((2.0_dp/7.0_dp)*mass_eff))*abs(log(et))
      eta_t = eta_t/sqrt(pi*pi + (log(et))**2)
    else
      eta_t = etat_fac*eta_n
    end if
    w = k_n/mass_eff - ((eta_n/mass_eff)**2)/4.0_dp
  end subroutine mfix_pair_springs

  !> The exact stability limit of a contact as a code steps it with `params`
  !> (central differences, dashpot on the previous velocity): `(2/omega)
  !> (sqrt(1 + z^2) - z)` with `omega = sqrt(k/m*)`, `z = gamma_n/(2 sqrt(k m*))`;
  !> for the Hertz conventions `k` is the tangent stiffness at `params%overlap`,
  !> 3/2 of the secant `k_n` (the force grows as overlap^(3/2)).
  !> `invalid_input` naming `k_n` or `m_star` when they are not finite and > 0.
  pure subroutine convention_limit(params, m_star, dt, status)
    !> The code's parameters (from [[contact_parameters]]).
    type(contact_parameters_type), intent(in) :: params
    !> Effective mass (> 0).
    real(dp), intent(in) :: m_star
    !> The limit.
    real(dp), intent(out) :: dt
    type(demstep_status_type), intent(out) :: status
    real(dp) :: k
    dt = 0.0_dp
    k = params%k_n
    if (params%overlap > 0.0_dp) k = 1.5_dp*params%k_n
    if (.not. (k > 0.0_dp .and. ieee_is_finite(k))) then
      call set_status(status, demstep_stat%invalid_input, "must be finite and > 0", where="k_n")
      return
    else if (.not. (m_star > 0.0_dp .and. ieee_is_finite(m_star))) then
      call set_status(status, demstep_stat%invalid_input, "must be finite and > 0", where="m_star")
      return
    end if
    dt = damped_limit(2.0_dp*(sqrt(m_star)/sqrt(k)), (0.5_dp*params%gamma_n/sqrt(k))/sqrt(m_star))
    status%stat = demstep_stat%ok
  end subroutine convention_limit

  !> Duration of a linear spring-dashpot contact `m x'' = -k x - gamma x'`
  !> that ends at zero overlap: `pi/sqrt(k/m - (gamma/2m)^2)`.
  !> `invalid_input` for a non-positive `k` or `m`, a negative `gamma`, or an
  !> overdamped contact (`gamma >= 2 sqrt(k m)`), which never rebounds.
  pure subroutine linear_contact_duration(k, gamma_n, m, t, status)
    !> Stiffness (> 0).
    real(dp), intent(in) :: k
    !> Damping coefficient (>= 0).
    real(dp), intent(in) :: gamma_n
    !> Effective mass (> 0).
    real(dp), intent(in) :: m
    !> The duration.
    real(dp), intent(out) :: t
    type(demstep_status_type), intent(out) :: status
    real(dp) :: w0, zeta
    t = 0.0_dp
    if (.not. (k > 0.0_dp .and. ieee_is_finite(k))) then
      call set_status(status, demstep_stat%invalid_input, "must be a finite number > 0", where="k")
      return
    else if (.not. (m > 0.0_dp .and. ieee_is_finite(m))) then
      call set_status(status, demstep_stat%invalid_input, "must be a finite number > 0", where="m")
      return
    else if (.not. (gamma_n >= 0.0_dp .and. ieee_is_finite(gamma_n))) then
      call set_status(status, demstep_stat%invalid_input, "must be a finite number >= 0", where="gamma")
      return
    end if
    ! scaled: omega0 = sqrt(k)/sqrt(m), zeta = gamma/(2 sqrt(k) sqrt(m))
    w0 = sqrt(k)/sqrt(m)
    zeta = gamma_n/(2.0_dp*sqrt(k)*sqrt(m))
    if (.not. (zeta < 1.0_dp)) then
      call set_status(status, demstep_stat%invalid_input, &
        "the contact is overdamped (damping ratio "//real_text(zeta)//" >= 1) and never rebounds", where="gamma")
      return
    end if
    t = pi/(w0*sqrt((1.0_dp - zeta)*(1.0_dp + zeta)))
    if (.not. (ieee_is_finite(t) .and. t > 0.0_dp)) then
      call set_status(status, demstep_stat%invalid_input, &
        "the contact duration leaves the double range; rescale the units", where="k")
      t = 0.0_dp
      return
    end if
    status%stat = demstep_stat%ok
  end subroutine linear_contact_duration

  !> The Rayleigh time `pi R sqrt(rho/G)/(0.1631 nu + 0.8766)`, `G = E/(2(1 + nu))`,
  !> as LIGGGHTS (fix_check_timestep_gran.cpp, calc_rayleigh_hertz_estims),
  !> MercuryDPM (helpers::getRayleighTime) and EDEM give it; `yade = .true.`
  !> uses Yade's constant 0.876605 (Shop::RayleighWaveTimeStep).
  pure subroutine rayleigh_time(mat, t, status, yade)
    !> The particle type.
    type(material_type), intent(in) :: mat
    !> The Rayleigh time.
    real(dp), intent(out) :: t
    type(demstep_status_type), intent(out) :: status
    !> Yade's constant instead of 0.8766.
    logical, intent(in), optional :: yade
    real(dp) :: g, c
    t = 0.0_dp
    call check_material(mat, "", status)
    if (status%stat /= demstep_stat%ok) return
    c = 0.8766_dp
    if (present(yade)) then
      if (yade) c = 0.876605_dp
    end if
    g = mat%young/(2.0_dp*(mat%poisson + 1.0_dp))
    t = pi*mat%radius*(sqrt(mat%density)/sqrt(g))/(0.1631_dp*mat%poisson + c)
    if (.not. (ieee_is_finite(t) .and. t > 0.0_dp)) then
      call set_status(status, demstep_stat%invalid_input, &
        "the Rayleigh time leaves the double range; rescale the units", where="radius")
      t = 0.0_dp
    end if
  end subroutine rayleigh_time

  !> Check a pair's loading inputs (restitution, restitution_t, impact_velocity,
  !> contact_time, stiffness): `invalid_input`, the message starting with the
  !> variable, for one out of its domain.
  pure subroutine check_pair(pair, status)
    type(material_pair_type), intent(in) :: pair
    type(demstep_status_type), intent(out) :: status
    if (.not. (pair%restitution > 0.0_dp .and. pair%restitution <= 1.0_dp)) then
      call set_status(status, demstep_stat%invalid_input, "must lie in (0, 1]", where="restitution")
    else if (.not. (pair%restitution_t == 0.0_dp .or. &
      (pair%restitution_t > 0.0_dp .and. pair%restitution_t <= 1.0_dp))) then
      call set_status(status, demstep_stat%invalid_input, &
        "must lie in (0, 1] (0: the normal restitution)", where="restitution_t")
    else if (.not. (pair%impact_velocity > 0.0_dp .and. ieee_is_finite(pair%impact_velocity))) then
      call set_status(status, demstep_stat%invalid_input, "must be a finite number > 0", where="impact_velocity")
    else if (.not. (pair%contact_time >= 0.0_dp .and. ieee_is_finite(pair%contact_time))) then
      call set_status(status, demstep_stat%invalid_input, &
        "must be a finite number >= 0 (0: the Hertz contact duration)", where="contact_time")
    else if (.not. (pair%stiffness >= 0.0_dp .and. ieee_is_finite(pair%stiffness))) then
      call set_status(status, demstep_stat%invalid_input, &
        "must be a finite number >= 0 (0: LIGGGHTS' Hooke stiffness)", where="stiffness")
    else
      status%stat = demstep_stat%ok
    end if
  end subroutine check_pair

  !> LIGGGHTS' Hooke stiffness (normal_model_hooke.h, surfacesIntersect):
  !> `k_n = 16/15 sqrt(R*) Y* (15 m* v^2/(16 sqrt(R*) Y*))^(1/5)`, the linear
  !> spring whose maximum overlap at `v` equals the Hertz one; in logarithms.
  pure real(dp) function liggghts_hooke_kn(eff, v) result(kn)
    type(effective_pair_type), intent(in) :: eff
    real(dp), intent(in) :: v
    real(dp) :: lk, ls
    ls = log(16.0_dp/15.0_dp) + 0.5_dp*log(eff%r_star) + log(eff%e_star)
    lk = ls + 0.2_dp*(log(eff%m_star) + 2.0_dp*log(v) - ls)
    kn = exp(min(lk, log(huge(1.0_dp))))
  end function liggghts_hooke_kn

  !> Contact parameters of a pair in one code's convention (see
  !> [[code_convention_enum]]). `invalid_input`, the message starting with
  !> the variable, for inputs out of their domain, an unknown convention, or
  !> results that leave the double range.
  pure subroutine contact_parameters(pair, convention, params, status, wall)
    !> The pair and its loading.
    type(material_pair_type), intent(in) :: pair
    !> One of `code_convention%...`.
    integer, intent(in) :: convention
    !> The parameters.
    type(contact_parameters_type), intent(out) :: params
    type(demstep_status_type), intent(out) :: status
    !> A particle of type `pair%a` on a wall of material `pair%b` (default
    !> no): the wall is flat and immovable, R* = R_a and m* = m_a, as the
    !> codes' wall contacts take them.
    logical, intent(in), optional :: wall
    type(effective_pair_type) :: eff
    real(dp) :: e, et, le, let, v, tc, delta, a, beta, kl, t_hertz, w
    real(dp) :: damp, hert_kn, hert_kt, eta_n, eta_t, g_eff, e_mfix, ra, rb
    params%convention = convention
    call check_pair(pair, status)
    if (status%stat /= demstep_stat%ok) return
    call effective_pair(pair%a, pair%b, eff, status)
    if (status%stat /= demstep_stat%ok) return
    if (present(wall)) then
      if (wall) then
        eff%r_star = pair%a%radius
        eff%m_star = eff%m_a
      end if
    end if
    e = pair%restitution
    et = merge(pair%restitution_t, e, pair%restitution_t > 0.0_dp)
    le = log(e)
    let = log(et)
    v = pair%impact_velocity
    call hertz_max_overlap(eff, v, delta, status)
    if (status%stat /= demstep_stat%ok) return
    call hertz_contact_duration(eff, v, t_hertz, status)
    if (status%stat /= demstep_stat%ok) return
    tc = merge(pair%contact_time, t_hertz, pair%contact_time > 0.0_dp)
    kl = merge(pair%stiffness, liggghts_hooke_kn(eff, v), pair%stiffness > 0.0_dp)
    a = sqrt(eff%r_star*delta)

    select case (convention)
    case (code_convention%liggghts_hooke)
      ! normal_model_hooke.h, NormalModel<HOOKE>::surfacesIntersect: kt = kn
      ! (ktToKnUser off), gamman = sqrt(4 m* kn ln(e)^2/(ln(e)^2 + pi^2)),
      ! gammat = gamman (tangential_damping on by default)
      params%k_n = liggghts_hooke_kn(eff, v)
      params%k_t = params%k_n
      params%gamma_n = sqrt(4.0_dp*eff%m_star*params%k_n*le**2/(le**2 + pi**2))
      params%gamma_t = params%gamma_n
    case (code_convention%liggghts_hertz)
      ! normal_model_hertz.h, NormalModel<HERTZ>::surfacesIntersect with
      ! Yeff, Geff, betaeff of global_properties.cpp (createYeff, createGeff,
      ! createBetaEff): Sn = 2 Y* sqrt(R* d), St = 8 G* sqrt(R* d),
      ! kn = 4/3 Y* sqrt(R* d), kt = St, gamman = -2 sqrt(5/6) beta sqrt(Sn m*),
      ! gammat = -2 sqrt(5/6) beta sqrt(St m*), beta = ln e/sqrt(ln^2 e + pi^2)
      beta = le/sqrt(le**2 + pi**2)
      params%overlap = delta
      params%k_n = 4.0_dp/3.0_dp*eff%e_star*a
      params%k_t = 8.0_dp*eff%g_star*a
      params%gamma_n = -2.0_dp*sqrt(5.0_dp/6.0_dp)*beta*sqrt(2.0_dp*eff%e_star*a*eff%m_star)
      params%gamma_t = -2.0_dp*sqrt(5.0_dp/6.0_dp)*beta*sqrt(params%k_t*eff%m_star)
    case (code_convention%yade_frictphys)
      ! FrictPhys.cpp, Ip2_FrictMat_FrictMat_FrictPhys::go:
      ! kn = 2 Ea Ra Eb Rb/(Ea Ra + Eb Rb), ks = 2 Ea Ra va Eb Rb vb/(Ea Ra va + Eb Rb vb);
      ! Yade's "poisson" is the ks/kn ratio; no contact damping (NewtonIntegrator damps)
      if (pair%a%poisson < 0.0_dp .or. pair%b%poisson < 0.0_dp) then
        call set_status(status, demstep_stat%invalid_input, &
          "Yade FrictPhys uses it as the ratio ks/kn, which must be >= 0", where="poisson")
        return
      end if
      ra = pair%a%young*pair%a%radius
      rb = pair%b%young*pair%b%radius
      params%k_n = 2.0_dp*ra/(1.0_dp + ra/rb)
      if (pair%a%poisson > 0.0_dp .and. pair%b%poisson > 0.0_dp) then
        params%k_t = 2.0_dp*ra*pair%a%poisson/(1.0_dp + ra*pair%a%poisson/(rb*pair%b%poisson))
      end if
    case (code_convention%yade_viscelphys)
      ! ViscoelasticPM.cpp, Calculate_ViscElMat_ViscElMat_ViscElPhys (tc, en, et branch;
      ! each side's value doubled, then halved by contactParameterCalculation):
      ! kn = m* (pi^2 + ln^2 en)/tc^2, cn = -2 m* ln(en)/tc,
      ! ks = 2/7 m* (pi^2 + ln^2 et)/tc^2, cs = -4/7 m* ln(et)/tc
      params%k_n = eff%m_star*(pi**2 + le**2)/tc**2
      params%gamma_n = -2.0_dp*eff%m_star*le/tc
      params%k_t = 2.0_dp/7.0_dp*eff%m_star*(pi**2 + let**2)/tc**2
      params%gamma_t = -4.0_dp/7.0_dp*eff%m_star*let/tc
      params%code_collision_time = tc
    case (code_convention%mfix_lsd)
      ! check_solids_dem.f, CHECK_SOLIDS_DEM_COLL_LSD: KT = KT_FAC KN (default 2/7),
      ! DES_ETAT = DES_ETAT_FAC DES_ETAN (default 1/2), TCOLL = pi/sqrt(w)
      call mfix_pair_springs(eff%m_star, e, params%k_n, params%k_t, params%gamma_n, params%gamma_t, w, &
        kn=kl, kt_fac=2.0_dp/7.0_dp, etat_fac=0.5_dp)
      params%code_collision_time = pi/sqrt(w)
    case (code_convention%mfix_hertzian)
      ! check_solids_dem.f, CHECK_SOLIDS_DEM_COLL_HERTZ (HERT_KN, HERT_KT, DES_ETAN,
      ! DES_ETAT); calc_force_dem.f: kn = HERT_KN sqrt(d), eta_n = DES_ETAN d^(1/4).
      ! TCOLL = pi/sqrt(HERT_KN/m* - (DES_ETAN/m*)^2/4) treats HERT_KN (N/m^1.5)
      ! as a stiffness: it is the linear duration at the secant stiffness of an
      ! overlap of ONE length unit (1 m in SI), not the Hertz duration.
      call mfix_moduli(pair%a%young, pair%a%poisson, pair%b%young, pair%b%poisson, e_mfix, g_eff)
      call mfix_pair_springs(eff%m_star, e, hert_kn, hert_kt, eta_n, eta_t, w, r_eff=eff%r_star, &
        e_eff=e_mfix, g_eff=g_eff, et=et)
      params%overlap = delta
      params%k_n = hert_kn*sqrt(delta)
      params%k_t = hert_kt*sqrt(delta)
      params%gamma_n = eta_n*sqrt(sqrt(delta))
      params%gamma_t = eta_t*sqrt(sqrt(delta))
      if (w > 0.0_dp) params%code_collision_time = pi/sqrt(w)
    case (code_convention%mercurydpm_linear)
      ! LinearViscoelasticNormalSpecies.cc, setCollisionTimeAndRestitutionCoefficient(tc, e,
      ! mass = 2 m*): dissipation = -mass ln(e)/tc, stiffness = mass/2 (pi^2/tc^2 +
      ! (dissipation/mass)^2); FormulaHelpers.cc (computeDisptFrom...): kt = 2/7 k
      ! (pi^2 + ln^2 et)/(pi^2 + ln^2 e), dispt = -2 ln(et) sqrt(m* kt/7/(pi^2 + ln^2 et))
      params%gamma_n = -(2.0_dp*eff%m_star)/tc*le
      params%k_n = 0.5_dp*(2.0_dp*eff%m_star)*((pi/tc)**2 + (params%gamma_n/(2.0_dp*eff%m_star))**2)
      params%k_t = 2.0_dp/7.0_dp*params%k_n*(pi**2 + let**2)/(pi**2 + le**2)
      params%gamma_t = -2.0_dp*let*sqrt(eff%m_star*params%k_t/7.0_dp/(pi**2 + let**2))
      params%code_collision_time = tc
    case (code_convention%lammps_hooke)
      ! gran_sub_mod_damping.cpp, GranSubModDampingCoeffRestitution::init (hooke):
      ! damp = -2 ln e/sqrt(pi^2 + ln^2 e); gran_sub_mod_damping_kernel.h (tsuji
      ! prefactor): gamma_n = damp sqrt(m* Fn/delta) = damp sqrt(m* k_n).
      ! k_n and k_t are user inputs (normal hooke k_n, tangential linear_history k_t):
      ! k_t is left 0; gamma_t = x_gamma_t gamma_n with x_gamma_t = 1.
      damp = -2.0_dp*le/sqrt(pi*pi + le*le)
      params%k_n = kl
      params%gamma_n = damp*sqrt(eff%m_star*kl)
      params%gamma_t = params%gamma_n
    case (code_convention%lammps_hertz_material)
      ! gran_sub_mod_normal.cpp, GranSubModNormalHertzMaterial: k = 4/3 E*
      ! (mix_stiffnessE), force k a delta with a = sqrt(R* delta); damping
      ! coeff_restitution (hertz): damp = -sqrt(3/2) 2 sqrt(5/6) ln e/sqrt(pi^2 + ln^2 e),
      ! gamma_n = damp sqrt(m* k a); tangential mindlin NULL: k_t = 8 G* a
      ! (mix_stiffnessG); gamma_t = x_gamma_t gamma_n with x_gamma_t = 1
      damp = -sqrt(1.5_dp)*2.0_dp*sqrt(5.0_dp/6.0_dp)*le/sqrt(pi*pi + le*le)
      params%overlap = delta
      params%k_n = 4.0_dp/3.0_dp*eff%e_star*a
      params%k_t = 8.0_dp*eff%g_star*a
      params%gamma_n = damp*sqrt(eff%m_star*params%k_n)
      params%gamma_t = params%gamma_n
    case default
      call set_status(status, demstep_stat%invalid_input, &
        "unknown code convention (1 to 9)", where="convention")
      return
    end select

    if (params%overlap > 0.0_dp) then
      params%t_contact = t_hertz
    else
      call linear_contact_duration(params%k_n, params%gamma_n, eff%m_star, params%t_contact, status)
      if (status%stat /= demstep_stat%ok) then
        call status_at(status, "restitution")
        return
      end if
    end if
    if (.not. all(ieee_is_finite([params%k_n, params%k_t, params%gamma_n, params%gamma_t, &
      params%t_contact, params%code_collision_time]))) then
      call set_status(status, demstep_stat%invalid_input, &
        "the contact parameters leave the double range; rescale the units", where="young")
      return
    end if
    status%stat = demstep_stat%ok
  end subroutine contact_parameters

  !> The time scales of a pair and the steps each peer's rule picks
  !> (see [[peer_rule_enum]]); a later step puts them beside demstep's exact
  !> limit as ratios.
  pure subroutine peer_time_steps(pair, steps, status)
    !> The pair and its loading.
    type(material_pair_type), intent(in) :: pair
    !> Time scales and steps.
    type(peer_steps_type), intent(out) :: steps
    type(demstep_status_type), intent(out) :: status
    type(effective_pair_type) :: eff
    type(contact_parameters_type) :: lsd, hz, mercury
    real(dp) :: ta, tb, v
    call check_pair(pair, status)
    if (status%stat /= demstep_stat%ok) return
    call effective_pair(pair%a, pair%b, eff, status)
    if (status%stat /= demstep_stat%ok) return
    v = pair%impact_velocity
    call rayleigh_time(pair%a, ta, status)
    if (status%stat /= demstep_stat%ok) return
    call rayleigh_time(pair%b, tb, status)
    if (status%stat /= demstep_stat%ok) return
    steps%rayleigh = min(ta, tb)
    call rayleigh_time(pair%a, ta, status, yade=.true.)
    call rayleigh_time(pair%b, tb, status, yade=.true.)
    steps%rayleigh_yade = min(ta, tb)
    call hertz_contact_duration(eff, v, steps%hertz_duration, status)
    if (status%stat /= demstep_stat%ok) return
    ! fix_check_timestep_gran.cpp, calc_rayleigh_hertz_estims (LIGGGHTS-PUBLIC
    ! 3d5c00f, lines 278-348): each type collides with itself, meff = 4/3 pi r^3 rho
    ! (the whole particle mass, not m/2), reff = r/2, Eeff = Yeff of the type with
    ! itself, at v_rel_max_simulation = max(2 vmax, vmax + vmax_mesh) (line 318):
    ! two particles at the impact velocity head on, 2 v (liggghts_velocity_factor)
    steps%hertz_liggghts = min(liggghts_hertz_time(pair%a, v), liggghts_hertz_time(pair%b, v))
    call contact_parameters(pair, code_convention%mfix_lsd, lsd, status)
    if (status%stat /= demstep_stat%ok) return
    call contact_parameters(pair, code_convention%mfix_hertzian, hz, status)
    if (status%stat /= demstep_stat%ok) return
    call contact_parameters(pair, code_convention%mercurydpm_linear, mercury, status)
    if (status%stat /= demstep_stat%ok) return
    steps%dt(peer_rule%edem_rayleigh_20) = edem_fraction_low*steps%rayleigh
    steps%dt(peer_rule%edem_rayleigh_40) = edem_fraction_high*steps%rayleigh
    steps%dt(peer_rule%liggghts_rayleigh_10) = liggghts_fraction_rayleigh*steps%rayleigh
    steps%dt(peer_rule%liggghts_hertz_10) = liggghts_fraction_hertz*steps%hertz_liggghts
    steps%dt(peer_rule%mfix_lsd_tc50) = lsd%code_collision_time/tc_over_dt_rule
    steps%dt(peer_rule%mfix_hertzian_tc50) = hz%code_collision_time/tc_over_dt_rule
    steps%dt(peer_rule%mercurydpm_tc50) = mercury%code_collision_time/tc_over_dt_rule
    ! Shop_01.cpp, Shop::PWaveTimeStep: min over spheres of r/sqrt(E/rho)
    steps%dt(peer_rule%yade_pwave) = min(pwave(pair%a), pwave(pair%b))
    steps%dt(peer_rule%yade_pwave_30) = yade_pwave_fraction*steps%dt(peer_rule%yade_pwave)
    if (.not. all(ieee_is_finite([steps%dt, steps%rayleigh, steps%hertz_liggghts]))) then
      call set_status(status, demstep_stat%invalid_input, &
        "the time scales leave the double range; rescale the units", where="young")
      return
    end if
    status%stat = demstep_stat%ok
  end subroutine peer_time_steps

  !> The peers' rules for a packing: each rule's smallest step over the pairs of
  !> the types present, each type at its smallest radius in the packing (as
  !> the peers' codes check every particle). `steps` holds the smallest time
  !> scales too. Status invalid_input naming `type_of` for a type outside
  !> `types`, or the pair's fault with the pair's types in its detail.
  pure subroutine packing_peer_steps(types, type_of, radius, restitution, restitution_t, &
      impact_velocity, steps, status)
    !> Materials per type.
    type(material_type), intent(in) :: types(:)
    !> Each particle's type (1-based).
    integer, intent(in) :: type_of(:)
    !> Each particle's radius.
    real(dp), intent(in) :: radius(:)
    !> Normal and tangential restitution, impact velocity (as `material_pair_type`).
    real(dp), intent(in) :: restitution, restitution_t, impact_velocity
    !> The smallest steps and time scales over the pairs present.
    type(peer_steps_type), intent(out) :: steps
    type(demstep_status_type), intent(out) :: status
    type(material_type) :: kinds(size(types))
    type(peer_steps_type) :: pair_steps
    logical :: present_type(size(types))
    integer :: i, j, nt
    character(len=:), allocatable :: where, detail
    nt = size(types)
    if (size(radius) /= size(type_of)) then
      call set_status(status, demstep_stat%invalid_input, "one per particle", where="radius")
      return
    end if
    do i = 1, size(type_of)
      if (type_of(i) < 1 .or. type_of(i) > nt) then
        call set_status(status, demstep_stat%invalid_input, "particle "//int_text(i)//": type "// &
          int_text(type_of(i))//" has no material (1 to "//int_text(nt)//")", where="type_of", index=i)
        return
      end if
    end do
    do i = 1, nt
      present_type(i) = any(type_of == i)
      kinds(i) = types(i)
      if (present_type(i)) kinds(i)%radius = minval(radius, mask=type_of == i)
    end do
    steps%dt = huge(1.0_dp)
    steps%rayleigh = huge(1.0_dp)
    steps%rayleigh_yade = huge(1.0_dp)
    steps%hertz_duration = huge(1.0_dp)
    steps%hertz_liggghts = huge(1.0_dp)
    do i = 1, nt
      if (.not. present_type(i)) cycle
      do j = i, nt
        if (.not. present_type(j)) cycle
        call peer_time_steps(material_pair_type(kinds(i), kinds(j), restitution, restitution_t, &
          impact_velocity), pair_steps, status)
        if (status%stat /= demstep_stat%ok) then
          where = status%where
          detail = "types "//int_text(i)//" and "//int_text(j)//": "//status%detail
          call status_restate(status, where, detail)
          return
        end if
        steps%dt = min(steps%dt, pair_steps%dt)
        steps%rayleigh = min(steps%rayleigh, pair_steps%rayleigh)
        steps%rayleigh_yade = min(steps%rayleigh_yade, pair_steps%rayleigh_yade)
        steps%hertz_duration = min(steps%hertz_duration, pair_steps%hertz_duration)
        steps%hertz_liggghts = min(steps%hertz_liggghts, pair_steps%hertz_liggghts)
      end do
    end do
    status%stat = demstep_stat%ok
  end subroutine packing_peer_steps

  !> LIGGGHTS' Hertz time of a type colliding with itself, particles at impact
  !> velocity v: `2.87 (m^2/(r/2 Y*^2 v_rel))^(1/5)` with the whole particle mass m
  !> and v_rel = `liggghts_velocity_factor` v; in logarithms (no overflow).
  pure real(dp) function liggghts_hertz_time(mat, v) result(t)
    type(material_type), intent(in) :: mat
    real(dp), intent(in) :: v
    real(dp) :: y, lm
    y = 1.0_dp/(2.0_dp*(1.0_dp - mat%poisson**2)/mat%young)
    lm = log(4.0_dp*pi/3.0_dp) + 3.0_dp*log(mat%radius) + log(mat%density)
    t = 2.87_dp*exp(0.2_dp*(2.0_dp*lm - log(0.5_dp*mat%radius) - 2.0_dp*log(y) &
      - log(liggghts_velocity_factor) - log(v)))
  end function liggghts_hertz_time

  !> Yade's P-wave time of one sphere, `r/sqrt(E/rho)`.
  pure real(dp) function pwave(mat) result(t)
    type(material_type), intent(in) :: mat
    t = mat%radius*(sqrt(mat%density)/sqrt(mat%young))
  end function pwave

  !> The `code_convention` code of a word (case ignored); 0 for another word.
  pure integer function code_convention_from_name(name) result(code)
    !> The word, one of `code_convention_names`.
    character(len=*), intent(in) :: name
    code = word_index(code_convention_names, name)
  end function code_convention_from_name

  !> The word of a `code_convention` code (`?` for another value).
  pure function code_convention_name(code) result(name)
    !> A code of `code_convention`.
    integer, intent(in) :: code
    character(len=:), allocatable :: name
    name = word_of(code_convention_names, code)
  end function code_convention_name

  !> The `peer_rule` code of a word (case ignored); 0 for another word.
  pure integer function peer_rule_from_name(name) result(code)
    !> The word, one of `peer_rule_names`.
    character(len=*), intent(in) :: name
    code = word_index(peer_rule_names, name)
  end function peer_rule_from_name

  !> The word of a `peer_rule` code (`?` for another value).
  pure function peer_rule_name(code) result(name)
    !> A code of `peer_rule`.
    integer, intent(in) :: code
    character(len=:), allocatable :: name
    name = word_of(peer_rule_names, code)
  end function peer_rule_name

end module demstep_material
