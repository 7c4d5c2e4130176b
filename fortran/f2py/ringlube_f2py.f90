!> The f2py layer: plain-array entry points with iso_c_binding kinds over ringlube_api.
!>
!> f2py cannot pass derived types, so a case is parsed once from deck text into a handle
!> (`rl_open`), run (`rl_run`, `rl_run_batch`) and closed (`rl_close`). Results come back
!> as arrays whose columns follow the kernel's result tables (`rl_table`), so Python
!> addresses them by name; `rl_run` writes the HDF5 file itself (the kernel's writer), so
!> results never travel back to the kernel to be written. Text travels as UTF-8 bytes. Errors come back as (code,
!> message); nothing here stops the process.

!> A kernel table as tab-separated text: 'inputs', 'presets', 'series', 'int_series',
!> 'scalars', 'flags'. `n` is the text's length (0 for an unknown table).
subroutine rl_table(which, text, n)
  use, intrinsic :: iso_c_binding, only: c_int
  use ringlube_api, only: api_table
  implicit none
  character(len=*), intent(in) :: which
  character(len=65536), intent(out) :: text
  integer(c_int), intent(out) :: n
  character(len=:), allocatable :: t
  t = api_table(which)
  n = min(len(t), len(text))
  text = t
end subroutine rl_table

!> The kernel's version.
subroutine rl_version(text)
  use ringlube_version, only: package_version
  implicit none
  character(len=32), intent(out) :: text
  text = package_version
end subroutine rl_version

!> The kernel build's identity (fortran/kernel_id.cmake: a hash of its sources, compiler
!> and flags).
subroutine rl_kernel_id(text)
  use ringlube_kernel_id, only: kernel_id
  implicit none
  character(len=32), intent(out) :: text
  text = kernel_id
end subroutine rl_kernel_id

!> Parse deck text (named `name` in messages, relative paths against `base_dir`) with the
!> variables of `overrides` replacing the deck's. Returns a handle, the crank steps, the liner
!> cells, the sectors (0 for a round bore) and the orders of the distortion a run reports.
subroutine rl_open(text, name, base_dir, overrides, overrides_name, load_trace, handle, &
                   nsteps, nliner, nsectors, norders, code, message, notes)
  use, intrinsic :: iso_c_binding, only: c_int
  use ringlube_error, only: error_type, error_status
  use ringlube_api, only: api_open, api_nsteps, api_liner_cells, api_notes, api_sectors, &
                          api_bore_orders
  implicit none
  character(len=*), intent(in) :: text, name, base_dir, overrides, overrides_name
  integer(c_int), intent(in) :: load_trace
  integer(c_int), intent(out) :: handle, nsteps, nliner, nsectors, norders, code
  character(len=4096), intent(out) :: message
  !> the case's warning ('' none; ringlube-solve prints it on stderr)
  character(len=1024), intent(out) :: notes
  type(error_type), allocatable :: err
  integer :: h
  handle = 0
  nsteps = 0
  nliner = 0
  nsectors = 0
  norders = 0
  notes = ''
  call api_open(text, name, base_dir, overrides, overrides_name, load_trace /= 0, h, err)
  call error_status(err, code, message)
  if (allocated(err)) return
  handle = h
  nsteps = api_nsteps(h)
  nliner = api_liner_cells(h)
  nsectors = api_sectors(h)
  norders = size(api_bore_orders(h))
  notes = api_notes(h)
end subroutine rl_open

!> Release a handle.
subroutine rl_close(handle)
  use, intrinsic :: iso_c_binding, only: c_int
  use ringlube_api, only: api_close
  implicit none
  integer(c_int), intent(in) :: handle
  call api_close(handle)
end subroutine rl_close

!> Effective value of `&group name` as deck text.
subroutine rl_get(handle, group, name, value, code, message)
  use, intrinsic :: iso_c_binding, only: c_int
  use ringlube_error, only: error_type, error_status
  use ringlube_api, only: api_get
  implicit none
  integer(c_int), intent(in) :: handle
  character(len=*), intent(in) :: group, name
  character(len=4096), intent(out) :: value, message
  integer(c_int), intent(out) :: code
  character(len=:), allocatable :: t
  type(error_type), allocatable :: err
  call api_get(handle, group, name, t, err)
  value = t
  call error_status(err, code, message)
end subroutine rl_get

!> Length in bytes of the deck text the kernel read (the deck, its calibration file and
!> the overrides).
subroutine rl_deck_length(handle, n)
  use, intrinsic :: iso_c_binding, only: c_int
  use ringlube_api, only: api_deck_text
  implicit none
  integer(c_int), intent(in) :: handle
  integer(c_int), intent(out) :: n
  n = len(api_deck_text(handle))
end subroutine rl_deck_length

!> The deck text the kernel read, one byte per element (f2py mishandles 1-byte integers).
subroutine rl_deck_text(handle, n, buf)
  use, intrinsic :: iso_c_binding, only: c_int
  use ringlube_api, only: api_deck_text
  implicit none
  integer(c_int), intent(in) :: handle, n
  integer(c_int), intent(out) :: buf(n)
  character(len=:), allocatable :: t
  integer :: i
  t = api_deck_text(handle)
  buf = 0
  do i = 1, min(n, len(t))
    buf(i) = ichar(t(i:i))
  end do
end subroutine rl_deck_text

!> Points of the case's gas-pressure trace (0 without one).
subroutine rl_trace_length(handle, n)
  use, intrinsic :: iso_c_binding, only: c_int
  use ringlube_api, only: api_trace
  implicit none
  integer(c_int), intent(in) :: handle
  integer(c_int), intent(out) :: n
  real(8), allocatable :: psi(:), p(:)
  call api_trace(handle, psi, p)
  n = size(psi)
end subroutine rl_trace_length

!> The case's gas-pressure trace as the kernel holds it (deg, Pa abs, times pressure_scale).
subroutine rl_trace(handle, n, psi, p)
  use, intrinsic :: iso_c_binding, only: c_int, c_double
  use ringlube_api, only: api_trace
  implicit none
  integer(c_int), intent(in) :: handle, n
  real(c_double), intent(out) :: psi(n), p(n)
  real(8), allocatable :: a(:), b(:)
  call api_trace(handle, a, b)
  psi = 0
  p = 0
  psi(1:min(n, size(a))) = a(1:min(n, size(a)))
  p(1:min(n, size(b))) = b(1:min(n, size(b)))
end subroutine rl_trace

!> Replace the case's gas-pressure trace (deg, Pa abs).
subroutine rl_set_trace(handle, n, psi, p, code, message)
  use, intrinsic :: iso_c_binding, only: c_int, c_double
  use ringlube_error, only: error_type, error_status
  use ringlube_api, only: api_set_trace
  implicit none
  integer(c_int), intent(in) :: handle, n
  real(c_double), intent(in) :: psi(n), p(n)
  integer(c_int), intent(out) :: code
  character(len=4096), intent(out) :: message
  type(error_type), allocatable :: err
  call api_set_trace(handle, psi, p, err)
  call error_status(err, code, message)
end subroutine rl_set_trace

!> Run the case. Columns of `series`, `iseries`, `scalars` and `liner` are the rows of the
!> tables 'series', 'int_series', 'scalars' and 'liner' (the liner film at the end of the
!> reported cycle, nliner cells: a starved inlet); `sectors(k, j, i)` is row i of the table
!> 'sectors' at crank step k and sector j (nm sectors of a distorted bore, from rl_open), and
!> `conform(i)` A_k over its conformability limit of the distortion's order `orders(i)` (nk
!> orders, from rl_open); `made` names the models whose results the run produced (the
!> `requires` of the rows it has, blank-separated). With a non-empty `out_path` the kernel
!> also writes the result there (HDF5, atomically; the path is checked before the run).
subroutine rl_run(handle, out_path, nsteps, ns, ni, nc, nl, nliner, nm, nsec, nk, series, &
                  iseries, scalars, liner, sectors, orders, conform, made, code, message)
  use, intrinsic :: iso_c_binding, only: c_int, c_double
  use ringlube_error, only: error_type, error_status, rl_runtime_error, rl_interrupted, fatal_error
  use ringlube_fsys, only: interrupt_catch_begin, interrupt_catch_end
  use ringlube_api, only: api_run
  use ringlube_results, only: result_type, n_series, n_int_series, n_scalars, n_liner, &
                              n_sector_series, produced_models
  implicit none
  integer(c_int), intent(in) :: handle, nsteps, ns, ni, nc, nl, nliner, nm, nsec, nk
  character(len=*), intent(in) :: out_path
  real(c_double), intent(out) :: series(nsteps, ns)
  integer(c_int), intent(out) :: iseries(nsteps, ni)
  real(c_double), intent(out) :: scalars(nc)
  real(c_double), intent(out) :: liner(nliner, nl)
  real(c_double), intent(out) :: sectors(nsteps, nm, nsec)
  integer(c_int), intent(out) :: orders(nk)
  real(c_double), intent(out) :: conform(nk)
  character(len=64), intent(out) :: made
  integer(c_int), intent(out) :: code
  character(len=4096), intent(out) :: message
  type(result_type) :: r
  type(error_type), allocatable :: err
  integer :: m, k
  series = 0.0_c_double
  iseries = 0
  scalars = 0.0_c_double
  liner = 0.0_c_double
  sectors = 0.0_c_double
  orders = 0
  conform = 0.0_c_double
  made = ''
  code = 0
  message = ''
  if (ns /= n_series .or. ni /= n_int_series .or. nc /= n_scalars .or. nl /= n_liner .or. &
      nsec /= n_sector_series) then
    code = rl_runtime_error
    message = 'rl_run: result table sizes differ from the caller''s'
    return
  end if
  ! Ctrl-C stops the kernel within a crank step (rl_interrupted), not after the run
  call interrupt_catch_begin()
  call api_run(handle, r, err, out_path)
  if (interrupt_catch_end() .and. .not. allocated(err)) &
    call fatal_error(err, 'interrupted', rl_interrupted)
  call error_status(err, code, message)
  if (allocated(err)) return
  m = 0
  if (allocated(r%sectors)) m = size(r%sectors, 2)
  k = 0
  if (allocated(r%conformability)) k = size(r%conformability)
  if (r%nsteps /= nsteps .or. size(r%liner, 1) /= nliner .or. m /= nm .or. k /= nk) then
    code = rl_runtime_error
   message = 'rl_run: number of crank steps, liner cells, sectors or orders differs from rl_open''s'
    return
  end if
  series = r%series
  iseries = r%int_series
  scalars = r%scalars
  liner = r%liner
  if (nm > 0) sectors = r%sectors
  if (nk > 0) then
    orders = r%conformability_orders
    conform = r%conformability
  end if
  made = produced_models(r)
end subroutine rl_run

!> Ask for a progress line on standard error (a terminal only) in the runs that follow
!> (on = 1) or not (0): `ringlube run` without -q (ringlube_fsys, fsys.c).
subroutine rl_progress(on)
  use, intrinsic :: iso_c_binding, only: c_int
  use ringlube_fsys, only: progress_enable
  implicit none
  integer(c_int), intent(in) :: on
  call progress_enable(on /= 0)
end subroutine rl_progress

!> Run `nd` designs of one case: row i of `x` gives the values of the variables named in
!> `keys` ('group.name' separated by blanks). `out(i, :)` are the scalar results of design
!> i (table 'scalars'); `codes(i)` its error code (0: ok) and `messages(i)` its error
!> message (UTF-8, blank for a design that ran).
subroutine rl_run_batch(handle, keys, nd, nv, x, nc, out, codes, messages)
  use, intrinsic :: iso_c_binding, only: c_int, c_double
  use ringlube_kinds, only: dp
  use ringlube_error, only: error_type, error_status, rl_input_error, rl_interrupted
  use ringlube_fsys, only: interrupt_catch_begin, interrupt_catch_end, interrupt_requested
  use ringlube_api, only: api_run_design
  use ringlube_results, only: n_scalars
  implicit none
  integer(c_int), intent(in) :: handle, nd, nv, nc
  character(len=*), intent(in) :: keys
  real(c_double), intent(in) :: x(nd, nv)
  real(c_double), intent(out) :: out(nd, nc)
  integer(c_int), intent(out) :: codes(nd)
  character(len=1024), intent(out) :: messages(nd)
  character(len=64) :: names(nv)
  type(error_type), allocatable :: err
  real(dp) :: s(n_scalars)
  integer :: i, ios
  out = 0.0_c_double
  codes = 0
  messages = ''
  names = ''
  read (keys, *, iostat=ios) names
  if (ios /= 0) then
    codes = rl_input_error
    messages = 'rl_run_batch: cannot read the variable names '//keys
    return
  end if
  ! Ctrl-C stops the batch within a crank step: the design running and every one after it
  ! get the code rl_interrupted
  call interrupt_catch_begin()
  do i = 1, nd
    call api_run_design(handle, names, x(i, :), s, err)
    call error_status(err, codes(i), messages(i))
    if (interrupt_requested()) then
      codes(i:) = rl_interrupted
      messages(i:) = 'interrupted'
      exit
    end if
    if (allocated(err)) then
      deallocate (err)
      cycle
    end if
    out(i, :) = s(1:nc)
  end do
  if (interrupt_catch_end()) codes(nd) = rl_interrupted
end subroutine rl_run_batch

!> The summary `ringlube-solve` prints, from the scalar results `scalars` (table
!> 'scalars') of which the run produced those with `made` nonzero; `title` and `written`
!> (the first and last line) left out when blank. A run that produced the conformability (a
!> distorted bore) gives it per order: `conform(i)` for the order `orders(i)`, i = 1 .. nk
!> (the arrays hold na >= nk values: f2py passes no empty array). `n` is the text's length.
subroutine rl_summary(nc, scalars, made, nk, na, orders, conform, title, written, text, n)
  use, intrinsic :: iso_c_binding, only: c_int, c_double
  use ringlube_kinds, only: dp
  use ringlube_results, only: n_scalars, sc_conformability
  use ringlube_results_summary, only: summary_text
  implicit none
  integer(c_int), intent(in) :: nc, nk, na
  real(c_double), intent(in) :: scalars(nc)
  integer(c_int), intent(in) :: made(nc)
  integer(c_int), intent(in) :: orders(na)
  real(c_double), intent(in) :: conform(na)
  character(len=*), intent(in) :: title, written
  character(len=8192), intent(out) :: text
  integer(c_int), intent(out) :: n
  character(len=:), allocatable :: t
  if (nc /= n_scalars .or. nk < 0 .or. nk > na) then
    t = 'rl_summary: scalar table size or orders differ from the caller''s'
  else if (made(sc_conformability) /= 0) then
    ! (as ringlube-solve: a distorted bore's run has its orders, none or several)
    t = summary_text(scalars, made /= 0, title, written, int(orders(1:nk)), real(conform(1:nk), dp))
  else
    t = summary_text(scalars, made /= 0, title, written)
  end if
  n = min(len(t), len(text))
  text = t
end subroutine rl_summary

!> Slider-crank kinematics (the kernel's): piston distance from TDC x [m] and sliding
!> speed u [m/s] at crank angles psi_deg, for crank speed omega [rad/s].
subroutine rl_kinematics(n, psi_deg, crank_radius, conrod_length, omega, x, u)
  use, intrinsic :: iso_c_binding, only: c_int, c_double
  use ringlube_kinematics, only: piston_position, sliding_speed, deg2rad
  implicit none
  integer(c_int), intent(in) :: n
  real(c_double), intent(in) :: psi_deg(n), crank_radius, conrod_length, omega
  real(c_double), intent(out) :: x(n), u(n)
  x = piston_position(deg2rad(psi_deg), crank_radius, conrod_length)
  u = sliding_speed(deg2rad(psi_deg), crank_radius, conrod_length, omega)
end subroutine rl_kinematics

!> The kernel's viscosity law (Roelands): eta [Pa s] at temperatures theta [K] and absolute
!> pressures p [Pa], for eta0 [Pa s] at theta0 [K], alpha [1/Pa] and beta [1/K].
subroutine rl_viscosity(n, theta, p, eta0, theta0, alpha, beta, eta)
  use, intrinsic :: iso_c_binding, only: c_int, c_double
  use ringlube_viscosity, only: roelands
  implicit none
  integer(c_int), intent(in) :: n
  real(c_double), intent(in) :: theta(n), p(n), eta0, theta0, alpha, beta
  real(c_double), intent(out) :: eta(n)
  eta = roelands(p, theta, eta0, theta0, alpha, beta)
end subroutine rl_viscosity

!> An SAE J300 grade's kinematic viscosities at 40 and 100 degC and its window at 100 degC
!> [mm^2/s]; `code` nonzero (and `message`) for a name that is not a grade.
subroutine rl_grade(name, kv40, kv100, kv100_min, kv100_max, code, message)
  use, intrinsic :: iso_c_binding, only: c_int, c_double
  use ringlube_oil, only: grade_viscosities
  implicit none
  character(len=*), intent(in) :: name
  real(c_double), intent(out) :: kv40, kv100, kv100_min, kv100_max
  integer(c_int), intent(out) :: code
  character(len=512), intent(out) :: message
  character(len=:), allocatable :: why
  kv100_min = 0
  kv100_max = 0
  call grade_viscosities(name, kv40, kv100, why, kv100_min, kv100_max)
  code = 0
  message = ''
  if (allocated(why)) then
    code = 1
    message = why
  end if
end subroutine rl_grade

!> Greenwood-Tripp functions at the given lambdas ('exact' unless `fit` is nonzero).
subroutine rl_greenwood_tripp(n, lam, f2, f52, fit)
  use, intrinsic :: iso_c_binding, only: c_int, c_double
  use ringlube_greenwood_tripp, only: gt_init, f2_exact, f52_exact, f2_fit, f52_fit
  implicit none
  integer(c_int), intent(in) :: n, fit
  real(c_double), intent(in) :: lam(n)
  real(c_double), intent(out) :: f2(n), f52(n)
  if (fit /= 0) then
    f2 = f2_fit(lam)
    f52 = f52_fit(lam)
  else
    call gt_init()
    f2 = f2_exact(lam)
    f52 = f52_exact(lam)
  end if
end subroutine rl_greenwood_tripp

!> Number of items of namelist text (see `rl_items`) and the bytes of all their values
!> (`nbytes`, at least 1); `lists` nonzero lets a variable take a list of values. An error of
!> the text comes back as (code, message) with n = 0.
subroutine rl_items_count(text, name, lists, n, nbytes, code, message)
  use, intrinsic :: iso_c_binding, only: c_int
  use ringlube_error, only: error_type, error_status
  use ringlube_namelist, only: nml_item, scan_namelist
  implicit none
  character(len=*), intent(in) :: text, name
  integer(c_int), intent(in) :: lists
  integer(c_int), intent(out) :: n, nbytes, code
  character(len=4096), intent(out) :: message
  type(nml_item), allocatable :: items(:)
  type(error_type), allocatable :: err
  integer :: m, i
  n = 0
  nbytes = 1
  call scan_namelist(text, name, items, m, err, lists=lists /= 0)
  call error_status(err, code, message)
  if (allocated(err)) return
  n = m
  nbytes = max(1, sum([(len(items(i)%value), i=1, m)]))
end subroutine rl_items_count

!> The items of namelist text as the kernel's scanner reads them (`name` names the text in
!> messages): for item i its group and variable (lower case, at most 64 bytes), its value as
!> written (quotes removed, doubled quotes undone: `vlen(i)` bytes of `chars`, the values one
!> after the other, of any length, as ringlube-solve reads them), the line it is on, its
!> position in its variable's list (`indices`, 1 for a scalar), whether it was quoted and the
!> line its group opens on. `n` and `nbytes` come from `rl_items_count`; a longer name is an
!> input error naming file:line.
subroutine rl_items(text, name, lists, n, nbytes, groups, names, chars, vlen, lines, indices, &
                    quoted, group_lines, code, message)
  use, intrinsic :: iso_c_binding, only: c_int
  use ringlube_error, only: error_type, error_status, rl_runtime_error, rl_input_error
  use ringlube_namelist, only: nml_item, scan_namelist
  use ringlube_textio, only: itoa
  implicit none
  character(len=*), intent(in) :: text, name
  integer(c_int), intent(in) :: lists, n, nbytes
  character(len=64), intent(out) :: groups(n), names(n)
  character(len=1), intent(out) :: chars(nbytes)
  integer(c_int), intent(out) :: vlen(n), lines(n), indices(n), quoted(n), group_lines(n)
  integer(c_int), intent(out) :: code
  character(len=4096), intent(out) :: message
  type(nml_item), allocatable :: items(:)
  type(error_type), allocatable :: err
  integer :: m, i, j, at
  groups = ''
  names = ''
  chars = ' '
  vlen = 0
  lines = 0
  indices = 0
  quoted = 0
  group_lines = 0
  call scan_namelist(text, name, items, m, err, lists=lists /= 0)
  call error_status(err, code, message)
  if (allocated(err)) return
  if (m /= n .or. sum([(len(items(i)%value), i=1, m)]) > nbytes) then
    code = rl_runtime_error
    message = 'rl_items: items differ from rl_items_count''s'
    return
  end if
  at = 0
  do i = 1, m
    if (len(items(i)%name) > len(names(i)) .or. len(items(i)%group) > len(groups(i))) then
      code = rl_input_error
      message = name//':'//itoa(items(i)%line)//': &'//items(i)%group//' '//items(i)%name// &
                ': longer than '//itoa(len(names(i)))//' bytes (a group or variable name)'
      return
    end if
    groups(i) = items(i)%group
    names(i) = items(i)%name
    do j = 1, len(items(i)%value)
      chars(at + j) = items(i)%value(j:j)
    end do
    at = at + len(items(i)%value)
    vlen(i) = len(items(i)%value)
    lines(i) = items(i)%line
    indices(i) = items(i)%index
    quoted(i) = merge(1, 0, items(i)%quoted)
    group_lines(i) = items(i)%group_line
  end do
end subroutine rl_items
