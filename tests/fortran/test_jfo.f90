!> The mass-conserving (JFO) film kernel ringlube_jfo against exact and independent answers
!> (docs/film_model.md, "Verification"):
!>  1. flooded steady parabolic ring = the Swift-Stieber closed form (no reformation), order in N;
!>  2. the oscillatory squeeze film with rupture and reformation (Ausas, Jai and Buscaglia 2009,
!>     J. Tribol. 131:031702, after Optasanu and Bonneau 2000): semi-analytical solution, order;
!>  3. mass conservation over a transient with sliding, reversal, rupture and reformation;
!>  4. an independent Elrod/Ausas relaxation solver (jfo_reference) on that transient;
!>  5. bounds and complementarity; starved inlet (closed form), theta_in -> 0 thins the film;
!>  6. the cavity-pressure connectivity rule: trailing gas (closed form), leading gas, enclosed;
!>  7. the anti-cycling guard and the Gauss-Seidel fallback;
!>  8. the inflow cap of the leading edge (the oil there) against a fill found by bisection.
!> Semi-analytical solution of the oscillatory squeeze film (see case_squeeze in test_jfo).
module squeeze_exact
  use ringlube_kinds, only: dp, pi
  implicit none
  real(dp), parameter :: pa = 0.025_dp
  real(dp) :: t1 = 0, t2 = 0

contains

  real(dp) function sq_h(t)
    real(dp), intent(in) :: t
    sq_h = 0.375_dp + 0.125_dp * cos(4 * pi * t)
  end function sq_h
  real(dp) function sq_hdot(t)
    real(dp), intent(in) :: t
    sq_hdot = -0.5_dp * pi * sin(4 * pi * t)
  end function sq_hdot
  real(dp) function sq_sigma_eq(t)
    real(dp), intent(in) :: t
    sq_sigma_eq = sqrt(2 * pa * sq_h(t)**3 / sq_hdot(t))
  end function sq_sigma_eq

  real(dp) function front_speed(tt, ss)
    real(dp), intent(in) :: tt, ss
    real(dp) :: den, q
    q = pa * sq_h(tt)**3 / ss - sq_hdot(tt) * ss / 2
    den = sq_h(tt) - content_at(ss)
    if (den <= 1e-14_dp .or. q <= 0.0_dp) then
      front_speed = 0.0_dp
    else
      front_speed = q / den
    end if
  end function front_speed
  !> content left in the cavity at x when the front passed it (growth phase t1..t2)
  real(dp) function content_at(xx)
    real(dp), intent(in) :: xx
    content_at = sq_h(bisect_t(t1, t2, xx))
  end function content_at
  !> oil in the cavity [s, 1/2] at time tt (Simpson)
  real(dp) function cavity_content(ss, tt)
    real(dp), intent(in) :: ss, tt
    integer, parameter :: m = 200
    integer :: q
    real(dp) :: hq, xq
    cavity_content = 0.0_dp
    if (ss >= 0.5_dp .or. tt < t1) return
    hq = (0.5_dp - ss) / m
    do q = 0, m
      xq = ss + q * hq
      cavity_content = cavity_content + hq / 3 * content_at(xq) &
                       * merge(1.0_dp, merge(4.0_dp, 2.0_dp, mod(q, 2) == 1), q == 0 .or. q == m)
    end do
  end function cavity_content
  !> the time in [ta, tb] at which sigma_eq (decreasing there) equals xx
  real(dp) function bisect_t(ta, tb, xx)
    real(dp), intent(in) :: ta, tb, xx
    real(dp) :: lo, hi, mid
    integer :: q
    lo = ta
    hi = tb
    do q = 1, 100
      mid = 0.5_dp * (lo + hi)
      if (sq_sigma_eq(mid) > xx) then
        lo = mid
      else
        hi = mid
      end if
    end do
    bisect_t = 0.5_dp * (lo + hi)
  end function bisect_t
  real(dp) function golden_min(ta, tb)
    real(dp), intent(in) :: ta, tb
    real(dp) :: lo, hi, m1, m2
    integer :: q
    lo = ta
    hi = tb
    do q = 1, 200
      m1 = lo + (hi - lo) * 0.381966_dp
      m2 = hi - (hi - lo) * 0.381966_dp
      if (sq_sigma_eq(m1) < sq_sigma_eq(m2)) then
        hi = m2
      else
        lo = m1
      end if
    end do
    golden_min = 0.5_dp * (lo + hi)
  end function golden_min
end module squeeze_exact

program test_jfo
  use ringlube_kinds, only: dp, pi
  use ringlube_jfo
  use ringlube_jfo_connect
  use ringlube_reynolds, only: reynolds_solve
  use jfo_reference, only: elrod_solve
  use ringlube_check
  use squeeze_exact
  use slider_closed_form, only: b, xs, h0, eta, kk, ns, hz, j2, j3
  implicit none

  if (run_case('flooded_slider')) call case_flooded_slider()
  if (run_case('trailing_gas')) call case_trailing_gas()
  if (run_case('starved')) call case_starved()
  if (run_case('squeeze')) call case_squeeze()
  if (run_case('transient')) call case_transient()
  if (run_case('connectivity_rule')) call case_connectivity_rule()
  if (run_case('enclosed_cavity')) call case_enclosed_cavity()
  if (run_case('guard')) call case_guard()
  if (run_case('inflow_cap')) call case_inflow_cap()
  if (run_case('bad_input')) call case_bad_input()
  call report('test_jfo')

contains

  ! ------------------------------------------------------------------ closed forms

  !> Full-film pressure for U > 0 from a point zc where p = pc0 and the flux is -(U/2) hc:
  !> k p' = (U/2)(hc - h)  ->  p = pc0 + 6 eta U [hc (J3(z) - J3(zc)) - (J2(z) - J2(zc))].
  elemental real(dp) function p_film(z, zc, hc, pc0, u)
    real(dp), intent(in) :: z, zc, hc, pc0, u
    p_film = pc0 + 6 * eta * u * (hc * (j3(z) - j3(zc)) - (j2(z) - j2(zc)))
  end function p_film

  !> Swift-Stieber / JFO rupture point for U > 0, inlet at x = +b/2 at pin, film ends at
  !> p = pexit with p' = 0 (bisection on the diverging side).
  real(dp) function rupture_point(u, pin, pexit) result(xc)
    real(dp), intent(in) :: u, pin, pexit
    real(dp) :: lo, hi, mid, zin
    integer :: it
    lo = -0.5_dp * b
    hi = -xs
    zin = 0.5_dp * b + xs
    do it = 1, 200
      mid = 0.5_dp * (lo + hi)
      ! p at the inlet of the film that ruptures at mid, minus pin
      if (p_film(zin, mid + xs, hz(mid + xs), pexit, u) - pin > 0.0_dp) then
        lo = mid
      else
        hi = mid
      end if
    end do
    xc = 0.5_dp * (lo + hi)
  end function rupture_point

  subroutine grid(n, x, h, hmid, kmid, dx)
    integer, intent(in) :: n
    real(dp), allocatable, intent(out) :: x(:), h(:), hmid(:), kmid(:)
    real(dp), intent(out) :: dx
    integer :: i
    dx = b / (n - 1)
    x = [(-0.5_dp * b + (i - 1) * dx, i=1, n)]
    h = hz(x + xs)
    hmid = hz(0.5_dp * (x(1:n - 1) + x(2:n)) + xs)
    kmid = hmid**3 / (12 * eta)
  end subroutine grid

  subroutine print_orders(label, err, lo)
    character(len=*), intent(in) :: label
    real(dp), intent(in) :: err(:), lo
    integer :: i
    real(dp) :: order
    character(len=120) :: what
    do i = 2, size(err)
      order = log(err(i - 1) / err(i)) / log(2.0_dp)
      write (*, '(2x, a, a, i0, a, f6.2)') label, ': observed order at N=', ns(i), ' is ', order
      write (what, '(a, a, i0, a, f6.2)') label, ' order N=', ns(i), ': ', order
      call check(order > lo, trim(what))
    end do
  end subroutine print_orders

  ! ------------------------------------------------------------------ 1. flooded steady slider
  !> U = 10 m/s (inlet at the crankcase edge, 2 bar), trailing edge at p_cav = 0: the JFO film
  !> ruptures with p = 0, p' = 0 and never re-forms, so it must equal Swift-Stieber.
  subroutine case_flooded_slider()
    real(dp), allocatable :: x(:), h(:), hmid(:), kmid(:), p(:), th(:), pc(:), pe(:), pss(:)
    logical, allocatable :: active(:)
    real(dp) :: dx, xc, err(4), dss(4), ql, qr, q_exact
    integer :: k, n, it, info, itw, its
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
      call jfo_solve(dx, h, hmid, kmid, 10.0_dp, 0.0_dp, h, 0.0_dp, 2e5_dp, 1.0_dp, 1.0_dp, pc, &
                     p, th, it, info, ql, qr)
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
      call reynolds_solve(dx, 2 * kmid, hmid, 10.0_dp, 0.0_dp, 0.0_dp, 2e5_dp, 0.0_dp, pss, &
                          active, its, info)
      dss(k) = maxval(abs(p - pss)) / maxval(pe)
      ! warm start from the solution, slightly perturbed step: 1 iteration
      call jfo_solve(dx, h, hmid, kmid, 10.0_dp * (1 + 1e-3_dp), 0.0_dp, h, 0.0_dp, 2e5_dp, &
                     1.0_dp, 1.0_dp, pc, p, th, itw, info)
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

  ! ------------------------------------------------------------------ 6a. trailing gas
  !> Trailing edge at p_t = 1 bar > p_cav = 0 with cavity_pressure = 'trailing_gas': the cavity
  !> touching the trailing edge sits at p_t, and the film ruptures with p = p_t, p' = 0
  !> (SPEC 13: the Reynolds exit condition at the downstream gas pressure).
  subroutine case_trailing_gas()
    real(dp), allocatable :: x(:), h(:), hmid(:), kmid(:), p(:), th(:), pc(:), pe(:)
    real(dp) :: dx, xc, err(4), pt
    integer :: k, n, it, outer, info
    pt = 1e5_dp
    xc = rupture_point(10.0_dp, 2e5_dp, pt)
    write (*, '(a)') '6a. trailing gas: film ruptures at p_t with dp/dx = 0 (closed form)'
    do k = 1, size(ns)
      n = ns(k)
      call grid(n, x, h, hmid, kmid, dx)
      allocate (p(n), th(n), pc(n))
      p = pt
      th = 1.0_dp
      ! the trailing edge admits gas only (theta_left = 0): no oil is pushed in from there
      call jfo_solve_connected(dx, h, hmid, kmid, 10.0_dp, 0.0_dp, h, pt, 2e5_dp, 0.0_dp, 1.0_dp, &
                               0.0_dp, .true., .false., pc, p, th, it, outer, info)
      call check(info == JFO_OK, 'trailing gas converges')
      pe = merge(p_film(x + xs, xc + xs, hz(xc + xs), pt, 10.0_dp), pt, x > xc)
      err(k) = maxval(abs(p - pe)) / maxval(pe)
      write (*, '(a, i4, a, es10.3, a, i0, a, i0)') '  N=', n, ' max|p-p_exact|/max p ', err(k), &
        '  outer loops ', outer, '  Newton its ', it
      call check(all(pc(2:n - 1) == merge(pt, 0.0_dp, th(2:n - 1) < 1.0_dp)), &
                 'trailing gas: cavity at p_t, full film at p_cav')
      call check(th(2) < 1.0_dp, 'trailing gas: the cavity reaches the trailing edge')
      deallocate (p, th, pc)
    end do
    call print_orders('trailing gas vs closed form', err, 0.9_dp)
  end subroutine case_trailing_gas

  ! ------------------------------------------------------------------ 5/6b. starved inlet
  !> Steady starved ring, U = 10 m/s, leading (crankcase) edge at p_l = 2 bar admits theta_in.
  !> Closed form: the partly filled inlet zone is open to the leading gas (p = p_l) and carries
  !> the Couette content theta_in h_le; the full film ends where h = h_c = theta_in h_le (flux
  !> -(U/2) h_c, p = p_cav, p' = 0) and starts at the meniscus x_m where the film pressure from
  !> there reaches p_l.
  subroutine case_starved()
    real(dp), allocatable :: x(:), h(:), hmid(:), kmid(:), p(:), th(:), pc(:), pe(:), te(:)
    real(dp), allocatable :: pf(:), tf(:)
    real(dp) :: dx, err(4), errt(4), tin, hle, hc, zc, xm, pl, lo, hi, mid, load, vol
    real(dp) :: prev_load, prev_vol
    real(dp), parameter :: fills(10) = [1.0_dp, 0.7_dp, 0.5_dp, 0.4_dp, 0.3_dp, 0.2_dp, 0.12_dp, &
                                        0.05_dp, 0.01_dp, 0.0_dp]
    integer :: k, n, it, outer, info, i
    logical :: thin, finite_ok
    pl = 2e5_dp
    tin = 0.12_dp
    hle = hz(0.5_dp * b + xs)
    hc = tin * hle
    zc = -sqrt((hc - h0) / kk)
    ! meniscus: p_film falls from its peak (at z = +sqrt((hc-h0)/kk)) to p_l
    lo = sqrt((hc - h0) / kk)
    hi = 0.5_dp * b + xs
    call check(p_film(hi, zc, hc, 0.0_dp, 10.0_dp) < pl, 'starved closed form: meniscus inside')
    do i = 1, 200
      mid = 0.5_dp * (lo + hi)
      if (p_film(mid, zc, hc, 0.0_dp, 10.0_dp) > pl) then
        lo = mid
      else
        hi = mid
      end if
    end do
    xm = 0.5_dp * (lo + hi) - xs
    write (*, '(a, f5.2, a, f8.2, a, f8.2, a)') '5. starved inlet, theta_in = ', tin, &
      ': rupture at ', (zc - xs) * 1e6_dp, ' um, meniscus at ', xm * 1e6_dp, ' um (exact)'
    do k = 1, size(ns)
      n = ns(k)
      call grid(n, x, h, hmid, kmid, dx)
      allocate (p(n), th(n), pc(n), pf(n), tf(n))
      p = 0.0_dp
      th = 1.0_dp
      call jfo_solve_connected(dx, h, hmid, kmid, 10.0_dp, 0.0_dp, h, 0.0_dp, pl, 1.0_dp, tin, &
                               0.0_dp, .false., .true., pc, p, th, it, outer, info)
      call check(info == JFO_OK, 'starved ring converges')
      pe = merge(p_film(x + xs, zc, hc, 0.0_dp, 10.0_dp), 0.0_dp, x > zc - xs)
      where (x >= xm) pe = pl
      te = merge(1.0_dp, hc / h, x > zc - xs .and. x < xm)
      err(k) = maxval(abs(p - pe)) / maxval(pe)
      errt(k) = sum(abs(th - te)) / n
      write (*, '(a, i4, a, es10.3, a, es10.3, a, i0, a, i0)') '  N=', n, &
        ' max|p-p_exact|/max p ', err(k), '  mean|theta-theta_exact| ', errt(k), &
        '  outer ', outer, '  its ', it
      call check(all(pc(n - 3:n - 1) == pl) .and. all(th(n - 3:n - 1) < 1.0_dp), &
                 'starved: inlet zone partly filled at the leading gas pressure')
      call check(all(p >= pc) .and. all(th >= 0.0_dp .and. th <= 1.0_dp), 'starved: bounds')
      ! theta_in = 1 with the leading-gas rule is the flooded film, exactly
      pf = 0.0_dp
      tf = 1.0_dp
      call jfo_solve_connected(dx, h, hmid, kmid, 10.0_dp, 0.0_dp, h, 0.0_dp, pl, 1.0_dp, 1.0_dp, &
                               0.0_dp, .false., .true., pc, pf, tf, it, outer, info)
      p = 0.0_dp
      th = 1.0_dp
      pc = 0.0_dp
      call jfo_solve(dx, h, hmid, kmid, 10.0_dp, 0.0_dp, h, 0.0_dp, pl, 1.0_dp, 1.0_dp, pc, p, th, &
                     it, info)
      call check(all(pf == p) .and. all(tf == th), 'starved: theta_in = 1 equals the flooded film')
      deallocate (p, th, pc, pf, tf)
    end do
    call print_orders('starved pressure vs closed form', err, 0.8_dp)
    call print_orders('starved fill vs closed form', errt, 0.8_dp)

    ! theta_in -> 0: load and oil volume fall monotonically, nothing breaks
    n = 101
    call grid(n, x, h, hmid, kmid, dx)
    allocate (p(n), th(n), pc(n))
    p = 0.0_dp
    th = 1.0_dp
    prev_load = huge(1.0_dp)
    prev_vol = huge(1.0_dp)
    thin = .true.
    finite_ok = .true.
    write (*, '(a)') '  theta_in   load (N/m)   oil volume (m^2)  info'
    do k = 1, size(fills)
      call jfo_solve_connected(dx, h, hmid, kmid, 10.0_dp, 0.0_dp, h, 0.0_dp, pl, 1.0_dp, &
                               fills(k), 0.0_dp, .false., .true., pc, p, th, it, outer, info)
      load = dx * sum(p(2:n - 1))
      vol = jfo_film_volume(dx, h, th)
      write (*, '(f10.2, es13.4, es16.4, i5)') fills(k), load, vol, info
      finite_ok = finite_ok .and. info == JFO_OK .and. all(abs(p) < huge(1.0_dp)) &
                  .and. all(th >= 0.0_dp .and. th <= 1.0_dp)
      thin = thin .and. load <= prev_load .and. vol < prev_vol
      prev_load = load
      prev_vol = vol
    end do
    call check(finite_ok, 'starved: every fill converges with finite p and theta in [0, 1]')
    call check(thin, 'starved: load and oil volume fall monotonically as theta_in -> 0')
    ! (dry to round-off: the Thomas sweep multiplies by reciprocals)
    call check(vol <= 1e-15_dp * dx * sum(h) .and. all(abs(p(2:n - 1) - pl) <= 1e-12_dp * pl), &
               'starved: theta_in = 0 is a dry face at p_l')
  end subroutine case_starved

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
        call jfo_solve(dx, h, hmid, kmid, 0.0_dp, dt, cold, pa, pa, 1.0_dp, 1.0_dp, pc, p, th, &
                       it, info)
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
      call jfo_solve(dx, h, hmid, kmid, u, dt, cold, 3e5_dp, 1e5_dp, tin_l, tin_r, pc, p, th, &
                     it, info, ql, qr)
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
      call jfo_solve_connected(dx, h, hmid, kmid, u, dt, cold, 3e5_dp, 1e5_dp, tin_l, tin_r, &
                               0.5e5_dp, .true., .true., pc, p, th, it, outer, info, ql, qr)
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

  ! ------------------------------------------------------------------ 6. connectivity rule
  subroutine case_connectivity_rule()
    real(dp) :: th(10), pc(10), pp(10)
    real(dp), parameter :: pcav = 0.1e5_dp, pch = 3e5_dp, pcc = 1e5_dp
    write (*, '(a)') '6. cavity-pressure connectivity rule on constructed fills'
    ! downstroke (u > 0): trailing = chamber (left), leading = crankcase (right)
    th = [1.0_dp, 0.5_dp, 0.5_dp, 1.0_dp, 0.3_dp, 0.3_dp, 1.0_dp, 1.0_dp, 0.4_dp, 0.4_dp]
    call jfo_cavity_pressure(th, 5.0_dp, pch, pcc, pcav, .true., .true., pc)
    call check(all(pc == [pcav, pch, pch, pcav, pcav, pcav, pcav, pcav, pcc, pcav]), &
               'rule: trailing run at p_t, enclosed at p_cav, leading zone at p_l (u > 0)')
    call jfo_cavity_pressure(th, 5.0_dp, pch, pcc, pcav, .false., .true., pc)
    call check(all(pc == [pcav, pcav, pcav, pcav, pcav, pcav, pcav, pcav, pcc, pcav]), &
               'rule: vapour trailing cavity, starved leading zone')
    call jfo_cavity_pressure(th, 5.0_dp, pch, pcc, pcav, .true., .false., pc)
    call check(all(pc == [pcav, pch, pch, pcav, pcav, pcav, pcav, pcav, pcav, pcav]), &
               'rule: trailing gas, flooded leading side')
    ! upstroke (u < 0): trailing = crankcase (right), leading = chamber (left)
    call jfo_cavity_pressure(th, -5.0_dp, pch, pcc, pcav, .true., .true., pc)
    call check(all(pc == [pcav, pch, pch, pcav, pcav, pcav, pcav, pcav, pcc, pcav]), &
               'rule: upstroke, both edge runs open to their gas')
    ! gas below the cavitation pressure: the cavity stays at p_cav
    call jfo_cavity_pressure(th, -5.0_dp, 0.0_dp, 0.0_dp, pcav, .true., .true., pc)
    call check(all(pc == pcav), 'rule: gas below p_cav leaves the cavity at p_cav')
    ! partly filled across the whole width: the higher gas pressure
    th = 0.5_dp
    call jfo_cavity_pressure(th, 5.0_dp, pch, pcc, pcav, .false., .true., pc)
    call check(all(pc(2:9) == pch), 'rule: face partly filled across its width at the higher gas')
    ! all full: p_cav everywhere
    th = 1.0_dp
    call jfo_cavity_pressure(th, 5.0_dp, pch, pcc, pcav, .true., .true., pc)
    call check(all(pc == pcav), 'rule: full film at p_cav')
    ! a starved inlet zone, then full film below the leading gas pressure up to the trailing
    ! edge: the zone reaches across the face only through full film, so the face is not partly
    ! filled across its width: the leading gas pressure, not the higher chamber pressure
    th = [1.0_dp, 1.0_dp, 1.0_dp, 1.0_dp, 1.0_dp, 1.0_dp, 1.0_dp, 0.5_dp, 0.5_dp, 0.5_dp]
    pp = 0.5e5_dp
    call jfo_cavity_pressure(th, 5.0_dp, pch, pcc, pcav, .false., .true., pc, pp)
    call check(all(pc(2:9) == pcc), &
               'rule: full film below the gas joins the zone, not a partly filled face')
    ! both edges open, their zones overlapping through full film below both: the lower gas
    call jfo_cavity_pressure(th, 5.0_dp, pch, pcc, pcav, .true., .true., pc, pp)
    call check(all(pc(2:9) == min(pch, pcc)), 'rule: overlapping zones at the lower gas')
  end subroutine case_connectivity_rule

  !> Both edges at 1 bar, U = 10 (the trailing edge is the left one), p_cav = 0. 'vapour' (both
  !> edges liquid, SPEC 13): the cavity that forms on the diverging side re-forms before the
  !> trailing edge, so it is enclosed and stays at p_cav. 'trailing_gas': the trailing edge is a
  !> gas interface, so the film below its gas pressure next to it joins the gas: the cavity
  !> reaches the trailing edge and sits at its pressure.
  subroutine case_enclosed_cavity()
    integer, parameter :: n = 201
    real(dp), allocatable :: x(:), h(:), hmid(:), kmid(:), p(:), th(:), pc(:)
    real(dp) :: dx, ql, qr
    integer :: it, outer, info
    call grid(n, x, h, hmid, kmid, dx)
    allocate (p(n), th(n), pc(n))
    p = 1e5_dp
    th = 1.0_dp
    call jfo_solve_connected(dx, h, hmid, kmid, 10.0_dp, 0.0_dp, h, 1e5_dp, 1e5_dp, 1.0_dp, &
                             1.0_dp, 0.0_dp, .false., .false., pc, p, th, it, outer, info, ql, qr)
    write (*, '(a, i0, a, i0, a, i0)') '6c. enclosed cavity: ', count(th < 1.0_dp), &
      ' cavity nodes, outer loops ', outer, ', Newton its ', it
    call check(info == JFO_OK, 'enclosed cavity converges')
    call check(count(th < 1.0_dp) > 3 .and. th(2) == 1.0_dp .and. th(n - 1) == 1.0_dp, &
               'enclosed cavity: ruptures and re-forms inside the face')
    call check(all(pc == 0.0_dp) .and. all(pack(p, th < 1.0_dp) == 0.0_dp), &
               'enclosed cavity: at p_cav, not at the gas pressure')
    call check_close(ql, qr, 1e-10_dp, 'enclosed cavity: steady flux through the face')
    p = 1e5_dp
    th = 1.0_dp
    call jfo_solve_connected(dx, h, hmid, kmid, 10.0_dp, 0.0_dp, h, 1e5_dp, 1e5_dp, 1.0_dp, &
                             1.0_dp, 0.0_dp, .true., .false., pc, p, th, it, outer, info, ql, qr)
    call check(info == JFO_OK, 'open cavity converges')
    call check(count(th < 1.0_dp) > 3 .and. th(2) < 1.0_dp .and. th(n - 1) == 1.0_dp, &
               'trailing gas: the cavity reaches the trailing edge')
    call check(all(pack(p, th < 1.0_dp) == 1e5_dp) .and. pc(2) == 1e5_dp, &
               'trailing gas: the open cavity at the trailing gas pressure')
    call check_close(ql, qr, 1e-10_dp, 'open cavity: steady flux through the face')
  end subroutine case_enclosed_cavity

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
    call grid(n, x, h, hmid, kmid, dx)
    allocate (p(n), th(n), pc(n), p0(n), t0(n), pg(n), tg(n))
    itmx = 0
    pc = 0.0_dp
    ! reference solution of a case with an enclosed cavity
    p0 = 1e5_dp
    t0 = 1.0_dp
    call jfo_solve(dx, h, hmid, kmid, 10.0_dp, 0.0_dp, h, 1e5_dp, 1e5_dp, 1.0_dp, 1.0_dp, pc, &
                   p0, t0, it, info)
    ! the Gauss-Seidel fallback alone reaches the same solution
    p = 1e5_dp
    th = 1.0_dp
    call jfo_solve(dx, h, hmid, kmid, 10.0_dp, 0.0_dp, h, 1e5_dp, 1e5_dp, 1.0_dp, 1.0_dp, pc, &
                   p, th, it, info, newton=.false., max_iter=2000000, sweeps=sw)
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
      hm = 0.3e-6_dp + 3e-6_dp * rnd(trial, 1)
      hh = hm + kk * (x + xs)**2
      hmm = hm + kk * (0.5_dp * (x(1:n - 1) + x(2:n)) + xs)**2
      km = hmm**3 / (12 * eta)
      u = 40.0_dp * (rnd(trial, 2) - 0.5_dp)
      pl = 1e5_dp + 1e6_dp * rnd(trial, 3)**3
      pr = 1e5_dp + 1e6_dp * rnd(trial, 4)**3
      tinl = min(1.0_dp, 1.5_dp * rnd(trial, 5))
      tinr = min(1.0_dp, 1.5_dp * rnd(trial, 6))
      dtr = 10.0_dp**(-7 + 4 * rnd(trial, 7))
      if (rnd(trial, 8) < 0.3_dp) dtr = 0.0_dp
      pc = 0.5e5_dp
      if (rnd(trial, 9) < 0.5_dp) pc(2:2 + int(20 * rnd(trial, 10))) = max(pl, 0.5e5_dp)
      do i = 1, n
        t0(i) = min(1.0_dp, 1.3_dp * rnd(trial, 10 + i))
        p0(i) = 1e7_dp * rnd(trial, 500 + i)**2
      end do
      cold = hh * min(1.0_dp, t0 + 0.2_dp)
      p = p0
      th = t0
      call jfo_solve(dx, hh, hmm, km, u, dtr, cold, pl, pr, tinl, tinr, pc, p, th, it, info, &
                     guard=.false., max_iter=200)
      if (info /= JFO_OK) nfail_plain = nfail_plain + 1
      pg = p0
      tg = t0
      call jfo_solve(dx, hh, hmm, km, u, dtr, cold, pl, pr, tinl, tinr, pc, pg, tg, it, info, &
                     sweeps=sw)
      if (info /= JFO_OK) nfail_guard = nfail_guard + 1
      if (sw > 0) nguarded = nguarded + 1
      itmx = max(itmx, it)
      ! one iteration only: not converged, flagged, finite and within bounds
      p = p0
      th = t0
      call jfo_solve(dx, hh, hmm, km, u, dtr, cold, pl, pr, tinl, tinr, pc, p, th, it, info, &
                     max_iter=1)
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

  !> deterministic pseudo-random number in [0, 1)
  real(dp) function rnd(i, j)
    integer, intent(in) :: i, j
    rnd = modulo(sin(real(i, dp) * 12.9898_dp + real(j, dp) * 78.233_dp) * 43758.5453_dp, 1.0_dp)
  end function rnd

  ! ------------------------------------------------------------------ 8. inflow cap
  !> The cap on the oil entering through the leading edge (inflow_cap) against an independent
  !> construction: the same problem without a cap, with the edge fill theta_left found by
  !> bisection such that the inflow equals the cap. The flux of the first face enters only the
  !> first node's balance, so both must give the same film.
  subroutine case_inflow_cap()
    integer, parameter :: n = 81
    real(dp), allocatable :: x(:), h(:), hmid(:), kmid(:), p(:), th(:), pc(:), pb(:), tb(:)
    real(dp) :: dx, dt, u, q0, qcap, ql, qr, lo, hi, tl, v0, v1
    integer :: it, info, k
    call grid(n, x, h, hmid, kmid, dx)
    allocate (p(n), th(n), pc(n), pb(n), tb(n))
    pc = 0.0_dp
    u = -10.0_dp              ! leading edge on the left (content moves to +x)
    dt = 1e-5_dp
    ! uncapped: a starved inlet (fill 0.5) at 3 bar drawn in by a film below it
    p = 1e5_dp
    th = 1.0_dp
    call jfo_solve(dx, h, hmid, kmid, u, dt, 0.6_dp * h, 3e5_dp, 1e5_dp, 0.5_dp, 1.0_dp, pc, p, &
                   th, it, info, q0, qr)
    call check(info == JFO_OK .and. q0 > 0.0_dp, 'inflow cap: the uncapped inlet draws oil in')
    qcap = 0.6_dp * q0
    p = 1e5_dp
    th = 1.0_dp
    call jfo_solve(dx, h, hmid, kmid, u, dt, 0.6_dp * h, 3e5_dp, 1e5_dp, 0.5_dp, 1.0_dp, pc, p, &
                   th, it, info, ql, qr, cap_left=qcap)
    v0 = jfo_film_volume(dx, h, 0.6_dp * h / h)
    v1 = jfo_film_volume(dx, h, th)
    call check(info == JFO_OK, 'inflow cap: converges')
    call check_close(ql, qcap, 1e-12_dp, 'inflow cap: the inflow equals the cap')
    call check(abs((v1 - v0) - dt * (ql - qr)) <= 1e-12_dp * v0, 'inflow cap: oil balance closes')
    ! independent: bisection on the edge fill of the uncapped problem
    lo = 0.0_dp
    hi = 0.5_dp
    do k = 1, 200
      tl = 0.5_dp * (lo + hi)
      pb = 1e5_dp
      tb = 1.0_dp
      call jfo_solve(dx, h, hmid, kmid, u, dt, 0.6_dp * h, 3e5_dp, 1e5_dp, tl, 1.0_dp, pc, pb, &
                     tb, it, info, ql, qr)
      if (ql > qcap) then
        hi = tl
      else
        lo = tl
      end if
      if (hi - lo < 1e-15_dp) exit
    end do
    write (*, '(a, f8.5, a, es10.3, a, es10.3)') '8. inflow cap: bisected edge fill ', tl, &
      ', max |dp|/max p ', maxval(abs(pb - p)) / maxval(p), ', max |dtheta| ', &
      maxval(abs(tb(2:n - 1) - th(2:n - 1)))
    ! (interior nodes: the edge values are the edge fills, 0.5 and the bisected one)
    call check(maxval(abs(pb - p)) <= 1e-8_dp * maxval(p) &
               .and. maxval(abs(tb(2:n - 1) - th(2:n - 1))) <= 1e-8_dp, &
               'inflow cap: the same film as the bisected edge fill')
    ! the Gauss-Seidel fallback alone applies the cap too and reaches the same film
    pb = 1e5_dp
    tb = 1.0_dp
    call jfo_solve(dx, h, hmid, kmid, u, dt, 0.6_dp * h, 3e5_dp, 1e5_dp, 0.5_dp, 1.0_dp, pc, pb, &
                   tb, it, info, ql, qr, cap_left=qcap, newton=.false., max_iter=2000000)
    write (*, '(a, i0, a, es10.3)') '   Gauss-Seidel alone with the cap: ', it, &
      ' sweeps, max |dp|/max p ', maxval(abs(pb - p)) / maxval(p)
    call check(info == JFO_OK .and. maxval(abs(pb - p)) <= 1e-8_dp * maxval(p) &
               .and. maxval(abs(tb(2:n - 1) - th(2:n - 1))) <= 1e-8_dp, &
               'inflow cap: the Gauss-Seidel fallback reaches the capped Newton film')
    call check_close(ql, qcap, 1e-8_dp, 'inflow cap: Gauss-Seidel inflow at the cap')
    ! a cap above the inflow changes nothing
    pb = 1e5_dp
    tb = 1.0_dp
    call jfo_solve(dx, h, hmid, kmid, u, dt, 0.6_dp * h, 3e5_dp, 1e5_dp, 0.5_dp, 1.0_dp, pc, pb, &
                   tb, it, info, ql, qr, cap_left=2.0_dp * q0)
    call check_close(ql, q0, 1e-12_dp, 'inflow cap: a cap above the inflow is inactive')
  end subroutine case_inflow_cap

  subroutine case_bad_input()
    real(dp) :: h(2), hm(1), km(1), p(2), th(2), pc(2)
    integer :: it, info
    h = 1e-6_dp
    hm = 1e-6_dp
    km = 1e-18_dp
    p = 0.0_dp
    th = 1.0_dp
    pc = 0.0_dp
    call jfo_solve(1e-5_dp, h, hm, km, 1.0_dp, 0.0_dp, h, 0.0_dp, 0.0_dp, 1.0_dp, 1.0_dp, pc, p, &
                   th, it, info)
    call check(info == JFO_BAD_INPUT, 'bad input: n < 3 flagged')
  end subroutine case_bad_input
end program test_jfo
