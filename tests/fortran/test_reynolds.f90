! ctest labels: numerics
!> The finite-difference Reynolds solver against closed-form pressures of a parabolic
!> ring at constant viscosity: steady sliding without and with Swift-Stieber rupture,
!> and pure squeeze (U = 0); observed convergence order in N.
program test_reynolds
  use ringlube_kinds, only: dp
  use ringlube_reynolds, only: reynolds_solve, reynolds_problem
  use ringlube_check
  use slider_closed_form, only: b, xs, h0, eta, kk, ns, hz, j2, j3
  implicit none
  real(dp) :: xc_exact

  xc_exact = rupture_point(10.0_dp, 2e5_dp, 0.0_dp)
  if (run_case('convergence_order')) call convergence_order()
  if (run_case('ambient_kkt')) call case_ambient_kkt()
  call report('test_reynolds')

contains

  !> Full film, pure squeeze and the rupture case against their closed forms, N = ns.
  subroutine convergence_order()
    real(dp) :: err_ff(4), err_sq(4), err_rey(4), order
    integer :: i
    character(len=80) :: what
    do i = 1, size(ns)
      err_ff(i) = case_full_film(ns(i))
      err_sq(i) = case_squeeze(ns(i))
      err_rey(i) = case_reynolds(ns(i))
    end do
    write (*, '(a)') '    N   full film    squeeze   reynolds (max |p - p_exact| / max p_exact)'
    do i = 1, size(ns)
      write (*, '(i5, 3es11.3)') ns(i), err_ff(i), err_sq(i), err_rey(i)
    end do
    do i = 2, size(ns)
      order = log(err_ff(i - 1) / err_ff(i)) / log(2.0_dp)
      write (what, '(a, i0, a, f5.2)') 'full film second order, N=', ns(i), ': order ', order
      call check(order > 1.9_dp, trim(what))
      order = log(err_sq(i - 1) / err_sq(i)) / log(2.0_dp)
      write (what, '(a, i0, a, f5.2)') 'squeeze second order, N=', ns(i), ': order ', order
      call check(order > 1.9_dp, trim(what))
      order = log(err_rey(i - 1) / err_rey(i)) / log(2.0_dp)
      write (what, '(a, i0, a, f5.2)') 'rupture case converges at least first order, N=', ns(i), &
        ': order ', order
      call check(order > 0.9_dp, trim(what))
    end do
    call check(err_ff(4) < 1e-4_dp .and. err_sq(4) < 1e-4_dp .and. err_rey(4) < 1e-3_dp, &
               'absolute accuracy at N=401')
  end subroutine convergence_order

  subroutine grid(n, x, hmid, kmid, dx)
    integer, intent(in) :: n
    real(dp), allocatable, intent(out) :: x(:), hmid(:), kmid(:)
    real(dp), intent(out) :: dx
    integer :: i
    allocate (x(n), hmid(n - 1), kmid(n - 1))
    dx = b / (n - 1)
    x = [(-0.5_dp * b + (i - 1) * dx, i=1, n)]
    hmid = hz(0.5_dp * (x(1:n - 1) + x(2:n)) + xs)
    kmid = hmid**3 / (6 * eta)
  end subroutine grid

  !> Both edges held (5 bar chamber side, 1 bar crankcase side), no cavitation.
  real(dp) function case_full_film(n) result(e)
    integer, intent(in) :: n
    real(dp), allocatable :: x(:), hmid(:), kmid(:), p(:), pe(:)
    logical, allocatable :: active(:)
    real(dp) :: dx, q, u, pa, pb, za, zb
    integer :: it, info
    u = -10.0_dp
    pa = 5e5_dp
    pb = 1e5_dp
    call grid(n, x, hmid, kmid, dx)
    allocate (p(n), active(n))
    active = .false.
    call reynolds_solve(reynolds_problem(dx=dx, u=u, sq=0.0_dp, p_left=pa, p_right=pb, &
                                         p_cav=-1e30_dp), kmid, hmid, p, active, it, info)
    call check(info == 0, 'full film solve')
    za = x(1) + xs
    zb = x(n) + xs
    q = ((pb - pa) / (6 * eta) + u * (j2(zb) - j2(za))) / (j3(zb) - j3(za))
    pe = pa + 6 * eta * (q * (j3(x + xs) - j3(za)) - u * (j2(x + xs) - j2(za)))
    e = maxval(abs(p - pe)) / maxval(abs(pe))
  end function case_full_film

  !> U = 0, approaching surfaces (dh0/dt < 0), both edges at 1 bar.
  real(dp) function case_squeeze(n) result(e)
    integer, intent(in) :: n
    real(dp), allocatable :: x(:), hmid(:), kmid(:), p(:), pe(:)
    logical, allocatable :: active(:)
    real(dp) :: dx, hdot, pa, c0, za, zb
    integer :: it, info
    hdot = -1e-3_dp
    pa = 1e5_dp
    call grid(n, x, hmid, kmid, dx)
    allocate (p(n), active(n))
    active = .false.
    call reynolds_solve(reynolds_problem(dx=dx, u=0.0_dp, sq=2 * hdot, p_left=pa, p_right=pa, &
                                         p_cav=0.0_dp), kmid, hmid, p, active, it, info)
    call check(info == 0 .and. .not. any(active), 'squeeze solve without cavitation')
    za = x(1) + xs
    zb = x(n) + xs
    ! K p' = 2 hdot x + C; p(b) = p(a) fixes C
    c0 = 2 * hdot / (4 * kk) * (1 / hz(zb)**2 - 1 / hz(za)**2) / (j3(zb) - j3(za))
    pe = pa + 6 * eta * (-2 * hdot / (4 * kk) * (1 / hz(x + xs)**2 - 1 / hz(za)**2) &
                         + c0 * (j3(x + xs) - j3(za)))
    e = maxval(abs(p - pe)) / maxval(abs(pe))
  end function case_squeeze

  !> Exact rupture point: lead edge x = +b/2 at p_in, p(x_c) = p_cav, p'(x_c) = 0.
  real(dp) function rupture_point(u, pin, pcav) result(xc)
    real(dp), intent(in) :: u, pin, pcav
    real(dp) :: lo, hi, mid
    integer :: it
    lo = -0.5_dp * b
    hi = -xs
    do it = 1, 200
      mid = 0.5_dp * (lo + hi)
      if (rupture_residual(mid, u, pin, pcav) > 0.0_dp) then
        hi = mid
      else
        lo = mid
      end if
    end do
    xc = 0.5_dp * (lo + hi)
  end function rupture_point

  !> p(x_c) - p_cav for a trial rupture point (flux fixed by p'(x_c) = 0).
  real(dp) function rupture_residual(x, u, pin, pcav) result(g)
    real(dp), intent(in) :: x, u, pin, pcav
    real(dp) :: zin, zc
    zin = 0.5_dp * b + xs
    zc = x + xs
    g = pin + 6 * eta * (u * hz(zc) * (j3(zc) - j3(zin)) - u * (j2(zc) - j2(zin))) - pcav
  end function rupture_residual

  !> Reynolds outlet: U > 0, inlet at the crankcase edge (2 bar), trailing edge at p_cav.
  real(dp) function case_reynolds(n) result(e)
    integer, intent(in) :: n
    real(dp), allocatable :: x(:), hmid(:), kmid(:), p(:), pe(:)
    logical, allocatable :: active(:)
    real(dp) :: dx, u, pin, q, zin, zc
    integer :: it, info, i, irupt
    u = 10.0_dp
    pin = 2e5_dp
    call grid(n, x, hmid, kmid, dx)
    allocate (p(n), active(n), pe(n))
    active = .false.
    call reynolds_solve(reynolds_problem(dx=dx, u=u, sq=0.0_dp, p_left=0.0_dp, p_right=pin, &
                                         p_cav=0.0_dp), kmid, hmid, p, active, it, info)
    call check(info == 0, 'reynolds solve')
    call check(all(p >= 0.0_dp), 'p >= p_cav everywhere')
    zin = 0.5_dp * b + xs
    zc = xc_exact + xs
    q = u * hz(zc)
    do i = 1, n
      if (x(i) <= xc_exact) then
        pe(i) = 0.0_dp
      else
        pe(i) = pin + 6 * eta * (q * (j3(x(i) + xs) - j3(zin)) - u * (j2(x(i) + xs) - j2(zin)))
      end if
    end do
    ! discrete rupture: the last cavitated node seen from the trailing (left) edge
    irupt = 1
    do i = 2, n - 1
      if (active(i)) irupt = i
    end do
    write (*, '(a, i4, a, f9.3, a, f9.3, a, i0)') 'N=', n, ' rupture at ', x(irupt) * 1e6_dp, &
      ' um, exact ', xc_exact * 1e6_dp, ' um; active-set iterations ', it
    call check(abs(x(irupt) - xc_exact) <= dx, 'rupture point within one cell')
    e = maxval(abs(p - pe)) / maxval(abs(pe))
  end function case_reynolds

  !> Ambient outlet with a sub-cavity zone: the discrete complementarity conditions hold.
  subroutine case_ambient_kkt()
    integer, parameter :: n = 201
    real(dp), allocatable :: x(:), hmid(:), kmid(:), p(:)
    logical, allocatable :: active(:)
    real(dp) :: dx, mu, r, u
    integer :: it, info, i
    u = 10.0_dp
    call grid(n, x, hmid, kmid, dx)
    allocate (p(n), active(n))
    active = .false.
    call reynolds_solve(reynolds_problem(dx=dx, u=u, sq=0.0_dp, p_left=1e5_dp, p_right=1e5_dp, &
                                         p_cav=0.0_dp), kmid, hmid, p, active, it, info)
    call check(info == 0 .and. count(active) > 0, 'ambient outlet: cavitation zone found')
    call check(all(p >= 0.0_dp), 'ambient: p >= p_cav')
    do i = 2, n - 1
      r = dx * u * (hmid(i) - hmid(i - 1))
      mu = -kmid(i - 1) * p(i - 1) + (kmid(i - 1) + kmid(i)) * p(i) - kmid(i) * p(i + 1) - r
      if (active(i)) then
        call check(p(i) == 0.0_dp .and. mu >= -1e-9_dp * abs(r), 'ambient: multiplier >= 0')
      else
        call check(abs(mu) <= 1e-9_dp * (abs(r) + kmid(i) * abs(p(i))), 'ambient: equation holds')
      end if
    end do
    ! the film re-forms before the trailing edge: p rises again to the edge value
    call check(.not. active(n - 1), 'ambient: film reformed before the trailing edge')
  end subroutine case_ambient_kkt
end program test_reynolds
