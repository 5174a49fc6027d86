!> The MPI facts and collectives rodsolve needs outside PETSc: rank, size, broadcasts of the
!> input text and of flags. Only src/parallel/ calls MPI (STYLE.md item 6). MPI is initialized
!> by PETSc (src/solver/petsc_env.F90); these routines run between PetscInitialize and
!> PetscFinalize.
!>
!> They act on the ACTIVE communicator: MPI_COMM_WORLD, or MPI_COMM_SELF between `work_alone`
!> and `work_together`. A sweep (DESIGN.md §5) runs each member as a whole scene on one rank
!> that way, so the code of a scene run (its "rank 0", its collectives) needs no sweep mode:
!> world_rank is 0 and world_size 1 while alone, and every collective involves this process
!> only. Outside that bracket "world" means MPI_COMM_WORLD.
module rs_parallel_mpi_env
    use mpi
    use rs_core_error, only: error_t, set_error
    implicit none
    private

    public :: world_rank, world_size, is_root, broadcast_text, broadcast_flag, barrier
    public :: mpi_library_version, any_rank_true, sum_over_ranks
    public :: max_over_ranks, broadcast_array, max_each_over_ranks
    public :: work_alone, work_together, working_alone, true_rank

    !> The active communicator (see the module header).
    integer :: active = MPI_COMM_WORLD

    !> Give every rank the whole array `root` holds (allocated to its length on the others).
    interface broadcast_array
        module procedure broadcast_reals, broadcast_integers
    end interface broadcast_array

contains

    !> From now on the collectives and world_rank / world_size involve this process only.
    subroutine work_alone()
        active = MPI_COMM_SELF
    end subroutine work_alone

    !> Back to MPI_COMM_WORLD.
    subroutine work_together()
        active = MPI_COMM_WORLD
    end subroutine work_together

    !> True between work_alone and work_together.
    logical function working_alone()
        working_alone = active == MPI_COMM_SELF
    end function working_alone

    !> This process's rank in MPI_COMM_WORLD, alone or not (for messages and file names).
    integer function true_rank()
        integer :: ierr
        call MPI_Comm_rank(MPI_COMM_WORLD, true_rank, ierr)
    end function true_rank

    !> This process's rank in the active communicator.
    integer function world_rank()
        integer :: ierr
        call MPI_Comm_rank(active, world_rank, ierr)
    end function world_rank

    !> Number of processes in the active communicator.
    integer function world_size()
        integer :: ierr
        call MPI_Comm_size(active, world_size, ierr)
    end function world_size

    !> True on rank 0, the rank that reads input, prints and writes serial output.
    logical function is_root()
        is_root = world_rank() == 0
    end function is_root

    !> Send `text` (allocated on `root` only) to every rank; every rank ends with the same text.
    subroutine broadcast_text(text, root)
        character(len=:), allocatable, intent(inout) :: text
        integer, intent(in) :: root
        integer :: length, ierr
        if (world_rank() == root) length = len(text)
        call MPI_Bcast(length, 1, MPI_INTEGER, root, active, ierr)
        if (world_rank() /= root) then
            if (allocated(text)) deallocate(text)
            allocate(character(len=length) :: text)
        end if
        if (length > 0) call MPI_Bcast(text, length, MPI_CHARACTER, root, active, ierr)
    end subroutine broadcast_text

    !> Give every rank the value `flag` has on `root`.
    subroutine broadcast_flag(flag, root)
        logical, intent(inout) :: flag
        integer, intent(in) :: root
        integer :: ierr
        call MPI_Bcast(flag, 1, MPI_LOGICAL, root, active, ierr)
    end subroutine broadcast_flag

    !> True on every rank if `flag` is true on any rank.
    logical function any_rank_true(flag)
        logical, intent(in) :: flag
        integer :: ierr
        call MPI_Allreduce(flag, any_rank_true, 1, MPI_LOGICAL, MPI_LOR, active, ierr)
    end function any_rank_true

    !> Sum of an integer over all ranks, on every rank.
    integer function sum_over_ranks(value)
        integer, intent(in) :: value
        integer :: ierr
        call MPI_Allreduce(value, sum_over_ranks, 1, MPI_INTEGER, MPI_SUM, active, ierr)
    end function sum_over_ranks

    !> Largest value of a real over all ranks, on every rank.
    real(kind(1.0d0)) function max_over_ranks(value)
        real(kind(1.0d0)), intent(in) :: value
        integer :: ierr
        call MPI_Allreduce(value, max_over_ranks, 1, MPI_DOUBLE_PRECISION, MPI_MAX, &
            active, ierr)
    end function max_over_ranks

    subroutine broadcast_reals(values, root)
        real(kind(1.0d0)), allocatable, intent(inout) :: values(:)
        integer, intent(in) :: root
        integer :: n, ierr
        if (world_rank() == root) n = size(values)
        call MPI_Bcast(n, 1, MPI_INTEGER, root, active, ierr)
        if (world_rank() /= root) then
            if (allocated(values)) deallocate(values)
            allocate(values(n))
        end if
        if (n > 0) call MPI_Bcast(values, n, MPI_DOUBLE_PRECISION, root, active, ierr)
    end subroutine broadcast_reals

    subroutine broadcast_integers(values, root)
        integer, allocatable, intent(inout) :: values(:)
        integer, intent(in) :: root
        integer :: n, ierr
        if (world_rank() == root) n = size(values)
        call MPI_Bcast(n, 1, MPI_INTEGER, root, active, ierr)
        if (world_rank() /= root) then
            if (allocated(values)) deallocate(values)
            allocate(values(n))
        end if
        if (n > 0) call MPI_Bcast(values, n, MPI_INTEGER, root, active, ierr)
    end subroutine broadcast_integers

    !> Element by element, the largest value over all ranks, on every rank (in place).
    subroutine max_each_over_ranks(values)
        integer, intent(inout) :: values(:)
        integer :: ierr
        if (size(values) == 0) return
        call MPI_Allreduce(MPI_IN_PLACE, values, size(values), MPI_INTEGER, MPI_MAX, &
            active, ierr)
    end subroutine max_each_over_ranks

    !> Wait for all ranks.
    subroutine barrier()
        integer :: ierr
        call MPI_Barrier(active, ierr)
    end subroutine barrier

    !> The MPI library's own version line (MPI_Get_library_version), first line only.
    function mpi_library_version() result(text)
        character(len=:), allocatable :: text
        character(len=MPI_MAX_LIBRARY_VERSION_STRING) :: buffer
        integer :: length, ierr, eol
        call MPI_Get_library_version(buffer, length, ierr)
        text = buffer(1:length)
        eol = scan(text, new_line('a') // ',')
        if (eol > 0) text = text(1:eol - 1)
    end function mpi_library_version

end module rs_parallel_mpi_env
