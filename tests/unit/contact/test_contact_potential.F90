#include "rs_assert.h"
!> Unit tests of rs_contact_potential (DESIGN.md §5, issue 10): the C2 support boundary, the
!> derivatives and the Newton tangent against central differences, the discrete gradient
!> against a quadruple-precision quotient at every step size, the energy identity of the
!> midpoint force (also for pairs entering and leaving the support), momentum and angular
!> momentum, and zero force outside the support.
!>
!> References in quadruple precision take the same double inputs (d2 values, or nodal positions
!> and weights), so they measure the round-off of the double computation only. Each test prints
!> the largest error it measured.
module rs_test_contact_potential
    use, intrinsic :: iso_fortran_env, only: output_unit
    use rs_core_kinds, only: rk
    use rs_test_random, only: set_random_seed, random_unit_vector, uniform, random_vector
    use rs_test_assert, only: run_test, assert_true, assert_close
    use rs_contact_potential, only: contact_params_t, contact_params_init, contact_psi, &
        contact_dpsi, contact_d2psi, contact_discrete_gradient, &
        contact_discrete_gradient_derivative, contact_point_force, contact_point_tangent, &
        contact_pair_force, contact_pair_tangent
    implicit none
    private

    public :: run_all_tests

    integer, parameter :: qp = selected_real_kind(30)
    ! Parameter sets: a thick pair and a thin wire pair with a margin (scale independence).
    integer, parameter :: n_sets = 2
    ! Central differences: step relative to r_c^2 (in d2) or r_c (in positions), tolerance
    ! relative to the largest entry of the exact derivative.
    real(rk), parameter :: fd_step = 1.0e-6_rk, fd_rtol = 1.0e-7_rk
    ! Energy identity tolerance, relative to the work scale |f_a . dx_a| + |f_b . dx_b| (plus,
    ! for pairs within round-off of the support boundary only, the round-off of psi itself).
    real(rk), parameter :: energy_rtol = 1.0e-13_rk
    ! Discrete gradient against the quadruple-precision quotient, relative.
    real(rk), parameter :: quotient_rtol = 1.0e-14_rk

    !> One pair of points given by weights and nodal positions at t_n and t_{n+1}.
    type :: pair_case_t
        integer :: na = 0, nb = 0
        real(rk) :: wa(3) = 0.0_rk, wb(3) = 0.0_rk
        real(rk) :: qa_n(3, 3) = 0.0_rk, qb_n(3, 3) = 0.0_rk, qa_1(3, 3) = 0.0_rk, qb_1(3, 3) = 0.0_rk
    end type pair_case_t

contains

    !> Run every test of this file through rs_test_assert.
    subroutine run_all_tests()
        call set_random_seed(20251121, 4421)
        call run_test('params_init', test_params_init)
        call run_test('support_boundary_c2', test_support_boundary_c2)
        call run_test('normal_force_formula', test_normal_force_formula)
        call run_test('derivatives_fd', test_derivatives_fd)
        call run_test('discrete_gradient_against_quad', test_discrete_gradient_against_quad)
        call run_test('discrete_gradient_derivative_fd', test_discrete_gradient_derivative_fd)
        call run_test('discrete_gradient_branches_join', test_discrete_gradient_branches_join)
        call run_test('energy_identity', test_energy_identity)
        call run_test('momentum_and_central_force', test_momentum_and_central_force)
        call run_test('zero_outside_support', test_zero_outside_support)
        call run_test('point_tangent_fd', test_point_tangent_fd)
        call run_test('pair_tangent_nodal_fd', test_pair_tangent_nodal_fd)
        call run_test('barrier_discrete_gradient_against_quad', test_barrier_discrete_gradient_against_quad)
        call run_test('barrier_derivatives_fd', test_barrier_derivatives_fd)
        call run_test('barrier_absent_above_its_distance', test_barrier_absent_above_its_distance)
        call run_test('barrier_unbounded_at_wall', test_barrier_unbounded_at_wall)
    end subroutine run_all_tests

    ! The parameter sets with the barrier at the wall 0.3 r_c (below d_b = r_c / 2).
    function barrier_set(i) result(params)
        integer, intent(in) :: i
        type(contact_params_t) :: params
        type(contact_params_t) :: plain
        logical :: ok
        plain = parameter_set(i)
        if (i == 1) then
            call contact_params_init(params, 0.5_rk, 0.3_rk, 200.0_rk, ok, &
                wall=0.3_rk * plain%contact_distance)
        else
            call contact_params_init(params, 1.0e-3_rk, 2.5e-3_rk, 3.0e6_rk, ok, margin=1.0e-4_rk, &
                wall=0.3_rk * plain%contact_distance)
        end if
        CHECK_TRUE(ok, 'barrier parameters accepted')
    end function barrier_set

    ! psi (penalty and barrier) in quadruple precision on a double d2.
    function psi_quad(d2, params) result(psi)
        real(rk), intent(in) :: d2
        type(contact_params_t), intent(in) :: params
        real(qp) :: psi
        real(qp) :: s, sb
        s = real(params%support2, qp) - real(d2, qp)
        sb = real(params%barrier2, qp) - real(d2, qp)
        psi = real(params%coefficient, qp) * max(s, 0.0_qp)**3
        if (sb > 0.0_qp) psi = psi + real(params%barrier_coefficient, qp) * sb**3 / &
            (real(d2, qp) - real(params%wall2, qp))
    end function psi_quad

    ! psi_bar with the barrier against [psi(d2_1) - psi(d2_n)] / (d2_1 - d2_n) in quadruple
    ! precision, for d2 between the wall and beyond r_c and |d2_1 - d2_n| / r_c^2 from 1 down to
    ! 1e-8 (the quotient of the quadruple psi loses digits below: its psi values carry the
    ! double inputs exactly, but the difference of two values near the wall grows as 1/u^2);
    ! psi_bar(d2, d2) = psi'(d2); the barrier's branches (both inside, one inside) all met.
    subroutine test_barrier_discrete_gradient_against_quad()
        type(contact_params_t) :: params
        real(rk) :: rc2, d2_n, d2_1, got, ref, worst, lo, hi
        integer :: set, i, k, regime
        character(len=120) :: text
        worst = 0.0_rk
        do set = 1, n_sets
            params = barrier_set(set)
            rc2 = params%support2
            lo = params%wall2 * 1.001_rk
            hi = params%barrier2
            do regime = 1, 3
                do k = 0, 8
                    do i = 1, 30
                        select case (regime)
                        case (1)
                            d2_n = uniform(lo, hi)
                            d2_1 = d2_n + (hi - lo) * 10.0_rk**(-k) * uniform(-1.0_rk, 1.0_rk)
                        case (2)
                            d2_n = uniform(lo, hi)
                            d2_1 = uniform(hi, 1.1_rk * rc2)
                        case default
                            d2_n = uniform(hi, 1.1_rk * rc2)
                            d2_1 = uniform(lo, hi)
                        end select
                        d2_1 = min(max(d2_1, lo), 1.2_rk * rc2)
                        if (d2_1 == d2_n) cycle
                        got = contact_discrete_gradient(d2_n, d2_1, params)
                        ref = real((psi_quad(d2_1, params) - psi_quad(d2_n, params)) / &
                            (real(d2_1, qp) - real(d2_n, qp)), rk)
                        CHECK_CLOSE(got, ref, 0.0_rk, 1.0e-14_rk, 'barrier psi_bar = quadruple quotient')
                        worst = max(worst, abs(got - ref) / abs(ref))
                        CHECK_TRUE(got < 0.0_rk, 'psi_bar < 0 with the barrier')
                    end do
                end do
            end do
            do i = 1, 20
                d2_n = uniform(lo, hi)
                got = contact_discrete_gradient(d2_n, d2_n, params)
                CHECK_CLOSE(got, contact_dpsi(d2_n, params), 0.0_rk, 1.0e-14_rk, 'psi_bar(d2, d2) = dpsi(d2) in the barrier')
            end do
        end do
        write(text, '(a,es9.2)') '    max relative error of the barrier''s psi_bar: ', worst
        write(output_unit, '(a)') trim(text)
    end subroutine test_barrier_discrete_gradient_against_quad

    ! psi', psi'' and d psi_bar / d d2_1 with the barrier against central differences (steps
    ! 1e-7 of the barrier's span, on one side of d_b^2).
    subroutine test_barrier_derivatives_fd()
        type(contact_params_t) :: params
        real(rk) :: h, d2, d2_n, lo, hi, fd, exact, worst
        integer :: set, i, branch
        character(len=120) :: text
        worst = 0.0_rk
        do set = 1, n_sets
            params = barrier_set(set)
            lo = params%wall2 + 0.05_rk * params%barrier_span
            hi = params%barrier2 - 0.01_rk * params%barrier_span
            h = 1.0e-7_rk * params%barrier_span
            do i = 1, 100
                d2 = uniform(lo, hi)
                fd = (contact_psi(d2 + h, params) - contact_psi(d2 - h, params)) / (2.0_rk * h)
                exact = contact_dpsi(d2, params)
                CHECK_CLOSE(fd, exact, 0.0_rk, 1.0e-7_rk, 'barrier dpsi = central difference')
                worst = max(worst, abs(fd - exact) / abs(exact))
                fd = (contact_dpsi(d2 + h, params) - contact_dpsi(d2 - h, params)) / (2.0_rk * h)
                exact = contact_d2psi(d2, params)
                CHECK_CLOSE(fd, exact, 0.0_rk, 1.0e-7_rk, 'barrier d2psi = central difference')
                worst = max(worst, abs(fd - exact) / abs(exact))
                do branch = 1, 3
                    select case (branch)
                    case (1)
                        d2_n = uniform(lo, hi)
                    case (2)
                        d2_n = params%barrier2 + uniform(0.01_rk, 1.0_rk) * params%barrier_span
                    case default
                        ! Inside at t_n, outside at t_{n+1}: the "leaving" branch.
                        d2_n = uniform(lo, hi)
                        d2 = params%barrier2 + uniform(0.01_rk, 0.5_rk) * params%barrier_span
                    end select
                    fd = (contact_discrete_gradient(d2_n, d2 + h, params) - &
                        contact_discrete_gradient(d2_n, d2 - h, params)) / (2.0_rk * h)
                    exact = contact_discrete_gradient_derivative(d2_n, d2, params)
                    CHECK_CLOSE(fd, exact, 0.0_rk, 1.0e-7_rk, 'barrier d psi_bar / d d2_1 = central difference')
                    worst = max(worst, abs(fd - exact) / abs(exact))
                end do
            end do
        end do
        write(text, '(a,es9.2)') '    max relative FD error of the barrier''s derivatives: ', worst
        write(output_unit, '(a)') trim(text)
    end subroutine test_barrier_derivatives_fd

    ! Above the barrier's distance at both times the barrier changes no bit of psi, psi_bar and
    ! its derivative (scenes that never come that close run bitwise as without it).
    subroutine test_barrier_absent_above_its_distance()
        type(contact_params_t) :: plain, params
        real(rk) :: d2_n, d2_1
        integer :: set, i
        logical :: same
        do set = 1, n_sets
            plain = parameter_set(set)
            params = barrier_set(set)
            do i = 1, 200
                d2_n = uniform(params%barrier2, 1.2_rk * params%support2)
                d2_1 = uniform(params%barrier2, 1.2_rk * params%support2)
                same = contact_psi(d2_n, params) == contact_psi(d2_n, plain)
                CHECK_TRUE(same, 'psi bitwise')
                same = contact_discrete_gradient(d2_n, d2_1, params) == &
                    contact_discrete_gradient(d2_n, d2_1, plain)
                CHECK_TRUE(same, 'psi_bar bitwise')
                same = contact_discrete_gradient_derivative(d2_n, d2_1, params) == &
                    contact_discrete_gradient_derivative(d2_n, d2_1, plain)
                CHECK_TRUE(same, 'd psi_bar bitwise')
            end do
        end do
    end subroutine test_barrier_absent_above_its_distance

    ! The barrier is infinite at the wall: at d = d_w (1 + 1e-6) a point pair holds more than
    ! 1e4 times the penalty's whole energy psi(0) = c r_c^6 (its closed form, about 2.3e4 for
    ! d_w = 0.3 r_c: kappa U^3 / (2 d_w^2 1e-6) / (c r_c^6)), and psi grows without bound.
    subroutine test_barrier_unbounded_at_wall()
        type(contact_params_t) :: params, plain
        real(rk) :: near, nearer, ratio
        integer :: set
        character(len=120) :: text
        do set = 1, n_sets
            params = barrier_set(set)
            plain = parameter_set(set)
            near = contact_psi((params%wall * (1.0_rk + 1.0e-6_rk))**2, params)
            nearer = contact_psi((params%wall * (1.0_rk + 1.0e-9_rk))**2, params)
            ratio = near / contact_psi(0.0_rk, plain)
            CHECK_TRUE(ratio > 1.0e4_rk, 'the barrier holds more than the penalty''s whole energy')
            CHECK_CLOSE(nearer / near, 1.0e3_rk, 0.0_rk, 1.0e-3_rk, 'psi ~ 1 / (d - d_w) at the wall')
        end do
        write(text, '(a,es9.2)') '    psi at 1e-6 from the wall / psi_penalty(0): ', ratio
        write(output_unit, '(a)') trim(text)
    end subroutine test_barrier_unbounded_at_wall

    function parameter_set(i) result(params)
        integer, intent(in) :: i
        type(contact_params_t) :: params
        logical :: ok
        if (i == 1) then
            call contact_params_init(params, 0.5_rk, 0.3_rk, 200.0_rk, ok)
        else
            call contact_params_init(params, 1.0e-3_rk, 2.5e-3_rk, 3.0e6_rk, ok, margin=1.0e-4_rk)
        end if
    end function parameter_set

    subroutine test_params_init()
        type(contact_params_t) :: params
        logical :: ok
        call contact_params_init(params, 0.5_rk, 0.3_rk, 200.0_rk, ok, margin=0.2_rk)
        CHECK_TRUE(ok, 'valid parameters accepted')
        CHECK_CLOSE(params%contact_distance, 1.0_rk, 0.0_rk, 1.0e-15_rk, 'r_c = r_a + r_b + margin')
        CHECK_CLOSE(params%support2, 1.0_rk, 0.0_rk, 1.0e-15_rk, 'support2 = r_c^2')
        CHECK_CLOSE(contact_psi(0.0_rk, params), 200.0_rk / 3.0_rk, 0.0_rk, 1.0e-15_rk, 'psi(0) = k r_c^2 / 3')
        call contact_params_init(params, 0.5_rk, 0.3_rk, 200.0_rk, ok)
        CHECK_CLOSE(params%contact_distance, 0.8_rk, 0.0_rk, 1.0e-15_rk, 'margin defaults to 0')
        call contact_params_init(params, 0.0_rk, 0.3_rk, 200.0_rk, ok)
        CHECK_TRUE(.not. ok, 'zero radius rejected')
        CHECK_CLOSE(contact_dpsi(0.0_rk, params), 0.0_rk, 0.0_rk, 0.0_rk, 'rejected: zero force')
        call contact_params_init(params, 0.5_rk, 0.3_rk, -1.0_rk, ok)
        CHECK_TRUE(.not. ok, 'negative stiffness rejected')
        call contact_params_init(params, 0.5_rk, 0.3_rk, 1.0_rk, ok, margin=-0.1_rk)
        CHECK_TRUE(.not. ok, 'negative margin rejected')
    end subroutine test_params_init

    ! At d2 = r_c^2 (1 - t): psi = c (t r_c^2)^3, psi' = -3 c (t r_c^2)^2, psi'' = 6 c t r_c^2 for
    ! t from 1e-1 to 1e-12, so the value and both derivatives go to 0 at the boundary (C2); they
    ! are exactly 0 at and beyond it.
    subroutine test_support_boundary_c2()
        type(contact_params_t) :: params
        real(rk) :: rc2, c, t, d2, limits(3), worst(3)
        integer :: set, k
        character(len=160) :: text
        worst = 0.0_rk
        do set = 1, n_sets
            params = parameter_set(set)
            rc2 = params%support2
            c = params%coefficient
            do k = 1, 12
                d2 = rc2 * (1.0_rk - 10.0_rk**(-k))
                ! The t that d2 represents (r_c^2 - d2 is exact here).
                t = (rc2 - d2) / rc2
                CHECK_CLOSE(contact_psi(d2, params), c * (t * rc2)**3, 0.0_rk, 1.0e-14_rk, 'psi ~ t^3')
                CHECK_CLOSE(contact_dpsi(d2, params), -3.0_rk * c * (t * rc2)**2, 0.0_rk, 1.0e-14_rk, 'dpsi ~ t^2')
                CHECK_CLOSE(contact_d2psi(d2, params), 6.0_rk * c * t * rc2, 0.0_rk, 1.0e-14_rk, 'd2psi ~ t')
            end do
            ! Relative to the values at d2 = 0, at t = 1e-12: 1e-36, 1e-24, 1e-12.
            limits = [contact_psi(d2, params) / contact_psi(0.0_rk, params), &
                contact_dpsi(d2, params) / contact_dpsi(0.0_rk, params), &
                contact_d2psi(d2, params) / contact_d2psi(0.0_rk, params)]
            CHECK_TRUE(all(limits >= 0.0_rk), 'signs kept up to the boundary')
            CHECK_TRUE(all(limits <= 1.01_rk * [1.0e-36_rk, 1.0e-24_rk, 1.0e-12_rk]), 'psi, dpsi, d2psi -> 0')
            worst = max(worst, limits)
            do k = 0, 3
                d2 = rc2 * (1.0_rk + real(k, rk) * 1.0e-3_rk)
                CHECK_CLOSE(contact_psi(d2, params), 0.0_rk, 0.0_rk, 0.0_rk, 'psi = 0 outside')
                CHECK_CLOSE(contact_dpsi(d2, params), 0.0_rk, 0.0_rk, 0.0_rk, 'dpsi = 0 outside')
                CHECK_CLOSE(contact_d2psi(d2, params), 0.0_rk, 0.0_rk, 0.0_rk, 'd2psi = 0 outside')
            end do
            CHECK_TRUE(contact_dpsi(0.3_rk * rc2, params) < 0.0_rk, 'dpsi < 0 inside')
            CHECK_TRUE(contact_d2psi(0.3_rk * rc2, params) > 0.0_rk, 'd2psi > 0 inside')
        end do
        write(text, '(a,3es9.2)') '    psi, dpsi, d2psi at d2 = r_c^2 (1 - 1e-12), relative to d2 = 0: ', worst
        write(output_unit, '(a)') trim(text)
    end subroutine test_support_boundary_c2

    ! The normal force stated in the module header: |F| = -2 psi'(d2) d at d = r_c - delta.
    subroutine test_normal_force_formula()
        type(contact_params_t) :: params
        real(rk) :: rc, k, delta, d, force, expected, worst
        integer :: set, i
        character(len=120) :: text
        worst = 0.0_rk
        do set = 1, n_sets
            params = parameter_set(set)
            rc = params%contact_distance
            k = params%stiffness
            do i = 1, 50
                delta = rc * uniform(1.0e-6_rk, 0.99_rk)
                d = rc - delta
                force = -2.0_rk * contact_dpsi(d * d, params) * d
                expected = 8.0_rk * k * delta**2 / rc * (1.0_rk - delta / rc) * (1.0_rk - 0.5_rk * delta / rc)**2
                CHECK_CLOSE(force, expected, 0.0_rk, 1.0e-9_rk, 'normal force at penetration delta')
                worst = max(worst, abs(force - expected) / expected)
            end do
        end do
        write(text, '(a,es9.2)') '    max relative error of the stated normal force: ', worst
        write(output_unit, '(a)') trim(text)
    end subroutine test_normal_force_formula

    subroutine test_derivatives_fd()
        type(contact_params_t) :: params
        real(rk) :: rc2, h, d2, fd, exact, worst1, worst2
        integer :: set, i
        character(len=120) :: text
        worst1 = 0.0_rk
        worst2 = 0.0_rk
        do set = 1, n_sets
            params = parameter_set(set)
            rc2 = params%support2
            h = fd_step * rc2
            do i = 1, 200
                ! Inside and outside, at least 10 steps away from the boundary (psi''' jumps there).
                d2 = rc2 * uniform(0.0_rk, 1.3_rk)
                if (abs(d2 - rc2) < 10.0_rk * h) cycle
                fd = (contact_psi(d2 + h, params) - contact_psi(d2 - h, params)) / (2.0_rk * h)
                exact = contact_dpsi(d2, params)
                CHECK_CLOSE(fd, exact, fd_rtol * params%stiffness, fd_rtol, 'dpsi = central difference')
                worst1 = max(worst1, abs(fd - exact) / params%stiffness)
                fd = (contact_dpsi(d2 + h, params) - contact_dpsi(d2 - h, params)) / (2.0_rk * h)
                exact = contact_d2psi(d2, params)
                CHECK_CLOSE(fd, exact, fd_rtol * params%stiffness / rc2, fd_rtol, 'd2psi = central difference')
                worst2 = max(worst2, abs(fd - exact) / (params%stiffness / rc2))
            end do
        end do
        write(text, '(a,es9.2,a,es9.2)') '    max FD error: dpsi / k ', worst1, ', d2psi / (k / r_c^2) ', worst2
        write(output_unit, '(a)') trim(text)
    end subroutine test_derivatives_fd

    ! psi_bar against [psi(d2_1) - psi(d2_n)] / (d2_1 - d2_n) in quadruple precision on the same
    ! double inputs, for |d2_1 - d2_n| / r_c^2 from 1 down to 1e-16 and 0, inside, across and
    ! near the boundary.
    subroutine test_discrete_gradient_against_quad()
        type(contact_params_t) :: params
        real(rk) :: rc2, d2_n, d2_1, got, ref, swapped, worst
        integer :: set, i, k, regime
        character(len=120) :: text
        worst = 0.0_rk
        do set = 1, n_sets
            params = parameter_set(set)
            rc2 = params%support2
            do regime = 1, 4
                do k = 0, 17
                    do i = 1, 20
                        select case (regime)
                        case (1)
                            d2_n = rc2 * uniform(0.0_rk, 0.99_rk)
                        case (2)
                            d2_n = rc2 * (1.0_rk - uniform(1.0e-12_rk, 1.0e-6_rk))
                        case (3)
                            d2_n = rc2 * (1.0_rk + uniform(0.0_rk, 0.5_rk))
                        case default
                            d2_n = rc2 * uniform(0.9_rk, 1.1_rk)
                        end select
                        d2_1 = d2_n
                        if (k < 17) d2_1 = d2_n + rc2 * 10.0_rk**(-k) * uniform(-1.0_rk, 1.0_rk)
                        d2_1 = max(d2_1, 0.0_rk)
                        got = contact_discrete_gradient(d2_n, d2_1, params)
                        ref = quotient_quad(d2_n, d2_1, params)
                        CHECK_CLOSE(got, ref, 0.0_rk, quotient_rtol, 'psi_bar = quadruple quotient')
                        if (ref /= 0.0_rk) worst = max(worst, abs(got - ref) / abs(ref))
                        if (ref == 0.0_rk) then
                            CHECK_CLOSE(got, 0.0_rk, 0.0_rk, 0.0_rk, 'psi_bar = 0 outside')
                        end if
                        swapped = contact_discrete_gradient(d2_1, d2_n, params)
                        CHECK_CLOSE(swapped, got, 0.0_rk, 5.0e-16_rk, 'psi_bar symmetric')
                        CHECK_TRUE(got <= 0.0_rk, 'psi_bar <= 0')
                    end do
                end do
            end do
            d2_n = 0.37_rk * rc2
            got = contact_discrete_gradient(d2_n, d2_n, params)
            CHECK_CLOSE(got, contact_dpsi(d2_n, params), 0.0_rk, 1.0e-15_rk, 'psi_bar(d2, d2) = dpsi(d2)')
        end do
        write(text, '(a,es9.2)') '    max relative error of psi_bar against the quadruple quotient: ', worst
        write(output_unit, '(a)') trim(text)
    end subroutine test_discrete_gradient_against_quad

    ! [psi(d2_1) - psi(d2_n)] / (d2_1 - d2_n) in quadruple precision, psi'(d2_n) if equal.
    function quotient_quad(d2_n, d2_1, params) result(q)
        real(rk), intent(in) :: d2_n, d2_1
        type(contact_params_t), intent(in) :: params
        real(rk) :: q
        real(qp) :: s_n, s_1
        s_n = real(params%support2, qp) - real(d2_n, qp)
        s_1 = real(params%support2, qp) - real(d2_1, qp)
        if (d2_n == d2_1) then
            q = real(-3.0_qp * real(params%coefficient, qp) * max(s_n, 0.0_qp)**2, rk)
        else
            q = real(real(params%coefficient, qp) * (max(s_1, 0.0_qp)**3 - max(s_n, 0.0_qp)**3) &
                / (real(d2_1, qp) - real(d2_n, qp)), rk)
        end if
    end function quotient_quad

    ! d psi_bar / d d2_1 against central differences in d2_1, in each branch (both inside, leaving,
    ! entering), with the step kept on one side of the boundary.
    subroutine test_discrete_gradient_derivative_fd()
        type(contact_params_t) :: params
        real(rk) :: rc2, h, d2_n, d2_1, fd, exact, scale, worst
        integer :: set, i, branch
        character(len=120) :: text
        worst = 0.0_rk
        do set = 1, n_sets
            params = parameter_set(set)
            rc2 = params%support2
            h = fd_step * rc2
            scale = params%stiffness / rc2
            do branch = 1, 3
                do i = 1, 100
                    select case (branch)
                    case (1)
                        d2_n = rc2 * uniform(0.0_rk, 0.99_rk)
                        d2_1 = rc2 * uniform(0.0_rk, 0.99_rk)
                        ! Includes the tiny step and the zero step.
                        if (i <= 10) d2_1 = d2_n + rc2 * 10.0_rk**(-i) * uniform(-1.0_rk, 1.0_rk)
                        if (i == 11) d2_1 = d2_n
                    case (2)
                        d2_n = rc2 * uniform(0.0_rk, 0.99_rk)
                        d2_1 = rc2 * uniform(1.01_rk, 1.5_rk)
                    case default
                        d2_n = rc2 * uniform(1.01_rk, 1.5_rk)
                        d2_1 = rc2 * uniform(0.0_rk, 0.99_rk)
                    end select
                    d2_1 = max(d2_1, 2.0_rk * h)
                    fd = (contact_discrete_gradient(d2_n, d2_1 + h, params) &
                        - contact_discrete_gradient(d2_n, d2_1 - h, params)) / (2.0_rk * h)
                    exact = contact_discrete_gradient_derivative(d2_n, d2_1, params)
                    CHECK_CLOSE(fd, exact, fd_rtol * scale, fd_rtol, 'd psi_bar / d d2_1 = central difference')
                    worst = max(worst, abs(fd - exact) / scale)
                end do
            end do
            ! Both outside: zero.
            exact = contact_discrete_gradient_derivative(1.2_rk * rc2, 1.1_rk * rc2, params)
            CHECK_CLOSE(exact, 0.0_rk, 0.0_rk, 0.0_rk, 'zero derivative outside')
        end do
        write(text, '(a,es9.2)') '    max FD error of d psi_bar / d d2_1 / (k / r_c^2): ', worst
        write(output_unit, '(a)') trim(text)
    end subroutine test_discrete_gradient_derivative_fd

    ! The branches (both inside; one outside) meet at d2_1 = r_c^2 with equal values, first and
    ! second derivatives: the jumps over a gap 2 tau shrink like tau, tau, tau respectively.
    subroutine test_discrete_gradient_branches_join()
        type(contact_params_t) :: params
        real(rk) :: rc2, tau, d2_n, g(2), dg(2), scale
        integer :: set, i, k
        do set = 1, n_sets
            params = parameter_set(set)
            rc2 = params%support2
            scale = params%stiffness / rc2
            do i = 1, 20
                do k = 4, 10
                    tau = rc2 * 10.0_rk**(-k)
                    ! Second argument crossing, first inside; then first crossing, second inside.
                    d2_n = rc2 * uniform(0.0_rk, 0.9_rk)
                    g = contact_discrete_gradient(d2_n, [rc2 - tau, rc2 + tau], params)
                    dg = contact_discrete_gradient_derivative(d2_n, [rc2 - tau, rc2 + tau], params)
                    CHECK_TRUE(abs(g(1) - g(2)) <= 4.0_rk * scale * tau, 'psi_bar continuous (d2_1 crossing)')
                    CHECK_TRUE(abs(dg(1) - dg(2)) <= 4.0_rk * scale * tau / rc2, 'derivative continuous (d2_1)')
                    g = contact_discrete_gradient([rc2 - tau, rc2 + tau], d2_n, params)
                    dg = contact_discrete_gradient_derivative([rc2 - tau, rc2 + tau], d2_n, params)
                    CHECK_TRUE(abs(g(1) - g(2)) <= 4.0_rk * scale * tau, 'psi_bar continuous (d2_n crossing)')
                    CHECK_TRUE(abs(dg(1) - dg(2)) <= 4.0_rk * scale * tau / rc2, 'derivative continuous (d2_n)')
                end do
            end do
        end do
    end subroutine test_discrete_gradient_branches_join

    ! A pair with random elements (1, 2 or 3 nodes; weights of a Lagrange element at a random
    ! point) whose relative position r = x_a - x_b is r_n at t_n and r_1 at t_{n+1}; every node
    ! also moves by `node_step` (times a random vector) so that the points move individually.
    function make_pair(r_n, r_1, node_step, rc) result(pc)
        real(rk), intent(in) :: r_n(3), r_1(3), node_step, rc
        type(pair_case_t) :: pc
        integer :: j
        pc%na = 1 + mod(int(uniform(0.0_rk, 3.0_rk)), 3)
        pc%nb = 1 + mod(int(uniform(0.0_rk, 3.0_rk)), 3)
        pc%wa(1:pc%na) = lagrange_weights(pc%na, uniform(-1.0_rk, 1.0_rk))
        pc%wb(1:pc%nb) = lagrange_weights(pc%nb, uniform(-1.0_rk, 1.0_rk))
        do j = 1, 3
            pc%qa_n(:, j) = random_vector(3, 2.0_rk * rc)
            pc%qb_n(:, j) = random_vector(3, 2.0_rk * rc)
            pc%qa_1(:, j) = pc%qa_n(:, j) + random_vector(3, node_step)
            pc%qb_1(:, j) = pc%qb_n(:, j) + random_vector(3, node_step)
        end do
        ! Shift element b (weights sum to 1) so that x_a - x_b = r at both times.
        call shift(pc%qb_n, point(pc%qa_n, pc%wa, pc%na) - r_n - point(pc%qb_n, pc%wb, pc%nb))
        call shift(pc%qb_1, point(pc%qa_1, pc%wa, pc%na) - r_1 - point(pc%qb_1, pc%wb, pc%nb))
    contains
        subroutine shift(q, v)
            real(rk), intent(inout) :: q(3, 3)
            real(rk), intent(in) :: v(3)
            integer :: i
            do i = 1, 3
                q(:, i) = q(:, i) + v
            end do
        end subroutine shift
    end function make_pair

    function lagrange_weights(n, xi) result(w)
        integer, intent(in) :: n
        real(rk), intent(in) :: xi
        real(rk) :: w(n)
        select case (n)
        case (1)
            w = 1.0_rk
        case (2)
            w = [0.5_rk * (1.0_rk - xi), 0.5_rk * (1.0_rk + xi)]
        case default
            w = [0.5_rk * xi * (xi - 1.0_rk), 1.0_rk - xi**2, 0.5_rk * xi * (xi + 1.0_rk)]
        end select
    end function lagrange_weights

    function point(q, w, n) result(x)
        real(rk), intent(in) :: q(3, 3), w(3)
        integer, intent(in) :: n
        real(rk) :: x(3)
        x = matmul(q(:, 1:n), w(1:n))
    end function point

    ! Energy increment psi(d2_1) - psi(d2_n) in quadruple precision from the double positions.
    function energy_increment_quad(pc, params) result(dpsi)
        type(pair_case_t), intent(in) :: pc
        type(contact_params_t), intent(in) :: params
        real(qp) :: dpsi
        real(qp) :: r_n(3), r_1(3), s_n, s_1, c
        r_n = matmul(real(pc%qa_n(:, 1:pc%na), qp), real(pc%wa(1:pc%na), qp)) &
            - matmul(real(pc%qb_n(:, 1:pc%nb), qp), real(pc%wb(1:pc%nb), qp))
        r_1 = matmul(real(pc%qa_1(:, 1:pc%na), qp), real(pc%wa(1:pc%na), qp)) &
            - matmul(real(pc%qb_1(:, 1:pc%nb), qp), real(pc%wb(1:pc%nb), qp))
        c = real(params%coefficient, qp)
        s_n = max(real(params%support2, qp) - sum(r_n**2), 0.0_qp)
        s_1 = max(real(params%support2, qp) - sum(r_1**2), 0.0_qp)
        dpsi = c * (s_1**3 - s_n**3)
    end function energy_increment_quad

    ! Forces through contact_pair_force, distributed to the nodes with the weights; the work
    ! sum_i w_i f_a . (q_a,1 - q_a,n)_i + sum_j w_j f_b . (q_b,1 - q_b,n)_j and its scale.
    subroutine pair_work(pc, params, f_a, f_b, work, work_scale)
        type(pair_case_t), intent(in) :: pc
        type(contact_params_t), intent(in) :: params
        real(rk), intent(out) :: f_a(3), f_b(3), work, work_scale
        real(rk) :: term
        integer :: i
        call contact_pair_force(pc%wa(1:pc%na), pc%wb(1:pc%nb), pc%qa_n(:, 1:pc%na), pc%qb_n(:, 1:pc%nb), &
            pc%qa_1(:, 1:pc%na), pc%qb_1(:, 1:pc%nb), params, f_a, f_b)
        work = 0.0_rk
        work_scale = 0.0_rk
        do i = 1, pc%na
            term = pc%wa(i) * dot_product(f_a, pc%qa_1(:, i) - pc%qa_n(:, i))
            work = work + term
            work_scale = work_scale + abs(term)
        end do
        do i = 1, pc%nb
            term = pc%wb(i) * dot_product(f_b, pc%qb_1(:, i) - pc%qb_n(:, i))
            work = work + term
            work_scale = work_scale + abs(term)
        end do
    end subroutine pair_work

    ! psi(d2_1) - psi(d2_n) = f_a . dx_a + f_b . dx_b for random pairs and steps: both points in
    ! the support with steps |r_1 - r_n| / r_c from 1e-1 down to 1e-14 and 0, rigid rotations
    ! of the pair (d2 unchanged), leaving and entering the support, and crossing within 1e-10 of
    ! the boundary. Checked against the quadruple-precision increment (relative to the work
    ! scale) and, literally, against the double increment (relative to the energy). Distances
    ! are at least 0.3 r_c (penetration far beyond the working range): r = x_a - x_b carries the
    ! round-off of the positions, eps |x|, which relative to |r| grows as the points coincide.
    subroutine test_energy_identity()
        type(contact_params_t) :: params
        type(pair_case_t) :: pc
        real(rk) :: rc, r_n(3), r_1(3), step, node_step, f_a(3), f_b(3), work, scale, psi_n, psi_1
        real(rk) :: error, worst(5), worst_literal(5), psi_scale, floor
        real(qp) :: reference
        integer :: set, i, k, kind
        character(len=160) :: text
        worst = 0.0_rk
        worst_literal = 0.0_rk
        do set = 1, n_sets
            params = parameter_set(set)
            rc = params%contact_distance
            do kind = 1, 5
                do k = 0, 15
                    do i = 1, 20
                        step = 0.0_rk
                        if (k > 0) step = rc * 10.0_rk**(-k)
                        node_step = max(step, rc * 1.0e-14_rk)
                        select case (kind)
                        case (1)
                            ! Both in the support (r_1 redrawn until it is).
                            r_n = rc * uniform(0.3_rk, 0.97_rk) * random_unit_vector()
                            do
                                r_1 = r_n + step * random_unit_vector()
                                if (norm2(r_1) < 0.99_rk * rc) exit
                            end do
                        case (2)
                            ! Rotation of r about a random axis: d2 unchanged.
                            r_n = rc * uniform(0.3_rk, 0.97_rk) * random_unit_vector()
                            r_1 = rotate(r_n, random_unit_vector(), uniform(-3.0_rk, 3.0_rk))
                            node_step = rc
                        case (3)
                            ! Leaving: inside with r_c^2 - d2 >= 0.05 r_c^2, then outside.
                            r_n = rc * uniform(0.3_rk, 0.97_rk) * random_unit_vector()
                            r_1 = rc * uniform(1.001_rk, 1.5_rk) * random_unit_vector()
                            node_step = rc
                        case (4)
                            ! Entering.
                            r_n = rc * uniform(1.001_rk, 1.5_rk) * random_unit_vector()
                            r_1 = rc * uniform(0.3_rk, 0.97_rk) * random_unit_vector()
                            node_step = rc
                        case default
                            ! Crossing within 1e-10 r_c of the boundary, either way.
                            r_n = rc * (1.0_rk + uniform(-1.0e-10_rk, 1.0e-10_rk)) * random_unit_vector()
                            r_1 = rc * (1.0_rk + uniform(-1.0e-10_rk, 1.0e-10_rk)) * random_unit_vector()
                        end select
                        pc = make_pair(r_n, r_1, node_step, rc)
                        call pair_work(pc, params, f_a, f_b, work, scale)
                        reference = energy_increment_quad(pc, params)
                        floor = 0.0_rk
                        if (kind == 5) then
                            ! psi within round-off of the boundary is itself only known to |psi'|
                            ! times the round-off of d2 (a few eps r_c^2): the error floor here.
                            floor = 8.0_rk * epsilon(1.0_rk) * params%support2 * max( &
                                abs(contact_dpsi(d2_of(pc%qa_n, pc%qb_n, pc), params)), &
                                abs(contact_dpsi(d2_of(pc%qa_1, pc%qb_1, pc), params)))
                        end if
                        error = abs(work - real(reference, rk))
                        CHECK_TRUE(error <= energy_rtol * scale + floor, 'energy increment = work of the midpoint force')
                        if (scale + floor > 0.0_rk) worst(kind) = max(worst(kind), error / (scale + floor / energy_rtol))
                        if (scale == 0.0_rk .and. kind /= 5) then
                            CHECK_TRUE(error == 0.0_rk, 'no work, no energy change')
                        end if
                        ! The literal identity in double precision, relative to the energy.
                        psi_n = contact_psi(d2_of(pc%qa_n, pc%qb_n, pc), params)
                        psi_1 = contact_psi(d2_of(pc%qa_1, pc%qb_1, pc), params)
                        psi_scale = max(psi_n, psi_1, scale)
                        error = abs(psi_1 - psi_n - work)
                        CHECK_TRUE(error <= energy_rtol * psi_scale + floor, 'psi_1 - psi_n = work, in double')
                        if (psi_scale + floor > 0.0_rk) then
                            worst_literal(kind) = max(worst_literal(kind), error / (psi_scale + floor / energy_rtol))
                        end if
                    end do
                end do
            end do
        end do
        write(text, '(a,5es9.2)') '    max energy error / work scale (inside, rotation, leaving, entering, '// &
            'boundary): ', worst
        write(output_unit, '(a)') trim(text)
        write(text, '(a,5es9.2)') '    same, double psi_1 - psi_n / max(psi_n, psi_1, work scale): ', &
            worst_literal
        write(output_unit, '(a)') trim(text)
    end subroutine test_energy_identity

    function d2_of(qa, qb, pc) result(d2)
        real(rk), intent(in) :: qa(3, 3), qb(3, 3)
        type(pair_case_t), intent(in) :: pc
        real(rk) :: d2, r(3)
        r = point(qa, pc%wa, pc%na) - point(qb, pc%wb, pc%nb)
        d2 = dot_product(r, r)
    end function d2_of

    ! Rodrigues' rotation of v about the unit axis by angle.
    function rotate(v, axis, angle) result(w)
        real(rk), intent(in) :: v(3), axis(3), angle
        real(rk) :: w(3)
        w = v * cos(angle) + cross(axis, v) * sin(angle) + axis * dot_product(axis, v) * (1.0_rk - cos(angle))
    end function rotate

    function cross(a, b) result(c)
        real(rk), intent(in) :: a(3), b(3)
        real(rk) :: c(3)
        c = [a(2) * b(3) - a(3) * b(2), a(3) * b(1) - a(1) * b(3), a(1) * b(2) - a(2) * b(1)]
    end function cross

    ! f_a + f_b = 0 exactly; r_mid x f_a = 0 and the total moment of the nodal forces about the
    ! origin at the midpoint vanish to round-off; the physical force -f_a is repulsive.
    subroutine test_momentum_and_central_force()
        type(contact_params_t) :: params
        type(pair_case_t) :: pc
        real(rk) :: rc, r_n(3), r_1(3), f_a(3), f_b(3), work, scale, r_mid(3), moment(3), magnitude
        real(rk) :: worst_central, worst_moment
        real(rk), parameter :: zero3(3) = 0.0_rk
        integer :: set, i, j
        character(len=160) :: text
        worst_central = 0.0_rk
        worst_moment = 0.0_rk
        do set = 1, n_sets
            params = parameter_set(set)
            rc = params%contact_distance
            do i = 1, 300
                r_n = rc * uniform(0.05_rk, 0.97_rk) * random_unit_vector()
                r_1 = rc * uniform(0.05_rk, 1.3_rk) * random_unit_vector()
                pc = make_pair(r_n, r_1, rc, rc)
                call pair_work(pc, params, f_a, f_b, work, scale)
                CHECK_CLOSE(f_a + f_b, zero3, 0.0_rk, 0.0_rk, 'f_a + f_b = 0')
                r_mid = 0.5_rk * (point(pc%qa_n, pc%wa, pc%na) + point(pc%qa_1, pc%wa, pc%na)) &
                    - 0.5_rk * (point(pc%qb_n, pc%wb, pc%nb) + point(pc%qb_1, pc%wb, pc%nb))
                magnitude = norm2(r_mid) * norm2(f_a)
                CHECK_TRUE(norm2(cross(r_mid, f_a)) <= 1.0e-14_rk * magnitude, '(x_a - x_b)_mid x f_a = 0')
                worst_central = max(worst_central, norm2(cross(r_mid, f_a)) / magnitude)
                CHECK_TRUE(dot_product(f_a, r_mid) < 0.0_rk, 'repulsive: -f_a points from b to a')
                ! Moment about the origin of the nodal forces w_i f at the nodal midpoints.
                moment = 0.0_rk
                magnitude = 0.0_rk
                do j = 1, pc%na
                    moment = moment + pc%wa(j) * cross(0.5_rk * (pc%qa_n(:, j) + pc%qa_1(:, j)), f_a)
                    magnitude = magnitude + abs(pc%wa(j)) * norm2(0.5_rk * (pc%qa_n(:, j) + pc%qa_1(:, j))) * norm2(f_a)
                end do
                do j = 1, pc%nb
                    moment = moment + pc%wb(j) * cross(0.5_rk * (pc%qb_n(:, j) + pc%qb_1(:, j)), f_b)
                    magnitude = magnitude + abs(pc%wb(j)) * norm2(0.5_rk * (pc%qb_n(:, j) + pc%qb_1(:, j))) * norm2(f_b)
                end do
                CHECK_TRUE(norm2(moment) <= 1.0e-14_rk * magnitude, 'total moment of the nodal forces = 0')
                worst_moment = max(worst_moment, norm2(moment) / magnitude)
            end do
        end do
        write(text, '(a,es9.2,a,es9.2)') '    max |r_mid x f_a| / (|r_mid| |f_a|): ', worst_central, &
            ', nodal moment / scale: ', worst_moment
        write(output_unit, '(a)') trim(text)
    end subroutine test_momentum_and_central_force

    subroutine test_zero_outside_support()
        type(contact_params_t) :: params
        real(rk) :: rc, xa_n(3), xb_n(3), xa_1(3), xb_1(3), f_a(3), f_b(3), tangent(6, 6)
        real(rk), parameter :: zero3(3) = 0.0_rk, zero66(6, 6) = 0.0_rk
        integer :: set, i
        do set = 1, n_sets
            params = parameter_set(set)
            rc = params%contact_distance
            do i = 1, 100
                xa_n = random_vector(3, 3.0_rk * rc)
                xa_1 = xa_n + random_vector(3, rc)
                xb_n = xa_n + rc * uniform(1.0_rk + 1.0e-12_rk, 3.0_rk) * random_unit_vector()
                xb_1 = xa_1 + rc * uniform(1.0_rk + 1.0e-12_rk, 3.0_rk) * random_unit_vector()
                if (sum((xa_n - xb_n)**2) < params%support2 .or. sum((xa_1 - xb_1)**2) < params%support2) cycle
                call contact_point_force(xa_n, xb_n, xa_1, xb_1, params, f_a, f_b)
                call contact_point_tangent(xa_n, xb_n, xa_1, xb_1, params, tangent)
                CHECK_CLOSE(f_a, zero3, 0.0_rk, 0.0_rk, 'f_a = 0 outside')
                CHECK_CLOSE(f_b, zero3, 0.0_rk, 0.0_rk, 'f_b = 0 outside')
                CHECK_CLOSE(tangent, zero66, 0.0_rk, 0.0_rk, 'tangent = 0 outside')
            end do
            ! Exactly at the contact distance at both times (d2 = r_c^2 in floating point).
            xa_n = 0.0_rk
            xb_n = [rc, 0.0_rk, 0.0_rk]
            xa_1 = [0.0_rk, 1.0_rk, 0.0_rk]
            xb_1 = [0.0_rk, 1.0_rk, rc]
            call contact_point_force(xa_n, xb_n, xa_1, xb_1, params, f_a, f_b)
            call contact_point_tangent(xa_n, xb_n, xa_1, xb_1, params, tangent)
            CHECK_CLOSE(f_a, zero3, 0.0_rk, 0.0_rk, 'f_a = 0 at the contact distance')
            CHECK_CLOSE(tangent, zero66, 0.0_rk, 0.0_rk, 'tangent = 0 at the contact distance')
            ! Inside at t_n only: the discrete gradient acts (the pair must be kept in the step).
            xb_n = [0.5_rk * rc, 0.0_rk, 0.0_rk]
            call contact_point_force(xa_n, xb_n, xa_1, xb_1, params, f_a, f_b)
            CHECK_TRUE(norm2(f_a) > 0.0_rk, 'force when one end of the step is inside')
        end do
    end subroutine test_zero_outside_support

    ! contact_point_tangent against central differences of contact_point_force in x_a,1 and
    ! x_b,1: both inside (steps down to 1e-10 r_c and zero), leaving, entering.
    subroutine test_point_tangent_fd()
        type(contact_params_t) :: params
        real(rk) :: rc, xa_n(3), xb_n(3), xa_1(3), xb_1(3), r_n(3), r_1(3), tangent(6, 6), fd(6, 6)
        real(rk) :: error, worst
        integer :: set, i, branch
        character(len=120) :: text
        worst = 0.0_rk
        do set = 1, n_sets
            params = parameter_set(set)
            rc = params%contact_distance
            do branch = 1, 3
                do i = 1, 60
                    select case (branch)
                    case (1)
                        r_n = rc * uniform(0.05_rk, 0.97_rk) * random_unit_vector()
                        r_1 = rc * uniform(0.05_rk, 0.97_rk) * random_unit_vector()
                        if (i <= 10) r_1 = r_n + rc * 10.0_rk**(-i) * random_unit_vector()
                        if (i == 11) r_1 = r_n
                        if (norm2(r_1) > 0.99_rk * rc) cycle
                    case (2)
                        r_n = rc * uniform(0.05_rk, 0.97_rk) * random_unit_vector()
                        r_1 = rc * uniform(1.01_rk, 1.5_rk) * random_unit_vector()
                    case default
                        r_n = rc * uniform(1.01_rk, 1.5_rk) * random_unit_vector()
                        r_1 = rc * uniform(0.05_rk, 0.97_rk) * random_unit_vector()
                    end select
                    xa_n = random_vector(3, 2.0_rk * rc)
                    xb_n = xa_n - r_n
                    xa_1 = xa_n + random_vector(3, rc)
                    xb_1 = xa_1 - r_1
                    call contact_point_tangent(xa_n, xb_n, xa_1, xb_1, params, tangent)
                    fd = point_fd(xa_n, xb_n, xa_1, xb_1, params)
                    error = maxval(abs(fd - tangent)) / maxval(abs(tangent))
                    CHECK_TRUE(error <= fd_rtol, 'point tangent = central differences')
                    worst = max(worst, error)
                    CHECK_CLOSE(tangent(4:6, 4:6), tangent(1:3, 1:3), 0.0_rk, 0.0_rk, 'block structure')
                    CHECK_CLOSE(tangent(1:3, 4:6), -tangent(1:3, 1:3), 0.0_rk, 0.0_rk, 'block structure')
                end do
            end do
        end do
        write(text, '(a,es9.2)') '    max FD error of the point tangent / max entry: ', worst
        write(output_unit, '(a)') trim(text)
    end subroutine test_point_tangent_fd

    function point_fd(xa_n, xb_n, xa_1, xb_1, params) result(fd)
        real(rk), intent(in) :: xa_n(3), xb_n(3), xa_1(3), xb_1(3)
        type(contact_params_t), intent(in) :: params
        real(rk) :: fd(6, 6)
        real(rk) :: x(6), xp(6), xm(6), fp(6), fm(6), h
        integer :: k
        h = fd_step * params%contact_distance
        x = [xa_1, xb_1]
        do k = 1, 6
            xp = x
            xm = x
            xp(k) = xp(k) + h
            xm(k) = xm(k) - h
            call contact_point_force(xa_n, xb_n, xp(1:3), xp(4:6), params, fp(1:3), fp(4:6))
            call contact_point_force(xa_n, xb_n, xm(1:3), xm(4:6), params, fm(1:3), fm(4:6))
            fd(:, k) = (fp - fm) / (2.0_rk * h)
        end do
    end function point_fd

    ! contact_pair_tangent through the chain rule: moving node j of element a by h e_k moves x_a
    ! by w_j h e_k, so d(f_a, f_b) / d q_a,j = w_j tangent(:, 1:3) (likewise b); and the pair
    ! routines equal the point routines at the interpolated points.
    subroutine test_pair_tangent_nodal_fd()
        type(contact_params_t) :: params
        type(pair_case_t) :: pc, pp, pm
        real(rk) :: rc, r_n(3), r_1(3), tangent(6, 6), point_tangent(6, 6), fp(6), fm(6), h
        real(rk) :: fd(6), error, worst
        integer :: set, i, j, k
        character(len=120) :: text
        worst = 0.0_rk
        do set = 1, n_sets
            params = parameter_set(set)
            rc = params%contact_distance
            h = fd_step * rc
            do i = 1, 40
                r_n = rc * uniform(0.05_rk, 0.97_rk) * random_unit_vector()
                r_1 = rc * uniform(0.05_rk, 0.97_rk) * random_unit_vector()
                if (mod(i, 4) == 0) r_1 = rc * uniform(1.01_rk, 1.5_rk) * random_unit_vector()
                pc = make_pair(r_n, r_1, rc, rc)
                call contact_pair_tangent(pc%wa(1:pc%na), pc%wb(1:pc%nb), pc%qa_n(:, 1:pc%na), &
                    pc%qb_n(:, 1:pc%nb), pc%qa_1(:, 1:pc%na), pc%qb_1(:, 1:pc%nb), params, tangent)
                call contact_point_tangent(point(pc%qa_n, pc%wa, pc%na), point(pc%qb_n, pc%wb, pc%nb), &
                    point(pc%qa_1, pc%wa, pc%na), point(pc%qb_1, pc%wb, pc%nb), params, point_tangent)
                CHECK_CLOSE(tangent, point_tangent, 0.0_rk, 1.0e-15_rk, 'pair tangent = point tangent')
                do j = 1, pc%na
                    if (abs(pc%wa(j)) < 0.05_rk) cycle
                    do k = 1, 3
                        pp = pc
                        pm = pc
                        pp%qa_1(k, j) = pp%qa_1(k, j) + h
                        pm%qa_1(k, j) = pm%qa_1(k, j) - h
                        call pair_forces(pp, params, fp)
                        call pair_forces(pm, params, fm)
                        fd = (fp - fm) / (2.0_rk * h)
                        error = maxval(abs(fd - pc%wa(j) * tangent(:, k))) / maxval(abs(pc%wa(j) * tangent))
                        CHECK_TRUE(error <= fd_rtol, 'd f / d q_a,j = w_j tangent')
                        worst = max(worst, error)
                    end do
                end do
                do j = 1, pc%nb
                    if (abs(pc%wb(j)) < 0.05_rk) cycle
                    do k = 1, 3
                        pp = pc
                        pm = pc
                        pp%qb_1(k, j) = pp%qb_1(k, j) + h
                        pm%qb_1(k, j) = pm%qb_1(k, j) - h
                        call pair_forces(pp, params, fp)
                        call pair_forces(pm, params, fm)
                        fd = (fp - fm) / (2.0_rk * h)
                        error = maxval(abs(fd - pc%wb(j) * tangent(:, 3 + k))) / maxval(abs(pc%wb(j) * tangent))
                        CHECK_TRUE(error <= fd_rtol, 'd f / d q_b,j = w_j tangent')
                        worst = max(worst, error)
                    end do
                end do
            end do
        end do
        write(text, '(a,es9.2)') '    max FD error of the nodal chain / max entry: ', worst
        write(output_unit, '(a)') trim(text)
    end subroutine test_pair_tangent_nodal_fd

    subroutine pair_forces(pc, params, f)
        type(pair_case_t), intent(in) :: pc
        type(contact_params_t), intent(in) :: params
        real(rk), intent(out) :: f(6)
        call contact_pair_force(pc%wa(1:pc%na), pc%wb(1:pc%nb), pc%qa_n(:, 1:pc%na), pc%qb_n(:, 1:pc%nb), &
            pc%qa_1(:, 1:pc%na), pc%qb_1(:, 1:pc%nb), params, f(1:3), f(4:6))
    end subroutine pair_forces

end module rs_test_contact_potential

program test_contact_potential
    use rs_test_contact_potential, only: run_all_tests
    use rs_test_assert, only: finish_tests
    implicit none
    call run_all_tests()
    call finish_tests()
end program test_contact_potential
