#include "rs_assert.h"
!> Unit tests of rs_ph_director_element (methods/ph_director_3d.md §2, §4, §5): analytic
!> Jacobians against central finite differences, the skew (power) structure, the exact discrete
!> energy and angular-momentum balances of one step, rigid-body and objectivity properties,
!> strain consistency, momenta, energies and the reference-element data.
!>
!> Residuals are at most quadratic in the unknowns, so central differences are exact up to
!> round-off; the tolerances below bound round-off only.
module rs_test_ph_director_element
    use, intrinsic :: iso_fortran_env, only: output_unit
    use rs_core_kinds, only: rk, pi
    use rs_test_random, only: set_random_seed, random_unit_vector
    use rs_test_assert, only: run_test, assert_true, assert_close
    use rs_math_so3, only: exp_so3
    use rs_math_quadrature, only: max_gauss_points
    use rs_ph_director_element, only: ph_director_material_t, ph_director_basis_t, &
        ph_director_basis_init, ph_director_basis_shape, ph_director_stress_shape, &
        ph_director_local_size, ph_director_element_residual, ph_director_node_residual, &
        ph_director_element_kinetic_energy, ph_director_element_complementary_energy, &
        ph_director_element_momenta, ph_director_element_position_integral, &
        ph_director_element_external_work, ph_director_node_external_work, &
        ph_director_element_strains, ph_director_node_constraint, ph_director_max_nodes, &
        ph_director_node_size
    implicit none
    private

    public :: run_all_tests

    integer, parameter :: max_local = 24 * ph_director_max_nodes + 12
    ! Finite-difference step (relative to max(1, |x|)) and tolerance relative to max |J|.
    real(rk), parameter :: fd_step = 1.0e-6_rk, fd_tol = 1.0e-6_rk
    ! Round-off tolerance of exact identities, relative to the size of their terms.
    real(rk), parameter :: exact_tol = 1.0e-12_rk

    !> One random step of one element: endpoint states, loads, geometry and material.
    type :: element_case_t
        type(ph_director_basis_t) :: basis
        type(ph_director_material_t) :: material
        real(rk) :: le = 1.0_rk, h = 0.1_rk
        real(rk) :: q_n(12, ph_director_max_nodes) = 0.0_rk
        real(rk) :: q_1(12, ph_director_max_nodes) = 0.0_rk
        real(rk) :: v_n(12, ph_director_max_nodes) = 0.0_rk
        real(rk) :: v_1(12, ph_director_max_nodes) = 0.0_rk
        real(rk) :: s_n(6, 2) = 0.0_rk, s_1(6, 2) = 0.0_rk
        real(rk) :: nbar(3) = 0.0_rk, mbar(3) = 0.0_rk
    end type element_case_t

contains

    !> Run every test of this file through rs_test_assert.
    subroutine run_all_tests()
        call set_random_seed(20250117, 104729)
        call run_test('basis_quadrature', test_basis_quadrature)
        call run_test('basis_invalid', test_basis_invalid)
        call run_test('element_jacobian_fd', test_element_jacobian_fd)
        call run_test('node_jacobian_fd', test_node_jacobian_fd)
        call run_test('node_without_lambda', test_node_without_lambda)
        call run_test('power_identity', test_power_identity)
        call run_test('energy_identity_element', test_energy_identity_element)
        call run_test('energy_identity_with_nodes', test_energy_identity_with_nodes)
        call run_test('angular_momentum_balance', test_angular_momentum_balance)
        call run_test('rigid_body', test_rigid_body)
        call run_test('objectivity', test_objectivity)
        call run_test('strain_consistency', test_strain_consistency)
        call run_test('momenta', test_momenta)
        call run_test('energies_and_mass', test_energies_and_mass)
        call run_test('constraint', test_constraint)
    end subroutine run_all_tests

    ! ---------------------------------------------------------------------------------------
    ! Random data

    function uniform(lo, hi) result(x)
        real(rk), intent(in) :: lo, hi
        real(rk) :: x
        call random_number(x)
        x = lo + (hi - lo) * x
    end function uniform

    ! Uniform entries in [-scale, scale].
    function random_vector(n, scale) result(x)
        integer, intent(in) :: n
        real(rk), intent(in) :: scale
        real(rk) :: x(n)
        call random_number(x)
        x = scale * (2.0_rk * x - 1.0_rk)
    end function random_vector

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

    ! A random element step: both endpoint states independent and non-trivial.
    function random_case(degree, n_gauss) result(ec)
        integer, intent(in) :: degree, n_gauss
        type(element_case_t) :: ec
        logical :: ok
        integer :: nen, a
        call ph_director_basis_init(ec%basis, degree, n_gauss, ok)
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
        ec%s_n(:, 1:degree) = reshape(random_vector(6 * degree, 1.0_rk), [6, degree])
        ec%s_1(:, 1:degree) = reshape(random_vector(6 * degree, 1.0_rk), [6, degree])
        ec%nbar = random_vector(3, 1.0_rk)
        ec%mbar = random_vector(3, 1.0_rk)
    end function random_case

    subroutine element_residual(ec, residual, jacobian)
        type(element_case_t), intent(in) :: ec
        real(rk), intent(out) :: residual(:)
        real(rk), intent(out), optional, contiguous :: jacobian(:, :)
        integer :: nen, p
        nen = ec%basis%nen
        p = ec%basis%degree
        call ph_director_element_residual(ec%basis, ec%material, ec%le, ec%h, ec%q_n(:, 1:nen), &
            ec%q_1(:, 1:nen), ec%v_n(:, 1:nen), ec%v_1(:, 1:nen), ec%s_n(:, 1:p), ec%s_1(:, 1:p), &
            ec%nbar, ec%mbar, residual, jacobian)
    end subroutine element_residual

    ! The t_{n+1} unknowns of a case in the element local layout, and back.
    subroutine pack_unknowns(ec, x)
        type(element_case_t), intent(in) :: ec
        real(rk), intent(out) :: x(:)
        integer :: a, b, nen
        nen = ec%basis%nen
        do a = 1, nen
            x(24 * (a - 1) + 1:24 * (a - 1) + 12) = ec%q_1(:, a)
            x(24 * (a - 1) + 13:24 * (a - 1) + 24) = ec%v_1(:, a)
        end do
        do b = 1, ec%basis%degree
            x(24 * nen + 6 * (b - 1) + 1:24 * nen + 6 * b) = ec%s_1(:, b)
        end do
    end subroutine pack_unknowns

    subroutine unpack_unknowns(x, ec)
        real(rk), intent(in) :: x(:)
        type(element_case_t), intent(inout) :: ec
        integer :: a, b, nen
        nen = ec%basis%nen
        do a = 1, nen
            ec%q_1(:, a) = x(24 * (a - 1) + 1:24 * (a - 1) + 12)
            ec%v_1(:, a) = x(24 * (a - 1) + 13:24 * (a - 1) + 24)
        end do
        do b = 1, ec%basis%degree
            ec%s_1(:, b) = x(24 * nen + 6 * (b - 1) + 1:24 * nen + 6 * b)
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

    ! Momentum rows (v rows) of node a and stress rows of coefficient b of an element residual.
    function v_rows(residual, a) result(r)
        real(rk), intent(in) :: residual(:)
        integer, intent(in) :: a
        real(rk) :: r(12)
        r = residual(24 * (a - 1) + 13:24 * a)
    end function v_rows

    function s_rows(residual, nen, b) result(r)
        real(rk), intent(in) :: residual(:)
        integer, intent(in) :: nen, b
        real(rk) :: r(6)
        r = residual(24 * nen + 6 * (b - 1) + 1:24 * nen + 6 * b)
    end function s_rows

    ! Kinetic and complementary energies at both ends and the external work of a case.
    subroutine element_energies(ec, t_n, t_1, w_n, w_1, w_ext)
        type(element_case_t), intent(in) :: ec
        real(rk), intent(out) :: t_n, t_1, w_n, w_1, w_ext
        integer :: nen, p
        nen = ec%basis%nen
        p = ec%basis%degree
        t_n = ph_director_element_kinetic_energy(ec%basis, ec%material, ec%le, ec%v_n(:, 1:nen))
        t_1 = ph_director_element_kinetic_energy(ec%basis, ec%material, ec%le, ec%v_1(:, 1:nen))
        w_n = ph_director_element_complementary_energy(ec%basis, ec%material, ec%le, &
            ec%s_n(:, 1:p))
        w_1 = ph_director_element_complementary_energy(ec%basis, ec%material, ec%le, &
            ec%s_1(:, 1:p))
        w_ext = ph_director_element_external_work(ec%basis, ec%le, ec%h, ec%q_n(:, 1:nen), &
            ec%q_1(:, 1:nen), ec%v_n(:, 1:nen), ec%v_1(:, 1:nen), ec%nbar, ec%mbar)
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

    ! ---------------------------------------------------------------------------------------
    ! Tests

    subroutine test_basis_quadrature()
        type(ph_director_basis_t) :: basis
        real(rk) :: moment, exact, nodes(3), n(3), dn(3), psi(2), delta(3), total
        logical :: ok
        integer :: p, ng, k, g, a
        do p = 1, 2
            do ng = 1, max_gauss_points
                call ph_director_basis_init(basis, p, ng, ok)
                CHECK_TRUE(ok, 'valid degree and rule')
                CHECK_TRUE(basis%nen == p + 1, 'nen = p + 1')
                CHECK_TRUE(ph_director_local_size(basis) == 24 * (p + 1) + 6 * p, 'local size')
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
        CHECK_TRUE(basis%nen == 0, 'rejected basis is empty')
    end subroutine test_basis_invalid

    subroutine test_element_jacobian_fd()
        type(element_case_t) :: ec, ep, em
        real(rk) :: x(max_local), xp(max_local), residual(max_local), rp(max_local)
        real(rk) :: rm(max_local), fd(max_local, max_local)
        real(rk), allocatable :: jac(:, :)
        real(rk) :: step, error, worst, zero(12), q_rows(12)
        integer :: p, ng, sample, n, j, a
        character(len=80) :: text
        worst = 0.0_rk
        zero = 0.0_rk
        do p = 1, 2
            do ng = 1, 3
                do sample = 1, 4
                    ec = random_case(p, ng)
                    n = ph_director_local_size(ec%basis)
                    if (allocated(jac)) deallocate(jac)
                    allocate(jac(n, n))
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
                        fd(1:n, j) = (rp(1:n) - rm(1:n)) / (2.0_rk * step)
                    end do
                    error = maxval(abs(jac - fd(1:n, 1:n))) / maxval(abs(jac))
                    worst = max(worst, error)
                    CHECK_TRUE(error < fd_tol, 'element Jacobian = central differences')
                    ! The same residual without the optional Jacobian.
                    call element_residual(ec, rp(1:n))
                    CHECK_CLOSE(rp(1:n), residual(1:n), 0.0_rk, 0.0_rk, 'without Jacobian')
                    ! The kinematic rows of an element are zero (they are nodal).
                    do a = 1, ec%basis%nen
                        q_rows = residual(24 * (a - 1) + 1:24 * (a - 1) + 12)
                        CHECK_CLOSE(q_rows, zero, 0.0_rk, 0.0_rk, 'q rows zero')
                    end do
                end do
            end do
        end do
        write(text, '(a,es9.2)') '    max relative FD error (element): ', worst
        write(output_unit, '(a)') trim(text)
    end subroutine test_element_jacobian_fd

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

    subroutine test_node_jacobian_fd()
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
                call ph_director_node_residual(h, q_n, q_1, v_n, v_1, lambda, with_lambda, &
                    force, moment, residual, jac)
                x = [q_1, v_1, lambda]
                do j = 1, ph_director_node_size
                    step = fd_step * max(1.0_rk, abs(x(j)))
                    xp = x
                    xp(j) = x(j) + step
                    xm = x
                    xm(j) = x(j) - step
                    call ph_director_node_residual(h, q_n, xp(1:12), v_n, xp(13:24), xp(25:30), &
                        with_lambda, force, moment, rp)
                    call ph_director_node_residual(h, q_n, xm(1:12), v_n, xm(13:24), xm(25:30), &
                        with_lambda, force, moment, rm)
                    fd(:, j) = (rp - rm) / (2.0_rk * step)
                end do
                error = maxval(abs(jac - fd)) / maxval(abs(jac))
                worst = max(worst, error)
                CHECK_TRUE(error < fd_tol, 'node Jacobian = central differences')
            end do
        end do
        write(text, '(a,es9.2)') '    max relative FD error (node): ', worst
        write(output_unit, '(a)') trim(text)
    end subroutine test_node_jacobian_fd

    subroutine test_node_without_lambda()
        real(rk) :: q_n(12), q_1(12), v_n(12), v_1(12), lambda(6), force(3), moment(3), h
        real(rk) :: r_with(30), r_without(30), r_zero(30), expected(12), zero(6), g_1(6)
        real(rk) :: d_mid(9), expected_d(9)
        integer :: i
        call random_node(q_n, q_1, v_n, v_1, lambda, force, moment)
        h = 0.3_rk
        zero = 0.0_rk
        call ph_director_node_residual(h, q_n, q_1, v_n, v_1, lambda, .false., force, moment, &
            r_without)
        call ph_director_node_residual(h, q_n, q_1, v_n, v_1, zero, .true., force, moment, r_zero)
        call ph_director_node_residual(h, q_n, q_1, v_n, v_1, lambda, .true., force, moment, &
            r_with)
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
        expected_d(1:3) = lambda(1) * d_mid(1:3) + 0.5_rk * lambda(4) * d_mid(4:6) &
            + 0.5_rk * lambda(6) * d_mid(7:9)
        expected_d(4:6) = 0.5_rk * lambda(4) * d_mid(1:3) + lambda(2) * d_mid(4:6) &
            + 0.5_rk * lambda(5) * d_mid(7:9)
        expected_d(7:9) = 0.5_rk * lambda(6) * d_mid(1:3) + 0.5_rk * lambda(5) * d_mid(4:6) &
            + lambda(3) * d_mid(7:9)
        do i = 1, 3
            expected_d(3 * i - 2:3 * i) = h * expected_d(3 * i - 2:3 * i) &
                - 0.5_rk * h * cross(moment, d_mid(3 * i - 2:3 * i))
        end do
        CHECK_CLOSE(r_with(16:24), expected_d, 1.0e-14_rk, 1.0e-14_rk, 'director rows')
    end subroutine test_node_without_lambda

    ! Skew structure (methods §4.3): the internal forces and the strain-rate operator are
    ! adjoint, v^T f_int(q, s) = s^T int psi eps_dot(q, v) ds for every q, v, s.
    subroutine test_power_identity()
        type(element_case_t) :: ec
        real(rk) :: residual(max_local), power_m, power_s
        integer :: p, ng, sample, n, nen, a, b
        do p = 1, 2
            do ng = 1, 3
                do sample = 1, 5
                    ec = random_case(p, ng)
                    nen = ec%basis%nen
                    n = ph_director_local_size(ec%basis)
                    ! Equal endpoints: no inertia and no compliance term, q_mid = q_n = q_1.
                    ec%q_1 = ec%q_n
                    ec%v_1 = ec%v_n
                    ec%s_1 = ec%s_n
                    ec%nbar = 0.0_rk
                    ec%mbar = 0.0_rk
                    call element_residual(ec, residual(1:n))
                    power_m = 0.0_rk
                    do a = 1, nen
                        power_m = power_m + dot_product(ec%v_n(:, a), v_rows(residual, a))
                    end do
                    power_s = 0.0_rk
                    do b = 1, p
                        power_s = power_s + dot_product(ec%s_n(:, b), s_rows(residual, nen, b))
                    end do
                    power_m = power_m / ec%h
                    power_s = power_s / ec%h
                    CHECK_TRUE(abs(power_m) > 1.0e-3_rk, 'non-trivial internal power')
                    CHECK_CLOSE(power_m, -power_s, 0.0_rk, exact_tol, 'v^T f_int = s^T eps_dot')
                end do
            end do
        end do
    end subroutine test_power_identity

    ! methods §5.3 item 1 at element level: for arbitrary x_n, x_1,
    ! v_mid^T R_M + s_mid^T R_S = Delta T + Delta W* - W_ext.
    subroutine test_energy_identity_element()
        type(element_case_t) :: ec
        real(rk) :: residual(max_local), lhs, rhs, scale, t_n, t_1, w_n, w_1, w_ext
        integer :: p, ng, sample, n, nen, a, b
        do p = 1, 2
            do ng = 1, 3
                do sample = 1, 5
                    ec = random_case(p, ng)
                    nen = ec%basis%nen
                    n = ph_director_local_size(ec%basis)
                    call element_residual(ec, residual(1:n))
                    lhs = 0.0_rk
                    do a = 1, nen
                        lhs = lhs + dot_product(0.5_rk * (ec%v_n(:, a) + ec%v_1(:, a)), &
                            v_rows(residual, a))
                    end do
                    do b = 1, p
                        lhs = lhs + dot_product(0.5_rk * (ec%s_n(:, b) + ec%s_1(:, b)), &
                            s_rows(residual, nen, b))
                    end do
                    call element_energies(ec, t_n, t_1, w_n, w_1, w_ext)
                    rhs = t_1 - t_n + w_1 - w_n - w_ext
                    scale = max(t_n, t_1, w_n, w_1, abs(w_ext))
                    CHECK_TRUE(abs(w_ext) > 1.0e-4_rk * scale, 'non-trivial external work')
                    CHECK_TRUE(abs(rhs) > 1.0e-4_rk * scale, 'non-trivial energy change')
                    CHECK_CLOSE(lhs, rhs, exact_tol * scale, 0.0_rk, 'element energy identity')
                end do
            end do
        end do
    end subroutine test_energy_identity_element

    ! The discrete energy proof with the nodal rows of the element's nodes (methods §5.3 items
    ! 1, 2): for arbitrary x_n, x_1 with nodal multipliers and end loads,
    !   sum_a v_mid,a^T (R_M,a + R_node,a) + s_mid^T R_S
    !     - sum_a lambda_a . (g(d_1,a) - g(d_n,a)) + sum_a lambda_a . G_d(d_mid,a) R_K,d,a
    !   = Delta T + Delta W* - W_ext (distributed and nodal loads).
    ! When the step is solved (R = 0, g(d_n) = 0) this is Delta H = W_ext. Node 1 is clamped
    ! (no multiplier), which must not change the identity.
    subroutine test_energy_identity_with_nodes()
        type(element_case_t) :: ec
        real(rk) :: residual(max_local), r_node(30), lambda(6), force(3), moment(3)
        real(rk) :: lhs, rhs, scale, t_n, t_1, w_n, w_1, w_ext, v_mid(12), d_mid(9)
        integer :: p, sample, n, nen, a, b
        logical :: with_lambda
        do p = 1, 2
            do sample = 1, 5
                ec = random_case(p, 2)
                nen = ec%basis%nen
                n = ph_director_local_size(ec%basis)
                call element_residual(ec, residual(1:n))
                call element_energies(ec, t_n, t_1, w_n, w_1, w_ext)
                lhs = 0.0_rk
                do b = 1, p
                    lhs = lhs + dot_product(0.5_rk * (ec%s_n(:, b) + ec%s_1(:, b)), &
                        s_rows(residual, nen, b))
                end do
                do a = 1, nen
                    with_lambda = a > 1
                    lambda = random_vector(6, 2.0_rk)
                    force = random_vector(3, 1.0_rk)
                    moment = random_vector(3, 1.0_rk)
                    call ph_director_node_residual(ec%h, ec%q_n(:, a), ec%q_1(:, a), &
                        ec%v_n(:, a), ec%v_1(:, a), lambda, with_lambda, force, moment, r_node)
                    w_ext = w_ext + ph_director_node_external_work(ec%h, ec%q_n(:, a), &
                        ec%q_1(:, a), ec%v_n(:, a), ec%v_1(:, a), force, moment)
                    v_mid = 0.5_rk * (ec%v_n(:, a) + ec%v_1(:, a))
                    d_mid = 0.5_rk * (ec%q_n(4:12, a) + ec%q_1(4:12, a))
                    lhs = lhs + dot_product(v_mid, v_rows(residual, a) + r_node(13:24))
                    if (with_lambda) then
                        lhs = lhs - dot_product(lambda, &
                            r_node(25:30) - ph_director_node_constraint(ec%q_n(:, a)))
                        lhs = lhs + constraint_power(lambda, d_mid, r_node(4:12))
                    end if
                end do
                rhs = t_1 - t_n + w_1 - w_n - w_ext
                scale = max(t_n, t_1, w_n, w_1, abs(w_ext))
                CHECK_CLOSE(lhs, rhs, exact_tol * scale, 0.0_rk, 'energy identity with nodes')
            end do
        end do
    end subroutine test_energy_identity_with_nodes

    ! methods §5.3 items 4, 5 at element level: with q_1 = q_n + h v_mid (kinematic rows
    ! solved) and everything at the midpoint,
    !   l_1 - l_n = sum_a (phi_a x R_phi,a + sum_i d_i,a x R_di,a)
    !               + h int (phi x nbar + 1/2 sum_i d_i x (mbar x d_i)) ds,
    !   p_1 - p_n = sum_a R_phi,a + h le nbar.
    subroutine test_angular_momentum_balance()
        type(element_case_t) :: ec
        real(rk) :: residual(max_local), lin_n(3), lin_1(3), ang_n(3), ang_1(3)
        real(rk) :: expected(3), point(3), q_mid(12, 3), x(12), r(12), scale, change(3)
        integer :: p, ng, sample, n, nen, a, g, i
        do p = 1, 2
            do ng = 1, 3
                do sample = 1, 4
                    ec = random_case(p, ng)
                    nen = ec%basis%nen
                    n = ph_director_local_size(ec%basis)
                    ec%q_1(:, 1:nen) = ec%q_n(:, 1:nen) &
                        + 0.5_rk * ec%h * (ec%v_n(:, 1:nen) + ec%v_1(:, 1:nen))
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
    end subroutine test_angular_momentum_balance

    ! Internal forces of any state have zero resultant and zero moment (partition of unity and
    ! invariance of the strains under superposed rotations, methods §5.3 items 4, 5); a rigid
    ! motion of the straight reference has the reference strains (methods §2.2, V10).
    subroutine test_rigid_body()
        type(element_case_t) :: ec
        type(ph_director_basis_t) :: basis
        real(rk) :: residual(max_local), q_mid(12, 3), resultant(3), torque(3), scale, r(12), tol
        real(rk) :: q(12, 3), rot(3, 3), origin(3), le, gamma(3, 2), kappa(3, 2), g0(3), zero(3)
        integer :: p, ng, sample, n, nen, a, b
        logical :: ok
        g0 = [0.0_rk, 0.0_rk, 1.0_rk]
        zero = 0.0_rk
        do p = 1, 2
            do ng = 1, 3
                do sample = 1, 4
                    ec = random_case(p, ng)
                    nen = ec%basis%nen
                    n = ph_director_local_size(ec%basis)
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
                    q_mid(:, 1:nen) = 0.5_rk * (ec%q_n(:, 1:nen) + ec%q_1(:, 1:nen))
                    torque = nodal_torque(q_mid, residual, nen)
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
    ! every 3-block of the momentum rows and leaves the stress rows unchanged; the nodal rows
    ! likewise (kinematic and momentum rows rotate, constraint rows are invariant).
    subroutine test_objectivity()
        type(element_case_t) :: ec, rotated
        real(rk) :: residual(max_local), r_rot(max_local), expected(max_local), rot(3, 3), tol
        real(rk) :: q_n(12), q_1(12), v_n(12), v_1(12), lambda(6), force(3), moment(3)
        real(rk) :: r_node(30), r_node_rot(30), expected_node(30)
        integer :: p, ng, sample, n, nen, a
        do p = 1, 2
            do ng = 1, 3
                do sample = 1, 3
                    ec = random_case(p, ng)
                    nen = ec%basis%nen
                    n = ph_director_local_size(ec%basis)
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
                    CHECK_CLOSE(r_rot(1:n), expected(1:n), tol, 0.0_rk, 'rotated element residual')
                end do
            end do
        end do
        do sample = 1, 5
            call random_node(q_n, q_1, v_n, v_1, lambda, force, moment)
            rot = random_rotation()
            call ph_director_node_residual(0.2_rk, q_n, q_1, v_n, v_1, lambda, .true., force, &
                moment, r_node)
            q_n = rotate_blocks(rot, q_n)
            q_1 = rotate_blocks(rot, q_1)
            v_n = rotate_blocks(rot, v_n)
            v_1 = rotate_blocks(rot, v_1)
            force = matmul(rot, force)
            moment = matmul(rot, moment)
            call ph_director_node_residual(0.2_rk, q_n, q_1, v_n, v_1, lambda, .true., force, &
                moment, r_node_rot)
            expected_node = r_node
            expected_node(1:24) = rotate_blocks(rot, r_node(1:24))
            tol = exact_tol * maxval(abs(r_node))
            CHECK_CLOSE(r_node_rot, expected_node, tol, 0.0_rk, 'rotated node residual')
        end do
    end subroutine test_objectivity

    ! Strain consistency (methods §5.3 item 3): with q_1 = q_n + h v_mid and a stress basis that
    ! interpolates at the Gauss points (p = 2 with 2 points, p = 1 with 1 point),
    ! R_S = le/2 w [C (s_1 - s_n) - (eps(q_1) - eps(q_n))] at each stress point, pointwise.
    subroutine test_strain_consistency()
        type(element_case_t) :: ec
        real(rk) :: residual(max_local), gamma_n(3, 2), kappa_n(3, 2), gamma_1(3, 2), kappa_1(3, 2)
        real(rk) :: expected(6), tol, r(6)
        integer :: p, sample, n, nen, b
        do p = 1, 2
            do sample = 1, 5
                ec = random_case(p, p)
                nen = ec%basis%nen
                n = ph_director_local_size(ec%basis)
                ec%q_1(:, 1:nen) = ec%q_n(:, 1:nen) &
                    + 0.5_rk * ec%h * (ec%v_n(:, 1:nen) + ec%v_1(:, 1:nen))
                call element_residual(ec, residual(1:n))
                call ph_director_element_strains(ec%basis, ec%le, ec%q_n(:, 1:nen), &
                    gamma_n(:, 1:p), kappa_n(:, 1:p))
                call ph_director_element_strains(ec%basis, ec%le, ec%q_1(:, 1:nen), &
                    gamma_1(:, 1:p), kappa_1(:, 1:p))
                do b = 1, p
                    expected(1:3) = gamma_1(:, b) - gamma_n(:, b)
                    expected(4:6) = kappa_1(:, b) - kappa_n(:, b)
                    expected = 0.5_rk * ec%le * ec%basis%w(b) &
                        * (ec%material%compliance * (ec%s_1(:, b) - ec%s_n(:, b)) - expected)
                    tol = exact_tol * maxval(abs(expected))
                    r = s_rows(residual, nen, b)
                    CHECK_CLOSE(r, expected, tol, 0.0_rk, 'strain consistency')
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
            do ng = 1, 4
                do sample = 1, 3
                    ec = random_case(p, ng)
                    nen = ec%basis%nen
                    n = ph_director_local_size(ec%basis)
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
        real(rk) :: v(12, 3), q(12, 3), s(6, 2), le, vel(3), linear(3), angular(3), energy
        real(rk) :: expected, rot(3, 3), origin(3), centre(3), integral(3)
        real(rk), parameter :: mass_p2(3) = [4.0_rk, 16.0_rk, 4.0_rk] / 30.0_rk
        integer :: p, ng, a
        logical :: ok
        material = random_material()
        do p = 1, 2
            do ng = 1, 5
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
        s(:, 1:2) = reshape(random_vector(12, 1.0_rk), [6, 2])
        energy = ph_director_element_complementary_energy(basis, material, le, s(:, 1:2))
        expected = 0.25_rk * le * (sum(material%compliance * s(:, 1)**2) &
            + sum(material%compliance * s(:, 2)**2))
        CHECK_CLOSE(energy, expected, 0.0_rk, 1.0e-14_rk, 'W* (p = 2, 2-point Gauss)')
        call ph_director_basis_init(basis, 1, 3, ok)
        energy = ph_director_element_complementary_energy(basis, material, le, s(:, 1:1))
        expected = 0.5_rk * le * sum(material%compliance * s(:, 1)**2)
        CHECK_CLOSE(energy, expected, 0.0_rk, 1.0e-14_rk, 'W* (p = 1)')
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

end module rs_test_ph_director_element

program test_ph_director_element
    use rs_test_ph_director_element, only: run_all_tests
    use rs_test_assert, only: finish_tests
    implicit none
    call run_all_tests()
    call finish_tests()
end program test_ph_director_element
