#include "rs_assert.h"
!> Unit tests of rs_formulations_generalized_alpha (Jansen, Whiting & Hulbert 2000; methods/
!> se3_petrov_galerkin.md §7.3) on linear test problems, where the step is solved exactly:
!> - the coefficients of rho_inf = 0.9 are the methods document's (alpha_m = 0.552632, alpha_f =
!>   gamma = 0.526316), and rho_inf = 1 is the midpoint rule (all 1/2);
!> - y' = lambda y: the spectral radius of the step at h lambda = -1e12 is rho_inf (the
!>   damping at infinite frequency the user chooses), and 1 for the midpoint rule;
!> - the harmonic oscillator x'' = -x as y = (x, v), y' = (v, -x) with the consistent y'_0:
!>   the error at t = 1 falls at order 2 (4 halvings of h) for rho_inf = 0, 0.5, 0.9.
!> The step problem of a linear F is affine in y_{n+1}: its matrix is built from the module's
!> stage procedures at y_{n+1} = 0 and the unit vectors, so the test solves the scheme as the
!> module defines it.
module rs_test_formulations_generalized_alpha
    use rs_core_kinds, only: rk
    use rs_test_assert, only: run_test, assert_true, assert_close
    use rs_formulations_generalized_alpha, only: generalized_alpha_t, generalized_alpha, &
        midpoint_scheme
    implicit none
    private

    public :: run_all_tests

contains

    subroutine run_all_tests()
        call run_test('coefficients', test_coefficients)
        call run_test('damping_at_infinity', test_damping_at_infinity)
        call run_test('oscillator_order', test_oscillator_order)
    end subroutine run_all_tests

    subroutine test_coefficients()
        type(generalized_alpha_t) :: s
        logical :: halves
        s = generalized_alpha(0.9_rk)
        CHECK_CLOSE(s%alpha_m, 0.552632_rk, 1.0e-6_rk, 0.0_rk, 'alpha_m (methods §7.3, 6 digits)')
        CHECK_CLOSE(s%alpha_f, 0.526316_rk, 1.0e-6_rk, 0.0_rk, 'alpha_f (methods §7.3, 6 digits)')
        CHECK_CLOSE(s%gamma, 0.526316_rk, 1.0e-6_rk, 0.0_rk, 'gamma (methods §7.3, 6 digits)')
        CHECK_TRUE(s%history, 'generalized-alpha carries y''_n')
        s = generalized_alpha(1.0_rk)
        halves = s%alpha_m == 0.5_rk .and. s%alpha_f == 0.5_rk .and. s%gamma == 0.5_rk
        CHECK_TRUE(halves, 'rho_inf = 1: alpha_m = alpha_f = gamma = 1/2 (the midpoint rule)')
        s = midpoint_scheme()
        halves = s%alpha_m == 0.5_rk .and. s%alpha_f == 0.5_rk .and. s%gamma == 0.5_rk
        CHECK_TRUE(halves .and. .not. s%history, 'the midpoint scheme: 1/2, no history')
    end subroutine test_coefficients

    !> y' = lambda y with h lambda = -1e12: the 2 x 2 step map of (y, y') has spectral radius
    !> rho_inf (JWH 2000's parameter). Its double root -rho_inf at infinity splits by about
    !> (h |lambda|)^(-1/2) = 1e-6 here, hence the tolerance 1e-5.
    subroutine test_damping_at_infinity()
        real(rk), parameter :: rhos(4) = [0.0_rk, 0.5_rk, 0.9_rk, 1.0_rk]
        real(rk) :: a(2, 2), radius
        integer :: i
        character(len=64) :: label
        do i = 1, size(rhos)
            a = scalar_step_map(generalized_alpha(rhos(i)), -1.0e12_rk, 1.0_rk)
            radius = spectral_radius_2x2(a)
            write(label, '(a,f4.2)') 'spectral radius at h lambda = -1e12, rho_inf = ', rhos(i)
            CHECK_CLOSE(radius, rhos(i), 1.0e-5_rk, 0.0_rk, trim(label))
        end do
    end subroutine test_damping_at_infinity

    !> x'' = -x from (x, v) = (1, 0) to t = 1 with h = 1/20 .. 1/320 (asymptotic: at h = 1/10
    !> -> 1/20 rho_inf = 0 gives 1.94): error orders 2 +- 0.05.
    subroutine test_oscillator_order()
        real(rk), parameter :: rhos(3) = [0.0_rk, 0.5_rk, 0.9_rk]
        real(rk) :: errors(5), order
        integer :: i, k
        character(len=80) :: label
        do i = 1, size(rhos)
            do k = 1, size(errors)
                errors(k) = oscillator_error(generalized_alpha(rhos(i)), 20 * 2**(k - 1))
            end do
            do k = 2, size(errors)
                order = log(errors(k - 1) / errors(k)) / log(2.0_rk)
                write(label, '(a,f4.2,a,i0,a,es9.2)') 'order, rho_inf = ', rhos(i), ', h = 1/', &
                    20 * 2**(k - 1), ', error ', errors(k)
                CHECK_CLOSE(order, 2.0_rk, 0.05_rk, 0.0_rk, trim(label))
            end do
        end do
    end subroutine test_oscillator_order

    !> The step map (y_n, y'_n) -> (y_{n+1}, y'_{n+1}) of y' = lambda y with step h.
    function scalar_step_map(s, lambda, h) result(a)
        type(generalized_alpha_t), intent(in) :: s
        real(rk), intent(in) :: lambda, h
        real(rk) :: a(2, 2)
        real(rk) :: y_n(1), rate_n(1), y_1(1), r0(1), r1(1)
        integer :: j
        do j = 1, 2
            y_n = merge(1.0_rk, 0.0_rk, j == 1)
            rate_n = merge(1.0_rk, 0.0_rk, j == 2)
            ! r(y_1) = y'_{n+alpha_m} - lambda y_{n+alpha_f}, affine in y_1.
            r0 = s%stage_rate(h, y_n, [0.0_rk], rate_n) - lambda * s%stage_value(y_n, [0.0_rk])
            r1 = s%stage_rate(h, y_n, [1.0_rk], rate_n) - lambda * s%stage_value(y_n, [1.0_rk])
            y_1 = -r0 / (r1 - r0)
            a(1, j) = y_1(1)
            a(2, j) = sum(s%end_rate(h, y_n, y_1, rate_n))
        end do
    end function scalar_step_map

    pure real(rk) function spectral_radius_2x2(a) result(radius)
        real(rk), intent(in) :: a(2, 2)
        real(rk) :: trace, det, disc
        trace = a(1, 1) + a(2, 2)
        det = a(1, 1) * a(2, 2) - a(1, 2) * a(2, 1)
        disc = 0.25_rk * trace**2 - det
        if (disc >= 0.0_rk) then
            radius = max(abs(0.5_rk * trace + sqrt(disc)), abs(0.5_rk * trace - sqrt(disc)))
        else
            radius = sqrt(det)
        end if
    end function spectral_radius_2x2

    !> |y(1) - (cos 1, -sin 1)| after n steps of x'' = -x, y'_0 = F(y_0).
    function oscillator_error(s, n) result(error)
        type(generalized_alpha_t), intent(in) :: s
        integer, intent(in) :: n
        real(rk) :: error
        real(rk) :: y(2), rate(2), y_1(2), r0(2), m(2, 2), e(2), h, det
        integer :: step, j
        h = 1.0_rk / real(n, rk)
        y = [1.0_rk, 0.0_rk]
        rate = oscillator(y)
        do step = 1, n
            r0 = s%stage_rate(h, y, [0.0_rk, 0.0_rk], rate) - &
                oscillator(s%stage_value(y, [0.0_rk, 0.0_rk]))
            do j = 1, 2
                e = 0.0_rk
                e(j) = 1.0_rk
                m(:, j) = s%stage_rate(h, y, e, rate) - oscillator(s%stage_value(y, e)) - r0
            end do
            det = m(1, 1) * m(2, 2) - m(1, 2) * m(2, 1)
            y_1 = -[m(2, 2) * r0(1) - m(1, 2) * r0(2), -m(2, 1) * r0(1) + m(1, 1) * r0(2)] / det
            rate = s%end_rate(h, y, y_1, rate)
            y = y_1
        end do
        error = norm2(y - [cos(1.0_rk), -sin(1.0_rk)])
    end function oscillator_error

    pure function oscillator(y) result(f)
        real(rk), intent(in) :: y(2)
        real(rk) :: f(2)
        f = [y(2), -y(1)]
    end function oscillator

end module rs_test_formulations_generalized_alpha

program test_formulations_generalized_alpha
    use rs_test_assert, only: finish_tests
    use rs_test_formulations_generalized_alpha, only: run_all_tests
    implicit none
    call run_all_tests()
    call finish_tests()
end program test_formulations_generalized_alpha
