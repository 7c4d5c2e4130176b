! ctest labels: unit;numerics
!> The mixed/boundary share (percentage of the cycle with h0/sigma < 4)
!> from lambda at the crank steps, against closed forms: lambda = 3 + 2 cos(psi) is
!> below 4 where cos(psi) < 1/2, two thirds of the cycle; linear interpolation between
!> steps makes the estimate second order in the step (a count of steps is first order).
program test_mixed_share
  use ringlube_kinds, only: dp, pi
  use ringlube_results, only: mixed_share
  use ringlube_check
  implicit none
  real(dp) :: e(3), order
  integer :: lev, m, j

  ! the error depends on where in a step the crossings fall: take the largest over 40
  ! phases of the curve against the grid
  e = 0.0_dp
  do lev = 1, 3
    m = 45 * 2**lev
    do j = 0, 39
      e(lev) = max(e(lev), abs(mixed_share(lam(m, j / 40.0_dp)) - 200.0_dp / 3.0_dp))
    end do
  end do
  write (*, '(a, 3es11.3)') 'largest error of the share [points] at 90, 180, 360 steps:', e
  order = log(e(2) / e(3)) / log(2.0_dp)
  write (*, '(a, f6.2)') 'observed order ', order
  call check(e(1) < 100.0_dp / 90 / 10, 'within a tenth of a step at 90 steps')
  call check(order > 1.8_dp, 'second order in the step')
  call check_close(mixed_share([(5.0_dp, m=1, 10)]), 0.0_dp, 0.0_dp, 'never below 4', 1e-14_dp)
  call check_close(mixed_share([(3.0_dp, m=1, 10)]), 100.0_dp, 1e-14_dp, 'always below 4')
  ! one step from 3 to 5 and back: below 4 for half of each of the two steps
  call check_close(mixed_share([3.0_dp, 5.0_dp]), 50.0_dp, 1e-14_dp, 'crossing at mid-step')
  call report('test_mixed_share')

contains

  !> lambda = 3 + 2 cos(psi) at n steps, shifted by `phase` steps
  function lam(n, phase) result(l)
    integer, intent(in) :: n
    real(dp), intent(in) :: phase
    real(dp) :: l(n)
    integer :: k
    do k = 1, n
      l(k) = 3.0_dp + 2.0_dp * cos(2.0_dp * pi * (k - 1 + phase) / n)
    end do
  end function lam
end program test_mixed_share
