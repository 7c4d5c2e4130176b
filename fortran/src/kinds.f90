!> Working precision and mathematical constants shared by every ringlube module.
module ringlube_kinds
  use, intrinsic :: iso_fortran_env, only: real64
  implicit none
  private

  !> Double precision used throughout the kernel.
  integer, parameter, public :: dp = real64
  real(dp), parameter, public :: pi = 3.14159265358979323846264338327950288_dp
end module ringlube_kinds
