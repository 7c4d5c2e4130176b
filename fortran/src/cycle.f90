!> One engine cycle of the ring: the warm-up, the cycles run until the ring's state is
!> periodic, and the reported cycle's results (docs/model.md "Cycle and periodic state"). A crank step
!> and what it carries are in ringlube_cycle_state.
module ringlube_cycle
  use ringlube_kinds, only: dp, pi
  use ringlube_error, only: error_type, fatal_error, rl_input_error, rl_interrupted
  use ringlube_case, only: case_type, ring_mass, steps_per_cycle, composite_sigma
  use ringlube_ring_pack, only: ring_pack_state, ring_pack_step_out, ring_pack_gas_mass
  use ringlube_ring_pack_cycle, only: ring_pack_totals, ring_pack_finish, ring_pack_scalars, &
                                      ring_pack_start, ring_pack_restart, ring_pack_cycle_out, &
                                      ring_pack_distance
  use ringlube_greenwood_tripp, only: gt_init
  ! the results' table: result_type and the column constants s_* (series), si_* (integer
  ! series), sc_* (scalars), l_* (liner) and m_* (models)
  use ringlube_results
  use ringlube_oil_supply, only: supply_type, supply_reset_counters, supply_stored, &
                                 supply_balance_error
  use ringlube_liner, only: liner_positions, strip_set, strip_copy
  use ringlube_film, only: film_type, film_setup, film_temperature
  use ringlube_load_balance, only: balance
  use ringlube_cycle_state, only: film_track, cycle_state, step_out, cycle_setup, advance, &
                                  solve_step, prepare_inlet, ring_pack_advance, take_film, &
                                  gap_volume, position, ring_team_begin, ring_team_serves, &
                                  ring_team_stop, ring_team_end, advance_steps
  use ringlube_sectors, only: sector_ring, exact_mean
  use ringlube_bore, only: bore_distortion, conformability, conformability_orders
  use ringlube_periodicity, only: cycle_history, history_start, history_h0, history_end, &
                                  history_measure, history_period, history_changes, &
                                  history_mean, history_clean, history_extrapolate, &
                                  q_ring_pack, q_energy, last_slot, liner_window_cells
  use ringlube_fsys, only: progress_begin, progress_cycle, progress_end
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
  !> the BDC start's second pass (bdc_start): from this many degrees before the warm-up's BDC
  !> (psi = 540) to as many after it [deg]. The ring gathers the film it laid leaving the
  !> last BDC within about 5 mm of the lower edge's BDC position (where the shipped decks'
  !> liner films rise above the supply film), which it travels in about 38 deg
  real(dp), parameter :: bdc_pass_deg = 40.0_dp
  !> the BDC (psi) the warm-up passes
  real(dp), parameter :: warmup_bdc = 540.0_dp
  !> the liner film's extrapolations a run makes at most (extrapolate_liner)
  integer, parameter :: max_extrapolations = 2
  !> the pilot cycle's crank step in steps of the run's (pilot_friction; halved until the
  !> cycle's steps divide by it, none below 2): without a starved inlet 8, whose friction
  !> starts the ring pack as well as 4 times the step did on the 'gas' decks (the same cycles,
  !> 0.17 instead of 0.34 of a cycle's crank steps); starved 4 (at 8 the 12,000 r/min 'gas'
  !> deck read in N/m was not periodic in 10 cycles, against 7 at 4)
  integer, parameter :: pilot_stride = 8, pilot_stride_starved = 4

  !> Where the ring pack's first cycle is solved again from after its restart (the re-warm):
  !> crank step k and the state before it.
  type :: rewarm_point
    integer :: k = 0
    type(film_track) :: film
    !> a distorted bore's sectors and their liner oil
    type(sector_ring), allocatable :: ring
    type(supply_type), allocatable :: sups(:)
    real(dp) :: s_prev = 0.0_dp, fric_prev = 0.0_dp
    !> the ring pack before step k of the cycle just run, and its periodic state there under
    !> that cycle's friction (the gas network alone, ring_pack_restart) where it was computed
    !> at the cycle's end (`periodic_done`)
    type(ring_pack_state) :: rp
    type(ring_pack_state) :: rp_periodic
    type(ring_pack_cycle_out) :: rp_periodic_cyc
    logical :: periodic_done = .false.
  end type rewarm_point

  !> What a run of cycles keeps between them beside the cycle state.
  type :: cycle_run
    !> the last cycles' states and results, and the period found (docs/model.md, "A period of
    !> several cycles")
    type(cycle_history) :: hist
    integer :: period = 0, cycles_run = 0
    logical :: periodic = .false.
    !> the next cycle starts where the last one ended (not after the ring pack's restart);
    !> the cycle being run did; its ring pack asks for a restart
    logical :: continues = .true., continued = .false., restart = .false.
    !> the next cycle starts from a liner film extrapolated with this contraction per cycle
    !> (accelerate; 0: not extrapolated); extrapolations so far
    real(dp) :: rho_map = 0.0_dp
    integer :: extrapolations = 0
    !> h0 at psi = 0 of the cycle and at its end (psi = 720 deg) [m]
    real(dp) :: h0_start = 0.0_dp, h0_end = 0.0_dp
    !> starved: stored oil and the gap's oil at the cycle's start of each film (one; a
    !> distorted bore's sectors) [m^2]; the first cycle's change of the ring's state (its
    !> energy has nothing to be compared with)
    real(dp), allocatable :: stored0(:), gap0(:)
    real(dp) :: change_first = 0.0_dp
    !> warm-up and re-warm [deg]
    real(dp) :: warmup = 0.0_dp, rewarm = 0.0_dp
    !> the pilot cycle's crank steps (with its warm-up) in cycles of the run's steps
    !> (`&numerics pilot_cycle`; 0: none)
    real(dp) :: pilot = 0.0_dp
    type(rewarm_point) :: rw
  end type cycle_run

contains

  !> Run cycles until the ring's state is periodic (or max_cycles) and report the last one
  !> (with a progress line on a terminal where the front end asked for one, ringlube_fsys).
  subroutine solve_cycle(c, res, err)
    type(case_type), intent(in) :: c
    type(result_type), intent(out) :: res
    type(error_type), allocatable, intent(out) :: err
    call progress_begin(c%max_cycles)
    call run_cycles(c, res, err)
    call progress_end()
  end subroutine solve_cycle

  !> Run cycles until the ring's state is periodic (or max_cycles) and report the last one.
  subroutine run_cycles(c, res, err)
    type(case_type), intent(in) :: c
    type(result_type), intent(out) :: res
    type(error_type), allocatable, intent(out) :: err
    type(cycle_state) :: st
    type(cycle_run) :: run
    real(dp), allocatable :: pilot_fric(:)
    integer :: icycle

    if (c%gt_functions == 'exact') call gt_init()
    call allocate_result(res, steps_per_cycle(c))
    call cycle_setup(st, c, initial_h0(c))
    if (allocated(st%ring)) call allocate_sectors(res, st%ring%bore%m)
    res%scalars(sc_sigma) = st%sigma
    res%scalars(sc_ring_mass) = ring_mass(c) * 1e3_dp   ! stored in g
    ! (not on a distorted bore; with a starved inlet the pilot's liner film is not kept: the
    ! pilot gives the ring pack its start, the film starts as without it, at BDC)
    if (c%pilot_cycle .and. allocated(st%rst) .and. .not. allocated(st%ring)) then
      call pilot_friction(c, pilot_fric, run%pilot, st%extra_film_solves, st%extra_solves, err)
      ! (a pilot that fails, or gives a non-finite friction, is no start: the run starts
      ! without it, and does not count it in its cycles and solves; an interrupt ends the run)
      if (allocated(err)) then
        if (err%code == rl_interrupted) return
        deallocate (err)
        if (allocated(pilot_fric)) deallocate (pilot_fric)
        run%pilot = 0.0_dp
      end if
    end if
    call warm_up(st, c, run, err, pilot_fric)
    if (allocated(err)) return
    do icycle = 1, c%max_cycles
      run%cycles_run = icycle
      call progress_cycle(icycle)
      call run_cycle(st, c, res, run, icycle)
      if (allocated(st%err)) then
        call move_alloc(st%err, err)
        return
      end if
      call end_cycle(st, c, res, run)
      if (allocated(st%err)) then
        call move_alloc(st%err, err)
        return
      end if
      if (run%periodic) exit
      ! (not after the last cycle: the cycle's blowby and liner film are the results reported)
      if (icycle == c%max_cycles) exit
      ! a cycle not periodic whose ring pack lies far from its periodic state under the cycle's
      ! friction (the first cycle, or a slow land that would take more than ten cycles to get
      ! there): the next starts the ring pack from that state (the land relaxes over several
      ! cycles; the friction settles with the film at once)
      ! (after a pilot the first cycle started near that state already; with `first_restart`
      ! 'away', starved on a round bore with the liner film judged over a window, not where the
      ! first cycle's ring pack lies within cycle_tol of it: the jump would gain nothing and
      ! leave the next cycle's energy unjudged)
      if (allocated(st%rst) .and. ((icycle == 1 .and. run%pilot == 0.0_dp .and. &
                                    first_restart(c, st, run)) .or. run%restart)) then
        call restart_ring_pack(st, c, res, run, err)
        if (allocated(err)) return
        run%continues = .false.
      end if
      if (c%accelerate) call extrapolate_liner(st, run)
    end do
    call report(st, c, res, run, err)
  end subroutine run_cycles

  !> Does the ring pack restart after a first cycle that was not periodic? With
  !> `first_restart = 'away'` (the default), a starved run on a round bore whose liner film is
  !> judged over a window of cells as well (liner_window_cells: the BDC start's 50) restarts it
  !> only where it lies beyond cycle_tol of the gas network's periodic state under the first
  !> cycle's friction (its distance measured directly, ring_pack_periodic, at the re-warm's
  !> first step rw%k, warmup_deg before the cycle's end):
  !> a ring pack within cycle_tol of that state gains nothing from the jump, and the cycle
  !> after a restart cannot be judged on its energy. Every other run (and 'always'): every
  !> time. Judged on the whole liner film alone, the second cycle is no safe test: the cold
  !> deck with the ring pack and the plain start passed it with h0 at 154 deg 1.9e-3 from its
  !> periodic state (docs/model.md, "Pilot cycle").
  logical function first_restart(c, st, run)
    type(case_type), intent(in) :: c
    type(cycle_state), intent(in) :: st
    type(cycle_run), intent(in) :: run
    integer :: w
    first_restart = .true.
    if (allocated(st%ring) .or. c%first_restart == 'always' .or. .not. st%film%f%starved) return
    w = liner_window_cells(c)
    if (w <= 0 .or. w >= st%film%sup%liner%nz) return
    first_restart = .not. (run%rw%periodic_done .and. run%hist%distance(q_ring_pack) <= c%cycle_tol)
  end function first_restart

  !> The friction of a pilot cycle at each crank step of case c (fric, interpolated linearly
  !> between the pilot's steps): the case run at pilot_stride (starved pilot_stride_starved)
  !> times its crank step over its warm-up and one cycle (the same grid and models). cost: the pilot's crank steps in cycles
  !> of the case's; its film and Reynolds solves are added to film_solves, solves. fric is
  !> not allocated where the cycle's steps do not divide by 2.
  subroutine pilot_friction(c, fric, cost, film_solves, solves, err)
    type(case_type), intent(in) :: c
    real(dp), allocatable, intent(out) :: fric(:)
    real(dp), intent(out) :: cost
    integer, intent(inout) :: film_solves, solves
    type(error_type), allocatable, intent(out) :: err
    type(case_type) :: cp
    type(cycle_state) :: sp
    type(cycle_run) :: rp
    type(result_type) :: resp
    integer :: m, mp, s, k, kc
    real(dp) :: r
    cost = 0.0_dp
    m = steps_per_cycle(c)
    s = pilot_stride
    if (c%inlet == 'starved') s = pilot_stride_starved
    do while (s > 1 .and. mod(m, s) /= 0)
      s = s / 2
    end do
    if (s == 1) return
    cp = c
    cp%dpsi_deg = s * c%dpsi_deg
    cp%pilot_cycle = .false.
    mp = m / s
    call allocate_result(resp, mp)
    call cycle_setup(sp, cp, initial_h0(cp))
    call warm_up(sp, cp, rp, err)
    if (allocated(err)) return
    rp%cycles_run = 1
    call run_cycle(sp, cp, resp, rp, 1)
    if (allocated(sp%err)) then
      call move_alloc(sp%err, err)
      return
    end if
    allocate (fric(m))
    do k = 1, m
      kc = (k - 1) / s
      r = real(mod(k - 1, s), dp) / s
      fric(k) = (1.0_dp - r) * resp%series(kc + 1, s_friction) &
                + r * resp%series(modulo(kc + 1, mp) + 1, s_friction)
    end do
    if (.not. all(ieee_is_finite(fric))) then  ! no start, and not counted
      deallocate (fric)
      return
    end if
    ! its crank steps, as run (a starved pilot's BDC start: its second pass too)
    cost = real(nint((rp%warmup + rp%rewarm) / cp%dpsi_deg) + mp, dp) / m
    film_solves = film_solves + sp%film%f%film_solves
    solves = solves + sp%film%f%reynolds_solves
  end subroutine pilot_friction

  !> h0 of the state before the first step: 4 sigma, or &numerics h0_initial, inside the
  !> bounds.
  pure real(dp) function initial_h0(c) result(h0)
    type(case_type), intent(in) :: c
    h0 = 4.0_dp * composite_sigma(c)
    if (c%h0_initial > 0.0_dp) h0 = c%h0_initial
    h0 = min(max(h0, c%h0_floor), c%h0_ceiling)
  end function initial_h0

  !> The warm-up: the last `warmup` degrees of a cycle before the first reported one, so that
  !> the squeeze-film memory of the initial guess has decayed by psi = 0. The mass-conserving
  !> film (starved, or flooded with a vapour cavity) warms up over at least the last upstroke
  !> and 90 deg before it (jfo_warmup_deg), so that the first downstroke meets the film the ring
  !> itself left on the liner and the first cycle can already be periodic. With the ring pack,
  !> its gas network starts from its own periodic state (ring_pack_start), and a coarse
  !> Swift-Stieber film runs the part of the warm-up before the film's own.
  subroutine warm_up(st, c, run, err, pilot_fric)
    type(cycle_state), intent(inout) :: st
    type(case_type), intent(in) :: c
    type(cycle_run), intent(inout) :: run
    type(error_type), allocatable, intent(out) :: err
    !> the friction of a pilot cycle at each crank step (pilot_friction; not allocated: none)
    real(dp), allocatable, intent(in), optional :: pilot_fric(:)
    type(step_out) :: out
    type(film_track) :: fine
    type(sector_ring), allocatable :: fine_ring
    type(case_type) :: cc
    type(cycle_state) :: first
    integer :: m, k, k_film, k_nodes, j, ka, kb
    logical :: piloted

    m = steps_per_cycle(c)
    call progress_cycle(0)
    run%warmup = c%warmup_deg
    associate (f => st%film%f)
      if (f%starved .or. (f%jfo .and. c%cavity_pressure == 'vapour')) &
        run%warmup = max(run%warmup, jfo_warmup_deg)
    end associate
    ! the film's own warm-up starts at crank step k_film
    k_film = m - nint(run%warmup / c%dpsi_deg) + 1
    piloted = .false.
    if (present(pilot_fric)) piloted = allocated(pilot_fric)
    ! (the ring pack's own warm-up brings the friction into the land pressure; a start under a
    ! pilot cycle's friction has it already)
    if (allocated(st%rst) .and. .not. piloted) run%warmup = max(run%warmup, ring_pack_warmup_deg)
    k = m - nint(run%warmup / c%dpsi_deg) + 1
    st%s_prev = position(c, (k - 2) * c%dpsi_deg)
    st%fric_prev = 0.0_dp
    run%rw%k = min(m, max(2, m - nint(c%warmup_deg / c%dpsi_deg) + 1))
    run%rewarm = 0.0_dp
    if (allocated(st%rst)) then
      call ring_pack_start(c, m, k, st%rpar, st%rst, st%rcyc, err)
      if (allocated(err)) return
      run%hist%land_contraction = st%rcyc%contraction
      if (piloted) then
        ! from the gas network's periodic state under the pilot cycle's friction
        call ring_pack_restart(c, st%rpar, k, pilot_fric, st%rst, st%rcyc, err)
        if (allocated(err)) return
        if (st%rcyc%contraction > 0.0_dp) run%hist%land_contraction = st%rcyc%contraction
      end if
    end if
    k_nodes = findloc(c%nodes >= 4 * ring_pack_warmup_nodes - 3, .true., dim=1)
    if (allocated(st%rst) .and. k < k_film .and. k_nodes > 0 .and. .not. st%film%f%jfo) then
      ! the ring pack's warm-up before the film's own: a coarse Swift-Stieber film (its friction
      ! moves the ring; docs/ring_pack.md "Start"), then the film itself at the h0 reached
      cc = c
      cc%nodes = ring_pack_warmup_nodes(k_nodes)
      fine%f = st%film%f
      call film_setup(cc, st%film%f)
      st%film%f%dt = st%ctx%dt
      if (allocated(st%ring)) then
        fine_ring = st%ring
        do j = 1, size(st%ring%films)
          st%ring%films(j) = st%film%f
        end do
      end if
      do k = k, k_film - 1
        call advance(st, c, (k - 1) * c%dpsi_deg, out)
      end do
      call take_film(st%film%f, fine%f)
      if (allocated(st%ring)) then
        do j = 1, size(st%ring%films)
          call take_film(st%ring%films(j), fine_ring%films(j))
        end do
      end if
    end if
    ! (`&numerics bdc_start`; not with a 'trailing_gas' cavity, nor on a distorted bore)
    ka = nint((warmup_bdc - bdc_pass_deg) / c%dpsi_deg) + 1
    kb = nint((warmup_bdc + bdc_pass_deg) / c%dpsi_deg) + 1
    if (st%film%f%starved .and. c%bdc_start .and. c%cavity_pressure == 'vapour' .and. &
        .not. allocated(st%ring) .and. ka >= k .and. kb <= m) then
      call flood_bdc(st, c)
      do k = k, kb
        if (k == ka) first = st
        call advance(st, c, (k - 1) * c%dpsi_deg, out)
      end do
      if (.not. allocated(st%err)) then
        call second_pass(st, c, first, (kb - 1) * c%dpsi_deg)
        run%rewarm = run%rewarm + (kb - ka + 1) * c%dpsi_deg
        k = ka
      end if
    end if
    call advance_steps(st, c, k, m)
    if (allocated(st%err)) call move_alloc(st%err, err)
  end subroutine warm_up

  !> The BDC start's first guess (bdc_start): the liner under the face at the warm-up's BDC
  !> flooded, at half the ring's largest initial gap at an edge (at least the supply film), so
  !> that the ring's gap fills through its leading edge in the last steps before BDC
  !> (inlet_fill is 1 for a film of half the gap there) and it reaches BDC full.
  subroutine flood_bdc(st, c)
    type(cycle_state), intent(inout) :: st
    type(case_type), intent(in) :: c
    real(dp) :: s, hf, removed, added
    associate (f => st%film%f, sup => st%film%sup)
      s = position(c, warmup_bdc)
      hf = max(sup%supply_film, 0.5_dp * max(f%content_old(1), f%content_old(f%n)))
      call strip_set(sup%liner, s - sup%half_width, s + sup%half_width, hf, removed, added)
    end associate
  end subroutine flood_bdc

  !> The BDC start's second pass: the state `first` (kept bdc_pass_deg before the warm-up's
  !> BDC) becomes the state again, with the film the ring has laid since BDC (from the lower
  !> edge's position at BDC to its position at psi_now) on its liner: the film a ring leaving
  !> the BDC before would have left there, which it gathers again before this one. The solve
  !> counters keep counting.
  subroutine second_pass(st, c, first, psi_now)
    type(cycle_state), intent(inout) :: st
    type(case_type), intent(in) :: c
    type(cycle_state), intent(inout) :: first
    real(dp), intent(in) :: psi_now
    integer :: nfs, nrs, efs, ers
    associate (sup => st%film%sup)
      call strip_copy(first%film%sup%liner, sup%liner, position(c, psi_now) + sup%half_width, &
                      position(c, warmup_bdc) + sup%half_width)
    end associate
    nfs = st%film%f%film_solves
    nrs = st%film%f%reynolds_solves
    efs = st%extra_film_solves
    ers = st%extra_solves
    st = first
    st%film%f%film_solves = nfs
    st%film%f%reynolds_solves = nrs
    st%extra_film_solves = efs
    st%extra_solves = ers
  end subroutine second_pass

  !> Run the cycle's crank steps and store them in res (with the ring pack, the first cycle
  !> keeps the state at the re-warm's first step).
  subroutine run_cycle(st, c, res, run, icycle)
    type(cycle_state), intent(inout) :: st
    type(case_type), intent(in) :: c
    type(result_type), intent(inout) :: res
    type(cycle_run), intent(inout) :: run
    integer, intent(in) :: icycle
    real(dp) :: h0
    real(dp), allocatable :: map(:)
    integer :: k, j
    logical :: held
    associate (f => st%film%f, sup => st%film%sup)
      if (f%starved .and. allocated(st%ring)) then
        run%gap0 = [(gap_volume(st%ring%films(j)), j=1, size(st%sups))]
        do j = 1, size(st%sups)
          call supply_reset_counters(st%sups(j))
        end do
        run%stored0 = [(supply_stored(st%sups(j)), j=1, size(st%sups))] + run%gap0
      else if (f%starved) then
        call supply_reset_counters(sup)
        run%gap0 = [gap_volume(f)]
        run%stored0 = [supply_stored(sup) + run%gap0(1)]
      end if
      call liner_map(st, map)
      ! (an unallocated state or map is an absent argument: the run has none)
      run%continued = run%continues .and. icycle > 1
      call history_start(run%hist, rp=st%rst, map=map, continued=run%continued, &
                         rho_map=run%rho_map)
      run%continues = .true.
      run%rho_map = 0.0_dp
      run%rw%periodic_done = .false.
      if (allocated(st%rst)) then
        st%rtot = ring_pack_totals()
        st%rtot%stored_start = ring_pack_gas_mass(st%rpar, st%rst)
      end if
      ! (a distorted bore with threads: the cycle's steps in one parallel region, thread 0
      ! running them, the others serving their passes over the sectors; ringlube_cycle_state)
      held = ring_team_begin(st, c)
      !$omp parallel if (held) num_threads(c%threads) default(shared)
      if (.not. ring_team_serves(held)) then
        do k = 1, steps_per_cycle(c)
          if (allocated(st%rst) .and. k == run%rw%k) run%rw%rp = st%rst
          if (allocated(st%rst) .and. k == run%rw%k) then
            run%rw%film%f = f
            run%rw%film%mem = st%film%mem
            if (f%starved) run%rw%film%sup = sup
            if (allocated(st%ring)) then
              run%rw%ring = st%ring
              run%rw%sups = st%sups
            end if
            run%rw%s_prev = st%s_prev
            run%rw%fric_prev = st%fric_prev
          end if
          call solve_step(st, c, res, k, h0)
          if (k == 1) run%h0_start = h0
          if (k == 1) call history_h0(run%hist, h0)
        end do
        call ring_team_stop(held)
      end if
      !$omp end parallel
      call ring_team_end(held)
    end associate
  end subroutine run_cycle

  !> The cycle's end: psi = 720 deg (psi = 0 of the next cycle) solved on a copy of the film,
  !> the cycle's results, and whether the ring's state is periodic: the smallest period after
  !> which it repeats (starved: the liner film and the energy, since h0 at psi = 0 carries a
  !> slowly decaying mode of the film collected again at the end of the next downstroke;
  !> docs/model.md, "Periodicity").
  subroutine end_cycle(st, c, res, run)
    type(cycle_state), intent(inout) :: st
    type(case_type), intent(in) :: c
    type(result_type), intent(inout) :: res
    type(cycle_run), intent(inout) :: run
    type(film_track) :: g
    type(ring_pack_state), allocatable :: gst
    type(ring_pack_step_out) :: gout
    type(step_out) :: out
    type(sector_ring), allocatable :: gring
    real(dp), allocatable :: map(:), gap_end(:)
    real(dp) :: direct
    integer :: j
    associate (f => st%film%f, sup => st%film%sup)
      g%f = f
      g%mem = st%film%mem
      call prepare_inlet(c, g%f, sup, st%s_prev, 0.0_dp)
      call film_temperature(c, g%f, 0.0_dp)
      if (allocated(st%ring)) then
        gring = st%ring
        do j = 1, size(st%sups)
          call prepare_inlet(c, gring%films(j), st%sups(j), st%s_prev, 0.0_dp)
          call film_temperature(c, gring%films(j), 0.0_dp)
        end do
        call bore_distortion(gring%bore, position(c, 720.0_dp), gring%d)
      end if
      if (allocated(st%rst)) then
        ! the ring pack's state repeats too (pressures relative to the peak chamber pressure,
        ! lift relative to the clearance), and its last step to psi = 720 on a copy
        call ring_pack_finish(st%rtot, ring_pack_gas_mass(st%rpar, st%rst), st%rcyc)
        gst = st%rst
        call ring_pack_advance(c, st%ctx, st%rpar, st%fric_prev, gst, gout, 720.0_dp, st%err)
        g%f%p_back = gst%p2
        g%f%p_lower = gst%p3
      end if
      if (allocated(st%ring)) then
        call balance(c, st%ctx, g%f, g%mem, 0.0_dp, run%h0_end, out%flags, out%resid, out%lp, &
                     gring)
      else
        call balance(c, st%ctx, g%f, g%mem, 0.0_dp, run%h0_end, out%flags, out%resid, out%lp)
      end if
      st%extra_film_solves = st%extra_film_solves + g%f%film_solves - f%film_solves
      st%extra_solves = st%extra_solves + g%f%reynolds_solves - f%reynolds_solves
      res%scalars(sc_cycle_change) = abs(run%h0_end - run%h0_start) / run%h0_start
      run%change_first = res%scalars(sc_cycle_change)
      if (f%starved .and. allocated(st%ring)) then
        gap_end = [(gap_volume(st%ring%films(j)), j=1, size(st%sups))]
        res%scalars(sc_oil_balance_error) = &
          maxval([(supply_balance_error(st%sups(j), run%stored0(j), gap_end(j)), &
                   j=1, size(st%sups))])
        res%scalars(sc_oil_to_chamber) = exact_mean(st%sups%to_chamber) * f%circ * 1e9_dp
      else if (f%starved) then
        gap_end = [gap_volume(f)]
        res%scalars(sc_oil_balance_error) = supply_balance_error(sup, run%stored0(1), gap_end(1))
        res%scalars(sc_oil_to_chamber) = sup%to_chamber * f%circ * 1e9_dp
      end if
      if (f%starved) then
        ! the first cycle has no energy to compare with: the ring's state instead, h0 and the
        ! oil in the gap at its start and end
        run%change_first = max(res%scalars(sc_cycle_change), &
                               abs(exact_mean(gap_end) - exact_mean(run%gap0)) &
                               / max(exact_mean(run%gap0), tiny(1.0_dp)))
      end if
      call cycle_results(st, c, res)
      call history_end(run%hist, res%scalars(sc_energy_loss), &
                       all(iand(res%int_series(:, si_flags), not(flag_ceiling)) == 0), &
                       res%scalars)
      call liner_map(st, map)
      run%restart = .false.
      if (allocated(st%rst)) then
        ! the ring pack's distance from the periodic state of the gas network under the
        ! cycle's friction (a slow land changes little in a cycle far from it)
        call ring_pack_periodic(st, c, res, run, direct)
        if (allocated(st%err)) return
        call history_measure(run%hist, c, run%h0_end, run%change_first, rp_end=st%rst, &
                             map_end=map, rp_direct=direct)
        ! a slow approach (contracting by more than a half a cycle, from one side) still more
        ! than ten of the cycle's own changes away: restart it there
        run%restart = direct > c%cycle_tol .and. run%hist%rho(q_ring_pack) > 0.5_dp .and. &
                      direct > 10.0_dp * run%hist%change(q_ring_pack, last_slot(run%hist))
      else
        call history_measure(run%hist, c, run%h0_end, run%change_first, map_end=map)
      end if
      ! (after a pilot the first cycle's energy says nothing of its distance: the ring's state
      ! may lie near the gas network's periodic state under the pilot's friction while the
      ! energy still moves with the coupled state, which only a cycle that continued it shows)
      if (run%pilot > 0.0_dp .and. run%hist%cycles == 1) run%hist%judged(q_energy) = .false.
      run%period = history_period(run%hist, c, run%h0_end, rp_end=st%rst, map_end=map)
      res%scalars([sc_cycle_change, sc_energy_change, sc_liner_change, sc_ring_pack_change]) = &
        history_changes(run%hist, c, run%h0_end, run%period, st%rst, map)
    end associate
    run%periodic = run%period > 0
  end subroutine end_cycle

  !> The cycle's results from its series (and the ring pack's sums).
  subroutine cycle_results(st, c, res)
    type(cycle_state), intent(in) :: st
    type(case_type), intent(in) :: c
    type(result_type), intent(inout) :: res
    associate (v => res%scalars)
      v(sc_energy_loss) = sum(res%series(:, s_power_loss)) * st%ctx%dt
      v(sc_mixed_share) = mixed_share(res%series(:, s_h0) / st%sigma)
      v(sc_min_film) = minval(res%series(:, s_lambda_min)) * st%sigma
      v(sc_max_friction) = maxval(abs(res%series(:, s_friction)))
    end associate
    if (allocated(st%rst)) call ring_pack_scalars(st%rcyc, res)
    call derive_results(res, c%speed_rpm, pi * c%bore_radius**2 * 2.0_dp * c%crank_radius, &
                        c%oil_density, c%cylinders)
    if (allocated(st%ring)) call ring_results(st, c, res)
  end subroutine cycle_results

  !> A distorted bore's cycle results: the share of sector-steps whose film carries less than
  !> 1 % of the mean load (off the liner), the gas through the faces per cycle, the share of
  !> the cycle held at the back clearance, the steps at which a sector jumps, and the
  !> conformability of the orders given.
  subroutine ring_results(st, c, res)
    type(cycle_state), intent(in) :: st
    type(case_type), intent(in) :: c
    type(result_type), intent(inout) :: res
    integer :: nk, m
    real(dp) :: light
    real(dp), allocatable :: lh(:, :)
    nk = res%nsteps
    m = size(res%sectors, 2)
    light = sum(st%light)
    ! each sector's ln h0 relative to the ring's (their mean): a sector's jump, not the whole
    ! ring's (which moves fast near firing TDC)
    lh = log(res%sectors(:, :, sec_h0))
    lh = lh - spread(sum(lh, dim=2) / m, 2, m)
    associate (v => res%scalars)
      v(sc_light_gap_share) = 100.0_dp * light / real(nk * m, dp)
      ! (towards the crankcase; the way back counts in the ring pack's blowback)
      v(sc_face_leakage) = sum(max(res%series(:, s_face_flow), 0.0_dp)) * st%ctx%dt * 1e6_dp
      v(sc_radial_collapse_share) = 100.0_dp * count(iand(res%int_series(:, si_flags), &
                                                          flag_ceiling) /= 0) / real(nk, dp)
      v(sc_sector_jumps) = count(maxval(abs(lh(2:nk, :) - lh(:nk - 1, :)), dim=2) > sector_jump_log)
      res%conformability = conformability(c, st%ring%bore)
      v(sc_conformability) = 0.0_dp
      if (size(res%conformability) > 0) v(sc_conformability) = maxval(res%conformability)
    end associate
    res%conformability_orders = conformability_orders(st%ring%bore)
  end subroutine ring_results

  !> The liner film of the run's films (one, or each sector's in turn) as one array;
  !> not allocated without a starved inlet.
  subroutine liner_map(st, map)
    type(cycle_state), intent(in) :: st
    real(dp), allocatable, intent(out) :: map(:)
    integer :: j
    if (.not. st%film%f%starved) return
    if (allocated(st%ring)) then
      map = [(st%sups(j)%liner%h, j=1, size(st%sups))]
    else
      map = st%film%sup%liner%h
    end if
  end subroutine liner_map

  !> A starved liner film that settles slowly (one mode contracting geometrically over the
  !> last two cycles) extrapolated toward its periodic state (history_extrapolate): the next
  !> cycle starts from it, and its change is judged with the contraction extrapolated with.
  subroutine extrapolate_liner(st, run)
    type(cycle_state), intent(inout) :: st
    type(cycle_run), intent(inout) :: run
    real(dp), allocatable :: map(:), new(:)
    real(dp) :: rho
    logical :: ok
    integer :: j, n
    ! (twice at most: the approach from the warm-up, where one mode settles; in an orbit of
    ! several cycles a film building up before it is picked up looks like one too)
    if (run%extrapolations >= max_extrapolations) return
    call liner_map(st, map)
    if (.not. allocated(map)) return
    allocate (new(size(map)))
    call history_extrapolate(run%hist, map, new, rho, ok)
    if (.not. ok) return
    if (allocated(st%ring)) then
      n = st%sups(1)%liner%nz
      do j = 1, size(st%sups)
        st%sups(j)%liner%h = new((j - 1) * n + 1:j * n)
      end do
    else
      st%film%sup%liner%h = new
    end if
    run%continues = .false.
    run%rho_map = rho
    run%extrapolations = run%extrapolations + 1
  end subroutine extrapolate_liner

  !> The ring pack's periodic state before the re-warm's first step under the friction of the
  !> cycle just run (the gas network alone from the cycle's own state there,
  !> ring_pack_restart; kept for the restart) and the cycle's distance from it there
  !> (ring_pack_distance; where the gas network did not settle in its cycles, plus its last
  !> cycle's change: the coupled state lies within that of an orbit the gas network has not
  !> left).
  subroutine ring_pack_periodic(st, c, res, run, distance)
    type(cycle_state), intent(inout) :: st
    type(case_type), intent(in) :: c
    type(result_type), intent(in) :: res
    type(cycle_run), intent(inout) :: run
    real(dp), intent(out) :: distance
    associate (rw => run%rw)
      rw%rp_periodic = rw%rp
      if (allocated(st%ring)) then
        call ring_pack_restart(c, st%rpar, rw%k, res%series(:, s_friction), rw%rp_periodic, &
                               rw%rp_periodic_cyc, st%err, st%face_ks)
      else
        call ring_pack_restart(c, st%rpar, rw%k, res%series(:, s_friction), rw%rp_periodic, &
                               rw%rp_periodic_cyc, st%err)
      end if
      rw%periodic_done = .not. allocated(st%err)
      distance = huge(1.0_dp)
      if (rw%periodic_done) distance = ring_pack_distance(c, rw%rp_periodic, rw%rp)
      if (rw%periodic_done .and. .not. rw%rp_periodic_cyc%converged) &
        distance = distance + ring_pack_distance(c, rw%rp_periodic, rw%rp_periodic_cyc%start)
    end associate
  end subroutine ring_pack_periodic

  !> The ring pack from its periodic state under the first cycle's friction, and the film
  !> from its state at the re-warm's first step again to psi = 720 with it: the next cycle
  !> starts without a jump in the groove and land pressures.
  subroutine restart_ring_pack(st, c, res, run, err)
    type(cycle_state), intent(inout) :: st
    type(case_type), intent(in) :: c
    type(result_type), intent(in) :: res
    type(cycle_run), intent(inout) :: run
    type(error_type), allocatable, intent(out) :: err
    integer :: m
    m = steps_per_cycle(c)
    if (run%rw%periodic_done) then
      ! (computed at the cycle's end, ring_pack_periodic)
      st%rst = run%rw%rp_periodic
      st%rcyc = run%rw%rp_periodic_cyc
    else if (allocated(st%ring)) then
      call ring_pack_restart(c, st%rpar, run%rw%k, res%series(:, s_friction), st%rst, st%rcyc, &
                             err, st%face_ks)
    else
      call ring_pack_restart(c, st%rpar, run%rw%k, res%series(:, s_friction), st%rst, st%rcyc, err)
    end if
    if (allocated(err)) return
    if (st%rcyc%contraction > 0.0_dp) run%hist%land_contraction = st%rcyc%contraction
    call take_film(st%film%f, run%rw%film%f)
    st%film%mem = run%rw%film%mem
    if (st%film%f%starved) st%film%sup = run%rw%film%sup
    if (allocated(st%ring)) call take_ring(st%ring, run%rw%ring)
    if (allocated(st%ring)) st%sups = run%rw%sups
    st%s_prev = run%rw%s_prev
    st%fric_prev = run%rw%fric_prev
    call advance_steps(st, c, run%rw%k, m)
    run%rewarm = run%rewarm + (m - run%rw%k + 1) * c%dpsi_deg
    if (allocated(st%err)) call move_alloc(st%err, err)
  end subroutine restart_ring_pack

  !> The ring becomes `saved` (a state kept earlier), its films' solve counters keep counting.
  subroutine take_ring(ring, saved)
    type(sector_ring), intent(inout) :: ring
    type(sector_ring), intent(in) :: saved
    type(film_type), allocatable :: now(:)
    integer :: j
    now = ring%films
    ring = saved
    do j = 1, size(now)
      ring%films(j) = now(j)
      call take_film(ring%films(j), saved%films(j))
    end do
  end subroutine take_ring

  !> The run's results: the models that made them, the liner film (starved), the means over a
  !> period of several cycles (the series and the extremes are the last cycle's), the solve
  !> counts and the convergence; a non-finite film is an error.
  subroutine report(st, c, res, run, err)
    type(cycle_state), intent(in) :: st
    type(case_type), intent(in) :: c
    type(result_type), intent(inout) :: res
    type(cycle_run), intent(in) :: run
    type(error_type), allocatable, intent(out) :: err
    logical :: finite
    integer :: k, j
    associate (f => st%film%f, sup => st%film%sup)
      res%made(m_gas) = allocated(st%rst)
      res%made(m_distorted) = allocated(st%ring)
      res%made(m_jfo) = f%jfo
      res%made(m_starved) = f%starved
      if (f%starved .and. allocated(st%ring)) then
        ! (the sectors' mean film)
        call allocate_liner(res, st%sups(1)%liner%nz)
        res%liner(:, l_liner_position) = liner_positions(st%sups(1)%liner)
        do k = 1, st%sups(1)%liner%nz
          res%liner(k, l_liner_oil_film) = exact_mean([(st%sups(j)%liner%h(k), j=1, size(st%sups))])
        end do
      else if (f%starved) then
        call allocate_liner(res, sup%liner%nz)
        res%liner(:, l_liner_position) = liner_positions(sup%liner)
        res%liner(:, l_liner_oil_film) = sup%liner%h
      end if
      call history_mean(run%hist, run%period, mean_over_period, res%scalars)
      associate (v => res%scalars, power_loss => res%series(:, s_power_loss), &
                 h0s => res%series(:, s_h0), friction => res%series(:, s_friction))
        v(sc_total_film_solves) = f%film_solves + st%extra_film_solves
        v(sc_reynolds_solves) = f%reynolds_solves + st%extra_solves
        v(sc_cycles_run) = run%cycles_run
        v(sc_cycles_computed) = run%cycles_run + (run%warmup + run%rewarm + c%dpsi_deg &
                                                  * run%cycles_run) / 720.0_dp + run%pilot
        v(sc_periodic) = truth(run%periodic)
        v(sc_period) = run%period
        ! a step held at h0_ceiling (the ring lifts off) is an answer of the model, flagged but
        ! not a failure; every other flag is, in every cycle of a period (all enter its means)
        v(sc_converged) = truth(run%periodic .and. history_clean(run%hist, run%period))
        k = findloc(ieee_is_finite(friction) .and. ieee_is_finite(h0s), .false., dim=1)
        finite = k == 0 .and. all(ieee_is_finite(power_loss)) &
                 .and. ieee_is_finite(v(sc_energy_loss))
      end associate
    end associate
    if (.not. finite) then
      ! every input lies in its plausible range, so a non-finite film comes from a
      ! combination of inputs the model cannot describe: report it as an input problem
      call fatal_error(err, c%deck_path//': these inputs give a non-finite film solution'// &
                       ' (first at crank angle '//trim(adjustl(angle_text(c, max(k, 1))))// &
                       ' deg): check the operating point, ring and surface values together', &
                       rl_input_error)
    end if
  end subroutine report

  !> Crank angle of step kk [deg] as text.
  function angle_text(c, kk) result(t)
    type(case_type), intent(in) :: c
    integer, intent(in) :: kk
    character(len=16) :: t
    write (t, '(f10.2)') (kk - 1) * c%dpsi_deg
  end function angle_text
end module ringlube_cycle
