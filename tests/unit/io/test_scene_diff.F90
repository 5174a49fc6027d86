#include "rs_assert.h"
!> Unit tests of rs_io_scene_diff: the first difference of two resolved scene texts names the
!> group, the rod (or the group's ordinal) and the variable with both values; a free variable,
!> comment lines and an identical text give none; a variable only one text has is named.
module rs_test_io_scene_diff
    use rs_test_assert, only: run_test, assert_true, assert_equal, assert_contains
    use rs_io_scene_diff, only: first_scene_difference
    implicit none
    private

    public :: run_all_tests

    character(len=*), parameter :: nl = new_line('a')
    character(len=*), parameter :: free(1) = [character(len=16) :: 'time%t_end']

contains

    subroutine run_all_tests()
        call run_test('same_scene', test_same_scene)
        call run_test('second_rod_named', test_second_rod_named)
        call run_test('repeated_unnamed_group', test_repeated_unnamed_group)
        call run_test('variable_only_in_one', test_variable_only_in_one)
    end subroutine run_all_tests

    !> Two rods, the second's EA and the time's t_end as given.
    function scene(t_end, ea_b, force_2) result(text)
        character(len=*), intent(in) :: t_end, ea_b, force_2
        character(len=:), allocatable :: text
        text = '! resolved scene of a.nml' // nl // '&time' // nl // '    t_end = ' // t_end // nl // &
            '    dt = 0.1' // nl // '/' // nl // &
            '&rod' // nl // "    name = 'a'" // nl // '    EA = 1.0' // nl // &
            '    ! GJ = 3.0   (from the section)' // nl // '/' // nl // &
            '&rod' // nl // "    name = 'b'" // nl // '    EA = ' // ea_b // nl // '/' // nl // &
            '&load' // nl // '    force = 0.0, 0.0, 1.0' // nl // '/' // nl // &
            '&load' // nl // '    force = ' // force_2 // nl // '/' // nl
    end function scene

    subroutine test_same_scene()
        character(len=:), allocatable :: got
        got = first_scene_difference(scene('1.0', '2.0', '1.0'), scene('5.0', '2.0', '1.0'), free)
        CHECK_EQUAL(got, '', 'only the free t_end differs (and a comment line)')
    end subroutine test_same_scene

    subroutine test_second_rod_named()
        character(len=:), allocatable :: got
        got = first_scene_difference(scene('1.0', '2.0', '1.0'), scene('1.0', '3.0', '1.0'), free)
        CHECK_EQUAL(got, "&rod 'b' EA: 2.0 in the checkpoint's scene, 3.0 in this one", 'rod b')
        got = first_scene_difference(scene('1.0', '2.0', '1.0'), scene('1.0', '3.0', '1.0'), free, &
            'the member''s file')
        CHECK_CONTAINS(got, "in the member's file", 'the stored text named as asked')
    end subroutine test_second_rod_named

    subroutine test_repeated_unnamed_group()
        character(len=:), allocatable :: got
        got = first_scene_difference(scene('1.0', '2.0', '1.0'), scene('1.0', '2.0', '4.0'), free)
        CHECK_EQUAL(got, "&load 2 force: 1.0 in the checkpoint's scene, 4.0 in this one", 'load 2')
    end subroutine test_repeated_unnamed_group

    subroutine test_variable_only_in_one()
        character(len=:), allocatable :: more, got
        more = scene('1.0', '2.0', '1.0') // '&bc' // nl // "    kind = 'clamped'" // nl // '/' // nl
        got = first_scene_difference(scene('1.0', '2.0', '1.0'), more, free)
        CHECK_EQUAL(got, "&bc kind = 'clamped' in this scene is not in the checkpoint's scene", 'new')
        got = first_scene_difference(more, scene('1.0', '2.0', '1.0'), free)
        CHECK_EQUAL(got, "&bc kind = 'clamped' in the checkpoint's scene is not in this scene", 'gone')
    end subroutine test_variable_only_in_one

end module rs_test_io_scene_diff

!> Test program: runs the tests of rs_test_io_scene_diff; exits non-zero if any failed.
program test_scene_diff
    use rs_test_io_scene_diff, only: run_all_tests
    use rs_test_assert, only: finish_tests
    implicit none
    call run_all_tests()
    call finish_tests()
end program test_scene_diff
