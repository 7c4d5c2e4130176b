!> An engine oil from its SAE J300 grade: the kinematic viscosities at 40 and 100 degC that
!> the kernel's viscosity law is put through (ringlube_case, validate_case).
!>
!> A grade fixes the kinematic viscosity at 100 degC only to a window (SAE J300, 2015): a
!> grade gives the window's centre. The viscosity at 40 degC follows from a viscosity index
!> (ASTM D2270, procedure B, with H of its table 1 at the window's centre): 160 for a
!> multigrade ('5W-30'), 100 for a straight grade ('30'), as docs/model.md explains. An oil's
!> data sheet (kv40, kv100) replaces both.
module ringlube_oil
  use ringlube_kinds, only: dp
  implicit none
  private
  public :: grade_viscosities

  !> Temperatures of a data sheet's kinematic viscosities [K].
  real(dp), parameter, public :: theta40 = 313.15_dp, theta100 = 373.15_dp
  !> Viscosity indices assumed for a grade's kinematic viscosity at 40 degC.
  real(dp), parameter, public :: vi_multigrade = 160.0_dp, vi_straight = 100.0_dp

  !> A high-temperature grade of SAE J300: its window of kinematic viscosity at 100 degC
  !> [mm^2/s] (min, below max) and H of ASTM D2270 table 1 at the window's centre [mm^2/s]
  !> (the kinematic viscosity at 40 degC of an oil of viscosity index 100 with the centre's
  !> at 100 degC).
  type :: j300_grade
    integer :: number = 0
    real(dp) :: kv100_min = 0.0_dp, kv100_max = 0.0_dp, h = 0.0_dp
  end type j300_grade

  !&< (a table laid out by hand: not reformatted)
  type(j300_grade), parameter :: grades(*) = [ &
    j300_grade(20, 6.9_dp, 9.3_dp, 60.74_dp), &     ! centre 8.1
    j300_grade(30, 9.3_dp, 12.5_dp, 93.92_dp), &    ! centre 10.9
    j300_grade(40, 12.5_dp, 16.3_dp, 141.0_dp), &   ! centre 14.4
    j300_grade(50, 16.3_dp, 21.9_dp, 214.4_dp), &   ! centre 19.1
    j300_grade(60, 21.9_dp, 26.1_dp, 301.8_dp) &    ! centre 24.0
  ]
  !&>
  !> The low-temperature (W) grades of SAE J300.
  integer, parameter :: w_grades(*) = [0, 5, 10, 15, 20, 25]

contains

  !> The kinematic viscosities [mm^2/s] at 40 and 100 degC of a grade 'xW-yy' or 'yy'
  !> (case and blanks ignored); `why` set for a name that is not a J300 grade. `kv100_min`
  !> and `kv100_max` are the grade's window at 100 degC.
  pure subroutine grade_viscosities(name, kv40, kv100, why, kv100_min, kv100_max)
    character(len=*), intent(in) :: name
    real(dp), intent(out) :: kv40, kv100
    character(len=:), allocatable, intent(out) :: why
    real(dp), intent(out), optional :: kv100_min, kv100_max
    character(len=:), allocatable :: g, hot, cold
    integer :: k, i, n, w
    real(dp) :: vi, expo
    kv40 = 0.0_dp
    kv100 = 0.0_dp
    g = upper(name)
    k = index(g, '-')
    if (k > 0) then
      cold = g(1:k - 1)
      hot = g(k + 1:)
    else
      cold = ''
      hot = g
    end if
    n = whole(hot)
    i = findloc(grades%number, n, dim=1)
    if (len(cold) > 0) then
      w = -1
      if (len(cold) >= 2) then
        if (cold(len(cold):) == 'W') w = whole(cold(1:len(cold) - 1))
      end if
      if (findloc(w_grades, w, dim=1) == 0) i = 0
    end if
    if (i == 0) then
      why = "'"//name//"' is not an SAE J300 engine-oil grade: 'xW-yy' or 'yy' with x 0, 5, "// &
            '10, 15, 20 or 25 and yy 20, 30, 40, 50 or 60'
      return
    end if
    vi = vi_straight
    if (len(cold) > 0) vi = vi_multigrade
    kv100 = 0.5_dp * (grades(i)%kv100_min + grades(i)%kv100_max)
    ! ASTM D2270 procedure B: VI = (10^N - 1)/0.00715 + 100, N = (log H - log U)/log Y
    expo = log10(1.0_dp + 0.00715_dp * (vi - 100.0_dp))
    kv40 = grades(i)%h / kv100**expo
    if (present(kv100_min)) kv100_min = grades(i)%kv100_min
    if (present(kv100_max)) kv100_max = grades(i)%kv100_max
  end subroutine grade_viscosities

  !> Upper case without blanks.
  pure function upper(t) result(u)
    character(len=*), intent(in) :: t
    character(len=:), allocatable :: u
    integer :: j
    u = ''
    do j = 1, len(t)
      if (t(j:j) == ' ') cycle
      if (t(j:j) >= 'a' .and. t(j:j) <= 'z') then
        u = u//achar(iachar(t(j:j)) - 32)
      else
        u = u//t(j:j)
      end if
    end do
  end function upper

  !> A whole number written with digits only (-1 otherwise).
  pure integer function whole(t) result(n)
    character(len=*), intent(in) :: t
    integer :: j
    n = -1
    if (len(t) == 0 .or. len(t) > 3) return
    if (verify(t, '0123456789') /= 0) return
    n = 0
    do j = 1, len(t)
      n = 10 * n + (iachar(t(j:j)) - iachar('0'))
    end do
  end function whole
end module ringlube_oil
