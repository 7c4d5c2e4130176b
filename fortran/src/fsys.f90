!> File-system questions Fortran cannot ask portably (stat, O_EXCL creation, errno text),
!> answered by the small C file fsys.c.
module ringlube_fsys
  use, intrinsic :: iso_c_binding, only: c_int, c_char, c_null_char, c_double
  implicit none
  private
  public :: file_kind, is_symlink, same_file, make_temp_file, rename_file, remove_file, dir_name, &
            dir_prefix, last_errno, clear_errno, errno_text, ignore_file_size_signal, &
            remove_temp_on_signal, interrupt_catch_begin, interrupt_catch_end, &
            interrupt_requested, progress_enable, progress_begin, progress_cycle, progress_step, &
            progress_end

  !> What `file_kind` returns.
  integer, parameter, public :: fs_missing = 0, fs_regular = 1, fs_directory = 2, &
                                fs_other = 3, fs_unknown = -1

  interface
    integer(c_int) function c_file_kind(path) bind(c, name='rl_file_kind')
      import :: c_int, c_char
      character(kind=c_char), intent(in) :: path(*)
    end function c_file_kind
    integer(c_int) function c_is_symlink(path) bind(c, name='rl_is_symlink')
      import :: c_int, c_char
      character(kind=c_char), intent(in) :: path(*)
    end function c_is_symlink
    integer(c_int) function c_same_file(a, b) bind(c, name='rl_same_file')
      import :: c_int, c_char
      character(kind=c_char), intent(in) :: a(*), b(*)
    end function c_same_file
    integer(c_int) function c_make_temp(base, out, outlen) bind(c, name='rl_make_temp')
      import :: c_int, c_char
      character(kind=c_char), intent(in) :: base(*)
      character(kind=c_char), intent(out) :: out(*)
      integer(c_int), value :: outlen
    end function c_make_temp
    integer(c_int) function c_errno() bind(c, name='rl_errno')
      import :: c_int
    end function c_errno
    subroutine c_clear_errno() bind(c, name='rl_clear_errno')
    end subroutine c_clear_errno
    subroutine c_strerror(code, out, outlen) bind(c, name='rl_strerror')
      import :: c_int, c_char
      integer(c_int), value :: code, outlen
      character(kind=c_char), intent(out) :: out(*)
    end subroutine c_strerror
    !> Catch SIGINT until the matching interrupt_catch_end (calls from Python; fsys.c).
    subroutine interrupt_catch_begin() bind(c, name='rl_interrupt_catch_begin')
    end subroutine interrupt_catch_begin
    integer(c_int) function c_interrupt_catch_end() bind(c, name='rl_interrupt_catch_end')
      import :: c_int
    end function c_interrupt_catch_end
    integer(c_int) function c_interrupt_requested() bind(c, name='rl_interrupt_requested')
      import :: c_int
    end function c_interrupt_requested
    subroutine remove_temp_on_signal() bind(c, name='rl_remove_temp_on_signal')
    end subroutine remove_temp_on_signal
    subroutine c_forget_temp(path) bind(c, name='rl_forget_temp')
      import :: c_char
      character(kind=c_char), intent(in) :: path(*)
    end subroutine c_forget_temp
    subroutine ignore_file_size_signal() bind(c, name='rl_ignore_sigxfsz')
    end subroutine ignore_file_size_signal
    subroutine c_progress_enable(on) bind(c, name='rl_progress_enable')
      import :: c_int
      integer(c_int), value :: on
    end subroutine c_progress_enable
    subroutine c_progress_begin(max_cycles) bind(c, name='rl_progress_begin')
      import :: c_int
      integer(c_int), value :: max_cycles
    end subroutine c_progress_begin
    subroutine c_progress_cycle(icycle) bind(c, name='rl_progress_cycle')
      import :: c_int
      integer(c_int), value :: icycle
    end subroutine c_progress_cycle
    subroutine c_progress_step(psi) bind(c, name='rl_progress_step')
      import :: c_double
      real(c_double), value :: psi
    end subroutine c_progress_step
    !> The run ends: the progress line, if shown, is cleared (fsys.c).
    subroutine progress_end() bind(c, name='rl_progress_end')
    end subroutine progress_end
    integer(c_int) function c_rename(old, new) bind(c, name='rename')
      import :: c_int, c_char
      character(kind=c_char), intent(in) :: old(*), new(*)
    end function c_rename
    integer(c_int) function c_unlink(path) bind(c, name='unlink')
      import :: c_int, c_char
      character(kind=c_char), intent(in) :: path(*)
    end function c_unlink
  end interface

contains

  !> Ask for a progress line on standard error (a terminal only) in the runs that follow, or
  !> not (fsys.c: the line, its timing and cost).
  subroutine progress_enable(on)
    logical, intent(in) :: on
    integer(c_int) :: flag
    flag = 0
    if (on) flag = 1
    call c_progress_enable(flag)
  end subroutine progress_enable

  !> A run of at most max_cycles cycles begins.
  subroutine progress_begin(max_cycles)
    integer, intent(in) :: max_cycles
    call c_progress_begin(int(max_cycles, c_int))
  end subroutine progress_begin

  !> The run enters cycle icycle (0: the warm-up).
  subroutine progress_cycle(icycle)
    integer, intent(in) :: icycle
    call c_progress_cycle(int(icycle, c_int))
  end subroutine progress_cycle

  !> The step to crank angle psi [deg] is being solved.
  subroutine progress_step(psi)
    real(c_double), intent(in) :: psi
    call c_progress_step(psi)
  end subroutine progress_step

  !> Whether `path` itself is a symbolic link.
  logical function is_symlink(path)
    character(len=*), intent(in) :: path
    is_symlink = c_is_symlink(trim(path)//c_null_char) /= 0
  end function is_symlink

  !> Whether SIGINT arrived during an interrupt catch (the kernel stops at the next step).
  logical function interrupt_requested()
    interrupt_requested = c_interrupt_requested() /= 0
  end function interrupt_requested

  !> End an interrupt catch; .true. if SIGINT arrived since the outermost begin.
  logical function interrupt_catch_end()
    interrupt_catch_end = c_interrupt_catch_end() /= 0
  end function interrupt_catch_end

  !> What `path` names, following symbolic links: one of the `fs_*` values.
  integer function file_kind(path)
    character(len=*), intent(in) :: path
    file_kind = int(c_file_kind(path//c_null_char))
  end function file_kind

  !> True when both paths exist and are the same file (same device and inode).
  logical function same_file(a, b)
    character(len=*), intent(in) :: a, b
    same_file = c_same_file(a//c_null_char, b//c_null_char) == 1
  end function same_file

  !> Create a new empty file `base.<pid>.<random>.part` (exclusively: no other process
  !> gets the same name) and return its name; `code` is 0 or the errno of the failure.
  subroutine make_temp_file(base, tmp, code)
    character(len=*), intent(in) :: base
    character(len=:), allocatable, intent(out) :: tmp
    integer, intent(out) :: code
    character(kind=c_char, len=len(base) + 64) :: buf
    integer :: n
    code = int(c_make_temp(base//c_null_char, buf, int(len(buf), c_int)))
    n = index(buf, c_null_char) - 1
    if (code /= 0 .or. n < 0) then
      tmp = ''
      if (code == 0) code = -1
      return
    end if
    tmp = buf(1:n)
  end subroutine make_temp_file

  !> rename(2): atomically replace `new` by `old`; `code` is 0 or the errno.
  subroutine rename_file(old, new, code)
    character(len=*), intent(in) :: old, new
    integer, intent(out) :: code
    call c_clear_errno()
    code = 0
    if (c_rename(old//c_null_char, new//c_null_char) /= 0) then
      code = max(int(c_errno()), 1)
    else
      call c_forget_temp(old//c_null_char)
    end if
  end subroutine rename_file

  !> Delete a file if it exists (no error if it does not).
  subroutine remove_file(path)
    character(len=*), intent(in) :: path
    integer(c_int) :: rc
    rc = c_unlink(path//c_null_char)
    call c_forget_temp(path//c_null_char)
  end subroutine remove_file

  !> Folder part of a path with its final '/' ('' for a bare name): the prefix of the paths
  !> relative to the path's folder.
  pure function dir_prefix(path) result(d)
    character(len=*), intent(in) :: path
    character(len=:), allocatable :: d
    d = path(1:index(path, '/', back=.true.))
  end function dir_prefix

  !> Folder part of a path, without the final '/': '.' for a bare name, '/' for the root.
  pure function dir_name(path) result(d)
    character(len=*), intent(in) :: path
    character(len=:), allocatable :: d
    d = dir_prefix(path)
    if (len(d) == 0) then
      d = '.'
    else if (len(d) > 1) then
      d = d(1:len(d) - 1)
    end if
  end function dir_name

  !> errno of the last failing system call (0 if none since `clear_errno`).
  integer function last_errno()
    last_errno = int(c_errno())
  end function last_errno

  !> Set errno to 0.
  subroutine clear_errno()
    call c_clear_errno()
  end subroutine clear_errno

  !> The system's text for an errno value ("No space left on device").
  function errno_text(code) result(s)
    integer, intent(in) :: code
    character(len=:), allocatable :: s
    character(kind=c_char, len=256) :: buf
    integer :: n
    buf = c_null_char
    call c_strerror(int(code, c_int), buf, int(len(buf), c_int))
    n = index(buf, c_null_char) - 1
    if (n < 0) n = len_trim(buf)
    s = buf(1:n)
  end function errno_text
end module ringlube_fsys
