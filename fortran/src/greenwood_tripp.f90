!> Greenwood-Tripp statistical functions F_2 and F_5/2.
!>
!> `F_n(lambda) = 1/sqrt(2 pi) int_lambda^inf (s - lambda)^n exp(-s^2/2) ds`.
!>
!> * F_2 uses its closed form in erfc and exp.
!> * F_5/2 ('exact') is `phi(lambda) I(lambda)` with `I(lambda) = int_0^inf t^(5/2)
!>   exp(-lambda t - t^2/2) dt`. The substitution t = u^2 makes the integrand smooth,
!>   so Gauss-Legendre quadrature converges exponentially. `log I` is tabulated with its
!>   exact derivative `-I_7/2 / I_5/2` and interpolated by cubic Hermite polynomials;
!>   the relative error is below 1e-8 on 0 <= lambda <= 10 (checked against adaptive
!>   quadrature in the tests). The table is a constant of the process: `gt_init` builds
!>   it once (about 1 ms) and later calls return at once; it holds no run state. Until
!>   it is built, `f52_exact` falls back to direct quadrature. Above lambda = 10 both
!>   functions are returned as 0 (F_5/2(10) ~ 1e-25).
!> * 'fit': the power laws `F_5/2 ~ 4.4068e-5 (4-lambda)^6.804` (the literature fit)
!>   and `F_2 ~ 2.5441e-4 (4-lambda)^5.0886` (same form, least squares on log F_2 over
!>   0..3.5, fitted for ringlube), both 0 for lambda >= 4.
module ringlube_greenwood_tripp
  use ringlube_kinds, only: dp, pi
  implicit none
  private
  public :: gt_init, f2_exact, f52_exact, f2_fit, f52_fit, gt_integrals, gauss_legendre

  !> Upper end of the tabulated range; F_n = 0 above it.
  real(dp), parameter, public :: gt_lambda_max = 10.0_dp
  !> Table spacing in lambda.
  real(dp), parameter :: dlam = 0.02_dp
  integer, parameter :: ntab = nint(gt_lambda_max / dlam) + 1
  !> Gauss-Legendre nodes per panel of the I_m quadrature.
  integer, parameter :: ngauss = 24

  !> Table of log I_5/2 and its lambda-derivative on a uniform grid (process constant).
  logical :: table_ready = .false.
  real(dp) :: logi(ntab), dlogi(ntab)

contains

  !> Gauss-Legendre nodes and weights on [-1, 1] (Newton iteration on P_n).
  pure subroutine gauss_legendre(n, x, w)
    integer, intent(in) :: n
    real(dp), intent(out) :: x(n), w(n)
    integer :: i, j, it
    real(dp) :: z, p1, p2, p3, pp, z1
    do i = 1, (n + 1) / 2
      z = cos(pi * (i - 0.25_dp) / (n + 0.5_dp))
      do it = 1, 100
        p1 = 1.0_dp
        p2 = 0.0_dp
        do j = 1, n
          p3 = p2
          p2 = p1
          p1 = ((2 * j - 1) * z * p2 - (j - 1) * p3) / j
        end do
        pp = n * (z * p1 - p2) / (z * z - 1.0_dp)
        z1 = z
        z = z1 - p1 / pp
        if (abs(z - z1) < 1e-15_dp) exit
      end do
      x(i) = -z
      x(n + 1 - i) = z
      w(i) = 2.0_dp / ((1.0_dp - z * z) * pp * pp)
      w(n + 1 - i) = w(i)
    end do
  end subroutine gauss_legendre

  !> `I_5/2` and `I_7/2` at lambda, where `I_m = int_0^inf t^m exp(-lambda t - t^2/2) dt`,
  !> by composite Gauss-Legendre in u = sqrt(t) (integrands 2 u^6 e^.. and 2 u^8 e^..).
  pure subroutine gt_integrals(lambda, i52, i72)
    real(dp), intent(in) :: lambda
    real(dp), intent(out) :: i52, i72
    real(dp) :: xg(ngauss), wg(ngauss)
    call gauss_legendre(ngauss, xg, wg)
    call gt_integrals_on(lambda, xg, wg, i52, i72)
  end subroutine gt_integrals

  !> gt_integrals with the ngauss Gauss-Legendre nodes xg and weights wg given.
  pure subroutine gt_integrals_on(lambda, xg, wg, i52, i72)
    real(dp), intent(in) :: lambda, xg(ngauss), wg(ngauss)
    real(dp), intent(out) :: i52, i72
    integer, parameter :: npanel = 8
    real(dp) :: umax, a, h, u, t, g
    integer :: ip, ig
    ! beyond umax the integrand is below exp(-60) of its scale
    umax = sqrt(-lambda + sqrt(lambda**2 + 120.0_dp))
    h = umax / npanel
    i52 = 0.0_dp
    i72 = 0.0_dp
    do ip = 1, npanel
      a = (ip - 1) * h
      do ig = 1, ngauss
        u = a + 0.5_dp * h * (xg(ig) + 1.0_dp)
        t = u * u
        g = h * wg(ig) * t**3 * exp(-lambda * t - 0.5_dp * t * t)
        i52 = i52 + g
        i72 = i72 + g * t
      end do
    end do
  end subroutine gt_integrals_on

  !> Build the F_5/2 table once per process (later calls return at once).
  subroutine gt_init()
    integer :: i
    real(dp) :: i52, i72, xg(ngauss), wg(ngauss)
    if (table_ready) return
    call gauss_legendre(ngauss, xg, wg)
    do i = 1, ntab
      call gt_integrals_on((i - 1) * dlam, xg, wg, i52, i72)
      logi(i) = log(i52)
      dlogi(i) = -i72 / i52
    end do
    table_ready = .true.
  end subroutine gt_init

  !> Standard normal density.
  elemental real(dp) function phi(x)
    real(dp), intent(in) :: x
    phi = exp(-0.5_dp * x * x) / sqrt(2.0_dp * pi)
  end function phi

  !> F_2 from its closed form `(1 + l^2) Q(l) - l phi(l)`, Q the normal tail.
  elemental real(dp) function f2_exact(lambda)
    real(dp), intent(in) :: lambda
    real(dp) :: l
    l = max(lambda, 0.0_dp)
    if (.not. (lambda <= gt_lambda_max)) then
      f2_exact = 0.0_dp
    else
      f2_exact = (1.0_dp + l * l) * 0.5_dp * erfc(l / sqrt(2.0_dp)) - l * phi(l)
    end if
  end function f2_exact

  !> F_5/2 from the table (cubic Hermite interpolation of log I).
  elemental real(dp) function f52_exact(lambda) result(f)
    real(dp), intent(in) :: lambda
    real(dp) :: l, s, t, h00, h10, h01, h11, y, i52, i72
    integer :: i
    ! a non-finite lambda never reaches the table index (NaN fails every comparison)
    if (.not. (lambda < gt_lambda_max)) then
      f = 0.0_dp
      return
    end if
    l = max(lambda, 0.0_dp)
    if (.not. table_ready) then
      call gt_integrals(l, i52, i72)
      f = phi(l) * i52
      return
    end if
    s = l / dlam
    i = min(int(s) + 1, ntab - 1)
    t = s - (i - 1)
    h00 = (1.0_dp + 2.0_dp * t) * (1.0_dp - t)**2
    h10 = t * (1.0_dp - t)**2
    h01 = t * t * (3.0_dp - 2.0_dp * t)
    h11 = t * t * (t - 1.0_dp)
    y = h00 * logi(i) + h10 * dlam * dlogi(i) + h01 * logi(i + 1) + h11 * dlam * dlogi(i + 1)
    f = phi(l) * exp(y)
  end function f52_exact

  !> Power-law fit of F_2 (ringlube's own coefficients, see module doc).
  elemental real(dp) function f2_fit(lambda)
    real(dp), intent(in) :: lambda
    f2_fit = power_fit(lambda, 2.5441e-4_dp, 5.0886_dp)
  end function f2_fit

  !> Literature power-law fit of F_5/2.
  elemental real(dp) function f52_fit(lambda)
    real(dp), intent(in) :: lambda
    f52_fit = power_fit(lambda, 4.4068e-5_dp, 6.804_dp)
  end function f52_fit

  !> The form of both fits: k (4 - lambda)^e below lambda = 4 (lambda < 0 taken as 0), zero above.
  elemental real(dp) function power_fit(lambda, k, e) result(f)
    real(dp), intent(in) :: lambda, k, e
    if (lambda < 4.0_dp) then
      f = k * (4.0_dp - max(lambda, 0.0_dp))**e
    else
      f = 0.0_dp
    end if
  end function power_fit
end module ringlube_greenwood_tripp
