!> The one table of every input variable: group, name, kind, default, plausible range,
!> unit and a one-line description; and the numerics presets.
!>
!> This table drives the deck reader (ringlube_deck), the defaults and range checks of a
!> case (ringlube_case), the Python package (exported through the f2py layer) and the
!> input table of docs/model.md (generated from it). A variable is added here and in the
!> storage binding `case_access` of ringlube_case, nowhere else.
module ringlube_inputs
  use ringlube_kinds, only: dp
  implicit none
  private
  public :: input_spec, inputs, n_inputs, find_input, preset_item, presets, n_presets, &
            preset_names, input_key

  !> Kinds of variables.
  integer, parameter, public :: kind_real = 1, kind_int = 2, kind_logical = 3, &
                                kind_string = 4, kind_choice = 5, kind_real_list = 6, &
                                kind_int_list = 7
  !> Most values of a list variable.
  integer, parameter, public :: max_list = 32

  !> One input variable.
  type :: input_spec
    character(len=12) :: group = ''
    character(len=24) :: name = ''
    integer :: kind = kind_real
    !> Default as deck text (parsed by the deck reader's own number reader); for the
    !> numerics a preset sets, '(preset)': the value of preset 'default'.
    character(len=24) :: default = ''
    !> Plausible range [lower, upper] of a number (of each value of a list), inclusive (values
    !> outside are an input error: NaN and infinities never pass).
    real(dp) :: lower = 0.0_dp, upper = 0.0_dp
    character(len=10) :: unit = ''
    !> Allowed values of a choice, separated by '|'.
    character(len=40) :: choices = ''
    character(len=100) :: description = ''
  end type input_spec

  !> Every input variable, in deck order (groups as in docs/model.md "Inputs").
  !&< (a table laid out by hand: not reformatted)
  type(input_spec), parameter :: inputs(*) = [ &
    input_spec('engine', 'crank_radius', kind_real, '31.5e-3', 1e-3_dp, 1.0_dp, 'm', '', &
      'crank radius r'), &
    input_spec('engine', 'conrod_length', kind_real, '107e-3', 2e-3_dp, 5.0_dp, 'm', '', &
      'connecting-rod length l_c (must exceed crank_radius)'), &
    input_spec('engine', 'bore_radius', kind_real, '48e-3', 1e-3_dp, 1.0_dp, 'm', '', &
      'bore radius r0 (ring circumference 2 pi r0)'), &
    input_spec('engine', 'cylinders', kind_int, '1', 1.0_dp, 64.0_dp, '1', '', &
      "cylinders, alike: the engine's totals (friction power, displacement) of its top rings"), &
    input_spec('operating', 'speed_rpm', kind_real, '4000', 1.0_dp, 50000.0_dp, 'r/min', '', &
      'engine speed'), &
    input_spec('operating', 'liner_temperature', kind_real, '348.0', 200.0_dp, 700.0_dp, 'K', '', &
      'liner (film) temperature theta_e'), &
    input_spec('operating', 'liner_temperature_top', kind_real, '0', 0.0_dp, 700.0_dp, 'K', '', &
      "liner temperature where the ring is at TDC, linear to _bottom; 0: liner_temperature"), &
    input_spec('operating', 'liner_temperature_bottom', kind_real, '0', 0.0_dp, 700.0_dp, 'K', '', &
      "liner temperature where the ring is at BDC; 0: liner_temperature"), &
    input_spec('operating', 'pressure_file', kind_string, '', 0.0_dp, 0.0_dp, '', '', &
      'gas-pressure CSV (deg, Pa abs); relative to the deck folder; empty: crankcase pressure'), &
    input_spec('operating', 'crankcase_pressure', kind_real, '101325', 0.0_dp, 1e7_dp, 'Pa', '', &
      'crankcase pressure (absolute)'), &
    input_spec('operating', 'cavitation_pressure', kind_real, '0', 0.0_dp, 1e7_dp, 'Pa', '', &
      'cavitation pressure p_cav (absolute; at most crankcase_pressure)'), &
    input_spec('operating', 'pressure_scale', kind_real, '1', 1e-3_dp, 1e3_dp, '1', '', &
      'factor applied to the gas-pressure trace'), &
    input_spec('ring', 'width', kind_real, '1.004e-3', 1e-5_dp, 0.05_dp, 'm', '', &
      'face width b'), &
    input_spec('ring', 'crown_height', kind_real, '9.31e-6', 0.0_dp, 1e-3_dp, 'm', '', &
      'crown height c of the parabolic face'), &
    input_spec('ring', 'crown_offset', kind_real, '-38.3e-6', -0.025_dp, 0.025_dp, 'm', '', &
      'crown offset x_s (minimum at x = -x_s; |x_s| < b/2)'), &
    input_spec('ring', 'profile', kind_choice, 'edge', 0.0_dp, 0.0_dp, '', 'edge|gauge|table', &
"face profile: crown_height at the edges, drops at gauge_length from the crown, or profile_file"), &
    input_spec('ring', 'gauge_length', kind_real, '502e-6', 1e-6_dp, 0.025_dp, 'm', '', &
      "profile = 'gauge': distance from the crown point at which the drops are given"), &
    input_spec('ring', 'gauge_drop_top', kind_real, '9.31e-6', 0.0_dp, 1e-3_dp, 'm', '', &
      "profile = 'gauge': drop of the face at gauge_length on the chamber (top) side"), &
    input_spec('ring', 'gauge_drop_bottom', kind_real, '9.31e-6', 0.0_dp, 1e-3_dp, 'm', '', &
      "profile = 'gauge': drop of the face at gauge_length on the crankcase (bottom) side"), &
    input_spec('ring', 'profile_file', kind_string, '', 0.0_dp, 0.0_dp, '', '', &
      "profile = 'table': CSV x from the top edge, drop S (m; header may name mm, um)"), &
    input_spec('ring', 'tension', kind_real, '8.0', 0.0_dp, 1e4_dp, '(unit)', '', &
      'ring tension, in the unit given by tension_unit'), &
    input_spec('ring', 'tension_unit', kind_choice, 'N', 0.0_dp, 0.0_dp, '', 'N|N/m', &
      "'N': tangential force F_T, p_e = F_T/(b r0); 'N/m': per circumference, p_e = tension/b"), &
    input_spec('ring', 'radial_depth', kind_real, '3.5e-3', 1e-4_dp, 0.1_dp, 'm', '', &
      'radial depth a of the ring section (below bore_radius)'), &
    input_spec('ring', 'density', kind_real, '7800', 100.0_dp, 30000.0_dp, 'kg/m^3', '', &
      'ring material density'), &
    input_spec('ring', 'lower_ring_distance', kind_real, '0', 0.0_dp, 0.2_dp, 'm', '', &
      'distance to the lower rings: they lay supply_film where z >= -b/2 + this (starved inlet)'), &
    input_spec('lubricant', 'eta0', kind_real, '0.05', 6.4e-5_dp, 100.0_dp, 'Pa s', '', &
      'viscosity at theta0 (above the Roelands reference 6.3e-5 Pa s)'), &
    input_spec('lubricant', 'theta0', kind_real, '313.15', 200.0_dp, 700.0_dp, 'K', '', &
      'reference temperature of eta0'), &
    input_spec('lubricant', 'beta', kind_real, '0.04', 0.0_dp, 1.0_dp, '1/K', '', &
      'viscosity-temperature coefficient'), &
    input_spec('lubricant', 'alpha', kind_real, '1e-8', 0.0_dp, 1e-6_dp, '1/Pa', '', &
      'pressure-viscosity coefficient'), &
    input_spec('lubricant', 'supply_film', kind_real, '1e-6', 0.0_dp, 1e-3_dp, 'm', '', &
      'oil film the lower rings leave on the liner for the top ring (starved inlet)'), &
    input_spec('lubricant', 'oil_density', kind_real, '850', 600.0_dp, 1200.0_dp, 'kg/m^3', '', &
      'oil density: the oil to the chamber in g/h; kv40, kv100 to viscosities (docs/model.md)'), &
    input_spec('lubricant', 'kv40', kind_real, '0', 0.0_dp, 1e5_dp, 'mm^2/s', '', &
  "data sheet: kinematic viscosity at 40 degC (with kv100 replaces eta0, theta0, beta; 0: none)"), &
    input_spec('lubricant', 'kv100', kind_real, '0', 0.0_dp, 1e4_dp, 'mm^2/s', '', &
      'data sheet: kinematic viscosity at 100 degC (with kv40; 0: none)'), &
    input_spec('lubricant', 'grade', kind_string, '', 0.0_dp, 0.0_dp, '', '', &
      "SAE J300 grade, e.g. '5W-30' or '40': kv40 and kv100 of a typical oil (docs/model.md)"), &
    input_spec('surface', 'rq_liner', kind_real, '0.378e-6', 1e-9_dp, 1e-4_dp, 'm', '', &
      'liner roughness Rq'), &
    input_spec('surface', 'rq_ring', kind_real, '0.238e-6', 1e-9_dp, 1e-4_dp, 'm', '', &
      'ring roughness Rq'), &
    input_spec('surface', 'zeta_kappa_sigma', kind_real, '0.04', 1e-4_dp, 1.0_dp, '1', '', &
      'roughness parameter zeta kappa sigma (Greenwood-Tripp)'), &
    input_spec('surface', 'sigma_over_kappa', kind_real, '1e-3', 1e-6_dp, 1.0_dp, '1', '', &
      'sigma/kappa (Greenwood-Tripp)'), &
    input_spec('surface', 'tau0', kind_real, '2e6', 0.0_dp, 1e9_dp, 'Pa', '', &
      'Eyring shear stress of the adsorbed layer'), &
    input_spec('surface', 'boundary_coefficient', kind_real, '0.17', 0.0_dp, 2.0_dp, '1', '', &
      'boundary shear coefficient s'), &
    input_spec('surface', 'e_ring', kind_real, '203e9', 1e8_dp, 1e13_dp, 'Pa', '', &
      "ring Young's modulus"), &
    input_spec('surface', 'nu_ring', kind_real, '0.3', 0.0_dp, 0.4999_dp, '1', '', &
      "ring Poisson's ratio"), &
    input_spec('surface', 'e_liner', kind_real, '400e9', 1e8_dp, 1e13_dp, 'Pa', '', &
      "liner Young's modulus"), &
    input_spec('surface', 'nu_liner', kind_real, '0.3', 0.0_dp, 0.4999_dp, '1', '', &
      "liner Poisson's ratio"), &
    input_spec('physics', 'roelands', kind_logical, '.true.', 0.0_dp, 0.0_dp, '', '', &
      'pressure dependence of viscosity (Roelands); .false.: eta at p = 0'), &
    input_spec('physics', 'squeeze', kind_logical, '.true.', 0.0_dp, 0.0_dp, '', '', &
      'squeeze term 2 dh0/dt in the Reynolds equation'), &
    input_spec('physics', 'asperity_contact', kind_logical, '.true.', 0.0_dp, 0.0_dp, '', '', &
      'Greenwood-Tripp asperity load and boundary friction'), &
    input_spec('physics', 'gt_functions', kind_choice, 'exact', 0.0_dp, 0.0_dp, '', 'exact|fit', &
      'F_2 and F_5/2: exact (tabulated integral) or power-law fits'), &
   input_spec('physics', 'contact_area', kind_choice, 'local', 0.0_dp, 0.0_dp, '', 'local|lumped', &
      'asperity contact with the local lambda(x), or lambda = h0/sigma over the whole face'), &
  input_spec('physics', 'outlet', kind_choice, 'reynolds', 0.0_dp, 0.0_dp, '', 'reynolds|ambient', &
      'trailing edge: Swift-Stieber (Reynolds) exit, or held at its gas pressure'), &
    input_spec('physics', 'cavitation', kind_choice, 'swift_stieber', 0.0_dp, 0.0_dp, '', &
      'swift_stieber|jfo', "film model: Swift-Stieber (the source study) or mass-conserving JFO"), &
    input_spec('physics', 'cavity_pressure', kind_choice, 'vapour', 0.0_dp, 0.0_dp, '', &
      'vapour|trailing_gas', 'cavities at cavitation_pressure, or one reaching the trailing edge at its gas'), &
    input_spec('physics', 'inlet', kind_choice, 'flooded', 0.0_dp, 0.0_dp, '', 'flooded|starved', &
      "leading edge fully flooded, or fed by the liner oil film (needs cavitation = 'jfo')"), &
    input_spec('physics', 'ring_pack', kind_choice, 'none', 0.0_dp, 0.0_dp, '', 'none|gas', &
  "'none': chamber above and behind the ring, crankcase below; 'gas': ring-pack gas (ring_pack.md)"), &
    input_spec('physics', 'bore', kind_choice, 'round', 0.0_dp, 0.0_dp, '', 'round|distorted', &
      "'round': one film for the whole ring; 'distorted': &bore, a film per sector (bore.md)"), &
    input_spec('bore', 'order', kind_int_list, '', 0.0_dp, 64.0_dp, '1', '', &
      'orders k of the distortion D = sum A_k cos(k (theta - phi_k)) (a list)'), &
    input_spec('bore', 'amplitude', kind_real_list, '', 0.0_dp, 1e-3_dp, 'm', '', &
      'amplitude A_k of each order (a list as long as order)'), &
    input_spec('bore', 'phase', kind_real_list, '', -6.2832_dp, 6.2832_dp, 'rad', '', &
      'phase phi_k of each order, in rad (not deg) within one turn (as long as order; none: 0)'), &
    input_spec('bore', 'distortion_file', kind_string, '', 0.0_dp, 0.0_dp, '', '', &
    'CSV z_m, order, amplitude_m, phase_rad (A_k, phi_k along the stroke); instead of the lists'), &
    input_spec('bore', 'sectors', kind_int, '24', 4.0_dp, 360.0_dp, '1', '', &
      'sectors M of the circumference, each with its own film (even; orders up to M/2)'), &
    input_spec('ring_pack', 'gas_temperature', kind_real, '450', 200.0_dp, 2000.0_dp, 'K', '', &
      'temperature of the isothermal gas in the groove and on the second land'), &
    input_spec('ring_pack', 'gamma', kind_real, '1.3', 1.01_dp, 1.67_dp, '1', '', &
      'ratio of specific heats of the gas (end-gap orifice flow)'), &
    input_spec('ring_pack', 'gas_viscosity', kind_real, '2.5e-5', 1e-6_dp, 1e-3_dp, 'Pa s', '', &
      'dynamic viscosity of the gas (groove-flank channels)'), &
    input_spec('ring_pack', 'discharge_coefficient', kind_real, '0.7', 0.05_dp, 1.0_dp, '1', '', &
      'discharge coefficient C_d of the end gaps'), &
    input_spec('ring_pack', 'top_gap_area', kind_real, '1e-7', 0.0_dp, 1e-4_dp, 'm^2', '', &
      'flow area of the top ring end gap'), &
    input_spec('ring_pack', 'second_gap_area', kind_real, '1.5e-7', 0.0_dp, 1e-4_dp, 'm^2', '', &
      'flow area of the second ring end gap'), &
    input_spec('ring_pack', 'groove_clearance', kind_real, '40e-6', 1e-6_dp, 1e-3_dp, 'm', '', &
      'axial clearance c_a of the top ring in its groove'), &
    input_spec('ring_pack', 'groove_volume', kind_real, '1e-7', 0.0_dp, 1e-3_dp, 'm^3', '', &
      'gas volume of the top ring groove (whole circumference); 0: the groove of the ring'), &
    input_spec('ring_pack', 'land_volume', kind_real, '5e-7', 1e-10_dp, 1e-2_dp, 'm^3', '', &
      'gas volume of the second land between the top and second rings'), &
    input_spec('ring_pack', 'back_clearance', kind_real, '0.3e-3', 1e-6_dp, 0.01_dp, 'm', '', &
      "radial clearance behind the ring (the groove's depth); h0 of a ring pushed off the liner"), &
    input_spec('numerics', 'preset', kind_choice, 'default', 0.0_dp, 0.0_dp, '', &
      'fast|default|accurate', 'numerics preset (nodes, crank step, tolerances); explicit values override'), &
    input_spec('numerics', 'nodes', kind_int, '(preset)', 5.0_dp, 20001.0_dp, '1', '', &
      'grid nodes across the ring face'), &
    input_spec('numerics', 'dpsi_deg', kind_real, '(preset)', 0.01_dp, 10.0_dp, 'deg', '', &
      'crank-angle step (must divide 720 deg)'), &
    input_spec('numerics', 'pressure_tol', kind_real, '(preset)', 1e-14_dp, 0.5_dp, '1', '', &
      'pressure-viscosity loop tolerance sum|dp| / sum|p|'), &
    input_spec('numerics', 'load_tol', kind_real, '(preset)', 1e-14_dp, 0.5_dp, '1', '', &
      'load balance tolerance |W_h + W_a - F| / F'), &
    input_spec('numerics', 'time_scheme', kind_choice, 'bdf2', 0.0_dp, 0.0_dp, '', 'bdf2|euler', &
      "squeeze term dh0/dt: BDF2 (second order) or backward Euler (the study's, first order)"), &
    input_spec('numerics', 'film_time_scheme', kind_choice, 'euler', 0.0_dp, 0.0_dp, '', &
      'euler|bdf2', &
      "content theta h of the 'jfo' film and the oil it exchanges: backward Euler or BDF2 (second order)"), &
    input_spec('numerics', 'film_edge_cells', kind_choice, 'face', 0.0_dp, 0.0_dp, '', &
 'face|edge|front', "'jfo' edge volumes: end at the first face, reach the edge, "// &
 "or that + front cells (experimental)"), &
    input_spec('numerics', 'h0_update', kind_choice, 'safeguarded', 0.0_dp, 0.0_dp, '', &
      'safeguarded|damped', "h0 update: safeguarded secant/Brent, or the study's damped rule"), &
    input_spec('numerics', 'damping', kind_real, '0.005', 1e-6_dp, 0.999_dp, '1', '', &
      "beta_d of the damped rule"), &
    input_spec('numerics', 'max_cycles', kind_int, '10', 1.0_dp, 1000.0_dp, '1', '', &
      'cycles at most before the run is reported not converged'), &
    input_spec('numerics', 'cycle_tol', kind_real, '1e-3', 1e-14_dp, 0.5_dp, '1', '', &
      'periodicity tolerance (h0; starved: liner film, energy; the ring pack)'), &
    input_spec('numerics', 'max_load_iterations', kind_int, '2000', 1.0_dp, 1e6_dp, '1', '', &
      'load-balance trials per crank step at most'), &
    input_spec('numerics', 'max_pressure_iterations', kind_int, '100', 1.0_dp, 1e4_dp, '1', '', &
      'pressure-viscosity iterations per film solve at most'), &
    input_spec('numerics', 'h0_floor', kind_real, '1e-9', 1e-12_dp, 1e-4_dp, 'm', '', &
      'lower bound on h0 (a step held there is flagged)'), &
    input_spec('numerics', 'h0_ceiling', kind_real, '1e-3', 1e-8_dp, 0.1_dp, 'm', '', &
      'upper bound on h0 (a step held there is flagged; above 10 h0_floor)'), &
    input_spec('numerics', 'h0_initial', kind_real, '0', 0.0_dp, 0.1_dp, 'm', '', &
      'h0 before the first step; 0: 4 sigma'), &
    input_spec('numerics', 'threads', kind_int, '1', 1.0_dp, 256.0_dp, '1', '', &
      "threads that solve a distorted bore's sectors (OpenMP; 1 per Dask worker)"), &
    input_spec('numerics', 'warmup_deg', kind_real, '90', 0.0_dp, 720.0_dp, 'deg', '', &
      'crank angle solved (not reported) before the first cycle'), &
    input_spec('numerics', 'accelerate', kind_logical, '.true.', 0.0_dp, 0.0_dp, '', '', &
      'extrapolate a slowly settling liner film (starved) toward its periodic state'), &
    input_spec('numerics', 'pilot_cycle', kind_logical, '.false.', 0.0_dp, 0.0_dp, '', '', &
     "start the ring pack under a pilot cycle's friction (8x step, starved 4x; round bore only)"), &
   input_spec('numerics', 'first_restart', kind_choice, 'away', 0.0_dp, 0.0_dp, '', 'away|always', &
      "starved, round bore, liner window: ring pack restarted after cycle 1 only if off its periodic state"), &
    input_spec('numerics', 'bdc_start', kind_logical, '.true.', 0.0_dp, 0.0_dp, '', '', &
      "starved 'vapour', round bore: the warm-up passes its BDC twice ('accurate': off)"), &
    input_spec('numerics', 'liner_window', kind_int, '0', 0.0_dp, 20000.0_dp, '1', '', &
      "starved, round bore: liner change over n cells too (0: 50 with BDC start, 'trailing_gas' periods >1)"), &
    input_spec('output', 'file', kind_string, 'result.h5', 0.0_dp, 0.0_dp, '', '', &
      'result file (relative to the deck folder); -o overrides it'), &
    input_spec('calibration', 'file', kind_string, '', 0.0_dp, 0.0_dp, '', '', &
      'deck of calibrated inputs read as if written here (relative to the deck folder)') &
  ]

  !> One (preset, variable, value) item of a numerics preset.
  type :: preset_item
    character(len=12) :: preset = ''
    character(len=24) :: name = ''
    character(len=12) :: value = ''
  end type preset_item

  !> The numerics presets, chosen from the measured speed/accuracy front
  !> (docs/performance.md). 'default' gives the built-in defaults.
  type(preset_item), parameter :: presets(*) = [ &
    preset_item('fast', 'nodes', '31'), preset_item('fast', 'dpsi_deg', '2.0'), &
    preset_item('fast', 'pressure_tol', '1e-4'), preset_item('fast', 'load_tol', '3e-3'), &
    preset_item('fast', 'bdc_start', '.true.'), &
    preset_item('default', 'nodes', '51'), preset_item('default', 'dpsi_deg', '2.0'), &
    preset_item('default', 'pressure_tol', '1e-5'), preset_item('default', 'load_tol', '1e-3'), &
    preset_item('default', 'bdc_start', '.true.'), &
    preset_item('accurate', 'nodes', '201'), preset_item('accurate', 'dpsi_deg', '0.25'), &
    preset_item('accurate', 'pressure_tol', '1e-6'), preset_item('accurate', 'load_tol', '1e-4'), &
    preset_item('accurate', 'bdc_start', '.false.') &
  ]

  !&>

  !> Number of table rows and of preset items.
  integer, parameter :: n_inputs = size(inputs), n_presets = size(presets)

contains

  !> Names of the presets, separated by '|' (from the choices of &numerics preset).
  pure function preset_names() result(names)
    character(len=:), allocatable :: names
    names = trim(inputs(find_input('numerics', 'preset'))%choices)
  end function preset_names

  !> Index of `&group name` in the table, 0 if there is none.
  pure integer function find_input(group, name) result(idx)
    character(len=*), intent(in) :: group, name
    integer :: i
    idx = 0
    do i = 1, n_inputs
      if (inputs(i)%group == group .and. inputs(i)%name == name) then
        idx = i
        return
      end if
    end do
  end function find_input

  !> 'group.name' of table row i.
  pure function input_key(i) result(key)
    integer, intent(in) :: i
    character(len=:), allocatable :: key
    key = trim(inputs(i)%group)//'.'//trim(inputs(i)%name)
  end function input_key
end module ringlube_inputs
