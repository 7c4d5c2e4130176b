! ctest labels: unit
!> film_copy (ringlube_film): the copy of a film that keeps the destination's arrays where
!> their shapes match. Every component of film_type and of the solvers' workspaces it holds
!> (jfo_system, jfo_scratch with its jfo_eval, reynolds_work) is set, in the source and the
!> destination, to values that differ between the two (`fill` with seeds 1 and 2); the
!> comparison `compare` counts the components that are equal. Before the copy none is (so
!> `compare` sees a difference in every component it checks), after it every one is.
!> (tests/python/test_film_copy.py checks that `fill` and `compare` name every component the
!> types declare, and film_copy too.)
!>
!> 1. same_shape: a destination of the same nodes: every component copied, and every array of
!>    the destination still at its address (the intrinsic assignment `dst = src` moves them;
!>    a free and an allocation of the same size in a row may return the same address, which
!>    this cannot see: the allocations are counted with callgrind, docs/bore.md "Cost").
!> 2. new_shape: a destination of other nodes, an empty one (a film never set up) and one
!>    whose arrays the source does not have allocated: every component copied, the bounds
!>    the source's, the arrays the source lacks deallocated.
program test_film_copy
  use, intrinsic :: iso_c_binding, only: c_intptr_t, c_loc
  use ringlube_kinds, only: dp
  use ringlube_film, only: film_type, film_copy
  use ringlube_check
  implicit none
  !> components compared by the last `compare` and how many of them were equal
  integer :: ncomp = 0, nsame = 0
  !> fill's seed and the components it has set so far
  integer :: seed = 0, k = 0
  !> the allocatable arrays of a film_type, its workspaces' included
  integer, parameter :: n_arrays = 50

  if (run_case('same_shape')) call same_shape()
  if (run_case('new_shape')) call new_shape()
  call report('test_film_copy')

contains

  subroutine same_shape()
    type(film_type) :: src
    type(film_type), target :: dst
    integer(c_intptr_t) :: before(n_arrays)
    call fill(src, 11, 1)
    call fill(dst, 11, 2)
    call compare(dst, src)
    call check(ncomp > 0 .and. nsame == 0, 'same_shape: every component differs before the copy')
    before = addresses(dst)
    call film_copy(dst, src)
    call compare(dst, src)
    call check(nsame == ncomp, 'same_shape: every component copied')
    call check(all(addresses(dst) == before), 'same_shape: the arrays kept their storage')
    ! the source is left as it was
    call fill(dst, 11, 1)
    call compare(dst, src)
    call check(nsame == ncomp, 'same_shape: the source unchanged')
  end subroutine same_shape

  subroutine new_shape()
    type(film_type) :: src, dst, empty
    call fill(src, 11, 1)
    call fill(dst, 7, 2)
    call film_copy(dst, src)
    call compare(dst, src)
    call check(nsame == ncomp, 'new_shape: every component copied from 11 nodes into 7')
    call check(size(dst%x) == 11 .and. size(dst%hmid) == 10 .and. &
               size(dst%jfo_scratch%ev%ju) == 11, 'new_shape: the source''s sizes')
    call film_copy(empty, src)
    call compare(empty, src)
    call check(nsame == ncomp, 'new_shape: every component copied into an empty film')
    ! a source without the JFO workspaces (a Swift-Stieber film never solved by JFO)
    call fill(dst, 11, 2)
    deallocate (src%jfo_work%ca, src%jfo_work%wv, src%jfo_scratch%v, src%jfo_scratch%ev%pn, &
                src%work%cp, src%active)
    call film_copy(dst, src)
    call compare(dst, src)
    call check(nsame == ncomp, 'new_shape: every component copied from a source with arrays unset')
    call check(.not. (allocated(dst%jfo_work%ca) .or. allocated(dst%jfo_work%wv) .or. &
                      allocated(dst%jfo_scratch%v) .or. allocated(dst%jfo_scratch%ev%pn) .or. &
                      allocated(dst%work%cp) .or. allocated(dst%active)), &
               'new_shape: the arrays the source lacks deallocated')
  end subroutine new_shape

  !> Every component of f set from seed (1 or 2: every value differs between the two), its
  !> arrays of n nodes (n - 1 faces, as film_setup sizes them); k counts the components.
  subroutine fill(f, n, s)
    type(film_type), intent(inout) :: f
    integer, intent(in) :: n, s
    seed = s
    k = 0
    f%n = n + seed
    f%dx = r()
    f%circ = r()
    f%sigma = r()
    f%eta_e = r()
    f%contact%sigma = r()
    f%contact%zeta_kappa_sigma = r()
    f%contact%sigma_over_kappa = r()
    f%contact%e_reduced = r()
    f%contact%fit = l()
    f%contact%lumped = l()
    f%contact%width = r()
    f%contact%circumference = r()
    call ra(f%x, n)
    call ra(f%s, n)
    call ra(f%smid, n - 1)
    call ra(f%h, n)
    call ra(f%hmid, n - 1)
    call ra(f%p, n)
    call ra(f%eta, n)
    call ra(f%kmid, n - 1)
    call ra(f%etamid, n - 1)
    call la(f%active, n)
    call ra(f%work%a0, n)
    call ra(f%work%b0, n)
    call ra(f%work%c0, n)
    call ra(f%work%r, n)
    call ra(f%work%cp, n)
    call ra(f%pold, n)
    f%lead_left = l()
    f%trailing_cavitated = l()
    f%law%eta0 = r()
    f%law%lnc = r()
    f%law%z0 = r()
    f%law%rtheta = r()
    f%temperature = r()
    f%h0 = r()
    f%wh = r()
    f%wa = r()
    f%aa = r()
    f%flags = i()
    f%film_solves = i()
    f%reynolds_solves = i()
    f%jfo = l()
    call ra(f%theta, n)
    call ra(f%content_old, n)
    call ra(f%pc, n)
    f%jfo_work%n = i()
    f%jfo_work%a = r()
    f%jfo_work%w = r()
    f%jfo_work%p_left = r()
    f%jfo_work%p_right = r()
    f%jfo_work%theta_left = r()
    f%jfo_work%theta_right = r()
    f%jfo_work%qcl = r()
    f%jfo_work%qcr = r()
    call ra(f%jfo_work%ca, n - 1)
    call ra(f%jfo_work%kd, n - 1)
    call ra(f%jfo_work%ps, n)
    call ra(f%jfo_work%h, n)
    call ra(f%jfo_work%content_old, n)
    call ra(f%jfo_work%pc, n)
    call ra(f%jfo_work%wv, n)
    f%jfo_work%dmax = r()
    f%jfo_work%edge_meniscus = l()
    f%jfo_work%front_content = l()
    f%jfo_work%edge_cells = l()
    f%jfo_work%thin_fade_from = r()
    f%jfo_work%thin_fade_width = r()
    f%jfo_work%full_hd = l()
    call ra(f%jfo_scratch%v, n)
    call ra(f%jfo_scratch%vt, n)
    call ra(f%jfo_scratch%vpre, n)
    call ra(f%jfo_scratch%vbest, n)
    call ra(f%jfo_scratch%dv, n)
    call ra(f%jfo_scratch%r, n)
    call ra(f%jfo_scratch%rt, n)
    call ra(f%jfo_scratch%tw, n)
    call ra(f%jfo_scratch%cp, n)
    call ra(f%jfo_scratch%y, n)
    call ra(f%jfo_scratch%ev%pn, n)
    call ra(f%jfo_scratch%ev%tn, n)
    call ra(f%jfo_scratch%ev%fl, n)
    call ra(f%jfo_scratch%ev%dfpl, n)
    call ra(f%jfo_scratch%ev%dfpr, n)
    call ra(f%jfo_scratch%ev%dftl, n)
    call ra(f%jfo_scratch%ev%dftr, n)
    call ra(f%jfo_scratch%ev%jl, n)
    call ra(f%jfo_scratch%ev%jd, n)
    call ra(f%jfo_scratch%ev%ju, n)
    f%q_left = r()
    f%q_right = r()
    f%dt = r()
    f%q_face_left = r()
    f%q_face_right = r()
    call ra(f%content_prev, n)
    call ra(f%content_key, n)
    call ra(f%content_end, n)
    call ra(f%content_hist, n)
    f%u_key = r()
    f%r_step = r()
    f%hist_steps = i()
    f%x_left = r()
    f%x_right = r()
    f%x_left_prev = r()
    f%x_right_prev = r()
    f%sign_prev = [i(), i(), i(), i()]
    f%held_prev = [l(), l()]
    f%held_end = l()
    f%blown = l()
    f%starved = l()
    f%available = r()
    f%ds = r()
    f%theta_in = r()
    f%edge_cells = l()
    f%front_content = l()
    f%behind = r()
    f%cap_left = r()
    f%cap_right = r()
    f%p_back = r()
    f%p_lower = r()
    f%gas_channel = l()
    f%w_gas = r()
    f%face_open = l()
  end subroutine fill

  real(dp) function r()
    k = k + 1
    r = seed + 0.001_dp * k
  end function r

  integer function i()
    k = k + 1
    i = 1000 * seed + k
  end function i

  logical function l()
    k = k + 1
    l = mod(seed + k, 2) == 0
  end function l

  subroutine ra(a, m)
    real(dp), allocatable, intent(inout) :: a(:)
    integer, intent(in) :: m
    integer :: j
    k = k + 1
    if (allocated(a)) deallocate (a)
    allocate (a(m))
    a = [(seed + 0.001_dp * k + 1e-6_dp * j, j=1, m)]
  end subroutine ra

  subroutine la(a, m)
    logical, allocatable, intent(inout) :: a(:)
    integer, intent(in) :: m
    integer :: j
    k = k + 1
    if (allocated(a)) deallocate (a)
    allocate (a(m))
    a = [(mod(seed + k + j, 2) == 0, j=1, m)]
  end subroutine la

  !> Compare every component of a and b: ncomp of them, nsame equal (arrays: allocation,
  !> bounds and values).
  subroutine compare(a, b)
    type(film_type), intent(in) :: a, b
    ncomp = 0
    nsame = 0
    call ci(a%n, b%n)
    call cr(a%dx, b%dx)
    call cr(a%circ, b%circ)
    call cr(a%sigma, b%sigma)
    call cr(a%eta_e, b%eta_e)
    call cr(a%contact%sigma, b%contact%sigma)
    call cr(a%contact%zeta_kappa_sigma, b%contact%zeta_kappa_sigma)
    call cr(a%contact%sigma_over_kappa, b%contact%sigma_over_kappa)
    call cr(a%contact%e_reduced, b%contact%e_reduced)
    call cl(a%contact%fit, b%contact%fit)
    call cl(a%contact%lumped, b%contact%lumped)
    call cr(a%contact%width, b%contact%width)
    call cr(a%contact%circumference, b%contact%circumference)
    call cra(a%x, b%x)
    call cra(a%s, b%s)
    call cra(a%smid, b%smid)
    call cra(a%h, b%h)
    call cra(a%hmid, b%hmid)
    call cra(a%p, b%p)
    call cra(a%eta, b%eta)
    call cra(a%kmid, b%kmid)
    call cra(a%etamid, b%etamid)
    call cla(a%active, b%active)
    call cra(a%work%a0, b%work%a0)
    call cra(a%work%b0, b%work%b0)
    call cra(a%work%c0, b%work%c0)
    call cra(a%work%r, b%work%r)
    call cra(a%work%cp, b%work%cp)
    call cra(a%pold, b%pold)
    call cl(a%lead_left, b%lead_left)
    call cl(a%trailing_cavitated, b%trailing_cavitated)
    call cr(a%law%eta0, b%law%eta0)
    call cr(a%law%lnc, b%law%lnc)
    call cr(a%law%z0, b%law%z0)
    call cr(a%law%rtheta, b%law%rtheta)
    call cr(a%temperature, b%temperature)
    call cr(a%h0, b%h0)
    call cr(a%wh, b%wh)
    call cr(a%wa, b%wa)
    call cr(a%aa, b%aa)
    call ci(a%flags, b%flags)
    call ci(a%film_solves, b%film_solves)
    call ci(a%reynolds_solves, b%reynolds_solves)
    call cl(a%jfo, b%jfo)
    call cra(a%theta, b%theta)
    call cra(a%content_old, b%content_old)
    call cra(a%pc, b%pc)
    call ci(a%jfo_work%n, b%jfo_work%n)
    call cr(a%jfo_work%a, b%jfo_work%a)
    call cr(a%jfo_work%w, b%jfo_work%w)
    call cr(a%jfo_work%p_left, b%jfo_work%p_left)
    call cr(a%jfo_work%p_right, b%jfo_work%p_right)
    call cr(a%jfo_work%theta_left, b%jfo_work%theta_left)
    call cr(a%jfo_work%theta_right, b%jfo_work%theta_right)
    call cr(a%jfo_work%qcl, b%jfo_work%qcl)
    call cr(a%jfo_work%qcr, b%jfo_work%qcr)
    call cra(a%jfo_work%ca, b%jfo_work%ca)
    call cra(a%jfo_work%kd, b%jfo_work%kd)
    call cra(a%jfo_work%ps, b%jfo_work%ps)
    call cra(a%jfo_work%h, b%jfo_work%h)
    call cra(a%jfo_work%content_old, b%jfo_work%content_old)
    call cra(a%jfo_work%pc, b%jfo_work%pc)
    call cra(a%jfo_work%wv, b%jfo_work%wv)
    call cr(a%jfo_work%dmax, b%jfo_work%dmax)
    call cl(a%jfo_work%edge_meniscus, b%jfo_work%edge_meniscus)
    call cl(a%jfo_work%front_content, b%jfo_work%front_content)
    call cl(a%jfo_work%edge_cells, b%jfo_work%edge_cells)
    call cr(a%jfo_work%thin_fade_from, b%jfo_work%thin_fade_from)
    call cr(a%jfo_work%thin_fade_width, b%jfo_work%thin_fade_width)
    call cl(a%jfo_work%full_hd, b%jfo_work%full_hd)
    call cra(a%jfo_scratch%v, b%jfo_scratch%v)
    call cra(a%jfo_scratch%vt, b%jfo_scratch%vt)
    call cra(a%jfo_scratch%vpre, b%jfo_scratch%vpre)
    call cra(a%jfo_scratch%vbest, b%jfo_scratch%vbest)
    call cra(a%jfo_scratch%dv, b%jfo_scratch%dv)
    call cra(a%jfo_scratch%r, b%jfo_scratch%r)
    call cra(a%jfo_scratch%rt, b%jfo_scratch%rt)
    call cra(a%jfo_scratch%tw, b%jfo_scratch%tw)
    call cra(a%jfo_scratch%cp, b%jfo_scratch%cp)
    call cra(a%jfo_scratch%y, b%jfo_scratch%y)
    call cra(a%jfo_scratch%ev%pn, b%jfo_scratch%ev%pn)
    call cra(a%jfo_scratch%ev%tn, b%jfo_scratch%ev%tn)
    call cra(a%jfo_scratch%ev%fl, b%jfo_scratch%ev%fl)
    call cra(a%jfo_scratch%ev%dfpl, b%jfo_scratch%ev%dfpl)
    call cra(a%jfo_scratch%ev%dfpr, b%jfo_scratch%ev%dfpr)
    call cra(a%jfo_scratch%ev%dftl, b%jfo_scratch%ev%dftl)
    call cra(a%jfo_scratch%ev%dftr, b%jfo_scratch%ev%dftr)
    call cra(a%jfo_scratch%ev%jl, b%jfo_scratch%ev%jl)
    call cra(a%jfo_scratch%ev%jd, b%jfo_scratch%ev%jd)
    call cra(a%jfo_scratch%ev%ju, b%jfo_scratch%ev%ju)
    call cr(a%q_left, b%q_left)
    call cr(a%q_right, b%q_right)
    call cr(a%dt, b%dt)
    call cr(a%q_face_left, b%q_face_left)
    call cr(a%q_face_right, b%q_face_right)
    call cra(a%content_prev, b%content_prev)
    call cra(a%content_key, b%content_key)
    call cra(a%content_end, b%content_end)
    call cra(a%content_hist, b%content_hist)
    call cr(a%u_key, b%u_key)
    call cr(a%r_step, b%r_step)
    call ci(a%hist_steps, b%hist_steps)
    call cr(a%x_left, b%x_left)
    call cr(a%x_right, b%x_right)
    call cr(a%x_left_prev, b%x_left_prev)
    call cr(a%x_right_prev, b%x_right_prev)
    call ci(a%sign_prev(1), b%sign_prev(1))
    call ci(a%sign_prev(2), b%sign_prev(2))
    call ci(a%sign_prev(3), b%sign_prev(3))
    call ci(a%sign_prev(4), b%sign_prev(4))
    call cl(a%held_prev(1), b%held_prev(1))
    call cl(a%held_prev(2), b%held_prev(2))
    call cl(a%held_end, b%held_end)
    call cl(a%blown, b%blown)
    call cl(a%starved, b%starved)
    call cr(a%available, b%available)
    call cr(a%ds, b%ds)
    call cr(a%theta_in, b%theta_in)
    call cl(a%edge_cells, b%edge_cells)
    call cl(a%front_content, b%front_content)
    call cr(a%behind, b%behind)
    call cr(a%cap_left, b%cap_left)
    call cr(a%cap_right, b%cap_right)
    call cr(a%p_back, b%p_back)
    call cr(a%p_lower, b%p_lower)
    call cl(a%gas_channel, b%gas_channel)
    call cr(a%w_gas, b%w_gas)
    call cl(a%face_open, b%face_open)
  end subroutine compare

  subroutine tally(same)
    logical, intent(in) :: same
    ncomp = ncomp + 1
    if (same) nsame = nsame + 1
  end subroutine tally

  subroutine cr(x, y)
    real(dp), intent(in) :: x, y
    call tally(x == y)
  end subroutine cr

  subroutine ci(x, y)
    integer, intent(in) :: x, y
    call tally(x == y)
  end subroutine ci

  subroutine cl(x, y)
    logical, intent(in) :: x, y
    call tally(x .eqv. y)
  end subroutine cl

  subroutine cra(x, y)
    real(dp), allocatable, intent(in) :: x(:), y(:)
    if (allocated(x) .neqv. allocated(y)) then
      call tally(.false.)
    else if (.not. allocated(x)) then
      call tally(.true.)
    else if (lbound(x, 1) /= lbound(y, 1) .or. ubound(x, 1) /= ubound(y, 1)) then
      call tally(.false.)
    else
      call tally(all(x == y))
    end if
  end subroutine cra

  subroutine cla(x, y)
    logical, allocatable, intent(in) :: x(:), y(:)
    if (allocated(x) .neqv. allocated(y)) then
      call tally(.false.)
    else if (.not. allocated(x)) then
      call tally(.true.)
    else if (lbound(x, 1) /= lbound(y, 1) .or. ubound(x, 1) /= ubound(y, 1)) then
      call tally(.false.)
    else
      call tally(all(x .eqv. y))
    end if
  end subroutine cla

  !> The addresses of f's arrays (all allocated).
  function addresses(f) result(a)
    type(film_type), intent(in), target :: f
    integer(c_intptr_t) :: a(n_arrays)
    a = [ad(f%x), ad(f%s), ad(f%smid), ad(f%h), ad(f%hmid), ad(f%p), ad(f%eta), ad(f%kmid), &
         ad(f%etamid), transfer(c_loc(f%active), 0_c_intptr_t), ad(f%work%a0), ad(f%work%b0), &
         ad(f%work%c0), ad(f%work%r), ad(f%work%cp), ad(f%pold), ad(f%theta), &
         ad(f%content_old), ad(f%pc), ad(f%jfo_work%ca), ad(f%jfo_work%kd), ad(f%jfo_work%ps), &
         ad(f%jfo_work%h), ad(f%jfo_work%content_old), ad(f%jfo_work%pc), ad(f%jfo_work%wv), &
         ad(f%jfo_scratch%v), ad(f%jfo_scratch%vt), ad(f%jfo_scratch%vpre), &
         ad(f%jfo_scratch%vbest), ad(f%jfo_scratch%dv), ad(f%jfo_scratch%r), &
         ad(f%jfo_scratch%rt), ad(f%jfo_scratch%tw), ad(f%jfo_scratch%cp), ad(f%jfo_scratch%y), &
         ad(f%jfo_scratch%ev%pn), ad(f%jfo_scratch%ev%tn), ad(f%jfo_scratch%ev%fl), &
         ad(f%jfo_scratch%ev%dfpl), ad(f%jfo_scratch%ev%dfpr), ad(f%jfo_scratch%ev%dftl), &
         ad(f%jfo_scratch%ev%dftr), ad(f%jfo_scratch%ev%jl), ad(f%jfo_scratch%ev%jd), &
         ad(f%jfo_scratch%ev%ju), ad(f%content_prev), ad(f%content_key), ad(f%content_end), &
         ad(f%content_hist)]
  end function addresses

  integer(c_intptr_t) function ad(x)
    real(dp), intent(in), target :: x(:)
    ad = transfer(c_loc(x), 0_c_intptr_t)
  end function ad
end program test_film_copy
