!> Reading a case from namelist text, from a file or from memory.
!>
!> Every group is optional (a missing group means all its defaults); an unknown group or
!> variable, a malformed value, a variable given twice or a value outside its range (the
!> table of ringlube_inputs) is an input error naming the file, the line, the group and the
!> variable. Relative paths (`pressure_file`, `profile_file`, output `file`, `&calibration file`) are
!> relative to the deck's folder (the base folder given with text from memory).
!>
!> Steps: scan the text into items; add the items of the `&calibration file`; check that
!> no variable is given twice; let the overrides replace items; apply a preset; assign the
!> items through the table; resolve paths; check the whole case and load the gas trace.
module ringlube_deck
  use ringlube_kinds, only: dp
  use ringlube_error, only: error_type, fatal_error, rl_input_error
  use ringlube_case, only: case_type, default_case, apply_preset, case_access, access_set, &
                           validate_case, real_text, uses_oil_data
  use ringlube_inputs, only: inputs, n_inputs, find_input, input_key, kind_string, kind_choice, &
                             kind_real_list, kind_int_list
  use ringlube_namelist, only: nml_item, scan_namelist
  use ringlube_textio, only: read_text_file, itoa
  use ringlube_gas, only: read_pressure_csv, max_pressure
  use ringlube_bore, only: read_distortion_csv
  use ringlube_profile, only: read_profile_csv
  use ringlube_fsys, only: dir_prefix
  implicit none
  private
  public :: read_deck, read_deck_text, resolve_path, finish_case, scale_trace

contains

  !> `path` if absolute, else `base_dir // path` (base_dir ends with '/' or is empty).
  pure function resolve_path(path, base_dir) result(r)
    character(len=*), intent(in) :: path, base_dir
    character(len=:), allocatable :: r
    if (len(path) == 0) then
      r = ''
    else if (path(1:1) == '/') then
      r = path
    else if (len(base_dir) == 0) then
      r = path
    else if (base_dir(len(base_dir):len(base_dir)) == '/') then
      r = base_dir//path
    else
      r = base_dir//'/'//path
    end if
  end function resolve_path

  !> Read, check and complete a case from the deck file at `path`. With
  !> `load_trace = .false.` the gas-pressure file is not read (its existence is checked).
  subroutine read_deck(path, c, err, load_trace)
    character(len=*), intent(in) :: path
    type(case_type), intent(out) :: c
    type(error_type), allocatable, intent(out) :: err
    logical, intent(in), optional :: load_trace
    character(len=:), allocatable :: text
    call read_text_file(path, text, err)
    if (allocated(err)) then
      c = default_case()
      return
    end if
    call read_deck_text(text, path, dir_prefix(path), c, err, load_trace=load_trace)
  end subroutine read_deck

  !> Read, check and complete a case from deck text held in memory.
  !>
  !> `name` names the text in messages (a file path, or e.g. '<case cold>'); `base_dir` is
  !> the folder relative paths are resolved against. `overrides` (optional) is more deck
  !> text whose variables replace those of the deck (and of its calibration file) instead
  !> of being an error when given twice; its messages name `overrides_name`.
  subroutine read_deck_text(text, name, base_dir, c, err, overrides, overrides_name, load_trace)
    character(len=*), intent(in) :: text, name, base_dir
    type(case_type), intent(out) :: c
    type(error_type), allocatable, intent(out) :: err
    character(len=*), intent(in), optional :: overrides, overrides_name
    logical, intent(in), optional :: load_trace
    type(nml_item), allocatable :: items(:), oitems(:)
    integer :: nitems, noitems

    c = default_case()
    c%deck_path = name
    c%deck_text = text
    call scan_namelist(text, name, items, nitems, err, list_vars=list_variables())
    if (allocated(err)) return
    noitems = 0
    if (present(overrides)) then
      if (len_trim(overrides) > 0) then
        if (present(overrides_name)) then
          call scan_namelist(overrides, overrides_name, oitems, noitems, err, &
                             list_vars=list_variables())
        else
          call scan_namelist(overrides, name//' (overrides)', oitems, noitems, err, &
                             list_vars=list_variables())
        end if
        if (allocated(err)) return
        c%deck_text = c%deck_text//new_line('a')//'! --- changed in Python ---'// &
                      new_line('a')//overrides
      end if
    end if
    call include_calibration(c, items, nitems, oitems, noitems, base_dir, err)
    if (allocated(err)) return
    call check_unique(items, nitems, err)
    if (allocated(err)) return
    call check_unique(oitems, noitems, err)
    if (allocated(err)) return
    call apply_overrides(items, nitems, oitems, noitems)
    call assign_items(c, items, nitems, err)
    if (allocated(err)) return
    call check_oil_sources(c, items, nitems, err)
    if (allocated(err)) return
    call note_unused(c, items, nitems)
    c%pressure_file = resolve_path(c%pressure_file, base_dir)
    c%profile_file = resolve_path(c%profile_file, base_dir)
    c%output_file = resolve_path(c%output_file, base_dir)
    c%calibration_file = resolve_path(c%calibration_file, base_dir)
    c%distortion_file = resolve_path(c%distortion_file, base_dir)
    call finish_case(c, err, load_trace)
    if (allocated(err)) call at_line(err, name, items, nitems)
    if (allocated(err) .and. noitems > 0) then
      err%message = err%message//' (in the deck with the changes of '//trim(oname())//')'
    end if

  contains

    function oname() result(t)
      character(len=:), allocatable :: t
      if (present(overrides_name)) then
        t = overrides_name
      else
        t = name//' (overrides)'
      end if
    end function oname
  end subroutine read_deck_text

  !> Add the items of the `&calibration file` (if the deck or the overrides name one) in
  !> front of the deck's; the file's text is appended to the case's deck text.
  subroutine include_calibration(c, items, nitems, oitems, noitems, base_dir, err)
    type(case_type), intent(inout) :: c
    type(nml_item), allocatable, intent(inout) :: items(:)
    integer, intent(inout) :: nitems
    type(nml_item), allocatable, intent(in) :: oitems(:)
    integer, intent(in) :: noitems
    character(len=*), intent(in) :: base_dir
    type(error_type), allocatable, intent(out) :: err
    type(nml_item), allocatable :: citems(:), all(:)
    character(len=:), allocatable :: cpath, ctext
    integer :: ncitems, k, j, jo

    j = 0
    do k = 1, nitems
      if (items(k)%group == 'calibration') j = k
    end do
    if (j > 0) cpath = resolve_path(items(j)%value, base_dir)
    jo = 0
    do k = 1, noitems
      if (oitems(k)%group == 'calibration') jo = k
    end do
    if (jo > 0) cpath = resolve_path(oitems(jo)%value, base_dir)
    if (.not. allocated(cpath)) return
    if (len(cpath) == 0) return
    call read_text_file(cpath, ctext, err)
    if (allocated(err)) then
      if (jo > 0) then
        err%message = oitems(jo)%file//':'//itoa(oitems(jo)%line)//': &calibration file: '// &
                      err%message
      else if (j > 0) then
        err%message = items(j)%file//':'//itoa(items(j)%line)//': &calibration file: '// &
                      err%message
      else
        err%message = c%deck_path//': &calibration file: '//err%message
      end if
      return
    end if
    call scan_namelist(ctext, cpath, citems, ncitems, err, list_vars=list_variables())
    if (allocated(err)) return
    do k = 1, ncitems
      if (citems(k)%group == 'calibration' .or. citems(k)%group == 'output' .or. &
          citems(k)%group == 'numerics') then
        call item_error(citems(k), '&'//citems(k)%group// &
                        ' cannot be set in a calibration file', err, with_name=.false.)
        return
      end if
      do j = 1, nitems
        if (items(j)%group == citems(k)%group .and. items(j)%name == citems(k)%name) then
          call item_error(items(j), 'also set by the calibration file '//cpath// &
                          ' (set it in one place only)', err)
          return
        end if
      end do
    end do
    c%deck_text = c%deck_text//new_line('a')//'! --- calibration file '//cpath// &
                  ' ---'//new_line('a')//ctext
    allocate (all(nitems + ncitems))
    all(1:ncitems) = citems(1:ncitems)
    all(ncitems + 1:) = items(1:nitems)
    call move_alloc(all, items)
    nitems = nitems + ncitems
  end subroutine include_calibration

  !> No variable may be given twice in one text.
  subroutine check_unique(items, nitems, err)
    type(nml_item), allocatable, intent(in) :: items(:)
    integer, intent(in) :: nitems
    type(error_type), allocatable, intent(out) :: err
    integer :: i, j
    do i = 1, nitems
      do j = 1, i - 1
        if (items(j)%group == items(i)%group .and. items(j)%name == items(i)%name) then
          call item_error(items(i), 'given twice (also on line '//itoa(items(j)%line)//')', err)
          return
        end if
      end do
    end do
  end subroutine check_unique

  !> Drop the items an override replaces, then append the overrides.
  subroutine apply_overrides(items, nitems, oitems, noitems)
    type(nml_item), allocatable, intent(inout) :: items(:)
    integer, intent(inout) :: nitems
    type(nml_item), allocatable, intent(in) :: oitems(:)
    integer, intent(in) :: noitems
    type(nml_item), allocatable :: kept(:)
    integer :: i, j, m
    logical :: replaced
    if (noitems == 0) return
    allocate (kept(nitems + noitems))
    m = 0
    do i = 1, nitems
      replaced = .false.
      do j = 1, noitems
        if (oitems(j)%group == items(i)%group .and. oitems(j)%name == items(i)%name) &
          replaced = .true.
      end do
      if (replaced) cycle
      m = m + 1
      kept(m) = items(i)
    end do
    kept(m + 1:m + noitems) = oitems(1:noitems)
    call move_alloc(kept, items)
    nitems = m + noitems
  end subroutine apply_overrides

  !> A preset first (so that numerics given explicitly override it), then every item
  !> through the table.
  subroutine assign_items(c, items, nitems, err)
    type(case_type), intent(inout) :: c
    type(nml_item), allocatable, intent(in) :: items(:)
    integer, intent(in) :: nitems
    type(error_type), allocatable, intent(out) :: err
    character(len=:), allocatable :: why, text
    integer :: i, k
    do i = 1, nitems
      if (items(i)%group == 'numerics' .and. items(i)%name == 'preset') then
        if (items(i)%quoted) then
          call apply_preset(c, items(i)%value, why)
        else
          why = 'must be a quoted string'
        end if
        if (allocated(why)) then
          call item_error(items(i), why, err)
          return
        end if
      end if
    end do
    do i = 1, nitems
      k = find_input(items(i)%group, items(i)%name)
      if (k == 0) then
        if (find_group(items(i)%group)) then
          call item_error(items(i), 'unknown variable', err)
        else
          call fatal_error(err, items(i)%file//':'//itoa(items(i)%line)// &
                           ': unknown namelist group &'//items(i)%group// &
                           ' (known: '//group_list()//')', rl_input_error)
        end if
        return
      end if
      if (items(i)%group == 'numerics' .and. items(i)%name == 'preset') cycle
      if (items(i)%quoted .neqv. any(inputs(k)%kind == [kind_string, kind_choice])) then
        if (items(i)%quoted) then
          why = 'expected a number or logical, got the string "'//items(i)%value//'"'
        else
          why = "expected a quoted string, e.g. '"//items(i)%value//"'"
        end if
        call item_error(items(i), why, err)
        return
      end if
      text = items(i)%value
      call case_access(c, k, access_set, text, why)
      if (allocated(why)) then
        call item_error(items(i), why, err)
        return
      end if
    end do
  end subroutine assign_items

  !> 'group.name' of the table's list variables (a deck gives each as one list).
  pure function list_variables() result(names)
    character(len=36), allocatable :: names(:)
    integer :: i
    names = [character(len=36) ::(input_key(i), i=1, n_inputs)]
    names = pack(names, inputs%kind == kind_real_list .or. inputs%kind == kind_int_list)
  end function list_variables

  !> Is `group` one of the table's groups?
  pure logical function find_group(group)
    character(len=*), intent(in) :: group
    integer :: i
    find_group = .false.
    do i = 1, n_inputs
      if (inputs(i)%group == group) find_group = .true.
    end do
  end function find_group

  !> The table's groups, comma-separated, in table order.
  pure function group_list() result(t)
    character(len=:), allocatable :: t
    integer :: i
    t = trim(inputs(1)%group)
    do i = 2, n_inputs
      if (inputs(i)%group /= inputs(i - 1)%group) t = t//', '//trim(inputs(i)%group)
    end do
  end function group_list

  !> The viscosity law comes from one source: eta0, theta0 and beta, or the oil's grade or data
  !> sheet (kv40, kv100), which give all three; a deck that sets both is an error at the line
  !> of the first of eta0, theta0 or beta.
  subroutine check_oil_sources(c, items, nitems, err)
    type(case_type), intent(in) :: c
    type(nml_item), intent(in) :: items(:)
    integer, intent(in) :: nitems
    type(error_type), allocatable, intent(out) :: err
    integer :: i
    if (.not. uses_oil_data(c)) return
    do i = 1, nitems
      if (items(i)%group /= 'lubricant') cycle
      select case (items(i)%name)
      case ('eta0', 'theta0', 'beta')
        call item_error(items(i), 'set together with the oil''s '//oil_source()// &
                        ', which gives eta0, theta0 and beta: set one or the other', err)
        return
      end select
    end do

  contains

    function oil_source() result(t)
      character(len=:), allocatable :: t
      t = 'kv40 and kv100'
      if (len(c%grade) > 0) t = 'grade'
    end function oil_source
  end subroutine check_oil_sources

  !> A warning (c%notes) for inputs set for a model that is off: `&bore` variables (and
  !> back_clearance) with `&physics bore = 'round'`, `&ring_pack` variables with `&physics
  !> ring_pack = 'none'` (but those a distorted bore uses), the face-profile variables of
  !> another `&ring profile` than the case's, are not used (the first one is named, at its
  !> line).
  subroutine note_unused(c, items, nitems)
    type(case_type), intent(inout) :: c
    type(nml_item), intent(in) :: items(:)
    integer, intent(in) :: nitems
    character(len=:), allocatable :: uses
    integer :: i
    c%notes = ''
    if (c%bore == 'round') then
      do i = 1, nitems
        ! (back_clearance also sizes the ring pack's groove with groove_volume = 0)
        if (items(i)%group /= 'bore' .and. .not. (items(i)%group == 'ring_pack' .and. &
                                                  items(i)%name == 'back_clearance' .and. &
                                                  .not. (c%ring_pack == 'gas' .and. &
                                                         c%groove_volume == 0.0_dp))) cycle
        c%notes = items(i)%file//':'//itoa(items(i)%line)//': &'//items(i)%group//' '// &
                  items(i)%name//' is set, but &physics bore = ''round'': the bore is round '// &
                  'and its distortion is not used'
        return
      end do
    end if
    do i = 1, nitems
      if (c%ring_pack /= 'none') exit
      if (items(i)%group /= 'ring_pack') cycle
      ! (the gas's temperature and viscosity also set the face leakage of a distorted bore)
      if (c%bore == 'distorted' .and. any(items(i)%name == [character(len=16) :: &
                                                            'gas_temperature', 'gas_viscosity', &
                                                            'back_clearance'])) cycle
      c%notes = items(i)%file//':'//itoa(items(i)%line)//': &ring_pack '//items(i)%name// &
                ' is set, but &physics ring_pack = ''none'': the ring pack is off and '// &
                'its inputs are not used'
      return
    end do
    do i = 1, nitems
      if (items(i)%group /= 'ring') cycle
      select case (items(i)%name)
      case ('crown_height')
        uses = 'edge'
      case ('gauge_length', 'gauge_drop_top', 'gauge_drop_bottom')
        uses = 'gauge'
      case ('profile_file')
        uses = 'table'
      case default
        cycle
      end select
      if (uses == c%profile) cycle
      c%notes = items(i)%file//':'//itoa(items(i)%line)//': &ring '//items(i)%name// &
                ' is set, but &ring profile = '''//c%profile//''': it is used with profile = '''// &
                uses//''' only'
      return
    end do
  end subroutine note_unused

  !> A check of the whole case ('NAME: &group name: why', finish_case) at the line that sets
  !> the variable: 'file:line: &group name: why' (the deck's or its calibration file's line;
  !> unchanged for a variable at its default).
  subroutine at_line(err, name, items, nitems)
    type(error_type), intent(inout) :: err
    character(len=*), intent(in) :: name
    type(nml_item), intent(in) :: items(:)
    integer, intent(in) :: nitems
    character(len=:), allocatable :: rest
    integer :: i, sp, colon
    if (len(err%message) < len(name) + 3) return
    if (err%message(1:len(name) + 3) /= name//': &') return
    rest = err%message(len(name) + 4:)
    sp = index(rest, ' ')
    colon = index(rest, ':')
    if (sp < 2 .or. colon < sp + 2) return
    do i = nitems, 1, -1
      if (items(i)%group == rest(1:sp - 1) .and. items(i)%name == rest(sp + 1:colon - 1)) then
        err%message = items(i)%file//':'//itoa(items(i)%line)//': &'//rest
        return
      end if
    end do
  end subroutine at_line

  !> An input error at an item: 'file:line: &group name: why'.
  subroutine item_error(it, why, err, with_name)
    type(nml_item), intent(in) :: it
    character(len=*), intent(in) :: why
    type(error_type), allocatable, intent(out) :: err
    logical, intent(in), optional :: with_name
    logical :: named
    named = .true.
    if (present(with_name)) named = with_name
    if (named) then
      call fatal_error(err, it%file//':'//itoa(it%line)//': &'//it%group//' '// &
                       it%name//': '//why, rl_input_error)
    else
      call fatal_error(err, it%file//':'//itoa(it%line)//': '//why, rl_input_error)
    end if
  end subroutine item_error

  !> Validate a case and load its gas-pressure trace (shared by the deck reader and the
  !> in-memory entry points). With `load_trace = .false.` only the file's existence is
  !> checked.
  subroutine finish_case(c, err, load_trace)
    type(case_type), intent(inout) :: c
    type(error_type), allocatable, intent(out) :: err
    logical, intent(in), optional :: load_trace
    logical :: exists, load
    ! the face profile's table first: validate_case checks it against the width
    if (allocated(c%profile_x)) deallocate (c%profile_x)
    if (allocated(c%profile_s)) deallocate (c%profile_s)
    if (c%profile == 'table' .and. len(c%profile_file) > 0) then
      call read_profile_csv(c%profile_file, c%profile_x, c%profile_s, err)
      if (allocated(err)) then
        err%message = c%deck_path//': &ring profile_file: '//err%message
        return
      end if
    else
      allocate (c%profile_x(0), c%profile_s(0))
    end if
    call validate_case(c, err)
    if (allocated(err)) return
    if (allocated(c%distortion)) deallocate (c%distortion)
    if (c%bore == 'distorted' .and. len(c%distortion_file) > 0) then
      call read_distortion_csv(c%distortion_file, c%sectors / 2, c%distortion, err)
      if (allocated(err)) then
        err%message = c%deck_path//': &bore distortion_file: '//err%message
        return
      end if
    end if
    load = .true.
    if (present(load_trace)) load = load_trace
    if (allocated(c%gas_psi)) deallocate (c%gas_psi)
    if (allocated(c%gas_p)) deallocate (c%gas_p)
    if (allocated(c%gas_p_trace)) deallocate (c%gas_p_trace)
    if (len(c%pressure_file) == 0) then
      allocate (c%gas_psi(0), c%gas_p(0), c%gas_p_trace(0))
      return
    end if
    if (.not. load) then
      inquire (file=c%pressure_file, exist=exists)
      if (.not. exists) then
        call fatal_error(err, c%deck_path//': &operating pressure_file: '// &
                         c%pressure_file//': pressure file not found', rl_input_error)
      end if
      allocate (c%gas_psi(0), c%gas_p(0), c%gas_p_trace(0))
      return
    end if
    call read_pressure_csv(c%pressure_file, c%gas_psi, c%gas_p_trace, err)
    if (allocated(err)) then
      err%message = c%deck_path//': &operating pressure_file: '//err%message
      return
    end if
    call scale_trace(c, err)
  end subroutine finish_case

  !> The chamber pressure the run uses, `gas_p` = pressure_scale x the trace as read
  !> (`gas_p_trace`): the one place the trace is scaled, after reading it, replacing it or
  !> changing pressure_scale. The scaled trace is held to the limit of a trace as read
  !> (`max_pressure`): above it, an input error naming pressure_scale, and `gas_p` unchanged.
  subroutine scale_trace(c, err)
    type(case_type), intent(inout) :: c
    type(error_type), allocatable, intent(out) :: err
    real(dp) :: peak
    if (.not. allocated(c%gas_p_trace)) return
    if (size(c%gas_p_trace) > 0) then
      peak = maxval(c%gas_p_trace)
      if (.not. (c%pressure_scale * peak <= max_pressure)) then
        call fatal_error(err, c%deck_path//': &operating pressure_scale: '// &
                         real_text(c%pressure_scale)//' times the trace''s highest pressure ('// &
                         itoa(nint(peak / 1e5_dp))//' bar) is '// &
                         itoa(nint(c%pressure_scale * peak / 1e5_dp))//' bar; the chamber '// &
                         'pressure is at most 1000 bar (1e8 Pa, absolute), as in a trace', &
                         rl_input_error)
        return
      end if
    end if
    c%gas_p = c%pressure_scale * c%gas_p_trace
  end subroutine scale_trace
end module ringlube_deck
