!> Facts about the HDF5 library rodsolve writes with (only src/io/ calls HDF5, STYLE.md item 6).
module rs_io_hdf5_info
    use hdf5, only: h5open_f, h5get_libversion_f
    use rs_core_strings, only: str
    implicit none
    private

    public :: hdf5_version

contains

    !> "major.minor.release" of the linked HDF5 library.
    function hdf5_version() result(text)
        character(len=:), allocatable :: text
        integer :: major, minor, release, status
        call h5open_f(status)
        call h5get_libversion_f(major, minor, release, status)
        if (status /= 0) then
            text = 'unknown'
        else
            text = str(major) // '.' // str(minor) // '.' // str(release)
        end if
    end function hdf5_version

end module rs_io_hdf5_info
