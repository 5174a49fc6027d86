!> Element kernels of the planar geometrically exact beam of seed 001 (methods/ph_planar.md):
!> the port-Hamiltonian energy-momentum scheme PH-EM (§4.3) and the two displacement-based
!> comparison schemes cl-EM (Stander-Stein, §5.1) and PH-EMi (§5.2), one implicit-midpoint step
!> each: internal nodal forces, strain rows, analytic Jacobians, strains, energies and the
!> consistent mass. Pure procedures on plain arrays: no PETSc, no MPI, no allocation
!> (DESIGN.md §2, STYLE.md item 4).
!>
!> Conventions (fixed; the planar formulation relies on them):
!> - Two-node element of reference length le (straight, stress-free reference: Gamma_ref = 0,
!>   kappa_ref = 0, methods §2.3). The kernels that form strains from positions measure them
!>   from the element's reference stretch, the optional `reference(2, n_gauss)`: Gamma_g =
!>   Lambda(phi_g)^T d_s r - reference(:, g) (default e1, methods eqs. 5-6). The formulation
!>   passes reference_stretches of the initial nodal coordinates: formed with the strains' own
!>   arithmetic, they make the given straight rod exactly stress-free (against e1, the
!>   round-off of d_s r, eps |r| / le, times EA was a force above Newton's tolerance:
!>   docs/theory/ph_planar.md "The reference stretch"). A prestrained rod (&rod prestrain,
!>   docs/theory/prestretched_starts.md) has that stretch times axial_reference = 1 / (1 +
!>   prestrain), its stress-free length per unit given length. The rate forms (PH-EM, PH-EMi)
!>   carry the elastic strains from their initial values and need none in a step. Nodal
!>   unknowns q = (x_a, y_a, phi_a, x_b, y_b, phi_b); element strains e = (Gamma1, Gamma2,
!>   kappa) (methods §3.1, P0); the angle phi is never wrapped (§2.2).
!> - Lambda(phi) = [[cos, -sin], [sin, cos]], S = [[0, 1], [-1, 0]], dLambda/dphi = S^T Lambda
!>   (methods §2.1 eq. 1, §2.2 eqs. 3-4); the planar cross product is a x b = a^T S b.
!> - stiffness = (EA, GA, EI) with GA the shear stiffness k G A: D_ts = diag(EA, GA) (eq. 10).
!> - viscosity = (tau_EA EA, tau_GA GA, tau_EI EI): the Kelvin-Voigt viscosities V (issue 26,
!>   docs/theory/damping.md) of the step kernels. Each stress of the step gains V (eps_{n+1} -
!>   eps_n) / h with the scheme's own strains eps (the mixed strains of PH-EM, the compatible
!>   strains of cl-EM and the Gauss-point history of PH-EMi at each Gauss point), so that the
!>   force rows, the adjoints of the step's strain increments, do the work -D of
!>   viscous_dissipation (docs/theory/ph_planar.md "Damping"). Zeros: the elastic scheme.
!> - Gauss rule of n_gauss points (1 = reduced, 2 = full; 1 .. max_gauss_points accepted) from
!>   rs_math_quadrature on xi in [-1, 1], ds = le/2 dxi, shape functions N_a = (1 - xi)/2,
!>   N_b = (1 + xi)/2, d_s N = (-1, +1)/le (methods §3.1). Angles at a Gauss point are the
!>   interpolated nodal angles.
!> - Time step: implicit midpoint. Kernels take the endpoint states at t_n (`_n`) and t_{n+1}
!>   (`_1`) and form midpoint values themselves, ( )_05 = 1/2 (( )_n + ( )_1). Jacobians are
!>   derivatives with respect to the t_{n+1} unknowns, so they contain the 1/2 of the midpoint.
!> - Residual rows hold internal forces only: inertia (element_mass) and external loads are
!>   added by the formulation. Force rows are the nodal force (x, y) and moment (phi) that the
!>   element exerts against the motion, i.e. R = M dv/h + r_int - f_ext (methods §4.3).
module rs_ph_planar_element
    use rs_core_kinds, only: rk
    use rs_math_quadrature, only: gauss_legendre, max_gauss_points
    implicit none
    private

    public :: ph_em_residual, ph_em_jacobian, ph_em_condensed
    public :: ph_em_static, ph_em_static_condensed, ph_em_projected_strains, cl_em_static
    public :: cl_em_residual, cl_em_jacobian
    public :: ph_emi_residual, ph_emi_jacobian, ph_emi_strains
    public :: compatible_strains, reference_stretches, element_mass
    public :: mixed_strain_energy, compatible_strain_energy, ph_emi_strain_energy
    public :: planar_sinc, viscous_dissipation

    !> Largest number of Gauss points an element accepts.
    integer, parameter, public :: planar_max_gauss = max_gauss_points

    ! Below this |x|, sin(x)/x and its derivative are evaluated by their Taylor series (the
    ! closed form of the derivative loses ~eps/x^3 relative accuracy to cancellation).
    real(rk), parameter :: sinc_series_limit = 0.1_rk
    ! The viscosity of an equilibrium (a state, no step: no strain rate).
    real(rk), parameter :: no_viscosity(3) = 0.0_rk

contains

    !> PH-EM element residual r(9) of one step (methods §4.3, eqs. 56c-h as solved in moofeKIT):
    !>   r(1:6): internal nodal forces, G2 N05 in the (x, y) rows and -V N05 + G1 M05 in the
    !>           phi rows, with N05 = D_ts 1/2 (Gamma_n + Gamma_1), M05 = EI 1/2 (kappa_n +
    !>           kappa_1) and G2, V at the midpoint configuration (§3.2);
    !>   r(7:8): R_Gamma = -C2e (Gamma_1 - Gamma_n)/h + G2e^T dr/h - Ve^T dphi/h;
    !>   r(9):   R_kappa = -le (kappa_1 - kappa_n)/h + (dphi_b - dphi_a)/h.
    !> With viscosity, N05 and M05 gain V (e_1 - e_n)/h. No inertia, no external loads.
    pure subroutine ph_em_residual(le, stiffness, viscosity, n_gauss, h, q_n, q_1, e_n, e_1, r)
        real(rk), intent(in) :: le, stiffness(3), viscosity(3)
        integer, intent(in) :: n_gauss
        real(rk), intent(in) :: h, q_n(6), q_1(6), e_n(3), e_1(3)
        real(rk), intent(out) :: r(9)
        real(rk) :: w(max_gauss_points), nn(2, max_gauss_points), cs(2, max_gauss_points)
        real(rk) :: q05(6), dq(6), inc(3)
        q05 = 0.5_rk * (q_n + q_1)
        dq = q_1 - q_n
        call gauss_shapes(n_gauss, w, nn)
        call gauss_point_angles(n_gauss, nn, q05(3), q05(6), cs)
        call ph_em_forces(le, stiffness, viscosity / h, n_gauss, w, nn, cs, q05, e_n, e_1, r(1:6))
        call ph_em_strain_increment(le, n_gauss, w, nn, cs, q05, dq, inc)
        r(7:9) = (-le * (e_1 - e_n) + inc) / h
    end subroutine ph_em_residual

    !> PH-EM element Jacobian k(9, 9) = d r / d (q_1(1:6), e_1(1:3)) of ph_em_residual,
    !> analytic (methods §4.3, §10 "Jacobian").
    pure subroutine ph_em_jacobian(le, stiffness, viscosity, n_gauss, h, q_n, q_1, e_n, e_1, k)
        real(rk), intent(in) :: le, stiffness(3), viscosity(3)
        integer, intent(in) :: n_gauss
        real(rk), intent(in) :: h, q_n(6), q_1(6), e_n(3), e_1(3)
        real(rk), intent(out) :: k(9, 9)
        real(rk) :: w(max_gauss_points), nn(2, max_gauss_points), cs(2, max_gauss_points)
        real(rk) :: q05(6), dq(6), r(6), inc(3), dinc(3, 6)
        integer :: i
        q05 = 0.5_rk * (q_n + q_1)
        dq = q_1 - q_n
        call gauss_shapes(n_gauss, w, nn)
        call gauss_point_angles(n_gauss, nn, q05(3), q05(6), cs)
        call ph_em_forces(le, stiffness, viscosity / h, n_gauss, w, nn, cs, q05, e_n, e_1, r, k)
        call ph_em_strain_increment(le, n_gauss, w, nn, cs, q05, dq, inc, dinc)
        k(7:9, 1:6) = dinc / h
        k(7:9, 7:9) = 0.0_rk
        do i = 7, 9
            k(i, i) = -le / h
        end do
    end subroutine ph_em_jacobian

    !> PH-EM with the element strains eliminated (methods §3.5 last bullet, §4.3 eqs. 63-64):
    !> C2e and C1e are diagonal, so R_Gamma = R_kappa = 0 give explicitly
    !>   Gamma_1 = Gamma_n + (1/le) (G2e^T dr - Ve^T dphi),
    !>   kappa_1 = kappa_n + (dphi_b - dphi_a)/le.
    !> Returns that e_1(3), the nodal rows r(6) = ph_em_residual(1:6) at e_1, and the exact
    !> condensed tangent k(6, 6) = dr/dq_1 + dr/de_1 de_1/dq_1 (the Schur complement of the full
    !> 9 x 9 Jacobian). h scales the eliminated rows and enters the nodal rows only through the
    !> viscous stress V (e_1 - e_n)/h: undamped, no output depends on it.
    pure subroutine ph_em_condensed(le, stiffness, viscosity, n_gauss, h, q_n, q_1, e_n, r, k, e_1)
        real(rk), intent(in) :: le, stiffness(3), viscosity(3)
        integer, intent(in) :: n_gauss
        real(rk), intent(in) :: h, q_n(6), q_1(6), e_n(3)
        real(rk), intent(out) :: r(6), k(6, 6), e_1(3)
        real(rk) :: w(max_gauss_points), nn(2, max_gauss_points), cs(2, max_gauss_points)
        real(rk) :: q05(6), dq(6), inc(3), dinc(3, 6), kf(9, 9)
        q05 = 0.5_rk * (q_n + q_1)
        dq = q_1 - q_n
        call gauss_shapes(n_gauss, w, nn)
        call gauss_point_angles(n_gauss, nn, q05(3), q05(6), cs)
        call ph_em_strain_increment(le, n_gauss, w, nn, cs, q05, dq, inc, dinc)
        e_1 = e_n + inc / le
        call ph_em_forces(le, stiffness, viscosity / h, n_gauss, w, nn, cs, q05, e_n, e_1, r, kf)
        k = kf(1:6, 1:6) + matmul(kf(1:6, 7:9), dinc / le)
    end subroutine ph_em_condensed

    !> PH-EM equilibrium of one state (the endpoint equilibrium of a quasistatic run, DESIGN.md
    !> §3; methods §4.7): nodal q and element strains e = (Gamma1, Gamma2, kappa) at the same
    !> time, no increment, i.e. the Hu-Washizu form of methods §2.9 that the rate form (56e-f)
    !> differentiates:
    !>   r(1:6): the internal nodal forces of ph_em_residual with q_n = q_1 = q, e_n = e_1 = e
    !>           (N = D_ts Gamma, M = EI kappa, G2 and V at q);
    !>   r(7:9): le (e_P0(q) - e) / h, e_P0 the P0 projection of the compatible strains
    !>           (ph_em_projected_strains): the strain rows in the scaling of a step h.
    !> k(9, 9) = d r / d(q, e), analytic. The midpoint rows depend on (q_n, q_1) and (e_n, e_1)
    !> only through their means, so d/dq = 2 d/dq_1 and d/de = 2 d/de_1 of ph_em_forces; and
    !> d(le e_P0)/dq is the increment matrix of eq. 64 at q (inc = G2^T dr - V^T dphi is the
    !> linearization of le e_P0, methods §4.3).
    pure subroutine ph_em_static(le, stiffness, n_gauss, h, q, e, r, k, reference)
        real(rk), intent(in) :: le, stiffness(3)
        integer, intent(in) :: n_gauss
        real(rk), intent(in) :: h, q(6), e(3)
        real(rk), intent(out) :: r(9)
        real(rk), intent(out), optional :: k(9, 9)
        real(rk), intent(in), optional :: reference(2, n_gauss)
        real(rk) :: w(max_gauss_points), nn(2, max_gauss_points), cs(2, max_gauss_points)
        real(rk) :: inc(3), dinc(3, 6), kf(9, 9)
        integer :: i
        call gauss_shapes(n_gauss, w, nn)
        call gauss_point_angles(n_gauss, nn, q(3), q(6), cs)
        r(7:9) = le * (ph_em_projected_strains(le, n_gauss, q, reference) - e) / h
        if (.not. present(k)) then
            call ph_em_forces(le, stiffness, no_viscosity, n_gauss, w, nn, cs, q, e, e, r(1:6))
            return
        end if
        call ph_em_forces(le, stiffness, no_viscosity, n_gauss, w, nn, cs, q, e, e, r(1:6), kf)
        call ph_em_strain_increment(le, n_gauss, w, nn, cs, q, [(0.0_rk, i = 1, 6)], inc, dinc)
        k = 0.0_rk
        k(1:6, :) = 2.0_rk * kf(1:6, :)
        k(7:9, 1:6) = dinc / h
        do i = 7, 9
            k(i, i) = -le / h
        end do
    end subroutine ph_em_static

    !> ph_em_static with the strains eliminated: e = e_P0(q) (the strain rows), the nodal rows
    !> r(6) at that e and the condensed tangent k(6, 6) = dr/dq + dr/de de/dq (optional), as
    !> ph_em_condensed does for a step.
    pure subroutine ph_em_static_condensed(le, stiffness, n_gauss, q, r, e, k, reference)
        real(rk), intent(in) :: le, stiffness(3)
        integer, intent(in) :: n_gauss
        real(rk), intent(in) :: q(6)
        real(rk), intent(out) :: r(6), e(3)
        real(rk), intent(out), optional :: k(6, 6)
        real(rk), intent(in), optional :: reference(2, n_gauss)
        real(rk) :: r9(9), k9(9, 9)
        e = ph_em_projected_strains(le, n_gauss, q, reference)
        if (.not. present(k)) then
            call ph_em_static(le, stiffness, n_gauss, 1.0_rk, q, e, r9, reference=reference)
        else
            call ph_em_static(le, stiffness, n_gauss, 1.0_rk, q, e, r9, k9, reference)
            ! de/dq = (k9 strain rows in q) / le with h = 1.
            k = k9(1:6, 1:6) + matmul(k9(1:6, 7:9), k9(7:9, 1:6) / le)
        end if
        r = r9(1:6)
    end subroutine ph_em_static_condensed

    !> The P0 projection onto one element of the compatible strains of nodal q (methods §3.1,
    !> §4.5) with the element's Gauss rule: sum_g w_g/2 (Lambda(phi_g)^T d_s r - reference(:, g)),
    !> and kappa = d_s phi. The strains the rate form (eqs. 63-64) tracks to O(h^2).
    pure function ph_em_projected_strains(le, n_gauss, q, reference) result(e)
        real(rk), intent(in) :: le
        integer, intent(in) :: n_gauss
        real(rk), intent(in) :: q(6)
        real(rk), intent(in), optional :: reference(2, n_gauss)
        real(rk) :: e(3)
        real(rk) :: gammas(3, max_gauss_points), xi(max_gauss_points), w(max_gauss_points)
        call gauss_rule(n_gauss, xi, w)
        call compatible_strains(le, n_gauss, q, gammas(:, 1:n_gauss), reference)
        e = matmul(gammas(:, 1:n_gauss), 0.5_rk * w(1:n_gauss))
    end function ph_em_projected_strains

    !> cl-EM (and PH-EMi) equilibrium of one state q: cl_em_residual with q_n = q_1 = q, i.e.
    !> Z1 = Z2 = 1 and N_g = D_ts (Lambda(phi_g)^T d_s r - e1), the internal forces of the
    !> compatible strains with the scheme's n_gauss rule (methods §5.1). PH-EMi has the same
    !> equilibrium once its Gauss-point history is the compatible strain (eq. 78 with dq = 0).
    !> k = dr/dq = 2 dr/dq_1: the midpoint residual is symmetric in (q_n, q_1) (Z1, Z2 are even
    !> in dphi, N uses the mean of the endpoint strains), so both partial derivatives agree at
    !> q_n = q_1.
    pure subroutine cl_em_static(le, stiffness, n_gauss, q, r, k, reference)
        real(rk), intent(in) :: le, stiffness(3)
        integer, intent(in) :: n_gauss
        real(rk), intent(in) :: q(6)
        real(rk), intent(out) :: r(6)
        real(rk), intent(out), optional :: k(6, 6)
        real(rk), intent(in), optional :: reference(2, n_gauss)
        real(rk) :: gamma_n(2, max_gauss_points)
        gamma_n = 0.0_rk
        call displacement_forces(.true., le, stiffness, no_viscosity, n_gauss, q, q, gamma_n, &
            reference_or_e1(n_gauss, reference), r, k)
        if (present(k)) k = 2.0_rk * k
    end subroutine cl_em_static

    !> cl-EM (Stander-Stein) internal nodal forces r(6) of one step (methods §5.1 eqs. 72-75):
    !>   (x, y) rows: sum_g w_g le/2 d_sN_I Z1 Lambda05_g N_g,
    !>   phi rows:   -sum_g w_g le/2 N_I (d_s r05)^T S Z2 Lambda05_g N_g -+ M05,
    !> N_g = D_ts (1/2 (Lambda(phi_1,g)^T d_s r_1 + Lambda(phi_n,g)^T d_s r_n) - e1),
    !> M05 = EI d_s phi05; Z1 = cos(dphi_g/2), Z2 = sin(dphi_g/2)/(dphi_g/2) at the interpolated
    !> Gauss-point increment dphi_g (eq. 67). n_gauss is the rule of the N terms (1 = reduced,
    !> 2 = full); bending is exact with any rule (kappa is constant per element). With viscosity,
    !> N_g gains V (Gamma_1,g - Gamma_n,g)/h (the compatible strains at the point) and M05
    !> gains V_EI (kappa_1 - kappa_n)/h: eq. 99 makes the rows the adjoints of exactly these
    !> increments, at every Gauss point of any rule.
    !> The scheme conserves energy exactly (Appendix A.5) but, since Z1 /= Z2, not angular
    !> momentum: the net internal torque about the origin, sum_I r05_I x F_I + m_I, is
    !> le sum_g w_g/2 (Z1 - Z2) d_s r05 x (Lambda05_g N_g) = O(dphi^2), not zero (unlike PH-EM
    !> and PH-EMi, where the Gauss-point integrands cancel, methods §4.3).
    pure subroutine cl_em_residual(le, stiffness, viscosity, n_gauss, h, q_n, q_1, r, &
            reference)
        real(rk), intent(in) :: le, stiffness(3), viscosity(3)
        integer, intent(in) :: n_gauss
        real(rk), intent(in) :: h, q_n(6), q_1(6)
        real(rk), intent(out) :: r(6)
        real(rk), intent(in), optional :: reference(2, n_gauss)
        real(rk) :: gamma_n(2, max_gauss_points)
        gamma_n = 0.0_rk
        call displacement_forces(.true., le, stiffness, viscosity / h, n_gauss, q_n, q_1, &
            gamma_n, reference_or_e1(n_gauss, reference), r)
    end subroutine cl_em_residual

    !> cl-EM Jacobian k(6, 6) = d r / d q_1 of cl_em_residual, analytic; smooth through
    !> dphi_g = 0 (series for Z2).
    pure subroutine cl_em_jacobian(le, stiffness, viscosity, n_gauss, h, q_n, q_1, k, &
            reference)
        real(rk), intent(in) :: le, stiffness(3), viscosity(3)
        integer, intent(in) :: n_gauss
        real(rk), intent(in) :: h, q_n(6), q_1(6)
        real(rk), intent(out) :: k(6, 6)
        real(rk), intent(in), optional :: reference(2, n_gauss)
        real(rk) :: gamma_n(2, max_gauss_points), r(6)
        gamma_n = 0.0_rk
        call displacement_forces(.true., le, stiffness, viscosity / h, n_gauss, q_n, q_1, &
            gamma_n, reference_or_e1(n_gauss, reference), r, k)
    end subroutine cl_em_jacobian

    !> PH-EMi internal nodal forces r(6) of one step (methods §5.2 eqs. 77-78): as cl-EM with
    !> Z1 = Z2 = 1 and the midpoint shear/axial strain from the Gauss-point history
    !>   Gamma05_g = gamma_n(:, g) + 1/2 (dphi_g Lambda05_g^T S d_s r05 + Lambda05_g^T d_s dr),
    !> N_g = D_ts Gamma05_g, M05 = EI d_s phi05. gamma_n(2, n_gauss): Gamma_n at the Gauss points.
    !> With viscosity, N_g gains V (gamma_1,g - gamma_n,g)/h, the history increment of eq. 78a,
    !> and M05 gains V_EI (kappa_1 - kappa_n)/h.
    pure subroutine ph_emi_residual(le, stiffness, viscosity, n_gauss, h, q_n, q_1, gamma_n, r)
        real(rk), intent(in) :: le, stiffness(3), viscosity(3)
        integer, intent(in) :: n_gauss
        real(rk), intent(in) :: h, q_n(6), q_1(6), gamma_n(2, n_gauss)
        real(rk), intent(out) :: r(6)
        call displacement_forces(.false., le, stiffness, viscosity / h, n_gauss, q_n, q_1, &
            gamma_n, reference_or_e1(n_gauss), r)
    end subroutine ph_emi_residual

    !> PH-EMi Jacobian k(6, 6) = d r / d q_1 of ph_emi_residual (history gamma_n fixed).
    pure subroutine ph_emi_jacobian(le, stiffness, viscosity, n_gauss, h, q_n, q_1, gamma_n, k)
        real(rk), intent(in) :: le, stiffness(3), viscosity(3)
        integer, intent(in) :: n_gauss
        real(rk), intent(in) :: h, q_n(6), q_1(6), gamma_n(2, n_gauss)
        real(rk), intent(out) :: k(6, 6)
        real(rk) :: r(6)
        call displacement_forces(.false., le, stiffness, viscosity / h, n_gauss, q_n, q_1, &
            gamma_n, reference_or_e1(n_gauss), r, k)
    end subroutine ph_emi_jacobian

    !> PH-EMi history update at the Gauss points (methods §5.2 eq. 78a, i.e. eq. 65 pointwise):
    !>   gamma_1(:, g) = gamma_n(:, g) + dphi_g Lambda05_g^T S d_s r05 + Lambda05_g^T d_s dr.
    pure subroutine ph_emi_strains(le, n_gauss, q_n, q_1, gamma_n, gamma_1)
        real(rk), intent(in) :: le
        integer, intent(in) :: n_gauss
        real(rk), intent(in) :: q_n(6), q_1(6), gamma_n(2, n_gauss)
        real(rk), intent(out) :: gamma_1(2, n_gauss)
        real(rk) :: w(max_gauss_points), nn(2, max_gauss_points), cs(2, max_gauss_points)
        real(rk) :: q05(6), u(2), dr_s(2), dq(6)
        integer :: g
        call gauss_shapes(n_gauss, w, nn)
        q05 = 0.5_rk * (q_n + q_1)
        dq = q_1 - q_n
        u = (q05(4:5) - q05(1:2)) / le
        dr_s = (dq(4:5) - dq(1:2)) / le
        call gauss_point_angles(n_gauss, nn, q05(3), q05(6), cs)
        do g = 1, n_gauss
            gamma_1(:, g) = gamma_n(:, g) + (nn(1, g) * dq(3) + nn(2, g) * dq(6)) &
                * rotate_back(cs(:, g), skew_times(u)) + rotate_back(cs(:, g), dr_s)
        end do
    end subroutine ph_emi_strains

    !> Kinematically compatible strains of nodal q at the Gauss points (methods §2.3 eqs. 5-6):
    !> gammas(1:2, g) = Lambda(phi_g)^T d_s r - reference(:, g) (default e1), gammas(3, g) =
    !> kappa = d_s phi (constant). For cl-EM energies and the drift diagnostic of PH-EM
    !> (methods §4.5).
    pure subroutine compatible_strains(le, n_gauss, q, gammas, reference)
        real(rk), intent(in) :: le
        integer, intent(in) :: n_gauss
        real(rk), intent(in) :: q(6)
        real(rk), intent(out) :: gammas(3, n_gauss)
        real(rk), intent(in), optional :: reference(2, n_gauss)
        real(rk) :: s(2, n_gauss)
        call stretches(le, n_gauss, q, s)
        gammas(1:2, :) = s - reference_or_e1(n_gauss, reference)
        gammas(3, :) = (q(6) - q(3)) / le
    end subroutine compatible_strains

    !> The reference stretch of an element whose stress-free state is nodal q0 shortened along
    !> its length by axial_reference (1 / (1 + prestrain), 1 for a stress-free start, docs/
    !> theory/prestretched_starts.md): reference(:, g) = axial_reference Lambda(phi_g)^T d_s r
    !> of q0 at the points of the n_gauss rule, the `reference` of the strain kernels. Formed
    !> with their arithmetic (stretches; cl-EM's step at q_n = q_1 forms the same products),
    !> so that the strains of q0 itself are exactly zero when axial_reference = 1, and not the
    !> round-off of d_s r against e1 (docs/theory/ph_planar.md "The reference stretch").
    pure subroutine reference_stretches(le, n_gauss, q0, axial_reference, reference)
        real(rk), intent(in) :: le
        integer, intent(in) :: n_gauss
        real(rk), intent(in) :: q0(6), axial_reference
        real(rk), intent(out) :: reference(2, n_gauss)
        call stretches(le, n_gauss, q0, reference)
        reference = axial_reference * reference
    end subroutine reference_stretches

    !> Consistent element mass m(6, 6) in the q ordering: rhoA M1^e on x and on y, rhoI M1^e on
    !> phi, M1^e = le/6 [[2, 1], [1, 2]] (methods §3.2, eq. 91; exact with 2-point Gauss, §4.3).
    pure subroutine element_mass(le, rhoA, rhoI, m)
        real(rk), intent(in) :: le, rhoA, rhoI
        real(rk), intent(out) :: m(6, 6)
        real(rk) :: m1(2, 2), dens(3)
        integer :: a, b, l
        m1 = le / 6.0_rk * reshape([2.0_rk, 1.0_rk, 1.0_rk, 2.0_rk], [2, 2])
        dens = [rhoA, rhoA, rhoI]
        m = 0.0_rk
        do a = 1, 2
            do b = 1, 2
                do l = 1, 3
                    m(3 * (a - 1) + l, 3 * (b - 1) + l) = dens(l) * m1(a, b)
                end do
            end do
        end do
    end subroutine element_mass

    !> Strain energy of the mixed strain DOFs e = (Gamma, kappa) of one element,
    !> le (1/2 Gamma^T D_ts Gamma + 1/2 EI kappa^2) (methods §3.2 eq. 44, the PH-EM Hamiltonian).
    pure function mixed_strain_energy(le, stiffness, e) result(energy)
        real(rk), intent(in) :: le, stiffness(3), e(3)
        real(rk) :: energy
        energy = 0.5_rk * le * sum(stiffness * e**2)
    end function mixed_strain_energy

    !> Strain energy of the compatible strains of nodal q with the n_gauss rule of the N terms
    !> (the cl-EM energy, methods §5.1 and Appendix A.5):
    !> sum_g w_g le/2 (1/2 Gamma_g^T D_ts Gamma_g) + le 1/2 EI kappa^2.
    pure function compatible_strain_energy(le, stiffness, n_gauss, q, reference) &
            result(energy)
        real(rk), intent(in) :: le, stiffness(3)
        integer, intent(in) :: n_gauss
        real(rk), intent(in) :: q(6)
        real(rk), intent(in), optional :: reference(2, n_gauss)
        real(rk) :: energy
        real(rk) :: gammas(3, max_gauss_points), xi(max_gauss_points), w(max_gauss_points)
        integer :: g
        call gauss_rule(n_gauss, xi, w)
        call compatible_strains(le, n_gauss, q, gammas(:, 1:n_gauss), reference)
        energy = 0.5_rk * le * stiffness(3) * gammas(3, 1)**2
        do g = 1, n_gauss
            energy = energy + 0.25_rk * le * w(g) * sum(stiffness(1:2) * gammas(1:2, g)**2)
        end do
    end function compatible_strain_energy

    !> Strain energy of PH-EMi (methods §5.2): the Gauss-point history strains gammas(2, n_gauss)
    !> for shear/axial and the compatible curvature of q for bending,
    !> sum_g w_g le/2 (1/2 gamma_g^T D_ts gamma_g) + le 1/2 EI (d_s phi)^2.
    pure function ph_emi_strain_energy(le, stiffness, n_gauss, q, gammas) result(energy)
        real(rk), intent(in) :: le, stiffness(3)
        integer, intent(in) :: n_gauss
        real(rk), intent(in) :: q(6), gammas(2, n_gauss)
        real(rk) :: energy
        real(rk) :: xi(max_gauss_points), w(max_gauss_points)
        integer :: g
        call gauss_rule(n_gauss, xi, w)
        energy = 0.5_rk * stiffness(3) * (q(6) - q(3))**2 / le
        do g = 1, n_gauss
            energy = energy + 0.25_rk * le * w(g) * sum(stiffness(1:2) * gammas(:, g)**2)
        end do
    end function ph_emi_strain_energy

    !> The energy the Kelvin-Voigt stresses of one step dissipate in one element
    !> (docs/theory/damping.md, docs/theory/ph_planar.md "Damping"):
    !>   D = sum_g w_g le/2 sum_i viscosity_i delta(i, g)^2 / h >= 0,
    !> delta(3, n_gauss) the step's strain increments (Gamma1, Gamma2, kappa)_{n+1} - ( )_n at
    !> the points of the n_gauss rule: the compatible strains (cl-EM) or the history (PH-EMi)
    !> there; PH-EM's P0 strains are one value per element, n_gauss = 1 (D = le delta^T V
    !> delta / h). It is the work -dq . r_v of the viscous part r_v of the step's force rows.
    pure function viscous_dissipation(le, viscosity, n_gauss, h, delta) result(d)
        real(rk), intent(in) :: le, viscosity(3)
        integer, intent(in) :: n_gauss
        real(rk), intent(in) :: h, delta(3, n_gauss)
        real(rk) :: d
        real(rk) :: xi(max_gauss_points), w(max_gauss_points)
        integer :: g
        call gauss_rule(n_gauss, xi, w)
        d = 0.0_rk
        do g = 1, n_gauss
            d = d + 0.5_rk * w(g) * le * sum(viscosity * delta(:, g)**2) / h
        end do
    end function viscous_dissipation

    !> s = sin(x)/x (1 at x = 0) and ds = ds/dx, the Z2 factor of cl-EM at x = dphi/2 (methods
    !> §5.1 eq. 67); Taylor series (to x^10 and x^9, truncation below 1e-19) for |x| < 0.1, so
    !> that Z2 and its derivative are smooth and accurate to round-off through dphi = 0.
    pure subroutine planar_sinc(x, s, ds)
        real(rk), intent(in) :: x
        real(rk), intent(out) :: s, ds
        call sinc_of(x, sin(x), cos(x), s, ds)
    end subroutine planar_sinc

    ! ---------------------------------------------------------------------------------------
    ! Private parts

    ! PH-EM nodal rows (methods §4.3): r = G2 N05 (x, y rows), -V N05 + G1 M05 (phi rows), and
    ! optionally their derivatives dr/d(q_1, e_1) in the rows 1:6 of k(9, 9) (rows 7:9 are left
    ! alone). G1 = [-1, +1]^T (§3.2), so G1 M05 = (-M05, +M05).
    ! rate(3): the Kelvin-Voigt viscosities over the step, V/h; the stresses of the step are
    ! (N05, M05) = D 1/2 (e_n + e_1) + rate (e_1 - e_n) (docs/theory/ph_planar.md "Damping").
    ! cs(:, g): Lambda_g at the interpolated midpoint angle (gauss_point_angles), no
    ! trigonometric factors (§4.3). The Gauss-point terms are those of gauss_point_force with
    ! Z1 = Z2 = 1 and N05 a function of e_1 only (dN05/de_1 = D_ts/2 + rate, columns 7 and 8).
    pure subroutine ph_em_forces(le, stiffness, rate, n_gauss, w, nn, cs, q05, e_n, e_1, r, k)
        real(rk), intent(in) :: le, stiffness(3), rate(3)
        integer, intent(in) :: n_gauss
        real(rk), intent(in) :: w(max_gauss_points), nn(2, max_gauss_points)
        real(rk), intent(in) :: cs(2, max_gauss_points), q05(6), e_n(3), e_1(3)
        real(rk), intent(out) :: r(6)
        real(rk), intent(inout), optional :: k(9, 9)
        real(rk) :: u(2), n05(2), m05, g0(2), sg0(2), t, hw, df_phi(2, 2), df_e(2, 2), dt(8), ut(2)
        real(rk) :: k_phi(2, 2), k_e(2, 2), k_t(8, 2), ds(3)
        integer :: g
        u = (q05(4:5) - q05(1:2)) / le
        ! N05 = D_ts Gamma05, M05 = EI kappa05 (eqs. 56g-h; W quadratic), plus the viscous
        ! stress; ds = d(N05, M05)/de_1.
        n05 = 0.5_rk * stiffness(1:2) * (e_n(1:2) + e_1(1:2))
        m05 = 0.5_rk * stiffness(3) * (e_n(3) + e_1(3))
        ds = 0.5_rk * stiffness
        if (any(rate /= 0.0_rk)) then
            n05 = n05 + rate(1:2) * (e_1(1:2) - e_n(1:2))
            m05 = m05 + rate(3) * (e_1(3) - e_n(3))
            ds = ds + rate
        end if
        r = 0.0_rk
        r(3) = -m05
        r(6) = m05
        ! The Gauss-point sums of the non-zero blocks of k, written to k after the loop (a
        ! tenth faster than adding to k's strided rows in place): k_phi and k_e are the
        ! (x, y)_a rows in the columns phi_a, phi_b (3, 6) and Gamma_1 (7, 8), whose
        ! (x, y)_b rows are their negatives; k_t(:, I) is the phi_I row in columns 1:8.
        k_phi = 0.0_rk
        k_e = 0.0_rk
        k_t = 0.0_rk
        do g = 1, n_gauss
            ! f = Lambda_g N05, t = (d_s r05)^T S Lambda_g N05
            g0 = rotate(cs(:, g), n05)
            sg0 = skew_times(g0)
            t = dot_product(u, sg0)
            hw = 0.5_rk * w(g)
            r(1:2) = r(1:2) - hw * g0
            r(4:5) = r(4:5) + hw * g0
            r(3) = r(3) - hw * le * nn(1, g) * t
            r(6) = r(6) - hw * le * nn(2, g) * t
            if (.not. present(k)) cycle
            ! df = df/d(unknowns) and dt = dt/d(unknowns) in their non-zero columns: f depends on
            ! phi_1 (columns 3, 6: df_phi) and e_1 (7, 8: df_e), t on everything but kappa_1 (9).
            ! Through N05: df = Lambda_g dN05, dt = (Lambda_g^T S^T u) . dN05 (S^T = -S)
            ut = rotate_back(cs(:, g), -skew_times(u))
            df_e(:, 1) = ds(1) * cs(:, g)
            df_e(:, 2) = ds(2) * [-cs(2, g), cs(1, g)]
            dt(7) = ds(1) * ut(1)
            dt(8) = ds(2) * ut(2)
            ! Through d_s r05 in t: d(d_s r05)/dr_1,b = -d(d_s r05)/dr_1,a = I/(2 le)
            dt(1:2) = -0.5_rk / le * sg0
            dt(4:5) = 0.5_rk / le * sg0
            ! Through phi05_g: dLambda_g/dphi_1,J = 1/2 N_J S^T Lambda_g
            df_phi(:, 1) = -nn(1, g) * 0.5_rk * sg0
            df_phi(:, 2) = -nn(2, g) * 0.5_rk * sg0
            dt(3) = nn(1, g) * 0.5_rk * dot_product(u, g0)
            dt(6) = nn(2, g) * 0.5_rk * dot_product(u, g0)
            k_phi = k_phi - hw * df_phi
            k_e = k_e - hw * df_e
            k_t(:, 1) = k_t(:, 1) - hw * le * nn(1, g) * dt
            k_t(:, 2) = k_t(:, 2) - hw * le * nn(2, g) * dt
        end do
        if (.not. present(k)) return
        k(1:6, :) = 0.0_rk
        k(1:2, 3:6:3) = k_phi
        k(4:5, 3:6:3) = -k_phi
        k(1:2, 7:8) = k_e
        k(4:5, 7:8) = -k_e
        k(3, 1:8) = k_t(:, 1)
        k(6, 1:8) = k_t(:, 2)
        k(3, 9) = -ds(3)
        k(6, 9) = ds(3)
    end subroutine ph_em_forces

    ! The PH-EM strain-row increments without the 1/h (methods §4.3, eq. 64 and eq. 63):
    !   inc(1:2) = G2e^T dr - Ve^T dphi
    !            = sum_g w_g le/2 [Lambda_g^T d_s dr + dphi_g Lambda_g^T S d_s r05]
    !   inc(3)   = G1e^T dphi = dphi_b - dphi_a,
    ! and optionally dinc(3, 6) = d inc / d q_1. cs(:, g): Lambda_g as in ph_em_forces (the same
    ! G2 and V in the momentum and the strain rows, §4.3).
    pure subroutine ph_em_strain_increment(le, n_gauss, w, nn, cs, q05, dq, inc, dinc)
        real(rk), intent(in) :: le
        integer, intent(in) :: n_gauss
        real(rk), intent(in) :: w(max_gauss_points), nn(2, max_gauss_points)
        real(rk), intent(in) :: cs(2, max_gauss_points), q05(6), dq(6)
        real(rk), intent(out) :: inc(3)
        real(rk), intent(out), optional :: dinc(3, 6)
        real(rk) :: u(2), dr_ba(2), dphi_g, su(2), b(2, 2), v(2), d_r(2, 2), d_phi(2, 2)
        integer :: g
        u = (q05(4:5) - q05(1:2)) / le
        dr_ba = dq(4:5) - dq(1:2)
        su = skew_times(u)
        inc = 0.0_rk
        inc(3) = dq(6) - dq(3)
        ! Gauss-point sums of d inc(1:2) / d r_1,b (= -d / d r_1,a) and d / d phi_1,a|b
        d_r = 0.0_rk
        d_phi = 0.0_rk
        do g = 1, n_gauss
            dphi_g = nn(1, g) * dq(3) + nn(2, g) * dq(6)
            ! (w_g le/2)(1/le) Lambda_g^T dr_ba + (w_g le/2) dphi_g Lambda_g^T S u
            inc(1:2) = inc(1:2) + 0.5_rk * w(g) * rotate_back(cs(:, g), dr_ba + le * dphi_g * su)
            if (.not. present(dinc)) cycle
            ! d/dr_1,b = w_g/2 Lambda_g^T (I + 1/2 dphi_g S)  (du/dr_1,b = I/(2 le)); r_1,a: minus
            b(:, 1) = 0.5_rk * w(g) * rotate_back(cs(:, g), [1.0_rk, -0.5_rk * dphi_g])
            b(:, 2) = 0.5_rk * w(g) * rotate_back(cs(:, g), [0.5_rk * dphi_g, 1.0_rk])
            d_r = d_r + b
            ! d/dphi_1,J = w_g/2 N_J Lambda_g^T [1/2 S dr_ba + le S u - 1/2 le dphi_g u]
            ! (dLambda_g^T/dphi_1,J = 1/2 N_J Lambda_g^T S, d dphi_g/dphi_1,J = N_J, S S = -I)
            v = 0.5_rk * w(g) * rotate_back(cs(:, g), 0.5_rk * skew_times(dr_ba) + le * su &
                - 0.5_rk * le * dphi_g * u)
            d_phi(:, 1) = d_phi(:, 1) + nn(1, g) * v
            d_phi(:, 2) = d_phi(:, 2) + nn(2, g) * v
        end do
        if (.not. present(dinc)) return
        dinc(1:2, 1:2) = -d_r
        dinc(1:2, 4:5) = d_r
        dinc(1:2, 3) = d_phi(:, 1)
        dinc(1:2, 6) = d_phi(:, 2)
        dinc(3, :) = [0.0_rk, 0.0_rk, -1.0_rk, 0.0_rk, 0.0_rk, 1.0_rk]
    end subroutine ph_em_strain_increment

    ! Nodal rows of the displacement-based schemes (methods §5.1 eq. 75 for cl-EM, §5.2 eq. 77
    ! for PH-EMi) and optionally k(6, 6) = dr/dq_1. cl-EM's strains are measured from the
    ! reference stretch reference(:, g) (PH-EMi's history carries its own). Bending is
    ! G1 M05 with M05 = EI d_s phi05 in both. `stander_stein` selects cl-EM (endpoint-average strain, Z1, Z2); otherwise PH-EMi
    ! (history strain gamma_n, Z1 = Z2 = 1). rate(3) = V/h: the stresses of the step are
    ! N_g = D_ts Gamma05_g + rate (Gamma_1,g - Gamma_n,g) and M05 = EI kappa05 + rate_EI dkappa,
    ! with the scheme's own strain increment (compatible, or the history update of eq. 78a);
    ! Gamma_1,g - Gamma_n,g = 2 (Gamma05_g - Gamma_n,g) as a function of q_1, so
    ! dN_g/dq_1 = (D_ts + 2 rate) dGamma05_g/dq_1.
    pure subroutine displacement_forces(stander_stein, le, stiffness, rate, n_gauss, q_n, q_1, &
            gamma_n, reference, r, k)
        logical, intent(in) :: stander_stein
        real(rk), intent(in) :: le, stiffness(3), rate(3)
        integer, intent(in) :: n_gauss
        real(rk), intent(in) :: q_n(6), q_1(6), gamma_n(2, n_gauss), reference(2, n_gauss)
        real(rk), intent(out) :: r(6)
        real(rk), intent(out), optional :: k(6, 6)
        real(rk) :: w(max_gauss_points), nn(2, max_gauss_points), q05(6), dq(6), u(2)
        real(rk) :: rs_1(2), rs_n(2), dr_s(2), cs05(2), cs1(2), cs_n(2), cs_half(2)
        real(rk) :: gam(2), dgam(2, 6), b(2, 2), v(2), z(2), dz(2), dphi_g, phi1_g, phin_g
        real(rk) :: phi05_g, m05, ei2, half, n(2), inc(2), g_n(2), dn_dgam(2)
        logical :: viscous
        integer :: g
        call gauss_shapes(n_gauss, w, nn)
        viscous = any(rate /= 0.0_rk)
        q05 = 0.5_rk * (q_n + q_1)
        dq = q_1 - q_n
        u = (q05(4:5) - q05(1:2)) / le
        rs_1 = (q_1(4:5) - q_1(1:2)) / le
        rs_n = (q_n(4:5) - q_n(1:2)) / le
        dr_s = rs_1 - rs_n
        ! G1 M05, M05 = EI kappa05 = EI d_s phi05 (eqs. 72-73, 78b), exact for any rule.
        m05 = stiffness(3) * (q05(6) - q05(3)) / le + rate(3) * (dq(6) - dq(3)) / le
        dn_dgam = stiffness(1:2) + 2.0_rk * rate(1:2)
        r = 0.0_rk
        r(3) = -m05
        r(6) = m05
        if (present(k)) then
            k = 0.0_rk
            ei2 = (0.5_rk * stiffness(3) + rate(3)) / le
            k(3, 3) = ei2
            k(3, 6) = -ei2
            k(6, 3) = -ei2
            k(6, 6) = ei2
        end if
        do g = 1, n_gauss
            phi1_g = nn(1, g) * q_1(3) + nn(2, g) * q_1(6)
            phin_g = nn(1, g) * q_n(3) + nn(2, g) * q_n(6)
            dphi_g = phi1_g - phin_g
            if (stander_stein) then
                ! Lambda05 = Lambda_n Lambda(dphi_g/2), Lambda_1 = Lambda05 Lambda(dphi_g/2)
                ! (rotations about one axis add): two sine-cosine pairs per point instead of
                ! four, and those of dphi_g/2 give Z1 and Z2 as well.
                half = 0.5_rk * dphi_g
                cs_n = [cos(phin_g), sin(phin_g)]
                cs_half = [cos(half), sin(half)]
                cs05 = rotate(cs_n, cs_half)
                cs1 = rotate(cs05, cs_half)
                ! Gamma05 = 1/2 (Lambda_1^T d_s r_1 + Lambda_n^T d_s r_n) - e1 (eq. 72; e1
                ! the reference stretch) and its increment Gamma_1 - Gamma_n. At q_n = q_1,
                ! cs1 = cs_n exactly (cs_half = (1, 0)) and both products are those of
                ! stretches: Gamma05 of the state reference_stretches had is exactly 0.
                gam = rotate_back(cs1, rs_1)
                g_n = rotate_back(cs_n, rs_n)
                inc = gam - g_n
                gam = 0.5_rk * (gam + g_n) - reference(:, g)
                ! Z1 = cos(dphi/2), Z2 = sin(dphi/2)/(dphi/2) (eq. 67), derivatives in dphi_g
                call sinc_of(half, cs_half(2), cs_half(1), z(2), dz(2))
                z(1) = cs_half(1)
                dz(1) = -0.5_rk * cs_half(2)
                dz(2) = 0.5_rk * dz(2)
                if (present(k)) then
                    ! dGamma05/dr_1,b = 1/(2 le) Lambda_1^T;
                    ! dGamma05/dphi_1,J = 1/2 N_J Lambda_1^T S d_s r_1
                    b(:, 1) = 0.5_rk / le * rotate_back(cs1, [1.0_rk, 0.0_rk])
                    b(:, 2) = 0.5_rk / le * rotate_back(cs1, [0.0_rk, 1.0_rk])
                    v = 0.5_rk * rotate_back(cs1, skew_times(rs_1))
                end if
            else
                phi05_g = 0.5_rk * (phi1_g + phin_g)
                cs05 = [cos(phi05_g), sin(phi05_g)]
                ! Gamma05 = Gamma_n + 1/2 (dphi Lambda05^T S d_s r05 + Lambda05^T d_s dr) (eq. 78a)
                inc = rotate_back(cs05, dphi_g * skew_times(u) + dr_s)
                gam = gamma_n(:, g) + 0.5_rk * inc
                z = 1.0_rk
                dz = 0.0_rk
                if (present(k)) then
                    ! dGamma05/dr_1,b = 1/(2 le) Lambda05^T (I + 1/2 dphi_g S);
                    ! dGamma05/dphi_1,J = 1/2 N_J Lambda05^T [S u - 1/2 dphi_g u + 1/2 S d_s dr]
                    b(:, 1) = 0.5_rk / le * rotate_back(cs05, [1.0_rk, -0.5_rk * dphi_g])
                    b(:, 2) = 0.5_rk / le * rotate_back(cs05, [0.5_rk * dphi_g, 1.0_rk])
                    v = 0.5_rk * rotate_back(cs05, skew_times(u) - 0.5_rk * dphi_g * u &
                        + 0.5_rk * skew_times(dr_s))
                end if
            end if
            n = stiffness(1:2) * gam
            if (viscous) n = n + rate(1:2) * inc
            if (present(k)) then
                ! dN = (D_ts + 2 rate) dGamma05
                dgam(:, 4:5) = b
                dgam(:, 1:2) = -b
                dgam(:, 3) = nn(1, g) * v
                dgam(:, 6) = nn(2, g) * v
                dgam(1, :) = dn_dgam(1) * dgam(1, :)
                dgam(2, :) = dn_dgam(2) * dgam(2, :)
                call gauss_point_force(le, w(g), nn(:, g), cs05, u, z, dz, n, r, dgam, k)
            else
                call gauss_point_force(le, w(g), nn(:, g), cs05, u, z, dz, n, r)
            end if
        end do
    end subroutine displacement_forces

    ! The reference stretch of an optional `reference` argument: e1 at every point when absent.
    pure function reference_or_e1(n_gauss, reference) result(value)
        integer, intent(in) :: n_gauss
        real(rk), intent(in), optional :: reference(2, n_gauss)
        real(rk) :: value(2, n_gauss)
        if (present(reference)) then
            value = reference
        else
            value(1, :) = 1.0_rk
            value(2, :) = 0.0_rk
        end if
    end function reference_or_e1

    ! The stretches s(:, g) = Lambda(phi_g)^T d_s r of nodal q at the points of the n_gauss
    ! rule (methods §2.3 eq. 5 without e1): the arithmetic of every strain formed from
    ! positions (compatible_strains, reference_stretches; displacement_forces forms the same
    ! products at q_n = q_1).
    pure subroutine stretches(le, n_gauss, q, s)
        real(rk), intent(in) :: le
        integer, intent(in) :: n_gauss
        real(rk), intent(in) :: q(6)
        real(rk), intent(out) :: s(2, n_gauss)
        real(rk) :: w(max_gauss_points), nn(2, max_gauss_points), cs(2, max_gauss_points), r_s(2)
        integer :: g
        call gauss_shapes(n_gauss, w, nn)
        call gauss_point_angles(n_gauss, nn, q(3), q(6), cs)
        r_s = (q(4:5) - q(1:2)) / le
        do g = 1, n_gauss
            s(:, g) = rotate_back(cs(:, g), r_s)
        end do
    end subroutine stretches

    ! Add the contribution of one Gauss point to the nodal rows of the displacement schemes
    ! (methods §4.3 "pointwise", §5.1 eq. 75), Lambda05 given by cs05 = (cos, sin) phi05_g:
    !   f = Z1 Lambda05 N,  t = Z2 (d_s r05)^T S Lambda05 N,
    !   r(x, y)_I += w le/2 d_sN_I f = -+ w/2 f,  r(phi)_I -= w le/2 N_I t,
    ! with Z1, Z2 functions of dphi_g (dz their derivatives in dphi_g; 0 and 1 in PH-EMi).
    ! With k: dn(2, 6) = dN/dq_1; the explicit dependencies are dphi_g/dphi_1,J = N_J,
    ! dLambda05/dphi_1,J = 1/2 N_J S^T Lambda05 and d(d_s r05)/dr_1,b = -d(d_s r05)/dr_1,a =
    ! I/(2 le). PH-EM's rows (ph_em_forces) are these with Z1 = Z2 = 1 and N a function of e_1.
    pure subroutine gauss_point_force(le, w, nn, cs05, u, z, dz, n, r, dn, k)
        real(rk), intent(in) :: le, w, nn(2), cs05(2), u(2), z(2), dz(2), n(2)
        real(rk), intent(inout) :: r(6)
        real(rk), intent(in), optional :: dn(2, 6)
        real(rk), intent(inout), optional :: k(6, 6)
        real(rk) :: g0(2), sg0(2), f(2), t, df(2, 6), dt(6), ut(2), e(2)
        integer :: j, a
        g0 = rotate(cs05, n)
        sg0 = skew_times(g0)
        f = z(1) * g0
        t = z(2) * dot_product(u, sg0)
        r(1:2) = r(1:2) - 0.5_rk * w * f
        r(4:5) = r(4:5) + 0.5_rk * w * f
        r(3) = r(3) - 0.5_rk * w * le * nn(1) * t
        r(6) = r(6) - 0.5_rk * w * le * nn(2) * t
        if (.not. present(k)) return
        ! Through N: df = Z1 Lambda05 dN, dt = Z2 (Lambda05^T S^T u) . dN (S^T = -S)
        ut = rotate_back(cs05, -skew_times(u))
        do j = 1, 6
            df(:, j) = z(1) * rotate(cs05, dn(:, j))
            dt(j) = z(2) * dot_product(ut, dn(:, j))
        end do
        ! Through d_s r05 in t
        dt(1:2) = dt(1:2) - 0.5_rk / le * z(2) * sg0
        dt(4:5) = dt(4:5) + 0.5_rk / le * z(2) * sg0
        ! Through dphi_g (Z1, Z2) and phi05_g (Lambda05); S^T g0 = -sg0
        e = dz(1) * g0 - 0.5_rk * z(1) * sg0
        do a = 1, 2
            j = 3 * a
            df(:, j) = df(:, j) + nn(a) * e
            dt(j) = dt(j) + nn(a) * (dz(2) * dot_product(u, sg0) &
                + 0.5_rk * z(2) * dot_product(u, g0))
        end do
        k(1:2, :) = k(1:2, :) - 0.5_rk * w * df
        k(4:5, :) = k(4:5, :) + 0.5_rk * w * df
        k(3, :) = k(3, :) - 0.5_rk * w * le * nn(1) * dt
        k(6, :) = k(6, :) - 0.5_rk * w * le * nn(2) * dt
    end subroutine gauss_point_force

    ! Gauss points and weights on [-1, 1] (methods §3.1: 2-point full, 1-point reduced); zero
    ! outside 1 .. max_gauss_points (the formulation validates n_gauss).
    pure subroutine gauss_rule(n_gauss, xi, w)
        integer, intent(in) :: n_gauss
        real(rk), intent(out) :: xi(max_gauss_points), w(max_gauss_points)
        logical :: ok
        xi = 0.0_rk
        w = 0.0_rk
        if (n_gauss < 1 .or. n_gauss > max_gauss_points) return
        call gauss_legendre(n_gauss, xi(1:n_gauss), w(1:n_gauss), ok)
    end subroutine gauss_rule

    ! The n_gauss rule with the linear shape functions at its points: weights w(g) and
    ! nn(:, g) = (N_a, N_b)(xi_g) = ((1 - xi_g)/2, (1 + xi_g)/2) (methods §3.1 eqs. 87-89).
    pure subroutine gauss_shapes(n_gauss, w, nn)
        integer, intent(in) :: n_gauss
        real(rk), intent(out) :: w(max_gauss_points), nn(2, max_gauss_points)
        real(rk) :: xi(max_gauss_points)
        call gauss_rule(n_gauss, xi, w)
        nn(1, :) = 0.5_rk * (1.0_rk - xi)
        nn(2, :) = 0.5_rk * (1.0_rk + xi)
    end subroutine gauss_shapes

    ! cs(:, g) = (cos, sin) of the interpolated angle N_a(xi_g) phi_a + N_b(xi_g) phi_b: one
    ! sine-cosine pair per Gauss point, for every term of a kernel that needs Lambda_g.
    pure subroutine gauss_point_angles(n_gauss, nn, phi_a, phi_b, cs)
        integer, intent(in) :: n_gauss
        real(rk), intent(in) :: nn(2, max_gauss_points), phi_a, phi_b
        real(rk), intent(out) :: cs(2, max_gauss_points)
        real(rk) :: phi
        integer :: g
        cs = 0.0_rk
        do g = 1, min(n_gauss, max_gauss_points)
            phi = nn(1, g) * phi_a + nn(2, g) * phi_b
            cs(:, g) = [cos(phi), sin(phi)]
        end do
    end subroutine gauss_point_angles

    ! Lambda x, Lambda = Lambda(phi) of methods §2.2 eq. (3) given by cs = (cos phi, sin phi).
    ! With cs = (cos b, sin b) for x this is (cos, sin)(phi + b).
    pure function rotate(cs, x) result(y)
        real(rk), intent(in) :: cs(2), x(2)
        real(rk) :: y(2)
        y(1) = cs(1) * x(1) - cs(2) * x(2)
        y(2) = cs(2) * x(1) + cs(1) * x(2)
    end function rotate

    ! Lambda^T x, Lambda given by cs as in rotate.
    pure function rotate_back(cs, x) result(y)
        real(rk), intent(in) :: cs(2), x(2)
        real(rk) :: y(2)
        y(1) = cs(1) * x(1) + cs(2) * x(2)
        y(2) = -cs(2) * x(1) + cs(1) * x(2)
    end function rotate_back

    ! S x with S = [[0, 1], [-1, 0]] of methods §2.1 eq. (1); S^T x = -S x.
    pure function skew_times(x) result(y)
        real(rk), intent(in) :: x(2)
        real(rk) :: y(2)
        y(1) = x(2)
        y(2) = -x(1)
    end function skew_times

    ! sin(x)/x and its derivative from x, sin(x) and cos(x) (planar_sinc; cl-EM has the sine
    ! and cosine of dphi_g/2 already, for Z1 and Lambda05).
    pure subroutine sinc_of(x, sin_x, cos_x, s, ds)
        real(rk), intent(in) :: x, sin_x, cos_x
        real(rk), intent(out) :: s, ds
        real(rk) :: x2
        if (abs(x) < sinc_series_limit) then
            x2 = x * x
            s = 1.0_rk - x2 / 6.0_rk * (1.0_rk - x2 / 20.0_rk * (1.0_rk - x2 / 42.0_rk &
                * (1.0_rk - x2 / 72.0_rk * (1.0_rk - x2 / 110.0_rk))))
            ds = -x / 3.0_rk * (1.0_rk - x2 / 10.0_rk * (1.0_rk - x2 / 28.0_rk &
                * (1.0_rk - x2 / 54.0_rk * (1.0_rk - x2 / 88.0_rk))))
        else
            s = sin_x / x
            ds = (cos_x - s) / x
        end if
    end subroutine sinc_of

end module rs_ph_planar_element
