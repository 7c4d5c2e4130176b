! ctest labels: unit
!> The result tables and the result stored by their rows: names unique in each table (the
!> kernel's index constants are found by name), kinds the writers know, storage of every
!> row, the derived results, the logical convention and the summary.
program test_results
  use ringlube_kinds, only: dp
  use ringlube_results, only: result_type, field_spec, allocate_result, allocate_liner, &
                              n_series, n_int_series, n_liner, n_scalars, series_spec, &
                              int_series_spec, scalar_spec, liner_spec, derive_results, truth, &
                              is_true, produced, produced_models, flag_ceiling, flag_load, &
                              s_crank_angle_deg, s_h0, s_second_gap_flow, si_flags, &
                              si_film_solves, sc_energy_loss, sc_ring_mass, sc_converged, &
                              sc_oil_to_chamber, sc_friction_power, sc_fmep, sc_fmep_bar, &
                              sc_displacement, sc_engine_friction_power, &
                              sc_oil_to_chamber_rate, sc_flagged_steps, sc_liner_lift_share, &
                              sc_blowby, sc_min_film, l_liner_position, l_liner_oil_film, &
                              models, m_jfo, m_gas, sc_lift_margin, sc_lift_margin_angle, &
                              sc_seal_margin, sc_seal_margin_angle, sc_margin_film_solves, &
                              margin_thresholds
  use ringlube_results_summary, only: summary_text
  use ringlube_check
  implicit none
  type(result_type) :: r
  integer :: i
  integer, parameter :: m = 7
  logical :: made(n_scalars)
  character(len=:), allocatable :: text

  call names_unique(series_spec, 'series')
  call names_unique(int_series_spec, 'int_series')
  call names_unique(scalar_spec, 'scalars')
  call names_unique(liner_spec, 'liner')
  call check(all(series_spec%kind == 'real') .and. all(liner_spec%kind == 'real'), &
             'real series and liner rows are real')
  call check(all(int_series_spec%kind == 'integer'), 'integer series rows are integer')
  do i = 1, n_scalars
    call check(any(scalar_spec(i)%kind == [character(len=8) :: 'real', 'integer', 'logical']), &
               'scalar '//trim(scalar_spec(i)%short)//': a kind the writers know')
  end do
  ! the index constants are the rows of their names (found by name when compiling)
  call check(series_spec(s_crank_angle_deg)%short == 'crank_angle_deg' .and. s_crank_angle_deg &
             == 1, 'the crank angle, the dimension scale, is the first series')
  call check(series_spec(s_h0)%short == 'h0' .and. &
             series_spec(s_second_gap_flow)%short == 'second_gap_flow', 'series rows')
  call check(int_series_spec(si_flags)%short == 'flags' .and. &
             int_series_spec(si_film_solves)%short == 'film_solves', 'integer series rows')
  call check(scalar_spec(sc_ring_mass)%short == 'ring_mass' .and. &
             scalar_spec(sc_ring_mass)%unit == 'g', 'scalar rows, the ring mass in g')
  call check(liner_spec(l_liner_position)%short == 'liner_position' .and. l_liner_position == 1 &
             .and. liner_spec(l_liner_oil_film)%short == 'liner_oil_film', &
             'liner rows, the position (the scale) first')
  call check(scalar_spec(sc_converged)%kind == 'logical', 'converged is a logical')
  call requires_models(series_spec)
  call requires_models(int_series_spec)
  call requires_models(scalar_spec)
  call requires_models(liner_spec)

  ! storage: one column a row, m zeros; an empty liner film until a starved run sets it
  call allocate_result(r, m)
  call check(r%nsteps == m, 'nsteps')
  call check(all(shape(r%series) == [m, n_series]) .and. all(r%series == 0.0_dp), &
             'real series: m x n_series zeros')
  call check(all(shape(r%int_series) == [m, n_int_series]) .and. all(r%int_series == 0), &
             'integer series: m x n_int_series zeros')
  call check(all(shape(r%liner) == [0, n_liner]), 'liner film empty')
  call allocate_liner(r, 3)
  call check(all(shape(r%liner) == [3, n_liner]) .and. all(r%liner == 0.0_dp), &
             'liner film: cells x n_liner zeros')
  call check(all(r%scalars == 0.0_dp) .and. size(r%scalars) == n_scalars, 'scalars zero')

  ! the logical convention: 1 true, 0 false
  call check(truth(.true.) == 1.0_dp .and. truth(.false.) == 0.0_dp, 'truth: 1 or 0')
  r%scalars(sc_converged) = truth(.true.)
  call check(is_true(r, sc_converged), 'is_true of 1')
  r%scalars(sc_converged) = truth(.false.)
  call check(.not. is_true(r, sc_converged), 'is_true of 0')

  ! the models a run produced
  call check(produced(r, '') .and. .not. produced(r, 'starved'), 'produced: always, not starved')
  call check(produced_models(r) == '', 'no optional results')
  r%made(m_jfo) = .true.
  r%made(m_gas) = .true.
  call check(produced_models(r) == 'jfo gas', 'models named: '//produced_models(r))

  ! the derived results
  r%scalars(sc_energy_loss) = 1.5_dp
  r%scalars(sc_oil_to_chamber) = 0.3_dp
  r%scalars(sc_ring_mass) = 7.958_dp
  r%scalars(sc_min_film) = 1e-6_dp
  r%int_series(:, si_flags) = [0, flag_ceiling, 0, 0, flag_load, 0, 0]  ! one lifted, two flagged
  call derive_results(r, 4000.0_dp, 4.5e-4_dp, 850.0_dp)
  call check_close(r%scalars(sc_liner_lift_share), 100.0_dp / 7.0_dp, 1e-14_dp, &
                   'lifted share: the steps with flag 2')
  ! 1.5 J per cycle at 4000 r/min = 2000 cycles/min: 50 W; 1.5 J / 0.45 L = 3.333 kPa;
  ! 0.3 mm^3 x 850 kg/m^3 = 0.255 mg per cycle x 120000 cycles/h = 30.6 g/h
  call check_close(r%scalars(sc_friction_power), 50.0_dp, 1e-14_dp, 'friction power = E n / 120')
  call check_close(r%scalars(sc_fmep), 1.5_dp / 4.5e-4_dp / 1e3_dp, 1e-14_dp, &
                   'FMEP = E / V_s in kPa')
  call check_close(r%scalars(sc_oil_to_chamber_rate), 30.6_dp, 1e-13_dp, &
                   'oil to the chamber in g/h')
  call check(r%scalars(sc_flagged_steps) == 2.0_dp, 'flagged steps counted')
  call check_close(r%scalars(sc_fmep_bar), 1.5_dp / 4.5e-4_dp / 1e5_dp, 1e-14_dp, 'FMEP in bar')
  call check_close(r%scalars(sc_displacement), 0.45_dp, 1e-14_dp, 'one cylinder: 0.45 L')
  call check(r%scalars(sc_engine_friction_power) == r%scalars(sc_friction_power), &
             'one cylinder: the engine is the ring')
  ! four cylinders: 1.8 L, 200 W; FMEP x displacement x cycles per second = friction power
  call derive_results(r, 4000.0_dp, 4.5e-4_dp, 850.0_dp, 4)
  call check_close(r%scalars(sc_displacement), 1.8_dp, 1e-14_dp, 'four cylinders: 1.8 L')
  call check_close(r%scalars(sc_engine_friction_power), 200.0_dp, 1e-14_dp, 'engine: 4 x 50 W')
  call check_close(r%scalars(sc_fmep) * 1e3_dp * r%scalars(sc_displacement) * 1e-3_dp &
                   * 4000.0_dp / 120.0_dp, r%scalars(sc_engine_friction_power), 1e-14_dp, &
                   'FMEP x displacement x cycles per second = friction power')

  ! the summary: a line per quantity with its unit, the oil only when the run made it
  made = .true.
  text = summary_text(r%scalars, made, 'title line', 'out.h5')
  call check(index(text, 'title line') == 1, 'summary title first')
  call check(index(text, '50.00 W') > 0 .and. index(text, '3.333 kPa') > 0, &
             'summary power and FMEP with units: '//text)
  call check(index(text, '30.6000 g/h') > 0 .and. index(text, 'mm^3 per cycle') > 0, &
             'summary oil in mm^3 per cycle and g/h')
  call check(index(text, '7.958 g') > 0 .and. index(text, '1.0000 um') > 0, &
             'mass in g, film in um')
  call check(index(text, 'blowby') > 0, 'summary blowby when made')
  call check(index(text, 'out.h5') > 0, 'summary names the file')
  made(sc_oil_to_chamber) = .false.
  made(sc_blowby) = .false.
  text = summary_text(r%scalars, made, '', '')
  call check(index(text, 'oil to the chamber') == 0 .and. index(text, 'blowby') == 0 .and. &
             index(text, 'written') == 0 .and. index(text, '  energy loss per cycle') == 1, &
             'no oil or blowby line, title or file when not made or given')
  call branch_risk()
  call report('test_results')

contains

  !> The run's margins from its steps' (margin_results, called by derive_results): the least
  !> lift-off margin measured; of the seal margin, each stretch of decision steps ends in a
  !> state whose margin is its value nearest 0 since the last change, and the run's is the
  !> least of the stretches' (a stretch may run over the cycle's end); the summary warns below
  !> the thresholds.
  subroutine branch_risk()
    type(result_type) :: q
    real(dp), parameter :: no = huge(1.0_dp)
    logical :: mk(n_scalars)
    character(len=:), allocatable :: txt
    call allocate_result(q, 8)
    q%series(:, s_crank_angle_deg) = [(90.0_dp * i, i=0, 7)]
    call derive_results(q, 4000.0_dp, 4.5e-4_dp, 850.0_dp)
    call check(q%scalars(sc_lift_margin) == 1.0_dp .and. q%scalars(sc_seal_margin) == 1.0_dp, &
               'nothing measured: margins 1')
    q%step_margins(:, 1) = [0.3_dp, -0.02_dp, 0.01_dp, no, no, no, no, no]
    q%step_margins(:, 3) = [1, 1, 1, 0, 0, 0, 0, 0]
    ! two stretches: steps 2-3, blown -0.05 then sealed 0.5 (ends sealed at 0.5), and steps
    ! 6-8, sealed 0.2, 0.05 then blown -0.1 (ends blown at -0.1): the run's, the least, -0.1
    q%step_margins(:, 2) = [no, -0.05_dp, 0.5_dp, no, no, 0.2_dp, 0.05_dp, -0.1_dp]
    call derive_results(q, 4000.0_dp, 4.5e-4_dp, 850.0_dp)
    call check(q%scalars(sc_lift_margin) == -0.02_dp .and. &
               q%scalars(sc_lift_margin_angle) == 90.0_dp, 'lift margin: the least, its angle')
    call check(q%scalars(sc_margin_film_solves) == 3.0_dp, 'film solves for the margins summed')
    call check(q%scalars(sc_seal_margin) == -0.1_dp .and. &
               q%scalars(sc_seal_margin_angle) == 630.0_dp, &
               'seal margin: the least of the stretches'' final states, -0.1 at 630 deg')
    q%step_margins(2:3, 2) = [-0.05_dp, 0.01_dp]
    call derive_results(q, 4000.0_dp, 4.5e-4_dp, 850.0_dp)
    call check(q%scalars(sc_seal_margin) == -0.1_dp, &
               'a stretch ending sealed at 0.01 does not hide one ending blown')
    ! one stretch over the cycle's end (steps 6, 7, 8, 1): sealed 0.2, 0.05, then blown -0.1,
    ! -0.3: ends blown, its margin -0.1 (the blown step nearest 0)
    q%step_margins(:, 2) = [-0.3_dp, no, no, no, no, 0.2_dp, 0.05_dp, -0.1_dp]
    call derive_results(q, 4000.0_dp, 4.5e-4_dp, 850.0_dp)
    call check(q%scalars(sc_seal_margin) == -0.1_dp .and. &
               q%scalars(sc_seal_margin_angle) == 630.0_dp, &
               'a stretch over the cycle''s end ends blown, -0.1 at 630 deg')
    q%step_margins(8, 2) = 0.07_dp
    q%step_margins(1, 2) = 0.3_dp
    call derive_results(q, 4000.0_dp, 4.5e-4_dp, 850.0_dp)
    call check(q%scalars(sc_seal_margin) == 0.05_dp .and. &
               q%scalars(sc_seal_margin_angle) == 540.0_dp, &
               'every stretch ends sealed: its weakest step since the last change, 0.05')
    q%step_margins(:, 2) = 0.2_dp
    q%step_margins(5, 2) = 0.15_dp
    call derive_results(q, 4000.0_dp, 4.5e-4_dp, 850.0_dp)
    call check(q%scalars(sc_seal_margin) == 0.15_dp, 'a decision at every step: one stretch')
    ! the summary's warnings: below the threshold only, the threshold and its reason stated
    mk = .true.
    q%scalars(sc_lift_margin) = 0.5_dp * margin_thresholds(1)%threshold
    q%scalars(sc_seal_margin) = -2.0_dp * margin_thresholds(2)%threshold
    txt = summary_text(q%scalars, mk, '', '')
    call check(index(txt, 'WARNING: lift-off margin') > 0 .and. index(txt, 'WARNING: seal') == 0 &
               .and. index(txt, trim(margin_thresholds(1)%reason)) > 0, &
               'a warning for the lift-off margin below its threshold, with its reason: '//txt)
    mk(sc_seal_margin) = .false.
    q%scalars(sc_seal_margin) = 0.0_dp
    q%scalars(sc_lift_margin) = -2.0_dp * margin_thresholds(1)%threshold
    txt = summary_text(q%scalars, mk, '', '')
    call check(index(txt, 'WARNING') == 0 .and. index(txt, 'seal margin') == 0, &
               'no warning above the thresholds, no seal margin where not made')
  end subroutine branch_risk

  !> Every short and every stored name of `spec` once.
  subroutine names_unique(spec, table)
    type(field_spec), intent(in) :: spec(:)
    character(len=*), intent(in) :: table
    integer :: k
    do k = 1, size(spec)
      call check(count(spec%short == spec(k)%short) == 1 .and. &
                 count(spec%stored == spec(k)%stored) == 1, &
                 table//': '//trim(spec(k)%short)//' named once')
    end do
  end subroutine names_unique

  !> Every row of `spec` requires no model or one of `models`.
  subroutine requires_models(spec)
    type(field_spec), intent(in) :: spec(:)
    integer :: k
    do k = 1, size(spec)
      call check(spec(k)%requires == '' .or. any(models%name == spec(k)%requires), &
                 trim(spec(k)%short)//': requires a known model')
    end do
  end subroutine requires_models
end program test_results
