! ctest labels: numerics
!> The edges of the mass-conserving film: both edges are liquid boundaries at their
!> gas pressures; the net oil entering through an edge is capped at the oil there; the shear
!> of an interval is weighted like its flux (no shear where the flux carries no oil).
!>
!> 1. A steady slider whose trailing edge sits at a gas pressure above p_cav: the flooded JFO
!>    film ('vapour') re-forms at the edge and equals the Swift-Stieber film with both edges at
!>    their gas pressures ('ambient'), at every N (no cavity: the two discretisations are the
!>    same scheme), and differs from a gas-only trailing edge.
!> 2. A huge supply equals the flooded film; next to a trailing edge with no oil behind it the
!>    interval carries gas only and no shear (it vanishes with the cell).
!> 3. A trailing edge with a little oil behind it draws at most that oil over the step.
program test_film_edges
  use ringlube_kinds, only: dp, pi
  use ringlube_case, only: case_type, default_case
  use ringlube_film, only: film_type, film_setup, film_evaluate, film_friction
  use ringlube_greenwood_tripp, only: gt_init
  use ringlube_check
  implicit none
  type(case_type) :: c

  call gt_init()
  c = default_case()
  c%roelands = .false.
  c%asperity_contact = .false.
  c%cavitation_pressure = 0.0_dp
  c%crankcase_pressure = 1e5_dp
  if (run_case('slider_reforms_at_the_trailing_edge')) call slider_reforms_at_the_trailing_edge()
  if (run_case('huge_supply_equals_flooded_and_gas_only_interval')) &
    call huge_supply_equals_flooded_and_gas_only_interval()
  if (run_case('trailing_edge_draws_at_most_the_oil_behind')) &
    call trailing_edge_draws_at_most_the_oil_behind()
  call report('test_film_edges')

contains

  !> Steady film at h0 with u > 0 (leading edge: crankcase, right; trailing: chamber, left).
  subroutine steady(cc, n, h0, u, p_ch, f)
    type(case_type), intent(in) :: cc
    integer, intent(in) :: n
    real(dp), intent(in) :: h0, u, p_ch
    type(film_type), intent(out) :: f
    type(case_type) :: cn
    cn = cc
    cn%nodes = n
    call film_setup(cn, f)
    f%dt = 0.0_dp
    f%lead_left = u < 0.0_dp
    f%content_old = h0 + f%s
    call film_evaluate(cn, f, h0, 0.0_dp, u, p_ch, 0.0_dp)
  end subroutine steady

  subroutine slider_reforms_at_the_trailing_edge()
    type(case_type) :: cj, cs
    type(film_type) :: fj, fs
    integer :: k, n
    real(dp) :: dmax
    character(len=80) :: what
    cj = c
    cj%cavitation = 'jfo'
    cj%cavity_pressure = 'vapour'
    cj%inlet = 'flooded'
    cs = c
    cs%cavitation = 'swift_stieber'
    cs%outlet = 'ambient'
    do k = 1, 4
      n = 50 * 2**k + 1
      call steady(cj, n, 2e-5_dp, 10.0_dp, 3e6_dp, fj)
      call steady(cs, n, 2e-5_dp, 10.0_dp, 3e6_dp, fs)
      dmax = maxval(abs(fj%p - fs%p)) / maxval(fs%p)
      write (*, '(a, i5, a, es10.3, a, f8.5)') '1. N = ', n, ': max|p_jfo - p_ambient|/max p = ', &
        dmax, ', min fill ', minval(fj%theta)
      write (what, '(a, i0)') 'liquid trailing edge: JFO equals the ambient film, N = ', n
      call check(dmax < 1e-9_dp, trim(what))
      write (what, '(a, i0)') 'liquid trailing edge: film re-formed (full) at the edge, N = ', n
      call check(all(fj%theta >= 1.0_dp), trim(what))
      call check(minval(fs%p) > cs%cavitation_pressure, 'ambient film does not cavitate here')
    end do
  end subroutine slider_reforms_at_the_trailing_edge

  !> The same situation set up two ways: a flooded film, and a starved one with far more oil at
  !> both edges than the step can take: the same film and friction. And the shear of the
  !> interval next to a trailing edge at 3 MPa that has no oil behind it: its net inflow is
  !> capped at zero, the pressure-driven flux carries only the oil that balances the Couette
  !> outflow (the rest is gas), and its Poiseuille shear, weighted by that oil, vanishes with
  !> the cell, where the unweighted (h/2) dp/dx stays at h/2 times the pressure jump.
  subroutine huge_supply_equals_flooded_and_gas_only_interval()
    type(case_type) :: cf, cst
    type(film_type) :: ff, fst
    real(dp) :: fvf, fbf, fvs, fbs, edge_shear(3), jump_shear
    integer :: k
    character(len=80) :: what
    cf = c
    cf%cavitation = 'jfo'
    cf%cavity_pressure = 'vapour'
    cf%inlet = 'flooded'
    cst = cf
    cst%inlet = 'starved'
    call step(cf, 201, 3e6_dp, 0.0_dp, 0.0_dp, ff)
    call step(cst, 201, 3e6_dp, 1.0_dp, 1.0_dp, fst)
    call film_friction(cf, ff, 10.0_dp, fvf, fbf)
    call film_friction(cst, fst, 10.0_dp, fvs, fbs)
    write (*, '(a, 2f12.6)') '2. viscous friction flooded, starved with a huge supply:', fvf, fvs
    call check(maxval(abs(ff%p - fst%p)) <= 1e-9_dp * maxval(ff%p) .and. &
               maxval(abs(ff%theta - fst%theta)) <= 1e-12_dp, 'huge supply: the flooded film')
    call check_close(fvs, fvf, 1e-9_dp, 'huge supply: the flooded friction')
    do k = 1, 3
      call step(cst, 50 * 2**k + 1, 3e6_dp, 1.0_dp, 0.0_dp, fst)
      edge_shear(k) = shear_left(fst)
      jump_shear = 0.5_dp * fst%hmid(1) * (fst%p(2) - fst%p(1))
      write (*, '(a, i5, a, es10.3, a, es10.3)') '   N = ', fst%n, &
        ': shear force of the edge interval ', edge_shear(k), ' N/m; unweighted ', jump_shear
      write (what, '(a, i0)') 'no oil behind: no oil drawn through the trailing edge, N = ', fst%n
      call check(fst%q_left <= 1e-12_dp * abs(fst%q_right), trim(what))
    end do
    call check(abs(edge_shear(3)) < 0.3_dp * abs(edge_shear(1)), &
               'gas-only interval: its shear vanishes with the cell')
    call check(abs(edge_shear(3)) < 1e-2_dp * abs(jump_shear), &
               'gas-only interval: no (h/2) dp/dx across the pressure jump')
  end subroutine huge_supply_equals_flooded_and_gas_only_interval

  !> Shear force per unit circumference [N/m] of the first interval (next to the left edge).
  real(dp) function shear_left(f)
    type(film_type), intent(in) :: f
    real(dp) :: fv, fb
    type(film_type) :: g
    g = f
    ! the friction of the first interval alone: the others' pressure gradients and fills zeroed
    g%p(3:) = g%p(2)
    g%theta(3:) = 0.0_dp
    call film_friction(cst_case(), g, 10.0_dp, fv, fb)
    shear_left = -fv / g%circ
  end function shear_left

  function cst_case() result(cc)
    type(case_type) :: cc
    cc = c
    cc%cavitation = 'jfo'
    cc%inlet = 'starved'
  end function cst_case

  !> One step of 20 us at u = 10 m/s (leading edge right, trailing edge, the chamber, left at
  !> p_ch) from a face a third full: `lead` [m^2] of oil at the leading edge, `behind` behind
  !> the trailing edge (both ignored when flooded).
  subroutine step(cc, n, p_ch, lead, behind, f)
    type(case_type), intent(in) :: cc
    integer, intent(in) :: n
    real(dp), intent(in) :: p_ch, lead, behind
    type(film_type), intent(out) :: f
    type(case_type) :: cn
    real(dp) :: h0
    cn = cc
    cn%nodes = n
    call film_setup(cn, f)
    h0 = 2e-6_dp
    f%dt = 2e-5_dp
    f%lead_left = .false.
    f%ds = 10.0_dp * f%dt
    f%available = lead
    f%behind = behind
    f%content_old = (h0 + f%s) / 3.0_dp
    call film_evaluate(cn, f, h0, 0.0_dp, 10.0_dp, p_ch, 0.0_dp)
  end subroutine step

  subroutine trailing_edge_draws_at_most_the_oil_behind()
    type(case_type) :: cj
    type(film_type) :: f0, f
    real(dp) :: behind, drawn0
    integer :: k
    character(len=80) :: what
    cj = c
    cj%cavitation = 'jfo'
    cj%cavity_pressure = 'vapour'
    cj%inlet = 'starved'
    ! unlimited oil behind: how much the edge would draw (inflow through the left face)
    call step(cj, 201, 3e6_dp, 1.0_dp, 1.0_dp, f0)
    drawn0 = f0%q_left * f0%dt
   write (*, '(a, es11.4, a)') '3. oil drawn back through the trailing edge with plenty behind: ', &
      drawn0, ' m^2'
    call check(drawn0 > 0.0_dp, 'the trailing edge draws oil back at 3 MPa')
    do k = 1, 3
      behind = drawn0 * 0.25_dp * k
      call step(cj, 201, 3e6_dp, 1.0_dp, behind, f)
      write (what, '(a, f5.2, a)') 'trailing edge draws at most the oil behind it (', &
        0.25_dp * k, ' of its demand)'
      call check_close(f%q_left * f%dt, behind, 1e-9_dp, trim(what))
    end do
  end subroutine trailing_edge_draws_at_most_the_oil_behind
end program test_film_edges
