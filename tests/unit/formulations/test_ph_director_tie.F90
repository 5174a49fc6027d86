#include "rs_assert.h"
!> Unit tests of rs_ph_director_tie (joints and end plates of ph_director, issue 10; methods/
!> ph_director_3d.md §5.3): the rows vanish in the reference and on a plate-driven node; the
!> gradient and the Hessian against central finite differences; the exact discrete-gradient
!> identity of the midpoint step; objectivity of the joint rows (translation and rotation of
!> both nodes); zero net force and torque of the joint forces where the position rows vanish,
!> and the torque g x lambda where they do not; independence of the tie rows from the nodal
!> orthonormality rows (smallest singular value of the stacked gradient, with the 9-row
!> rigid joint as the singular counterexample); the exact rotation rows of the rigid joint,
!> the revolute hinge and the plate under a finite rotation; invalid arguments.
!>
!> Every row is at most quadratic, so central differences are exact up to round-off; the
!> tolerances bound round-off only. Measured worst values are printed.
module rs_test_ph_director_tie
    use, intrinsic :: iso_fortran_env, only: output_unit
    use, intrinsic :: ieee_arithmetic, only: ieee_is_finite
    use rs_core_kinds, only: rk, pi
    use rs_test_singular_values, only: svd_values => singular_values
    use rs_test_random, only: set_random_seed, random_unit_vector, uniform, random_vector
    use rs_test_assert, only: run_test, assert_true, assert_close, assert_equal
    use rs_math_so3, only: exp_so3
    use rs_ph_director_element, only: ph_director_node_constraint
    use rs_ph_director_tie, only: ph_director_tie_t, ph_director_joint_tie, &
        ph_director_plate_tie, ph_director_tie_value, ph_director_tie_gradient, &
        ph_director_tie_hessian, ph_director_tie_size, ph_director_tie_max_rows
    implicit none
    private

    public :: run_all_tests


    integer, parameter :: nz = ph_director_tie_size
    character(len=9), parameter :: kinds(3) = [character(len=9) :: 'spherical', 'rigid', &
        'revolute']
    integer, parameter :: rows_of_kind(3) = [3, 6, 5]
    ! Random cases per kind and test.
    integer, parameter :: n_cases = 20
    ! Finite-difference step (relative to max(1, |z|)) and its tolerance relative to max |G|.
    real(rk), parameter :: fd_step = 1.0e-6_rk, fd_tol = 1.0e-8_rk
    ! Round-off tolerance of exact identities, relative to the size of their terms.
    real(rk), parameter :: exact_tol = 1.0e-14_rk
    ! Smallest admissible singular value of the stacked constraint gradient, relative to the
    ! largest (independence), and the largest one counted as zero (the singular control).
    real(rk), parameter :: rank_tol = 1.0e-2_rk, zero_tol = 1.0e-12_rk
    real(rk), parameter :: zero3(3) = 0.0_rk

    !> A joint in its reference: the two nodes, the hinge axis, the tie.
    type :: joint_case_t
        real(rk) :: q_a(12) = 0.0_rk, q_b(12) = 0.0_rk, axis(3) = 0.0_rk
        type(ph_director_tie_t) :: tie
    end type joint_case_t

    real(rk) :: worst_fd = 0.0_rk, worst_exact = 0.0_rk, worst_momentum = 0.0_rk
    real(rk) :: worst_sigma = huge(1.0_rk)

contains

    !> Run every test of this file through rs_test_assert.
    subroutine run_all_tests()
        call set_random_seed(20250310, 7919)
        call run_test('rows_and_invalid_arguments', test_rows_and_invalid_arguments)
        call run_test('reference_zero', test_reference_zero)
        call run_test('plate_moved_node', test_plate_moved_node)
        call run_test('gradient_hessian_fd', test_gradient_hessian_fd)
        call run_test('discrete_gradient', test_discrete_gradient)
        call run_test('joint_objectivity', test_joint_objectivity)
        call run_test('net_force_and_torque', test_net_force_and_torque)
        call run_test('independence', test_independence)
        call run_test('rigid_rotation_rows', test_rigid_rotation_rows)
        call run_test('revolute_hinge', test_revolute_hinge)
        call run_test('plate_rotation_rows', test_plate_rotation_rows)
        write(output_unit, '(a,es10.3)') '  worst FD error / max|G|:              ', worst_fd
        write(output_unit, '(a,es10.3)') '  worst exact-identity error / scale:   ', worst_exact
        write(output_unit, '(a,es10.3)') '  worst net force, torque / scale:      ', worst_momentum
        write(output_unit, '(a,es10.3)') '  smallest sigma_min / sigma_max (ties): ', worst_sigma
    end subroutine run_all_tests

    ! ---------------------------------------------------------------------------------------
    ! Data

    function random_rotation() result(r)
        real(rk) :: r(3, 3)
        r = exp_so3(uniform(0.0_rk, pi) * random_unit_vector())
    end function random_rotation

    ! Nodal coordinates at position phi with directors the columns of rot.
    pure function node(phi, rot) result(q)
        real(rk), intent(in) :: phi(3), rot(3, 3)
        real(rk) :: q(12)
        q(1:3) = phi
        q(4:12) = reshape(rot, [9])
    end function node

    ! Every 3-vector of z (positions and directors) turned by rot; positions then moved by t.
    pure function rigid_motion(rot, t, z) result(y)
        real(rk), intent(in) :: rot(3, 3), t(3), z(nz)
        real(rk) :: y(nz)
        integer :: p
        do p = 0, nz / 3 - 1
            y(3 * p + 1:3 * p + 3) = matmul(rot, z(3 * p + 1:3 * p + 3))
        end do
        y(1:3) = y(1:3) + t
        y(13:15) = y(13:15) + t
    end function rigid_motion

    ! Node b (second half of z) turned by rot about the point `pivot`.
    pure function turn_b(rot, pivot, z) result(y)
        real(rk), intent(in) :: rot(3, 3), pivot(3), z(nz)
        real(rk) :: y(nz)
        integer :: p
        y = z
        y(13:15) = pivot + matmul(rot, z(13:15) - pivot)
        do p = 5, 7
            y(3 * p + 1:3 * p + 3) = matmul(rot, z(3 * p + 1:3 * p + 3))
        end do
    end function turn_b

    ! A joint of kind k in a random reference: independent random frames, coinciding ends or
    ! (offset) ends 0.3 apart, a random hinge axis of length 2.5.
    function random_joint(k, offset) result(jc)
        integer, intent(in) :: k
        logical, intent(in) :: offset
        type(joint_case_t) :: jc
        real(rk) :: phi(3)
        phi = random_vector(3, 2.0_rk)
        jc%q_a = node(phi, random_rotation())
        if (offset) phi = phi + 0.3_rk * random_unit_vector()
        jc%q_b = node(phi, random_rotation())
        jc%axis = 2.5_rk * random_unit_vector()
        jc%tie = ph_director_joint_tie(trim(kinds(k)), jc%q_a, jc%q_b, jc%axis)
    end function random_joint

    ! A plate tie of a random node with random centre and, unless `at_rest`, random motion.
    subroutine random_plate(at_rest, q_ref, centre, displacement, rotation, tie)
        logical, intent(in) :: at_rest
        real(rk), intent(out) :: q_ref(12), centre(3), displacement(3), rotation(3)
        type(ph_director_tie_t), intent(out) :: tie
        q_ref = node(random_vector(3, 2.0_rk), random_rotation())
        centre = random_vector(3, 1.0_rk)
        displacement = 0.0_rk
        rotation = 0.0_rk
        if (.not. at_rest) then
            displacement = random_vector(3, 1.0_rk)
            rotation = uniform(0.1_rk, pi) * random_unit_vector()
        end if
        tie = ph_director_plate_tie(q_ref, centre, displacement, rotation)
    end subroutine random_plate

    ! Central-difference gradient of the rows (n x nz).
    function fd_gradient(tie, z) result(gz)
        type(ph_director_tie_t), intent(in) :: tie
        real(rk), intent(in) :: z(nz)
        real(rk) :: gz(tie%n, nz), zp(nz), zm(nz), step
        integer :: j
        do j = 1, nz
            step = fd_step * max(1.0_rk, abs(z(j)))
            zp = z
            zm = z
            zp(j) = z(j) + step
            zm(j) = z(j) - step
            gz(:, j) = (ph_director_tie_value(tie, zp) - ph_director_tie_value(tie, zm)) &
                / (2.0_rk * step)
        end do
    end function fd_gradient

    ! Central-difference gradient (6 x 12) of a node's orthonormality rows.
    function orthonormality_gradient(q) result(gq)
        real(rk), intent(in) :: q(12)
        real(rk) :: gq(6, 12), qp(12), qm(12)
        integer :: j
        ! The rows are quadratic: a unit step has no truncation error and the least round-off.
        do j = 1, 12
            qp = q
            qm = q
            qp(j) = q(j) + 1.0_rk
            qm(j) = q(j) - 1.0_rk
            gq(:, j) = 0.5_rk * (ph_director_node_constraint(qp) - ph_director_node_constraint(qm))
        end do
    end function orthonormality_gradient

    ! Singular values of a (m x n), in decreasing order (min(m, n) of them). Reference LAPACK
    ! raises IEEE exceptions on purpose (its NaN and scaling probes), so the Debug build's
    ! traps are off during the call and the flags it leaves are cleared.
    function singular_values(a) result(s)
        real(rk), intent(in) :: a(:, :)
        real(rk) :: s(min(size(a, 1), size(a, 2)))
        integer :: info
        s = svd_values(a, info)
        CHECK_EQUAL(info, 0, 'dgesvd')
        CHECK_TRUE(all(ieee_is_finite(s)), 'finite singular values')
    end function singular_values

    ! Net force (1:3) and torque about the origin (4:6) of the generalized forces f on the
    ! 3-vectors x of z: force on phi_a and phi_b, torque sum_p x_p x f_p over all 8 vectors.
    pure function wrench(z, f) result(w)
        real(rk), intent(in) :: z(nz), f(nz)
        real(rk) :: w(6)
        integer :: p
        w(1:3) = f(1:3) + f(13:15)
        w(4:6) = 0.0_rk
        do p = 0, nz / 3 - 1
            w(4:6) = w(4:6) + cross(z(3 * p + 1:3 * p + 3), f(3 * p + 1:3 * p + 3))
        end do
    end function wrench

    ! The position rows (1:3) of a joint's gradient.
    pure function position_rows(gz) result(rows)
        real(rk), intent(in) :: gz(:, :)
        real(rk) :: rows(3, nz)
        rows = gz(1:3, :)
    end function position_rows

    pure function cross(a, b) result(c)
        real(rk), intent(in) :: a(3), b(3)
        real(rk) :: c(3)
        c = [a(2) * b(3) - a(3) * b(2), a(3) * b(1) - a(1) * b(3), a(1) * b(2) - a(2) * b(1)]
    end function cross

    subroutine record(worst, value)
        real(rk), intent(inout) :: worst
        real(rk), intent(in) :: value
        worst = max(worst, value)
    end subroutine record

    ! ---------------------------------------------------------------------------------------
    ! Tests

    subroutine test_rows_and_invalid_arguments()
        type(ph_director_tie_t) :: tie
        type(joint_case_t) :: jc
        real(rk) :: q_ref(12), centre(3), displacement(3), rotation(3)
        integer :: k
        do k = 1, 3
            jc = random_joint(k, .false.)
            CHECK_EQUAL(jc%tie%n, rows_of_kind(k), 'rows of ' // trim(kinds(k)))
            CHECK_TRUE(jc%tie%two_nodes, 'a joint ties two nodes')
            CHECK_TRUE(all(jc%tie%a(:, :, jc%tie%n + 1:) == 0.0_rk), 'unused rows are zero')
        end do
        ! Trailing blanks, as read from a namelist, are no error.
        tie = ph_director_joint_tie('rigid   ', jc%q_a, jc%q_b, jc%axis)
        CHECK_EQUAL(tie%n, 6, 'kind with trailing blanks')
        tie = ph_director_joint_tie('hinge', jc%q_a, jc%q_b, jc%axis)
        CHECK_EQUAL(tie%n, 0, 'unknown kind: empty tie')
        tie = ph_director_joint_tie('revolute', jc%q_a, jc%q_b, [0.0_rk, 0.0_rk, 0.0_rk])
        CHECK_EQUAL(tie%n, 0, 'zero revolute axis: empty tie')
        call random_plate(.false., q_ref, centre, displacement, rotation, tie)
        CHECK_EQUAL(tie%n, 6, 'plate rows')
        CHECK_TRUE(.not. tie%two_nodes, 'a plate ties one node')
        CHECK_TRUE(all(tie%a == 0.0_rk), 'plate rows are linear')
        CHECK_TRUE(all(tie%b(13:nz, :) == 0.0_rk), 'plate rows: zero b-part')
        CHECK_EQUAL(size(ph_director_tie_value(tie, random_vector(nz, 1.0_rk))), 6, 'size of g')
    end subroutine test_rows_and_invalid_arguments

    subroutine test_reference_zero()
        type(joint_case_t) :: jc
        type(ph_director_tie_t) :: tie
        real(rk) :: q_ref(12), centre(3), displacement(3), rotation(3), z(nz), scale
        real(rk), allocatable :: g(:)
        integer :: k, i
        do k = 1, 3
            do i = 1, n_cases
                jc = random_joint(k, i > n_cases / 2)
                z = [jc%q_a, jc%q_b]
                g = ph_director_tie_value(jc%tie, z)
                scale = maxval(abs(z))
                call record(worst_exact, maxval(abs(g)) / scale)
                CHECK_CLOSE(g, 0.0_rk * g, exact_tol * scale, 0.0_rk, trim(kinds(k)) // ': g(ref)')
            end do
        end do
        do i = 1, n_cases
            call random_plate(.true., q_ref, centre, displacement, rotation, tie)
            z = 0.0_rk
            z(1:12) = q_ref
            g = ph_director_tie_value(tie, z)
            scale = maxval(abs(z)) + maxval(abs(centre))
            call record(worst_exact, maxval(abs(g)) / scale)
            CHECK_CLOSE(g, 0.0_rk * g, exact_tol * scale, 0.0_rk, 'plate at rest: g(ref) = 0')
        end do
    end subroutine test_reference_zero

    ! A node moved rigidly with the plate satisfies the tie; one left behind does not.
    subroutine test_plate_moved_node()
        type(ph_director_tie_t) :: tie
        real(rk) :: q_ref(12), centre(3), displacement(3), rotation(3), rot(3, 3), z(nz)
        real(rk) :: scale
        real(rk), allocatable :: g(:)
        integer :: i, j
        do i = 1, n_cases
            call random_plate(.false., q_ref, centre, displacement, rotation, tie)
            rot = exp_so3(rotation)
            z = 0.0_rk
            z(1:3) = centre + displacement + matmul(rot, q_ref(1:3) - centre)
            do j = 1, 3
                z(3 * j + 1:3 * j + 3) = matmul(rot, q_ref(3 * j + 1:3 * j + 3))
            end do
            g = ph_director_tie_value(tie, z)
            scale = maxval(abs(z)) + maxval(abs(centre)) + maxval(abs(displacement))
            call record(worst_exact, maxval(abs(g)) / scale)
            CHECK_CLOSE(g, 0.0_rk * g, exact_tol * scale, 0.0_rk, 'plate moved: node moved along')
            z(1:12) = q_ref
            g = ph_director_tie_value(tie, z)
            CHECK_TRUE(maxval(abs(g)) > 1.0e-2_rk, 'plate moved: node left behind violates it')
        end do
    end subroutine test_plate_moved_node

    ! G and sum lambda_k A_k against central differences at random (unsatisfied) z; A_k symmetric.
    subroutine test_gradient_hessian_fd()
        type(ph_director_tie_t) :: tie
        type(joint_case_t) :: jc
        real(rk) :: q_ref(12), centre(3), displacement(3), rotation(3), z(nz), zp(nz), zm(nz)
        real(rk) :: hz(nz, nz), hz_fd(nz, nz), lambda(ph_director_tie_max_rows), step, tol
        real(rk), allocatable :: gz(:, :), gz_fd(:, :)
        integer :: k, i, j, n
        do k = 1, 4
            do i = 1, n_cases
                if (k <= 3) then
                    jc = random_joint(k, mod(i, 2) == 0)
                    tie = jc%tie
                else
                    call random_plate(mod(i, 2) == 0, q_ref, centre, displacement, rotation, tie)
                end if
                n = tie%n
                z = random_vector(nz, 1.5_rk)
                gz = ph_director_tie_gradient(tie, z)
                gz_fd = fd_gradient(tie, z)
                tol = fd_tol * max(1.0_rk, maxval(abs(gz)))
                call record(worst_fd, maxval(abs(gz - gz_fd)) / max(1.0_rk, maxval(abs(gz))))
                CHECK_CLOSE(gz, gz_fd, tol, 0.0_rk, 'gradient vs central differences')
                lambda(1:n) = random_vector(n, 1.0_rk)
                hz = ph_director_tie_hessian(tie, lambda(1:n))
                do j = 1, nz
                    step = fd_step * max(1.0_rk, abs(z(j)))
                    zp = z
                    zm = z
                    zp(j) = z(j) + step
                    zm(j) = z(j) - step
                    gz = ph_director_tie_gradient(tie, zp)
                    gz_fd = ph_director_tie_gradient(tie, zm)
                    hz_fd(:, j) = matmul(lambda(1:n), gz - gz_fd) / (2.0_rk * step)
                end do
                tol = fd_tol * max(1.0_rk, maxval(abs(hz)))
                call record(worst_fd, maxval(abs(hz - hz_fd)) / max(1.0_rk, maxval(abs(hz))))
                CHECK_CLOSE(hz, hz_fd, tol, 0.0_rk, 'Hessian vs central differences')
                CHECK_CLOSE(hz, transpose(hz), 0.0_rk, 0.0_rk, 'Hessian symmetric')
            end do
        end do
    end subroutine test_gradient_hessian_fd

    ! g(z_1) - g(z_n) = G(z_mid)(z_1 - z_n) for random z_n, z_1 (methods §5.3 item 2).
    subroutine test_discrete_gradient()
        type(ph_director_tie_t) :: tie
        type(joint_case_t) :: jc
        real(rk) :: q_ref(12), centre(3), displacement(3), rotation(3), z_n(nz), z_1(nz)
        real(rk) :: scale
        real(rk), allocatable :: lhs(:), rhs(:)
        integer :: k, i
        do k = 1, 4
            do i = 1, n_cases
                if (k <= 3) then
                    jc = random_joint(k, mod(i, 2) == 0)
                    tie = jc%tie
                else
                    call random_plate(.false., q_ref, centre, displacement, rotation, tie)
                end if
                z_n = random_vector(nz, 1.5_rk)
                z_1 = random_vector(nz, 1.5_rk)
                lhs = ph_director_tie_value(tie, z_1) - ph_director_tie_value(tie, z_n)
                rhs = matmul(ph_director_tie_gradient(tie, 0.5_rk * (z_n + z_1)), z_1 - z_n)
                scale = maxval(abs(ph_director_tie_value(tie, z_1))) &
                    + maxval(abs(ph_director_tie_value(tie, z_n))) + 1.0_rk
                call record(worst_exact, maxval(abs(lhs - rhs)) / scale)
                CHECK_CLOSE(lhs, rhs, exact_tol * scale, 0.0_rk, 'exact discrete gradient')
            end do
        end do
    end subroutine test_discrete_gradient

    ! Under a common translation every joint row is unchanged; under a common rotation R the
    ! rotation rows are unchanged and the position rows turn with R.
    subroutine test_joint_objectivity()
        type(joint_case_t) :: jc
        real(rk) :: z(nz), rot(3, 3), t(3), ident(3, 3), scale
        real(rk), allocatable :: g(:), g_moved(:)
        integer :: k, i, n
        ident = 0.0_rk
        ident(1, 1) = 1.0_rk
        ident(2, 2) = 1.0_rk
        ident(3, 3) = 1.0_rk
        do k = 1, 3
            do i = 1, n_cases
                jc = random_joint(k, mod(i, 2) == 0)
                n = jc%tie%n
                z = random_vector(nz, 1.5_rk)
                rot = random_rotation()
                t = random_vector(3, 2.0_rk)
                g = ph_director_tie_value(jc%tie, z)
                scale = maxval(abs(g)) + 1.0_rk
                g_moved = ph_director_tie_value(jc%tie, rigid_motion(ident, t, z))
                call record(worst_exact, maxval(abs(g_moved - g)) / scale)
                CHECK_CLOSE(g_moved, g, exact_tol * scale, 0.0_rk, 'translation invariance')
                g_moved = ph_director_tie_value(jc%tie, rigid_motion(rot, 0.0_rk * t, z))
                g(1:3) = matmul(rot, g(1:3))
                call record(worst_exact, maxval(abs(g_moved - g)) / scale)
                CHECK_CLOSE(g_moved(1:3), g(1:3), exact_tol * scale, 0.0_rk, 'position rows turn')
                if (n > 3) then
                    CHECK_CLOSE(g_moved(4:n), g(4:n), exact_tol * scale, 0.0_rk, 'rotation rows')
                end if
            end do
        end do
    end subroutine test_joint_objectivity

    ! Joint forces f = G(z)^T lambda: zero net force at any z; torque g_pos(z) x lambda_pos, so
    ! zero at the midpoint of two satisfied configurations (rigidly moved reference, plus for
    ! the revolute joint a relative turn about the hinge), where the step's work
    ! lambda^T G(z_mid)(z_1 - z_n) vanishes too.
    subroutine test_net_force_and_torque()
        type(joint_case_t) :: jc
        real(rk) :: z_ref(nz), z_n(nz), z_1(nz), z_mid(nz), z(nz), f(nz), w(6), lambda(6)
        real(rk) :: torque(3), scale, work, hinge(3)
        real(rk), allocatable :: g(:)
        integer :: k, i, n
        do k = 1, 3
            do i = 1, n_cases
                jc = random_joint(k, mod(i, 2) == 0)
                n = jc%tie%n
                lambda(1:n) = random_vector(n, 1.0_rk)
                ! any z
                z = random_vector(nz, 1.5_rk)
                f = matmul(lambda(1:n), ph_director_tie_gradient(jc%tie, z))
                w = wrench(z, f)
                g = ph_director_tie_value(jc%tie, z)
                torque = cross(g(1:3), lambda(1:3))
                scale = maxval(abs(z)) * maxval(abs(f)) + 1.0_rk
                call record(worst_momentum, maxval(abs(w(1:3))) / scale)
                CHECK_CLOSE(w(1:3), zero3, exact_tol * scale, 0.0_rk, 'net force, any z')
                CHECK_CLOSE(w(4:6), torque, exact_tol * scale, 0.0_rk, 'torque = g x lambda')
                ! midpoint of two satisfied configurations
                z_ref = [jc%q_a, jc%q_b]
                z_n = rigid_motion(random_rotation(), random_vector(3, 1.0_rk), z_ref)
                z_1 = rigid_motion(random_rotation(), random_vector(3, 1.0_rk), z_ref)
                if (kinds(k) == 'revolute') then
                    ! z_1's hinge axis is the reference axis turned like z_1's node a.
                    hinge = matmul(reshape(z_1(4:12), [3, 3]), &
                        matmul(transpose(reshape(jc%q_a(4:12), [3, 3])), jc%axis))
                    z_1 = turn_b(exp_so3(uniform(-pi, pi) * hinge / norm2(hinge)), z_1(1:3), z_1)
                end if
                z_mid = 0.5_rk * (z_n + z_1)
                f = matmul(lambda(1:n), ph_director_tie_gradient(jc%tie, z_mid))
                w = wrench(z_mid, f)
                scale = maxval(abs(z_mid)) * maxval(abs(f)) + 1.0_rk
                call record(worst_momentum, maxval(abs(w)) / scale)
                CHECK_CLOSE(w, 0.0_rk * w, exact_tol * scale, 0.0_rk, trim(kinds(k)) // ': wrench')
                work = dot_product(f, z_1 - z_n)
                CHECK_CLOSE(work, 0.0_rk, exact_tol * scale, 0.0_rk, trim(kinds(k)) // ': work')
            end do
        end do
    end subroutine test_net_force_and_torque

    ! At the reference, [tie rows; orthonormality rows of the tied nodes] has full row rank
    ! (n + 12 for a joint, n + 6 for a plate). Control: a rigid joint written as the 9 rows
    ! d_b^j - sum_i C_ij d_a^i repeats 6 orthonormality rows (DESIGN.md §5) and is singular.
    subroutine test_independence()
        type(joint_case_t) :: jc
        type(ph_director_tie_t) :: tie
        real(rk) :: q_ref(12), centre(3), displacement(3), rotation(3), z(nz)
        real(rk) :: stack(24, nz), c(3, 3), ratio
        real(rk), allocatable :: s(:)
        integer :: k, i, n, a, b, l
        do k = 1, 3
            do i = 1, n_cases
                jc = random_joint(k, mod(i, 2) == 0)
                n = jc%tie%n
                z = [jc%q_a, jc%q_b]
                stack = 0.0_rk
                stack(1:n, :) = ph_director_tie_gradient(jc%tie, z)
                stack(n + 1:n + 6, 1:12) = orthonormality_gradient(jc%q_a)
                stack(n + 7:n + 12, 13:24) = orthonormality_gradient(jc%q_b)
                s = singular_values(stack(1:n + 12, :))
                ratio = s(n + 12) / s(1)
                worst_sigma = min(worst_sigma, ratio)
                CHECK_TRUE(ratio > rank_tol, trim(kinds(k)) // ': independent of orthonormality')
            end do
        end do
        do i = 1, n_cases
            call random_plate(mod(i, 2) == 0, q_ref, centre, displacement, rotation, tie)
            z = 0.0_rk
            z(1:12) = q_ref
            stack = 0.0_rk
            stack(1:6, :) = ph_director_tie_gradient(tie, z)
            stack(7:12, 1:12) = orthonormality_gradient(q_ref)
            s = singular_values(stack(1:12, 1:12))
            ratio = s(12) / s(1)
            worst_sigma = min(worst_sigma, ratio)
            CHECK_TRUE(ratio > rank_tol, 'plate: independent of orthonormality')
        end do
        ! the 9-row rigid joint
        jc = random_joint(2, .false.)
        do a = 1, 3
            do b = 1, 3
                c(a, b) = dot_product(jc%q_a(3 * a + 1:3 * a + 3), jc%q_b(3 * b + 1:3 * b + 3))
            end do
        end do
        stack = 0.0_rk
        stack(1:3, :) = position_rows(ph_director_tie_gradient(jc%tie, [jc%q_a, jc%q_b]))
        do b = 1, 3
            do l = 1, 3
                stack(3 + 3 * (b - 1) + l, 15 + 3 * (b - 1) + l) = 1.0_rk
                do a = 1, 3
                    stack(3 + 3 * (b - 1) + l, 3 + 3 * (a - 1) + l) = -c(a, b)
                end do
            end do
        end do
        stack(13:18, 1:12) = orthonormality_gradient(jc%q_a)
        stack(19:24, 13:24) = orthonormality_gradient(jc%q_b)
        s = singular_values(stack)
        write(output_unit, '(a,2es10.3)') '  9-row rigid joint: sigma_18, sigma_19 / sigma_1: ', &
            s(18) / s(1), s(19) / s(1)
        CHECK_TRUE(s(19) / s(1) < zero_tol, '9-row rigid joint: 6 dependent rows')
        CHECK_TRUE(s(18) / s(1) > rank_tol, '9-row rigid joint: rank 18')
    end subroutine test_independence

    ! Node b turned by the angle theta about a unit u through the pivot (node a's position):
    ! the position rows stay zero and the rotation rows are -sin(theta) u . d_b^k exactly.
    subroutine test_rigid_rotation_rows()
        type(joint_case_t) :: jc
        real(rk) :: z(nz), u(3), theta, expected(6)
        real(rk), allocatable :: g(:)
        integer :: i, k
        do i = 1, n_cases
            jc = random_joint(2, mod(i, 2) == 0)
            u = random_unit_vector()
            theta = uniform(-pi, pi)
            z = turn_b(exp_so3(theta * u), jc%q_a(1:3), [jc%q_a, jc%q_b])
            g = ph_director_tie_value(jc%tie, z)
            expected(1:3) = 0.0_rk
            do k = 1, 3
                expected(3 + k) = -sin(theta) * dot_product(u, jc%q_b(3 * k + 1:3 * k + 3))
            end do
            call record(worst_exact, maxval(abs(g - expected)) / maxval(abs(z)))
            CHECK_CLOSE(g, expected, exact_tol * maxval(abs(z)), 0.0_rk, 'rigid: finite turn')
        end do
    end subroutine test_rigid_rotation_rows

    ! Revolute: node b turned about the hinge axis through the pivot keeps g = 0; turned about a
    ! perpendicular axis by theta it gives |(g_4, g_5)| = |sin(theta)| and g(1:3) = 0.
    subroutine test_revolute_hinge()
        type(joint_case_t) :: jc
        real(rk) :: z(nz), e(3), u(3), theta, scale, tol
        real(rk), allocatable :: g(:)
        integer :: i
        do i = 1, n_cases
            jc = random_joint(3, mod(i, 2) == 0)
            e = jc%axis / norm2(jc%axis)
            theta = uniform(-pi, pi)
            z = turn_b(exp_so3(theta * e), jc%q_a(1:3), [jc%q_a, jc%q_b])
            g = ph_director_tie_value(jc%tie, z)
            scale = maxval(abs(z))
            tol = exact_tol * scale
            call record(worst_exact, maxval(abs(g)) / scale)
            CHECK_CLOSE(g, 0.0_rk * g, tol, 0.0_rk, 'revolute: turn about the axis')
            u = cross(e, random_unit_vector())
            u = u / norm2(u)
            z = turn_b(exp_so3(theta * u), jc%q_a(1:3), [jc%q_a, jc%q_b])
            g = ph_director_tie_value(jc%tie, z)
            CHECK_CLOSE(g(1:3), zero3, tol, 0.0_rk, 'revolute: pivot kept')
            CHECK_CLOSE(norm2(g(4:5)), abs(sin(theta)), tol, 0.0_rk, 'revolute: normal turn')
        end do
    end subroutine test_revolute_hinge

    ! Plate: the node at its target turned further by theta about u gives rotation rows
    ! -sin(theta) u . t^k with t^k = R d_ref^k, exactly.
    subroutine test_plate_rotation_rows()
        type(ph_director_tie_t) :: tie
        real(rk) :: q_ref(12), centre(3), displacement(3), rotation(3), rot(3, 3), turn(3, 3)
        real(rk) :: z(nz), t(3), u(3), theta, expected(6), scale
        real(rk), allocatable :: g(:)
        integer :: i, k
        do i = 1, n_cases
            call random_plate(.false., q_ref, centre, displacement, rotation, tie)
            rot = exp_so3(rotation)
            u = random_unit_vector()
            theta = uniform(-pi, pi)
            turn = exp_so3(theta * u)
            z = 0.0_rk
            z(1:3) = centre + displacement + matmul(rot, q_ref(1:3) - centre)
            expected(1:3) = 0.0_rk
            do k = 1, 3
                t = matmul(rot, q_ref(3 * k + 1:3 * k + 3))
                z(3 * k + 1:3 * k + 3) = matmul(turn, t)
                expected(3 + k) = -sin(theta) * dot_product(u, t)
            end do
            g = ph_director_tie_value(tie, z)
            scale = maxval(abs(z)) + maxval(abs(centre)) + maxval(abs(displacement))
            call record(worst_exact, maxval(abs(g - expected)) / scale)
            CHECK_CLOSE(g, expected, exact_tol * scale, 0.0_rk, 'plate: rows of a finite turn')
        end do
    end subroutine test_plate_rotation_rows

end module rs_test_ph_director_tie

program test_ph_director_tie
    use rs_test_ph_director_tie, only: run_all_tests
    use rs_test_assert, only: finish_tests
    implicit none
    call run_all_tests()
    call finish_tests()
end program test_ph_director_tie
