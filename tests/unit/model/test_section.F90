#include "rs_assert.h"
!> Unit tests of rs_model_section: circle, tube and rectangle properties against the hand
!> formulas (A, I1 about d1, I2 about d2, polar = I1 + I2), and Saint-Venant's torsion constant
!> of rectangles against Timoshenko & Goodier's table (beta in J = beta a b^3, a the long side),
!> the square's 0.140577 a^4, the thin-strip limit a b^3 / 3 and width/height symmetry.
module rs_test_model_section
    use rs_core_kinds, only: rk, pi
    use rs_test_assert, only: run_test, assert_true, assert_close
    use rs_model_section, only: section_properties_t, circle_section, tube_section, &
        rectangle_section
    implicit none
    private

    public :: run_all_tests

    real(rk), parameter :: tight = 1.0e-14_rk

contains

    !> Run every test of this file through rs_test_assert.
    subroutine run_all_tests()
        call run_test('circle', test_circle)
        call run_test('tube', test_tube)
        call run_test('tube_without_hole_is_circle', test_tube_without_hole_is_circle)
        call run_test('thin_tube', test_thin_tube)
        call run_test('rectangle_moments', test_rectangle_moments)
        call run_test('square_saint_venant', test_square_saint_venant)
        call run_test('rectangle_saint_venant_table', test_rectangle_saint_venant_table)
        call run_test('rectangle_saint_venant_symmetric', test_rectangle_saint_venant_symmetric)
        call run_test('thin_strip_limit', test_thin_strip_limit)
        call run_test('saint_venant_below_polar', test_saint_venant_below_polar)
    end subroutine run_all_tests

    ! A = pi r^2, I1 = I2 = pi r^4 / 4, J = pi r^4 / 2 (Saint-Venant equals polar for a circle).
    subroutine test_circle()
        type(section_properties_t) :: s
        real(rk) :: r
        r = 0.01_rk
        s = circle_section(r)
        CHECK_CLOSE(s%area, 3.14159265358979e-4_rk, 0.0_rk, 1.0e-13_rk, 'area of r = 0.01')
        CHECK_CLOSE(s%i1, 7.85398163397448e-9_rk, 0.0_rk, 1.0e-13_rk, 'I1 of r = 0.01')
        CHECK_CLOSE(s%i2, s%i1, 0.0_rk, 0.0_rk, 'I2 = I1')
        CHECK_CLOSE(s%polar, 1.570796326794897e-8_rk, 0.0_rk, 1.0e-13_rk, 'polar of r = 0.01')
        CHECK_CLOSE(s%saint_venant, s%polar, 0.0_rk, tight, 'Saint-Venant = polar')
        r = 2.5_rk
        s = circle_section(r)
        CHECK_CLOSE(s%area, pi * 6.25_rk, 0.0_rk, tight, 'area of r = 2.5')
        CHECK_CLOSE(s%i1, pi * 39.0625_rk / 4.0_rk, 0.0_rk, tight, 'I1 of r = 2.5')
        CHECK_CLOSE(s%polar, pi * 39.0625_rk / 2.0_rk, 0.0_rk, tight, 'polar of r = 2.5')
    end subroutine test_circle

    ! A = pi (R^2 - r^2), I = pi (R^4 - r^4) / 4, J = 2 I.
    subroutine test_tube()
        type(section_properties_t) :: s
        s = tube_section(0.05_rk, 0.04_rk)
        CHECK_CLOSE(s%area, pi * 9.0e-4_rk, 0.0_rk, tight, 'area')
        CHECK_CLOSE(s%i1, pi * 3.69e-6_rk / 4.0_rk, 0.0_rk, 1.0e-13_rk, 'I1')
        CHECK_CLOSE(s%i2, s%i1, 0.0_rk, 0.0_rk, 'I2 = I1')
        CHECK_CLOSE(s%polar, pi * 3.69e-6_rk / 2.0_rk, 0.0_rk, 1.0e-13_rk, 'polar')
        CHECK_CLOSE(s%saint_venant, s%polar, 0.0_rk, tight, 'Saint-Venant = polar')
    end subroutine test_tube

    subroutine test_tube_without_hole_is_circle()
        type(section_properties_t) :: t, c
        t = tube_section(0.3_rk, 0.0_rk)
        c = circle_section(0.3_rk)
        CHECK_CLOSE(t%area, c%area, 0.0_rk, 0.0_rk, 'area')
        CHECK_CLOSE(t%i1, c%i1, 0.0_rk, 0.0_rk, 'I1')
        CHECK_CLOSE(t%polar, c%polar, 0.0_rk, 0.0_rk, 'polar')
    end subroutine test_tube_without_hole_is_circle

    ! Thin wall (mean radius R, thickness t << R): A ~ 2 pi R t, J ~ 2 pi R^3 t, to O((t/R)^2).
    subroutine test_thin_tube()
        type(section_properties_t) :: s
        real(rk) :: rm, t
        rm = 1.0_rk
        t = 1.0e-3_rk
        s = tube_section(rm + t / 2.0_rk, rm - t / 2.0_rk)
        CHECK_CLOSE(s%area, 2.0_rk * pi * rm * t, 0.0_rk, 1.0e-10_rk, 'area (exact for a ring)')
        CHECK_CLOSE(s%polar, 2.0_rk * pi * rm**3 * t, 0.0_rk, 1.0e-6_rk, 'thin-wall J')
    end subroutine test_thin_tube

    ! Width along d1, height along d2: I1 (about d1) = w h^3 / 12, I2 = h w^3 / 12.
    subroutine test_rectangle_moments()
        type(section_properties_t) :: s
        s = rectangle_section(0.2_rk, 0.05_rk)
        CHECK_CLOSE(s%area, 0.01_rk, 0.0_rk, tight, 'area 0.2 x 0.05')
        CHECK_CLOSE(s%i1, 0.2_rk * 0.05_rk**3 / 12.0_rk, 0.0_rk, tight, 'I1 = w h^3 / 12')
        CHECK_CLOSE(s%i1, 2.0833333333333333e-6_rk, 0.0_rk, 1.0e-14_rk, 'I1 by hand')
        CHECK_CLOSE(s%i2, 3.3333333333333333e-5_rk, 0.0_rk, 1.0e-14_rk, 'I2 = h w^3 / 12 by hand')
        CHECK_TRUE(s%i2 > s%i1, 'the wide side along d1 is stiff about d2')
        CHECK_CLOSE(s%polar, s%i1 + s%i2, 0.0_rk, tight, 'polar = I1 + I2')
        s = rectangle_section(3.0_rk, 3.0_rk)
        CHECK_CLOSE(s%i1, 6.75_rk, 0.0_rk, tight, 'square 3 x 3: 81 / 12')
        CHECK_CLOSE(s%i2, 6.75_rk, 0.0_rk, tight, 'square: I2 = I1')
    end subroutine test_rectangle_moments

    ! Square a x a: J = 0.140577 a^4 (Timoshenko & Goodier §109; the table rounds to 0.141).
    subroutine test_square_saint_venant()
        type(section_properties_t) :: s
        s = rectangle_section(1.0_rk, 1.0_rk)
        CHECK_CLOSE(s%saint_venant, 0.140577_rk, 0.0_rk, 1.0e-5_rk, 'unit square')
        s = rectangle_section(0.02_rk, 0.02_rk)
        CHECK_CLOSE(s%saint_venant, 0.140577_rk * 0.02_rk**4, 0.0_rk, 1.0e-5_rk, 'square of 2 cm')
        CHECK_CLOSE(s%saint_venant / s%polar, 0.843462_rk, 0.0_rk, 1.0e-5_rk, 'J / Ip = 6 beta')
    end subroutine test_square_saint_venant

    ! J = beta a b^3 with a the long side: beta = 0.141, 0.229, 0.263, 0.281, 0.312 for
    ! a / b = 1, 2, 3, 4, 10 (Timoshenko & Goodier's table, three decimals: +- 5e-4).
    subroutine test_rectangle_saint_venant_table()
        real(rk), parameter :: ratio(5) = [1.0_rk, 2.0_rk, 3.0_rk, 4.0_rk, 10.0_rk]
        real(rk), parameter :: beta(5) = [0.141_rk, 0.229_rk, 0.263_rk, 0.281_rk, 0.312_rk]
        type(section_properties_t) :: s
        real(rk) :: a, b
        integer :: i
        b = 0.01_rk
        do i = 1, size(ratio)
            a = ratio(i) * b
            s = rectangle_section(a, b)
            CHECK_CLOSE(s%saint_venant / (a * b**3), beta(i), 5.0e-4_rk, 0.0_rk, 'table beta')
        end do
    end subroutine test_rectangle_saint_venant_table

    subroutine test_rectangle_saint_venant_symmetric()
        type(section_properties_t) :: s, t
        s = rectangle_section(0.3_rk, 0.07_rk)
        t = rectangle_section(0.07_rk, 0.3_rk)
        CHECK_CLOSE(t%saint_venant, s%saint_venant, 0.0_rk, 0.0_rk, 'J(w, h) = J(h, w)')
        CHECK_CLOSE(t%i1, s%i2, 0.0_rk, tight, 'I1 and I2 swap')
        CHECK_CLOSE(t%i2, s%i1, 0.0_rk, tight, 'I2 and I1 swap')
        CHECK_CLOSE(t%area, s%area, 0.0_rk, 0.0_rk, 'area')
    end subroutine test_rectangle_saint_venant_symmetric

    ! a / b -> infinity: beta -> 1/3 - 0.21 b / a (Roark; the series gives 0.21008296: 64 / pi^5
    ! times sum over odd n of 1 / n^5 = 1.0045238), exponentially accurate for a >> b.
    subroutine test_thin_strip_limit()
        real(rk), parameter :: c = 0.21008296_rk
        type(section_properties_t) :: s
        real(rk) :: a, b, beta
        b = 1.0e-3_rk
        a = 1.0_rk
        s = rectangle_section(a, b)
        beta = s%saint_venant / (a * b**3)
        CHECK_CLOSE(beta, 1.0_rk / 3.0_rk - c * b / a, 1.0e-9_rk, 0.0_rk, 'a / b = 1000')
        CHECK_TRUE(beta < 1.0_rk / 3.0_rk, 'below the 1/3 limit')
        a = 20.0_rk * b
        s = rectangle_section(a, b)
        beta = s%saint_venant / (a * b**3)
        CHECK_CLOSE(beta, 1.0_rk / 3.0_rk - c / 20.0_rk, 1.0e-8_rk, 0.0_rk, 'a / b = 20')
    end subroutine test_thin_strip_limit

    ! Saint-Venant's constant of a non-circular section is below the polar moment.
    subroutine test_saint_venant_below_polar()
        type(section_properties_t) :: s
        real(rk) :: h
        integer :: i
        do i = 1, 6
            h = 0.1_rk * real(i, rk)
            s = rectangle_section(0.1_rk, h)
            CHECK_TRUE(s%saint_venant < s%polar, 'J < I1 + I2')
            CHECK_TRUE(s%saint_venant > 0.0_rk, 'J > 0')
        end do
    end subroutine test_saint_venant_below_polar

end module rs_test_model_section

!> Test program: runs the tests of rs_test_model_section; exits non-zero if any failed.
program test_section
    use rs_test_model_section, only: run_all_tests
    use rs_test_assert, only: finish_tests
    implicit none
    call run_all_tests()
    call finish_tests()
end program test_section
