!> The rules of the kernel's CSV inputs (pressure trace, face profile, bore distortion): fields,
!> numbers, the optional header row; a CSV file read row by row (`open_csv`, `next_row`,
!> `row_error`), and the rows of a two-column file (`split_pair`, `add_pair`, `take_pairs`).
!>
!> A file is read as lines; blank lines and lines starting with '#' are skipped, a line's
!> trailing carriage return (a Windows file) dropped. Only the first row can be the header,
!> and only if none of its fields could be a number (`is_header`). `row_error` names the
!> file, the line's number and its text.
module ringlube_csv
  use ringlube_kinds, only: dp
  use ringlube_error, only: error_type, fatal_error, rl_input_error
  use ringlube_textio, only: read_text_file, itoa, after_bom
  use, intrinsic :: iso_c_binding, only: c_char, c_double, c_ptr, c_null_char, c_loc, c_size_t
  implicit none
  private
  public :: field_end, is_header, to_real, field_number, field_nonfinite, field_bad
  public :: csv_rows, open_csv, next_row, split_pair, row_error, add_pair, take_pairs

  !> What `to_real` made of a field.
  integer, parameter :: field_number = 0, field_nonfinite = 1, field_bad = 2

  !> A CSV file being read: its text, where the reading is, the current line and its number,
  !> and (a two-column file) the rows taken so far (`add_pair`).
  type :: csv_rows
    !> the file (for messages) and what it holds ('pressure', 'profile': "pressure file ...")
    character(len=:), allocatable :: path, what
    character(len=:), allocatable :: text
    !> the current line (trimmed, without a trailing carriage return) and its number
    character(len=:), allocatable :: line
    integer :: nline = 0
    integer :: pos = 1
    logical :: seen_header = .false.
    !> the rows taken: x(1:nrow), y(1:nrow)
    integer :: nrow = 0
    real(dp), allocatable :: x(:), y(:)
  end type csv_rows

  interface
    real(c_double) function c_strtod(str, endptr) bind(c, name='strtod')
      import :: c_char, c_double, c_ptr
      character(kind=c_char), intent(in) :: str(*)
      type(c_ptr), intent(out) :: endptr
    end function c_strtod
  end interface

contains

  !> Open the CSV file `path` holding `what` (a missing file: "<path>: <what> file not found"),
  !> its text read whole; a UTF-8 byte-order mark at its start (spreadsheets write one) is not
  !> data.
  subroutine open_csv(path, what, rows, err)
    character(len=*), intent(in) :: path, what
    type(csv_rows), intent(out) :: rows
    type(error_type), allocatable, intent(out) :: err
    logical :: exists

    inquire (file=path, exist=exists)
    if (.not. exists) then
      call fatal_error(err, trim(path)//': '//what//' file not found', rl_input_error)
      return
    end if
    call read_text_file(path, rows%text, err)
    if (allocated(err)) return
    rows%path = trim(path)
    rows%what = what
    rows%pos = after_bom(rows%text)
  end subroutine open_csv

  !> The next line that holds data into rows%line (false at the end of the text); `header`:
  !> it is the first such line and a header (`is_header`).
  logical function next_row(rows, header) result(got)
    type(csv_rows), intent(inout) :: rows
    logical, intent(out) :: header
    integer :: eol
    character(len=:), allocatable :: line
    got = .false.
    header = .false.
    do while (rows%pos <= len(rows%text))
      eol = field_end(rows%text, rows%pos, new_line('a'))
      line = trim(adjustl(rows%text(rows%pos:eol - 1)))
      if (len(line) > 0) then
        if (line(len(line):len(line)) == achar(13)) line = line(1:len(line) - 1)
      end if
      rows%pos = eol + 1
      rows%nline = rows%nline + 1
      rows%line = line
      if (len_trim(line) == 0) cycle
      if (line(1:1) == '#') cycle
      got = .true.
      if (.not. rows%seen_header) then
        rows%seen_header = .true.   ! only the first row can be the header
        header = is_header(line)
      end if
      return
    end do
  end function next_row

  !> The two fields of a row "a, b" as numbers, with what `to_real` made of each (`field_bad`
  !> both when the row has not exactly two fields, the first not empty).
  subroutine split_pair(line, a, b, fa, fb)
    character(len=*), intent(in) :: line
    real(dp), intent(out) :: a, b
    integer, intent(out) :: fa, fb
    integer :: icomma
    logical :: ok
    a = 0.0_dp
    b = 0.0_dp
    icomma = index(line, ',')
    ok = icomma > 1
    if (ok) ok = index(line(icomma + 1:), ',') == 0
    fa = field_bad
    fb = field_bad
    if (ok) then
      call to_real(line(1:icomma - 1), a, fa)
      call to_real(line(icomma + 1:), b, fb)
    end if
  end subroutine split_pair

  !> The error of the current line: "<path>: line <n>: <why>: "<line>"".
  subroutine row_error(rows, why, err)
    type(csv_rows), intent(in) :: rows
    character(len=*), intent(in) :: why
    type(error_type), allocatable, intent(out) :: err
    call fatal_error(err, rows%path//': line '//itoa(rows%nline)//': '//why//': "' &
                     //trim(rows%line)//'"', rl_input_error)
  end subroutine row_error

  !> Take the row (a, b) of the current line; the first column must increase strictly
  !> (`not_increasing`: the current line's error when it does not).
  subroutine add_pair(rows, a, b, not_increasing, err)
    type(csv_rows), intent(inout) :: rows
    real(dp), intent(in) :: a, b
    character(len=*), intent(in) :: not_increasing
    type(error_type), allocatable, intent(out) :: err
    if (rows%nrow > 0) then
      if (.not. (a > rows%x(rows%nrow))) then
        call row_error(rows, not_increasing, err)
        return
      end if
    end if
    if (.not. allocated(rows%x)) then
      allocate (rows%x(max(16, len(rows%text) / 8)), rows%y(max(16, len(rows%text) / 8)))
    end if
    rows%nrow = rows%nrow + 1
    if (rows%nrow > size(rows%x)) then
      rows%x = [rows%x, rows%x]
      rows%y = [rows%y, rows%y]
    end if
    rows%x(rows%nrow) = a
    rows%y(rows%nrow) = b
  end subroutine add_pair

  !> The rows taken, at least two ("<path>: <what> file needs at least two rows").
  subroutine take_pairs(rows, x, y, err)
    type(csv_rows), intent(in) :: rows
    real(dp), allocatable, intent(out) :: x(:), y(:)
    type(error_type), allocatable, intent(out) :: err
    if (rows%nrow < 2) then
      call fatal_error(err, rows%path//': '//rows%what//' file needs at least two rows', &
                       rl_input_error)
      return
    end if
    x = rows%x(1:rows%nrow)
    y = rows%y(1:rows%nrow)
  end subroutine take_pairs

  !> Whether a CSV row is a header: every comma-separated field a non-empty word that
  !> cannot be read as a number (first character not a digit, sign or point; not a
  !> spelling of nan or inf).
  logical function is_header(line)
    character(len=*), intent(in) :: line
    integer :: i0, i1
    character(len=:), allocatable :: f
    is_header = .false.
    i0 = 1
    do
      i1 = field_end(line, i0, ',')
      f = trim(adjustl(line(i0:i1 - 1)))
      if (len(f) == 0) return
      if (scan(f(1:1), '0123456789+-.') /= 0) return
      if (nonfinite_word(f)) return
      if (i1 > len(line)) exit
      i0 = i1 + 1
    end do
    is_header = .true.
  end function is_header

  !> Where the field of `text` that starts at `from` ends: the index of the next `sep` at or
  !> after `from`, or len(text) + 1 when there is none (lines of a file, fields of a line).
  pure integer function field_end(text, from, sep) result(i)
    character(len=*), intent(in) :: text, sep
    integer, intent(in) :: from
    i = index(text(from:), sep)
    if (i == 0) then
      i = len(text) + 1
    else
      i = from + i - 1
    end if
  end function field_end

  !> nan, inf or infinity (any case, optional sign, nan(...) included): what C's strtod
  !> would read as a non-finite number.
  pure logical function nonfinite_word(field)
    character(len=*), intent(in) :: field
    character(len=:), allocatable :: f
    integer :: i
    f = trim(adjustl(field))
    do i = 1, len(f)
      if (f(i:i) >= 'A' .and. f(i:i) <= 'Z') f(i:i) = achar(iachar(f(i:i)) + 32)
    end do
    if (len(f) > 0) then
      if (f(1:1) == '+' .or. f(1:1) == '-') f = f(2:)
    end if
    nonfinite_word = f == 'nan' .or. f == 'inf' .or. f == 'infinity'
    if (len(f) >= 4) nonfinite_word = nonfinite_word .or. f(1:4) == 'nan('
  end function nonfinite_word

  !> A whole field (surrounding blanks allowed) as a real, by C's strtod. `kind` is
  !> `field_number` (a finite decimal number), `field_nonfinite` (nan, inf, or a number
  !> beyond the range of a double) or `field_bad` (anything else).
  subroutine to_real(field, v, kind)
    character(len=*), intent(in) :: field
    real(dp), intent(out) :: v
    integer, intent(out) :: kind
    character(kind=c_char, len=:), allocatable, target :: buf
    type(c_ptr) :: endp
    integer(c_size_t) :: consumed
    integer :: i
    character(len=:), allocatable :: f
    f = trim(adjustl(field))
    v = 0.0_dp
    kind = field_bad
    if (len(f) == 0) return
    if (nonfinite_word(f)) then
      kind = field_nonfinite
      return
    end if
    if (verify(f, '0123456789+-.eEdD') /= 0) return   ! no hex or other words
    ! Fortran-style exponents (1.0d5) as C ones
    do i = 1, len(f)
      if (f(i:i) == 'd' .or. f(i:i) == 'D') f(i:i) = 'e'
    end do
    buf = f//c_null_char
    v = c_strtod(buf, endp)
    consumed = transfer(endp, consumed) - transfer(c_loc(buf), consumed)
    if (consumed /= int(len(f), c_size_t)) return
    if (abs(v) > huge(v)) then
      kind = field_nonfinite   ! overflow: strtod gives +-HUGE_VAL (inf)
    else
      kind = field_number
    end if
  end subroutine to_real
end module ringlube_csv
