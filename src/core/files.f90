!> Files and directories beyond what Fortran's I/O statements do.
module rs_core_files
    use, intrinsic :: iso_c_binding, only: c_char, c_int
    use rs_core_strings, only: to_c_string
    implicit none
    private

    public :: make_directories

    interface
        function c_mkdir(path, mode) bind(C, name='mkdir') result(status)
            import :: c_char, c_int
            character(kind=c_char), intent(in) :: path(*)
            integer(c_int), value :: mode
            integer(c_int) :: status
        end function c_mkdir
    end interface

contains

    !> `mkdir -p directory` (mode 0777 less the umask): failures are ignored here and detected
    !> by the caller's own check when it uses the directory.
    subroutine make_directories(directory)
        character(len=*), intent(in) :: directory
        integer :: i, status
        do i = 2, len(directory) + 1
            if (i <= len(directory)) then
                if (directory(i:i) /= '/') cycle
            end if
            status = c_mkdir(to_c_string(directory(1:i - 1)), int(o'777', c_int))
        end do
    end subroutine make_directories

end module rs_core_files
