!> The f2py layer: plain-array entry points with iso_c_binding kinds.
!>
!> f2py cannot pass derived types, so a case travels as a deck file (the same reader as
!> ringlube-solve, hence identical numbers) and results come back as arrays. Errors come
!> back as (code, message); nothing here stops the process.

!> Number of crank steps a deck will produce, or an input error.
subroutine rl_count_steps(deck, nsteps, code, message)
  use, intrinsic :: iso_c_binding, only: c_int
  use ringlube_error, only: error_type
  use ringlube_case, only: case_type, steps_per_cycle
  use ringlube_input, only: read_deck
  implicit none
  character(len=*), intent(in) :: deck
  integer(c_int), intent(out) :: nsteps, code
  character(len=2048), intent(out) :: message
  type(case_type) :: c
  type(error_type), allocatable :: err
  nsteps = 0
  code = 0
  message = ''
  call read_deck(deck, c, err, load_trace=.false.)
  if (allocated(err)) then
    code = err%code
    message = err%message
    return
  end if
  nsteps = steps_per_cycle(c)
end subroutine rl_count_steps

!> Run the deck. `series(:, j)` holds, for j = 1..13: crank angle, sliding speed, h0,
!> lambda_min, gas pressure, applied load, hydrodynamic load, asperity load, viscous
!> friction, boundary friction, friction, power loss, load residual. `scalars`: energy
!> loss J, mixed share %, ring mass g, min film m, max friction N, converged, cycles run,
!> cycle change, sigma m, run time s, film solves, periodic, Reynolds solves, cycles
!> computed (including warm-up).
subroutine rl_run_deck(deck, nsteps, series, flags, iterations, scalars, code, message)
  use, intrinsic :: iso_c_binding, only: c_int, c_double, c_int64_t
  use ringlube_kinds, only: dp
  use ringlube_error, only: error_type, rl_input_error
  use ringlube_case, only: case_type, steps_per_cycle, composite_sigma
  use ringlube_input, only: read_deck
  use ringlube_cycle, only: result_type, solve_cycle
  implicit none
  character(len=*), intent(in) :: deck
  integer(c_int), intent(in) :: nsteps
  real(c_double), intent(out) :: series(nsteps, 13)
  integer(c_int), intent(out) :: flags(nsteps), iterations(nsteps)
  real(c_double), intent(out) :: scalars(14)
  integer(c_int), intent(out) :: code
  character(len=2048), intent(out) :: message
  type(case_type) :: c
  type(result_type) :: r
  type(error_type), allocatable :: err
  integer(c_int64_t) :: t0, t1, rate

  series = 0.0_c_double
  flags = 0
  iterations = 0
  scalars = 0.0_c_double
  code = 0
  message = ''
  call read_deck(deck, c, err)
  if (allocated(err)) then
    code = err%code
    message = err%message
    return
  end if
  if (steps_per_cycle(c) /= nsteps) then
    code = rl_input_error
    message = deck // ': number of crank steps changed between calls'
    return
  end if
  call system_clock(t0, rate)
  call solve_cycle(c, r, err)
  call system_clock(t1)
  if (allocated(err)) then
    code = err%code
    message = err%message
    return
  end if
  series(:, 1) = r%crank_angle_deg
  series(:, 2) = r%sliding_speed
  series(:, 3) = r%h0
  series(:, 4) = r%lambda_min
  series(:, 5) = r%gas_pressure
  series(:, 6) = r%applied_load
  series(:, 7) = r%hydrodynamic_load
  series(:, 8) = r%asperity_load
  series(:, 9) = r%viscous_friction
  series(:, 10) = r%boundary_friction
  series(:, 11) = r%friction
  series(:, 12) = r%power_loss
  series(:, 13) = r%load_residual
  flags = r%flags
  iterations = r%iterations
  scalars(1) = r%energy_loss
  scalars(2) = r%mixed_share
  scalars(3) = r%ring_mass * 1e3_dp
  scalars(4) = r%min_film
  scalars(5) = r%max_friction
  scalars(6) = merge(1.0_dp, 0.0_dp, r%converged)
  scalars(7) = r%cycles_run
  scalars(8) = r%cycle_change
  scalars(9) = composite_sigma(c)
  scalars(10) = real(t1 - t0, dp) / real(rate, dp)
  scalars(11) = r%evaluations
  scalars(12) = merge(1.0_dp, 0.0_dp, r%periodic)
  scalars(13) = r%reynolds_solves
  scalars(14) = r%cycles_computed
end subroutine rl_run_deck

!> Greenwood-Tripp functions at the given lambdas ('exact' unless `fit` is nonzero).
subroutine rl_greenwood_tripp(n, lam, f2, f52, fit)
  use, intrinsic :: iso_c_binding, only: c_int, c_double
  use ringlube_greenwood_tripp, only: gt_init, f2_exact, f52_exact, f2_fit, f52_fit
  implicit none
  integer(c_int), intent(in) :: n, fit
  real(c_double), intent(in) :: lam(n)
  real(c_double), intent(out) :: f2(n), f52(n)
  if (fit /= 0) then
    f2 = f2_fit(lam)
    f52 = f52_fit(lam)
  else
    call gt_init()
    f2 = f2_exact(lam)
    f52 = f52_exact(lam)
  end if
end subroutine rl_greenwood_tripp
