#include "rs_assert.h"
!> Unit tests of rs_contact_element (DESIGN.md §5, issue 10): the contact-point rule, the element
!> kernel against a brute-force double loop (also around the bounding-sphere skip), its tangent
!> against central differences, the exact energy identity of the midpoint forces (pairs entering
!> and leaving the support included), linear and angular momentum, exact zeros for pairs out of
!> reach, the closed-form line-contact law and its inverse, the law recovered from chains of
!> elements, and the ripple of the contact force of one rod sliding along another, which backs
!> the point-density rule of the module header.
!>
!> Each test prints the largest error or the quantities it measured.
module rs_test_contact_element
    use, intrinsic :: iso_fortran_env, only: output_unit
    use rs_core_kinds, only: rk
    use rs_test_random, only: set_random_seed, random_unit_vector, uniform, random_vector
    use rs_test_assert, only: run_test, assert_true, assert_close
    use rs_contact_potential, only: contact_params_t, contact_params_init, contact_psi, &
        contact_dpsi, contact_point_force
    use rs_contact_element, only: contact_element_pair, contact_points, contact_line_force, &
        contact_line_peak_force, contact_line_penetration, contact_element_swept_clear
    implicit none
    private

    public :: run_all_tests

    ! Parameter sets: a thick pair (r_c = 0.8) near the origin and a thin wire pair with a margin
    ! (r_c = 3.6e-3) placed 10 m from the origin (scale and absolute-position independence).
    integer, parameter :: n_sets = 2
    ! Central differences: step relative to r_c, tolerance relative to the largest tangent entry.
    real(rk), parameter :: fd_step = 1.0e-6_rk, fd_rtol = 1.0e-7_rk
    ! Energy identity, relative to the scale sum |w psi| + sum |r_i . dX_i| (module header).
    real(rk), parameter :: energy_rtol = 1.0e-13_rk
    ! Kernel against the quadruple-precision double loop: forces relative to k r_c L_a L_b,
    ! energies to k r_c^2 L_a L_b (a point pair at full penetration), distances to r_c.
    real(rk), parameter :: brute_rtol = 1.0e-14_rk
    ! Largest nodes per element in these tests.
    integer, parameter :: max_n = 3
    integer, parameter :: qp = selected_real_kind(30)

    !> A pair of elements with their contact points and nodal positions at t_n and t_{n+1}.
    type :: element_pair_t
        integer :: na = 0, ma = 0, nb = 0, mb = 0
        real(rk), allocatable :: shape_a(:, :), shape_b(:, :), wa(:), wb(:)
        real(rk), allocatable :: slope_a(:, :), slope_b(:, :)
        real(rk), allocatable :: xa_n(:, :), xa_1(:, :), xb_n(:, :), xb_1(:, :)
    end type element_pair_t

contains

    !> Run every test of this file through rs_test_assert.
    subroutine run_all_tests()
        call set_random_seed(20251207, 5813)
        call run_test('contact_points_rule', test_contact_points_rule)
        call run_test('matches_brute_force', test_matches_brute_force)
        call run_test('tangent_fd', test_tangent_fd)
        call run_test('energy_identity', test_energy_identity)
        call run_test('momentum_and_angular_momentum', test_momentum_and_angular_momentum)
        call run_test('zero_out_of_reach', test_zero_out_of_reach)
        call run_test('skip_safe_for_folded_element', test_skip_safe_for_folded_element)
        call run_test('line_law_closed_form', test_line_law_closed_form)
        call run_test('line_penetration_inverse', test_line_penetration_inverse)
        call run_test('line_law_from_elements', test_line_law_from_elements)
        call run_test('sliding_ripple', test_sliding_ripple)
        call run_test('friction_tangent_fd', test_friction_tangent_fd)
        call run_test('friction_balance', test_friction_balance)
        call run_test('friction_coulomb_line', test_friction_coulomb_line)
        call run_test('swept_crossing', test_swept_crossing)
        call run_test('swept_against_sampling', test_swept_against_sampling)
    end subroutine run_all_tests

    ! The barrier's swept test (issue 24 item 1) on two straight quadratic elements of length 1
    ! crossing at right angles, 8 points each (spacing at most 0.2, wall 0.2): a step that carries
    ! element a from 0.5 above b to 0.5 below it (both ends far outside the wall) is caught; the
    ! same step beside b (a shifted along b's normal plane by 2), or stopping 0.25 above it, is
    ! clear; a pair far apart is clear by its spheres.
    subroutine test_swept_crossing()
        real(rk) :: shape(3, 8), w(8), xa_n(3, 3), xa_1(3, 3), xb(3, 3), wall
        logical :: ok, clear
        integer :: i
        call contact_points(2, 8, shape, w, ok)
        wall = 0.2_rk
        do i = 1, 3
            xa_n(:, i) = [0.5_rk * real(i - 2, rk), 0.0_rk, 0.5_rk]
            xb(:, i) = [0.0_rk, 0.5_rk * real(i - 2, rk), 0.0_rk]
        end do
        xa_1 = xa_n
        xa_1(3, :) = -0.5_rk
        clear = contact_element_swept_clear(shape, xa_n, xa_1, shape, xb, xb, wall)
        CHECK_TRUE(.not. clear, 'a step through the other centreline is caught')
        clear = contact_element_swept_clear(shape, xa_1, xa_n, shape, xb, xb, wall)
        CHECK_TRUE(.not. clear, 'and back')
        xa_1(3, :) = 0.25_rk
        clear = contact_element_swept_clear(shape, xa_n, xa_1, shape, xb, xb, wall)
        CHECK_TRUE(clear, 'a step that stops above the wall is clear')
        xa_1(3, :) = 0.15_rk
        clear = contact_element_swept_clear(shape, xa_n, xa_1, shape, xb, xb, wall)
        CHECK_TRUE(.not. clear, 'a step that ends inside the wall is caught')
        xa_n(2, :) = 2.0_rk
        xa_1 = xa_n
        xa_1(3, :) = -0.5_rk
        clear = contact_element_swept_clear(shape, xa_n, xa_1, shape, xb, xb, wall)
        CHECK_TRUE(clear, 'the same step beside the other element is clear')
        xa_n(2, :) = 20.0_rk
        xa_1 = xa_n
        clear = contact_element_swept_clear(shape, xa_n, xa_1, shape, xb, xb, wall)
        CHECK_TRUE(clear, 'a far pair is clear')
    end subroutine test_swept_crossing

    ! The swept test against the smallest point distance sampled at 4001 instants of the step,
    ! on random pairs of a curved quadratic and a linear element and random steps (the exact
    ! minimum over the step lies within (step / 4000)^2 / 8 of the sampled one times the
    ! relative speed squared over the distance: cases within 1 % of the wall are not judged).
    subroutine test_swept_against_sampling()
        real(rk) :: shape_a(3, 6), shape_b(2, 5), wa(6), wb(5)
        real(rk) :: xa_n(3, 3), xa_1(3, 3), xb_n(3, 2), xb_1(3, 2), pa(3), pb(3), tau, smallest
        real(rk) :: wall
        logical :: ok, clear
        integer :: trial, k, g, h, judged, caught
        character(len=120) :: text
        call contact_points(2, 6, shape_a, wa, ok)
        CHECK_TRUE(ok, 'quadratic points')
        call contact_points(1, 5, shape_b, wb, ok)
        CHECK_TRUE(ok, 'linear points')
        wall = 0.1_rk
        judged = 0
        caught = 0
        do trial = 1, 400
            xa_n = reshape(random_vector(9, 1.0_rk), [3, 3])
            xb_n = reshape(random_vector(6, 1.0_rk), [3, 2])
            xa_1 = xa_n + reshape(random_vector(9, 0.5_rk), [3, 3])
            xb_1 = xb_n + reshape(random_vector(6, 0.5_rk), [3, 2])
            smallest = huge(1.0_rk)
            do k = 0, 4000
                tau = real(k, rk) / 4000.0_rk
                do g = 1, 6
                    pa = matmul((1.0_rk - tau) * xa_n + tau * xa_1, shape_a(:, g))
                    do h = 1, 5
                        pb = matmul((1.0_rk - tau) * xb_n + tau * xb_1, shape_b(:, h))
                        smallest = min(smallest, norm2(pa - pb))
                    end do
                end do
            end do
            if (abs(smallest - wall) < 0.01_rk * wall) cycle
            judged = judged + 1
            clear = contact_element_swept_clear(shape_a, xa_n, xa_1, shape_b, xb_n, xb_1, wall)
            CHECK_TRUE(clear .eqv. (smallest > wall), 'swept test = sampled smallest distance')
            if (.not. clear) caught = caught + 1
        end do
        write(text, '(a,i0,a,i0,a)') '    ', judged, ' random steps judged, ', caught, ' caught'
        write(output_unit, '(a)') trim(text)
        CHECK_TRUE(caught > 20 .and. judged - caught > 20, 'both verdicts met')
    end subroutine test_swept_against_sampling

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

    function scene_origin(i) result(origin)
        integer, intent(in) :: i
        real(rk) :: origin(3)
        origin = 0.0_rk
        if (i == 2) origin = [10.0_rk, -7.0_rk, 3.0_rk]
    end function scene_origin

    ! The rule of contact_points: weights sum to 1, t^k integrated exactly on [0, 1] for
    ! k <= 2m - 1 (tabulated m <= 5 and Newton-computed m > 5), shape values a partition of
    ! unity that reproduces x = t for straight elements; invalid arguments rejected.
    subroutine test_contact_points_rule()
        real(rk), allocatable :: shape(:, :), w(:)
        real(rk) :: t, integral, worst
        integer :: m, k, g, degree
        logical :: ok
        character(len=120) :: text
        worst = 0.0_rk
        do degree = 1, 2
            do m = 1, 40
                if (allocated(shape)) deallocate(shape, w)
                allocate(shape(degree + 1, m), w(m))
                call contact_points(degree, m, shape, w, ok)
                CHECK_TRUE(ok, 'valid rule accepted')
                CHECK_CLOSE(sum(w), 1.0_rk, 0.0_rk, 4.0e-15_rk, 'weights sum to 1')
                CHECK_TRUE(all(w > 0.0_rk), 'positive weights')
                do k = 0, 2 * m - 1
                    integral = 0.0_rk
                    do g = 1, m
                        ! t = x on [0, 1] from the nodal values 0, (1/2), 1 of the element.
                        t = shape(degree + 1, g)
                        if (degree == 2) t = t + 0.5_rk * shape(2, g)
                        integral = integral + w(g) * t**k
                    end do
                    CHECK_CLOSE(integral, 1.0_rk / real(k + 1, rk), 0.0_rk, 1.0e-13_rk, 't^k exact')
                    worst = max(worst, abs(integral * real(k + 1, rk) - 1.0_rk))
                end do
                do g = 1, m
                    CHECK_CLOSE(sum(shape(:, g)), 1.0_rk, 0.0_rk, 4.0e-15_rk, 'partition of unity')
                end do
            end do
        end do
        deallocate(shape, w)
        allocate(shape(4, 2), w(2))
        call contact_points(3, 2, shape, w, ok)
        CHECK_TRUE(.not. ok, 'degree 3 rejected')
        deallocate(shape, w)
        allocate(shape(2, 0), w(0))
        call contact_points(1, 0, shape, w, ok)
        CHECK_TRUE(.not. ok, 'm = 0 rejected')
        write(text, '(a,es9.2)') '    max relative error of int t^k, k <= 2m - 1, m <= 40: ', worst
        write(output_unit, '(a)') trim(text)
    end subroutine test_contact_points_rule

    ! A random pair of curved elements: a quadratic with m_a = 4 points, b quadratic (m_b = 3) or
    ! linear (m_b = 2), each of length about 1.5 r_c with nodes perturbed by 0.15 r_c, b's centre
    ! `offset` r_c from a's in a random direction, the step X_1 - X_n of size `step` r_c.
    function random_pair(params, origin, offset, step, linear_b) result(pc)
        type(contact_params_t), intent(in) :: params
        real(rk), intent(in) :: origin(3), offset, step
        logical, intent(in) :: linear_b
        type(element_pair_t) :: pc
        real(rk) :: rc, length, centre(3), axis(3)
        logical :: ok
        integer :: i
        rc = params%contact_distance
        pc%na = 3
        pc%ma = 4
        pc%nb = 3
        pc%mb = 3
        if (linear_b) then
            pc%nb = 2
            pc%mb = 2
        end if
        length = 1.5_rk * rc
        allocate(pc%shape_a(pc%na, pc%ma), pc%wa(pc%ma), pc%shape_b(pc%nb, pc%mb), pc%wb(pc%mb))
        allocate(pc%xa_n(3, pc%na), pc%xa_1(3, pc%na), pc%xb_n(3, pc%nb), pc%xb_1(3, pc%nb))
        allocate(pc%slope_a(pc%na, pc%ma), pc%slope_b(pc%nb, pc%mb))
        call contact_points(pc%na - 1, pc%ma, pc%shape_a, pc%wa, ok, pc%slope_a)
        call contact_points(pc%nb - 1, pc%mb, pc%shape_b, pc%wb, ok, pc%slope_b)
        pc%wa = length * pc%wa
        pc%wb = length * pc%wb
        axis = random_unit_vector()
        do i = 1, pc%na
            pc%xa_n(:, i) = origin + length * (real(i - 1, rk) / real(pc%na - 1, rk) - 0.5_rk) * axis &
                + random_vector(3, 0.15_rk * rc)
        end do
        centre = origin + offset * rc * random_unit_vector()
        axis = random_unit_vector()
        do i = 1, pc%nb
            pc%xb_n(:, i) = centre + length * (real(i - 1, rk) / real(pc%nb - 1, rk) - 0.5_rk) * axis &
                + random_vector(3, 0.15_rk * rc)
        end do
        do i = 1, pc%na
            pc%xa_1(:, i) = pc%xa_n(:, i) + random_vector(3, step * rc)
        end do
        do i = 1, pc%nb
            pc%xb_1(:, i) = pc%xb_n(:, i) + random_vector(3, step * rc)
        end do
    end function random_pair

    ! The kernel on a pair; r packs r_a then r_b (3 per node).
    subroutine evaluate(pc, params, r, e_n, e_1, tangent, closest, dissipation)
        type(element_pair_t), intent(in) :: pc
        type(contact_params_t), intent(in) :: params
        real(rk), intent(out) :: r(3 * (pc%na + pc%nb)), e_n, e_1
        real(rk), intent(out), optional :: tangent(3 * (pc%na + pc%nb), 3 * (pc%na + pc%nb)), closest
        real(rk), intent(out), optional :: dissipation
        real(rk) :: r_a(3, pc%na), r_b(3, pc%nb)
        call contact_element_pair(params, pc%shape_a, pc%wa, pc%xa_n, pc%xa_1, pc%shape_b, pc%wb, &
            pc%xb_n, pc%xb_1, r_a, r_b, e_n, e_1, tangent, closest, dissipation, pc%slope_a, &
            pc%slope_b)
        r(1:3 * pc%na) = reshape(r_a, [3 * pc%na])
        r(3 * pc%na + 1:) = reshape(r_b, [3 * pc%nb])
    end subroutine evaluate

    ! The double loop over all point pairs written directly from the module header, in
    ! quadruple precision from the same double inputs and without any skipping; psi_bar is the
    ! plain quotient [psi(d2_1) - psi(d2_n)] / (d2_1 - d2_n). The shape values are scaled to sum
    ! to 1 exactly (in double they miss by an ulp, which times a position 10 m from the origin
    ! would move a point by 1e-15 m). Also the closest point distance at t_{n+1} and the number
    ! of pairs inside the support at t_n and at t_{n+1}.
    subroutine brute_force(pc, params, r, e_n, e_1, closest, inside_n, inside_1)
        type(element_pair_t), intent(in) :: pc
        type(contact_params_t), intent(in) :: params
        real(rk), intent(out) :: r(3 * (pc%na + pc%nb)), e_n, e_1, closest
        integer, intent(out) :: inside_n, inside_1
        real(qp) :: pa_n(3), pa_1(3), pb_n(3), pb_1(3), f_a(3), w, d2_n, d2_1, s_n, s_1, c, psi_bar
        real(qp) :: rq(3 * (pc%na + pc%nb)), eq_n, eq_1, closest2, na(pc%na), nb(pc%nb)
        integer :: g, h, i, o
        rq = 0.0_qp
        eq_n = 0.0_qp
        eq_1 = 0.0_qp
        closest2 = huge(1.0_rk)
        inside_n = 0
        inside_1 = 0
        c = real(params%coefficient, qp)
        o = 3 * pc%na
        do g = 1, pc%ma
            na = real(pc%shape_a(:, g), qp)
            na = na / sum(na)
            pa_n = matmul(real(pc%xa_n, qp), na)
            pa_1 = matmul(real(pc%xa_1, qp), na)
            do h = 1, pc%mb
                nb = real(pc%shape_b(:, h), qp)
                nb = nb / sum(nb)
                pb_n = matmul(real(pc%xb_n, qp), nb)
                pb_1 = matmul(real(pc%xb_1, qp), nb)
                w = real(pc%wa(g), qp) * real(pc%wb(h), qp)
                d2_n = sum((pa_n - pb_n)**2)
                d2_1 = sum((pa_1 - pb_1)**2)
                closest2 = min(closest2, d2_1)
                s_n = max(real(params%support2, qp) - d2_n, 0.0_qp)
                s_1 = max(real(params%support2, qp) - d2_1, 0.0_qp)
                if (s_n > 0.0_qp) inside_n = inside_n + 1
                if (s_1 > 0.0_qp) inside_1 = inside_1 + 1
                eq_n = eq_n + w * c * s_n**3
                eq_1 = eq_1 + w * c * s_1**3
                if (d2_1 == d2_n) then
                    psi_bar = -3.0_qp * c * s_1**2
                else
                    psi_bar = c * (s_1**3 - s_n**3) / (d2_1 - d2_n)
                end if
                f_a = psi_bar * (pa_n - pb_n + pa_1 - pb_1)
                do i = 1, pc%na
                    rq(3 * i - 2:3 * i) = rq(3 * i - 2:3 * i) + w * na(i) * f_a
                end do
                do i = 1, pc%nb
                    rq(o + 3 * i - 2:o + 3 * i) = rq(o + 3 * i - 2:o + 3 * i) - w * nb(i) * f_a
                end do
            end do
        end do
        r = real(rq, rk)
        e_n = real(eq_n, rk)
        e_1 = real(eq_1, rk)
        closest = real(sqrt(closest2), rk)
    end subroutine brute_force

    ! The kernel equals the quadruple-precision double loop (forces, energies, closest distance)
    ! for element centres from 0 to 3.5 r_c apart, which crosses the bounding-sphere threshold:
    ! a wrong skip would return zeros where the reference is not zero. Also counts the pairs
    ! the bounding spheres skipped (their `closest` is the lower bound, below the true distance).
    subroutine test_matches_brute_force()
        type(contact_params_t) :: params
        type(element_pair_t) :: pc
        real(rk) :: r(3 * 2 * max_n), ref(3 * 2 * max_n), e_n, e_1, ref_n, ref_1, closest, ref_closest
        real(rk) :: rc, f_scale, e_scale, worst_r, worst_e, worst_d
        integer :: set, i, n, inside_n, inside_1, n_skipped, n_near_zero, n_active
        character(len=200) :: text
        worst_r = 0.0_rk
        worst_e = 0.0_rk
        worst_d = 0.0_rk
        n_skipped = 0
        n_near_zero = 0
        n_active = 0
        do set = 1, n_sets
            params = parameter_set(set)
            rc = params%contact_distance
            do i = 1, 3000
                pc = random_pair(params, scene_origin(set), uniform(0.0_rk, 3.5_rk), 0.1_rk, mod(i, 3) == 0)
                n = 3 * (pc%na + pc%nb)
                call evaluate(pc, params, r(1:n), e_n, e_1, closest=closest)
                call brute_force(pc, params, ref(1:n), ref_n, ref_1, ref_closest, inside_n, inside_1)
                f_scale = params%stiffness * rc * sum(pc%wa) * sum(pc%wb)
                e_scale = f_scale * rc
                if (inside_n + inside_1 > 0) then
                    n_active = n_active + 1
                    CHECK_CLOSE(r(1:n), ref(1:n), brute_rtol * f_scale, 0.0_rk, 'r = brute force')
                    CHECK_CLOSE(e_n, ref_n, brute_rtol * e_scale, 0.0_rk, 'E_n = brute force')
                    CHECK_CLOSE(e_1, ref_1, brute_rtol * e_scale, 0.0_rk, 'E_1 = brute force')
                    worst_r = max(worst_r, maxval(abs(r(1:n) - ref(1:n))) / f_scale)
                    worst_e = max(worst_e, max(abs(e_n - ref_n), abs(e_1 - ref_1)) / e_scale)
                else
                    CHECK_TRUE(all(r(1:n) == 0.0_rk), 'r = 0 with no pair inside')
                    CHECK_TRUE(e_n == 0.0_rk .and. e_1 == 0.0_rk, 'E = 0 with no pair inside')
                    if (ref_closest < 1.5_rk * rc) n_near_zero = n_near_zero + 1
                end if
                if (ref_closest < rc) then
                    CHECK_CLOSE(closest, ref_closest, brute_rtol * rc, 0.0_rk, 'closest exact below r_c')
                    worst_d = max(worst_d, abs(closest - ref_closest) / rc)
                else
                    CHECK_TRUE(closest >= rc * (1.0_rk - brute_rtol), 'closest: >= r_c')
                    CHECK_TRUE(closest <= ref_closest + brute_rtol * rc, 'closest: a lower bound')
                    if (closest < ref_closest - brute_rtol * rc) n_skipped = n_skipped + 1
                end if
            end do
        end do
        CHECK_TRUE(n_skipped > 500, 'the bounding-sphere skip was exercised')
        CHECK_TRUE(n_near_zero > 100, 'pairs just out of reach were exercised')
        CHECK_TRUE(n_active > 1000, 'pairs in contact were exercised')
        write(text, '(a,3es9.2)') '    max error of r / (k r_c L_a L_b), E / (k r_c^2 L_a L_b), closest / r_c: ', &
            worst_r, worst_e, worst_d
        write(output_unit, '(a)') trim(text)
        write(text, '(a,i0,a,i0,a,i0,a)') '    ', n_active, ' active pairs, ', n_near_zero, &
            ' within 1.5 r_c but inactive, ', n_skipped, ' skipped by the bounding spheres'
        write(output_unit, '(a)') trim(text)
    end subroutine test_matches_brute_force

    ! tangent = d r / d X_1 against central differences (quadratic-quadratic and
    ! quadratic-linear pairs, at least 3 point pairs inside the support).
    subroutine test_tangent_fd()
        real(rk) :: worst
        integer :: n_cases
        character(len=120) :: text
        call tangent_fd_sweep(.false., worst, n_cases)
        write(text, '(a,es9.2,a,i0,a)') '    max FD error of the tangent / max entry: ', worst, ' (', n_cases, ' pairs)'
        write(output_unit, '(a)') trim(text)
    end subroutine test_tangent_fd

    ! The tangent of 40 random touching pairs per parameter set against central differences of
    ! r (without or with friction: mu = 0.3 and slip lengths eta from 0.03 to 1 times the step,
    ! the regularization's smooth stick branch and its Coulomb branch).
    subroutine tangent_fd_sweep(friction, worst, n_cases)
        logical, intent(in) :: friction
        real(rk), intent(out) :: worst
        integer, intent(out) :: n_cases
        type(contact_params_t) :: params
        type(element_pair_t) :: pc, pp, pm
        real(rk), allocatable :: tangent(:, :)
        real(rk) :: r(3 * 2 * max_n), rp(3 * 2 * max_n), rm(3 * 2 * max_n)
        real(rk) :: fd(3 * 2 * max_n), e_n, e_1, ref_closest, rc, h, error, x0, width
        integer :: set, trial, k, node, comp, n, inside_n, inside_1
        worst = 0.0_rk
        n_cases = 0
        do set = 1, n_sets
            params = parameter_set(set)
            rc = params%contact_distance
            h = fd_step * rc
            if (friction) params%mu = 0.3_rk
            do trial = 1, 40
                if (friction) params%slip_length = 10.0_rk**uniform(-1.5_rk, 0.0_rk) * 0.1_rk * rc
                do
                    pc = random_pair(params, scene_origin(set), uniform(0.3_rk, 0.9_rk), 0.1_rk, mod(trial, 2) == 0)
                    call brute_force(pc, params, r, e_n, e_1, ref_closest, inside_n, inside_1)
                    if (inside_1 >= 3) exit
                end do
                n_cases = n_cases + 1
                n = 3 * (pc%na + pc%nb)
                if (allocated(tangent)) deallocate(tangent)
                allocate(tangent(n, n))
                call evaluate(pc, params, r(1:n), e_n, e_1, tangent=tangent)
                do k = 1, n
                    node = (k - 1) / 3 + 1
                    comp = k - 3 * (node - 1)
                    pp = pc
                    pm = pc
                    ! The steps actually taken (x + h - x differs from h far from the origin).
                    if (node <= pc%na) then
                        x0 = pc%xa_1(comp, node)
                        pp%xa_1(comp, node) = x0 + h
                        pm%xa_1(comp, node) = x0 - h
                        width = pp%xa_1(comp, node) - pm%xa_1(comp, node)
                    else
                        x0 = pc%xb_1(comp, node - pc%na)
                        pp%xb_1(comp, node - pc%na) = x0 + h
                        pm%xb_1(comp, node - pc%na) = x0 - h
                        width = pp%xb_1(comp, node - pc%na) - pm%xb_1(comp, node - pc%na)
                    end if
                    call evaluate(pp, params, rp(1:n), e_n, e_1)
                    call evaluate(pm, params, rm(1:n), e_n, e_1)
                    fd(1:n) = (rp(1:n) - rm(1:n)) / width
                    error = maxval(abs(fd(1:n) - tangent(:, k))) / maxval(abs(tangent))
                    CHECK_TRUE(error <= fd_rtol, 'tangent column = central difference of r')
                    worst = max(worst, error)
                end do
            end do
        end do
    end subroutine tangent_fd_sweep

    ! E_ab(t_{n+1}) - E_ab(t_n) = r . (X_1 - X_n) for random steps of 0.02 to 0.5 r_c, many of
    ! which move point pairs into or out of the support.
    subroutine test_energy_identity()
        type(contact_params_t) :: params
        type(element_pair_t) :: pc
        real(rk) :: r(3 * 2 * max_n), ref(3 * 2 * max_n), dx(3 * 2 * max_n), e_n, e_1, ref_n, ref_1
        real(rk) :: ref_closest, work, scale, error, worst
        integer :: set, trial, n, inside_n, inside_1, n_crossing
        character(len=120) :: text
        worst = 0.0_rk
        n_crossing = 0
        do set = 1, n_sets
            params = parameter_set(set)
            do trial = 1, 1000
                pc = random_pair(params, scene_origin(set), uniform(0.2_rk, 1.5_rk), &
                    uniform(0.02_rk, 0.5_rk), mod(trial, 4) == 0)
                call brute_force(pc, params, ref, ref_n, ref_1, ref_closest, inside_n, inside_1)
                if (inside_n + inside_1 == 0) cycle
                if (inside_n /= inside_1) n_crossing = n_crossing + 1
                n = 3 * (pc%na + pc%nb)
                call evaluate(pc, params, r(1:n), e_n, e_1)
                dx(1:3 * pc%na) = reshape(pc%xa_1(:, 1:pc%na) - pc%xa_n(:, 1:pc%na), [3 * pc%na])
                dx(3 * pc%na + 1:n) = reshape(pc%xb_1(:, 1:pc%nb) - pc%xb_n(:, 1:pc%nb), [3 * pc%nb])
                work = dot_product(r(1:n), dx(1:n))
                scale = sum(abs(r(1:n) * dx(1:n))) + abs(e_n) + abs(e_1)
                error = abs(e_1 - e_n - work) / scale
                CHECK_TRUE(error <= energy_rtol, 'E_1 - E_n = r . (X_1 - X_n)')
                worst = max(worst, error)
            end do
        end do
        CHECK_TRUE(n_crossing > 100, 'steps with pairs entering or leaving the support')
        write(text, '(a,es9.2,a,i0,a)') '    max |E_1 - E_n - r . dX| / scale: ', worst, ' (', n_crossing, &
            ' steps with pairs entering or leaving)'
        write(output_unit, '(a)') trim(text)
    end subroutine test_energy_identity

    ! sum r = 0 and sum_i X_i,mid x r_i = 0 (the moment about any origin, since sum r = 0);
    ! the moment with the positions at t_{n+1} instead of the midpoint does not vanish, which
    ! shows that the midpoint is what keeps angular momentum.
    subroutine test_momentum_and_angular_momentum()
        type(contact_params_t) :: params
        type(element_pair_t) :: pc
        real(rk) :: r(3 * 2 * max_n), e_n, e_1, force(3), moment(3), moment_1(3), x_mid(3), x_1(3)
        real(rk) :: f_scale, m_scale, worst_force, worst_moment, smallest_end_moment
        integer :: set, trial, i, k
        character(len=160) :: text
        worst_force = 0.0_rk
        worst_moment = 0.0_rk
        smallest_end_moment = huge(1.0_rk)
        do set = 1, n_sets
            params = parameter_set(set)
            do trial = 1, 300
                pc = random_pair(params, scene_origin(set), uniform(0.2_rk, 1.0_rk), 0.3_rk, mod(trial, 2) == 0)
                call evaluate(pc, params, r(1:3 * (pc%na + pc%nb)), e_n, e_1)
                if (all(r(1:3 * (pc%na + pc%nb)) == 0.0_rk)) cycle
                force = 0.0_rk
                moment = 0.0_rk
                moment_1 = 0.0_rk
                f_scale = 0.0_rk
                m_scale = 0.0_rk
                do i = 1, pc%na + pc%nb
                    k = 3 * (i - 1)
                    if (i <= pc%na) then
                        x_mid = 0.5_rk * (pc%xa_n(:, i) + pc%xa_1(:, i))
                        x_1 = pc%xa_1(:, i)
                    else
                        x_mid = 0.5_rk * (pc%xb_n(:, i - pc%na) + pc%xb_1(:, i - pc%na))
                        x_1 = pc%xb_1(:, i - pc%na)
                    end if
                    force = force + r(k + 1:k + 3)
                    moment = moment + cross(x_mid, r(k + 1:k + 3))
                    moment_1 = moment_1 + cross(x_1, r(k + 1:k + 3))
                    f_scale = f_scale + norm2(r(k + 1:k + 3))
                    m_scale = m_scale + norm2(x_mid) * norm2(r(k + 1:k + 3))
                end do
                CHECK_TRUE(norm2(force) <= 1.0e-14_rk * f_scale, 'sum of nodal forces = 0')
                CHECK_TRUE(norm2(moment) <= 1.0e-14_rk * m_scale, 'sum X_mid x r = 0')
                worst_force = max(worst_force, norm2(force) / f_scale)
                worst_moment = max(worst_moment, norm2(moment) / m_scale)
                smallest_end_moment = min(smallest_end_moment, norm2(moment_1) / m_scale)
            end do
        end do
        CHECK_TRUE(smallest_end_moment > 1.0e-10_rk, 'sum X_1 x r /= 0 (the midpoint matters)')
        write(text, '(a,es9.2,a,es9.2,a,es9.2)') '    max |sum r| / scale ', worst_force, ', |sum X_mid x r| / scale ', &
            worst_moment, '; min |sum X_1 x r| / scale ', smallest_end_moment
        write(output_unit, '(a)') trim(text)
    end subroutine test_momentum_and_angular_momentum

    ! Far pairs (skipped by the bounding spheres) and pairs within reach of the spheres but
    ! with every point pair outside at both times give exact zeros, also in the tangent.
    subroutine test_zero_out_of_reach()
        type(contact_params_t) :: params
        type(element_pair_t) :: pc
        real(rk), allocatable :: tangent(:, :)
        real(rk) :: r(3 * 2 * max_n), e_n, e_1, closest, rc
        integer :: set, trial, n, i
        do set = 1, n_sets
            params = parameter_set(set)
            rc = params%contact_distance
            do trial = 1, 50
                pc = random_pair(params, scene_origin(set), 6.0_rk, 0.2_rk, mod(trial, 2) == 0)
                n = 3 * (pc%na + pc%nb)
                if (allocated(tangent)) deallocate(tangent)
                allocate(tangent(n, n), source=1.0_rk)
                call evaluate(pc, params, r(1:n), e_n, e_1, tangent, closest)
                CHECK_TRUE(all(r(1:n) == 0.0_rk) .and. e_n == 0.0_rk .and. e_1 == 0.0_rk, 'far pair: zeros')
                CHECK_TRUE(all(tangent == 0.0_rk), 'far pair: zero tangent')
                CHECK_TRUE(closest >= rc, 'far pair: closest >= r_c')
            end do
            ! Two parallel straight quadratic elements with the same 4 points, 1.001 r_c apart, then
            ! moved to 1.2 r_c: their spheres overlap, every point pair is outside.
            pc = random_pair(params, scene_origin(set), 1.0_rk, 0.0_rk, .false.)
            pc%mb = pc%ma
            pc%shape_b = pc%shape_a
            pc%wb = pc%wa
            do i = 1, 3
                pc%xa_n(:, i) = scene_origin(set) + [0.75_rk * rc * real(i - 2, rk), 0.0_rk, 0.0_rk]
                pc%xb_n(:, i) = pc%xa_n(:, i) + [0.3_rk * rc, 1.001_rk * rc, 0.0_rk]
                pc%xa_1(:, i) = pc%xa_n(:, i)
                pc%xb_1(:, i) = pc%xa_n(:, i) + [0.0_rk, 1.2_rk * rc, 0.0_rk]
            end do
            n = 3 * (pc%na + pc%nb)
            if (allocated(tangent)) deallocate(tangent)
            allocate(tangent(n, n), source=1.0_rk)
            call evaluate(pc, params, r(1:n), e_n, e_1, tangent, closest)
            CHECK_TRUE(all(r(1:n) == 0.0_rk) .and. e_n == 0.0_rk .and. e_1 == 0.0_rk, 'out of the support: zeros')
            CHECK_TRUE(all(tangent == 0.0_rk), 'out of the support: zero tangent')
            CHECK_CLOSE(closest, 1.2_rk * rc, 0.0_rk, 1.0e-13_rk, 'closest = the distance of the lines')
            ! The same at t_n 0.999 r_c apart: one end of the step inside, forces act.
            do i = 1, 3
                pc%xb_n(:, i) = pc%xa_n(:, i) + [0.0_rk, 0.999_rk * rc, 0.0_rk]
            end do
            call evaluate(pc, params, r(1:n), e_n, e_1, tangent, closest)
            CHECK_TRUE(e_n > 0.0_rk .and. e_1 == 0.0_rk .and. any(r(1:n) /= 0.0_rk), 'inside at t_n: force')
        end do
    end subroutine test_zero_out_of_reach

    ! The bounding sphere must cover points outside the sphere through the nodes: a folded
    ! quadratic element (nodes c, c + 10 r_c e, c - 10 r_c e) with 8 points reaches 1.041 x 10 r_c
    ! from its centre c at point 4. A short linear element 0.9 r_c beyond that point is in
    ! contact, although the spheres of radius max_i |X_i - c| are 1.3 r_c apart.
    subroutine test_skip_safe_for_folded_element()
        type(contact_params_t) :: params
        type(element_pair_t) :: pc
        real(rk) :: r(3 * 5), ref(3 * 5), e_n, e_1, ref_n, ref_1, closest, ref_closest, rc, e(3), f(3)
        real(rk) :: reach, f_scale
        integer :: set, inside_n, inside_1
        logical :: ok
        do set = 1, n_sets
            params = parameter_set(set)
            rc = params%contact_distance
            pc = random_pair(params, scene_origin(set), 1.0_rk, 0.0_rk, .true.)
            deallocate(pc%shape_a, pc%wa)
            pc%ma = 8
            allocate(pc%shape_a(3, 8), pc%wa(8))
            call contact_points(2, 8, pc%shape_a, pc%wa, ok)
            pc%wa = 20.0_rk * rc * pc%wa
            e = [0.7232_rk, 0.6906_rk, 0.0_rk]
            e = e / norm2(e)
            f = [-e(2), e(1), 0.0_rk]
            pc%xa_n(:, 1) = scene_origin(set)
            pc%xa_n(:, 2) = scene_origin(set) + 10.0_rk * rc * e
            pc%xa_n(:, 3) = scene_origin(set) - 10.0_rk * rc * e
            reach = dot_product(matmul(pc%xa_n, pc%shape_a(:, 4)) - scene_origin(set), e)
            CHECK_TRUE(reach > 10.4_rk * rc, 'point 4 of the folded element lies outside the node sphere')
            pc%xb_n(:, 1) = scene_origin(set) + (reach + 0.9_rk * rc) * e - 0.005_rk * rc * f
            pc%xb_n(:, 2) = scene_origin(set) + (reach + 0.9_rk * rc) * e + 0.005_rk * rc * f
            pc%xa_1 = pc%xa_n
            pc%xb_1 = pc%xb_n
            call evaluate(pc, params, r, e_n, e_1, closest=closest)
            call brute_force(pc, params, ref, ref_n, ref_1, ref_closest, inside_n, inside_1)
            f_scale = params%stiffness * rc * sum(pc%wa) * sum(pc%wb)
            CHECK_TRUE(inside_1 > 0 .and. any(r /= 0.0_rk), 'folded element in contact')
            CHECK_CLOSE(r, ref, brute_rtol * f_scale, 0.0_rk, 'folded element: r = brute force')
            CHECK_CLOSE(closest, ref_closest, brute_rtol * rc, 0.0_rk, 'folded element: closest')
            CHECK_CLOSE(closest, 0.9_rk * rc, 1.0e-4_rk * rc, 0.0_rk, 'folded element: 0.9 r_c')
        end do
    end subroutine test_skip_safe_for_folded_element

    ! contact_line_force against the line integral of the point law evaluated independently:
    ! on |u| < a the integrand -2 d psi'(d^2 + u^2) is a polynomial of degree 4 in u, so the
    ! 3-point Gauss rule on [-a, a] gives its integral exactly; and -dPhi/dd of the energy
    ! Phi(d) = integral psi (degree 6, 4-point rule) by central differences.
    subroutine test_line_law_closed_form()
        type(contact_params_t) :: params
        real(rk) :: rc, d, exact, from_dpsi, from_energy, worst, worst_fd, hd
        integer :: set, i
        character(len=120) :: text
        worst = 0.0_rk
        worst_fd = 0.0_rk
        do set = 1, n_sets
            params = parameter_set(set)
            rc = params%contact_distance
            do i = 1, 99
                d = rc * real(i, rk) / 100.0_rk
                exact = contact_line_force(params, d)
                from_dpsi = line_integral_force(params, d)
                CHECK_CLOSE(exact, from_dpsi, 0.0_rk, 1.0e-13_rk, 'f(d) = integral of -2 d psi_prime')
                worst = max(worst, abs(exact - from_dpsi) / from_dpsi)
                hd = 1.0e-5_rk * rc
                if (d - hd > 0.0_rk .and. d + hd < rc) then
                    from_energy = -(line_energy(params, d + hd) - line_energy(params, d - hd)) / (2.0_rk * hd)
                    CHECK_CLOSE(exact, from_energy, 1.0e-8_rk * params%stiffness * rc**2, 1.0e-7_rk, 'f = -dPhi/dd')
                    worst_fd = max(worst_fd, abs(exact - from_energy) / (params%stiffness * rc**2))
                end if
            end do
            CHECK_CLOSE(contact_line_force(params, rc), 0.0_rk, 0.0_rk, 0.0_rk, 'f(r_c) = 0')
            CHECK_CLOSE(contact_line_force(params, 2.0_rk * rc), 0.0_rk, 0.0_rk, 0.0_rk, 'f = 0 beyond r_c')
            CHECK_CLOSE(contact_line_force(params, 0.0_rk), 0.0_rk, 0.0_rk, 0.0_rk, 'f(0) = 0')
        end do
        write(text, '(a,es9.2,a,es9.2)') '    max rel. error against the exact line integral: ', worst, &
            '; against -dPhi/dd (FD) / (k r_c^2): ', worst_fd
        write(output_unit, '(a)') trim(text)
    end subroutine test_line_law_closed_form

    function line_integral_force(params, d) result(f)
        type(contact_params_t), intent(in) :: params
        real(rk), intent(in) :: d
        real(rk) :: f, a, u(3), w(3)
        integer :: j
        a = sqrt(params%support2 - d**2)
        u = a * [-sqrt(0.6_rk), 0.0_rk, sqrt(0.6_rk)]
        w = a * [5.0_rk, 8.0_rk, 5.0_rk] / 9.0_rk
        f = 0.0_rk
        do j = 1, 3
            f = f - 2.0_rk * d * w(j) * contact_dpsi(d**2 + u(j)**2, params)
        end do
    end function line_integral_force

    function line_energy(params, d) result(phi)
        type(contact_params_t), intent(in) :: params
        real(rk), intent(in) :: d
        real(rk) :: phi, a, x1, x2, w1, w2, u(4), w(4)
        a = sqrt(params%support2 - d**2)
        x1 = sqrt(3.0_rk / 7.0_rk - 2.0_rk / 7.0_rk * sqrt(1.2_rk))
        x2 = sqrt(3.0_rk / 7.0_rk + 2.0_rk / 7.0_rk * sqrt(1.2_rk))
        w1 = (18.0_rk + sqrt(30.0_rk)) / 36.0_rk
        w2 = (18.0_rk - sqrt(30.0_rk)) / 36.0_rk
        u = a * [-x2, -x1, x1, x2]
        w = a * [w2, w1, w1, w2]
        phi = sum(w * contact_psi(d**2 + u**2, params))
    end function line_energy

    ! contact_line_penetration inverts contact_line_force on the stable branch for penetrations
    ! from 1e-8 r_c to just below the peak; the peak value and position; the small-penetration
    ! asymptote f ~ (128 sqrt(2) / 15) k delta^(5/2) / sqrt(r_c) (1 - 9 delta / (4 r_c)); loads
    ! <= 0 and above the peak.
    subroutine test_line_penetration_inverse()
        type(contact_params_t) :: params
        real(rk) :: rc, k, d, delta, load, got, peak, asymptote, worst, worst_asym, delta_peak, expected
        integer :: set, i
        character(len=120) :: text
        worst = 0.0_rk
        worst_asym = 0.0_rk
        do set = 1, n_sets
            params = parameter_set(set)
            rc = params%contact_distance
            k = params%stiffness
            delta_peak = rc * (1.0_rk - 1.0_rk / sqrt(6.0_rk))
            do i = 0, 80
                ! The penetration that d = r_c - delta represents (r_c - d is exact).
                d = rc - rc * 10.0_rk**(-8.0_rk + 0.1_rk * real(i, rk))
                delta = rc - d
                if (delta > 0.98_rk * delta_peak) exit
                load = contact_line_force(params, d)
                got = contact_line_penetration(params, load)
                CHECK_CLOSE(got, delta, 0.0_rk, 1.0e-12_rk, 'penetration inverts the line law')
                worst = max(worst, abs(got - delta) / delta)
                if (delta <= 1.0e-3_rk * rc .and. delta >= 1.0e-6_rk * rc) then
                    ! f / asymptote = 1 - (9/4) delta/r_c + 1.72 (delta/r_c)^2 + ...
                    asymptote = 128.0_rk * sqrt(2.0_rk) / 15.0_rk * k * delta**2.5_rk / sqrt(rc)
                    CHECK_CLOSE(load / asymptote - 1.0_rk, -2.25_rk * delta / rc, 0.0_rk, 1.0e-3_rk, 'asymptote')
                    worst_asym = max(worst_asym, abs((load / asymptote - 1.0_rk) / (-2.25_rk * delta / rc) - 1.0_rk))
                end if
            end do
            peak = contact_line_peak_force(params)
            expected = 32.0_rk / 15.0_rk / sqrt(6.0_rk) * (5.0_rk / 6.0_rk)**2.5_rk * k * rc**2
            CHECK_CLOSE(peak, expected, 0.0_rk, 1.0e-14_rk, 'peak f_max = (32/15) 6^(-1/2) (5/6)^(5/2) k r_c^2')
            CHECK_CLOSE(peak / (k * rc**2), 0.5521_rk, 1.0e-4_rk, 0.0_rk, 'stated value of the peak')
            CHECK_TRUE(contact_line_force(params, rc / sqrt(6.0_rk) * 1.001_rk) < peak, 'peak is a maximum')
            CHECK_TRUE(contact_line_force(params, rc / sqrt(6.0_rk) * 0.999_rk) < peak, 'peak is a maximum')
            CHECK_CLOSE(contact_line_penetration(params, 0.0_rk), 0.0_rk, 0.0_rk, 0.0_rk, 'no load: 0')
            CHECK_CLOSE(contact_line_penetration(params, -1.0_rk), 0.0_rk, 0.0_rk, 0.0_rk, 'negative load: 0')
            CHECK_CLOSE(contact_line_penetration(params, 1.01_rk * peak), rc, 0.0_rk, 0.0_rk, 'above the peak: r_c')
            got = contact_line_penetration(params, 0.999999_rk * peak)
            CHECK_TRUE(got < delta_peak .and. got > 0.99_rk * delta_peak, 'just below the peak: stable branch')
        end do
        write(text, '(a,es9.2,a,es9.2)') '    max rel. error of the inverse: ', worst, &
            '; asymptote: rel. deviation of the 9/4 delta/r_c correction ', worst_asym
        write(output_unit, '(a)') trim(text)
    end subroutine test_line_penetration_inverse

    ! Total contact force of a straight rod A (a chain of elements of length `length`, degree
    ! `degree`, m points each) lying at distance d above a straight rod B of the same
    ! discretization that extends `overhang` beyond A at both ends, A shifted along B by
    ! `offset`. Returns the force on A (minus the gradient r_a summed over A's nodes): normal
    ! (away from B) and tangential components.
    subroutine chain_force(params, degree, m, length, n_el_a, overhang, d, offset, normal, tangential)
        type(contact_params_t), intent(in) :: params
        integer, intent(in) :: degree, m, n_el_a
        real(rk), intent(in) :: length, overhang, d, offset
        real(rk), intent(out) :: normal, tangential
        real(rk) :: shape(degree + 1, m), w(m), xa(3, degree + 1), xb(3, degree + 1)
        real(rk) :: r_a(3, degree + 1), r_b(3, degree + 1), e_n, e_1
        integer :: ea, eb, eb_first, eb_last, i
        logical :: ok
        call contact_points(degree, m, shape, w, ok)
        w = length * w
        eb_first = floor((offset - overhang) / length) - 1
        eb_last = ceiling((offset + n_el_a * length + overhang) / length) + 1
        normal = 0.0_rk
        tangential = 0.0_rk
        do ea = 0, n_el_a - 1
            do i = 1, degree + 1
                xa(:, i) = [offset + length * (real(ea, rk) + real(i - 1, rk) / real(degree, rk)), d, 0.0_rk]
            end do
            do eb = eb_first, eb_last
                do i = 1, degree + 1
                    xb(:, i) = [length * (real(eb, rk) + real(i - 1, rk) / real(degree, rk)), 0.0_rk, 0.0_rk]
                end do
                call contact_element_pair(params, shape, w, xa, xa, shape, w, xb, xb, r_a, r_b, e_n, e_1)
                normal = normal - sum(r_a(2, :))
                tangential = tangential - sum(r_a(1, :))
            end do
        end do
    end subroutine chain_force

    ! The line law from elements: rod A of 6 straight quadratic elements with 4 points each at
    ! spacing L/m = a/8 (a = sqrt(r_c^2 - d^2), the half-length of the contact patch), rod B
    ! overhanging by 1.5 r_c, both at rest. At every offset the force per length of A matches
    ! contact_line_force within the quadrature ripple (< 1e-3, next test); averaged over 32
    ! offsets per point spacing, where the exact average over all offsets equals the line law
    ! for any quadrature, it matches to the sampling error (< 1e-7).
    subroutine test_line_law_from_elements()
        type(contact_params_t) :: params
        real(rk) :: rc, deltas(3), d, a, length, law, normal, tangential, mean, err, worst, worst_mean
        integer :: set, id, k, n_offsets
        integer, parameter :: m = 4, n_el_a = 6
        character(len=120) :: text
        worst = 0.0_rk
        worst_mean = 0.0_rk
        deltas = [0.005_rk, 0.05_rk, 0.3_rk]
        do set = 1, n_sets
            params = parameter_set(set)
            rc = params%contact_distance
            do id = 1, 3
                d = rc - deltas(id) * rc
                a = sqrt(params%support2 - d**2)
                length = real(m, rk) * a / 8.0_rk
                law = contact_line_force(params, d)
                n_offsets = 32 * m
                mean = 0.0_rk
                do k = 0, n_offsets - 1
                    call chain_force(params, 2, m, length, n_el_a, 1.5_rk * rc, d, &
                        length * real(k, rk) / real(n_offsets, rk), normal, tangential)
                    err = normal / (n_el_a * length) / law - 1.0_rk
                    CHECK_TRUE(abs(err) <= 1.0e-3_rk, 'force per length = line law within the ripple')
                    worst = max(worst, abs(err))
                    mean = mean + normal
                end do
                mean = mean / n_offsets / (n_el_a * length) / law - 1.0_rk
                CHECK_TRUE(abs(mean) <= 1.0e-7_rk, 'mean over offsets = line law')
                worst_mean = max(worst_mean, abs(mean))
            end do
        end do
        write(text, '(a,es9.2,a,es9.2)') '    spacing a/8: max rel. deviation from the line law ', worst, &
            ', of the mean over offsets ', worst_mean
        write(output_unit, '(a)') trim(text)
    end subroutine test_line_law_from_elements

    ! Rod A (one straight linear element of length L, m points) slides along rod B (a chain of
    ! the same elements) at distance d = r_c - delta over one element length, 24 samples per
    ! point spacing. Ripple = (max - min) / mean of the normal force; the spurious tangential
    ! force max |F_t| / mean F_n is reported in units of a / d. The normal ripple depends only
    ! on m and h / a (h = L / m, a = sqrt(r_c^2 - d^2)): psi' is (a^2 - u^2)^2 up to a factor,
    ! checked across two penetrations. Asserted rule (module header): h <= a/2: ripple < 5%;
    ! h <= a/4: < 1%; h <= a/8: < 0.1%; and h = a gives > 10%, so the rule is needed.
    subroutine test_sliding_ripple()
        type(contact_params_t) :: params
        real(rk), parameter :: ratios(4) = [1.0_rk, 0.5_rk, 0.25_rk, 0.125_rk]
        real(rk), parameter :: limits(4) = [huge(1.0_rk), 0.05_rk, 0.01_rk, 0.001_rk]
        integer, parameter :: ms(6) = [1, 2, 3, 4, 6, 8]
        real(rk) :: rc, d, a, ripple, tangential, ripple2, tangential2, worst(4), least(4), worst_t(4)
        integer :: im, ir
        character(len=160) :: text
        logical :: ok
        call contact_params_init(params, 0.5_rk, 0.5_rk, 1.0_rk, ok)
        rc = params%contact_distance
        worst = 0.0_rk
        least = huge(1.0_rk)
        worst_t = 0.0_rk
        write(output_unit, '(a)') '    ripple (max - min) / mean of the normal force; tangential max / mean / (a/d)'
        do im = 1, size(ms)
            text = ''
            write(text, '(a,i2,a)') '    m =', ms(im), ':'
            do ir = 1, size(ratios)
                d = rc - 0.02_rk * rc
                a = sqrt(params%support2 - d**2)
                call sliding_ripple(params, ms(im), ratios(ir) * a * ms(im), d, ripple, tangential)
                tangential = tangential / (a / d)
                d = rc - 0.2_rk * rc
                a = sqrt(params%support2 - d**2)
                call sliding_ripple(params, ms(im), ratios(ir) * a * ms(im), d, ripple2, tangential2)
                CHECK_CLOSE(ripple2, ripple, 1.0e-12_rk, 1.0e-9_rk, 'ripple depends on m and h/a only')
                CHECK_TRUE(ripple < limits(ir), 'ripple within the rule of the module header')
                worst(ir) = max(worst(ir), ripple)
                least(ir) = min(least(ir), ripple)
                worst_t(ir) = max(worst_t(ir), tangential, tangential2 / (a / d))
                write(text, '(a,a,f5.3,a,es8.2,a,es8.2)') trim(text), '  h/a ', ratios(ir), ': ', ripple, ' / ', tangential
            end do
            write(output_unit, '(a)') trim(text)
        end do
        CHECK_TRUE(least(1) > 0.1_rk, 'h = a: ripple > 10% for every m')
        CHECK_TRUE(worst_t(2) < 0.05_rk, 'h <= a/2: tangential force < 0.05 (a/d) F_n')
        write(text, '(a,4es9.2)') '    worst ripple for h/a = 1, 1/2, 1/4, 1/8: ', worst
        write(output_unit, '(a)') trim(text)
        write(text, '(a,4es9.2)') '    worst tangential / (a/d):                ', worst_t
        write(output_unit, '(a)') trim(text)
    end subroutine test_sliding_ripple

    ! Friction (rs_contact_potential, Friction): the tangent with friction against central
    ! differences (tangent_fd_sweep).
    subroutine test_friction_tangent_fd()
        real(rk) :: worst
        integer :: n_cases
        character(len=120) :: text
        call tangent_fd_sweep(.true., worst, n_cases)
        write(text, '(a,es9.2,a,i0,a)') '    max FD error of the tangent with friction / max entry: ', &
            worst, ' (', n_cases, ' pairs)'
        write(output_unit, '(a)') trim(text)
    end subroutine test_friction_tangent_fd

    ! The step's balance with friction, computed here from the forces: the work r . (X_1 - X_n)
    ! of the nodal terms with friction equals E_1 - E_n + D with the kernel's dissipation D, and
    ! D > 0 where the points slip in contact (random steps of 0.02 to 0.5 r_c); the friction
    ! terms sum to zero (linear momentum). Their moment about the midpoints does not vanish
    ! (the centreline law's couple, module header of rs_contact_potential): shown, not zero.
    subroutine test_friction_balance()
        type(contact_params_t) :: params
        type(element_pair_t) :: pc
        real(rk) :: r(3 * 2 * max_n), dx(3 * 2 * max_n), e_n, e_1, dissipation, work, scale
        real(rk) :: error, worst, force(3), f_scale, worst_force, smallest
        integer :: set, trial, n, i, n_slipping
        character(len=160) :: text
        worst = 0.0_rk
        worst_force = 0.0_rk
        smallest = huge(1.0_rk)
        n_slipping = 0
        do set = 1, n_sets
            params = parameter_set(set)
            params%mu = 0.4_rk
            params%slip_length = 0.01_rk * params%contact_distance
            do trial = 1, 1000
                pc = random_pair(params, scene_origin(set), uniform(0.2_rk, 1.5_rk), &
                    uniform(0.02_rk, 0.5_rk), mod(trial, 4) == 0)
                n = 3 * (pc%na + pc%nb)
                call evaluate(pc, params, r(1:n), e_n, e_1, dissipation=dissipation)
                if (all(r(1:n) == 0.0_rk)) cycle
                dx(1:3 * pc%na) = reshape(pc%xa_1 - pc%xa_n, [3 * pc%na])
                dx(3 * pc%na + 1:n) = reshape(pc%xb_1 - pc%xb_n, [3 * pc%nb])
                work = dot_product(r(1:n), dx(1:n))
                scale = sum(abs(r(1:n) * dx(1:n))) + abs(e_n) + abs(e_1)
                error = abs(work - (e_1 - e_n) - dissipation) / scale
                CHECK_TRUE(error <= energy_rtol, 'r . dX = E_1 - E_n + D')
                worst = max(worst, error)
                if (dissipation > 1.0e-3_rk * scale) then
                    n_slipping = n_slipping + 1
                    smallest = min(smallest, dissipation / scale)
                end if
                force = 0.0_rk
                f_scale = 0.0_rk
                do i = 1, pc%na + pc%nb
                    force = force + r(3 * i - 2:3 * i)
                    f_scale = f_scale + norm2(r(3 * i - 2:3 * i))
                end do
                CHECK_TRUE(norm2(force) <= 1.0e-14_rk * f_scale, 'sum of nodal terms = 0')
                worst_force = max(worst_force, norm2(force) / f_scale)
            end do
        end do
        CHECK_TRUE(n_slipping > 200, 'steps that slip in contact and dissipate')
        write(text, '(a,es9.2,a,es9.2,a,i0,a)') '    max |r . dX - dE - D| / scale: ', worst, &
            ', |sum r| / scale: ', worst_force, ' (', n_slipping, ' slipping steps)'
        write(output_unit, '(a)') trim(text)
    end subroutine test_friction_balance

    ! Coulomb's law, closed form: element a slides along element b, parallel to it (a line
    ! contact) or crossing it at right angles (a point contact), centrelines d = 0.9 r_c apart,
    ! step s along b's axis. The contact normal n (rs_contact_potential, Friction) is the radial
    ! direction or the common normal, the slip of every point pair the whole step, so the
    ! friction on a is exactly mu times the sum of the pairs' f_a . n, its normal force, up to
    ! the regularization factor |u| / sqrt(|u|^2 + eta^2) = 1 - 5e-13 (eta = 1e-6 s), whatever
    ! the quadrature. And a normal step (a pressed towards b) slips nowhere: no friction, no
    ! dissipation (the point pairs' own directions, oblique along a line contact, would slip).
    subroutine test_friction_coulomb_line()
        type(contact_params_t) :: params, rough
        type(element_pair_t) :: pc
        real(rk) :: r_normal(18), r_both(18), e_n, e_1, rc, s, slide(3), ratio, worst, d_t
        real(rk) :: largest_normal, largest_dissipation
        integer :: degree, i, layout
        logical :: ok
        character(len=200) :: text
        call contact_params_init(params, 0.5_rk, 0.5_rk, 1.0e3_rk, ok)
        rc = params%contact_distance
        s = 0.01_rk * rc
        rough = params
        rough%mu = 0.25_rk
        rough%slip_length = 1.0e-6_rk * s
        worst = 0.0_rk
        largest_normal = 0.0_rk
        largest_dissipation = 0.0_rk
        do layout = 1, 2
            do degree = 1, 2
                pc = straight_pair(degree, rc, layout == 2)
                ! b lies along x (parallel) or y (crossing); a moves by s along b's axis,
                ! placed so that the midpoint configuration is symmetric.
                slide = merge([s, 0.0_rk, 0.0_rk], [0.0_rk, s, 0.0_rk], layout == 1)
                do i = 1, pc%na
                    pc%xa_n(:, i) = pc%xa_n(:, i) - 0.5_rk * slide
                    pc%xa_1(:, i) = pc%xa_n(:, i) + slide
                end do
                call evaluate(pc, params, r_normal(1:6 * pc%na), e_n, e_1)
                call evaluate(pc, rough, r_both(1:6 * pc%na), e_n, e_1)
                ratio = dot_product(friction_on_a(pc, r_both - r_normal), slide / s) / &
                    abs(sum(r_normal(3:3 * pc%na:3)))
                CHECK_CLOSE(ratio, rough%mu, 0.0_rk, 1.0e-11_rk, 'friction = mu times the normal force')
                worst = max(worst, abs(ratio / rough%mu - 1.0_rk))
                ! Pressed: a moves by s towards b.
                pc = straight_pair(degree, rc, layout == 2)
                do i = 1, pc%na
                    pc%xa_1(:, i) = pc%xa_n(:, i) - [0.0_rk, 0.0_rk, s]
                end do
                call evaluate(pc, params, r_normal(1:6 * pc%na), e_n, e_1)
                call evaluate(pc, rough, r_both(1:6 * pc%na), e_n, e_1, dissipation=d_t)
                largest_normal = max(largest_normal, maxval(abs(r_both(1:6 * pc%na) - &
                    r_normal(1:6 * pc%na))) / maxval(abs(r_normal(1:6 * pc%na))))
                largest_dissipation = max(largest_dissipation, d_t / abs(dot_product( &
                    r_normal(1:6 * pc%na), [reshape(pc%xa_1 - pc%xa_n, [3 * pc%na]), &
                    reshape(pc%xb_1 - pc%xb_n, [3 * pc%nb])])))
            end do
        end do
        ! Round-off only: the tangents' ulps tilt n by 1e-16, a slip of 1e-16 s that the
        ! regularization (eta = 1e-6 s) magnifies to a friction of 1e-10 mu f_N.
        CHECK_TRUE(largest_normal <= 1.0e-9_rk, 'a normal step has no friction')
        CHECK_TRUE(largest_dissipation <= 1.0e-20_rk, 'a normal step does not dissipate')
        write(text, '(a,es9.2,a,es9.2,a,es9.2)') '    |friction / (mu normal force) - 1|: ', &
            worst, '; a normal step: friction / normal force ', largest_normal, &
            ', D / normal work ', largest_dissipation
        write(output_unit, '(a)') trim(text)
    end subroutine test_friction_coulomb_line

    ! Two straight elements of degree `degree` and length 2 r_c with 8 contact points each,
    ! centred at the origin: b along x, a 0.9 r_c above it along x (or y if `crossing`), at rest.
    function straight_pair(degree, rc, crossing) result(pc)
        integer, intent(in) :: degree
        real(rk), intent(in) :: rc
        logical, intent(in) :: crossing
        type(element_pair_t) :: pc
        real(rk) :: xi, axis(3)
        integer :: i
        logical :: ok
        pc%na = degree + 1
        pc%nb = degree + 1
        pc%ma = 8
        pc%mb = 8
        allocate(pc%shape_a(pc%na, pc%ma), pc%wa(pc%ma), pc%shape_b(pc%nb, pc%mb), pc%wb(pc%mb))
        allocate(pc%slope_a(pc%na, pc%ma), pc%slope_b(pc%nb, pc%mb))
        allocate(pc%xa_n(3, pc%na), pc%xa_1(3, pc%na), pc%xb_n(3, pc%nb), pc%xb_1(3, pc%nb))
        call contact_points(degree, pc%ma, pc%shape_a, pc%wa, ok, pc%slope_a)
        call contact_points(degree, pc%mb, pc%shape_b, pc%wb, ok, pc%slope_b)
        pc%wa = 2.0_rk * rc * pc%wa
        pc%wb = 2.0_rk * rc * pc%wb
        axis = merge([0.0_rk, 1.0_rk, 0.0_rk], [1.0_rk, 0.0_rk, 0.0_rk], crossing)
        do i = 1, pc%na
            xi = 2.0_rk * rc * (real(i - 1, rk) / degree - 0.5_rk)
            pc%xa_n(:, i) = xi * axis + [0.0_rk, 0.0_rk, 0.9_rk * rc]
            pc%xb_n(:, i) = [xi, 0.0_rk, 0.0_rk]
        end do
        pc%xa_1 = pc%xa_n
        pc%xb_1 = pc%xb_n
    end function straight_pair

    ! The sum of the terms r (packed as evaluate's) on the nodes of a.
    function friction_on_a(pc, r) result(total)
        type(element_pair_t), intent(in) :: pc
        real(rk), intent(in) :: r(:)
        real(rk) :: total(3)
        integer :: i
        total = 0.0_rk
        do i = 1, pc%na
            total = total + r(3 * i - 2:3 * i)
        end do
    end function friction_on_a

    subroutine sliding_ripple(params, m, length, d, ripple, tangential)
        type(contact_params_t), intent(in) :: params
        integer, intent(in) :: m
        real(rk), intent(in) :: length, d
        real(rk), intent(out) :: ripple, tangential
        real(rk) :: normal, t, lo, hi, mean
        integer :: k, n_offsets
        n_offsets = 24 * m
        lo = huge(1.0_rk)
        hi = -huge(1.0_rk)
        mean = 0.0_rk
        tangential = 0.0_rk
        do k = 0, n_offsets - 1
            call chain_force(params, 1, m, length, 1, params%contact_distance, d, &
                length * real(k, rk) / real(n_offsets, rk), normal, t)
            lo = min(lo, normal)
            hi = max(hi, normal)
            mean = mean + normal / n_offsets
            tangential = max(tangential, abs(t))
        end do
        ripple = (hi - lo) / mean
        tangential = tangential / mean
    end subroutine sliding_ripple

    pure function cross(u, v) result(w)
        real(rk), intent(in) :: u(3), v(3)
        real(rk) :: w(3)
        w = [u(2) * v(3) - u(3) * v(2), u(3) * v(1) - u(1) * v(3), u(1) * v(2) - u(2) * v(1)]
    end function cross

end module rs_test_contact_element

program test_contact_element
    use rs_test_contact_element, only: run_all_tests
    use rs_test_assert, only: finish_tests
    implicit none
    call run_all_tests()
    call finish_tests()
end program test_contact_element
