! ctest labels: numerics
!> The ring on a distorted bore (docs/bore.md): zero distortion gives the round bore's answer
!> bit for bit with every film model; orders 0 and 1 only move the ring as a rigid body; a
!> dry ring conforms to a single order exactly up to the classical limit; the sector solve's
!> residuals close; the faces pass gas only where a light gap opens, more with a larger
!> distortion and less with more tension, and the ring pack's gas still balances.
program test_bore
  use ringlube_kinds, only: dp, pi
  use ringlube_error, only: error_type
  use ringlube_case, only: case_type, default_case, elastic_pressure
  use ringlube_deck, only: finish_case, read_deck_text
  use ringlube_fsys, only: dir_prefix
  use ringlube_textio, only: read_text_file
  use ringlube_cycle, only: solve_cycle
  use ringlube_load_balance, only: missed_solved_again, loose_answers_solved
  use ringlube_cycle_state, only: cycle_state, step_out, cycle_setup, advance
  use ringlube_bore, only: ring_compliance
  use ringlube_results, only: result_type, is_true, s_h0, s_friction, s_power_loss, &
                              s_load_residual, si_flags, sc_energy_loss, sc_converged, &
                              sc_face_leakage, sc_gas_balance_error, sc_light_gap_share, &
                              sec_h0, sec_load, flag_sectors, flag_ceiling, &
                              sc_margin_film_solves, si_film_solves, sc_run_time, &
                              s_crank_angle_deg, flag_viscosity, flag_load
  use ringlube_sectors, only: free_mean_position, team_spin, team_busy_check, loose_trials, &
                              phase_solves, phase_calls, team_busy_every, team_busy_checks, &
                              sector_ring, sector_trial, ring_evaluate, jump_exit, &
                              solve_failures, relative_jump, refused_far, stalled_failures
  use ringlube_cycle_state, only: cycle_regions
  use ringlube_check
  implicit none

  if (run_case('zero_distortion_is_round')) call zero_distortion_is_round()
  if (run_case('rigid_body_orders')) call rigid_body_orders()
  if (run_case('dry_conformability_limit')) call dry_conformability_limit()
  if (run_case('sector_residuals_close')) call sector_residuals_close()
  if (run_case('face_leakage')) call face_leakage()
  if (run_case('gas_assisted_conformability')) call gas_assisted_conformability()
  if (run_case('ceiling_from_last_ceiling')) call ceiling_from_last_ceiling()
  if (run_case('ceiling_rising_loads')) call ceiling_rising_loads()
  if (run_case('held_on_groove_root')) call held_on_groove_root()
  if (run_case('margin_on_groove_root')) call margin_on_groove_root()
  if (run_case('free_mean_position')) call free_mean_position_test()
  if (run_case('loose_trials')) call loose_trials_test()
  if (run_case('loose_trials_add_no_flag')) call loose_trials_add_no_flag()
  if (run_case('jump_exit_early')) call jump_exit_early()
  if (run_case('refusals_ring_moves')) call refusals_ring_moves()
  if (run_case('loose_trial_at_floor')) call loose_trial_at_floor()
  if (run_case('loose_answer_solved_tight')) call loose_answer_solved_tight()
  if (run_case('unsettled_answer_flag')) call unsettled_answer_flag()
  if (run_case('missed_trial_solved_again')) call missed_trial_solved_again()
  if (run_case('team_wait_modes')) call team_wait_modes()
  call report('test_bore')

contains

  !> The cold deck's ring at a coarse resolution, tension read in N (the physical reading).
  function base_case() result(c)
    type(case_type) :: c
    c = default_case()
    c%nodes = 31
    c%dpsi_deg = 2.0_dp
    c%pressure_file = 'inputs/pressure/crf450r_4000rpm_full.csv'
  end function base_case

  !> c with a distorted bore of one order k of amplitude a [m] on m sectors.
  function distorted(c0, k, a, m) result(c)
    type(case_type), intent(in) :: c0
    integer, intent(in) :: k, m
    real(dp), intent(in) :: a
    type(case_type) :: c
    c = c0
    c%bore = 'distorted'
    c%bore_order = [k]
    c%bore_amplitude = [a]
    c%bore_phase = [real(dp) ::]
    c%sectors = m
  end function distorted

  !> c read from a shipped deck with overrides (namelist text, '' for none), checked.
  logical function shipped_deck(deck, overrides, c) result(ok)
    character(len=*), intent(in) :: deck, overrides
    type(case_type), intent(out) :: c
    type(error_type), allocatable :: err
    character(len=:), allocatable :: text
    call read_text_file(deck, text, err)
    if (.not. allocated(err)) then
      if (len(overrides) > 0) then
        call read_deck_text(text, deck, dir_prefix(deck), c, err, overrides, 'overrides')
      else
        call read_deck_text(text, deck, dir_prefix(deck), c, err)
      end if
    end if
    if (allocated(err)) write (*, '(a)') err%message
    ok = .not. allocated(err)
    call check(ok, 'the shipped deck read')
  end function shipped_deck

  subroutine solve(c, res, what)
    type(case_type), intent(inout) :: c
    type(result_type), intent(out) :: res
    character(len=*), intent(in) :: what
    type(error_type), allocatable :: err
    call finish_case(c, err)
    if (allocated(err)) write (*, '(a)') err%message
    call check(.not. allocated(err), what//': case accepted')
    if (allocated(err)) call report('test_bore')
    call solve_cycle(c, res, err)
    if (allocated(err)) write (*, '(a)') err%message
    call check(.not. allocated(err), what//': solved')
    if (allocated(err)) call report('test_bore')
  end subroutine solve

  !> Every film model: a distorted bore of zero amplitude is the round bore, bit for bit (the
  !> sectors' films are the round film and the first trial of every step satisfies the
  !> sector equations exactly). The round run starts plainly: the BDC start (a starved 'vapour'
  !> film's default) is a round-bore start that a distorted bore does not take.
  subroutine zero_distortion_is_round()
    character(len=*), parameter :: names(5) = [character(len=24) :: 'swift_stieber', &
                                                 'jfo flooded', 'jfo trailing_gas', 'jfo starved', &
                                                                            'jfo starved ring pack']
    type(case_type) :: c, cd
    type(result_type) :: r, rd
    integer :: i
    do i = 1, size(names)
      c = base_case()
      if (i >= 2) c%cavitation = 'jfo'
      if (i == 3) c%cavity_pressure = 'trailing_gas'
      if (i >= 4) c%inlet = 'starved'
      if (i == 5) c%ring_pack = 'gas'
      c%bdc_start = .false.
      cd = distorted(c, 3, 0.0_dp, 8)
      call solve(c, r, trim(names(i))//' round')
      call solve(cd, rd, trim(names(i))//' distorted, zero amplitude')
      call check(r%scalars(sc_energy_loss) == rd%scalars(sc_energy_loss), &
                 trim(names(i))//': the same energy bit for bit')
      call check(all(r%series(:, s_h0) == rd%series(:, s_h0)) .and. &
                 all(r%series(:, s_friction) == rd%series(:, s_friction)), &
                 trim(names(i))//': the same h0 and friction at every step')
      call check(all(rd%sectors(:, :, sec_h0) == spread(r%series(:, s_h0), 2, 8)), &
                 trim(names(i))//': every sector at the round h0')
    end do
  end subroutine zero_distortion_is_round

  !> An order-0 distortion (a larger bore) moves the mean position only: the round bore's
  !> answer bit for bit. An order-1 distortion (an offset bore) moves the centre: every
  !> sector's film is the round one's to the sector solve's tolerance (its first harmonic of
  !> the load within load_tol q: with a film stiffness |dln W/dln h0| >= 1 the sectors' h0
  !> differ by at most 2 load_tol), the energy within 2 load_tol.
  subroutine rigid_body_orders()
    type(case_type) :: c, cd
    type(result_type) :: r, rd
    real(dp) :: spread_h
    c = base_case()
    call solve(c, r, 'round')
    cd = distorted(c, 0, 15e-6_dp, 8)
    call solve(cd, rd, 'order 0')
    call check(r%scalars(sc_energy_loss) == rd%scalars(sc_energy_loss) .and. &
              all(r%series(:, s_h0) == rd%series(:, s_h0)), 'order 0: the round answer bit for bit')
    cd = distorted(c, 1, 15e-6_dp, 8)
    call solve(cd, rd, 'order 1')
    spread_h = maxval((maxval(rd%sectors(:, :, sec_h0), dim=2) &
                       - minval(rd%sectors(:, :, sec_h0), dim=2)) / rd%series(:, s_h0))
    write (*, '(a, es10.2, a, es10.2)') 'order 1: sectors'' h0 spread ', spread_h, &
      ', energy vs round ', abs(rd%scalars(sc_energy_loss) / r%scalars(sc_energy_loss) - 1)
    call check(spread_h <= 2.0_dp * c%load_tol, 'order 1: every sector at one h0 (2 load_tol)')
    call check_close(rd%scalars(sc_energy_loss), r%scalars(sc_energy_loss), 2.0_dp * c%load_tol, &
                     'order 1: the round energy within 2 load_tol')
  end subroutine rigid_body_orders

  !> A dry ring (no film: the slowest engine speed and the thinnest oil make the film's load
  !> negligible; very smooth, stiff asperities make the contact nearly rigid) under its
  !> elastic pressure alone follows a single order-k distortion fully up to A_k = q C_k, and
  !> a light gap opens above it: at 0.95 of the limit every sector touches, at 1.05 some
  !> sector carries less than 1 % of the mean load.
  subroutine dry_conformability_limit()
    type(case_type) :: c
    type(error_type), allocatable :: err
    integer :: k, i
    real(dp) :: q, limit, factors(2)
    integer :: light(2)
    factors = [0.95_dp, 1.05_dp]
    do k = 2, 4
      do i = 1, 2
        c = default_case()
        c%nodes = 21
        c%dpsi_deg = 2.0_dp
        c%speed_rpm = 1.0_dp
        c%eta0 = 1e-4_dp
        c%beta = 0.0_dp
        c%roelands = .false.
        c%squeeze = .false.
        c%crankcase_pressure = 0.0_dp
        c%cavitation_pressure = 0.0_dp
        c%pressure_file = ''
        c%rq_liner = 1e-8_dp
        c%rq_ring = 1e-8_dp
        c%zeta_kappa_sigma = 1.0_dp
        c%tension = 20.0_dp
        c%h0_floor = 1e-12_dp
        q = elastic_pressure(c) * c%width
        limit = q * ring_compliance(c, k)
        c = distorted(c, k, factors(i) * limit, 24)
        call finish_case(c, err)
        call check(.not. allocated(err), 'dry ring: case accepted')
        light(i) = light_sectors(c)
      end do
      write (*, '(a, i0, a, es10.3, a, 2i4)') 'order ', k, ': limit ', limit, &
        ' m; light sectors at 0.95 and 1.05 of it: ', light
      call check(light(1) == 0, 'order '//achar(48 + k)//': the dry ring conforms at 0.95 '// &
                 'of the limit')
      call check(light(2) > 0, 'order '//achar(48 + k)//': a light gap opens at 1.05 of the limit')
    end do
  end subroutine dry_conformability_limit

  !> Sectors whose load is below 1 % of the mean after one step at 90 deg.
  integer function light_sectors(c) result(n)
    type(case_type), intent(in) :: c
    type(cycle_state) :: st
    type(step_out) :: out
    call cycle_setup(st, c, 1e-7_dp)
    call advance(st, c, 90.0_dp, out)
    call check(iand(out%flags, flag_sectors) == 0, 'dry ring: the sectors solved')
    n = count(st%ring%w < 0.01_dp * out%lp%load / st%film%f%circ)
  end function light_sectors

  !> The sector solve closes to its tolerance at every step of a distorted deck (order 4
  !> beyond its conformability limit, starved film): no step flagged, every load residual
  !> within load_tol.
  subroutine sector_residuals_close()
    type(case_type) :: c
    type(result_type) :: r
    c = base_case()
    c%cavitation = 'jfo'
    c%inlet = 'starved'
    c = distorted(c, 4, 10e-6_dp, 16)
    call solve(c, r, 'order 4, 10 um, starved')
    call check(all(iand(r%int_series(:, si_flags), flag_sectors) == 0), &
               'no step with the sectors outside their tolerance')
    call check(all(abs(r%series(:, s_load_residual)) <= c%load_tol), &
               'the load balance within load_tol at every step')
  end subroutine sector_residuals_close

  !> The ring pack with a starved film on a bore of order 4: no gas through the faces of a
  !> conforming ring (a full zone in every sector); above the limit the faces pass gas, more
  !> with a larger amplitude and less with a higher tension; the ring pack's gas balances.
  subroutine face_leakage()
    type(case_type) :: c
    type(result_type) :: r
    real(dp) :: leak(3), leak_tense
    integer :: i
    real(dp), parameter :: amp(3) = [1e-6_dp, 15e-6_dp, 30e-6_dp]
    do i = 1, 3
      c = base_case()
      c%cavitation = 'jfo'
      c%inlet = 'starved'
      c%ring_pack = 'gas'
      c = distorted(c, 4, amp(i), 8)
      call solve(c, r, 'face leakage')
      leak(i) = r%scalars(sc_face_leakage)
      call check(r%scalars(sc_gas_balance_error) <= 1e-8_dp, 'the gas balances with the face flow')
    end do
    c = base_case()
    c%cavitation = 'jfo'
    c%inlet = 'starved'
    c%ring_pack = 'gas'
    c%tension = 3.0_dp * c%tension
    c = distorted(c, 4, amp(3), 8)
    call solve(c, r, 'face leakage, tension x 3')
    leak_tense = r%scalars(sc_face_leakage)
    write (*, '(a, 3es11.3, a, es11.3)') 'face leakage [mg/cycle] at 1, 15, 30 um: ', leak, &
      '; 30 um, tension x 3: ', leak_tense
    call check(leak(1) == 0.0_dp, 'a conforming ring passes no gas through its faces')
    call check(leak(2) > leak(1) .and. leak(3) > leak(2), 'face leakage rises with the amplitude')
    call check(leak_tense < leak(3), 'face leakage falls with the tension')
  end subroutine face_leakage
  !> The gas behind the ring makes it conform when the chamber pressure is high: an order-4
  !> distortion of 3.7 times its dry limit (20 um) leaves light gaps (sectors at more than 4
  !> times the smallest h0) on the intake stroke, none just after firing TDC, where the gas in
  !> the groove presses every sector onto the liner; with the gas channel in the open faces.
  !> (16 sectors, four per wave: with two, at k = M/2, the ring's response is not resolved and
  !> it does not conform.)
  subroutine gas_assisted_conformability()
    type(case_type) :: c
    type(result_type) :: r
    integer :: k
    real(dp) :: ratio_intake, ratio_firing
    c = base_case()
    c%tension_unit = 'N'
    c%cavitation = 'jfo'
    c%inlet = 'starved'
    c%ring_pack = 'gas'
    c = distorted(c, 4, 20e-6_dp, 16)
    call solve(c, r, 'gas-assisted conformability')
    ratio_intake = 0.0_dp
    ratio_firing = 0.0_dp
    do k = 1, r%nsteps
      associate (psi => (k - 1) * c%dpsi_deg, hs => r%sectors(k, :, sec_h0))
        if (psi >= 60.0_dp .and. psi <= 120.0_dp) ratio_intake = max(ratio_intake, &
                                                                     maxval(hs) / minval(hs))
        if (psi >= 370.0_dp .and. psi <= 390.0_dp) ratio_firing = max(ratio_firing, &
                                                                      maxval(hs) / minval(hs))
      end associate
    end do
    write (*, '(a, f8.2, a, f8.2)') 'largest over smallest sector h0: intake ', ratio_intake, &
      ', after firing TDC ', ratio_firing
    call check(ratio_intake > 4.0_dp, 'light gaps open on the intake stroke')
    call check(ratio_firing < 1.5_dp, 'the gas makes the ring conform after firing TDC')
  end subroutine gas_assisted_conformability

  !> The lift-off margin's solve of the sectors at the ceiling starts from the last such solve
  !> (ring_ceiling): with the starved film and the ring pack on an order-4 bore of 20 um, whose
  !> sectors' loads at the ceiling differ by half the mean load on the intake stroke, it takes
  !> at most 2 film solves per sector and margin step (1.03 measured). Started from the step's
  !> sectors near the liner it took 6.0 on this case, and on the shipped distorted decks up to
  !> the sectors' 40 Newton iterations (about 100 film solves per sector at some steps). The steps' own solution does not depend on it: the margin is
  !> measured on a copy.
  subroutine ceiling_from_last_ceiling()
    type(case_type) :: c
    type(result_type) :: r
    real(dp) :: per_sector
    integer :: steps
    c = base_case()
    c%tension_unit = 'N'
    c%cavitation = 'jfo'
    c%inlet = 'starved'
    c%ring_pack = 'gas'
    c = distorted(c, 4, 20e-6_dp, 16)
    call solve(c, r, 'the margin at the ceiling')
    steps = count(r%step_margins(:, 3) > 0.0_dp)
    per_sector = r%scalars(sc_margin_film_solves) / (16.0_dp * max(steps, 1))
    write (*, '(a, i0, a, f8.2)') 'margin steps ', steps, ', film solves per sector and step ', &
      per_sector
    call check(steps > 0, 'the margin is measured on the intake stroke')
    call check(per_sector <= 2.0_dp, 'at most 2 film solves per sector at the ceiling')
  end subroutine ceiling_from_last_ceiling

  !> The lift-off margin where the sectors' films carry more load the farther they are from
  !> the liner at the ceiling (ring_ceiling: the shipped 4000 r/min hot distorted deck with
  !> the flooded film, d ln W / d ln h0 about +0.01 there): the margin's solve converges to
  !> the root continued from the last margin step, so the margin is smooth over the intake
  !> stroke's first 140 deg (each step within 0.1 load_tol of the mean of its neighbours,
  !> 6e-6 measured), in at most 4 film solves per sector and margin step, more than 10 at one
  !> step at most (2.9, one step measured: the first attempt's 40 iterations and the second's).
  !> With the balance's falling slopes alone the solve crawled to another root, the ring slid
  !> sideways by the clearance: 0.017 off its neighbours at 72 deg (a solve stopped at 40
  !> Newton iterations), 7.4 film solves per sector and margin step, more than 10 at 4 steps.
  subroutine ceiling_rising_loads()
    character(len=*), parameter :: deck = 'inputs/crf450r_4000rpm_full_hot_distorted.nml'
    type(case_type) :: c
    type(result_type) :: r
    type(error_type), allocatable :: err
    real(dp), allocatable :: psi(:), lm(:), solves(:)
    real(dp) :: off
    integer :: k, n
    if (.not. shipped_deck(deck, "&physics cavitation = 'jfo', inlet = 'flooded' /", c)) return
    call solve_cycle(c, r, err)
    call check(.not. allocated(err), 'the flooded film on the distorted deck solved')
    if (allocated(err)) return
    ! the margin steps of the reported cycle (the intake stroke)
    psi = pack(r%series(:, s_crank_angle_deg), r%step_margins(:, 1) < huge(1.0_dp))
    lm = pack(r%step_margins(:, 1), r%step_margins(:, 1) < huge(1.0_dp))
    solves = pack(r%step_margins(:, 3), r%step_margins(:, 1) < huge(1.0_dp)) / c%sectors
    n = size(lm)
    off = 0.0_dp
    do k = 2, n - 1
      if (psi(k + 1) <= 140.0_dp) off = max(off, abs(lm(k) - 0.5_dp * (lm(k - 1) + lm(k + 1))))
    end do
    write (*, '(a, i0, a, es10.3, a, f7.2, a, i0)') 'margin steps ', n, &
      ', largest offset from the neighbours'' mean ', off, &
      ', film solves per sector and step ', sum(solves) / max(n, 1), ', steps above 10: ', &
      count(solves > 10.0_dp)
    call check(n > 80, 'the margin is measured over the intake stroke')
    call check(off <= 0.1_dp * c%load_tol, 'the margin is smooth where the ceiling''s loads rise')
    call check(sum(solves) / max(n, 1) <= 4.0_dp, 'at most 4 film solves per sector and step')
    call check(count(solves > 10.0_dp) <= 1, 'more than 10 film solves per sector at one step')
  end subroutine ceiling_rising_loads

  !> A ring pushed off the liner is held at back_clearance on its groove's root, which stops
  !> its translation: at every step of the shipped 12,000 r/min distorted deck held there
  !> (flag 2; 360 deg of the reported cycle) the centre's translation, the first harmonic of
  !> the sectors' h0_j - D_j (D the bore's distortion; the ring's bending has orders 2 and
  !> up), is 0 within the sectors' positions' tolerance (0.1 load_tol of the mean position;
  !> 5.5e-9 m measured) and no sector is farther from the liner than the clearance and its
  !> distortion (within 1 % of the clearance: the ring's bending; 8.5e-7 m measured). Without
  !> the groove's root the balance's Newton iteration left the ring slid sideways there by
  !> 6.8e-5 m, 0.23 of the clearance (at an earlier kernel 0.38), on other films by the whole
  !> clearance.
  subroutine held_on_groove_root()
    character(len=*), parameter :: deck = 'inputs/crf450r_12000rpm_full_hot_distorted.nml'
    type(case_type) :: c
    type(result_type) :: r
    type(error_type), allocatable :: err
    real(dp), allocatable :: theta(:), d(:), hd(:), phase(:)
    real(dp) :: xc, yc, centre, beyond
    integer :: k, i, m, held
    if (.not. shipped_deck(deck, '', c)) return
    call solve_cycle(c, r, err)
    call check(.not. allocated(err), 'the shipped distorted deck solved')
    if (allocated(err)) return
    m = c%sectors
    theta = [(2.0_dp * pi * (i - 1) / m, i=1, m)]
    phase = [(0.0_dp, i=1, size(c%bore_order))]
    if (allocated(c%bore_phase)) then
      if (size(c%bore_phase) == size(phase)) phase = c%bore_phase
    end if
    d = [(sum(c%bore_amplitude * cos(c%bore_order * (theta(i) - phase))), i=1, m)]
    held = 0
    centre = 0.0_dp
    beyond = -huge(1.0_dp)
    do k = 1, r%nsteps
      if (iand(r%int_series(k, si_flags), flag_ceiling) == 0) cycle
      held = held + 1
      hd = r%sectors(k, :, sec_h0) - d
      xc = -2.0_dp * sum(hd * cos(theta)) / m
      yc = -2.0_dp * sum(hd * sin(theta)) / m
      centre = max(centre, hypot(xc, yc))
      beyond = max(beyond, maxval(hd) - c%back_clearance)
    end do
    write (*, '(a, i0, a, es10.3, a, es10.3)') 'steps held at the clearance ', held, &
      ', largest translation ', centre, ' m, farthest sector beyond the clearance ', beyond
    call check(held > 0, 'a step held at the clearance')
    call check(centre <= 0.1_dp * c%load_tol * c%back_clearance, &
               'the ring''s centre held at 0 there (the positions'' tolerance)')
    call check(beyond <= 0.01_dp * c%back_clearance, &
               'no sector beyond the clearance and its distortion (1 %)')
  end subroutine held_on_groove_root

  !> The lift-off margin's solve at the ceiling (ring_ceiling, on the intake stroke) holds the
  !> ring on its groove's root as the root finder's trials there do: the starved film on a bore
  !> of orders 2, 3 and 4 (10, 10 and 20 um), 16 sectors, without the ring pack (which a cycle's
  !> start sets up), stepped to 180 deg: its last solve at the ceiling has the centre at 0
  !> exactly (slid by 1.5e-5 m without the groove's root).
  subroutine margin_on_groove_root()
    type(case_type) :: c
    type(cycle_state) :: st
    type(step_out) :: out
    type(error_type), allocatable :: err
    integer :: k
    c = base_case()
    c%tension_unit = 'N'
    c%cavitation = 'jfo'
    c%inlet = 'starved'
    c = distorted(c, 4, 20e-6_dp, 16)
    c%bore_order = [2, 3, 4]
    c%bore_amplitude = [10e-6_dp, 10e-6_dp, 20e-6_dp]
    call finish_case(c, err)
    call check(.not. allocated(err), 'the case accepted')
    if (allocated(err)) return
    call cycle_setup(st, c, 1e-6_dp)
    do k = 1, nint(180.0_dp / c%dpsi_deg)
      call advance(st, c, k * c%dpsi_deg, out)
      if (allocated(st%err)) then
        call check(.false., 'the step solved: '//st%err%message)
        return
      end if
    end do
    write (*, '(a, 3es11.3)') 'the margin''s last solve at the ceiling: c, x_c, y_c', &
      st%ring%ceil_c, st%ring%ceil_xc, st%ring%ceil_yc
    call check(st%ring%ceil_c >= c%back_clearance * (1.0_dp - 1e-12_dp), &
               'the margin solved at the back clearance')
    call check(st%ring%ceil_xc == 0.0_dp .and. st%ring%ceil_yc == 0.0_dp, &
               'its centre held at 0 there')
  end subroutine margin_on_groove_root

  !> The step's mean position solved with the sectors in one Newton iteration (ring_solve)
  !> gives the answer of the root finder on the mean position alone (each of whose trials
  !> solves the sectors), to the balance's tolerance: every step's load residual within
  !> load_tol and no step flagged, the mean position within 5 load_tol at every step and the
  !> energy within 2 load_tol (starved film and flooded, order 4 beyond its conformability
  !> limit, and orders 2 and 3 with the ring pack), in fewer film solves.
  subroutine free_mean_position_test()
    type(case_type) :: c, cases(3)
    type(result_type) :: r_free, r_root
    real(dp) :: dh, de
    integer :: i
    c = base_case()
    c%tension_unit = 'N'
    c%cavitation = 'jfo'
    c%inlet = 'starved'
    cases(1) = distorted(c, 4, 10e-6_dp, 16)
    c%inlet = 'flooded'
    cases(2) = distorted(c, 4, 10e-6_dp, 16)
    c%inlet = 'starved'
    c%ring_pack = 'gas'
    cases(3) = distorted(c, 2, 8e-6_dp, 16)
    cases(3)%bore_order = [2, 3]
    cases(3)%bore_amplitude = [8e-6_dp, 6e-6_dp]
    do i = 1, size(cases)
      c = cases(i)
      free_mean_position = .true.
      call solve(c, r_free, 'mean position with the sectors')
      c = cases(i)
      free_mean_position = .false.
      call solve(c, r_root, 'mean position by the root finder')
      free_mean_position = .true.
      dh = maxval(abs(r_free%series(:, s_h0) / r_root%series(:, s_h0) - 1))
      de = abs(r_free%scalars(sc_energy_loss) / r_root%scalars(sc_energy_loss) - 1)
      write (*, '(a, i0, a, es10.2, a, es10.2, a, 2i8)') 'case ', i, ': h0 ', dh, ', energy ', &
        de, ', film solves ', sum(r_free%int_series(:, si_film_solves)), &
        sum(r_root%int_series(:, si_film_solves))
      call check(all(iand(r_free%int_series(:, si_flags), flag_sectors) == 0), &
                 'no step with the sectors outside their tolerance')
      call check(all(abs(r_free%series(:, s_load_residual)) <= c%load_tol), &
                 'the load balance within load_tol at every step')
      call check(dh <= 5.0_dp * c%load_tol, 'the root finder''s mean position (5 load_tol)')
      call check(de <= 2.0_dp * c%load_tol, 'the root finder''s energy (2 load_tol)')
      call check(sum(r_free%int_series(:, si_film_solves)) &
                 < sum(r_root%int_series(:, si_film_solves)), 'fewer film solves')
    end do
  end subroutine free_mean_position_test

  !> The root finder's trials at a step that ring_solve did not take are loose (far from the
  !> root a trial's sectors end at a tolerance in proportion to its load residual): on the
  !> shipped 12,000 r/min distorted deck with the flooded film, where ring_solve is refused at
  !> 67 steps, the root finder takes such a step in at most 0.75 times the film solves per
  !> sector of trials solved to the sectors' own tolerance (16.8 against 27.3 measured; 28
  !> against 52 before the ring at the clearance was held on its groove's root, when the
  !> trials at the ceiling, tight either way, crawled to a ring slid sideways), and the
  !> answers stay the balance's: every step not held at a bound within load_tol, no more steps
  !> with the sectors outside their tolerance, the energy within load_tol.
  subroutine loose_trials_test()
    character(len=*), parameter :: deck = 'inputs/crf450r_12000rpm_full_hot_distorted.nml'
    type(case_type) :: c
    type(result_type) :: r(2)
    type(error_type), allocatable :: err
    real(dp) :: per_step(2), de
    integer :: i, flagged(2)
    logical, allocatable :: free(:)
    if (.not. shipped_deck(deck, "&ring tension_unit = 'N' / "// &
                           "&physics cavitation = 'jfo', inlet = 'flooded' /", c)) return
    do i = 1, 2
      loose_trials = i == 1
      phase_solves = 0
      phase_calls = 0
      call solve_cycle(c, r(i), err)
      call check(.not. allocated(err), 'the 12,000 r/min flooded film solved')
      if (allocated(err)) return
      per_step(i) = real(phase_solves(3), dp) / (c%sectors * max(phase_calls(2), 1))
      free = iand(r(i)%int_series(:, si_flags), 3) == 0
      flagged(i) = count(iand(r(i)%int_series(:, si_flags), flag_sectors) /= 0)
      call check(all(abs(pack(r(i)%series(:, s_load_residual), free)) <= c%load_tol), &
                 'every step not held at a bound within load_tol')
    end do
    loose_trials = .true.
    de = abs(r(1)%scalars(sc_energy_loss) / r(2)%scalars(sc_energy_loss) - 1)
 write (*, '(a, 2f8.2, a, 2i4, a, es10.2)') 'root finder film solves per sector and refused step', &
      per_step, ', steps with the sectors flagged', flagged, ', energy', de
    call check(phase_calls(2) > 20, 'ring_solve is refused at some steps')
    call check(per_step(1) <= 0.75_dp * per_step(2), 'the loose trials take at most 0.75 times the solves')
    call check(flagged(1) <= flagged(2), 'no more steps with the sectors outside their tolerance')
    call check(de <= c%load_tol, 'the energy within load_tol')
  end subroutine loose_trials_test

  !> The loose trials add no flagged step: the narrow ring (0.54 mm, 8 N) on the shipped
  !> 4000 r/min distorted deck, a row of the validation's bore table, has no flagged step with
  !> the trials solved to the sectors' own tolerance nor with loose ones. (With loose trials
  !> its path moves within load_tol, and ring_solve at 366 deg then ended on a sector film
  !> whose cavitation set had not settled, flagged; the balance now solves the sectors once
  !> more at such an answer, from the films just solved there.)
  subroutine loose_trials_add_no_flag()
    character(len=*), parameter :: deck = 'inputs/crf450r_4000rpm_full_hot_distorted.nml'
    type(case_type) :: c
    type(result_type) :: r(2)
    type(error_type), allocatable :: err
    integer :: i, flagged(2)
    if (.not. shipped_deck(deck, '&ring width = 0.54e-3 /', c)) return
    call check(c%tension == 8.0_dp, 'the 8 N ring')
    do i = 1, 2
      loose_trials = i == 1
      call solve_cycle(c, r(i), err)
      call check(.not. allocated(err), 'the narrow ring solved')
      if (allocated(err)) return
      flagged(i) = count(r(i)%int_series(:, si_flags) /= 0)
    end do
    loose_trials = .true.
    write (*, '(a, 2i4)') 'flagged steps with loose and tight trials', flagged
    call check(flagged(2) == 0, 'no flagged step with tight trials')
    call check(flagged(1) == 0, 'no flagged step with loose trials')
    call check(is_true(r(1), sc_converged), 'converged with loose trials')
    call check_close(r(1)%scalars(sc_energy_loss), r(2)%scalars(sc_energy_loss), c%load_tol, &
                     'the energy within load_tol of the tight trials')
  end subroutine loose_trials_add_no_flag

  !> ring_solve's Newton iteration ends once a sector is beyond jump_exit from the last step
  !> and moving away (its answer would be refused): on the shipped 12,000 r/min distorted deck
  !> with the flooded film the refused ring_solves take at most 0.85 times the film solves
  !> they take with the rule off (0.71 measured: 0.28 against 0.40 per sector-step), more of
  !> the refusals are jumps, and every answer is the same to the bit (each step's h0, load
  !> residual, friction, flags, the energy).
  subroutine jump_exit_early()
    character(len=*), parameter :: deck = 'inputs/crf450r_12000rpm_full_hot_distorted.nml'
    type(case_type) :: c
    type(result_type) :: r(2)
    type(error_type), allocatable :: err
    real(dp) :: exit_at
    integer :: i, wasted(2), jumps(2)
    if (.not. shipped_deck(deck, "&ring tension_unit = 'N' / "// &
                           "&physics cavitation = 'jfo', inlet = 'flooded' /", c)) return
    exit_at = jump_exit
    call check(exit_at > 0.0_dp, 'the early end on by default')
    do i = 1, 2
      jump_exit = merge(exit_at, 0.0_dp, i == 1)
      phase_solves = 0
      phase_calls = 0
      solve_failures = 0
      call solve_cycle(c, r(i), err)
      call check(.not. allocated(err), 'the 12,000 r/min flooded film solved')
      if (allocated(err)) return
      wasted(i) = phase_solves(2)
      jumps(i) = solve_failures(3)
    end do
    jump_exit = exit_at
    write (*, '(a, 2i8, a, 2i4)') 'refused ring_solves'' film solves with and without', &
      wasted, ', refused as jumps', jumps
    call check(real(wasted(1), dp) <= 0.85_dp * wasted(2), &
               'the refused ring_solves take at most 0.85 times the film solves')
    call check(jumps(1) > jumps(2), 'more refusals are jumps')
    call check(all(r(1)%series(:, s_h0) == r(2)%series(:, s_h0)), 'every step''s h0 to the bit')
    call check(all(r(1)%series(:, s_load_residual) == r(2)%series(:, s_load_residual)), &
               'every step''s load residual to the bit')
    call check(all(r(1)%series(:, s_friction) == r(2)%series(:, s_friction)), &
               'every step''s friction to the bit')
    call check(all(r(1)%int_series(:, si_flags) == r(2)%int_series(:, si_flags)), &
               'every step''s flags the same')
    call check(r(1)%scalars(sc_energy_loss) == r(2)%scalars(sc_energy_loss), &
               'the energy to the bit')
  end subroutine jump_exit_early

  !> Why ring_solve is refused on the shipped 12,000 r/min deck's flooded film: at nearly every
  !> refused step, stalled or refused as a jump, the step's answer (the root finder's) moves a
  !> sector by more than max_jump from the last step, so no Newton iteration that converged
  !> there would be accepted; and at most of them it is the whole ring that moves (off the
  !> ceiling or far in its clearance: a sector's move against the ring's mean move within
  !> max_jump; bench_kernel's line "beyond the limit"). With relative_jump (off by default: the
  !> answers move) the refusals as a jump, which measure a sector's move against the ring's,
  !> fall to a few, the energy within 1e-4 of itself.
  subroutine refusals_ring_moves()
    character(len=*), parameter :: deck = 'inputs/crf450r_12000rpm_full_hot_distorted.nml'
    type(case_type) :: c
    type(result_type) :: r(2)
    type(error_type), allocatable :: err
    integer :: i, far(4, 3, 2), refused(4, 2), stalled(2)
    if (.not. shipped_deck(deck, "&ring tension_unit = 'N' / "// &
                           "&physics cavitation = 'jfo', inlet = 'flooded' /", c)) return
    call check(.not. relative_jump, 'a sector''s move in ln h0 by default')
    do i = 1, 2
      relative_jump = i == 2
      solve_failures = 0
      stalled_failures = 0
      refused_far = 0
      call solve_cycle(c, r(i), err)
      call check(.not. allocated(err), 'the 12,000 r/min flooded film solved')
      if (allocated(err)) exit
      far(:, :, i) = refused_far
      refused(:, i) = solve_failures
      stalled(i) = stalled_failures
    end do
    relative_jump = .false.
    if (allocated(err)) return
    write (*, '(a, 4i4, a, i4)') 'refusals (not converged, bound, jump, light)', refused(:, 1), &
      ', stalled', stalled(1)
    write (*, '(a, 2i4, a, 2i4, a, 2i4)') 'their answers beyond max_jump: not converged, jump', &
      far([1, 3], 1, 1), '; against the ring''s move', far([1, 3], 2, 1), '; at the ceiling', &
      far([1, 3], 3, 1)
    write (*, '(a, 4i4, a, 2f12.7)') 'with relative_jump: refusals', refused(:, 2), &
      '; energy J', r(:)%scalars(sc_energy_loss)
    call check(stalled(1) >= 10, 'line searches without descent on this deck')
    ! (measured: 18 of the 21 refusals not converged beyond max_jump, 18 stalled; 46 of the 46
    ! refusals as a jump)
    call check(10 * far(1, 1, 1) >= 8 * stalled(1), &
               'the refusals not converged: answers beyond max_jump for eight in ten stalls')
    call check(10 * far(3, 1, 1) >= 9 * refused(3, 1), &
               'the refusals as a jump: nine in ten answers beyond max_jump')
    call check(far(1, 2, 1) + far(3, 2, 1) <= (far(1, 1, 1) + far(3, 1, 1)) / 4, &
               'at most a quarter of them a sector''s move against the ring''s')
    call check(refused(3, 2) <= refused(3, 1) / 4, &
               'with relative_jump a quarter of the jumps or less')
    call check(abs(r(2)%scalars(sc_energy_loss) / r(1)%scalars(sc_energy_loss) - 1.0_dp) &
               < 1e-4_dp, 'the energy within 1e-4')
  end subroutine refusals_ring_moves

  !> A loose trial of the root finder at the floor is solved to the sectors' own tolerance:
  !> the root finder's trial there is exp(ln h0_floor), within round-off of h0_floor and here
  !> above it (h0_floor 5e-8 m, at which the sectors of the step at 90 deg do not settle in one
  !> film solve: exp(ln 5e-8) is 5.3e-23 m above; exp(ln 1e-9), the default's, 6.2e-25 m), and
  !> was taken for a trial strictly between the bounds, ending loose. (The same trial at 2
  !> h0_floor, far below the balance, ends loose: the test tells the two apart.)
  subroutine loose_trial_at_floor()
    type(case_type) :: c
    type(cycle_state) :: st
    type(step_out) :: out
    type(sector_ring) :: ring
    type(sector_trial) :: tr
    real(dp) :: cc(2)
    logical :: loosened(2)
    integer :: i
    c = base_case()
    c%tension_unit = 'N'
    c = distorted(c, 4, 10e-6_dp, 16)
    c%h0_floor = 5e-8_dp
    call cycle_setup(st, c, 1e-7_dp)
    call advance(st, c, 90.0_dp, out)
    cc = [exp(log(c%h0_floor)), 2.0_dp * c%h0_floor]
    call check(cc(1) /= c%h0_floor, 'exp(ln h0_floor) is not h0_floor')
    do i = 1, 2
      ring = st%ring
      tr = sector_trial(cc=cc(i), sq_a=out%lp%sq_a, dt=out%lp%dt, u=out%lp%u, &
                        p_chamber=out%lp%pg, load=out%lp%load, floor=c%h0_floor, &
                        ceiling=c%h0_ceiling, cc_floor=c%h0_floor, cc_ceiling=out%lp%ceiling)
      tr%loose = .true.
      call ring_evaluate(c, ring, st%film%f, tr)
      loosened(i) = ring%loosened
    end do
    write (*, '(a, 2l2)') 'loose trial ended loose at exp(ln h0_floor), 2 h0_floor:', loosened
    call check(.not. loosened(1), 'the trial at the floor solved to the sectors'' own tolerance')
    call check(loosened(2), 'the trial above the floor ends loose')
  end subroutine loose_trial_at_floor

  !> A step whose root finder ends on a trial far from the root (a loose one: the sectors not
  !> within their own tolerance) has its sectors solved to their own tolerance at that answer
  !> (the balance's `finish`): after every step the ring's last evaluation is not loose. The
  !> 0.75 mm ring on the shipped 12,000 r/min distorted deck without the ring pack, from a cold
  !> start, with max_load_iterations = 1 and the root finder's remembered slope set to -1e-3
  !> before each step (its first trial then half a unit of ln h0 from the guess): the refused
  !> steps end after one Brent trial, most more than 10 load_tol off the balance (60 of 63).
  !> (Without that solve the path moves: 17 of its 25 refused steps ended loose.)
  subroutine loose_answer_solved_tight()
    character(len=*), parameter :: deck = 'inputs/crf450r_12000rpm_full_hot_distorted.nml'
    type(case_type) :: c
    type(cycle_state) :: st
    type(step_out) :: out
    integer :: k, refused, far, loose_after
    if (.not. shipped_deck(deck, "&ring width = 0.75e-3 / &physics ring_pack = 'none' / "// &
                           "&numerics max_load_iterations = 1 /", c)) return
    call cycle_setup(st, c, 1e-6_dp)
    loose_answers_solved = 0
    refused = 0
    far = 0
    loose_after = 0
    do k = 1, nint(720.0_dp / c%dpsi_deg)
      phase_calls = 0
      st%film%mem%slope = -1e-3_dp
      call advance(st, c, k * c%dpsi_deg, out)
      if (allocated(st%err)) then
        call check(.false., 'the step solved: '//st%err%message)
        return
      end if
      if (phase_calls(2) == 0) cycle
      refused = refused + 1
      if (iand(out%flags, 3) == 0 .and. abs(out%resid) > 10.0_dp * c%load_tol) far = far + 1
      if (st%ring%loosened) loose_after = loose_after + 1
    end do
    write (*, '(a, 3(1x, i0))') 'refused steps, ended over 10 load_tol off the balance, loose after '// &
      'the step:', refused, far, loose_after
    write (*, '(a, i0)') 'answers on a loose trial solved again: ', loose_answers_solved
    call check(far > 0, 'some refused steps end far from the balance')
    call check(loose_answers_solved > 0, 'some answers were on a loose trial')
    call check(loose_after == 0, 'no step ends on a loose trial')
  end subroutine loose_answer_solved_tight

  !> An answer within load_tol at which a sector's film is not settled (here its
  !> pressure-viscosity loop, at max_pressure_iterations = 1, flag 8) is solved once more there;
  !> where the load then lies beyond load_tol the step is flagged as a load balance outside
  !> load_tol (flag 4) and keeps the film's flag beside it (the balance was met with the film
  !> unsettled). The shipped 12,000 r/min distorted deck's first cycle: steps flagged 8 with a
  !> load residual beyond load_tol, every one of them flagged 4 as well.
  subroutine unsettled_answer_flag()
    character(len=*), parameter :: deck = 'inputs/crf450r_12000rpm_full_hot_distorted.nml'
    type(case_type) :: c
    type(result_type) :: r
    type(error_type), allocatable :: err
    logical, allocatable :: off(:)
    integer :: both
    if (.not. shipped_deck(deck, '&numerics max_pressure_iterations = 1, '// &
                           'max_cycles = 1 /', c)) return
    call solve_cycle(c, r, err)
    call check(.not. allocated(err), 'the deck solved')
    if (allocated(err)) return
    ! steps not held at a bound whose film was unsettled and whose load lies beyond load_tol
    off = iand(r%int_series(:, si_flags), 3) == 0 .and. &
          iand(r%int_series(:, si_flags), flag_viscosity) /= 0 .and. &
          abs(r%series(:, s_load_residual)) > c%load_tol
    both = count(off .and. iand(r%int_series(:, si_flags), flag_load) /= 0)
    write (*, '(a, 2(1x, i0))') 'steps flagged 8 beyond load_tol, of them flagged 4 too:', &
      count(off), both
    call check(count(off) > 0, 'steps with an unsettled film beyond load_tol')
    call check(both == count(off), 'each flagged as a load balance outside load_tol too')
  end subroutine unsettled_answer_flag

  !> A trial of the root finder whose sectors missed their tolerance is solved once more
  !> before the root finder takes its residual (ringlube_load_balance, residual): the cold
  !> 4000 r/min deck starved on an order-4 bore of 10 um on 8 sectors, its tension read in N/m
  !> (identical.py's distorted_starved in that reading), 5 cycles. At 330-334 deg of the fifth
  !> cycle the first trial's sectors missed (40 Newton iterations) with a residual of -0.10 to
  !> -0.16 where the ring's, solved, is +0.05 to +0.12; the root finder bracketed the root with
  !> it and closed the bracket on that trial, the steps flagged 4 with the load 5.4, 9.2 and
  !> 11.7 % off. Solved again, the trial is on the side it is and the steps are within load_tol.
  subroutine missed_trial_solved_again()
    character(len=*), parameter :: deck = 'inputs/crf450r_4000rpm_full_cold.nml'
    character(len=*), parameter :: variant = &
                         "&physics cavitation = 'jfo', inlet = 'starved', bore = 'distorted' / "// &
               "&bore order = 4, amplitude = 10e-6, sectors = 8 / &ring tension_unit = 'N/m' / "// &
                        "&calibration file = 'calibration_n_per_m.nml' / &numerics max_cycles = 5 /"
    type(case_type) :: c
    type(result_type) :: r
    type(error_type), allocatable :: err
    real(dp), allocatable :: psi(:), res(:)
    logical, allocatable :: steps(:)
    if (.not. shipped_deck(deck, variant, c)) return
    missed_solved_again = 0
    call solve_cycle(c, r, err)
    call check(.not. allocated(err), 'the starved film on the distorted bore solved')
    if (allocated(err)) return
    write (*, '(a, i0)') 'trials whose sectors missed, solved again: ', missed_solved_again
    call check(missed_solved_again > 0, 'some trial missed and was solved again')
    psi = r%series(:, s_crank_angle_deg)
    steps = psi >= 329.0_dp .and. psi <= 335.0_dp
    res = pack(r%series(:, s_load_residual), steps)
    write (*, '(a, *(es10.2))') 'load residual at 330-334 deg:', res
    call check(size(res) == 3, 'the steps at 330, 332 and 334 deg')
    call check(all(abs(res) <= c%load_tol), 'the steps at 330-334 deg within load_tol')
    call check(all(pack(r%int_series(:, si_flags), steps) == 0), &
               'the steps at 330-334 deg not flagged')
  end subroutine missed_trial_solved_again

  !> Two threads give the one thread's answer bit for bit however the team's threads wait
  !> between a step's passes over the sectors (ringlube_sectors; the load average not
  !> consulted, so that the step is a team on a loaded machine too): always asleep (team_spin
  !> 0: thread 0 meets them at a barrier at every pass), and awake up to 1 ms (they take each
  !> job without a barrier unless they lose their core); with a cycle's steps in one parallel
  !> region (its threads waiting for the next step's jobs between steps) and with a region per
  !> step (ringlube_cycle_state, cycle_regions);
  !> starved film with the ring pack (its sectors' inlets, films, lift-off margin copies and
  !> oil after the balance all jobs of the team), 12 sectors, orders 2 and 4.
  subroutine team_wait_modes()
    type(case_type) :: c, c0
    type(result_type) :: r1, r2
    real(dp) :: spins(2) = [0.0_dp, 1e-3_dp], keep
    integer :: i, k
    logical :: keep_regions
    c0 = base_case()
    c0%tension_unit = 'N'
    c0%cavitation = 'jfo'
    c0%inlet = 'starved'
    c0%ring_pack = 'gas'
    c0 = distorted(c0, 2, 8e-6_dp, 12)
    c0%bore_order = [2, 4]
    c0%bore_amplitude = [8e-6_dp, 5e-6_dp]
    ! (coarse: on a loaded machine every wake-up of a thread asleep takes milliseconds)
    c0%dpsi_deg = 6.0_dp
    c0%max_cycles = 1
    c = c0
    call solve(c, r1, 'one thread')
    keep = team_spin
    keep_regions = cycle_regions
    do k = 1, 2
      ! (a cycle's steps in one parallel region, then a region per step)
      cycle_regions = k == 1
      do i = 1, size(spins)
        team_spin = spins(i)
        team_busy_check = .false.
        c = c0
        c%threads = 2
        call solve(c, r2, 'two threads')
        r1%scalars(sc_run_time) = 0.0_dp
        r2%scalars(sc_run_time) = 0.0_dp
        call check(all(r2%series == r1%series) .and. all(r2%int_series == r1%int_series) .and. &
                   all(r2%sectors == r1%sectors) .and. all(r2%scalars == r1%scalars) .and. &
                   all(r2%liner == r1%liner), 'two threads: the one thread''s answer bit for bit')
      end do
    end do
    ! (a cycle's team on a machine taken for busy at every other three load checks: those
    ! steps thread 0's alone, the other threads waiting: team_pause)
    cycle_regions = .true.
    team_spin = 0.0_dp
    team_busy_every = 3
    team_busy_checks = 0
    c = c0
    c%threads = 2
    call solve(c, r2, 'two threads, busy at times')
    call check(team_busy_checks > 4 * team_busy_every, 'the machine taken for busy at times')
    r2%scalars(sc_run_time) = 0.0_dp
    call check(all(r2%series == r1%series) .and. all(r2%int_series == r1%int_series) .and. &
               all(r2%sectors == r1%sectors) .and. all(r2%scalars == r1%scalars) .and. &
               all(r2%liner == r1%liner), &
               'two threads, the machine busy at times: the one thread''s answer bit for bit')
    team_busy_every = 0
    cycle_regions = keep_regions
    team_spin = keep
    team_busy_check = .true.
  end subroutine team_wait_modes
end program test_bore

