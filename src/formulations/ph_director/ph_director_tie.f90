!> Constraint kernels of joints between two ph_director nodes and of rod ends tied to a rigid
!> end plate (issue 10; methods/ph_director_3d.md §5, DESIGN.md §3, §5). Pure procedures on
!> plain arrays: no PETSc, no MPI, no allocation (STYLE.md item 4).
!>
!> Representation. A tie is n <= 6 holonomic constraint rows on z = [q_a; q_b] (24 entries,
!> q = (phi, d1, d2, d3) as in rs_ph_director_element; a one-node tie, the plate, uses z(1:12)
!> and has zero b-parts), each row quadratic:
!>   g_k(z) = 1/2 z^T A_k z + b_k^T z + c_k,   A_k symmetric,
!>   G(z) = dg/dz, row k = (A_k z + b_k)^T.
!> Because every row is quadratic, the midpoint gradient is an exact discrete gradient,
!>   g(z_1) - g(z_n) = G(z_mid) (z_1 - z_n),   z_mid = (z_n + z_1)/2,
!> the property that gives the nodal orthonormality rows their exactness (methods §5.3 item 2).
!> Dense A is deliberate: a scene has few ties, and one generic form serves every kind.
!>
!> How the midpoint step uses a tie (methods §5.1, §5.2, §5.6; the rows of the two nodes are
!> those of ph_director_node_residual, momentum rows scaled by h, constraint rows not):
!> - momentum (v) rows of the two nodes: + h G(z_t)^T lambda, z_t = z_mid (z_{n+1} in a static
!>   step), lambda the multiplier of the step;
!> - constraint rows: g(z_{n+1}) = 0, imposed at the endpoint like the orthonormality rows
!>   (DESIGN.md §3), so a tie holds to round-off and does not drift with the Newton tolerance;
!> - Newton blocks: d(momentum)/dz_{n+1} = theta h sum_k lambda_k A_k (theta = 1/2 midpoint, 1
!>   static; ph_director_tie_hessian), d(momentum)/dlambda = h G(z_t)^T, d(constraint)/dz_{n+1}
!>   = G(z_{n+1}) (ph_director_tie_gradient).
!> What this keeps (tested in tests/unit/formulations/test_ph_director_tie.F90):
!> - energy: the constraint forces do work -lambda^T G(z_mid)(z_{n+1} - z_n) = -lambda^T
!>   (g(z_{n+1}) - g(z_n)) = 0 on the rods for a time-independent tie (joints, a fixed plate);
!> - linear and angular momentum (joints): every joint row is invariant under a common
!>   translation, the rotation rows under a common rotation of both nodes, and the position
!>   rows rotate with it (g(Rz) = R g(z)). Hence G(z)^T lambda has zero net force at every z
!>   and zero net torque (about the origin, at the positions and directors of z) where the
!>   position rows vanish; they are linear, so they vanish at z_mid when they hold at both
!>   endpoints.
!> - a plate whose pose changes in time does work on the rods: with the tie of the pose used in
!>   the step, W = -lambda^T G (z_{n+1} - z_n), booked as the plate's work in the energy
!>   balance. A plate exerts net force and torque (it is a support).
!>
!> Rows (reference values: the tie holds in the reference configuration passed in):
!> - spherical (3 rows): phi_a - phi_b - sum_j s_j d_b^j, s_j = d_b^j . (phi_a - phi_b) in the
!>   reference. The pivot is node a's position, a point fixed in b's section: for coinciding
!>   reference ends (what the input check demands, up to its tolerance) s = 0 and the rows are
!>   phi_a - phi_b; a residual reference gap is carried along instead of being closed by the
!>   first step. Linear.
!> - rigid (6 rows): the 3 position rows and 3 rotation rows. With C_ij = d_a^i . d_b^j in the
!>   reference, the targets t^j = sum_i C_ij d_a^i equal d_b^j in the reference, and
!>     g_3+k = 1/2 (t^l . d_b^m - t^m . d_b^l),   (k, l, m) cyclic,
!>   the skew part of C^T D, D_ij = d_a^i . d_b^j the relative rotation. Bilinear in (d_a,
!>   d_b), invariant under a common rotation, zero in the reference. Near it, with the nodes
!>   turned by small spatial rotation vectors w_a, w_b (the motions orthonormality leaves),
!>   g_3+k = (w_a - w_b) . d_b^k: independent of each other and of the orthonormality rows.
!>   A rotation of b alone by the angle theta about a unit u gives g_3+k = -sin(theta) u.d_b^k
!>   exactly. (C^T D is also symmetric at half turns: a spurious root far from the reference.)
!>   Nine rows d_b^j - t^j would repeat 6 orthonormality rows (DESIGN.md §5: duplicates make
!>   the system singular); these 3 leave both nodes their own orthonormality rows.
!> - revolute (5 rows): the 3 position rows and 2 rows keeping the hinge axis e = axis/|axis|
!>   fixed in both sections: with alpha_i = e . d_a^i, and p, r unit vectors with (e, p, r)
!>   orthonormal, gamma1_j = p . d_b^j, gamma2_j = r . d_b^j (reference values),
!>     g_4 = (sum_i alpha_i d_a^i) . (sum_j gamma1_j d_b^j),   g_5 likewise with gamma2:
!>   the axis carried by a stays perpendicular to p and r carried by b. Bilinear, invariant
!>   under a common rotation; a relative rotation about the axis keeps them zero, one about
!>   a perpendicular u gives (g_4, g_5) = sin(theta) (e . (u x p), e . (u x r)); linearized,
!>   (w_a - w_b) . (e x p) and (w_a - w_b) . (e x r).
!> - plate (one node, 6 rows): the plate's reference pose moved by `displacement` and turned by
!>   R = exp(rotation) about `centre` carries the tied node to position c = centre +
!>   displacement + R (phi_ref - centre) and directors t^j = R d_ref^j:
!>     g_k = phi_k - c_k,   g_3+k = 1/2 (t^l . d^m - t^m . d^l),   (k, l, m) cyclic.
!>   Linear in q (A = 0); linearized about the target, g_3+k = -w . t^k.
!> Orthonormality of each node's directors is imposed elsewhere (ph_director_node_constraint,
!> 6 rows per node); no tie row repeats it: at the reference [tie rows; orthonormality rows of
!> the tied nodes] has full row rank, n + 12 for a joint, n + 6 for a plate.
module rs_ph_director_tie
    use rs_core_kinds, only: rk
    use rs_math_so3, only: exp_so3, perpendicular_pair
    implicit none
    private

    public :: ph_director_tie_t
    public :: ph_director_joint_tie, ph_director_plate_tie
    public :: ph_director_tie_value, ph_director_tie_gradient, ph_director_tie_hessian

    !> Largest number of rows of a tie.
    integer, parameter, public :: ph_director_tie_max_rows = 6
    !> Size of the tie's unknowns z = [q_a; q_b].
    integer, parameter, public :: ph_director_tie_size = 24

    !> Holonomic constraint rows g_k(z) = 1/2 z^T A_k z + b_k^T z + c_k, k = 1..n, on z =
    !> [q_a; q_b] (module header). A one-node tie (two_nodes false) has zero b-parts. An empty
    !> tie (n = 0) is what the constructors return for invalid arguments.
    type :: ph_director_tie_t
        !> Number of constraint rows.
        integer :: n = 0
        !> The tie couples two nodes (joint) or ties one node (plate; z(13:24) unused).
        logical :: two_nodes = .true.
        !> Symmetric Hessians A_k of the rows.
        real(rk) :: a(ph_director_tie_size, ph_director_tie_size, ph_director_tie_max_rows) &
            = 0.0_rk
        !> Linear parts b_k of the rows.
        real(rk) :: b(ph_director_tie_size, ph_director_tie_max_rows) = 0.0_rk
        !> Constant parts c_k of the rows.
        real(rk) :: c(ph_director_tie_max_rows) = 0.0_rk
    end type ph_director_tie_t

    ! Offsets in z of phi_a, phi_b (the director d^i of node a starts at 3 i, of b at 12 + 3 i).
    integer, parameter :: node_a = 0, node_b = 12

contains

    !> The joint of `kind` ('spherical', 'rigid' or 'revolute') between nodes a and b whose
    !> reference nodal coordinates q_a, q_b satisfy it (module header). `axis` is the revolute
    !> hinge axis in the reference (inertial components, any nonzero length; ignored by the
    !> other kinds). An unknown kind or a zero revolute axis gives the empty tie (n = 0); the
    !> input check (rs_io_input_check) reports those before any tie is built.
    pure function ph_director_joint_tie(kind, q_a, q_b, axis) result(tie)
        character(len=*), intent(in) :: kind
        real(rk), intent(in) :: q_a(12), q_b(12), axis(3)
        type(ph_director_tie_t) :: tie
        real(rk) :: c(3, 3), e(3), p(3), r(3), alpha(3), gamma(3, 2)
        integer :: i, j, k, l, m

        select case (kind)
        case ('spherical', 'rigid')
        case ('revolute')
            if (norm2(axis) <= 0.0_rk) return
        case default
            return
        end select
        tie%two_nodes = .true.
        call add_position_rows(tie, q_a, q_b)

        select case (kind)
        case ('rigid')
            do i = 1, 3
                do j = 1, 3
                    c(i, j) = dot_product(director(q_a, i), director(q_b, j))
                end do
            end do
            ! Row k = 1/2 sum_i (C_il d_a^i . d_b^m - C_im d_a^i . d_b^l).
            do k = 1, 3
                l = cyclic(k + 1)
                m = cyclic(k + 2)
                do i = 1, 3
                    call add_bilinear(tie, 3 + k, node_a + 3 * i, node_b + 3 * m, &
                        0.5_rk * c(i, l))
                    call add_bilinear(tie, 3 + k, node_a + 3 * i, node_b + 3 * l, &
                        -0.5_rk * c(i, m))
                end do
            end do
            tie%n = 6
        case ('revolute')
            e = axis / norm2(axis)
            call perpendicular_pair(e, p, r)
            do i = 1, 3
                alpha(i) = dot_product(e, director(q_a, i))
                gamma(i, 1) = dot_product(p, director(q_b, i))
                gamma(i, 2) = dot_product(r, director(q_b, i))
            end do
            do k = 1, 2
                do i = 1, 3
                    do j = 1, 3
                        call add_bilinear(tie, 3 + k, node_a + 3 * i, node_b + 3 * j, &
                            alpha(i) * gamma(j, k))
                    end do
                end do
            end do
            tie%n = 5
        case default
            tie%n = 3
        end select
    end function ph_director_joint_tie

    !> One node tied to a rigid plate (module header): q_ref are its reference nodal
    !> coordinates, and the plate's reference pose has moved by `displacement` and turned by the
    !> rotation vector `rotation` (exp_so3) about `centre` (all inertial components). Zero
    !> motion ties the node to its reference pose.
    pure function ph_director_plate_tie(q_ref, centre, displacement, rotation) result(tie)
        real(rk), intent(in) :: q_ref(12), centre(3), displacement(3), rotation(3)
        type(ph_director_tie_t) :: tie
        real(rk) :: rot(3, 3), t(3, 3)
        integer :: j, k, l, m

        rot = exp_so3(rotation)
        tie%two_nodes = .false.
        tie%n = 6
        do k = 1, 3
            tie%b(node_a + k, k) = 1.0_rk
        end do
        tie%c(1:3) = -(centre + displacement + matmul(rot, q_ref(1:3) - centre))
        do j = 1, 3
            t(:, j) = matmul(rot, director(q_ref, j))
        end do
        ! Row 3 + k = 1/2 (t^l . d^m - t^m . d^l).
        do k = 1, 3
            l = cyclic(k + 1)
            m = cyclic(k + 2)
            tie%b(node_a + 3 * m + 1:node_a + 3 * m + 3, 3 + k) = 0.5_rk * t(:, l)
            tie%b(node_a + 3 * l + 1:node_a + 3 * l + 3, 3 + k) = -0.5_rk * t(:, m)
        end do
    end function ph_director_plate_tie

    !> Values g_k(z), k = 1..n, of the tie's rows at z = [q_a; q_b].
    pure function ph_director_tie_value(tie, z) result(g)
        type(ph_director_tie_t), intent(in) :: tie
        real(rk), intent(in) :: z(ph_director_tie_size)
        real(rk) :: g(tie%n)
        integer :: k
        do k = 1, tie%n
            g(k) = 0.5_rk * dot_product(z, matmul(tie%a(:, :, k), z)) &
                + dot_product(tie%b(:, k), z) + tie%c(k)
        end do
    end function ph_director_tie_value

    !> Gradient G(z) = dg/dz (n x 24): row k is (A_k z + b_k)^T. At z_mid it is the exact
    !> discrete gradient of the step (module header).
    pure function ph_director_tie_gradient(tie, z) result(gz)
        type(ph_director_tie_t), intent(in) :: tie
        real(rk), intent(in) :: z(ph_director_tie_size)
        real(rk) :: gz(tie%n, ph_director_tie_size)
        integer :: k
        do k = 1, tie%n
            gz(k, :) = matmul(tie%a(:, :, k), z) + tie%b(:, k)
        end do
    end function ph_director_tie_gradient

    !> d(G(z)^T lambda)/dz = sum_k lambda_k A_k (24 x 24, symmetric, constant in z); lambda
    !> has the n multipliers of the tie. The midpoint Newton block is theta h times this.
    pure function ph_director_tie_hessian(tie, lambda) result(hz)
        type(ph_director_tie_t), intent(in) :: tie
        real(rk), intent(in) :: lambda(:)
        real(rk) :: hz(ph_director_tie_size, ph_director_tie_size)
        integer :: k
        hz = 0.0_rk
        do k = 1, min(tie%n, size(lambda))
            hz = hz + lambda(k) * tie%a(:, :, k)
        end do
    end function ph_director_tie_hessian

    ! The position rows of a joint, k = 1..3: phi_a - phi_b - sum_j s_j d_b^j with the
    ! reference offset s_j = d_b^j . (phi_a - phi_b) of the pivot in b's section.
    pure subroutine add_position_rows(tie, q_a, q_b)
        type(ph_director_tie_t), intent(inout) :: tie
        real(rk), intent(in) :: q_a(12), q_b(12)
        real(rk) :: s
        integer :: j, k
        do k = 1, 3
            tie%b(node_a + k, k) = 1.0_rk
            tie%b(node_b + k, k) = -1.0_rk
        end do
        do j = 1, 3
            s = dot_product(director(q_b, j), q_a(1:3) - q_b(1:3))
            do k = 1, 3
                tie%b(node_b + 3 * j + k, k) = -s
            end do
        end do
    end subroutine add_position_rows

    ! Add coef x . y to row k, x = z(i0 + 1:i0 + 3) and y = z(j0 + 1:j0 + 3) in different
    ! nodes: the blocks (i0, j0) and (j0, i0) of A_k get coef I, so 1/2 z^T A_k z gains coef x.y.
    pure subroutine add_bilinear(tie, k, i0, j0, coef)
        type(ph_director_tie_t), intent(inout) :: tie
        integer, intent(in) :: k, i0, j0
        real(rk), intent(in) :: coef
        integer :: l
        do l = 1, 3
            tie%a(i0 + l, j0 + l, k) = tie%a(i0 + l, j0 + l, k) + coef
            tie%a(j0 + l, i0 + l, k) = tie%a(j0 + l, i0 + l, k) + coef
        end do
    end subroutine add_bilinear

    ! Director i of nodal coordinates q.
    pure function director(q, i) result(d)
        real(rk), intent(in) :: q(12)
        integer, intent(in) :: i
        real(rk) :: d(3)
        d = q(3 * i + 1:3 * i + 3)
    end function director

    ! 1, 2, 3 for i = 1, 2, 3 and 4, 5 (the cyclic successors).
    pure integer function cyclic(i)
        integer, intent(in) :: i
        cyclic = modulo(i - 1, 3) + 1
    end function cyclic

    pure function cross(a, b) result(c)
        real(rk), intent(in) :: a(3), b(3)
        real(rk) :: c(3)
        c = [a(2) * b(3) - a(3) * b(2), a(3) * b(1) - a(1) * b(3), a(1) * b(2) - a(2) * b(1)]
    end function cross

end module rs_ph_director_tie
