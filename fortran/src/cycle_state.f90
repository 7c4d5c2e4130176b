!> What an engine cycle carries from one crank step to the next, and the crank step on it.
!>
!> `film_track` is the film of the ring with what its next step starts from (the film's state
!> and warm starts, the load balance's memory, the liner's oil of a starved inlet);
!> `cycle_state` adds what a step needs beside it (the step's constants, the piston's last
!> position, the ring pack's gas and the friction that moves the ring in its groove, the first
!> error of a step). A crank step (`advance`) prepares the starved inlet, advances the ring
!> pack, balances the load and carries the film content and the oil forward; `solve_step`
!> does that and stores the step's results.
module ringlube_cycle_state
  use ringlube_kinds, only: dp, pi
  use ringlube_error, only: error_type, fatal_error, rl_interrupted
  use ringlube_fsys, only: interrupt_requested, progress_step
  use ringlube_case, only: case_type, elastic_pressure
  use ringlube_kinematics, only: deg2rad, piston_position, piston_acceleration
  use ringlube_gas, only: gas_pressure
  use ringlube_ring_pack, only: ring_pack_params, ring_pack_state, ring_pack_step_out, &
                                ring_pack_step
  use ringlube_ring_pack_cycle, only: ring_pack_totals, ring_pack_cycle_out, ring_pack_accumulate
  use ringlube_results, only: result_type, s_crank_angle_deg, s_sliding_speed, s_h0, &
                              s_lambda_min, s_gas_pressure, s_applied_load, s_hydrodynamic_load, &
                              s_asperity_load, s_viscous_friction, s_boundary_friction, &
                              s_friction, s_power_loss, s_load_residual, si_flags, &
                              si_film_solves, s_inlet_fill, s_wetted_width, s_oil_left, &
                              s_oil_bank, s_groove_pressure, s_land_pressure, s_ring_lift, &
                              s_top_gap_flow, s_second_gap_flow, s_face_flow, sec_h0, &
                              sec_load, flag_ceiling, s_film_temperature, m_trailing
  use ringlube_oil_supply, only: supply_type, supply_setup, supply_edges, supply_step, &
                                 supply_to_chamber, supply_turn
  use ringlube_film, only: film_type, film_setup, film_friction, film_temperature, film_copy
  use ringlube_load_balance, only: step_context, load_problem, balance_memory, balance, &
                                   start_history
  use ringlube_sectors, only: sector_ring, ring_setup, ring_accept, exact_mean, team_begin, &
                              team_size_is, team_end, team_post, team_wait, team_claim, team_done, &
                              team_join, team_sectors, job_caller, team_wanted, team_pause
!$ use omp_lib, only: omp_in_parallel, omp_get_thread_num, omp_get_num_threads
  use ringlube_bore, only: bore_distortion
  use ringlube_ring_pack_flow, only: gas_constant
  implicit none
  private
  !> the team's jobs of a step beyond ringlube_sectors' own (numbered below job_caller): each
  !> sector's friction, oil and gas after the balance, the sectors' inlets (a cycle's team), and
  !> the end of a cycle's team
  integer, parameter :: job_post = job_caller, job_inlet = job_caller + 1, &
                        job_stop = job_caller + 2
  !> a cycle's steps run in one parallel region (ring_team_begin, the default); .false.: a
  !> region per step (tests/bench/bench_kernel: RINGLUBE_REGION_PER_STEP=1; docs/bore.md,
  !> "Cost"), the same answers bit for bit
  logical, save, public :: cycle_regions = .true.
  !> thread 0 of a cycle's team is running its steps (advance_ring posts each pass over the
  !> sectors to the team)
  logical, save :: cycle_team = .false.

  public :: film_track, cycle_state, step_out, cycle_setup, advance, solve_step, prepare_inlet, &
            ring_pack_advance, take_film, gap_volume, position, ring_team_begin, &
            ring_team_serves, ring_team_stop, ring_team_end, advance_steps

  !> The film of the ring along the cycle, with what its next crank step starts from.
  type :: film_track
    !> the film, solved at the last step (its content and the warm starts of the next)
    type(film_type) :: f
    !> the load balance's root finder: h0 of the last steps, the residual's slope
    type(balance_memory) :: mem
    !> the liner's oil, the bank and the oil counters (a starved inlet only)
    type(supply_type) :: sup
  end type film_track

  !> What a cycle carries from step to step.
  type :: cycle_state
    !> the step's constants: crank speed, time step, elastic pressure
    type(step_context) :: ctx
    type(film_track) :: film
    !> composite roughness sigma [m]
    real(dp) :: sigma = 0.0_dp
    !> piston position at the last step [m]
    real(dp) :: s_prev = 0.0_dp
    !> the ring pack (ring_pack = 'gas'; else rst is not allocated): its parameters, state, the
    !> last step's flows, the cycle's sums and its start or restart
    type(ring_pack_params) :: rpar
    type(ring_pack_state), allocatable :: rst
    type(ring_pack_step_out) :: rout
    type(ring_pack_totals) :: rtot
    type(ring_pack_cycle_out) :: rcyc
    !> friction of the last step [N]: viscous, boundary, and their sum that moves the ring in
    !> its groove over the next step
    real(dp) :: fv = 0.0_dp, fb = 0.0_dp, fric_prev = 0.0_dp
    !> film and Reynolds solves of the psi = 720 deg steps solved on copies
    integer :: extra_film_solves = 0, extra_solves = 0
    !> the first error of a step (Ctrl-C, the ring pack): later steps do nothing, and the
    !> cycle loops end the run at their check
    type(error_type), allocatable :: err
    !> a distorted bore (else not allocated): the sectors' films (film%f is then the ring's
    !> summary: its edge state and mean loads), each sector's liner oil (starved)
    type(sector_ring), allocatable :: ring
    type(supply_type), allocatable :: sups(:)
    !> a distorted bore's gas path through the sectors' faces at the last step: its
    !> conductance sum_j l_j h_gas,j^3 [m^4] and the mass flow [kg/s], positive towards the
    !> crankcase
    real(dp) :: face_k = 0.0_dp, face_flow = 0.0_dp
    !> the face's conductance at each crank step of the cycle [m^4] (for the ring pack's
    !> restart)
    real(dp), allocatable :: face_ks(:)
    !> sectors off the liner at each crank step of the cycle: their film carries less than 1 %
    !> of the mean load beyond the gas passing an open face (light gaps)
    integer, allocatable :: light(:)
  end type cycle_state

  !> One crank step's answer: h0, its flags and relative load residual, the load problem
  !> (speed, gas pressure, applied load), and the oil through the leading and trailing faces.
  type :: step_out
    real(dp) :: h0 = 0.0_dp, resid = 0.0_dp, v_in = 0.0_dp, v_out = 0.0_dp
    integer :: flags = 0
    type(load_problem) :: lp
  end type step_out

  !> the step of advance_ring, for its team's jobs: the state, the case, the piston's position,
  !> the crank angle, the sliding speed and flags of the balance, and the sectors' results:
  !> viscous and boundary friction [N], oil in and out [m^2], their face's gas height [m]
  type(cycle_state), pointer, save :: step_st => null()
  type(case_type), pointer, save :: step_c => null()
  real(dp), save :: step_s = 0.0_dp, step_psi = 0.0_dp, step_u = 0.0_dp
  integer, save :: step_flags = 0
  real(dp), allocatable, save :: step_fv(:), step_fb(:), step_vin(:), step_vout(:), step_hgas(:)

contains

  !> The state before a run's first step: the film of case c at h0_init (full), the step's
  !> constants, the liner at the supply film (starved) and the ring pack's presence.
  subroutine cycle_setup(st, c, h0_init)
    type(cycle_state), intent(out) :: st
    type(case_type), intent(in) :: c
    real(dp), intent(in) :: h0_init
    call film_setup(c, st%film%f)
    st%ctx%omega = c%speed_rpm * 2.0_dp * pi / 60.0_dp
    st%ctx%dt = deg2rad(c%dpsi_deg) / st%ctx%omega
    st%ctx%p_e = elastic_pressure(c)
    st%sigma = st%film%f%sigma
    call start_history(st%film%mem, h0_init)
    associate (f => st%film%f)
      f%dt = st%ctx%dt
      ! the mass-conserving film starts full; the starved inlet from the supply film everywhere
      f%content_old = h0_init + f%s
      if (f%starved) call supply_setup(st%film%sup, c%width, 2.0_dp * c%crank_radius, f%dx, &
                                       c%supply_film, c%lower_ring_distance)
    end associate
    if (c%ring_pack == 'gas') allocate (st%rst)
    if (c%bore == 'distorted') then
      allocate (st%ring)
      call ring_setup(c, st%film%f, h0_init, st%ring)
      allocate (st%sups(st%ring%bore%m))
      st%sups = st%film%sup
    end if
  end subroutine cycle_setup

  !> Piston position [m] at crank angle psi [deg].
  real(dp) function position(c, psi)
    type(case_type), intent(in) :: c
    real(dp), intent(in) :: psi
    position = piston_position(deg2rad(psi), c%crank_radius, c%conrod_length)
  end function position

  !> Oil in the gap (the interior volumes of the film) [m^2].
  pure real(dp) function gap_volume(f)
    type(film_type), intent(in) :: f
    gap_volume = f%dx * sum(f%content_old(2:f%n - 1))
    ! the volumes next to the edges reach the edges (`&numerics film_edge_cells`)
    if (f%edge_cells) gap_volume = gap_volume + 0.5_dp * f%dx * (f%content_old(2) + f%content_old(f%n - 1))
  end function gap_volume

  !> Direction the piston moves in from s_prev to s: 1 towards the crankcase, -1 away, 0.
  pure integer function motion(s_prev, s)
    real(dp), intent(in) :: s_prev, s
    motion = 0
    if (s > s_prev) motion = 1
    if (s < s_prev) motion = -1
  end function motion

  !> Set what the starved inlet of film `ff` can draw on in the step to psi from the liner's
  !> oil `sup` (the piston at s_prev before it).
  subroutine prepare_inlet(c, ff, sup, s_prev, psi)
    type(case_type), intent(in) :: c
    type(film_type), intent(inout) :: ff
    type(supply_type), intent(in) :: sup
    real(dp), intent(in) :: s_prev, psi
    real(dp) :: s
    integer :: dir
    if (.not. ff%starved) return
    s = position(c, psi)
    dir = motion(s_prev, s)
    if (dir == 0) dir = sup%direction
    ff%ds = s - s_prev
    call supply_edges(sup, s_prev, s, dir, ff%available, ff%behind)
  end subroutine prepare_inlet

  !> Solve the step to psi and carry the film content and the oil supply forward.
  subroutine advance(st, c, psi, out)
    type(cycle_state), intent(inout) :: st
    type(case_type), intent(in) :: c
    real(dp), intent(in) :: psi
    type(step_out), intent(out) :: out
    real(dp) :: s
    ! Ctrl-C during a call from Python: the run stops here, the loops end it at their check
    if (.not. allocated(st%err) .and. interrupt_requested()) &
      call fatal_error(st%err, c%deck_path//': interrupted', rl_interrupted)
    if (allocated(st%err)) return
    call progress_step(psi)
    if (allocated(st%ring)) then
      call advance_ring(st, c, psi, out)
      return
    end if
    associate (f => st%film%f, sup => st%film%sup)
      if (f%jfo .and. f%starved) then
        ! a reversal's change of the liner, once, before the step reads it
        s = position(c, psi)
        call supply_turn(sup, st%s_prev, motion(st%s_prev, s))
      end if
      call prepare_inlet(c, f, sup, st%s_prev, psi)
      call film_temperature(c, f, psi)
      if (allocated(st%rst)) then
        call ring_pack_advance(c, st%ctx, st%rpar, st%fric_prev, st%rst, st%rout, psi, st%err)
        f%p_back = st%rst%p2
        f%p_lower = st%rst%p3
      end if
      call balance(c, st%ctx, f, st%film%mem, psi, out%h0, out%flags, out%resid, out%lp)
      if (allocated(st%rst)) then
        ! the friction that moves the ring in its groove over the next step
        call film_friction(c, f, out%lp%u, st%fv, st%fb)
        st%fric_prev = st%fv + st%fb
      end if
      if (.not. f%jfo) return
      f%content_old = f%theta * f%h
      if (f%front_content) f%content_old = f%content_end
      ! oil through the leading and trailing faces over the step
      if (f%lead_left) then
        out%v_in = f%q_left * st%ctx%dt
        out%v_out = f%q_right * st%ctx%dt
      else
        out%v_in = -f%q_right * st%ctx%dt
        out%v_out = -f%q_left * st%ctx%dt
      end if
      ! (a starved film's s is the one above)
      if (.not. f%starved) s = position(c, psi)
      if (f%starved) then
        call supply_step(sup, st%s_prev, s, motion(st%s_prev, s), out%v_in, out%v_out)
        call supply_to_chamber(sup)
      end if
      st%s_prev = s
    end associate
  end subroutine advance

  !> The step to psi of a ring on a distorted bore: every sector's inlet, the bore's
  !> distortion at the ring's position, the ring pack, the load balance on the ring's mean
  !> position (each trial solves the sectors), then each sector's friction, oil and face
  !> leakage; the ring's friction and the oil through its faces are the sectors' means.
  !>
  !> With `&numerics threads` > 1 (on a machine not busy: team_wanted; else each pass over
  !> the sectors' films is a parallel loop) the step's passes over the sectors are jobs of a
  !> team (ringlube_sectors: team_post): the sectors' inlets, each pass over their films, and
  !> the sectors' friction, oil and gas after the balance, while thread 0 runs the step. The
  !> team is the cycle's (ring_team_begin: one parallel region over a cycle's steps, its
  !> threads waiting for the next step's jobs between steps; a step on a machine that became
  !> busy since, team_wanted, is thread 0's alone) or, outside one, the step's own parallel
  !> region. Each sector's work is its own (its film and its liner's oil) and the
  !> means are taken after the team's jobs in sector order: the answer of one thread bit for
  !> bit.
  subroutine advance_ring(st, c, psi, out)
    type(cycle_state), intent(inout), target :: st
    type(case_type), intent(in), target :: c
    real(dp), intent(in) :: psi
    type(step_out), intent(out) :: out
    real(dp) :: s, p_low
    integer :: j, m, job, seen
    m = size(st%sups)
    s = position(c, psi)
    call film_temperature(c, st%film%f, psi)
    call step_begin(st, c, s, psi, m)
    if (cycle_team .and. .not. team_wanted(c%threads)) then
      ! (the cycle's team on a machine that became busy: the step is thread 0's alone, the
      ! other threads waiting for a later step's jobs)
      call team_pause(.true.)
      do j = 1, m
        call inlet_sector(j)
      end do
      call balance_step()
      do j = 1, m
        call post_sector(j)
      end do
      call team_pause(.false.)
    else if (cycle_team) then
      ! (the cycle's team: its other threads wait for the step's jobs)
      call team_post(job_inlet)
      call inlet_share()
      call team_join()
      call balance_step()
      call team_post(job_post)
      call post_share()
      call team_join()
    else if (.not. in_parallel() .and. team_wanted(c%threads)) then
      call team_begin(c%threads)
      !$omp parallel num_threads(c%threads) default(shared) private(job, seen)
      seen = 0
      call inlet_share()
      if (thread_number() == 0) then
        call team_size_is(team_threads())
        call team_join()
        call balance_step()
        call team_post(job_post)
        call post_share()
        call team_join()
      else
        do
          job = team_wait(seen)
          if (job >= job_caller) exit
          call team_sectors()
        end do
        call post_share()
      end if
      !$omp end parallel
      call team_end()
    else
      do j = 1, m
        call inlet_sector(j)
      end do
      call balance_step()
      do j = 1, m
        call post_sector(j)
      end do
    end if
    associate (f => st%film%f, ring => st%ring)
      st%fv = exact_mean(step_fv(1:m))
      st%fb = exact_mean(step_fb(1:m))
      st%fric_prev = st%fv + st%fb
      out%v_in = exact_mean(step_vin(1:m))
      out%v_out = exact_mean(step_vout(1:m))
      ! the gas path through the faces: a laminar isothermal channel of arc l_j = 2 pi r0 / M,
      ! length b and height h_gas,j per sector, between the upper and the lower edge
      p_low = c%crankcase_pressure
      if (f%p_lower >= 0.0_dp) p_low = f%p_lower
      st%face_k = f%circ / m * sum(step_hgas(1:m)**3)
      if (allocated(st%rst)) then
        ! (the ring pack's: the flow over the step its gas balance counts)
        st%face_flow = st%rout%face_flow
      else
        st%face_flow = st%face_k * (out%lp%pg**2 - p_low**2) / (24.0_dp * c%gas_viscosity &
                                                       * gas_constant * c%gas_temperature * c%width)
      end if
      if (ring%films(1)%jfo) st%s_prev = s
    end associate
    nullify (step_st, step_c)

  contains

    !> The distortion, the ring pack and the load balance (thread 0 of a team); the step's
    !> sliding speed and flags for the work after it.
    subroutine balance_step()
      associate (f => st%film%f, ring => st%ring)
        call bore_distortion(ring%bore, s, ring%d)
        if (allocated(st%rst)) then
          ! the gas through the faces over the step: their path at the last step (explicit, as
          ! the friction)
          st%rst%face_k = st%face_k
          call ring_pack_advance(c, st%ctx, st%rpar, st%fric_prev, st%rst, st%rout, psi, st%err)
          f%p_back = st%rst%p2
          f%p_lower = st%rst%p3
        end if
        call balance(c, st%ctx, f, st%film%mem, psi, out%h0, out%flags, out%resid, out%lp, ring)
        call ring_accept(ring)
      end associate
      step_u = out%lp%u
      step_flags = out%flags
    end subroutine balance_step
  end subroutine advance_ring

  !> The step advance_ring works on, for the jobs of its team's threads: the state, the case,
  !> the piston's position and the crank angle; the per-sector results' arrays sized for m.
  subroutine step_begin(st, c, s, psi, m)
    type(cycle_state), intent(inout), target :: st
    type(case_type), intent(in), target :: c
    real(dp), intent(in) :: s, psi
    integer, intent(in) :: m
    step_st => st
    step_c => c
    step_s = s
    step_psi = psi
    if (allocated(step_fv)) then
      if (size(step_fv) < m) deallocate (step_fv, step_fb, step_vin, step_vout, step_hgas)
    end if
    if (.not. allocated(step_fv)) allocate (step_fv(m), step_fb(m), step_vin(m), step_vout(m), &
                                            step_hgas(m))
  end subroutine step_begin

  !> A thread's share of the sectors' inlets.
  subroutine inlet_share()
    integer :: j
    do while (team_claim(size(step_st%sups), j))
      call inlet_sector(j)
    end do
    call team_done()
  end subroutine inlet_share

  !> A thread's share of the sectors' work after the balance.
  subroutine post_share()
    integer :: j
    do while (team_claim(size(step_st%sups), j))
      call post_sector(j)
    end do
    call team_done()
  end subroutine post_share

  !> Sector j's inlet from its liner's oil and its film's temperature.
  subroutine inlet_sector(j)
    integer, intent(in) :: j
    associate (st => step_st, c => step_c, s => step_s, psi => step_psi)
      ! a reversal's change of the liner, once, before the step reads it
      if (st%ring%films(j)%jfo .and. st%ring%films(j)%starved) &
        call supply_turn(st%sups(j), st%s_prev, motion(st%s_prev, s))
      call prepare_inlet(c, st%ring%films(j), st%sups(j), st%s_prev, psi)
      call film_temperature(c, st%ring%films(j), psi)
    end associate
  end subroutine inlet_sector

  !> Sector j after the balance: its friction, the gas height of its face, its film content
  !> and the oil through its faces over the step, its liner's oil.
  subroutine post_sector(j)
    integer, intent(in) :: j
    associate (st => step_st, c => step_c, s => step_s, fj => step_st%ring%films(j), &
               fv => step_fv, fb => step_fb, vin => step_vin, vout => step_vout, &
               hgas => step_hgas)
      call film_friction(c, fj, step_u, fv(j), fb(j))
      hgas(j) = 0.0_dp
      vin(j) = 0.0_dp
      vout(j) = 0.0_dp
      ! (the edge nodes hold the fill of what enters there, not the film's)
      if (fj%jfo) hgas(j) = max(minval((1.0_dp - fj%theta(2:fj%n - 1)) * fj%h(2:fj%n - 1)), &
                                0.0_dp)
      ! a ring pushed off the liner, held at the back clearance: its face open to the gas
      if (iand(step_flags, flag_ceiling) /= 0) hgas(j) = st%ring%h(j)
      if (.not. fj%jfo) return
      fj%face_open = all(fj%theta(2:fj%n - 1) < 1.0_dp)
      fj%content_old = fj%theta * fj%h
      if (fj%front_content) fj%content_old = fj%content_end
      if (fj%lead_left) then
        vin(j) = fj%q_left * st%ctx%dt
        vout(j) = fj%q_right * st%ctx%dt
      else
        vin(j) = -fj%q_right * st%ctx%dt
        vout(j) = -fj%q_left * st%ctx%dt
      end if
      if (fj%starved) then
        call supply_step(st%sups(j), st%s_prev, s, motion(st%s_prev, s), vin(j), vout(j))
        call supply_to_chamber(st%sups(j))
      end if
    end associate
  end subroutine post_sector

  !> The crank steps k1..k2 in turn (advance; a distorted bore with threads: in one parallel
  !> region, ring_team_begin).
  subroutine advance_steps(st, c, k1, k2)
    type(cycle_state), intent(inout) :: st
    type(case_type), intent(in) :: c
    integer, intent(in) :: k1, k2
    type(step_out) :: out
    integer :: k
    logical :: held
    held = ring_team_begin(st, c)
    !$omp parallel if (held) num_threads(c%threads) default(shared)
    if (.not. ring_team_serves(held)) then
      do k = k1, k2
        call advance(st, c, (k - 1) * c%dpsi_deg, out)
      end do
      call ring_team_stop(held)
    end if
    !$omp end parallel
    call ring_team_end(held)
  end subroutine advance_steps

  !> Before a cycle's steps (ringlube_cycle, run_cycle): whether they run in one parallel
  !> region of `&numerics threads` threads (a distorted bore, more than one thread, outside a
  !> parallel region, the machine not busy: team_wanted), the team then set up. In the region
  !> thread 0 runs the steps (ring_team_serves .false.), the other threads serve the steps'
  !> jobs (ring_team_serves .true., after thread 0's ring_team_stop), and after it
  !> ring_team_end.
  logical function ring_team_begin(st, c) result(held)
    type(cycle_state), intent(in) :: st
    type(case_type), intent(in) :: c
    held = .false.
    if (.not. allocated(st%ring) .or. .not. cycle_regions) return
    if (in_parallel()) return
    held = team_wanted(c%threads)
    if (held) call team_begin(c%threads)
  end function ring_team_begin

  !> In the cycle's region: thread 0 returns .false. at once (it runs the steps, their passes
  !> over the sectors the team's jobs); any other thread serves the steps' jobs until thread 0's
  !> ring_team_stop and returns .true.. Outside a team (held .false.): .false..
  logical function ring_team_serves(held) result(served)
    logical, intent(in) :: held
    integer :: job, seen
    served = .false.
    if (.not. held) return
    if (thread_number() == 0) then
      call team_size_is(team_threads())
      !$omp flush
      cycle_team = .true.
      return
    end if
    served = .true.
    seen = 0
    do
      job = team_wait(seen)
      select case (job)
      case (job_stop)
        exit
      case (job_inlet)
        call inlet_share()
      case (job_post)
        call post_share()
      case default
        call team_sectors()
      end select
    end do
  end function ring_team_serves

  !> Thread 0, after the cycle's steps: the other threads of the team stop serving.
  subroutine ring_team_stop(held)
    logical, intent(in) :: held
    if (.not. held) return
    cycle_team = .false.
    call team_post(job_stop)
  end subroutine ring_team_stop

  !> After the cycle's region: no team.
  subroutine ring_team_end(held)
    logical, intent(in) :: held
    if (held) call team_end()
  end subroutine ring_team_end

  !> .true. inside an active parallel region (OpenMP; .false. without it).
  logical function in_parallel()
    in_parallel = .false.
!$  in_parallel = omp_in_parallel()
  end function in_parallel

  !> The calling thread's number in its team (0: alone, or OpenMP absent).
  integer function thread_number()
    thread_number = 0
!$  thread_number = omp_get_thread_num()
  end function thread_number

  !> Threads of the current team (1 outside one, or OpenMP absent).
  integer function team_threads()
    team_threads = 1
!$  team_threads = omp_get_num_threads()
  end function team_threads

  !> The film becomes `saved` (a state kept earlier), its solve counters keep counting.
  pure subroutine take_film(f, saved)
    type(film_type), intent(inout) :: f
    type(film_type), intent(in) :: saved
    integer :: nfs, nrs
    nfs = f%film_solves
    nrs = f%reynolds_solves
    call film_copy(f, saved)
    f%film_solves = nfs
    f%reynolds_solves = nrs
  end subroutine take_film

  !> Solve crank step k (psi = (k-1) dpsi) and store it in res; h0 the step's (a distorted
  !> bore's: its mean position).
  subroutine solve_step(st, c, res, k, h0)
    type(cycle_state), intent(inout) :: st
    type(case_type), intent(in) :: c
    type(result_type), intent(inout) :: res
    integer, intent(in) :: k
    real(dp), intent(out) :: h0
    type(step_out) :: out
    real(dp) :: psi
    integer :: nev, j
    psi = (k - 1) * c%dpsi_deg
    nev = st%film%f%film_solves
    call advance(st, c, psi, out)
    h0 = out%h0
    associate (f => st%film%f, lp => out%lp)
      if (.not. allocated(st%rst) .and. .not. allocated(st%ring)) &
        call film_friction(c, f, lp%u, st%fv, st%fb)
      res%series(k, s_crank_angle_deg) = psi
      res%series(k, s_sliding_speed) = lp%u
      res%series(k, s_gas_pressure) = lp%pg
      res%series(k, s_applied_load) = lp%load
      res%series(k, s_hydrodynamic_load) = f%wh
      res%series(k, s_asperity_load) = f%wa
      res%series(k, s_viscous_friction) = st%fv
      res%series(k, s_boundary_friction) = st%fb
      res%series(k, s_friction) = st%fv + st%fb
      res%series(k, s_power_loss) = abs((st%fv + st%fb) * lp%u)
      res%series(k, s_load_residual) = out%resid
      res%series(k, s_film_temperature) = f%temperature
      res%int_series(k, si_flags) = out%flags
      res%int_series(k, si_film_solves) = f%film_solves - nev
      ! the step's branch risk (ringlube_results, margin_results)
      res%step_margins(k, :) = [lp%lift_margin, lp%seal_margin, real(lp%margin_solves, dp)]
      res%made(m_trailing) = f%jfo .and. c%cavity_pressure == 'trailing_gas'
      if (allocated(st%ring)) then
        ! the ring's smallest film (mixed when any sector is), and the sectors' means
        res%series(k, s_h0) = minval(st%ring%h)
        res%series(k, s_lambda_min) = minval([(minval(st%ring%films(j)%h), &
                                               j=1, size(st%ring%films))]) / st%sigma
        res%sectors(k, :, sec_h0) = st%ring%h
        res%sectors(k, :, sec_load) = st%ring%w
        res%series(k, s_face_flow) = st%face_flow
        if (.not. allocated(st%face_ks)) allocate (st%face_ks(res%nsteps), st%light(res%nsteps))
        st%face_ks(k) = st%face_k
        st%light(k) = count(st%ring%w - st%ring%films%w_gas / f%circ < 0.01_dp * lp%load / f%circ)
        if (f%jfo) then
          res%series(k, s_inlet_fill) = exact_mean(st%ring%films%theta_in)
          res%series(k, s_wetted_width) = exact_mean([(wetted_width(st%ring%films(j)), &
                                                       j=1, size(st%ring%films))])
          res%series(k, s_oil_left) = exact_mean([(oil_left(st%ring%films(j)), &
                                                   j=1, size(st%ring%films))])
        end if
        if (f%starved) res%series(k, s_oil_bank) = exact_mean(st%sups%bank)
      else
        res%series(k, s_h0) = out%h0
        res%series(k, s_lambda_min) = minval(f%h) / st%sigma
        if (f%jfo) then
          res%series(k, s_inlet_fill) = f%theta_in
          res%series(k, s_wetted_width) = wetted_width(f)
          res%series(k, s_oil_left) = oil_left(f)
        end if
        if (f%starved) res%series(k, s_oil_bank) = st%film%sup%bank
      end if
      if (allocated(st%rst)) then
        res%series(k, s_groove_pressure) = st%rst%p2
        res%series(k, s_land_pressure) = st%rst%p3
        res%series(k, s_ring_lift) = st%rst%x
        res%series(k, s_top_gap_flow) = st%rout%top_gap_flow
        res%series(k, s_second_gap_flow) = st%rout%second_gap_flow
        call ring_pack_accumulate(st%rtot, st%rout, st%ctx%dt)
      end if
    end associate

  contains

    !> The length of full film of a mass-conserving film: the control volumes of its full
    !> nodes, dx inside, dx/2 at an edge [m].
    pure real(dp) function wetted_width(ff)
      type(film_type), intent(in) :: ff
      wetted_width = ff%dx * (count(ff%theta(2:ff%n - 1) >= 1.0_dp - 1e-9_dp) &
                              + 0.5_dp * count([ff%theta(1), ff%theta(ff%n)] >= 1.0_dp - 1e-9_dp))
    end function wetted_width

    !> The oil film the trailing edge of film ff left on the liner over the step [m].
    pure real(dp) function oil_left(ff)
      type(film_type), intent(in) :: ff
      real(dp) :: vo
      if (ff%lead_left) then
        vo = ff%q_right * st%ctx%dt
      else
        vo = -ff%q_left * st%ctx%dt
      end if
      oil_left = 0.0_dp
      if (abs(ff%ds) > 0.0_dp) oil_left = max(vo, 0.0_dp) / abs(ff%ds)
      if (.not. ff%starved .and. abs(out%lp%u) > 0.0_dp) &
        oil_left = max(vo, 0.0_dp) / (abs(out%lp%u) * st%ctx%dt)
    end function oil_left
  end subroutine solve_step

  !> Chamber pressure [Pa] at crank angle psi [deg] (the trace, scaled).
  real(dp) function chamber(c, psi)
    type(case_type), intent(in) :: c
    real(dp), intent(in) :: psi
    chamber = gas_pressure(c%gas_psi, c%gas_p, modulo(psi, 720.0_dp), c%crankcase_pressure)
  end function chamber

  !> Advance the ring pack's state `rs` (parameters par) over the crank step ending at psi
  !> [deg]: the chamber pressure linear in time over the step, the friction of the last step
  !> fric_prev (explicit: the gas and the ring's axial motion are advanced first, then the film
  !> at the step's end sees the new groove and land pressures), the piston's acceleration at
  !> mid-step. Nothing once err is set.
  subroutine ring_pack_advance(c, ctx, par, fric_prev, rs, out, psi, err)
    type(case_type), intent(in) :: c
    type(step_context), intent(in) :: ctx
    type(ring_pack_params), intent(in) :: par
    real(dp), intent(in) :: fric_prev, psi
    type(ring_pack_state), intent(inout) :: rs
    type(ring_pack_step_out), intent(out) :: out
    type(error_type), allocatable, intent(inout) :: err
    real(dp) :: a_p
    a_p = -piston_acceleration(deg2rad(psi - 0.5_dp * c%dpsi_deg), c%crank_radius, &
                               c%conrod_length, ctx%omega)
    if (allocated(err)) return
    call ring_pack_step(par, rs, chamber(c, psi - c%dpsi_deg), chamber(c, psi), &
                        c%crankcase_pressure, -fric_prev, a_p, ctx%dt, out, err)
  end subroutine ring_pack_advance
end module ringlube_cycle_state
