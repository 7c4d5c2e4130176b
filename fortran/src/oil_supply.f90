!> Oil supply of a starved ring: the liner film ahead of the leading
!> edge, the bank pushed ahead of it, the film left behind the trailing edge, the supply
!> film laid by the lower rings, and the oil carried past the top of the ring's travel.
!>
!> Positions z on the liner are measured from the top ring's position at TDC, positive
!> towards the crankcase; a face node x lies at z = s + x, s the piston's distance from TDC.
!> Every exchange is a volume per unit circumference (m^2) over the strip of liner an edge
!> sweeps in a crank step, so the balance of liner, bank and gap closes to round-off; the
!> rates of the model (theta_in = min(1, 2 h_oil / h_le), h_oil = |q_te| / |U|) are the limits
!> of these transfers for small steps.
module ringlube_oil_supply
  use ringlube_kinds, only: dp
  use ringlube_liner, only: liner_type, liner_init, strip_volume, strip_take, strip_put, &
                            strip_set, strip_draw, liner_volume
  implicit none
  private
  public :: supply_balance_error
  public :: supply_type, supply_setup, supply_edges, inlet_fill, supply_step, supply_turn, &
            supply_reset_counters, supply_stored, supply_to_chamber

  !> State and counters of the oil supply (volumes per unit circumference, m^2).
  type :: supply_type
    type(liner_type) :: liner
    real(dp) :: half_width = 0.0_dp       !< m, b/2
    real(dp) :: supply_film = 0.0_dp      !< m, film laid by the lower rings
    real(dp) :: lower_limit = 0.0_dp      !< m, z from which the lower rings reach
    real(dp) :: bank = 0.0_dp             !< oil pushed ahead of the leading edge
    integer :: direction = 0              !< sign of the sliding speed of the last moving step
    ! counters since the last reset
    real(dp) :: supplied = 0.0_dp         !< laid by the lower rings
    real(dp) :: taken_down = 0.0_dp       !< downstroke film taken down by the lower rings
    real(dp) :: to_chamber = 0.0_dp       !< carried above the top of the ring's travel
    real(dp) :: overdrawn = 0.0_dp        !< drawn through the inlet beyond the oil there
  end type supply_type

contains

  !> The liner grid over the swept length plus a margin, every cell at the supply film.
  pure subroutine supply_setup(sup, width, stroke, dx, supply_film, lower_ring_distance)
    type(supply_type), intent(out) :: sup
    real(dp), intent(in) :: width, stroke, dx, supply_film, lower_ring_distance
    real(dp) :: dz
    sup%half_width = 0.5_dp * width
    sup%supply_film = supply_film
    sup%lower_limit = -0.5_dp * width + lower_ring_distance
    ! cells no longer than the face node spacing, at most 20,000 of them
    dz = max(dx, (stroke + 2.0_dp * width) / 20000.0_dp)
  call liner_init(sup%liner, -0.5_dp * width - 4.0_dp * dz, stroke + 0.5_dp * width + 4.0_dp * dz, &
                    dz, supply_film)
  end subroutine supply_setup

  !> The leading edge's position for piston position s and sliding direction dir.
  pure real(dp) function leading_edge(sup, s, dir)
    type(supply_type), intent(in) :: sup
    real(dp), intent(in) :: s
    integer, intent(in) :: dir
    leading_edge = s + sign(sup%half_width, real(dir, dp))
  end function leading_edge

  !> Oil available to the inlet in a step from s_prev to s (bank plus the liner strip the
  !> leading edge sweeps) [m^2].
  pure real(dp) function inlet_available(sup, s_prev, s, dir) result(v)
    type(supply_type), intent(in) :: sup
    real(dp), intent(in) :: s_prev, s
    integer, intent(in) :: dir
    ! at a reversal the bank stays behind on the liner: it is not ahead of the new inlet
    v = sup%bank
    if (dir /= 0 .and. sup%direction /= 0 .and. dir /= sup%direction) v = 0.0_dp
    if (dir /= 0) v = v + strip_volume(sup%liner, leading_edge(sup, s_prev, dir), &
                                       leading_edge(sup, s, dir))
  end function inlet_available

  !> Oil the trailing edge may draw back into the gap in a step from s_prev to s [m^2]: the
  !> liner film on the strip just behind its position at the start of the step, as long as
  !> the distance moved (the film it left there; at a reversal, the bank left by the old
  !> leading edge). Its rate limit is |U| h_oil, as the leading edge's.
  pure real(dp) function trailing_available(sup, s_prev, s, dir) result(v)
    type(supply_type), intent(in) :: sup
    real(dp), intent(in) :: s_prev, s
    integer, intent(in) :: dir
    real(dp) :: te
    v = 0.0_dp
    if (dir == 0) return
    te = leading_edge(sup, s_prev, -dir)
    v = strip_volume(sup%liner, te, te - dir * abs(s - s_prev))
  end function trailing_available

  !> Fill of the oil the leading edge admits: min(1, 2 V / (h_le |ds|)), V the oil
  !> available over the step, h_le the gap at the leading face, |ds| the distance moved
  !> (at a dead centre: 1 if there is any oil, else 0).
  pure real(dp) function inlet_fill(available, h_le, ds) result(theta)
    real(dp), intent(in) :: available, h_le, ds
    if (abs(ds) * h_le > 0.0_dp) then
      theta = min(1.0_dp, max(0.0_dp, 2.0_dp * available / (h_le * abs(ds))))
    else if (available > 0.0_dp) then
      theta = 1.0_dp
    else
      theta = 0.0_dp
    end if
  end function inlet_fill

  !> The oil the leading edge may take in (`inlet_available`) and the trailing edge may draw
  !> back (`trailing_available`) in a step from s_prev to s in direction dir. A reversal
  !> changes the liner first (the bank left on it, the lower rings' film: supply_reverse, as
  !> supply_step does), so at a reversal both are taken from the changed liner.
  pure subroutine supply_edges(sup, s_prev, s, dir, available, behind)
    type(supply_type), intent(in) :: sup
    real(dp), intent(in) :: s_prev, s
    integer, intent(in) :: dir
    real(dp), intent(out) :: available, behind
    type(supply_type) :: rev
    if (supply_reverses(sup, dir)) then
      rev = sup
      call supply_reverse(rev, s_prev, dir)
      available = inlet_available(rev, s_prev, s, dir)
      behind = trailing_available(rev, s_prev, s, dir)
    else
      available = inlet_available(sup, s_prev, s, dir)
      behind = trailing_available(sup, s_prev, s, dir)
    end if
  end subroutine supply_edges

  !> Does a step in direction dir reverse the sliding direction of the last one?
  pure logical function supply_reverses(sup, dir)
    type(supply_type), intent(in) :: sup
    integer, intent(in) :: dir
    supply_reverses = dir /= 0 .and. sup%direction /= 0 .and. dir /= sup%direction
  end function supply_reverses

  !> The liner at a reversal of the sliding direction (a step from s_prev in direction dir
  !> that reverses the last one; nothing otherwise): the bank stays on the liner just beyond
  !> the old leading edge, and at the start of an upstroke the lower rings replace the
  !> downstroke film where they reach. The direction itself is left to supply_step.
  pure subroutine supply_reverse(sup, s_prev, dir)
    type(supply_type), intent(inout) :: sup
    real(dp), intent(in) :: s_prev
    integer, intent(in) :: dir
    real(dp) :: put, zl, zend, removed, added, edge
    if (.not. supply_reverses(sup, dir)) return
    ! reversal: the bank stays on the liner just beyond the old leading edge
    edge = leading_edge(sup, s_prev, sup%direction)
    call strip_put(sup%liner, edge, edge + sign(sup%liner%dz, real(sup%direction, dp)), &
                   sup%bank, put)
    sup%overdrawn = sup%overdrawn + (sup%bank - put)   ! off the grid: cannot happen
    sup%bank = 0.0_dp
    if (dir < 0) then
      ! start of an upstroke: where the lower rings reach (z >= lower_limit) they took the
      ! downstroke film down and laid theirs (not under the face, which holds the gap)
      zl = s_prev - sup%half_width
      if (zl > sup%lower_limit) then
        call strip_set(sup%liner, sup%lower_limit, zl, sup%supply_film, removed, added)
        sup%taken_down = sup%taken_down + removed
        sup%supplied = sup%supplied + added
      end if
      ! below the face to the end of the grid; nothing where the lower rings start beyond it
      ! (lower_ring_distance past the stroke: strip_set would put the film of the strip
      ! beyond the grid on its last cell)
      zl = max(sup%lower_limit, s_prev + sup%half_width)
      zend = sup%liner%z0 + sup%liner%nz * sup%liner%dz
      if (zl < zend) then
        call strip_set(sup%liner, zl, zend, sup%supply_film, removed, added)
        sup%taken_down = sup%taken_down + removed
        sup%supplied = sup%supplied + added
      end if
    end if
  end subroutine supply_reverse

  !> The liner's change at a reversal (supply_reverse) of a step from s_prev in direction dir,
  !> taken before the step: the direction becomes dir, so that supply_edges reads the changed
  !> liner itself instead of a copy and supply_step finds nothing left to reverse. Nothing
  !> without a reversal.
  pure subroutine supply_turn(sup, s_prev, dir)
    type(supply_type), intent(inout) :: sup
    real(dp), intent(in) :: s_prev
    integer, intent(in) :: dir
    if (.not. supply_reverses(sup, dir)) return
    call supply_reverse(sup, s_prev, dir)
    sup%direction = dir
  end subroutine supply_turn

  !> The exchanges of one crank step from s_prev to s with sliding direction dir (sign of U;
  !> 0 at a dead centre): `v_in` oil entered the gap through the leading edge (negative:
  !> pushed out ahead), `v_out` oil left it through the trailing edge (negative: drawn back from
  !> the liner behind it, `trailing_available`). At a reversal the
  !> bank stays on the liner ahead of the old leading edge; at the start of an upstroke the
  !> lower rings replace the downstroke film where they reach.
  pure subroutine supply_step(sup, s_prev, s, dir, v_in, v_out)
    type(supply_type), intent(inout) :: sup
    real(dp), intent(in) :: s_prev, s, v_in, v_out
    integer, intent(in) :: dir
    real(dp) :: swept, put, edge
    call supply_reverse(sup, s_prev, dir)
    if (dir /= 0) sup%direction = dir
    if (sup%direction == 0) return
    ! the leading edge's strip: its oil entered the gap or joined the bank
    call strip_take(sup%liner, leading_edge(sup, s_prev, sup%direction), &
                    leading_edge(sup, s, sup%direction), swept)
    sup%bank = sup%bank + swept - v_in
    if (sup%bank < 0.0_dp) then
      sup%overdrawn = sup%overdrawn - sup%bank
      sup%bank = 0.0_dp
    end if
    ! the trailing edge's strip: the film that left the gap, or the oil drawn back into it
    ! from the strip behind the trailing edge
    if (v_out > 0.0_dp) then
      call strip_put(sup%liner, leading_edge(sup, s_prev, -sup%direction), &
                     leading_edge(sup, s, -sup%direction), v_out, put)
      sup%overdrawn = sup%overdrawn + (v_out - put)
    else if (v_out < 0.0_dp) then
      edge = leading_edge(sup, s_prev, -sup%direction)
      call strip_draw(sup%liner, edge, edge - sup%direction * abs(s - s_prev), -v_out, put)
      sup%overdrawn = sup%overdrawn + (-v_out - put)
    end if
  end subroutine supply_step

  !> Oil carried above the top of the ring's travel (z < -b/2) leaves the liner towards the
  !> chamber: counted and removed.
  pure subroutine supply_to_chamber(sup)
    type(supply_type), intent(inout) :: sup
    real(dp) :: v
    call strip_take(sup%liner, sup%liner%z0, -sup%half_width, v)
    sup%to_chamber = sup%to_chamber + v
  end subroutine supply_to_chamber

  !> Oil held on the liner and in the bank [m^2].
  pure real(dp) function supply_stored(sup)
    type(supply_type), intent(in) :: sup
    supply_stored = liner_volume(sup%liner) + sup%bank
  end function supply_stored

  !> Relative closure of the oil balance over a cycle: oil in (the supply film laid) = oil out
  !> (to the chamber, taken down by the lower rings) + change of the oil stored (liner, bank
  !> and the gap's `gap_end`, from `stored_start` at the cycle's start). Oil drawn beyond what
  !> was there shows up as an error.
  pure real(dp) function supply_balance_error(sup, stored_start, gap_end) result(e)
    type(supply_type), intent(in) :: sup
    real(dp), intent(in) :: stored_start, gap_end
    real(dp) :: stored1, scale
    stored1 = supply_stored(sup) + gap_end
    scale = max(sup%supplied, sup%taken_down + sup%to_chamber, abs(stored1 - stored_start), &
                1e-3_dp * stored_start, tiny(1.0_dp))
    e = abs((stored1 - stored_start) - (sup%supplied - sup%to_chamber - sup%taken_down)) / scale
  end function supply_balance_error

  !> Zero the counters (start of a cycle).
  pure subroutine supply_reset_counters(sup)
    type(supply_type), intent(inout) :: sup
    sup%supplied = 0.0_dp
    sup%taken_down = 0.0_dp
    sup%to_chamber = 0.0_dp
    sup%overdrawn = 0.0_dp
  end subroutine supply_reset_counters
end module ringlube_oil_supply
