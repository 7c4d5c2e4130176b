!> Finite-difference Reynolds equation with cavitation as a complementarity problem
!> (docs/model.md "Film and Reynolds equation").
!>
!> On a uniform grid of n nodes the conservative scheme
!> `[K(i+1/2)(p(i+1)-p(i)) - K(i-1/2)(p(i)-p(i-1))]/dx^2 = -U (h(i+1/2)-h(i-1/2))/dx + 2 dh0/dt`,
!> `K = h^3/(6 eta)` at the cell midpoints, is second order. Its matrix is an M-matrix,
!> so the discrete cavitation problem
!> `p >= p_cav,  A p - r >= 0,  (p - p_cav)(A p - r) = 0`
!> has a unique solution, found by a primal-dual active-set loop of Thomas solves: nodes
!> with p < p_cav join the active set (p fixed at p_cav); active nodes whose multiplier
!> `A p - r` turns negative leave it. For an M-matrix the loop ends in finitely many
!> steps (usually 1-3 with a warm start from the previous active set). The free boundary
!> is thereby located to within one cell and, in the limit, carries the Swift-Stieber
!> conditions p = p_cav, dp/dx = 0.
module ringlube_reynolds
  use ringlube_kinds, only: dp
  use ringlube_tridiag, only: thomas_fixed
  implicit none
  private
  public :: reynolds_solve, reynolds_problem, reynolds_work, reynolds_work_init

  !> One solve of the Swift-Stieber film: its scalars, the record reynolds_solve takes beside
  !> the film's conductances and gaps. All components must be given.
  type :: reynolds_problem
    !> node spacing [m]
    real(dp) :: dx
    !> sliding speed [m/s]
    real(dp) :: u
    !> the squeeze term 2 dh0/dt [m/s]
    real(dp) :: sq
    !> Dirichlet pressures at x = -b/2 (node 1) and x = +b/2 (node n) [Pa]
    real(dp) :: p_left, p_right
    !> cavitation pressure [Pa]: the pressure of the cavitated nodes, the least of the others
    real(dp) :: p_cav
  end type reynolds_problem

  !> Scratch arrays of reynolds_solve (kept by the caller between solves, so that a
  !> solve allocates nothing).
  type :: reynolds_work
    real(dp), allocatable :: a0(:), b0(:), c0(:), r(:), cp(:)
  end type reynolds_work

contains

  !> Scratch arrays for n nodes.
  pure subroutine reynolds_work_init(w, n)
    type(reynolds_work), intent(out) :: w
    integer, intent(in) :: n
    allocate (w%a0(n), w%b0(n), w%c0(n), w%r(n), w%cp(n))
  end subroutine reynolds_work_init

  !> Solve for the nodal pressures p(1:n).
  !>
  !> `problem` (reynolds_problem) the solve's scalars; `kmid(i)` and `hmid(i)` are K and h
  !> between nodes i and i+1. `active` (in/out) is the cavitated set, used as the warm start.
  !> `iterations` the Thomas solves of the active-set loop; `info`: 0 converged, 1 active-set
  !> loop did not settle, 2 singular system. `work`: optional scratch (reynolds_work_init(n)).
  pure recursive subroutine reynolds_solve(problem, kmid, hmid, p, active, iterations, info, work)
    type(reynolds_problem), intent(in) :: problem
    real(dp), intent(in) :: kmid(:), hmid(:)
    real(dp), intent(out) :: p(:)
    logical, intent(inout) :: active(:)
    integer, intent(out) :: iterations, info
    type(reynolds_work), intent(inout), optional :: work
    type(reynolds_work) :: local
    real(dp) :: mu, scale, pscale
    integer :: i, n, it, tinfo
    logical :: changed

    if (.not. present(work)) then
      call reynolds_work_init(local, size(p))
      call reynolds_solve(problem, kmid, hmid, p, active, iterations, info, local)
      return
    end if
    n = size(p)
    info = 0
    associate (a0 => work%a0, b0 => work%b0, c0 => work%c0, r => work%r, dx => problem%dx, &
               u => problem%u, sq => problem%sq, p_left => problem%p_left, &
               p_right => problem%p_right, p_cav => problem%p_cav)
      a0(1) = 0.0_dp; b0(1) = 1.0_dp; c0(1) = 0.0_dp; r(1) = p_left
      a0(n) = 0.0_dp; b0(n) = 1.0_dp; c0(n) = 0.0_dp; r(n) = p_right
      do i = 2, n - 1
        a0(i) = -kmid(i - 1)
        c0(i) = -kmid(i)
        b0(i) = kmid(i - 1) + kmid(i)
        r(i) = dx * (u * (hmid(i) - hmid(i - 1)) - sq * dx)
      end do
      active(1) = .false.
      active(n) = .false.
      pscale = max(abs(p_left), abs(p_right), abs(p_cav), 1.0_dp)

      do it = 1, n + 1
        iterations = it
        ! the cavitated nodes are held at p_cav
        call thomas_fixed(a0(1:n), b0(1:n), c0(1:n), r(1:n), active, p_cav, p, tinfo, work%cp)
        if (tinfo /= 0) then
          info = 2
          return
        end if
        changed = .false.
        do i = 2, n - 1
          if (active(i)) then
            mu = a0(i) * p(i - 1) + b0(i) * p(i) + c0(i) * p(i + 1) - r(i)
            scale = abs(a0(i) * p(i - 1)) + abs(b0(i) * p(i)) + abs(c0(i) * p(i + 1)) + abs(r(i))
            if (mu < -1e-12_dp * scale) then
              active(i) = .false.
              changed = .true.
            end if
          else if (p(i) < p_cav - 1e-12_dp * pscale) then
            active(i) = .true.
            changed = .true.
          end if
        end do
        if (.not. changed) return
      end do
      info = 1
    end associate
  end subroutine reynolds_solve
end module ringlube_reynolds
