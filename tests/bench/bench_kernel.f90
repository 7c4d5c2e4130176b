!> Kernel benchmark (not a test; built with the ctest programs, run by `make bench`).
!>
!>   bench_kernel DECK [OVERRIDES [REPEATS]]
!>
!> Runs DECK (with OVERRIDES, deck text such as "&numerics preset='fast' /") REPEATS
!> times (default 5) and prints one line of key=value pairs: the best kernel time per run
!> and per computed cycle (CPU time of the process), the energy loss, mixed share, film solves and Reynolds
!> (Thomas) solves per run, the number of crank steps computed, and the film solves of the
!> reported cycle for the lift-off margin (not in film_solves). With a distorted bore a last
!> line gives the sectors' film solves of the last run by phase of its crank steps (all its
!> cycles; ringlube_sectors' phase counters): ring_solve accepted, refused, the root finder's
!> trials and the lift-off margin's solves, their calls, and ring_solve's refusals by reason;
!> and another the root finder's film solves at the refused steps by the refusal's reason, of
!> them those at the steps held at a bound, and the refusals not converged whose line search
!> found no descent; and another the root finder's trials at the ceiling: their count, film
!> solves, Newton iterations and those whose Newton iteration missed; and another the refused
!> steps whose answer (the root finder's) moves a sector by more than ring_solve's limit from
!> the last step, by the refusal's reason: in ln h0, against the ring's mean move, and of the
!> first those whose last step or answer is at the ceiling. Then a line per flagged
!> step of the last run: its index, crank angle, h0 and flags (the bits of /cycle/flags).
!> With RINGLUBE_ACCEPT_JUMPS=1 in the environment ring_solve accepts an answer that moves a
!> sector by more than its limit (ringlube_sectors' accept_jumps: the answers move); with
!> RINGLUBE_LOOSE_TRIALS=0 the root finder's trials at a step ring_solve did not take solve
!> their sectors to their own tolerance (ringlube_sectors' loose_trials off: the answers move);
!> with RINGLUBE_RING_SOLVE_CAP=n ring_solve's Newton iteration takes at most n iterations
!> (ringlube_sectors' max_free, 12 without it; the answers move); with RINGLUBE_JUMP_EXIT=x
!> ring_solve's iteration ends once a sector is more than x in ln h0 from the last step and
!> moving away (ringlube_sectors' jump_exit, 0.35 without it; 0: off); with
!> RINGLUBE_RELATIVE_JUMP=1 both measure a sector's move against the ring's mean move
!> (ringlube_sectors' relative_jump: the answers move).
!> For a distorted bore with `&numerics threads` > 1: RINGLUBE_TEAM_ALWAYS=1 makes the steps a
!> team whatever the load average (ringlube_sectors' team_busy_check off: the team's cost on a
!> loaded machine), RINGLUBE_REGION_PER_STEP=1 makes each crank step its own parallel region
!> instead of one per cycle (ringlube_cycle_state's cycle_regions off); wall_ms_per_run is
!> the wall time of the run of the best CPU time.
!>
!>   bench_kernel --micro [NODES]
!>
!> The roofline pieces alone at NODES (default 51): one Thomas solve, one Roelands
!> evaluation of every node, and one film solve of the cold deck at a mid-stroke crank
!> step, each timed over many repetitions (best of 5 batches), in ns.
program bench_kernel
  use ringlube_kinds, only: dp, pi
  use ringlube_error, only: error_type
  use ringlube_case, only: case_type, elastic_pressure
  use ringlube_deck, only: read_deck_text
  use ringlube_fsys, only: dir_prefix
  use ringlube_cycle, only: solve_cycle
  use ringlube_results, only: result_type, si_film_solves, sc_cycles_computed, sc_energy_loss, &
                              sc_mixed_share, sc_total_film_solves, sc_reynolds_solves, &
                              sc_converged, sc_margin_film_solves, si_flags, s_crank_angle_deg, &
                              s_h0
  use ringlube_tridiag, only: thomas
  use ringlube_viscosity, only: roelands_eta
  use ringlube_film, only: film_type, film_setup, film_evaluate
  use ringlube_greenwood_tripp, only: gt_init
  use ringlube_textio, only: read_text_file, itoa
  use ringlube_sectors, only: phase_solves, phase_calls, solve_failures, accept_jumps, &
                              loose_trials, ceiling_trials, max_free, jump_exit, &
                              refused_solves, refused_held_solves, stalled_failures, &
                              relative_jump, refused_far, &
                              team_busy_check
  use ringlube_cycle_state, only: cycle_regions
  use omp_lib, only: omp_get_wtime
  use, intrinsic :: iso_fortran_env, only: output_unit
  implicit none
  character(len=4096) :: arg
  character(len=:), allocatable :: deck, overrides
  integer :: repeats, nodes

  call get_command_argument(1, arg)
  if (trim(arg) == '--micro') then
    nodes = 51
    if (command_argument_count() >= 2) then
      call get_command_argument(2, arg)
      read (arg, *) nodes
    end if
    call micro(nodes)
    stop
  end if
  deck = trim(arg)
  overrides = ''
  repeats = 5
  if (command_argument_count() >= 2) then
    call get_command_argument(2, arg)
    overrides = trim(arg)
  end if
  if (command_argument_count() >= 3) then
    call get_command_argument(3, arg)
    read (arg, *) repeats
  end if
  call whole_run(deck, overrides, repeats)

contains

  !> Process CPU time [s] (the machine is shared: CPU time is steadier than wall time).
  real(dp) function now()
    call cpu_time(now)
  end function now

  subroutine load(path, ovr, c)
    character(len=*), intent(in) :: path, ovr
    type(case_type), intent(out) :: c
    type(error_type), allocatable :: err
    character(len=:), allocatable :: text
    call read_text_file(path, text, err)
    if (allocated(err)) error stop 'cannot read the deck'
    call read_deck_text(text, path, dir_prefix(path), c, err, ovr, 'overrides')
    if (allocated(err)) then
      write (output_unit, '(a)') err%message
      error stop 1
    end if
  end subroutine load

  subroutine whole_run(path, ovr, nrep)
    character(len=*), intent(in) :: path, ovr
    integer, intent(in) :: nrep
    type(case_type) :: c
    type(result_type) :: res
    type(error_type), allocatable :: err
    real(dp) :: t0, best, w0, wall
    integer :: i, k
    character(len=8) :: env
    call load(path, ovr, c)
    call get_environment_variable('RINGLUBE_ACCEPT_JUMPS', env)
    accept_jumps = trim(env) == '1'
    call get_environment_variable('RINGLUBE_LOOSE_TRIALS', env)
    loose_trials = trim(env) /= '0'
    call get_environment_variable('RINGLUBE_RING_SOLVE_CAP', env)
    if (len_trim(env) > 0) read (env, *) max_free
    call get_environment_variable('RINGLUBE_JUMP_EXIT', env)
    if (len_trim(env) > 0) read (env, *) jump_exit
    call get_environment_variable('RINGLUBE_RELATIVE_JUMP', env)
    relative_jump = trim(env) == '1'
    call get_environment_variable('RINGLUBE_TEAM_ALWAYS', env)
    team_busy_check = trim(env) /= '1'
    call get_environment_variable('RINGLUBE_REGION_PER_STEP', env)
    cycle_regions = trim(env) /= '1'
    best = huge(1.0_dp)
    wall = 0.0_dp
    do i = 1, nrep
      phase_solves = 0
      phase_calls = 0
      solve_failures = 0
      refused_solves = 0
      refused_held_solves = 0
      stalled_failures = 0
      ceiling_trials = 0
      refused_far = 0
      t0 = now()
      w0 = omp_get_wtime()
      call solve_cycle(c, res, err)
      if (now() - t0 < best) wall = omp_get_wtime() - w0
      best = min(best, now() - t0)
      if (allocated(err)) error stop 'run failed'
    end do
    associate (v => res%scalars, film_solves => res%int_series(:, si_film_solves))
      write (output_unit, &
             '(2(a, f0.3), a, es14.7, a, f0.3, 2(a, i0), a, f0.3, 3(a, i0), a, f0.3)') &
        'ms_per_run=', best * 1e3_dp, ' ms_per_cycle=', best * 1e3_dp / v(sc_cycles_computed), &
        ' energy=', v(sc_energy_loss), ' mixed=', v(sc_mixed_share), &
        ' film_solves=', nint(v(sc_total_film_solves)), &
        ' reynolds_solves=', nint(v(sc_reynolds_solves)), &
        ' cycles_computed=', v(sc_cycles_computed), ' steps=', res%nsteps, &
        ' converged=', nint(v(sc_converged)), &
        ' margin_film_solves=', nint(v(sc_margin_film_solves)), ' wall_ms_per_run=', wall * 1e3_dp
      write (output_unit, '(a, 4(1x, i0))') &
        'steps of the reported cycle with 1, 2, 3, >= 4 film solves:', &
        count(film_solves == 1), count(film_solves == 2), count(film_solves == 3), &
        count(film_solves >= 4)
      if (sum(phase_calls) > 0) write (output_unit, '(a, 4(1x, i0), a, 4(1x, i0), a, 4(1x, i0))') &
        'sector film solves by phase (ring_solve accepted, refused, root finder, margin):', &
        phase_solves, ' calls:', phase_calls, &
        ' refusals (not converged, bound, jump, light):', solve_failures
      if (sum(phase_calls) > 0) write (output_unit, '(a, 4(1x, i0), a, 4(1x, i0), a, i0)') &
        'root finder film solves by refusal (not converged, bound, jump, light):', &
        refused_solves, ' held at a bound:', refused_held_solves, &
        ' not converged with a stalled line search: ', stalled_failures
      if (sum(phase_calls) > 0) write (output_unit, '(a, 4(1x, i0))') &
        'root finder trials at the ceiling (trials, film solves, iterations, missed):', &
        ceiling_trials
      if (sum(phase_calls) > 0) write (output_unit, '(a, 3(4(1x, i0), a))') &
        'refused steps whose answer moves a sector beyond the limit (not converged, bound, '// &
        'jump, light):', refused_far(:, 1), ' against the ring''s mean move:', &
        refused_far(:, 2), ' of the first at the ceiling:', refused_far(:, 3), ''
      do k = 1, size(res%int_series, 1)
        if (res%int_series(k, si_flags) == 0) cycle
        write (output_unit, '(a, i0, a, f0.2, a, es10.3, a, i0)') 'flagged step ', k, &
          ' crank_angle_deg=', res%series(k, s_crank_angle_deg), ' h0=', &
          res%series(k, s_h0), ' flags=', res%int_series(k, si_flags)
      end do
    end associate
  end subroutine whole_run

  subroutine micro(n)
    integer, intent(in) :: n
    type(case_type) :: c
    type(film_type) :: f
    real(dp) :: a(n), b(n), cc(n), d(n), x(n), p(n), eta(n), t0, tt, tv, tf, sink
    integer :: i, k, rep, info, nrep
    call load('inputs/crf450r_4000rpm_full_cold.nml', &
              '&numerics nodes = '//itoa(n)//' /', c)
    call gt_init()
    call film_setup(c, f)
    ! a Reynolds-like M-matrix system
    do i = 1, n
      a(i) = -1.0_dp - 0.1_dp * sin(real(i, dp))
      cc(i) = -1.0_dp - 0.1_dp * cos(real(i, dp))
      b(i) = -(a(i) + cc(i)) + 1e-3_dp
      d(i) = 1.0_dp
    end do
    nrep = 200000
    sink = 0.0_dp
    tt = huge(1.0_dp)
    do rep = 1, 5
      t0 = now()
      do k = 1, nrep
        d(1) = 1.0_dp + 1e-9_dp * k
        call thomas(a, b, cc, d, x, info)
        sink = sink + x(n / 2)
      end do
      tt = min(tt, (now() - t0) / nrep)
    end do
    ! Roelands at every node, ring-like pressures 0.1-6 MPa
    do i = 1, n
      p(i) = 1e5_dp + 6e6_dp * sin(pi * (i - 1) / (n - 1))**2
    end do
    tv = huge(1.0_dp)
    do rep = 1, 5
      t0 = now()
      do k = 1, nrep
        p(1) = 1e5_dp + k
        eta = roelands_eta(f%law, p)
        sink = sink + eta(n / 2)
      end do
      tv = min(tv, (now() - t0) / nrep)
    end do
    ! film solves at mid-stroke (u = -10 m/s, 2 bar in the chamber), warm-started as in
    ! the load balance: trials alternate between h0 = 3 sigma and 1 % above it
    f%film_solves = 0
    f%reynolds_solves = 0
    tf = huge(1.0_dp)
    nrep = 20000
    do rep = 1, 5
      t0 = now()
      do k = 1, nrep
        call film_evaluate(c, f, 3.0_dp * f%sigma * (1.0_dp + 0.01_dp * mod(k, 2)), 0.0_dp, &
                           -10.0_dp, 2e5_dp, &
                           c%load_tol * (elastic_pressure(c) + 2e5_dp) * c%width * f%circ)
        sink = sink + f%wh
      end do
      tf = min(tf, (now() - t0) / nrep)
    end do
    write (output_unit, '(a, i0, a, f0.1, a, f0.1, a, f0.1, a, f0.2, a, i0, a, es9.2)') &
      'nodes=', n, ' thomas_ns=', tt * 1e9_dp, ' roelands_all_nodes_ns=', tv * 1e9_dp, &
      ' film_solve_ns=', tf * 1e9_dp, ' reynolds_per_film_solve=', &
      real(f%reynolds_solves, dp) / f%film_solves, ' film_solves=', f%film_solves, ' sink=', sink
  end subroutine micro
end program bench_kernel
