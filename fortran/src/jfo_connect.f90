!> The connectivity rule of the mass-conserving film: which cavities are
!> open to an edge's gas and at which pressure (`jfo_cavity_pressure`), and the JFO solve of
!> ringlube_jfo inside the outer loop that makes the cavity pressures and the solution agree
!> (`jfo_solve_connected`). Details and verification: docs/film_model.md.
module ringlube_jfo_connect
  use, intrinsic :: ieee_arithmetic, only: ieee_is_finite
  use ringlube_kinds, only: dp
  use ringlube_jfo, only: jfo_solve, jfo_options, jfo_problem, jfo_stats, JFO_OK, JFO_DRY, &
                          JFO_CONNECTIVITY, JFO_BAD_INPUT
  use ringlube_jfo_system, only: jfo_system, jfo_scratch
  implicit none
  private
  public :: jfo_solve_connected, jfo_cavity_pressure, jfo_seal_margin

contains

  !> Cavity pressure per node by the connectivity rule, for the sliding speed,
  !> edge pressures, p_cav, trailing_gas and leading_gas of problem (jfo_problem).
  !>
  !> Cavities are the runs of interior nodes with theta < 1. An edge is open to its gas when
  !> it is the trailing edge and trailing_gas is set, or the leading edge and leading_gas is set
  !> (leading: the crankcase edge, right, when u > 0, the chamber edge, left, when u < 0; when
  !> u = 0 an edge is open if either flag is set). The zone open to an edge's gas is the run of
  !> theta < 1 nodes next to that edge (the cavity reaching the trailing edge; the partly filled
  !> inlet zone of a starved film); when p is given it also takes in the full nodes next to the
  !> run, or next to an edge that is a gas interface (it admits gas, theta(1) or theta(n) < 1,
  !> or it is the trailing edge with trailing_gas), whose pressure is below
  !> that gas pressure: a meniscus is in pressure equilibrium with the gas behind it, so a film
  !> below the gas pressure cannot touch the gas. The zone sits at max(p_gas, p_cav); a zone
  !> spanning the face (partly filled across its width) at the higher of the two gas pressures;
  !> every other node (full film, enclosed cavities) at p_cav.
  !> blown (out, optional): the face is partly filled across its width at a level above the
  !> leading edge's gas pressure, so that the gas in it blows out through the leading edge
  !> (see jfo_solve_connected).
  pure subroutine jfo_cavity_pressure(problem, theta, pc, p, blown)
    type(jfo_problem), intent(in) :: problem
    real(dp), intent(in) :: theta(:)
    real(dp), intent(out) :: pc(:)
    real(dp), intent(in), optional :: p(:)
    logical, intent(out), optional :: blown
    integer :: n, il, ir
    logical :: open_left, open_right, gas_left, gas_right
    real(dp) :: lev_l, lev_r

    n = size(theta)
    pc = problem%p_cav
    if (present(blown)) blown = .false.
    if (allocated(problem%gas_channel)) then
      ! a face open at the last step passes the gas from edge to edge: its cavities at the gas
      ! channel's pressure (each edge at its own; no face is blown)
      pc(2:n - 1) = max(problem%gas_channel(2:n - 1), problem%p_cav)
      return
    end if
    if (problem%u > 0.0_dp) then
      open_left = problem%trailing_gas
      open_right = problem%leading_gas
    else if (problem%u < 0.0_dp) then
      open_left = problem%leading_gas
      open_right = problem%trailing_gas
    else
      open_left = problem%trailing_gas .or. problem%leading_gas
      open_right = open_left
    end if
    ! an edge is a gas interface (film below its pressure next to it joins its gas) when it
    ! admits gas (fill < 1: a starved inlet) or it is the trailing edge with trailing_gas
    gas_left = theta(1) < 1.0_dp .or. (problem%trailing_gas .and. problem%u >= 0.0_dp)
    gas_right = theta(n) < 1.0_dp .or. (problem%trailing_gas .and. problem%u <= 0.0_dp)
    lev_l = max(problem%p_left, problem%p_cav)
    lev_r = max(problem%p_right, problem%p_cav)
    ! il: last node of the zone open at the left edge (1: none); ir: first of the right one (n)
    il = 1
    if (open_left) then
      if (theta(2) < 1.0_dp .or. (present(p) .and. gas_left)) then
        do while (il < n - 1)
          if (.not. in_zone(il + 1, lev_l)) exit
          il = il + 1
        end do
      end if
    end if
    ir = n
    if (open_right) then
      if (theta(n - 1) < 1.0_dp .or. (present(p) .and. gas_right)) then
        do while (ir > 2)
          if (.not. in_zone(ir - 1, lev_r)) exit
          ir = ir - 1
        end do
      end if
    end if
    if (il >= ir - 1 .and. all(theta(2:n - 1) < 1.0_dp)) then
      ! the face is partly filled across its width: open to the higher of the two gas pressures
      pc(2:n - 1) = max(lev_l, lev_r)
      if (present(blown)) then
        if (problem%u > 0.0_dp) blown = max(lev_l, lev_r) > problem%p_right
        if (problem%u < 0.0_dp) blown = max(lev_l, lev_r) > problem%p_left
      end if
    else
      ! each open zone at its own gas pressure; where they overlap through full film below
      ! both gas pressures (not a partly filled face), at the lower one
      pc(2:il) = lev_l
      pc(ir:n - 1) = lev_r
      if (il >= ir) pc(ir:il) = min(lev_l, lev_r)
    end if

  contains

    pure logical function in_zone(i, level)
      integer, intent(in) :: i
      real(dp), intent(in) :: level
      in_zone = theta(i) < 1.0_dp
      if (present(p)) in_zone = in_zone .or. p(i) <= level
    end function in_zone
  end subroutine jfo_cavity_pressure

  !> jfo_solve inside the outer loop of the connectivity rule: pc from the warm-start theta,
  !> solve, recompute pc from the new theta, repeat until pc no longer changes, or until it
  !> alternates between two sets (a meniscus between two nodes): then the larger pc of the two
  !> at every node and one more solve (docs/film_model.md).
  !>
  !> A face partly filled across its width at a gas pressure above the leading edge's (the
  !> trailing gas reaching the leading edge: `blown`) has its meniscus at the leading edge, where
  !> the gas blows out. Flooded, the leading edge then admits gas only (its fill 0), so that the
  !> oil in the face is what Couette transport leaves there, whatever the grid. Starved
  !> (leading_gas), the edge is held at the face's gas level and admits its fill theta_left or
  !> theta_right: the liner's oil enters by Couette transport alone (no pressure-driven flux
  !> over the edge's cell), so a blown face can take in oil again (admitting gas only, it
  !> stayed dry for whole strokes). Without either the oil entering at the leading edge is blown
  !> back out over one cell at a rate k dp/dx, so the face's fill, its shear and the energy
  !> scaled with the cell size.
  !>
  !> Arguments as jfo_solve, the problem's p_cav, trailing_gas and leading_gas included (see
  !> jfo_cavity_pressure); pc (out) the cavity pressures of the solution; stats (out) as
  !> jfo_solve's, with the iterations, sweeps and settled summed over the solves, outer the
  !> number of solves and blown the state above. stats%info JFO_CONNECTIVITY if the loop did not settle
  !> in max_outer solves (default 200; a warm start needs 1-2).
  pure subroutine jfo_solve_connected(problem, h, hmid, kmid, content_old, pc, p, theta, stats, &
                                      options, work, scratch)
    type(jfo_problem), intent(in) :: problem
    real(dp), intent(in) :: h(:), hmid(:), kmid(:), content_old(:)
    real(dp), intent(out) :: pc(:)
    real(dp), intent(inout) :: p(:), theta(:)
    type(jfo_stats), intent(out) :: stats
    type(jfo_options), intent(in), optional :: options
    !> jfo_solve's system and working arrays, kept between calls (optional)
    type(jfo_system), intent(inout), optional :: work
    type(jfo_scratch), intent(inout), optional :: scratch
    ! the rule's set of a solution; the warm-start fill with non-finite entries replaced
    real(dp), allocatable :: pcn(:), th(:)
    ! every set solved with so far, most recent first (a cycle of any length is detected);
    ! allocated when a second solve is needed (most calls need one)
    real(dp), allocatable :: hist(:, :)
    logical, allocatable :: hist_bl(:)
    logical :: bl, bln, final
    integer :: k, kmax, i, j, n
    type(jfo_options) :: opt
    ! the problem of one solve (the edges of a blown face changed) and what it reports
    type(jfo_problem) :: step
    type(jfo_stats) :: last

    if (present(options)) opt = options
    kmax = opt%max_outer
    n = size(h)
    if (size(pc) /= size(h) .or. size(theta) /= size(h)) then
      stats%info = JFO_BAD_INPUT
      return
    end if
    allocate (pcn(size(pc)))
    ! first guess from the warm-start fill only (its pressures may belong to another pc);
    ! finite: |theta| <= huge (NaN compares false)
    if (all(abs(theta) <= huge(1.0_dp))) then
      call jfo_cavity_pressure(problem, theta, pc, blown=bl)
    else
      th = theta
      where (.not. ieee_is_finite(th)) th = 1.0_dp
      call jfo_cavity_pressure(problem, th, pc, blown=bl)
    end if
    ! final: the set of a cycle, solved once more and kept whatever the solve's state
    final = .false.
    do k = 1, kmax + 1
      if (k > kmax .and. .not. final) exit
      stats%outer = k
      step = problem
      if (bl .and. problem%leading_gas) then
        if (problem%u > 0.0_dp) step%p_right = maxval(pc(2:n - 1))
        if (problem%u < 0.0_dp) step%p_left = maxval(pc(2:n - 1))
      else
        if (bl .and. problem%u > 0.0_dp) step%theta_right = 0.0_dp
        if (bl .and. problem%u < 0.0_dp) step%theta_left = 0.0_dp
      end if
      stats%blown = bl
      call jfo_solve(step, h, hmid, kmid, content_old, pc, p, theta, last, options, work, scratch)
      stats%iterations = stats%iterations + last%iterations
      stats%sweeps = stats%sweeps + last%sweeps
      stats%settled = stats%settled + last%settled
      stats%info = last%info
      stats%q_left = last%q_left
      stats%q_right = last%q_right
      if (final) return
      if (stats%info /= JFO_OK .and. stats%info /= JFO_DRY) return
      call jfo_cavity_pressure(problem, theta, pcn, p, bln)
      if (all(pcn == pc) .and. (bln .eqv. bl)) return
      ! a cycle: pcn equals one of the sets solved with before (a two-cycle is a meniscus
      ! between two nodes: a node joined to the gas-connected zone rises above the gas pressure,
      ! left out of it falls below; a starved blown face, its leading edge at the face's gas
      ! level, gave cycles of 17 to 32 sets, which a history of the last 16 missed: the loop ran
      ! to max_outer at every pressure-viscosity iteration, flags 16 and 4). No fixed point
      ! exists on this grid; the nodes are taken as connected (the largest pc of the sets in the
      ! cycle) and solved once more.
      if (.not. allocated(hist)) allocate (hist(size(pc), max(kmax, 1)), hist_bl(max(kmax, 1)))
      do j = 1, min(k - 1, size(hist, 2))
        if (all(pcn == hist(:, j)) .and. (bln .eqv. hist_bl(j))) then
          do i = 1, j
            pc = max(pc, hist(:, i))
            bl = bl .or. hist_bl(i)
          end do
          final = .true.
          exit
        end if
      end do
      if (final) cycle
      ! hist(:, 1) the set just solved with, hist(:, 2) the one before, ...
      j = min(k, size(hist, 2))
      hist(:, 2:j) = hist(:, 1:j - 1)
      hist_bl(2:j) = hist_bl(1:j - 1)
      hist(:, 1) = pc
      hist_bl(1) = bl
      pc = pcn
      bl = bln
    end do
    stats%info = JFO_CONNECTIVITY

  end subroutine jfo_solve_connected

  !> The margin of the seal of a face with a gas interface at its trailing edge (trailing_gas):
  !> whether the film holds the trailing edge's gas back from the leading edge, as a number
  !> that is continuous in the film's solution and changes sign where the state changes.
  !>
  !> The gas zone open at the trailing edge takes in every partly filled node and every full
  !> node whose pressure is at or below the gas level `max(p_trailing, p_cav)` (the
  !> connectivity rule of jfo_cavity_pressure); it stops only at a full node above that level.
  !> So the face is sealed when some interior node is full at a pressure above the level, and
  !> the gas reaches the leading edge (blown) when none is. Each interior node i scores
  !> - full (theta = 1): (p_i - level) / (p_i - p_leading) where p_i > level (in (0, 1): the
  !>   share of the film's pressure drop to the leading edge that the gas does not take up),
  !>   else (p_i - level) / (level - p_leading) clipped at -1;
  !> - partly filled: theta_i - 1 (in [-1, 0): how far from full it is);
  !> and the margin is the largest score: > 0 sealed, <= 0 blown, 0 where a node becomes full at
  !> the gas level or the last full node at it empties. A decision exists only where the
  !> trailing edge's gas is above the leading edge's (u /= 0); elsewhere `huge(1.0_dp)`.
  !> u: sliding speed (its sign: the leading edge, as in jfo_cavity_pressure); p_left,
  !> p_right: the gas pressures at the edges (not the solution's edge values: a blown face
  !> holds its leading edge at the face's level); theta, p: the solution.
  pure real(dp) function jfo_seal_margin(u, p_left, p_right, p_cav, theta, p) result(m)
    real(dp), intent(in) :: u, p_left, p_right, p_cav, theta(:), p(:)
    real(dp) :: level, p_lead, score
    integer :: i, n
    m = huge(1.0_dp)
    if (u > 0.0_dp) then
      level = max(p_left, p_cav)
      p_lead = p_right
    else if (u < 0.0_dp) then
      level = max(p_right, p_cav)
      p_lead = p_left
    else
      return
    end if
    if (.not. level > p_lead) return
    n = size(theta)
    m = -1.0_dp
    do i = 2, n - 1
      if (theta(i) < 1.0_dp) then
        score = theta(i) - 1.0_dp
      else if (p(i) > level) then
        score = (p(i) - level) / (p(i) - p_lead)
      else
        score = max((p(i) - level) / (level - p_lead), -1.0_dp)
      end if
      m = max(m, score)
    end do
  end function jfo_seal_margin
end module ringlube_jfo_connect
