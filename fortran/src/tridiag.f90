!> Tridiagonal linear systems.
module ringlube_tridiag
  use ringlube_kinds, only: dp
  implicit none
  private
  public :: thomas

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
      allocate(cp(size(b)))
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
      m = b(i) - a(i) * cp(i-1)
      if (m == 0.0_dp) then
        info = i
        x = 0.0_dp
        return
      end if
      m = 1.0_dp / m
      cp(i) = c(i) * m
      x(i) = (d(i) - a(i) * x(i-1)) * m
    end do
    do i = n - 1, 1, -1
      x(i) = x(i) - cp(i) * x(i+1)
    end do
  end subroutine sweep
end module ringlube_tridiag
