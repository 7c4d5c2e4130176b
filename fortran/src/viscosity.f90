!> Roelands pressure-temperature viscosity, the one home of the formula.
module ringlube_viscosity
  use ringlube_kinds, only: dp
  implicit none
  private
  public :: roelands_law, roelands_law_at, roelands_eta, roelands, roelands_through, &
            roelands_update

  !> The constants of Roelands' law at one film temperature:
  !> `eta = eta0 exp(lnc (-1 + rtheta (1 + 5.1e-9 p)^z0))`.
  type :: roelands_law
    real(dp) :: eta0 = 0.0_dp   !< Pa s at theta0
    real(dp) :: lnc = 0.0_dp    !< ln eta0 + 9.67
    real(dp) :: z0 = 0.0_dp     !< alpha / (5.1e-9 lnc)
    !> ((theta - 138)/(theta0 - 138))^(-s0), s0 = beta (theta0 - 138) / lnc
    real(dp) :: rtheta = 0.0_dp
  end type roelands_law

contains

  !> The law at film temperature theta [K]; eta0 [Pa s] is the viscosity at theta0 [K],
  !> alpha [1/Pa] the pressure-viscosity and beta [1/K] the viscosity-temperature
  !> coefficient.
  pure function roelands_law_at(theta, eta0, theta0, alpha, beta) result(law)
    real(dp), intent(in) :: theta, eta0, theta0, alpha, beta
    type(roelands_law) :: law
    law%eta0 = eta0
    law%lnc = log(eta0) + 9.67_dp
    law%z0 = alpha / (5.1e-9_dp * law%lnc)
    law%rtheta = ((theta - 138.0_dp) / (theta0 - 138.0_dp))**(-beta * (theta0 - 138.0_dp) / law%lnc)
  end function roelands_law_at

  !> The law's eta0 [Pa s], theta0 [K] and beta [1/K] through two viscosities at p = 0:
  !> eta1 at theta1 and eta2 at theta2 [K] (theta1 < theta2, both viscosities above the
  !> Roelands reference 6.3e-5 Pa s). At p = 0 the law is
  !> `ln eta + 9.67 = (ln eta0 + 9.67) ((theta - 138)/(theta0 - 138))^(-s0)`: with theta0 =
  !> theta1 and eta0 = eta1 it passes through the first point for every s0, and
  !> `s0 = -ln((ln eta2 + 9.67)/(ln eta1 + 9.67)) / ln((theta2 - 138)/(theta1 - 138))` puts it
  !> through the second; beta = s0 (ln eta0 + 9.67)/(theta0 - 138) (the law's slope
  !> -d ln eta/d theta at theta0).
  pure subroutine roelands_through(theta1, eta1, theta2, eta2, eta0, theta0, beta)
    real(dp), intent(in) :: theta1, eta1, theta2, eta2
    real(dp), intent(out) :: eta0, theta0, beta
    real(dp) :: lnc1, s0
    lnc1 = log(eta1) + 9.67_dp
    s0 = -log((log(eta2) + 9.67_dp) / lnc1) / log((theta2 - 138.0_dp) / (theta1 - 138.0_dp))
    eta0 = eta1
    theta0 = theta1
    beta = s0 * lnc1 / (theta1 - 138.0_dp)
  end subroutine roelands_through

  !> Viscosity [Pa s] at absolute pressure p >= 0 [Pa] (one exp-log pair per call for the
  !> pressure factor, the temperature factor folded into the law).
  elemental real(dp) function roelands_eta(law, p)
    type(roelands_law), intent(in) :: law
    real(dp), intent(in) :: p
    roelands_eta = law%eta0 * exp(law%lnc * (-1.0_dp + law%rtheta &
                                             * exp(law%z0 * log(1.0_dp + 5.1e-9_dp * p))))
  end function roelands_eta

  !> The viscosity step of a pressure-viscosity iteration over n nodes: where the pressure p(i)
  !> differs from the last iteration's pold(i), eta(i) = roelands_eta(law, p(i) clipped to
  !> [0, p_max]); elsewhere eta(i) is kept. dvisc: the largest relative change of eta. Here, in
  !> the law's module, the law is evaluated inline (no call per node).
  pure subroutine roelands_update(law, n, p, pold, p_max, eta, dvisc)
    type(roelands_law), intent(in) :: law
    integer, intent(in) :: n
    real(dp), intent(in) :: p(n), pold(n), p_max
    real(dp), intent(inout) :: eta(n)
    real(dp), intent(out) :: dvisc
    real(dp) :: e
    integer :: i
    dvisc = 0.0_dp
    do i = 1, n
      if (p(i) /= pold(i)) then
        e = roelands_eta(law, min(max(p(i), 0.0_dp), p_max))
        dvisc = max(dvisc, abs(e - eta(i)) / eta(i))
        eta(i) = e
      end if
    end do
  end subroutine roelands_update

  !> Viscosity [Pa s] at absolute pressure p [Pa] and film temperature theta [K]. Gauge
  !> pressures below zero are not used by the solver (p >= p_cav >= 0); a negative p is
  !> treated as 0.
  elemental real(dp) function roelands(p, theta, eta0, theta0, alpha, beta)
    real(dp), intent(in) :: p, theta, eta0, theta0, alpha, beta
    roelands = roelands_eta(roelands_law_at(theta, eta0, theta0, alpha, beta), max(p, 0.0_dp))
  end function roelands
end module ringlube_viscosity
