! ctest labels: numerics
!> Whole-cycle checks on the 4000 r/min cold case at moderate resolution: the load
!> balance holds at every step, the outputs are consistent with their definitions, and
!> the damped and safeguarded h0 updates give the same cycle to within the load
!> tolerance (the difference shrinks when the tolerance is tightened).
program test_cycle
  use ringlube_kinds, only: dp, pi
  use ringlube_error, only: error_type
  use ringlube_case, only: case_type, default_case, composite_sigma, elastic_pressure
  use ringlube_deck, only: finish_case
  use ringlube_cycle, only: solve_cycle
  use ringlube_results, only: result_type, is_true, s_h0, s_gas_pressure, s_applied_load, &
                              s_hydrodynamic_load, s_asperity_load, s_friction, s_power_loss, &
                              s_sliding_speed, s_lambda_min, si_flags, si_film_solves, &
                              sc_converged, sc_energy_loss, sc_mixed_share
  use, intrinsic :: ieee_arithmetic, only: ieee_is_finite
  use ringlube_check
  implicit none
  type(result_type) :: rs, rd, rs5, rd5
  real(dp) :: dh, dh5, de, de5

  call run('safeguarded', 1e-3_dp, rs)
  call run('damped', 1e-3_dp, rd)
  call consistency(rs, 'safeguarded')
  call consistency(rd, 'damped')
  dh = maxval(abs(rs%series(:, s_h0) - rd%series(:, s_h0)) / rs%series(:, s_h0))
  de = abs(energy(rs) - energy(rd)) / energy(rs)
  write (*, '(a, 2es10.2)') 'load_tol 1e-3: max rel h0 difference, rel energy difference ', dh, de
  call check(dh <= 5e-3_dp, 'damped vs safeguarded: h0 within 5 load_tol at every step')
  call check(de <= 2e-3_dp, 'damped vs safeguarded: energy within 2 load_tol')
  call check(abs(rs%scalars(sc_mixed_share) - rd%scalars(sc_mixed_share)) &
             <= 100.0_dp * 2 / rs%nsteps + 1e-12_dp, &
             'damped vs safeguarded: mixed share within two crank steps')

  call run('safeguarded', 1e-5_dp, rs5)
  call run('damped', 1e-5_dp, rd5)
  dh5 = maxval(abs(rs5%series(:, s_h0) - rd5%series(:, s_h0)) / rs5%series(:, s_h0))
  de5 = abs(energy(rs5) - energy(rd5)) / energy(rs5)
  write (*, '(a, 2es10.2)') 'load_tol 1e-5: max rel h0 difference, rel energy difference ', dh5, de5
  call check(dh5 <= 5e-5_dp .and. dh5 < 0.1_dp * dh, 'h0 difference shrinks with load_tol')
  call check(de5 <= 2e-5_dp, 'energy difference shrinks with load_tol')
  write (*, '(a, 2i8)') 'film solves per cycle, safeguarded / damped: ', &
    sum(rs%int_series(:, si_film_solves)), sum(rd%int_series(:, si_film_solves))
  call report('test_cycle')

contains

  subroutine run(update, tol, res)
    character(len=*), intent(in) :: update
    real(dp), intent(in) :: tol
    type(result_type), intent(out) :: res
    type(case_type) :: c
    type(error_type), allocatable :: err
    c = default_case()
    c%nodes = 101
    c%dpsi_deg = 1.0_dp
    c%load_tol = tol
    c%h0_update = update
    c%pressure_file = 'inputs/pressure/crf450r_4000rpm_full.csv'
    call finish_case(c, err)
    call check(.not. allocated(err), 'case accepted')
    if (allocated(err)) then
      write (*, '(a)') err%message
      call report('test_cycle')
    end if
    call solve_cycle(c, res, err)
    call check(.not. allocated(err), 'solve_cycle without error ('//update//')')
    call check(is_true(res, sc_converged), 'cycle converged ('//update//')')
  end subroutine run

  subroutine consistency(res, what)
    type(result_type), intent(in) :: res
    character(len=*), intent(in) :: what
    type(case_type) :: c
    real(dp) :: load(res%nsteps), sigma, dt
    associate (h0 => res%series(:, s_h0), gas_pressure => res%series(:, s_gas_pressure), &
               applied_load => res%series(:, s_applied_load), &
               hydrodynamic_load => res%series(:, s_hydrodynamic_load), &
               asperity_load => res%series(:, s_asperity_load), &
               friction => res%series(:, s_friction), power_loss => res%series(:, s_power_loss), &
               sliding_speed => res%series(:, s_sliding_speed), &
               lambda_min => res%series(:, s_lambda_min), flags => res%int_series(:, si_flags))
      c = default_case()
      sigma = composite_sigma(c)
      load = (elastic_pressure(c) + gas_pressure) * c%width * 2 * pi * c%bore_radius
      call check(maxval(abs(load - applied_load) / load) < 1e-12_dp, &
                 what//': applied load = (p_e + p_gas) b 2 pi r0')
      call check(all(abs(hydrodynamic_load + asperity_load - applied_load) &
                     <= c%load_tol * applied_load * (1 + 1e-9_dp)), &
                 what//': load balanced at every step')
      call check(all(flags == 0), what//': no flagged step')
      call check(all(h0 > 0.0_dp) .and. all(ieee_is_finite(friction)), &
                 what//': h0 > 0, friction finite')
      call check(maxval(abs(power_loss - abs(friction * sliding_speed))) < 1e-9_dp, &
                 what//': P = |f U|')
      dt = 1.0_dp * pi / 180.0_dp / (c%speed_rpm * 2 * pi / 60.0_dp)  ! run() uses 1 deg steps
      call check_close(energy(res), sum(power_loss) * dt, 1e-12_dp, what//': E = sum P dt')
      ! the share interpolates lambda between steps: it differs from the count of steps
      ! with h0 < 4 sigma by less than one step per crossing of 4 sigma
      call check(abs(res%scalars(sc_mixed_share) - 100.0_dp * count(h0 < 4 * sigma) / res%nsteps) &
                 <= 100.0_dp * count((h0 < 4 * sigma) .neqv. (cshift(h0, 1) < 4 * sigma)) &
                 / res%nsteps, what//': mixed share from h0 < 4 sigma, within a step per crossing')
      ! the crown minimum lies inside the face: min h is h0 up to the node spacing
      call check(all(lambda_min >= h0 / sigma * (1 - 1e-12_dp)) .and. &
                 all(lambda_min <= (h0 + c%crown_height * (c%width / 100 / c%width)**2) &
                     / sigma), &
                 what//': h0/sigma <= lambda_min <= (h0 + S(dx/2))/sigma')
      ! friction opposes the motion on average over every stroke
      call check(sum(friction * sliding_speed) < 0.0_dp, what//': friction dissipates')
    end associate
  end subroutine consistency

  !> The energy loss per cycle of a result [J].
  real(dp) function energy(res)
    type(result_type), intent(in) :: res
    energy = res%scalars(sc_energy_loss)
  end function energy
end program test_cycle
