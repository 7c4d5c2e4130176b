!> The ring pack over a cycle: a cycle's sums of the steps of ringlube_ring_pack,
!> the cycle quantities from them (blowby, blowback, ring lift share, flutter events,
!> gas balance), and the gas network alone run to its periodic state under prescribed
!> chamber pressure, piston acceleration and friction.
module ringlube_ring_pack_cycle
  use ringlube_kinds, only: dp, pi
  use ringlube_kinematics, only: piston_acceleration, deg2rad
  use ringlube_error, only: error_type, fatal_error, rl_input_error
  use ringlube_ring_pack_flow, only: gas_constant
  use ringlube_ring_pack, only: ring_pack_params, ring_pack_state, ring_pack_step_out, &
                                ring_pack_init, ring_pack_step, ring_pack_gas_mass, &
                                ring_pack_params_from_case, ring_pack_inputs
  use ringlube_case, only: case_type
  use ringlube_results, only: sc_blowby, sc_blowby_mass, sc_blowback_mass, sc_ring_lift_share, &
                              sc_flutter_events, sc_gas_balance_error, sc_flutter_margin, &
                              sc_flutter_margin_ratio, sc_peak_groove_pressure, &
                              sc_peak_groove_angle, sc_peak_land_pressure, sc_peak_land_angle, &
                              result_type, s_groove_pressure, s_land_pressure, s_crank_angle_deg, &
                              sc_gas_exchange
  implicit none
  private
  public :: ring_pack_totals, ring_pack_cycle_out, ring_pack_accumulate, ring_pack_finish, &
            ring_pack_cycle, ring_pack_scalars, ring_pack_start, ring_pack_restart, &
            ring_pack_distance, ring_pack_check

  !> Standard state of the blowby volume flow: 101325 Pa, 293.15 K.
  real(dp), parameter, public :: std_pressure = 101325.0_dp, std_temperature = 293.15_dp
  !> the gas network's start: its tolerance (relative to the peak chamber pressure) and the
  !> largest crank step of its coarse cycles [deg]
  real(dp), parameter :: start_tol = 1e-4_dp, start_coarse_deg = 8.0_dp
  !> the contraction of the fine cycles taken this many times the coarse cycles' estimate
  real(dp), parameter :: prior_safety = 10.0_dp
  !> the least land gauge pressure the periodicity test judges the land's change by,
  !> relative to the peak chamber pressure (ring_pack_distance)
  real(dp), parameter :: land_floor = 1e-2_dp

  !> Sums over a cycle (ring_pack_accumulate), turned into the cycle quantities by
  !> ring_pack_finish.
  type :: ring_pack_totals
    real(dp) :: time = 0.0_dp, blowby_mass = 0.0_dp, blowback_mass = 0.0_dp, &
                inflow_mass = 0.0_dp, gross_mass = 0.0_dp, lift_time = 0.0_dp, &
                lift_time_against_gas = 0.0_dp, land_gross_mass = 0.0_dp
    integer :: flutter_events = 0, lift_offs = 0
    real(dp) :: stored_start = -1.0_dp  !< m2 + m3 at the start (set by the caller) [kg]
    !> the least force holding the ring on its lower flank while p1 > p3, the largest inertia
    !> force [N] (ring_pack_step_out)
    real(dp) :: hold_margin = huge(1.0_dp), inertia = 0.0_dp
  end type ring_pack_totals

  !> One periodic cycle (ring_pack_cycle): per crank step (at its end) and totals.
  type :: ring_pack_cycle_out
    real(dp), allocatable :: p2(:), p3(:), x(:), top_gap_flow(:), second_gap_flow(:), &
                             upper_channel_flow(:), lower_channel_flow(:)
    real(dp) :: blowby_l_min = 0.0_dp, blowby_mg_per_cycle = 0.0_dp, &
                blowback_mg_per_cycle = 0.0_dp, ring_lift_share_pct = 0.0_dp, &
                gas_balance_error = 0.0_dp
    !> Gas mass over the cycle through the boundaries of space 3, or of spaces 2+3 together
    !> where that is less, every way [mg]: 0 where the land's gas is trapped (ring_pack_check).
    real(dp) :: gas_exchange_mg_per_cycle = 0.0_dp
    !> Share of the cycle the ring is off its lower flank while the chamber pressure exceeds
    !> the land pressure (lift against the gas: inertia or friction beat the gas force) [%].
    real(dp) :: lift_against_gas_pct = 0.0_dp
    !> Net inflow minus outflow of spaces 2+3 over the cycle relative to the gross flow
    !> (zero when periodic).
    real(dp) :: periodicity_error = 0.0_dp
    !> the land pressure's contraction per cycle at the last cycle, the ratio of its last two
    !> changes (negative: alternating; 0: not known)
    real(dp) :: contraction = 0.0_dp
    integer :: flutter_events = 0, cycles_run = 0, substeps = 0
    logical :: converged = .false.
    !> the least force holding the ring on its lower flank while the chamber pressure exceeds
    !> the land's [N] (negative: it lifts, a flutter event), and over the largest inertia force
    !> m_r |a_p| of the cycle; with no such instant (no gas above the land) that inertia force
    !> and 1: the gas never pushes on the ring, a margin as large as anything that could lift it
    real(dp) :: flutter_margin = huge(1.0_dp), flutter_margin_ratio = 1.0_dp
    !> the state at the last cycle's start
    type(ring_pack_state) :: start
  end type ring_pack_cycle_out

contains

  !> Add one step's output to a cycle's sums.
  pure subroutine ring_pack_accumulate(tot, out, dt)
    type(ring_pack_totals), intent(inout) :: tot
    type(ring_pack_step_out), intent(in) :: out
    real(dp), intent(in) :: dt
    tot%time = tot%time + dt
    tot%blowby_mass = tot%blowby_mass + out%second_gap_flow * dt
    tot%blowback_mass = tot%blowback_mass + out%blowback_mass
    tot%inflow_mass = tot%inflow_mass + (out%top_gap_flow + out%upper_channel_flow &
                                         + out%face_flow) * dt
    tot%gross_mass = tot%gross_mass + out%gross_mass
    tot%land_gross_mass = tot%land_gross_mass + out%land_gross_mass
    tot%lift_time = tot%lift_time + out%lift_time
    tot%lift_time_against_gas = tot%lift_time_against_gas + out%lift_time_against_gas
    tot%flutter_events = tot%flutter_events + out%flutter_events
    tot%lift_offs = tot%lift_offs + out%lift_offs
    tot%hold_margin = min(tot%hold_margin, out%hold_margin)
    tot%inertia = max(tot%inertia, out%inertia)
  end subroutine ring_pack_accumulate

  !> A cycle's quantities into the kernel's scalar results of `res` (ringlube_results), and
  !> the peak groove and land pressures of its series with their crank angles (the first
  !> step of the highest).
  pure subroutine ring_pack_scalars(cyc, res)
    type(ring_pack_cycle_out), intent(in) :: cyc
    type(result_type), intent(inout) :: res
    integer :: k
    associate (v => res%scalars, series => res%series)
      k = maxloc(series(:, s_groove_pressure), dim=1)
      v(sc_peak_groove_pressure) = series(k, s_groove_pressure)
      v(sc_peak_groove_angle) = series(k, s_crank_angle_deg)
      k = maxloc(series(:, s_land_pressure), dim=1)
      v(sc_peak_land_pressure) = series(k, s_land_pressure)
      v(sc_peak_land_angle) = series(k, s_crank_angle_deg)
      call cycle_scalars(v)
    end associate

  contains

    pure subroutine cycle_scalars(v)
      real(dp), intent(inout) :: v(:)
      v(sc_blowby) = cyc%blowby_l_min
      v(sc_blowby_mass) = cyc%blowby_mg_per_cycle
      v(sc_blowback_mass) = cyc%blowback_mg_per_cycle
      v(sc_ring_lift_share) = cyc%ring_lift_share_pct
      v(sc_flutter_events) = cyc%flutter_events
      v(sc_flutter_margin) = cyc%flutter_margin
      v(sc_flutter_margin_ratio) = cyc%flutter_margin_ratio
      v(sc_gas_balance_error) = cyc%gas_balance_error
      v(sc_gas_exchange) = cyc%gas_exchange_mg_per_cycle
    end subroutine cycle_scalars
  end subroutine ring_pack_scalars

  !> A run of case c with a sealed ring pack is refused: a land without end gaps
  !> (top_gap_area = second_gap_area = 0) that exchanged no gas over the reported cycle (its
  !> scalar results v: `gas_exchange` 0), with the groove through the lower channel while the
  !> top ring rested on its upper flank all cycle (closing the groove as well), or with
  !> anything while it rested on its lower flank. The gas trapped there is whatever the
  !> warm-up left, which no cycle decides (the warm-up and the crank step change it, and with
  !> it the land pressure and the friction). (With an end gap open, no exchange means equal
  !> pressures everywhere, which the gap decides.)
  subroutine ring_pack_check(c, v, err)
    type(case_type), intent(in) :: c
    real(dp), intent(in) :: v(:)
    type(error_type), allocatable, intent(out) :: err
    if (c%ring_pack /= 'gas' .or. c%top_gap_area > 0.0_dp .or. c%second_gap_area > 0.0_dp) return
    if (v(sc_gas_exchange) > 0.0_dp) return
    call fatal_error(err, c%deck_path//': &ring_pack: a sealed ring pack: no gas reached '// &
                     'the second land from the chamber or the crankcase over the cycle '// &
                     '(top_gap_area and second_gap_area 0 give it no end gap, and the top '// &
                     'ring stayed on one flank of its groove all cycle, closing the way past '// &
                     'it), so its pressure is whatever gas the warm-up trapped, not a result '// &
                     'of the cycle; give the top or the second ring an end gap (top_gap_area '// &
                     'or second_gap_area > 0)', rl_input_error)
  end subroutine ring_pack_check

  !> The ring pack of case c at the start of the warm-up (crank step kstart of a cycle of m):
  !> its parameters `par`, and the gas network alone (no friction, one step per crank step)
  !> run over whole cycles from the warm-up's first step to its periodic state there, so that
  !> the coupled cycles start near their own (the land takes 2-16 gas cycles to settle from a
  !> cold start, docs/ring_pack.md). cyc%converged: the start settled (its fine cycles, or its
  !> coarse ones where the fine did not); cyc%contraction: the land's contraction per cycle.
  subroutine ring_pack_start(c, m, kstart, par, st, cyc, err)
    type(case_type), intent(in) :: c
    integer, intent(in) :: m, kstart
    type(ring_pack_params), intent(out) :: par
    type(ring_pack_state), intent(out) :: st
    type(ring_pack_cycle_out), intent(out) :: cyc
    type(error_type), allocatable, intent(out) :: err
    real(dp) :: p1(0:m - 1), ap(0:m - 1), ff(0:m - 1), rho_coarse
    type(ring_pack_params) :: cheap
    type(ring_pack_state) :: st_coarse
    integer :: s
    logical :: coarse_ok
    par = ring_pack_params_from_case(c)
    ! from the crank angle the warm-up's first step starts from
    call ring_pack_inputs(c, kstart - 2, p1, ap)
    ff = 0.0_dp
    call ring_pack_init(st, p1(0), c%crankcase_pressure)
    ! one backward-Euler step per crank step (no sub-steps), to 1e-4 of the peak chamber
    ! pressure: its periodic land pressure lies 0.25 % from the sub-stepped one on the cold
    ! deck, the size of what the film's friction changes and the coupled warm-up corrects, at
    ! a third of the cost (energy within 1e-6 of the sub-stepped start to 1e-6)
    cheap = par
    cheap%adaptive = .false.
    ! first on every s-th crank step (steps of start_coarse_deg at most), to the same
    ! tolerance: their periodic land pressure lies within 1e-3 of the peak chamber pressure of
    ! the fine cycles' (5e-5 to 8e-4 on the shipped decks), so the fine cycles start near
    ! their own and the first can already pass, with the coarse cycles' contraction
    ! (docs/ring_pack.md, "Start"); if the coarse cycles fail, the fine ones start cold
    s = coarse_stride(m, c%dpsi_deg)
    rho_coarse = 0.0_dp
    coarse_ok = .false.
    if (s > 1) then
      call ring_pack_cycle(cheap, p1(0:m - 1:s), ap(0:m - 1:s), ff(0:m - 1:s), s * c%dpsi_deg, &
                           c%speed_rpm, c%crankcase_pressure, st, cyc, err, max_cycles=50, &
                           tol=start_tol)
      if (allocated(err) .or. .not. cyc%converged) then
        if (allocated(err)) deallocate (err)
        call ring_pack_init(st, p1(0), c%crankcase_pressure)
      else
        rho_coarse = cyc%contraction
        coarse_ok = .true.
        st_coarse = st
      end if
    end if
    call ring_pack_cycle(cheap, p1, ap, ff, c%dpsi_deg, c%speed_rpm, c%crankcase_pressure, st, &
                         cyc, err, max_cycles=50, tol=start_tol, rho_prior=abs(rho_coarse))
    if (allocated(err)) return
    ! fine cycles that do not settle leave the start where the coarse ones did: a slow land
    ! (rho near 1) whose cycle map bends at its fixed point sends Aitken's extrapolation past
    ! it, back and forth, and the last cycle can end far off (a 0.39 L land: 772 kPa against a
    ! periodic 497 kPa, the coarse cycles' 496 kPa; test
    ! test_a_slow_land_starts_where_its_coarse_cycles_settled)
    if (coarse_ok .and. .not. cyc%converged) then
      st = st_coarse
      cyc%contraction = rho_coarse
      cyc%converged = .true.
    end if
    ! the land's contraction for the coupled cycles' test: the fine cycles', else the coarse
    if (cyc%contraction == 0.0_dp) cyc%contraction = rho_coarse
  end subroutine ring_pack_start

  !> Stride of the start's coarse cycles: the largest power of two s dividing m with s dpsi
  !> at most start_coarse_deg (1: none).
  pure integer function coarse_stride(m, dpsi_deg) result(s)
    integer, intent(in) :: m
    real(dp), intent(in) :: dpsi_deg
    s = 1
    do while (mod(m, 2 * s) == 0 .and. 2 * s * dpsi_deg <= start_coarse_deg * (1.0_dp + 1e-9_dp))
      s = 2 * s
    end do
  end function coarse_stride

  !> The ring pack before crank step kfrom (psi = (kfrom - 2) dpsi) of a cycle of size(friction)
  !> steps: the gas network run to its periodic state under the friction of the cycle just
  !> computed (the kernel's, positive towards the crankcase). Each step as the coupled cycle's
  !> own (cycle_state's ring_pack_advance): the friction at its start, the piston's
  !> acceleration at mid-step, so that the periodic state of the coupled cycle is this one's
  !> too.
  subroutine ring_pack_restart(c, par, kfrom, friction, st, cyc, err, face_k)
    type(case_type), intent(in) :: c
    type(ring_pack_params), intent(in) :: par
    integer, intent(in) :: kfrom
    real(dp), intent(in) :: friction(:)
    !> the face's gas path of each step of the cycle (a distorted bore)
    real(dp), intent(in), optional :: face_k(:)
    type(ring_pack_state), intent(inout) :: st
    type(ring_pack_cycle_out), intent(out) :: cyc
    type(error_type), allocatable, intent(out) :: err
    real(dp) :: p1(0:size(friction) - 1), ap(0:size(friction) - 1), ff(0:size(friction) - 1), &
                omega
    integer :: j, m
    m = size(friction)
    call ring_pack_inputs(c, kfrom - 2, p1, ap)
    omega = c%speed_rpm * 2.0_dp * pi / 60.0_dp
    ap = [(-piston_acceleration(deg2rad((kfrom - 1.5_dp + j) * c%dpsi_deg), c%crank_radius, &
                                c%conrod_length, omega), j=0, m - 1)]
    ff = [(-friction(modulo(kfrom - 2 + j, m) + 1), j=0, m - 1)]
    if (present(face_k)) then
      call ring_pack_cycle(par, p1, ap, ff, c%dpsi_deg, c%speed_rpm, c%crankcase_pressure, st, &
                           cyc, err, max_cycles=50, tol=1e-6_dp, step_values=.true., &
                           face_k=[(face_k(modulo(kfrom - 2 + j, m) + 1), j=0, m - 1)])
    else
      call ring_pack_cycle(par, p1, ap, ff, c%dpsi_deg, c%speed_rpm, c%crankcase_pressure, st, &
                           cyc, err, max_cycles=50, tol=1e-6_dp, step_values=.true.)
    end if
  end subroutine ring_pack_restart

  !> The ring pack's change from state st0 to st: its periodicity test. The groove pressure
  !> relative to the peak chamber pressure of case c, the land pressure relative to its gauge
  !> pressure above the crankcase (the larger of the two states'; at least land_floor of the
  !> peak: the blowby follows the land's gauge pressure, which lies far below the chamber's
  !> peak), the lift relative to the groove clearance. With the land pressure's contraction
  !> per cycle rho in (0, 1), the land's change counts as its distance from the periodic
  !> state, |d| / (1 - rho): a slow land changes little in a cycle far from it.
  pure real(dp) function ring_pack_distance(c, st, st0, rho)
    type(case_type), intent(in) :: c
    type(ring_pack_state), intent(in) :: st, st0
    real(dp), intent(in), optional :: rho
    real(dp) :: land, peak
    ! (no trace and no crankcase pressure: no gas anywhere, every pressure stays 0)
    peak = max(c%crankcase_pressure, maxval(c%gas_p, mask=c%gas_p > 0.0_dp), tiny(1.0_dp))
    land = abs(st%p3 - st0%p3) / max(max(st%p3, st0%p3) - c%crankcase_pressure, land_floor * peak)
    if (present(rho)) then
      if (rho > 0.0_dp .and. rho < 1.0_dp) land = land / (1.0_dp - rho)
    end if
    ring_pack_distance = max(abs(st%p2 - st0%p2) / peak, land) &
                         + abs(st%x - st0%x) / c%groove_clearance
  end function ring_pack_distance

  !> The cycle quantities from a cycle's sums; stored_end = m2 + m3 at the end, and
  !> tot%stored_start must hold m2 + m3 at the start.
  pure subroutine ring_pack_finish(tot, stored_end, cyc)
    type(ring_pack_totals), intent(in) :: tot
    real(dp), intent(in) :: stored_end
    type(ring_pack_cycle_out), intent(inout) :: cyc
    real(dp) :: gross
    gross = tot%gross_mass
    ! a sealed cycle (no gas through the boundaries): its closure relative to the gas held
    if (.not. gross > 0.0_dp) gross = max(tot%stored_start, stored_end, tiny(1.0_dp))
    cyc%blowby_mg_per_cycle = 1e6_dp * tot%blowby_mass
    cyc%blowby_l_min = tot%blowby_mass / tot%time * gas_constant * std_temperature &
                       / std_pressure * 6e4_dp
    cyc%blowback_mg_per_cycle = 1e6_dp * tot%blowback_mass
    ! (at most the whole cycle: the sub-steps' times add up to the cycle's within round-off,
    ! and 100 t / t can round above 100, a ring lifted all cycle read 100.00000000000001 %)
    cyc%ring_lift_share_pct = min(100.0_dp, 100.0_dp * tot%lift_time / tot%time)
    cyc%lift_against_gas_pct = min(100.0_dp, 100.0_dp * tot%lift_time_against_gas / tot%time)
    cyc%flutter_events = tot%flutter_events
    if (tot%hold_margin < huge(1.0_dp)) then
      cyc%flutter_margin = tot%hold_margin
      cyc%flutter_margin_ratio = tot%hold_margin / max(tot%inertia, tiny(1.0_dp))
    else
      cyc%flutter_margin = tot%inertia
      cyc%flutter_margin_ratio = 1.0_dp
    end if
    cyc%gas_exchange_mg_per_cycle = 1e6_dp * min(tot%gross_mass, tot%land_gross_mass)
    cyc%gas_balance_error = abs((stored_end - tot%stored_start) &
                                - (tot%inflow_mass - tot%blowby_mass)) / gross
    cyc%periodicity_error = abs(tot%inflow_mass - tot%blowby_mass) / gross
  end subroutine ring_pack_finish

  !> Run the gas network over whole cycles with prescribed p1, a_p and f_f at the crank
  !> angles psi_k = k dpsi_deg, k = 0 .. n-1 (periodic, n = 720/dpsi_deg; a_p and f_f on
  !> ring_pack_step's axis), until the state at psi = 0 repeats within `tol` (pressures
  !> relative to the largest chamber pressure, lift relative to the clearance) or
  !> max_cycles. st: the start (ring_pack_init if its p2 is not positive), then the state
  !> at the end. cyc: the last cycle.
  subroutine ring_pack_cycle(par, p1, a_p, f_f, dpsi_deg, speed_rpm, p4, st, cyc, err, &
                             max_cycles, tol, accelerate, rho_prior, face_k, step_values)
    type(ring_pack_params), intent(in) :: par
    real(dp), intent(in) :: p1(0:), a_p(0:), f_f(0:), dpsi_deg, speed_rpm, p4
    type(ring_pack_state), intent(inout) :: st
    type(ring_pack_cycle_out), intent(out) :: cyc
    type(error_type), allocatable, intent(out) :: err
    integer, intent(in), optional :: max_cycles
    real(dp), intent(in), optional :: tol
    !> Aitken's extrapolation of the land pressure (default .true.; .false.: plain cycles)
    logical, intent(in), optional :: accelerate
    !> the contraction a cycle of this map is known to have (from coarser cycles to the same
    !> state): in (0, 1), the first cycle can pass the test with it
    real(dp), intent(in), optional :: rho_prior
    !> the gas path through the ring's face at each crank angle (ring_pack_state%face_k;
    !> default none)
    real(dp), intent(in), optional :: face_k(0:)
    !> a_p(k) and f_f(k) are the step's own from psi_k to psi_k+1 and the step's length is the
    !> coupled cycle's (default .false.: the step takes the mean of its ends)
    logical, intent(in), optional :: step_values
    type(ring_pack_step_out) :: out
    type(ring_pack_totals) :: tot
    type(ring_pack_state) :: st0
    real(dp) :: dt, tol_, pmax, q(0:2), den, rho, d, dprev, rho_first
    integer :: n, k, kn, icyc, ncyc, nq
    logical :: acc, jumped, own
    real(dp) :: ff_k, ap_k
    n = size(p1)
    ncyc = 200
    if (present(max_cycles)) ncyc = max_cycles
    tol_ = 1e-9_dp
    if (present(tol)) tol_ = tol
    dt = dpsi_deg / (6.0_dp * speed_rpm)
    pmax = maxval(p1)
    if (st%p2 <= 0.0_dp) call ring_pack_init(st, p1(0), p4)
    allocate (cyc%p2(n), cyc%p3(n), cyc%x(n), cyc%top_gap_flow(n), cyc%second_gap_flow(n), &
              cyc%upper_channel_flow(n), cyc%lower_channel_flow(n))
    acc = .true.
    if (present(accelerate)) acc = accelerate
    own = .false.
    if (present(step_values)) own = step_values
    ! (the coupled cycle's step to the last bit, as cycle_state computes it: the sub-step
    ! control compares times with it)
    if (own) dt = deg2rad(dpsi_deg) / (speed_rpm * 2.0_dp * pi / 60.0_dp)
    nq = 0
    dprev = 0.0_dp
    do icyc = 1, ncyc
      jumped = .false.
      ! Aitken's extrapolation of the land pressure, the network's slow mode (the groove and
      ! the ring forget their start within a cycle): from three land pressures at a cycle's
      ! start, each the cycle map of the one before, when they converge monotonically (not the
      ! first start, often far from the linear regime)
      if (icyc > 1 .and. acc) then
        q(nq) = st%p3
        nq = nq + 1
      end if
      if (nq == 3) then
        den = q(2) - 2.0_dp * q(1) + q(0)
        rho = -1.0_dp
        if (q(1) /= q(0)) rho = (q(2) - q(1)) / (q(1) - q(0))
        ! (up to rho near 1: a large land relaxes over thousands of cycles; kept within half
        ! the last value and the peak chamber pressure)
        if (rho > 0.0_dp .and. rho < 0.9999_dp .and. abs(den) > 0.0_dp) then
          st%p3 = min(pmax, max(0.5_dp * q(2), q(2) - (q(2) - q(1))**2 / den))
          q(0) = st%p3
          nq = 1
          jumped = .true.
        else
          q(0:1) = q(1:2)
          nq = 2
        end if
      end if
      st0 = st
      cyc%start = st
      tot = ring_pack_totals()
      tot%stored_start = ring_pack_gas_mass(par, st)
      cyc%substeps = 0
      do k = 0, n - 1
        kn = mod(k + 1, n)
        if (present(face_k)) st%face_k = face_k(k)
        ff_k = 0.5_dp * (f_f(k) + f_f(kn))
        ap_k = 0.5_dp * (a_p(k) + a_p(kn))
        if (own) then
          ff_k = f_f(k)
          ap_k = a_p(k)
        end if
        call ring_pack_step(par, st, p1(k), p1(kn), p4, ff_k, ap_k, dt, out, err)
        if (allocated(err)) return
        call ring_pack_accumulate(tot, out, dt)
        cyc%substeps = cyc%substeps + out%substeps
        cyc%p2(k + 1) = st%p2
        cyc%p3(k + 1) = st%p3
        cyc%x(k + 1) = st%x
        cyc%top_gap_flow(k + 1) = out%top_gap_flow
        cyc%second_gap_flow(k + 1) = out%second_gap_flow
        cyc%upper_channel_flow(k + 1) = out%upper_channel_flow
        cyc%lower_channel_flow(k + 1) = out%lower_channel_flow
      end do
      call ring_pack_finish(tot, ring_pack_gas_mass(par, st), cyc)
      cyc%cycles_run = icyc
      cyc%converged = abs(st%p2 - st0%p2) <= tol_ * pmax .and. abs(st%p3 - st0%p3) <= tol_ * pmax &
                      .and. abs(st%x - st0%x) <= tol_ * par%groove_clearance &
                      .and. st%flank == st0%flank
      ! a slow land changes little in a cycle far from its periodic state: its distance there,
      ! d / (1 - rho) for a land pressure that contracts by rho a cycle, within tol too (and
      ! two cycles in a row, for rho: not the first)
      d = st%p3 - st0%p3
      ! (from an extrapolated start: the contraction the extrapolation estimated)
      if (.not. jumped) then
        rho = 0.0_dp
        if (dprev /= 0.0_dp) rho = d / dprev
      end if
      if (icyc == 1) then
        ! the first cycle only from a start near the periodic state (the coarse cycles'), with
        ! the contraction known from them: the land pressure it ends at then lies within
        ! rho |d| / (1 - rho) of its periodic value; rho taken prior_safety times the estimate,
        ! and the start at most 10 tol away
        rho_first = 0.0_dp
        if (present(rho_prior)) rho_first = prior_safety * rho_prior
        cyc%converged = cyc%converged .or. (abs(d) <= 10.0_dp * tol_ * pmax &
                                            .and. abs(st%p2 - st0%p2) <= tol_ * pmax &
                                            .and. abs(st%x - st0%x) <= tol_ * par%groove_clearance &
                                            .and. st%flank == st0%flank)
        cyc%converged = cyc%converged .and. rho_first > 0.0_dp .and. rho_first < 1.0_dp
        if (cyc%converged) cyc%converged = rho_first * abs(d) / (1.0_dp - rho_first) <= tol_ * pmax
      else if (rho > 0.0_dp .and. rho < 1.0_dp) then
        cyc%converged = cyc%converged .and. abs(d) / (1.0_dp - rho) <= tol_ * pmax
      else if (rho >= 1.0_dp) then
        ! not contracting: only round-off changes left
        cyc%converged = cyc%converged .and. abs(d) <= 1e-2_dp * tol_ * pmax
      end if
      dprev = d
      cyc%contraction = 0.0_dp
      if (icyc > 1 .and. abs(rho) < 1.0_dp) cyc%contraction = rho
      if (cyc%converged) exit
    end do
  end subroutine ring_pack_cycle
end module ringlube_ring_pack_cycle
