#include "rs_assert.h"
!> Unit tests of rs_ph_director, the assembled step problem: the CSR Jacobian equals central
!> finite differences of the assembled residual for a clamped-free rod with end and gravity
!> loads (so the dof map, the scatter and the exact pattern are checked together: every
!> non-zero of the difference quotient lies in the pattern), the unknowns and pattern size
!> follow from the mesh, and one assembled step conserves energy when solved by Newton here.
module rs_test_ph_director
    use rs_core_kinds, only: rk
    use rs_core_error, only: error_t
    use rs_test_assert, only: run_test, assert_true, assert_close, assert_equal
    use rs_test_random, only: set_random_seed
    use rs_model_scene, only: scene_t, rod_input_t, bc_input_t, load_input_t
    use rs_formulations_formulation, only: state_valid
    use rs_ph_director, only: ph_director_t
    implicit none
    private

    public :: run_all_tests

contains

    subroutine run_all_tests()
        call run_test('sizes', test_sizes)
        call run_test('jacobian_matches_differences_p2', test_jacobian_p2)
        call run_test('jacobian_matches_differences_p1', test_jacobian_p1)
        call run_test('condensed_jacobian_matches_differences_p2', test_condensed_jacobian_p2)
        call run_test('condensed_jacobian_matches_differences_p1', test_condensed_jacobian_p1)
        call run_test('newton_step_balances_energy', test_newton_step_energy)
        call run_test('condensed_step_is_the_same_step', test_condensed_same_step)
    end subroutine run_all_tests

    !> A rod along (1, 2, 2)/3 with a clamped start, an end load and gravity.
    function cantilever_scene(n_elements, degree, condensed) result(scene)
        integer, intent(in) :: n_elements, degree
        logical, intent(in) :: condensed
        type(scene_t) :: scene
        type(rod_input_t) :: rod
        type(bc_input_t) :: bc
        type(load_input_t) :: tip, gravity
        rod%name = 'beam'
        rod%formulation = 'ph_director'
        rod%n_elements = n_elements
        rod%degree = degree
        rod%n_gauss = 2
        rod%start = [0.5_rk, -1.0_rk, 0.25_rk]
        rod%direction = [1.0_rk, 2.0_rk, 2.0_rk] / 3.0_rk
        rod%d1 = [-2.0_rk, 1.0_rk, 0.0_rk] / sqrt(5.0_rk)
        rod%length = 2.0_rk
        rod%EA = 1.0e4_rk
        rod%GA1 = 5.0e3_rk
        rod%GA2 = 4.0e3_rk
        rod%EI1 = 80.0_rk
        rod%EI2 = 60.0_rk
        rod%GJ = 50.0_rk
        rod%rhoA = 1.5_rk
        rod%rhoI1 = 0.02_rk
        rod%rhoI2 = 0.03_rk
        bc%rod = 'beam'
        bc%end = 'start'
        bc%kind = 'clamped'
        tip%rod = 'beam'
        tip%where = 'end'
        tip%force = [10.0_rk, -20.0_rk, 5.0_rk]
        tip%moment = [3.0_rk, 1.0_rk, -2.0_rk]
        tip%time_function = 'ramp'
        tip%t_on = 0.0_rk
        tip%t_off = 1.0_rk
        gravity%where = 'gravity'
        gravity%acceleration = [0.0_rk, 0.0_rk, -9.81_rk]
        scene%solver%condense_stresses = condensed
        scene%rods = [rod]
        scene%bcs = [bc]
        scene%loads = [tip, gravity]
    end function cantilever_scene

    subroutine build(n_elements, degree, rod, condensed)
        integer, intent(in) :: n_elements, degree
        type(ph_director_t), intent(inout) :: rod
        logical, intent(in) :: condensed
        type(scene_t) :: scene
        type(error_t), allocatable :: err
        scene = cantilever_scene(n_elements, degree, condensed)
        call rod%init(scene, 1, err)
        CHECK_TRUE(.not. allocated(err), 'init succeeds')
    end subroutine build

    !> 30 unknowns per free node, 6 p per element; the clamped node has none. Condensed: 18
    !> per free node (q and the multipliers).
    subroutine test_sizes()
        type(ph_director_t) :: rod, condensed
        integer, allocatable :: row_ptr(:), cols(:)
        call build(4, 2, rod, .false.)
        CHECK_EQUAL(rod%n_unknown(), 30 * 8 + 12 * 4, 'unknowns of 4 quadratic elements, one end clamped')
        CHECK_EQUAL(rod%n_state(), 30 * 8 + 12 * 4, 'state of 4 quadratic elements')
        call build(4, 2, condensed, .true.)
        CHECK_EQUAL(condensed%n_unknown(), 18 * 8, 'condensed unknowns of 4 quadratic elements')
        CHECK_EQUAL(condensed%n_state(), 30 * 8 + 12 * 4, 'the condensed run keeps the full state')
        call rod%jacobian_pattern(row_ptr, cols)
        CHECK_EQUAL(size(row_ptr), rod%n_unknown() + 1, 'row pointer length')
        CHECK_EQUAL(row_ptr(1), 0, 'zero-based rows')
        CHECK_EQUAL(row_ptr(size(row_ptr)), size(cols), 'last row pointer = nnz')
        CHECK_TRUE(all(cols >= 0 .and. cols < rod%n_unknown()), 'zero-based columns in range')
    end subroutine test_sizes

    !> A state near the reference with random perturbations of every unknown.
    subroutine perturbed_state(rod, x, size_of_noise)
        type(ph_director_t), intent(in) :: rod
        real(rk), intent(out) :: x(:)
        real(rk), intent(in) :: size_of_noise
        real(rk), allocatable :: noise(:)
        call rod%initial_state(x)
        allocate(noise(size(x)))
        call random_number(noise)
        x = x + size_of_noise * (noise - 0.5_rk)
    end subroutine perturbed_state

    subroutine check_jacobian(n_elements, degree, condensed)
        integer, intent(in) :: n_elements, degree
        logical, intent(in) :: condensed
        type(ph_director_t) :: rod
        real(rk), allocatable :: x_n(:), y(:), f_plus(:), f_minus(:), values(:), dense(:, :)
        real(rk), allocatable :: difference(:, :)
        integer, allocatable :: row_ptr(:), cols(:)
        real(rk) :: t_n, h, step, scale, worst, outside
        integer :: n, j, k, row, status
        call set_random_seed(20261121, degree)
        call build(n_elements, degree, rod, condensed)
        n = rod%n_unknown()
        allocate(x_n(rod%n_state()), y(n), f_plus(n), f_minus(n), dense(n, n), difference(n, n))
        call perturbed_state(rod, x_n, 0.1_rk)
        call rod%predictor(0.3_rk, 0.05_rk, x_n, y)
        block
            real(rk) :: noise(n)
            call random_number(noise)
            y = y + 0.1_rk * (noise - 0.5_rk)
        end block
        t_n = 0.3_rk
        h = 0.05_rk
        call rod%jacobian_pattern(row_ptr, cols)
        allocate(values(size(cols)))
        call rod%step_jacobian(t_n, h, x_n, y, values, status)
        CHECK_EQUAL(status, state_valid, 'Jacobian status')
        dense = 0.0_rk
        do row = 1, n
            do k = row_ptr(row) + 1, row_ptr(row + 1)
                dense(row, cols(k) + 1) = values(k)
            end do
        end do
        step = 1.0e-6_rk
        do j = 1, n
            y(j) = y(j) + step
            call rod%step_residual(t_n, h, x_n, y, f_plus, status)
            y(j) = y(j) - 2.0_rk * step
            call rod%step_residual(t_n, h, x_n, y, f_minus, status)
            y(j) = y(j) + step
            difference(:, j) = (f_plus - f_minus) / (2.0_rk * step)
        end do
        scale = maxval(abs(difference))
        worst = maxval(abs(difference - dense)) / scale
        ! Entries of the difference quotient outside the pattern (dense is zero there).
        outside = 0.0_rk
        do row = 1, n
            do j = 1, n
                if (dense(row, j) == 0.0_rk .and. .not. in_pattern(row, j)) &
                    outside = max(outside, abs(difference(row, j)))
            end do
        end do
        write(*, '(a,i0,a,l1,a,es10.3,a,es10.3)') '  p = ', degree, ', condensed ', condensed, &
            ': relative difference ', worst, &
            ', largest entry outside the pattern ', outside / scale
        CHECK_TRUE(worst <= 1.0e-6_rk, 'assembled Jacobian = central differences (relative 1e-6)')
        CHECK_TRUE(outside / scale <= 1.0e-9_rk, 'no non-zero outside the preallocated pattern')
    contains
        logical function in_pattern(i, jj)
            integer, intent(in) :: i, jj
            in_pattern = any(cols(row_ptr(i) + 1 : row_ptr(i + 1)) == jj - 1)
        end function in_pattern
    end subroutine check_jacobian

    subroutine test_jacobian_p2()
        call check_jacobian(3, 2, .false.)
    end subroutine test_jacobian_p2

    subroutine test_jacobian_p1()
        call check_jacobian(4, 1, .false.)
    end subroutine test_jacobian_p1

    subroutine test_condensed_jacobian_p2()
        call check_jacobian(3, 2, .true.)
    end subroutine test_condensed_jacobian_p2

    subroutine test_condensed_jacobian_p1()
        call check_jacobian(4, 1, .true.)
    end subroutine test_condensed_jacobian_p1

    !> Newton on the assembled residual with a dense solve: one loaded step from rest ends with
    !> H_{n+1} - H_n = W_n (methods §5.3 item 1) to a multiple of the final residual.
    subroutine test_newton_step_energy()
        type(ph_director_t) :: rod
        real(rk), allocatable :: x_n(:), x_1(:)
        call newton_step(rod, .false., x_n, x_1)
    end subroutine test_newton_step_energy

    !> The condensed step reaches the same state as the uncondensed one.
    subroutine test_condensed_same_step()
        type(ph_director_t) :: full, condensed
        real(rk), allocatable :: x_n(:), x_full(:), x_condensed(:)
        call newton_step(full, .false., x_n, x_full)
        call newton_step(condensed, .true., x_n, x_condensed)
        CHECK_CLOSE(x_condensed, x_full, 1.0e-10_rk, 0.0_rk, 'same state at t_{n+1}')
    end subroutine test_condensed_same_step

    subroutine newton_step(rod, condensed, x_n, x_1)
        type(ph_director_t), intent(inout) :: rod
        logical, intent(in) :: condensed
        real(rk), allocatable, intent(out) :: x_n(:), x_1(:)
        real(rk), allocatable :: y(:), f(:), values(:), dense(:, :), delta(:)
        integer, allocatable :: row_ptr(:), cols(:), pivots(:)
        real(rk) :: t_n, h, kinetic, strain, energy_n, energy_1
        integer :: n, k, row, it, status, info
        call build(3, 2, rod, condensed)
        n = rod%n_unknown()
        allocate(x_n(rod%n_state()), x_1(rod%n_state()), y(n), f(n), dense(n, n), delta(n), &
            pivots(n))
        call rod%initial_state(x_n)
        call rod%jacobian_pattern(row_ptr, cols)
        allocate(values(size(cols)))
        t_n = 0.5_rk
        h = 0.01_rk
        call rod%predictor(t_n, h, x_n, y)
        do it = 1, 20
            call rod%step_residual(t_n, h, x_n, y, f, status)
            if (norm2(f) < 1.0e-12_rk) exit
            call rod%step_jacobian(t_n, h, x_n, y, values, status)
            dense = 0.0_rk
            do row = 1, n
                do k = row_ptr(row) + 1, row_ptr(row + 1)
                    dense(row, cols(k) + 1) = values(k)
                end do
            end do
            delta = -f
            call dgesv(n, 1, dense, n, pivots, delta, n, info)
            CHECK_EQUAL(info, 0, 'dense LU of the step Jacobian')
            y = y + delta
        end do
        CHECK_TRUE(norm2(f) < 1.0e-12_rk, 'Newton converged')
        call rod%update(t_n, h, x_n, y, x_1)
        call rod%energy(x_n, kinetic, strain)
        energy_n = kinetic + strain
        call rod%energy(x_1, kinetic, strain)
        energy_1 = kinetic + strain
        call rod%accept_step(t_n, h, x_n, x_1, it, norm2(f))
        CHECK_TRUE(energy_1 > 0.0_rk, 'the loads put energy in')
        CHECK_CLOSE(rod%balance_since_record, 0.0_rk, 1.0e-9_rk * energy_1, 0.0_rk, 'H_1 - H_0 - W = 0')
        CHECK_CLOSE(rod%work_since_record, energy_1 - energy_n, 1.0e-9_rk * energy_1, 0.0_rk, 'W = H_1 - H_0')
    end subroutine newton_step

end module rs_test_ph_director

program test_ph_director
    use rs_test_assert, only: finish_tests
    use rs_test_ph_director, only: run_all_tests
    implicit none
    call run_all_tests()
    call finish_tests()
end program test_ph_director
