!> Results of one run and the one table of their names, units and descriptions.
!>
!> The tables drive the storage (a result holds each table's values by row: column i of
!> `series` is row i of `series_spec`), the HDF5 writer, the f2py export (results reach
!> Python by name) and the docs. `short` is the name in Python and in studies, `stored` the
!> HDF5 dataset or root attribute name (docs/model.md "Results"). A new result is a row of its table;
!> kernel code that sets it names its column by a constant below (`s_h0`: the row 'h0' of
!> `series_spec`), found in the table by name when compiling.
module ringlube_results
  use ringlube_kinds, only: dp
  implicit none
  private
  public :: mixed_share
  public :: result_type, field_spec, flag_spec, series_spec, n_series, int_series_spec, &
            n_int_series, scalar_spec, n_scalars, flag_bits, n_flags, allocate_result, &
            allocate_sectors, sector_spec, n_sector_series, &
            allocate_liner, flag_description, liner_spec, n_liner, produced, produced_models, &
            derive_results, truth, is_true, model_spec, models, n_models

  !> Branch risk: a margin below its threshold is warned of in the summary and marks a study's
  !> design (docs/model.md, "Branch risk"), with the reason given here.
  type :: margin_spec
    character(len=24) :: name = ''
    real(dp) :: threshold = 0.0_dp
    character(len=300) :: reason = ''
  end type margin_spec
  !&<
  type(margin_spec), parameter, public :: margin_thresholds(*) = [ &
    margin_spec('lift_margin', 0.01_dp, 'ten times the default load_tol: near the threshold '// &
      'the balance accepts a ring at h0_ceiling within load_tol and the cycle changes branch '// &
      'there; and a 1 % change of the gas pressures on the intake stroke, rarely known '// &
      'better, moves the margin by about 1 %'), &
    margin_spec('seal_margin', 0.1_dp, 'the crank step alone moved the face between sealed '// &
      'and blown at margins below 0.1 on the shipped cold deck') &
  ]
  !&>

  !> Per-step flag bits (dataset `/cycle/flags`).
  integer, parameter, public :: flag_floor = 1        !< h0 held at h0_floor
  integer, parameter, public :: flag_ceiling = 2      !< h0 held at h0_ceiling
  integer, parameter, public :: flag_load = 4         !< load balance outside load_tol
  integer, parameter, public :: flag_viscosity = 8    !< pressure-viscosity loop not converged
  integer, parameter, public :: flag_cavitation = 16  !< cavitation active set not settled
  integer, parameter, public :: flag_piezo = 32       !< film pressure above roelands_p_max
  integer, parameter, public :: flag_overdraw = 64    !< inlet drew more oil than was there
  integer, parameter, public :: flag_sectors = 128    !< a distorted bore's sectors not solved
  !> A sector's state change between two crank steps (result `sector_jumps`): its h0 changes
  !> relative to the ring's (the sectors' geometric mean) by more than this in ln (a factor
  !> e^0.2, 22 %)
  real(dp), parameter, public :: sector_jump_log = 0.2_dp

  !> One result quantity.
  type :: field_spec
    character(len=24) :: short = ''
    character(len=32) :: stored = ''
    character(len=8) :: unit = ''
    !> 'real'; 'integer' (a count) or 'logical' (1 true, 0 false): a whole number, stored
    !> as an integer (a scalar of `result_type` holds it as a real)
    character(len=8) :: kind = 'real'
    character(len=110) :: long_name = ''
    !> '' (always written), 'jfo' (mass-conserving film only), 'starved' (starved inlet only),
    !> 'gas' (ring_pack = 'gas' only) or 'distorted' (bore = 'distorted' only)
    character(len=10) :: requires = ''
    !> a design quantity a study records for every design (and may optimise)
    logical :: objective = .false.
    !> a design quantity a study may optimise, recorded when a study names it
    logical :: optimisable = .false.
  end type field_spec

  !> An optional model: the results whose `requires` is `name` exist when the input
  !> &`group` `variable` is `value`.
  type :: model_spec
    character(len=10) :: name = ''
    character(len=12) :: group = ''
    character(len=16) :: variable = ''
    character(len=12) :: value = ''
  end type model_spec

  !> One flag bit.
  type :: flag_spec
    integer :: bit = 0
    character(len=20) :: name = ''
    character(len=60) :: description = ''
  end type flag_spec

  !&< (tables laid out by hand: not reformatted)
  !> Real series over the reported cycle, one value per crank step (group /cycle).
  type(field_spec), parameter :: series_spec(*) = [ &
    field_spec('crank_angle_deg', 'crank_angle_deg', 'deg', 'real', &
      'crank angle, 0 = TDC at the start of intake, 360 = firing TDC'), &
    field_spec('sliding_speed', 'sliding_speed_m_s', 'm/s', 'real', &
      'piston sliding speed, positive towards the crankcase'), &
    field_spec('h0', 'h0_m', 'm', 'real', 'film thickness at the crown minimum h0'), &
    field_spec('lambda_min', 'lambda_min', '1', 'real', &
      'smallest film thickness over the face divided by the composite roughness sigma'), &
  field_spec('gas_pressure', 'gas_pressure_Pa', 'Pa', 'real', 'chamber gas pressure (absolute)'), &
    field_spec('applied_load', 'applied_load_N', 'N', 'real', &
      'load pressing the ring on the liner, (p_e + p_gas) b 2 pi r0'), &
    field_spec('hydrodynamic_load', 'hydrodynamic_load_N', 'N', 'real', &
      'load carried by the film pressure'), &
    field_spec('asperity_load', 'asperity_load_N', 'N', 'real', &
      'load carried by asperity contact (Greenwood-Tripp)'), &
    field_spec('viscous_friction', 'viscous_friction_N', 'N', 'real', &
      'viscous friction on the ring, positive towards the crankcase'), &
    field_spec('boundary_friction', 'boundary_friction_N', 'N', 'real', &
      'boundary friction on the ring, positive towards the crankcase'), &
    field_spec('friction', 'friction_N', 'N', 'real', &
      'total friction on the ring, positive towards the crankcase'), &
    field_spec('power_loss', 'power_loss_W', 'W', 'real', 'friction power loss |f U|'), &
    field_spec('load_residual', 'load_residual', '1', 'real', &
      'load balance residual (W_h + W_a - F) / F'), &
    field_spec('film_temperature', 'film_temperature_K', 'K', 'real', &
      'film temperature: the liner temperature where the ring is (its viscosity law''s)'), &
    field_spec('inlet_fill', 'inlet_fill', '1', 'real', &
      'fill theta of the oil entering at the leading edge (1: flooded)', 'jfo'), &
    field_spec('wetted_width', 'wetted_width_m', 'm', 'real', &
      'length of full film across the face', 'jfo'), &
    field_spec('oil_left', 'oil_left_m', 'm', 'real', &
      'oil film left on the liner at the trailing edge', 'jfo'), &
    field_spec('oil_bank', 'oil_bank_m2', 'm^2', 'real', &
      'oil bank pushed ahead of the leading edge, per unit circumference', 'starved'), &
    field_spec('groove_pressure', 'groove_pressure_Pa', 'Pa', 'real', &
      'gas pressure in the groove behind the top ring, space 2 (its back pressure)', 'gas'), &
    field_spec('land_pressure', 'land_pressure_Pa', 'Pa', 'real', &
      'gas pressure on the second land, space 3 (the ring''s lower edge)', 'gas'), &
    field_spec('ring_lift', 'ring_lift_m', 'm', 'real', &
      'top ring lift above the lower groove flank', 'gas'), &
    field_spec('top_gap_flow', 'top_gap_flow_kg_s', 'kg/s', 'real', &
      'gas flow through the top ring''s end gap, chamber to land, positive towards the crankcase', &
      'gas'), &
    field_spec('second_gap_flow', 'second_gap_flow_kg_s', 'kg/s', 'real', &
      'gas flow through the second ring''s end gap, land to crankcase (blowby)', 'gas'), &
    field_spec('face_flow', 'face_flow_kg_s', 'kg/s', 'real', &
      'gas flow through the ring''s face where its film leaves a gas path, positive towards '// &
      'the crankcase', 'distorted') &
  ]
  !> Series per crank step and sector of a distorted bore (group /cycle, crank angle x sector).
  type(field_spec), parameter :: sector_spec(*) = [ &
    field_spec('sector_h0', 'sector_h0_m', 'm', 'real', &
      'film thickness at the crown minimum of each sector', 'distorted'), &
    field_spec('sector_load', 'sector_load_N_per_m', 'N/m', 'real', &
      'load the film of each sector carries per unit circumference (hydrodynamic + asperity)', &
      'distorted') &
  ]
  !> Integer series over the reported cycle.
  type(field_spec), parameter :: int_series_spec(*) = [ &
    field_spec('flags', 'flags', '1', 'integer', 'bit flags of the crank step (see description)'), &
    field_spec('film_solves', 'film_solves', '1', 'integer', &
      'film (Reynolds + contact) solves used by the load balance at this step') &
  ]

  !> Scalar results (root attributes).
  type(field_spec), parameter :: scalar_spec(*) = [ &
    field_spec('energy_loss', 'energy_loss_J', 'J', 'real', 'friction energy lost per cycle', &
      '', .true.), &
    field_spec('mixed_share', 'mixed_share_pct', '%', 'real', &
      'share of the cycle with h0/sigma < 4 (mixed/boundary lubrication)', '', .true.), &
    field_spec('ring_mass', 'ring_mass_g', 'g', 'real', 'ring mass', '', .true.), &
    field_spec('min_film', 'min_film_m', 'm', 'real', 'smallest film thickness over the cycle', &
      '', .true.), &
   field_spec('max_friction', 'max_friction_N', 'N', 'real', 'largest |friction| over the cycle', &
      '', .true.), &
    field_spec('converged', 'converged', '1', 'logical', &
      '1: periodic within cycle_tol, no flagged step but lift-off (flag 2)'), &
    field_spec('cycles_run', 'cycles_run', '1', 'integer', 'cycles run (the last is reported)'), &
    field_spec('cycle_change', 'cycle_change', '1', 'real', &
      'h0 at psi = 0: last cycle''s relative change / (1 - contraction), or over the period'), &
    field_spec('energy_change', 'energy_change', '1', 'real', &
      'energy_loss: last cycle''s relative change / (1 - contraction), or over the period'), &
    field_spec('liner_change', 'liner_change', '1', 'real', &
      'liner film: last cycle''s L1 change / (1 - contraction), or over the period', &
      'starved'), &
    field_spec('ring_pack_change', 'ring_pack_change', '1', 'real', &
      'the ring pack''s distance from its periodic state, or its change over the period', 'gas'), &
 field_spec('sigma', 'sigma_m', 'm', 'real', 'composite roughness sqrt(Rq_liner^2 + Rq_ring^2)'), &
    field_spec('run_time', 'run_time_s', 's', 'real', 'kernel time of the run'), &
    field_spec('total_film_solves', 'film_solves', '1', 'integer', &
      'film solves over the whole run'), &
    field_spec('reynolds_solves', 'reynolds_solves', '1', 'integer', &
      'Reynolds (tridiagonal) solves over the whole run'), &
    field_spec('cycles_computed', 'cycles_computed', '1', 'real', &
      "cycles' worth of crank steps solved, warm-up included"), &
    field_spec('periodic', 'periodic', '1', 'logical', &
      '1: the state repeats within cycle_tol after period cycles'), &
 field_spec('period', 'period', '1', 'integer', 'cycles after which the state repeats (1 .. 12;'// &
      ' 0: none); from 2 the cycle quantities are means over them'), &
    field_spec('oil_to_chamber', 'oil_to_chamber_mm3', 'mm^3', 'real', &
      'oil transported towards the chamber per cycle, whole circumference', 'starved', .true.), &
    field_spec('oil_balance_error', 'oil_balance_error', '1', 'real', &
      'relative closure error of the oil balance over the reported cycle', 'starved'), &
    field_spec('friction_power', 'friction_power_W', 'W', 'real', &
      'mean friction power of the ring: energy_loss x cycles per second (four-stroke, rpm/120)', &
      '', .false., .true.), &
    field_spec('fmep', 'fmep_kPa', 'kPa', 'real', &
      "the ring's friction mean effective pressure: energy_loss / swept volume pi r0^2 2 r", &
      '', .false., .true.), &
  field_spec('fmep_bar', 'fmep_bar', 'bar', 'real', 'fmep in bar (100 kPa)', '', .false., .true.), &
    field_spec('displacement', 'displacement_L', 'L', 'real', &
      "the engine's swept volume: cylinders x pi r0^2 2 r"), &
    field_spec('engine_friction_power', 'engine_friction_power_W', 'W', 'real', &
     "the engine's top rings' mean friction power: friction_power x cylinders (its FMEP is fmep)", &
      '', .false., .true.), &
    field_spec('oil_to_chamber_rate', 'oil_to_chamber_g_h', 'g/h', 'real', &
      'oil to the chamber per hour: oil_to_chamber x oil_density x cycles per hour', 'starved'), &
    field_spec('flagged_steps', 'flagged_steps', '1', 'integer', &
      'crank steps of the reported cycle with a flag (see /cycle/flags)'), &
    field_spec('liner_lift_share', 'liner_lift_share_pct', '%', 'real', &
      'share of the cycle the ring is lifted off the liner (h0 held at h0_ceiling, flag 2)', &
      '', .true.), &
    field_spec('blowby', 'blowby_l_min', 'L/min', 'real', &
      'mean gas flow past the second ring to the crankcase, at 101325 Pa and 293.15 K', 'gas', &
      .true.), &
    field_spec('blowby_mass', 'blowby_mg_per_cycle', 'mg', 'real', &
      'gas mass past the second ring per cycle', 'gas'), &
    field_spec('blowback_mass', 'blowback_mg_per_cycle', 'mg', 'real', &
      'gas mass flowing back from the ring pack into the chamber per cycle', 'gas'), &
    field_spec('ring_lift_share', 'ring_lift_share_pct', '%', 'real', &
      'share of the cycle the top ring is off its lower groove flank', 'gas', .true.), &
    ! (a real: with a period of several cycles their mean, 1.5 for 1 and 2 events)
    field_spec('flutter_events', 'flutter_events', '1', 'real', &
      'times per cycle the top ring leaves its lower flank while the chamber pressure exceeds '// &
      'the land''s', &
      'gas', .true.), &
    field_spec('flutter_margin', 'flutter_margin_N', 'N', 'real', &
      'least net force holding the top ring on its lower flank while chamber pressure > '// &
      'land''s (< 0: flutter)', 'gas', .false., .true.), &
    field_spec('flutter_margin_ratio', 'flutter_margin_ratio', '1', 'real', &
      'flutter_margin over the largest inertia force of the ring, m_r max|a_p|', 'gas', .false., &
      .true.), &
    field_spec('lift_margin', 'lift_margin', '1', 'real', &
      'smallest (F - W at h0_ceiling) / F over the intake stroke: < 0 the ring can lift off '// &
      '(branch risk)', '', .true.), &
    field_spec('lift_margin_angle', 'lift_margin_angle_deg', 'deg', 'real', &
      'crank angle of lift_margin'), &
    field_spec('seal_margin', 'seal_margin', '1', 'real', &
     'margin of the state (sealed > 0, blown <= 0) the face ends its trailing-gas decisions in '// &
      '(branch risk)', 'trailing'), &
    field_spec('seal_margin_angle', 'seal_margin_angle_deg', 'deg', 'real', &
      'crank angle of seal_margin', 'trailing'), &
    field_spec('margin_film_solves', 'margin_film_solves', '1', 'integer', &
      'film solves of the reported cycle on copies of the film for lift_margin (not in '// &
      'film_solves)'), &
    field_spec('peak_groove_pressure', 'peak_groove_pressure_Pa', 'Pa', 'real', &
      'highest groove pressure of the cycle', 'gas'), &
    field_spec('peak_groove_angle', 'peak_groove_angle_deg', 'deg', 'real', &
      'crank angle of the highest groove pressure', 'gas'), &
    field_spec('peak_land_pressure', 'peak_land_pressure_Pa', 'Pa', 'real', &
      'highest second-land pressure of the cycle', 'gas'), &
    field_spec('peak_land_angle', 'peak_land_angle_deg', 'deg', 'real', &
      'crank angle of the highest second-land pressure', 'gas'), &
    field_spec('gas_balance_error', 'gas_balance_error', '1', 'real', &
      'relative closure of the ring pack''s gas mass over the reported cycle', 'gas'), &
    field_spec('gas_exchange', 'gas_exchange_mg_per_cycle', 'mg', 'real', &
      'gas through the second land''s boundaries per cycle, or the groove''s and land''s '// &
      'if less (0: trapped)', &
      'gas'), &
    field_spec('conformability', 'conformability', '1', 'real', &
      'largest A_k over its conformability limit q C_k of the orders given (> 1: light gaps '// &
      'open without a film)', 'distorted', .true.), &
    field_spec('light_gap_share', 'light_gap_share_pct', '%', 'real', &
      'share of sector-steps whose film carries less than 1 % of the mean load (off the liner)', &
      'distorted', .true.), &
    field_spec('face_leakage', 'face_leakage_mg_per_cycle', 'mg', 'real', &
      'gas mass through the ring''s face towards the crankcase per cycle (the way back: '// &
      'blowback)', 'distorted', &
      .true.), &
    field_spec('radial_collapse_share', 'radial_collapse_share_pct', '%', 'real', &
      'share of the cycle the ring is pushed off the liner, held at back_clearance', &
      'distorted'), &
    field_spec('sector_jumps', 'sector_jumps', '1', 'real', &
      'crank steps of the cycle at which a sector''s h0 changes relative to the ring''s by '// &
      'over e^0.2 (a state change)', 'distorted') &
  ]

  !> The liner film at the end of the reported cycle (group /liner).
  type(field_spec), parameter :: liner_spec(*) = [ &
    field_spec('liner_position', 'position_m', 'm', 'real', &
      'liner position from the top ring at TDC, positive towards the crankcase', 'starved'), &
    field_spec('liner_oil_film', 'oil_film_m', 'm', 'real', &
      'oil film thickness on the liner', 'starved') &
  ]

  !> The models a result may require (the `requires` of the tables above).
  type(model_spec), parameter :: models(*) = [ &
    model_spec('jfo', 'physics', 'cavitation', 'jfo'), &
    model_spec('starved', 'physics', 'inlet', 'starved'), &
    model_spec('gas', 'physics', 'ring_pack', 'gas'), &
    model_spec('distorted', 'physics', 'bore', 'distorted'), &
    model_spec('trailing', 'physics', 'cavity_pressure', 'trailing_gas') &
  ]

  !> Meaning of the bits of /cycle/flags.
  type(flag_spec), parameter :: flag_bits(*) = [ &
    flag_spec(flag_floor, 'h0_floor', 'h0 at h0_floor'), &
    flag_spec(flag_ceiling, 'h0_ceiling', 'h0 at h0_ceiling'), &
    flag_spec(flag_load, 'load', 'load outside load_tol'), &
    flag_spec(flag_viscosity, 'viscosity', 'pressure-viscosity loop not converged'), &
    flag_spec(flag_cavitation, 'cavitation', 'cavitation set not settled'), &
    flag_spec(flag_piezo, 'piezoviscous_clip', 'film pressure above 1 GPa (Roelands clipped)'), &
    flag_spec(flag_overdraw, 'inlet_overdraw', 'starved inlet drew more oil than the liner held'), &
    flag_spec(flag_sectors, 'sectors', 'sectors of the distorted bore outside their tolerance') &
  ]
  !&>

  integer, parameter :: n_series = size(series_spec), n_int_series = size(int_series_spec), &
                        n_scalars = size(scalar_spec), n_liner = size(liner_spec), &
                        n_flags = size(flag_bits), n_models = size(models), &
                        n_sector_series = size(sector_spec)

  !> the implied-do index of `row` (Fortran wants its type declared)
  integer :: k_row
  !> row(k) = k for the rows of every table: row(0), where findloc found no row of the
  !> name, is out of bounds, so a misspelt name below does not compile
  integer, parameter :: row(*) = [(k_row, k_row=1, max(n_series, n_int_series, n_scalars, &
                                                       n_liner, n_models, n_sector_series))]

  ! The columns kernel code sets its results in, found by name in the tables when compiling:
  ! s_NAME the real series NAME (a row of `series_spec`), si_ the integer series, sc_ the
  ! scalars, l_ the liner film. A result the kernel sets needs its line here.
  !&< (one line a row: not reformatted)
  !> Columns of the real series (`series_spec`).
  integer, parameter, public :: &
    s_crank_angle_deg = row(findloc(series_spec%short, 'crank_angle_deg', dim=1)), &
    s_sliding_speed = row(findloc(series_spec%short, 'sliding_speed', dim=1)), &
    s_h0 = row(findloc(series_spec%short, 'h0', dim=1)), &
    s_lambda_min = row(findloc(series_spec%short, 'lambda_min', dim=1)), &
    s_gas_pressure = row(findloc(series_spec%short, 'gas_pressure', dim=1)), &
    s_applied_load = row(findloc(series_spec%short, 'applied_load', dim=1)), &
    s_hydrodynamic_load = row(findloc(series_spec%short, 'hydrodynamic_load', dim=1)), &
    s_asperity_load = row(findloc(series_spec%short, 'asperity_load', dim=1)), &
    s_viscous_friction = row(findloc(series_spec%short, 'viscous_friction', dim=1)), &
    s_boundary_friction = row(findloc(series_spec%short, 'boundary_friction', dim=1)), &
    s_friction = row(findloc(series_spec%short, 'friction', dim=1)), &
    s_power_loss = row(findloc(series_spec%short, 'power_loss', dim=1)), &
    s_load_residual = row(findloc(series_spec%short, 'load_residual', dim=1)), &
    s_film_temperature = row(findloc(series_spec%short, 'film_temperature', dim=1)), &
    s_inlet_fill = row(findloc(series_spec%short, 'inlet_fill', dim=1)), &
    s_wetted_width = row(findloc(series_spec%short, 'wetted_width', dim=1)), &
    s_oil_left = row(findloc(series_spec%short, 'oil_left', dim=1)), &
    s_oil_bank = row(findloc(series_spec%short, 'oil_bank', dim=1)), &
    s_groove_pressure = row(findloc(series_spec%short, 'groove_pressure', dim=1)), &
    s_land_pressure = row(findloc(series_spec%short, 'land_pressure', dim=1)), &
    s_ring_lift = row(findloc(series_spec%short, 'ring_lift', dim=1)), &
    s_top_gap_flow = row(findloc(series_spec%short, 'top_gap_flow', dim=1)), &
    s_second_gap_flow = row(findloc(series_spec%short, 'second_gap_flow', dim=1)), &
    s_face_flow = row(findloc(series_spec%short, 'face_flow', dim=1))
  !> Columns of the sector series (`sector_spec`).
  integer, parameter, public :: &
    sec_h0 = row(findloc(sector_spec%short, 'sector_h0', dim=1)), &
    sec_load = row(findloc(sector_spec%short, 'sector_load', dim=1))
  !> Columns of the integer series (`int_series_spec`).
  integer, parameter, public :: &
    si_flags = row(findloc(int_series_spec%short, 'flags', dim=1)), &
    si_film_solves = row(findloc(int_series_spec%short, 'film_solves', dim=1))
  !> Columns of the scalars (`scalar_spec`).
  integer, parameter, public :: &
    sc_energy_loss = row(findloc(scalar_spec%short, 'energy_loss', dim=1)), &
    sc_mixed_share = row(findloc(scalar_spec%short, 'mixed_share', dim=1)), &
    sc_ring_mass = row(findloc(scalar_spec%short, 'ring_mass', dim=1)), &
    sc_min_film = row(findloc(scalar_spec%short, 'min_film', dim=1)), &
    sc_max_friction = row(findloc(scalar_spec%short, 'max_friction', dim=1)), &
    sc_converged = row(findloc(scalar_spec%short, 'converged', dim=1)), &
    sc_cycles_run = row(findloc(scalar_spec%short, 'cycles_run', dim=1)), &
    sc_cycle_change = row(findloc(scalar_spec%short, 'cycle_change', dim=1)), &
    sc_energy_change = row(findloc(scalar_spec%short, 'energy_change', dim=1)), &
    sc_liner_change = row(findloc(scalar_spec%short, 'liner_change', dim=1)), &
    sc_ring_pack_change = row(findloc(scalar_spec%short, 'ring_pack_change', dim=1)), &
    sc_sigma = row(findloc(scalar_spec%short, 'sigma', dim=1)), &
    sc_run_time = row(findloc(scalar_spec%short, 'run_time', dim=1)), &
    sc_total_film_solves = row(findloc(scalar_spec%short, 'total_film_solves', dim=1)), &
    sc_reynolds_solves = row(findloc(scalar_spec%short, 'reynolds_solves', dim=1)), &
    sc_cycles_computed = row(findloc(scalar_spec%short, 'cycles_computed', dim=1)), &
    sc_periodic = row(findloc(scalar_spec%short, 'periodic', dim=1)), &
    sc_period = row(findloc(scalar_spec%short, 'period', dim=1)), &
    sc_oil_to_chamber = row(findloc(scalar_spec%short, 'oil_to_chamber', dim=1)), &
    sc_oil_balance_error = row(findloc(scalar_spec%short, 'oil_balance_error', dim=1)), &
    sc_friction_power = row(findloc(scalar_spec%short, 'friction_power', dim=1)), &
    sc_fmep = row(findloc(scalar_spec%short, 'fmep', dim=1)), &
    sc_fmep_bar = row(findloc(scalar_spec%short, 'fmep_bar', dim=1)), &
    sc_displacement = row(findloc(scalar_spec%short, 'displacement', dim=1)), &
    sc_engine_friction_power = row(findloc(scalar_spec%short, 'engine_friction_power', dim=1)), &
    sc_oil_to_chamber_rate = row(findloc(scalar_spec%short, 'oil_to_chamber_rate', dim=1)), &
    sc_flagged_steps = row(findloc(scalar_spec%short, 'flagged_steps', dim=1)), &
    sc_liner_lift_share = row(findloc(scalar_spec%short, 'liner_lift_share', dim=1)), &
    sc_blowby = row(findloc(scalar_spec%short, 'blowby', dim=1)), &
    sc_blowby_mass = row(findloc(scalar_spec%short, 'blowby_mass', dim=1)), &
    sc_blowback_mass = row(findloc(scalar_spec%short, 'blowback_mass', dim=1)), &
    sc_ring_lift_share = row(findloc(scalar_spec%short, 'ring_lift_share', dim=1)), &
    sc_flutter_events = row(findloc(scalar_spec%short, 'flutter_events', dim=1)), &
    sc_gas_balance_error = row(findloc(scalar_spec%short, 'gas_balance_error', dim=1)), &
    sc_gas_exchange = row(findloc(scalar_spec%short, 'gas_exchange', dim=1)), &
    sc_conformability = row(findloc(scalar_spec%short, 'conformability', dim=1)), &
    sc_light_gap_share = row(findloc(scalar_spec%short, 'light_gap_share', dim=1)), &
    sc_face_leakage = row(findloc(scalar_spec%short, 'face_leakage', dim=1)), &
    sc_radial_collapse_share = row(findloc(scalar_spec%short, 'radial_collapse_share', dim=1)), &
    sc_sector_jumps = row(findloc(scalar_spec%short, 'sector_jumps', dim=1)), &
    sc_flutter_margin = row(findloc(scalar_spec%short, 'flutter_margin', dim=1)), &
    sc_flutter_margin_ratio = row(findloc(scalar_spec%short, 'flutter_margin_ratio', dim=1)), &
    sc_lift_margin = row(findloc(scalar_spec%short, 'lift_margin', dim=1)), &
    sc_lift_margin_angle = row(findloc(scalar_spec%short, 'lift_margin_angle', dim=1)), &
    sc_seal_margin = row(findloc(scalar_spec%short, 'seal_margin', dim=1)), &
    sc_seal_margin_angle = row(findloc(scalar_spec%short, 'seal_margin_angle', dim=1)), &
    sc_margin_film_solves = row(findloc(scalar_spec%short, 'margin_film_solves', dim=1)), &
    sc_peak_groove_pressure = row(findloc(scalar_spec%short, 'peak_groove_pressure', dim=1)), &
    sc_peak_groove_angle = row(findloc(scalar_spec%short, 'peak_groove_angle', dim=1)), &
    sc_peak_land_pressure = row(findloc(scalar_spec%short, 'peak_land_pressure', dim=1)), &
    sc_peak_land_angle = row(findloc(scalar_spec%short, 'peak_land_angle', dim=1))
  !> The cycle quantities a period of several cycles reports as the means over them.
  integer, parameter, public :: mean_over_period(*) = [sc_energy_loss, sc_mixed_share, &
    sc_friction_power, sc_fmep, sc_fmep_bar, sc_engine_friction_power, sc_oil_to_chamber, &
    sc_oil_to_chamber_rate, sc_liner_lift_share, &
    sc_blowby, sc_blowby_mass, sc_blowback_mass, sc_ring_lift_share, sc_flutter_events, &
    sc_gas_exchange, sc_light_gap_share, sc_face_leakage, sc_radial_collapse_share, &
    sc_sector_jumps]
  !> Columns of the liner film (`liner_spec`).
  integer, parameter, public :: &
    l_liner_position = row(findloc(liner_spec%short, 'liner_position', dim=1)), &
    l_liner_oil_film = row(findloc(liner_spec%short, 'liner_oil_film', dim=1))
  !> The models (`models`).
  integer, parameter, public :: &
    m_jfo = row(findloc(models%name, 'jfo', dim=1)), &
    m_starved = row(findloc(models%name, 'starved', dim=1)), &
    m_gas = row(findloc(models%name, 'gas', dim=1)), &
    m_distorted = row(findloc(models%name, 'distorted', dim=1)), &
    m_trailing = row(findloc(models%name, 'trailing', dim=1))
  !&>

  !> Results of one run: the reported (last) cycle and its summary, each table's values by
  !> row, in the table's units.
  type :: result_type
    integer :: nsteps = 0
    !> series(k, i): row i of `series_spec` at crank step k
    real(dp), allocatable :: series(:, :)
    !> int_series(k, i): row i of `int_series_spec` at crank step k
    integer, allocatable :: int_series(:, :)
    !> scalars(i): row i of `scalar_spec` in its stored unit; an 'integer' or 'logical' row
    !> holds a whole number (a logical 1 or 0: `truth`, `is_true`)
    real(dp) :: scalars(n_scalars) = 0.0_dp
    !> liner(j, i): row i of `liner_spec` at liner cell j (the liner film at the end of the
    !> reported cycle; no cells without a starved inlet)
    real(dp), allocatable :: liner(:, :)
    !> made(i): the run produced the results that require model i of `models`
    logical :: made(n_models) = .false.
    !> sectors(k, j, i): row i of `sector_spec` at crank step k and sector j (a distorted
    !> bore; no sectors else)
    real(dp), allocatable :: sectors(:, :, :)
    !> a distorted bore's conformability: the orders given and A_k over the limit of each
    integer, allocatable :: conformability_orders(:)
    real(dp), allocatable :: conformability(:)
    !> step_margins(k, i): the branch risk of crank step k (ringlube_load_balance, `margins`):
    !> i = 1 the lift-off margin, 2 the seal margin (huge(1.0_dp) where not measured), 3 the
    !> film solves made for them; the scalars lift_margin and seal_margin are made from them
    real(dp), allocatable :: step_margins(:, :)
  end type result_type

contains

  !> Allocate every series of the tables for m crank steps (zeros) and an empty liner film.
  pure subroutine allocate_result(res, m)
    type(result_type), intent(inout) :: res
    integer, intent(in) :: m
    res%nsteps = m
    if (allocated(res%series)) deallocate (res%series)
    if (allocated(res%int_series)) deallocate (res%int_series)
    allocate (res%series(m, n_series), res%int_series(m, n_int_series))
    res%series = 0.0_dp
    res%int_series = 0
    if (allocated(res%step_margins)) deallocate (res%step_margins)
    allocate (res%step_margins(m, 3))
    res%step_margins(:, 1:2) = huge(1.0_dp)
    res%step_margins(:, 3) = 0.0_dp
    call allocate_liner(res, 0)
    call allocate_sectors(res, 0)
  end subroutine allocate_result

  !> Allocate the sector series for `sectors` sectors (zeros).
  pure subroutine allocate_sectors(res, sectors)
    type(result_type), intent(inout) :: res
    integer, intent(in) :: sectors
    if (allocated(res%sectors)) deallocate (res%sectors)
    allocate (res%sectors(res%nsteps, sectors, n_sector_series))
    res%sectors = 0.0_dp
  end subroutine allocate_sectors

  !> Allocate the liner film for `cells` cells (zeros).
  pure subroutine allocate_liner(res, cells)
    type(result_type), intent(inout) :: res
    integer, intent(in) :: cells
    if (allocated(res%liner)) deallocate (res%liner)
    allocate (res%liner(cells, n_liner))
    res%liner = 0.0_dp
  end subroutine allocate_liner

  !> A logical as a scalar of `result_type` holds it: 1 (true) or 0 (false).
  elemental real(dp) function truth(l)
    logical, intent(in) :: l
    truth = merge(1.0_dp, 0.0_dp, l)
  end function truth

  !> Is the 'logical' scalar i of `res` true?
  pure logical function is_true(res, i)
    type(result_type), intent(in) :: res
    integer, intent(in) :: i
    is_true = res%scalars(i) /= 0.0_dp
  end function is_true

  !> The models whose results the run produced (the `requires` of the rows it has),
  !> blank-separated, e.g. 'jfo starved' ('' when none).
  function produced_models(res) result(t)
    type(result_type), intent(in) :: res
    character(len=:), allocatable :: t
    integer :: i
    t = ''
    do i = 1, n_models
      if (res%made(i)) t = t//' '//trim(models(i)%name)
    end do
    t = trim(adjustl(t))
  end function produced_models

  !> Did the run produce a result that `requires` this model ('' always, an unknown model
  !> never)?
  pure logical function produced(res, requires)
    type(result_type), intent(in) :: res
    character(len=*), intent(in) :: requires
    integer :: i
    produced = len_trim(requires) == 0
    if (produced) return
    i = findloc(models%name, requires, dim=1)
    if (i > 0) produced = res%made(i)
  end function produced

  !> The results engineers quote, from the cycle's (called at the end of a run): mean
  !> friction power [W] (energy per cycle x speed_rpm / 120 cycles per second, four-stroke),
  !> FMEP [kPa, bar] (energy per cycle / swept volume [m^3] of one cylinder), the engine's
  !> displacement [L] and its top rings' friction power [W] (`cylinders` alike, 1 if absent),
  !> the oil to the chamber in g/h (oil_density [kg/m^3]), the count of flagged crank steps
  !> and the share lifted off.
  pure subroutine derive_results(res, speed_rpm, swept_volume, oil_density, cylinders)
    type(result_type), intent(inout) :: res
    real(dp), intent(in) :: speed_rpm, swept_volume, oil_density
    integer, intent(in), optional :: cylinders
    integer :: nc
    nc = 1
    if (present(cylinders)) nc = cylinders
    associate (v => res%scalars)
      v(sc_friction_power) = v(sc_energy_loss) * speed_rpm / 120.0_dp
      v(sc_fmep) = v(sc_energy_loss) / swept_volume * 1e-3_dp
      v(sc_fmep_bar) = v(sc_fmep) * 1e-2_dp
      v(sc_displacement) = nc * swept_volume * 1e3_dp
      v(sc_engine_friction_power) = nc * v(sc_friction_power)
      ! mm^3/cycle x 1e-9 m^3/mm^3 x kg/m^3 x 1e3 g/kg x 30 speed_rpm cycles per hour
      v(sc_oil_to_chamber_rate) = v(sc_oil_to_chamber) * 1e-6_dp * oil_density * 30.0_dp &
                                  * speed_rpm
      if (allocated(res%int_series)) then
        associate (flags => res%int_series(:, si_flags))
          v(sc_flagged_steps) = count(flags /= 0)
          v(sc_liner_lift_share) = 100.0_dp * count(iand(flags, flag_ceiling) /= 0) &
                                   / real(max(size(flags), 1), dp)
        end associate
      end if
    end associate
    call margin_results(res)
  end subroutine derive_results

  !> The run's branch risk from the margins of its crank steps (`step_margins`; docs/model.md,
  !> "Branch risk"):
  !> - lift_margin: the smallest lift-off margin of the cycle (1 if none was measured), at
  !>   lift_margin_angle;
  !> - seal_margin: each stretch of consecutive decision steps (the trailing edge's gas above
  !>   the leading edge's; the cycle is periodic, so a stretch may run over its end) ends in
  !>   a state, sealed (margin > 0) or blown (<= 0), which it has held since its last change:
  !>   the margin of that state over those steps is the one nearest the other state (sealed: the
  !>   smallest, blown: the largest). seal_margin is the smallest of the stretches' margins, at
  !>   seal_margin_angle (1 with no decision step: nothing to decide): < 0 the face ends a
  !>   decision blown (and stays blown unless every such decision changes), > 0 it ends every
  !>   decision sealed (and blows if the weakest changes).
  !> Both are continuous in the inputs while the state is kept and change sign where it changes.
  pure subroutine margin_results(res)
    type(result_type), intent(inout) :: res
    real(dp), parameter :: none = huge(1.0_dp)
    real(dp) :: m, best, ang, best_ang
    integer :: n, k, kk, j0, i
    logical :: live, was_live
    associate (v => res%scalars)
      v(sc_lift_margin) = 1.0_dp
      v(sc_lift_margin_angle) = 0.0_dp
      v(sc_seal_margin) = 1.0_dp
      v(sc_seal_margin_angle) = 0.0_dp
      v(sc_margin_film_solves) = 0.0_dp
      if (.not. allocated(res%step_margins)) return
      n = size(res%step_margins, 1)
      if (n == 0) return
      v(sc_margin_film_solves) = sum(res%step_margins(:, 3))
      k = minloc(res%step_margins(:, 1), dim=1)
      if (res%step_margins(k, 1) < none) then
        v(sc_lift_margin) = res%step_margins(k, 1)
        v(sc_lift_margin_angle) = res%series(k, s_crank_angle_deg)
      end if
      associate (sm => res%step_margins(:, 2))
        ! start after a step without a decision (a stretch over the cycle's end is one)
        j0 = findloc(sm >= none, .true., dim=1)
        if (j0 == 0) j0 = n
        best = none
        best_ang = 0.0_dp
        m = none
        ang = 0.0_dp
        was_live = .false.
        do i = 1, n + 1
          kk = mod(j0 + i - 1, n) + 1
          live = sm(kk) < none .and. i <= n
          if (live) then
            if (.not. was_live .or. (sm(kk) > 0.0_dp .neqv. m > 0.0_dp)) then
              ! a stretch begins, or its state changes: the margin starts again
              m = sm(kk)
              ang = res%series(kk, s_crank_angle_deg)
            else if (abs(sm(kk)) < abs(m)) then
              m = sm(kk)
              ang = res%series(kk, s_crank_angle_deg)
            end if
          else if (was_live) then
            ! the stretch ended: its final state's margin
            if (m < best) then
              best = m
              best_ang = ang
            end if
          end if
          was_live = live
        end do
        if (best < none) then
          v(sc_seal_margin) = best
          v(sc_seal_margin_angle) = best_ang
        end if
      end associate
    end associate
  end subroutine margin_results

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

  !> Percentage of the cycle with lambda = h0/sigma < 4, lambda linear
  !> between crank steps (periodic): a crossing of 4 inside a step counts the part of
  !> the step below it, so the share varies continuously with the inputs instead of in
  !> whole steps.
  pure real(dp) function mixed_share(lam)
    real(dp), intent(in) :: lam(:)
    real(dp) :: a, b, below
    integer :: kk, nn
    nn = size(lam)
    below = 0.0_dp
    do kk = 1, nn
      a = lam(kk)
      b = lam(mod(kk, nn) + 1)
      if (a < 4.0_dp .and. b < 4.0_dp) then
        below = below + 1.0_dp
      else if (a < 4.0_dp .neqv. b < 4.0_dp) then
        below = below + (4.0_dp - min(a, b)) / abs(b - a)
      end if
    end do
    mixed_share = 100.0_dp * below / real(nn, dp)
  end function mixed_share
end module ringlube_results
