!> Mass-conserving (JFO / Elrod-Adams) 1D film: p-theta complementarity.
!>
!> Ring frame, x from the chamber edge (node 1) to the crankcase edge (node n), liner at -U:
!>
!>   d/dx( k dp/dx ) = -(U/2) d(theta h)/dx + d(theta h)/dt,   k = h^3/(12 eta),
!>   p >= pc,  0 <= theta <= 1,  (p - pc)(1 - theta) = 0,
!>   flux q = -(U/2) theta h - k dp/dx   (positive towards the crankcase).
!>
!> Discretisation (docs/film_model.md): finite volumes around the interior nodes 2..n-1, face
!> fluxes `F(f) = a theta(up(f)) hmid(f) - g(f) theta_P(f)`, `g(f) = kmid(f) (p(f+1) - p(f))/dx`,
!> between nodes f and f+1, with a = -U/2 the Couette speed of the content, up(f) the upwind node
!> (f when a > 0, f+1 when a < 0) and theta_P the fill of the node at the higher pressure;
!> backward Euler on the content theta h. In full film (theta = 1) this is the second-order
!> scheme of ringlube_reynolds. The edges are Dirichlet in pressure; what enters through an edge
!> carries that edge's fill theta_left or theta_right.
!>
!> Method: one unknown per interior node, the universal variable v (Payvar-Salant type),
!> `p = pc + max(v, 0)`, `theta = 1 + min(v, 0)`, which satisfies complementarity by construction.
!> The residual R(v) is piecewise smooth; a semismooth Newton step uses its Jacobian on the
!> current piece, which is tridiagonal and a nonsingular M-matrix for the upwind scheme (every
!> column has a positive diagonal, non-positive off-diagonals and a non-negative column sum, and
!> the last column on the outflow side is strictly dominant: weakly chained diagonal dominance of
!> the transpose), so one Thomas solve without pivoting per iteration is safe. Once the piece is
!> right the step is exact, so a warm start needs 1-2 iterations. Guard against cycling: after
!> free_steps full steps a step must bring ||R||^2 below the largest of the last few accepted
!> values (non-monotone Armijo, halving); if it cannot, projected Gauss-Seidel sweeps on v (a
!> convergent M-function iteration; gs_sweeps sweeps, doubling at each further use up to 16 times,
!> gs_budget in all per solve) take over for a while.
!> The pressure-driven content is upwind in pressure (theta_P), so a cavity at a gas pressure
!> above its neighbour pushes out oil only in proportion to its fill: theta >= 0 by construction.
!> Details and verification: docs/film_model.md.
module ringlube_jfo
  use, intrinsic :: ieee_arithmetic, only: ieee_is_finite
  use ringlube_kinds, only: dp
  use ringlube_jfo_system, only: jfo_problem, jfo_system, jfo_system_setup, jfo_residual, &
                                 jfo_gauss_seidel, jfo_scratch, jfo_scratch_size, &
                                 jfo_newton_eval, jfo_newton_step, jfo_residual_only, &
                                 jfo_newton_apply, jfo_state_to_v, jfo_eval
  implicit none
  private
  public :: jfo_solve, jfo_film_volume, jfo_options, jfo_problem, jfo_stats
  public :: JFO_OK, JFO_NOT_CONVERGED, JFO_SINGULAR, JFO_DRY, JFO_CONNECTIVITY, JFO_BAD_INPUT

  !> info codes of jfo_solve / jfo_solve_connected
  integer, parameter :: JFO_OK = 0            !< converged
  integer, parameter :: JFO_NOT_CONVERGED = 1 !< iteration cap reached; best state returned
  !> zero pivot with guard = .false. (with the guard, the Gauss-Seidel sweeps take over)
  integer, parameter :: JFO_SINGULAR = 2
  !> converged, but a cavity node would need theta < 0 (clipped to 0; not expected)
  integer, parameter :: JFO_DRY = 3
  integer, parameter :: JFO_CONNECTIVITY = 4  !< cavity-pressure outer loop did not settle
  !> inconsistent sizes, n < 3 or dx <= 0; p and theta untouched
  integer, parameter :: JFO_BAD_INPUT = 5

  !> Options of a solve (the defaults are the film's): tol the residual tolerance relative to
  !> the largest flux term of a node; max_iter the Newton iterations (newton = .false.: the
  !> Gauss-Seidel sweeps); max_outer the solves of jfo_solve_connected's outer loop; guard =
  !> .false. switches the anti-cycling guard off and newton = .false. uses the Gauss-Seidel
  !> fallback alone (both for the tests and the benchmark); coarse = .false. switches the
  !> coarse-grid predictor off (for the tests); coarse_from: the smallest solve (nodes) that
  !> restarts from the coarse grids (the coarse solves themselves restart down to coarse_min);
  !> settle = .false. evaluates the residual after every Newton step (`step_settles`: for the
  !> tests and the benchmark).
  type :: jfo_options
    real(dp) :: tol = 1e-11_dp
    integer :: max_iter = 200, max_outer = 200, coarse_from = 401
    logical :: guard = .true., newton = .true., coarse = .true., settle = .true.
  end type jfo_options

  !> residual (relative to the same scale) below which a converged state is left as it is
  real(dp), parameter :: polish_tol = 1e-14_dp
  !> Newton steps taken in full before the guard (Armijo backtracking, Gauss-Seidel) engages:
  !> the merit ||R|| of a semismooth Newton step need not fall even when the step is right,
  !> and a step moves a cavity boundary by a few nodes, so on fine grids a warm start needs
  !> more steps than on coarse ones (8 sent the starved film at 1001 nodes to the sweeps for
  !> 65 % of its run time; 30 sends it there for 13 %, with the same answers)
  integer, parameter :: free_steps = 30
  !> after that, a step is accepted if it decreases ||R||^2 below the largest of the last
  !> `nonmonotone` accepted values (non-monotone Armijo rule, Grippo, Lampariello and Lucidi 1986)
  integer, parameter :: nonmonotone = 5
  !> Gauss-Seidel sweeps of the first fallback (doubling at each further use, up to 16 times):
  !> a fixed number, not one per node, so that a fallback costs O(n) like a Newton step (with n
  !> sweeps it cost O(n^2): 95 % of a starved run at 801 nodes). The sweeps only have to move
  !> the state off the piece where Newton cycles, not to converge (8, 32 and 4 gave the same
  !> answers and iteration counts within 5 %).
  integer, parameter :: gs_sweeps = 8
  !> Gauss-Seidel sweeps one solve may spend in all: a solve where neither method converges (a
  !> few trial films of extreme starved designs) ends at the iteration cap, flagged, after
  !> O(n) work, not after tens of thousands of sweeps. Newton, not the sweeps, converges the
  !> solves that need a fallback: 128 instead of 2048 sweeps cut the starved film at 1001
  !> nodes from 8.5 to 2.9 s with the same energy to 1e-10 (docs/performance.md)
  integer, parameter :: gs_budget = 128
  !> Coarse-grid predictor (`coarse_start`; docs/film_model.md "Coarse-grid predictor"): a
  !> Newton step moves a reformation front advancing against the Couette flow by one node. When
  !> walk_steps consecutive steps each switch one or two nodes, a solve of at least
  !> `coarse_from` nodes (jfo_options) restarts from the step solved on grids coarser by 2-5
  !> (recursively, down to coarse_min nodes), at most max_coarse times; a restart that the
  !> next walk, or a stall with the sweeps' budget spent, finds worse than the state before it
  !> is taken back. It changes the start, not the answer (the fine solve's tolerance decides).
  integer, parameter :: walk_steps = 3, coarse_min = 65, max_coarse = 3
  !> Rounding of the residual after an exact Newton step (`step_settles`), per unit of the
  !> residual's scale and of the Jacobian's terms times the step: the residual's sum of a
  !> node's terms at either state (about 6 roundings each), the elimination's backward error
  !> (about 3 per term) and the rounding of v + dv, counted twice over.
  real(dp), parameter :: step_rounding = 16 * epsilon(1.0_dp)

  !> What a solve reports (jfo_solve; jfo_solve_connected sums over its solves).
  type :: jfo_stats
    !> Newton iterations (newton = .false.: Gauss-Seidel sweeps), summed over the solves
    integer :: iterations = 0
    !> JFO_OK, or the code of what went wrong (JFO_NOT_CONVERGED ... JFO_BAD_INPUT)
    integer :: info = JFO_OK
    !> Gauss-Seidel sweeps of the fallback, summed over the solves
    integer :: sweeps = 0
    !> jfo_solve_connected: the solves of its outer loop (0 from jfo_solve)
    integer :: outer = 0
    !> solves that ended on a Newton step proven to settle the residual, without evaluating
    !> it (`step_settles`), summed over the solves
    integer :: settled = 0
    !> oil flux [m^2/s, positive towards +x] through the first and last interior faces, so that
    !> `jfo_film_volume` after - before = dt (q_left - q_right) to the tolerance
    real(dp) :: q_left = 0.0_dp, q_right = 0.0_dp
    !> jfo_solve_connected: the face is partly filled across its width at a gas pressure above
    !> the leading edge's (see there)
    logical :: blown = .false.
  end type jfo_stats

  !> Where one solve's iteration stands (jfo_solve): what its internal procedures change.
  type :: solve_state
    !> ||R||^2 at the state v, the last accepted values of it (the non-monotone rule) and the
    !> scale of the residual's terms
    real(dp) :: f0 = 0.0_dp, fhist(nonmonotone) = 0.0_dp, rscale = 0.0_dp
    !> the scratch's cp, y hold the Newton step's forward elimination at v (piv: its pivots
    !> are nonzero; sgn: the Jacobian has the M-matrix sign pattern), and rmax the largest
    !> residual at v
    logical :: jac_ok = .false., piv = .false., sgn = .false.
    real(dp) :: rmax = 0.0_dp
    !> damped Newton steps since the last fallback or fresh start
    integer :: stall = 0
    !> Gauss-Seidel sweeps and fallbacks so far; sweeps spent in restarts taken back
    integer :: nsweep = 0, nfall = 0, nsweep_back = 0
    !> coarse restarts made (max_coarse: none left)
    integer :: ncoarse = max_coarse
    !> the last restart stands (not taken back), and the scratch's vpre, fpre, nsweep_pre,
    !> nfall_pre are the state before it
    logical :: restarted = .false.
    real(dp) :: fpre = huge(1.0_dp)
    integer :: nsweep_pre = 0, nfall_pre = 0
  end type solve_state

contains

  !> One time step (or a steady state) of the mass-conserving film.
  !>
  !> problem (jfo_problem): the step's scalars: node spacing, sliding speed, time step (dt > 0
  !> backward Euler on the content, dt <= 0 a steady solve), the edge pressures and the fills
  !> of what enters through each edge, and the caps on the oil entering through the edge faces
  !> (the oil there: a starved inlet's strip and bank, the liner film behind a trailing edge):
  !> `F_in = min(F_in, cap)`, a kink like the others of the residual; beyond it the edge admits
  !> gas. Both edges are treated alike, whichever leads; the Newton solve and the Gauss-Seidel
  !> fallback apply the same caps. (p_cav, trailing_gas and leading_gas are
  !> jfo_solve_connected's.)
  !> h(n) gap at the nodes; hmid(n-1), kmid(n-1) = hmid^3/(12 eta) at the faces;
  !> content_old(n) theta h at the previous step (nodes 2..n-1 used); pc(n) cavity pressure per
  !> node (nodes 2..n-1 used).
  !> p, theta (in/out): warm start in, solution out. Edge values out: p(1) = p_left,
  !> p(n) = p_right, theta(1) = theta_left, theta(n) = theta_right.
  !> stats (jfo_stats, out): iterations, info, Gauss-Seidel sweeps and the edge fluxes.
  !> options (jfo_options): tolerance, iteration cap, guard, Newton or the fallback alone.
  !> work (jfo_system), scratch (jfo_scratch): the step's system and working arrays, kept by a
  !> caller between solves (else local ones).
  pure recursive subroutine jfo_solve(problem, h, hmid, kmid, content_old, pc, p, theta, stats, &
                                      options, work, scratch)
    type(jfo_problem), intent(in) :: problem
    real(dp), intent(in) :: h(:), hmid(:), kmid(:), content_old(:), pc(:)
    real(dp), intent(inout) :: p(:), theta(:)
    type(jfo_stats), intent(out) :: stats
    type(jfo_options), intent(in), optional :: options
    type(jfo_system), intent(inout), optional :: work
    type(jfo_scratch), intent(inout), optional :: scratch
    type(jfo_system) :: local
    type(jfo_scratch) :: local_scratch
    type(solve_state) :: s
    real(dp) :: rtol, ft, fbest, t, rmax
    integer :: n, it, itmax, tinfo, nls, nsw, walk
    logical :: use_guard, use_newton, accepted, settled
    type(jfo_options) :: opt

    if (.not. present(work)) then
      call jfo_solve(problem, h, hmid, kmid, content_old, pc, p, theta, stats, options, local, &
                     scratch)
      return
    end if
    if (.not. present(scratch)) then
      call jfo_solve(problem, h, hmid, kmid, content_old, pc, p, theta, stats, options, work, &
                     local_scratch)
      return
    end if
    n = size(h)
    call jfo_scratch_size(scratch, n)
    associate (v => scratch%v, vt => scratch%vt, vpre => scratch%vpre, vbest => scratch%vbest, &
               dv => scratch%dv, r => scratch%r, rt => scratch%rt, &
               pn => scratch%ev%pn, tn => scratch%ev%tn, fl => scratch%ev%fl)
      if (n < 3 .or. size(hmid) /= n - 1 .or. size(kmid) /= n - 1 .or. size(content_old) /= n &
          .or. size(pc) /= n .or. size(p) /= n .or. size(theta) /= n &
          .or. .not. (problem%dx > 0.0_dp)) then
        stats%info = JFO_BAD_INPUT
        return
      end if
      if (present(options)) opt = options
      rtol = opt%tol
      itmax = opt%max_iter
      use_guard = opt%guard
      use_newton = opt%newton

      call jfo_system_setup(work, problem, h, hmid, kmid, content_old, pc)

      ! warm start: v = (p - pc)/ps on full nodes, theta - 1 on cavity nodes; not finite -> 0
      call jfo_state_to_v(work, p, theta, v)

      ! s%jac_ok: the Newton step's elimination at v is in the scratch (the residual of an
      ! accepted step is evaluated with it, so the next iteration need not evaluate again)
      call evaluate(s, scratch, .false., use_newton, s%f0)
      if (.not. (ieee_is_finite(s%rscale) .and. ieee_is_finite(s%f0))) then
        ! a warm start whose terms overflow (pressures near huge()) made the scale infinite, and
        ! Inf <= tol * Inf passed as converged: start from full film at the cavity pressure
        v = 0.0_dp
        call evaluate(s, scratch, .false., use_newton, s%f0)
      end if
      s%jac_ok = use_newton
      vbest = v
      fbest = s%f0
      s%fhist = s%f0
      walk = 0
      settled = .false.
      if (use_newton .and. opt%coarse .and. n >= max(opt%coarse_from, coarse_min) &
          .and. coarse_factor(n) > 0) s%ncoarse = 0
      do it = 0, itmax
        rmax = s%rmax
        if (rmax <= rtol * s%rscale .or. it == itmax) exit
        if (walk >= walk_steps .and. (s%ncoarse < max_coarse .or. s%restarted)) then
          ! the boundaries walk a node or two per step: start again from the coarse grids'
          ! solution, which moves them a few coarse nodes per step. Where the coarse grids'
          ! cavities differ from the fine grid's, the walk resumes from a worse state: then the
          ! state before is taken back and the walk goes on from there (also after the last
          ! restart).
          walk = 0
          if (s%restarted .and. s%f0 > s%fpre) then
            call take_back(s, scratch)
          else if (s%ncoarse < max_coarse) then
            s%ncoarse = s%ncoarse + 1
            vpre = v
            s%fpre = s%f0
            s%nsweep_pre = s%nsweep
            s%nfall_pre = s%nfall
            s%restarted = .true.
            call coarse_start(v, pn, tn)
            call fresh_start(s, scratch, .true.)
          else
            s%restarted = .false.
          end if
          if (s%f0 < fbest) then
            fbest = s%f0
            vbest = v
          end if
          rmax = s%rmax
          if (rmax <= rtol * s%rscale) exit
        end if
        stats%iterations = it + 1
        if (.not. use_newton) then
          call jfo_gauss_seidel(work, v, 1, s%nsweep)
          call evaluate(s, scratch, .false., .false., s%f0)
          cycle
        end if
        if (.not. s%jac_ok) call evaluate(s, scratch, .false., .true., ft)
        s%jac_ok = .false.
        ! the M-matrix sign pattern holds by construction (upwinding); a violation (a degenerate
        ! zero diagonal) is treated like a zero pivot
        if (use_guard .and. .not. s%sgn) then
          tinfo = -1
        else if (.not. s%piv) then
          tinfo = 1
        else
          tinfo = 0
        end if
        if (tinfo /= 0 .and. .not. use_guard) then
          stats%info = JFO_SINGULAR
          exit
        end if
        accepted = .false.
        if (tinfo == 0 .and. (.not. use_guard .or. it < free_steps)) then
          ! a full step, taken whatever it does to ||R||: in place (the back substitution and
          ! the update in one pass)
          call jfo_newton_apply(n, scratch%cp, scratch%y, dv, v, nsw)
          ! a step that switched no node stays on its piece, where the residual is nearly
          ! affine, and is usually the last: the residual alone. A step that switched nodes
          ! left the piece, and the next iteration needs the elimination there: the residual
          ! with it, in one pass (the same residual bit for bit, one pass fewer)
          s%jac_ok = nsw > 0
          if (s%jac_ok) then
            call evaluate(s, scratch, .false., .true., ft)
          else if (opt%settle) then
            ! no node switched: where the step provably settles the residual (its kinks not
            ! crossed, its products' change below the polish level, its rounding bounded
            ! below the tolerance), the solve ends here without evaluating it, with the
            ! outputs (the node states and the edge fluxes) an evaluation would give
            call step_settles(work, v, dv, rtol, scratch%ev, s%rscale, s%rmax, settled)
            if (settled) exit
            call jfo_residual_only(work, v, r, s%rscale, s%rmax, ft, scratch%ev)
          else
            call jfo_residual_only(work, v, r, s%rscale, s%rmax, ft, scratch%ev)
          end if
          accepted = .true.
          nls = 0
          if (nsw >= 1 .and. nsw <= 2) then
            walk = walk + 1
          else
            walk = 0
          end if
          s%f0 = ft
          s%fhist(mod(it, size(s%fhist)) + 1) = s%f0
        else if (tinfo == 0) then
          ! after free_steps iterations, halve the step until ||R||^2 falls below the largest of
          ! the last accepted values (non-monotone Armijo)
          call jfo_newton_step(n, scratch%cp, scratch%y, dv)
          t = 1.0_dp
          do nls = 0, 30
            vt = v + t * dv
            ! the residual alone: most trials are rejected, and an accepted one is eliminated
            ! by the next iteration (the same numbers; a trial used to eliminate too, and a
            ! starved film with the ring pack at 5001 nodes made 13 trials per damped step)
            call jfo_residual_only(work, vt, rt, s%rscale, s%rmax, ft, scratch%ev)
            if (ft <= (1.0_dp - 1e-4_dp * t) * maxval(s%fhist)) then
              accepted = .true.
              exit
            end if
            t = 0.5_dp * t
          end do
          if (accepted) then
            nsw = count((v(2:n - 1) < 0.0_dp) .neqv. (vt(2:n - 1) < 0.0_dp))
            if (nsw >= 1 .and. nsw <= 2) then
              walk = walk + 1
            else
              walk = 0
            end if
            v = vt
            r = rt
            s%jac_ok = .false.   ! the last evaluation was at vt, without the elimination
            s%f0 = ft
            s%fhist(mod(it, size(s%fhist)) + 1) = s%f0
            if (nls > 0) s%stall = s%stall + 1
          end if
        end if
        if ((.not. accepted .or. s%stall >= 3) .and. s%restarted .and. s%f0 > s%fpre &
            .and. s%nsweep >= gs_budget) then
          ! Newton stalls from a restart that has not yet improved on the state before it, and
          ! the sweeps' budget is spent: without a further walk the rule above would never take
          ! it back, and the solve would end at the iteration cap there. Take it back, with the
          ! sweeps spent since (taking a restart back at every stall above the state before it
          ! made the starved cold deck at 2001 nodes and 2 deg 4 times slower a run)
          call take_back(s, scratch)
        else if (.not. accepted .or. s%stall >= 3) then
          ! zero pivot, no descent, or repeated damping: Gauss-Seidel sweeps, then Newton again
          ! (each fallback sweeps twice as long as the previous one, at most 16 gs_sweeps, and
          ! gs_budget in all: where neither converges, as in a few extreme starved designs, a
          ! solve must still end at the iteration cap, flagged, after O(n) work)
          if (s%nsweep < gs_budget) &
            call jfo_gauss_seidel(work, v, min(gs_sweeps * 2**min(s%nfall, 4), &
                                               gs_budget - s%nsweep), s%nsweep)
          s%nfall = s%nfall + 1
          call fresh_start(s, scratch, .false.)
        end if
        if (s%f0 < fbest) then
          fbest = s%f0
          vbest = v
        end if
      end do
      if (use_newton .and. stats%info == JFO_OK .and. s%rmax <= rtol * s%rscale &
          .and. s%rmax > polish_tol * s%rscale .and. .not. settled) then
        ! within the tolerance but above round-off (a damped or Gauss-Seidel last step): one more
        ! Newton step on this piece, kept if it helps, so that the oil balance closes to round-off
        call evaluate(s, scratch, .false., .true., ft)
        if (s%piv) then
          call jfo_newton_step(n, scratch%cp, scratch%y, dv)
          vt = v
          vt(2:n - 1) = v(2:n - 1) + dv(2:n - 1)
          call evaluate(s, scratch, .true., .false., ft)
          if (ft < s%f0) then
            v = vt
            r = rt
            stats%iterations = stats%iterations + 1
          end if
        end if
        call evaluate(s, scratch, .false., .false., ft)
      end if
      stats%sweeps = s%nsweep + s%nsweep_back
      if (settled) stats%settled = 1
      if (s%rmax > rtol * s%rscale) then
        if (stats%info == JFO_OK) stats%info = JFO_NOT_CONVERGED
        if (fbest < s%f0) then
          v = vbest
          call evaluate(s, scratch, .false., .false., ft)
        end if
      end if

      ! outputs (pn, tn, fl hold the state of the last residual evaluation, which is v's)
      p = pn
      if (stats%info == JFO_OK) then
        ! (count: the test of any, without an exit from the loop, so that it vectorises)
        if (count(tn(2:n - 1) < -1e-12_dp) > 0) stats%info = JFO_DRY
      end if
      theta(1) = tn(1)
      theta(2:n - 1) = min(max(tn(2:n - 1), 0.0_dp), 1.0_dp)
      theta(n) = tn(n)
      stats%q_left = fl(1)
      stats%q_right = fl(n - 1)
    end associate

  contains

    !> The residual at the state sc%v (trial: sc%vt) into sc%r (sc%rt), its scale (s%rscale),
    !> largest entry (s%rmax) and sum of squares fsq; with newton also the Newton step's
    !> elimination there (sc%cp, sc%y; s%piv, s%sgn). sc%ev holds that state's node states and
    !> face fluxes.
    pure subroutine evaluate(s, sc, trial, newton, fsq)
      type(solve_state), intent(inout) :: s
      type(jfo_scratch), intent(inout) :: sc
      logical, intent(in) :: trial, newton
      real(dp), intent(out) :: fsq
      if (trial .and. newton) then
        call jfo_newton_eval(work, sc%vt, sc%rt, s%rscale, s%rmax, fsq, sc%ev, sc%cp, sc%y, &
                             s%piv, s%sgn)
      else if (newton) then
        call jfo_newton_eval(work, sc%v, sc%r, s%rscale, s%rmax, fsq, sc%ev, sc%cp, sc%y, &
                             s%piv, s%sgn)
      else if (trial) then
        call jfo_residual(work, sc%vt, sc%rt, s%rscale, .false., sc%ev)
        s%rmax = maxval(abs(sc%rt(2:n - 1)))
        fsq = sum(sc%rt(2:n - 1)**2)
      else
        call jfo_residual(work, sc%v, sc%r, s%rscale, .false., sc%ev)
        s%rmax = maxval(abs(sc%r(2:n - 1)))
        fsq = sum(sc%r(2:n - 1)**2)
      end if
    end subroutine evaluate

    !> The residual at the state v (with jac also its Jacobian) as a fresh start of the merit:
    !> f0 from it, the non-monotone history all f0, no damped steps counted.
    pure subroutine fresh_start(s, sc, jac)
      type(solve_state), intent(inout) :: s
      type(jfo_scratch), intent(inout) :: sc
      logical, intent(in) :: jac
      call evaluate(s, sc, .false., jac, s%f0)
      s%jac_ok = jac
      s%fhist = s%f0
      s%stall = 0
    end subroutine fresh_start

    !> Take the last coarse restart back: v the state before it with its counters, no further
    !> restart; the sweeps spent since count in nsweep_back.
    pure subroutine take_back(s, sc)
      type(solve_state), intent(inout) :: s
      type(jfo_scratch), intent(inout) :: sc
      sc%v = sc%vpre
      s%ncoarse = max_coarse
      s%restarted = .false.
      s%nsweep_back = s%nsweep_back + s%nsweep - s%nsweep_pre
      s%nsweep = s%nsweep_pre
      s%nfall = s%nfall_pre
      call fresh_start(s, sc, .true.)
    end subroutine take_back

    !> The coarse-grid predictor (see walk_steps): the step's system restricted to every k-th
    !> node (k the smallest of 4, 2, 3, 5 dividing n - 1; none: v unchanged), solved, and its
    !> pressure and fill interpolated linearly to the fine nodes; v is the warm start of that
    !> state (as at entry). Faces: the mean gap and the series conductance of the k fine faces;
    !> nodes: the gap and the last content weighted like the fine control volumes they cover
    !> (hat weights), the cavity pressure and the current state sampled.
    pure recursive subroutine coarse_start(v, pn, tn)
      real(dp), intent(inout) :: v(:), pn(:), tn(:)
      integer :: k, nc, ic, i0, j
      real(dp), allocatable :: hc(:), hmc(:), kmc(:), coc(:), pcc(:), ppc(:), thc(:)
      real(dp) :: wsum, wj, s
      type(jfo_options) :: copt
      type(jfo_problem) :: coarse
      type(jfo_stats) :: cstats
      k = coarse_factor(n)
      if (k == 0) return
      nc = (n - 1) / k + 1
      allocate (hc(nc), hmc(nc - 1), kmc(nc - 1), coc(nc), pcc(nc), ppc(nc), thc(nc))
      do ic = 1, nc - 1
        i0 = 1 + (ic - 1) * k
        hmc(ic) = sum(hmid(i0:i0 + k - 1)) / k
        s = sum(1.0_dp / kmid(i0:i0 + k - 1))
        kmc(ic) = k / s
      end do
      do ic = 1, nc
        i0 = 1 + (ic - 1) * k
        hc(ic) = h(i0)
        coc(ic) = content_old(i0)
        pcc(ic) = pc(i0)
        ppc(ic) = pn(i0)
        thc(ic) = tn(i0)
        if (ic == 1 .or. ic == nc) cycle
        hc(ic) = 0.0_dp
        coc(ic) = 0.0_dp
        wsum = 0.0_dp
        do j = i0 - k + 1, i0 + k - 1
          wj = 1.0_dp - real(abs(j - i0), dp) / k
          hc(ic) = hc(ic) + wj * h(j)
          coc(ic) = coc(ic) + wj * content_old(j)
          wsum = wsum + wj
        end do
        hc(ic) = hc(ic) / wsum
        coc(ic) = coc(ic) / wsum
      end do
      copt = opt
      copt%coarse_from = coarse_min
      coarse = problem
      coarse%dx = problem%dx * k
      call jfo_solve(coarse, hc, hmc, kmc, coc, pcc, ppc, thc, cstats, copt)
      do ic = 1, nc - 1
        i0 = 1 + (ic - 1) * k
        do j = 1, k
          s = real(j, dp) / k
          if (i0 + j > n - 1) exit
          pn(i0 + j) = (1.0_dp - s) * ppc(ic) + s * ppc(ic + 1)
          tn(i0 + j) = (1.0_dp - s) * thc(ic) + s * thc(ic + 1)
        end do
      end do
      call jfo_state_to_v(work, pn, tn, v)
    end subroutine coarse_start

  end subroutine jfo_solve

  !> After a full Newton step v = v0 + dv that switched no node (every node on its side of the
  !> kink v = 0): whether the residual at v is, without evaluating it, proven below half the
  !> tolerance tol of the solve's scale. On the piece of v0 the residual is affine but for the
  !> products of a face's pressure difference g and the fill theta_P its pressure-driven
  !> content takes, so an exact Newton step leaves only those products' change and rounding.
  !> The step settles when, along the segment v0 -> v: (1) no face changes which node's fill
  !> theta_P is (the sign of g), unless both nodes' fills are equal at both ends; (2) no edge
  !> face comes to or leaves its cap; (3) the products' change, delta g delta theta_P (two
  !> faces per node), is below a quarter of the polish level `polish_tol` of the scale, so
  !> that, as after an evaluation, no polish step is due; (4) with it, the rounding
  !> `step_rounding` of the scale and of the Jacobian's terms times the step (each of its
  !> rows at most 6 m, m the larger of the scale and the largest diagonal, w h + |a hmid| +
  !> |a hmid| or (kmid/dx + kmid/dx) ps, times the largest |dv|) stays below half the tolerance
  !> of a lower bound of the new scale (the scale less 4 m max |dv|, what its terms can lose).
  !> The rounding bound is a worst case of the order of the polish level itself; the residual
  !> an evaluation would find is, in practice, rounding far below it, so the evaluation would
  !> end the solve here too with the same outputs (tests/bench/identical.py: every shipped
  !> deck to the bit). A meniscus at an inflow edge (edge_meniscus) is another kink, and the
  !> fronts' excess (front_content) is not affine on a piece: then never.
  !> tol: the solve's tolerance. ev: in, the node states and edge fluxes at v0
  !> (jfo_newton_eval's); out when settled, at v (the node states bit for bit jfo_residual's,
  !> the edge faces' fluxes computed alike), other entries undefined (when not settled the
  !> node states too). rscale: in, the scale at v0; out when settled, the lower bound at v.
  !> rmax (out, when settled): the bound of the residual's largest entry.
  pure subroutine step_settles(sys, v, dv, tol, ev, rscale, rmax, settled)
    type(jfo_system), intent(in) :: sys
    real(dp), intent(in), contiguous :: v(:), dv(:)
    real(dp), intent(in) :: tol
    type(jfo_eval), intent(inout) :: ev
    real(dp), intent(inout) :: rscale
    real(dp), intent(out) :: rmax
    logical, intent(out) :: settled
    settled = .false.
    rmax = huge(1.0_dp)
    if (sys%edge_meniscus .or. sys%front_content) return
    call settles_nodes(sys, sys%n, sys%kd, sys%ca, sys%pc, sys%ps, v, dv, tol, ev%pn, ev%tn, &
                       ev%fl, rscale, rmax, settled)
  end subroutine step_settles

  !> step_settles on explicit-shape arrays (contiguous, so indexed without descriptors). Only
  !> the edge faces and the faces between a full and a partly filled node can cross a kink or
  !> hold a changed product (between two full nodes theta_P = 1; between two partly filled
  !> ones g is fixed): those are checked first, at the states of v0 (pn, tn) and v; then every
  !> node's state at v. The largest diagonal is the system's (sys%dmax).
  pure subroutine settles_nodes(sys, n, kd, ca, pc, ps, v, dv, tol, pn, tn, fl, rscale, rmax, &
                                settled)
    type(jfo_system), intent(in) :: sys
    integer, intent(in) :: n
    real(dp), intent(in) :: kd(n), ca(n), pc(n), ps(n), v(n), dv(n), tol
    real(dp), intent(inout) :: pn(n), tn(n), fl(n), rscale
    real(dp), intent(out) :: rmax
    logical, intent(out) :: settled
    real(dp) :: q, d, m, lower, fo, fn
    integer :: j
    settled = .false.
    q = 0.0_dp
    ! the edge faces: the flux (as jfo_residual) on the same side of its cap at both ends
    call face_change(1, q, fo, fn)
    if (q < 0.0_dp .or. ((fo > sys%qcl) .neqv. (fn > sys%qcl))) return
    if (fn <= sys%qcl) fl(1) = fn
    call face_change(n - 1, q, fo, fn)
    if (q < 0.0_dp .or. ((-fo > sys%qcr) .neqv. (-fn > sys%qcr))) return
    fl(n - 1) = fn
    if (-fn > sys%qcr) fl(n - 1) = -sys%qcr
    do j = 2, n - 2
      if ((v(j) < 0.0_dp) .neqv. (v(j + 1) < 0.0_dp)) then
        call face_change(j, q, fo, fn)
        if (q < 0.0_dp) return
      end if
    end do
    d = 0.0_dp
    do j = 2, n - 1
      pn(j) = pc(j) + ps(j) * max(v(j), 0.0_dp)
      tn(j) = 1.0_dp + min(v(j), 0.0_dp)
      d = max(d, abs(dv(j)))
    end do
    m = max(rscale, sys%dmax)
    lower = rscale - 4.0_dp * m * d
    rmax = 2.0_dp * q + step_rounding * (rscale + 6.0_dp * m * d)
    if (.not. (lower > 0.0_dp .and. q <= 0.25_dp * polish_tol * lower &
               .and. rmax <= 0.5_dp * tol * lower)) return
    rscale = lower
    settled = .true.

  contains

    !> Face f at v0 (pn, tn) and at v: q the largest changed product so far, or -1 where the
    !> pressure-driven content changes sides between two different fills; fo, fn its flux at
    !> both ends.
    pure subroutine face_change(f, q, fo, fn)
      integer, intent(in) :: f
      real(dp), intent(inout) :: q
      real(dp), intent(out) :: fo, fn
      real(dp) :: go, gn, pl, tl, pr, tr
      pl = pn(f)
      tl = tn(f)
      if (f > 1) then
        pl = pc(f) + ps(f) * max(v(f), 0.0_dp)
        tl = 1.0_dp + min(v(f), 0.0_dp)
      end if
      pr = pn(f + 1)
      tr = tn(f + 1)
      if (f + 1 < n) then
        pr = pc(f + 1) + ps(f + 1) * max(v(f + 1), 0.0_dp)
        tr = 1.0_dp + min(v(f + 1), 0.0_dp)
      end if
      go = kd(f) * (pn(f + 1) - pn(f))
      gn = kd(f) * (pr - pl)
      if (sys%a > 0.0_dp) then
        fo = ca(f) * tn(f) - go * merge(tn(f), tn(f + 1), go <= 0.0_dp)
        fn = ca(f) * tl - gn * merge(tl, tr, gn <= 0.0_dp)
      else
        fo = ca(f) * tn(f + 1) - go * merge(tn(f), tn(f + 1), go <= 0.0_dp)
        fn = ca(f) * tr - gn * merge(tl, tr, gn <= 0.0_dp)
      end if
      if ((go <= 0.0_dp) .neqv. (gn <= 0.0_dp)) then
        if (tn(f) /= tn(f + 1) .or. tl /= tr) q = -1.0_dp
      else if (gn <= 0.0_dp) then
        q = max(q, abs((gn - go) * (tl - tn(f))))
      else
        q = max(q, abs((gn - go) * (tr - tn(f + 1))))
      end if
    end subroutine face_change
  end subroutine settles_nodes

  !> The coarsening of the predictor for n nodes: the first of 4, 2, 3, 5 that divides n - 1
  !> (0: none, and the solve does not restart).
  pure integer function coarse_factor(n) result(k)
    integer, intent(in) :: n
    k = 0
    if (mod(n - 1, 4) == 0) then
      k = 4
    else if (mod(n - 1, 2) == 0) then
      k = 2
    else if (mod(n - 1, 3) == 0) then
      k = 3
    else if (mod(n - 1, 5) == 0) then
      k = 5
    end if
  end function coarse_factor

  !> Oil volume per unit circumference held by the interior finite volumes (m^2): the quantity
  !> whose change jfo_solve's edge fluxes balance. edge_cells (default .false.): the volumes
  !> next to the edges reach the edges (jfo_problem%edge_cells).
  pure real(dp) function jfo_film_volume(dx, h, theta, edge_cells) result(vol)
    real(dp), intent(in) :: dx, h(:), theta(:)
    logical, intent(in), optional :: edge_cells
    integer :: n
    n = size(h)
    vol = dx * sum(theta(2:n - 1) * h(2:n - 1))
    if (present(edge_cells)) then
      if (edge_cells) vol = vol + 0.5_dp * dx * (theta(2) * h(2) + theta(n - 1) * h(n - 1))
    end if
  end function jfo_film_volume
end module ringlube_jfo
