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
  use jfo_test_tools, only: grid
  implicit none

  if (run_case('meniscus_walk')) call case_meniscus_walk()
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
        call jfo_solve(dx, h, hmid, kmid, u, 1e-5_dp, cold, pl, pr, tl, tr, pc, p, th, it_on, &
                       info_on)
        call jfo_solve(dx, h, hmid, kmid, u, 1e-5_dp, cold, pl, pr, tl, tr, pc, p2, th2, it_off, &
                       info_off, options=off)
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
end program test_jfo_coarse
