!> Minimal assertion helpers for the ctest programs, and case selection: a test program
!> guards each case with `if (run_case('name')) call name()`; run without arguments it runs
!> every case, run as `test_x name` only that one (tests/fortran/tests.cmake registers one
!> ctest `x/name` per `run_case('name')` it finds in the source).
module ringlube_check
  use ringlube_kinds, only: dp
  implicit none
  private
  public :: check, check_close, report, run_case
  integer, save :: nfail = 0, npass = 0
  !> cases selected so far; the case asked for on the command line ('' = all)
  integer, save :: nselected = 0
  character(len=:), allocatable, save :: wanted

contains

  subroutine check(cond, what)
    logical, intent(in) :: cond
    character(len=*), intent(in) :: what
    if (cond) then
      npass = npass + 1
    else
      nfail = nfail + 1
      write (*, '(a)') 'FAIL: '//what
    end if
  end subroutine check

  !> |a - b| <= rtol |b| + atol
  subroutine check_close(a, b, rtol, what, atol)
    real(dp), intent(in) :: a, b, rtol
    character(len=*), intent(in) :: what
    real(dp), intent(in), optional :: atol
    real(dp) :: at
    at = 0.0_dp
    if (present(atol)) at = atol
    if (abs(a - b) <= rtol * abs(b) + at) then
      npass = npass + 1
    else
      nfail = nfail + 1
      write (*, '(a, 2es24.15, a, es10.2)') 'FAIL: '//what//': got, expected ', a, b, &
        ' rel err ', abs(a - b) / max(abs(b), tiny(1.0_dp))
    end if
  end subroutine check_close

  !> Whether to run the case `name`: every case when the program has no argument, else only
  !> the one its first argument names.
  logical function run_case(name)
    character(len=*), intent(in) :: name
    integer :: n
    if (.not. allocated(wanted)) then
      call get_command_argument(1, length=n)
      allocate (character(len=n) :: wanted)
      if (n > 0) call get_command_argument(1, wanted)
    end if
    run_case = len(wanted) == 0 .or. wanted == name
    if (run_case) nselected = nselected + 1
    if (run_case .and. len(wanted) > 0) write (*, '(a)') 'case '//name
  end function run_case

  !> Print the tally and stop with status 1 on any failure, when no check ran, or when the
  !> case asked for on the command line does not exist.
  subroutine report(name)
    character(len=*), intent(in) :: name
    if (allocated(wanted)) then
      if (len(wanted) > 0 .and. nselected == 0) then
        write (*, '(a)') 'FAIL: '//name//' has no case named '//wanted
        stop 1
      end if
    end if
    if (npass + nfail == 0) then
      write (*, '(a)') 'FAIL: '//name//': no check ran'
      stop 1
    end if
    write (*, '(a, i0, a, i0, a)') name//': ', npass, ' passed, ', nfail, ' failed'
    if (nfail > 0) stop 1
  end subroutine report
end module ringlube_check
