!> Unit quaternions as rotation parameters (the alternative to the rotation vector of methods/
!> se3_petrov_galerkin.md §5.5, footnote 1).
!>
!> Conventions (docs/theory/lie_groups.md):
!> - Scalar first: q = (q0, q1, q2, q3) = (cos(angle/2), sin(angle/2) axis), stored as `q(4)`.
!> - Active rotations, the same as rs_math_so3: `quaternion_to_matrix(q)` is the matrix A with
!>   `I a = A K a`, and the quaternion of `exp_so3(psi)` is `quaternion_from_rotation_vector(psi)`.
!> - Hamilton product: `quaternion_product(p, q)` composes so that
!>   matrix(p q) = matrix(p) matrix(q) (first q, then p, as for matrices).
!> - q and -q are the same rotation. Conversions that produce a quaternion return the one with
!>   q0 >= 0, whose angle lies in [0, pi]; at exactly pi (q0 = 0) either sign may come out.
!> - `quaternion_to_matrix` accepts a non-unit q and returns the rotation of q/|q| (the form
!>   A(P) = 1 + (2/|P|^2)(p0 p~ + p~^2) of methods §5.5), so a drifting quaternion still gives
!>   an orthogonal matrix. The other procedures expect unit quaternions unless stated.
!>
!> Small angles: sin(x)/x is a Taylor polynomial below x = 1e-4 (truncation error below 1e-27).
module rs_math_quaternion
    use rs_core_kinds, only: rk
    implicit none
    private

    public :: quaternion_from_matrix, quaternion_to_matrix, quaternion_product
    public :: quaternion_conjugate, quaternion_normalize, quaternion_rotate
    public :: quaternion_from_rotation_vector, quaternion_to_rotation_vector

    ! Half-angle below which sin(x)/x uses its series 1 - x^2/6 + x^4/120.
    real(rk), parameter :: series_half_angle = 1.0e-4_rk

contains

    !> Quaternion (q0 >= 0) of the rotation matrix `a` by Shepperd's method: the largest of
    !> 4 q0^2 = 1 + tr A and 4 qi^2 = 1 + 2 A_ii - tr A is taken as the pivot, so the square
    !> root never acts on a small number and the result is accurate at every angle including pi.
    pure function quaternion_from_matrix(a) result(q)
        real(rk), intent(in) :: a(3, 3)
        real(rk) :: q(4)
        real(rk) :: trace, squares(4), s
        integer :: pivot
        trace = a(1, 1) + a(2, 2) + a(3, 3)
        squares = [1.0_rk + trace, 1.0_rk + 2.0_rk * a(1, 1) - trace, &
            1.0_rk + 2.0_rk * a(2, 2) - trace, 1.0_rk + 2.0_rk * a(3, 3) - trace]
        pivot = maxloc(squares, dim=1)
        ! 4 q_pivot^2 = squares(pivot) >= 1; the other components follow from the skew part
        ! (4 q0 qi) and the symmetric off-diagonal part (4 qi qj) of A.
        s = 0.5_rk * sqrt(squares(pivot))
        select case (pivot)
        case (1)
            q = [s, a(3, 2) - a(2, 3), a(1, 3) - a(3, 1), a(2, 1) - a(1, 2)]
        case (2)
            q = [a(3, 2) - a(2, 3), s, a(1, 2) + a(2, 1), a(1, 3) + a(3, 1)]
        case (3)
            q = [a(1, 3) - a(3, 1), a(1, 2) + a(2, 1), s, a(2, 3) + a(3, 2)]
        case default
            q = [a(2, 1) - a(1, 2), a(1, 3) + a(3, 1), a(2, 3) + a(3, 2), s]
        end select
        q(pivot) = 4.0_rk * s * s
        q = q / (4.0_rk * s)
        if (q(1) < 0.0_rk) q = -q
        q = q / norm2(q)
    end function quaternion_from_matrix

    !> Rotation matrix of the quaternion q / |q| (methods §5.5: A(P) = 1 + (2/|P|^2)(p0 p~ +
    !> p~^2)). Requires q /= 0.
    pure function quaternion_to_matrix(q) result(a)
        real(rk), intent(in) :: q(4)
        real(rk) :: a(3, 3)
        real(rk) :: s, p(3)
        integer :: i, j
        s = 2.0_rk / dot_product(q, q)
        p = q(2:4)
        ! p~^2 = p p^T - |p|^2 1.
        do j = 1, 3
            do i = 1, 3
                a(i, j) = s * p(i) * p(j)
            end do
            a(j, j) = a(j, j) + 1.0_rk - s * dot_product(p, p)
        end do
        a(3, 2) = a(3, 2) + s * q(1) * p(1)
        a(2, 3) = a(2, 3) - s * q(1) * p(1)
        a(1, 3) = a(1, 3) + s * q(1) * p(2)
        a(3, 1) = a(3, 1) - s * q(1) * p(2)
        a(2, 1) = a(2, 1) + s * q(1) * p(3)
        a(1, 2) = a(1, 2) - s * q(1) * p(3)
    end function quaternion_to_matrix

    !> Hamilton product p q = (p0 q0 - p.q, p0 q + q0 p + p x q): the rotation q followed by p.
    pure function quaternion_product(p, q) result(pq)
        real(rk), intent(in) :: p(4), q(4)
        real(rk) :: pq(4)
        pq(1) = p(1) * q(1) - dot_product(p(2:4), q(2:4))
        pq(2:4) = p(1) * q(2:4) + q(1) * p(2:4) + cross(p(2:4), q(2:4))
    end function quaternion_product

    !> Conjugate (q0, -q1, -q2, -q3): the inverse rotation of a unit quaternion.
    pure function quaternion_conjugate(q) result(q_conj)
        real(rk), intent(in) :: q(4)
        real(rk) :: q_conj(4)
        q_conj = [q(1), -q(2:4)]
    end function quaternion_conjugate

    !> q / |q|, the projection applied after each step in methods §5.5. Requires q /= 0.
    pure function quaternion_normalize(q) result(q_unit)
        real(rk), intent(in) :: q(4)
        real(rk) :: q_unit(4)
        q_unit = q / norm2(q)
    end function quaternion_normalize

    !> The vector x rotated by the unit quaternion q, A(q) x, without forming A.
    pure function quaternion_rotate(q, x) result(y)
        real(rk), intent(in) :: q(4), x(3)
        real(rk) :: y(3)
        real(rk) :: t(3)
        ! A x = x + 2 q0 (p x x) + 2 p x (p x x) for a unit quaternion (q0, p).
        t = 2.0_rk * cross(q(2:4), x)
        y = x + q(1) * t + cross(q(2:4), t)
    end function quaternion_rotate

    !> Unit quaternion of the rotation vector psi, (cos(|psi|/2), sin(|psi|/2) psi/|psi|); the
    !> same rotation as exp_so3(psi). q0 < 0 when |psi| > pi.
    pure function quaternion_from_rotation_vector(psi) result(q)
        real(rk), intent(in) :: psi(3)
        real(rk) :: q(4)
        real(rk) :: half
        half = 0.5_rk * norm2(psi)
        q = [cos(half), 0.5_rk * sinc(half) * psi]
    end function quaternion_from_rotation_vector

    !> Principal rotation vector (|psi| in [0, pi]) of the unit quaternion q; q and -q give the
    !> same vector except at exactly pi. A non-unit q is normalized first.
    pure function quaternion_to_rotation_vector(q) result(psi)
        real(rk), intent(in) :: q(4)
        real(rk) :: psi(3)
        real(rk) :: u(4), sin_half, half
        u = q / norm2(q)
        if (u(1) < 0.0_rk) u = -u
        sin_half = norm2(u(2:4))
        ! atan2 keeps the half angle accurate both near 0 (where acos(q0) is not) and near pi.
        half = atan2(sin_half, u(1))
        psi = (2.0_rk / sinc(half)) * u(2:4)
    end function quaternion_to_rotation_vector

    ! sin(x) / x for x >= 0.
    pure function sinc(x) result(s)
        real(rk), intent(in) :: x
        real(rk) :: s
        if (x < series_half_angle) then
            s = 1.0_rk - x * x / 6.0_rk * (1.0_rk - x * x / 20.0_rk)
        else
            s = sin(x) / x
        end if
    end function sinc

    pure function cross(a, b) result(c)
        real(rk), intent(in) :: a(3), b(3)
        real(rk) :: c(3)
        c = [a(2) * b(3) - a(3) * b(2), a(3) * b(1) - a(1) * b(3), a(1) * b(2) - a(2) * b(1)]
    end function cross

end module rs_math_quaternion
