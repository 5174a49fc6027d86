#include "rs_assert.h"
!> Unit tests of rs_se3_pg's dynamics with the generalized-alpha scheme (&time scheme =
!> 'generalized_alpha'; methods/se3_petrov_galerkin.md §7.3, docs/theory/se3_pg.md), on scenes
!> parsed here (a spinning rod pinned at its start, with dead and follower end loads, a load per
!> length and gravity, so that every term of the step enters):
!> - the assembled step Jacobian equals central differences of the step residual, at a state
!>   with a random history (rho_inf = 0.6 and 0.9), and Newton on the step converges
!>   quadratically;
!> - rho_inf = 1 is the midpoint rule: the same residual, Jacobian and new q, u as scheme =
!>   'midpoint' whatever the history;
!> - the initial history y'_0 is consistent: r' = v and T(psi) psi' = omega per node, and M u'_0 =
!>   f_ext - g_int - f_gyr on the free rows (M, g_int and f_gyr from the element kernels, the
!>   loads written here), u'_0 = 0 on the pin;
!> - the complement update after a step that turns a rotation vector past 1.25 pi carries psi' to
!>   the new chart with the same body rate, Exp(psi_c) = Exp(psi); past pi only, the chart stays.
!> With damping (Kelvin-Voigt times per component, drag and angular drag; docs/theory/se3_pg.md,
!> "Damping"), for the midpoint rule and generalized-alpha:
!> - the Jacobian against central differences, with a random strain-rate history, and Newton's
!>   quadratic convergence; rho_inf = 1 is still the midpoint rule;
!> - the initial history includes the drag: M u'_0 = f_ext - g_int - f_gyr - C u_0, and the
!>   strain-rate history of the rigid initial motion is zero;
!> - the booked dissipation of a midpoint step is the work of the drag forces over the step
!>   (exactly), and that of the Kelvin-Voigt forces up to the element's Petrov-Galerkin defect.
!> A prestrained rod with a support released at a time (issue 26 item 3, docs/theory/
!> prestretched_starts.md): the Jacobian against central differences while the end is held and
!> after its release; while held, the end's rows are y - x_n.
module rs_test_se3_pg
    use rs_core_kinds, only: rk, pi
    use rs_core_error, only: error_t, error_list_t
    use rs_test_assert, only: run_test, assert_true, assert_close, assert_equal
    use rs_test_random, only: set_random_seed
    use rs_test_formulation_fixture, only: central_differences, dense_jacobian
    use rs_model_scene, only: scene_t
    use rs_io_input_file, only: parse_scene
    use rs_formulations_formulation, only: state_valid, step_energy_t
    use rs_math_so3, only: exp_so3, tangent_so3, complement_rotation_vector
    use rs_se3_pg, only: se3_pg_t
    use rs_se3_pg_element, only: se3_element_mass, se3_gyroscopic, se3_internal_force, &
        se3_strains
    implicit none
    private

    public :: run_all_tests

    character(len=*), parameter :: nl = new_line('a')
    !> Damping of the damped scenes: a time per component (EA, GA1, GA2, EI1, EI2, GJ), drag and
    !> angular drag; and the same in se3_pg's K order for the checks written here.
    character(len=*), parameter :: all_damping = ', kelvin_voigt_time = 0.02, 0.03, 0.01, ' // &
        '0.05, 0.04, 0.06, drag = 0.3, angular_drag = 0.2'
    real(rk), parameter :: drag = 0.3_rk, angular_drag = 0.2_rk
    real(rk), parameter :: t_n = 0.3_rk, h = 0.05_rk
    !> The scene's gravity, end force and rod data (used by the initial-history test).
    real(rk), parameter :: gravity(3) = [0.0_rk, 0.0_rk, -9.81_rk], end_force(3) = &
        [0.5_rk, 0.2_rk, -1.0_rk], rho_a = 1.0_rk, inertia(3) = [0.25_rk, 0.1_rk, 0.15_rk]

contains

    subroutine run_all_tests()
        call set_random_seed(20261127, 17)
        call run_test('jacobian_matches_differences', test_jacobian)
        call run_test('newton_converges_quadratically', test_newton)
        call run_test('rho_inf_1_is_the_midpoint_rule', test_midpoint_limit)
        call run_test('initial_history_is_consistent', test_initial_history)
        call run_test('complement_carries_the_history', test_complement_history)
        call run_test('damped_jacobian_matches_differences', test_damped_jacobian)
        call run_test('damped_newton_converges_quadratically', test_damped_newton)
        call run_test('damped_rho_inf_1_is_the_midpoint_rule', test_damped_midpoint_limit)
        call run_test('damped_initial_history_is_consistent', test_damped_initial_history)
        call run_test('dissipation_is_the_damping_work', test_dissipation)
        call run_test('released_support_jacobian', test_released_jacobian)
        call run_test('held_twist', test_held_twist)
        call run_test('stress_only_is_the_stress_stiffness', test_stress_only)
    end subroutine run_all_tests

    !> hold = 'twist' (a ball joint that does not turn about the axis): on a rod along x, the
    !> start's rotation vector psi = 0 loses its first component (T(0)^T e_x = e_x) and keeps
    !> the two bending ones; the step Jacobian equals central differences. On a rod along z
    !> (its frame (d3, d1, d2) = (e_z, e_x, e_y), a turn about (1, 1, 1)) no component of psi
    !> is the twist: init refuses it, naming the end and psi.
    subroutine test_held_twist()
        type(se3_pg_t), allocatable :: rod
        type(scene_t) :: scene
        type(error_list_t) :: errors
        type(error_t), allocatable :: err
        real(rk), allocatable :: x_n(:), y(:)
        character(len=:), allocatable :: text
        real(rk) :: worst
        logical :: ok, held
        text = '&time t_end = 1, dt = 0.05 /' // nl // &
            "&rod name = 'beam', formulation = 'se3_pg', n_elements = 4, length = 2," // nl // &
            '     EA = 1e3, GA1 = 5e2, GA2 = 5e2, EI1 = 2, EI2 = 3, GJ = 1.5,' // nl // &
            '     rhoA = 1, rhoI1 = 0.1, rhoI2 = 0.15 /' // nl // &
            "&bc rod = 'beam', end = 'start', kind = 'held', hold = 'x', 'y', 'z', 'twist' /" // nl // &
            "&load rod = 'beam', where = 'end', moment = 0.3, 0.1, -0.2, force = 0, 0.2, 0.1 /" // nl
        allocate(rod)
        call build(rod, text, ok)
        if (.not. ok) return
        CHECK_EQUAL(rod%n_unknown(), 6 * 5 - 4, 'the start holds x, y, z and one rotation coordinate')
        held = rod%unknown_of(4, 1) == 0 .and. all(rod%unknown_of(5:6, 1) > 0)
        CHECK_TRUE(held, 'the held one is psi_1, the twist of a rod along x')
        call perturbed_step(rod, x_n, y)
        worst = jacobian_mismatch(rod, x_n, y, 'held twist')
        CHECK_TRUE(worst <= 1.0e-8_rk, 'Jacobian with a held twist = central differences')
        deallocate(rod)
        allocate(rod)
        text = '&time t_end = 1, dt = 0.05 /' // nl // &
            "&rod name = 'beam', formulation = 'se3_pg', n_elements = 4, length = 2," // nl // &
            '     EA = 1e3, GA1 = 5e2, GA2 = 5e2, EI1 = 2, EI2 = 3, GJ = 1.5,' // nl // &
            '     rhoA = 1, rhoI1 = 0.1, rhoI2 = 0.15, direction = 0, 0, 1 /' // nl // &
            "&bc rod = 'beam', end = 'start', kind = 'held', hold = 'x', 'y', 'z', 'twist' /" // nl
        call parse_scene(text, 'along_z.nml', scene, errors)
        CHECK_EQUAL(errors%count, 0, 'the scene along z parses: ' // errors%joined())
        if (errors%count > 0) return
        call rod%init(scene, [1], err)
        CHECK_TRUE(allocated(err), 'a rod along z: the twist is no coordinate of psi')
        if (.not. allocated(err)) return
        ok = index(err%message, 'se3_pg holds the twist of the ''start'' end') > 0
        CHECK_TRUE(ok, 'the refusal names the end: ' // err%message)
    end subroutine test_held_twist

    !> stress_only(loaded) (linearized buckling's stress stiffness): statics without loads, so
    !> the step is the internal force alone. At the reference state the residual is the
    !> internal force of the loaded state's stresses and the Jacobian their stress stiffness:
    !> the same as the elastic rod's whose reference strains are shifted so that the reference
    !> carries those stresses, less the unshifted rod's Jacobian (its material stiffness), to
    !> round-off of the latter. stress_only() gives back the elastic rod.
    subroutine test_stress_only()
        type(se3_pg_t) :: rod
        real(rk), allocatable :: x0(:), loaded(:), y(:), y0(:), f_held(:), f_shifted(:), &
            k_held(:), k_shifted(:), k_elastic(:), free(:, :)
        integer, allocatable :: row_ptr(:), cols(:)
        real(rk) :: eps_e(6), worst
        integer :: status, e
        logical :: ok, available
        call build(rod, '&time t_end = 1, dt = 0.05, quasistatic = .true. /' // nl // &
            "&rod name = 'beam', formulation = 'se3_pg', n_elements = 4, length = 2," // nl // &
            '     EA = 1e3, GA1 = 5e2, GA2 = 5e2, EI1 = 2, EI2 = 3, GJ = 1.5,' // nl // &
            '     rhoA = 1, rhoI1 = 0.1, rhoI2 = 0.15 /' // nl // &
            "&bc rod = 'beam', end = 'start', kind = 'clamped' /" // nl, ok)
        if (.not. ok) return
        call perturbed_step(rod, loaded, y)
        allocate(x0(rod%n_state()), y0(rod%n_unknown()), f_held(rod%n_unknown()), &
            f_shifted(rod%n_unknown()))
        call rod%initial_state(x0)
        call rod%predictor(0.0_rk, 1.0_rk, x0, y0)
        call rod%jacobian_pattern(row_ptr, cols)
        allocate(k_held(size(cols)), k_shifted(size(cols)), k_elastic(size(cols)))
        call rod%step_jacobian(0.0_rk, 1.0_rk, x0, y0, k_elastic, status)
        call rod%stress_only(available, loaded)
        CHECK_TRUE(available, 'se3_pg holds its stresses')
        call rod%step_residual(0.0_rk, 1.0_rk, x0, y0, f_held, status)
        call rod%step_jacobian(0.0_rk, 1.0_rk, x0, y0, k_held, status)
        call rod%stress_only(available)
        free = rod%eps_ref
        do e = 1, rod%n_elements
            call se3_strains(rod%element_length(e), loaded(6 * (e - 1) + 1:6 * (e + 1)), eps_e)
            rod%eps_ref(:, e) = 2.0_rk * free(:, e) - eps_e
        end do
        call rod%step_residual(0.0_rk, 1.0_rk, x0, y0, f_shifted, status)
        call rod%step_jacobian(0.0_rk, 1.0_rk, x0, y0, k_shifted, status)
        CHECK_CLOSE(f_held, f_shifted, 1.0e-12_rk, 1.0e-12_rk, 'the internal force of the loaded stresses')
        worst = maxval(abs(k_held - (k_shifted - k_elastic))) / maxval(abs(k_elastic))
        write(*, '(a,es10.3)') '  stress stiffness against the shifted difference: ', worst
        CHECK_TRUE(worst <= 1.0e-13_rk, 'the held stresses'' tangent = their stress stiffness')
        worst = maxval(abs(k_held)) / maxval(abs(k_elastic))
        CHECK_TRUE(worst > 1.0e-6_rk, 'the stress stiffness is not zero')
        rod%eps_ref = free
        call rod%step_jacobian(0.0_rk, 1.0_rk, x0, y0, k_shifted, status)
        CHECK_CLOSE(k_shifted, k_elastic, 0.0_rk, 0.0_rk, 'the elastic rod again')
    end subroutine test_stress_only

    !> A prestrained rod clamped at its start and pinned at its end, released at t = 1 (held in
    !> the step from t_n = 0.3) or at t = 0.1 (free), under gravity, midpoint rule: the step
    !> Jacobian equals central differences at a perturbed state, and while held the rows of the
    !> end's position are y - x_n (rs_formulations_held_rows).
    subroutine test_released_jacobian()
        character(len=3), parameter :: release(2) = ['1.0', '0.1']
        type(se3_pg_t), allocatable :: rod
        real(rk), allocatable :: x_n(:), y(:), values(:), dense(:, :), difference(:, :), f(:)
        integer, allocatable :: row_ptr(:), cols(:)
        real(rk) :: worst, held_value
        integer :: k, i, status, row
        logical :: ok
        do k = 1, 2
            if (allocated(rod)) deallocate(rod)
            allocate(rod)
            call build(rod, '&time t_end = 1, dt = 0.05 /' // nl // &
                "&rod name = 'beam', formulation = 'se3_pg', n_elements = 4, length = 2," // nl // &
                '     EA = 1e3, GA1 = 5e2, GA2 = 5e2, EI1 = 2, EI2 = 3, GJ = 1.5,' // nl // &
                '     rhoA = 1, rhoI1 = 0.1, rhoI2 = 0.15, prestrain = 0.01 /' // nl // &
                "&bc rod = 'beam', end = 'start', kind = 'clamped' /" // nl // &
                "&bc rod = 'beam', end = 'end', kind = 'pinned', release_time = " // &
                release(k) // ' /' // nl // &
                "&load where = 'gravity', acceleration = 0, 0, -9.81 /" // nl, ok)
            if (.not. ok) return
            CHECK_EQUAL(rod%n_unknown(), 6 * 4, 'the released end''s position stays unknown')
            call perturbed_step(rod, x_n, y)
            call rod%jacobian_pattern(row_ptr, cols)
            if (allocated(values)) deallocate(values, f)
            allocate(values(size(cols)), f(size(y)))
            call rod%step_jacobian(t_n, h, x_n, y, values, status)
            CHECK_EQUAL(status, state_valid, 'Jacobian status')
            dense = dense_jacobian(row_ptr, cols, values)
            difference = central_differences(rod, t_n, h, x_n, y, 1.0e-6_rk)
            worst = maxval(abs(difference - dense)) / maxval(abs(difference))
            write(*, '(a,es10.3)') '  release at ' // release(k) // ': relative difference ', worst
            CHECK_TRUE(worst <= 1.0e-8_rk, 'Jacobian with a released support = central differences')
            call rod%step_residual(t_n, h, x_n, y, f, status)
            do i = 1, 3
                row = rod%unknown_of(i, 5)
                held_value = y(row) - x_n(6 * 4 + i)
                if (k == 1) then
                    CHECK_CLOSE(f(row), held_value, 0.0_rk, 0.0_rk, 'held: y - x_n')
                else
                    CHECK_TRUE(abs(f(row) - held_value) > 1e-6_rk, 'released: the equation of motion')
                end if
            end do
        end do
    end subroutine test_released_jacobian

    !> A rod of 4 elements along x, pinned at its start and spinning about (0.4, -0.3, 2) through
    !> it; `scheme` is the &time line's tail; `all_loads` adds follower and dead end moments and a
    !> load per length to gravity and the dead end force.
    !> `damping` (optional) is added to the &rod line (all_damping).
    function scene_text(scheme, all_loads, damping) result(text)
        character(len=*), intent(in) :: scheme
        logical, intent(in) :: all_loads
        character(len=*), intent(in), optional :: damping
        character(len=:), allocatable :: text
        character(len=:), allocatable :: extra
        extra = ''
        if (present(damping)) extra = damping
        text = '&time t_end = 1, dt = 0.05' // scheme // ' /' // nl // &
            "&rod name = 'beam', formulation = 'se3_pg', n_elements = 4, length = 2," // nl // &
            '     EA = 1e3, GA1 = 5e2, GA2 = 5e2, EI1 = 2, EI2 = 3, GJ = 1.5,' // nl // &
            '     rhoA = 1, rhoI1 = 0.1, rhoI2 = 0.15, angular_velocity = 0.4, -0.3, 2.0,' // nl // &
            '     rotation_center = 0, 0, 0' // extra // ' /' // nl // &
            "&bc rod = 'beam', end = 'start', kind = 'pinned' /" // nl // &
            "&load rod = 'beam', where = 'end', force = 0.5, 0.2, -1.0 /" // nl // &
            "&load where = 'gravity', acceleration = 0, 0, -9.81 /" // nl
        if (all_loads) text = text // &
            "&load rod = 'beam', where = 'end', moment = 0.1, 0.4, 0, frame = 'follower'," // nl // &
            '      force = 0, 0.3, 0.2 /' // nl // &
            "&load rod = 'beam', where = 'end', moment = 0, 0.2, -0.1 /" // nl // &
            "&load rod = 'beam', where = 'distributed', force = 0, 0.1, -0.2 /" // nl
    end function scene_text

    subroutine build(rod, text, ok)
        type(se3_pg_t), intent(inout) :: rod
        character(len=*), intent(in) :: text
        logical, intent(out) :: ok
        type(scene_t) :: scene
        type(error_list_t) :: errors
        type(error_t), allocatable :: err
        call parse_scene(text, 'spinning.nml', scene, errors)
        CHECK_EQUAL(errors%count, 0, 'the scene parses: ' // errors%joined())
        ok = errors%count == 0
        if (.not. ok) return
        call rod%init(scene, [1], err)
        CHECK_TRUE(.not. allocated(err), 'init')
        ok = .not. allocated(err)
    end subroutine build

    !> The largest difference of the rod's step Jacobian at (x_n, y) from central differences
    !> (step 1e-6), relative to the largest of these, printed after `label`.
    function jacobian_mismatch(rod, x_n, y, label) result(worst)
        type(se3_pg_t), intent(inout) :: rod
        real(rk), intent(in) :: x_n(:)
        real(rk), intent(inout) :: y(:)
        character(len=*), intent(in) :: label
        real(rk) :: worst
        real(rk), allocatable :: values(:), dense(:, :), difference(:, :)
        integer, allocatable :: row_ptr(:), cols(:)
        integer :: status
        call rod%jacobian_pattern(row_ptr, cols)
        allocate(values(size(cols)))
        call rod%step_jacobian(t_n, h, x_n, y, values, status)
        CHECK_EQUAL(status, state_valid, 'Jacobian status')
        dense = dense_jacobian(row_ptr, cols, values)
        difference = central_differences(rod, t_n, h, x_n, y, 1.0e-6_rk)
        worst = maxval(abs(difference - dense)) / maxval(abs(difference))
        write(*, '(a,es10.3)') '  ' // label // ': relative difference ', worst
    end function jacobian_mismatch

    !> The initial state moved by a random 0.05 in every entry (history included) and the
    !> predicted unknown moved by a random 0.01: no term vanishes by the symmetry of the start.
    subroutine perturbed_step(rod, x_n, y)
        type(se3_pg_t), intent(inout) :: rod
        real(rk), allocatable, intent(out) :: x_n(:), y(:)
        real(rk), allocatable :: noise(:)
        allocate(x_n(rod%n_state()), y(rod%n_unknown()), noise(rod%n_state()))
        call rod%initial_state(x_n)
        call random_number(noise)
        x_n = x_n + 0.05_rk * (noise - 0.5_rk)
        call rod%predictor(t_n, h, x_n, y)
        call random_number(noise)
        y = y + 0.01_rk * (noise(1:size(y)) - 0.5_rk)
    end subroutine perturbed_step

    !> Central differences with step 1e-6 agree to round-off over the step (residuals of size
    !> M / h^2 ~ 1e3 times 1e-16 / 1e-6); the bound 1e-8 is that of the conformance test
    !> (test_formulations_conformance), far below a missing term (the history's share of the
    !> stage velocity's derivative is alpha_f dT[psi'] ~ 1e-2 of the mass term here).
    subroutine test_jacobian()
        call check_jacobian('0.6')
        call check_jacobian('0.9')
    end subroutine test_jacobian

    subroutine check_jacobian(rho_text, damping)
        character(len=*), intent(in) :: rho_text
        character(len=*), intent(in), optional :: damping
        type(se3_pg_t) :: rod
        real(rk), allocatable :: x_n(:), y(:)
        real(rk) :: worst
        logical :: ok
        if (rho_text == 'midpoint') then
            call build(rod, scene_text('', .true., damping), ok)
        else
            call build(rod, scene_text(", scheme = 'generalized_alpha', rho_inf = " // rho_text, &
                .true., damping), ok)
        end if
        if (.not. ok) return
        if (present(damping) .and. rho_text /= 'midpoint') then
            CHECK_EQUAL(rod%n_state(), 24 * 5 + 6 * 4, 'the state: q, u, q'', u'' per node, eps'' per element')
        else if (.not. present(damping)) then
            CHECK_EQUAL(rod%n_state(), 24 * 5, 'the state carries q, u, q'' and u'' per node')
        end if
        call perturbed_step(rod, x_n, y)
        worst = jacobian_mismatch(rod, x_n, y, 'rho_inf = ' // rho_text)
        CHECK_TRUE(worst <= 1.0e-8_rk, 'assembled Jacobian = central differences')
    end subroutine check_jacobian

    !> check_jacobian with all_damping, for the midpoint rule and generalized-alpha (the
    !> random state includes the strain-rate history, so the Kelvin-Voigt stress, the drag's
    !> stage velocities and their derivatives all enter).
    subroutine test_damped_jacobian()
        call check_jacobian('midpoint', all_damping)
        call check_jacobian('0.6', all_damping)
        call check_jacobian('0.9', all_damping)
    end subroutine test_damped_jacobian

    !> Newton with the assembled Jacobian (LAPACK's dense LU) from the predictor:
    !> the residual reaches 1e-9 of its first value within 5 iterations, and the last reduction
    !> above that floor is quadratic, log(r_k / r_{k-1}) / log(r_{k-1} / r_{k-2}) >= 1.8 (the
    !> first iterations are not yet in the quadratic regime: 85 -> 0.28 -> 3e-3 -> 5e-10 here,
    !> the last rate 3.4).
    subroutine test_newton()
        call newton_on_a_step()
    end subroutine test_newton

    !> test_newton with all_damping.
    subroutine test_damped_newton()
        call newton_on_a_step(all_damping)
    end subroutine test_damped_newton

    subroutine newton_on_a_step(damping)
        character(len=*), intent(in), optional :: damping
        type(se3_pg_t) :: rod
        real(rk), allocatable :: x_n(:), y(:), values(:), dense(:, :), f(:)
        integer, allocatable :: row_ptr(:), cols(:), pivots(:)
        real(rk) :: norms(0:8), rate
        integer :: k, status, n, info
        logical :: ok
        call build(rod, scene_text(", scheme = 'generalized_alpha', rho_inf = 0.9", .true., &
            damping), ok)
        if (.not. ok) return
        call perturbed_step(rod, x_n, y)
        call rod%predictor(t_n, h, x_n, y)
        n = rod%n_unknown()
        call rod%jacobian_pattern(row_ptr, cols)
        allocate(values(size(cols)), f(n), pivots(n))
        norms = 0.0_rk
        do k = 0, 8
            call rod%step_residual(t_n, h, x_n, y, f, status)
            norms(k) = norm2(f)
            if (norms(k) <= 1.0e-9_rk * norms(0)) exit
            call rod%step_jacobian(t_n, h, x_n, y, values, status)
            dense = dense_jacobian(row_ptr, cols, values)
            call dgesv(n, 1, dense, n, pivots, f, n, info)
            CHECK_EQUAL(info, 0, 'dense LU of the step Jacobian')
            y = y - f
        end do
        k = min(k, 8)
        write(*, '(a,9es10.2)') '  residual norms:', norms(0:k)
        CHECK_TRUE(k <= 5, 'Newton reaches 1e-9 of the first residual in 5 iterations')
        if (k < 3) return
        rate = log(norms(k) / norms(k - 1)) / log(norms(k - 1) / norms(k - 2))
        write(*, '(a,f6.2)') '  rate of the last iteration: ', rate
        CHECK_TRUE(rate >= 1.8_rk, 'quadratic convergence')
    end subroutine newton_on_a_step

    !> rho_inf = 1 reads no history: residual, Jacobian and X_{n+1}'s q and u equal the
    !> midpoint rule's, to round-off of the reordered arithmetic (1e-12 relative).
    subroutine test_midpoint_limit()
        call compare_with_midpoint()
    end subroutine test_midpoint_limit

    !> test_midpoint_limit with all_damping: the strain-rate history is not read either.
    subroutine test_damped_midpoint_limit()
        call compare_with_midpoint(all_damping)
    end subroutine test_damped_midpoint_limit

    subroutine compare_with_midpoint(damping)
        character(len=*), intent(in), optional :: damping
        type(se3_pg_t) :: alpha, midpoint
        real(rk), allocatable :: x_n(:), y(:), f_a(:), f_m(:), v_a(:), v_m(:), x_a(:), x_m(:)
        integer, allocatable :: row_ptr(:), cols(:)
        integer :: status, n
        logical :: ok
        call build(alpha, scene_text(", scheme = 'generalized_alpha', rho_inf = 1", .true., &
            damping), ok)
        if (.not. ok) return
        call build(midpoint, scene_text('', .true., damping), ok)
        if (.not. ok) return
        call perturbed_step(alpha, x_n, y)
        n = midpoint%n_state()
        allocate(f_a(size(y)), f_m(size(y)), x_a(alpha%n_state()), x_m(n))
        call alpha%step_residual(t_n, h, x_n, y, f_a, status)
        call midpoint%step_residual(t_n, h, x_n(1:n), y, f_m, status)
        CHECK_TRUE(maxval(abs(f_a - f_m)) <= 1.0e-12_rk * maxval(abs(f_m)), 'the same residual')
        call alpha%jacobian_pattern(row_ptr, cols)
        allocate(v_a(size(cols)), v_m(size(cols)))
        call alpha%step_jacobian(t_n, h, x_n, y, v_a, status)
        call midpoint%step_jacobian(t_n, h, x_n(1:n), y, v_m, status)
        CHECK_TRUE(maxval(abs(v_a - v_m)) <= 1.0e-12_rk * maxval(abs(v_m)), 'the same Jacobian')
        call alpha%update(t_n, h, x_n, y, x_a)
        call midpoint%update(t_n, h, x_n(1:n), y, x_m)
        ok = maxval(abs(x_a(1:n) - x_m)) <= 1.0e-12_rk * maxval(abs(x_m))
        CHECK_TRUE(ok, 'the same q_{n+1} and u_{n+1}')
    end subroutine compare_with_midpoint

    !> y'_0 against the equations of motion at t = 0, written here from the kernels: M and
    !> f_gyr per element (se3_element_mass, se3_gyroscopic), g_int (zero in the stress-free
    !> start, se3_internal_force), gravity rho_a g l_e / 2 per node of each element and the
    !> dead end force. Tolerance: round-off of forces of size 10 (1e-12).
    subroutine test_initial_history()
        call check_initial_history(.false.)
    end subroutine test_initial_history

    !> test_initial_history with drag and angular drag, written here as l [[1/3, 1/6], [1/6,
    !> 1/3]] (x) blockdiag(drag 1_3, angular_drag 1_3) per element (the consistent matrix of
    !> linear velocities and test functions), and Kelvin-Voigt: the strain-rate history of the
    !> rigid initial motion is zero (1e-12 of |omega| / l), so no viscous stress enters.
    subroutine test_damped_initial_history()
        call check_initial_history(.true.)
    end subroutine test_damped_initial_history

    subroutine check_initial_history(damped)
        logical, intent(in) :: damped
        type(se3_pg_t) :: rod
        real(rk), allocatable :: x(:)
        real(rk) :: m_e(12, 12), g(12), kg(12, 12), q(6, 5), u(6, 5), rate(6, 5), accel(6, 5)
        real(rk) :: rows(6, 5), inertial(6, 5), l, c_e(12, 12)
        integer :: k, e, n, i
        logical :: ok
        if (damped) then
            call build(rod, scene_text(", scheme = 'generalized_alpha'", .false., all_damping), ok)
        else
            call build(rod, scene_text(", scheme = 'generalized_alpha'", .false.), ok)
        end if
        if (.not. ok) return
        n = 5
        allocate(x(rod%n_state()))
        call rod%initial_state(x)
        q = reshape(x(1:30), [6, n])
        u = reshape(x(31:60), [6, n])
        rate = reshape(x(61:90), [6, n])
        accel = reshape(x(91:120), [6, n])
        do k = 1, n
            CHECK_TRUE(all(abs(rate(1:3, k) - u(1:3, k)) <= 1.0e-14_rk), 'r'' = v')
            ok = all(abs(matmul(tangent_so3(q(4:6, k)), rate(4:6, k)) - u(4:6, k)) <= 1.0e-13_rk)
            CHECK_TRUE(ok, 'T(psi) psi'' = omega')
        end do
        CHECK_TRUE(all(accel(1:3, 1) == 0.0_rk), 'the pin does not accelerate')
        rows = 0.0_rk
        inertial = 0.0_rk
        l = 2.0_rk / 4.0_rk
        do e = 1, 4
            call se3_element_mass(l, rho_a, inertia, m_e)
            inertial(:, e:e + 1) = inertial(:, e:e + 1) + reshape(matmul(m_e, &
                [accel(:, e), accel(:, e + 1)]), [6, 2])
            call se3_gyroscopic(l, inertia, [u(:, e), u(:, e + 1)], g, kg)
            rows(:, e:e + 1) = rows(:, e:e + 1) - reshape(g, [6, 2])
            call se3_internal_force(l, [1.0e3_rk, 5.0e2_rk, 5.0e2_rk, 1.5_rk, 2.0_rk, 3.0_rk], &
                [1.0_rk, 0.0_rk, 0.0_rk, 0.0_rk, 0.0_rk, 0.0_rk], [q(:, e), q(:, e + 1)], g)
            rows(:, e:e + 1) = rows(:, e:e + 1) - reshape(g, [6, 2])
            rows(1:3, e) = rows(1:3, e) + rho_a * gravity * 0.5_rk * l
            rows(1:3, e + 1) = rows(1:3, e + 1) + rho_a * gravity * 0.5_rk * l
            if (damped) then
                c_e = 0.0_rk
                do i = 1, 6
                    c_e(i, i) = l * merge(drag, angular_drag, i <= 3) / 3.0_rk
                    c_e(i + 6, i + 6) = c_e(i, i)
                    c_e(i, i + 6) = c_e(i, i) / 2.0_rk
                    c_e(i + 6, i) = c_e(i, i + 6)
                end do
                rows(:, e:e + 1) = rows(:, e:e + 1) - reshape(matmul(c_e, [u(:, e), &
                    u(:, e + 1)]), [6, 2])
            end if
        end do
        if (damped) then
            ok = maxval(abs(x(24 * n + 1:))) <= 1.0e-12_rk * maxval(abs(u(4:6, :))) / l
            CHECK_TRUE(size(x) == 24 * n + 24 .and. ok, 'the rigid start has no strain rate')
        end if
        rows(1:3, n) = rows(1:3, n) + end_force
        ok = maxval(abs(inertial(4:6, 1) - rows(4:6, 1))) <= 1.0e-12_rk
        CHECK_TRUE(ok, 'M u''_0 = f on the pin''s rotation rows')
        ok = maxval(abs(inertial(:, 2:n) - rows(:, 2:n))) <= 1.0e-12_rk
        CHECK_TRUE(ok, 'M u''_0 = f_ext - g_int - f_gyr on the free rows')
        ok = maxval(abs(u(4:6, :))) > 1.0_rk .and. maxval(abs(rows(4:6, 2:n))) > 1.0e-2_rk
        CHECK_TRUE(ok, 'the test is not trivial: the rod spins and f_gyr acts')
    end subroutine check_initial_history

    !> A midpoint step from the perturbed state, solved by Newton: the dissipation accept_step
    !> books for the drag alone equals the drag's work over the step, sum over the free rows of
    !> (F_damped - F_undamped) . ds with ds = (dr, T(psi_mid) dpsi) per node (the pin's dr is
    !> zero), to round-off (1e-12); for Kelvin-Voigt alone, D_n = h l (d eps / h)^T V (d eps / h)
    !> matches the viscous forces' work to the Petrov-Galerkin defect of the element (their
    !> virtual work is not the variation of the strains, docs/theory/se3_pg.md): within 0.5 % at
    !> these relative rotations of about 0.05 rad (measured 4.5e-4); both are positive.
    subroutine test_dissipation()
        call check_dissipation(', drag = 0.3, angular_drag = 0.2', 1.0e-12_rk)
        call check_dissipation(', kelvin_voigt_time = 0.02, 0.03, 0.01, 0.05, 0.04, 0.06', &
            5.0e-3_rk)
    end subroutine test_dissipation

    subroutine check_dissipation(damping, tolerance)
        character(len=*), intent(in) :: damping
        real(rk), intent(in) :: tolerance
        type(se3_pg_t) :: damped, undamped
        real(rk), allocatable :: x_n(:), y(:), f(:), f_0(:), values(:), dense(:, :), x_1(:), ds(:)
        integer, allocatable :: row_ptr(:), cols(:), pivots(:)
        type(step_energy_t) :: terms(1)
        real(rk) :: q_n(6), q_1(6), work
        integer :: k, i, status, n, info, iteration
        logical :: ok
        call build(damped, scene_text('', .true., damping), ok)
        if (.not. ok) return
        call build(undamped, scene_text('', .true.), ok)
        if (.not. ok) return
        call perturbed_step(damped, x_n, y)
        call damped%predictor(t_n, h, x_n, y)
        n = damped%n_unknown()
        call damped%jacobian_pattern(row_ptr, cols)
        allocate(values(size(cols)), f(n), f_0(n), pivots(n), ds(n), x_1(damped%n_state()))
        do iteration = 1, 8
            call damped%step_residual(t_n, h, x_n, y, f, status)
            call damped%step_jacobian(t_n, h, x_n, y, values, status)
            dense = dense_jacobian(row_ptr, cols, values)
            call dgesv(n, 1, dense, n, pivots, f, n, info)
            y = y - f
        end do
        call damped%step_residual(t_n, h, x_n, y, f, status)
        call undamped%step_residual(t_n, h, x_n, y, f_0, status)
        ds = 0.0_rk
        do k = 1, 5
            q_n = x_n(6 * (k - 1) + 1:6 * k)
            q_1 = q_n
            do i = 1, 6
                if (damped%unknown_of(i, k) > 0) q_1(i) = y(damped%unknown_of(i, k))
            end do
            q_1(4:6) = matmul(tangent_so3(0.5_rk * (q_n(4:6) + q_1(4:6))), q_1(4:6) - q_n(4:6))
            q_1(1:3) = q_1(1:3) - q_n(1:3)
            do i = 1, 6
                if (damped%unknown_of(i, k) > 0) ds(damped%unknown_of(i, k)) = q_1(i)
            end do
        end do
        work = dot_product(f - f_0, ds)
        call damped%update(t_n, h, x_n, y, x_1)
        call damped%accept_step(t_n, h, x_n, x_1, terms)
        write(*, '(a,2es12.4,a,es10.2)') '  ' // damping // ': D, work ', terms(1)%dissipated, &
            work, ', relative difference ', abs(terms(1)%dissipated - work) / work
        CHECK_TRUE(maxval(abs(f)) <= 1.0e-9_rk, 'Newton converged on the step')
        CHECK_TRUE(work > 0.0_rk .and. terms(1)%dissipated > 0.0_rk, 'D > 0')
        ok = abs(terms(1)%dissipated - work) <= tolerance * work
        CHECK_TRUE(ok, 'D = the damping forces'' work')
    end subroutine check_dissipation

    !> The last node's rotation vector at 1.25 pi - 0.05 about its axis, turned to 1.25 pi + 0.05
    !> by the step (generalized-alpha's threshold of the complement, rs_se3_pg complement_angle):
    !> X_{n+1} holds its complement, and psi' the same body rate in the new chart at psi_d = psi
    !> + d psi', d = (1/2 - gamma) h (the time whose rate psi' approximates): T(psi_d,c) psi'_c =
    !> T(psi_d) psi'. Below the threshold (pi + 0.05) the chart stays.
    subroutine test_complement_history()
        type(se3_pg_t) :: rod
        real(rk), allocatable :: x_n(:), y(:), x_1(:)
        real(rk) :: axis(3), psi_1(3), rate_1(3), psi_c(3), rate_c(3), psi_d(3), d
        integer :: at, aq, n
        logical :: ok
        call build(rod, scene_text(", scheme = 'generalized_alpha', rho_inf = 0.9", .true.), ok)
        if (.not. ok) return
        call perturbed_step(rod, x_n, y)
        n = 5
        at = 6 * (n - 1)
        aq = 12 * n + at
        axis = [0.3_rk, -0.5_rk, 0.8_rk] / norm2([0.3_rk, -0.5_rk, 0.8_rk])
        allocate(x_1(rod%n_state()))
        x_n(at + 4:at + 6) = (pi - 0.05_rk) * axis
        y(rod%unknown_of(4:6, n)) = (pi + 0.05_rk) * axis
        call rod%update(t_n, h, x_n, y, x_1)
        ok = all(x_1(at + 4:at + 6) == (pi + 0.05_rk) * axis)
        CHECK_TRUE(ok, 'just beyond pi, the chart stays')
        x_n(at + 4:at + 6) = (1.25_rk * pi - 0.05_rk) * axis
        psi_1 = (1.25_rk * pi + 0.05_rk) * axis + [1.0e-3_rk, -2.0e-3_rk, 0.5e-3_rk]
        y(rod%unknown_of(4:6, n)) = psi_1
        call rod%update(t_n, h, x_n, y, x_1)
        rate_1 = rod%scheme%end_rate(h, x_n(at + 4:at + 6), psi_1, x_n(aq + 4:aq + 6))
        psi_c = x_1(at + 4:at + 6)
        rate_c = x_1(aq + 4:aq + 6)
        ok = all(psi_c == complement_rotation_vector(psi_1)) .and. norm2(psi_c) < pi
        CHECK_TRUE(ok, 'the rotation vector is complemented')
        CHECK_TRUE(maxval(abs(exp_so3(psi_c) - exp_so3(psi_1))) <= 1.0e-14_rk, 'the same rotation')
        d = (0.5_rk - rod%scheme%gamma) * h
        psi_d = psi_1 + d * rate_1
        ok = maxval(abs(matmul(tangent_so3(complement_rotation_vector(psi_d)), rate_c) - &
            matmul(tangent_so3(psi_d), rate_1))) <= 1.0e-12_rk * norm2(rate_1)
        CHECK_TRUE(ok, 'T(psi_d,c) psi''_c = T(psi_d) psi''')
        ok = maxval(abs(rate_c - rate_1)) > 1.0e-3_rk * norm2(rate_1)
        CHECK_TRUE(ok, 'the test is not trivial: psi'' changes with the chart')
    end subroutine test_complement_history

end module rs_test_se3_pg

program test_se3_pg
    use rs_test_assert, only: finish_tests
    use rs_test_se3_pg, only: run_all_tests
    implicit none
    call run_all_tests()
    call finish_tests()
end program test_se3_pg
