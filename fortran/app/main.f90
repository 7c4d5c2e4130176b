!> ringlube-solve: one engine cycle of the top compression ring from a namelist deck.
!>
!> Usage: ringlube-solve CASE.nml [-o OUT.h5] [-q]
!> Exit status: 0 success, 1 runtime error (e.g. output not writable, disk full), 2 bad
!> input (including an unsafe output: one of the run's inputs, a folder, a device, or a
!> path in a folder that does not exist; checked before the run), 3 run did not converge
!> (the result is still written, with converged = 0).
!> With `&numerics threads` > 1 (a distorted bore's sectors in OpenMP threads) set
!> OMP_WAIT_POLICY=PASSIVE in the environment: libgomp reads it when the program starts, and
!> with its default a waiting thread spins and takes a core from the ones with work (the
!> Python package sets it itself; docs/bore.md, "Cost").
program ringlube_solve
  use ringlube_kinds, only: dp
  use ringlube_error, only: error_type, rl_input_error, rl_not_converged, rl_runtime_error
  use ringlube_case, only: case_type, composite_sigma
  use ringlube_deck, only: read_deck
  use ringlube_cycle, only: solve_cycle
  use ringlube_ring_pack_cycle, only: ring_pack_check
  use ringlube_results, only: result_type, produced, scalar_spec, n_scalars, is_true, &
                              sc_run_time, sc_converged
  use ringlube_results_summary, only: summary_text
  use ringlube_hdf5_output, only: write_result
  use ringlube_output_path, only: check_output
  use ringlube_version, only: package_version
  use ringlube_kernel_id, only: kernel_id
  use ringlube_fsys, only: ignore_file_size_signal, remove_temp_on_signal, progress_enable
  use, intrinsic :: iso_fortran_env, only: error_unit, output_unit, int64
  implicit none
  type(case_type) :: c
  type(result_type) :: res
  type(error_type), allocatable :: err
  character(len=:), allocatable :: deck, out, summary
  character(len=4096), allocatable :: inputs(:)
  !> what each of `inputs` is, for messages
  character(len=*), parameter :: input_labels(5) = [character(len=20) :: &
                                                    'the deck', 'the pressure file', &
                                                    'the calibration file', 'the profile file', &
                                                    'the distortion file']
  character(len=4096) :: arg
  integer :: i, nargs
  logical :: made(n_scalars)
  integer(int64) :: t0, t1, rate
  real(dp) :: runtime
  logical :: quiet

  ! over the file-size limit a write fails (exit 1, temporary file removed), as on a full
  ! disk, instead of the process being killed by SIGXFSZ
  call ignore_file_size_signal()
  ! Ctrl-C or kill while the result is being written leaves no temporary file
  call remove_temp_on_signal()
  quiet = .false.
  nargs = command_argument_count()
  i = 1
  do while (i <= nargs)
    call get_command_argument(i, arg)
    select case (trim(arg))
    case ('-h', '--help')
      call usage(output_unit)
      stop
    case ('--version')
      write (output_unit, '(a)') 'ringlube-solve '//package_version//' (kernel '//kernel_id//')'
      stop
    case ('-q', '--quiet')
      quiet = .true.
    case ('-o', '--output')
      if (i == nargs) call die('option -o needs a file name', rl_input_error)
      i = i + 1
      call get_command_argument(i, arg)
      out = trim(arg)
    case default
      if (arg(1:1) == '-') call die('unknown option '//trim(arg), rl_input_error)
      if (allocated(deck)) call die('only one deck can be given', rl_input_error)
      deck = trim(arg)
    end select
    i = i + 1
  end do
  if (.not. allocated(deck)) then
    call usage(error_unit)
    stop rl_input_error, quiet = .true.
  end if

  call read_deck(deck, c, err)
  if (allocated(err)) call die(err%message, err%code)
  if (len(c%notes) > 0) write (error_unit, '(a)') 'ringlube-solve: warning: '//c%notes
  if (.not. allocated(out)) out = c%output_file
  ! refuse an unsafe output before spending time on the run
  inputs = [character(len=4096) :: deck, c%pressure_file, c%calibration_file, c%profile_file, &
            c%distortion_file]
  call check_output(out, inputs, input_labels, err)
  if (allocated(err)) call die(err%message, err%code)
  ! the file records where it was written (-o, else the deck's &output file)
  c%output_file = out

  ! a line on the terminal (standard error) says where a run of more than a few seconds is
  call progress_enable(.not. quiet)
  call system_clock(t0, rate)
  call solve_cycle(c, res, err)
  call system_clock(t1)
  if (.not. allocated(err)) call ring_pack_check(c, res%scalars, err)
  if (allocated(err)) call die(err%message, err%code)
  runtime = real(t1 - t0, dp) / real(rate, dp)
  res%scalars(sc_run_time) = runtime

  call write_result(out, c, res, err, inputs, input_labels)
  if (allocated(err)) call die(err%message, err%code)

  if (.not. quiet) then
    do i = 1, n_scalars
      made(i) = produced(res, scalar_spec(i)%requires)
    end do
    if (allocated(res%conformability)) then
      summary = summary_text(res%scalars, made, 'ringlube '//package_version//': '//deck, out, &
                             res%conformability_orders, res%conformability)
    else
      summary = summary_text(res%scalars, made, 'ringlube '//package_version//': '//deck, out)
    end if
    write (output_unit, '(a)', advance='no') summary
  end if
  if (.not. is_true(res, sc_converged)) then
    write (error_unit, '(a)') 'ringlube-solve: warning: the run did not converge; '// &
      'result written with converged = 0'
    stop rl_not_converged, quiet = .true.
  end if

contains

  subroutine usage(unit)
    integer, intent(in) :: unit
    write (unit, '(a)') 'usage: ringlube-solve CASE.nml [-o OUT.h5] [-q]'
    write (unit, '(a)') '  Computes one engine cycle of the top compression ring (see README.md).'
    write (unit, '(a)') '  exit status: 0 ok, 1 runtime error (e.g. disk full), 2 bad input'
    write (unit, '(a)') '  (also an output that is an input, a folder, a device or in a missing'
    write (unit, '(a)') '  folder),'
    write (unit, '(a)') '  3 not converged (result written with converged = 0)'
write (unit, '(a)') '  with &numerics threads > 1: set OMP_WAIT_POLICY=PASSIVE (docs/bore.md, Cost)'
  end subroutine usage

  subroutine die(msg, code)
    character(len=*), intent(in) :: msg
    integer, intent(in) :: code
    write (error_unit, '(a)') 'ringlube-solve: error: '//msg
    select case (code)
    case (rl_input_error)
      stop rl_input_error, quiet = .true.
    case (rl_not_converged)
      stop rl_not_converged, quiet = .true.
    case default
      stop rl_runtime_error, quiet = .true.
    end select
  end subroutine die
end program ringlube_solve
