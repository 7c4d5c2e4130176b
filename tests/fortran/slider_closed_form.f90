!> The parabolic ring of the film tests (test_reynolds, test_jfo) and its closed forms at
!> constant viscosity: film thickness h = h0 + kk z^2 (z = x + xs, the crown offset xs) and
!> the antiderivatives J1 = int dz/h, J2 = int dz/h^2, J3 = int dz/h^3 from which the exact
!> pressures of the Reynolds equation are written.
module slider_closed_form
  use ringlube_kinds, only: dp
  implicit none
  private
  public :: b, crown, xs, h0, eta, kk, ns, hz, j1, j2, j3
  !> ring width, crown height, crown offset, minimum film (m); viscosity (Pa s)
  real(dp), parameter :: b = 1e-3_dp, crown = 10e-6_dp, xs = -38e-6_dp, h0 = 1e-6_dp
  real(dp), parameter :: eta = 0.01_dp, kk = crown / (0.5_dp * b)**2
  !> the grids of the convergence studies (nodes)
  integer, parameter :: ns(4) = [51, 101, 201, 401]

contains

  !> film thickness at z = x + xs
  elemental real(dp) function hz(z)
    real(dp), intent(in) :: z
    hz = h0 + kk * z * z
  end function hz

  !> int dz / (h0 + kk z^2)
  elemental real(dp) function j1(z)
    real(dp), intent(in) :: z
    j1 = atan(z * sqrt(kk / h0)) / sqrt(h0 * kk)
  end function j1
  !> int dz / h^2
  elemental real(dp) function j2(z)
    real(dp), intent(in) :: z
    j2 = z / (2 * h0 * hz(z)) + j1(z) / (2 * h0)
  end function j2
  !> int dz / h^3
  elemental real(dp) function j3(z)
    real(dp), intent(in) :: z
    j3 = z / (4 * h0 * hz(z)**2) + 3 * j2(z) / (4 * h0)
  end function j3
end module slider_closed_form
