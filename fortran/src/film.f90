!> The film at one crank step: grid and profile, the film solve for a trial h0 (pressure
!> with the pressure-viscosity loop, hydrodynamic and asperity loads) and the friction
!> (docs/model.md, from "Film shape" to "Friction, power, energy").
!>
!> What the load balance (ringlube_load_balance) uses of a film model, and all a second
!> model has to provide: `film_evaluate` at a trial h0 (given 2 dh0/dt, the sliding speed,
!> the chamber pressure and the load tolerance in N), leaving `wh`, `wa`, `aa`, `flags`,
!> `h0` and the counters `film_solves` and `reynolds_solves` set; `film_friction` at the
!> accepted h0; `lead_left` set by the caller from the sign of u. Everything else in
!> film_type is this model's own state (warm starts of the next trial and step).
module ringlube_film
  use ringlube_kinds, only: dp
  use ringlube_case, only: case_type
  use ringlube_film_state, only: film_type, film_setup, roelands_p_max, film_temperature, film_copy
  use ringlube_film_reynolds, only: reynolds_evaluate
  use ringlube_film_jfo, only: jfo_evaluate
  implicit none
  private
  public :: film_type, film_setup, film_evaluate, film_friction, roelands_p_max, film_temperature, &
            film_copy

contains

  !> Solve the film for a trial h0: pressures (with the pressure-viscosity loop) and the
  !> hydrodynamic and asperity loads. `sq` is 2 dh0/dt; `p_chamber`, `p_crankcase` the
  !> edge pressures; `u` the sliding speed (its sign picks the inlet for the Reynolds outlet);
  !> `w_tol` [N] the load tolerance of the caller (the load balance accepts a load within
  !> w_tol of the applied load).
  !>
  !> The pressure-viscosity loop (Roelands) alternates a Reynolds solve with the viscosity
  !> of the pressure just solved. `f%eta` always holds the viscosity of the pressure in
  !> `f%p` of the previous solve (warm start). It stops when either
  !> - the viscosity update moves the load by less than a tenth of w_tol: the largest
  !>   relative change of eta over the nodes times W_h bounds the change of W_h the next
  !>   solve would make (the pressure above the edge values scales with eta), and the loop
  !>   contracts (alpha p << 1 at ring pressures), so the load then carries a viscosity
  !>   error below about w_tol/10; or
  !> - the pressure update is below `pressure_tol`: sum|p_new - p_old| <= pressure_tol
  !>   sum|p_new| (its meaning before the load criterion was added).
  !> Usually the first criterion ends the loop after one Reynolds solve.
  pure subroutine film_evaluate(c, f, h0, sq, u, p_chamber, w_tol)
    type(case_type), intent(in) :: c
    type(film_type), intent(inout) :: f
    real(dp), intent(in) :: h0, sq, u, p_chamber, w_tol
    f%h0 = h0
    f%flags = 0
    f%film_solves = f%film_solves + 1
    f%h = h0 + f%s
    f%hmid = h0 + f%smid
    if (f%jfo) then
      call jfo_evaluate(c, f, u, p_chamber, w_tol)
    else
      call reynolds_evaluate(c, f, sq, u, p_chamber, w_tol)
    end if
  end subroutine film_evaluate

  !> Viscous and boundary friction on the ring [N], positive towards the crankcase.
  !>
  !> Mass-conserving film: the shear of each interval is weighted like its flux (
  !> no shear where the flux carries no oil). The Couette shear `eta U / h` by the fill the
  !> Couette flux carries (the upwind node's), the Poiseuille shear `(h/2) dp/dx` by the fill
  !> the pressure-driven flux carries (the node at the higher pressure, as in the flux of
  !> ringlube_jfo), and at an edge face whose inflow was capped at the oil there by the share
  !> of that flux that is oil. So a gas-only interval (a gas-filled edge next to a cavity) has
  !> no shear, and a lifted ring whose gap holds a little oil has the shear of that oil only.
  !>
  !> Full-film cells: `tau = (h/2) dp/dx + eta U / h` at the cell midpoint. Cavitated cells
  !> (both ends at p_cav): Couette shear scaled by the film fraction `h_c / h`, h_c the
  !> gap at the upstream rupture node (the oil passes the ruptured zone as streamers of
  !> total thickness h_c). Boundary: `tau0 A_a + s W_a`, opposing the motion.
  !>
  !> A lifted ring (h0 at h0_ceiling: the film carries more than the load at every
  !> separation) has no friction: its friction is taken in the limit of unbounded
  !> separation, where the shear of the oil its gap holds (content / h^2) and the contact
  !> vanish, so that no answer depends on the numerical bound (docs/model.md, "Lift-off").
  pure subroutine film_friction(c, f, u, fv, fb)
    type(case_type), intent(in) :: c
    type(film_type), intent(in) :: f
    real(dp), intent(in) :: u
    real(dp), intent(out) :: fv, fb
    real(dp) :: tau, hc, theta
    integer :: i, j, n, step, first
    logical :: cav_l, cav_r

    n = f%n
    fv = 0.0_dp
    fb = 0.0_dp
    ! (the root finder works on ln h0: exp(log(h0_ceiling)) may be an ulp below the bound)
    if (f%h0 >= c%h0_ceiling * (1.0_dp - 1e-12_dp)) return
    if (f%jfo) then
      do i = 1, n - 1
        fv = fv + jfo_shear(i) * f%dx
      end do
      fv = -f%circ * fv
      fb = boundary()
      return
    end if
    if (f%lead_left) then
      first = 1
      step = 1
    else
      first = n - 1
      step = -1
    end if
    hc = f%hmid(first)
    do j = 0, n - 2
      i = first + step * j
      cav_l = cavitated(i)
      cav_r = cavitated(i + 1)
      if (cav_l .and. cav_r) then
        theta = min(1.0_dp, hc / f%hmid(i))
        tau = f%etamid(i) * u / f%hmid(i) * theta
      else
        tau = 0.5_dp * f%hmid(i) * (f%p(i + 1) - f%p(i)) / f%dx + f%etamid(i) * u / f%hmid(i)
        ! gap at the upstream end of this cell, the rupture point if the next cell is dry
        if (step == 1) then
          hc = f%h(i + 1)
        else
          hc = f%h(i)
        end if
      end if
      fv = fv + tau * f%dx
    end do
    fv = -f%circ * fv
    fb = boundary()

  contains

    !> Boundary friction tau0 A_a + s W_a, opposing the motion (0 at a dead centre).
    pure real(dp) function boundary()
      if (u > 0.0_dp) then
        boundary = -(c%tau0 * f%aa + c%boundary_coefficient * f%wa)
      else if (u < 0.0_dp) then
        boundary = c%tau0 * f%aa + c%boundary_coefficient * f%wa
      else
        boundary = 0.0_dp
      end if
    end function boundary

    !> Shear [Pa] of interval i (nodes i, i+1) of the mass-conserving film, weighted like
    !> its flux (see above).
    pure real(dp) function jfo_shear(i)
      integer, intent(in) :: i
      real(dp) :: g, wp, wc, c_flux, p_flux, q_act
      g = f%kmid(i) * (f%p(i + 1) - f%p(i)) / f%dx
      wp = merge(f%theta(i), f%theta(i + 1), g <= 0.0_dp)
      wc = merge(f%theta(i), f%theta(i + 1), u < 0.0_dp)
      if (i == 1 .or. i == n - 1) then
        ! an edge face: the flux actually carried (capped at the oil there) against the
        ! uncapped one; the cut falls on the pressure-driven part, then on the Couette part
        c_flux = -0.5_dp * u * wc * f%hmid(i)
        p_flux = -g * wp
        if (i == 1) then
          q_act = f%q_face_left
        else
          q_act = f%q_face_right
        end if
        if (abs(q_act - (c_flux + p_flux)) > 1e-12_dp * (abs(c_flux) + abs(p_flux))) then
          if (abs(p_flux) > 0.0_dp) wp = wp * min(1.0_dp, max(0.0_dp, (q_act - c_flux) / p_flux))
          if (abs(c_flux) > 0.0_dp .and. (q_act - c_flux) * c_flux < 0.0_dp .and. &
              abs(q_act) < abs(c_flux)) wc = wc * max(0.0_dp, q_act / c_flux)
        end if
      end if
      jfo_shear = wp * 0.5_dp * f%hmid(i) * (f%p(i + 1) - f%p(i)) / f%dx + &
                  wc * f%etamid(i) * u / f%hmid(i)
    end function jfo_shear

    pure logical function cavitated(k)
      integer, intent(in) :: k
      if (k == 1 .or. k == n) then
        cavitated = f%trailing_cavitated .and. (f%lead_left .eqv. (k == n))
      else
        cavitated = f%active(k)
      end if
    end function cavitated
  end subroutine film_friction
end module ringlube_film
