!> Element kernels of the planar geometrically exact beam of seed 001 (methods/ph_planar.md):
!> the port-Hamiltonian energy-momentum scheme PH-EM (§4.3) and the two displacement-based
!> comparison schemes cl-EM (Stander-Stein, §5.1) and PH-EMi (§5.2), one implicit-midpoint step
!> each: internal nodal forces, strain rows, analytic Jacobians, strains, energies and the
!> consistent mass. Pure procedures on plain arrays: no PETSc, no MPI, no allocation
!> (DESIGN.md §2, STYLE.md item 4).
!>
!> Conventions (fixed; the planar formulation relies on them):
!> - Two-node element of reference length le (straight, stress-free reference: Gamma_ref = 0,
!>   kappa_ref = 0, methods §2.3). Nodal unknowns q = (x_a, y_a, phi_a, x_b, y_b, phi_b);
!>   element strains e = (Gamma1, Gamma2, kappa) (methods §3.1, P0); the angle phi is never
!>   wrapped (§2.2).
!> - Lambda(phi) = [[cos, -sin], [sin, cos]], S = [[0, 1], [-1, 0]], dLambda/dphi = S^T Lambda
!>   (methods §2.1 eq. 1, §2.2 eqs. 3-4); the planar cross product is a x b = a^T S b.
!> - stiffness = (EA, GA, EI) with GA the shear stiffness k G A: D_ts = diag(EA, GA) (eq. 10).
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
    public :: cl_em_residual, cl_em_jacobian
    public :: ph_emi_residual, ph_emi_jacobian, ph_emi_strains
    public :: compatible_strains, element_mass
    public :: mixed_strain_energy, compatible_strain_energy, ph_emi_strain_energy
    public :: planar_sinc

    !> Largest number of Gauss points an element accepts.
    integer, parameter, public :: planar_max_gauss = max_gauss_points

    ! S of methods §2.1 eq. (1), column-major: S = [[0, 1], [-1, 0]].
    real(rk), parameter :: skew(2, 2) = reshape([0.0_rk, -1.0_rk, 1.0_rk, 0.0_rk], [2, 2])
    ! Below this |x|, sin(x)/x and its derivative are evaluated by their Taylor series (the
    ! closed form of the derivative loses ~eps/x^3 relative accuracy to cancellation).
    real(rk), parameter :: sinc_series_limit = 0.1_rk

contains

    !> PH-EM element residual r(9) of one step (methods §4.3, eqs. 56c-h as solved in moofeKIT):
    !>   r(1:6): internal nodal forces, G2 N05 in the (x, y) rows and -V N05 + G1 M05 in the
    !>           phi rows, with N05 = D_ts 1/2 (Gamma_n + Gamma_1), M05 = EI 1/2 (kappa_n +
    !>           kappa_1) and G2, V at the midpoint configuration (§3.2);
    !>   r(7:8): R_Gamma = -C2e (Gamma_1 - Gamma_n)/h + G2e^T dr/h - Ve^T dphi/h;
    !>   r(9):   R_kappa = -le (kappa_1 - kappa_n)/h + (dphi_b - dphi_a)/h.
    !> No inertia, no external loads.
    pure subroutine ph_em_residual(le, stiffness, n_gauss, h, q_n, q_1, e_n, e_1, r)
        real(rk), intent(in) :: le, stiffness(3)
        integer, intent(in) :: n_gauss
        real(rk), intent(in) :: h, q_n(6), q_1(6), e_n(3), e_1(3)
        real(rk), intent(out) :: r(9)
        real(rk) :: inc(3)
        call ph_em_forces(le, stiffness, n_gauss, q_n, q_1, e_n, e_1, r(1:6))
        call ph_em_strain_increment(le, n_gauss, q_n, q_1, inc)
        r(7:9) = (-le * (e_1 - e_n) + inc) / h
    end subroutine ph_em_residual

    !> PH-EM element Jacobian k(9, 9) = d r / d (q_1(1:6), e_1(1:3)) of ph_em_residual,
    !> analytic (methods §4.3, §10 "Jacobian").
    pure subroutine ph_em_jacobian(le, stiffness, n_gauss, h, q_n, q_1, e_n, e_1, k)
        real(rk), intent(in) :: le, stiffness(3)
        integer, intent(in) :: n_gauss
        real(rk), intent(in) :: h, q_n(6), q_1(6), e_n(3), e_1(3)
        real(rk), intent(out) :: k(9, 9)
        real(rk) :: r(6), inc(3), dinc(3, 6)
        integer :: i
        call ph_em_forces(le, stiffness, n_gauss, q_n, q_1, e_n, e_1, r, k(1:6, :))
        call ph_em_strain_increment(le, n_gauss, q_n, q_1, inc, dinc)
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
    !> 9 x 9 Jacobian). h only scales the eliminated rows, so none of the outputs depends on it.
    pure subroutine ph_em_condensed(le, stiffness, n_gauss, h, q_n, q_1, e_n, r, k, e_1)
        real(rk), intent(in) :: le, stiffness(3)
        integer, intent(in) :: n_gauss
        real(rk), intent(in) :: h, q_n(6), q_1(6), e_n(3)
        real(rk), intent(out) :: r(6), k(6, 6), e_1(3)
        real(rk) :: inc(3), dinc(3, 6), kf(6, 9), h_unused
        h_unused = h
        call ph_em_strain_increment(le, n_gauss, q_n, q_1, inc, dinc)
        e_1 = e_n + inc / le
        call ph_em_forces(le, stiffness, n_gauss, q_n, q_1, e_n, e_1, r, kf)
        k = kf(:, 1:6) + matmul(kf(:, 7:9), dinc / le)
    end subroutine ph_em_condensed

    !> cl-EM (Stander-Stein) internal nodal forces r(6) of one step (methods §5.1 eqs. 72-75):
    !>   (x, y) rows: sum_g w_g le/2 d_sN_I Z1 Lambda05_g N_g,
    !>   phi rows:   -sum_g w_g le/2 N_I (d_s r05)^T S Z2 Lambda05_g N_g -+ EI kappa05,
    !> N_g = D_ts (1/2 (Lambda(phi_1,g)^T d_s r_1 + Lambda(phi_n,g)^T d_s r_n) - e1),
    !> kappa05 = d_s phi05; Z1 = cos(dphi_g/2), Z2 = sin(dphi_g/2)/(dphi_g/2) at the interpolated
    !> Gauss-point increment dphi_g (eq. 67). n_gauss is the rule of the N terms (1 = reduced,
    !> 2 = full); bending is exact with any rule (kappa is constant per element).
    !> The scheme conserves energy exactly (Appendix A.5) but, since Z1 /= Z2, not angular
    !> momentum: the net internal torque about the origin, sum_I r05_I x F_I + m_I, is
    !> le sum_g w_g/2 (Z1 - Z2) d_s r05 x (Lambda05_g N_g) = O(dphi^2), not zero (unlike PH-EM
    !> and PH-EMi, where the Gauss-point integrands cancel, methods §4.3).
    pure subroutine cl_em_residual(le, stiffness, n_gauss, q_n, q_1, r)
        real(rk), intent(in) :: le, stiffness(3)
        integer, intent(in) :: n_gauss
        real(rk), intent(in) :: q_n(6), q_1(6)
        real(rk), intent(out) :: r(6)
        real(rk) :: gamma_n(2, max_gauss_points)
        gamma_n = 0.0_rk
        call displacement_forces(.true., le, stiffness, n_gauss, q_n, q_1, gamma_n, r)
    end subroutine cl_em_residual

    !> cl-EM Jacobian k(6, 6) = d r / d q_1 of cl_em_residual, analytic; smooth through
    !> dphi_g = 0 (series for Z2).
    pure subroutine cl_em_jacobian(le, stiffness, n_gauss, q_n, q_1, k)
        real(rk), intent(in) :: le, stiffness(3)
        integer, intent(in) :: n_gauss
        real(rk), intent(in) :: q_n(6), q_1(6)
        real(rk), intent(out) :: k(6, 6)
        real(rk) :: gamma_n(2, max_gauss_points), r(6)
        gamma_n = 0.0_rk
        call displacement_forces(.true., le, stiffness, n_gauss, q_n, q_1, gamma_n, r, k)
    end subroutine cl_em_jacobian

    !> PH-EMi internal nodal forces r(6) of one step (methods §5.2 eqs. 77-78): as cl-EM with
    !> Z1 = Z2 = 1 and the midpoint shear/axial strain from the Gauss-point history
    !>   Gamma05_g = gamma_n(:, g) + 1/2 (dphi_g Lambda05_g^T S d_s r05 + Lambda05_g^T d_s dr),
    !> N_g = D_ts Gamma05_g, M05 = EI d_s phi05. gamma_n(2, n_gauss): Gamma_n at the Gauss points.
    pure subroutine ph_emi_residual(le, stiffness, n_gauss, q_n, q_1, gamma_n, r)
        real(rk), intent(in) :: le, stiffness(3)
        integer, intent(in) :: n_gauss
        real(rk), intent(in) :: q_n(6), q_1(6), gamma_n(2, n_gauss)
        real(rk), intent(out) :: r(6)
        call displacement_forces(.false., le, stiffness, n_gauss, q_n, q_1, gamma_n, r)
    end subroutine ph_emi_residual

    !> PH-EMi Jacobian k(6, 6) = d r / d q_1 of ph_emi_residual (history gamma_n fixed).
    pure subroutine ph_emi_jacobian(le, stiffness, n_gauss, q_n, q_1, gamma_n, k)
        real(rk), intent(in) :: le, stiffness(3)
        integer, intent(in) :: n_gauss
        real(rk), intent(in) :: q_n(6), q_1(6), gamma_n(2, n_gauss)
        real(rk), intent(out) :: k(6, 6)
        real(rk) :: r(6)
        call displacement_forces(.false., le, stiffness, n_gauss, q_n, q_1, gamma_n, r, k)
    end subroutine ph_emi_jacobian

    !> PH-EMi history update at the Gauss points (methods §5.2 eq. 78a, i.e. eq. 65 pointwise):
    !>   gamma_1(:, g) = gamma_n(:, g) + dphi_g Lambda05_g^T S d_s r05 + Lambda05_g^T d_s dr.
    pure subroutine ph_emi_strains(le, n_gauss, q_n, q_1, gamma_n, gamma_1)
        real(rk), intent(in) :: le
        integer, intent(in) :: n_gauss
        real(rk), intent(in) :: q_n(6), q_1(6), gamma_n(2, n_gauss)
        real(rk), intent(out) :: gamma_1(2, n_gauss)
        real(rk) :: xi(max_gauss_points), w(max_gauss_points), nn(2), q05(6), u(2), dr_s(2)
        real(rk) :: dq(6), lam(2, 2)
        integer :: g
        call gauss_rule(n_gauss, xi, w)
        q05 = 0.5_rk * (q_n + q_1)
        dq = q_1 - q_n
        u = (q05(4:5) - q05(1:2)) / le
        dr_s = (dq(4:5) - dq(1:2)) / le
        do g = 1, n_gauss
            nn = shape_values(xi(g))
            lam = rotation(nn(1) * q05(3) + nn(2) * q05(6))
            gamma_1(:, g) = gamma_n(:, g) + (nn(1) * dq(3) + nn(2) * dq(6)) &
                * matmul(transpose(lam), matmul(skew, u)) + matmul(transpose(lam), dr_s)
        end do
    end subroutine ph_emi_strains

    !> Kinematically compatible strains of nodal q at the Gauss points (methods §2.3 eqs. 5-6):
    !> gammas(1:2, g) = Lambda(phi_g)^T d_s r - e1, gammas(3, g) = kappa = d_s phi (constant).
    !> For cl-EM energies and the drift diagnostic of PH-EM (methods §4.5).
    pure subroutine compatible_strains(le, n_gauss, q, gammas)
        real(rk), intent(in) :: le
        integer, intent(in) :: n_gauss
        real(rk), intent(in) :: q(6)
        real(rk), intent(out) :: gammas(3, n_gauss)
        real(rk) :: xi(max_gauss_points), w(max_gauss_points), nn(2), r_s(2)
        integer :: g
        call gauss_rule(n_gauss, xi, w)
        r_s = (q(4:5) - q(1:2)) / le
        do g = 1, n_gauss
            nn = shape_values(xi(g))
            gammas(1:2, g) = matmul(transpose(rotation(nn(1) * q(3) + nn(2) * q(6))), r_s)
            gammas(1, g) = gammas(1, g) - 1.0_rk
            gammas(3, g) = (q(6) - q(3)) / le
        end do
    end subroutine compatible_strains

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
    pure function compatible_strain_energy(le, stiffness, n_gauss, q) result(energy)
        real(rk), intent(in) :: le, stiffness(3)
        integer, intent(in) :: n_gauss
        real(rk), intent(in) :: q(6)
        real(rk) :: energy
        real(rk) :: gammas(3, max_gauss_points), xi(max_gauss_points), w(max_gauss_points)
        integer :: g
        call gauss_rule(n_gauss, xi, w)
        call compatible_strains(le, n_gauss, q, gammas(:, 1:n_gauss))
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

    ! ---------------------------------------------------------------------------------------
    ! Private parts

    ! PH-EM nodal rows (methods §4.3): r = G2 N05 (x, y rows), -V N05 + G1 M05 (phi rows), and
    ! optionally k(6, 9) = dr/d(q_1, e_1) (assumed shape: a section of the 9 x 9 Jacobian).
    ! G1 = [-1, +1]^T (§3.2), so G1 M05 = (-M05, +M05).
    pure subroutine ph_em_forces(le, stiffness, n_gauss, q_n, q_1, e_n, e_1, r, k)
        real(rk), intent(in) :: le, stiffness(3)
        integer, intent(in) :: n_gauss
        real(rk), intent(in) :: q_n(6), q_1(6), e_n(3), e_1(3)
        real(rk), intent(out) :: r(6)
        real(rk), intent(out), optional :: k(:, :)
        real(rk) :: xi(max_gauss_points), w(max_gauss_points), nn(2), q05(6), u(2), n05(2)
        real(rk) :: m05, dn(2, 9)
        integer :: g
        call gauss_rule(n_gauss, xi, w)
        q05 = 0.5_rk * (q_n + q_1)
        u = (q05(4:5) - q05(1:2)) / le
        ! N05 = D_ts Gamma05, M05 = EI kappa05 (eqs. 56g-h; W quadratic)
        n05 = 0.5_rk * stiffness(1:2) * (e_n(1:2) + e_1(1:2))
        m05 = 0.5_rk * stiffness(3) * (e_n(3) + e_1(3))
        dn = 0.0_rk
        dn(1, 7) = 0.5_rk * stiffness(1)
        dn(2, 8) = 0.5_rk * stiffness(2)
        r = 0.0_rk
        r(3) = -m05
        r(6) = m05
        if (present(k)) then
            k = 0.0_rk
            k(3, 9) = -0.5_rk * stiffness(3)
            k(6, 9) = 0.5_rk * stiffness(3)
        end if
        do g = 1, n_gauss
            nn = shape_values(xi(g))
            ! Lambda_g at the interpolated midpoint angle, no trigonometric factors (§4.3).
            if (present(k)) then
                call gauss_point_force(le, w(g), nn, rotation(nn(1) * q05(3) + nn(2) * q05(6)), &
                    u, [1.0_rk, 1.0_rk], [0.0_rk, 0.0_rk], n05, r, dn, k)
            else
                call gauss_point_force(le, w(g), nn, rotation(nn(1) * q05(3) + nn(2) * q05(6)), &
                    u, [1.0_rk, 1.0_rk], [0.0_rk, 0.0_rk], n05, r)
            end if
        end do
    end subroutine ph_em_forces

    ! The PH-EM strain-row increments without the 1/h (methods §4.3, eq. 64 and eq. 63):
    !   inc(1:2) = G2e^T dr - Ve^T dphi
    !            = sum_g w_g le/2 [Lambda_g^T d_s dr + dphi_g Lambda_g^T S d_s r05]
    !   inc(3)   = G1e^T dphi = dphi_b - dphi_a,
    ! and optionally dinc(3, 6) = d inc / d q_1.
    pure subroutine ph_em_strain_increment(le, n_gauss, q_n, q_1, inc, dinc)
        real(rk), intent(in) :: le
        integer, intent(in) :: n_gauss
        real(rk), intent(in) :: q_n(6), q_1(6)
        real(rk), intent(out) :: inc(3)
        real(rk), intent(out), optional :: dinc(3, 6)
        real(rk) :: xi(max_gauss_points), w(max_gauss_points), nn(2), q05(6), dq(6), u(2)
        real(rk) :: dr_ba(2), lam_t(2, 2), dphi_g, su(2), b(2, 2), v(2)
        integer :: g
        call gauss_rule(n_gauss, xi, w)
        q05 = 0.5_rk * (q_n + q_1)
        dq = q_1 - q_n
        u = (q05(4:5) - q05(1:2)) / le
        dr_ba = dq(4:5) - dq(1:2)
        su = matmul(skew, u)
        inc = 0.0_rk
        inc(3) = dq(6) - dq(3)
        if (present(dinc)) then
            dinc = 0.0_rk
            dinc(3, 3) = -1.0_rk
            dinc(3, 6) = 1.0_rk
        end if
        do g = 1, n_gauss
            nn = shape_values(xi(g))
            lam_t = transpose(rotation(nn(1) * q05(3) + nn(2) * q05(6)))
            dphi_g = nn(1) * dq(3) + nn(2) * dq(6)
            ! (w_g le/2)(1/le) Lambda_g^T dr_ba + (w_g le/2) dphi_g Lambda_g^T S u
            inc(1:2) = inc(1:2) + 0.5_rk * w(g) * matmul(lam_t, dr_ba + le * dphi_g * su)
            if (.not. present(dinc)) cycle
            ! d/dr_1,b = w_g/2 Lambda_g^T (I + 1/2 dphi_g S)  (du/dr_1,b = I/(2 le)); r_1,a: minus
            b = 0.5_rk * w(g) * matmul(lam_t, identity2() + 0.5_rk * dphi_g * skew)
            dinc(1:2, 4:5) = dinc(1:2, 4:5) + b
            dinc(1:2, 1:2) = dinc(1:2, 1:2) - b
            ! d/dphi_1,J = w_g/2 N_J Lambda_g^T [1/2 S dr_ba + le S u - 1/2 le dphi_g u]
            ! (dLambda_g^T/dphi_1,J = 1/2 N_J Lambda_g^T S, d dphi_g/dphi_1,J = N_J, S S = -I)
            v = 0.5_rk * w(g) * matmul(lam_t, 0.5_rk * matmul(skew, dr_ba) + le * su &
                - 0.5_rk * le * dphi_g * u)
            dinc(1:2, 3) = dinc(1:2, 3) + nn(1) * v
            dinc(1:2, 6) = dinc(1:2, 6) + nn(2) * v
        end do
    end subroutine ph_em_strain_increment

    ! Nodal rows of the displacement-based schemes (methods §5.1 eq. 75 for cl-EM, §5.2 eq. 77
    ! for PH-EMi) and optionally k(6, 6) = dr/dq_1. Bending is G1 M05 with M05 = EI d_s phi05 in
    ! both. `stander_stein` selects cl-EM (endpoint-average strain, Z1, Z2); otherwise PH-EMi
    ! (history strain gamma_n, Z1 = Z2 = 1).
    pure subroutine displacement_forces(stander_stein, le, stiffness, n_gauss, q_n, q_1, &
            gamma_n, r, k)
        logical, intent(in) :: stander_stein
        real(rk), intent(in) :: le, stiffness(3)
        integer, intent(in) :: n_gauss
        real(rk), intent(in) :: q_n(6), q_1(6), gamma_n(:, :)
        real(rk), intent(out) :: r(6)
        real(rk), intent(out), optional :: k(6, 6)
        real(rk) :: xi(max_gauss_points), w(max_gauss_points), nn(2), q05(6), dq(6), u(2)
        real(rk) :: rs_1(2), rs_n(2), dr_s(2), lam05(2, 2), lam05_t(2, 2), lam1_t(2, 2)
        real(rk) :: gam(2), dgam(2, 6), b(2, 2), v(2), z(2), dz(2), dphi_g, phi1_g, phin_g
        real(rk) :: m05, ei2, half
        integer :: g
        call gauss_rule(n_gauss, xi, w)
        q05 = 0.5_rk * (q_n + q_1)
        dq = q_1 - q_n
        u = (q05(4:5) - q05(1:2)) / le
        rs_1 = (q_1(4:5) - q_1(1:2)) / le
        rs_n = (q_n(4:5) - q_n(1:2)) / le
        dr_s = rs_1 - rs_n
        ! G1 M05, M05 = EI kappa05 = EI d_s phi05 (eqs. 72-73, 78b), exact for any rule.
        m05 = stiffness(3) * (q05(6) - q05(3)) / le
        r = 0.0_rk
        r(3) = -m05
        r(6) = m05
        if (present(k)) then
            k = 0.0_rk
            ei2 = 0.5_rk * stiffness(3) / le
            k(3, 3) = ei2
            k(3, 6) = -ei2
            k(6, 3) = -ei2
            k(6, 6) = ei2
        end if
        do g = 1, n_gauss
            nn = shape_values(xi(g))
            phi1_g = nn(1) * q_1(3) + nn(2) * q_1(6)
            phin_g = nn(1) * q_n(3) + nn(2) * q_n(6)
            dphi_g = phi1_g - phin_g
            lam05 = rotation(0.5_rk * (phi1_g + phin_g))
            lam05_t = transpose(lam05)
            dgam = 0.0_rk
            if (stander_stein) then
                ! Gamma05 = 1/2 (Lambda_1^T d_s r_1 + Lambda_n^T d_s r_n) - e1 (eq. 72)
                lam1_t = transpose(rotation(phi1_g))
                gam = 0.5_rk * (matmul(lam1_t, rs_1) + matmul(transpose(rotation(phin_g)), rs_n))
                gam(1) = gam(1) - 1.0_rk
                ! Z1 = cos(dphi/2), Z2 = sin(dphi/2)/(dphi/2) (eq. 67), derivatives in dphi_g
                half = 0.5_rk * dphi_g
                call planar_sinc(half, z(2), dz(2))
                z(1) = cos(half)
                dz(1) = -0.5_rk * sin(half)
                dz(2) = 0.5_rk * dz(2)
                if (present(k)) then
                    ! dGamma05/dr_1,b = 1/(2 le) Lambda_1^T;
                    ! dGamma05/dphi_1,J = 1/2 N_J Lambda_1^T S d_s r_1
                    b = 0.5_rk / le * lam1_t
                    v = 0.5_rk * matmul(lam1_t, matmul(skew, rs_1))
                end if
            else
                ! Gamma05 = Gamma_n + 1/2 (dphi Lambda05^T S d_s r05 + Lambda05^T d_s dr) (eq. 78a)
                gam = gamma_n(:, g) + 0.5_rk * matmul(lam05_t, dphi_g * matmul(skew, u) + dr_s)
                z = 1.0_rk
                dz = 0.0_rk
                if (present(k)) then
                    ! dGamma05/dr_1,b = 1/(2 le) Lambda05^T (I + 1/2 dphi_g S);
                    ! dGamma05/dphi_1,J = 1/2 N_J Lambda05^T [S u - 1/2 dphi_g u + 1/2 S d_s dr]
                    b = 0.5_rk / le * matmul(lam05_t, identity2() + 0.5_rk * dphi_g * skew)
                    v = 0.5_rk * matmul(lam05_t, matmul(skew, u) - 0.5_rk * dphi_g * u &
                        + 0.5_rk * matmul(skew, dr_s))
                end if
            end if
            if (present(k)) then
                dgam(:, 4:5) = b
                dgam(:, 1:2) = -b
                dgam(:, 3) = nn(1) * v
                dgam(:, 6) = nn(2) * v
                ! N = D_ts Gamma05: dN = D_ts dGamma05
                dgam(1, :) = stiffness(1) * dgam(1, :)
                dgam(2, :) = stiffness(2) * dgam(2, :)
                call gauss_point_force(le, w(g), nn, lam05, u, z, dz, stiffness(1:2) * gam, r, &
                    dgam, k)
            else
                call gauss_point_force(le, w(g), nn, lam05, u, z, dz, stiffness(1:2) * gam, r)
            end if
        end do
    end subroutine displacement_forces

    ! Add the contribution of one Gauss point to the nodal rows (methods §4.3 "pointwise",
    ! §5.1 eq. 75):
    !   f = Z1 Lambda05 N,  t = Z2 (d_s r05)^T S Lambda05 N,
    !   r(x, y)_I += w le/2 d_sN_I f = -+ w/2 f,  r(phi)_I -= w le/2 N_I t,
    ! with Z1, Z2 functions of dphi_g (dz their derivatives in dphi_g; 0 and 1 outside cl-EM).
    ! With k (ncol <= 9 columns, the q_1 unknowns first): dn(2, ncol) = dN/d(unknowns); the explicit
    ! dependencies are dphi_g/dphi_1,J = N_J, dLambda05/dphi_1,J = 1/2 N_J S^T Lambda05 and
    ! d(d_s r05)/dr_1,b = -d(d_s r05)/dr_1,a = I/(2 le).
    pure subroutine gauss_point_force(le, w, nn, lam05, u, z, dz, n, r, dn, k)
        real(rk), intent(in) :: le, w, nn(2), lam05(2, 2), u(2), z(2), dz(2), n(2)
        real(rk), intent(inout) :: r(6)
        real(rk), intent(in), optional :: dn(:, :)
        real(rk), intent(inout), optional :: k(:, :)
        real(rk) :: g0(2), sg0(2), f(2), t, df(2, 9), dt(9), ut(2), e(2)
        integer :: j, a, ncol
        g0 = matmul(lam05, n)
        sg0 = matmul(skew, g0)
        f = z(1) * g0
        t = z(2) * dot_product(u, sg0)
        r(1:2) = r(1:2) - 0.5_rk * w * f
        r(4:5) = r(4:5) + 0.5_rk * w * f
        r(3) = r(3) - 0.5_rk * w * le * nn(1) * t
        r(6) = r(6) - 0.5_rk * w * le * nn(2) * t
        if (.not. present(k)) return
        ! Through N: df = Z1 Lambda05 dN, dt = Z2 (Lambda05^T S^T u) . dN
        ncol = size(k, 2)
        ut = matmul(transpose(lam05), matmul(transpose(skew), u))
        do j = 1, ncol
            df(:, j) = z(1) * matmul(lam05, dn(:, j))
            dt(j) = z(2) * dot_product(ut, dn(:, j))
        end do
        ! Through d_s r05 in t
        dt(1:2) = dt(1:2) - 0.5_rk / le * z(2) * sg0
        dt(4:5) = dt(4:5) + 0.5_rk / le * z(2) * sg0
        ! Through dphi_g (Z1, Z2) and phi05_g (Lambda05); S S^T = I
        e = dz(1) * g0 + 0.5_rk * z(1) * matmul(transpose(skew), g0)
        do a = 1, 2
            j = 3 * a
            df(:, j) = df(:, j) + nn(a) * e
            dt(j) = dt(j) + nn(a) * (dz(2) * dot_product(u, sg0) &
                + 0.5_rk * z(2) * dot_product(u, g0))
        end do
        do j = 1, 2
            k(j, :) = k(j, :) - 0.5_rk * w * df(j, 1:ncol)
            k(3 + j, :) = k(3 + j, :) + 0.5_rk * w * df(j, 1:ncol)
        end do
        k(3, :) = k(3, :) - 0.5_rk * w * le * nn(1) * dt(1:ncol)
        k(6, :) = k(6, :) - 0.5_rk * w * le * nn(2) * dt(1:ncol)
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

    ! Linear shape functions (N_a, N_b) at xi (methods §3.1 eqs. 87-89).
    pure function shape_values(xi) result(nn)
        real(rk), intent(in) :: xi
        real(rk) :: nn(2)
        nn = [0.5_rk * (1.0_rk - xi), 0.5_rk * (1.0_rk + xi)]
    end function shape_values

    ! Lambda(phi) of methods §2.2 eq. (3).
    pure function rotation(phi) result(lam)
        real(rk), intent(in) :: phi
        real(rk) :: lam(2, 2)
        real(rk) :: c, s
        c = cos(phi)
        s = sin(phi)
        lam = reshape([c, s, -s, c], [2, 2])
    end function rotation

    pure function identity2() result(eye)
        real(rk) :: eye(2, 2)
        eye = reshape([1.0_rk, 0.0_rk, 0.0_rk, 1.0_rk], [2, 2])
    end function identity2

    !> s = sin(x)/x (1 at x = 0) and ds = ds/dx, the Z2 factor of cl-EM at x = dphi/2 (methods
    !> §5.1 eq. 67); Taylor series (to x^10 and x^9, truncation below 1e-19) for |x| < 0.1, so
    !> that Z2 and its derivative are smooth and accurate to round-off through dphi = 0.
    pure subroutine planar_sinc(x, s, ds)
        real(rk), intent(in) :: x
        real(rk), intent(out) :: s, ds
        real(rk) :: x2
        if (abs(x) < sinc_series_limit) then
            x2 = x * x
            s = 1.0_rk - x2 / 6.0_rk * (1.0_rk - x2 / 20.0_rk * (1.0_rk - x2 / 42.0_rk &
                * (1.0_rk - x2 / 72.0_rk * (1.0_rk - x2 / 110.0_rk))))
            ds = -x / 3.0_rk * (1.0_rk - x2 / 10.0_rk * (1.0_rk - x2 / 28.0_rk &
                * (1.0_rk - x2 / 54.0_rk * (1.0_rk - x2 / 88.0_rk))))
        else
            s = sin(x) / x
            ds = (cos(x) - s) / x
        end if
    end subroutine planar_sinc

end module rs_ph_planar_element
