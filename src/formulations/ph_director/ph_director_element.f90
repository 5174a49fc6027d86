!> Element and node kernels of the port-Hamiltonian director rod (formulation `ph_director`,
!> seed 000, methods/ph_director_3d.md): residuals and Jacobians of one implicit-midpoint step,
!> energies, momenta and strains. Pure procedures on plain arrays: no PETSc, no MPI, no
!> allocation (DESIGN.md §2, STYLE.md item 4).
!>
!> Conventions (fixed; the assembly relies on them):
!> - Node unknowns q = (phi, d1, d2, d3) in R^12 (components 1:3 phi, 4:6 d1, 7:9 d2,
!>   10:12 d3); velocities v = (v_phi, v_d1, v_d2, v_d3) likewise (methods §2.1, §2.6).
!> - An element of degree p in {1, 2} has nen = p + 1 nodes, ordered along s as the nodes of
!>   `rs_math_lagrange` (xi = -1, 1 for p = 1; xi = -1, 0, 1 for p = 2); ds = le/2 dxi with le
!>   the reference arc length of the element.
!> - Stresses are discontinuous P^{p-1} (methods §4.1): p coefficients per component, s(6, p)
!>   with components (N1, N2, N3, M1, M2, M3) in the material frame. Basis: psi = 1 for p = 1;
!>   for p = 2 the linear Lagrange functions of the stress points xi = -1/sqrt(3), +1/sqrt(3), so
!>   coefficients are values there and the 2-point Gauss compliance matrix is diagonal (§4.4).
!> - Element local layout, size nloc = 24 nen + 6 p: entries 24(a-1) + 1..12 are q_a,
!>   24(a-1) + 13..24 are v_a, then 24 nen + 6(b-1) + k is stress component k of coefficient b.
!>   Residual rows use the same layout: the q rows of an element are zero (the kinematic rows
!>   are nodal), the v rows hold the momentum residual R_M, the stress rows R_S (§5.6).
!> - Node local layout, size 30: q (1:12), v (13:24), the midpoint multiplier
!>   lambda = (l11, l22, l33, l12, l23, l31) (25:30) (§2.1 order, §5.2 last bullet).
!> - Time step: implicit midpoint (§5.1, §5.2). Kernels take endpoint values at t_n (`_n`) and
!>   t_{n+1} (`_1`) and form midpoint values themselves; Jacobians are derivatives with respect
!>   to the t_{n+1} unknowns (and lambda_mid), so they contain the 1/2 of the midpoint.
!> - Straight stress-free reference: Gamma_0 = (0, 0, 1), K_0 = 0 (methods §2.1, Remark 2.1).
!> - Loads (nbar, mbar distributed per unit length, force and moment at nodes) are spatial
!>   vectors at t_mid; a moment m acts on director i as 1/2 m x d_i (T(d) m, methods §2.5).
!> - All integrals use the element's Gauss rule, including mass and compliance matrices, so the
!>   discrete energy balance holds exactly for any rule (methods §4.6(a), §5.3).
module rs_ph_director_element
    use rs_core_kinds, only: rk
    use rs_math_quadrature, only: gauss_legendre, max_gauss_points
    use rs_math_lagrange, only: lagrange_shape
    use rs_math_so3, only: hat
    implicit none
    private

    public :: ph_director_material_t, ph_director_basis_t
    public :: ph_director_basis_init, ph_director_basis_shape, ph_director_stress_shape
    public :: ph_director_local_size
    public :: ph_director_element_residual, ph_director_node_residual
    public :: ph_director_element_kinetic_energy, ph_director_element_complementary_energy
    public :: ph_director_element_momenta, ph_director_element_position_integral
    public :: ph_director_element_external_work, ph_director_node_external_work
    public :: ph_director_element_strains, ph_director_node_constraint

    !> Largest element degree (quadratic elements).
    integer, parameter, public :: ph_director_max_degree = 2
    !> Largest number of nodes of an element.
    integer, parameter, public :: ph_director_max_nodes = ph_director_max_degree + 1
    !> Size of the node local layout: q (12), v (12), lambda (6).
    integer, parameter, public :: ph_director_node_size = 30

    !> Section properties of a rod (methods §2.3, §2.4): line density rhoA, director inertias
    !> rhoI = (M_rho^11, M_rho^22) (the d3 block has no mass), and the diagonal compliance
    !> (1/GA1, 1/GA2, 1/EA, 1/EI1, 1/EI2, 1/GJ). A zero compliance is a rigid component
    !> (methods §2.3); kernels never divide by it.
    type :: ph_director_material_t
        !> Mass per unit length.
        real(rk) :: rhoA = 0.0_rk
        !> Second moments of mass M_rho^11, M_rho^22 of the cross-section (principal axes).
        real(rk) :: rhoI(2) = 0.0_rk
        !> Diagonal of C = blockdiag(C_N, C_M), material frame.
        real(rk) :: compliance(6) = 0.0_rk
    end type ph_director_material_t

    !> Reference-element data of one (degree, Gauss rule) pair, built by ph_director_basis_init.
    !> Arrays have the maximal size; only the leading nen, n_gauss and degree entries are used.
    type :: ph_director_basis_t
        !> Polynomial degree p of the q and v interpolation (1 or 2).
        integer :: degree = 0
        !> Nodes per element, p + 1.
        integer :: nen = 0
        !> Gauss points of the element rule (1 .. max_gauss_points).
        integer :: n_gauss = 0
        !> Gauss points xi_g on [-1, 1].
        real(rk) :: xi(max_gauss_points) = 0.0_rk
        !> Gauss weights w_g on [-1, 1] (ds = le/2 w_g).
        real(rk) :: w(max_gauss_points) = 0.0_rk
        !> shape(a, g) = N_a(xi_g).
        real(rk) :: shape(ph_director_max_nodes, max_gauss_points) = 0.0_rk
        !> dshape(a, g) = dN_a/dxi at xi_g.
        real(rk) :: dshape(ph_director_max_nodes, max_gauss_points) = 0.0_rk
        !> psi(b, g): stress basis function b at xi_g.
        real(rk) :: psi(ph_director_max_degree, max_gauss_points) = 0.0_rk
        !> Stress points (nodes of the stress basis): 0 for p = 1, -+1/sqrt(3) for p = 2.
        real(rk) :: stress_xi(ph_director_max_degree) = 0.0_rk
    end type ph_director_basis_t

contains

    !> Build the reference-element data for `degree` (1 or 2) and an `n_gauss`-point Gauss
    !> rule (1 .. max_gauss_points); `ok` is false (and `basis` empty) for other values.
    pure subroutine ph_director_basis_init(basis, degree, n_gauss, ok)
        type(ph_director_basis_t), intent(out) :: basis
        integer, intent(in) :: degree, n_gauss
        logical, intent(out) :: ok
        real(rk) :: points(2), weights(2)
        integer :: g
        ok = degree >= 1 .and. degree <= ph_director_max_degree .and. n_gauss >= 1 &
            .and. n_gauss <= max_gauss_points
        if (.not. ok) return
        basis%degree = degree
        basis%nen = degree + 1
        basis%n_gauss = n_gauss
        call gauss_legendre(n_gauss, basis%xi(1:n_gauss), basis%w(1:n_gauss), ok)
        if (.not. ok) return
        if (degree == 1) then
            basis%stress_xi(1) = 0.0_rk
        else
            ! The stress points are the 2-point Gauss points, taken from the same table so that
            ! psi_b(xi_g) is exactly delta_bg under 2-point Gauss (methods §4.4, §4.6(a)).
            call gauss_legendre(2, points, weights, ok)
            basis%stress_xi(1:2) = points
        end if
        do g = 1, n_gauss
            call ph_director_basis_shape(basis, basis%xi(g), basis%shape(1:basis%nen, g), &
                basis%dshape(1:basis%nen, g))
            call ph_director_stress_shape(basis, basis%xi(g), basis%psi(1:degree, g))
        end do
    end subroutine ph_director_basis_init

    !> Shape functions N_a(xi) and derivatives dN_a/dxi of the nen element nodes at any xi.
    pure subroutine ph_director_basis_shape(basis, xi, values, derivatives)
        type(ph_director_basis_t), intent(in) :: basis
        real(rk), intent(in) :: xi
        real(rk), intent(out) :: values(basis%nen), derivatives(basis%nen)
        logical :: ok
        call lagrange_shape(basis%degree, xi, values, derivatives, ok)
    end subroutine ph_director_basis_shape

    !> Stress basis functions psi_b(xi), b = 1..degree: 1 for p = 1; for p = 2 the linear
    !> Lagrange functions of the stress points (methods §4.4, §9 item 12).
    pure subroutine ph_director_stress_shape(basis, xi, psi)
        type(ph_director_basis_t), intent(in) :: basis
        real(rk), intent(in) :: xi
        real(rk), intent(out) :: psi(basis%degree)
        real(rk) :: x1, x2
        if (basis%degree == 1) then
            psi(1) = 1.0_rk
        else
            x1 = basis%stress_xi(1)
            x2 = basis%stress_xi(2)
            psi(1) = (x2 - xi) / (x2 - x1)
            psi(2) = (xi - x1) / (x2 - x1)
        end if
    end subroutine ph_director_stress_shape

    !> Size 24 nen + 6 p of the element local layout.
    pure integer function ph_director_local_size(basis) result(nloc)
        type(ph_director_basis_t), intent(in) :: basis
        nloc = 24 * basis%nen + 6 * basis%degree
    end function ph_director_local_size

    !> Residual (and optionally Jacobian with respect to q_1, v_1, s_1) of one element in one
    !> implicit-midpoint step, methods/ph_director_3d.md §5.2 (M1), (M2), (S1), (S2) and §5.6:
    !>   R_M = M_e (v_1 - v_n) + h [f_int(q_mid, s_mid) - f_ext(nbar, mbar, q_mid)]   (v rows)
    !>   R_S = C_e (s_1 - s_n) - h int psi_b eps_dot(q_mid, v_mid) ds             (stress rows)
    !> q rows are zero. nbar, mbar: distributed spatial force and moment per unit length at
    !> t_mid, constant over the element (gravity: nbar = rhoA g).
    pure subroutine ph_director_element_residual(basis, material, le, h, q_n, q_1, v_n, v_1, &
            s_n, s_1, nbar, mbar, residual, jacobian)
        type(ph_director_basis_t), intent(in) :: basis
        type(ph_director_material_t), intent(in) :: material
        real(rk), intent(in) :: le, h
        real(rk), intent(in) :: q_n(12, basis%nen), q_1(12, basis%nen)
        real(rk), intent(in) :: v_n(12, basis%nen), v_1(12, basis%nen)
        real(rk), intent(in) :: s_n(6, basis%degree), s_1(6, basis%degree)
        real(rk), intent(in) :: nbar(3), mbar(3)
        real(rk), intent(out) :: residual(24 * basis%nen + 6 * basis%degree)
        real(rk), intent(out), optional :: jacobian(24 * basis%nen + 6 * basis%degree, &
            24 * basis%nen + 6 * basis%degree)
        real(rk) :: q_mid(12, ph_director_max_nodes), v_mid(12, ph_director_max_nodes)
        real(rk) :: dv(12, ph_director_max_nodes), s_mid(6, ph_director_max_degree)
        real(rk) :: ds_(6, ph_director_max_degree), mass(12)
        real(rk) :: nn(ph_director_max_nodes), bb(ph_director_max_nodes)
        real(rk) :: psi(ph_director_max_degree)
        ! Midpoint fields at a Gauss point: phi', d_i, d_i', v_phi', v_i, v_i' (columns i).
        real(rk) :: phi_s(3), d(3, 3), d_s(3, 3), vphi_s(3), vd(3, 3), vd_s(3, 3)
        real(rk) :: sig(6), force(12), rate(6), n_spatial(3), m_hat(3, 3), eye(3, 3)
        real(rk) :: wds, c, mab, wab, cpsi
        integer :: nen, p, g, a, b, cc, i, j, k, ra, rb, rs, cs, l
        logical :: with_jacobian

        nen = basis%nen
        p = basis%degree
        with_jacobian = present(jacobian)
        q_mid(:, 1:nen) = 0.5_rk * (q_n + q_1)
        v_mid(:, 1:nen) = 0.5_rk * (v_n + v_1)
        dv(:, 1:nen) = v_1 - v_n
        s_mid(:, 1:p) = 0.5_rk * (s_n + s_1)
        ds_(:, 1:p) = s_1 - s_n
        ! M_o = blockdiag(rhoA I, M^11 I, M^22 I, 0) (methods §2.4, §2.6 eq. 20)
        mass(1:3) = material%rhoA
        mass(4:6) = material%rhoI(1)
        mass(7:9) = material%rhoI(2)
        mass(10:12) = 0.0_rk
        m_hat = hat(mbar)
        eye = 0.0_rk
        do l = 1, 3
            eye(l, l) = 1.0_rk
        end do

        residual = 0.0_rk
        if (with_jacobian) jacobian = 0.0_rk

        do g = 1, basis%n_gauss
            nn(1:nen) = basis%shape(1:nen, g)
            bb(1:nen) = basis%dshape(1:nen, g) * (2.0_rk / le)
            psi(1:p) = basis%psi(1:p, g)
            wds = basis%w(g) * 0.5_rk * le
            c = 0.5_rk * h * wds
            ! Midpoint fields and their s-derivatives at the Gauss point (methods §4.4).
            phi_s = matmul(q_mid(1:3, 1:nen), bb(1:nen))
            d = reshape(matmul(q_mid(4:12, 1:nen), nn(1:nen)), [3, 3])
            d_s = reshape(matmul(q_mid(4:12, 1:nen), bb(1:nen)), [3, 3])
            vphi_s = matmul(v_mid(1:3, 1:nen), bb(1:nen))
            vd = reshape(matmul(v_mid(4:12, 1:nen), nn(1:nen)), [3, 3])
            vd_s = reshape(matmul(v_mid(4:12, 1:nen), bb(1:nen)), [3, 3])
            sig = matmul(s_mid(:, 1:p), psi(1:p))
            ! n = R N = N_i d_i (methods §2.3 eq. 7)
            n_spatial = matmul(d, sig(1:3))

            ! Strain rates eps_dot = (Gamma_dot, K_dot) at q_mid, v_mid (methods §2.2, §2.6
            ! eq. 18): Gamma_dot_i = d_i . v_phi' + phi' . v_i and, with (i, j, k) cyclic,
            ! K_dot_i = 1/2 [(d_j' . v_k - d_j . v_k') - (d_k' . v_j - d_k . v_j')].
            do i = 1, 3
                j = mod(i, 3) + 1
                k = mod(i + 1, 3) + 1
                rate(i) = dot_product(d(:, i), vphi_s) + dot_product(phi_s, vd(:, i))
                rate(3 + i) = 0.5_rk * (dot_product(d_s(:, j), vd(:, k)) &
                    - dot_product(d(:, j), vd_s(:, k)) - dot_product(d_s(:, k), vd(:, j)) &
                    + dot_product(d(:, k), vd_s(:, j)))
            end do

            do a = 1, nen
                ra = 24 * (a - 1) + 12
                ! Inertia: consistent mass from the same Gauss rule (methods §4.3 eq. 112).
                do b = 1, nen
                    mab = wds * nn(a) * nn(b)
                    rb = 24 * (b - 1) + 12
                    residual(ra + 1:ra + 12) = residual(ra + 1:ra + 12) + mab * mass * dv(:, b)
                    if (with_jacobian) then
                        do l = 1, 12
                            jacobian(ra + l, rb + l) = jacobian(ra + l, rb + l) + mab * mass(l)
                        end do
                    end if
                end do
                ! Internal forces (methods §4.4): r_phi,a = int N_a' n;
                ! r_di,a = int N_a N_i phi' + N_a (L(d')^T M)_i - N_a' (L(d)^T M)_i with
                ! (L(d)^T M)_i = 1/2 (M_j d_k - M_k d_j), (i, j, k) cyclic (methods §2.2).
                ! External: - int N_a nbar, - int N_a 1/2 mbar x d_i (T(d) mbar, §2.5, §4.3).
                force(1:3) = bb(a) * n_spatial - nn(a) * nbar
                do i = 1, 3
                    j = mod(i, 3) + 1
                    k = mod(i + 1, 3) + 1
                    force(3 * i + 1:3 * i + 3) = nn(a) * sig(i) * phi_s &
                        + 0.5_rk * sig(3 + j) * (nn(a) * d_s(:, k) - bb(a) * d(:, k)) &
                        - 0.5_rk * sig(3 + k) * (nn(a) * d_s(:, j) - bb(a) * d(:, j)) &
                        - 0.5_rk * nn(a) * cross(mbar, d(:, i))
                end do
                residual(ra + 1:ra + 12) = residual(ra + 1:ra + 12) + h * wds * force
            end do

            ! Compliance-rate rows (methods §4.4, §5.2 (S1), (S2)).
            do b = 1, p
                rs = 24 * nen + 6 * (b - 1)
                residual(rs + 1:rs + 6) = residual(rs + 1:rs + 6) - h * wds * psi(b) * rate
                do cc = 1, p
                    residual(rs + 1:rs + 6) = residual(rs + 1:rs + 6) &
                        + wds * psi(b) * psi(cc) * material%compliance * ds_(:, cc)
                end do
            end do

            if (.not. with_jacobian) cycle

            ! Jacobian (methods §5.6): every midpoint quantity enters with the factor 1/2, hence
            ! c = h wds / 2 on the geometric and stress-coupling blocks.
            do a = 1, nen
                ra = 24 * (a - 1) + 12
                do b = 1, nen
                    rb = 24 * (b - 1)
                    wab = nn(a) * bb(b) - bb(a) * nn(b)
                    do i = 1, 3
                        j = mod(i, 3) + 1
                        k = mod(i + 1, 3) + 1
                        ! d f_phi,a / d d_i,b = N_a' N_i N_b I
                        call add_block(jacobian, ra, rb + 3 * i, c * bb(a) * sig(i) * nn(b) * eye)
                        ! d f_di,a / d phi_b = N_a N_i N_b' I
                        call add_block(jacobian, ra + 3 * i, rb, c * nn(a) * sig(i) * bb(b) * eye)
                        ! d(-1/2 N_a mbar x d_i) / d d_i,b = -1/2 N_a N_b mbar^
                        call add_block(jacobian, ra + 3 * i, rb + 3 * i, &
                            -0.5_rk * c * nn(a) * nn(b) * m_hat)
                        ! bending/torsion: d/d d_k,b = 1/2 M_j W_ab I, d/d d_j,b = -1/2 M_k W_ab I
                        call add_block(jacobian, ra + 3 * i, rb + 3 * k, &
                            0.5_rk * c * sig(3 + j) * wab * eye)
                        call add_block(jacobian, ra + 3 * i, rb + 3 * j, &
                            -0.5_rk * c * sig(3 + k) * wab * eye)
                    end do
                end do
                ! Stress columns: psi_c times the coefficient of sigma in f (methods §5.6).
                do cc = 1, p
                    cs = 24 * nen + 6 * (cc - 1)
                    cpsi = c * psi(cc)
                    do i = 1, 3
                        j = mod(i, 3) + 1
                        k = mod(i + 1, 3) + 1
                        ! f_phi,a = N_a' N_i d_i and f_di,a = N_a N_i phi' + ...
                        call add_column(jacobian, ra, cs + i, cpsi * bb(a) * d(:, i))
                        call add_column(jacobian, ra + 3 * i, cs + i, cpsi * nn(a) * phi_s)
                        ! ... + 1/2 M_j (N_a d_k' - N_a' d_k) - 1/2 M_k (N_a d_j' - N_a' d_j)
                        call add_column(jacobian, ra + 3 * i, cs + 3 + j, &
                            0.5_rk * cpsi * (nn(a) * d_s(:, k) - bb(a) * d(:, k)))
                        call add_column(jacobian, ra + 3 * i, cs + 3 + k, &
                            -0.5_rk * cpsi * (nn(a) * d_s(:, j) - bb(a) * d(:, j)))
                    end do
                end do
            end do

            ! Stress rows: -h/2 psi_c d(eps_dot)/d(q_mid, v_mid), and C_e.
            do cc = 1, p
                rs = 24 * nen + 6 * (cc - 1)
                cpsi = -c * psi(cc)
                do b = 1, nen
                    rb = 24 * (b - 1)
                    do i = 1, 3
                        j = mod(i, 3) + 1
                        k = mod(i + 1, 3) + 1
                        ! Gamma_dot_i: d/d d_i = N_b v_phi'^T, d/d phi = N_b' v_i^T,
                        ! d/d v_phi = N_b' d_i^T, d/d v_i = N_b phi'^T
                        call add_row(jacobian, rs + i, rb + 3 * i, cpsi * nn(b) * vphi_s)
                        call add_row(jacobian, rs + i, rb, cpsi * bb(b) * vd(:, i))
                        call add_row(jacobian, rs + i, rb + 12, cpsi * bb(b) * d(:, i))
                        call add_row(jacobian, rs + i, rb + 12 + 3 * i, cpsi * nn(b) * phi_s)
                        ! K_dot_i: d/d d_j = 1/2 (N_b' v_k - N_b v_k')^T,
                        ! d/d d_k = -1/2 (N_b' v_j - N_b v_j')^T,
                        ! d/d v_k = 1/2 (N_b d_j' - N_b' d_j)^T,
                        ! d/d v_j = -1/2 (N_b d_k' - N_b' d_k)^T
                        call add_row(jacobian, rs + 3 + i, rb + 3 * j, &
                            0.5_rk * cpsi * (bb(b) * vd(:, k) - nn(b) * vd_s(:, k)))
                        call add_row(jacobian, rs + 3 + i, rb + 3 * k, &
                            -0.5_rk * cpsi * (bb(b) * vd(:, j) - nn(b) * vd_s(:, j)))
                        call add_row(jacobian, rs + 3 + i, rb + 12 + 3 * k, &
                            0.5_rk * cpsi * (nn(b) * d_s(:, j) - bb(b) * d(:, j)))
                        call add_row(jacobian, rs + 3 + i, rb + 12 + 3 * j, &
                            -0.5_rk * cpsi * (nn(b) * d_s(:, k) - bb(b) * d(:, k)))
                    end do
                end do
                ! C_e = int psi_b psi_c diag(compliance) ds (methods §4.3 eq. 113)
                do b = 1, p
                    cs = 24 * nen + 6 * (b - 1)
                    do l = 1, 6
                        jacobian(rs + l, cs + l) = jacobian(rs + l, cs + l) &
                            + wds * psi(cc) * psi(b) * material%compliance(l)
                    end do
                end do
            end do
        end do
    end subroutine ph_director_element_residual

    !> Residual (and optionally Jacobian with respect to q_1, v_1, lambda) of the nodal rows of
    !> one node in one implicit-midpoint step (methods §5.2 (K1), (K2), §5.6, DESIGN.md §3):
    !>   q rows: R_K = q_1 - q_n - h/2 (v_1 + v_n)
    !>   v rows: + h G_d(d_mid)^T lambda - h force (phi) - h 1/2 moment x d_i,mid (director i)
    !>   lambda rows: g(d_1) (the constraint imposed at the endpoint, methods §5.3 item 2).
    !> lambda is the midpoint multiplier. force and moment are the concentrated spatial loads at
    !> t_mid (zero at interior nodes). Without `with_lambda` (a clamped node, methods §4.6(c))
    !> the lambda rows are identity rows with residual lambda and lambda does not enter the v rows.
    pure subroutine ph_director_node_residual(h, q_n, q_1, v_n, v_1, lambda, with_lambda, force, &
            moment, residual, jacobian)
        real(rk), intent(in) :: h
        real(rk), intent(in) :: q_n(12), q_1(12), v_n(12), v_1(12), lambda(6)
        logical, intent(in) :: with_lambda
        real(rk), intent(in) :: force(3), moment(3)
        real(rk), intent(out) :: residual(ph_director_node_size)
        real(rk), intent(out), optional :: jacobian(ph_director_node_size, ph_director_node_size)
        real(rk) :: d_mid(9), lam(3, 3), gd(6, 9), m_hat(3, 3)
        integer :: i, j, l

        d_mid = 0.5_rk * (q_n(4:12) + q_1(4:12))
        residual(1:12) = q_1 - q_n - 0.5_rk * h * (v_1 + v_n)
        residual(13:15) = -h * force
        do i = 1, 3
            residual(12 + 3 * i + 1:12 + 3 * i + 3) = &
                -0.5_rk * h * cross(moment, d_mid(3 * i - 2:3 * i))
        end do
        if (with_lambda) then
            ! G_d(d)^T lambda, block i = sum_j S_ij d_j with the symmetric S of methods §5.6
            lam = multiplier_matrix(lambda)
            do i = 1, 3
                do j = 1, 3
                    residual(12 + 3 * i + 1:12 + 3 * i + 3) = &
                        residual(12 + 3 * i + 1:12 + 3 * i + 3) &
                        + h * lam(i, j) * d_mid(3 * j - 2:3 * j)
                end do
            end do
            residual(25:30) = ph_director_node_constraint(q_1)
        else
            residual(25:30) = lambda
        end if

        if (.not. present(jacobian)) return
        jacobian = 0.0_rk
        do l = 1, 12
            jacobian(l, l) = 1.0_rk
            jacobian(l, 12 + l) = -0.5_rk * h
        end do
        ! moment term: d(-h/2 moment x d_i,mid)/d d_i,1 = -h/4 moment^
        m_hat = hat(moment)
        do i = 1, 3
            jacobian(12 + 3 * i + 1:12 + 3 * i + 3, 3 * i + 1:3 * i + 3) = -0.25_rk * h * m_hat
        end do
        if (with_lambda) then
            do i = 1, 3
                do j = 1, 3
                    do l = 1, 3
                        jacobian(12 + 3 * i + l, 3 * j + l) = jacobian(12 + 3 * i + l, 3 * j + l) &
                            + 0.5_rk * h * lam(i, j)
                    end do
                end do
            end do
            gd = constraint_jacobian(d_mid)
            jacobian(16:24, 25:30) = h * transpose(gd)
            jacobian(25:30, 4:12) = constraint_jacobian(q_1(4:12))
        else
            do l = 25, 30
                jacobian(l, l) = 1.0_rk
            end do
        end if
    end subroutine ph_director_node_residual

    !> Kinetic energy 1/2 v^T M_e v of one element with the element's Gauss rule (methods §4.3
    !> eq. 35); v(12, nen) nodal velocities.
    pure function ph_director_element_kinetic_energy(basis, material, le, v) result(energy)
        type(ph_director_basis_t), intent(in) :: basis
        type(ph_director_material_t), intent(in) :: material
        real(rk), intent(in) :: le
        real(rk), intent(in) :: v(12, basis%nen)
        real(rk) :: energy
        real(rk) :: u(12)
        integer :: g
        energy = 0.0_rk
        do g = 1, basis%n_gauss
            u = matmul(v, basis%shape(1:basis%nen, g))
            energy = energy + 0.25_rk * le * basis%w(g) * (material%rhoA * sum(u(1:3)**2) &
                + material%rhoI(1) * sum(u(4:6)**2) + material%rhoI(2) * sum(u(7:9)**2))
        end do
    end function ph_director_element_kinetic_energy

    !> Complementary energy 1/2 s^T C_e s of one element with the element's Gauss rule
    !> (methods §2.3 eq. 9, §4.3 eq. 35); s(6, p) stress coefficients.
    pure function ph_director_element_complementary_energy(basis, material, le, s) result(energy)
        type(ph_director_basis_t), intent(in) :: basis
        type(ph_director_material_t), intent(in) :: material
        real(rk), intent(in) :: le
        real(rk), intent(in) :: s(6, basis%degree)
        real(rk) :: energy
        real(rk) :: sig(6)
        integer :: g
        energy = 0.0_rk
        do g = 1, basis%n_gauss
            sig = matmul(s, basis%psi(1:basis%degree, g))
            energy = energy + 0.25_rk * le * basis%w(g) * sum(material%compliance * sig**2)
        end do
    end function ph_director_element_complementary_energy

    !> Linear and angular momentum (about the origin) of one element in the bilinear mass-matrix
    !> form the scheme conserves (methods §5.3 items 4, 5; §9 item 3):
    !>   linear = sum_ab M_ab rhoA v_phi,b,
    !>   angular = sum_ab M_ab [rhoA phi_a x v_phi,b + sum_alpha M^aa d_alpha,a x v_alpha,b],
    !> with M_ab = int N_a N_b ds under the element's Gauss rule.
    pure subroutine ph_director_element_momenta(basis, material, le, q, v, linear, angular)
        type(ph_director_basis_t), intent(in) :: basis
        type(ph_director_material_t), intent(in) :: material
        real(rk), intent(in) :: le
        real(rk), intent(in) :: q(12, basis%nen), v(12, basis%nen)
        real(rk), intent(out) :: linear(3), angular(3)
        real(rk) :: mab
        integer :: g, a, b
        linear = 0.0_rk
        angular = 0.0_rk
        do g = 1, basis%n_gauss
            do a = 1, basis%nen
                do b = 1, basis%nen
                    mab = 0.5_rk * le * basis%w(g) * basis%shape(a, g) * basis%shape(b, g)
                    linear = linear + mab * material%rhoA * v(1:3, b)
                    angular = angular + mab * (material%rhoA * cross(q(1:3, a), v(1:3, b)) &
                        + material%rhoI(1) * cross(q(4:6, a), v(4:6, b)) &
                        + material%rhoI(2) * cross(q(7:9, a), v(7:9, b)))
                end do
            end do
        end do
    end subroutine ph_director_element_momenta

    !> int phi^h ds over the element with its Gauss rule (centre of mass = sum / L for uniform
    !> rhoA; methods §6.1 r^h).
    pure function ph_director_element_position_integral(basis, le, q) result(integral)
        type(ph_director_basis_t), intent(in) :: basis
        real(rk), intent(in) :: le
        real(rk), intent(in) :: q(12, basis%nen)
        real(rk) :: integral(3)
        integer :: g
        integral = 0.0_rk
        do g = 1, basis%n_gauss
            integral = integral + 0.5_rk * le * basis%w(g) &
                * matmul(q(1:3, 1:basis%nen), basis%shape(1:basis%nen, g))
        end do
    end function ph_director_element_position_integral

    !> Work of the distributed loads in one step, h v_mid . f_ext with f_ext the external part of
    !> the element residual: h int [nbar . v_phi + sum_i 1/2 (mbar x d_i) . v_i] ds at the
    !> midpoint (methods §4.3 eq. 117, §5.3 item 1).
    pure function ph_director_element_external_work(basis, le, h, q_n, q_1, v_n, v_1, nbar, &
            mbar) result(work)
        type(ph_director_basis_t), intent(in) :: basis
        real(rk), intent(in) :: le, h
        real(rk), intent(in) :: q_n(12, basis%nen), q_1(12, basis%nen)
        real(rk), intent(in) :: v_n(12, basis%nen), v_1(12, basis%nen)
        real(rk), intent(in) :: nbar(3), mbar(3)
        real(rk) :: work
        real(rk) :: x(12), u(12), power
        integer :: g, i
        work = 0.0_rk
        do g = 1, basis%n_gauss
            x = 0.5_rk * matmul(q_n + q_1, basis%shape(1:basis%nen, g))
            u = 0.5_rk * matmul(v_n + v_1, basis%shape(1:basis%nen, g))
            power = dot_product(nbar, u(1:3))
            do i = 1, 3
                power = power + 0.5_rk * dot_product(cross(mbar, x(3 * i + 1:3 * i + 3)), &
                    u(3 * i + 1:3 * i + 3))
            end do
            work = work + 0.5_rk * le * basis%w(g) * power
        end do
        work = h * work
    end function ph_director_element_external_work

    !> Work of concentrated end loads at a node in one step (methods §5.3 item 1):
    !> h [force . v_phi,mid + sum_i 1/2 (moment x d_i,mid) . v_i,mid].
    pure function ph_director_node_external_work(h, q_n, q_1, v_n, v_1, force, moment) result(work)
        real(rk), intent(in) :: h
        real(rk), intent(in) :: q_n(12), q_1(12), v_n(12), v_1(12)
        real(rk), intent(in) :: force(3), moment(3)
        real(rk) :: work
        real(rk) :: x(12), u(12)
        integer :: i
        x = 0.5_rk * (q_n + q_1)
        u = 0.5_rk * (v_n + v_1)
        work = dot_product(force, u(1:3))
        do i = 1, 3
            work = work + 0.5_rk * dot_product(cross(moment, x(3 * i + 1:3 * i + 3)), &
                u(3 * i + 1:3 * i + 3))
        end do
        work = h * work
    end function ph_director_node_external_work

    !> Displacement-derived strains at the stress points (xi = 0 for p = 1, -+1/sqrt(3) for
    !> p = 2), methods §2.2: Gamma_i = d_i . phi' and
    !> K = 1/2 (d3.d2' - d2.d3', d1.d3' - d3.d1', d2.d1' - d1.d2').
    pure subroutine ph_director_element_strains(basis, le, q, gamma, kappa)
        type(ph_director_basis_t), intent(in) :: basis
        real(rk), intent(in) :: le
        real(rk), intent(in) :: q(12, basis%nen)
        real(rk), intent(out) :: gamma(3, basis%degree), kappa(3, basis%degree)
        real(rk) :: nn(ph_director_max_nodes), dn(ph_director_max_nodes), x(12), xs(12)
        integer :: b, i, j, k
        do b = 1, basis%degree
            call ph_director_basis_shape(basis, basis%stress_xi(b), nn(1:basis%nen), &
                dn(1:basis%nen))
            x = matmul(q, nn(1:basis%nen))
            xs = matmul(q, dn(1:basis%nen)) * (2.0_rk / le)
            do i = 1, 3
                j = mod(i, 3) + 1
                k = mod(i + 1, 3) + 1
                gamma(i, b) = dot_product(x(3 * i + 1:3 * i + 3), xs(1:3))
                kappa(i, b) = 0.5_rk * (dot_product(x(3 * k + 1:3 * k + 3), &
                    xs(3 * j + 1:3 * j + 3)) - dot_product(x(3 * j + 1:3 * j + 3), &
                    xs(3 * k + 1:3 * k + 3)))
            end do
        end do
    end subroutine ph_director_element_strains

    !> Orthonormality constraint g(d) of one node (methods §2.1 eq. 2):
    !> g_ij = 1/2 (d_i . d_j - delta_ij) in the order (11, 22, 33, 12, 23, 31); q(12) nodal.
    pure function ph_director_node_constraint(q) result(g)
        real(rk), intent(in) :: q(12)
        real(rk) :: g(6)
        g(1) = 0.5_rk * (dot_product(q(4:6), q(4:6)) - 1.0_rk)
        g(2) = 0.5_rk * (dot_product(q(7:9), q(7:9)) - 1.0_rk)
        g(3) = 0.5_rk * (dot_product(q(10:12), q(10:12)) - 1.0_rk)
        g(4) = 0.5_rk * dot_product(q(4:6), q(7:9))
        g(5) = 0.5_rk * dot_product(q(7:9), q(10:12))
        g(6) = 0.5_rk * dot_product(q(10:12), q(4:6))
    end function ph_director_node_constraint

    ! G_d(d) = dg/dd (6 x 9), methods §2.1 eq. 15.
    pure function constraint_jacobian(d) result(gd)
        real(rk), intent(in) :: d(9)
        real(rk) :: gd(6, 9)
        gd = 0.0_rk
        gd(1, 1:3) = d(1:3)
        gd(2, 4:6) = d(4:6)
        gd(3, 7:9) = d(7:9)
        gd(4, 1:3) = 0.5_rk * d(4:6)
        gd(4, 4:6) = 0.5_rk * d(1:3)
        gd(5, 4:6) = 0.5_rk * d(7:9)
        gd(5, 7:9) = 0.5_rk * d(4:6)
        gd(6, 1:3) = 0.5_rk * d(7:9)
        gd(6, 7:9) = 0.5_rk * d(1:3)
    end function constraint_jacobian

    ! The symmetric matrix S with G_d(d)^T lambda = (sum_j S_ij d_j)_i (methods §5.6).
    pure function multiplier_matrix(lambda) result(s)
        real(rk), intent(in) :: lambda(6)
        real(rk) :: s(3, 3)
        s(1, 1) = lambda(1)
        s(2, 2) = lambda(2)
        s(3, 3) = lambda(3)
        s(1, 2) = 0.5_rk * lambda(4)
        s(2, 1) = s(1, 2)
        s(2, 3) = 0.5_rk * lambda(5)
        s(3, 2) = s(2, 3)
        s(3, 1) = 0.5_rk * lambda(6)
        s(1, 3) = s(3, 1)
    end function multiplier_matrix

    ! Add a 3 x 3 block at rows row0 + 1:3, columns col0 + 1:3.
    pure subroutine add_block(matrix, row0, col0, block)
        real(rk), intent(inout) :: matrix(:, :)
        integer, intent(in) :: row0, col0
        real(rk), intent(in) :: block(3, 3)
        matrix(row0 + 1:row0 + 3, col0 + 1:col0 + 3) = &
            matrix(row0 + 1:row0 + 3, col0 + 1:col0 + 3) + block
    end subroutine add_block

    ! Add a 3-vector at rows row0 + 1:3 of column col.
    pure subroutine add_column(matrix, row0, col, vector)
        real(rk), intent(inout) :: matrix(:, :)
        integer, intent(in) :: row0, col
        real(rk), intent(in) :: vector(3)
        matrix(row0 + 1:row0 + 3, col) = matrix(row0 + 1:row0 + 3, col) + vector
    end subroutine add_column

    ! Add a 3-vector at columns col0 + 1:3 of row row.
    pure subroutine add_row(matrix, row, col0, vector)
        real(rk), intent(inout) :: matrix(:, :)
        integer, intent(in) :: row, col0
        real(rk), intent(in) :: vector(3)
        matrix(row, col0 + 1:col0 + 3) = matrix(row, col0 + 1:col0 + 3) + vector
    end subroutine add_row

    pure function cross(a, b) result(c)
        real(rk), intent(in) :: a(3), b(3)
        real(rk) :: c(3)
        c = [a(2) * b(3) - a(3) * b(2), a(3) * b(1) - a(1) * b(3), a(1) * b(2) - a(2) * b(1)]
    end function cross

end module rs_ph_director_element
