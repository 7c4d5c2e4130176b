!> Where a result may be written: the output-path checks of `ringlube-solve` and of the
!> f2py runs.
!>
!> `check_output` refuses an output that is one of the run's inputs (compared by device
!> and inode, so other spellings and links count), anything that exists and is not a
!> regular file (a folder, a device such as /dev/null, a pipe), a symbolic link, and a path
!> whose folder does not exist: all input errors (exit status 2).
module ringlube_output_path
  use ringlube_error, only: error_type, fatal_error, rl_input_error
  use ringlube_fsys, only: file_kind, is_symlink, same_file, dir_name, last_errno, clear_errno, errno_text, &
                           fs_missing, fs_regular, fs_directory, fs_other, fs_unknown
  implicit none
  private
  public :: check_output

contains

  !> Refuse an output path that would destroy something: one of the run's `inputs`
  !> (same device and inode; `labels(i)` names input i in the message, e.g. "the deck"),
  !> an existing non-regular file (folder, device, pipe, socket), a path in a folder that
  !> does not exist, or an empty name. Blank entries of `inputs` are skipped. Errors are
  !> input errors (exit status 2) and name the output and the reason. An existing regular
  !> file is replaced; a symbolic link is refused, as for every file ringlube writes
  !> (`ringlube.outputs.check_output`; before 2026-11-26 the link was replaced).
  subroutine check_output(path, inputs, labels, err)
    character(len=*), intent(in) :: path
    character(len=*), intent(in) :: inputs(:), labels(:)
    type(error_type), allocatable, intent(out) :: err
    character(len=:), allocatable :: d
    integer :: i, kind, e

    if (len_trim(path) == 0) then
      call fatal_error(err, 'the output file name is empty', rl_input_error)
      return
    end if
    if (path(len(path):len(path)) == '/') then
      call fatal_error(err, path//': output names a folder, not a file', rl_input_error)
      return
    end if
    if (is_symlink(path)) then
      call fatal_error(err, path//': output is a symbolic link; refusing to write through it '// &
                       '(remove it first)', rl_input_error)
      return
    end if
    call clear_errno()
    kind = file_kind(path)
    e = last_errno()
    select case (kind)
    case (fs_missing)
      d = dir_name(path)
      select case (file_kind(d))
      case (fs_directory)
      case (fs_missing)
        call fatal_error(err, path//': output folder '//d//' does not exist', &
                         rl_input_error)
      case (fs_unknown)
        call fatal_error(err, path//': output folder '//d//' cannot be used: '// &
                         errno_text(last_errno()), rl_input_error)
      case default
        call fatal_error(err, path//': '//d//' is not a folder', rl_input_error)
      end select
    case (fs_regular)
      do i = 1, size(inputs)
        if (len_trim(inputs(i)) == 0) cycle
        if (same_file(path, trim(inputs(i)))) then
          call fatal_error(err, path//': output is '//trim(labels(min(i, size(labels)))) &
                           //' '//trim(inputs(i))//' of this run; refusing to overwrite an input', &
                           rl_input_error)
          return
        end if
      end do
    case (fs_directory)
      call fatal_error(err, path//': output is a folder, not a file', rl_input_error)
    case (fs_other)
      call fatal_error(err, path//': output exists and is not a regular file '// &
                       '(a device, pipe or socket); refusing to replace it', rl_input_error)
    case default
      call fatal_error(err, path//': cannot use as output: '//errno_text(e), rl_input_error)
    end select
  end subroutine check_output
end module ringlube_output_path
