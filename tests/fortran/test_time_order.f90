! ctest labels: numerics
!> Order of the time schemes of the squeeze term (`&numerics time_scheme`), through the
!> load balance itself, on a problem with a closed-form answer.
!>
!> A flat ring (no crown) on a liner at rest (u = 0), isoviscous, without asperity
!> contact, both edges at the crankcase pressure p_a, pressed by its elastic pressure p_e:
!> the film is a pure squeeze film between parallel plates. With K = h^3/(6 eta) and
!> K p'' = 2 dh/dt the pressure is p_a + 6 eta (-dh/dt)/h^3 (b^2/4 - x^2), a parabola the
!> finite-difference scheme reproduces exactly at the nodes; the trapezoidal load of
!> (b^2/4 - x^2) on n nodes is b^3/6 - dx^2 b/6 (Euler-Maclaurin ends at the first
!> term for a parabola). The balance W_h = (p_e + p_a) b 2 pi r0 then reads
!>   -dh/dt = k h^3,   k = p_e / (eta (b^2 - dx^2)),
!> whose solution is h(t) = (h(0)^-2 + 2 k t)^(-1/2). The load balance at tight load_tol
!> integrates this ODE with the chosen scheme; halving the step must divide the error at
!> t_end by about 2 (Euler) or 4 (BDF2).
program test_time_order
  use ringlube_kinds, only: dp, pi
  use ringlube_case, only: case_type, default_case, elastic_pressure
  use ringlube_viscosity, only: roelands
  use ringlube_film, only: film_type, film_setup
  use ringlube_load_balance, only: step_context, load_problem, balance_memory, balance, &
                                   start_history
  use ringlube_results, only: flag_floor
  use ringlube_check
  implicit none
  integer, parameter :: nlev = 4
  real(dp) :: e_euler(nlev), e_bdf2(nlev), order
  integer :: lev

  do lev = 1, nlev
    e_euler(lev) = final_error('euler', 10 * 2**(lev - 1))
    e_bdf2(lev) = final_error('bdf2', 10 * 2**(lev - 1))
  end do
  write (*, '(a, 4es11.3)') 'euler: relative error of h(t_end) at 10, 20, 40, 80 steps:', e_euler
  write (*, '(a, 4es11.3)') 'bdf2:  relative error of h(t_end) at 10, 20, 40, 80 steps:', e_bdf2
  do lev = 2, nlev
    order = log(e_euler(lev - 1) / e_euler(lev)) / log(2.0_dp)
    write (*, '(a, i0, a, f6.3)') 'euler observed order, level ', lev, ': ', order
    call check(abs(order - 1.0_dp) < 0.15_dp, 'euler: observed order 1')
    order = log(e_bdf2(lev - 1) / e_bdf2(lev)) / log(2.0_dp)
    write (*, '(a, i0, a, f6.3)') 'bdf2 observed order, level ', lev, ': ', order
    call check(abs(order - 2.0_dp) < 0.15_dp, 'bdf2: observed order 2')
  end do
  call check(e_bdf2(1) < 0.2_dp * e_euler(1), 'bdf2 more accurate than euler at 10 steps')
  call check(e_bdf2(nlev) < 1e-4_dp, 'bdf2 within 1e-4 at 80 steps')

  call fallback()
  call report('test_time_order')

contains

  !> Relative error of h at t_end = 20 ms after nsteps steps of `scheme`.
  real(dp) function final_error(scheme, nsteps)
    character(len=*), intent(in) :: scheme
    integer, intent(in) :: nsteps
    type(case_type) :: c
    type(film_type) :: f
    type(balance_memory) :: mem
    type(step_context) :: ctx
    type(load_problem) :: lp
    real(dp) :: h_init, t_end, eta, k, dxx, h, resid, exact
    integer :: i, flags
    c = squeeze_case(scheme)
    call film_setup(c, f)
    h_init = 2e-6_dp
    t_end = 20e-3_dp
    ctx%omega = 0.0_dp
    ctx%dt = t_end / nsteps
    ctx%p_e = elastic_pressure(c)
    call start_history(mem, h_init)
    do i = 1, nsteps
      call balance(c, ctx, f, mem, 90.0_dp, h, flags, resid, lp)
      call check(flags == 0 .and. abs(resid) <= c%load_tol, scheme//': step balanced, unflagged')
      call check(lp%u == 0.0_dp, 'liner at rest')
    end do
    eta = roelands(0.0_dp, c%liner_temperature, c%eta0, c%theta0, c%alpha, c%beta)
    dxx = c%width / (c%nodes - 1)
    k = ctx%p_e / (eta * (c%width**2 - dxx**2))
    exact = (h_init**(-2) + 2.0_dp * k * t_end)**(-0.5_dp)
    final_error = abs(h - exact) / exact
  end function final_error

  type(case_type) function squeeze_case(scheme) result(c)
    character(len=*), intent(in) :: scheme
    c = default_case()
    c%crown_height = 0.0_dp
    c%crown_offset = 0.0_dp
    c%roelands = .false.
    c%asperity_contact = .false.
    c%outlet = 'ambient'
    c%nodes = 21
    c%load_tol = 1e-12_dp
    c%time_scheme = scheme
  end function squeeze_case

  !> BDF2 starts with an Euler step and restarts after a step held at h0_floor: the
  !> first step and the first step after a held one give the same h0 as Euler from the
  !> same state.
  subroutine fallback()
    type(case_type) :: ce, cb
    type(film_type) :: fe, fb
    type(balance_memory) :: me, mb
    type(step_context) :: ctx
    type(load_problem) :: lp
    real(dp) :: he, hb, resid
    integer :: flags, i
    ce = squeeze_case('euler')
    cb = squeeze_case('bdf2')
    call film_setup(ce, fe)
    call film_setup(cb, fb)
    ctx%omega = 0.0_dp
    ctx%dt = 1e-3_dp
    ctx%p_e = elastic_pressure(ce)
    call start_history(me, 2e-6_dp)
    call start_history(mb, 2e-6_dp)
    call balance(ce, ctx, fe, me, 0.0_dp, he, flags, resid, lp)
    call balance(cb, ctx, fb, mb, 0.0_dp, hb, flags, resid, lp)
    call check_close(hb, he, 1e-10_dp, 'bdf2 first step = euler step')
    call balance(cb, ctx, fb, mb, 0.0_dp, hb, flags, resid, lp)
    call balance(ce, ctx, fe, me, 0.0_dp, he, flags, resid, lp)
    call check(abs(hb - he) > 1e-6_dp * he, 'bdf2 second step differs from euler')
    ! a floor above the film: the step is held there and flagged
    cb%h0_floor = 1.5_dp * hb
    ce%h0_floor = cb%h0_floor
    do i = 1, 2
      call balance(cb, ctx, fb, mb, 0.0_dp, hb, flags, resid, lp)
    end do
    call check(iand(flags, flag_floor) /= 0 .and. abs(hb - cb%h0_floor) <= 1e-12_dp * hb, &
               'held at h0_floor')
    ! from the held state, BDF2's next step is an Euler step
    cb%h0_floor = 1e-9_dp
    ce%h0_floor = 1e-9_dp
    call start_history(me, hb)
    call balance(cb, ctx, fb, mb, 0.0_dp, hb, flags, resid, lp)
    call balance(ce, ctx, fe, me, 0.0_dp, he, flags, resid, lp)
    call check_close(hb, he, 1e-10_dp, 'bdf2 restarts with an euler step after a held step')
  end subroutine fallback
end program test_time_order
