! ctest labels: unit
!> The oil supply of a starved ring (ringlube_oil_supply) over crank steps with reversals.
!>
!> 1. turn_before_step: taking a reversal's change of the liner before the step
!>    (`supply_turn`, as the cycle does) gives what the step gives without it, bit for bit: the
!>    oil the leading edge may take in and the trailing edge may draw back (`supply_edges`),
!>    and after `supply_step` the liner film (each cell's oil and where it lies), the bank, the
!>    direction and the counters. Without a reversal `supply_turn` changes nothing.
program test_oil_supply
  use ringlube_kinds, only: dp, pi
  use ringlube_oil_supply
  use ringlube_check
  implicit none

  if (run_case('turn_before_step')) call turn_before_step()
  call report('test_oil_supply')

contains

  subroutine turn_before_step()
    type(supply_type) :: sup, a, b
    real(dp) :: s_prev, s, av_a, be_a, av_b, be_b, v_in, v_out
    integer :: k, dir, reversals, same, compared
    logical :: took_down
    call supply_setup(sup, 1e-3_dp, 60e-3_dp, 2e-5_dp, 1.5e-6_dp, 4e-3_dp)
    s_prev = 0.0_dp
    reversals = 0
    same = 0
    compared = 0
    took_down = .false.
    ! two crank cycles of 5 deg steps from TDC: a downstroke, an upstroke, ...
    do k = 1, 144
      s = 30e-3_dp * (1.0_dp - cos(k * 5.0_dp * pi / 180.0_dp))
      dir = 0
      if (s > s_prev) dir = 1
      if (s < s_prev) dir = -1
      ! the step without the turn
      a = sup
      call supply_edges(a, s_prev, s, merge(dir, a%direction, dir /= 0), av_a, be_a)
      ! the oil through the faces: part of what the inlet may take, and alternately a film
      ! left behind or oil drawn back
      v_in = 0.6_dp * av_a
      v_out = 0.4e-6_dp * abs(s - s_prev)
      if (mod(k, 3) == 0) v_out = -0.5_dp * be_a
      call supply_step(a, s_prev, s, dir, v_in, v_out)
      ! the step with the turn taken first
      b = sup
      if (dir /= 0 .and. b%direction /= 0 .and. dir /= b%direction) then
        reversals = reversals + 1
        if (dir < 0) took_down = .true.
      else
        call supply_turn(b, s_prev, dir)
        compared = compared + 1
        if (same_supply(b, sup)) same = same + 1
        b = sup
      end if
      call supply_turn(b, s_prev, dir)
      call supply_edges(b, s_prev, s, merge(dir, b%direction, dir /= 0), av_b, be_b)
      call check(av_b == av_a .and. be_b == be_a, 'the edges read the same oil, step '//itoa(k))
      call supply_step(b, s_prev, s, dir, v_in, v_out)
      call check(same_supply(a, b), 'the same supply after the step, step '//itoa(k))
      sup = b
      s_prev = s
    end do
    call check(reversals == 3, 'three reversals in two cycles')
    call check(took_down, 'an upstroke reversal (the lower rings take the film down)')
    call check(sup%taken_down > 0.0_dp .and. sup%supplied > 0.0_dp, &
               'the lower rings took oil down and laid theirs')
    call check(same == compared .and. compared > 100, 'no reversal: the turn changes nothing')
  end subroutine turn_before_step

  !> Every component of two supplies equal, bit for bit.
  logical function same_supply(x, y)
    type(supply_type), intent(in) :: x, y
    same_supply = x%liner%nz == y%liner%nz .and. x%liner%z0 == y%liner%z0 &
                  .and. x%liner%dz == y%liner%dz
    if (.not. same_supply) return
    same_supply = all(x%liner%h == y%liner%h) .and. all(x%liner%lo == y%liner%lo) &
                  .and. all(x%liner%hi == y%liner%hi) .and. x%bank == y%bank &
                  .and. x%direction == y%direction .and. x%supplied == y%supplied &
                  .and. x%taken_down == y%taken_down .and. x%to_chamber == y%to_chamber &
                  .and. x%overdrawn == y%overdrawn
  end function same_supply

  function itoa(i) result(t)
    integer, intent(in) :: i
    character(len=:), allocatable :: t
    character(len=12) :: buf
    write (buf, '(i0)') i
    t = trim(buf)
  end function itoa
end program test_oil_supply
