!> Version of the demstep package.
module demstep_version
  implicit none
  private
  !> Version string, as in fpm.toml.
  character(len=*), parameter, public :: demstep_version_string = "0.1.0"
end module demstep_version
