#include "rs_assert.h"
!> Unit tests of rs_model_coupling: the systems a scene's joints, plates and contact make
!> (DESIGN.md §5). A scene without joints has one system per rod; joints join their rods into
!> one system whose first rod leads; chains join transitively; a joint naming an unknown rod
!> joins nothing; the rods of a plate are one system (and a plate and a joint chain join);
!> &contact makes every rod of the scene one system.
module rs_test_model_coupling
    use rs_test_assert, only: run_test, assert_true, assert_equal
    use rs_model_scene, only: scene_t, rod_input_t, joint_input_t, plate_input_t
    use rs_model_coupling, only: coupled_systems
    implicit none
    private

    public :: run_all_tests

contains

    subroutine run_all_tests()
        call run_test('no_joints', test_no_joints)
        call run_test('four_bar_and_a_free_rod', test_four_bar_and_a_free_rod)
        call run_test('chain_out_of_order', test_chain_out_of_order)
        call run_test('unknown_rod_joins_nothing', test_unknown_rod_joins_nothing)
        call run_test('plates_join_their_rods', test_plates_join_their_rods)
        call run_test('contact_joins_all_rods', test_contact_joins_all_rods)
    end subroutine run_all_tests

    !> A scene with rods named r1..rn and the given joints (pairs of rod numbers).
    function scene_with(n, pairs) result(scene)
        integer, intent(in) :: n, pairs(:, :)
        type(scene_t) :: scene
        integer :: i
        allocate(scene%rods(n), scene%joints(size(pairs, 2)))
        do i = 1, n
            write(scene%rods(i)%name, '(a, i0)') 'r', i
        end do
        do i = 1, size(pairs, 2)
            write(scene%joints(i)%rod_a, '(a, i0)') 'r', pairs(1, i)
            write(scene%joints(i)%rod_b, '(a, i0)') 'r', pairs(2, i)
        end do
    end function scene_with

    subroutine test_no_joints()
        type(scene_t) :: scene
        integer, allocatable :: system_of(:), first(:), members(:)
        integer :: empty(2, 0)
        scene = scene_with(3, empty)
        call coupled_systems(scene, system_of, first, members)
        CHECK_TRUE(all(system_of == [1, 2, 3]), 'one system per rod, in rod order')
        CHECK_TRUE(all(first == [1, 2, 3, 4]), 'one member each')
        CHECK_TRUE(all(members == [1, 2, 3]), 'members in rod order')
    end subroutine test_no_joints

    ! The four-bar (rods 1-2-3 joined) and a free rod 4.
    subroutine test_four_bar_and_a_free_rod()
        type(scene_t) :: scene
        integer, allocatable :: system_of(:), first(:), members(:)
        scene = scene_with(4, reshape([1, 2, 2, 3], [2, 2]))
        call coupled_systems(scene, system_of, first, members)
        CHECK_TRUE(all(system_of == [1, 1, 1, 2]), 'rods 1-3 one system, rod 4 another')
        CHECK_TRUE(all(first == [1, 4, 5]), 'three members, then one')
        CHECK_TRUE(all(members == [1, 2, 3, 4]), 'members in rod order')
    end subroutine test_four_bar_and_a_free_rod

    ! Joints 4-5, 2-5 and a free rod 1 and 3: systems {1}, {2, 4, 5}, {3}, led by 2.
    subroutine test_chain_out_of_order()
        type(scene_t) :: scene
        integer, allocatable :: system_of(:), first(:), members(:)
        scene = scene_with(5, reshape([4, 5, 5, 2], [2, 2]))
        call coupled_systems(scene, system_of, first, members)
        CHECK_TRUE(all(system_of == [1, 2, 3, 2, 2]), 'systems numbered by their first rod')
        CHECK_TRUE(all(first == [1, 2, 5, 6]), 'sizes 1, 3, 1')
        CHECK_TRUE(all(members == [1, 2, 4, 5, 3]), 'the joined rods together, first rod leads')
    end subroutine test_chain_out_of_order

    subroutine test_unknown_rod_joins_nothing()
        type(scene_t) :: scene
        integer, allocatable :: system_of(:), first(:), members(:)
        scene = scene_with(2, reshape([1, 2], [2, 1]))
        scene%joints(1)%rod_b = 'nobody'
        call coupled_systems(scene, system_of, first, members)
        CHECK_TRUE(all(system_of == [1, 2]), 'an unknown rod name joins nothing')
    end subroutine test_unknown_rod_joins_nothing

    ! Rods 1..6: plate 'top' ties r5 and r3 (listed out of order, after a blank and an
    ! unknown name), plate 'bottom' r6 alone, joint 3-4: systems {1}, {2}, {3, 4, 5}, {6}.
    subroutine test_plates_join_their_rods()
        type(scene_t) :: scene
        integer, allocatable :: system_of(:), first(:), members(:)
        scene = scene_with(6, reshape([3, 4], [2, 1]))
        allocate(scene%plates(2))
        scene%plates(1)%name = 'top'
        scene%plates(1)%rods(1:3) = [character(len=8) :: 'nobody', 'r5', 'r3']
        scene%plates(2)%name = 'bottom'
        scene%plates(2)%rods(1) = 'r6'
        call coupled_systems(scene, system_of, first, members)
        CHECK_TRUE(all(system_of == [1, 2, 3, 3, 3, 4]), 'plate rods and their joint one system')
        CHECK_TRUE(all(first == [1, 2, 3, 6, 7]), 'sizes 1, 1, 3, 1')
        CHECK_TRUE(all(members == [1, 2, 3, 4, 5, 6]), 'members in rod order, first rod leads')
    end subroutine test_plates_join_their_rods

    ! Contact may couple any two rods: with &contact every rod is in system 1; without it the
    ! same scene has one system per rod.
    subroutine test_contact_joins_all_rods()
        type(scene_t) :: scene
        integer, allocatable :: system_of(:), first(:), members(:)
        integer :: empty(2, 0)
        scene = scene_with(4, empty)
        call coupled_systems(scene, system_of, first, members)
        CHECK_EQUAL(size(first) - 1, 4, 'without contact: four systems')
        scene%contact%given = .true.
        call coupled_systems(scene, system_of, first, members)
        CHECK_TRUE(all(system_of == 1), 'with contact: one system')
        CHECK_TRUE(all(first == [1, 5]), 'of four members')
        CHECK_TRUE(all(members == [1, 2, 3, 4]), 'in rod order')
    end subroutine test_contact_joins_all_rods

end module rs_test_model_coupling

program test_model_coupling
    use rs_test_model_coupling, only: run_all_tests
    use rs_test_assert, only: finish_tests
    implicit none
    call run_all_tests()
    call finish_tests()
end program test_model_coupling
