!> The writer's helpers: UTF-8 cleaning, the file-system questions (fsys), the output
!> checks, unique temporary names, and (with the argument `signal`) removal of the
!> temporary file when the program is terminated while writing.
program test_hdf5_output
  use, intrinsic :: iso_c_binding, only: c_int
  use ringlube_textio, only: utf8_clean
  use ringlube_fsys, only: file_kind, same_file, make_temp_file, remove_file, dir_name, &
                           dir_prefix, remove_temp_on_signal, fs_missing, fs_regular, &
                           fs_directory, fs_other
  use ringlube_error, only: error_type, rl_input_error
  use ringlube_output_path, only: check_output
  use ringlube_check
  implicit none
  interface
    integer(c_int) function c_raise(sig) bind(c, name='raise')
      import :: c_int
      integer(c_int), value :: sig
    end function c_raise
  end interface
  character(len=3), parameter :: fffd = char(239)//char(191)//char(189)
  character(len=:), allocatable :: a, b, t1, s
  character(len=256) :: arg
  type(error_type), allocatable :: err
  integer :: code

  ! `test_hdf5_output signal BASE`: make a temporary file for BASE, print its name, and
  ! be terminated by SIGTERM (the calling script checks that the file is gone)
  if (command_argument_count() == 2) then
    call get_command_argument(2, arg)
    call remove_temp_on_signal()
    call make_temp_file(trim(arg), t1, code)
    write (*, '(a)') t1
    flush (6)
    code = c_raise(15_c_int)
    stop 0   ! not reached
  end if

  ! --- utf8_clean: valid text unchanged, each bad byte one U+FFFD ---
  call check(utf8_clean('plain ASCII, 1e-3') == 'plain ASCII, 1e-3', 'ascii unchanged')
  s = 'caf'//char(195)//char(169)//' '//char(226)//char(128)//char(148)//' '// &
      char(240)//char(159)//char(152)//char(128)      ! é, em dash, a 4-byte emoji
  call check(utf8_clean(s) == s, 'valid multi-byte UTF-8 unchanged')
  call check(utf8_clean('Stra'//char(223)//'e') == 'Stra'//fffd//'e', 'Latin-1 byte replaced')
  call check(utf8_clean('a'//char(0)//'b') == 'a'//fffd//'b', 'NUL replaced')
  call check(utf8_clean(char(195)) == fffd, 'truncated sequence at the end')
  call check(utf8_clean(char(195)//'x') == fffd//'x', 'lead byte without continuation')
  call check(utf8_clean(char(192)//char(175)) == fffd//fffd, 'overlong encoding (C0 AF)')
  call check(utf8_clean(char(237)//char(160)//char(128)) == fffd//fffd//fffd, &
             'UTF-16 surrogate (ED A0 80)')
  call check(utf8_clean(char(244)//char(144)//char(128)//char(128)) == &
             fffd//fffd//fffd//fffd, 'beyond U+10FFFF (F4 90 80 80)')
  call check(utf8_clean(char(128)) == fffd, 'lone continuation byte')
  call check(utf8_clean('') == '', 'empty')

  ! --- dir_name ---
  call check(dir_name('out.h5') == '.', 'dir_name bare')
  call check(dir_name('a/b/out.h5') == 'a/b', 'dir_name relative')
  call check(dir_name('/out.h5') == '/', 'dir_name root')
  call check(dir_prefix('out.h5') == '', 'dir_prefix bare')
  call check(dir_prefix('a/b/out.h5') == 'a/b/', 'dir_prefix relative')
  call check(dir_prefix('/out.h5') == '/', 'dir_prefix root')

  ! --- file_kind, same_file ---
  call make_temp_file('test_hdf5_output.tmp', a, code)
  call check(code == 0, 'make_temp_file')
  call check(file_kind(a) == fs_regular, 'file_kind regular')
  call check(file_kind('.') == fs_directory, 'file_kind folder')
  call check(file_kind('/dev/null') == fs_other, 'file_kind device')
  call check(file_kind('no/such/file') == fs_missing, 'file_kind missing')
  call check(same_file(a, './'//a), 'same_file by another spelling')
  call make_temp_file('test_hdf5_output.tmp', b, code)
  call check(code == 0 .and. a /= b, 'two temporary names differ')
  call check(index(a, 'test_hdf5_output.tmp.') == 1 .and. a(len(a) - 4:) == '.part', &
             'temporary name is BASE.<pid>.<random>.part: '//a)
  call check(.not. same_file(a, b), 'different files are not the same')
  call check(.not. same_file(a, 'no/such/file'), 'missing file is not the same')

  ! --- check_output ---
  call check_output(a, [character(len=64) :: 'x.nml', './'//a], &
                    [character(len=24) :: 'the deck', 'the pressure file'], err)
  call check(allocated(err), 'output that is an input refused')
  if (allocated(err)) then
    call check(err%code == rl_input_error .and. index(err%message, 'the pressure file') > 0, &
               'refusal names the input: '//err%message)
  end if
  call check_output(a, [character(len=64) :: 'x.nml'], [character(len=16) :: 'the deck'], err)
  call check(.not. allocated(err), 'existing regular file that is not an input accepted')
  call check_output('new.h5', [character(len=64) :: a], [character(len=16) :: 'the deck'], err)
  call check(.not. allocated(err), 'new file in an existing folder accepted')
  call check_output('/dev/null', [character(len=1) :: ''], [character(len=1) :: ''], err)
  call check(allocated(err), '/dev/null refused')
  call check_output('.', [character(len=1) :: ''], [character(len=1) :: ''], err)
  call check(allocated(err), 'folder refused')
  call check_output('no/such/x.h5', [character(len=1) :: ''], [character(len=1) :: ''], err)
  call check(allocated(err), 'missing folder refused')
  if (allocated(err)) call check(index(err%message, 'no/such') > 0, 'names the folder')

  ! --- remove_file ---
  call remove_file(a)
  call remove_file(b)
  call check(file_kind(a) == fs_missing .and. file_kind(b) == fs_missing, 'remove_file')
  call remove_file(a)   ! no error when missing
  call report('test_hdf5_output')
end program test_hdf5_output
