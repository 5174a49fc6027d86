#include "rs_assert.h"
!> Unit tests of rs_model_support: what each kind of &bc holds (the projector onto the held
!> directions of the position and the rotation flag, the twist alone), held_coordinates
!> (inertial coordinates, refused for an oblique slide and the twist alone, with the twist's
!> own message), held_names and hold_list for the plan and messages. The
!> planar mapping of a hold is tested with rs_model_planarity (test_planarity.F90).
module rs_test_model_support
    use rs_core_kinds, only: rk
    use rs_test_assert, only: run_test, assert_true, assert_close, assert_equal
    use rs_model_scene, only: bc_input_t
    use rs_model_support, only: end_hold_t, end_hold, held_coordinates, held_names, hold_list, &
        coordinate_hold_refusal
    implicit none
    private

    public :: run_all_tests

contains

    subroutine run_all_tests()
        call run_test('kinds', test_kinds)
        call run_test('held_entries', test_held_entries)
        call run_test('sliding', test_sliding)
        call run_test('twist', test_twist)
        call run_test('names', test_names)
    end subroutine run_all_tests

    function bc_of(kind) result(bc)
        character(len=*), intent(in) :: kind
        type(bc_input_t) :: bc
        bc%rod = 'beam'
        bc%end = 'end'
        bc%kind = kind
    end function bc_of

    !> The coordinates mask of a bc, with ok.
    subroutine mask_of(bc, mask, ok)
        type(bc_input_t), intent(in) :: bc
        logical, intent(out) :: mask(6), ok
        call held_coordinates(end_hold(bc), mask, ok)
    end subroutine mask_of

    !> clamped and driven hold everything, pinned the position, free and body nothing.
    subroutine test_kinds()
        logical :: mask(6), ok
        call mask_of(bc_of('clamped'), mask, ok)
        CHECK_TRUE(ok .and. all(mask), 'clamped: all held')
        call mask_of(bc_of('driven'), mask, ok)
        CHECK_TRUE(ok .and. all(mask), 'driven: all held (moved by the formulation)')
        call mask_of(bc_of('pinned'), mask, ok)
        CHECK_TRUE(ok .and. all(mask(1:3)) .and. .not. any(mask(4:6)), 'pinned: the position')
        call mask_of(bc_of('free'), mask, ok)
        CHECK_TRUE(ok .and. .not. any(mask), 'free: nothing')
        call mask_of(bc_of('body'), mask, ok)
        CHECK_TRUE(ok .and. .not. any(mask), 'body: nothing')
    end subroutine test_kinds

    !> kind = 'held': the named coordinates and the rotation; 'x', 'y', 'z', 'rotation' is a
    !> clamp, 'y', 'z', 'rotation' a slide along x.
    subroutine test_held_entries()
        type(bc_input_t) :: bc
        type(end_hold_t) :: hold
        logical :: mask(6), ok, good
        real(rk) :: expected(3, 3)
        bc = bc_of('held')
        bc%hold(1) = 'z'
        hold = end_hold(bc)
        expected = 0.0_rk
        expected(3, 3) = 1.0_rk
        CHECK_CLOSE(hold%position, expected, 0.0_rk, 0.0_rk, 'z: the projector e_z e_z^T')
        CHECK_TRUE(.not. hold%rotation, 'z: rotation free')
        call mask_of(bc, mask, ok)
        good = ok .and. all(mask .eqv. [.false., .false., .true., .false., .false., .false.])
        CHECK_TRUE(good, 'z: a roller')
        bc%hold(1:4) = ['x       ', 'y       ', 'z       ', 'rotation']
        call mask_of(bc, mask, ok)
        CHECK_TRUE(ok .and. all(mask), 'x, y, z, rotation: clamped')
        bc%hold = ''
        bc%hold(1:3) = ['y       ', 'rotation', 'z       ']
        call mask_of(bc, mask, ok)
        good = ok .and. all(mask .eqv. [.false., .true., .true., .true., .true., .true.])
        CHECK_TRUE(good, 'y, rotation, z: sliding along x, in any order')
    end subroutine test_held_entries

    !> A slide holds I - a a^T and the rotation: a coordinate axis is held by coordinates (the
    !> others), an oblique one is not (ok false); the axis need not be normalized.
    subroutine test_sliding()
        type(bc_input_t) :: bc
        type(end_hold_t) :: hold
        logical :: mask(6), ok, good
        real(rk) :: expected(3, 3)
        bc = bc_of('sliding')
        bc%axis = [0.0_rk, 0.0_rk, -2.5_rk]
        call mask_of(bc, mask, ok)
        good = ok .and. all(mask .eqv. [.true., .true., .false., .true., .true., .true.])
        CHECK_TRUE(good, 'slide along -z: x, y and the rotation held')
        bc%axis = [1.0_rk, 1.0_rk, 0.0_rk]
        hold = end_hold(bc)
        expected = reshape([0.5_rk, -0.5_rk, 0.0_rk, -0.5_rk, 0.5_rk, 0.0_rk, 0.0_rk, 0.0_rk, &
            1.0_rk], [3, 3])
        CHECK_CLOSE(hold%position, expected, 1.0e-15_rk, 0.0_rk, 'oblique slide: I - a a^T')
        call mask_of(bc, mask, ok)
        CHECK_TRUE(.not. ok, 'an oblique slide is not held by coordinates')
    end subroutine test_sliding

    !> hold = 'twist': the twist alone (not the rotation), which no formulation that holds the
    !> rotation as a whole holds by coordinates (ok false, and the refusal says so); with
    !> 'rotation' the whole rotation (the input check refuses naming both).
    subroutine test_twist()
        type(bc_input_t) :: bc
        type(end_hold_t) :: hold
        logical :: mask(6), ok
        character(len=:), allocatable :: message
        bc = bc_of('held')
        bc%hold(1:4) = ['x       ', 'y       ', 'z       ', 'twist   ']
        hold = end_hold(bc)
        CHECK_TRUE(hold%twist .and. .not. hold%rotation, 'x, y, z, twist: the twist alone')
        call mask_of(bc, mask, ok)
        CHECK_TRUE(.not. ok, 'the twist alone is no coordinate of held_coordinates')
        message = coordinate_hold_refusal('beam', 'ph_director', 'phi', bc)
        ok = index(message, 'cannot hold the twist of an end alone') > 0
        CHECK_TRUE(ok, 'the refusal names the twist')
        bc%hold(4) = 'rotation'
        bc%hold(3) = 'twist'
        hold = end_hold(bc)
        CHECK_TRUE(hold%rotation .and. .not. hold%twist, 'rotation and twist: the rotation')
    end subroutine test_twist

    subroutine test_names()
        type(bc_input_t) :: bc
        logical :: twist(6)
        CHECK_EQUAL(held_names([.true., .false., .true., .false., .false., .false.]), 'x, z', 'x, z')
        CHECK_EQUAL(held_names([.false., .false., .false., .true., .true., .true.]), 'rotation', 'rotation')
        CHECK_EQUAL(held_names([.false., .false., .false., .false., .false., .false.]), 'none', 'none')
        twist = [.true., .true., .true., .true., .false., .false.]
        CHECK_EQUAL(held_names(twist), 'x, y, z, twist', 'one rotation coordinate: the twist (se3_pg)')
        bc = bc_of('held')
        bc%hold(1:2) = ['z       ', 'rotation']
        CHECK_EQUAL(hold_list(bc), '''z'', ''rotation''', 'the entries quoted')
    end subroutine test_names

end module rs_test_model_support

program test_model_support
    use rs_test_assert, only: finish_tests
    use rs_test_model_support, only: run_all_tests
    implicit none
    call run_all_tests()
    call finish_tests()
end program test_model_support
