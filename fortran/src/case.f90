!> One ringlube case: every input of SPEC section 9 with its documented default.
module ringlube_case
  use ringlube_kinds, only: dp, pi
  use ringlube_error, only: error_type, fatal_error, rl_input_error
  implicit none
  private
  public :: case_type, validate_case, composite_sigma, reduced_modulus, elastic_pressure, &
    ring_profile, ring_mass, steps_per_cycle

  !> All inputs of one run. Names follow the namelist variables (SPEC section 9).
  type :: case_type
    ! &engine
    real(dp) :: crank_radius = 31.5e-3_dp      !< m
    real(dp) :: conrod_length = 107e-3_dp      !< m
    real(dp) :: bore_radius = 48e-3_dp         !< m (r0)
    ! &operating
    real(dp) :: speed_rpm = 4000.0_dp
    real(dp) :: liner_temperature = 348.0_dp   !< K, film temperature theta_e
    real(dp) :: crankcase_pressure = 101325.0_dp  !< Pa abs
    real(dp) :: cavitation_pressure = 0.0_dp   !< Pa abs
    real(dp) :: pressure_scale = 1.0_dp        !< multiplies the gas-pressure trace
    !> Gas-pressure CSV as resolved against the deck folder; empty: chamber at
    !> crankcase pressure all cycle (no compression, no combustion).
    character(len=:), allocatable :: pressure_file
    ! &ring (defaults: the study's optimum ring, SPEC section 11)
    real(dp) :: width = 1.004e-3_dp            !< m, face width b
    real(dp) :: crown_height = 9.31e-6_dp      !< m, c
    real(dp) :: crown_offset = -38.3e-6_dp     !< m, x_s
    real(dp) :: tension = 8.0_dp               !< N (or N/m, see tension_unit)
    character(len=:), allocatable :: tension_unit  !< 'N' (default) or 'N/m'
    real(dp) :: radial_depth = 3.5e-3_dp       !< m, a
    real(dp) :: density = 7800.0_dp            !< kg/m^3
    ! &lubricant
    real(dp) :: eta0 = 0.05_dp                 !< Pa s at theta0
    real(dp) :: theta0 = 313.15_dp             !< K
    real(dp) :: beta = 0.04_dp                 !< 1/K
    real(dp) :: alpha = 1e-8_dp                !< 1/Pa
    ! &surface
    real(dp) :: rq_liner = 0.378e-6_dp
    real(dp) :: rq_ring = 0.238e-6_dp
    real(dp) :: zeta_kappa_sigma = 0.04_dp
    real(dp) :: sigma_over_kappa = 1e-3_dp
    real(dp) :: tau0 = 2e6_dp
    real(dp) :: boundary_coefficient = 0.17_dp
    real(dp) :: e_ring = 203e9_dp
    real(dp) :: nu_ring = 0.3_dp
    real(dp) :: e_liner = 400e9_dp
    real(dp) :: nu_liner = 0.3_dp
    ! &physics
    logical :: roelands = .true.
    logical :: squeeze = .true.
    logical :: asperity_contact = .true.
    character(len=:), allocatable :: gt_functions   !< 'exact' | 'fit'
    character(len=:), allocatable :: contact_area   !< 'local' | 'lumped'
    character(len=:), allocatable :: outlet         !< 'reynolds' | 'ambient'
    ! &numerics
    integer :: nodes = 51                      !< preset 'default'
    real(dp) :: dpsi_deg = 1.0_dp              !< deg, preset 'default'
    real(dp) :: pressure_tol = 1e-5_dp
    real(dp) :: load_tol = 1e-3_dp
    character(len=:), allocatable :: h0_update      !< 'safeguarded' | 'damped'
    real(dp) :: damping = 0.005_dp
    integer :: max_cycles = 10
    real(dp) :: cycle_tol = 1e-3_dp
    integer :: max_load_iterations = 2000      !< per crank step
    integer :: max_pressure_iterations = 100   !< pressure-viscosity iterations per solve
    real(dp) :: h0_floor = 1e-9_dp             !< m, lower bound on h0 (flagged when hit)
    real(dp) :: h0_ceiling = 1e-3_dp           !< m, upper bound on h0 (flagged when hit)
    real(dp) :: h0_initial = 0.0_dp            !< m, h0 before the first step; 0: 4 sigma
    real(dp) :: warmup_deg = 360.0_dp          !< deg solved (not reported) before cycle 1
    ! &output
    character(len=:), allocatable :: output_file
    ! not namelist variables
    real(dp), allocatable :: gas_psi(:)        !< deg, 0..720, increasing
    real(dp), allocatable :: gas_p(:)          !< Pa abs
    character(len=:), allocatable :: deck_path
    character(len=:), allocatable :: deck_text
  contains
    procedure :: set_string_defaults
  end type case_type

contains

  !> Give the deferred-length strings their defaults (call once after construction).
  pure subroutine set_string_defaults(self)
    class(case_type), intent(inout) :: self
    if (.not. allocated(self%pressure_file)) self%pressure_file = ''
    if (.not. allocated(self%tension_unit)) self%tension_unit = 'N'
    if (.not. allocated(self%gt_functions)) self%gt_functions = 'exact'
    if (.not. allocated(self%contact_area)) self%contact_area = 'local'
    if (.not. allocated(self%outlet)) self%outlet = 'reynolds'
    if (.not. allocated(self%h0_update)) self%h0_update = 'safeguarded'
    if (.not. allocated(self%output_file)) self%output_file = 'result.h5'
    if (.not. allocated(self%deck_path)) self%deck_path = '<memory>'
    if (.not. allocated(self%deck_text)) self%deck_text = ''
  end subroutine set_string_defaults

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

  !> Elastic pressure of the ring on the liner p_e [Pa] (SPEC section 7).
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

  !> Ring mass [kg]: rho 2 pi (r0 - a/2) (a b - int S dx) (SPEC section 8).
  pure real(dp) function ring_mass(c)
    type(case_type), intent(in) :: c
    real(dp) :: hb, area_s
    hb = 0.5_dp * c%width
    area_s = c%crown_height / hb**2 * ((hb + c%crown_offset)**3 - (c%crown_offset - hb)**3) / 3.0_dp
    ring_mass = c%density * 2.0_dp * pi * (c%bore_radius - 0.5_dp * c%radial_depth) &
      * (c%radial_depth * c%width - area_s)
  end function ring_mass

  !> Number of crank steps in one 720 deg cycle.
  pure integer function steps_per_cycle(c)
    type(case_type), intent(in) :: c
    steps_per_cycle = nint(720.0_dp / c%dpsi_deg)
  end function steps_per_cycle

  !> Check every value against its physical range; the message names group and variable.
  subroutine validate_case(c, err)
    type(case_type), intent(in) :: c
    type(error_type), allocatable, intent(out) :: err

    call positive('engine', 'crank_radius', c%crank_radius); if (allocated(err)) return
    call positive('engine', 'conrod_length', c%conrod_length); if (allocated(err)) return
    if (c%conrod_length <= c%crank_radius) then
      call bad('engine', 'conrod_length', 'must exceed crank_radius'); return
    end if
    call positive('engine', 'bore_radius', c%bore_radius); if (allocated(err)) return
    call positive('operating', 'speed_rpm', c%speed_rpm); if (allocated(err)) return
    if (c%liner_temperature <= 138.0_dp) then
      call bad('operating', 'liner_temperature', 'must be above 138 K (Roelands pole)'); return
    end if
    call nonneg('operating', 'crankcase_pressure', c%crankcase_pressure); if (allocated(err)) return
    call nonneg('operating', 'cavitation_pressure', c%cavitation_pressure); if (allocated(err)) return
    call positive('operating', 'pressure_scale', c%pressure_scale); if (allocated(err)) return
    if (c%cavitation_pressure > c%crankcase_pressure) then
      call bad('operating', 'cavitation_pressure', 'must not exceed crankcase_pressure'); return
    end if
    call positive('ring', 'width', c%width); if (allocated(err)) return
    call nonneg('ring', 'crown_height', c%crown_height); if (allocated(err)) return
    if (abs(c%crown_offset) >= 0.5_dp * c%width) then
      call bad('ring', 'crown_offset', 'must lie inside the face, |crown_offset| < width/2'); return
    end if
    call nonneg('ring', 'tension', c%tension); if (allocated(err)) return
    if (c%tension_unit /= 'N' .and. c%tension_unit /= 'N/m') then
      call bad('ring', 'tension_unit', "must be 'N' or 'N/m'"); return
    end if
    call positive('ring', 'radial_depth', c%radial_depth); if (allocated(err)) return
    if (c%radial_depth >= c%bore_radius) then
      call bad('ring', 'radial_depth', 'must be smaller than bore_radius'); return
    end if
    call positive('ring', 'density', c%density); if (allocated(err)) return
    call positive('lubricant', 'eta0', c%eta0); if (allocated(err)) return
    if (log(c%eta0) + 9.67_dp <= 0.0_dp) then
      call bad('lubricant', 'eta0', 'must exceed 6.3e-5 Pa s (Roelands reference 10^-4.2)'); return
    end if
    if (c%theta0 <= 138.0_dp) then
      call bad('lubricant', 'theta0', 'must be above 138 K (Roelands pole)'); return
    end if
    call nonneg('lubricant', 'beta', c%beta); if (allocated(err)) return
    call nonneg('lubricant', 'alpha', c%alpha); if (allocated(err)) return
    call positive('surface', 'rq_liner', c%rq_liner); if (allocated(err)) return
    call positive('surface', 'rq_ring', c%rq_ring); if (allocated(err)) return
    call positive('surface', 'zeta_kappa_sigma', c%zeta_kappa_sigma); if (allocated(err)) return
    call positive('surface', 'sigma_over_kappa', c%sigma_over_kappa); if (allocated(err)) return
    call nonneg('surface', 'tau0', c%tau0); if (allocated(err)) return
    call nonneg('surface', 'boundary_coefficient', c%boundary_coefficient); if (allocated(err)) return
    call positive('surface', 'e_ring', c%e_ring); if (allocated(err)) return
    call positive('surface', 'e_liner', c%e_liner); if (allocated(err)) return
    if (c%nu_ring < 0.0_dp .or. c%nu_ring >= 0.5_dp) then
      call bad('surface', 'nu_ring', 'must be in [0, 0.5)'); return
    end if
    if (c%nu_liner < 0.0_dp .or. c%nu_liner >= 0.5_dp) then
      call bad('surface', 'nu_liner', 'must be in [0, 0.5)'); return
    end if
    if (c%gt_functions /= 'exact' .and. c%gt_functions /= 'fit') then
      call bad('physics', 'gt_functions', "must be 'exact' or 'fit'"); return
    end if
    if (c%contact_area /= 'local' .and. c%contact_area /= 'lumped') then
      call bad('physics', 'contact_area', "must be 'local' or 'lumped'"); return
    end if
    if (c%outlet /= 'reynolds' .and. c%outlet /= 'ambient') then
      call bad('physics', 'outlet', "must be 'reynolds' or 'ambient'"); return
    end if
    if (c%nodes < 5 .or. c%nodes > 100001) then
      call bad('numerics', 'nodes', 'must be between 5 and 100001'); return
    end if
    if (c%dpsi_deg <= 0.0_dp .or. c%dpsi_deg > 10.0_dp) then
      call bad('numerics', 'dpsi_deg', 'must be in (0, 10] deg'); return
    end if
    if (abs(720.0_dp / c%dpsi_deg - nint(720.0_dp / c%dpsi_deg)) > 1e-6_dp) then
      call bad('numerics', 'dpsi_deg', 'must divide 720 deg into a whole number of steps'); return
    end if
    call tol('numerics', 'pressure_tol', c%pressure_tol); if (allocated(err)) return
    call tol('numerics', 'load_tol', c%load_tol); if (allocated(err)) return
    call tol('numerics', 'cycle_tol', c%cycle_tol); if (allocated(err)) return
    if (c%h0_update /= 'safeguarded' .and. c%h0_update /= 'damped') then
      call bad('numerics', 'h0_update', "must be 'safeguarded' or 'damped'"); return
    end if
    if (c%damping <= 0.0_dp .or. c%damping >= 1.0_dp) then
      call bad('numerics', 'damping', 'must be in (0, 1)'); return
    end if
    if (c%max_cycles < 1) then
      call bad('numerics', 'max_cycles', 'must be at least 1'); return
    end if
    if (c%max_load_iterations < 1) then
      call bad('numerics', 'max_load_iterations', 'must be at least 1'); return
    end if
    if (c%max_pressure_iterations < 1) then
      call bad('numerics', 'max_pressure_iterations', 'must be at least 1'); return
    end if
    call positive('numerics', 'h0_floor', c%h0_floor); if (allocated(err)) return
    if (c%h0_ceiling <= 10.0_dp * c%h0_floor) then
      call bad('numerics', 'h0_ceiling', 'must exceed 10 h0_floor'); return
    end if
    call nonneg('numerics', 'h0_initial', c%h0_initial); if (allocated(err)) return
    if (.not. (c%warmup_deg >= 0.0_dp .and. c%warmup_deg <= 720.0_dp)) then
      call bad('numerics', 'warmup_deg', 'must be in [0, 720] deg'); return
    end if
    if (len_trim(c%output_file) == 0) then
      call bad('output', 'file', 'must not be empty'); return
    end if

  contains

    subroutine bad(group, name, why)
      character(len=*), intent(in) :: group, name, why
      call fatal_error(err, trim(c%deck_path) // ': &' // group // ' ' // name // ': ' // why, &
        rl_input_error)
    end subroutine bad

    subroutine positive(group, name, v)
      character(len=*), intent(in) :: group, name
      real(dp), intent(in) :: v
      if (.not. (v > 0.0_dp .and. v < huge(v))) call bad(group, name, 'must be positive and finite')
    end subroutine positive

    subroutine nonneg(group, name, v)
      character(len=*), intent(in) :: group, name
      real(dp), intent(in) :: v
      if (.not. (v >= 0.0_dp .and. v < huge(v))) call bad(group, name, 'must be >= 0 and finite')
    end subroutine nonneg

    subroutine tol(group, name, v)
      character(len=*), intent(in) :: group, name
      real(dp), intent(in) :: v
      if (.not. (v > 0.0_dp .and. v < 1.0_dp)) call bad(group, name, 'must be in (0, 1)')
    end subroutine tol
  end subroutine validate_case
end module ringlube_case
