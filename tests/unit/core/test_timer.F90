#include "rs_assert.h"
!> Unit tests of rs_core_timer: wall_time never goes back; a timer measures at least the time
!> spent between start and stop (by wall_time, the same clock) and at most the time around
!> the calls; laps accumulate; a running lap counts in seconds(); stop without start and reset.
module rs_test_core_timer
    use rs_core_kinds, only: rk
    use rs_test_assert, only: run_test, assert_true, assert_equal, assert_close
    use rs_core_timer, only: timer_t, wall_time
    implicit none
    private

    public :: run_all_tests

    !> Relative slack for comparing two differences of the same clock read in different ways.
    real(rk), parameter :: slack = 1.0e-9_rk

contains

    !> Run every test of this file through rs_test_assert.
    subroutine run_all_tests()
        call run_test('wall_time_monotone', test_wall_time_monotone)
        call run_test('new_timer_is_zero', test_new_timer_is_zero)
        call run_test('one_lap_bounds', test_one_lap_bounds)
        call run_test('laps_accumulate', test_laps_accumulate)
        call run_test('running_lap_counts', test_running_lap_counts)
        call run_test('reset', test_reset)
    end subroutine run_all_tests

    !> Spin until wall_time has advanced by `seconds`.
    subroutine busy_wait(seconds)
        real(rk), intent(in) :: seconds
        real(rk) :: t0
        t0 = wall_time()
        do while (wall_time() - t0 < seconds)
        end do
    end subroutine busy_wait

    subroutine test_wall_time_monotone()
        real(rk) :: previous, now, t0
        integer :: i, n_back
        n_back = 0
        t0 = wall_time()
        previous = t0
        do i = 1, 100000
            now = wall_time()
            if (now < previous) n_back = n_back + 1
            previous = now
        end do
        CHECK_EQUAL(n_back, 0, 'wall_time went back')
        CHECK_TRUE(previous > t0, 'advances within 100000 calls')
    end subroutine test_wall_time_monotone

    subroutine test_new_timer_is_zero()
        type(timer_t) :: t
        CHECK_CLOSE(t%seconds(), 0.0_rk, 0.0_rk, 0.0_rk, 'no time before start')
        CHECK_EQUAL(t%laps, 0, 'no laps')
        call t%stop()
        CHECK_EQUAL(t%laps, 0, 'stop without start is not a lap')
        CHECK_CLOSE(t%seconds(), 0.0_rk, 0.0_rk, 0.0_rk, 'stop without start adds nothing')
    end subroutine test_new_timer_is_zero

    subroutine test_one_lap_bounds()
        type(timer_t) :: t
        real(rk) :: outer_start, outer
        outer_start = wall_time()
        call t%start()
        call busy_wait(0.02_rk)
        call t%stop()
        outer = wall_time() - outer_start
        CHECK_EQUAL(t%laps, 1, 'one lap')
        CHECK_TRUE(t%seconds() >= 0.02_rk * (1.0_rk - slack), 'at least the busy wait')
        CHECK_TRUE(t%seconds() <= outer * (1.0_rk + slack), 'at most the time around it')
        CHECK_CLOSE(t%seconds(), t%total, 0.0_rk, 0.0_rk, 'stopped: seconds() is the total')
        call busy_wait(0.01_rk)
        CHECK_CLOSE(t%seconds(), t%total, 0.0_rk, 0.0_rk, 'stopped timer does not advance')
    end subroutine test_one_lap_bounds

    ! Time between laps is not counted; two laps of >= 10 ms and >= 20 ms make >= 30 ms.
    subroutine test_laps_accumulate()
        type(timer_t) :: t
        real(rk) :: outer_start, outer, first
        outer_start = wall_time()
        call t%start()
        call busy_wait(0.01_rk)
        call t%stop()
        first = t%seconds()
        call busy_wait(0.05_rk)
        call t%start()
        call busy_wait(0.02_rk)
        call t%stop()
        outer = wall_time() - outer_start
        CHECK_EQUAL(t%laps, 2, 'two laps')
        CHECK_TRUE(t%seconds() >= 0.03_rk * (1.0_rk - slack), 'sum of the laps')
        CHECK_TRUE(t%seconds() - first >= 0.02_rk * (1.0_rk - slack), 'second lap added')
        CHECK_TRUE(t%seconds() <= outer - 0.05_rk * (1.0_rk - slack), 'pause excluded')
    end subroutine test_laps_accumulate

    subroutine test_running_lap_counts()
        type(timer_t) :: t
        real(rk) :: s1, s2
        call t%start()
        call busy_wait(0.01_rk)
        s1 = t%seconds()
        call busy_wait(0.01_rk)
        s2 = t%seconds()
        CHECK_TRUE(s1 >= 0.01_rk * (1.0_rk - slack), 'running lap included')
        CHECK_TRUE(s2 >= s1 + 0.01_rk * (1.0_rk - slack), 'seconds() grows while running')
        CHECK_EQUAL(t%laps, 0, 'a running lap is not yet counted')
        CHECK_CLOSE(t%total, 0.0_rk, 0.0_rk, 0.0_rk, 'total not touched while running')
        call t%stop()
        CHECK_TRUE(t%seconds() >= s2, 'stop keeps the running time')
    end subroutine test_running_lap_counts

    subroutine test_reset()
        type(timer_t) :: t
        call t%start()
        call busy_wait(0.005_rk)
        call t%stop()
        call t%start()
        call t%reset()
        CHECK_CLOSE(t%seconds(), 0.0_rk, 0.0_rk, 0.0_rk, 'reset clears total and running lap')
        CHECK_EQUAL(t%laps, 0, 'reset clears the laps')
        call t%stop()
        CHECK_EQUAL(t%laps, 0, 'reset stopped the running lap')
    end subroutine test_reset

end module rs_test_core_timer

!> Test program: runs the tests of rs_test_core_timer; exits non-zero if any failed.
program test_timer
    use rs_test_core_timer, only: run_all_tests
    use rs_test_assert, only: finish_tests
    implicit none
    call run_all_tests()
    call finish_tests()
end program test_timer
