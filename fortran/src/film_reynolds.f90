!> The Swift-Stieber film: the Reynolds equation with its cavitation
!> condition inside the pressure-viscosity loop, at the trial h0 in f%h.
module ringlube_film_reynolds
  use ringlube_kinds, only: dp
  use ringlube_case, only: case_type
  use ringlube_viscosity, only: roelands_eta
  use ringlube_reynolds, only: reynolds_solve, reynolds_problem
  use ringlube_results, only: flag_cavitation
  use ringlube_film_state, only: film_type, lower_edge_pressure, start_viscosity, conductance, &
                                 update_viscosity, film_loads, roelands_p_max
  implicit none
  private
  public :: reynolds_evaluate

contains

  !> The Swift-Stieber film at the trial h0 in f%h (set by film_evaluate, which documents the
  !> pressure-viscosity loop): `sq` 2 dh0/dt, `u` the sliding speed (its sign picks the inlet
  !> for the Reynolds outlet), `p_chamber` the chamber edge's pressure, `w_tol` [N] the load
  !> tolerance.
  pure subroutine reynolds_evaluate(c, f, sq, u, p_chamber, w_tol)
    type(case_type), intent(in) :: c
    type(film_type), intent(inout) :: f
    real(dp), intent(in) :: sq, u, p_chamber, w_tol
    real(dp) :: pl, pr
    integer :: it, iters, info, n
    logical :: settled
    type(reynolds_problem) :: prob

    n = f%n
    pl = p_chamber
    pr = lower_edge_pressure(c, f)
    f%trailing_cavitated = .false.
    if (c%outlet == 'reynolds') then
      f%trailing_cavitated = .true.
      if (f%lead_left) then
        pr = c%cavitation_pressure
      else
        pl = c%cavitation_pressure
      end if
    end if

    ! The pressure-viscosity loop starts from the previous trial's pressure, where the fixed
    ! point is a contraction and unique (ring pressures, far below 100 MPa). After a trial
    ! above 100 MPa it starts from the isoviscous film (eta at p = 0) instead: from a
    ! high-pressure state the iteration can land on a second, high-pressure branch and make
    ! W(h0) jump, which the load balance cannot bracket.
    prob = reynolds_problem(dx=f%dx, u=u, sq=sq, p_left=pl, p_right=pr, &
                            p_cav=c%cavitation_pressure)
    call start_viscosity(c, f)
    do it = 1, c%max_pressure_iterations
      call conductance(f, 6.0_dp)
      call reynolds_solve(prob, f%kmid, f%hmid, f%p, f%active, iters, info, f%work)
      f%reynolds_solves = f%reynolds_solves + iters
      if (info == 1) f%flags = ior(f%flags, flag_cavitation)
      if (info == 2) then
        ! singular system: cannot happen for h > 0; keep a finite state and flag it
        f%p = max(pl, pr)
        f%flags = ior(f%flags, flag_cavitation)
        if (c%roelands) f%eta = roelands_eta(f%law, min(max(f%p, 0.0_dp), roelands_p_max))
        exit
      end if
      if (.not. c%roelands) exit
      call update_viscosity(c, f, w_tol, it, settled)
      if (settled) exit
    end do

    call film_loads(c, f)
  end subroutine reynolds_evaluate
end module ringlube_film_reynolds
