!> Facts about the HDF5 library rodsolve writes with (only src/io/ calls HDF5, STYLE.md item 6).
module rs_io_hdf5_info
    use hdf5, only: h5open_f, h5get_libversion_f
    use rs_core_strings, only: str
    implicit none
    private

    public :: hdf5_version, hdf5_open_library

contains

    !> The Fortran API of HDF5, initialized once per process. h5open_f copies the predefined
    !> datatypes anew at every call and then counts every open identifier (H5Fget_obj_count),
    !> so calling it at every file open (and for the version in every result file's root) made
    !> each call slower than the one before: a sweep, which opens its scratch file and writes a
    !> root for every member, paid 41 ms a member at 100 members and 56 ms at 300 (13 % of its
    !> time in H5T_is_named), 29 ms in its first 100 members of 1000 and 120 ms in its last.
    subroutine hdf5_open_library(status)
        integer, intent(out) :: status
        logical, save :: opened = .false.
        status = 0
        if (opened) return
        call h5open_f(status)
        opened = status == 0
    end subroutine hdf5_open_library

    !> "major.minor.release" of the linked HDF5 library.
    function hdf5_version() result(text)
        character(len=:), allocatable :: text
        integer :: major, minor, release, status
        call hdf5_open_library(status)
        call h5get_libversion_f(major, minor, release, status)
        if (status /= 0) then
            text = 'unknown'
        else
            text = str(major) // '.' // str(minor) // '.' // str(release)
        end if
    end function hdf5_version

end module rs_io_hdf5_info
