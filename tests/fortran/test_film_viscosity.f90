! ctest labels: numerics
!> The pressure-viscosity loop's stopping rule (film_evaluate): stopped when the viscosity
!> update moves the load by less than a tenth of the caller's load tolerance w_tol, the
!> film's load must lie within w_tol/10 of the fully converged fixed point (pressure_tol
!> 1e-14, w_tol 0), from warm starts at other trial films, at ring pressures up to the
!> combustion peak (60 bar in the chamber, where alpha p is largest).
program test_film_viscosity
  use ringlube_kinds, only: dp
  use ringlube_case, only: case_type, default_case, elastic_pressure
  use ringlube_film, only: film_type, film_setup, film_evaluate
  use ringlube_greenwood_tripp, only: gt_init
  use ringlube_check
  implicit none
  type(case_type) :: c, ctight
  real(dp) :: p_ch(3), w_tol, w_ref, load, h0, start
  integer :: i, j, solves_loose, solves_tight
  character(len=80) :: what

  call gt_init()
  c = default_case()
  ctight = c
  ctight%pressure_tol = 1e-14_dp
  p_ch = [1e5_dp, 2e6_dp, 6e6_dp]
  solves_loose = 0
  solves_tight = 0
  do i = 1, size(p_ch)
    load = (elastic_pressure(c) + p_ch(i)) * c%width * 2.0_dp * acos(-1.0_dp) * c%bore_radius
    w_tol = c%load_tol * load
    do j = 1, 4
      h0 = 0.6e-6_dp * j
      start = h0 * merge(1.05_dp, 0.95_dp, mod(j, 2) == 0)
      call solve(ctight, 0.0_dp, w_ref, solves_tight)
      call solve(c, w_tol, load, solves_loose)
      write (what, '(a, es9.2, a, es9.2, a)') &
        'load within w_tol/10 of the fixed point (p_chamber ', &
        p_ch(i), ', h0 ', h0, ')'
      call check(abs(load - w_ref) <= 0.1_dp * w_tol, trim(what))
      if (abs(load - w_ref) > 0.1_dp * w_tol) write (*, '(a, 3es12.4)') '  W, W_ref, w_tol: ', &
        load, w_ref, w_tol
      load = (elastic_pressure(c) + p_ch(i)) * c%width * 2.0_dp * acos(-1.0_dp) * c%bore_radius
    end do
  end do
  write (*, '(a, 2i6)') 'Reynolds solves, load criterion / pressure_tol 1e-14: ', solves_loose, &
    solves_tight
  call check(solves_loose < solves_tight, 'the load criterion saves Reynolds solves')
  call report('test_film_viscosity')

contains

  !> Film load W_h [N] at h0 (mid-stroke, u = -10 m/s, chamber at p_ch(i)), warm-started
  !> from the film solved at `start`; adds the Reynolds solves of the second solve.
  subroutine solve(cc, wt, w, count)
    type(case_type), intent(in) :: cc
    real(dp), intent(in) :: wt
    real(dp), intent(out) :: w
    integer, intent(inout) :: count
    type(film_type) :: f
    integer :: before
    call film_setup(cc, f)
    call film_evaluate(cc, f, start, 0.0_dp, -10.0_dp, p_ch(i), 0.0_dp)
    before = f%reynolds_solves
    call film_evaluate(cc, f, h0, 0.0_dp, -10.0_dp, p_ch(i), wt)
    count = count + f%reynolds_solves - before
    w = f%wh
    call check(f%flags == 0, 'film solve unflagged')
  end subroutine solve
end program test_film_viscosity
