! ctest labels: numerics
!> The coarse-grid predictor of the mass-conserving film solve (ringlube_jfo, `walk_steps`;
!> docs/film_model.md "Coarse-grid predictor"): a Newton step moves a reformation front that
!> has to advance against the Couette flow by one node, so without the predictor the
!> iterations of a solve whose warm start puts that front far off grow with the nodes (251 to
!> 4001 nodes: 14, 50, 192, and the cap of 200 at 8001). With it (from 401 nodes) they stay
!> bounded, and the answer is the same solve's (the predictor changes the start, not the
!> tolerance).
program test_jfo_coarse
  use ringlube_kinds, only: dp
  use ringlube_jfo
  use ringlube_check
  use jfo_test_tools, only: grid, rnd, random_step
  use slider_closed_form, only: b
  implicit none

  if (run_case('meniscus_walk')) call case_meniscus_walk()
  if (run_case('random_starts')) call case_random_starts()
  call report('test_jfo_coarse')

contains

  !> The parabolic ring of the other JFO tests, one backward Euler step of 10 us at 10 m/s,
  !> starved inlet (fill 0.2) at 3 bar, the other edge at 1 bar, cavitation at 0 Pa. Two
  !> set-ups: the inlet on the right with a flooded film before (content h) and a flooded warm
  !> start; the inlet on the left with a half-filled film before and the warm start at the
  !> inlet's fill. The inlet's partly filled zone ends at a meniscus hundreds of nodes from
  !> where the warm start has it. At 251 (below the predictor's 401), 1000 (coarsening by 3),
  !> 1001 and 4001 nodes: the solve converges in at most 16 iterations at every size, the
  !> iterations at 4001 nodes are at most 1.5 times those at 1001, and without the predictor the solve (where it converges)
  !> gives the same pressure to 1e-12 and fill to 1e-12, and takes at least 4 times as many
  !> iterations at 4001 nodes.
  subroutine case_meniscus_walk()
    integer, parameter :: sizes(4) = [251, 1000, 1001, 4001]
    real(dp), allocatable :: x(:), h(:), hmid(:), kmid(:), p(:), th(:), p2(:), th2(:), pc(:)
    real(dp), allocatable :: cold(:)
    real(dp) :: dx, u, pl, pr, tl, tr
    integer :: k, setup, n, it_on, it_off, info_on, info_off, its(size(sizes))
    type(jfo_options) :: off
    type(jfo_problem) :: prob
    type(jfo_stats) :: st
    character(len=100) :: what
    off%coarse = .false.
    do setup = 1, 2
      do k = 1, size(sizes)
        n = sizes(k)
        call grid(n, x, h, hmid, kmid, dx)
        if (allocated(p)) deallocate (p, th, p2, th2, pc, cold)
        allocate (p(n), th(n), p2(n), th2(n), pc(n), cold(n))
        pc = 0.0_dp
        if (setup == 1) then
          u = 10.0_dp
          pl = 1e5_dp
          pr = 3e5_dp
          tl = 1.0_dp
          tr = 0.2_dp
          cold = h
          p = 1e5_dp
          th = 1.0_dp
        else
          u = -10.0_dp
          pl = 3e5_dp
          pr = 1e5_dp
          tl = 0.2_dp
          tr = 1.0_dp
          cold = 0.5_dp * h
          p = 0.0_dp
          th = 0.2_dp
        end if
        p2 = p
        th2 = th
        prob = jfo_problem(dx=dx, u=u, dt=1e-5_dp, p_left=pl, p_right=pr, theta_left=tl, &
                           theta_right=tr)
        call jfo_solve(prob, h, hmid, kmid, cold, pc, p, th, st)
        it_on = st%iterations; info_on = st%info
        call jfo_solve(prob, h, hmid, kmid, cold, pc, p2, th2, st, off)
        it_off = st%iterations; info_off = st%info
        its(k) = it_on
        write (*, '(2x, a, i0, a, i5, a, i4, a, i4)') 'set-up ', setup, ', nodes', n, &
          ': iterations with the predictor', it_on, ', without', it_off
        write (what, '(a, i0, a, i0, a)') 'set-up ', setup, ', ', n, &
          ' nodes: converges in at most 16 iterations'
        call check(info_on == JFO_OK .and. it_on <= 16, trim(what))
        if (info_off == JFO_OK) then
          write (what, '(a, i0, a, i0, a)') 'set-up ', setup, ', ', n, &
            ' nodes: the same solution as without the predictor'
          call check(maxval(abs(p - p2)) <= 1e-12_dp * maxval(p) .and. &
                     maxval(abs(th - th2)) <= 1e-12_dp, trim(what))
        end if
        if (n == 4001) then
          write (what, '(a, i0, a)') 'set-up ', setup, &
            ', 4001 nodes: at least 4 times fewer iterations than without the predictor'
          call check(it_off >= 4 * it_on, trim(what))
        end if
      end do
      write (what, '(a, i0, a)') 'set-up ', setup, ': iterations at 4001 nodes <= 1.5 x at 1001'
      call check(real(its(4), dp) <= 1.5_dp * its(3), trim(what))
    end do
  end subroutine case_meniscus_walk

  !> Random cold starts (as test_jfo's guard case: gap, speed, edge pressures and fills,
  !> steady or transient, zones at gas pressures up to 36 bar, capped edges, random warm-start
  !> fills and pressures up to 100 bar), each solved with and without the predictor. At 401
  !> and 405 nodes (coarsening by 4 and by 2) at most 1 of 200 solves that converge without
  !> the predictor fail with it (before: 8 and 7: a restart that Newton stalled from, with the
  !> Gauss-Seidel budget spent, was never taken back, and the solve ended at the iteration cap
  !> from it), and where both converge they agree to 1e-10 (pressure, relative) and 1e-10
  !> (fill). At 402 nodes (401 prime: no coarsening) the solve is the one without the
  !> predictor, iteration for iteration (a restart without a coarse grid used to reset the
  !> guard's history and change the path).
  subroutine case_random_starts()
    integer, parameter :: sizes(3) = [401, 405, 402], ntrial = 200
    real(dp), allocatable :: x(:), hh(:), hmm(:), km(:), cold(:), pc(:), p0(:), t0(:)
    real(dp), allocatable :: p1(:), th1(:), p2(:), th2(:)
    real(dp) :: dx, hm, u, pl, pr, tl, tr, dtr, capl, capr, qs, dpm, dtm
    integer :: k, n, trial, i, j, a, w, it1, it2, in1, in2, nbroken, nfixed, ndiff, nsame
    logical :: capped
    type(jfo_options) :: off
    type(jfo_problem) :: prob
    type(jfo_stats) :: st
    character(len=100) :: what
    off%coarse = .false.
    do k = 1, size(sizes)
      n = sizes(k)
      if (allocated(x)) deallocate (x, hh, hmm, km, cold, pc, p0, t0, p1, th1, p2, th2)
      allocate (x(n), hh(n), hmm(n - 1), km(n - 1), cold(n), pc(n), p0(n), t0(n), p1(n), &
                th1(n), p2(n), th2(n))
      dx = b / (n - 1)
      x = [(-0.5_dp * b + (i - 1) * dx, i=1, n)]
      nbroken = 0
      nfixed = 0
      ndiff = 0
      nsame = 0
      do trial = 1, ntrial
        call random_step(trial, x, hm, hh, hmm, km, u, pl, pr, tl, tr, dtr)
        if (rnd(trial, 20) < 0.1_dp) u = 0.0_dp
        pc = 0.5e5_dp
        if (rnd(trial, 9) < 0.5_dp) then
          do j = 1, 1 + int(4 * rnd(trial, 30))
            a = 2 + int((n - 3) * rnd(trial, 30 + 2 * j))
            w = 1 + int(0.2_dp * n * rnd(trial, 31 + 2 * j))
            pc(a:min(n - 1, a + w)) = 1e5_dp + 3.5e6_dp * rnd(trial, 40 + j)**2
          end do
        end if
        do i = 1, n
          t0(i) = min(1.0_dp, 1.3_dp * rnd(trial, 100 + i))
          p0(i) = 1e7_dp * rnd(trial, 100000 + i)**2
        end do
        cold = hh * min(1.0_dp, t0 + 0.2_dp)
        if (rnd(trial, 14) < 0.5_dp) cold = hh * (0.3_dp + 0.7_dp * rnd(trial, 15))
        capped = rnd(trial, 16) < 0.3_dp
        qs = abs(u) * 0.5_dp * hm + 1e-9_dp
        capl = huge(1.0_dp)
        capr = huge(1.0_dp)
        if (capped) then
          capl = qs * rnd(trial, 17)**2
          capr = qs * rnd(trial, 18)**2
        end if
        p1 = p0
        th1 = t0
        p2 = p0
        th2 = t0
        prob = jfo_problem(dx=dx, u=u, dt=dtr, p_left=pl, p_right=pr, theta_left=tl, &
                           theta_right=tr, cap_left=capl, cap_right=capr)
        call jfo_solve(prob, hh, hmm, km, cold, pc, p1, th1, st)
        it1 = st%iterations; in1 = st%info
        call jfo_solve(prob, hh, hmm, km, cold, pc, p2, th2, st, off)
        it2 = st%iterations; in2 = st%info
        if (in1 /= JFO_OK .and. in2 == JFO_OK) nbroken = nbroken + 1
        if (in1 == JFO_OK .and. in2 /= JFO_OK) nfixed = nfixed + 1
        dpm = maxval(abs(p1 - p2)) / maxval(abs(p2))
        dtm = maxval(abs(th1 - th2))
        if (in1 == JFO_OK .and. in2 == JFO_OK .and. (dpm > 1e-10_dp .or. dtm > 1e-10_dp)) &
          ndiff = ndiff + 1
        if (in1 == in2 .and. it1 == it2 .and. all(p1 == p2) .and. all(th1 == th2)) &
          nsame = nsame + 1
      end do
      write (*, '(2x, i0, a, i0, a, i0, a, i0, a, i0, a, i0, a)') n, ' nodes, ', ntrial, &
        ' random starts: converged only without the predictor ', nbroken, ', only with it ', &
        nfixed, ', answers differing ', ndiff, ', identical solves ', nsame
      write (what, '(i0, a)') n, &
        ' nodes: at most 1 solve that converges without the predictor fails with it'
      call check(nbroken <= 1, trim(what))
      write (what, '(i0, a)') n, ' nodes: the same answers with and without the predictor'
      call check(ndiff == 0, trim(what))
      if (n == 402) call check(nsame == ntrial, &
                      '402 nodes (no coarse grid): solves identical to those without the predictor')
    end do
  end subroutine case_random_starts
end program test_jfo_coarse

