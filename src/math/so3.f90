!> The rotation group SO(3): hat/vee, exponential and logarithm, the tangent operator of the
!> rotation vector, its inverse and their derivatives, and the complement rotation vector.
!>
!> Conventions (docs/theory/lie_groups.md, methods/se3_petrov_galerkin.md §2 and §4.2):
!> - Rotations are active: `A` maps cross-section (K) components to inertial (I) components,
!>   `I a = A K a`; `exp_so3(psi)` rotates by the angle |psi| about the axis psi/|psi|.
!> - `hat(w)` is the tilde map (73): `hat(w) x = w x x` (cross product); `vee` is its inverse.
!> - The tangent operator `T(psi)` (78) is material (body frame): the left-trivialized
!>   differential of methods eq. (67), often called the right Jacobian.
!>   `K omega = T(psi) psi_dot` and `A^T dA = hat(T(psi) dpsi)`. `T^T(psi) = T(-psi)` is the
!>   spatial (left) Jacobian, `I omega = T^T(psi) psi_dot`.
!> - Derivatives of matrix-valued functions are rank-3 arrays `D(i, j, k) = d M_ij / d psi_k`.
!> - `log_so3` returns the principal rotation vector, |psi| in [0, pi]. At exactly pi both
!>   signs are valid; the one returned is then whichever the round-off of the skew part
!>   selects. Near pi the axis comes from the symmetric part of A (not from A - A^T, whose size
!>   is sin|psi|), with the sign taken from the skew part, so the result stays accurate to
!>   round-off up to the angle pi.
!>
!> Small angles: every scalar coefficient (sin x / x, (1 - cos x)/x^2, ...) is a Taylor
!> polynomial in x^2 for x = |psi| < `so3_series_angle` = 0.5 and its closed form from 0.5 on.
!> The series are carried until their truncation error is below 1e-17 relative at 0.5; the
!> closed forms lose at most about 6 eps / x to cancellation there (about 3e-15), so Exp, T,
!> T^{-1} and their derivatives are accurate to a few 1e-15 relative at every angle in [0, pi)
!> (checked against quadruple precision in tests/unit/math/test_so3.F90) and no branch divides
!> by the angle at 0. A first-order branch below 1e-6 (methods §4.4) would leave errors of order
!> eps / x, up to about 1e-9, in the derivatives just above its threshold.
module rs_math_so3
    use rs_core_kinds, only: rk, pi
    implicit none
    private

    public :: hat, vee, exp_so3, log_so3
    public :: tangent_so3, tangent_inverse_so3
    public :: exp_so3_derivative, tangent_so3_derivative, tangent_inverse_so3_derivative
    public :: tangent_so3_directional, tangent_inverse_so3_directional
    public :: complement_rotation_vector, nearest_rotation_vector, unit_vector
    public :: perpendicular_pair

    !> Angle (radians) below which the scalar coefficients use their Taylor series.
    real(rk), parameter, public :: so3_series_angle = 0.5_rk

    ! Taylor coefficients in t = x^2 of the scalar functions, lowest order first.
    ! sin x / x = sum (-1)^n t^n / (2n+1)!
    real(rk), parameter :: series_alpha(8) = [1.0_rk, -1.0_rk / 6.0_rk, 1.0_rk / 120.0_rk, &
        -1.0_rk / 5040.0_rk, 1.0_rk / 362880.0_rk, -1.0_rk / 39916800.0_rk, &
        1.0_rk / 6227020800.0_rk, -1.0_rk / 1307674368000.0_rk]
    ! (1 - cos x) / x^2 = sum (-1)^n t^n / (2n+2)!
    real(rk), parameter :: series_half_beta(7) = [1.0_rk / 2.0_rk, -1.0_rk / 24.0_rk, &
        1.0_rk / 720.0_rk, -1.0_rk / 40320.0_rk, 1.0_rk / 3628800.0_rk, &
        -1.0_rk / 479001600.0_rk, 1.0_rk / 87178291200.0_rk]
    ! (x - sin x) / x^3 = sum (-1)^n t^n / (2n+3)!
    real(rk), parameter :: series_t2(7) = [1.0_rk / 6.0_rk, -1.0_rk / 120.0_rk, &
        1.0_rk / 5040.0_rk, -1.0_rk / 362880.0_rk, 1.0_rk / 39916800.0_rk, &
        -1.0_rk / 6227020800.0_rk, 1.0_rk / 1307674368000.0_rk]
    ! (cos x - sin x / x) / x^2 = sum (-1)^(n+1) (2n+2) t^n / (2n+3)!
    real(rk), parameter :: series_dalpha(7) = [-1.0_rk / 3.0_rk, 1.0_rk / 30.0_rk, &
        -1.0_rk / 840.0_rk, 1.0_rk / 45360.0_rk, -1.0_rk / 3991680.0_rk, &
        1.0_rk / 518918400.0_rk, -1.0_rk / 93405312000.0_rk]
    ! (sin x / x - 2 (1 - cos x) / x^2) / x^2 = sum (-1)^(n+1) (2n+2) t^n / (2n+4)!
    real(rk), parameter :: series_dhalf_beta(7) = [-1.0_rk / 12.0_rk, 1.0_rk / 180.0_rk, &
        -1.0_rk / 6720.0_rk, 1.0_rk / 453600.0_rk, -1.0_rk / 47900160.0_rk, &
        1.0_rk / 7264857600.0_rk, -1.0_rk / 1494484992000.0_rk]
    ! (3 sin x / x - 2 - cos x) / x^4 = sum (-1)^n (-2n - 2) t^n / (2n+5)!
    real(rk), parameter :: series_dt2(7) = [-1.0_rk / 60.0_rk, &
        1.0_rk / 1260.0_rk, -1.0_rk / 60480.0_rk, 1.0_rk / 4989600.0_rk, &
        -1.0_rk / 622702080.0_rk, 1.0_rk / 108972864000.0_rk, -1.0_rk / 25406244864000.0_rk]
    ! (1 - (x/2) cot(x/2)) / x^2 = sum |B_(2n+2)| t^n / (2n+2)!, B_k the Bernoulli numbers;
    ! the series converges for x < 2 pi.
    real(rk), parameter :: series_tinv2(9) = [1.0_rk / 12.0_rk, 1.0_rk / 720.0_rk, &
        1.0_rk / 30240.0_rk, 1.0_rk / 1209600.0_rk, 1.0_rk / 47900160.0_rk, &
        691.0_rk / 1307674368000.0_rk, 1.0_rk / 74724249600.0_rk, &
        3617.0_rk / 10670622842880000.0_rk, 43867.0_rk / 5109094217170944000.0_rk]

contains

    !> The tilde map (methods eq. (73)): the skew matrix with `hat(w) x = w x x`.
    pure function hat(w) result(w_hat)
        real(rk), intent(in) :: w(3)
        real(rk) :: w_hat(3, 3)
        w_hat(:, 1) = [0.0_rk, w(3), -w(2)]
        w_hat(:, 2) = [-w(3), 0.0_rk, w(1)]
        w_hat(:, 3) = [w(2), -w(1), 0.0_rk]
    end function hat

    !> Inverse of `hat`, applied to the skew-symmetric part of `w_hat`, so that a nearly skew
    !> matrix (a finite-difference quotient, A^T dA) gives its best skew approximation.
    pure function vee(w_hat) result(w)
        real(rk), intent(in) :: w_hat(3, 3)
        real(rk) :: w(3)
        w = 0.5_rk * [w_hat(3, 2) - w_hat(2, 3), w_hat(1, 3) - w_hat(3, 1), &
            w_hat(2, 1) - w_hat(1, 2)]
    end function vee

    !> Rotation matrix of the rotation vector `psi` (Rodrigues, methods eq. (75)).
    pure function exp_so3(psi) result(a)
        real(rk), intent(in) :: psi(3)
        real(rk) :: a(3, 3)
        real(rk) :: angle
        integer :: i
        angle = norm2(psi)
        ! 1 + alpha W + (beta/2) W^2 with W^2 = psi psi^T - |psi|^2 1 and 1 - (beta/2)|psi|^2 =
        ! cos|psi|: the diagonal then carries cos|psi| exactly instead of a cancelling sum.
        a = coef_alpha(angle) * hat(psi) + coef_half_beta(angle) * outer(psi, psi)
        do i = 1, 3
            a(i, i) = a(i, i) + cos(angle)
        end do
    end function exp_so3

    !> Principal rotation vector of the rotation matrix `a` (methods eqs. (76)-(77)), |psi| in
    !> [0, pi], with a robust branch near pi (module header).
    pure function log_so3(a) result(psi)
        real(rk), intent(in) :: a(3, 3)
        real(rk) :: psi(3)
        real(rk) :: axis_sin(3), sin_angle, cos_angle, angle, sym(3, 3), axis(3)
        integer :: i, j
        ! The skew part is sin(angle) * axis and the trace gives cos(angle); atan2 of both is
        ! accurate at every angle, unlike arccos near 0 and pi (eq. (76)).
        axis_sin = vee(a)
        sin_angle = norm2(axis_sin)
        cos_angle = 0.5_rk * (a(1, 1) + a(2, 2) + a(3, 3) - 1.0_rk)
        angle = atan2(sin_angle, cos_angle)
        if (cos_angle >= 0.0_rk) then
            if (angle < so3_series_angle) then
                psi = axis_sin / coef_alpha(angle)
            else
                psi = (angle / sin_angle) * axis_sin
            end if
        else
            ! Above pi/2 the skew part shrinks like sin(angle) and its direction loses accuracy;
            ! (A + A^T)/2 = cos(angle) 1 + (1 - cos(angle)) axis axis^T gives the axis up to a
            ! sign from its largest diagonal entry (squared component >= 1/3).
            sym = 0.5_rk * (a + transpose(a))
            i = maxloc([sym(1, 1), sym(2, 2), sym(3, 3)], dim=1)
            axis(i) = sqrt(max(sym(i, i) - cos_angle, 0.0_rk) / (1.0_rk - cos_angle))
            do j = 1, 3
                if (j /= i) axis(j) = sym(i, j) / ((1.0_rk - cos_angle) * axis(i))
            end do
            axis = axis / norm2(axis)
            if (dot_product(axis, axis_sin) < 0.0_rk) axis = -axis
            psi = angle * axis
        end if
    end function log_so3

    !> Tangent operator T(psi) of methods eq. (78): K omega = T(psi) psi_dot.
    pure function tangent_so3(psi) result(t)
        real(rk), intent(in) :: psi(3)
        real(rk) :: t(3, 3)
        real(rk) :: angle
        integer :: i
        angle = norm2(psi)
        ! 1 - (beta/2) W + ((1 - alpha)/|psi|^2) W^2 with W^2 = psi psi^T - |psi|^2 1.
        t = -coef_half_beta(angle) * hat(psi) + coef_t2(angle) * outer(psi, psi)
        do i = 1, 3
            t(i, i) = t(i, i) + coef_alpha(angle)
        end do
    end function tangent_so3

    !> Inverse tangent operator of methods eq. (79): psi_dot = T^{-1}(psi) K omega. Singular
    !> at |psi| = 2 pi k, k >= 1 (§5.5); keep |psi| <= pi with `complement_rotation_vector`.
    pure function tangent_inverse_so3(psi) result(t_inv)
        real(rk), intent(in) :: psi(3)
        real(rk) :: t_inv(3, 3)
        real(rk) :: angle, g
        integer :: i
        angle = norm2(psi)
        ! 1 + W/2 + ((1 - gamma)/|psi|^2) W^2 with W^2 = psi psi^T - |psi|^2 1.
        g = coef_tinv2(angle)
        t_inv = 0.5_rk * hat(psi) + g * outer(psi, psi)
        do i = 1, 3
            t_inv(i, i) = t_inv(i, i) + 1.0_rk - g * angle**2
        end do
    end function tangent_inverse_so3

    !> Derivative of Exp_SO3, d(i, j, k) = d Exp_ij / d psi_k (methods eq. (93)).
    pure function exp_so3_derivative(psi) result(d)
        real(rk), intent(in) :: psi(3)
        real(rk) :: d(3, 3, 3)
        real(rk) :: angle, w(3, 3), w2(3, 3), alpha, half_beta, dalpha, dhalf_beta
        integer :: k
        angle = norm2(psi)
        w = hat(psi)
        w2 = matmul(w, w)
        alpha = coef_alpha(angle)
        half_beta = coef_half_beta(angle)
        ! d alpha / d psi_k = ((cos - alpha)/|psi|^2) psi_k and
        ! d (beta/2) / d psi_k = ((alpha - beta)/|psi|^2) psi_k (eq. (92)).
        dalpha = coef_dalpha(angle)
        dhalf_beta = coef_dhalf_beta(angle)
        do k = 1, 3
            d(:, :, k) = alpha * unit_hat(k) + half_beta * square_derivative(psi, k) &
                + psi(k) * (dalpha * w + dhalf_beta * w2)
        end do
    end function exp_so3_derivative

    !> Derivative of T(psi), d(i, j, k) = d T_ij / d psi_k (methods eq. (97)).
    pure function tangent_so3_derivative(psi) result(d)
        real(rk), intent(in) :: psi(3)
        real(rk) :: d(3, 3, 3)
        integer :: k
        do k = 1, 3
            d(:, :, k) = tangent_so3_directional(psi, unit_vector(k))
        end do
    end function tangent_so3_derivative

    !> Derivative of T^{-1}(psi), d(i, j, k) = d T^{-1}_ij / d psi_k (methods eq. (98) with the
    !> sign of its last term corrected as in §13 item 2).
    pure function tangent_inverse_so3_derivative(psi) result(d)
        real(rk), intent(in) :: psi(3)
        real(rk) :: d(3, 3, 3)
        integer :: k
        do k = 1, 3
            d(:, :, k) = tangent_inverse_so3_directional(psi, unit_vector(k))
        end do
    end function tangent_inverse_so3_derivative

    !> Directional derivative sum_k dpsi_k dT/dpsi_k of T at `psi` (methods eq. (97)
    !> contracted with dpsi). Also the off-diagonal block of the SE(3) tangent operator.
    pure function tangent_so3_directional(psi, dpsi) result(dt)
        real(rk), intent(in) :: psi(3), dpsi(3)
        real(rk) :: dt(3, 3)
        real(rk) :: angle, w(3, 3), slope
        angle = norm2(psi)
        w = hat(psi)
        slope = dot_product(psi, dpsi)
        ! T = 1 - (beta/2) W + c W^2 with c = (1 - alpha)/|psi|^2, d(beta/2) = ((alpha - beta)
        ! /|psi|^2) psi.dpsi and dc = ((3 alpha - 2 - cos)/|psi|^4) psi.dpsi.
        dt = -coef_half_beta(angle) * hat(dpsi) &
            + coef_t2(angle) * square_directional(psi, dpsi) &
            + slope * (-coef_dhalf_beta(angle) * w &
            + coef_dt2(angle) * matmul(w, w))
    end function tangent_so3_directional

    !> Directional derivative sum_k dpsi_k dT^{-1}/dpsi_k of T^{-1} at `psi` (corrected methods
    !> eq. (98), §13 item 2).
    pure function tangent_inverse_so3_directional(psi, dpsi) result(dt_inv)
        real(rk), intent(in) :: psi(3), dpsi(3)
        real(rk) :: dt_inv(3, 3)
        real(rk) :: angle, w(3, 3)
        angle = norm2(psi)
        w = hat(psi)
        ! T^{-1} = 1 + W/2 + g W^2 with g = (1 - gamma)/|psi|^2 and
        ! dg = -((2(1 - gamma) + gamma(1 - gamma))/|psi|^2 - 1/4)/|psi|^2 psi.dpsi.
        dt_inv = 0.5_rk * hat(dpsi) &
            + coef_tinv2(angle) * square_directional(psi, dpsi) &
            + dot_product(psi, dpsi) * coef_dtinv2(angle) * matmul(w, w)
    end function tangent_inverse_so3_directional

    !> Complement rotation vector (methods §5.5 eq. (40)): for |psi| > pi the vector
    !> (1 - 2 pi k/|psi|) psi with the integer k that brings its length into [0, pi]; it
    !> describes the same rotation. For pi < |psi| <= 3 pi this is exactly (40) (k = 1);
    !> vectors with |psi| <= pi are returned unchanged.
    pure function complement_rotation_vector(psi) result(psi_c)
        real(rk), intent(in) :: psi(3)
        real(rk) :: psi_c(3)
        real(rk) :: angle, turns
        angle = norm2(psi)
        if (angle <= pi) then
            psi_c = psi
        else
            turns = real(nint(angle / (2.0_rk * pi)), rk)
            psi_c = (1.0_rk - 2.0_rk * pi * turns / angle) * psi
        end if
    end function complement_rotation_vector

    !> Of psi and its complements psi (1 + 2 pi k / |psi|), k = -2..2 (the same rotation), the
    !> one nearest to `near`: undoes a complement (eq. 40) taken between two states, so that a
    !> step's increment is the one the rotation turned.
    pure function nearest_rotation_vector(psi, near) result(best)
        real(rk), intent(in) :: psi(3), near(3)
        real(rk) :: best(3), candidate(3), angle
        integer :: k
        best = psi
        angle = norm2(psi)
        if (angle == 0.0_rk) return
        do k = -2, 2
            candidate = psi * (1.0_rk + 2.0_rk * pi * real(k, rk) / angle)
            if (norm2(candidate - near) < norm2(best - near)) best = candidate
        end do
    end function nearest_rotation_vector
    ! Scalar coefficients of the SO(3) toolkit, functions of the angle x = |psi| >= 0
    ! (methods eqs. (74), (78), (79), (92)). Each `coef_d...` is the radial slope of the
    ! coefficient it names: d coef / d psi_k = coef_d... * psi_k.

    ! alpha = sin x / x.
    pure function coef_alpha(x) result(c)
        real(rk), intent(in) :: x
        real(rk) :: c
        if (x < so3_series_angle) then
            c = horner(series_alpha, x * x)
        else
            c = sin(x) / x
        end if
    end function coef_alpha

    ! beta/2 = (1 - cos x) / x^2.
    pure function coef_half_beta(x) result(c)
        real(rk), intent(in) :: x
        real(rk) :: c
        if (x < so3_series_angle) then
            c = horner(series_half_beta, x * x)
        else
            ! 1 - cos x = 2 sin^2(x/2) avoids the cancellation of the printed form.
            c = 0.5_rk * (sin(0.5_rk * x) / (0.5_rk * x))**2
        end if
    end function coef_half_beta

    ! (1 - alpha) / x^2 = (x - sin x) / x^3, the W^2 coefficient of T (eq. (78)).
    pure function coef_t2(x) result(c)
        real(rk), intent(in) :: x
        real(rk) :: c
        if (x < so3_series_angle) then
            c = horner(series_t2, x * x)
        else
            c = (x - sin(x)) / x**3
        end if
    end function coef_t2

    ! (1 - gamma) / x^2 with gamma = (x/2) cot(x/2), the W^2 coefficient of T^{-1} (eq. (79));
    ! valid for x < 2 pi.
    pure function coef_tinv2(x) result(c)
        real(rk), intent(in) :: x
        real(rk) :: c
        if (x < so3_series_angle) then
            c = horner(series_tinv2, x * x)
        else
            c = (1.0_rk - 0.5_rk * x * cos(0.5_rk * x) / sin(0.5_rk * x)) / x**2
        end if
    end function coef_tinv2

    ! (cos x - alpha) / x^2, slope of alpha (eq. (92)).
    pure function coef_dalpha(x) result(c)
        real(rk), intent(in) :: x
        real(rk) :: c
        if (x < so3_series_angle) then
            c = horner(series_dalpha, x * x)
        else
            c = (cos(x) - coef_alpha(x)) / x**2
        end if
    end function coef_dalpha

    ! (alpha - beta) / x^2, slope of beta/2 (eq. (92)).
    pure function coef_dhalf_beta(x) result(c)
        real(rk), intent(in) :: x
        real(rk) :: c
        if (x < so3_series_angle) then
            c = horner(series_dhalf_beta, x * x)
        else
            c = (coef_alpha(x) - 2.0_rk * coef_half_beta(x)) / x**2
        end if
    end function coef_dhalf_beta

    ! (3 alpha - 2 - cos x) / x^4, slope of coef_t2 (eq. (97), last term).
    pure function coef_dt2(x) result(c)
        real(rk), intent(in) :: x
        real(rk) :: c
        if (x < so3_series_angle) then
            c = horner(series_dt2, x * x)
        else
            c = (3.0_rk * coef_alpha(x) - 2.0_rk - cos(x)) / x**4
        end if
    end function coef_dt2

    ! -(2(1 - gamma) + gamma (1 - gamma) - x^2/4) / x^4, slope of coef_tinv2 (eq. (98) with the
    ! sign and the 1/4 of §13 items 1-2).
    pure function coef_dtinv2(x) result(c)
        real(rk), intent(in) :: x
        real(rk) :: c, g
        ! With gamma = 1 - x^2 g this is g^2 - (3 g - 1/4)/x^2. The series of 3 g - 1/4 starts
        ! at x^2, so below the threshold it is divided out term by term.
        g = coef_tinv2(x)
        if (x < so3_series_angle) then
            c = g**2 - 3.0_rk * horner(series_tinv2(2:), x * x)
        else
            c = g**2 - (3.0_rk * g - 0.25_rk) / x**2
        end if
    end function coef_dtinv2
    ! Polynomial sum coeffs(n) t^(n-1), evaluated from the highest order down.
    pure function horner(coeffs, t) result(p)
        real(rk), intent(in) :: coeffs(:), t
        real(rk) :: p
        integer :: n
        p = coeffs(size(coeffs))
        do n = size(coeffs) - 1, 1, -1
            p = coeffs(n) + t * p
        end do
    end function horner

    ! d hat(psi) / d psi_k = hat(e_k).
    pure function unit_hat(k) result(e_hat)
        integer, intent(in) :: k
        real(rk) :: e_hat(3, 3)
        e_hat = hat(unit_vector(k))
    end function unit_hat

    ! d (W^2) / d psi_k = hat(e_k) W + W hat(e_k) (methods §4.4 index identity).
    pure function square_derivative(psi, k) result(dw2)
        real(rk), intent(in) :: psi(3)
        integer, intent(in) :: k
        real(rk) :: dw2(3, 3)
        dw2 = square_directional(psi, unit_vector(k))
    end function square_derivative

    ! hat(u) hat(psi) + hat(psi) hat(u) = psi u^T + u psi^T - 2 (psi.u) 1, the derivative of
    ! hat(psi)^2 in the direction u.
    pure function square_directional(psi, u) result(dw2)
        real(rk), intent(in) :: psi(3), u(3)
        real(rk) :: dw2(3, 3)
        real(rk) :: s
        integer :: i
        dw2 = outer(psi, u) + outer(u, psi)
        s = 2.0_rk * dot_product(psi, u)
        do i = 1, 3
            dw2(i, i) = dw2(i, i) - s
        end do
    end function square_directional

    pure function outer(u, v) result(m)
        real(rk), intent(in) :: u(3), v(3)
        real(rk) :: m(3, 3)
        integer :: j
        do j = 1, 3
            m(:, j) = u * v(j)
        end do
    end function outer

    !> Unit vectors p, r with (e, p, r) a right-handed orthonormal triad, e a unit vector; p is
    !> built from the coordinate axis least aligned with e, so it is well conditioned (the
    !> hinge frames of revolute joints, rs_ph_director_tie and rs_se3_pg_tie).
    pure subroutine perpendicular_pair(e, p, r)
        real(rk), intent(in) :: e(3)
        real(rk), intent(out) :: p(3), r(3)
        real(rk) :: u(3)
        u = 0.0_rk
        u(minloc(abs(e), dim=1)) = 1.0_rk
        p = [e(2) * u(3) - e(3) * u(2), e(3) * u(1) - e(1) * u(3), e(1) * u(2) - e(2) * u(1)]
        p = p / norm2(p)
        r = [e(2) * p(3) - e(3) * p(2), e(3) * p(1) - e(1) * p(3), e(1) * p(2) - e(2) * p(1)]
    end subroutine perpendicular_pair

    !> The k-th unit vector e_k.
    pure function unit_vector(k) result(e)
        integer, intent(in) :: k
        real(rk) :: e(3)
        e = 0.0_rk
        e(k) = 1.0_rk
    end function unit_vector

end module rs_math_so3
