!> The mass-conserving film (SPEC section 13) at the trial h0 in f%h: the JFO solve of
!> ringlube_jfo (and its connectivity rule) inside the pressure-viscosity loop.
module ringlube_film_jfo
  use ringlube_kinds, only: dp
  use ringlube_case, only: case_type
  use ringlube_results, only: flag_cavitation, flag_overdraw
  use ringlube_jfo, only: jfo_solve, jfo_problem, jfo_stats, JFO_OK
  use ringlube_jfo_connect, only: jfo_solve_connected
  use ringlube_oil_supply, only: inlet_fill
  use ringlube_film_state, only: film_type, lower_edge_pressure, start_viscosity, conductance, &
                                 update_viscosity, film_loads
  implicit none
  private
  public :: jfo_evaluate

contains

  !> The mass-conserving film at the trial h0 in f%h (SPEC 13): the JFO solve of
  !> ringlube_jfo inside the same pressure-viscosity loop as the Swift-Stieber film. Both
  !> edges are liquid boundaries held at their gas pressures; the content theta h of the last
  !> accepted step gives the time term (backward Euler on the content, whatever the
  !> time_scheme of the squeeze term of the Swift-Stieber film). The leading edge admits oil of
  !> fill 1 (flooded) or, starved, the fill the available oil gives (`inlet_fill`); the
  !> trailing edge admits oil of fill 1 (pushed back in by its gas pressure). Starved, the net
  !> oil entering through either edge over the step is capped at the oil there (the leading
  !> edge's strip and bank, the liner film just behind the trailing edge: `f%available`,
  !> `f%behind`), inside the solve; beyond the cap the edge admits gas. 'trailing_gas' puts a
  !> cavity reaching the trailing edge at that edge's gas pressure; a starved inlet's partly
  !> filled zone is at the leading edge's gas pressure (the connectivity rule of ringlube_jfo).
  pure subroutine jfo_evaluate(c, f, u, p_chamber, w_tol)
    type(case_type), intent(in) :: c
    type(film_type), intent(inout) :: f
    real(dp), intent(in) :: u, p_chamber, w_tol
    real(dp) :: v_in, h_le, qlead, qtrail
    integer :: it, n
    logical :: settled
    type(jfo_problem) :: prob
    type(jfo_stats) :: stats

    n = f%n
    prob = jfo_problem(dx=f%dx, u=u, dt=f%dt, p_left=p_chamber, &
                       p_right=lower_edge_pressure(c, f), p_cav=c%cavitation_pressure, &
                       trailing_gas=c%cavity_pressure == 'trailing_gas', leading_gas=f%starved)
    if (f%lead_left) then
      h_le = f%hmid(1)
    else
      h_le = f%hmid(n - 1)
    end if
    f%theta_in = 1.0_dp
    qlead = huge(1.0_dp)
    qtrail = huge(1.0_dp)
    if (f%starved) then
      f%theta_in = inlet_fill(f%available, h_le, f%ds)
      ! each edge admits at most the oil there over the step
      if (f%dt > 0.0_dp) then
        qlead = max(f%available, 0.0_dp) / f%dt
        qtrail = max(f%behind, 0.0_dp) / f%dt
      end if
    end if
    if (f%lead_left) then
      prob%theta_left = f%theta_in
      prob%cap_left = qlead
      prob%cap_right = qtrail
    else
      prob%theta_right = f%theta_in
      prob%cap_left = qtrail
      prob%cap_right = qlead
    end if
    f%cap_left = prob%cap_left
    f%cap_right = prob%cap_right
    if (f%gas_channel .and. f%face_open) &
      prob%gas_channel = gas_channel_pressure(f, prob%p_left, prob%p_right)
    call start_viscosity(c, f)
    do it = 1, c%max_pressure_iterations
      call conductance(f, 12.0_dp)
      if (prob%leading_gas .or. prob%trailing_gas .or. allocated(prob%gas_channel)) then
        call jfo_solve_connected(prob, f%h, f%hmid, f%kmid, f%content_old, f%pc, f%p, f%theta, &
                                 stats, work=f%jfo_work, scratch=f%jfo_scratch)
      else
        f%pc = c%cavitation_pressure
        call jfo_solve(prob, f%h, f%hmid, f%kmid, f%content_old, f%pc, f%p, f%theta, stats, &
                       work=f%jfo_work, scratch=f%jfo_scratch)
      end if
      f%q_left = stats%q_left
      f%q_right = stats%q_right
      f%blown = stats%blown
      f%reynolds_solves = f%reynolds_solves + stats%iterations
      if (stats%info /= JFO_OK) f%flags = ior(f%flags, flag_cavitation)
      if (.not. c%roelands) exit
      call update_viscosity(c, f, w_tol, it, settled)
      if (settled) exit
    end do
    if (f%starved) then
      ! oil entering through the leading edge over the step must be oil that is there (the
      ! cap inside the solve ensures it; a solve that ended unconverged may not)
      if (f%lead_left) then
        v_in = f%q_left * f%dt
      else
        v_in = -f%q_right * f%dt
      end if
      if (v_in > f%available * (1.0_dp + 1e-9_dp) + 1e-30_dp) f%flags = ior(f%flags, flag_overdraw)
    end if

    call film_loads(c, f)
  end subroutine jfo_evaluate

  !> The pressure of the gas flowing through the face of film f from the left edge (at p_l)
  !> to the right (at p_r), a face open from edge to edge (SPEC 15): an isothermal laminar
  !> channel whose gap is the gap not taken by the oil, g = h - theta h (the content of the
  !> last accepted step), so that p^2 falls along the face as the integral of dx / g^3:
  !> linearly across a uniform gap, and nearly all at once where the oil almost closes it.
  !> Whether the face is open is decided at the last step (film_type%face_open), so that the
  !> film's load is continuous in h0 within a step (a full zone forming in a trial builds its
  !> pressure from the channel's).
  pure function gas_channel_pressure(f, p_l, p_r) result(pg)
    type(film_type), intent(in) :: f
    real(dp), intent(in) :: p_l, p_r
    real(dp) :: pg(f%n), g(f%n), r(f%n - 1), cum
    integer :: i
    g = max(f%h - f%content_old, 1e-6_dp * f%h)
    r = 1.0_dp / (0.5_dp * (g(1:f%n - 1) + g(2:f%n)))**3
    pg(1) = p_l
    cum = 0.0_dp
    do i = 2, f%n
      cum = cum + r(i - 1)
      pg(i) = cum
    end do
    pg(2:f%n) = sqrt(max(p_l**2 + (p_r**2 - p_l**2) * pg(2:f%n) / cum, 0.0_dp))
  end function gas_channel_pressure
end module ringlube_film_jfo
