! ctest labels: numerics;slow
!> The mass-conserving (JFO) film kernel ringlube_jfo against exact and independent answers
!> (docs/film_model.md, "Verification"):
!>  1. flooded steady parabolic ring = the Swift-Stieber closed form (no reformation), order in N;
!>  2. the oscillatory squeeze film with rupture and reformation (Ausas, Jai and Buscaglia 2009,
!>     J. Tribol. 131:031702, after Optasanu and Bonneau 2000): semi-analytical solution, order;
!>  3. mass conservation over a transient with sliding, reversal, rupture and reformation;
!>  4. an independent Elrod/Ausas relaxation solver (jfo_reference) on that transient;
!>  5. bounds and complementarity;
!>  7. the anti-cycling guard and the Gauss-Seidel fallback;
!>  8. the one-pass evaluations of the Newton iteration against the residual and Jacobian rows
!>     of jfo_residual;
!>  9. a solve that ends on a Newton step proven to settle (no residual evaluated after it)
!>     against the same solve evaluating it, and against jfo_residual at its answer.
!> The connectivity rule, the starved inlet and the inflow cap: test_jfo_connect.
program test_jfo
  use, intrinsic :: ieee_arithmetic, only: ieee_is_finite
  use ringlube_kinds, only: dp, pi
  use ringlube_jfo
  use ringlube_jfo_connect
  use ringlube_jfo_system, only: jfo_system, jfo_system_setup, jfo_residual, jfo_scratch, &
                                 jfo_scratch_size, jfo_newton_eval, jfo_newton_step, &
                                 jfo_residual_only, jfo_newton_apply, jfo_state_to_v
  use ringlube_reynolds, only: reynolds_solve, reynolds_problem
  use jfo_reference, only: elrod_solve
  use ringlube_check
  use squeeze_exact
  use slider_closed_form, only: b, xs, h0, eta, kk, ns, hz, j2, j3
  use jfo_test_tools
  implicit none

  if (run_case('flooded_slider')) call case_flooded_slider()
  if (run_case('squeeze')) call case_squeeze()
  if (run_case('transient')) call case_transient()
  if (run_case('guard')) call case_guard()
  if (run_case('bad_input')) call case_bad_input()
  if (run_case('huge_warm_start')) call case_huge_warm_start()
  if (run_case('newton_passes')) call case_newton_passes()
  if (run_case('settled_step')) call case_settled_step()
  call report('test_jfo')

contains

  ! ------------------------------------------------------------------ 1. flooded steady slider
  !> U = 10 m/s (inlet at the crankcase edge, 2 bar), trailing edge at p_cav = 0: the JFO film
  !> ruptures with p = 0, p' = 0 and never re-forms, so it must equal Swift-Stieber.
  subroutine case_flooded_slider()
    real(dp), allocatable :: x(:), h(:), hmid(:), kmid(:), p(:), th(:), pc(:), pe(:), pss(:)
    logical, allocatable :: active(:)
    real(dp) :: dx, xc, err(4), dss(4), ql, qr, q_exact
    integer :: k, n, it, info, itw, its
    type(jfo_stats) :: st
    xc = rupture_point(10.0_dp, 2e5_dp, 0.0_dp)
    write (*, '(a)') '1. flooded steady slider against Swift-Stieber (closed form and '// &
      'reynolds_solve)'
    write (*, '(a)') '    N  max|p-p_SS|/max p  |p_jfo - p_reynolds_solve|  Newton its (cold, warm)'
    do k = 1, size(ns)
      n = ns(k)
      call grid(n, x, h, hmid, kmid, dx)
      allocate (p(n), th(n), pc(n), pss(n), active(n))
      pc = 0.0_dp
      p = 0.0_dp
      th = 1.0_dp
      call jfo_solve(jfo_problem(dx=dx, u=10.0_dp, dt=0.0_dp, p_left=0.0_dp, p_right=2e5_dp), h, &
                     hmid, kmid, h, pc, p, th, st)
      it = st%iterations; info = st%info; ql = st%q_left; qr = st%q_right
      call check(info == JFO_OK, 'flooded slider converges')
      pe = merge(p_film(x + xs, xc + xs, hz(xc + xs), 0.0_dp, 10.0_dp), 0.0_dp, x > xc)
      err(k) = maxval(abs(p - pe)) / maxval(pe)
      ! the flux is the Couette flux at the rupture point: -(U/2) h(xc)
      q_exact = -5.0_dp * hz(xc + xs)
      call check_close(qr, q_exact, 2.0_dp * dx * 2 * kk * abs(xc + xs) / hz(xc + xs) + 1e-2_dp, &
                       'flooded slider: inflow = Couette flux at the rupture point')
      call check_close(ql, qr, 1e-10_dp, 'flooded slider: steady, q_left = q_right')
      ! Swift-Stieber on the same grid (K = h^3/(6 eta))
      active = .false.
      call reynolds_solve(reynolds_problem(dx=dx, u=10.0_dp, sq=0.0_dp, p_left=0.0_dp, &
                                           p_right=2e5_dp, p_cav=0.0_dp), 2 * kmid, hmid, pss, &
                          active, its, info)
      dss(k) = maxval(abs(p - pss)) / maxval(pe)
      ! warm start from the solution, slightly perturbed step: 1 iteration
      call jfo_solve(jfo_problem(dx=dx, u=10.0_dp * (1 + 1e-3_dp), dt=0.0_dp, p_left=0.0_dp, &
                                 p_right=2e5_dp), h, hmid, kmid, h, pc, p, th, st)
      itw = st%iterations; info = st%info
      write (*, '(i5, es16.3, es22.3, 6x, i3, i4)') n, err(k), dss(k), it, itw
      call check(itw <= 3, 'flooded slider: warm start needs at most 3 iterations')
      call check(all(th >= 0.0_dp .and. th <= 1.0_dp), 'flooded slider: theta in [0, 1]')
      deallocate (p, th, pc, pss, active)
    end do
    call print_orders('flooded slider vs Swift-Stieber', err, 0.9_dp)
    call check(err(4) < 1e-3_dp, 'flooded slider: error at N=401 below 1e-3')
    ! JFO and the discrete Swift-Stieber differ by less than either's discretisation error
    call check(all(dss <= err), 'flooded slider: JFO within discretisation error of reynolds_solve')
  end subroutine case_flooded_slider

  ! ------------------------------------------------------------------ 2. oscillatory squeeze
  ! Parallel plates, U = 0, x in [0, 1], k = h^3 (eta = 1/12), both edges at p_a = 0.025 and
  ! flooded, p_cav = 0, h(t) = hm + ha cos(4 pi t). Rupture: a cavity opens at the centre while
  ! the plates separate, its edge Sigma(t) follows p(Sigma) = 0, p'(Sigma) = 0, i.e.
  ! Sigma = sqrt(2 p_a k / h') as long as that recedes; the cavity keeps the content c(x) it
  ! had when it opened; then the front re-forms with (h - c(Sigma)) dSigma/dt = q(Sigma),
  ! q(Sigma) = p_a k / Sigma - h' Sigma / 2 (mass balance across the front). Derived in
  ! docs/film_model.md; the test of Ausas, Jai and Buscaglia (2009).
  subroutine case_squeeze()
    integer, parameter :: nsq(4) = [51, 101, 201, 401]
    real(dp), parameter :: tend = 0.75_dp, dts = 2e-6_dp
    real(dp), allocatable :: sig(:), x(:), h(:), hmid(:), kmid(:), p(:), th(:), pc(:), cold(:)
    real(dp) :: t, s, k1, k2, k3, k4, errv(4), errp(4), errs(4), dx, dt, vex, vnum, pex
    real(dp) :: hh, hd, b0, sn, smin, perr, pref, pnorm, order
    integer :: nt, i, j, k, n, nsteps, it, info, itmax, itsum
    type(jfo_stats) :: st
    ! --- exact front: growth from t1 (Sigma_eq = 1/2) to t2 (Sigma_eq minimal), then the ODE
    t1 = bisect_t(0.25_dp + 1e-9_dp, 0.375_dp, 0.5_dp)
    t = t1
    do while (sq_sigma_eq(t + dts) < sq_sigma_eq(t))
      t = t + dts
    end do
    t2 = golden_min(t - dts, t + dts)
    smin = sq_sigma_eq(t2)
    nt = nint(tend / dts)
    allocate (sig(0:nt))
    s = 0.5_dp
    do i = 0, nt
      t = i * dts
      if (t <= t1) then
        sig(i) = 0.5_dp
      else if (t <= t2) then
        sig(i) = sq_sigma_eq(t)
      else
        if (i > 0 .and. sig(i - 1) < 0.5_dp .and. (i - 1) * dts >= t2) then
          s = sig(i - 1)
          k1 = front_speed((i - 1) * dts, s)
          k2 = front_speed((i - 0.5_dp) * dts, s + 0.5_dp * dts * k1)
          k3 = front_speed((i - 0.5_dp) * dts, s + 0.5_dp * dts * k2)
          k4 = front_speed(i * dts, s + dts * k3)
          sig(i) = min(0.5_dp, s + dts * (k1 + 2 * k2 + 2 * k3 + k4) / 6)
        else if ((i - 1) * dts < t2) then
          sig(i) = smin
        else
          sig(i) = 0.5_dp
        end if
      end if
    end do
    write (*, '(a)') '2. oscillatory squeeze film (Ausas, Jai, Buscaglia 2009), t in [0, 0.75]'
    write (*, '(a, f8.5, a, f8.5, a, f8.5, a, f8.5)') '   exact: cavity opens t1 = ', t1, &
      ', widest at t2 = ', t2, ' (Sigma = ', smin, '), closes at t3 = ', &
      count(sig < 0.5_dp) * dts + t1
    call check(any(sig(nt / 2:) < 0.5_dp) .and. sig(nt) == 0.5_dp, &
               'squeeze: exact solution ruptures, re-forms and closes before t = 0.75')
    ! --- numerical: N nodes, dt = 1/(4 (N-1))
    do k = 1, size(nsq)
      n = nsq(k)
      dx = 1.0_dp / (n - 1)
      nsteps = 4 * (n - 1) / 2
      dt = tend / nsteps
      x = [((i - 1) * dx, i=1, n)]
      allocate (h(n), hmid(n - 1), kmid(n - 1), p(n), th(n), pc(n), cold(n))
      pc = 0.0_dp
      p = pa
      th = 1.0_dp
      h = sq_h(0.0_dp)
      errv(k) = 0.0_dp
      errp(k) = 0.0_dp
      errs(k) = 0.0_dp
      pnorm = 0.0_dp
      itmax = 0
      itsum = 0
      do j = 1, nsteps
        t = j * dt
        cold = th * h
        h = sq_h(t)
        hmid = h(1)
        kmid = hmid**3
        call jfo_solve(jfo_problem(dx=dx, u=0.0_dp, dt=dt, p_left=pa, p_right=pa), h, hmid, kmid, &
                       cold, pc, p, th, st)
        it = st%iterations; info = st%info
        if (info /= JFO_OK) call check(.false., 'squeeze step converges')
        itmax = max(itmax, it)
        itsum = itsum + it
        ! exact state at t
        i = nint(t / dts)
        s = sig(i)
        hh = h(1)
        hd = sq_hdot(t)
        vex = 2 * (hh * s + cavity_content(s, t))
        vnum = jfo_film_volume(dx, h, th) + hh * dx
        errv(k) = max(errv(k), abs(vnum - vex))
        ! numerical front: the full-film length from the left edge, theta-weighted
        sn = 0.5_dp * dx + dx * count(th(2:(n + 1) / 2) >= 1.0_dp)
        if (s < 0.5_dp) errs(k) = errs(k) + abs(sn - s) * dt
        b0 = -(pa + hd * s * s / (2 * hh**3)) / s
        perr = 0.0_dp
        pref = 0.0_dp
        do i = 1, n
          if (x(i) <= s) then
            pex = pa + hd / (2 * hh**3) * x(i)**2 + b0 * x(i)
          else if (x(i) >= 1 - s) then
            pex = pa + hd / (2 * hh**3) * (1 - x(i))**2 + b0 * (1 - x(i))
          else
            pex = 0.0_dp
          end if
          if (s >= 0.5_dp) pex = pa + hd / (2 * hh**3) * x(i) * (x(i) - 1)
          perr = max(perr, abs(p(i) - pex))
          pref = max(pref, abs(pex))
        end do
        errp(k) = errp(k) + perr * dt
        pnorm = pnorm + pref * dt
      end do
      errp(k) = errp(k) / pnorm
      write (*, '(a, i4, a, es10.3, a, es10.3, a, es10.3, a, i0, a, f5.2)') '   N=', n, &
        ' max|V-V_exact| ', errv(k), ' int max|p-p_exact| dt (rel) ', errp(k), &
        ' int|Sigma_err|dt ', &
        errs(k), '  Newton its max ', itmax, ' mean ', real(itsum, dp) / nsteps
      deallocate (h, hmid, kmid, p, th, pc, cold)
    end do
    call print_orders('squeeze oil volume', errv, 0.8_dp)
    call print_orders('squeeze pressure', errp, 0.7_dp)
    ! the numerical front is known to a cell only: check the order over the whole range
    order = log(errs(1) / errs(4)) / log(8.0_dp)
    write (*, '(a, f6.2)') '  squeeze front position (time-integrated): order from N=51 to 401 ', &
      order
    call check(order > 0.7_dp, 'squeeze front position converges at first order')
  end subroutine case_squeeze

  ! ------------------------------------------------------------------ 3/4. transient ring
  !> The ring over a crank-like sequence: U = 10 sin(phase), h0 oscillating, both edges held
  !> (chamber 3 bar, crankcase 1 bar), cavitation at 0.5 bar, starved inlet on the upstroke:
  !> rupture and reformation inside the face, a reversal, a squeeze. Checks: the oil balance
  !> per step and in total, bounds, complementarity, and agreement with the Elrod relaxation.
  subroutine case_transient()
    integer, parameter :: n = 61, nsteps = 240
    real(dp), allocatable :: x(:), h(:), hmid(:), kmid(:), p(:), th(:), pc(:), cold(:)
    real(dp), allocatable :: pr(:), tr(:), hold(:)
    real(dp) :: dx, dt, t, u, v0, v1, ql, qr, bal, balmax, total_in, vstart, dev_p, dev_t
    real(dp) :: pmax, tin_l, tin_r, compl, hmin_t
    integer :: j, it, info, sw, itmax, itsum, swmax, ncav, nref, outer, outmax, outsum
    type(jfo_stats) :: st
    logical :: ok_bounds, reformed, ruptured
    call grid(n, x, h, hmid, kmid, dx)
    allocate (p(n), th(n), pc(n), cold(n), pr(n), tr(n))
    pc = 0.5e5_dp
    p = 1e5_dp
    th = 1.0_dp
    pr = p
    tr = th
    dt = 2e-5_dp
    balmax = 0.0_dp
    total_in = 0.0_dp
    dev_p = 0.0_dp
    dev_t = 0.0_dp
    pmax = 0.0_dp
    compl = 0.0_dp
    itmax = 0
    itsum = 0
    swmax = 0
    ok_bounds = .true.
    reformed = .false.
    ruptured = .false.
    vstart = jfo_film_volume(dx, h, th)
    do j = 1, nsteps
      t = j * dt
      u = 10.0_dp * sin(2 * pi * t / (nsteps * dt) + 0.3_dp)
      hold = h
      cold = th * h
      hmin_t = 1e-6_dp * (1.0_dp + 0.6_dp * sin(6 * pi * t / (nsteps * dt)))
      h = hmin_t + kk * (x + xs)**2
      hmid = hmin_t + kk * (0.5_dp * (x(1:n - 1) + x(2:n)) + xs)**2
      kmid = hmid**3 / (12 * eta)
      ! starved on the upstroke (u < 0, inlet at the chamber edge), flooded on the downstroke
      tin_l = merge(0.6_dp, 1.0_dp, u < 0.0_dp)
      tin_r = 1.0_dp
      v0 = jfo_film_volume(dx, h, cold / h)
      call jfo_solve(jfo_problem(dx=dx, u=u, dt=dt, p_left=3e5_dp, p_right=1e5_dp, &
                                 theta_left=tin_l, theta_right=tin_r), h, hmid, kmid, cold, pc, &
                     p, th, st)
      it = st%iterations; info = st%info; ql = st%q_left; qr = st%q_right
      call check(info == JFO_OK, 'transient step converges')
      v1 = jfo_film_volume(dx, h, th)
      bal = abs((v1 - v0) - dt * (ql - qr))
      balmax = max(balmax, bal)
      total_in = total_in + dt * (ql - qr)
      itmax = max(itmax, it)
      itsum = itsum + it
      ok_bounds = ok_bounds .and. all(th >= 0.0_dp .and. th <= 1.0_dp) &
                  .and. all(p(2:n - 1) >= pc(2:n - 1))
      compl = max(compl, maxval(abs((p(2:n - 1) - pc(2:n - 1)) * (1 - th(2:n - 1)))))
      if (any(th(2:n - 1) < 1.0_dp)) ruptured = .true.
      if (count_runs(th) >= 1 .and. th(2) == 1.0_dp .and. th(n - 1) == 1.0_dp) reformed = .true.
      ! the independent relaxation from its own previous state, on the same step
      call elrod_solve(dx, h, hmid, kmid, u, dt, tr * hold, 3e5_dp, 1e5_dp, tin_l, tin_r, pc, &
                       pr, tr, sw, 1e-13_dp, 1.7_dp, 200000)
      swmax = max(swmax, sw)
      dev_p = max(dev_p, maxval(abs(pr - p)))
      dev_t = max(dev_t, maxval(abs(tr - th)))
      pmax = max(pmax, maxval(p))
    end do
    ncav = count(th(2:n - 1) < 1.0_dp)
    nref = count_runs(th)
    write (*, '(a)') '3. oil balance over a transient (61 nodes, 240 steps, reversal, '// &
      'starved upstroke)'
    write (*, '(a, es10.3, a, es10.3)') '   max per-step |dV - dt (q_l - q_r)| = ', balmax, &
      ' m^2;  relative to the film volume ', balmax / vstart
    write (*, '(a, i0, a, f5.2, a, i0)') '   Newton iterations per step: max ', itmax, ', mean ', &
      real(itsum, dp) / nsteps, ';  Elrod relaxation sweeps per step: max ', swmax
    write (*, '(a, es10.3, a, es10.3)') '4. JFO vs Elrod relaxation: max |dp|/max p ', &
      dev_p / pmax, ', max |dtheta| ', dev_t
    write (*, '(a, es10.3)') '5. max |(p - pc)(1 - theta)| = ', compl
    call check(balmax <= 1e-12_dp * vstart, 'transient: oil balance closes to 1e-12 of the volume')
    call check(ok_bounds, 'transient: theta in [0, 1], p >= pc')
    call check(compl == 0.0_dp, 'transient: complementarity exact')
    call check(ruptured .and. reformed, 'transient: rupture and reformation inside the face occur')
    call check(dev_p / pmax < 1e-8_dp .and. dev_t < 1e-8_dp, &
               'transient: JFO agrees with the independent Elrod relaxation')
    call check(real(itsum, dp) / nsteps <= 3.0_dp, 'transient: warm-started mean <= 3 iterations')
    call check(ncav >= 0 .and. nref >= 0, 'transient: final state read')

    ! the same transient through the connectivity rule: trailing gas and the starved inlet zone
    ! open to the leading gas, warm-started from step to step
    p = 1e5_dp
    th = 1.0_dp
    h = hz(x + xs)
    balmax = 0.0_dp
    outmax = 0
    outsum = 0
    itsum = 0
    ok_bounds = .true.
    do j = 1, nsteps
      t = j * dt
      u = 10.0_dp * sin(2 * pi * t / (nsteps * dt) + 0.3_dp)
      cold = th * h
      hmin_t = 1e-6_dp * (1.0_dp + 0.6_dp * sin(6 * pi * t / (nsteps * dt)))
      h = hmin_t + kk * (x + xs)**2
      hmid = hmin_t + kk * (0.5_dp * (x(1:n - 1) + x(2:n)) + xs)**2
      kmid = hmid**3 / (12 * eta)
      ! upstroke: starved chamber-side inlet, crankcase side gas only behind the trailing edge;
      ! downstroke: flooded crankcase-side inlet, chamber side gas only
      tin_l = merge(0.6_dp, 0.0_dp, u < 0.0_dp)
      tin_r = merge(0.0_dp, 1.0_dp, u < 0.0_dp)
      v0 = jfo_film_volume(dx, h, cold / h)
      call jfo_solve_connected(jfo_problem(dx=dx, u=u, dt=dt, p_left=3e5_dp, p_right=1e5_dp, &
                                           theta_left=tin_l, theta_right=tin_r, p_cav=0.5e5_dp, &
                                           trailing_gas=.true., leading_gas=.true.), &
                               h, hmid, kmid, cold, pc, p, th, st)
      it = st%iterations; outer = st%outer; info = st%info; ql = st%q_left; qr = st%q_right
      if (info /= JFO_OK) call check(.false., 'connected transient step converges')
      v1 = jfo_film_volume(dx, h, th)
      balmax = max(balmax, abs((v1 - v0) - dt * (ql - qr)))
      outmax = max(outmax, outer)
      outsum = outsum + outer
      itsum = itsum + it
      ok_bounds = ok_bounds .and. all(th >= 0.0_dp .and. th <= 1.0_dp) &
                  .and. all(p(2:n - 1) >= pc(2:n - 1))
    end do
    write (*, '(a, f5.2, a, i0, a, f5.2, a, es10.3)') &
      '6d. same transient, trailing gas + starved: outer solves per step mean ', &
      real(outsum, dp) / nsteps, ', max ', outmax, '; Newton its per step ', &
      real(itsum, dp) / nsteps, '; oil balance ', balmax / vstart
    call check(balmax <= 1e-12_dp * vstart, 'connected transient: oil balance closes')
    call check(ok_bounds, 'connected transient: bounds')
    call check(real(outsum, dp) / nsteps < 1.5_dp, &
               'connected transient: warm starts need ~1 outer solve')
  end subroutine case_transient

  !> number of cavity runs strictly inside the face
  integer function count_runs(th) result(c)
    real(dp), intent(in) :: th(:)
    integer :: i
    c = 0
    do i = 2, size(th) - 1
      if (th(i) < 1.0_dp .and. th(i - 1) >= 1.0_dp) c = c + 1
    end do
  end function count_runs

  ! ------------------------------------------------------------------ 7. guard and fallback
  subroutine case_guard()
    integer, parameter :: n = 101
    real(dp), allocatable :: x(:), h(:), hmid(:), kmid(:), p(:), th(:), pc(:), p0(:), t0(:)
    real(dp), allocatable :: pg(:), tg(:)
    real(dp) :: dx
    integer :: it, info, sw, trial, nfail_plain, nfail_guard, i, nguarded, nflagged, itmx
    integer, parameter :: ntrial = 2000, count_converged_in_one = 0
    real(dp) :: hh(n), hmm(n - 1), km(n - 1), cold(n), hm, tinr, dtr
    real(dp) :: u, pl, pr, tinl
    type(jfo_problem) :: prob
    type(jfo_stats) :: st
    call grid(n, x, h, hmid, kmid, dx)
    allocate (p(n), th(n), pc(n), p0(n), t0(n), pg(n), tg(n))
    itmx = 0
    pc = 0.0_dp
    ! reference solution of a case with an enclosed cavity
    p0 = 1e5_dp
    t0 = 1.0_dp
    prob = jfo_problem(dx=dx, u=10.0_dp, dt=0.0_dp, p_left=1e5_dp, p_right=1e5_dp)
    call jfo_solve(prob, h, hmid, kmid, h, pc, p0, t0, st)
    ! the Gauss-Seidel fallback alone reaches the same solution
    p = 1e5_dp
    th = 1.0_dp
    call jfo_solve(prob, h, hmid, kmid, h, pc, p, th, st, &
                   jfo_options(newton=.false., max_iter=2000000))
    it = st%iterations; info = st%info; sw = st%sweeps
    write (*, '(a, i0, a, es10.3)') '7. Gauss-Seidel fallback alone: ', sw, &
      ' sweeps, max |p - p_newton|/max p = ', maxval(abs(p - p0)) / maxval(p0)
    call check(info == JFO_OK .and. maxval(abs(p - p0)) <= 1e-8_dp * maxval(p0) &
               .and. maxval(abs(th - t0)) <= 1e-8_dp, &
               'guard: fallback sweeps reach the Newton solution')
    ! cold starts far from the answer: random gap, speed, edge pressures and fills, steady or
    ! transient, part of the face at a gas pressure, random warm-start fills and pressures up to
    ! 100 bar. Plain Newton (guard off) cycles on some; the guarded solve must converge on all.
    nfail_plain = 0
    nfail_guard = 0
    nguarded = 0
    nflagged = 0
    do trial = 1, ntrial
      call random_step(trial, x, hm, hh, hmm, km, u, pl, pr, tinl, tinr, dtr)
      pc = 0.5e5_dp
      if (rnd(trial, 9) < 0.5_dp) pc(2:2 + int(20 * rnd(trial, 10))) = max(pl, 0.5e5_dp)
      do i = 1, n
        t0(i) = min(1.0_dp, 1.3_dp * rnd(trial, 10 + i))
        p0(i) = 1e7_dp * rnd(trial, 500 + i)**2
      end do
      cold = hh * min(1.0_dp, t0 + 0.2_dp)
      p = p0
      th = t0
      prob = jfo_problem(dx=dx, u=u, dt=dtr, p_left=pl, p_right=pr, theta_left=tinl, &
                         theta_right=tinr)
      call jfo_solve(prob, hh, hmm, km, cold, pc, p, th, st, &
                     jfo_options(guard=.false., max_iter=200))
      info = st%info
      if (info /= JFO_OK) nfail_plain = nfail_plain + 1
      pg = p0
      tg = t0
      call jfo_solve(prob, hh, hmm, km, cold, pc, pg, tg, st)
      it = st%iterations; info = st%info; sw = st%sweeps
      if (info /= JFO_OK) nfail_guard = nfail_guard + 1
      if (sw > 0) nguarded = nguarded + 1
      itmx = max(itmx, it)
      ! one iteration only: not converged, flagged, finite and within bounds
      p = p0
      th = t0
      call jfo_solve(prob, hh, hmm, km, cold, pc, p, th, st, jfo_options(max_iter=1))
      info = st%info
      if (info == JFO_NOT_CONVERGED .and. all(abs(p) < huge(1.0_dp)) &
          .and. all(p(2:n - 1) >= pc(2:n - 1)) &
          .and. all(th >= 0.0_dp .and. th <= 1.0_dp)) nflagged = nflagged + 1
    end do
    write (*, '(3x, i0, a, i0, a, i0, a, i0, a, i0)') ntrial, &
      ' random cold starts: plain Newton failed ', &
      nfail_plain, ', guarded failed ', nfail_guard, ' (guard engaged in ', nguarded, &
      ', max iterations ', itmx
    call check(nfail_plain > 0, &
               'guard: the random set contains cases plain Newton does not solve')
    call check(nfail_guard == 0, 'guard: every random cold start converges')
    call check(nflagged == ntrial - count_converged_in_one, &
               'a solve cut off after one iteration is flagged, finite, in bounds')
  end subroutine case_guard

  subroutine case_bad_input()
    real(dp) :: h(2), hm(1), km(1), p(2), th(2), pc(2)
    integer :: info
    type(jfo_stats) :: st
    h = 1e-6_dp
    hm = 1e-6_dp
    km = 1e-18_dp
    p = 0.0_dp
    th = 1.0_dp
    pc = 0.0_dp
    call jfo_solve(jfo_problem(dx=1e-5_dp, u=1.0_dp, dt=0.0_dp, p_left=0.0_dp, p_right=0.0_dp), &
                   h, hm, km, h, pc, p, th, st)
    info = st%info
    call check(info == JFO_BAD_INPUT, 'bad input: n < 3 flagged')
  end subroutine case_bad_input

  !> A warm start with pressures near huge() overflowed the residual's scale, and Inf <= tol *
  !> Inf passed as converged: p = +Inf returned with info 3 after 0 iterations (the review of
  !> the coarse-grid predictor). It must give the solution of an ordinary warm start.
  subroutine case_huge_warm_start()
    integer, parameter :: n = 61
    real(dp), allocatable :: x(:), h(:), hmid(:), kmid(:)
    real(dp) :: dx, p(n), th(n), p2(n), th2(n), pc(n)
    integer :: info
    type(jfo_stats) :: st
    call grid(n, x, h, hmid, kmid, dx)
    pc = 0.0_dp
    p = 1e5_dp
    th = 1.0_dp
    p(20:25) = huge(1.0_dp)
    p2 = 1e5_dp
    th2 = 1.0_dp
    call jfo_solve(jfo_problem(dx=dx, u=10.0_dp, dt=1e-5_dp, p_left=3e5_dp, p_right=1e5_dp), h, &
                   hmid, kmid, h, pc, p, th, st)
    info = st%info
    call jfo_solve(jfo_problem(dx=dx, u=10.0_dp, dt=1e-5_dp, p_left=3e5_dp, p_right=1e5_dp), h, &
                   hmid, kmid, h, pc, p2, th2, st)
    call check(info == JFO_OK .and. all(ieee_is_finite(p)), 'huge warm start: converges, finite')
  call check(maxval(abs(p - p2)) <= 1e-10_dp * maxval(p2) .and. maxval(abs(th - th2)) <= 1e-10_dp, &
               'huge warm start: the solution of an ordinary warm start')
  end subroutine case_huge_warm_start

  !> The one-pass evaluations of the Newton iteration (jfo_newton_eval, jfo_residual_only,
  !> jfo_newton_apply) against jfo_residual's residual and Jacobian rows, at states mixing
  !> full and partly filled nodes, both sliding directions, a starved inlet and a capped edge:
  !> the same residual bit for bit, its largest entry and sum of squares, the elimination's
  !> step solving J dv = -R, and the step taken in place equal to v + dv with the nodes it
  !> switched counted.
  subroutine case_newton_passes()
    integer, parameter :: n = 61
    real(dp), allocatable :: x(:), h(:), hmid(:), kmid(:)
    real(dp) :: dx, v(n), r(n), r2(n), r3(n), cp(n), y(n), dv(n), dv2(n), v2(n), pc(n), cold(n)
    real(dp) :: sc, sc2, sc3, rmax, rmax3, fsq, fsq3, e, emax
    real(dp) :: jl(n), jd(n), ju(n)
    logical :: piv, sgn, same, apply_ok
    integer :: trial, i, nsw
    type(jfo_system) :: sys
    type(jfo_scratch) :: sk
    type(jfo_problem) :: prob
    call grid(n, x, h, hmid, kmid, dx)
    call jfo_scratch_size(sk, n)
    same = .true.
    apply_ok = .true.
    emax = 0.0_dp
    do trial = 1, 8
      pc = 0.5e5_dp
      cold = h * (0.5_dp + 0.5_dp * rnd(trial, [(i, i=1, n)]))
      prob = jfo_problem(dx=dx, u=merge(10.0_dp, -10.0_dp, mod(trial, 2) == 0), dt=1e-5_dp, &
                         p_left=3e5_dp, p_right=1e5_dp, theta_left=0.6_dp)
      if (trial > 4) prob%cap_right = 1e-7_dp
      call jfo_system_setup(sys, prob, h, hmid, kmid, cold, pc)
      ! a state with cavities and full zones: v in [-0.9, 2)
      v = -0.9_dp + 2.9_dp * rnd(trial, [(i + 100, i=1, n)])
      call jfo_residual(sys, v, r, sc, .true., sk%ev)
      jl = sk%ev%jl
      jd = sk%ev%jd
      ju = sk%ev%ju
      call jfo_newton_eval(sys, v, r2, sc2, rmax, fsq, sk%ev, cp, y, piv, sgn)
      call jfo_residual_only(sys, v, r3, sc3, rmax3, fsq3, sk%ev)
      same = same .and. all(r2(2:n - 1) == r(2:n - 1)) .and. all(r3(2:n - 1) == r(2:n - 1)) &
             .and. sc2 == sc .and. sc3 == sc .and. rmax == maxval(abs(r(2:n - 1))) &
             .and. rmax3 == rmax .and. fsq3 == fsq &
             .and. abs(fsq - sum(r(2:n - 1)**2)) <= 1e-14_dp * fsq
      call check(piv .and. sgn, 'newton passes: pivots nonzero, M-matrix signs')
      call jfo_newton_step(n, cp, y, dv)
      ! J dv = -R on this piece, to round-off of the terms
      do i = 2, n - 1
        e = jd(i) * dv(i) + r(i)
        if (i > 2) e = e + jl(i) * dv(i - 1)
        if (i < n - 1) e = e + ju(i) * dv(i + 1)
        emax = max(emax, abs(e) / (abs(jd(i) * dv(i)) + abs(r(i)) + abs(jl(i) * dv(max(i - 1, 1))) &
                                   + abs(ju(i) * dv(min(i + 1, n))) + tiny(1.0_dp)))
      end do
      v2 = v
      call jfo_newton_apply(n, cp, y, dv2, v2, nsw)
      apply_ok = apply_ok .and. all(dv2 == dv) .and. all(v2(2:n - 1) == v(2:n - 1) + dv(2:n - 1)) &
                 .and. nsw == count((v(2:n - 1) < 0.0_dp) .neqv. (v2(2:n - 1) < 0.0_dp)) &
                 .and. v2(1) == v(1) .and. v2(n) == v(n)
    end do
    write (*, '(2x, a, es10.2)') 'newton passes: largest relative residual of J dv = -R ', emax
    call check(same, 'newton passes: the residual, scale, largest entry and sum of squares')
    call check(emax <= 1e-12_dp, 'newton passes: the step solves J dv = -R')
    call check(apply_ok, 'newton passes: the step taken in place is v + dv, switches counted')
  end subroutine case_newton_passes

  ! ------------------------------------------------------------------ 9. settled steps
  !> The transient of case 3 (starved upstroke, the inflow capped below its Couette content on
  !> every other upstroke step, so that the cap comes and goes), solved twice, each from its
  !> own last state: with the settled-step exit (the default) and with the residual evaluated
  !> after every step (settle = .false.). The exit must be taken, give the same answers to the
  !> bit, and leave a state whose residual, evaluated by jfo_residual, is within the tolerance.
  subroutine case_settled_step()
    integer, parameter :: n = 61, nsteps = 240
    real(dp), allocatable :: x(:), h(:), hmid(:), kmid(:)
    real(dp) :: dx, dt, t, u, hmin_t, tin_l, rworst, sc
    real(dp) :: p(n), th(n), pb(n), tb(n), pc(n), cold(n), coldb(n), v(n), r(n)
    integer :: j, nsettled, ncapped
    logical :: same
    type(jfo_stats) :: st, stb
    type(jfo_problem) :: prob
    type(jfo_options) :: plain
    type(jfo_system) :: sys
    type(jfo_scratch) :: sk
    call grid(n, x, h, hmid, kmid, dx)
    call jfo_scratch_size(sk, n)
    plain%settle = .false.
    pc = 0.5e5_dp
    p = 1e5_dp
    th = 1.0_dp
    pb = p
    tb = th
    dt = 2e-5_dp
    same = .true.
    nsettled = 0
    ncapped = 0
    rworst = 0.0_dp
    do j = 1, nsteps
      t = j * dt
      u = 10.0_dp * sin(2 * pi * t / (nsteps * dt) + 0.3_dp)
      cold = th * h
      coldb = tb * h
      hmin_t = 1e-6_dp * (1.0_dp + 0.6_dp * sin(6 * pi * t / (nsteps * dt)))
      h = hmin_t + kk * (x + xs)**2
      hmid = hmin_t + kk * (0.5_dp * (x(1:n - 1) + x(2:n)) + xs)**2
      kmid = hmid**3 / (12 * eta)
      tin_l = merge(0.6_dp, 1.0_dp, u < 0.0_dp)
      prob = jfo_problem(dx=dx, u=u, dt=dt, p_left=3e5_dp, p_right=1e5_dp, theta_left=tin_l)
      if (u < 0.0_dp .and. mod(j, 2) == 0) then
        prob%cap_left = 0.8_dp * (-0.5_dp * u) * tin_l * hmid(1)
        ncapped = ncapped + 1
      end if
      call jfo_solve(prob, h, hmid, kmid, cold, pc, p, th, st)
      call jfo_solve(prob, h, hmid, kmid, coldb, pc, pb, tb, stb, plain)
      call check(st%info == JFO_OK .and. stb%info == JFO_OK, 'settled step: steps converge')
      call check(stb%settled == 0, 'settled step: settle = .false. evaluates every step')
      nsettled = nsettled + st%settled
      same = same .and. all(p == pb) .and. all(th == tb) .and. st%q_left == stb%q_left &
             .and. st%q_right == stb%q_right .and. st%iterations == stb%iterations
      ! the answer's residual, evaluated anew
      call jfo_system_setup(sys, prob, h, hmid, kmid, cold, pc)
      call jfo_state_to_v(sys, p, th, v)
      call jfo_residual(sys, v, r, sc, .false., sk%ev)
      rworst = max(rworst, maxval(abs(r(2:n - 1))) / sc)
    end do
    write (*, '(2x, a, i0, a, i0, a, i0, a, es10.2)') 'settled step: ', nsettled, ' of ', nsteps, &
      ' solves ended on a settled step (', ncapped, ' capped steps); worst residual / scale ', &
      rworst
    call check(nsettled >= nsteps / 4, 'settled step: the exit is taken')
    call check(same, 'settled step: the same answers, fluxes and iterations to the bit')
    call check(rworst <= 1e-11_dp, 'settled step: the answer within the tolerance')
  end subroutine case_settled_step
end program test_jfo
