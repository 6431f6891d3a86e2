!> Bonds between two particles in each DEM code's convention, and the peers'
!> step rules for bonded scenes (MUSEN, Kratos, exaDEM).
!>
!> A bond here is the interaction kernel's spring set (`contact_product`) held
!> about its rest state in tension and compression alike: normal k_n along the
!> bond axis n, shear k_t on the relative displacement of the point where the
!> shear force acts, at lever arms (arm_i, arm_j) from the two centres along n,
!> bending k_r on the tangential and twisting k_w on the axial part of the
!> relative rotation, and dashpots (c_n, c_t, c_r, c_w) on the same rates.
!> Each code's bond is exactly this kernel once its inputs are turned into the
!> four stiffnesses and the arms (linearised about the unloaded rest state):
!>
!> - PFC parallel bond (Potyondy and Cundall 2004, doi:10.1016/j.ijrmms.2004.09.011,
!>   eqs. 5-7): k_n = kbar_n A, k_t = kbar_s A, k_r = kbar_n I, k_w = kbar_s J
!>   with Rbar = lambda min(r_i, r_j), A = pi Rbar^2, I = pi Rbar^4/4,
!>   J = pi Rbar^4/2 (3D; 2D discs of unit thickness: A = 2 Rbar, I = 2 Rbar^3/3,
!>   no twisting); the bond sits at the contact point, r_i - d/2 from centre i
!>   (d = r_i + r_j - L the overlap, negative for a gap); no bond dashpots.
!> - MUSEN solid bond (Models/SolidBonds/BondModelElastic/ModelSBElastic.cpp,
!>   CalculateSB, msolids/musen at e0ff360): normal force E A strain (strain
!>   over the initial centre distance L), tangential stiffness G A/L, twisting
!>   2 G I/L = G J/L, bending E I/L with A = pi d^2/4 and I = pi d^4/64
!>   (Modules/SystemStructure/SolidBond.cpp:63-64); the relative velocity is
!>   taken at the bond's middle (rAC = half the bond) and the shear force's
!>   moment rAC x F goes to both particles: arms L/2, L/2; no dashpots in this
!>   model.
!> - Yade `CohFrictPhys` (pkg/dem/CohesiveFrictionalContactLaw.cpp, trunk of
!>   2022-11, Ip2_CohFrictMat_CohFrictMat_CohFrictPhys::go, lines 288-308):
!>   kn = 2 E_a r_a E_b r_b/(E_a r_a + E_b r_b) (the harmonic mean of the two
!>   spheres' E r), ks the same with E nu (nu the
!>   material's ks/kn ratio `poisson`), kr = r_a r_b ks alphaKr and
!>   ktw = r_a r_b ks alphaKtw (alphas averaged harmonically; one material
!>   here). Law2_ScGeom6D_CohFrictPhys_CohesionMoment applies the shear force at
!>   the contact point (r - d/2 from each centre) while ScGeom's shear increment
!>   (pkg/dem/ScGeom.cpp:82-83, avoidGranularRatcheting) takes
!>   alpha (v_j - v_i) with alpha = (r_a + r_b)/L and the spins at arms r_a, r_b:
!>   for equal radii (or d = 0) that is this kernel with k_t = alpha ks and arms
!>   r - d/2; for unequal radii with d /= 0 Yade's tangent is not symmetric and
!>   this is its symmetric counterpart. No bond dashpots.
!> - LAMMPS `bond_style bpm/rotational` (src/BPM/bond_bpm_rotational.cpp,
!>   elastic_forces and damping_forces; doc/src/bond_bpm_rotational.rst):
!>   f_r = K_r (r - r_0); the shear force K_s r gamma from the bond's turn
!>   against particle 2's frame plus -K_s r theta/2 from the relative rotation,
!>   with moments r/2 x F on both: to first order a shear spring K_s at the
!>   bond's middle (arms r_0/2); bending K_b, twisting K_t. Dashpots:
!>   gamma_n on the normal and gamma_s on the middle's sliding velocity, the
!>   rolling torque gamma_r r (omega_1 - omega_2) x rhat/2 and twisting torque
!>   gamma_t (omega_1 - omega_2).rhat/2: c = (gamma_n, gamma_s, gamma_r r_0/2,
!>   gamma_t/2). (`normalize no`, the default: K_r and K_s in force/distance.)
!>   validation/lammps/bpm_rotational_check.py differentiates LAMMPS' formulas
!>   at rest: this kernel to 6e-8 (elastic) and 6e-16 (dashpots).
module demstep_bonds
  use demstep_kinds, only: dp, pi
  use demstep_status, only: demstep_status_type, demstep_stat, set_status
  use demstep_words, only: word_index, word_of
  use demstep_text, only: int_text
  use, intrinsic :: ieee_arithmetic, only: ieee_is_finite
  implicit none
  private

  public :: bond_law, check_bond_parameters, bond_parameter_count, bond_parameter_name, &
    bond_pair_modes, musen_bond_time, musen_recommended_step, kratos_step, exadem_step, &
    bond_model_from_name, bond_model_name

  !> The bond models, each code's inputs (`bond_model%musen`); 0: none.
  type, public :: bond_model_enum
    !> PFC parallel bond: (kbar_n, kbar_s, lambda) - stiffness per area
    !> (normal, shear) and the radius multiplier.
    integer :: pfc = 1
    !> MUSEN solid bond: (E, G, d) - the bond's normal and shear moduli and
    !> its diameter.
    integer :: musen = 2
    !> Yade CohFrictMat/CohFrictPhys: (young, poisson, alpha_kr, alpha_ktw) -
    !> poisson is Yade's ks/kn ratio.
    integer :: yade = 3
    !> LAMMPS bpm/rotational: (K_r, K_s, K_t, K_b, gamma_n, gamma_s, gamma_r,
    !> gamma_t) in bond_coeff's order without the four strengths.
    integer :: lammps = 4
  end type bond_model_enum
  !> The bond models by name.
  type(bond_model_enum), parameter, public :: bond_model = bond_model_enum()
  !> Their words, in code order (`bond_model_from_name`, `bond_model_name`).
  character(len=*), parameter, public :: bond_model_names(4) = [character(len=6) :: "pfc", "musen", &
    "yade", "lammps"]
  !> Most parameters a model takes.
  integer, parameter, public :: max_bond_parameters = 8
  !> MUSEN's factor on its smallest characteristic time
  !> (Modules/SystemStructure/SystemStructure.cpp:468, GetRecommendedTimeStep).
  real(dp), parameter, public :: musen_step_factor = 0.1_dp

  !> Each model's parameter names, in order (blank: unused).
  character(len=*), parameter :: parameter_names(max_bond_parameters, 4) = reshape([character(len=9) :: &
    "kbar_n", "kbar_s", "lambda", "", "", "", "", "", &
    "e", "g", "diameter", "", "", "", "", "", &
    "young", "poisson", "alpha_kr", "alpha_ktw", "", "", "", "", &
    "k_r", "k_s", "k_t", "k_b", "gamma_n", "gamma_s", "gamma_r", "gamma_t"], [max_bond_parameters, 4])
  !> Which parameters are lengths that must be > 0 (the rest must be >= 0).
  logical, parameter :: positive(max_bond_parameters, 4) = reshape([ &
    .false., .false., .true., .false., .false., .false., .false., .false., &
    .false., .false., .true., .false., .false., .false., .false., .false., &
    .false., .false., .false., .false., .false., .false., .false., .false., &
    .false., .false., .false., .false., .false., .false., .false., .false.], [max_bond_parameters, 4])

  !> One bond's linear law: stiffnesses (k_n, k_t, k_r, k_w), dashpots
  !> (c_n, c_t, c_r, c_w) and the shear spring's lever arms from the centres of
  !> i and j along the bond axis.
  type, public :: bond_law_type
    real(dp) :: k(4) = 0.0_dp, c(4) = 0.0_dp, arm(2) = 0.0_dp
  end type bond_law_type

contains

  !> How many parameters a model takes (0 for an unknown model).
  pure integer function bond_parameter_count(model) result(n)
    !> A code of `bond_model`.
    integer, intent(in) :: model
    n = 0
    if (model < 1 .or. model > size(bond_model_names)) return
    n = count(len_trim(parameter_names(:, model)) > 0)
  end function bond_parameter_count

  !> The name of a model's p-th parameter (`?` outside the model's list).
  pure function bond_parameter_name(model, p) result(name)
    !> A code of `bond_model` and the parameter's position.
    integer, intent(in) :: model, p
    character(len=:), allocatable :: name
    name = "?"
    if (p < 1 .or. p > bond_parameter_count(model)) return
    name = trim(parameter_names(p, model))
  end function bond_parameter_name

  !> Check a model and its parameters: the model one of `bond_model`, as many
  !> parameters as it takes, each finite, stiffness and damping >= 0 and the
  !> lengths (lambda, diameter) > 0. Status invalid_input naming `bond_model`
  !> or `bond_parameters` (index: the parameter's position).
  pure subroutine check_bond_parameters(model, p, status)
    !> A code of `bond_model`.
    integer, intent(in) :: model
    !> The model's parameters, in its order.
    real(dp), intent(in) :: p(:)
    type(demstep_status_type), intent(out) :: status
    integer :: q, n
    n = bond_parameter_count(model)
    if (n == 0) then
      call set_status(status, demstep_stat%invalid_input, "not a bond model (pfc, musen, yade, lammps)", &
        where="bond_model")
      return
    end if
    if (size(p) /= n) then
      call set_status(status, demstep_stat%invalid_input, "the "//trim(bond_model_names(model))// &
        " bond takes "//int_text(n)//" values ("//parameter_list(model)//")", where="bond_parameters")
      return
    end if
    do q = 1, n
      if (positive(q, model)) then
        if (.not. (ieee_is_finite(p(q)) .and. p(q) > 0.0_dp)) then
          call set_status(status, demstep_stat%invalid_input, trim(parameter_names(q, model))// &
            " must be > 0 and finite", where="bond_parameters", index=q, subscript=.true.)
          return
        end if
      else if (.not. (ieee_is_finite(p(q)) .and. p(q) >= 0.0_dp)) then
        call set_status(status, demstep_stat%invalid_input, trim(parameter_names(q, model))// &
          " must be >= 0 and finite", where="bond_parameters", index=q, subscript=.true.)
        return
      end if
    end do
    status%stat = demstep_stat%ok
  end subroutine check_bond_parameters

  !> A model's parameter names, comma-separated.
  pure function parameter_list(model) result(text)
    integer, intent(in) :: model
    character(len=:), allocatable :: text
    integer :: q
    text = trim(parameter_names(1, model))
    do q = 2, bond_parameter_count(model)
      text = text//", "//trim(parameter_names(q, model))
    end do
  end function parameter_list

  !> The linear law of one bond of a model (parameters checked by
  !> `check_bond_parameters`) between spheres of radii r_i, r_j whose centres
  !> are `length` apart at rest, in `dim` dimensions (see the module's notes
  !> for each code's convention).
  pure function bond_law(model, p, r_i, r_j, length, dim) result(law)
    !> A code of `bond_model` and its parameters.
    integer, intent(in) :: model
    real(dp), intent(in) :: p(:)
    !> Radii and the rest distance of the centres (> 0).
    real(dp), intent(in) :: r_i, r_j, length
    !> Dimension (2: PFC's discs of unit thickness).
    integer, intent(in) :: dim
    type(bond_law_type) :: law
    real(dp) :: rb, a, i2, j2, d, alpha, kn, ks
    d = r_i + r_j - length
    select case (model)
    case (bond_model%pfc)
      rb = p(3)*min(r_i, r_j)
      if (dim == 2) then
        a = 2.0_dp*rb
        i2 = 2.0_dp*rb**3/3.0_dp
        j2 = 0.0_dp
      else
        a = pi*rb**2
        i2 = 0.25_dp*pi*rb**4
        j2 = 0.5_dp*pi*rb**4
      end if
      law%k = [p(1)*a, p(2)*a, p(1)*i2, p(2)*j2]
      law%arm = [r_i - 0.5_dp*d, r_j - 0.5_dp*d]
    case (bond_model%musen)
      a = 0.25_dp*pi*p(3)**2
      i2 = pi*p(3)**4/64.0_dp
      law%k = [p(1)*a, p(2)*a, p(1)*i2, 2.0_dp*p(2)*i2]/length
      law%arm = 0.5_dp*length
    case (bond_model%yade)
      ! 2 E_a r_a E_b r_b/(E_a r_a + E_b r_b), one material: 2 E r_i r_j/(r_i + r_j)
      kn = 2.0_dp*p(1)*r_i*r_j/(r_i + r_j)
      ks = p(2)*kn
      alpha = (r_i + r_j)/length
      law%k = [kn, alpha*ks, r_i*r_j*ks*p(3), r_i*r_j*ks*p(4)]
      law%arm = [r_i - 0.5_dp*d, r_j - 0.5_dp*d]
    case (bond_model%lammps)
      law%k = [p(1), p(2), p(4), p(3)]
      law%c = [p(5), p(6), 0.5_dp*p(7)*length, 0.5_dp*p(8)]
      law%arm = 0.5_dp*length
    end select
  end function bond_law

  !> The four vibration modes of a bonded pair of free spheres (masses m_i,
  !> m_j, moments of inertia i_i, i_j) held by one bond law alone, as omega^2:
  !> (axial, shear-rotation, bending, twisting) = (k_n/m*, k_t (1/m* +
  !> a_i^2/I_i + a_j^2/I_j), k_r/I*, k_w/I*), m* and I* the reduced mass and
  !> moment of inertia, a the lever arms. The shear-rotation mode moves the
  !> centres apart sideways and turns both spheres alike (the shear spring
  !> alone); the bending mode turns them against each other. For equal
  !> spheres these are the pair's exact modes; for unequal ones shear and
  !> bending couple and the two middle values are their uncoupled parts.
  pure function bond_pair_modes(law, m_i, m_j, i_i, i_j) result(w2)
    type(bond_law_type), intent(in) :: law
    real(dp), intent(in) :: m_i, m_j, i_i, i_j
    real(dp) :: w2(4)
    real(dp) :: ms, is
    ms = m_i*m_j/(m_i + m_j)
    is = i_i*i_j/(i_i + i_j)
    w2 = [law%k(1)/ms, law%k(2)*(1.0_dp/ms + law%arm(1)**2/i_i + law%arm(2)**2/i_j), law%k(3)/is, &
      law%k(4)/is]
  end function bond_pair_modes

  !> MUSEN's characteristic time of one solid bond,
  !> T_bond = 2 sqrt(m_min/K_b) with K_b = max(E A/L, E A/(2 L (1 + nu))) = E A/L,
  !> A = pi d^2/4, L the current centre distance and m_min the lighter partner
  !> (Modules/SystemStructure/SystemStructure.cpp:449-465, GetRecommendedTimeStep).
  elemental real(dp) function musen_bond_time(m_i, m_j, young, poisson, diameter, length) result(t)
    !> The partners' masses, the bond material's Young's modulus and Poisson
    !> ratio, the bond's diameter and length.
    real(dp), intent(in) :: m_i, m_j, young, poisson, diameter, length
    real(dp) :: a, kb
    a = 0.25_dp*pi*diameter**2
    kb = max(young*a/length, young*a/(2.0_dp*length*(1.0_dp + poisson)))
    t = 2.0_dp*sqrt(min(m_i, m_j)/kb)
  end function musen_bond_time

  !> MUSEN's recommended step for a scene of particles and solid bonds:
  !> 0.1 min(T_Rayleigh, T_bond) over all particles and bonds, as MUSEN's code
  !> computes it (Modules/SystemStructure/SystemStructure.cpp:433-469). Its
  !> simulator manual gives T_Rayleigh without the 0.1 for scenes without
  !> bonds (msolids/musen#22); with bonds both say 0.1 min(T_R, T_bond).
  pure real(dp) function musen_recommended_step(t_rayleigh, t_bond) result(dt)
    !> The smallest Rayleigh time of the particles and the smallest
    !> `musen_bond_time` of the bonds.
    real(dp), intent(in) :: t_rayleigh, t_bond
    dt = musen_step_factor*min(t_rayleigh, t_bond)
  end function musen_recommended_step

  !> Kratos DEM's automatic step (applications/DEMApplication/custom_processes/
  !> automatic_dt_process.cpp, PR #7166): correction_factor sqrt(m_min/k_n),
  !> m_min the smallest particle's mass and k_n its bond's normal stiffness
  !> (the smallest particle bonded to itself; correction_factor default 1,
  !> automatic_dt_process.hpp).
  elemental real(dp) function kratos_step(m_min, k_n, correction_factor) result(dt)
    real(dp), intent(in) :: m_min, k_n, correction_factor
    dt = correction_factor*sqrt(m_min/k_n)
  end function kratos_step

  !> exaDEM's critical step, pi sqrt(m_min/k_n,max) (Collab4exaNBody/exaDEM
  !> at 0d0dc65, src/field/check_dt_critical.cpp:92, `4 atan(1)
  !> sqrt(mass/kn)`): `mass` the smallest particle's (data/config/
  !> config_dt_critical.msp:1-12, the `min_mass` operator) and `kn` the
  !> largest normal stiffness of its contact and inner-bond parameters
  !> (`max_kn`: src/polyhedron/contact_force_polyhedron.cu.in:142-145,
  !> src/polyhedron/inner_bond_force.cu:92-94), for spheres and polyhedra
  !> alike (a polyhedron is one rigid body). exaDEM warns when dt/dt_critical
  !> reaches its `treshold` (default 1; 0.02 in its documentation's example,
  !> check_dt_critical.cpp:34-47); this is the raw value.
  elemental real(dp) function exadem_step(m_min, k_n_max) result(dt)
    real(dp), intent(in) :: m_min, k_n_max
    dt = pi*sqrt(m_min/k_n_max)
  end function exadem_step

  !> The `bond_model` code of a word (case ignored); 0 for another word.
  pure integer function bond_model_from_name(name) result(code)
    !> The word, one of `bond_model_names`.
    character(len=*), intent(in) :: name
    code = word_index(bond_model_names, name)
  end function bond_model_from_name

  !> The word of a `bond_model` code (`?` for another value).
  pure function bond_model_name(code) result(name)
    !> A code of `bond_model`.
    integer, intent(in) :: code
    character(len=:), allocatable :: name
    name = word_of(bond_model_names, code)
  end function bond_model_name

end module demstep_bonds
