#include "rs_assert.h"
!> Unit tests of rs_math_so3 (methods/se3_petrov_galerkin.md §4.2, §4.4, §5.5, §14.0, §15.1).
!>
!> Accuracy references are evaluated in quadruple precision from the closed forms of the method
!> document, on the same (double) arguments, so they check both branches of every coefficient.
module rs_test_math_so3
    use rs_core_kinds, only: rk, pi
    use rs_test_random, only: set_random_seed, random_unit_vector
    use rs_test_assert, only: run_test, assert_true, assert_close
    use rs_math_so3, only: hat, vee, exp_so3, log_so3, tangent_so3, tangent_inverse_so3, &
        exp_so3_derivative, tangent_so3_derivative, tangent_inverse_so3_derivative, &
        tangent_so3_directional, tangent_inverse_so3_directional, complement_rotation_vector, &
        so3_series_angle
    implicit none
    private

    public :: run_all_tests

    integer, parameter :: qp = selected_real_kind(30)
    real(rk), parameter :: identity(3, 3) = reshape([1.0_rk, 0.0_rk, 0.0_rk, 0.0_rk, 1.0_rk, &
        0.0_rk, 0.0_rk, 0.0_rk, 1.0_rk], [3, 3])
    ! Finite-difference step and tolerances of the double-precision derivative checks.
    real(rk), parameter :: fd_step = 1.0e-6_rk, fd_rtol = 1.0e-7_rk, fd_atol = 1.0e-8_rk
    ! Tolerance against the quadruple-precision references (relative to max(1, max |entry|)).
    real(rk), parameter :: quad_tol = 5.0e-15_rk

    abstract interface
        pure function matrix_function(psi) result(m)
            import :: rk
            real(rk), intent(in) :: psi(3)
            real(rk) :: m(3, 3)
        end function matrix_function
        pure function derivative_function(psi) result(d)
            import :: rk
            real(rk), intent(in) :: psi(3)
            real(rk) :: d(3, 3, 3)
        end function derivative_function
    end interface

contains

    !> Run every test of this file through rs_test_assert.
    subroutine run_all_tests()
        call set_random_seed(20240611, 7919)
        call run_test('hat_vee', test_hat_vee)
        call run_test('exp_is_rotation', test_exp_is_rotation)
        call run_test('exp_log_round_trip_random', test_exp_log_round_trip_random)
        call run_test('log_near_pi', test_log_near_pi)
        call run_test('log_small_angle', test_log_small_angle)
        call run_test('tangent_times_inverse', test_tangent_times_inverse)
        call run_test('tangent_transpose_symmetry', test_tangent_transpose_symmetry)
        call run_test('tangent_body_frame', test_tangent_body_frame)
        call run_test('exp_derivative_fd', test_exp_derivative_fd)
        call run_test('tangent_derivative_fd', test_tangent_derivative_fd)
        call run_test('tangent_inverse_derivative_fd', test_tangent_inverse_derivative_fd)
        call run_test('directional_matches_derivative', test_directional_matches_derivative)
        call run_test('values_at_zero', test_values_at_zero)
        call run_test('accuracy_against_quad', test_accuracy_against_quad)
        call run_test('derivative_accuracy_against_quad', test_derivative_accuracy_against_quad)
        call run_test('complement_rotation_vector', test_complement_rotation_vector)
    end subroutine run_all_tests

    ! Angle of sample i: uniform in [0, pi), within 1e-8 of 0, within 1e-8 of pi, or
    ! log-uniform in [1e-12, 1], in turn.
    function sample_angle(i) result(angle)
        integer, intent(in) :: i
        real(rk) :: angle, u
        call random_number(u)
        select case (mod(i, 4))
        case (0)
            angle = pi * u
        case (1)
            angle = 1.0e-8_rk * u
        case (2)
            angle = pi - 1.0e-8_rk * u
        case default
            angle = 10.0_rk**(-12.0_rk * u)
        end select
    end function sample_angle

    function cross(a, b) result(c)
        real(rk), intent(in) :: a(3), b(3)
        real(rk) :: c(3)
        c = [a(2) * b(3) - a(3) * b(2), a(3) * b(1) - a(1) * b(3), a(1) * b(2) - a(2) * b(1)]
    end function cross

    function determinant(a) result(d)
        real(rk), intent(in) :: a(3, 3)
        real(rk) :: d
        d = dot_product(a(:, 1), cross(a(:, 2), a(:, 3)))
    end function determinant

    subroutine test_hat_vee()
        real(rk) :: w(3), x(3)
        integer :: i
        do i = 1, 20
            call random_number(w)
            call random_number(x)
            w = 4.0_rk * w - 2.0_rk
            CHECK_CLOSE(matmul(hat(w), x), cross(w, x), 1.0e-15_rk, 1.0e-15_rk, 'hat(w) x = w x x')
            CHECK_CLOSE(hat(w), -transpose(hat(w)), 0.0_rk, 0.0_rk, 'hat is skew')
            CHECK_CLOSE(vee(hat(w)), w, 0.0_rk, 0.0_rk, 'vee(hat(w)) = w')
            CHECK_CLOSE(vee(hat(w) + 3.0_rk * identity), w, 0.0_rk, 1.0e-15_rk, 'vee of skew part')
        end do
    end subroutine test_hat_vee

    subroutine test_exp_is_rotation()
        real(rk) :: psi(3), a(3, 3)
        integer :: i
        CHECK_CLOSE(exp_so3([0.0_rk, 0.0_rk, 0.0_rk]), identity, 0.0_rk, 0.0_rk, 'Exp(0) = 1')
        a = exp_so3([0.0_rk, 0.0_rk, 0.5_rk * pi])
        ! Active rotation: a quarter turn about e_z takes e_x to e_y.
        CHECK_CLOSE(a(:, 1), identity(:, 2), 1.0e-16_rk, 0.0_rk, 'A e_x = e_y')
        do i = 1, 200
            psi = sample_angle(i) * random_unit_vector()
            a = exp_so3(psi)
            CHECK_CLOSE(matmul(transpose(a), a), identity, 4.0e-15_rk, 0.0_rk, 'A^T A = 1')
            CHECK_CLOSE(determinant(a), 1.0_rk, 4.0e-15_rk, 0.0_rk, 'det A = 1')
            CHECK_CLOSE(matmul(a, psi), psi, 4.0e-15_rk, 0.0_rk, 'axis is fixed')
        end do
    end subroutine test_exp_is_rotation

    subroutine test_exp_log_round_trip_random()
        real(rk) :: angle, psi(3), a(3, 3), psi_back(3), error
        integer :: i
        do i = 1, 1000
            angle = sample_angle(i)
            psi = angle * random_unit_vector()
            a = exp_so3(psi)
            psi_back = log_so3(a)
            CHECK_CLOSE(exp_so3(psi_back), a, 4.0e-15_rk, 0.0_rk, 'Exp(Log(A)) = A')
            CHECK_CLOSE(norm2(psi_back), angle, 2.0e-15_rk, 2.0e-15_rk, '|Log(Exp(psi))|')
            ! Within round-off of pi both psi and -psi are logarithms of A.
            if (pi - angle > 1.0e-13_rk) then
                CHECK_CLOSE(psi_back, psi, 1.0e-15_rk, 1.0e-14_rk, 'Log(Exp(psi)) = psi')
            else
                error = min(norm2(psi_back - psi), norm2(psi_back + psi))
                CHECK_TRUE(error < 1.0e-14_rk, 'Log(Exp(psi)) = +/- psi at pi')
            end if
        end do
    end subroutine test_exp_log_round_trip_random

    subroutine test_log_near_pi()
        real(rk), parameter :: gaps(4) = [1.0e-6_rk, 1.0e-8_rk, 1.0e-10_rk, 1.0e-12_rk]
        real(rk) :: axis(3), psi(3), a(3, 3), psi_back(3), error
        integer :: i, j
        do j = 1, 4
            do i = 1, 25
                axis = random_unit_vector()
                psi = (pi - gaps(j)) * axis
                a = exp_so3(psi)
                psi_back = log_so3(a)
                CHECK_CLOSE(psi_back, psi, 4.0e-15_rk, 0.0_rk, 'Log near pi keeps the sign')
                CHECK_CLOSE(norm2(psi_back), pi - gaps(j), 4.0e-15_rk, 0.0_rk, 'angle near pi')
            end do
        end do
        ! Exactly pi: A = 2 n n^T - 1; either sign is a logarithm.
        do i = 1, 25
            axis = random_unit_vector()
            a = 2.0_rk * spread(axis, 2, 3) * spread(axis, 1, 3) - identity
            psi_back = log_so3(a)
            CHECK_CLOSE(norm2(psi_back), pi, 4.0e-15_rk, 0.0_rk, 'angle pi')
            error = min(norm2(psi_back - pi * axis), norm2(psi_back + pi * axis))
            CHECK_TRUE(error < 4.0e-15_rk, 'axis at pi')
            CHECK_CLOSE(exp_so3(psi_back), a, 4.0e-15_rk, 0.0_rk, 'Exp(Log(A)) = A at pi')
        end do
        ! Half turns about the coordinate axes select each diagonal pivot.
        do i = 1, 3
            a = -identity
            a(i, i) = 1.0_rk
            psi_back = log_so3(a)
            CHECK_CLOSE(abs(psi_back(i)), pi, 0.0_rk, 2.0e-15_rk, 'half turn about e_i')
            CHECK_CLOSE(norm2(psi_back), pi, 0.0_rk, 2.0e-15_rk, 'half turn angle')
        end do
    end subroutine test_log_near_pi

    subroutine test_log_small_angle()
        real(rk), parameter :: angles(7) = [0.0_rk, 1.0e-300_rk, 1.0e-12_rk, 1.0e-8_rk, &
            1.0e-4_rk, 0.4999999_rk, 0.5000001_rk]
        real(rk) :: psi(3)
        integer :: i, j
        do j = 1, size(angles)
            do i = 1, 10
                psi = angles(j) * random_unit_vector()
                CHECK_CLOSE(log_so3(exp_so3(psi)), psi, 1.0e-300_rk, 2.0e-15_rk, 'Log(Exp(psi))')
            end do
        end do
    end subroutine test_log_small_angle

    subroutine test_tangent_times_inverse()
        real(rk) :: psi(3), t(3, 3), t_inv(3, 3)
        integer :: i
        do i = 1, 400
            psi = sample_angle(i) * random_unit_vector()
            t = tangent_so3(psi)
            t_inv = tangent_inverse_so3(psi)
            CHECK_CLOSE(matmul(t, t_inv), identity, 4.0e-15_rk, 0.0_rk, 'T T^{-1} = 1')
            CHECK_CLOSE(matmul(t_inv, t), identity, 4.0e-15_rk, 0.0_rk, 'T^{-1} T = 1')
        end do
    end subroutine test_tangent_times_inverse

    subroutine test_tangent_transpose_symmetry()
        real(rk) :: psi(3), t(3, 3), t_inv(3, 3)
        integer :: i
        do i = 1, 200
            psi = sample_angle(i) * random_unit_vector()
            t = transpose(tangent_so3(psi))
            t_inv = transpose(tangent_inverse_so3(psi))
            CHECK_CLOSE(tangent_so3(-psi), t, 1.0e-16_rk, 0.0_rk, 'T(-psi) = T(psi)^T')
            CHECK_CLOSE(tangent_inverse_so3(-psi), t_inv, 1.0e-16_rk, 0.0_rk, 'T^{-1}(-psi)')
        end do
    end subroutine test_tangent_transpose_symmetry

    ! A^T dA/dpsi_k = hat(T(psi) e_k): T is the material (body-frame) tangent (methods eq. (78)).
    subroutine test_tangent_body_frame()
        real(rk) :: psi(3), a(3, 3), da(3, 3), t(3, 3), e(3)
        integer :: i, k
        do i = 1, 100
            psi = fd_angle(i) * random_unit_vector()
            a = exp_so3(psi)
            t = tangent_so3(psi)
            do k = 1, 3
                e = 0.0_rk
                e(k) = fd_step
                da = matmul(transpose(a), exp_so3(psi + e) - exp_so3(psi - e)) / (2 * fd_step)
                CHECK_CLOSE(da, hat(t(:, k)), fd_atol, fd_rtol, 'A^T dA = hat(T dpsi)')
            end do
        end do
    end subroutine test_tangent_body_frame

    ! Angles for the finite-difference checks: small (1e-5), large (3.0) and random in [0, pi).
    function fd_angle(i) result(angle)
        integer, intent(in) :: i
        real(rk) :: angle
        select case (mod(i, 4))
        case (0)
            angle = 1.0e-5_rk
        case (1)
            angle = 3.0_rk
        case default
            call random_number(angle)
            angle = pi * angle
        end select
    end function fd_angle

    subroutine test_exp_derivative_fd()
        call check_derivative_fd(exp_so3, exp_so3_derivative, 'dExp/dpsi_k')
    end subroutine test_exp_derivative_fd

    subroutine test_tangent_derivative_fd()
        call check_derivative_fd(tangent_so3, tangent_so3_derivative, 'dT/dpsi_k')
    end subroutine test_tangent_derivative_fd

    subroutine test_tangent_inverse_derivative_fd()
        call check_derivative_fd(tangent_inverse_so3, tangent_inverse_so3_derivative, &
            'dT^{-1}/dpsi_k')
    end subroutine test_tangent_inverse_derivative_fd

    !> The analytic derivative d(:, :, k) = dM/dpsi_k against central differences of M at 100
    !> rotation vectors whose angles are chosen by fd_angle.
    subroutine check_derivative_fd(matrix_of, derivative_of, label)
        procedure(matrix_function) :: matrix_of
        procedure(derivative_function) :: derivative_of
        character(len=*), intent(in) :: label
        real(rk) :: psi(3), d(3, 3, 3), e(3), fd(3, 3)
        integer :: i, k
        do i = 1, 100
            psi = fd_angle(i) * random_unit_vector()
            d = derivative_of(psi)
            do k = 1, 3
                e = 0.0_rk
                e(k) = fd_step
                fd = (matrix_of(psi + e) - matrix_of(psi - e)) / (2.0_rk * fd_step)
                CHECK_CLOSE(d(:, :, k), fd, fd_atol, fd_rtol, label)
            end do
        end do
    end subroutine check_derivative_fd

    subroutine test_directional_matches_derivative()
        real(rk) :: psi(3), u(3), dt(3, 3, 3), dt_inv(3, 3, 3), expected(3, 3), got(3, 3)
        integer :: i, k
        do i = 1, 50
            psi = sample_angle(i) * random_unit_vector()
            call random_number(u)
            u = 2.0_rk * u - 1.0_rk
            dt = tangent_so3_derivative(psi)
            dt_inv = tangent_inverse_so3_derivative(psi)
            expected = 0.0_rk
            do k = 1, 3
                expected = expected + u(k) * dt(:, :, k)
            end do
            CHECK_CLOSE(tangent_so3_directional(psi, u), expected, 1.0e-15_rk, 1.0e-14_rk, 'D T')
            expected = 0.0_rk
            do k = 1, 3
                expected = expected + u(k) * dt_inv(:, :, k)
            end do
            got = tangent_inverse_so3_directional(psi, u)
            CHECK_CLOSE(got, expected, 1.0e-15_rk, 1.0e-14_rk, 'D T^{-1}')
        end do
    end subroutine test_directional_matches_derivative

    ! Limits at psi = 0 (methods §4.2, §4.4): T = T^{-1} = Exp = 1, dExp_k = hat(e_k),
    ! dT_k = -hat(e_k)/2, dT^{-1}_k = hat(e_k)/2; no division by the zero angle.
    subroutine test_values_at_zero()
        real(rk) :: zero(3), d_exp(3, 3, 3), d_t(3, 3, 3), d_tinv(3, 3, 3), e(3)
        integer :: k
        zero = 0.0_rk
        CHECK_CLOSE(tangent_so3(zero), identity, 0.0_rk, 0.0_rk, 'T(0) = 1')
        CHECK_CLOSE(tangent_inverse_so3(zero), identity, 0.0_rk, 0.0_rk, 'T^{-1}(0) = 1')
        CHECK_CLOSE(log_so3(identity), zero, 0.0_rk, 0.0_rk, 'Log(1) = 0')
        d_exp = exp_so3_derivative(zero)
        d_t = tangent_so3_derivative(zero)
        d_tinv = tangent_inverse_so3_derivative(zero)
        do k = 1, 3
            e = 0.0_rk
            e(k) = 1.0_rk
            CHECK_CLOSE(d_exp(:, :, k), hat(e), 0.0_rk, 0.0_rk, 'dExp(0)')
            CHECK_CLOSE(d_t(:, :, k), -0.5_rk * hat(e), 0.0_rk, 0.0_rk, 'dT(0)')
            CHECK_CLOSE(d_tinv(:, :, k), 0.5_rk * hat(e), 0.0_rk, 0.0_rk, 'dT^{-1}(0)')
        end do
    end subroutine test_values_at_zero

    ! Angles straddling the series threshold and spanning (0, pi).
    function accuracy_angles() result(angles)
        real(rk) :: angles(16)
        angles = [1.0e-9_rk, 1.0e-6_rk, 1.0e-4_rk, 1.0e-2_rk, 0.1_rk, 0.3_rk, &
            so3_series_angle * (1.0_rk - 1.0e-12_rk), so3_series_angle, &
            so3_series_angle * (1.0_rk + 1.0e-12_rk), 0.7_rk, 1.0_rk, 1.5_rk, 2.0_rk, 2.5_rk, &
            3.0_rk, pi - 1.0e-6_rk]
    end function accuracy_angles

    subroutine check_quad(actual, reference, message)
        real(rk), intent(in) :: actual(:, :)
        real(qp), intent(in) :: reference(:, :)
        character(len=*), intent(in) :: message
        real(rk) :: scale
        scale = max(1.0_rk, real(maxval(abs(reference)), rk))
        CHECK_CLOSE(actual, real(reference, rk), quad_tol * scale, 0.0_rk, message)
    end subroutine check_quad

    subroutine test_accuracy_against_quad()
        real(rk) :: psi(3), angles(16)
        integer :: i, j
        angles = accuracy_angles()
        do j = 1, size(angles)
            do i = 1, 5
                psi = angles(j) * random_unit_vector()
                call check_quad(exp_so3(psi), exp_quad(real(psi, qp)), 'Exp vs quad')
                call check_quad(tangent_so3(psi), tangent_quad(real(psi, qp)), 'T vs quad')
                call check_quad(tangent_inverse_so3(psi), tangent_inverse_quad(real(psi, qp)), &
                    'T^{-1} vs quad')
            end do
        end do
    end subroutine test_accuracy_against_quad

    ! Derivatives against central differences of the quadruple-precision closed forms (step
    ! 1e-10: truncation ~1e-20, round-off ~1e-24), which resolve the double results to round-off.
    subroutine test_derivative_accuracy_against_quad()
        real(qp), parameter :: h = 1.0e-10_qp
        real(rk) :: psi(3), angles(16), d_exp(3, 3, 3), d_t(3, 3, 3), d_tinv(3, 3, 3)
        real(qp) :: psi_q(3), e(3)
        integer :: i, j, k
        angles = accuracy_angles()
        do j = 1, size(angles)
            do i = 1, 3
                psi = angles(j) * random_unit_vector()
                psi_q = real(psi, qp)
                d_exp = exp_so3_derivative(psi)
                d_t = tangent_so3_derivative(psi)
                d_tinv = tangent_inverse_so3_derivative(psi)
                do k = 1, 3
                    e = 0.0_qp
                    e(k) = h
                    call check_quad(d_exp(:, :, k), (exp_quad(psi_q + e) - exp_quad(psi_q - e)) &
                        / (2.0_qp * h), 'dExp vs quad')
                    call check_quad(d_t(:, :, k), (tangent_quad(psi_q + e) &
                        - tangent_quad(psi_q - e)) / (2.0_qp * h), 'dT vs quad')
                    call check_quad(d_tinv(:, :, k), (tangent_inverse_quad(psi_q + e) &
                        - tangent_inverse_quad(psi_q - e)) / (2.0_qp * h), 'dT^{-1} vs quad')
                end do
            end do
        end do
    end subroutine test_derivative_accuracy_against_quad

    subroutine test_complement_rotation_vector()
        real(rk) :: psi(3), psi_c(3), angle, axis(3), expected(3)
        integer :: i
        do i = 1, 200
            axis = random_unit_vector()
            call random_number(angle)
            angle = pi + 2.0_rk * pi * angle
            psi = angle * axis
            psi_c = complement_rotation_vector(psi)
            expected = (1.0_rk - 2.0_rk * pi / angle) * psi
            CHECK_CLOSE(psi_c, expected, 1.0e-14_rk, 0.0_rk, 'complement (40)')
            CHECK_TRUE(norm2(psi_c) <= pi + 1.0e-14_rk, '|psi_c| <= pi')
            CHECK_CLOSE(exp_so3(psi_c), exp_so3(psi), 4.0e-15_rk, 0.0_rk, 'same rotation')
            psi = (pi - 1.0e-3_rk) * axis
            CHECK_CLOSE(complement_rotation_vector(psi), psi, 0.0_rk, 0.0_rk, '|psi| <= pi kept')
        end do
        ! Several turns: 5.5 pi -> -0.5 pi along the same axis.
        psi = 5.5_rk * pi * axis
        psi_c = complement_rotation_vector(psi)
        CHECK_CLOSE(psi_c, -0.5_rk * pi * axis, 1.0e-14_rk, 0.0_rk, 'several turns')
        CHECK_CLOSE(exp_so3(psi_c), exp_so3(psi), 1.0e-14_rk, 0.0_rk, 'several turns: Exp')
    end subroutine test_complement_rotation_vector

    ! Quadruple-precision closed forms of methods eqs. (75), (78), (79) (angle > 0).

    function hat_quad(w) result(w_hat)
        real(qp), intent(in) :: w(3)
        real(qp) :: w_hat(3, 3)
        w_hat = reshape([0.0_qp, w(3), -w(2), -w(3), 0.0_qp, w(1), w(2), -w(1), 0.0_qp], [3, 3])
    end function hat_quad

    function identity_quad() result(one)
        real(qp) :: one(3, 3)
        integer :: i
        one = 0.0_qp
        do i = 1, 3
            one(i, i) = 1.0_qp
        end do
    end function identity_quad

    function exp_quad(psi) result(a)
        real(qp), intent(in) :: psi(3)
        real(qp) :: a(3, 3), x, w(3, 3)
        x = norm2(psi)
        w = hat_quad(psi)
        a = identity_quad() + sin(x) / x * w + (1.0_qp - cos(x)) / x**2 * matmul(w, w)
    end function exp_quad

    function tangent_quad(psi) result(t)
        real(qp), intent(in) :: psi(3)
        real(qp) :: t(3, 3), x, w(3, 3)
        x = norm2(psi)
        w = hat_quad(psi)
        t = identity_quad() - (1.0_qp - cos(x)) / x**2 * w + (x - sin(x)) / x**3 * matmul(w, w)
    end function tangent_quad

    function tangent_inverse_quad(psi) result(t)
        real(qp), intent(in) :: psi(3)
        real(qp) :: t(3, 3), x, w(3, 3), gamma
        x = norm2(psi)
        w = hat_quad(psi)
        gamma = 0.5_qp * x * cos(0.5_qp * x) / sin(0.5_qp * x)
        t = identity_quad() + 0.5_qp * w + (1.0_qp - gamma) / x**2 * matmul(w, w)
    end function tangent_inverse_quad

end module rs_test_math_so3

program test_so3
    use rs_test_math_so3, only: run_all_tests
    use rs_test_assert, only: finish_tests
    implicit none
    call run_all_tests()
    call finish_tests()
end program test_so3
