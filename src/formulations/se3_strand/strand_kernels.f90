!> Pure kernels of the SE(3)-strand rod of seed 004 (methods/se3_strands.md): the paper's
!> 6 x 6 ad matrix, the coefficient blocks of the semi-implicit staggered scheme (eqs. 11-12,
!> §3.5) and the closed-form reconstruction of the placement (Appendix A, §3.6).
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
