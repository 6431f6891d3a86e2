!> Benchmark of a scene's exact stability limit at DEM scale: random periodic
!> packings (`random_periodic_packing`, rotations and tangential springs, 6 DOF
!> per particle) tiled up (`tile_scene`) to 1e3 .. 1e6 particles. Per size, one
!> run each: the Gershgorin bound, Lanczos to 1e-6 with 1 and 2 OpenMP
!> threads, dense LAPACK where it fits (<= 4000 DOF), and SciPy's eigsh
!> (bench/eigsh_scene.py, tolerance 1e-6, eigsh alone timed, median of 3 calls) on the same scaled
!> matrix A', which this program writes in Matrix Market format to a temporary
!> file (removed afterwards). The base packing's limit (Lanczos to 1e-10) is a
!> floor for the tiled one: its modes, repeated in phase in every copy, are
!> modes of the tiled scene (test_packing checks this on the matrices). Memory: the peak resident size (VmHWM of
!> /proc/self/status) after the Lanczos runs, and over the particles, for the
!> cases that raised the process's peak (the file and eigsh's memory are not
!> counted: they come after, and eigsh runs in its own process).
!>
!> With the path of the `demstep` program as the third argument, the app is
!> also run end to end from files (median of 3 runs, wall time of the whole
!> process): the tiled scene written as a particles table (17 digits) and a
!> contacts table (`i j k_n k_t`: no contact search) with a deck in
!> /tmp/demstep_bench_app_N/, `eigen_solver = 'lanczos'` at the default
!> tolerance; its omega_max is compared with eigsh's.
!>
!> Run it with OPENBLAS_NUM_THREADS=1: OpenBLAS's own threads spin between
!> ARPACK's calls and take the cores from the OpenMP operator (2 threads were
!> slower than 1 at 1e4 particles without it); eigsh keeps OpenBLAS's default.
!>
!>   OPENBLAS_NUM_THREADS=1 fpm run --example bench_scene_eigen --profile release [-- MAX_PARTICLES [noscipy [APP [MIN_PARTICLES [random]]]]]
!>
!>   ... [-- MAX_PARTICLES [noscipy [APP [MIN_PARTICLES [random|tile [yade]]]]]]
!>
!> (MIN_PARTICLES: the cases below it are left out, e.g. 1000000 alone.
!> `random`: the app's tables are written in a fixed random order, as a DEM
!> code's dump by particle id lists a settled pile (particles permuted,
!> contacts renamed and permuted), in /tmp/demstep_bench_app_random_N/.
!> `yade`: the base is Yade's periodic "random" assembly instead
!> (validation/yade/data/random, read as the app reads it: 600 spheres and
!> the 1899 contacts Yade integrated, each with its own k_n and k_t), tiled
!> K = 1, 2, 4, 6, 12 times along each axis; the app's tables, in
!> /tmp/demstep_bench_app_yade_N/, list the tiled contacts with their own
!> stiffness. Run it from the project's root.)
program bench_scene_eigen
  use, intrinsic :: iso_fortran_env, only: output_unit
  use demstep_kinds, only: dp, i8
  use demstep_status, only: demstep_status_type, demstep_stat
  use demstep_progress, only: progress_seconds
  use demstep_scene_data, only: scene_type
  use demstep_packing, only: random_periodic_packing, tile_scene
  use demstep_neighbours, only: contact_list
  use demstep_assembly, only: assembly_critical_steps, critical_step_type, eigen_solver, &
    assembly_operator, assembly_operator_type, assembly_matrix
  use demstep_csr, only: csr_matrix_type
  use demstep_scene_input, only: scene_input_type, scene_setup_type, scene_from_input
  use demstep_material, only: material_set_type
  use demstep_results, only: read_result, result_get, result_group_type
  !$ use omp_lib, only: omp_set_num_threads
  implicit none

  !> The cases: base packing size and repetitions (base times product(reps) particles).
  integer, parameter :: n_cases = 5
  !> (the dense-sized case last: its dense matrix would dominate the small
  !> cases' peak memory)
  integer, parameter :: base(n_cases) = [1000, 1250, 800, 1000, 500]
  integer, parameter :: reps(3, n_cases) = reshape([1, 1, 1, 2, 2, 2, 5, 5, 5, 10, 10, 10, 1, 1, 1], [3, n_cases])
  !> The Yade base's tilings (K along each axis: 600 K^3 spheres).
  integer, parameter :: yade_k(5) = [1, 2, 4, 6, 12]
  integer, parameter :: dense_limit = 4000
  !> Runs of the app from files per case (the median is reported).
  integer, parameter :: app_repeats = 3
  real(dp), parameter :: tol = 1.0e-6_dp
  character(len=*), parameter :: mtx = "/tmp/demstep_bench_scene_eigen.mtx"
  character(len=*), parameter :: eigsh_out = "/tmp/demstep_bench_scene_eigen.out"
  type(scene_type) :: packing, scene
  type(critical_step_type) :: r_bound, r_lanczos(2), r_dense, r_base
  type(demstep_status_type) :: status
  character(len=32) :: arg
  character(len=512) :: app
  real(dp) :: t_app, omega_app
  integer(i8) :: app_products
  integer :: c, n_max, n_min, ios, threads, nb, rp(3)
  logical :: scipy, shuffled, yade
  real(dp) :: t_build, t_tile, t_bound, t_lanczos(2), t_dense, t_write, t_eigsh, lam_eigsh, omega_eigsh
  real(dp) :: t0, z, overlap, mb, peak_before
  character(len=48) :: memory

  n_max = huge(1)
  call get_command_argument(1, arg)
  if (arg /= "") read(arg, *, iostat=ios) n_max
  call get_command_argument(2, arg)
  scipy = arg /= "noscipy"
  call get_command_argument(3, app)
  n_min = 0
  call get_command_argument(4, arg)
  if (arg /= "") read(arg, *, iostat=ios) n_min
  call get_command_argument(5, arg)
  shuffled = arg == "random"
  call get_command_argument(6, arg)
  yade = arg == "yade"
  peak_before = 0.0_dp

  if (yade) then
    write(output_unit, '(a)') "# Yade's periodic packing (validation/yade/data/random: its contacts, each with " &
      //"its k_n and k_t) tiled up; 6 DOF per particle; one run each;"
  else
    write(output_unit, '(a)') "# random periodic packings (seed 1) tiled up; 6 DOF per particle; one run each;"
  end if
  write(output_unit, '(a)') "# times in seconds; dt bound/limit = omega_max/omega_bound; the last columns compare " &
    //"omega_max: eigsh's (SciPy on A' from the file) and the base packing's against Lanczos'"
  write(output_unit, '(a)') "| particles | DOF | base x reps | z | mean overlap/r | build s | tile s | bound s " &
    //"| Lanczos 1 thr s | Lanczos 2 thr s | dense s | eigsh s | dt bound/limit | rel. residual " &
    //"| eigsh vs Lanczos | Lanczos vs base | MB peak | bytes/particle |"
  write(output_unit, '(a)') "|---:|---:|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|"
  do c = 1, merge(size(yade_k), n_cases, yade)
    if (yade) then
      nb = 600
      rp = yade_k(c)
    else
      nb = base(c)
      rp = reps(:, c)
    end if
    if (nb*product(rp) > n_max .or. nb*product(rp) < n_min) cycle
    t0 = progress_seconds()
    if (yade) then
      call read_yade(packing)
    else
      call random_periodic_packing(packing, nb, status, seed=1)
      call require("random_periodic_packing")
    end if
    t_build = progress_seconds() - t0
    t0 = progress_seconds()
    call tile_scene(packing, rp, scene, status)
    call require("tile_scene")
    t_tile = progress_seconds() - t0
    call network_statistics(packing, z, overlap)
    ! every mode of the base packing is a mode of the tiled scene (in phase in
    ! every copy): the base's limit (Lanczos to 1e-10) is a floor for omega_max
    call assembly_critical_steps(packing, r_base, status, solver=eigen_solver%lanczos, tolerance=1.0e-10_dp)
    call require("base limit")

    t0 = progress_seconds()
    call assembly_critical_steps(scene, r_bound, status, solver=eigen_solver%none)
    call require("bound")
    t_bound = progress_seconds() - t0
    do threads = 1, 2
      !$ call omp_set_num_threads(threads)
      t0 = progress_seconds()
      call assembly_critical_steps(scene, r_lanczos(threads), status, solver=eigen_solver%lanczos, &
        tolerance=tol)
      call require("lanczos")
      t_lanczos(threads) = progress_seconds() - t0
    end do
    ! the peak is the process's: it tells this case's memory when this case raised it
    mb = peak_megabytes()
    memory = "- | -"
    if (mb > peak_before) memory = trim(fixed(mb, 0))//" | "//trim(fixed(mb*1.0e6_dp/scene%n, 0))
    peak_before = mb
    t_dense = -1.0_dp
    if (r_bound%n_dof <= dense_limit) then
      t0 = progress_seconds()
      call assembly_critical_steps(scene, r_dense, status, solver=eigen_solver%dense)
      call require("dense")
      t_dense = progress_seconds() - t0
      if (abs(r_dense%omega_max/r_lanczos(2)%omega_max - 1.0_dp) > 1.0e-5_dp) &
        write(output_unit, '(a, 2es24.16)') "# dense and Lanczos differ: ", r_dense%omega_max, &
          r_lanczos(2)%omega_max
    end if
    t_eigsh = -1.0_dp
    omega_eigsh = 0.0_dp
    if (scipy) then
      call run_eigsh(scene, t_write, t_eigsh, lam_eigsh, omega_eigsh)
      write(output_unit, '(a, i0, a, a, a)') "# ", scene%n, " particles: A' assembled and written " &
        //"(Matrix Market) in ", trim(fixed(t_write, 1)), " s"
    end if
    if (len_trim(app) > 0) then
      call run_app_files(scene, trim(app), t_app, omega_app, app_products)
      write(output_unit, '(a)') "# "//int_text(scene%n)//" particles: the app from files (median of " &
        //int_text(app_repeats)//") "//trim(fixed(t_app, 3))//" s, "//int_text(int(app_products)) &
        //" products; eigsh "//trim(fixed(t_eigsh, 3))//" s; app/eigsh "//trim(fixed(t_app/t_eigsh, 2)) &
        //"; eigsh vs app omega_max "//trim(relative(omega_eigsh, omega_app))
    end if
    write(output_unit, '(a)') "| "//int_text(scene%n)//" | "//int_text(r_bound%n_dof)//" | "// &
      int_text(nb)//"x"//int_text(rp(1))//"x"//int_text(rp(2))//"x"//int_text(rp(3)) &
      //" | "//trim(fixed(z, 2))//" | "//trim(sci(overlap))//" | "//trim(fixed(t_build, 3))//" | " &
      //trim(fixed(t_tile, 3))//" | "//trim(fixed(t_bound, 3))//" | "//trim(fixed(t_lanczos(1), 3)) &
      //" | "//trim(fixed(t_lanczos(2), 3))//" | "//trim(fixed(t_dense, 3))//" | " &
      //trim(fixed(t_eigsh, 3))//" | "//trim(fixed(r_lanczos(2)%omega_max/r_bound%omega_bound, 3)) &
      //" | "//trim(sci(r_lanczos(2)%eigen_residual))//" | "//trim(relative(omega_eigsh, &
      r_lanczos(2)%omega_max))//" | "//trim(relative(r_lanczos(2)%omega_max, r_base%omega_max)) &
      //" | "//trim(memory)//" |"
    if (r_lanczos(2)%omega_max < r_base%omega_max*(1.0_dp - 1.0e-6_dp)) write(output_unit, '(a)') &
      "# Lanczos omega_max below the base packing's: it missed the top of the spectrum"
    flush(output_unit)
  end do

contains

  !> Yade's periodic "random" assembly from its tables (as the app's deck
  !> `example/yade_random.nml` reads them).
  subroutine read_yade(base_scene)
    type(scene_type), intent(out) :: base_scene
    type(scene_input_type) :: input
    type(material_set_type) :: set
    type(scene_setup_type) :: setup
    integer :: part
    input%dim = 3
    input%particles_file = "validation/yade/data/random/particles.txt"
    input%contacts_file = "validation/yade/data/random/contacts.txt"
    input%periodic = [.true., .true., .true.]
    input%cell_hi = spread(0.16332048070942493_dp, 1, 3)
    call scene_from_input(input, set, base_scene, setup, status, part)
    call require("Yade's tables")
  end subroutine read_yade

  !> The app end to end from files (see the program's notes): the median wall
  !> time of `app_repeats` runs, its omega_max and products.
  subroutine run_app_files(s, app, t_app, omega, products)
    type(scene_type), intent(in) :: s
    character(len=*), intent(in) :: app
    real(dp), intent(out) :: t_app, omega
    integer(i8), intent(out) :: products
    character(len=:), allocatable :: dir
    integer, parameter :: chunk = 4000000
    character(len=chunk + 512) :: buf
    integer, allocatable :: ci(:), cj(:)
    real(dp), allocatable :: cn(:, :), cd(:), kn(:), kt(:)
    real(dp) :: times(app_repeats), t0
    type(result_group_type) :: res
    integer, allocatable :: row_of(:), new_of(:), contact_at(:)
    integer :: unit, pos, i, r, k, exitstat, q
    dir = "/tmp/demstep_bench_app_"//int_text(s%n)
    if (shuffled) dir = "/tmp/demstep_bench_app_random_"//int_text(s%n)
    if (yade) dir = "/tmp/demstep_bench_app_yade_"//int_text(s%n)
    call execute_command_line("mkdir -p "//dir, wait=.true.)
    if (s%given_contacts) then
      ! (the given contacts, each with its own stiffness)
      ci = s%contact_pairs(1, :)
      cj = s%contact_pairs(2, :)
      kn = s%contact_k(1, :)
      kt = s%contact_k(2, :)
    else
      call contact_list(s, ci, cj, cn, cd, status)
      call require("contact_list")
      kn = spread(s%k_normal, 1, size(ci))
      kt = spread(s%k_tangential, 1, size(ci))
    end if
    ! the rows' order: row_of(k) is the particle (contact_at(k) the contact)
    ! written k-th, new_of(i) particle i's row
    row_of = permutation(s%n, shuffled, 1)
    contact_at = permutation(size(ci), shuffled, 2)
    allocate(new_of(s%n))
    do k = 1, s%n
      new_of(row_of(k)) = k
    end do
    ! particles: x y z, v, mass, radius, fixed, inertia
    open(newunit=unit, file=dir//"/particles.txt", access="stream", form="unformatted", status="replace", &
      action="write")
    pos = 0
    do q = 1, s%n
      i = row_of(q)
      do k = 1, 3
        call put_real(buf, pos, s%x(k, i))
        pos = pos + 1
        buf(pos:pos) = " "
      end do
      buf(pos + 1:pos + 6) = "0 0 0 "
      pos = pos + 6
      call put_real(buf, pos, s%mass(i))
      pos = pos + 1
      buf(pos:pos) = " "
      call put_real(buf, pos, s%radius(i))
      buf(pos + 1:pos + 3) = " 0 "
      pos = pos + 3
      call put_real(buf, pos, s%inertia(i))
      pos = pos + 1
      buf(pos:pos) = new_line("a")
      if (pos > chunk) then
        write(unit) buf(:pos)
        pos = 0
      end if
    end do
    if (pos > 0) write(unit) buf(:pos)
    close(unit)
    open(newunit=unit, file=dir//"/contacts.txt", access="stream", form="unformatted", status="replace", &
      action="write")
    pos = 0
    do q = 1, size(ci)
      i = contact_at(q)
      call put_integer(buf, pos, new_of(ci(i)))
      pos = pos + 1
      buf(pos:pos) = " "
      call put_integer(buf, pos, new_of(cj(i)))
      pos = pos + 1
      buf(pos:pos) = " "
      call put_real(buf, pos, kn(i))
      pos = pos + 1
      buf(pos:pos) = " "
      call put_real(buf, pos, kt(i))
      pos = pos + 1
      buf(pos:pos) = new_line("a")
      if (pos > chunk) then
        write(unit) buf(:pos)
        pos = 0
      end if
    end do
    if (pos > 0) write(unit) buf(:pos)
    close(unit)
    open(newunit=unit, file=dir//"/deck.nml", status="replace", action="write")
    write(unit, '(a)') "&scene", "  dim = 3", "  particles_file = 'particles.txt'", &
      "  contacts_file = 'contacts.txt'", "  periodic = T, T, T"
    write(unit, '(a, 3(es25.17, :, ","))') "  cell_lo = ", s%cell_lo
    write(unit, '(a, 3(es25.17, :, ","))') "  cell_hi = ", s%cell_hi
    write(unit, '(a)') "  effects = 'contacts', 'rotation'", "  eigen_solver = 'lanczos'", "/"
    close(unit)
    do r = 1, app_repeats
      t0 = progress_seconds()
      call execute_command_line(app//" -q "//dir//"/deck.nml -o "//dir//"/result.nml > /dev/null", &
        exitstat=exitstat)
      times(r) = progress_seconds() - t0
      if (exitstat /= 0) then
        write(output_unit, '(a, i0)') "# the app failed: exit status ", exitstat
        error stop 1
      end if
    end do
    t_app = median(times)
    call read_result(dir//"/result.nml", "scene_result", res, status)
    call require("the app's result")
    call result_get(res, "omega_max", omega, status)
    call require("omega_max")
    products = 0
    call result_get(res, "eigen_products", products, status)
    if (status%stat /= demstep_stat%ok) products = -1
  end subroutine run_app_files

  !> 1..n in order, or (`mixed`) in a fixed pseudo-random order (Fisher-Yates
  !> on the compiler's generator, its seed set from `seed`).
  function permutation(n, mixed, seed) result(p)
    integer, intent(in) :: n, seed
    logical, intent(in) :: mixed
    integer, allocatable :: p(:), put(:)
    real(dp) :: u
    integer :: i, j, t, m
    p = [(i, i = 1, n)]
    if (.not. mixed) return
    call random_seed(size=m)
    put = [(seed + 7919*i, i = 1, m)]
    call random_seed(put=put)
    do i = n, 2, -1
      call random_number(u)
      j = min(i, int(u*i) + 1)
      t = p(i)
      p(i) = p(j)
      p(j) = t
    end do
  end function permutation

  !> The median of a few values.
  real(dp) function median(x)
    real(dp), intent(in) :: x(:)
    real(dp) :: y(size(x)), t
    integer :: i, j
    y = x
    do i = 2, size(y)
      t = y(i)
      j = i - 1
      do while (j >= 1)
        if (y(j) <= t) exit
        y(j + 1) = y(j)
        j = j - 1
      end do
      y(j + 1) = t
    end do
    median = y((size(y) + 1)/2)
  end function median

  !> Mean coordination and mean overlap over the pair's mean radius.
  subroutine network_statistics(s, z, overlap)
    type(scene_type), intent(in) :: s
    real(dp), intent(out) :: z, overlap
    integer, allocatable :: i(:), j(:)
    real(dp), allocatable :: n(:, :), d(:)
    call contact_list(s, i, j, n, d, status)
    call require("contact_list")
    z = 2.0_dp*size(i)/s%n
    overlap = sum(d/(0.5_dp*(s%radius(i) + s%radius(j))))/size(i)
  end subroutine network_statistics

  !> Write A' (lower triangle, Matrix Market symmetric), run eigsh on it,
  !> remove the files; omega = rate sqrt(lambda).
  subroutine run_eigsh(s, t_write, t_eigsh, lam, omega)
    type(scene_type), intent(in) :: s
    real(dp), intent(out) :: t_write, t_eigsh, lam, omega
    type(assembly_operator_type) :: op
    type(csr_matrix_type) :: a
    real(dp) :: rate
    integer :: unit, exitstat, cmdstat, order
    character(len=256) :: msg
    character(len=8) :: word
    real(dp) :: eigsh_mb
    t0 = progress_seconds()
    call assembly_operator(s, op, rate, status)
    call require("assembly_operator")
    call assembly_matrix(op, a)
    call write_matrix_market(a, mtx)
    t_write = progress_seconds() - t0
    msg = ""
    ! (at most 20 minutes: a stalled eigsh is reported, not waited for; with
    ! OpenBLAS's own thread count, whatever this process was given)
    call execute_command_line("env -u OPENBLAS_NUM_THREADS timeout 1200 python3 bench/eigsh_scene.py " &
      //mtx//" 1e-6 > "//eigsh_out, &
      exitstat=exitstat, cmdstat=cmdstat, cmdmsg=msg)
    call delete_file(mtx)
    t_eigsh = -1.0_dp
    lam = 0.0_dp
    omega = 0.0_dp
    if (cmdstat /= 0 .or. exitstat /= 0) then
      write(output_unit, '(a, 2(1x, i0), 1x, a)') "# eigsh failed:", cmdstat, exitstat, trim(msg)
      call delete_file(eigsh_out)
      return
    end if
    open(newunit=unit, file=eigsh_out, status="old", action="read", iostat=ios)
    if (ios == 0) read(unit, *, iostat=ios) word, order, t_eigsh, lam, eigsh_mb
    if (ios == 0) close(unit, status="delete")
    if (ios /= 0 .or. order /= a%n) then
      write(output_unit, '(a)') "# eigsh: unreadable output"
      t_eigsh = -1.0_dp
      return
    end if
    omega = rate*sqrt(lam)
    write(output_unit, '(a, i0, a, a, a)') "# ", s%n, " particles: eigsh's peak memory (reading the " &
      //"file included) ", trim(fixed(eigsh_mb, 0)), " MB"
  end subroutine run_eigsh

  !> The lower triangle of a symmetric CSR matrix as a Matrix Market file
  !> ("coordinate real symmetric"), 17 significant digits, formatted by hand
  !> into a buffer (list-directed output of 1e8 entries would take minutes).
  subroutine write_matrix_market(a, path)
    type(csr_matrix_type), intent(in) :: a
    character(len=*), intent(in) :: path
    integer, parameter :: chunk = 4000000
    character(len=chunk + 128) :: buf
    character(len=64) :: header
    integer :: unit, i, pos
    integer(i8) :: p, entries
    entries = 0
    do i = 1, a%n
      do p = a%row_start(i), a%row_start(i + 1) - 1
        if (a%col(p) <= i) entries = entries + 1
      end do
    end do
    open(newunit=unit, file=path, access="stream", form="unformatted", status="replace", action="write")
    write(header, '(i0, 1x, i0, 1x, i0)') a%n, a%n, entries
    write(unit) "%%MatrixMarket matrix coordinate real symmetric"//new_line("a")//trim(header)//new_line("a")
    pos = 0
    do i = 1, a%n
      do p = a%row_start(i), a%row_start(i + 1) - 1
        if (a%col(p) > i) cycle
        call put_integer(buf, pos, i)
        pos = pos + 1
        buf(pos:pos) = " "
        call put_integer(buf, pos, a%col(p))
        pos = pos + 1
        buf(pos:pos) = " "
        call put_real(buf, pos, a%val(p))
        pos = pos + 1
        buf(pos:pos) = new_line("a")
        if (pos > chunk) then
          write(unit) buf(:pos)
          pos = 0
        end if
      end do
    end do
    if (pos > 0) write(unit) buf(:pos)
    close(unit)
  end subroutine write_matrix_market

  !> Append the decimal digits of k >= 0 at buf(pos+1:).
  subroutine put_integer(buf, pos, k)
    character(len=*), intent(inout) :: buf
    integer, intent(inout) :: pos
    integer, intent(in) :: k
    character(len=12) :: digits
    integer :: m, nd
    m = k
    nd = 0
    do
      nd = nd + 1
      digits(nd:nd) = achar(48 + mod(m, 10))
      m = m/10
      if (m == 0) exit
    end do
    do m = nd, 1, -1
      pos = pos + 1
      buf(pos:pos) = digits(m:m)
    end do
  end subroutine put_integer

  !> Append x as d.dddddddddddddddde+XXX (17 significant digits; the mantissa
  !> from x/10^e, good to a few units of the 17th digit).
  subroutine put_real(buf, pos, x)
    character(len=*), intent(inout) :: buf
    integer, intent(inout) :: pos
    real(dp), intent(in) :: x
    integer(i8) :: digits
    integer :: e, k
    character(len=17) :: text
    if (x == 0.0_dp) then
      buf(pos + 1:pos + 1) = "0"
      pos = pos + 1
      return
    end if
    if (x < 0.0_dp) then
      pos = pos + 1
      buf(pos:pos) = "-"
    end if
    e = floor(log10(abs(x)))
    digits = nint(abs(x)/10.0_dp**e*1.0e16_dp, i8)
    if (digits >= 100000000000000000_i8) then
      digits = digits/10_i8
      e = e + 1
    else if (digits < 10000000000000000_i8) then
      digits = digits*10_i8
      e = e - 1
    end if
    do k = 17, 1, -1
      text(k:k) = achar(48 + int(mod(digits, 10_i8)))
      digits = digits/10_i8
    end do
    buf(pos + 1:pos + 18) = text(1:1)//"."//text(2:17)
    pos = pos + 18
    pos = pos + 1
    buf(pos:pos) = "e"
    if (e < 0) then
      pos = pos + 1
      buf(pos:pos) = "-"
    end if
    call put_integer(buf, pos, abs(e))
  end subroutine put_real

  subroutine delete_file(path)
    character(len=*), intent(in) :: path
    integer :: unit, stat
    open(newunit=unit, file=path, status="old", iostat=stat)
    if (stat == 0) close(unit, status="delete")
  end subroutine delete_file

  !> Peak resident memory (VmHWM) in MB, 0 where /proc is missing.
  real(dp) function peak_megabytes() result(mb)
    integer :: unit, stat, kb
    character(len=128) :: line
    mb = 0.0_dp
    open(newunit=unit, file="/proc/self/status", status="old", action="read", iostat=stat)
    if (stat /= 0) return
    do
      read(unit, '(a)', iostat=stat) line
      if (stat /= 0) exit
      if (line(1:6) == "VmHWM:") then
        read(line(7:), *, iostat=stat) kb
        if (stat == 0) mb = kb/1024.0_dp
        exit
      end if
    end do
    close(unit)
  end function peak_megabytes

  !> x in fixed notation with d decimals (a leading 0 kept), "-" when negative.
  function fixed(x, d) result(text)
    real(dp), intent(in) :: x
    integer, intent(in) :: d
    character(len=24) :: text, form
    text = "-"
    if (x < 0.0_dp) return
    write(form, '(a, i0, a)') "(f24.", d, ")"
    write(text, form) x
    text = adjustl(text)
    if (d == 0) text = text(:len_trim(text) - 1)
  end function fixed

  function sci(x) result(text)
    real(dp), intent(in) :: x
    character(len=16) :: text
    write(text, '(es9.2)') x
    text = adjustl(text)
  end function sci

  !> a/b - 1, "-" when a was not computed.
  function relative(a, b) result(text)
    real(dp), intent(in) :: a, b
    character(len=16) :: text
    text = "-"
    if (a > 0.0_dp) write(text, '(es9.1)') a/b - 1.0_dp
    text = adjustl(text)
  end function relative

  function int_text(i) result(text)
    integer, intent(in) :: i
    character(len=:), allocatable :: text
    character(len=16) :: buf
    write(buf, '(i0)') i
    text = trim(buf)
  end function int_text

  subroutine require(what)
    character(len=*), intent(in) :: what
    if (status%stat /= demstep_stat%ok) then
      write(output_unit, '(a)') "bench_scene_eigen: "//what//": "//trim(status%message)
      error stop 1
    end if
  end subroutine require

end program bench_scene_eigen
