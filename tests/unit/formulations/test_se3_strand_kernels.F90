#include "rs_assert.h"
!> Unit tests of rs_se3_strand_kernels (seed 004, methods/se3_strands.md §2.1, §2.3, §3.6), all
!> on random arguments:
!> - strand_ad against the explicit 6 x 6 matrix of methods §2.3, its antisymmetry
!>   ad_X Y = -ad_Y X and ad_X X = 0 (to round-off), and cross_matrix against the cross product;
!> - the compatibility condition dU/dt - dV/ds = ad_U V (methods §2.3, eq. 8) by central
!>   differences on smooth random SE(3) motions g(s, t), with U and V taken from the paper's own
!>   definitions (methods §2.1: u1 = d3'.d2, u2 = d1'.d3, u3 = d2'.d1, sigma_i = x'.d_i, and
!>   the same with dots for V) and checked against the standard body twists g^{-1} dg/ds and
!>   g^{-1} dg/dt with negated angular parts. This is the check of the paper's sign convention;
!> - strand_twist_of: (u3, u1, u2, s3, s1, s2) -> (s3, s1, s2, -u3, -u1, -u2);
!> - strand_march against a truncated Taylor series (scaled and squared) of the 4 x 4
!>   homogeneous exponential of h [[hat(kappa), sigma], [0, 0]], kappa = -u, and of the paper's
!>   placement update exp(h L) P with L written out as in eq. (1) (methods §3.6, eq. 16), for
!>   angles |h kappa| of 0, about 1e-9, up to 1 and about 3;
!> - the straight rod: U = (0, 0, 0, 1, 0, 0) moves x by h along d3 and keeps the directors;
!> - the written-out block kernels of the step's system equal, bit for bit, the expressions with
!>   strand_ad and hat they replaced (strand_ad_transpose_block, strand_ad_block), or those summed
!>   term by term from zero in column order, as the inlined 6 x 6 matmul of the Release build does
!>   (strand_ad_times, strand_cross; libgfortran's own matmul, called at -O0, may use FMA), so the
!>   step's results do not move; strand_row_residual against matmul to round-off;
!>   strand_row_to_csr against the CSR order; strand_row_has_nan finds a NaN at every position
!>   and takes an infinity for a number, as any(blocks /= blocks) did.
!>
!> A pose is (a, x) with a = [d3 d1 d2] (K to inertial components), as in the kernels.
module rs_test_se3_strand_kernels
    use, intrinsic :: iso_fortran_env, only: output_unit
    use, intrinsic :: ieee_arithmetic, only: ieee_value, ieee_quiet_nan, ieee_positive_inf
    use rs_core_kinds, only: rk
    use rs_test_random, only: set_random_seed, uniform, random_vector, random_unit_vector
    use rs_test_assert, only: run_test, assert_true, assert_close
    use rs_math_so3, only: hat, vee, exp_so3
    use rs_math_se3, only: exp_se3, pose_compose
    use rs_se3_strand_kernels, only: strand_ad, cross_matrix, strand_march, strand_twist_of, &
        strand_ad_transpose_block, strand_ad_block, strand_ad_times, strand_cross, &
        strand_row_residual, strand_row_to_csr, strand_row_has_nan
    implicit none
    private

    public :: run_all_tests

    real(rk), parameter :: eps = epsilon(1.0_rk)
    ! Random samples per test.
    integer, parameter :: n_samples = 40
    ! Steps of the inner (U, V from g) and outer (d/dt U, d/ds V) central differences, both
    ! with the fourth-order stencil: truncation about 1e-12, round-off about eps / h^2 ~ 1e-10.
    real(rk), parameter :: inner_step = 1.0e-3_rk, outer_step = 1.0e-3_rk
    ! Tolerance of the compatibility residual, relative to the largest of its three terms.
    real(rk), parameter :: compat_tol = 1.0e-6_rk
    ! Tolerance of strand_march against the Taylor exponential (rotation entries; positions
    ! relative to max(1, |x_next|)).
    real(rk), parameter :: march_tol = 1.0e-12_rk
    ! Directions of differentiation.
    integer, parameter :: along_s = 1, along_t = 2

    !> A smooth motion g(s, t) = Exp(theta_1(s, t)) Exp(theta_2(s, t)) with twists (v, omega)
    !> quadratic in (s, t): theta_k = c(:, 1, k) + s c(:, 2, k) + t c(:, 3, k) + s t c(:, 4, k)
    !> + s^2 c(:, 5, k) + t^2 c(:, 6, k).
    type :: motion_t
        real(rk) :: c(6, 6, 2) = 0.0_rk
    end type motion_t

contains

    !> Run every test of this file through rs_test_assert.
    subroutine run_all_tests()
        call set_random_seed(20250704, 7919)
        call run_test('ad_explicit_matrix', test_ad_explicit_matrix)
        call run_test('ad_antisymmetry', test_ad_antisymmetry)
        call run_test('cross_matrix', test_cross_matrix)
        call run_test('compatibility_eq8', test_compatibility)
        call run_test('march_exponential', test_march_exponential)
        call run_test('twist_of', test_twist_of)
        call run_test('straight_rod_march', test_straight_rod_march)
        call run_test('ad_transpose_block', test_ad_transpose_block)
        call run_test('ad_block', test_ad_block)
        call run_test('ad_times_and_cross', test_ad_times_and_cross)
        call run_test('row_residual', test_row_residual)
        call run_test('row_to_csr', test_row_to_csr)
        call run_test('row_has_nan', test_row_has_nan)
    end subroutine run_all_tests

    ! ---------------------------------------------------------------------------------------
    ! Helpers

    pure function cross(a, b) result(c)
        real(rk), intent(in) :: a(3), b(3)
        real(rk) :: c(3)
        c = [a(2) * b(3) - a(3) * b(2), a(3) * b(1) - a(1) * b(3), a(1) * b(2) - a(2) * b(1)]
    end function cross

    ! A random rotation matrix of angle up to max_angle.
    function random_rotation_matrix(max_angle) result(a)
        real(rk), intent(in) :: max_angle
        real(rk) :: a(3, 3)
        a = exp_so3(uniform(0.0_rk, max_angle) * random_unit_vector())
    end function random_rotation_matrix

    ! The 4 x 4 matrix exponential by a Taylor series of 30 terms after scaling by 2^-k to a
    ! 1-norm below 1/4, then k squarings.
    pure function expm_taylor(x) result(e)
        real(rk), intent(in) :: x(4, 4)
        real(rk) :: e(4, 4)
        real(rk) :: y(4, 4), term(4, 4), norm1
        integer :: k, n, i
        norm1 = maxval(sum(abs(x), dim=1))
        k = 0
        if (norm1 > 0.25_rk) k = ceiling(log(norm1 / 0.25_rk) / log(2.0_rk))
        y = x / 2.0_rk**k
        e = 0.0_rk
        do i = 1, 4
            e(i, i) = 1.0_rk
        end do
        term = e
        do n = 1, 30
            term = matmul(term, y) / real(n, rk)
            e = e + term
        end do
        do i = 1, k
            e = matmul(e, e)
        end do
    end function expm_taylor

    ! A random smooth motion: constant twists of size up to 1.5 (rotation) and 2 (translation),
    ! first- and second-order coefficients of size up to 1.
    function random_motion() result(m)
        type(motion_t) :: m
        integer :: k, j
        do k = 1, 2
            m%c(1:3, 1, k) = random_vector(3, 2.0_rk)
            m%c(4:6, 1, k) = random_vector(3, 1.5_rk)
            do j = 2, 6
                m%c(:, j, k) = random_vector(6, 1.0_rk)
            end do
        end do
    end function random_motion

    ! The pose g(s, t) = (a, x) of a motion.
    pure subroutine motion_pose(m, s, t, a, x)
        type(motion_t), intent(in) :: m
        real(rk), intent(in) :: s, t
        real(rk), intent(out) :: a(3, 3), x(3)
        real(rk) :: theta(6, 2), a1(3, 3), x1(3), a2(3, 3), x2(3)
        integer :: k
        do k = 1, 2
            theta(:, k) = m%c(:, 1, k) + s * m%c(:, 2, k) + t * m%c(:, 3, k) &
                + s * t * m%c(:, 4, k) + s**2 * m%c(:, 5, k) + t**2 * m%c(:, 6, k)
        end do
        call exp_se3(theta(:, 1), a1, x1)
        call exp_se3(theta(:, 2), a2, x2)
        call pose_compose(a1, x1, a2, x2, a, x)
    end subroutine motion_pose

    ! Derivatives da, dx of the pose along s or t at (s, t), fourth-order central differences.
    pure subroutine motion_derivative(m, s, t, direction, step, da, dx)
        type(motion_t), intent(in) :: m
        real(rk), intent(in) :: s, t, step
        integer, intent(in) :: direction
        real(rk), intent(out) :: da(3, 3), dx(3)
        real(rk), parameter :: weight(4) = [1.0_rk, -8.0_rk, 8.0_rk, -1.0_rk]
        real(rk), parameter :: offset(4) = [-2.0_rk, -1.0_rk, 1.0_rk, 2.0_rk]
        real(rk) :: a(3, 3), x(3)
        integer :: i
        da = 0.0_rk
        dx = 0.0_rk
        do i = 1, 4
            if (direction == along_s) then
                call motion_pose(m, s + offset(i) * step, t, a, x)
            else
                call motion_pose(m, s, t + offset(i) * step, a, x)
            end if
            da = da + weight(i) * a
            dx = dx + weight(i) * x
        end do
        da = da / (12.0_rk * step)
        dx = dx / (12.0_rk * step)
    end subroutine motion_derivative

    ! The paper's strain U (direction = along_s) or velocity V (along_t) at (s, t), from the
    ! definitions of methods §2.1 with d3, d1, d2 the columns of a: (u3, u1, u2, sigma3,
    ! sigma1, sigma2) with u1 = d3'.d2, u2 = d1'.d3, u3 = d2'.d1 and sigma_i = x'.d_i.
    pure function paper_six_vector(m, s, t, direction) result(u)
        type(motion_t), intent(in) :: m
        real(rk), intent(in) :: s, t
        integer, intent(in) :: direction
        real(rk) :: u(6)
        real(rk) :: a(3, 3), x(3), da(3, 3), dx(3)
        call motion_pose(m, s, t, a, x)
        call motion_derivative(m, s, t, direction, inner_step, da, dx)
        u(1) = dot_product(da(:, 3), a(:, 2))
        u(2) = dot_product(da(:, 1), a(:, 3))
        u(3) = dot_product(da(:, 2), a(:, 1))
        u(4:6) = matmul(dx, a)
    end function paper_six_vector

    ! The same from the standard body twist g^{-1} dg = (a^T dx, vee(a^T da)) with the sign of
    ! the angular part flipped (methods §2.1: u = -kappa, w = -omega).
    pure function body_twist_six_vector(m, s, t, direction) result(u)
        type(motion_t), intent(in) :: m
        real(rk), intent(in) :: s, t
        integer, intent(in) :: direction
        real(rk) :: u(6)
        real(rk) :: a(3, 3), x(3), da(3, 3), dx(3)
        call motion_pose(m, s, t, a, x)
        call motion_derivative(m, s, t, direction, inner_step, da, dx)
        u(1:3) = -vee(matmul(transpose(a), da))
        u(4:6) = matmul(transpose(a), dx)
    end function body_twist_six_vector

    ! d/dt U (direction = along_t) or d/ds V (along_s) at (s, t), fourth-order central
    ! differences of paper_six_vector.
    pure function outer_derivative(m, s, t, direction) result(du)
        type(motion_t), intent(in) :: m
        real(rk), intent(in) :: s, t
        integer, intent(in) :: direction
        real(rk) :: du(6)
        real(rk), parameter :: weight(4) = [1.0_rk, -8.0_rk, 8.0_rk, -1.0_rk]
        real(rk), parameter :: offset(4) = [-2.0_rk, -1.0_rk, 1.0_rk, 2.0_rk]
        integer :: i
        du = 0.0_rk
        do i = 1, 4
            if (direction == along_t) then
                du = du + weight(i) * paper_six_vector(m, s, t + offset(i) * outer_step, along_s)
            else
                du = du + weight(i) * paper_six_vector(m, s + offset(i) * outer_step, t, along_t)
            end if
        end do
        du = du / (12.0_rk * outer_step)
    end function outer_derivative

    ! The paper's L of eq. (1) (methods §2.1) for U = (u3, u1, u2, s3, s1, s2), acting on the
    ! augmented placement with rows (1, x), (0, d3), (0, d1), (0, d2).
    pure function paper_l_matrix(u) result(l)
        real(rk), intent(in) :: u(6)
        real(rk) :: l(4, 4)
        real(rk) :: u3, u1, u2
        u3 = u(1)
        u1 = u(2)
        u2 = u(3)
        l(1, :) = [0.0_rk, u(4), u(5), u(6)]
        l(2, :) = [0.0_rk, 0.0_rk, -u2, u1]
        l(3, :) = [0.0_rk, u2, 0.0_rk, -u3]
        l(4, :) = [0.0_rk, -u1, u3, 0.0_rk]
    end function paper_l_matrix

    ! ---------------------------------------------------------------------------------------
    ! Tests

    ! strand_ad equals the explicit matrix of methods §2.3, entry by entry (so that the
    ! antisymmetry test below cannot pass on a zero matrix).
    subroutine test_ad_explicit_matrix()
        real(rk) :: x(6), expected(6, 6), ad(6, 6)
        integer :: sample
        do sample = 1, n_samples
            x = random_vector(6, 2.0_rk)
            expected(1, :) = [0.0_rk, x(3), -x(2), 0.0_rk, 0.0_rk, 0.0_rk]
            expected(2, :) = [-x(3), 0.0_rk, x(1), 0.0_rk, 0.0_rk, 0.0_rk]
            expected(3, :) = [x(2), -x(1), 0.0_rk, 0.0_rk, 0.0_rk, 0.0_rk]
            expected(4, :) = [0.0_rk, x(6), -x(5), 0.0_rk, x(3), -x(2)]
            expected(5, :) = [-x(6), 0.0_rk, x(4), -x(3), 0.0_rk, x(1)]
            expected(6, :) = [x(5), -x(4), 0.0_rk, x(2), -x(1), 0.0_rk]
            ad = strand_ad(x)
            CHECK_CLOSE(ad, expected, 0.0_rk, 0.0_rk, 'strand_ad = explicit matrix of methods 2.3')
        end do
    end subroutine test_ad_explicit_matrix

    ! ad_X Y = -ad_Y X and ad_X X = 0, to a few eps |X| |Y|, for arguments of size 1e-3 to 1e3.
    subroutine test_ad_antisymmetry()
        real(rk) :: x(6), y(6), xy(6), yx(6), xx(6), scale_x, scale_y, worst(2)
        real(rk), parameter :: zero6(6) = 0.0_rk
        integer :: sample
        character(len=160) :: text
        worst = 0.0_rk
        do sample = 1, n_samples
            scale_x = 10.0_rk**uniform(-3.0_rk, 3.0_rk)
            scale_y = 10.0_rk**uniform(-3.0_rk, 3.0_rk)
            x = random_vector(6, scale_x)
            y = random_vector(6, scale_y)
            xy = matmul(strand_ad(x), y)
            yx = matmul(strand_ad(y), x)
            xx = matmul(strand_ad(x), x)
            worst(1) = max(worst(1), maxval(abs(xy + yx)) / (maxval(abs(x)) * maxval(abs(y))))
            worst(2) = max(worst(2), maxval(abs(xx)) / maxval(abs(x))**2)
            CHECK_CLOSE(xy, -yx, 8.0_rk * eps * maxval(abs(x)) * maxval(abs(y)), 0.0_rk, 'ad_X Y = -ad_Y X')
            CHECK_CLOSE(xx, zero6, 8.0_rk * eps * maxval(abs(x))**2, 0.0_rk, 'ad_X X = 0')
            CHECK_TRUE(maxval(abs(xy)) > 1.0e-3_rk * maxval(abs(x)) * maxval(abs(y)), 'ad_X Y is not zero')
        end do
        write(text, '(a,2es9.2)') '    max |ad_X Y + ad_Y X| / (|X| |Y|), |ad_X X| / |X|^2: ', &
            worst
        write(output_unit, '(a)') trim(text)
    end subroutine test_ad_antisymmetry

    ! cross_matrix(a) b = a x b.
    subroutine test_cross_matrix()
        real(rk) :: a(3), b(3)
        integer :: sample
        do sample = 1, n_samples
            a = random_vector(3, 3.0_rk)
            b = random_vector(3, 3.0_rk)
            CHECK_CLOSE(matmul(cross_matrix(a), b), cross(a, b), 4.0_rk * eps * 9.0_rk, 0.0_rk, 'cross_matrix(a) b = a x b')
        end do
    end subroutine test_cross_matrix

    ! Eq. (8): dU/dt - dV/ds = ad_U V on smooth random motions at random (s, t) in [0, 1]^2.
    ! The residual with -ad_U V in its place must be large: the check sees the sign.
    subroutine test_compatibility()
        type(motion_t) :: m
        real(rk) :: s, t, u(6), v(6), u_body(6), v_body(6), du_dt(6), dv_ds(6), ad_u_v(6)
        real(rk) :: term_scale, error, flipped, worst, worst_def, least_flipped, def_error
        integer :: sample
        character(len=200) :: text
        worst = 0.0_rk
        worst_def = 0.0_rk
        least_flipped = huge(1.0_rk)
        do sample = 1, n_samples
            m = random_motion()
            s = uniform(0.0_rk, 1.0_rk)
            t = uniform(0.0_rk, 1.0_rk)
            u = paper_six_vector(m, s, t, along_s)
            v = paper_six_vector(m, s, t, along_t)
            ! The paper's definitions agree with the standard body twists, angular parts negated.
            u_body = body_twist_six_vector(m, s, t, along_s)
            v_body = body_twist_six_vector(m, s, t, along_t)
            def_error = max(maxval(abs(u - u_body)) / maxval(abs(u)), &
                maxval(abs(v - v_body)) / maxval(abs(v)))
            worst_def = max(worst_def, def_error)
            CHECK_TRUE(def_error < 1.0e-9_rk, 'paper U, V = body twists with negated angular part')
            du_dt = outer_derivative(m, s, t, along_t)
            dv_ds = outer_derivative(m, s, t, along_s)
            ad_u_v = matmul(strand_ad(u), v)
            term_scale = max(maxval(abs(du_dt)), maxval(abs(dv_ds)), maxval(abs(ad_u_v)))
            error = maxval(abs(du_dt - dv_ds - ad_u_v)) / term_scale
            flipped = maxval(abs(du_dt - dv_ds + ad_u_v)) / term_scale
            worst = max(worst, error)
            least_flipped = min(least_flipped, flipped)
            CHECK_CLOSE(du_dt - dv_ds, ad_u_v, compat_tol * term_scale, 0.0_rk, 'dU/dt - dV/ds = ad_U V (eq. 8)')
            CHECK_TRUE(flipped > 1.0e-2_rk, 'the residual with -ad_U V is not small')
        end do
        write(text, '(a,es9.2,a,es9.2,a,es9.2)') '    max relative residual of eq. (8): ', worst, &
            '; with -ad_U V (min): ', least_flipped, '; paper vs body twist: ', worst_def
        write(output_unit, '(a)') trim(text)
    end subroutine test_compatibility

    ! strand_march = (a, x) times the homogeneous exponential of h [[hat(kappa), sigma], [0, 0]],
    ! and = exp(h L) P with the paper's L of eq. (1); angle classes |h kappa| = 0, ~1e-9,
    ! up to 1, ~3.
    subroutine test_march_exponential()
        real(rk) :: a(3, 3), x(3), u(6), h, angle, kappa(3), sigma(3), a_next(3, 3), x_next(3)
        real(rk) :: pose(4, 4), step(4, 4), expected(4, 4), placement(4, 4), paper(4, 4)
        real(rk) :: x_scale, worst_rot, worst_pos
        integer :: kind, sample
        character(len=12), parameter :: kind_name(4) = [character(len=12) :: 'zero', 'tiny', &
            'moderate', 'large']
        character(len=200) :: text
        character(len=:), allocatable :: label
        do kind = 1, 4
            label = trim(kind_name(kind)) // ' angles'
            worst_rot = 0.0_rk
            worst_pos = 0.0_rk
            do sample = 1, n_samples
                a = random_rotation_matrix(3.0_rk)
                x = random_vector(3, 2.0_rk)
                h = uniform(0.01_rk, 2.0_rk)
                select case (kind)
                case (1)
                    angle = 0.0_rk
                case (2)
                    angle = uniform(0.5e-9_rk, 2.0e-9_rk)
                case (3)
                    angle = uniform(1.0e-3_rk, 1.0_rk)
                case default
                    angle = uniform(2.8_rk, 3.1_rk)
                end select
                kappa = (angle / h) * random_unit_vector()
                sigma = [1.0_rk, 0.0_rk, 0.0_rk] + random_vector(3, 0.3_rk)
                u(1:3) = -kappa
                u(4:6) = sigma
                call strand_march(a, x, u, h, a_next, x_next)
                pose = 0.0_rk
                pose(1:3, 1:3) = a
                pose(1:3, 4) = x
                pose(4, 4) = 1.0_rk
                step = 0.0_rk
                step(1:3, 1:3) = h * hat(kappa)
                step(1:3, 4) = h * sigma
                expected = matmul(pose, expm_taylor(step))
                x_scale = max(1.0_rk, maxval(abs(expected(1:3, 4))))
                worst_rot = max(worst_rot, maxval(abs(a_next - expected(1:3, 1:3))))
                worst_pos = max(worst_pos, maxval(abs(x_next - expected(1:3, 4))) / x_scale)
                CHECK_CLOSE(a_next, expected(1:3, 1:3), march_tol, 0.0_rk, 'march rotation = 4x4 exp, ' // label)
                CHECK_CLOSE(x_next, expected(1:3, 4), march_tol * x_scale, 0.0_rk, 'march position = 4x4 exp, ' // label)
                ! The paper's placement, rows (1, x), (0, d3), (0, d1), (0, d2), by eq. (16).
                placement = 0.0_rk
                placement(1, 1) = 1.0_rk
                placement(1, 2:4) = x
                placement(2:4, 2:4) = transpose(a)
                paper = matmul(expm_taylor(h * paper_l_matrix(u)), placement)
                CHECK_CLOSE(transpose(a_next), paper(2:4, 2:4), march_tol, 0.0_rk, 'march directors = exp(hL) P, ' // label)
                CHECK_CLOSE(x_next, paper(1, 2:4), march_tol * x_scale, 0.0_rk, 'march position = exp(hL) P, ' // label)
                worst_rot = max(worst_rot, maxval(abs(transpose(a_next) - paper(2:4, 2:4))))
                worst_pos = max(worst_pos, maxval(abs(x_next - paper(1, 2:4))) / x_scale)
            end do
            write(text, '(a,2es9.2)') '    max error of the march (' // trim(kind_name(kind)) // &
                ' angles; rotation, position / max(1, |x|)): ', worst_rot, worst_pos
            write(output_unit, '(a)') trim(text)
        end do
    end subroutine test_march_exponential

    ! strand_twist_of maps (u3, u1, u2, s3, s1, s2) to (s3, s1, s2, -u3, -u1, -u2).
    subroutine test_twist_of()
        real(rk) :: u(6), expected(6)
        integer :: sample
        do sample = 1, n_samples
            u = random_vector(6, 5.0_rk)
            expected = [u(4), u(5), u(6), -u(1), -u(2), -u(3)]
            CHECK_CLOSE(strand_twist_of(u), expected, 0.0_rk, 0.0_rk, 'strand_twist_of(u3,u1,u2,s3,s1,s2)')
        end do
    end subroutine test_twist_of

    ! A straight, unstretched segment, U = (0, 0, 0, 1, 0, 0), moves x by h along d3 = a(:, 1)
    ! and keeps the directors.
    subroutine test_straight_rod_march()
        real(rk) :: a(3, 3), x(3), h, a_next(3, 3), x_next(3)
        real(rk), parameter :: u(6) = [0.0_rk, 0.0_rk, 0.0_rk, 1.0_rk, 0.0_rk, 0.0_rk]
        integer :: sample
        do sample = 1, n_samples
            a = random_rotation_matrix(3.1_rk)
            x = random_vector(3, 2.0_rk)
            h = uniform(1.0e-3_rk, 5.0_rk)
            call strand_march(a, x, u, h, a_next, x_next)
            CHECK_CLOSE(a_next, a, 4.0_rk * eps, 0.0_rk, 'straight march keeps the directors')
            CHECK_CLOSE(x_next, x + h * a(:, 1), 4.0_rk * eps * (2.0_rk + h), 0.0_rk, 'straight march moves x by h d3')
        end do
    end subroutine test_straight_rod_march

    ! diag(d) + alpha ad_X^T, for the node row's alphas (1/2, -1) and a random one.
    subroutine test_ad_transpose_block()
        real(rk) :: x(6), d(6), alpha, m(6, 6), expected(6, 6)
        integer :: sample, i
        do sample = 1, n_samples
            x = random_vector(6, 10.0_rk**uniform(-3.0_rk, 3.0_rk))
            d = random_vector(6, 1.0e3_rk)
            select case (mod(sample, 3))
            case (0)
                alpha = 0.5_rk
            case (1)
                alpha = -1.0_rk
            case default
                alpha = uniform(-2.0_rk, 2.0_rk)
            end select
            expected = alpha * transpose(strand_ad(x))
            do i = 1, 6
                expected(i, i) = d(i)
            end do
            call strand_ad_transpose_block(x, alpha, d, m)
            CHECK_CLOSE(m, expected, 0.0_rk, 0.0_rk, 'strand_ad_transpose_block = diag(d) + alpha ad^T')
        end do
    end subroutine test_ad_transpose_block

    ! diag(d) + diag(left) ad_X diag(right), each entry as (left_i ad_ij) right_j.
    subroutine test_ad_block()
        real(rk) :: x(6), d(6), left(6), right(6), ad(6, 6), m(6, 6), expected(6, 6)
        integer :: sample, i, j
        do sample = 1, n_samples
            x = random_vector(6, 10.0_rk**uniform(-3.0_rk, 3.0_rk))
            d = random_vector(6, 1.0e3_rk)
            left = random_vector(6, 1.0e9_rk)
            right = random_vector(6, 1.0e-6_rk)
            ad = strand_ad(x)
            do j = 1, 6
                do i = 1, 6
                    expected(i, j) = left(i) * ad(i, j) * right(j)
                end do
                expected(j, j) = d(j)
            end do
            call strand_ad_block(x, left, right, d, m)
            CHECK_CLOSE(m, expected, 0.0_rk, 0.0_rk, 'strand_ad_block = diag(d) + left ad right')
        end do
    end subroutine test_ad_block

    ! ad_X Y and hat(a) b, each row summed from zero in column order, bit for bit.
    subroutine test_ad_times_and_cross()
        real(rk) :: x(6), y(6), a(3), b(3), ad(6, 6), a_hat(3, 3), expected(6)
        integer :: sample, i, j
        do sample = 1, n_samples
            x = random_vector(6, 10.0_rk**uniform(-3.0_rk, 3.0_rk))
            y = random_vector(6, 10.0_rk**uniform(-3.0_rk, 3.0_rk))
            ad = strand_ad(x)
            expected = 0.0_rk
            do j = 1, 6
                do i = 1, 6
                    expected(i) = expected(i) + ad(i, j) * y(j)
                end do
            end do
            CHECK_CLOSE(strand_ad_times(x, y), expected, 0.0_rk, 0.0_rk, 'strand_ad_times = ad_X Y')
            a = x(1:3)
            b = y(4:6)
            a_hat = hat(a)
            expected = 0.0_rk
            do j = 1, 3
                do i = 1, 3
                    expected(i) = expected(i) + a_hat(i, j) * b(j)
                end do
            end do
            CHECK_CLOSE(strand_cross(a, b), expected(1:3), 0.0_rk, 0.0_rk, 'strand_cross = hat(a) b')
            CHECK_CLOSE(strand_cross(a, b), cross(a, b), 4.0_rk * eps * maxval(abs(a)) * maxval(abs(b)), 0.0_rk, 'strand_cross = a x b')
        end do
    end subroutine test_ad_times_and_cross

    ! A block row's A y - b against matmul (to round-off: entries and y in [-1, 1], 19 terms),
    ! an absent block (column -1) left out.
    subroutine test_row_residual()
        real(rk) :: blocks(6, 6, 3), rhs(6), y(36), r(6), expected(6)
        integer :: sample, c, cols(3)
        do sample = 1, n_samples
            call random_number(blocks)
            blocks = 2.0_rk * blocks - 1.0_rk
            rhs = random_vector(6, 1.0_rk)
            y = random_vector(36, 1.0_rk)
            if (mod(sample, 2) == 0) then
                cols = [2, 3, 4]
            else
                cols = [0, 5, -1]
            end if
            expected = -rhs
            do c = 1, 3
                if (cols(c) < 0) cycle
                expected = expected + matmul(blocks(:, :, c), y(6 * cols(c) + 1:6 * cols(c) + 6))
            end do
            call strand_row_residual(blocks, cols, rhs, y, r)
            CHECK_CLOSE(r, expected, 64.0_rk * eps, 0.0_rk, 'strand_row_residual = sum of block products - rhs')
            CHECK_TRUE(maxval(abs(r + rhs)) > 1.0e-3_rk, 'the block products are not zero')
        end do
    end subroutine test_row_residual

    ! values(j, c, i) = blocks(i, j, c): row i of the block row, its blocks side by side.
    subroutine test_row_to_csr()
        real(rk) :: blocks(6, 6, 3), values(108)
        integer :: n_c, i, j, c, at
        call random_number(blocks)
        do n_c = 1, 3
            values = -1.0_rk
            call strand_row_to_csr(blocks, n_c, values)
            at = 0
            do i = 1, 6
                do c = 1, n_c
                    do j = 1, 6
                        at = at + 1
                        CHECK_TRUE(values(at) == blocks(i, j, c), 'strand_row_to_csr: CSR order')
                    end do
                end do
            end do
            CHECK_TRUE(all(values(at + 1:) == -1.0_rk), 'strand_row_to_csr writes 36 n_c values')
        end do
    end subroutine test_row_to_csr

    ! A NaN anywhere in the 108 entries is found; a clean row and an infinity are not NaN.
    subroutine test_row_has_nan()
        real(rk) :: blocks(6, 6, 3), probe(6, 6, 3)
        integer :: k
        call random_number(blocks)
        CHECK_TRUE(.not. strand_row_has_nan(blocks), 'no NaN in a random row')
        do k = 1, 108
            probe = blocks
            probe(mod(k - 1, 6) + 1, mod((k - 1) / 6, 6) + 1, (k - 1) / 36 + 1) = &
                ieee_value(1.0_rk, ieee_quiet_nan)
            CHECK_TRUE(strand_row_has_nan(probe), 'a NaN is found at every position')
        end do
        probe = blocks
        probe(3, 4, 2) = ieee_value(1.0_rk, ieee_positive_inf)
        CHECK_TRUE(.not. strand_row_has_nan(probe), 'an infinity is not a NaN')
    end subroutine test_row_has_nan

end module rs_test_se3_strand_kernels

program test_se3_strand_kernels
    use rs_test_se3_strand_kernels, only: run_all_tests
    use rs_test_assert, only: finish_tests
    implicit none
    call run_all_tests()
    call finish_tests()
end program test_se3_strand_kernels
