! ctest labels: numerics
!> Time integration of the mass-conserving film (`&numerics film_time_scheme`, docs/film_model.md
!> "Time"): the film's own history of its content, driven step by step as the cycle drives it
!> (film_evaluate at the step's h0, then content_old = theta h), without the load balance.
!>
!> A starved film on the ring of the tests (b = 1 mm, crown 10 um, offset -38 um), isoviscous,
!> no asperity contact; h0(t) prescribed, the sliding speed u(t) prescribed; the leading edge
!> takes the oil of a liner film h_l(z) over the strip it sweeps (its integral in closed form)
!> plus the bank it pushed ahead, the trailing edge may draw back a film behind it.
!>
!> 1. bdf2_conserves_oil: through a transient with a reversal, at every step the oil the film
!>    holds changes by exactly the oil exchanged through its edge faces over the step (the
!>    BDF2-filtered exchanges the liner and the bank take), to round-off; the step's weight is
!>    1/3 on the smooth stretches and 0 (backward Euler) at the start and at and after a
!>    reversal.
!> 2. bdf2_order: a smooth transient (no reversal): the oil taken in, the oil left behind, the
!>    film's load, friction and content at the end converge at order 2 in the step with BDF2 and at
!>    order 1 with backward Euler (against 3200 steps).
program test_film_time
  use ringlube_kinds, only: dp, pi
  use ringlube_case, only: case_type, default_case
  use ringlube_film, only: film_type, film_setup, film_evaluate, film_friction
  use ringlube_greenwood_tripp, only: gt_init
  use ringlube_check
  implicit none
  !> What a transient reports: the oil taken in through the leading edge, left through the
  !> trailing edge, the film's load and viscous friction at the end [N], the content at the
  !> end [m^2], the largest
  !> per-step error of the oil balance relative to the film's volume, and the steps taken with
  !> the weights r = 1/3, 0 < r < 1/3 and r = 0.
  type :: transient_out
    real(dp) :: taken = 0.0_dp, left = 0.0_dp, load = 0.0_dp, friction = 0.0_dp, content = 0.0_dp
    real(dp) :: balance = 0.0_dp
    integer :: full = 0, limited = 0, euler = 0
  end type transient_out
  type(case_type) :: c

  call gt_init()
  c = default_case()
  c%roelands = .false.
  c%asperity_contact = .false.
  c%cavitation_pressure = 0.0_dp
  c%crankcase_pressure = 1e5_dp
  c%cavitation = 'jfo'
  c%cavity_pressure = 'vapour'
  c%inlet = 'starved'
  c%nodes = 51
  c%width = 1e-3_dp
  c%crown_height = 10e-6_dp
  c%crown_offset = -38e-6_dp
  if (run_case('bdf2_conserves_oil')) call bdf2_conserves_oil()
  if (run_case('bdf2_order')) call bdf2_order()
  call report('test_film_time')

contains

  !> The liner film at z [m] and its integral from 0 to z.
  pure real(dp) function liner_film(z)
    real(dp), intent(in) :: z
    liner_film = 1.2e-6_dp * (1.0_dp + 0.5_dp * sin(z / 2e-3_dp))
  end function liner_film

  pure real(dp) function liner_oil(z)
    real(dp), intent(in) :: z
    liner_oil = 1.2e-6_dp * (z - 0.5_dp * 2e-3_dp * (cos(z / 2e-3_dp) - 1.0_dp))
  end function liner_oil

  !> nsteps steps over [0, t_end] with sliding speed u0 (a + sin(w t)) (a >= 1: no reversal)
  !> and h0 = 1.5 um (1 + 0.3 sin(w t + 1)), w = 2 pi / t_end; the edge's travel is the
  !> integral of |u|.
  function transient(scheme, nsteps, a) result(o)
    character(len=*), intent(in) :: scheme
    integer, intent(in) :: nsteps
    real(dp), intent(in) :: a
    type(transient_out) :: o
    type(case_type) :: cc
    type(film_type) :: f
    real(dp), parameter :: u0 = 6.0_dp, t_end = 2e-3_dp
    real(dp) :: w, dt, t, u, h0, z, z_prev, bank, vol0, vol1, x_in, x_out, s, fv, fb
    integer :: k
    cc = c
    cc%film_time_scheme = scheme
    call film_setup(cc, f)
    w = 2.0_dp * pi / t_end
    dt = t_end / nsteps
    f%dt = dt
    h0 = 1.5e-6_dp * (1.0_dp + 0.3_dp * sin(1.0_dp))
    f%content_old = (h0 + f%s) * 0.5_dp
    bank = 0.0_dp
    z_prev = 0.0_dp
    do k = 1, nsteps
      t = k * dt
      u = u0 * (a + sin(w * t))
      if (abs(u) < 1e-9_dp) u = 0.0_dp
      h0 = 1.5e-6_dp * (1.0_dp + 0.3_dp * sin(w * t + 1.0_dp))
      ! the distance the leading edge sweeps: the integral of |u| (a >= 1: u > 0)
      z = u0 * (a * t - (cos(w * t) - 1.0_dp) / w)
      if (a < 1.0_dp) z = z_prev + abs(u) * dt
      f%ds = z - z_prev
      if (u < 0.0_dp) f%lead_left = .true.
      if (u > 0.0_dp) f%lead_left = .false.
      f%available = bank + liner_oil(z) - liner_oil(z_prev)
      f%behind = 0.3e-6_dp * abs(f%ds)
      vol0 = f%dx * sum(f%content_old(2:f%n - 1))
      call film_evaluate(cc, f, h0, 0.0_dp, u, 3e5_dp, 1e-9_dp)
      if (f%r_step == 1.0_dp / 3.0_dp) then
        o%full = o%full + 1
      else if (f%r_step > 0.0_dp) then
        o%limited = o%limited + 1
      else
        o%euler = o%euler + 1
      end if
      ! the cycle's acceptance: the content carried on, the oil exchanged with liner and bank
      f%content_old = f%theta * f%h
      vol1 = f%dx * sum(f%content_old(2:f%n - 1))
      if (f%lead_left) then
        x_in = f%q_left * dt
        x_out = f%q_right * dt
      else
        x_in = -f%q_right * dt
        x_out = -f%q_left * dt
      end if
      s = max(vol0, vol1, tiny(1.0_dp))
      o%balance = max(o%balance, abs((vol1 - vol0) - (x_in - x_out)) / s)
      bank = max(f%available - x_in, 0.0_dp)
      o%taken = o%taken + x_in
      o%left = o%left + x_out
      o%load = f%wh
      call film_friction(cc, f, u, fv, fb)
      o%friction = fv
      z_prev = z
    end do
    o%content = vol1
  end function transient

  subroutine bdf2_conserves_oil()
    type(transient_out) :: o
    ! u = u0 (0.3 + sin): reverses twice
    o = transient('bdf2', 400, 0.3_dp)
    write (*, '(a, es10.3, a, 3i5)') '1. largest per-step oil balance error / film volume: ', &
      o%balance, '; steps with r = 1/3, limited, 0: ', o%full, o%limited, o%euler
    call check(o%balance <= 1e-12_dp, 'BDF2: each step conserves the oil to round-off')
    call check(o%full > 300, 'BDF2 on the smooth stretches')
    ! the first five steps (two to have a history, then four of one sign), and five from each of
    ! the two reversals (the step where u changes sign and the four after it)
    call check(o%euler >= 5 .and. o%euler <= 5 + 2 * 5, 'backward Euler at the start and reversals')
    o = transient('euler', 400, 0.3_dp)
    call check(o%balance <= 1e-12_dp, 'backward Euler: each step conserves the oil to round-off')
    call check(o%full == 0 .and. o%limited == 0, 'film_time_scheme euler: r = 0 at every step')
  end subroutine bdf2_conserves_oil

  subroutine bdf2_order()
    integer, parameter :: nlev = 4, nref = 3200
    type(transient_out) :: o(nlev), ref
    character(len=5), parameter :: schemes(2) = ['bdf2 ', 'euler']
    real(dp) :: e(nlev, 5), slope(5)
    character(len=14), parameter :: names(5) = [character(len=14) :: &
                                              'oil taken', 'oil left', 'end load', 'end friction', &
                                                'end content']
    integer :: l, q, is
    character(len=96) :: what
    do is = 1, 2
      ref = transient(trim(schemes(is)), nref, 1.5_dp)
      do l = 1, nlev
        o(l) = transient(trim(schemes(is)), 50 * 2**(l - 1), 1.5_dp)
        e(l, :) = abs([o(l)%taken - ref%taken, o(l)%left - ref%left, o(l)%load - ref%load, &
                       o(l)%friction - ref%friction, o(l)%content - ref%content]) &
                  / abs([ref%taken, ref%left, ref%load, ref%friction, ref%content])
      end do
      do q = 1, 5
        slope(q) = log(e(nlev - 1, q) / e(nlev, q)) / log(2.0_dp)
        write (*, '(a, a6, a, a14, a, 4es10.2, a, f6.2)') '2. ', trim(schemes(is)), ' ', names(q), &
          ' error at 50..400 steps:', e(:, q), '; order ', slope(q)
        if (is == 1) then
          write (what, '(a, a)') 'BDF2: order about 2 in the step, ', trim(names(q))
          call check(slope(q) > 1.7_dp .and. slope(q) < 2.5_dp, trim(what))
        else
          write (what, '(a, a)') 'backward Euler: order about 1 in the step, ', trim(names(q))
          call check(slope(q) > 0.7_dp .and. slope(q) < 1.4_dp, trim(what))
        end if
      end do
    end do
  end subroutine bdf2_order
end program test_film_time
