!> Writing a result to HDF5 in the layout of SPEC section 9.
!>
!> The file is written under a temporary name (`FILE.part`) and renamed to its final
!> name only when complete, so an interrupted run never leaves a half-written result.
module ringlube_hdf5_output
  use, intrinsic :: iso_c_binding, only: c_int, c_char, c_null_char
  use ringlube_kinds, only: dp
  use ringlube_error, only: error_type, fatal_error, rl_runtime_error
  use ringlube_case, only: case_type, composite_sigma
  use ringlube_cycle, only: result_type
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
    type(result_type), intent(in) :: res
    real(dp), intent(in) :: runtime_s
    type(error_type), allocatable, intent(out) :: err
    character(len=:), allocatable :: tmp
    integer(hid_t) :: fid, gid
    integer :: herr, conv

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
    conv = 0
    if (res%converged) conv = 1
    call attr_real(fid, 'energy_loss_J', res%energy_loss)
    call attr_real(fid, 'mixed_share_pct', res%mixed_share)
    call attr_real(fid, 'ring_mass_g', res%ring_mass * 1e3_dp)
    call attr_real(fid, 'min_film_m', res%min_film)
    call attr_real(fid, 'max_friction_N', res%max_friction)
    call attr_int(fid, 'converged', conv)
    call attr_int(fid, 'cycles_run', res%cycles_run)
    call attr_real(fid, 'cycle_change', res%cycle_change)
    call attr_real(fid, 'sigma_m', composite_sigma(c))
    call attr_real(fid, 'run_time_s', runtime_s)
    call attr_int(fid, 'film_solves', res%evaluations)
    call attr_int(fid, 'reynolds_solves', res%reynolds_solves)
    call attr_real(fid, 'cycles_computed', res%cycles_computed)
    call attr_str(fid, 'deck', c%deck_text)
    call attr_str(fid, 'deck_path', c%deck_path)
    call attr_str(fid, 'pressure_file', c%pressure_file)
    call attr_str(fid, 'ringlube_version', package_version)
    if (herr /= 0) goto 900

    call h5gcreate_f(fid, 'cycle', gid, herr)
    if (herr /= 0) goto 900
    call dset(gid, 'crank_angle_deg', res%crank_angle_deg, 'deg')
    call dset(gid, 'sliding_speed_m_s', res%sliding_speed, 'm/s')
    call dset(gid, 'h0_m', res%h0, 'm')
    call dset(gid, 'lambda_min', res%lambda_min, '1')
    call dset(gid, 'gas_pressure_Pa', res%gas_pressure, 'Pa')
    call dset(gid, 'applied_load_N', res%applied_load, 'N')
    call dset(gid, 'hydrodynamic_load_N', res%hydrodynamic_load, 'N')
    call dset(gid, 'asperity_load_N', res%asperity_load, 'N')
    call dset(gid, 'viscous_friction_N', res%viscous_friction, 'N')
    call dset(gid, 'boundary_friction_N', res%boundary_friction, 'N')
    call dset(gid, 'friction_N', res%friction, 'N')
    call dset(gid, 'power_loss_W', res%power_loss, 'W')
    call dset(gid, 'load_residual', res%load_residual, '1')
    call dset_int(gid, 'flags', res%flags, '1', &
      '1: h0 at h0_floor, 2: h0 at h0_ceiling, 4: load outside load_tol, ' // &
      '8: pressure-viscosity loop not converged, 16: cavitation set not settled, ' // &
      '32: film pressure above 1 GPa (Roelands clipped)')
    call dset_int(gid, 'film_solves', res%iterations, '1', &
      'film (Reynolds + contact) solves used by the load balance at this step')
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
