!> The gas flows of the ring pack: the end-gap orifice (isentropic nozzle, choked
!> and unchoked, straight near r = 1 so that Newton's method has a finite slope) and the
!> groove-flank channels (isothermal viscous flow between parallel plates).
module ringlube_ring_pack_flow
  use ringlube_kinds, only: dp
  implicit none
  private
  public :: orifice_consts, orifice_constants, orifice_eval, orifice_flow, channel_flow, orifice_psi

  !> Gas constant of air and burnt gas [J/(kg K)].
  real(dp), parameter, public :: gas_constant = 287.0_dp
  !> Below a pressure difference of this fraction of the upstream pressure the orifice's
  !> Psi(r) is replaced by the straight line from Psi(1 - orifice_linear) to 0 at r = 1
  !> (the exact Psi has an infinite slope there; Newton's method needs a finite one).
  real(dp), parameter, public :: orifice_linear = 1e-4_dp

  !> Constants of the orifice law for one gamma: 2 g/(g-1), 2/g, (g+1)/g, r*, Psi(r*) and
  !> Psi where it turns straight.
  type :: orifice_consts
    real(dp) :: k = 0.0_dp, e1 = 0.0_dp, e2 = 0.0_dp, rc = 0.0_dp, psi_c = 0.0_dp, &
                psi_lin = 0.0_dp
  end type orifice_consts

contains

  !> The orifice's flow function: Psi(r) = sqrt(2 g/(g-1) (r^(2/g) - r^((g+1)/g))) for
  !> r = p_d/p_u above the critical ratio (2/(g+1))^(g/(g-1)), Psi(r*) below it (choked).
  pure real(dp) function orifice_psi(r, gamma) result(psi)
    real(dp), intent(in) :: r, gamma
    real(dp) :: rr
    rr = max(r, (2.0_dp / (gamma + 1.0_dp))**(gamma / (gamma - 1.0_dp)))
    rr = min(rr, 1.0_dp)
    psi = sqrt(max(0.0_dp, 2.0_dp * gamma / (gamma - 1.0_dp) &
                   * (rr**(2.0_dp / gamma) - rr**((gamma + 1.0_dp) / gamma))))
  end function orifice_psi

  !> Isentropic orifice flow from a to b [kg/s] (negative from b to a):
  !> C_d A p_u / sqrt(R T) Psi(p_d/p_u), with Psi straight within
  !> `orifice_linear` of r = 1. Optional derivatives with respect to p_a and p_b.
  pure subroutine orifice_flow(cd_area, pa, pb, temperature, gamma, q, dq_dpa, dq_dpb)
    real(dp), intent(in) :: cd_area, pa, pb, temperature, gamma
    real(dp), intent(out) :: q
    real(dp), intent(out), optional :: dq_dpa, dq_dpb
    real(dp) :: da, db
    call orifice_eval(orifice_constants(gamma), cd_area / sqrt(gas_constant * temperature), &
                      pa, pb, q, da, db)
    if (present(dq_dpa)) dq_dpa = da
    if (present(dq_dpb)) dq_dpb = db
  end subroutine orifice_flow

  !> The gamma-dependent constants of the orifice law.
  pure function orifice_constants(gamma) result(oc)
    real(dp), intent(in) :: gamma
    type(orifice_consts) :: oc
    oc%k = 2.0_dp * gamma / (gamma - 1.0_dp)
    oc%e1 = 2.0_dp / gamma
    oc%e2 = (gamma + 1.0_dp) / gamma
    oc%rc = (2.0_dp / (gamma + 1.0_dp))**(gamma / (gamma - 1.0_dp))
    oc%psi_c = orifice_psi(oc%rc, gamma)
    oc%psi_lin = orifice_psi(1.0_dp - orifice_linear, gamma)
  end function orifice_constants

  !> orifice_flow with the constants at hand; c = C_d A / sqrt(R T).
  pure subroutine orifice_eval(oc, c, pa, pb, q, dq_dpa, dq_dpb)
    type(orifice_consts), intent(in) :: oc
    real(dp), intent(in) :: c, pa, pb
    real(dp), intent(out) :: q, dq_dpa, dq_dpb
    real(dp) :: pu, pd, r, psi, dpsi, sgn, dq_pu, dq_pd, lr, ra, rb
    if (pa >= pb) then
      pu = pa
      pd = pb
      sgn = 1.0_dp
    else
      pu = pb
      pd = pa
      sgn = -1.0_dp
    end if
    if (pu <= 0.0_dp .or. c <= 0.0_dp) then
      q = 0.0_dp
      dq_dpa = 0.0_dp
      dq_dpb = 0.0_dp
      return
    end if
    r = pd / pu
    if (r <= oc%rc) then
      psi = oc%psi_c
      dpsi = 0.0_dp
    else if (r < 1.0_dp - orifice_linear) then
      ! Psi = sqrt(k (r^e1 - r^e2)), dPsi/dr = k (e1 r^e1 - e2 r^e2) / (2 r Psi)
      lr = log(r)
      ra = exp(oc%e1 * lr)
      rb = exp(oc%e2 * lr)
      psi = sqrt(max(0.0_dp, oc%k * (ra - rb)))
      dpsi = 0.0_dp
      if (psi > 0.0_dp) dpsi = 0.5_dp * oc%k * (oc%e1 * ra - oc%e2 * rb) / (r * psi)
    else
      psi = oc%psi_lin * (1.0_dp - r) / orifice_linear
      dpsi = -oc%psi_lin / orifice_linear
    end if
    q = sgn * c * pu * psi
    ! q = c pu Psi(pd/pu): d/dpu = c (Psi - r Psi'), d/dpd = c Psi'
    dq_pu = c * (psi - r * dpsi)
    dq_pd = c * dpsi
    if (sgn > 0.0_dp) then
      dq_dpa = dq_pu
      dq_dpb = dq_pd
    else
      dq_dpa = -dq_pd
      dq_dpb = -dq_pu
    end if
  end subroutine orifice_eval

  !> Laminar isothermal channel flow from a to b [kg/s] through a gap g of length w and
  !> width l: l g^3 (p_a^2 - p_b^2) / (24 mu R T w); derivatives optional.
  pure subroutine channel_flow(width, gap, length, viscosity, temperature, pa, pb, q, &
                               dq_dpa, dq_dpb)
    real(dp), intent(in) :: width, gap, length, viscosity, temperature, pa, pb
    real(dp), intent(out) :: q
    real(dp), intent(out), optional :: dq_dpa, dq_dpb
    real(dp) :: k
    k = width * max(gap, 0.0_dp)**3 / (24.0_dp * viscosity * gas_constant * temperature * length)
    q = k * (pa**2 - pb**2)
    if (present(dq_dpa)) dq_dpa = 2.0_dp * k * pa
    if (present(dq_dpb)) dq_dpb = -2.0_dp * k * pb
  end subroutine channel_flow
end module ringlube_ring_pack_flow
