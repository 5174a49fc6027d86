!> Gauss-Legendre quadrature with 1 to `max_gauss_points` points, on [-1, 1] and on [a, b].
!>
!> The n-point rule integrates polynomials of degree 2n - 1 exactly. Points are returned in
!> ascending order. The values are the closed forms (roots of the Legendre polynomials, e.g.
!> sqrt(3/7 -+ (2/7) sqrt(6/5)) for n = 4) tabulated to 25 significant digits, so every entry is
!> the double nearest to the exact value.
!>
!> A point count outside 1..max_gauss_points is a programming error of the caller: the
!> procedures then return `ok = .false.` and zero points and weights.
module rs_math_quadrature
    use rs_core_kinds, only: rk
    implicit none
    private

    public :: gauss_legendre, gauss_legendre_interval

    !> Largest number of points tabulated.
    integer, parameter, public :: max_gauss_points = 5

    ! Non-negative points and their weights of the n-point rules, smallest point first.
    real(rk), parameter :: x2 = 0.5773502691896257645091488_rk
    real(rk), parameter :: x3 = 0.7745966692414833770358531_rk
    real(rk), parameter :: w3_0 = 0.8888888888888888888888889_rk
    real(rk), parameter :: w3_1 = 0.5555555555555555555555556_rk
    real(rk), parameter :: x4_1 = 0.3399810435848562648026658_rk
    real(rk), parameter :: x4_2 = 0.8611363115940525752239465_rk
    real(rk), parameter :: w4_1 = 0.6521451548625461426269361_rk
    real(rk), parameter :: w4_2 = 0.3478548451374538573730639_rk
    real(rk), parameter :: x5_1 = 0.5384693101056830910363144_rk
    real(rk), parameter :: x5_2 = 0.9061798459386639927976269_rk
    real(rk), parameter :: w5_0 = 0.5688888888888888888888889_rk
    real(rk), parameter :: w5_1 = 0.4786286704993664680412915_rk
    real(rk), parameter :: w5_2 = 0.2369268850561890875142640_rk

contains

    !> Points and weights of the n-point Gauss-Legendre rule on [-1, 1]; `ok` is false (and the
    !> arrays zero) unless 1 <= n <= max_gauss_points.
    pure subroutine gauss_legendre(n, points, weights, ok)
        integer, intent(in) :: n
        real(rk), intent(out) :: points(n), weights(n)
        logical, intent(out) :: ok
        ok = .true.
        select case (n)
        case (1)
            points = [0.0_rk]
            weights = [2.0_rk]
        case (2)
            points = [-x2, x2]
            weights = [1.0_rk, 1.0_rk]
        case (3)
            points = [-x3, 0.0_rk, x3]
            weights = [w3_1, w3_0, w3_1]
        case (4)
            points = [-x4_2, -x4_1, x4_1, x4_2]
            weights = [w4_2, w4_1, w4_1, w4_2]
        case (5)
            points = [-x5_2, -x5_1, 0.0_rk, x5_1, x5_2]
            weights = [w5_2, w5_1, w5_0, w5_1, w5_2]
        case default
            ok = .false.
            points = 0.0_rk
            weights = 0.0_rk
        end select
    end subroutine gauss_legendre

    !> The n-point Gauss-Legendre rule mapped affinely to [a, b]: x = (a + b)/2 + (b - a)/2 xi,
    !> weights scaled by (b - a)/2. Same `ok` contract as `gauss_legendre`.
    pure subroutine gauss_legendre_interval(n, a, b, points, weights, ok)
        integer, intent(in) :: n
        real(rk), intent(in) :: a, b
        real(rk), intent(out) :: points(n), weights(n)
        logical, intent(out) :: ok
        real(rk) :: half_length
        call gauss_legendre(n, points, weights, ok)
        if (.not. ok) return
        half_length = 0.5_rk * (b - a)
        points = 0.5_rk * (a + b) + half_length * points
        weights = half_length * weights
    end subroutine gauss_legendre_interval

end module rs_math_quadrature
