#include "rs_assert.h"
!> Unit tests of rs_model_rod_geometry: straight lines, helices and polylines as functions of
!> the arc length. Helices with random axes, radii, pitches of both signs and starts: points on
!> the cylinder about the documented axis, the closed-form rise and angle, the length formula,
!> unit speed and tangent = phi' (central differences), an orthonormal right-handed frame with
!> d3 the tangent and d1(0) the given d1, and parallel transport: d1' . d2 = 0 (no twist about
!> d3) and d1' along the tangent. Polylines: vertices at their arc lengths, the minimal
!> rotation at each vertex (no twist; a plane polyline keeps the normal to its plane), the
!> bisecting frame at a vertex, and a finely sampled helix whose discrete transport approaches
!> the helix's at second order.
!>
!> Central differences with step hs have truncation error O(hs^2 |phi'''|) and round-off
!> O(eps / hs); with hs = 1e-5 and curvatures below 10 both are below the tolerances used.
module rs_test_model_rod_geometry
    use rs_core_kinds, only: rk, pi
    use rs_test_assert, only: run_test, assert_true, assert_close
    use rs_test_random, only: set_random_seed, random_unit_vector, uniform
    use rs_model_rod_geometry, only: rod_geometry_t, straight_geometry, helix_geometry, &
        polyline_geometry, set_start_director, centreline_point, centreline_tangent, &
        centreline_frame, default_normal, helix_axis_point
    implicit none
    private

    public :: run_all_tests

    real(rk), parameter :: tight = 1.0e-13_rk
    !> Step of the central differences (absolute, in the arc length).
    real(rk), parameter :: hs = 1.0e-5_rk
    !> Tolerance of quantities formed by central differences.
    real(rk), parameter :: fd_tol = 1.0e-8_rk

contains

    !> Run every test of this file through rs_test_assert.
    subroutine run_all_tests()
        call set_random_seed(20250611, 7919)
        call run_test('straight', test_straight)
        call run_test('default_normal', test_default_normal)
        call run_test('helix_on_cylinder', test_helix_on_cylinder)
        call run_test('helix_arc_length', test_helix_arc_length)
        call run_test('helix_frame_orthonormal', test_helix_frame_orthonormal)
        call run_test('helix_parallel_transport', test_helix_parallel_transport)
        call run_test('helix_pitch_zero_is_circle', test_helix_pitch_zero_is_circle)
        call run_test('helix_phases_share_axis', test_helix_phases_share_axis)
        call run_test('polyline_points_and_length', test_polyline_points_and_length)
        call run_test('polyline_transport', test_polyline_transport)
        call run_test('polyline_vertex_bisects', test_polyline_vertex_bisects)
        call run_test('polyline_converges_to_helix', test_polyline_converges_to_helix)
    end subroutine run_all_tests

    function cross(a, b) result(c)
        real(rk), intent(in) :: a(3), b(3)
        real(rk) :: c(3)
        c = [a(2) * b(3) - a(3) * b(2), a(3) * b(1) - a(1) * b(3), a(1) * b(2) - a(2) * b(1)]
    end function cross

    ! (x, y, z) (the assertion macros cannot take an array constructor).
    function vec(x, y, z) result(v)
        real(rk), intent(in) :: x, y, z
        real(rk) :: v(3)
        v = [x, y, z]
    end function vec

    !> A random helix with its frame started at d1 = default normal of the tangent at 0 turned
    !> by a random angle about it.
    function random_helix() result(g)
        type(rod_geometry_t) :: g
        real(rk) :: start(3), t(3), n(3), angle
        start = [uniform(-1.0_rk, 1.0_rk), uniform(-1.0_rk, 1.0_rk), uniform(-1.0_rk, 1.0_rk)]
        g = helix_geometry(start, random_unit_vector(), uniform(0.1_rk, 1.0_rk), &
            uniform(-1.0_rk, 1.0_rk), uniform(0.5_rk, 3.0_rk))
        t = centreline_tangent(g, 0.0_rk)
        n = default_normal(t)
        angle = uniform(0.0_rk, 2.0_rk * pi)
        call set_start_director(g, cos(angle) * n + sin(angle) * cross(t, n))
    end function random_helix

    ! d1' by central differences.
    function d1_rate(g, s) result(rate)
        type(rod_geometry_t), intent(in) :: g
        real(rk), intent(in) :: s
        real(rk) :: rate(3), plus(3, 3), minus(3, 3)
        plus = centreline_frame(g, s + hs)
        minus = centreline_frame(g, s - hs)
        rate = (plus(:, 1) - minus(:, 1)) / (2.0_rk * hs)
    end function d1_rate

    ! phi = start + s t, a constant frame (d1 given, d2 = t x d1).
    subroutine test_straight()
        type(rod_geometry_t) :: g
        real(rk) :: start(3), t(3), d1(3), d(3, 3), s
        integer :: k
        start = [1.0_rk, -2.0_rk, 0.5_rk]
        t = [2.0_rk, 1.0_rk, 2.0_rk] / 3.0_rk
        d1 = default_normal(t)
        g = straight_geometry(start, t, 4.0_rk)
        call set_start_director(g, d1)
        CHECK_CLOSE(g%length, 4.0_rk, 0.0_rk, 0.0_rk, 'length as given')
        do k = 0, 8
            s = 0.5_rk * real(k, rk)
            CHECK_CLOSE(centreline_point(g, s), start + s * t, tight, 0.0_rk, 'point')
            CHECK_CLOSE(centreline_tangent(g, s), t, 0.0_rk, 0.0_rk, 'tangent')
            d = centreline_frame(g, s)
            CHECK_CLOSE(d(:, 1), d1, 0.0_rk, 0.0_rk, 'd1 constant')
            CHECK_CLOSE(d(:, 2), cross(t, d1), 0.0_rk, 0.0_rk, 'd2 = d3 x d1')
            CHECK_CLOSE(d(:, 3), t, 0.0_rk, 0.0_rk, 'd3 = t')
        end do
    end subroutine test_straight

    ! e_z x t normalized; e_x for t along e_z; e_y for t = e_x (the rule of docs/user/input.md).
    subroutine test_default_normal()
        real(rk) :: t(3)
        integer :: sample
        CHECK_CLOSE(default_normal(vec(1.0_rk, 0.0_rk, 0.0_rk)), vec(0.0_rk, 1.0_rk, 0.0_rk), 0.0_rk, 0.0_rk, 'e_x')
        CHECK_CLOSE(default_normal(vec(0.0_rk, 0.0_rk, -1.0_rk)), vec(1.0_rk, 0.0_rk, 0.0_rk), 0.0_rk, 0.0_rk, '-e_z')
        do sample = 1, 20
            t = random_unit_vector()
            CHECK_CLOSE(dot_product(default_normal(t), t), 0.0_rk, tight, 0.0_rk, 'normal to t')
            CHECK_CLOSE(norm2(default_normal(t)), 1.0_rk, tight, 0.0_rk, 'unit')
        end do
    end subroutine test_default_normal

    ! Every point lies on the cylinder of radius R about the line through start - R u along a;
    ! its axial coordinate rises by pitch per turn and its angle is theta = s / c.
    subroutine test_helix_on_cylinder()
        type(rod_geometry_t) :: g
        real(rk) :: x(3), axis_point(3), r(3), s, axial, expected_axial, angle, expected_angle
        integer :: sample, k
        logical :: ok
        do sample = 1, 20
            g = random_helix()
            axis_point = helix_axis_point(g)
            CHECK_CLOSE(centreline_point(g, 0.0_rk), g%start, tight, 0.0_rk, 'starts at start')
            CHECK_CLOSE(norm2(g%start - axis_point), g%radius, tight, 0.0_rk, 'start on the cylinder')
            do k = 0, 16
                s = g%length * real(k, rk) / 16.0_rk
                x = centreline_point(g, s)
                axial = dot_product(x - axis_point, g%axis)
                r = x - axis_point - axial * g%axis
                CHECK_CLOSE(norm2(r), g%radius, tight, 0.0_rk, 'distance from the axis = radius')
                expected_axial = g%rise * s / g%speed
                CHECK_CLOSE(axial, expected_axial, tight, 0.0_rk, 'rise = pitch per turn')
                angle = atan2(dot_product(r, g%lateral), dot_product(r, g%radial))
                expected_angle = modulo(s / g%speed + pi, 2.0_rk * pi) - pi
                ok = abs(modulo(angle - expected_angle + pi, 2.0_rk * pi) - pi) < 1.0e-12_rk
                CHECK_TRUE(ok, 'angle about the axis = s / c, right-handed about the axis')
            end do
        end do
    end subroutine test_helix_on_cylinder

    ! helix_phase: six helices with phases k pi/3 (k = 0..5) about one oblique axis, each
    ! started at axis_point + R u_k with u_k = cos(k pi/3) n + sin(k pi/3) (a x n), n the
    ! default normal of the axis: every one has that axis (helix_axis_point is axis_point, every
    ! point lies at distance R from the line), all have the same length, wire k is wire 0
    ! turned by k pi/3 about the axis at every s, and phase 0 is the helix without a phase.
    subroutine test_helix_phases_share_axis()
        type(rod_geometry_t) :: g(0:5), plain
        real(rk) :: a(3), n(3), u(3), p(3), x(3), x0(3), r(3), phase, s, axial, c, sn
        real(rk), parameter :: radius = 0.3_rk, pitch = 0.7_rk, turns = 1.75_rk
        integer :: k, j
        a = [1.0_rk, -2.0_rk, 0.5_rk]
        a = a / norm2(a)
        n = default_normal(a)
        p = [0.25_rk, -1.0_rk, 2.0_rk]
        do k = 0, 5
            phase = real(k, rk) * pi / 3.0_rk
            u = cos(phase) * n + sin(phase) * cross(a, n)
            g(k) = helix_geometry(p + radius * u, a, radius, pitch, turns, phase)
            CHECK_CLOSE(helix_axis_point(g(k)), p, tight, 0.0_rk, 'axis through the common point')
            CHECK_CLOSE(g(k)%length, g(0)%length, tight, 0.0_rk, 'same length')
            CHECK_CLOSE(dot_product(g(k)%radial, a), 0.0_rk, tight, 0.0_rk, 'u normal to the axis')
            CHECK_CLOSE(norm2(g(k)%radial), 1.0_rk, tight, 0.0_rk, 'u unit')
            do j = 0, 8
                s = g(k)%length * real(j, rk) / 8.0_rk
                x = centreline_point(g(k), s)
                axial = dot_product(x - p, a)
                r = x - p - axial * a
                CHECK_CLOSE(norm2(r), radius, tight, 0.0_rk, 'on the cylinder about the common axis')
                ! Wire 0 turned by the phase about the axis (Rodrigues' formula) is wire k.
                x0 = centreline_point(g(0), s) - p
                c = cos(phase)
                sn = sin(phase)
                x0 = c * x0 + sn * cross(a, x0) + (1.0_rk - c) * dot_product(a, x0) * a
                CHECK_CLOSE(x - p, x0, tight, 0.0_rk, 'wire k = wire 0 turned by k pi / 3')
            end do
        end do
        plain = helix_geometry(p + radius * n, a, radius, pitch, turns)
        CHECK_CLOSE(g(0)%radial, plain%radial, 0.0_rk, 0.0_rk, 'phase 0 is no phase, bit for bit')
        x = centreline_point(g(0), 0.3_rk)
        CHECK_CLOSE(x, centreline_point(plain, 0.3_rk), 0.0_rk, 0.0_rk, 'phase 0: same points')
    end subroutine test_helix_phases_share_axis

    ! L = turns sqrt((2 pi R)^2 + P^2); phi' has unit length and equals the tangent (central
    ! differences); the chord sum of a fine subdivision approaches L from below.
    subroutine test_helix_arc_length()
        type(rod_geometry_t) :: g
        real(rk) :: derivative(3), s, pitch, turns, radius, chords
        integer :: sample, k, n
        logical :: ok
        do sample = 1, 20
            radius = uniform(0.1_rk, 1.0_rk)
            pitch = uniform(-1.0_rk, 1.0_rk)
            turns = uniform(0.5_rk, 3.0_rk)
            g = helix_geometry([0.0_rk, 0.0_rk, 0.0_rk], random_unit_vector(), radius, pitch, turns)
            CHECK_CLOSE(g%length, turns * sqrt((2.0_rk * pi * radius)**2 + pitch**2), tight, tight, 'length formula')
            do k = 1, 15
                s = g%length * real(k, rk) / 16.0_rk
                derivative = (centreline_point(g, s + hs) - centreline_point(g, s - hs)) / (2.0_rk * hs)
                CHECK_CLOSE(norm2(derivative), 1.0_rk, fd_tol, 0.0_rk, 'unit speed: s is arc length')
                CHECK_CLOSE(derivative, centreline_tangent(g, s), fd_tol, 0.0_rk, 'tangent = phi''')
            end do
            n = 20000
            chords = 0.0_rk
            do k = 1, n
                chords = chords + norm2(centreline_point(g, g%length * real(k, rk) / real(n, rk)) &
                    - centreline_point(g, g%length * real(k - 1, rk) / real(n, rk)))
            end do
            ok = chords <= g%length .and. g%length - chords < 1.0e-7_rk * g%length
            CHECK_TRUE(ok, 'chord sum approaches the length from below')
        end do
    end subroutine test_helix_arc_length

    ! (d1, d2, d3) orthonormal and right-handed, d3 the tangent, d1(0) the given d1.
    subroutine test_helix_frame_orthonormal()
        type(rod_geometry_t) :: g
        real(rk) :: d(3, 3), eye(3, 3), s
        integer :: sample, k, i
        eye = 0.0_rk
        do i = 1, 3
            eye(i, i) = 1.0_rk
        end do
        do sample = 1, 20
            g = random_helix()
            d = centreline_frame(g, 0.0_rk)
            CHECK_CLOSE(d(:, 1), g%d1_start, tight, 0.0_rk, 'd1(0) is the given d1')
            do k = 0, 16
                s = g%length * real(k, rk) / 16.0_rk
                d = centreline_frame(g, s)
                CHECK_CLOSE(matmul(transpose(d), d), eye, tight, 0.0_rk, 'orthonormal')
                CHECK_CLOSE(cross(d(:, 1), d(:, 2)), d(:, 3), tight, 0.0_rk, 'right-handed')
                CHECK_CLOSE(d(:, 3), centreline_tangent(g, s), tight, 0.0_rk, 'd3 = tangent')
            end do
        end do
    end subroutine test_helix_frame_orthonormal

    ! Bishop frame: d1' . d2 = 0 (no twist about d3) and d1' = -(kappa . d1) t, i.e. d1' has no
    ! component normal to the tangent. The Frenet frame, which twists at the torsion rate, would
    ! give |d1' . d2| = |tau| > 0: the test can fail.
    subroutine test_helix_parallel_transport()
        type(rod_geometry_t) :: g
        real(rk) :: d(3, 3), rate(3), s, tau, normal_part(3), zero(3)
        integer :: sample, k
        logical :: ok
        zero = 0.0_rk
        do sample = 1, 20
            g = random_helix()
            tau = g%rise / g%speed**2
            do k = 1, 15
                s = g%length * real(k, rk) / 16.0_rk
                d = centreline_frame(g, s)
                rate = d1_rate(g, s)
                CHECK_CLOSE(dot_product(rate, d(:, 2)), 0.0_rk, fd_tol, 0.0_rk, 'd1'' . d2 = 0')
                normal_part = rate - dot_product(rate, d(:, 3)) * d(:, 3)
                CHECK_CLOSE(normal_part, zero, fd_tol, 0.0_rk, 'd1'' along the tangent')
            end do
            ok = norm2(d1_rate(g, 0.5_rk * g%length)) > 1.0e-3_rk
            if (abs(tau) > 0.1_rk) CHECK_TRUE(ok, 'd1 does turn along a curved centreline')
        end do
    end subroutine test_helix_parallel_transport

    ! Pitch 0: a plane circle of radius R about start - R u in the plane normal to the axis; the
    ! transported d1 keeps a constant angle with the axis (no torsion).
    subroutine test_helix_pitch_zero_is_circle()
        type(rod_geometry_t) :: g
        real(rk) :: axis(3), d(3, 3), d0(3, 3), s
        integer :: k
        axis = [0.0_rk, 0.0_rk, 1.0_rk]
        g = helix_geometry([1.0_rk, 0.0_rk, 0.0_rk], axis, 1.0_rk, 0.0_rk, 1.0_rk)
        call set_start_director(g, [0.0_rk, 0.6_rk, 0.8_rk] - 0.6_rk * centreline_tangent(g, 0.0_rk))
        CHECK_CLOSE(helix_axis_point(g), vec(0.0_rk, 0.0_rk, 0.0_rk), tight, 0.0_rk, 'axis through origin')
        CHECK_CLOSE(g%length, 2.0_rk * pi, tight, 0.0_rk, 'circumference')
        d0 = centreline_frame(g, 0.0_rk)
        do k = 0, 12
            s = g%length * real(k, rk) / 12.0_rk
            CHECK_CLOSE(norm2(centreline_point(g, s)), 1.0_rk, tight, 0.0_rk, 'on the unit circle')
            CHECK_CLOSE(centreline_point(g, s), vec(cos(s), sin(s), 0.0_rk), tight, 0.0_rk, 'anticlockwise')
            d = centreline_frame(g, s)
            CHECK_CLOSE(dot_product(d(:, 1), axis), dot_product(d0(:, 1), axis), tight, 0.0_rk, 'd1 . axis')
        end do
    end subroutine test_helix_pitch_zero_is_circle

    ! Vertices at their cumulative arc lengths, straight segments between them.
    subroutine test_polyline_points_and_length()
        type(rod_geometry_t) :: g
        real(rk) :: p(3, 4), s
        p = reshape([0.0_rk, 0.0_rk, 0.0_rk, 3.0_rk, 0.0_rk, 0.0_rk, 3.0_rk, 4.0_rk, 0.0_rk, &
            3.0_rk, 4.0_rk, 12.0_rk], [3, 4])
        g = polyline_geometry(p)
        call set_start_director(g, [0.0_rk, 1.0_rk, 0.0_rk])
        CHECK_CLOSE(g%length, 19.0_rk, 0.0_rk, 0.0_rk, 'length = 3 + 4 + 12')
        CHECK_CLOSE(centreline_point(g, 0.0_rk), p(:, 1), 0.0_rk, 0.0_rk, 'first point')
        CHECK_CLOSE(centreline_point(g, 3.0_rk), p(:, 2), tight, 0.0_rk, 'second vertex')
        CHECK_CLOSE(centreline_point(g, 7.0_rk), p(:, 3), tight, 0.0_rk, 'third vertex')
        CHECK_CLOSE(centreline_point(g, 19.0_rk), p(:, 4), tight, 0.0_rk, 'last point')
        s = 5.0_rk
        CHECK_CLOSE(centreline_point(g, s), vec(3.0_rk, 2.0_rk, 0.0_rk), tight, 0.0_rk, 'inside a segment')
        CHECK_CLOSE(centreline_tangent(g, 1.0_rk), vec(1.0_rk, 0.0_rk, 0.0_rk), 0.0_rk, 0.0_rk, 'tangent 1')
        CHECK_CLOSE(centreline_tangent(g, 10.0_rk), vec(0.0_rk, 0.0_rk, 1.0_rk), 0.0_rk, 0.0_rk, 'tangent 3')
    end subroutine test_polyline_points_and_length

    ! The frame is constant on a segment and turned at a vertex by the smallest rotation taking
    ! t_j to t_{j+1}: the component of d1 along t_j x t_{j+1} is kept, and a plane polyline with
    ! d1 normal to its plane keeps d1 (a plane curve has no torsion). Random 3D polylines keep
    ! the frame orthonormal with d3 the segment tangent.
    subroutine test_polyline_transport()
        type(rod_geometry_t) :: g
        real(rk) :: p(3, 6), d(3, 3), before(3, 3), after(3, 3), eye(3, 3), binormal(3), s, kept(2)
        integer :: j, i, sample
        eye = 0.0_rk
        do i = 1, 3
            eye(i, i) = 1.0_rk
        end do
        p = reshape([0.0_rk, 0.0_rk, 0.0_rk, 1.0_rk, 0.0_rk, 0.0_rk, 1.5_rk, 1.0_rk, 0.0_rk, &
            0.5_rk, 2.0_rk, 0.0_rk, -1.0_rk, 1.5_rk, 0.0_rk, -1.0_rk, 0.0_rk, 0.0_rk], [3, 6])
        g = polyline_geometry(p)
        call set_start_director(g, [0.0_rk, 0.0_rk, 1.0_rk])
        do j = 1, 5
            s = 0.5_rk * (g%vertex_s(j) + g%vertex_s(j + 1))
            d = centreline_frame(g, s)
            CHECK_CLOSE(d(:, 1), vec(0.0_rk, 0.0_rk, 1.0_rk), tight, 0.0_rk, 'plane polyline keeps d1')
        end do
        do sample = 1, 10
            do j = 1, 6
                p(:, j) = real(j, rk) * [1.0_rk, 0.0_rk, 0.0_rk] + 0.7_rk * random_unit_vector()
            end do
            g = polyline_geometry(p)
            call set_start_director(g, default_normal(g%tangents(:, 1)))
            do j = 1, 4
                before = centreline_frame(g, g%vertex_s(j + 1) - 1.0e-3_rk)
                after = centreline_frame(g, g%vertex_s(j + 1) + 1.0e-3_rk)
                CHECK_CLOSE(matmul(transpose(after), after), eye, tight, 0.0_rk, 'orthonormal')
                CHECK_CLOSE(after(:, 3), g%tangents(:, j + 1), tight, 0.0_rk, 'd3 = segment tangent')
                binormal = cross(g%tangents(:, j), g%tangents(:, j + 1))
                binormal = binormal / norm2(binormal)
                kept = matmul(binormal, after(:, 1:2))
                CHECK_CLOSE(kept, matmul(binormal, before(:, 1:2)), tight, 0.0_rk, 'd . binormal kept')
            end do
        end do
    end subroutine test_polyline_transport

    ! At a vertex the tangent is the bisector and the frame is turned half way.
    subroutine test_polyline_vertex_bisects()
        type(rod_geometry_t) :: g
        real(rk) :: p(3, 3), d(3, 3), half
        p = reshape([0.0_rk, 0.0_rk, 0.0_rk, 1.0_rk, 0.0_rk, 0.0_rk, 1.0_rk, 1.0_rk, 0.0_rk], [3, 3])
        g = polyline_geometry(p)
        call set_start_director(g, [0.0_rk, 1.0_rk, 0.0_rk])
        half = sqrt(0.5_rk)
        CHECK_CLOSE(centreline_tangent(g, 1.0_rk), vec(half, half, 0.0_rk), tight, 0.0_rk, 'bisector')
        d = centreline_frame(g, 1.0_rk)
        CHECK_CLOSE(d(:, 1), vec(-half, half, 0.0_rk), tight, 0.0_rk, 'd1 turned 45 degrees')
        CHECK_CLOSE(d(:, 2), vec(0.0_rk, 0.0_rk, 1.0_rk), tight, 0.0_rk, 'd2 normal to the plane')
        d = centreline_frame(g, 1.5_rk)
        CHECK_CLOSE(d(:, 1), vec(-1.0_rk, 0.0_rk, 0.0_rk), tight, 0.0_rk, 'd1 turned 90 degrees after')
    end subroutine test_polyline_vertex_bisects

    ! A polyline through n points of a helix with the helix's d1(0): the discrete transport
    ! approaches the helix's frame at the end with error O(1/n^2) (factor about 4 per doubling).
    subroutine test_polyline_converges_to_helix()
        type(rod_geometry_t) :: helix, poly
        real(rk), allocatable :: p(:, :)
        real(rk) :: error(3), d_helix(3, 3), d_poly(3, 3), rate
        integer :: level, n, k
        helix = helix_geometry([0.0_rk, 0.0_rk, 0.0_rk], [0.0_rk, 0.0_rk, 1.0_rk], 0.5_rk, 0.4_rk, &
            2.0_rk)
        call set_start_director(helix, default_normal(centreline_tangent(helix, 0.0_rk)))
        d_helix = centreline_frame(helix, helix%length)
        do level = 1, 3
            n = 50 * 2**(level - 1)
            allocate(p(3, n + 1))
            do k = 0, n
                p(:, k + 1) = centreline_point(helix, helix%length * real(k, rk) / real(n, rk))
            end do
            poly = polyline_geometry(p)
            ! The first chord's direction differs from the tangent by O(1/n): start d1 normal to it.
            call set_start_director(poly, default_normal(poly%tangents(:, 1)))
            d_poly = centreline_frame(poly, poly%length)
            ! Compare d1 after removing the (chord-versus-tangent) tilt: the angle about d3.
            error(level) = abs(atan2(dot_product(d_poly(:, 1), d_helix(:, 2)), &
                dot_product(d_poly(:, 1), d_helix(:, 1))) - atan2(dot_product(poly%normals(:, 1), &
                start_frame(helix, 2)), dot_product(poly%normals(:, 1), start_frame(helix, 1))))
            deallocate(p)
        end do
        rate = log(error(2) / error(3)) / log(2.0_rk)
        CHECK_TRUE(error(3) < 1.0e-3_rk, 'discrete transport close to the helix frame')
        CHECK_TRUE(rate > 1.7_rk, 'discrete transport converges at second order')
    contains
        function start_frame(g, i) result(v)
            type(rod_geometry_t), intent(in) :: g
            integer, intent(in) :: i
            real(rk) :: v(3), d(3, 3)
            d = centreline_frame(g, 0.0_rk)
            v = d(:, i)
        end function start_frame
    end subroutine test_polyline_converges_to_helix

end module rs_test_model_rod_geometry

program test_model_rod_geometry
    use rs_test_model_rod_geometry, only: run_all_tests
    use rs_test_assert, only: finish_tests
    implicit none
    call run_all_tests()
    call finish_tests()
end program test_model_rod_geometry
