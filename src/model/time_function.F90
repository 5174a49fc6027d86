!> Time functions that scale loads, actuators and driven ends: the factor f(t) of a `&load`, an
!> `&actuator` or a driven `&bc` (DESIGN.md §6).
!>
!> - `constant`: f = 1 at all times.
!> - `ramp`: 0 up to t_on, linear to 1 at t_off, 1 afterwards.
!> - `hat`: 0 outside [t_on, t_off], linear up to 1 at the centre and back to 0 at t_off; the
!>   load history of the flying spaghetti (seed 000 §6.1, methods/ph_director_3d.md §6.1:
!>   f(t) = 80 t up to 2.5, 400 - 80 t up to 5, is 200 * hat with t_on = 0, t_off = 5).
!> - `pulse`: the smooth pulse of seed 000 §6.2, f = (1 - cos(2 pi (t - t_on)/(t_off - t_on)))/2
!>   inside [t_on, t_off], 0 outside (peak 1 at the centre).
!> - `sine`: 0 up to t_on, sin(2 pi (t - t_on)/(t_off - t_on)) afterwards: t_off - t_on is the
!>   period, and it keeps oscillating after t_off (the base oscillation of seed 004 §3.3,
!>   methods/se3_strands.md §4.5, prescribed as a velocity).
!> - `table`: piecewise linear through (table_times, table_values), constant beyond the ends.
!>
!> The midpoint scheme evaluates f at the mid time t_{n+1/2} (methods §5.1), so a kink of a
!> piecewise-linear function is only integrated exactly when it lies on a step boundary.
#include "rs_macros.h"
module rs_model_time_function
    use rs_core_kinds, only: rk
    use rs_core_error, only: error_t, set_error
    use rs_model_scene, only: load_input_t, actuator_input_t, bc_input_t, plate_input_t, &
        obstacle_input_t, scene_t, unset_real
    implicit none
    private

    public :: time_function_from_load, time_function_from_actuator, time_function_from_bc
    public :: time_function_from_plate, time_function_from_obstacle, scene_time_kinks

    !> The names `time_function_from_load`, `time_function_from_actuator` and
    !> `time_function_from_bc` accept.
    character(len=*), parameter, public :: time_function_names = 'constant|ramp|hat|pulse|sine|table'

    integer, parameter :: kind_constant = 1, kind_ramp = 2, kind_hat = 3, kind_pulse = 4, &
        kind_table = 5, kind_sine = 6

    !> A scalar function of time, evaluated by `value`.
    type, public :: time_function_t
        integer :: kind = kind_constant
        real(rk) :: t_on = 0.0_rk
        real(rk) :: t_off = 1.0_rk
        real(rk), allocatable :: times(:), values(:)
    contains
        procedure :: value => time_function_value
        procedure :: kinks => time_function_kinks
    end type time_function_t

contains

    !> The time function of a `&load`; an unknown name is an error that lists the valid ones.
    subroutine time_function_from_load(load, tf, err)
        type(load_input_t), intent(in) :: load
        type(time_function_t), intent(out) :: tf
        type(error_t), allocatable, intent(out) :: err
        call time_function_from_parts('time_function_from_load', load%time_function, load%t_on, &
            load%t_off, load%table_times, load%table_values, tf, err)
    end subroutine time_function_from_load

    !> The time function f of an `&actuator` (its force is tau(t) = -pressure area f(t) or
    !> tension f(t)); the same names and rules as `time_function_from_load`.
    subroutine time_function_from_actuator(actuator, tf, err)
        type(actuator_input_t), intent(in) :: actuator
        type(time_function_t), intent(out) :: tf
        type(error_t), allocatable, intent(out) :: err
        call time_function_from_parts('time_function_from_actuator', actuator%time_function, &
            actuator%t_on, actuator%t_off, actuator%table_times, actuator%table_values, tf, err)
    end subroutine time_function_from_actuator

    !> The time function f of a driven `&bc` (its pose, or its velocity, at t is the motion
    !> scaled by f(t)); the same names and rules as `time_function_from_load`.
    subroutine time_function_from_bc(bc, tf, err)
        type(bc_input_t), intent(in) :: bc
        type(time_function_t), intent(out) :: tf
        type(error_t), allocatable, intent(out) :: err
        call time_function_from_parts('time_function_from_bc', bc%time_function, bc%t_on, &
            bc%t_off, bc%table_times, bc%table_values, tf, err)
    end subroutine time_function_from_bc

    !> The time function f of a driven `&plate` (its pose at t is the motion scaled by f(t));
    !> the same names and rules as `time_function_from_load`.
    subroutine time_function_from_plate(plate, tf, err)
        type(plate_input_t), intent(in) :: plate
        type(time_function_t), intent(out) :: tf
        type(error_t), allocatable, intent(out) :: err
        call time_function_from_parts('time_function_from_plate', plate%time_function, plate%t_on, &
            plate%t_off, plate%table_times, plate%table_values, tf, err)
    end subroutine time_function_from_plate

    !> The time function f of a moving `&obstacle` (it is translated by f(t) displacement); the
    !> same names and rules as `time_function_from_load`.
    subroutine time_function_from_obstacle(obstacle, tf, err)
        type(obstacle_input_t), intent(in) :: obstacle
        type(time_function_t), intent(out) :: tf
        type(error_t), allocatable, intent(out) :: err
        call time_function_from_parts('time_function_from_obstacle', obstacle%time_function, &
            obstacle%t_on, obstacle%t_off, obstacle%table_times, obstacle%table_values, tf, err)
    end subroutine time_function_from_obstacle

    !> The time function named `name` on [t_on, t_off] or through the set entries of
    !> (times, values); errors name `routine`, the public entry point.
    subroutine time_function_from_parts(routine, name, t_on, t_off, times, values, tf, err)
        character(len=*), intent(in) :: routine, name
        real(rk), intent(in) :: t_on, t_off, times(:), values(:)
        type(time_function_t), intent(out) :: tf
        type(error_t), allocatable, intent(out) :: err
        character(len=:), allocatable :: message
        integer :: n
        tf%t_on = t_on
        if (t_off /= unset_real) tf%t_off = t_off
        select case (trim(name))
        case ('constant')
            tf%kind = kind_constant
        case ('ramp')
            tf%kind = kind_ramp
        case ('hat')
            tf%kind = kind_hat
        case ('pulse')
            tf%kind = kind_pulse
        case ('sine')
            tf%kind = kind_sine
        case ('table')
            tf%kind = kind_table
            n = count(times /= unset_real)
            tf%times = times(1:n)
            tf%values = values(1:n)
            if (n < 1 .or. count(values /= unset_real) /= n) then
                RS_SET_ERROR(err, routine, 'a table needs as many table_values as table_times')
                return
            end if
        case default
            message = 'unknown time function ''' // trim(name) // '''; known: ' // time_function_names
            RS_SET_ERROR(err, routine, message)
            return
        end select
        if (tf%kind /= kind_constant .and. tf%kind /= kind_table .and. tf%t_off <= tf%t_on) then
            RS_SET_ERROR(err, routine, 'time function needs t_off > t_on')
        end if
    end subroutine time_function_from_parts

    !> The times where f or one of its first two derivatives jumps: the ends of a ramp, a pulse
    !> (its curvature) and a hat and the hat's peak, the start of a sine, a table's knots. An
    !> adaptive stepper hits them exactly and starts its error estimate afresh there.
    pure function time_function_kinks(this) result(times)
        class(time_function_t), intent(in) :: this
        real(rk), allocatable :: times(:)
        select case (this%kind)
        case (kind_ramp, kind_pulse)
            times = [this%t_on, this%t_off]
        case (kind_hat)
            times = [this%t_on, 0.5_rk * (this%t_on + this%t_off), this%t_off]
        case (kind_sine)
            times = [this%t_on]
        case (kind_table)
            times = this%times
        case default
            allocate(times(0))
        end select
    end function time_function_kinks

    !> The kinks of every time function of a checked scene (loads, actuators, driven ends and
    !> plates, moving obstacles) and the release times of supports, in no particular order.
    function scene_time_kinks(scene) result(times)
        type(scene_t), intent(in) :: scene
        real(rk), allocatable :: times(:)
        type(time_function_t) :: tf
        type(error_t), allocatable :: err
        integer :: i
        allocate(times(0))
        if (allocated(scene%loads)) then
            do i = 1, size(scene%loads)
                call time_function_from_load(scene%loads(i), tf, err)
                call add(tf, err)
            end do
        end if
        if (allocated(scene%actuators)) then
            do i = 1, size(scene%actuators)
                call time_function_from_actuator(scene%actuators(i), tf, err)
                call add(tf, err)
            end do
        end if
        if (allocated(scene%bcs)) then
            do i = 1, size(scene%bcs)
                call time_function_from_bc(scene%bcs(i), tf, err)
                call add(tf, err)
                ! A support released at a time (&bc release_time) changes the equations there.
                if (scene%bcs(i)%release_time /= unset_real) &
                    times = [times, scene%bcs(i)%release_time]
            end do
        end if
        if (allocated(scene%plates)) then
            do i = 1, size(scene%plates)
                call time_function_from_plate(scene%plates(i), tf, err)
                call add(tf, err)
            end do
        end if
        if (allocated(scene%obstacles)) then
            do i = 1, size(scene%obstacles)
                call time_function_from_obstacle(scene%obstacles(i), tf, err)
                call add(tf, err)
            end do
        end if
    contains
        !> The kinks of `tf`, unless building it failed (the input checks report that).
        subroutine add(tf, err)
            type(time_function_t), intent(in) :: tf
            type(error_t), allocatable, intent(in) :: err
            if (.not. allocated(err)) times = [times, tf%kinks()]
        end subroutine add
    end function scene_time_kinks

    !> f(t).
    pure real(rk) function time_function_value(this, t) result(f)
        class(time_function_t), intent(in) :: this
        real(rk), intent(in) :: t
        real(rk), parameter :: two_pi = 2.0_rk * acos(-1.0_rk)
        real(rk) :: x
        integer :: i
        ! Only ramp, hat, pulse and sine have t_off > t_on; a constant or table may have
        ! t_off = t_on.
        x = 0.0_rk
        if (any(this%kind == [kind_ramp, kind_hat, kind_pulse, kind_sine])) then
            x = (t - this%t_on) / (this%t_off - this%t_on)
        end if
        select case (this%kind)
        case (kind_ramp)
            f = min(1.0_rk, max(0.0_rk, x))
        case (kind_hat)
            if (x <= 0.0_rk .or. x >= 1.0_rk) then
                f = 0.0_rk
            else
                f = 1.0_rk - abs(2.0_rk * x - 1.0_rk)
            end if
        case (kind_pulse)
            if (x <= 0.0_rk .or. x >= 1.0_rk) then
                f = 0.0_rk
            else
                f = 0.5_rk * (1.0_rk - cos(two_pi * x))
            end if
        case (kind_sine)
            if (x <= 0.0_rk) then
                f = 0.0_rk
            else
                f = sin(two_pi * x)
            end if
        case (kind_table)
            associate (ts => this%times, vs => this%values)
                if (t <= ts(1)) then
                    f = vs(1)
                else if (t >= ts(size(ts))) then
                    f = vs(size(vs))
                else
                    do i = 2, size(ts)
                        if (t <= ts(i)) exit
                    end do
                    f = vs(i - 1) + (vs(i) - vs(i - 1)) * (t - ts(i - 1)) / (ts(i) - ts(i - 1))
                end if
            end associate
        case default
            f = 1.0_rk
        end select
    end function time_function_value

end module rs_model_time_function
