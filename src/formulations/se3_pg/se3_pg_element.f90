!> Element and node kernels of the objective, locking-free SE(3) Petrov-Galerkin rod of seed 002
!> (methods/se3_petrov_galerkin.md §5-§6): element strains, internal forces and their analytic
!> tangent, the constant mass matrix, gyroscopic forces, the kinematic map q_dot = B u and the
!> configuration-dependent nodal loads. Pure procedures on plain arrays: no PETSc, no MPI, no
!> allocation (DESIGN.md §2, STYLE.md item 4).
!>
!> Conventions (fixed; the se3_pg formulation relies on them; docs/theory/lie_groups.md):
!> - Element unknowns q(12) = (r_a, psi_a, r_b, psi_b): inertial node positions and total
!>   rotation vectors, A_i = exp_so3(psi_i) maps K to I components, e_x^K along the rod
!>   (methods §2, §5.1). Node poses H_i = (A_i, r_i) (eq. (34)).
!> - Element twist theta = Log_SE3(H_a^{-1} H_b) = (v, omega), translation first (eq. (36)),
!>   principal branch: the relative rotation |omega| must stay below pi (§5.2).
!> - l = Delta_xi J is the element's reference length (constant per element, §5.3). Strains are
!>   constant: eps = (K gamma, K kappa) = theta / l (eq. (38)).
!> - stiffness(6) = (k_e, k_s, k_s', k_t, k_b, k_b'), eps_ref(6) = (gamma0, kappa0):
!>   n = diag(stiffness(1:3)) (gamma - gamma0), m = diag(stiffness(4:6)) (kappa - kappa0)
!>   (eq. (12)); a straight stress-free reference has eps_ref = (1, 0, 0, 0, 0, 0).
!> - Virtual displacements ("delta s") per node are (I delta r_i, K_i delta phi_i) with
!>   K_i delta phi_i = T(psi_i) delta psi_i (§5.4); velocities u_i = (I v_i, K_i omega_i). Force
!>   vectors are in delta-s space; Jacobians are with respect to q (or u), 12 x 12, not
!>   symmetric (§6.4).
!> - g = -f_e^int of eq. (42): equilibrium reads g = f_ext, the equation of motion
!>   M u_dot + f^gyr + g = f_ext (§6.3, §7.1).
!> - Element integrals use the 2-point Gauss-Legendre rule on the element (§6.1 item 6). They
!>   are written in the local coordinate t = (xi - xi^e)/Delta_xi in [0, 1], d xi = Delta_xi dt,
!>   N_0 = 1 - t, N_1 = t, N_{i,xi} = -+1/Delta_xi. Then Delta_xi and J only enter through l:
!>   N_{i,xi} d xi = -+dt, and N_i (gamma_bar x n) d xi = N_i (Delta_xi J gamma x n) dt
!>   = N_i (theta_v x n) dt (gamma_bar = J gamma, kappa_bar = J kappa, eq. (8)).
!>
!> The Petrov-Galerkin virtual work is not the variation of the discrete strain energy l W:
!> g . delta s equals d(l W) to first order only when the relative rotation of the element
!> vanishes; otherwise they differ by O(|omega|^2) relative (T^T(omega) against T^{-1}(omega)
!> in the position rows and 1 + hat(omega)/2 against T^{-1}(omega) in the rotation rows). This
!> is what makes the tangent non-symmetric; tests/unit/formulations/test_se3_pg_element.F90
!> measures the defect and its second order in the element length.
module rs_se3_pg_element
    use rs_core_kinds, only: rk
    use rs_math_so3, only: hat, exp_so3, tangent_so3, tangent_inverse_so3, &
        tangent_inverse_so3_derivative
    use rs_math_se3, only: log_se3, pose_relative, tangent_inverse_se3
    implicit none
    private

    public :: se3_strains, se3_internal_force, se3_internal_tangent, se3_internal_force_tangent
    public :: se3_strain_energy, se3_element_mass, se3_gyroscopic, se3_mass_solve
    public :: se3_kinematics, tinv_times_derivative, follower_force, dead_moment
    public :: se3_element_twist, se3_twist_tangent, se3_viscous_internal_force

    !> Points (on [0, 1]) and weight of the 2-point Gauss-Legendre rule of every element
    !> integral (methods §6.1 item 6).
    real(rk), parameter, public :: se3_gauss_points(2) = &
        [0.5_rk - 0.5_rk / sqrt(3.0_rk), 0.5_rk + 0.5_rk / sqrt(3.0_rk)]
    real(rk), parameter, public :: se3_gauss_weight = 0.5_rk
    real(rk), parameter :: no_stress(6) = 0.0_rk

contains

    !> Element twist theta = Log_SE3(H_a^{-1} H_b) (methods eq. (36)) and the nodal rotation
    !> matrices A_a, A_b of the element unknowns q.
    pure subroutine se3_element_twist(q, theta, a_a, a_b)
        real(rk), intent(in) :: q(12)
        real(rk), intent(out) :: theta(6), a_a(3, 3), a_b(3, 3)
        real(rk) :: a_rel(3, 3), r_rel(3)
        a_a = exp_so3(q(4:6))
        a_b = exp_so3(q(10:12))
        call pose_relative(a_a, q(1:3), a_b, q(7:9), a_rel, r_rel)
        theta = log_se3(a_rel, r_rel)
    end subroutine se3_element_twist

    !> Constant element strains eps = (K gamma, K kappa) = theta / l (methods eq. (38)).
    pure subroutine se3_strains(l, q, eps)
        real(rk), intent(in) :: l, q(12)
        real(rk), intent(out) :: eps(6)
        real(rk) :: theta(6), a_a(3, 3), a_b(3, 3)
        call se3_element_twist(q, theta, a_a, a_b)
        eps = theta / l
    end subroutine se3_strains

    !> Strain energy of the element, l W with the quadratic W of methods eq. (12).
    pure function se3_strain_energy(l, stiffness, eps_ref, q) result(energy)
        real(rk), intent(in) :: l, stiffness(6), eps_ref(6), q(12)
        real(rk) :: energy
        real(rk) :: eps(6)
        call se3_strains(l, q, eps)
        energy = 0.5_rk * l * sum(stiffness * (eps - eps_ref)**2)
    end function se3_strain_energy

    !> Internal force g(12) = -f_e^int of methods eq. (42), in delta-s space. Per node i:
    !>   position rows  int N_{i,xi} A(xi) n d xi = -+ sum_g w_g A(t_g) n,
    !>   rotation rows  int [N_{i,xi} m - N_i (gamma_bar x n + kappa_bar x m)] d xi
    !>                  = -+ m - (theta_v x n + theta_w x m)/2,
    !> with A(t) = A_a Exp_SO3(t theta_w) (§6.1 item 4); the rotation rows are integrated exactly
    !> by the 2-point rule, so their closed form is used.
    pure subroutine se3_internal_force(l, stiffness, eps_ref, q, g)
        real(rk), intent(in) :: l, stiffness(6), eps_ref(6), q(12)
        real(rk), intent(out) :: g(12)
        real(rk) :: k(12, 12)
        call internal_force_tangent(.false., l, stiffness, eps_ref, no_stress, q, g, k)
    end subroutine se3_internal_force

    !> Analytic tangent k(12, 12) = d g / d q of `se3_internal_force` (methods §6.4 with the
    !> product rule of §13 item 4), not symmetric.
    pure subroutine se3_internal_tangent(l, stiffness, eps_ref, q, k)
        real(rk), intent(in) :: l, stiffness(6), eps_ref(6), q(12)
        real(rk), intent(out) :: k(12, 12)
        real(rk) :: g(12)
        call internal_force_tangent(.true., l, stiffness, eps_ref, no_stress, q, g, k)
    end subroutine se3_internal_tangent

    !> `se3_internal_force` and `se3_internal_tangent` in one evaluation (one Log, two Exp).
    pure subroutine se3_internal_force_tangent(l, stiffness, eps_ref, q, g, k)
        real(rk), intent(in) :: l, stiffness(6), eps_ref(6), q(12)
        real(rk), intent(out) :: g(12), k(12, 12)
        call internal_force_tangent(.true., l, stiffness, eps_ref, no_stress, q, g, k)
    end subroutine se3_internal_force_tangent

    !> The internal force with a viscous stress sigma_v = (n_v, m_v) (K components, the order of
    !> eps) added to the elastic one, the Kelvin-Voigt stress of docs/theory/se3_pg.md "Damping":
    !> g of `se3_internal_force` with n + n_v and m + m_v in methods eq. (42). With `k`: d g / d q
    !> at fixed sigma_v (the tangent of `se3_internal_tangent` with the total stress in its
    !> geometric terms); with `b_t`: d g / d sigma_v (12 x 6), the Petrov-Galerkin operator that
    !> carries a stress to the virtual-displacement rows: -+ sum_g w_g A(t_g) on n in the
    !> position rows, -hat(theta_v) / 2 on n and -+1 - hat(theta_w) / 2 on m in the rotation
    !> rows.
    pure subroutine se3_viscous_internal_force(l, stiffness, eps_ref, sigma_v, q, g, k, b_t)
        real(rk), intent(in) :: l, stiffness(6), eps_ref(6), sigma_v(6), q(12)
        real(rk), intent(out) :: g(12)
        real(rk), intent(out), optional :: k(12, 12), b_t(12, 6)
        real(rk) :: k_local(12, 12), b_local(12, 6)
        call internal_force_tangent(present(k), l, stiffness, eps_ref, sigma_v, q, g, k_local, &
            present(b_t), b_local)
        if (present(k)) k = k_local
        if (present(b_t)) b_t = b_local
    end subroutine se3_viscous_internal_force

    !> The element twist theta = Log_SE3(H_a^{-1} H_b) and its derivative d theta / d q (6 x 12)
    !> (the linearization of `internal_force_tangent`): d theta = -T_SE3^{-1}(-theta) d eta_a +
    !> T_SE3^{-1}(theta) d eta_b with the body variations d eta_i = (A_i^T dr_i, T(psi_i) dpsi_i).
    !> d theta / l applied to a velocity (v_i, psi'_i) is the rate of the objective strains
    !> (methods eq. (38)); it vanishes on every rigid velocity field.
    pure subroutine se3_twist_tangent(q, theta, dtheta)
        real(rk), intent(in) :: q(12)
        real(rk), intent(out) :: theta(6), dtheta(6, 12)
        real(rk) :: a_a(3, 3), a_b(3, 3)
        call se3_element_twist(q, theta, a_a, a_b)
        call twist_derivative(q, theta, a_a, a_b, dtheta)
    end subroutine se3_twist_tangent

    pure subroutine twist_derivative(q, theta, a_a, a_b, dtheta)
        real(rk), intent(in) :: q(12), theta(6), a_a(3, 3), a_b(3, 3)
        real(rk), intent(out) :: dtheta(6, 12)
        real(rk) :: tinv_a(6, 6), tinv_b(6, 6)
        tinv_a = tangent_inverse_se3(-theta)
        tinv_b = tangent_inverse_se3(theta)
        dtheta(:, 1:3) = -matmul(tinv_a(:, 1:3), transpose(a_a))
        dtheta(:, 4:6) = -matmul(tinv_a(:, 4:6), tangent_so3(q(4:6)))
        dtheta(:, 7:9) = matmul(tinv_b(:, 1:3), transpose(a_b))
        dtheta(:, 10:12) = matmul(tinv_b(:, 4:6), tangent_so3(q(10:12)))
    end subroutine twist_derivative

    ! Internal force and, when want_tangent, its derivative with respect to q.
    !
    ! Linearization: with the body variations d eta_i = (A_i^T dr_i, T(psi_i) dpsi_i) the
    ! relative pose becomes H_rel Exp(h), h = -Ad(H_rel^{-1}) d eta_a + d eta_b, and since
    ! Exp(theta)^{-1} dExp(theta) = T_SE3(theta) dtheta (material tangent), dtheta =
    ! T_SE3^{-1}(theta) h. With Ad(H_rel^{-1}) = exp(-ad_theta) and T_SE3(-theta) =
    ! exp(ad_theta) T_SE3(theta) this is
    !     dtheta = -T_SE3^{-1}(-theta) d eta_a + T_SE3^{-1}(theta) d eta_b,
    ! which replaces the matrix derivative of Log of App. C (§4.4) and needs no Ad. At a Gauss
    ! point, A(t) = A_a E with E = Exp_SO3(t theta_w), A_a^T dA_a = hat(T_a dpsi_a) and
    ! E^T dE = hat(t T(t theta_w) dtheta_w) give
    !     d(A(t) n) = A(t) [dn - hat(n) (E^T T_a dpsi_a + t T(t theta_w) dtheta_w)].
    ! The stress is the elastic one plus sigma_extra (held fixed in k); with want_stress_map,
    ! b_t = d g / d sigma_extra (se3_viscous_internal_force).
    pure subroutine internal_force_tangent(want_tangent, l, stiffness, eps_ref, sigma_extra, q, &
            g, k, want_stress_map, b_t)
        logical, intent(in) :: want_tangent
        real(rk), intent(in) :: l, stiffness(6), eps_ref(6), sigma_extra(6), q(12)
        real(rk), intent(out) :: g(12), k(12, 12)
        logical, intent(in), optional :: want_stress_map
        real(rk), intent(out), optional :: b_t(12, 6)
        real(rk) :: theta(6), a_a(3, 3), a_b(3, 3), n(3), m(3), couple(3), an(3)
        real(rk) :: e(3, 3, 2), a_t(3, 3, 2), t_a(3, 3)
        real(rk) :: dtheta(6, 12), dsigma(6, 12), dv(3, 12), dw(3, 12), dn(3, 12), dm(3, 12)
        real(rk) :: rot(3, 12), dan(3, 12), dcouple(3, 12), n_hat(3, 3), t_t(3, 3)
        integer :: ig, j
        call se3_element_twist(q, theta, a_a, a_b)
        n = stiffness(1:3) * (theta(1:3) / l - eps_ref(1:3)) + sigma_extra(1:3)
        m = stiffness(4:6) * (theta(4:6) / l - eps_ref(4:6)) + sigma_extra(4:6)
        an = 0.0_rk
        do ig = 1, 2
            e(:, :, ig) = exp_so3(se3_gauss_points(ig) * theta(4:6))
            a_t(:, :, ig) = matmul(a_a, e(:, :, ig))
            an = an + se3_gauss_weight * matmul(a_t(:, :, ig), n)
        end do
        couple = 0.5_rk * (cross(theta(1:3), n) + cross(theta(4:6), m))
        g(1:3) = -an
        g(4:6) = -m - couple
        g(7:9) = an
        g(10:12) = m - couple
        if (present(want_stress_map)) then
            if (want_stress_map) call stress_map(theta, a_t, b_t)
        end if
        if (.not. want_tangent) then
            k = 0.0_rk
            return
        end if

        t_a = tangent_so3(q(4:6))
        call twist_derivative(q, theta, a_a, a_b, dtheta)
        do j = 1, 12
            dsigma(:, j) = (stiffness / l) * dtheta(:, j)
        end do
        dv = dtheta(1:3, :)
        dw = dtheta(4:6, :)
        dn = dsigma(1:3, :)
        dm = dsigma(4:6, :)

        n_hat = hat(n)
        dan = 0.0_rk
        do ig = 1, 2
            t_t = tangent_so3(se3_gauss_points(ig) * theta(4:6))
            rot = se3_gauss_points(ig) * matmul(t_t, dw)
            rot(:, 4:6) = rot(:, 4:6) + matmul(transpose(e(:, :, ig)), t_a)
            dan = dan + se3_gauss_weight * matmul(a_t(:, :, ig), dn - matmul(n_hat, rot))
        end do
        ! d(a x b) = -hat(b) da + hat(a) db
        dcouple = 0.5_rk * (-matmul(n_hat, dv) + matmul(hat(theta(1:3)), dn) &
            - matmul(hat(m), dw) + matmul(hat(theta(4:6)), dm))
        k(1:3, :) = -dan
        k(4:6, :) = -dm - dcouple
        k(7:9, :) = dan
        k(10:12, :) = dm - dcouple
    end subroutine internal_force_tangent

    ! b_t = d g / d sigma (12 x 6) of `internal_force_tangent` at the element twist theta, with
    ! the Gauss points' rotations a_t: -+ sum_g w_g A(t_g) on n in the position rows,
    ! -hat(theta_v) / 2 on n and -+1 - hat(theta_w) / 2 on m in the rotation rows.
    pure subroutine stress_map(theta, a_t, b_t)
        real(rk), intent(in) :: theta(6), a_t(3, 3, 2)
        real(rk), intent(out) :: b_t(12, 6)
        integer :: j
        b_t = 0.0_rk
        b_t(7:9, 1:3) = se3_gauss_weight * (a_t(:, :, 1) + a_t(:, :, 2))
        b_t(1:3, 1:3) = -b_t(7:9, 1:3)
        b_t(4:6, 1:3) = -0.5_rk * hat(theta(1:3))
        b_t(10:12, 1:3) = b_t(4:6, 1:3)
        b_t(4:6, 4:6) = -0.5_rk * hat(theta(4:6))
        b_t(10:12, 4:6) = b_t(4:6, 4:6)
        do j = 1, 3
            b_t(3 + j, 3 + j) = b_t(3 + j, 3 + j) - 1.0_rk
            b_t(9 + j, 3 + j) = b_t(9 + j, 3 + j) + 1.0_rk
        end do
    end subroutine stress_map

    !> Consistent constant mass matrix m(12, 12) in u space of a centroidal section
    !> (S_rho0 = 0, methods §6.3): l [[1/3, 1/6], [1/6, 1/3]] (x) blockdiag(rho_a 1_3,
    !> diag(inertia)), inertia = diagonal of K I_rho0. Exact for the 2-point rule.
    pure subroutine se3_element_mass(l, rho_a, inertia, m)
        real(rk), intent(in) :: l, rho_a, inertia(3)
        real(rk), intent(out) :: m(12, 12)
        real(rk) :: node(6)
        integer :: i
        node = [rho_a, rho_a, rho_a, inertia]
        m = 0.0_rk
        do i = 1, 6
            m(i, i) = l * node(i) / 3.0_rk
            m(i + 6, i + 6) = m(i, i)
            m(i, i + 6) = l * node(i) / 6.0_rk
            m(i + 6, i) = m(i, i + 6)
        end do
    end subroutine se3_element_mass

    !> Accelerations a(6, nodes) with M a = rows on the free coordinates (free(i, k)) and a = 0
    !> on the others, M the assembled consistent mass matrix of `se3_element_mass` on elements
    !> of lengths l(:) (nodes = size(l) + 1) with masses rho_a(e), inertia(:, e). M is (1D
    !> consistent mass) x blockdiag(rho_a 1_3, diag(inertia)) per element, so each of the six
    !> coordinates is its own tridiagonal system over the nodes, with diagonal sum of
    !> m_e l_e / 3 and neighbours m_e l_e / 6 (m_e the coordinate's mass of element e):
    !> the Thomas algorithm solves it without pivoting, as it is diagonally dominant; a held
    !> coordinate splits the chain (its row becomes a = 0). For the initial history of
    !> generalized-alpha (rs_se3_pg initial_rates).
    pure subroutine se3_mass_solve(l, rho_a, inertia, free, rows, a)
        real(rk), intent(in) :: l(:), rho_a(:), inertia(:, :)
        logical, intent(in) :: free(:, :)
        real(rk), intent(in) :: rows(:, :)
        real(rk), intent(out) :: a(:, :)
        ! Element masses m_e l_e padded with zero beyond both ends: node k touches
        ! lengths(k - 1, k).
        real(rk) :: lengths(0:size(l) + 1), diagonal(size(l) + 1), coupling(size(l))
        real(rk) :: node(6, size(l)), rhs(size(l) + 1), factor
        integer :: i, k, n
        n = size(l) + 1
        do k = 1, n - 1
            node(:, k) = [rho_a(k), rho_a(k), rho_a(k), inertia(:, k)]
        end do
        do i = 1, 6
            lengths = 0.0_rk
            lengths(1:n - 1) = node(i, :) * l
            ! Row k: diagonal(k) a_k + coupling(k - 1) a_{k-1} + coupling(k) a_{k+1} = rhs(k).
            do k = 1, n
                diagonal(k) = merge((lengths(k - 1) + lengths(k)) / 3.0_rk, 1.0_rk, free(i, k))
                rhs(k) = merge(rows(i, k), 0.0_rk, free(i, k))
            end do
            do k = 1, n - 1
                coupling(k) = merge(lengths(k) / 6.0_rk, 0.0_rk, free(i, k) .and. free(i, k + 1))
            end do
            do k = 2, n
                factor = coupling(k - 1) / diagonal(k - 1)
                diagonal(k) = diagonal(k) - factor * coupling(k - 1)
                rhs(k) = rhs(k) - factor * rhs(k - 1)
            end do
            a(i, n) = rhs(n) / diagonal(n)
            do k = n - 1, 1, -1
                a(i, k) = (rhs(k) - coupling(k) * a(i, k + 1)) / diagonal(k)
            end do
        end do
    end subroutine se3_mass_solve

    !> Gyroscopic force g(12) = f_e^gyr of methods §6.3 for a centroidal section, in delta-s
    !> space: rotation rows of node i l sum_g w_g N_i(t_g) omega x (K I_rho0 omega) with
    !> omega(t) = N_0 omega_a + N_1 omega_b (eq. (41)); zero position rows. k(12, 12) = dg/du.
    !> u(12) = (v_a, omega_a, v_b, omega_b); inertia = diagonal of K I_rho0. The 2-point rule
    !> integrates the cubic integrand exactly.
    pure subroutine se3_gyroscopic(l, inertia, u, g, k)
        real(rk), intent(in) :: l, inertia(3), u(12)
        real(rk), intent(out) :: g(12), k(12, 12)
        real(rk) :: shape(2), w(3), iw(3), f(3), df(3, 3), c
        integer :: ig, i, j, j1, j2
        g = 0.0_rk
        k = 0.0_rk
        do ig = 1, 2
            shape = [1.0_rk - se3_gauss_points(ig), se3_gauss_points(ig)]
            w = shape(1) * u(4:6) + shape(2) * u(10:12)
            iw = inertia * w
            f = cross(w, iw)
            ! d(w x I w)/dw = hat(w) I - hat(I w)
            df = matmul(hat(w), diagonal(inertia)) - hat(iw)
            c = l * se3_gauss_weight
            do i = 1, 2
                j1 = 6 * i - 2
                g(j1:j1 + 2) = g(j1:j1 + 2) + c * shape(i) * f
                do j = 1, 2
                    j2 = 6 * j - 2
                    k(j1:j1 + 2, j2:j2 + 2) = k(j1:j1 + 2, j2:j2 + 2) &
                        + c * shape(i) * shape(j) * df
                end do
            end do
        end do
    end subroutine se3_gyroscopic

    !> Rotation block b(3, 3) = T^{-1}(psi) of the kinematic map q_dot = B(q) u (methods eq.
    !> (39)): psi_dot = T^{-1}(psi) K omega; the position block is the identity. Singular at
    !> |psi| = 2 pi k, k >= 1 (§5.5).
    pure subroutine se3_kinematics(psi, b)
        real(rk), intent(in) :: psi(3)
        real(rk), intent(out) :: b(3, 3)
        b = tangent_inverse_so3(psi)
    end subroutine se3_kinematics

    !> d(i, k) = d (T^{-1}(psi) w)_i / d psi_k (corrected methods eq. (98), §13 item 2), the
    !> derivative of the kinematic map at fixed velocity w.
    pure subroutine tinv_times_derivative(psi, w, d)
        real(rk), intent(in) :: psi(3), w(3)
        real(rk), intent(out) :: d(3, 3)
        real(rk) :: d3(3, 3, 3)
        integer :: k
        d3 = tangent_inverse_so3_derivative(psi)
        do k = 1, 3
            d(:, k) = matmul(d3(:, :, k), w)
        end do
    end subroutine tinv_times_derivative

    !> Follower force at a node with rotation vector psi: f(3) = A(psi) b_k in the position rows
    !> (b_k in K components, methods §3.4), and k(3, 3) = df/dpsi = -A hat(b_k) T(psi).
    pure subroutine follower_force(psi, b_k, f, k)
        real(rk), intent(in) :: psi(3), b_k(3)
        real(rk), intent(out) :: f(3), k(3, 3)
        real(rk) :: a(3, 3)
        a = exp_so3(psi)
        f = matmul(a, b_k)
        k = -matmul(a, matmul(hat(b_k), tangent_so3(psi)))
    end subroutine follower_force

    !> Dead moment c_i (I components) at a node with rotation vector psi: f(3) = A(psi)^T c_i in
    !> the rotation rows (methods §3.4, §6.2), and k(3, 3) = df/dpsi = hat(A^T c_i) T(psi).
    pure subroutine dead_moment(psi, c_i, f, k)
        real(rk), intent(in) :: psi(3), c_i(3)
        real(rk), intent(out) :: f(3), k(3, 3)
        real(rk) :: a(3, 3)
        a = exp_so3(psi)
        f = matmul(c_i, a)
        k = matmul(hat(f), tangent_so3(psi))
    end subroutine dead_moment

    pure function cross(a, b) result(c)
        real(rk), intent(in) :: a(3), b(3)
        real(rk) :: c(3)
        c = [a(2) * b(3) - a(3) * b(2), a(3) * b(1) - a(1) * b(3), a(1) * b(2) - a(2) * b(1)]
    end function cross

    pure function diagonal(d) result(m)
        real(rk), intent(in) :: d(3)
        real(rk) :: m(3, 3)
        m = 0.0_rk
        m(1, 1) = d(1)
        m(2, 2) = d(2)
        m(3, 3) = d(3)
    end function diagonal

end module rs_se3_pg_element
