!> Lagrange shape functions on the reference interval [-1, 1] with equidistant nodes, degree 1
!> (nodes -1, 1) and degree 2 (nodes -1, 0, 1), and their first derivatives d/dxi.
!>
!> Node i (1-based, ascending) carries shape function N_i with N_i(node_j) = delta_ij. A degree
!> outside 1..max_lagrange_degree is a programming error of the caller: the procedures then
!> return `ok = .false.` and zero arrays.
module rs_math_lagrange
    use rs_core_kinds, only: rk
    implicit none
    private

    public :: lagrange_nodes, lagrange_shape

    !> Largest polynomial degree provided.
    integer, parameter, public :: max_lagrange_degree = 2

contains

    !> The degree + 1 equidistant nodes of the degree-`degree` element on [-1, 1], ascending.
    pure subroutine lagrange_nodes(degree, nodes, ok)
        integer, intent(in) :: degree
        real(rk), intent(out) :: nodes(degree + 1)
        logical, intent(out) :: ok
        ok = .true.
        select case (degree)
        case (1)
            nodes = [-1.0_rk, 1.0_rk]
        case (2)
            nodes = [-1.0_rk, 0.0_rk, 1.0_rk]
        case default
            ok = .false.
            nodes = 0.0_rk
        end select
    end subroutine lagrange_nodes

    !> Values N_i(xi) and derivatives dN_i/dxi of the degree + 1 shape functions at xi.
    pure subroutine lagrange_shape(degree, xi, values, derivatives, ok)
        integer, intent(in) :: degree
        real(rk), intent(in) :: xi
        real(rk), intent(out) :: values(degree + 1), derivatives(degree + 1)
        logical, intent(out) :: ok
        ok = .true.
        select case (degree)
        case (1)
            values = [0.5_rk * (1.0_rk - xi), 0.5_rk * (1.0_rk + xi)]
            derivatives = [-0.5_rk, 0.5_rk]
        case (2)
            values = [0.5_rk * xi * (xi - 1.0_rk), (1.0_rk - xi) * (1.0_rk + xi), &
                0.5_rk * xi * (xi + 1.0_rk)]
            derivatives = [xi - 0.5_rk, -2.0_rk * xi, xi + 0.5_rk]
        case default
            ok = .false.
            values = 0.0_rk
            derivatives = 0.0_rk
        end select
    end subroutine lagrange_shape

end module rs_math_lagrange
