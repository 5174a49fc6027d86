!> Pure kernels of the SE(3)-strand rod of seed 004 (methods/se3_strands.md): the paper's
!> 6 x 6 ad matrix, the coefficient blocks of the semi-implicit staggered scheme (eqs. 11-12,
!> §3.5) and the closed-form reconstruction of the placement (Appendix A, §3.6).
!>
!> The block kernels (strand_ad_transpose_block, strand_ad_block, strand_ad_times, strand_cross)
!> write the entries of ad out one by one: they run three times per node and per segment in
!> every step, and 6 x 6 matrices built from out-of-line hat calls, transpose and matmul cost
!> a quarter of the step at N = 16. Each entry and each row sum is formed as the strand_ad, hat
!> and (inlined) matmul expressions they replaced formed it, so the step's results are unchanged
!> bit for bit (tests/unit/formulations/test_se3_strand_kernels.F90).
!>
!> Conventions (methods §2.1, the paper's): six-vectors are ordered (3, 1, 2) as
!> U = (u3, u1, u2, sigma3, sigma1, sigma2), V = (w3, w1, w2, v3, v1, v2), Sigma and P likewise,
!> i.e. in the K basis (d3, d1, d2), which is right-handed, so cross products work as usual. The
!> ANGULAR parts carry the paper's sign: they are the NEGATIVES of the standard curvature,
!> angular velocity, moment and angular momentum (u = -kappa, w = -omega); the linear parts
!> (strain sigma, velocity v, force n, momentum) have the standard sign. The relaxed stretch is
!> sigma3 = 1 (methods §7 item 1).
module rs_se3_strand_kernels
    use rs_core_kinds, only: rk
    use rs_math_so3, only: hat
    use rs_math_se3, only: exp_se3
    implicit none
    private

    public :: strand_ad, cross_matrix, strand_march, strand_twist_of
    public :: strand_ad_transpose_block, strand_ad_block, strand_ad_times, strand_cross
    public :: strand_row_residual, strand_row_to_csr, strand_row_has_nan

contains

    !> The paper's ad_X (methods §2.3): [[-hat(w), 0], [-hat(v), -hat(w)]] for X = (w, v), so
    !> that the compatibility condition reads dU/dt - V' = ad_U V (eq. 8) and the balance
    !> dP/dt - Sigma' = ad_V^T P - ad_U^T Sigma (eq. 6).
    pure function strand_ad(x) result(ad)
        real(rk), intent(in) :: x(6)
        real(rk) :: ad(6, 6)
        ad = 0.0_rk
        ad(1:3, 1:3) = -hat(x(1:3))
        ad(4:6, 1:3) = -hat(x(4:6))
        ad(4:6, 4:6) = -hat(x(1:3))
    end function strand_ad

    !> [a]_x, the matrix of b -> a x b.
    pure function cross_matrix(a) result(m)
        real(rk), intent(in) :: a(3)
        real(rk) :: m(3, 3)
        m = hat(a)
    end function cross_matrix

    !> m = diag(d) + alpha ad_X^T, every entry set: ad_X^T = [[hat(w), hat(v)], [0, hat(w)]] for
    !> X = (w, v) (methods §2.3). The coefficients of P_k and Sigma in the node row (§3.5,
    !> eq. 11): alpha = -1 with d = 1/dt + D_ex M^-1, alpha = 1/2 with d = +-1/h~_k.
    pure subroutine strand_ad_transpose_block(x, alpha, d, m)
        real(rk), intent(in) :: x(6), alpha, d(6)
        real(rk), intent(out) :: m(6, 6)
        real(rk) :: w1, w2, w3, v1, v2, v3
        w1 = alpha * x(1)
        w2 = alpha * x(2)
        w3 = alpha * x(3)
        v1 = alpha * x(4)
        v2 = alpha * x(5)
        v3 = alpha * x(6)
        ! Entry by entry (array constructors here cost a store-to-load stall each): alpha
        ! [[hat(w), hat(v)], [0, hat(w)]], d on the diagonal.
        m(1, 1) = d(1)
        m(2, 1) = w3
        m(3, 1) = -w2
        m(4:6, 1) = 0.0_rk
        m(1, 2) = -w3
        m(2, 2) = d(2)
        m(3, 2) = w1
        m(4:6, 2) = 0.0_rk
        m(1, 3) = w2
        m(2, 3) = -w1
        m(3, 3) = d(3)
        m(4:6, 3) = 0.0_rk
        m(1, 4) = 0.0_rk
        m(2, 4) = v3
        m(3, 4) = -v2
        m(4, 4) = d(4)
        m(5, 4) = w3
        m(6, 4) = -w2
        m(1, 5) = -v3
        m(2, 5) = 0.0_rk
        m(3, 5) = v1
        m(4, 5) = -w3
        m(5, 5) = d(5)
        m(6, 5) = w1
        m(1, 6) = v2
        m(2, 6) = -v1
        m(3, 6) = 0.0_rk
        m(4, 6) = w2
        m(5, 6) = -w1
        m(6, 6) = d(6)
    end subroutine strand_ad_transpose_block

    !> m = diag(d) + diag(left) ad_X diag(right), every entry set (methods §2.3: ad_X =
    !> [[-hat(w), 0], [-hat(v), -hat(w)]]). The coefficients of the segment row (§3.5, eq. 12):
    !> left = A/4, right = A^-1 for Sigma; left = -A/4, right = M^-1 for P_k and P_{k+1}.
    pure subroutine strand_ad_block(x, left, right, d, m)
        real(rk), intent(in) :: x(6), left(6), right(6), d(6)
        real(rk), intent(out) :: m(6, 6)
        ! Entry by entry, as (left_i ad_ij) right_j.
        m(1, 1) = d(1)
        m(2, 1) = left(2) * (-x(3)) * right(1)
        m(3, 1) = left(3) * x(2) * right(1)
        m(4, 1) = 0.0_rk
        m(5, 1) = left(5) * (-x(6)) * right(1)
        m(6, 1) = left(6) * x(5) * right(1)
        m(1, 2) = left(1) * x(3) * right(2)
        m(2, 2) = d(2)
        m(3, 2) = left(3) * (-x(1)) * right(2)
        m(4, 2) = left(4) * x(6) * right(2)
        m(5, 2) = 0.0_rk
        m(6, 2) = left(6) * (-x(4)) * right(2)
        m(1, 3) = left(1) * (-x(2)) * right(3)
        m(2, 3) = left(2) * x(1) * right(3)
        m(3, 3) = d(3)
        m(4, 3) = left(4) * (-x(5)) * right(3)
        m(5, 3) = left(5) * x(4) * right(3)
        m(6, 3) = 0.0_rk
        m(1:3, 4) = 0.0_rk
        m(4, 4) = d(4)
        m(5, 4) = left(5) * (-x(3)) * right(4)
        m(6, 4) = left(6) * x(2) * right(4)
        m(1:3, 5) = 0.0_rk
        m(4, 5) = left(4) * x(3) * right(5)
        m(5, 5) = d(5)
        m(6, 5) = left(6) * (-x(1)) * right(5)
        m(1:3, 6) = 0.0_rk
        m(4, 6) = left(4) * (-x(2)) * right(6)
        m(5, 6) = left(5) * x(1) * right(6)
        m(6, 6) = d(6)
    end subroutine strand_ad_block

    !> ad_X Y (methods §2.3), the terms of each row summed left to right.
    pure function strand_ad_times(x, y) result(z)
        real(rk), intent(in) :: x(6), y(6)
        real(rk) :: z(6)
        z(1) = x(3) * y(2) - x(2) * y(3)
        z(2) = -x(3) * y(1) + x(1) * y(3)
        z(3) = x(2) * y(1) - x(1) * y(2)
        z(4) = x(6) * y(2) - x(5) * y(3) + x(3) * y(5) - x(2) * y(6)
        z(5) = -x(6) * y(1) + x(4) * y(3) - x(3) * y(4) + x(1) * y(6)
        z(6) = x(5) * y(1) - x(4) * y(2) + x(2) * y(4) - x(1) * y(5)
    end function strand_ad_times

    !> a x b, as hat(a) b.
    pure function strand_cross(a, b) result(c)
        real(rk), intent(in) :: a(3), b(3)
        real(rk) :: c(3)
        c(1) = -a(3) * b(2) + a(2) * b(3)
        c(2) = a(3) * b(1) - a(1) * b(3)
        c(3) = -a(2) * b(1) + a(1) * b(2)
    end function strand_cross

    !> Block row r = sum_c blocks(:, :, c) y_{cols(c)} - rhs of the step's system A Y = b
    !> (§3.5), cols(c) < 0 for an absent block; each block's product is summed from zero and then
    !> added, as a 6 x 6 matmul would.
    pure subroutine strand_row_residual(blocks, cols, rhs, y, r)
        real(rk), intent(in) :: blocks(6, 6, 3), rhs(6), y(:)
        integer, intent(in) :: cols(3)
        real(rk), intent(out) :: r(6)
        real(rk) :: t(6)
        integer :: c, j
        r = -rhs
        do c = 1, 3
            if (cols(c) < 0) cycle
            t = 0.0_rk
            do j = 1, 6
                t = t + blocks(:, j, c) * y(6 * cols(c) + j)
            end do
            r = r + t
        end do
    end subroutine strand_row_residual

    !> The block row `blocks` in compressed-row order: each of its 6 rows with the n_c blocks
    !> present (the first n_c) side by side.
    pure subroutine strand_row_to_csr(blocks, n_c, values)
        real(rk), intent(in) :: blocks(6, 6, 3)
        integer, intent(in) :: n_c
        real(rk), intent(out) :: values(6, n_c, 6)
        integer :: i, c
        do i = 1, 6
            do c = 1, n_c
                values(:, c, i) = blocks(i, :, c)
            end do
        end do
    end subroutine strand_row_to_csr

    !> Whether a block row (its 6 x 6 x 3 entries, by sequence association) holds a NaN. A
    !> fixed-size count rather than any(): it vectorizes, and any() over the whole system cost
    !> half of the assembly.
    pure logical function strand_row_has_nan(blocks) result(has_nan)
        real(rk), intent(in) :: blocks(108)
        integer :: i, n
        n = 0
        do i = 1, 108
            n = n + merge(1, 0, blocks(i) /= blocks(i))
        end do
        has_nan = n > 0
    end function strand_row_has_nan

    !> The standard body twist (v, omega) per unit length of the paper's strain U: linear part
    !> sigma, angular part kappa = -u, both in K components.
    pure function strand_twist_of(u) result(theta)
        real(rk), intent(in) :: u(6)
        real(rk) :: theta(6)
        theta(1:3) = u(4:6)
        theta(4:6) = -u(1:3)
    end function strand_twist_of

    !> One step of the space reconstruction P_{k+1} = exp(h L_{k,k+1}) P_k (Appendix A, eq. 16):
    !> the section at s + h of a segment with constant strain u, from the pose (a, x) at s, where
    !> a = [d3 d1 d2] maps K to inertial components. SE(3)'s closed-form exponential of the
    !> standard twist h (sigma, kappa) is the paper's formula in another notation.
    pure subroutine strand_march(a, x, u, h, a_next, x_next)
        real(rk), intent(in) :: a(3, 3), x(3), u(6), h
        real(rk), intent(out) :: a_next(3, 3), x_next(3)
        real(rk) :: a_rel(3, 3), r_rel(3)
        call exp_se3(h * strand_twist_of(u), a_rel, r_rel)
        a_next = matmul(a, a_rel)
        x_next = x + matmul(a, r_rel)
    end subroutine strand_march

end module rs_se3_strand_kernels
