!> The one kind module of demstep.
module demstep_kinds
  use, intrinsic :: iso_fortran_env, only: real32, real64, int64
  implicit none
  private

  !> Working precision of every real in the library.
  integer, parameter, public :: dp = real64
  !> Storage precision where a vector may be kept rounded (the Lanczos
  !> vectors of `demstep_lanczos`'s single run, at loose tolerances).
  integer, parameter, public :: sp = real32
  !> Integer kind for step counts.
  integer, parameter, public :: i8 = int64
  !> pi to working precision.
  real(dp), parameter, public :: pi = 3.14159265358979323846264338327950288_dp
end module demstep_kinds
