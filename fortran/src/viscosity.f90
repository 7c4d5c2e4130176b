!> Roelands pressure-temperature viscosity (SPEC section 5).
module ringlube_viscosity
  use ringlube_kinds, only: dp
  implicit none
  private
  public :: roelands

contains

  !> Viscosity [Pa s] at absolute pressure p [Pa] and film temperature theta [K].
  !>
  !> eta0 is the viscosity at theta0; alpha [1/Pa] the pressure-viscosity and beta [1/K]
  !> the viscosity-temperature coefficient. Gauge pressures below zero are not used by
  !> the solver (p >= p_cav >= 0); a negative p is treated as 0.
  elemental real(dp) function roelands(p, theta, eta0, theta0, alpha, beta)
    real(dp), intent(in) :: p, theta, eta0, theta0, alpha, beta
    real(dp) :: lnc, z0, s0, pp
    lnc = log(eta0) + 9.67_dp
    z0 = alpha / (5.1e-9_dp * lnc)
    s0 = beta * (theta0 - 138.0_dp) / lnc
    pp = max(p, 0.0_dp)
    roelands = eta0 * exp(lnc * (-1.0_dp + (1.0_dp + 5.1e-9_dp * pp)**z0 &
      * ((theta - 138.0_dp) / (theta0 - 138.0_dp))**(-s0)))
  end function roelands
end module ringlube_viscosity
