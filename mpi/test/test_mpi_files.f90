!> Distributed input (`demstep_mpi_dist_scene`): scenes read in parts from
!> particles and contacts tables against the serial reader and solver
!> (`scene_from_input`, `assembly_critical_steps`) on the same files, on
!> every rank count (CI runs it under `mpirun -np 2`): periodic packings in
!> random file order (each rank's halo a thin layer at its slab's faces,
!> far below the whole scene) and sorted into slabs, with contacts across the
!> periodic face between the first and the last rank, a 2D packing with
!> given dashpots and CRLF lines, ranks without particles or without free
!> ones, the slab partition against a count over all rows, and the refusals
!> (each the serial reader's message, on every rank).
!> Prints one PASS/FAIL line per check (rank 0) and exits non-zero on a failure.
program test_mpi_files
  use mpi_f08
  use mpi_test_support, only: test_start, test_finish, report, uniform, random_particles, num, close, &
    same_everywhere, msg, same_status, rank, nranks, delete
  use demstep_kinds, only: dp, i8
  use demstep_status, only: demstep_status_type, demstep_stat
  use demstep_scene_data, only: scene_type, scene_effect, branch_vector
  use demstep_scene_builders, only: new_scene, scene_set_cell
  use demstep_neighbours, only: contact_list
  use demstep_material, only: material_set_type
  use demstep_scene_input, only: scene_input_type, scene_from_input, scene_setup_type
  use demstep_assembly, only: critical_step_type, assembly_critical_steps, eigen_solver
  use demstep_mpi_dist_scene, only: mpi_files_critical_steps, dist_scene_part_type, mpi_read_scene, &
    mpi_part_critical_steps, slab_owners, ordered_key
  implicit none
  integer :: n
  character(len=*), parameter :: stem = "build/test_mpi_files_"
  character(len=:), allocatable :: pfile, cfile
  real(dp), allocatable :: x(:, :)
  type(scene_input_type) :: input

  call test_start(4242_i8)
  ! (the tables go to build/, which fpm makes; made here when run elsewhere)
  if (rank == 0) call execute_command_line("mkdir -p build")
  call MPI_Barrier(MPI_COMM_WORLD)
  pfile = stem//"particles.txt"
  cfile = stem//"contacts.txt"

  ! a 3D periodic packing in the generator's (random) order: the slabs
  ! gather each rank's particles from all over the files
  call packing_files(300, 3, .false., 4, .false.)
  input = base_input(3)
  input%effects = [scene_effect%contacts, scene_effect%damping, scene_effect%rotation]
  input%damping_ratio = 0.2_dp
  call compare("3D periodic packing, random order, damping")
  call compare("3D periodic packing, all on the last rank", owned=last_rank_owns())
  call compare("3D periodic packing, all on the first rank", owned=first_rank_owns())
  ! 2D, random order: slabs of a long box, each rank's halo a thin layer
  call packing_files(800, 2, .false., 4, .false.)
  input = base_input(2)
  call compare("2D periodic packing, random order")
  call check_thin_halo()
  ! the same sorted along x: contiguous ranges are slabs, and the periodic
  ! face joins the first slab to the last
  call packing_files(400, 3, .true., 4, .false.)
  input = base_input(3)
  call report("slabs: contacts cross the periodic face", crossing_contacts() > 0, "")
  call compare("3D periodic packing in slabs, no damping")
  input%prestress = .true.
  call compare("3D periodic packing in slabs, pre-stress")
  ! 2D, contacts with k_r, k_w and given dashpots, CRLF line ends
  call packing_files(250, 2, .true., 10, .true.)
  input = base_input(2)
  input%effects = [scene_effect%contacts, scene_effect%damping, scene_effect%rotation]
  input%damping_ratio = 0.1_dp
  call compare("2D periodic packing, given dashpots, CRLF")
  call fixed_tail_files()
  input = base_input(2)
  input%periodic = [.false., .false.]
  call compare("a rank with fixed particles only", owned=tail_owned())
  call check_released()
  call check_slab_owners()
  call refusals()

  if (rank == 0) then
    call delete(pfile)
    call delete(cfile)
  end if
  call test_finish("test_mpi_files")

contains

  !> The input of the packing files: periodic cell [0, box)^dim.
  function base_input(dim) result(inp)
    integer, intent(in) :: dim
    type(scene_input_type) :: inp
    inp%dim = dim
    inp%particles_file = pfile
    inp%contacts_file = cfile
    inp%periodic = spread(.true., 1, dim)
    inp%cell_hi = spread(box_of(n, dim), 1, dim)
    inp%eigen_tolerance = 1.0e-10_dp
  end function base_input

  real(dp) function box_of(count, dim)
    integer, intent(in) :: count, dim
    box_of = real(count, dp)**(1.0_dp/dim)
  end function box_of

  !> A random periodic packing of `count` particles (radii 0.4..0.7, masses
  !> 1..2) written as a particles table (with a moment of inertia column) and
  !> its contacts table (`ncol` columns: k_n = 100 +- 50 %, k_t, and for 10
  !> also k_r, k_w and dashpots), optionally sorted along x, optionally with
  !> CRLF line ends. Rank 0 writes; all ranks keep the positions.
  subroutine packing_files(count, dim, sorted, ncol, crlf)
    integer, intent(in) :: count, dim, ncol
    logical, intent(in) :: sorted, crlf
    type(scene_type) :: scene
    type(demstep_status_type) :: st
    real(dp), allocatable :: r(:), m(:), nrm(:, :), ov(:), key(:)
    integer, allocatable :: ci(:), cj(:), order(:)
    real(dp) :: box, kn
    integer :: i, u, c
    character(len=:), allocatable :: eol
    n = count
    box = box_of(count, dim)
    call random_particles(dim, count, box, x, r, m)
    if (sorted) then
      key = x(1, :)
      order = [(i, i = 1, count)]
      call sort_by(key, order)
      x = x(:, order)
      r = r(order)
      m = m(order)
    end if
    call new_scene(scene, dim, x, m, r, st)
    call scene_set_cell(scene, spread(.true., 1, 3) .and. [1, 2, 3] <= dim, [0.0_dp, 0.0_dp, 0.0_dp], &
      spread(box, 1, 3), st)
    call contact_list(scene, ci, cj, nrm, ov)
    eol = ""
    if (crlf) eol = achar(13)
    if (rank == 0) then
      open (newunit=u, file=pfile, status="replace", action="write")
      write (u, '(a)') "# x(dim) v(dim) mass radius fixed inertia"//eol
      do i = 1, count
        write (u, '(*(es24.16, 1x))', advance="no") x(:, i), spread(0.0_dp, 1, dim), m(i), r(i), &
          0.0_dp, 0.4_dp*m(i)*r(i)**2
        write (u, '(a)') eol
      end do
      close (u)
      open (newunit=u, file=cfile, status="replace", action="write")
      write (u, '(a)') "# i j k_n k_t ..."//eol
      do c = 1, size(ci)
        kn = 100.0_dp*(0.5_dp + uniform())
        if (ncol == 4) then
          write (u, '(2(i0, 1x), 2(es24.16, 1x))', advance="no") ci(c), cj(c), kn, 0.3_dp*kn
        else
          write (u, '(2(i0, 1x), 8(es24.16, 1x))', advance="no") ci(c), cj(c), kn, 0.3_dp*kn, &
            0.05_dp*kn, 0.02_dp*kn, 0.5_dp, 0.2_dp, 0.01_dp, 0.005_dp
        end if
        write (u, '(a)') eol
      end do
      close (u)
    else
      do c = 1, size(ci)
        kn = uniform()
      end do
    end if
    call MPI_Barrier(MPI_COMM_WORLD)
  end subroutine packing_files

  !> 2D: a row of 40 free particles along x, each on a fixed one below it,
  !> continued by a row of 40 fixed ones touching the last free one, no
  !> cell (listed with the fixed ones first): with the last 40 in slab order
  !> (along x, the free ones' widest spread) the last rank owns only fixed
  !> particles (no rows).
  subroutine fixed_tail_files()
    integer :: u, i
    n = 120
    if (rank == 0) then
      open (newunit=u, file=pfile, status="replace", action="write")
      do i = 1, 80
        write (u, '(a, f6.2, a)') "", 1.0_dp*(i - 1), merge(" 0.0", " 1.0", i <= 40)//"  0 0  1.0 0.55 1"
      end do
      do i = 1, 40
        write (u, '(a, f6.2, a)') "", 1.0_dp*(i - 1), " 1.0  0 0  1.5 0.55 0"
      end do
      close (u)
      open (newunit=u, file=cfile, status="replace", action="write")
      do i = 81, 119
        write (u, '(i0, 1x, i0, a)') i, i + 1, " 100 30"
      end do
      do i = 1, 40
        write (u, '(i0, 1x, i0, a)') i + 80, i, " 250 60"
      end do
      write (u, '(a)') "120 41 150 40"
      close (u)
    end if
    call MPI_Barrier(MPI_COMM_WORLD)
  end subroutine fixed_tail_files

  !> Contacts whose branch vector crosses the periodic face along x and whose
  !> particles lie in the first and the last rank's parts (rank 0 counts).
  integer function crossing_contacts() result(k)
    integer :: u, i, j, ios
    character(len=512) :: line
    k = 0
    if (rank == 0) then
      open (newunit=u, file=cfile, status="old", action="read")
      do
        read (u, '(a)', iostat=ios) line
        if (ios /= 0) exit
        if (line(1:1) == "#") cycle
        read (line, *) i, j
        if (abs(x(1, i) - x(1, j)) > 0.5_dp*box_of(n, 3) .and. (min(i, j) <= n/nranks .and. &
          max(i, j) > n - n/nranks)) k = k + 1
      end do
      close (u)
    end if
    call MPI_Bcast(k, 1, MPI_INTEGER, 0, MPI_COMM_WORLD)
  end function crossing_contacts

  function last_rank_owns() result(owned)
    integer :: owned(nranks)
    owned = 0
    owned(nranks) = n
  end function last_rank_owns

  function first_rank_owns() result(owned)
    integer :: owned(nranks)
    owned = 0
    owned(1) = n
  end function first_rank_owns

  !> The last n/3 (in slab order) on the last rank, the rest on the first ones.
  function tail_owned() result(owned)
    integer :: owned(nranks)
    owned = 0
    owned(nranks) = n/3
    owned(1) = owned(1) + n - n/3
    if (nranks > 2) then
      owned(1) = owned(1) - (nranks - 2)
      owned(2:nranks - 1) = 1
    end if
  end function tail_owned

  !> The distributed result from the files against the serial one.
  subroutine compare(name, owned)
    character(len=*), intent(in) :: name
    integer, intent(in), optional :: owned(:)
    type(critical_step_type) :: par, lan, den
    type(demstep_status_type) :: st_par, st_ser
    type(scene_type) :: scene
    type(scene_setup_type) :: setup
    type(material_set_type) :: materials
    integer :: part
    call mpi_files_critical_steps(MPI_COMM_WORLD, input, par, st_par, owned=owned)
    call scene_from_input(input, materials, scene, setup, st_ser, part)
    if (st_ser%stat == demstep_stat%ok) call assembly_critical_steps(scene, lan, st_ser, &
      prestress=input%prestress, solver=eigen_solver%lanczos, tolerance=1.0e-10_dp)
    if (st_ser%stat == demstep_stat%ok) call assembly_critical_steps(scene, den, st_ser, &
      prestress=input%prestress, solver=eigen_solver%dense)
    call report(name//": status ok", st_par%stat == demstep_stat%ok .and. st_ser%stat == &
      demstep_stat%ok, msg(st_par)//" | "//msg(st_ser))
    if (st_par%stat /= demstep_stat%ok .or. st_ser%stat /= demstep_stat%ok) return
    call report(name//": model as serial", par%n_dof == lan%n_dof .and. par%n_springs == &
      lan%n_springs .and. par%dof_per_particle == lan%dof_per_particle .and. &
      (par%rotation .eqv. lan%rotation) .and. (par%tangential .eqv. lan%tangential) .and. &
      (par%periodic .eqv. lan%periodic) .and. all(par%dashpots .eqv. lan%dashpots) .and. &
      par%eigen_converged, "n_dof "//num(real(par%n_dof, dp))//" springs "//num(real(par%n_springs, dp)))
    ! both Lanczos results meet the relative tolerance 1e-10 on omega^2 with
    ! the top found (the dense value checks it), so each omega is within 5e-11
    ! of the true one (Weinstein) plus rounding: 1e-10 apart at most
    call report(name//": omega_max as serial Lanczos and dense (1e-10)", &
      close(par%omega_max, lan%omega_max, 1.0e-10_dp) .and. close(par%omega_max, den%omega_max, &
      1.0e-10_dp), num(par%omega_max)//num(lan%omega_max)//num(den%omega_max))
    call report(name//": safe step at or below the exact limit", par%dt_critical_safe <= &
      den%dt_critical_eigen*(1.0_dp + 1.0e-14_dp), num(par%dt_critical_safe))
    ! the same sums of the same terms in another order and a scaling by the
    ! same factors: rounding only
    call report(name//": bound and contact rule as serial (1e-13)", close(par%omega_bound, &
      lan%omega_bound, 1.0e-13_dp) .and. close(par%dt_contact_rule, lan%dt_contact_rule, 1.0e-13_dp), &
      num(par%omega_bound)//num(lan%omega_bound))
    ! the damped limit: the Newton steps stop when lambda_max(h^2 A + 2 h B) is
    ! within its solve's error bar (1e-10 relative) of 4, and the step taken
    ! is h 4/(theta + err); lambda grows like h to h^2 near the root, so h is
    ! within about 4e-10 of the root: 1e-9
    call report(name//": damped limit as dense (1e-9)", close(par%dt_critical_damped, &
      den%dt_critical_damped, 1.0e-9_dp) .and. (par%damped_exact .eqv. den%damped_exact), &
      num(par%dt_critical_damped)//num(den%dt_critical_damped))
    call report(name//": the same result on every rank", same_everywhere(par%omega_max) .and. &
      same_everywhere(par%omega_upper) .and. same_everywhere(par%omega_bound) .and. &
      same_everywhere(par%dt_critical_damped) .and. same_everywhere(real(par%eigen_products, dp)), "")
  end subroutine compare

  !> The 2D random-order packing read in parts: each rank owns its share
  !> (n/nranks, as equal as can be) and holds a halo of at most n/8
  !> particles. The slabs' halo is the layer within a contact of the two
  !> faces of a slab in a box 28.3 wide (33 particles on 2 ranks); contiguous
  !> ranges of the file's random order hold most of the other ranks' particles
  !> (343 of the other rank's 400 on 2 ranks with the file-number partition
  !> this reader used up to c4d4041: this check failed there).
  subroutine check_thin_halo()
    type(dist_scene_part_type) :: part
    type(demstep_status_type) :: st
    integer :: counts(2), most(2), fewest
    call mpi_read_scene(MPI_COMM_WORLD, input, part, st)
    call report("random order: the part read", st%stat == demstep_stat%ok, msg(st))
    if (st%stat /= demstep_stat%ok) return
    counts = [part%n_own, part%scene%n - part%n_own]
    call MPI_Allreduce(counts, most, 2, MPI_INTEGER, MPI_MAX, MPI_COMM_WORLD)
    call MPI_Allreduce(counts(1), fewest, 1, MPI_INTEGER, MPI_MIN, MPI_COMM_WORLD)
    call report("random order: own particles balanced", most(1) - fewest <= 1, &
      "own "//num(real(most(1), dp))//num(real(fewest, dp)))
    call report("random order: each rank's halo thin (at most n/8)", most(2) <= n/8, &
      "largest halo "//num(real(most(2), dp))//" of "//num(real(n, dp)))
  end subroutine check_thin_halo

  !> A part solved with `release` (its positions, velocities and contacts
  !> dropped once its springs are built): a second solve is refused with a
  !> status naming the part, the same on every rank (with or without
  !> `release` again), no result; a part solved without it solves again to
  !> the same result (the same run: bit for bit), and its solve with
  !> `release` too.
  subroutine check_released()
    type(dist_scene_part_type) :: part
    type(critical_step_type) :: first, again
    type(demstep_status_type) :: st
    call packing_files(200, 3, .true., 4, .false.)
    input = base_input(3)
    call mpi_read_scene(MPI_COMM_WORLD, input, part, st)
    call report("release: the part read", st%stat == demstep_stat%ok, msg(st))
    if (st%stat /= demstep_stat%ok) return
    call mpi_part_critical_steps(MPI_COMM_WORLD, part, first, st, tolerance=1.0e-10_dp)
    call report("release: a kept part solved", st%stat == demstep_stat%ok, msg(st))
    if (st%stat /= demstep_stat%ok) return
    call mpi_part_critical_steps(MPI_COMM_WORLD, part, again, st, tolerance=1.0e-10_dp)
    call report("release: a kept part solved again, the same result", st%stat == demstep_stat%ok .and. &
      again%omega_max == first%omega_max .and. again%dt_critical_safe == first%dt_critical_safe .and. &
      again%dt_critical_damped == first%dt_critical_damped, num(again%omega_max)//num(first%omega_max))
    call mpi_part_critical_steps(MPI_COMM_WORLD, part, again, st, tolerance=1.0e-10_dp, release=.true.)
    call report("release: solved with release, the same result", st%stat == demstep_stat%ok .and. &
      again%omega_max == first%omega_max, msg(st)//num(again%omega_max))
    call mpi_part_critical_steps(MPI_COMM_WORLD, part, again, st, tolerance=1.0e-10_dp)
    call report("release: a released part's second solve refused", st%stat == demstep_stat%invalid_input .and. &
      st%where == "part" .and. same_status(st) .and. .not. again%eigen_computed .and. again%omega_max == 0.0_dp, &
      msg(st))
    call mpi_part_critical_steps(MPI_COMM_WORLD, part, again, st, tolerance=1.0e-10_dp, release=.true.)
    call report("release: refused with release again", st%stat == demstep_stat%invalid_input .and. &
      st%where == "part" .and. same_status(st), msg(st))
  end subroutine check_released

  !> The slab partition (`slab_owners`) against its definition, counted
  !> over all rows: on 60 tables in random order, with many equal
  !> coordinates (five values; -0 and 0 only, which are equal) or distinct
  !> ones, ranks holding from none to 59 of the rows and quotas of any size
  !> (zero too), every rank's rows are its run of the file; a row's rank is
  !> the d with sum(quota(:d-1)) < p <= sum(quota(:d)), p its place when
  !> all rows are ordered by (coordinate, file number). The cuts fall inside
  !> runs of equal coordinates, so the search on file numbers is tried too.
  subroutine check_slab_owners()
    integer :: trial, total, i, d, f, p, bad
    integer, allocatable :: rows_of(:), quota(:), slab(:)
    real(dp), allocatable :: coord(:)
    integer(i8) :: offset
    real(dp) :: u
    bad = 0
    allocate(rows_of(0:nranks - 1), quota(0:nranks - 1))
    do trial = 1, 60
      ! (every rank draws the same numbers: the shared sequence)
      do d = 0, nranks - 1
        rows_of(d) = int(60*uniform())
        if (mod(trial + d, 7) == 0) rows_of(d) = 0
      end do
      total = sum(rows_of)
      do d = 0, nranks - 2
        quota(d) = min(int((total + 1)*uniform()), total - sum(quota(:d - 1)))
        if (mod(trial + d, 5) == 0) quota(d) = 0
      end do
      quota(nranks - 1) = total - sum(quota(:nranks - 2))
      allocate(coord(total))
      do i = 1, total
        u = uniform()
        select case (mod(trial, 3))
        case (0)
          coord(i) = real(int(5*u) - 2, dp)
        case (1)
          coord(i) = merge(-0.0_dp, 0.0_dp, u < 0.5_dp)
        case default
          coord(i) = 100*u - 50
        end select
      end do
      offset = sum(rows_of(:rank - 1))
      allocate(slab(rows_of(rank)))
      call slab_owners(MPI_COMM_WORLD, ordered_key(coord(offset + 1:offset + rows_of(rank))), offset, &
        quota, slab)
      do i = 1, rows_of(rank)
        f = int(offset) + i
        p = count(coord < coord(f)) + count(coord(:f) == coord(f))
        d = 0
        do while (sum(quota(:d)) < p)
          d = d + 1
        end do
        if (slab(i) /= d) bad = bad + 1
      end do
      deallocate(coord, slab)
    end do
    call report("slab_owners: each row's rank as counted over all rows (60 tables)", bad == 0, &
      "rows misplaced "//num(real(bad, dp)))
  end subroutine check_slab_owners

  !> Bad files: the serial reader's status, the same on every rank. Each bad
  !> row sits in the last rank's part (the file's second half) unless said.
  subroutine refusals()
    character(len=:), allocatable :: good_p, good_c
    call packing_files(60, 2, .true., 4, .false.)
    input = base_input(2)
    good_p = slurp(pfile)
    good_c = slurp(cfile)
    ! (every rank has read both before rank 0 rewrites them: `refused`)
    call MPI_Barrier(MPI_COMM_WORLD)
    call refused("a particle row of 6 numbers", late_line(good_p, "1 2 3 4 5 6"), good_c)
    call refused("a fixed column of 2", late_line(good_p, "1 2 0 0 1 0.5 2 0.1"), good_c)
    call refused("a mass of 0", late_line(good_p, "1 2 0 0 0 0.5 0 0.1"), good_c)
    call refused("an inertia of 0", late_line(good_p, "1 2 0 0 1 0.5 0 0"), good_c)
    call refused("a contact naming a missing particle", good_p, late_line(good_c, "3 61 100 30"))
    call refused("a contact pairing a particle with itself", good_p, late_line(good_c, "7 7 100 30"))
    call refused("a contact with k_n = 0", good_p, late_line(good_c, "7 8 0 30"))
    call refused("a contact row of 5 numbers", good_p, late_line(good_c, "7 8 100 30 1"))
    call refused("a particle number 1.5", good_p, late_line(good_c, "1.5 8 100 30"))
    ! a late control character is reported before an early bad row (the
    ! serial reader checks the whole text first)
    call refused("a late control byte beats an early bad row", early_line(late_line(good_p, &
      "1 2 0 0 1 0.5 0 0.1"//achar(1)), "oops"), good_c)
    call refused("two bad rows: the first in the file", early_line(late_line(good_p, "bad"), &
      "1 2 3"), good_c)
    call refused("no particles", "# nothing"//achar(10), good_c)
    call refused("no contacts: no stiffness", good_p, "# none"//achar(10))
    call write_text(pfile, good_p)
    input%particles_file = stem//"missing.txt"
    call refused_input("a missing particles file")
    input%particles_file = pfile
    input%periodic = [.true., .true.]
    input%cell_hi = [1.0_dp, 1.0_dp]
    call refused_input("a periodic cell shorter than two diameters")
    input = base_input(2)
    input%k_normal = 10.0_dp
    call check_unsupported()
  end subroutine refusals

  !> The files as given: the distributed status is the serial one on every rank.
  subroutine refused(name, ptext, ctext)
    character(len=*), intent(in) :: name, ptext, ctext
    call write_text(pfile, ptext)
    call write_text(cfile, ctext)
    call refused_input(name)
  end subroutine refused

  subroutine refused_input(name)
    character(len=*), intent(in) :: name
    type(critical_step_type) :: par
    type(demstep_status_type) :: st_par, st_ser
    type(scene_type) :: scene
    type(scene_setup_type) :: setup
    type(material_set_type) :: materials
    type(critical_step_type) :: ser
    integer :: part
    call mpi_files_critical_steps(MPI_COMM_WORLD, input, par, st_par)
    ! (the serial refusal of the reader, or of the solve)
    call scene_from_input(input, materials, scene, setup, st_ser, part)
    if (st_ser%stat == demstep_stat%ok) call assembly_critical_steps(scene, ser, st_ser, &
      solver=eigen_solver%lanczos, tolerance=input%eigen_tolerance)
    call report("refused, "//name//": the serial status", st_par%stat /= demstep_stat%ok .and. &
      st_par%stat == st_ser%stat .and. msg(st_par) == msg(st_ser) .and. &
      st_par%where == st_ser%where .and. same_status(st_par), msg(st_par)//" | "//msg(st_ser))
  end subroutine refused_input

  !> An input component the distributed reader does not read: refused by name.
  subroutine check_unsupported()
    type(critical_step_type) :: par
    type(demstep_status_type) :: st
    call mpi_files_critical_steps(MPI_COMM_WORLD, input, par, st)
    call report("refused, k_normal with a contacts file: not read in parts", &
      st%stat == demstep_stat%invalid_input .and. st%where == "k_normal" .and. same_status(st), msg(st))
  end subroutine check_unsupported

  !> The text with line k (a data line in the last quarter) replaced.
  function late_line(text, row) result(out)
    character(len=*), intent(in) :: text, row
    character(len=:), allocatable :: out
    out = replace_line(text, (3*count_lines(text))/4, row)
  end function late_line

  !> The text with its third line replaced (in the first rank's part).
  function early_line(text, row) result(out)
    character(len=*), intent(in) :: text, row
    character(len=:), allocatable :: out
    out = replace_line(text, 3, row)
  end function early_line

  integer function count_lines(text)
    character(len=*), intent(in) :: text
    integer :: i
    count_lines = count([(text(i:i) == achar(10), i = 1, len(text))])
  end function count_lines

  function replace_line(text, k, row) result(out)
    character(len=*), intent(in) :: text, row
    integer, intent(in) :: k
    character(len=:), allocatable :: out
    integer :: i, line, first, last
    line = 1
    first = 1
    last = len(text)
    do i = 1, len(text)
      if (text(i:i) /= achar(10)) cycle
      line = line + 1
      if (line == k) first = i + 1
      if (line == k + 1) then
        last = i - 1
        exit
      end if
    end do
    out = text(:first - 1)//row//text(last + 1:)
  end function replace_line

  function slurp(path) result(text)
    character(len=*), intent(in) :: path
    character(len=:), allocatable :: text
    integer :: u, sz
    open (newunit=u, file=path, access="stream", form="unformatted", status="old", action="read")
    inquire (unit=u, size=sz)
    allocate (character(len=sz) :: text)
    read (u) text
    close (u)
  end function slurp

  !> Rank 0 writes the file; all wait.
  subroutine write_text(path, text)
    character(len=*), intent(in) :: path, text
    integer :: u
    if (rank == 0) then
      open (newunit=u, file=path, access="stream", form="unformatted", status="replace", action="write")
      write (u) text
      close (u)
    end if
    call MPI_Barrier(MPI_COMM_WORLD)
  end subroutine write_text

  !> Sort order by key (insertion sort: small n).
  subroutine sort_by(key, order)
    real(dp), intent(inout) :: key(:)
    integer, intent(inout) :: order(:)
    integer :: i, j, t
    real(dp) :: kt
    do i = 2, size(key)
      kt = key(i)
      t = order(i)
      j = i - 1
      do while (j >= 1)
        if (key(j) <= kt) exit
        key(j + 1) = key(j)
        order(j + 1) = order(j)
        j = j - 1
      end do
      key(j + 1) = kt
      order(j + 1) = t
    end do
  end subroutine sort_by

end program test_mpi_files
