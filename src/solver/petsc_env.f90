!> PETSc's life cycle in rodsolve: initialization with the options rodsolve did not consume,
!> finalization, and the versions of PETSc and of the MUMPS it solves with.
module rs_solver_petsc_env
    use, intrinsic :: iso_c_binding, only: c_int, c_char, c_null_char
    use rs_core_error, only: error_t, set_error
    use rs_core_strings, only: str
    implicit none
    private

    public :: petsc_initialize, petsc_finalize, petsc_is_initialized, petsc_version, mumps_version

    interface
        integer(c_int) function rs_petsc_initialize(count, args, total_length) bind(C)
            import :: c_int, c_char
            integer(c_int), value :: count, total_length
            character(kind=c_char), intent(in) :: args(*)
        end function rs_petsc_initialize
        integer(c_int) function rs_petsc_finalize() bind(C)
            import :: c_int
        end function rs_petsc_finalize
        integer(c_int) function rs_petsc_initialized() bind(C)
            import :: c_int
        end function rs_petsc_initialized
        subroutine rs_petsc_version(buffer, length) bind(C)
            import :: c_char, c_int
            character(kind=c_char), intent(out) :: buffer(*)
            integer(c_int), value :: length
        end subroutine rs_petsc_version
        subroutine rs_mumps_version(buffer, length) bind(C)
            import :: c_char, c_int
            character(kind=c_char), intent(out) :: buffer(*)
            integer(c_int), value :: length
        end subroutine rs_mumps_version
    end interface

contains

    !> Initialize PETSc (and with it MPI) with `program` as argv(0) and `options` as the rest.
    subroutine petsc_initialize(program, options, err)
        character(len=*), intent(in) :: program
        character(len=*), intent(in) :: options(:)
        type(error_t), allocatable, intent(out) :: err
        character(len=:), allocatable :: packed
        integer :: i
        integer(c_int) :: ierr
        packed = trim(program) // c_null_char
        do i = 1, size(options)
            packed = packed // trim(options(i)) // c_null_char
        end do
        ierr = rs_petsc_initialize(int(size(options) + 1, c_int), packed, int(len(packed), c_int))
        if (ierr /= 0) call set_error(err, 'PetscInitialize failed with error code ' // &
            str(int(ierr)), 'petsc_initialize', __FILE__, __LINE__)
    end subroutine petsc_initialize

    !> Finalize PETSc (which finalizes MPI, since PETSc initialized it); safe to call twice.
    subroutine petsc_finalize()
        integer(c_int) :: ierr
        if (rs_petsc_initialized() == 1) ierr = rs_petsc_finalize()
    end subroutine petsc_finalize

    !> True between petsc_initialize and petsc_finalize.
    logical function petsc_is_initialized()
        petsc_is_initialized = rs_petsc_initialized() == 1
    end function petsc_is_initialized

    !> PETSc's version line.
    function petsc_version() result(text)
        character(len=:), allocatable :: text
        text = c_text(0)
    end function petsc_version

    !> Version of the linked MUMPS (needs MPI initialized).
    function mumps_version() result(text)
        character(len=:), allocatable :: text
        text = c_text(1)
    end function mumps_version

    function c_text(which) result(text)
        integer, intent(in) :: which
        character(len=:), allocatable :: text
        character(kind=c_char) :: buffer(256)
        integer :: n
        buffer = c_null_char
        if (which == 0) then
            call rs_petsc_version(buffer, 256_c_int)
        else
            call rs_mumps_version(buffer, 256_c_int)
        end if
        n = 0
        do while (n < size(buffer))
            if (buffer(n + 1) == c_null_char) exit
            n = n + 1
        end do
        allocate(character(len=n) :: text)
        text = transfer(buffer(1:n), text)
    end function c_text

end module rs_solver_petsc_env
