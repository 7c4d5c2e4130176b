!> Error values returned by the kernel instead of stopping the process.
!>
!> A routine that can fail takes `type(error_type), allocatable, intent(out) :: err`;
!> the caller checks `if (allocated(err)) return`.
module ringlube_error
  implicit none
  private

  !> Exit statuses of `ringlube-solve`, also used as error codes.
  integer, parameter, public :: rl_ok = 0
  integer, parameter, public :: rl_runtime_error = 1
  integer, parameter, public :: rl_input_error = 2
  integer, parameter, public :: rl_not_converged = 3
  !> Stopped by SIGINT (Ctrl-C) during a call from Python (128 + SIGINT, as a shell reports it).
  integer, parameter, public :: rl_interrupted = 130

  !> An error travelling back to the caller.
  type, public :: error_type
    !> One of the `rl_*` codes above.
    integer :: code = rl_runtime_error
    !> Human-readable message (names file, group and variable for input errors).
    character(len=:), allocatable :: message
  end type error_type

  public :: fatal_error, error_status

contains

  !> Create an error with a message and an optional code (default `rl_runtime_error`).
  pure subroutine fatal_error(err, message, code)
    type(error_type), allocatable, intent(out) :: err
    character(len=*), intent(in) :: message
    integer, intent(in), optional :: code
    allocate (err)
    err%message = message
    if (present(code)) err%code = code
  end subroutine fatal_error

  !> The code and message of `err` for a caller that hands them on as plain values
  !> (`rl_ok` and '' when there is no error; the message cut to the length of `message`).
  pure subroutine error_status(err, code, message)
    type(error_type), allocatable, intent(in) :: err
    integer, intent(out) :: code
    character(len=*), intent(out) :: message
    code = rl_ok
    message = ''
    if (.not. allocated(err)) return
    code = err%code
    message = err%message
  end subroutine error_status
end module ringlube_error
