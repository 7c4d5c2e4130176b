! ctest labels: unit
!> Thomas algorithm against LAPACK dgtsv on random diagonally dominant systems.
program test_tridiag
  use ringlube_kinds, only: dp
  use ringlube_tridiag, only: thomas
  use ringlube_check
  implicit none
  integer, parameter :: sizes(4) = [2, 5, 101, 2001]
  integer :: is, n, info, trial
  real(dp), allocatable :: a(:), b(:), c(:), d(:), x(:), dl(:), dd(:), du(:), rhs(:, :)
  character(len=64) :: what
  real(dp) :: y(2)
  external :: dgtsv

  call random_seed(put=[(12345 + is, is=1, 64)])
  do is = 1, size(sizes)
    n = sizes(is)
    do trial = 1, 5
      allocate (a(n), b(n), c(n), d(n), x(n), dl(n - 1), dd(n), du(n - 1), rhs(n, 1))
      call random_number(a); call random_number(c); call random_number(d)
      a = a - 0.5_dp; c = c - 0.5_dp; d = 1e5_dp * (d - 0.5_dp)
      call random_number(b)
      b = abs(a) + abs(c) + 0.01_dp + b   ! strictly diagonally dominant
      if (mod(trial, 2) == 0) b = -b
      call thomas(a, b, c, d, x, info)
      write (what, '(a, i0, a, i0)') 'thomas info n=', n, ' trial ', trial
      call check(info == 0, trim(what))
      dl = a(2:n); dd = b; du = c(1:n - 1); rhs(:, 1) = d
      call dgtsv(n, 1, dl, dd, du, rhs, n, info)
      call check(info == 0, 'dgtsv info')
      write (what, '(a, i0, a, i0)') 'thomas vs dgtsv n=', n, ' trial ', trial
      call check(maxval(abs(x - rhs(:, 1))) <= 1e-12_dp * maxval(abs(rhs(:, 1))), trim(what))
      deallocate (a, b, c, d, x, dl, dd, du, rhs)
    end do
  end do
  ! a zero pivot is reported, not divided by
  call thomas([0.0_dp, 1.0_dp], [0.0_dp, 1.0_dp], [1.0_dp, 0.0_dp], [1.0_dp, 1.0_dp], &
              y, info)
  call check(info == 1, 'zero pivot reported')
  call report('test_tridiag')
end program test_tridiag
