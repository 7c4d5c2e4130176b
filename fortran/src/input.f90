!> Reading a case from a namelist deck (SPEC section 9).
!>
!> Every group is optional (a missing group means all its defaults); an unknown group or
!> variable, a malformed value, a variable given twice or a value outside its physical
!> range is an input error naming the file, the group and the variable. Relative paths
!> (`pressure_file`, output `file`) are relative to the deck's own folder.
module ringlube_input
  use ringlube_kinds, only: dp
  use ringlube_error, only: error_type, fatal_error, rl_input_error
  use ringlube_case, only: case_type, validate_case
  use ringlube_namelist, only: nml_item, scan_namelist, lower
  use ringlube_textio, only: read_text_file, itoa
  use ringlube_gas, only: read_pressure_csv
  implicit none
  private
  public :: read_deck, resolve_path, finish_case, apply_preset

contains

  !> Folder part of a path ('' for a bare file name).
  pure function dirname(path) result(d)
    character(len=*), intent(in) :: path
    character(len=:), allocatable :: d
    integer :: i
    i = index(path, '/', back=.true.)
    if (i == 0) then
      d = ''
    else
      d = path(1:i)
    end if
  end function dirname

  !> `path` if absolute, else `base_dir // path`.
  pure function resolve_path(path, base_dir) result(r)
    character(len=*), intent(in) :: path, base_dir
    character(len=:), allocatable :: r
    if (len(path) == 0) then
      r = ''
    else if (path(1:1) == '/') then
      r = path
    else
      r = base_dir // path
    end if
  end function resolve_path

  !> Read, check and complete a case from the deck at `path`. With `load_trace = .false.`
  !> the gas-pressure file is not read (its existence is still checked).
  subroutine read_deck(path, c, err, load_trace)
    character(len=*), intent(in) :: path
    type(case_type), intent(out) :: c
    type(error_type), allocatable, intent(out) :: err
    logical, intent(in), optional :: load_trace
    character(len=:), allocatable :: text, calibration_file
    type(nml_item), allocatable :: items(:)
    integer :: nitems, i, j

    c%deck_path = path
    call read_text_file(path, text, err)
    if (allocated(err)) return
    c%deck_text = text
    call scan_namelist(text, path, items, nitems, err)
    if (allocated(err)) return
    ! &calibration file = '...': that file's values are read as if they were in the deck
    ! (a variable may be set in one of the two, not both)
    j = 0
    do i = 1, nitems
      if (items(i)%group /= 'calibration') cycle
      if (items(i)%name /= 'file') then
        call item_error(items(i), 'unknown variable')
        return
      end if
      if (j > 0) then
        call item_error(items(i), 'given twice (also on line ' // itoa(items(j)%line) // ')')
        return
      end if
      j = i
    end do
    if (j > 0) then
      calibration_file = resolve_path(items(j)%value, dirname(path))
      call include_calibration(calibration_file)
      if (allocated(err)) return
    end if
    ! a preset first, so that numerics given explicitly override it
    do i = 1, nitems
      if (items(i)%group == 'numerics' .and. items(i)%name == 'preset') then
        call apply_preset(c, items(i)%value, err)
        if (allocated(err)) then
          text = err%message   ! err is intent(out) in item_error: copy its message first
          call item_error(items(i), text)
          return
        end if
      end if
    end do
    do i = 1, nitems
      do j = 1, i - 1
        if (items(j)%group == items(i)%group .and. items(j)%name == items(i)%name) then
          call item_error(items(i), 'given twice (also on line ' // itoa(items(j)%line) // ')')
          return
        end if
      end do
      if (items(i)%group == 'numerics' .and. items(i)%name == 'preset') cycle
      if (items(i)%group == 'calibration') cycle
      call assign_item(items(i))
      if (allocated(err)) return
    end do
    call c%set_string_defaults()
    c%pressure_file = resolve_path(c%pressure_file, dirname(path))
    c%output_file = resolve_path(c%output_file, dirname(path))
    call finish_case(c, err, load_trace)

  contains

    !> Read the calibration file and add its items (named by their own file) to the deck's.
    subroutine include_calibration(cpath)
      character(len=*), intent(in) :: cpath
      character(len=:), allocatable :: ctext
      type(nml_item), allocatable :: citems(:), all(:)
      integer :: ncitems, k, m
      call read_text_file(cpath, ctext, err)
      if (allocated(err)) then
        err%message = path // ': &calibration file: ' // err%message
        return
      end if
      call scan_namelist(ctext, cpath, citems, ncitems, err)
      if (allocated(err)) return
      do k = 1, ncitems
        if (citems(k)%group == 'calibration' .or. citems(k)%group == 'output' .or. &
          citems(k)%group == 'numerics') then
          call fatal_error(err, cpath // ':' // itoa(citems(k)%line) // ': &' // citems(k)%group &
            // ' cannot be set in a calibration file', rl_input_error)
          return
        end if
        do m = 1, nitems
          if (items(m)%group == citems(k)%group .and. items(m)%name == citems(k)%name) then
            call item_error(items(m), 'also set by the calibration file ' // cpath // &
              ' (set it in one place only)')
            return
          end if
        end do
      end do
      c%deck_text = c%deck_text // new_line('a') // '! --- calibration file ' // cpath // &
        ' ---' // new_line('a') // ctext
      allocate(all(nitems + ncitems))
      all(1:ncitems) = citems(1:ncitems)
      all(ncitems+1:) = items(1:nitems)
      call move_alloc(all, items)
      nitems = nitems + ncitems
    end subroutine include_calibration

    subroutine item_error(it, why)
      type(nml_item), intent(in) :: it
      character(len=*), intent(in) :: why
      call fatal_error(err, it%file // ':' // itoa(it%line) // ': &' // it%group // ' ' // &
        it%name // ': ' // why, rl_input_error)
    end subroutine item_error

    subroutine assign_item(it)
      type(nml_item), intent(in) :: it
      select case (it%group)
      case ('engine')
        select case (it%name)
        case ('crank_radius'); call get_real(it, c%crank_radius)
        case ('conrod_length'); call get_real(it, c%conrod_length)
        case ('bore_radius'); call get_real(it, c%bore_radius)
        case default; call unknown(it)
        end select
      case ('operating')
        select case (it%name)
        case ('speed_rpm'); call get_real(it, c%speed_rpm)
        case ('liner_temperature'); call get_real(it, c%liner_temperature)
        case ('pressure_file'); call get_string(it, c%pressure_file)
        case ('crankcase_pressure'); call get_real(it, c%crankcase_pressure)
        case ('cavitation_pressure'); call get_real(it, c%cavitation_pressure)
        case ('pressure_scale'); call get_real(it, c%pressure_scale)
        case default; call unknown(it)
        end select
      case ('ring')
        select case (it%name)
        case ('width'); call get_real(it, c%width)
        case ('crown_height'); call get_real(it, c%crown_height)
        case ('crown_offset'); call get_real(it, c%crown_offset)
        case ('tension'); call get_real(it, c%tension)
        case ('tension_unit'); call get_string(it, c%tension_unit)
        case ('radial_depth'); call get_real(it, c%radial_depth)
        case ('density'); call get_real(it, c%density)
        case default; call unknown(it)
        end select
      case ('lubricant')
        select case (it%name)
        case ('eta0'); call get_real(it, c%eta0)
        case ('theta0'); call get_real(it, c%theta0)
        case ('beta'); call get_real(it, c%beta)
        case ('alpha'); call get_real(it, c%alpha)
        case default; call unknown(it)
        end select
      case ('surface')
        select case (it%name)
        case ('rq_liner'); call get_real(it, c%rq_liner)
        case ('rq_ring'); call get_real(it, c%rq_ring)
        case ('zeta_kappa_sigma'); call get_real(it, c%zeta_kappa_sigma)
        case ('sigma_over_kappa'); call get_real(it, c%sigma_over_kappa)
        case ('tau0'); call get_real(it, c%tau0)
        case ('boundary_coefficient'); call get_real(it, c%boundary_coefficient)
        case ('e_ring'); call get_real(it, c%e_ring)
        case ('nu_ring'); call get_real(it, c%nu_ring)
        case ('e_liner'); call get_real(it, c%e_liner)
        case ('nu_liner'); call get_real(it, c%nu_liner)
        case default; call unknown(it)
        end select
      case ('physics')
        select case (it%name)
        case ('roelands'); call get_logical(it, c%roelands)
        case ('squeeze'); call get_logical(it, c%squeeze)
        case ('asperity_contact'); call get_logical(it, c%asperity_contact)
        case ('gt_functions'); call get_string(it, c%gt_functions)
        case ('contact_area'); call get_string(it, c%contact_area)
        case ('outlet'); call get_string(it, c%outlet)
        case default; call unknown(it)
        end select
      case ('numerics')
        select case (it%name)
        case ('preset'); continue
        case ('nodes'); call get_int(it, c%nodes)
        case ('dpsi_deg'); call get_real(it, c%dpsi_deg)
        case ('pressure_tol'); call get_real(it, c%pressure_tol)
        case ('load_tol'); call get_real(it, c%load_tol)
        case ('h0_update'); call get_string(it, c%h0_update)
        case ('damping'); call get_real(it, c%damping)
        case ('max_cycles'); call get_int(it, c%max_cycles)
        case ('cycle_tol'); call get_real(it, c%cycle_tol)
        case ('max_load_iterations'); call get_int(it, c%max_load_iterations)
        case ('max_pressure_iterations'); call get_int(it, c%max_pressure_iterations)
        case ('h0_floor'); call get_real(it, c%h0_floor)
        case ('h0_ceiling'); call get_real(it, c%h0_ceiling)
        case ('h0_initial'); call get_real(it, c%h0_initial)
        case ('warmup_deg'); call get_real(it, c%warmup_deg)
        case default; call unknown(it)
        end select
      case ('output')
        select case (it%name)
        case ('file'); call get_string(it, c%output_file)
        case default; call unknown(it)
        end select
      case default
        call fatal_error(err, it%file // ':' // itoa(it%line) // ': unknown namelist group &' // &
          it%group // ' (known: engine, operating, ring, lubricant, surface, physics, ' // &
          'numerics, output, calibration)', rl_input_error)
      end select
    end subroutine assign_item

    subroutine unknown(it)
      type(nml_item), intent(in) :: it
      call item_error(it, 'unknown variable')
    end subroutine unknown

    subroutine get_real(it, v)
      type(nml_item), intent(in) :: it
      real(dp), intent(inout) :: v
      integer :: ios
      real(dp) :: tmp
      if (it%quoted .or. verify(it%value, '0123456789+-.eEdD') /= 0) then
        call item_error(it, 'malformed number "' // it%value // '"')
        return
      end if
      read(it%value, *, iostat=ios) tmp
      if (ios /= 0) then
        call item_error(it, 'malformed number "' // it%value // '"')
        return
      end if
      v = tmp
    end subroutine get_real

    subroutine get_int(it, v)
      type(nml_item), intent(in) :: it
      integer, intent(inout) :: v
      integer :: ios, tmp
      if (it%quoted .or. verify(it%value, '0123456789+-') /= 0) then
        call item_error(it, 'malformed integer "' // it%value // '"')
        return
      end if
      read(it%value, *, iostat=ios) tmp
      if (ios /= 0) then
        call item_error(it, 'malformed integer "' // it%value // '"')
        return
      end if
      v = tmp
    end subroutine get_int

    subroutine get_logical(it, v)
      type(nml_item), intent(in) :: it
      logical, intent(inout) :: v
      select case (lower(it%value))
      case ('.true.', '.t.', 't', 'true')
        v = .true.
      case ('.false.', '.f.', 'f', 'false')
        v = .false.
      case default
        call item_error(it, 'malformed logical "' // it%value // '" (use .true. or .false.)')
      end select
    end subroutine get_logical

    subroutine get_string(it, v)
      type(nml_item), intent(in) :: it
      character(len=:), allocatable, intent(inout) :: v
      v = it%value
    end subroutine get_string
  end subroutine read_deck

  !> Numerical settings of a named preset (chosen from the measured speed/accuracy front,
  !> docs/performance.md): nodes, crank step, pressure and load tolerances.
  subroutine apply_preset(c, name, err)
    type(case_type), intent(inout) :: c
    character(len=*), intent(in) :: name
    type(error_type), allocatable, intent(out) :: err
    select case (name)
    case ('fast')
      c%nodes = 31
      c%dpsi_deg = 2.0_dp
      c%pressure_tol = 1e-4_dp
      c%load_tol = 3e-3_dp
    case ('default')
      c%nodes = 51
      c%dpsi_deg = 1.0_dp
      c%pressure_tol = 1e-5_dp
      c%load_tol = 1e-3_dp
    case ('accurate')
      c%nodes = 201
      c%dpsi_deg = 0.25_dp
      c%pressure_tol = 1e-6_dp
      c%load_tol = 1e-4_dp
    case default
      call fatal_error(err, "unknown preset '" // name // "' (use 'fast', 'default' or 'accurate')", &
        rl_input_error)
    end select
  end subroutine apply_preset

  !> Validate a case and load its gas-pressure trace (shared by the deck reader and the
  !> Python entry points).
  subroutine finish_case(c, err, load_trace)
    type(case_type), intent(inout) :: c
    type(error_type), allocatable, intent(out) :: err
    logical, intent(in), optional :: load_trace
    logical :: exists
    call c%set_string_defaults()
    call validate_case(c, err)
    if (allocated(err)) return
    if (present(load_trace)) then
      if (.not. load_trace .and. len(c%pressure_file) > 0) then
        inquire(file=c%pressure_file, exist=exists)
        if (.not. exists) call fatal_error(err, c%deck_path // ': &operating pressure_file: ' // &
          c%pressure_file // ': pressure file not found', rl_input_error)
        allocate(c%gas_psi(0), c%gas_p(0))
        return
      end if
    end if
    if (len(c%pressure_file) > 0) then
      call read_pressure_csv(c%pressure_file, c%gas_psi, c%gas_p, err)
      if (allocated(err)) then
        err%message = c%deck_path // ': &operating pressure_file: ' // err%message
        return
      end if
      c%gas_p = c%pressure_scale * c%gas_p
    else
      allocate(c%gas_psi(0), c%gas_p(0))
    end if
  end subroutine finish_case
end module ringlube_input
