!> A rigid body on a rod's end node in director form (issue 24 item 4: a tip mass, a payload):
!> pure kernels on plain arrays, no allocation (STYLE.md item 4).
!>
!> The body is rigidly attached to the end's cross-section: its material points are
!> X(xi) = phi + sum_i xi_i d_i with body coordinates xi in the node's director basis (phi the
!> node's centreline point, d_i its directors). Its kinetic energy is then a constant quadratic
!> form in the node's velocities v = (v_phi, w_1, w_2, w_3) (12):
!>
!>     T = 1/2 integral rho |v_phi + sum_i xi_i w_i|^2 = 1/2 v^T M_b v,
!>     M_b = [[m I, m c_j I], [m c_i I, E_ij I]],  E_ij = integral rho xi_i xi_j = E^cm_ij + m c_i c_j,
!>
!> with m the mass, c the centre of mass (body coordinates) and E^cm = tr(J)/2 I - J the
!> Euler tensor of the inertia tensor J about the centre of mass (body components). This is the
!> director form of rigid body dynamics (Betsch and Steinmann 2001): for orthonormal directors
!> T = 1/2 m |v_c|^2 + 1/2 omega . J omega exactly. Because M_b is constant, the body's inertia
!> adds to the node's momentum rows as the rod's own consistent mass does, and the midpoint
!> rule with the nodal orthonormality constraints of methods/ph_director_3d.md §5.3 item 2
!> keeps the energy (T is quadratic: the discrete gradient is the midpoint gradient, Remark
!> 4.2), the linear momentum p = M_b v (its phi part) and the angular momentum
!> phi x p_phi + sum_i d_i x p_i.
!>
!> Its weight m g acts at its centre of mass phi + sum_i c_i d_i, a point linear in the node's
!> coordinates q: the generalized force is (m g, c_1 m g, c_2 m g, c_3 m g), whose work over a
!> step is exactly minus the change of the potential -m g . (phi + sum_i c_i d_i).
module rs_ph_director_body
    use rs_core_kinds, only: rk
    use rs_math_so3, only: hat
    implicit none
    private

    !> A body on node `node` of the rod (0: none).
    type, public :: ph_director_body_t
        integer :: node = 0
        real(rk) :: mass = 0.0_rk
        !> Centre of mass c in the node's director basis.
        real(rk) :: centre(3) = 0.0_rk
        !> The mass matrix M_b (12, 12) in the node's velocities.
        real(rk) :: mass_matrix(12, 12) = 0.0_rk
    end type ph_director_body_t

    public :: ph_director_body_init, ph_director_body_kinetic_energy
    public :: ph_director_body_momenta, ph_director_body_weight, ph_director_body_centre

contains

    !> The body of mass `mass` with its centre of mass `centre` relative to the node's point
    !> and its inertia tensor `inertia` (3, 3) about the centre of mass, both in inertial
    !> components at the node's reference directors `directors` (3, 3: column i is d_i).
    pure function ph_director_body_init(node, mass, centre, inertia, directors) result(body)
        integer, intent(in) :: node
        real(rk), intent(in) :: mass, centre(3), inertia(3, 3), directors(3, 3)
        type(ph_director_body_t) :: body
        real(rk) :: j_body(3, 3), second(3, 3)
        integer :: i, j, l
        body%node = node
        body%mass = mass
        body%centre = matmul(transpose(directors), centre)
        j_body = matmul(transpose(directors), matmul(inertia, directors))
        ! Symmetric to the last bit (the products of the turn round differently).
        j_body = 0.5_rk * (j_body + transpose(j_body))
        ! E = tr(J)/2 I - J about the centre of mass, moved to the node: + m c c^T.
        second = -j_body
        do i = 1, 3
            second(i, i) = second(i, i) + 0.5_rk * (j_body(1, 1) + j_body(2, 2) + j_body(3, 3))
        end do
        do j = 1, 3
            do i = 1, 3
                second(i, j) = second(i, j) + mass * (body%centre(i) * body%centre(j))
            end do
        end do
        body%mass_matrix = 0.0_rk
        do l = 1, 3
            body%mass_matrix(l, l) = mass
            do i = 1, 3
                body%mass_matrix(l, 3 * i + l) = mass * body%centre(i)
                body%mass_matrix(3 * i + l, l) = mass * body%centre(i)
                do j = 1, 3
                    body%mass_matrix(3 * i + l, 3 * j + l) = second(i, j)
                end do
            end do
        end do
    end function ph_director_body_init

    !> T = 1/2 v^T M_b v of the node's velocities v (12).
    pure real(rk) function ph_director_body_kinetic_energy(body, v) result(energy)
        type(ph_director_body_t), intent(in) :: body
        real(rk), intent(in) :: v(12)
        energy = 0.5_rk * dot_product(v, matmul(body%mass_matrix, v))
    end function ph_director_body_kinetic_energy

    !> Linear momentum p_phi and angular momentum phi x p_phi + sum_i d_i x p_i (about the
    !> origin) of the body, p = M_b v, at the node's coordinates q and velocities v.
    pure subroutine ph_director_body_momenta(body, q, v, linear, angular)
        type(ph_director_body_t), intent(in) :: body
        real(rk), intent(in) :: q(12), v(12)
        real(rk), intent(out) :: linear(3), angular(3)
        real(rk) :: p(12)
        integer :: i
        p = matmul(body%mass_matrix, v)
        linear = p(1:3)
        angular = matmul(hat(q(1:3)), p(1:3))
        do i = 1, 3
            angular = angular + matmul(hat(q(3 * i + 1:3 * i + 3)), p(3 * i + 1:3 * i + 3))
        end do
    end subroutine ph_director_body_momenta

    !> The generalized force (12) of the body's weight m g on the node's coordinates.
    pure function ph_director_body_weight(body, acceleration) result(force)
        type(ph_director_body_t), intent(in) :: body
        real(rk), intent(in) :: acceleration(3)
        real(rk) :: force(12)
        integer :: i
        force(1:3) = body%mass * acceleration
        do i = 1, 3
            force(3 * i + 1:3 * i + 3) = body%centre(i) * body%mass * acceleration
        end do
    end function ph_director_body_weight

    !> The body's centre of mass phi + sum_i c_i d_i at the node's coordinates q.
    pure function ph_director_body_centre(body, q) result(x)
        type(ph_director_body_t), intent(in) :: body
        real(rk), intent(in) :: q(12)
        real(rk) :: x(3)
        x = q(1:3) + body%centre(1) * q(4:6) + body%centre(2) * q(7:9) + &
            body%centre(3) * q(10:12)
    end function ph_director_body_centre

end module rs_ph_director_body
