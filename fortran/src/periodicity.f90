!> The periodic state of a run of cycles (docs/model.md, "Cycle and periodic state" and "A
!> period of several cycles"): the ring's state at the start of each of the last cycles, and
!> the smallest number of cycles after which it repeats within `cycle_tol`. A period of one is
!> judged on each carried quantity's distance from its periodic state: its change over the
!> cycle divided by 1 - its contraction per cycle, measured as the ratio of its last two
!> changes where the cycle continued the one before (history_measure); a liner film that
!> settles by one mode is extrapolated toward its periodic state (history_extrapolate).
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
            history_measure, history_period, history_changes, history_mean, history_clean, &
            history_extrapolate, last_slot, liner_window_cells, q_h0, q_energy, q_map, q_ring_pack

  !> the longest period a run looks for [cycles]
  integer, parameter :: max_period = 12
  !> cycles kept: a period of p is checked over the last 2 p + 1 cycles
  integer, parameter :: kept = 2 * max_period + 1
  !> the contraction per cycle taken where none is measured (a run's first cycle, the first
  !> after the ring pack's restart or an extrapolated start) for h0 at psi = 0, the energy and
  !> the liner film: 0, the change itself. The warm-up brings the film's own state near its
  !> periodic one (the squeeze term's memory of h0 decays within 100 deg; on the shipped decks
  !> the liner film's first cycles contract by 0.05 or less where their first change is within
  !> cycle_tol); the ring pack is judged directly there (history_measure's rp_direct).
  real(dp), parameter :: rho_unknown = 0.0_dp
  !> the largest contraction a distance is taken with: a quantity whose change does not
  !> shrink passes only when its change is within 1 % of cycle_tol (its noise)
  real(dp), parameter :: rho_largest = 0.99_dp
  !> the largest contraction of the liner film extrapolated from (history_extrapolate): beyond
  !> it the step r / (1 - r) times the last change amplifies the noise of the film's solves
  real(dp), parameter :: rho_extrapolate = 0.95_dp
  !> the least cosine between the liner film's last two changes that it is extrapolated along:
  !> one mode decaying (a front that moves from cell to cell changes other cells each cycle)
  real(dp), parameter :: aligned = 0.9_dp
  !> the liner cells the liner film's change is also measured over with a BDC start where
  !> liner_window is 0 (map_change): 1 mm at the shipped decks' 20 um cells, a fifth of the
  !> strip near BDC in which the film the ring laid leaving BDC settles (the BDC start's first
  !> cycle passed on the whole film's change with that film still settling)
  integer, parameter :: bdc_start_window = 50
  !> the carried quantities' rows in cycle_history%change: h0 at psi = 0, the energy, the
  !> liner film, the ring pack
  integer, parameter :: q_h0 = 1, q_energy = 2, q_map = 3, q_ring_pack = 4

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
    !> with which its change is judged as a distance (ring_pack_distance) where the coupled
    !> cycles have not measured one
    real(dp) :: land_contraction = 0.0_dp
    !> the cycle started where the one before ended (not the first cycle, nor one after the
    !> ring pack's restart or an extrapolated start): its changes measure a contraction
    logical :: continued(0:kept - 1) = .false.
    !> the cycle's changes over it (set by history_period), (q_h0 .. q_ring_pack, slot): h0
    !> at psi = 0 and the energy relative, the liner film (L1), the ring pack
    !> (ring_pack_distance without a contraction)
    real(dp) :: change(4, 0:kept - 1) = 0.0_dp
    !> their signs' carriers (set by history_measure), (q_h0 .. q_ring_pack, slot): h0's and
    !> the energy's changes, the map's inner product with its change over the cycle before,
    !> the land pressure's change
    real(dp) :: sense(4, 0:kept - 1) = 0.0_dp
    !> the distances of the cycle just run from the periodic state, (q_h0 .. q_ring_pack):
    !> what the test of a period of one compares with cycle_tol
    real(dp) :: distance(4) = 0.0_dp
    !> the liner film's contraction per cycle taken for a cycle that starts from an
    !> extrapolated film (history_start's rho_map; the extrapolation's own estimate)
    real(dp) :: prior_map(0:kept - 1) = 0.0_dp
    !> each quantity's contraction last measured (rho_unknown before the first), and the
    !> contractions the cycle just run was judged with (-1 for the ring pack's: not measured)
    real(dp) :: rho_last(4) = rho_unknown, rho(4) = 0.0_dp
    !> the cycle just run can be judged on the quantity (the energy not in the first cycle
    !> after a jump)
    logical :: judged(4) = .true.
  end type cycle_history

contains

  pure integer function slot(k)
    integer, intent(in) :: k
    slot = modulo(k, kept)
  end function slot

  !> The slot of the cycle just run (its column in cycle_history%change).
  pure integer function last_slot(hist)
    type(cycle_history), intent(in) :: hist
    last_slot = slot(hist%cycles)
  end function last_slot

  !> A cycle starts from the ring pack's state rp and the liner film map (where the run has
  !> them); continued: from the end of the cycle before (default: after the first cycle).
  !> rho_map: the cycle starts from a liner film extrapolated with this contraction per cycle
  !> (history_extrapolate), which its change is judged with.
  pure subroutine history_start(hist, rp, map, continued, rho_map)
    type(cycle_history), intent(inout) :: hist
    type(ring_pack_state), intent(in), optional :: rp
    real(dp), intent(in), optional :: map(:)
    logical, intent(in), optional :: continued
    real(dp), intent(in), optional :: rho_map
    integer :: j
    hist%cycles = hist%cycles + 1
    j = slot(hist%cycles)
    hist%continued(j) = hist%cycles > 1
    if (present(continued)) hist%continued(j) = continued .and. hist%cycles > 1
    hist%prior_map(j) = rho_unknown
    if (present(rho_map)) hist%prior_map(j) = rho_map
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

  !> The changes over the cycle just run (from its start to h0_end, rp_end, map_end; the
  !> energy against the cycle before, the first cycle's first_change: the change of the ring's
  !> state, which stands in for it) and each one's distance from its periodic state (stored in
  !> hist%change and hist%distance), for the test of a period of one. A distance is the change
  !> divided by 1 - rho, rho the quantity's contraction per cycle: the ratio of its change to
  !> the one over the cycle before, where this cycle continued that one and that one its own
  !> predecessor or the warm-up (two steps of one trajectory), at most rho_largest; a change of
  !> the other sense (an alternating approach, or an orbit of two cycles within the change)
  !> counts as it is. Where none is measured: the last one measured (rho_unknown before the
  !> first), the liner film after an extrapolation the contraction extrapolated with; the
  !> ring pack its distance measured directly (rp_direct: from the periodic state of the gas
  !> network under the cycle's friction), else with its start's land contraction
  !> (ring_pack_distance). The energy moves at the rate of the film's carried state (the liner
  !> film's, else h0's), and the first cycle after a jump cannot be judged on it (its change
  !> compares cycles run from different states). The energy of the cycle just run must be set
  !> (history_end).
  pure subroutine history_measure(hist, c, h0_end, first_change, rp_end, map_end, rp_direct)
    type(cycle_history), intent(inout) :: hist
    type(case_type), intent(in) :: c
    real(dp), intent(in) :: h0_end, first_change
    type(ring_pack_state), intent(in), optional :: rp_end
    real(dp), intent(in), optional :: map_end(:), rp_direct
    real(dp) :: raw(4), sense(4), rho(4), prev(4)
    logical :: measured(4)
    integer :: k, j, jm, i
    k = hist%cycles
    j = slot(k)
    jm = slot(k - 1)
    raw = 0.0_dp
    sense = 0.0_dp
    raw(q_h0) = abs(h0_end - hist%h0(j)) / hist%h0(j)
    sense(q_h0) = h0_end - hist%h0(j)
    raw(q_energy) = first_change
    if (k >= 2) then
      raw(q_energy) = energy_change(hist, k, 1)
      sense(q_energy) = hist%energy(j) - hist%energy(jm)
    end if
    if (present(map_end)) then
      raw(q_map) = map_change(c, map_end, hist%map(:, j))
      ! (the sign of the map's change against the last one: their inner product)
     if (k >= 2) sense(q_map) = sum((map_end - hist%map(:, j)) * (hist%map(:, j) - hist%map(:, jm)))
    end if
    if (present(rp_end)) then
      raw(q_ring_pack) = ring_pack_distance(c, rp_end, hist%rp(j))
      sense(q_ring_pack) = rp_end%p3 - hist%rp(j)%p3
    end if
    hist%change(:, j) = raw
    hist%sense(:, j) = sense
    prev = hist%change(:, jm)
    ! (two changes of one trajectory: this cycle continued the one before, and that one its
    ! own predecessor or the warm-up; after a jump the first change is a residual, not a step
    ! of the mode)
    measured = hist%continued(j) .and. (k == 2 .or. hist%continued(jm)) .and. prev > 0.0_dp
    ! (where none is measured: the last one measured before the jump, which moved the state
    ! but not its rate; the liner film's after an extrapolation: the one it was made with)
    rho = hist%rho_last
    if (.not. hist%continued(j) .and. hist%cycles > 1 .and. hist%prior_map(j) > 0.0_dp) &
      rho(q_map) = hist%prior_map(j)
    do i = 1, 4
      if (.not. measured(i)) cycle
      rho(i) = min(raw(i) / prev(i), rho_largest)
      ! (the map's inner product holds the sign already)
      if (i /= q_map .and. sense(i) * hist%sense(i, jm) < 0.0_dp) rho(i) = 0.0_dp
      if (i == q_map .and. sense(i) <= 0.0_dp) rho(i) = 0.0_dp
      hist%rho_last(i) = rho(i)
    end do
    ! the energy is no state of its own: it moves with what the cycle carries, at the film's
    ! rate (its own ratio is mostly the load balance's noise once the state settles; the ring
    ! pack is judged, and restarted, against its periodic state)
    if (present(map_end)) then
      rho(q_energy) = rho(q_map)
    else
      rho(q_energy) = rho(q_h0)
    end if
    hist%distance = raw / (1.0_dp - rho)
    ! (after a jump the energy's change compares cycles run from different states: it says
    ! nothing of this one's distance, which only the next cycle's change will show)
    hist%judged(q_energy) = k == 1 .or. hist%continued(j)
    hist%rho = rho
    if (.not. measured(q_ring_pack)) hist%rho(q_ring_pack) = -1.0_dp
    if (present(rp_end) .and. .not. measured(q_ring_pack)) then
      hist%distance(q_ring_pack) = ring_pack_distance(c, rp_end, hist%rp(j), &
                                                      hist%land_contraction)
      if (present(rp_direct)) hist%distance(q_ring_pack) = rp_direct
    end if
  end subroutine history_measure

  !> The smallest period p (cycles) after which the state at the end of the cycle just run
  !> (h0_end, rp_end, map_end) equals the state p cycles before within c%cycle_tol; 0: none.
  !> Without a starved inlet the state is h0 at psi = 0 and the energy (and the ring pack's);
  !> starved, the liner film and the cycle's energy (and the ring pack's), or the liner film
  !> over p cycles with energy and ring pack repeating every cycle. A period of one compares
  !> each quantity's distance from its periodic state (history_measure, called first) with
  !> cycle_tol. A period of 2 or more compares with the start of the second cycle at the
  !> earliest (the warm-up's end is not a cycle's, and with the ring pack the first cycle runs
  !> before its restart), and never with the first cycle's energy; each cycle in it continued
  !> the one before (none started from a restarted ring pack or an extrapolated film: not an
  !> orbit of the cycle's own map); and a state whose every tested
  !> quantity changed by at most cycle_tol over the last cycle drifts, it has no period of
  !> several cycles (a monotone drift changes more over several cycles than over one). A
  !> period of 3 or more must repeat as a whole (every state and energy of its last p cycles
  !> equal to those p cycles before), so it is found from cycle 2 p + 1 on.
  pure integer function history_period(hist, c, h0_end, rp_end, map_end) result(p)
    type(cycle_history), intent(in) :: hist
    type(case_type), intent(in) :: c
    real(dp), intent(in) :: h0_end
    type(ring_pack_state), intent(in), optional :: rp_end
    real(dp), intent(in), optional :: map_end(:)
    integer :: k, j, q, i
    real(dp) :: e1, rp1, ep, rpp, mp, tol
    logical :: ok, drift
    k = hist%cycles
    tol = c%cycle_tol
    ! (a period of one: each quantity's distance from its periodic state)
    e1 = hist%distance(q_energy)
    if (.not. hist%judged(q_energy)) e1 = huge(1.0_dp)
    rp1 = hist%distance(q_ring_pack)
    ! every quantity tested changed by at most cycle_tol over the last cycle: a state that
    ! still drifts (else a period of one), which also repeats after several cycles within
    ! cycle_tol (a monotone drift changes more over several cycles than over one): not a
    ! period of several
    associate (ch => hist%change(:, slot(k)))
      if (present(map_end)) then
        drift = ch(q_map) <= tol
      else
        drift = ch(q_h0) <= tol
      end if
      drift = drift .and. (k < 2 .or. ch(q_energy) <= tol) .and. ch(q_ring_pack) <= tol
    end associate
    do q = 1, min(max_period, k)
      p = q
      if (q >= 2 .and. drift) exit
      ! (an orbit of several cycles is one of the cycle's own map: every cycle in it continued
      ! the one before, none started from an extrapolated or restarted state; its energies are
      ! compared with those of the cycles q before)
      if (q >= 2) then
        if (.not. all([(hist%continued(slot(k - i)), i=0, q - 1)])) cycle
      end if
      if (q == 2 .and. k < 3) exit
      if (q >= 3 .and. k < 2 * q + 1) exit
      j = slot(k - q + 1)
      rpp = change_rp(q)
      if (present(map_end)) then
        mp = map_change(c, map_end, hist%map(:, j), several=q >= 2)
        if (q == 1) mp = hist%distance(q_map)
        ep = e1
        ! (not against the first cycle's energy: with the ring pack it ran before the restart)
        if (q >= 2) ep = huge(1.0_dp)
        if (q >= 2 .and. k - q >= 2) ep = energy_change(hist, k, q)
        ok = mp <= tol .and. ((e1 <= tol .and. rp1 <= tol) .or. (ep <= tol .and. rpp <= tol))
      else if (q == 1) then
        ok = hist%distance(q_h0) <= tol .and. e1 <= tol .and. rp1 <= tol
      else
        ok = abs(h0_end - hist%h0(j)) / hist%h0(j) <= tol .and. rpp <= tol &
             .and. energy_change(hist, k, q) <= tol
      end if
      ! a period of three or more repeats as a whole: every state and energy of its last q
      ! cycles equals the one q cycles before (a wandering state would otherwise meet one of
      ! the 12 before it by chance, and a transient can repeat for a few cycles)
      if (ok .and. q >= 3) ok = repeats_whole(q)
      ! a period of two: the cycle before the last repeats its energy too (the one two before
      ! it, where that is a cycle of the run after the first: a single cycle of another state
      ! between two alike is no orbit; never against the first cycle's energy, which with the
      ! ring pack ran before its restart)
      if (ok .and. q == 2 .and. k - 3 >= 2) ok = energy_change(hist, k - 1, 2) <= tol
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
          repeats_whole = repeats_whole .and. &
                          map_change(c, hist%map(:, j1), hist%map(:, j0), several=.true.) <= tol
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

  !> The liner film at the end of the cycle just run (map_end) extrapolated to its periodic
  !> state along its last change d1, which continued the change d0 of the cycle before: one
  !> mode contracting by rho = d1.d0 / d0.d0 a cycle lies rho / (1 - rho) d1 further on (the
  !> vector form of Aitken's extrapolation). Only for 0 < rho <= rho_extrapolate with d1 and
  !> d0 aligned (cosine at least `aligned`) and an energy that changed less than over the cycle
  !> before (from the third cycle: the first's energy change is not one); the film held at 0
  !> or above. ok: extrapolated.
  pure subroutine history_extrapolate(hist, map_end, map_new, rho, ok)
    type(cycle_history), intent(in) :: hist
    real(dp), intent(in) :: map_end(:)
    real(dp), intent(out) :: map_new(size(map_end)), rho
    logical, intent(out) :: ok
    real(dp) :: d00, d10, d11
    integer :: k, j, jm
    k = hist%cycles
    j = slot(k)
    jm = slot(k - 1)
    ok = .false.
    rho = 0.0_dp
    map_new = map_end
    if (k < 3 .or. .not. hist%continued(j) .or. .not. allocated(hist%map)) return
    ! (the energy settling too: not a cycle in which oil built up elsewhere was picked up)
    if (abs(hist%sense(q_energy, j)) > abs(hist%sense(q_energy, jm))) return
    associate (d1 => map_end - hist%map(:, j), d0 => hist%map(:, j) - hist%map(:, jm))
      d00 = sum(d0 * d0)
      d10 = sum(d1 * d0)
      d11 = sum(d1 * d1)
      if (.not. (d00 > 0.0_dp .and. d11 > 0.0_dp)) return
      rho = d10 / d00
      if (rho <= 0.0_dp .or. rho > rho_extrapolate .or. d10 < aligned * sqrt(d00 * d11)) return
      map_new = max(map_end + rho / (1.0_dp - rho) * d1, 0.0_dp)
    end associate
    ok = .true.
  end subroutine history_extrapolate

  !> The changes of the state that the periodicity test compares with cycle_tol (p: the
  !> period found, 1 if none): [h0 at psi = 0, energy, liner film, ring pack], 0 for those the
  !> run has not. A period of one: their distances from the periodic state (history_measure).
  !> A period of several cycles: their changes over its p cycles (h0_end, map_end and rp_end
  !> against the start of those cycles, the energy against the cycle p before); starved, the
  !> energy's and ring pack's distances over the last cycle where those are the smaller (the
  !> test accepts either, history_period).
  pure function history_changes(hist, c, h0_end, p, rp_end, map_end) result(ch)
    type(cycle_history), intent(in) :: hist
    type(case_type), intent(in) :: c
    real(dp), intent(in) :: h0_end
    integer, intent(in) :: p
    type(ring_pack_state), intent(in), optional :: rp_end
    real(dp), intent(in), optional :: map_end(:)
    real(dp) :: ch(4), e1, rp1
    integer :: k, q, j
    k = hist%cycles
    q = min(max(p, 1), k)
    ch = hist%distance
    if (q == 1) return
    j = slot(k - q + 1)
    ch = [abs(h0_end - hist%h0(j)) / hist%h0(j), energy_change(hist, k, q), 0.0_dp, 0.0_dp]
    if (present(map_end)) ch(3) = map_change(c, map_end, hist%map(:, j), several=.true.)
    if (present(rp_end)) ch(4) = ring_pack_distance(c, rp_end, hist%rp(j), hist%land_contraction)
    ! starved, a period of several liner-film cycles: history_period also accepts energy and
    ! ring pack repeating every cycle; report those where they are the ones that passed
    if (present(map_end)) then
      ! (history_period never compares with the first cycle's energy: not a change it passed)
      if (k - q < 2) ch(2) = huge(1.0_dp)
      e1 = hist%distance(q_energy)
      rp1 = hist%distance(q_ring_pack)
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

  !> The liner film's change from b to a: its L1 norm relative to a's over the whole film,
  !> and with `liner_window` on a round bore the larger of that and the same over any
  !> liner_window consecutive cells, there relative to a's over those cells or to a's mean over
  !> that many cells, whichever is the larger (a dry strip's round-off is no change); where
  !> liner_window is 0 a BDC start (`bdc_start`, a 'vapour' cavity) takes bdc_start_window,
  !> and so does a 'trailing_gas' cavity comparing a period of several cycles (`several`): an
  !> orbit repeats everywhere, and a film near BDC still settling after the ring stopped lifting
  !> off on alternate cycles had repeated over the whole film within cycle_tol (the 4000 r/min
  !> cold deck read in N/m accepted with a period of two 22 % above its periodic energy).
  !> The whole film's norm dilutes a change confined to a strip: the film near BDC, which the
  !> ring gathers and lays again there, settles over a few millimetres (docs/model.md, "Cycle
  !> and periodic state"). Not on a distorted bore (its sectors' liners one after another):
  !> there a sector's film near BDC keeps changing by a few per cent a cycle over a
  !> millimetre, and no run would pass.
  pure real(dp) function map_change(c, a, b, several)
    type(case_type), intent(in) :: c
    real(dp), intent(in) :: a(:), b(:)
    logical, intent(in), optional :: several
    real(dp) :: ca(0:size(a)), cd(0:size(a)), floor_w
    integer :: n, w, i
    n = size(a)
    map_change = sum(abs(a - b)) / max(sum(abs(a)), tiny(1.0_dp))
    w = liner_window_cells(c)
    if (present(several)) then
      if (w == 0 .and. several .and. c%cavity_pressure == 'trailing_gas') w = bdc_start_window
    end if
    if (w <= 0 .or. w >= n .or. c%bore /= 'round') return
    ! (running sums of |a| and |a - b|: each window's sums are differences of two)
    ca(0) = 0.0_dp
    cd(0) = 0.0_dp
    do i = 1, n
      ca(i) = ca(i - 1) + abs(a(i))
      cd(i) = cd(i - 1) + abs(a(i) - b(i))
    end do
    floor_w = max(ca(n) * w / n, tiny(1.0_dp))
    do i = w, n
      map_change = max(map_change, (cd(i) - cd(i - w)) / max(ca(i) - ca(i - w), floor_w))
    end do
  end function map_change

  !> The liner cells over which a period of one judges the liner film's change besides the
  !> whole film (map_change; 0: the whole film alone): `liner_window`, or where that is 0
  !> bdc_start_window with a BDC start and a vapour cavity. (On a distorted bore, or with a
  !> window of the film's cells or more, map_change judges the whole film alone.)
  pure integer function liner_window_cells(c) result(w)
    type(case_type), intent(in) :: c
    w = c%liner_window
    if (w == 0 .and. c%bdc_start .and. c%cavity_pressure == 'vapour') w = bdc_start_window
  end function liner_window_cells

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
