!> The summary of a run printed by `ringlube-solve`, `ringlube run` and
!> `CycleResult.summary()`, from the scalars of ringlube_results.
module ringlube_results_summary
  use ringlube_kinds, only: dp
  use ringlube_inputs, only: inputs, find_input
  use ringlube_results, only: n_scalars, sc_energy_loss, sc_friction_power, sc_fmep, &
                              sc_fmep_bar, sc_displacement, sc_engine_friction_power, &
                              sc_flutter_margin, sc_flutter_margin_ratio, &
                              sc_peak_groove_pressure, sc_peak_groove_angle, &
                              sc_peak_land_pressure, sc_peak_land_angle, &
                              sc_mixed_share, sc_oil_to_chamber, sc_oil_to_chamber_rate, &
                              sc_liner_lift_share, sc_blowby, sc_blowby_mass, sc_ring_lift_share, &
                              sc_flutter_events, sc_ring_mass, sc_min_film, sc_max_friction, &
                              sc_cycles_run, sc_cycle_change, sc_flagged_steps, sc_converged, &
                              sc_run_time, sc_cycles_computed, sc_period, sc_periodic, &
                              sc_energy_change, sc_liner_change, sc_ring_pack_change, &
                              sc_conformability, sc_light_gap_share, sc_face_leakage, &
                              sc_radial_collapse_share, sc_sector_jumps, sc_lift_margin, &
                              sc_lift_margin_angle, &
                              sc_seal_margin, sc_seal_margin_angle, margin_thresholds
  implicit none
  private
  public :: summary_text

contains

  !> The summary of a run that `ringlube-solve`, `ringlube run` and
  !> `CycleResult.summary()` print: one line per quantity with its unit, from the scalars
  !> `v` (rows and stored units of `scalar_spec`) of which the run produced those `made`
  !> (the oil with a starved inlet, blowby with the ring pack: lines shown only then);
  !> `title` (first line) and `written` (the file, last line) are left out when blank. A
  !> distorted bore's conformability per order (`orders`, `conformability`: A_k over its
  !> limit) is a table when given, else its largest value.
  function summary_text(v, made, title, written, orders, conformability) result(t)
    real(dp), intent(in) :: v(n_scalars)
    logical, intent(in) :: made(n_scalars)
    character(len=*), intent(in) :: title, written
    integer, intent(in), optional :: orders(:)
    real(dp), intent(in), optional :: conformability(:)
    character(len=:), allocatable :: t
    character(len=64) :: a
    character(len=128) :: b
    character(len=16) :: w, wl
    character(len=1), parameter :: nl = achar(10)
    integer :: i
    t = ''
    if (len_trim(title) > 0) t = trim(title)//nl
    write (a, '(f10.4)') v(sc_energy_loss)
    call line('energy loss per cycle', a, 'J')
    write (a, '(f10.2)') v(sc_friction_power)
    call line('mean friction power', a, 'W (energy per cycle x cycles per second)')
    write (a, '(f10.3)') v(sc_fmep)
    write (w, '(f12.5)') v(sc_fmep_bar)
    call line('FMEP of the ring', a, 'kPa = '//trim(adjustl(w))//' bar (energy per cycle / '// &
              'swept volume)')
    ! (the engine's cylinders: its friction power over the ring's)
    if (v(sc_engine_friction_power) > 1.5_dp * v(sc_friction_power)) then
      write (a, '(f10.2)') v(sc_engine_friction_power)
      write (w, '(i0)') nint(v(sc_engine_friction_power) / v(sc_friction_power))
      write (b, '(f8.3)') v(sc_displacement)
      call line('engine, top rings', a, 'W ('//trim(w)//' cylinders, '//trim(adjustl(b))//' L)')
    end if
    write (a, '(f10.3)') v(sc_mixed_share)
    call line('mixed/boundary share', a, '% of the cycle (h0/sigma < 4)')
    if (made(sc_oil_to_chamber)) then
      call line('oil to the chamber', num(v(sc_oil_to_chamber)), 'mm^3 per cycle = '// &
                trim(adjustl(num(v(sc_oil_to_chamber_rate))))//' g/h (oil_density)')
    end if
    write (a, '(f10.2)') v(sc_liner_lift_share)
    call line('lifted off the liner', a, '% of the cycle (h0 at h0_ceiling)')
    ! branch risk (docs/model.md, "Branch risk")
    write (a, '(f10.4)') v(sc_lift_margin)
    write (w, '(f8.1)') v(sc_lift_margin_angle)
    call line('lift-off margin', a, '(F - W at h0_ceiling) / F, the least on the intake '// &
              'stroke, at '//trim(adjustl(w))//' deg (< 0: can lift off)')
    if (made(sc_seal_margin)) then
      write (a, '(f10.4)') v(sc_seal_margin)
      write (w, '(f8.1)') v(sc_seal_margin_angle)
      call line('seal margin', a, 'the least over the trailing gas''s decisions, at '// &
                trim(adjustl(w))//' deg (> 0: the face ends them sealed, <= 0: blown)')
    end if
    call risk(sc_lift_margin, 'lift-off margin', 'whether the ring lifts off the liner on '// &
              'the intake stroke')
    if (made(sc_seal_margin)) call risk(sc_seal_margin, 'seal margin', 'whether the face '// &
                                        'seals or blows where the trailing gas is above the '// &
                                        'leading edge''s')
    if (made(sc_blowby)) then
      write (a, '(f10.3)') v(sc_blowby)
      write (b, '(f8.2)') v(sc_blowby_mass)
      call line('blowby', a, 'L/min ('//trim(adjustl(b))//' mg per cycle)')
      write (a, '(f10.2)') v(sc_ring_lift_share)
      ! (whole but for the mean of a period of several cycles)
      write (b, '(f8.1)') v(sc_flutter_events)
      if (v(sc_flutter_events) == anint(v(sc_flutter_events))) &
        write (b, '(i8)') nint(v(sc_flutter_events))
      call line('ring lift in its groove', a, '% of the cycle ('//trim(adjustl(b))// &
                ' flutter events)')
      write (a, '(f10.2)') v(sc_flutter_margin)
      write (b, '(f8.3)') v(sc_flutter_margin_ratio)
      call line('flutter margin', a, 'N ('//trim(adjustl(b))//' x peak inertia; < 0: '// &
                'lifts against the gas)')
      write (a, '(f10.3)') v(sc_peak_groove_pressure) * 1e-5_dp
      write (w, '(f6.1)') v(sc_peak_groove_angle)
      write (b, '(f8.3)') v(sc_peak_land_pressure) * 1e-5_dp
      write (wl, '(f6.1)') v(sc_peak_land_angle)
      call line('peak groove pressure', a, 'bar at '//trim(adjustl(w))//' deg (land '// &
                trim(adjustl(b))//' bar at '//trim(adjustl(wl))//' deg)')
    end if
    if (made(sc_conformability)) then
      if (present(orders) .and. present(conformability)) then
        b = ''
        do i = 1, size(orders)
          write (w, '(f10.2)') conformability(i)
          write (a, '(a, i0, a)') 'k=', orders(i), ': '
          ! (', ' with its blank: trim(b)//', ' would drop it)
          if (i > 1) then
            b = trim(b)//', '//trim(a)//' '//trim(adjustl(w))
          else
            b = trim(a)//' '//trim(adjustl(w))
          end if
        end do
        write (a, '(f10.2)') v(sc_conformability)
call line('conformability', a, 'A_k / limit, the largest ('//trim(b)//'; > 1 does not conform dry)')
      else
        write (a, '(f10.2)') v(sc_conformability)
        call line('conformability', a, 'A_k / limit, the largest (> 1 does not conform dry)')
      end if
      write (a, '(f10.2)') v(sc_light_gap_share)
      call line('light gaps', a, '% of sector-steps (film carries < 1 % of the mean load)')
      write (a, '(f10.4)') v(sc_face_leakage)
      call line('face leakage', a, 'mg per cycle (gas through the faces, towards the crankcase)')
      write (a, '(f10.2)') v(sc_radial_collapse_share)
      call line('radial collapse', a, '% of the cycle (pushed off the liner: back_clearance)')
      write (a, '(f10.1)') v(sc_sector_jumps)
      call line('sector jumps', a, 'crank steps at which a sector''s h0 jumps by > 22 % '// &
                'against the ring''s (its film changed state: the answer hangs on the history)')
    end if
    write (a, '(f10.3)') v(sc_ring_mass)
    call line('ring mass', a, 'g')
    write (a, '(f10.4)') v(sc_min_film) * 1e6_dp
    call line('minimum film', a, 'um')
    write (a, '(f10.3)') v(sc_max_friction)
    call line('peak friction', a, 'N')
    write (a, '(i10)') nint(v(sc_cycles_run))
    ! what the test of a period of one compares with cycle_tol (starved: the liner film, else
    ! h0; the energy; and the ring pack): each one's last change / (1 - its contraction)
    if (made(sc_liner_change)) then
      b = 'liner film '//e(v(sc_liner_change))//', energy '//e(v(sc_energy_change))
    else
      b = 'h0 '//e(v(sc_cycle_change))//', energy '//e(v(sc_energy_change))
    end if
    if (made(sc_ring_pack_change)) b = trim(b)//', ring pack '//e(v(sc_ring_pack_change))
    if (nint(v(sc_period)) >= 2) then
      write (w, '(i0)') nint(v(sc_period))
      call line('cycles run', a, '  (change over the period of '//trim(w)//' cycles: '// &
                trim(b)//')')
    else
      call line('cycles run', a, '  (last cycle''s change: '//trim(b)//')')
    end if
    write (a, '(i10)') nint(v(sc_flagged_steps))
    ! the reported cycle's; with a period of 2 or more the period's other cycles may have some
    if (nint(v(sc_period)) >= 2) then
      call line('flagged crank steps', a, '(the last cycle''s; see /cycle/flags)')
    else
      call line('flagged crank steps', a, '(see /cycle/flags)')
    end if
    b = ''
    if (nint(v(sc_period)) >= 2) write (b, '(a, i0, a)') '(a period of ', nint(v(sc_period)), &
      ' cycles: energy, shares, blowby are means)'
    ! not periodic: a state may repeat after more cycles than were run (docs/model.md)
    if (v(sc_periodic) == 0.0_dp) b = '(no period of 1-12 cycles yet: a period p needs 2p + 1 '// &
                                      'cycles; try a larger max_cycles)'
    ! (max_cycles at the most it may be: only a looser cycle_tol is left)
    if (v(sc_periodic) == 0.0_dp .and. v(sc_cycles_run) >= &
        inputs(find_input('numerics', 'max_cycles'))%upper) then
      write (w, '(i0)') nint(v(sc_cycles_run))
      b = '(no period of 1-12 cycles in '//trim(w)//' cycles, the most max_cycles allows: '// &
          'loosen cycle_tol, or the state may never repeat)'
    end if
    if (v(sc_periodic) /= 0.0_dp .and. v(sc_converged) == 0.0_dp) &
      b = trim(b)//' (a step is flagged in the period''s cycles)'
    call line('converged', merge('       yes', '        no', v(sc_converged) /= 0.0_dp), trim(b))
    write (a, '(f10.3)') v(sc_run_time)
    write (b, '(f8.1)') 1e3_dp * v(sc_run_time) / max(v(sc_cycles_computed), tiny(1.0_dp))
    call line('run time', a, 's ('//trim(adjustl(b))//' ms per cycle; '// &
              trim(adjustl(fixed(v(sc_cycles_computed))))//' cycles incl. warm-up)')
    if (len_trim(written) > 0) call line('written', trim(written), '')
  contains
    !> A warning line when the margin in column i is below its threshold (margin_thresholds).
    subroutine risk(i, label, what)
      integer, intent(in) :: i
      character(len=*), intent(in) :: label, what
      integer :: j
      character(len=16) :: th, val
      j = findloc(margin_thresholds%name, label_of(i), dim=1)
      if (j == 0) return
      if (.not. abs(v(i)) < margin_thresholds(j)%threshold) return
      write (th, '(f8.3)') margin_thresholds(j)%threshold
      write (val, '(f9.4)') v(i)
      t = t//'  WARNING: '//label//' '//trim(adjustl(val))//' is below its threshold '//trim(adjustl(th))// &
          ': '//what//' may change with a small change of the inputs or the numerics ('// &
          trim(margin_thresholds(j)%reason)//'; docs/model.md, "Branch risk")'//nl
    end subroutine risk
    function label_of(i) result(s)
      integer, intent(in) :: i
      character(len=24) :: s
      s = 'lift_margin'
      if (i == sc_seal_margin) s = 'seal_margin'
    end function label_of
    subroutine line(label, value, unit)
      character(len=*), intent(in) :: label, value, unit
      character(len=24) :: l
      l = label
      t = t//'  '//l//trim(value)
      if (len_trim(unit) > 0) t = t//' '//trim(unit)
      t = t//nl
    end subroutine line
    !> es9.2 without blanks
    function e(y) result(s)
      real(dp), intent(in) :: y
      character(len=:), allocatable :: s
      character(len=16) :: w
      write (w, '(es9.2)') y
      s = trim(adjustl(w))
    end function e
    !> f10.4 where that shows four significant digits, else es10.3
    function num(y) result(s)
      real(dp), intent(in) :: y
      character(len=16) :: s
      if (y == 0.0_dp .or. (abs(y) >= 1e-1_dp .and. abs(y) < 1e5_dp)) then
        write (s, '(f10.4)') y
      else
        write (s, '(es10.3)') y
      end if
    end function num
    function fixed(y) result(s)
      real(dp), intent(in) :: y
      character(len=16) :: s
      write (s, '(f8.2)') y
    end function fixed
  end function summary_text
end module ringlube_results_summary
