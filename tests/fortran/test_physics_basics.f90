! ctest labels: unit;numerics
!> Kinematics against a finite difference of the piston position; Roelands against its
!> defining properties and a hand-computed value, and its pressure-viscosity step
!> (roelands_update) against the law node by node; the gas trace's interpolation against a
!> plain search for the interval.
program test_physics_basics
  use ringlube_kinds, only: dp, pi
  use ringlube_kinematics, only: sliding_speed, piston_position
  use ringlube_viscosity, only: roelands, roelands_law, roelands_law_at, roelands_eta, &
                                roelands_update
  use ringlube_gas, only: gas_pressure
  use ringlube_check
  implicit none
  real(dp), parameter :: r = 31.5e-3_dp, l = 107e-3_dp, w = 4000.0_dp * 2.0_dp * pi / 60.0_dp
  real(dp) :: psi, h, fd, e1, e2, lnc, z0, s0, expected, dl, dvisc, dmax
  real(dp) :: pu(6), pou(6), etau(6), eta_in(6)
  type(roelands_law) :: law
  integer :: i
  character(len=64) :: what

  ! U = dx/dt = w dx/dpsi: central difference error must fall as h^2
  do i = 0, 71
    psi = i * 10.0_dp * pi / 180.0_dp + 0.1_dp
    h = 1e-3_dp
    fd = w * (piston_position(psi + h, r, l) - piston_position(psi - h, r, l)) / (2 * h)
    e1 = abs(fd - sliding_speed(psi, r, l, w))
    h = 0.5e-3_dp
    fd = w * (piston_position(psi + h, r, l) - piston_position(psi - h, r, l)) / (2 * h)
    e2 = abs(fd - sliding_speed(psi, r, l, w))
    write (what, '(a, f7.2)') 'U vs finite difference at psi=', psi * 180 / pi
    call check(e2 <= 1e-6_dp * r * w, trim(what))
    if (e1 > 1e-9_dp * r * w) call check(e1 / e2 > 3.5_dp, trim(what)//' (second order)')
  end do
  call check(abs(sliding_speed(0.0_dp, r, l, w)) == 0.0_dp, 'U(0) = 0')
  call check(sliding_speed(0.5_dp * pi, r, l, w) > 0.0_dp, &
             'U > 0 on the intake stroke (towards crankcase)')
  call check_close(sliding_speed(0.5_dp * pi, r, l, w), r * w, 1e-14_dp, 'U(90 deg) = r w')

  ! Roelands: eta(0, theta0) = eta0; d ln eta/dp at p=0, theta0 = alpha;
  ! d ln eta/dtheta at p=0, theta0 = -beta (the definitions of alpha and beta)
  call check_close(roelands(0.0_dp, 313.15_dp, 0.05_dp, 313.15_dp, 1e-8_dp, 0.04_dp), 0.05_dp, &
                   1e-14_dp, 'eta(0, theta0) = eta0')
  dl = 1e2_dp
  fd = (log(roelands(dl, 313.15_dp, 0.05_dp, 313.15_dp, 1e-8_dp, 0.04_dp)) &
        - log(roelands(0.0_dp, 313.15_dp, 0.05_dp, 313.15_dp, 1e-8_dp, 0.04_dp))) / dl
  call check_close(fd, 1e-8_dp, 1e-5_dp, 'd ln eta / dp = alpha at p = 0')
  dl = 1e-4_dp
  fd = (log(roelands(0.0_dp, 313.15_dp + dl, 0.05_dp, 313.15_dp, 1e-8_dp, 0.04_dp)) &
        - log(roelands(0.0_dp, 313.15_dp - dl, 0.05_dp, 313.15_dp, 1e-8_dp, 0.04_dp))) / (2 * dl)
  call check_close(fd, -0.04_dp, 1e-7_dp, 'd ln eta / dtheta = -beta at theta0')
  ! hand computation at p = 50 MPa, theta = 348 K, written out step by step:
  ! ln eta0 + 9.67 = ln 0.05 + 9.67 = 6.674267...; z0 = 1e-8/(5.1e-9*6.674267) = 0.293785...
  ! s0 = 0.04*175.15/6.674267 = 1.049720...; (1 + 0.255)^z0 = exp(z0 ln 1.255)
  ! ((348-138)/175.15)^-s0 = exp(-s0 ln(210/175.15))
  lnc = log(0.05_dp) + 9.67_dp
  z0 = 1e-8_dp / (5.1e-9_dp * lnc)
  s0 = 0.04_dp * 175.15_dp / lnc
  expected = 0.05_dp * exp(lnc * (exp(z0 * log(1.255_dp) - s0 * log(210.0_dp / 175.15_dp)) &
                                  - 1.0_dp))
  call check_close(roelands(50e6_dp, 348.0_dp, 0.05_dp, 313.15_dp, 1e-8_dp, 0.04_dp), expected, &
                   1e-13_dp, 'Roelands at 50 MPa, 348 K (hand computation)')
  call check_close(expected, 2.29912e-2_dp, 1e-5_dp, 'hand value 0.0229912 Pa s (by calculator)')

  ! the pressure-viscosity step: the law's viscosity, bit for bit, where the pressure changed
  ! (clipped to [0, p_max]: a negative pressure as 0, one above p_max as p_max), the old
  ! viscosity kept where it did not, and the largest relative change
  law = roelands_law_at(348.0_dp, 0.05_dp, 313.15_dp, 1e-8_dp, 0.04_dp)
  pu = [1e5_dp, 2e7_dp, -3e4_dp, 5e6_dp, 2e9_dp, 7e7_dp]
  pou = [1e5_dp, 1e7_dp, 0.0_dp, 5e6_dp, 1e9_dp, 6e7_dp]
  eta_in = [0.01_dp, 0.02_dp, 0.03_dp, 0.04_dp, 0.05_dp, 0.06_dp]
  etau = eta_in
  call roelands_update(law, 6, pu, pou, 1e9_dp, etau, dvisc)
  call check(etau(1) == eta_in(1) .and. etau(4) == eta_in(4), &
             'roelands_update keeps eta where p is unchanged')
  call check(etau(2) == roelands_eta(law, 2e7_dp) .and. etau(6) == roelands_eta(law, 7e7_dp), &
             'roelands_update: the law at the new pressure, bit for bit')
  call check(etau(3) == roelands_eta(law, 0.0_dp) .and. etau(5) == roelands_eta(law, 1e9_dp), &
             'roelands_update clips the pressure to [0, p_max]')
  dmax = 0.0_dp
  do i = 1, 6
    dmax = max(dmax, abs(etau(i) - eta_in(i)) / eta_in(i))
  end do
  call check(dvisc == dmax .and. dvisc > 0.0_dp, 'roelands_update: largest relative change')

  ! the chamber pressure between trace samples: the interval found from a guess (exact for an
  ! even trace) and by bisection must be the one a plain search finds, on an even trace and
  ! on an uneven one (samples crowded near 360 deg), at angles on and between the samples
  call check_trace([(5.0_dp * i, i=0, 143)], 'even trace')
  call check_trace([(360.0_dp + 355.0_dp * sign(abs(i / 72.0_dp)**3, real(i, dp)), &
                     i=-72, 72)], 'uneven trace')
  call report('test_physics_basics')
contains
  subroutine check_trace(tpsi, name)
    real(dp), intent(in) :: tpsi(:)
    character(len=*), intent(in) :: name
    real(dp) :: tp(size(tpsi)), a, expect
    integer :: j, n, worst
    n = size(tpsi)
    tp = [(1e5_dp + 1e4_dp * j + 3e3_dp * sin(0.7_dp * j), j=1, n)]
    worst = 0
    do i = 0, 7199
      a = 0.1_dp * i
      if (i == 7199) a = tpsi(n)
      if (a >= tpsi(1) .and. a < tpsi(n)) then
        j = 1
        do while (tpsi(j + 1) <= a)
          j = j + 1
        end do
        expect = tp(j) + (tp(j + 1) - tp(j)) * (a - tpsi(j)) / (tpsi(j + 1) - tpsi(j))
      else
        ! the wrap-around segment from the last sample to the first one 720 deg on
        if (a < tpsi(1)) a = a + 720.0_dp
        expect = tp(n) + (tp(1) - tp(n)) * (a - tpsi(n)) / (tpsi(1) + 720.0_dp - tpsi(n))
        a = modulo(a, 720.0_dp)
      end if
      if (gas_pressure(tpsi, tp, a, 0.0_dp) /= expect) worst = worst + 1
    end do
    call check(worst == 0, 'gas_pressure on the '//name//' equals a plain search''s interval')
  end subroutine check_trace
end program test_physics_basics
