!> The film at one crank step: grid and profile, the film solve for a trial h0 (pressure
!> with the pressure-viscosity loop, hydrodynamic and asperity loads) and the friction
!> (SPEC sections 3-6 and 8).
!>
!> What the load balance (ringlube_load_balance) uses of a film model, and all a second
!> model has to provide: `film_evaluate` at a trial h0 (given 2 dh0/dt, the sliding speed,
!> the chamber pressure and the load tolerance in N), leaving `wh`, `wa`, `aa`, `flags`,
!> `h0` and the counters `evaluations` and `reynolds_solves` set; `film_friction` at the
!> accepted h0; `lead_left` set by the caller from the sign of u. Everything else in
!> film_type is this model's own state (warm starts of the next trial and step).
module ringlube_film
  use ringlube_kinds, only: dp, pi
  use ringlube_case, only: case_type, composite_sigma, reduced_modulus, ring_profile
  use ringlube_viscosity, only: roelands_law, roelands_law_at, roelands_eta
  use ringlube_contact, only: asperity_contact
  use ringlube_reynolds, only: reynolds_solve, reynolds_work, reynolds_work_init
  use ringlube_results, only: flag_viscosity, flag_cavitation, flag_piezo, flag_overdraw
  use ringlube_jfo, only: jfo_solve, JFO_OK
  use ringlube_jfo_connect, only: jfo_solve_connected
  use ringlube_oil_supply, only: inlet_fill
  implicit none
  private
  public :: film_type, film_setup, film_evaluate, film_friction

  !> Roelands is evaluated with the pressure clipped here [Pa]. Ring pressures are far
  !> lower; only trial films far below the load-balance root reach it, where an unclipped
  !> pressure-viscosity iteration runs away to overflow.
  real(dp), parameter, public :: roelands_p_max = 1e9_dp

  !> Workspace of the film at one crank step.
  type :: film_type
    integer :: n = 0
    real(dp) :: dx = 0.0_dp, circ = 0.0_dp, sigma = 0.0_dp, e_reduced = 0.0_dp, eta_e = 0.0_dp
    real(dp), allocatable :: x(:), s(:), smid(:), h(:), hmid(:), p(:), eta(:), kmid(:), etamid(:)
    logical, allocatable :: active(:)
    !> scratch of the Reynolds solver, and the pressure and viscosity of the last iteration
    type(reynolds_work) :: work
    real(dp), allocatable :: pold(:), eta_new(:)
    logical :: lead_left = .true.          !< leading edge is the chamber edge (x = -b/2)
    logical :: trailing_cavitated = .false.  !< Reynolds outlet: trailing edge at p_cav
    !> Roelands' law at the film temperature of the run
    type(roelands_law) :: law
    ! state of the last evaluation
    real(dp) :: h0 = -1.0_dp, wh = 0.0_dp, wa = 0.0_dp, aa = 0.0_dp
    integer :: flags = 0
    integer :: evaluations = 0             !< film solves (load-balance trials)
    integer :: reynolds_solves = 0         !< Reynolds solves (incl. pressure-viscosity loop)
    ! the mass-conserving (JFO) film: fill, its content at the last accepted step, the
    ! cavity pressures, and the oil fluxes through the first and last interior faces
    logical :: jfo = .false.
    real(dp), allocatable :: theta(:), content_old(:), pc(:)
    real(dp) :: q_left = 0.0_dp, q_right = 0.0_dp, dt = 0.0_dp
    !> the face is partly filled across its width at a gas pressure above the leading edge's,
    !> whose meniscus is then at the leading edge (ringlube_jfo, jfo_solve_connected)
    logical :: blown = .false.
    !> starved inlet: oil available to the leading edge over the step [m^2] and the distance
    !> the ring moves in it [m] (set by the caller); the fill the inlet admitted
    logical :: starved = .false.
    real(dp) :: available = 0.0_dp, ds = 0.0_dp, theta_in = 1.0_dp
    !> starved: oil on the liner just behind the trailing edge that it may draw back over the
    !> step [m^2]; the caps on the inflow through the left and right edge faces [m^2/s]
    real(dp) :: behind = 0.0_dp, cap_left = huge(1.0_dp), cap_right = huge(1.0_dp)
    !> the gas around the ring (SPEC 14, set by the caller with ring_pack = 'gas'): the
    !> pressure behind the ring (its gas load) and at its lower (crankcase) edge [Pa];
    !> negative: the chamber pressure behind it and the crankcase pressure below it
    real(dp) :: p_back = -1.0_dp, p_lower = -1.0_dp
  end type film_type

contains

  !> Build the grid and the profile of a case.
  pure subroutine film_setup(c, f)
    type(case_type), intent(in) :: c
    type(film_type), intent(out) :: f
    integer :: i, n
    real(dp) :: hb
    n = c%nodes
    f%n = n
    hb = 0.5_dp * c%width
    f%dx = c%width / (n - 1)
    f%circ = 2.0_dp * pi * c%bore_radius
    f%sigma = composite_sigma(c)
    f%e_reduced = reduced_modulus(c)
    f%law = roelands_law_at(c%liner_temperature, c%eta0, c%theta0, c%alpha, c%beta)
    f%eta_e = roelands_eta(f%law, 0.0_dp)
    allocate (f%x(n), f%s(n), f%h(n), f%p(n), f%eta(n), f%active(n))
    allocate (f%smid(n - 1), f%hmid(n - 1), f%kmid(n - 1), f%etamid(n - 1), f%pold(n), f%eta_new(n))
    call reynolds_work_init(f%work, n)
    do i = 1, n
      f%x(i) = -hb + (i - 1) * f%dx
    end do
    f%x(n) = hb
    f%s = ring_profile(f%x, c%width, c%crown_height, c%crown_offset)
  f%smid = ring_profile(0.5_dp * (f%x(1:n - 1) + f%x(2:n)), c%width, c%crown_height, c%crown_offset)
    f%p = c%crankcase_pressure
    f%eta = f%eta_e
    ! the viscosity of the pressure held (see film_evaluate)
    if (c%roelands) f%eta = roelands_eta(f%law, c%crankcase_pressure)
    f%active = .false.
    f%jfo = c%cavitation == 'jfo'
    f%starved = c%inlet == 'starved'
    allocate (f%theta(n), f%content_old(n), f%pc(n))
    f%theta = 1.0_dp
    f%pc = c%cavitation_pressure
    f%content_old = f%s   ! a full film at h0 = 0: the caller sets it at the first h0
  end subroutine film_setup

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
    real(dp) :: pl, pr
    integer :: it, iters, info, n
    logical :: settled

    n = f%n
    f%h0 = h0
    f%flags = 0
    f%evaluations = f%evaluations + 1
    f%h = h0 + f%s
    f%hmid = h0 + f%smid
    if (f%jfo) then
      call jfo_evaluate(c, f, u, p_chamber, w_tol)
      return
    end if
    pl = p_chamber
    pr = lower_edge_pressure(c, f)
    f%trailing_cavitated = .false.
    if (c%outlet == 'reynolds') then
      f%trailing_cavitated = .true.
      if (f%lead_left) then
        pr = c%cavitation_pressure
      else
        pl = c%cavitation_pressure
      end if
    end if

    ! The pressure-viscosity loop starts from the previous trial's pressure, where the fixed
    ! point is a contraction and unique (ring pressures, far below 100 MPa). After a trial
    ! above 100 MPa it starts from the isoviscous film (eta at p = 0) instead: from a
    ! high-pressure state the iteration can land on a second, high-pressure branch and make
    ! W(h0) jump, which the load balance cannot bracket.
    call start_viscosity(c, f)
    do it = 1, c%max_pressure_iterations
      call conductance(f, 6.0_dp)
      call reynolds_solve(f%dx, f%kmid, f%hmid, u, sq, pl, pr, c%cavitation_pressure, f%p, &
                          f%active, iters, info, f%work)
      f%reynolds_solves = f%reynolds_solves + iters
      if (info == 1) f%flags = ior(f%flags, flag_cavitation)
      if (info == 2) then
        ! singular system: cannot happen for h > 0; keep a finite state and flag it
        f%p = max(pl, pr)
        f%flags = ior(f%flags, flag_cavitation)
        if (c%roelands) f%eta = roelands_eta(f%law, min(max(f%p, 0.0_dp), roelands_p_max))
        exit
      end if
      if (.not. c%roelands) exit
      call update_viscosity(c, f, w_tol, it, settled)
      if (settled) exit
    end do

    call film_loads(c, f)
  end subroutine film_evaluate

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
    real(dp) :: pl, pr, tl, tr, v_in, h_le, qlead, qtrail, ql, qr
    integer :: it, iters, outer, info, n
    logical :: settled
    logical :: trailing_gas

    n = f%n
    pl = p_chamber
    pr = lower_edge_pressure(c, f)
    trailing_gas = c%cavity_pressure == 'trailing_gas'
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
      tl = f%theta_in
      tr = 1.0_dp
      ql = qlead
      qr = qtrail
    else
      tl = 1.0_dp
      tr = f%theta_in
      ql = qtrail
      qr = qlead
    end if
    f%cap_left = ql
    f%cap_right = qr
    call start_viscosity(c, f)
    do it = 1, c%max_pressure_iterations
      call conductance(f, 12.0_dp)
      if (f%starved .or. trailing_gas) then
        call jfo_solve_connected(f%dx, f%h, f%hmid, f%kmid, u, f%dt, f%content_old, pl, pr, &
                tl, tr, c%cavitation_pressure, trailing_gas, f%starved, f%pc, f%p, f%theta, iters, &
                                 outer, info, f%q_left, f%q_right, cap_left=ql, cap_right=qr, &
                                 blown=f%blown)
      else
        f%blown = .false.
        f%pc = c%cavitation_pressure
        call jfo_solve(f%dx, f%h, f%hmid, f%kmid, u, f%dt, f%content_old, pl, pr, tl, tr, &
                       f%pc, f%p, f%theta, iters, info, f%q_left, f%q_right)
      end if
      f%reynolds_solves = f%reynolds_solves + iters
      if (info /= JFO_OK) f%flags = ior(f%flags, flag_cavitation)
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

  !> Gas pressure at the ring's lower (crankcase) edge [Pa]: the land pressure with the ring
  !> pack, else the crankcase pressure.
  pure real(dp) function lower_edge_pressure(c, f) result(p)
    type(case_type), intent(in) :: c
    type(film_type), intent(in) :: f
    p = c%crankcase_pressure
    if (f%p_lower >= 0.0_dp) p = f%p_lower
  end function lower_edge_pressure

  !> The viscosity the pressure-viscosity loop of either film model starts from: the previous
  !> trial's, or the isoviscous film's (eta at p = 0) after a trial above 100 MPa or without
  !> Roelands.
  pure subroutine start_viscosity(c, f)
    type(case_type), intent(in) :: c
    type(film_type), intent(inout) :: f
    if (maxval(f%p) > 1e8_dp) then
      f%p = 0.0_dp
      f%eta = f%eta_e
    end if
    if (.not. c%roelands) f%eta = f%eta_e
  end subroutine start_viscosity

  !> Face conductances kmid = hmid^3 / (factor eta_mid) for the next solve (factor 6 in the
  !> Swift-Stieber film's form, 12 in the JFO solve's), the pressure kept as the old one.
  pure subroutine conductance(f, factor)
    type(film_type), intent(inout) :: f
    real(dp), intent(in) :: factor
    integer :: n
    n = f%n
    f%etamid = 0.5_dp * (f%eta(1:n - 1) + f%eta(2:n))
    f%kmid = f%hmid**3 / (factor * f%etamid)
    f%pold = f%p
  end subroutine conductance

  !> One step of the pressure-viscosity loop of either film model, after a solve: the
  !> viscosity of the new pressure (once per node and iteration; only where the pressure
  !> changed, e.g. not in a cavity held at its pressure), kept for the next iteration or the
  !> next trial. `done` when the loop may stop (see film_evaluate); flags a loop that reaches
  !> max_pressure_iterations.
  pure subroutine update_viscosity(c, f, w_tol, it, done)
    type(case_type), intent(in) :: c
    type(film_type), intent(inout) :: f
    real(dp), intent(in) :: w_tol
    integer, intent(in) :: it
    logical, intent(out) :: done
    real(dp) :: dvisc
    integer :: i, n
    n = f%n
    dvisc = 0.0_dp
    do i = 1, n
      if (f%p(i) /= f%pold(i)) then
        f%eta_new(i) = roelands_eta(f%law, min(max(f%p(i), 0.0_dp), roelands_p_max))
        dvisc = max(dvisc, abs(f%eta_new(i) - f%eta(i)) / f%eta(i))
        f%eta(i) = f%eta_new(i)
      end if
    end do
    f%wh = f%circ * f%dx * (sum(f%p) - 0.5_dp * (f%p(1) + f%p(n)))
    done = dvisc * abs(f%wh) <= 0.1_dp * w_tol
    if (.not. done) done = sum(abs(f%p - f%pold)) <= c%pressure_tol * sum(abs(f%p))
    if (.not. done .and. it == c%max_pressure_iterations) f%flags = ior(f%flags, flag_viscosity)
  end subroutine update_viscosity

  !> The loads of a solved film: W_h (trapezoidal rule) and the asperity load and area.
  !> A blown face (the gas in it reaching the leading edge, see film_type) has its meniscus at
  !> the leading edge: the gas pressure acts up to the edge, so the leading edge's interval
  !> carries the pressure of its interior node, not the mean with the edge's lower gas pressure
  !> (whose share, (p_gas - p_edge) dx / 2, is a cell-size error).
  pure subroutine film_loads(c, f)
    type(case_type), intent(in) :: c
    type(film_type), intent(inout) :: f
    integer :: n
    real(dp) :: pl, pr
    n = f%n
    if (c%roelands .and. maxval(f%p) > roelands_p_max) f%flags = ior(f%flags, flag_piezo)
    pl = f%p(1)
    pr = f%p(n)
    if (f%jfo .and. f%blown) then
      if (f%lead_left) then
        pl = max(pl, f%p(2))
      else
        pr = max(pr, f%p(n - 1))
      end if
    end if
    f%wh = f%circ * f%dx * (sum(f%p(2:n - 1)) + 0.5_dp * (pl + pr))
    if (c%asperity_contact) then
      call asperity_contact(f%h, f%h0, f%dx, c%width, f%circ, f%sigma, c%zeta_kappa_sigma, &
                            c%sigma_over_kappa, f%e_reduced, c%gt_functions == 'fit', &
                            c%contact_area == 'lumped', f%wa, f%aa)
    else
      f%wa = 0.0_dp
      f%aa = 0.0_dp
    end if
  end subroutine film_loads

  !> Viscous and boundary friction on the ring [N], positive towards the crankcase.
  !>
  !> Mass-conserving film: the shear of each interval is weighted like its flux (SPEC 13:
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
          q_act = f%q_left
        else
          q_act = f%q_right
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
