!> The mass-conserving film (docs/film_model.md) at the trial h0 in f%h: the JFO solve of
!> ringlube_jfo (and its connectivity rule) inside the pressure-viscosity loop.
module ringlube_film_jfo
  use ringlube_kinds, only: dp
  use ringlube_case, only: case_type
  use ringlube_results, only: flag_cavitation, flag_overdraw
  use ringlube_jfo, only: jfo_solve, jfo_problem, jfo_stats, JFO_OK
  use ringlube_jfo_connect, only: jfo_solve_connected
  use ringlube_jfo_system, only: jfo_front_content
  use ringlube_oil_supply, only: inlet_fill
  use ringlube_film_state, only: film_type, lower_edge_pressure, start_viscosity, conductance, &
                                 update_viscosity, film_loads
  implicit none
  private
  public :: jfo_evaluate

contains

  !> The mass-conserving film at the trial h0 in f%h: the JFO solve of
  !> ringlube_jfo inside the same pressure-viscosity loop as the Swift-Stieber film. Both
  !> edges are liquid boundaries held at their gas pressures; the content theta h of the last
  !> accepted step gives the time term (`&numerics film_time_scheme`: backward Euler on the
  !> content, or BDF2 through the history of step_history). The leading edge admits oil of
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
    real(dp) :: v_in, h_le, qlead, qtrail, dte, r, x_lead, x_trail
    integer :: it, n
    logical :: settled
    type(jfo_problem) :: prob
    type(jfo_stats) :: stats

    n = f%n
    call step_history(c, f, u)
    r = f%r_step
    ! BDF2 is backward Euler over 2/3 of the step from the history content (r = 1/3)
    dte = f%dt
    if (r > 0.0_dp) dte = f%dt * (1.0_dp - r)
    prob = jfo_problem(dx=f%dx, u=u, dt=dte, p_left=p_chamber, &
                       p_right=lower_edge_pressure(c, f), p_cav=c%cavitation_pressure, &
                       trailing_gas=c%cavity_pressure == 'trailing_gas', leading_gas=f%starved)
    prob%edge_cells = f%edge_cells
    prob%edge_meniscus = f%edge_cells
    prob%front_content = f%front_content
    if (f%lead_left) then
      h_le = f%hmid(1)
      x_lead = f%x_left_prev
      x_trail = -f%x_right_prev
    else
      h_le = f%hmid(n - 1)
      x_lead = -f%x_right_prev
      x_trail = f%x_left_prev
    end if
    f%theta_in = 1.0_dp
    qlead = huge(1.0_dp)
    qtrail = huge(1.0_dp)
    if (f%starved) then
      f%theta_in = inlet_fill(f%available, h_le, f%ds)
      ! each edge admits at most the oil there over the step
      if (f%dt > 0.0_dp) then
        qlead = max(max(f%available, 0.0_dp) - r * x_lead, 0.0_dp) / dte
        qtrail = max(max(f%behind, 0.0_dp) - r * x_trail, 0.0_dp) / dte
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
    associate (content => f%content_hist)
      if (r == 0.0_dp) content = f%content_old
      do it = 1, c%max_pressure_iterations
        call conductance(f, 12.0_dp)
        if (prob%leading_gas .or. prob%trailing_gas .or. allocated(prob%gas_channel)) then
          call jfo_solve_connected(prob, f%h, f%hmid, f%kmid, content, f%pc, f%p, f%theta, &
                                   stats, work=f%jfo_work, scratch=f%jfo_scratch)
        else
          f%pc = c%cavitation_pressure
          call jfo_solve(prob, f%h, f%hmid, f%kmid, content, f%pc, f%p, f%theta, stats, &
                         work=f%jfo_work, scratch=f%jfo_scratch)
        end if
        f%q_face_left = stats%q_left
        f%q_face_right = stats%q_right
        f%blown = stats%blown
        f%reynolds_solves = f%reynolds_solves + stats%iterations
        if (stats%info /= JFO_OK) f%flags = ior(f%flags, flag_cavitation)
        if (.not. c%roelands) exit
        call update_viscosity(c, f, w_tol, it, settled)
        if (settled) exit
      end do
    end associate
    ! the oil through the edge faces over the step: the flux at the step's end (backward
    ! Euler), or its BDF2 filter, whose sum over the faces is the content's change
    if (r == 0.0_dp) then
      f%q_left = f%q_face_left
      f%q_right = f%q_face_right
    else
      f%q_left = (dte * f%q_face_left + r * f%x_left_prev) / f%dt
      f%q_right = (dte * f%q_face_right + r * f%x_right_prev) / f%dt
    end if
    f%x_left = f%q_left * f%dt
    f%x_right = f%q_right * f%dt
    if (f%starved) then
      ! oil entering through the leading edge over the step must be oil that is there (the
      ! cap inside the solve ensures it; a solve that ended unconverged may not)
      if (f%lead_left) then
        v_in = f%x_left
      else
        v_in = -f%x_right
      end if
      if (v_in > f%available * (1.0_dp + 1e-9_dp) + 1e-30_dp) f%flags = ior(f%flags, flag_overdraw)
    end if
    if (f%front_content) then
      f%content_end = jfo_front_content(prob, f%h, f%hmid, f%kmid, f%pc, f%p, f%theta)
    else
      f%content_end = f%theta * f%h
    end if
    f%held_end = f%h0 <= c%h0_floor * (1.0_dp + 1e-12_dp) .or. &
                 f%h0 >= c%h0_ceiling * (1.0_dp - 1e-12_dp)
    if (c%bore == 'distorted') f%held_end = f%held_end .or. &
                                            f%h0 >= c%back_clearance * (1.0_dp - 1e-12_dp)

    call film_loads(c, f)
  end subroutine jfo_evaluate

  !> The pressure of the gas flowing through the face of film f from the left edge (at p_l)
  !> to the right (at p_r), a face open from edge to edge (docs/bore.md): an isothermal laminar
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

  !> The content's time history at an evaluation of the film (BDF2 of the content,
  !> `&numerics film_time_scheme`; docs/film_model.md "Time"). The film is evaluated several times
  !> a crank step (the load balance's trials) from the same last content; a new step starts
  !> when the sliding speed or the last content changes. If the last content is the state of
  !> the last evaluation (the cycle accepted it: content_old = theta h), the history moves on
  !> a step; any other content (the start of a run) restarts it. The step's weight r: 1/3
  !> (BDF2: the content's change is 2/3 of the backward-Euler change over the step plus 1/3
  !> of the last step's change, and the exchanges with the liner are filtered alike), or 0
  !> (backward Euler) with film_time_scheme = 'euler', in the first two steps, at and after a dead
  !> centre or a reversal, and after a step whose h0 came to or left a bound. r is lowered
  !> below 1/3 where the history content would be negative at a node, or where the oil the
  !> last step drew through an edge would leave none to draw over this one.
  pure subroutine step_history(c, f, u)
    type(case_type), intent(in) :: c
    type(film_type), intent(inout) :: f
    real(dp), intent(in) :: u
    real(dp) :: r, x_lead, x_trail
    integer :: i, n, su
    n = f%n
    if (f%hist_steps > 0) then
      if (u == f%u_key .and. all(f%content_old == f%content_key)) return
    end if
    su = sign_of(u)
    if (f%hist_steps > 0 .and. all(f%content_old == f%content_end)) then
      f%content_prev = f%content_key
      f%x_left_prev = f%x_left
      f%x_right_prev = f%x_right
      f%sign_prev(2:4) = f%sign_prev(1:3)
      f%sign_prev(1) = sign_of(f%u_key)
      f%held_prev(2) = f%held_prev(1)
      f%held_prev(1) = f%held_end
      f%hist_steps = f%hist_steps + 1
    else
      f%hist_steps = 1
    end if
    f%content_key = f%content_old
    f%u_key = u
    f%r_step = 0.0_dp
    if (c%film_time_scheme /= 'bdf2' .or. f%hist_steps < 3 .or. .not. f%dt > 0.0_dp) return
    ! four steps on this side of a dead centre (at a reversal the cavities move to the other
    ! side within a step: a difference across it is not a derivative; with only the two earlier
    ! contents on this side the liner film near the dead centres settled over the cycles
    ! 1.5-2.4 times slower on the starved decks)
    if (su == 0 .or. any(f%sign_prev /= su)) return
    if (f%held_prev(1) .neqv. f%held_prev(2)) return
    r = 1.0_dp / 3.0_dp
    ! the history content content_old + r (content_old - content_prev) stays >= 0 (so the
    ! fill does: a node loses at most what it holds)
    do i = 2, n - 1
      if (f%content_prev(i) > f%content_old(i)) &
        r = min(r, f%content_old(i) / (f%content_prev(i) - f%content_old(i)))
    end do
    if (f%starved) then
      ! the share r of the last step's inflow through an edge is drawn again: at most the oil
      ! there (the leading edge's strip and bank, the liner behind the trailing edge)
      if (f%lead_left) then
        x_lead = f%x_left_prev
        x_trail = -f%x_right_prev
      else
        x_lead = -f%x_right_prev
        x_trail = f%x_left_prev
      end if
      if (x_lead > 0.0_dp) r = min(r, max(f%available, 0.0_dp) / x_lead)
      if (x_trail > 0.0_dp) r = min(r, max(f%behind, 0.0_dp) / x_trail)
    end if
    f%r_step = max(r, 0.0_dp)
 if (f%r_step > 0.0_dp) f%content_hist = f%content_old + f%r_step * (f%content_old - f%content_prev)
  end subroutine step_history

  !> -1, 0 or 1.
  pure integer function sign_of(x)
    real(dp), intent(in) :: x
    sign_of = 0
    if (x > 0.0_dp) sign_of = 1
    if (x < 0.0_dp) sign_of = -1
  end function sign_of
end module ringlube_film_jfo
