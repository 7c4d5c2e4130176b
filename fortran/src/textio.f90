!> Small text helpers shared by the readers and the writer: whole-file reads, integer
!> formatting, and making text valid UTF-8.
module ringlube_textio
  use ringlube_error, only: error_type, fatal_error, rl_input_error
  use ringlube_fsys, only: file_kind, fs_regular
  implicit none
  private
  public :: read_text_file, itoa, utf8_clean, after_bom

contains

  !> Read a whole text file into one string (lines joined by new_line).
  subroutine read_text_file(path, text, err)
    character(len=*), intent(in) :: path
    character(len=:), allocatable, intent(out) :: text
    type(error_type), allocatable, intent(out) :: err
    integer :: u, ios, sz
    character(len=256) :: msg
    logical :: exists
    inquire (file=path, exist=exists)
    if (.not. exists) then
      call fatal_error(err, trim(path)//': file not found', rl_input_error)
      return
    end if
    if (file_kind(path) /= fs_regular) then
      call fatal_error(err, trim(path)//': not a regular file (a folder or a device)', &
                       rl_input_error)
      return
    end if
    open (newunit=u, file=path, access='stream', form='unformatted', status='old', &
          action='read', iostat=ios, iomsg=msg)
    if (ios /= 0) then
      call fatal_error(err, trim(path)//': cannot open: '//trim(msg), rl_input_error)
      return
    end if
    inquire (unit=u, size=sz)
    allocate (character(len=max(sz, 0)) :: text)
    if (sz > 0) read (u, iostat=ios, iomsg=msg) text
    close (u)
    if (ios /= 0) then
      call fatal_error(err, trim(path)//': cannot read: '//trim(msg), rl_input_error)
    end if
  end subroutine read_text_file

  !> `s` as valid UTF-8: every byte that does not start or continue a well-formed UTF-8
  !> sequence (e.g. a Latin-1 'é' in a comment), and every NUL byte, becomes U+FFFD
  !> (the replacement character); valid text (ASCII included) is returned unchanged.
  !> Used for string attributes written as UTF-8, which a reader would otherwise fail
  !> to decode (or, in C, cut at the NUL).
  pure function utf8_clean(s) result(t)
    character(len=*), intent(in) :: s
    character(len=:), allocatable :: t
    character(len=3), parameter :: fffd = char(239)//char(191)//char(189)
    integer :: i, n, b, need, lo, hi, k
    logical :: good
    if (is_clean(s)) then
      t = s
      return
    end if
    t = ''
    n = len(s)
    i = 1
    do while (i <= n)
      b = iachar(s(i:i))
      call lead(b, need, lo, hi)
      good = need >= 0 .and. b /= 0 .and. i + need <= n
      if (good .and. need > 0) then
        good = iachar(s(i + 1:i + 1)) >= lo .and. iachar(s(i + 1:i + 1)) <= hi
        do k = 2, need
          if (.not. good) exit
          good = iachar(s(i + k:i + k)) >= 128 .and. iachar(s(i + k:i + k)) <= 191
        end do
      end if
      if (good) then
        t = t//s(i:i + need)
        i = i + need + 1
      else
        t = t//fffd
        i = i + 1
      end if
    end do

  contains

    !> Continuation bytes a lead byte `b` needs (-1: not a lead byte) and the range of
    !> the first of them.
    pure subroutine lead(b, need, lo, hi)
      integer, intent(in) :: b
      integer, intent(out) :: need, lo, hi
      lo = 128
      hi = 191
      select case (b)
      case (0:127)
        need = 0
      case (194:223)
        need = 1
      case (224)
        need = 2
        lo = 160
      case (225:236, 238:239)
        need = 2
      case (237)
        need = 2
        hi = 159
      case (240)
        need = 3
        lo = 144
      case (241:243)
        need = 3
      case (244)
        need = 3
        hi = 143
      case default
        need = -1
      end select
    end subroutine lead

    !> Plain ASCII without NUL (the common case, checked quickly).
    pure logical function is_clean(s)
      character(len=*), intent(in) :: s
      integer :: j
      is_clean = .false.
      do j = 1, len(s)
        if (iachar(s(j:j)) == 0 .or. iachar(s(j:j)) > 127) return
      end do
      is_clean = .true.
    end function is_clean
  end function utf8_clean

  !> Where the text of a file starts: 4 after a UTF-8 byte-order mark (editors and
  !> spreadsheets write one; it is not data), else 1.
  pure integer function after_bom(text) result(pos)
    character(len=*), intent(in) :: text
    pos = 1
    if (len(text) >= 3) then
      if (text(1:3) == char(239)//char(187)//char(191)) pos = 4
    end if
  end function after_bom

  !> An integer as text, without blanks.
  pure function itoa(i) result(s)
    integer, intent(in) :: i
    character(len=:), allocatable :: s
    character(len=16) :: buf
    write (buf, '(i0)') i
    s = trim(buf)
  end function itoa
end module ringlube_textio
