#include "rs_assert.h"
!> Unit tests of rs_ph_director, the assembled step problem: the CSR Jacobian equals central
!> finite differences of the assembled residual for a clamped-free rod with end and gravity
!> loads (so the dof map, the scatter and the exact pattern are checked together: every
!> non-zero of the difference quotient lies in the pattern), the unknowns and pattern size
!> follow from the mesh, and one assembled step conserves energy when solved by Newton here.
!> The same checks run on an inextensible rod with a generalized-Maxwell branch, a tendon and
!> a pressure chamber (energy balance with dissipation and actuator work), and on a
!> quasistatic rod in endpoint-equilibrium mode (no mass terms, the static kernels).
module rs_test_ph_director
    use rs_core_kinds, only: rk
    use rs_core_error, only: error_t
    use rs_test_assert, only: run_test, assert_true, assert_close, assert_equal
    use rs_test_random, only: set_random_seed
    use rs_test_formulation_fixture, only: central_differences
    use rs_model_scene, only: scene_t, rod_input_t, bc_input_t, load_input_t, actuator_input_t
    use rs_formulations_formulation, only: state_valid, formulation_traits_t
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
        if (endpoint) call rod%set_endpoint_solve(.true., 0.8_rk)
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
        if (endpoint) call rod%set_endpoint_solve(.false., 0.8_rk)
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
        real(rk) :: energy_1, kinetic, strain, tol
        call build_scene(actuated_scene(3, 2), rod)
        call newton_solve(rod, 0.5_rk, 0.01_rk, x_n, x_1)
        call rod%energy(x_1, kinetic, strain)
        energy_1 = kinetic + strain
        CHECK_TRUE(rod%dissipated_since_record > 0.0_rk, 'the Maxwell branch dissipates')
        CHECK_TRUE(abs(rod%actuator_work_since_record) > 1.0e-6_rk * energy_1, 'the actuators work')
        tol = 1.0e-9_rk * energy_1
        CHECK_CLOSE(rod%balance_since_record, 0.0_rk, tol, 0.0_rk, 'H_1 - H_0 - W - W_act + D = 0')
    end subroutine test_newton_step_energy_actuated

    !> Newton converges on the endpoint equilibrium of the quasistatic rod (load time 0.3).
    subroutine test_newton_endpoint()
        type(ph_director_t) :: rod
        real(rk), allocatable :: x_n(:), x_1(:)
        call build_scene(quasistatic_scene(3, 2), rod)
        call rod%set_endpoint_solve(.true., 0.3_rk)
        call newton_solve(rod, 0.0_rk, 0.3_rk, x_n, x_1)
        call rod%set_endpoint_solve(.false., 0.3_rk)
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
        real(rk) :: kinetic, strain, energy_n, energy_1
        call build(3, 2, rod, condensed)
        call newton_solve(rod, 0.5_rk, 0.01_rk, x_n, x_1)
        call rod%energy(x_n, kinetic, strain)
        energy_n = kinetic + strain
        call rod%energy(x_1, kinetic, strain)
        energy_1 = kinetic + strain
        CHECK_TRUE(energy_1 > 0.0_rk, 'the loads put energy in')
        CHECK_CLOSE(rod%balance_since_record, 0.0_rk, 1.0e-9_rk * energy_1, 0.0_rk, 'H_1 - H_0 - W = 0')
        CHECK_CLOSE(rod%work_since_record, energy_1 - energy_n, 1.0e-9_rk * energy_1, 0.0_rk, 'W = H_1 - H_0')
    end subroutine newton_step

    !> One step (t_n, h) of a built rod from its initial state, solved by Newton with a dense
    !> LU to |F| < 1e-12 and accepted.
    subroutine newton_solve(rod, t_n, h, x_n, x_1)
        type(ph_director_t), intent(inout) :: rod
        real(rk), intent(in) :: t_n, h
        real(rk), allocatable, intent(out) :: x_n(:), x_1(:)
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
        call rod%accept_step(t_n, h, x_n, x_1, it, norm2(f))
    end subroutine newton_solve

end module rs_test_ph_director

program test_ph_director
    use rs_test_assert, only: finish_tests
    use rs_test_ph_director, only: run_all_tests
    implicit none
    call run_all_tests()
    call finish_tests()
end program test_ph_director
