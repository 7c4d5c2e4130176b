!> Greenwood-Tripp asperity load and contact area over the ring face (SPEC section 6).
module ringlube_contact
  use ringlube_kinds, only: dp, pi
  use ringlube_greenwood_tripp, only: f2_exact, f52_exact, f2_fit, f52_fit, gt_lambda_max
  implicit none
  private
  public :: asperity_contact, asperity_pressure_scale

contains

  !> `(8 sqrt 2 / 15) pi (zeta kappa sigma)^2 sqrt(sigma/kappa) E'` [Pa]: W_a per unit
  !> nominal area is this times F_5/2.
  pure real(dp) function asperity_pressure_scale(zks, sok, e_reduced)
    real(dp), intent(in) :: zks, sok, e_reduced
    asperity_pressure_scale = 8.0_dp * sqrt(2.0_dp) / 15.0_dp * pi * zks**2 * sqrt(sok) * e_reduced
  end function asperity_pressure_scale

  !> Asperity load W_a [N] and real contact area A_a [m^2].
  !>
  !> `local`: trapezoidal integral of the local lambda(x) = h(x)/sigma over the nodes
  !> (spacing dx) times the circumference `circ`; `lumped`: lambda = h0/sigma over the
  !> whole face b * circ. `fit` selects the power-law fits. Nodes with lambda beyond the
  !> functions' range (F_n = 0) are skipped.
  pure subroutine asperity_contact(h, h0, dx, width, circ, sigma, zks, sok, e_reduced, &
                                   use_fit, lumped, wa, aa)
    real(dp), intent(in) :: h(:), h0, dx, width, circ, sigma, zks, sok, e_reduced
    logical, intent(in) :: use_fit, lumped
    real(dp), intent(out) :: wa, aa
    real(dp) :: s52, s2, lam, w
    integer :: i, n

    n = size(h)
    if (lumped) then
      call fvals(h0 / sigma, s52, s2)
      s52 = s52 * width
      s2 = s2 * width
    else
      s52 = 0.0_dp
      s2 = 0.0_dp
      do i = 1, n
        lam = h(i) / sigma
        if (lam >= gt_lambda_max) cycle
        w = dx
        if (i == 1 .or. i == n) w = 0.5_dp * dx
        block
          real(dp) :: a, b
          call fvals(lam, a, b)
          s52 = s52 + w * a
          s2 = s2 + w * b
        end block
      end do
    end if
    wa = asperity_pressure_scale(zks, sok, e_reduced) * circ * s52
    aa = pi**2 * (zks)**2 * circ * s2

  contains

    pure subroutine fvals(l, f52, f2)
      real(dp), intent(in) :: l
      real(dp), intent(out) :: f52, f2
      if (use_fit) then
        f52 = f52_fit(l)
        f2 = f2_fit(l)
      else
        f52 = f52_exact(l)
        f2 = f2_exact(l)
      end if
    end subroutine fvals
  end subroutine asperity_contact
end module ringlube_contact
