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
  pure subroutine thomas(a, b, c, d, x, info)
    real(dp), intent(in) :: a(:), b(:), c(:), d(:)
    real(dp), intent(out) :: x(:)
    integer, intent(out) :: info
    real(dp) :: cp(size(b)), dp_(size(b)), m
    integer :: i, n

    n = size(b)
    info = 0
    if (b(1) == 0.0_dp) then
      info = 1
      x = 0.0_dp
      return
    end if
    cp(1) = c(1) / b(1)
    dp_(1) = d(1) / b(1)
    do i = 2, n
      m = b(i) - a(i) * cp(i-1)
      if (m == 0.0_dp) then
        info = i
        x = 0.0_dp
        return
      end if
      cp(i) = c(i) / m
      dp_(i) = (d(i) - a(i) * dp_(i-1)) / m
    end do
    x(n) = dp_(n)
    do i = n - 1, 1, -1
      x(i) = dp_(i) - cp(i) * x(i+1)
    end do
  end subroutine thomas
end module ringlube_tridiag
