!> Where the oil a starved ring's leading edge turns back goes wrong (docs/film_model.md, "The
!> oil turned back"; not a test, the numbers its section quotes): the moving meniscus of ctest
!> jfo_connect/starved_transient_order (the parabolic ring at U = 10 m/s, fed 1.2 um of supply
!> content through the inflow face, its minimum film oscillating 1 um +- 50 %) on 51-201 nodes
!> against 801, over the second period. Per grid: the error of the oil turned back (relative to
!> the supply over the period), the share of it accrued within 10 steps of the reference's
!> arrival at the leading edge, and how far the meniscus leads the reference's on its way to the
!> edge (mean over the steps before the arrival with the reference's beyond 0.25 mm, in cells;
!> the meniscus placed by the jump condition between its full node D and the partly filled node
!> upstream, or the edge).
!>
!> With a fourth argument, a node count of the table, per step from 40 (the fifth) steps before the
!> reference's arrival to one step after: that grid's meniscus's distance from the edge (in its
!> cells) beside the reference's, each one's oil turned back, and how much more oil than the
!> reference that grid's edge cell (the 1.5 of its cells next to the edge) holds, and the change
!> of that over the step (the oil in a step's supply; the stored content, jfo_front_content);
!> then the flux into the edge cell through the face behind it (in the supply's flux), split
!> into that grid's Couette term and pressure term, the reference's flux at that place (the
!> grid's less the change above) and the front pair's s at that face (0 without that pair);
!> and on a second line the oil between the edge and a face 1.5 ... 32.5 of its cells from it,
!> that grid's less the reference's (in a step's supply).
!>
!> Then every 10 steps over the same span of steps, the oil between the edge and 2 cells short of
!> the nearer of the two fronts (the starved zone ahead of both), between the edge and 3 cells
!> behind the farther, and in the whole film, that grid's less the reference's; the first of
!> these split into the stored content less the carried theta hd (hd the gap at the face a
!> node's Couette flux leaves through; all, and of the nodes of fill 0.6 to 1) and the carried
!> content less the supply's (that grid's less the reference's, then that grid's own).
!>
!> The sixth and seventh arguments move where, with front_content, the thinly filled cells'
!> stored content theta hd fades to theta h (jfo_problem%thin_fade_from and thin_fade_width,
!> the kernel's 0.3 and 0.3 by default), and an eighth, 1, sets jfo_problem%full_hd (a full node
!> next to a partly filled one storing hd + s (h - hd)): bench-only variants of the kernel.
!>
!>     ./build/bench_oil_turned_back [steps per period, 2000] [period s, 0.01] [front_content 0/1, 1]
!>                                   [nodes to trace, none] [steps before the arrival, 40]
!>                                   [fill where theta hd fades, 0.3] [over a fill of, 0.3]
!>                                   [full_hd 0/1, 0]
program bench_oil_turned_back
  use ringlube_kinds, only: dp, pi
  use ringlube_jfo
  use ringlube_jfo_connect
  use ringlube_jfo_system, only: jfo_front_content
  use slider_closed_form, only: b, xs, h0, kk
  use jfo_test_tools, only: ring_gap
  implicit none
  integer, parameter :: nn(6) = [51, 71, 101, 141, 201, 801]
  real(dp), parameter :: u = 10.0_dp, pl = 1e5_dp, cs = 1.2e-6_dp
  real(dp), allocatable :: x(:), h(:), hmid(:), kmid(:), p(:), th(:), pc(:), cold(:)
  real(dp), allocatable :: bstep(:, :), xf(:, :), oil(:, :), fcou(:), fpoi(:), sfr(:)
  real(dp), allocatable :: spn(:, :, :), prg(:, :), prr(:, :), xg(:), xr(:)
  real(dp), allocatable :: tdg(:, :), tdr(:, :), hig(:, :), hir(:, :)
  real(dp) :: per, dx, dt, t, hm, back(6), supply, share, lead, sup, dch, tf0, tfw
  integer :: nsteps, k, n, i, j, nfail(6), jarr, ifc, m, ntr, ntb, ifh
  logical :: fc, fh
  type(jfo_stats) :: st
  type(jfo_problem) :: prob
  character(len=32) :: arg
  nsteps = 2000
  per = 1e-2_dp
  ifc = 1
  if (command_argument_count() >= 1) then
    call get_command_argument(1, arg)
    read (arg, *) nsteps
  end if
  if (command_argument_count() >= 2) then
    call get_command_argument(2, arg)
    read (arg, *) per
  end if
  if (command_argument_count() >= 3) then
    call get_command_argument(3, arg)
    read (arg, *) ifc
  end if
  fc = ifc == 1
  ntr = 0
  if (command_argument_count() >= 4) then
    call get_command_argument(4, arg)
    read (arg, *) ntr
  end if
  ntb = 40
  if (command_argument_count() >= 5) then
    call get_command_argument(5, arg)
    read (arg, *) ntb
  end if
  tf0 = 0.3_dp
  tfw = 0.3_dp
  if (command_argument_count() >= 6) then
    call get_command_argument(6, arg)
    read (arg, *) tf0
  end if
  if (command_argument_count() >= 7) then
    call get_command_argument(7, arg)
    read (arg, *) tfw
  end if
  ifh = 0
  if (command_argument_count() >= 8) then
    call get_command_argument(8, arg)
    read (arg, *) ifh
  end if
  fh = ifh == 1
  allocate (bstep(nsteps, size(nn)), xf(nsteps, size(nn)), oil(nsteps, size(nn)))
  allocate (fcou(nsteps), fpoi(nsteps), sfr(nsteps))
  allocate (spn(nsteps, size(nn), 6))
  oil = 0.0_dp
  fcou = 0.0_dp
  fpoi = 0.0_dp
  sfr = 0.0_dp
  dt = per / nsteps
  supply = 0.5_dp * u * cs * per
  do k = 1, size(nn)
    n = nn(k)
    dx = b / (n - 1)
    x = [(-0.5_dp * b + (i - 1) * dx, i=1, n)]
    if (allocated(p)) deallocate (p, th, pc, cold, hmid, kmid, h)
    allocate (p(n), th(n), pc(n), cold(n), hmid(n - 1), kmid(n - 1), h(n))
    p = pl
    th = 1.0_dp
    pc = 0.0_dp
    h = h0 + kk * (x + xs)**2
    cold = h
    nfail(k) = 0
    bstep(:, k) = 0.0_dp
    do j = 1, 2 * nsteps
      t = j * dt
      hm = h0 * (1.0_dp + 0.5_dp * sin(2 * pi * t / per + 1.0_dp))
      call ring_gap(x, hm, h, hmid, kmid)
      prob = jfo_problem(dx=dx, u=u, dt=dt, p_left=pl, p_right=pl, &
                         theta_right=min(1.0_dp, cs / hmid(n - 1)), p_cav=0.0_dp, &
                         leading_gas=.true., edge_meniscus=.true., edge_cells=.true., &
                         front_content=fc, thin_fade_from=tf0, thin_fade_width=tfw, &
                         full_hd=fh)
      call jfo_solve_connected(prob, h, hmid, kmid, cold, pc, p, th, st)
      cold = jfo_front_content(prob, h, hmid, kmid, pc, p, th)
      if (st%info /= JFO_OK) nfail(k) = nfail(k) + 1
      if (j > nsteps) then
        bstep(j - nsteps, k) = dt * (0.5_dp * u * cs + st%q_right)
        xf(j - nsteps, k) = meniscus()
        if (ntr > 1) oil(j - nsteps, k) = edge_oil(1.5_dp * b / (ntr - 1))
        if (ntr > 1) then
          do m = 1, 6
            spn(j - nsteps, k, m) = edge_oil((2**(m - 1) + 0.5_dp) * b / (ntr - 1))
          end do
        end if
        if (n == ntr) call face_behind(fcou(j - nsteps), fpoi(j - nsteps), sfr(j - nsteps))
        if (ntr > 1 .and. (n == ntr .or. k == size(nn))) then
          if (n == ntr) then
            if (.not. allocated(prg)) allocate (prg(n, nsteps), tdg(n, nsteps), hig(n, nsteps))
            prg(:, j - nsteps) = cold
            tdg(:, j - nsteps) = carried()
            hig(:, j - nsteps) = merge(cold - tdg(:, j - nsteps), 0.0_dp, &
                                       th >= 0.6_dp .and. th < 1.0_dp)
            xg = x
          else
            if (.not. allocated(prr)) allocate (prr(n, nsteps), tdr(n, nsteps), hir(n, nsteps))
            prr(:, j - nsteps) = cold
            tdr(:, j - nsteps) = carried()
            hir(:, j - nsteps) = merge(cold - tdr(:, j - nsteps), 0.0_dp, &
                                       th >= 0.6_dp .and. th < 1.0_dp)
            xr = x
          end if
        end if
      end if
    end do
    back(k) = sum(bstep(:, k))
  end do
  jarr = findloc(bstep(:, size(nn)) > 1e-9_dp * 0.5_dp * u * cs * dt, .true., 1)
  write (*, '(a, i0, a, es9.2, a, l1, a, 2f6.3, a, l1, a, i0, a, es11.4, a)') &
    'steps per period ', nsteps, ', period ', per, ' s, front_content ', fc, &
    ', theta hd fading from, over ', tf0, tfw, ', full_hd ', fh, &
    '; the reference arrives at step ', jarr, ', turns back ', back(size(nn)) / supply, &
    ' of the supply'
  write (*, '(a)') 'nodes  oil turned back error / supply  share within 10 steps of the '// &
    'arrival  meniscus lead (cells)  steps not converged'
  do k = 1, size(nn) - 1
    share = sum(bstep(max(jarr - 10, 1):min(jarr + 10, nsteps), k) &
                - bstep(max(jarr - 10, 1):min(jarr + 10, nsteps), size(nn))) &
            / (back(k) - back(size(nn)))
    lead = 0.0_dp
    m = 0
    do j = 1, nsteps
      if (j < jarr .and. xf(j, size(nn)) > 0.25e-3_dp) then
        lead = lead + (xf(j, k) - xf(j, size(nn)))
        m = m + 1
      end if
    end do
    write (*, '(i5, es20.3, f30.3, f24.3, i10)') nn(k), (back(k) - back(size(nn))) / supply, &
      share, lead / max(m, 1) / (b / (nn(k) - 1)), nfail(k)
  end do
  k = findloc(nn, ntr, 1)
  if (k > 0 .and. k < size(nn)) then
    write (*, '(a, i0, a)') 'step  meniscus from the edge in cells of ', nn(k), &
      ' nodes: grid, reference  oil turned back / step supply: grid, reference  oil in the '// &
      'grid''s edge cell / step supply: grid less reference, its change over the step'// &
      '; the flux into the edge cell through the face behind it / step supply: the grid''s '// &
      'Couette term, its pressure term, the reference''s at that place (the grid''s less the '// &
      'change); the front pair''s s at that face (D the node behind it, 0 no pair); below, '// &
      'the oil between the edge and a face of that grid, grid less reference'
    sup = 0.5_dp * u * cs
    do j = max(jarr - ntb, 2), min(jarr + 1, nsteps)
      dch = (oil(j, k) - oil(j, size(nn)) - oil(j - 1, k) + oil(j - 1, size(nn))) / (sup * dt)
      write (*, '(i5, 2f12.4, 2es14.4, 2f12.4, 3f10.4, f8.3)') j, &
        (0.5_dp * b - xf(j, k)) / (b / (nn(k) - 1)), &
        (0.5_dp * b - xf(j, size(nn))) / (b / (nn(k) - 1)), &
        bstep(j, k) / (sup * dt), bstep(j, size(nn)) / (sup * dt), &
        (oil(j, k) - oil(j, size(nn))) / (sup * dt), dch, fcou(j) / sup, fpoi(j) / sup, &
        (fcou(j) + fpoi(j)) / sup - dch, sfr(j)
      write (*, '(a, 6f10.4)') '   edge to 1.5, 2.5, 4.5, 8.5, 16.5, 32.5 cells:', &
        (spn(j, k, :) - spn(j, size(nn), :)) / (sup * dt)
    end do
    write (*, '(a)') 'step  fronts from the edge in cells (grid, reference; no front: '// &
      'the trailing edge)  oil from the edge to 2 cells short of the nearer front, to 3 '// &
      'cells behind the farther, in the whole film / step supply: grid less reference; '// &
      'the first split: the stored content less the carried theta hd (all, and of the nodes '// &
      'of fill 0.6 to 1), and the carried less the supply''s content (grid less reference; '// &
      'then the grid''s own)'
    do j = max(jarr - ntb, 1), jarr, 10
      dch = min(0.5_dp * b - xf(j, k), 0.5_dp * b - xf(j, size(nn))) - 2.0_dp * b / (ntr - 1)
      lead = max(0.5_dp * b - xf(j, k), 0.5_dp * b - xf(j, size(nn))) + 3.0_dp * b / (ntr - 1)
      write (*, '(i5, 2f10.3, 7f10.4)') j, (0.5_dp * b - xf(j, k)) / (b / (ntr - 1)), &
        (0.5_dp * b - xf(j, size(nn))) / (b / (ntr - 1)), &
        (span(prg(:, j), xg, dch) - span(prr(:, j), xr, dch)) / (sup * dt), &
        (span(prg(:, j) - tdg(:, j), xg, dch) - span(prr(:, j) - tdr(:, j), xr, dch)) &
        / (sup * dt), (span(hig(:, j), xg, dch) - span(hir(:, j), xr, dch)) / (sup * dt), &
        (span(tdg(:, j), xg, dch) - span(tdr(:, j), xr, dch)) / (sup * dt), &
        (span(tdg(:, j), xg, dch) - cs * dch) / (sup * dt), &
        (span(prg(:, j), xg, lead) - span(prr(:, j), xr, lead)) / (sup * dt), &
        (span(prg(:, j), xg, 2 * b) - span(prr(:, j), xr, 2 * b)) / (sup * dt)
    end do
  end if

contains

  !> Each node's carried content, theta hd (hd the gap at the face its Couette flux leaves
  !> through, towards the trailing edge; the supply's content in a steady starved zone).
  function carried() result(c)
    real(dp) :: c(n)
    c = 0.0_dp
    c(2:n - 1) = th(2:n - 1) * hmid(1:n - 2)
  end function carried

  !> As edge_oil for a stored content c on the nodes xx (a grid's, stored beside the run).
  pure real(dp) function span(c, xx, ell) result(v)
    real(dp), intent(in) :: c(:), xx(:), ell
    real(dp) :: lo, hi, dq
    integer :: q, nq
    nq = size(xx)
    dq = xx(2) - xx(1)
    v = 0.0_dp
    do q = 2, nq - 1
      lo = xx(q) - 0.5_dp * dq
      hi = xx(q) + 0.5_dp * dq
      if (q == nq - 1) hi = xx(nq)
      if (q == 2) lo = xx(1)
      v = v + c(q) * max(0.0_dp, hi - max(lo, xx(nq) - ell))
    end do
  end function span

  !> The oil (per unit width) between the inflow (right) edge and a distance ell from it: each
  !> node's stored content (cold, per unit length over its cell; the cell next to the edge
  !> reaches it) times the length of its cell within that span.
  real(dp) function edge_oil(ell) result(v)
    real(dp), intent(in) :: ell
    real(dp) :: lo, hi
    v = 0.0_dp
    do i = 2, n - 1
      lo = x(i) - 0.5_dp * dx
      hi = x(i) + 0.5_dp * dx
      if (i == n - 1) hi = x(n)
      if (i == 2) lo = x(1)
      v = v + cold(i) * max(0.0_dp, hi - max(lo, x(n) - ell))
    end do
  end function edge_oil

  !> The flux into the edge cell (node n - 1) through the face behind it (n - 2 | n - 1), split
  !> into its Couette term (a hmid theta of the edge cell's node, a = -U/2) and its pressure
  !> term (-kd (p_(n-1) - p_(n-2)) times the upwind fill), and the front pair's s = A / (A + B)
  !> at that face (D = n - 2 full, U = n - 1 partly filled; 0 without that pair).
  subroutine face_behind(fc_, fp_, s_)
    real(dp), intent(out) :: fc_, fp_, s_
    real(dp) :: g, aa, bb
    g = kmid(n - 2) / dx * (p(n - 1) - p(n - 2))
    fc_ = -0.5_dp * u * hmid(n - 2) * th(n - 1)
    fp_ = -g * merge(th(n - 2), th(n - 1), g <= 0.0_dp)
    s_ = 0.0_dp
    if (th(n - 2) >= 1.0_dp .and. th(n - 1) < 1.0_dp) then
      aa = max(p(n - 2) - p(n - 1), 0.0_dp)
      bb = (1.0_dp - th(n - 1)) * 0.5_dp * u * hmid(n - 2) / (kmid(n - 2) / dx)
      s_ = aa / (aa + bb)
    end if
  end subroutine face_behind

  !> The leading meniscus: the jump condition's front between the full node D nearest the
  !> inflow (right) edge and the node upstream of it (the edge when D is next to it).
  real(dp) function meniscus() result(xm)
    integer :: id
    real(dp) :: aa, bb
    do id = n - 1, 2, -1
      if (th(id) >= 1.0_dp) exit
    end do
    bb = (1.0_dp - th(id + 1)) * 0.5_dp * u * hmid(id) / (kmid(id) / dx)
    if (id + 1 == n) then
      aa = max(p(id) - pl, 0.0_dp)
      xm = x(id) + min(aa / bb, 1.0_dp) * dx
    else
      aa = max(p(id) - p(id + 1), 0.0_dp)
      xm = x(id) + aa / (aa + bb) * dx
    end if
  end function meniscus
end program bench_oil_turned_back
