#include "rs_assert.h"
!> Unit tests of rs_math_quadrature: exactness up to degree 2n - 1, points are the Legendre roots,
!> weights sum to 2, the mapping to [a, b], and the invalid-count contract.
module rs_test_math_quadrature
    use rs_core_kinds, only: rk
    use rs_test_assert, only: run_test, assert_true, assert_close
    use rs_math_quadrature, only: gauss_legendre, gauss_legendre_interval, max_gauss_points
    implicit none
    private

    public :: run_all_tests

contains

    !> Run every test of this file through rs_test_assert.
    subroutine run_all_tests()
        call run_test('weights_sum_to_two', test_weights_sum_to_two)
        call run_test('polynomial_exactness', test_polynomial_exactness)
        call run_test('points_are_legendre_roots', test_points_are_legendre_roots)
        call run_test('interval_mapping', test_interval_mapping)
        call run_test('invalid_count', test_invalid_count)
    end subroutine run_all_tests

    subroutine test_weights_sum_to_two()
        real(rk) :: x(max_gauss_points), w(max_gauss_points)
        logical :: ok
        integer :: n
        do n = 1, max_gauss_points
            call gauss_legendre(n, x(1:n), w(1:n), ok)
            CHECK_TRUE(ok, 'valid point count')
            CHECK_CLOSE(sum(w(1:n)), 2.0_rk, 1.0e-15_rk, 0.0_rk, 'sum of weights')
            CHECK_TRUE(all(w(1:n) > 0.0_rk), 'positive weights')
        end do
    end subroutine test_weights_sum_to_two

    ! Exact for x^k, k <= 2n - 1, and not exact for x^(2n): the degree is exactly 2n - 1.
    subroutine test_polynomial_exactness()
        real(rk) :: x(max_gauss_points), w(max_gauss_points), exact, rule
        logical :: ok
        integer :: n, k
        do n = 1, max_gauss_points
            call gauss_legendre(n, x(1:n), w(1:n), ok)
            do k = 0, 2 * n
                exact = merge(2.0_rk / real(k + 1, rk), 0.0_rk, mod(k, 2) == 0)
                rule = sum(w(1:n) * x(1:n)**k)
                if (k <= 2 * n - 1) then
                    CHECK_CLOSE(rule, exact, 1.0e-15_rk, 0.0_rk, 'exact for degree <= 2n - 1')
                else
                    CHECK_TRUE(abs(rule - exact) > 1.0e-4_rk, 'not exact for degree 2n')
                end if
            end do
        end do
    end subroutine test_polynomial_exactness

    ! P_n(x_i) = 0 and w_i = 2 / ((1 - x_i^2) P_n'(x_i)^2), from the three-term recurrence.
    subroutine test_points_are_legendre_roots()
        real(rk) :: x(max_gauss_points), w(max_gauss_points), p, dp
        logical :: ok
        integer :: n, i
        do n = 1, max_gauss_points
            call gauss_legendre(n, x(1:n), w(1:n), ok)
            CHECK_CLOSE(x(1:n), -x(n:1:-1), 0.0_rk, 0.0_rk, 'symmetric points')
            CHECK_CLOSE(w(1:n), w(n:1:-1), 0.0_rk, 0.0_rk, 'symmetric weights')
            CHECK_TRUE(all(x(2:n) > x(1:n - 1)), 'ascending points')
            do i = 1, n
                call legendre(n, x(i), p, dp)
                CHECK_CLOSE(p, 0.0_rk, 1.0e-15_rk, 0.0_rk, 'P_n(x_i) = 0')
                CHECK_CLOSE(w(i), 2.0_rk / ((1.0_rk - x(i)**2) * dp**2), 0.0_rk, 2.0e-15_rk, 'w_i')
            end do
        end do
    end subroutine test_points_are_legendre_roots

    ! Legendre polynomial P_n and its derivative at x (Bonnet's recurrence).
    subroutine legendre(n, x, p, dp)
        integer, intent(in) :: n
        real(rk), intent(in) :: x
        real(rk), intent(out) :: p, dp
        real(rk) :: p_prev, p_next
        integer :: k
        p_prev = 1.0_rk
        p = x
        do k = 1, n - 1
            p_next = (real(2 * k + 1, rk) * x * p - real(k, rk) * p_prev) / real(k + 1, rk)
            p_prev = p
            p = p_next
        end do
        dp = real(n, rk) * (x * p - p_prev) / (x**2 - 1.0_rk)
    end subroutine legendre

    subroutine test_interval_mapping()
        real(rk), parameter :: a = -0.3_rk, b = 2.1_rk
        real(rk) :: x(max_gauss_points), w(max_gauss_points), exact, rule
        logical :: ok
        integer :: n, k
        do n = 1, max_gauss_points
            call gauss_legendre_interval(n, a, b, x(1:n), w(1:n), ok)
            CHECK_TRUE(ok, 'valid point count')
            CHECK_TRUE(all(x(1:n) > a .and. x(1:n) < b), 'points inside the interval')
            do k = 0, 2 * n - 1
                exact = (b**(k + 1) - a**(k + 1)) / real(k + 1, rk)
                rule = sum(w(1:n) * x(1:n)**k)
                CHECK_CLOSE(rule, exact, 1.0e-15_rk, 2.0e-15_rk, 'exact on the interval')
            end do
        end do
    end subroutine test_interval_mapping

    subroutine test_invalid_count()
        integer, parameter :: counts(3) = [0, -1, max_gauss_points + 1]
        real(rk) :: x(max_gauss_points + 1), w(max_gauss_points + 1)
        logical :: ok
        integer :: j, n
        do j = 1, size(counts)
            n = counts(j)
            x = 1.0_rk
            w = 1.0_rk
            call gauss_legendre(n, x, w, ok)
            CHECK_TRUE(.not. ok, 'invalid count rejected')
            call gauss_legendre_interval(n, 0.0_rk, 1.0_rk, x, w, ok)
            CHECK_TRUE(.not. ok, 'invalid count rejected (interval)')
        end do
        call gauss_legendre(max_gauss_points + 1, x, w, ok)
        CHECK_TRUE(all(x == 0.0_rk) .and. all(w == 0.0_rk), 'zero arrays on failure')
    end subroutine test_invalid_count

end module rs_test_math_quadrature

program test_quadrature
    use rs_test_math_quadrature, only: run_all_tests
    use rs_test_assert, only: finish_tests
    implicit none
    call run_all_tests()
    call finish_tests()
end program test_quadrature
