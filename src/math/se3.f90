!> The rigid-motion group SE(3): poses, twists, exponential and logarithm, the tangent operator
!> and its inverse, the adjoint (methods/se3_petrov_galerkin.md §2, §4.1, §4.3).
!>
!> Conventions (docs/theory/lie_groups.md):
!> - A pose is the pair (A, r) of a rotation matrix A (active, K to I components, as in
!>   rs_math_so3) and a position r; it stands for the homogeneous matrix H = [[A, r], [0, 1]]
!>   (methods eq. (17)). Procedures take and return the pair as plain arrays `a(3, 3), r(3)`;
!>   `pose_matrix` and `pose_from_matrix` convert to and from the 4x4 form.
!> - A twist is theta = (v, omega) in R^6, translation first (methods eq. (82)), with
!>   `hat_se3(theta)` = [[hat(omega), v], [0, 0]].
!> - `ad_se3(theta)` is the 6x6 matrix of ad in this order, [[hat(omega), hat(v)],
!>   [0, hat(omega)]] (the operator written with corner brackets in methods eq. (68)).
!> - The tangent operator is material (left-trivialized differential, right Jacobian), as in
!>   methods eqs. (62), (67)-(68):
!>   Exp(theta)^{-1} d/dt Exp(theta) = hat_se3(T_SE3(theta) theta_dot), with
!>   T_SE3(x) = sum_i (-1)^i/(i+1)! ad_x^i. Its diagonal blocks are T_SO3(omega) and its upper
!>   right block is the derivative of T_SO3 at omega in the direction v (the series of T_SE3 is
!>   the matrix function T applied to a block-triangular argument), evaluated in closed form by
!>   rs_math_so3 with the small-angle series described there.
!> - `log_se3` returns the principal twist: its rotation part has length in [0, pi] (the branch
!>   of log_so3, robust near pi).
module rs_math_se3
    use rs_core_kinds, only: rk
    use rs_math_so3, only: hat, exp_so3, log_so3, tangent_so3, tangent_inverse_so3, &
        tangent_so3_directional, tangent_inverse_so3_directional
    implicit none
    private

    public :: hat_se3, vee_se3, ad_se3, exp_se3, log_se3
    public :: tangent_se3, tangent_inverse_se3, adjoint_se3
    public :: pose_compose, pose_inverse, pose_relative, pose_matrix, pose_from_matrix

contains

    !> The 4x4 matrix j_SE3(theta) = [[hat(omega), v], [0, 0]] of the twist theta = (v, omega)
    !> (methods eq. (82)).
    pure function hat_se3(theta) result(x)
        real(rk), intent(in) :: theta(6)
        real(rk) :: x(4, 4)
        x = 0.0_rk
        x(1:3, 1:3) = hat(theta(4:6))
        x(1:3, 4) = theta(1:3)
    end function hat_se3

    !> Inverse of `hat_se3`: v from the last column, omega from the skew part of the 3x3 block.
    pure function vee_se3(x) result(theta)
        real(rk), intent(in) :: x(4, 4)
        real(rk) :: theta(6)
        theta(1:3) = x(1:3, 4)
        theta(4:6) = 0.5_rk * [x(3, 2) - x(2, 3), x(1, 3) - x(3, 1), x(2, 1) - x(1, 2)]
    end function vee_se3

    !> The 6x6 matrix of ad_theta, ad_theta(y) = [theta, y], in (v, omega) order (methods eq.
    !> (68)): [[hat(omega), hat(v)], [0, hat(omega)]].
    pure function ad_se3(theta) result(ad)
        real(rk), intent(in) :: theta(6)
        real(rk) :: ad(6, 6)
        ad = 0.0_rk
        ad(1:3, 1:3) = hat(theta(4:6))
        ad(1:3, 4:6) = hat(theta(1:3))
        ad(4:6, 4:6) = ad(1:3, 1:3)
    end function ad_se3

    !> Exp_SE3(theta) = (Exp_SO3(omega), T_SO3^T(omega) v) (methods eq. (83)).
    pure subroutine exp_se3(theta, a, r)
        real(rk), intent(in) :: theta(6)
        real(rk), intent(out) :: a(3, 3), r(3)
        a = exp_so3(theta(4:6))
        r = matmul(theta(1:3), tangent_so3(theta(4:6)))
    end subroutine exp_se3

    !> Log_SE3(A, r) = (T_SO3^{-T}(psi) r, psi) with psi = Log_SO3(A) (methods eqs. (84)-(85)).
    pure function log_se3(a, r) result(theta)
        real(rk), intent(in) :: a(3, 3), r(3)
        real(rk) :: theta(6)
        theta(4:6) = log_so3(a)
        theta(1:3) = matmul(r, tangent_inverse_so3(theta(4:6)))
    end function log_se3

    !> Tangent operator T_SE3(theta) of methods eqs. (67)-(68): the material velocity of
    !> Exp(theta) is T_SE3(theta) theta_dot.
    pure function tangent_se3(theta) result(t)
        real(rk), intent(in) :: theta(6)
        real(rk) :: t(6, 6)
        t(1:3, 1:3) = tangent_so3(theta(4:6))
        t(1:3, 4:6) = tangent_so3_directional(theta(4:6), theta(1:3))
        t(4:6, 1:3) = 0.0_rk
        t(4:6, 4:6) = t(1:3, 1:3)
    end function tangent_se3

    !> Inverse of T_SE3 (methods eq. (69)), built like `tangent_se3` from T_SO3^{-1} and its
    !> directional derivative. Singular when |omega| = 2 pi k, k >= 1.
    pure function tangent_inverse_se3(theta) result(t_inv)
        real(rk), intent(in) :: theta(6)
        real(rk) :: t_inv(6, 6)
        t_inv(1:3, 1:3) = tangent_inverse_so3(theta(4:6))
        t_inv(1:3, 4:6) = tangent_inverse_so3_directional(theta(4:6), theta(1:3))
        t_inv(4:6, 1:3) = 0.0_rk
        t_inv(4:6, 4:6) = t_inv(1:3, 1:3)
    end function tangent_inverse_se3

    !> Adjoint of the pose (A, r) in (v, omega) order, [[A, hat(r) A], [0, A]]:
    !> H hat_se3(theta) H^{-1} = hat_se3(Ad_H theta).
    pure function adjoint_se3(a, r) result(ad)
        real(rk), intent(in) :: a(3, 3), r(3)
        real(rk) :: ad(6, 6)
        ad(1:3, 1:3) = a
        ad(1:3, 4:6) = matmul(hat(r), a)
        ad(4:6, 1:3) = 0.0_rk
        ad(4:6, 4:6) = a
    end function adjoint_se3

    !> The pose H1 H2: (A1 A2, r1 + A1 r2).
    pure subroutine pose_compose(a1, r1, a2, r2, a, r)
        real(rk), intent(in) :: a1(3, 3), r1(3), a2(3, 3), r2(3)
        real(rk), intent(out) :: a(3, 3), r(3)
        a = matmul(a1, a2)
        r = r1 + matmul(a1, r2)
    end subroutine pose_compose

    !> The pose H^{-1}: (A^T, -A^T r) (methods eq. (19)).
    pure subroutine pose_inverse(a, r, a_inv, r_inv)
        real(rk), intent(in) :: a(3, 3), r(3)
        real(rk), intent(out) :: a_inv(3, 3), r_inv(3)
        a_inv = transpose(a)
        r_inv = -matmul(r, a)
    end subroutine pose_inverse

    !> The relative pose H1^{-1} H2: (A1^T A2, A1^T (r2 - r1)), whose logarithm is the element
    !> twist of methods §5.2.
    pure subroutine pose_relative(a1, r1, a2, r2, a, r)
        real(rk), intent(in) :: a1(3, 3), r1(3), a2(3, 3), r2(3)
        real(rk), intent(out) :: a(3, 3), r(3)
        a = matmul(transpose(a1), a2)
        r = matmul(r2 - r1, a1)
    end subroutine pose_relative

    !> The homogeneous matrix [[A, r], [0, 1]] of the pose (A, r) (methods eq. (17)).
    pure function pose_matrix(a, r) result(h)
        real(rk), intent(in) :: a(3, 3), r(3)
        real(rk) :: h(4, 4)
        h(1:3, 1:3) = a
        h(1:3, 4) = r
        h(4, :) = [0.0_rk, 0.0_rk, 0.0_rk, 1.0_rk]
    end function pose_matrix

    !> The pair (A, r) of a homogeneous matrix; its last row is not checked.
    pure subroutine pose_from_matrix(h, a, r)
        real(rk), intent(in) :: h(4, 4)
        real(rk), intent(out) :: a(3, 3), r(3)
        a = h(1:3, 1:3)
        r = h(1:3, 4)
    end subroutine pose_from_matrix

end module rs_math_se3
