!> Tridiagonal linear systems.
module ringlube_tridiag
  use ringlube_kinds, only: dp
  implicit none
  private
  public :: thomas, thomas_fixed

contains

  !> Solve a tridiagonal system with the Thomas algorithm (no pivoting).
  !>
  !> Row i reads `a(i) x(i-1) + b(i) x(i) + c(i) x(i+1) = d(i)`; `a(1)` and `c(n)` are
  !> ignored. Stable for diagonally dominant or M-matrix systems, which is what the
  !> Reynolds discretisation produces. `info` is nonzero if a zero pivot was met.
  !> `work` (optional, size >= n) is scratch space for the modified upper diagonal; the
  !> modified right-hand side is kept in `x`. One division per row.
  pure subroutine thomas(a, b, c, d, x, info, work)
    real(dp), intent(in) :: a(:), b(:), c(:), d(:)
    real(dp), intent(out) :: x(:)
    integer, intent(out) :: info
    real(dp), intent(inout), optional :: work(:)
    real(dp), allocatable :: cp(:)
    if (present(work)) then
      call sweep(a, b, c, d, x, info, work)
    else
      allocate (cp(size(b)))
      call sweep(a, b, c, d, x, info, cp)
    end if
  end subroutine thomas

  pure subroutine sweep(a, b, c, d, x, info, cp)
    real(dp), intent(in) :: a(:), b(:), c(:), d(:)
    real(dp), intent(out) :: x(:)
    integer, intent(out) :: info
    real(dp), intent(inout) :: cp(:)
    real(dp) :: m
    integer :: i, n
    n = size(b)
    info = 0
    if (b(1) == 0.0_dp) then
      info = 1
      x = 0.0_dp
      return
    end if
    m = 1.0_dp / b(1)
    cp(1) = c(1) * m
    x(1) = d(1) * m
    do i = 2, n
      m = b(i) - a(i) * cp(i - 1)
      if (m == 0.0_dp) then
        info = i
        x = 0.0_dp
        return
      end if
      m = 1.0_dp / m
      cp(i) = c(i) * m
      x(i) = (d(i) - a(i) * x(i - 1)) * m
    end do
    do i = n - 1, 1, -1
      x(i) = x(i) - cp(i) * x(i + 1)
    end do
  end subroutine sweep

  !> The Thomas algorithm with some unknowns fixed: rows with `fixed(i)` read
  !> `x(i) = value` (as if a(i) = c(i) = 0, b(i) = 1, d(i) = value), the other rows as in
  !> `thomas`. The fixed rows cost no division and the system needs no copy with those
  !> rows replaced (the Reynolds solver's cavitated nodes). `work` (size >= n): scratch.
  pure subroutine thomas_fixed(a, b, c, d, fixed, value, x, info, work)
    real(dp), intent(in) :: a(:), b(:), c(:), d(:), value
    logical, intent(in) :: fixed(:)
    real(dp), intent(out) :: x(:)
    integer, intent(out) :: info
    real(dp), intent(inout) :: work(:)
    real(dp) :: m
    integer :: i, n
    n = size(b)
    info = 0
    if (fixed(1)) then
      work(1) = 0.0_dp
      x(1) = value
    else
      if (b(1) == 0.0_dp) then
        info = 1
        x = 0.0_dp
        return
      end if
      m = 1.0_dp / b(1)
      work(1) = c(1) * m
      x(1) = d(1) * m
    end if
    do i = 2, n
      if (fixed(i)) then
        work(i) = 0.0_dp
        x(i) = value
        cycle
      end if
      m = b(i) - a(i) * work(i - 1)
      if (m == 0.0_dp) then
        info = i
        x = 0.0_dp
        return
      end if
      m = 1.0_dp / m
      work(i) = c(i) * m
      x(i) = (d(i) - a(i) * x(i - 1)) * m
    end do
    do i = n - 1, 1, -1
      x(i) = x(i) - work(i) * x(i + 1)
    end do
  end subroutine thomas_fixed
end module ringlube_tridiag
