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
!> - Stresses are discontinuous P^{p-1} (methods §4.1): p coefficients per component and branch,
!>   s(6, p, 0:m) with components (N1, N2, N3, M1, M2, M3) in the material frame, branch 0 the
!>   elastic one and 1..m the generalized-Maxwell branches (§3.1). Basis: psi = 1 for p = 1;
!>   for p = 2 the linear Lagrange functions of the stress points xi = -1/sqrt(3), +1/sqrt(3), so
!>   coefficients are values there and the 2-point Gauss compliance matrix is diagonal (§4.4).
!> - Element local layout, size nloc = 24 nen + 6 p (1 + m): entries 24(a-1) + 1..12 are q_a,
!>   24(a-1) + 13..24 are v_a, then 24 nen + 6 p br + 6(b-1) + k is stress component k of
!>   coefficient b of branch br. Residual rows use the same layout: the q rows of an element
!>   are zero (the kinematic rows are nodal), the v rows hold the momentum residual R_M, the
!>   stress rows R_S (§5.6).
!> - Node local layout, size 30: q (1:12), v (13:24), the midpoint multiplier
!>   lambda = (l11, l22, l33, l12, l23, l31) (25:30) (§2.1 order, §5.2 last bullet).
!> - Time step: implicit midpoint (§5.1, §5.2). Kernels take endpoint values at t_n (`_n`) and
!>   t_{n+1} (`_1`) and form midpoint values themselves; Jacobians are derivatives with respect
!>   to the t_{n+1} unknowns (and lambda_mid), so they contain the 1/2 of the midpoint. A
!>   `static` step evaluates the same rows at t_{n+1} instead (the endpoint equilibrium of a
!>   quasistatic run, DESIGN.md §3).
!> - Reference strains eps_0 = (Gamma_0, K_0) are given per element at its Gauss points
!>   (eps_ref(6, n_gauss)): for a stress-free reference they are the strains of the reference
!>   nodes, ph_director_element_reference_strains, so that a curved reference has eps(q_ref) -
!>   eps_0 = 0 exactly at the Gauss points; the straight reference of methods §2.1 (Remark 2.1)
!>   has Gamma_0 = (0, 0, 1), K_0 = 0 (ph_director_straight_strain) up to round-off.
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

    public :: ph_director_material_t, ph_director_basis_t, ph_director_actuation_t
    public :: ph_director_basis_init, ph_director_basis_shape, ph_director_stress_shape
    public :: ph_director_local_size
    public :: ph_director_element_residual, ph_director_node_residual
    public :: ph_director_element_kinetic_energy, ph_director_element_complementary_energy
    public :: ph_director_element_momenta, ph_director_element_position_integral
    public :: ph_director_element_external_work, ph_director_node_external_work
    public :: ph_director_element_strains, ph_director_node_constraint
    public :: ph_director_element_dissipation, ph_director_element_actuator_work
    public :: ph_director_element_damping_dissipation
    public :: ph_director_element_reference_strains, ph_director_element_initial_stress

    !> Largest element degree (quadratic elements).
    integer, parameter, public :: ph_director_max_degree = 2
    !> Largest number of nodes of an element.
    integer, parameter, public :: ph_director_max_nodes = ph_director_max_degree + 1
    !> Size of the node local layout: q (12), v (12), lambda (6).
    integer, parameter, public :: ph_director_node_size = 30
    !> Largest number of generalized-Maxwell branches of a rod.
    integer, parameter, public :: ph_director_max_branches = 8
    !> Largest number of tendons of a rod.
    integer, parameter, public :: ph_director_max_tendons = 16
    !> Strains of the straight stress-free reference, (Gamma_0, K_0) (methods §2.1).
    real(rk), parameter, public :: ph_director_straight_strain(6) = &
        [0.0_rk, 0.0_rk, 1.0_rk, 0.0_rk, 0.0_rk, 0.0_rk]

    !> Section properties of a rod (methods §2.3, §2.4): line density rhoA, director inertias
    !> rhoI = (M_rho^11, M_rho^22) (the d3 block has no mass), and the diagonal compliance
    !> (1/GA1, 1/GA2, 1/EA, 1/EI1, 1/EI2, 1/GJ). A zero compliance is a rigid component
    !> (methods §2.3); kernels never divide by it.
    type :: ph_director_material_t
        !> Mass per unit length.
        real(rk) :: rhoA = 0.0_rk
        !> Second moments of mass M_rho^11, M_rho^22 of the cross-section (principal axes).
        real(rk) :: rhoI(2) = 0.0_rk
        !> Diagonal of C = blockdiag(C_N, C_M) of the elastic branch, material frame.
        real(rk) :: compliance(6) = 0.0_rk
        !> Generalized-Maxwell branches (methods §3.1): number, compliance C_i = (f_i k)^{-1}
        !> and fluidity F_i = V_i^{-1} = (tau f_i k)^{-1} per component, and which components
        !> have a branch (not the rigid ones, whose stress is a multiplier).
        integer :: n_branches = 0
        real(rk) :: branch_compliance(6, ph_director_max_branches) = 0.0_rk
        real(rk) :: branch_fluidity(6, ph_director_max_branches) = 0.0_rk
        logical :: branch_active(6, ph_director_max_branches) = .false.
        !> Kelvin-Voigt viscosity V = diag(tau_i k_i) per component (docs/theory/damping.md): the
        !> rigid-spring limit of a Maxwell branch (methods §3.1, Remark 5.2), whose midpoint
        !> stress the element condenses (no unknowns). Zero for rigid components.
        real(rk) :: viscosity(6) = 0.0_rk
        !> External drag: the force -drag v_phi and the moment -angular_drag w per unit length,
        !> the latter as the force -angular_drag/2 v_i on every director (d1, d2, d3).
        real(rk) :: drag = 0.0_rk
        real(rk) :: angular_drag = 0.0_rk
    end type ph_director_material_t

    !> The actuators of a rod at one time (methods §3.2): the constant material stress of the
    !> pneumatic chambers, sum_k tau_k (0, 0, 1, rho_k^2, -rho_k^1, 0), and the tendons as
    !> (tau, rho^1, rho^2) columns.
    type :: ph_director_actuation_t
        real(rk) :: pneumatic(6) = 0.0_rk
        integer :: n_tendons = 0
        real(rk) :: tendon(3, ph_director_max_tendons) = 0.0_rk
    end type ph_director_actuation_t

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
    !> rule (degree .. max_gauss_points); `ok` is false (and `basis` empty) for other values.
    pure subroutine ph_director_basis_init(basis, degree, n_gauss, ok)
        type(ph_director_basis_t), intent(out) :: basis
        integer, intent(in) :: degree, n_gauss
        logical, intent(out) :: ok
        real(rk) :: points(2), weights(2)
        integer :: g
        ! n_gauss >= degree: fewer points leave the P^{p-1} stress block singular.
        ok = degree >= 1 .and. degree <= ph_director_max_degree .and. n_gauss >= degree &
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

    !> Size 24 nen + 6 p (1 + n_branches) of the element local layout.
    pure integer function ph_director_local_size(basis, material) result(nloc)
        type(ph_director_basis_t), intent(in) :: basis
        type(ph_director_material_t), intent(in) :: material
        nloc = 24 * basis%nen + 6 * basis%degree * (1 + material%n_branches)
    end function ph_director_local_size

    !> Residual and/or Jacobian (with respect to q_1, v_1, s_1) of one element in one
    !> implicit-midpoint step, methods/ph_director_3d.md §5.2 (M1), (M2), (S1), (S2), §5.6, with
    !> the generalized-Maxwell branches of §3.1 and the actuation of §3.2:
    !>   R_M = M_e (v_1 - v_n) + h [int B(q_t)^T (sigma_t + dsigma_act(q_t)) - f_ext]  (v rows)
    !>   R_S = C_e s_1 - int psi (eps(q_1) - eps_0)                     (elastic stress rows)
    !>   R_i = C_i (s_1 - s_n) - int psi (eps(q_1) - eps(q_n)) + h F_i s_mid  (branch i rows)
    !> with q_t = q_n + theta (q_1 - q_n), sigma_t the sum over the branches of
    !> s_n + theta (s_1 - s_n), B the strain-variation operator (eps_dot = B v), C_i and
    !> F_i = V_i^{-1} the branch compliance and fluidity. theta = 1/2 (midpoint step) or 1 with
    !> the viscous term off (`static`: the endpoint equilibrium of a quasistatic run, methods
    !> §2.8 eqs. 96e-g, DESIGN.md §3). q rows are zero.
    !>
    !> Damping (docs/theory/ph_director.md "Damping"; off in a `static` step): sigma_t gains the
    !> Kelvin-Voigt stress s_v of the step, the midpoint stress of a Maxwell branch with zero
    !> compliance and viscosity V (methods §3.1, Remark 5.2), condensed here (viscous_stress):
    !> s_v = V/h Pi (eps(q_1) - eps(q_n)), Pi the projection on the stress basis; and R_M gains
    !> the drag h int N_a N_b diag(c I, c_w/2 I, c_w/2 I, c_w/2 I) (v_n + v_1)/2 ds.
    !>
    !> The elastic stress rows are the non-rate (Hellinger-Reissner) form of (S1), (S2): since
    !> eps is bilinear, int psi (eps(q_1) - eps(q_n)) = h int psi eps_dot(q_mid, v_mid) exactly
    !> when (K1), (K2) hold, so the two forms have the same solutions (methods §5.3 item 3), but
    !> this one keeps strain consistency, and a zero compliance (a constrained component, §2.3,
    !> whose stress is then a multiplier) at the level of the Newton residual at every step
    !> instead of accumulating it (DESIGN.md §3, "constraints at the right level"). A component
    !> that is rigid has no Maxwell branch: its branch rows are s_1 = 0.
    !> nbar, mbar: distributed spatial force and moment per unit length at t_mid, constant over
    !> the element (gravity: nbar = rhoA g). eps_ref(:, g): the reference strains eps_0 at Gauss
    !> point g (module header).
    pure subroutine ph_director_element_residual(basis, material, le, eps_ref, h, static, q_n, &
            q_1, v_n, v_1, s_n, s_1, nbar, mbar, actuation, residual, jacobian)
        type(ph_director_basis_t), intent(in) :: basis
        type(ph_director_material_t), intent(in) :: material
        real(rk), intent(in) :: le, h
        real(rk), intent(in) :: eps_ref(6, basis%n_gauss)
        logical, intent(in) :: static
        real(rk), intent(in) :: q_n(12, basis%nen), q_1(12, basis%nen)
        real(rk), intent(in) :: v_n(12, basis%nen), v_1(12, basis%nen)
        real(rk), intent(in) :: s_n(6, basis%degree, 0:material%n_branches)
        real(rk), intent(in) :: s_1(6, basis%degree, 0:material%n_branches)
        real(rk), intent(in) :: nbar(3), mbar(3)
        type(ph_director_actuation_t), intent(in) :: actuation
        real(rk), intent(out), contiguous, optional :: residual(:)
        real(rk), intent(out), contiguous, optional :: jacobian(:, :)
        real(rk) :: q_t(12, ph_director_max_nodes), dv(12, ph_director_max_nodes), mass(12)
        real(rk) :: nn(ph_director_max_nodes), bb(ph_director_max_nodes)
        real(rk) :: psi(ph_director_max_degree)
        ! Fields at the Gauss point: phi', d_i, d_i' (columns i), at q_t and at q_1.
        real(rk) :: phi_s(3), d(3, 3), d_s(3, 3), phi_s1(3), d1(3, 3), d_s1(3, 3)
        ! Strains and their derivatives with respect to the values (x) and s-derivatives (xs)
        ! of (phi, d1, d2, d3): d eps = e_x dx + e_xs dxs (methods §2.2, §4.4).
        real(rk) :: eps(6), e_x(6, 12), e_xs(6, 12), eps_1(6), e_x1(6, 12), e_xs1(6, 12)
        real(rk) :: phi_sn(3), dn(3, 3), d_sn(3, 3), eps_n(6)
        real(rk) :: act(6), act_x(6, 12), act_xs(6, 12)
        ! B_a = N_a e_x + N_a' e_xs of each node at q_t (b_t) and at q_1 (b_1).
        real(rk) :: b_t(6, 12, ph_director_max_nodes), b_1(6, 12, ph_director_max_nodes)
        ! live(:, br): the components of branch br that are stresses: all of the elastic branch,
        ! the non-rigid ones of a Maxwell branch (a rigid component has none, methods §3.1).
        logical :: live(6, 0:ph_director_max_branches)
        real(rk) :: sig(6), branch_sig(6), force(12), m_hat(3, 3), comp(6), visc(6)
        real(rk) :: theta, h_visc, wds, c, mab, wab, cpsi, wpsi
        ! Kelvin-Voigt stress coefficients, their derivatives d s_v(:, b)/d q_1 of node m
        ! (ds_v(:, :, m, b)) and at the Gauss point (dsig_v(:, :, m)); drag per component of v.
        real(rk) :: s_v(6, ph_director_max_degree)
        real(rk) :: ds_v(6, 12, ph_director_max_nodes, ph_director_max_degree)
        real(rk) :: dsig_v(6, 12, ph_director_max_nodes), damp(12)
        integer :: nen, p, nb, g, a, b, cc, i, j, k, ra, rb, rs, cs, l, m, br
        logical :: with_residual, with_jacobian, viscous, dragged

        nen = basis%nen
        p = basis%degree
        nb = material%n_branches
        with_residual = present(residual)
        with_jacobian = present(jacobian)
        theta = merge(1.0_rk, 0.5_rk, static)
        h_visc = merge(0.0_rk, h, static)
        q_t(:, 1:nen) = q_n + theta * (q_1 - q_n)
        dv(:, 1:nen) = v_1 - v_n
        ! M_o = blockdiag(rhoA I, M^11 I, M^22 I, 0) (methods §2.4, §2.6 eq. 20)
        mass(1:3) = material%rhoA
        mass(4:6) = material%rhoI(1)
        mass(7:9) = material%rhoI(2)
        mass(10:12) = 0.0_rk
        m_hat = hat(mbar)
        live(:, 0) = .true.
        live(:, 1:nb) = material%branch_active(:, 1:nb)
        ! Damping: skipped, and costs nothing, when its coefficients are zero.
        viscous = any(material%viscosity > 0.0_rk) .and. .not. static
        dragged = (material%drag > 0.0_rk .or. material%angular_drag > 0.0_rk) .and. .not. static
        if (viscous) call viscous_stress(basis, material, le, h, q_n, q_1, with_jacobian, s_v, &
            ds_v)
        damp(1:3) = material%drag
        damp(4:12) = 0.5_rk * material%angular_drag

        if (with_residual) residual = 0.0_rk
        if (with_jacobian) jacobian = 0.0_rk
        ! Branch components of rigid (constrained) components: s_1 = 0.
        do br = 1, nb
            do b = 1, p
                rs = stress_row(basis, br, b)
                do l = 1, 6
                    if (material%branch_active(l, br)) cycle
                    if (with_residual) residual(rs + l) = s_1(l, b, br)
                    if (with_jacobian) jacobian(rs + l, rs + l) = 1.0_rk
                end do
            end do
        end do

        do g = 1, basis%n_gauss
            nn(1:nen) = basis%shape(1:nen, g)
            bb(1:nen) = basis%dshape(1:nen, g) * (2.0_rk / le)
            psi(1:p) = basis%psi(1:p, g)
            wds = basis%w(g) * 0.5_rk * le
            c = theta * h * wds
            call gauss_fields(q_t(:, 1:nen), nn(1:nen), bb(1:nen), phi_s, d, d_s)
            call strain_operator(phi_s, d, d_s, eps, e_x, e_xs)
            call gauss_fields(q_1, nn(1:nen), bb(1:nen), phi_s1, d1, d_s1)
            ! Total stress at q_t: all branches plus the actuators (methods §3.1 eq. 49, §3.2).
            sig = stress_at(s_n(:, :, 0), s_1(:, :, 0), theta, psi(1:p))
            do br = 1, nb
                ! A rigid component has no branch: its branch unknown is not a stress.
                branch_sig = stress_at(s_n(:, :, br), s_1(:, :, br), theta, psi(1:p))
                where (material%branch_active(:, br)) sig = sig + branch_sig
            end do
            call actuation_stress(actuation, phi_s, d, d_s, act, act_x, act_xs)
            sig = sig + act
            if (viscous) then
                ! The Kelvin-Voigt stress is a midpoint quantity: it enters in full.
                do b = 1, p
                    sig = sig + psi(b) * s_v(:, b)
                end do
            end if
            do a = 1, nen
                b_t(:, :, a) = nn(a) * e_x + bb(a) * e_xs
            end do

            if (with_residual) then
                do a = 1, nen
                    ra = 24 * (a - 1) + 12
                    ! Inertia: consistent mass from the same Gauss rule (methods §4.3 eq. 112).
                    do b = 1, nen
                        mab = wds * nn(a) * nn(b)
                        residual(ra + 1:ra + 12) = residual(ra + 1:ra + 12) + mab * mass * dv(:, b)
                        ! Drag against the midpoint velocity (docs/theory/damping.md).
                        if (dragged) residual(ra + 1:ra + 12) = residual(ra + 1:ra + 12) &
                            + 0.5_rk * h * mab * damp * (v_n(:, b) + v_1(:, b))
                    end do
                    ! Internal force int B_a^T sigma with B_a = N_a e_x + N_a' e_xs: the adjoint
                    ! of the strain rate, i.e. r_phi,a = int N_a' n and r_di,a = int N_a N_i
                    ! phi' + N_a (L(d')^T M)_i - N_a' (L(d)^T M)_i (methods §2.6
                    ! J_v = J_sigma^*, §4.4). External: - int N_a nbar, - int N_a 1/2 mbar x d_i
                    ! (T(d) mbar, §2.5, §4.3).
                    force = matmul(sig, b_t(:, :, a))
                    force(1:3) = force(1:3) - nn(a) * nbar
                    do i = 1, 3
                        force(3 * i + 1:3 * i + 3) = force(3 * i + 1:3 * i + 3) &
                            - 0.5_rk * nn(a) * cross(mbar, d(:, i))
                    end do
                    residual(ra + 1:ra + 12) = residual(ra + 1:ra + 12) + h * wds * force
                end do

                ! Stress rows (methods §4.4, §5.2 (S1), (S2), §3.1 eq. 52, midpoint rule).
                eps_1 = point_strains(phi_s1, d1, d_s1)
                if (nb > 0) then
                    call gauss_fields(q_n, nn(1:nen), bb(1:nen), phi_sn, dn, d_sn)
                    eps_n = point_strains(phi_sn, dn, d_sn)
                end if
                do b = 1, p
                    rs = stress_row(basis, 0, b)
                    residual(rs + 1:rs + 6) = residual(rs + 1:rs + 6) &
                        - wds * psi(b) * (eps_1 - eps_ref(:, g))
                    do cc = 1, p
                        residual(rs + 1:rs + 6) = residual(rs + 1:rs + 6) &
                            + wds * psi(b) * psi(cc) * material%compliance * s_1(:, cc, 0)
                    end do
                    do br = 1, nb
                        rs = stress_row(basis, br, b)
                        do cc = 1, p
                            where (material%branch_active(:, br)) residual(rs + 1:rs + 6) = &
                                residual(rs + 1:rs + 6) + wds * psi(b) * psi(cc) &
                                * (material%branch_compliance(:, br) * (s_1(:, cc, br) &
                                - s_n(:, cc, br)) + 0.5_rk * h_visc &
                                * material%branch_fluidity(:, br) &
                                * (s_1(:, cc, br) + s_n(:, cc, br)))
                        end do
                        where (material%branch_active(:, br)) residual(rs + 1:rs + 6) = &
                            residual(rs + 1:rs + 6) - wds * psi(b) * (eps_1 - eps_n)
                    end do
                end do
            end if

            if (.not. with_jacobian) cycle

            ! Jacobian (methods §5.6): q_t and sigma_t enter with the factor theta, hence
            ! c = theta h wds on the geometric, actuation and stress-coupling blocks.
            if (viscous) then
                ! d s_v/d q_1 at the Gauss point: the viscous stress's own q columns.
                dsig_v = 0.0_rk
                do b = 1, p
                    dsig_v(:, :, 1:nen) = dsig_v(:, :, 1:nen) + psi(b) * ds_v(:, :, 1:nen, b)
                end do
            end if
            do a = 1, nen
                ra = 24 * (a - 1) + 12
                do b = 1, nen
                    rb = 24 * (b - 1)
                    ! Inertia: the consistent mass in the v columns (methods §4.3 eq. 112).
                    mab = wds * nn(a) * nn(b)
                    do l = 1, 12
                        jacobian(ra + l, rb + 12 + l) = jacobian(ra + l, rb + 12 + l) &
                            + mab * mass(l)
                    end do
                    if (dragged) then
                        do l = 1, 12
                            jacobian(ra + l, rb + 12 + l) = jacobian(ra + l, rb + 12 + l) &
                                + 0.5_rk * h * mab * damp(l)
                        end do
                    end if
                    ! Kelvin-Voigt: h B_a^T d s_v/d q_1,b (the midpoint stress has no theta),
                    ! column by column (no array temporary).
                    if (viscous) then
                        do m = 1, 12
                            do l = 1, 6
                                jacobian(ra + 1:ra + 12, rb + m) = jacobian(ra + 1:ra + 12, rb + m) &
                                    + h * wds * dsig_v(l, m, b) * b_t(l, :, a)
                            end do
                        end do
                    end if
                    wab = nn(a) * bb(b) - bb(a) * nn(b)
                    do i = 1, 3
                        j = cyclic_next(i)
                        k = cyclic_next(j)
                        ! d f_phi,a / d d_i,b = N_a' N_i N_b I
                        call add_diagonal(jacobian, ra, rb + 3 * i, c * bb(a) * sig(i) * nn(b))
                        ! d f_di,a / d phi_b = N_a N_i N_b' I
                        call add_diagonal(jacobian, ra + 3 * i, rb, c * nn(a) * sig(i) * bb(b))
                        ! d(-1/2 N_a mbar x d_i) / d d_i,b = -1/2 N_a N_b mbar^
                        call add_block(jacobian, ra + 3 * i, rb + 3 * i, &
                            -0.5_rk * c * nn(a) * nn(b) * m_hat)
                        ! bending/torsion: d/d d_k,b = 1/2 M_j W_ab I, d/d d_j,b = -1/2 M_k W_ab I
                        call add_diagonal(jacobian, ra + 3 * i, rb + 3 * k, &
                            0.5_rk * c * sig(3 + j) * wab)
                        call add_diagonal(jacobian, ra + 3 * i, rb + 3 * j, &
                            -0.5_rk * c * sig(3 + k) * wab)
                    end do
                    ! State-dependent actuation (tendons): B_a^T d(dsigma_act)/dq_b (§5.6 end).
                    if (actuation%n_tendons > 0) jacobian(ra + 1:ra + 12, rb + 1:rb + 12) = &
                        jacobian(ra + 1:ra + 12, rb + 1:rb + 12) &
                        + c * matmul(transpose(b_t(:, :, a)), nn(b) * act_x + bb(b) * act_xs)
                end do
                ! Stress columns: psi_c B_a^T for every branch (sigma = sum of the branches).
                do br = 0, nb
                    do cc = 1, p
                        cs = stress_row(basis, br, cc)
                        cpsi = c * psi(cc)
                        do l = 1, 6
                            if (.not. live(l, br)) cycle
                            jacobian(ra + 1:ra + 12, cs + l) = jacobian(ra + 1:ra + 12, cs + l) &
                                + cpsi * b_t(l, :, a)
                        end do
                    end do
                end do
            end do

            ! Stress rows: -psi_c d eps(q_1)/dq_1 (down the columns: the 6 rows of a stress
            ! coefficient are adjacent) and the branch matrices.
            call strain_operator(phi_s1, d1, d_s1, eps_1, e_x1, e_xs1)
            do b = 1, nen
                b_1(:, :, b) = nn(b) * e_x1 + bb(b) * e_xs1
            end do
            do cc = 1, p
                wpsi = wds * psi(cc)
                do br = 0, nb
                    rs = stress_row(basis, br, cc)
                    do b = 1, nen
                        rb = 24 * (b - 1)
                        do m = 1, 12
                            where (live(:, br)) jacobian(rs + 1:rs + 6, rb + m) = &
                                jacobian(rs + 1:rs + 6, rb + m) - wpsi * b_1(:, m, b)
                        end do
                    end do
                end do
                do b = 1, p
                    ! C_e = int psi_b psi_c diag(compliance) ds (methods §4.3 eq. 113)
                    rs = stress_row(basis, 0, cc)
                    cs = stress_row(basis, 0, b)
                    do l = 1, 6
                        jacobian(rs + l, cs + l) = jacobian(rs + l, cs + l) &
                            + wds * psi(cc) * psi(b) * material%compliance(l)
                    end do
                    do br = 1, nb
                        rs = stress_row(basis, br, cc)
                        cs = stress_row(basis, br, b)
                        comp = material%branch_compliance(:, br)
                        visc = material%branch_fluidity(:, br)
                        do l = 1, 6
                            if (.not. material%branch_active(l, br)) cycle
                            jacobian(rs + l, cs + l) = jacobian(rs + l, cs + l) &
                                + wds * psi(cc) * psi(b) * (comp(l) + 0.5_rk * h_visc * visc(l))
                        end do
                    end do
                end do
            end do
        end do
    end subroutine ph_director_element_residual

    !> Residual (and optionally Jacobian with respect to q_1, v_1, lambda) of the nodal rows of
    !> one node in one implicit-midpoint step (methods §5.2 (K1), (K2), §5.6, DESIGN.md §3):
    !>   q rows: R_K = q_1 - q_n - h/2 (v_1 + v_n)
    !>   v rows: + h G_d(d_t)^T lambda - h force (phi) - h 1/2 moment x d_i,t (director i)
    !>   lambda rows: g(d_1) (the constraint imposed at the endpoint, methods §5.3 item 2).
    !> d_t is the midpoint d_mid, or d_1 in a `static` (endpoint equilibrium) step, where the
    !> q rows become -h/2 (v_1 - v_n) (velocities are kept). lambda is the multiplier of the
    !> step. force and moment are the concentrated spatial loads at the load time (zero at
    !> interior nodes). Without `with_lambda` (a clamped node, methods §4.6(c)) the lambda rows
    !> are identity rows with residual lambda and lambda does not enter the v rows.
    pure subroutine ph_director_node_residual(h, static, q_n, q_1, v_n, v_1, lambda, with_lambda, &
            force, moment, residual, jacobian)
        real(rk), intent(in) :: h
        logical, intent(in) :: static
        real(rk), intent(in) :: q_n(12), q_1(12), v_n(12), v_1(12), lambda(6)
        logical, intent(in) :: with_lambda
        real(rk), intent(in) :: force(3), moment(3)
        real(rk), intent(out) :: residual(ph_director_node_size)
        real(rk), intent(out), optional :: jacobian(ph_director_node_size, ph_director_node_size)
        real(rk) :: d_t(9), lam(3, 3), gd(6, 9), m_hat(3, 3), theta
        integer :: i, j, l

        theta = merge(1.0_rk, 0.5_rk, static)
        d_t = q_n(4:12) + theta * (q_1(4:12) - q_n(4:12))
        if (static) then
            residual(1:12) = -0.5_rk * h * (v_1 - v_n)
        else
            residual(1:12) = q_1 - q_n - 0.5_rk * h * (v_1 + v_n)
        end if
        residual(13:15) = -h * force
        do i = 1, 3
            residual(12 + 3 * i + 1:12 + 3 * i + 3) = &
                -0.5_rk * h * cross(moment, d_t(3 * i - 2:3 * i))
        end do
        if (with_lambda) then
            ! G_d(d)^T lambda, block i = sum_j S_ij d_j with the symmetric S of methods §5.6
            lam = multiplier_matrix(lambda)
            do i = 1, 3
                do j = 1, 3
                    residual(12 + 3 * i + 1:12 + 3 * i + 3) = &
                        residual(12 + 3 * i + 1:12 + 3 * i + 3) &
                        + h * lam(i, j) * d_t(3 * j - 2:3 * j)
                end do
            end do
            residual(25:30) = ph_director_node_constraint(q_1)
        else
            residual(25:30) = lambda
        end if

        if (.not. present(jacobian)) return
        jacobian = 0.0_rk
        do l = 1, 12
            if (.not. static) jacobian(l, l) = 1.0_rk
            jacobian(l, 12 + l) = -0.5_rk * h
        end do
        ! moment term: d(-h/2 moment x d_i,t)/d d_i,1 = -theta h/2 moment^
        m_hat = hat(moment)
        do i = 1, 3
            jacobian(12 + 3 * i + 1:12 + 3 * i + 3, 3 * i + 1:3 * i + 3) = -0.5_rk * theta * h * m_hat
        end do
        if (with_lambda) then
            do i = 1, 3
                do j = 1, 3
                    do l = 1, 3
                        jacobian(12 + 3 * i + l, 3 * j + l) = jacobian(12 + 3 * i + l, 3 * j + l) &
                            + theta * h * lam(i, j)
                    end do
                end do
            end do
            gd = constraint_jacobian(d_t)
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

    !> Complementary energy 1/2 s^T C_e s of one element, summed over the elastic and the Maxwell
    !> branches, with the element's Gauss rule (methods §2.3 eq. 9, §3.1 eq. 55-58, §4.3 eq. 35);
    !> s(6, p, 0:n_branches) stress coefficients (0: the elastic branch).
    pure function ph_director_element_complementary_energy(basis, material, le, s) result(energy)
        type(ph_director_basis_t), intent(in) :: basis
        type(ph_director_material_t), intent(in) :: material
        real(rk), intent(in) :: le
        real(rk), intent(in) :: s(6, basis%degree, 0:material%n_branches)
        real(rk) :: energy
        real(rk) :: sig(6)
        integer :: g, br
        energy = 0.0_rk
        do g = 1, basis%n_gauss
            sig = matmul(s(:, :, 0), basis%psi(1:basis%degree, g))
            energy = energy + 0.25_rk * le * basis%w(g) * sum(material%compliance * sig**2)
            do br = 1, material%n_branches
                sig = matmul(s(:, :, br), basis%psi(1:basis%degree, g))
                energy = energy + 0.25_rk * le * basis%w(g) &
                    * sum(material%branch_compliance(:, br) * sig**2)
            end do
        end do
    end function ph_director_element_complementary_energy

    !> Energy dissipated by the Maxwell branches of one element in one step,
    !> D_n = h int sum_i s_mid^(i) . F_i s_mid^(i) ds >= 0 with the fluidity F_i = V_i^{-1}
    !> (methods §3.1 eqs. 59-61, §5.3 item 1, §9 item 7).
    pure function ph_director_element_dissipation(basis, material, le, h, s_n, s_1) result(energy)
        type(ph_director_basis_t), intent(in) :: basis
        type(ph_director_material_t), intent(in) :: material
        real(rk), intent(in) :: le, h
        real(rk), intent(in) :: s_n(6, basis%degree, 0:material%n_branches)
        real(rk), intent(in) :: s_1(6, basis%degree, 0:material%n_branches)
        real(rk) :: energy
        real(rk) :: sig(6)
        integer :: g, br
        energy = 0.0_rk
        do g = 1, basis%n_gauss
            do br = 1, material%n_branches
                sig = 0.5_rk * matmul(s_n(:, :, br) + s_1(:, :, br), basis%psi(1:basis%degree, g))
                energy = energy + 0.5_rk * le * basis%w(g) &
                    * sum(material%branch_fluidity(:, br) * sig**2)
            end do
        end do
        energy = h * energy
    end function ph_director_element_dissipation

    !> Energy dissipated in one step by the damping of one element (docs/theory/ph_director.md
    !> "Damping"): `viscous` = h int s_v . V^{-1} s_v ds, the Maxwell form of methods §3.1
    !> eq. 60 for the Kelvin-Voigt stress s_v of the step (the rigid-spring branch, Remark 5.2),
    !> over the components with V > 0; `external` = h int u_mid . diag(c I, c_w/2 I9) u_mid ds
    !> with u_mid = (v_n + v_1)/2 (the drag). Both >= 0, and exactly what the momentum rows of
    !> ph_director_element_residual take out of the energy once the kinematic rows hold.
    pure subroutine ph_director_element_damping_dissipation(basis, material, le, h, q_n, q_1, &
            v_n, v_1, viscous, external)
        type(ph_director_basis_t), intent(in) :: basis
        type(ph_director_material_t), intent(in) :: material
        real(rk), intent(in) :: le, h
        real(rk), intent(in) :: q_n(12, basis%nen), q_1(12, basis%nen)
        real(rk), intent(in) :: v_n(12, basis%nen), v_1(12, basis%nen)
        real(rk), intent(out) :: viscous, external
        real(rk) :: s_v(6, ph_director_max_degree)
        real(rk) :: ds_v(6, 12, ph_director_max_nodes, ph_director_max_degree)
        real(rk) :: sig(6), u(12), damp(12), wds
        integer :: g, b, p, a
        p = basis%degree
        viscous = 0.0_rk
        external = 0.0_rk
        if (any(material%viscosity > 0.0_rk)) then
            call viscous_stress(basis, material, le, h, q_n, q_1, .false., s_v, ds_v)
            do g = 1, basis%n_gauss
                sig = 0.0_rk
                do b = 1, p
                    sig = sig + basis%psi(b, g) * s_v(:, b)
                end do
                wds = 0.5_rk * le * basis%w(g)
                viscous = viscous + wds * sum(sig**2 / material%viscosity, &
                    mask=material%viscosity > 0.0_rk)
            end do
            viscous = h * viscous
        end if
        if (material%drag > 0.0_rk .or. material%angular_drag > 0.0_rk) then
            damp(1:3) = material%drag
            damp(4:12) = 0.5_rk * material%angular_drag
            do g = 1, basis%n_gauss
                ! Summed node by node: matmul of run-time-sized sections would allocate.
                u = 0.0_rk
                do a = 1, basis%nen
                    u = u + 0.5_rk * basis%shape(a, g) * (v_n(:, a) + v_1(:, a))
                end do
                external = external + 0.5_rk * le * basis%w(g) * sum(damp * u**2)
            end do
            external = h * external
        end if
    end subroutine ph_director_element_damping_dissipation

    !> Work of the actuators on one element in one step, W_act = -h int dsigma_act(q_mid) .
    !> eps_dot(q_mid, v_mid) ds: the power of the actuation port (methods §3.2 eq. 66, §10 V9),
    !> which is what the momentum rows put into the energy balance.
    pure function ph_director_element_actuator_work(basis, le, h, q_n, q_1, v_n, v_1, actuation) &
            result(work)
        type(ph_director_basis_t), intent(in) :: basis
        real(rk), intent(in) :: le, h
        real(rk), intent(in) :: q_n(12, basis%nen), q_1(12, basis%nen)
        real(rk), intent(in) :: v_n(12, basis%nen), v_1(12, basis%nen)
        type(ph_director_actuation_t), intent(in) :: actuation
        real(rk) :: work
        real(rk) :: q_mid(12, basis%nen), v_mid(12, basis%nen), bb(basis%nen)
        real(rk) :: phi_s(3), d(3, 3), d_s(3, 3), eps(6), e_x(6, 12), e_xs(6, 12)
        real(rk) :: act(6), act_x(6, 12), act_xs(6, 12), rate(6)
        integer :: g
        q_mid = 0.5_rk * (q_n + q_1)
        v_mid = 0.5_rk * (v_n + v_1)
        work = 0.0_rk
        do g = 1, basis%n_gauss
            bb = basis%dshape(1:basis%nen, g) * (2.0_rk / le)
            call gauss_fields(q_mid, basis%shape(1:basis%nen, g), bb, phi_s, d, d_s)
            call strain_operator(phi_s, d, d_s, eps, e_x, e_xs)
            call actuation_stress(actuation, phi_s, d, d_s, act, act_x, act_xs)
            rate = matmul(e_x, matmul(v_mid, basis%shape(1:basis%nen, g))) &
                + matmul(e_xs, matmul(v_mid, bb))
            work = work - 0.5_rk * le * basis%w(g) * dot_product(act, rate)
        end do
        work = h * work
    end function ph_director_element_actuator_work

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

    !> Strains eps(q) = (Gamma, K) of nodal q(12, nen) at the element's Gauss points, with the
    !> strain operator of the residual (methods §2.2): the reference strains eps_0 of a
    !> stress-free reference q (module header), so that eps(q_ref) - eps_0 = 0 there exactly.
    pure subroutine ph_director_element_reference_strains(basis, le, q, eps_ref)
        type(ph_director_basis_t), intent(in) :: basis
        real(rk), intent(in) :: le
        real(rk), intent(in) :: q(12, basis%nen)
        real(rk), intent(out) :: eps_ref(6, basis%n_gauss)
        real(rk) :: bb(ph_director_max_nodes), phi_s(3), d(3, 3), d_s(3, 3), e_x(6, 12), e_xs(6, 12)
        integer :: g
        do g = 1, basis%n_gauss
            bb(1:basis%nen) = basis%dshape(1:basis%nen, g) * (2.0_rk / le)
            call gauss_fields(q, basis%shape(1:basis%nen, g), bb(1:basis%nen), phi_s, d, d_s)
            call strain_operator(phi_s, d, d_s, eps_ref(:, g), e_x, e_xs)
        end do
    end subroutine ph_director_element_reference_strains

    !> Elastic stress coefficients s(6, p) consistent with nodal q and reference strains
    !> eps_ref: the solution of the stress rows R_S = C_e s - int psi (eps(q) - eps_0) = 0
    !> (methods §5.4, the projection of eqs. 96e-f), component by component (C_e is block
    !> diagonal in the components). Rigid components (zero compliance, their stress a
    !> multiplier) get 0.
    pure subroutine ph_director_element_initial_stress(basis, material, le, q, eps_ref, s)
        type(ph_director_basis_t), intent(in) :: basis
        type(ph_director_material_t), intent(in) :: material
        real(rk), intent(in) :: le
        real(rk), intent(in) :: q(12, basis%nen), eps_ref(6, basis%n_gauss)
        real(rk), intent(out) :: s(6, basis%degree)
        real(rk) :: eps(6, basis%n_gauss), rhs(6, ph_director_max_degree)
        real(rk) :: gram(ph_director_max_degree, ph_director_max_degree), wds, det
        integer :: g, b, c, p
        p = basis%degree
        call ph_director_element_reference_strains(basis, le, q, eps)
        rhs = 0.0_rk
        gram = 0.0_rk
        do g = 1, basis%n_gauss
            wds = basis%w(g) * 0.5_rk * le
            do b = 1, p
                rhs(:, b) = rhs(:, b) + wds * basis%psi(b, g) * (eps(:, g) - eps_ref(:, g))
                do c = 1, p
                    gram(b, c) = gram(b, c) + wds * basis%psi(b, g) * basis%psi(c, g)
                end do
            end do
        end do
        ! C_e = gram x diag(compliance): solve gram y = rhs, then s = y / compliance.
        if (p == 1) then
            s(:, 1) = rhs(:, 1) / gram(1, 1)
        else
            det = gram(1, 1) * gram(2, 2) - gram(1, 2) * gram(2, 1)
            s(:, 1) = (gram(2, 2) * rhs(:, 1) - gram(1, 2) * rhs(:, 2)) / det
            s(:, 2) = (gram(1, 1) * rhs(:, 2) - gram(2, 1) * rhs(:, 1)) / det
        end if
        do b = 1, p
            where (material%compliance > 0.0_rk)
                s(:, b) = s(:, b) / material%compliance
            elsewhere
                s(:, b) = 0.0_rk
            end where
        end do
    end subroutine ph_director_element_initial_stress

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

    ! Offset of the rows (and columns) of stress coefficient b of branch br (0: elastic) in the
    ! element local layout.
    pure integer function stress_row(basis, br, b)
        type(ph_director_basis_t), intent(in) :: basis
        integer, intent(in) :: br, b
        stress_row = 24 * basis%nen + 6 * basis%degree * br + 6 * (b - 1)
    end function stress_row

    ! phi', d_i and d_i' (columns i) at a point from nodal q(12, nen), shape values nn and
    ! s-derivatives bb. Sums over the nodes in node order, written out: matmul of sections of
    ! run-time size would allocate temporaries.
    pure subroutine gauss_fields(q, nn, bb, phi_s, d, d_s)
        real(rk), intent(in) :: q(:, :), nn(:), bb(:)
        real(rk), intent(out) :: phi_s(3), d(3, 3), d_s(3, 3)
        integer :: a, i
        phi_s = 0.0_rk
        d = 0.0_rk
        d_s = 0.0_rk
        do a = 1, size(nn)
            phi_s = phi_s + q(1:3, a) * bb(a)
            do i = 1, 3
                d(:, i) = d(:, i) + q(3 * i + 1:3 * i + 3, a) * nn(a)
                d_s(:, i) = d_s(:, i) + q(3 * i + 1:3 * i + 3, a) * bb(a)
            end do
        end do
    end subroutine gauss_fields

    ! Stress sum_b psi_b (s_n + theta (s_1 - s_n))_b of one branch at a point (s_n, s_1 with
    ! p = size(psi) coefficients), summed in coefficient order.
    pure function stress_at(s_n, s_1, theta, psi) result(sig)
        real(rk), intent(in) :: s_n(:, :), s_1(:, :), theta, psi(:)
        real(rk) :: sig(6)
        integer :: b
        sig = 0.0_rk
        do b = 1, size(psi)
            sig = sig + (s_n(:, b) + theta * (s_1(:, b) - s_n(:, b))) * psi(b)
        end do
    end function stress_at

    ! The Kelvin-Voigt stress of a step (docs/theory/ph_director.md "Damping"): the midpoint
    ! stress s_v of a Maxwell branch with zero compliance and viscosity V (methods §3.1,
    ! Remark 5.2). Its branch row (methods §5.2) with C = 0 and the strain increment of the
    ! elastic rows' non-rate form, int psi_b [h V^{-1} s_v - (eps(q_1) - eps(q_n))] ds = 0,
    ! is solved element by element, s_v(:, b) = V/h sum_c Ginv_bc int psi_c (eps(q_1) -
    ! eps(q_n)) ds with Ginv the inverse of the stress basis's Gram matrix int psi_b psi_c ds
    ! (the same Gauss rule): the stress is condensed, no unknown of the step. The strain
    ! increment is evaluated as B(q_mid) (q_1 - q_n), h J_sigma(q_mid) v_mid of the brief's
    ! branch row, equal to eps(q_1) - eps(q_n) since eps is bilinear (methods §5.3 item 3), but
    ! without the cancellation of two O(1) strains: V/h multiplies what rounding is left, and
    ! the difference of the strains made Newton stagnate above newton_atol (the flying
    ! spaghetti with tau = 0.05 s at 2e-11). With `derivative`, ds_v(:, :, m, b) =
    ! d s_v(:, b) / d q_1 of node m (12 columns): V/h Ginv int psi B(q_1).
    pure subroutine viscous_stress(basis, material, le, h, q_n, q_1, derivative, s_v, ds_v)
        type(ph_director_basis_t), intent(in) :: basis
        type(ph_director_material_t), intent(in) :: material
        real(rk), intent(in) :: le, h
        real(rk), intent(in) :: q_n(:, :), q_1(:, :)
        logical, intent(in) :: derivative
        real(rk), intent(out) :: s_v(6, ph_director_max_degree)
        real(rk), intent(out) :: ds_v(6, 12, ph_director_max_nodes, ph_director_max_degree)
        real(rk) :: rhs(6, ph_director_max_degree)
        real(rk) :: drhs(6, 12, ph_director_max_nodes, ph_director_max_degree)
        real(rk) :: gram(ph_director_max_degree, ph_director_max_degree)
        real(rk) :: ginv(ph_director_max_degree, ph_director_max_degree)
        real(rk) :: nn(ph_director_max_nodes), bb(ph_director_max_nodes), wds, det, weight
        real(rk) :: phi_s(3), d(3, 3), d_s(3, 3), eps(6), e_x(6, 12), e_xs(6, 12), increment(6)
        real(rk) :: q_mid(12, ph_director_max_nodes), dq(12, ph_director_max_nodes)
        real(rk) :: dx(12), dxs(12)
        integer :: nen, p, g, b, c, m, l
        nen = basis%nen
        p = basis%degree
        q_mid(:, 1:nen) = 0.5_rk * (q_n + q_1)
        dq(:, 1:nen) = q_1 - q_n
        rhs = 0.0_rk
        drhs = 0.0_rk
        gram = 0.0_rk
        do g = 1, basis%n_gauss
            nn(1:nen) = basis%shape(1:nen, g)
            bb(1:nen) = basis%dshape(1:nen, g) * (2.0_rk / le)
            wds = basis%w(g) * 0.5_rk * le
            call gauss_fields(q_mid(:, 1:nen), nn(1:nen), bb(1:nen), phi_s, d, d_s)
            call strain_operator(phi_s, d, d_s, eps, e_x, e_xs)
            dx = 0.0_rk
            dxs = 0.0_rk
            do m = 1, nen
                dx = dx + nn(m) * dq(:, m)
                dxs = dxs + bb(m) * dq(:, m)
            end do
            increment = matmul(e_x, dx) + matmul(e_xs, dxs)
            if (derivative) then
                call gauss_fields(q_1, nn(1:nen), bb(1:nen), phi_s, d, d_s)
                call strain_operator(phi_s, d, d_s, eps, e_x, e_xs)
            end if
            do b = 1, p
                weight = wds * basis%psi(b, g)
                rhs(:, b) = rhs(:, b) + weight * increment
                do c = 1, p
                    gram(b, c) = gram(b, c) + weight * basis%psi(c, g)
                end do
                if (.not. derivative) cycle
                do m = 1, nen
                    drhs(:, :, m, b) = drhs(:, :, m, b) + weight * (nn(m) * e_x + bb(m) * e_xs)
                end do
            end do
        end do
        if (p == 1) then
            ginv(1, 1) = 1.0_rk / gram(1, 1)
        else
            det = gram(1, 1) * gram(2, 2) - gram(1, 2) * gram(2, 1)
            ginv(1, 1) = gram(2, 2) / det
            ginv(2, 2) = gram(1, 1) / det
            ginv(1, 2) = -gram(1, 2) / det
            ginv(2, 1) = -gram(2, 1) / det
        end if
        s_v = 0.0_rk
        ds_v = 0.0_rk
        do b = 1, p
            do c = 1, p
                s_v(:, b) = s_v(:, b) + ginv(b, c) * rhs(:, c)
                if (derivative) ds_v(:, :, 1:nen, b) = ds_v(:, :, 1:nen, b) &
                    + ginv(b, c) * drhs(:, :, 1:nen, c)
            end do
            s_v(:, b) = material%viscosity / h * s_v(:, b)
            if (.not. derivative) cycle
            do l = 1, 6
                ds_v(l, :, 1:nen, b) = material%viscosity(l) / h * ds_v(l, :, 1:nen, b)
            end do
        end do
    end subroutine viscous_stress

    ! Strains eps = (Gamma, K) at a point (methods §2.2): Gamma_i = d_i . phi',
    ! K_i = 1/2 (d_k . d_j' - d_j . d_k') with (i, j, k) cyclic.
    pure function point_strains(phi_s, d, d_s) result(eps)
        real(rk), intent(in) :: phi_s(3), d(3, 3), d_s(3, 3)
        real(rk) :: eps(6)
        integer :: i, j, k
        do i = 1, 3
            j = cyclic_next(i)
            k = cyclic_next(j)
            eps(i) = dot_product(d(:, i), phi_s)
            eps(3 + i) = 0.5_rk * (dot_product(d(:, k), d_s(:, j)) - dot_product(d(:, j), d_s(:, k)))
        end do
    end function point_strains

    ! The strains at a point (point_strains) and the constant-coefficient operators of their
    ! variation, d eps = e_x d(phi, d) + e_xs d(phi', d'): eps is bilinear, so the same
    ! operators give the strain rate eps_dot = e_x v + e_xs v' (eq. 18) and, by adjointness,
    ! the internal force of a node, int (N_a e_x + N_a' e_xs)^T sigma ds.
    pure subroutine strain_operator(phi_s, d, d_s, eps, e_x, e_xs)
        real(rk), intent(in) :: phi_s(3), d(3, 3), d_s(3, 3)
        real(rk), intent(out) :: eps(6), e_x(6, 12), e_xs(6, 12)
        integer :: i, j, k
        eps = point_strains(phi_s, d, d_s)
        e_x = 0.0_rk
        e_xs = 0.0_rk
        do i = 1, 3
            j = cyclic_next(i)
            k = cyclic_next(j)
            e_x(i, 3 * i + 1:3 * i + 3) = phi_s
            e_xs(i, 1:3) = d(:, i)
            e_x(3 + i, 3 * k + 1:3 * k + 3) = 0.5_rk * d_s(:, j)
            e_x(3 + i, 3 * j + 1:3 * j + 3) = -0.5_rk * d_s(:, k)
            e_xs(3 + i, 3 * j + 1:3 * j + 3) = 0.5_rk * d(:, k)
            e_xs(3 + i, 3 * k + 1:3 * k + 3) = -0.5_rk * d(:, j)
        end do
    end subroutine strain_operator

    ! The successor of i in the cyclic order (1, 2, 3).
    pure integer function cyclic_next(i)
        integer, intent(in) :: i
        integer, parameter :: next(3) = [2, 3, 1]
        cyclic_next = next(i)
    end function cyclic_next

    ! Additional material stresses of the actuators at a point (methods §3.2 eqs. 62-65):
    ! dN = R^T n_u, dM = R^T m_u with n_u = sum_k tau_k t_k and m_u = sum_k rho_k x tau_k t_k.
    ! Pneumatic chambers (t = d3) give the constant `pneumatic`; a tendon at material offset
    ! (rho^1, rho^2) has rho = rho^a d_a and t = r'/|r'| with r' = phi' + rho^a d_a', so
    ! dN_i = tau d_i . t and dM_i = tau d_i . (rho x t). Derivatives as for the strains:
    ! d(dsigma) = act_x d(phi, d) + act_xs d(phi', d'), with dt = (I - t t^T)/|r'| dr'.
    pure subroutine actuation_stress(actuation, phi_s, d, d_s, act, act_x, act_xs)
        type(ph_director_actuation_t), intent(in) :: actuation
        real(rk), intent(in) :: phi_s(3), d(3, 3), d_s(3, 3)
        real(rk), intent(out) :: act(6), act_x(6, 12), act_xs(6, 12)
        real(rk) :: tau, rho_c(2), rho(3), r_s(3), length, t(3), proj(3, 3), w(3), u(3)
        integer :: n, i, a, l
        act = actuation%pneumatic
        act_x = 0.0_rk
        act_xs = 0.0_rk
        do n = 1, actuation%n_tendons
            tau = actuation%tendon(1, n)
            rho_c = actuation%tendon(2:3, n)
            rho = rho_c(1) * d(:, 1) + rho_c(2) * d(:, 2)
            r_s = phi_s + rho_c(1) * d_s(:, 1) + rho_c(2) * d_s(:, 2)
            length = norm2(r_s)
            t = r_s / length
            proj = -spread(t, 2, 3) * spread(t, 1, 3) / length
            do l = 1, 3
                proj(l, l) = proj(l, l) + 1.0_rk / length
            end do
            do i = 1, 3
                ! force: dN_i = tau d_i . t
                act(i) = act(i) + tau * dot_product(d(:, i), t)
                act_x(i, 3 * i + 1:3 * i + 3) = act_x(i, 3 * i + 1:3 * i + 3) + tau * t
                w = tau * matmul(proj, d(:, i))
                act_xs(i, 1:3) = act_xs(i, 1:3) + w
                do a = 1, 2
                    act_xs(i, 3 * a + 1:3 * a + 3) = act_xs(i, 3 * a + 1:3 * a + 3) + rho_c(a) * w
                end do
                ! moment: dM_i = tau d_i . (rho x t) = tau t . (d_i x rho) = tau rho . (t x d_i)
                act(3 + i) = act(3 + i) + tau * dot_product(d(:, i), cross(rho, t))
                act_x(3 + i, 3 * i + 1:3 * i + 3) = act_x(3 + i, 3 * i + 1:3 * i + 3) &
                    + tau * cross(rho, t)
                u = tau * cross(t, d(:, i))
                w = tau * matmul(proj, cross(d(:, i), rho))
                act_xs(3 + i, 1:3) = act_xs(3 + i, 1:3) + w
                do a = 1, 2
                    act_x(3 + i, 3 * a + 1:3 * a + 3) = act_x(3 + i, 3 * a + 1:3 * a + 3) &
                        + rho_c(a) * u
                    act_xs(3 + i, 3 * a + 1:3 * a + 3) = act_xs(3 + i, 3 * a + 1:3 * a + 3) &
                        + rho_c(a) * w
                end do
            end do
        end do
    end subroutine actuation_stress

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
        real(rk), intent(inout), contiguous :: matrix(:, :)
        integer, intent(in) :: row0, col0
        real(rk), intent(in) :: block(3, 3)
        matrix(row0 + 1:row0 + 3, col0 + 1:col0 + 3) = &
            matrix(row0 + 1:row0 + 3, col0 + 1:col0 + 3) + block
    end subroutine add_block

    ! Add value I (3 x 3) at rows row0 + 1:3, columns col0 + 1:3.
    pure subroutine add_diagonal(matrix, row0, col0, value)
        real(rk), intent(inout), contiguous :: matrix(:, :)
        integer, intent(in) :: row0, col0
        real(rk), intent(in) :: value
        integer :: l
        do l = 1, 3
            matrix(row0 + l, col0 + l) = matrix(row0 + l, col0 + l) + value
        end do
    end subroutine add_diagonal

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
