!> Greenwood-Tripp asperity load and contact area over the ring face.
module ringlube_contact
  use ringlube_kinds, only: dp, pi
  use ringlube_greenwood_tripp, only: f2_exact, f52_exact, f2_fit, f52_fit, gt_lambda_max
  implicit none
  private
  public :: asperity_contact, asperity_pressure_scale, contact_params

  !> The asperity contact of a run (Greenwood-Tripp): the surfaces and the face, built once
  !> per run from the case. All components but the switches must be given.
  type :: contact_params
    !> composite roughness sigma = sqrt(Rq_liner^2 + Rq_ring^2) [m]
    real(dp) :: sigma
    !> roughness parameter zeta kappa sigma [1]
    real(dp) :: zeta_kappa_sigma
    !> sigma / kappa [1]
    real(dp) :: sigma_over_kappa
    !> reduced modulus E' [Pa]
    real(dp) :: e_reduced
    !> the power-law fits of F_5/2 and F_2 (else the exact, tabulated integrals)
    logical :: fit = .false.
    !> lambda = h0/sigma over the whole face (else the local lambda(x) at the nodes)
    logical :: lumped = .false.
    !> width b of the ring face and the circumference it runs along [m]
    real(dp) :: width, circumference
  end type contact_params

contains

  !> `(8 sqrt 2 / 15) pi (zeta kappa sigma)^2 sqrt(sigma/kappa) E'` [Pa]: W_a per unit
  !> nominal area is this times F_5/2.
  pure real(dp) function asperity_pressure_scale(zks, sok, e_reduced)
    real(dp), intent(in) :: zks, sok, e_reduced
    asperity_pressure_scale = 8.0_dp * sqrt(2.0_dp) / 15.0_dp * pi * zks**2 * sqrt(sok) * e_reduced
  end function asperity_pressure_scale

  !> Asperity load W_a [N] and real contact area A_a [m^2].
  !>
  !> Local (params%lumped false): trapezoidal integral of the local lambda(x) = h(x)/sigma over
  !> the nodes (gap h, spacing dx) times the circumference; lumped: lambda = h0/sigma over the
  !> whole face b * circumference. params%fit selects the power-law fits. Nodes with lambda
  !> beyond the functions' range (F_n = 0) are skipped.
  pure subroutine asperity_contact(params, h, h0, dx, wa, aa)
    type(contact_params), intent(in) :: params
    real(dp), intent(in) :: h(:), h0, dx
    real(dp), intent(out) :: wa, aa
    real(dp) :: s52, s2, lam, w
    integer :: i, n

    n = size(h)
    if (params%lumped) then
      call fvals(h0 / params%sigma, s52, s2)
      s52 = s52 * params%width
      s2 = s2 * params%width
    else
      s52 = 0.0_dp
      s2 = 0.0_dp
      do i = 1, n
        lam = h(i) / params%sigma
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
    wa = asperity_pressure_scale(params%zeta_kappa_sigma, params%sigma_over_kappa, &
                                 params%e_reduced) * params%circumference * s52
    aa = pi**2 * (params%zeta_kappa_sigma)**2 * params%circumference * s2

  contains

    pure subroutine fvals(l, f52, f2)
      real(dp), intent(in) :: l
      real(dp), intent(out) :: f52, f2
      if (params%fit) then
        f52 = f52_fit(l)
        f2 = f2_fit(l)
      else
        f52 = f52_exact(l)
        f2 = f2_exact(l)
      end if
    end subroutine fvals
  end subroutine asperity_contact
end module ringlube_contact
