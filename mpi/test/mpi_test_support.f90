!> What every MPI test program shares: MPI started and stopped with the
!> summary line, a check reported once (rank 0) and failed when it fails on
!> any rank, a random sequence that is the same on every rank, the
!> comparisons of a value or a status across the ranks, and a scratch file's deletion.
module mpi_test_support
  use mpi_f08
  use demstep_kinds, only: dp, i8
  use demstep_status, only: demstep_status_type
  implicit none
  private

  public :: test_start, test_finish, report, uniform, random_particles, num, close, same_everywhere, msg, &
    same_status, delete

  !> This rank, the ranks of MPI_COMM_WORLD and the checks failed so far.
  integer, public, protected :: rank = 0, nranks = 1, failures = 0

  !> State of the random sequence (`uniform`).
  integer(i8) :: seed = 1_i8

contains

  !> Start MPI and the counts; `first` seeds `uniform` (> 0).
  subroutine test_start(first)
    integer(i8), intent(in) :: first
    call MPI_Init()
    call MPI_Comm_rank(MPI_COMM_WORLD, rank)
    call MPI_Comm_size(MPI_COMM_WORLD, nranks)
    failures = 0
    seed = first
  end subroutine test_start

  !> The summary line of program `name` (rank 0), MPI stopped, and a non-zero
  !> exit status when a check failed.
  subroutine test_finish(name)
    character(len=*), intent(in) :: name
    if (rank == 0) then
      if (failures == 0) then
        write (*, '(a, i0, a)') name//": all checks passed on ", nranks, " ranks"
      else
        write (*, '(a, i0, a, i0, a)') name//": ", failures, " checks FAILED on ", nranks, " ranks"
      end if
    end if
    call MPI_Finalize()
    if (failures > 0) error stop 1
  end subroutine test_finish

  !> One PASS/FAIL line (rank 0): the check passes when `ok` holds on every
  !> rank. Collective.
  subroutine report(name, ok, detail)
    character(len=*), intent(in) :: name
    logical, intent(in) :: ok
    character(len=*), intent(in) :: detail
    logical :: all_ok
    call MPI_Allreduce(ok, all_ok, 1, MPI_LOGICAL, MPI_LAND, MPI_COMM_WORLD)
    if (.not. all_ok) failures = failures + 1
    if (rank == 0) then
      if (all_ok) then
        write (*, '(a)') "PASS "//name//" "//detail
      else
        write (*, '(a)') "FAIL "//name//" "//detail
      end if
    end if
  end subroutine report

  !> Uniform (0,1) from a 64-bit linear congruential sequence: the same on every rank.
  function uniform() result(u)
    real(dp) :: u
    seed = mod(48271_i8*seed, 2147483647_i8)
    u = real(seed, dp)/2147483647.0_dp
  end function uniform

  !> `count` particles at random in [0, box)^dim (`uniform`, the same on every
  !> rank): positions, radii 0.4..0.7 and masses 1..2, drawn particle by
  !> particle.
  subroutine random_particles(dim, count, box, x, r, m)
    integer, intent(in) :: dim, count
    real(dp), intent(in) :: box
    real(dp), allocatable, intent(out) :: x(:, :), r(:), m(:)
    integer :: i, d
    allocate(x(dim, count), r(count), m(count))
    do i = 1, count
      do d = 1, dim
        x(d, i) = box*uniform()
      end do
      r(i) = 0.4_dp + 0.3_dp*uniform()
      m(i) = 1.0_dp + uniform()
    end do
  end subroutine random_particles

  !> A value with all its digits, for a report's detail.
  function num(x) result(text)
    real(dp), intent(in) :: x
    character(len=24) :: text
    write (text, '(es24.16)') x
  end function num

  !> |a - b| <= rel |b|.
  logical function close(a, b, rel)
    real(dp), intent(in) :: a, b, rel
    close = abs(a - b) <= rel*abs(b)
  end function close

  !> True when x is the same on every rank, bit for bit. Collective.
  logical function same_everywhere(x)
    real(dp), intent(in) :: x
    real(dp) :: lo, hi
    call MPI_Allreduce(x, lo, 1, MPI_DOUBLE_PRECISION, MPI_MIN, MPI_COMM_WORLD)
    call MPI_Allreduce(x, hi, 1, MPI_DOUBLE_PRECISION, MPI_MAX, MPI_COMM_WORLD)
    same_everywhere = lo == x .and. hi == x
  end function same_everywhere

  !> The status's message, '' on success.
  function msg(st) result(text)
    type(demstep_status_type), intent(in) :: st
    character(len=:), allocatable :: text
    text = ""
    if (allocated(st%message)) text = st%message
  end function msg

  !> True when every rank holds this status code and message length. Collective.
  logical function same_status(st)
    type(demstep_status_type), intent(in) :: st
    integer :: mine(2), lo(2), hi(2)
    mine = [st%stat, len(msg(st))]
    call MPI_Allreduce(mine, lo, 2, MPI_INTEGER, MPI_MIN, MPI_COMM_WORLD)
    call MPI_Allreduce(mine, hi, 2, MPI_INTEGER, MPI_MAX, MPI_COMM_WORLD)
    same_status = all(lo == mine) .and. all(hi == mine)
  end function same_status

  !> Delete a file if it exists (a test's scratch tables).
  subroutine delete(path)
    character(len=*), intent(in) :: path
    integer :: u, ios
    open (newunit=u, file=path, status="old", iostat=ios)
    if (ios == 0) close (u, status="delete")
  end subroutine delete

end module mpi_test_support
