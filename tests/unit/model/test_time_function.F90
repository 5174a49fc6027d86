#include "rs_assert.h"
!> Unit tests of rs_model_time_function: every kind against its definition in the module header
!> at characteristic points and on dense grids (constant 1; ramp 0 / linear / 1; hat 0 / up /
!> down / 0 with the flying-spaghetti history 200 hat(t) = 80 t, 400 - 80 t on [0, 5]; pulse
!> (1 - cos(2 pi x)) / 2 = sin^2(pi x) with peak 1 at the centre, zero slope at both ends and
!> integral (t_off - t_on) / 2; sine 0 up to t_on, then sin(2 pi x), periodic beyond t_off;
!> table interpolation and constant extrapolation), and the errors of time_function_from_load
!> (unknown name listing the valid ones, t_off <= t_on, table without matching values).
!> time_function_from_actuator gives the same function as a load with the same time variables,
!> bit for bit, the same errors naming its own routine, and reads a table filled to capacity
!> (max_table points); time_function_from_bc gives the sine of a driven end as a load's. Loads,
!> actuators and supports are built as plain load_input_t, actuator_input_t and bc_input_t
!> values, without input files.
module rs_test_model_time_function
    use rs_core_kinds, only: rk, pi
    use rs_core_error, only: error_t
    use rs_test_assert, only: run_test, assert_true, assert_close, assert_equal, assert_contains
    use rs_model_scene, only: load_input_t, actuator_input_t, bc_input_t, max_table
    use rs_model_time_function, only: time_function_t, time_function_from_load, &
        time_function_from_actuator, time_function_from_bc, time_function_names
    implicit none
    private

    public :: run_all_tests

    real(rk), parameter :: tight = 1.0e-14_rk

contains

    !> Run every test of this file through rs_test_assert.
    subroutine run_all_tests()
        call run_test('constant', test_constant)
        call run_test('constant_ignores_t_on_t_off', test_constant_ignores_t_on_t_off)
        call run_test('ramp_points', test_ramp_points)
        call run_test('ramp_grid', test_ramp_grid)
        call run_test('hat_flying_spaghetti', test_hat_flying_spaghetti)
        call run_test('hat_shifted_symmetric', test_hat_shifted_symmetric)
        call run_test('pulse_points', test_pulse_points)
        call run_test('pulse_zero_slope_at_ends', test_pulse_zero_slope_at_ends)
        call run_test('pulse_integral', test_pulse_integral)
        call run_test('sine_points', test_sine_points)
        call run_test('sine_slope_and_periods', test_sine_slope_and_periods)
        call run_test('bc_sine', test_bc_sine)
        call run_test('table_interpolation', test_table_interpolation)
        call run_test('table_extrapolation', test_table_extrapolation)
        call run_test('table_ignores_t_on_t_off', test_table_ignores_t_on_t_off)
        call run_test('unknown_name_lists_valid', test_unknown_name_lists_valid)
        call run_test('t_off_not_after_t_on', test_t_off_not_after_t_on)
        call run_test('table_errors', test_table_errors)
        call run_test('actuator_same_as_load', test_actuator_same_as_load)
        call run_test('actuator_errors', test_actuator_errors)
        call run_test('actuator_full_table', test_actuator_full_table)
    end subroutine run_all_tests

    !> The time function of `load`, recording a failure if it is rejected.
    function make(load) result(tf)
        type(load_input_t), intent(in) :: load
        type(time_function_t) :: tf
        type(error_t), allocatable :: err
        call time_function_from_load(load, tf, err)
        CHECK_TRUE(.not. allocated(err), 'load accepted: ' // trim(load%time_function))
    end function make

    !> A load with time function `name` on [t_on, t_off].
    function load_of(name, t_on, t_off) result(load)
        character(len=*), intent(in) :: name
        real(rk), intent(in) :: t_on, t_off
        type(load_input_t) :: load
        load%rod = 'beam'
        load%where = 'end'
        load%force = [0.0_rk, 0.0_rk, 1.0_rk]
        load%time_function = name
        load%t_on = t_on
        load%t_off = t_off
    end function load_of

    subroutine test_constant()
        type(load_input_t) :: load
        type(time_function_t) :: tf
        integer :: i
        tf = make(load)      ! the default &load: time_function = 'constant', t_off unset
        do i = -20, 200
            CHECK_CLOSE(tf%value(0.25_rk * real(i, rk)), 1.0_rk, 0.0_rk, 0.0_rk, 'f = 1')
        end do
        CHECK_CLOSE(tf%value(1.0e12_rk), 1.0_rk, 0.0_rk, 0.0_rk, 'f = 1 at a late time')
    end subroutine test_constant

    ! t_on and t_off mean nothing to a constant; t_off = t_on must not divide by zero (the Debug
    ! build traps floating-point exceptions).
    subroutine test_constant_ignores_t_on_t_off()
        type(load_input_t) :: load
        type(time_function_t) :: tf
        load%t_on = 1.0_rk       ! t_off unset
        tf = make(load)
        CHECK_CLOSE(tf%value(0.0_rk), 1.0_rk, 0.0_rk, 0.0_rk, 'before t_on')
        CHECK_CLOSE(tf%value(1.0_rk), 1.0_rk, 0.0_rk, 0.0_rk, 'at t_on')
        CHECK_CLOSE(tf%value(7.0_rk), 1.0_rk, 0.0_rk, 0.0_rk, 'after t_on')
        tf = make(load_of('constant', 3.0_rk, 3.0_rk))
        CHECK_CLOSE(tf%value(3.0_rk), 1.0_rk, 0.0_rk, 0.0_rk, 't_on = t_off: at t_on')
        CHECK_CLOSE(tf%value(2.0_rk), 1.0_rk, 0.0_rk, 0.0_rk, 't_on = t_off: before')
        tf = make(load_of('constant', 4.0_rk, 2.0_rk))
        CHECK_CLOSE(tf%value(3.0_rk), 1.0_rk, 0.0_rk, 0.0_rk, 't_off < t_on is no error here')
    end subroutine test_constant_ignores_t_on_t_off

    ! Ramp on [1, 3]: 0, then (t - 1) / 2, then 1.
    subroutine test_ramp_points()
        type(time_function_t) :: tf
        tf = make(load_of('ramp', 1.0_rk, 3.0_rk))
        CHECK_CLOSE(tf%value(-5.0_rk), 0.0_rk, 0.0_rk, 0.0_rk, 'long before')
        CHECK_CLOSE(tf%value(0.0_rk), 0.0_rk, 0.0_rk, 0.0_rk, 't = 0')
        CHECK_CLOSE(tf%value(1.0_rk), 0.0_rk, 0.0_rk, 0.0_rk, 't = t_on')
        CHECK_CLOSE(tf%value(1.5_rk), 0.25_rk, 0.0_rk, tight, 't = 1.5')
        CHECK_CLOSE(tf%value(2.0_rk), 0.5_rk, 0.0_rk, tight, 'midpoint')
        CHECK_CLOSE(tf%value(2.5_rk), 0.75_rk, 0.0_rk, tight, 't = 2.5')
        CHECK_CLOSE(tf%value(3.0_rk), 1.0_rk, 0.0_rk, tight, 't = t_off')
        CHECK_CLOSE(tf%value(3.5_rk), 1.0_rk, 0.0_rk, 0.0_rk, 'after t_off')
        CHECK_CLOSE(tf%value(1.0e6_rk), 1.0_rk, 0.0_rk, 0.0_rk, 'long after')
    end subroutine test_ramp_points

    ! Ramp on [0.2, 0.7] on a grid over [-0.5, 1.5]: monotone, within [0, 1], and linear inside.
    subroutine test_ramp_grid()
        type(time_function_t) :: tf
        real(rk) :: t, expected, previous
        integer :: i
        tf = make(load_of('ramp', 0.2_rk, 0.7_rk))
        previous = -1.0_rk
        do i = 0, 400
            t = -0.5_rk + 0.005_rk * real(i, rk)
            if (t <= 0.2_rk) then
                expected = 0.0_rk
            else if (t >= 0.7_rk) then
                expected = 1.0_rk
            else
                expected = (t - 0.2_rk) / 0.5_rk
            end if
            CHECK_CLOSE(tf%value(t), expected, 1.0e-14_rk, 0.0_rk, 'ramp on the grid')
            CHECK_TRUE(tf%value(t) >= previous, 'ramp is non-decreasing')
            previous = tf%value(t)
        end do
    end subroutine test_ramp_grid

    ! Flying spaghetti (seed 000 §6.1): 200 hat(t) on [0, 5] is 80 t up to t = 2.5, then
    ! 400 - 80 t up to t = 5, and 0 after.
    subroutine test_hat_flying_spaghetti()
        type(time_function_t) :: tf
        real(rk) :: t, expected
        integer :: i
        tf = make(load_of('hat', 0.0_rk, 5.0_rk))
        CHECK_CLOSE(200.0_rk * tf%value(1.0_rk), 80.0_rk, 0.0_rk, tight, 't = 1')
        CHECK_CLOSE(200.0_rk * tf%value(2.5_rk), 200.0_rk, 0.0_rk, tight, 'peak 200 at t = 2.5')
        CHECK_CLOSE(200.0_rk * tf%value(4.0_rk), 80.0_rk, 0.0_rk, tight, 't = 4')
        CHECK_CLOSE(200.0_rk * tf%value(4.75_rk), 20.0_rk, 0.0_rk, tight, 't = 4.75')
        CHECK_CLOSE(tf%value(0.0_rk), 0.0_rk, 0.0_rk, 0.0_rk, 't = 0')
        CHECK_CLOSE(tf%value(5.0_rk), 0.0_rk, 0.0_rk, 0.0_rk, 't = 5')
        CHECK_CLOSE(tf%value(-1.0_rk), 0.0_rk, 0.0_rk, 0.0_rk, 'before')
        do i = 0, 700
            t = 0.01_rk * real(i, rk)
            if (t <= 2.5_rk) then
                expected = 80.0_rk * t
            else if (t <= 5.0_rk) then
                expected = 400.0_rk - 80.0_rk * t
            else
                expected = 0.0_rk
            end if
            CHECK_CLOSE(200.0_rk * tf%value(t), expected, 1.0e-11_rk, 0.0_rk, '200 hat(t) on the grid')
        end do
    end subroutine test_hat_flying_spaghetti

    ! Hat on [2, 4]: peak 1 at 3, 1/2 at 2.5 and 3.5, symmetric about the centre, 0 outside.
    subroutine test_hat_shifted_symmetric()
        type(time_function_t) :: tf
        real(rk) :: s
        integer :: i
        tf = make(load_of('hat', 2.0_rk, 4.0_rk))
        CHECK_CLOSE(tf%value(3.0_rk), 1.0_rk, 0.0_rk, tight, 'peak at the centre')
        CHECK_CLOSE(tf%value(2.5_rk), 0.5_rk, 0.0_rk, tight, 'rising half')
        CHECK_CLOSE(tf%value(3.5_rk), 0.5_rk, 0.0_rk, tight, 'falling half')
        CHECK_CLOSE(tf%value(1.0_rk), 0.0_rk, 0.0_rk, 0.0_rk, 'before t_on')
        CHECK_CLOSE(tf%value(4.5_rk), 0.0_rk, 0.0_rk, 0.0_rk, 'after t_off')
        do i = 1, 60
            s = 0.02_rk * real(i, rk)
            CHECK_CLOSE(tf%value(3.0_rk + s), tf%value(3.0_rk - s), 1.0e-14_rk, 0.0_rk, 'symmetric')
            CHECK_TRUE(tf%value(3.0_rk + s) <= 1.0_rk, 'at most 1')
        end do
    end subroutine test_hat_shifted_symmetric

    ! Pulse on [1, 3]: sin^2(pi (t - 1) / 2), peak 1 at t = 2.
    subroutine test_pulse_points()
        type(time_function_t) :: tf
        real(rk) :: t, s
        integer :: i
        tf = make(load_of('pulse', 1.0_rk, 3.0_rk))
        CHECK_CLOSE(tf%value(2.0_rk), 1.0_rk, 0.0_rk, tight, 'peak 1 at the centre')
        CHECK_CLOSE(tf%value(1.0_rk), 0.0_rk, 0.0_rk, 0.0_rk, 't = t_on')
        CHECK_CLOSE(tf%value(3.0_rk), 0.0_rk, 0.0_rk, 0.0_rk, 't = t_off')
        CHECK_CLOSE(tf%value(1.5_rk), 0.5_rk, 1.0e-15_rk, 0.0_rk, 'quarter: 1/2')
        CHECK_CLOSE(tf%value(2.5_rk), 0.5_rk, 1.0e-15_rk, 0.0_rk, 'three quarters: 1/2')
        CHECK_CLOSE(tf%value(1.0_rk + 1.0_rk / 3.0_rk), 0.25_rk, 1.0e-15_rk, 0.0_rk, 'x = 1/6: sin^2(pi/6)')
        CHECK_CLOSE(tf%value(0.0_rk), 0.0_rk, 0.0_rk, 0.0_rk, 'before')
        CHECK_CLOSE(tf%value(3.5_rk), 0.0_rk, 0.0_rk, 0.0_rk, 'after')
        do i = 0, 500
            t = 0.5_rk + 0.006_rk * real(i, rk)
            if (t > 1.0_rk .and. t < 3.0_rk) then
                CHECK_CLOSE(tf%value(t), sin(pi * (t - 1.0_rk) / 2.0_rk)**2, 1.0e-15_rk, 0.0_rk, 'sin^2')
            else
                CHECK_CLOSE(tf%value(t), 0.0_rk, 0.0_rk, 0.0_rk, 'zero outside')
            end if
            CHECK_TRUE(tf%value(t) <= 1.0_rk, 'at most 1')
            s = t - 2.0_rk
            CHECK_CLOSE(tf%value(2.0_rk + s), tf%value(2.0_rk - s), 1.0e-15_rk, 0.0_rk, 'symmetric')
        end do
    end subroutine test_pulse_points

    ! Zero slope at both ends: f(t_on + h) = sin^2(pi h / T) ~ (pi / T)^2 h^2, so f / h^2 tends
    ! to (pi / T)^2 (a kink like the ramp's would make f / h grow like 1 / h). Inside, the
    ! central difference of f matches (pi / T) sin(2 pi x).
    subroutine test_pulse_zero_slope_at_ends()
        type(time_function_t) :: tf
        real(rk), parameter :: t_on = 0.5_rk, t_off = 2.5_rk, period = t_off - t_on
        real(rk) :: h, slope, x
        integer :: k
        tf = make(load_of('pulse', t_on, t_off))
        do k = 2, 4
            h = 10.0_rk**(-k)
            CHECK_CLOSE(tf%value(t_on + h) / h**2, (pi / period)**2, 0.0_rk, 1.0e-4_rk, 'f / h^2 at t_on')
            CHECK_CLOSE(tf%value(t_off - h) / h**2, (pi / period)**2, 0.0_rk, 1.0e-4_rk, 'f / h^2 at t_off')
            slope = (tf%value(t_on + h) - tf%value(t_on - h)) / (2.0_rk * h)
            CHECK_CLOSE(slope, 0.0_rk, 3.0_rk * h, 0.0_rk, 'one-sided slopes vanish at t_on')
            slope = (tf%value(t_off + h) - tf%value(t_off - h)) / (2.0_rk * h)
            CHECK_CLOSE(slope, 0.0_rk, 3.0_rk * h, 0.0_rk, 'one-sided slopes vanish at t_off')
        end do
        h = 1.0e-5_rk
        do k = 1, 9
            x = 0.1_rk * real(k, rk)
            slope = (tf%value(t_on + x * period + h) - tf%value(t_on + x * period - h)) / (2.0_rk * h)
            CHECK_CLOSE(slope, pi / period * sin(2.0_rk * pi * x), 1.0e-8_rk, 0.0_rk, 'slope inside')
        end do
    end subroutine test_pulse_zero_slope_at_ends

    ! The midpoint rule is exact (to round-off) for sin^2 over a whole period: integral T / 2.
    subroutine test_pulse_integral()
        type(time_function_t) :: tf
        real(rk), parameter :: t_on = 0.3_rk, t_off = 1.1_rk
        real(rk) :: h, total
        integer :: i, n
        tf = make(load_of('pulse', t_on, t_off))
        n = 1000
        h = (t_off - t_on) / real(n, rk)
        total = 0.0_rk
        do i = 1, n
            total = total + h * tf%value(t_on + (real(i, rk) - 0.5_rk) * h)
        end do
        CHECK_CLOSE(total, 0.4_rk, 0.0_rk, 1.0e-12_rk, 'integral = (t_off - t_on) / 2')
    end subroutine test_pulse_integral

    ! Sine with t_on = 1 and period t_off - t_on = 2: 0 up to t_on, then sin(pi (t - 1)), and
    ! still oscillating after t_off (0 at t_on + k T / 2, +-1 at the quarter periods).
    subroutine test_sine_points()
        type(time_function_t) :: tf
        real(rk) :: t
        integer :: i
        tf = make(load_of('sine', 1.0_rk, 3.0_rk))
        CHECK_CLOSE(tf%value(0.0_rk), 0.0_rk, 0.0_rk, 0.0_rk, 'before t_on')
        CHECK_CLOSE(tf%value(1.0_rk), 0.0_rk, 0.0_rk, 0.0_rk, 't = t_on')
        CHECK_CLOSE(tf%value(1.5_rk), 1.0_rk, tight, 0.0_rk, 'quarter period: 1')
        CHECK_CLOSE(tf%value(2.0_rk), 0.0_rk, tight, 0.0_rk, 'half period: 0')
        CHECK_CLOSE(tf%value(2.5_rk), -1.0_rk, tight, 0.0_rk, 'three quarters: -1')
        CHECK_CLOSE(tf%value(3.0_rk), 0.0_rk, tight, 0.0_rk, 't = t_off: a whole period')
        CHECK_CLOSE(tf%value(3.5_rk), 1.0_rk, tight, 0.0_rk, 'after t_off it goes on: 1')
        CHECK_CLOSE(tf%value(4.5_rk), -1.0_rk, 1.0e-13_rk, 0.0_rk, 'second period: -1')
        CHECK_CLOSE(tf%value(1.0_rk + 1.0_rk / 6.0_rk), 0.5_rk, 1.0e-15_rk, 0.0_rk, 'x = 1/12: sin(pi/6)')
        do i = -50, 500
            t = 0.013_rk * real(i, rk)
            if (t <= 1.0_rk) then
                CHECK_CLOSE(tf%value(t), 0.0_rk, 0.0_rk, 0.0_rk, 'zero up to t_on')
            else
                CHECK_CLOSE(tf%value(t), sin(pi * (t - 1.0_rk)), 1.0e-13_rk, 0.0_rk, 'sin(2 pi x)')
            end if
        end do
    end subroutine test_sine_points

    ! Periodic with period T = t_off - t_on beyond t_off; slope 2 pi / T at t_on (a kink from
    ! the zero before it, as a velocity drive that starts oscillating) and the central
    ! difference (2 pi / T) cos(2 pi x) inside.
    subroutine test_sine_slope_and_periods()
        type(time_function_t) :: tf
        real(rk), parameter :: t_on = 0.5_rk, t_off = 0.5_rk + 1.0_rk / 4.5_rk, period = t_off - t_on
        real(rk) :: h, slope, t, expected
        integer :: k
        tf = make(load_of('sine', t_on, t_off))
        do k = 1, 40
            t = t_on + 0.037_rk * real(k, rk) * period
            CHECK_CLOSE(tf%value(t + 3.0_rk * period), tf%value(t), 1.0e-12_rk, 0.0_rk, 'period T')
        end do
        h = 1.0e-6_rk
        slope = (tf%value(t_on + h) - tf%value(t_on)) / h
        CHECK_CLOSE(slope, 2.0_rk * pi / period, 0.0_rk, 1.0e-8_rk, 'slope 2 pi / T just after t_on')
        slope = (tf%value(t_on) - tf%value(t_on - h)) / h
        CHECK_CLOSE(slope, 0.0_rk, 0.0_rk, 0.0_rk, 'flat before t_on')
        h = 1.0e-5_rk
        do k = 1, 9
            t = t_on + 0.1_rk * real(k, rk) * period
            slope = (tf%value(t + h) - tf%value(t - h)) / (2.0_rk * h)
            expected = 2.0_rk * pi / period * cos(0.2_rk * pi * real(k, rk))
            CHECK_CLOSE(slope, expected, 1.0e-6_rk, 0.0_rk, 'slope inside')
        end do
    end subroutine test_sine_slope_and_periods

    ! A driven &bc takes the sine too (the base oscillation of seed 004 §3.3 as a velocity), with
    ! the same values as a load and the same t_off > t_on rule.
    subroutine test_bc_sine()
        type(bc_input_t) :: bc
        type(time_function_t) :: from_bc, from_load
        type(error_t), allocatable :: err
        real(rk) :: t
        integer :: i
        bc%rod = 'beam'
        bc%end = 'start'
        bc%kind = 'driven'
        bc%velocity = [0.0_rk, 0.0_rk, 0.5655_rk]
        bc%time_function = 'sine'
        bc%t_on = 0.25_rk
        bc%t_off = 0.75_rk
        call time_function_from_bc(bc, from_bc, err)
        CHECK_TRUE(.not. allocated(err), 'bc sine accepted')
        if (allocated(err)) return
        from_load = make(load_of('sine', 0.25_rk, 0.75_rk))
        do i = 0, 300
            t = 0.01_rk * real(i, rk)
            CHECK_TRUE(from_bc%value(t) == from_load%value(t), 'same f(t) as a load')
        end do
        bc%t_off = 0.25_rk
        call time_function_from_bc(bc, from_bc, err)
        CHECK_TRUE(allocated(err), 't_off = t_on is an error')
        if (allocated(err)) then
            CHECK_EQUAL(err%routine, 'time_function_from_bc', 'names the bc routine')
        end if
    end subroutine test_bc_sine

    !> A table load through (times, values).
    function table_load(times, values) result(load)
        real(rk), intent(in) :: times(:), values(:)
        type(load_input_t) :: load
        load = load_of('table', 0.0_rk, 1.0_rk)
        load%table_times(1:size(times)) = times
        load%table_values(1:size(values)) = values
    end function table_load

    ! Through (0, 0), (1, 2), (3, -1), (3.5, 4): linear between the points.
    subroutine test_table_interpolation()
        type(time_function_t) :: tf
        real(rk) :: times(4), values(4), t, expected
        integer :: i, k
        times = [0.0_rk, 1.0_rk, 3.0_rk, 3.5_rk]
        values = [0.0_rk, 2.0_rk, -1.0_rk, 4.0_rk]
        tf = make(table_load(times, values))
        do k = 1, 4
            CHECK_CLOSE(tf%value(times(k)), values(k), 0.0_rk, 0.0_rk, 'at a table point')
        end do
        CHECK_CLOSE(tf%value(0.5_rk), 1.0_rk, 0.0_rk, tight, 't = 0.5')
        CHECK_CLOSE(tf%value(0.25_rk), 0.5_rk, 0.0_rk, tight, 't = 0.25')
        CHECK_CLOSE(tf%value(2.0_rk), 0.5_rk, 0.0_rk, tight, 't = 2')
        CHECK_CLOSE(tf%value(2.5_rk), -0.25_rk, 0.0_rk, tight, 't = 2.5')
        CHECK_CLOSE(tf%value(3.25_rk), 1.5_rk, 0.0_rk, tight, 't = 3.25')
        ! On a grid, against the segment that contains t.
        do i = 0, 340
            t = 0.01_rk * real(i, rk)
            do k = 2, 4
                if (t <= times(k)) exit
            end do
            expected = values(k - 1) + (values(k) - values(k - 1)) / (times(k) - times(k - 1)) * &
                (t - times(k - 1))
            CHECK_CLOSE(tf%value(t), expected, 1.0e-13_rk, 0.0_rk, 'piecewise linear on the grid')
        end do
    end subroutine test_table_interpolation

    ! Constant beyond the ends: the first value before the first time, the last after the last.
    subroutine test_table_extrapolation()
        type(time_function_t) :: tf
        real(rk) :: times(3), values(3), single(1)
        times = [0.5_rk, 1.0_rk, 2.0_rk]
        values = [3.0_rk, -2.0_rk, 7.0_rk]
        tf = make(table_load(times, values))
        CHECK_CLOSE(tf%value(0.0_rk), 3.0_rk, 0.0_rk, 0.0_rk, 'before the first time')
        CHECK_CLOSE(tf%value(-100.0_rk), 3.0_rk, 0.0_rk, 0.0_rk, 'long before')
        CHECK_CLOSE(tf%value(2.0_rk + 1.0e-12_rk), 7.0_rk, 0.0_rk, 0.0_rk, 'just after the last time')
        CHECK_CLOSE(tf%value(50.0_rk), 7.0_rk, 0.0_rk, 0.0_rk, 'long after')
        ! One point: constant everywhere.
        single = 0.75_rk
        tf = make(table_load(single, single))
        CHECK_CLOSE(tf%value(-1.0_rk), 0.75_rk, 0.0_rk, 0.0_rk, 'one point: before')
        CHECK_CLOSE(tf%value(0.75_rk), 0.75_rk, 0.0_rk, 0.0_rk, 'one point: at')
        CHECK_CLOSE(tf%value(9.0_rk), 0.75_rk, 0.0_rk, 0.0_rk, 'one point: after')
    end subroutine test_table_extrapolation

    ! A table is defined by its points alone: t_on and t_off (even t_off = t_on) change nothing.
    subroutine test_table_ignores_t_on_t_off()
        type(load_input_t) :: load
        type(time_function_t) :: tf
        real(rk) :: times(2), values(2)
        times = [0.0_rk, 2.0_rk]
        values = [1.0_rk, 3.0_rk]
        load = table_load(times, values)
        load%t_on = 1.0_rk
        load%t_off = 1.0_rk
        tf = make(load)
        CHECK_CLOSE(tf%value(1.0_rk), 2.0_rk, 0.0_rk, tight, 'midpoint')
        CHECK_CLOSE(tf%value(0.5_rk), 1.5_rk, 0.0_rk, tight, 't = 0.5')
        CHECK_CLOSE(tf%value(3.0_rk), 3.0_rk, 0.0_rk, 0.0_rk, 'after')
    end subroutine test_table_ignores_t_on_t_off

    subroutine test_unknown_name_lists_valid()
        type(load_input_t) :: load
        type(time_function_t) :: tf
        type(error_t), allocatable :: err
        character(len=8), parameter :: names(6) = [character(len=8) :: 'constant', 'ramp', 'hat', &
            'pulse', 'sine', 'table']
        integer :: i
        load = load_of('rampp', 0.0_rk, 1.0_rk)
        call time_function_from_load(load, tf, err)
        CHECK_TRUE(allocated(err), 'unknown name is an error')
        if (.not. allocated(err)) return
        CHECK_CONTAINS(err%message, "unknown time function 'rampp'", 'names the unknown one')
        do i = 1, size(names)
            CHECK_CONTAINS(err%message, trim(names(i)), 'lists every valid name')
        end do
        CHECK_CONTAINS(err%message, 'constant|ramp|hat|pulse|sine|table', 'the full list')
        CHECK_EQUAL(time_function_names, 'constant|ramp|hat|pulse|sine|table', 'published list')
        ! Every listed name but 'table' (which needs points; see the table tests) is accepted.
        do i = 1, size(names) - 1
            call time_function_from_load(load_of(trim(names(i)), 0.0_rk, 1.0_rk), tf, err)
            CHECK_TRUE(.not. allocated(err), 'listed name accepted: ' // trim(names(i)))
        end do
        call time_function_from_load(load_of('', 0.0_rk, 1.0_rk), tf, err)
        CHECK_TRUE(allocated(err), 'blank name is an error')
    end subroutine test_unknown_name_lists_valid

    ! Ramp, hat, pulse and sine need t_off > t_on.
    subroutine test_t_off_not_after_t_on()
        character(len=5), parameter :: names(4) = [character(len=5) :: 'ramp', 'hat', 'pulse', 'sine']
        type(time_function_t) :: tf
        type(error_t), allocatable :: err
        integer :: i
        do i = 1, size(names)
            call time_function_from_load(load_of(trim(names(i)), 2.0_rk, 2.0_rk), tf, err)
            CHECK_TRUE(allocated(err), 't_off = t_on is an error: ' // trim(names(i)))
            if (allocated(err)) then
                CHECK_CONTAINS(err%message, 't_off > t_on', 'says why')
            end if
            call time_function_from_load(load_of(trim(names(i)), 2.0_rk, 1.0_rk), tf, err)
            CHECK_TRUE(allocated(err), 't_off < t_on is an error: ' // trim(names(i)))
            call time_function_from_load(load_of(trim(names(i)), 2.0_rk, 2.0_rk + 1.0e-9_rk), tf, err)
            CHECK_TRUE(.not. allocated(err), 't_off just after t_on is fine: ' // trim(names(i)))
        end do
    end subroutine test_t_off_not_after_t_on

    ! A table needs at least one time and a value for each time.
    subroutine test_table_errors()
        type(load_input_t) :: load
        type(time_function_t) :: tf
        type(error_t), allocatable :: err
        real(rk) :: times(3), values(2)
        load = load_of('table', 0.0_rk, 1.0_rk)
        call time_function_from_load(load, tf, err)
        CHECK_TRUE(allocated(err), 'a table without points is an error')
        times = [0.0_rk, 1.0_rk, 2.0_rk]
        values = [0.0_rk, 1.0_rk]
        call time_function_from_load(table_load(times, values), tf, err)
        CHECK_TRUE(allocated(err), 'three times and two values is an error')
        if (allocated(err)) then
            CHECK_CONTAINS(err%message, 'as many table_values as table_times', 'says why')
        end if
        call time_function_from_load(table_load(times(1:2), [values, 5.0_rk]), tf, err)
        CHECK_TRUE(allocated(err), 'two times and three values is an error')
    end subroutine test_table_errors

    !> The actuator with the time variables of `load` (a tendon, as the kind does not matter).
    function actuator_like(load) result(actuator)
        type(load_input_t), intent(in) :: load
        type(actuator_input_t) :: actuator
        actuator%rod = load%rod
        actuator%kind = 'tendon'
        actuator%offset = [0.0_rk, 0.01_rk]
        actuator%tension = 3.0_rk
        actuator%time_function = load%time_function
        actuator%t_on = load%t_on
        actuator%t_off = load%t_off
        actuator%table_times = load%table_times
        actuator%table_values = load%table_values
    end function actuator_like

    ! Every kind: an actuator's f(t) equals the load's bit for bit on a grid that covers both
    ! sides of [t_on, t_off] and of the table.
    subroutine test_actuator_same_as_load()
        character(len=8), parameter :: names(6) = [character(len=8) :: 'constant', 'ramp', 'hat', &
            'pulse', 'sine', 'table']
        type(load_input_t) :: load
        type(time_function_t) :: from_load, from_actuator
        type(error_t), allocatable :: err
        real(rk) :: t
        integer :: i, k
        do k = 1, size(names)
            load = load_of(trim(names(k)), 0.5_rk, 2.25_rk)
            if (names(k) == 'table') load = table_load([0.0_rk, 1.0_rk, 3.0_rk], &
                [0.0_rk, 2.0_rk, -1.0_rk])
            from_load = make(load)
            call time_function_from_actuator(actuator_like(load), from_actuator, err)
            CHECK_TRUE(.not. allocated(err), 'actuator accepted: ' // trim(names(k)))
            if (allocated(err)) cycle
            do i = -10, 400
                t = 0.01_rk * real(i, rk)
                CHECK_TRUE(from_actuator%value(t) == from_load%value(t), 'same f(t): ' // trim(names(k)))
            end do
        end do
        ! Spot values, so that equal but wrong functions cannot pass: ramp on [0.5, 2.25].
        load = load_of('ramp', 0.5_rk, 2.25_rk)
        call time_function_from_actuator(actuator_like(load), from_actuator, err)
        CHECK_CLOSE(from_actuator%value(0.5_rk), 0.0_rk, 0.0_rk, 0.0_rk, 'ramp at t_on')
        CHECK_CLOSE(from_actuator%value(1.375_rk), 0.5_rk, 0.0_rk, tight, 'ramp half way')
        CHECK_CLOSE(from_actuator%value(3.0_rk), 1.0_rk, 0.0_rk, 0.0_rk, 'ramp after t_off')
    end subroutine test_actuator_same_as_load

    ! The errors of time_function_from_load, reported by time_function_from_actuator itself.
    subroutine test_actuator_errors()
        type(time_function_t) :: tf
        type(error_t), allocatable :: err
        type(actuator_input_t) :: actuator
        character(len=:), allocatable :: message
        call time_function_from_actuator(actuator_like(load_of('rampp', 0.0_rk, 1.0_rk)), tf, err)
        CHECK_TRUE(allocated(err), 'unknown name is an error')
        if (allocated(err)) then
            message = "unknown time function 'rampp'; known: " // time_function_names
            CHECK_CONTAINS(err%message, message, 'names the unknown one and lists the valid ones')
            CHECK_EQUAL(err%routine, 'time_function_from_actuator', 'names the actuator routine')
        end if
        call time_function_from_load(load_of('rampp', 0.0_rk, 1.0_rk), tf, err)
        if (allocated(err)) then
            CHECK_EQUAL(err%routine, 'time_function_from_load', 'the load routine names itself')
        end if
        call time_function_from_actuator(actuator_like(load_of('pulse', 2.0_rk, 2.0_rk)), tf, err)
        CHECK_TRUE(allocated(err), 't_off = t_on is an error')
        if (allocated(err)) then
            CHECK_CONTAINS(err%message, 't_off > t_on', 'says why')
        end if
        actuator = actuator_like(table_load([0.0_rk, 1.0_rk, 2.0_rk], [0.0_rk, 1.0_rk]))
        call time_function_from_actuator(actuator, tf, err)
        CHECK_TRUE(allocated(err), 'three times and two values is an error')
        if (allocated(err)) then
            CHECK_CONTAINS(err%message, 'as many table_values as table_times', 'says why')
        end if
        ! The default actuator: constant 1.
        actuator = actuator_input_t()
        call time_function_from_actuator(actuator, tf, err)
        CHECK_TRUE(.not. allocated(err), 'default actuator accepted')
        CHECK_CLOSE(tf%value(7.0_rk), 1.0_rk, 0.0_rk, 0.0_rk, 'default f = 1')
    end subroutine test_actuator_errors

    ! A table of max_table points, f(t_k) = t_k^2 at t_k = k / 8: every point is used,
    ! including the last, and f is linear between points.
    subroutine test_actuator_full_table()
        type(actuator_input_t) :: actuator
        type(time_function_t) :: tf
        type(error_t), allocatable :: err
        real(rk) :: t
        integer :: k
        actuator%kind = 'pneumatic'
        actuator%time_function = 'table'
        do k = 1, max_table
            actuator%table_times(k) = real(k - 1, rk) / 8.0_rk
            actuator%table_values(k) = actuator%table_times(k)**2
        end do
        call time_function_from_actuator(actuator, tf, err)
        CHECK_TRUE(.not. allocated(err), 'full table accepted')
        if (allocated(err)) return
        CHECK_EQUAL(size(tf%times), max_table, 'every point kept')
        do k = 1, max_table
            t = actuator%table_times(k)
            CHECK_CLOSE(tf%value(t), t**2, 0.0_rk, 0.0_rk, 'at a table point')
        end do
        do k = 1, max_table - 1
            t = (real(k, rk) - 0.5_rk) / 8.0_rk
            CHECK_CLOSE(tf%value(t), t**2 + 1.0_rk / 256.0_rk, 1.0e-12_rk, 1.0e-14_rk, 'chord midpoint')
        end do
        t = actuator%table_values(max_table)
        CHECK_CLOSE(tf%value(1.0e3_rk), t, 0.0_rk, 0.0_rk, 'after the last')
    end subroutine test_actuator_full_table

end module rs_test_model_time_function

!> Test program: runs the tests of rs_test_model_time_function; exits non-zero if any failed.
program test_time_function
    use rs_test_model_time_function, only: run_all_tests
    use rs_test_assert, only: finish_tests
    implicit none
    call run_all_tests()
    call finish_tests()
end program test_time_function
