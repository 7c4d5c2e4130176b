!> Chamber gas-pressure trace: CSV reading and periodic interpolation.
module ringlube_gas
  use ringlube_kinds, only: dp
  use ringlube_error, only: error_type, fatal_error, rl_input_error
  use ringlube_textio, only: read_text_file, itoa, after_bom
  use, intrinsic :: iso_c_binding, only: c_char, c_double, c_ptr, c_null_char, c_loc, c_size_t
  implicit none
  private
  public :: read_pressure_csv, gas_pressure, check_pressure_trace
  ! (the CSV readers of other inputs share the field rules)
  public :: field_end, is_header, to_real, field_number, field_nonfinite

  !> Largest plausible cylinder pressure [Pa] and smallest span of a trace [deg].
  real(dp), parameter, public :: max_pressure = 1e8_dp, min_span_deg = 700.0_dp

  ! what `to_real` made of a field
  integer, parameter :: field_number = 0, field_nonfinite = 1, field_bad = 2

  interface
    real(c_double) function c_strtod(str, endptr) bind(c, name='strtod')
      import :: c_char, c_double, c_ptr
      character(kind=c_char), intent(in) :: str(*)
      type(c_ptr), intent(out) :: endptr
    end function c_strtod
  end interface

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
    character(len=:), allocatable :: text, line
    real(dp), allocatable :: tpsi(:), tp(:)
    real(dp) :: a, b
    integer :: sz, nline, nrow, pos, eol, icomma, fa, fb
    logical :: exists, seen_header, ok

    inquire (file=path, exist=exists)
    if (.not. exists) then
      call fatal_error(err, trim(path)//': pressure file not found', rl_input_error)
      return
    end if
    call read_text_file(path, text, err)
    if (allocated(err)) return
    sz = len(text)
    allocate (tpsi(max(16, sz / 8)), tp(max(16, sz / 8)))
    nline = 0
    nrow = 0
    seen_header = .false.
    pos = after_bom(text)
    do while (pos <= len(text))
      eol = field_end(text, pos, new_line('a'))
      line = trim(adjustl(text(pos:eol - 1)))
      if (len(line) > 0) then
        if (line(len(line):len(line)) == achar(13)) line = line(1:len(line) - 1)
      end if
      pos = eol + 1
      nline = nline + 1
      if (len_trim(line) == 0) cycle
      if (line(1:1) == '#') cycle
      if (nrow == 0 .and. .not. seen_header) then
        seen_header = .true.   ! only the first row can be the header
        if (is_header(line)) cycle
      end if
      icomma = index(line, ',')
      ok = icomma > 1
      if (ok) ok = index(line(icomma + 1:), ',') == 0
      fa = 2
      fb = 2
      if (ok) then
        call to_real(line(1:icomma - 1), a, fa)
        call to_real(line(icomma + 1:), b, fb)
      end if
      if (fa == field_nonfinite) then
        call bad_row('crank angle is not a finite number')
        return
      end if
      if (fb == field_nonfinite) then
        call bad_row('pressure is not a finite number')
        return
      end if
      if (fa /= field_number .or. fb /= field_number) then
        call bad_row('expected "crank angle deg, pressure Pa"')
        return
      end if
      if (.not. (a >= 0.0_dp .and. a <= 720.0_dp)) then
        call bad_row('crank angle outside [0, 720] deg')
        return
      end if
      if (.not. (b > 0.0_dp .and. b < huge(b))) then
        call bad_row('pressure must be positive (absolute, Pa)')
        return
      end if
      if (nrow > 0) then
        if (a <= tpsi(nrow)) then
          call bad_row('crank angles must increase strictly')
          return
        end if
      end if
      nrow = nrow + 1
      if (nrow > size(tpsi)) then
        tpsi = [tpsi, tpsi]
        tp = [tp, tp]
      end if
      tpsi(nrow) = a
      tp(nrow) = b
    end do
    if (nrow < 2) then
      call fatal_error(err, trim(path)//': pressure file needs at least two rows', rl_input_error)
      return
    end if
    psi = tpsi(1:nrow)
    p = tp(1:nrow)
    call check_pressure_trace(psi, p, err)
    if (allocated(err)) err%message = trim(path)//': '//err%message

  contains

    subroutine bad_row(why)
      character(len=*), intent(in) :: why
      call fatal_error(err, trim(path)//': line '//itoa(nline)//': '//why//': "' &
                       //trim(line)//'"', rl_input_error)
    end subroutine bad_row
  end subroutine read_pressure_csv

  !> Whether a CSV row is a header: every comma-separated field a non-empty word that
  !> cannot be read as a number (first character not a digit, sign or point; not a
  !> spelling of nan or inf).
  logical function is_header(line)
    character(len=*), intent(in) :: line
    integer :: i0, i1
    character(len=:), allocatable :: f
    is_header = .false.
    i0 = 1
    do
      i1 = field_end(line, i0, ',')
      f = trim(adjustl(line(i0:i1 - 1)))
      if (len(f) == 0) return
      if (scan(f(1:1), '0123456789+-.') /= 0) return
      if (nonfinite_word(f)) return
      if (i1 > len(line)) exit
      i0 = i1 + 1
    end do
    is_header = .true.
  end function is_header

  !> Where the field of `text` that starts at `from` ends: the index of the next `sep` at or
  !> after `from`, or len(text) + 1 when there is none (lines of a file, fields of a line).
  pure integer function field_end(text, from, sep) result(i)
    character(len=*), intent(in) :: text, sep
    integer, intent(in) :: from
    i = index(text(from:), sep)
    if (i == 0) then
      i = len(text) + 1
    else
      i = from + i - 1
    end if
  end function field_end

  !> nan, inf or infinity (any case, optional sign, nan(...) included): what C's strtod
  !> would read as a non-finite number.
  pure logical function nonfinite_word(field)
    character(len=*), intent(in) :: field
    character(len=:), allocatable :: f
    integer :: i
    f = trim(adjustl(field))
    do i = 1, len(f)
      if (f(i:i) >= 'A' .and. f(i:i) <= 'Z') f(i:i) = achar(iachar(f(i:i)) + 32)
    end do
    if (len(f) > 0) then
      if (f(1:1) == '+' .or. f(1:1) == '-') f = f(2:)
    end if
    nonfinite_word = f == 'nan' .or. f == 'inf' .or. f == 'infinity'
    if (len(f) >= 4) nonfinite_word = nonfinite_word .or. f(1:4) == 'nan('
  end function nonfinite_word

  !> A whole field (surrounding blanks allowed) as a real, by C's strtod. `kind` is
  !> `field_number` (a finite decimal number), `field_nonfinite` (nan, inf, or a number
  !> beyond the range of a double) or `field_bad` (anything else).
  subroutine to_real(field, v, kind)
    character(len=*), intent(in) :: field
    real(dp), intent(out) :: v
    integer, intent(out) :: kind
    character(kind=c_char, len=:), allocatable, target :: buf
    type(c_ptr) :: endp
    integer(c_size_t) :: consumed
    integer :: i
    character(len=:), allocatable :: f
    f = trim(adjustl(field))
    v = 0.0_dp
    kind = field_bad
    if (len(f) == 0) return
    if (nonfinite_word(f)) then
      kind = field_nonfinite
      return
    end if
    if (verify(f, '0123456789+-.eEdD') /= 0) return   ! no hex or other words
    ! Fortran-style exponents (1.0d5) as C ones
    do i = 1, len(f)
      if (f(i:i) == 'd' .or. f(i:i) == 'D') f(i:i) = 'e'
    end do
    buf = f//c_null_char
    v = c_strtod(buf, endp)
    consumed = transfer(endp, consumed) - transfer(c_loc(buf), consumed)
    if (consumed /= int(len(f), c_size_t)) return
    if (abs(v) > huge(v)) then
      kind = field_nonfinite   ! overflow: strtod gives +-HUGE_VAL (inf)
    else
      kind = field_number
    end if
  end subroutine to_real

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
