#include "rs_assert.h"
!> Unit tests of rs_ph_director, the assembled step problem: the CSR Jacobian equals central
!> finite differences of the assembled residual for a clamped-free rod with end and gravity
!> loads (so the dof map, the scatter and the exact pattern are checked together: every
!> non-zero of the difference quotient lies in the pattern), the unknowns and pattern size
!> follow from the mesh, and one assembled step conserves energy when solved by Newton here.
!> The same checks run on an inextensible rod with a generalized-Maxwell branch, a tendon and
!> a pressure chamber (energy balance with dissipation and actuator work), and on a
!> quasistatic rod in endpoint-equilibrium mode (no mass terms, the static kernels). What the
!> system layer reads of the rod (issue 22): the node table (its momentum rows are where an end
!> load enters), the continuation anchor of set_step_problem, the largest rotation of
!> state_measures, and the tie wrapper of new_tie (equal to the kernels of rs_ph_director_tie,
!> its gradient to central differences of its value). Damping (docs/theory/ph_director.md
!> "Damping"): the viscosities built from &rod kelvin_voigt_time (its order, none on rigid
!> components), the damped Jacobian (condensed and not, with constraints and a branch) against
!> central differences, and a damped Newton step that balances H_1 - H_0 = W - D with D > 0.
module rs_test_ph_director
    use rs_core_kinds, only: rk
    use rs_core_error, only: error_t
    use rs_test_assert, only: run_test, assert_true, assert_close, assert_equal
    use rs_test_random, only: set_random_seed
    use rs_test_formulation_fixture, only: central_differences
    use rs_model_scene, only: scene_t, rod_input_t, bc_input_t, load_input_t, actuator_input_t
    use rs_formulations_formulation, only: state_valid, formulation_traits_t, step_energy_t, &
        rod_nodes_t, state_measures_t, node_tie_t
    use rs_math_so3, only: exp_so3
    use rs_ph_director, only: ph_director_t
    use rs_ph_director_tie, only: ph_director_tie_t, ph_director_joint_tie, &
        ph_director_plate_tie, ph_director_tie_value, ph_director_tie_gradient, &
        ph_director_tie_hessian
    implicit none
    private

    public :: run_all_tests

    !> Kelvin-Voigt times of the damped scenes, (EA, GA1, GA2, EI1, EI2, GJ).
    real(rk), parameter :: kv_times(6) = [0.01_rk, 0.02_rk, 0.015_rk, 0.03_rk, 0.025_rk, 0.005_rk]
    !> The motion of the driven start of driven_scene at f = 1.
    real(rk), parameter :: drive_displacement(3) = [0.02_rk, -0.03_rk, 0.01_rk]
    real(rk), parameter :: drive_rotation(3) = [0.4_rk, -0.2_rk, 0.3_rk]

contains

    subroutine run_all_tests()
        call run_test('sizes', test_sizes)
        call run_test('jacobian_matches_differences_p2', test_jacobian_p2)
        call run_test('jacobian_matches_differences_p1', test_jacobian_p1)
        call run_test('condensed_jacobian_matches_differences_p2', test_condensed_jacobian_p2)
        call run_test('condensed_jacobian_matches_differences_p1', test_condensed_jacobian_p1)
        call run_test('jacobian_assigns_every_value', test_jacobian_assigns_every_value)
        call run_test('newton_step_balances_energy', test_newton_step_energy)
        call run_test('condensed_step_is_the_same_step', test_condensed_same_step)
        call run_test('sizes_with_branches', test_sizes_with_branches)
        call run_test('jacobian_matches_differences_actuated_p2', test_jacobian_actuated_p2)
        call run_test('jacobian_matches_differences_actuated_p1', test_jacobian_actuated_p1)
        call run_test('jacobian_matches_differences_endpoint_p2', test_jacobian_endpoint_p2)
        call run_test('jacobian_matches_differences_endpoint_p1', test_jacobian_endpoint_p1)
        call run_test('jacobian_matches_differences_quasistatic_step', test_jacobian_quasistatic_step)
        call run_test('newton_step_balances_energy_actuated', test_newton_step_energy_actuated)
        call run_test('newton_endpoint_equilibrium', test_newton_endpoint)
        call run_test('chamber_and_tendon_agree_on_straight_rod', test_chamber_equals_tendon)
        call run_test('node_table', test_node_table)
        call run_test('node_table_condensed', test_node_table_condensed)
        call run_test('continuation_starts_at_its_anchor', test_continuation_anchor)
        call run_test('state_measures', test_state_measures)
        call run_test('tie_wrapper_equals_kernels', test_tie_wrapper)
        call run_test('damped_material', test_damped_material)
        call run_test('jacobian_matches_differences_damped', test_jacobian_damped)
        call run_test('newton_step_balances_energy_damped', test_newton_step_energy_damped)
        call run_test('pinned_sizes', test_pinned_sizes)
        call run_test('jacobian_matches_differences_pinned', test_jacobian_pinned)
        call run_test('newton_step_balances_energy_pinned', test_newton_step_energy_pinned)
        call run_test('jacobian_matches_differences_follower', test_jacobian_follower)
        call run_test('newton_step_balances_energy_follower', test_newton_step_energy_follower)
        call run_test('rigid_subset', test_rigid_subset)
        call run_test('jacobian_matches_differences_driven', test_driven_jacobian)
        call run_test('newton_step_balances_energy_driven', test_driven_newton_step)
        call run_test('jacobian_matches_differences_held', test_held_jacobian)
        call run_test('newton_step_balances_energy_held', test_held_newton_step)
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

    !> The cantilever made inextensible and shear-rigid (constraint 'inextensible': GA1, GA2
    !> and EA rigid, their stresses multipliers) with one generalized-Maxwell branch, a tendon
    !> (ramped tension) and a pressure chamber (constant pressure) along the rod (methods §3.1,
    !> §3.2).
    function actuated_scene(n_elements, degree) result(scene)
        integer, intent(in) :: n_elements, degree
        type(scene_t) :: scene
        type(actuator_input_t) :: tendon, chamber
        scene = cantilever_scene(n_elements, degree, .false.)
        scene%rods(1)%constraint = 'inextensible'
        scene%rods(1)%maxwell_fraction(1) = 0.3_rk
        scene%rods(1)%maxwell_tau_E(1) = 0.02_rk
        scene%rods(1)%maxwell_tau_G(1) = 0.05_rk
        tendon%rod = 'beam'
        tendon%kind = 'tendon'
        tendon%offset = [0.03_rk, -0.02_rk]
        tendon%tension = 40.0_rk
        tendon%time_function = 'ramp'
        tendon%t_on = 0.0_rk
        tendon%t_off = 1.0_rk
        chamber%rod = 'beam'
        chamber%kind = 'pneumatic'
        chamber%offset = [-0.02_rk, 0.025_rk]
        chamber%area = 1.0e-3_rk
        chamber%pressure = 3.0e4_rk
        chamber%time_function = 'constant'
        scene%actuators = [tendon, chamber]
    end function actuated_scene

    !> The cantilever with Kelvin-Voigt times, one per component in &rod's order (EA, GA1, GA2,
    !> EI1, EI2, GJ), drag and angular drag (docs/theory/damping.md).
    function damped_scene(n_elements, degree, condensed) result(scene)
        integer, intent(in) :: n_elements, degree
        logical, intent(in) :: condensed
        type(scene_t) :: scene
        scene = cantilever_scene(n_elements, degree, condensed)
        scene%rods(1)%kelvin_voigt_time = kv_times
        scene%rods(1)%drag = 0.7_rk
        scene%rods(1)%angular_drag = 0.04_rk
    end function damped_scene

    !> The cantilever in a quasistatic run (no mass terms) with a tendon.
    function quasistatic_scene(n_elements, degree) result(scene)
        integer, intent(in) :: n_elements, degree
        type(scene_t) :: scene
        type(actuator_input_t) :: tendon
        scene = cantilever_scene(n_elements, degree, .false.)
        scene%time%quasistatic = .true.
        tendon%rod = 'beam'
        tendon%kind = 'tendon'
        tendon%offset = [-0.01_rk, 0.03_rk]
        tendon%tension = 30.0_rk
        tendon%time_function = 'constant'
        scene%actuators = [tendon]
    end function quasistatic_scene

    subroutine build_scene(scene, rod)
        type(scene_t), intent(in) :: scene
        type(ph_director_t), intent(inout) :: rod
        type(error_t), allocatable :: err
        call rod%init(scene, [1], err)
        CHECK_TRUE(.not. allocated(err), 'init succeeds')
    end subroutine build_scene

    subroutine build(n_elements, degree, rod, condensed)
        integer, intent(in) :: n_elements, degree
        type(ph_director_t), intent(inout) :: rod
        logical, intent(in) :: condensed
        type(scene_t) :: scene
        type(error_t), allocatable :: err
        scene = cantilever_scene(n_elements, degree, condensed)
        call rod%init(scene, [1], err)
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
        character(len=40) :: label
        call set_random_seed(20261121, degree)
        call build(n_elements, degree, rod, condensed)
        write(label, '(a,i0,a,l1)') 'p = ', degree, ', condensed ', condensed
        call check_jacobian_of(rod, trim(label), .false.)
    end subroutine check_jacobian

    !> The CSR Jacobian of a built rod against central differences of its step residual at a
    !> perturbed state and unknown, and exact preallocation (nothing outside the pattern). In
    !> `endpoint` mode the rod solves the endpoint equilibrium at load time 0.8 (DESIGN.md §3).
    !> Columns of the branch stresses of rigid components (components that have no branch,
    !> methods §3.1) are reported on their own, so that an error there does not hide any other.
    subroutine check_jacobian_of(rod, label, endpoint)
        type(ph_director_t), intent(inout) :: rod
        character(len=*), intent(in) :: label
        logical, intent(in) :: endpoint
        real(rk), allocatable :: x_n(:), y(:), values(:), dense(:, :), difference(:, :)
        integer, allocatable :: row_ptr(:), cols(:)
        logical, allocatable :: rigid_branch(:)
        real(rk) :: t_n, h, step, scale, worst, outside, worst_rigid, outside_rigid, entry
        integer :: n, j, k, row, status, e, m
        if (endpoint) call rod%set_step_problem(.true., 0.8_rk)
        n = rod%n_unknown()
        allocate(x_n(rod%n_state()), y(n), dense(n, n))
        call perturbed_state(rod, x_n, 0.1_rk)
        call rod%predictor(0.3_rk, 0.05_rk, x_n, y)
        block
            real(rk) :: noise(n)
            call random_number(noise)
            y = y + 0.1_rk * (noise - 0.5_rk)
        end block
        ! Unknowns that are branch stresses of a rigid component (uncondensed layout).
        allocate(rigid_branch(n), source=.false.)
        if (.not. rod%condensed) then
            m = 6 * rod%degree
            do e = 1, rod%n_elements
                do j = m + 1, size(rod%stress_dof, 1)
                    rigid_branch(rod%stress_dof(j, e)) = &
                        .not. rod%material%branch_active(mod(j - 1, 6) + 1, (j - 1) / m)
                end do
            end do
        end if
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
        difference = central_differences(rod, t_n, h, x_n, y, step)
        scale = maxval(abs(difference))
        worst = 0.0_rk
        worst_rigid = 0.0_rk
        ! Entries of the difference quotient outside the pattern (dense is zero there).
        outside = 0.0_rk
        outside_rigid = 0.0_rk
        do j = 1, n
            do row = 1, n
                entry = abs(difference(row, j) - dense(row, j))
                if (rigid_branch(j)) then
                    worst_rigid = max(worst_rigid, entry)
                else
                    worst = max(worst, entry)
                end if
                if (dense(row, j) == 0.0_rk .and. .not. in_pattern(row, j)) then
                    if (rigid_branch(j)) then
                        outside_rigid = max(outside_rigid, abs(difference(row, j)))
                    else
                        outside = max(outside, abs(difference(row, j)))
                    end if
                end if
            end do
        end do
        worst = worst / scale
        worst_rigid = worst_rigid / scale
        write(*, '(a,es10.3,a,es10.3)') '  ' // label // ': relative difference ', worst, &
            ', largest entry outside the pattern ', outside / scale
        outside = outside / scale
        CHECK_TRUE(worst <= 1.0e-6_rk, label // ': assembled Jacobian = central differences')
        CHECK_TRUE(outside <= 1.0e-9_rk, label // ': no non-zero outside the pattern')
        if (any(rigid_branch)) then
            write(*, '(a,es10.3,a,es10.3)') '  ' // label // &
                ', branch-stress columns of rigid components: relative difference ', worst_rigid, &
                ', largest entry outside the pattern ', outside_rigid / scale
            outside_rigid = outside_rigid / scale
            CHECK_TRUE(worst_rigid <= 1.0e-6_rk, label // ': rigid branch columns = differences')
            CHECK_TRUE(outside_rigid <= 1.0e-9_rk, label // ': rigid branch columns in the pattern')
        end if
        if (endpoint) call rod%set_step_problem(.false., 0.8_rk)
    contains
        logical function in_pattern(i, jj)
            integer, intent(in) :: i, jj
            in_pattern = any(cols(row_ptr(i) + 1 : row_ptr(i + 1)) == jj - 1)
        end function in_pattern
    end subroutine check_jacobian_of

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

    !> With one Maxwell branch every element has 12 p stress unknowns (elastic and branch);
    !> the branch stresses of the rigid components stay unknowns with identity rows.
    subroutine test_sizes_with_branches()
        type(ph_director_t) :: rod
        logical :: live
        call build_scene(actuated_scene(4, 2), rod)
        CHECK_EQUAL(rod%n_unknown(), 30 * 8 + 24 * 4, 'unknowns of 4 quadratic elements')
        CHECK_EQUAL(rod%material%n_branches, 1, 'one Maxwell branch')
        CHECK_TRUE(all(rod%material%compliance(1:3) == 0.0_rk), 'GA1, GA2, EA rigid')
        CHECK_TRUE(all(rod%material%compliance(4:6) > 0.0_rk), 'bending and torsion compliant')
        live = all(rod%material%branch_active(4:6, 1)) .and. &
            .not. any(rod%material%branch_active(1:3, 1))
        CHECK_TRUE(live, 'no branch for rigid components')
        CHECK_EQUAL(size(rod%actuators), 2, 'a tendon and a chamber')
    end subroutine test_sizes_with_branches

    subroutine test_jacobian_actuated_p2()
        type(ph_director_t) :: rod
        call set_random_seed(20261122, 2)
        call build_scene(actuated_scene(3, 2), rod)
        call check_jacobian_of(rod, 'inextensible + Maxwell + tendon + chamber, p = 2', .false.)
    end subroutine test_jacobian_actuated_p2

    subroutine test_jacobian_actuated_p1()
        type(ph_director_t) :: rod
        call set_random_seed(20261122, 1)
        call build_scene(actuated_scene(4, 1), rod)
        call check_jacobian_of(rod, 'inextensible + Maxwell + tendon + chamber, p = 1', .false.)
    end subroutine test_jacobian_actuated_p1

    subroutine test_jacobian_endpoint_p2()
        type(ph_director_t) :: rod
        type(formulation_traits_t) :: traits
        call set_random_seed(20261123, 2)
        call build_scene(quasistatic_scene(3, 2), rod)
        traits = rod%traits()
        CHECK_TRUE(traits%wants_endpoint_solve, 'a quasistatic rod wants the endpoint solve')
        call check_jacobian_of(rod, 'quasistatic endpoint equilibrium, p = 2', .true.)
    end subroutine test_jacobian_endpoint_p2

    subroutine test_jacobian_endpoint_p1()
        type(ph_director_t) :: rod
        type(scene_t) :: scene
        call set_random_seed(20261123, 1)
        ! With the constraints, branch and chamber of the actuated scene as well.
        scene = actuated_scene(4, 1)
        scene%time%quasistatic = .true.
        call build_scene(scene, rod)
        call check_jacobian_of(rod, 'quasistatic endpoint equilibrium, actuated, p = 1', .true.)
    end subroutine test_jacobian_endpoint_p1

    !> The midpoint steps of a quasistatic run (no mass terms): the pattern has no mass entries.
    subroutine test_jacobian_quasistatic_step()
        type(ph_director_t) :: rod
        call set_random_seed(20261124, 2)
        call build_scene(quasistatic_scene(3, 2), rod)
        call check_jacobian_of(rod, 'quasistatic midpoint step, p = 2', .false.)
    end subroutine test_jacobian_quasistatic_step

    !> One Newton step of the actuated, viscoelastic, inextensible rod from rest: the books
    !> balance, H_1 - H_0 = W_ext + W_act - D (methods §5.3 item 1, §3.1 eqs. 59-61, §3.2),
    !> with D > 0 and W_act /= 0.
    subroutine test_newton_step_energy_actuated()
        type(ph_director_t) :: rod
        real(rk), allocatable :: x_n(:), x_1(:)
        type(step_energy_t) :: terms(1)
        real(rk) :: energy_1, kinetic, strain, tol, balance
        call build_scene(actuated_scene(3, 2), rod)
        call newton_solve(rod, 0.5_rk, 0.01_rk, x_n, x_1, terms)
        call rod%energy(x_1, kinetic, strain)
        energy_1 = kinetic + strain
        CHECK_TRUE(terms(1)%reported, 'a time step reports its energy terms')
        CHECK_CLOSE(terms(1)%after, energy_1, 0.0_rk, 0.0_rk, 'H_{n+1} of the terms')
        CHECK_TRUE(terms(1)%dissipated > 0.0_rk, 'the Maxwell branch dissipates')
        CHECK_TRUE(abs(terms(1)%actuator_work) > 1.0e-6_rk * energy_1, 'the actuators work')
        tol = 1.0e-9_rk * energy_1
        balance = step_balance(terms(1))
        CHECK_CLOSE(balance, 0.0_rk, tol, 0.0_rk, 'H_1 - H_0 - W - W_act + D = 0')
    end subroutine test_newton_step_energy_actuated

    !> The balance of a step's terms, as the record ledger books it.
    pure real(rk) function step_balance(step)
        type(step_energy_t), intent(in) :: step
        step_balance = step%after - step%before - step%work - step%actuator_work + step%dissipated
    end function step_balance

    !> Newton converges on the endpoint equilibrium of the quasistatic rod (load time 0.3); the
    !> step books no energy and is not a step of the time grid.
    subroutine test_newton_endpoint()
        type(ph_director_t) :: rod
        real(rk), allocatable :: x_n(:), x_1(:)
        type(step_energy_t) :: terms(1)
        call build_scene(quasistatic_scene(3, 2), rod)
        call rod%set_step_problem(.true., 0.3_rk)
        call newton_solve(rod, 0.0_rk, 0.3_rk, x_n, x_1, terms)
        CHECK_TRUE(.not. terms(1)%reported, 'the endpoint equilibrium reports no energy')
        CHECK_TRUE(.not. terms(1)%grid_step, 'the endpoint equilibrium is not a grid step')
        CHECK_TRUE(terms(1)%residual < 0.0_rk, 'the solver reports the residual')
        call rod%set_step_problem(.false., 0.3_rk)
    end subroutine test_newton_endpoint

    !> On the straight reference a tendon runs along d3, so (methods §3.2) its stress is
    !> T (0, 0, 1, rho^2, -rho^1, 0), that of a chamber with tau = -pressure area = T at the
    !> same offset: the formulation's two constructions (force sign, offset order) give the
    !> same assembled residual at the initial state, and a different one from no actuator.
    subroutine test_chamber_equals_tendon()
        type(ph_director_t) :: with_tendon, with_chamber, bare
        type(scene_t) :: scene
        type(actuator_input_t) :: tendon, chamber
        real(rk), allocatable :: x(:), f_tendon(:), f_chamber(:), f_bare(:)
        real(rk) :: scale
        integer :: status
        scene = cantilever_scene(3, 2, .false.)
        call build_scene(scene, bare)
        tendon%rod = 'beam'
        tendon%kind = 'tendon'
        tendon%offset = [0.03_rk, -0.02_rk]
        tendon%tension = 40.0_rk
        chamber%rod = 'beam'
        chamber%kind = 'pneumatic'
        chamber%offset = tendon%offset
        chamber%area = 2.0e-3_rk
        chamber%pressure = -tendon%tension / chamber%area
        scene%actuators = [tendon]
        call build_scene(scene, with_tendon)
        scene%actuators = [chamber]
        call build_scene(scene, with_chamber)
        allocate(x(bare%n_state()), f_tendon(bare%n_unknown()), f_chamber(bare%n_unknown()), &
            f_bare(bare%n_unknown()))
        call bare%initial_state(x)
        call bare%step_residual(0.0_rk, 0.01_rk, x, x, f_bare, status)
        call with_tendon%step_residual(0.0_rk, 0.01_rk, x, x, f_tendon, status)
        call with_chamber%step_residual(0.0_rk, 0.01_rk, x, x, f_chamber, status)
        scale = maxval(abs(f_tendon - f_bare))
        CHECK_TRUE(scale > 1.0e-3_rk * maxval(abs(f_tendon)), 'the tendon acts')
        scale = 1.0e-12_rk * maxval(abs(f_tendon))
        CHECK_CLOSE(f_chamber, f_tendon, scale, 0.0_rk, 'chamber = tendon on a straight rod')
    end subroutine test_chamber_equals_tendon

    !> The uncondensed Jacobian assigns every stored value (there is no zeroing pass: each
    !> position is assigned by the first element or node that writes it, scatter_t): it does
    !> not depend on what the array held, on a clamped rod of each degree and on one with a
    !> Maxwell branch, rigid components (their branch stresses' identity rows) and actuators.
    subroutine test_jacobian_assigns_every_value()
        call check_assigns_every_value(cantilever_scene(3, 2, .false.), 'p = 2')
        call check_assigns_every_value(cantilever_scene(4, 1, .false.), 'p = 1')
        call check_assigns_every_value(actuated_scene(3, 2), 'actuated, p = 2')
    end subroutine test_jacobian_assigns_every_value

    subroutine check_assigns_every_value(scene, label)
        type(scene_t), intent(in) :: scene
        character(len=*), intent(in) :: label
        type(ph_director_t) :: rod
        real(rk), allocatable :: x_n(:), y(:), from_zero(:), from_stale(:)
        integer, allocatable :: row_ptr(:), cols(:)
        integer :: status
        call set_random_seed(20261126, 7)
        call build_scene(scene, rod)
        allocate(x_n(rod%n_state()), y(rod%n_unknown()))
        call perturbed_state(rod, x_n, 0.1_rk)
        call rod%predictor(0.3_rk, 0.05_rk, x_n, y)
        call rod%jacobian_pattern(row_ptr, cols)
        allocate(from_zero(size(cols)), source=0.0_rk)
        allocate(from_stale(size(cols)), source=huge(1.0_rk))
        call rod%step_jacobian(0.3_rk, 0.05_rk, x_n, y, from_zero, status)
        CHECK_EQUAL(status, state_valid, label // ': Jacobian status')
        call rod%step_jacobian(0.3_rk, 0.05_rk, x_n, y, from_stale, status)
        CHECK_TRUE(all(from_stale == from_zero), label // ': every value assigned')
    end subroutine check_assigns_every_value

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
        type(step_energy_t) :: terms(1)
        real(rk) :: kinetic, strain, energy_n, energy_1, balance, tol
        call build(3, 2, rod, condensed)
        call newton_solve(rod, 0.5_rk, 0.01_rk, x_n, x_1, terms)
        call rod%energy(x_n, kinetic, strain)
        energy_n = kinetic + strain
        call rod%energy(x_1, kinetic, strain)
        energy_1 = kinetic + strain
        CHECK_TRUE(energy_1 > 0.0_rk, 'the loads put energy in')
        CHECK_TRUE(terms(1)%reported .and. terms(1)%grid_step, 'a time step of the grid')
        CHECK_CLOSE(terms(1)%before, energy_n, 0.0_rk, 0.0_rk, 'H_n of the terms')
        CHECK_CLOSE(terms(1)%after, energy_1, 0.0_rk, 0.0_rk, 'H_{n+1} of the terms')
        balance = step_balance(terms(1))
        tol = 1.0e-9_rk * energy_1
        CHECK_CLOSE(balance, 0.0_rk, tol, 0.0_rk, 'H_1 - H_0 - W = 0')
        CHECK_CLOSE(terms(1)%work, energy_1 - energy_n, tol, 0.0_rk, 'W = H_1 - H_0')
    end subroutine newton_step

    !> One step (t_n, h) of a built rod from its initial state, solved by Newton with a dense
    !> LU to |F| < 1e-12 and accepted (with the step's energy terms in `terms`).
    subroutine newton_solve(rod, t_n, h, x_n, x_1, terms)
        type(ph_director_t), intent(inout) :: rod
        real(rk), intent(in) :: t_n, h
        real(rk), allocatable, intent(out) :: x_n(:), x_1(:)
        type(step_energy_t), intent(out) :: terms(1)
        real(rk), allocatable :: y(:), f(:), values(:), dense(:, :), delta(:)
        integer, allocatable :: row_ptr(:), cols(:), pivots(:)
        integer :: n, k, row, it, status, info
        n = rod%n_unknown()
        allocate(x_n(rod%n_state()), x_1(rod%n_state()), y(n), f(n), dense(n, n), delta(n), &
            pivots(n))
        call rod%initial_state(x_n)
        call rod%jacobian_pattern(row_ptr, cols)
        allocate(values(size(cols)))
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
        write(*, '(a,i0,a,es10.3)') '  Newton iterations ', it, ', |F| ', norm2(f)
        CHECK_TRUE(norm2(f) < 1.0e-12_rk, 'Newton converged')
        call rod%update(t_n, h, x_n, y, x_1)
        call rod%accept_step(t_n, h, x_n, x_1, terms)
    end subroutine newton_solve

    !> The node table (rod_nodes_t) of the uncondensed cantilever: the sizes of the mesh, q of
    !> a free node where the state holds it and, in Y = X, at the same place; the clamped node
    !> held at its reference. Its momentum rows are where an end load enters: with the tip load
    !> the residual changes in the tip's momentum rows only, by -h F f(t_mid) in its position
    !> rows (methods §5.2; the ramp is t at the mid time 0.325).
    subroutine test_node_table()
        call check_node_table(.false.)
    end subroutine test_node_table

    !> The same for the condensed rod: q and the momentum rows are the condensed unknowns.
    subroutine test_node_table_condensed()
        call check_node_table(.true.)
    end subroutine test_node_table_condensed

    subroutine check_node_table(condensed)
        logical, intent(in) :: condensed
        type(ph_director_t) :: rod, bare
        type(scene_t) :: scene
        type(rod_nodes_t) :: nodes
        real(rk), allocatable :: x(:), y(:), f(:), f_bare(:), change(:)
        logical, allocatable :: tip_rows(:)
        real(rk) :: expected(3), scale, q(12)
        logical :: elsewhere
        integer :: k, status, tip
        scene = cantilever_scene(3, 2, condensed)
        call build_scene(scene, rod)
        scene%loads = scene%loads(2:2)
        call build_scene(scene, bare)
        nodes = rod%nodes()
        tip = rod%n_nodes
        CHECK_EQUAL(nodes%n_coordinates, 12, 'q = (phi, d1, d2, d3)')
        CHECK_EQUAL(nodes%n_nodes, 7, 'nodes of 3 quadratic elements')
        CHECK_EQUAL(nodes%n_elements, 3, 'elements')
        CHECK_EQUAL(nodes%degree, 2, 'degree')
        CHECK_EQUAL(nodes%n_gauss, 2, 'Gauss points')
        CHECK_CLOSE(nodes%element_length, rod%element_length, 0.0_rk, 0.0_rk, 'element lengths')
        CHECK_TRUE(all(nodes%state(:, 1) == 0), 'clamped start: not in the state')
        CHECK_TRUE(all(nodes%unknown(:, 1) == 0), 'clamped start: not in the unknowns')
        CHECK_TRUE(all(nodes%momentum(:, 1) == 0), 'clamped start: no momentum rows')
        CHECK_CLOSE(nodes%held(:, 1), rod%fixed_q(:, 1), 0.0_rk, 0.0_rk, 'held at the reference')
        allocate(x(rod%n_state()), y(rod%n_unknown()), f(rod%n_unknown()), &
            f_bare(rod%n_unknown()), change(rod%n_unknown()))
        call perturbed_state(rod, x, 0.1_rk)
        call rod%predictor(0.3_rk, 0.05_rk, x, y)
        do k = 2, nodes%n_nodes
            CHECK_TRUE(all(nodes%state(:, k) > 0), 'a free node is in the state')
            ! The predictor moves q on by h v (uncondensed) or keeps it (condensed).
            q = x(nodes%state(:, k))
            if (.not. condensed) q = q + 0.05_rk * x(rod%node_dof(13:24, k))
            CHECK_CLOSE(y(nodes%unknown(:, k)), q, 0.0_rk, 0.0_rk, 'q of Y')
        end do
        call rod%step_residual(0.3_rk, 0.05_rk, x, y, f, status)
        call bare%step_residual(0.3_rk, 0.05_rk, x, y, f_bare, status)
        change = f - f_bare
        allocate(tip_rows(size(f)), source=.false.)
        tip_rows(nodes%momentum(:, tip)) = .true.
        elsewhere = any(pack(change, .not. tip_rows) /= 0.0_rk)
        CHECK_TRUE(.not. elsewhere, 'the load enters no other row')
        expected = -0.05_rk * 0.325_rk * scene_tip_force()
        scale = 1.0e-13_rk * maxval(abs(expected))
        CHECK_CLOSE(change(nodes%momentum(1:3, tip)), expected, scale, 0.0_rk, 'h F f(t_mid)')
    end subroutine check_node_table

    !> The tip force of cantilever_scene.
    pure function scene_tip_force() result(force)
        real(rk) :: force(3)
        force = [10.0_rk, -20.0_rk, 5.0_rk]
    end function scene_tip_force

    !> The continuation anchored at x (set_step_problem with continue_from) starts there: at
    !> the pseudo-time 0 its residual vanishes exactly at Y = x; back to time steps it is the
    !> midpoint residual again.
    subroutine test_continuation_anchor()
        type(ph_director_t) :: rod, reference
        real(rk), allocatable :: x(:), f(:), f_reference(:)
        integer :: status
        call set_random_seed(20261127, 1)
        call build_scene(quasistatic_scene(3, 2), rod)
        call build_scene(quasistatic_scene(3, 2), reference)
        allocate(x(rod%n_state()), f(rod%n_unknown()), f_reference(rod%n_unknown()))
        call perturbed_state(rod, x, 0.1_rk)
        call rod%set_step_problem(.true., 0.6_rk, x)
        CHECK_TRUE(rod%continuing, 'a continuation')
        CHECK_CLOSE(rod%row_scale, 1.0_rk, 0.0_rk, 0.0_rk, 'rows of a step of length 1')
        call rod%step_residual(0.0_rk, 0.0_rk, x, x, f, status)
        CHECK_TRUE(all(f == 0.0_rk), 'R(x) - anchor = 0 at tau = 0')
        call rod%set_step_problem(.false., 0.6_rk)
        CHECK_TRUE(.not. rod%continuing, 'time steps end the continuation')
        call rod%step_residual(0.3_rk, 0.05_rk, x, x, f, status)
        call reference%step_residual(0.3_rk, 0.05_rk, x, x, f_reference, status)
        CHECK_CLOSE(f, f_reference, 0.0_rk, 0.0_rk, 'the midpoint residual again')
    end subroutine test_continuation_anchor

    !> state_measures: no kinetic energy; the largest rotation of the cross-sections is the
    !> angle by which the directors of the free nodes were turned (0.3 rad, one node 0.7).
    subroutine test_state_measures()
        type(ph_director_t) :: rod
        type(state_measures_t) :: measures
        real(rk), allocatable :: x(:), turned(:)
        real(rk) :: r(3, 3), angle
        integer :: k, i
        call build(3, 2, rod, .false.)
        allocate(x(rod%n_state()))
        call rod%initial_state(x)
        turned = x
        do k = 2, rod%n_nodes
            ! About d1: d2 and d3 turn by the whole angle.
            angle = merge(0.7_rk, 0.3_rk, k == 4)
            r = exp_so3(angle * x(rod%node_dof(4:6, k)))
            do i = 1, 3
                turned(rod%node_dof(3 * i + 1:3 * i + 3, k)) = &
                    matmul(r, x(rod%node_dof(3 * i + 1:3 * i + 3, k)))
            end do
        end do
        measures = rod%state_measures(turned)
        CHECK_CLOSE(measures%kinetic_energy, -1.0_rk, 0.0_rk, 0.0_rk, 'no kinetic energy')
        CHECK_CLOSE(measures%largest_rotation, 0.0_rk, 0.0_rk, 0.0_rk, 'no rotation measured')
        measures = rod%state_measures(turned, x)
        CHECK_CLOSE(measures%largest_rotation, 0.7_rk, 1.0e-12_rk, 0.0_rk, 'largest rotation')
    end subroutine test_state_measures

    !> The tie of new_tie (rs_ph_director_node_tie) on two nodes of the cantilever's reference:
    !> a rigid joint, and a plate tie placed in a moved pose, give the value, gradient and
    !> Hessian of the kernels of rs_ph_director_tie bitwise; the gradient equals central
    !> differences of the value (the rows are quadratic: exact up to round-off). A kind that is
    !> not a tie of ph_director gives no tie.
    subroutine test_tie_wrapper()
        type(ph_director_t) :: rod
        class(node_tie_t), allocatable :: tie
        type(ph_director_tie_t) :: kernel
        real(rk) :: q_a(12), q_b(12), axis(3), centre(3), displacement(3), rotation(3)
        real(rk) :: none(0), zero(3)
        call set_random_seed(20261128, 1)
        call build(3, 2, rod, .false.)
        q_a = rod%fixed_q(:, rod%n_nodes)
        q_b = rod%fixed_q(:, 2)
        axis = [0.0_rk, 0.0_rk, 1.0_rk]
        call rod%new_tie('rigid', q_a, q_b, axis, tie)
        CHECK_TRUE(allocated(tie), 'a rigid joint')
        kernel = ph_director_joint_tie('rigid', q_a, q_b, axis)
        call check_tie(tie, kernel, q_a, q_b, 'rigid joint')
        deallocate(tie)
        call rod%new_tie('plate', q_a, none, axis, tie)
        CHECK_TRUE(allocated(tie), 'a plate tie')
        centre = [0.2_rk, -0.1_rk, 0.4_rk]
        displacement = [0.05_rk, 0.02_rk, -0.03_rk]
        rotation = [0.1_rk, -0.2_rk, 0.15_rk]
        zero = 0.0_rk
        kernel = ph_director_plate_tie(q_a, zero, zero, zero)
        call check_tie(tie, kernel, q_a, zero12(), 'plate in its reference pose')
        call tie%place(centre, displacement, rotation)
        kernel = ph_director_plate_tie(q_a, centre, displacement, rotation)
        call check_tie(tie, kernel, q_a, zero12(), 'placed plate')
        deallocate(tie)
        call rod%new_tie('weld', q_a, q_b, axis, tie)
        CHECK_TRUE(.not. allocated(tie), 'no tie of an unknown kind')
    end subroutine test_tie_wrapper

    pure function zero12() result(q)
        real(rk) :: q(12)
        q = 0.0_rk
    end function zero12

    !> The tie against its kernel at z near [q_a; q_b] (q_b = 0 for a one-node tie: the b-part
    !> of z stays zero, as the system passes it).
    subroutine check_tie(tie, kernel, q_a, q_b, label)
        class(node_tie_t), intent(in) :: tie
        type(ph_director_tie_t), intent(in) :: kernel
        real(rk), intent(in) :: q_a(12), q_b(12)
        character(len=*), intent(in) :: label
        real(rk) :: z(24), lambda(6), g(6), gradient(6, 24), hessian(24, 24), noise(24)
        real(rk) :: g_plus(6), g_minus(6), difference(6, 24), step, scale
        logical :: same
        integer :: j, n
        CHECK_EQUAL(tie%n, kernel%n, label // ': rows')
        CHECK_EQUAL(tie%n_coordinates, 12, label // ': coordinates per node')
        n = tie%n
        call random_number(noise)
        z(1:12) = q_a + 0.1_rk * (noise(1:12) - 0.5_rk)
        z(13:24) = 0.0_rk
        if (any(q_b /= 0.0_rk)) z(13:24) = q_b + 0.1_rk * (noise(13:24) - 0.5_rk)
        call random_number(lambda)
        call tie%value(z, g)
        same = all(g(1:n) == ph_director_tie_value(kernel, z))
        CHECK_TRUE(same, label // ': value = kernel')
        call tie%gradient(z, gradient)
        same = all(gradient(1:n, :) == ph_director_tie_gradient(kernel, z))
        CHECK_TRUE(same, label // ': gradient = kernel')
        call tie%force_hessian(z, lambda(1:n), hessian)
        same = all(hessian == ph_director_tie_hessian(kernel, lambda(1:n)))
        CHECK_TRUE(same, label // ': Hessian = kernel')
        step = 1.0e-6_rk
        do j = 1, 24
            z(j) = z(j) + step
            call tie%value(z, g_plus)
            z(j) = z(j) - 2.0_rk * step
            call tie%value(z, g_minus)
            z(j) = z(j) + step
            difference(1:n, j) = (g_plus(1:n) - g_minus(1:n)) / (2.0_rk * step)
        end do
        scale = 1.0e-8_rk * max(1.0_rk, maxval(abs(gradient(1:n, :))))
        CHECK_CLOSE(gradient(1:n, :), difference(1:n, :), scale, 0.0_rk, label // ': differences')
    end subroutine check_tie

    !> The Kelvin-Voigt viscosities V = tau k in the stress order (GA1, GA2, EA, EI1, EI2, GJ)
    !> from &rod's order (EA, GA1, GA2, EI1, EI2, GJ), the drags as given; an inextensible
    !> rod has none on its rigid components (their strain rate is zero), with or without a
    !> Maxwell branch (whose stiffness split leaves V = tau k with the full k).
    subroutine test_damped_material()
        type(ph_director_t) :: rod, constrained
        type(scene_t) :: scene
        real(rk) :: expected(6), zero(3)
        zero = 0.0_rk
        scene = damped_scene(3, 2, .false.)
        call build_scene(scene, rod)
        associate (input => scene%rods(1))
            expected = [kv_times(2) * input%GA1, kv_times(3) * input%GA2, kv_times(1) * input%EA, &
                kv_times(4) * input%EI1, kv_times(5) * input%EI2, kv_times(6) * input%GJ]
        end associate
        CHECK_CLOSE(rod%material%viscosity, expected, 0.0_rk, 1.0e-15_rk, 'V = tau k, stress order')
        CHECK_CLOSE(rod%material%drag, 0.7_rk, 0.0_rk, 0.0_rk, 'drag')
        CHECK_CLOSE(rod%material%angular_drag, 0.04_rk, 0.0_rk, 0.0_rk, 'angular drag')
        CHECK_EQUAL(rod%n_unknown(), 30 * 6 + 12 * 3, 'Kelvin-Voigt adds no unknowns')
        scene = actuated_scene(3, 2)
        scene%rods(1)%kelvin_voigt_time = kv_times
        call build_scene(scene, constrained)
        CHECK_CLOSE(constrained%material%viscosity(1:3), zero, 0.0_rk, 0.0_rk, 'rigid: no viscosity')
        ! Bending and torsion: V = tau k with the full stiffness, not the branch's split.
        CHECK_CLOSE(constrained%material%viscosity(4:6), expected(4:6), 0.0_rk, 1.0e-15_rk, 'V of the full k')
    end subroutine test_damped_material

    !> The damped Jacobian against central differences and its pattern: uncondensed (p = 2, 1),
    !> condensed (the viscous stress adds no unknowns, so condensation stays available), and
    !> with constraints, a Maxwell branch and actuators; every value assigned.
    subroutine test_jacobian_damped()
        type(ph_director_t) :: p2, p1, condensed_p2, condensed_p1, constrained
        type(scene_t) :: scene
        call set_random_seed(20261127, 2)
        call build_scene(damped_scene(3, 2, .false.), p2)
        call check_jacobian_of(p2, 'damped, p = 2', .false.)
        call build_scene(damped_scene(4, 1, .false.), p1)
        call check_jacobian_of(p1, 'damped, p = 1', .false.)
        call build_scene(damped_scene(3, 2, .true.), condensed_p2)
        CHECK_TRUE(condensed_p2%condensed, 'a damped rod can be condensed')
        call check_jacobian_of(condensed_p2, 'damped, p = 2, condensed', .false.)
        call build_scene(damped_scene(4, 1, .true.), condensed_p1)
        call check_jacobian_of(condensed_p1, 'damped, p = 1, condensed', .false.)
        scene = actuated_scene(3, 2)
        scene%rods(1)%kelvin_voigt_time = kv_times
        scene%rods(1)%drag = 0.7_rk
        scene%rods(1)%angular_drag = 0.04_rk
        call build_scene(scene, constrained)
        call check_jacobian_of(constrained, 'damped, inextensible + Maxwell + actuators, p = 2', &
            .false.)
        call check_assigns_every_value(damped_scene(3, 2, .false.), 'damped, p = 2')
    end subroutine test_jacobian_damped

    !> One damped Newton step from rest under the ramped loads: the books balance with the
    !> dissipation, H_1 - H_0 = W - D, D > 0 (docs/theory/ph_director.md "Damping"); the
    !> condensed step reaches the same state and books the same terms.
    subroutine test_newton_step_energy_damped()
        type(ph_director_t) :: rod
        real(rk), allocatable :: x_n(:), x_1(:)
        type(step_energy_t) :: terms(1), terms_c(1)
        real(rk) :: tol
        call build_scene(damped_scene(3, 2, .false.), rod)
        call newton_solve(rod, 0.5_rk, 0.01_rk, x_n, x_1, terms)
        CHECK_TRUE(terms(1)%dissipated > 1.0e-6_rk * terms(1)%after, 'the damping dissipates')
        tol = 1.0e-9_rk * terms(1)%after
        CHECK_CLOSE(step_balance(terms(1)), 0.0_rk, tol, 0.0_rk, 'H_1 - H_0 - W + D = 0')
        call check_condensed_step(damped_scene(3, 2, .true.), x_1, tol, terms_c)
        CHECK_CLOSE(terms_c(1)%dissipated, terms(1)%dissipated, 0.0_rk, 1.0e-8_rk, 'condensed: same D')
    end subroutine test_newton_step_energy_damped

    !> The condensed rod of `scene` takes the same Newton step (0.5, 0.01) from rest as the
    !> uncondensed one that reached x_1, and its books balance within tol.
    subroutine check_condensed_step(scene, x_1, tol, terms, t_n)
        type(scene_t), intent(in) :: scene
        real(rk), intent(in) :: x_1(:), tol
        type(step_energy_t), intent(out) :: terms(1)
        !> The step's start (default 0.5).
        real(rk), intent(in), optional :: t_n
        type(ph_director_t) :: condensed
        real(rk), allocatable :: x_n(:), x_c(:)
        real(rk) :: start
        start = 0.5_rk
        if (present(t_n)) start = t_n
        call build_scene(scene, condensed)
        call newton_solve(condensed, start, 0.01_rk, x_n, x_c, terms)
        CHECK_CLOSE(x_c, x_1, 1.0e-10_rk, 0.0_rk, 'condensed: same state at t_{n+1}')
        CHECK_CLOSE(step_balance(terms(1)), 0.0_rk, tol, 0.0_rk, 'condensed: balance')
    end subroutine check_condensed_step

    ! ---- Supports and loads (issue 26 item 2) ----------------------------------------------

    !> The cantilever with both ends pinned (phi held, directors free): its end load then works
    !> through its moment only.
    function pinned_scene(n_elements, degree, condensed) result(scene)
        integer, intent(in) :: n_elements, degree
        logical, intent(in) :: condensed
        type(scene_t) :: scene
        scene = cantilever_scene(n_elements, degree, condensed)
        scene%bcs(1)%kind = 'pinned'
        scene%bcs = [scene%bcs(1), scene%bcs(1)]
        scene%bcs(2)%end = 'end'
    end function pinned_scene

    !> A pinned node has 6 unknowns fewer than a free one (phi, v_phi), 3 fewer condensed (phi).
    subroutine test_pinned_sizes()
        type(ph_director_t) :: rod, condensed
        call build_scene(pinned_scene(4, 2, .false.), rod)
        CHECK_EQUAL(rod%n_unknown(), 30 * 9 - 2 * 6 + 12 * 4, 'unknowns of 4 quadratic elements, both ends pinned')
        call build_scene(pinned_scene(4, 2, .true.), condensed)
        CHECK_EQUAL(condensed%n_unknown(), 18 * 9 - 2 * 3, 'condensed unknowns, both ends pinned')
    end subroutine test_pinned_sizes

    !> The pinned-pinned rod's Jacobian against central differences, p = 2 and p = 1,
    !> uncondensed and condensed.
    subroutine test_jacobian_pinned()
        type(ph_director_t) :: p2, p1, p2_condensed, p1_condensed
        call set_random_seed(20261126, 2)
        call build_scene(pinned_scene(3, 2, .false.), p2)
        call check_jacobian_of(p2, 'pinned p = 2', .false.)
        call build_scene(pinned_scene(4, 1, .false.), p1)
        call check_jacobian_of(p1, 'pinned p = 1', .false.)
        call build_scene(pinned_scene(3, 2, .true.), p2_condensed)
        call check_jacobian_of(p2_condensed, 'pinned p = 2 condensed', .false.)
        call build_scene(pinned_scene(4, 1, .true.), p1_condensed)
        call check_jacobian_of(p1_condensed, 'pinned p = 1 condensed', .false.)
    end subroutine test_jacobian_pinned

    !> One Newton step of the pinned-pinned rod: the pinned positions stay at the reference, the
    !> end directors turn, the books balance (the held positions do no work), and the
    !> condensed rod takes the same step.
    subroutine test_newton_step_energy_pinned()
        type(ph_director_t) :: rod
        real(rk), allocatable :: x_n(:), x_1(:)
        type(step_energy_t) :: terms(1), terms_c(1)
        real(rk) :: tol
        call build_scene(pinned_scene(3, 2, .false.), rod)
        call newton_solve(rod, 0.5_rk, 0.01_rk, x_n, x_1, terms)
        CHECK_CLOSE(rod%q_1(1:3, 1), rod%fixed_q(1:3, 1), 0.0_rk, 0.0_rk, 'start position held')
        CHECK_CLOSE(rod%q_1(1:3, rod%n_nodes), rod%fixed_q(1:3, rod%n_nodes), 0.0_rk, 0.0_rk, 'end position held')
        CHECK_TRUE(norm2(rod%q_1(4:12, rod%n_nodes) - rod%fixed_q(4:12, rod%n_nodes)) > 1.0e-8_rk, 'end directors turn')
        CHECK_TRUE(abs(terms(1)%work) > 1.0e-8_rk * terms(1)%after, 'the end moment works')
        tol = 1.0e-9_rk * terms(1)%after
        CHECK_CLOSE(step_balance(terms(1)), 0.0_rk, tol, 0.0_rk, 'H_1 - H_0 - W = 0')
        call check_condensed_step(pinned_scene(3, 2, .true.), x_1, tol, terms_c)
    end subroutine test_newton_step_energy_pinned

    !> The cantilever with its tip load and a distributed load as follower loads (components
    !> in the director basis) besides its gravity (dead).
    function follower_scene(n_elements, degree, condensed) result(scene)
        integer, intent(in) :: n_elements, degree
        logical, intent(in) :: condensed
        type(scene_t) :: scene
        type(load_input_t) :: spread
        scene = cantilever_scene(n_elements, degree, condensed)
        scene%loads(1)%frame = 'follower'
        spread%rod = 'beam'
        spread%where = 'distributed'
        spread%frame = 'follower'
        spread%force = [4.0_rk, -3.0_rk, 7.0_rk]
        spread%moment = [-1.5_rk, 2.0_rk, 0.5_rk]
        spread%time_function = 'ramp'
        spread%t_on = 0.0_rk
        spread%t_off = 1.0_rk
        scene%loads = [scene%loads, spread]
    end function follower_scene

    !> Follower end and distributed loads (rs_ph_director_follower): the assembled Jacobian
    !> against central differences, p = 2 and p = 1, condensed, and in the endpoint
    !> equilibrium (the loads at t_{n+1}).
    subroutine test_jacobian_follower()
        type(ph_director_t) :: p2, p1, p2_condensed, p2_endpoint
        type(scene_t) :: scene
        call set_random_seed(20261127, 2)
        call build_scene(follower_scene(3, 2, .false.), p2)
        call check_jacobian_of(p2, 'follower p = 2', .false.)
        call build_scene(follower_scene(4, 1, .false.), p1)
        call check_jacobian_of(p1, 'follower p = 1', .false.)
        call build_scene(follower_scene(3, 2, .true.), p2_condensed)
        call check_jacobian_of(p2_condensed, 'follower p = 2 condensed', .false.)
        scene = follower_scene(3, 2, .false.)
        scene%time%quasistatic = .true.
        call build_scene(scene, p2_endpoint)
        call check_jacobian_of(p2_endpoint, 'follower p = 2 endpoint', .true.)
    end subroutine test_jacobian_follower

    !> One Newton step under the follower loads: the work booked at the midpoint value of the
    !> loads balances the step (H_1 - H_0 - W = 0 to the Newton tolerance), the same as the
    !> condensed rod's; and it differs from the dead loads' work (the loads turned).
    subroutine test_newton_step_energy_follower()
        type(ph_director_t) :: rod
        real(rk), allocatable :: x_n(:), x_1(:)
        type(step_energy_t) :: terms(1), terms_c(1)
        real(rk) :: tol
        call build_scene(follower_scene(3, 2, .false.), rod)
        call newton_solve(rod, 0.5_rk, 0.01_rk, x_n, x_1, terms)
        CHECK_TRUE(abs(terms(1)%work) > 1.0e-6_rk * terms(1)%after, 'the follower loads work')
        tol = 1.0e-9_rk * terms(1)%after
        CHECK_CLOSE(step_balance(terms(1)), 0.0_rk, tol, 0.0_rk, 'H_1 - H_0 - W = 0')
        call check_condensed_step(follower_scene(3, 2, .true.), x_1, tol, terms_c)
    end subroutine test_newton_step_energy_follower

    !> &rod rigid = 'EA', 'GJ' (issue 26 item 2): exactly those compliances are zero, the
    !> Jacobian matches central differences and a Newton step balances its books.
    subroutine test_rigid_subset()
        type(ph_director_t) :: rod, dynamic
        type(scene_t) :: scene
        real(rk), allocatable :: x_n(:), x_1(:)
        type(step_energy_t) :: terms(1)
        logical :: expected(6)
        call set_random_seed(20261128, 2)
        scene = cantilever_scene(3, 2, .false.)
        scene%rods(1)%rigid(1:2) = ['EA', 'GJ']
        call build_scene(scene, rod)
        expected = [.false., .false., .true., .false., .false., .true.]
        CHECK_TRUE(all((rod%material%compliance == 0.0_rk) .eqv. expected), 'N3 and M3 rigid, the rest compliant')
        call check_jacobian_of(rod, 'rigid EA, GJ, p = 2', .false.)
        call build_scene(scene, dynamic)
        call newton_solve(dynamic, 0.5_rk, 0.01_rk, x_n, x_1, terms)
        CHECK_CLOSE(step_balance(terms(1)), 0.0_rk, 1.0e-9_rk * terms(1)%after, 0.0_rk, 'H_1 - H_0 - W = 0')
    end subroutine test_rigid_subset

    ! ---- Driven, sliding and held ends (issue 26 items 2 and 3) ---------------------------

    !> The cantilever with its start driven: moved by f(t) (0.02, -0.03, 0.01) and turned by
    !> f(t) (0.4, -0.2, 0.3), f the ramp t (so q of the driven node is the pose at t).
    function driven_scene(n_elements, degree, condensed) result(scene)
        integer, intent(in) :: n_elements, degree
        logical, intent(in) :: condensed
        type(scene_t) :: scene
        scene = cantilever_scene(n_elements, degree, condensed)
        scene%bcs(1)%kind = 'driven'
        scene%bcs(1)%displacement = drive_displacement
        scene%bcs(1)%rotation = drive_rotation
        scene%bcs(1)%time_function = 'ramp'
        scene%bcs(1)%t_on = 0.0_rk
        scene%bcs(1)%t_off = 1.0_rk
    end function driven_scene

    !> q of the driven start at time t, computed here: the reference moved and turned.
    function driven_q(rod, t) result(q)
        type(ph_director_t), intent(in) :: rod
        real(rk), intent(in) :: t
        real(rk) :: q(12)
        real(rk) :: r(3, 3)
        integer :: i
        r = exp_so3(t * drive_rotation)
        q(1:3) = rod%fixed_q(1:3, 1) + t * drive_displacement
        do i = 1, 3
            q(3 * i + 1:3 * i + 3) = matmul(r, rod%fixed_q(3 * i + 1:3 * i + 3, 1))
        end do
    end function driven_q

    !> A driven node has no unknowns (its q prescribed, its velocities state only, 12 after the
    !> unknowns). The Jacobian against central differences: p = 2, p = 1, condensed, and in the
    !> endpoint equilibrium of a quasistatic run.
    subroutine test_driven_jacobian()
        type(ph_director_t) :: p2, p1, p2_condensed, p2_endpoint
        type(scene_t) :: scene
        call set_random_seed(20261201, 2)
        call build_scene(driven_scene(4, 2, .false.), p2)
        CHECK_EQUAL(p2%n_unknown(), 30 * 8 + 12 * 4, 'unknowns with a driven start')
        CHECK_EQUAL(p2%n_state(), 30 * 8 + 12 * 4 + 12, 'state with a driven start')
        call check_jacobian_of(p2, 'driven p = 2', .false.)
        call build_scene(driven_scene(4, 1, .false.), p1)
        call check_jacobian_of(p1, 'driven p = 1', .false.)
        call build_scene(driven_scene(3, 2, .true.), p2_condensed)
        CHECK_EQUAL(p2_condensed%n_unknown(), 18 * 6, 'condensed unknowns with a driven start')
        call check_jacobian_of(p2_condensed, 'driven p = 2 condensed', .false.)
        scene = driven_scene(3, 2, .false.)
        scene%time%quasistatic = .true.
        call build_scene(scene, p2_endpoint)
        call check_jacobian_of(p2_endpoint, 'driven p = 2 endpoint', .true.)
    end subroutine test_driven_jacobian

    !> One Newton step from the reference at t = 0 (where the state is consistent: the drive
    !> starts at the reference pose) with the driven start: its q is the pose at h computed here, its
    !> velocity the one the midpoint rule implies (v_1 = 2 (q_1 - q_n)/h - v_n), the drive
    !> works, and the books balance with the drive's work (H_1 - H_0 - W = 0); the condensed
    !> rod takes the same step.
    subroutine test_driven_newton_step()
        type(ph_director_t) :: rod
        real(rk), allocatable :: x_n(:), x_1(:), x_dead(:)
        type(step_energy_t) :: terms(1), terms_c(1), terms_dead(1)
        type(ph_director_t) :: loads_only
        type(scene_t) :: scene
        real(rk) :: tol, q_n(12), q_1(12), v_1(12)
        call build_scene(driven_scene(3, 2, .false.), rod)
        call newton_solve(rod, 0.0_rk, 0.01_rk, x_n, x_1, terms)
        q_n = driven_q(rod, 0.0_rk)
        q_1 = driven_q(rod, 0.01_rk)
        CHECK_CLOSE(rod%q_1(:, 1), q_1, 1.0e-15_rk, 0.0_rk, 'driven q = the pose at t_n + h')
        v_1 = x_1(rod%drive_state(1):rod%drive_state(1) + 11)
        CHECK_CLOSE(v_1, 2.0_rk * (q_1 - q_n) / 0.01_rk, 1.0e-13_rk, 0.0_rk, 'driven v_1 = 2 dq/h - v_n')
        tol = 1.0e-9_rk * terms(1)%after
        write(*, '(a,es10.3,a,es10.3)') '  driven step: |balance| / H_1 ', &
            abs(step_balance(terms(1))) / terms(1)%after, ', W ', terms(1)%work
        CHECK_CLOSE(step_balance(terms(1)), 0.0_rk, tol, 0.0_rk, 'H_1 - H_0 - W = 0 with the drive')
        ! The same step with the start clamped books the loads' work alone: the drive's share
        ! is what differs, and it is not small.
        scene = cantilever_scene(3, 2, .false.)
        call build_scene(scene, loads_only)
        call newton_solve(loads_only, 0.0_rk, 0.01_rk, x_n, x_dead, terms_dead)
        CHECK_TRUE(abs(terms(1)%work - terms_dead(1)%work) > 1.0e-3_rk * abs(terms(1)%work), 'the drive works')
        call check_condensed_step(driven_scene(3, 2, .true.), x_1, tol, terms_c, 0.0_rk)
        CHECK_CLOSE(terms_c(1)%work, terms(1)%work, 0.0_rk, 1.0e-8_rk, 'condensed: same work')
    end subroutine test_driven_newton_step

    !> The cantilever whose end is held: hold = 'y', 'rotation' (x and z free), or sliding
    !> along z (x, y and the rotation held).
    function held_scene(n_elements, degree, condensed, kind) result(scene)
        integer, intent(in) :: n_elements, degree
        logical, intent(in) :: condensed
        character(len=*), intent(in) :: kind
        type(scene_t) :: scene
        scene = cantilever_scene(n_elements, degree, condensed)
        scene%bcs = [scene%bcs(1), scene%bcs(1)]
        scene%bcs(2)%end = 'end'
        scene%bcs(2)%kind = kind
        if (kind == 'held') then
            scene%bcs(2)%hold(1:2) = ['y       ', 'rotation']
        else
            scene%bcs(2)%axis = [0.0_rk, 0.0_rk, 1.0_rk]
        end if
    end function held_scene

    !> A held end keeps the dofs of its free coordinates: hold = 'y', 'rotation' leaves x, z and
    !> their velocities (4), no directors, no multipliers; sliding along z leaves z (2).
    !> Jacobians against central differences, uncondensed and condensed; a slide along an
    !> oblique axis is refused, naming the rod and the axis.
    subroutine test_held_jacobian()
        type(ph_director_t) :: held, held_condensed, sliding, oblique
        type(scene_t) :: scene
        type(error_t), allocatable :: err
        character(len=:), allocatable :: message
        character(len=*), parameter :: expected_refusal = 'rod ''beam'': ph_director holds ' // &
            'the coordinates of phi, so a sliding end''s axis must be a coordinate axis (x, y ' // &
            'or z); axis = (1.0, 1.0, 0.0)'
        call set_random_seed(20261202, 2)
        call build_scene(held_scene(3, 2, .false., 'held'), held)
        CHECK_EQUAL(held%n_unknown(), 30 * 5 + 4 + 12 * 3, 'unknowns with an end held in y and rotation')
        call check_jacobian_of(held, 'held y, rotation, p = 2', .false.)
        call build_scene(held_scene(3, 2, .true., 'held'), held_condensed)
        CHECK_EQUAL(held_condensed%n_unknown(), 18 * 5 + 2, 'condensed unknowns, held end')
        call check_jacobian_of(held_condensed, 'held y, rotation, p = 2 condensed', .false.)
        call build_scene(held_scene(4, 1, .false., 'sliding'), sliding)
        CHECK_EQUAL(sliding%n_unknown(), 30 * 3 + 2 + 6 * 4, 'unknowns with an end sliding along z')
        call check_jacobian_of(sliding, 'sliding along z, p = 1', .false.)
        scene = held_scene(3, 2, .false., 'sliding')
        scene%bcs(2)%axis = [1.0_rk, 1.0_rk, 0.0_rk]
        call oblique%init(scene, [1], err)
        CHECK_TRUE(allocated(err), 'an oblique slide is refused')
        if (allocated(err)) then
            message = err%message
            CHECK_EQUAL(message, expected_refusal, 'the refusal names the rod and the axis')
        end if
    end subroutine test_held_jacobian

    !> One Newton step with the end held in y and rotation: y and the directors stay at the
    !> reference exactly, x and z move, the books balance (held coordinates do no work), and the
    !> condensed rod takes the same step.
    subroutine test_held_newton_step()
        type(ph_director_t) :: rod
        real(rk), allocatable :: x_n(:), x_1(:)
        type(step_energy_t) :: terms(1), terms_c(1)
        real(rk) :: tol
        integer :: tip
        call build_scene(held_scene(3, 2, .false., 'held'), rod)
        call newton_solve(rod, 0.5_rk, 0.01_rk, x_n, x_1, terms)
        tip = rod%n_nodes
        CHECK_CLOSE(rod%q_1(2, tip), rod%fixed_q(2, tip), 0.0_rk, 0.0_rk, 'end y held')
        CHECK_CLOSE(rod%q_1(4:12, tip), rod%fixed_q(4:12, tip), 0.0_rk, 0.0_rk, 'end directors held')
        CHECK_TRUE(abs(rod%q_1(1, tip) - rod%fixed_q(1, tip)) > 1.0e-9_rk, 'end x moves')
        CHECK_TRUE(abs(rod%q_1(3, tip) - rod%fixed_q(3, tip)) > 1.0e-9_rk, 'end z moves')
        tol = 1.0e-9_rk * terms(1)%after
        CHECK_CLOSE(step_balance(terms(1)), 0.0_rk, tol, 0.0_rk, 'H_1 - H_0 - W = 0')
        call check_condensed_step(held_scene(3, 2, .true., 'held'), x_1, tol, terms_c)
    end subroutine test_held_newton_step

end module rs_test_ph_director

program test_ph_director
    use rs_test_assert, only: finish_tests
    use rs_test_ph_director, only: run_all_tests
    implicit none
    call run_all_tests()
    call finish_tests()
end program test_ph_director
