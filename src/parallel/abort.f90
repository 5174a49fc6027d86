!> Stopping the program: `stop_all` is collective (every rank calls it; rank 0 prints once,
!> libraries are finalized, every rank exits with the same status), `abort_all` is for an error
!> seen by one rank only (that rank prints, MPI_Abort takes all ranks down).
module rs_parallel_abort
    use, intrinsic :: iso_fortran_env, only: error_unit, output_unit
    use, intrinsic :: iso_c_binding, only: c_int
    use mpi
    implicit none
    private

    public :: stop_all, abort_all, set_cleanup

    abstract interface
        !> Finalizes what lives above MPI (PETSc), called once before MPI_Finalize.
        subroutine cleanup_procedure()
        end subroutine cleanup_procedure
    end interface

    procedure(cleanup_procedure), pointer :: registered_cleanup => null()
    logical :: cleanup_pending = .false.

    interface
        subroutine c_exit(status) bind(C, name='exit')
            import :: c_int
            integer(c_int), value :: status
        end subroutine c_exit
    end interface

contains

    !> Register the routine that finalizes PETSc (and with it MPI) on the way out.
    subroutine set_cleanup(routine)
        procedure(cleanup_procedure) :: routine
        registered_cleanup => routine
        cleanup_pending = .true.
    end subroutine set_cleanup

    !> Collective stop with exit `status`: rank 0 prints `message` (if any) on standard error.
    subroutine stop_all(status, message)
        integer, intent(in) :: status
        character(len=*), intent(in), optional :: message
        integer :: rank, ierr
        logical :: initialized, finalized
        call MPI_Initialized(initialized, ierr)
        rank = 0
        if (initialized) then
            call MPI_Finalized(finalized, ierr)
            if (.not. finalized) call MPI_Comm_rank(MPI_COMM_WORLD, rank, ierr)
        end if
        if (present(message) .and. rank == 0) then
            if (len(message) > 0) write(error_unit, '(a)') message
        end if
        flush(output_unit)
        flush(error_unit)
        if (cleanup_pending) then
            cleanup_pending = .false.
            call registered_cleanup()
        end if
        call MPI_Initialized(initialized, ierr)
        if (initialized) then
            call MPI_Finalized(finalized, ierr)
            if (.not. finalized) call MPI_Finalize(ierr)
        end if
        call c_exit(int(status, c_int))
    end subroutine stop_all

    !> Non-collective abort: this rank prints `message` with its rank and all ranks stop.
    subroutine abort_all(status, message)
        integer, intent(in) :: status
        character(len=*), intent(in) :: message
        integer :: rank, ierr
        call MPI_Comm_rank(MPI_COMM_WORLD, rank, ierr)
        write(error_unit, '(a,i0,a)') '[rank ', rank, '] ' // message
        flush(error_unit)
        call MPI_Abort(MPI_COMM_WORLD, status, ierr)
    end subroutine abort_all

end module rs_parallel_abort
