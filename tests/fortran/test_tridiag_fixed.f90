! ctest labels: unit
!> thomas_fixed (unknowns held at a value without rewriting their rows) against LAPACK
!> dgtsv on the same systems with those rows replaced by x(i) = value, on random
!> diagonally dominant systems with random sets of fixed rows (none, some, the first,
!> the last, runs of neighbours).
program test_tridiag_fixed
  use ringlube_kinds, only: dp
  use ringlube_tridiag, only: thomas_fixed
  use ringlube_check
  implicit none
  integer, parameter :: sizes(4) = [2, 7, 51, 801]
  integer :: is, n, info, trial, i
  real(dp), allocatable :: a(:), b(:), c(:), d(:), x(:), dl(:), dd(:), du(:), rhs(:, :), u(:), w(:)
  logical, allocatable :: fixed(:)
  real(dp) :: value
  character(len=64) :: what
  external :: dgtsv

  call random_seed(put=[(4321 + is, is=1, 64)])
  do is = 1, size(sizes)
    n = sizes(is)
    do trial = 1, 6
      allocate (a(n), b(n), c(n), d(n), x(n), dl(n - 1), dd(n), du(n - 1), rhs(n, 1), u(n), w(n), &
                fixed(n))
      call random_number(a); call random_number(c); call random_number(d)
      a = -a; c = -c; d = 1e5_dp * (d - 0.5_dp)
      call random_number(b)
      b = abs(a) + abs(c) + 0.01_dp + b
      call random_number(u)
      select case (trial)
      case (1)
        fixed = .false.
      case (2)
        fixed = u < 0.3_dp
      case (3)
        fixed = u < 0.7_dp
        fixed(1) = .true.
      case (4)
        fixed = .false.
        fixed(n) = .true.
      case (5)   ! a run of neighbours, as a cavitated zone
        fixed = .false.
        fixed(n / 2:n - 1) = .true.
      case default
        fixed = .true.
      end select
      value = 1234.5_dp
      call thomas_fixed(a, b, c, d, fixed, value, x, info, w)
      write (what, '(a, i0, a, i0)') 'thomas_fixed info n=', n, ' case ', trial
      call check(info == 0, trim(what))
      ! the same system with the fixed rows written out, solved by LAPACK
      dd = b; dl = a(2:n); du = c(1:n - 1); rhs(:, 1) = d
      do i = 1, n
        if (.not. fixed(i)) cycle
        dd(i) = 1.0_dp
        rhs(i, 1) = value
        if (i > 1) dl(i - 1) = 0.0_dp
        if (i < n) du(i) = 0.0_dp
      end do
      call dgtsv(n, 1, dl, dd, du, rhs, n, info)
      write (what, '(a, i0, a, i0)') 'thomas_fixed vs dgtsv n=', n, ' case ', trial
      call check(maxval(abs(x - rhs(:, 1))) <= 1e-12_dp * maxval(abs(rhs(:, 1))), trim(what))
      call check(all(pack(x, fixed) == value), 'fixed unknowns exactly at their value')
      deallocate (a, b, c, d, x, dl, dd, du, rhs, u, w, fixed)
    end do
  end do
  call report('test_tridiag_fixed')
end program test_tridiag_fixed
