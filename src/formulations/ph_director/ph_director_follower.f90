!> Follower loads of the port-Hamiltonian director rod (issue 26 item 2; seed 000,
!> methods/ph_director_3d.md): end and distributed forces and moments whose components are
!> given in the director basis, n = sum_j n_j d_j and m = sum_j m_j d_j (&load frame =
!> 'follower'), with their exact Jacobians. Pure kernels on plain arrays, in the layouts of
!> rs_ph_director_element (q = (phi, d1, d2, d3); Jacobians with respect to q_{n+1}).
!>
!> A follower load is a state-dependent input u(x) of the port-Hamiltonian system (methods §4.3
!> eq. 33). The midpoint rule evaluates it at the midpoint state, u_mid = u(x_mid, t_mid) (the
!> directors d_mid = (d_n + d_{n+1})/2, methods §5.1), and enters it in the momentum rows as a
!> dead load of that value would enter (methods §5.2 (M1), (M2): -h n, -h 1/2 m x d_i). The
!> energy proof of methods §5.3 item 1 uses only that the momentum rows are tested with v_mid,
!> so H_{n+1} - H_n = h y_mid . u_mid for any u_mid: the work booked with the same u_mid,
!> W_n = h [n_mid . v_phi,mid + 1/2 sum_i (m_mid x d_i,mid) . v_i,mid] (the dead-load work of
!> §5.3 item 1 at the midpoint value), balances the step exactly. A `static` step (the endpoint
!> equilibrium of a quasistatic run) evaluates at t_{n+1} instead, as the element kernels do.
!>
!> The interpolated directors are not orthonormal between the nodes (methods §4.1), so a
!> distributed follower load at a Gauss point is taken in the interpolated basis d_j^h: the
!> same discretization error as the strains', vanishing with the mesh.
module rs_ph_director_follower
    use rs_core_kinds, only: rk
    use rs_math_so3, only: hat
    use rs_ph_director_element, only: ph_director_basis_t
    implicit none
    private

    public :: ph_director_follower_vector, ph_director_node_follower
    public :: ph_director_element_follower, ph_director_element_follower_work

contains

    !> The spatial vector sum_j c_j d_j of components c in the director basis d (9: d1, d2, d3).
    pure function ph_director_follower_vector(d, c) result(v)
        real(rk), intent(in) :: d(9), c(3)
        real(rk) :: v(3)
        v = c(1) * d(1:3) + c(2) * d(4:6) + c(3) * d(7:9)
    end function ph_director_follower_vector

    !> Momentum rows (node layout 13:24, here 1:12) of a follower force and moment with
    !> components `force`, `moment` at a node (methods §5.2 (M1), (M2) at d_mid): -h n and
    !> -h/2 m x d_i with n = sum_j force_j d_j,mid, m = sum_j moment_j d_j,mid; and their
    !> derivatives with respect to q_{n+1} (columns 1:12): d(-h n)/d d_j = -theta h force_j I,
    !> d(-h/2 m x d_i)/d d_k = theta h/2 (moment_k hat(d_i) - delta_ik hat(m)), theta = 1/2
    !> (1 for a static step).
    pure subroutine ph_director_node_follower(h, static, q_n, q_1, force, moment, residual, &
            jacobian)
        real(rk), intent(in) :: h
        logical, intent(in) :: static
        real(rk), intent(in) :: q_n(12), q_1(12), force(3), moment(3)
        real(rk), intent(out) :: residual(12)
        real(rk), intent(out), optional :: jacobian(12, 12)
        real(rk) :: d(9), theta
        theta = merge(1.0_rk, 0.5_rk, static)
        d = q_n(4:12) + theta * (q_1(4:12) - q_n(4:12))
        call follower_rows(d, force, moment, -h, residual)
        if (present(jacobian)) call follower_tangent(d, force, moment, -theta * h, jacobian)
    end subroutine ph_director_node_follower

    !> Momentum rows of a distributed follower force and moment per unit length with components
    !> `force`, `moment` on one element, residual(12, a) for node a (the v rows of its local
    !> layout), and their derivatives jacobian(12, a, 12, b) with respect to q_{n+1} of node b:
    !> the node kernel's rows at the interpolated midpoint directors d^h(s_g), weighted by
    !> N_a (and N_b) le/2 w_g (methods §4.3: n̄ enters as int N_a n̄, m̄ as int N_a T(d^h) m̄).
    pure subroutine ph_director_element_follower(basis, le, h, static, q_n, q_1, force, moment, &
            residual, jacobian)
        type(ph_director_basis_t), intent(in) :: basis
        real(rk), intent(in) :: le, h
        logical, intent(in) :: static
        real(rk), intent(in) :: q_n(12, basis%nen), q_1(12, basis%nen), force(3), moment(3)
        real(rk), intent(out) :: residual(12, basis%nen)
        real(rk), intent(out), optional :: jacobian(12, basis%nen, 12, basis%nen)
        real(rk) :: q_t(12, basis%nen), d(9), r(12), j(12, 12), weight, theta
        integer :: g, a, b
        theta = merge(1.0_rk, 0.5_rk, static)
        q_t = q_n + theta * (q_1 - q_n)
        residual = 0.0_rk
        if (present(jacobian)) jacobian = 0.0_rk
        do g = 1, basis%n_gauss
            associate (nn => basis%shape(1:basis%nen, g))
                d = matmul(q_t(4:12, :), nn)
                weight = 0.5_rk * le * basis%w(g)
                call follower_rows(d, force, moment, -h * weight, r)
                if (present(jacobian)) call follower_tangent(d, force, moment, &
                    -theta * h * weight, j)
                do a = 1, basis%nen
                    residual(:, a) = residual(:, a) + nn(a) * r
                    if (.not. present(jacobian)) cycle
                    do b = 1, basis%nen
                        jacobian(:, a, :, b) = jacobian(:, a, :, b) + nn(a) * nn(b) * j
                    end do
                end do
            end associate
        end do
    end subroutine ph_director_element_follower

    !> The work of a distributed follower load on one element in one step, computed as the
    !> element residual tests it (module header): h int [n . u_phi + 1/2 sum_i (m x d_i) . u_i]
    !> ds with the midpoint directors and velocities u = (v_n + v_1)/2 interpolated at the Gauss
    !> points.
    pure function ph_director_element_follower_work(basis, le, h, q_n, q_1, v_n, v_1, force, &
            moment) result(work)
        type(ph_director_basis_t), intent(in) :: basis
        real(rk), intent(in) :: le, h
        real(rk), intent(in) :: q_n(12, basis%nen), q_1(12, basis%nen)
        real(rk), intent(in) :: v_n(12, basis%nen), v_1(12, basis%nen), force(3), moment(3)
        real(rk) :: work
        real(rk) :: d(9), u(12), r(12)
        integer :: g
        work = 0.0_rk
        do g = 1, basis%n_gauss
            d = 0.5_rk * matmul(q_n(4:12, :) + q_1(4:12, :), basis%shape(1:basis%nen, g))
            u = 0.5_rk * matmul(v_n + v_1, basis%shape(1:basis%nen, g))
            ! The rows with the factor -1 are the generalized force (n, 1/2 m x d_i).
            call follower_rows(d, force, moment, 1.0_rk, r)
            work = work + 0.5_rk * le * basis%w(g) * dot_product(r, u)
        end do
        work = h * work
    end function ph_director_element_follower_work

    !> factor (n, 1/2 m x d_1, 1/2 m x d_2, 1/2 m x d_3) with n, m the follower vectors at d.
    pure subroutine follower_rows(d, force, moment, factor, rows)
        real(rk), intent(in) :: d(9), force(3), moment(3), factor
        real(rk), intent(out) :: rows(12)
        real(rk) :: m_hat(3, 3)
        integer :: i
        m_hat = hat(ph_director_follower_vector(d, moment))
        rows(1:3) = factor * ph_director_follower_vector(d, force)
        do i = 1, 3
            rows(3 * i + 1:3 * i + 3) = 0.5_rk * factor * matmul(m_hat, d(3 * i - 2:3 * i))
        end do
    end subroutine follower_rows

    !> factor times the derivative of follower_rows (factor 1) with respect to d (columns 4:12;
    !> the phi columns 1:3 are zero): d n / d d_j = force_j I, d(1/2 m x d_i)/d d_k =
    !> 1/2 (-moment_k hat(d_i) + delta_ik hat(m)).
    pure subroutine follower_tangent(d, force, moment, factor, tangent)
        real(rk), intent(in) :: d(9), force(3), moment(3), factor
        real(rk), intent(out) :: tangent(12, 12)
        real(rk) :: m_hat(3, 3), eye(3, 3)
        integer :: i, k, l
        eye = 0.0_rk
        do l = 1, 3
            eye(l, l) = 1.0_rk
        end do
        m_hat = hat(ph_director_follower_vector(d, moment))
        tangent = 0.0_rk
        do k = 1, 3
            tangent(1:3, 3 * k + 1:3 * k + 3) = factor * force(k) * eye
            do i = 1, 3
                tangent(3 * i + 1:3 * i + 3, 3 * k + 1:3 * k + 3) = &
                    -0.5_rk * factor * moment(k) * hat(d(3 * i - 2:3 * i))
            end do
            tangent(3 * k + 1:3 * k + 3, 3 * k + 1:3 * k + 3) = &
                tangent(3 * k + 1:3 * k + 3, 3 * k + 1:3 * k + 3) + 0.5_rk * factor * m_hat
        end do
    end subroutine follower_tangent

end module rs_ph_director_follower
