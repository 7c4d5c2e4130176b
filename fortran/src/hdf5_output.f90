!> Writing a result to HDF5 in the layout of SPEC section 9.
!>
!> The file is written under a temporary name (`FILE.part`) and renamed to its final
!> name only when complete, so an interrupted run never leaves a half-written result.
module ringlube_hdf5_output
  use, intrinsic :: iso_c_binding, only: c_int, c_char, c_null_char
  use ringlube_kinds, only: dp
  use ringlube_error, only: error_type, fatal_error, rl_runtime_error
  use ringlube_case, only: case_type, composite_sigma
  use ringlube_results, only: result_type, result_scalar, scalar_spec, n_scalars, series_spec, &
    n_series, int_series_spec, n_int_series, series_ptr, int_series_ptr, flag_description
  use ringlube_version, only: package_version
  use hdf5
  implicit none
  private
  public :: write_result, remove_file

  interface
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

  !> Delete a file if it exists (no error if it does not).
  subroutine remove_file(path)
    character(len=*), intent(in) :: path
    integer(c_int) :: rc
    rc = c_unlink(path // c_null_char)
  end subroutine remove_file

  !> Write the result of case `c` to `path` (atomically, via `path.part`).
  subroutine write_result(path, c, res, runtime_s, err)
    character(len=*), intent(in) :: path
    type(case_type), intent(in) :: c
    type(result_type), intent(in), target :: res
    real(dp), intent(in) :: runtime_s
    type(error_type), allocatable, intent(out) :: err
    character(len=:), allocatable :: tmp
    integer(hid_t) :: fid, gid
    integer :: herr, i
    type(result_type) :: r
    real(dp) :: v

    r = res
    r%run_time = runtime_s
    tmp = path // '.part'
    call h5open_f(herr)
    if (herr /= 0) then
      call fatal_error(err, 'HDF5 library could not be initialised', rl_runtime_error)
      return
    end if
    call h5eset_auto_f(0, herr)
    call h5fcreate_f(tmp, H5F_ACC_TRUNC_F, fid, herr)
    if (herr /= 0) then
      call fatal_error(err, tmp // ': cannot create HDF5 file', rl_runtime_error)
      return
    end if
    do i = 1, n_scalars
      call result_scalar(r, i, v, .false.)
      if (scalar_spec(i)%integer_valued) then
        call attr_int(fid, trim(scalar_spec(i)%stored), nint(v))
      else
        call attr_real(fid, trim(scalar_spec(i)%stored), v)
      end if
    end do
    call attr_str(fid, 'deck', c%deck_text)
    call attr_str(fid, 'deck_path', c%deck_path)
    call attr_str(fid, 'pressure_file', c%pressure_file)
    call attr_str(fid, 'ringlube_version', package_version)
    if (herr /= 0) goto 900

    call h5gcreate_f(fid, 'cycle', gid, herr)
    if (herr /= 0) goto 900
    do i = 1, n_series
      call dset(gid, trim(series_spec(i)%stored), series_ptr(res, i), trim(series_spec(i)%unit))
    end do
    do i = 1, n_int_series
      if (trim(int_series_spec(i)%stored) == 'flags') then
        call dset_int(gid, trim(int_series_spec(i)%stored), int_series_ptr(res, i), &
          trim(int_series_spec(i)%unit), flag_description())
      else
        call dset_int(gid, trim(int_series_spec(i)%stored), int_series_ptr(res, i), &
          trim(int_series_spec(i)%unit), trim(int_series_spec(i)%long_name))
      end if
    end do
    call h5gclose_f(gid, herr)
    if (herr /= 0) goto 900
    call h5fclose_f(fid, herr)
    if (herr /= 0) goto 900
    if (c_rename(tmp // c_null_char, path // c_null_char) /= 0) then
      call remove_file(tmp)
      call fatal_error(err, path // ': cannot move the finished result into place', &
        rl_runtime_error)
    end if
    return

900 continue
    call h5fclose_f(fid, herr)
    call remove_file(tmp)
    call fatal_error(err, tmp // ': error while writing HDF5 data', rl_runtime_error)

  contains

    subroutine attr_real(loc, name, v)
      integer(hid_t), intent(in) :: loc
      character(len=*), intent(in) :: name
      real(dp), intent(in) :: v
      integer(hid_t) :: sid, aid
      integer(hsize_t) :: dims(1) = [1]
      integer :: e
      call h5screate_f(H5S_SCALAR_F, sid, e)
      call h5acreate_f(loc, name, H5T_NATIVE_DOUBLE, sid, aid, e)
      call h5awrite_f(aid, H5T_NATIVE_DOUBLE, v, dims, e)
      call h5aclose_f(aid, e)
      call h5sclose_f(sid, e)
      if (e /= 0) herr = e
    end subroutine attr_real

    subroutine attr_int(loc, name, v)
      integer(hid_t), intent(in) :: loc
      character(len=*), intent(in) :: name
      integer, intent(in) :: v
      integer(hid_t) :: sid, aid
      integer(hsize_t) :: dims(1) = [1]
      integer :: e
      call h5screate_f(H5S_SCALAR_F, sid, e)
      call h5acreate_f(loc, name, H5T_NATIVE_INTEGER, sid, aid, e)
      call h5awrite_f(aid, H5T_NATIVE_INTEGER, v, dims, e)
      call h5aclose_f(aid, e)
      call h5sclose_f(sid, e)
      if (e /= 0) herr = e
    end subroutine attr_int

    subroutine attr_str(loc, name, v)
      integer(hid_t), intent(in) :: loc
      character(len=*), intent(in) :: name, v
      integer(hid_t) :: sid, aid, tid
      integer(hsize_t) :: dims(1) = [1]
      integer :: e
      character(len=max(len(v), 1)) :: buf
      buf = v
      call h5screate_f(H5S_SCALAR_F, sid, e)
      call h5tcopy_f(H5T_FORTRAN_S1, tid, e)
      call h5tset_size_f(tid, int(len(buf), size_t), e)
      call h5tset_strpad_f(tid, H5T_STR_NULLPAD_F, e)
      call h5acreate_f(loc, name, tid, sid, aid, e)
      call h5awrite_f(aid, tid, buf, dims, e)
      call h5aclose_f(aid, e)
      call h5tclose_f(tid, e)
      call h5sclose_f(sid, e)
      if (e /= 0) herr = e
    end subroutine attr_str

    subroutine dset(loc, name, v, units)
      integer(hid_t), intent(in) :: loc
      character(len=*), intent(in) :: name, units
      real(dp), intent(in) :: v(:)
      integer(hid_t) :: sid, did
      integer(hsize_t) :: dims(1)
      integer :: e
      dims(1) = size(v)
      call h5screate_simple_f(1, dims, sid, e)
      call h5dcreate_f(loc, name, H5T_NATIVE_DOUBLE, sid, did, e)
      call h5dwrite_f(did, H5T_NATIVE_DOUBLE, v, dims, e)
      call attr_str(did, 'units', units)
      call h5dclose_f(did, e)
      call h5sclose_f(sid, e)
      if (e /= 0) herr = e
    end subroutine dset

    subroutine dset_int(loc, name, v, units, description)
      integer(hid_t), intent(in) :: loc
      character(len=*), intent(in) :: name, units, description
      integer, intent(in) :: v(:)
      integer(hid_t) :: sid, did
      integer(hsize_t) :: dims(1)
      integer :: e
      dims(1) = size(v)
      call h5screate_simple_f(1, dims, sid, e)
      call h5dcreate_f(loc, name, H5T_NATIVE_INTEGER, sid, did, e)
      call h5dwrite_f(did, H5T_NATIVE_INTEGER, v, dims, e)
      call attr_str(did, 'units', units)
      call attr_str(did, 'description', description)
      call h5dclose_f(did, e)
      call h5sclose_f(sid, e)
      if (e /= 0) herr = e
    end subroutine dset_int
  end subroutine write_result
end module ringlube_hdf5_output
