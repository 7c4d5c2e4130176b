!> One ringlube case: every input of the table in ringlube_inputs, stored by name.
!>
!> The defaults, plausible ranges, choices and units are those of the table; this module
!> holds the storage (`case_type`), its one binding to the table (`case_access`), the
!> checks that relate two variables, and small derived quantities.
module ringlube_case
  use ringlube_kinds, only: dp, pi
  use ringlube_error, only: error_type, fatal_error, rl_input_error
  use ringlube_inputs, only: inputs, n_inputs, find_input, input_key, presets, n_presets, &
                             preset_names, kind_choice, kind_int, max_list
  use ringlube_textio, only: itoa
  use ringlube_namelist, only: lower
  use ringlube_viscosity, only: roelands_law_at, roelands_eta, roelands_through
  use ringlube_oil, only: grade_viscosities, theta40, theta100
  use ringlube_profile, only: gauge_profile, gauge_area, table_profile, table_area, &
                              check_profile_table
  use, intrinsic :: ieee_arithmetic, only: ieee_is_finite
  implicit none
  private
  public :: case_type, default_case, apply_preset, case_access, validate_case, parse_real, &
         real_text, choice_list, composite_sigma, reduced_modulus, elastic_pressure, ring_profile, &
            ring_mass, steps_per_cycle, face_profile, uses_oil_data, liner_temperature_at, &
            uniform_liner

  !> Most crank steps per cycle (0.01 deg): bounds the memory of a run.
  integer, parameter, public :: max_steps_per_cycle = 72000

  !> All inputs of one run. Names follow the namelist variables; defaults, ranges, units
  !> and descriptions live in the table of ringlube_inputs (start from `default_case()`).
  type :: case_type
    ! &engine
    real(dp) :: crank_radius = 0.0_dp, conrod_length = 0.0_dp, bore_radius = 0.0_dp
    integer :: cylinders = 0
    ! &operating
    real(dp) :: speed_rpm = 0.0_dp, liner_temperature = 0.0_dp, crankcase_pressure = 0.0_dp, &
                cavitation_pressure = 0.0_dp, pressure_scale = 0.0_dp
    real(dp) :: liner_temperature_top = 0.0_dp, liner_temperature_bottom = 0.0_dp
    !> Gas-pressure CSV as resolved against the deck folder; empty: chamber at
    !> crankcase pressure all cycle (no compression, no combustion).
    character(len=:), allocatable :: pressure_file
    ! &ring
    real(dp) :: width = 0.0_dp, crown_height = 0.0_dp, crown_offset = 0.0_dp, tension = 0.0_dp
    character(len=:), allocatable :: tension_unit
    real(dp) :: radial_depth = 0.0_dp, density = 0.0_dp, lower_ring_distance = 0.0_dp
    character(len=:), allocatable :: profile
    real(dp) :: gauge_length = 0.0_dp, gauge_drop_top = 0.0_dp, gauge_drop_bottom = 0.0_dp
    !> face-profile CSV as resolved against the deck folder (profile = 'table')
    character(len=:), allocatable :: profile_file
    ! &lubricant
    real(dp) :: eta0 = 0.0_dp, theta0 = 0.0_dp, beta = 0.0_dp, alpha = 0.0_dp, supply_film = 0.0_dp
    real(dp) :: oil_density = 0.0_dp, kv40 = 0.0_dp, kv100 = 0.0_dp
    !> SAE J300 grade ('' none)
    character(len=:), allocatable :: grade
    ! &surface
    real(dp) :: rq_liner = 0.0_dp, rq_ring = 0.0_dp, zeta_kappa_sigma = 0.0_dp, &
         sigma_over_kappa = 0.0_dp, tau0 = 0.0_dp, boundary_coefficient = 0.0_dp, e_ring = 0.0_dp, &
                nu_ring = 0.0_dp, e_liner = 0.0_dp, nu_liner = 0.0_dp
    ! &physics
    logical :: roelands = .false., squeeze = .false., asperity_contact = .false.
    character(len=:), allocatable :: gt_functions, contact_area, outlet, cavitation, &
                                     cavity_pressure, inlet, ring_pack, bore
    ! &bore
    integer, allocatable :: bore_order(:)
    real(dp), allocatable :: bore_amplitude(:), bore_phase(:)
    !> the distortion CSV as resolved against the deck folder (empty: the lists)
    character(len=:), allocatable :: distortion_file
    integer :: sectors = 0
    ! &ring_pack
    real(dp) :: gas_temperature = 0.0_dp, gamma = 0.0_dp, gas_viscosity = 0.0_dp, &
                discharge_coefficient = 0.0_dp, top_gap_area = 0.0_dp, second_gap_area = 0.0_dp, &
                groove_clearance = 0.0_dp, groove_volume = 0.0_dp, land_volume = 0.0_dp, &
                back_clearance = 0.0_dp
    ! &numerics
    character(len=:), allocatable :: preset
    integer :: nodes = 0
    real(dp) :: dpsi_deg = 0.0_dp, pressure_tol = 0.0_dp, load_tol = 0.0_dp
    character(len=:), allocatable :: time_scheme, film_time_scheme, film_edge_cells, h0_update
    character(len=:), allocatable :: first_restart
    real(dp) :: damping = 0.0_dp
    integer :: max_cycles = 0
    real(dp) :: cycle_tol = 0.0_dp
    integer :: max_load_iterations = 0, max_pressure_iterations = 0
    real(dp) :: h0_floor = 0.0_dp, h0_ceiling = 0.0_dp, h0_initial = 0.0_dp, warmup_deg = 0.0_dp
    integer :: threads = 1, liner_window = 0
    logical :: accelerate = .false., pilot_cycle = .false., bdc_start = .false.
    ! &output, &calibration
    character(len=:), allocatable :: output_file, calibration_file
    ! not namelist variables
    real(dp), allocatable :: gas_psi(:)        !< deg, 0..720, increasing
    real(dp), allocatable :: gas_p(:)          !< Pa abs, pressure_scale x gas_p_trace
    real(dp), allocatable :: gas_p_trace(:)    !< Pa abs, the trace as read (scale_trace)
    !> the face profile of profile = 'table' as read: position from the top edge and drop [m]
    real(dp), allocatable :: profile_x(:), profile_s(:)
    character(len=:), allocatable :: deck_path  !< where the case came from (in messages)
    character(len=:), allocatable :: deck_text  !< the deck's text (and included files')
    !> the bore's distortion as read from distortion_file: rows (z [m], order, amplitude [m],
    !> phase [rad]), (row, column)
    real(dp), allocatable :: distortion(:, :)
    !> a warning about the case ('' none): inputs set for a model that is off
    character(len=:), allocatable :: notes
  end type case_type

  !> Modes of `case_access`.
  integer, parameter, public :: access_set = 1, access_get = 2, access_check = 3

contains

  !> A case with every variable at its table default (the numerics a preset sets from
  !> preset 'default').
  function default_case() result(c)
    type(case_type) :: c
    character(len=:), allocatable :: why, text
    integer :: i
    do i = 1, n_inputs
      if (inputs(i)%default == '(preset)') cycle
      text = trim(inputs(i)%default)
      call case_access(c, i, access_set, text, why)
      if (allocated(why)) error stop 'ringlube_inputs: bad default of '//input_key(i)
    end do
    call apply_preset(c, 'default', why)
    if (allocated(why)) error stop 'ringlube_inputs: bad preset default'
    c%deck_path = '<memory>'
    c%notes = ''
    c%deck_text = ''
    allocate (c%gas_psi(0), c%gas_p(0), c%gas_p_trace(0), c%profile_x(0), c%profile_s(0))
  end function default_case

  !> Set the numerics of a named preset; `why` is allocated if the name is unknown.
  subroutine apply_preset(c, name, why)
    type(case_type), intent(inout) :: c
    character(len=*), intent(in) :: name
    character(len=:), allocatable, intent(out) :: why
    character(len=:), allocatable :: text
    integer :: i, found
    found = 0
    do i = 1, n_presets
      if (presets(i)%preset /= name) cycle
      found = found + 1
      text = trim(presets(i)%value)
      call case_access(c, find_input('numerics', trim(presets(i)%name)), access_set, text, why)
      if (allocated(why)) return
    end do
    if (found == 0) then
      why = "unknown preset '"//name//"' (use "//choice_list(preset_names())//')'
      return
    end if
    c%preset = name
  end subroutine apply_preset

  !> Read, write or check table row `i` of a case: the one binding of the table's names to
  !> the components of case_type.
  !>
  !> `access_set`: parse `text` (deck syntax, unquoted value) into the variable and check it
  !> against its range or choices; `access_get`: the value as deck text in `text`;
  !> `access_check`: check the current value. On a bad value `why` says why (without file,
  !> group or variable: the caller adds them).
  subroutine case_access(c, i, mode, text, why)
    type(case_type), intent(inout) :: c
    integer, intent(in) :: i, mode
    character(len=:), allocatable, intent(inout) :: text
    character(len=:), allocatable, intent(out) :: why
    select case (input_key(i))
    case ('engine.crank_radius'); call r(c%crank_radius)
    case ('engine.conrod_length'); call r(c%conrod_length)
    case ('engine.bore_radius'); call r(c%bore_radius)
    case ('engine.cylinders'); call n(c%cylinders)
    case ('operating.speed_rpm'); call r(c%speed_rpm)
    case ('operating.liner_temperature'); call r(c%liner_temperature)
    case ('operating.liner_temperature_top'); call r(c%liner_temperature_top)
    case ('operating.liner_temperature_bottom'); call r(c%liner_temperature_bottom)
    case ('operating.pressure_file'); call s(c%pressure_file)
    case ('operating.crankcase_pressure'); call r(c%crankcase_pressure)
    case ('operating.cavitation_pressure'); call r(c%cavitation_pressure)
    case ('operating.pressure_scale'); call r(c%pressure_scale)
    case ('ring.width'); call r(c%width)
    case ('ring.crown_height'); call r(c%crown_height)
    case ('ring.crown_offset'); call r(c%crown_offset)
    case ('ring.profile'); call s(c%profile)
    case ('ring.gauge_length'); call r(c%gauge_length)
    case ('ring.gauge_drop_top'); call r(c%gauge_drop_top)
    case ('ring.gauge_drop_bottom'); call r(c%gauge_drop_bottom)
    case ('ring.profile_file'); call s(c%profile_file)
    case ('ring.tension'); call r(c%tension)
    case ('ring.tension_unit'); call s(c%tension_unit)
    case ('ring.radial_depth'); call r(c%radial_depth)
    case ('ring.density'); call r(c%density)
    case ('ring.lower_ring_distance'); call r(c%lower_ring_distance)
    case ('lubricant.eta0'); call r(c%eta0)
    case ('lubricant.theta0'); call r(c%theta0)
    case ('lubricant.beta'); call r(c%beta)
    case ('lubricant.alpha'); call r(c%alpha)
    case ('lubricant.supply_film'); call r(c%supply_film)
    case ('lubricant.oil_density'); call r(c%oil_density)
    case ('lubricant.kv40'); call r(c%kv40)
    case ('lubricant.kv100'); call r(c%kv100)
    case ('lubricant.grade'); call s(c%grade)
    case ('surface.rq_liner'); call r(c%rq_liner)
    case ('surface.rq_ring'); call r(c%rq_ring)
    case ('surface.zeta_kappa_sigma'); call r(c%zeta_kappa_sigma)
    case ('surface.sigma_over_kappa'); call r(c%sigma_over_kappa)
    case ('surface.tau0'); call r(c%tau0)
    case ('surface.boundary_coefficient'); call r(c%boundary_coefficient)
    case ('surface.e_ring'); call r(c%e_ring)
    case ('surface.nu_ring'); call r(c%nu_ring)
    case ('surface.e_liner'); call r(c%e_liner)
    case ('surface.nu_liner'); call r(c%nu_liner)
    case ('physics.roelands'); call l(c%roelands)
    case ('physics.squeeze'); call l(c%squeeze)
    case ('physics.asperity_contact'); call l(c%asperity_contact)
    case ('physics.gt_functions'); call s(c%gt_functions)
    case ('physics.contact_area'); call s(c%contact_area)
    case ('physics.outlet'); call s(c%outlet)
    case ('physics.cavitation'); call s(c%cavitation)
    case ('physics.cavity_pressure'); call s(c%cavity_pressure)
    case ('physics.inlet'); call s(c%inlet)
    case ('physics.ring_pack'); call s(c%ring_pack)
    case ('physics.bore'); call s(c%bore)
    case ('bore.order'); call nlist(c%bore_order)
    case ('bore.amplitude'); call rlist(c%bore_amplitude)
    case ('bore.phase'); call rlist(c%bore_phase)
    case ('bore.distortion_file'); call s(c%distortion_file)
    case ('bore.sectors'); call n(c%sectors)
    case ('ring_pack.gas_temperature'); call r(c%gas_temperature)
    case ('ring_pack.gamma'); call r(c%gamma)
    case ('ring_pack.gas_viscosity'); call r(c%gas_viscosity)
    case ('ring_pack.discharge_coefficient'); call r(c%discharge_coefficient)
    case ('ring_pack.top_gap_area'); call r(c%top_gap_area)
    case ('ring_pack.second_gap_area'); call r(c%second_gap_area)
    case ('ring_pack.groove_clearance'); call r(c%groove_clearance)
    case ('ring_pack.groove_volume'); call r(c%groove_volume)
    case ('ring_pack.land_volume'); call r(c%land_volume)
    case ('ring_pack.back_clearance'); call r(c%back_clearance)
    case ('numerics.preset'); call s(c%preset)
    case ('numerics.nodes'); call n(c%nodes)
    case ('numerics.dpsi_deg'); call r(c%dpsi_deg)
    case ('numerics.pressure_tol'); call r(c%pressure_tol)
    case ('numerics.load_tol'); call r(c%load_tol)
    case ('numerics.time_scheme'); call s(c%time_scheme)
    case ('numerics.film_time_scheme'); call s(c%film_time_scheme)
    case ('numerics.film_edge_cells'); call s(c%film_edge_cells)
    case ('numerics.h0_update'); call s(c%h0_update)
    case ('numerics.damping'); call r(c%damping)
    case ('numerics.max_cycles'); call n(c%max_cycles)
    case ('numerics.cycle_tol'); call r(c%cycle_tol)
    case ('numerics.max_load_iterations'); call n(c%max_load_iterations)
    case ('numerics.max_pressure_iterations'); call n(c%max_pressure_iterations)
    case ('numerics.h0_floor'); call r(c%h0_floor)
    case ('numerics.h0_ceiling'); call r(c%h0_ceiling)
    case ('numerics.h0_initial'); call r(c%h0_initial)
    case ('numerics.warmup_deg'); call r(c%warmup_deg)
    case ('numerics.accelerate'); call l(c%accelerate)
    case ('numerics.pilot_cycle'); call l(c%pilot_cycle)
    case ('numerics.first_restart'); call s(c%first_restart)
    case ('numerics.bdc_start'); call l(c%bdc_start)
    case ('numerics.liner_window'); call n(c%liner_window)
    case ('numerics.threads'); call n(c%threads)
    case ('output.file'); call s(c%output_file)
    case ('calibration.file'); call s(c%calibration_file)
    case default
      why = 'no storage for '//input_key(i)//' (ringlube_case: case_access)'
    end select

  contains

    subroutine r(v)
      real(dp), intent(inout) :: v
      real(dp) :: tmp
      logical :: ok
      select case (mode)
      case (access_set)
        call parse_real(text, tmp, ok)
        if (.not. ok) then
          select case (lower(text))
          case ('nan', '+nan', '-nan', 'inf', '+inf', '-inf', 'infinity', '+infinity', '-infinity')
            why = 'must be a finite number, got "'//text//'"'
          case default
            why = 'malformed number "'//text//'"'
          end select
          return
        end if
        call check_range(tmp)
        if (.not. allocated(why)) v = tmp
      case (access_get)
        text = real_text(v)
      case (access_check)
        call check_range(v)
      end select
    end subroutine r

    subroutine n(v)
      integer, intent(inout) :: v
      integer :: tmp, ios
      select case (mode)
      case (access_set)
        if (len(text) == 0 .or. verify(text, '0123456789+-') /= 0) then
          why = 'malformed integer "'//text//'"'
          return
        end if
        read (text, *, iostat=ios) tmp
        if (ios /= 0) then
          why = 'malformed integer "'//text//'"'
          return
        end if
        call check_range(real(tmp, dp))
        if (.not. allocated(why)) v = tmp
      case (access_get)
        text = itoa(v)
      case (access_check)
        call check_range(real(v, dp))
      end select
    end subroutine n

    subroutine l(v)
      logical, intent(inout) :: v
      select case (mode)
      case (access_set)
        select case (lower(text))
        case ('.true.', '.t.', 't', 'true')
          v = .true.
        case ('.false.', '.f.', 'f', 'false')
          v = .false.
        case default
          why = 'malformed logical "'//text//'" (use .true. or .false.)'
        end select
      case (access_get)
        if (v) then
          text = '.true.'
        else
          text = '.false.'
        end if
      end select
    end subroutine l

    !> A list of reals: deck text "v1, v2, ..." (commas or blanks between values; '' none).
    subroutine rlist(v)
      real(dp), allocatable, intent(inout) :: v(:)
      real(dp), allocatable :: tmp(:)
      character(len=:), allocatable :: words(:)
      integer :: j
      select case (mode)
      case (access_set)
        call split_list(text, words, why)
        if (allocated(why)) return
        allocate (tmp(size(words)))
        do j = 1, size(words)
          text = trim(words(j))
          call r(tmp(j))
          if (allocated(why)) then
            why = 'value '//itoa(j)//': '//why
            return
          end if
        end do
        call move_alloc(tmp, v)
      case (access_get)
        text = ''
        if (.not. allocated(v)) return
        do j = 1, size(v)
          if (j > 1) text = text//', '
          text = text//real_text(v(j))
        end do
      case (access_check)
        if (.not. allocated(v)) then
          why = 'not set'
          return
        end if
        do j = 1, size(v)
          call check_range(v(j))
          if (allocated(why)) then
            why = 'value '//itoa(j)//': '//why
            return
          end if
        end do
      end select
    end subroutine rlist

    !> A list of integers (as rlist).
    subroutine nlist(v)
      integer, allocatable, intent(inout) :: v(:)
      integer, allocatable :: tmp(:)
      character(len=:), allocatable :: words(:)
      integer :: j
      select case (mode)
      case (access_set)
        call split_list(text, words, why)
        if (allocated(why)) return
        allocate (tmp(size(words)))
        do j = 1, size(words)
          text = trim(words(j))
          call n(tmp(j))
          if (allocated(why)) then
            why = 'value '//itoa(j)//': '//why
            return
          end if
        end do
        call move_alloc(tmp, v)
      case (access_get)
        text = ''
        if (.not. allocated(v)) return
        do j = 1, size(v)
          if (j > 1) text = text//', '
          text = text//itoa(v(j))
        end do
      case (access_check)
        if (.not. allocated(v)) then
          why = 'not set'
          return
        end if
        do j = 1, size(v)
          call check_range(real(v(j), dp))
          if (allocated(why)) then
            why = 'value '//itoa(j)//': '//why
            return
          end if
        end do
      end select
    end subroutine nlist

    subroutine s(v)
      character(len=:), allocatable, intent(inout) :: v
      select case (mode)
      case (access_set)
        call check_choice(text)
        if (.not. allocated(why)) v = text
      case (access_get)
        text = v
      case (access_check)
        if (.not. allocated(v)) then
          why = 'not set'
        else
          call check_choice(v)
        end if
      end select
    end subroutine s

    subroutine check_choice(v)
      character(len=*), intent(in) :: v
      if (inputs(i)%kind /= kind_choice) return
      if (index('|'//trim(inputs(i)%choices)//'|', '|'//v//'|') == 0 .or. len(v) == 0 &
          .or. index(v, '|') > 0) then
        why = 'must be '//choice_list(inputs(i)%choices)//", got '"//v//"'"
      end if
    end subroutine check_choice

    subroutine check_range(v)
      real(dp), intent(in) :: v
      if (.not. (v >= inputs(i)%lower .and. v <= inputs(i)%upper)) then
        if (inputs(i)%kind == kind_int) then
          why = 'must be in ['//itoa(nint(inputs(i)%lower))//', '// &
                itoa(nint(inputs(i)%upper))//'], got '//itoa(nint(v))
        else
          why = 'must be in ['//real_text(inputs(i)%lower)//', '// &
                real_text(inputs(i)%upper)//']'//unit_text()//', got '//real_text(v)
        end if
      end if
    end subroutine check_range

    function unit_text() result(u)
      character(len=:), allocatable :: u
      select case (trim(inputs(i)%unit))
      case ('', '1')
        u = ''
      case ('(unit)')
        u = ' '//c%tension_unit
      case default
        u = ' '//trim(inputs(i)%unit)
      end select
    end function unit_text
  end subroutine case_access

  !> The values of a list's deck text "v1, v2, ..." (separated by commas or blanks; '' is
  !> the empty list); `why` for an empty value between commas or more than max_list values.
  pure subroutine split_list(text, words, why)
    character(len=*), intent(in) :: text
    character(len=:), allocatable, intent(out) :: words(:)
    character(len=:), allocatable, intent(out) :: why
    character(len=len(text)) :: buf(max_list)
    integer :: i, start, nw
    logical :: comma
    nw = 0
    i = 1
    comma = .false.
    do
      do while (i <= len(text))
        if (text(i:i) /= ' ' .and. text(i:i) /= achar(9)) exit
        i = i + 1
      end do
      if (i > len(text)) exit
      if (text(i:i) == ',') then
        if (comma .or. nw == 0) then
          why = 'an empty value in the list "'//text//'"'
          return
        end if
        comma = .true.
        i = i + 1
        cycle
      end if
      start = i
      do while (i <= len(text))
        if (text(i:i) == ' ' .or. text(i:i) == ',' .or. text(i:i) == achar(9)) exit
        i = i + 1
      end do
      nw = nw + 1
      if (nw > max_list) then
        why = 'more than '//itoa(max_list)//' values'
        return
      end if
      buf(nw) = text(start:i - 1)
      comma = .false.
    end do
    if (comma) then
      why = 'an empty value at the end of the list "'//text//'"'
      return
    end if
    allocate (character(len=max(len(text), 1)) :: words(nw))
    words = buf(1:nw)
  end subroutine split_list

  !> A number in deck syntax (Fortran or C exponents; no words such as nan or inf).
  subroutine parse_real(text, v, ok)
    character(len=*), intent(in) :: text
    real(dp), intent(out) :: v
    logical, intent(out) :: ok
    integer :: ios
    v = 0.0_dp
    ok = len(text) > 0
    if (.not. ok) return
    ok = verify(text, '0123456789+-.eEdD') == 0 .and. scan(text, '0123456789') > 0
    if (.not. ok) return
    read (text, *, iostat=ios) v
    ok = ios == 0
    if (ok) ok = ieee_is_finite(v)
  end subroutine parse_real

  !> Shortest scientific text that reads back as the same double.
  function real_text(v) result(t)
    real(dp), intent(in) :: v
    character(len=:), allocatable :: t
    character(len=40) :: buf
    real(dp) :: back
    integer :: d, ios
    if (.not. ieee_is_finite(v)) then
      write (buf, *) v
      t = trim(adjustl(buf))
      return
    end if
    do d = 1, 17   ! (es0.0 would print every digit)
      write (buf, '(es0.'//itoa(d)//')') v
      read (buf, *, iostat=ios) back
      if (ios == 0 .and. back == v) exit
    end do
    t = trim(adjustl(buf))
  end function real_text

  !> "'a', 'b' or 'c'" from "a|b|c".
  pure function choice_list(choices) result(t)
    character(len=*), intent(in) :: choices
    character(len=:), allocatable :: t, rest
    integer :: k
    t = ''
    rest = trim(choices)
    do
      k = index(rest, '|')
      if (k == 0) exit
      if (len(t) > 0) t = t//', '
      t = t//"'"//rest(1:k - 1)//"'"
      rest = rest(k + 1:)
    end do
    if (len(t) > 0) t = t//' or '
    t = t//"'"//rest//"'"
  end function choice_list

  !> Composite roughness sigma = sqrt(Rq_liner^2 + Rq_ring^2) [m].
  pure real(dp) function composite_sigma(c)
    type(case_type), intent(in) :: c
    composite_sigma = sqrt(c%rq_liner**2 + c%rq_ring**2)
  end function composite_sigma

  !> Reduced modulus E' = 2 / ((1-nu1^2)/E1 + (1-nu2^2)/E2) [Pa].
  pure real(dp) function reduced_modulus(c)
    type(case_type), intent(in) :: c
    reduced_modulus = 2.0_dp / ((1.0_dp - c%nu_ring**2) / c%e_ring &
                                + (1.0_dp - c%nu_liner**2) / c%e_liner)
  end function reduced_modulus

  !> Elastic pressure of the ring on the liner p_e [Pa].
  pure real(dp) function elastic_pressure(c)
    type(case_type), intent(in) :: c
    if (c%tension_unit == 'N/m') then
      elastic_pressure = c%tension / c%width
    else
      elastic_pressure = c%tension / (c%width * c%bore_radius)
    end if
  end function elastic_pressure

  !> Crown profile S(x) = c (x + x_s)^2 / (b/2)^2 [m].
  elemental real(dp) function ring_profile(x, width, crown_height, crown_offset)
    real(dp), intent(in) :: x, width, crown_height, crown_offset
    ring_profile = crown_height * (x + crown_offset)**2 / (0.5_dp * width)**2
  end function ring_profile

  !> The face profile S [m] of the case (`profile`) at the nodes x(1:n) of the film's grid
  !> (x(i) = -b/2 + (i - 1) dx, x(n) = b/2) in `s` and at their midpoints in `smid`.
  !> A table is evaluated at the same points from the top edge, (i - 1) dx, b and their
  !> midpoints (a table holding them gives its values there exactly).
  pure subroutine face_profile(c, x, s, smid)
    type(case_type), intent(in) :: c
    real(dp), intent(in) :: x(:)
    real(dp), intent(out) :: s(:), smid(:)
    real(dp) :: xi(size(x)), s_min, area
    integer :: i, n
    n = size(x)
    select case (c%profile)
    case ('gauge')
      s = gauge_profile(x, c%crown_offset, c%gauge_length, c%gauge_drop_top, c%gauge_drop_bottom)
      smid = gauge_profile(0.5_dp * (x(1:n - 1) + x(2:n)), c%crown_offset, c%gauge_length, &
                           c%gauge_drop_top, c%gauge_drop_bottom)
    case ('table')
      do i = 1, n
        xi(i) = (i - 1) * (c%width / (n - 1))
      end do
      xi(n) = c%width
      call table_area(c%width, c%profile_x, c%profile_s, s_min, area)
      do i = 1, n
        s(i) = table_profile(xi(i), c%profile_x, c%profile_s, s_min)
      end do
      do i = 1, n - 1
        smid(i) = table_profile(0.5_dp * (xi(i) + xi(i + 1)), c%profile_x, c%profile_s, s_min)
      end do
    case default
      s = ring_profile(x, c%width, c%crown_height, c%crown_offset)
      smid = ring_profile(0.5_dp * (x(1:n - 1) + x(2:n)), c%width, c%crown_height, c%crown_offset)
    end select
  end subroutine face_profile

  !> Ring mass [kg]: rho 2 pi (r0 - a/2) (a b - int S dx), with the face
  !> profile of the case (closed form for 'edge' and 'gauge', exact for a table's linear
  !> interpolant).
  pure real(dp) function ring_mass(c)
    type(case_type), intent(in) :: c
    real(dp) :: hb, area_s, s_min
    hb = 0.5_dp * c%width
    select case (c%profile)
    case ('gauge')
      area_s = gauge_area(c%width, c%crown_offset, c%gauge_length, c%gauge_drop_top, &
                          c%gauge_drop_bottom)
    case ('table')
      call table_area(c%width, c%profile_x, c%profile_s, s_min, area_s)
    case default
      area_s = c%crown_height / hb**2 * ((hb + c%crown_offset)**3 - (c%crown_offset - hb)**3) &
               / 3.0_dp
    end select
    ring_mass = c%density * 2.0_dp * pi * (c%bore_radius - 0.5_dp * c%radial_depth) &
                * (c%radial_depth * c%width - area_s)
  end function ring_mass

  !> The liner temperature [K] where the ring is when the piston is at s [m] from TDC:
  !> linear from liner_temperature_top (s = 0) to liner_temperature_bottom (s = 2 r), each
  !> liner_temperature where it is 0.
  pure real(dp) function liner_temperature_at(c, s) result(t)
    type(case_type), intent(in) :: c
    real(dp), intent(in) :: s
    real(dp) :: top, bottom
    top = c%liner_temperature
    bottom = c%liner_temperature
    if (c%liner_temperature_top > 0.0_dp) top = c%liner_temperature_top
    if (c%liner_temperature_bottom > 0.0_dp) bottom = c%liner_temperature_bottom
    t = top + (bottom - top) * (s / (2.0_dp * c%crank_radius))
  end function liner_temperature_at

  !> One liner temperature over the whole stroke, liner_temperature (neither end given)?
  pure logical function uniform_liner(c)
    type(case_type), intent(in) :: c
    uniform_liner = c%liner_temperature_top == 0.0_dp .and. c%liner_temperature_bottom == 0.0_dp
  end function uniform_liner

  !> Number of crank steps in one 720 deg cycle.
  pure integer function steps_per_cycle(c)
    type(case_type), intent(in) :: c
    steps_per_cycle = nint(720.0_dp / c%dpsi_deg)
  end function steps_per_cycle

  !> Check every value against its range or choices (the table), then the conditions that
  !> relate two variables; the message names the case, the group and the variable.
  subroutine validate_case(c, err)
    type(case_type), intent(inout) :: c
    type(error_type), allocatable, intent(out) :: err
    character(len=:), allocatable :: why, text
    real(dp) :: eta
    integer :: i

    do i = 1, n_inputs
      call case_access(c, i, access_check, text, why)
      if (allocated(why)) then
        call bad(trim(inputs(i)%group), trim(inputs(i)%name), why)
        return
      end if
    end do
    if (c%conrod_length <= c%crank_radius) then
      call bad('engine', 'conrod_length', 'must exceed crank_radius'); return
    end if
    if (c%cavitation_pressure > c%crankcase_pressure) then
      call bad('operating', 'cavitation_pressure', 'must not exceed crankcase_pressure'); return
    end if
    if (abs(c%crown_offset) >= 0.5_dp * c%width) then
      call bad('ring', 'crown_offset', 'must lie inside the face, |crown_offset| < width/2'); return
    end if
    if (c%radial_depth >= c%bore_radius) then
      call bad('ring', 'radial_depth', 'must be smaller than bore_radius'); return
    end if
    if (c%profile == 'table') then
      if (len(c%profile_file) == 0) then
        call bad('ring', 'profile_file', "must name the profile's CSV file with profile = 'table'")
        return
      end if
      if (allocated(c%profile_x)) then
        call check_profile_table(c%profile_x, c%profile_s, c%width, why)
        if (allocated(why)) then
          call bad('ring', 'profile_file', c%profile_file//': '//why); return
        end if
      end if
    end if
    if (c%groove_volume > 0.0_dp .and. c%groove_volume < 1e-10_dp) then
      call bad('ring_pack', 'groove_volume', 'must be 0 (from the groove) or at least 1e-10 m^3'); return
    end if
    if (c%ring_pack == 'gas' .and. c%groove_volume == 0.0_dp .and. &
        c%radial_depth + c%back_clearance >= c%bore_radius) then
    call bad('ring_pack', 'back_clearance', "with the ring's radial_depth must be smaller than "// &
               'bore_radius (the groove root), or give groove_volume'); return
    end if
    if (abs(720.0_dp / c%dpsi_deg - nint(720.0_dp / c%dpsi_deg)) > 1e-6_dp) then
      call bad('numerics', 'dpsi_deg', 'must divide 720 deg into a whole number of steps'); return
    end if
    if (steps_per_cycle(c) > max_steps_per_cycle) then
      call bad('numerics', 'dpsi_deg', 'gives more than '//itoa(max_steps_per_cycle)// &
               ' crank steps per cycle'); return
    end if
    if (uses_oil_data(c)) then
      call oil_law(why)
      if (allocated(why)) return
    end if
    if (c%liner_temperature_top > 0.0_dp .and. c%liner_temperature_top < 200.0_dp) then
      call bad('operating', 'liner_temperature_top', 'must be 0 (liner_temperature) or at '// &
               'least 200 K'); return
    end if
    if (c%liner_temperature_bottom > 0.0_dp .and. c%liner_temperature_bottom < 200.0_dp) then
      call bad('operating', 'liner_temperature_bottom', 'must be 0 (liner_temperature) or at '// &
               'least 200 K'); return
    end if
    do i = 1, 2
      eta = roelands_eta(roelands_law_at(liner_temperature_at(c, (i - 1) * 2.0_dp * &
                                                              c%crank_radius), c%eta0, &
                                         c%theta0, c%alpha, c%beta), 0.0_dp)
      if (.not. (eta >= 1e-5_dp .and. eta <= 100.0_dp)) then
        call bad('lubricant', 'eta0', 'with theta0, beta and the liner temperature gives a '// &
                 'viscosity of '//real_text(eta)//' Pa s at the liner temperature, outside the '// &
                 'plausible 1e-5 .. 100 Pa s'); return
      end if
    end do
    if (c%cavity_pressure == 'trailing_gas' .and. c%cavitation /= 'jfo') then
      call bad('physics', 'cavity_pressure', "'trailing_gas' is implemented for "// &
               "cavitation = 'jfo' only"); return
    end if
    if (c%inlet == 'starved' .and. c%cavitation /= 'jfo') then
      call bad('physics', 'inlet', "'starved' needs the mass-conserving film, cavitation = 'jfo'")
      return
    end if
    if (c%h0_ceiling <= 10.0_dp * c%h0_floor) then
      call bad('numerics', 'h0_ceiling', 'must exceed 10 h0_floor'); return
    end if
    if (len_trim(c%output_file) == 0) then
      call bad('output', 'file', 'must not be empty'); return
    end if
    if (c%bore == 'distorted') then
      call check_bore()
      if (allocated(err)) return
    end if

  contains

    subroutine bad(group, name, reason)
      character(len=*), intent(in) :: group, name, reason
      call fatal_error(err, c%deck_path//': &'//group//' '//name//': '//reason, &
                       rl_input_error)
    end subroutine bad

    !> The distortion of a distorted bore: lists of one length, orders up to M/2 once each,
    !> lists or a file, one of them given.
    subroutine check_bore()
      integer :: j
      if (mod(c%sectors, 2) /= 0) then
        call bad('bore', 'sectors', 'must be even, got '//itoa(c%sectors)); return
      end if
      if (len(c%distortion_file) > 0 .and. size(c%bore_order) + size(c%bore_amplitude) + &
          size(c%bore_phase) > 0) then
        call bad('bore', 'distortion_file', 'give the distortion as the lists order, '// &
                 'amplitude, phase or as a file, not both'); return
      end if
      if (size(c%bore_amplitude) /= size(c%bore_order)) then
        call bad('bore', 'amplitude', 'must have one value per order ('// &
                 itoa(size(c%bore_order))//' orders, '//itoa(size(c%bore_amplitude))// &
                 ' amplitudes)'); return
      end if
      if (size(c%bore_phase) /= 0 .and. size(c%bore_phase) /= size(c%bore_order)) then
        call bad('bore', 'phase', 'must have one value per order ('// &
                 itoa(size(c%bore_order))//' orders, '//itoa(size(c%bore_phase))// &
                 ' phases) or none (all 0)'); return
      end if
      do j = 1, size(c%bore_order)
        if (c%bore_order(j) > c%sectors / 2) then
          call bad('bore', 'order', 'order '//itoa(c%bore_order(j))//' needs at least '// &
                   itoa(2 * c%bore_order(j))//' sectors (sectors = '//itoa(c%sectors)//')')
          return
        end if
        if (any(c%bore_order(:j - 1) == c%bore_order(j))) then
          call bad('bore', 'order', 'order '//itoa(c%bore_order(j))//' given twice'); return
        end if
      end do
      if (len(c%distortion_file) == 0 .and. size(c%bore_order) == 0) then
        call bad('physics', 'bore', "'distorted' needs the distortion: &bore order and "// &
                 'amplitude, or &bore distortion_file (none is given)'); return
      end if
    end subroutine check_bore

    !> eta0, theta0 and beta of the law through the oil's kinematic viscosities at 40 and
    !> 100 degC (its grade's or its data sheet's) times oil_density; `fail` set (and `err`)
    !> for inconsistent oil data.
    subroutine oil_law(fail)
      character(len=:), allocatable, intent(out) :: fail
      real(dp) :: kv40, kv100
      character(len=:), allocatable :: whyg
      if (len(c%grade) > 0) then
        if (c%kv40 > 0.0_dp .or. c%kv100 > 0.0_dp) then
          call bad('lubricant', 'grade', 'and the data sheet''s kv40, kv100 are both given: '// &
                   'give one of them')
          fail = 'x'
          return
        end if
        call grade_viscosities(c%grade, kv40, kv100, whyg)
        if (allocated(whyg)) then
          call bad('lubricant', 'grade', whyg)
          fail = 'x'
          return
        end if
      else
        kv40 = c%kv40
        kv100 = c%kv100
        if (.not. (kv40 > 0.0_dp)) then
          call bad('lubricant', 'kv40', 'must be given with kv100 (the data sheet''s '// &
                   'kinematic viscosities at 40 and 100 degC)')
        else if (.not. (kv100 > 0.0_dp)) then
          call bad('lubricant', 'kv100', 'must be given with kv40 (the data sheet''s '// &
                   'kinematic viscosities at 40 and 100 degC)')
        else if (.not. (kv40 > kv100)) then
          call bad('lubricant', 'kv40', 'must exceed kv100 (an oil thins as it warms)')
        end if
        if (allocated(err)) then
          fail = 'x'
          return
        end if
      end if
      if (.not. (min(kv40, kv100) * 1e-6_dp * c%oil_density > 7e-5_dp)) then
        call bad('lubricant', 'kv100', 'with oil_density gives a viscosity below the '// &
                 'Roelands reference 6.3e-5 Pa s')
        fail = 'x'
        return
      end if
      call roelands_through(theta40, kv40 * 1e-6_dp * c%oil_density, theta100, &
                            kv100 * 1e-6_dp * c%oil_density, c%eta0, c%theta0, c%beta)
    end subroutine oil_law
  end subroutine validate_case

  !> Does the case take its viscosity law from oil data (a grade, or kv40 and kv100) rather
  !> than eta0, theta0 and beta?
  pure logical function uses_oil_data(c)
    type(case_type), intent(in) :: c
    uses_oil_data = .false.
    if (allocated(c%grade)) uses_oil_data = len(c%grade) > 0
    uses_oil_data = uses_oil_data .or. c%kv40 > 0.0_dp .or. c%kv100 > 0.0_dp
  end function uses_oil_data
end module ringlube_case
