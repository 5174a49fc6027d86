#include "rs_assert.h"
!> Unit tests of rs_model_rod_history: `init` sizes and zero-fills every array (the Maxwell
!> branch stresses only with n_branches > 0), `free` deallocates, `next_record` hands out
!> 1 .. capacity and then 0, `clear` forgets the records and keeps the capacity, and re-`init`
!> starts over; a large capacity is not allocated up front: the arrays grow with the records
!> and keep them (issue 21 item 17).
module rs_test_model_rod_history
    use rs_core_kinds, only: rk
    use rs_test_assert, only: run_test, assert_true, assert_close, assert_equal
    use rs_test_random, only: set_random_seed
    use rs_model_rod_history, only: rod_history_t
    implicit none
    private

    public :: run_all_tests

contains

    !> Run every test of this file through rs_test_assert.
    subroutine run_all_tests()
        call set_random_seed(2417, 31)
        call run_test('init_sizes', test_init_sizes)
        call run_test('init_sizes_branches', test_init_sizes_branches)
        call run_test('next_record_capacity', test_next_record_capacity)
        call run_test('reinit_starts_over', test_reinit_starts_over)
        call run_test('clear_keeps_capacity', test_clear_keeps_capacity)
        call run_test('grows_with_records', test_grows_with_records)
    end subroutine run_all_tests

    ! Capacity 1000000 (flush_every = 1000000 preallocated 3.2 GB for a 5-step run): room for a
    ! few records at init, 20 records keep their values through the growth, an array the
    ! formulation dropped stays dropped, and the capacity still ends the records.
    subroutine test_grows_with_records()
        type(rod_history_t) :: h
        integer :: r, room
        logical :: kept
        call h%init('long', 'se3_strand', 3, 2, 1000000)
        room = size(h%time)
        CHECK_TRUE(room <= 8, 'room for at most 8 records at init, not the capacity')
        CHECK_TRUE(all(shape(h%directors) == [3, 3, 3, room]), 'directors as time')
        deallocate(h%constraint_residual)
        do r = 1, 20
            CHECK_EQUAL(h%next_record(), r, 'next record')
            h%time(r) = real(r, rk)
            h%position(:, :, r) = real(r, rk)
            h%directors(:, :, :, r) = -real(r, rk)
            h%linear_momentum(:, r) = 2.0_rk * real(r, rk)
            h%newton_iterations(r) = 3 * r
        end do
        CHECK_TRUE(size(h%time) >= 20 .and. size(h%time) <= 64, 'grown to 20 to 64 records')
        CHECK_TRUE(all(h%time(1:20) == [(real(r, rk), r = 1, 20)]), 'times kept')
        CHECK_TRUE(all([(all(h%position(:, :, r) == real(r, rk)), r = 1, 20)]), 'positions kept')
        kept = all([(all(h%directors(:, :, :, r) == -real(r, rk)), r = 1, 20)])
        CHECK_TRUE(kept, 'directors kept')
        kept = all(h%linear_momentum(1, 1:20) == [(2.0_rk * real(r, rk), r = 1, 20)])
        CHECK_TRUE(kept, 'momenta kept')
        CHECK_TRUE(all(h%newton_iterations(1:20) == [(3 * r, r = 1, 20)]), 'iterations kept')
        CHECK_EQUAL(size(h%stress, 3), size(h%time), 'stress grown as time')
        CHECK_TRUE(.not. allocated(h%constraint_residual), 'a dropped array stays dropped')
        call h%init('short', 'se3_strand', 3, 2, 10)
        do r = 1, 10
            CHECK_EQUAL(h%next_record(), r, 'record within the capacity')
        end do
        CHECK_EQUAL(h%next_record(), 0, 'capacity 10 used up')
        CHECK_EQUAL(size(h%time), 10, 'never more room than the capacity')
    end subroutine test_grows_with_records

    subroutine test_init_sizes()
        type(rod_history_t) :: h
        call h%init('beam', 'ph_director', 7, 12, 5)
        CHECK_EQUAL(h%name, 'beam', 'name')
        CHECK_EQUAL(h%formulation, 'ph_director', 'formulation')
        CHECK_EQUAL(h%n_nodes, 7, 'n_nodes')
        CHECK_EQUAL(h%n_stress_points, 12, 'n_stress_points')
        CHECK_EQUAL(h%n_branches, 0, 'no Maxwell branches by default')
        CHECK_EQUAL(h%n_stored, 0, 'nothing stored yet')
        CHECK_EQUAL(size(h%mesh), 7, 'mesh')
        CHECK_EQUAL(size(h%stress_mesh), 12, 'stress_mesh')
        CHECK_EQUAL(size(h%time), 5, 'time')
        CHECK_TRUE(all(shape(h%position) == [3, 7, 5]), 'position shape')
        CHECK_TRUE(all(shape(h%directors) == [3, 3, 7, 5]), 'directors shape')
        CHECK_TRUE(all(shape(h%velocity) == [3, 7, 5]), 'velocity shape')
        CHECK_TRUE(all(shape(h%director_velocity) == [3, 3, 7, 5]), 'director_velocity shape')
        CHECK_TRUE(all(shape(h%stress) == [6, 12, 5]), 'stress shape')
        CHECK_TRUE(all(shape(h%strains) == [6, 12, 5]), 'strains shape')
        CHECK_TRUE(.not. allocated(h%branch_stress), 'no branch_stress without branches')
        CHECK_TRUE(all(shape(h%linear_momentum) == [3, 5]), 'linear_momentum shape')
        CHECK_TRUE(all(shape(h%angular_momentum) == [3, 5]), 'angular_momentum shape')
        CHECK_TRUE(all(shape(h%center_of_mass) == [3, 5]), 'center_of_mass shape')
        CHECK_EQUAL(size(h%kinetic), 5, 'kinetic')
        CHECK_EQUAL(size(h%strain), 5, 'strain')
        CHECK_EQUAL(size(h%total), 5, 'total')
        CHECK_EQUAL(size(h%external_work), 5, 'external_work')
        CHECK_EQUAL(size(h%balance_error), 5, 'balance_error')
        CHECK_EQUAL(size(h%dissipated), 5, 'dissipated')
        CHECK_EQUAL(size(h%actuator_work), 5, 'actuator_work')
        CHECK_EQUAL(size(h%constraint_residual), 5, 'constraint_residual')
        CHECK_EQUAL(size(h%newton_iterations), 5, 'newton_iterations')
        CHECK_EQUAL(size(h%newton_residual), 5, 'newton_residual')
        CHECK_EQUAL(size(h%dt), 5, 'dt')
        CHECK_TRUE(all(h%position == 0.0_rk) .and. all(h%directors == 0.0_rk), 'zero-filled')
        CHECK_TRUE(all(h%stress == 0.0_rk) .and. all(h%newton_iterations == 0), 'zero-filled')
        CHECK_TRUE(all(h%strains == 0.0_rk) .and. all(h%dissipated == 0.0_rk), 'zero-filled')
        CHECK_TRUE(all(h%actuator_work == 0.0_rk), 'zero-filled')
        call h%free()
        CHECK_TRUE(.not. allocated(h%position) .and. .not. allocated(h%name), 'free deallocates')
        CHECK_TRUE(.not. allocated(h%strains), 'free deallocates strains')
        CHECK_TRUE(.not. allocated(h%dissipated), 'free deallocates dissipated')
        CHECK_TRUE(.not. allocated(h%actuator_work), 'free deallocates actuator_work')
        CHECK_EQUAL(h%n_nodes, 0, 'free resets n_nodes')
    end subroutine test_init_sizes

    ! With Maxwell branches: branch_stress (6, points, branches, capacity), zero-filled; `free`
    ! and a re-`init` without branches drop it.
    subroutine test_init_sizes_branches()
        type(rod_history_t) :: h
        call h%init('damped', 'ph_director', 4, 6, 3, n_branches=2)
        CHECK_EQUAL(h%n_branches, 2, 'n_branches')
        CHECK_TRUE(allocated(h%branch_stress), 'branch_stress allocated')
        if (.not. allocated(h%branch_stress)) return
        CHECK_TRUE(all(shape(h%branch_stress) == [6, 6, 2, 3]), 'branch_stress shape')
        CHECK_TRUE(all(h%branch_stress == 0.0_rk), 'branch_stress zero-filled')
        CHECK_TRUE(all(shape(h%strains) == [6, 6, 3]), 'strains shape')
        call h%free()
        CHECK_EQUAL(h%n_branches, 0, 'free resets n_branches')
        CHECK_TRUE(.not. allocated(h%branch_stress), 'free deallocates branch_stress')
        call h%init('damped', 'ph_director', 4, 6, 3, 1)
        CHECK_TRUE(all(shape(h%branch_stress) == [6, 6, 1, 3]), 'positional n_branches')
        call h%init('elastic', 'ph_director', 4, 6, 3)
        CHECK_EQUAL(h%n_branches, 0, 're-init without branches')
        CHECK_TRUE(.not. allocated(h%branch_stress), 're-init without branches drops them')
        call h%init('elastic', 'ph_director', 4, 6, 3, 0)
        CHECK_TRUE(.not. allocated(h%branch_stress), 'n_branches = 0: no branch_stress')
    end subroutine test_init_sizes_branches

    subroutine test_next_record_capacity()
        type(rod_history_t) :: h
        integer :: k
        call h%init('r', 'ph_director', 2, 1, 3)
        do k = 1, 3
            CHECK_EQUAL(h%next_record(), k, 'records 1 .. capacity in order')
            CHECK_EQUAL(h%n_stored, k, 'n_stored counts them')
        end do
        CHECK_EQUAL(h%next_record(), 0, 'full: 0')
        CHECK_EQUAL(h%next_record(), 0, 'still full: 0')
        CHECK_EQUAL(h%n_stored, 3, 'n_stored stays at the capacity')
        call h%init('r', 'ph_director', 2, 1, 0)
        CHECK_EQUAL(h%next_record(), 0, 'capacity 0: full at once')
        CHECK_EQUAL(h%n_stored, 0, 'capacity 0: nothing stored')
    end subroutine test_next_record_capacity

    subroutine test_reinit_starts_over()
        type(rod_history_t) :: h
        integer :: k
        call h%init('first', 'ph_director', 3, 2, 2)
        do k = 1, 2
            CHECK_EQUAL(h%next_record(), k, 'first life')
        end do
        h%position = 5.0_rk
        call h%init('second rod', 'se3_pg', 4, 1, 4)
        CHECK_EQUAL(h%n_stored, 0, 're-init empties')
        CHECK_EQUAL(h%name, 'second rod', 'new name')
        CHECK_EQUAL(h%formulation, 'se3_pg', 'new formulation')
        CHECK_TRUE(all(shape(h%position) == [3, 4, 4]), 'new shape')
        CHECK_TRUE(all(h%position == 0.0_rk), 'new values are zero')
        CHECK_EQUAL(h%next_record(), 1, 'records start at 1 again')
    end subroutine test_reinit_starts_over

    ! After the records went to the file (DESIGN.md §7): the count restarts, the arrays stay.
    subroutine test_clear_keeps_capacity()
        type(rod_history_t) :: h
        integer :: k
        call h%init('arm', 'ph_director', 3, 2, 3)
        do k = 1, 3
            CHECK_EQUAL(h%next_record(), k, 'filled')
        end do
        CHECK_EQUAL(h%next_record(), 0, 'full')
        call h%clear()
        CHECK_EQUAL(h%n_stored, 0, 'clear empties')
        CHECK_TRUE(all(shape(h%position) == [3, 3, 3]), 'capacity kept')
        CHECK_EQUAL(h%next_record(), 1, 'records start at 1 again')
    end subroutine test_clear_keeps_capacity

end module rs_test_model_rod_history

!> Test program: runs the tests of rs_test_model_rod_history; exits non-zero if any failed.
program test_rod_history
    use rs_test_model_rod_history, only: run_all_tests
    use rs_test_assert, only: finish_tests
    implicit none
    call run_all_tests()
    call finish_tests()
end program test_rod_history
