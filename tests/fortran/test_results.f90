!> The result tables and their one map to the components of result_type: every row of
!> every table reaches its own component (a row added without its line in the map, or two
!> rows on one component, fails here), and the scalars come out in their stored units.
program test_results
  use ringlube_kinds, only: dp
  use ringlube_results, only: result_type, allocate_result, series_ptr, int_series_ptr, &
                              liner_ptr, scalar_value, n_series, n_int_series, n_liner, &
                              n_scalars, scalar_spec, series_spec, derive_results, &
                              flag_ceiling, flag_load
  use ringlube_results_summary, only: summary_text
  use ringlube_check
  implicit none
  type(result_type), target :: r
  real(dp), pointer :: p(:)
  integer, pointer :: ip(:)
  integer :: i
  integer, parameter :: m = 7
  character(len=8) :: num
  real(dp), allocatable :: v(:)
  character(len=:), allocatable :: text

  call allocate_result(r, m)
  call check(r%nsteps == m, 'nsteps')
  ! every real series: allocated with m zeros, and its own storage
  do i = 1, n_series
    write (num, '(i0)') i
    p => series_ptr(r, i)
    call check(associated(p), 'series '//trim(series_spec(i)%short)//' mapped')
    if (.not. associated(p)) cycle
    call check(size(p) == m .and. all(p == 0.0_dp), 'series '//trim(num)//' allocated, zeros')
    p = real(i, dp)
  end do
  do i = 1, n_series
    p => series_ptr(r, i)
    if (associated(p)) call check(all(p == real(i, dp)), 'series '// &
                                  trim(series_spec(i)%short)//' has its own component')
  end do
  call check(all(r%h0 == real(3, dp)) .and. all(r%crank_angle_deg == 1.0_dp), &
             'rows reach the named components')
  do i = 1, n_int_series
    ip => int_series_ptr(r, i)
    call check(associated(ip), 'integer series mapped')
    if (.not. associated(ip)) cycle
    call check(size(ip) == m .and. all(ip == 0), 'integer series allocated, zeros')
    ip = i
  end do
  call check(all(r%flags == 1) .and. all(r%film_solves == 2), 'integer series by row')
  ! the liner film: empty until a starved run sets it; then by row
  do i = 1, n_liner
    p => liner_ptr(r, i)
    call check(associated(p), 'liner row mapped')
    if (associated(p)) call check(size(p) == 0, 'liner empty')
  end do
  r%liner_z = [1.0_dp, 2.0_dp]
  r%liner_h = [3.0_dp, 4.0_dp]
  p => liner_ptr(r, 1)
  call check(all(p == [1.0_dp, 2.0_dp]), 'liner position is row 1')
  p => liner_ptr(r, 2)
  call check(all(p == [3.0_dp, 4.0_dp]), 'liner film is row 2')

  ! every scalar reaches a component (none left at the map's 0) in its stored unit
  r%energy_loss = 1.5_dp
  r%mixed_share = 2.0_dp
  r%ring_mass = 7.958e-3_dp
  r%min_film = 1e-6_dp
  r%max_friction = 3.0_dp
  r%converged = .true.
  r%periodic = .true.
  r%cycles_run = 4
  r%cycle_change = 1e-4_dp
  r%sigma = 4e-7_dp
  r%run_time = 0.5_dp
  r%total_film_solves = 11
  r%reynolds_solves = 12
  r%cycles_computed = 4.25_dp
  r%oil_to_chamber = 0.3_dp
  r%oil_balance_error = 1e-9_dp
  r%flags = [0, flag_ceiling, 0, 0, flag_load, 0, 0]   ! one step lifted off, two flagged
  r%blowby = 2.5_dp
  r%blowby_mass = 1.5_dp
  r%blowback_mass = 5.0_dp
  r%ring_lift_share = 55.0_dp
  r%flutter_events = 1
  r%gas_balance_error = 1e-15_dp
  call derive_results(r, 4000.0_dp, 4.5e-4_dp, 850.0_dp)
  call check_close(r%liner_lift_share, 100.0_dp / 7.0_dp, 1e-14_dp, &
                   'lifted share: the steps with flag 2')
  ! 1.5 J per cycle at 4000 r/min = 2000 cycles/min: 50 W; 1.5 J / 0.45 L = 3.333 kPa;
  ! 0.3 mm^3 x 850 kg/m^3 = 0.255 mg per cycle x 120000 cycles/h = 30.6 g/h
  call check_close(r%friction_power, 50.0_dp, 1e-14_dp, 'friction power = E n / 120')
  call check_close(r%fmep, 1.5_dp / 4.5e-4_dp / 1e3_dp, 1e-14_dp, 'FMEP = E / V_s in kPa')
  call check_close(r%oil_to_chamber_rate, 30.6_dp, 1e-13_dp, 'oil to the chamber in g/h')
  call check(r%flagged_steps == 2, 'flagged steps counted')
  do i = 1, n_scalars
    call check(scalar_value(r, i) /= 0.0_dp, 'scalar '//trim(scalar_spec(i)%short)//' mapped')
  end do
  do i = 1, n_scalars
    select case (trim(scalar_spec(i)%short))
    case ('ring_mass')
      call check(scalar_value(r, i) == 7.958e-3_dp * 1e3_dp, 'ring mass stored in g')
    case ('converged')
      call check(scalar_value(r, i) == 1.0_dp, 'logical as 1')
    case ('total_film_solves')
      call check(scalar_value(r, i) == 11.0_dp, 'film solves')
    end select
  end do
  ! the summary: a line per quantity with its unit, the oil only for a starved inlet
  allocate (v(n_scalars))
  do i = 1, n_scalars
    v(i) = scalar_value(r, i)
  end do
  text = summary_text(v, .true., 'title line', 'out.h5')
  call check(index(text, 'title line') == 1, 'summary title first')
  call check(index(text, '50.00 W') > 0 .and. index(text, '3.333 kPa') > 0, &
             'summary power and FMEP with units: '//text)
  call check(index(text, '30.6000 g/h') > 0 .and. index(text, 'mm^3 per cycle') > 0, &
             'summary oil in mm^3 per cycle and g/h')
  call check(index(text, '7.958 g') > 0 .and. index(text, '1.0000 um') > 0, 'mass in g, film in um')
  call check(index(text, 'out.h5') > 0, 'summary names the file')
  text = summary_text(v, .false., '', '')
  call check(index(text, 'oil to the chamber') == 0 .and. index(text, 'written') == 0 .and. &
           index(text, '  energy loss per cycle') == 1, 'no oil line, title or file when not given')
  r%converged = .false.
  do i = 1, n_scalars
    if (trim(scalar_spec(i)%short) == 'converged') &
      call check(scalar_value(r, i) == 0.0_dp, 'logical false as 0')
  end do
  call report('test_results')
end program test_results
