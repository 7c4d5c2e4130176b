!> Shared by the mass-conserving film's tests (test_jfo, test_jfo_connect, test_jfo_coarse):
!> the closed forms of the parabolic slider's full film and rupture point, its grid, the
!> observed order of a sequence of errors, and the random steps of the cold-start tests.
module jfo_test_tools
  use ringlube_kinds, only: dp
  use ringlube_check
  use slider_closed_form, only: b, xs, eta, kk, ns, hz, j2, j3
  implicit none
  private
  public :: p_film, rupture_point, meniscus_point, grid, print_orders, rnd, random_step, ring_gap

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

  !> Where the full film that ruptures at zc with the flux -(U/2) hc (U = 10 m/s, p = 0
  !> there) falls to pl on its converging side: bisection on [lo, hi] (z, p_film > pl at lo).
  pure real(dp) function meniscus_point(zc, hc, pl, lo, hi) result(zm)
    real(dp), intent(in) :: zc, hc, pl, lo, hi
    real(dp) :: a, c, mid
    integer :: it
    a = lo
    c = hi
    do it = 1, 200
      mid = 0.5_dp * (a + c)
      if (p_film(mid, zc, hc, 0.0_dp, 10.0_dp) > pl) then
        a = mid
      else
        c = mid
      end if
    end do
    zm = 0.5_dp * (a + c)
  end function meniscus_point

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

  !> A reproducible number in [0, 1) for trial i, draw j (a hash, the same on every machine).
  elemental real(dp) function rnd(i, j)
    integer, intent(in) :: i, j
    rnd = modulo(sin(real(i, dp) * 12.9898_dp + real(j, dp) * 78.233_dp) * 43758.5453_dp, 1.0_dp)
  end function rnd

  !> The parabolic ring at the minimum gap hm on the nodes x: the gap h at the nodes, hmid and
  !> the Poiseuille conductance kmid at the faces.
  pure subroutine ring_gap(x, hm, h, hmid, kmid)
    real(dp), intent(in) :: x(:), hm
    real(dp), intent(out) :: h(:), hmid(:), kmid(:)
    integer :: n
    n = size(x)
    h = hm + kk * (x + xs)**2
    hmid = hm + kk * (0.5_dp * (x(1:n - 1) + x(2:n)) + xs)**2
    kmid = hmid**3 / (12 * eta)
  end subroutine ring_gap

  !> The random step of trial `trial` on the nodes x (draws 1-8): the parabolic ring at a
  !> minimum gap hm of 0.3-3.3 um (gap h at the nodes, hmid and kmid at the faces), speed u in
  !> +-20 m/s, edge pressures pl, pr of 1-11 bar, edge fills tl, tr, and a backward Euler
  !> step dt of 1e-7 to 1e-3 s, or a steady solve (dt = 0) three times in ten.
  subroutine random_step(trial, x, hm, h, hmid, kmid, u, pl, pr, tl, tr, dt)
    integer, intent(in) :: trial
    real(dp), intent(in) :: x(:)
    real(dp), intent(out) :: hm, h(:), hmid(:), kmid(:), u, pl, pr, tl, tr, dt
    hm = 0.3e-6_dp + 3e-6_dp * rnd(trial, 1)
    call ring_gap(x, hm, h, hmid, kmid)
    u = 40.0_dp * (rnd(trial, 2) - 0.5_dp)
    pl = 1e5_dp + 1e6_dp * rnd(trial, 3)**3
    pr = 1e5_dp + 1e6_dp * rnd(trial, 4)**3
    tl = min(1.0_dp, 1.5_dp * rnd(trial, 5))
    tr = min(1.0_dp, 1.5_dp * rnd(trial, 6))
    dt = 10.0_dp**(-7 + 4 * rnd(trial, 7))
    if (rnd(trial, 8) < 0.3_dp) dt = 0.0_dp
  end subroutine random_step
end module jfo_test_tools
