! ctest labels: unit;numerics
!> F_2 and F_5/2 against adaptive quadrature of their defining integral, and the cost
!> of the power-law fits.
program test_greenwood_tripp
  use ringlube_kinds, only: dp, pi
  use ringlube_greenwood_tripp, only: gt_init, f2_exact, f52_exact, f2_fit, f52_fit
  use ringlube_check
  use, intrinsic :: ieee_arithmetic, only: ieee_value, ieee_quiet_nan, ieee_positive_inf
  implicit none
  integer :: i
  real(dp) :: lam, q2, q52, e2, e52, worst2, worst52, fiterr52(0:6), fiterr2(0:6)
  character(len=64) :: what
  real(dp) :: qn, ql   ! order and lambda of the integrand being integrated

  ! before the table exists f52_exact integrates directly; after, it interpolates
  call check_close(f52_exact(1.234_dp), quad(2.5_dp, 1.234_dp), 1e-9_dp, 'F5/2 direct before init')
  call gt_init()
  worst2 = 0.0_dp
  worst52 = 0.0_dp
  do i = 0, 600
    lam = i * 0.01_dp + 0.003_dp * mod(i, 3)   ! on and between table nodes
    q2 = quad(2.0_dp, lam)
    q52 = quad(2.5_dp, lam)
    e2 = abs(f2_exact(lam) - q2) / q2
    e52 = abs(f52_exact(lam) - q52) / q52
    worst2 = max(worst2, e2)
    worst52 = max(worst52, e52)
    write (what, '(a, f6.3)') 'F2 closed form vs quadrature at lambda=', lam
    call check(e2 <= 1e-9_dp, trim(what))
    write (what, '(a, f6.3)') 'F5/2 vs quadrature to 1e-6 at lambda=', lam
    call check(e52 <= 1e-6_dp, trim(what))
  end do
  write (*, '(a, es9.2, a, es9.2)') 'max rel error on [0,6]: F2 ', worst2, '  F5/2 ', worst52
  ! limits: F_n(0) = 2^(n/2) Gamma((n+1)/2) / (2 sqrt(pi))
  call check_close(f2_exact(0.0_dp), 0.5_dp, 1e-14_dp, 'F2(0) = 1/2')
  call check_close(f52_exact(0.0_dp), 2.0_dp**1.25_dp * gamma(1.75_dp) / (2.0_dp * sqrt(pi)), &
                   1e-8_dp, 'F5/2(0) from the Gamma function')
  call check(f52_exact(10.5_dp) == 0.0_dp .and. f2_exact(10.5_dp) == 0.0_dp, 'zero above lambda 10')

  ! fits: never negative, zero from lambda = 4, and their error measured (printed)
  do i = 0, 6
    lam = real(i, dp)
    fiterr52(i) = (f52_fit(lam) - f52_exact(lam)) / f52_exact(lam)
    fiterr2(i) = (f2_fit(lam) - f2_exact(lam)) / f2_exact(lam)
  end do
  write (*, '(a)') 'fit relative error at lambda = 0..6:'
  write (*, '(a, 7f8.3)') '  F5/2 ', fiterr52
  write (*, '(a, 7f8.3)') '  F2   ', fiterr2
  do i = 0, 800
    lam = i * 0.01_dp
    call check(f52_fit(lam) >= 0.0_dp .and. f2_fit(lam) >= 0.0_dp, 'fits never negative')
  end do
  call check(f52_fit(4.0_dp) == 0.0_dp .and. f2_fit(4.5_dp) == 0.0_dp, 'fits zero above 4')
  ! a non-finite lambda (from a non-finite film) must never index the table
  call check(f52_exact(ieee_value(1.0_dp, ieee_quiet_nan)) == 0.0_dp, &
             'F5/2(NaN) = 0, no table index')
  call check(f2_exact(ieee_value(1.0_dp, ieee_quiet_nan)) == 0.0_dp, 'F2(NaN) = 0')
  call check(f52_exact(ieee_value(1.0_dp, ieee_positive_inf)) == 0.0_dp, 'F5/2(+Inf) = 0')
  call report('test_greenwood_tripp')

contains

  !> Independent reference: adaptive Simpson of (s-l)^n phi(s) over s in [l, l+40],
  !> started on 400 panels so that no feature of the integrand is missed.
  real(dp) function quad(n, l)
    real(dp), intent(in) :: n, l
    real(dp) :: a, b, fa, fm, fb, whole, tol
    integer :: i
    qn = n
    ql = l
    ! absolute tolerance per panel, scaled to the size of the result
    tol = 1e-16_dp * exp(-0.5_dp * l * l) / (1.0_dp + l)**(n + 1.0_dp)
    quad = 0.0_dp
    do i = 1, 400
      a = l + (i - 1) * 0.1_dp
      b = a + 0.1_dp
      fa = g(a); fb = g(b); fm = g(0.5_dp * (a + b))
      whole = (b - a) / 6.0_dp * (fa + 4.0_dp * fm + fb)
      quad = quad + simpson(a, b, fa, fm, fb, whole, tol, 40)
    end do
  end function quad

  real(dp) function g(s)
    real(dp), intent(in) :: s
    g = (s - ql)**qn * exp(-0.5_dp * s * s) / sqrt(2.0_dp * pi)
  end function g

  recursive real(dp) function simpson(a, b, fa, fm, fb, whole, tol, depth) result(r)
    real(dp), intent(in) :: a, b, fa, fm, fb, whole, tol
    integer, intent(in) :: depth
    real(dp) :: m, lm, rm, flm, frm, left, right
    m = 0.5_dp * (a + b)
    lm = 0.5_dp * (a + m); rm = 0.5_dp * (m + b)
    flm = g(lm); frm = g(rm)
    left = (m - a) / 6.0_dp * (fa + 4.0_dp * flm + fm)
    right = (b - m) / 6.0_dp * (fm + 4.0_dp * frm + fb)
    if (depth <= 0 .or. abs(left + right - whole) <= 15.0_dp * tol) then
      r = left + right + (left + right - whole) / 15.0_dp
    else
      r = simpson(a, m, fa, flm, fm, left, 0.5_dp * tol, depth - 1) &
          + simpson(m, b, fm, frm, fb, right, 0.5_dp * tol, depth - 1)
    end if
  end function simpson
end program test_greenwood_tripp
