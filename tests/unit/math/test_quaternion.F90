#include "rs_assert.h"
!> Unit tests of rs_math_quaternion: conversions at every angle including pi, composition,
!> conjugation, rotation of vectors, agreement with rs_math_so3.
module rs_test_math_quaternion
    use rs_core_kinds, only: rk, pi
    use rs_test_random, only: set_random_seed, random_unit_vector
    use rs_test_assert, only: run_test, assert_true, assert_close
    use rs_math_quaternion, only: quaternion_from_matrix, quaternion_to_matrix, &
        quaternion_product, quaternion_conjugate, quaternion_normalize, quaternion_rotate, &
        quaternion_from_rotation_vector, quaternion_to_rotation_vector
    use rs_math_so3, only: exp_so3
    implicit none
    private

    public :: run_all_tests

    real(rk), parameter :: identity(3, 3) = reshape([1.0_rk, 0.0_rk, 0.0_rk, 0.0_rk, 1.0_rk, &
        0.0_rk, 0.0_rk, 0.0_rk, 1.0_rk], [3, 3])
    real(rk), parameter :: unit_q(4) = [1.0_rk, 0.0_rk, 0.0_rk, 0.0_rk]

contains

    !> Run every test of this file through rs_test_assert.
    subroutine run_all_tests()
        call set_random_seed(31337, 104729)
        call run_test('matrix_round_trip', test_matrix_round_trip)
        call run_test('shepperd_pivots', test_shepperd_pivots)
        call run_test('to_matrix_is_rotation', test_to_matrix_is_rotation)
        call run_test('product_matches_matrix_product', test_product_matches_matrix_product)
        call run_test('conjugate_is_inverse', test_conjugate_is_inverse)
        call run_test('rotate_vector', test_rotate_vector)
        call run_test('rotation_vector_round_trip', test_rotation_vector_round_trip)
        call run_test('normalize', test_normalize)
    end subroutine run_all_tests

    ! Angle of sample i: uniform in [0, pi], within 1e-8 of 0, within 1e-8 of pi, exactly pi.
    function sample_angle(i) result(angle)
        integer, intent(in) :: i
        real(rk) :: angle, u
        call random_number(u)
        select case (mod(i, 4))
        case (0)
            angle = pi * u
        case (1)
            angle = 1.0e-8_rk * u
        case (2)
            angle = pi - 1.0e-8_rk * u
        case default
            angle = pi
        end select
    end function sample_angle

    function random_quaternion() result(q)
        real(rk) :: q(4)
        q = quaternion_from_rotation_vector(sample_angle(0) * random_unit_vector())
    end function random_quaternion

    subroutine test_matrix_round_trip()
        real(rk) :: psi(3), a(3, 3), q(4), cosine
        integer :: i
        do i = 1, 1000
            psi = sample_angle(i) * random_unit_vector()
            a = exp_so3(psi)
            q = quaternion_from_matrix(a)
            CHECK_CLOSE(norm2(q), 1.0_rk, 4.0e-15_rk, 0.0_rk, 'unit quaternion')
            CHECK_TRUE(q(1) >= 0.0_rk, 'q0 >= 0')
            CHECK_CLOSE(quaternion_to_matrix(q), a, 4.0e-15_rk, 0.0_rk, 'A(q(A)) = A')
            cosine = abs(dot_product(q, quaternion_from_rotation_vector(psi)))
            CHECK_CLOSE(cosine, 1.0_rk, 4.0e-15_rk, 0.0_rk, 'q(Exp(psi)) = +/- q(psi)')
        end do
    end subroutine test_matrix_round_trip

    ! Half turns about e_x, e_y, e_z and a generic rotation select each of the four pivots;
    ! the expected quaternions are known exactly.
    subroutine test_shepperd_pivots()
        real(rk) :: a(3, 3), q(4), expected(4), axis(3)
        integer :: i
        do i = 1, 3
            a = -identity
            a(i, i) = 1.0_rk
            q = quaternion_from_matrix(a)
            expected = 0.0_rk
            expected(i + 1) = 1.0_rk
            CHECK_CLOSE(abs(q), expected, 4.0e-15_rk, 0.0_rk, 'half turn about e_i')
        end do
        axis = [1.0_rk, 1.0_rk, 1.0_rk] / sqrt(3.0_rk)
        a = exp_so3(2.0_rk * pi / 3.0_rk * axis)
        CHECK_CLOSE(a(:, 1), identity(:, 2), 4.0e-15_rk, 0.0_rk, 'third turn about (1 1 1)')
        q = quaternion_from_matrix(a)
        expected = 0.5_rk
        CHECK_CLOSE(q, expected, 4.0e-15_rk, 0.0_rk, 'third turn about (1 1 1)')
        CHECK_CLOSE(quaternion_from_matrix(identity), unit_q, 0.0_rk, 0.0_rk, 'identity')
    end subroutine test_shepperd_pivots

    subroutine test_to_matrix_is_rotation()
        real(rk) :: q(4), a(3, 3), psi(3)
        integer :: i
        do i = 1, 200
            psi = sample_angle(i) * random_unit_vector()
            q = quaternion_from_rotation_vector(psi)
            a = quaternion_to_matrix(q)
            CHECK_CLOSE(matmul(transpose(a), a), identity, 4.0e-15_rk, 0.0_rk, 'A^T A = 1')
            CHECK_CLOSE(a, exp_so3(psi), 4.0e-15_rk, 0.0_rk, 'A(q(psi)) = Exp(psi)')
            CHECK_CLOSE(quaternion_to_matrix(-q), a, 0.0_rk, 0.0_rk, 'A(-q) = A(q)')
        end do
    end subroutine test_to_matrix_is_rotation

    subroutine test_product_matches_matrix_product()
        real(rk) :: p(4), q(4), pq(4), expected(3, 3)
        integer :: i
        do i = 1, 200
            p = random_quaternion()
            q = random_quaternion()
            pq = quaternion_product(p, q)
            expected = matmul(quaternion_to_matrix(p), quaternion_to_matrix(q))
            CHECK_CLOSE(quaternion_to_matrix(pq), expected, 4.0e-15_rk, 0.0_rk, 'A(pq) = A(p)A(q)')
            CHECK_CLOSE(norm2(pq), 1.0_rk, 4.0e-15_rk, 0.0_rk, '|pq| = 1')
            CHECK_CLOSE(quaternion_product(unit_q, q), q, 0.0_rk, 0.0_rk, '1 q = q')
        end do
    end subroutine test_product_matches_matrix_product

    subroutine test_conjugate_is_inverse()
        real(rk) :: q(4), q_conj(4), a(3, 3)
        integer :: i
        do i = 1, 200
            q = random_quaternion()
            q_conj = quaternion_conjugate(q)
            CHECK_CLOSE(quaternion_product(q, q_conj), unit_q, 4.0e-15_rk, 0.0_rk, 'q q* = 1')
            a = transpose(quaternion_to_matrix(q))
            CHECK_CLOSE(quaternion_to_matrix(q_conj), a, 4.0e-15_rk, 0.0_rk, 'A(q*) = A(q)^T')
        end do
    end subroutine test_conjugate_is_inverse

    subroutine test_rotate_vector()
        real(rk) :: q(4), x(3), y(3)
        integer :: i
        do i = 1, 200
            q = random_quaternion()
            call random_number(x)
            x = 2.0_rk * x - 1.0_rk
            y = quaternion_rotate(q, x)
            CHECK_CLOSE(y, matmul(quaternion_to_matrix(q), x), 4.0e-15_rk, 0.0_rk, 'q x = A(q) x')
            CHECK_CLOSE(norm2(y), norm2(x), 4.0e-15_rk, 0.0_rk, '|q x| = |x|')
        end do
    end subroutine test_rotate_vector

    subroutine test_rotation_vector_round_trip()
        real(rk) :: psi(3), q(4), psi_back(3), angle, error
        integer :: i
        do i = 1, 1000
            angle = sample_angle(i)
            psi = angle * random_unit_vector()
            q = quaternion_from_rotation_vector(psi)
            CHECK_CLOSE(norm2(q), 1.0_rk, 4.0e-15_rk, 0.0_rk, 'unit quaternion')
            psi_back = quaternion_to_rotation_vector(q)
            if (pi - angle > 1.0e-13_rk) then
                CHECK_CLOSE(psi_back, psi, 1.0e-300_rk, 2.0e-15_rk, 'psi(q(psi)) = psi')
            else
                error = min(norm2(psi_back - psi), norm2(psi_back + psi))
                CHECK_TRUE(error < 4.0e-15_rk, 'psi(q(psi)) = +/- psi at pi')
            end if
            psi_back = quaternion_to_rotation_vector(-q)
            CHECK_CLOSE(exp_so3(psi_back), exp_so3(psi), 4.0e-15_rk, 0.0_rk, 'psi(-q) ~ psi(q)')
        end do
        ! Beyond pi the principal vector is the complement (methods §5.5).
        psi = 1.5_rk * pi * [0.0_rk, 0.0_rk, 1.0_rk]
        q = quaternion_from_rotation_vector(psi)
        CHECK_TRUE(q(1) < 0.0_rk, 'q0 < 0 beyond pi')
        psi_back = quaternion_to_rotation_vector(q)
        CHECK_CLOSE(psi_back(3), -0.5_rk * pi, 4.0e-15_rk, 0.0_rk, 'principal vector beyond pi')
    end subroutine test_rotation_vector_round_trip

    subroutine test_normalize()
        real(rk) :: q(4), p(4), a(3, 3)
        integer :: i
        do i = 1, 100
            q = random_quaternion()
            p = 3.7_rk * q
            CHECK_CLOSE(quaternion_normalize(p), q, 4.0e-15_rk, 0.0_rk, 'normalize(3.7 q) = q')
            a = quaternion_to_matrix(q)
            CHECK_CLOSE(quaternion_to_matrix(p), a, 4.0e-15_rk, 0.0_rk, 'A(P) of a non-unit P')
            p = q + [1.0e-3_rk, -2.0e-3_rk, 0.5e-3_rk, 1.0e-3_rk]
            CHECK_CLOSE(norm2(quaternion_normalize(p)), 1.0_rk, 4.0e-15_rk, 0.0_rk, '|q| = 1')
        end do
    end subroutine test_normalize

end module rs_test_math_quaternion

program test_quaternion
    use rs_test_math_quaternion, only: run_all_tests
    use rs_test_assert, only: finish_tests
    implicit none
    call run_all_tests()
    call finish_tests()
end program test_quaternion
