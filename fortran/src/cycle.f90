!> One engine cycle of the ring: load balance at every crank step, periodic state,
!> friction, power and energy (SPEC sections 4, 7, 8).
module ringlube_cycle
  use ringlube_kinds, only: dp, pi
  use ringlube_error, only: error_type, fatal_error, rl_runtime_error
  use ringlube_case, only: case_type, validate_case, composite_sigma, reduced_modulus, &
    elastic_pressure, ring_profile, ring_mass, steps_per_cycle
  use ringlube_kinematics, only: sliding_speed, deg2rad
  use ringlube_viscosity, only: roelands
  use ringlube_greenwood_tripp, only: gt_init
  use ringlube_contact, only: asperity_contact
  use ringlube_reynolds, only: reynolds_solve
  use ringlube_gas, only: gas_pressure
  use, intrinsic :: ieee_arithmetic, only: ieee_is_finite
  implicit none
  private
  public :: result_type, solve_cycle, film_type, film_setup, film_evaluate, film_friction

  !> Per-step flag bits (dataset `/cycle/flags`).
  integer, parameter, public :: flag_floor = 1        !< h0 held at h0_floor
  integer, parameter, public :: flag_ceiling = 2      !< h0 held at h0_ceiling
  integer, parameter, public :: flag_load = 4         !< load balance outside load_tol
  integer, parameter, public :: flag_viscosity = 8    !< pressure-viscosity loop not converged
  integer, parameter, public :: flag_cavitation = 16  !< cavitation active set not settled
  integer, parameter, public :: flag_piezo = 32       !< film pressure above roelands_p_max

  !> Roelands is evaluated with the pressure clipped here [Pa]. Ring pressures are far
  !> lower; only trial films far below the load-balance root reach it, where an unclipped
  !> pressure-viscosity iteration runs away to overflow.
  real(dp), parameter, public :: roelands_p_max = 1e9_dp

  !> Results of one run: the reported (last) cycle and its summary.
  type :: result_type
    integer :: nsteps = 0
    real(dp), allocatable :: crank_angle_deg(:), sliding_speed(:), h0(:), lambda_min(:), &
      gas_pressure(:), applied_load(:), hydrodynamic_load(:), asperity_load(:), &
      viscous_friction(:), boundary_friction(:), friction(:), power_loss(:), load_residual(:)
    integer, allocatable :: flags(:), iterations(:)
    real(dp) :: energy_loss = 0.0_dp       !< J per cycle
    real(dp) :: mixed_share = 0.0_dp       !< % of the cycle with h0/sigma < 4
    real(dp) :: ring_mass = 0.0_dp         !< kg
    real(dp) :: min_film = 0.0_dp          !< m, min over the cycle of min_x h
    real(dp) :: max_friction = 0.0_dp      !< N, max |f|
    real(dp) :: cycle_change = 0.0_dp      !< |h0 end - h0 start| / h0 start of the last cycle
    logical :: converged = .false.         !< periodic within cycle_tol and no flagged step
    logical :: periodic = .false.          !< periodic within cycle_tol
    integer :: cycles_run = 0
    integer :: evaluations = 0             !< film solves over the whole run
    integer :: reynolds_solves = 0         !< Reynolds solves over the whole run
    !> cycles' worth of crank steps solved: cycles_run + warm-up + periodicity checks
    real(dp) :: cycles_computed = 0.0_dp
  end type result_type

  !> Workspace of the film at one crank step.
  type :: film_type
    integer :: n = 0
    real(dp) :: dx = 0.0_dp, circ = 0.0_dp, sigma = 0.0_dp, e_reduced = 0.0_dp, eta_e = 0.0_dp
    real(dp), allocatable :: x(:), s(:), smid(:), h(:), hmid(:), p(:), eta(:), kmid(:), etamid(:)
    logical, allocatable :: active(:)
    logical :: lead_left = .true.          !< leading edge is the chamber edge (x = -b/2)
    logical :: trailing_cavitated = .false.  !< Reynolds outlet: trailing edge at p_cav
    ! Roelands constants of the run: eta = eta0 exp(lnc (-1 + rtheta (1 + 5.1e-9 p)^z0))
    real(dp) :: lnc = 0.0_dp, z0 = 0.0_dp, rtheta = 0.0_dp
    ! state of the last evaluation
    real(dp) :: h0 = -1.0_dp, wh = 0.0_dp, wa = 0.0_dp, aa = 0.0_dp
    integer :: flags = 0
    integer :: evaluations = 0             !< film solves (load-balance trials)
    integer :: reynolds_solves = 0         !< Reynolds solves (incl. pressure-viscosity loop)
    ! load-balance memory: the last two trials (y = ln h0, relative residual) and the slope
    real(dp) :: y_hist(2) = 0.0_dp, g_hist(2) = 0.0_dp
    real(dp) :: slope = 0.0_dp             !< d residual / d ln h0 of the last step (< 0), 0: none
  end type film_type

  !> Constants of a run needed at every step.
  type :: step_context
    real(dp) :: omega = 0.0_dp   !< crank speed, rad/s
    real(dp) :: dt = 0.0_dp      !< time step, s
    real(dp) :: p_e = 0.0_dp     !< elastic pressure of the ring, Pa
  end type step_context

  !> The load balance at one crank step.
  type :: load_problem
    real(dp) :: u = 0.0_dp, hp = 0.0_dp, dt = 0.0_dp, pg = 0.0_dp, load = 0.0_dp
  end type load_problem

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
    f%e_reduced = reduced_modulus(c)
    f%eta_e = roelands(0.0_dp, c%liner_temperature, c%eta0, c%theta0, c%alpha, c%beta)
    f%lnc = log(c%eta0) + 9.67_dp
    f%z0 = c%alpha / (5.1e-9_dp * f%lnc)
    f%rtheta = ((c%liner_temperature - 138.0_dp) / (c%theta0 - 138.0_dp)) &
      **(-c%beta * (c%theta0 - 138.0_dp) / f%lnc)
    allocate(f%x(n), f%s(n), f%h(n), f%p(n), f%eta(n), f%active(n))
    allocate(f%smid(n-1), f%hmid(n-1), f%kmid(n-1), f%etamid(n-1))
    do i = 1, n
      f%x(i) = -hb + (i - 1) * f%dx
    end do
    f%x(n) = hb
    f%s = ring_profile(f%x, c%width, c%crown_height, c%crown_offset)
    f%smid = ring_profile(0.5_dp * (f%x(1:n-1) + f%x(2:n)), c%width, c%crown_height, c%crown_offset)
    f%p = c%crankcase_pressure
    f%eta = f%eta_e
    f%active = .false.
  end subroutine film_setup

  !> Solve the film for a trial h0: pressures (with the pressure-viscosity loop) and the
  !> hydrodynamic and asperity loads. `sq` is 2 dh0/dt; `p_chamber`, `p_crankcase` the
  !> edge pressures; `u` the sliding speed (its sign picks the inlet for the Reynolds outlet).
  pure subroutine film_evaluate(c, f, h0, sq, u, p_chamber)
    type(case_type), intent(in) :: c
    type(film_type), intent(inout) :: f
    real(dp), intent(in) :: h0, sq, u, p_chamber
    real(dp) :: pl, pr, diff, tot
    real(dp) :: pold(f%n)
    integer :: it, iters, info, n

    n = f%n
    f%h0 = h0
    f%flags = 0
    f%evaluations = f%evaluations + 1
    f%h = h0 + f%s
    f%hmid = h0 + f%smid
    pl = p_chamber
    pr = c%crankcase_pressure
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
    if (maxval(f%p) > 1e8_dp) f%p = 0.0_dp
    do it = 1, c%max_pressure_iterations
      if (c%roelands) then
        ! Roelands with the temperature factor of the run precomputed (same formula)
        f%eta = c%eta0 * exp(f%lnc * (-1.0_dp + f%rtheta &
          * exp(f%z0 * log(1.0_dp + 5.1e-9_dp * min(max(f%p, 0.0_dp), roelands_p_max)))))
      else
        f%eta = f%eta_e
      end if
      f%etamid = 0.5_dp * (f%eta(1:n-1) + f%eta(2:n))
      f%kmid = f%hmid**3 / (6.0_dp * f%etamid)
      pold = f%p
      call reynolds_solve(f%dx, f%kmid, f%hmid, u, sq, pl, pr, c%cavitation_pressure, f%p, &
        f%active, iters, info)
      f%reynolds_solves = f%reynolds_solves + iters
      if (info == 1) f%flags = ior(f%flags, flag_cavitation)
      if (info == 2) then
        ! singular system: cannot happen for h > 0; keep a finite state and flag it
        f%p = max(pl, pr)
        f%flags = ior(f%flags, flag_cavitation)
        exit
      end if
      if (.not. c%roelands) exit
      diff = sum(abs(f%p - pold))
      tot = sum(abs(f%p))
      if (diff <= c%pressure_tol * tot) exit
      if (it == c%max_pressure_iterations) f%flags = ior(f%flags, flag_viscosity)
    end do

    if (c%roelands .and. maxval(f%p) > roelands_p_max) f%flags = ior(f%flags, flag_piezo)
    f%wh = f%circ * f%dx * (sum(f%p) - 0.5_dp * (f%p(1) + f%p(n)))
    if (c%asperity_contact) then
      call asperity_contact(f%h, h0, f%dx, c%width, f%circ, f%sigma, c%zeta_kappa_sigma, &
        c%sigma_over_kappa, f%e_reduced, c%gt_functions == 'fit', c%contact_area == 'lumped', &
        f%wa, f%aa)
    else
      f%wa = 0.0_dp
      f%aa = 0.0_dp
    end if
  end subroutine film_evaluate

  !> Viscous and boundary friction on the ring [N], positive towards the crankcase.
  !>
  !> Full-film cells: `tau = (h/2) dp/dx + eta U / h` at the cell midpoint. Cavitated cells
  !> (both ends at p_cav): Couette shear scaled by the film fraction `h_c / h`, h_c the
  !> gap at the upstream rupture node (the oil passes the ruptured zone as streamers of
  !> total thickness h_c). Boundary: `tau0 A_a + s W_a`, opposing the motion.
  pure subroutine film_friction(c, f, u, fv, fb)
    type(case_type), intent(in) :: c
    type(film_type), intent(in) :: f
    real(dp), intent(in) :: u
    real(dp), intent(out) :: fv, fb
    real(dp) :: tau, hc, theta
    integer :: i, j, n, step, first
    logical :: cav_l, cav_r

    n = f%n
    fv = 0.0_dp
    if (f%lead_left) then
      first = 1
      step = 1
    else
      first = n - 1
      step = -1
    end if
    hc = f%hmid(first)
    do j = 0, n - 2
      i = first + step * j
      cav_l = cavitated(i)
      cav_r = cavitated(i + 1)
      if (cav_l .and. cav_r) then
        theta = min(1.0_dp, hc / f%hmid(i))
        tau = f%etamid(i) * u / f%hmid(i) * theta
      else
        tau = 0.5_dp * f%hmid(i) * (f%p(i+1) - f%p(i)) / f%dx + f%etamid(i) * u / f%hmid(i)
        ! gap at the upstream end of this cell, the rupture point if the next cell is dry
        if (step == 1) then
          hc = f%h(i + 1)
        else
          hc = f%h(i)
        end if
      end if
      fv = fv + tau * f%dx
    end do
    fv = -f%circ * fv
    if (u > 0.0_dp) then
      fb = -(c%tau0 * f%aa + c%boundary_coefficient * f%wa)
    else if (u < 0.0_dp) then
      fb = c%tau0 * f%aa + c%boundary_coefficient * f%wa
    else
      fb = 0.0_dp
    end if

  contains

    pure logical function cavitated(k)
      integer, intent(in) :: k
      if (k == 1 .or. k == n) then
        cavitated = f%trailing_cavitated .and. (f%lead_left .eqv. (k == n))
      else
        cavitated = f%active(k)
      end if
    end function cavitated
  end subroutine film_friction

  !> Run cycles until h0 is periodic (or max_cycles) and report the last one.
  subroutine solve_cycle(c, res, err)
    type(case_type), intent(in) :: c
    type(result_type), intent(out) :: res
    type(error_type), allocatable, intent(out) :: err
    type(film_type) :: f, g
    type(step_context) :: ctx
    integer :: m, k, icycle, flags
    real(dp) :: sigma, h0_prev, h0_prev2, h0_start, h0, h0_end, resid
    type(load_problem) :: lp
    integer :: extra_evaluations, extra_solves

    call validate_case(c, err)
    if (allocated(err)) return
    if (c%gt_functions == 'exact') call gt_init()

    m = steps_per_cycle(c)
    res%nsteps = m
    allocate(res%crank_angle_deg(m), res%sliding_speed(m), res%h0(m), res%lambda_min(m), &
      res%gas_pressure(m), res%applied_load(m), res%hydrodynamic_load(m), &
      res%asperity_load(m), res%viscous_friction(m), res%boundary_friction(m), &
      res%friction(m), res%power_loss(m), res%load_residual(m), res%flags(m), &
      res%iterations(m))

    call film_setup(c, f)
    ctx%omega = c%speed_rpm * 2.0_dp * pi / 60.0_dp
    ctx%dt = deg2rad(c%dpsi_deg) / ctx%omega
    ctx%p_e = elastic_pressure(c)
    sigma = f%sigma
    res%ring_mass = ring_mass(c)

    h0_prev = 4.0_dp * sigma
    if (c%h0_initial > 0.0_dp) h0_prev = c%h0_initial
    h0_prev = min(max(h0_prev, c%h0_floor), c%h0_ceiling)
    h0_prev2 = h0_prev
    h0_start = h0_prev
    extra_evaluations = 0
    extra_solves = 0
    ! warm-up: the last warmup_deg of a cycle before the first reported one, so that the
    ! squeeze-film memory of the initial guess has decayed by psi = 0
    do k = steps_per_cycle(c) - nint(c%warmup_deg / c%dpsi_deg) + 1, m
      call balance(c, ctx, f, (k - 1) * c%dpsi_deg, h0_prev, h0_prev2, h0, flags, resid, lp)
      h0_prev2 = h0_prev
      h0_prev = h0
    end do
    do icycle = 1, c%max_cycles
      res%cycles_run = icycle
      do k = 1, m
        call step(k, h0_prev, h0_prev2, h0)
        if (k == 1) h0_start = h0
        h0_prev2 = h0_prev
        h0_prev = h0
      end do
      ! psi = 720 deg is psi = 0 of the next cycle: solve it on a copy of the film
      g = f
      call balance(c, ctx, g, 0.0_dp, h0_prev, h0_prev2, h0_end, flags, resid, lp)
      extra_evaluations = extra_evaluations + g%evaluations - f%evaluations
      extra_solves = extra_solves + g%reynolds_solves - f%reynolds_solves
      res%cycle_change = abs(h0_end - h0_start) / h0_start
      if (res%cycle_change <= c%cycle_tol) then
        res%periodic = .true.
        exit
      end if
    end do

    res%energy_loss = sum(res%power_loss) * ctx%dt
    res%mixed_share = 100.0_dp * count(res%h0 / sigma < 4.0_dp) / real(m, dp)
    res%min_film = minval(res%lambda_min) * sigma
    res%max_friction = maxval(abs(res%friction))
    res%evaluations = f%evaluations + extra_evaluations
    res%reynolds_solves = f%reynolds_solves + extra_solves
    res%cycles_computed = res%cycles_run + (c%warmup_deg + c%dpsi_deg * res%cycles_run) / 720.0_dp
    res%converged = res%periodic .and. all(res%flags == 0)
    if (.not. all(ieee_is_finite(res%friction)) .or. .not. all(ieee_is_finite(res%h0))) then
      call fatal_error(err, 'internal error: non-finite result', rl_runtime_error)
    end if

  contains

    !> Solve crank step k (psi = (k-1) dpsi) and store it.
    subroutine step(k, hp, hp2, h0out)
      integer, intent(in) :: k
      real(dp), intent(in) :: hp, hp2
      real(dp), intent(out) :: h0out
      real(dp) :: psi, fv, fb, resid
      type(load_problem) :: lp
      integer :: flags, nev
      psi = (k - 1) * c%dpsi_deg
      nev = f%evaluations
      call balance(c, ctx, f, psi, hp, hp2, h0out, flags, resid, lp)
      call film_friction(c, f, lp%u, fv, fb)
      res%crank_angle_deg(k) = psi
      res%sliding_speed(k) = lp%u
      res%h0(k) = h0out
      res%lambda_min(k) = minval(f%h) / sigma
      res%gas_pressure(k) = lp%pg
      res%applied_load(k) = lp%load
      res%hydrodynamic_load(k) = f%wh
      res%asperity_load(k) = f%wa
      res%viscous_friction(k) = fv
      res%boundary_friction(k) = fb
      res%friction(k) = fv + fb
      res%power_loss(k) = abs((fv + fb) * lp%u)
      res%load_residual(k) = resid
      res%flags(k) = flags
      res%iterations(k) = f%evaluations - nev
    end subroutine step
  end subroutine solve_cycle

  !> Sliding speed at crank angle psi [deg]; round-off speeds at the dead centres are 0.
  pure real(dp) function speed(c, ctx, psi)
    type(case_type), intent(in) :: c
    type(step_context), intent(in) :: ctx
    real(dp), intent(in) :: psi
    speed = sliding_speed(deg2rad(psi), c%crank_radius, c%conrod_length, ctx%omega)
    ! sin(pi) is 1e-16, not 0: treat round-off speeds at the dead centres as zero
    if (abs(speed) < 1e-12_dp * c%crank_radius * ctx%omega) speed = 0.0_dp
  end function speed

  !> Find h0 at crank angle psi so that W_h + W_a = F (within load_tol); hp, hp2 are h0
  !> at the two previous steps. The film `g` is left solved at the returned h0; `lp`
  !> returns the step's sliding speed, gas pressure and applied load.
  subroutine balance(c, ctx, g, psi, hp, hp2, h0out, flags, resid, lp)
    type(case_type), intent(in) :: c
    type(step_context), intent(in) :: ctx
    type(film_type), intent(inout) :: g
    real(dp), intent(in) :: psi, hp, hp2
    real(dp), intent(out) :: h0out, resid
    integer, intent(out) :: flags
    type(load_problem), intent(out) :: lp
    real(dp) :: u, guess
    u = speed(c, ctx, psi)
    if (u < 0.0_dp) g%lead_left = .true.
    if (u > 0.0_dp) g%lead_left = .false.
    lp%u = u
    lp%hp = hp
    lp%dt = ctx%dt
    lp%pg = gas_pressure(c%gas_psi, c%gas_p, psi, c%crankcase_pressure)
    lp%load = (ctx%p_e + lp%pg) * c%width * g%circ
    ! log-linear extrapolation from the two previous steps, limited to a factor 1.2
    guess = hp * min(1.2_dp, max(1.0_dp / 1.2_dp, hp / hp2))
    guess = min(max(guess, c%h0_floor), c%h0_ceiling)
    if (c%h0_update == 'damped') then
      call damped(c, lp, g, guess, h0out, flags, resid)
    else
      call safeguarded(c, lp, g, guess, h0out, flags, resid)
    end if
  end subroutine balance

  !> Relative load residual (W_h + W_a - F) / F at trial h0 (solves the film).
  real(dp) function residual(c, lp, g, h0)
    type(case_type), intent(in) :: c
    type(load_problem), intent(in) :: lp
    type(film_type), intent(inout) :: g
    real(dp), intent(in) :: h0
    real(dp) :: sq
    sq = 0.0_dp
    if (c%squeeze) sq = 2.0_dp * (h0 - lp%hp) / lp%dt
    call film_evaluate(c, g, h0, sq, lp%u, lp%pg)
    residual = (g%wh + g%wa - lp%load) / lp%load
    g%y_hist(1) = g%y_hist(2)
    g%g_hist(1) = g%g_hist(2)
    g%y_hist(2) = log(h0)
    g%g_hist(2) = residual
  end function residual

  !> The source study's rule h0 <- (1 + beta_d chi) h0, chi = (W - F)/max(W, F).
  subroutine damped(c, lp, g, guess, h0out, flags, resid)
    type(case_type), intent(in) :: c
    type(load_problem), intent(in) :: lp
    type(film_type), intent(inout) :: g
    real(dp), intent(in) :: guess
    real(dp), intent(out) :: h0out, resid
    integer, intent(out) :: flags
    real(dp) :: h, w, chi
    integer :: it
    h = guess
    flags = flag_load
    do it = 1, c%max_load_iterations
      resid = residual(c, lp, g, h)
      if (abs(resid) <= c%load_tol) then
        flags = 0
        exit
      end if
      w = g%wh + g%wa
      chi = (w - lp%load) / max(w, lp%load)
      if (h <= c%h0_floor .and. chi < 0.0_dp) then
        flags = flag_floor
        exit
      end if
      if (h >= c%h0_ceiling .and. chi > 0.0_dp) then
        flags = flag_ceiling
        exit
      end if
      if (it == c%max_load_iterations) exit
      h = min(max((1.0_dp + c%damping * chi) * h, c%h0_floor), c%h0_ceiling)
    end do
    flags = ior(flags, g%flags)
    h0out = h
  end subroutine damped

  !> Safeguarded secant (Brent's method) on y = ln h0 inside an expanding bracket.
  subroutine safeguarded(c, lp, g, guess, h0out, flags, resid)
    type(case_type), intent(in) :: c
    type(load_problem), intent(in) :: lp
    type(film_type), intent(inout) :: g
    real(dp), intent(in) :: guess
    real(dp), intent(out) :: h0out, resid
    integer, intent(out) :: flags
    real(dp) :: ya, yb, ga, gb, dy, ylo, yhi
    integer :: it

    flags = 0
    ylo = log(c%h0_floor)
    yhi = log(c%h0_ceiling)
    ya = log(guess)
    ga = residual(c, lp, g, guess)
    if (abs(ga) <= c%load_tol) then
      call finish(guess, ga)
      return
    end if
    ! bracket the root: the residual falls with h0 (W > F means the film can open). The
    ! first trial is a Newton step with the slope remembered from the previous crank
    ! step (usually within load_tol at once); then secant extrapolation, then expansion.
    if (g%slope < 0.0_dp) then
      dy = -ga / g%slope
      dy = sign(min(max(abs(dy), 1e-6_dp), 0.5_dp), dy)
    else
      dy = sign(0.01_dp, ga)
    end if
    do it = 1, 200
      yb = min(max(ya + dy, ylo), yhi)
      gb = residual(c, lp, g, exp(yb))
      if (abs(gb) <= c%load_tol) then
        call finish(exp(yb), gb)
        return
      end if
      if (sign(1.0_dp, gb) /= sign(1.0_dp, ga)) exit
      if (yb <= ylo .or. yb >= yhi) then
        if (yb <= ylo) flags = flag_floor
        if (yb >= yhi) flags = flag_ceiling
        call finish(exp(yb), gb)
        return
      end if
      if ((gb - ga) / (yb - ya) < 0.0_dp .and. abs(gb) < abs(ga)) then
        ! secant extrapolation past the root (by 50 %), at least doubling the step
        dy = sign(max(1.5_dp * abs(gb * (yb - ya) / (gb - ga)), 2.0_dp * abs(yb - ya)), dy)
      else
        dy = 3.0_dp * dy
      end if
      dy = sign(min(abs(dy), 2.0_dp), dy)
      ya = yb
      ga = gb
    end do
    call brent(ya, yb, ga, gb)

  contains

    subroutine finish(h, r)
      real(dp), intent(in) :: h, r
      if (g%h0 /= h) then
        resid = residual(c, lp, g, h)  ! leave the film solved at h
      else
        resid = r
      end if
      h0out = h
      if (abs(resid) > c%load_tol .and. flags == 0) flags = flag_load
      flags = ior(flags, g%flags)
      ! remember the local slope for the next crank step's first trial
      if (g%y_hist(1) /= g%y_hist(2)) then
        if ((g%g_hist(2) - g%g_hist(1)) / (g%y_hist(2) - g%y_hist(1)) < 0.0_dp) &
          g%slope = (g%g_hist(2) - g%g_hist(1)) / (g%y_hist(2) - g%y_hist(1))
      end if
    end subroutine finish

    !> Brent's method (inverse quadratic / secant steps, bisection safeguard).
    subroutine brent(a0, b0, fa0, fb0)
      real(dp), intent(in) :: a0, b0, fa0, fb0
      real(dp) :: a, b, cc, fa, fb, fc, d, e, tol1, xm, p, q, r, s
      integer :: iter
      a = a0; b = b0; fa = fa0; fb = fb0
      cc = a; fc = fa; d = b - a; e = d
      do iter = 1, c%max_load_iterations
        if (sign(1.0_dp, fb) == sign(1.0_dp, fc)) then
          cc = a; fc = fa; d = b - a; e = d
        end if
        if (abs(fc) < abs(fb)) then
          a = b; b = cc; cc = a
          fa = fb; fb = fc; fc = fa
        end if
        tol1 = 2.0_dp * epsilon(1.0_dp) * abs(b) + 1e-15_dp
        xm = 0.5_dp * (cc - b)
        if (abs(fb) <= c%load_tol .or. abs(xm) <= tol1) exit
        if (abs(e) >= tol1 .and. abs(fa) > abs(fb)) then
          s = fb / fa
          if (a == cc) then
            p = 2.0_dp * xm * s
            q = 1.0_dp - s
          else
            q = fa / fc
            r = fb / fc
            p = s * (2.0_dp * xm * q * (q - r) - (b - a) * (r - 1.0_dp))
            q = (q - 1.0_dp) * (r - 1.0_dp) * (s - 1.0_dp)
          end if
          if (p > 0.0_dp) q = -q
          p = abs(p)
          if (2.0_dp * p < min(3.0_dp * xm * q - abs(tol1 * q), abs(e * q))) then
            e = d
            d = p / q
          else
            d = xm
            e = d
          end if
        else
          d = xm
          e = d
        end if
        a = b
        fa = fb
        if (abs(d) > tol1) then
          b = b + d
        else
          b = b + sign(tol1, xm)
        end if
        fb = residual(c, lp, g, exp(b))
      end do
      call finish(exp(b), fb)
    end subroutine brent
  end subroutine safeguarded
end module ringlube_cycle
