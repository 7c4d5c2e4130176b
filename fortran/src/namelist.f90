!> A strict scanner for namelist decks of scalar variables.
!>
!> gfortran's own namelist read reports a malformed value with messages such as
!> "Cannot match namelist object name .0e-3" and can read some malformed input as
!> end-of-file, which a reader could mistake for "group absent". This scanner splits a
!> deck into (group, variable, value, line) items itself, so that every error can name
!> the file, the group, the variable and the line. Syntax: `&group name = value, ... /`
!> (or `&end`), `!` comments, values quoted with ' or " (doubled quotes escape), one
!> value per variable. A caller that allows lists (`lists = .true.`, the `&study` decks)
!> also gets `name = v1, v2, ...` (values separated by commas or blanks, over several
!> lines if need be) as one item per value, numbered by `index`; kernel decks are scanned
!> without, so a list for a kernel scalar is an error naming file:line, group and variable;
!> the kernel's list variables (`list_vars`, e.g. `&bore amplitude`) take a list as one item
!> whose value is the list's text, "v1, v2, ...".
!> Not supported (an error, never a silent reinterpretation): array indices `name(i)`,
!> repeat counts `3*1.0` and null values.
module ringlube_namelist
  use ringlube_error, only: error_type, fatal_error, rl_input_error
  use ringlube_textio, only: itoa, after_bom
  implicit none
  private
  public :: nml_item, scan_namelist, lower, nul_message

  !> The error of a deck holding a NUL byte (after 'file:line: ').
  character(len=*), parameter :: nul_message = 'a NUL byte (binary data, not text) in the deck'

  !> One `name = value` of a group.
  type :: nml_item
    character(len=:), allocatable :: group, name, value
    character(len=:), allocatable :: file   !< the file the item was read from
    integer :: line = 0
    logical :: quoted = .false.
    integer :: index = 1       !< position of the value in its variable's list (1: first)
    integer :: group_line = 0  !< line on which the item's group opens
  end type nml_item

contains

  !> How many new_line('a') characters `s` holds.
  pure integer function count_newlines(s) result(k)
    character(len=*), intent(in) :: s
    integer :: i
    k = 0
    do i = 1, len(s)
      if (s(i:i) == new_line('a')) k = k + 1
    end do
  end function count_newlines

  !> Lower-case copy of a string.
  pure function lower(s) result(t)
    character(len=*), intent(in) :: s
    character(len=len(s)) :: t
    integer :: i
    t = s
    do i = 1, len(s)
      if (s(i:i) >= 'A' .and. s(i:i) <= 'Z') t(i:i) = achar(iachar(s(i:i)) + 32)
    end do
  end function lower

  !> Scan the deck text (lines separated by new_line('a')) into items. `path` is used
  !> in messages only. With `lists = .true.` a variable may take a list of values (one
  !> item per value); without, a second value is an error.
  subroutine scan_namelist(text, path, items, nitems, err, lists, list_vars)
    character(len=*), intent(in) :: text, path
    type(nml_item), allocatable, intent(out) :: items(:)
    integer, intent(out) :: nitems
    type(error_type), allocatable, intent(out) :: err
    logical, intent(in), optional :: lists
    !> 'group.name' of the variables that take a list as one item (values joined by ', ')
    character(len=*), intent(in), optional :: list_vars(:)
    integer :: pos, n, line, start, gline, idx
    character(len=:), allocatable :: group, name, value
    logical :: quoted, more, allow_lists, joined
    character(len=1) :: q

    allow_lists = .false.
    if (present(lists)) allow_lists = lists

    n = len(text)
    line = 1
    nitems = 0
    allocate (items(16))
    pos = after_bom(text)   ! a UTF-8 byte-order mark is not part of the deck
    ! a NUL byte: binary data, where readers of C strings would end the deck
    if (index(text, achar(0)) > 0) then
      line = 1 + count_newlines(text(1:index(text, achar(0))))
      call fail(nul_message)
      return
    end if

    ! the deck, group by group: "&group", then "name = value" items up to "/" or "&end"
    groups: do
      call skip_blank()
      if (pos > n) exit groups
      call read_group()
      if (allocated(err)) return
      items_of_group: do
        call skip_blank()
        if (group_closed()) cycle groups
        if (allocated(err)) return
        call read_name()
        if (allocated(err)) return
        idx = 0
        joined = .false.
        if (present(list_vars)) joined = any(list_vars == group//'.'//name)
        values_of_name: do
          call read_value()
          if (allocated(err)) return
          idx = idx + 1
          if (joined .and. idx > 1) then
            items(nitems)%value = items(nitems)%value//', '//value
          else
            call add(group, name, value, quoted)
          end if
          call check_follower()
          if (allocated(err)) return
          if (.not. more) exit values_of_name
        end do values_of_name
      end do items_of_group
    end do groups

  contains

    !> "&group" at pos: the group's name (lower case) and the line it opens on.
    subroutine read_group()
      if (text(pos:pos) /= '&') then
        ! text outside a group (other than comments) is an error: it is usually a
        ! variable whose group line was lost
        call fail('text outside a namelist group: "'//snippet()//'"')
        return
      end if
      pos = pos + 1
      group = identifier()
      gline = line
      if (len(group) == 0) then
        call fail('"&" not followed by a group name')
      else if (group == 'end') then
        call fail('"&end" without an open group')
      else if (group == 'study' .and. .not. allow_lists) then
        ! (a case deck's groups hold one value per variable; the study's lists would be
        ! reported as a malformed value)
        call fail('&study: this is a study deck, not a case deck (a study runs with '// &
                  '`ringlube optimise`)')
      end if
    end subroutine read_group

    !> The identifier at pos (lower case; empty if none), pos moved past it.
    function identifier() result(word)
      character(len=:), allocatable :: word
      start = pos
      do while (pos <= n)
        if (.not. is_ident(text(pos:pos))) exit
        pos = pos + 1
      end do
      word = lower(text(start:pos - 1))
    end function identifier

    !> Is the group closed at pos ("/" or "&end", consumed)? An end of text or another
    !> group before that is an error.
    logical function group_closed()
      group_closed = .false.
      if (pos > n) then
        call fail('&'//group//' (opened on line '//itoa(gline)//') is not closed with "/"')
        return
      end if
      if (text(pos:pos) == '/') then
        pos = pos + 1
        group_closed = .true.
      else if (text(pos:pos) == '&') then
        if (pos + 3 <= n) then
          if (lower(text(pos:pos + 3)) == '&end') then
            pos = pos + 4
            group_closed = .true.
            return
          end if
        end if
        call fail('&'//group//' (opened on line '//itoa(gline)// &
                  ') is not closed with "/" before the next group')
      end if
    end function group_closed

    !> "name =" at pos.
    subroutine read_name()
      if (.not. is_ident(text(pos:pos))) then
        call fail('&'//group//': expected a variable name, found "'//snippet()//'"')
        return
      end if
      name = identifier()
      call skip_space()
      if (pos > n) then
        call fail('&'//group//' '//name//': expected "=" after the name')
      else if ((text(pos:pos) == '(' .or. text(pos:pos) == '%') .and. allow_lists) then
        call fail('&'//group//' '//name//': "'//name//trim(token(pos))//'": no array elements '// &
                  'or components; give the whole list (write '//name//' = value, value, ...)')
      else if (text(pos:pos) == '(' .or. text(pos:pos) == '%') then
        call fail('&'//group//' '//name//': "'//name//trim(token(pos))//'" is not an input: '// &
                  'the inputs are single values, no array elements or components (write '// &
                  'the variable''s own name, e.g. '//plain(name//trim(token(pos)))//' = value)')
      else if (text(pos:pos) /= '=') then
        call fail('&'//group//' '//name//': expected "=" after the name, found "' &
                  //snippet()//'"')
      else
        pos = pos + 1
        call skip_space()
      end if
    end subroutine read_name

    !> The value at pos: a quoted string (doubled quotes escape) or a run of characters up
    !> to a separator.
    subroutine read_value()
      quoted = .false.
      if (pos <= n) quoted = text(pos:pos) == "'" .or. text(pos:pos) == '"'
      if (quoted) then
        call read_quoted()
        return
      end if
      start = pos
      value = token(pos)
      pos = pos + len(value)
      if (len(value) == 0) call fail('&'//group//' '//name//': missing value')
    end subroutine read_value

    subroutine read_quoted()
      q = text(pos:pos)
      pos = pos + 1
      value = ''
      do
        ! the run of characters up to the next quote or the end of the line, at once
        ! (one character at a time costs quadratic time on long strings)
        start = pos
        do while (pos <= n)
          if (text(pos:pos) == q .or. text(pos:pos) == new_line('a')) exit
          pos = pos + 1
        end do
        if (pos > start) value = value//text(start:pos - 1)
        if (pos > n) then
          call fail('&'//group//' '//name//': unterminated string')
          return
        end if
        if (text(pos:pos) == new_line('a')) then
          call fail('&'//group//' '//name//': unterminated string')
          return
        end if
        ! a quote: doubled, it stands for itself; else it ends the string
        if (pos < n) then
          if (text(pos + 1:pos + 1) == q) then
            value = value//q
            pos = pos + 2
            cycle
          end if
        end if
        pos = pos + 1
        exit
      end do
    end subroutine read_quoted

    !> After a value: an optional comma, then a name followed by "=", "/" or "&end"
    !> (anything else is a further value: `more` with lists, else an error).
    subroutine check_follower()
      more = .false.
      call skip_space()
      if (pos <= n) then
        if (text(pos:pos) == ',') pos = pos + 1
      end if
      call skip_blank()
      if (pos > n) return
      if (is_ident(text(pos:pos))) then
        start = pos
        do while (pos <= n)
          if (.not. is_ident(text(pos:pos))) exit
          pos = pos + 1
        end do
        call skip_space()
        if (pos <= n) then
          ! a name: "name =", or "name(" / "name%" (an array element or a component, which
          ! read_name then refuses, naming that variable and not the one before)
          if (text(pos:pos) == '=' .or. text(pos:pos) == '(' .or. text(pos:pos) == '%') then
            pos = start
            return
          end if
        end if
        pos = start
        if (allow_lists .or. joined) then
          more = .true.
          return
        end if
        if (quoted) then
          call fail('&'//group//' '//name//': malformed value "'''//value//'''" followed by "' &
                    //token(start)//'" (one value per variable)')
        else
          call fail('&'//group//' '//name//': malformed value "'//value//' ' &
                    //token(start)//'" (one value per variable)')
        end if
      else if (text(pos:pos) /= '/' .and. text(pos:pos) /= '&') then
        if ((allow_lists .or. joined) .and. text(pos:pos) /= '(' .and. text(pos:pos) /= '=') then
          more = .true.
          return
        end if
        call fail('&'//group//' '//name//': malformed value "'//value//'" followed by "'// &
                  snippet()//'" (one value per variable)')
      end if
    end subroutine check_follower

    !> The name a user most likely meant in "a%b(1)": the last component, without indices.
    pure function plain(t) result(w)
      character(len=*), intent(in) :: t
      character(len=:), allocatable :: w
      integer :: i
      w = t
      i = index(w, '=')
      if (i > 0) w = w(:i - 1)
      i = index(w, '%', back=.true.)
      if (i > 0) w = w(i + 1:)
      i = index(w, '(')
      if (i > 0) w = w(:i - 1)
      ! ("a % b": the component is beyond a blank; name the variable itself)
      if (len_trim(w) == 0) w = name
    end function plain

    pure logical function is_ident(ch)
      character(len=1), intent(in) :: ch
      is_ident = (ch >= 'a' .and. ch <= 'z') .or. (ch >= 'A' .and. ch <= 'Z') &
                 .or. (ch >= '0' .and. ch <= '9') .or. ch == '_'
    end function is_ident

    pure logical function is_sep(ch)
      character(len=1), intent(in) :: ch
      is_sep = ch == ' ' .or. ch == ',' .or. ch == '/' .or. ch == '!' .or. ch == achar(9) &
               .or. ch == new_line('a') .or. ch == achar(13)
    end function is_sep

    !> Skip spaces and tabs (not newlines).
    subroutine skip_space()
      do while (pos <= n)
        if (text(pos:pos) /= ' ' .and. text(pos:pos) /= achar(9) .and. &
            text(pos:pos) /= achar(13)) exit
        pos = pos + 1
      end do
    end subroutine skip_space

    !> Skip whitespace, newlines and comments.
    subroutine skip_blank()
      do while (pos <= n)
        if (text(pos:pos) == new_line('a')) then
          line = line + 1
        else if (text(pos:pos) == '!') then
          do while (pos <= n)
            if (text(pos:pos) == new_line('a')) exit
            pos = pos + 1
          end do
          cycle
        else if (text(pos:pos) /= ' ' .and. text(pos:pos) /= achar(9) .and. &
                 text(pos:pos) /= achar(13)) then
          exit
        end if
        pos = pos + 1
      end do
    end subroutine skip_blank

    !> The run of non-separator characters starting at i.
    function token(i) result(s)
      integer, intent(in) :: i
      character(len=:), allocatable :: s
      integer :: e
      e = i
      do while (e <= n)
        if (is_sep(text(e:e))) exit
        e = e + 1
      end do
      s = text(i:e - 1)
    end function token

    function snippet() result(s)
      character(len=:), allocatable :: s
      integer :: e
      e = pos
      do while (e <= n .and. e < pos + 30)
        if (text(e:e) == new_line('a')) exit
        e = e + 1
      end do
      s = text(pos:e - 1)
    end function snippet

    subroutine add(g, nm, v, qt)
      character(len=*), intent(in) :: g, nm, v
      logical, intent(in) :: qt
      type(nml_item), allocatable :: tmp(:)
      if (nitems == size(items)) then
        allocate (tmp(2 * nitems))
        tmp(1:nitems) = items
        call move_alloc(tmp, items)
      end if
      nitems = nitems + 1
      items(nitems)%group = g
      items(nitems)%name = nm
      items(nitems)%value = v
      items(nitems)%line = line
      items(nitems)%quoted = qt
      items(nitems)%file = path
      items(nitems)%index = idx
      items(nitems)%group_line = gline
    end subroutine add

    subroutine fail(msg)
      character(len=*), intent(in) :: msg
      call fatal_error(err, path//':'//itoa(line)//': '//msg, rl_input_error)
    end subroutine fail
  end subroutine scan_namelist
end module ringlube_namelist
