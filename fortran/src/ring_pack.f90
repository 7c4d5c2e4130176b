!> The ring pack's gas: groove (space 2) and second land (space 3) as
!> isothermal gas volumes joined by the top and second rings' end gaps (orifices) and the
!> top ring's groove-flank channels, and the top ring's axial motion in its groove.
!>
!> Standalone: the film is not involved here; a caller couples it. Spaces: 1 the chamber
!> (given p1), 2 the groove behind the top ring, 3 the second land, 4 the crankcase (given
!> p4). Flows are signed positive towards the crankcase: `top_gap` 1 -> 3, `second_gap`
!> 3 -> 4, `upper_channel` 1 -> 2 (over the ring's upper flank), `lower_channel` 2 -> 3.
!> Axial axis: piston frame, positive towards the chamber; lift x_r in [0, c_a] above the
!> lower groove flank.
!>
!> How to call it from a crank loop (one call per crank step dt):
!>
!>     type(ring_pack_params) :: par
!>     type(ring_pack_state)  :: st
!>     type(ring_pack_step_out) :: out
!>     type(ring_pack_totals) :: tot
!>     par = ring_pack_params_from_case(c)          ! once
!>     call ring_pack_init(st, p1_start, p4)    ! once (or keep st from the last cycle)
!>     ! every crank step:
!>     call ring_pack_step(par, st, p1_old, p1_new, p4, f_f, a_p, dt, out, err)
!>     call ring_pack_accumulate(tot, out, dt)       ! cycle quantities (ringlube_ring_pack_cycle)
!>     ! st%p2: back pressure of the ring (its gas load p2 b l), p1 its upper edge,
!>     ! st%p3 its lower edge; st%x lift, st%flank which flank it rests on.
!>
!> - p1_old, p1_new: chamber pressure at the start and end of the step (Pa abs), linear
!>   in time in between.
!> - p4: crankcase pressure (Pa abs).
!> - f_f: the liner's friction force on the ring along the axis positive towards the
!>   chamber (N). The kernel's friction is positive towards the crankcase: f_f = -friction.
!> - a_p: the piston's acceleration, positive towards the chamber (m/s^2). The kinematics'
!>   `piston_acceleration` is positive towards the crankcase: a_p = -piston_acceleration.
!>   f_f and a_p are held constant over the step: pass values representative of it (at
!>   its middle, or the mean of its ends).
!> - dt: the step (s).
!>
!> Integrator (docs/ring_pack.md): each crank step is split into adaptive sub-steps. In a
!> sub-step the ring moves exactly under a constant net force (the land pressure at the
!> sub-step's start, the chamber pressure at its middle), stopping at a flank it meets
!> (velocity set to zero, plastic impact) and resting there while the force presses it
!> on; then the gas masses take one backward-Euler step with the flank gaps at the
!> sub-step's end, solved by Newton's method on the 2x2 system (analytic Jacobian,
!> backtracking on the residual; from the pressures' rate of the last sub-step, stopped at a
!> step of 1e-8 of the pressure scale taken with linearised flows). Backward Euler is
!> L-stable: the groove's time constant V_2 / (R T dmdot/dp2) through an open 40 um channel
!> is about 5 us at 1 MPa and 0.5 us at 10 MPa (it scales with 1/(g^3 p)), down to 1/50 of a
!> crank step of 2 deg at 12,000 r/min; backward Euler then gives the groove its
!> quasi-static pressure where an explicit scheme would blow up and the trapezoidal rule
!> would ring. Sub-steps are halved until the groove and land pressures change by at most
!> `pressure_rtol` and the ring travels at most `travel_fraction` of the clearance per
!> sub-step, which bounds the first-order error (measured in tests/fortran/test_ring_pack.f90).
module ringlube_ring_pack
  use ringlube_kinds, only: dp, pi
  use ringlube_error, only: error_type, fatal_error, rl_not_converged
  use ringlube_case, only: case_type, ring_mass
  use ringlube_gas, only: gas_pressure
  use ringlube_kinematics, only: deg2rad, piston_acceleration
  use ringlube_ring_pack_flow, only: gas_constant, orifice_linear, orifice_consts, &
                                     orifice_constants, orifice_eval, orifice_flow, channel_flow, &
                                     orifice_psi
  implicit none
  private
  public :: ring_pack_params, ring_pack_state, ring_pack_step_out
  public :: ring_pack_params_from_case, groove_gas_volume, ring_pack_init, ring_pack_step, ring_pack_gas_mass, &
            ring_pack_inputs
  public :: orifice_flow, channel_flow, orifice_psi, ring_gas_force, gas_constant, orifice_linear

  !> Newton's method in the backward-Euler step stops at a step of at most this fraction of the
  !> pressure scale, taken with the flows linearised (its error is of order the step squared)
  real(dp), parameter :: newton_tol = 1e-8_dp

  !> Which flank the ring rests on.
  integer, parameter, public :: flank_none = 0, flank_lower = 1, flank_upper = 2

  !> Parameters of the gas network and the ring (from a case: ring_pack_params_from_case).
  type :: ring_pack_params
    real(dp) :: gas_temperature = 0.0_dp      !< T [K]
    real(dp) :: gamma = 0.0_dp                !< ratio of specific heats
    real(dp) :: gas_viscosity = 0.0_dp        !< mu_g [Pa s]
    real(dp) :: discharge_coefficient = 0.0_dp !< C_d
    real(dp) :: top_gap_area = 0.0_dp         !< top ring end gap [m^2]
    real(dp) :: second_gap_area = 0.0_dp      !< second ring end gap [m^2]
    real(dp) :: groove_clearance = 0.0_dp     !< c_a [m]
    real(dp) :: groove_volume = 0.0_dp        !< V_2 [m^3]
    real(dp) :: land_volume = 0.0_dp          !< V_3 [m^3]
    real(dp) :: circumference = 0.0_dp        !< l = 2 pi r0 [m]
    real(dp) :: radial_depth = 0.0_dp         !< d = w, the channel length [m]
    real(dp) :: ring_mass = 0.0_dp            !< m_r [kg]
    real(dp) :: width = 0.0_dp                !< b, the face's channel length [m]
    !> Sub-step control: largest land-pressure change per sub-step relative to the land
    !> pressure, largest ring travel per sub-step relative to the clearance, and at most
    !> 2^max_halvings sub-steps per crank step. adaptive = .false.: one sub-step per call.
    real(dp) :: pressure_rtol = 3e-2_dp
    real(dp) :: travel_fraction = 0.3_dp
    !> An accepted sub-step that used at most this share of its allowed change (of
    !> pressure_rtol, travel_fraction) lets the next one be twice as long (huge: always).
    real(dp) :: grow_share = 0.5_dp
    integer :: max_halvings = 20
    logical :: adaptive = .true.
    !> The orifice law's constants for gamma = oc_gamma (ring_pack_params_from_case fills
    !> them; a step whose gamma differs computes its own)
    type(orifice_consts) :: oc
    real(dp) :: oc_gamma = -1.0_dp
  end type ring_pack_params

  !> State of the ring pack at one instant.
  type :: ring_pack_state
    real(dp) :: p2 = 0.0_dp       !< groove pressure [Pa]
    real(dp) :: p3 = 0.0_dp       !< land pressure [Pa]
    real(dp) :: x = 0.0_dp        !< ring lift above the lower flank [m], in [0, c_a]
    real(dp) :: v = 0.0_dp        !< ring velocity [m/s], positive towards the chamber
    integer :: flank = flank_lower !< flank the ring rests on (flank_none: in flight)
    real(dp) :: h_next = 0.0_dp   !< sub-step to try first in the next call [s] (0: dt)
    real(dp) :: rate2 = 0.0_dp, rate3 = 0.0_dp  !< dp2/dt, dp3/dt of the last sub-step [Pa/s]
    !> the gas path through the ring's face (a distorted bore; set by the caller for the next
    !> step): sum over its sectors of l_j h_gas,j^3 [m^4], a laminar channel of length b
    !> from space 1 to space 3
    real(dp) :: face_k = 0.0_dp
    !> off its lower flank since it left it while p1 > p3 (a flutter lift), and p1 > p3 since
    logical :: fluttering = .false.
  end type ring_pack_state

  !> What one crank step did. Flows are means over the step (mass through / dt), kg/s,
  !> positive towards the crankcase.
  type :: ring_pack_step_out
    real(dp) :: top_gap_flow = 0.0_dp
    real(dp) :: second_gap_flow = 0.0_dp
    real(dp) :: upper_channel_flow = 0.0_dp
    real(dp) :: lower_channel_flow = 0.0_dp
    !> through the ring's face (a distorted bore), chamber to land
    real(dp) :: face_flow = 0.0_dp
    !> Mass that flowed back into the chamber (top gap and upper channel, reverse part) [kg].
    real(dp) :: blowback_mass = 0.0_dp
    !> Gross mass through the boundaries of spaces 2+3, sum of |flow| h [kg].
    real(dp) :: gross_mass = 0.0_dp
    !> Gross mass through the boundaries of space 3 alone (end gaps, lower channel, face) [kg].
    real(dp) :: land_gross_mass = 0.0_dp
    real(dp) :: lift_time = 0.0_dp  !< time off the lower flank [s]
    real(dp) :: lift_time_against_gas = 0.0_dp  !< of which while p1 > p3 [s]
    integer :: lift_offs = 0        !< times the ring left its lower flank
    integer :: flutter_events = 0   !< of which while p1 > p3
    !> The smallest net force holding the ring on its lower flank while p1 > p3 [N]: over the
    !> sub-steps with p1 > p3 (the chamber pressure at their middle, the land's at their start)
    !> that start with the ring on its lower flank, in which it leaves it, or in which it is
    !> off it since a flutter lift, the force pressing it there,
    !> -(l d (p3 - p1)/2 + f_f - m_r a_p); huge when there is none. Negative exactly when the
    !> step has a flutter event or continues one (the same force decides the ring's
    !> departure); past the first event it goes on to the least force of the lift (how far the
    !> gas is from holding the ring), not the sampled instant of the departure.
    real(dp) :: hold_margin = huge(1.0_dp)
    !> the largest inertia force m_r |a_p| of the step [N]
    real(dp) :: inertia = 0.0_dp
    integer :: substeps = 0
    logical :: on_lower = .false., on_upper = .false.  !< at the end of the step
  end type ring_pack_step_out

contains

  !> Parameters from a case (&ring_pack, the ring's geometry and mass).
  function ring_pack_params_from_case(c) result(par)
    type(case_type), intent(in) :: c
    type(ring_pack_params) :: par
    par = ring_pack_params(gas_temperature=c%gas_temperature, gamma=c%gamma, &
                           gas_viscosity=c%gas_viscosity, &
                           discharge_coefficient=c%discharge_coefficient, &
                           top_gap_area=c%top_gap_area, second_gap_area=c%second_gap_area, &
                          groove_clearance=c%groove_clearance, groove_volume=groove_gas_volume(c), &
                           land_volume=c%land_volume, circumference=2.0_dp * pi * c%bore_radius, &
                           radial_depth=c%radial_depth, ring_mass=ring_mass(c), width=c%width)
    par%oc = orifice_constants(par%gamma)
    par%oc_gamma = par%gamma
  end function ring_pack_params_from_case

  !> Gas volume of the top ring groove [m^3]: `&ring_pack groove_volume` if given (> 0), else
  !> the groove cut for the ring (docs/ring_pack.md): the space behind the ring, between its
  !> back (radius r0 - a) and the groove root (r0 - a - e), over the groove height b + c_a,
  !> plus the side clearance c_a over the ring's radial depth a,
  !> `pi ((r0 - a)^2 - (r0 - a - e)^2) (b + c_a) + pi (r0^2 - (r0 - a)^2) c_a`
  !> (r0 bore radius, b ring width, e back_clearance, c_a groove_clearance).
  pure real(dp) function groove_gas_volume(c)
    type(case_type), intent(in) :: c
    real(dp) :: r0, a
    if (c%groove_volume > 0.0_dp) then
      groove_gas_volume = c%groove_volume
      return
    end if
    r0 = c%bore_radius
    a = c%radial_depth
    groove_gas_volume = pi * ((r0 - a)**2 - (r0 - a - c%back_clearance)**2) &
                  * (c%width + c%groove_clearance) + pi * (r0**2 - (r0 - a)**2) * c%groove_clearance
  end function groove_gas_volume

  !> The prescribed inputs of a gas-only cycle of case c (ringlube_ring_pack_cycle): the
  !> chamber pressure p1 and the piston's acceleration a_p (towards the chamber) at the crank
  !> angles (k0 + j) dpsi_deg, j = 0 .. size(p1) - 1.
  pure subroutine ring_pack_inputs(c, k0, p1, a_p)
    type(case_type), intent(in) :: c
    integer, intent(in) :: k0
    real(dp), intent(out) :: p1(0:), a_p(0:)
    real(dp) :: psi, omega
    integer :: j
    omega = c%speed_rpm * 2.0_dp * pi / 60.0_dp
    do j = 0, size(p1) - 1
      psi = (k0 + j) * c%dpsi_deg
      p1(j) = gas_pressure(c%gas_psi, c%gas_p, modulo(psi, 720.0_dp), c%crankcase_pressure)
      a_p(j) = -piston_acceleration(deg2rad(psi), c%crank_radius, c%conrod_length, omega)
    end do
  end subroutine ring_pack_inputs

  !> A starting state: groove at the chamber pressure, land at the crankcase pressure,
  !> ring at rest on its lower flank.
  pure subroutine ring_pack_init(st, p1, p4)
    type(ring_pack_state), intent(out) :: st
    real(dp), intent(in) :: p1, p4
    st%p2 = p1
    st%p3 = p4
    st%x = 0.0_dp
    st%v = 0.0_dp
    st%flank = flank_lower
    st%h_next = 0.0_dp
    st%rate2 = 0.0_dp
    st%rate3 = 0.0_dp
  end subroutine ring_pack_init

  !> Gas mass in spaces 2 and 3 [kg].
  pure real(dp) function ring_pack_gas_mass(par, st) result(m)
    type(ring_pack_params), intent(in) :: par
    type(ring_pack_state), intent(in) :: st
    m = (st%p2 * par%groove_volume + st%p3 * par%land_volume) &
        / (gas_constant * par%gas_temperature)
  end function ring_pack_gas_mass

  !> Gas force on the ring, positive towards the chamber [N]: l d ((p3 + p2)/2 - (p1 + p2)/2).
  pure real(dp) function ring_gas_force(par, p1, p3) result(f)
    type(ring_pack_params), intent(in) :: par
    real(dp), intent(in) :: p1, p3
    f = par%circumference * par%radial_depth * 0.5_dp * (p3 - p1)
  end function ring_gas_force

  !> Advance the gas network and the ring over one crank step dt (see the module header
  !> for the arguments). `err` is set if a sub-step of dt / 2^max_halvings still fails.
  subroutine ring_pack_step(par, st, p1_old, p1_new, p4, f_f, a_p, dt, out, err)
    type(ring_pack_params), intent(in) :: par
    type(ring_pack_state), intent(inout) :: st
    real(dp), intent(in) :: p1_old, p1_new, p4, f_f, a_p, dt
    type(ring_pack_step_out), intent(out) :: out
    type(error_type), allocatable, intent(out) :: err
    type(ring_pack_state) :: trial
    real(dp) :: t, h, hmin, q(5), lift_time, against, pa, pb, blowback, gross, land_gross, used, &
                hold
    integer :: lift_offs, flutter
    logical :: ok, accept
    real(dp) :: mass(5)
    type(orifice_consts) :: oc

    if (par%oc_gamma == par%gamma) then
      oc = par%oc
    else
      oc = orifice_constants(par%gamma)
    end if
    mass = 0.0_dp
    blowback = 0.0_dp
    gross = 0.0_dp
    land_gross = 0.0_dp
    hmin = dt / 2.0_dp**par%max_halvings
    h = dt
    if (par%adaptive .and. st%h_next > 0.0_dp) h = min(dt, st%h_next)
    t = 0.0_dp
    do while (t < dt * (1.0_dp - 1e-12_dp))
      h = min(h, dt - t)
      pa = p1_old + (p1_new - p1_old) * (t / dt)
      pb = p1_old + (p1_new - p1_old) * ((t + h) / dt)
      trial = st
      call substep(par, oc, trial, pa, pb, p4, f_f, a_p, h, q, lift_time, lift_offs, flutter, &
                   against, hold, ok)
      accept = ok
      used = 0.0_dp
      if (accept .and. par%adaptive) then
        ! share of the allowed change the sub-step used (pressures, travel)
        used = max(abs(trial%p3 - st%p3) / (par%pressure_rtol * max(trial%p3, st%p3)), &
                   abs(trial%p2 - st%p2) / (par%pressure_rtol * max(trial%p2, st%p2)), &
                   abs(trial%x - st%x) / (par%travel_fraction * par%groove_clearance))
        accept = used <= 1.0_dp
      end if
      if (.not. accept .and. h > hmin * 1.5_dp .and. (par%adaptive .or. .not. ok)) then
        h = 0.5_dp * h
        cycle
      end if
      if (.not. ok) then
        call fatal_error(err, 'ring_pack_step: the gas network did not converge in a '// &
                         'sub-step of the smallest size', rl_not_converged)
        return
      end if
      st = trial
      t = t + h
      mass = mass + h * q
      blowback = blowback + h * (max(0.0_dp, -q(1)) + max(0.0_dp, -q(3)) + max(0.0_dp, -q(5)))
      gross = gross + h * (abs(q(1)) + abs(q(2)) + abs(q(3)) + abs(q(5)))
      land_gross = land_gross + h * (abs(q(1)) + abs(q(2)) + abs(q(4)) + abs(q(5)))
      out%lift_time = out%lift_time + lift_time
      out%lift_time_against_gas = out%lift_time_against_gas + against
      out%lift_offs = out%lift_offs + lift_offs
      out%flutter_events = out%flutter_events + flutter
      out%hold_margin = min(out%hold_margin, hold)
      out%substeps = out%substeps + 1
      st%h_next = h
      ! the next sub-step twice as long only if this one used at most half the allowance
      ! (the change grows about in proportion to the sub-step): growing after every accepted
      ! sub-step would have every other one rejected where the allowance binds
      if (par%adaptive .and. accept .and. used <= par%grow_share) h = 2.0_dp * h
    end do
    if (par%adaptive) st%h_next = min(h, dt)
    out%top_gap_flow = mass(1) / dt
    out%second_gap_flow = mass(2) / dt
    out%upper_channel_flow = mass(3) / dt
    out%lower_channel_flow = mass(4) / dt
    out%face_flow = mass(5) / dt
    out%blowback_mass = blowback
    out%gross_mass = gross
    out%land_gross_mass = land_gross
    out%on_lower = st%flank == flank_lower
    out%on_upper = st%flank == flank_upper
    out%inertia = par%ring_mass * abs(a_p)
  end subroutine ring_pack_step

  !> One sub-step of length h: the ring under a constant force, then backward Euler on
  !> the gas masses. q: flows at the end (top gap, second gap, upper, lower channel, face);
  !> hold: the force holding the ring on its lower flank while p1 > p3 (ring_pack_step_out's
  !> hold_margin; huge if the sub-step does not count).
  pure subroutine substep(par, oc, st, p1a, p1b, p4, f_f, a_p, h, q, lift_time, lift_offs, &
                          flutter, against, hold, ok)
    type(ring_pack_params), intent(in) :: par
    type(orifice_consts), intent(in) :: oc
    type(ring_pack_state), intent(inout) :: st
    real(dp), intent(in) :: p1a, p1b, p4, f_f, a_p, h
    real(dp), intent(out) :: q(5), lift_time, against, hold
    integer, intent(out) :: lift_offs, flutter
    logical, intent(out) :: ok
    real(dp) :: force, p1m
    logical :: on_lower
    p1m = 0.5_dp * (p1a + p1b)
    force = ring_gas_force(par, p1m, st%p3) + f_f - par%ring_mass * a_p
    on_lower = st%flank == flank_lower
    call move_ring(st%x, st%v, st%flank, force, par%ring_mass, par%groove_clearance, h, &
                   lift_time, lift_offs)
    flutter = 0
    against = 0.0_dp
    hold = huge(1.0_dp)
    if (p1m > st%p3) then
      flutter = lift_offs
      against = lift_time
      if (on_lower .or. lift_offs > 0 .or. st%fluttering) hold = -force
      if (lift_offs > 0) st%fluttering = .true.
    else
      st%fluttering = .false.
    end if
    if (st%flank == flank_lower) st%fluttering = .false.
    call gas_backward_euler(par, oc, st, p1b, p4, h, q, ok)
  end subroutine substep

  !> The ring over time h under a constant force: free flight x + v t + F t^2/(2 m)
  !> between the flanks; at a flank it stops (v = 0) and rests while the force presses it
  !> there. lift_time: time off the lower flank; lift_offs: departures from it.
  pure subroutine move_ring(x, v, flank, force, mass, clearance, h, lift_time, lift_offs)
    real(dp), intent(inout) :: x, v
    integer, intent(inout) :: flank
    real(dp), intent(in) :: force, mass, clearance, h
    real(dp), intent(out) :: lift_time
    integer, intent(out) :: lift_offs
    real(dp) :: left, acc, t_hit, t_lo, t_up
    integer :: iter
    lift_time = 0.0_dp
    lift_offs = 0
    left = h
    acc = force / mass
    do iter = 1, 8
      if (left <= 0.0_dp) exit
      if (flank == flank_lower) then
        if (force <= 0.0_dp) exit
        flank = flank_none
        x = 0.0_dp
        v = 0.0_dp
        lift_offs = lift_offs + 1
      else if (flank == flank_upper) then
        if (force >= 0.0_dp) then
          lift_time = lift_time + left
          exit
        end if
        flank = flank_none
        x = clearance
        v = 0.0_dp
      else if (x <= 0.0_dp .and. v <= 0.0_dp) then
        ! in flight, at or (by round-off) below the lower flank and still moving down
        x = 0.0_dp
        v = 0.0_dp
        flank = flank_lower
        cycle
      else if (x >= clearance .and. v >= 0.0_dp) then
        x = clearance
        v = 0.0_dp
        flank = flank_upper
        cycle
      end if
      t_lo = first_hit(x, v, acc, 0.0_dp, left)
      t_up = first_hit(x, v, acc, clearance, left)
      t_hit = min(t_lo, t_up)
      if (t_hit > left) then
        x = min(clearance, max(0.0_dp, x + v * left + 0.5_dp * acc * left**2))
        v = v + acc * left
        lift_time = lift_time + left
        exit
      end if
      lift_time = lift_time + t_hit
      left = left - t_hit
      v = 0.0_dp
      if (t_lo <= t_up) then
        x = 0.0_dp
        flank = flank_lower
      else
        x = clearance
        flank = flank_upper
      end if
    end do
  end subroutine move_ring

  !> First time t in (0, tmax] at which x + v t + a t^2/2 reaches b; huge if none.
  pure real(dp) function first_hit(x, v, a, b, tmax) result(t)
    real(dp), intent(in) :: x, v, a, b, tmax
    real(dp) :: c, disc, r1, r2, qq, tiny_t
    t = huge(1.0_dp)
    c = x - b
    tiny_t = 1e-14_dp * tmax
    ! the ring leaving the flank b it sits on does not "reach" b at t = 0
    if (abs(a) <= tiny(1.0_dp)) then
      if (v /= 0.0_dp) then
        r1 = -c / v
        if (r1 > tiny_t .and. r1 <= tmax) t = r1
      end if
      return
    end if
    disc = v**2 - 2.0_dp * a * c
    if (disc < 0.0_dp) return
    qq = -0.5_dp * (v + sign(sqrt(disc), v))
    if (qq /= 0.0_dp) then
      r1 = qq / (0.5_dp * a)
      r2 = c / qq
    else
      r1 = 0.0_dp
      r2 = 0.0_dp
    end if
    if (r1 > tiny_t .and. r1 <= tmax) t = min(t, r1)
    if (r2 > tiny_t .and. r2 <= tmax) t = min(t, r2)
  end function first_hit

  !> Backward Euler on the masses of spaces 2 and 3 over h with the chamber at p1 and the
  !> gaps of the ring's current lift; Newton's method on (p2, p3).
  pure subroutine gas_backward_euler(par, oc, st, p1, p4, h, q, ok)
    type(ring_pack_params), intent(in) :: par
    type(orifice_consts), intent(in) :: oc
    type(ring_pack_state), intent(inout) :: st
    real(dp), intent(in) :: p1, p4, h
    real(dp), intent(out) :: q(5)
    logical, intent(out) :: ok
    real(dp) :: c2, c3, p(2), p_old(2), res(2), jac(2, 2), dp_(2), trial(2), res_t(2), &
                scale, norm0, norm_t, det, lam, g_up, g_lo, c_top, c_2nd, dq(5, 2), dq_t(5, 2), &
                q_t(5), kf
    integer :: it, ls
    c_top = par%discharge_coefficient * par%top_gap_area / sqrt(gas_constant * par%gas_temperature)
    c_2nd = par%discharge_coefficient * par%second_gap_area &
            / sqrt(gas_constant * par%gas_temperature)
    c2 = par%groove_volume / (gas_constant * par%gas_temperature)
    c3 = par%land_volume / (gas_constant * par%gas_temperature)
    g_up = par%groove_clearance - st%x
    g_lo = st%x
    ! the face's laminar channel, q5 = kf (p1^2 - p3^2)
    kf = 0.0_dp
    if (st%face_k > 0.0_dp) kf = st%face_k / (24.0_dp * par%gas_viscosity * gas_constant &
                                              * par%gas_temperature * par%width)
    p_old = [st%p2, st%p3]
    scale = max(p1, p4, p_old(1), p_old(2))
    ! predictor: the pressures' rate of the last sub-step (kept positive)
    p(1) = max(0.5_dp * p_old(1), p_old(1) + st%rate2 * h)
    p(2) = max(0.5_dp * p_old(2), p_old(2) + st%rate3 * h)
    ok = .false.
    call residual(p, res, jac, q, dq)
    norm0 = rnorm(res)
    do it = 1, 100
      det = jac(1, 1) * jac(2, 2) - jac(1, 2) * jac(2, 1)
      if (.not. (abs(det) > 0.0_dp)) exit
      dp_(1) = -(jac(2, 2) * res(1) - jac(1, 2) * res(2)) / det
      dp_(2) = -(-jac(2, 1) * res(1) + jac(1, 1) * res(2)) / det
      if (maxval(abs(dp_)) <= newton_tol * scale) then
        ! converged (Newton's step is quadratic: the error after it is of order
        ! |dp|^2 / scale; at most |dp| at a kink of the orifice law): the step taken with the
        ! flows linearised at p, for which the residual is zero, so the masses balance the
        ! flows to round-off
        p = p + dp_
        q = q + matmul(dq, dp_)
        ok = .true.
        exit
      end if
      lam = 1.0_dp
      ! keep the pressures positive
      if (p(1) + dp_(1) < 0.1_dp * p(1)) lam = min(lam, 0.9_dp * p(1) / max(-dp_(1), tiny(1.0_dp)))
      if (p(2) + dp_(2) < 0.1_dp * p(2)) lam = min(lam, 0.9_dp * p(2) / max(-dp_(2), tiny(1.0_dp)))
      do ls = 1, 40
        trial = p + lam * dp_
        call residual(trial, res_t, jac, q_t, dq_t)
        norm_t = rnorm(res_t)
        if (norm_t <= (1.0_dp - 1e-4_dp * lam) * norm0 .or. norm_t == 0.0_dp) exit
        lam = 0.5_dp * lam
      end do
      ! no decrease (a step within newton_tol has been taken above): not solved, the caller
      ! halves the sub-step
      if (ls > 40) exit
      p = trial
      res = res_t
      q = q_t
      dq = dq_t
      norm0 = norm_t
      if (norm0 == 0.0_dp) then
        ok = .true.
        exit
      end if
    end do
    if (ok) then
      st%rate2 = (p(1) - p_old(1)) / h
      st%rate3 = (p(2) - p_old(2)) / h
      st%p2 = p(1)
      st%p3 = p(2)
    end if

  contains

    !> Residuals (kg) and Jacobian (kg/Pa) of backward Euler; q the flows at p, dq their
    !> derivatives with respect to (p2, p3).
    pure subroutine residual(pp, r, j, qq, dqq)
      real(dp), intent(in) :: pp(2)
      real(dp), intent(out) :: r(2), j(2, 2), qq(5), dqq(5, 2)
      real(dp) :: d12a, d12b, d23a, d23b, d13a, d13b, d34a, d34b
      call orifice_eval(oc, c_top, p1, pp(2), qq(1), d13a, d13b)
      call orifice_eval(oc, c_2nd, pp(2), p4, qq(2), d34a, d34b)
      call channel_flow(par%circumference, g_up, par%radial_depth, par%gas_viscosity, &
                        par%gas_temperature, p1, pp(1), qq(3), d12a, d12b)
      call channel_flow(par%circumference, g_lo, par%radial_depth, par%gas_viscosity, &
                        par%gas_temperature, pp(1), pp(2), qq(4), d23a, d23b)
      qq(5) = kf * (p1**2 - pp(2)**2)
      r(1) = c2 * (pp(1) - p_old(1)) - h * (qq(3) - qq(4))
      r(2) = c3 * (pp(2) - p_old(2)) - h * (qq(1) + qq(4) + qq(5) - qq(2))
      j(1, 1) = c2 - h * (d12b - d23a)
      j(1, 2) = h * d23b
      j(2, 1) = -h * d23a
      j(2, 2) = c3 - h * (d13b + d23b - 2.0_dp * kf * pp(2) - d34a)
      dqq(:, 1) = [0.0_dp, 0.0_dp, d12b, d23a, 0.0_dp]
      dqq(:, 2) = [d13b, d34a, 0.0_dp, d23b, -2.0_dp * kf * pp(2)]
    end subroutine residual

    !> Residual norm in units of the pressure scale.
    pure real(dp) function rnorm(r)
      real(dp), intent(in) :: r(2)
      rnorm = max(abs(r(1)) / c2, abs(r(2)) / c3) / scale
    end function rnorm
  end subroutine gas_backward_euler

end module ringlube_ring_pack
