!> One engine cycle of the ring: the load balance at every crank step, the periodic state,
!> friction, power and energy (SPEC sections 4, 7, 8).
module ringlube_cycle
  use ringlube_kinds, only: dp, pi
  use ringlube_error, only: error_type, fatal_error, rl_input_error, rl_interrupted
  use ringlube_fsys, only: interrupt_requested
  use ringlube_case, only: case_type, elastic_pressure, ring_mass, steps_per_cycle
  use ringlube_kinematics, only: deg2rad, piston_position, piston_acceleration
  use ringlube_gas, only: gas_pressure
  use ringlube_ring_pack, only: ring_pack_params, ring_pack_state, ring_pack_step_out, &
                                ring_pack_step, ring_pack_gas_mass
  use ringlube_ring_pack_cycle, only: ring_pack_totals, ring_pack_cycle_out, ring_pack_accumulate, &
                                      ring_pack_finish, ring_pack_scalars, ring_pack_start, &
                                      ring_pack_restart
  use ringlube_greenwood_tripp, only: gt_init
  ! the results' table: result_type and the column constants s_* (series), si_* (integer
  ! series), sc_* (scalars), l_* (liner) and m_* (models)
  use ringlube_results
  use ringlube_oil_supply, only: supply_type, supply_setup, supply_edges, supply_step, &
                                 supply_reset_counters, supply_stored, supply_to_chamber, &
                                 supply_balance_error
  use ringlube_liner, only: liner_positions
  use ringlube_film, only: film_type, film_setup, film_friction
  use ringlube_load_balance, only: step_context, load_problem, balance_memory, balance, &
                                   start_history
  use ringlube_periodicity, only: cycle_history, history_start, history_h0, history_end, &
                                  history_period, history_changes, history_mean, &
                                  history_clean
  use, intrinsic :: ieee_arithmetic, only: ieee_is_finite
  implicit none
  private
  public :: solve_cycle

  !> least warm-up of the mass-conserving film [deg]. A starved inlet: the last upstroke and the
  !> 90 deg before it, so that the film the ring leaves on it is past the start-up transient of
  !> h0. Flooded with a vapour cavity: the cavity's content remembers the initial full film
  !> longer than the Swift-Stieber squeeze term remembers h0 (with 90 deg every shipped deck
  !> took a second cycle, 2.13 cycles computed instead of 1.38). Not 'trailing_gas', whose
  !> first cycle is periodic after 90 deg.
  real(dp), parameter :: jfo_warmup_deg = 270.0_dp
  !> least warm-up with the ring pack [deg]: from the end of the expansion stroke (450 deg),
  !> so that the land pressure at psi = 0 carries the film's friction through the ring's
  !> lift at blowdown (its start, the gas network's periodic state without friction, lies
  !> 0.3 % below the coupled one at psi = 0; with 90 deg the 8000 r/min deck needs a second
  !> cycle: docs/ring_pack.md)
  real(dp), parameter :: ring_pack_warmup_deg = 270.0_dp
  !> nodes of the Swift-Stieber film that runs the ring pack's warm-up before the film's own
  !> (it feeds the gas network its friction): the first of these for which the film has 4
  !> times as many intervals or more (none: the film itself)
  integer, parameter :: ring_pack_warmup_nodes(2) = [11, 7]

contains

  !> Run cycles until h0 is periodic (or max_cycles) and report the last one.
  subroutine solve_cycle(c, res, err)
    type(case_type), intent(in) :: c
    type(result_type), intent(out) :: res
    type(error_type), allocatable, intent(out) :: err
    type(film_type) :: f, g
    type(balance_memory) :: mem, gmem
    type(step_context) :: ctx
    type(supply_type) :: sup
    integer :: m, k, icycle, flags, cycles_run
    logical :: periodic, finite, start_settled
    real(dp) :: sigma, h0_init, h0_start, h0, h0_end, resid, s_prev, vin, vout
    real(dp) :: stored0, gap0, warmup, change_first, chg(4)
    ! the last cycles' states and results, and the period found (docs/model.md, "A period of
    ! several cycles")
    type(cycle_history) :: hist
    integer :: period
    type(load_problem) :: lp
    integer :: extra_film_solves, extra_solves
    ! the ring pack (SPEC 14): parameters, state (now, at the start of the cycle, on the copy
    ! that solves psi = 720), the last step, the cycle's sums; the last step's friction
    logical :: gas_pack
    type(ring_pack_params) :: rpar
    type(ring_pack_state) :: rst, gst
    type(ring_pack_step_out) :: rout, gout
    type(ring_pack_totals) :: rtot
    type(ring_pack_cycle_out) :: rcyc
    type(error_type), allocatable :: rerr
    real(dp) :: fric_prev, fv_adv, fb_adv
    ! the film's state where the re-warm after the first cycle starts (crank step k_rw)
    type(film_type) :: f_rw
    type(balance_memory) :: mem_rw
    type(supply_type) :: sup_rw
    real(dp) :: s_prev_rw, fric_rw, rewarm
    integer :: k_rw, k_film, k_nodes
    type(case_type) :: cc

    if (c%gt_functions == 'exact') call gt_init()

    m = steps_per_cycle(c)
    call allocate_result(res, m)

    call film_setup(c, f)
    ctx%omega = c%speed_rpm * 2.0_dp * pi / 60.0_dp
    ctx%dt = deg2rad(c%dpsi_deg) / ctx%omega
    ctx%p_e = elastic_pressure(c)
    sigma = f%sigma
    res%scalars(sc_sigma) = sigma
    res%scalars(sc_ring_mass) = ring_mass(c) * 1e3_dp   ! stored in g

    h0_init = 4.0_dp * sigma
    if (c%h0_initial > 0.0_dp) h0_init = c%h0_initial
    h0_init = min(max(h0_init, c%h0_floor), c%h0_ceiling)
    call start_history(mem, h0_init)
    h0_start = h0_init
    extra_film_solves = 0
    extra_solves = 0
    f%dt = ctx%dt
    ! the mass-conserving film starts full; the starved inlet from the supply film everywhere
    f%content_old = h0_init + f%s
    if (f%starved) call supply_setup(sup, c%width, 2.0_dp * c%crank_radius, f%dx, &
                                     c%supply_film, c%lower_ring_distance)
    ! warm-up: the last warmup_deg of a cycle before the first reported one, so that the
    ! squeeze-film memory of the initial guess has decayed by psi = 0; the mass-conserving film
    ! (starved, or flooded with a vapour cavity) warms up over at least the last upstroke and 90
    ! deg before it (jfo_warmup_deg), so that the first downstroke meets the film the ring itself
    ! left on the liner and the first cycle can already be periodic
    warmup = c%warmup_deg
    if (f%starved .or. (f%jfo .and. c%cavity_pressure == 'vapour')) &
      warmup = max(warmup, jfo_warmup_deg)
    ! the film's own warm-up starts at crank step k_film
    k_film = steps_per_cycle(c) - nint(warmup / c%dpsi_deg) + 1
    if (c%ring_pack == 'gas') warmup = max(warmup, ring_pack_warmup_deg)
    k = steps_per_cycle(c) - nint(warmup / c%dpsi_deg) + 1
    s_prev = position((k - 2) * c%dpsi_deg)
    fric_prev = 0.0_dp
    gas_pack = c%ring_pack == 'gas'
    k_rw = min(m, max(2, m - nint(c%warmup_deg / c%dpsi_deg) + 1))
    rewarm = 0.0_dp
    start_settled = .true.
    if (gas_pack) then
      call ring_pack_start(c, m, k, rpar, rst, rcyc, err)
      if (allocated(err)) return
      hist%land_contraction = rcyc%contraction
      start_settled = rcyc%converged
    end if
    k_nodes = findloc(c%nodes >= 4 * ring_pack_warmup_nodes - 3, .true., dim=1)
    if (gas_pack .and. k < k_film .and. k_nodes > 0 .and. .not. f%jfo) then
      ! the ring pack's warm-up before the film's own: a coarse Swift-Stieber film (its friction
      ! moves the ring; docs/ring_pack.md "Start"), then the film itself at the h0 reached
      cc = c
      cc%nodes = ring_pack_warmup_nodes(k_nodes)
      f_rw = f
      call film_setup(cc, f)
      f%dt = ctx%dt
      do k = k, k_film - 1
        call advance((k - 1) * c%dpsi_deg, h0, flags, resid, lp, vin, vout)
      end do
      call take_film(f_rw)
    end if
    do k = k, m
      call advance((k - 1) * c%dpsi_deg, h0, flags, resid, lp, vin, vout)
    end do
    if (allocated(rerr)) then
      call move_alloc(rerr, err)
      return
    end if
    periodic = .false.
    period = 0
    cycles_run = 0
    do icycle = 1, c%max_cycles
      cycles_run = icycle
      if (f%starved) then
        call supply_reset_counters(sup)
        gap0 = gap_volume()
        stored0 = supply_stored(sup) + gap0
      end if
      if (f%starved .and. gas_pack) then
        call history_start(hist, rp=rst, map=sup%liner%h)
      else if (f%starved) then
        call history_start(hist, map=sup%liner%h)
      else if (gas_pack) then
        call history_start(hist, rp=rst)
      else
        call history_start(hist)
      end if
      if (gas_pack) then
        rtot = ring_pack_totals()
        rtot%stored_start = ring_pack_gas_mass(rpar, rst)
      end if
      do k = 1, m
        if (gas_pack .and. icycle == 1 .and. k == k_rw) then
          f_rw = f
          mem_rw = mem
          if (f%starved) sup_rw = sup
          s_prev_rw = s_prev
          fric_rw = fric_prev
        end if
        call step(k, h0)
        if (k == 1) h0_start = h0
        if (k == 1) call history_h0(hist, h0)
      end do
      if (allocated(rerr)) then
        call move_alloc(rerr, err)
        return
      end if
      ! psi = 720 deg is psi = 0 of the next cycle: solve it on a copy of the film
      g = f
      gmem = mem
      call prepare(g, 0.0_dp)
      if (gas_pack) then
        ! the ring pack's state repeats too (pressures relative to the peak chamber pressure,
        ! lift relative to the clearance), and its last step to psi = 720 on a copy
        call ring_pack_finish(rtot, ring_pack_gas_mass(rpar, rst), rcyc)
        gst = rst
        call ring_pack_advance(gst, gout, 720.0_dp)
        g%p_back = gst%p2
        g%p_lower = gst%p3
      end if
      call balance(c, ctx, g, gmem, 0.0_dp, h0_end, flags, resid, lp)
      extra_film_solves = extra_film_solves + g%film_solves - f%film_solves
      extra_solves = extra_solves + g%reynolds_solves - f%reynolds_solves
      res%scalars(sc_cycle_change) = abs(h0_end - h0_start) / h0_start
      if (f%starved) then
        res%scalars(sc_oil_balance_error) = supply_balance_error(sup, stored0, gap_volume())
        res%scalars(sc_oil_to_chamber) = sup%to_chamber * f%circ * 1e9_dp
        ! the first cycle has no energy to compare with: the ring's state instead, h0 and the
        ! oil in the gap at its start and end
        change_first = max(res%scalars(sc_cycle_change), &
                           abs(gap_volume() - gap0) / max(gap0, tiny(1.0_dp)))
      end if
      call cycle_results()
      call history_end(hist, res%scalars(sc_energy_loss), &
                       all(iand(res%int_series(:, si_flags), not(flag_ceiling)) == 0), res%scalars)
      ! periodic: the smallest period after which the state repeats (starved: the liner film
      ! and the energy, since h0 at psi = 0 carries a slowly decaying mode of the film
      ! collected again at the end of the next downstroke; docs/model.md, "Periodicity")
      if (.not. f%starved) change_first = res%scalars(sc_cycle_change)
      if (f%starved .and. gas_pack) then
        period = history_period(hist, c, h0_end, change_first, rp_end=rst, map_end=sup%liner%h)
        chg = history_changes(hist, c, h0_end, change_first, period, rst, sup%liner%h)
      else if (f%starved) then
        period = history_period(hist, c, h0_end, change_first, map_end=sup%liner%h)
        chg = history_changes(hist, c, h0_end, change_first, period, map_end=sup%liner%h)
      else if (gas_pack) then
        period = history_period(hist, c, h0_end, change_first, rp_end=rst)
        chg = history_changes(hist, c, h0_end, change_first, period, rp_end=rst)
      else
        period = history_period(hist, c, h0_end, change_first)
        chg = history_changes(hist, c, h0_end, change_first, period)
      end if
      res%scalars([sc_cycle_change, sc_energy_change, sc_liner_change, sc_ring_pack_change]) = chg
      ! a gas start that did not settle says nothing of the land's distance from its periodic
      ! state, which a slow land's change over the first cycle does not show: the restart follows
      if (icycle == 1 .and. gas_pack .and. .not. start_settled) period = 0
      periodic = period > 0
      if (periodic) exit
      ! the first cycle not periodic: the next starts the ring pack from its periodic state
      ! under this cycle's friction (the land relaxes over several cycles; the friction settles
      ! with the film at once). Once only: the restart's state differs from the coupled
      ! cycle's by the half step its friction is shifted by, which a restart every cycle
      ! would feed back into the film at every cycle boundary.
      ! (not after the last cycle: the cycle's blowby and liner film are the results reported)
      if (gas_pack .and. icycle == 1 .and. icycle < c%max_cycles) then
        call ring_pack_restart(c, rpar, k_rw, res%series(:, s_friction), rst, rcyc, err)
        if (allocated(err)) return
        if (rcyc%contraction > 0.0_dp) hist%land_contraction = rcyc%contraction
        ! the film from its state at step k_rw again to psi = 720 with the restarted ring pack
        ! (the re-warm): the next cycle starts without a jump in the groove and land pressures
        call take_film(f_rw)
        mem = mem_rw
        if (f%starved) sup = sup_rw
        s_prev = s_prev_rw
        fric_prev = fric_rw
        do k = k_rw, m
          call advance((k - 1) * c%dpsi_deg, h0, flags, resid, lp, vin, vout)
        end do
        rewarm = (m - k_rw + 1) * c%dpsi_deg
        if (allocated(rerr)) then
          call move_alloc(rerr, err)
          return
        end if
      end if
    end do
    res%made(m_gas) = gas_pack
    res%made(m_jfo) = f%jfo
    res%made(m_starved) = f%starved
    if (f%starved) then
      call allocate_liner(res, sup%liner%nz)
      res%liner(:, l_liner_position) = liner_positions(sup%liner)
      res%liner(:, l_liner_oil_film) = sup%liner%h
    end if
    ! a period of several cycles: its cycle quantities are the means over them (the series and
    ! the extremes are the last cycle's)
    call history_mean(hist, period, mean_over_period, res%scalars)
    associate (v => res%scalars, power_loss => res%series(:, s_power_loss), &
               h0s => res%series(:, s_h0), friction => res%series(:, s_friction))
      v(sc_total_film_solves) = f%film_solves + extra_film_solves
      v(sc_reynolds_solves) = f%reynolds_solves + extra_solves
      v(sc_cycles_run) = cycles_run
      v(sc_cycles_computed) = cycles_run + (warmup + rewarm + c%dpsi_deg * cycles_run) / 720.0_dp
      v(sc_periodic) = truth(periodic)
      v(sc_period) = period
      ! a step held at h0_ceiling (the ring lifts off) is an answer of the model, flagged but not
      ! a failure; every other flag is, in every cycle of a period (all enter its means)
      v(sc_converged) = truth(periodic .and. history_clean(hist, period))
      k = findloc(ieee_is_finite(friction) .and. ieee_is_finite(h0s), .false., dim=1)
      finite = k == 0 .and. all(ieee_is_finite(power_loss)) .and. ieee_is_finite(v(sc_energy_loss))
    end associate
    if (.not. finite) then
      ! every input lies in its plausible range, so a non-finite film comes from a
      ! combination of inputs the model cannot describe: report it as an input problem
      call fatal_error(err, c%deck_path//': these inputs give a non-finite film solution'// &
             ' (first at crank angle '//trim(adjustl(angle_text(max(k, 1))))//' deg): check the'// &
                       ' operating point, ring and surface values together', rl_input_error)
    end if

  contains

    !> The cycle's results from its series (and the ring pack's sums).
    subroutine cycle_results()
      associate (v => res%scalars)
        v(sc_energy_loss) = sum(res%series(:, s_power_loss)) * ctx%dt
        v(sc_mixed_share) = mixed_share(res%series(:, s_h0) / sigma)
        v(sc_min_film) = minval(res%series(:, s_lambda_min)) * sigma
        v(sc_max_friction) = maxval(abs(res%series(:, s_friction)))
      end associate
      if (gas_pack) call ring_pack_scalars(rcyc, res%scalars)
      call derive_results(res, c%speed_rpm, pi * c%bore_radius**2 * 2.0_dp * c%crank_radius, &
                          c%oil_density)
    end subroutine cycle_results

    !> Piston position [m] at crank angle psi [deg].
    real(dp) function position(psi)
      real(dp), intent(in) :: psi
      position = piston_position(deg2rad(psi), c%crank_radius, c%conrod_length)
    end function position

    !> Oil in the gap (the interior volumes of the film) [m^2].
    real(dp) function gap_volume()
      gap_volume = f%dx * sum(f%content_old(2:f%n - 1))
    end function gap_volume

    !> Direction the piston moves in from s_prev to s: 1 towards the crankcase, -1 away, 0.
    integer function motion(s)
      real(dp), intent(in) :: s
      motion = 0
      if (s > s_prev) motion = 1
      if (s < s_prev) motion = -1
    end function motion

    !> Set what the starved inlet of film `ff` can draw on in the step to psi.
    subroutine prepare(ff, psi)
      type(film_type), intent(inout) :: ff
      real(dp), intent(in) :: psi
      real(dp) :: s
      integer :: dir
      if (.not. ff%starved) return
      s = position(psi)
      dir = motion(s)
      if (dir == 0) dir = sup%direction
      ff%ds = s - s_prev
      call supply_edges(sup, s_prev, s, dir, ff%available, ff%behind)
    end subroutine prepare

    !> Solve the step to psi and carry the film content and the oil supply forward.
    subroutine advance(psi, h0out, flags_out, resid_out, lp_out, v_in, v_out)
      real(dp), intent(in) :: psi
      real(dp), intent(out) :: h0out, resid_out, v_in, v_out
      integer, intent(out) :: flags_out
      type(load_problem), intent(out) :: lp_out
      real(dp) :: s
      integer :: dir
      ! Ctrl-C during a call from Python: the run stops here, the loops end it at their check
      if (.not. allocated(rerr) .and. interrupt_requested()) &
        call fatal_error(rerr, c%deck_path//': interrupted', rl_interrupted)
      if (allocated(rerr)) then
        h0out = 0.0_dp
        resid_out = 0.0_dp
        v_in = 0.0_dp
        v_out = 0.0_dp
        flags_out = 0
        return
      end if
      call prepare(f, psi)
      if (gas_pack) then
        call ring_pack_advance(rst, rout, psi)
        f%p_back = rst%p2
        f%p_lower = rst%p3
      end if
      call balance(c, ctx, f, mem, psi, h0out, flags_out, resid_out, lp_out)
      if (gas_pack) then
        ! the friction that moves the ring in its groove over the next step
        call film_friction(c, f, lp_out%u, fv_adv, fb_adv)
        fric_prev = fv_adv + fb_adv
      end if
      v_in = 0.0_dp
      v_out = 0.0_dp
      if (.not. f%jfo) return
      f%content_old = f%theta * f%h
      ! oil through the leading and trailing faces over the step
      if (f%lead_left) then
        v_in = f%q_left * ctx%dt
        v_out = f%q_right * ctx%dt
      else
        v_in = -f%q_right * ctx%dt
        v_out = -f%q_left * ctx%dt
      end if
      s = position(psi)
      if (f%starved) then
        dir = motion(s)
        call supply_step(sup, s_prev, s, dir, v_in, v_out)
        call supply_to_chamber(sup)
      end if
      s_prev = s
    end subroutine advance

    !> The film becomes `saved` (a state kept earlier), its solve counters keep counting.
    subroutine take_film(saved)
      type(film_type), intent(in) :: saved
      integer :: nfs, nrs
      nfs = f%film_solves
      nrs = f%reynolds_solves
      f = saved
      f%film_solves = nfs
      f%reynolds_solves = nrs
    end subroutine take_film

    function angle_text(kk) result(t)
      integer, intent(in) :: kk
      character(len=16) :: t
      write (t, '(f10.2)') (kk - 1) * c%dpsi_deg
    end function angle_text

    !> Solve crank step k (psi = (k-1) dpsi) and store it.
    subroutine step(k, h0out)
      integer, intent(in) :: k
      real(dp), intent(out) :: h0out
      real(dp) :: psi, resid, vin, vout
      type(load_problem) :: lp
      integer :: flags, nev
      psi = (k - 1) * c%dpsi_deg
      nev = f%film_solves
      call advance(psi, h0out, flags, resid, lp, vin, vout)
      if (.not. gas_pack) call film_friction(c, f, lp%u, fv_adv, fb_adv)
      res%series(k, s_crank_angle_deg) = psi
      res%series(k, s_sliding_speed) = lp%u
      res%series(k, s_h0) = h0out
      res%series(k, s_lambda_min) = minval(f%h) / sigma
      res%series(k, s_gas_pressure) = lp%pg
      res%series(k, s_applied_load) = lp%load
      res%series(k, s_hydrodynamic_load) = f%wh
      res%series(k, s_asperity_load) = f%wa
      res%series(k, s_viscous_friction) = fv_adv
      res%series(k, s_boundary_friction) = fb_adv
      res%series(k, s_friction) = fv_adv + fb_adv
      res%series(k, s_power_loss) = abs((fv_adv + fb_adv) * lp%u)
      res%series(k, s_load_residual) = resid
      res%int_series(k, si_flags) = flags
      res%int_series(k, si_film_solves) = f%film_solves - nev
      if (f%jfo) then
        res%series(k, s_inlet_fill) = f%theta_in
        ! the control volumes of full nodes: dx inside, dx/2 at an edge
        res%series(k, s_wetted_width) = f%dx * (count(f%theta(2:f%n - 1) >= 1.0_dp - 1e-9_dp) &
                                                + 0.5_dp * count([f%theta(1), f%theta(f%n)] &
                                                                 >= 1.0_dp - 1e-9_dp))
        res%series(k, s_oil_left) = 0.0_dp
        if (abs(f%ds) > 0.0_dp) res%series(k, s_oil_left) = max(vout, 0.0_dp) / abs(f%ds)
        if (.not. f%starved .and. abs(lp%u) > 0.0_dp) &
          res%series(k, s_oil_left) = max(vout, 0.0_dp) / (abs(lp%u) * ctx%dt)
      end if
      if (f%starved) res%series(k, s_oil_bank) = sup%bank
      if (gas_pack) then
        res%series(k, s_groove_pressure) = rst%p2
        res%series(k, s_land_pressure) = rst%p3
        res%series(k, s_ring_lift) = rst%x
        res%series(k, s_top_gap_flow) = rout%top_gap_flow
        res%series(k, s_second_gap_flow) = rout%second_gap_flow
        call ring_pack_accumulate(rtot, rout, ctx%dt)
      end if
    end subroutine step

    !> Chamber pressure [Pa] at crank angle psi [deg] (the trace, scaled).
    real(dp) function chamber(psi)
      real(dp), intent(in) :: psi
      chamber = gas_pressure(c%gas_psi, c%gas_p, modulo(psi, 720.0_dp), c%crankcase_pressure)
    end function chamber

    !> Advance the ring pack's state `st` over the crank step ending at psi [deg]: the chamber
    !> pressure linear in time over the step, the friction of the last step (explicit: the
    !> gas and the ring's axial motion are advanced first, then the film at the step's end
    !> sees the new groove and land pressures), the piston's acceleration at mid-step.
    subroutine ring_pack_advance(st, out, psi)
      type(ring_pack_state), intent(inout) :: st
      type(ring_pack_step_out), intent(out) :: out
      real(dp), intent(in) :: psi
      real(dp) :: a_p
      a_p = -piston_acceleration(deg2rad(psi - 0.5_dp * c%dpsi_deg), c%crank_radius, &
                                 c%conrod_length, ctx%omega)
      if (allocated(rerr)) return
      call ring_pack_step(rpar, st, chamber(psi - c%dpsi_deg), chamber(psi), &
                          c%crankcase_pressure, -fric_prev, a_p, ctx%dt, out, rerr)
    end subroutine ring_pack_advance
  end subroutine solve_cycle
end module ringlube_cycle
