!> Benchmark and reference numbers of the ring pack's gas network (not a test): the periodic
!> cycle with the shipped 4000 r/min full-load trace at 4000 and 12,000 r/min, friction 0, 10
!> and 20 N, crank step 0.5 deg (or the argument); prints the cycle quantities of
!> docs/ring_pack.md and the CPU time per cycle. Run from the source folder:
!> `build/bench_ring_pack [DPSI_DEG [PRESSURE_RTOL [GROW_SHARE]]]` (PRESSURE_RTOL also sets travel_fraction
!> to 10 times it; 1 or more: no sub-steps; 0: the defaults; GROW_SHARE: ring_pack_params grow_share).
program bench_ring_pack
  use ringlube_kinds, only: dp, pi
  use ringlube_error, only: error_type
  use ringlube_case, only: case_type, default_case
  use ringlube_gas, only: read_pressure_csv, gas_pressure
  use ringlube_kinematics, only: sliding_speed, piston_acceleration, deg2rad
  use ringlube_ring_pack
  use ringlube_ring_pack_cycle
  implicit none
  type(case_type) :: c
  type(ring_pack_params) :: par
  type(ring_pack_state) :: st
  type(ring_pack_cycle_out) :: cyc
  type(error_type), allocatable :: err
  real(dp), allocatable :: tpsi(:), tp(:), p1(:), ap(:), ff(:)
  real(dp) :: rpm, w, dpsi, fr, t0, t1, charge, u, rtol, grow
  integer :: k, n, i, j
  character(len=32) :: arg
  character(len=*), parameter :: fmt = '(f7.0, f5.0, f14.3, f10.3, f9.3, f13.3, f7.2, '// &
                                 'f10.2, i9, f13.3, f8.1, i10, f10.2, es9.1)'

  c = default_case()
  call read_pressure_csv('inputs/pressure/crf450r_4000rpm_full.csv', tpsi, tp, err)
  if (allocated(err)) error stop 'run from the source folder (inputs/pressure/...)'
  dpsi = 0.5_dp
  rtol = -1
  if (command_argument_count() >= 1) then
    call get_command_argument(1, arg)
    read (arg, *) dpsi
  end if
  if (command_argument_count() >= 2) then
    call get_command_argument(2, arg)
    read (arg, *) rtol
  end if
  grow = -1
  if (command_argument_count() >= 3) then
    call get_command_argument(3, arg)
    read (arg, *) grow
  end if
  n = nint(720 / dpsi)
  allocate (p1(0:n - 1), ap(0:n - 1), ff(0:n - 1))
  ! the charge: swept volume at 0.1 MPa and 300 K [mg]
  charge = 1e5_dp * (pi * c%bore_radius**2 * 2 * c%crank_radius) / (287 * 300) * 1e6_dp
  print '(a, f8.1)', 'charge mg (swept volume, 0.1 MPa, 300 K): ', charge
  print '(a)', '  r/min  F_f  blowby_L/min  mg/cycle  %charge  blowback_mg  lift%  '// &
    'against%  flutter  p3max/p1max  at_deg  substeps  ms/cycle  balance'
  do j = 0, 2
    do i = 1, 2
      rpm = merge(4000.0_dp, 12000.0_dp, i == 1)
      fr = 10.0_dp * j
      par = ring_pack_params_from_case(c)
      if (rtol > 0) par%pressure_rtol = rtol
      if (rtol > 0) par%travel_fraction = 10 * rtol
      if (rtol >= 1) par%adaptive = .false.
      if (grow > 0) par%grow_share = grow
      w = rpm * 2 * pi / 60
      do k = 0, n - 1
        p1(k) = gas_pressure(tpsi, tp, k * dpsi, c%crankcase_pressure)
        ap(k) = -piston_acceleration(deg2rad(k * dpsi), c%crank_radius, c%conrod_length, w)
        u = sliding_speed(deg2rad(k * dpsi), c%crank_radius, c%conrod_length, w)
        ff(k) = fr * tanh(u / 0.1_dp)
      end do
      st%p2 = 0
      call cpu_time(t0)
      call ring_pack_cycle(par, p1, ap, ff, dpsi, rpm, c%crankcase_pressure, st, cyc, err, &
                           max_cycles=400, tol=1e-9_dp)
      call cpu_time(t1)
      if (allocated(err)) error stop 'ring_pack_cycle failed'
      print fmt, rpm, fr, cyc%blowby_l_min, cyc%blowby_mg_per_cycle, &
        cyc%blowby_mg_per_cycle / charge * 100, cyc%blowback_mg_per_cycle, &
        cyc%ring_lift_share_pct, cyc%lift_against_gas_pct, cyc%flutter_events, &
        maxval(cyc%p3) / maxval(p1), maxloc(cyc%p3, 1) * dpsi, cyc%substeps, &
        (t1 - t0) / cyc%cycles_run * 1e3_dp, cyc%gas_balance_error
    end do
  end do
end program bench_ring_pack
