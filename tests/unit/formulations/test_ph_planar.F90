#include "rs_assert.h"
!> Unit tests of rs_ph_planar's assembled step with damping (issue 26 item 1; docs/theory/
!> ph_planar.md "Damping"), on scenes parsed here: a rod in the xy-plane pinned at its start and
!> swinging about it, with Kelvin-Voigt times (six different ones), drag, angular drag, an end
!> force and gravity, so that every term of the damped step enters:
!> - the assembled step Jacobian equals central differences of the step residual, for PH-EM
!>   (strain unknowns and condensed), cl-EM with 1 and 2 Gauss points and PH-EMi (the element
!>   kernels' viscous terms are checked in test_planar_element; here the drag's C/h and the
!>   assembly);
!> - a translation step of a free rod, q_{n+1} = q_n + dx on every node, is resisted by exactly
!>   the drag of the rod, c L dx / h in sum over the nodes, and by nothing else of the damping
!>   (no strain changes, no turn): the damped residual minus the undamped one.
module rs_test_ph_planar
    use rs_core_kinds, only: rk
    use rs_test_assert, only: run_test, assert_true, assert_close, assert_equal
    use rs_test_random, only: set_random_seed
    use rs_test_formulation_fixture, only: init_from_text, jacobian_at, central_differences, &
        dense_jacobian, fixture_t_n, fixture_h
    use rs_formulations_formulation, only: state_valid
    use rs_ph_planar, only: ph_planar_t
    implicit none
    private

    public :: run_all_tests

    character(len=*), parameter :: nl = new_line('a')
    !> The damping of the scenes: drag c, angular drag c_w (and Kelvin-Voigt times).
    real(rk), parameter :: drag = 0.7_rk, angular_drag = 0.05_rk, length = 2.0_rk
    character(len=*), parameter :: damping = 'kelvin_voigt_time = 0.01, 0.02, 0.03, 0.04, ' // &
        '0.05, 0.06, drag = 0.7, angular_drag = 0.05'

contains

    subroutine run_all_tests()
        call set_random_seed(20261127, 29)
        call run_test('damped_jacobian_matches_differences', test_jacobian)
        call run_test('translation_meets_the_drag', test_translation)
        call run_test('prestrained_released_jacobian', test_released)
    end subroutine run_all_tests

    !> Prestrain and a support released at a time (issue 26 item 3; docs/theory/
    !> prestretched_starts.md): a prestrained rod pinned at its start and clamped at its end,
    !> released at t = 1 (held in the fixture's step from t_n = 0.3) or at t = 0.1 (free), under
    !> gravity, for every scheme: the step Jacobian equals central differences (the kernels'
    !> axial reference and the held unit rows), and the clamped end's three unknowns stay.
    subroutine test_released()
        character(len=*), parameter :: variants(3) = [character(len=80) :: &
            "formulation = 'ph_planar'", "formulation = 'cl_em_planar'", &
            "formulation = 'cl_em_planar', em_variant = 'ph_irreducible', n_gauss = 2"]
        character(len=3), parameter :: release(2) = ['1.0', '0.1']
        type(ph_planar_t), allocatable :: rod
        real(rk), allocatable :: x_n(:), y(:), values(:), dense(:, :), difference(:, :)
        integer, allocatable :: row_ptr(:), cols(:)
        real(rk) :: worst
        logical :: ok
        integer :: v, k
        do v = 1, size(variants)
            do k = 1, 2
                if (allocated(rod)) deallocate(rod)
                allocate(rod)
                call init_from_text(rod, scene_text(trim(variants(v)) // ', prestrain = 0.01', &
                    "&bc rod = 'beam', end = 'start', kind = 'pinned' /" // nl // &
                    "&bc rod = 'beam', end = 'end', kind = 'clamped', release_time = " // &
                    release(k) // ' /' // nl // &
                    "&load where = 'gravity', acceleration = 0, -9.81, 0 /" // nl), &
                    trim(variants(v)), ok)
                if (.not. ok) cycle
                CHECK_EQUAL(rod%n_free, 3 * 5 - 2, 'only the pin eliminates unknowns')
                call jacobian_at(rod, x_n, y, row_ptr, cols, values)
                dense = dense_jacobian(row_ptr, cols, values)
                difference = central_differences(rod, fixture_t_n, fixture_h, x_n, y, 1.0e-6_rk)
                worst = maxval(abs(difference - dense)) / maxval(abs(difference))
                write(*, '(a,es10.3)') '  ' // trim(variants(v)) // ', release at ' // &
                    release(k) // ': relative difference ', worst
                CHECK_TRUE(worst <= 1.0e-8_rk, 'prestrained, released: Jacobian = central differences')
            end do
        end do
    end subroutine test_released

    !> A planar rod of 4 elements along x in the xy-plane; `rod_tail` ends its &rod group, `rest`
    !> follows it (supports, loads, &solver).
    function scene_text(rod_tail, rest) result(text)
        character(len=*), intent(in) :: rod_tail, rest
        character(len=:), allocatable :: text
        text = '&time t_end = 1, dt = 0.05 /' // nl // &
            "&rod name = 'beam', n_elements = 4, length = 2, direction = 1, 0, 0," // nl // &
            '     EA = 1e3, GA1 = 5e2, GA2 = 5e2, EI1 = 2, EI2 = 3, GJ = 1.5,' // nl // &
            '     rhoA = 1, rhoI1 = 0.1, rhoI2 = 0.15, ' // rod_tail // ' /' // nl // rest
    end function scene_text

    !> The damped step Jacobian of each scheme against central differences (step 1e-6) at a
    !> random unknown near the prediction; as in test_formulations_conformance, the bound 1e-8
    !> of the largest entry sits far above round-off and far below a missing term (the drag's
    !> c M1/h is 0.7 * 0.5/3 / 0.05 = 2.3 against entries of 1e3).
    subroutine test_jacobian()
        character(len=*), parameter :: variants(5) = [character(len=80) :: &
            "formulation = 'ph_planar'", "formulation = 'ph_planar'", &
            "formulation = 'cl_em_planar'", "formulation = 'cl_em_planar', n_gauss = 2", &
            "formulation = 'cl_em_planar', em_variant = 'ph_irreducible', n_gauss = 2"]
        character(len=*), parameter :: rest = "&bc rod = 'beam', end = 'start', kind = 'pinned' /" &
            // nl // "&load rod = 'beam', where = 'end', force = 0.5, -1.0, 0 /" // nl // &
            "&load where = 'gravity', acceleration = 0, -9.81, 0 /" // nl
        type(ph_planar_t), allocatable :: rod
        real(rk), allocatable :: x_n(:), y(:), values(:), dense(:, :), difference(:, :)
        integer, allocatable :: row_ptr(:), cols(:)
        character(len=:), allocatable :: solver
        real(rk) :: worst
        logical :: ok
        integer :: v
        do v = 1, size(variants)
            solver = ''
            if (v == 2) solver = '&solver condense_stresses = .true. /' // nl
            ! A new object per scene (init builds on an empty one).
            if (allocated(rod)) deallocate(rod)
            allocate(rod)
            call init_from_text(rod, scene_text(trim(variants(v)) // ', ' // damping // &
                ', angular_velocity = 0, 0, 1.5, rotation_center = 0, 0, 0', rest // solver), &
                trim(variants(v)), ok)
            if (.not. ok) cycle
            call jacobian_at(rod, x_n, y, row_ptr, cols, values)
            dense = dense_jacobian(row_ptr, cols, values)
            difference = central_differences(rod, fixture_t_n, fixture_h, x_n, y, 1.0e-6_rk)
            worst = maxval(abs(difference - dense)) / maxval(abs(difference))
            write(*, '(a,es10.3)') '  ' // trim(variants(v)) // trim(merge(', condensed', &
                '           ', v == 2)) // ': relative difference ', worst
            CHECK_TRUE(worst <= 1.0e-8_rk, trim(variants(v)) // ': damped Jacobian = central differences')
        end do
    end subroutine test_jacobian

    !> A free rod at rest moved by dx = (3e-3, -2e-3) on every node in one step h: the nodal
    !> rows of the damped rod minus those of the undamped one sum to c L dx / h on (x, y) (the
    !> consistent drag of a uniform velocity dx/h), to 0 on theta (no turn: no angular drag; no
    !> strain change: no viscous stress), for each scheme.
    subroutine test_translation()
        character(len=*), parameter :: variants(3) = [character(len=80) :: &
            "formulation = 'ph_planar'", "formulation = 'cl_em_planar'", &
            "formulation = 'cl_em_planar', em_variant = 'ph_irreducible', n_gauss = 2"]
        type(ph_planar_t), allocatable :: damped, undamped
        real(rk), allocatable :: x_n(:), y(:), f_damped(:), f_undamped(:), extra(:)
        real(rk) :: dx(2), expected(3), got(3)
        integer :: v, k, status
        logical :: ok_damped, ok_undamped
        dx = [3.0e-3_rk, -2.0e-3_rk]
        expected = [drag * length * dx / fixture_h, 0.0_rk]
        do v = 1, size(variants)
            if (allocated(damped)) deallocate(damped, undamped)
            allocate(damped, undamped)
            call init_from_text(damped, scene_text(trim(variants(v)) // ', ' // damping, ''), &
                trim(variants(v)), ok_damped)
            call init_from_text(undamped, scene_text(trim(variants(v)), ''), trim(variants(v)), &
                ok_undamped)
            if (.not. (ok_damped .and. ok_undamped)) cycle
            allocate(x_n(damped%n_state()), y(damped%n_unknown()))
            call damped%initial_state(x_n)
            call damped%predictor(fixture_t_n, fixture_h, x_n, y)
            ! A free rod: Y begins with q in node order (x, y, theta per node).
            do k = 1, 5
                y(3 * k - 2:3 * k - 1) = y(3 * k - 2:3 * k - 1) + dx
            end do
            allocate(f_damped(size(y)), f_undamped(size(y)))
            call damped%step_residual(fixture_t_n, fixture_h, x_n, y, f_damped, status)
            CHECK_EQUAL(status, state_valid, 'damped residual')
            call undamped%step_residual(fixture_t_n, fixture_h, x_n, y, f_undamped, status)
            CHECK_EQUAL(status, state_valid, 'undamped residual')
            extra = f_damped - f_undamped
            got = [sum(extra(1:15:3)), sum(extra(2:15:3)), maxval(abs(extra(3:15:3)))]
            CHECK_CLOSE(got, expected, 1.0e-12_rk, 1.0e-12_rk, trim(variants(v)) // ': the drag of a translation, c L dx/h')
            deallocate(x_n, y, f_damped, f_undamped)
        end do
    end subroutine test_translation

end module rs_test_ph_planar

program test_ph_planar
    use rs_test_ph_planar, only: run_all_tests
    use rs_test_assert, only: finish_tests
    implicit none
    call run_all_tests()
    call finish_tests()
end program test_ph_planar
