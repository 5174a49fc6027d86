!> Wall-clock timers for the run summary and benchmarks (DESIGN.md §9). A timer accumulates
!> over start/stop pairs, so one timer can measure all assembly calls of a run.
module rs_core_timer
    use rs_core_kinds, only: rk, i8
    implicit none
    private

    public :: timer_t, wall_time

    !> An accumulating stopwatch.
    type :: timer_t
        integer(i8) :: started = -1
        real(rk) :: total = 0.0_rk
        integer :: laps = 0
    contains
        procedure :: start => timer_start
        procedure :: stop => timer_stop
        procedure :: reset => timer_reset
        !> Accumulated seconds, including a lap still running.
        procedure :: seconds => timer_seconds
    end type timer_t

contains

    !> Seconds since an arbitrary fixed origin.
    real(rk) function wall_time()
        integer(i8) :: count, rate
        call system_clock(count, rate)
        wall_time = real(count, rk) / real(rate, rk)
    end function wall_time

    subroutine timer_start(this)
        class(timer_t), intent(inout) :: this
        integer(i8) :: rate
        call system_clock(this%started, rate)
    end subroutine timer_start

    subroutine timer_stop(this)
        class(timer_t), intent(inout) :: this
        integer(i8) :: now, rate
        if (this%started < 0) return
        call system_clock(now, rate)
        this%total = this%total + real(now - this%started, rk) / real(rate, rk)
        this%started = -1
        this%laps = this%laps + 1
    end subroutine timer_stop

    subroutine timer_reset(this)
        class(timer_t), intent(inout) :: this
        this%started = -1
        this%total = 0.0_rk
        this%laps = 0
    end subroutine timer_reset

    real(rk) function timer_seconds(this)
        class(timer_t), intent(in) :: this
        integer(i8) :: now, rate
        timer_seconds = this%total
        if (this%started >= 0) then
            call system_clock(now, rate)
            timer_seconds = timer_seconds + real(now - this%started, rk) / real(rate, rk)
        end if
    end function timer_seconds

end module rs_core_timer
