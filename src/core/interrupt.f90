!> A request to stop: SIGTERM (a scheduler's time limit) or SIGINT (Ctrl-C) noted by a signal
!> handler (interrupt.c) and read by the time loop after each step, which then ends the run
!> cleanly: a last flush, status 'interrupted', exit status 128 + the signal (issue 21 item 18;
!> docs/user/output.md).
module rs_core_interrupt
    use, intrinsic :: iso_c_binding, only: c_int
    implicit none
    private

    public :: install_interrupt_handlers, interrupt_signal, signal_name

    interface
        function c_install() bind(C, name='rs_install_interrupt_handlers') result(status)
            import :: c_int
            integer(c_int) :: status
        end function c_install

        function c_signal() bind(C, name='rs_interrupt_signal') result(signal)
            import :: c_int
            integer(c_int) :: signal
        end function c_signal
    end interface

contains

    !> Catch SIGTERM and SIGINT from now on; false if the system refused.
    logical function install_interrupt_handlers()
        install_interrupt_handlers = c_install() == 0
    end function install_interrupt_handlers

    !> The signal number of a request to stop, 0 if none came.
    integer function interrupt_signal()
        interrupt_signal = int(c_signal())
    end function interrupt_signal

    !> 'SIGTERM', 'SIGINT' or 'signal <n>'.
    function signal_name(signal) result(name)
        integer, intent(in) :: signal
        character(len=:), allocatable :: name
        character(len=12) :: number
        select case (signal)
        case (15)
            name = 'SIGTERM'
        case (2)
            name = 'SIGINT'
        case default
            write(number, '(i0)') signal
            name = 'signal ' // trim(number)
        end select
    end function signal_name

end module rs_core_interrupt
