!> The bore as it is (docs/bore.md): its distortion D(theta, z) from the liner's round
!> shape, the ring's bending compliance per Fourier order, and the classical conformability
!> limit.
!>
!> The circumference is split into M equal sectors at theta_j = 2 pi (j - 1) / M. The ring is
!> a thin closed ring of radius r0 and in-plane bending stiffness E_r I, I = b d^3 / 12: a
!> radial line load q_k cos(k theta) of order k >= 2 (N per m of circumference) bends it by
!> u_k = C_k q_k, C_k = r0^4 / (E_r I (k^2 - 1)^2). Orders 0 and 1 are rigid-body motions
!> (the ring's mean position and the translation of its centre) and carry no elastic load.
!> On the sectors the deflection of a load W_j is u = -C [W], C the circulant matrix
!> C_jl = sum_(k=2..M/2) C_k w_k cos(k (theta_j - theta_l)), w_k = 2/M (1/M for k = M/2):
!> the orders 2..M/2 of W, each scaled by its compliance (docs/bore.md).
module ringlube_bore
  use ringlube_kinds, only: dp, pi
  use ringlube_error, only: error_type, fatal_error, rl_input_error
  use ringlube_case, only: case_type, elastic_pressure
  use ringlube_textio, only: read_text_file, itoa, after_bom
  use ringlube_csv, only: field_end, is_header, to_real, field_number, field_nonfinite
  implicit none
  private
  public :: bore_type, bore_setup, bore_distortion, ring_compliance, conformability, &
            conformability_orders, read_distortion_csv

  !> The most rows a distortion file may hold (every step looks its orders up in them).
  integer, parameter :: max_distortion_rows = 10000

  !> The sectors, the ring's compliance on them and the bore's distortion.
  type :: bore_type
    !> sectors M
    integer :: m = 0
    !> the sectors' angles [rad] and their cosines and sines
    real(dp), allocatable :: theta(:), cos1(:), sin1(:)
    !> the compliance matrix C [m per N/m] (M x M), its pseudo-inverse on the orders 2..M/2
    !> [N/m per m], and the projection on the rigid-body orders 0 and 1
    real(dp), allocatable :: cmat(:, :), cinv(:, :), p01(:, :)
    !> the distortion's orders, amplitudes [m] and phases [rad], constant along the stroke
    integer, allocatable :: order(:)
    real(dp), allocatable :: amplitude(:), phase(:)
    !> or along the stroke: rows (z [m], order, amplitude [m], phase [rad])
    real(dp), allocatable :: table(:, :)
  end type bore_type

contains

  !> Compliance C_k [m per N/m] of the ring of case c for a line load of order k (0 for the
  !> rigid-body orders 0 and 1).
  pure real(dp) function ring_compliance(c, k) result(ck)
    type(case_type), intent(in) :: c
    integer, intent(in) :: k
    real(dp) :: ei
    ck = 0.0_dp
    if (k < 2) return
    ei = c%e_ring * c%width * c%radial_depth**3 / 12.0_dp
    ck = c%bore_radius**4 / (ei * real(k * k - 1, dp)**2)
  end function ring_compliance

  !> A_k over the conformability limit of each order of the distortion given in the lists
  !> (its largest amplitude along the stroke where a file gives it): the dry ring under the
  !> uniform load q = p_e b follows a single order-k distortion fully exactly when
  !> A_k <= q C_k. Orders 0 and 1 (rigid-body motions) always conform: 0.
  pure function conformability(c, b) result(ratio)
    type(case_type), intent(in) :: c
    type(bore_type), intent(in) :: b
    real(dp), allocatable :: ratio(:)
    integer :: i, k
    real(dp) :: q, a
    q = elastic_pressure(c) * c%width
    if (allocated(b%table)) then
      ratio = [real(dp) ::]
      do k = 0, b%m / 2
        if (.not. any(nint(b%table(:, 2)) == k)) cycle
        a = maxval(abs(b%table(:, 3)), mask=nint(b%table(:, 2)) == k)
        ratio = [ratio, limit_ratio(k, a)]
      end do
    else
      allocate (ratio(size(b%order)))
      do i = 1, size(b%order)
        ratio(i) = limit_ratio(b%order(i), b%amplitude(i))
      end do
    end if

  contains

    pure real(dp) function limit_ratio(k, amp)
      integer, intent(in) :: k
      real(dp), intent(in) :: amp
      limit_ratio = 0.0_dp
      if (k >= 2 .and. q > 0.0_dp) limit_ratio = amp / (q * ring_compliance(c, k))
      if (k >= 2 .and. q <= 0.0_dp .and. amp > 0.0_dp) limit_ratio = huge(1.0_dp)
    end function limit_ratio
  end function conformability

  !> The orders of the distortion (as `conformability` lists them).
  pure function conformability_orders(b) result(orders)
    type(bore_type), intent(in) :: b
    integer, allocatable :: orders(:)
    integer :: k
    if (allocated(b%table)) then
      orders = [integer ::]
      do k = 0, b%m / 2
        if (any(nint(b%table(:, 2)) == k)) orders = [orders, k]
      end do
    else
      orders = b%order
    end if
  end function conformability_orders

  !> The sectors, the compliance matrix and the distortion of case c.
  pure subroutine bore_setup(c, b)
    type(case_type), intent(in) :: c
    type(bore_type), intent(out) :: b
    integer :: j, l, k, m
    real(dp) :: w
    m = c%sectors
    b%m = m
    allocate (b%theta(m), b%cos1(m), b%sin1(m), b%cmat(m, m), b%cinv(m, m), b%p01(m, m))
    do j = 1, m
      b%theta(j) = 2.0_dp * pi * (j - 1) / m
    end do
    b%cos1 = cos(b%theta)
    b%sin1 = sin(b%theta)
    b%cmat = 0.0_dp
    b%cinv = 0.0_dp
    do k = 2, m / 2
      w = 2.0_dp / m
      if (2 * k == m) w = 1.0_dp / m
      do l = 1, m
        do j = 1, m
        b%cmat(j, l) = b%cmat(j, l) + ring_compliance(c, k) * w * cos(k * (b%theta(j) - b%theta(l)))
        b%cinv(j, l) = b%cinv(j, l) + w * cos(k * (b%theta(j) - b%theta(l))) / ring_compliance(c, k)
        end do
      end do
    end do
    do l = 1, m
      do j = 1, m
        b%p01(j, l) = (1.0_dp + 2.0_dp * cos(b%theta(j) - b%theta(l))) / m
      end do
    end do
    if (allocated(c%distortion)) then
      if (size(c%distortion, 1) > 0) then
        b%table = c%distortion
        return
      end if
    end if
    b%order = c%bore_order
    b%amplitude = c%bore_amplitude
    if (size(c%bore_phase) == size(c%bore_order)) then
      b%phase = c%bore_phase
    else
      allocate (b%phase(size(b%order)))
      b%phase = 0.0_dp
    end if
  end subroutine bore_setup

  !> The distortion D(theta_j, z) [m] at every sector for the ring at z [m] (its position
  !> from its TDC position): the lists, or the file's rows of each order linear in z between
  !> rows and constant beyond them. Its mean over the sectors (order 0, a larger or smaller
  !> bore) is taken out: it moves the ring's mean position only, which is solved for anyway
  !> (the ring's mean position then counts from the mean bore).
  pure subroutine bore_distortion(b, z, d)
    type(bore_type), intent(in) :: b
    real(dp), intent(in) :: z
    real(dp), intent(out) :: d(:)
    integer :: i, k
    real(dp) :: a, ph
    d = 0.0_dp
    if (allocated(b%table)) then
      do k = 0, b%m / 2
        if (.not. any(nint(b%table(:, 2)) == k)) cycle
        if (k == 0) cycle
        call along_stroke(k, a, ph)
        d = d + a * cos(k * (b%theta - ph))
      end do
      return
    end if
    do i = 1, size(b%order)
      if (b%order(i) == 0) cycle
      d = d + b%amplitude(i) * cos(b%order(i) * (b%theta - b%phase(i)))
    end do

  contains

    !> Amplitude and phase of order k at z from the table's rows of that order (in z order).
    pure subroutine along_stroke(k, amp, phase)
      integer, intent(in) :: k
      real(dp), intent(out) :: amp, phase
      integer :: r, prev
      real(dp) :: t
      prev = 0
      amp = 0.0_dp
      phase = 0.0_dp
      do r = 1, size(b%table, 1)
        if (nint(b%table(r, 2)) /= k) cycle
        if (b%table(r, 1) >= z) then
          if (prev == 0) then
            amp = b%table(r, 3)
            phase = b%table(r, 4)
          else
            t = (z - b%table(prev, 1)) / (b%table(r, 1) - b%table(prev, 1))
            amp = (1.0_dp - t) * b%table(prev, 3) + t * b%table(r, 3)
            phase = (1.0_dp - t) * b%table(prev, 4) + t * b%table(r, 4)
          end if
          return
        end if
        prev = r
      end do
      amp = b%table(prev, 3)
      phase = b%table(prev, 4)
    end subroutine along_stroke
  end subroutine bore_distortion

  !> Read a distortion CSV: rows `z_m, order, amplitude_m, phase_rad` (an optional header
  !> line; blank lines and lines starting with '#' skipped), the rows of each order in
  !> strictly increasing z; orders 0..max_order, amplitudes 0..1 mm, |phase| <= 100 rad; at
  !> most max_distortion_rows rows; a UTF-8 byte-order mark skipped. Rows sorted by order,
  !> then z.
  subroutine read_distortion_csv(path, max_order, table, err)
    character(len=*), intent(in) :: path
    integer, intent(in) :: max_order
    real(dp), allocatable, intent(out) :: table(:, :)
    type(error_type), allocatable, intent(out) :: err
    character(len=:), allocatable :: text, line
    real(dp), allocatable :: rows(:, :), last_z(:)
    real(dp) :: v(4)
    integer :: pos, eol, nline, nrow, i0, i1, f, kind, j, k
    logical :: exists, seen_header
    character(len=*), parameter :: names(4) = [character(len=9) :: 'z_m', 'order', &
                                                                               'amplitude', 'phase']

    inquire (file=path, exist=exists)
    if (.not. exists) then
      call fatal_error(err, trim(path)//': distortion file not found', rl_input_error)
      return
    end if
    call read_text_file(path, text, err)
    if (allocated(err)) return
    allocate (rows(4, 16), last_z(0:max_order))
    last_z = -huge(1.0_dp)
    nrow = 0
    nline = 0
    seen_header = .false.
    pos = after_bom(text)   ! a UTF-8 byte-order mark (spreadsheets write one) is not data
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
        seen_header = .true.
        if (is_header(line)) cycle
      end if
      i0 = 1
      do f = 1, 4
        i1 = field_end(line, i0, ',')
        if (i0 > len(line) + 1 .or. (f < 4 .and. i1 > len(line))) then
          call bad_row('expected four fields "z_m, order, amplitude_m, phase_rad"')
          return
        end if
        call to_real(line(i0:i1 - 1), v(f), kind)
        if (kind == field_nonfinite) then
          call bad_row(trim(names(f))//' is not a finite number')
          return
        else if (kind /= field_number) then
          call bad_row('expected four numbers "z_m, order, amplitude_m, phase_rad"')
          return
        end if
        i0 = i1 + 1
      end do
      if (i1 <= len(line)) then
        call bad_row('expected four fields "z_m, order, amplitude_m, phase_rad"')
        return
      end if
      if (.not. (abs(v(1)) <= 1.0_dp)) then
        call bad_row('z outside [-1, 1] m (a position along the stroke, in m)')
        return
      end if
      if (v(2) /= anint(v(2)) .or. v(2) < 0.0_dp .or. v(2) > max_order) then
        call bad_row('order must be a whole number in [0, '//itoa(max_order)// &
                     '] (at most &bore sectors / 2)')
        return
      end if
      if (.not. (v(3) >= 0.0_dp .and. v(3) <= 1e-3_dp)) then
        call bad_row('amplitude outside [0, 1e-3] m (amplitudes in m, not um)')
        return
      end if
      if (.not. (abs(v(4)) <= 100.0_dp)) then
        call bad_row('phase outside [-100, 100] rad')
        return
      end if
      if (v(1) <= last_z(nint(v(2)))) then
        call bad_row('the rows of order '//itoa(nint(v(2)))//' must increase strictly in z')
        return
      end if
      last_z(nint(v(2))) = v(1)
      if (nrow == max_distortion_rows) then
        call bad_row('more than '//itoa(max_distortion_rows)//' rows (a distortion needs a '// &
                     'few rows per order along the stroke)')
        return
      end if
      nrow = nrow + 1
      if (nrow > size(rows, 2)) rows = reshape([rows, rows], [4, 2 * size(rows, 2)])
      rows(:, nrow) = v
    end do
    if (nrow == 0) then
      call fatal_error(err, trim(path)//': distortion file has no rows', rl_input_error)
      return
    end if
    ! by order, then z (the file's order within each order is kept: z increases)
    allocate (table(nrow, 4))
    j = 0
    do k = 0, max_order
      do i0 = 1, nrow
        if (nint(rows(2, i0)) /= k) cycle
        j = j + 1
        table(j, :) = rows(:, i0)
      end do
    end do

  contains

    subroutine bad_row(why)
      character(len=*), intent(in) :: why
      call fatal_error(err, trim(path)//':'//itoa(nline)//': '//why, rl_input_error)
    end subroutine bad_row
  end subroutine read_distortion_csv
end module ringlube_bore
