! ctest labels: unit
!> The liner film's strip operations conserve oil to round-off and put it where asked.
program test_liner
  use ringlube_kinds, only: dp
  use ringlube_liner
  use ringlube_check
  implicit none
  type(liner_type) :: lin, other
  real(dp) :: v0, v, put, removed, added, total
  integer :: k
  real(dp) :: za, zb

  call liner_init(lin, -1e-3_dp, 64e-3_dp, 1e-4_dp, 2e-6_dp)
  call check(lin%nz == 650, 'grid: 650 cells of 0.1 mm')
  call check_close(liner_volume(lin), 2e-6_dp * 65e-3_dp, 1e-12_dp, 'initial volume')
  ! a strip with partial cells at both ends
  v0 = strip_volume(lin, 1.03e-3_dp, 2.57e-3_dp)
  call check_close(v0, 2e-6_dp * 1.54e-3_dp, 1e-12_dp, 'strip volume with partial cells')
  call check_close(strip_volume(lin, 2.57e-3_dp, 1.03e-3_dp), v0, 1e-15_dp, &
                   'strip order irrelevant')
  total = liner_volume(lin)
  call strip_take(lin, 1.03e-3_dp, 2.57e-3_dp, v)
  call check_close(v, v0, 1e-14_dp, 'take removes the strip volume')
  ! the partial end cells keep the oil outside the strip, and only that
  call check(strip_volume(lin, 1.03e-3_dp, 2.57e-3_dp) == 0.0_dp, 'strip emptied')
  call check_close(liner_volume(lin), total - v, 1e-14_dp, 'take conserves')
  call check_close(strip_volume(lin, 1.0e-3_dp, 1.03e-3_dp), 2e-6_dp * 0.03e-3_dp, 1e-12_dp, &
                   'the end cell keeps its oil outside the strip')
  ! an edge sweeping on: the next step's strip starts where this one ended, inside the cell
  ! [2.5, 2.6] mm, and takes the rest of that cell's oil (with the oil uniform over the cell,
  ! the cell split 0.7/0.3 by the two steps kept 0.7 * 0.3 of its film: a spike)
  call strip_take(lin, 2.57e-3_dp, 3.01e-3_dp, v)
  call check_close(v, 2e-6_dp * 0.44e-3_dp, 1e-12_dp, 'the next strip takes its length of oil')
  call check(strip_volume(lin, 1.03e-3_dp, 3.01e-3_dp) == 0.0_dp, &
             'successive strips of a sweep leave no oil in the cell they share')
  call strip_take(lin, 0.95e-3_dp, 1.03e-3_dp, v)
  call strip_take(lin, 3.01e-3_dp, 3.2e-3_dp, v)
  call check(strip_volume(lin, 0.95e-3_dp, 3.2e-3_dp) == 0.0_dp, 'a sweep from the other side too')
  ! many random-ish transfers: total + (put - taken) bookkeeping to round-off
  total = liner_volume(lin)
  do k = 1, 2000
    za = -1e-3_dp + modulo(k * 0.0371_dp, 1.0_dp) * 65e-3_dp
    zb = za + modulo(k * 0.00713_dp, 1.0_dp) * 2e-3_dp
    if (mod(k, 3) == 0) then
      call strip_take(lin, za, zb, v)
      total = total - v
    else if (mod(k, 3) == 1) then
      call strip_put(lin, za, zb, 1e-9_dp * k, put)
      total = total + put
    else
      call strip_set(lin, za, zb, 3e-6_dp, removed, added)
      total = total + added - removed
    end if
  end do
  call check_close(liner_volume(lin), total, 1e-12_dp, &
                   '2000 transfers: bookkeeping closes to round-off')
  call check(all(lin%h >= 0.0_dp), 'film never negative')
  ! strip_set gives the asked thickness on whole cells
  call strip_set(lin, 10e-3_dp, 20e-3_dp, 5e-6_dp, removed, added)
  ! (the strip's ends fall inside cells: round-off of the cell edges, 1e-10 relative)
  call check_close(strip_volume(lin, 10e-3_dp, 20e-3_dp), 5e-6_dp * 10e-3_dp, 1e-10_dp, &
                   'strip_set: film thickness as asked')
  ! strip_copy: the cells whose centres lie on the strip take the other liner's film, with
  ! where its oil lies (a cell narrowed by a sweep stays narrowed); the others keep theirs
  call liner_init(lin, 0.0_dp, 1e-3_dp, 1e-4_dp, 1e-6_dp)
  call liner_init(other, 0.0_dp, 1e-3_dp, 1e-4_dp, 3e-6_dp)
  call strip_take(other, 0.32e-3_dp, 0.5e-3_dp, v)
  call strip_copy(lin, other, 0.64e-3_dp, 0.24e-3_dp)
  call check(all(lin%h(3:6) == other%h(3:6)) .and. all(lin%h([1, 2, 7, 8, 9, 10]) == 1e-6_dp), &
             'strip_copy: cells 3-6 (centres 0.25-0.55 mm) copied, the others kept')
  call check_close(strip_volume(lin, 0.3e-3_dp, 0.32e-3_dp), 3e-6_dp * 0.02e-3_dp, 1e-12_dp, &
                   'strip_copy: the oil of a narrowed cell lies where it lay')
  call report('test_liner')
end program test_liner
