!> The load balance at one crank step: h0 such that W_h + W_a = F within
!> load_tol, by the study's damped rule or a safeguarded secant/Brent iteration on ln h0.
!>
!> The squeeze term 2 dh0/dt is discretised in time by backward Euler (first order) or
!> BDF2 (second order, `&numerics time_scheme`); both are implicit in h0, so the film is
!> solved at the new h0 only. BDF2 needs two previous steps on a smooth stretch of h0(t):
!> it takes one Euler step at the start, after a step whose h0 is not a solution of the
!> balance (held at h0_floor or h0_ceiling), and at a reversal of the sliding speed
!> (the steps at and after a dead centre, or where u changes sign): there the outlet moves to
!> the other edge, dh0/dt jumps, and the BDF2 difference across the kink would make a
!> first-order error.
!>
!> With a distorted bore (a `ring` of sectors) the first attempt solves the mean position with
!> the sectors in one Newton iteration (ringlube_sectors, ring_solve); the root finder below is
!> its safeguard (lift-off, the floor, a light sector, a Newton iteration that fails).
!>
!> The film model enters only through `film_evaluate` (loads at a trial h0) in
!> `residual`: a second film model plugs in there.
module ringlube_load_balance
  use ringlube_kinds, only: dp, pi
  use ringlube_case, only: case_type
  use ringlube_kinematics, only: sliding_speed, deg2rad
  use ringlube_gas, only: gas_pressure
  use ringlube_film, only: film_type, film_evaluate, film_copy
  use ringlube_film_state, only: lower_edge_pressure
  use ringlube_jfo_connect, only: jfo_seal_margin
  use ringlube_sectors, only: sector_ring, sector_trial, ring_evaluate, ring_ceiling, ring_solve, &
                              ring_coupled, loose_trials, phase_calls, phase_solves, &
                              refused_solves, refused_held_solves, last_refusal, bound_rtol, &
                              count_refused_answer
  use ringlube_results, only: flag_floor, flag_ceiling, flag_load, flag_viscosity, &
                              flag_cavitation, flag_sectors
  implicit none
  private
  public :: step_context, load_problem, balance_memory, balance, speed, start_history
  public :: lift_margin_end, missed_solved_again, loose_answers_solved

  !> the lift-off margin is measured on the steps of the intake stroke, psi (mod 720) from 0
  !> to this crank angle [deg]
  real(dp), parameter :: lift_margin_end = 180.0_dp

  !> trials of a distorted bore whose sectors missed their tolerance and were solved once more
  !> (residual; a count for tests and benchmarks, reset by its user; the balance runs on one
  !> thread)
  integer, save :: missed_solved_again = 0
  !> answers of the root finder on a loose trial, solved again to the sectors' own tolerance
  !> (finish; a count for tests and benchmarks, as missed_solved_again)
  integer, save :: loose_answers_solved = 0

  !> Constants of a run needed at every step.
  type :: step_context
    real(dp) :: omega = 0.0_dp   !< crank speed, rad/s
    real(dp) :: dt = 0.0_dp      !< time step, s
    real(dp) :: p_e = 0.0_dp     !< elastic pressure of the ring, Pa
  end type step_context

  !> The load balance at one crank step. The squeeze velocity at trial h0 is
  !> dh0/dt = (sq_a h0 - sq_b) / dt (Euler: sq_a = 1, sq_b = h0 of the previous step;
  !> BDF2: sq_a = 3/2, sq_b = 2 h_(k-1) - h_(k-2)/2).
  !> ceiling: the largest h0 (h0_ceiling; with a distorted bore also back_clearance, where a
  !> ring pushed off the liner is held).
  type :: load_problem
    real(dp) :: u = 0.0_dp, dt = 0.0_dp, pg = 0.0_dp, load = 0.0_dp
    real(dp) :: sq_a = 1.0_dp, sq_b = 0.0_dp
    real(dp) :: ceiling = 0.0_dp
    !> branch risk (docs/model.md, "Branch risk"): the lift-off margin (F - W at the ceiling)
    !> / F on the steps of the intake stroke, the seal margin (jfo_seal_margin) where the
    !> trailing gas is above the leading edge's; huge(1.0_dp) where not measured
    real(dp) :: lift_margin = huge(1.0_dp), seal_margin = huge(1.0_dp)
    !> film solves on a copy of the film for the lift-off margin (not in the film's counters)
    integer :: margin_solves = 0
  end type load_problem

  !> What the root finder remembers between trials and crank steps.
  type :: balance_memory
    !> the last two trials: y = ln h0 and the relative residual
    real(dp) :: y_hist(2) = 0.0_dp, g_hist(2) = 0.0_dp
    !> d residual / d ln h0 of the last step with two trials (< 0); 0: none yet
    real(dp) :: slope = 0.0_dp
    !> trials made at the current step
    integer :: trials = 0
    !> h0 of the last three crank steps, most recent first, and how many of them form a
    !> smooth history (0-3; set to 1 by `start_history` and after a held step)
    real(dp) :: h(3) = 0.0_dp
    integer :: nh = 0
    !> sliding speed of the last step (0 at the start)
    real(dp) :: u = 0.0_dp
    !> the film at h0_ceiling of the last lift-off margin (`margins`), the warm start of the
    !> next: pressure, viscosity and fill (not allocated before the first)
    real(dp), allocatable :: p_ceiling(:), eta_ceiling(:), theta_ceiling(:)
    !> the margin's copy of the film (its arrays kept from step to step: film_copy)
    type(film_type) :: ceiling_film
  end type balance_memory

  !> trials of the damped rule over which its best residual must fall by 1 % (else it stops)
  integer, parameter :: stall_window = 25

contains

  !> Sliding speed at crank angle psi [deg]; round-off speeds at the dead centres are 0.
  pure real(dp) function speed(c, ctx, psi)
    type(case_type), intent(in) :: c
    type(step_context), intent(in) :: ctx
    real(dp), intent(in) :: psi
    speed = sliding_speed(deg2rad(psi), c%crank_radius, c%conrod_length, ctx%omega)
    ! sin(pi) is 1e-16, not 0: treat round-off speeds at the dead centres as zero
    if (abs(speed) < 1e-12_dp * c%crank_radius * ctx%omega) speed = 0.0_dp
  end function speed

  !> Start the h0 history of a run at h0 (the state before the first step).
  pure subroutine start_history(mem, h0)
    type(balance_memory), intent(inout) :: mem
    real(dp), intent(in) :: h0
    mem%h = h0
    mem%nh = 1
    mem%u = 0.0_dp
  end subroutine start_history

  !> Find h0 at crank angle psi so that W_h + W_a = F (within load_tol), from the h0
  !> history in `mem` (the root finder's memory, carried from step to step; the new h0 is
  !> pushed onto it). The film `g` is left solved at the returned h0; `lp` returns the
  !> step's sliding speed, gas pressure and applied load. With `ring` (a distorted bore) h0 is
  !> the ring's mean position and each trial solves the ring's sectors (ringlube_sectors); g
  !> is then the ring's summary film (its edge state, the mean loads).
  subroutine balance(c, ctx, g, mem, psi, h0out, flags, resid, lp, ring)
    type(case_type), intent(in) :: c
    type(step_context), intent(in) :: ctx
    type(film_type), intent(inout) :: g
    type(sector_ring), intent(inout), optional :: ring
    type(balance_memory), intent(inout) :: mem
    real(dp), intent(in) :: psi
    real(dp), intent(out) :: h0out, resid
    integer, intent(out) :: flags
    type(load_problem), intent(out) :: lp
    real(dp) :: u, guess
    integer :: refusals, solves
    u = speed(c, ctx, psi)
    if (u < 0.0_dp) g%lead_left = .true.
    if (u > 0.0_dp) g%lead_left = .false.
    lp%u = u
    lp%dt = ctx%dt
    lp%ceiling = c%h0_ceiling
    if (present(ring)) lp%ceiling = min(c%h0_ceiling, c%back_clearance)
    lp%pg = gas_pressure(c%gas_psi, c%gas_p, psi, c%crankcase_pressure)
    ! the gas behind the ring: the chamber's, or the groove's with the ring pack
    if (g%p_back >= 0.0_dp) then
      lp%load = (ctx%p_e + g%p_back) * c%width * g%circ
    else
      lp%load = (ctx%p_e + lp%pg) * c%width * g%circ
    end if
    ! BDF2 on a smooth stretch: two previous steps, and the sign of u (the inlet edge)
    ! as at the last step
    if (c%time_scheme == 'bdf2' .and. mem%nh >= 2 .and. &
        sign_of(u) == sign_of(mem%u)) then
      lp%sq_a = 1.5_dp
      lp%sq_b = 2.0_dp * mem%h(1) - 0.5_dp * mem%h(2)
    else
      lp%sq_a = 1.0_dp
      lp%sq_b = mem%h(1)
    end if
    guess = predictor(mem)
    mem%trials = 0
    guess = min(max(guess, c%h0_floor), lp%ceiling)
    refusals = phase_calls(2)
    solves = phase_solves(3)
    call find_h0(c, lp, g, mem, guess, h0out, flags, resid, ring)
    ! (benchmark counters: the root finder's film solves at a step ring_solve refused)
    if (present(ring) .and. phase_calls(2) > refusals) then
      associate (r => last_refusal, n => phase_solves(3) - solves)
        refused_solves(r) = refused_solves(r) + n
        if (iand(flags, flag_floor + flag_ceiling) /= 0) &
          refused_held_solves(r) = refused_held_solves(r) + n
      end associate
      call count_refused_answer(ring, max(mem%h(1), h0out) >= lp%ceiling * (1.0_dp - bound_rtol))
    end if
    call margins(c, lp, g, mem, psi, h0out, flags, resid, ring)
    mem%h(3) = mem%h(2)
    mem%h(2) = mem%h(1)
    mem%h(1) = h0out
    mem%nh = min(mem%nh + 1, 3)
    if (iand(flags, flag_floor + flag_ceiling) /= 0) mem%nh = 1
    mem%u = u
  end subroutine balance

  !> The step's branch risk in `lp` (docs/model.md, "Branch risk"), from the film `g` solved
  !> at the accepted h0 (flags and resid the balance's).
  !>
  !> Lift-off margin, on the steps of the intake stroke (psi mod 720 in [0, lift_margin_end]),
  !> where the chamber and the elastic pressure pressing the ring on the liner are closest to the
  !> gas below it: (F - W) / F with W the load the film carries at the ceiling (the largest
  !> h0), the squeeze of the step included. The balance holds a step at the ceiling (lift-off,
  !> flag 2) when W > F there, so the margin is < 0 where the ring can be lifted off and > 0
  !> where it cannot. A step held at the ceiling has W from the balance's own solve there;
  !> every other step one film solve more, on a copy of the film (and of a distorted bore's
  !> sectors), which changes nothing of the step. The copy starts from the film of the last
  !> such solve (`mem`; a distorted bore's sectors: ring_ceiling), not from the step's film at
  !> its h0: the film at the ceiling changes little from step to step (from the step's film, a
  !> run of the hot deck with a starved inlet took 25 % more CPU time than without the margin,
  !> from the last ceiling film 4 %).
  !>
  !> Seal margin, with 'trailing_gas' on a step not held at the ceiling: jfo_seal_margin of
  !> the film (of the sectors of a distorted bore, the smallest: the gas passes where one blows).
  subroutine margins(c, lp, g, mem, psi, h0out, flags, resid, ring)
    type(case_type), intent(in) :: c
    type(load_problem), intent(inout) :: lp
    type(film_type), intent(in) :: g
    type(balance_memory), intent(inout) :: mem
    real(dp), intent(in) :: psi, h0out, resid
    integer, intent(in) :: flags
    type(sector_ring), intent(inout), optional :: ring
    type(sector_trial) :: tr
    real(dp) :: sq
    integer :: j
    if (modulo(psi, 720.0_dp) <= lift_margin_end) then
      if (iand(flags, flag_ceiling) /= 0 .or. h0out >= lp%ceiling) then
        lp%lift_margin = -resid
      else
        associate (gc => mem%ceiling_film)
          call film_copy(gc, g)
          if (present(ring)) then
            tr = sector_trial(cc=lp%ceiling, sq_a=lp%sq_a, dt=lp%dt, u=lp%u, p_chamber=lp%pg, &
                              load=lp%load, floor=c%h0_floor, ceiling=c%h0_ceiling)
            call ring_ceiling(c, ring, gc, tr)
          else
            sq = 0.0_dp
            if (c%squeeze) sq = 2.0_dp * (lp%sq_a * lp%ceiling - lp%sq_b) / lp%dt
            if (allocated(mem%p_ceiling)) then
              gc%p = mem%p_ceiling
              gc%eta = mem%eta_ceiling
              if (gc%jfo) gc%theta = mem%theta_ceiling
            end if
          call film_evaluate(c, gc, lp%ceiling, sq, lp%u, lp%pg, c%load_tol * max(lp%load, 1e-3_dp))
            mem%p_ceiling = gc%p
            mem%eta_ceiling = gc%eta
            if (gc%jfo) mem%theta_ceiling = gc%theta
          end if
          lp%margin_solves = gc%film_solves - g%film_solves
          lp%lift_margin = (lp%load - gc%wh - gc%wa) / max(lp%load, 1e-3_dp)
        end associate
      end if
    end if
    if (.not. g%jfo .or. c%cavity_pressure /= 'trailing_gas') return
    if (iand(flags, flag_ceiling) /= 0) return
    if (present(ring)) then
      do j = 1, size(ring%films)
        associate (fj => ring%films(j))
          lp%seal_margin = min(lp%seal_margin, &
                               jfo_seal_margin(lp%u, lp%pg, lower_edge_pressure(c, fj), &
                                               c%cavitation_pressure, fj%theta, fj%p))
        end associate
      end do
    else
      lp%seal_margin = jfo_seal_margin(lp%u, lp%pg, lower_edge_pressure(c, g), &
                                       c%cavitation_pressure, g%theta, g%p)
    end if
  end subroutine margins

  !> -1, 0 or 1.
  pure integer function sign_of(x)
    real(dp), intent(in) :: x
    sign_of = 0
    if (x > 0.0_dp) sign_of = 1
    if (x < 0.0_dp) sign_of = -1
  end function sign_of

  !> First trial h0 of a step: extrapolation of ln h0 from the previous steps (quadratic
  !> from three, linear from two), limited to a factor 1.2 from the last step. (A
  !> correction for the part of the new applied load the same extrapolation of ln F does
  !> not foresee was tried and needed more film solves.)
  pure real(dp) function predictor(mem) result(guess)
    type(balance_memory), intent(in) :: mem
    real(dp) :: y1, y
    y1 = log(mem%h(1))
    y = extrapolate(log(mem%h), mem%nh)
    guess = exp(min(max(y, y1 - log(1.2_dp)), y1 + log(1.2_dp)))
  end function predictor

  !> The next value of a series from its last nh values (most recent first).
  pure real(dp) function extrapolate(v, nh)
    real(dp), intent(in) :: v(3)
    integer, intent(in) :: nh
    select case (nh)
    case (3)
      extrapolate = 3.0_dp * v(1) - 3.0_dp * v(2) + v(3)
    case (2)
      extrapolate = 2.0_dp * v(1) - v(2)
    case default
      extrapolate = v(1)
    end select
  end function extrapolate

  !> Relative load residual (W_h + W_a - F) / F at trial h0 (solves the film). loose (a
  !> distorted bore's step that ring_solve did not take): a trial far from the root may end its
  !> sectors' Newton iteration early (ringlube_sectors, sector_trial's loose). A distorted
  !> bore's trial strictly between the bounds whose sectors missed their tolerance (even a
  !> loose trial's: flag_sectors) carries a load that is not the ring's at h0; its sign can be
  !> wrong, and the root finder would bracket the root with it and close the bracket there with
  !> the load 5-12 % off (the cold 4000 r/min deck starved, read in N/m, at 330-334 deg): it is
  !> solved once more, its Newton iteration continued from where it stopped.
  real(dp) function residual(c, lp, g, mem, h0, ring, loose)
    type(case_type), intent(in) :: c
    type(load_problem), intent(in) :: lp
    type(film_type), intent(inout) :: g
    type(balance_memory), intent(inout) :: mem
    real(dp), intent(in) :: h0
    type(sector_ring), intent(inout), optional :: ring
    logical, intent(in), optional :: loose
    real(dp) :: sq
    type(sector_trial) :: tr
    if (present(ring)) then
      tr = sector_trial(cc=h0, sq_a=lp%sq_a, dt=lp%dt, u=lp%u, p_chamber=lp%pg, load=lp%load, &
                        floor=c%h0_floor, ceiling=c%h0_ceiling, cc_floor=c%h0_floor, &
                        cc_ceiling=lp%ceiling)
      if (present(loose)) tr%loose = loose
      call ring_evaluate(c, ring, g, tr)
      if (iand(g%flags, flag_sectors) /= 0 .and. h0 > c%h0_floor * (1.0_dp + bound_rtol) .and. &
          h0 < lp%ceiling * (1.0_dp - bound_rtol)) then
        tr = sector_trial(cc=h0, sq_a=lp%sq_a, dt=lp%dt, u=lp%u, p_chamber=lp%pg, load=lp%load, &
                          floor=c%h0_floor, ceiling=c%h0_ceiling, cc_floor=c%h0_floor, &
                          cc_ceiling=lp%ceiling)
        if (present(loose)) tr%loose = loose
        call ring_evaluate(c, ring, g, tr)
        missed_solved_again = missed_solved_again + 1
      end if
    else
      sq = 0.0_dp
      if (c%squeeze) sq = 2.0_dp * (lp%sq_a * h0 - lp%sq_b) / lp%dt
      call film_evaluate(c, g, h0, sq, lp%u, lp%pg, c%load_tol * max(lp%load, 1e-3_dp))
    end if
    ! relative to the applied load; a load of zero (no tension, no gas, crankcase at
    ! 0 Pa) is measured against 1 mN, so that the residual stays finite
    residual = (g%wh + g%wa - lp%load) / max(lp%load, 1e-3_dp)
    mem%y_hist(1) = mem%y_hist(2)
    mem%g_hist(1) = mem%g_hist(2)
    mem%y_hist(2) = log(h0)
    mem%g_hist(2) = residual
    mem%trials = mem%trials + 1
  end function residual

  !> h0 from `guess` by the rule of `&numerics h0_update`: the source study's damped rule or a
  !> safeguarded secant (Brent's method) on y = ln h0 inside an expanding bracket.
  subroutine find_h0(c, lp, g, mem, guess, h0out, flags, resid, ring)
    type(case_type), intent(in) :: c
    type(load_problem), intent(in) :: lp
    type(film_type), intent(inout) :: g
    type(balance_memory), intent(inout) :: mem
    type(sector_ring), intent(inout), optional :: ring
    real(dp), intent(in) :: guess
    real(dp), intent(out) :: h0out, resid
    integer, intent(out) :: flags
    real(dp) :: ya, yb, ga, gb, dy, ylo, yhi
    integer :: it
    logical :: solved, loose

    if (c%h0_update == 'damped') then
      call damped()
      return
    end if
    flags = 0
    ! (the root finder's trials after a refused ring_solve may be loose: far from the root
    ! their sectors end early, at a tolerance in proportion to the load residual)
    loose = .false.
    if (present(ring)) then
      if (ring_coupled(ring)) then
        call free_ring(solved)
        if (solved) return
        loose = loose_trials
      end if
    end if
    ylo = log(c%h0_floor)
    yhi = log(lp%ceiling)
    ya = log(guess)
    ga = residual(c, lp, g, mem, guess, ring, loose)
    if (abs(ga) <= c%load_tol) then
      call finish(guess, ga)
      return
    end if
    ! bracket the root: the residual falls with h0 (W > F means the film can open). The
    ! first trial is a Newton step with the slope remembered from the previous crank
    ! step (usually within load_tol at once); then secant extrapolation, then expansion.
    if (mem%slope < 0.0_dp) then
      dy = -ga / mem%slope
      dy = sign(min(max(abs(dy), 1e-6_dp), 0.5_dp), dy)
    else
      dy = sign(0.01_dp, ga)
    end if
    do it = 1, 200
      yb = min(max(ya + dy, ylo), yhi)
      gb = residual(c, lp, g, mem, exp(yb), ring, loose)
      if (abs(gb) <= c%load_tol) then
        call finish(exp(yb), gb)
        return
      end if
      if (sign(1.0_dp, gb) /= sign(1.0_dp, ga)) exit
      if (yb <= ylo .or. yb >= yhi) then
        if (yb <= ylo) flags = flag_floor
        if (yb >= yhi) flags = flag_ceiling
        call finish(exp(yb), gb)
        return
      end if
      if ((gb - ga) / (yb - ya) < 0.0_dp .and. abs(gb) < abs(ga)) then
        ! secant step, aimed 2 % past the root so that a miss brackets it
        dy = sign(1.02_dp * abs(gb * (yb - ya) / (gb - ga)), dy)
      else
        dy = 3.0_dp * dy
      end if
      dy = sign(min(abs(dy), 2.0_dp), dy)
      ya = yb
      ga = gb
    end do
    call brent(ya, yb, ga, gb)

  contains

    !> A distorted bore's mean position solved with its sectors (ring_solve: one Newton
    !> iteration on the M + 3 unknowns) from `guess`; solved: within load_tol strictly
    !> between the bounds, the step is finished there (and the slope of the load residual
    !> against ln h0 remembered for the root finder of a later step). Not solved: the root
    !> finder on the mean position below takes over (lift-off, the floor, a stalled Newton).
    subroutine free_ring(solved)
      logical, intent(out) :: solved
      type(sector_trial) :: tr
      real(dp) :: r
      tr = sector_trial(cc=guess, sq_a=lp%sq_a, dt=lp%dt, u=lp%u, p_chamber=lp%pg, load=lp%load, &
                        floor=c%h0_floor, ceiling=c%h0_ceiling, cc_floor=c%h0_floor, &
                        cc_ceiling=lp%ceiling)
      call ring_solve(c, ring, g, tr, solved)
      if (.not. solved) return
      r = (g%wh + g%wa - lp%load) / max(lp%load, 1e-3_dp)
      solved = abs(r) <= c%load_tol
      if (.not. solved) return
      if (tr%dres_dlnc < 0.0_dp) mem%slope = tr%dres_dlnc
      call finish(tr%cc, r)
    end subroutine free_ring

    !> The source study's rule h0 <- (1 + beta_d chi) h0, chi = (W - F)/max(W, F).
    subroutine damped()
      real(dp) :: h, w, chi, best, best_before
      integer :: it
      h = guess
      flags = flag_load
      best = huge(1.0_dp)
      best_before = huge(1.0_dp)
      do it = 1, c%max_load_iterations
        resid = residual(c, lp, g, mem, h, ring)
        if (abs(resid) <= c%load_tol) then
          flags = 0
          exit
        end if
        ! a rule that no longer contracts (a damping near 1 overshoots and oscillates) ends,
        ! flagged, when the best residual of the last `stall_window` trials is not 1 % below
        ! the best before them, instead of spending max_load_iterations at every step
        best = min(best, abs(resid))
        if (mod(it, stall_window) == 0) then
          if (best > 0.99_dp * best_before) exit
          best_before = best
        end if
        w = g%wh + g%wa
        chi = (w - lp%load) / max(w, lp%load)
        if (h <= c%h0_floor .and. chi < 0.0_dp) then
          flags = flag_floor
          exit
        end if
        if (h >= lp%ceiling .and. chi > 0.0_dp) then
          flags = flag_ceiling
          exit
        end if
        if (it == c%max_load_iterations) exit
        h = min(max((1.0_dp + c%damping * chi) * h, c%h0_floor), lp%ceiling)
      end do
      flags = ior(flags, g%flags)
      h0out = h
    end subroutine damped

    subroutine finish(h, r)
      real(dp), intent(in) :: h, r
      logical :: again
      integer :: unsettled
      real(dp) :: r_unsettled
      again = g%h0 /= h
      ! (a loose trial's sectors are solved to their own tolerance at the answer)
      if (present(ring)) then
        if (ring%loosened) loose_answers_solved = loose_answers_solved + 1
        again = again .or. ring%loosened
      end if
      if (again) then
        resid = residual(c, lp, g, mem, h, ring)  ! leave the film solved at h
      else
        resid = r
      end if
      ! (a distorted bore's sector whose cavitation set or pressure-viscosity loop did not
      ! settle at the answer: solved once more there, from the films just solved)
      unsettled = 0
      r_unsettled = resid
      if (present(ring)) unsettled = iand(g%flags, flag_viscosity + flag_cavitation)
      if (unsettled /= 0) resid = residual(c, lp, g, mem, h, ring)
      h0out = h
      if (abs(resid) > c%load_tol .and. flags == 0) then
        ! the load is outside load_tol (4); an answer within it with a film not settled, whose
        ! settled films then carry a load beyond it, keeps the unsettled film's flag (16, 8)
        ! beside it: the balance was met only before the film settled
        flags = flag_load
        if (unsettled /= 0 .and. abs(r_unsettled) <= c%load_tol) flags = ior(flag_load, unsettled)
      end if
      flags = ior(flags, g%flags)
      ! remember the local slope for the next crank step's first trial (from two trials
      ! of this step: trials of two steps differ in time as well as in h0)
      if (mem%trials >= 2 .and. mem%y_hist(1) /= mem%y_hist(2)) then
        if ((mem%g_hist(2) - mem%g_hist(1)) / (mem%y_hist(2) - mem%y_hist(1)) < 0.0_dp) &
          mem%slope = (mem%g_hist(2) - mem%g_hist(1)) / (mem%y_hist(2) - mem%y_hist(1))
      end if
    end subroutine finish

    !> Brent's method (inverse quadratic / secant steps, bisection safeguard).
    subroutine brent(a0, b0, fa0, fb0)
      real(dp), intent(in) :: a0, b0, fa0, fb0
      real(dp) :: a, b, cc, fa, fb, fc, d, e, tol1, xm, p, q, r, s
      integer :: iter
      a = a0; b = b0; fa = fa0; fb = fb0
      cc = a; fc = fa; d = b - a; e = d
      do iter = 1, c%max_load_iterations
        if (sign(1.0_dp, fb) == sign(1.0_dp, fc)) then
          cc = a; fc = fa; d = b - a; e = d
        end if
        if (abs(fc) < abs(fb)) then
          a = b; b = cc; cc = a
          fa = fb; fb = fc; fc = fa
        end if
        tol1 = 2.0_dp * epsilon(1.0_dp) * abs(b) + 1e-15_dp
        xm = 0.5_dp * (cc - b)
        if (abs(fb) <= c%load_tol .or. abs(xm) <= tol1) exit
        if (abs(e) >= tol1 .and. abs(fa) > abs(fb)) then
          s = fb / fa
          if (a == cc) then
            p = 2.0_dp * xm * s
            q = 1.0_dp - s
          else
            q = fa / fc
            r = fb / fc
            p = s * (2.0_dp * xm * q * (q - r) - (b - a) * (r - 1.0_dp))
            q = (q - 1.0_dp) * (r - 1.0_dp) * (s - 1.0_dp)
          end if
          if (p > 0.0_dp) q = -q
          p = abs(p)
          if (2.0_dp * p < min(3.0_dp * xm * q - abs(tol1 * q), abs(e * q))) then
            e = d
            d = p / q
          else
            d = xm
            e = d
          end if
        else
          d = xm
          e = d
        end if
        a = b
        fa = fb
        if (abs(d) > tol1) then
          b = b + d
        else
          b = b + sign(tol1, xm)
        end if
        fb = residual(c, lp, g, mem, exp(b), ring, loose)
      end do
      call finish(exp(b), fb)
    end subroutine brent
  end subroutine find_h0
end module ringlube_load_balance
