#include "rs_assert.h"
!> Unit tests of rs_math_lagrange: partition of unity, derivatives summing to zero, the
!> Kronecker property, exact reproduction of degree-p polynomials and the invalid-degree contract.
module rs_test_math_lagrange
    use rs_core_kinds, only: rk
    use rs_test_assert, only: run_test, assert_true, assert_close
    use rs_math_lagrange, only: lagrange_nodes, lagrange_shape, max_lagrange_degree
    implicit none
    private

    public :: run_all_tests

    integer, parameter :: n_samples = 41

contains

    !> Run every test of this file through rs_test_assert.
    subroutine run_all_tests()
        call run_test('partition_of_unity', test_partition_of_unity)
        call run_test('kronecker_at_nodes', test_kronecker_at_nodes)
        call run_test('polynomial_reproduction', test_polynomial_reproduction)
        call run_test('derivatives_fd', test_derivatives_fd)
        call run_test('invalid_degree', test_invalid_degree)
    end subroutine run_all_tests

    ! Sample point j of n_samples equidistant points on [-1, 1].
    function sample(j) result(xi)
        integer, intent(in) :: j
        real(rk) :: xi
        xi = -1.0_rk + 2.0_rk * real(j - 1, rk) / real(n_samples - 1, rk)
    end function sample

    subroutine test_partition_of_unity()
        real(rk) :: n(max_lagrange_degree + 1), dn(max_lagrange_degree + 1)
        logical :: ok
        integer :: p, j
        do p = 1, max_lagrange_degree
            do j = 1, n_samples
                call lagrange_shape(p, sample(j), n(1:p + 1), dn(1:p + 1), ok)
                CHECK_TRUE(ok, 'valid degree')
                CHECK_CLOSE(sum(n(1:p + 1)), 1.0_rk, 1.0e-15_rk, 0.0_rk, 'sum N_i = 1')
                CHECK_CLOSE(sum(dn(1:p + 1)), 0.0_rk, 1.0e-15_rk, 0.0_rk, 'sum dN_i = 0')
            end do
        end do
    end subroutine test_partition_of_unity

    subroutine test_kronecker_at_nodes()
        real(rk) :: nodes(max_lagrange_degree + 1), n(max_lagrange_degree + 1)
        real(rk) :: dn(max_lagrange_degree + 1), delta(max_lagrange_degree + 1)
        logical :: ok
        integer :: p, i
        do p = 1, max_lagrange_degree
            call lagrange_nodes(p, nodes(1:p + 1), ok)
            CHECK_TRUE(ok, 'valid degree')
            CHECK_CLOSE(nodes(1), -1.0_rk, 0.0_rk, 0.0_rk, 'first node at -1')
            CHECK_CLOSE(nodes(p + 1), 1.0_rk, 0.0_rk, 0.0_rk, 'last node at 1')
            do i = 1, p + 1
                call lagrange_shape(p, nodes(i), n(1:p + 1), dn(1:p + 1), ok)
                delta(1:p + 1) = 0.0_rk
                delta(i) = 1.0_rk
                CHECK_CLOSE(n(1:p + 1), delta(1:p + 1), 0.0_rk, 0.0_rk, 'N_i(node_j) = delta_ij')
            end do
        end do
    end subroutine test_kronecker_at_nodes

    ! sum_i N_i(xi) f(node_i) = f(xi) and sum_i dN_i(xi) f(node_i) = f'(xi) for f = xi^k, k <= p;
    ! for k = p + 1 the interpolant differs (the degree is exactly p).
    subroutine test_polynomial_reproduction()
        real(rk) :: nodes(max_lagrange_degree + 1), n(max_lagrange_degree + 1)
        real(rk) :: dn(max_lagrange_degree + 1), xi, f(max_lagrange_degree + 1)
        real(rk) :: value, slope, exact_slope, max_error
        logical :: ok
        integer :: p, j, k
        do p = 1, max_lagrange_degree
            call lagrange_nodes(p, nodes(1:p + 1), ok)
            do k = 0, p + 1
                f(1:p + 1) = nodes(1:p + 1)**k
                max_error = 0.0_rk
                do j = 1, n_samples
                    xi = sample(j)
                    call lagrange_shape(p, xi, n(1:p + 1), dn(1:p + 1), ok)
                    value = dot_product(n(1:p + 1), f(1:p + 1))
                    slope = dot_product(dn(1:p + 1), f(1:p + 1))
                    if (k <= p) then
                        CHECK_CLOSE(value, xi**k, 1.0e-15_rk, 0.0_rk, 'reproduces xi^k')
                        exact_slope = real(k, rk) * xi**max(k - 1, 0)
                        CHECK_CLOSE(slope, exact_slope, 1.0e-15_rk, 0.0_rk, 'slope of xi^k')
                    end if
                    max_error = max(max_error, abs(value - xi**k))
                end do
                if (k == p + 1) then
                    CHECK_TRUE(max_error > 0.1_rk, 'does not reproduce xi^(p+1)')
                end if
            end do
        end do
    end subroutine test_polynomial_reproduction

    subroutine test_derivatives_fd()
        real(rk), parameter :: h = 1.0e-6_rk
        real(rk) :: n_plus(max_lagrange_degree + 1), n_minus(max_lagrange_degree + 1)
        real(rk) :: dn(max_lagrange_degree + 1), scratch(max_lagrange_degree + 1), xi
        logical :: ok
        integer :: p, j
        do p = 1, max_lagrange_degree
            do j = 1, n_samples
                xi = sample(j)
                call lagrange_shape(p, xi + h, n_plus(1:p + 1), scratch(1:p + 1), ok)
                call lagrange_shape(p, xi - h, n_minus(1:p + 1), scratch(1:p + 1), ok)
                call lagrange_shape(p, xi, scratch(1:p + 1), dn(1:p + 1), ok)
                scratch(1:p + 1) = (n_plus(1:p + 1) - n_minus(1:p + 1)) / (2.0_rk * h)
                CHECK_CLOSE(dn(1:p + 1), scratch(1:p + 1), 1.0e-9_rk, 0.0_rk, 'dN/dxi vs FD')
            end do
        end do
    end subroutine test_derivatives_fd

    subroutine test_invalid_degree()
        integer, parameter :: degrees(3) = [0, -1, max_lagrange_degree + 1]
        real(rk) :: n(max_lagrange_degree + 2), dn(max_lagrange_degree + 2)
        logical :: ok
        integer :: j, p
        do j = 1, size(degrees)
            p = degrees(j)
            call lagrange_nodes(p, n(1:max(p + 1, 0)), ok)
            CHECK_TRUE(.not. ok, 'invalid degree rejected by lagrange_nodes')
            call lagrange_shape(p, 0.3_rk, n(1:max(p + 1, 0)), dn(1:max(p + 1, 0)), ok)
            CHECK_TRUE(.not. ok, 'invalid degree rejected by lagrange_shape')
        end do
    end subroutine test_invalid_degree

end module rs_test_math_lagrange

program test_lagrange
    use rs_test_math_lagrange, only: run_all_tests
    use rs_test_assert, only: finish_tests
    implicit none
    call run_all_tests()
    call finish_tests()
end program test_lagrange
