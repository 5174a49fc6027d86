#include "rs_assert.h"
!> The formulation contract, checked for every formulation the factory knows (issue 22 item 6):
!> on a parsed cantilever scene of each (clamped start, free end with a force and a moment,
!> gravity and a load per length, an initial velocity), at a perturbed state and unknown,
!>   - the assembled CSR step Jacobian equals central differences of the step residual, and
!>     nothing lies outside the preallocated pattern (exact preallocation, STYLE.md);
!>   - the pattern is sorted, in range and square (what PETSc's MatSeqAIJ takes);
!>   - the state round-trips through the checkpoint layout (canonical_state, from_canonical)
!>     and the internal variables through save_internal and restore_internal, bitwise.
!> ph_director's own test (test_ph_director) covers its variants (p = 1, 2, condensed, Maxwell,
!> actuators, endpoint); this one holds every formulation to the same contract, so that a new
!> one, or a redesign of the contract, is checked the same day.
module rs_test_formulations_conformance
    use rs_core_kinds, only: rk
    use rs_core_error, only: error_t
    use rs_test_assert, only: run_test, assert_true, assert_equal
    use rs_model_capabilities, only: capability_t
    use rs_formulations_registry, only: capability_of
    use rs_formulations_formulation, only: rod_formulation_t
    use rs_formulations_factory, only: create_formulation, available_formulations
    use rs_test_random, only: set_random_seed
    use rs_test_formulation_fixture, only: init_cantilever, jacobian_at, central_differences, &
        dense_jacobian, fixture_t_n, fixture_h
    implicit none
    private

    public :: run_all_tests

contains

    subroutine run_all_tests()
        call run_test('ph_director', test_ph_director)
        call run_test('ph_planar', test_ph_planar)
        call run_test('cl_em_planar', test_cl_em_planar)
        call run_test('se3_pg', test_se3_pg)
        call run_test('se3_strand', test_se3_strand)
        call run_test('every_formulation_listed', test_every_formulation_listed)
    end subroutine run_all_tests

    subroutine test_ph_director()
        call check_formulation('ph_director')
    end subroutine test_ph_director

    subroutine test_ph_planar()
        call check_formulation('ph_planar')
    end subroutine test_ph_planar

    subroutine test_cl_em_planar()
        call check_formulation('cl_em_planar')
    end subroutine test_cl_em_planar

    subroutine test_se3_pg()
        call check_formulation('se3_pg')
    end subroutine test_se3_pg

    subroutine test_se3_strand()
        call check_formulation('se3_strand')
    end subroutine test_se3_strand

    !> The formulations checked above are the ones the factory lists: a new one must be added.
    subroutine test_every_formulation_listed()
        character(len=*), parameter :: checked = 'ph_director, ph_planar, cl_em_planar, se3_pg, se3_strand'
        CHECK_EQUAL(available_formulations(), checked, 'the factory lists the formulations checked')
    end subroutine test_every_formulation_listed

    !> The contract on the fixture's cantilever of 4 elements (rs_test_formulation_fixture).
    subroutine check_formulation(name)
        character(len=*), intent(in) :: name
        class(rod_formulation_t), allocatable :: rod
        type(error_t), allocatable :: err
        type(capability_t) :: row
        logical :: ok
        row = capability_of(name)
        if (.not. row%available) return
        call set_random_seed(20261126, len_trim(name))
        call create_formulation(name, rod, err)
        CHECK_TRUE(.not. allocated(err), name // ': the factory creates it')
        if (allocated(err)) return
        call init_cantilever(rod, name, 4, ok)
        if (.not. ok) return
        call check_pattern(rod, name)
        call check_jacobian(rod, name)
        call check_checkpoint_round_trip(rod, name)
    end subroutine check_formulation

    !> CSR rows sorted, columns in range, one entry per (row, column).
    subroutine check_pattern(rod, name)
        class(rod_formulation_t), intent(in) :: rod
        character(len=*), intent(in) :: name
        integer, allocatable :: row_ptr(:), cols(:)
        integer :: n, row
        logical :: sorted, in_range
        n = rod%n_unknown()
        call rod%jacobian_pattern(row_ptr, cols)
        CHECK_EQUAL(size(row_ptr), n + 1, name // ': one row pointer per unknown, and one more')
        CHECK_EQUAL(row_ptr(1), 0, name // ': zero-based row pointers')
        CHECK_EQUAL(row_ptr(n + 1), size(cols), name // ': the last row pointer is the count')
        sorted = .true.
        in_range = all(cols >= 0 .and. cols < n)
        do row = 1, n
            associate (c => cols(row_ptr(row) + 1:row_ptr(row + 1)))
                if (size(c) > 1) sorted = sorted .and. all(c(2:) > c(:size(c) - 1))
            end associate
        end do
        CHECK_TRUE(sorted, name // ': each row''s columns strictly increasing')
        CHECK_TRUE(in_range, name // ': columns in 0 .. n - 1')
    end subroutine check_pattern

    !> The assembled Jacobian against central differences of the step residual, at the
    !> initial state moved by one predicted step and a random unknown near the prediction.
    !> Central differences with step 1e-6 agree with the Jacobian to 5e-13 .. 1.3e-10 of the
    !> largest entry here (round-off of residuals of size O(1e3) over the step); the bound 1e-8
    !> sits 100 times above the worst of them, and far below a wrong or missing stiffness term:
    !> the weakest against the strongest here is bending against stretching on an element,
    !> (EI / l^2) / EA = (2 / 0.5^2) / 1e3 = 8e-3.
    subroutine check_jacobian(rod, name)
        class(rod_formulation_t), intent(inout) :: rod
        character(len=*), intent(in) :: name
        real(rk), allocatable :: x_n(:), y(:), values(:), dense(:, :), difference(:, :)
        integer, allocatable :: row_ptr(:), cols(:)
        real(rk) :: scale, worst, outside
        integer :: n, j, row
        n = rod%n_unknown()
        call jacobian_at(rod, x_n, y, row_ptr, cols, values)
        dense = dense_jacobian(row_ptr, cols, values)
        difference = central_differences(rod, fixture_t_n, fixture_h, x_n, y, 1.0e-6_rk)
        scale = maxval(abs(difference))
        worst = maxval(abs(difference - dense)) / scale
        outside = 0.0_rk
        do j = 1, n
            do row = 1, n
                if (.not. any(cols(row_ptr(row) + 1:row_ptr(row + 1)) == j - 1)) &
                    outside = max(outside, abs(difference(row, j)))
            end do
        end do
        outside = outside / scale
        write(*, '(a,i0,a,es10.3,a,es10.3)') '  ' // name // ': ', n, ' unknowns, relative ' // &
            'difference ', worst, ', largest entry outside the pattern ', outside
        CHECK_TRUE(worst <= 1.0e-8_rk, name // ': assembled Jacobian = central differences')
        CHECK_TRUE(outside <= 1.0e-9_rk, name // ': no non-zero outside the pattern')
    end subroutine check_jacobian

    !> A checkpoint stores canonical_state and save_internal; a restart reads them back with
    !> from_canonical and restore_internal. Both must be exact (DESIGN.md §7: a restart
    !> continues bitwise).
    subroutine check_checkpoint_round_trip(rod, name)
        class(rod_formulation_t), intent(inout) :: rod
        character(len=*), intent(in) :: name
        real(rk), allocatable :: x(:), canonical(:), back(:), internal(:), internal_back(:), noise(:)
        allocate(x(rod%n_state()), canonical(rod%n_state()), back(rod%n_state()), noise(rod%n_state()))
        call rod%initial_state(x)
        call random_number(noise)
        x = x + 1.0e-3_rk * noise
        call rod%canonical_state(x, canonical)
        call rod%from_canonical(canonical, back)
        CHECK_TRUE(all(back == x), name // ': state = from_canonical(canonical_state(state))')
        allocate(internal(rod%n_internal()), internal_back(rod%n_internal()))
        call rod%save_internal(internal)
        call rod%restore_internal(internal)
        call rod%save_internal(internal_back)
        CHECK_TRUE(all(internal_back == internal), name // ': internal variables round-trip')
    end subroutine check_checkpoint_round_trip

end module rs_test_formulations_conformance

program test_formulations_conformance
    use rs_test_assert, only: finish_tests
    use rs_test_formulations_conformance, only: run_all_tests
    implicit none
    call run_all_tests()
    call finish_tests()
end program test_formulations_conformance
