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
      ! lo and hi are neighbouring numbers (after about 55 halvings): later ones give mid again
      if (mid <= lo .or. mid >= hi) exit
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
