!> The summary of a run printed by `ringlube-solve`, `ringlube run` and
!> `CycleResult.summary()`, from the scalars of ringlube_results.
module ringlube_results_summary
  use ringlube_kinds, only: dp
  use ringlube_results, only: n_scalars, scalar_spec
  implicit none
  private
  public :: summary_text

contains

  !> The summary of a run that `ringlube-solve`, `ringlube run` and
  !> `CycleResult.summary()` print: one line per quantity with its unit, from the scalars
  !> `v` (order and stored units of `scalar_spec`). The oil line needs a starved inlet
  !> (`has_starved`); `title` (first line) and `written`
  !> (the file, last line) are left out when blank.
  function summary_text(v, has_starved, title, written, has_ring_pack) result(t)
    real(dp), intent(in) :: v(:)
    logical, intent(in) :: has_starved
    logical, intent(in), optional :: has_ring_pack
    character(len=*), intent(in) :: title, written
    character(len=:), allocatable :: t
    character(len=64) :: a, b
    character(len=1), parameter :: nl = achar(10)
    t = ''
    if (len_trim(title) > 0) t = trim(title)//nl
    write (a, '(f10.4)') x('energy_loss')
    call line('energy loss per cycle', a, 'J')
    write (a, '(f10.2)') x('friction_power')
    call line('mean friction power', a, 'W (energy per cycle x cycles per second)')
    write (a, '(f10.3)') x('fmep')
    call line('FMEP of the ring', a, 'kPa (energy per cycle / swept volume)')
    write (a, '(f10.3)') x('mixed_share')
    call line('mixed/boundary share', a, '% of the cycle (h0/sigma < 4)')
    if (has_starved) then
      call line('oil to the chamber', num(x('oil_to_chamber')), 'mm^3 per cycle = '// &
                trim(adjustl(num(x('oil_to_chamber_rate'))))//' g/h (oil_density)')
    end if
    write (a, '(f10.2)') x('liner_lift_share')
    call line('lifted off the liner', a, '% of the cycle (h0 at h0_ceiling)')
    if (present(has_ring_pack)) then
      if (has_ring_pack) then
        write (a, '(f10.3)') x('blowby')
        write (b, '(f8.2)') x('blowby_mass')
        call line('blowby', a, 'L/min ('//trim(adjustl(b))//' mg per cycle)')
        write (a, '(f10.2)') x('ring_lift_share')
        write (b, '(i8)') nint(x('flutter_events'))
        call line('ring lift in its groove', a, '% of the cycle ('//trim(adjustl(b))// &
                  ' flutter events)')
      end if
    end if
    write (a, '(f10.3)') x('ring_mass')
    call line('ring mass', a, 'g')
    write (a, '(f10.4)') x('min_film') * 1e6_dp
    call line('minimum film', a, 'um')
    write (a, '(f10.3)') x('max_friction')
    call line('peak friction', a, 'N')
    write (a, '(i10)') nint(x('cycles_run'))
    write (b, '(es9.2)') x('cycle_change')
    call line('cycles run', a, '  (last cycle change in h0: '//trim(adjustl(b))//')')
    write (a, '(i10)') nint(x('flagged_steps'))
    call line('flagged crank steps', a, '(see /cycle/flags)')
    call line('converged', merge('       yes', '        no', x('converged') > 0.5_dp), '')
    write (a, '(f10.3)') x('run_time')
    write (b, '(f8.1)') 1e3_dp * x('run_time') / max(x('cycles_computed'), tiny(1.0_dp))
    call line('run time', a, 's ('//trim(adjustl(b))//' ms per cycle; '// &
              trim(adjustl(fixed(x('cycles_computed'))))//' cycles incl. warm-up)')
    if (len_trim(written) > 0) call line('written', trim(written), '')
  contains
    real(dp) function x(name)
      character(len=*), intent(in) :: name
      integer :: i
      x = 0.0_dp
      do i = 1, min(size(v), n_scalars)
        if (trim(scalar_spec(i)%short) == name) x = v(i)
      end do
    end function x
    subroutine line(label, value, unit)
      character(len=*), intent(in) :: label, value, unit
      character(len=24) :: l
      l = label
      t = t//'  '//l//trim(value)
      if (len_trim(unit) > 0) t = t//' '//trim(unit)
      t = t//nl
    end subroutine line
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
