!> Progress of long library work (a scene run, a fine scan), reported through an
!> object the caller passes in.
!>
!> Numerical routines call `start` once with the amount of work, `update` as it
!> goes and `finish` at the end; they never write anything themselves. Extend
!> `progress_type` to show progress your way, or use `text_progress_type`, which
!> writes a line to a unit (stderr in the app) once the work has taken longer than
!> `delay` seconds, then every `interval` seconds, with an estimate of the time left.
!>
!>```fortran
!> type(text_progress_type) :: progress
!> progress = text_progress_type(unit=error_unit, label="&scene")
!> call scene_run(scene, dt, steps, summary, status, progress=progress)
!>```
module demstep_progress
  use demstep_kinds, only: dp, i8
  implicit none
  private

  public :: progress_type, text_progress_type, progress_seconds

  !> Receives the progress of long work.
  type, abstract :: progress_type
  contains
    !> Work begins: `total` units of `what` (e.g. "steps").
    procedure(progress_start), deferred :: start
    !> `done` units of the total are complete.
    procedure(progress_update), deferred :: update
    !> The work ended (completed or not).
    procedure(progress_finish), deferred :: finish
  end type progress_type

  abstract interface
    subroutine progress_start(self, what, total)
      import :: progress_type, i8
      class(progress_type), intent(inout) :: self
      character(len=*), intent(in) :: what
      integer(i8), intent(in) :: total
    end subroutine progress_start
    subroutine progress_update(self, done)
      import :: progress_type, i8
      class(progress_type), intent(inout) :: self
      integer(i8), intent(in) :: done
    end subroutine progress_update
    subroutine progress_finish(self)
      import :: progress_type
      class(progress_type), intent(inout) :: self
    end subroutine progress_finish
  end interface

  !> Progress as text lines on a unit: `LABEL: DONE of TOTAL WHAT (P %), about S s left`.
  type, extends(progress_type) :: text_progress_type
    !> Unit to write to.
    integer :: unit = 0
    !> Prefix of every line (e.g. "demstep: &scene").
    character(len=:), allocatable :: label
    !> Seconds of work before the first line.
    real(dp) :: delay = 3.0_dp
    !> Seconds between lines.
    real(dp) :: interval = 5.0_dp
    !> Lines written so far.
    integer :: lines = 0
    character(len=:), allocatable :: what
    integer(i8) :: total = 0, started = 0, last = 0
  contains
    procedure :: start => text_start
    procedure :: update => text_update
    procedure :: finish => text_finish
  end type text_progress_type

contains

  !> Wall-clock seconds since an arbitrary origin (monotonic, 64-bit count).
  function progress_seconds() result(t)
    real(dp) :: t
    integer(i8) :: count, rate
    call system_clock(count, rate)
    t = real(count, dp)/real(max(rate, 1_i8), dp)
  end function progress_seconds

  subroutine text_start(self, what, total)
    class(text_progress_type), intent(inout) :: self
    character(len=*), intent(in) :: what
    integer(i8), intent(in) :: total
    integer(i8) :: rate
    self%what = what
    self%total = total
    self%lines = 0
    call system_clock(self%started, rate)
    self%last = self%started
    if (.not. allocated(self%label)) self%label = "demstep"
  end subroutine text_start

  subroutine text_update(self, done)
    class(text_progress_type), intent(inout) :: self
    integer(i8), intent(in) :: done
    integer(i8) :: now, rate
    real(dp) :: elapsed, since, left
    character(len=32) :: pct, secs
    call system_clock(now, rate)
    rate = max(rate, 1_i8)
    elapsed = real(now - self%started, dp)/real(rate, dp)
    since = real(now - self%last, dp)/real(rate, dp)
    if (elapsed < self%delay) return
    if (self%lines > 0 .and. since < self%interval) return
    self%last = now
    self%lines = self%lines + 1
    if (self%total > 0 .and. done > 0) then
      write(pct, '(f6.1)') 100.0_dp*real(done, dp)/real(self%total, dp)
      left = elapsed*real(max(self%total - done, 0_i8), dp)/real(done, dp)
      secs = seconds_text(left)
      write(self%unit, '(a, i0, a, i0, a)') self%label//": ", done, " of ", self%total, &
        " "//self%what//" ("//trim(adjustl(pct))//" %), about "//trim(secs)//" s left"
    else
      write(self%unit, '(a, i0, a)') self%label//": ", done, " "//self%what
    end if
    flush(self%unit)
  end subroutine text_update

  subroutine text_finish(self)
    class(text_progress_type), intent(inout) :: self
    integer(i8) :: now, rate
    character(len=32) :: secs
    if (self%lines == 0) return
    call system_clock(now, rate)
    secs = seconds_text(real(now - self%started, dp)/real(max(rate, 1_i8), dp))
    write(self%unit, '(a)') self%label//": done in "//trim(secs)//" s"
    flush(self%unit)
  end subroutine text_finish

  !> Seconds as text: one decimal, or exponent form beyond 1e12.
  pure function seconds_text(t) result(text)
    real(dp), intent(in) :: t
    character(len=32) :: text
    if (abs(t) < 1.0e12_dp) then
      write(text, '(f16.1)') t
    else
      write(text, '(es10.3)') t
    end if
    text = adjustl(text)
  end function seconds_text

end module demstep_progress
