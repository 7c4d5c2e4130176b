!> Slider-crank kinematics of the piston.
module ringlube_kinematics
  use ringlube_kinds, only: dp, pi
  implicit none
  private
  public :: sliding_speed, piston_position, piston_acceleration, deg2rad

contains

  !> Degrees to radians.
  elemental real(dp) function deg2rad(deg)
    real(dp), intent(in) :: deg
    deg2rad = deg * pi / 180.0_dp
  end function deg2rad

  !> Piston distance from TDC towards the crankcase [m] at crank angle psi [rad].
  elemental real(dp) function piston_position(psi, crank_radius, conrod_length)
    real(dp), intent(in) :: psi, crank_radius, conrod_length
    real(dp) :: r, l
    r = crank_radius
    l = conrod_length
    piston_position = r * (1.0_dp - cos(psi)) + l - sqrt(l**2 - (r * sin(psi))**2)
  end function piston_position

  !> Piston sliding speed [m/s], positive towards the crankcase:
  !> `U = r w sin(psi) (1 + cos(psi)/sqrt((l/r)^2 - sin(psi)^2))`.
  elemental real(dp) function sliding_speed(psi, crank_radius, conrod_length, omega)
    real(dp), intent(in) :: psi, crank_radius, conrod_length, omega
    real(dp) :: s
    s = sin(psi)
    sliding_speed = crank_radius * omega * s &
                    * (1.0_dp + cos(psi) / sqrt((conrod_length / crank_radius)**2 - s**2))
  end function sliding_speed

  !> Piston acceleration [m/s^2], positive towards the crankcase: the crank-angle
  !> derivative of `sliding_speed` times omega,
  !> `a = r w^2 (cos(psi) + cos(2 psi)/S + sin(psi)^2 cos(psi)^2 / S^3)`,
  !> `S = sqrt((l/r)^2 - sin(psi)^2)`.
  elemental real(dp) function piston_acceleration(psi, crank_radius, conrod_length, omega)
    real(dp), intent(in) :: psi, crank_radius, conrod_length, omega
    real(dp) :: s, c, q
    s = sin(psi)
    c = cos(psi)
    q = sqrt((conrod_length / crank_radius)**2 - s**2)
    piston_acceleration = crank_radius * omega**2 &
                          * (c + cos(2.0_dp * psi) / q + (s * c)**2 / q**3)
  end function piston_acceleration
end module ringlube_kinematics
