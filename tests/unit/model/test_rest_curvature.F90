#include "rs_assert.h"
!> Unit tests of rs_model_rest_curvature and the 'curvature' centreline of rs_model_rod_geometry:
!> a constant Darboux vector gives the helix of the closed form written here from rotations
!> about the fixed spatial axis a = R0 kappa / |kappa| (not from Exp_SE3): d_i(s) = Rot(a,
!> |kappa| s) d_i(0), phi(s) = phi0 + (a . d3) a s + sin(|kappa| s) / |kappa| d3_perp +
!> (1 - cos(|kappa| s)) / |kappa| a x d3_perp, with radius kb / |kappa|^2 and pitch
!> 2 pi kappa3 / |kappa|^2; a table with a jump is the product of the two constant pieces'
!> exponentials; any table gives an orthonormal frame with R^T R' = hat(kappa(s)) and
!> phi' = d3 (central differences); a varying table agrees with 2048 Magnus steps per interval
!> to 1e-13 of its length; the Magnus step's local error falls as h^7.
!>
!> Central differences with step hs = 1e-5 have truncation error O(hs^2 |kappa|^3) and
!> round-off O(eps / hs): below fd_tol for |kappa| <= 4.
module rs_test_model_rest_curvature
    use rs_core_kinds, only: rk, pi
    use rs_test_assert, only: run_test, assert_true, assert_close
    use rs_test_random, only: set_random_seed, random_unit_vector, uniform
    use rs_math_so3, only: hat
    use rs_math_se3, only: exp_se3, pose_compose
    use rs_model_rest_curvature, only: rest_curvature_t, rest_curvature_table, &
        place_rest_curvature, rest_curvature_pose, rest_curvature_at, magnus_twist, advance_pose
    use rs_model_rod_geometry, only: rod_geometry_t, curvature_geometry, set_start_director, &
        centreline_point, centreline_tangent, centreline_frame, default_normal
    implicit none
    private

    public :: run_all_tests

    real(rk), parameter :: tight = 1.0e-13_rk
    real(rk), parameter :: hs = 1.0e-5_rk
    real(rk), parameter :: fd_tol = 1.0e-8_rk

contains

    !> Run every test of this file through rs_test_assert.
    subroutine run_all_tests()
        call set_random_seed(20261127, 4099)
        call run_test('constant_is_helix', test_constant_is_helix)
        call run_test('geometry_start_and_frame', test_geometry_start_and_frame)
        call run_test('jump_is_product', test_jump_is_product)
        call run_test('table_frame_derivative', test_table_frame_derivative)
        call run_test('table_accuracy', test_table_accuracy)
        call run_test('magnus_local_order', test_magnus_local_order)
    end subroutine run_all_tests

    pure function crossed(a, b) result(c)
        real(rk), intent(in) :: a(3), b(3)
        real(rk) :: c(3)
        c = matmul(hat(a), b)
    end function crossed

    ! x turned by the angle t about the unit axis a (Rodrigues).
    pure function turned(a, t, x) result(y)
        real(rk), intent(in) :: a(3), t, x(3)
        real(rk) :: y(3)
        y = cos(t) * x + sin(t) * crossed(a, x) + (1.0_rk - cos(t)) * dot_product(a, x) * a
    end function turned

    ! A random start frame (d1, d2, d3) with d3 = direction.
    function random_frame(direction) result(frame)
        real(rk), intent(in) :: direction(3)
        real(rk) :: frame(3, 3), n(3), angle
        n = default_normal(direction)
        angle = uniform(0.0_rk, 2.0_rk * pi)
        frame(:, 1) = cos(angle) * n + sin(angle) * crossed(direction, n)
        frame(:, 3) = direction
        frame(:, 2) = crossed(frame(:, 3), frame(:, 1))
    end function random_frame

    ! A random curvature table of 5 rows on [0, 2] with a jump at s = 1.
    function random_table() result(c)
        type(rest_curvature_t) :: c
        real(rk) :: kappa(3, 5)
        integer :: j
        do j = 1, 5
            kappa(:, j) = uniform(0.5_rk, 3.0_rk) * random_unit_vector()
        end do
        c = rest_curvature_table([0.0_rk, 0.6_rk, 1.0_rk, 1.0_rk, 2.0_rk], kappa)
    end function random_table

    ! Constant kappa: the closed-form helix (module header), its radius and pitch; one piece.
    subroutine test_constant_is_helix()
        type(rest_curvature_t) :: c
        real(rk) :: kappa(3), frame0(3, 3), start(3), frame(3, 3), point(3), a(3), d3_perp(3)
        real(rk) :: k, s, x(3), radius, pitch, kb
        integer :: sample, j, i
        do sample = 1, 20
            kappa = [uniform(-3.0_rk, 3.0_rk), uniform(-3.0_rk, 3.0_rk), uniform(-3.0_rk, 3.0_rk)]
            start = random_unit_vector()
            frame0 = random_frame(random_unit_vector())
            c = rest_curvature_table([0.0_rk, 4.0_rk], reshape([kappa, kappa], [3, 2]))
            call place_rest_curvature(c, frame0, start)
            CHECK_TRUE(size(c%piece_s, 2) == 1, 'a constant kappa is one piece')
            k = norm2(kappa)
            kb = norm2(kappa(1:2))
            a = matmul(frame0, kappa) / k
            d3_perp = frame0(:, 3) - dot_product(a, frame0(:, 3)) * a
            radius = norm2(d3_perp) / k
            pitch = 2.0_rk * pi * dot_product(a, frame0(:, 3)) / k
            CHECK_CLOSE(radius, kb / k**2, tight, 0.0_rk, 'radius kb / |kappa|^2')
            x(1) = 2.0_rk * pi * kappa(3) / k**2
            CHECK_CLOSE(pitch, x(1), tight, 0.0_rk, 'pitch 2 pi tau / |kappa|^2')
            do j = 0, 16
                s = 0.25_rk * real(j, rk)
                call rest_curvature_pose(c, s, frame, point)
                x = start + dot_product(a, frame0(:, 3)) * a * s + sin(k * s) / k * d3_perp + &
                    (1.0_rk - cos(k * s)) / k * crossed(a, d3_perp)
                CHECK_CLOSE(point, x, tight, 0.0_rk, 'point on the closed-form helix')
                do i = 1, 3
                    x = turned(a, k * s, frame0(:, i))
                    CHECK_CLOSE(frame(:, i), x, tight, 0.0_rk, 'frame turned about R0 kappa')
                end do
            end do
        end do
    end subroutine test_constant_is_helix

    ! curvature_geometry: phi(0) = start, d3(0) = direction, d1(0) the given d1, length the
    ! last s; set_start_director again re-places the frame (d1 turned about d3 turns the rod).
    subroutine test_geometry_start_and_frame()
        type(rod_geometry_t) :: g, turned_g
        real(rk) :: direction(3), start(3), d(3, 3), d1(3), kappa(3, 2), a, expected(3)
        direction = random_unit_vector()
        start = [0.5_rk, -1.0_rk, 2.0_rk]
        kappa = reshape([1.0_rk, -0.5_rk, 2.0_rk, 0.0_rk, 1.5_rk, -1.0_rk], [3, 2])
        g = curvature_geometry(start, direction, [0.0_rk, 3.0_rk], kappa)
        CHECK_CLOSE(g%length, 3.0_rk, 0.0_rk, 0.0_rk, 'length = the last s')
        d1 = default_normal(direction)
        d = centreline_frame(g, 0.0_rk)
        CHECK_CLOSE(d(:, 1), d1, tight, 0.0_rk, 'placed with the default d1 first')
        a = 0.7_rk
        d1 = turned(direction, a, d1)
        turned_g = g
        call set_start_director(turned_g, d1)
        d = centreline_frame(turned_g, 0.0_rk)
        CHECK_CLOSE(d(:, 1), d1, tight, 0.0_rk, 'd1(0) as given')
        CHECK_CLOSE(d(:, 3), direction, tight, 0.0_rk, 'd3(0) = direction')
        CHECK_CLOSE(centreline_point(turned_g, 0.0_rk), start, 0.0_rk, 0.0_rk, 'phi(0) = start')
        d = centreline_frame(turned_g, 2.0_rk)
        CHECK_CLOSE(centreline_tangent(turned_g, 2.0_rk), d(:, 3), 0.0_rk, 0.0_rk, 'tangent = d3')
        ! Turning d1(0) by a about d3(0) turns the whole rod by a about that line.
        expected = turned(direction, a, centreline_point(g, 3.0_rk) - start)
        d1 = centreline_point(turned_g, 3.0_rk) - start
        CHECK_CLOSE(d1, expected, tight, 0.0_rk, 'turns with d1(0)')
    end subroutine test_geometry_start_and_frame

    ! Two rows at s = 1: the pose at 2 is H0 Exp(xi_a) Exp(xi_b), each piece constant.
    subroutine test_jump_is_product()
        type(rest_curvature_t) :: c
        real(rk) :: ka(3), kb(3), frame0(3, 3), a1(3, 3), r1(3), a2(3, 3), r2(3), a(3, 3), r(3)
        real(rk) :: frame(3, 3), point(3), e(3, 3), p(3)
        ka = [0.3_rk, 1.2_rk, -0.8_rk]
        kb = [-2.0_rk, 0.1_rk, 0.6_rk]
        frame0 = random_frame(random_unit_vector())
        c = rest_curvature_table([0.0_rk, 1.0_rk, 1.0_rk, 2.0_rk], &
            reshape([ka, ka, kb, kb], [3, 4]))
        call place_rest_curvature(c, frame0, [0.0_rk, 0.0_rk, 0.0_rk])
        CHECK_TRUE(size(c%piece_s, 2) == 2, 'two constant pieces, the jump has none')
        call exp_se3([0.0_rk, 0.0_rk, 1.0_rk, ka], a1, r1)
        call exp_se3([0.0_rk, 0.0_rk, 1.0_rk, kb], a2, r2)
        call pose_compose(frame0, [0.0_rk, 0.0_rk, 0.0_rk], a1, r1, a, r)
        call pose_compose(a, r, a2, r2, e, p)
        call rest_curvature_pose(c, 2.0_rk, frame, point)
        CHECK_CLOSE(point, p, tight, 0.0_rk, 'point = product of the pieces')
        CHECK_CLOSE(frame, e, tight, 0.0_rk, 'frame = product of the pieces')
        CHECK_CLOSE(rest_curvature_at(c, 0.999_rk), ka, 0.0_rk, 0.0_rk, 'kappa before the jump')
        CHECK_CLOSE(rest_curvature_at(c, 1.0_rk), kb, 0.0_rk, 0.0_rk, 'kappa from the jump on')
    end subroutine test_jump_is_product

    ! Orthonormal right-handed frame, R^T R' = hat(kappa(s)) and phi' = d3 along random tables.
    subroutine test_table_frame_derivative()
        type(rest_curvature_t) :: c
        real(rk) :: frame(3, 3), plus(3, 3), minus(3, 3), point(3), p_plus(3), p_minus(3)
        real(rk) :: eye(3, 3), rate(3, 3), third(3), s
        integer :: sample, j, i
        eye = 0.0_rk
        do i = 1, 3
            eye(i, i) = 1.0_rk
        end do
        do sample = 1, 10
            c = random_table()
            call place_rest_curvature(c, random_frame(random_unit_vector()), random_unit_vector())
            do j = 1, 19
                s = 0.1_rk * real(j, rk) + 0.013_rk
                call rest_curvature_pose(c, s, frame, point)
                CHECK_CLOSE(matmul(transpose(frame), frame), eye, tight, 0.0_rk, 'orthonormal')
                third = crossed(frame(:, 1), frame(:, 2))
                CHECK_CLOSE(third, frame(:, 3), tight, 0.0_rk, 'right-handed')
                call rest_curvature_pose(c, s + hs, plus, p_plus)
                call rest_curvature_pose(c, s - hs, minus, p_minus)
                rate = matmul(transpose(frame), plus - minus) / (2.0_rk * hs)
                CHECK_CLOSE(rate, hat(rest_curvature_at(c, s)), fd_tol, 0.0_rk, 'R^T R'' = hat k')
                p_plus = (p_plus - p_minus) / (2.0_rk * hs)
                CHECK_CLOSE(p_plus, frame(:, 3), fd_tol, 0.0_rk, 'phi'' = d3')
            end do
        end do
    end subroutine test_table_frame_derivative

    ! A strongly varying table against 256 Magnus steps per interval.
    subroutine test_table_accuracy()
        type(rest_curvature_t) :: c
        real(rk) :: frame0(3, 3), frame(3, 3), point(3), a(3, 3), r(3), h, ka(3), kb(3)
        integer :: sample, j, k
        integer, parameter :: steps = 256
        do sample = 1, 5
            c = random_table()
            frame0 = random_frame(random_unit_vector())
            call place_rest_curvature(c, frame0, [0.0_rk, 0.0_rk, 0.0_rk])
            a = frame0
            r = 0.0_rk
            do j = 1, size(c%s) - 1
                if (c%s(j + 1) == c%s(j)) cycle
                h = (c%s(j + 1) - c%s(j)) / real(steps, rk)
                do k = 1, steps
                    kb = (c%kappa(:, j + 1) - c%kappa(:, j)) / real(steps, rk)
                    ka = c%kappa(:, j) + kb * real(k - 1, rk)
                    kb = ka + kb
                    call advance_pose(a, r, magnus_twist(ka, kb, h))
                end do
            end do
            call rest_curvature_pose(c, 2.0_rk, frame, point)
            CHECK_CLOSE(point, r, 1.0e-13_rk * 2.0_rk, 0.0_rk, 'end point to 1e-13 of the length')
            CHECK_CLOSE(frame, a, 1.0e-13_rk, 0.0_rk, 'end frame to 1e-13')
        end do
    end subroutine test_table_accuracy

    ! One Magnus step of h and of h / 2 against 256 substeps: local errors in the ratio 2^7.
    subroutine test_magnus_local_order()
        real(rk) :: ka(3), kb(3), a(3, 3), r(3), a_ref(3, 3), r_ref(3), e(2), h, ks(3), ke(3)
        integer :: level, k
        integer, parameter :: sub = 256
        ka = [1.0_rk, -2.0_rk, 0.5_rk]
        kb = [-1.5_rk, 0.5_rk, 2.0_rk]
        do level = 1, 2
            h = 0.4_rk / real(level, rk)
            ! kappa linear over [0, 0.4]; this step covers [0, h].
            ke = ka + (kb - ka) * h / 0.4_rk
            call exp_se3(magnus_twist(ka, ke, h), a, r)
            a_ref = reshape([1.0_rk, 0.0_rk, 0.0_rk, 0.0_rk, 1.0_rk, 0.0_rk, 0.0_rk, 0.0_rk, &
                1.0_rk], [3, 3])
            r_ref = 0.0_rk
            do k = 1, sub
                ks = ka + (ke - ka) * real(k - 1, rk) / real(sub, rk)
                call advance_pose(a_ref, r_ref, magnus_twist(ks, ka + (ke - ka) * real(k, rk) / &
                    real(sub, rk), h / real(sub, rk)))
            end do
            e(level) = max(maxval(abs(a - a_ref)), maxval(abs(r - r_ref)))
        end do
        CHECK_TRUE(abs(log(e(1) / e(2)) / log(2.0_rk) - 7.0_rk) < 0.3_rk, 'local error O(h^7)')
    end subroutine test_magnus_local_order

end module rs_test_model_rest_curvature

program test_model_rest_curvature
    use rs_test_model_rest_curvature, only: run_all_tests
    use rs_test_assert, only: finish_tests
    implicit none
    call run_all_tests()
    call finish_tests()
end program test_model_rest_curvature
