#include "rs_assert.h"
!> Unit tests of rs_contact_obstacle (issue 24 item 3): for the plane, the sphere and the
!> cylinder, the energy identity of the midpoint force for random steps (into, out of and
!> through the support), the force direction (along the normal, through the centre, at right
!> angles through the axis), the penalty law k delta^2 at small penetration, and the tangent
!> against central differences; friction: its dissipation (f_T . dx = D_T >= 0, |f_T| <= mu f_N)
!> and its tangent against central differences. Each test prints the largest error it
!> measured.
module rs_test_contact_obstacle
    use, intrinsic :: iso_fortran_env, only: output_unit
    use rs_core_kinds, only: rk
    use rs_test_random, only: set_random_seed, random_unit_vector, uniform
    use rs_test_assert, only: run_test, assert_true, assert_close
    use rs_contact_obstacle, only: obstacle_params_t, obstacle_params_init, obstacle_support, &
        obstacle_energy, obstacle_penetration, obstacle_point_force, obstacle_point_tangent, &
        obstacle_plane, obstacle_sphere, obstacle_cylinder, obstacle_point_friction, &
        obstacle_point_friction_tangent, obstacle_point_damping, &
        obstacle_point_damping_tangent
    implicit none
    private

    public :: run_all_tests

    real(rk), parameter :: stiffness = 1.0e10_rk, rod_radius = 0.005_rk
    ! Random steps per obstacle.
    integer, parameter :: n_steps = 2000
    ! Energy identity, relative to the work scale |f| |x_1 - x_n| + |psi_1| + |psi_n|: a few
    ! round-offs of the cubic (measured below 1e-15).
    real(rk), parameter :: energy_rtol = 1.0e-13_rk
    ! Central differences with the step fd_step r, relative to the largest tangent entry
    ! (truncation ~ (fd_step r / delta)^2 with delta ~ 1e-3: about 1e-8; measured below).
    real(rk), parameter :: fd_step = 1.0e-5_rk, fd_rtol = 1.0e-6_rk

contains

    subroutine run_all_tests()
        call run_test('energy_identity', test_energy_identity)
        call run_test('force_direction', test_force_direction)
        call run_test('penalty_law', test_penalty_law)
        call run_test('tangent_fd', test_tangent_fd)
        call run_test('friction_dissipation', test_friction_dissipation)
        call run_test('friction_tangent_fd', test_friction_tangent_fd)
        call run_test('damping', test_damping)
    end subroutine run_all_tests

    !> An obstacle with friction mu = 0.3 and slip velocity 1e-3 m/s.
    function rough(k) result(params)
        integer, intent(in) :: k
        type(obstacle_params_t) :: params
        params = obstacle(k)
        params%mu = 0.3_rk
        params%slip_velocity = 1.0e-3_rk
    end function rough

    !> The three obstacles: the ground z = 0, a ball of radius 0.1 about p, a cylinder of
    !> radius 0.05 about the axis through p along a tilted unit vector.
    function obstacle(k) result(params)
        integer, intent(in) :: k
        type(obstacle_params_t) :: params
        real(rk), parameter :: p(3) = [0.01_rk, -0.02_rk, 0.03_rk]
        select case (k)
        case (1)
            params = obstacle_params_init(obstacle_plane, p, [0.0_rk, 0.0_rk, 1.0_rk], 0.0_rk, &
                stiffness, rod_radius)
        case (2)
            params = obstacle_params_init(obstacle_sphere, p, [0.0_rk, 0.0_rk, 0.0_rk], 0.1_rk, &
                stiffness, rod_radius)
        case default
            params = obstacle_params_init(obstacle_cylinder, p, &
                [0.6_rk, 0.0_rk, 0.8_rk], 0.05_rk, stiffness, rod_radius)
        end select
    end function obstacle

    !> A point near the obstacle's surface (within about 2 r of it, inside or out).
    function near_surface(params) result(x)
        type(obstacle_params_t), intent(in) :: params
        real(rk) :: x(3), u(3), height
        height = uniform(-0.5_rk, 2.0_rk) * rod_radius
        u = random_unit_vector()
        select case (params%kind)
        case (obstacle_plane)
            x = params%point + uniform(-0.1_rk, 0.1_rk) * [1.0_rk, 0.0_rk, 0.0_rk] + &
                uniform(-0.1_rk, 0.1_rk) * [0.0_rk, 1.0_rk, 0.0_rk] + height * params%normal
        case (obstacle_sphere)
            x = params%point + (params%radius + height) * u
        case default
            u = u - dot_product(u, params%normal) * params%normal
            u = u / norm2(u)
            x = params%point + uniform(-0.1_rk, 0.1_rk) * params%normal + &
                (params%radius + height) * u
        end select
    end function near_surface

    !> f . (x_1 - x_n) = psi(x_1) - psi(x_n) for random steps of up to 2 r.
    subroutine test_energy_identity()
        type(obstacle_params_t) :: params
        real(rk) :: x_n(3), x_1(3), f(3), scale, error, worst
        logical :: touching
        integer :: k, i, touched
        character(len=120) :: text
        call set_random_seed(11, 1)
        worst = 0.0_rk
        do k = 1, 3
            params = obstacle(k)
            touched = 0
            do i = 1, n_steps
                x_n = near_surface(params)
                x_1 = x_n + uniform(0.0_rk, 2.0_rk) * rod_radius * random_unit_vector()
                call obstacle_point_force(params, x_n, x_1, f, touching)
                if (touching) touched = touched + 1
                scale = norm2(f) * norm2(x_1 - x_n) + obstacle_energy(params, x_1) + &
                    obstacle_energy(params, x_n) + tiny(1.0_rk)
                error = abs(dot_product(f, x_1 - x_n) - (obstacle_energy(params, x_1) - &
                    obstacle_energy(params, x_n))) / scale
                worst = max(worst, error)
            end do
            CHECK_TRUE(touched > n_steps / 4, 'a quarter of the steps or more touch the obstacle')
        end do
        CHECK_TRUE(worst <= energy_rtol, 'f . dx = Delta psi')
        write(text, '(a,es9.2)') '    max relative energy error: ', worst
        write(output_unit, '(a)') trim(text)
    end subroutine test_energy_identity

    !> At rest (x_n = x_1) the force is the gradient of the energy: along -n for the plane,
    !> along the radius for the sphere, at right angles to the axis for the cylinder.
    subroutine test_force_direction()
        type(obstacle_params_t) :: params
        real(rk) :: x(3), f(3), radial(3), worst
        logical :: touching
        integer :: k, i
        character(len=120) :: text
        call set_random_seed(12, 1)
        worst = 0.0_rk
        do k = 1, 3
            params = obstacle(k)
            do i = 1, 200
                x = near_surface(params)
                call obstacle_point_force(params, x, x, f, touching)
                if (.not. touching) cycle
                select case (k)
                case (1)
                    radial = params%normal
                case (2)
                    radial = (x - params%point) / norm2(x - params%point)
                case default
                    radial = x - params%point
                    radial = radial - dot_product(radial, params%normal) * params%normal
                    radial = radial / norm2(radial)
                end select
                ! -f (the force on the rod) points outwards along `radial`.
                worst = max(worst, norm2(f + norm2(f) * radial) / norm2(f))
            end do
        end do
        CHECK_TRUE(worst <= 1.0e-14_rk, 'the force is normal to the surface, outwards')
        write(text, '(a,es9.2)') '    max direction error: ', worst
        write(output_unit, '(a)') trim(text)
    end subroutine test_force_direction

    !> A point at penetration delta carries the force k delta^2 (exactly on the plane, to
    !> first order in delta / (R + r) on the sphere and the cylinder) and its penetration is
    !> reported as delta.
    subroutine test_penalty_law()
        type(obstacle_params_t) :: params
        real(rk) :: x(3), f(3), outward(3), delta, rtol
        logical :: touching
        integer :: k
        delta = 1.0e-4_rk
        do k = 1, 3
            params = obstacle(k)
            select case (k)
            case (1)
                outward = params%normal
                x = params%point + (rod_radius - delta) * outward
            case (2)
                outward = [0.0_rk, 0.0_rk, 1.0_rk]
                x = params%point + (params%radius + rod_radius - delta) * outward
            case default
                outward = [-0.8_rk, 0.0_rk, 0.6_rk]
                x = params%point + (params%radius + rod_radius - delta) * outward
            end select
            call obstacle_point_force(params, x, x, f, touching)
            CHECK_TRUE(touching, 'the point touches')
            ! |f| = k delta^2 (1 - delta / (2 (R + r)))^2 (1 - delta / (R + r)): relative
            ! first-order term 2 delta / (R + r) (1.9e-3 for the ball, 3.6e-3 for the cylinder),
            ! bounded by 3 delta / (R + r); the plane's law is exact (round-off).
            rtol = 1.0e-12_rk
            if (k > 1) rtol = 3.0_rk * delta / (params%radius + rod_radius)
            CHECK_CLOSE(norm2(f), stiffness * delta**2, 0.0_rk, rtol, '|f| = k delta^2')
            CHECK_CLOSE(obstacle_penetration(params, x), delta, 1.0e-15_rk, 1.0e-9_rk, 'penetration = delta')
        end do
    end subroutine test_penalty_law

    !> d f / d x_1 against central differences, for steps into and within the support.
    subroutine test_tangent_fd()
        type(obstacle_params_t) :: params
        real(rk) :: x_n(3), x_1(3), tangent(3, 3), h, worst
        integer :: k, i, tested
        character(len=120) :: text
        call set_random_seed(13, 1)
        worst = 0.0_rk
        h = fd_step * rod_radius
        do k = 1, 3
            params = obstacle(k)
            tested = 0
            do i = 1, 300
                x_n = near_surface(params)
                x_1 = x_n + uniform(0.0_rk, 1.0_rk) * rod_radius * random_unit_vector()
                ! Away from the support's edge, where f is C2 but the difference would straddle it.
                if (abs(obstacle_support(params, x_1)) < 1.0e3_rk * h * (1.0_rk + &
                    merge(2.0_rk * (params%radius + rod_radius), 0.0_rk, k > 1))) cycle
                call obstacle_point_tangent(params, x_n, x_1, tangent)
                if (maxval(abs(tangent)) == 0.0_rk) cycle
                tested = tested + 1
                worst = max(worst, difference_error(params, x_n, x_1, h, 0.0_rk, tangent))
            end do
            CHECK_TRUE(tested > 50, 'enough touching steps tested')
        end do
        CHECK_TRUE(worst <= fd_rtol, 'd f / d x_1 = tangent')
        write(text, '(a,es9.2)') '    max FD error / max entry: ', worst
        write(output_unit, '(a)') trim(text)
    end subroutine test_tangent_fd

    !> For random touching steps: f_T . (x_1 - x_n) = D_T (relative to |f_T| |dx|), and
    !> |f_T| <= mu f_N (Coulomb's bound; f_N the normal force of the same step).
    subroutine test_friction_dissipation()
        type(obstacle_params_t) :: params
        real(rk) :: x_n(3), x_1(3), f(3), f_t(3), d, h, worst, excess
        logical :: touching
        integer :: k, i, touched
        character(len=120) :: text
        call set_random_seed(14, 1)
        worst = 0.0_rk
        excess = 0.0_rk
        h = 1.0e-4_rk
        do k = 1, 3
            params = rough(k)
            touched = 0
            do i = 1, n_steps
                x_n = near_surface(params)
                x_1 = x_n + uniform(0.0_rk, 0.5_rk) * rod_radius * random_unit_vector()
                call obstacle_point_force(params, x_n, x_1, f, touching)
                if (.not. touching) cycle
                touched = touched + 1
                call obstacle_point_friction(params, x_n, x_1, h, f_t, d)
                worst = max(worst, abs(dot_product(f_t, x_1 - x_n) - d) / &
                    (norm2(f_t) * norm2(x_1 - x_n) + tiny(1.0_rk)))
                excess = max(excess, norm2(f_t) - params%mu * norm2(f))
            end do
            CHECK_TRUE(touched > n_steps / 4, 'a quarter of the steps or more touch')
        end do
        CHECK_TRUE(worst <= energy_rtol, 'f_T . dx = D_T')
        CHECK_TRUE(excess <= 0.0_rk, '|f_T| <= mu f_N')
        write(text, '(a,es9.2,a,es9.2)') '    max relative error of f_T . dx - D_T: ', worst, &
            '; max |f_T| - mu f_N: ', excess
        write(output_unit, '(a)') trim(text)
    end subroutine test_friction_dissipation

    !> d f_T / d x_1 against central differences (slips of 0.1 to 10 slip velocities).
    subroutine test_friction_tangent_fd()
        type(obstacle_params_t) :: params
        real(rk) :: x_n(3), x_1(3), tangent(3, 3), h, step, worst
        integer :: k, i, tested
        character(len=120) :: text
        call set_random_seed(15, 1)
        worst = 0.0_rk
        step = 1.0e-4_rk
        do k = 1, 3
            params = rough(k)
            tested = 0
            do i = 1, 300
                x_n = near_surface(params)
                x_1 = x_n + 10.0_rk**uniform(-1.0_rk, 1.0_rk) * params%slip_velocity * step * &
                    random_unit_vector()
                if (obstacle_support(params, x_1) < 0.1_rk * rod_radius * merge(1.0_rk, &
                    2.0_rk * (params%radius + rod_radius), k == 1)) cycle
                if (obstacle_support(params, x_n) < 0.1_rk * rod_radius * merge(1.0_rk, &
                    2.0_rk * (params%radius + rod_radius), k == 1)) cycle
                call obstacle_point_friction_tangent(params, x_n, x_1, step, tangent)
                tested = tested + 1
                ! Differences of 1e-4 of the slip scale eta = v_s h.
                h = 1.0e-4_rk * params%slip_velocity * step
                worst = max(worst, difference_error(params, x_n, x_1, h, step, tangent))
            end do
            CHECK_TRUE(tested > 50, 'enough touching steps tested')
        end do
        CHECK_TRUE(worst <= fd_rtol, 'd f_T / d x_1 = tangent')
        write(text, '(a,es9.2)') '    max FD error / max entry: ', worst
        write(output_unit, '(a)') trim(text)
    end subroutine test_friction_tangent_fd

    !> Normal damping (alpha = 0.5 s/m): f_D . (x_1 - x_n) = D_N >= 0 for random steps (relative
    !> to |f_D| |dx|), D_N > 0 for a point that moves into the obstacle; the plane's term is
    !> alpha k delta_bar^2 (d delta / dt) along the normal (Hunt and Crossley) with delta_bar the
    !> mean penetration; its tangent against central differences.
    subroutine test_damping()
        type(obstacle_params_t) :: params
        real(rk) :: x_n(3), x_1(3), f(3), d, h, step, worst, worst_fd, worst_law, tangent(3, 3)
        real(rk) :: xp(3), xm(3), fp(3), fm(3), delta_n, delta_1, expected(3)
        integer :: k, i, j, touched
        character(len=160) :: text
        call set_random_seed(16, 1)
        worst = 0.0_rk
        worst_fd = 0.0_rk
        worst_law = 0.0_rk
        h = 1.0e-4_rk
        do k = 1, 3
            params = obstacle(k)
            params%damping = 0.5_rk
            touched = 0
            do i = 1, n_steps
                x_n = near_surface(params)
                x_1 = x_n + uniform(0.0_rk, 0.3_rk) * rod_radius * random_unit_vector()
                call obstacle_point_damping(params, x_n, x_1, h, f, d)
                if (all(f == 0.0_rk)) cycle
                touched = touched + 1
                CHECK_TRUE(d >= 0.0_rk, 'D_N >= 0')
                worst = max(worst, abs(dot_product(f, x_1 - x_n) - d) / &
                    (norm2(f) * norm2(x_1 - x_n)))
                if (k == 1 .and. obstacle_support(params, x_n) > 0.0_rk .and. &
                        obstacle_support(params, x_1) > 0.0_rk) then
                    delta_n = obstacle_support(params, x_n)
                    delta_1 = obstacle_support(params, x_1)
                    ! The physical force -f_D = alpha k delta_bar^2 (delta_1 - delta_n) / h n.
                    expected = -params%damping * stiffness * (0.5_rk * (delta_n + delta_1))**2 * &
                        (delta_1 - delta_n) / h * params%normal
                    worst_law = max(worst_law, norm2(f - expected) / norm2(expected))
                end if
                if (obstacle_support(params, x_1) < 0.1_rk * rod_radius * merge(1.0_rk, &
                    2.0_rk * (params%radius + rod_radius), k == 1)) cycle
                call obstacle_point_damping_tangent(params, x_n, x_1, h, tangent)
                step = 1.0e-7_rk * rod_radius
                do j = 1, 3
                    xp = x_1
                    xm = x_1
                    xp(j) = xp(j) + step
                    xm(j) = xm(j) - step
                    call obstacle_point_damping(params, x_n, xp, h, fp, d)
                    call obstacle_point_damping(params, x_n, xm, h, fm, d)
                    worst_fd = max(worst_fd, maxval(abs((fp - fm) / (2.0_rk * step) - &
                        tangent(:, j))) / maxval(abs(tangent)))
                end do
            end do
            CHECK_TRUE(touched > n_steps / 4, 'a quarter of the steps or more touch')
        end do
        ! D_N takes (s_1 - s_n)^2 and f_D . dx (s_1 - s_n) grad_bar . dx: equal in exact
        ! arithmetic; s_1 - s_n cancels where s ~ (R + r)^2 and the step is small (measured
        ! 2.7e-12 relative on the sphere and the cylinder).
        CHECK_TRUE(worst <= 1.0e-10_rk, 'f_D . dx = D_N')
        CHECK_TRUE(worst_law <= 1.0e-14_rk, 'the plane: Hunt and Crossley')
        CHECK_TRUE(worst_fd <= fd_rtol, 'd f_D / d x_1 = tangent')
        write(text, '(a,es9.2,a,es9.2,a,es9.2)') '    f_D . dx - D_N: ', worst, &
            '; the plane''s law: ', worst_law, '; FD error / max entry: ', worst_fd
        write(output_unit, '(a)') trim(text)
    end subroutine test_damping

    !> The largest entry of central differences (step h in x_1) minus `tangent`, relative to
    !> its largest entry: of the normal force (time_step 0) or of the friction term of a step
    !> of length time_step.
    function difference_error(params, x_n, x_1, h, time_step, tangent) result(error)
        type(obstacle_params_t), intent(in) :: params
        real(rk), intent(in) :: x_n(3), x_1(3), h, time_step, tangent(3, 3)
        real(rk) :: error, xp(3), xm(3), fp(3), fm(3)
        logical :: touching
        integer :: j
        error = 0.0_rk
        do j = 1, 3
            xp = x_1
            xm = x_1
            xp(j) = xp(j) + h
            xm(j) = xm(j) - h
            if (time_step > 0.0_rk) then
                call obstacle_point_friction(params, x_n, xp, time_step, fp)
                call obstacle_point_friction(params, x_n, xm, time_step, fm)
            else
                call obstacle_point_force(params, x_n, xp, fp, touching)
                call obstacle_point_force(params, x_n, xm, fm, touching)
            end if
            error = max(error, maxval(abs((fp - fm) / (2.0_rk * h) - tangent(:, j))) / &
                maxval(abs(tangent)))
        end do
    end function difference_error

end module rs_test_contact_obstacle

program test_contact_obstacle
    use rs_test_contact_obstacle, only: run_all_tests
    use rs_test_assert, only: finish_tests
    implicit none
    call run_all_tests()
    call finish_tests()
end program test_contact_obstacle
