!> Rigid bodies made of a scene's spheres: clumps (Yade), multispheres
!> (LIGGGHTS `fix multisphere`, EDEM, Rocky), DEM-Engine clumps.
!>
!> A body is a set of member particles moving as one rigid body: a mass, a
!> centre of mass and a full inertia tensor about it (global axes), and each
!> member's offset from the centre of mass. A member's velocity is
!> v + omega x (x_member - x_com); its forces act on the body with the lever
!> arm x_member - x_com. Every particle belongs to exactly one body; a particle
!> in no clump is a body of its own (one member, its own mass and moment of
!> inertia), so a scene of single spheres is a scene of one-member bodies.
!>
!> Mass and inertia from the members (`bodies_from_members`) follow Yade's
!> `Clump::updateProperties` without its optional grid integration
!> (core/Clump.cpp, yade/trunk as mirrored in Togekey/yade_trunk e627a44d):
!> the members' masses and moments of inertia are summed with Steiner's
!> parallel-axis term about the common centre of mass (lines 221-234, 250-252),
!> so volume shared by overlapping members counts twice. That is Yade's
!> default (`discretization` 0 skips the overlap test, line 140); Yade
!> integrates over a grid only when asked, and a one-member clump keeps its
!> member's mass and inertia (lines 117-135), as here.
!>
!> LIGGGHTS `fix multisphere` gives each body's mass instead (on every
!> member: a dump's `mass` column); with `body_mass` the members share it
!> in proportion to their volumes r^3 (one density per body) and the
!> centre of mass and inertia follow with Steiner's term as above. That is
!> LIGGGHTS' body exactly when its template states `mass` and
!> `inertia_tensor` equal to the members' sum (then LIGGGHTS takes the
!> template's origin as the centre of mass, runs no Monte Carlo estimate,
!> fix_template_multisphere.cpp:261-275, CFDEMproject/LIGGGHTS-PUBLIC
!> 3d5c00f) and its origin at the members' volume-weighted centre, or for
!> members that do not overlap; a template left to LIGGGHTS' Monte Carlo
!> counts the overlap once (fix_template_multiplespheres.cpp:458-503) and
!> has a larger tensor for its mass than the sum: with `union` the centre
!> and tensor are the union's (`demstep_sphere_union`) at the body's mass.
module demstep_bodies
  use demstep_sort, only: heap_sort, count_before
  use demstep_kinds, only: dp, pi
  use demstep_status, only: demstep_status_type, demstep_stat, set_status
  use demstep_text, only: int_text
  use demstep_scene_data, only: scene_type, branch_vector
  use demstep_sphere_union, only: sphere_union_moments
  use, intrinsic :: ieee_arithmetic, only: ieee_is_finite
  implicit none
  private

  public :: bodies_from_members, bodies_from_lists, bodies_given, check_inertia_tensor, check_bodies

  !> Relative size of the smallest pivot of a positive definite inertia
  !> tensor's Cholesky factor (against its largest diagonal entry): below it
  !> the tensor is refused as singular (a rod of point masses, say).
  real(dp), parameter, public :: inertia_pivot_tolerance = 1.0e-12_dp

  !> Rigid bodies over a scene's particles.
  type, public :: body_set_type
    !> Number of bodies.
    integer :: n = 0
    !> The body of each particle (1..n).
    integer, allocatable :: body_of(:)
    !> Each particle's offset x - x_com from its body's centre of mass (3,
    !> particles; through the nearest periodic image).
    real(dp), allocatable :: offset(:, :)
    !> Mass, centre of mass (3, n) and inertia tensor about it (3, 3, n),
    !> global axes.
    real(dp), allocatable :: mass(:), com(:, :), inertia(:, :, :)
    !> Fixed bodies (all members fixed) are ground.
    logical, allocatable :: fixed(:)
    !> Number of members of each body.
    integer, allocatable :: members(:)
  end type body_set_type

contains

  !> Bodies from a body id per particle, mass and inertia summed from the
  !> members as Yade does (see the module's notes): id 0 is a particle on its
  !> own; positive ids group particles (any values, e.g. Yade's clump ids),
  !> the bodies numbered in increasing id. Members' masses and moments of inertia are the
  !> scene's, or with `density` rho: m = rho (4/3) pi r^3 and 2/5 m r^2
  !> (Yade, core/Clump.cpp:229-234); with `body_mass` (LIGGGHTS'
  !> multisphere, see the module's notes) a body's members share its mass in
  !> proportion to r^3. Status invalid_input naming `body_of` (size, a
  !> negative id), `fixed` (a body with fixed and free members), `density`
  !> or `body_mass` (not finite and > 0, or differing between a body's
  !> members, with the particle's index).
  subroutine bodies_from_members(scene, body_of, bodies, status, density, body_mass, union)
    type(scene_type), intent(in) :: scene
    !> Body id of each particle (0: on its own).
    integer, intent(in) :: body_of(:)
    type(body_set_type), intent(out) :: bodies
    type(demstep_status_type), intent(out) :: status
    !> Density of the members (default: the scene's masses and inertias).
    real(dp), intent(in), optional :: density
    !> Each particle's body's mass (the same on every member of a body).
    real(dp), intent(in), optional :: body_mass(:)
    !> With `body_mass`: the centre of mass and inertia tensor of the union
    !> of the members (the overlap counted once, `body_union_moments`), as
    !> LIGGGHTS' Monte Carlo template; default the members' sum.
    logical, intent(in), optional :: union
    real(dp), allocatable :: m(:), im(:), ref(:, :)
    integer, allocatable :: first(:)
    real(dp) :: d(3), eye(3, 3)
    integer :: i, b
    call number_bodies(scene, body_of, bodies, status)
    if (status%stat /= demstep_stat%ok) return
    allocate(m(scene%n), im(scene%n))
    if (present(density)) then
      if (.not. (ieee_is_finite(density) .and. density > 0.0_dp)) then
        call set_status(status, demstep_stat%invalid_input, "must be finite and > 0", where="density")
        return
      end if
      m(:) = density*(4.0_dp/3.0_dp)*pi*scene%radius**3
      im(:) = 0.4_dp*m*scene%radius**2
    else if (present(body_mass)) then
      call shared_mass(body_mass, m, status)
      if (status%stat /= demstep_stat%ok) return
      im(:) = 0.4_dp*m*scene%radius**2
    else
      m(:) = scene%mass
      im(:) = scene%inertia
    end if
    eye = reshape([1.0_dp, 0.0_dp, 0.0_dp, 0.0_dp, 1.0_dp, 0.0_dp, 0.0_dp, 0.0_dp, 1.0_dp], [3, 3])
    allocate(bodies%mass(bodies%n), source=0.0_dp)
    allocate(bodies%com(3, bodies%n), source=0.0_dp)
    allocate(bodies%inertia(3, 3, bodies%n), source=0.0_dp)
    allocate(first(bodies%n), source=0)
    allocate(ref(3, scene%n))
    ! each member's position seen from its body's first member (nearest image)
    do i = 1, scene%n
      b = bodies%body_of(i)
      if (first(b) == 0) first(b) = i
      ref(:, i) = branch_vector(scene, first(b), i)
      bodies%mass(b) = bodies%mass(b) + m(i)
      bodies%com(:, b) = bodies%com(:, b) + m(i)*ref(:, i)
    end do
    do b = 1, bodies%n
      bodies%com(:, b) = bodies%com(:, b)/bodies%mass(b)
    end do
    ! Steiner about the centre of mass: I_m 1 + m (|d|^2 1 - d d^T)
    do i = 1, scene%n
      b = bodies%body_of(i)
      d = ref(:, i) - bodies%com(:, b)
      bodies%offset(:, i) = d
      bodies%inertia(:, :, b) = bodies%inertia(:, :, b) + im(i)*eye &
        + m(i)*(dot_product(d, d)*eye - spread(d, 2, 3)*spread(d, 1, 3))
    end do
    if (present(body_mass) .and. present(union)) then
      if (union) then
        call body_union_moments(scene, bodies, ref, body_mass(first), status)
        if (status%stat /= demstep_stat%ok) return
      end if
    end if
    do b = 1, bodies%n
      bodies%com(:, b) = bodies%com(:, b) + scene%x(:, first(b))
    end do
    status%stat = demstep_stat%ok

  contains

    !> Members' masses from their body's: m_i = M r_i^3 / sum over the body
    !> of r^3.
    subroutine shared_mass(given, m, status)
      real(dp), intent(in) :: given(:)
      real(dp), intent(out) :: m(:)
      type(demstep_status_type), intent(out) :: status
      integer, allocatable :: one(:)
      real(dp), allocatable :: vol(:)
      if (size(given) /= scene%n) then
        call set_status(status, demstep_stat%invalid_input, "has "//int_text(size(given)) &
          //" values for "//int_text(scene%n)//" particles", where="body_mass")
        return
      end if
      allocate(vol(bodies%n), source=0.0_dp)
      allocate(one(bodies%n), source=0)
      do i = 1, scene%n
        b = bodies%body_of(i)
        if (.not. (ieee_is_finite(given(i)) .and. given(i) > 0.0_dp)) then
          call set_status(status, demstep_stat%invalid_input, "must be finite and > 0", where="body_mass", &
            index=i, subscript=.true.)
          return
        end if
        if (one(b) == 0) one(b) = i
        if (given(i) /= given(one(b))) then
          call set_status(status, demstep_stat%invalid_input, "differs from body_mass("//int_text(one(b)) &
            //") of the same body (a body's members carry its mass)", where="body_mass", index=i, &
            subscript=.true.)
          return
        end if
        vol(b) = vol(b) + scene%radius(i)**3
      end do
      do i = 1, scene%n
        m(i) = given(i)*scene%radius(i)**3/vol(bodies%body_of(i))
      end do
      status%stat = demstep_stat%ok
    end subroutine shared_mass
  end subroutine bodies_from_members

  !> Each body's centre of mass and inertia tensor as the union of its
  !> member spheres (`sphere_union_moments`) at one density, its mass
  !> `mass(b)`: com and the members' offsets from it replaced (com still
  !> relative to the body's first member, `ref` each member's position from
  !> it). Status: `sphere_union_moments`' with the body's index.
  subroutine body_union_moments(scene, bodies, ref, mass, status)
    type(scene_type), intent(in) :: scene
    type(body_set_type), intent(inout) :: bodies
    real(dp), intent(in) :: ref(:, :), mass(:)
    type(demstep_status_type), intent(out) :: status
    integer, allocatable :: start(:), list(:), fill(:)
    real(dp) :: volume, centroid(3), tensor(3, 3)
    integer :: i, b
    character(len=:), allocatable :: detail
    ! the members of body b: list(start(b):start(b + 1) - 1)
    allocate(start(bodies%n + 1), fill(bodies%n), list(scene%n))
    start(1) = 1
    do b = 1, bodies%n
      start(b + 1) = start(b) + bodies%members(b)
    end do
    fill(:) = start(:bodies%n)
    do i = 1, scene%n
      b = bodies%body_of(i)
      list(fill(b)) = i
      fill(b) = fill(b) + 1
    end do
    do b = 1, bodies%n
      associate (m => list(start(b):start(b + 1) - 1))
        call sphere_union_moments(ref(:, m), scene%radius(m), volume, centroid, tensor, status)
        if (status%stat /= demstep_stat%ok) then
          detail = status%message
          call set_status(status, demstep_stat%invalid_input, "body "//int_text(b)//": "//detail, &
            where="body_union")
          return
        end if
        bodies%com(:, b) = centroid
        bodies%inertia(:, :, b) = (mass(b)/volume)*tensor
        do i = 1, size(m)
          bodies%offset(:, m(i)) = ref(:, m(i)) - centroid
        end do
      end associate
    end do
    status%stat = demstep_stat%ok
  end subroutine body_union_moments

  !> Bodies from lists of members (`members(first(k):first(k+1)-1)` for body
  !> k), mass and inertia as `bodies_from_members`; particles in no list are
  !> bodies of their own. Status invalid_input naming `first` (not
  !> non-decreasing from 1 to size(members) + 1), `members` (a particle
  !> outside 1..n, or listed twice: in two bodies or twice in one), or the
  !> statuses of `bodies_from_members`.
  subroutine bodies_from_lists(scene, first, members, bodies, status, density)
    type(scene_type), intent(in) :: scene
    integer, intent(in) :: first(:), members(:)
    type(body_set_type), intent(out) :: bodies
    type(demstep_status_type), intent(out) :: status
    real(dp), intent(in), optional :: density
    integer, allocatable :: id(:)
    integer :: k, j, p
    if (size(first) < 1) then
      call set_status(status, demstep_stat%invalid_input, "needs at least one entry", where="first")
      return
    end if
    if (first(1) /= 1 .or. first(size(first)) /= size(members) + 1 .or. &
        any(first(2:) < first(:size(first) - 1))) then
      call set_status(status, demstep_stat%invalid_input, "must rise from 1 to size(members) + 1", &
        where="first")
      return
    end if
    if (size(first) - 1 > scene%n) then
      call set_status(status, demstep_stat%invalid_input, "more bodies than particles", where="first")
      return
    end if
    allocate(id(scene%n), source=0)
    do k = 1, size(first) - 1
      do j = first(k), first(k + 1) - 1
        p = members(j)
        if (p < 1 .or. p > scene%n) then
          call set_status(status, demstep_stat%invalid_input, "particle "//int_text(p) &
            //" is not in 1.."//int_text(scene%n), where="members", index=j, subscript=.true.)
          return
        end if
        if (id(p) /= 0) then
          call set_status(status, demstep_stat%invalid_input, "particle "//int_text(p) &
            //" is listed in body "//int_text(id(p))//" and again in body "//int_text(k), &
            where="members", index=j, subscript=.true.)
          return
        end if
        id(p) = k
      end do
    end do
    call bodies_from_members(scene, id, bodies, status, density)
  end subroutine bodies_from_lists

  !> Bodies with given mass, centre of mass and inertia tensor (global axes,
  !> about the centre of mass): body k (ids 1..size(mass), each with at least
  !> one member) holds the particles with body_of = k; particles with id 0
  !> are bodies of their own (numbered after). Status invalid_input naming
  !> `body_of`, `mass` (not finite and > 0), `com` (not finite), `inertia`
  !> (`check_inertia_tensor`) or `fixed`, with the body's index.
  subroutine bodies_given(scene, body_of, mass, com, inertia, bodies, status)
    type(scene_type), intent(in) :: scene
    integer, intent(in) :: body_of(:)
    real(dp), intent(in) :: mass(:), com(:, :), inertia(:, :, :)
    type(body_set_type), intent(out) :: bodies
    type(demstep_status_type), intent(out) :: status
    integer :: k, i, b, nb
    real(dp) :: d(3), eye(3, 3)
    integer :: ax
    character(len=:), allocatable :: detail
    nb = size(mass)
    if (size(com, 1) /= 3 .or. size(com, 2) /= nb .or. size(inertia, 1) /= 3 .or. size(inertia, 2) /= 3 &
        .or. size(inertia, 3) /= nb) then
      call set_status(status, demstep_stat%invalid_input, "need com(3, nb) and inertia(3, 3, nb) " &
        //"for nb = size(mass) bodies", where="inertia")
      return
    end if
    if (any(body_of > nb)) then
      call set_status(status, demstep_stat%invalid_input, "a body id above the "//int_text(nb) &
        //" bodies given", where="body_of", index=maxloc(body_of, 1), subscript=.true.)
      return
    end if
    call number_bodies(scene, body_of, bodies, status)
    if (status%stat /= demstep_stat%ok) return
    do k = 1, nb
      if (.not. any(body_of == k)) then
        call set_status(status, demstep_stat%invalid_input, "body "//int_text(k)//" has no member", &
          where="body_of")
        return
      end if
      if (.not. (ieee_is_finite(mass(k)) .and. mass(k) > 0.0_dp)) then
        call set_status(status, demstep_stat%invalid_input, "must be finite and > 0", where="mass", &
          index=k, subscript=.true.)
        return
      end if
      if (.not. all(ieee_is_finite(com(:, k)))) then
        call set_status(status, demstep_stat%invalid_input, "must be finite", where="com", index=k, &
          subscript=.true.)
        return
      end if
      call check_inertia_tensor(inertia(:, :, k), status)
      if (status%stat /= demstep_stat%ok) then
        detail = status%detail
        call set_status(status, demstep_stat%invalid_input, detail, where="inertia", index=k, &
          subscript=.true.)
        return
      end if
    end do
    eye = reshape([1.0_dp, 0.0_dp, 0.0_dp, 0.0_dp, 1.0_dp, 0.0_dp, 0.0_dp, 0.0_dp, 1.0_dp], [3, 3])
    allocate(bodies%mass(bodies%n), bodies%com(3, bodies%n), bodies%inertia(3, 3, bodies%n))
    ! ids 1..nb keep their number (number_bodies numbers in increasing id)
    bodies%mass(:nb) = mass
    bodies%com(:, :nb) = com
    bodies%inertia(:, :, :nb) = inertia
    do i = 1, scene%n
      b = bodies%body_of(i)
      if (b > nb) then
        bodies%mass(b) = scene%mass(i)
        bodies%com(:, b) = scene%x(:, i)
        bodies%inertia(:, :, b) = scene%inertia(i)*eye
      end if
      d = scene%x(:, i) - bodies%com(:, b)
      do ax = 1, 3
        if (scene%periodic(ax)) d(ax) = d(ax) - (scene%cell_hi(ax) - scene%cell_lo(ax)) &
          *anint(d(ax)/(scene%cell_hi(ax) - scene%cell_lo(ax)))
      end do
      bodies%offset(:, i) = d
    end do
    status%stat = demstep_stat%ok
  end subroutine bodies_given

  !> Whether `bodies` were made for this scene (one body per particle).
  !> Status invalid_input naming `bodies`.
  pure subroutine check_bodies(scene, bodies, status)
    type(scene_type), intent(in) :: scene
    type(body_set_type), intent(in) :: bodies
    type(demstep_status_type), intent(out) :: status
    if (.not. allocated(bodies%body_of)) then
      call set_status(status, demstep_stat%invalid_input, "no bodies given (see bodies_from_members)", &
        where="bodies")
    else if (size(bodies%body_of) /= scene%n) then
      call set_status(status, demstep_stat%invalid_input, "made for "//int_text(size(bodies%body_of)) &
        //" particles, the scene has "//int_text(scene%n), where="bodies")
    else
      status%stat = demstep_stat%ok
    end if
  end subroutine check_bodies

  !> An inertia tensor a body can have: finite, symmetric (to 1e-12 of its
  !> largest entry) and positive definite (each Cholesky pivot above
  !> `inertia_pivot_tolerance` of the largest diagonal entry). Status
  !> invalid_input with what is wrong (no `where`: the caller names it).
  pure subroutine check_inertia_tensor(t, status)
    real(dp), intent(in) :: t(3, 3)
    type(demstep_status_type), intent(out) :: status
    real(dp) :: l(3, 3), scale, p
    integer :: j, k
    if (.not. all(ieee_is_finite(t))) then
      call set_status(status, demstep_stat%invalid_input, "the inertia tensor must be finite")
      return
    end if
    scale = maxval(abs(t))
    if (any(abs(t - transpose(t)) > 1.0e-12_dp*scale)) then
      call set_status(status, demstep_stat%invalid_input, "the inertia tensor must be symmetric")
      return
    end if
    ! Cholesky, pivot by pivot
    l = 0.0_dp
    do j = 1, 3
      p = t(j, j) - sum(l(j, :j - 1)**2)
      if (.not. p > inertia_pivot_tolerance*maxval([(t(k, k), k = 1, 3)])) then
        call set_status(status, demstep_stat%invalid_input, "the inertia tensor is singular or not " &
          //"positive definite (a body must resist rotation about every axis)")
        return
      end if
      l(j, j) = sqrt(p)
      do k = j + 1, 3
        l(k, j) = (t(k, j) - sum(l(k, :j - 1)*l(j, :j - 1)))/l(j, j)
      end do
    end do
    status%stat = demstep_stat%ok
  end subroutine check_inertia_tensor

  !> Number the bodies from ids (0: alone; the positive ids in increasing
  !> order, then one body per lone particle), allocate the per-particle arrays
  !> and the fixed flags. O(n log n) (the ids sorted). Status invalid_input
  !> naming `body_of` or `fixed`.
  subroutine number_bodies(scene, body_of, bodies, status)
    type(scene_type), intent(in) :: scene
    integer, intent(in) :: body_of(:)
    type(body_set_type), intent(inout) :: bodies
    type(demstep_status_type), intent(out) :: status
    integer, allocatable :: ids(:)
    integer :: i, k, b, nu
    if (size(body_of) /= scene%n) then
      call set_status(status, demstep_stat%invalid_input, "needs one entry per particle ("// &
        int_text(scene%n)//"), has "//int_text(size(body_of)), where="body_of")
      return
    end if
    do i = 1, scene%n
      if (body_of(i) < 0) then
        call set_status(status, demstep_stat%invalid_input, "a body id is 0 (alone) or positive", &
          where="body_of", index=i, subscript=.true.)
        return
      end if
    end do
    ! the distinct positive ids, ascending
    ids = pack(body_of, body_of > 0)
    call heap_sort(ids)
    nu = 0
    do i = 1, size(ids)
      if (nu > 0) then
        if (ids(i) == ids(nu)) cycle
      end if
      nu = nu + 1
      ids(nu) = ids(i)
    end do
    allocate(bodies%body_of(scene%n), bodies%offset(3, scene%n))
    bodies%offset = 0.0_dp
    k = nu
    do i = 1, scene%n
      if (body_of(i) > 0) then
        ! (ids(:nu) distinct and ascending, holding body_of(i))
        bodies%body_of(i) = count_before(ids(:nu), body_of(i), .false.) + 1
      else
        k = k + 1
        bodies%body_of(i) = k
      end if
    end do
    bodies%n = k
    allocate(bodies%fixed(k), source=.false.)
    allocate(bodies%members(k), source=0)
    do i = 1, scene%n
      b = bodies%body_of(i)
      bodies%members(b) = bodies%members(b) + 1
      if (scene%fixed(i)) bodies%fixed(b) = .true.
    end do
    do i = 1, scene%n
      b = bodies%body_of(i)
      if (bodies%fixed(b) .neqv. scene%fixed(i)) then
        call set_status(status, demstep_stat%invalid_input, "body "//int_text(b)//" has fixed and " &
          //"free members (fix all of a body's members or none)", where="fixed", index=i, subscript=.true.)
        return
      end if
    end do
    status%stat = demstep_stat%ok
  end subroutine number_bodies

end module demstep_bodies
