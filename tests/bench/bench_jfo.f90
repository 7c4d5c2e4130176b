!> Cost of the mass-conserving film solve (docs/film_model.md, "Why Newton"): microseconds
!> and iterations per warm-started solve of ringlube_jfo's semismooth Newton against the
!> Elrod / Ausas relaxation (tests/fortran/jfo_reference.f90, SOR factor 1.7, stopped when no
!> value moves by more than 1e-10) and against the Swift-Stieber solve (ringlube_reynolds), on
!> the same transient: the parabolic ring of the tests (b = 1 mm, crown 10 um, offset -38 um),
!> U = 10 sin(2 pi t/T) m/s, h0 = 1 um (1 + 0.6 sin(6 pi t/T)), chamber edge 3 bar, crankcase
!> edge 1 bar, cavitation at 0.5 bar, starved upstroke (theta_in = 0.6), 720 steps per period.
!> Built by CMake (target bench_jfo), never run as a test:
!>
!>     cmake --build build --target bench_jfo && ./build/bench_jfo
!>
!> Each size runs three times (the machine may be shared); quote the fastest.
!>
!>     ./build/bench_jfo --alone [NODES]
!>
!> only the solvers alone (each loop timed as a whole, CPU time), at NODES alone if given, with
!> each solver's iterations over one repetition of the transient: for an instruction count
!> (`valgrind --tool=callgrind ./build/bench_jfo --alone 51`: the inclusive counts of
!> jfo_solve and reynolds_solve over 15 times those iterations, instructions per iteration).
program bench_jfo
  use ringlube_kinds, only: dp, pi
  use ringlube_jfo, only: jfo_solve, jfo_problem, jfo_stats
  use ringlube_jfo_system, only: jfo_system, jfo_scratch
  use ringlube_reynolds, only: reynolds_solve, reynolds_problem, reynolds_work, reynolds_work_init
  use jfo_reference, only: elrod_solve
  implicit none
  integer, parameter :: sizes(2) = [51, 201]
  integer :: k, rep, only
  character(len=16) :: arg

  only = 0
  if (command_argument_count() >= 2) then
    call get_command_argument(2, arg)
    read (arg, *) only
  end if
  call get_command_argument(1, arg)
  if (arg /= '--alone') then
    ! the machine may be shared: three repetitions, quote the fastest
    write (*, '(a)') '  nodes  solver                      us/solve  '// &
      'iterations/solve (mean, max)  us/iteration'
    do k = 1, size(sizes)
      do rep = 1, 3
        call run(sizes(k))
      end do
    end do
  end if
  ! each solver alone over the transient, the whole loop timed (best of 15): per solve and per
  ! iteration, against the Swift-Stieber solve
  write (*, '(a)') '  nodes  solver alone, best of 15     us/solve  us/iteration'// &
    '  x Swift-Stieber per iteration'
  if (only > 0) then
    call alone(only)
  else
    do k = 1, size(sizes)
      call alone(sizes(k))
    end do
  end if

contains

  !> The transient of `run` solved by jfo_solve alone and by reynolds_solve alone, each loop
  !> timed as a whole (CPU time, fastest of 15 repetitions): microseconds per solve and per iteration.
  subroutine alone(n)
    integer, intent(in) :: n
    real(dp), parameter :: b = 1e-3_dp, crown = 10e-6_dp, xs = -38e-6_dp, eta = 0.01_dp
    real(dp), parameter :: kk = crown / (0.5_dp * b)**2
    integer, parameter :: nsteps = 720, periods = 3
    real(dp) :: x(n), h(n), hold(n), hmid(n - 1), kmid(n - 1), p(n), th(n), pc(n), cold(n), ps(n)
    logical :: active(n)
    real(dp) :: dx, dt, u, hm, tin, tj, ts, tbest(2)
    integer :: i, j, rep, it, info, itj, its
    real(dp) :: c0r, c1r
    type(jfo_stats) :: st
    type(jfo_system) :: work
    type(jfo_scratch) :: scratch
    type(reynolds_work) :: rwork
    call reynolds_work_init(rwork, n)
    dx = b / (n - 1)
    x = [(-0.5_dp * b + (i - 1) * dx, i=1, n)]
    dt = 1e-5_dp
    pc = 0.5e5_dp
    tbest = huge(1.0_dp)
    do rep = 1, 15
      p = 1e5_dp
      th = 1.0_dp
      ps = p
      active = .false.
      itj = 0
      its = 0
      tj = 0.0_dp
      ts = 0.0_dp
      h = 1e-6_dp + kk * (x + xs)**2
      ! JFO alone
      call cpu_time(c0r)
      do j = 1, periods * nsteps
        u = 10.0_dp * sin(2 * pi * j / nsteps)
        hold = h
        hm = 1e-6_dp * (1.0_dp + 0.6_dp * sin(6 * pi * j / nsteps))
        h = hm + kk * (x + xs)**2
        hmid = hm + kk * (0.5_dp * (x(1:n - 1) + x(2:n)) + xs)**2
        kmid = hmid**3 / (12 * eta)
        tin = merge(0.6_dp, 1.0_dp, u < 0.0_dp)
        cold = th * hold
        call jfo_solve(jfo_problem(dx=dx, u=u, dt=dt, p_left=3e5_dp, p_right=1e5_dp, &
                                   theta_left=tin), h, hmid, kmid, cold, pc, p, th, st, &
                       work=work, scratch=scratch)
        itj = itj + st%iterations
      end do
      call cpu_time(c1r)
      tj = c1r - c0r
      ! Swift-Stieber alone (the same gaps)
      h = 1e-6_dp + kk * (x + xs)**2
      call cpu_time(c0r)
      do j = 1, periods * nsteps
        u = 10.0_dp * sin(2 * pi * j / nsteps)
        hold = h
        hm = 1e-6_dp * (1.0_dp + 0.6_dp * sin(6 * pi * j / nsteps))
        h = hm + kk * (x + xs)**2
        hmid = hm + kk * (0.5_dp * (x(1:n - 1) + x(2:n)) + xs)**2
        kmid = hmid**3 / (12 * eta)
        call reynolds_solve(reynolds_problem(dx=dx, u=u, sq=2 * (h(1) - hold(1)) / dt, &
                                             p_left=3e5_dp, p_right=1e5_dp, p_cav=0.5e5_dp), &
                            2 * kmid, hmid, ps, active, it, info, rwork)
        its = its + it
      end do
      call cpu_time(c1r)
      ts = c1r - c0r
      tbest(1) = min(tbest(1), tj)
      tbest(2) = min(tbest(2), ts)
    end do
    write (*, '(i7, 2x, a, f10.3, f14.3, f10.2)') n, 'jfo_solve (Newton)         ', &
      1e6_dp * tbest(1) / (periods * nsteps), 1e6_dp * tbest(1) / itj, &
      (tbest(1) / itj) / (tbest(2) / its)
    write (*, '(i7, 2x, a, f10.3, f14.3)') n, 'reynolds_solve (Swift-St.) ', &
      1e6_dp * tbest(2) / (periods * nsteps), 1e6_dp * tbest(2) / its
    write (*, '(i7, 2x, a, i8, a, i8, a)') n, 'iterations per repetition: ', itj, &
      ' (jfo_solve), ', its, ' (reynolds_solve)'
  end subroutine alone

  subroutine run(n)
    integer, intent(in) :: n
    real(dp), parameter :: b = 1e-3_dp, crown = 10e-6_dp, xs = -38e-6_dp, eta = 0.01_dp
    real(dp), parameter :: kk = crown / (0.5_dp * b)**2
    integer, parameter :: nsteps = 720, periods = 3
    real(dp) :: x(n), h(n), hold(n), hmid(n - 1), kmid(n - 1), p(n), th(n), pc(n), cold(n)
    real(dp) :: pr(n), tr(n), ps(n)
    logical :: active(n)
    real(dp) :: dx, dt, t, u, hm, tin, tn, te, ts
    integer :: i, j, it, info, sw, itsum, itmax, swsum, swmax, ssum, smax, nsolve
    integer(8) :: c0, c1, rate
    type(jfo_stats) :: st
    ! the solvers' working arrays, kept between solves as the film keeps them
    type(jfo_system) :: work
    type(jfo_scratch) :: scratch
    type(reynolds_work) :: rwork

    call reynolds_work_init(rwork, n)
    dx = b / (n - 1)
    x = [(-0.5_dp * b + (i - 1) * dx, i=1, n)]
    dt = 1e-5_dp
    pc = 0.5e5_dp
    p = 1e5_dp
    th = 1.0_dp
    pr = p
    tr = th
    active = .false.
    tn = 0.0_dp
    te = 0.0_dp
    ts = 0.0_dp
    itsum = 0
    itmax = 0
    swsum = 0
    swmax = 0
    ssum = 0
    smax = 0
    nsolve = 0
    h = 1e-6_dp + kk * (x + xs)**2
    do j = 1, periods * nsteps
      t = j * dt
      u = 10.0_dp * sin(2 * pi * j / nsteps)
      hold = h
      hm = 1e-6_dp * (1.0_dp + 0.6_dp * sin(6 * pi * j / nsteps))
      h = hm + kk * (x + xs)**2
      hmid = hm + kk * (0.5_dp * (x(1:n - 1) + x(2:n)) + xs)**2
      kmid = hmid**3 / (12 * eta)
      tin = merge(0.6_dp, 1.0_dp, u < 0.0_dp)
      cold = th * hold
      call system_clock(c0, rate)
      call jfo_solve(jfo_problem(dx=dx, u=u, dt=dt, p_left=3e5_dp, p_right=1e5_dp, &
                                 theta_left=tin), h, hmid, kmid, cold, pc, p, th, st, &
                     work=work, scratch=scratch)
      call system_clock(c1)
      it = st%iterations
      if (j <= nsteps) cycle   ! first period: settle the periodic state
      tn = tn + real(c1 - c0, dp) / rate
      itsum = itsum + it
      itmax = max(itmax, it)
      nsolve = nsolve + 1
      cold = tr * hold
      call system_clock(c0)
      call elrod_solve(dx, h, hmid, kmid, u, dt, cold, 3e5_dp, 1e5_dp, tin, 1.0_dp, pc, pr, tr, &
                       sw, &
                       1e-10_dp, 1.7_dp, 10000000)
      call system_clock(c1)
      te = te + real(c1 - c0, dp) / rate
      swsum = swsum + sw
      swmax = max(swmax, sw)
      call system_clock(c0)
      call reynolds_solve(reynolds_problem(dx=dx, u=u, sq=2 * (h(1) - hold(1)) / dt, &
                                           p_left=3e5_dp, p_right=1e5_dp, p_cav=0.5e5_dp), &
                          2 * kmid, hmid, ps, active, it, info, rwork)
      call system_clock(c1)
      ts = ts + real(c1 - c0, dp) / rate
      ssum = ssum + it
      smax = max(smax, it)
    end do
    write (*, '(i7, 2x, a, f10.2, f10.2, i6, f10.3)') n, 'jfo_solve (Newton)         ', &
      1e6_dp * tn / nsolve, &
      real(itsum, dp) / nsolve, itmax, 1e6_dp * tn / itsum
    write (*, '(i7, 2x, a, f10.1, f10.2, i6)') n, 'Elrod/Ausas relaxation     ', &
      1e6_dp * te / nsolve, &
      real(swsum, dp) / nsolve, swmax
    write (*, '(i7, 2x, a, f10.2, f10.2, i6, f10.3)') n, 'reynolds_solve (Swift-St.) ', &
      1e6_dp * ts / nsolve, &
      real(ssum, dp) / nsolve, smax, 1e6_dp * ts / ssum
    write (*, '(i7, 2x, a, es10.2, a, es10.2)') n, 'max |p_jfo - p_elrod| / max p at the end ', &
      maxval(abs(p - pr)) / maxval(p), ', max |theta diff| ', maxval(abs(th - tr))
  end subroutine run
end program bench_jfo
