!> The film's state at one crank step (its grid, profile and the warm starts of either film
!> model), its setup, and what both film models share: the gas pressure at the lower edge, the
!> pressure-viscosity loop's start and step, and the loads of a solved film.
module ringlube_film_state
  use ringlube_kinds, only: dp, pi
  use ringlube_case, only: case_type, composite_sigma, reduced_modulus, face_profile, &
                           liner_temperature_at, uniform_liner
  use ringlube_kinematics, only: deg2rad, piston_position
  use ringlube_viscosity, only: roelands_law, roelands_law_at, roelands_eta, roelands_update
  use ringlube_contact, only: asperity_contact, contact_params
  use ringlube_reynolds, only: reynolds_work, reynolds_work_init
  use ringlube_jfo_system, only: jfo_system, jfo_scratch
  use ringlube_results, only: flag_viscosity, flag_piezo
  implicit none
  private
  public :: film_type, film_setup, lower_edge_pressure, start_viscosity, conductance, &
            update_viscosity, film_loads, film_temperature, film_copy

  !> A copy of an allocatable array that keeps the destination's storage when the shapes match.
  interface copy_array
    module procedure copy_real, copy_logical
  end interface copy_array

  !> Roelands is evaluated with the pressure clipped here [Pa]. Ring pressures are far
  !> lower; only trial films far below the load-balance root reach it, where an unclipped
  !> pressure-viscosity iteration runs away to overflow.
  real(dp), parameter, public :: roelands_p_max = 1e9_dp

  !> Workspace of the film at one crank step.
  type :: film_type
    integer :: n = 0
    real(dp) :: dx = 0.0_dp, circ = 0.0_dp, sigma = 0.0_dp, eta_e = 0.0_dp
    !> the asperity contact of the run (ringlube_contact)
    type(contact_params) :: contact
    real(dp), allocatable :: x(:), s(:), smid(:), h(:), hmid(:), p(:), eta(:), kmid(:), etamid(:)
    logical, allocatable :: active(:)
    !> scratch of the Reynolds solver, and the pressure of the last iteration
    type(reynolds_work) :: work
    real(dp), allocatable :: pold(:)
    logical :: lead_left = .true.          !< leading edge is the chamber edge (x = -b/2)
    logical :: trailing_cavitated = .false.  !< Reynolds outlet: trailing edge at p_cav
    !> Roelands' law at the film's temperature, the liner's where the ring is [K]
    type(roelands_law) :: law
    real(dp) :: temperature = 0.0_dp
    ! state of the last evaluation
    real(dp) :: h0 = -1.0_dp, wh = 0.0_dp, wa = 0.0_dp, aa = 0.0_dp
    integer :: flags = 0
    integer :: film_solves = 0             !< film solves (load-balance trials)
    integer :: reynolds_solves = 0         !< Reynolds solves (incl. pressure-viscosity loop)
    ! the mass-conserving (JFO) film: fill, its content at the last accepted step, the
    ! cavity pressures, and the oil fluxes through the first and last interior faces
    logical :: jfo = .false.
    real(dp), allocatable :: theta(:), content_old(:), pc(:)
    !> the JFO solve's system, kept between solves (its arrays allocated once)
    type(jfo_system) :: jfo_work
    type(jfo_scratch) :: jfo_scratch
    !> the oil through the left and right edge faces over the step, per unit time [m^2/s,
    !> positive towards +x]: what the liner and the bank exchange with the gap (q dt); the
    !> solve's flux at the step's end with backward Euler, its second-order filtered value
    !> with BDF2 (ringlube_film_jfo, jfo_history)
    real(dp) :: q_left = 0.0_dp, q_right = 0.0_dp, dt = 0.0_dp
    !> the solve's flux through the first and last interior faces at the step's end [m^2/s]
    real(dp) :: q_face_left = 0.0_dp, q_face_right = 0.0_dp
    !> the content's time history (BDF2 of the content, `&numerics film_time_scheme`): the content
    !> of the step before content_old (content_prev), the content_old and sliding speed of the
    !> step being solved (content_key, u_key: a new step starts when they change), theta h at
    !> the end of the last evaluation (content_end: the state the cycle accepted), the step's
    !> BDF2 weight r (0: backward Euler; 1/3: BDF2) and history content
    !> content_old + r (content_old - content_prev), and the number of accepted steps known
    real(dp), allocatable :: content_prev(:), content_key(:), content_end(:), content_hist(:)
    real(dp) :: u_key = 0.0_dp, r_step = 0.0_dp
    integer :: hist_steps = 0
    !> oil through the left and right faces over the step [m^2], for this evaluation (x_*) and
    !> the last accepted step (x_*_prev);
    !> the sign of u at the last four accepted steps and whether h0 was held at a bound at the
    !> last two
    real(dp) :: x_left = 0.0_dp, x_right = 0.0_dp
    real(dp) :: x_left_prev = 0.0_dp, x_right_prev = 0.0_dp
    integer :: sign_prev(4) = 0
    logical :: held_prev(2) = .false., held_end = .false.
    !> the face is partly filled across its width at a gas pressure above the leading edge's,
    !> whose meniscus is then at the leading edge (ringlube_jfo, jfo_solve_connected)
    logical :: blown = .false.
    !> starved inlet: oil available to the leading edge over the step [m^2] and the distance
    !> the ring moves in it [m] (set by the caller); the fill the inlet admitted
    logical :: starved = .false.
    real(dp) :: available = 0.0_dp, ds = 0.0_dp, theta_in = 1.0_dp
    !> the mass-conserving film's volumes next to the edges reach the edges (`&numerics
    !> film_edge_cells`; ringlube_jfo's jfo_problem%edge_cells): the oil in the gap counts them
    logical :: edge_cells = .false.
    !> `&numerics film_edge_cells = 'front'`: the reformation fronts' cells hold their front's
    !> oil (ringlube_jfo's jfo_problem%front_content): the content carried between steps is
    !> jfo_front_content's (content_end), not theta h
    logical :: front_content = .false.
    !> starved: oil on the liner just behind the trailing edge that it may draw back over the
    !> step [m^2]; the caps on the inflow through the left and right edge faces [m^2/s]
    real(dp) :: behind = 0.0_dp, cap_left = huge(1.0_dp), cap_right = huge(1.0_dp)
    !> the gas around the ring (docs/ring_pack.md, set by the caller with ring_pack = 'gas'): the
    !> pressure behind the ring (its gas load) and at its lower (crankcase) edge [Pa];
    !> negative: the chamber pressure behind it and the crankcase pressure below it
    real(dp) :: p_back = -1.0_dp, p_lower = -1.0_dp
    !> a sector of a distorted bore (docs/bore.md); w_gas [N, as a whole ring]: the load of the gas
    !> on a face with no full zone (an open face: all its hydrodynamic load; 0 while it seals)
    logical :: gas_channel = .false.
    real(dp) :: w_gas = 0.0_dp
    !> a sector's face had no full zone at the last accepted step (set by the cycle): it passes
    !> gas from edge to edge over this step
    logical :: face_open = .false.
  end type film_type

contains

  !> Build the grid and the profile of a case.
  pure subroutine film_setup(c, f)
    type(case_type), intent(in) :: c
    type(film_type), intent(out) :: f
    integer :: i, n
    real(dp) :: hb
    n = c%nodes
    f%n = n
    hb = 0.5_dp * c%width
    f%dx = c%width / (n - 1)
    f%circ = 2.0_dp * pi * c%bore_radius
    f%sigma = composite_sigma(c)
    f%contact = contact_params(sigma=f%sigma, zeta_kappa_sigma=c%zeta_kappa_sigma, &
                               sigma_over_kappa=c%sigma_over_kappa, e_reduced=reduced_modulus(c), &
                               fit=c%gt_functions == 'fit', lumped=c%contact_area == 'lumped', &
                               width=c%width, circumference=f%circ)
    f%temperature = c%liner_temperature
    f%law = roelands_law_at(c%liner_temperature, c%eta0, c%theta0, c%alpha, c%beta)
    f%eta_e = roelands_eta(f%law, 0.0_dp)
    allocate (f%x(n), f%s(n), f%h(n), f%p(n), f%eta(n), f%active(n))
    allocate (f%smid(n - 1), f%hmid(n - 1), f%kmid(n - 1), f%etamid(n - 1), f%pold(n))
    call reynolds_work_init(f%work, n)
    do i = 1, n
      f%x(i) = -hb + (i - 1) * f%dx
    end do
    f%x(n) = hb
    call face_profile(c, f%x, f%s, f%smid)
    f%p = c%crankcase_pressure
    f%eta = f%eta_e
    ! the viscosity of the pressure held (see film_evaluate)
    if (c%roelands) f%eta = roelands_eta(f%law, c%crankcase_pressure)
    f%active = .false.
    f%jfo = c%cavitation == 'jfo'
    f%starved = c%inlet == 'starved'
    f%edge_cells = f%jfo .and. (c%film_edge_cells == 'edge' .or. c%film_edge_cells == 'front')
    f%front_content = f%jfo .and. c%film_edge_cells == 'front'
    allocate (f%theta(n), f%content_old(n), f%pc(n))
    allocate (f%content_prev(n), f%content_key(n), f%content_end(n), f%content_hist(n))
    f%content_prev = 0.0_dp
    f%content_key = 0.0_dp
    f%content_end = 0.0_dp
    f%content_hist = 0.0_dp
    f%theta = 1.0_dp
    f%pc = c%cavitation_pressure
    f%content_old = f%s   ! a full film at h0 = 0: the caller sets it at the first h0
  end subroutine film_setup

  !> dst becomes a copy of src, every component (what the intrinsic assignment `dst = src`
  !> makes), but each allocatable array of dst whose shape matches src's keeps its storage and
  !> takes the values only: no allocation when dst already holds a film of the same nodes
  !> (the lift-off margin's and the saved states' copies, made at every step). An array is
  !> allocated anew where the shapes differ and deallocated where src's is not allocated.
  !> A component added to film_type (or to the solvers' workspaces it holds) must be added
  !> here; test_film_copy sets every component and compares.
  pure subroutine film_copy(dst, src)
    type(film_type), intent(inout) :: dst
    type(film_type), intent(in) :: src
    dst%n = src%n
    dst%dx = src%dx
    dst%circ = src%circ
    dst%sigma = src%sigma
    dst%eta_e = src%eta_e
    dst%contact = src%contact
    call copy_array(dst%x, src%x)
    call copy_array(dst%s, src%s)
    call copy_array(dst%smid, src%smid)
    call copy_array(dst%h, src%h)
    call copy_array(dst%hmid, src%hmid)
    call copy_array(dst%p, src%p)
    call copy_array(dst%eta, src%eta)
    call copy_array(dst%kmid, src%kmid)
    call copy_array(dst%etamid, src%etamid)
    call copy_array(dst%active, src%active)
    call copy_array(dst%work%a0, src%work%a0)
    call copy_array(dst%work%b0, src%work%b0)
    call copy_array(dst%work%c0, src%work%c0)
    call copy_array(dst%work%r, src%work%r)
    call copy_array(dst%work%cp, src%work%cp)
    call copy_array(dst%pold, src%pold)
    dst%lead_left = src%lead_left
    dst%trailing_cavitated = src%trailing_cavitated
    dst%law = src%law
    dst%temperature = src%temperature
    dst%h0 = src%h0
    dst%wh = src%wh
    dst%wa = src%wa
    dst%aa = src%aa
    dst%flags = src%flags
    dst%film_solves = src%film_solves
    dst%reynolds_solves = src%reynolds_solves
    dst%jfo = src%jfo
    call copy_array(dst%theta, src%theta)
    call copy_array(dst%content_old, src%content_old)
    call copy_array(dst%pc, src%pc)
    call copy_system(dst%jfo_work, src%jfo_work)
    call copy_scratch(dst%jfo_scratch, src%jfo_scratch)
    dst%q_left = src%q_left
    dst%q_right = src%q_right
    dst%dt = src%dt
    dst%q_face_left = src%q_face_left
    dst%q_face_right = src%q_face_right
    call copy_array(dst%content_prev, src%content_prev)
    call copy_array(dst%content_key, src%content_key)
    call copy_array(dst%content_end, src%content_end)
    call copy_array(dst%content_hist, src%content_hist)
    dst%u_key = src%u_key
    dst%r_step = src%r_step
    dst%hist_steps = src%hist_steps
    dst%x_left = src%x_left
    dst%x_right = src%x_right
    dst%x_left_prev = src%x_left_prev
    dst%x_right_prev = src%x_right_prev
    dst%sign_prev = src%sign_prev
    dst%held_prev = src%held_prev
    dst%held_end = src%held_end
    dst%blown = src%blown
    dst%starved = src%starved
    dst%available = src%available
    dst%ds = src%ds
    dst%theta_in = src%theta_in
    dst%edge_cells = src%edge_cells
    dst%front_content = src%front_content
    dst%behind = src%behind
    dst%cap_left = src%cap_left
    dst%cap_right = src%cap_right
    dst%p_back = src%p_back
    dst%p_lower = src%p_lower
    dst%gas_channel = src%gas_channel
    dst%w_gas = src%w_gas
    dst%face_open = src%face_open
  end subroutine film_copy

  !> film_copy's part for the JFO solve's system (ringlube_jfo_system's jfo_system).
  pure subroutine copy_system(dst, src)
    type(jfo_system), intent(inout) :: dst
    type(jfo_system), intent(in) :: src
    dst%n = src%n
    dst%a = src%a
    dst%w = src%w
    dst%p_left = src%p_left
    dst%p_right = src%p_right
    dst%theta_left = src%theta_left
    dst%theta_right = src%theta_right
    dst%qcl = src%qcl
    dst%qcr = src%qcr
    call copy_array(dst%ca, src%ca)
    call copy_array(dst%kd, src%kd)
    call copy_array(dst%ps, src%ps)
    call copy_array(dst%h, src%h)
    call copy_array(dst%content_old, src%content_old)
    call copy_array(dst%pc, src%pc)
    call copy_array(dst%wv, src%wv)
    dst%dmax = src%dmax
    dst%edge_meniscus = src%edge_meniscus
    dst%front_content = src%front_content
    dst%edge_cells = src%edge_cells
    dst%thin_fade_from = src%thin_fade_from
    dst%thin_fade_width = src%thin_fade_width
    dst%full_hd = src%full_hd
  end subroutine copy_system

  !> film_copy's part for the JFO solve's working arrays (ringlube_jfo_system's jfo_scratch).
  pure subroutine copy_scratch(dst, src)
    type(jfo_scratch), intent(inout) :: dst
    type(jfo_scratch), intent(in) :: src
    call copy_array(dst%v, src%v)
    call copy_array(dst%vt, src%vt)
    call copy_array(dst%vpre, src%vpre)
    call copy_array(dst%vbest, src%vbest)
    call copy_array(dst%dv, src%dv)
    call copy_array(dst%r, src%r)
    call copy_array(dst%rt, src%rt)
    call copy_array(dst%tw, src%tw)
    call copy_array(dst%cp, src%cp)
    call copy_array(dst%y, src%y)
    call copy_array(dst%ev%pn, src%ev%pn)
    call copy_array(dst%ev%tn, src%ev%tn)
    call copy_array(dst%ev%fl, src%ev%fl)
    call copy_array(dst%ev%dfpl, src%ev%dfpl)
    call copy_array(dst%ev%dfpr, src%ev%dfpr)
    call copy_array(dst%ev%dftl, src%ev%dftl)
    call copy_array(dst%ev%dftr, src%ev%dftr)
    call copy_array(dst%ev%jl, src%ev%jl)
    call copy_array(dst%ev%jd, src%ev%jd)
    call copy_array(dst%ev%ju, src%ev%ju)
  end subroutine copy_scratch

  !> a becomes a copy of b (bounds and values), in a's storage where the bounds match;
  !> unallocated where b is.
  pure subroutine copy_real(a, b)
    real(dp), allocatable, intent(inout) :: a(:)
    real(dp), allocatable, intent(in) :: b(:)
    if (allocated(a)) then
      if (.not. allocated(b)) then
        deallocate (a)
      else if (lbound(a, 1) /= lbound(b, 1) .or. ubound(a, 1) /= ubound(b, 1)) then
        deallocate (a)
      end if
    end if
    if (.not. allocated(b)) return
    if (.not. allocated(a)) allocate (a(lbound(b, 1):ubound(b, 1)))
    a(:) = b(:)
  end subroutine copy_real

  !> copy_real for a logical array.
  pure subroutine copy_logical(a, b)
    logical, allocatable, intent(inout) :: a(:)
    logical, allocatable, intent(in) :: b(:)
    if (allocated(a)) then
      if (.not. allocated(b)) then
        deallocate (a)
      else if (lbound(a, 1) /= lbound(b, 1) .or. ubound(a, 1) /= ubound(b, 1)) then
        deallocate (a)
      end if
    end if
    if (.not. allocated(b)) return
    if (.not. allocated(a)) allocate (a(lbound(b, 1):ubound(b, 1)))
    a(:) = b(:)
  end subroutine copy_logical

  !> The film's temperature for the step to crank angle psi [deg]: the liner's where the ring
  !> is (liner_temperature_at), with Roelands' law at it and the viscosity of the pressure
  !> held (the warm start of the next solve) under that law. One liner temperature: the law of
  !> film_setup, unchanged.
  pure subroutine film_temperature(c, f, psi)
    type(case_type), intent(in) :: c
    type(film_type), intent(inout) :: f
    real(dp), intent(in) :: psi
    real(dp) :: theta
    if (uniform_liner(c)) return
    theta = liner_temperature_at(c, piston_position(deg2rad(psi), c%crank_radius, &
                                                    c%conrod_length))
    if (theta == f%temperature) return
    f%temperature = theta
    f%law = roelands_law_at(theta, c%eta0, c%theta0, c%alpha, c%beta)
    f%eta_e = roelands_eta(f%law, 0.0_dp)
    if (c%roelands) then
      f%eta = roelands_eta(f%law, min(max(f%p, 0.0_dp), roelands_p_max))
    else
      f%eta = f%eta_e
    end if
  end subroutine film_temperature

  !> Gas pressure at the ring's lower (crankcase) edge [Pa]: the land pressure with the ring
  !> pack, else the crankcase pressure.
  pure real(dp) function lower_edge_pressure(c, f) result(p)
    type(case_type), intent(in) :: c
    type(film_type), intent(in) :: f
    p = c%crankcase_pressure
    if (f%p_lower >= 0.0_dp) p = f%p_lower
  end function lower_edge_pressure

  !> The viscosity the pressure-viscosity loop of either film model starts from: the previous
  !> trial's, or the isoviscous film's (eta at p = 0) after a trial above 100 MPa or without
  !> Roelands.
  pure subroutine start_viscosity(c, f)
    type(case_type), intent(in) :: c
    type(film_type), intent(inout) :: f
    if (maxval(f%p) > 1e8_dp) then
      f%p = 0.0_dp
      f%eta = f%eta_e
    end if
    if (.not. c%roelands) f%eta = f%eta_e
  end subroutine start_viscosity

  !> Face conductances kmid = hmid^3 / (factor eta_mid) for the next solve (factor 6 in the
  !> Swift-Stieber film's form, 12 in the JFO solve's), the pressure kept as the old one.
  pure subroutine conductance(f, factor)
    type(film_type), intent(inout) :: f
    real(dp), intent(in) :: factor
    integer :: n
    n = f%n
    f%etamid = 0.5_dp * (f%eta(1:n - 1) + f%eta(2:n))
    f%kmid = f%hmid**3 / (factor * f%etamid)
    f%pold = f%p
  end subroutine conductance

  !> One step of the pressure-viscosity loop of either film model, after a solve: the
  !> viscosity of the new pressure (once per node and iteration; only where the pressure
  !> changed, e.g. not in a cavity held at its pressure), kept for the next iteration or the
  !> next trial. `done` when the loop may stop (see film_evaluate); flags a loop that reaches
  !> max_pressure_iterations.
  pure subroutine update_viscosity(c, f, w_tol, it, done)
    type(case_type), intent(in) :: c
    type(film_type), intent(inout) :: f
    real(dp), intent(in) :: w_tol
    integer, intent(in) :: it
    logical, intent(out) :: done
    real(dp) :: dvisc
    integer :: n
    n = f%n
    call roelands_update(f%law, n, f%p, f%pold, roelands_p_max, f%eta, dvisc)
    f%wh = f%circ * f%dx * (sum(f%p) - 0.5_dp * (f%p(1) + f%p(n)))
    done = dvisc * abs(f%wh) <= 0.1_dp * w_tol
    if (.not. done) done = sum(abs(f%p - f%pold)) <= c%pressure_tol * sum(abs(f%p))
    if (.not. done .and. it == c%max_pressure_iterations) f%flags = ior(f%flags, flag_viscosity)
  end subroutine update_viscosity

  !> The loads of a solved film: W_h (trapezoidal rule) and the asperity load and area.
  !> A blown face (the gas in it reaching the leading edge, see film_type) has its meniscus at
  !> the leading edge: the gas pressure acts up to the edge, so the leading edge's interval
  !> carries the pressure of its interior node, not the mean with the edge's lower gas pressure
  !> (whose share, (p_gas - p_edge) dx / 2, is a cell-size error).
  pure subroutine film_loads(c, f)
    type(case_type), intent(in) :: c
    type(film_type), intent(inout) :: f
    integer :: n
    real(dp) :: pl, pr
    n = f%n
    if (c%roelands .and. maxval(f%p) > roelands_p_max) f%flags = ior(f%flags, flag_piezo)
    pl = f%p(1)
    pr = f%p(n)
    if (f%jfo .and. f%blown) then
      if (f%lead_left) then
        pl = max(pl, f%p(2))
      else
        pr = max(pr, f%p(n - 1))
      end if
    end if
    f%wh = f%circ * f%dx * (sum(f%p(2:n - 1)) + 0.5_dp * (pl + pr))
    ! the gas's share: all of an open face's load (a face with no full zone is at the gas
    ! pressures its connectivity rule gives it)
    f%w_gas = 0.0_dp
    if (f%gas_channel .and. f%jfo) then
      if (all(f%theta(2:n - 1) < 1.0_dp)) f%w_gas = f%wh
    end if
    if (c%asperity_contact) then
      call asperity_contact(f%contact, f%h, f%h0, f%dx, f%wa, f%aa)
    else
      f%wa = 0.0_dp
      f%aa = 0.0_dp
    end if
  end subroutine film_loads
end module ringlube_film_state
