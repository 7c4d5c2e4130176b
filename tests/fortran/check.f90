!> Minimal assertion helpers for the ctest programs.
module ringlube_check
  use ringlube_kinds, only: dp
  implicit none
  private
  public :: check, check_close, report
  integer, save :: nfail = 0, npass = 0

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

  !> Print the tally and stop with status 1 on any failure.
  subroutine report(name)
    character(len=*), intent(in) :: name
    write (*, '(a, i0, a, i0, a)') name//': ', npass, ' passed, ', nfail, ' failed'
    if (nfail > 0) stop 1
  end subroutine report
end module ringlube_check
