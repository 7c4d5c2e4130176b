!> Chamber gas-pressure trace: CSV reading and periodic interpolation (SPEC section 10).
module ringlube_gas
  use ringlube_kinds, only: dp
  use ringlube_error, only: error_type, fatal_error, rl_input_error
  implicit none
  private
  public :: read_pressure_csv, gas_pressure

contains

  !> Read a two-column CSV (crank angle deg, absolute pressure Pa) with an optional
  !> header line; blank lines and lines starting with '#' are skipped. Angles must
  !> increase strictly and lie in [0, 720]; pressures must be positive.
  subroutine read_pressure_csv(path, psi, p, err)
    character(len=*), intent(in) :: path
    real(dp), allocatable, intent(out) :: psi(:), p(:)
    type(error_type), allocatable, intent(out) :: err
    integer :: u, ios, nline, nrow, icomma
    character(len=1024) :: line
    character(len=256) :: msg
    real(dp) :: a, b
    real(dp), allocatable :: tpsi(:), tp(:)
    logical :: exists, seen_header

    inquire(file=path, exist=exists)
    if (.not. exists) then
      call fatal_error(err, trim(path) // ': pressure file not found', rl_input_error)
      return
    end if
    open(newunit=u, file=path, status='old', action='read', iostat=ios, iomsg=msg)
    if (ios /= 0) then
      call fatal_error(err, trim(path) // ': cannot open pressure file: ' // trim(msg), &
        rl_input_error)
      return
    end if
    allocate(tpsi(1024), tp(1024))
    nline = 0
    seen_header = .false.
    nrow = 0
    do
      read(u, '(a)', iostat=ios) line
      if (ios /= 0) exit
      nline = nline + 1
      line = adjustl(line)
      if (len_trim(line) == 0) cycle
      if (line(1:1) == '#') cycle
      icomma = index(line, ',')
      ios = 1
      if (icomma > 1) then
        read(line(1:icomma-1), *, iostat=ios) a
        if (ios == 0) read(line(icomma+1:), *, iostat=ios) b
        if (ios == 0 .and. len_trim(line(icomma+1:)) == 0) ios = 1
        if (ios == 0 .and. index(line(icomma+1:), ',') > 0) ios = 1
      end if
      if (ios /= 0) then
        if (nrow == 0 .and. .not. has_digit_start(line) .and. .not. seen_header) then
          seen_header = .true.  ! one optional header line before the first row
          cycle
        end if
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
    close(u)
    if (nrow < 2) then
      call fatal_error(err, trim(path) // ': pressure file needs at least two rows', rl_input_error)
      return
    end if
    psi = tpsi(1:nrow)
    p = tp(1:nrow)

  contains

    subroutine bad_row(why)
      character(len=*), intent(in) :: why
      character(len=16) :: num
      write(num, '(i0)') nline
      close(u)
      call fatal_error(err, trim(path) // ': line ' // trim(num) // ': ' // why // ': "' &
        // trim(line) // '"', rl_input_error)
    end subroutine bad_row

    pure logical function has_digit_start(s)
      character(len=*), intent(in) :: s
      has_digit_start = scan(s(1:1), '0123456789+-.') > 0
    end function has_digit_start
  end subroutine read_pressure_csv

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
    lo = 1
    hi = n
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
