!> Reference solver for tests/fortran/test_jfo.f90 and tests/bench/bench_jfo.f90: the Elrod /
!> Ausas et al. relaxation for the p-theta film, written independently of ringlube_jfo on the
!> primitive unknowns (p, theta) and with its own flux routine, on the same finite volumes
!> (face flux a theta_up hmid - kmid (p(f+1) - p(f))/dx theta_P, see docs/film_model.md).
!>
!> Each sweep visits the interior nodes downstream; a node in full film (p > pc or theta = 1)
!> gets an over-relaxed pressure update from its own equation at theta = 1 and is cut at pc;
!> a node at pc gets theta from its own equation at p = pc and is cut at 1 (Ausas, Jai and
!> Buscaglia 2009, J. Tribol. 131:031702). Sweeps stop when no value moves by more than tol
!> (relative to the pressure scale for p, absolute for theta).
module jfo_reference
  use ringlube_kinds, only: dp
  implicit none
  private
  public :: elrod_solve

contains

  subroutine elrod_solve(dx, h, hmid, kmid, u, dt, cold, p_left, p_right, th_left, th_right, pc, &
                         p, theta, sweeps, tol, omega, max_sweeps)
    real(dp), intent(in) :: dx, h(:), hmid(:), kmid(:), u, dt, cold(:)
    real(dp), intent(in) :: p_left, p_right, th_left, th_right, pc(:), tol, omega
    real(dp), intent(inout) :: p(:), theta(:)
    integer, intent(out) :: sweeps
    integer, intent(in) :: max_sweeps
    real(dp) :: a, w, pscale, change, r, slope, pnew, tnew, g
    integer :: n, j, k, j0, j1, st

    n = size(h)
    a = -0.5_dp * u
    w = 0.0_dp
    if (dt > 0.0_dp) w = dx / dt
    p(1) = p_left
    p(n) = p_right
    theta(1) = th_left
    theta(n) = th_right
    pscale = max(maxval(abs(pc)), abs(p_left), abs(p_right), 1.0_dp)
    if (a >= 0.0_dp) then
      j0 = 2; j1 = n - 1; st = 1
    else
      j0 = n - 1; j1 = 2; st = -1
    end if
    do k = 1, max_sweeps
      sweeps = k
      change = 0.0_dp
      do j = j0, j1, st
        if (p(j) > pc(j) .or. theta(j) >= 1.0_dp) then
          theta(j) = 1.0_dp
          r = row(j)
          slope = kmid(j) / dx * up_p(j, j + 1) + kmid(j - 1) / dx * up_p(j, j - 1)
          pnew = p(j) - omega * r / slope
          if (pnew < pc(j)) pnew = pc(j)
          change = max(change, abs(pnew - p(j)) / pscale)
          p(j) = pnew
        end if
        if (p(j) <= pc(j)) then
          p(j) = pc(j)
          r = row(j)
          slope = w * h(j)
          if (a > 0.0_dp) slope = slope + a * hmid(j)
          if (a < 0.0_dp) slope = slope - a * hmid(j - 1)
          g = kmid(j) / dx * (p(j + 1) - p(j))
          if (g <= 0.0_dp) slope = slope - g
          g = kmid(j - 1) / dx * (p(j) - p(j - 1))
          if (g > 0.0_dp) slope = slope + g
          tnew = min(theta(j) - r / slope, 1.0_dp)
          change = max(change, abs(tnew - theta(j)))
          theta(j) = tnew
        end if
      end do
      if (change < tol) exit
    end do

  contains

    !> the fill carried by pressure between node j and its neighbour m: upwind in pressure
    real(dp) function up_p(j, m)
      integer, intent(in) :: j, m
      if (p(j) >= p(m)) then
        up_p = 1.0_dp
      else
        up_p = theta(m)
      end if
    end function up_p

    real(dp) function flux(f)
      integer, intent(in) :: f
      real(dp) :: tc, tp, dpf
      tc = theta(f + 1)
      if (a > 0.0_dp) tc = theta(f)
      dpf = p(f + 1) - p(f)
      tp = theta(f + 1)
      if (dpf <= 0.0_dp) tp = theta(f)
      flux = a * hmid(f) * tc - kmid(f) / dx * dpf * tp
    end function flux

    real(dp) function row(j)
      integer, intent(in) :: j
      row = w * (theta(j) * h(j) - cold(j)) + flux(j) - flux(j - 1)
    end function row
  end subroutine elrod_solve
end module jfo_reference
