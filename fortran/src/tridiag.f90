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
    call sweep(a, b, c, d, x, info, work, fixed, value)
  end subroutine thomas_fixed

  !> The one elimination of `thomas` and `thomas_fixed`: forward sweep with the modified
  !> upper diagonal in `cp` and the modified right-hand side in `x`, then back
  !> substitution. Rows with `fixed(i)` (when given) are `x(i) = value`.
  pure subroutine sweep(a, b, c, d, x, info, cp, fixed, value)
    real(dp), intent(in) :: a(:), b(:), c(:), d(:)
    real(dp), intent(out) :: x(:)
    integer, intent(out) :: info
    real(dp), intent(inout) :: cp(:)
    logical, intent(in), optional :: fixed(:)
    real(dp), intent(in), optional :: value
    real(dp) :: m, r
    integer :: i, n
    n = size(b)
    info = 0
    do i = 1, n
      if (present(fixed)) then
        if (fixed(i)) then
          cp(i) = 0.0_dp
          x(i) = value
          cycle
        end if
      end if
      if (i == 1) then
        m = b(1)
        r = d(1)
      else
        m = b(i) - a(i) * cp(i - 1)
        r = d(i) - a(i) * x(i - 1)
      end if
      if (m == 0.0_dp) then
        info = i
        x = 0.0_dp
        return
      end if
      m = 1.0_dp / m
      cp(i) = c(i) * m
      x(i) = r * m
    end do
    do i = n - 1, 1, -1
      x(i) = x(i) - cp(i) * x(i + 1)
    end do
  end subroutine sweep
end module ringlube_tridiag
