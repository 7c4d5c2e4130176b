! ctest labels: unit;numerics
!> The ring pack's gas network and the top ring's axial motion in one step
!> (ringlube_ring_pack) against exact answers: the parameters from a case, the orifice and
!> channel formulas, the piston's acceleration, the closed-form isothermal blowdown of one
!> volume (choked, then unchoked) and the ring's motion under a constant force. Over whole
!> cycles: test_ring_pack_cycle.

program test_ring_pack
  use ringlube_kinds, only: dp, pi
  use ringlube_error, only: error_type
  use ringlube_case, only: case_type, default_case
  use ringlube_gas, only: read_pressure_csv, gas_pressure
  use ringlube_kinematics, only: sliding_speed, piston_acceleration, deg2rad
  use ringlube_ring_pack
  use ringlube_ring_pack_cycle
  use ringlube_check
  implicit none
  real(dp), parameter :: rgas = 287.0_dp
  character(len=*), parameter :: trace = 'inputs/pressure/crf450r_4000rpm_full.csv'
  type(case_type) :: c
  type(ring_pack_params) :: base
  real(dp), allocatable :: tpsi(:), tp(:)
  type(error_type), allocatable :: err
  logical, parameter :: verbose = .true.
  ! the blowdown's initial, crankcase pressures, rate k, choked Psi*, critical ratio, end of choking
  real(dp) :: p0, p4, k, psis, rc, tstar

  c = default_case()
  base = ring_pack_params_from_case(c)
  call read_pressure_csv(trace, tpsi, tp, err)
  call check(.not. allocated(err), 'read the shipped gas trace '//trace)
  if (allocated(err)) call report('test_ring_pack')

  if (run_case('params_from_case')) call test_params_from_case()
  if (run_case('flow_formulas')) call test_flow_formulas()
  if (run_case('piston_acceleration')) call test_piston_acceleration()
  if (run_case('blowdown')) call test_blowdown()
  if (run_case('constant_force')) call test_constant_force()
  if (run_case('newton_predictor')) call test_newton_predictor()
  if (run_case('hold_margin')) call test_hold_margin()
  call report('test_ring_pack')

contains

  !> The defaults of the input table reach the parameters (docs/ring_pack.md).
  subroutine test_params_from_case()
    call check_close(base%gas_temperature, 450.0_dp, 0.0_dp, 'default gas_temperature 450 K')
    call check_close(base%gamma, 1.3_dp, 0.0_dp, 'default gamma 1.3')
    call check_close(base%gas_viscosity, 2.5e-5_dp, 0.0_dp, 'default gas_viscosity')
    call check_close(base%discharge_coefficient, 0.7_dp, 0.0_dp, 'default discharge_coefficient')
    call check_close(base%top_gap_area, 1e-7_dp, 0.0_dp, 'default top_gap_area 0.1 mm^2')
    call check_close(base%second_gap_area, 1.5e-7_dp, 0.0_dp, 'default second_gap_area')
    call check_close(base%groove_clearance, 40e-6_dp, 0.0_dp, 'default groove_clearance')
    call check_close(base%groove_volume, 1e-7_dp, 0.0_dp, 'default groove_volume 0.1 cm^3')
    ! groove_volume = 0: the groove cut for the default ring (r0 48 mm, radial depth 3.5 mm,
    ! back clearance 0.3 mm, width 1.004 mm, side clearance 40 um), the differences of squares
    ! worked out by hand: (44.5^2 - 44.2^2) = 0.3 x 88.7 and (48^2 - 44.5^2) = 3.5 x 92.5 mm^2
    c%groove_volume = 0.0_dp
    call check_close(groove_gas_volume(c), pi * (0.3e-3_dp * 88.7e-3_dp * 1.044e-3_dp &
                                                 + 3.5e-3_dp * 92.5e-3_dp * 40e-6_dp), 1e-13_dp, &
                     'groove_volume 0: the groove of the ring (0.128 cm^3)')
    c%width = 2e-3_dp  ! a wider ring, a higher groove: only the back space grows
    call check_close(groove_gas_volume(c) - pi * (0.3e-3_dp * 88.7e-3_dp * 1.044e-3_dp &
                                                  + 3.5e-3_dp * 92.5e-3_dp * 40e-6_dp), &
                     pi * 0.3e-3_dp * 88.7e-3_dp * 0.996e-3_dp, 1e-11_dp, &
                     'groove_volume follows the ring width')
    c%groove_volume = 1e-7_dp  ! given: used as it is
    call check_close(groove_gas_volume(c), 1e-7_dp, 0.0_dp, 'a given groove_volume is used')
    c = default_case()
    call check_close(base%land_volume, 5e-7_dp, 0.0_dp, 'default land_volume 0.5 cm^3')
    call check_close(base%circumference, 2 * pi * 48e-3_dp, 1e-15_dp, 'circumference 2 pi r0')
    call check(base%ring_mass > 1e-3_dp .and. base%ring_mass < 2e-2_dp, 'ring mass of grams')
  end subroutine test_params_from_case

  !> Orifice: choked value, the critical ratio, reversal, continuity at r*, derivatives
  !> against central differences; channel: the formula by hand.
  subroutine test_flow_formulas()
    real(dp) :: g, rc, q, qa, qb, da, db, fd, psi_c, k, h, pa, pb
    real(dp), parameter :: pas(6) = [2e5_dp, 5e6_dp, 1.2e5_dp, 1e5_dp, 3e5_dp, 1.05e5_dp], &
                           pbs(6) = [1.5e5_dp, 1e5_dp, 1e5_dp, 1.6e5_dp, 1e5_dp, 1e5_dp]
    integer :: i
    character(len=80) :: what
    g = 1.3_dp
    rc = (2 / (g + 1))**(g / (g - 1))
    psi_c = sqrt(2 * g / (g - 1) * (rc**(2 / g) - rc**((g + 1) / g)))
    ! Psi(r*) = sqrt(g) (2/(g+1))^((g+1)/(2(g-1))) (the textbook choked value)
    call check_close(psi_c, sqrt(g) * (2 / (g + 1))**((g + 1) / (2 * (g - 1))), 1e-14_dp, &
                     'orifice: Psi(r*) = sqrt(g) (2/(g+1))^((g+1)/(2(g-1)))')
    call check_close(orifice_psi(0.1_dp, g), psi_c, 1e-15_dp, 'orifice: choked below r*')
    call check_close(orifice_psi(rc * (1 + 1e-9_dp), g), psi_c, 1e-8_dp, &
                     'orifice: Psi continuous at r*')
    call orifice_flow(0.7_dp * 1e-7_dp, 5e6_dp, 1e5_dp, 450.0_dp, g, q)
    call check_close(q, 0.7_dp * 1e-7_dp * 5e6_dp / sqrt(rgas * 450.0_dp) * psi_c, 1e-14_dp, &
                     'orifice: choked flow C_d A p_u Psi* / sqrt(R T)')
    call orifice_flow(0.7e-7_dp, 1e5_dp, 5e6_dp, 450.0_dp, g, qa)
    call check_close(qa, -q, 1e-15_dp, 'orifice: reversed pressures reverse the flow')
    ! derivatives (unchoked, choked, and reversed)
    do i = 1, 6
      pa = pas(i)
      pb = pbs(i)
      call orifice_flow(1e-7_dp, pa, pb, 450.0_dp, g, q, da, db)
      h = 1e-6_dp * pa
      call orifice_flow(1e-7_dp, pa + h, pb, 450.0_dp, g, qa)
      call orifice_flow(1e-7_dp, pa - h, pb, 450.0_dp, g, qb)
      fd = (qa - qb) / (2 * h)
      write (what, '(a, 2es10.2)') 'orifice: dq/dp_a vs central difference at ', pa, pb
      call check_close(da, fd, 1e-5_dp, trim(what), atol=1e-9_dp * abs(q / pa))
      h = 1e-6_dp * pb
      call orifice_flow(1e-7_dp, pa, pb + h, 450.0_dp, g, qa)
      call orifice_flow(1e-7_dp, pa, pb - h, 450.0_dp, g, qb)
      fd = (qa - qb) / (2 * h)
      write (what, '(a, 2es10.2)') 'orifice: dq/dp_b vs central difference at ', pa, pb
      call check_close(db, fd, 1e-5_dp, trim(what), atol=1e-9_dp * abs(q / pa))
    end do
    ! near r = 1 the flow is the incompressible C_d A sqrt(2 rho dp) (to O(dp/p))
    call orifice_flow(1e-7_dp, 1.01e5_dp, 1e5_dp, 450.0_dp, g, q)
    call check_close(q, 1e-7_dp * sqrt(2 * 1.01e5_dp / (rgas * 450) * 1e3_dp), 1e-2_dp, &
                     'orifice: incompressible limit near r = 1')
    call orifice_flow(1e-7_dp, 1e5_dp, 1e5_dp, 450.0_dp, g, q)
    call check(q == 0.0_dp, 'orifice: no flow at equal pressures')
    ! channel: l g^3 (p_u^2 - p_d^2) / (24 mu R T w)
    k = 0.3_dp * (20e-6_dp)**3 / (24 * 2.5e-5_dp * rgas * 450 * 3.5e-3_dp)
    call channel_flow(0.3_dp, 20e-6_dp, 3.5e-3_dp, 2.5e-5_dp, 450.0_dp, 3e6_dp, 1e6_dp, q, da, db)
    call check_close(q, k * (9e12_dp - 1e12_dp), 1e-14_dp, 'channel: the laminar channel formula')
    call check_close(da, 2 * k * 3e6_dp, 1e-14_dp, 'channel: dq/dp_u')
    call check_close(db, -2 * k * 1e6_dp, 1e-14_dp, 'channel: dq/dp_d')
    call channel_flow(0.3_dp, 0.0_dp, 3.5e-3_dp, 2.5e-5_dp, 450.0_dp, 3e6_dp, 1e6_dp, q)
    call check(q == 0.0_dp, 'channel: closed at zero gap')
  end subroutine test_flow_formulas

  !> The piston acceleration is the time derivative of the sliding speed.
  subroutine test_piston_acceleration()
    real(dp) :: w, psi, h, fd
    integer :: i
    character(len=64) :: what
    w = 4000 * 2 * pi / 60
    h = 1e-4_dp
    do i = 0, 35
      psi = i * 20 * pi / 180 + 0.05_dp
      fd = w * (sliding_speed(psi + h, c%crank_radius, c%conrod_length, w) &
                - sliding_speed(psi - h, c%crank_radius, c%conrod_length, w)) / (2 * h)
      write (what, '(a, f7.2)') 'piston acceleration vs dU/dt at psi=', psi * 180 / pi
      call check_close(piston_acceleration(psi, c%crank_radius, c%conrod_length, w), fd, &
                       1e-6_dp, trim(what), atol=1e-7_dp * c%crank_radius * w**2)
    end do
    call check_close(piston_acceleration(0.0_dp, c%crank_radius, c%conrod_length, w), &
                     c%crank_radius * w**2 * (1 + c%crank_radius / c%conrod_length), 1e-14_dp, &
                     'piston acceleration at TDC r w^2 (1 + r/l)')
  end subroutine test_piston_acceleration

  !> The land alone (top gap shut, ring held on its lower flank) discharging through the
  !> second gap into the crankcase: isothermal, dp/dt = -k p Psi(p4/p), k = C_d A sqrt(RT)/V.
  !> Choked: p = p0 exp(-k Psi* t) down to p4/r*; then, for gamma = 1.4 exactly,
  !> t - t* = sqrt(7)/k (G(T*) - G(T)), G(T) = T + 2T^3/3 + T^5/5, T = sqrt((1-s)/s),
  !> s = (p4/p)^(2/7).
  subroutine test_blowdown()
    type(ring_pack_params) :: par
    real(dp) :: dt, err_max, err1, err2
    integer :: nsteps
    par = base
    par%gamma = 1.4_dp
    par%top_gap_area = 0.0_dp
    p0 = 1e6_dp
    p4 = 1e5_dp
    k = par%discharge_coefficient * par%second_gap_area * sqrt(rgas * par%gas_temperature) &
        / par%land_volume
    rc = (2 / 2.4_dp)**3.5_dp
    psis = orifice_psi(rc, 1.4_dp)
    tstar = log(p0 * rc / p4) / (k * psis)
    ! adaptive (the default control), crank-like steps of 20 us over both phases
    dt = 2e-5_dp
    nsteps = nint(3 * tstar / dt)
    call run_blowdown(par, dt, nsteps, err_max)
    if (verbose) print '(a, es10.3)', 'blowdown: max relative error, default control: ', err_max
    ! the crank step bounds the sub-step here: backward Euler's relative error at h = dt is
    ! about (lambda t)(lambda h)/2 with lambda = k Psi*, 8.6e-4 at the end of choking
    call check(err_max <= 1.2e-3_dp, 'blowdown: closed form to 1.2e-3 with the default sub-steps')
    par%pressure_rtol = 1e-4_dp
    call run_blowdown(par, dt, nsteps, err_max)
    if (verbose) print '(a, es10.3)', 'blowdown: max relative error, pressure_rtol 1e-4: ', err_max
    ! backward Euler's local error (k Psi h)^2/2 with k Psi h = rtol, over ln(p0/p4)/rtol
    ! sub-steps: a global error of about ln(10)/2 rtol = 1.15e-4
    call check(err_max <= 2e-4_dp, 'blowdown: closed form to 2e-4 with pressure_rtol 1e-4')
    ! backward Euler without sub-steps: first order in dt
    par%adaptive = .false.
    call run_blowdown(par, 2e-4_dp, nint(3 * tstar / 2e-4_dp), err1)
    call run_blowdown(par, 1e-4_dp, nint(3 * tstar / 1e-4_dp), err2)
    if (verbose) print '(a, 2es10.3)', 'blowdown: backward Euler errors at 200, 100 us: ', &
      err1, err2
    call check(err2 / err1 > 0.4_dp .and. err2 / err1 < 0.6_dp, &
               'blowdown: backward Euler first order (error halves with the step)')
  end subroutine test_blowdown

  subroutine run_blowdown(par, dt, nsteps, err_max)
    type(ring_pack_params), intent(in) :: par
    real(dp), intent(in) :: dt
    integer, intent(in) :: nsteps
    real(dp), intent(out) :: err_max
    integer :: i
    type(error_type), allocatable :: err
    type(ring_pack_state) :: st
    type(ring_pack_step_out) :: out
    real(dp) :: t, pex
    call ring_pack_init(st, p4, p4)
    st%p3 = p0
    err_max = 0.0_dp
    t = 0.0_dp
    do i = 1, nsteps
      ! chamber at p4 (the upper channel fills the groove only); the ring held down
      call ring_pack_step(par, st, p4, p4, p4, 0.0_dp, 1e6_dp, dt, out, err)
      if (allocated(err)) then
        call check(.false., 'blowdown: '//err%message)
        return
      end if
      t = t + dt
      pex = exact(t)
      if (p4 / pex < 0.99_dp) err_max = max(err_max, abs(st%p3 - pex) / pex)
      if (st%flank /= flank_lower) then
        call check(.false., 'blowdown: ring held on its lower flank')
        return
      end if
    end do
  end subroutine run_blowdown

  !> Exact pressure at t (bisection on the unchoked closed form).
  real(dp) function exact(t) result(p)
    real(dp), intent(in) :: t
    real(dp) :: lo, hi, mid
    integer :: it
    if (t <= tstar) then
      p = p0 * exp(-k * psis * t)
      return
    end if
    lo = rc
    hi = 1.0_dp
    do it = 1, 200
      mid = 0.5_dp * (lo + hi)
      if (t_of_r(mid) > t) then
        hi = mid
      else
        lo = mid
      end if
    end do
    p = p4 / (0.5_dp * (lo + hi))
  end function exact

  real(dp) function t_of_r(r)
    real(dp), intent(in) :: r
    t_of_r = tstar + sqrt(7.0_dp) / k * (gg(rc) - gg(r))
  end function t_of_r

  real(dp) function gg(r)
    real(dp), intent(in) :: r
    real(dp) :: s, tt
    s = r**(2.0_dp / 7.0_dp)
    tt = sqrt(max(0.0_dp, (1 - s) / s))
    gg = tt + 2 * tt**3 / 3 + tt**5 / 5
  end function gg

  !> Equal pressures everywhere (no gas force, no flow) and a constant force: from rest
  !> on the lower flank x = F t^2 / (2 m) until the upper flank, then rest there; a force
  !> pressing it down keeps it on the lower flank; from the upper flank back down.
  subroutine test_constant_force()
    type(ring_pack_params) :: par
    type(ring_pack_state) :: st
    type(ring_pack_step_out) :: out
    type(error_type), allocatable :: err
    real(dp) :: f, m, dt, t, xex, thit, errx, tlift
    integer :: i
    logical :: ok_flank
    par = base
    m = par%ring_mass
    f = 2.0_dp
    dt = 1e-5_dp
    thit = sqrt(2 * m * par%groove_clearance / f)
    call ring_pack_init(st, 1e5_dp, 1e5_dp)
    errx = 0.0_dp
    ok_flank = .true.
    tlift = 0.0_dp
    t = 0.0_dp
    do i = 1, nint(2 * thit / dt)
      call ring_pack_step(par, st, 1e5_dp, 1e5_dp, 1e5_dp, f, 0.0_dp, dt, out, err)
      t = t + dt
      tlift = tlift + out%lift_time
      xex = min(par%groove_clearance, f * t**2 / (2 * m))
      errx = max(errx, abs(st%x - xex))
      if (t > thit) ok_flank = ok_flank .and. st%flank == flank_upper .and. st%v == 0.0_dp
      if (t < thit - dt) ok_flank = ok_flank .and. st%flank == flank_none
    end do
    call check(errx <= 1e-12_dp * par%groove_clearance, &
               'constant force: x = F t^2/(2 m) until the upper flank')
    call check(ok_flank, 'constant force: in flight, then at rest on the upper flank')
    call check_close(tlift, t, 1e-12_dp, 'constant force: whole time off the lower flank')
    ! the same with the force from inertia: F_i = -m a_p
    call ring_pack_init(st, 1e5_dp, 1e5_dp)
    call ring_pack_step(par, st, 1e5_dp, 1e5_dp, 1e5_dp, 0.0_dp, -f / m, 0.5_dp * thit, out, err)
    call check_close(st%x, f * (0.5_dp * thit)**2 / (2 * m), 1e-12_dp, &
                     'constant force: inertia -m a_p lifts the ring as F does')
    call check(out%lift_offs == 1, 'constant force: one lift-off counted')
    ! back down from the upper flank under -F
    call ring_pack_init(st, 1e5_dp, 1e5_dp)
    st%x = par%groove_clearance
    st%flank = flank_upper
    call ring_pack_step(par, st, 1e5_dp, 1e5_dp, 1e5_dp, -f, 0.0_dp, 0.5_dp * thit, out, err)
    call check_close(st%x, par%groove_clearance - f * (0.5_dp * thit)**2 / (2 * m), 1e-12_dp, &
                     'constant force: from the upper flank x = c_a - F t^2/(2 m)')
    ! pressed on the lower flank: stays
    call ring_pack_init(st, 1e5_dp, 1e5_dp)
    call ring_pack_step(par, st, 1e5_dp, 1e5_dp, 1e5_dp, -f, 0.0_dp, thit, out, err)
    call check(st%x == 0.0_dp .and. st%flank == flank_lower .and. out%lift_time == 0.0_dp, &
               'constant force: pressed on the lower flank it stays')
    ! gas force: p1 above p3 presses the ring down, p3 above p1 lifts it by l d (p3-p1)/2
    call check_close(ring_gas_force(par, 2e5_dp, 1e5_dp), &
                     -par%circumference * par%radial_depth * 0.5e5_dp, 1e-14_dp, &
                     'gas force l d (p3 - p1)/2')
  end subroutine test_constant_force

  !> The flutter margin of a step: with the chamber above the land, the net force pressing the
  !> ring on its lower flank, -(l d (p3 - p1)/2 + F_f - m a_p); negative exactly when the ring
  !> leaves the flank (a flutter event); not counted with the land above the chamber.
  subroutine test_hold_margin()
    type(ring_pack_params) :: par
    type(ring_pack_state) :: st
    type(ring_pack_step_out) :: out
    type(error_type), allocatable :: err
    real(dp) :: gas, m, want
    real(dp), parameter :: wants(2) = [3.0_dp, -2.0_dp]
    integer :: i
    par = base
    par%top_gap_area = 0.0_dp     ! no flow into or out of the land: p3 stays
    par%second_gap_area = 0.0_dp
    m = par%ring_mass
    gas = ring_gas_force(par, 2e5_dp, 1e5_dp)   ! (negative: presses the ring down)
    do i = 1, 2
      want = wants(i)
      call ring_pack_init(st, 2e5_dp, 1e5_dp)
      ! the inertia force -m a_p makes the net force -want
      call ring_pack_step(par, st, 2e5_dp, 2e5_dp, 1e5_dp, 0.0_dp, (gas + want) / m, 1e-7_dp, &
                          out, err)
      call check(.not. allocated(err), 'hold margin: the step runs')
      call check_close(out%hold_margin, want, 1e-9_dp, 'hold margin: the force pressing the '// &
                       'ring on its lower flank while p1 > p3')
      call check((out%hold_margin < 0.0_dp) .eqv. (out%flutter_events > 0), &
                 'hold margin: negative exactly with a flutter event')
      call check_close(out%inertia, abs(gas + want), 1e-14_dp, 'hold margin: the inertia m |a_p|')
    end do
    ! the land above the chamber: the ring may lift, but that is not flutter, nor counted
    call ring_pack_init(st, 1e5_dp, 1e5_dp)
    st%p3 = 2e5_dp
    call ring_pack_step(par, st, 1e5_dp, 1e5_dp, 1e5_dp, 0.0_dp, 0.0_dp, 1e-7_dp, out, err)
    call check(out%hold_margin == huge(1.0_dp) .and. out%flutter_events == 0 .and. &
               out%lift_offs == 1, 'hold margin: none while the land is above the chamber')
  end subroutine test_hold_margin

  !> Newton's method in the backward-Euler step starts from the pressures' last rate (a
  !> predictor) and stops at a step of 1e-8 of the pressure scale taken with linearised flows:
  !> the same state as from the step's start (no predictor) to 1e-10 relative, and the gas
  !> masses balance the step's flows to round-off. Over a falling chamber pressure with the
  !> ring lifting off in the second half (inertia towards the chamber), sub-stepped and not.
  subroutine test_newton_predictor()
    type(ring_pack_params) :: par
    type(ring_pack_state) :: st, a, b
    type(ring_pack_step_out) :: out, oa, ob
    real(dp) :: dt, p1a, p1b, m0, dm, flows, worst_p, worst_m, ap
    integer :: i, j
    logical :: lifted, moving
    moving = .true.
    worst_p = 0.0_dp
    worst_m = 0.0_dp
    lifted = .false.
    do j = 1, 2
      par = base
      par%adaptive = j == 1
      ! 2 deg at 4000 r/min
      dt = 2.0_dp / (6.0_dp * 4000.0_dp)
      call ring_pack_init(st, 3.1e6_dp, 1e5_dp)
      do i = 1, 120
        p1a = 1e5_dp + 3e6_dp * exp(-(i - 1) / 20.0_dp)
        p1b = 1e5_dp + 3e6_dp * exp(-i / 20.0_dp)
        ! the piston decelerating hard from step 60 on: the ring lifts off its lower flank
        ap = -1e3_dp
        if (i > 60) ap = -4e4_dp
        a = st
        b = st
        b%rate2 = 0.0_dp
        b%rate3 = 0.0_dp
        call ring_pack_step(par, a, p1a, p1b, 1e5_dp, 0.0_dp, ap, dt, oa, err)
        call check(.not. allocated(err), 'newton predictor: step')
        call ring_pack_step(par, b, p1a, p1b, 1e5_dp, 0.0_dp, ap, dt, ob, err)
        worst_p = max(worst_p, abs(a%p2 - b%p2) / b%p2, abs(a%p3 - b%p3) / b%p3)
        m0 = ring_pack_gas_mass(par, st)
        dm = ring_pack_gas_mass(par, a) - m0
        flows = (oa%top_gap_flow + oa%upper_channel_flow - oa%second_gap_flow) * dt
        worst_m = max(worst_m, abs(dm - flows) / max(oa%gross_mass, tiny(1.0_dp)))
        st = a
        lifted = lifted .or. st%flank /= flank_lower
        ! the predictor works from the rates of the step before (not zero: a and b differ)
        if (i > 1) moving = moving .and. (a%rate2 /= 0.0_dp .or. a%rate3 /= 0.0_dp)
      end do
    end do
    call check(lifted, 'newton predictor: the ring lifted off')
    call check(moving, 'newton predictor: the steps carry the pressures'' rates')
    if (verbose) print '(a, 2es10.2)', 'newton predictor: pressures vs no predictor, '// &
      'mass balance: ', worst_p, worst_m
    call check(worst_p <= 1e-10_dp, 'newton predictor: the state of a start without it')
    call check(worst_m <= 1e-12_dp, 'newton predictor: masses balance the flows')
  end subroutine test_newton_predictor
end program test_ring_pack
