#include "rs_assert.h"
!> Unit tests of rs_ph_director_body (a rigid body on a rod's end node in director form, issue
!> 24 item 4): for random bodies (mass, centre off the node, a full inertia tensor) at random
!> orientations with rigid director rates w_i = omega x d_i, the director form's kinetic
!> energy and momenta equal the rigid body's 1/2 m |v_c|^2 + 1/2 omega . J omega, m v_c and
!> x_c x m v_c + J omega (J turned with the body); the mass matrix is symmetric; the weight's
!> generalized force does the work m g . (change of the centre of mass) for any step of the
!> node's coordinates. Measured worst values are printed.
module rs_test_ph_director_body
    use, intrinsic :: iso_fortran_env, only: output_unit
    use rs_core_kinds, only: rk
    use rs_test_random, only: set_random_seed, random_unit_vector, uniform, random_vector
    use rs_test_assert, only: run_test, assert_true
    use rs_math_so3, only: exp_so3, hat
    use rs_ph_director_body, only: ph_director_body_t, ph_director_body_init, &
        ph_director_body_kinetic_energy, ph_director_body_momenta, ph_director_body_weight, &
        ph_director_body_centre
    implicit none
    private

    public :: run_all_tests

    !> Round-off of sums of a few products of O(1) numbers.
    real(rk), parameter :: rtol = 1.0e-13_rk
    integer, parameter :: n_trials = 200

contains

    subroutine run_all_tests()
        call set_random_seed(2024, 11)
        call run_test('rigid_form', test_rigid_form)
        call run_test('weight_work', test_weight_work)
    end subroutine run_all_tests

    !> A random body: mass, centre, an inertia tensor of a body (J = tr(E) I - E for a random
    !> positive semidefinite second-moment tensor E), at random reference directors.
    subroutine random_body(body, mass, centre, inertia, directors)
        type(ph_director_body_t), intent(out) :: body
        real(rk), intent(out) :: mass, centre(3), inertia(3, 3), directors(3, 3)
        real(rk) :: a(3, 3), second(3, 3)
        integer :: i
        mass = uniform(0.1_rk, 5.0_rk)
        centre = random_vector(3, 0.3_rk)
        do i = 1, 3
            a(:, i) = random_vector(3, 0.2_rk)
        end do
        second = mass * matmul(a, transpose(a))
        inertia = -second
        do i = 1, 3
            inertia(i, i) = inertia(i, i) + second(1, 1) + second(2, 2) + second(3, 3)
        end do
        directors = exp_so3(uniform(0.0_rk, 3.0_rk) * random_unit_vector())
        body = ph_director_body_init(1, mass, centre, inertia, directors)
    end subroutine random_body

    subroutine test_rigid_form()
        type(ph_director_body_t) :: body
        real(rk) :: mass, centre(3), inertia(3, 3), reference(3, 3), rotation(3, 3), d(3, 3)
        real(rk) :: q(12), v(12), omega(3), velocity(3), x_c(3), v_c(3), j_now(3, 3)
        real(rk) :: energy, expected, linear(3), angular(3), worst(4), asymmetry
        integer :: trial, i
        character(len=160) :: text
        worst = 0.0_rk
        asymmetry = 0.0_rk
        do trial = 1, n_trials
            call random_body(body, mass, centre, inertia, reference)
            asymmetry = max(asymmetry, maxval(abs(body%mass_matrix - &
                transpose(body%mass_matrix))))
            ! The body turned by a random rotation and moving rigidly.
            rotation = exp_so3(uniform(0.0_rk, 3.0_rk) * random_unit_vector())
            d = matmul(rotation, reference)
            q(1:3) = random_vector(3, 2.0_rk)
            omega = random_vector(3, 3.0_rk)
            velocity = random_vector(3, 1.0_rk)
            v(1:3) = velocity
            do i = 1, 3
                q(3 * i + 1:3 * i + 3) = d(:, i)
                v(3 * i + 1:3 * i + 3) = matmul(hat(omega), d(:, i))
            end do
            x_c = ph_director_body_centre(body, q)
            v_c = velocity + matmul(hat(omega), x_c - q(1:3))
            j_now = matmul(rotation, matmul(inertia, transpose(rotation)))
            energy = ph_director_body_kinetic_energy(body, v)
            expected = 0.5_rk * mass * dot_product(v_c, v_c) + &
                0.5_rk * dot_product(omega, matmul(j_now, omega))
            worst(1) = max(worst(1), abs(energy - expected) / expected)
            call ph_director_body_momenta(body, q, v, linear, angular)
            worst(2) = max(worst(2), norm2(linear - mass * v_c) / norm2(mass * v_c))
            worst(3) = max(worst(3), norm2(angular - (mass * matmul(hat(x_c), v_c) + &
                matmul(j_now, omega))) / (norm2(mass * matmul(hat(x_c), v_c)) + &
                norm2(matmul(j_now, omega))))
            ! The centre is where the input put it, turned with the body.
            worst(4) = max(worst(4), norm2(x_c - q(1:3) - matmul(rotation, centre)) / &
                (1.0_rk + norm2(centre)))
        end do
        CHECK_TRUE(asymmetry == 0.0_rk, 'the mass matrix is symmetric')
        CHECK_TRUE(worst(1) <= rtol, 'T = 1/2 m |v_c|^2 + 1/2 omega . J omega')
        CHECK_TRUE(worst(2) <= rtol, 'p = m v_c')
        CHECK_TRUE(worst(3) <= rtol, 'l = x_c x m v_c + J omega')
        CHECK_TRUE(worst(4) <= rtol, 'the centre of mass turns with the body')
        write(text, '(a,4es9.2)') '    max relative error of T, p, l, x_c against the rigid body: ', &
            worst
        write(output_unit, '(a)') trim(text)
    end subroutine test_rigid_form

    !> The weight's generalized force g_w . (q_1 - q_n) = m g . (x_c(q_1) - x_c(q_n)) for any
    !> step of the coordinates (also non-rigid ones: the centre is linear in q).
    subroutine test_weight_work()
        type(ph_director_body_t) :: body
        real(rk) :: mass, centre(3), inertia(3, 3), reference(3, 3), q_n(12), q_1(12), g(3)
        real(rk) :: work, expected, worst
        integer :: trial
        character(len=120) :: text
        worst = 0.0_rk
        do trial = 1, n_trials
            call random_body(body, mass, centre, inertia, reference)
            q_n = random_vector(12, 1.0_rk)
            q_1 = q_n + random_vector(12, 0.3_rk)
            g = random_vector(3, 10.0_rk)
            work = dot_product(ph_director_body_weight(body, g), q_1 - q_n)
            expected = mass * dot_product(g, ph_director_body_centre(body, q_1) - &
                ph_director_body_centre(body, q_n))
            worst = max(worst, abs(work - expected) / (mass * norm2(g) * (1.0_rk + &
                norm2(q_1 - q_n))))
        end do
        CHECK_TRUE(worst <= rtol, 'the weight does the work m g . dx_c')
        write(text, '(a,es9.2)') '    max relative error of the weight''s work: ', worst
        write(output_unit, '(a)') trim(text)
    end subroutine test_weight_work

end module rs_test_ph_director_body

program test_ph_director_body
    use rs_test_ph_director_body, only: run_all_tests
    use rs_test_assert, only: finish_tests
    implicit none
    call run_all_tests()
    call finish_tests()
end program test_ph_director_body
