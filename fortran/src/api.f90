!> Cases held in memory for callers that cannot hold derived types (the f2py layer).
!>
!> A case is parsed once from deck text (`api_open`), kept in a small store under an
!> integer handle, run any number of times (one design or a batch of designs), and closed
!> (`api_close`). The store holds parsed inputs only, never run state: two runs of the
!> same handle give identical results; a run writes its own HDF5 file when given a path
!> (`api_run`), so results never come back to the kernel to be written. The tables of
!> inputs, presets and results are exported as tab-separated text (`api_table`).
!>
!> The store is module state and not safe to call from several threads at once. Python never
!> does: the f2py layer holds the GIL for the whole of every call (no `threadsafe`), so
!> calls from several Python threads take turns (tests/python/test_run.py,
!> test_runs_from_several_threads_equal_serial); parallel studies use processes.
module ringlube_api
  use ringlube_kinds, only: dp
  use ringlube_error, only: error_type, fatal_error, rl_input_error
  use ringlube_case, only: case_type, case_access, access_set, access_get, validate_case, &
                           real_text, uses_oil_data
  use ringlube_inputs, only: inputs, n_inputs, find_input, presets, n_presets, kind_int, kind_real
  use ringlube_deck, only: read_deck_text, scale_trace
  use ringlube_gas, only: check_pressure_trace, max_pressure
  use ringlube_results, only: result_type, series_spec, n_series, int_series_spec, &
                              n_int_series, scalar_spec, n_scalars, flag_bits, n_flags, &
                              field_spec, liner_spec, n_liner, sc_run_time, models, n_models, &
                              sector_spec, n_sector_series, &
                              margin_thresholds
  use ringlube_hdf5_output, only: write_result
  use ringlube_output_path, only: check_output
  use ringlube_cycle, only: solve_cycle
  use ringlube_ring_pack_cycle, only: ring_pack_check
  use ringlube_oil_supply, only: supply_type, supply_setup
  use ringlube_bore, only: bore_type, bore_setup, conformability_orders
  use ringlube_textio, only: itoa
  use, intrinsic :: iso_fortran_env, only: int64
  implicit none
  private
  public :: api_open, api_close, api_notes, api_case_ok, api_run, api_get, api_set, api_set_trace, &
            api_run_design, api_table, api_nsteps, api_deck_text, api_trace, api_liner_cells, &
            api_sectors, api_bore_orders

  type(case_type), allocatable, save :: store(:)
  logical, allocatable, save :: used(:)

  character(len=1), parameter :: tab = achar(9), nl = achar(10)
  !> what the inputs of a run are, in output-file messages
  character(len=*), parameter :: input_labels(5) = [character(len=20) :: &
                                                    'the deck', 'the pressure file', &
                                                    'the calibration file', 'the profile file', &
                                                    'the distortion file']

contains

  !> Parse deck text into a new handle (see `read_deck_text` for the arguments).
  subroutine api_open(text, name, base_dir, overrides, overrides_name, load_trace, handle, err)
    character(len=*), intent(in) :: text, name, base_dir, overrides, overrides_name
    logical, intent(in) :: load_trace
    integer, intent(out) :: handle
    type(error_type), allocatable, intent(out) :: err
    type(case_type) :: c
    handle = 0
    call read_deck_text(text, name, base_dir, c, err, overrides, overrides_name, load_trace)
    if (allocated(err)) return
    handle = free_slot()
    store(handle) = c
    used(handle) = .true.
  end subroutine api_open

  !> Release a handle (an unknown handle is ignored).
  subroutine api_close(handle)
    integer, intent(in) :: handle
    type(case_type) :: empty
    if (.not. api_case_ok(handle)) return
    store(handle) = empty
    used(handle) = .false.
  end subroutine api_close

  !> Is `handle` an open case?
  logical function api_case_ok(handle)
    integer, intent(in) :: handle
    api_case_ok = .false.
    if (.not. allocated(used)) return
    if (handle < 1 .or. handle > size(used)) return
    api_case_ok = used(handle)
  end function api_case_ok

  !> Crank steps of the reported cycle.
  integer function api_nsteps(handle)
    integer, intent(in) :: handle
    api_nsteps = nint(720.0_dp / store(handle)%dpsi_deg)
  end function api_nsteps

  !> The deck text of a case as the kernel read it ('' for an unknown handle).
  function api_deck_text(handle) result(t)
    integer, intent(in) :: handle
    character(len=:), allocatable :: t
    t = ''
    if (api_case_ok(handle)) t = store(handle)%deck_text
  end function api_deck_text

  !> The case's warning ('' none: c%notes, e.g. inputs of a model that is off).
  function api_notes(handle) result(t)
    integer, intent(in) :: handle
    character(len=:), allocatable :: t
    t = ''
    if (api_case_ok(handle)) then
      if (allocated(store(handle)%notes)) t = store(handle)%notes
    end if
  end function api_notes

  !> Cells of the liner film a run of the case reports (0 without a starved inlet).
  integer function api_liner_cells(handle)
    integer, intent(in) :: handle
    api_liner_cells = 0
    if (api_case_ok(handle)) api_liner_cells = liner_cells(store(handle))
  end function api_liner_cells

  !> Sectors of the circumference a run of the case reports (0 for a round bore).
  integer function api_sectors(handle)
    integer, intent(in) :: handle
    api_sectors = 0
    if (.not. api_case_ok(handle)) return
    if (store(handle)%bore == 'distorted') api_sectors = store(handle)%sectors
  end function api_sectors

  !> The orders of a distorted bore's distortion, as a run reports their conformability
  !> (`result_type%conformability_orders`; none for a round bore or an unknown handle).
  function api_bore_orders(handle) result(orders)
    integer, intent(in) :: handle
    integer, allocatable :: orders(:)
    type(bore_type) :: b
    allocate (orders(0))
    if (api_sectors(handle) == 0) return
    call bore_setup(store(handle), b)
    orders = conformability_orders(b)
  end function api_bore_orders

  !> The gas-pressure trace of a case (empty for an unknown handle or no trace).
  subroutine api_trace(handle, psi, p)
    integer, intent(in) :: handle
    real(dp), allocatable, intent(out) :: psi(:), p(:)
    if (api_case_ok(handle)) then
      psi = store(handle)%gas_psi
      p = store(handle)%gas_p
    else
      allocate (psi(0), p(0))
    end if
  end subroutine api_trace

  !> Run the case; its scalar `run_time` is the kernel time. With a non-blank `out_path` the
  !> result is also written there (HDF5, atomically); the path is checked before the run
  !> (not one of the run's inputs, see `check_output`).
  subroutine api_run(handle, res, err, out_path)
    integer, intent(in) :: handle
    type(result_type), intent(out) :: res
    type(error_type), allocatable, intent(out) :: err
    character(len=*), intent(in), optional :: out_path
    integer(int64) :: t0, t1, rate
    logical :: to_file
    type(case_type) :: cw
    if (.not. check_handle(handle, err)) return
    to_file = .false.
    if (present(out_path)) to_file = len_trim(out_path) > 0
    associate (c => store(handle))
      if (to_file) then
        call check_output(out_path, [character(len=max(len(c%deck_path), len(c%pressure_file), &
                                                       len(c%calibration_file), &
                                                       len(c%profile_file), &
                                                       len(c%distortion_file), 1)) :: &
                                     c%deck_path, c%pressure_file, c%calibration_file, &
                                     c%profile_file, c%distortion_file], input_labels, err)
        if (allocated(err)) return
      end if
      call system_clock(t0, rate)
      call solve_cycle(c, res, err)
      call system_clock(t1)
      res%scalars(sc_run_time) = real(t1 - t0, dp) / real(rate, dp)
      if (.not. allocated(err)) call ring_pack_check(c, res%scalars, err)
      if (allocated(err) .or. .not. to_file) return
      ! the file records where it was written, not the deck's &output file
      cw = c
      cw%output_file = out_path
      call write_result(out_path, cw, res, err, &
                        [character(len=max(len(c%calibration_file), len(c%profile_file), &
                                           len(c%distortion_file))) :: &
                         c%calibration_file, c%profile_file, c%distortion_file], input_labels(3:5))
    end associate
  end subroutine api_run

  !> Run one design: the case with `values(j)` (deck text) assigned to the variables
  !> `keys(j)` ('group.name'); the stored case is not changed. `scalars` are the scalar
  !> results in the order of `scalar_spec`.
  subroutine api_run_design(handle, keys, values, scalars, err)
    integer, intent(in) :: handle
    character(len=*), intent(in) :: keys(:)
    real(dp), intent(in) :: values(:)
    real(dp), intent(out) :: scalars(n_scalars)
    type(error_type), allocatable, intent(out) :: err
    type(case_type) :: c
    type(result_type) :: res
    character(len=:), allocatable :: text, why
    integer :: j, k
    integer(int64) :: t0, t1, rate
    scalars = 0.0_dp
    if (.not. check_handle(handle, err)) return
    c = store(handle)
    do j = 1, size(keys)
      k = key_index(keys(j))
      if (k == 0) then
        call fatal_error(err, c%deck_path//': '//trim(keys(j))//': unknown variable', &
                         rl_input_error)
        return
      end if
      if (uses_oil_data(c) .and. trim(inputs(k)%group) == 'lubricant' .and. &
          any(trim(inputs(k)%name) == [character(len=6) :: 'eta0', 'theta0', 'beta'])) then
        call fatal_error(err, c%deck_path//': &lubricant '//trim(inputs(k)%name)//': the '// &
                         'case takes its viscosity from the oil''s grade or kv40 and kv100, '// &
                         'which give eta0, theta0 and beta: vary those instead', rl_input_error)
        return
      end if
      if (inputs(k)%kind == kind_int) then
        if (.not. (abs(values(j)) < 2e9_dp)) then
          why = 'not an integer: '//real_text(values(j))
        else if (values(j) /= anint(values(j))) then
          why = 'not an integer: '//real_text(values(j))
        else
          text = itoa(nint(values(j)))
          call case_access(c, k, access_set, text, why)
        end if
      else if (inputs(k)%kind == kind_real .and. trim(inputs(k)%name) /= 'pressure_file') then
        text = real_text(values(j))
        call case_access(c, k, access_set, text, why)
      else
        why = 'cannot be set per design (not a number)'
      end if
      if (allocated(why)) then
        call fatal_error(err, c%deck_path//': &'//trim(inputs(k)%group)//' '// &
                         trim(inputs(k)%name)//': '//why, rl_input_error)
        return
      end if
    end do
    call validate_case(c, err)
    if (allocated(err)) return
    ! the design's pressure_scale times the trace as read
    call scale_trace(c, err)
    if (allocated(err)) return
    call system_clock(t0, rate)
    call solve_cycle(c, res, err)
    call system_clock(t1)
    if (allocated(err)) return
    call ring_pack_check(c, res%scalars, err)
    if (allocated(err)) return
    res%scalars(sc_run_time) = real(t1 - t0, dp) / real(rate, dp)
    scalars = res%scalars
  end subroutine api_run_design

  !> The effective value of `&group name` as deck text.
  subroutine api_get(handle, group, name, text, err)
    integer, intent(in) :: handle
    character(len=*), intent(in) :: group, name
    character(len=:), allocatable, intent(out) :: text
    type(error_type), allocatable, intent(out) :: err
    character(len=:), allocatable :: why
    integer :: k
    text = ''
    if (.not. check_handle(handle, err)) return
    k = find_input(group, name)
    if (k == 0) then
      call fatal_error(err, '&'//group//' '//name//': unknown variable', rl_input_error)
      return
    end if
    call case_access(store(handle), k, access_get, text, why)
  end subroutine api_get

  !> Set `&group name` from deck text (range-checked; relations checked with the case).
  subroutine api_set(handle, group, name, text, err)
    integer, intent(in) :: handle
    character(len=*), intent(in) :: group, name, text
    type(error_type), allocatable, intent(out) :: err
    character(len=:), allocatable :: why, t
    integer :: k
    if (.not. check_handle(handle, err)) return
    k = find_input(group, name)
    if (k == 0) then
      call fatal_error(err, store(handle)%deck_path//': &'//group//' '//name// &
                       ': unknown variable', rl_input_error)
      return
    end if
    t = text
    call case_access(store(handle), k, access_set, t, why)
    if (allocated(why)) then
      call fatal_error(err, store(handle)%deck_path//': &'//group//' '//name//': ' &
                       //why, rl_input_error)
      return
    end if
    call validate_case(store(handle), err)
    if (allocated(err)) return
    call scale_trace(store(handle), err)   ! pressure_scale may be what changed
  end subroutine api_set

  !> Replace the gas-pressure trace by arrays (deg, Pa abs; checked like a CSV file, then
  !> multiplied by the case's pressure_scale).
  subroutine api_set_trace(handle, psi, p, err)
    integer, intent(in) :: handle
    real(dp), intent(in) :: psi(:), p(:)
    type(error_type), allocatable, intent(out) :: err
    if (.not. check_handle(handle, err)) return
    call check_pressure_trace(psi, p, err)
    if (allocated(err)) then
      err%message = store(handle)%deck_path//': pressure trace: '//err%message
      return
    end if
    if (.not. (store(handle)%pressure_scale * maxval(p) <= max_pressure)) then
      call fatal_error(err, store(handle)%deck_path//': pressure trace: with &operating '// &
                       'pressure_scale = '//real_text(store(handle)%pressure_scale)// &
                       ' its highest pressure is above 1000 bar (1e8 Pa, absolute)', rl_input_error)
      return
    end if
    store(handle)%gas_psi = psi
    store(handle)%gas_p_trace = p
    call scale_trace(store(handle), err)
    store(handle)%pressure_file = '<array>'
  end subroutine api_set_trace

  !> A table as tab-separated text with a header line: 'inputs', 'presets', 'series',
  !> 'int_series', 'scalars', 'liner', 'sectors', 'flags', 'models' or 'margins' ('' for an
  !> unknown name).
  function api_table(which) result(t)
    character(len=*), intent(in) :: which
    character(len=:), allocatable :: t
    integer :: i
    t = ''
    select case (which)
    case ('inputs')
      t = line('group', 'name', 'kind', 'default', 'lower', 'upper', 'unit', 'choices', &
               'description')
      do i = 1, n_inputs
        t = t//line(inputs(i)%group, inputs(i)%name, kind_name(inputs(i)%kind), &
                    inputs(i)%default, real_text(inputs(i)%lower), real_text(inputs(i)%upper), &
                    inputs(i)%unit, inputs(i)%choices, inputs(i)%description)
      end do
    case ('presets')
      t = line('preset', 'name', 'value')
      do i = 1, n_presets
        t = t//line(presets(i)%preset, presets(i)%name, presets(i)%value)
      end do
    case ('series')
      t = fields(series_spec, n_series)
    case ('int_series')
      t = fields(int_series_spec, n_int_series)
    case ('scalars')
      t = fields(scalar_spec, n_scalars)
    case ('liner')
      t = fields(liner_spec, n_liner)
    case ('sectors')
      t = fields(sector_spec, n_sector_series)
    case ('flags')
      t = line('bit', 'name', 'description')
      do i = 1, n_flags
        t = t//line(itoa(flag_bits(i)%bit), flag_bits(i)%name, flag_bits(i)%description)
      end do
    case ('models')
      t = line('name', 'group', 'variable', 'value')
      do i = 1, n_models
        t = t//line(models(i)%name, models(i)%group, models(i)%variable, models(i)%value)
      end do
    case ('margins')
      t = line('name', 'threshold', 'reason')
      do i = 1, size(margin_thresholds)
        t = t//line(margin_thresholds(i)%name, real_text(margin_thresholds(i)%threshold), &
                    margin_thresholds(i)%reason)
      end do
    end select
  end function api_table

  function fields(spec, n) result(t)
    type(field_spec), intent(in) :: spec(:)
    integer, intent(in) :: n
    character(len=:), allocatable :: t
    integer :: i
    t = line('short', 'stored', 'unit', 'kind', 'long_name', 'requires', 'objective', &
             'optimisable')
    do i = 1, n
      t = t//line(spec(i)%short, spec(i)%stored, spec(i)%unit, spec(i)%kind, spec(i)%long_name, &
                  spec(i)%requires, merge('1', '0', spec(i)%objective), &
                  merge('1', '0', spec(i)%objective .or. spec(i)%optimisable))
    end do
  end function fields

  !> One line of a table: the cells (three to nine) without their trailing blanks,
  !> tab-separated.
  pure function line(c1, c2, c3, c4, c5, c6, c7, c8, c9) result(t)
    character(len=*), intent(in) :: c1, c2, c3
    character(len=*), intent(in), optional :: c4, c5, c6, c7, c8, c9
    character(len=:), allocatable :: t
    t = trim(c1)//tab//trim(c2)//tab//trim(c3)
    if (present(c4)) t = t//tab//trim(c4)
    if (present(c5)) t = t//tab//trim(c5)
    if (present(c6)) t = t//tab//trim(c6)
    if (present(c7)) t = t//tab//trim(c7)
    if (present(c8)) t = t//tab//trim(c8)
    if (present(c9)) t = t//tab//trim(c9)
    t = t//nl
  end function line

  pure function kind_name(k) result(t)
    integer, intent(in) :: k
    character(len=:), allocatable :: t
    select case (k)
    case (1); t = 'real'
    case (2); t = 'integer'
    case (3); t = 'logical'
    case (4); t = 'string'
    case (6); t = 'real_list'
    case (7); t = 'integer_list'
    case default; t = 'choice'
    end select
  end function kind_name

  !> Table index of 'group.name' (or 'group:name'), 0 if none.
  integer function key_index(key)
    character(len=*), intent(in) :: key
    integer :: k
    k = scan(key, '.:')
    key_index = 0
    if (k < 2) return
    key_index = find_input(key(1:k - 1), trim(key(k + 1:)))
  end function key_index

  logical function check_handle(handle, err)
    integer, intent(in) :: handle
    type(error_type), allocatable, intent(out) :: err
    check_handle = api_case_ok(handle)
    if (.not. check_handle) call fatal_error(err, 'no open case with handle '//itoa(handle))
  end function check_handle

  integer function free_slot()
    type(case_type), allocatable :: tmp(:)
    logical, allocatable :: utmp(:)
    integer :: n
    if (.not. allocated(used)) then
      allocate (store(4), used(4))
      used = .false.
    end if
    do free_slot = 1, size(used)
      if (.not. used(free_slot)) return
    end do
    n = size(used)
    allocate (tmp(2 * n), utmp(2 * n))
    tmp(1:n) = store
    utmp = .false.
    utmp(1:n) = used
    call move_alloc(tmp, store)
    call move_alloc(utmp, used)
    free_slot = n + 1
  end function free_slot

  !> Cells of the liner film a run of case c reports (0 without a starved inlet).
  integer function liner_cells(c)
    type(case_type), intent(in) :: c
    type(supply_type) :: sup
    liner_cells = 0
    if (c%inlet /= 'starved') return
    call supply_setup(sup, c%width, 2.0_dp * c%crank_radius, c%width / (c%nodes - 1), &
                      c%supply_film, c%lower_ring_distance)
    liner_cells = sup%liner%nz
  end function liner_cells
end module ringlube_api
