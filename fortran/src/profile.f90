!> The ring's face profile S (the drop of the face below its lowest point, so h = h0 + S) in
!> the two forms besides the edge crown of ringlube_case (`ring_profile`): a barrel given by
!> its drops at a gauge length on each side of the crown point ('gauge'), and a measured
!> profile read from a CSV file ('table'); their integrals across the face (ring mass).
!>
!> Coordinates: x across the face from the chamber edge -b/2 to the crankcase edge +b/2
!> (the film's); a table gives its positions from the top (chamber) edge, xi = x + b/2 in
!> [0, b], as profilometer traces across a face are taken.
module ringlube_profile
  use ringlube_kinds, only: dp
  use ringlube_error, only: error_type
  use ringlube_csv, only: csv_rows, open_csv, next_row, split_pair, row_error, add_pair, &
                          take_pairs, field_end, field_number, field_nonfinite
  implicit none
  private
  public :: gauge_profile, gauge_area, table_profile, table_area, read_profile_csv, &
            check_profile_table

  !> Largest plausible drop of a face [m] (the range of &ring crown_height): a table whose
  !> drops exceed it is not in metres.
  real(dp), parameter, public :: max_drop = 1e-3_dp
  !> A table must reach the face's edges to within this share of the width.
  real(dp), parameter, public :: edge_tolerance = 1e-3_dp

contains

  !> Barrel face given by its drops at a gauge length from the crown point x_c = -x_s:
  !> S = d_top ((x + x_s)/g)^2 on the chamber side (x < x_c), d_bottom ((x + x_s)/g)^2 on the
  !> crankcase side [m]. With g = b/2 and both drops c it is the edge crown c (x + x_s)^2/(b/2)^2
  !> (the same operations: the same numbers).
  elemental real(dp) function gauge_profile(x, crown_offset, gauge_length, drop_top, &
                                            drop_bottom) result(s)
    real(dp), intent(in) :: x, crown_offset, gauge_length, drop_top, drop_bottom
    if (x + crown_offset < 0.0_dp) then
      s = drop_top * (x + crown_offset)**2 / gauge_length**2
    else
      s = drop_bottom * (x + crown_offset)**2 / gauge_length**2
    end if
  end function gauge_profile

  !> int S dx over the face [-b/2, b/2] of the gauge profile [m^2] (closed form).
  pure real(dp) function gauge_area(width, crown_offset, gauge_length, drop_top, drop_bottom) &
    result(a)
    real(dp), intent(in) :: width, crown_offset, gauge_length, drop_top, drop_bottom
    real(dp) :: hb
    hb = 0.5_dp * width
    ! (the crown point lies inside the face: |x_s| < b/2)
    a = (drop_top * (hb - crown_offset)**3 + drop_bottom * (hb + crown_offset)**3) &
        / (3.0_dp * gauge_length**2)
  end function gauge_area

  !> The table's profile at xi (from the top edge) [m]: linear between its points, the end
  !> values beyond them (a table reaches the edges to within edge_tolerance of the width), less
  !> `s_min` (the lowest point on the face, `table_area`'s): 0 at the lowest point. At a
  !> point of the table its value exactly.
  pure real(dp) function table_profile(xi, tx, ts, s_min) result(s)
    real(dp), intent(in) :: xi, tx(:), ts(:), s_min
    integer :: lo, hi, mid, n
    n = size(tx)
    if (xi <= tx(1)) then
      s = ts(1) - s_min
      return
    else if (xi >= tx(n)) then
      s = ts(n) - s_min
      return
    end if
    lo = 1
    hi = n
    do while (hi - lo > 1)
      mid = (lo + hi) / 2
      if (tx(mid) <= xi) then
        lo = mid
      else
        hi = mid
      end if
    end do
    if (xi == tx(lo)) then
      s = ts(lo) - s_min
    else
      s = ts(lo) + (ts(hi) - ts(lo)) * ((xi - tx(lo)) / (tx(hi) - tx(lo))) - s_min
    end if
  end function table_profile

  !> The lowest point of the table's profile on the face [0, width] (`s_min`), and the
  !> integral of the profile less s_min over the face [m^2] (exact for the linear
  !> interpolant: the trapezoidal rule on its points and the face's edges).
  pure subroutine table_area(width, tx, ts, s_min, area)
    real(dp), intent(in) :: width, tx(:), ts(:)
    real(dp), intent(out) :: s_min, area
    real(dp) :: xa, xb, sa, sb
    integer :: j
    s_min = min(table_profile(0.0_dp, tx, ts, 0.0_dp), table_profile(width, tx, ts, 0.0_dp))
    do j = 1, size(tx)
      if (tx(j) > 0.0_dp .and. tx(j) < width) s_min = min(s_min, ts(j))
    end do
    area = 0.0_dp
    xa = 0.0_dp
    sa = table_profile(0.0_dp, tx, ts, 0.0_dp)
    do j = 1, size(tx) + 1
      if (j <= size(tx)) then
        if (tx(j) <= 0.0_dp) cycle
        xb = min(tx(j), width)
      else
        xb = width
      end if
      sb = table_profile(xb, tx, ts, 0.0_dp)
      area = area + 0.5_dp * (sa + sb) * (xb - xa)
      xa = xb
      sa = sb
      if (xa >= width) exit
    end do
    area = area - s_min * width
  end subroutine table_area

  !> Check a profile table against the face's width [m]: it must reach both edges, 0 and
  !> width, to within edge_tolerance of the width (positions from the top edge), and its
  !> drops span at most max_drop. `why` says what is wrong (unset: nothing).
  subroutine check_profile_table(tx, ts, width, why)
    real(dp), intent(in) :: tx(:), ts(:), width
    character(len=:), allocatable, intent(out) :: why
    real(dp) :: tol, span
    integer :: n
    n = size(tx)
    if (n < 2) then
      why = 'the profile table has fewer than two points'
      return
    end if
    tol = edge_tolerance * width
    if (abs(tx(1)) > tol .or. abs(tx(n) - width) > tol) then
      span = tx(n) - tx(1)
      why = 'the profile runs from x = '//num(tx(1))//' to '//num(tx(n))//' m, the face from '// &
            '0 (top edge) to width = '//num(width)//' m: the table must span the face'
      if (abs(span / width - 1e3_dp) < 0.01e3_dp) then
        why = why//' (x looks like mm: name the unit in the header, e.g. "x_mm, S_um")'
      else if (abs(span / width - 1e6_dp) < 0.01e6_dp) then
        why = why//' (x looks like um: name the unit in the header, e.g. "x_um, S_um")'
      else
        why = why//' (x from the top edge, in m unless the header names the unit)'
      end if
      return
    end if
    if (maxval(ts) - minval(ts) > max_drop) then
      why = 'the profile''s drops span '//num(maxval(ts) - minval(ts))//' m, more than the '// &
            num(max_drop)//' m a ring face can have (S in m unless the header names the '// &
            'unit, e.g. "x_mm, S_um")'
    end if

  contains

    function num(v) result(t)
      real(dp), intent(in) :: v
      character(len=:), allocatable :: t
      character(len=24) :: buf
      write (buf, '(es11.4)') v
      t = trim(adjustl(buf))
    end function num
  end subroutine check_profile_table

  !> Read a face profile: a two-column CSV (x from the top edge, S the face's drop; metres)
  !> with an optional header line whose fields may name the unit of their column, 'x_mm',
  !> 'x [mm]' or 'x (mm)' (m, mm or um); blank lines and lines starting with '#' skipped.
  !> Positions must increase strictly; every value finite (named errors, with the line).
  !> Returned in metres.
  subroutine read_profile_csv(path, tx, ts, err)
    character(len=*), intent(in) :: path
    real(dp), allocatable, intent(out) :: tx(:), ts(:)
    type(error_type), allocatable, intent(out) :: err
    type(csv_rows) :: rows
    character(len=:), allocatable :: why
    real(dp) :: a, b, scale(2)
    integer :: fa, fb
    logical :: header

    scale = 1.0_dp
    call open_csv(path, 'profile', rows, err)
    if (allocated(err)) return
    do while (next_row(rows, header))
      if (header) then
        call header_units(rows%line, scale, why)
        if (allocated(why)) then
          call row_error(rows, why, err)
          return
        end if
        cycle
      end if
      call split_pair(rows%line, a, b, fa, fb)
      if (fa == field_nonfinite .or. fb == field_nonfinite) then
        call row_error(rows, 'not a finite number', err)
      else if (fa /= field_number .or. fb /= field_number) then
        call row_error(rows, 'expected "x, S" (two numbers: position from the top edge, drop)', &
                       err)
      else
        call add_pair(rows, a * scale(1), b * scale(2), 'positions x must increase strictly', err)
      end if
      if (allocated(err)) return
    end do
    call take_pairs(rows, tx, ts, err)
  end subroutine read_profile_csv

  !> The units the header's two fields name (factors to metres); `why` if a field names one
  !> that is not m, mm or um, or the header has not two fields.
  subroutine header_units(line, scale, why)
    character(len=*), intent(in) :: line
    real(dp), intent(out) :: scale(2)
    character(len=:), allocatable, intent(out) :: why
    integer :: i0, i1, k
    scale = 1.0_dp
    i0 = 1
    do k = 1, 2
      i1 = field_end(line, i0, ',')
      if ((k == 1 .and. i1 > len(line)) .or. (k == 2 .and. i1 <= len(line))) then
        why = 'a header has two fields (x, S), e.g. "x_mm, S_um"'
        return
      end if
      call field_unit(trim(adjustl(line(i0:i1 - 1))), scale(k), why)
      if (allocated(why)) return
      i0 = i1 + 1
    end do
  end subroutine header_units

  !> The unit a header field names: in brackets 'x [mm]', 'x (mm)', or after the last '_',
  !> 'x_mm' (a suffix that is not a unit is part of the name: metres).
  subroutine field_unit(field, factor, why)
    character(len=*), intent(in) :: field
    real(dp), intent(out) :: factor
    character(len=:), allocatable, intent(out) :: why
    character(len=:), allocatable :: u
    integer :: i, j
    logical :: bracketed
    factor = 1.0_dp
    i = scan(field, '[(')
    bracketed = i > 0
    if (bracketed) then
      j = scan(field, '])', back=.true.)
      if (j <= i) j = len(field) + 1
      u = trim(adjustl(field(i + 1:j - 1)))
    else
      i = index(field, '_', back=.true.)
      if (i == 0) return
      u = field(i + 1:)
    end if
    select case (u)
    case ('m')
      factor = 1.0_dp
    case ('mm')
      factor = 1e-3_dp
    case ('um', 'micron', 'microns', achar(194)//achar(181)//'m', achar(206)//achar(188)//'m')
      factor = 1e-6_dp
    case default
      if (bracketed) why = 'unknown unit "'//u//'" in the header (m, mm or um)'
    end select
  end subroutine field_unit
end module ringlube_profile
