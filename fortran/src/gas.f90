!> Chamber gas-pressure trace: CSV reading and periodic interpolation.
module ringlube_gas
  use ringlube_kinds, only: dp
  use ringlube_error, only: error_type, fatal_error, rl_input_error
  use ringlube_textio, only: itoa
  use ringlube_csv, only: csv_rows, open_csv, next_row, split_pair, row_error, add_pair, &
                          take_pairs, field_number, field_nonfinite
  implicit none
  private
  public :: read_pressure_csv, gas_pressure, check_pressure_trace

  !> Largest plausible cylinder pressure [Pa] and smallest span of a trace [deg].
  real(dp), parameter, public :: max_pressure = 1e8_dp, min_span_deg = 700.0_dp

contains

  !> Read a two-column CSV (crank angle deg, absolute pressure Pa) with an optional
  !> header line; blank lines, lines starting with '#' and a UTF-8 byte-order mark are skipped. Only the first
  !> row can be the header, and only if none of its fields could be a number: every
  !> field a word (not starting with a digit, sign or point, and not nan/inf), so that a
  !> first row such as `nan,1e5` is an error, not a skipped header. Angles must increase
  !> strictly and lie in [0, 720]; pressures must be positive; nan, inf and numbers too
  !> large for a double are named errors. Numbers are converted with C's strtod
  !> (correctly rounded, as gfortran's own reads).
  subroutine read_pressure_csv(path, psi, p, err)
    character(len=*), intent(in) :: path
    real(dp), allocatable, intent(out) :: psi(:), p(:)
    type(error_type), allocatable, intent(out) :: err
    type(csv_rows) :: rows
    real(dp) :: a, b
    integer :: fa, fb
    logical :: header

    call open_csv(path, 'pressure', rows, err)
    if (allocated(err)) return
    do while (next_row(rows, header))
      if (header) cycle
      call split_pair(rows%line, a, b, fa, fb)
      if (fa == field_nonfinite) then
        call row_error(rows, 'crank angle is not a finite number', err)
      else if (fb == field_nonfinite) then
        call row_error(rows, 'pressure is not a finite number', err)
      else if (fa /= field_number .or. fb /= field_number) then
        call row_error(rows, 'expected "crank angle deg, pressure Pa"', err)
      else if (.not. (a >= 0.0_dp .and. a <= 720.0_dp)) then
        call row_error(rows, 'crank angle outside [0, 720] deg', err)
      else if (.not. (b > 0.0_dp .and. b < huge(b))) then
        call row_error(rows, 'pressure must be positive (absolute, Pa)', err)
      else
        call add_pair(rows, a, b, 'crank angles must increase strictly', err)
      end if
      if (allocated(err)) return
    end do
    call take_pairs(rows, psi, p, err)
    if (allocated(err)) return
    call check_pressure_trace(psi, p, err)
    if (allocated(err)) err%message = trim(path)//': '//err%message
  end subroutine read_pressure_csv

  !> Check a trace (from a CSV file or given as arrays): at least two points, crank angles
  !> strictly increasing in [0, 720] deg and spanning at least `min_span_deg` of the cycle
  !> (the trace is periodic: a short trace would be stretched over the whole cycle without a
  !> word), pressures positive, finite and at most `max_pressure` (absolute, Pa).
  subroutine check_pressure_trace(psi, p, err)
    real(dp), intent(in) :: psi(:), p(:)
    type(error_type), allocatable, intent(out) :: err
    integer :: i
    if (size(psi) /= size(p)) then
      call fatal_error(err, 'crank angles and pressures differ in length', rl_input_error)
    else if (size(psi) < 2) then
      call fatal_error(err, 'needs at least two points', rl_input_error)
    else
      do i = 1, size(psi)
        if (.not. (psi(i) >= 0.0_dp .and. psi(i) <= 720.0_dp)) then
          call fatal_error(err, 'point '//itoa(i)//': crank angle outside [0, 720] deg', &
                           rl_input_error)
        else if (.not. (p(i) > 0.0_dp .and. p(i) <= max_pressure)) then
          call fatal_error(err, 'point '//itoa(i)//': pressure must be positive and at '// &
                           'most 1e8 Pa (1000 bar, absolute)', rl_input_error)
        else if (i > 1) then
          if (.not. (psi(i) > psi(i - 1))) then
            call fatal_error(err, 'point '//itoa(i)//': crank angles must increase strictly', &
                             rl_input_error)
          end if
        end if
        if (allocated(err)) return
      end do
      if (psi(size(psi)) - psi(1) < min_span_deg) then
        call fatal_error(err, 'the trace covers only crank angles '//trim(deg_text(psi(1)))// &
                         ' to '//trim(deg_text(psi(size(psi))))//' deg: it must span at least '// &
                         '700 of the 720 deg of the cycle', rl_input_error)
      end if
    end if
  contains
    function deg_text(v) result(t)
      real(dp), intent(in) :: v
      character(len=16) :: t
      write (t, '(f8.1)') v
      t = adjustl(t)
    end function deg_text
  end subroutine check_pressure_trace

  !> Pressure [Pa] at crank angle psi_deg, linear and periodic over 720 deg. With no
  !> trace (`size(psi) == 0`) the constant `p_default` is returned.
  pure real(dp) function gas_pressure(psi, p, psi_deg, p_default) result(pg)
    real(dp), intent(in) :: psi(:), p(:), psi_deg, p_default
    real(dp) :: a, x0, x1
    integer :: lo, hi, mid, n
    n = size(psi)
    if (n == 0) then
      pg = p_default
      return
    end if
    a = modulo(psi_deg, 720.0_dp)
    if (a < psi(1) .or. a >= psi(n)) then
      ! wrap-around segment between the last and the first sample
      x0 = psi(n)
      x1 = psi(1) + 720.0_dp
      if (a < psi(1)) a = a + 720.0_dp
      if (x1 - x0 <= 0.0_dp) then
        pg = p(n)
      else
        pg = p(n) + (p(1) - p(n)) * (a - x0) / (x1 - x0)
      end if
      return
    end if
    ! the interval of an evenly sampled trace at once: a guess in proportion to the angle,
    ! bisection from there when the samples are uneven (the same interval either way)
    lo = min(n - 1, max(1, 1 + int((a - psi(1)) / (psi(n) - psi(1)) * (n - 1))))
    hi = lo + 1
    if (psi(lo) > a) then
      hi = lo
      lo = 1
    else if (psi(hi) <= a) then
      lo = hi
      hi = n
    end if
    do while (hi - lo > 1)
      mid = (lo + hi) / 2
      if (psi(mid) <= a) then
        lo = mid
      else
        hi = mid
      end if
    end do
    pg = p(lo) + (p(hi) - p(lo)) * (a - psi(lo)) / (psi(hi) - psi(lo))
  end function gas_pressure
end module ringlube_gas
