!> The discretised system of one time step of the mass-conserving film (ringlube_jfo): the
!> step's problem (`jfo_problem`), the face coefficients of the upwind finite-volume scheme, its
!> residual and Jacobian at a state of the universal variable v, and the projected Gauss-Seidel
!> sweeps of the fallback. The scheme and the method are described in ringlube_jfo and
!> docs/film_model.md.
module ringlube_jfo_system
  use ringlube_kinds, only: dp
  implicit none
  private
  public :: jfo_problem, jfo_system, jfo_system_setup, jfo_residual, jfo_gauss_seidel, &
            jfo_eval, jfo_scratch, jfo_scratch_size, jfo_newton_eval, jfo_newton_step, &
            jfo_residual_only, jfo_newton_apply, jfo_state_to_v, jfo_front_content

  !> One step of the mass-conserving film: its scalars, the record jfo_solve and
  !> jfo_solve_connected take beside the film's arrays (the gap, the conductances, the content
  !> of the last step, the cavity pressures). dx, u, dt, p_left and p_right have no default
  !> and must be given.
  type :: jfo_problem
    !> node spacing [m]
    real(dp) :: dx
    !> sliding speed [m/s]: the content moves at -u/2
    real(dp) :: u
    !> backward Euler step on the content [s]; dt <= 0: a steady solve
    real(dp) :: dt
    !> pressures held at the left (node 1) and right (node n) edge [Pa]
    real(dp) :: p_left, p_right
    !> fill of whatever enters through the left (right) edge, by Couette transport at the
    !> inflow edge or pushed in by pressure at either edge: 1 oil, 0 gas only
    real(dp) :: theta_left = 1.0_dp, theta_right = 1.0_dp
    !> caps on the oil entering the gap through the left (right) edge face [m^2/s] (the oil
    !> there; beyond it the edge admits gas); negative counts as 0; default none
    real(dp) :: cap_left = huge(1.0_dp), cap_right = huge(1.0_dp)
    !> jfo_solve_connected only: the film's cavity pressure [Pa] (ringlube_jfo_connect)
    real(dp) :: p_cav = 0.0_dp
    !> jfo_solve_connected only: a cavity reaching the trailing edge is open to its gas; the
    !> partly filled zone at the leading edge (a starved inlet) is open to the leading edge's gas
    logical :: trailing_gas = .false., leading_gas = .false.
    !> jfo_solve_connected only: the pressure [Pa] at each node of the gas flowing through a
    !> face open from edge to edge (a distorted bore's sector whose face had no full zone at
    !> the last step), which its cavities take instead of the connectivity rule's levels; not
    !> allocated: the rule
    real(dp), allocatable :: gas_channel(:)
    !> the inflow edge face when the film pushes oil back out through it (a meniscus at the
    !> edge, `&numerics film_edge_cells`): .false. the supply's Couette content less the
    !> pushed-back flow; .true. the lesser of the supply's Couette content and the face's
    !> full-film flux (`inflow_edge`)
    logical :: edge_meniscus = .false.
    !> .true.: the finite volumes next to the edges reach the edges (1.5 dx: the half cells
    !> between an edge node and its first face hold oil, `&numerics film_edge_cells`);
    !> .false.: they end at the first face and the half cells hold none
    logical :: edge_cells = .false.
    !> .true.: a reformation front's two cells hold the oil of the front the pressures place
    !> (`front_excess`): their content is theta h less the excess the upwind scheme holds there,
    !> so the front moves with the oil it bounds (a step's content_old must then be
    !> `jfo_front_content` of the last step); .false.: theta h. Only with edge_cells (without
    !> them a meniscus at the inflow edge has no cell to hold it) and a time step
    logical :: front_content = .false.
    !> with front_content: the fill where the thinly filled cells' stored content (theta hd,
    !> `front_excess`) begins to fade to theta h, and the width of the fill over which it fades
    !> (a smoothstep). The defaults are the kernel's; other values are for the bench
    !> (tests/bench/bench_oil_turned_back.f90: where the starved zone's oil comes from)
    real(dp) :: thin_fade_from = 0.3_dp, thin_fade_width = 0.3_dp
    !> with front_content, for the bench only: every partly filled node stores theta hd (set
    !> thin_fade_from 1 too) and a full node next to a partly filled one hd + s (h - hd), s its
    !> fronts' (`front_excess`); .false. (the kernel): h
    logical :: full_hd = .false.
  end type jfo_problem

  !> One step's system: n nodes; a = -U/2 the Couette speed of the content; w = dx/dt (0 for a
  !> steady solve); ca = a hmid and kd = kmid/dx per face; ps the pressure per unit v of each
  !> node's full side; the gap, the content of the last step and the cavity pressure per node;
  !> the edges' pressures and fills; qcl, qcr the caps on the inflow through the edge faces.
  type :: jfo_system
    integer :: n = 0
    real(dp) :: a = 0.0_dp, w = 0.0_dp
    real(dp) :: p_left = 0.0_dp, p_right = 0.0_dp, theta_left = 1.0_dp, theta_right = 1.0_dp
    real(dp) :: qcl = huge(1.0_dp), qcr = huge(1.0_dp)
    real(dp), allocatable :: ca(:), kd(:), ps(:), h(:), content_old(:), pc(:)
    !> w times each node's volume in dx (1; 1.5 next to an edge with jfo_problem%edge_cells)
    real(dp), allocatable :: wv(:)
    !> the largest diagonal of the Jacobian's fill and pressure sides over the interior nodes,
    !> max(w h + |a hmid| + |a hmid|, (kmid/dx + kmid/dx) ps) (jfo_solve's `step_settles`)
    real(dp) :: dmax = 0.0_dp
    !> jfo_problem%edge_meniscus
    logical :: edge_meniscus = .false.
    !> jfo_problem%front_content with a time step (w > 0) and edge cells; jfo_problem%edge_cells
    logical :: front_content = .false., edge_cells = .false.
    !> jfo_problem%thin_fade_from, jfo_problem%thin_fade_width
    real(dp) :: thin_fade_from = 0.3_dp, thin_fade_width = 0.3_dp
    !> jfo_problem%full_hd
    logical :: full_hd = .false.
  end type jfo_system

  !> The residual's evaluation at a state v (jfo_residual), all per node or per face (n).
  type :: jfo_eval
    !> pressure and fill of each node
    real(dp), allocatable :: pn(:), tn(:)
    !> flux through each face f (nodes f, f+1)
    real(dp), allocatable :: fl(:)
    !> the flux's derivatives by the pressure (dfpl, dfpr) and the fill (dftl, dftr) of the
    !> face's left and right node
    real(dp), allocatable :: dfpl(:), dfpr(:), dftl(:), dftr(:)
    !> the residual's Jacobian rows by v on the current piece: sub-, main and super-diagonal
    real(dp), allocatable :: jl(:), jd(:), ju(:)
  end type jfo_eval

  !> jfo_solve's working arrays (allocated once for a film's n nodes and kept, like
  !> jfo_system: no allocation per solve).
  type :: jfo_scratch
    !> the state v, a trial state vt, the state before the last coarse restart vpre, the best
    !> state vbest and the Newton step dv
    real(dp), allocatable :: v(:), vt(:), vpre(:), vbest(:), dv(:)
    !> the residuals at v and at vt, and the Thomas solve's work array
    real(dp), allocatable :: r(:), rt(:), tw(:)
    !> the Newton step's forward elimination at the last state jfo_newton_eval evaluated: the
    !> eliminated upper diagonal and right-hand side of the Jacobian system J dv = -R
    real(dp), allocatable :: cp(:), y(:)
    !> the residual's evaluation at the last state evaluated
    type(jfo_eval) :: ev
  end type jfo_scratch

contains

  !> Scratch arrays for n nodes (allocated only when their size changes).
  pure subroutine jfo_scratch_size(s, n)
    type(jfo_scratch), intent(inout) :: s
    integer, intent(in) :: n
    if (allocated(s%v)) then
      if (size(s%v) == n) return
      deallocate (s%v, s%vt, s%vpre, s%vbest, s%dv, s%r, s%rt, s%tw, s%cp, s%y)
      deallocate (s%ev%pn, s%ev%tn, s%ev%fl, s%ev%dfpl, s%ev%dfpr, s%ev%dftl, s%ev%dftr, &
                  s%ev%jl, s%ev%jd, s%ev%ju)
    end if
    allocate (s%v(n), s%vt(n), s%vpre(n), s%vbest(n), s%dv(n), s%r(n), s%rt(n), s%tw(n), &
              s%cp(n), s%y(n))
    allocate (s%ev%pn(n), s%ev%tn(n), s%ev%fl(n), s%ev%dfpl(n), s%ev%dfpr(n), s%ev%dftl(n), &
              s%ev%dftr(n), s%ev%jl(n), s%ev%jd(n), s%ev%ju(n))
  end subroutine jfo_scratch_size

  !> The discretised system of one jfo_solve call (arguments as jfo_solve; the caps clipped at
  !> 0), in sys's arrays (allocated once for a film's n nodes and kept: jfo_solve's `work`).
  pure subroutine jfo_system_setup(sys, problem, h, hmid, kmid, content_old, pc)
    type(jfo_system), intent(inout) :: sys
    type(jfo_problem), intent(in) :: problem
    real(dp), intent(in) :: h(:), hmid(:), kmid(:), content_old(:), pc(:)
    integer :: n
    n = size(h)
    sys%n = n
    sys%h = h
    sys%content_old = content_old
    sys%pc = pc
    sys%p_left = problem%p_left
    sys%p_right = problem%p_right
    sys%theta_left = problem%theta_left
    sys%theta_right = problem%theta_right
    sys%qcl = max(problem%cap_left, 0.0_dp)
    sys%qcr = max(problem%cap_right, 0.0_dp)
    sys%edge_meniscus = problem%edge_meniscus
    sys%edge_cells = problem%edge_cells
    sys%front_content = problem%front_content .and. problem%dt > 0.0_dp .and. problem%edge_cells
    sys%thin_fade_from = problem%thin_fade_from
    sys%thin_fade_width = problem%thin_fade_width
    sys%full_hd = problem%full_hd
    if (allocated(sys%ca)) then
      if (size(sys%ca) /= n) deallocate (sys%ca, sys%kd, sys%ps, sys%wv)
    end if
    if (.not. allocated(sys%ca)) allocate (sys%ca(n), sys%kd(n), sys%ps(n), sys%wv(n))
    associate (a => sys%a, w => sys%w, ca => sys%ca, kd => sys%kd, ps => sys%ps, dx => problem%dx, &
               dt => problem%dt, wv => sys%wv)
      a = -0.5_dp * problem%u
      w = 0.0_dp
      if (dt > 0.0_dp) w = dx / dt
      call setup_nodes(n, a, w, dx, problem%edge_cells, hmid, kmid, sys%h, wv, ca, kd, ps, &
                       sys%dmax)
    end associate
  end subroutine jfo_system_setup

  !> jfo_system_setup's node terms on explicit-shape arrays: the content's weights wv, the
  !> Couette and Poiseuille coefficients ca, kd of the faces, the pressure scales ps and the
  !> largest diagonal dmax.
  pure subroutine setup_nodes(n, a, w, dx, edge_cells, hmid, kmid, h, wv, ca, kd, ps, dmax)
    integer, intent(in) :: n
    real(dp), intent(in) :: a, w, dx, hmid(n - 1), kmid(n - 1), h(n)
    logical, intent(in) :: edge_cells
    real(dp), intent(out) :: wv(n), ca(n), kd(n), ps(n), dmax
    real(dp) :: t, d, q
    integer :: i
    wv = w
    if (edge_cells) then
      wv(2) = wv(2) + 0.5_dp * w
      wv(n - 1) = wv(n - 1) + 0.5_dp * w
    end if
    ca(1:n - 1) = a * hmid
    kd(1:n - 1) = kmid / dx
    ca(n) = 0.0_dp
    kd(n) = 0.0_dp
    ! pressure per unit v on the full side: the ratio of a node's fill and pressure diagonals,
    ! so that both sides of the kink weigh alike; and the largest of either diagonal
    ps(1) = 1.0_dp
    ps(n) = 1.0_dp
    dmax = 0.0_dp
    do i = 2, n - 1
      t = wv(i) * h(i) + abs(ca(i)) + abs(ca(i - 1))
      d = kd(i - 1) + kd(i)
      q = 1.0_dp
      if (t > 0.0_dp .and. d > 0.0_dp) q = t / d
      ps(i) = q
      dmax = max(dmax, t, d * q)
    end do
  end subroutine setup_nodes

  !> The residual res of the interior finite volumes at the state x and the scale of its
  !> terms; in ev the node states pn, tn, the face fluxes fl and their derivatives, and with jac
  !> also the Jacobian rows jl, jd, ju on this piece.
  !> Face f (nodes f, f+1): F = a theta_up hmid - g theta_P, g = kmid (p(f+1) - p(f))/dx, the
  !> Couette content upwind by the sign of a, the pressure-driven content upwind by the sign of g
  !> (full film: theta_P = 1; a cavity pushed out by a higher pressure carries oil fraction
  !> theta, the rest is gas).
  pure subroutine jfo_residual(sys, x, res, scale, jac, ev)
    type(jfo_system), intent(in) :: sys
    real(dp), intent(in) :: x(:)
    real(dp), intent(out) :: res(:), scale
    logical, intent(in) :: jac
    type(jfo_eval), intent(inout) :: ev
    real(dp) :: g, tp, s
    real(dp), allocatable :: fe(:), fed(:), fel(:), feu(:)
    integer :: j
    associate (n => sys%n, a => sys%a, w => sys%w, wv => sys%wv, ca => sys%ca, kd => sys%kd, ps => sys%ps, &
               h => sys%h, content_old => sys%content_old, p_left => sys%p_left, &
               p_right => sys%p_right, theta_left => sys%theta_left, &
               theta_right => sys%theta_right, qcl => sys%qcl, qcr => sys%qcr, pn => ev%pn, &
               tn => ev%tn, fl => ev%fl, dfpl => ev%dfpl, dfpr => ev%dfpr, dftl => ev%dftl, &
               dftr => ev%dftr, jl => ev%jl, jd => ev%jd, ju => ev%ju)
      pn(1) = p_left
      pn(n) = p_right
      tn(1) = theta_left
      tn(n) = theta_right
      do j = 2, n - 1
        pn(j) = node_p(sys, j, x(j))
        tn(j) = node_t(x(j))
      end do
      do j = 1, n - 1
        g = kd(j) * (pn(j + 1) - pn(j))
        dftl(j) = 0.0_dp
        dftr(j) = 0.0_dp
        if (g <= 0.0_dp) then
          tp = tn(j)
          dftl(j) = -g
        else
          tp = tn(j + 1)
          dftr(j) = -g
        end if
        if (a > 0.0_dp) then
          fl(j) = ca(j) * tn(j) - g * tp
          dftl(j) = dftl(j) + ca(j)
        else
          fl(j) = ca(j) * tn(j + 1) - g * tp
          dftr(j) = dftr(j) + ca(j)
        end if
        dfpl(j) = kd(j) * tp
        dfpr(j) = -kd(j) * tp
      end do
      if (sys%edge_meniscus) then
        if (a > 0.0_dp) call inflow_edge(sys, pn, tn, 1, fl(1), dfpl(1), dfpr(1), dftl(1), dftr(1))
        if (a < 0.0_dp) call inflow_edge(sys, pn, tn, n - 1, fl(n - 1), dfpl(n - 1), dfpr(n - 1), &
                                         dftl(n - 1), dftr(n - 1))
      end if
      ! oil entering through an edge face is capped at the oil there: beyond it the edge
      ! admits gas; the capped flux does not depend on the interior nodes
      if (fl(1) > qcl) then
        fl(1) = qcl
        dfpr(1) = 0.0_dp
        dftr(1) = 0.0_dp
      end if
      if (-fl(n - 1) > qcr) then
        fl(n - 1) = -qcr
        dfpl(n - 1) = 0.0_dp
        dftl(n - 1) = 0.0_dp
      end if
      scale = tiny(1.0_dp)
      res(1) = 0.0_dp
      res(n) = 0.0_dp
      do j = 2, n - 1
        res(j) = wv(j) * (tn(j) * h(j) - content_old(j)) + fl(j) - fl(j - 1)
        s = wv(j) * (abs(tn(j)) * h(j) + abs(content_old(j))) + abs(ca(j)) + abs(ca(j - 1)) &
            + kd(j) * (abs(pn(j + 1)) + abs(pn(j))) + kd(j - 1) * (abs(pn(j)) + abs(pn(j - 1)))
        scale = max(scale, s)
      end do
      if (sys%front_content) then
        allocate (fe(n), fed(n), fel(n), feu(n))
        call front_excess(n, a, ca, kd, ps, h, pn, tn, sys%edge_cells, sys%thin_fade_from, &
                          sys%thin_fade_width, sys%full_hd, fe, fed, fel, feu)
        res(2:n - 1) = res(2:n - 1) - w * fe(2:n - 1)
      end if
      if (.not. jac) return
      do j = 2, n - 1
        if (x(j) >= 0.0_dp) then
          jd(j) = (dfpl(j) - dfpr(j - 1)) * ps(j)
        else
          jd(j) = wv(j) * h(j) + dftl(j) - dftr(j - 1)
        end if
        if (j < n - 1) then
          if (x(j + 1) >= 0.0_dp) then
            ju(j) = dfpr(j) * ps(j + 1)
          else
            ju(j) = dftr(j)
          end if
        else
          ju(j) = 0.0_dp
        end if
        if (j > 2) then
          if (x(j - 1) >= 0.0_dp) then
            jl(j) = -dfpl(j - 1) * ps(j - 1)
          else
            jl(j) = -dftl(j - 1)
          end if
        else
          jl(j) = 0.0_dp
        end if
        if (sys%front_content) then
          ! the excess's derivatives (exact: the Jacobian need not keep its M-matrix pattern)
          jd(j) = jd(j) - w * fed(j)
          if (j > 2) jl(j) = jl(j) - w * fel(j)
          if (j < n - 1) ju(j) = ju(j) - w * feu(j)
        end if
      end do
    end associate
  end subroutine jfo_residual

  !> The residual of jfo_residual at the state x and, in the same pass over the nodes, the
  !> forward elimination of the Newton system J dv = -R on this piece (J as jfo_residual's
  !> rows jl, jd, ju, which are not stored): cp the eliminated upper diagonal, y the
  !> eliminated right-hand side, so that jfo_newton_step's back substitution gives the step.
  !> One pass instead of jfo_residual's four and the Thomas solve's forward sweep, with the
  !> same arithmetic (the states, residuals and steps are bit for bit those of jfo_residual
  !> and `thomas`). Also the residual's largest entry rmax and its sum of squares fsq. pivots:
  !> every pivot of the elimination nonzero (else y is not a step); signs: the Jacobian has
  !> the M-matrix sign pattern (diagonal > 0, off-diagonals <= 0; see ringlube_jfo).
  !> ev%pn, ev%tn, ev%fl hold the node states and face fluxes (ev's derivatives and Jacobian
  !> rows are not set).
  pure subroutine jfo_newton_eval(sys, x, res, scale, rmax, fsq, ev, cp, y, pivots, signs)
    type(jfo_system), intent(in) :: sys
    real(dp), intent(in), contiguous :: x(:)
    real(dp), intent(out), contiguous :: res(:), cp(:), y(:)
    real(dp), intent(out) :: scale, rmax, fsq
    type(jfo_eval), intent(inout) :: ev
    logical, intent(out) :: pivots, signs
    if (sys%front_content) then
      call newton_eval_front(sys, sys%n, sys%ca, sys%kd, sys%ps, sys%wv, sys%h, sys%content_old, &
                             x, res, scale, rmax, fsq, ev%pn, ev%tn, ev%fl, cp, y, pivots, signs)
      return
    end if
    call newton_eval_nodes(sys, sys%n, sys%ca, sys%kd, sys%ps, sys%pc, sys%wv, sys%h, &
                           sys%content_old, x, res, scale, rmax, fsq, ev%pn, ev%tn, ev%fl, cp, y, &
                           pivots, signs)
  end subroutine jfo_newton_eval

  !> jfo_newton_eval on explicit-shape arrays (contiguous, so indexed without descriptors).
  !> One node per pass of the loop, what the next node needs carried in scalars: the next
  !> node's state, the face before it (its flux and its derivatives by the right node), its
  !> row's sub-diagonal, the scale's conductance term of the shared face and the last pivot's
  !> quotients. The edge nodes' rows are the loop's first and last pass (jl = 0 by cp(1) = y(1)
  !> = 0, the same arithmetic; ju = 0 at the last); the edge faces' caps are applied at the
  !> first face before the loop and at the last one in its last pass.
  pure subroutine newton_eval_nodes(sys, n, ca, kd, ps, pc, wv, h, content_old, x, res, scale, &
                                    rmax, fsq, pn, tn, fl, cp, y, pivots, signs)
    type(jfo_system), intent(in) :: sys
    integer, intent(in) :: n
    real(dp), intent(in) :: ca(n), kd(n), ps(n), pc(n), wv(n), h(n), content_old(n), x(n)
    real(dp), intent(out) :: res(n), scale, rmax, fsq, cp(n), y(n)
    real(dp), intent(inout) :: pn(n), tn(n), fl(n)
    logical, intent(out) :: pivots, signs
    real(dp) :: s, jl, jd, ju, m, rr, rj, flj, flp
    ! the face before node j (f = j - 1, its derivatives by its right node) and after it (f =
    ! j); the states of nodes j and j + 1; the scale's terms of the faces before and after j
    real(dp) :: pl0, pr0, tl0, tr0, pl1, pr1, tl1, tr1, pj, tj, pk, tk, cl, cr, al, ar
    ! the last pivot's quotients; the scale, largest residual and sum of squares so far, and
    ! the flags (locals, kept in registers)
    real(dp) :: cpp, yp, sc, rm, fs
    logical :: apos, fullj, fullk, piv, sgn
    integer :: j
    apos = sys%a > 0.0_dp
    piv = .true.
    sgn = .true.
    pn(1) = sys%p_left
    pn(n) = sys%p_right
    tn(1) = sys%theta_left
    tn(n) = sys%theta_right
    pn(2) = pc(2) + ps(2) * max(x(2), 0.0_dp)
    tn(2) = 1.0_dp + min(x(2), 0.0_dp)
    call face_eval(sys, pn, tn, 1, fl(1), pl0, pr0, tl0, tr0)
    if (sys%edge_meniscus .and. apos) call inflow_edge(sys, pn, tn, 1, fl(1), pl0, pr0, tl0, tr0)
    if (fl(1) > sys%qcl) then
      fl(1) = sys%qcl
      pr0 = 0.0_dp
      tr0 = 0.0_dp
    end if
    flp = fl(1)
    sc = tiny(1.0_dp)
    rm = 0.0_dp
    fs = 0.0_dp
    res(1) = 0.0_dp
    res(n) = 0.0_dp
    ! the row of node 2 has no sub-diagonal: m = jd - 0 cp(1), rr = -R - 0 y(1)
    jl = 0.0_dp
    cpp = 0.0_dp
    yp = 0.0_dp
    cp(1) = 0.0_dp
    y(1) = 0.0_dp
    pj = pn(2)
    tj = tn(2)
    fullj = x(2) >= 0.0_dp
    cl = kd(1) * (abs(pj) + abs(pn(1)))
    al = abs(ca(1))
    do j = 2, n - 1
      if (j < n - 1) then
        pk = pc(j + 1) + ps(j + 1) * max(x(j + 1), 0.0_dp)
        tk = 1.0_dp + min(x(j + 1), 0.0_dp)
        pn(j + 1) = pk
        tn(j + 1) = tk
        fullk = x(j + 1) >= 0.0_dp
      else
        pk = pn(n)
        tk = tn(n)
        fullk = .false.
      end if
      call face_terms(kd(j), ca(j), pj, pk, tj, tk, apos, flj, pl1, pr1, tl1, tr1)
      if (j == n - 1) then
        fl(j) = flj
        if (sys%edge_meniscus .and. sys%a < 0.0_dp) &
          call inflow_edge(sys, pn, tn, j, fl(j), pl1, pr1, tl1, tr1)
        if (-fl(j) > sys%qcr) then
          fl(j) = -sys%qcr
          pl1 = 0.0_dp
          tl1 = 0.0_dp
        end if
        flj = fl(j)
      end if
      fl(j) = flj
      rj = wv(j) * (tj * h(j) - content_old(j)) + flj - flp
      res(j) = rj
      ar = abs(ca(j))
      cr = kd(j) * (abs(pk) + abs(pj))
      s = wv(j) * (abs(tj) * h(j) + abs(content_old(j))) + ar + al + cr + cl
      sc = max(sc, s)
      rm = max(rm, abs(rj))
      fs = fs + rj**2
      ! the Jacobian's row j on this piece (as jfo_residual); the next row's sub-diagonal
      if (fullj) then
        jd = (pl1 - pr0) * ps(j)
      else
        jd = wv(j) * h(j) + tl1 - tr0
      end if
      ju = 0.0_dp
      if (j < n - 1) then
        if (fullk) then
          ju = pr1 * ps(j + 1)
        else
          ju = tr1
        end if
      end if
      if (.not. jd > 0.0_dp .or. jl > 0.0_dp .or. ju > 0.0_dp) sgn = .false.
      ! forward elimination (as `thomas`), right-hand side -R
      if (piv) then
        m = jd - jl * cpp
        rr = -rj - jl * yp
        if (m == 0.0_dp) then
          piv = .false.
        else
          m = 1.0_dp / m
          cpp = ju * m
          yp = rr * m
          cp(j) = cpp
          y(j) = yp
        end if
      end if
      if (fullj) then
        jl = -pl1 * ps(j)
      else
        jl = -tl1
      end if
      pr0 = pr1
      tr0 = tr1
      flp = flj
      pj = pk
      tj = tk
      fullj = fullk
      cl = cr
      al = ar
    end do
    scale = sc
    rmax = rm
    fsq = fs
    pivots = piv
    signs = sgn
  end subroutine newton_eval_nodes

  !> Flux fl through a face between two nodes of pressures pl, pr and fills tl, tr, and its
  !> derivatives by the pressure (dpl, dpr) and fill (dtl, dtr) of its left and right node,
  !> as face_eval (kdf = kd(f), caf = ca(f); apos: a > 0, the Couette content from the left).
  pure subroutine face_terms(kdf, caf, pl, pr, tl, tr, apos, fl, dpl, dpr, dtl, dtr)
    real(dp), intent(in) :: kdf, caf, pl, pr, tl, tr
    logical, intent(in) :: apos
    real(dp), intent(out) :: fl, dpl, dpr, dtl, dtr
    real(dp) :: g, tp
    g = kdf * (pr - pl)
    dtl = 0.0_dp
    dtr = 0.0_dp
    if (g <= 0.0_dp) then
      tp = tl
      dtl = -g
    else
      tp = tr
      dtr = -g
    end if
    if (apos) then
      fl = caf * tl - g * tp
      dtl = dtl + caf
    else
      fl = caf * tr - g * tp
      dtr = dtr + caf
    end if
    dpl = kdf * tp
    dpr = -kdf * tp
  end subroutine face_terms

  !> The residual of jfo_residual at the state x alone (no derivatives), in one pass: res, its
  !> scale, largest entry rmax and sum of squares fsq, the node states and face fluxes in ev
  !> (bit for bit jfo_residual's). For the test after a Newton step, which is usually the last.
  pure subroutine jfo_residual_only(sys, x, res, scale, rmax, fsq, ev)
    type(jfo_system), intent(in) :: sys
    real(dp), intent(in), contiguous :: x(:)
    real(dp), intent(out), contiguous :: res(:)
    real(dp), intent(out) :: scale, rmax, fsq
    type(jfo_eval), intent(inout) :: ev
    if (sys%front_content) then
      call residual_front(sys, sys%n, sys%ca, sys%kd, sys%wv, sys%h, sys%content_old, x, res, &
                          scale, rmax, fsq, ev%pn, ev%tn, ev%fl)
      return
    end if
    call residual_nodes(sys, sys%n, sys%ca, sys%kd, sys%wv, sys%h, sys%content_old, x, res, scale, &
                        rmax, fsq, ev%pn, ev%tn, ev%fl)
  end subroutine jfo_residual_only

  !> jfo_residual_only on explicit-shape arrays (contiguous, so indexed without descriptors);
  !> with `fe` (jfo_problem%front_content) the fronts' excess in the storage.
  pure subroutine residual_nodes(sys, n, ca, kd, wv, h, content_old, x, res, scale, rmax, fsq, &
                                 pn, tn, fl, fe)
    type(jfo_system), intent(in) :: sys
    integer, intent(in) :: n
    real(dp), intent(in) :: ca(n), kd(n), wv(n), h(n), content_old(n), x(n)
    real(dp), intent(out) :: res(n), scale, rmax, fsq
    real(dp), intent(inout) :: pn(n), tn(n), fl(n)
    real(dp), intent(in), optional :: fe(n)
    real(dp) :: s, g, d1, d2, d3, d4
    integer :: j
    associate (a => sys%a, w => sys%w, qcl => sys%qcl, qcr => sys%qcr)
      pn(1) = sys%p_left
      pn(n) = sys%p_right
      tn(1) = sys%theta_left
      tn(n) = sys%theta_right
      pn(2) = node_p(sys, 2, x(2))
      tn(2) = node_t(x(2))
      scale = tiny(1.0_dp)
      rmax = 0.0_dp
      fsq = 0.0_dp
      res(1) = 0.0_dp
      res(n) = 0.0_dp
      do j = 1, n - 1
        if (j + 1 < n) then
          pn(j + 1) = node_p(sys, j + 1, x(j + 1))
          tn(j + 1) = node_t(x(j + 1))
        end if
        g = kd(j) * (pn(j + 1) - pn(j))
        if (a > 0.0_dp) then
          fl(j) = ca(j) * tn(j) - g * merge(tn(j), tn(j + 1), g <= 0.0_dp)
        else
          fl(j) = ca(j) * tn(j + 1) - g * merge(tn(j), tn(j + 1), g <= 0.0_dp)
        end if
        if (sys%edge_meniscus) then
          if ((j == 1 .and. a > 0.0_dp) .or. (j == n - 1 .and. a < 0.0_dp)) &
            call inflow_edge(sys, pn, tn, j, fl(j), d1, d2, d3, d4)
        end if
        if (j == 1) then
          if (fl(1) > qcl) fl(1) = qcl
          cycle
        end if
        if (j == n - 1) then
          if (-fl(n - 1) > qcr) fl(n - 1) = -qcr
        end if
        res(j) = wv(j) * (tn(j) * h(j) - content_old(j)) + fl(j) - fl(j - 1)
        if (present(fe)) res(j) = res(j) - w * fe(j)
        s = wv(j) * (abs(tn(j)) * h(j) + abs(content_old(j))) + abs(ca(j)) + abs(ca(j - 1)) &
            + kd(j) * (abs(pn(j + 1)) + abs(pn(j))) + kd(j - 1) * (abs(pn(j)) + abs(pn(j - 1)))
        scale = max(scale, s)
        rmax = max(rmax, abs(res(j)))
        fsq = fsq + res(j)**2
      end do
    end associate
  end subroutine residual_nodes

  !> jfo_newton_eval with jfo_problem%front_content (its own routine, so that the one-pass
  !> evaluation above stays as it is): the fronts' excess (`front_excess`) in the residual's
  !> storage and its derivatives in the Jacobian's rows, then the same forward elimination.
  pure subroutine newton_eval_front(sys, n, ca, kd, ps, wv, h, content_old, x, res, scale, rmax, &
                                    fsq, pn, tn, fl, cp, y, pivots, signs)
    type(jfo_system), intent(in) :: sys
    integer, intent(in) :: n
    real(dp), intent(in) :: ca(n), kd(n), ps(n), wv(n), h(n), content_old(n), x(n)
    real(dp), intent(out) :: res(n), scale, rmax, fsq, cp(n), y(n)
    real(dp), intent(inout) :: pn(n), tn(n), fl(n)
    logical, intent(out) :: pivots, signs
    real(dp) :: s, jl, jd, ju, m, rr
    ! the face before node j (f = j - 1) and after it (f = j): flux derivatives
    real(dp) :: pl0, pr0, tl0, tr0, pl1, pr1, tl1, tr1
    real(dp), allocatable :: fe(:), fed(:), fel(:), feu(:)
    integer :: j
    associate (a => sys%a, w => sys%w, qcl => sys%qcl, qcr => sys%qcr)
      ! the fronts' excess needs every node's state first
      allocate (fe(n), fed(n), fel(n), feu(n))
      pn(1) = sys%p_left
      pn(n) = sys%p_right
      tn(1) = sys%theta_left
      tn(n) = sys%theta_right
      do j = 2, n - 1
        pn(j) = node_p(sys, j, x(j))
        tn(j) = node_t(x(j))
      end do
      call front_excess(n, a, ca, kd, ps, h, pn, tn, sys%edge_cells, sys%thin_fade_from, &
                        sys%thin_fade_width, sys%full_hd, fe, fed, fel, feu)
      pivots = .true.
      signs = .true.
      pn(1) = sys%p_left
      pn(n) = sys%p_right
      tn(1) = sys%theta_left
      tn(n) = sys%theta_right
      pn(2) = node_p(sys, 2, x(2))
      tn(2) = node_t(x(2))
      call face_eval(sys, pn, tn, 1, fl(1), pl0, pr0, tl0, tr0)
      if (sys%edge_meniscus .and. sys%a > 0.0_dp) &
        call inflow_edge(sys, pn, tn, 1, fl(1), pl0, pr0, tl0, tr0)
      if (fl(1) > qcl) then
        fl(1) = qcl
        pr0 = 0.0_dp
        tr0 = 0.0_dp
      end if
      scale = tiny(1.0_dp)
      rmax = 0.0_dp
      fsq = 0.0_dp
      res(1) = 0.0_dp
      res(n) = 0.0_dp
      do j = 2, n - 1
        if (j + 1 < n) then
          pn(j + 1) = node_p(sys, j + 1, x(j + 1))
          tn(j + 1) = node_t(x(j + 1))
        end if
        call face_eval(sys, pn, tn, j, fl(j), pl1, pr1, tl1, tr1)
        if (j == n - 1) then
          if (sys%edge_meniscus .and. sys%a < 0.0_dp) &
            call inflow_edge(sys, pn, tn, j, fl(j), pl1, pr1, tl1, tr1)
          if (-fl(n - 1) > qcr) then
            fl(n - 1) = -qcr
            pl1 = 0.0_dp
            tl1 = 0.0_dp
          end if
        end if
        res(j) = wv(j) * (tn(j) * h(j) - content_old(j)) + fl(j) - fl(j - 1)
        res(j) = res(j) - w * fe(j)
        s = wv(j) * (abs(tn(j)) * h(j) + abs(content_old(j))) + abs(ca(j)) + abs(ca(j - 1)) &
            + kd(j) * (abs(pn(j + 1)) + abs(pn(j))) + kd(j - 1) * (abs(pn(j)) + abs(pn(j - 1)))
        scale = max(scale, s)
        rmax = max(rmax, abs(res(j)))
        fsq = fsq + res(j)**2
        ! the Jacobian's row j on this piece (as jfo_residual)
        if (x(j) >= 0.0_dp) then
          jd = (pl1 - pr0) * ps(j)
        else
          jd = wv(j) * h(j) + tl1 - tr0
        end if
        ju = 0.0_dp
        if (j < n - 1) then
          if (x(j + 1) >= 0.0_dp) then
            ju = pr1 * ps(j + 1)
          else
            ju = tr1
          end if
        end if
        jl = 0.0_dp
        if (j > 2) then
          if (x(j - 1) >= 0.0_dp) then
            jl = -pl0 * ps(j - 1)
          else
            jl = -tl0
          end if
        end if
        ! the excess's exact derivatives: they break the M-matrix sign pattern without making
        ! the step wrong, so signs stays .true. (the pivots alone decide)
        jd = jd - w * fed(j)
        if (j > 2) jl = jl - w * fel(j)
        if (j < n - 1) ju = ju - w * feu(j)
        ! forward elimination (as `thomas`), right-hand side -R
        if (pivots) then
          if (j == 2) then
            m = jd
            rr = -res(j)
          else
            m = jd - jl * cp(j - 1)
            rr = -res(j) - jl * y(j - 1)
          end if
          if (m == 0.0_dp) then
            pivots = .false.
          else
            m = 1.0_dp / m
            cp(j) = ju * m
            y(j) = rr * m
          end if
        end if
        pl0 = pl1
        pr0 = pr1
        tl0 = tl1
        tr0 = tr1
      end do
    end associate
  end subroutine newton_eval_front

  !> jfo_residual_only with jfo_problem%front_content (its own routine, as newton_eval_front):
  !> the residual with the fronts' excess in the storage.
  pure subroutine residual_front(sys, n, ca, kd, wv, h, content_old, x, res, scale, rmax, fsq, &
                                 pn, tn, fl)
    type(jfo_system), intent(in) :: sys
    integer, intent(in) :: n
    real(dp), intent(in) :: ca(n), kd(n), wv(n), h(n), content_old(n), x(n)
    real(dp), intent(out) :: res(n), scale, rmax, fsq
    real(dp), intent(inout) :: pn(n), tn(n), fl(n)
    real(dp), allocatable :: fe(:), fed(:), fel(:), feu(:)
    integer :: j
    allocate (fe(n), fed(n), fel(n), feu(n))
    pn(1) = sys%p_left
    pn(n) = sys%p_right
    tn(1) = sys%theta_left
    tn(n) = sys%theta_right
    do j = 2, n - 1
      pn(j) = node_p(sys, j, x(j))
      tn(j) = node_t(x(j))
    end do
    call front_excess(n, sys%a, ca, kd, sys%ps, h, pn, tn, sys%edge_cells, sys%thin_fade_from, &
                      sys%thin_fade_width, sys%full_hd, fe, fed, fel, feu)
    call residual_nodes(sys, n, ca, kd, wv, h, content_old, x, res, scale, rmax, fsq, pn, tn, fl, &
                        fe)
  end subroutine residual_front

  !> Flux fl through face f (nodes f, f+1) at the node states pn, tn and its derivatives by
  !> the pressure (dpl, dpr) and fill (dtl, dtr) of its left and right node, as jfo_residual.
  pure subroutine face_eval(sys, pn, tn, f, fl, dpl, dpr, dtl, dtr)
    type(jfo_system), intent(in) :: sys
    real(dp), intent(in), contiguous :: pn(:), tn(:)
    integer, intent(in) :: f
    real(dp), intent(out) :: fl, dpl, dpr, dtl, dtr
    real(dp) :: g, tp
    associate (kd => sys%kd, ca => sys%ca)
      g = kd(f) * (pn(f + 1) - pn(f))
      dtl = 0.0_dp
      dtr = 0.0_dp
      if (g <= 0.0_dp) then
        tp = tn(f)
        dtl = -g
      else
        tp = tn(f + 1)
        dtr = -g
      end if
      if (sys%a > 0.0_dp) then
        fl = ca(f) * tn(f) - g * tp
        dtl = dtl + ca(f)
      else
        fl = ca(f) * tn(f + 1) - g * tp
        dtr = dtr + ca(f)
      end if
      dpl = kd(f) * tp
      dpr = -kd(f) * tp
    end associate
  end subroutine face_eval

  !> The inflow edge face f (1 when a > 0, n - 1 when a < 0) with the film pushing oil back
  !> out through it (the pressure-driven flow leaves through the edge, from a node of fill tp):
  !> the face lies in the film that reaches the edge (a meniscus at the edge, the oil it rejects
  !> left to the bank ahead), so its flux is the lesser inflow of the supply's Couette content
  !> a theta_in hmid and the face's flux with the node's fill in the Couette term too,
  !> a tp hmid - g tp; with tp <= theta_in (or theta_in = 1) the flux as before. Continuous in
  !> the state (at g = 0 and tp = theta_in it is the flux before); fl and its derivatives by
  !> the pressure (dpl, dpr) and fill (dtl, dtr) of the face's nodes in place.
  pure subroutine inflow_edge(sys, pn, tn, f, fl, dpl, dpr, dtl, dtr)
    type(jfo_system), intent(in) :: sys
    real(dp), intent(in) :: pn(:), tn(:)
    integer, intent(in) :: f
    real(dp), intent(inout) :: fl, dpl, dpr, dtl, dtr
    real(dp) :: g, e, fs
    associate (ca => sys%ca(f))
      g = sys%kd(f) * (pn(f + 1) - pn(f))
      if (sys%a > 0.0_dp) then
        ! inflow through the left edge (node f = 1, fill theta_in), pushed back by node 2
        if (.not. g > 0.0_dp) return
        e = ca * (tn(f + 1) - tn(f))
        if (.not. e > 0.0_dp) return
        fs = ca * tn(f)
        if (fl + e < fs) then
          fl = fl + e
          dtr = dtr + ca
        else
          fl = fs
          dpl = 0.0_dp
          dpr = 0.0_dp
          dtl = 0.0_dp
          dtr = 0.0_dp
        end if
      else
        ! inflow through the right edge (node f + 1 = n), pushed back by node n - 1
        if (.not. g < 0.0_dp) return
        e = ca * (tn(f) - tn(f + 1))
        if (.not. e < 0.0_dp) return
        fs = ca * tn(f + 1)
        if (fl + e > fs) then
          fl = fl + e
          dtl = dtl + ca
        else
          fl = fs
          dpl = 0.0_dp
          dpr = 0.0_dp
          dtl = 0.0_dp
          dtr = 0.0_dp
        end if
      end if
    end associate
  end subroutine inflow_edge

  !> The oil a reformation front's two cells hold beyond the film with the front where the
  !> pressures place it (docs/film_model.md, "The reformation front"), e(i) per node (content
  !> per dx: the residual's storage of node i is wv(i) theta h - w e(i)), and its exact
  !> derivatives by v of node i (ed), i - 1 (el) and i + 1 (eu). A front: a partly filled node U
  !> (fill theta_U < 1) whose neighbour D downstream in the Couette flow is full. With
  !> A = p_D - p_U and B = (1 - theta_U) |a hmid| / kd, the front lies a fraction
  !> s = A / (A + B) from D to U, h_f the gap there; with fac = 1/2 + s (vol_U - 1) (vol_U the
  !> volume of U's cell in dx: 1.5 next to an edge with edge cells) D holds
  !> (1 - s) fac (1 - theta_U) h_f and U holds s fac (1 - theta_Q) h_f more than the film with
  !> that front (theta_Q the fill of the node upstream of U): D's share is the oil missing
  !> ahead of a front in D's half (U's fill), U's the oil missing ahead of a front in U's half
  !> (Q's fill). Continuous when U fills (s = 1: the pair (Q, U) starts with the same on U) and
  !> when D empties (s = 0: the pair (D, D2) ends with the same on D), and each share depends
  !> only on its node and its two neighbours (the Jacobian stays tridiagonal). A lone full node
  !> (its neighbour downstream partly filled: no pair takes over when it empties) scales both
  !> by s. With edge cells, a full node D next to the inflow edge U (fill theta_U < 1): the
  !> front a fraction s = A / B (in [0, 1]) from D to the edge and D holds
  !> (1 - s) (1 - theta_U) h_f (the interior pair's at s = 1 when D fills; 0 with the film full
  !> to the edge). And every partly filled node of fill up to 0.3 holds theta (h - hd) more
  !> (times its volume in dx), hd the gap at the face it leaves through: it stores theta hd, the
  !> content its Couette flux a theta hd carries (in a starved inlet zone the supply's content,
  !> which theta h exceeds by theta (h - hd), a fraction of a cell's gap change), so that a
  !> front sweeping the zone fills each cell with the oil the supply lacks there
  !> (docs/film_model.md, "The oil turned back"); from 0.3 to 0.6 that share falls to 0 by a
  !> smoothstep in theta (continuous, with its derivative), above it theta h as before (0.3
  !> and the width 0.3 by default: tf0 and tfw, jfo_problem%thin_fade_from and thin_fade_width;
  !> fhd, jfo_problem%full_hd, a bench-only variant of the full nodes' content).
  pure subroutine front_excess(n, a, ca, kd, ps, h, pn, tn, edge_cells, tf0, tfw, fhd, e, ed, el, &
                               eu)
    integer, intent(in) :: n
    real(dp), intent(in) :: a, ca(n), kd(n), ps(n), h(n), pn(n), tn(n)
    logical, intent(in) :: edge_cells
    real(dp), intent(in) :: tf0, tfw
    logical, intent(in) :: fhd
    real(dp), intent(out) :: e(n), ed(n), el(n), eu(n)
    real(dp) :: c, aa, bb, sf, hf, fac, dsd, dsu, vu, ku, kq, gd, gu, gdp, gup, dkq, tt, gg, gp
    logical :: lone
    integer :: iu, id, iq, f, dn, i2
    real(dp) :: sd, sr, dsdl, dsdu, dsrl, dsrr, hh, a1, b1, c1, vl
    integer :: il, iup, ir, f1
    e = 0.0_dp
    ed = 0.0_dp
    el = 0.0_dp
    eu = 0.0_dp
    if (a == 0.0_dp) return
    dn = merge(-1, 1, a < 0.0_dp)
    ! a thinly filled node stores what its Couette flux carries, theta hd (hd the gap at the
    ! face it leaves through), not theta h: it holds theta g (h - hd) more, g = 1 up to a fill
    ! of 0.3, a smoothstep to 0 at 0.6 (so that a node filling, or a cavity's nearly full
    ! nodes around a lone full node, keep theta h: continuous, and Newton converges as before)
    do iu = 2, n - 1
      if (.not. tn(iu) < 1.0_dp) cycle
      vu = 1.0_dp
      if (edge_cells .and. (iu == 2 .or. iu == n - 1)) vu = 1.5_dp
      hf = h(iu) - ca(merge(iu - 1, iu, a < 0.0_dp)) / a
      tt = min(max((tn(iu) - tf0) / tfw, 0.0_dp), 1.0_dp)
      gg = 1.0_dp - tt**2 * (3.0_dp - 2.0_dp * tt)
      gp = -6.0_dp * tt * (1.0_dp - tt) / tfw
      e(iu) = e(iu) + vu * tn(iu) * gg * hf
      ed(iu) = ed(iu) + vu * (gg + tn(iu) * gp) * hf
    end do
    do iu = 2, n - 1
      id = iu + dn
      ! D interior and not next to the edge downstream (a film full to that edge has no front)
      if (id + dn < 2 .or. id + dn > n - 1) cycle
      if (.not. (tn(iu) < 1.0_dp .and. tn(id) >= 1.0_dp)) cycle
      f = min(iu, id)
      c = abs(ca(f))
      if (.not. (c > 0.0_dp .and. kd(f) > 0.0_dp)) cycle
      iq = iu - dn
      aa = max(pn(id) - pn(iu), 0.0_dp)
      bb = (1.0_dp - tn(iu)) * c / kd(f)
      sf = aa / (aa + bb)
      ! ds by v of D (its pressure) and of U (its fill)
      dsd = 0.0_dp
      if (pn(id) - pn(iu) > 0.0_dp) dsd = bb / (aa + bb)**2 * ps(id)
      dsu = aa * c / (kd(f) * (aa + bb)**2)
      vu = 1.0_dp
      if (edge_cells .and. (iu == 2 .or. iu == n - 1)) vu = 1.5_dp
      fac = 0.5_dp + sf * (vu - 1.0_dp)
      hf = h(id) + sf * (h(iu) - h(id))
      ku = 1.0_dp - tn(iu)
      kq = max(1.0_dp - tn(iq), 0.0_dp)
      ! dkq: d kq / d v_Q where Q is an unknown (interior) and partly filled
      dkq = 0.0_dp
      if (iq >= 2 .and. iq <= n - 1 .and. 1.0_dp - tn(iq) > 0.0_dp) dkq = -1.0_dp
      ! the shares per unit fill deficit, gd(s) = (1 - s) fac hf and gu(s) = s fac hf, and
      ! their derivatives by s
      gd = (1.0_dp - sf) * fac * hf
      gu = sf * fac * hf
      gdp = -fac * hf + (1.0_dp - sf) * ((vu - 1.0_dp) * hf + fac * (h(iu) - h(id)))
      gup = fac * hf + sf * ((vu - 1.0_dp) * hf + fac * (h(iu) - h(id)))
      ! D the only full node (its neighbour downstream partly filled, or next to the edge):
      ! both shares scaled by s, so that they vanish when D empties
      i2 = id + dn
      lone = i2 + dn < 2 .or. i2 + dn > n - 1
      if (.not. lone) lone = tn(i2) < 1.0_dp
      if (lone) then
        gdp = gd + sf * gdp
        gup = gu + sf * gup
        gd = sf * gd
        gu = sf * gu
      end if
      e(id) = e(id) + gd * ku
      e(iu) = e(iu) + gu * kq
      ! by v_D
      ed(id) = ed(id) + gdp * dsd * ku
      ! by v_U (the fill of U: ku by -1)
      ed(iu) = ed(iu) + gup * dsu * kq
      if (dn > 0) then
        ! U = D - 1, Q = U - 1
        el(id) = el(id) + gdp * dsu * ku - gd
        eu(iu) = eu(iu) + gup * dsd * kq
        el(iu) = el(iu) + gu * dkq
      else
        ! U = D + 1, Q = U + 1
        eu(id) = eu(id) + gdp * dsu * ku - gd
        el(iu) = el(iu) + gup * dsd * kq
        eu(iu) = eu(iu) + gu * dkq
      end if
    end do
    if (fhd) then
      ! (bench only) a full node next to a partly filled one stores hd + sd sr (h - hd): sd the
      ! front's s with the partly filled node upstream (1 without one), sr the same with the
      ! one downstream, so that it stores hd, as the partly filled nodes then all do, when it
      ! empties towards either, and h once its pressure has risen above both fronts' scale
      do il = 2, n - 1
        if (tn(il) < 1.0_dp) cycle
        iup = il - dn
        ir = il + dn
        sd = 1.0_dp
        dsdl = 0.0_dp
        dsdu = 0.0_dp
        if (tn(iup) < 1.0_dp) then
          f1 = min(il, iup)
          c1 = abs(ca(f1))
          if (c1 > 0.0_dp .and. kd(f1) > 0.0_dp) then
            a1 = max(pn(il) - pn(iup), 0.0_dp)
            b1 = (1.0_dp - tn(iup)) * c1 / kd(f1)
            if (iup == 1 .or. iup == n) then
              sd = min(a1 / b1, 1.0_dp)
              if (a1 > 0.0_dp .and. a1 < b1) dsdl = ps(il) / b1
            else
              sd = a1 / (a1 + b1)
              if (pn(il) - pn(iup) > 0.0_dp) dsdl = b1 / (a1 + b1)**2 * ps(il)
              dsdu = a1 * c1 / (kd(f1) * (a1 + b1)**2)
            end if
          end if
        end if
        sr = 1.0_dp
        dsrl = 0.0_dp
        dsrr = 0.0_dp
        if (ir >= 2 .and. ir <= n - 1) then
          if (tn(ir) < 1.0_dp) then
            f1 = min(il, ir)
            c1 = abs(ca(f1))
            if (c1 > 0.0_dp .and. kd(f1) > 0.0_dp) then
              a1 = max(pn(il) - pn(ir), 0.0_dp)
              b1 = (1.0_dp - tn(ir)) * c1 / kd(f1)
              sr = a1 / (a1 + b1)
              if (pn(il) - pn(ir) > 0.0_dp) dsrl = b1 / (a1 + b1)**2 * ps(il)
              dsrr = a1 * c1 / (kd(f1) * (a1 + b1)**2)
            else
              sr = 0.0_dp
            end if
          end if
        end if
        vl = 1.0_dp
        if (edge_cells .and. (il == 2 .or. il == n - 1)) vl = 1.5_dp
        hh = vl * (h(il) - ca(merge(il - 1, il, a < 0.0_dp)) / a)
        e(il) = e(il) + (1.0_dp - sd * sr) * hh
        ed(il) = ed(il) - (dsdl * sr + sd * dsrl) * hh
        ! by v of the upstream node (its fill: 1 - theta by -1, so ds by v = dsdu) and of the
        ! downstream one
        if (dn > 0) then
          el(il) = el(il) - sr * dsdu * hh
          eu(il) = eu(il) - sd * dsrr * hh
        else
          eu(il) = eu(il) - sr * dsdu * hh
          el(il) = el(il) - sd * dsrr * hh
        end if
      end do
    end if
    if (.not. edge_cells) return
    ! the full node next to the inflow edge with the meniscus between them
    if (dn < 0) then
      iu = n
    else
      iu = 1
    end if
    id = iu + dn
    if (.not. (tn(iu) < 1.0_dp .and. tn(id) >= 1.0_dp)) return
    f = min(iu, id)
    c = abs(ca(f))
    if (.not. (c > 0.0_dp .and. kd(f) > 0.0_dp)) return
    kq = 1.0_dp - tn(iu)
    bb = kq * c / kd(f)
    aa = pn(id) - pn(iu)
    sf = min(max(aa / bb, 0.0_dp), 1.0_dp)
    hf = h(id) + sf * (h(iu) - h(id))
    e(id) = e(id) + (1.0_dp - sf) * kq * hf
    if (aa > 0.0_dp .and. aa < bb) &
      ed(id) = ed(id) + (-kq * hf + (1.0_dp - sf) * kq * (h(iu) - h(id))) * ps(id) / bb
  end subroutine front_excess

  !> The content of each node of a film state p, theta for jfo_problem%front_content (the
  !> next step's content_old): theta h less the reformation fronts' excess (`front_excess`)
  !> per unit of the node's volume; theta h at the edges and without the option or a step.
  pure function jfo_front_content(problem, h, hmid, kmid, pc, p, theta) result(c)
    type(jfo_problem), intent(in) :: problem
    real(dp), intent(in) :: h(:), hmid(:), kmid(:), pc(:), p(:), theta(:)
    real(dp) :: c(size(h))
    type(jfo_system) :: sys
    real(dp), allocatable :: e(:), d1(:), d2(:), d3(:), pn(:), tn(:)
    integer :: n, j
    n = size(h)
    c = theta * h
    if (.not. (problem%front_content .and. problem%dt > 0.0_dp .and. problem%edge_cells) &
        .or. n < 3) return
    call jfo_system_setup(sys, problem, h, hmid, kmid, c, pc)
    allocate (e(n), d1(n), d2(n), d3(n), pn(n), tn(n))
    pn = p
    tn = theta
    pn(1) = problem%p_left
    pn(n) = problem%p_right
    tn(1) = problem%theta_left
    tn(n) = problem%theta_right
    do j = 2, n - 1
      if (theta(j) < 1.0_dp) pn(j) = pc(j)
    end do
    call front_excess(n, sys%a, sys%ca, sys%kd, sys%ps, h, pn, tn, problem%edge_cells, &
                      sys%thin_fade_from, sys%thin_fade_width, sys%full_hd, e, d1, d2, d3)
    do j = 2, n - 1
      c(j) = c(j) - e(j) * sys%w / sys%wv(j)
    end do
  end function jfo_front_content

  !> The Newton step from jfo_newton_eval's elimination (back substitution): dv on the
  !> interior nodes, 0 at the edges.
  pure subroutine jfo_newton_step(n, cp, y, dv)
    integer, intent(in) :: n
    real(dp), intent(in), contiguous :: cp(:), y(:)
    real(dp), intent(out), contiguous :: dv(:)
    integer :: j
    dv(1) = 0.0_dp
    dv(n) = 0.0_dp
    dv(n - 1) = y(n - 1)
    do j = n - 2, 2, -1
      dv(j) = y(j) - cp(j) * dv(j + 1)
    end do
  end subroutine jfo_newton_step

  !> The full Newton step from jfo_newton_eval's elimination, taken: jfo_newton_step's back
  !> substitution and v = v + dv in the same backward pass (the same arithmetic), and the
  !> number of nodes whose side of the kink (v < 0 or not) the step switched.
  pure subroutine jfo_newton_apply(n, cp, y, dv, v, nswitch)
    integer, intent(in) :: n
    real(dp), intent(in), contiguous :: cp(:), y(:)
    real(dp), intent(out), contiguous :: dv(:)
    real(dp), intent(inout), contiguous :: v(:)
    integer, intent(out) :: nswitch
    call newton_apply_nodes(n, cp, y, dv, v, nswitch)
  end subroutine jfo_newton_apply

  pure subroutine newton_apply_nodes(n, cp, y, dv, v, nswitch)
    integer, intent(in) :: n
    real(dp), intent(in) :: cp(n), y(n)
    real(dp), intent(out) :: dv(n)
    real(dp), intent(inout) :: v(n)
    integer, intent(out) :: nswitch
    real(dp) :: vn
    integer :: j
    dv(1) = 0.0_dp
    dv(n) = 0.0_dp
    dv(n - 1) = y(n - 1)
    nswitch = 0
    vn = v(n - 1) + dv(n - 1)
    if ((v(n - 1) < 0.0_dp) .neqv. (vn < 0.0_dp)) nswitch = nswitch + 1
    v(n - 1) = vn
    do j = n - 2, 2, -1
      dv(j) = y(j) - cp(j) * dv(j + 1)
      vn = v(j) + dv(j)
      if ((v(j) < 0.0_dp) .neqv. (vn < 0.0_dp)) nswitch = nswitch + 1
      v(j) = vn
    end do
  end subroutine newton_apply_nodes

  !> The universal variable v of a state p, theta of the step's system (a warm start):
  !> theta - 1 on a partly filled node, (p - pc)/ps (at least 0) on a full one, 0 where that
  !> is not finite and at the edges.
  pure subroutine jfo_state_to_v(sys, p, theta, v)
    type(jfo_system), intent(in) :: sys
    real(dp), intent(in) :: p(:), theta(:)
    real(dp), intent(out), contiguous :: v(:)
    call state_to_v_nodes(sys%n, sys%pc, sys%ps, p, theta, v)
  end subroutine jfo_state_to_v

  pure subroutine state_to_v_nodes(n, pc, ps, p, theta, v)
    integer, intent(in) :: n
    real(dp), intent(in) :: pc(n), ps(n), p(n), theta(n)
    real(dp), intent(out) :: v(n)
    integer :: i
    v(1) = 0.0_dp
    v(n) = 0.0_dp
    do i = 2, n - 1
      if (theta(i) < 1.0_dp) then
        v(i) = theta(i) - 1.0_dp
      else
        v(i) = max(p(i) - pc(i), 0.0_dp) / ps(i)
      end if
      ! not finite (NaN compares false)
      if (.not. abs(v(i)) <= huge(1.0_dp)) v(i) = 0.0_dp
    end do
  end subroutine state_to_v_nodes

  !> Projected Gauss-Seidel on v: each node solves its own equation (monotone in v(j)) with
  !> the neighbours fixed and the upwind choices of the current state, sweeping downstream.
  !> The edge caps apply as in the residual: at a node next to an edge, if the inflow through
  !> the edge face of the update exceeds the cap, the node is solved again with that face
  !> carrying the cap (a constant).
  pure subroutine jfo_gauss_seidel(sys, x, nsw, nsweep)
    type(jfo_system), intent(in) :: sys
    real(dp), intent(inout), contiguous :: x(:)
    integer, intent(in) :: nsw
    integer, intent(inout) :: nsweep
    call gauss_seidel_nodes(sys, sys%n, sys%ca, sys%kd, sys%ps, sys%pc, sys%wv, sys%h, &
                            sys%content_old, x, nsw, nsweep)
  end subroutine jfo_gauss_seidel

  !> jfo_gauss_seidel's sweeps on explicit-shape arrays (contiguous, indexed without the
  !> components' descriptors), a node's update on its own and its left face's terms.
  pure subroutine gauss_seidel_nodes(sys, n, ca, kd, ps, pc, wv, h, content_old, x, nsw, nsweep)
    type(jfo_system), intent(in) :: sys
    integer, intent(in) :: n, nsw
    real(dp), intent(in) :: ca(n), kd(n), ps(n), pc(n), wv(n), h(n), content_old(n)
    real(dp), intent(inout) :: x(n)
    integer, intent(inout) :: nsweep
    integer :: s, k, j, j0, j1, step
    real(dp) :: pl, pr, tl, tr
    logical :: capl, capr, again
    associate (a => sys%a, p_left => sys%p_left, p_right => sys%p_right, &
               theta_left => sys%theta_left, theta_right => sys%theta_right, qcl => sys%qcl, &
               qcr => sys%qcr)
      if (a >= 0.0_dp) then
        j0 = 2; j1 = n - 1; step = 1
      else
        j0 = n - 1; j1 = 2; step = -1
      end if
      do s = 1, nsw
        nsweep = nsweep + 1
        do k = j0, j1, step
          j = k
          pl = pc(j - 1) + ps(j - 1) * max(x(j - 1), 0.0_dp)
          tl = 1.0_dp + min(x(j - 1), 0.0_dp)
          if (j == 2) then
            pl = p_left
            tl = theta_left
          end if
          pr = pc(j + 1) + ps(j + 1) * max(x(j + 1), 0.0_dp)
          tr = 1.0_dp + min(x(j + 1), 0.0_dp)
          if (j == n - 1) then
            pr = p_right
            tr = theta_right
          end if
          capl = .false.
          capr = .false.
          do
            call node_update(a, qcl, qcr, ca(j - 1), ca(j), kd(j - 1), kd(j), pc(j), ps(j), &
                             wv(j), h(j), content_old(j), pl, pr, tl, tr, capl, capr, x(j))
            again = .false.
            if (j == 2 .and. .not. capl) then
              if (face_flux(sys, 1, pl, node_p(sys, j, x(j)), tl, node_t(x(j))) > qcl) capl = .true.
              again = capl
            end if
            if (j == n - 1 .and. .not. capr) then
             if (-face_flux(sys, j, node_p(sys, j, x(j)), pr, node_t(x(j)), tr) > qcr) capr = .true.
              again = again .or. capr
            end if
            if (.not. again) exit
          end do
        end do
      end do
    end associate
  end subroutine gauss_seidel_nodes

  !> Pressure and fill of node j at the universal variable xj (p = pc + ps max(v, 0),
  !> theta = 1 + min(v, 0)).
  pure real(dp) function node_p(sys, j, xj)
    type(jfo_system), intent(in) :: sys
    integer, intent(in) :: j
    real(dp), intent(in) :: xj
    associate (ps => sys%ps, pc => sys%pc)
      node_p = pc(j) + ps(j) * max(xj, 0.0_dp)
    end associate
  end function node_p

  pure real(dp) function node_t(xj)
    real(dp), intent(in) :: xj
    node_t = 1.0_dp + min(xj, 0.0_dp)
  end function node_t

  !> Flux through face f (nodes f, f+1) as in the residual.
  pure real(dp) function face_flux(sys, f, p0, p1, t0, t1)
    type(jfo_system), intent(in) :: sys
    integer, intent(in) :: f
    real(dp), intent(in) :: p0, p1, t0, t1
    real(dp) :: g
    associate (a => sys%a, ca => sys%ca, kd => sys%kd)
      g = kd(f) * (p1 - p0)
      face_flux = -g * merge(t0, t1, g <= 0.0_dp)
      if (a > 0.0_dp) then
        face_flux = face_flux + ca(f) * t0
      else
        face_flux = face_flux + ca(f) * t1
      end if
    end associate
  end function face_flux

  !> Node j's own equation with its neighbours (pl, tl), (pr, tr) fixed; with capl (capr)
  !> the left (right) face carries the constant inflow qcl (qcr). The system's terms of node j
  !> and of its faces: cal, car = ca(j-1), car; kdl, kdr = kd(j-1), kdr; pcj, psj, wvj, hj,
  !> coj = pc, ps, wv, h, content_old at j.
  pure subroutine node_update(a, qcl, qcr, cal, car, kdl, kdr, pcj, psj, wvj, hj, coj, pl, pr, &
                              tl, tr, capl, capr, xj)
    real(dp), intent(in) :: a, qcl, qcr, cal, car, kdl, kdr, pcj, psj, wvj, hj, coj
    real(dp), intent(in) :: pl, pr, tl, tr
    logical, intent(in) :: capl, capr
    real(dp), intent(out) :: xj
    real(dp) :: r0, dpr, dth, gl, gr, cl, cr, pj, rj, fl0, fr0
    integer :: q
    ! fluxes with p(j) = pc(j), theta(j) = 1 (v = 0): F(j) - F(j-1)
    gl = kdl * (pcj - pl)
    gr = kdr * (pr - pcj)
    cl = cal * tl
    cr = car * tr
    if (a > 0.0_dp) cr = car
    if (a < 0.0_dp) cl = cal
    fr0 = cr - gr * merge(1.0_dp, tr, gr <= 0.0_dp)
    fl0 = cl - gl * merge(tl, 1.0_dp, gl <= 0.0_dp)
    if (capl) fl0 = qcl
    if (capr) fr0 = -qcr
    r0 = wvj * (hj - coj) + fr0 - fl0
    if (r0 < 0.0_dp) then
      ! full film, p(j) > pc(j): R(p) is piecewise linear, increasing and convex in p
      ! (the pressure-driven content switches to theta = 1 once p(j) passes a neighbour),
      ! so Newton from p = pc reaches its root without overshoot in at most 3 steps
      pj = pcj
      rj = r0
      do q = 1, 4
        dpr = 0.0_dp
        if (.not. capr) dpr = dpr + kdr * merge(tr, 1.0_dp, pr > pj)
        if (.not. capl) dpr = dpr + kdl * merge(tl, 1.0_dp, pl > pj)
        if (.not. dpr > 0.0_dp) exit
        pj = pj - rj / dpr
        fr0 = cr - kdr * (pr - pj) * merge(tr, 1.0_dp, pr > pj)
        fl0 = cl - kdl * (pj - pl) * merge(tl, 1.0_dp, pl > pj)
        if (capl) fl0 = qcl
        if (capr) fr0 = -qcr
        rj = wvj * (hj - coj) + fr0 - fl0
        if (rj >= 0.0_dp) exit
      end do
      xj = (pj - pcj) / psj
    else
      ! cavity: theta(j) from the balance at p(j) = pc(j)
      dth = wvj * hj
      if (.not. capr) dth = dth + max(car, 0.0_dp) - min(gr, 0.0_dp)
      if (.not. capl) dth = dth - min(cal, 0.0_dp) + max(gl, 0.0_dp)
      if (dth > 0.0_dp) then
        xj = -r0 / dth
      else
        xj = 0.0_dp
      end if
    end if
  end subroutine node_update
end module ringlube_jfo_system
