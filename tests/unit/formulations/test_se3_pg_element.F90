#include "rs_assert.h"
!> Unit tests of rs_se3_pg_element (methods/se3_petrov_galerkin.md §5-§6, checklist §15 items
!> 1-3): every analytic Jacobian (internal tangent, gyroscopic, follower force, dead moment,
!> derivative of T^{-1}) against central differences on random states (nodal rotations up to
!> 2.5 rad, rotation vectors beyond pi as met inside Newton before the complement update, angles
!> at and near 0, relative element rotations up to 3 rad); the constant-strain property of the
!> SE(3) interpolation; the quarter circle of Fig. 2; zero internal force and unchanged strains
!> under rigid motions (objectivity); linear momentum; the energy consistency of the
!> Petrov-Galerkin virtual work (exact for zero relative rotation, second order in the element
!> length otherwise); hand-computed stretch, torsion, bending and shear; the mass matrix; the
!> one- and two-element cantilever of methods §10.1 solved by Newton with the analytic tangent
!> against the tip positions of §14.1. Damping (docs/theory/se3_pg.md, "Damping"): the internal
!> force with a viscous stress, its tangent at fixed stress and its derivative in the stress, and
!> the derivative of the element twist, against central differences; the viscous force without
!> stress is the elastic one; the strain rate of a rigid velocity field is zero (a rigid motion
!> is not damped).
!>
!> Central differences use the step fd_step max(1, |x_j|) per unknown; errors are relative per
!> row (to the largest entry of the analytic row).
module rs_test_se3_pg_element
    use, intrinsic :: iso_fortran_env, only: output_unit
    use rs_core_kinds, only: rk, pi
    use rs_test_random, only: set_random_seed, uniform, random_vector
    use rs_test_assert, only: run_test, assert_true, assert_close
    use rs_math_so3, only: vee, exp_so3, log_so3, tangent_so3, tangent_inverse_so3
    use rs_math_se3, only: exp_se3, pose_matrix, pose_inverse, vee_se3, pose_compose
    use rs_math_quadrature, only: gauss_legendre_interval
    use rs_se3_pg_element, only: se3_strains, se3_internal_force, se3_internal_tangent, &
        se3_internal_force_tangent, se3_strain_energy, se3_element_mass, se3_gyroscopic, &
        se3_kinematics, tinv_times_derivative, follower_force, dead_moment, se3_element_twist, &
        se3_mass_solve, se3_viscous_internal_force, se3_twist_tangent
    implicit none
    private

    public :: run_all_tests

    ! Finite-difference step (relative to max(1, |x|)) and tolerance (relative, per row).
    real(rk), parameter :: fd_step = 1.0e-6_rk, fd_tol = 1.0e-6_rk
    ! Kernels of the generic finite-difference driver.
    integer, parameter :: k_internal = 1, k_gyroscopic = 2, k_follower = 3, k_dead = 4, &
        k_tinv = 5, k_viscous = 6, k_viscous_stress = 7, k_twist = 8
    character(len=14), parameter :: kernel_name(8) = [character(len=14) :: 'internal', &
        'gyroscopic', 'follower force', 'dead moment', 'T^-1 w', 'viscous', 'd g / d sigma', &
        'd theta / d q']
    ! Kinds of random states: general, rotation vectors beyond pi, small angles.
    integer, parameter :: general = 1, beyond_pi = 2, small_angles = 3

    !> One random element: reference length, material, reference strains, state, velocity,
    !> and the data of the nodal kernels (a rotation vector, a load and a velocity).
    type :: se3_case_t
        real(rk) :: l = 1.0_rk
        real(rk) :: stiffness(6) = 1.0_rk, eps_ref(6) = 0.0_rk, inertia(3) = 1.0_rk
        real(rk) :: q(12) = 0.0_rk, u(12) = 0.0_rk
        real(rk) :: psi(3) = 0.0_rk, load(3) = 0.0_rk
        !> A viscous stress (n_v, m_v), of the order of a tenth of the stiffnesses.
        real(rk) :: sigma_v(6) = 0.0_rk
    end type se3_case_t

contains

    !> Run every test of this file through rs_test_assert.
    subroutine run_all_tests()
        call set_random_seed(20250611, 7919)
        call run_test('element_mass', test_element_mass)
        call run_test('mass_solve', test_mass_solve)
        call run_test('quarter_circle', test_quarter_circle)
        call run_test('constant_strain', test_constant_strain)
        call run_test('hand_cases', test_hand_cases)
        call run_test('internal_tangent_fd', test_internal_tangent_fd)
        call run_test('viscous_force_fd', test_viscous_force_fd)
        call run_test('rigid_strain_rate', test_rigid_strain_rate)
        call run_test('gyroscopic', test_gyroscopic)
        call run_test('kinematics', test_kinematics)
        call run_test('loads', test_loads)
        call run_test('rigid_motion_objectivity', test_rigid_motion_objectivity)
        call run_test('linear_momentum', test_linear_momentum)
        call run_test('energy_consistency', test_energy_consistency)
        call run_test('cantilever_one_two_elements', test_cantilever)
    end subroutine run_all_tests

    ! ---------------------------------------------------------------------------------------
    ! Random data and helpers

    ! A rotation vector with a random axis and the given angle.
    function random_rotation(angle) result(psi)
        real(rk), intent(in) :: angle
        real(rk) :: psi(3)
        psi = random_vector(3, 1.0_rk)
        do while (norm2(psi) < 0.1_rk)
            psi = random_vector(3, 1.0_rk)
        end do
        psi = angle * psi / norm2(psi)
    end function random_rotation

    pure function cross(a, b) result(c)
        real(rk), intent(in) :: a(3), b(3)
        real(rk) :: c(3)
        c = [a(2) * b(3) - a(3) * b(2), a(3) * b(1) - a(1) * b(3), a(1) * b(2) - a(2) * b(1)]
    end function cross

    ! Element unknowns of node a at (r_a, psi_a) and node b at H_a Exp_SE3(theta); psi_b is the
    ! principal rotation vector of A_b.
    function element_state(r_a, psi_a, theta) result(q)
        real(rk), intent(in) :: r_a(3), psi_a(3), theta(6)
        real(rk) :: q(12)
        real(rk) :: a_a(3, 3), a_rel(3, 3), r_rel(3), a_b(3, 3), r_b(3)
        a_a = exp_so3(psi_a)
        call exp_se3(theta, a_rel, r_rel)
        call pose_compose(a_a, r_a, a_rel, r_rel, a_b, r_b)
        q(1:3) = r_a
        q(4:6) = psi_a
        q(7:9) = r_b
        q(10:12) = log_so3(a_b)
    end function element_state

    ! The other rotation vector of the same rotation, of length 2 pi - |psi| (in (pi, 2 pi)
    ! for 0 < |psi| < pi), as a node carries it inside Newton before the complement update.
    function beyond_pi_vector(psi) result(psi_o)
        real(rk), intent(in) :: psi(3)
        real(rk) :: psi_o(3)
        psi_o = (1.0_rk - 2.0_rk * pi / norm2(psi)) * psi
    end function beyond_pi_vector

    ! A random element: length in [0.3, 3], stretch and shear up to 0.2, relative rotation up
    ! to 3 rad (< pi, methods §5.2), node a rotated up to 2.5 rad; reference strains away from
    ! the state so that n and m are of the order of the stiffnesses. `kind` = beyond_pi: both
    ! rotation vectors replaced by their length-(2 pi - |psi|) twins; small_angles: node
    ! rotation below 1e-3 (exactly 0 in a third of the cases) and relative rotation below 1e-4.
    function random_case(kind) result(c)
        integer, intent(in) :: kind
        type(se3_case_t) :: c
        real(rk) :: theta(6), psi_a(3), rel_angle, node_angle, choice
        c%l = uniform(0.3_rk, 3.0_rk)
        c%stiffness = [uniform(1.0e3_rk, 1.0e4_rk), uniform(5.0e2_rk, 5.0e3_rk), &
            uniform(5.0e2_rk, 5.0e3_rk), uniform(10.0_rk, 100.0_rk), uniform(10.0_rk, 100.0_rk), &
            uniform(10.0_rk, 100.0_rk)]
        rel_angle = uniform(0.0_rk, 3.0_rk)
        node_angle = uniform(0.0_rk, 2.5_rk)
        if (kind == small_angles) then
            call random_number(choice)
            rel_angle = uniform(0.0_rk, 1.0e-4_rk)
            node_angle = merge(0.0_rk, uniform(0.0_rk, 1.0e-3_rk), choice < 1.0_rk / 3.0_rk)
        end if
        theta(1:3) = c%l * ([1.0_rk, 0.0_rk, 0.0_rk] + random_vector(3, 0.2_rk))
        theta(4:6) = random_rotation(rel_angle)
        psi_a = random_rotation(node_angle)
        c%q = element_state(random_vector(3, 2.0_rk), psi_a, theta)
        if (kind == beyond_pi) then
            c%q(4:6) = beyond_pi_vector(c%q(4:6))
            c%q(10:12) = beyond_pi_vector(c%q(10:12))
        end if
        c%eps_ref = theta / c%l + [random_vector(3, 0.1_rk), random_vector(3, 0.5_rk)]
        c%inertia = [uniform(0.5_rk, 2.0_rk), uniform(0.2_rk, 1.0_rk), uniform(0.2_rk, 1.0_rk)]
        c%u = random_vector(12, 3.0_rk)
        c%psi = random_rotation(merge(uniform(0.0_rk, 1.0e-3_rk), uniform(0.0_rk, 3.0_rk), &
            kind == small_angles))
        if (kind == beyond_pi) c%psi = beyond_pi_vector(random_rotation(uniform(0.5_rk, 3.0_rk)))
        c%load = random_vector(3, 10.0_rk)
        c%sigma_v = 0.1_rk * c%stiffness * random_vector(6, 1.0_rk)
    end function random_case

    ! Number of unknowns of a kernel.
    pure integer function n_unknowns(kernel)
        integer, intent(in) :: kernel
        select case (kernel)
        case (k_internal, k_gyroscopic, k_viscous, k_twist)
            n_unknowns = 12
        case (k_viscous_stress)
            n_unknowns = 6
        case default
            n_unknowns = 3
        end select
    end function n_unknowns

    ! Number of force rows of a kernel.
    pure integer function n_rows(kernel)
        integer, intent(in) :: kernel
        select case (kernel)
        case (k_viscous_stress)
            n_rows = 12
        case (k_twist)
            n_rows = 6
        case default
            n_rows = n_unknowns(kernel)
        end select
    end function n_rows

    ! The case's point of evaluation of a kernel.
    function evaluation_point(kernel, c) result(x)
        integer, intent(in) :: kernel
        type(se3_case_t), intent(in) :: c
        real(rk) :: x(12)
        x = 0.0_rk
        select case (kernel)
        case (k_internal, k_viscous, k_twist)
            x = c%q
        case (k_viscous_stress)
            x(1:6) = c%sigma_v
        case (k_gyroscopic)
            x = c%u
        case default
            x(1:3) = c%psi
        end select
    end function evaluation_point

    ! Force f (leading n entries) of a kernel at x, and optionally its analytic Jacobian.
    subroutine kernel_force(kernel, c, x, f, k)
        integer, intent(in) :: kernel
        type(se3_case_t), intent(in) :: c
        real(rk), intent(in) :: x(12)
        real(rk), intent(out) :: f(12)
        real(rk), intent(out), optional :: k(12, 12)
        real(rk) :: g(12), kg(12, 12), f3(3), k3(3, 3), b(3, 3), b_t(12, 6), dtheta(6, 12)
        f = 0.0_rk
        if (present(k)) k = 0.0_rk
        select case (kernel)
        case (k_internal)
            call se3_internal_force(c%l, c%stiffness, c%eps_ref, x, f)
            if (present(k)) call se3_internal_tangent(c%l, c%stiffness, c%eps_ref, x, k)
        case (k_gyroscopic)
            call se3_gyroscopic(c%l, c%inertia, x, g, kg)
            f = g
            if (present(k)) k = kg
        case (k_follower)
            call follower_force(x(1:3), c%load, f3, k3)
        case (k_dead)
            call dead_moment(x(1:3), c%load, f3, k3)
        case (k_tinv)
            call se3_kinematics(x(1:3), b)
            f3 = matmul(b, c%load)
            call tinv_times_derivative(x(1:3), c%load, k3)
        case (k_viscous)
            if (present(k)) then
                call se3_viscous_internal_force(c%l, c%stiffness, c%eps_ref, c%sigma_v, x, f, k)
            else
                call se3_viscous_internal_force(c%l, c%stiffness, c%eps_ref, c%sigma_v, x, f)
            end if
        case (k_viscous_stress)
            call se3_viscous_internal_force(c%l, c%stiffness, c%eps_ref, x(1:6), c%q, f, b_t=b_t)
            if (present(k)) k(:, 1:6) = b_t
        case (k_twist)
            call se3_twist_tangent(x, f(1:6), dtheta)
            if (present(k)) k(1:6, :) = dtheta
        end select
        if (kernel >= k_follower .and. kernel <= k_tinv) then
            f(1:3) = f3
            if (present(k)) k(1:3, 1:3) = k3
        end if
    end subroutine kernel_force

    ! Largest per-row relative difference between a kernel's analytic Jacobian and central
    ! differences at the case's point of evaluation.
    function fd_error(kernel, c) result(error)
        integer, intent(in) :: kernel
        type(se3_case_t), intent(in) :: c
        real(rk) :: error
        real(rk) :: x(12), xp(12), fp(12), fm(12), f(12), k(12, 12), fd(12, 12), step, row_scale
        integer :: n, m, i, j
        n = n_unknowns(kernel)
        m = n_rows(kernel)
        x = evaluation_point(kernel, c)
        call kernel_force(kernel, c, x, f, k)
        fd = 0.0_rk
        do j = 1, n
            step = fd_step * max(1.0_rk, abs(x(j)))
            xp = x
            xp(j) = x(j) + step
            call kernel_force(kernel, c, xp, fp)
            xp(j) = x(j) - step
            call kernel_force(kernel, c, xp, fm)
            fd(1:m, j) = (fp(1:m) - fm(1:m)) / (2.0_rk * step)
        end do
        error = 0.0_rk
        do i = 1, m
            row_scale = maxval(abs(k(i, 1:n)))
            if (row_scale > 0.0_rk) then
                error = max(error, maxval(abs(k(i, 1:n) - fd(i, 1:n))) / row_scale)
            else
                error = max(error, maxval(abs(fd(i, 1:n))))
            end if
        end do
    end function fd_error

    ! FD check of a kernel on random states of each kind; prints the worst error per kind.
    subroutine check_fd_random(kernel, n_samples)
        integer, intent(in) :: kernel, n_samples
        type(se3_case_t) :: c
        real(rk) :: error, worst(3)
        integer :: kind, sample
        character(len=160) :: text
        worst = 0.0_rk
        do kind = general, small_angles
            do sample = 1, n_samples
                c = random_case(kind)
                error = fd_error(kernel, c)
                worst(kind) = max(worst(kind), error)
                CHECK_TRUE(error < fd_tol, trim(kernel_name(kernel)) // ': Jacobian = central differences')
            end do
        end do
        write(text, '(a,3es9.2,a)') '    max relative FD error (' // trim(kernel_name(kernel)) &
            // '; general, |psi| > pi, small angles): ', worst
        write(output_unit, '(a)') trim(text)
    end subroutine check_fd_random

    ! Energy gradient in delta-s space, P^{-T} dE/dq with P = blockdiag(1, T(psi_a), 1,
    ! T(psi_b)), from central differences of se3_strain_energy.
    function energy_gradient_s(c) result(grad)
        type(se3_case_t), intent(in) :: c
        real(rk) :: grad(12)
        real(rk) :: x(12), step, ep, em
        integer :: j
        do j = 1, 12
            step = fd_step * max(1.0_rk, abs(c%q(j)))
            x = c%q
            x(j) = c%q(j) + step
            ep = se3_strain_energy(c%l, c%stiffness, c%eps_ref, x)
            x(j) = c%q(j) - step
            em = se3_strain_energy(c%l, c%stiffness, c%eps_ref, x)
            grad(j) = (ep - em) / (2.0_rk * step)
        end do
        grad(4:6) = matmul(grad(4:6), tangent_inverse_so3(c%q(4:6)))
        grad(10:12) = matmul(grad(10:12), tangent_inverse_so3(c%q(10:12)))
    end function energy_gradient_s

    ! Relative defect |g - P^{-T} dE/dq| / |g| of the virtual work against the energy.
    function energy_defect(c) result(defect)
        type(se3_case_t), intent(in) :: c
        real(rk) :: defect
        real(rk) :: g(12)
        call se3_internal_force(c%l, c%stiffness, c%eps_ref, c%q, g)
        defect = norm2(g - energy_gradient_s(c)) / norm2(g)
    end function energy_defect

    ! ---------------------------------------------------------------------------------------
    ! Mass, strains, hand-computed forces

    ! Consistent mass (methods §6.3): l [[1/3, 1/6], [1/6, 1/3]] (x) blockdiag(rho_a 1,
    ! diag(inertia)); no coupling between components; kinetic energy 1/2 rho_a l |v|^2 of a
    ! translation and 1/2 l omega . I omega of a uniform spin; equal to the 2-point Gauss
    ! integral of N_i N_k.
    subroutine test_element_mass()
        real(rk) :: m(12, 12), l, rho_a, inertia(3), u(12), v(3), w(3), expected(12, 12)
        real(rk) :: node(6), t(2), wt(2), shape(2), energy
        integer :: i, j, a, b, ig
        logical :: ok
        l = 1.5_rk
        rho_a = 2.0_rk
        inertia = [0.8_rk, 0.3_rk, 0.5_rk]
        call se3_element_mass(l, rho_a, inertia, m)
        CHECK_CLOSE(m(1, 1), 1.0_rk, 1.0e-15_rk, 0.0_rk, 'rho_a l/3')
        CHECK_CLOSE(m(8, 2), 0.5_rk, 1.0e-15_rk, 0.0_rk, 'rho_a l/6 (y_b, y_a)')
        CHECK_CLOSE(m(4, 4), 0.4_rk, 1.0e-15_rk, 0.0_rk, 'I_1 l/3')
        CHECK_CLOSE(m(12, 6), 0.125_rk, 1.0e-15_rk, 0.0_rk, 'I_3 l/6')
        CHECK_CLOSE(m, transpose(m), 0.0_rk, 0.0_rk, 'symmetric')
        v = [0.3_rk, -0.7_rk, 1.1_rk]
        u = [v, 0.0_rk, 0.0_rk, 0.0_rk, v, 0.0_rk, 0.0_rk, 0.0_rk]
        energy = 0.5_rk * dot_product(u, matmul(m, u))
        CHECK_CLOSE(energy, 0.5_rk * rho_a * l * dot_product(v, v), 1.0e-14_rk, 0.0_rk, 'translation')
        w = [1.5_rk, -0.4_rk, 0.9_rk]
        u = [0.0_rk, 0.0_rk, 0.0_rk, w, 0.0_rk, 0.0_rk, 0.0_rk, w]
        CHECK_CLOSE(0.5_rk * dot_product(u, matmul(m, u)), 0.5_rk * l * sum(inertia * w**2), 1.0e-14_rk, 0.0_rk, 'spin')
        ! The integral l int N_a N_b dt (x) blockdiag by the 2-point rule of rs_math_quadrature.
        call gauss_legendre_interval(2, 0.0_rk, 1.0_rk, t, wt, ok)
        CHECK_TRUE(ok, '2-point rule')
        node = [rho_a, rho_a, rho_a, inertia]
        expected = 0.0_rk
        do ig = 1, 2
            shape = [1.0_rk - t(ig), t(ig)]
            do a = 1, 2
                do b = 1, 2
                    do i = 1, 6
                        j = 6 * (a - 1) + i
                        expected(j, 6 * (b - 1) + i) = expected(j, 6 * (b - 1) + i) &
                            + l * wt(ig) * shape(a) * shape(b) * node(i)
                    end do
                end do
            end do
        end do
        CHECK_CLOSE(m, expected, 1.0e-15_rk, 0.0_rk, 'mass = 2-point Gauss integral')
    end subroutine test_element_mass

    ! se3_mass_solve on 5 elements of random lengths with some coordinates held (a clamped first
    ! node, a held y at node 3, a held rotation at the last node): the assembled M (from
    ! se3_element_mass) times a equals the right-hand side on the free rows to round-off, and
    ! a = 0 on the held ones.
    subroutine test_mass_solve()
        integer, parameter :: n_el = 5, n = n_el + 1
        real(rk) :: l(n_el), rhs(6, n), a(6, n), m(12, 12), product(6, n), inertia(3), rho_a
        logical :: free(6, n), ok
        integer :: e
        call random_number(l)
        l = 0.2_rk + l
        call random_number(rhs)
        rhs = rhs - 0.5_rk
        rho_a = 3.0_rk
        inertia = [0.02_rk, 0.01_rk, 0.015_rk]
        free = .true.
        free(:, 1) = .false.
        free(2, 3) = .false.
        free(4:6, n) = .false.
        call se3_mass_solve(l, spread(rho_a, 1, size(l)), spread(inertia, 2, size(l)), free, rhs, a)
        product = 0.0_rk
        do e = 1, n_el
            call se3_element_mass(l(e), rho_a, inertia, m)
            product(:, e:e + 1) = product(:, e:e + 1) + reshape(matmul(m, [a(:, e), a(:, e + 1)]), &
                [6, 2])
        end do
        ok = all(abs(product - rhs) <= 1.0e-14_rk .or. .not. free)
        CHECK_TRUE(ok, 'M a = rhs on the free rows')
        ok = all(a == 0.0_rk .or. free)
        CHECK_TRUE(ok, 'a = 0 on the held coordinates')
    end subroutine test_mass_solve

    ! Fig. 2 (methods §8.1, §13 item 6, §14.0): node a at the origin with psi_a = (0, -pi/2, 0),
    ! node b at (1, 0, 1) with psi_b = 0, l = 1: theta = (pi/2, 0, 0, 0, pi/2, 0), so gamma =
    ! (pi/2, 0, 0) and kappa = (0, pi/2, 0); the interpolated centreline H_a Exp(xi theta) lies on
    ! the circle of radius 1 about (1, 0, 0) in the e_x-e_z plane.
    subroutine test_quarter_circle()
        real(rk) :: q(12), eps(6), theta(6), a_a(3, 3), a_b(3, 3), expected(6), a(3, 3), r(3)
        real(rk) :: ap(3, 3), rp(3), centre(3)
        integer :: i
        centre = [1.0_rk, 0.0_rk, 0.0_rk]
        q = [0.0_rk, 0.0_rk, 0.0_rk, 0.0_rk, -0.5_rk * pi, 0.0_rk, 1.0_rk, 0.0_rk, 1.0_rk, &
            0.0_rk, 0.0_rk, 0.0_rk]
        expected = [0.5_rk * pi, 0.0_rk, 0.0_rk, 0.0_rk, 0.5_rk * pi, 0.0_rk]
        call se3_element_twist(q, theta, a_a, a_b)
        CHECK_CLOSE(theta, expected, 1.0e-15_rk, 0.0_rk, 'theta = (pi/2, 0, 0, 0, pi/2, 0)')
        call se3_strains(1.0_rk, q, eps)
        CHECK_CLOSE(eps, expected, 1.0e-15_rk, 0.0_rk, 'strains of l = 1')
        call se3_strains(2.0_rk, q, eps)
        CHECK_CLOSE(eps, 0.5_rk * expected, 1.0e-15_rk, 0.0_rk, 'strains of l = 2')
        do i = 0, 8
            call exp_se3((real(i, rk) / 8.0_rk) * theta, a, r)
            call pose_compose(a_a, q(1:3), a, r, ap, rp)
            CHECK_CLOSE(norm2(rp - centre), 1.0_rk, 1.0e-15_rk, 0.0_rk, 'on the unit circle about (1, 0, 0)')
            CHECK_CLOSE(rp(2), 0.0_rk, 1.0e-15_rk, 0.0_rk, 'in the e_x-e_z plane')
        end do
    end subroutine test_quarter_circle

    ! Constant strains (methods §5.3, §15 item 2): for random nodal poses, an element
    ! [xi_e, xi_e + dxi] of a rod parametrized by xi in [0, 1] and reference tangent length J,
    ! vee(H^{-1} dH/dxi)/J of the interpolated field H(xi) = H_a Exp_SE3(N_1(xi) theta), by
    ! central differences in xi, equals se3_strains(l = dxi J) at interior and end points; H
    ! interpolates node b at xi_e + dxi.
    subroutine test_constant_strain()
        type(se3_case_t) :: c
        real(rk) :: theta(6), a_a(3, 3), a_b(3, 3), eps(6), eps_fd(6), dxi, jac, xi_e, h, s
        real(rk) :: hp(4, 4), hm(4, 4), h0inv(4, 4), a(3, 3), r(3), ai(3, 3), ri(3), worst
        real(rk) :: stations(5)
        integer :: sample, i, kind
        character(len=120) :: text
        stations = [0.0_rk, 0.21_rk, 0.5_rk, 0.83_rk, 1.0_rk]
        worst = 0.0_rk
        do kind = general, small_angles
            do sample = 1, 6
                c = random_case(kind)
                dxi = 1.0_rk / real(2 + sample, rk)
                xi_e = dxi * real(sample / 2, rk)
                jac = c%l / dxi
                call se3_strains(c%l, c%q, eps)
                call se3_element_twist(c%q, theta, a_a, a_b)
                h = 1.0e-5_rk * dxi
                do i = 1, size(stations)
                    s = stations(i)
                    call field_pose(s, a, r)
                    call pose_inverse(a, r, ai, ri)
                    h0inv = pose_matrix(ai, ri)
                    call field_pose(s + h / dxi, a, r)
                    hp = pose_matrix(a, r)
                    call field_pose(s - h / dxi, a, r)
                    hm = pose_matrix(a, r)
                    eps_fd = vee_se3(matmul(h0inv, (hp - hm) / (2.0_rk * h))) / jac
                    CHECK_CLOSE(eps_fd, eps, 1.0e-8_rk * max(1.0_rk, maxval(abs(eps))), 0.0_rk, 'H^-1 H_xi / J = theta / l')
                    worst = max(worst, maxval(abs(eps_fd - eps)) / max(1.0_rk, maxval(abs(eps))))
                end do
                call field_pose(1.0_rk, a, r)
                CHECK_CLOSE(r, c%q(7:9), 1.0e-13_rk * (1.0_rk + norm2(c%q(7:9))), 0.0_rk, 'interpolates r_b')
                CHECK_CLOSE(a, a_b, 1.0e-14_rk, 0.0_rk, 'interpolates A_b')
            end do
        end do
        write(text, '(a,es9.2)') '    max relative error of the FD strain field: ', worst
        write(output_unit, '(a)') trim(text)
    contains
        ! Pose of the interpolated field at the local coordinate t = (xi - xi_e)/dxi.
        subroutine field_pose(t, a_t, r_t)
            real(rk), intent(in) :: t
            real(rk), intent(out) :: a_t(3, 3), r_t(3)
            real(rk) :: a_loc(3, 3), r_loc(3)
            call exp_se3(t * theta, a_loc, r_loc)
            call pose_compose(a_a, c%q(1:3), a_loc, r_loc, a_t, r_t)
        end subroutine field_pose
    end subroutine test_constant_strain

    ! Hand-computed internal forces (methods eqs. (12), (42)) on elements of length L with
    ! arbitrarily rotated node a:
    ! - stretch by delta along the axis: position rows -+ k_e delta A e_x, no moments, energy
    !   1/2 L k_e delta^2;
    ! - torsion by phi: rotation rows -+ k_t (phi/L) e_x;
    ! - uniform bending kappa about e_z (an arc): rotation rows -+ k_b' kappa e_z, no forces;
    ! - uniform shear s (gamma = (1, s, 0)): shear force -+ k_s s A e_y and, in both rotation
    !   rows, -(L/2) theta_v x n / L = -(L/2) k_s s e_z.
    subroutine test_hand_cases()
        real(rk) :: stiffness(6), eps_ref(6), q(12), g(12), expected(12), psi(3), a(3, 3), el
        real(rk) :: delta, phi, kappa, s, r_a(3), energy
        stiffness = [1.0e4_rk, 3.0e3_rk, 2.0e3_rk, 40.0_rk, 60.0_rk, 70.0_rk]
        eps_ref = [1.0_rk, 0.0_rk, 0.0_rk, 0.0_rk, 0.0_rk, 0.0_rk]
        el = 1.7_rk
        psi = [0.4_rk, -1.9_rk, 0.7_rk]
        a = exp_so3(psi)
        r_a = [0.3_rk, -0.2_rk, 1.4_rk]

        delta = 0.01_rk
        q = element_state(r_a, psi, [el * (1.0_rk + delta), 0.0_rk, 0.0_rk, 0.0_rk, 0.0_rk, 0.0_rk])
        call se3_internal_force(el, stiffness, eps_ref, q, g)
        expected = 0.0_rk
        expected(7:9) = stiffness(1) * delta * a(:, 1)
        expected(1:3) = -expected(7:9)
        CHECK_CLOSE(g, expected, 1.0e-10_rk, 0.0_rk, 'stretch: -+ k_e delta A e_x')
        energy = se3_strain_energy(el, stiffness, eps_ref, q)
        CHECK_CLOSE(energy, 0.5_rk * el * stiffness(1) * delta**2, 0.0_rk, 1.0e-12_rk, 'stretch energy')

        phi = 0.6_rk
        q = element_state(r_a, psi, [el, 0.0_rk, 0.0_rk, phi, 0.0_rk, 0.0_rk])
        call se3_internal_force(el, stiffness, eps_ref, q, g)
        expected = 0.0_rk
        expected(10) = stiffness(4) * phi / el
        expected(4) = -expected(10)
        CHECK_CLOSE(g, expected, 1.0e-11_rk, 0.0_rk, 'torsion: -+ k_t phi/L e_x')

        kappa = 0.8_rk
        q = element_state(r_a, psi, [el, 0.0_rk, 0.0_rk, 0.0_rk, 0.0_rk, kappa * el])
        call se3_internal_force(el, stiffness, eps_ref, q, g)
        expected = 0.0_rk
        expected(12) = stiffness(6) * kappa
        expected(6) = -expected(12)
        CHECK_CLOSE(g, expected, 1.0e-11_rk, 0.0_rk, 'bending: -+ k_b kappa e_z')

        s = 0.05_rk
        q = element_state(r_a, psi, [el, el * s, 0.0_rk, 0.0_rk, 0.0_rk, 0.0_rk])
        call se3_internal_force(el, stiffness, eps_ref, q, g)
        expected = 0.0_rk
        expected(7:9) = stiffness(2) * s * a(:, 2)
        expected(1:3) = -expected(7:9)
        expected(6) = -0.5_rk * el * stiffness(2) * s
        expected(12) = expected(6)
        CHECK_CLOSE(g, expected, 1.0e-10_rk, 0.0_rk, 'shear: force and couple')
    end subroutine test_hand_cases

    ! ---------------------------------------------------------------------------------------
    ! Jacobians

    ! se3_internal_tangent against central differences of se3_internal_force on random states;
    ! se3_internal_force_tangent returns the same g and k.
    subroutine test_internal_tangent_fd()
        type(se3_case_t) :: c
        real(rk) :: g1(12), g2(12), k1(12, 12), k2(12, 12)
        integer :: sample
        call check_fd_random(k_internal, 12)
        do sample = 1, 4
            c = random_case(general)
            call se3_internal_force(c%l, c%stiffness, c%eps_ref, c%q, g1)
            call se3_internal_tangent(c%l, c%stiffness, c%eps_ref, c%q, k1)
            call se3_internal_force_tangent(c%l, c%stiffness, c%eps_ref, c%q, g2, k2)
            CHECK_CLOSE(g2, g1, 0.0_rk, 0.0_rk, 'combined kernel: same g')
            CHECK_CLOSE(k2, k1, 0.0_rk, 0.0_rk, 'combined kernel: same k')
        end do
    end subroutine test_internal_tangent_fd

    ! The Kelvin-Voigt kernels (docs/theory/se3_pg.md, "Damping"): se3_viscous_internal_force's
    ! tangent at fixed stress and its b_t = d g / d sigma_v, and se3_twist_tangent's d theta / d q,
    ! against central differences; without a viscous stress it is se3_internal_force, with one
    ! it is se3_internal_force with the stress moved into the reference strains (n + n_v =
    ! k (eps - (eps_ref - n_v / k))); its tangent at fixed stress is then se3_internal_tangent's
    ! at those strains.
    subroutine test_viscous_force_fd()
        type(se3_case_t) :: c
        real(rk) :: g1(12), g2(12), k1(12, 12), k2(12, 12), zero(6), theta(6), a_a(3, 3)
        real(rk) :: a_b(3, 3), theta_2(6), dtheta(6, 12)
        integer :: sample
        call check_fd_random(k_viscous, 8)
        call check_fd_random(k_viscous_stress, 8)
        call check_fd_random(k_twist, 8)
        zero = 0.0_rk
        do sample = 1, 4
            c = random_case(general)
            call se3_internal_force_tangent(c%l, c%stiffness, c%eps_ref, c%q, g1, k1)
            call se3_viscous_internal_force(c%l, c%stiffness, c%eps_ref, zero, c%q, g2, k2)
            CHECK_CLOSE(g2, g1, 0.0_rk, 0.0_rk, 'no viscous stress: the elastic force')
            CHECK_CLOSE(k2, k1, 0.0_rk, 0.0_rk, 'no viscous stress: the elastic tangent')
            call se3_internal_force_tangent(c%l, c%stiffness, c%eps_ref - c%sigma_v / c%stiffness, &
                c%q, g1, k1)
            call se3_viscous_internal_force(c%l, c%stiffness, c%eps_ref, c%sigma_v, c%q, g2, k2)
            CHECK_CLOSE(g2, g1, 1.0e-12_rk * maxval(abs(g1)), 0.0_rk, 'viscous stress: force')
            CHECK_CLOSE(k2, k1, 1.0e-12_rk * maxval(abs(k1)), 0.0_rk, 'viscous stress: tangent')
            call se3_element_twist(c%q, theta, a_a, a_b)
            call se3_twist_tangent(c%q, theta_2, dtheta)
            CHECK_CLOSE(theta_2, theta, 0.0_rk, 0.0_rk, 'se3_twist_tangent: the element twist')
        end do
    end subroutine test_viscous_force_fd

    ! A rigid velocity field, v_i = V + W x r_i and K omega_i = A_i^T W, i.e. q'_i = (v_i,
    ! T^{-1}(psi_i) A_i^T W), has zero strain rate d theta / d q q' (1e-12 of |d theta / d q|
    ! |q'|), on random elements and velocities (also with |psi| > pi): the Kelvin-Voigt stress,
    ! and so the dissipation, of a rigid motion is zero; a deforming velocity field has one.
    subroutine test_rigid_strain_rate()
        type(se3_case_t) :: c
        real(rk) :: theta(6), dtheta(6, 12), rate(12), big(3), w(3), rate_norm
        integer :: sample, i
        real(rk) :: worst
        logical :: ok
        character(len=100) :: text
        worst = 0.0_rk
        do sample = 1, 12
            c = random_case(merge(general, beyond_pi, sample <= 8))
            big = random_vector(3, 5.0_rk)
            w = random_vector(3, 3.0_rk)
            do i = 0, 1
                rate(6 * i + 1:6 * i + 3) = big + cross(w, c%q(6 * i + 1:6 * i + 3))
                rate(6 * i + 4:6 * i + 6) = matmul(tangent_inverse_so3(c%q(6 * i + 4:6 * i + 6)), &
                    matmul(w, exp_so3(c%q(6 * i + 4:6 * i + 6))))
            end do
            call se3_twist_tangent(c%q, theta, dtheta)
            rate_norm = maxval(abs(dtheta)) * maxval(abs(rate))
            worst = max(worst, maxval(abs(matmul(dtheta, rate))) / rate_norm)
            ok = maxval(abs(matmul(dtheta, rate))) <= 1.0e-12_rk * rate_norm
            CHECK_TRUE(ok, 'rigid: no strain rate')
            rate(7:9) = rate(7:9) + 0.1_rk * c%q(7:9)
            ok = maxval(abs(matmul(dtheta, rate))) > 1.0e-3_rk * rate_norm
            CHECK_TRUE(ok, 'deforming: a strain rate')
        end do
        write(text, '(a,es9.2)') '    rigid velocity fields: max |d theta / d q q''| (rel.) ', &
            worst
        write(output_unit, '(a)') trim(text)
    end subroutine test_rigid_strain_rate

    ! se3_gyroscopic (methods §6.3): Jacobian against central differences; zero position rows;
    ! uniform spin gives (l/2) w x I w in both rotation rows; the 2-point rule equals the
    ! 5-point rule (the integrand is cubic).
    subroutine test_gyroscopic()
        type(se3_case_t) :: c
        real(rk) :: g(12), k(12, 12), w(3), expected(12), t(5), wt(5), shape(2), om(3), zero(3)
        integer :: ig
        logical :: ok
        call check_fd_random(k_gyroscopic, 6)
        c = random_case(general)
        w = c%u(4:6)
        c%u(10:12) = w
        call se3_gyroscopic(c%l, c%inertia, c%u, g, k)
        expected = 0.0_rk
        expected(4:6) = 0.5_rk * c%l * cross(w, c%inertia * w)
        expected(10:12) = expected(4:6)
        CHECK_CLOSE(g, expected, 1.0e-13_rk * maxval(abs(expected)), 0.0_rk, 'uniform spin')
        c = random_case(general)
        call se3_gyroscopic(c%l, c%inertia, c%u, g, k)
        zero = 0.0_rk
        CHECK_CLOSE(g(1:3), zero, 0.0_rk, 0.0_rk, 'no position rows (a)')
        CHECK_CLOSE(g(7:9), zero, 0.0_rk, 0.0_rk, 'no position rows (b)')
        call gauss_legendre_interval(5, 0.0_rk, 1.0_rk, t, wt, ok)
        expected = 0.0_rk
        do ig = 1, 5
            shape = [1.0_rk - t(ig), t(ig)]
            om = shape(1) * c%u(4:6) + shape(2) * c%u(10:12)
            expected(4:6) = expected(4:6) + c%l * wt(ig) * shape(1) * cross(om, c%inertia * om)
            expected(10:12) = expected(10:12) + c%l * wt(ig) * shape(2) * cross(om, c%inertia * om)
        end do
        CHECK_CLOSE(g, expected, 1.0e-13_rk * maxval(abs(expected)), 0.0_rk, '2-point = 5-point rule')
    end subroutine test_gyroscopic

    ! Kinematic map (methods eq. (39), §5.4): B = T^{-1}(psi) with T B = 1; psi_dot = B w gives
    ! the material angular velocity w, vee(A^T dA/dt) = w by central differences in time; the
    ! derivative of T^{-1}(psi) w against central differences (also for |psi| > pi and near 0).
    subroutine test_kinematics()
        type(se3_case_t) :: c
        real(rk) :: b(3, 3), eye(3, 3), w(3), h, a(3, 3), ap(3, 3), am(3, 3), omega(3)
        integer :: sample, i
        eye = 0.0_rk
        do i = 1, 3
            eye(i, i) = 1.0_rk
        end do
        do sample = 1, 6
            c = random_case(merge(beyond_pi, general, sample > 3))
            call se3_kinematics(c%psi, b)
            CHECK_CLOSE(matmul(tangent_so3(c%psi), b), eye, 1.0e-13_rk, 0.0_rk, 'T B = 1')
            w = c%load
            h = 1.0e-5_rk
            a = exp_so3(c%psi)
            ap = exp_so3(c%psi + h * matmul(b, w))
            am = exp_so3(c%psi - h * matmul(b, w))
            omega = vee(matmul(transpose(a), ap - am)) / (2.0_rk * h)
            CHECK_CLOSE(omega, w, 1.0e-7_rk * norm2(w), 0.0_rk, 'material angular velocity')
        end do
        call check_fd_random(k_tinv, 8)
    end subroutine test_kinematics

    ! Loads (methods §3.4, §6.2): Jacobians against central differences; the follower force
    ! (0, 0, pi/2) applied to e_x points along e_y; the dead moment e_y seen from a section
    ! rotated by pi/2 about e_z is e_x in K.
    subroutine test_loads()
        real(rk) :: f(3), k(3, 3), psi(3), expected(3)
        call check_fd_random(k_follower, 6)
        call check_fd_random(k_dead, 6)
        psi = [0.0_rk, 0.0_rk, 0.5_rk * pi]
        call follower_force(psi, [2.0_rk, 0.0_rk, 0.0_rk], f, k)
        expected = [0.0_rk, 2.0_rk, 0.0_rk]
        CHECK_CLOSE(f, expected, 1.0e-15_rk, 0.0_rk, 'follower force A b_K')
        call dead_moment(psi, [0.0_rk, 3.0_rk, 0.0_rk], f, k)
        expected = [3.0_rk, 0.0_rk, 0.0_rk]
        CHECK_CLOSE(f, expected, 1.0e-15_rk, 0.0_rk, 'dead moment A^T c_I')
    end subroutine test_loads

    ! ---------------------------------------------------------------------------------------
    ! Invariants

    ! Rigid motions (methods §5.3, §15 item 3): with eps_ref = the strains of a random
    ! reference, g = 0 there and at rigidly moved copies (H_+ applied to both nodes), whose
    ! strains are unchanged. For a deformed state, a moved copy has the same strains and energy,
    ! position rows rotated by A_+ and the same rotation rows (objectivity, eq. (30)).
    subroutine test_rigid_motion_objectivity()
        type(se3_case_t) :: c
        real(rk) :: q_moved(12), eps(6), eps_moved(6), g(12), g_moved(12), expected(12), zero(12)
        real(rk) :: a_plus(3, 3), shift(3), scale, worst_ref, worst_obj, energy, energy_ref
        integer :: sample, moves
        character(len=120) :: text
        zero = 0.0_rk
        worst_ref = 0.0_rk
        worst_obj = 0.0_rk
        do sample = 1, 12
            c = random_case(merge(general, beyond_pi, sample <= 8))
            scale = maxval(c%stiffness)
            call se3_strains(c%l, c%q, eps)
            call se3_internal_force(c%l, c%stiffness, eps, c%q, g)
            CHECK_CLOSE(g, zero, 0.0_rk, 0.0_rk, 'stress-free reference')
            call se3_internal_force(c%l, c%stiffness, c%eps_ref, c%q, g)
            energy_ref = se3_strain_energy(c%l, c%stiffness, c%eps_ref, c%q)
            do moves = 1, 3
                a_plus = exp_so3(random_rotation(uniform(0.0_rk, 3.0_rk)))
                shift = random_vector(3, 10.0_rk)
                q_moved = rigid_copy(c%q, a_plus, shift)
                call se3_strains(c%l, q_moved, eps_moved)
                CHECK_CLOSE(eps_moved, eps, 1.0e-13_rk, 0.0_rk, 'strains objective')
                call se3_internal_force(c%l, c%stiffness, eps, q_moved, g_moved)
                CHECK_CLOSE(g_moved, zero, 1.0e-12_rk * scale, 0.0_rk, 'moved reference stress-free')
                worst_ref = max(worst_ref, maxval(abs(g_moved)) / scale)
                call se3_internal_force(c%l, c%stiffness, c%eps_ref, q_moved, g_moved)
                expected = [matmul(a_plus, g(1:3)), g(4:6), matmul(a_plus, g(7:9)), g(10:12)]
                CHECK_CLOSE(g_moved, expected, 1.0e-12_rk * maxval(abs(g)), 0.0_rk, 'internal force objective')
                worst_obj = max(worst_obj, maxval(abs(g_moved - expected)) / maxval(abs(g)))
                energy = se3_strain_energy(c%l, c%stiffness, c%eps_ref, q_moved)
                CHECK_CLOSE(energy, energy_ref, 0.0_rk, 1.0e-12_rk, 'energy objective')
            end do
        end do
        write(text, '(a,es9.2,a,es9.2)') '    moved reference: max |g|/max(stiffness) ', &
            worst_ref, &
            '; deformed: max rel. deviation ', worst_obj
        write(output_unit, '(a)') trim(text)
    contains
        function rigid_copy(q, a_p, c_p) result(qm)
            real(rk), intent(in) :: q(12), a_p(3, 3), c_p(3)
            real(rk) :: qm(12)
            qm(1:3) = matmul(a_p, q(1:3)) + c_p
            qm(4:6) = log_so3(matmul(a_p, exp_so3(q(4:6))))
            qm(7:9) = matmul(a_p, q(7:9)) + c_p
            qm(10:12) = log_so3(matmul(a_p, exp_so3(q(10:12))))
        end function rigid_copy
    end subroutine test_rigid_motion_objectivity

    ! Linear momentum (methods §9, eqs. (109)-(110)): the position rows of g sum to zero for any
    ! state (the test function delta s_i = (c, 0) is admissible).
    subroutine test_linear_momentum()
        type(se3_case_t) :: c
        real(rk) :: g(12), zero(3)
        integer :: sample, kind
        zero = 0.0_rk
        do kind = general, small_angles
            do sample = 1, 6
                c = random_case(kind)
                call se3_internal_force(c%l, c%stiffness, c%eps_ref, c%q, g)
                CHECK_CLOSE(g(1:3) + g(7:9), zero, 1.0e-14_rk * maxval(abs(g)), 0.0_rk, 'sum of position rows')
                CHECK_TRUE(maxval(abs(g(1:3))) > 1.0e-3_rk * maxval(abs(g)), 'position rows not trivially zero')
            end do
        end do
    end subroutine test_linear_momentum

    ! Energy consistency of the Petrov-Galerkin virtual work (methods §3.3, §6.1, §9): the
    ! defect |g - P^{-T} dE/dq| / |g| (E = se3_strain_energy, P dq = delta s).
    ! - Zero relative rotation (any node rotation, stretch, shear, any reference strains): the
    !   interpolated test functions are the consistent variations, so g . delta s = dE exactly;
    !   the defect is the finite-difference error.
    ! - Otherwise the defect is O(|theta_w|^2): T^T(theta_w) (the exact integral of A(t), up to
    !   the Gauss rule) against T^{-1}(theta_w) in the position rows and 1 + hat(theta_w)/2
    !   against T^{-1}(theta_w) in the rotation rows. Halving the element at fixed strains
    !   divides it by 4 (ratios within [3.5, 4.5]), and it is not small at |theta_w| ~ 1.
    subroutine test_energy_consistency()
        type(se3_case_t) :: c
        real(rk) :: defect, worst, strain(6), sigma_shift(6), psi_a(3), r_a(3), d(4), l0
        integer :: sample, kind, i
        character(len=160) :: text
        worst = 0.0_rk
        do kind = general, small_angles
            do sample = 1, 4
                c = random_case(kind)
                strain = c%eps_ref - [random_vector(3, 0.1_rk), random_vector(3, 0.5_rk)]
                strain(4:6) = 0.0_rk
                c%q = element_state(c%q(1:3), c%q(4:6), c%l * strain)
                if (kind == beyond_pi) c%q(10:12) = beyond_pi_vector(c%q(10:12))
                defect = energy_defect(c)
                worst = max(worst, defect)
                CHECK_TRUE(defect < 1.0e-7_rk, 'zero relative rotation: g . delta s = dE')
            end do
        end do
        write(text, '(a,es9.2)') '    energy defect at zero relative rotation (FD error): ', worst
        write(output_unit, '(a)') trim(text)
        do sample = 1, 4
            c = random_case(general)
            l0 = 1.0_rk
            strain(1:3) = [1.0_rk, 0.0_rk, 0.0_rk] + random_vector(3, 0.2_rk)
            strain(4:6) = random_rotation(1.2_rk)
            sigma_shift = [random_vector(3, 0.1_rk), random_vector(3, 0.5_rk)]
            c%eps_ref = strain + sigma_shift
            psi_a = c%q(4:6)
            r_a = c%q(1:3)
            do i = 1, 4
                c%l = l0 / 2.0_rk**(i - 1)
                c%q = element_state(r_a, psi_a, c%l * strain)
                d(i) = energy_defect(c)
            end do
            CHECK_TRUE(d(1) > 1.0e-3_rk, 'Petrov-Galerkin: not the energy variation at |theta_w| = 1.2')
            do i = 1, 3
                CHECK_TRUE(d(i) / d(i + 1) > 3.5_rk .and. d(i) / d(i + 1) < 4.5_rk, 'defect second order in l')
            end do
            write(text, '(a,4es9.2)') '    energy defect at |theta_w| = 1.2, 0.6, 0.3, 0.15: ', d
            write(output_unit, '(a)') trim(text)
        end do
    end subroutine test_energy_consistency

    ! ---------------------------------------------------------------------------------------
    ! End to end: the cantilever of methods §10.1 with one and two elements

    ! Slenderness 1e3 (L = 1e3, w = 1, E = 1, G = 0.5), clamp r = 0, A = 1 at node 0, follower
    ! tip moment K c = (0, 0, pi k_b/(2L)) and follower tip force A (0, 0, pi k_b/(2L^2)),
    ! 20 load increments, Newton with the analytic tangent to a max-norm residual of 1e-10,
    ! the complement update after each increment. Tip positions of methods §14.1 (an
    ! independent NumPy implementation with 2-point Gauss): one element (595.470, 588.798,
    ! 294.399), two elements (552.127, 588.790, 354.014), to their 3 decimals. Newton must
    ! converge in at most 8 iterations per increment.
    subroutine test_cantilever()
        real(rk), parameter :: length = 1.0e3_rk
        real(rk) :: stiffness(6), eps_ref(6), x(18), res(12), jac(12, 12), q(12), g(12)
        real(rk) :: k(12, 12), f(3), kf(3, 3), force, moment, lam, expected(3, 2), le, kb, psi(3)
        integer :: ne, n, e, inc, it, i, worst_its
        logical :: converged
        character(len=120) :: text
        expected(:, 1) = [595.470_rk, 588.798_rk, 294.399_rk]
        expected(:, 2) = [552.127_rk, 588.790_rk, 354.014_rk]
        kb = 1.0_rk / 12.0_rk
        stiffness = [1.0_rk, 0.5_rk, 0.5_rk, kb, kb, kb]
        eps_ref = [1.0_rk, 0.0_rk, 0.0_rk, 0.0_rk, 0.0_rk, 0.0_rk]
        moment = 0.5_rk * pi * kb / length
        force = moment / length
        do ne = 1, 2
            n = 6 * ne
            le = length / real(ne, rk)
            x = 0.0_rk
            do i = 1, ne
                x(6 * i + 1) = le * real(i, rk)
            end do
            worst_its = 0
            do inc = 1, 20
                lam = real(inc, rk) / 20.0_rk
                converged = .false.
                do it = 1, 30
                    res = 0.0_rk
                    jac = 0.0_rk
                    do e = 1, ne
                        q = x(6 * e - 5:6 * e + 6)
                        call se3_internal_force_tangent(le, stiffness, eps_ref, q, g, k)
                        call scatter(e, g, k)
                    end do
                    call follower_force(x(n + 4:n + 6), [0.0_rk, 0.0_rk, lam * force], f, kf)
                    res(n - 5:n - 3) = res(n - 5:n - 3) - f
                    jac(n - 5:n - 3, n - 2:n) = jac(n - 5:n - 3, n - 2:n) - kf
                    res(n) = res(n) - lam * moment
                    if (maxval(abs(res(1:n))) < 1.0e-10_rk) then
                        converged = .true.
                        exit
                    end if
                    call solve_dense(n, jac, res)
                    x(7:n + 6) = x(7:n + 6) - res(1:n)
                end do
                CHECK_TRUE(converged, 'Newton converged')
                worst_its = max(worst_its, it - 1)
                ! Complement update (methods §5.5 eq. (40)) after the converged increment.
                do i = 1, ne
                    psi = x(6 * i + 4:6 * i + 6)
                    if (norm2(psi) > pi) psi = (1.0_rk - 2.0_rk * pi / norm2(psi)) * psi
                    x(6 * i + 4:6 * i + 6) = psi
                end do
            end do
            CHECK_TRUE(worst_its <= 8, 'quadratic convergence: at most 8 Newton iterations')
            CHECK_CLOSE(x(n + 1:n + 3), expected(:, ne), 1.0e-3_rk, 0.0_rk, 'tip of methods §14.1')
            write(text, '(a,i0,a,3f12.5,a,i0)') '    cantilever, ', ne, ' element(s): tip ', &
                x(n + 1:n + 3), ', most Newton iterations per increment ', worst_its
            write(output_unit, '(a)') trim(text)
        end do
    contains
        ! Add element e's rows and columns to the unknowns of nodes 1..ne (node 0 is clamped).
        subroutine scatter(e, ge, ke)
            integer, intent(in) :: e
            real(rk), intent(in) :: ge(12), ke(12, 12)
            integer :: a, b, row, col
            do a = 1, 12
                row = 6 * (e - 2) + a
                if (row < 1) cycle
                res(row) = res(row) + ge(a)
                do b = 1, 12
                    col = 6 * (e - 2) + b
                    if (col >= 1) jac(row, col) = jac(row, col) + ke(a, b)
                end do
            end do
        end subroutine scatter
    end subroutine test_cantilever

    ! Solve a x = b in place (b <- x) for the leading n x n block by Gaussian elimination with
    ! partial pivoting.
    subroutine solve_dense(n, a, b)
        integer, intent(in) :: n
        real(rk), intent(inout) :: a(12, 12), b(12)
        real(rk) :: row(12), factor, tmp
        integer :: i, j, p
        do j = 1, n
            p = j - 1 + maxloc(abs(a(j:n, j)), dim=1)
            if (p /= j) then
                row(1:n) = a(j, 1:n)
                a(j, 1:n) = a(p, 1:n)
                a(p, 1:n) = row(1:n)
                tmp = b(j)
                b(j) = b(p)
                b(p) = tmp
            end if
            do i = j + 1, n
                factor = a(i, j) / a(j, j)
                a(i, j:n) = a(i, j:n) - factor * a(j, j:n)
                b(i) = b(i) - factor * b(j)
            end do
        end do
        do j = n, 1, -1
            b(j) = (b(j) - dot_product(a(j, j + 1:n), b(j + 1:n))) / a(j, j)
        end do
    end subroutine solve_dense

end module rs_test_se3_pg_element

program test_se3_pg_element
    use rs_test_se3_pg_element, only: run_all_tests
    use rs_test_assert, only: finish_tests
    implicit none
    call run_all_tests()
    call finish_tests()
end program test_se3_pg_element
