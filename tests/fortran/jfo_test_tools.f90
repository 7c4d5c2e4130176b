!> Shared by the mass-conserving film's tests (test_jfo, test_jfo_connect): the closed forms
!> of the parabolic slider's full film and rupture point, its grid, and the observed order of
!> a sequence of errors.
module jfo_test_tools
  use ringlube_kinds, only: dp
  use ringlube_check
  use slider_closed_form, only: b, xs, eta, ns, hz, j2, j3
  implicit none
  private
  public :: p_film, rupture_point, grid, print_orders

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
end module jfo_test_tools
