#include "rs_assert.h"
!> The formulation contract, checked for every formulation the factory knows (issue 22 item 6):
!> on a parsed cantilever scene of each (clamped start, free end with a force and a moment,
!> gravity and a load per length, an initial velocity), at a perturbed state and unknown,
!>   - the assembled CSR step Jacobian equals central differences of the step residual, and
!>     nothing lies outside the preallocated pattern (exact preallocation, STYLE.md);
!>   - the pattern is sorted, in range and square (what PETSc's MatSeqAIJ takes);
!>   - through the system layer (rs_system_rod_system, what every run steps): the state
!>     round-trips through the checkpoint layout (canonical_state, from_canonical) bitwise, and
!>     the record ledger (rs_system_ledger) writes into a record exactly the sums of the terms
!>     the formulation's accept_step gave for the steps since the last record (work, balance,
!>     Newton statistics, smallest step), starts again after it, and round-trips through its
!>     checkpoint entries.
!> ph_director's own test (test_ph_director) covers its variants (p = 1, 2, condensed, Maxwell,
!> actuators, endpoint); this one holds every formulation to the same contract, so that a new
!> one, or a redesign of the contract, is checked the same day.
module rs_test_formulations_conformance
    use rs_core_kinds, only: rk
    use rs_core_error, only: error_t
    use rs_test_assert, only: run_test, assert_true, assert_equal
    use rs_model_capabilities, only: capability_t
    use rs_formulations_registry, only: capability_of
    use rs_formulations_formulation, only: rod_formulation_t, formulation_traits_t
    use rs_formulations_energy_sentinel, only: step_energy_t
    use rs_model_rod_history, only: rod_history_t
    use rs_system_rod_system, only: rod_system_t
    use rs_formulations_factory, only: create_formulation, available_formulations
    use rs_test_random, only: set_random_seed
    use rs_test_formulation_fixture, only: init_cantilever, init_cantilever_system, jacobian_at, &
        central_differences, dense_jacobian, fixture_t_n, fixture_h
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
        call check_system_records(rod, name)
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

    !> The system of the same cantilever: the checkpoint layout and the record ledger. Two
    !> steps from perturbed states are accepted (they need not solve the step: the ledger books
    !> what it is given), with Newton statistics made up here; the record must hold the sums of
    !> the terms `rod`, a separate object of the same formulation, gives for the same steps,
    !> and the balance error of each step recomputed here from its terms. The ledger's
    !> checkpoint entries restore it exactly.
    subroutine check_system_records(rod, name)
        class(rod_formulation_t), intent(inout) :: rod
        character(len=*), intent(in) :: name
        type(rod_system_t) :: system
        type(rod_history_t) :: histories(1)
        type(step_energy_t) :: terms(1, 2)
        type(formulation_traits_t) :: traits
        real(rk), allocatable :: x(:, :), canonical(:), back(:), noise(:), saved(:), again(:)
        real(rk) :: work, balance, h(2), residual(2), expected_residual
        integer :: iterations(2), expected_iterations, k, r
        logical :: ok, balance_ok
        call init_cantilever_system(system, name, 4, ok)
        if (.not. ok) return
        CHECK_EQUAL(system%n_state(), rod%n_state(), name // ': a one-rod system has its rod''s state')
        allocate(x(rod%n_state(), 0:2), canonical(rod%n_state()), back(rod%n_state()), &
            noise(rod%n_state()))
        call rod%initial_state(x(:, 0))
        do k = 1, 2
            call random_number(noise)
            x(:, k) = x(:, k - 1) + 1.0e-3_rk * noise
        end do
        call system%canonical_state(x(:, 2), canonical)
        call system%from_canonical(canonical, back)
        CHECK_TRUE(all(back == x(:, 2)), name // ': state = from_canonical(canonical_state(state))')
        call system%init_history(histories, 10)
        call system%record(histories, 0.0_rk, x(:, 0))
        h = [0.05_rk, 0.03_rk]
        iterations = [3, 0]
        residual = [1.0e-9_rk, 2.0e-11_rk]
        traits = rod%traits()
        work = 0.0_rk
        balance = 0.0_rk
        do k = 1, 2
            call rod%accept_step(0.05_rk * (k - 1), h(k), x(:, k - 1), x(:, k), terms(:, k))
            call system%accept_step(0.05_rk * (k - 1), h(k), x(:, k - 1), x(:, k), &
                iterations(k), residual(k))
            if (.not. terms(1, k)%reported) cycle
            work = work + terms(1, k)%work
            balance = balance + (terms(1, k)%after - terms(1, k)%before - terms(1, k)%work - &
                terms(1, k)%actuator_work + terms(1, k)%dissipated)
        end do
        ! A restart between the steps and the record continues the same sums.
        allocate(saved(system%n_ledger()), again(system%n_ledger()))
        call system%save_ledger(saved)
        call system%restore_ledger(saved)
        call system%save_ledger(again)
        CHECK_TRUE(all(again == saved), name // ': the ledger round-trips through a checkpoint')
        call system%record(histories, 0.1_rk, x(:, 2))
        r = histories(1)%n_stored
        CHECK_EQUAL(r, 2, name // ': two records')
        expected_iterations = merge(3 + 1, 3 + 0, traits%linear_step)
        expected_residual = merge(terms(1, 2)%residual, residual(2), terms(1, 2)%residual >= 0.0_rk)
        CHECK_EQUAL(histories(1)%newton_iterations(r), expected_iterations, name // ': iterations summed')
        CHECK_TRUE(histories(1)%newton_residual(r) == expected_residual, name // ': last residual')
        CHECK_TRUE(histories(1)%dt(r) == minval(h), name // ': smallest step')
        CHECK_TRUE(histories(1)%external_work(r) == work, name // ': work summed')
        ! Summed in the ledger's order; the bound is round-off of the energies summed.
        balance_ok = abs(histories(1)%balance_error(r) - balance) <= &
            1.0e-14_rk * max(1.0_rk, abs(terms(1, 1)%before))
        CHECK_TRUE(balance_ok, name // ': balance = sum of H_1 - H_0 - W - W_act + D')
        ! The next record starts from zero.
        call system%record(histories, 0.2_rk, x(:, 2))
        r = histories(1)%n_stored
        CHECK_EQUAL(histories(1)%newton_iterations(r), 0, name // ': iterations start again')
        CHECK_TRUE(histories(1)%external_work(r) == 0.0_rk, name // ': work starts again')
        CHECK_TRUE(histories(1)%dt(r) == 0.0_rk, name // ': no step since the record')
    end subroutine check_system_records

end module rs_test_formulations_conformance

program test_formulations_conformance
    use rs_test_assert, only: finish_tests
    use rs_test_formulations_conformance, only: run_all_tests
    implicit none
    call run_all_tests()
    call finish_tests()
end program test_formulations_conformance
