!> Ties of se3_pg nodes (issue 22 item 5): joints between two rod ends (spherical, rigid,
!> revolute) and a rod end tied to a rigid end plate, in se3_pg's coordinates q = (r, psi),
!> A = Exp(psi) (methods/se3_petrov_galerkin.md §5.1; rs_math_so3 conventions: A maps K to I
!> components, A^T dA = hat(T(psi) dpsi)). The system layer's tie coupling
!> (rs_system_tie_coupling) uses them as it uses ph_director's (rs_ph_director_tie): the same
!> kinds, the same rows up to the coordinates, so a scene means the same with either.
!>
!> The rows (z = [q_a; q_b], 12 entries; a plate ties one node, z(7:12) unused):
!> - position rows (3): r_a - r_b - A_b s, s = A_b^T (r_a - r_b) in the reference (a pivot fixed
!>   in b's section; s = 0 for coinciding ends, what the input check demands up to its
!>   tolerance); a plate: r_a - c, c = centre + displacement + R (r_ref - centre);
!> - rigid (3 more): the skew part of C^T A_a^T A_b with C = A_a^T A_b in the reference,
!>   g_3+k = 1/2 (e_l^T C^T A_a^T A_b e_m - e_m^T C^T A_a^T A_b e_l), (k, l, m) cyclic: zero in
!>   the reference, invariant under a common rotation (ph_director's rows with its directors
!>   replaced by the columns of A);
!> - revolute (2 more): (A_a alpha) . (A_b gamma_j), alpha = A_a^T e and gamma_j = A_b^T p_j in
!>   the reference, (e, p_1, p_2) orthonormal, e the hinge axis;
!> - plate (3 more): the skew part of (R A_ref)^T A_a, as the rigid rows with A_a replaced by
!>   the plate's pose.
!> Every rotation row is a sum of bilinear terms u^T X^T Y v (X, Y rotations, u, v constant),
!> whose variations in the body rotations (dX = X hat(da), dY = Y hat(db)) are, with R = X^T Y,
!>   dg = da . (u x R v) + db . (v x R^T u),
!> and the variations of those (the body Hessian)
!>   d(u x R v) = hat(u) hat(R v) da - hat(u) R hat(v) db,
!>   d(v x R^T u) = -hat(v) R^T hat(u) da + hat(v) hat(R^T u) db.
!> se3_pg's rows are virtual-displacement rows (I dr, K dphi; methods eqs. 42-45), so a tie's
!> generalized force enters them in the body basis (force_gradient), while its own rows are
!> differentiated in the coordinates: dg/dpsi = (dg/dphi) T(psi) (gradient), and
!> d(force_gradient^T lambda)/dpsi = H_phi T(psi) (force_hessian). Checked against central
!> differences in tests/unit/formulations/test_se3_pg_tie.F90.
module rs_se3_pg_tie
    use rs_core_kinds, only: rk
    use rs_math_so3, only: exp_so3, hat, tangent_so3, unit_vector, perpendicular_pair
    use rs_formulations_formulation, only: node_tie_t
    implicit none
    private

    public :: se3_pg_node_tie_t, se3_pg_node_tie

    !> Bilinear terms per rotation row at most, and rotation rows at most.
    integer, parameter :: max_terms = 2, max_rotation_rows = 3

    type, extends(node_tie_t) :: se3_pg_node_tie_t
        character(len=16) :: kind = ''
        !> The pivot offset s in b's section (joints).
        real(rk) :: s(3) = 0.0_rk
        !> Rotation rows: their count and terms coef u^T X^T Y v.
        integer :: n_rotation = 0
        integer :: n_terms(max_rotation_rows) = 0
        real(rk) :: coef(max_terms, max_rotation_rows) = 0.0_rk
        real(rk) :: u(3, max_terms, max_rotation_rows) = 0.0_rk
        real(rk) :: v(3, max_terms, max_rotation_rows) = 0.0_rk
        !> A plate: the tied node's reference coordinates, the plate's pose (its rotation P
        !> applied to A_ref, and the node's target position).
        real(rk) :: q_ref(6) = 0.0_rk
        real(rk) :: pose(3, 3) = 0.0_rk
        real(rk) :: target(3) = 0.0_rk
    contains
        procedure :: place => tie_place
        procedure :: value => tie_value
        procedure :: gradient => tie_gradient
        procedure :: force_gradient => tie_force_gradient
        procedure :: force_hessian => tie_force_hessian
    end type se3_pg_node_tie_t

contains

    !> The tie of `kind` ('spherical', 'rigid', 'revolute' between nodes of reference
    !> coordinates q_a, q_b; 'plate' on the node q_a, at the plate's reference pose); `axis` the
    !> revolute hinge axis (inertial components). An unknown kind or a zero axis: n = 0.
    pure subroutine se3_pg_node_tie(kind, q_a, q_b, axis, tie)
        character(len=*), intent(in) :: kind
        real(rk), intent(in) :: q_a(6), q_b(6), axis(3)
        type(se3_pg_node_tie_t), intent(out) :: tie
        real(rk) :: a_a(3, 3), a_b(3, 3), c(3, 3), e(3), p(3, 2)
        real(rk), parameter :: zero(3) = 0.0_rk
        integer :: k
        tie%kind = kind
        tie%n_coordinates = 6
        a_a = exp_so3(q_a(4:6))
        a_b = exp_so3(q_b(4:6))
        select case (kind)
        case ('spherical', 'rigid', 'revolute')
            tie%s = matmul(transpose(a_b), q_a(1:3) - q_b(1:3))
            c = matmul(transpose(a_a), a_b)
            if (kind == 'rigid') then
                call skew_rows(tie, c)
            else if (kind == 'revolute') then
                if (norm2(axis) == 0.0_rk) return
                e = axis / norm2(axis)
                call perpendicular_pair(e, p(:, 1), p(:, 2))
                tie%n_rotation = 2
                do k = 1, 2
                    tie%n_terms(k) = 1
                    tie%coef(1, k) = 1.0_rk
                    tie%u(:, 1, k) = matmul(transpose(a_a), e)
                    tie%v(:, 1, k) = matmul(transpose(a_b), p(:, k))
                end do
            end if
        case ('plate')
            tie%q_ref = q_a
            call skew_rows(tie, reshape([1.0_rk, 0.0_rk, 0.0_rk, 0.0_rk, 1.0_rk, 0.0_rk, &
                0.0_rk, 0.0_rk, 1.0_rk], [3, 3]))
            call tie%place(zero, zero, zero)
        case default
            return
        end select
        tie%n = 3 + tie%n_rotation
    end subroutine se3_pg_node_tie

    !> The three rows of the skew part of C^T X^T Y (rigid joint: C the reference relative
    !> rotation; plate: C = 1, X the plate's pose of the reference).
    pure subroutine skew_rows(tie, c)
        type(se3_pg_node_tie_t), intent(inout) :: tie
        real(rk), intent(in) :: c(3, 3)
        integer :: k, l, m
        tie%n_rotation = 3
        do k = 1, 3
            l = modulo(k, 3) + 1
            m = modulo(k + 1, 3) + 1
            tie%n_terms(k) = 2
            tie%coef(:, k) = [0.5_rk, -0.5_rk]
            tie%u(:, 1, k) = c(:, l)
            tie%v(:, 1, k) = unit_vector(m)
            tie%u(:, 2, k) = c(:, m)
            tie%v(:, 2, k) = unit_vector(l)
        end do
    end subroutine skew_rows

    !> A plate's pose: turned by R = exp(rotation) about `centre`, moved by `displacement`.
    pure subroutine tie_place(this, centre, displacement, rotation)
        class(se3_pg_node_tie_t), intent(inout) :: this
        real(rk), intent(in) :: centre(3), displacement(3), rotation(3)
        real(rk) :: r(3, 3)
        if (this%kind /= 'plate') return
        r = exp_so3(rotation)
        this%pose = matmul(r, exp_so3(this%q_ref(4:6)))
        this%target = centre + displacement + matmul(r, this%q_ref(1:3) - centre)
    end subroutine tie_place

    !> X and Y of the rotation rows at z: (A_a, A_b) for a joint, (plate pose, A_a) for a plate.
    pure subroutine rotations(this, z, x, y)
        type(se3_pg_node_tie_t), intent(in) :: this
        real(rk), intent(in) :: z(:)
        real(rk), intent(out) :: x(3, 3), y(3, 3)
        if (this%kind == 'plate') then
            x = this%pose
            y = exp_so3(z(4:6))
        else
            x = exp_so3(z(4:6))
            y = exp_so3(z(10:12))
        end if
    end subroutine rotations

    pure subroutine tie_value(this, z, g)
        class(se3_pg_node_tie_t), intent(in) :: this
        real(rk), intent(in) :: z(:)
        real(rk), intent(out) :: g(:)
        real(rk) :: x(3, 3), y(3, 3), r(3, 3)
        integer :: k, t
        call rotations(this, z, x, y)
        if (this%kind == 'plate') then
            g(1:3) = z(1:3) - this%target
        else
            g(1:3) = z(1:3) - z(7:9) - matmul(y, this%s)
        end if
        r = matmul(transpose(x), y)
        do k = 1, this%n_rotation
            g(3 + k) = 0.0_rk
            do t = 1, this%n_terms(k)
                g(3 + k) = g(3 + k) + this%coef(t, k) * dot_product(this%u(:, t, k), &
                    matmul(r, this%v(:, t, k)))
            end do
        end do
    end subroutine tie_value

    !> dg/d(r_a, phi_a, r_b, phi_b): the rows in the body basis of the rotations (module header).
    pure subroutine tie_force_gradient(this, z, gradient)
        class(se3_pg_node_tie_t), intent(in) :: this
        real(rk), intent(in) :: z(:)
        real(rk), intent(out) :: gradient(:, :)
        real(rk) :: x(3, 3), y(3, 3), r(3, 3), ga(3), gb(3)
        integer :: k, t, i
        call rotations(this, z, x, y)
        gradient = 0.0_rk
        do i = 1, 3
            gradient(i, i) = 1.0_rk
            if (this%kind /= 'plate') gradient(i, 6 + i) = -1.0_rk
        end do
        ! -Y s varies by Y hat(s) db.
        if (this%kind /= 'plate') gradient(1:3, 10:12) = matmul(y, hat(this%s))
        r = matmul(transpose(x), y)
        do k = 1, this%n_rotation
            do t = 1, this%n_terms(k)
                ga = matmul(hat(this%u(:, t, k)), matmul(r, this%v(:, t, k)))
                gb = matmul(hat(this%v(:, t, k)), matmul(transpose(r), this%u(:, t, k)))
                if (this%kind == 'plate') then
                    gradient(3 + k, 4:6) = gradient(3 + k, 4:6) + this%coef(t, k) * gb
                else
                    gradient(3 + k, 4:6) = gradient(3 + k, 4:6) + this%coef(t, k) * ga
                    gradient(3 + k, 10:12) = gradient(3 + k, 10:12) + this%coef(t, k) * gb
                end if
            end do
        end do
    end subroutine tie_force_gradient

    !> dg/dz in the coordinates: the body columns times T(psi) of their node.
    pure subroutine tie_gradient(this, z, gradient)
        class(se3_pg_node_tie_t), intent(in) :: this
        real(rk), intent(in) :: z(:)
        real(rk), intent(out) :: gradient(:, :)
        call this%force_gradient(z, gradient)
        gradient(:, 4:6) = matmul(gradient(:, 4:6), tangent_so3(z(4:6)))
        if (this%kind /= 'plate') gradient(:, 10:12) = matmul(gradient(:, 10:12), &
            tangent_so3(z(10:12)))
    end subroutine tie_gradient

    !> d(force_gradient(z)^T lambda)/dz in the coordinates (module header).
    pure subroutine tie_force_hessian(this, z, lambda, hessian)
        class(se3_pg_node_tie_t), intent(in) :: this
        real(rk), intent(in) :: z(:), lambda(:)
        real(rk), intent(out) :: hessian(:, :)
        real(rk) :: x(3, 3), y(3, 3), r(3, 3), w(3), c
        real(rk) :: haa(3, 3), hab(3, 3), hba(3, 3), hbb(3, 3)
        integer :: k, t
        call rotations(this, z, x, y)
        haa = 0.0_rk
        hab = 0.0_rk
        hba = 0.0_rk
        hbb = 0.0_rk
        if (this%kind /= 'plate') then
            ! d((Y hat(s))^T lambda) = -hat(s) hat(Y^T lambda) db.
            w = matmul(transpose(y), lambda(1:3))
            hbb = -matmul(hat(this%s), hat(w))
        end if
        r = matmul(transpose(x), y)
        do k = 1, this%n_rotation
            do t = 1, this%n_terms(k)
                c = lambda(3 + k) * this%coef(t, k)
                associate (u => this%u(:, t, k), v => this%v(:, t, k))
                    haa = haa + c * matmul(hat(u), hat(matmul(r, v)))
                    hab = hab - c * matmul(matmul(hat(u), r), hat(v))
                    hba = hba - c * matmul(matmul(hat(v), transpose(r)), hat(u))
                    hbb = hbb + c * matmul(hat(v), hat(matmul(transpose(r), u)))
                end associate
            end do
        end do
        hessian = 0.0_rk
        if (this%kind == 'plate') then
            ! The node is Y of the rotation rows.
            hessian(4:6, 4:6) = matmul(hbb, tangent_so3(z(4:6)))
        else
            hessian(4:6, 4:6) = matmul(haa, tangent_so3(z(4:6)))
            hessian(4:6, 10:12) = matmul(hab, tangent_so3(z(10:12)))
            hessian(10:12, 4:6) = matmul(hba, tangent_so3(z(4:6)))
            hessian(10:12, 10:12) = matmul(hbb, tangent_so3(z(10:12)))
        end if
    end subroutine tie_force_hessian

end module rs_se3_pg_tie
