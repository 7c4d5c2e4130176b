!> The oil film on the liner: a film thickness per cell of a uniform grid
!> over the liner position z (m, from the top ring's position at TDC, positive towards the
!> crankcase), and the exchanges of oil volume with the ring as strips of liner.
!>
!> Oil is held as a volume per cell (reported as the cell's mean thickness), spread evenly over
!> the part of the cell it occupies, [lo, hi]: the whole cell at first; an edge that takes
!> the oil of a strip covering one end of that part leaves the rest. Every operation moves a
!> volume per unit circumference (m^2) between a strip [za, zb] of liner and somewhere else,
!> computed from the overlap of the strip with the occupied part of each cell, so the sums
!> balance to round-off, and an edge sweeping over a cell in two crank steps, [a, b] then
!> [b, c], takes all its oil. (With the oil uniform over the whole cell, a cell split f, 1 - f
!> between the two steps kept f (1 - f) of its oil: a spike of up to a quarter of the film at
!> every step's boundary on the liner.)
module ringlube_liner
  use ringlube_kinds, only: dp
  implicit none
  private
  public :: liner_type, liner_init, strip_volume, strip_take, strip_put, strip_set, strip_draw, &
            strip_copy, liner_volume, liner_positions

  !> The liner film.
  type :: liner_type
    real(dp) :: z0 = 0.0_dp          !< m, left end of cell 1
    real(dp) :: dz = 0.0_dp          !< m, cell length
    integer :: nz = 0
    real(dp), allocatable :: h(:)    !< m, film thickness of each cell (mean over the cell)
    real(dp), allocatable :: lo(:)   !< m, the oil of a cell lies evenly on [lo, hi]
    real(dp), allocatable :: hi(:)
  end type liner_type

contains

  !> A grid covering [zmin, zmax] with cells of about dz, every cell at film h_init.
  pure subroutine liner_init(lin, zmin, zmax, dz, h_init)
    type(liner_type), intent(out) :: lin
    real(dp), intent(in) :: zmin, zmax, dz, h_init
    integer :: i
    lin%nz = max(1, ceiling((zmax - zmin) / dz))
    lin%z0 = zmin
    lin%dz = (zmax - zmin) / lin%nz
    allocate (lin%h(lin%nz))
    lin%h = h_init
    lin%lo = [(lin%z0 + (i - 1) * lin%dz, i=1, lin%nz)]
    lin%hi = lin%lo + lin%dz
  end subroutine liner_init

  !> Cell centres [m].
  pure function liner_positions(lin) result(z)
    type(liner_type), intent(in) :: lin
    real(dp) :: z(lin%nz)
    integer :: i
    z = [(lin%z0 + (i - 0.5_dp) * lin%dz, i=1, lin%nz)]
  end function liner_positions

  !> Oil on the whole liner [m^2 per unit circumference].
  pure real(dp) function liner_volume(lin)
    type(liner_type), intent(in) :: lin
    liner_volume = sum(lin%h) * lin%dz
  end function liner_volume

  !> Overlap [m] of [za, zb] with cell i.
  pure real(dp) function overlap(lin, i, za, zb)
    type(liner_type), intent(in) :: lin
    integer, intent(in) :: i
    real(dp), intent(in) :: za, zb
    real(dp) :: c0, c1
    c0 = lin%z0 + (i - 1) * lin%dz
    c1 = c0 + lin%dz
    overlap = min(lin%dz, max(0.0_dp, min(zb, c1) - max(za, c0)))
  end function overlap

  !> Share of the oil of cell i that lies on [za, zb] (za <= zb): the overlap of the strip
  !> with the part of the cell the oil occupies, over that part's length.
  pure real(dp) function share_in(lin, i, za, zb)
    type(liner_type), intent(in) :: lin
    integer, intent(in) :: i
    real(dp), intent(in) :: za, zb
    real(dp) :: length
    length = lin%hi(i) - lin%lo(i)
    if (length > 0.0_dp) then
      share_in = min(1.0_dp, max(0.0_dp, min(zb, lin%hi(i)) - max(za, lin%lo(i))) / length)
    else
      share_in = merge(1.0_dp, 0.0_dp, lin%lo(i) >= za .and. lin%lo(i) <= zb)
    end if
  end function share_in

  !> Cells that [za, zb] can touch.
  pure subroutine cell_range(lin, za, zb, i0, i1)
    type(liner_type), intent(in) :: lin
    real(dp), intent(in) :: za, zb
    integer, intent(out) :: i0, i1
    i0 = max(1, floor((min(za, zb) - lin%z0) / lin%dz) + 1)
    i1 = min(lin%nz, floor((max(za, zb) - lin%z0) / lin%dz) + 1)
  end subroutine cell_range

  !> Oil on the strip between za and zb (either order) [m^2].
  pure real(dp) function strip_volume(lin, za, zb) result(v)
    type(liner_type), intent(in) :: lin
    real(dp), intent(in) :: za, zb
    integer :: i, i0, i1
    v = 0.0_dp
    call cell_range(lin, za, zb, i0, i1)
    do i = i0, i1
      v = v + lin%h(i) * lin%dz * share_in(lin, i, min(za, zb), max(za, zb))
    end do
  end function strip_volume

  !> Remove all the oil on the strip; returns the volume removed [m^2].
  pure subroutine strip_take(lin, za, zb, v)
    type(liner_type), intent(inout) :: lin
    real(dp), intent(in) :: za, zb
    real(dp), intent(out) :: v
    real(dp) :: f, a, b
    integer :: i, i0, i1
    v = 0.0_dp
    a = min(za, zb)
    b = max(za, zb)
    call cell_range(lin, za, zb, i0, i1)
    do i = i0, i1
      f = share_in(lin, i, a, b)
      if (f <= 0.0_dp) cycle
      v = v + lin%h(i) * lin%dz * f
      if (f >= 1.0_dp) then
        lin%h(i) = 0.0_dp
      else
        lin%h(i) = lin%h(i) * (1.0_dp - f)
        ! the oil left lies beyond the strip (a strip inside the part: left as it was)
        if (a <= lin%lo(i)) lin%lo(i) = b
        if (b >= lin%hi(i)) lin%hi(i) = a
      end if
    end do
  end subroutine strip_take

  !> Take volume v [m^2] from the strip, the same share of the oil of every part of it (at
  !> most all of it); returns in `taken` what was taken.
  pure subroutine strip_draw(lin, za, zb, v, taken)
    type(liner_type), intent(inout) :: lin
    real(dp), intent(in) :: za, zb, v
    real(dp), intent(out) :: taken
    real(dp) :: f, avail, share
    integer :: i, i0, i1
    taken = 0.0_dp
    avail = strip_volume(lin, za, zb)
    if (.not. (avail > 0.0_dp) .or. .not. (v > 0.0_dp)) return
    share = min(1.0_dp, v / avail)
    call cell_range(lin, za, zb, i0, i1)
    do i = i0, i1
      f = share_in(lin, i, min(za, zb), max(za, zb))
      if (f <= 0.0_dp) cycle
      taken = taken + share * lin%h(i) * lin%dz * f
      lin%h(i) = lin%h(i) * (1.0_dp - share * f)
    end do
  end subroutine strip_draw

  !> Spread volume v [m^2] evenly over the strip (over the nearest cell if it has no length
  !> on the grid). Returns in `put` what was placed (v, unless the strip lies off the grid).
  pure subroutine strip_put(lin, za, zb, v, put)
    type(liner_type), intent(inout) :: lin
    real(dp), intent(in) :: za, zb, v
    real(dp), intent(out) :: put
    real(dp) :: o, length
    integer :: i, i0, i1
    put = 0.0_dp
    call cell_range(lin, za, zb, i0, i1)
    length = 0.0_dp
    do i = i0, i1
      length = length + overlap(lin, i, min(za, zb), max(za, zb))
    end do
    if (length <= 0.0_dp) then
      i = min(max(1, floor((0.5_dp * (za + zb) - lin%z0) / lin%dz) + 1), lin%nz)
      call occupy(lin, i, lin%z0 + (i - 1) * lin%dz, lin%z0 + i * lin%dz)
      lin%h(i) = lin%h(i) + v / lin%dz
      put = v
      return
    end if
    do i = i0, i1
      o = overlap(lin, i, min(za, zb), max(za, zb))
      if (o <= 0.0_dp) cycle
      call occupy(lin, i, max(min(za, zb), lin%z0 + (i - 1) * lin%dz), &
                  min(max(za, zb), lin%z0 + i * lin%dz))
      lin%h(i) = lin%h(i) + v * (o / length) / lin%dz
      put = put + v * (o / length)
    end do
  end subroutine strip_put

  !> Where the oil of cell i lies after oil is put on [a, b] of it: on [a, b] if the cell was
  !> empty, else spread over the span of both.
  pure subroutine occupy(lin, i, a, b)
    type(liner_type), intent(inout) :: lin
    integer, intent(in) :: i
    real(dp), intent(in) :: a, b
    if (lin%h(i) > 0.0_dp) then
      lin%lo(i) = min(lin%lo(i), a)
      lin%hi(i) = max(lin%hi(i), b)
    else
      lin%lo(i) = a
      lin%hi(i) = b
    end if
  end subroutine occupy

  !> The film of `src` (a liner on the same grid) on the cells whose centres lie on the strip
  !> between za and zb (either order) replaces lin's there, where its oil lies included.
  pure subroutine strip_copy(lin, src, za, zb)
    type(liner_type), intent(inout) :: lin
    type(liner_type), intent(in) :: src
    real(dp), intent(in) :: za, zb
    integer :: i0, i1
    i0 = max(1, ceiling((min(za, zb) - lin%z0) / lin%dz + 0.5_dp))
    i1 = min(lin%nz, floor((max(za, zb) - lin%z0) / lin%dz + 0.5_dp))
    if (i1 < i0) return
    lin%h(i0:i1) = src%h(i0:i1)
    lin%lo(i0:i1) = src%lo(i0:i1)
    lin%hi(i0:i1) = src%hi(i0:i1)
  end subroutine strip_copy

  !> Set the film on the strip to thickness hf; returns the volumes removed and added [m^2].
  pure subroutine strip_set(lin, za, zb, hf, removed, added)
    type(liner_type), intent(inout) :: lin
    real(dp), intent(in) :: za, zb, hf
    real(dp), intent(out) :: removed, added
    real(dp) :: put
    call strip_take(lin, za, zb, removed)
    call strip_put(lin, za, zb, hf * abs(zb - za), put)
    added = put
  end subroutine strip_set
end module ringlube_liner
