!> Writing a result to HDF5 in the layout of docs/model.md "Results" (README "Output").
!>
!> Safety:
!> - The output is first checked by `check_output` (ringlube_output_path).
!> - The file is written under a unique temporary name in the destination folder
!>   (`OUT.<pid>.<random>.part`, created with O_EXCL) and moved into place with one
!>   rename(2) when complete: an interrupted run never leaves a half-written result, and
!>   two runs writing the same output each publish a whole file (the last rename wins).
!> - Every HDF5 call is checked; on a failure whatever is open is closed, the temporary
!>   file is deleted and a runtime error (exit status 1) is returned with the system's
!>   message (e.g. "No space left on device", or "File too large" over `ulimit -f`). HDF5
!>   1.10 crashes at exit (its atexit clean-up) after a file whose close failed, so the
!>   library is told not to install that clean-up (h5dont_atexit): every object is closed
!>   here, on success and on failure. The finished file is not fsync'ed before the rename:
!>   the rename protects against concurrent writers and interruption, not against a power
!>   cut (an fsync would add a disk flush to every result, which sweeps writing thousands
!>   of files would feel).
!>
!> Root attributes: the scalar results (table `scalar_spec`), the deck's text and paths,
!> and every input of the case by the input table as `group.name` (e.g. `ring.width`,
!> its effective value: deck, calibration file, preset or default).
!>
!> Layout for xarray/netCDF readers: `/cycle/crank_angle_deg` is an HDF5 dimension scale
!> attached to every other `/cycle` dataset (so it is their coordinate); every dataset has
!> `units` and a one-line `long_name`; every string attribute is a variable-length UTF-8
!> string (h5py reads it as `str`). The file is written with the HDF5 1.8 object format
!> or later (libver bounds V18..latest) so that attributes larger than 64 KiB (a long
!> deck) are kept in dense attribute storage instead of failing.
module ringlube_hdf5_output
  use, intrinsic :: iso_c_binding, only: c_char, c_null_char, c_ptr, c_loc
  use, intrinsic :: ieee_arithmetic, only: ieee_value, ieee_quiet_nan
  use ringlube_kinds, only: dp
  use ringlube_error, only: error_type, fatal_error, rl_runtime_error
  use ringlube_case, only: case_type, case_access, access_get
  use ringlube_inputs, only: input_table => inputs, n_inputs, input_key, kind_real, kind_int, &
                             kind_logical
  use ringlube_results, only: result_type, scalar_spec, n_scalars, series_spec, n_series, &
                              int_series_spec, n_int_series, flag_description, liner_spec, &
                              n_liner, produced, si_flags, m_starved, m_distorted, &
                              sector_spec, n_sector_series
  use ringlube_version, only: package_version
  use ringlube_kernel_id, only: kernel_id
  use ringlube_textio, only: utf8_clean, itoa
  use ringlube_fsys, only: make_temp_file, rename_file, remove_file, dir_name, last_errno, &
                           clear_errno, errno_text
  use ringlube_output_path, only: check_output
  use hdf5
  use h5ds, only: h5dsset_scale_f, h5dsattach_scale_f
  implicit none
  private
  public :: write_result, remove_file

  ! kinds of open HDF5 objects, for closing them in reverse order after a failure
  integer, parameter :: k_file = 1, k_group = 2, k_dset = 3, k_space = 4, k_attr = 5, &
                        k_type = 6, k_plist = 7

  !> Whether h5open_f has been called (h5dont_atexit_f must come before it).
  logical, save :: library_open = .false.

contains

  !> Write the result of case `c` to `path` (atomically, via a unique temporary file in
  !> the same folder): every series and scalar of the result tables, by index. `path` is
  !> first checked by `check_output` against the deck and the pressure file of `c` and the
  !> optional further `inputs` (named by `labels`).
  subroutine write_result(path, c, res, err, inputs, labels)
    character(len=*), intent(in) :: path
    type(case_type), intent(in) :: c
    type(result_type), intent(in) :: res
    type(error_type), allocatable, intent(out) :: err
    character(len=*), intent(in), optional :: inputs(:), labels(:)
    type(case_type) :: cc
    real(dp) :: v
    integer :: i, n, ios
    character(len=:), allocatable :: text, why
    character(len=:), allocatable :: tmp, failed
    character(len=max(len(c%deck_path), len(c%pressure_file), 1)) :: own(2)
    integer(hid_t) :: ids(16), fid, gid, fapl, scale_id, lid, liner_scale
    integer :: kinds(16), nopen, herr, code, fail_errno
    logical :: ok

    own = [character(len=len(own)) :: c%deck_path, c%pressure_file]
    call check_output(path, own, [character(len=18) :: 'the deck', 'the pressure file'], err)
    if (allocated(err)) return
    if (present(inputs)) then
      if (present(labels)) then
        call check_output(path, inputs, labels, err)
      else
        call check_output(path, inputs, ['an input'], err)
      end if
      if (allocated(err)) return
    end if

    call make_temp_file(path, tmp, code)
    if (code /= 0) then
      call fatal_error(err, path//': cannot create a temporary file in '//dir_name(path) &
                       //': '//errno_text(code), rl_runtime_error)
      return
    end if
    if (.not. library_open) then
      ! only valid before the library is initialised: if some other code has done that
      ! already, the guard is not available and its failure is not an error here
      call h5dont_atexit_f(herr)
    end if
    call h5open_f(herr)
    if (herr /= 0) then
      call remove_file(tmp)
      call fatal_error(err, 'HDF5 library could not be initialised', rl_runtime_error)
      return
    end if
    library_open = .true.
    call h5eset_auto_f(0, herr)   ! errors are reported here, not printed by HDF5
    if (herr /= 0) then
      call remove_file(tmp)
      call fatal_error(err, 'HDF5 error printing could not be switched off', rl_runtime_error)
      return
    end if

    call clear_errno()
    ok = .true.
    nopen = 0
    fail_errno = 0
    call h5pcreate_f(H5P_FILE_ACCESS_F, fapl, herr)
    if (step(herr, 'file access properties', fapl, k_plist)) then
      call h5pset_libver_bounds_f(fapl, H5F_LIBVER_V18_F, H5F_LIBVER_LATEST_F, herr)
      call check(herr, 'file format version')
      if (ok) call h5fcreate_f(tmp, H5F_ACC_TRUNC_F, fid, herr, access_prp=fapl)
      call opened(herr, 'file creation', fid, k_file)
      if (ok) then
        call close_object(fapl, k_plist, herr)   ! not the top of the stack: close by hand
        call forget(fapl)
        call check(herr, 'file access properties')
      end if
    end if

    ! the scalar results, by the kernel's table (whole numbers as integers)
    do i = 1, n_scalars
      if (.not. produced(res, scalar_spec(i)%requires)) cycle
      v = res%scalars(i)
      if (scalar_spec(i)%kind /= 'real') then
        call attr_int(fid, trim(scalar_spec(i)%stored), nint(v))
      else
        call attr_real(fid, trim(scalar_spec(i)%stored), v)
      end if
    end do
    ! the effective inputs of the case, by the input table, as `group.name` (reals and
    ! integers as numbers, logicals as 0/1, text as text), so that files can be compared
    ! without reading their decks
    cc = c
    do i = 1, n_inputs
      call case_access(cc, i, access_get, text, why)
      select case (input_table(i)%kind)
      case (kind_real)
        read (text, *, iostat=ios) v
        if (ios /= 0) v = ieee_value(v, ieee_quiet_nan)
        call attr_real(fid, input_key(i), v)
      case (kind_int)
        read (text, *, iostat=ios) n
        if (ios /= 0) n = -huge(n)
        call attr_int(fid, input_key(i), n)
      case (kind_logical)
        call attr_int(fid, input_key(i), merge(1, 0, text == '.true.'))
      case default
        call attr_str(fid, input_key(i), text)
      end select
    end do
    ! a distorted bore's conformability per order: conformability_<k>
    if (res%made(m_distorted)) then
      do i = 1, size(res%conformability)
        call attr_real(fid, 'conformability_'//itoa(res%conformability_orders(i)), &
                       res%conformability(i))
      end do
    end if
    call attr_str(fid, 'deck', c%deck_text)
    call attr_str(fid, 'deck_path', c%deck_path)
    call attr_str(fid, 'pressure_file', c%pressure_file)
    call attr_str(fid, 'ringlube_version', package_version)
    call attr_str(fid, 'kernel_id', kernel_id)

    if (ok) then
      call h5gcreate_f(fid, 'cycle', gid, herr)
      call opened(herr, 'group /cycle', gid, k_group)
    end if
    ! the crank angle is the dimension scale (coordinate) of every other /cycle dataset;
    ! it stays open until they are written
    do i = 1, n_series
      if (.not. produced(res, series_spec(i)%requires)) cycle
      if (i == 1) then
        call dset(gid, trim(series_spec(i)%stored), res%series(:, i), trim(series_spec(i)%unit), &
                  trim(series_spec(i)%long_name), keep=scale_id)
      else
        call dset(gid, trim(series_spec(i)%stored), res%series(:, i), trim(series_spec(i)%unit), &
                  trim(series_spec(i)%long_name))
      end if
    end do
    do i = 1, n_int_series
      if (i == si_flags) then
        call dset_int(gid, trim(int_series_spec(i)%stored), res%int_series(:, i), &
                      trim(int_series_spec(i)%unit), trim(int_series_spec(i)%long_name), &
                      flag_description())
      else
        call dset_int(gid, trim(int_series_spec(i)%stored), res%int_series(:, i), &
                      trim(int_series_spec(i)%unit), trim(int_series_spec(i)%long_name), &
                      trim(int_series_spec(i)%long_name))
      end if
    end do
    ! a distorted bore's series per crank step and sector (crank angle x sector)
    if (res%made(m_distorted)) then
      do i = 1, n_sector_series
        call dset2(gid, trim(sector_spec(i)%stored), transpose(res%sectors(:, :, i)), &
                   trim(sector_spec(i)%unit), trim(sector_spec(i)%long_name))
      end do
    end if
    ! the liner film at the end of the cycle (starved inlet): its position (the first row
    ! of the table) is the scale
    if (res%made(m_starved) .and. ok) then
      call h5gcreate_f(fid, 'liner', lid, herr)
      call opened(herr, 'group /liner', lid, k_group)
      do i = 1, n_liner
        if (i == 1) then
          call dset(lid, trim(liner_spec(i)%stored), res%liner(:, i), trim(liner_spec(i)%unit), &
                    trim(liner_spec(i)%long_name), keep=liner_scale)
          scale_id = liner_scale
        else
          call dset(lid, trim(liner_spec(i)%stored), res%liner(:, i), trim(liner_spec(i)%unit), &
                    trim(liner_spec(i)%long_name))
        end if
      end do
    end if
    ! close the scale, the group and the file (the file's metadata is written then)
    do while (ok .and. nopen > 0)
      call close_top(herr)
      call check(herr, 'closing the file')
    end do
    if (.not. ok) then
      do while (nopen > 0)
        call close_top(herr)   ! after a failure: close the rest, errors ignored
      end do
      call remove_file(tmp)
      failed = path//': cannot write the result (HDF5 error at '//failed//')'
      if (fail_errno /= 0) failed = failed//': '//errno_text(fail_errno)
      call fatal_error(err, failed, rl_runtime_error)
      return
    end if
    call rename_file(tmp, path, code)
    if (code /= 0) then
      call remove_file(tmp)
      call fatal_error(err, path//': cannot move the finished result into place: '// &
                       errno_text(code), rl_runtime_error)
    end if

  contains

    !> After an HDF5 call with status `e`: on success remember the object it opened (if
    !> any) and return true; on failure record what failed and return false.
    logical function step(e, what, id, kind)
      integer, intent(in) :: e
      character(len=*), intent(in) :: what
      integer(hid_t), intent(in), optional :: id
      integer, intent(in), optional :: kind
      step = e >= 0 .and. ok
      if (e < 0 .and. ok) then
        ok = .false.
        failed = what
        fail_errno = last_errno()
      end if
      call clear_errno()   ! so that errno at the next failure is that failure's
      if (step .and. present(id) .and. nopen == size(ids)) then
        ok = .false.          ! cannot happen with this layout (at most 9 open)
        step = .false.
        failed = what//' (too many open objects)'
      end if
      if (step .and. present(id)) then
        nopen = nopen + 1
        ids(nopen) = id
        kinds(nopen) = kind
      end if
    end function step

    !> `step` for a call that opened object `id` of the given kind.
    subroutine opened(e, what, id, kind)
      integer, intent(in) :: e, kind
      character(len=*), intent(in) :: what
      integer(hid_t), intent(in) :: id
      if (step(e, what, id, kind)) return
    end subroutine opened

    !> `step` without an object to remember.
    subroutine check(e, what)
      integer, intent(in) :: e
      character(len=*), intent(in) :: what
      if (step(e, what)) return
    end subroutine check

    !> Close the most recently opened object and drop it from the list.
    subroutine close_top(e)
      integer, intent(out) :: e
      call close_object(ids(nopen), kinds(nopen), e)
      nopen = nopen - 1
    end subroutine close_top

    !> Drop `id` from the list of open objects (after closing it out of order).
    subroutine forget(id)
      integer(hid_t), intent(in) :: id
      integer :: i
      do i = nopen, 1, -1
        if (ids(i) == id) then
          ids(i:nopen - 1) = ids(i + 1:nopen)
          kinds(i:nopen - 1) = kinds(i + 1:nopen)
          nopen = nopen - 1
          return
        end if
      end do
    end subroutine forget

    subroutine attr_real(loc, name, v)
      integer(hid_t), intent(in) :: loc
      character(len=*), intent(in) :: name
      real(dp), intent(in), target :: v
      call attr_write(loc, name, H5T_NATIVE_DOUBLE, c_loc(v))
    end subroutine attr_real

    subroutine attr_int(loc, name, v)
      integer(hid_t), intent(in) :: loc
      character(len=*), intent(in) :: name
      integer, intent(in), target :: v
      call attr_write(loc, name, H5T_NATIVE_INTEGER, c_loc(v))
    end subroutine attr_int

    !> A scalar variable-length UTF-8 string attribute (text that is not valid UTF-8 is
    !> written with U+FFFD for each bad byte, see `utf8_clean`).
    subroutine attr_str(loc, name, text)
      integer(hid_t), intent(in) :: loc
      character(len=*), intent(in) :: name, text
      character(kind=c_char), allocatable, target :: cbuf(:)
      character(len=:), allocatable :: v
      type(c_ptr), target :: ptr(1)
      integer(hid_t) :: tid
      integer :: e, i
      if (.not. ok) return
      v = utf8_clean(text)
      allocate (cbuf(len(v) + 1))
      do i = 1, len(v)
        cbuf(i) = v(i:i)
      end do
      cbuf(len(v) + 1) = c_null_char
      ptr(1) = c_loc(cbuf)
      call h5tcopy_f(H5T_STRING, tid, e)
      if (.not. step(e, 'string type of attribute '//name, tid, k_type)) return
      call h5tset_cset_f(tid, H5T_CSET_UTF8_F, e)
      if (.not. step(e, 'string type of attribute '//name)) return
      call attr_write(loc, name, tid, c_loc(ptr))
      if (.not. ok) return
      call close_top(e)
      if (.not. step(e, 'string type of attribute '//name)) return
    end subroutine attr_str

    !> A scalar attribute of type `tid` holding the value at `buf`.
    subroutine attr_write(loc, name, tid, buf)
      integer(hid_t), intent(in) :: loc, tid
      character(len=*), intent(in) :: name
      type(c_ptr), intent(in) :: buf
      integer(hid_t) :: sid, aid
      integer :: e
      if (.not. ok) return
      call h5screate_f(H5S_SCALAR_F, sid, e)
      if (.not. step(e, 'attribute '//name, sid, k_space)) return
      call h5acreate_f(loc, name, tid, sid, aid, e)
      if (.not. step(e, 'attribute '//name, aid, k_attr)) return
      call h5awrite_f(aid, tid, buf, e)
      if (.not. step(e, 'attribute '//name)) return
      call close_top(e)   ! attribute
      if (.not. step(e, 'attribute '//name)) return
      call close_top(e)   ! its dataspace
      if (.not. step(e, 'attribute '//name)) return
    end subroutine attr_write

    !> A 1-D dataset of doubles with `units` and `long_name`. With `keep`, the dataset
    !> becomes the dimension scale and stays open (its id returned in `keep`); without,
    !> the scale `scale_id` is attached to it.
    subroutine dset(loc, name, v, units, long_name, keep)
      integer(hid_t), intent(in) :: loc
      character(len=*), intent(in) :: name, units, long_name
      real(dp), intent(in), target, contiguous :: v(:)
      integer(hid_t), intent(out), optional :: keep
      call dset_write(loc, name, H5T_NATIVE_DOUBLE, size(v), c_loc(v), units, long_name, &
                      keep=keep)
    end subroutine dset

    !> A 2-D dataset of doubles v(sector, step) (in the file: crank angle x sector), the
    !> crank angle attached as the scale of its steps.
    subroutine dset2(loc, name, v, units, long_name)
      integer(hid_t), intent(in) :: loc
      character(len=*), intent(in) :: name, units, long_name
      real(dp), intent(in), target, contiguous :: v(:, :)
      call dset_write(loc, name, H5T_NATIVE_DOUBLE, size(v, 2), c_loc(v), units, long_name, &
                      inner=size(v, 1))
    end subroutine dset2

    subroutine dset_int(loc, name, v, units, long_name, description)
      integer(hid_t), intent(in) :: loc
      character(len=*), intent(in) :: name, units, long_name, description
      integer, intent(in), target, contiguous :: v(:)
      call dset_write(loc, name, H5T_NATIVE_INTEGER, size(v), c_loc(v), units, long_name, &
                      description=description)
    end subroutine dset_int

    !> (inner: a 2-D dataset of inner x n values in Fortran order, n the crank steps)
    subroutine dset_write(loc, name, tid, n, buf, units, long_name, description, keep, inner)
      integer(hid_t), intent(in) :: loc, tid
      character(len=*), intent(in) :: name, units, long_name
      integer, intent(in) :: n
      type(c_ptr), intent(in) :: buf
      character(len=*), intent(in), optional :: description
      integer(hid_t), intent(out), optional :: keep
      integer, intent(in), optional :: inner
      integer(hid_t) :: sid, did
      integer(hsize_t) :: dims(2)
      integer :: e, rank
      if (.not. ok) return
      rank = 1
      dims(1) = n
      if (present(inner)) then
        rank = 2
        dims = [int(inner, hsize_t), int(n, hsize_t)]
      end if
      call h5screate_simple_f(rank, dims(1:rank), sid, e)
      if (.not. step(e, 'dataset /cycle/'//name, sid, k_space)) return
      call h5dcreate_f(loc, name, tid, sid, did, e)
      if (.not. step(e, 'dataset /cycle/'//name, did, k_dset)) return
      call h5dwrite_f(did, tid, buf, e)
      if (.not. step(e, 'dataset /cycle/'//name)) return
      call attr_str(did, 'units', units)
      call attr_str(did, 'long_name', long_name)
      if (present(description)) call attr_str(did, 'description', description)
      if (.not. ok) return
      if (present(keep)) then
        call h5dsset_scale_f(did, e, name)
        if (.not. step(e, 'dimension scale /cycle/'//name)) return
        keep = did
        ! close the dataspace under the dataset; the dataset stays open as the scale
        call close_object(sid, k_space, e)
        call forget(sid)
        if (.not. step(e, 'dataset /cycle/'//name)) return
      else
        ! (the index counts the file's dimensions, first the crank steps)
        call h5dsattach_scale_f(did, scale_id, 1, e)
        if (.not. step(e, 'dimension scale of /cycle/'//name)) return
        call close_top(e)   ! dataset
        if (.not. step(e, 'dataset /cycle/'//name)) return
        call close_top(e)   ! its dataspace
        if (.not. step(e, 'dataset /cycle/'//name)) return
      end if
    end subroutine dset_write
  end subroutine write_result

  !> Close one HDF5 object of the given kind.
  subroutine close_object(id, kind, e)
    integer(hid_t), intent(in) :: id
    integer, intent(in) :: kind
    integer, intent(out) :: e
    select case (kind)
    case (k_file)
      call h5fclose_f(id, e)
    case (k_group)
      call h5gclose_f(id, e)
    case (k_dset)
      call h5dclose_f(id, e)
    case (k_space)
      call h5sclose_f(id, e)
    case (k_attr)
      call h5aclose_f(id, e)
    case (k_type)
      call h5tclose_f(id, e)
    case (k_plist)
      call h5pclose_f(id, e)
    case default
      e = -1
    end select
  end subroutine close_object
end module ringlube_hdf5_output
