#include "rs_assert.h"
!> Unit tests of rs_ph_director_element (methods/ph_director_3d.md §2, §3, §4, §5): analytic
!> Jacobians against central finite differences (midpoint and static steps, generalized-Maxwell
!> branches, rigid components, pneumatic and tendon actuation), the skew (power) structure,
!> the exact discrete energy balance of one step with Maxwell dissipation and actuator work,
!> the angular-momentum balance, rigid-body and objectivity properties, strain consistency of
!> the non-rate stress rows, the tendon stress against its closed form, momenta, energies and
!> the reference-element data; and the reference strains: every random case has its own
!> (non-straight) reference strains at the Gauss points, a curved (helical) reference is
!> stress-free (zero residual and zero consistent stress, so zero strain energy), and the
!> prestressed initial stresses solve the stress rows. Damping (docs/theory/ph_director.md
!> "Damping"): the Kelvin-Voigt stress and the drags in the Jacobian against central
!> differences, in the exact energy identity, their dissipation in closed form, no viscous
!> stress for a rigid motion, objectivity, and internal forces without resultant.
!>
!> Without tendons the residuals are at most quadratic in the unknowns, so central differences
!> are exact up to round-off; a tendon direction r'/|r'| adds an O(step^2) truncation error far
!> below the tolerance. The tolerances below bound round-off only.
module rs_test_ph_director_element
    use, intrinsic :: iso_fortran_env, only: output_unit
    use rs_core_kinds, only: rk, pi
    use rs_test_random, only: set_random_seed, random_unit_vector, uniform, random_vector
    use rs_test_assert, only: run_test, assert_true, assert_close
    use rs_math_so3, only: exp_so3
    use rs_math_quadrature, only: max_gauss_points
    use rs_model_rod_geometry, only: rod_geometry_t, helix_geometry, set_start_director, &
        centreline_point, centreline_tangent, centreline_frame, default_normal
    use rs_ph_director_element, only: ph_director_material_t, ph_director_basis_t, &
        ph_director_actuation_t, ph_director_basis_init, ph_director_basis_shape, &
        ph_director_stress_shape, ph_director_local_size, ph_director_element_residual, &
        ph_director_node_residual, ph_director_element_kinetic_energy, &
        ph_director_element_complementary_energy, ph_director_element_momenta, &
        ph_director_element_position_integral, ph_director_element_external_work, &
        ph_director_node_external_work, ph_director_element_strains, &
        ph_director_node_constraint, ph_director_element_dissipation, &
        ph_director_element_actuator_work, ph_director_max_nodes, ph_director_max_degree, &
        ph_director_node_size, ph_director_element_reference_strains, &
        ph_director_element_initial_stress, ph_director_straight_strain, &
        ph_director_element_damping_dissipation
    implicit none
    private

    public :: run_all_tests

    ! Largest number of generalized-Maxwell branches of the cases here.
    integer, parameter :: max_br = 2
    integer, parameter :: max_local = 24 * ph_director_max_nodes &
        + 6 * ph_director_max_degree * (1 + max_br)
    ! Finite-difference step (relative to max(1, |x|)) and tolerance relative to max |J|.
    real(rk), parameter :: fd_step = 1.0e-6_rk, fd_tol = 1.0e-6_rk
    ! Round-off tolerance of exact identities, relative to the size of their terms.
    real(rk), parameter :: exact_tol = 1.0e-12_rk
    ! Rigid-component sets: none, shear (Kirchhoff), shear and dilatation (inextensible).
    logical, parameter :: no_rigid(6) = .false.
    logical, parameter :: kirchhoff(6) = [.true., .true., .false., .false., .false., .false.]
    logical, parameter :: inextensible(6) = [.true., .true., .true., .false., .false., .false.]

    !> One random step of one element: endpoint states, loads, actuation, geometry, material.
    type :: element_case_t
        type(ph_director_basis_t) :: basis
        type(ph_director_material_t) :: material
        type(ph_director_actuation_t) :: actuation
        logical :: static = .false.
        real(rk) :: le = 1.0_rk, h = 0.1_rk
        real(rk) :: q_n(12, ph_director_max_nodes) = 0.0_rk
        real(rk) :: q_1(12, ph_director_max_nodes) = 0.0_rk
        real(rk) :: v_n(12, ph_director_max_nodes) = 0.0_rk
        real(rk) :: v_1(12, ph_director_max_nodes) = 0.0_rk
        !> Stress coefficients (component, coefficient, branch; 0: elastic).
        real(rk) :: s_n(6, ph_director_max_degree, 0:max_br) = 0.0_rk
        real(rk) :: s_1(6, ph_director_max_degree, 0:max_br) = 0.0_rk
        real(rk) :: nbar(3) = 0.0_rk, mbar(3) = 0.0_rk
        !> Reference strains eps_0 at the Gauss points.
        real(rk) :: eps_ref(6, max_gauss_points) = 0.0_rk
    end type element_case_t

contains

    !> Run every test of this file through rs_test_assert.
    subroutine run_all_tests()
        call set_random_seed(20250117, 104729)
        call run_test('basis_quadrature', test_basis_quadrature)
        call run_test('basis_invalid', test_basis_invalid)
        call run_test('element_jacobian_fd', test_element_jacobian_fd)
        call run_test('element_jacobian_fd_static', test_element_jacobian_fd_static)
        call run_test('element_jacobian_fd_maxwell', test_element_jacobian_fd_maxwell)
        call run_test('element_jacobian_fd_rigid', test_element_jacobian_fd_rigid)
        call run_test('rigid_branch_stress', test_rigid_branch_stress)
        call run_test('element_jacobian_fd_pneumatic', test_element_jacobian_fd_pneumatic)
        call run_test('element_jacobian_fd_tendons', test_element_jacobian_fd_tendons)
        call run_test('node_jacobian_fd', test_node_jacobian_fd)
        call run_test('node_jacobian_fd_static', test_node_jacobian_fd_static)
        call run_test('node_without_lambda', test_node_without_lambda)
        call run_test('node_static_rows', test_node_static_rows)
        call run_test('power_identity', test_power_identity)
        call run_test('energy_identity_element', test_energy_identity_element)
        call run_test('energy_identity_with_nodes', test_energy_identity_with_nodes)
        call run_test('energy_identity_maxwell_actuation', test_energy_identity_maxwell_actuation)
        call run_test('energy_balance_solved_stresses', test_energy_balance_solved_stresses)
        call run_test('dissipation_and_actuator_work', test_dissipation_and_actuator_work)
        call run_test('tendon_closed_form', test_tendon_closed_form)
        call run_test('angular_momentum_balance', test_angular_momentum_balance)
        call run_test('rigid_body', test_rigid_body)
        call run_test('objectivity', test_objectivity)
        call run_test('strain_consistency', test_strain_consistency)
        call run_test('momenta', test_momenta)
        call run_test('energies_and_mass', test_energies_and_mass)
        call run_test('constraint', test_constraint)
        call run_test('reference_strains_straight', test_reference_strains_straight)
        call run_test('curved_reference_stress_free', test_curved_reference_stress_free)
        call run_test('prestressed_initial_stress', test_prestressed_initial_stress)
        call run_test('element_jacobian_fd_damping', test_element_jacobian_fd_damping)
        call run_test('energy_identity_damping', test_energy_identity_damping)
        call run_test('damping_dissipation_closed_form', test_damping_dissipation)
        call run_test('rigid_motion_not_damped', test_rigid_motion_not_damped)
        call run_test('damping_objective_and_internal', test_damping_objective_and_internal)
    end subroutine run_all_tests

    ! ---------------------------------------------------------------------------------------
    ! Random data

    function random_rotation() result(r)
        real(rk) :: r(3, 3)
        r = exp_so3(uniform(0.0_rk, pi) * random_unit_vector())
    end function random_rotation

    function cross(a, b) result(c)
        real(rk), intent(in) :: a(3), b(3)
        real(rk) :: c(3)
        c = [a(2) * b(3) - a(3) * b(2), a(3) * b(1) - a(1) * b(3), a(1) * b(2) - a(2) * b(1)]
    end function cross

    ! Node configurations of a deformed element: a rotated, stretched and bent straight piece
    ! with directors perturbed from orthonormal by `perturbation`.
    subroutine random_configuration(nen, le, perturbation, q)
        integer, intent(in) :: nen
        real(rk), intent(in) :: le, perturbation
        real(rk), intent(out) :: q(12, nen)
        real(rk) :: r(3, 3), origin(3)
        integer :: a
        r = random_rotation()
        origin = random_vector(3, 2.0_rk)
        do a = 1, nen
            q(1:3, a) = origin + le * real(a - 1, rk) / real(nen - 1, rk) * r(:, 3) &
                + random_vector(3, 0.2_rk * le)
            q(4:12, a) = reshape(r, [9]) + random_vector(9, perturbation)
        end do
    end subroutine random_configuration

    function random_material() result(material)
        type(ph_director_material_t) :: material
        integer :: l
        material%rhoA = uniform(0.5_rk, 2.0_rk)
        material%rhoI = [uniform(0.1_rk, 1.0_rk), uniform(0.1_rk, 1.0_rk)]
        do l = 1, 6
            material%compliance(l) = uniform(0.1_rk, 1.0_rk)
        end do
    end function random_material

    ! A random element step: both endpoint states independent and non-trivial; elastic
    ! material without branches, no actuation, midpoint step; reference strains those of a
    ! straight rod perturbed at every Gauss point (a curved, sheared, twisted reference).
    function random_case(degree, n_gauss) result(ec)
        integer, intent(in) :: degree, n_gauss
        type(element_case_t) :: ec
        logical :: ok
        integer :: nen, a
        call ph_director_basis_init(ec%basis, degree, n_gauss, ok)
        if (.not. ok) error stop 'random_case: invalid degree or number of Gauss points'
        nen = ec%basis%nen
        ec%material = random_material()
        ec%le = uniform(0.2_rk, 2.0_rk)
        ec%h = uniform(0.01_rk, 0.5_rk)
        call random_configuration(nen, ec%le, 0.1_rk, ec%q_n(:, 1:nen))
        do a = 1, nen
            ec%q_1(:, a) = ec%q_n(:, a) + random_vector(12, 0.1_rk)
            ec%v_n(:, a) = random_vector(12, 1.0_rk)
            ec%v_1(:, a) = random_vector(12, 1.0_rk)
        end do
        ec%s_n(:, 1:degree, 0) = reshape(random_vector(6 * degree, 1.0_rk), [6, degree])
        ec%s_1(:, 1:degree, 0) = reshape(random_vector(6 * degree, 1.0_rk), [6, degree])
        ec%nbar = random_vector(3, 1.0_rk)
        ec%mbar = random_vector(3, 1.0_rk)
        do a = 1, n_gauss
            ec%eps_ref(:, a) = ph_director_straight_strain + random_vector(6, 0.2_rk)
        end do
    end function random_case

    ! Give a case nb generalized-Maxwell branches (methods §3.1) with random compliances,
    ! fluidities and stresses. Components flagged `rigid` get zero compliance in the elastic
    ! branch and no Maxwell branch (branch_active false, compliance and fluidity 0), as the
    ! formulation builds a constrained rod (methods §2.3); their branch stress is zero at t_n
    ! (the identity rows held) and random at t_{n+1}.
    subroutine add_branches(ec, nb, rigid)
        type(element_case_t), intent(inout) :: ec
        integer, intent(in) :: nb
        logical, intent(in) :: rigid(6)
        integer :: br, l, p
        p = ec%basis%degree
        ec%material%n_branches = nb
        where (rigid) ec%material%compliance = 0.0_rk
        do br = 1, nb
            do l = 1, 6
                ec%material%branch_active(l, br) = .not. rigid(l)
                if (rigid(l)) then
                    ec%material%branch_compliance(l, br) = 0.0_rk
                    ec%material%branch_fluidity(l, br) = 0.0_rk
                else
                    ec%material%branch_compliance(l, br) = uniform(0.2_rk, 2.0_rk)
                    ec%material%branch_fluidity(l, br) = uniform(0.1_rk, 5.0_rk)
                end if
            end do
            ec%s_n(:, 1:p, br) = reshape(random_vector(6 * p, 1.0_rk), [6, p])
            ec%s_1(:, 1:p, br) = reshape(random_vector(6 * p, 1.0_rk), [6, p])
            do l = 1, 6
                if (rigid(l)) ec%s_n(l, 1:p, br) = 0.0_rk
            end do
        end do
    end subroutine add_branches

    ! Give a case damping (docs/theory/ph_director.md "Damping"): random Kelvin-Voigt
    ! viscosities V = tau k (none on rigid components, as the formulation builds them), drag
    ! and angular drag; `viscous`, `external` switch the two laws.
    subroutine add_damping(ec, rigid, viscous, external)
        type(element_case_t), intent(inout) :: ec
        logical, intent(in) :: rigid(6), viscous, external
        integer :: l
        if (viscous) then
            do l = 1, 6
                ec%material%viscosity(l) = merge(0.0_rk, uniform(0.05_rk, 2.0_rk), rigid(l))
            end do
        end if
        if (external) then
            ec%material%drag = uniform(0.2_rk, 2.0_rk)
            ec%material%angular_drag = uniform(0.2_rk, 2.0_rk)
        end if
    end subroutine add_damping

    ! Zero the branch stresses of rigid components at t_{n+1} too (their rows s_1 = 0 solved).
    subroutine zero_inactive_branch_stresses(ec)
        type(element_case_t), intent(inout) :: ec
        integer :: br, l
        do br = 1, ec%material%n_branches
            do l = 1, 6
                if (.not. ec%material%branch_active(l, br)) then
                    ec%s_n(l, :, br) = 0.0_rk
                    ec%s_1(l, :, br) = 0.0_rk
                end if
            end do
        end do
    end subroutine zero_inactive_branch_stresses

    ! Two pressure chambers at random offsets: the constant material stress
    ! sum_k tau_k (0, 0, 1, rho_k^2, -rho_k^1, 0) with tau_k = p_k A_k < 0 (methods §3.2).
    subroutine add_pneumatic(ec)
        type(element_case_t), intent(inout) :: ec
        real(rk) :: tau, rho(2)
        integer :: k
        do k = 1, 2
            tau = uniform(-2.0_rk, -0.5_rk)
            rho = random_vector(2, 0.3_rk)
            ec%actuation%pneumatic = ec%actuation%pneumatic &
                + tau * [0.0_rk, 0.0_rk, 1.0_rk, rho(2), -rho(1), 0.0_rk]
        end do
    end subroutine add_pneumatic

    ! n tendons with tension tau in [0.5, 2] at random material offsets 0.05 <= |rho| <= 0.3.
    subroutine add_tendons(ec, n)
        type(element_case_t), intent(inout) :: ec
        integer, intent(in) :: n
        real(rk) :: rho(2)
        integer :: k
        ec%actuation%n_tendons = n
        do k = 1, n
            do
                rho = random_vector(2, 0.3_rk)
                if (norm2(rho) >= 0.05_rk .and. norm2(rho) <= 0.3_rk) exit
            end do
            ec%actuation%tendon(:, k) = [uniform(0.5_rk, 2.0_rk), rho]
        end do
    end subroutine add_tendons

    ! q_1 from the kinematic rows, q_1 - q_n = h/2 (v_1 + v_n), exactly.
    subroutine solve_kinematic_rows(ec)
        type(element_case_t), intent(inout) :: ec
        integer :: nen
        nen = ec%basis%nen
        ec%q_1(:, 1:nen) = ec%q_n(:, 1:nen) &
            + 0.5_rk * ec%h * (ec%v_n(:, 1:nen) + ec%v_1(:, 1:nen))
    end subroutine solve_kinematic_rows

    integer function local_size(ec)
        type(element_case_t), intent(in) :: ec
        local_size = ph_director_local_size(ec%basis, ec%material)
    end function local_size

    subroutine element_residual(ec, residual, jacobian)
        type(element_case_t), intent(in) :: ec
        real(rk), intent(out), optional, contiguous :: residual(:)
        real(rk), intent(out), optional, contiguous :: jacobian(:, :)
        ! Contiguous copies of the stresses (no array temporaries at the call).
        real(rk) :: s_n(6, ec%basis%degree, 0:ec%material%n_branches)
        real(rk) :: s_1(6, ec%basis%degree, 0:ec%material%n_branches)
        integer :: nen
        nen = ec%basis%nen
        s_n = ec%s_n(:, 1:ec%basis%degree, 0:ec%material%n_branches)
        s_1 = ec%s_1(:, 1:ec%basis%degree, 0:ec%material%n_branches)
        call ph_director_element_residual(ec%basis, ec%material, ec%le, &
            ec%eps_ref(:, 1:ec%basis%n_gauss), ec%h, ec%static, ec%q_n(:, 1:nen), ec%q_1(:, 1:nen), &
            ec%v_n(:, 1:nen), ec%v_1(:, 1:nen), s_n, s_1, ec%nbar, ec%mbar, ec%actuation, residual, &
            jacobian)
    end subroutine element_residual

    ! Offset of the rows of stress coefficient b of branch br in the element local layout.
    integer function stress_offset(ec, br, b)
        type(element_case_t), intent(in) :: ec
        integer, intent(in) :: br, b
        stress_offset = 24 * ec%basis%nen + 6 * ec%basis%degree * br + 6 * (b - 1)
    end function stress_offset

    ! The t_{n+1} unknowns of a case in the element local layout, and back.
    subroutine pack_unknowns(ec, x)
        type(element_case_t), intent(in) :: ec
        real(rk), intent(out) :: x(:)
        integer :: a, b, br, o
        do a = 1, ec%basis%nen
            x(24 * (a - 1) + 1:24 * (a - 1) + 12) = ec%q_1(:, a)
            x(24 * (a - 1) + 13:24 * (a - 1) + 24) = ec%v_1(:, a)
        end do
        do br = 0, ec%material%n_branches
            do b = 1, ec%basis%degree
                o = stress_offset(ec, br, b)
                x(o + 1:o + 6) = ec%s_1(:, b, br)
            end do
        end do
    end subroutine pack_unknowns

    subroutine unpack_unknowns(x, ec)
        real(rk), intent(in) :: x(:)
        type(element_case_t), intent(inout) :: ec
        integer :: a, b, br, o
        do a = 1, ec%basis%nen
            ec%q_1(:, a) = x(24 * (a - 1) + 1:24 * (a - 1) + 12)
            ec%v_1(:, a) = x(24 * (a - 1) + 13:24 * (a - 1) + 24)
        end do
        do br = 0, ec%material%n_branches
            do b = 1, ec%basis%degree
                o = stress_offset(ec, br, b)
                ec%s_1(:, b, br) = x(o + 1:o + 6)
            end do
        end do
    end subroutine unpack_unknowns

    ! lambda . G_d(d) r for the nodal director vectors d, r (9), from the rows of methods §2.1.
    function constraint_power(lambda, d, r) result(power)
        real(rk), intent(in) :: lambda(6), d(9), r(9)
        real(rk) :: power
        power = lambda(1) * dot_product(d(1:3), r(1:3)) + lambda(2) * dot_product(d(4:6), r(4:6)) &
            + lambda(3) * dot_product(d(7:9), r(7:9)) &
            + 0.5_rk * lambda(4) * (dot_product(d(4:6), r(1:3)) + dot_product(d(1:3), r(4:6))) &
            + 0.5_rk * lambda(5) * (dot_product(d(7:9), r(4:6)) + dot_product(d(4:6), r(7:9))) &
            + 0.5_rk * lambda(6) * (dot_product(d(7:9), r(1:3)) + dot_product(d(1:3), r(7:9)))
    end function constraint_power

    ! Momentum rows (v rows) of node a and stress rows of coefficient b of branch br.
    function v_rows(residual, a) result(r)
        real(rk), intent(in) :: residual(:)
        integer, intent(in) :: a
        real(rk) :: r(12)
        r = residual(24 * (a - 1) + 13:24 * a)
    end function v_rows

    function s_rows(ec, residual, br, b) result(r)
        type(element_case_t), intent(in) :: ec
        real(rk), intent(in) :: residual(:)
        integer, intent(in) :: br, b
        real(rk) :: r(6)
        integer :: o
        o = stress_offset(ec, br, b)
        r = residual(o + 1:o + 6)
    end function s_rows

    ! Kinetic and complementary energies at both ends, the external and actuator work and the
    ! dissipation of a case (Maxwell branches and damping).
    subroutine element_energies(ec, t_n, t_1, w_n, w_1, w_ext, w_act, dissipation)
        type(element_case_t), intent(in) :: ec
        real(rk), intent(out) :: t_n, t_1, w_n, w_1, w_ext, w_act, dissipation
        real(rk) :: viscous, external
        real(rk) :: s_n(6, ec%basis%degree, 0:ec%material%n_branches)
        real(rk) :: s_1(6, ec%basis%degree, 0:ec%material%n_branches)
        integer :: nen
        nen = ec%basis%nen
        s_n = ec%s_n(:, 1:ec%basis%degree, 0:ec%material%n_branches)
        s_1 = ec%s_1(:, 1:ec%basis%degree, 0:ec%material%n_branches)
        t_n = ph_director_element_kinetic_energy(ec%basis, ec%material, ec%le, ec%v_n(:, 1:nen))
        t_1 = ph_director_element_kinetic_energy(ec%basis, ec%material, ec%le, ec%v_1(:, 1:nen))
        w_n = ph_director_element_complementary_energy(ec%basis, ec%material, ec%le, s_n)
        w_1 = ph_director_element_complementary_energy(ec%basis, ec%material, ec%le, s_1)
        w_ext = ph_director_element_external_work(ec%basis, ec%le, ec%h, ec%q_n(:, 1:nen), &
            ec%q_1(:, 1:nen), ec%v_n(:, 1:nen), ec%v_1(:, 1:nen), ec%nbar, ec%mbar)
        w_act = ph_director_element_actuator_work(ec%basis, ec%le, ec%h, ec%q_n(:, 1:nen), &
            ec%q_1(:, 1:nen), ec%v_n(:, 1:nen), ec%v_1(:, 1:nen), ec%actuation)
        dissipation = ph_director_element_dissipation(ec%basis, ec%material, ec%le, ec%h, &
            s_n, s_1)
        call ph_director_element_damping_dissipation(ec%basis, ec%material, ec%le, ec%h, &
            ec%q_n(:, 1:nen), ec%q_1(:, 1:nen), ec%v_n(:, 1:nen), ec%v_1(:, 1:nen), viscous, &
            external)
        dissipation = dissipation + viscous + external
    end subroutine element_energies

    ! Each 3-block of x rotated by rot.
    function rotate_blocks(rot, x) result(y)
        real(rk), intent(in) :: rot(3, 3), x(:)
        real(rk) :: y(size(x))
        integer :: blk
        do blk = 1, size(x) / 3
            y(3 * blk - 2:3 * blk) = matmul(rot, x(3 * blk - 2:3 * blk))
        end do
    end function rotate_blocks

    ! Torque of the nodal vectors f (v-row layout) about the origin through the node positions
    ! and directors q: sum_a phi_a x f_phi,a + sum_i d_i,a x f_di,a.
    function nodal_torque(q, residual, nen) result(torque)
        real(rk), intent(in) :: q(:, :), residual(:)
        integer, intent(in) :: nen
        real(rk) :: torque(3)
        real(rk) :: f(12)
        integer :: a, i
        torque = 0.0_rk
        do a = 1, nen
            f = v_rows(residual, a)
            do i = 0, 3
                torque = torque + cross(q(3 * i + 1:3 * i + 3, a), f(3 * i + 1:3 * i + 3))
            end do
        end do
    end function nodal_torque

    ! Solution of the small dense system a x = b (Gaussian elimination, partial pivoting).
    function solve(a, b) result(x)
        real(rk), intent(in) :: a(:, :), b(:)
        real(rk) :: x(size(b))
        real(rk) :: m(size(b), size(b)), row(size(b)), factor, swap
        integer :: n, i, k, piv
        n = size(b)
        m = a
        x = b
        do i = 1, n
            piv = i - 1 + maxloc(abs(m(i:, i)), 1)
            if (piv /= i) then
                row = m(i, :)
                m(i, :) = m(piv, :)
                m(piv, :) = row
                swap = x(i)
                x(i) = x(piv)
                x(piv) = swap
            end if
            do k = i + 1, n
                factor = m(k, i) / m(i, i)
                m(k, i:) = m(k, i:) - factor * m(i, i:)
                x(k) = x(k) - factor * x(i)
            end do
        end do
        do i = n, 1, -1
            x(i) = (x(i) - dot_product(m(i, i + 1:), x(i + 1:))) / m(i, i)
        end do
    end function solve

    ! The stresses s_1 (all branches) that zero the stress rows of a case: the rows are linear
    ! in s_1 with the constant block J_ss of the kernel's Jacobian, so s_1 = -J_ss^{-1} R_S(0).
    ! Returns the stress rows at the result in `rows` and max |R_S(0)| in `size0`.
    subroutine solve_stress_rows(ec, rows, size0)
        type(element_case_t), intent(inout) :: ec
        real(rk), intent(out) :: rows(:), size0
        real(rk) :: residual(max_local), x(max_local)
        real(rk), allocatable :: jac(:, :)
        integer :: n, first
        n = local_size(ec)
        first = 24 * ec%basis%nen + 1
        allocate(jac(n, n))
        ec%s_1 = 0.0_rk
        call element_residual(ec, residual(1:n), jac)
        size0 = maxval(abs(residual(first:n)))
        call pack_unknowns(ec, x(1:n))
        x(first:n) = -solve(jac(first:n, first:n), residual(first:n))
        call unpack_unknowns(x(1:n), ec)
        call element_residual(ec, residual(1:n))
        rows(1:n - first + 1) = residual(first:n)
    end subroutine solve_stress_rows

    ! ---------------------------------------------------------------------------------------
    ! Tests

    subroutine test_basis_quadrature()
        type(ph_director_basis_t) :: basis
        type(ph_director_material_t) :: material
        real(rk) :: moment, exact, nodes(3), n(3), dn(3), psi(2), delta(3), total
        logical :: ok
        integer :: p, ng, k, g, a, n_local
        do p = 1, 2
            do ng = p, max_gauss_points
                call ph_director_basis_init(basis, p, ng, ok)
                CHECK_TRUE(ok, 'valid degree and rule')
                CHECK_TRUE(basis%nen == p + 1, 'nen = p + 1')
                material%n_branches = 0
                n_local = ph_director_local_size(basis, material)
                CHECK_TRUE(n_local == 24 * (p + 1) + 6 * p, 'local size without branches')
                material%n_branches = 2
                n_local = ph_director_local_size(basis, material)
                CHECK_TRUE(n_local == 24 * (p + 1) + 18 * p, 'local size with two branches')
                ! The n-point rule integrates xi^k exactly for k <= 2n - 1, not xi^(2n).
                do k = 0, 2 * ng - 1
                    moment = sum(basis%w(1:ng) * basis%xi(1:ng)**k)
                    exact = (1.0_rk - (-1.0_rk)**(k + 1)) / real(k + 1, rk)
                    CHECK_CLOSE(moment, exact, 1.0e-15_rk, 1.0e-15_rk, 'Gauss moment')
                end do
                moment = sum(basis%w(1:ng) * basis%xi(1:ng)**(2 * ng))
                exact = 2.0_rk / real(2 * ng + 1, rk)
                CHECK_TRUE(abs(moment - exact) > 1.0e-3_rk, 'xi^(2n) is not integrated exactly')
                do g = 1, ng
                    total = sum(basis%shape(1:p + 1, g))
                    CHECK_CLOSE(total, 1.0_rk, 1.0e-15_rk, 0.0_rk, 'sum N = 1')
                    total = sum(basis%dshape(1:p + 1, g))
                    CHECK_CLOSE(total, 0.0_rk, 1.0e-15_rk, 0.0_rk, 'sum dN = 0')
                    total = sum(basis%psi(1:p, g))
                    CHECK_CLOSE(total, 1.0_rk, 1.0e-15_rk, 0.0_rk, 'sum psi = 1')
                end do
            end do
            ! Node order along s: nodes at xi = -1, (0,) 1.
            do a = 1, p + 1
                nodes(a) = -1.0_rk + 2.0_rk * real(a - 1, rk) / real(p, rk)
            end do
            do a = 1, p + 1
                call ph_director_basis_shape(basis, nodes(a), n(1:p + 1), dn(1:p + 1))
                delta = 0.0_rk
                delta(a) = 1.0_rk
                CHECK_CLOSE(n(1:p + 1), delta(1:p + 1), 1.0e-15_rk, 0.0_rk, 'N_a(node_b) = delta')
            end do
            ! Stress basis: Lagrange functions of the stress points.
            do a = 1, p
                call ph_director_stress_shape(basis, basis%stress_xi(a), psi(1:p))
                delta = 0.0_rk
                delta(a) = 1.0_rk
                CHECK_CLOSE(psi(1:p), delta(1:p), 0.0_rk, 0.0_rk, 'psi_b(stress point c) = delta')
            end do
        end do
        call ph_director_basis_init(basis, 1, 1, ok)
        CHECK_CLOSE(basis%stress_xi(1), 0.0_rk, 0.0_rk, 0.0_rk, 'p = 1 stress point')
        call ph_director_basis_init(basis, 2, 2, ok)
        exact = 1.0_rk / sqrt(3.0_rk)
        CHECK_CLOSE(basis%stress_xi(1), -exact, 0.0_rk, 4.0e-16_rk, 'p = 2 point 1')
        CHECK_CLOSE(basis%stress_xi(2), exact, 0.0_rk, 4.0e-16_rk, 'p = 2 point 2')
        ! Under 2-point Gauss the stress basis is exactly the Kronecker delta (diagonal C_e).
        delta(1:2) = [1.0_rk, 0.0_rk]
        CHECK_CLOSE(basis%psi(1:2, 1), delta(1:2), 0.0_rk, 0.0_rk, 'psi(1:2, g = 1)')
        delta(1:2) = [0.0_rk, 1.0_rk]
        CHECK_CLOSE(basis%psi(1:2, 2), delta(1:2), 0.0_rk, 0.0_rk, 'psi(1:2, g = 2)')
    end subroutine test_basis_quadrature

    subroutine test_basis_invalid()
        type(ph_director_basis_t) :: basis
        logical :: ok
        call ph_director_basis_init(basis, 3, 2, ok)
        CHECK_TRUE(.not. ok, 'degree 3 rejected')
        call ph_director_basis_init(basis, 0, 2, ok)
        CHECK_TRUE(.not. ok, 'degree 0 rejected')
        call ph_director_basis_init(basis, 2, 0, ok)
        CHECK_TRUE(.not. ok, 'zero Gauss points rejected')
        call ph_director_basis_init(basis, 2, max_gauss_points + 1, ok)
        CHECK_TRUE(.not. ok, 'too many Gauss points rejected')
        call ph_director_basis_init(basis, 2, 1, ok)
        CHECK_TRUE(.not. ok, 'p = 2 with 1 Gauss point (singular stress block) rejected')
        CHECK_TRUE(basis%nen == 0, 'rejected basis is empty')
    end subroutine test_basis_invalid

    ! Whether column j of the element local layout is the branch stress of a component that
    ! has no branch (a rigid one, branch_active false).
    logical function inactive_branch_column(ec, j)
        type(element_case_t), intent(in) :: ec
        integer, intent(in) :: j
        integer :: k, br
        inactive_branch_column = .false.
        k = j - 24 * ec%basis%nen
        if (k <= 6 * ec%basis%degree) return
        br = (k - 1) / (6 * ec%basis%degree)
        inactive_branch_column = .not. ec%material%branch_active(mod(k - 1, 6) + 1, br)
    end function inactive_branch_column

    ! Analytic element Jacobian of one case against central differences of its residual,
    ! relative to max |J|; the residual without the Jacobian and the Jacobian without the
    ! residual are the same, and the q rows of an element are zero (they are nodal).
    subroutine element_fd_error(ec, error)
        type(element_case_t), intent(in) :: ec
        real(rk), intent(out) :: error
        type(element_case_t) :: ep, em
        real(rk) :: x(max_local), xp(max_local), residual(max_local), rp(max_local)
        real(rk) :: rm(max_local), zero(12), q_rows(12), step
        real(rk), allocatable :: jac(:, :), fd(:, :), jac_alone(:, :)
        integer :: n, j, a
        zero = 0.0_rk
        n = local_size(ec)
        allocate(jac(n, n), fd(n, n), jac_alone(n, n))
        call element_residual(ec, residual(1:n), jac)
        call pack_unknowns(ec, x(1:n))
        do j = 1, n
            step = fd_step * max(1.0_rk, abs(x(j)))
            xp(1:n) = x(1:n)
            xp(j) = x(j) + step
            ep = ec
            call unpack_unknowns(xp(1:n), ep)
            call element_residual(ep, rp(1:n))
            xp(j) = x(j) - step
            em = ec
            call unpack_unknowns(xp(1:n), em)
            call element_residual(em, rm(1:n))
            fd(:, j) = (rp(1:n) - rm(1:n)) / (2.0_rk * step)
        end do
        error = maxval(abs(jac - fd)) / maxval(abs(jac))
        call element_residual(ec, rp(1:n))
        CHECK_CLOSE(rp(1:n), residual(1:n), 0.0_rk, 0.0_rk, 'residual without Jacobian')
        call element_residual(ec, jacobian=jac_alone)
        CHECK_TRUE(all(jac_alone == jac), 'Jacobian without residual')
        do a = 1, ec%basis%nen
            q_rows = residual(24 * (a - 1) + 1:24 * (a - 1) + 12)
            CHECK_CLOSE(q_rows, zero, 0.0_rk, 0.0_rk, 'q rows zero')
        end do
    end subroutine element_fd_error

    ! Element Jacobian against central differences on random cases of one family: p = 1, 2,
    ! n_gauss = p .. 4, with the step kind, branches, rigid set and actuators given.
    subroutine check_fd_family(label, static, nb, rigid, pneumatic, n_tendons, viscous, external)
        character(len=*), intent(in) :: label
        logical, intent(in) :: static
        integer, intent(in) :: nb
        logical, intent(in) :: rigid(6), pneumatic
        integer, intent(in) :: n_tendons
        !> Kelvin-Voigt viscosity and drags (add_damping); none when absent.
        logical, intent(in), optional :: viscous, external
        type(element_case_t) :: ec
        real(rk) :: error, worst
        integer :: p, ng, sample
        character(len=160) :: text
        worst = 0.0_rk
        do p = 1, 2
            do ng = p, 4
                do sample = 1, 3
                    ec = random_case(p, ng)
                    ec%static = static
                    call add_branches(ec, nb, rigid)
                    if (pneumatic) call add_pneumatic(ec)
                    if (n_tendons > 0) call add_tendons(ec, n_tendons)
                    if (present(viscous)) call add_damping(ec, rigid, viscous, external)
                    call element_fd_error(ec, error)
                    worst = max(worst, error)
                    CHECK_TRUE(error < fd_tol, label // ': element Jacobian = central differences')
                end do
            end do
        end do
        write(text, '(a,es9.2)') '    max relative FD error (element, ' // label // '): ', worst
        write(output_unit, '(a)') trim(text)
    end subroutine check_fd_family

    subroutine test_element_jacobian_fd()
        call check_fd_family('midpoint', .false., 0, no_rigid, .false., 0)
    end subroutine test_element_jacobian_fd

    ! static = .true.: theta = 1, no viscous term (the endpoint equilibrium of quasistatics).
    subroutine test_element_jacobian_fd_static()
        call check_fd_family('static', .true., 0, no_rigid, .false., 0)
        call check_fd_family('static, 2 branches, rigid shear, pneumatic, 2 tendons', .true., 2, &
            kirchhoff, .true., 2)
    end subroutine test_element_jacobian_fd_static

    ! 1 and 2 generalized-Maxwell branches, all components active (methods §3.1, §5.2).
    subroutine test_element_jacobian_fd_maxwell()
        call check_fd_family('1 branch', .false., 1, no_rigid, .false., 0)
        call check_fd_family('2 branches', .false., 2, no_rigid, .false., 0)
    end subroutine test_element_jacobian_fd_maxwell

    ! Rigid components (zero compliance, no branch): the stresses are multipliers.
    subroutine test_element_jacobian_fd_rigid()
        call check_fd_family('inextensible, no branch', .false., 0, inextensible, .false., 0)
        call check_fd_family('inextensible, 1 branch', .false., 1, inextensible, .false., 0)
        call check_fd_family('inextensible, 2 branches', .false., 2, inextensible, .false., 0)
        call check_fd_family('kirchhoff, 1 branch, static', .true., 1, kirchhoff, .false., 0)
    end subroutine test_element_jacobian_fd_rigid

    ! Pressure chambers: a constant material stress in the momentum rows (methods §3.2).
    subroutine test_element_jacobian_fd_pneumatic()
        call check_fd_family('pneumatic', .false., 0, no_rigid, .true., 0)
        call check_fd_family('pneumatic, static', .true., 0, no_rigid, .true., 0)
    end subroutine test_element_jacobian_fd_pneumatic

    ! Tendons at non-trivial offsets on curved, stretched states with non-orthonormal
    ! interpolated directors: the state-dependent direction t = r'/|r'| (methods §3.2, §5.6).
    subroutine test_element_jacobian_fd_tendons()
        call check_fd_family('1 tendon', .false., 0, no_rigid, .false., 1)
        call check_fd_family('2 tendons', .false., 0, no_rigid, .false., 2)
        call check_fd_family('2 tendons, static', .true., 0, no_rigid, .false., 2)
        call check_fd_family('2 tendons, pneumatic, 1 branch, inextensible', .false., 1, &
            inextensible, .true., 2)
    end subroutine test_element_jacobian_fd_tendons

    ! A rigid component has no Maxwell branch (kernel documentation, methods §3.1 with §2.3):
    ! its branch rows are s_1 = 0 and its branch stress is not a stress of the rod, so the
    ! momentum rows must not depend on it, as the Jacobian (and the formulation's pattern,
    ! which has no such entries) assume. Checked on states where that stress is not yet zero
    ! (any Newton iterate before its identity row is solved): the momentum rows with and
    ! without it, and the Jacobian columns against central differences.
    subroutine test_rigid_branch_stress()
        type(element_case_t) :: ec, cleared, ep, em
        real(rk) :: residual(max_local), r_cleared(max_local), rp(max_local), rm(max_local)
        real(rk) :: x(max_local), xp(max_local), fd(max_local), tol, step, worst_r, worst_j
        real(rk), allocatable :: jac(:, :)
        integer :: p, ng, sample, n, nm, j, nb
        character(len=120) :: text
        worst_r = 0.0_rk
        worst_j = 0.0_rk
        do p = 1, 2
            do ng = p, 3
                do sample = 1, 4
                    nb = 1 + mod(sample, 2)
                    ec = random_case(p, ng)
                    ec%static = sample > 2
                    call add_branches(ec, nb, merge(inextensible, kirchhoff, sample > 2))
                    n = local_size(ec)
                    nm = 24 * ec%basis%nen
                    if (allocated(jac)) deallocate(jac)
                    allocate(jac(n, n))
                    call element_residual(ec, residual(1:n), jac)
                    cleared = ec
                    call zero_inactive_branch_stresses(cleared)
                    cleared%s_n = ec%s_n
                    call element_residual(cleared, r_cleared(1:n))
                    tol = exact_tol * maxval(abs(residual(1:nm)))
                    worst_r = max(worst_r, maxval(abs(residual(1:nm) - r_cleared(1:nm))) &
                        / maxval(abs(residual(1:nm))))
                    CHECK_CLOSE(residual(1:nm), r_cleared(1:nm), tol, 0.0_rk, 'R_M free of s_rigid')
                    call pack_unknowns(ec, x(1:n))
                    do j = 1, n
                        if (.not. inactive_branch_column(ec, j)) cycle
                        step = fd_step * max(1.0_rk, abs(x(j)))
                        xp(1:n) = x(1:n)
                        xp(j) = x(j) + step
                        ep = ec
                        call unpack_unknowns(xp(1:n), ep)
                        call element_residual(ep, rp(1:n))
                        xp(j) = x(j) - step
                        em = ec
                        call unpack_unknowns(xp(1:n), em)
                        call element_residual(em, rm(1:n))
                        fd(1:n) = (rp(1:n) - rm(1:n)) / (2.0_rk * step)
                        worst_j = max(worst_j, maxval(abs(jac(1:nm, j) - fd(1:nm))) &
                            / maxval(abs(jac(1:n, 1:n))))
                        tol = fd_tol * maxval(abs(jac(1:n, 1:n)))
                        CHECK_CLOSE(jac(1:nm, j), fd(1:nm), tol, 0.0_rk, 'rigid branch column')
                    end do
                end do
            end do
        end do
        write(text, '(a,es9.2,a,es9.2)') '    rigid branch stress: relative change of R_M ', &
            worst_r, ', relative FD error of its J columns ', worst_j
        write(output_unit, '(a)') trim(text)
    end subroutine test_rigid_branch_stress

    subroutine random_node(q_n, q_1, v_n, v_1, lambda, force, moment)
        real(rk), intent(out) :: q_n(12), q_1(12), v_n(12), v_1(12), lambda(6)
        real(rk), intent(out) :: force(3), moment(3)
        real(rk) :: q(12, 2)
        call random_configuration(2, 1.0_rk, 0.1_rk, q)
        q_n = q(:, 1)
        q_1 = q_n + random_vector(12, 0.1_rk)
        v_n = random_vector(12, 1.0_rk)
        v_1 = random_vector(12, 1.0_rk)
        lambda = random_vector(6, 2.0_rk)
        force = random_vector(3, 1.0_rk)
        moment = random_vector(3, 1.0_rk)
    end subroutine random_node

    ! Node Jacobian against central differences, with and without multipliers.
    subroutine check_node_jacobian(static)
        logical, intent(in) :: static
        real(rk) :: q_n(12), q_1(12), v_n(12), v_1(12), lambda(6), force(3), moment(3), h
        real(rk) :: x(30), xp(30), xm(30), residual(30), rp(30), rm(30), jac(30, 30), fd(30, 30)
        real(rk) :: step, error, worst
        integer :: sample, j, variant
        logical :: with_lambda
        character(len=80) :: text
        worst = 0.0_rk
        do variant = 1, 2
            with_lambda = variant == 1
            do sample = 1, 10
                call random_node(q_n, q_1, v_n, v_1, lambda, force, moment)
                h = uniform(0.01_rk, 0.5_rk)
                call ph_director_node_residual(h, static, q_n, q_1, v_n, v_1, lambda, &
                    with_lambda, force, moment, residual, jac)
                x = [q_1, v_1, lambda]
                do j = 1, ph_director_node_size
                    step = fd_step * max(1.0_rk, abs(x(j)))
                    xp = x
                    xp(j) = x(j) + step
                    xm = x
                    xm(j) = x(j) - step
                    call ph_director_node_residual(h, static, q_n, xp(1:12), v_n, xp(13:24), &
                        xp(25:30), with_lambda, force, moment, rp)
                    call ph_director_node_residual(h, static, q_n, xm(1:12), v_n, xm(13:24), &
                        xm(25:30), with_lambda, force, moment, rm)
                    fd(:, j) = (rp - rm) / (2.0_rk * step)
                end do
                error = maxval(abs(jac - fd)) / maxval(abs(jac))
                worst = max(worst, error)
                CHECK_TRUE(error < fd_tol, 'node Jacobian = central differences')
            end do
        end do
        write(text, '(a,l1,a,es9.2)') '    max relative FD error (node, static = ', static, &
            '): ', worst
        write(output_unit, '(a)') trim(text)
    end subroutine check_node_jacobian

    subroutine test_node_jacobian_fd()
        call check_node_jacobian(.false.)
    end subroutine test_node_jacobian_fd

    subroutine test_node_jacobian_fd_static()
        call check_node_jacobian(.true.)
    end subroutine test_node_jacobian_fd_static

    ! Expected director rows of the node kernel: h G_d(d)^T lambda - h/2 moment x d_i.
    function director_rows(h, d, lambda, moment) result(expected_d)
        real(rk), intent(in) :: h, d(9), lambda(6), moment(3)
        real(rk) :: expected_d(9)
        integer :: i
        expected_d(1:3) = lambda(1) * d(1:3) + 0.5_rk * lambda(4) * d(4:6) &
            + 0.5_rk * lambda(6) * d(7:9)
        expected_d(4:6) = 0.5_rk * lambda(4) * d(1:3) + lambda(2) * d(4:6) &
            + 0.5_rk * lambda(5) * d(7:9)
        expected_d(7:9) = 0.5_rk * lambda(6) * d(1:3) + 0.5_rk * lambda(5) * d(4:6) &
            + lambda(3) * d(7:9)
        do i = 1, 3
            expected_d(3 * i - 2:3 * i) = h * expected_d(3 * i - 2:3 * i) &
                - 0.5_rk * h * cross(moment, d(3 * i - 2:3 * i))
        end do
    end function director_rows

    subroutine test_node_without_lambda()
        real(rk) :: q_n(12), q_1(12), v_n(12), v_1(12), lambda(6), force(3), moment(3), h
        real(rk) :: r_with(30), r_without(30), r_zero(30), expected(12), zero(6), g_1(6)
        real(rk) :: d_mid(9), expected_d(9)
        call random_node(q_n, q_1, v_n, v_1, lambda, force, moment)
        h = 0.3_rk
        zero = 0.0_rk
        call ph_director_node_residual(h, .false., q_n, q_1, v_n, v_1, lambda, .false., force, &
            moment, r_without)
        call ph_director_node_residual(h, .false., q_n, q_1, v_n, v_1, zero, .true., force, &
            moment, r_zero)
        call ph_director_node_residual(h, .false., q_n, q_1, v_n, v_1, lambda, .true., force, &
            moment, r_with)
        g_1 = ph_director_node_constraint(q_1)
        CHECK_CLOSE(r_without(25:30), lambda, 0.0_rk, 0.0_rk, 'lambda rows = lambda')
        CHECK_CLOSE(r_without(1:24), r_zero(1:24), 0.0_rk, 0.0_rk, 'no lambda in q, v rows')
        CHECK_CLOSE(r_with(25:30), g_1, 0.0_rk, 0.0_rk, 'lambda rows = g(d_1)')
        expected = q_1 - q_n - 0.5_rk * h * (v_1 + v_n)
        CHECK_CLOSE(r_with(1:12), expected, 1.0e-15_rk, 1.0e-15_rk, 'kinematic rows')
        expected(1:3) = -h * force
        CHECK_CLOSE(r_with(13:15), expected(1:3), 1.0e-15_rk, 1.0e-15_rk, 'force rows')
        ! Director rows: h G_d(d_mid)^T lambda - h/2 moment x d_i,mid (methods §2.1, §2.9).
        d_mid = 0.5_rk * (q_n(4:12) + q_1(4:12))
        expected_d = director_rows(h, d_mid, lambda, moment)
        CHECK_CLOSE(r_with(16:24), expected_d, 1.0e-14_rk, 1.0e-14_rk, 'director rows')
    end subroutine test_node_without_lambda

    ! The static (endpoint equilibrium) node rows: q rows -h/2 (v_1 - v_n), loads and
    ! multipliers at d_1, the constraint g(d_1) (kernel documentation, DESIGN.md §3).
    subroutine test_node_static_rows()
        real(rk) :: q_n(12), q_1(12), v_n(12), v_1(12), lambda(6), force(3), moment(3), h
        real(rk) :: r_static(30), r_without(30), expected(12), expected_d(9), g_1(6)
        integer :: sample
        do sample = 1, 5
            call random_node(q_n, q_1, v_n, v_1, lambda, force, moment)
            h = uniform(0.01_rk, 0.5_rk)
            call ph_director_node_residual(h, .true., q_n, q_1, v_n, v_1, lambda, .true., force, &
                moment, r_static)
            expected = -0.5_rk * h * (v_1 - v_n)
            CHECK_CLOSE(r_static(1:12), expected, 1.0e-15_rk, 1.0e-15_rk, 'static q rows')
            expected(1:3) = -h * force
            CHECK_CLOSE(r_static(13:15), expected(1:3), 1.0e-15_rk, 1.0e-15_rk, 'static force rows')
            expected_d = director_rows(h, q_1(4:12), lambda, moment)
            CHECK_CLOSE(r_static(16:24), expected_d, 1.0e-14_rk, 1.0e-14_rk, 'static director rows')
            g_1 = ph_director_node_constraint(q_1)
            CHECK_CLOSE(r_static(25:30), g_1, 0.0_rk, 0.0_rk, 'static lambda rows = g(d_1)')
            call ph_director_node_residual(h, .true., q_n, q_1, v_n, v_1, lambda, .false., force, &
                moment, r_without)
            CHECK_CLOSE(r_without(25:30), lambda, 0.0_rk, 0.0_rk, 'static clamped: lambda rows')
        end do
    end subroutine test_node_static_rows

    ! Skew structure (methods §4.3, §2.6 J_v = J_sigma^*): the internal forces and the strain
    ! variation are adjoint, v^T f_int(q, sigma) = sigma^T int psi B(q) v ds for every q, v and
    ! sigma. In a static step without mass, loads or actuators the momentum rows are
    ! h f_int(q_1, sum of the branches of s_1); every stress row (elastic or branch) holds
    ! -int psi eps(q_1) plus terms free of q_1, and eps is quadratic, so
    ! R_S(q_1 + v) - R_S(q_1 - v) = -2 int psi B(q_1) v exactly.
    subroutine test_power_identity()
        type(element_case_t) :: ec, plus, minus
        real(rk) :: residual(max_local), r_plus(max_local), r_minus(max_local), power_m, power_s
        integer :: p, ng, sample, n, nen, a, b, br, nb
        do nb = 0, 2
            do p = 1, 2
                do ng = p, 3
                    do sample = 1, 3
                        ec = random_case(p, ng)
                        call add_branches(ec, nb, no_rigid)
                        nen = ec%basis%nen
                        n = local_size(ec)
                        ec%static = .true.
                        ec%v_1 = ec%v_n
                        ec%nbar = 0.0_rk
                        ec%mbar = 0.0_rk
                        call element_residual(ec, residual(1:n))
                        plus = ec
                        minus = ec
                        plus%q_1(:, 1:nen) = ec%q_1(:, 1:nen) + ec%v_n(:, 1:nen)
                        minus%q_1(:, 1:nen) = ec%q_1(:, 1:nen) - ec%v_n(:, 1:nen)
                        call element_residual(plus, r_plus(1:n))
                        call element_residual(minus, r_minus(1:n))
                        power_m = 0.0_rk
                        do a = 1, nen
                            power_m = power_m + dot_product(ec%v_n(:, a), v_rows(residual, a))
                        end do
                        power_s = 0.0_rk
                        do br = 0, nb
                            do b = 1, p
                                power_s = power_s + 0.5_rk * dot_product(ec%s_1(:, b, br), &
                                    s_rows(ec, r_plus, br, b) - s_rows(ec, r_minus, br, b))
                            end do
                        end do
                        power_m = power_m / ec%h
                        CHECK_TRUE(abs(power_m) > 1.0e-3_rk, 'non-trivial internal power')
                        CHECK_CLOSE(power_m, -power_s, 0.0_rk, exact_tol, 'v f_int = s int psi B v')
                    end do
                end do
            end do
        end do
    end subroutine test_power_identity

    ! The element energy identity (methods §5.3 item 1 with §3.1, §3.2) for a midpoint case
    ! whose kinematic rows hold exactly, q_1 - q_n = h/2 (v_1 + v_n), and any stresses:
    !   v_mid^T R_M + s_mid^(0)T [R_0(q_1, s_1) - R_0(q_n, s_n)] + sum_i s_mid^(i)T R_i
    !     = Delta T + Delta W* - W_ext - W_act + D.
    ! eps is bilinear, so h B(q_mid) v_mid = eps(q_1) - eps(q_n), which turns the internal
    ! power of the momentum rows (stresses and actuators) into the strain terms of the elastic
    ! and branch rows. R_0(q_n, s_n), the elastic rows at t_n, is zero after a solved step;
    ! evaluating it lets the identity hold for arbitrary stresses.
    subroutine energy_identity(ec, lhs, rhs, scale)
        type(element_case_t), intent(in) :: ec
        real(rk), intent(out) :: lhs, rhs, scale
        type(element_case_t) :: previous
        real(rk) :: residual(max_local), r_previous(max_local), lhs_m, lhs_s, s_mid(6)
        real(rk) :: t_n, t_1, w_n, w_1, w_ext, w_act, dissipation
        integer :: n, a, b, br
        n = local_size(ec)
        call element_residual(ec, residual(1:n))
        previous = ec
        previous%q_1 = ec%q_n
        previous%v_1 = ec%v_n
        previous%s_1 = ec%s_n
        call element_residual(previous, r_previous(1:n))
        lhs_m = 0.0_rk
        do a = 1, ec%basis%nen
            lhs_m = lhs_m + dot_product(0.5_rk * (ec%v_n(:, a) + ec%v_1(:, a)), &
                v_rows(residual, a))
        end do
        lhs_s = 0.0_rk
        do br = 0, ec%material%n_branches
            do b = 1, ec%basis%degree
                s_mid = 0.5_rk * (ec%s_n(:, b, br) + ec%s_1(:, b, br))
                if (br == 0) then
                    lhs_s = lhs_s + dot_product(s_mid, s_rows(ec, residual, br, b) &
                        - s_rows(ec, r_previous, br, b))
                else
                    lhs_s = lhs_s + dot_product(s_mid, s_rows(ec, residual, br, b))
                end if
            end do
        end do
        lhs = lhs_m + lhs_s
        call element_energies(ec, t_n, t_1, w_n, w_1, w_ext, w_act, dissipation)
        rhs = t_1 - t_n + w_1 - w_n - w_ext - w_act + dissipation
        scale = max(t_n, t_1, w_n, w_1, abs(w_ext), abs(w_act), dissipation, abs(lhs_m), &
            abs(lhs_s))
    end subroutine energy_identity

    subroutine test_energy_identity_element()
        type(element_case_t) :: ec
        real(rk) :: lhs, rhs, scale, t_n, t_1, w_n, w_1, w_ext, w_act, dissipation
        integer :: p, ng, sample
        do p = 1, 2
            do ng = p, 3
                do sample = 1, 5
                    ec = random_case(p, ng)
                    call solve_kinematic_rows(ec)
                    call energy_identity(ec, lhs, rhs, scale)
                    call element_energies(ec, t_n, t_1, w_n, w_1, w_ext, w_act, dissipation)
                    CHECK_TRUE(abs(w_ext) > 1.0e-4_rk * scale, 'non-trivial external work')
                    CHECK_TRUE(abs(rhs) > 1.0e-4_rk * scale, 'non-trivial energy change')
                    CHECK_CLOSE(w_act, 0.0_rk, 0.0_rk, 0.0_rk, 'no actuators: W_act = 0')
                    CHECK_CLOSE(dissipation, 0.0_rk, 0.0_rk, 0.0_rk, 'no branches: D = 0')
                    CHECK_CLOSE(lhs, rhs, exact_tol * scale, 0.0_rk, 'element energy identity')
                end do
            end do
        end do
    end subroutine test_energy_identity_element

    ! The discrete energy proof with the nodal rows of the element's nodes (methods §5.3 items
    ! 1, 2): with the kinematic rows solved, nodal multipliers and end loads,
    !   sum_a v_mid,a^T (R_M,a + R_node,a) + s_mid^T [R_S(q_1, s_1) - R_S(q_n, s_n)]
    !     - sum_a lambda_a . (g(d_1,a) - g(d_n,a)) + sum_a lambda_a . G_d(d_mid,a) R_K,d,a
    !   = Delta T + Delta W* - W_ext (distributed and nodal loads),
    ! where the last sum is round-off (R_K = 0) and the multiplier power of the director rows,
    ! h v_mid . G_d(d_mid)^T lambda = lambda . (g(d_1) - g(d_n)) (g quadratic), cancels the
    ! third. When the step is solved (R = 0, g(d_n) = 0) this is Delta H = W_ext. Node 1 is
    ! clamped (no multiplier), which must not change the identity.
    subroutine test_energy_identity_with_nodes()
        type(element_case_t) :: ec
        real(rk) :: r_node(30), lambda(6), force(3), moment(3), w_act, dissipation
        real(rk) :: lhs, rhs, scale, t_n, t_1, w_n, w_1, w_ext, v_mid(12), d_mid(9), w_node
        integer :: p, sample, nen, a
        logical :: with_lambda
        do p = 1, 2
            do sample = 1, 5
                ec = random_case(p, 2)
                call solve_kinematic_rows(ec)
                nen = ec%basis%nen
                call energy_identity(ec, lhs, rhs, scale)
                call element_energies(ec, t_n, t_1, w_n, w_1, w_ext, w_act, dissipation)
                do a = 1, nen
                    with_lambda = a > 1
                    lambda = random_vector(6, 2.0_rk)
                    force = random_vector(3, 1.0_rk)
                    moment = random_vector(3, 1.0_rk)
                    call ph_director_node_residual(ec%h, .false., ec%q_n(:, a), ec%q_1(:, a), &
                        ec%v_n(:, a), ec%v_1(:, a), lambda, with_lambda, force, moment, r_node)
                    w_node = ph_director_node_external_work(ec%h, ec%q_n(:, a), &
                        ec%q_1(:, a), ec%v_n(:, a), ec%v_1(:, a), force, moment)
                    rhs = rhs - w_node
                    scale = max(scale, abs(w_node))
                    v_mid = 0.5_rk * (ec%v_n(:, a) + ec%v_1(:, a))
                    d_mid = 0.5_rk * (ec%q_n(4:12, a) + ec%q_1(4:12, a))
                    lhs = lhs + dot_product(v_mid, r_node(13:24))
                    if (with_lambda) then
                        lhs = lhs - dot_product(lambda, &
                            r_node(25:30) - ph_director_node_constraint(ec%q_n(:, a)))
                        lhs = lhs + constraint_power(lambda, d_mid, r_node(4:12))
                    end if
                end do
                CHECK_CLOSE(lhs, rhs, exact_tol * scale, 0.0_rk, 'energy identity with nodes')
            end do
        end do
    end subroutine test_energy_identity_with_nodes

    ! The element energy identity with generalized-Maxwell branches, rigid components,
    ! pressure chambers and tendons: dissipation D >= 0 and actuator work enter exactly
    ! (methods §3.1 eqs. 59-61, §3.2, §5.3 item 1).
    subroutine test_energy_identity_maxwell_actuation()
        type(element_case_t) :: ec
        real(rk) :: lhs, rhs, scale, t_n, t_1, w_n, w_1, w_ext, w_act, dissipation, worst, tol
        integer :: p, ng, sample, nb, variant
        logical :: rigid(6)
        character(len=80) :: text
        worst = 0.0_rk
        do variant = 1, 2
            rigid = merge(inextensible, no_rigid, variant == 2)
            do nb = 1, 2
                do p = 1, 2
                    do ng = p, 3
                        do sample = 1, 3
                            ec = random_case(p, ng)
                            call add_branches(ec, nb, rigid)
                            call zero_inactive_branch_stresses(ec)
                            call add_pneumatic(ec)
                            call add_tendons(ec, 2)
                            call solve_kinematic_rows(ec)
                            call energy_identity(ec, lhs, rhs, scale)
                            call element_energies(ec, t_n, t_1, w_n, w_1, w_ext, w_act, &
                                dissipation)
                            CHECK_TRUE(dissipation > 1.0e-4_rk * scale, 'non-trivial D > 0')
                            CHECK_TRUE(abs(w_act) > 1.0e-4_rk * scale, 'non-trivial W_act')
                            tol = exact_tol * scale
                            CHECK_CLOSE(lhs, rhs, tol, 0.0_rk, 'identity, branches, actuators')
                            worst = max(worst, abs(lhs - rhs) / scale)
                        end do
                    end do
                end do
            end do
        end do
        write(text, '(a,es9.2)') '    max relative energy-identity error: ', worst
        write(output_unit, '(a)') trim(text)
    end subroutine test_energy_identity_maxwell_actuation

    ! The solved-step form of the energy balance (methods §5.3 item 1, §3.1, §3.2): kinematic
    ! rows exact, stresses consistent at t_n (elastic rows zero at q_n) and s_1 solving every
    ! stress row at t_{n+1}; then only the momentum residual remains,
    !   v_mid^T R_M = Delta T + Delta W* - W_ext - W_act + D,
    ! so a solved step has H_1 - H_n = W_ext + W_act - D with D >= 0.
    subroutine test_energy_balance_solved_stresses()
        type(element_case_t) :: ec, previous
        real(rk) :: residual(max_local), rows(max_local), zero(max_local), lhs, rhs, scale
        real(rk) :: t_n, t_1, w_n, w_1, w_ext, w_act, dissipation, worst, tol
        integer :: p, ng, sample, nb, n, ns, a
        character(len=80) :: text
        worst = 0.0_rk
        do nb = 0, 2
            do p = 1, 2
                ! p = 2 under 1-point Gauss has a singular C_e (rank 1): no unique stress.
                do ng = p, 3
                    do sample = 1, 3
                        ec = random_case(p, ng)
                        call add_branches(ec, nb, no_rigid)
                        call add_pneumatic(ec)
                        call add_tendons(ec, 1 + mod(sample, 2))
                        call solve_kinematic_rows(ec)
                        n = local_size(ec)
                        ns = n - 24 * ec%basis%nen
                        ! Consistent elastic stresses at t_n: the elastic rows at q_n vanish.
                        previous = ec
                        previous%q_1 = ec%q_n
                        call solve_stress_rows(previous, rows, scale)
                        ec%s_n(:, :, 0) = previous%s_1(:, :, 0)
                        call solve_stress_rows(ec, rows, scale)
                        zero = 0.0_rk
                        tol = exact_tol * scale
                        CHECK_CLOSE(rows(1:ns), zero(1:ns), tol, 0.0_rk, 'stress rows solved')
                        call element_residual(ec, residual(1:n))
                        lhs = 0.0_rk
                        do a = 1, ec%basis%nen
                            lhs = lhs + dot_product(0.5_rk * (ec%v_n(:, a) + ec%v_1(:, a)), &
                                v_rows(residual, a))
                        end do
                        call element_energies(ec, t_n, t_1, w_n, w_1, w_ext, w_act, dissipation)
                        rhs = t_1 - t_n + w_1 - w_n - w_ext - w_act + dissipation
                        scale = max(t_n, t_1, w_n, w_1, abs(w_ext), abs(w_act), dissipation, &
                            abs(lhs))
                        if (nb > 0) then
                            CHECK_TRUE(dissipation > 0.0_rk, 'D > 0 with branches')
                        else
                            CHECK_CLOSE(dissipation, 0.0_rk, 0.0_rk, 0.0_rk, 'D = 0, no branches')
                        end if
                        CHECK_TRUE(abs(w_act) > 1.0e-4_rk * scale, 'non-trivial W_act')
                        tol = exact_tol * scale
                        CHECK_CLOSE(lhs, rhs, tol, 0.0_rk, 'v_mid R_M = dH - W_ext - W_act + D')
                        worst = max(worst, abs(lhs - rhs) / scale)
                    end do
                end do
            end do
        end do
        write(text, '(a,es9.2)') '    max relative energy-balance error (solved stresses): ', worst
        write(output_unit, '(a)') trim(text)
    end subroutine test_energy_balance_solved_stresses

    ! Maxwell dissipation D_n = h int sum_i s_mid^(i) . F_i s_mid^(i) ds (methods §3.1 eq. 60):
    ! zero without branches or with s_mid = 0, non-negative, and in closed form where the
    ! quadrature is diagonal. Actuator work W_act = -h int dsigma_act(q_mid) . eps_dot(q_mid,
    ! v_mid) ds: zero without actuators or at zero midpoint velocity, and exactly the power the
    ! actuators put into the momentum rows, W_act = -v_mid^T [R_M - R_M(no actuators)], for
    ! any state.
    subroutine test_dissipation_and_actuator_work()
        type(element_case_t) :: ec, bare
        real(rk) :: residual(max_local), r_bare(max_local), s_mid(6), dissipation, expected
        real(rk) :: t_n, t_1, w_n, w_1, w_ext, w_act, power, scale
        integer :: p, ng, sample, n, nb, br, b, a, nen
        do p = 1, 2
            do ng = p, 3
                do sample = 1, 3
                    ec = random_case(p, ng)
                    call element_energies(ec, t_n, t_1, w_n, w_1, w_ext, w_act, dissipation)
                    CHECK_CLOSE(dissipation, 0.0_rk, 0.0_rk, 0.0_rk, 'D = 0 without branches')
                    CHECK_CLOSE(w_act, 0.0_rk, 0.0_rk, 0.0_rk, 'W_act = 0 without actuators')
                    nb = 1 + mod(sample, 2)
                    call add_branches(ec, nb, kirchhoff)
                    call element_energies(ec, t_n, t_1, w_n, w_1, w_ext, w_act, dissipation)
                    CHECK_TRUE(dissipation > 0.0_rk, 'D > 0 with branches')
                    ! Closed form where psi_b(xi_g) = delta_bg: p = 1 (any rule), p = 2 with
                    ! 2-point Gauss (le/2 per stress point).
                    if (p == 1 .or. ng == 2) then
                        expected = 0.0_rk
                        do br = 1, nb
                            do b = 1, p
                                s_mid = 0.5_rk * (ec%s_n(:, b, br) + ec%s_1(:, b, br))
                                expected = expected + ec%le / real(p, rk) &
                                    * sum(ec%material%branch_fluidity(:, br) * s_mid**2)
                            end do
                        end do
                        expected = ec%h * expected
                        CHECK_CLOSE(dissipation, expected, 0.0_rk, 1.0e-14_rk, 'D in closed form')
                    end if
                    ec%s_1 = -ec%s_n
                    call element_energies(ec, t_n, t_1, w_n, w_1, w_ext, w_act, dissipation)
                    CHECK_CLOSE(dissipation, 0.0_rk, 0.0_rk, 0.0_rk, 'D = 0 at s_mid = 0')
                    ! Actuators on an arbitrary (not solved) state.
                    call add_pneumatic(ec)
                    call add_tendons(ec, 2)
                    n = local_size(ec)
                    bare = ec
                    bare%actuation = ph_director_actuation_t()
                    call element_residual(ec, residual(1:n))
                    call element_residual(bare, r_bare(1:n))
                    power = 0.0_rk
                    do a = 1, ec%basis%nen
                        power = power + dot_product(0.5_rk * (ec%v_n(:, a) + ec%v_1(:, a)), &
                            v_rows(residual, a) - v_rows(r_bare, a))
                    end do
                    call element_energies(ec, t_n, t_1, w_n, w_1, w_ext, w_act, dissipation)
                    nen = ec%basis%nen
                    scale = maxval(abs(residual(1:24 * nen) - r_bare(1:24 * nen))) &
                        * maxval(abs(ec%v_n(:, 1:nen) + ec%v_1(:, 1:nen)))
                    CHECK_TRUE(abs(w_act) > 1.0e-3_rk * scale, 'non-trivial W_act')
                    scale = exact_tol * scale
                    CHECK_CLOSE(w_act, -power, scale, 0.0_rk, 'W_act = -v_mid (R_M - R_M bare)')
                    ec%v_1 = -ec%v_n
                    call element_energies(ec, t_n, t_1, w_n, w_1, w_ext, w_act, dissipation)
                    CHECK_CLOSE(w_act, 0.0_rk, 0.0_rk, 0.0_rk, 'W_act = 0 at v_mid = 0')
                    ec%v_n = 0.0_rk
                    ec%v_1 = 0.0_rk
                    call element_energies(ec, t_n, t_1, w_n, w_1, w_ext, w_act, dissipation)
                    CHECK_CLOSE(w_act, 0.0_rk, 0.0_rk, 0.0_rk, 'W_act = 0 at rest')
                end do
            end do
        end do
    end subroutine test_dissipation_and_actuator_work

    ! Tendon stress in closed form (methods §3.2 eqs. 62-65).
    ! (1) On a straight, uniformly stretched state with orthonormal directors, r' = phi' =
    !     lambda d3, so t = d3 and, for a tendon at offset rho = rho^1 d1 + rho^2 d2 with
    !     tension T, dN = T R^T d3 = T (0, 0, 1) and dM = T R^T (rho x d3) = T (rho^2, -rho^1, 0):
    !     the tendon acts exactly like a pressure chamber with tau = T at the same offset, whose
    !     material stress is tau (0, 0, 1, rho^2, -rho^1, 0) by construction.
    ! (2) A pressure chamber's stress is added to the stress in the momentum rows: the same
    !     momentum rows as an elastic stress equal to it.
    ! (3) With a single Gauss point the tendon stress is one vector, computed here from its
    !     definition dN_i = T d_i . t, dM_i = T d_i . (rho x t), t = r'/|r'|, r' = phi' +
    !     rho^a d_a', at q_t of a curved state with non-orthonormal interpolated directors; the
    !     kernel with the tendons equals the kernel with that vector as pneumatic stress.
    subroutine test_tendon_closed_form()
        type(element_case_t) :: ec, chamber, elastic
        real(rk) :: residual(max_local), r_chamber(max_local), rot(3, 3), origin(3), stretch
        real(rk) :: tension, rho(2), q_t(12, ph_director_max_nodes), nn(3), dn(3), x(12), xs(12)
        real(rk) :: dsig(6), rho_v(3), r_s(3), t(3), tol, v_elastic(max_local), v_chamber(max_local)
        integer :: p, ng, sample, n, nen, a, i, k, kind
        do p = 1, 2
            do ng = p, 3
                do sample = 1, 3
                    do kind = 1, 3
                        ! (1) straight state; kind 1: offset (r, 0); 2: general; 3: two tendons
                        ec = random_case(p, ng)
                        ec%static = sample == 3
                        nen = ec%basis%nen
                        rot = random_rotation()
                        origin = random_vector(3, 2.0_rk)
                        stretch = uniform(0.8_rk, 1.25_rk)
                        do a = 1, nen
                            ec%q_n(1:3, a) = origin + stretch * ec%le * real(a - 1, rk) &
                                / real(p, rk) * rot(:, 3)
                            ec%q_n(4:12, a) = reshape(rot, [9])
                        end do
                        ec%q_1 = ec%q_n
                        chamber = ec
                        ec%actuation%n_tendons = merge(2, 1, kind == 3)
                        do k = 1, ec%actuation%n_tendons
                            tension = uniform(0.5_rk, 2.0_rk)
                            rho = random_vector(2, 0.3_rk)
                            if (kind == 1) rho(2) = 0.0_rk
                            ec%actuation%tendon(:, k) = [tension, rho]
                            chamber%actuation%pneumatic = chamber%actuation%pneumatic &
                                + tension * [0.0_rk, 0.0_rk, 1.0_rk, rho(2), -rho(1), 0.0_rk]
                        end do
                        n = local_size(ec)
                        call element_residual(ec, residual(1:n))
                        call element_residual(chamber, r_chamber(1:n))
                        tol = exact_tol * maxval(abs(residual(1:n)))
                        CHECK_CLOSE(residual(1:n), r_chamber(1:n), tol, 0.0_rk, 'straight: tendon')
                    end do
                    ! (2) chamber stress = elastic stress in the momentum rows.
                    ec = random_case(p, ng)
                    call add_pneumatic(ec)
                    nen = ec%basis%nen
                    n = local_size(ec)
                    ec%s_n = 0.0_rk
                    ec%s_1 = 0.0_rk
                    elastic = ec
                    elastic%actuation = ph_director_actuation_t()
                    do a = 1, p
                        elastic%s_n(:, a, 0) = ec%actuation%pneumatic
                        elastic%s_1(:, a, 0) = ec%actuation%pneumatic
                    end do
                    call element_residual(ec, residual(1:n))
                    call element_residual(elastic, r_chamber(1:n))
                    do a = 1, nen
                        v_chamber(12 * (a - 1) + 1:12 * a) = v_rows(residual, a)
                        v_elastic(12 * (a - 1) + 1:12 * a) = v_rows(r_chamber, a)
                    end do
                    tol = exact_tol * maxval(abs(v_chamber(1:12 * nen)))
                    n = 12 * nen
                    CHECK_CLOSE(v_chamber(1:n), v_elastic(1:n), tol, 0.0_rk, 'chamber = stress')
                end do
            end do
            ! (3) one Gauss point (so degree 1), curved state, two tendons, midpoint and static.
            do sample = 1, 6
                ec = random_case(1, 1)
                ec%static = sample > 3
                call add_tendons(ec, 2)
                nen = ec%basis%nen
                n = local_size(ec)
                if (ec%static) then
                    q_t(:, 1:nen) = ec%q_1(:, 1:nen)
                else
                    q_t(:, 1:nen) = 0.5_rk * (ec%q_n(:, 1:nen) + ec%q_1(:, 1:nen))
                end if
                call ph_director_basis_shape(ec%basis, ec%basis%xi(1), nn(1:nen), dn(1:nen))
                x = matmul(q_t(:, 1:nen), nn(1:nen))
                xs = matmul(q_t(:, 1:nen), dn(1:nen)) * (2.0_rk / ec%le)
                dsig = 0.0_rk
                do k = 1, 2
                    tension = ec%actuation%tendon(1, k)
                    rho = ec%actuation%tendon(2:3, k)
                    rho_v = rho(1) * x(4:6) + rho(2) * x(7:9)
                    r_s = xs(1:3) + rho(1) * xs(4:6) + rho(2) * xs(7:9)
                    t = r_s / norm2(r_s)
                    do i = 1, 3
                        dsig(i) = dsig(i) + tension * dot_product(x(3 * i + 1:3 * i + 3), t)
                        dsig(3 + i) = dsig(3 + i) &
                            + tension * dot_product(x(3 * i + 1:3 * i + 3), cross(rho_v, t))
                    end do
                end do
                chamber = ec
                chamber%actuation = ph_director_actuation_t()
                chamber%actuation%pneumatic = dsig
                call element_residual(ec, residual(1:n))
                call element_residual(chamber, r_chamber(1:n))
                tol = exact_tol * maxval(abs(residual(1:n)))
                CHECK_CLOSE(residual(1:n), r_chamber(1:n), tol, 0.0_rk, 'curved: tendon stress')
            end do
        end do
    end subroutine test_tendon_closed_form

    ! methods §5.3 items 4, 5 at element level: with q_1 = q_n + h v_mid (kinematic rows
    ! solved) and everything at the midpoint,
    !   l_1 - l_n = sum_a (phi_a x R_phi,a + sum_i d_i,a x R_di,a)
    !               + h int (phi x nbar + 1/2 sum_i d_i x (mbar x d_i)) ds,
    !   p_1 - p_n = sum_a R_phi,a + h le nbar.
    ! The internal forces (branches and actuators included) have zero resultant and moment.
    subroutine test_angular_momentum_balance()
        type(element_case_t) :: ec
        real(rk) :: residual(max_local), lin_n(3), lin_1(3), ang_n(3), ang_1(3)
        real(rk) :: expected(3), point(3), q_mid(12, 3), x(12), r(12), scale, change(3)
        integer :: p, ng, sample, n, nen, a, g, i, variant
        do variant = 1, 2
            do p = 1, 2
                do ng = p, 3
                    do sample = 1, 4
                        ec = random_case(p, ng)
                        if (variant == 2) then
                            call add_branches(ec, 2, kirchhoff)
                            call add_pneumatic(ec)
                            call add_tendons(ec, 2)
                        end if
                        nen = ec%basis%nen
                        n = local_size(ec)
                        call solve_kinematic_rows(ec)
                        call element_residual(ec, residual(1:n))
                        call ph_director_element_momenta(ec%basis, ec%material, ec%le, &
                            ec%q_n(:, 1:nen), ec%v_n(:, 1:nen), lin_n, ang_n)
                        call ph_director_element_momenta(ec%basis, ec%material, ec%le, &
                            ec%q_1(:, 1:nen), ec%v_1(:, 1:nen), lin_1, ang_1)
                        q_mid(:, 1:nen) = 0.5_rk * (ec%q_n(:, 1:nen) + ec%q_1(:, 1:nen))
                        expected = nodal_torque(q_mid, residual, nen)
                        do g = 1, ng
                            x = matmul(q_mid(:, 1:nen), ec%basis%shape(1:nen, g))
                            point = cross(x(1:3), ec%nbar)
                            do i = 1, 3
                                point = point + 0.5_rk * cross(x(3 * i + 1:3 * i + 3), &
                                    cross(ec%mbar, x(3 * i + 1:3 * i + 3)))
                            end do
                            expected = expected + ec%h * 0.5_rk * ec%le * ec%basis%w(g) * point
                        end do
                        scale = maxval(abs(ang_1)) + maxval(abs(ang_n))
                        change = ang_1 - ang_n
                        CHECK_CLOSE(change, expected, exact_tol * scale, 0.0_rk, 'angular balance')
                        expected = ec%h * ec%le * ec%nbar
                        do a = 1, nen
                            r = v_rows(residual, a)
                            expected = expected + r(1:3)
                        end do
                        scale = maxval(abs(lin_1)) + maxval(abs(lin_n))
                        change = lin_1 - lin_n
                        CHECK_CLOSE(change, expected, exact_tol * scale, 0.0_rk, 'linear balance')
                    end do
                end do
            end do
        end do
    end subroutine test_angular_momentum_balance

    ! Internal forces of any state have zero resultant and zero moment (partition of unity and
    ! invariance of the strains and actuator stresses under superposed rotations, methods §5.3
    ! items 4, 5), also in a static step and with branches and actuators; a rigid motion of the
    ! straight reference has the reference strains (methods §2.2, V10).
    subroutine test_rigid_body()
        type(element_case_t) :: ec
        type(ph_director_basis_t) :: basis
        real(rk) :: residual(max_local), q_t(12, 3), resultant(3), torque(3), scale, r(12), tol
        real(rk) :: q(12, 3), rot(3, 3), origin(3), le, gamma(3, 2), kappa(3, 2), g0(3), zero(3)
        integer :: p, ng, sample, n, nen, a, b
        logical :: ok
        g0 = [0.0_rk, 0.0_rk, 1.0_rk]
        zero = 0.0_rk
        do p = 1, 2
            do ng = p, 3
                do sample = 1, 6
                    ec = random_case(p, ng)
                    if (sample > 2) then
                        call add_branches(ec, 1, no_rigid)
                        call add_pneumatic(ec)
                        call add_tendons(ec, 2)
                    end if
                    ec%static = mod(sample, 2) == 0
                    nen = ec%basis%nen
                    n = local_size(ec)
                    ec%v_1 = ec%v_n
                    ec%nbar = 0.0_rk
                    ec%mbar = 0.0_rk
                    call element_residual(ec, residual(1:n))
                    resultant = 0.0_rk
                    scale = 0.0_rk
                    do a = 1, nen
                        r = v_rows(residual, a)
                        resultant = resultant + r(1:3)
                        scale = max(scale, maxval(abs(r)))
                    end do
                    tol = exact_tol * scale
                    CHECK_CLOSE(resultant, zero, tol, 0.0_rk, 'internal forces sum to zero')
                    if (ec%static) then
                        q_t(:, 1:nen) = ec%q_1(:, 1:nen)
                    else
                        q_t(:, 1:nen) = 0.5_rk * (ec%q_n(:, 1:nen) + ec%q_1(:, 1:nen))
                    end if
                    torque = nodal_torque(q_t, residual, nen)
                    CHECK_CLOSE(torque, zero, 10.0_rk * tol, 0.0_rk, 'internal moment is zero')
                end do
                ! Rigid rotation and translation of the straight stress-free reference.
                call ph_director_basis_init(basis, p, ng, ok)
                do sample = 1, 5
                    rot = random_rotation()
                    origin = random_vector(3, 5.0_rk)
                    le = uniform(0.2_rk, 2.0_rk)
                    do a = 1, p + 1
                        q(1:3, a) = origin + le * real(a - 1, rk) / real(p, rk) * rot(:, 3)
                        q(4:12, a) = reshape(rot, [9])
                    end do
                    call ph_director_element_strains(basis, le, q(:, 1:p + 1), gamma(:, 1:p), &
                        kappa(:, 1:p))
                    do b = 1, p
                        CHECK_CLOSE(gamma(:, b), g0, 1.0e-13_rk, 0.0_rk, 'rigid Gamma = (0, 0, 1)')
                        CHECK_CLOSE(kappa(:, b), zero, 1.0e-13_rk, 0.0_rk, 'rigid K = 0')
                    end do
                end do
            end do
        end do
    end subroutine test_rigid_body

    ! Superposed rigid rotation (methods §5.3 item 7, V10): rotating q, v, nbar and mbar rotates
    ! every 3-block of the momentum rows and leaves the stress rows unchanged (branches, rigid
    ! components, actuators and static steps included); the nodal rows likewise (kinematic and
    ! momentum rows rotate, constraint rows are invariant).
    subroutine test_objectivity()
        type(element_case_t) :: ec
        real(rk) :: rot(3, 3), tol
        real(rk) :: q_n(12), q_1(12), v_n(12), v_1(12), lambda(6), force(3), moment(3)
        real(rk) :: r_node(30), r_node_rot(30), expected_node(30)
        integer :: p, ng, sample
        logical :: static
        do p = 1, 2
            do ng = p, 3
                do sample = 1, 4
                    ec = random_case(p, ng)
                    if (sample > 2) then
                        call add_branches(ec, 2, inextensible)
                        call add_pneumatic(ec)
                        call add_tendons(ec, 2)
                    end if
                    ec%static = mod(sample, 2) == 0
                    call check_rotated_residual(ec, 'rotated element residual')
                end do
            end do
        end do
        do sample = 1, 6
            static = sample > 3
            call random_node(q_n, q_1, v_n, v_1, lambda, force, moment)
            rot = random_rotation()
            call ph_director_node_residual(0.2_rk, static, q_n, q_1, v_n, v_1, lambda, .true., &
                force, moment, r_node)
            q_n = rotate_blocks(rot, q_n)
            q_1 = rotate_blocks(rot, q_1)
            v_n = rotate_blocks(rot, v_n)
            v_1 = rotate_blocks(rot, v_1)
            force = matmul(rot, force)
            moment = matmul(rot, moment)
            call ph_director_node_residual(0.2_rk, static, q_n, q_1, v_n, v_1, lambda, .true., &
                force, moment, r_node_rot)
            expected_node = r_node
            expected_node(1:24) = rotate_blocks(rot, r_node(1:24))
            tol = exact_tol * maxval(abs(r_node))
            CHECK_CLOSE(r_node_rot, expected_node, tol, 0.0_rk, 'rotated node residual')
        end do
    end subroutine test_objectivity

    ! The element residual of a case with everything rotated by a random rotation (states,
    ! velocities, loads) is the rotated residual: momentum rows rotated, stress rows (material
    ! components) unchanged.
    subroutine check_rotated_residual(ec, label)
        type(element_case_t), intent(in) :: ec
        character(len=*), intent(in) :: label
        type(element_case_t) :: rotated
        real(rk) :: residual(max_local), r_rot(max_local), expected(max_local), rot(3, 3), tol
        integer :: n, nen, a
        nen = ec%basis%nen
        n = local_size(ec)
        rot = random_rotation()
        rotated = ec
        do a = 1, nen
            rotated%q_n(:, a) = rotate_blocks(rot, ec%q_n(:, a))
            rotated%q_1(:, a) = rotate_blocks(rot, ec%q_1(:, a))
            rotated%v_n(:, a) = rotate_blocks(rot, ec%v_n(:, a))
            rotated%v_1(:, a) = rotate_blocks(rot, ec%v_1(:, a))
        end do
        rotated%nbar = matmul(rot, ec%nbar)
        rotated%mbar = matmul(rot, ec%mbar)
        call element_residual(ec, residual(1:n))
        call element_residual(rotated, r_rot(1:n))
        expected(1:n) = residual(1:n)
        expected(1:24 * nen) = rotate_blocks(rot, residual(1:24 * nen))
        tol = exact_tol * maxval(abs(residual(1:n)))
        CHECK_CLOSE(r_rot(1:n), expected(1:n), tol, 0.0_rk, label)
    end subroutine check_rotated_residual

    ! Strain consistency of the non-rate stress rows (methods §2.8 eqs. 96e-f, §5.3 item 3):
    ! with a stress basis that interpolates at the Gauss points (p = 2 with 2 points, p = 1
    ! with 1 point) the rows hold pointwise at each stress point b, with w_b = le/2 w_g,
    !   elastic: w_b [C s_1 - (eps(q_1) - eps_0)]  (eps_0 the case's reference strain at b)
    !   branch:  w_b [C_i (s_1 - s_n) + h/2 F_i (s_1 + s_n) - (eps(q_1) - eps(q_n))]
    !            (no viscous term in a static step), s_1 for a rigid component,
    ! so a solved step has C s = eps - eps_0 at the stress points at every step. With the
    ! kinematic rows solved, the difference of the elastic rows at t_{n+1} and t_n is the old
    ! rate form C (s_1 - s_n) - (eps(q_1) - eps(q_n)) = C (s_1 - s_n) - h eps_dot(q_mid, v_mid).
    subroutine test_strain_consistency()
        type(element_case_t) :: ec
        real(rk) :: residual(max_local), gamma_n(3, 2), kappa_n(3, 2), gamma_1(3, 2), kappa_1(3, 2)
        real(rk) :: expected(6), eps_n(6), eps_1(6), tol, r(6), wb, h_visc
        integer :: p, sample, n, b, br, l
        do p = 1, 2
            do sample = 1, 6
                ec = random_case(p, p)
                if (sample > 2) call add_branches(ec, 2, kirchhoff)
                ec%static = mod(sample, 2) == 0
                h_visc = merge(0.0_rk, ec%h, ec%static)
                n = local_size(ec)
                call solve_kinematic_rows(ec)
                call element_residual(ec, residual(1:n))
                call ph_director_element_strains(ec%basis, ec%le, ec%q_n(:, 1:p + 1), &
                    gamma_n(:, 1:p), kappa_n(:, 1:p))
                call ph_director_element_strains(ec%basis, ec%le, ec%q_1(:, 1:p + 1), &
                    gamma_1(:, 1:p), kappa_1(:, 1:p))
                do b = 1, p
                    eps_n = [gamma_n(:, b), kappa_n(:, b)]
                    eps_1 = [gamma_1(:, b), kappa_1(:, b)]
                    wb = 0.5_rk * ec%le * ec%basis%w(b)
                    expected = wb * (ec%material%compliance * ec%s_1(:, b, 0) &
                        - (eps_1 - ec%eps_ref(:, b)))
                    tol = exact_tol * maxval(abs(expected))
                    r = s_rows(ec, residual, 0, b)
                    CHECK_CLOSE(r, expected, tol, 0.0_rk, 'strain consistency (elastic rows)')
                    do br = 1, ec%material%n_branches
                        do l = 1, 6
                            if (ec%material%branch_active(l, br)) then
                                expected(l) = wb * (ec%material%branch_compliance(l, br) &
                                    * (ec%s_1(l, b, br) - ec%s_n(l, b, br)) + 0.5_rk * h_visc &
                                    * ec%material%branch_fluidity(l, br) &
                                    * (ec%s_1(l, b, br) + ec%s_n(l, b, br)) &
                                    - (eps_1(l) - eps_n(l)))
                            else
                                expected(l) = ec%s_1(l, b, br)
                            end if
                        end do
                        tol = exact_tol * maxval(abs(expected))
                        r = s_rows(ec, residual, br, b)
                        CHECK_CLOSE(r, expected, tol, 0.0_rk, 'strain consistency (branch rows)')
                    end do
                end do
            end do
        end do
    end subroutine test_strain_consistency

    ! Momenta in the mass-matrix form: with h = 0 the momentum rows are M_e (v_1 - v_n), so
    ! with v_n = 0 they give the mass-matrix products the momenta must equal (methods §5.3
    ! item 4); linear momentum is also the quadrature of rhoA v_phi^h.
    subroutine test_momenta()
        type(element_case_t) :: ec
        real(rk) :: residual(max_local), linear(3), angular(3), expected(3), r(12), u(12), scale
        integer :: p, ng, sample, n, nen, a, g
        do p = 1, 2
            do ng = p, 4
                do sample = 1, 3
                    ec = random_case(p, ng)
                    nen = ec%basis%nen
                    n = local_size(ec)
                    ec%h = 0.0_rk
                    ec%v_n = 0.0_rk
                    call element_residual(ec, residual(1:n))
                    call ph_director_element_momenta(ec%basis, ec%material, ec%le, &
                        ec%q_1(:, 1:nen), ec%v_1(:, 1:nen), linear, angular)
                    expected = 0.0_rk
                    do a = 1, nen
                        r = v_rows(residual, a)
                        expected = expected + r(1:3)
                    end do
                    scale = maxval(abs(linear))
                    CHECK_CLOSE(linear, expected, exact_tol * scale, 0.0_rk, 'linear = sum M v')
                    expected = 0.0_rk
                    do g = 1, ng
                        u = matmul(ec%v_1(:, 1:nen), ec%basis%shape(1:nen, g))
                        expected = expected &
                            + 0.5_rk * ec%le * ec%basis%w(g) * ec%material%rhoA * u(1:3)
                    end do
                    CHECK_CLOSE(linear, expected, exact_tol * scale, 0.0_rk, 'p = int rhoA v_phi')
                    expected = nodal_torque(ec%q_1, residual, nen)
                    scale = maxval(abs(angular))
                    CHECK_CLOSE(angular, expected, exact_tol * scale, 0.0_rk, 'l = sum q x M v')
                end do
            end do
        end do
    end subroutine test_momenta

    ! Kinetic and complementary energies, mass matrix entries and the position integral.
    subroutine test_energies_and_mass()
        type(ph_director_basis_t) :: basis
        type(ph_director_material_t) :: material
        real(rk) :: v(12, 3), q(12, 3), s(6, 2, 0:2), s_p1(6, 1, 0:0), le, vel(3), linear(3)
        real(rk) :: angular(3), energy
        real(rk) :: expected, rot(3, 3), origin(3), centre(3), integral(3)
        real(rk), parameter :: mass_p2(3) = [4.0_rk, 16.0_rk, 4.0_rk] / 30.0_rk
        integer :: p, ng, a, b, br
        logical :: ok
        material = random_material()
        do p = 1, 2
            do ng = p, 5
                call ph_director_basis_init(basis, p, ng, ok)
                le = uniform(0.2_rk, 2.0_rk)
                ! Rigid translation: T = 1/2 m |V|^2 and p = m V with m = rhoA le, any rule.
                vel = random_vector(3, 1.0_rk)
                v = 0.0_rk
                q = 0.0_rk
                do a = 1, p + 1
                    v(1:3, a) = vel
                end do
                energy = ph_director_element_kinetic_energy(basis, material, le, v(:, 1:p + 1))
                expected = 0.5_rk * material%rhoA * le * dot_product(vel, vel)
                CHECK_CLOSE(energy, expected, 0.0_rk, 1.0e-14_rk, 'T of a translation')
                call ph_director_element_momenta(basis, material, le, q(:, 1:p + 1), &
                    v(:, 1:p + 1), linear, angular)
                vel = material%rhoA * le * vel
                CHECK_CLOSE(linear, vel, 0.0_rk, 1.0e-14_rk, 'p of a translation')
                ! Exactly integrated consistent mass (2n - 1 >= 2p): diagonal entries of
                ! le/6 [2 1; 1 2] and le/30 [4 2 -1; 2 16 2; -1 2 4], for each mass block.
                if (2 * ng - 1 >= 2 * p) then
                    do a = 1, p + 1
                        v = 0.0_rk
                        v(:, a) = 1.0_rk
                        energy = ph_director_element_kinetic_energy(basis, material, le, &
                            v(:, 1:p + 1))
                        if (p == 1) then
                            expected = le / 3.0_rk
                        else
                            expected = le * mass_p2(a)
                        end if
                        expected = 1.5_rk * expected * (material%rhoA + sum(material%rhoI))
                        CHECK_CLOSE(energy, expected, 0.0_rk, 1.0e-14_rk, 'mass matrix diagonal')
                    end do
                end if
                ! Straight rigid piece: int phi ds = le (origin + le/2 d3).
                rot = random_rotation()
                origin = random_vector(3, 3.0_rk)
                do a = 1, p + 1
                    q(1:3, a) = origin + le * real(a - 1, rk) / real(p, rk) * rot(:, 3)
                end do
                centre = le * (origin + 0.5_rk * le * rot(:, 3))
                integral = ph_director_element_position_integral(basis, le, q(:, 1:p + 1))
                CHECK_CLOSE(integral, centre, 1.0e-14_rk, 1.0e-14_rk, 'int phi ds')
            end do
        end do
        ! Complementary energy: diagonal under 2-point Gauss with p = 2, 1/2 le C s^2 for p = 1.
        call ph_director_basis_init(basis, 2, 2, ok)
        le = 0.7_rk
        s = 0.0_rk
        s(:, 1:2, 0) = reshape(random_vector(12, 1.0_rk), [6, 2])
        energy = ph_director_element_complementary_energy(basis, material, le, s(:, :, 0:0))
        expected = 0.25_rk * le * (sum(material%compliance * s(:, 1, 0)**2) &
            + sum(material%compliance * s(:, 2, 0)**2))
        CHECK_CLOSE(energy, expected, 0.0_rk, 1.0e-14_rk, 'W* (p = 2, 2-point Gauss)')
        call ph_director_basis_init(basis, 1, 3, ok)
        s_p1(:, 1, 0) = s(:, 1, 0)
        energy = ph_director_element_complementary_energy(basis, material, le, s_p1)
        expected = 0.5_rk * le * sum(material%compliance * s(:, 1, 0)**2)
        CHECK_CLOSE(energy, expected, 0.0_rk, 1.0e-14_rk, 'W* (p = 1)')
        ! With two Maxwell branches W* sums 1/2 s^(i) C_i s^(i) over all branches (methods §3.1).
        material%n_branches = 2
        do br = 1, 2
            material%branch_compliance(:, br) = [(uniform(0.2_rk, 2.0_rk), a = 1, 6)]
            material%branch_active(:, br) = .true.
            s(:, 1:2, br) = reshape(random_vector(12, 1.0_rk), [6, 2])
        end do
        call ph_director_basis_init(basis, 2, 2, ok)
        energy = ph_director_element_complementary_energy(basis, material, le, s)
        expected = 0.0_rk
        do b = 1, 2
            expected = expected + sum(material%compliance * s(:, b, 0)**2)
            do br = 1, 2
                expected = expected + sum(material%branch_compliance(:, br) * s(:, b, br)**2)
            end do
        end do
        expected = 0.25_rk * le * expected
        CHECK_CLOSE(energy, expected, 0.0_rk, 1.0e-14_rk, 'W* with two branches')
    end subroutine test_energies_and_mass

    subroutine test_constraint()
        real(rk) :: q(12), rot(3, 3), g(6), expected(6)
        integer :: sample
        do sample = 1, 10
            rot = random_rotation()
            q(1:3) = random_vector(3, 1.0_rk)
            q(4:12) = reshape(rot, [9])
            g = ph_director_node_constraint(q)
            expected = 0.0_rk
            CHECK_CLOSE(g, expected, 1.0e-15_rk, 0.0_rk, 'orthonormal directors: g = 0')
            q(4:6) = 2.0_rk * q(4:6)
            q(7:9) = q(7:9) + rot(:, 3)
            g = ph_director_node_constraint(q)
            ! d1 = 2 e1', d2 = e2' + e3', d3 = e3' in the rotated basis e'.
            expected = [1.5_rk, 0.5_rk, 0.0_rk, 0.0_rk, 0.5_rk, 0.0_rk]
            CHECK_CLOSE(g, expected, 1.0e-14_rk, 0.0_rk, 'g of scaled, sheared directors')
        end do
    end subroutine test_constraint

    ! ---------------------------------------------------------------------------------------
    ! Reference strains (docs/theory/ph_director.md, "curved stress-free reference")

    ! Nodes of one element of a helix with random axis, radius, pitch and start, its first node
    ! at arc length s0 and reference length le; frame parallel-transported from default d1.
    subroutine helix_element(nen, le, q)
        integer, intent(in) :: nen
        real(rk), intent(in) :: le
        real(rk), intent(out) :: q(12, nen)
        type(rod_geometry_t) :: helix
        real(rk) :: d(3, 3), s0, s
        integer :: a
        helix = helix_geometry(random_vector(3, 1.0_rk), random_unit_vector(), &
            uniform(0.2_rk, 1.0_rk), uniform(-0.5_rk, 0.5_rk), 2.0_rk)
        call set_start_director(helix, default_normal(centreline_tangent(helix, 0.0_rk)))
        s0 = uniform(0.0_rk, helix%length - le)
        do a = 1, nen
            s = s0 + le * real(a - 1, rk) / real(nen - 1, rk)
            q(1:3, a) = centreline_point(helix, s)
            d = centreline_frame(helix, s)
            q(4:12, a) = reshape(d, [9])
        end do
    end subroutine helix_element

    ! A rigidly placed straight element: its reference strains are Gamma_0 = (0, 0, 1), K_0 = 0
    ! up to round-off, and at that state with zero stress and velocity the residual is zero.
    subroutine test_reference_strains_straight()
        type(element_case_t) :: ec
        real(rk) :: residual(max_local), rot(3, 3), origin(3), expected(6)
        integer :: p, ng, sample, a, g, n, nen
        do p = 1, 2
            do ng = p, 3
                do sample = 1, 4
                    ec = random_case(p, ng)
                    nen = ec%basis%nen
                    rot = random_rotation()
                    origin = random_vector(3, 5.0_rk)
                    do a = 1, nen
                        ec%q_n(1:3, a) = origin + ec%le * real(a - 1, rk) / real(p, rk) * rot(:, 3)
                        ec%q_n(4:12, a) = reshape(rot, [9])
                    end do
                    call ph_director_element_reference_strains(ec%basis, ec%le, ec%q_n(:, 1:nen), &
                        ec%eps_ref(:, 1:ng))
                    do g = 1, ng
                        expected = ph_director_straight_strain
                        CHECK_CLOSE(ec%eps_ref(:, g), expected, 1.0e-13_rk, 0.0_rk, 'straight reference strains')
                    end do
                    call rest_at_reference(ec)
                    n = local_size(ec)
                    call element_residual(ec, residual(1:n))
                    CHECK_TRUE(maxval(abs(residual(1:n))) == 0.0_rk, 'straight reference: zero residual')
                end do
            end do
        end do
    end subroutine test_reference_strains_straight

    ! q_1 = q_n, v = 0, s = 0, no loads or actuators.
    subroutine rest_at_reference(ec)
        type(element_case_t), intent(inout) :: ec
        ec%q_1 = ec%q_n
        ec%v_n = 0.0_rk
        ec%v_1 = 0.0_rk
        ec%s_n = 0.0_rk
        ec%s_1 = 0.0_rk
        ec%nbar = 0.0_rk
        ec%mbar = 0.0_rk
        ec%actuation = ph_director_actuation_t()
    end subroutine rest_at_reference

    ! A curved (helical, hence bent and twisted) reference with its own strains at the Gauss
    ! points is stress-free: at rest there the residual (elastic and Maxwell rows, midpoint and
    ! static steps) is exactly zero, the consistent stress is zero and so is the strain energy;
    ! the strains are objective (a rotated helix has the same ones); the reference is really
    ! curved (K differs from 0), and a deformation of it is not stress-free.
    subroutine test_curved_reference_stress_free()
        type(element_case_t) :: ec
        real(rk) :: residual(max_local), s(6, ph_director_max_degree), eps_rot(6, max_gauss_points)
        real(rk) :: q_rot(12, ph_director_max_nodes), rot(3, 3), energy, zero(6)
        real(rk) :: s_all(6, ph_director_max_degree, 0:max_br)
        integer :: p, ng, sample, a, n, nen
        zero = 0.0_rk
        do p = 1, 2
            do ng = p, 3
                do sample = 1, 4
                    ec = random_case(p, ng)
                    if (sample > 2) call add_branches(ec, 2, kirchhoff)
                    ec%static = mod(sample, 2) == 0
                    ! An element short against the radius of curvature, as in a converged mesh.
                    ec%le = uniform(0.05_rk, 0.3_rk)
                    nen = ec%basis%nen
                    call helix_element(nen, ec%le, ec%q_n(:, 1:nen))
                    call ph_director_element_reference_strains(ec%basis, ec%le, ec%q_n(:, 1:nen), &
                        ec%eps_ref(:, 1:ng))
                    CHECK_TRUE(maxval(abs(ec%eps_ref(4:6, 1:ng))) > 0.1_rk, 'the helix reference is curved (|K| > 0.1)')
                    call rest_at_reference(ec)
                    n = local_size(ec)
                    call element_residual(ec, residual(1:n))
                    CHECK_TRUE(maxval(abs(residual(1:n))) == 0.0_rk, 'curved stress-free reference: zero residual')
                    call ph_director_element_initial_stress(ec%basis, ec%material, ec%le, &
                        ec%q_n(:, 1:nen), ec%eps_ref(:, 1:ng), s(:, 1:p))
                    do a = 1, p
                        CHECK_CLOSE(s(:, a), zero, 0.0_rk, 0.0_rk, 'consistent stress is zero')
                    end do
                    s_all = 0.0_rk
                    s_all(:, 1:p, 0) = s(:, 1:p)
                    energy = ph_director_element_complementary_energy(ec%basis, ec%material, &
                        ec%le, s_all(:, 1:p, 0:ec%material%n_branches))
                    CHECK_TRUE(energy == 0.0_rk, 'zero strain energy in the reference')
                    rot = random_rotation()
                    do a = 1, nen
                        q_rot(:, a) = rotate_blocks(rot, ec%q_n(:, a))
                    end do
                    call ph_director_element_reference_strains(ec%basis, ec%le, q_rot(:, 1:nen), &
                        eps_rot(:, 1:ng))
                    CHECK_CLOSE(eps_rot(:, 1:ng), ec%eps_ref(:, 1:ng), 1.0e-13_rk, 0.0_rk, 'objective strains')
                    ec%q_1(1:3, nen) = ec%q_1(1:3, nen) + 0.01_rk * random_unit_vector()
                    call element_residual(ec, residual(1:n))
                    CHECK_TRUE(maxval(abs(residual(24 * nen + 1:n))) > 1.0e-6_rk, 'a deformed reference is not stress-free')
                end do
            end do
        end do
    end subroutine test_curved_reference_stress_free

    ! prestressed: with the straight reference strains, a helical initial geometry gets the
    ! consistent elastic stresses ph_director_element_initial_stress, which solve the elastic
    ! stress rows at that geometry (to round-off) and are zero in rigid components.
    subroutine test_prestressed_initial_stress()
        type(element_case_t) :: ec
        real(rk) :: residual(max_local), s(6, ph_director_max_degree), r(6), tol, zero(6)
        integer :: p, ng, sample, n, nen, b, g
        zero = 0.0_rk
        do p = 1, 2
            do ng = p, 3
                do sample = 1, 4
                    ec = random_case(p, ng)
                    if (sample > 2) ec%material%compliance(1:2) = 0.0_rk
                    nen = ec%basis%nen
                    call helix_element(nen, ec%le, ec%q_n(:, 1:nen))
                    do g = 1, ng
                        ec%eps_ref(:, g) = ph_director_straight_strain
                    end do
                    call ph_director_element_initial_stress(ec%basis, ec%material, ec%le, &
                        ec%q_n(:, 1:nen), ec%eps_ref(:, 1:ng), s(:, 1:p))
                    call rest_at_reference(ec)
                    ec%s_n(:, 1:p, 0) = s(:, 1:p)
                    ec%s_1(:, 1:p, 0) = s(:, 1:p)
                    CHECK_TRUE(maxval(abs(s(4:6, 1:p))) > 0.1_rk, 'a bent start is prestressed')
                    if (sample > 2) CHECK_TRUE(all(s(1:2, 1:p) == 0.0_rk), 'rigid components: 0')
                    n = local_size(ec)
                    call element_residual(ec, residual(1:n))
                    tol = exact_tol * ec%le * (1.0_rk + maxval(abs(s(:, 1:p))))
                    do b = 1, p
                        r = s_rows(ec, residual, 0, b)
                        if (sample > 2) r(1:2) = 0.0_rk
                        CHECK_CLOSE(r, zero, tol, 0.0_rk, 'prestress solves the stress rows')
                    end do
                end do
            end do
        end do
    end subroutine test_prestressed_initial_stress

    ! ---------------------------------------------------------------------------------------
    ! Damping (docs/theory/ph_director.md "Damping")

    ! The element Jacobian with the Kelvin-Voigt stress (its q columns, through the condensed
    ! s_v and through B(q_mid)) and the drags (v columns), alone and with branches, rigid
    ! components and actuators; a static step has no damping, and its Jacobian stays right.
    subroutine test_element_jacobian_fd_damping()
        call check_fd_family('Kelvin-Voigt', .false., 0, no_rigid, .false., 0, .true., .false.)
        call check_fd_family('drag', .false., 0, no_rigid, .false., 0, .false., .true.)
        call check_fd_family('Kelvin-Voigt and drag', .false., 0, no_rigid, .false., 0, .true., &
            .true.)
        call check_fd_family('damped, inextensible, 1 branch, pneumatic, 2 tendons', .false., 1, &
            inextensible, .true., 2, .true., .true.)
        call check_fd_family('damped, kirchhoff, 2 branches', .false., 2, kirchhoff, .false., 0, &
            .true., .true.)
        call check_fd_family('damped, static', .true., 1, kirchhoff, .false., 0, .true., .true.)
    end subroutine test_element_jacobian_fd_damping

    ! The element energy identity (energy_identity) with damping: the momentum rows take out
    ! exactly the dissipation D = h int s_v . V^{-1} s_v + h int u_mid . diag(c, c_w/2) u_mid
    ! of ph_director_element_damping_dissipation, for each law alone and together, with
    ! branches, rigid components and actuators; each law's D is positive.
    subroutine test_energy_identity_damping()
        type(element_case_t) :: ec
        real(rk) :: lhs, rhs, scale, viscous, external, worst
        integer :: p, ng, sample, variant, nen
        logical :: rigid(6)
        character(len=80) :: text
        worst = 0.0_rk
        do variant = 1, 4
            rigid = merge(inextensible, no_rigid, variant == 4)
            do p = 1, 2
                do ng = p, 3
                    do sample = 1, 3
                        ec = random_case(p, ng)
                        if (variant == 4) then
                            call add_branches(ec, 1, rigid)
                            call zero_inactive_branch_stresses(ec)
                            call add_pneumatic(ec)
                            call add_tendons(ec, 2)
                        end if
                        call add_damping(ec, rigid, variant /= 2, variant /= 1)
                        call solve_kinematic_rows(ec)
                        nen = ec%basis%nen
                        call ph_director_element_damping_dissipation(ec%basis, ec%material, &
                            ec%le, ec%h, ec%q_n(:, 1:nen), ec%q_1(:, 1:nen), ec%v_n(:, 1:nen), &
                            ec%v_1(:, 1:nen), viscous, external)
                        call energy_identity(ec, lhs, rhs, scale)
                        if (variant /= 2) then
                            CHECK_TRUE(viscous > 1.0e-4_rk * scale, 'Kelvin-Voigt D > 0')
                        else
                            CHECK_CLOSE(viscous, 0.0_rk, 0.0_rk, 0.0_rk, 'no viscosity: D = 0')
                        end if
                        if (variant /= 1) then
                            CHECK_TRUE(external > 1.0e-4_rk * scale, 'drag D > 0')
                        else
                            CHECK_CLOSE(external, 0.0_rk, 0.0_rk, 0.0_rk, 'no drag: D = 0')
                        end if
                        CHECK_CLOSE(lhs, rhs, exact_tol * scale, 0.0_rk, 'identity with damping')
                        worst = max(worst, abs(lhs - rhs) / scale)
                    end do
                end do
            end do
        end do
        write(text, '(a,es9.2)') '    max relative energy-identity error with damping: ', worst
        write(output_unit, '(a)') trim(text)
    end subroutine test_energy_identity_damping

    ! The dissipation in closed form. Kelvin-Voigt: where the stress basis interpolates at the
    ! Gauss points (p = 1 with 1 point, p = 2 with 2), s_v = V (eps_1 - eps_n)/h at the stress
    ! points, so D = h sum_b w_b s_v . V^{-1} s_v = sum_b (le/p) Delta eps . V Delta eps / h,
    ! Delta eps from ph_director_element_strains. Drag: a uniform translation and rotation
    ! rate with orthonormal directors, v_phi = u, v_i = w x d_i at every node, dissipates
    ! D = h le (c |u|^2 + c_w |w|^2): sum_i |w x d_i|^2 = 2 |w|^2, so the forces -c_w/2 v_i
    ! are the moment -c_w w. Zero at rest (q_1 = q_n, v_1 = -v_n); none in a static step.
    subroutine test_damping_dissipation()
        type(element_case_t) :: ec, bare
        real(rk) :: viscous, external, expected, gamma_n(3, 2), kappa_n(3, 2), gamma_1(3, 2)
        real(rk) :: kappa_1(3, 2), strain(6), rot(3, 3), u(3), w(3), residual(max_local)
        real(rk) :: r_bare(max_local)
        integer :: p, sample, nen, b, a, i, n
        do p = 1, 2
            do sample = 1, 4
                ec = random_case(p, p)
                call add_damping(ec, no_rigid, .true., .true.)
                nen = ec%basis%nen
                call ph_director_element_damping_dissipation(ec%basis, ec%material, ec%le, ec%h, &
                    ec%q_n(:, 1:nen), ec%q_1(:, 1:nen), ec%v_n(:, 1:nen), ec%v_1(:, 1:nen), &
                    viscous, external)
                call ph_director_element_strains(ec%basis, ec%le, ec%q_n(:, 1:nen), &
                    gamma_n(:, 1:p), kappa_n(:, 1:p))
                call ph_director_element_strains(ec%basis, ec%le, ec%q_1(:, 1:nen), &
                    gamma_1(:, 1:p), kappa_1(:, 1:p))
                expected = 0.0_rk
                do b = 1, p
                    strain = [gamma_1(:, b) - gamma_n(:, b), kappa_1(:, b) - kappa_n(:, b)]
                    expected = expected + ec%le / real(p, rk) &
                        * sum(ec%material%viscosity * strain**2) / ec%h
                end do
                CHECK_TRUE(viscous > 0.0_rk, 'Kelvin-Voigt D > 0')
                CHECK_CLOSE(viscous, expected, 0.0_rk, 1.0e-12_rk, 'Kelvin-Voigt D in closed form')
                ! Uniform rates on orthonormal directors.
                rot = random_rotation()
                u = random_vector(3, 1.0_rk)
                w = random_vector(3, 1.0_rk)
                do a = 1, nen
                    ec%q_n(4:12, a) = reshape(rot, [9])
                    ec%v_n(1:3, a) = u
                    do i = 1, 3
                        ec%v_n(3 * i + 1:3 * i + 3, a) = cross(w, rot(:, i))
                    end do
                end do
                ec%v_1 = ec%v_n
                call ph_director_element_damping_dissipation(ec%basis, ec%material, ec%le, ec%h, &
                    ec%q_n(:, 1:nen), ec%q_1(:, 1:nen), ec%v_n(:, 1:nen), ec%v_1(:, 1:nen), &
                    viscous, external)
                expected = ec%h * ec%le * (ec%material%drag * dot_product(u, u) &
                    + ec%material%angular_drag * dot_product(w, w))
                CHECK_CLOSE(external, expected, 0.0_rk, 1.0e-13_rk, 'drag D in closed form')
                ! At rest: nothing dissipated.
                ec%q_1 = ec%q_n
                ec%v_1 = -ec%v_n
                call ph_director_element_damping_dissipation(ec%basis, ec%material, ec%le, ec%h, &
                    ec%q_n(:, 1:nen), ec%q_1(:, 1:nen), ec%v_n(:, 1:nen), ec%v_1(:, 1:nen), &
                    viscous, external)
                CHECK_CLOSE(viscous, 0.0_rk, 0.0_rk, 0.0_rk, 'Kelvin-Voigt D = 0 at q_1 = q_n')
                CHECK_CLOSE(external, 0.0_rk, 0.0_rk, 0.0_rk, 'drag D = 0 at v_mid = 0')
                ! A static step (the endpoint equilibrium) has no damping.
                ec = random_case(p, 2)
                ec%static = .true.
                bare = ec
                call add_damping(ec, no_rigid, .true., .true.)
                n = local_size(ec)
                call element_residual(ec, residual(1:n))
                call element_residual(bare, r_bare(1:n))
                CHECK_CLOSE(residual(1:n), r_bare(1:n), 0.0_rk, 0.0_rk, 'static: no damping')
            end do
        end do
    end subroutine test_damping_dissipation

    ! The strains are objective, so a rigid motion between t_n and t_{n+1} (q_1 = R q_n + c)
    ! has no strain increment and no Kelvin-Voigt stress: the residual is that of the
    ! undamped element, the dissipation zero to round-off (docs/theory/damping.md).
    subroutine test_rigid_motion_not_damped()
        type(element_case_t) :: ec, bare
        real(rk) :: residual(max_local), r_bare(max_local), rot(3, 3), shift(3), tol
        real(rk) :: viscous, external, moving
        integer :: p, ng, sample, n, nen, a
        do p = 1, 2
            do ng = p, 3
                do sample = 1, 3
                    ec = random_case(p, ng)
                    nen = ec%basis%nen
                    rot = random_rotation()
                    shift = random_vector(3, 1.0_rk)
                    do a = 1, nen
                        ec%q_1(:, a) = rotate_blocks(rot, ec%q_n(:, a))
                        ec%q_1(1:3, a) = ec%q_1(1:3, a) + shift
                    end do
                    bare = ec
                    call add_damping(ec, no_rigid, .true., .false.)
                    n = local_size(ec)
                    call element_residual(ec, residual(1:n))
                    call element_residual(bare, r_bare(1:n))
                    tol = exact_tol * maxval(abs(r_bare(1:n)))
                    CHECK_CLOSE(residual(1:n), r_bare(1:n), tol, 0.0_rk, 'rigid motion: no s_v')
                    call ph_director_element_damping_dissipation(ec%basis, ec%material, ec%le, &
                        ec%h, ec%q_n(:, 1:nen), ec%q_1(:, 1:nen), ec%v_n(:, 1:nen), &
                        ec%v_1(:, 1:nen), viscous, external)
                    ! Against the dissipation of a strain increment of size 1 over the step.
                    moving = ec%le * maxval(ec%material%viscosity) / ec%h
                    CHECK_CLOSE(viscous, 0.0_rk, 1.0e-24_rk * moving, 0.0_rk, 'rigid motion: D = 0')
                end do
            end do
        end do
    end subroutine test_rigid_motion_not_damped

    ! The damped element residual is objective (everything rotated: the residual rotated), and
    ! the Kelvin-Voigt forces are internal: zero resultant and zero moment about the origin
    ! through q_mid (methods §5.3 items 4, 5), so they keep both momenta.
    subroutine test_damping_objective_and_internal()
        type(element_case_t) :: ec, bare
        real(rk) :: residual(max_local), tol
        real(rk) :: r_bare(max_local), forces(max_local), q_mid(12, 3), resultant(3), torque(3)
        real(rk) :: zero(3), scale
        integer :: p, ng, sample, n, nen, a
        zero = 0.0_rk
        do p = 1, 2
            do ng = p, 3
                do sample = 1, 3
                    ec = random_case(p, ng)
                    if (sample == 3) then
                        call add_branches(ec, 1, kirchhoff)
                        call add_tendons(ec, 1)
                    end if
                    call add_damping(ec, merge(kirchhoff, no_rigid, sample == 3), .true., .true.)
                    call check_rotated_residual(ec, 'rotated damped residual')
                    nen = ec%basis%nen
                    n = local_size(ec)
                    ! The Kelvin-Voigt forces alone: damped minus undamped, drag off.
                    ec%material%drag = 0.0_rk
                    ec%material%angular_drag = 0.0_rk
                    bare = ec
                    bare%material%viscosity = 0.0_rk
                    call element_residual(ec, residual(1:n))
                    call element_residual(bare, r_bare(1:n))
                    forces(1:n) = residual(1:n) - r_bare(1:n)
                    scale = maxval(abs(forces(1:24 * nen))) * (1.0_rk + maxval(abs(ec%q_n)) &
                        + maxval(abs(ec%q_1)))
                    CHECK_TRUE(maxval(abs(forces(1:24 * nen))) > 1.0e-3_rk, 'viscous forces act')
                    resultant = 0.0_rk
                    do a = 1, nen
                        resultant = resultant + forces(24 * (a - 1) + 13:24 * (a - 1) + 15)
                    end do
                    q_mid(:, 1:nen) = 0.5_rk * (ec%q_n(:, 1:nen) + ec%q_1(:, 1:nen))
                    torque = nodal_torque(q_mid, forces, nen)
                    tol = exact_tol * scale
                    CHECK_CLOSE(resultant, zero, tol, 0.0_rk, 'viscous forces: no resultant')
                    CHECK_CLOSE(torque, zero, tol, 0.0_rk, 'viscous forces: no moment')
                end do
            end do
        end do
    end subroutine test_damping_objective_and_internal

end module rs_test_ph_director_element

program test_ph_director_element
    use rs_test_ph_director_element, only: run_all_tests
    use rs_test_assert, only: finish_tests
    implicit none
    call run_all_tests()
    call finish_tests()
end program test_ph_director_element
