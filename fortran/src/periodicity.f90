!> The periodic state of a run of cycles (docs/model.md, "Cycle and periodic state" and "A
!> period of several cycles"): the ring's state at the start of each of the last cycles, and
!> the smallest number of cycles after which it repeats within `cycle_tol`.
module ringlube_periodicity
  use ringlube_kinds, only: dp
  use ringlube_case, only: case_type
  use ringlube_ring_pack, only: ring_pack_state
  use ringlube_ring_pack_cycle, only: ring_pack_distance
  use ringlube_results, only: sc_flutter_margin, sc_flutter_margin_ratio, sc_peak_groove_pressure, &
                              sc_peak_groove_angle, sc_peak_land_pressure, sc_peak_land_angle
  implicit none
  private
  public :: max_period, cycle_history, history_start, history_h0, history_end, &
            history_period, history_changes, history_mean, history_clean

  !> the longest period a run looks for [cycles]
  integer, parameter :: max_period = 12
  !> cycles kept: a period of p is checked over the last 2 p + 1 cycles
  integer, parameter :: kept = 2 * max_period + 1

  !> The last `kept` cycles: cycle k in slot modulo(k, kept).
  type :: cycle_history
    !> cycles started
    integer :: cycles = 0
    !> h0 at psi = 0 of the cycle (its first crank step) [m]
    real(dp) :: h0(0:kept - 1) = 0.0_dp
    !> the ring pack at the cycle's start (with ring_pack = 'gas')
    type(ring_pack_state) :: rp(0:kept - 1)
    !> the liner film at the cycle's start [m] (starved), (liner point, slot)
    real(dp), allocatable :: map(:, :)
    !> the cycle's energy [J] (set at its end)
    real(dp) :: energy(0:kept - 1) = 0.0_dp
    !> no flag in the cycle but lift-off (set at its end)
    logical :: clean(0:kept - 1) = .false.
    !> the cycle's scalar results (set at its end), (result, slot)
    real(dp), allocatable :: scalars(:, :)
    !> the ring pack's land pressure contraction per cycle (0: not known; set by the caller),
    !> with which its change is judged as a distance (ring_pack_distance)
    real(dp) :: land_contraction = 0.0_dp
  end type cycle_history

contains

  pure integer function slot(k)
    integer, intent(in) :: k
    slot = modulo(k, kept)
  end function slot

  !> A cycle starts from the ring pack's state rp and the liner film map (where the run has
  !> them).
  pure subroutine history_start(hist, rp, map)
    type(cycle_history), intent(inout) :: hist
    type(ring_pack_state), intent(in), optional :: rp
    real(dp), intent(in), optional :: map(:)
    integer :: j
    hist%cycles = hist%cycles + 1
    j = slot(hist%cycles)
    if (present(rp)) hist%rp(j) = rp
    if (present(map)) then
      if (.not. allocated(hist%map)) allocate (hist%map(size(map), 0:kept - 1))
      hist%map(:, j) = map
    end if
  end subroutine history_start

  !> h0 at psi = 0 of the cycle started (its first crank step).
  pure subroutine history_h0(hist, h0)
    type(cycle_history), intent(inout) :: hist
    real(dp), intent(in) :: h0
    hist%h0(slot(hist%cycles)) = h0
  end subroutine history_h0

  !> The cycle just run ends with this energy, flags (clean: none but lift-off) and results.
  pure subroutine history_end(hist, energy, clean, scalars)
    type(cycle_history), intent(inout) :: hist
    real(dp), intent(in) :: energy, scalars(:)
    logical, intent(in) :: clean
    integer :: j
    j = slot(hist%cycles)
    if (.not. allocated(hist%scalars)) allocate (hist%scalars(size(scalars), 0:kept - 1))
    hist%energy(j) = energy
    hist%clean(j) = clean
    hist%scalars(:, j) = scalars
  end subroutine history_end

  !> The smallest period p (cycles) after which the state at the end of the cycle just run
  !> (h0_end, rp_end, map_end) equals the state p cycles before within c%cycle_tol; 0: none.
  !> Without a starved inlet the state is h0 at psi = 0 (and the ring pack's); starved, the
  !> liner film and the cycle's energy (and the ring pack's), or the liner film over p cycles
  !> with energy and ring pack repeating every cycle. The energy of the cycle just run must be
  !> set (history_end). first_change: the first cycle's change of the ring's state, which
  !> stands in for its energy's change (starved). A period of 2 or more compares with the start
  !> of the second cycle at the earliest (the warm-up's end is not a cycle's, and with the ring
  !> pack the first cycle runs before its restart), and never with the first cycle's energy. A
  !> period of 3 or more must repeat as a whole (every state and energy of its last p cycles
  !> equal to those p cycles before), so it is found from cycle 2 p + 1 on.
  pure integer function history_period(hist, c, h0_end, first_change, rp_end, map_end) result(p)
    type(cycle_history), intent(in) :: hist
    type(case_type), intent(in) :: c
    real(dp), intent(in) :: h0_end, first_change
    type(ring_pack_state), intent(in), optional :: rp_end
    real(dp), intent(in), optional :: map_end(:)
    integer :: k, j, q
    real(dp) :: e1, rp1, ep, rpp, mp, tol
    logical :: ok
    k = hist%cycles
    tol = c%cycle_tol
    e1 = first_change
    if (k >= 2) e1 = energy_change(hist, k, 1)
    rp1 = change_rp(1)
    do q = 1, min(max_period, k)
      p = q
      if (q == 2 .and. k < 3) exit
      if (q >= 3 .and. k < 2 * q + 1) exit
      j = slot(k - q + 1)
      rpp = change_rp(q)
      if (present(map_end)) then
        mp = map_change(map_end, hist%map(:, j))
        ep = e1
        ! (not against the first cycle's energy: with the ring pack it ran before the restart)
        if (q >= 2) ep = huge(1.0_dp)
        if (q >= 2 .and. k - q >= 2) ep = energy_change(hist, k, q)
        ok = mp <= tol .and. ((e1 <= tol .and. rp1 <= tol) .or. (ep <= tol .and. rpp <= tol))
      else
        ok = abs(h0_end - hist%h0(j)) / hist%h0(j) <= tol .and. rpp <= tol
      end if
      ! a period of three or more repeats as a whole: every state and energy of its last q
      ! cycles equals the one q cycles before (a wandering state would otherwise meet one of
      ! the 12 before it by chance, and a transient can repeat for a few cycles)
      if (ok .and. q >= 3) ok = repeats_whole(q)
      if (ok) return
    end do
    p = 0

  contains

    !> Every state at the start of cycles k - d + 2 .. k (the ends of cycles k - d + 1 .. k -
    !> 1) equals the one d cycles before, and the energy of every cycle k - d + 1 .. k that of
    !> the cycle d before (the end of cycle k is compared by the caller).
    pure logical function repeats_whole(d)
      integer, intent(in) :: d
      integer :: i, j1, j0
      repeats_whole = .true.
      do i = 0, d - 1
        repeats_whole = repeats_whole .and. energy_change(hist, k - i, d) <= tol
      end do
      do i = 0, d - 2
        j1 = slot(k - i)
        j0 = slot(k - i - d)
        if (present(map_end)) then
          repeats_whole = repeats_whole .and. map_change(hist%map(:, j1), hist%map(:, j0)) <= tol
        else
          repeats_whole = repeats_whole .and. abs(hist%h0(j1) - hist%h0(j0)) <= tol * hist%h0(j0)
        end if
        if (present(rp_end)) repeats_whole = repeats_whole .and. &
                       ring_pack_distance(c, hist%rp(j1), hist%rp(j0), hist%land_contraction) <= tol
      end do
    end function repeats_whole

    pure real(dp) function change_rp(d)
      integer, intent(in) :: d
      change_rp = 0.0_dp
      if (present(rp_end)) change_rp = ring_pack_distance(c, rp_end, hist%rp(slot(k - d + 1)), &
                                                          hist%land_contraction)
    end function change_rp
  end function history_period

  !> The changes of the state that the periodicity test compares with cycle_tol, over the
  !> last p cycles (p: the period found, 1 if none): [h0 at psi = 0 (h0_end against the start
  !> of those cycles), energy (against the cycle p before; the first cycle's: first_change),
  !> liner film (map_end), ring pack (rp_end)], 0 for those the run has not. Starved with a
  !> period of several cycles, the energy's and ring pack's over the last cycle where those
  !> are the smaller (the test accepts either, history_period).
  pure function history_changes(hist, c, h0_end, first_change, p, rp_end, map_end) result(ch)
    type(cycle_history), intent(in) :: hist
    type(case_type), intent(in) :: c
    real(dp), intent(in) :: h0_end, first_change
    integer, intent(in) :: p
    type(ring_pack_state), intent(in), optional :: rp_end
    real(dp), intent(in), optional :: map_end(:)
    real(dp) :: ch(4), e1, rp1
    integer :: k, q, j
    k = hist%cycles
    q = min(max(p, 1), k)
    j = slot(k - q + 1)
    ch = [abs(h0_end - hist%h0(j)) / hist%h0(j), first_change, 0.0_dp, 0.0_dp]
    if (k - q >= 1) ch(2) = energy_change(hist, k, q)
    if (present(map_end)) ch(3) = map_change(map_end, hist%map(:, j))
    if (present(rp_end)) ch(4) = ring_pack_distance(c, rp_end, hist%rp(j), hist%land_contraction)
    ! starved, a period of several liner-film cycles: history_period also accepts energy and
    ! ring pack repeating every cycle; report those changes where they are the ones that passed
    if (present(map_end) .and. q >= 2) then
      ! (history_period never compares with the first cycle's energy: not a change it passed)
      if (k - q < 2) ch(2) = huge(1.0_dp)
      e1 = energy_change(hist, k, 1)
      rp1 = 0.0_dp
      if (present(rp_end)) rp1 = ring_pack_distance(c, rp_end, hist%rp(slot(k)), &
                                                    hist%land_contraction)
      if (max(e1, rp1) < max(ch(2), ch(4))) ch([2, 4]) = [e1, rp1]
    end if
  end function history_changes

  !> The energy of cycle kk against that of cycle kk - d, relative.
  pure real(dp) function energy_change(hist, kk, d)
    type(cycle_history), intent(in) :: hist
    integer, intent(in) :: kk, d
    real(dp) :: e
    e = hist%energy(slot(kk))
    energy_change = abs(e - hist%energy(slot(kk - d))) / max(e, tiny(1.0_dp))
  end function energy_change

  !> The liner film's change from b to a, relative to a (L1).
  pure real(dp) function map_change(a, b)
    real(dp), intent(in) :: a(:), b(:)
    map_change = sum(abs(a - b)) / max(sum(abs(a)), tiny(1.0_dp))
  end function map_change

  !> The means of results idx over the last p cycles (p >= 2; p = 1 leaves v alone), and the
  !> extremes of the ring pack's: the least flutter margin of the cycles (negative if one
  !> flutters, as their mean flutter_events is positive), and the highest groove and land
  !> pressures with their crank angles.
  pure subroutine history_mean(hist, p, idx, v)
    type(cycle_history), intent(in) :: hist
    integer, intent(in) :: p, idx(:)
    real(dp), intent(inout) :: v(:)
    real(dp) :: s(size(idx))
    integer :: i, ks(p)
    if (p < 2) return
    s = hist%scalars(idx, slot(hist%cycles))
    do i = 1, p - 1
      s = s + hist%scalars(idx, slot(hist%cycles - i))
    end do
    v(idx) = s / p
    ks = [(slot(hist%cycles - i), i=0, p - 1)]
    v(sc_flutter_margin) = minval(hist%scalars(sc_flutter_margin, ks))
    v(sc_flutter_margin_ratio) = minval(hist%scalars(sc_flutter_margin_ratio, ks))
    i = ks(maxloc(hist%scalars(sc_peak_groove_pressure, ks), dim=1))
    v([sc_peak_groove_pressure, sc_peak_groove_angle]) = &
      hist%scalars([sc_peak_groove_pressure, sc_peak_groove_angle], i)
    i = ks(maxloc(hist%scalars(sc_peak_land_pressure, ks), dim=1))
    v([sc_peak_land_pressure, sc_peak_land_angle]) = &
      hist%scalars([sc_peak_land_pressure, sc_peak_land_angle], i)
  end subroutine history_mean

  !> No flag but lift-off in any of the last p (>= 1) cycles.
  pure logical function history_clean(hist, p)
    type(cycle_history), intent(in) :: hist
    integer, intent(in) :: p
    integer :: i
    history_clean = all([(hist%clean(slot(hist%cycles - i)), i=0, max(p, 1) - 1)])
  end function history_clean
end module ringlube_periodicity
