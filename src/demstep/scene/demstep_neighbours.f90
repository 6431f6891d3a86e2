!> Neighbour search: the particle contacts of a scene's current configuration,
!> found with a cell list (periodic axes wrap around, distances by minimum
!> image) or taken from the scene's explicit contact list, and the wall
!> contacts. Lists grow by doubling (amortised constant cost per contact).
module demstep_neighbours
  use demstep_kinds, only: dp, i8
  use demstep_sort, only: radix_sort
  use demstep_status, only: demstep_status_type, demstep_stat, set_status
  use demstep_text, only: int_text
  use demstep_interaction, only: wall_overlap
  use demstep_scene_data, only: scene_type, branch_vector
  use, intrinsic :: ieee_arithmetic, only: ieee_is_finite
  implicit none
  private

  public :: prepare_search, find_contacts, find_wall_contacts, search_trouble, contact_list, spatial_order

  !> Most particle contacts a search may detect at once (about 1 GB of contact
  !> data in the analysis; a DEM packing has a few per particle). A given
  !> contact list is not limited: its rows bound its contacts.
  integer, parameter, public :: contact_limit = 10000000
  !> At most this many of the largest particles are searched against every
  !> particle instead of sizing the cells (a few giants must not put every
  !> particle into one cell).
  integer, parameter :: n_giants = 16
  !> Rows of an explicit contact list per block of `listed_contacts` (blocks
  !> run in parallel; the result does not depend on it).
  integer, parameter :: list_block = 32768

  !> The contact lists of one configuration and the search's scratch.
  !> Values of a contact's history: shear displacement and relative rotation.
  integer, parameter, public :: history_size = 6

  type, public :: search_type
    !> Particle contacts: i < j (or the explicit list's order), unit normal i to j
    !> (minimum image), overlap, branch length, row of the explicit list (0:
    !> detected), the stepper's history: shear displacement (1:3) and relative
    !> rotation (4:6).
    integer :: n_pairs = 0
    integer, allocatable :: pair_i(:), pair_j(:), pair_c(:)
    real(dp), allocatable :: pair_n(:, :), pair_d(:), pair_l(:), pair_us(:, :)
    !> Wall contacts: particle, wall, overlap.
    integer :: n_walls = 0
    integer, allocatable :: wall_i(:), wall_k(:)
    real(dp), allocatable :: wall_d(:)
    real(dp) :: max_overlap = 0.0_dp
    integer :: max_contacts = 0
    integer, allocatable :: cell_start(:), cell_particle(:), cell_of(:)
    !> Cell width before coarsening: twice the largest radius of a non-giant.
    real(dp) :: cell_width = 0.0_dp
    !> Giants: particles searched against all others, not put into cells.
    integer, allocatable :: giants(:)
    logical, allocatable :: is_giant(:)
    !> The first pair found at the same point, and whether contact_limit was hit.
    integer :: coincident(2) = 0
    logical :: too_many = .false.
  end type search_type

contains

  !> Allocate the lists; split off the giants (radius above twice the
  !> (n_giants+1)-th largest) and size the cells for the rest.
  subroutine prepare_search(scene, s)
    type(scene_type), intent(in) :: scene
    type(search_type), intent(out) :: s
    real(dp) :: top(n_giants + 1)
    integer :: i, k, m
    allocate(s%pair_i(64), s%pair_j(64), s%pair_c(64), s%pair_n(3, 64), s%pair_d(64), &
      s%pair_l(64), s%pair_us(history_size, 64))
    allocate(s%wall_i(16), s%wall_k(16), s%wall_d(16))
    ! the m largest radii, descending (insertion into a short list: linear in n)
    m = min(scene%n, n_giants + 1)
    top = -1.0_dp
    do i = 1, scene%n
      if (scene%radius(i) <= top(max(m, 1))) cycle
      k = m
      do while (k > 1)
        if (top(k - 1) >= scene%radius(i)) exit
        top(k) = top(k - 1)
        k = k - 1
      end do
      top(k) = scene%radius(i)
    end do
    allocate(s%is_giant(scene%n))
    if (m > n_giants) then
      s%is_giant = scene%radius > 2.0_dp*top(m)
    else
      s%is_giant = .false.
    end if
    s%giants = pack([(i, i = 1, scene%n)], s%is_giant)
    s%cell_width = 0.0_dp
    do i = 1, scene%n
      if (.not. s%is_giant(i)) s%cell_width = max(s%cell_width, 2.0_dp*scene%radius(i))
    end do
  end subroutine prepare_search

  !> The search's refusals as a status: coincident particles, too many contacts.
  subroutine search_trouble(s, status)
    type(search_type), intent(in) :: s
    type(demstep_status_type), intent(out) :: status
    if (s%coincident(1) > 0) then
      call set_status(status, demstep_stat%invalid_input, "particles "// &
        int_text(s%coincident(1))//" and "//int_text(s%coincident(2))//" are at the same " &
        //"point (their contact normal is undefined)", where="position")
    else if (s%too_many) then
      call set_status(status, demstep_stat%invalid_input, "more than "// &
        int_text(contact_limit)//" particle contacts (the limit; the particles overlap far more than " &
        //"in a DEM packing)", where="position")
    else
      status%stat = demstep_stat%ok
    end if
  end subroutine search_trouble

  !> The overlapping particle pairs of the current configuration: particles
  !> i(k), j(k), unit normal n(:, k) from i to j (nearest image), overlap d(k),
  !> and (optional) the row of the explicit contact list c(k) (0: detected).
  !> Status (when present) `invalid_input` for coincident particles or more
  !> than `contact_limit` contacts (the lists then hold what was found).
  subroutine contact_list(scene, i, j, n, d, status, c)
    type(scene_type), intent(in) :: scene
    integer, allocatable, intent(out) :: i(:), j(:)
    real(dp), allocatable, intent(out) :: n(:, :), d(:)
    type(demstep_status_type), intent(out), optional :: status
    integer, allocatable, intent(out), optional :: c(:)
    type(search_type) :: s
    integer, allocatable :: rows(:)
    if (scene%given_contacts) then
      ! (the explicit list in parallel, straight into the result: no search's
      ! lists and histories)
      call listed_contacts(scene, i, j, n, d, rows, s%coincident)
      if (present(c)) call move_alloc(rows, c)
      if (present(status)) call search_trouble(s, status)
      return
    end if
    call prepare_search(scene, s)
    call find_contacts(scene, s)
    i = s%pair_i(:s%n_pairs)
    j = s%pair_j(:s%n_pairs)
    n = s%pair_n(:, :s%n_pairs)
    d = s%pair_d(:s%n_pairs)
    if (present(c)) c = s%pair_c(:s%n_pairs)
    if (present(status)) call search_trouble(s, status)
  end subroutine contact_list

  !> The explicit contact list's overlapping rows, in list order, as
  !> `contact_list` gives them (rows c(k)), and the first pair of the list at
  !> the same point (`coincident`, 0 if none; not a contact). Blocks of
  !> `list_block` rows in parallel, each row's contact at the row's own place
  !> (the same pairs and bits as `try_pair` row by row); only when some rows
  !> are not contacts are the contacts then moved up to their places in the
  !> result (a given list is usually all contacts).
  subroutine listed_contacts(scene, i, j, n, d, c, coincident)
    type(scene_type), intent(in) :: scene
    integer, allocatable, intent(out) :: i(:), j(:), c(:)
    real(dp), allocatable, intent(out) :: n(:, :), d(:)
    integer, intent(inout) :: coincident(2)
    integer, allocatable :: start(:), same(:), ti(:), tj(:), tc(:)
    real(dp), allocatable :: tn(:, :), td(:)
    real(dp) :: dist
    integer :: nk, nb, b, k, p
    logical :: touching
    nk = size(scene%contact_pairs, 2)
    nb = (nk + list_block - 1)/list_block
    allocate(start(nb + 1), same(nb), i(nk), j(nk), c(nk), n(3, nk), d(nk))
    start(1) = 1
    !$omp parallel do private(b, k, p, touching, dist) schedule(static) if(nb > 1)
    do b = 1, nb
      p = 0
      same(b) = 0
      do k = (b - 1)*list_block + 1, min(nk, b*list_block)
        i(k) = scene%contact_pairs(1, k)
        j(k) = scene%contact_pairs(2, k)
        call pair_geometry(scene, i(k), j(k), touching, n(:, k), d(k), dist)
        c(k) = 0
        if (.not. touching) cycle
        if (.not. dist > 0.0_dp) then
          if (same(b) == 0) same(b) = k
          cycle
        end if
        c(k) = k
        p = p + 1
      end do
      start(b + 1) = p
    end do
    !$omp end parallel do
    do b = 1, nb
      start(b + 1) = start(b + 1) + start(b)
      if (same(b) == 0 .or. coincident(1) /= 0) cycle
      coincident = scene%contact_pairs(:, same(b))
    end do
    if (start(nb + 1) - 1 == nk) return
    ! some rows are not contacts: each block's contacts moved to their places
    p = start(nb + 1) - 1
    allocate(ti(p), tj(p), tc(p), tn(3, p), td(p))
    !$omp parallel do private(b, k, p) schedule(static) if(nb > 1)
    do b = 1, nb
      p = start(b)
      do k = (b - 1)*list_block + 1, min(nk, b*list_block)
        if (c(k) == 0) cycle
        ti(p) = i(k)
        tj(p) = j(k)
        tc(p) = k
        tn(:, p) = n(:, k)
        td(p) = d(k)
        p = p + 1
      end do
    end do
    !$omp end parallel do
    call move_alloc(ti, i)
    call move_alloc(tj, j)
    call move_alloc(tc, c)
    call move_alloc(tn, n)
    call move_alloc(td, d)
  end subroutine listed_contacts

  !> The particle contact list: the explicit list's overlapping rows, or every
  !> pair of overlapping particles found with a cell list (cells at least one
  !> non-giant diameter wide, at most about 4 per particle; periodic axes wrap)
  !> and the giants against every particle, in time linear in n plus the pairs
  !> of neighbouring cells. Pairs at the same point are not contacts (the normal
  !> is undefined): the first is recorded in s%coincident. The search stops at
  !> `contact_limit` detected contacts (s%too_many; a given list is not
  !> limited). Shear histories start at zero.
  subroutine find_contacts(scene, s)
    type(scene_type), intent(in) :: scene
    type(search_type), intent(inout) :: s
    integer :: dim, n, i, j, c, k, ncell(3), idx(3), a, b, cc, p, g, n_cells, ax
    integer :: lo(3), hi(3), ca(3)
    real(dp) :: xmin(3), xmax(3), h, d(3), width(3)
    logical :: wrap(3), any_wrap
    dim = scene%dim
    n = scene%n
    s%n_pairs = 0
    s%coincident = 0
    s%too_many = .false.
    if (scene%given_contacts) then
      ! (a given list bounds its contacts itself: room for all its rows at
      ! once, memory linear in the list, and no contact_limit)
      call reserve_pairs(s, size(scene%contact_pairs, 2))
      do k = 1, size(scene%contact_pairs, 2)
        call try_pair(scene, s, scene%contact_pairs(1, k), scene%contact_pairs(2, k), k)
      end do
      s%max_contacts = max(s%max_contacts, s%n_pairs + s%n_walls)
      return
    end if
    if (n < 2) return
    xmin = 0.0_dp
    xmax = 0.0_dp
    xmin(:dim) = minval(scene%x(:dim, :), dim=2)
    xmax(:dim) = maxval(scene%x(:dim, :), dim=2)
    ! a blown-up state has no contacts to find; the run's energy check reports it
    if (.not. all(ieee_is_finite(xmax(:dim) - xmin(:dim)))) return
    wrap = scene%periodic
    any_wrap = any(wrap)
    where (wrap)
      xmin = scene%cell_lo
      xmax = scene%cell_hi
    end where
    h = s%cell_width
    ! no more cells than about 4 per particle: coarser cells only cost more pairs
    do while (product(max(1.0_dp, (xmax(:dim) - xmin(:dim))/h + 1.0_dp)) > 4.0_dp*n + 64.0_dp)
      h = 2.0_dp*h
    end do
    ncell = 1
    width = h
    do ax = 1, dim
      if (wrap(ax)) then
        ! whole cells across the period, each at least h wide
        ncell(ax) = max(1, int((xmax(ax) - xmin(ax))/h))
        width(ax) = (xmax(ax) - xmin(ax))/ncell(ax)
      else
        ncell(ax) = max(1, int((xmax(ax) - xmin(ax))/h) + 1)
      end if
    end do
    n_cells = product(ncell)
    if (.not. allocated(s%cell_of)) allocate(s%cell_of(n), s%cell_particle(n))
    if (allocated(s%cell_start)) then
      if (size(s%cell_start) < n_cells + 1) deallocate(s%cell_start)
    end if
    if (.not. allocated(s%cell_start)) allocate(s%cell_start(n_cells + 1))
    ! counting sort of the non-giants by cell
    s%cell_start(:n_cells + 1) = 0
    do i = 1, n
      if (s%is_giant(i)) cycle
      idx = 0
      idx(:dim) = max(0, min(ncell(:dim) - 1, int((scene%x(:dim, i) - xmin(:dim))/width(:dim))))
      c = 1 + idx(1) + ncell(1)*(idx(2) + ncell(2)*idx(3))
      s%cell_of(i) = c
      s%cell_start(c + 1) = s%cell_start(c + 1) + 1
    end do
    s%cell_start(1) = 1
    do c = 2, n_cells + 1
      s%cell_start(c) = s%cell_start(c) + s%cell_start(c - 1)
    end do
    do i = 1, n
      if (s%is_giant(i)) cycle
      c = s%cell_of(i)
      s%cell_particle(s%cell_start(c)) = i
      s%cell_start(c) = s%cell_start(c) + 1
    end do
    do c = n_cells, 1, -1
      s%cell_start(c + 1) = s%cell_start(c)
    end do
    s%cell_start(1) = 1
    ! every non-giant against the non-giants of its own and the neighbouring cells
    particles: do i = 1, n
      if (s%is_giant(i)) cycle
      c = s%cell_of(i) - 1
      idx(1) = mod(c, ncell(1))
      idx(2) = mod(c/ncell(1), ncell(2))
      idx(3) = c/(ncell(1)*ncell(2))
      ! neighbour offsets: -1 to 1 clipped at the ends, or around a periodic
      ! axis (each cell once: 0 only with 1 cell, 0 and 1 with 2)
      do ax = 1, 3
        if (wrap(ax)) then
          lo(ax) = merge(-1, 0, ncell(ax) >= 3)
          hi(ax) = merge(1, 0, ncell(ax) >= 2)
        else
          lo(ax) = max(-1, -idx(ax))
          hi(ax) = min(1, ncell(ax) - 1 - idx(ax))
        end if
      end do
      do a = lo(3), hi(3)
        ca(3) = wrapped(idx(3) + a, ncell(3))
        do b = lo(2), hi(2)
          ca(2) = wrapped(idx(2) + b, ncell(2))
          do cc = lo(1), hi(1)
            ca(1) = wrapped(idx(1) + cc, ncell(1))
            k = 1 + ca(1) + ncell(1)*(ca(2) + ncell(2)*ca(3))
            do p = s%cell_start(k), s%cell_start(k + 1) - 1
              j = s%cell_particle(p)
              if (j <= i) cycle
              ! the distance test inline (the hot loop); try_pair for the hits
              d = scene%x(:, j) - scene%x(:, i)
              if (any_wrap) d = branch_vector(scene, i, j)
              if (d(1)**2 + d(2)**2 + d(3)**2 >= (scene%radius(i) + scene%radius(j))**2) cycle
              call try_pair(scene, s, i, j, 0)
              if (s%too_many) exit particles
            end do
          end do
        end do
      end do
    end do particles
    ! every giant against every other particle (a pair of giants once)
    giants: do g = 1, size(s%giants)
      i = s%giants(g)
      do j = 1, n
        if (j == i) cycle
        if (s%is_giant(j) .and. j < i) cycle
        call try_pair(scene, s, min(i, j), max(i, j), 0)
        if (s%too_many) exit giants
      end do
    end do giants
    s%max_contacts = max(s%max_contacts, s%n_pairs + s%n_walls)
  end subroutine find_contacts

  !> Cell coordinate c in 0 to n-1, from -1 to n (wrapping around).
  elemental integer function wrapped(c, n)
    integer, intent(in) :: c, n
    wrapped = c
    if (c < 0) wrapped = c + n
    if (c >= n) wrapped = c - n
  end function wrapped

  !> Add the pair (i, j) to the contact list if the particles overlap (nearest image).
  subroutine try_pair(scene, s, i, j, c)
    type(scene_type), intent(in) :: scene
    type(search_type), intent(inout) :: s
    integer, intent(in) :: i, j, c
    real(dp) :: normal(3), overlap, dist
    logical :: touching
    call pair_geometry(scene, i, j, touching, normal, overlap, dist)
    if (.not. touching) return
    if (.not. dist > 0.0_dp) then
      if (s%coincident(1) == 0) s%coincident = [i, j]
      return
    end if
    call add_pair(s, i, j, c, normal, overlap, dist)
  end subroutine try_pair

  !> Whether particles i and j overlap (nearest image), and then their
  !> distance and, when it is above 0, the unit normal i to j and the overlap.
  pure subroutine pair_geometry(scene, i, j, touching, normal, overlap, dist)
    type(scene_type), intent(in) :: scene
    integer, intent(in) :: i, j
    logical, intent(out) :: touching
    real(dp), intent(out) :: normal(3), overlap, dist
    real(dp) :: d(3), reach
    d = branch_vector(scene, i, j)
    reach = scene%radius(i) + scene%radius(j)
    normal = 0.0_dp
    overlap = 0.0_dp
    dist = 0.0_dp
    ! (a NaN distance is not a miss: it goes on to the same-point test)
    touching = .not. d(1)**2 + d(2)**2 + d(3)**2 >= reach**2
    if (.not. touching) return
    dist = norm2(d)
    if (.not. dist > 0.0_dp) return
    normal = d/dist
    overlap = reach - dist
  end subroutine pair_geometry

  subroutine add_pair(s, i, j, c, normal, overlap, dist)
    type(search_type), intent(inout) :: s
    integer, intent(in) :: i, j, c
    real(dp), intent(in) :: normal(3), overlap, dist
    integer :: m
    integer, allocatable :: ti(:), tj(:), tc(:)
    real(dp), allocatable :: td(:), tl(:), tn(:, :), tu(:, :)
    if (s%n_pairs == size(s%pair_i)) then
      ! (the room only grows to contact_limit: a given list has room for all its rows)
      if (s%n_pairs >= contact_limit) then
        s%too_many = .true.
        return
      end if
      ! double the capacity: amortised constant cost per pair
      m = min(2*size(s%pair_i), contact_limit)
      allocate(ti(m), tj(m), tc(m), td(m), tl(m), tn(3, m), tu(history_size, m))
      ti(:s%n_pairs) = s%pair_i
      tj(:s%n_pairs) = s%pair_j
      tc(:s%n_pairs) = s%pair_c
      td(:s%n_pairs) = s%pair_d
      tl(:s%n_pairs) = s%pair_l
      tn(:, :s%n_pairs) = s%pair_n
      tu(:, :s%n_pairs) = s%pair_us
      call move_alloc(ti, s%pair_i)
      call move_alloc(tj, s%pair_j)
      call move_alloc(tc, s%pair_c)
      call move_alloc(td, s%pair_d)
      call move_alloc(tl, s%pair_l)
      call move_alloc(tn, s%pair_n)
      call move_alloc(tu, s%pair_us)
    end if
    s%n_pairs = s%n_pairs + 1
    s%pair_i(s%n_pairs) = i
    s%pair_j(s%n_pairs) = j
    s%pair_c(s%n_pairs) = c
    s%pair_n(:, s%n_pairs) = normal
    s%pair_d(s%n_pairs) = overlap
    s%pair_l(s%n_pairs) = dist
    s%pair_us(:, s%n_pairs) = 0.0_dp
    s%max_overlap = max(s%max_overlap, overlap)
  end subroutine add_pair

  !> Room for at least m particle contacts (the lists' contents are not kept:
  !> call it with no contacts listed).
  subroutine reserve_pairs(s, m)
    type(search_type), intent(inout) :: s
    integer, intent(in) :: m
    if (size(s%pair_i) >= m) return
    deallocate(s%pair_i, s%pair_j, s%pair_c, s%pair_n, s%pair_d, s%pair_l, s%pair_us)
    allocate(s%pair_i(m), s%pair_j(m), s%pair_c(m), s%pair_n(3, m), s%pair_d(m), s%pair_l(m), &
      s%pair_us(history_size, m))
  end subroutine reserve_pairs

  !> The wall contact list: particles overlapping a wall.
  subroutine find_wall_contacts(scene, s)
    type(scene_type), intent(in) :: scene
    type(search_type), intent(inout) :: s
    integer :: i, w
    real(dp) :: overlap
    s%n_walls = 0
    do w = 1, size(scene%wall_normal, 2)
      do i = 1, scene%n
        overlap = wall_overlap(scene%x(:, i), scene%radius(i), scene%wall_point(:, w), scene%wall_normal(:, w))
        ! (a NaN overlap, after a blow-up, is no contact)
        if (overlap > 0.0_dp) then
          if (s%n_walls == size(s%wall_i)) call grow_walls(s)
          s%n_walls = s%n_walls + 1
          s%wall_i(s%n_walls) = i
          s%wall_k(s%n_walls) = w
          s%wall_d(s%n_walls) = overlap
          s%max_overlap = max(s%max_overlap, overlap)
        end if
      end do
    end do
    s%max_contacts = max(s%max_contacts, s%n_pairs + s%n_walls)
  end subroutine find_wall_contacts

  !> Double the capacity of the wall contact list (amortised constant cost).
  subroutine grow_walls(s)
    type(search_type), intent(inout) :: s
    integer, allocatable :: ti(:), tk(:)
    real(dp), allocatable :: td(:)
    integer :: m
    m = 2*size(s%wall_i)
    allocate(ti(m), tk(m), td(m))
    ti(:s%n_walls) = s%wall_i(:s%n_walls)
    tk(:s%n_walls) = s%wall_k(:s%n_walls)
    td(:s%n_walls) = s%wall_d(:s%n_walls)
    call move_alloc(ti, s%wall_i)
    call move_alloc(tk, s%wall_k)
    call move_alloc(td, s%wall_d)
  end subroutine grow_walls

  !> The points picked (`pick`, default all) in the order of a Z-order
  !> (Morton) curve through their bounding box: points near in space come
  !> near in the list, and a run of consecutive points fills a compact
  !> region (a locality order for the operator's blocks of bodies). Each
  !> axis is cut into 2^b cells, b as many bits as the key leaves beside the
  !> point's index (14 bits at 1e6 points in 3D); points in one cell keep
  !> their index order. x(dim, n), dim 1 to 3, finite. O(n) (a radix sort).
  function spatial_order(x, pick) result(order)
    real(dp), intent(in) :: x(:, :)
    logical, intent(in), optional :: pick(:)
    integer, allocatable :: order(:)
    integer(i8), allocatable :: key(:)
    real(dp) :: lo(3), span(3), cells
    integer(i8) :: code, q(3), mask
    integer :: dim, n, m, i, k, c, bits, index_bits
    dim = min(3, size(x, 1))
    n = size(x, 2)
    m = n
    if (present(pick)) m = count(pick)
    allocate(order(m), key(m))
    if (m == 0) return
    ! the index in the low bits, the curve's code above it (63 bits in all)
    index_bits = 1
    do while (2_i8**index_bits < int(n, i8))
      index_bits = index_bits + 1
    end do
    bits = min(20, (62 - index_bits)/max(dim, 1))
    cells = real(2_i8**bits - 1, dp)
    lo = 0.0_dp
    span = 0.0_dp
    do c = 1, dim
      lo(c) = huge(1.0_dp)
      span(c) = -huge(1.0_dp)
      do i = 1, n
        if (present(pick)) then
          if (.not. pick(i)) cycle
        end if
        lo(c) = min(lo(c), x(c, i))
        span(c) = max(span(c), x(c, i))
      end do
      span(c) = span(c) - lo(c)
    end do
    mask = 2_i8**index_bits - 1
    k = 0
    do i = 1, n
      if (present(pick)) then
        if (.not. pick(i)) cycle
      end if
      k = k + 1
      q = 0
      do c = 1, dim
        if (span(c) > 0.0_dp) q(c) = int(min(cells, max(0.0_dp, (x(c, i) - lo(c))/span(c)*cells)), i8)
      end do
      ! the cell's bits interleaved, the highest first
      code = 0
      do c = bits - 1, 0, -1
        code = ishft(code, dim)
        if (dim >= 3) code = ior(code, ishft(iand(ishft(q(3), -c), 1_i8), 2))
        if (dim >= 2) code = ior(code, ishft(iand(ishft(q(2), -c), 1_i8), 1))
        code = ior(code, iand(ishft(q(1), -c), 1_i8))
      end do
      key(k) = ior(ishft(code, index_bits), int(i - 1, i8))
    end do
    call radix_sort(key)
    do k = 1, m
      order(k) = int(iand(key(k), mask)) + 1
    end do
  end function spatial_order

end module demstep_neighbours
