!> Slider-crank kinematics of the piston (SPEC section 2).
module ringlube_kinematics
  use ringlube_kinds, only: dp, pi
  implicit none
  private
  public :: sliding_speed, piston_position, deg2rad

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
end module ringlube_kinematics
