!> Small text helpers shared by the readers: whole-file reads and integer formatting.
module ringlube_textio
  use ringlube_error, only: error_type, fatal_error, rl_input_error
  implicit none
  private
  public :: read_text_file, itoa

contains

  !> Read a whole text file into one string (lines joined by new_line).
  subroutine read_text_file(path, text, err)
    character(len=*), intent(in) :: path
    character(len=:), allocatable, intent(out) :: text
    type(error_type), allocatable, intent(out) :: err
    integer :: u, ios, sz
    character(len=256) :: msg
    logical :: exists
    inquire(file=path, exist=exists)
    if (.not. exists) then
      call fatal_error(err, trim(path) // ': file not found', rl_input_error)
      return
    end if
    open(newunit=u, file=path, access='stream', form='unformatted', status='old', &
      action='read', iostat=ios, iomsg=msg)
    if (ios /= 0) then
      call fatal_error(err, trim(path) // ': cannot open: ' // trim(msg), rl_input_error)
      return
    end if
    inquire(unit=u, size=sz)
    allocate(character(len=max(sz, 0)) :: text)
    if (sz > 0) read(u, iostat=ios, iomsg=msg) text
    close(u)
    if (ios /= 0) then
      call fatal_error(err, trim(path) // ': cannot read: ' // trim(msg), rl_input_error)
    end if
  end subroutine read_text_file

  !> An integer as text, without blanks.
  pure function itoa(i) result(s)
    integer, intent(in) :: i
    character(len=:), allocatable :: s
    character(len=16) :: buf
    write(buf, '(i0)') i
    s = trim(buf)
  end function itoa
end module ringlube_textio
