!> Errors as values: library code returns an allocatable `error_t` (unallocated = success) and
!> callers propagate it (STYLE.md item 12, after fpm's `error_t`). Only the main program turns an
!> error into an exit, through rs_parallel_abort.
!>
!> `error_list_t` collects many independent problems (all input errors of one file) so they can
!> be reported together (DESIGN.md §6).
module rs_core_error
    implicit none
    private

    public :: error_t, error_list_t, set_error, set_petsc_error

    !> Exit status for invalid input (DESIGN.md §6).
    integer, parameter, public :: exit_input_error = 2
    !> Exit status for a failure during the run (solver divergence after all cut-backs, I/O).
    integer, parameter, public :: exit_run_error = 1
    !> Exit status of a run that ended without reaching what it was asked to (&time relaxation
    !> that did not relax by t_end): its records are valid, its answer is not the one asked for.
    integer, parameter, public :: exit_not_reached = 3

    !> One error: what went wrong, where it was detected and with which exit status the program
    !> should stop if nobody handles it.
    type :: error_t
        character(len=:), allocatable :: message
        character(len=:), allocatable :: routine
        character(len=:), allocatable :: file
        integer :: line = 0
        integer :: exit_status = exit_run_error
    contains
        !> The message followed by "(in routine, file:line)".
        procedure :: describe => error_describe
    end type error_t

    !> An ordered list of messages, for reporting every problem of an input at once.
    type :: error_list_t
        character(len=:), allocatable :: text
        integer :: count = 0
    contains
        !> Append one message (one or more lines).
        procedure :: add => error_list_add
        !> All messages, one per line.
        procedure :: joined => error_list_joined
    end type error_list_t

contains

    !> Set `err` (allocating it) with its message and origin; macro RS_SET_ERROR adds file/line.
    subroutine set_error(err, message, routine, file, line, exit_status)
        type(error_t), allocatable, intent(inout) :: err
        character(len=*), intent(in) :: message, routine, file
        integer, intent(in) :: line
        integer, intent(in), optional :: exit_status
        if (allocated(err)) deallocate(err)
        allocate(err)
        err%message = message
        err%routine = routine
        err%file = source_relative(file)
        err%line = line
        if (present(exit_status)) err%exit_status = exit_status
    end subroutine set_error

    !> An error from a PETSc call that returned `ierr`; PETSc has already printed its trace.
    subroutine set_petsc_error(err, ierr, what, routine, file, line)
        type(error_t), allocatable, intent(inout) :: err
        integer, intent(in) :: ierr, line
        character(len=*), intent(in) :: what, routine, file
        character(len=16) :: code
        write(code, '(i0)') ierr
        call set_error(err, 'PETSc call ' // what // ' failed with error code ' // trim(code), &
            routine, file, line)
    end subroutine set_petsc_error

    function error_describe(this) result(text)
        class(error_t), intent(in) :: this
        character(len=:), allocatable :: text
        character(len=16) :: line
        write(line, '(i0)') this%line
        text = this%message
        if (allocated(this%routine)) text = text // ' (in ' // this%routine // ', ' // &
            this%file // ':' // trim(line) // ')'
    end function error_describe

    subroutine error_list_add(this, message)
        class(error_list_t), intent(inout) :: this
        character(len=*), intent(in) :: message
        if (.not. allocated(this%text)) this%text = ''
        if (this%count > 0) this%text = this%text // new_line('a')
        this%text = this%text // message
        this%count = this%count + 1
    end subroutine error_list_add

    function error_list_joined(this) result(text)
        class(error_list_t), intent(in) :: this
        character(len=:), allocatable :: text
        if (allocated(this%text)) then
            text = this%text
        else
            text = ''
        end if
    end function error_list_joined

    !> __FILE__ is absolute in CMake builds; messages show the path from src/ or tests/ on.
    pure function source_relative(path) result(short)
        character(len=*), intent(in) :: path
        character(len=:), allocatable :: short
        integer :: at
        at = max(index(path, '/src/', back=.true.), index(path, '/tests/', back=.true.))
        if (at > 0) then
            short = path(at + 1:)
        else
            short = path
        end if
    end function source_relative

end module rs_core_error
