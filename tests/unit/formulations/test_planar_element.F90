#include "rs_assert.h"
!> Unit tests of rs_ph_planar_element (methods/ph_planar.md §3-§5): analytic Jacobians of PH-EM,
!> condensed PH-EM, cl-EM and PH-EMi against central finite differences on random states (angles
!> and angle increments of several radians, non-trivial strains, and cl-EM increments at, near
!> and across dphi = 0 and the series switch of Z2); the condensed kernel as the Schur complement
!> of the full one; the discrete energy identities of the three schemes; the internal force and
!> torque balance (angular momentum, methods §4.3/§4.4); rigid motions (cl-EM exactly stress-free,
!> PH-EM and PH-EMi with the Cayley-angle strain drift of §4.5); the reference stretch (a straight
!> element exactly stress-free at its initial coordinates); objectivity; hand-computed
!> cases (axial stretch EA delta/L, uniform shear angle, pure bending) and the consistent mass.
!> Kelvin-Voigt damping (issue 26, docs/theory/ph_planar.md "Damping"): the Jacobians with
!> viscosity against central differences, the energy identities with the dissipation
!> dq . r = V_1 - V_n + D (D = viscous_dissipation > 0) for every scheme and rule, and the
!> viscous force of a stretching element by hand.
!>
!> Central differences use the step fd_step max(1, |x_j|) per unknown; the residuals are smooth
!> (trigonometric in the angles, at most quadratic otherwise), so the truncation error is
!> O(step^2) and the comparison bounds round-off; errors are relative per row (to the largest
!> entry of the analytic row).
module rs_test_planar_element
    use, intrinsic :: iso_fortran_env, only: output_unit
    use rs_core_kinds, only: rk
    use rs_test_random, only: set_random_seed, uniform, random_vector
    use rs_test_assert, only: run_test, assert_true, assert_close
    use rs_math_quadrature, only: gauss_legendre
    use rs_ph_planar_element, only: ph_em_residual, ph_em_jacobian, ph_em_condensed, &
        cl_em_residual, cl_em_jacobian, ph_emi_residual, ph_emi_jacobian, ph_emi_strains, &
        compatible_strains, element_mass, mixed_strain_energy, compatible_strain_energy, &
        ph_emi_strain_energy, planar_max_gauss, planar_sinc, ph_em_static, &
        ph_em_static_condensed, ph_em_projected_strains, cl_em_static, viscous_dissipation, &
        reference_stretches
    implicit none
    private

    public :: run_all_tests

    ! Finite-difference step (relative to max(1, |x|)) and tolerance (relative, per row).
    real(rk), parameter :: fd_step = 1.0e-6_rk, fd_tol = 1.0e-6_rk
    ! Round-off tolerance of exact identities, relative to the size of their terms.
    real(rk), parameter :: exact_tol = 1.0e-12_rk
    ! The viscosity of an undamped element.
    real(rk), parameter :: no_viscosity(3) = 0.0_rk
    ! Schemes of the generic residual/Jacobian drivers below.
    ! The equilibrium kernels of the quasistatic endpoint solve (static_*) take the state
    ! (q, e) or q of the case's t_{n+1}.
    integer, parameter :: ph_em = 1, ph_em_cond = 2, cl_em = 3, ph_emi = 4, static_ph_em = 5, &
        static_ph_em_cond = 6, static_cl_em = 7
    character(len=16), parameter :: scheme_name(7) = [character(len=16) :: 'PH-EM', &
        'PH-EM cond.', 'cl-EM', 'PH-EMi', 'static PH-EM', 'static PH-EM cond', 'static cl-EM']

    !> One random element step: geometry, stiffness, Kelvin-Voigt viscosity (zero unless
    !> damped), endpoint states, strains and history.
    type :: planar_case_t
        real(rk) :: le = 1.0_rk, h = 0.1_rk
        real(rk) :: stiffness(3) = 1.0_rk, viscosity(3) = 0.0_rk
        real(rk) :: q_n(6) = 0.0_rk, q_1(6) = 0.0_rk
        real(rk) :: e_n(3) = 0.0_rk, e_1(3) = 0.0_rk
        real(rk) :: gamma_n(2, planar_max_gauss) = 0.0_rk
    end type planar_case_t

contains

    !> Run every test of this file through rs_test_assert.
    subroutine run_all_tests()
        call set_random_seed(20250530, 7919)
        call run_test('element_mass', test_element_mass)
        call run_test('compatible_strains_hand', test_compatible_strains_hand)
        call run_test('axial_stretch_hand', test_axial_stretch_hand)
        call run_test('shear_and_bending_hand', test_shear_and_bending_hand)
        call run_test('ph_em_jacobian_fd', test_ph_em_jacobian_fd)
        call run_test('ph_em_condensed_schur', test_ph_em_condensed_schur)
        call run_test('cl_em_jacobian_fd', test_cl_em_jacobian_fd)
        call run_test('cl_em_jacobian_fd_small_dphi', test_cl_em_jacobian_fd_small_dphi)
        call run_test('sinc_series', test_sinc_series)
        call run_test('ph_emi_jacobian_fd', test_ph_emi_jacobian_fd)
        call run_test('ph_em_energy_identity', test_ph_em_energy_identity)
        call run_test('cl_em_energy_identity', test_cl_em_energy_identity)
        call run_test('ph_emi_energy_identity', test_ph_emi_energy_identity)
        call run_test('internal_force_and_torque', test_internal_force_and_torque)
        call run_test('rigid_motion', test_rigid_motion)
        call run_test('objectivity', test_objectivity)
        call run_test('static_jacobian_fd', test_static_jacobian_fd)
        call run_test('static_equilibrium_rows', test_static_equilibrium_rows)
        call run_test('damped_jacobian_fd', test_damped_jacobian_fd)
        call run_test('viscous_stretch_hand', test_viscous_stretch_hand)
        ! Last: its random draws leave the other tests' cases as they were.
        call run_test('reference_stretch', test_reference_stretch)
    end subroutine run_all_tests

    ! ---------------------------------------------------------------------------------------
    ! Random data and helpers

    pure function rot2(phi) result(lam)
        real(rk), intent(in) :: phi
        real(rk) :: lam(2, 2)
        lam = reshape([cos(phi), sin(phi), -sin(phi), cos(phi)], [2, 2])
    end function rot2

    ! Planar cross product a x b = a1 b2 - a2 b1 (methods §2.1).
    pure function cross2(a, b) result(c)
        real(rk), intent(in) :: a(2), b(2)
        real(rk) :: c
        c = a(1) * b(2) - a(2) * b(1)
    end function cross2

    ! Straight stress-free element: node a at ra, direction phi0, angles phi0.
    function straight_element(ra, phi0, le) result(q)
        real(rk), intent(in) :: ra(2), phi0, le
        real(rk) :: q(6)
        q(1:2) = ra
        q(3) = phi0
        q(4:5) = ra + le * [cos(phi0), sin(phi0)]
        q(6) = phi0
    end function straight_element

    ! Rigid motion: rotation by theta about the point p, then the shift c.
    function rigid_map(q, theta, p, c) result(qr)
        real(rk), intent(in) :: q(6), theta, p(2), c(2)
        real(rk) :: qr(6)
        real(rk) :: rot(2, 2)
        rot = rot2(theta)
        qr(1:2) = p + matmul(rot, q(1:2) - p) + c
        qr(4:5) = p + matmul(rot, q(4:5) - p) + c
        qr(3) = q(3) + theta
        qr(6) = q(6) + theta
    end function rigid_map

    ! A random step: a stretched, sheared and bent element at angle phi0 in [-6, 6]; t_{n+1} is
    ! a rigid rotation by up to 2.5 rad about a random point plus a deformation (angle
    ! increments of the two nodes differ by up to 0.6 rad); strains and history ~ 0.1.
    function random_case() result(c)
        type(planar_case_t) :: c
        real(rk) :: phi0, beta, stretch
        c%le = uniform(0.5_rk, 2.0_rk)
        c%h = uniform(0.01_rk, 0.5_rk)
        c%stiffness = [uniform(1.0e3_rk, 1.0e4_rk), uniform(5.0e2_rk, 5.0e3_rk), &
            uniform(10.0_rk, 100.0_rk)]
        phi0 = uniform(-6.0_rk, 6.0_rk)
        beta = uniform(-0.3_rk, 0.3_rk)
        stretch = uniform(-0.2_rk, 0.2_rk)
        c%q_n(1:2) = random_vector(2, 2.0_rk)
        c%q_n(4:5) = c%q_n(1:2) + c%le * (1.0_rk + stretch) * [cos(phi0 + beta), sin(phi0 + beta)]
        c%q_n(3) = phi0 + uniform(-0.3_rk, 0.3_rk)
        c%q_n(6) = phi0 + uniform(-0.3_rk, 0.3_rk)
        c%q_1 = rigid_map(c%q_n, uniform(-2.5_rk, 2.5_rk), random_vector(2, 3.0_rk), &
            random_vector(2, 1.0_rk))
        c%q_1 = c%q_1 + [random_vector(2, 0.1_rk * c%le), uniform(-0.3_rk, 0.3_rk), &
            random_vector(2, 0.1_rk * c%le), uniform(-0.3_rk, 0.3_rk)]
        c%e_n = random_vector(3, 0.1_rk)
        c%e_1 = random_vector(3, 0.1_rk)
        c%gamma_n = reshape(random_vector(2 * planar_max_gauss, 0.1_rk), [2, planar_max_gauss])
    end function random_case

    ! A random case with Kelvin-Voigt viscosity: times tau_i in [0.1, 2] h, so that the
    ! viscous stress V de/h is of the size of the elastic one.
    function random_damped_case() result(c)
        type(planar_case_t) :: c
        integer :: i
        c = random_case()
        do i = 1, 3
            c%viscosity(i) = uniform(0.1_rk, 2.0_rk) * c%h * c%stiffness(i)
        end do
    end function random_damped_case

    ! Number of unknowns of a scheme's residual.
    pure integer function n_unknowns(scheme)
        integer, intent(in) :: scheme
        n_unknowns = merge(9, 6, scheme == ph_em .or. scheme == static_ph_em)
    end function n_unknowns

    ! Residual of `scheme` as a function of the t_{n+1} unknowns x = (q_1, e_1) or q_1.
    subroutine scheme_residual(scheme, c, ng, x, r)
        integer, intent(in) :: scheme, ng
        type(planar_case_t), intent(in) :: c
        real(rk), intent(in) :: x(:)
        real(rk), intent(out) :: r(:)
        real(rk) :: k(6, 6), e_1(3)
        select case (scheme)
        case (ph_em)
            call ph_em_residual(c%le, c%stiffness, c%viscosity, ng, c%h, c%q_n, x(1:6), c%e_n, &
                x(7:9), r(1:9))
        case (ph_em_cond)
            call ph_em_condensed(c%le, c%stiffness, c%viscosity, ng, c%h, c%q_n, x(1:6), c%e_n, &
                r(1:6), k, e_1)
        case (cl_em)
            call cl_em_residual(c%le, c%stiffness, c%viscosity, ng, c%h, c%q_n, x(1:6), r(1:6))
        case (ph_emi)
            call ph_emi_residual(c%le, c%stiffness, c%viscosity, ng, c%h, c%q_n, x(1:6), &
                c%gamma_n(:, 1:ng), r(1:6))
        case (static_ph_em)
            call ph_em_static(c%le, c%stiffness, ng, c%h, x(1:6), x(7:9), r(1:9))
        case (static_ph_em_cond)
            call ph_em_static_condensed(c%le, c%stiffness, ng, x(1:6), r(1:6), e_1)
        case (static_cl_em)
            call cl_em_static(c%le, c%stiffness, ng, x(1:6), r(1:6))
        end select
    end subroutine scheme_residual

    ! Analytic Jacobian of `scheme` at the case's t_{n+1} unknowns (leading 6 x 6 or 9 x 9).
    subroutine scheme_jacobian(scheme, c, ng, k)
        integer, intent(in) :: scheme, ng
        type(planar_case_t), intent(in) :: c
        real(rk), intent(out) :: k(9, 9)
        real(rk) :: r(6), e_1(3), k6(6, 6), r9(9)
        k = 0.0_rk
        select case (scheme)
        case (ph_em)
            call ph_em_jacobian(c%le, c%stiffness, c%viscosity, ng, c%h, c%q_n, c%q_1, c%e_n, &
                c%e_1, k)
        case (ph_em_cond)
            call ph_em_condensed(c%le, c%stiffness, c%viscosity, ng, c%h, c%q_n, c%q_1, c%e_n, r, &
                k6, e_1)
        case (cl_em)
            call cl_em_jacobian(c%le, c%stiffness, c%viscosity, ng, c%h, c%q_n, c%q_1, k6)
        case (ph_emi)
            call ph_emi_jacobian(c%le, c%stiffness, c%viscosity, ng, c%h, c%q_n, c%q_1, &
                c%gamma_n(:, 1:ng), k6)
        case (static_ph_em)
            call ph_em_static(c%le, c%stiffness, ng, c%h, c%q_1, c%e_1, r9, k)
        case (static_ph_em_cond)
            call ph_em_static_condensed(c%le, c%stiffness, ng, c%q_1, r, e_1, k6)
        case (static_cl_em)
            call cl_em_static(c%le, c%stiffness, ng, c%q_1, r, k6)
        end select
        if (scheme /= ph_em .and. scheme /= static_ph_em) k(1:6, 1:6) = k6
    end subroutine scheme_jacobian

    ! Largest per-row relative difference between the analytic Jacobian and central differences.
    function fd_error(scheme, c, ng) result(error)
        integer, intent(in) :: scheme, ng
        type(planar_case_t), intent(in) :: c
        real(rk) :: error
        real(rk) :: x(9), xp(9), rp(9), rm(9), k(9, 9), fd(9, 9), step, row_scale
        integer :: n, i, j
        n = n_unknowns(scheme)
        x(1:6) = c%q_1
        x(7:9) = c%e_1
        call scheme_jacobian(scheme, c, ng, k)
        do j = 1, n
            step = fd_step * max(1.0_rk, abs(x(j)))
            xp(1:n) = x(1:n)
            xp(j) = x(j) + step
            call scheme_residual(scheme, c, ng, xp(1:n), rp(1:n))
            xp(j) = x(j) - step
            call scheme_residual(scheme, c, ng, xp(1:n), rm(1:n))
            fd(1:n, j) = (rp(1:n) - rm(1:n)) / (2.0_rk * step)
        end do
        error = 0.0_rk
        do i = 1, n
            row_scale = max(maxval(abs(k(i, 1:n))), tiny(1.0_rk))
            error = max(error, maxval(abs(k(i, 1:n) - fd(i, 1:n))) / row_scale)
        end do
    end function fd_error

    ! FD check of one scheme on random cases with 1, 2 and 3 Gauss points (with Kelvin-Voigt
    ! viscosity if `damped`).
    subroutine check_fd_random(scheme, damped)
        integer, intent(in) :: scheme
        logical, intent(in), optional :: damped
        type(planar_case_t) :: c
        real(rk) :: error, worst
        integer :: ng, sample
        logical :: viscous
        character(len=:), allocatable :: label
        character(len=120) :: text
        viscous = .false.
        if (present(damped)) viscous = damped
        label = trim(scheme_name(scheme))
        if (viscous) label = label // ', damped'
        worst = 0.0_rk
        do ng = 1, 3
            do sample = 1, 8
                if (viscous) then
                    c = random_damped_case()
                else
                    c = random_case()
                end if
                error = fd_error(scheme, c, ng)
                worst = max(worst, error)
                CHECK_TRUE(error < fd_tol, label // ': Jacobian = central differences')
            end do
        end do
        write(text, '(a,es9.2,a,es8.1,a)') '    max relative FD error (' &
            // label // '): ', worst, ' (step ', fd_step, ' max(1,|x|))'
        write(output_unit, '(a)') trim(text)
    end subroutine check_fd_random

    ! Nodal force sum and torque about the origin of nodal rows r(6) with lever arms at the
    ! midpoint nodal positions q05: sum_I r05_I x F_I + m_I (methods §4.3, §4.4).
    subroutine force_and_torque(q05, r, force, torque, scale)
        real(rk), intent(in) :: q05(6), r(6)
        real(rk), intent(out) :: force(2), torque, scale
        force = r(1:2) + r(4:5)
        torque = cross2(q05(1:2), r(1:2)) + r(3) + cross2(q05(4:5), r(4:5)) + r(6)
        scale = norm2(q05(1:2)) * norm2(r(1:2)) + norm2(q05(4:5)) * norm2(r(4:5)) &
            + abs(r(3)) + abs(r(6))
    end subroutine force_and_torque

    ! Inverse of a 3 x 3 matrix by cofactors.
    function inverse3(a) result(b)
        real(rk), intent(in) :: a(3, 3)
        real(rk) :: b(3, 3)
        real(rk) :: det
        b(1, 1) = a(2, 2) * a(3, 3) - a(2, 3) * a(3, 2)
        b(1, 2) = a(1, 3) * a(3, 2) - a(1, 2) * a(3, 3)
        b(1, 3) = a(1, 2) * a(2, 3) - a(1, 3) * a(2, 2)
        b(2, 1) = a(2, 3) * a(3, 1) - a(2, 1) * a(3, 3)
        b(2, 2) = a(1, 1) * a(3, 3) - a(1, 3) * a(3, 1)
        b(2, 3) = a(1, 3) * a(2, 1) - a(1, 1) * a(2, 3)
        b(3, 1) = a(2, 1) * a(3, 2) - a(2, 2) * a(3, 1)
        b(3, 2) = a(1, 2) * a(3, 1) - a(1, 1) * a(3, 2)
        b(3, 3) = a(1, 1) * a(2, 2) - a(1, 2) * a(2, 1)
        det = a(1, 1) * b(1, 1) + a(1, 2) * b(2, 1) + a(1, 3) * b(3, 1)
        b = b / det
    end function inverse3

    ! ---------------------------------------------------------------------------------------
    ! Hand-computed cases

    ! Consistent mass (methods §3.2): M1 = le/6 [[2, 1], [1, 2]] per component; total mass
    ! rhoA le; kinetic energy of a translation 1/2 rhoA le |v|^2 and of a uniform spin
    ! 1/2 rhoI le omega^2; no coupling between x, y and phi.
    subroutine test_element_mass()
        real(rk) :: m(6, 6), le, rhoA, rhoI, v(6)
        le = 1.2_rk
        rhoA = 2.0_rk
        rhoI = 0.5_rk
        call element_mass(le, rhoA, rhoI, m)
        CHECK_CLOSE(m(1, 1), 0.8_rk, 1.0e-15_rk, 0.0_rk, 'rhoA le/3')
        CHECK_CLOSE(m(5, 2), 0.4_rk, 1.0e-15_rk, 0.0_rk, 'rhoA le/6 (y_b, y_a)')
        CHECK_CLOSE(m(6, 6), 0.2_rk, 1.0e-15_rk, 0.0_rk, 'rhoI le/3')
        CHECK_CLOSE(m(3, 6), 0.1_rk, 1.0e-15_rk, 0.0_rk, 'rhoI le/6')
        CHECK_TRUE(m(1, 2) == 0.0_rk .and. m(1, 3) == 0.0_rk .and. m(2, 6) == 0.0_rk, 'no coupling')
        CHECK_CLOSE(m, transpose(m), 0.0_rk, 0.0_rk, 'symmetric')
        v = [0.3_rk, -0.7_rk, 0.0_rk, 0.3_rk, -0.7_rk, 0.0_rk]
        CHECK_CLOSE(0.5_rk * dot_product(v, matmul(m, v)), 0.5_rk * rhoA * le * 0.58_rk, 1.0e-15_rk, 0.0_rk, 'translation')
        v = [0.0_rk, 0.0_rk, 1.5_rk, 0.0_rk, 0.0_rk, 1.5_rk]
        CHECK_CLOSE(0.5_rk * dot_product(v, matmul(m, v)), 0.5_rk * rhoI * le * 2.25_rk, 1.0e-15_rk, 0.0_rk, 'spin')
    end subroutine test_element_mass

    ! Compatible strains (methods §2.3 eqs. 5-6) of hand-built states: an element along
    ! (cos alpha, sin alpha) stretched by (1 + eps) with the section turned by beta against it:
    ! Gamma = (1 + eps)(cos beta, -sin beta) - e1 at every Gauss point; and a bent element,
    ! kappa = (phi_b - phi_a)/le.
    subroutine test_compatible_strains_hand()
        real(rk) :: q(6), gammas(3, 3), le, alpha, beta, eps, expected(3)
        integer :: ng, g
        le = 1.7_rk
        alpha = 2.3_rk
        beta = 0.2_rk
        eps = 0.05_rk
        q(1:2) = [0.4_rk, -1.1_rk]
        q(4:5) = q(1:2) + (1.0_rk + eps) * le * [cos(alpha), sin(alpha)]
        q(3) = alpha + beta
        q(6) = alpha + beta
        expected = [(1.0_rk + eps) * cos(beta) - 1.0_rk, -(1.0_rk + eps) * sin(beta), 0.0_rk]
        do ng = 1, 3
            call compatible_strains(le, ng, q, gammas(:, 1:ng))
            do g = 1, ng
                CHECK_CLOSE(gammas(:, g), expected, 1.0e-14_rk, 0.0_rk, 'stretched and sheared')
            end do
        end do
        q(6) = q(3) + 0.34_rk
        call compatible_strains(le, 1, q, gammas(:, 1:1))
        CHECK_CLOSE(gammas(3, 1), 0.2_rk, 1.0e-15_rk, 0.0_rk, 'kappa = dphi/le')
        ! 1-point Gauss: the angle at the midpoint, alpha + beta + 0.17
        expected(1:2) = (1.0_rk + eps) * [cos(beta + 0.17_rk), -sin(beta + 0.17_rk)] &
            - [1.0_rk, 0.0_rk]
        CHECK_CLOSE(gammas(1:2, 1), expected(1:2), 1.0e-14_rk, 0.0_rk, 'angle interpolated to the Gauss point')
    end subroutine test_compatible_strains_hand

    ! Straight element along e_x stretched by delta, phi = 0: cl-EM force EA delta/L on node b
    ! (-EA delta/L on a), no shear, no moment, for the reduced and the full rule, when both
    ! endpoints are stretched; half of it for a step from the unstretched state (N05 averages
    ! the endpoint strains, eq. 72). PH-EM with e = (delta/L, 0, 0) and PH-EMi with history
    ! delta/L give the same force.
    subroutine test_axial_stretch_hand()
        real(rk) :: le, delta, stiffness(3), q0(6), qs(6), r(6), r9(9), expected(6), gam(2, 2)
        integer :: ng
        le = 2.0_rk
        delta = 0.01_rk
        stiffness = [1.0e4_rk, 3.0e3_rk, 50.0_rk]
        q0 = [0.0_rk, 0.0_rk, 0.0_rk, le, 0.0_rk, 0.0_rk]
        qs = q0
        qs(4) = le + delta
        expected = 0.0_rk
        expected(1) = -stiffness(1) * delta / le
        expected(4) = stiffness(1) * delta / le
        CHECK_CLOSE(expected(4), 50.0_rk, 1.0e-12_rk, 0.0_rk, 'EA delta/L = 50')
        do ng = 1, 2
            call cl_em_residual(le, stiffness, no_viscosity, ng, 0.1_rk, qs, qs, r)
            CHECK_CLOSE(r, expected, 1.0e-10_rk, 0.0_rk, 'cl-EM: EA delta/L')
            call cl_em_residual(le, stiffness, no_viscosity, ng, 0.1_rk, q0, qs, r)
            CHECK_CLOSE(r, 0.5_rk * expected, 1.0e-10_rk, 0.0_rk, 'cl-EM from rest: EA delta/(2L)')
            call ph_em_residual(le, stiffness, no_viscosity, ng, 0.1_rk, qs, qs, [delta / le, 0.0_rk, 0.0_rk], &
                [delta / le, 0.0_rk, 0.0_rk], r9)
            CHECK_CLOSE(r9(1:6), expected, 1.0e-10_rk, 0.0_rk, 'PH-EM: EA delta/L')
            gam = 0.0_rk
            gam(1, 1:ng) = delta / le
            call ph_emi_residual(le, stiffness, no_viscosity, ng, 0.1_rk, qs, qs, gam(:, 1:ng), r)
            CHECK_CLOSE(r, expected, 1.0e-10_rk, 0.0_rk, 'PH-EMi: EA delta/L')
        end do
    end subroutine test_axial_stretch_hand

    ! Uniform section angle beta on a straight element along e_x (q_n = q_1): cl-EM force
    ! F_b = Lambda(beta) D (cos beta - 1, -sin beta) = -F_a and moments m_a = m_b = -(L/2) F_b,y
    ! (the shear couple, eq. 75). Pure bending in PH-EM, e = (0, 0, kappa): moments -+ EI kappa
    ! and no force; cl-EM with phi_b - phi_a = kappa L on a straight chord has the same moments
    ! plus the shear of the rotated sections.
    subroutine test_shear_and_bending_hand()
        real(rk) :: le, beta, stiffness(3), q(6), r(6), r9(9), fb(2), kappa, expected(6)
        integer :: ng
        le = 1.5_rk
        beta = 0.3_rk
        stiffness = [1.0e4_rk, 3.0e3_rk, 50.0_rk]
        q = [0.0_rk, 0.0_rk, beta, le, 0.0_rk, beta]
        fb = matmul(rot2(beta), stiffness(1:2) * [cos(beta) - 1.0_rk, -sin(beta)])
        expected = [-fb(1), -fb(2), -0.5_rk * le * fb(2), fb(1), fb(2), -0.5_rk * le * fb(2)]
        do ng = 1, 2
            call cl_em_residual(le, stiffness, no_viscosity, ng, 0.1_rk, q, q, r)
            CHECK_CLOSE(r, expected, 1.0e-10_rk, 0.0_rk, 'cl-EM: uniformly rotated sections')
        end do
        kappa = 0.4_rk
        expected = [0.0_rk, 0.0_rk, -stiffness(3) * kappa, 0.0_rk, 0.0_rk, stiffness(3) * kappa]
        do ng = 1, 2
            call ph_em_residual(le, stiffness, no_viscosity, ng, 0.1_rk, q, q, [0.0_rk, 0.0_rk, kappa], &
                [0.0_rk, 0.0_rk, kappa], r9)
            CHECK_CLOSE(r9(1:6), expected, 1.0e-12_rk, 0.0_rk, 'PH-EM: pure bending')
        end do
        q = [0.0_rk, 0.0_rk, -0.5_rk * kappa * le, le, 0.0_rk, 0.5_rk * kappa * le]
        call cl_em_residual(le, stiffness, no_viscosity, 1, 0.1_rk, q, q, r)
        ! 1-point rule: the Gauss-point angle is 0, so the sections there are unsheared.
        CHECK_CLOSE(r, expected, 1.0e-10_rk, 0.0_rk, 'cl-EM reduced: pure bending')
    end subroutine test_shear_and_bending_hand

    ! ---------------------------------------------------------------------------------------
    ! Jacobians

    subroutine test_ph_em_jacobian_fd()
        call check_fd_random(ph_em)
    end subroutine test_ph_em_jacobian_fd

    ! The condensed kernel (methods §3.5, §4.3 eqs. 63-64): its e_1 zeroes the strain rows of
    ! ph_em_residual (to round-off), its r equals the nodal rows there, its k equals the Schur
    ! complement K_qq - K_qe K_ee^-1 K_eq of the full 9 x 9 Jacobian and central differences of
    ! its own r (the total derivative including de_1/dq_1).
    subroutine test_ph_em_condensed_schur()
        type(planar_case_t) :: c
        real(rk) :: r(6), k(6, 6), e_1(3), r9(9), k9(9, 9), schur(6, 6), zero(3), tol, kscale
        real(rk) :: kee(3, 3)
        real(rk) :: worst_schur, worst_rows
        integer :: ng, sample
        character(len=120) :: text
        zero = 0.0_rk
        worst_schur = 0.0_rk
        worst_rows = 0.0_rk
        do ng = 1, 3
            do sample = 1, 8
                c = random_case()
                call ph_em_condensed(c%le, c%stiffness, c%viscosity, ng, c%h, c%q_n, c%q_1, &
                    c%e_n, r, k, e_1)
                call ph_em_residual(c%le, c%stiffness, c%viscosity, ng, c%h, c%q_n, c%q_1, c%e_n, &
                    e_1, r9)
                CHECK_CLOSE(r, r9(1:6), 0.0_rk, 1.0e-14_rk, 'condensed r = nodal rows at e_1')
                tol = exact_tol * c%le * (maxval(abs(e_1)) + maxval(abs(c%e_n))) / c%h
                CHECK_CLOSE(r9(7:9), zero, tol, 0.0_rk, 'strain rows vanish at e_1')
                worst_rows = max(worst_rows, maxval(abs(r9(7:9))) * c%h &
                    / (c%le * (maxval(abs(e_1)) + maxval(abs(c%e_n)))))
                c%e_1 = e_1
                call ph_em_jacobian(c%le, c%stiffness, c%viscosity, ng, c%h, c%q_n, c%q_1, c%e_n, &
                    e_1, k9)
                kee = k9(7:9, 7:9)
                schur = k9(1:6, 1:6) - matmul(k9(1:6, 7:9), matmul(inverse3(kee), k9(7:9, 1:6)))
                kscale = maxval(abs(k))
                CHECK_CLOSE(k, schur, exact_tol * kscale, 0.0_rk, 'condensed k = Schur complement')
                worst_schur = max(worst_schur, maxval(abs(k - schur)) / kscale)
            end do
        end do
        write(text, '(a,es9.2,a,es9.2)') '    condensed: max |k - Schur|/max|k| ', worst_schur, &
            ', max strain rows (relative) ', worst_rows
        write(output_unit, '(a)') trim(text)
        call check_fd_random(ph_em_cond)
    end subroutine test_ph_em_condensed_schur

    subroutine test_cl_em_jacobian_fd()
        call check_fd_random(cl_em)
    end subroutine test_cl_em_jacobian_fd

    ! cl-EM near dphi = 0, where Z2 = sin(dphi/2)/(dphi/2) switches to its series: increments
    ! of the two nodes 0, 1e-7, 1e-3 and 0.2 (the switch |dphi_g/2| = 0.1 at the Gauss point of
    ! the reduced rule, so the FD stencil straddles it), equal and unequal.
    subroutine test_cl_em_jacobian_fd_small_dphi()
        type(planar_case_t) :: c
        real(rk) :: increments(6, 2), error, worst
        integer :: ng, i
        character(len=120) :: text
        increments(:, 1) = [0.0_rk, 1.0e-7_rk, 1.0e-3_rk, 0.2_rk, -0.2_rk, 1.0e-3_rk]
        increments(:, 2) = [0.0_rk, 1.0e-7_rk, 1.0e-3_rk, 0.2_rk, -0.2_rk, -3.0e-3_rk]
        worst = 0.0_rk
        do ng = 1, 2
            do i = 1, 6
                c = random_case()
                c%q_1(1:2) = c%q_n(1:2) + random_vector(2, 0.05_rk)
                c%q_1(4:5) = c%q_n(4:5) + random_vector(2, 0.05_rk)
                c%q_1(3) = c%q_n(3) + increments(i, 1)
                c%q_1(6) = c%q_n(6) + increments(i, 2)
                error = fd_error(cl_em, c, ng)
                worst = max(worst, error)
                CHECK_TRUE(error < fd_tol, 'cl-EM small dphi: Jacobian = central differences')
            end do
        end do
        write(text, '(a,es9.2)') '    max relative FD error (cl-EM, dphi near 0): ', worst
        write(output_unit, '(a)') trim(text)
    end subroutine test_cl_em_jacobian_fd_small_dphi

    ! Z2 = sin(x)/x and its derivative (methods §5.1 eq. 67): exact values at 0, the closed
    ! forms where they are accurate (|x| >= 0.05: cancellation error of the derivative below
    ! eps/x^3 ~ 2e-12 relative), continuity across the series switch at |x| = 0.1, and the
    ! leading Taylor terms 1 - x^2/6, -x/3 at tiny x.
    subroutine test_sinc_series()
        real(rk) :: xs(6), x, s, ds, s_ref, ds_ref, sp, dsp, sm, dsm
        integer :: i
        call planar_sinc(0.0_rk, s, ds)
        CHECK_TRUE(s == 1.0_rk .and. ds == 0.0_rk, 'sinc(0) = 1, sinc''(0) = 0')
        xs = [0.05_rk, 0.07_rk, 0.0999_rk, -0.08_rk, 0.1_rk, 0.3_rk]
        do i = 1, size(xs)
            x = xs(i)
            call planar_sinc(x, s, ds)
            s_ref = sin(x) / x
            ds_ref = (x * cos(x) - sin(x)) / x**2
            CHECK_CLOSE(s, s_ref, 0.0_rk, 1.0e-15_rk, 'sinc against sin(x)/x')
            CHECK_CLOSE(ds, ds_ref, 0.0_rk, 5.0e-12_rk, 'sinc'' against the closed form')
        end do
        x = 0.1_rk
        call planar_sinc(x * (1.0_rk - 1.0e-15_rk), sm, dsm)
        call planar_sinc(x * (1.0_rk + 1.0e-15_rk), sp, dsp)
        CHECK_CLOSE(sm, sp, 0.0_rk, 1.0e-15_rk, 'sinc continuous at the switch')
        CHECK_CLOSE(dsm, dsp, 0.0_rk, 1.0e-13_rk, 'sinc'' continuous at the switch')
        x = 1.0e-5_rk
        call planar_sinc(x, s, ds)
        CHECK_CLOSE(s, 1.0_rk - x**2 / 6.0_rk, 0.0_rk, 1.0e-16_rk, 'sinc near 0')
        CHECK_CLOSE(ds, -x / 3.0_rk, 0.0_rk, 1.0e-10_rk, 'sinc'' near 0')
    end subroutine test_sinc_series

    subroutine test_ph_emi_jacobian_fd()
        call check_fd_random(ph_emi)
    end subroutine test_ph_emi_jacobian_fd

    ! ---------------------------------------------------------------------------------------
    ! Discrete energy identities

    ! A random case, undamped for damping = 0 and with Kelvin-Voigt viscosity for damping = 1.
    function case_of(damping) result(c)
        integer, intent(in) :: damping
        type(planar_case_t) :: c
        if (damping == 0) then
            c = random_case()
        else
            c = random_damped_case()
        end if
    end function case_of

    ! The discrete energy identity of one element step, dq . r = V_1 - V_n + D, to round-off
    ! (relative to the size of its terms), and D > 0 exactly when the case is damped; `worst`
    ! keeps the largest relative error.
    subroutine check_balance(scheme, damping, dq, r, v1, vn, d, worst)
        character(len=*), intent(in) :: scheme
        integer, intent(in) :: damping
        real(rk), intent(in) :: dq(6), r(6), v1, vn, d
        real(rk), intent(inout) :: worst
        real(rk) :: lhs, rhs, scale
        CHECK_TRUE((d > 0.0_rk) .eqv. (damping == 1), scheme // ': D > 0 iff damped')
        lhs = dot_product(dq, r)
        rhs = v1 - vn + d
        scale = sum(abs(dq * r)) + v1 + vn + d
        CHECK_CLOSE(lhs, rhs, exact_tol * scale, 0.0_rk, scheme // ': dq.r = V_1 - V_n + D')
        worst = max(worst, abs(lhs - rhs) / scale)
    end subroutine check_balance

    ! PH-EM (methods §4.3 "why energy is exact"): with e_1 from the strain rows,
    ! dq . r(1:6) = H_mix(e_1) - H_mix(e_n) + D exactly, D = le de^T V de / h the Kelvin-Voigt
    ! dissipation (0 undamped, > 0 damped); for an arbitrary e_1 the strain rows enter as
    ! dq . r(1:6) - h (sigma05 . r(7:9)) = H_mix(e_1) - H_mix(e_n) + D, sigma05 the step's
    ! stresses D_ts e05 + V de/h (their work against the rate-form rows, docs/theory/ph_planar.md
    ! "Damping").
    subroutine test_ph_em_energy_identity()
        type(planar_case_t) :: c
        real(rk) :: r(6), k(6, 6), e_1(3), r9(9), dq(6), n05(3), lhs, rhs, scale, worst, d
        integer :: ng, sample, damping
        character(len=120) :: text
        worst = 0.0_rk
        do damping = 0, 1
            do ng = 1, 3
                do sample = 1, 8
                    c = case_of(damping)
                    call ph_em_condensed(c%le, c%stiffness, c%viscosity, ng, c%h, c%q_n, c%q_1, &
                        c%e_n, r, k, e_1)
                    dq = c%q_1 - c%q_n
                    d = viscous_dissipation(c%le, c%viscosity, 1, c%h, &
                        reshape(e_1 - c%e_n, [3, 1]))
                    call check_balance('PH-EM', damping, dq, r, &
                        mixed_strain_energy(c%le, c%stiffness, e_1), &
                        mixed_strain_energy(c%le, c%stiffness, c%e_n), d, worst)
                    call ph_em_residual(c%le, c%stiffness, c%viscosity, ng, c%h, c%q_n, c%q_1, &
                        c%e_n, c%e_1, r9)
                    n05 = 0.5_rk * c%stiffness * (c%e_n + c%e_1) + c%viscosity * (c%e_1 - c%e_n) / c%h
                    d = viscous_dissipation(c%le, c%viscosity, 1, c%h, &
                        reshape(c%e_1 - c%e_n, [3, 1]))
                    lhs = dot_product(dq, r9(1:6)) - c%h * dot_product(n05, r9(7:9))
                    rhs = mixed_strain_energy(c%le, c%stiffness, c%e_1) &
                        - mixed_strain_energy(c%le, c%stiffness, c%e_n) + d
                    scale = sum(abs(dq * r9(1:6))) + c%h * sum(abs(n05 * r9(7:9))) &
                        + mixed_strain_energy(c%le, c%stiffness, c%e_1) &
                        + mixed_strain_energy(c%le, c%stiffness, c%e_n) + d
                    CHECK_CLOSE(lhs, rhs, exact_tol * scale, 0.0_rk, 'PH-EM: identity with strain rows')
                    worst = max(worst, abs(lhs - rhs) / scale)
                end do
            end do
        end do
        write(text, '(a,es9.2)') '    PH-EM energy identity (undamped and damped), max relative error: ', &
            worst
        write(output_unit, '(a)') trim(text)
    end subroutine test_ph_em_energy_identity

    ! cl-EM (methods §5.1, Appendix A.5 eqs. 98-99): dq . r = V(q_1) - V(q_n) + D with the
    ! compatible strain energy under the same rule, for the reduced and the full rule; D the
    ! Kelvin-Voigt dissipation of the compatible strain increments at the rule's points (eq. 99
    ! holds at each point, so the viscous rows do exactly that work).
    subroutine test_cl_em_energy_identity()
        type(planar_case_t) :: c
        real(rk) :: r(6), dq(6), v1, vn, worst, d, g_n(3, 3), g_1(3, 3)
        integer :: ng, sample, damping
        character(len=120) :: text
        worst = 0.0_rk
        do damping = 0, 1
            do ng = 1, 3
                do sample = 1, 8
                    c = case_of(damping)
                    if (sample == 1) c%q_1(6) = c%q_1(3) - c%q_n(3) + c%q_n(6)
                    dq = c%q_1 - c%q_n
                    call cl_em_residual(c%le, c%stiffness, c%viscosity, ng, c%h, c%q_n, c%q_1, r)
                    v1 = compatible_strain_energy(c%le, c%stiffness, ng, c%q_1)
                    vn = compatible_strain_energy(c%le, c%stiffness, ng, c%q_n)
                    call compatible_strains(c%le, ng, c%q_n, g_n(:, 1:ng))
                    call compatible_strains(c%le, ng, c%q_1, g_1(:, 1:ng))
                    d = viscous_dissipation(c%le, c%viscosity, ng, c%h, g_1(:, 1:ng) - g_n(:, 1:ng))
                    call check_balance('cl-EM', damping, dq, r, v1, vn, d, worst)
                end do
            end do
        end do
        write(text, '(a,es9.2)') '    cl-EM energy identity (undamped and damped), max relative error: ', &
            worst
        write(output_unit, '(a)') trim(text)
    end subroutine test_cl_em_energy_identity

    ! PH-EMi (methods §5.2): with the history update gamma_1 of eq. (78a),
    ! dq . r = sum_g w_g le/2 (1/2 gamma^T D gamma)|_{n+1} - |_n + le/2 EI (kappa_1^2 - kappa_n^2)
    ! + D with kappa = d_s phi (ph_emi_strain_energy), because N_g = D (gamma_n + gamma_1)/2
    ! + V (gamma_1 - gamma_n)/h and gamma_1 - gamma_n is the Gauss-point strain increment the
    ! force rows are the adjoint of; D the Kelvin-Voigt dissipation of those increments.
    subroutine test_ph_emi_energy_identity()
        type(planar_case_t) :: c
        real(rk) :: r(6), dq(6), gamma_1(2, 3), v1, vn, worst, d, delta(3, 3)
        integer :: ng, sample, damping
        character(len=120) :: text
        worst = 0.0_rk
        do damping = 0, 1
            do ng = 1, 3
                do sample = 1, 8
                    c = case_of(damping)
                    dq = c%q_1 - c%q_n
                    call ph_emi_residual(c%le, c%stiffness, c%viscosity, ng, c%h, c%q_n, c%q_1, &
                        c%gamma_n(:, 1:ng), r)
                    call ph_emi_strains(c%le, ng, c%q_n, c%q_1, c%gamma_n(:, 1:ng), &
                        gamma_1(:, 1:ng))
                    v1 = ph_emi_strain_energy(c%le, c%stiffness, ng, c%q_1, gamma_1(:, 1:ng))
                    vn = ph_emi_strain_energy(c%le, c%stiffness, ng, c%q_n, c%gamma_n(:, 1:ng))
                    delta(1:2, 1:ng) = gamma_1(:, 1:ng) - c%gamma_n(:, 1:ng)
                    delta(3, 1:ng) = (dq(6) - dq(3)) / c%le
                    d = viscous_dissipation(c%le, c%viscosity, ng, c%h, delta(:, 1:ng))
                    call check_balance('PH-EMi', damping, dq, r, v1, vn, d, worst)
                end do
            end do
        end do
        write(text, '(a,es9.2)') '    PH-EMi energy identity (undamped and damped), max relative error: ', &
            worst
        write(output_unit, '(a)') trim(text)
    end subroutine test_ph_emi_energy_identity

    ! ---------------------------------------------------------------------------------------
    ! Momentum, rigid motion, objectivity

    ! Internal forces sum to zero and, with lever arms at the midpoint nodes r05, exert no net
    ! torque, sum_I r05_I x F_I + m_I = 0 (discrete angular momentum, methods §4.3, §4.4), for
    ! PH-EM (any e_1) and PH-EMi: the integrands cancel at every Gauss point. cl-EM as specified
    ! in methods §5.1 (and moofeKIT) scales the force rows by Z1 and the moment rows by Z2, so
    ! its net torque is le sum_g w_g/2 (Z1_g - Z2_g) d_s r05 x (Lambda05_g N_g), O(dphi^2): the
    ! test checks that closed form (with N_g from the compatible strains), that it is non-zero
    ! for finite increments, and that the torque vanishes when the angles do not change.
    subroutine test_internal_force_and_torque()
        type(planar_case_t) :: c
        real(rk) :: r(6), r9(9), q05(6), force(2), torque, scale, zero2(2), worst_cl
        real(rk) :: defect, xi(3), w(3), gn(3, 3), g1(3, 3), nn(2), dphi, phi05, u(2), n(2)
        integer :: ng, sample, g
        logical :: ok
        character(len=120) :: text
        zero2 = 0.0_rk
        worst_cl = 0.0_rk
        do ng = 1, 3
            call gauss_legendre(ng, xi(1:ng), w(1:ng), ok)
            do sample = 1, 8
                c = random_case()
                q05 = 0.5_rk * (c%q_n + c%q_1)
                call ph_em_residual(c%le, c%stiffness, c%viscosity, ng, c%h, c%q_n, c%q_1, c%e_n, &
                    c%e_1, r9)
                call force_and_torque(q05, r9(1:6), force, torque, scale)
                CHECK_CLOSE(force, zero2, exact_tol * scale, 0.0_rk, 'PH-EM: sum F = 0')
                CHECK_CLOSE(torque, 0.0_rk, exact_tol * scale, 0.0_rk, 'PH-EM: net torque 0')
                call ph_emi_residual(c%le, c%stiffness, c%viscosity, ng, c%h, c%q_n, c%q_1, &
                    c%gamma_n(:, 1:ng), r)
                call force_and_torque(q05, r, force, torque, scale)
                CHECK_CLOSE(force, zero2, exact_tol * scale, 0.0_rk, 'PH-EMi: sum F = 0')
                CHECK_CLOSE(torque, 0.0_rk, exact_tol * scale, 0.0_rk, 'PH-EMi: net torque 0')
                ! cl-EM: the Z1/Z2 torque defect in closed form
                call cl_em_residual(c%le, c%stiffness, c%viscosity, ng, c%h, c%q_n, c%q_1, r)
                call force_and_torque(q05, r, force, torque, scale)
                CHECK_CLOSE(force, zero2, exact_tol * scale, 0.0_rk, 'cl-EM: sum F = 0')
                call compatible_strains(c%le, ng, c%q_n, gn(:, 1:ng))
                call compatible_strains(c%le, ng, c%q_1, g1(:, 1:ng))
                u = (q05(4:5) - q05(1:2)) / c%le
                defect = 0.0_rk
                do g = 1, ng
                    nn = [0.5_rk * (1.0_rk - xi(g)), 0.5_rk * (1.0_rk + xi(g))]
                    dphi = nn(1) * (c%q_1(3) - c%q_n(3)) + nn(2) * (c%q_1(6) - c%q_n(6))
                    phi05 = nn(1) * q05(3) + nn(2) * q05(6)
                    n = 0.5_rk * c%stiffness(1:2) * (gn(1:2, g) + g1(1:2, g))
                    defect = defect + 0.5_rk * w(g) * c%le * (cos(0.5_rk * dphi) &
                        - sin(0.5_rk * dphi) / (0.5_rk * dphi)) * cross2(u, matmul(rot2(phi05), n))
                end do
                CHECK_CLOSE(torque, defect, exact_tol * scale, 0.0_rk, 'cl-EM: torque = Z1/Z2 defect')
                worst_cl = max(worst_cl, abs(torque) / scale)
                ! No change of the angles: Z1 = Z2 = 1 and the torque vanishes.
                c%q_1(3) = c%q_n(3)
                c%q_1(6) = c%q_n(6)
                q05 = 0.5_rk * (c%q_n + c%q_1)
                call cl_em_residual(c%le, c%stiffness, c%viscosity, ng, c%h, c%q_n, c%q_1, r)
                call force_and_torque(q05, r, force, torque, scale)
                CHECK_CLOSE(torque, 0.0_rk, exact_tol * scale, 0.0_rk, 'cl-EM, dphi = 0: net torque 0')
            end do
        end do
        CHECK_TRUE(worst_cl > 1.0e-3_rk, 'cl-EM: the torque defect is not zero for finite dphi')
        write(text, '(a,es9.2)') '    cl-EM net internal torque / force scale, max: ', worst_cl
        write(output_unit, '(a)') trim(text)
    end subroutine test_internal_force_and_torque

    ! Rigid motion of the straight stress-free element (rotation by theta about a random point,
    ! then a shift), e_n = 0, history 0:
    ! - cl-EM: compatible strains at t_{n+1} vanish and the internal force is zero (round-off);
    ! - PH-EM: the strain rows give kappa_1 = 0, Gamma1_1 = 0, but Gamma2_1 = 2 sin(theta/2)
    !   - theta cos(theta/2) = theta^3/12 - theta^5/480 + ... (the Cayley-angle drift of
    !   methods §4.5: eq. 65 turns d_s r by 2 atan(theta/2) instead of theta);
    ! - PH-EMi: the same Gamma_1 at every Gauss point (eq. 78a is eq. 65 pointwise).
    subroutine test_rigid_motion()
        real(rk) :: thetas(7), le, stiffness(3), q_n(6), q_1(6), r(6), k(6, 6), e_1(3), drift
        real(rk) :: gam(3, 3), gamma_0(2, 3), gamma_1(2, 3), zero6(6), zero3(3), expected(3)
        real(rk) :: zero33(3, 3)
        integer :: i, ng, g
        thetas = [1.0e-3_rk, 1.0e-2_rk, 0.1_rk, -0.5_rk, 1.0_rk, 2.0_rk, -3.0_rk]
        zero6 = 0.0_rk
        zero3 = 0.0_rk
        zero33 = 0.0_rk
        gamma_0 = 0.0_rk
        do i = 1, size(thetas)
            le = uniform(0.5_rk, 2.0_rk)
            stiffness = [uniform(1.0e3_rk, 1.0e4_rk), uniform(5.0e2_rk, 5.0e3_rk), &
                uniform(10.0_rk, 100.0_rk)]
            q_n = straight_element(random_vector(2, 2.0_rk), uniform(-6.0_rk, 6.0_rk), le)
            q_1 = rigid_map(q_n, thetas(i), random_vector(2, 3.0_rk), random_vector(2, 1.0_rk))
            drift = 2.0_rk * sin(0.5_rk * thetas(i)) - thetas(i) * cos(0.5_rk * thetas(i))
            expected = [0.0_rk, drift, 0.0_rk]
            do ng = 1, 3
                call compatible_strains(le, ng, q_1, gam(:, 1:ng))
                CHECK_CLOSE(gam(:, 1:ng), zero33(:, 1:ng), 1.0e-14_rk, 0.0_rk, 'compatible strains: 0')
                call cl_em_residual(le, stiffness, no_viscosity, ng, 0.1_rk, q_n, q_1, r)
                CHECK_CLOSE(r, zero6, 1.0e-13_rk * maxval(stiffness), 0.0_rk, 'cl-EM: stress-free')
                call ph_em_condensed(le, stiffness, no_viscosity, ng, 0.1_rk, q_n, q_1, zero3, r, &
                    k, e_1)
                CHECK_CLOSE(e_1, expected, 1.0e-14_rk, 1.0e-12_rk, 'PH-EM: Gamma_1 = Cayley drift')
                call ph_emi_strains(le, ng, q_n, q_1, gamma_0(:, 1:ng), gamma_1(:, 1:ng))
                do g = 1, ng
                    CHECK_CLOSE(gamma_1(:, g), expected(1:2), 1.0e-14_rk, 1.0e-12_rk, 'PH-EMi: Cayley drift')
                end do
            end do
            if (abs(thetas(i)) <= 0.1_rk) then
                CHECK_CLOSE(drift / (thetas(i)**3 / 12.0_rk), 1.0_rk, 0.0_rk, thetas(i)**2 / 35.0_rk, 'drift ~ theta^3/12')
            end if
        end do
    end subroutine test_rigid_motion

    ! The reference stretch (reference_stretches, docs/theory/ph_planar.md "The reference
    ! stretch"): short straight elements far from the origin in random directions, the
    ! discretization of a long steel rod (le = 1e-3 at |r| up to 30: d_s r is known to
    ! eps |r| / le = 7e-12 against e1). From their own reference stretch the strains, the
    ! cl-EM step at rest, its equilibrium rows and the PH-EM projected strains of the initial
    ! coordinates are exactly zero; against e1 (the default) some are not (at most 2e-12,
    ! bound 1e-10). Prestrained (axial_reference a), the strains are (1 - a, 0), as against
    ! a e1 (to 1.9e-14, bound 1e-12), and the cl-EM energy identity holds with the reference
    ! for a random step (to 8.8e-13 relative, bound 5e-11).
    subroutine test_reference_stretch()
        real(rk) :: le, stiffness(3), q0(6), q1(6), reference(2, 2), gam(3, 2), r(6), k(6, 6)
        real(rk) :: e(3), largest_default, a, work, energy, expected(3, 2)
        integer :: ng, sample
        stiffness = [6.3e7_rk, 2.5e7_rk, 1.6e3_rk]
        le = 1.0e-3_rk
        largest_default = 0.0_rk
        do sample = 1, 20
            q0 = straight_element(random_vector(2, 30.0_rk), uniform(-6.0_rk, 6.0_rk), le)
            do ng = 1, 2
                call reference_stretches(le, ng, q0, 1.0_rk, reference(:, 1:ng))
                call compatible_strains(le, ng, q0, gam(:, 1:ng), reference(:, 1:ng))
                CHECK_TRUE(all(gam(:, 1:ng) == 0.0_rk), 'strains of the reference state: 0')
                call cl_em_residual(le, stiffness, no_viscosity, ng, 1.0e-4_rk, q0, q0, r, &
                    reference(:, 1:ng))
                CHECK_TRUE(all(r == 0.0_rk), 'cl-EM step at rest: no force')
                call cl_em_static(le, stiffness, ng, q0, r, k, reference(:, 1:ng))
                CHECK_TRUE(all(r == 0.0_rk), 'cl-EM equilibrium rows of the reference: 0')
                e = ph_em_projected_strains(le, ng, q0, reference(:, 1:ng))
                CHECK_TRUE(all(e == 0.0_rk), 'PH-EM projected strains of the reference: 0')
                call compatible_strains(le, ng, q0, gam(:, 1:ng))
                largest_default = max(largest_default, maxval(abs(gam(1:2, 1:ng))))
                a = 1.0_rk / (1.0_rk + uniform(-0.01_rk, 0.01_rk))
                call reference_stretches(le, ng, q0, a, reference(:, 1:ng))
                call compatible_strains(le, ng, q0, gam(:, 1:ng), reference(:, 1:ng))
                expected(:, 1:ng) = 0.0_rk
                expected(1, 1:ng) = 1.0_rk - a
                CHECK_CLOSE(gam(:, 1:ng), expected(:, 1:ng), 1.0e-12_rk, 0.0_rk, 'prestrained: (1 - a, 0, 0)')
                q1 = q0 + [random_vector(2, 1.0e-4_rk), uniform(-0.1_rk, 0.1_rk), &
                    random_vector(2, 1.0e-4_rk), uniform(-0.1_rk, 0.1_rk)]
                call cl_em_residual(le, stiffness, no_viscosity, ng, 1.0e-4_rk, q0, q1, r, &
                    reference(:, 1:ng))
                work = dot_product(r, q1 - q0)
                energy = compatible_strain_energy(le, stiffness, ng, q1, reference(:, 1:ng)) - &
                    compatible_strain_energy(le, stiffness, ng, q0, reference(:, 1:ng))
                CHECK_CLOSE(work, energy, 0.0_rk, 5.0e-11_rk, 'cl-EM energy identity with the reference')
            end do
        end do
        ! d_s r of these elements is known to 7e-12: against e1 their strains are round-off.
        CHECK_TRUE(largest_default > 0.0_rk, 'against e1 the reference state has strains')
        CHECK_CLOSE(largest_default, 0.0_rk, 1.0e-10_rk, 0.0_rk, 'against e1: round-off')
    end subroutine test_reference_stretch

    ! Superposed rigid motion of both endpoint states (rotation alpha about the origin, shift):
    ! nodal forces rotate by Lambda(alpha), moments, strain rows, e_1 and the PH-EMi history
    ! update are unchanged, for all three schemes.
    subroutine test_objectivity()
        type(planar_case_t) :: c, d
        real(rk) :: alpha, shift(2), rot(2, 2), r9(9), s9(9), r(6), s(6), k(6, 6), e_1(3), f_1(3)
        real(rk) :: expected(9), tol, g1(2, 3), g2(2, 3)
        integer :: ng, sample
        do ng = 1, 2
            do sample = 1, 6
                c = random_case()
                alpha = uniform(-3.0_rk, 3.0_rk)
                shift = random_vector(2, 5.0_rk)
                rot = rot2(alpha)
                d = c
                d%q_n = rigid_map(c%q_n, alpha, [0.0_rk, 0.0_rk], shift)
                d%q_1 = rigid_map(c%q_1, alpha, [0.0_rk, 0.0_rk], shift)
                call ph_em_residual(c%le, c%stiffness, c%viscosity, ng, c%h, c%q_n, c%q_1, c%e_n, &
                    c%e_1, r9)
                call ph_em_residual(d%le, d%stiffness, d%viscosity, ng, d%h, d%q_n, d%q_1, d%e_n, &
                    d%e_1, s9)
                expected = r9
                expected(1:2) = matmul(rot, r9(1:2))
                expected(4:5) = matmul(rot, r9(4:5))
                tol = 1.0e-12_rk * maxval(abs(r9))
                CHECK_CLOSE(s9, expected, tol, 0.0_rk, 'PH-EM objective')
                call ph_em_condensed(c%le, c%stiffness, c%viscosity, ng, c%h, c%q_n, c%q_1, &
                    c%e_n, r, k, e_1)
                call ph_em_condensed(d%le, d%stiffness, d%viscosity, ng, d%h, d%q_n, d%q_1, &
                    d%e_n, s, k, f_1)
                CHECK_CLOSE(f_1, e_1, 1.0e-13_rk, 0.0_rk, 'PH-EM: e_1 invariant')
                call cl_em_residual(c%le, c%stiffness, c%viscosity, ng, c%h, c%q_n, c%q_1, r)
                call cl_em_residual(d%le, d%stiffness, d%viscosity, ng, d%h, d%q_n, d%q_1, s)
                expected(1:6) = [matmul(rot, r(1:2)), r(3), matmul(rot, r(4:5)), r(6)]
                CHECK_CLOSE(s, expected(1:6), 1.0e-12_rk * maxval(abs(r)), 0.0_rk, 'cl-EM objective')
                call ph_emi_residual(c%le, c%stiffness, c%viscosity, ng, c%h, c%q_n, c%q_1, &
                    c%gamma_n(:, 1:ng), r)
                call ph_emi_residual(d%le, d%stiffness, d%viscosity, ng, d%h, d%q_n, d%q_1, &
                    d%gamma_n(:, 1:ng), s)
                expected(1:6) = [matmul(rot, r(1:2)), r(3), matmul(rot, r(4:5)), r(6)]
                CHECK_CLOSE(s, expected(1:6), 1.0e-12_rk * maxval(abs(r)), 0.0_rk, 'PH-EMi objective')
                call ph_emi_strains(c%le, ng, c%q_n, c%q_1, c%gamma_n(:, 1:ng), g1(:, 1:ng))
                call ph_emi_strains(d%le, ng, d%q_n, d%q_1, d%gamma_n(:, 1:ng), g2(:, 1:ng))
                CHECK_CLOSE(g2(:, 1:ng), g1(:, 1:ng), 1.0e-13_rk, 0.0_rk, 'PH-EMi: history invariant')
            end do
        end do
    end subroutine test_objectivity

    ! The equilibrium kernels of the quasistatic endpoint solve (DESIGN.md §3): their analytic
    ! Jacobians d/d(q, e) (static PH-EM, built from the midpoint kernels' d/dq_1 times 2), the
    ! condensed one and cl-EM's (2 d/dq_1 by the symmetry of its midpoint rows) against central
    ! differences on the random cases.
    subroutine test_static_jacobian_fd()
        call check_fd_random(static_ph_em)
        call check_fd_random(static_ph_em_cond)
        call check_fd_random(static_cl_em)
    end subroutine test_static_jacobian_fd

    ! The equilibrium rows of a state: zero for a rigidly moved straight element with zero
    ! strains (every scheme); the strain rows of static PH-EM vanish exactly at the projected
    ! strains, and at those strains its force rows are the condensed kernel's and, with one
    ! Gauss point, cl-EM's (the same compatible strain at the one point).
    subroutine test_static_equilibrium_rows()
        type(planar_case_t) :: c
        real(rk) :: q(6), r9(9), r6(6), rc(6), e(3), scale
        integer :: sample
        q = rigid_map(straight_element([0.3_rk, -0.2_rk], 0.7_rk, 1.3_rk), 2.1_rk, &
            [1.0_rk, 2.0_rk], [-0.5_rk, 0.4_rk])
        call ph_em_static(1.3_rk, [1.0e4_rk, 5.0e3_rk, 50.0_rk], 2, 0.1_rk, q, [0.0_rk, 0.0_rk, &
            0.0_rk], r9)
        CHECK_TRUE(maxval(abs(r9)) < 1.0e-9_rk, 'static PH-EM: a rigid motion is an equilibrium')
        call cl_em_static(1.3_rk, [1.0e4_rk, 5.0e3_rk, 50.0_rk], 2, q, r6)
        CHECK_TRUE(maxval(abs(r6)) < 1.0e-9_rk, 'static cl-EM: a rigid motion is an equilibrium')
        do sample = 1, 8
            c = random_case()
            e = ph_em_projected_strains(c%le, 1, c%q_1)
            call ph_em_static(c%le, c%stiffness, 1, c%h, c%q_1, e, r9)
            scale = maxval(abs(r9(1:6)))
            CHECK_TRUE(maxval(abs(r9(7:9))) < exact_tol, 'static PH-EM: strain rows 0 at e_P0')
            call ph_em_static_condensed(c%le, c%stiffness, 1, c%q_1, rc, e)
            CHECK_TRUE(maxval(abs(rc - r9(1:6))) < exact_tol * scale, 'condensed = full at e_P0')
            call cl_em_static(c%le, c%stiffness, 1, c%q_1, r6)
            CHECK_TRUE(maxval(abs(r6 - r9(1:6))) < exact_tol * scale, 'one point: PH-EM = cl-EM')
        end do
    end subroutine test_static_equilibrium_rows

    ! ---------------------------------------------------------------------------------------
    ! Kelvin-Voigt damping

    ! The analytic Jacobians with Kelvin-Voigt viscosity (the viscous stress V de/h adds V/h to
    ! dN/de_1 in PH-EM and 2 V/h to dN/dGamma05 in the displacement schemes) against central
    ! differences, for every step kernel and rule.
    subroutine test_damped_jacobian_fd()
        call check_fd_random(ph_em, damped=.true.)
        call check_fd_random(ph_em_cond, damped=.true.)
        call check_fd_random(cl_em, damped=.true.)
        call check_fd_random(ph_emi, damped=.true.)
    end subroutine test_damped_jacobian_fd

    ! Straight element along e_x stretched from rest by delta over a step h, with the axial
    ! viscosity eta only: the force on node b is the elastic EA delta/(2L) of test_axial_stretch
    ! plus eta (delta/L)/h, the viscous stress of the strain rate, for every scheme and rule
    ! (PH-EM with its strains e_n = 0, e_1 = delta/L; PH-EMi from a zero history). The
    ! dissipation of the step is L eta (delta/L)^2/h, the work of that viscous force.
    subroutine test_viscous_stretch_hand()
        real(rk) :: le, delta, h, eta, stiffness(3), viscosity(3), q0(6), qs(6), r(6), r9(9)
        real(rk) :: expected(6), gam(2, 2), strains(3, 2), d, e_1(3)
        integer :: ng, g
        le = 2.0_rk
        delta = 0.01_rk
        h = 0.05_rk
        eta = 30.0_rk
        stiffness = [1.0e4_rk, 3.0e3_rk, 50.0_rk]
        viscosity = [eta, 0.0_rk, 0.0_rk]
        q0 = [0.0_rk, 0.0_rk, 0.0_rk, le, 0.0_rk, 0.0_rk]
        qs = q0
        qs(4) = le + delta
        e_1 = [delta / le, 0.0_rk, 0.0_rk]
        expected = 0.0_rk
        expected(4) = stiffness(1) * delta / (2.0_rk * le) + eta * delta / (le * h)
        expected(1) = -expected(4)
        CHECK_CLOSE(expected(4), 28.0_rk, 1.0e-12_rk, 0.0_rk, 'EA delta/(2L) + eta delta/(L h) = 25 + 3')
        gam = 0.0_rk
        do ng = 1, 2
            call cl_em_residual(le, stiffness, viscosity, ng, h, q0, qs, r)
            CHECK_CLOSE(r, expected, 1.0e-10_rk, 0.0_rk, 'cl-EM: elastic + viscous force')
            call ph_em_residual(le, stiffness, viscosity, ng, h, q0, qs, no_viscosity, e_1, r9)
            CHECK_CLOSE(r9(1:6), expected, 1.0e-10_rk, 0.0_rk, 'PH-EM: elastic + viscous force')
            CHECK_CLOSE(r9(7:9), no_viscosity, 1.0e-12_rk, 0.0_rk, 'PH-EM: strain rows hold (0)')
            call ph_emi_residual(le, stiffness, viscosity, ng, h, q0, qs, gam(:, 1:ng), r)
            CHECK_CLOSE(r, expected, 1.0e-10_rk, 0.0_rk, 'PH-EMi: elastic + viscous force')
            call compatible_strains(le, ng, qs, strains(:, 1:ng))
            do g = 1, ng
                CHECK_CLOSE(strains(:, g), e_1, 1.0e-15_rk, 0.0_rk, 'strain delta/L')
            end do
            d = viscous_dissipation(le, viscosity, ng, h, strains(:, 1:ng))
            CHECK_CLOSE(d, le * eta * (delta / le)**2 / h, 0.0_rk, 1.0e-12_rk, 'D = L eta (delta/L)^2/h')
        end do
    end subroutine test_viscous_stretch_hand

end module rs_test_planar_element

program test_planar_element
    use rs_test_planar_element, only: run_all_tests
    use rs_test_assert, only: finish_tests
    implicit none
    call run_all_tests()
    call finish_tests()
end program test_planar_element
