! ctest labels: unit
!> The periodic state of a run of cycles (ringlube_periodicity) on made-up sequences of
!> cycle-end states whose periods are known: the smallest period, found at the first cycle
!> that can show it; no period of two or more against the warm-up's end; the starved test on
!> the liner film and the energy; a change of the liner film confined to a strip; the means
!> over a period and its flags.

program test_periodicity
  use ringlube_kinds, only: dp
  use ringlube_case, only: case_type, default_case
  use ringlube_ring_pack, only: ring_pack_state
  use ringlube_periodicity
  use ringlube_check
  implicit none
  type(case_type) :: c

  c = default_case()
  c%cycle_tol = 1e-3_dp
  c%gas_p = [1e5_dp, 5e6_dp]   ! the ring pack's pressures relative to its peak
  if (run_case('h0_periods')) call test_h0_periods()
  if (run_case('not_against_the_warmup')) call test_not_against_the_warmup()
  if (run_case('one_match_is_not_a_period')) call test_one_match_is_not_a_period()
  if (run_case('longest_period')) call test_longest_period()
  if (run_case('slow_decay')) call test_slow_decay()
  if (run_case('one_odd_cycle')) call test_one_odd_cycle()
  if (run_case('two_after_restart')) call test_two_after_restart()
  if (run_case('ring_pack_state')) call test_ring_pack_state()
  if (run_case('starved_map_and_energy')) call test_starved_map_and_energy()
  if (run_case('means_and_flags')) call test_means_and_flags()
  if (run_case('strip_change')) call test_strip_change()
  if (run_case('strip_settling_in_an_orbit')) call test_strip_settling_in_an_orbit()
  call report('test_periodicity')

contains

  !> h0 at psi = 0 of cycle k (s(k)); cycle k ends with s(k + 1). Runs cycles until a period
  !> is found or kmax; returns the period and the cycle it was found in.
  subroutine run_h0(s, kmax, p, kfound, energy)
    real(dp), intent(in) :: s(:)
    integer, intent(in) :: kmax
    integer, intent(out) :: p, kfound
    !> the cycles' energies (default: all 1 J)
    real(dp), intent(in), optional :: energy(:)
    type(cycle_history) :: hist
    integer :: k
    real(dp) :: e
    p = 0
    kfound = 0
    do k = 1, kmax
      call history_start(hist)
      call history_h0(hist, s(k))
      e = 1.0_dp
      if (present(energy)) e = energy(k)
      call history_end(hist, e, .true., [real(k, dp)])
      call history_measure(hist, c, s(k + 1), 0.0_dp)
      p = history_period(hist, c, s(k + 1))
      kfound = k
      if (p > 0) return
    end do
  end subroutine run_h0

  !> Sequences of period 1 .. 6 from the first cycle: period 1 is found in the first cycle,
  !> 2 in the third (the first whose end can equal the start of the second cycle, two cycles
  !> before), q >= 3 in cycle 2 q + 1 (the whole period must repeat, against cycles from the
  !> second on); never a multiple of the period or a smaller one.
  subroutine test_h0_periods()
    real(dp) :: s(40)
    integer :: q, k, p, kf
    character(len=40) :: what
    do q = 1, 6
      s = [(1e-6_dp * (1.0_dp + 0.1_dp * modulo(k - 1, q)), k=1, 40)]
      call run_h0(s, 30, p, kf)
      write (what, '(a, i0)') 'h0 with period ', q
      call check(p == q, trim(what)//': the period found')
      if (q == 1) then
        call check(kf == 1, trim(what)//': found in the first cycle')
      else if (q == 2) then
        call check(kf == 3, trim(what)//': found in the third cycle')
      else
        call check(kf == 2 * q + 1, trim(what)//': found in cycle 2 q + 1')
      end if
    end do
  end subroutine test_h0_periods

  !> One state meeting an earlier one by chance (h0 at the end of cycle 5 equals h0 at the
  !> start of cycle 3, nothing else repeats) is not a period of 3; nor is h0 repeating every
  !> three cycles while the energy does not; nor two states in a row that repeat once.
  subroutine test_one_match_is_not_a_period()
    real(dp) :: s(12), e(12), s2(16)
    integer :: k, p, kf
    s = 1e-6_dp*[1.0_dp, 1.1_dp, 1.2_dp, 1.3_dp, 1.4_dp, 1.2_dp, 1.5_dp, 1.6_dp, 1.7_dp, &
                 1.8_dp, 1.9_dp, 2.0_dp]
    call run_h0(s, 10, p, kf)
    call check(p == 0, 'a single chance match at a lag of 3 is not a period')
    s = [(1e-6_dp * (1.0_dp + 0.1_dp * modulo(k - 1, 3)), k=1, 12)]
    e = [(1.0_dp + 0.01_dp * k, k=1, 12)]
    call run_h0(s, 10, p, kf, e)
    call check(p == 0, 'h0 with period 3, the energy rising: not periodic')
    ! two states in a row repeat after 4 cycles (h0 at the starts of cycles 11 and 12 equals
    ! that of 7 and 8), the two before them do not: a transient, not a period of 4
    s2 = 1e-6_dp*[20.0_dp, 21.0_dp, 22.0_dp, 23.0_dp, 1.0_dp, 2.0_dp, 3.0_dp, 4.0_dp, 9.0_dp, &
                  10.0_dp, 3.0_dp, 4.0_dp, 11.0_dp, 12.0_dp, 13.0_dp, 14.0_dp]
    call run_h0(s2, 15, p, kf)
    call check(p == 0, 'a stretch of two repeating states is not a period of 4')
  end subroutine test_one_match_is_not_a_period

  !> a, b, a, b: cycle 2 ends with the warm-up's end state (a), which is not a cycle's end,
  !> so period 2 is found only in cycle 3
  subroutine test_not_against_the_warmup()
    real(dp) :: s(10)
    integer :: p, kf
    s = [1.0_dp, 2.0_dp, 1.0_dp, 2.0_dp, 1.0_dp, 2.0_dp, 1.0_dp, 2.0_dp, 1.0_dp, 2.0_dp] * 1e-6_dp
    call run_h0(s, 2, p, kf)
    call check(p == 0, 'a period of two is not found against the warm-up (cycle 2)')
    call run_h0(s, 8, p, kf)
    call check(p == 2 .and. kf == 3, 'a period of two is found in cycle 3')
  end subroutine test_not_against_the_warmup

  !> max_period is the longest period looked for: one more is not periodic
  subroutine test_longest_period()
    real(dp) :: s(80)
    integer :: k, p, kf
    s = [(1e-6_dp * (1.0_dp + 0.1_dp * modulo(k - 1, max_period)), k=1, 80)]
    call run_h0(s, 60, p, kf)
    call check(p == max_period, 'period max_period is found')
    s = [(1e-6_dp * (1.0_dp + 0.1_dp * modulo(k - 1, max_period + 1)), k=1, 80)]
    call run_h0(s, 60, p, kf)
    call check(p == 0, 'period max_period + 1 is not')
  end subroutine test_longest_period

  !> h0 decaying like rho**k to its limit, rho = 0.5, 0.9, 0.97: period 1, and the state
  !> accepted lies within cycle_tol of the limit (its change over the cycle is (1 - rho) times
  !> its distance: a slow decay changes little in a cycle far from its limit, and taking the
  !> change for the distance accepted it 9 times cycle_tol away at rho = 0.9, 32 times at
  !> 0.97); not in a cycle before the first whose distance is within cycle_tol
  subroutine test_slow_decay()
    real(dp), parameter :: rhos(3) = [0.5_dp, 0.9_dp, 0.97_dp]
    real(dp) :: s(400), rho
    integer :: k, p, kf, i
    character(len=60) :: what
    do i = 1, size(rhos)
      rho = rhos(i)
      s = [(1e-6_dp * (1.0_dp + rho**k), k=1, 400)]
      call run_h0(s, 390, p, kf)
      write (what, '(a, f4.2)') 'h0 decaying by ', rho
      call check(p == 1, trim(what)//': period 1')
      call check(abs(s(kf + 1) - 1e-6_dp) / 1e-6_dp <= c%cycle_tol, &
                 trim(what)//': the state accepted lies within cycle_tol of the limit')
      call check(rho**(kf - 1) > c%cycle_tol, &
                 trim(what)//': not accepted a cycle later than needed')
    end do
  end subroutine test_slow_decay

  !> h0 settled and one cycle's energy 20 % off between cycles alike (a single excursion to
  !> another state): cycle 5's energy equals cycle 3's, but cycle 4's is not cycle 2's, so no
  !> period of two (it was taken, with the mean of 4 and 5); the next cycle alike is a period
  !> of one
  subroutine test_one_odd_cycle()
    real(dp) :: s(10), e(10)
    integer :: p, kf
    ! (h0 settles by cycle 4, then stays)
    s = 1e-6_dp*[1.0_dp, 1.1_dp, 1.2_dp, 1.3_dp, 1.3_dp, 1.3_dp, 1.3_dp, 1.3_dp, 1.3_dp, 1.3_dp]
    e = [1.0_dp, 1.0_dp, 1.0_dp, 1.2_dp, 1.0_dp, 1.0_dp, 1.0_dp, 1.0_dp, 1.0_dp, 1.0_dp]
    call run_h0(s, 9, p, kf, e)
    call check(p == 1 .and. kf == 6, 'one odd cycle between cycles alike: no period of two')
  end subroutine test_one_odd_cycle

  !> starved, with the ring pack restarted after the first cycle (its energy another one): the
  !> liner film settles into a period of two from cycle 3 on, every energy after the first the
  !> same; the period is found in cycle 4 (its film equals cycle 2's end), not refused on the
  !> first cycle's energy, which the second-to-last cycle's is compared with only from cycle 5
  subroutine test_two_after_restart()
    type(cycle_history) :: hist
    real(dp) :: maps(3, 8), e
    integer :: k, p
    maps(:, 1) = 1e-6_dp*[1.0_dp, 1.0_dp, 1.0_dp]
    maps(:, 2) = 1e-6_dp*[1.5_dp, 1.0_dp, 1.0_dp]
    do k = 3, 8
      maps(:, k) = 1e-6_dp*[2.0_dp, 1.0_dp + modulo(k - 1, 2), 1.0_dp]
    end do
    do k = 1, 7
      call history_start(hist, map=maps(:, k), continued=k /= 2)
      call history_h0(hist, 1e-6_dp)
      e = 2.0_dp
      if (k == 1) e = 1.8_dp
      call history_end(hist, e, .true., [e])
      call history_measure(hist, c, 1e-6_dp, 1.0_dp, map_end=maps(:, k + 1))
      p = history_period(hist, c, 1e-6_dp, map_end=maps(:, k + 1))
      if (p > 0) exit
    end do
    call check(p == 2 .and. k == 4, 'starved period of two after a restart: found in cycle 4')
  end subroutine test_two_after_restart

  !> the ring pack repeats too: h0 constant, the land pressure with period 3
  subroutine test_ring_pack_state()
    type(cycle_history) :: hist
    type(ring_pack_state) :: st(12)
    integer :: k, p
    do k = 1, 12
      st(k)%p2 = 1e5_dp
      st(k)%p3 = 1e5_dp * (1.0_dp + 0.5_dp * modulo(k - 1, 3))
    end do
    do k = 1, 10
      call history_start(hist, rp=st(k))
      call history_h0(hist, 1e-6_dp)
      call history_end(hist, 1.0_dp, .true., [1.0_dp])
      call history_measure(hist, c, 1e-6_dp, 0.0_dp, rp_end=st(k + 1))
      p = history_period(hist, c, 1e-6_dp, rp_end=st(k + 1))
      if (p > 0) exit
    end do
    call check(p == 3 .and. k == 7, 'h0 periodic, the land pressure with period 3: period 3')
  end subroutine test_ring_pack_state

  !> starved, a change of the liner film confined to a strip (the film near BDC settling): 50
  !> of 2000 cells at 1 um change by 1 % over the first cycle, 2.5e-4 of the whole film (L1),
  !> within cycle_tol 1e-3. Judged on the whole film (liner_window 0 without the BDC start) the
  !> cycle passes; with liner_window 50 on a round bore the change over those cells (0.01 / 1.01
  !> of their film) is what the test sees: no period (so with bdc_start, the default, and
  !> liner_window 0); on
  !> a distorted bore (its sectors' films one after another) the whole film's. A dry strip
  !> whose film changes by round-off is measured against the mean film over as many cells,
  !> not against its own: period 1.
  subroutine test_strip_change()
    type(case_type) :: cp, cw, cd, cb
    real(dp) :: m0(2000), m1(2000), ch(4)
    integer :: p
    m0 = 1e-6_dp
    m1 = m0
    m1(1901:1950) = 1.01e-6_dp
    cp = c
    cp%bdc_start = .false.
    cw = cp
    cw%liner_window = 50
    cd = cw
    cd%bore = 'distorted'
    call first_cycle(cp, m0, m1, p, ch)
    call check(p == 1, 'strip change on the whole film (liner_window 0, no BDC start): period 1')
    call check(abs(ch(q_map) - 50 * 0.01_dp / (1950 + 50 * 1.01_dp)) <= 1e-12_dp, &
               "strip change on the whole film: the whole film's change reported")
    call first_cycle(cw, m0, m1, p, ch)
    call check(p == 0, 'strip change, liner_window 50 on a round bore: no period')
    call check(abs(ch(q_map) - 0.01_dp / 1.01_dp) <= 1e-12_dp, &
               "strip change, liner_window 50 on a round bore: the strip's own change reported")
    cb = c
    cb%bdc_start = .true.
    call first_cycle(cb, m0, m1, p, ch)
    call check(p == 0, 'strip change, bdc_start with liner_window 0: over 50 cells, no period')
    call first_cycle(cd, m0, m1, p, ch)
    call check(p == 1, 'strip change, liner_window 50 on a distorted bore: period 1')
    call check(abs(ch(q_map) - 50 * 0.01_dp / (1950 + 50 * 1.01_dp)) <= 1e-12_dp, &
               "strip change, liner_window 50 on a distorted bore: the whole film's change")
    ! (a dry strip: round-off on nothing)
    m0(1901:1950) = 0.0_dp
    m1 = m0
    m1(1901:1950) = 1e-18_dp
    call first_cycle(cw, m0, m1, p, ch)
    call check(p == 1, 'a dry strip changed by round-off, liner_window 50: period 1')

  end subroutine test_strip_change

  !> starved: half the liner film and the energy alternate between two states (a ring lifting
  !> off on alternate cycles) while a strip of 50 of 2000 cells (the film near BDC) grows by 1 %
  !> a cycle: over two cycles 5e-4 of the whole film (L1), within cycle_tol 1e-3. Judged on the
  !> whole film (a vapour cavity without the BDC start) that is a period of two, found in cycle
  !> 4; a 'trailing_gas' cavity compares a period of several cycles over any 50 cells as well
  !> (its strip changed by 2 %): none in 8 cycles, nor with the BDC start (the default).
  subroutine test_strip_settling_in_an_orbit()
    type(case_type) :: cp, ct
    real(dp) :: maps(2000, 9), energy(8)
    integer :: k, p
    do k = 1, 9
      maps(:, k) = 1e-6_dp
      maps(1:1000, k) = 1e-6_dp * (1.0_dp + 0.1_dp * modulo(k, 2))
      maps(1901:1950, k) = 1e-6_dp * 1.01_dp**k
    end do
    energy = [(1.2_dp + 0.6_dp * modulo(k, 2), k=1, 8)]
    cp = c
    cp%bdc_start = .false.
    ct = cp
    ct%cavity_pressure = 'trailing_gas'
    call orbit(cp, maps, energy, p, k)
    call check(p == 2 .and. k == 4, 'strip settling in an orbit, whole film: period 2 in cycle 4')
    call orbit(ct, maps, energy, p, k)
    call check(p == 0, "strip settling in an orbit, 'trailing_gas': no period in 8 cycles")
    call orbit(c, maps, energy, p, k)
    call check(p == 0, 'strip settling in an orbit, BDC start: no period in 8 cycles')
  end subroutine test_strip_settling_in_an_orbit

  !> Starved cycles k = 1, 2, ... from the liner film maps(:, k) to maps(:, k + 1) with energy
  !> energy(k), judged with case cc until a period is found: the period (0: none) and the
  !> cycle it was found in.
  subroutine orbit(cc, maps, energy, p, kfound)
    type(case_type), intent(in) :: cc
    real(dp), intent(in) :: maps(:, :), energy(:)
    integer, intent(out) :: p, kfound
    type(cycle_history) :: hist
    integer :: j
    p = 0
    kfound = 0
    do j = 1, size(energy)
      kfound = j
      call history_start(hist, map=maps(:, j))
      call history_h0(hist, 1e-6_dp)
      call history_end(hist, energy(j), .true., [energy(j)])
      call history_measure(hist, cc, 1e-6_dp, 1.0_dp, map_end=maps(:, j + 1))
      p = history_period(hist, cc, 1e-6_dp, map_end=maps(:, j + 1))
      if (p > 0) return
    end do
  end subroutine orbit

  !> One starved cycle from the liner film m0 to m1 judged with case cc: its period and changes.
  subroutine first_cycle(cc, m0, m1, p, ch)
    type(case_type), intent(in) :: cc
    real(dp), intent(in) :: m0(:), m1(:)
    integer, intent(out) :: p
    real(dp), intent(out) :: ch(4)
    type(cycle_history) :: hist
    call history_start(hist, map=m0)
    call history_h0(hist, 1e-6_dp)
    call history_end(hist, 2.0_dp, .true., [2.0_dp])
    call history_measure(hist, cc, 1e-6_dp, 0.0_dp, map_end=m1)
    p = history_period(hist, cc, 1e-6_dp, map_end=m1)
    ch = history_changes(hist, cc, 1e-6_dp, 1, map_end=m1)
  end subroutine first_cycle

  !> starved: the liner film (map) and the energy. The map with period 3 and the energy
  !> repeating every cycle: period 3; the energy with period 2 and the map every cycle:
  !> period 2; the first cycle, without an energy before it, takes first_change instead.
  subroutine test_starved_map_and_energy()
    real(dp) :: maps(4, 12), energy(12)
    integer :: k, p
    do k = 1, 12
      maps(:, k) = 1e-6_dp*[1.0_dp, 2.0_dp, 3.0_dp, 1.0_dp + modulo(k - 1, 3)]
    end do
    energy = 2.0_dp
    p = run_starved(maps, energy, 0.0_dp, k)
    call check(p == 3 .and. k == 7, 'starved: map period 3, energy constant: period 3')
    maps = spread(maps(:, 1), 2, 12)
    energy = [(2.0_dp + modulo(k - 1, 2), k=1, 12)]
    p = run_starved(maps, energy, 1.0_dp, k)
    call check(p == 2 .and. k == 4, &
               'starved: map constant, energy period 2: period 2, not against the first cycle')
    energy = 2.0_dp
    p = run_starved(maps, energy, 0.0_dp, k)
    call check(p == 1 .and. k == 1, 'starved: all constant: period 1 in the first cycle')
    p = run_starved(maps, energy, 1.0_dp, k)
    call check(p == 1 .and. k == 2, &
               'starved: a first cycle whose ring state changed: period 1 in the second')
  end subroutine test_starved_map_and_energy

  integer function run_starved(maps, energy, first_change, kfound) result(p)
    real(dp), intent(in) :: maps(:, :), energy(:), first_change
    integer, intent(out) :: kfound
    type(cycle_history) :: hist
    integer :: k
    p = 0
    do k = 1, size(energy) - 1
      kfound = k
      call history_start(hist, map=maps(:, k))
      call history_h0(hist, 1e-6_dp)
      call history_end(hist, energy(k), .true., [energy(k)])
      call history_measure(hist, c, 1e-6_dp, first_change, map_end=maps(:, k + 1))
      p = history_period(hist, c, 1e-6_dp, map_end=maps(:, k + 1))
      if (p > 0) return
    end do
  end function run_starved

  !> history_mean averages the chosen results over the last p cycles and leaves the others;
  !> history_clean is false if any of them had a flag
  subroutine test_means_and_flags()
    type(cycle_history) :: hist
    real(dp) :: v(3)
    integer :: k
    do k = 1, 20
      call history_start(hist)
      call history_h0(hist, 1e-6_dp)
      call history_end(hist, 1.0_dp, k /= 16, [real(k, dp), 10.0_dp * k, -1.0_dp * k])
    end do
    v = [20.0_dp, 200.0_dp, -20.0_dp]
    call history_mean(hist, 4, [1, 3], v)
    call check_close(v(1), 18.5_dp, 1e-15_dp, 'mean of cycles 17-20')
    call check_close(v(3), -18.5_dp, 1e-15_dp, 'mean of cycles 17-20, third result')
    call check(v(2) == 200.0_dp, 'a result not asked for is left alone')
    v = [20.0_dp, 200.0_dp, -20.0_dp]
    call history_mean(hist, 1, [1, 2, 3], v)
    call check(all(v == [20.0_dp, 200.0_dp, -20.0_dp]), 'period 1 leaves the results alone')
    call check(history_clean(hist, 4), 'cycles 17-20 have no flag')
    call check(.not. history_clean(hist, 5), 'cycle 16 has one')
    call check(history_clean(hist, 1), 'the last cycle has none')
  end subroutine test_means_and_flags
end program test_periodicity
