#include "rs_assert.h"
!> Unit tests of rs_model_planarity on scenes built from components (no input file): a rod in
!> the xy-plane (planar coordinates = x, y), a rod in the xz-plane (normal e_y, e2 = -e_z), a
!> vertical rod with no other vector (normal from the candidate list), a tilted cross-section
!> (the normal is d1), and the reasons of scenes that are not planar, each checked by a key
!> substring: an out-of-plane force, velocity and gravity, a moment and an angular velocity not
!> along the normal, two rods in different planes, an oblique d1, a helix. Also the tolerance
!> (1e-12 relative), the right-handed orthonormal basis, and round trips point_in_plane /
!> point_from_plane, vector_in_plane / vector_from_plane and angle_in_plane; the planar
!> coordinates a support's hold fixes (planar_held).
module rs_test_model_planarity
    use rs_core_kinds, only: rk, pi
    use rs_test_assert, only: run_test, assert_true, assert_close, assert_equal, assert_contains
    use rs_model_scene, only: scene_t, rod_input_t, load_input_t
    use rs_model_planarity, only: plane_t, plane_of_rods, point_in_plane, vector_in_plane, &
        point_from_plane, vector_from_plane, angle_in_plane, planarity_tolerance, planar_held
    use rs_model_support, only: end_hold_t
    implicit none
    private

    public :: run_all_tests

    real(rk), parameter :: tight = 1.0e-14_rk
    real(rk), parameter :: e_x(3) = [1.0_rk, 0.0_rk, 0.0_rk]
    real(rk), parameter :: e_y(3) = [0.0_rk, 1.0_rk, 0.0_rk]
    real(rk), parameter :: e_z(3) = [0.0_rk, 0.0_rk, 1.0_rk]
    real(rk), parameter :: zero(3) = 0.0_rk

contains

    !> Run every test of this file through rs_test_assert.
    subroutine run_all_tests()
        call run_test('xy_plane_rod', test_xy_plane_rod)
        call run_test('xz_plane_rod', test_xz_plane_rod)
        call run_test('lone_vertical_rod', test_lone_vertical_rod)
        call run_test('tilted_section', test_tilted_section)
        call run_test('out_of_plane_force', test_out_of_plane_force)
        call run_test('out_of_plane_velocity_and_gravity', test_out_of_plane_velocity_and_gravity)
        call run_test('moment_not_along_normal', test_moment_not_along_normal)
        call run_test('two_rods_in_different_planes', test_two_rods_in_different_planes)
        call run_test('oblique_d1', test_oblique_d1)
        call run_test('helix', test_helix)
        call run_test('tolerance', test_tolerance)
        call run_test('round_trips', test_round_trips)
        call run_test('planar_held', test_planar_held)
    end subroutine run_all_tests

    !> A straight rod as the resolver leaves it (d1 normal to the unit direction).
    function rod(name, line, start, direction, d1, length) result(r)
        character(len=*), intent(in) :: name
        integer, intent(in) :: line
        real(rk), intent(in) :: start(3), direction(3), d1(3), length
        type(rod_input_t) :: r
        r%name = name
        r%input_line = line
        r%start = start
        r%direction = direction / norm2(direction)
        r%d1 = d1 / norm2(d1)
        r%length = length
        r%rotation_center = start
    end function rod

    function load(rod_name, line, where, force, moment, acceleration) result(l)
        character(len=*), intent(in) :: rod_name, where
        integer, intent(in) :: line
        real(rk), intent(in) :: force(3), moment(3), acceleration(3)
        type(load_input_t) :: l
        l%rod = rod_name
        l%input_line = line
        l%where = where
        l%force = force
        l%moment = moment
        l%acceleration = acceleration
    end function load

    !> A scene of `rods` and `loads`.
    function scene_of(rods, loads) result(scene)
        type(rod_input_t), intent(in) :: rods(:)
        type(load_input_t), intent(in) :: loads(:)
        type(scene_t) :: scene
        scene%source_file = 'test.nml'
        scene%rods = rods
        scene%loads = loads
        allocate(scene%bcs(0), scene%actuators(0), scene%joints(0))
    end function scene_of

    function no_loads() result(loads)
        type(load_input_t), allocatable :: loads(:)
        allocate(loads(0))
    end function no_loads

    !> e1, e2, normal orthonormal and right-handed, origin on the normal through 0.
    subroutine check_basis(plane, label)
        type(plane_t), intent(in) :: plane
        character(len=*), intent(in) :: label
        CHECK_CLOSE(norm2(plane%e1), 1.0_rk, tight, 0.0_rk, label // ': |e1| = 1')
        CHECK_CLOSE(norm2(plane%e2), 1.0_rk, tight, 0.0_rk, label // ': |e2| = 1')
        CHECK_CLOSE(norm2(plane%normal), 1.0_rk, tight, 0.0_rk, label // ': |n| = 1')
        CHECK_CLOSE(dot_product(plane%e1, plane%e2), 0.0_rk, tight, 0.0_rk, label // ': e1 . e2 = 0')
        CHECK_CLOSE(cross(plane%e1, plane%e2), plane%normal, tight, 0.0_rk, label // ': e1 x e2 = n')
        call assert_close(norm2(cross(plane%origin, plane%normal)), 0.0_rk, tight, 0.0_rk, &
            label // ': origin along n', __FILE__, __LINE__)
    end subroutine check_basis

    ! A rod in the xy-plane under gravity along -e_y: e1 = e_x, e2 = e_y, n = e_z, origin 0, so
    ! the planar coordinates are x and y, and the rod's angle is that of its direction.
    subroutine test_xy_plane_rod()
        type(scene_t) :: scene
        type(plane_t) :: plane
        scene = scene_of([rod('a', 3, v3(1.0_rk, 2.0_rk, 0.0_rk), v3(1.0_rk, 1.0_rk, 0.0_rk), e_z, 2.0_rk)], &
            [load('', 7, 'gravity', zero, zero, v3(0.0_rk, -9.81_rk, 0.0_rk))])
        plane = plane_of_rods(scene, [1])
        CHECK_TRUE(plane%found, 'xy-plane rod is planar: ' // plane%reason)
        CHECK_EQUAL(plane%reason, '', 'no reason')
        CHECK_CLOSE(plane%normal, e_z, 0.0_rk, 0.0_rk, 'normal e_z')
        CHECK_CLOSE(plane%e1, e_x, 0.0_rk, 0.0_rk, 'e1 = e_x')
        CHECK_CLOSE(plane%e2, e_y, 0.0_rk, 0.0_rk, 'e2 = e_y')
        CHECK_CLOSE(plane%origin, zero, 0.0_rk, 0.0_rk, 'origin 0')
        call assert_close(point_in_plane(plane, v3(3.5_rk, -1.25_rk, 0.0_rk)), v2(3.5_rk, -1.25_rk), 0.0_rk, &
            0.0_rk, 'planar coordinates are x, y', __FILE__, __LINE__)
        call assert_close(angle_in_plane(plane, scene%rods(1)%direction), pi / 4.0_rk, tight, 0.0_rk, &
            'angle of the direction (1, 1, 0)', __FILE__, __LINE__)
        call check_basis(plane, 'xy')
    end subroutine test_xy_plane_rod

    ! A rod along e_x at y = 3 with a tip force along -e_z: the plane y = 3, normal +e_y (no
    ! z component, so the sign makes n . e_y > 0), e1 = e_x and e2 = n x e1 = -e_z.
    subroutine test_xz_plane_rod()
        type(scene_t) :: scene
        type(plane_t) :: plane
        scene = scene_of([rod('a', 3, v3(0.0_rk, 3.0_rk, 0.0_rk), e_x, e_y, 1.0_rk)], &
            [load('a', 5, 'end', v3(0.0_rk, 0.0_rk, -1.0_rk), v3(0.0_rk, 0.5_rk, 0.0_rk), zero)])
        plane = plane_of_rods(scene, [1])
        CHECK_TRUE(plane%found, 'xz-plane rod is planar: ' // plane%reason)
        CHECK_CLOSE(plane%normal, e_y, 0.0_rk, 0.0_rk, 'normal e_y')
        CHECK_CLOSE(plane%origin, v3(0.0_rk, 3.0_rk, 0.0_rk), 0.0_rk, 0.0_rk, 'origin (0, 3, 0)')
        CHECK_CLOSE(plane%e1, e_x, 0.0_rk, 0.0_rk, 'e1 = e_x')
        CHECK_CLOSE(plane%e2, -e_z, 0.0_rk, 0.0_rk, 'e2 = -e_z')
        call assert_close(point_in_plane(plane, v3(2.0_rk, 3.0_rk, 5.0_rk)), v2(2.0_rk, -5.0_rk), tight, 0.0_rk, &
            'planar coordinates (x, -z)', __FILE__, __LINE__)
        call assert_close(vector_in_plane(plane, v3(0.0_rk, 0.0_rk, -1.0_rk)), v2(0.0_rk, 1.0_rk), tight, 0.0_rk, &
            'the force points along +e2', __FILE__, __LINE__)
        call check_basis(plane, 'xz')
    end subroutine test_xz_plane_rod

    ! A rod along e_z with nothing else: every plane through it would do; e_z is not normal to
    ! it, e_y is and d1 = e_x (the default for a rod along e_z) lies in that plane.
    subroutine test_lone_vertical_rod()
        type(scene_t) :: scene
        type(plane_t) :: plane
        scene = scene_of([rod('post', 2, zero, e_z, e_x, 1.0_rk)], no_loads())
        plane = plane_of_rods(scene, [1])
        CHECK_TRUE(plane%found, 'a lone rod is planar: ' // plane%reason)
        CHECK_CLOSE(plane%normal, e_y, 0.0_rk, 0.0_rk, 'normal e_y (first candidate after e_z)')
        call check_basis(plane, 'vertical')
    end subroutine test_lone_vertical_rod

    ! A rod along e_x whose d1 is tilted in the yz-plane: neither e_z nor e_y meets the
    ! director rule, so the normal is d1 itself, with e2 = n x e_x.
    subroutine test_tilted_section()
        type(scene_t) :: scene
        type(plane_t) :: plane
        real(rk) :: d1(3)
        d1 = v3(0.0_rk, 0.6_rk, 0.8_rk)
        scene = scene_of([rod('a', 2, zero, e_x, d1, 1.0_rk)], no_loads())
        plane = plane_of_rods(scene, [1])
        CHECK_TRUE(plane%found, 'tilted section: planar about d1: ' // plane%reason)
        CHECK_CLOSE(plane%normal, d1, tight, 0.0_rk, 'normal = d1')
        CHECK_CLOSE(plane%e1, e_x, tight, 0.0_rk, 'e1 = e_x')
        CHECK_CLOSE(plane%e2, v3(0.0_rk, 0.8_rk, -0.6_rk), tight, 0.0_rk, 'e2 = n x e1')
        call check_basis(plane, 'tilted')
    end subroutine test_tilted_section

    ! The normal comes from the angular velocity (e_z); a force along -e_z leaves the plane.
    subroutine test_out_of_plane_force()
        type(scene_t) :: scene
        type(plane_t) :: plane
        type(rod_input_t) :: r
        r = rod('a', 3, zero, e_x, e_y, 1.0_rk)
        r%angular_velocity = v3(0.0_rk, 0.0_rk, 2.0_rk)
        scene = scene_of([r], [load('a', 40, 'end', v3(1.0_rk, 0.0_rk, 0.0_rk), zero, zero), &
            load('a', 41, 'distributed', v3(0.0_rk, 0.0_rk, -5.0_rk), zero, zero)])
        plane = plane_of_rods(scene, [1])
        CHECK_TRUE(.not. plane%found, 'out-of-plane force')
        call assert_contains(plane%reason, 'load 2 (line 41): force (0.0, 0.0, -5.0) has a component ' // &
            'along the plane normal (0.0, 0.0, 1.0)', 'reason names the load, its line and force', __FILE__, __LINE__)
        call assert_contains(plane%reason, "the plane follows from rod 'a' (line 3): angular_velocity", &
            'reason names where the normal came from', __FILE__, __LINE__)
    end subroutine test_out_of_plane_force

    ! In-plane vectors e_x and e_y give n = e_z; a velocity along e_z, and separately a gravity
    ! load without rod (it applies to every rod) along e_z, leave the plane; a gravity load on
    ! another rod does not apply.
    subroutine test_out_of_plane_velocity_and_gravity()
        type(scene_t) :: scene
        type(plane_t) :: plane
        type(rod_input_t) :: r
        type(load_input_t) :: push
        push = load('a', 6, 'end', e_y, zero, zero)
        r = rod('a', 3, zero, e_x, e_y, 1.0_rk)
        r%velocity = v3(0.0_rk, 1.0_rk, 0.25_rk)
        scene = scene_of([r], [push])
        plane = plane_of_rods(scene, [1])
        CHECK_TRUE(.not. plane%found, 'out-of-plane velocity')
        call assert_contains(plane%reason, "rod 'a' (line 3): velocity (0.0, 1.0, 0.25) has a component along", &
            'velocity reason', __FILE__, __LINE__)
        r%velocity = 0.0_rk
        scene = scene_of([r], [push, load('', 9, 'gravity', zero, zero, v3(0.0_rk, 0.0_rk, -9.81_rk))])
        plane = plane_of_rods(scene, [1])
        CHECK_TRUE(.not. plane%found, 'gravity of every rod out of plane')
        call assert_contains(plane%reason, 'load 2 (line 9): gravity acceleration (0.0, 0.0, -9.81) has a ' // &
            'component along the plane normal (0.0, 0.0, 1.0)', 'gravity reason', __FILE__, __LINE__)
        scene = scene_of([r, rod('other', 4, v3(0.0_rk, 0.0_rk, 7.0_rk), e_z, e_x, 1.0_rk)], &
            [push, load('other', 9, 'gravity', zero, zero, v3(0.0_rk, 0.0_rk, -9.81_rk))])
        plane = plane_of_rods(scene, [1])
        CHECK_TRUE(plane%found, 'gravity of another rod does not apply: ' // plane%reason)
    end subroutine test_out_of_plane_velocity_and_gravity

    ! The first moment fixes the normal (e_z); a second moment, and an angular velocity, that
    ! are not along it are reasons.
    subroutine test_moment_not_along_normal()
        type(scene_t) :: scene
        type(plane_t) :: plane
        type(rod_input_t) :: r
        r = rod('a', 3, zero, e_x, e_y, 1.0_rk)
        scene = scene_of([r], [load('a', 5, 'end', e_y, v3(0.0_rk, 0.0_rk, 2.0_rk), zero), &
            load('a', 6, 'start', zero, v3(0.1_rk, 0.0_rk, 1.0_rk), zero)])
        plane = plane_of_rods(scene, [1])
        CHECK_TRUE(.not. plane%found, 'second moment off the normal')
        call assert_contains(plane%reason, 'load 2 (line 6): moment (0.1, 0.0, 1.0) is not along the plane ' // &
            'normal (0.0, 0.0, 1.0)', 'moment reason', __FILE__, __LINE__)
        CHECK_CONTAINS(plane%reason, 'the plane follows from load 1 (line 5): moment', 'normal source')
        r%angular_velocity = v3(0.0_rk, 0.0_rk, 1.0_rk)
        scene = scene_of([r], [load('a', 5, 'end', zero, v3(0.0_rk, 3.0_rk, 0.0_rk), zero)])
        plane = plane_of_rods(scene, [1])
        CHECK_TRUE(.not. plane%found, 'moment off the angular velocity')
        call assert_contains(plane%reason, 'load 1 (line 5): moment (0.0, 3.0, 0.0) is not along', &
            'moment against angular velocity', __FILE__, __LINE__)
        scene = scene_of([r], [load('a', 5, 'end', e_y, v3(0.0_rk, 0.0_rk, -4.0_rk), zero)])
        plane = plane_of_rods(scene, [1])
        CHECK_TRUE(plane%found, 'moment along -e_z and spin along e_z: planar: ' // plane%reason)
    end subroutine test_moment_not_along_normal

    ! Rod a along e_x at the origin, rod b along e_y starting at (0, 0, 1): the directions give
    ! n = e_z and b's start lies 1 off that plane. Moved to z = 0, the two rods are planar.
    subroutine test_two_rods_in_different_planes()
        type(scene_t) :: scene
        type(plane_t) :: plane
        scene = scene_of([rod('a', 3, zero, e_x, e_y, 1.0_rk), &
            rod('b', 5, v3(0.0_rk, 0.0_rk, 1.0_rk), e_y, -e_x, 1.0_rk)], no_loads())
        plane = plane_of_rods(scene, [1, 2])
        CHECK_TRUE(.not. plane%found, 'two planes')
        call assert_contains(plane%reason, "rod 'b' (line 5): start (0.0, 0.0, 1.0) lies off the plane " // &
            'through (0.0, 0.0, 0.0) with normal (0.0, 0.0, 1.0) (distance 1.0)', 'start reason', __FILE__, __LINE__)
        plane = plane_of_rods(scene, [2])
        CHECK_TRUE(plane%found, 'rod b alone is planar: ' // plane%reason)
        CHECK_CLOSE(plane%origin, v3(0.0_rk, 0.0_rk, 1.0_rk), 0.0_rk, 0.0_rk, 'rod b alone: plane z = 1')
        scene%rods(2)%start = v3(1.0_rk, 0.0_rk, 0.0_rk)
        plane = plane_of_rods(scene, [1, 2])
        CHECK_TRUE(plane%found, 'both in z = 0: ' // plane%reason)
        CHECK_CLOSE(plane%normal, e_z, 0.0_rk, 0.0_rk, 'both in z = 0: normal e_z')
    end subroutine test_two_rods_in_different_planes

    ! With a force along e_y the plane is z = 0; a d1 tilted out of it (neither in the plane
    ! nor along e_z) would twist the section: not planar.
    subroutine test_oblique_d1()
        type(scene_t) :: scene
        type(plane_t) :: plane
        scene = scene_of([rod('a', 3, zero, e_x, v3(0.0_rk, 0.6_rk, 0.8_rk), 1.0_rk)], &
            [load('a', 5, 'end', e_y, zero, zero)])
        plane = plane_of_rods(scene, [1])
        CHECK_TRUE(.not. plane%found, 'oblique d1')
        call assert_contains(plane%reason, "rod 'a' (line 3): d1 (0.0, 0.6, 0.8) is neither along nor " // &
            'perpendicular to the plane normal (0.0, 0.0, 1.0)', 'd1 reason', __FILE__, __LINE__)
    end subroutine test_oblique_d1

    ! A helix is a curved reference, even a flat one (pitch 0).
    subroutine test_helix()
        type(scene_t) :: scene
        type(plane_t) :: plane
        type(rod_input_t) :: r
        r = rod('spring', 4, zero, e_z, e_x, 1.0_rk)
        r%geometry = 'helix'
        r%helix_radius = 0.1_rk
        r%helix_pitch = 0.0_rk
        r%helix_turns = 1.0_rk
        scene = scene_of([rod('a', 2, zero, e_x, e_y, 1.0_rk), r], no_loads())
        plane = plane_of_rods(scene, [1, 2])
        CHECK_TRUE(.not. plane%found, 'helix')
        call assert_contains(plane%reason, "rod 'spring' (line 4): curved reference (geometry 'helix')", &
            'helix reason', __FILE__, __LINE__)
    end subroutine test_helix

    ! A direction whose component along the normal is far below 1e-12 of its length is in the
    ! plane; one of 1e-10 is not (the normal comes from the angular velocity, so the direction
    ! cannot tilt it).
    subroutine test_tolerance()
        type(scene_t) :: scene
        type(plane_t) :: plane
        type(rod_input_t) :: r
        r = rod('a', 3, zero, v3(1.0_rk, 0.0_rk, 1.0e-14_rk), e_y, 1.0_rk)
        r%angular_velocity = e_z
        scene = scene_of([r], no_loads())
        plane = plane_of_rods(scene, [1])
        CHECK_TRUE(plane%found, 'component 1e-14: planar: ' // plane%reason)
        CHECK_TRUE(planarity_tolerance == 1.0e-12_rk, 'tolerance 1e-12')
        scene%rods(1)%direction = v3(1.0_rk, 0.0_rk, 1.0e-10_rk)
        plane = plane_of_rods(scene, [1])
        CHECK_TRUE(.not. plane%found, 'component 1e-10: not planar')
        CHECK_CONTAINS(plane%reason, "rod 'a' (line 3): direction", 'direction reason')
    end subroutine test_tolerance

    ! point_in_plane / point_from_plane, vector_in_plane / vector_from_plane are inverse on the
    ! plane, and angle_in_plane inverts (cos a, sin a), in the tilted plane of test_tilted_section
    ! shifted off the origin.
    subroutine test_round_trips()
        type(scene_t) :: scene
        type(plane_t) :: plane
        real(rk) :: xy(2), p(3), a
        integer :: k
        scene = scene_of([rod('a', 2, v3(1.0_rk, -2.0_rk, 3.0_rk), e_x, v3(0.0_rk, 0.6_rk, 0.8_rk), &
            1.0_rk)], no_loads())
        plane = plane_of_rods(scene, [1])
        CHECK_TRUE(plane%found, 'tilted plane: ' // plane%reason)
        call assert_close(dot_product(scene%rods(1)%start - plane%origin, plane%normal), 0.0_rk, tight, &
            0.0_rk, 'the start lies in the plane', __FILE__, __LINE__)
        do k = 1, 8
            xy = v2(real(k, rk) * 0.7_rk - 3.0_rk, 2.5_rk - real(k * k, rk) * 0.3_rk)
            p = point_from_plane(plane, xy)
            call assert_close(dot_product(p - plane%origin, plane%normal), 0.0_rk, 1.0e-13_rk, 0.0_rk, &
                'point_from_plane lies in the plane', __FILE__, __LINE__)
            CHECK_CLOSE(point_in_plane(plane, p), xy, 1.0e-13_rk, 0.0_rk, 'point round trip')
            call assert_close(point_from_plane(plane, point_in_plane(plane, p)), p, 1.0e-13_rk, 0.0_rk, &
                'point round trip from 3D', __FILE__, __LINE__)
            call assert_close(vector_in_plane(plane, vector_from_plane(plane, xy)), xy, 1.0e-13_rk, 0.0_rk, &
                'vector round trip', __FILE__, __LINE__)
            a = -pi + real(k, rk) * 2.0_rk * pi / 8.0_rk - 0.1_rk
            call assert_close(angle_in_plane(plane, vector_from_plane(plane, [cos(a), sin(a)])), a, &
                1.0e-13_rk, 0.0_rk, 'angle round trip', __FILE__, __LINE__)
        end do
        call assert_close(point_in_plane(plane, scene%rods(1)%start), v2(1.0_rk, -3.4_rk), 1.0e-13_rk, 0.0_rk, &
            'start in planar coordinates: x = 1, y = (start - origin) . e2', __FILE__, __LINE__)
    end subroutine test_round_trips

    !> The vector (a, b, c): an array constructor's commas would split a CHECK macro's arguments.
    pure function v3(a, b, c) result(v)
        real(rk), intent(in) :: a, b, c
        real(rk) :: v(3)
        v(1) = a
        v(2) = b
        v(3) = c
    end function v3

    pure function v2(a, b) result(v)
        real(rk), intent(in) :: a, b
        real(rk) :: v(2)
        v(1) = a
        v(2) = b
    end function v2

    pure function cross(a, b) result(c)
        real(rk), intent(in) :: a(3), b(3)
        real(rk) :: c(3)
        c = [a(2) * b(3) - a(3) * b(2), a(3) * b(1) - a(1) * b(3), a(1) * b(2) - a(2) * b(1)]
    end function cross

    !> A hold in planar coordinates (x, y, theta): in the xz-plane (e1 = e_x, e2 = -e_z) z held
    !> is y held, x held is x, y held (the normal) nothing; a slide along e_x holds y and theta;
    !> in the plane with normal (1, 1, 1)/sqrt(3) (e1 = (2, -1, -1)/sqrt(6), e2 = (0, 1, -1)
    !> /sqrt(2)) y alone fixes an oblique planar direction (not ok), x and y fix both.
    subroutine test_planar_held()
        type(plane_t) :: plane
        type(end_hold_t) :: hold
        logical :: held(3), ok
        plane%found = .true.
        plane%e1 = e_x
        plane%e2 = -e_z
        plane%normal = e_y
        hold = hold_of([.false., .false., .true.], .false.)
        call planar_held(plane, hold, held, ok)
        CHECK_TRUE(ok .and. all(held .eqv. [.false., .true., .false.]), 'xz-plane: z is y')
        call planar_held(plane, hold_of([.true., .false., .false.], .false.), held, ok)
        CHECK_TRUE(ok .and. all(held .eqv. [.true., .false., .false.]), 'xz-plane: x is x')
        call planar_held(plane, hold_of([.false., .true., .false.], .true.), held, ok)
        CHECK_TRUE(ok .and. all(held .eqv. [.false., .false., .true.]), 'xz-plane: y (normal) nothing, rotation theta')
        hold%position = reshape([0.0_rk, 0.0_rk, 0.0_rk, 0.0_rk, 1.0_rk, 0.0_rk, 0.0_rk, 0.0_rk, &
            1.0_rk], [3, 3])
        hold%rotation = .true.
        call planar_held(plane, hold, held, ok)
        CHECK_TRUE(ok .and. all(held .eqv. [.false., .true., .true.]), 'xz-plane: a slide along x')
        plane%normal = [1.0_rk, 1.0_rk, 1.0_rk] / sqrt(3.0_rk)
        plane%e1 = [2.0_rk, -1.0_rk, -1.0_rk] / sqrt(6.0_rk)
        plane%e2 = [0.0_rk, 1.0_rk, -1.0_rk] / sqrt(2.0_rk)
        call planar_held(plane, hold_of([.false., .true., .false.], .false.), held, ok)
        CHECK_TRUE(.not. ok, 'tilted plane: y alone is oblique')
        call planar_held(plane, hold_of([.true., .true., .false.], .false.), held, ok)
        CHECK_TRUE(ok .and. all(held .eqv. [.true., .true., .false.]), 'tilted plane: x and y fix both')
    contains
        pure function hold_of(axes, rotation) result(h)
            logical, intent(in) :: axes(3), rotation
            type(end_hold_t) :: h
            integer :: i
            h%position = 0.0_rk
            do i = 1, 3
                if (axes(i)) h%position(i, i) = 1.0_rk
            end do
            h%rotation = rotation
        end function hold_of
    end subroutine test_planar_held

end module rs_test_model_planarity

!> Test program: runs the tests of rs_test_model_planarity; exits non-zero if any failed.
program test_planarity
    use rs_test_model_planarity, only: run_all_tests
    use rs_test_assert, only: finish_tests
    implicit none
    call run_all_tests()
    call finish_tests()
end program test_planarity
