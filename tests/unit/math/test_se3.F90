#include "rs_assert.h"
!> Unit tests of rs_math_se3 (methods/se3_petrov_galerkin.md §4, §5.2, §5.3, §8.1, §14.0).
module rs_test_math_se3
    use rs_core_kinds, only: rk, pi
    use rs_test_random, only: set_random_seed, random_unit_vector
    use rs_test_assert, only: run_test, assert_true, assert_close
    use rs_math_so3, only: exp_so3
    use rs_math_se3, only: hat_se3, vee_se3, ad_se3, exp_se3, log_se3, tangent_se3, &
        tangent_inverse_se3, adjoint_se3, pose_compose, pose_inverse, pose_relative, &
        pose_matrix, pose_from_matrix
    implicit none
    private

    public :: run_all_tests

    real(rk), parameter :: fd_step = 1.0e-6_rk, fd_rtol = 1.0e-7_rk, fd_atol = 1.0e-8_rk

contains

    !> Run every test of this file through rs_test_assert.
    subroutine run_all_tests()
        call set_random_seed(271828, 1299709)
        call run_test('hat_vee_ad', test_hat_vee_ad)
        call run_test('exp_log_round_trip', test_exp_log_round_trip)
        call run_test('exp_matches_matrix_series', test_exp_matches_matrix_series)
        call run_test('tangent_matches_series', test_tangent_matches_series)
        call run_test('tangent_material_fd', test_tangent_material_fd)
        call run_test('tangent_times_inverse', test_tangent_times_inverse)
        call run_test('tangent_fixes_own_twist', test_tangent_fixes_own_twist)
        call run_test('adjoint', test_adjoint)
        call run_test('pose_helpers', test_pose_helpers)
        call run_test('quarter_circle', test_quarter_circle)
        call run_test('constant_strain', test_constant_strain)
    end subroutine run_all_tests

    ! Twist of sample i: translation in [-2, 2]^3, rotation angle uniform in [0, pi), within
    ! 1e-8 of 0, within 1e-8 of pi, or fixed small (1e-5) / large (3.0), in turn.
    function random_twist(i) result(theta)
        integer, intent(in) :: i
        real(rk) :: theta(6), angle
        call random_number(theta(1:3))
        theta(1:3) = 4.0_rk * theta(1:3) - 2.0_rk
        call random_number(angle)
        select case (mod(i, 5))
        case (0)
            angle = pi * angle
        case (1)
            angle = 1.0e-8_rk * angle
        case (2)
            angle = pi - 1.0e-8_rk * angle
        case (3)
            angle = 1.0e-5_rk
        case default
            angle = 3.0_rk
        end select
        theta(4:6) = angle * random_unit_vector()
    end function random_twist

    function exp_matrix(theta) result(h)
        real(rk), intent(in) :: theta(6)
        real(rk) :: h(4, 4), a(3, 3), r(3)
        call exp_se3(theta, a, r)
        h = pose_matrix(a, r)
    end function exp_matrix

    function inverse_matrix(h) result(h_inv)
        real(rk), intent(in) :: h(4, 4)
        real(rk) :: h_inv(4, 4), a(3, 3), r(3), a_inv(3, 3), r_inv(3)
        call pose_from_matrix(h, a, r)
        call pose_inverse(a, r, a_inv, r_inv)
        h_inv = pose_matrix(a_inv, r_inv)
    end function inverse_matrix

    function identity(n) result(one)
        integer, intent(in) :: n
        real(rk) :: one(n, n)
        integer :: i
        one = 0.0_rk
        do i = 1, n
            one(i, i) = 1.0_rk
        end do
    end function identity

    subroutine test_hat_vee_ad()
        real(rk) :: x(6), y(6), lie_bracket(4, 4)
        integer :: i
        do i = 1, 50
            x = random_twist(i)
            y = random_twist(i + 1)
            CHECK_CLOSE(vee_se3(hat_se3(x)), x, 0.0_rk, 0.0_rk, 'vee(hat(x)) = x')
            ! ad_x y is the twist of the commutator [hat x, hat y] (methods §4.1).
            lie_bracket = matmul(hat_se3(x), hat_se3(y)) - matmul(hat_se3(y), hat_se3(x))
            CHECK_CLOSE(hat_se3(matmul(ad_se3(x), y)), lie_bracket, 1.0e-14_rk, 0.0_rk, 'ad')
        end do
    end subroutine test_hat_vee_ad

    subroutine test_exp_log_round_trip()
        real(rk) :: theta(6), a(3, 3), r(3), theta_back(6), a_back(3, 3), r_back(3)
        integer :: i
        do i = 1, 1000
            theta = random_twist(i)
            call exp_se3(theta, a, r)
            theta_back = log_se3(a, r)
            call exp_se3(theta_back, a_back, r_back)
            CHECK_CLOSE(a_back, a, 4.0e-15_rk, 0.0_rk, 'Exp(Log(H)) = H: rotation')
            CHECK_CLOSE(r_back, r, 1.0e-14_rk, 0.0_rk, 'Exp(Log(H)) = H: position')
            ! Exactly at pi the logarithm is not unique; the samples stay 1e-13 away from it.
            if (pi - norm2(theta(4:6)) > 1.0e-13_rk) then
                CHECK_CLOSE(theta_back, theta, 1.0e-12_rk, 0.0_rk, 'Log(Exp(theta)) = theta')
            end if
        end do
    end subroutine test_exp_log_round_trip

    ! Exp_SE3 (83) against the matrix exponential series of hat_se3(theta).
    subroutine test_exp_matches_matrix_series()
        real(rk) :: theta(6), x(4, 4), term(4, 4), series(4, 4)
        integer :: i, n
        do i = 1, 100
            theta = random_twist(i)
            theta(4:6) = theta(4:6) * (2.0_rk / pi)
            x = hat_se3(theta)
            term = identity(4)
            series = term
            do n = 1, 60
                term = matmul(term, x) / real(n, rk)
                series = series + term
            end do
            CHECK_CLOSE(exp_matrix(theta), series, 1.0e-14_rk, 0.0_rk, 'Exp_SE3 = exp series')
        end do
    end subroutine test_exp_matches_matrix_series

    ! T_SE3 against its defining series sum (-1)^i/(i+1)! ad^i (methods eq. (68)), at small and
    ! moderate twists.
    subroutine test_tangent_matches_series()
        real(rk), parameter :: scales(5) = [1.0e-9_rk, 1.0e-5_rk, 1.0e-2_rk, 0.3_rk, 1.0_rk]
        real(rk) :: theta(6), ad(6, 6), power(6, 6), series(6, 6)
        integer :: i, j, n
        do j = 1, size(scales)
            do i = 1, 20
                call random_number(theta)
                theta = scales(j) * (2.0_rk * theta - 1.0_rk)
                ad = ad_se3(theta)
                ! power = (-ad)^n / n!, term n of the series = power / (n + 1).
                power = identity(6)
                series = power
                do n = 1, 60
                    power = -matmul(power, ad) / real(n, rk)
                    series = series + power / real(n + 1, rk)
                end do
                CHECK_CLOSE(tangent_se3(theta), series, 4.0e-15_rk, 0.0_rk, 'T_SE3 = series')
            end do
        end do
    end subroutine test_tangent_matches_series

    ! Exp(theta)^{-1} dExp(theta)/dtheta_k = hat_se3(T_SE3(theta) e_k): the material (right)
    ! convention of methods eqs. (62), (67).
    subroutine test_tangent_material_fd()
        real(rk) :: theta(6), t(6, 6), e(6), dh(4, 4), h_inv(4, 4), zero(4)
        integer :: i, k
        zero = 0.0_rk
        do i = 1, 100
            theta = random_twist(i)
            t = tangent_se3(theta)
            h_inv = inverse_matrix(exp_matrix(theta))
            do k = 1, 6
                e = 0.0_rk
                e(k) = fd_step
                dh = (exp_matrix(theta + e) - exp_matrix(theta - e)) / (2.0_rk * fd_step)
                dh = matmul(h_inv, dh)
                CHECK_CLOSE(vee_se3(dh), t(:, k), fd_atol, fd_rtol, 'H^{-1} dH = hat(T dtheta)')
                CHECK_CLOSE(dh(4, :), zero, fd_atol, 0.0_rk, 'last row of H^{-1} dH')
            end do
        end do
    end subroutine test_tangent_material_fd

    subroutine test_tangent_times_inverse()
        real(rk) :: theta(6), product(6, 6)
        integer :: i
        do i = 1, 500
            theta = random_twist(i)
            product = matmul(tangent_se3(theta), tangent_inverse_se3(theta))
            CHECK_CLOSE(product, identity(6), 1.0e-14_rk, 0.0_rk, 'T_SE3 T_SE3^{-1} = 1')
            product = matmul(tangent_inverse_se3(theta), tangent_se3(theta))
            CHECK_CLOSE(product, identity(6), 1.0e-14_rk, 0.0_rk, 'T_SE3^{-1} T_SE3 = 1')
        end do
    end subroutine test_tangent_times_inverse

    ! If j(x) and j(y) commute, T(x) y = y (methods §4.1, the reason for constant strains (33)).
    subroutine test_tangent_fixes_own_twist()
        real(rk) :: theta(6), s, image(6)
        integer :: i
        do i = 1, 200
            theta = random_twist(i)
            call random_number(s)
            image = matmul(tangent_se3(s * theta), theta)
            CHECK_CLOSE(image, theta, 1.0e-14_rk, 0.0_rk, 'T(s x) x = x')
            image = matmul(tangent_inverse_se3(s * theta), theta)
            CHECK_CLOSE(image, theta, 1.0e-14_rk, 0.0_rk, 'T^{-1}(s x) x = x')
        end do
    end subroutine test_tangent_fixes_own_twist

    subroutine test_adjoint()
        real(rk) :: theta(6), x(6), a(3, 3), r(3), a2(3, 3), r2(3), a12(3, 3), r12(3)
        real(rk) :: h(4, 4), expected(6, 6), conjugated(4, 4)
        integer :: i
        do i = 1, 100
            x = random_twist(i)
            call exp_se3(x, a, r)
            call exp_se3(random_twist(i + 2), a2, r2)
            theta = random_twist(i + 1)
            h = pose_matrix(a, r)
            conjugated = matmul(matmul(h, hat_se3(theta)), inverse_matrix(h))
            x = matmul(adjoint_se3(a, r), theta)
            CHECK_CLOSE(hat_se3(x), conjugated, 1.0e-13_rk, 0.0_rk, 'H hat(y) H^-1 = hat(Ad y)')
            call pose_compose(a, r, a2, r2, a12, r12)
            expected = matmul(adjoint_se3(a, r), adjoint_se3(a2, r2))
            CHECK_CLOSE(adjoint_se3(a12, r12), expected, 1.0e-13_rk, 0.0_rk, 'Ad(H1 H2)')
            ! Exp(Ad_H theta) = H Exp(theta) H^{-1}.
            conjugated = matmul(matmul(h, exp_matrix(theta)), inverse_matrix(h))
            CHECK_CLOSE(exp_matrix(x), conjugated, 1.0e-13_rk, 0.0_rk, 'Exp(Ad y) = H Exp(y) H^-1')
        end do
    end subroutine test_adjoint

    subroutine test_pose_helpers()
        real(rk) :: a1(3, 3), r1(3), a2(3, 3), r2(3), a(3, 3), r(3), h1(4, 4), h2(4, 4)
        real(rk) :: expected(4, 4)
        integer :: i
        do i = 1, 100
            call exp_se3(random_twist(i), a1, r1)
            call exp_se3(random_twist(i + 1), a2, r2)
            h1 = pose_matrix(a1, r1)
            h2 = pose_matrix(a2, r2)
            call pose_from_matrix(h1, a, r)
            CHECK_CLOSE(pose_matrix(a, r), h1, 0.0_rk, 0.0_rk, 'matrix round trip')
            call pose_compose(a1, r1, a2, r2, a, r)
            expected = matmul(h1, h2)
            CHECK_CLOSE(pose_matrix(a, r), expected, 1.0e-14_rk, 0.0_rk, 'compose = H1 H2')
            call pose_inverse(a1, r1, a, r)
            CHECK_CLOSE(matmul(pose_matrix(a, r), h1), identity(4), 1.0e-14_rk, 0.0_rk, 'H^-1 H')
            CHECK_CLOSE(matmul(h1, pose_matrix(a, r)), identity(4), 1.0e-14_rk, 0.0_rk, 'H H^-1')
            call pose_relative(a1, r1, a2, r2, a, r)
            expected = matmul(inverse_matrix(h1), h2)
            CHECK_CLOSE(pose_matrix(a, r), expected, 1.0e-14_rk, 0.0_rk, 'relative = H1^-1 H2')
        end do
    end subroutine test_pose_helpers

    ! Fig. 2 data (methods §8.1, §13 item 6, §14.0): node 0 at the origin with psi_0 =
    ! (0, -pi/2, 0), node 1 at (1, 0, 1) with psi_1 = 0. The element twist is (pi/2, 0, 0, 0,
    ! pi/2, 0) and the interpolated centreline H_0 Exp(xi theta) lies on the circle of radius 1
    ! about (1, 0, 0) in the e_x-e_z plane.
    subroutine test_quarter_circle()
        real(rk) :: a0(3, 3), r0(3), a1(3, 3), r1(3), a(3, 3), r(3), theta(6), expected(6)
        real(rk) :: a_xi(3, 3), r_xi(3), point(3), xi, centre(3)
        integer :: i
        a0 = exp_so3([0.0_rk, -0.5_rk * pi, 0.0_rk])
        r0 = 0.0_rk
        a1 = identity(3)
        r1 = [1.0_rk, 0.0_rk, 1.0_rk]
        centre = [1.0_rk, 0.0_rk, 0.0_rk]
        call pose_relative(a0, r0, a1, r1, a, r)
        theta = log_se3(a, r)
        expected = [0.5_rk * pi, 0.0_rk, 0.0_rk, 0.0_rk, 0.5_rk * pi, 0.0_rk]
        CHECK_CLOSE(theta, expected, 4.0e-15_rk, 0.0_rk, 'element twist of Fig. 2')
        do i = 0, 20
            xi = real(i, rk) / 20.0_rk
            call exp_se3(xi * theta, a_xi, r_xi)
            call pose_compose(a0, r0, a_xi, r_xi, a, point)
            CHECK_CLOSE(norm2(point - centre), 1.0_rk, 4.0e-15_rk, 0.0_rk, 'radius')
            CHECK_CLOSE(point(2), 0.0_rk, 4.0e-15_rk, 0.0_rk, 'e_x-e_z plane')
            ! The director e_x^K stays tangent to the circle.
            r = [point(3), 0.0_rk, 1.0_rk - point(1)]
            CHECK_CLOSE(a(:, 1), r, 4.0e-15_rk, 0.0_rk, 'tangent director')
        end do
        CHECK_CLOSE(point, r1, 4.0e-15_rk, 0.0_rk, 'interpolates node 1')
        CHECK_CLOSE(a, a1, 4.0e-15_rk, 0.0_rk, 'interpolates node 1 rotation')
    end subroutine test_quarter_circle

    ! For random nodal poses the interpolated field H(xi) = H_0 Exp(xi theta) has the constant
    ! strain vee(H^{-1} dH/dxi) = theta (methods eq. (33), §14.0, §15 item 2).
    subroutine test_constant_strain()
        real(rk) :: a0(3, 3), r0(3), a1(3, 3), r1(3), a(3, 3), r(3), theta(6), xi, h0(4, 4)
        real(rk) :: dh(4, 4)
        integer :: i, j
        do i = 1, 50
            call exp_se3(random_twist(i), a0, r0)
            call exp_se3(random_twist(i + 1), a1, r1)
            call pose_relative(a0, r0, a1, r1, a, r)
            theta = log_se3(a, r)
            h0 = pose_matrix(a0, r0)
            do j = 1, 5
                call random_number(xi)
                dh = matmul(h0, exp_matrix((xi + fd_step) * theta)) &
                    - matmul(h0, exp_matrix((xi - fd_step) * theta))
                dh = matmul(inverse_matrix(matmul(h0, exp_matrix(xi * theta))), dh)
                dh = dh / (2.0_rk * fd_step)
                CHECK_CLOSE(vee_se3(dh), theta, fd_atol, fd_rtol, 'strain = theta')
            end do
            dh = matmul(h0, exp_matrix(theta))
            CHECK_CLOSE(dh, pose_matrix(a1, r1), 1.0e-13_rk, 0.0_rk, 'H(1) = H_1')
        end do
    end subroutine test_constant_strain

end module rs_test_math_se3

program test_se3
    use rs_test_math_se3, only: run_all_tests
    use rs_test_assert, only: finish_tests
    implicit none
    call run_all_tests()
    call finish_tests()
end program test_se3
