!> Rank-0 logging with levels. The rank is handed in at start-up (core knows no MPI); every rank
!> may call the logging routines, only rank 0 prints. Errors that concern one rank only are
!> printed by rs_parallel_abort, not here.
module rs_core_logger
    use, intrinsic :: iso_fortran_env, only: output_unit, error_unit
    implicit none
    private

    public :: logger_init, log_error, log_warning, log_info, log_debug, log_level_from_name
    public :: logger_prints, logger_level, logger_set_level

    integer, parameter, public :: level_error = 0, level_warning = 1, level_info = 2, level_debug = 3

    integer :: my_rank = 0
    integer :: threshold = level_info

contains

    !> Set this process's rank and the most detailed level printed (`quiet` keeps warnings and
    !> errors only).
    subroutine logger_init(rank, level, quiet)
        integer, intent(in) :: rank
        integer, intent(in), optional :: level
        logical, intent(in), optional :: quiet
        my_rank = rank
        threshold = level_info
        if (present(level)) threshold = level
        if (present(quiet)) then
            if (quiet) threshold = min(threshold, level_warning)
        end if
    end subroutine logger_init

    !> Level number of 'error', 'warning', 'info' or 'debug'; -1 for another name.
    pure integer function log_level_from_name(name) result(level)
        character(len=*), intent(in) :: name
        select case (name)
        case ('error')
            level = level_error
        case ('warning')
            level = level_warning
        case ('info')
            level = level_info
        case ('debug')
            level = level_debug
        case default
            level = -1
        end select
    end function log_level_from_name

    !> The most detailed level printed now.
    integer function logger_level()
        logger_level = threshold
    end function logger_level

    !> Print messages up to `level` from now on (a sweep quietens its members' runs).
    subroutine logger_set_level(level)
        integer, intent(in) :: level
        threshold = level
    end subroutine logger_set_level

    !> True on the rank that prints messages of `level`.
    logical function logger_prints(level)
        integer, intent(in) :: level
        logger_prints = my_rank == 0 .and. level <= threshold
    end function logger_prints

    !> An error of the whole run, on standard error.
    subroutine log_error(message)
        character(len=*), intent(in) :: message
        if (logger_prints(level_error)) call emit(error_unit, 'error: ', message)
    end subroutine log_error

    !> Something the user should know about, on standard error.
    subroutine log_warning(message)
        character(len=*), intent(in) :: message
        if (logger_prints(level_warning)) call emit(error_unit, 'warning: ', message)
    end subroutine log_warning

    !> Progress and results, on standard output.
    subroutine log_info(message)
        character(len=*), intent(in) :: message
        if (logger_prints(level_info)) call emit(output_unit, '', message)
    end subroutine log_info

    !> Details for developers, on standard output.
    subroutine log_debug(message)
        character(len=*), intent(in) :: message
        if (logger_prints(level_debug)) call emit(output_unit, 'debug: ', message)
    end subroutine log_debug

    subroutine emit(unit, prefix, message)
        integer, intent(in) :: unit
        character(len=*), intent(in) :: prefix, message
        write(unit, '(a)') prefix // message
        flush(unit)
    end subroutine emit

end module rs_core_logger
