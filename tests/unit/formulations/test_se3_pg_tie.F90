#include "rs_assert.h"
!> Unit tests of rs_se3_pg_tie (se3_pg's joints and end plates, issue 22 item 5): for every kind
!> (spherical, rigid, revolute about a random axis, a plate placed at a random pose) at random
!> reference nodes (positions in [-2, 2]^3, rotation vectors of angle below 2.5) and random
!> perturbed coordinates z,
!>   - the rows vanish at the reference (a plate: at its reference pose, and with its node at
!>     the pose it was placed at);
!>   - gradient = central differences of value in the 12 coordinates;
!>   - force_gradient's rotation columns times T(psi) of their node are gradient's (the rows'
!>     body basis, module header of rs_se3_pg_tie);
!>   - force_hessian = central differences of force_gradient^T lambda in the coordinates;
!>   - joints: under a common rigid motion of both nodes (r -> Q r + c, psi -> log(Q Exp(psi)))
!>     the rotation rows are unchanged and the position rows turn with Q; hence the forces
!>     F^T lambda have zero net force and the torque g_pos x lambda_pos (zero where the joint
!>     holds), for every lambda;
!>   - the revolute joint turns about its hinge axis freely and not about a normal one;
!>   - an unknown kind, and a revolute joint without an axis, have no rows; se3_pg's new_tie
!>     then allocates no tie.
!>
!> Central differences with the step 1e-6 max(1, |z_j|): the rows are smooth (products of
!> rotations) with third derivatives of the size of the rows' terms, so truncation is about
!> 1e-12; the round-off of a difference quotient is eps |terms| / step, up to about 1e-9 with
!> terms of size 5 (positions up to 2 plus a perturbation, pivots up to 7). The bound 1e-8
!> relative to the largest entry sits 10 times above that and far below any wrong term. Exact
!> identities are held to round-off (1e-14, 1e-13 where log and exp of a rotation enter).
!> Measured worst values are printed.
module rs_test_se3_pg_tie
    use, intrinsic :: iso_fortran_env, only: output_unit
    use rs_core_kinds, only: rk
    use rs_test_random, only: set_random_seed, random_unit_vector, uniform, random_vector
    use rs_test_assert, only: run_test, assert_true, assert_close, assert_equal
    use rs_math_so3, only: exp_so3, log_so3, tangent_so3, hat
    use rs_formulations_formulation, only: node_tie_t
    use rs_se3_pg_tie, only: se3_pg_node_tie_t, se3_pg_node_tie
    use rs_se3_pg, only: se3_pg_t
    implicit none
    private

    public :: run_all_tests

    integer, parameter :: nz = 12
    character(len=9), parameter :: kinds(4) = [character(len=9) :: 'spherical', 'rigid', &
        'revolute', 'plate']
    integer, parameter :: rows_of_kind(4) = [3, 6, 5, 6]
    integer, parameter :: plate = 4
    ! Random cases per kind and test.
    integer, parameter :: n_cases = 20
    ! Largest angle of the reference rotation vectors, size of the perturbation of z.
    real(rk), parameter :: max_angle = 2.5_rk, perturbation = 0.3_rk
    ! Finite-difference step (relative to max(1, |z_j|)) and its tolerance relative to the
    ! largest entry (module header).
    real(rk), parameter :: fd_step = 1.0e-6_rk, fd_tol = 1.0e-8_rk
    ! Round-off tolerances of exact identities, relative to the size of their terms: 1e-14 for
    ! the same products recomputed, 1e-13 where z went through log and exp of a rotation.
    real(rk), parameter :: exact_tol = 1.0e-14_rk, motion_tol = 1.0e-13_rk

    !> A tie in its reference: the kind, the coordinates at which it holds, and a plate's pose.
    type :: tie_case_t
        integer :: kind = 0
        type(se3_pg_node_tie_t) :: tie
        !> [q_a; q_b] of the reference (a plate: q_a at the pose it is placed at, q_b unused).
        real(rk) :: z_ref(nz) = 0.0_rk
        !> A plate's node in the reference pose (before `place`).
        real(rk) :: q_ref(6) = 0.0_rk
        real(rk) :: axis(3) = 0.0_rk
    end type tie_case_t

    real(rk) :: worst_zero = 0.0_rk, worst_fd_gradient = 0.0_rk, worst_fd_hessian = 0.0_rk
    real(rk) :: worst_exact = 0.0_rk, worst_motion = 0.0_rk, worst_momentum = 0.0_rk

contains

    !> Run every test of this file through rs_test_assert.
    subroutine run_all_tests()
        call set_random_seed(20260214, 4001)
        call run_test('rows_and_unknown_kind', test_rows_and_unknown_kind)
        call run_test('reference_zero', test_reference_zero)
        call run_test('gradient_fd', test_gradient_fd)
        call run_test('force_gradient_body_basis', test_force_gradient_body_basis)
        call run_test('force_hessian_fd', test_force_hessian_fd)
        call run_test('joint_rigid_motion', test_joint_rigid_motion)
        call run_test('joint_net_force_and_torque', test_joint_net_force_and_torque)
        call run_test('revolute_hinge', test_revolute_hinge)
        write(output_unit, '(a,es10.3)') '  worst |g| at the reference / scale:         ', &
            worst_zero
        write(output_unit, '(a,es10.3)') '  worst gradient FD error / max|G|:           ', &
            worst_fd_gradient
        write(output_unit, '(a,es10.3)') '  worst Hessian FD error / max|H|:            ', &
            worst_fd_hessian
        write(output_unit, '(a,es10.3)') '  worst body-basis identity error / scale:    ', &
            worst_exact
        write(output_unit, '(a,es10.3)') '  worst rigid-motion change / scale:          ', &
            worst_motion
        write(output_unit, '(a,es10.3)') '  worst net force, torque error / scale:      ', &
            worst_momentum
    end subroutine run_all_tests

    ! ---------------------------------------------------------------------------------------
    ! Data

    ! A node at a random position with a rotation vector of random axis and angle < max_angle.
    function random_node() result(q)
        real(rk) :: q(6)
        q(1:3) = random_vector(3, 2.0_rk)
        q(4:6) = uniform(0.0_rk, max_angle) * random_unit_vector()
    end function random_node

    ! A tie of kind k in a random reference. Joints: independent random sections, with the
    ! ends coinciding (as the input check demands) or, for `offset`, up to 4 apart (a pivot s
    ! fixed in b's section). Revolute: a random hinge axis of length 2.5 (normalized by the
    ! tie). Plate: built at its reference pose, then placed at a random pose (centre,
    ! displacement, a rotation of angle in [0.1, 2.5]); z_ref holds the node at that pose.
    function random_case(k, offset) result(tc)
        integer, intent(in) :: k
        logical, intent(in) :: offset
        type(tie_case_t) :: tc
        real(rk) :: q_a(6), q_b(6), centre(3), displacement(3), rotation(3), r(3, 3)
        tc%kind = k
        q_a = random_node()
        q_b = random_node()
        if (.not. offset) q_b(1:3) = q_a(1:3)
        tc%axis = 2.5_rk * random_unit_vector()
        call se3_pg_node_tie(trim(kinds(k)), q_a, q_b, tc%axis, tc%tie)
        tc%z_ref(1:6) = q_a
        tc%z_ref(7:12) = q_b
        if (k /= plate) return
        tc%q_ref = q_a
        centre = random_vector(3, 1.0_rk)
        displacement = random_vector(3, 1.0_rk)
        rotation = uniform(0.1_rk, max_angle) * random_unit_vector()
        call tc%tie%place(centre, displacement, rotation)
        r = exp_so3(rotation)
        tc%z_ref(1:3) = centre + displacement + matmul(r, q_a(1:3) - centre)
        tc%z_ref(4:6) = log_so3(matmul(r, exp_so3(q_a(4:6))))
        tc%z_ref(7:12) = random_vector(6, 1.0_rk)
    end function random_case

    ! The reference coordinates moved by a random perturbation (unsatisfied rows).
    function perturbed(tc) result(z)
        type(tie_case_t), intent(in) :: tc
        real(rk) :: z(nz)
        z = tc%z_ref + random_vector(nz, perturbation)
    end function perturbed

    function rows_at(tie, z) result(g)
        class(node_tie_t), intent(in) :: tie
        real(rk), intent(in) :: z(nz)
        real(rk) :: g(tie%n)
        call tie%value(z, g)
    end function rows_at

    function gradient_at(tie, z) result(gz)
        class(node_tie_t), intent(in) :: tie
        real(rk), intent(in) :: z(nz)
        real(rk) :: gz(tie%n, nz)
        call tie%gradient(z, gz)
    end function gradient_at

    function force_gradient_at(tie, z) result(fz)
        class(node_tie_t), intent(in) :: tie
        real(rk), intent(in) :: z(nz)
        real(rk) :: fz(tie%n, nz)
        call tie%force_gradient(z, fz)
    end function force_gradient_at

    ! Both nodes of z moved rigidly: r -> rot r + shift, A -> rot A.
    function rigid_motion(rot, shift, z) result(moved)
        real(rk), intent(in) :: rot(3, 3), shift(3), z(nz)
        real(rk) :: moved(nz)
        integer :: at
        do at = 0, 6, 6
            moved(at + 1:at + 3) = matmul(rot, z(at + 1:at + 3)) + shift
            moved(at + 4:at + 6) = log_so3(matmul(rot, exp_so3(z(at + 4:at + 6))))
        end do
    end function rigid_motion

    ! Node b of z turned by rot about the point `pivot`.
    function turn_b(rot, pivot, z) result(moved)
        real(rk), intent(in) :: rot(3, 3), pivot(3), z(nz)
        real(rk) :: moved(nz)
        moved = z
        moved(7:9) = pivot + matmul(rot, z(7:9) - pivot)
        moved(10:12) = log_so3(matmul(rot, exp_so3(z(10:12))))
    end function turn_b

    ! The larger of 1 and the largest |entry|: the scale of absolute round-off.
    pure real(rk) function scale_of(v)
        real(rk), intent(in) :: v(:)
        scale_of = max(1.0_rk, maxval(abs(v)))
    end function scale_of

    subroutine record(worst, value)
        real(rk), intent(inout) :: worst
        real(rk), intent(in) :: value
        worst = max(worst, value)
    end subroutine record

    ! ---------------------------------------------------------------------------------------
    ! Tests

    ! Rows per kind and their coordinates; no rows for an unknown kind or a zero hinge axis,
    ! and then se3_pg's new_tie allocates nothing (the contract: no such tie).
    subroutine test_rows_and_unknown_kind()
        type(tie_case_t) :: tc
        type(se3_pg_node_tie_t) :: tie
        type(se3_pg_t) :: rod
        class(node_tie_t), allocatable :: made
        real(rk) :: q_a(6), q_b(6), zero3(3)
        integer :: k
        do k = 1, size(kinds)
            tc = random_case(k, .false.)
            CHECK_EQUAL(tc%tie%n, rows_of_kind(k), trim(kinds(k)) // ': rows')
            CHECK_EQUAL(tc%tie%n_coordinates, 6, trim(kinds(k)) // ': coordinates per node')
        end do
        q_a = random_node()
        q_b = random_node()
        zero3 = 0.0_rk
        call se3_pg_node_tie('hinge', q_a, q_b, random_unit_vector(), tie)
        CHECK_EQUAL(tie%n, 0, 'unknown kind: no rows')
        call se3_pg_node_tie('revolute', q_a, q_b, zero3, tie)
        CHECK_EQUAL(tie%n, 0, 'revolute without an axis: no rows')
        call rod%new_tie('hinge', q_a, q_b, random_unit_vector(), made)
        CHECK_TRUE(.not. allocated(made), 'se3_pg new_tie: no tie of an unknown kind')
        call rod%new_tie('spherical', q_a, q_b, random_unit_vector(), made)
        CHECK_TRUE(allocated(made), 'se3_pg new_tie: a spherical joint')
    end subroutine test_rows_and_unknown_kind

    ! g = 0 at the reference: joints at [q_a; q_b] (pivot offset or not), a plate with its node
    ! at the placed pose, and, unplaced, at its reference node.
    subroutine test_reference_zero()
        type(tie_case_t) :: tc
        type(se3_pg_node_tie_t) :: unplaced
        real(rk) :: scale, tol, z(nz), zero(6)
        real(rk), allocatable :: g(:)
        character(len=:), allocatable :: what
        integer :: k, i
        zero = 0.0_rk
        do k = 1, size(kinds)
            do i = 1, n_cases
                tc = random_case(k, mod(i, 2) == 0)
                g = rows_at(tc%tie, tc%z_ref)
                scale = scale_of(tc%z_ref)
                call record(worst_zero, maxval(abs(g)) / scale)
                tol = exact_tol * scale
                what = trim(kinds(k)) // ': g = 0'
                CHECK_CLOSE(g, zero(1:tc%tie%n), tol, 0.0_rk, what)
                if (k /= plate) cycle
                call se3_pg_node_tie('plate', tc%q_ref, tc%q_ref, tc%axis, unplaced)
                z = 0.0_rk
                z(1:6) = tc%q_ref
                g = rows_at(unplaced, z)
                scale = scale_of(z)
                call record(worst_zero, maxval(abs(g)) / scale)
                tol = exact_tol * scale
                CHECK_CLOSE(g, zero, tol, 0.0_rk, 'plate at its reference pose: g = 0')
            end do
        end do
    end subroutine test_reference_zero

    ! G = dg/dz against central differences in the 12 coordinates at a perturbed z.
    subroutine test_gradient_fd()
        type(tie_case_t) :: tc
        real(rk) :: z(nz), zp(nz), zm(nz), step, tol, error
        real(rk), allocatable :: gz(:, :), gz_fd(:, :)
        character(len=:), allocatable :: what
        integer :: k, i, j
        do k = 1, size(kinds)
            do i = 1, n_cases
                tc = random_case(k, mod(i, 2) == 0)
                z = perturbed(tc)
                gz = gradient_at(tc%tie, z)
                allocate(gz_fd(tc%tie%n, nz))
                do j = 1, nz
                    step = fd_step * max(1.0_rk, abs(z(j)))
                    zp = z
                    zm = z
                    zp(j) = z(j) + step
                    zm(j) = z(j) - step
                    gz_fd(:, j) = (rows_at(tc%tie, zp) - rows_at(tc%tie, zm)) / (2.0_rk * step)
                end do
                tol = fd_tol * max(1.0_rk, maxval(abs(gz)))
                error = maxval(abs(gz - gz_fd)) / max(1.0_rk, maxval(abs(gz)))
                call record(worst_fd_gradient, error)
                what = trim(kinds(k)) // ': gradient vs central differences'
                CHECK_CLOSE(gz, gz_fd, tol, 0.0_rk, what)
                deallocate(gz_fd)
            end do
        end do
    end subroutine test_gradient_fd

    ! The rows' forces in the body basis: force_gradient's position columns are gradient's, its
    ! rotation columns times T(psi) of their node are gradient's rotation columns (a plate's
    ! unused node b has none).
    subroutine test_force_gradient_body_basis()
        type(tie_case_t) :: tc
        real(rk) :: z(nz), scale, tol
        real(rk), allocatable :: gz(:, :), fz(:, :), expected(:, :)
        character(len=:), allocatable :: what
        integer :: k, i
        do k = 1, size(kinds)
            do i = 1, n_cases
                tc = random_case(k, mod(i, 2) == 0)
                z = perturbed(tc)
                gz = gradient_at(tc%tie, z)
                fz = force_gradient_at(tc%tie, z)
                expected = fz
                expected(:, 4:6) = matmul(fz(:, 4:6), tangent_so3(z(4:6)))
                expected(:, 10:12) = matmul(fz(:, 10:12), tangent_so3(z(10:12)))
                scale = max(1.0_rk, maxval(abs(fz)))
                call record(worst_exact, maxval(abs(gz - expected)) / scale)
                tol = exact_tol * scale
                what = trim(kinds(k)) // ': G = F T(psi)'
                CHECK_CLOSE(gz, expected, tol, 0.0_rk, what)
                if (k == plate) then
                    CHECK_TRUE(all(fz(:, 7:12) == 0.0_rk), 'plate: nothing on node b')
                end if
            end do
        end do
    end subroutine test_force_gradient_body_basis

    ! d(F(z)^T lambda)/dz against central differences in the coordinates, random lambda.
    subroutine test_force_hessian_fd()
        type(tie_case_t) :: tc
        real(rk) :: z(nz), zp(nz), zm(nz), hz(nz, nz), hz_fd(nz, nz), step, tol, error
        real(rk), allocatable :: lambda(:)
        character(len=:), allocatable :: what
        integer :: k, i, j, n
        do k = 1, size(kinds)
            do i = 1, n_cases
                tc = random_case(k, mod(i, 2) == 0)
                n = tc%tie%n
                z = perturbed(tc)
                lambda = random_vector(n, 1.0_rk)
                call tc%tie%force_hessian(z, lambda, hz)
                do j = 1, nz
                    step = fd_step * max(1.0_rk, abs(z(j)))
                    zp = z
                    zm = z
                    zp(j) = z(j) + step
                    zm(j) = z(j) - step
                    hz_fd(:, j) = matmul(lambda, force_gradient_at(tc%tie, zp) - &
                        force_gradient_at(tc%tie, zm)) / (2.0_rk * step)
                end do
                tol = fd_tol * max(1.0_rk, maxval(abs(hz)))
                error = maxval(abs(hz - hz_fd)) / max(1.0_rk, maxval(abs(hz)))
                call record(worst_fd_hessian, error)
                what = trim(kinds(k)) // ': Hessian vs central differences'
                CHECK_CLOSE(hz, hz_fd, tol, 0.0_rk, what)
            end do
        end do
    end subroutine test_force_hessian_fd

    ! A common rigid motion of both nodes: the rotation rows are unchanged, the position rows
    ! (a vector between the two sections) turn with Q; a translation alone changes nothing.
    subroutine test_joint_rigid_motion()
        type(tie_case_t) :: tc
        real(rk) :: z(nz), rot(3, 3), shift(3), ident(3, 3), scale, tol
        real(rk), allocatable :: g(:), g_moved(:)
        character(len=:), allocatable :: what
        integer :: k, i, n, l
        ident = 0.0_rk
        do l = 1, 3
            ident(l, l) = 1.0_rk
        end do
        do k = 1, 3
            do i = 1, n_cases
                tc = random_case(k, mod(i, 2) == 0)
                n = tc%tie%n
                z = perturbed(tc)
                rot = exp_so3(uniform(0.0_rk, max_angle) * random_unit_vector())
                shift = random_vector(3, 2.0_rk)
                g = rows_at(tc%tie, z)
                scale = scale_of(z) + scale_of(shift)
                tol = motion_tol * scale
                g_moved = rows_at(tc%tie, rigid_motion(ident, shift, z))
                call record(worst_motion, maxval(abs(g_moved - g)) / scale)
                what = trim(kinds(k)) // ': translation invariance'
                CHECK_CLOSE(g_moved, g, tol, 0.0_rk, what)
                g_moved = rows_at(tc%tie, rigid_motion(rot, shift, z))
                g(1:3) = matmul(rot, g(1:3))
                call record(worst_motion, maxval(abs(g_moved - g)) / scale)
                what = trim(kinds(k)) // ': position rows turn with Q'
                CHECK_CLOSE(g_moved(1:3), g(1:3), tol, 0.0_rk, what)
                if (n > 3) then
                    what = trim(kinds(k)) // ': rotation rows invariant'
                    CHECK_CLOSE(g_moved(4:n), g(4:n), tol, 0.0_rk, what)
                end if
                ! The reference moved rigidly still satisfies the joint.
                g_moved = rows_at(tc%tie, rigid_motion(rot, shift, tc%z_ref))
                call record(worst_motion, maxval(abs(g_moved)) / scale)
                what = trim(kinds(k)) // ': moved reference holds'
                CHECK_CLOSE(g_moved, 0.0_rk * g_moved, tol, 0.0_rk, what)
            end do
        end do
    end subroutine test_joint_rigid_motion

    ! Joint forces f = F(z)^T lambda (position rows: forces; rotation rows: body moments) at any
    ! z and lambda: the net force f(1:3) + f(7:9) vanishes, and the net moment about the
    ! origin, r_a x f_a + A_a m_a + r_b x f_b + A_b m_b, is g_pos x lambda_pos (the virtual
    ! work of an infinitesimal common rotation w, lambda . dg = lambda_pos . (w x g_pos), since
    ! the rotation rows do not change and the position rows turn).
    subroutine test_joint_net_force_and_torque()
        type(tie_case_t) :: tc
        real(rk) :: z(nz), f(nz), net(3), torque(3), expected(3), scale, tol, zero3(3)
        real(rk), allocatable :: lambda(:), g(:)
        character(len=:), allocatable :: what
        integer :: k, i, n, at
        zero3 = 0.0_rk
        do k = 1, 3
            do i = 1, n_cases
                tc = random_case(k, mod(i, 2) == 0)
                n = tc%tie%n
                z = perturbed(tc)
                lambda = random_vector(n, 1.0_rk)
                f = matmul(lambda, force_gradient_at(tc%tie, z))
                net = f(1:3) + f(7:9)
                scale = max(1.0_rk, maxval(abs(f)))
                call record(worst_momentum, maxval(abs(net)) / scale)
                tol = motion_tol * scale
                what = trim(kinds(k)) // ': net force'
                CHECK_CLOSE(net, zero3, tol, 0.0_rk, what)
                torque = 0.0_rk
                do at = 0, 6, 6
                    torque = torque + matmul(hat(z(at + 1:at + 3)), f(at + 1:at + 3)) + &
                        matmul(exp_so3(z(at + 4:at + 6)), f(at + 4:at + 6))
                end do
                g = rows_at(tc%tie, z)
                expected = matmul(hat(g(1:3)), lambda(1:3))
                scale = scale * scale_of(z)
                call record(worst_momentum, maxval(abs(torque - expected)) / scale)
                tol = motion_tol * scale
                what = trim(kinds(k)) // ': torque = g_pos x lambda_pos'
                CHECK_CLOSE(torque, expected, tol, 0.0_rk, what)
            end do
        end do
    end subroutine test_joint_net_force_and_torque

    ! Revolute joint with coinciding ends: node b turned about the hinge axis through the joint
    ! keeps every row at zero; turned by theta about an axis normal to the hinge it keeps the
    ! position rows and |(g_4, g_5)| = |sin(theta)| (the hinge axis tilted by theta).
    subroutine test_revolute_hinge()
        type(tie_case_t) :: tc
        real(rk) :: z(nz), e(3), u(3), theta, scale, tol, zero5(5)
        real(rk), allocatable :: g(:)
        integer :: i
        zero5 = 0.0_rk
        do i = 1, n_cases
            tc = random_case(3, .false.)
            e = tc%axis / norm2(tc%axis)
            theta = uniform(-max_angle, max_angle)
            z = turn_b(exp_so3(theta * e), tc%z_ref(1:3), tc%z_ref)
            g = rows_at(tc%tie, z)
            scale = scale_of(z)
            tol = motion_tol * scale
            call record(worst_motion, maxval(abs(g)) / scale)
            CHECK_CLOSE(g, zero5, tol, 0.0_rk, 'revolute: turn about the axis')
            u = matmul(hat(e), random_unit_vector())
            u = u / norm2(u)
            z = turn_b(exp_so3(theta * u), tc%z_ref(1:3), tc%z_ref)
            g = rows_at(tc%tie, z)
            CHECK_CLOSE(g(1:3), zero5(1:3), tol, 0.0_rk, 'revolute: pivot kept')
            CHECK_CLOSE(norm2(g(4:5)), abs(sin(theta)), tol, 0.0_rk, 'revolute: normal turn')
        end do
    end subroutine test_revolute_hinge

end module rs_test_se3_pg_tie

program test_se3_pg_tie
    use rs_test_se3_pg_tie, only: run_all_tests
    use rs_test_assert, only: finish_tests
    implicit none
    call run_all_tests()
    call finish_tests()
end program test_se3_pg_tie
