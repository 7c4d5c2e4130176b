!> Results of one run and the one table of their names, units and descriptions.
!>
!> The tables drive the HDF5 writer, the f2py export (results reach Python by name) and
!> the docs. `short` is the name in Python and in studies, `stored` the HDF5 dataset or
!> root attribute name (SPEC section 9).
module ringlube_results
  use ringlube_kinds, only: dp
  implicit none
  private
  public :: result_type, field_spec, flag_spec, series_spec, n_series, int_series_spec, &
            n_int_series, scalar_spec, n_scalars, flag_bits, n_flags, series_ptr, int_series_ptr, &
            liner_ptr, scalar_value, allocate_result, flag_description, liner_spec, n_liner, &
            produced, derive_results

  !> Per-step flag bits (dataset `/cycle/flags`).
  integer, parameter, public :: flag_floor = 1        !< h0 held at h0_floor
  integer, parameter, public :: flag_ceiling = 2      !< h0 held at h0_ceiling
  integer, parameter, public :: flag_load = 4         !< load balance outside load_tol
  integer, parameter, public :: flag_viscosity = 8    !< pressure-viscosity loop not converged
  integer, parameter, public :: flag_cavitation = 16  !< cavitation active set not settled
  integer, parameter, public :: flag_piezo = 32       !< film pressure above roelands_p_max
  integer, parameter, public :: flag_overdraw = 64    !< inlet drew more oil than was there

  !> One result quantity.
  type :: field_spec
    character(len=24) :: short = ''
    character(len=24) :: stored = ''
    character(len=8) :: unit = ''
    logical :: integer_valued = .false.
    character(len=110) :: long_name = ''
    !> '' (always written), 'jfo' (mass-conserving film only), 'starved' (starved inlet only)
    !> or 'gas' (ring_pack = 'gas' only)
    character(len=8) :: requires = ''
    !> a design quantity a study records for every design (and may optimise)
    logical :: objective = .false.
  end type field_spec

  !> One flag bit.
  type :: flag_spec
    integer :: bit = 0
    character(len=20) :: name = ''
    character(len=60) :: description = ''
  end type flag_spec

  !&< (tables laid out by hand: not reformatted)
  !> Real series over the reported cycle, one value per crank step (group /cycle).
  type(field_spec), parameter :: series_spec(*) = [ &
    field_spec('crank_angle_deg', 'crank_angle_deg', 'deg', .false., &
      'crank angle, 0 = TDC at the start of intake, 360 = firing TDC'), &
    field_spec('sliding_speed', 'sliding_speed_m_s', 'm/s', .false., &
      'piston sliding speed, positive towards the crankcase'), &
    field_spec('h0', 'h0_m', 'm', .false., 'film thickness at the crown minimum h0'), &
    field_spec('lambda_min', 'lambda_min', '1', .false., &
      'smallest film thickness over the face divided by the composite roughness sigma'), &
  field_spec('gas_pressure', 'gas_pressure_Pa', 'Pa', .false., 'chamber gas pressure (absolute)'), &
    field_spec('applied_load', 'applied_load_N', 'N', .false., &
      'load pressing the ring on the liner, (p_e + p_gas) b 2 pi r0'), &
    field_spec('hydrodynamic_load', 'hydrodynamic_load_N', 'N', .false., &
      'load carried by the film pressure'), &
    field_spec('asperity_load', 'asperity_load_N', 'N', .false., &
      'load carried by asperity contact (Greenwood-Tripp)'), &
    field_spec('viscous_friction', 'viscous_friction_N', 'N', .false., &
      'viscous friction on the ring, positive towards the crankcase'), &
    field_spec('boundary_friction', 'boundary_friction_N', 'N', .false., &
      'boundary friction on the ring, positive towards the crankcase'), &
    field_spec('friction', 'friction_N', 'N', .false., &
      'total friction on the ring, positive towards the crankcase'), &
    field_spec('power_loss', 'power_loss_W', 'W', .false., 'friction power loss |f U|'), &
    field_spec('load_residual', 'load_residual', '1', .false., &
      'load balance residual (W_h + W_a - F) / F'), &
    field_spec('inlet_fill', 'inlet_fill', '1', .false., &
      'fill theta of the oil entering at the leading edge (1: flooded)', 'jfo'), &
    field_spec('wetted_width', 'wetted_width_m', 'm', .false., &
      'length of full film across the face', 'jfo'), &
    field_spec('oil_left', 'oil_left_m', 'm', .false., &
      'oil film left on the liner at the trailing edge', 'jfo'), &
    field_spec('oil_bank', 'oil_bank_m2', 'm^2', .false., &
      'oil bank pushed ahead of the leading edge, per unit circumference', 'starved'), &
    field_spec('groove_pressure', 'groove_pressure_Pa', 'Pa', .false., &
      'gas pressure in the groove behind the top ring, space 2 (its back pressure)', 'gas'), &
    field_spec('land_pressure', 'land_pressure_Pa', 'Pa', .false., &
      'gas pressure on the second land, space 3 (the ring''s lower edge)', 'gas'), &
    field_spec('ring_lift', 'ring_lift_m', 'm', .false., &
      'top ring lift above the lower groove flank', 'gas'), &
    field_spec('top_gap_flow', 'top_gap_flow_kg_s', 'kg/s', .false., &
      'gas flow through the top ring''s end gap, chamber to land, positive towards the crankcase', &
      'gas'), &
    field_spec('second_gap_flow', 'second_gap_flow_kg_s', 'kg/s', .false., &
      'gas flow through the second ring''s end gap, land to crankcase (blowby)', 'gas') &
  ]
  !> Integer series over the reported cycle.
  type(field_spec), parameter :: int_series_spec(*) = [ &
    field_spec('flags', 'flags', '1', .true., 'bit flags of the crank step (see description)'), &
    field_spec('film_solves', 'film_solves', '1', .true., &
      'film (Reynolds + contact) solves used by the load balance at this step') &
  ]

  !> Scalar results (root attributes).
  type(field_spec), parameter :: scalar_spec(*) = [ &
    field_spec('energy_loss', 'energy_loss_J', 'J', .false., 'friction energy lost per cycle', &
      '', .true.), &
    field_spec('mixed_share', 'mixed_share_pct', '%', .false., &
      'share of the cycle with h0/sigma < 4 (mixed/boundary lubrication)', '', .true.), &
    field_spec('ring_mass', 'ring_mass_g', 'g', .false., 'ring mass', '', .true.), &
    field_spec('min_film', 'min_film_m', 'm', .false., 'smallest film thickness over the cycle', &
      '', .true.), &
   field_spec('max_friction', 'max_friction_N', 'N', .false., 'largest |friction| over the cycle', &
      '', .true.), &
    field_spec('converged', 'converged', '1', .true., &
      '1: periodic within cycle_tol, no flagged step but lift-off (flag 2)'), &
    field_spec('cycles_run', 'cycles_run', '1', .true., 'cycles run (the last is reported)'), &
    field_spec('cycle_change', 'cycle_change', '1', .false., &
      'relative change of h0 at psi = 0 over the last cycle'), &
 field_spec('sigma', 'sigma_m', 'm', .false., 'composite roughness sqrt(Rq_liner^2 + Rq_ring^2)'), &
    field_spec('run_time', 'run_time_s', 's', .false., 'kernel time of the run'), &
    field_spec('total_film_solves', 'film_solves', '1', .true., 'film solves over the whole run'), &
    field_spec('reynolds_solves', 'reynolds_solves', '1', .true., &
      'Reynolds (tridiagonal) solves over the whole run'), &
    field_spec('cycles_computed', 'cycles_computed', '1', .false., &
      "cycles' worth of crank steps solved, warm-up included"), &
    field_spec('periodic', 'periodic', '1', .true., '1: h0 periodic within cycle_tol'), &
    field_spec('oil_to_chamber', 'oil_to_chamber_mm3', 'mm^3', .false., &
      'oil transported towards the chamber per cycle, whole circumference', 'starved', .true.), &
    field_spec('oil_balance_error', 'oil_balance_error', '1', .false., &
      'relative closure error of the oil balance over the reported cycle', 'starved'), &
    field_spec('friction_power', 'friction_power_W', 'W', .false., &
      'mean friction power of the ring: energy_loss x cycles per second (four-stroke, rpm/120)'), &
    field_spec('fmep', 'fmep_kPa', 'kPa', .false., &
      "the ring's friction mean effective pressure: energy_loss / swept volume pi r0^2 2 r"), &
    field_spec('oil_to_chamber_rate', 'oil_to_chamber_g_h', 'g/h', .false., &
      'oil to the chamber per hour: oil_to_chamber x oil_density x cycles per hour', 'starved'), &
    field_spec('flagged_steps', 'flagged_steps', '1', .true., &
      'crank steps of the reported cycle with a flag (see /cycle/flags)'), &
    field_spec('liner_lift_share', 'liner_lift_share_pct', '%', .false., &
      'share of the cycle the ring is lifted off the liner (h0 held at h0_ceiling, flag 2)', &
      '', .true.), &
    field_spec('blowby', 'blowby_l_min', 'L/min', .false., &
      'mean gas flow past the second ring to the crankcase, at 101325 Pa and 293.15 K', 'gas', &
      .true.), &
    field_spec('blowby_mass', 'blowby_mg_per_cycle', 'mg', .false., &
      'gas mass past the second ring per cycle', 'gas'), &
    field_spec('blowback_mass', 'blowback_mg_per_cycle', 'mg', .false., &
      'gas mass flowing back from the ring pack into the chamber per cycle', 'gas'), &
    field_spec('ring_lift_share', 'ring_lift_share_pct', '%', .false., &
      'share of the cycle the top ring is off its lower groove flank', 'gas', .true.), &
    field_spec('flutter_events', 'flutter_events', '1', .true., &
      'times the top ring leaves its lower flank while the chamber pressure exceeds the land''s', &
      'gas', .true.), &
    field_spec('gas_balance_error', 'gas_balance_error', '1', .false., &
      'relative closure of the ring pack''s gas mass over the reported cycle', 'gas') &
  ]

  !> The liner film at the end of the reported cycle (group /liner).
  type(field_spec), parameter :: liner_spec(*) = [ &
    field_spec('liner_position', 'position_m', 'm', .false., &
      'liner position from the top ring at TDC, positive towards the crankcase', 'starved'), &
    field_spec('liner_oil_film', 'oil_film_m', 'm', .false., &
      'oil film thickness on the liner', 'starved') &
  ]

  !> Meaning of the bits of /cycle/flags.
  type(flag_spec), parameter :: flag_bits(*) = [ &
    flag_spec(flag_floor, 'h0_floor', 'h0 at h0_floor'), &
    flag_spec(flag_ceiling, 'h0_ceiling', 'h0 at h0_ceiling'), &
    flag_spec(flag_load, 'load', 'load outside load_tol'), &
    flag_spec(flag_viscosity, 'viscosity', 'pressure-viscosity loop not converged'), &
    flag_spec(flag_cavitation, 'cavitation', 'cavitation set not settled'), &
    flag_spec(flag_piezo, 'piezoviscous_clip', 'film pressure above 1 GPa (Roelands clipped)'), &
    flag_spec(flag_overdraw, 'inlet_overdraw', 'starved inlet drew more oil than the liner held') &
  ]

  !&>

  integer, parameter :: n_series = size(series_spec), n_int_series = size(int_series_spec), &
                n_scalars = size(scalar_spec), n_flags = size(flag_bits), n_liner = size(liner_spec)

  !> Results of one run: the reported (last) cycle and its summary.
  type :: result_type
    integer :: nsteps = 0
    real(dp), allocatable :: crank_angle_deg(:), sliding_speed(:), h0(:), lambda_min(:), &
                         gas_pressure(:), applied_load(:), hydrodynamic_load(:), asperity_load(:), &
          viscous_friction(:), boundary_friction(:), friction(:), power_loss(:), load_residual(:), &
                             inlet_fill(:), wetted_width(:), oil_left(:), oil_bank(:), &
                             groove_pressure(:), land_pressure(:), ring_lift(:), top_gap_flow(:), &
                             second_gap_flow(:)
    integer, allocatable :: flags(:), film_solves(:)
    !> which optional results the run produced ('jfo', 'starved', 'gas')
    logical :: has_jfo = .false., has_starved = .false., has_ring_pack = .false.
    !> share of the cycle lifted off the liner [%]; the ring pack's cycle quantities
    real(dp) :: liner_lift_share = 0.0_dp
    real(dp) :: blowby = 0.0_dp, blowby_mass = 0.0_dp, blowback_mass = 0.0_dp, &
                ring_lift_share = 0.0_dp, gas_balance_error = 0.0_dp
    integer :: flutter_events = 0
    !> liner film at the end of the reported cycle
    real(dp), allocatable :: liner_z(:), liner_h(:)
    real(dp) :: oil_to_chamber = 0.0_dp     !< mm^3 per cycle, whole circumference
    real(dp) :: oil_balance_error = 0.0_dp  !< relative
    real(dp) :: oil_to_chamber_rate = 0.0_dp  !< g/h
    real(dp) :: friction_power = 0.0_dp    !< W, mean over the cycle
    real(dp) :: fmep = 0.0_dp              !< kPa
    integer :: flagged_steps = 0           !< crank steps with a flag
    real(dp) :: energy_loss = 0.0_dp       !< J per cycle
    real(dp) :: mixed_share = 0.0_dp       !< % of the cycle with h0/sigma < 4
    real(dp) :: ring_mass = 0.0_dp         !< kg
    real(dp) :: min_film = 0.0_dp          !< m, min over the cycle of min_x h
    real(dp) :: max_friction = 0.0_dp      !< N, max |f|
    real(dp) :: cycle_change = 0.0_dp      !< |h0 end - h0 start| / h0 start of the last cycle
    real(dp) :: sigma = 0.0_dp             !< m, composite roughness
    real(dp) :: run_time = 0.0_dp          !< s, set by the caller that times the run
    logical :: converged = .false.         !< periodic within cycle_tol and no flagged step
    logical :: periodic = .false.          !< periodic within cycle_tol
    integer :: cycles_run = 0
    integer :: total_film_solves = 0       !< film solves over the whole run
    integer :: reynolds_solves = 0         !< Reynolds solves over the whole run
    !> cycles' worth of crank steps solved: cycles_run + warm-up + periodicity checks
    real(dp) :: cycles_computed = 0.0_dp
  end type result_type

contains

  !> Allocate every series of the tables for m crank steps (zeros; the liner film empty).
  subroutine allocate_result(res, m)
    type(result_type), intent(inout), target :: res
    integer, intent(in) :: m
    integer :: i
    res%nsteps = m
    do i = 1, n_series
      call real_field(res, 'series', i, m=m)
    end do
    do i = 1, n_int_series
      call int_field(res, i, m=m)
    end do
    do i = 1, n_liner
      call real_field(res, 'liner', i, m=0)
    end do
  end subroutine allocate_result

  !> Did the run produce a result that `requires` this model ('' always)?
  pure logical function produced(res, requires)
    type(result_type), intent(in) :: res
    character(len=*), intent(in) :: requires
    select case (trim(requires))
    case ('jfo'); produced = res%has_jfo
    case ('starved'); produced = res%has_starved
    case ('gas'); produced = res%has_ring_pack
    case default; produced = .true.
    end select
  end function produced

  !> The real series i of `series_spec`.
  function series_ptr(res, i) result(p)
    type(result_type), intent(inout), target :: res
    integer, intent(in) :: i
    real(dp), pointer :: p(:)
    call real_field(res, 'series', i, p=p)
  end function series_ptr

  !> The liner film quantity i of `liner_spec`.
  function liner_ptr(res, i) result(p)
    type(result_type), intent(inout), target :: res
    integer, intent(in) :: i
    real(dp), pointer :: p(:)
    call real_field(res, 'liner', i, p=p)
  end function liner_ptr

  !> The integer series i of `int_series_spec`.
  function int_series_ptr(res, i) result(p)
    type(result_type), intent(inout), target :: res
    integer, intent(in) :: i
    integer, pointer :: p(:)
    call int_field(res, i, p=p)
  end function int_series_ptr

  !> The one map from the rows of `series_spec` (`table = 'series'`) and `liner_spec`
  !> ('liner') to the components of `result_type`: with `m`, (re)allocate the component
  !> with m zeros; with `p`, point p at it. A new series is a row of the table, its
  !> component and one line here.
  subroutine real_field(res, table, i, m, p)
    type(result_type), intent(inout), target :: res
    character(len=*), intent(in) :: table
    integer, intent(in) :: i
    integer, intent(in), optional :: m
    real(dp), pointer, intent(out), optional :: p(:)
    character(len=:), allocatable :: name
    if (present(p)) p => null()
    if (table == 'liner') then
      name = trim(liner_spec(i)%short)
    else
      name = trim(series_spec(i)%short)
    end if
    select case (name)
    case ('crank_angle_deg'); call point(res%crank_angle_deg)
    case ('sliding_speed'); call point(res%sliding_speed)
    case ('h0'); call point(res%h0)
    case ('lambda_min'); call point(res%lambda_min)
    case ('gas_pressure'); call point(res%gas_pressure)
    case ('applied_load'); call point(res%applied_load)
    case ('hydrodynamic_load'); call point(res%hydrodynamic_load)
    case ('asperity_load'); call point(res%asperity_load)
    case ('viscous_friction'); call point(res%viscous_friction)
    case ('boundary_friction'); call point(res%boundary_friction)
    case ('friction'); call point(res%friction)
    case ('power_loss'); call point(res%power_loss)
    case ('load_residual'); call point(res%load_residual)
    case ('inlet_fill'); call point(res%inlet_fill)
    case ('wetted_width'); call point(res%wetted_width)
    case ('oil_left'); call point(res%oil_left)
    case ('oil_bank'); call point(res%oil_bank)
    case ('groove_pressure'); call point(res%groove_pressure)
    case ('land_pressure'); call point(res%land_pressure)
    case ('ring_lift'); call point(res%ring_lift)
    case ('top_gap_flow'); call point(res%top_gap_flow)
    case ('second_gap_flow'); call point(res%second_gap_flow)
    case ('liner_position'); call point(res%liner_z)
    case ('liner_oil_film'); call point(res%liner_h)
    end select
  contains
    subroutine point(x)
      real(dp), allocatable, target, intent(inout) :: x(:)
      if (present(m)) then
        if (allocated(x)) deallocate (x)
        allocate (x(m))
        x = 0.0_dp
      end if
      if (present(p)) p => x
    end subroutine point
  end subroutine real_field

  !> `real_field` for the rows of `int_series_spec`.
  subroutine int_field(res, i, m, p)
    type(result_type), intent(inout), target :: res
    integer, intent(in) :: i
    integer, intent(in), optional :: m
    integer, pointer, intent(out), optional :: p(:)
    if (present(p)) p => null()
    select case (trim(int_series_spec(i)%short))
    case ('flags'); call point(res%flags)
    case ('film_solves'); call point(res%film_solves)
    end select
  contains
    subroutine point(x)
      integer, allocatable, target, intent(inout) :: x(:)
      if (present(m)) then
        if (allocated(x)) deallocate (x)
        allocate (x(m))
        x = 0
      end if
      if (present(p)) p => x
    end subroutine point
  end subroutine int_field

  !> Scalar i of `scalar_spec` in its stored unit (mass in g; integers and logicals as
  !> 0/1 reals): the one map from the rows of the table to the components of `result_type`.
  pure real(dp) function scalar_value(res, i) result(v)
    type(result_type), intent(in) :: res
    integer, intent(in) :: i
    v = 0.0_dp
    select case (trim(scalar_spec(i)%short))
    case ('energy_loss'); v = res%energy_loss
    case ('mixed_share'); v = res%mixed_share
    case ('ring_mass'); v = res%ring_mass * 1e3_dp
    case ('min_film'); v = res%min_film
    case ('max_friction'); v = res%max_friction
    case ('converged'); v = merge(1.0_dp, 0.0_dp, res%converged)
    case ('cycles_run'); v = real(res%cycles_run, dp)
    case ('cycle_change'); v = res%cycle_change
    case ('sigma'); v = res%sigma
    case ('run_time'); v = res%run_time
    case ('total_film_solves'); v = real(res%total_film_solves, dp)
    case ('reynolds_solves'); v = real(res%reynolds_solves, dp)
    case ('cycles_computed'); v = res%cycles_computed
    case ('periodic'); v = merge(1.0_dp, 0.0_dp, res%periodic)
    case ('oil_to_chamber'); v = res%oil_to_chamber
    case ('oil_balance_error'); v = res%oil_balance_error
    case ('friction_power'); v = res%friction_power
    case ('fmep'); v = res%fmep
    case ('oil_to_chamber_rate'); v = res%oil_to_chamber_rate
    case ('flagged_steps'); v = real(res%flagged_steps, dp)
    case ('liner_lift_share'); v = res%liner_lift_share
    case ('blowby'); v = res%blowby
    case ('blowby_mass'); v = res%blowby_mass
    case ('blowback_mass'); v = res%blowback_mass
    case ('ring_lift_share'); v = res%ring_lift_share
    case ('flutter_events'); v = real(res%flutter_events, dp)
    case ('gas_balance_error'); v = res%gas_balance_error
    end select
  end function scalar_value

  !> The results engineers quote, from the cycle's (called at the end of a run): mean
  !> friction power [W] (energy per cycle x speed_rpm / 120 cycles per second, four-stroke),
  !> FMEP [kPa] (energy per cycle / swept volume [m^3]), the oil to the chamber in g/h
  !> (oil_density [kg/m^3]) and the count of flagged crank steps.
  pure subroutine derive_results(res, speed_rpm, swept_volume, oil_density)
    type(result_type), intent(inout) :: res
    real(dp), intent(in) :: speed_rpm, swept_volume, oil_density
    res%friction_power = res%energy_loss * speed_rpm / 120.0_dp
    res%fmep = res%energy_loss / swept_volume * 1e-3_dp
    ! mm^3/cycle x 1e-9 m^3/mm^3 x kg/m^3 x 1e3 g/kg x 30 speed_rpm cycles per hour
    res%oil_to_chamber_rate = res%oil_to_chamber * 1e-6_dp * oil_density * 30.0_dp * speed_rpm
    if (allocated(res%flags)) then
      res%flagged_steps = count(res%flags /= 0)
      res%liner_lift_share = 100.0_dp * count(iand(res%flags, flag_ceiling) /= 0) &
                             / real(max(size(res%flags), 1), dp)
    end if
  end subroutine derive_results

  !> "1: h0 at h0_floor, 2: ..." (the `description` of /cycle/flags).
  function flag_description() result(t)
    character(len=:), allocatable :: t
    character(len=12) :: buf
    integer :: i
    t = ''
    do i = 1, n_flags
      write (buf, '(i0)') flag_bits(i)%bit
      if (i > 1) t = t//', '
      t = t//trim(buf)//': '//trim(flag_bits(i)%description)
    end do
  end function flag_description
end module ringlube_results
