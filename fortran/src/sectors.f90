!> The ring on a distorted bore (docs/bore.md): a film per sector of the circumference,
!> coupled through the ring's bending and its rigid-body modes.
!>
!> At a crank step `ring_solve` finds the ring's mean position c, the centre's translation
!> (x_c, y_c) and the sectors together: one Newton iteration on the M + 3 unknowns, the load
!> balance mean W = (p_e + p_back) b the last equation. Where it does not apply or fails (no
!> or a uniform distortion, a light sector at the last step, lift-off or the floor, a Newton
!> iteration that stalls or jumps a sector by more than max_jump), the load balance's root
!> finder on c (ringlube_load_balance, the round bore's) takes over, and for each trial c
!> `ring_evaluate` solves the sectors' films together with the centre's translation:
!>
!>   h0_j = c - x_c cos(theta_j) - y_c sin(theta_j) + D_j + [C (W - mean W)]_j,
!>   sum_j (W_j - mean W) cos(theta_j) = sum_j (W_j - mean W) sin(theta_j) = 0,
!>
!> W_j the load per unit circumference the film of sector j carries at h0_j (hydrodynamic +
!> asperity), D_j the bore's distortion there, C the ring's compliance on the sectors
!> (ringlube_bore: the orders 2..M/2 of the load bend the ring; -C [W] is its deflection), and
!> returns the mean load: the load balance then sets mean W = (p_e + p_back) b. A trial at
!> back_clearance (the ring pushed off the liner into its groove) holds x_c = y_c = 0 instead
!> of the two lateral equations: the groove's root stops the ring's translation
!> (sector_trial's pinned). At a step that
!> ring_solve did not take, a trial far from the root is loose: its sectors' Newton iteration
!> ends once their residuals are within loose_share of its load residual (stall_share after a
!> line search without descent), for the root finder takes only that residual's sign and size
!> from it; near the root and at a bound they are solved to their own tolerance. The M + 2
!> unknowns (ln h0_j, x_c, y_c), M + 3 with ln c, are found by Newton's method with a dense
!> LAPACK solve; each sector's dW_j/dh0_j is a secant kept from its last two films (a film's
!> load depends on its own h0 only, so the Jacobian is exact up to these slopes). With zero distortion every
!> sector's film is the round bore's and the first trial already satisfies the equations:
!> the ring's answer is the round bore's bit for bit (means are taken as w_1 + mean(w - w_1),
!> exact for equal values). The sectors' films are independent within an iteration and are
!> solved in parallel threads (OpenMP, `&numerics threads`): inside a crank step's parallel
!> region (ringlube_cycle_state, advance_ring) the step runs on thread 0 and hands each pass
!> over the sectors to the team as a job (team_post, team_claim, team_done, team_join),
!> outside one a pass is a parallel loop of its own.
module ringlube_sectors
  use ringlube_kinds, only: dp
  use ringlube_case, only: case_type
  use ringlube_film, only: film_type, film_evaluate, film_copy
  use ringlube_bore, only: bore_type, bore_setup
  use ringlube_results, only: flag_sectors
  use, intrinsic :: iso_c_binding, only: c_int, c_double
!$ use omp_lib, only: omp_lock_kind, omp_init_lock, omp_set_lock, omp_unset_lock, omp_get_wtime, &
!$                   omp_get_thread_num, omp_get_num_procs
  implicit none
  private
  public :: sector_ring, sector_trial, ring_setup, ring_evaluate, ring_solve, ring_accept, &
            exact_mean, ring_loads, ring_ceiling, ring_coupled, free_mean_position
  public :: team_begin, team_size_is, team_end, team_post, team_wait, team_claim, team_done, &
            team_join, team_sectors, job_caller, job_none, team_spin, team_busy_check, &
            team_busy_every, team_busy_checks, team_wanted, team_pause
  public :: n_phases, phase_solves, phase_calls, solve_failures, accept_jumps, loose_trials
  public :: refused_solves, refused_held_solves, stalled_failures, last_refusal
  public :: ceiling_trials, bound_rtol, max_free, jump_exit, relative_jump, refused_far, &
            count_refused_answer

  !> Newton iterations of the sectors at one trial at most
  integer, parameter :: max_inner = 40
  !> Newton iterations of ring_solve (the mean position an unknown too) at most, before the
  !> outer root finder takes over (a switch for benchmarks: tests/bench/bench_kernel with
  !> RINGLUBE_RING_SOLVE_CAP=n; other values move the answers)
  integer, save :: max_free = 12
  !> Solve the mean position with the sectors (ring_solve) where ring_coupled; .false.: the
  !> root finder on the mean position alone (for tests and benchmarks that compare the two)
  logical, save :: free_mean_position = .true.
  !> ring_solve only after a step whose every sector carried this share of the mean load
  real(dp), parameter :: light_share = 0.25_dp
  !> ring_solve's answer only where no sector's h0 moved by more than this in ln from the last step
  real(dp), parameter :: max_jump = 0.25_dp
  !> .true.: ring_solve accepts an answer that moves a sector by more than max_jump (a switch
  !> for benchmarks, off: tests/bench/bench_kernel with RINGLUBE_ACCEPT_JUMPS=1; the answers
  !> move)
  logical, save :: accept_jumps = .false.
  !> ring_solve's Newton iteration ends, refused as a jump, once a sector's ln h0 is more than
  !> this from the last step's and still moving away (the answer would be refused as a jump
  !> or not converge: the iterations it skips are wasted). Above max_jump, so that an
  !> iteration that swings out and back still converges: on the shipped decks and the
  !> variants of tests/bench/identical.py every answer is the same to the bit, with 3-4 % fewer
  !> film solves on the 12,000 r/min deck's mass-conserving films. (0: off, for tests and
  !> benchmarks: tests/bench/bench_kernel with RINGLUBE_JUMP_EXIT=x. Without "still moving
  !> away" the answers moved: identical.py's distorted_starved variant no longer settled.)
  real(dp), save :: jump_exit = 0.35_dp
  !> .true.: a sector's move from the last step (max_jump, jump_exit) is measured against the
  !> ring's mean move, the mean of the sectors' changes of ln h0, as `sector_jumps` counts a
  !> jump: the whole ring moving (off the ceiling, towards the liner) is then no sector's jump.
  !> A switch for benchmarks, off (tests/bench/bench_kernel with RINGLUBE_RELATIVE_JUMP=1; the
  !> answers move: on the shipped 12,000 r/min deck most of its refusals as a jump, and most of
  !> ring_solve's stalled line searches, are at steps where the ring moves as a whole)
  logical, save :: relative_jump = .false.
  !> .true.: the root finder's trials at a step that ring_solve did not take are loose
  !> (sector_trial's loose); .false. (a switch for benchmarks: tests/bench/bench_kernel with
  !> RINGLUBE_LOOSE_TRIALS=0) every trial's sectors are solved to their own tolerance
  logical, save :: loose_trials = .true.
  !> largest change of a sector's ln h0 per Newton step
  real(dp), parameter :: max_dlog = 0.5_dp
  !> a loose trial of the root finder (sector_trial's loose) ends once its sectors' residuals
  !> are within this share of the load residual |mean W - q| / q over load_tol (or within
  !> their own tolerance, whichever is looser). (0.3 took 23 instead of 28 film solves per
  !> sector and refused step on the shipped 12,000 r/min deck's flooded film, but moved its
  !> starved film's energy by about -7e-4 on the mean of runs at load_tol 0.97e-3 .. 1.03e-3,
  !> beyond the spread that load_tol alone gives it (standard deviation 5.5e-4): the root
  !> finder then picked other states of its sectors; at 0.1 the mean stays, +4e-5.)
  real(dp), parameter :: loose_share = 0.1_dp
  !> ... or, after a line search without descent, within the load residual over load_tol
  !> (the next iterations would crawl: the residual's sign is what the root finder needs)
  real(dp), parameter :: stall_share = 1.0_dp
  !> a trial's mean position within this relative distance of a bound is at that bound (a
  !> loose trial's then solved to the sectors' own tolerance, loose_enough; a trial at the
  !> ceiling counted, at back_clearance held on the groove's root; the balance's re-solve of a
  !> missed trial strictly between the bounds): the root finder's trial at a bound,
  !> exp(ln bound), lies within round-off of it (exp(ln 1e-9) is 6e-25 m above 1e-9 m)
  real(dp), parameter :: bound_rtol = 1e-12_dp
  !> Newton iterations at most of the lift-off margin's second attempt at the ceiling
  !> (ring_ceiling: with the films' secants of either sign)
  integer, parameter :: ceiling_signed_iterations = 12

  !> Benchmark counters (tests/bench/bench_kernel prints them; not results), summed over the
  !> process's runs until the caller sets them to 0: the sectors' film solves and the calls of
  !> each phase of a distorted bore's crank steps: 1 ring_solve accepted, 2 ring_solve not
  !> accepted (the root finder then takes the step), 3 the root finder's trials
  !> (ring_evaluate), 4 the lift-off margin's solves at the ceiling (ring_ceiling); and
  !> ring_solve's refusals by their first reason: 1 not converged (max_free iterations, a line
  !> search without descent, a singular Jacobian), 2 the mean position at a bound, 3 a sector
  !> moved by more than max_jump (or, the iteration ended early, beyond jump_exit and moving
  !> away), 4 a light sector. (Only the thread that runs a step counts.)
  integer, parameter :: n_phases = 4
  integer, save :: phase_solves(n_phases) = 0, phase_calls(n_phases) = 0, solve_failures(4) = 0
  !> ... and by the reason of the step's refusal (as solve_failures'; set by the load
  !> balance, ringlube_load_balance): the root finder's film solves at such steps, of which at
  !> the steps it held at a bound (the floor or the ceiling: lift-off); of the refusals not
  !> converged, those whose line search found no descent (the others: max_free iterations or a
  !> singular Jacobian); and the reason of the last refusal (0: the last ring_solve accepted)
  integer, save :: refused_solves(4) = 0, refused_held_solves(4) = 0, stalled_failures = 0, &
                   last_refusal = 0
  !> ... and the root finder's trials at the ceiling (ring_evaluate): 1 trials, 2 their film
  !> solves, 3 their Newton iterations, 4 those whose Newton iteration missed
  integer, save :: ceiling_trials(4) = 0
  !> ... and by the reason of the step's refusal, the refused steps whose answer (the root
  !> finder's) moved a sector by more than max_jump from the last step: (:, 1) in ln h0, (:, 2)
  !> against the ring's mean move (relative_jump's measure), (:, 3) those of (:, 1) whose last
  !> step or answer is at the ceiling (count_refused_answer)
  integer, save :: refused_far(4, 3) = 0

  !> The sectors' films and what the next trial and step start from.
  type :: sector_ring
    type(bore_type) :: bore
    !> the films of the sectors (each its own state: content, warm starts)
    type(film_type), allocatable :: films(:)
    !> h0_j of the last evaluation [m]; the last three accepted steps' (3, M), most recent first
    real(dp), allocatable :: h(:), hist(:, :)
    !> the last evaluation was a loose trial that ended before its sectors met their own
    !> tolerance (sector_trial's loose)
    logical :: loosened = .false.
    !> the distortion at the step's position [m]
    real(dp), allocatable :: d(:)
    !> load per unit circumference of each sector at the last evaluation [N/m], its slope
    !> dW_j/dh0_j [N/m per m] (0: not known yet), and the deflection term C (W - mean W) [m]
    real(dp), allocatable :: w(:), slope(:), u(:)
    !> the centre's translation [m] and the mean position of the last evaluation (0: none)
    real(dp) :: xc = 0.0_dp, yc = 0.0_dp, c_last = 0.0_dp
    !> the mean position of the last two accepted steps, how many steps were accepted, and
    !> whether the next evaluation is a step's first
    real(dp) :: chist(2) = 0.0_dp
    !> the sectors' loads at the last two accepted steps [N/m] (2, M)
    real(dp), allocatable :: whist(:, :)
    integer :: steps = 0
    logical :: fresh = .true.
    !> Newton iterations over the run, and trials whose sectors missed the tolerance
    integer :: iterations = 0, missed = 0
    !> the last solve at the ceiling (ring_ceiling, the lift-off margin's): its mean position
    !> (0: none yet), centre, sectors' h0, loads and slopes, and each sector's film iterate
    !> there (pressure, viscosity, fill: (nodes, M))
    real(dp) :: ceil_c = 0.0_dp, ceil_xc = 0.0_dp, ceil_yc = 0.0_dp
    real(dp), allocatable :: ceil_h(:), ceil_w(:), ceil_slope(:)
    real(dp), allocatable :: ceil_p(:, :), ceil_eta(:, :), ceil_theta(:, :)
    !> the films of ring_ceiling's copy of the ring, kept between its calls for their arrays
    !> (film_copy; their values are the copy's, set anew at each call)
    type(film_type), allocatable :: ceil_films(:)
    !> the state ring_solve restores where it fails: the sectors' h0, loads, slopes and
    !> deflection (4, M), centre and mean position, and each sector's film iterate (pressure,
    !> viscosity, fill: (nodes, M))
    real(dp), allocatable :: sv(:, :), sv_p(:, :), sv_eta(:, :), sv_theta(:, :)
    real(dp) :: sv_xc = 0.0_dp, sv_yc = 0.0_dp, sv_c = 0.0_dp
    logical :: sv_fresh = .true.
  end type sector_ring

  !> One trial of the mean position: cc [m]; the squeeze term's scheme sq_a (1: Euler, 1.5:
  !> BDF2, on each sector's own history) and the step dt [s]; the sliding speed u, the chamber
  !> edge's pressure, the applied load [N, as a whole ring] and the bounds of every h0_j (set
  !> by the caller); the films' load tolerance [N], the load per unit circumference q, the
  !> first harmonic's tolerance [N/m] and the circumference (set by ring_evaluate).
  type :: sector_trial
    real(dp) :: cc = 0.0_dp, sq_a = 1.0_dp, dt = 0.0_dp, u = 0.0_dp, p_chamber = 0.0_dp, &
                load = 0.0_dp, floor = 0.0_dp, ceiling = 0.0_dp
    real(dp) :: w_tol = 0.0_dp, q = 0.0_dp, tol_f = 0.0_dp, circ = 0.0_dp
    !> free: the mean position cc is an unknown of the Newton iteration as well (ring_solve),
    !> between the bounds cc_floor and cc_ceiling; dres_dlnc: at its solution, the derivative
    !> of the relative load residual (mean W - q) / q against ln cc with the sectors solved
    !> (the outer root finder's slope; 0: not known)
    logical :: free = .false.
    real(dp) :: cc_floor = 0.0_dp, cc_ceiling = 0.0_dp, dres_dlnc = 0.0_dp
    !> Newton iterations at most (0: max_inner, or max_free with free); signed_slopes: each
    !> sector's slope is the secant of its film's load over the last step whatever its sign
    !> (ring_ceiling's second attempt); else only a falling secant is kept (update_slopes)
    integer :: max_iterations = 0
    logical :: signed_slopes = .false.
    !> loose: a root finder's trial far from its root, strictly between cc_floor and
    !> cc_ceiling, may end its sectors' Newton iteration at a tolerance loosened in proportion
    !> to its load residual (loose_share; stall_share after a line search without descent):
    !> its residual's sign and size are all the root finder takes from it; near the root
    !> (within load_tol / loose_share) and at a bound the tolerance is the sectors' own
    logical :: loose = .false.
    !> pinned: the mean position is at back_clearance (the ring pushed off the liner into its
    !> groove: the root finder's trial at the ceiling, the lift-off margin's solve there), where
    !> the groove's root, concentric with the piston, stops the ring's translation: the centre
    !> is held at 0 and the groove carries the lateral force (the two lateral equations are
    !> dropped). A ring slid sideways at that mean position would put the sectors on one side
    !> beyond the groove's root. (Set by newton_solve.)
    logical :: pinned = .false.
  end type sector_trial

  !> The team of a crank step's parallel region (ringlube_cycle_state, advance_ring): thread 0
  !> runs the step and posts a job for each pass over the sectors (a pass of their films, or
  !> the step's per-sector work before and after the balance); every thread claims sectors
  !> one at a time (a light or starved sector's film costs more) and counts itself done when
  !> none is left; thread 0 waits for the count (the other threads' last sector, a film solve
  !> at most). Between the jobs of a step the other threads wait for the next one reading the
  !> job count for a while (thread 0's Newton arithmetic between two passes takes some
  !> microseconds), then go to sleep at a barrier, where thread 0's next post meets them
  !> (team_wait, team_post): a pass wakes no sleeping thread unless thread 0 took longer than
  !> that. The while is team_spin at most, halved after each wait that ended asleep and
  !> team_spin again after one that did not; none (asleep at once) after a wait during which
  !> the waiting thread lost its core to another process for more than half the wait (a loaded
  !> machine: a thread waiting awake then takes CPU time from the others, and the threads of
  !> the team are off their cores for milliseconds at a time), with a wait of team_spin every
  !> spin_probe waits to find out whether the machine is quiet again. Thread 0 waiting longer
  !> than team_spin for the count marks the machine loaded too: the threads then wait asleep
  !> (but for the probes) and end each job at a barrier, until a probe keeps its core. On a
  !> busy machine (load average over the last minute above its cores plus a half:
  !> check_busy) there is no team (team_wanted). One region at a time: a kernel call holds
  !> Python's lock for its whole run. The job and the counters are shared by the team; only
  !> thread 0 writes the job, between passes.
  !>
  !> job_none: no job; job_films: the films of team_ring at the trial team_tr;
  !> job_ceiling_in, _out: the films of the lift-off margin's copy team_copy of team_ring from
  !> it and its last iterates at the ceiling back (ring_ceiling); from job_caller on the
  !> caller's own.
  integer, parameter :: job_none = 0, job_films = 1, job_ceiling_in = 2, job_ceiling_out = 3, &
                        job_caller = 10
  !> how long [s] a thread of the team waits for the next job awake before it sleeps, at most;
  !> 0: it sleeps at once (every pass then wakes it, as a parallel loop per pass would)
  real(dp), save :: team_spin = 100e-6_dp
  !> every spin_probe-th wait of a thread waits team_spin awake whatever its last waits did
  integer, parameter :: spin_probe = 16
  !> per thread, the time it waits awake next [s] and its waits so far ((line / 2, 0:n-1))
  real(dp), allocatable, save :: team_budget(:, :)
  !> the job, the next sector to claim, the threads done, the team's size, jobs posted in the
  !> region, threads asleep at the barrier for the next job, and whether the last post meets
  !> them there
  integer, save :: team_job = job_none, team_size = 1, team_finished = 0, team_gen = 0, &
                   team_sleepers = 0
  !> the threads asked for: thread t owns the sectors t m / n + 1 .. (t + 1) m / n of a job
  !> (its films stay in its core's caches from pass to pass), and once none of its own is left
  !> takes the next thread's (a light or starved sector's film costs more)
  integer, save :: team_ranges = 1
  !> per owner, the sectors of its range claimed so far (one cache line each: (line, 0:n-1))
  integer, parameter :: line = 16
  integer, allocatable, save :: team_next(:, :)
  logical, save :: team_active = .false., team_meet = .false., team_lock_made = .false.
  !> a thread of the team lost its core during its last wait awake (1; else 0: the machine
  !> looks quiet), and whether the threads end the current job at a barrier (set by team_post
  !> from it: on a loaded machine thread 0 then waits for the others asleep, not reading the
  !> count)
  integer, save :: team_loaded = 0
  logical, save :: team_bar = .false.
  !> the machine is busy: its load average over the last minute above its cores plus a half
  !> (checked by team_wanted every busy_check seconds; when it was last checked, -1: not yet):
  !> a step is then no team
  logical, save :: team_busy = .false.
  real(dp), save :: team_busy_checked = -1.0_dp
  !> check the load average (.false.: the machine is taken for quiet; for tests that make the
  !> team's threads wait awake whatever else runs)
  logical, save :: team_busy_check = .true.
  !> with team_busy_check .false., for tests of a team held over a cycle: > 0 takes the machine
  !> for busy at every other run of team_busy_every load checks (0: quiet all along)
  integer, save :: team_busy_every = 0
  !> the load checks counted with team_busy_every
  integer, save :: team_busy_checks = 0
  real(dp), parameter :: busy_check = 0.5_dp
!$ integer(omp_lock_kind), save :: team_lock
  type(case_type), pointer, save :: team_case => null()
  type(sector_ring), pointer, save :: team_ring => null(), team_copy => null()
  type(sector_trial), save :: team_tr

  !> The Newton iteration's arrays: residuals, Jacobian (LU after dgetf2), direction, pivots,
  !> its status, the merit of the last residuals, and the state before the last step.
  type :: newton_work
    real(dp), allocatable :: r(:), a(:, :), b(:), dy(:), h_old(:), w_old(:)
    integer, allocatable :: ipiv(:)
    integer :: info = 0
    real(dp) :: merit = 0.0_dp
    !> the last step's line search found no descent
    logical :: stalled = .false.
  end type newton_work

  interface
    !> POSIX: the calling thread gives its core to another that is ready to run
    integer(c_int) function c_sched_yield() bind(c, name='sched_yield')
      import :: c_int
    end function c_sched_yield
    !> the system's load averages (POSIX getloadavg): the first n of them, how many it gave
    integer(c_int) function c_getloadavg(loads, n) bind(c, name='getloadavg')
      import :: c_int, c_double
      real(c_double), intent(out) :: loads(*)
      integer(c_int), value :: n
    end function c_getloadavg
    !> CPU time the calling thread has used [s] (fsys.c; 0 without the clock)
    real(c_double) function c_thread_cpu() bind(c, name='rl_thread_cpu_seconds')
      import :: c_double
    end function c_thread_cpu
  end interface

contains

  !> The ring of case c whose every sector starts from the film f (set up, at h0_start).
  subroutine ring_setup(c, f, h0_start, ring)
    type(case_type), intent(in) :: c
    type(film_type), intent(in) :: f
    real(dp), intent(in) :: h0_start
    type(sector_ring), intent(out) :: ring
    integer :: m, j
    call bore_setup(c, ring%bore)
    m = ring%bore%m
    allocate (ring%films(m), ring%h(m), ring%hist(3, m), ring%d(m), ring%w(m), ring%slope(m), &
              ring%u(m))
    do j = 1, m
      ring%films(j) = f
      ring%films(j)%gas_channel = .true.
    end do
    ring%h = h0_start
    ring%hist = h0_start
    ring%d = 0.0_dp
    ring%w = 0.0_dp
    ring%slope = 0.0_dp
    ring%u = 0.0_dp
  end subroutine ring_setup

  !> The mean of x, w_1 + mean(x - x_1): exactly x_1 when every value equals it.
  pure real(dp) function exact_mean(x) result(m)
    real(dp), intent(in) :: x(:)
    m = x(1) + sum(x - x(1)) / size(x)
  end function exact_mean

  !> Solve the sectors for the trial mean position tr%cc (see the module's description) and
  !> leave the films solved there; g is the ring's summary film: its edge state (leading
  !> edge, gas pressures) is given to every sector, and it receives the trial's h0, the mean
  !> loads (as a whole ring: N), the union of the sectors' flags and their solve counts.
  subroutine ring_evaluate(c, ring, g, tr)
    type(case_type), intent(in) :: c
    type(sector_ring), intent(inout) :: ring
    type(film_type), intent(inout) :: g
    type(sector_trial), intent(inout) :: tr
    logical :: done, root_trial, at_ceiling
    integer :: nfs, its
    nfs = sum(ring%films%film_solves)
    its = ring%iterations
    ! (the root finder's trial; ring_ceiling counts its own)
    root_trial = .not. tr%signed_slopes .and. tr%max_iterations == 0
    ! (exp(ln ceiling): within round-off of it)
    at_ceiling = root_trial .and. tr%cc_ceiling > 0.0_dp .and. &
                 tr%cc >= tr%cc_ceiling * (1.0_dp - bound_rtol)
    call newton_solve(c, ring, g, tr, done)
    if (at_ceiling) then
      ceiling_trials(1) = ceiling_trials(1) + 1
      ceiling_trials(2) = ceiling_trials(2) + sum(ring%films%film_solves) - nfs
      ceiling_trials(3) = ceiling_trials(3) + ring%iterations - its
      if (.not. done) ceiling_trials(4) = ceiling_trials(4) + 1
    end if
    if (root_trial) then
      phase_calls(3) = phase_calls(3) + 1
      phase_solves(3) = phase_solves(3) + sum(ring%films%film_solves) - nfs
    end if
  end subroutine ring_evaluate

  !> Solve the sectors and the mean position together: the equations of ring_evaluate and the
  !> load balance (mean W = q, within load_tol relative, as the outer root finder's residual),
  !> M + 3 unknowns (ln h0_j, x_c, y_c, ln cc), by one Newton iteration from tr%cc (the load
  !> balance's first trial), cc kept within [tr%cc_floor, tr%cc_ceiling]. ok: converged with cc
  !> strictly inside them; tr%cc is then the step's mean position, the films are solved there,
  !> and tr%dres_dlnc is the load residual's slope against ln cc with the sectors solved. Not
  !> ok (the mean position reaches a bound: a ring held at the floor or lifted off; a Newton
  !> iteration that stalls; a sector beyond jump_exit from the last step and moving away): the
  !> sectors and their films' iterates are restored as they were (the film solves stay counted
  !> in g), and the caller's root finder on cc takes over from there as without this solve.
  subroutine ring_solve(c, ring, g, tr, ok)
    type(case_type), intent(in) :: c
    type(sector_ring), intent(inout) :: ring
    type(film_type), intent(inout) :: g
    type(sector_trial), intent(inout) :: tr
    logical, intent(out) :: ok
    integer :: nfs, reason, phase
    logical :: stalled, jumped
    nfs = sum(ring%films%film_solves)
    call save_state(ring)
    tr%free = .true.
    tr%dres_dlnc = 0.0_dp
    call newton_solve(c, ring, g, tr, ok, stalled, jumped)
    reason = 0
    if (jumped) then
      reason = 3
    else if (.not. ok) then
      reason = 1
    else if (tr%cc <= tr%cc_floor .or. tr%cc >= tr%cc_ceiling) then
      reason = 2
    else if (ring%steps >= 1) then
      if (sector_jump(ring, relative_jump) > max_jump .and. .not. accept_jumps) then
        reason = 3
      else if (minval(ring%w) <= light_share * exact_mean(ring%w)) then
        reason = 4
      end if
    end if
    ok = reason == 0
    tr%free = .false.
    if (.not. ok) call restore_state(ring)
    phase = 1
    last_refusal = reason
    if (.not. ok) then
      phase = 2
      solve_failures(reason) = solve_failures(reason) + 1
      if (reason == 1 .and. stalled) stalled_failures = stalled_failures + 1
    end if
    phase_calls(phase) = phase_calls(phase) + 1
    phase_solves(phase) = phase_solves(phase) + sum(ring%films%film_solves) - nfs
  end subroutine ring_solve

  !> The largest change of a sector's ln h0 from the last accepted step; relative: less the
  !> ring's mean change (the mean of the sectors' changes of ln h0).
  pure real(dp) function sector_jump(ring, relative) result(j)
    type(sector_ring), intent(in) :: ring
    logical, intent(in) :: relative
    real(dp) :: dl(size(ring%h))
    dl = log(ring%h / ring%hist(1, :))
    if (relative) dl = dl - sum(dl) / size(dl)
    j = maxval(abs(dl))
  end function sector_jump

  !> Benchmark counters (refused_far) at a step ring_solve refused for last_refusal, the ring
  !> at the root finder's answer (before ring_accept); ceil: the last step or the answer at the
  !> ceiling.
  subroutine count_refused_answer(ring, ceil)
    type(sector_ring), intent(in) :: ring
    logical, intent(in) :: ceil
    if (last_refusal == 0 .or. ring%steps < 1) return
    if (sector_jump(ring, .false.) > max_jump) then
      refused_far(last_refusal, 1) = refused_far(last_refusal, 1) + 1
      if (ceil) refused_far(last_refusal, 3) = refused_far(last_refusal, 3) + 1
    end if
    if (sector_jump(ring, .true.) > max_jump) &
      refused_far(last_refusal, 2) = refused_far(last_refusal, 2) + 1
  end subroutine count_refused_answer

  !> Keep what ring_solve changes (the sectors' state and their films' iterates).
  subroutine save_state(ring)
    type(sector_ring), intent(inout) :: ring
    integer :: j, m
    m = ring%bore%m
    if (.not. allocated(ring%sv)) allocate (ring%sv(4, m))
    call fit(ring%sv_p, size(ring%films(1)%p))
    call fit(ring%sv_eta, size(ring%films(1)%eta))
    if (ring%films(1)%jfo) call fit(ring%sv_theta, size(ring%films(1)%theta))
    ring%sv(1, :) = ring%h
    ring%sv(2, :) = ring%w
    ring%sv(3, :) = ring%slope
    ring%sv(4, :) = ring%u
    ring%sv_xc = ring%xc
    ring%sv_yc = ring%yc
    ring%sv_c = ring%c_last
    ring%sv_fresh = ring%fresh
    do j = 1, m
      ring%sv_p(:, j) = ring%films(j)%p
      ring%sv_eta(:, j) = ring%films(j)%eta
      if (ring%films(j)%jfo) ring%sv_theta(:, j) = ring%films(j)%theta
    end do

  contains

    !> a (n, M), allocated anew where it is not that shape
    subroutine fit(a, n)
      real(dp), allocatable, intent(inout) :: a(:, :)
      integer, intent(in) :: n
      if (allocated(a)) then
        if (size(a, 1) == n .and. size(a, 2) == m) return
        deallocate (a)
      end if
      allocate (a(n, m))
    end subroutine fit
  end subroutine save_state

  !> Back to the state save_state kept.
  subroutine restore_state(ring)
    type(sector_ring), intent(inout) :: ring
    integer :: j
    ring%h = ring%sv(1, :)
    ring%w = ring%sv(2, :)
    ring%slope = ring%sv(3, :)
    ring%u = ring%sv(4, :)
    ring%xc = ring%sv_xc
    ring%yc = ring%sv_yc
    ring%c_last = ring%sv_c
    ring%fresh = ring%sv_fresh
    do j = 1, ring%bore%m
      ring%films(j)%p = ring%sv_p(:, j)
      ring%films(j)%eta = ring%sv_eta(:, j)
      if (ring%films(j)%jfo) ring%films(j)%theta = ring%sv_theta(:, j)
    end do
  end subroutine restore_state

  !> The step's mean position is solved with the sectors (ring_solve): free_mean_position, the
  !> distortion at the step is not uniform (orders other than 0 present; a uniform one, no
  !> distortion or order 0 alone, keeps every sector at one h0: the round bore's root finder,
  !> bit for bit), and every sector carried at least light_share of the mean load at the last
  !> step (a light sector's film may have an open and a closed state: the root finder
  !> continues from the last state).
  pure logical function ring_coupled(ring)
    type(sector_ring), intent(in) :: ring
    ring_coupled = free_mean_position .and. maxval(ring%d) > minval(ring%d)
    if (.not. ring_coupled .or. ring%steps < 1) return
    ring_coupled = minval(ring%whist(1, :)) > light_share * exact_mean(ring%whist(1, :))
  end function ring_coupled

  !> The Newton iteration of ring_evaluate (tr%free: of ring_solve); done: converged;
  !> stalled: its last line search found no descent.
  subroutine newton_solve(c, ring, g, tr, done, stalled, jumped)
    type(case_type), intent(in) :: c
    type(sector_ring), intent(inout) :: ring
    type(film_type), intent(inout) :: g
    type(sector_trial), intent(inout) :: tr
    logical, intent(out) :: done
    logical, intent(out), optional :: stalled, jumped
    logical :: jump
    real(dp) :: jmax, jprev
    type(newton_work) :: nw
    integer :: it, j, nfs, nrs, max_it
    logical :: loosened
    nfs = sum(ring%films%film_solves)
    nrs = sum(ring%films%reynolds_solves)
    do j = 1, ring%bore%m
      ring%films(j)%lead_left = g%lead_left
      ring%films(j)%p_back = g%p_back
      ring%films(j)%p_lower = g%p_lower
    end do
    ! (exp(ln back_clearance): within round-off of it)
    tr%pinned = .not. tr%free .and. tr%cc >= c%back_clearance * (1.0_dp - bound_rtol)
    call trial_setup(c, ring, g, tr, nw)
    call first_guess(c, ring, tr, nw)
    call solve_films(c, ring, tr)
    call residuals(c, ring, tr, nw%r, nw%merit, done)
    loosened = loose_enough(c, ring, tr, nw, done)
    done = done .or. loosened
    jump = .false.
    jprev = huge(1.0_dp)
    max_it = max_inner
    if (tr%max_iterations > 0) max_it = tr%max_iterations
    if (tr%free) max_it = max_free
    do it = 1, max_it
      if (done) exit
      call newton_direction(ring, tr, nw)
      if (nw%info /= 0) exit
      if (step_within_tolerance(c, ring, tr, nw)) then
        done = .true.
        exit
      end if
      ring%iterations = ring%iterations + 1
      call take_step(c, ring, tr, nw, done)
      call update_slopes(ring, tr, nw)
      loosened = loose_enough(c, ring, tr, nw, done)
      done = done .or. loosened
      ! (a free mean position at a bound: the caller's root finder holds it there; a line
      ! search without descent: the root finder takes the step)
      if (tr%free .and. (tr%cc <= tr%cc_floor .or. tr%cc >= tr%cc_ceiling .or. nw%stalled)) exit
      ! (a sector beyond jump_exit from the last step and moving away: ring_solve would refuse
      ! the answer)
      if (tr%free .and. .not. done .and. jump_exit > 0.0_dp .and. ring%steps >= 1 .and. &
          .not. accept_jumps) then
        jmax = sector_jump(ring, relative_jump)
        jump = jmax > jump_exit .and. jmax > jprev
        if (jump) exit
        jprev = jmax
      end if
    end do
    ring%c_last = tr%cc
    ring%loosened = loosened
    if (present(stalled)) stalled = nw%stalled
    if (present(jumped)) jumped = jump
    if (tr%free .and. done) call total_slope(ring, tr, nw)
    if (.not. done .and. .not. tr%free) ring%missed = ring%missed + 1
    call summarise(ring, g, tr, nfs, nrs, done .or. tr%free)
  end subroutine newton_solve

  !> A loose trial (tr%loose, strictly between its bounds) whose sectors are not within their
  !> own tolerance (done: they are) but within loose_share of its load residual over load_tol.
  !> (The root finder's trial at a bound is exp(ln bound), within round-off of it: a trial
  !> within bound_rtol of a bound is at it.)
  pure logical function loose_enough(c, ring, tr, nw, done) result(ok)
    type(case_type), intent(in) :: c
    type(sector_ring), intent(in) :: ring
    type(sector_trial), intent(in) :: tr
    type(newton_work), intent(in) :: nw
    logical, intent(in) :: done
    real(dp) :: r_out
    ok = .false.
    if (done .or. .not. tr%loose .or. tr%free) return
    if (tr%cc <= tr%cc_floor * (1.0_dp + bound_rtol) .or. &
        tr%cc >= tr%cc_ceiling * (1.0_dp - bound_rtol)) return
    r_out = (exact_mean(ring%w) * tr%circ - tr%load) / max(tr%load, 1e-3_dp)
    ok = nw%merit <= loose_share * abs(r_out) / c%load_tol
    if (nw%stalled) ok = ok .or. nw%merit <= stall_share * abs(r_out) / c%load_tol
  end function loose_enough

  !> tr%dres_dlnc: the Jacobian of the M + 3 equations solved for a unit change of the load
  !> residual, whose ln cc component is 1 / (d residual / d ln cc) with the sectors solved.
  subroutine total_slope(ring, tr, nw)
    type(sector_ring), intent(in) :: ring
    type(sector_trial), intent(inout) :: tr
    type(newton_work), intent(inout) :: nw
    integer :: n
    n = ring%bore%m + 3
    nw%r = 0.0_dp
    nw%r(n) = -1.0_dp
    call newton_direction(ring, tr, nw)
    if (nw%info == 0 .and. nw%b(n) /= 0.0_dp) tr%dres_dlnc = 1.0_dp / nw%b(n)
  end subroutine total_slope

  !> The trial's tolerances (the films' load tolerance as the round film's, the load per
  !> unit circumference the balance asks for, the first harmonic's tolerance) and the Newton
  !> iteration's arrays.
  pure subroutine trial_setup(c, ring, g, tr, nw)
    type(case_type), intent(in) :: c
    type(sector_ring), intent(in) :: ring
    type(film_type), intent(in) :: g
    type(sector_trial), intent(inout) :: tr
    type(newton_work), intent(out) :: nw
    integer :: m, n
    m = ring%bore%m
    tr%w_tol = c%load_tol * max(tr%load, 1e-3_dp)
    tr%q = max(tr%load, 1e-3_dp) / g%circ
    tr%tol_f = 0.5_dp * m * tr%q * c%load_tol
    tr%circ = g%circ
    n = m + 2
    if (tr%free) n = m + 3
    allocate (nw%r(n), nw%a(n, n), nw%b(n), nw%dy(m), nw%ipiv(n), nw%h_old(m), nw%w_old(m))
  end subroutine trial_setup

  !> The first trial: the last evaluation's sectors moved with the mean position (at a step's
  !> first trial: each sector's h0 extrapolated from its last steps, moved like the mean
  !> position's extrapolation, and the loads extrapolated too); where that puts a sector below
  !> the floor (a trial far below the last), the last sectors scaled to cc. Then one Newton
  !> step on the films' linear models about the last evaluation (no film solve; none where
  !> the first trial already satisfies them, as without distortion).
  subroutine first_guess(c, ring, tr, nw)
    type(case_type), intent(in) :: c
    type(sector_ring), intent(inout) :: ring
    type(sector_trial), intent(inout) :: tr
    type(newton_work), intent(inout) :: nw
    real(dp) :: h_prev(ring%bore%m), guess(ring%bore%m), t
    logical :: have_prev, done
    h_prev = ring%h
    have_prev = ring%c_last > 0.0_dp
    if (ring%fresh .and. ring%steps >= 2) then
      guess = tr%cc + (predicted(ring%hist(1, :), ring%hist(2, :)) &
                       - predicted(ring%chist(1), ring%chist(2)))
      h_prev = predicted(ring%hist(1, :), ring%hist(2, :))
      ring%w = 2.0_dp * ring%whist(1, :) - ring%whist(2, :)
    else if (ring%c_last > 0.0_dp) then
      guess = tr%cc + (ring%h - ring%c_last)
    else
      guess = tr%cc - ring%xc * ring%bore%cos1 - ring%yc * ring%bore%sin1 + ring%d + ring%u
    end if
    ring%fresh = .false.
    if (any(guess < tr%floor) .and. ring%c_last > 0.0_dp) then
      ring%h = min(max(ring%h * (tr%cc / ring%c_last), tr%floor), tr%ceiling)
      ring%xc = ring%xc * (tr%cc / ring%c_last)
      ring%yc = ring%yc * (tr%cc / ring%c_last)
    else
      ring%h = min(max(guess, tr%floor), tr%ceiling)
    end if
    if (tr%pinned) then
      ! (the sectors' translation taken out: the centre held at 0)
      ring%h = min(max(ring%h + ring%xc * ring%bore%cos1 + ring%yc * ring%bore%sin1, tr%floor), &
                   tr%ceiling)
      ring%xc = 0.0_dp
      ring%yc = 0.0_dp
    end if
    ring%c_last = tr%cc
    if (.not. have_prev) return
    ring%w = ring%w + ring%slope * (ring%h - h_prev)
    call deflection(ring)
    call residuals(c, ring, tr, nw%r, nw%merit, done)
    if (done) return
    call newton_direction(ring, tr, nw)
    if (nw%info /= 0) return
    t = step_length(ring, tr, nw)
    ring%h = min(max(ring%h * exp(t * nw%dy), tr%floor), tr%ceiling)
    ring%xc = ring%xc + t * nw%b(ring%bore%m + 1)
    ring%yc = ring%yc + t * nw%b(ring%bore%m + 2)
    if (tr%free) tr%cc = free_cc(ring, tr, nw, t, tr%cc)
  end subroutine first_guess

  !> The Newton step's length: ln h0 (and ln cc) changed by at most max_dlog.
  pure real(dp) function step_length(ring, tr, nw) result(t)
    type(sector_ring), intent(in) :: ring
    type(sector_trial), intent(in) :: tr
    type(newton_work), intent(in) :: nw
    real(dp) :: big
    big = maxval(abs(nw%dy))
    if (tr%free) big = max(big, abs(nw%b(ring%bore%m + 3)))
    t = min(1.0_dp, max_dlog / max(big, tiny(1.0_dp)))
  end function step_length

  !> The mean position after a step t of the Newton direction from cc0, within its bounds.
  pure real(dp) function free_cc(ring, tr, nw, t, cc0) result(cc)
    type(sector_ring), intent(in) :: ring
    type(sector_trial), intent(in) :: tr
    type(newton_work), intent(in) :: nw
    real(dp), intent(in) :: t, cc0
    cc = min(max(cc0 * exp(t * nw%b(ring%bore%m + 3)), tr%cc_floor), tr%cc_ceiling)
  end function free_cc

  !> The ring's load at the ceiling for the lift-off margin (ringlube_load_balance, margins):
  !> ring_evaluate at tr%cc on a copy of the ring (the step's own is left alone; g is the
  !> summary film's copy). The copy starts from the last such solve, kept in the ring (the
  !> sectors' h0, centre, loads and slopes, and their films' iterates), not from the step's
  !> sectors near the liner: the ceiling's solution changes little from step to step, while
  !> from the step's sectors, two orders of magnitude below it, Newton's method took 4-5 film
  !> solves per sector and, where the sectors' loads at the ceiling differ by half the mean
  !> load (the starved decks' intake stroke), up to its 40 iterations.
  !>
  !> At the ceiling a flooded film's load can rise with its h0 (the face's pressure, not the
  !> wedge, carries it: d ln W / d ln h0 about +0.01 on the shipped 4000 r/min deck's flooded
  !> film), where the balance's Newton keeps only falling secants (update_slopes): there its
  !> steps move the centre the wrong way and crawl, without converging in its 40 iterations,
  !> towards another root where the ring has slid sideways by the whole clearance (a sector
  !> at a few um from the liner, the opposite ones at twice the groove's clearance), reached
  !> at steps decided by the tolerance and round-off. So where that solve misses, a second
  !> starts from the same state with each film's secant of either sign (at most
  !> ceiling_signed_iterations) and converges to the root continued from the last solve;
  !> where it misses too (a starved film's secants are noisier than its load's change), the
  !> first attempt's result stands, as before. At back_clearance the slid root is no longer
  !> one: the centre is held at 0 there (sector_trial's pinned); the second attempt stays
  !> for where the first still misses.
  subroutine ring_ceiling(c, ring, g, tr)
    type(case_type), intent(in) :: c
    type(sector_ring), intent(inout) :: ring
    type(film_type), intent(inout) :: g
    type(sector_trial), intent(inout) :: tr
    type(sector_ring), target :: rc
    type(sector_ring) :: first
    type(film_type) :: g_first
    type(film_type), allocatable :: films(:), ceil_films(:)
    integer :: m, missed, nfs, solves
    m = ring%bore%m
    ! (the films copied sector by sector, each by the thread that owns the sector in a team,
    ! into the arrays of the last call's copy)
    call move_alloc(ring%films, films)
    call move_alloc(ring%ceil_films, ceil_films)
    rc = ring
    call move_alloc(films, ring%films)
    call move_alloc(ceil_films, rc%films)
    if (.not. allocated(rc%films)) allocate (rc%films(m))
    call ceiling_start(c, ring, rc)
    missed = rc%missed
    tr%max_iterations = max_inner
    tr%signed_slopes = .false.
    nfs = sum(rc%films%film_solves)
    call ring_evaluate(c, rc, g, tr)
    phase_solves(4) = phase_solves(4) + sum(rc%films%film_solves) - nfs
    if (rc%missed > missed) then
      ! (the first attempt is kept for where the second misses as well)
      first = rc
      g_first = g
      call ceiling_start(c, ring, rc)
      tr%max_iterations = ceiling_signed_iterations
      tr%signed_slopes = .true.
      nfs = sum(rc%films%film_solves)
      call ring_evaluate(c, rc, g, tr)
      phase_solves(4) = phase_solves(4) + sum(rc%films%film_solves) - nfs
      if (rc%missed > missed + 1) then
        solves = g%film_solves
        rc = first
        g = g_first
        g%film_solves = solves
      end if
    end if
    phase_calls(4) = phase_calls(4) + 1
    ring%ceil_c = rc%c_last
    ring%ceil_xc = rc%xc
    ring%ceil_yc = rc%yc
    ring%ceil_h = rc%h
    ring%ceil_w = rc%w
    ring%ceil_slope = rc%slope
    if (.not. allocated(ring%ceil_p)) then
      allocate (ring%ceil_p(rc%films(1)%n, m), ring%ceil_eta(rc%films(1)%n, m))
      allocate (ring%ceil_theta(rc%films(1)%n, m))
      ring%ceil_theta = 1.0_dp
    end if
    call sectors_job(c, ring, rc, job_ceiling_out)
    call move_alloc(rc%films, ring%ceil_films)
  end subroutine ring_ceiling

  !> The start of ring_ceiling's solve on the copy rc of ring: the last solve at the ceiling
  !> (if any; else the ring's own last evaluation), and the films' iterates there.
  subroutine ceiling_start(c, ring, rc)
    type(case_type), intent(in) :: c
    type(sector_ring), intent(inout) :: ring, rc
    if (ring%ceil_c > 0.0_dp) then
      rc%c_last = ring%ceil_c
      rc%xc = ring%ceil_xc
      rc%yc = ring%ceil_yc
      rc%h = ring%ceil_h
      rc%w = ring%ceil_w
      rc%slope = ring%ceil_slope
      rc%fresh = .false.
    else
      rc%c_last = ring%c_last
      rc%xc = ring%xc
      rc%yc = ring%yc
      rc%h = ring%h
      rc%w = ring%w
      rc%slope = ring%slope
      rc%fresh = ring%fresh
    end if
    call sectors_job(c, ring, rc, job_ceiling_in)
  end subroutine ceiling_start

  !> Every sector's film at its h0 (its own squeeze term), the loads W_j and the deflection:
  !> in a crank step's team a job for it (thread 0's call), else a parallel loop.
  subroutine solve_films(c, ring, tr)
    type(case_type), intent(in), target :: c
    type(sector_ring), intent(inout), target :: ring
    type(sector_trial), intent(in) :: tr
    integer :: jj
    if (team_active) then
      team_tr = tr
      call sectors_job(c, ring, ring, job_films)
    else
      !$omp parallel do private(jj) schedule(dynamic) if (c%threads > 1) &
      !$omp num_threads(c%threads)
      do jj = 1, ring%bore%m
        call solve_film(c, ring, tr, jj)
      end do
      !$omp end parallel do
    end if
    ring%w = (ring%films%wh + ring%films%wa) / tr%circ
    call deflection(ring)
    ! a first slope: the hydrodynamic film's W ~ 1/h0^2 (the secants refine it)
    if (tr%signed_slopes) then
      where (ring%slope == 0.0_dp) ring%slope = -2.0_dp * max(ring%w, tr%q) / ring%h
    else
      where (ring%slope >= 0.0_dp) ring%slope = -2.0_dp * max(ring%w, tr%q) / ring%h
    end if
  end subroutine solve_films

  !> A pass of `job` over the sectors of ring (job_films: its films at team_tr; the ceiling's
  !> copies: between ring and its copy rc): the team's job in a crank step's team (thread 0's
  !> call), else a loop.
  subroutine sectors_job(c, ring, rc, job)
    type(case_type), intent(in), target :: c
    type(sector_ring), intent(inout), target :: ring, rc
    integer, intent(in) :: job
    integer :: jj
    team_case => c
    team_ring => ring
    team_copy => rc
    if (team_active) then
      call team_post(job)
      call team_sectors()
      call team_join()
    else
      do jj = 1, ring%bore%m
        call sector_work(job, jj)
      end do
    end if
    nullify (team_case, team_ring, team_copy)
  end subroutine sectors_job

  !> Sector jj's part of `job` (on team_case, team_ring, team_copy).
  subroutine sector_work(job, jj)
    integer, intent(in) :: job, jj
    select case (job)
    case (job_films)
      call solve_film(team_case, team_ring, team_tr, jj)
    case (job_ceiling_in)
      ! the ceiling's copy of the sector's film, from its last iterate there (if any)
      associate (fc => team_copy%films(jj))
        call film_copy(fc, team_ring%films(jj))
        if (team_ring%ceil_c > 0.0_dp) then
          fc%p = team_ring%ceil_p(:, jj)
          fc%eta = team_ring%ceil_eta(:, jj)
          if (fc%jfo) fc%theta = team_ring%ceil_theta(:, jj)
        end if
      end associate
    case (job_ceiling_out)
      associate (fc => team_copy%films(jj))
        team_ring%ceil_p(:, jj) = fc%p
        team_ring%ceil_eta(:, jj) = fc%eta
        if (fc%jfo) team_ring%ceil_theta(:, jj) = fc%theta
      end associate
    end select
  end subroutine sector_work

  !> Sector jj's film at its h0 with its own squeeze term.
  subroutine solve_film(c, ring, tr, jj)
    type(case_type), intent(in) :: c
    type(sector_ring), intent(inout) :: ring
    type(sector_trial), intent(in) :: tr
    integer, intent(in) :: jj
    real(dp) :: sq, sq_b
    sq = 0.0_dp
    if (c%squeeze) then
      if (tr%sq_a == 1.0_dp) then
        sq_b = ring%hist(1, jj)
      else
        sq_b = 2.0_dp * ring%hist(1, jj) - 0.5_dp * ring%hist(2, jj)
      end if
      sq = 2.0_dp * (tr%sq_a * ring%h(jj) - sq_b) / tr%dt
    end if
    call film_evaluate(c, ring%films(jj), ring%h(jj), sq, tr%u, tr%p_chamber, tr%w_tol)
  end subroutine solve_film

  !> A thread's share of a job of ringlube_sectors (job_films, job_ceiling_in or _out): the
  !> sectors it claims, then counted done.
  subroutine team_sectors()
    integer :: jj
    do while (team_claim(team_ring%bore%m, jj))
      call sector_work(team_job, jj)
    end do
    call team_done()
  end subroutine team_sectors

  !> Before a crank step's parallel region of `threads` threads: its team starts with the
  !> first job (every thread of the region's start takes its share of the caller's per-sector
  !> work at once), and every pass over the sectors of thread 0's calls becomes a job of the
  !> team until team_end.
  subroutine team_begin(threads)
    integer, intent(in) :: threads
    team_job = job_none
    if (allocated(team_next)) then
      if (size(team_next, 2) /= threads) deallocate (team_next, team_budget)
    end if
    if (.not. allocated(team_next)) then
      allocate (team_next(line, 0:threads - 1), team_budget(line / 2, 0:threads - 1))
      team_budget(1, :) = team_spin
      team_budget(2, :) = 0.0_dp
    end if
    team_next = 0
    team_ranges = threads
    team_finished = 0
    team_size = 1
    team_gen = 0
    team_sleepers = 0
    team_meet = .false.
    team_bar = .false.
    if (.not. team_lock_made) then
!$    call omp_init_lock(team_lock)
      team_lock_made = .true.
    end if
    team_active = .true.
  end subroutine team_begin

  !> Thread 0, at the region's start: the team has `threads` threads (the number it got).
  subroutine team_size_is(threads)
    integer, intent(in) :: threads
    team_size = threads
  end subroutine team_size_is

  !> Thread 0 of a team held over several steps: its passes over the sectors are its own
  !> (paused: the other threads keep waiting for the next job) or the team's jobs again.
  subroutine team_pause(paused)
    logical, intent(in) :: paused
    team_active = .not. paused
  end subroutine team_pause

  !> After the region: no team.
  subroutine team_end()
    team_active = .false.
    team_size = 1
  end subroutine team_end

  !> Thread 0: post `job` to the team (the threads asleep at the barrier are met there); then
  !> it takes its own share (team_claim until none is left, team_done) and team_join.
  subroutine team_post(job)
    integer, intent(in) :: job
    logical :: meet
    integer :: loaded
    team_job = job
    team_next(1, :) = 0
    team_finished = 0
!$  call omp_set_lock(team_lock)
    meet = team_sleepers > 0
    team_meet = meet
    !$omp atomic read
    loaded = team_loaded
    !$omp end atomic
    team_bar = loaded == 1
    team_sleepers = 0
    !$omp flush
    !$omp atomic update
    team_gen = team_gen + 1
    !$omp end atomic
!$  call omp_unset_lock(team_lock)
    if (meet) then
      !$omp barrier
    end if
  end subroutine team_post

  !> The other threads: wait for thread 0's next job after the `seen` first (reading the job
  !> count for the thread's time awake, then asleep at the barrier of team_post) and return it.
  integer function team_wait(seen) result(job)
    integer, intent(inout) :: seen
    integer :: g, spins, me, loaded
    logical :: met
    real(dp) :: t0, awake, cpu0, wall
    me = 0
!$  me = omp_get_thread_num()
    team_budget(2, me) = team_budget(2, me) + 1.0_dp
    awake = team_budget(1, me)
    !$omp atomic read
    loaded = team_loaded
    !$omp end atomic
    if (loaded == 1) awake = 0.0_dp
    if (mod(nint(team_budget(2, me)), spin_probe) == 0) awake = team_spin
    met = .false.
    spins = 0
    t0 = -1.0_dp
    cpu0 = -1.0_dp
    if (awake > 0.0_dp) then
      t0 = wall_clock()
      cpu0 = c_thread_cpu()
    end if
    do
      !$omp atomic read
      g = team_gen
      !$omp end atomic
      if (g /= seen) exit
      spins = spins + 1
      if (mod(spins, 64) /= 0 .or. met) cycle
      if (t0 >= 0.0_dp) then
        if (wall_clock() - t0 < awake) cycle
      end if
      ! no job yet: asleep at the barrier, where thread 0's next post (which sees the count of
      ! sleepers under the lock) meets this thread
!$    call omp_set_lock(team_lock)
      !$omp atomic read
      g = team_gen
      !$omp end atomic
      if (g == seen) then
        team_sleepers = team_sleepers + 1
!$      call omp_unset_lock(team_lock)
        !$omp barrier
        met = .true.
      else
!$      call omp_unset_lock(team_lock)
      end if
    end do
    ! (asleep: half the time awake next; else team_spin; none after a wait awake that lost the
    ! core for more than half of it)
    team_budget(1, me) = team_spin
    if (met) team_budget(1, me) = 0.5_dp * awake
    if (cpu0 >= 0.0_dp .and. .not. met) then
      wall = wall_clock() - t0
      if (c_thread_cpu() - cpu0 < 0.5_dp * wall) then
        team_budget(1, me) = 0.0_dp
        !$omp atomic write
        team_loaded = 1
        !$omp end atomic
      else
        !$omp atomic write
        team_loaded = 0
        !$omp end atomic
      end if
    end if
    !$omp flush
    ! (another thread slept: the post meets every thread at the barrier)
    if (team_meet .and. .not. met) then
      !$omp barrier
    end if
    seen = g
    job = team_job
  end function team_wait

  !> A crank step of `threads` threads runs as a team (a parallel region of its own, thread 0
  !> leading): more than one thread asked for and the machine not busy (check_busy). On a busy
  !> machine a pass over the sectors' films is a parallel loop of its own, the rest of the
  !> step serial: with threads asleep between passes, the team's cheap jobs (the inlets, the
  !> work after the balance, the lift-off margin's copies) cost more wake-ups than they gain.
  logical function team_wanted(threads)
    integer, intent(in) :: threads
    team_wanted = .false.
    if (threads <= 1) return
    call check_busy()
    team_wanted = .not. team_busy
  end function team_wanted

  !> team_busy from the load average over the last minute, every busy_check seconds.
  subroutine check_busy()
    real(c_double) :: loads(1)
    real(dp) :: now
    integer :: procs
    if (.not. team_busy_check) then
      team_busy = .false.
      if (team_busy_every > 0) then
        team_busy = mod(team_busy_checks / team_busy_every, 2) == 1
        team_busy_checks = team_busy_checks + 1
      end if
      return
    end if
    now = wall_clock()
    if (team_busy_checked >= 0.0_dp .and. now - team_busy_checked < busy_check) return
    team_busy_checked = now
    procs = 1
!$  procs = omp_get_num_procs()
    if (c_getloadavg(loads, 1_c_int) == 1) team_busy = loads(1) > procs + 0.5_dp
  end subroutine check_busy

  !> Seconds of a wall clock (OpenMP's; 0 without it).
  real(dp) function wall_clock()
    wall_clock = 0.0_dp
!$  wall_clock = omp_get_wtime()
  end function wall_clock

  !> Claim the next sector of a job over m sectors: j, .false. when none is left (the
  !> calling thread's own range first, then the next threads').
  logical function team_claim(m, j) result(got)
    integer, intent(in) :: m
    integer, intent(out) :: j
    integer :: me, t, k, i, lo, hi
    me = 0
!$  me = omp_get_thread_num()
    got = .false.
    do i = 0, team_ranges - 1
      t = mod(me + i, team_ranges)
      lo = t * m / team_ranges + 1
      hi = (t + 1) * m / team_ranges
      !$omp atomic read
      k = team_next(1, t)
      !$omp end atomic
      if (k >= hi - lo + 1) cycle
      !$omp atomic capture
      team_next(1, t) = team_next(1, t) + 1
      k = team_next(1, t)
      !$omp end atomic
      j = lo + k - 1
      got = j <= hi
      if (got) return
    end do
  end function team_claim

  !> This thread has finished its share of the job (its results are flushed first); with
  !> team_bar it waits for the others at a barrier.
  subroutine team_done()
    logical :: bar
    ! (read before the count: once it is full thread 0 may post the next job)
    bar = team_bar
    !$omp flush
    !$omp atomic update
    team_finished = team_finished + 1
    !$omp end atomic
    if (bar) then
      !$omp barrier
    end if
  end subroutine team_done

  !> Thread 0: wait until every thread of the team has finished its share (they are working:
  !> at most the last claimed sector's solve), reading the count; then every result is seen.
  subroutine team_join()
    integer :: n, spins
    integer(c_int) :: r
    real(dp) :: t0
    spins = 0
    t0 = -1.0_dp
    do
      !$omp atomic read
      n = team_finished
      !$omp end atomic
      if (n >= team_size) exit
      spins = spins + 1
      if (mod(spins, 64) /= 0) cycle
      if (t0 < 0.0_dp) t0 = wall_clock()
      if (wall_clock() - t0 < team_spin) cycle
      ! (a long wait: the thread that has the last sector is not running; unless it was asleep
      ! when the job was posted (its wake-up takes that long) the machine looks loaded: give
      ! way to it, and the next jobs end at a barrier)
      if (.not. team_meet) then
        !$omp atomic write
        team_loaded = 1
        !$omp end atomic
      end if
      r = c_sched_yield()
    end do
    !$omp flush
  end subroutine team_join

  !> u = C (W - mean W) (exactly 0 for equal loads).
  pure subroutine deflection(ring)
    type(sector_ring), intent(inout) :: ring
    ring%u = matmul(ring%bore%cmat, ring%w - exact_mean(ring%w))
  end subroutine deflection

  !> The residuals: the sectors' positions h0_j - (c - x_c cos - y_c sin + D + u)_j (m) and
  !> the first harmonics of the load (N/m, as res(m+1:m+2) relative to M q); mx the largest
  !> of them against its tolerance, ok when all are within it. The positions' orders 2..M/2
  !> are measured as the load that would bend the ring by them (C^+ R): for a ring far more
  !> compliant than the film (order 2) a position error of a nanometre is a negligible load,
  !> for a stiff order a large one, and the load tolerance is load_tol q, as the balance's.
  !> Their orders 0 and 1 (no elastic load) are positions, within 0.1 load_tol of the mean
  !> position.
  pure subroutine residuals(c, ring, tr, res, mx, ok)
    type(case_type), intent(in) :: c
    type(sector_ring), intent(in) :: ring
    type(sector_trial), intent(in) :: tr
    real(dp), intent(out) :: res(:), mx
    logical, intent(out) :: ok
    real(dp) :: wm, fx, fy, rl(ring%bore%m), rg(ring%bore%m), tol_g
    integer :: m
    m = ring%bore%m
    wm = exact_mean(ring%w)
    res(1:m) = ring%h - (tr%cc - ring%xc * ring%bore%cos1 - ring%yc * ring%bore%sin1 + ring%d &
                         + ring%u)
    ! (a sector held at a bound that its position lies beyond has no residual)
    where ((ring%h >= tr%ceiling .and. res(1:m) < 0.0_dp) .or. &
           (ring%h <= tr%floor .and. res(1:m) > 0.0_dp)) res(1:m) = 0.0_dp
    fx = sum((ring%w - wm) * ring%bore%cos1)
    fy = sum((ring%w - wm) * ring%bore%sin1)
    ! (a ring on its groove's root: the groove carries the lateral force)
    if (tr%pinned) then
      fx = 0.0_dp
      fy = 0.0_dp
    end if
    res(m + 1) = fx / (m * tr%q)
    res(m + 2) = fy / (m * tr%q)
    rl = matmul(ring%bore%cinv, res(1:m))
    rg = matmul(ring%bore%p01, res(1:m))
    tol_g = 0.1_dp * c%load_tol * tr%cc
    mx = max(maxval(abs(rl)) / (c%load_tol * tr%q), maxval(abs(rg)) / tol_g, &
             max(abs(fx), abs(fy)) / tr%tol_f)
    if (tr%free) then
      ! the load balance's residual (ringlube_load_balance), from the loads W_j (which the
      ! first guess extrapolates)
      res(m + 3) = (wm * tr%circ - tr%load) / max(tr%load, 1e-3_dp)
      mx = max(mx, abs(res(m + 3)) / c%load_tol)
    end if
    ok = mx <= 1.0_dp .and. .not. tr%free
  end subroutine residuals

  !> The Newton direction (ln h0_j, x_c, y_c) of the residuals nw%r: the Jacobian (exact up to
  !> the sectors' slopes) solved by LAPACK (dgetf2, dgetrs); nw%info its status.
  subroutine newton_direction(ring, tr, nw)
    type(sector_ring), intent(in) :: ring
    type(sector_trial), intent(in) :: tr
    type(newton_work), intent(inout) :: nw
    integer :: l, m, n
    real(dp) :: gl
    m = ring%bore%m
    n = size(nw%r)
    nw%a = 0.0_dp
    do l = 1, m
      gl = ring%slope(l) * ring%h(l)
      nw%a(1:m, l) = -ring%bore%cmat(:, l) * gl
      nw%a(l, l) = nw%a(l, l) + ring%h(l)
      nw%a(m + 1, l) = gl * ring%bore%cos1(l) / (m * tr%q)
      nw%a(m + 2, l) = gl * ring%bore%sin1(l) / (m * tr%q)
      if (tr%free) nw%a(m + 3, l) = gl / (m * tr%q)
    end do
    nw%a(1:m, m + 1) = ring%bore%cos1
    nw%a(1:m, m + 2) = ring%bore%sin1
    if (tr%free) nw%a(1:m, m + 3) = -tr%cc
    if (tr%pinned) then
      ! (the centre held: x_c = y_c = 0 in place of the lateral balance)
      nw%a(m + 1:m + 2, :) = 0.0_dp
      nw%a(m + 1, m + 1) = 1.0_dp
      nw%a(m + 2, m + 2) = 1.0_dp
    end if
    nw%b = -nw%r
    ! (LAPACK's unblocked LU: at these sizes dgesv's blocked, recursive one spends its time in
    ! the calls of its BLAS 3 kernels, a serial part of a threaded run)
    call dgetf2(n, n, nw%a, n, nw%ipiv, nw%info)
    if (nw%info == 0) call dgetrs('N', n, 1, nw%a, n, nw%ipiv, nw%b, n, nw%info)
    nw%dy = nw%b(1:m)
  end subroutine newton_direction

  !> The next step would change no sector's load by more than load_tol q and no h0 by more
  !> than load_tol of itself, and the centre's force is within its tolerance.
  pure logical function step_within_tolerance(c, ring, tr, nw) result(ok)
    type(case_type), intent(in) :: c
    type(sector_ring), intent(in) :: ring
    type(sector_trial), intent(in) :: tr
    type(newton_work), intent(in) :: nw
    integer :: m
    m = ring%bore%m
    ok = maxval(abs(ring%slope * ring%h * nw%dy)) <= c%load_tol * tr%q .and. &
         maxval(abs(nw%dy)) <= c%load_tol .and. &
         maxval(abs(nw%r(m + 1:m + 2))) * m * tr%q <= tr%tol_f
    ! with the mean position free, its own residual too (the load balance checks it)
    if (tr%free) ok = ok .and. abs(nw%r(m + 3)) <= c%load_tol
  end function step_within_tolerance

  !> The Newton step, ln h0 changed by at most max_dlog, halved up to three times while the
  !> residuals grow; the films solved at the step's end.
  subroutine take_step(c, ring, tr, nw, done)
    type(case_type), intent(in) :: c
    type(sector_ring), intent(inout) :: ring
    type(sector_trial), intent(inout) :: tr
    type(newton_work), intent(inout) :: nw
    logical, intent(out) :: done
    real(dp) :: t, xc_old(2), merit_new, cc_old
    integer :: ls, m
    m = ring%bore%m
    t = step_length(ring, tr, nw)
    nw%h_old = ring%h
    nw%w_old = ring%w
    xc_old = [ring%xc, ring%yc]
    cc_old = tr%cc
    do ls = 1, 4
      ring%h = min(max(nw%h_old * exp(t * nw%dy), tr%floor), tr%ceiling)
      ring%xc = xc_old(1) + t * nw%b(m + 1)
      ring%yc = xc_old(2) + t * nw%b(m + 2)
      if (tr%free) tr%cc = free_cc(ring, tr, nw, t, cc_old)
      call solve_films(c, ring, tr)
      call residuals(c, ring, tr, nw%r, merit_new, done)
      if (done .or. merit_new < nw%merit) exit
      t = 0.5_dp * t
    end do
    nw%stalled = .not. done .and. merit_new >= nw%merit
    nw%merit = merit_new
  end subroutine take_step

  !> The secant of each sector's load against its h0 over the last step (kept where it is
  !> not a descent), from a change of load well above a film's own noise, its load
  !> tolerance; a smaller change over a step in h0 bounds the slope's size (an open face's
  !> load hardly depends on its h0).
  pure subroutine update_slopes(ring, tr, nw)
    type(sector_ring), intent(inout) :: ring
    type(sector_trial), intent(in) :: tr
    type(newton_work), intent(in) :: nw
    integer :: j
    do j = 1, ring%bore%m
      if (ring%h(j) == nw%h_old(j)) cycle
      if (tr%signed_slopes) then
        ! (the secant as it is, however small the change: at the ceiling a sector's load
        ! changes by far less than its film's tolerance over a step)
        if (ring%w(j) /= nw%w_old(j)) &
          ring%slope(j) = (ring%w(j) - nw%w_old(j)) / (ring%h(j) - nw%h_old(j))
        cycle
      end if
      if (abs(ring%w(j) - nw%w_old(j)) > tr%w_tol / tr%circ) then
        if ((ring%w(j) - nw%w_old(j)) / (ring%h(j) - nw%h_old(j)) < 0.0_dp) &
          ring%slope(j) = (ring%w(j) - nw%w_old(j)) / (ring%h(j) - nw%h_old(j))
      else
        ring%slope(j) = -min(abs(ring%slope(j)), tr%w_tol / tr%circ / abs(ring%h(j) - nw%h_old(j)))
      end if
    end do
  end subroutine update_slopes

  !> The ring's summary film: the trial's h0, the sectors' mean loads, their flags (and
  !> flag_sectors where they missed the tolerance) and solve counts (since nfs, nrs).
  pure subroutine summarise(ring, g, tr, nfs, nrs, done)
    type(sector_ring), intent(in) :: ring
    type(film_type), intent(inout) :: g
    type(sector_trial), intent(in) :: tr
    integer, intent(in) :: nfs, nrs
    logical, intent(in) :: done
    integer :: j
    g%h0 = tr%cc
    g%wh = exact_mean(ring%films%wh)
    g%wa = exact_mean(ring%films%wa)
    g%aa = exact_mean(ring%films%aa)
    g%flags = 0
    do j = 1, ring%bore%m
      g%flags = ior(g%flags, ring%films(j)%flags)
    end do
    if (.not. done) g%flags = ior(g%flags, flag_sectors)
    g%film_solves = g%film_solves + sum(ring%films%film_solves) - nfs
    g%reynolds_solves = g%reynolds_solves + sum(ring%films%reynolds_solves) - nrs
  end subroutine summarise

  !> The step is accepted at the ring's last evaluation: its h0_j enter the history.
  pure subroutine ring_accept(ring)
    type(sector_ring), intent(inout) :: ring
    ring%hist(3, :) = ring%hist(2, :)
    ring%hist(2, :) = ring%hist(1, :)
    ring%hist(1, :) = ring%h
    ring%chist(2) = ring%chist(1)
    ring%chist(1) = ring%c_last
    if (.not. allocated(ring%whist)) allocate (ring%whist(2, size(ring%w)))
    ring%whist(2, :) = ring%whist(1, :)
    ring%whist(1, :) = ring%w
    ring%steps = ring%steps + 1
    ring%fresh = .true.
  end subroutine ring_accept

  !> The next step's value of a series from its last two (h1 the last), linear in ln,
  !> within a factor 1.2 of h1.
  elemental real(dp) function predicted(h1, h2)
    real(dp), intent(in) :: h1, h2
    predicted = h1 * min(max(h1 / h2, 1.0_dp / 1.2_dp), 1.2_dp)
  end function predicted

  !> Loads per unit circumference of the sectors' films [N/m].
  pure function ring_loads(ring, circ) result(w)
    type(sector_ring), intent(in) :: ring
    real(dp), intent(in) :: circ
    real(dp) :: w(size(ring%films))
    w = (ring%films%wh + ring%films%wa) / circ
  end function ring_loads
end module ringlube_sectors
