!> A scene read and held in parts on MPI ranks (distributed input), and its
!> critical time steps: no rank ever holds the whole particles or contacts
!> table, nor the whole scene.
!>
!> Ownership: slabs. The particles are cut into slabs along the axis on
!> which the free ones spread furthest (`slab_axis`, the replicated path's
!> rule), one per rank in rank order, balanced by count (or as the caller
!> gives the counts): ordered by (coordinate, file number), the slabs are
!> consecutive runs of that order. The cuts are found without gathering the
!> scene: a bisection on the coordinate (as an ordered 64-bit key) and then
!> on the file number among equal coordinates, every cut at once, each round
!> a binary search per cut in each rank's sorted keys and one
!> `MPI_Allreduce` (`slab_owners`). A contact belongs to the owner of its
!> first particle. Each rank holds its
!> own particles (in file order), every contact that touches one of them
!> (the contacts of its own first particles, then the others, each in file
!> order) and the partners of those contacts it does not own (the halo: the
!> particles across its slab's faces, the periodic ones included), in a
!> scene of its own: own particles first, then the halo by owner in rank
!> order, each owner's in file order (so its free bodies' rows ascend, as
!> the halo exchange takes them).
!>
!> Reading (`mpi_read_scene`). Each rank reads one byte range of each table
!> (`read_table_part`) and checks its rows there, numbered as in the file
!> (the checks are the serial `scene_from_input`'s, in the same order; the
!> refusal reported is the one the serial reader reports, the same on every
!> rank: `agree_status`). It then sends each particle row, with its file
!> number, to its slab's rank (`MPI_Alltoallv`), asks the rank that read
!> each contact's particles for their places (a particle's place: its
!> number when the ranks' own particles are listed in rank order, each
!> rank's in file order, so it tells the owner and the particle's number
!> there without a search), sends each contact row with its two places to
!> the ranks of its two particles, and asks the owners of its halo
!> particles for their rows. No rank holds more than its byte ranges, its
!> rows, its part and one place per row it read.
!>
!> The operator. The free bodies are numbered slab by slab in rank order,
!> in file order within a slab (in file order over the whole scene when the
!> file lists the particles in slab order), so each rank's own bodies are
!> one block of rows. (The Lanczos start vectors, and the certificate's
!> Gaussian start, are entered by row number, as on the replicated path:
!> another numbering than the serial path's file order gives another draw
!> of the same fixed sequences, the same stopping rules and error bars, an
!> answer equal to the serial one within the tolerance.) Each
!> rank builds the serial matrix-free operator (`operator_from_springs`) of
!> its part, scaled by the whole scene's largest stiffness and smallest mass
!> (the serial scaling), and a product y = M^-1/2 K M^-1/2 x is one halo
!> exchange of x (`dist_halo_exchange`) and the serial product on the part,
!> of which the own rows are kept. PARPACK runs over the ranks that own free
!> bodies (a rank without any waits and gets the result).
!>
!> Memory per rank: its particles and halo (the scene and the part's numbers:
!> about 110 bytes each), its contacts (about 80 bytes each in the scene,
!> 136 as springs while the operator is built, 192 in the operator), each
!> free body's operator arrays (about 110 bytes with 6 dof) and its two
!> halo-extended vectors (96 bytes), the Lanczos run's vectors of its rows
!> (at most seven: the recurrence's three, the Ritz vector, two more for
!> its second pass, the eigenvector returned; more only where all the
!> certificate's steps fit in `lanczos_store_bytes` at the global order)
!> and, while reading, its byte ranges of the files and their rows. With
!> `release` (as `mpi_files_critical_steps` runs) the positions and
!> contacts go once the springs are built, and the springs once the
!> operator is. Measured (`mpi/example/mpi_files`, 6 dof and 3 contacts per
!> particle, 2 ranks, tolerance 1e-6): 3.39 kB per own particle at 1e6
!> particles (the Lanczos vectors kept in single precision 2.2 kB of it) and
!> 1.18 kB at 1e7 (5.5 GiB per rank; none kept), the fixed 27 MiB per rank
!> included.
module demstep_mpi_dist_scene
  use mpi_f08
  use demstep_kinds, only: dp, i8
  use demstep_status, only: demstep_status_type, demstep_stat, set_status, status_restate
  use demstep_text, only: int_text
  use demstep_progress, only: progress_type
  use demstep_scene_data, only: scene_type, scene_effect, has_tangential, branch_vector
  use demstep_scene_builders, only: new_scene, scene_set_cell, scene_set_contacts, contact_rows_check
  use demstep_scene_input, only: scene_input_type, particle_columns, particles_from_rows, scene_input_check_dim, &
    contact_columns, scene_input_effects, scene_input_damping
  use demstep_interaction, only: dof_components
  use demstep_neighbours, only: search_type, search_trouble
  use demstep_assembly, only: assembly_operator_type, assembly_operator, assembly_operator_apply, &
    assembly_check_options, assembly_set_bound, assembly_set_springs, &
    critical_step_type, eigen_solver, scene_lanczos_ncv, scene_lanczos_restarts, bound_iterations, &
    damped_problem_type, damped_newton, spring_block_type, linearise, &
    operator_from_springs, operator_abs_product, operator_mix, dof_masses, hertz_linearization
  use demstep_lanczos, only: eigen_result_type, lanczos_tolerance_default
  use demstep_mpi_lanczos, only: dist_operator_type, dist_halo_type, dist_halo_create, &
    dist_halo_exchange, dist_halo_free, parallel_lanczos_largest, offsets_of
  use demstep_mpi_scene, only: slab_axis, mpi_lanczos_estimates, mpi_damped_solve_done, mpi_damped_lanczos
  use demstep_sort, only: heap_sort, radix_sort, count_before
  use demstep_mpi_parts, only: read_table_part, agree_status, broadcast_status, no_fault
  implicit none
  private

  public :: mpi_read_scene, mpi_part_critical_steps, mpi_files_critical_steps, dist_scene_bytes, &
    slab_owners, ordered_key

  !> This rank's part of a scene read in parts.
  type, public :: dist_scene_part_type
    !> Particles of the whole scene; the axis of the slabs (1 to 3).
    integer :: n_particles = 0, axis = 1
    !> Own particles: the first n_own of the part's scene; the halo follows.
    integer :: n_own = 0
    !> The part: own particles, halo, the contacts touching own particles.
    type(scene_type) :: scene
    !> File number of each of the part's particles; free-body number of each
    !> (file order over the whole scene; 0: fixed).
    integer, allocatable :: global(:), body(:)
    !> Row of each of the part's contacts in the contacts file (1-based).
    integer, allocatable :: contact_row(:)
    !> Its positions, velocities and contacts were released by a solve with
    !> `release`: no further solve (read the scene again).
    logical :: released = .false.
  end type dist_scene_part_type

  !> The distributed operator A' = M'^-1/2 K' M'^-1/2 of a part: the serial
  !> operator of the part (own bodies first) and the halo exchange.
  type, extends(dist_operator_type) :: dist_scene_operator_type
    type(assembly_operator_type) :: op
    type(dist_halo_type) :: halo
    real(dp), allocatable :: x_ext(:), y_ext(:)
  contains
    procedure :: apply => scene_operator_apply
  end type dist_scene_operator_type

  !> The distributed damped-limit problem: the operator mixed per tau.
  type, extends(damped_problem_type) :: part_damped_type
    type(dist_scene_operator_type), pointer :: dop => null()
    real(dp), allocatable :: vec(:)
  contains
    procedure :: top => part_damped_top
  end type part_damped_type

contains

  !> Read the scene an input describes in parts (see the module's notes):
  !> `particles_file` and `contacts_file` (both required), `dim`, the
  !> periodic cell, `effects` and the dashpots. Collective; the same status
  !> on every rank: the serial reader's (`scene_from_input`) for the same
  !> input, or invalid_input naming an input component the distributed
  !> reader does not read, or `owned`.
  subroutine mpi_read_scene(comm, input, part, status, owned)
    type(MPI_Comm), intent(in) :: comm
    type(scene_input_type), intent(in) :: input
    type(dist_scene_part_type), intent(out) :: part
    type(demstep_status_type), intent(out) :: status
    !> Particles owned by each rank: the slabs' counts, in rank order,
    !> summing to the particles read; default: as equal as can be.
    integer, intent(in), optional :: owned(:)
    type(scene_type) :: probe
    type(demstep_status_type) :: st
    real(dp), allocatable :: rows(:, :), own_rows(:, :), halo_rows(:, :), x(:, :), v(:, :), m(:), &
      r(:), inertia(:), contacts(:, :), mine(:, :), buffer(:, :)
    integer, allocatable :: lines(:), pairs(:, :), quota(:), send_n(:), recv_n(:), send_at(:), &
      recv_at(:), dest(:, :), partners(:), halo(:), asked(:), ask_n(:), give_n(:), local_pairs(:, :), &
      sent_row(:), own_first(:), &
      order(:), own_body(:), own_file(:), place(:), slab_to(:), asked_of(:), halo_rank(:), earlier(:), base(:), &
      read_from(:)
    logical, allocatable :: fixed(:)
    logical :: periodic(3)
    real(dp) :: cell_hi(3), rmax, lo(3), hi(3)
    integer(i8) :: row_offset, n_total, fault, c_offset, c_total
    integer :: nranks, rank, dim, ncol, n, i, k, c, d, e, q, width, n_halo, first_body, n_free

    call MPI_Comm_size(comm, nranks)
    call MPI_Comm_rank(comm, rank)
    dim = input%dim
    call scene_input_check_dim(input, status)
    if (status%stat /= demstep_stat%ok) return
    call check_supported(input, status)
    if (status%stat /= demstep_stat%ok) return

    ! the particles: this rank's rows of the file, checked
    call read_table_part(comm, input%particles_file, particle_columns(dim), rows, lines, row_offset, &
      n_total, status)
    if (status%stat /= demstep_stat%ok) then
      call status_restate(status, "particles_file", status%message)
      return
    end if
    call particles_from_rows(input%particles_file, dim, rows, lines, x, v, m, r, fixed, inertia, &
      status, fault_line=k)
    call agree_status(comm, status, merge(no_fault, int(k, i8), status%stat == demstep_stat%ok))
    if (status%stat /= demstep_stat%ok) then
      call status_restate(status, "particles_file", status%message)
      return
    end if
    deallocate(lines, x, v, m, r, fixed)
    if (allocated(inertia)) deallocate(inertia)
    if (n_total == 0) then
      call set_status(status, demstep_stat%invalid_input, input%particles_file//": no particles", &
        where="particles_file")
      return
    else if (n_total > huge(1)) then
      call set_status(status, demstep_stat%invalid_input, input%particles_file//": more than " &
        //int_text(huge(1))//" particles", where="particles_file")
      return
    end if
    part%n_particles = int(n_total)
    ! the counts owned (slab order)
    allocate(quota(0:nranks - 1))
    if (present(owned)) then
      if (size(owned) /= nranks .or. any(owned < 0) .or. sum(int(owned, i8)) /= n_total) then
        call set_status(status, demstep_stat%invalid_input, "one count >= 0 per rank, summing to the " &
          //int_text(n_total)//" particles read", where="owned")
        return
      end if
      quota = owned
    else
      do d = 0, nranks - 1
        quota(d) = int(int(d + 1, i8)*n_total/nranks - int(d, i8)*n_total/nranks)
      end do
    end if
    ncol = size(rows, 1)

    ! the serial scene's checks of the rows read (numbered as in the file)
    call part_arrays(rows)
    block
      ! (a scene of the rows read, for its checks only)
      type(scene_type) :: rows_scene
      if (allocated(inertia)) then
        call new_scene(rows_scene, dim, x, m, r, status, v=v, fixed=fixed, inertia=inertia, search=.false., &
          first_number=int(row_offset) + 1)
      else
        call new_scene(rows_scene, dim, x, m, r, status, v=v, fixed=fixed, search=.false., &
          first_number=int(row_offset) + 1)
      end if
    end block
    fault = no_fault
    if (status%stat /= demstep_stat%ok) then
      select case (status%where)
      case ("mass", "radius", "position")
        fault = status%index
      case ("inertia")
        fault = n_total + status%index
      case default
        fault = 2*n_total + 1
      end select
    end if
    call agree_status(comm, status, fault)
    if (status%stat /= demstep_stat%ok) then
      if (status%where == "inertia") call status_restate(status, "particles_file", &
        input%particles_file//": "//status%message)
      return
    end if
    rmax = 0.0_dp
    if (size(r) > 0) rmax = maxval(r)
    call MPI_Allreduce(MPI_IN_PLACE, rmax, 1, MPI_DOUBLE_PRECISION, MPI_MAX, comm)

    ! the slabs: along the free particles' widest spread (the replicated
    ! path's rule), cut by count; each row read goes to its slab's rank
    lo = huge(1.0_dp)
    hi = -huge(1.0_dp)
    do i = 1, size(fixed)
      if (fixed(i)) cycle
      lo(:dim) = min(lo(:dim), x(:, i))
      hi(:dim) = max(hi(:dim), x(:, i))
    end do
    call MPI_Allreduce(MPI_IN_PLACE, lo, 3, MPI_DOUBLE_PRECISION, MPI_MIN, comm)
    call MPI_Allreduce(MPI_IN_PLACE, hi, 3, MPI_DOUBLE_PRECISION, MPI_MAX, comm)
    part%axis = slab_axis(dim, lo, hi)
    allocate(place(size(rows, 2)))
    call slab_owners(comm, ordered_key(x(part%axis, :)), row_offset, quota, place)
    deallocate(x, v, m, r, fixed)
    if (allocated(inertia)) deallocate(inertia)
    ! the rows to their ranks, each with its file number: every rank's rows
    ! come in file order from ranks in file order, so the own rows ascend.
    ! Each row's place (from here on, `place` holds it instead of the rank):
    ! its number when the ranks' own particles are listed in rank order, each
    ! rank's in file order (rank d's own particle q has place base(d) + q)
    allocate(send_n(0:nranks - 1), recv_n(0:nranks - 1), send_at(0:nranks - 1), recv_at(0:nranks - 1), &
      ask_n(0:nranks - 1), give_n(0:nranks - 1), earlier(0:nranks - 1), source=0)
    allocate(base(0:nranks), source=0)
    do d = 0, nranks - 1
      base(d + 1) = base(d) + quota(d)
    end do
    call group(place, order, send_n)
    call MPI_Exscan(send_n, earlier, nranks, MPI_INTEGER, MPI_SUM, comm)
    if (rank == 0) earlier = 0
    send_at = offsets_of(send_n)
    allocate(buffer(ncol + 1, size(rows, 2)))
    do k = 1, size(rows, 2)
      buffer(:ncol, k) = rows(:, order(k))
      buffer(ncol + 1, k) = real(row_offset + order(k), dp)
      d = place(order(k))
      place(order(k)) = base(d) + earlier(d) + k - send_at(d)
    end do
    deallocate(rows, order)
    send_n = send_n*(ncol + 1)
    call MPI_Alltoall(send_n, 1, MPI_INTEGER, recv_n, 1, MPI_INTEGER, comm)
    part%n_own = sum(recv_n)/(ncol + 1)
    allocate(own_rows(ncol + 1, part%n_own))
    call exchange(buffer, own_rows)
    deallocate(buffer)
    own_file = nint(own_rows(ncol + 1, :))
    ! own free bodies: numbered after those of the ranks before, in file order
    call part_arrays(own_rows(:ncol, :))
    n_free = count(.not. fixed)
    first_body = 0
    call MPI_Exscan(n_free, first_body, 1, MPI_INTEGER, MPI_SUM, comm)
    if (rank == 0) first_body = 0
    allocate(own_body(part%n_own), source=0)
    n_free = first_body
    do i = 1, part%n_own
      if (fixed(i)) cycle
      n_free = n_free + 1
      own_body(i) = n_free
    end do
    deallocate(x, v, m, r, fixed)
    if (allocated(inertia)) deallocate(inertia)

    ! the periodic cell, checked as the serial path checks it (the longest
    ! contact: the largest diameter of the whole scene)
    periodic = .false.
    cell_hi = 0.0_dp
    if (allocated(input%periodic)) periodic(:size(input%periodic)) = input%periodic
    if (allocated(input%cell_hi)) cell_hi(:size(input%cell_hi)) = input%cell_hi
    if (any(periodic)) then
      if (.not. allocated(input%cell_hi)) then
        call set_status(status, demstep_stat%invalid_input, "required with periodic axes", where="cell_hi")
        return
      end if
      call new_scene(probe, dim, reshape(spread(0.0_dp, 1, dim), [dim, 1]), [1.0_dp], [rmax], status, &
        search=.false.)
      if (status%stat == demstep_stat%ok) call scene_set_cell(probe, periodic, input%cell_lo, cell_hi, &
        status, search=.false.)
      if (status%stat /= demstep_stat%ok) return
    end if

    ! the contacts: this rank's rows of the file, checked as the serial
    ! scene_set_contacts checks them (the particle numbers against the whole scene)
    call read_table_part(comm, input%contacts_file, contact_columns, rows, lines, c_offset, c_total, &
      status, index_columns=[1, 2])
    if (status%stat /= demstep_stat%ok) then
      call status_restate(status, "contacts_file", status%message)
      return
    end if
    pairs = nint(rows(1:2, :))
    call contact_rows_check(part%n_particles, pairs, rows(3:, :), st)
    fault = no_fault
    if (st%stat /= demstep_stat%ok) then
      fault = 0
      if (st%index > 0 .and. st%index <= size(lines)) then
        fault = lines(st%index)
        call status_restate(st, "contacts_file", input%contacts_file//": line "// &
          int_text(lines(st%index))//": "//st%detail)
      end if
    end if
    status = st
    call agree_status(comm, status, fault)
    if (status%stat /= demstep_stat%ok) then
      if (status%where /= "contacts_file") call status_restate(status, "contacts_file", status%message)
      return
    end if
    deallocate(lines)
    ! the places of the contacts' particles, asked of the ranks that read them
    allocate(read_from(0:nranks))
    call MPI_Allgather(int(row_offset), 1, MPI_INTEGER, read_from, 1, MPI_INTEGER, comm)
    read_from(nranks) = part%n_particles
    call group([((rank_of(read_from, pairs(e, c)), e = 1, 2), c = 1, size(pairs, 2))], order, ask_n)
    asked_of = [(pairs(mod(order(k) - 1, 2) + 1, (order(k) - 1)/2 + 1), k = 1, size(order))]
    call MPI_Alltoall(ask_n, 1, MPI_INTEGER, give_n, 1, MPI_INTEGER, comm)
    allocate(asked(sum(give_n)))
    call int_exchange(asked_of, ask_n, asked, give_n)
    asked = place(asked - row_offset)
    call int_exchange(asked, give_n, asked_of, ask_n)
    allocate(dest(2, size(pairs, 2)))
    do k = 1, size(order)
      dest(mod(order(k) - 1, 2) + 1, (order(k) - 1)/2 + 1) = asked_of(k)
    end do
    deallocate(asked, asked_of, order, place)
    ! each row to the ranks of its two particles, with its file row first and
    ! the two places last
    ! (slab_to(k): the rank of the k-th copy, of contact row sent_row(k))
    width = size(rows, 1) + 3
    allocate(slab_to(2*size(rows, 2)), sent_row(2*size(rows, 2)))
    k = 0
    do c = 1, size(rows, 2)
      do e = 1, 2
        d = rank_of(base, dest(e, c))
        if (e == 2) then
          if (d == slab_to(k)) cycle
        end if
        k = k + 1
        slab_to(k) = d
        sent_row(k) = c
      end do
    end do
    deallocate(pairs)
    call group(slab_to(:k), order, send_n)
    allocate(mine(width, k))
    do i = 1, k
      c = sent_row(order(i))
      mine(1, i) = real(c_offset + c, dp)
      mine(2:width - 2, i) = rows(:, c)
      mine(width - 1:, i) = real(dest(:, c), dp)
    end do
    deallocate(rows, dest, order, slab_to, sent_row)
    send_n = send_n*width
    call MPI_Alltoall(send_n, 1, MPI_INTEGER, recv_n, 1, MPI_INTEGER, comm)
    allocate(contacts(width, sum(recv_n)/width))
    call exchange(mine, contacts)
    deallocate(mine)
    ! own contacts first (the first particle is this rank's), each group in
    ! file order (the part's c-th contact is contacts(:, own_first(c)));
    ! local_pairs: their particles' places
    allocate(own_first(size(contacts, 2)))
    n = 0
    do c = 1, size(contacts, 2)
      if (.not. is_own(nint(contacts(width - 1, c)))) cycle
      n = n + 1
      own_first(n) = c
    end do
    do c = 1, size(contacts, 2)
      if (is_own(nint(contacts(width - 1, c)))) cycle
      n = n + 1
      own_first(n) = c
    end do
    local_pairs = nint(contacts(width - 1:, own_first))

    ! the halo: the partners this rank does not own, by place (by owner, each
    ! owner's in file order: their rows ascend, as the halo exchange takes them)
    allocate(partners(2*size(local_pairs, 2)))
    n = 0
    do c = 1, size(local_pairs, 2)
      do e = 1, 2
        if (is_own(local_pairs(e, c))) cycle
        n = n + 1
        partners(n) = local_pairs(e, c)
      end do
    end do
    partners = partners(:n)
    call heap_sort(partners)
    allocate(halo(n))
    n_halo = 0
    do i = 1, n
      if (n_halo > 0) then
        if (halo(n_halo) == partners(i)) cycle
      end if
      n_halo = n_halo + 1
      halo(n_halo) = partners(i)
    end do
    halo = halo(:n_halo)
    deallocate(partners)
    ! ask their owners for their rows, file and free-body numbers
    halo_rank = [(rank_of(base, halo(i)), i = 1, n_halo)]
    call group(halo_rank, order, ask_n)
    call MPI_Alltoall(ask_n, 1, MPI_INTEGER, give_n, 1, MPI_INTEGER, comm)
    allocate(asked(sum(give_n)))
    call int_exchange(halo, ask_n, asked, give_n)
    allocate(buffer(ncol + 2, size(asked)))
    do i = 1, size(asked)
      q = asked(i) - base(rank)
      buffer(:ncol, i) = own_rows(:ncol, q)
      buffer(ncol + 1, i) = real(own_body(q), dp)
      buffer(ncol + 2, i) = real(own_file(q), dp)
    end do
    allocate(halo_rows(ncol + 2, n_halo))
    send_n = give_n*(ncol + 2)
    recv_n = ask_n*(ncol + 2)
    call exchange(buffer, halo_rows)
    deallocate(buffer, asked, order)

    ! the part's scene: own particles, then the halo
    part%global = [own_file, nint(halo_rows(ncol + 2, :))]
    part%body = [own_body, nint(halo_rows(ncol + 1, :))]
    allocate(buffer(ncol, part%n_own + n_halo))
    buffer(:, :part%n_own) = own_rows(:ncol, :)
    deallocate(own_rows)
    buffer(:, part%n_own + 1:) = halo_rows(:ncol, :)
    deallocate(halo_rows)
    call part_arrays(buffer)
    deallocate(buffer)
    if (allocated(inertia)) then
      call new_scene(part%scene, dim, x, m, r, st, v=v, fixed=fixed, inertia=inertia, search=.false.)
    else
      call new_scene(part%scene, dim, x, m, r, st, v=v, fixed=fixed, search=.false.)
    end if
    deallocate(x, v, m, r, fixed)
    if (allocated(inertia)) deallocate(inertia)
    if (any(periodic) .and. st%stat == demstep_stat%ok) call scene_set_cell(part%scene, periodic, &
      input%cell_lo, cell_hi, st, search=.false.)
    ! the contacts in the part's numbers
    do c = 1, size(local_pairs, 2)
      do e = 1, 2
        local_pairs(e, c) = local_number(local_pairs(e, c))
      end do
    end do
    part%contact_row = nint(contacts(1, own_first))
    if (st%stat == demstep_stat%ok) call scene_set_contacts(part%scene, local_pairs, &
      contacts(4:width - 2, own_first), st)
    deallocate(contacts, local_pairs, own_first)
    ! (the checks above passed: a part's scene is built as the whole one)
    call agree_status(comm, st, merge(no_fault, int(rank, i8), st%stat == demstep_stat%ok))
    if (st%stat /= demstep_stat%ok) then
      status = st
      return
    end if
    ! effects and dashpots as the serial reader sets them, and rotations when
    ! any contact (on any rank) has tangential springs
    call scene_input_effects(input, part%scene, status)
    if (status%stat /= demstep_stat%ok) return
    if (part%scene%effects(scene_effect%walls)) then
      call set_status(status, demstep_stat%invalid_input, "the 'walls' effect and the walls array go " &
        //"together", where="walls")
      return
    end if
    if (.not. allocated(input%effects) .and. has_tangential(part%scene)) &
      part%scene%effects(scene_effect%rotation) = .true.
    call MPI_Allreduce(MPI_IN_PLACE, part%scene%effects(scene_effect%rotation), 1, MPI_LOGICAL, &
      MPI_LOR, comm)
    call scene_input_damping(input, part%scene, status)

  contains

    !> Whether the particle at place p is this rank's.
    elemental logical function is_own(p)
      integer, intent(in) :: p
      is_own = p > base(rank) .and. p <= base(rank + 1)
    end function is_own

    !> The part's number of the particle at place p (own or halo).
    integer function local_number(p)
      integer, intent(in) :: p
      if (is_own(p)) then
        local_number = p - base(rank)
      else
        local_number = part%n_own + count_before(halo, p, .false.) + 1
      end if
    end function local_number

    !> The scene's arrays from particle rows (checked before).
    subroutine part_arrays(prows)
      real(dp), intent(in) :: prows(:, :)
      integer, allocatable :: no_lines(:)
      allocate(no_lines(size(prows, 2)), source=0)
      call particles_from_rows(input%particles_file, dim, prows, no_lines, x, v, m, r, fixed, inertia, st)
    end subroutine part_arrays

    !> Columns of `sent` to the ranks, send_n(d) values to rank d in rank
    !> order, into `got`, recv_n(d) values from rank d (counts set, the
    !> displacements from them). Collective.
    subroutine exchange(sent, got)
      real(dp), intent(in) :: sent(:, :)
      real(dp), intent(inout) :: got(:, :)
      if (.not. allocated(recv_n)) allocate(recv_n(0:nranks - 1))
      call MPI_Alltoall(send_n, 1, MPI_INTEGER, recv_n, 1, MPI_INTEGER, comm)
      send_at = offsets_of(send_n)
      recv_at = offsets_of(recv_n)
      call MPI_Alltoallv(sent, send_n, send_at, MPI_DOUBLE_PRECISION, got, recv_n, recv_at, &
        MPI_DOUBLE_PRECISION, comm)
    end subroutine exchange

    !> Integers `sent` to the ranks, n_sent(d) to rank d in rank order, into
    !> `got`, n_got(d) from rank d. Collective.
    subroutine int_exchange(sent, n_sent, got, n_got)
      integer, intent(in) :: sent(:), n_sent(0:), n_got(0:)
      integer, intent(inout) :: got(:)
      send_at = offsets_of(n_sent)
      recv_at = offsets_of(n_got)
      call MPI_Alltoallv(sent, n_sent, send_at, MPI_INTEGER, got, n_got, recv_at, MPI_INTEGER, comm)
    end subroutine int_exchange

  end subroutine mpi_read_scene

  !> The rank whose run of numbers (starts(d), starts(d + 1)] holds p: the
  !> last d < ubound(starts) with starts(d) < p (a rank with an empty run
  !> is never the answer).
  pure integer function rank_of(starts, p) result(d)
    integer, intent(in) :: starts(0:), p
    integer :: hi, mid
    d = 0
    hi = ubound(starts, 1) - 1
    do while (d < hi)
      mid = (d + hi + 1)/2
      if (starts(mid) < p) then
        d = mid
      else
        hi = mid - 1
      end if
    end do
  end function rank_of

  !> A stable grouping of items by rank: `order` lists the items of rank 0
  !> first, then rank 1's, ..., each in item order; `n(d)` items of rank d.
  pure subroutine group(item_rank, order, n)
    integer, intent(in) :: item_rank(:)
    integer, allocatable, intent(out) :: order(:)
    integer, intent(inout) :: n(0:)
    integer :: at(0:size(n) - 1), i
    n = 0
    do i = 1, size(item_rank)
      n(item_rank(i)) = n(item_rank(i)) + 1
    end do
    at = offsets_of(n)
    allocate(order(size(item_rank)))
    do i = 1, size(item_rank)
      at(item_rank(i)) = at(item_rank(i)) + 1
      order(at(item_rank(i))) = i
    end do
  end subroutine group

  !> An integer whose order is the order of the real number a (equal
  !> numbers, -0 and 0 too, equal keys): its bits, the negative ones' flipped.
  elemental integer(i8) function ordered_key(a) result(key)
    real(dp), intent(in) :: a
    key = transfer(a + 0.0_dp, 1_i8)
    if (key < 0) key = ieor(key, huge(1_i8))
  end function ordered_key

  !> The rank of each row read (`slab_of`) in the slab partition: the rows of
  !> all ranks ordered by (key, file number) and cut into consecutive runs
  !> of quota(d) rows for rank d, in rank order. Each cut is the pair (key,
  !> file number) of its run's last row; the cuts are found all at once, by
  !> bisection on the key (at most 64 steps, four a round: the counts at the
  !> 15 points those four steps could visit, one MPI_Allreduce a round) and
  !> then on the file number among the rows with the cut's key (one step a
  !> round, at most 32; none where the cut takes all those rows, as when the
  !> keys are distinct: their largest file number is the cut's, one
  !> MPI_Allreduce). This rank's keys are sorted once (`radix_sort`) and its
  !> rows with a cut's key listed once, so each count is a binary search: a
  !> round costs O(cuts log rows), and the whole search O(rows + cuts log
  !> rows) besides the sort and the final assignment, O(rows cuts). No rank
  !> holds more than its rows and their sorted keys. Collective.
  subroutine slab_owners(comm, key, row_offset, quota, slab_of)
    type(MPI_Comm), intent(in) :: comm
    !> `ordered_key` of this rank's rows; file number of its first less one.
    integer(i8), intent(in) :: key(:), row_offset
    !> Rows per rank.
    integer, intent(in) :: quota(0:)
    integer, intent(out) :: slab_of(:)
    integer(i8) :: below(size(quota) - 1), lo(size(quota) - 1), hi(size(quota) - 1), &
      mid(size(quota) - 1), cnt(size(quota) - 1), cut_key(size(quota) - 1), range(2), &
      less(2*(size(quota) - 1))
    integer(i8), allocatable :: sorted(:), tied(:)
    integer, parameter :: levels = 4, ways = 2**levels
    integer(i8) :: points(0:ways, size(quota) - 1), cnts(ways - 1, size(quota) - 1)
    integer :: first(size(quota) - 1), at(size(quota)), j, i, k, nc, step
    nc = size(quota) - 1
    slab_of = 0
    if (nc == 0) return
    do j = 1, nc
      below(j) = sum(int(quota(0:j - 1), i8))
    end do
    sorted = key
    call radix_sort(sorted)
    range = -huge(1_i8)
    if (size(key) > 0) range = [-sorted(1), sorted(size(key))]
    call MPI_Allreduce(MPI_IN_PLACE, range, 2, MPI_INTEGER8, MPI_MAX, comm)
    ! the smallest key v with below(j) keys at or below it (none: below the
    ! least): `levels` bisection steps a round, the counts at the points
    ! those steps could visit (the midpoints of the midpoints) in one MPI_Allreduce
    lo = -range(1) - 1
    hi = range(2)
    where (below == 0) hi = lo
    do
      if (all(floor_mean(lo, hi) == lo)) exit
      do j = 1, nc
        points(0, j) = lo(j)
        points(ways, j) = hi(j)
        step = ways
        do while (step > 1)
          do k = step/2, ways - 1, step
            points(k, j) = floor_mean(points(k - step/2, j), points(k + step/2, j))
          end do
          step = step/2
        end do
        do k = 1, ways - 1
          cnts(k, j) = count_before(sorted, points(k, j), .true.)
        end do
      end do
      call MPI_Allreduce(MPI_IN_PLACE, cnts, nc*(ways - 1), MPI_INTEGER8, MPI_SUM, comm)
      do j = 1, nc
        k = findloc(cnts(:, j) >= below(j), .true., dim=1)
        if (k == 0) then
          lo(j) = points(ways - 1, j)
        else
          hi(j) = points(k, j)
          lo(j) = points(k - 1, j)
        end if
      end do
    end do
    cut_key = hi
    do j = 1, nc
      less(j) = count_before(sorted, cut_key(j), .false.)
    end do
    deallocate(sorted)
    ! this rank's rows with a cut's key (the cuts' keys ascend): their file
    ! numbers, ascending, listed once for the first cut with that key
    ! (tied(at(j):at(j + 1) - 1)), and how many there are in all
    first = [(j, j = 1, nc)]
    do j = 2, nc
      if (cut_key(j) == cut_key(j - 1)) first(j) = first(j - 1)
    end do
    at = 0
    do i = 1, size(key)
      j = cut_of(key(i))
      if (j > 0) at(j + 1) = at(j + 1) + 1
    end do
    less(nc + 1:) = at(first + 1)
    at(1) = 1
    do j = 1, nc
      at(j + 1) = at(j + 1) + at(j)
    end do
    allocate(tied(at(nc + 1) - 1))
    do i = 1, size(key)
      j = cut_of(key(i))
      if (j == 0) cycle
      tied(at(j)) = row_offset + i
      at(j) = at(j) + 1
    end do
    do j = nc, 1, -1
      at(j + 1) = at(j)
    end do
    at(1) = 1
    ! of the rows with that key (all ranks), the first t(j) by file number
    call MPI_Allreduce(MPI_IN_PLACE, less, 2*nc, MPI_INTEGER8, MPI_SUM, comm)
    associate (t => below - less(:nc), tied_count => less(nc + 1:))
      ! the largest file number with the key, where the cut takes all such rows
      mid = -1
      do j = 1, nc
        if (at(first(j) + 1) > at(first(j))) mid(j) = tied(at(first(j) + 1) - 1)
      end do
      call MPI_Allreduce(MPI_IN_PLACE, mid, nc, MPI_INTEGER8, MPI_MAX, comm)
      lo = -1
      hi = sum(int(quota, i8))
      where (t == 0) hi = 0
      where (t > 0 .and. t == tied_count)
        hi = mid
        lo = mid - 1
      end where
      do
        mid = floor_mean(lo, hi)
        if (all(mid == lo)) exit
        do j = 1, nc
          cnt(j) = count_before(tied(at(first(j)):at(first(j) + 1) - 1), mid(j), .true.)
        end do
        call MPI_Allreduce(MPI_IN_PLACE, cnt, nc, MPI_INTEGER8, MPI_SUM, comm)
        where (mid > lo .and. cnt >= t) hi = mid
        where (mid > lo .and. cnt < t) lo = mid
      end do
    end associate
    do i = 1, size(key)
      slab_of(i) = count(key(i) > cut_key .or. (key(i) == cut_key .and. row_offset + i > hi))
    end do

  contains

    !> The first cut whose key is k (0: none).
    pure integer function cut_of(k)
      integer(i8), intent(in) :: k
      integer :: a
      a = count_before(cut_key, k, .false.) + 1
      cut_of = 0
      if (a > nc) return
      if (cut_key(a) == k) cut_of = first(a)
    end function cut_of

  end subroutine slab_owners

  !> floor((a + b)/2) without overflow.
  elemental integer(i8) function floor_mean(a, b)
    integer(i8), intent(in) :: a, b
    floor_mean = shifta(a, 1) + shifta(b, 1) + iand(iand(a, b), 1_i8)
  end function floor_mean

  !> Refuse the input components the distributed reader does not read (it
  !> reads tables of particles and contacts, a cell, effects and dashpots).
  subroutine check_supported(input, status)
    type(scene_input_type), intent(in) :: input
    type(demstep_status_type), intent(out) :: status
    character(len=:), allocatable :: what
    what = ""
    if (.not. allocated(input%particles_file)) what = "particles_file"
    if (.not. allocated(input%contacts_file)) what = "contacts_file"
    if (len(what) > 0) then
      call set_status(status, demstep_stat%invalid_input, "required by the distributed reader " &
        //"(particles_file and contacts_file)", where=what)
      return
    end if
    if (allocated(input%snapshot_file)) what = "snapshot_file"
    if (allocated(input%liggghts_script)) what = "liggghts_script"
    if (allocated(input%bonds_file) .or. allocated(input%bonds)) what = "bonds"
    if (allocated(input%bond_model)) what = "bond_model"
    if (allocated(input%bodies_file)) what = "bodies_file"
    if (allocated(input%walls)) what = "walls"
    if (allocated(input%types)) what = "types"
    if (allocated(input%k_normal) .or. allocated(input%k_tangential) .or. allocated(input%kt_ratio)) &
      what = "k_normal"
    if (allocated(input%e_star) .or. allocated(input%law)) what = "law"
    if (allocated(input%position)) what = "position"
    if (len(what) > 0) then
      call set_status(status, demstep_stat%invalid_input, "not read by the distributed reader " &
        //"(it reads particles_file, contacts_file, the cell, effects and dashpots)", where=what)
      return
    end if
    status%stat = demstep_stat%ok
  end subroutine check_supported

  !> The critical time steps of a scene read in parts (`mpi_read_scene`), on
  !> the ranks of `comm`: `assembly_critical_steps`' with the Lanczos solver
  !> (same scaling, Krylov size, restarts, tolerance, certificate, bound,
  !> per-contact rule and exact damped limit). Collective; the same result
  !> and status on every rank, those of the serial path for the whole scene.
  !> With `release`, the part's positions, velocities and contacts are
  !> released once its springs are built (the positions once the operator
  !> has chosen its order; the solve needs only these): the
  !> part cannot be solved again, and a solve of a released part (on any
  !> rank) is refused with invalid_input naming `part`.
  subroutine mpi_part_critical_steps(comm, part, result, status, prestress, tolerance, progress, release)
    type(MPI_Comm), intent(in) :: comm
    type(dist_scene_part_type), intent(inout) :: part
    type(critical_step_type), intent(out) :: result
    type(demstep_status_type), intent(out) :: status
    !> Count the pre-stress (geometric) stiffness of loaded contacts (default no).
    logical, intent(in), optional :: prestress
    !> Relative tolerance on omega_max^2 (default `lanczos_tolerance_default`).
    real(dp), intent(in), optional :: tolerance
    !> Reports the Lanczos products (pass it on one rank, e.g. rank 0).
    class(progress_type), intent(inout), optional :: progress
    !> Release the part's positions and contacts after the springs (default no).
    logical, intent(in), optional :: release
    type(dist_scene_operator_type), target :: dop
    type(spring_block_type), allocatable :: springs(:)
    real(dp), allocatable :: position(:, :)
    type(critical_step_type) :: mine
    type(MPI_Comm) :: rows_comm
    integer, allocatable :: comp(:), blocks(:, :), halo(:)
    real(dp) :: tol, scales(2), rate, b_bound
    integer(i8) :: fault, counts(2)
    integer :: rank, nranks, nc, i, s, q, n_own_bodies, root, color, n_owned
    logical :: geo, rotation, flags(8), active, gone

    call MPI_Comm_rank(comm, rank)
    call MPI_Comm_size(comm, nranks)
    ! (released on one rank: refused on every rank, before any other collective)
    gone = part%released
    call MPI_Allreduce(MPI_IN_PLACE, gone, 1, MPI_LOGICAL, MPI_LOR, comm)
    if (gone) then
      call set_status(status, demstep_stat%invalid_input, "released by an earlier solve (release): its " &
        //"positions and contacts are gone; read the scene again (mpi_read_scene)", where="part")
      return
    end if
    geo = .false.
    if (present(prestress)) geo = prestress
    tol = lanczos_tolerance_default
    if (present(tolerance)) tol = tolerance
    call assembly_check_options(part%scene, tol, status)
    if (status%stat /= demstep_stat%ok) return
    associate (scene => part%scene)
      ! a listed pair at one point: the serial search's refusal, first in file order
      fault = no_fault
      if (scene%effects(scene_effect%contacts)) then
        do s = 1, size(scene%contact_pairs, 2)
          if (part%contact_row(s) >= fault) cycle
          if (coincident(scene, scene%contact_pairs(1, s), scene%contact_pairs(2, s))) &
            fault = part%contact_row(s)
        end do
      end if
      if (fault /= no_fault) call coincident_status(status)
      call agree_status(comm, status, fault)
      if (status%stat /= demstep_stat%ok) return
      call linearise(scene, hertz_linearization%current, 0.0_dp, geo, springs, status)
      call agree_status(comm, status, merge(no_fault, int(rank, i8), status%stat == demstep_stat%ok))
      if (status%stat /= demstep_stat%ok) return
      if (present(release)) then
        if (release) then
          ! (the positions kept until the operator has chosen its order)
          call move_alloc(scene%x, position)
          call release_contacts(part)
        end if
      end if

      ! the whole scene's scales and counts
      rotation = scene%effects(scene_effect%rotation) .and. scene%dim > 1
      comp = dof_components(scene%dim, rotation)
      nc = size(comp)
      scales = [0.0_dp, -huge(1.0_dp)]
      flags = .false.
      do s = 1, size(springs)
        if (.not. maxval(springs(s)%k) > 0.0_dp) cycle
        scales(1) = max(scales(1), springs(s)%k(1), springs(s)%k(2))
        if (springs(s)%a > 0) flags(1) = flags(1) .or. .not. scene%fixed(springs(s)%a)
        flags(1) = flags(1) .or. .not. scene%fixed(springs(s)%b)
      end do
      do i = 1, scene%n
        if (.not. scene%fixed(i)) scales(2) = max(scales(2), -minval(pick(dof_masses(scene%mass(i), &
          scene%inertia(i), scene%radius(i)), comp)))
      end do
      flags(2) = any(springs%c(1) > 0.0_dp .or. springs%c(2) > 0.0_dp .or. springs%c(3) > 0.0_dp &
        .or. springs%c(4) > 0.0_dp)
      call MPI_Allreduce(MPI_IN_PLACE, scales, 2, MPI_DOUBLE_PRECISION, MPI_MAX, comm)
      scales(2) = -scales(2)
      call MPI_Allreduce(MPI_IN_PLACE, flags, 2, MPI_LOGICAL, MPI_LOR, comm)
      n_own_bodies = count(.not. scene%fixed(:part%n_own))
      counts = [int(n_own_bodies, i8), 0_i8]
      call MPI_Allreduce(MPI_IN_PLACE, counts, 2, MPI_INTEGER8, MPI_SUM, comm)
      if (counts(1) == 0 .or. .not. (flags(1) .and. scales(1) > 0.0_dp)) then
        ! every particle fixed, or no stiffness: the serial refusal, from a
        ! one-particle scene that fails the same way
        call serial_refusal(counts(1) == 0)
        return
      end if
      if (counts(1)*nc > huge(1)) then
        call set_status(status, demstep_stat%invalid_input, "more than "//int_text(huge(1)) &
          //" degrees of freedom", where="particles_file")
        return
      end if

      ! the operator on the ranks that own free bodies
      active = n_own_bodies > 0
      color = MPI_UNDEFINED
      if (active) color = 0
      call MPI_Comm_split(comm, color, rank, rows_comm)
      root = huge(1)
      if (active) root = rank
      call MPI_Allreduce(MPI_IN_PLACE, root, 1, MPI_INTEGER, MPI_MIN, comm)
      if (active) then
        ! (the part's bodies in a locality order where its file order
        ! scatters them: the products' vectors stay in the part's order)
        if (allocated(position)) then
          call operator_from_springs(scene%dim, rotation, scene%mass, scene%inertia, scene%radius, springs, &
            geo, dop%op, rate, status, scene%fixed, scales, position=position)
          deallocate(position)
        else
          call operator_from_springs(scene%dim, rotation, scene%mass, scene%inertia, scene%radius, springs, &
            geo, dop%op, rate, status, scene%fixed, scales, position=scene%x)
        end if
        if (flags(2) .and. size(dop%op%dcoef, 2) == 0) then
          ! (dashpots elsewhere, none here: B' is zero on this part)
          deallocate(dop%op%dcoef)
          allocate(dop%op%dcoef(4, dop%op%n_springs), source=0.0_dp)
        end if
        dop%n_global = int(counts(1))*nc
        dop%n_local = n_own_bodies*nc
        dop%first_row = (part%body(first_free()) - 1)*nc + 1
        dop%comm = rows_comm
        call MPI_Comm_size(rows_comm, q)
        allocate(blocks(2, 0:q - 1))
        call MPI_Allgather([dop%first_row, dop%n_local], 2, MPI_INTEGER, blocks, 2, MPI_INTEGER, rows_comm)
        ! the halo's rows: its free bodies' (part order: by owner, then file
        ! order; their rows ascend)
        halo = pack(part%body(part%n_own + 1:), part%body(part%n_own + 1:) > 0)
        halo = [((halo((i - 1)/nc + 1) - 1)*nc + mod(i - 1, nc) + 1, i = 1, nc*size(halo))]
        call dist_halo_create(rows_comm, blocks, halo, dop%halo)
        allocate(dop%x_ext(dop%op%n), dop%y_ext(dop%op%n), source=0.0_dp)
      end if
      ! what the springs tell: each contact counted by its owner (the owned
      ! springs moved to the front, in order: no copy of the springs)
      n_owned = 0
      do s = 1, size(springs)
        if (.not. owned_spring(springs(s)%a, springs(s)%b)) cycle
        n_owned = n_owned + 1
        if (n_owned < s) springs(n_owned) = springs(s)
      end do
      call assembly_set_springs(mine, springs(:n_owned))
      deallocate(springs)
    end associate
    result = mine
    result%rotation = rotation
    result%periodic = any(part%scene%periodic)
    result%prestress = geo
    result%dof_per_particle = nc
    result%n_dof = int(counts(1))*nc
    call MPI_Allreduce(mine%n_springs, result%n_springs, 1, MPI_INTEGER, MPI_SUM, comm)
    call MPI_Allreduce(mine%dt_contact_rule, result%dt_contact_rule, 1, MPI_DOUBLE_PRECISION, MPI_MIN, comm)
    flags = [mine%tangential, mine%dashpots, .false.]
    call MPI_Allreduce(MPI_IN_PLACE, flags, 8, MPI_LOGICAL, MPI_LOR, comm)
    result%tangential = flags(1)
    result%dashpots = flags(2:7)
    result%solver = eigen_solver%lanczos
    result%eigen_tolerance = tol
    rate = sqrt(scales(1))/sqrt(scales(2))

    if (active) then
      call estimates()
      call dist_halo_free(dop%halo)
      call MPI_Comm_free(rows_comm)
    end if
    ! the result from the first rank with rows
    ! a byte copy: right while critical_step_type has no allocatable or pointer
    ! component (test_mpi_files compares every rank's result with the serial one)
    call MPI_Bcast(result, int(storage_size(result)/8), MPI_BYTE, root, comm)
    call broadcast_status(comm, status, root)

  contains

    !> The part's number of its first own free particle.
    integer function first_free()
      first_free = findloc(part%scene%fixed(:part%n_own), .false., dim=1)
    end function first_free

    !> Whether a spring is this rank's: a contact by its first particle, a
    !> drag spring by its body.
    elemental logical function owned_spring(a, b)
      integer, intent(in) :: a, b
      if (a > 0) then
        owned_spring = a <= part%n_own
      else
        owned_spring = b <= part%n_own
      end if
    end function owned_spring

    !> The entries c of v.
    pure function pick(v, c) result(w)
      real(dp), intent(in) :: v(:)
      integer, intent(in) :: c(:)
      real(dp) :: w(size(c))
      w = v(c)
    end function pick

    !> The serial path's refusal of a scene without free particles or
    !> without stiffness, from a one-particle scene with the same effects.
    subroutine serial_refusal(all_fixed)
      logical, intent(in) :: all_fixed
      type(scene_type) :: one
      type(assembly_operator_type) :: probe_op
      real(dp) :: probe_rate
      call new_scene(one, part%scene%dim, reshape(spread(0.0_dp, 1, part%scene%dim), &
        [part%scene%dim, 1]), [1.0_dp], [1.0_dp], status, fixed=[all_fixed], search=.false.)
      one%effects = part%scene%effects
      one%effects(scene_effect%damping) = .false.
      call assembly_operator(one, probe_op, probe_rate, status)
    end subroutine serial_refusal

    !> The search's refusal of the first coincident pair (file numbers).
    subroutine coincident_status(st)
      type(demstep_status_type), intent(out) :: st
      type(search_type) :: s_probe
      integer :: c
      c = findloc(part%contact_row, int(fault), dim=1)
      s_probe%coincident = part%global(part%scene%contact_pairs(:, c))
      call search_trouble(s_probe, st)
    end subroutine coincident_status

    !> Bound, Lanczos and damping on the ranks with rows.
    subroutine estimates()
      type(eigen_result_type) :: lanczos
      real(dp), allocatable :: vec(:)
      real(dp) :: bound, lower
      logical :: has_mode

      bound = scene_bound(dop)
      call assembly_set_bound(result, rate, bound, status)
      if (status%stat /= demstep_stat%ok) return
      b_bound = 0.0_dp
      if (size(dop%op%dcoef, 2) > 0 .or. flags(2)) then
        call operator_mix(dop%op, 0.0_dp, 1.0_dp)
        b_bound = scene_bound(dop)
        call operator_mix(dop%op, 1.0_dp, 0.0_dp)
      end if
      allocate(vec(dop%n_local))
      lower = 0.0_dp
      if (geo) lower = -(result%omega_bound/rate)**2
      call parallel_lanczos_largest(dop, lanczos, status, eigenvector=vec, tolerance=tol, &
        ncv=min(scene_lanczos_ncv, dop%n_global), max_restarts=scene_lanczos_restarts, &
        progress=progress, certify=.true., lower_bound=lower)
      call mpi_lanczos_estimates(rows_comm, lanczos, vec, rate, b_bound, result, status, has_mode)
      if (status%stat /= demstep_stat%ok .or. .not. has_mode .or. .not. b_bound > 0.0_dp) return
      call exact_damped(vec, lanczos%eigenvalue, lanczos%certified)
    end subroutine estimates

    !> The exact damped limit from the top undamped mode's block `vec`, its
    !> converged steps confirmed by a cold solve when that top was certified.
    subroutine exact_damped(vec, lam, certified)
      real(dp), intent(in) :: vec(:), lam
      logical, intent(in) :: certified
      type(part_damped_type) :: problem
      real(dp), allocatable :: y(:)
      real(dp) :: vb
      problem%confirm_cold = certified
      problem%dop => dop
      problem%vec = vec
      allocate(y(size(vec)))
      call operator_mix(dop%op, 0.0_dp, 1.0_dp)
      call dop%apply(vec, y)
      call operator_mix(dop%op, 1.0_dp, 0.0_dp)
      vb = sum(vec*y)
      call MPI_Allreduce(MPI_IN_PLACE, vb, 1, MPI_DOUBLE_PRECISION, MPI_SUM, rows_comm)
      call damped_newton(problem, lam, vb, rate, tol, result, status, progress)
    end subroutine exact_damped

  end subroutine mpi_part_critical_steps

  !> Whether particles i and j of a scene, listed as a contact, are at one
  !> point within reach (the serial search's test: no contact normal).
  pure logical function coincident(scene, i, j)
    type(scene_type), intent(in) :: scene
    integer, intent(in) :: i, j
    real(dp) :: d(3)
    d = branch_vector(scene, i, j)
    coincident = d(1)**2 + d(2)**2 + d(3)**2 < (scene%radius(i) + scene%radius(j))**2 .and. &
      .not. norm2(d) > 0.0_dp
  end function coincident

  !> Read a scene in parts and compute its critical time steps: 
  !> `mpi_read_scene` then `mpi_part_critical_steps` with the input's
  !> pre-stress and tolerance. Collective; the same result and status on
  !> every rank.
  subroutine mpi_files_critical_steps(comm, input, result, status, owned, progress)
    type(MPI_Comm), intent(in) :: comm
    type(scene_input_type), intent(in) :: input
    type(critical_step_type), intent(out) :: result
    type(demstep_status_type), intent(out) :: status
    !> Particles owned by each rank (see `mpi_read_scene`).
    integer, intent(in), optional :: owned(:)
    !> Reports the Lanczos products (pass it on one rank).
    class(progress_type), intent(inout), optional :: progress
    type(dist_scene_part_type) :: part
    call mpi_read_scene(comm, input, part, status, owned)
    if (status%stat /= demstep_stat%ok) return
    call mpi_part_critical_steps(comm, part, result, status, input%prestress, input%eigen_tolerance, &
      progress, release=.true.)
  end subroutine mpi_files_critical_steps

  !> Release a part's positions, velocities and contacts (its scene keeps
  !> the particles' masses, radii, inertia and fixed flags).
  subroutine release_contacts(part)
    type(dist_scene_part_type), intent(inout) :: part
    if (allocated(part%scene%x)) deallocate(part%scene%x)
    if (allocated(part%scene%v)) deallocate(part%scene%v)
    if (allocated(part%scene%w)) deallocate(part%scene%w)
    if (allocated(part%scene%contact_pairs)) deallocate(part%scene%contact_pairs)
    if (allocated(part%scene%contact_k)) deallocate(part%scene%contact_k)
    if (allocated(part%contact_row)) deallocate(part%contact_row)
    part%released = .true.
  end subroutine release_contacts

  !> Bytes of a part's particle and contact arrays on this rank (the scene's
  !> per-particle and per-contact arrays and the part's numbers).
  pure function dist_scene_bytes(part) result(bytes)
    type(dist_scene_part_type), intent(in) :: part
    integer(i8) :: bytes
    integer(i8) :: n, c
    n = part%scene%n
    c = 0
    if (allocated(part%scene%contact_pairs)) c = size(part%scene%contact_pairs, 2)
    ! x, v, w (3 each), mass, radius, inertia; fixed; global, body; pairs, k (8), row
    bytes = n*(12*8 + 4 + 2*4) + c*(2*4 + 8*8 + 4)
  end function dist_scene_bytes

  !> y = A' x on this rank's rows: the halo of x, then the part's product.
  subroutine scene_operator_apply(op, x, y)
    class(dist_scene_operator_type), intent(inout) :: op
    real(dp), intent(in) :: x(:)
    real(dp), intent(out) :: y(:)
    associate (n => op%n_local)
      op%x_ext(1:n) = x(1:n)
      call dist_halo_exchange(op%halo, x, op%x_ext(n + 1:))
      call assembly_operator_apply(op%op, op%x_ext, op%y_ext)
      y(1:n) = op%y_ext(1:n)
    end associate
  end subroutine scene_operator_apply

  !> The serial bound (`operator_bound`: Collatz-Wielandt quotients of |A'|
  !> for the operator as it is mixed, from v = 1, `bound_iterations` steps)
  !> over the ranks: each |A'| v from the part's rows with v's halo.
  function scene_bound(dop) result(bound)
    type(dist_scene_operator_type), intent(inout) :: dop
    real(dp) :: bound
    real(dp), allocatable :: v(:), r(:), v_ext(:), r_ext(:), dsum(:, :)
    real(dp) :: q(2)
    integer :: k, n
    n = dop%n_local
    allocate(v(n), r(n), v_ext(dop%op%n), r_ext(dop%op%n))
    ! (the diagonal blocks, summed by the first product for the later ones)
    allocate(dsum(18, merge(dop%op%n_bodies, 0, dop%op%nc == 6)))
    v = 1.0_dp
    bound = huge(1.0_dp)
    do k = 0, bound_iterations
      v_ext(1:n) = v
      call dist_halo_exchange(dop%halo, v, v_ext(n + 1:))
      call operator_abs_product(dop%op, v_ext, r_ext, dsum, k > 0)
      r = r_ext(1:n)
      q = [maxval(r/v), maxval(r)]
      call MPI_Allreduce(MPI_IN_PLACE, q, 2, MPI_DOUBLE_PRECISION, MPI_MAX, dop%comm)
      bound = min(bound, q(1))
      if (.not. q(2) > 0.0_dp) exit
      v = max(r/q(2), 1.0e-3_dp)
    end do
  end function scene_bound

  !> Top eigenpair of tau^2 A' + 2 tau B' on the ranks (warm start from the
  !> last mode, or with `cold` set none: `mpi_damped_lanczos`) and v'A'v of it.
  subroutine part_damped_top(problem, tau, tol, theta, err, va, has_mode, result, status, progress)
    class(part_damped_type), intent(inout) :: problem
    real(dp), intent(in) :: tau, tol
    real(dp), intent(out) :: theta, err, va
    logical, intent(out) :: has_mode
    type(critical_step_type), intent(inout) :: result
    type(demstep_status_type), intent(out) :: status
    class(progress_type), intent(inout), optional :: progress
    type(eigen_result_type) :: lanczos
    real(dp), allocatable :: y(:)
    theta = 0.0_dp
    err = 0.0_dp
    va = 0.0_dp
    call operator_mix(problem%dop%op, tau**2, 2.0_dp*tau)
    call mpi_damped_lanczos(problem%dop, problem%cold, tol, problem%vec, lanczos, status, progress)
    call operator_mix(problem%dop%op, 1.0_dp, 0.0_dp)
    call mpi_damped_solve_done(problem%dop%comm, lanczos, problem%vec, result, status, theta, err, has_mode)
    if (status%stat /= demstep_stat%ok) return
    allocate(y(size(problem%vec)))
    call problem%dop%apply(problem%vec, y)
    va = sum(problem%vec*y)
    call MPI_Allreduce(MPI_IN_PLACE, va, 1, MPI_DOUBLE_PRECISION, MPI_SUM, problem%dop%comm)
  end subroutine part_damped_top

end module demstep_mpi_dist_scene
