!> Penalty potential of rod-rod contact and its energy-consistent midpoint force (issue 10,
!> DESIGN.md §5 "Contact that keeps energy"). Pure kernels on plain arrays: no PETSc, no MPI, no
!> allocation (DESIGN.md §2, STYLE.md item 4).
!>
!> The potential. Two points a and b on two centrelines (quadrature points of nearby elements)
!> at squared distance d2 = |x_a - x_b|^2 carry the energy psi(d2), a polynomial in d2 (no
!> square root, smooth in the positions also at d2 = 0):
!>
!>     psi(d2) = k / (3 r_c^4) (r_c^2 - d2)^3    for d2 < r_c^2,    psi(d2) = 0 otherwise,
!>
!> with r_c = radius_a + radius_b + margin the contact distance and k the stiffness. Summed over
!> pairs of quadrature points with weights w_a w_b (lengths), psi approximates a double line
!> integral (rs_contact_element), so psi is an energy per length squared (J/m^2 = N/m) and k,
!> psi divided by a length squared, has units N/m^3. psi, psi' and psi'' vanish at d2 = r_c^2,
!> so psi is C2 (psi''' jumps).
!> Write s = r_c^2 - d2 (> 0 in the support) and c = k / (3 r_c^4): psi = c s^3,
!> psi' = -3 c s^2, psi'' = 6 c s (derivatives with respect to d2).
!>
!> Normal force. The pair pushes a and b apart with |F| = -2 psi'(d2) d, d = sqrt(d2), a force
!> per length squared (N/m^2; times w_a w_b it is the force between the two points); at the
!> penetration delta = r_c - d, exactly
!>
!>     |F|(delta) = 8 k delta^2 / r_c (1 - delta / r_c) (1 - delta / (2 r_c))^2,
!>
!> so |F| ~ 8 k delta^2 / r_c for delta << r_c. |F| peaks at d = r_c / sqrt(5) (delta =
!> 0.553 r_c) and falls to 0 at d = 0. Rods touch along lines, not at points: for choosing k use
!> the line-contact law of rs_contact_element (force per length ~ 12.07 k delta^(5/2) / sqrt(r_c),
!> contact_line_force, contact_line_penetration), and keep the working penetration well below
!> its peak (DESIGN.md §5: penetration is reported).
!>
!> The midpoint step (methods/ph_director_3d.md §5.1, §5.3 item 1). The unknowns are the
!> positions at t_{n+1} (suffix `_1`; t_n is suffix `_n`). With r = x_a - x_b and
!> r_mid = (r_n + r_1) / 2, d2 is quadratic, so d2_1 - d2_n = 2 r_mid . (r_1 - r_n) exactly.
!> The force uses the discrete gradient psi_bar = [psi(d2_1) - psi(d2_n)] / (d2_1 - d2_n):
!>
!>     f_a = 2 psi_bar r_mid,    f_b = -f_a,
!>
!> hence f_a . (x_a,1 - x_a,n) + f_b . (x_b,1 - x_b,n) = psi(d2_1) - psi(d2_n) for any step
!> (energy), f_a + f_b = 0 (linear momentum) and r_mid x f_a = 0 (a central force at the
!> midpoint: angular momentum), as DESIGN.md §5 requires.
!>
!> Sign convention: f_a and f_b are gradients of the contact energy (the discrete gradient with
!> respect to x_a and x_b), i.e. the terms that enter the momentum residual as the internal
!> forces do (methods §5.6, R_M); the physical force on point a is -f_a, which points away from
!> b because psi_bar <= 0. The caller multiplies by h and by quadrature weights where it uses them.
!>
!> Evaluating psi_bar without cancellation. On the support psi is the cubic c s^3, so its divided
!> difference is the polynomial -c (s_n^2 + s_n s_1 + s_1^2) = psi'(d2_mid) + psi''' (d2_1 -
!> d2_n)^2 / 24: the Taylor expansion about the midpoint terminates. It is used whenever both
!> points lie in the support, for every step size down to d2_1 = d2_n (where it equals psi'),
!> so no step-size threshold and no fallback branch are needed; it has no cancellation (all terms
!> have the sign of psi'). When exactly one point lies in the support, the quotient
!> -c s_in^3 / (s_in - s_out) is used: its denominator s_in + |s_out| is at least s_in > 0,
!> again without cancellation. Outside (both s <= 0) psi_bar = 0. psi_bar is symmetric, and
!> where one argument crosses r_c^2 while the other is inside, the pieces join with continuous
!> values, first and second derivatives. (A non-polynomial psi would need a Taylor switch at
!> small |d2_1 - d2_n|; this choice avoids it.)
!>
!> Pairs. Outside the support at both t_n and t_{n+1} a pair contributes nothing; a pair with one
!> end in the support does (the broad phase must see pairs at both times: a step is redone if a
!> new pair enters, DESIGN.md §5).
!>
!> The barrier (issue 24 item 1: no tunnelling, ever). psi is bounded (psi(0) = k r_c^2 / 3): a
!> point pair with more kinetic energy than that passes through, as a rope thrown at another at
!> 12 m/s did. With a `wall` d_w (contact_params_init; the contact coupling sets it above the
!> spacing of the contact points, so that two centrelines cannot cross without some point pair
!> coming closer than d_w) a barrier term joins psi below the barrier distance d_b = r_c / 2:
!>
!>     psi_B(d2) = kappa s^3 / u,    s = d_b^2 - d2 > 0,    u = d2 - d_w^2 > 0,
!>
!> (0 for s <= 0), kappa = c r_c^2. It is C2 at d_b (psi_B, psi_B', psi_B'' vanish there) and
!> infinite at the wall, so a state of finite energy keeps every point pair outside d_w; the
!> coupling's swept test (contact_element_swept_clear) rejects steps whose straight path takes
!> a pair inside it, so no step jumps the barrier. Below penetrations of half the contact
!> distance nothing changes (psi_B = 0 exactly: every scene that stays there runs bitwise as
!> without it). The barrier enters the step as psi does, through the divided difference in the
!> squared distance, a quadratic of the positions (the discrete gradient of methods/
!> ph_director_3d.md §5.3 item 1, exact for any step). With U = d_b^2 - d_w^2 (u = U - s) the
!> divided difference of psi_B in d2 is, both points in its support,
!>
!>     psi_B_bar = -kappa (s_1^2 u_n + s_n^2 u_1 + U s_n s_1) / (u_n u_1),
!>
!> a sum of terms of one sign (no cancellation, exact for d2_1 = d2_n), and with one point
!> outside -kappa s_in^3 / (u_in (s_in - s_out)) as for psi. It needs u > 0 at both times:
!> the caller evaluates only states the swept test admitted.
!>
!> Friction (regularized Coulomb, issue 24 item 2: the law of rs_contact_obstacle on the relative
!> motion of the two points). The friction acts in the tangent plane of the contact, whose
!> normal n is that of the two centrelines, not of the point pair: point pairs at an offset
!> along a line contact are oblique, and with their own direction as the normal, two rods pressed
!> together (a normal motion) would slip at every oblique pair and dissipate. With the unit
!> tangents t_a, t_b of the centrelines at the two points and P = I - t t^T,
!>
!>     n = q / |q|,    q = (P_a P_b + P_b P_a) r_n / 2
!>
!> (r_n / |r_n| where q = 0): for parallel rods the radial direction, for crossing rods their
!> common normal t_a x t_b, continuous in between. n is taken at t_n, fixed in the step (the
!> friction's direction explicit, its magnitude and the slip implicit). With the normal force
!> f_N = |f_a . n| = 2 |psi_bar| |r_mid . n|, the step's relative slip u = (I - n n^T)(r_1 - r_n)
!> and eta = v_s h (params%slip_length, set by the caller per step), the friction terms are
!>
!>     f_Ta = mu f_N u / sqrt(|u|^2 + eta^2),    f_Tb = -f_Ta,
!>
!> added to f_a and f_b. The physical force -f_Ta on a opposes a's slip relative to b with at
!> most mu f_N (Coulomb's bound for |u| >> eta; a viscous stick branch below v_s). Their work
!> on the step is -(f_Ta . (x_a,1 - x_a,n) + f_Tb . (x_b,1 - x_b,n)) = -D with
!> D = mu f_N |u|^2 / sqrt(|u|^2 + eta^2) >= 0 by construction (contact_point_friction returns
!> it): the balance H_{n+1} - H_n = W_n - D_n of methods/ph_director_3d.md §5.3 item 1 holds with
!> D booked. On a line contact sliding along its axis the friction is exactly mu times the
!> normal force (the f_a . n of all pairs sum to it), and a normal motion does not slip.
!> f_Ta + f_Tb = 0 keeps linear momentum. Angular momentum is not kept: the two tangential
!> forces act at centreline points a distance |r_mid| (about r_c) apart, a couple r_mid x f_Ta
!> that a contact between the surfaces would apply to the cross-sections (their rotations), which
!> a centreline law leaves out; for the same reason a rod rolling on another slips at its
!> centreline (docs/theory/bundles.md, Friction).
module rs_contact_potential
    use rs_core_kinds, only: rk
    implicit none
    private

    public :: contact_params_t, contact_params_init
    public :: contact_psi, contact_dpsi, contact_d2psi
    public :: contact_discrete_gradient, contact_discrete_gradient_derivative
    public :: contact_point_force, contact_point_tangent
    public :: contact_pair_force, contact_pair_tangent
    public :: contact_friction_normal, contact_point_friction, contact_point_friction_tangent

    !> Parameters of the potential of one pair of rods; set them with contact_params_init, which
    !> also fills the derived components.
    type :: contact_params_t
        !> Stiffness k (N/m^3; psi = k (r_c^2 - d2)^3 / (3 r_c^4) is an energy per length squared).
        real(rk) :: stiffness = 0.0_rk
        !> Contact distance r_c = radius_a + radius_b + margin.
        real(rk) :: contact_distance = 0.0_rk
        !> r_c^2: psi = 0 for d2 >= support2.
        real(rk) :: support2 = 0.0_rk
        !> c = k / (3 r_c^4), so that psi = c (r_c^2 - d2)^3 on the support.
        real(rk) :: coefficient = 0.0_rk
        !> Coulomb friction coefficient (0: frictionless) and the regularization length
        !> eta = v_s h of the step (m; module header, Friction).
        real(rk) :: mu = 0.0_rk
        real(rk) :: slip_length = 0.0_rk
        !> The barrier (module header): the wall d_w (0: no barrier), d_w^2, d_b^2,
        !> U = d_b^2 - d_w^2 and kappa.
        real(rk) :: wall = 0.0_rk
        real(rk) :: wall2 = 0.0_rk
        real(rk) :: barrier2 = 0.0_rk
        real(rk) :: barrier_span = 0.0_rk
        real(rk) :: barrier_coefficient = 0.0_rk
    end type contact_params_t

    !> The barrier's distance d_b as a fraction of the contact distance r_c.
    real(rk), parameter, public :: barrier_fraction = 0.5_rk

contains

    !> Parameters for two rods of radii `radius_a`, `radius_b` (> 0), stiffness `stiffness` (> 0)
    !> and an optional `margin` (>= 0, default 0) added to the contact distance. Invalid values
    !> are a programming error of the caller (input validation rejects them first): `ok` is then
    !> false and `params` is the default (zero force everywhere). An optional `wall` d_w in
    !> (0, d_b) adds the barrier (module header); 0 or absent: none.
    pure subroutine contact_params_init(params, radius_a, radius_b, stiffness, ok, margin, wall)
        type(contact_params_t), intent(out) :: params
        real(rk), intent(in) :: radius_a, radius_b, stiffness
        logical, intent(out) :: ok
        real(rk), intent(in), optional :: margin, wall
        real(rk) :: extra, d_w
        extra = 0.0_rk
        if (present(margin)) extra = margin
        d_w = 0.0_rk
        if (present(wall)) d_w = wall
        ok = radius_a > 0.0_rk .and. radius_b > 0.0_rk .and. stiffness > 0.0_rk &
            .and. extra >= 0.0_rk .and. d_w >= 0.0_rk .and. &
            d_w < barrier_fraction * (radius_a + radius_b + extra)
        if (.not. ok) return
        params%stiffness = stiffness
        params%contact_distance = radius_a + radius_b + extra
        params%support2 = params%contact_distance**2
        params%coefficient = stiffness / (3.0_rk * params%support2**2)
        if (d_w == 0.0_rk) return
        params%wall = d_w
        params%wall2 = d_w**2
        params%barrier2 = (barrier_fraction * params%contact_distance)**2
        params%barrier_span = params%barrier2 - params%wall2
        params%barrier_coefficient = params%coefficient * params%support2
    end subroutine contact_params_init

    !> The pair energy psi(d2) = k (r_c^2 - d2)^3 / (3 r_c^4) on the support, 0 outside.
    elemental function contact_psi(d2, params) result(psi)
        real(rk), intent(in) :: d2
        type(contact_params_t), intent(in) :: params
        real(rk) :: psi
        real(rk) :: s
        s = params%support2 - d2
        psi = 0.0_rk
        if (s > 0.0_rk) psi = params%coefficient * s**3
        if (d2 < params%barrier2) psi = psi + params%barrier_coefficient * &
            (params%barrier2 - d2)**3 / (d2 - params%wall2)
    end function contact_psi

    !> dpsi/d(d2) = -k (r_c^2 - d2)^2 / r_c^4 on the support (<= 0), 0 outside.
    elemental function contact_dpsi(d2, params) result(dpsi)
        real(rk), intent(in) :: d2
        type(contact_params_t), intent(in) :: params
        real(rk) :: dpsi
        real(rk) :: s, u
        s = params%support2 - d2
        dpsi = 0.0_rk
        if (s > 0.0_rk) dpsi = -3.0_rk * params%coefficient * s**2
        if (d2 < params%barrier2) then
            s = params%barrier2 - d2
            u = d2 - params%wall2
            dpsi = dpsi - params%barrier_coefficient * (3.0_rk * s**2 / u + s**3 / u**2)
        end if
    end function contact_dpsi

    !> d2psi/d(d2)^2 = 2 k (r_c^2 - d2) / r_c^4 on the support (>= 0), 0 outside.
    elemental function contact_d2psi(d2, params) result(d2psi)
        real(rk), intent(in) :: d2
        type(contact_params_t), intent(in) :: params
        real(rk) :: d2psi
        real(rk) :: s, u
        s = params%support2 - d2
        d2psi = 0.0_rk
        if (s > 0.0_rk) d2psi = 6.0_rk * params%coefficient * s
        if (d2 < params%barrier2) then
            s = params%barrier2 - d2
            u = d2 - params%wall2
            d2psi = d2psi + params%barrier_coefficient * (6.0_rk * s / u + 6.0_rk * s**2 / u**2 &
                + 2.0_rk * s**3 / u**3)
        end if
    end function contact_d2psi

    !> The discrete gradient psi_bar = [psi(d2_1) - psi(d2_n)] / (d2_1 - d2_n), equal to
    !> dpsi(d2_n) when d2_1 = d2_n; evaluated without cancellation for every step size (module
    !> header). Symmetric in its two arguments; <= 0.
    elemental function contact_discrete_gradient(d2_n, d2_1, params) result(psi_bar)
        real(rk), intent(in) :: d2_n, d2_1
        type(contact_params_t), intent(in) :: params
        real(rk) :: psi_bar
        real(rk) :: s_n, s_1
        s_n = params%support2 - d2_n
        s_1 = params%support2 - d2_1
        if (s_n > 0.0_rk .and. s_1 > 0.0_rk) then
            psi_bar = -params%coefficient * (s_n**2 + s_n * s_1 + s_1**2)
        else if (s_n > 0.0_rk) then
            psi_bar = -params%coefficient * s_n**3 / (s_n - s_1)
        else if (s_1 > 0.0_rk) then
            psi_bar = -params%coefficient * s_1**3 / (s_1 - s_n)
        else
            psi_bar = 0.0_rk
        end if
        if (d2_n < params%barrier2 .or. d2_1 < params%barrier2) psi_bar = psi_bar + &
            barrier_discrete_gradient(d2_n, d2_1, params)
    end function contact_discrete_gradient

    !> d psi_bar / d(d2_1), the derivative of contact_discrete_gradient with respect to its second
    !> argument (the t_{n+1} value, for the Newton Jacobian), branch by branch as there.
    elemental function contact_discrete_gradient_derivative(d2_n, d2_1, params) result(dpsi_bar)
        real(rk), intent(in) :: d2_n, d2_1
        type(contact_params_t), intent(in) :: params
        real(rk) :: dpsi_bar
        real(rk) :: s_n, s_1
        s_n = params%support2 - d2_n
        s_1 = params%support2 - d2_1
        ! d/d(d2_1) = -d/d(s_1) of the expressions of contact_discrete_gradient.
        if (s_n > 0.0_rk .and. s_1 > 0.0_rk) then
            dpsi_bar = params%coefficient * (s_n + 2.0_rk * s_1)
        else if (s_n > 0.0_rk) then
            dpsi_bar = params%coefficient * s_n**3 / (s_n - s_1)**2
        else if (s_1 > 0.0_rk) then
            dpsi_bar = params%coefficient * s_1**2 * (2.0_rk * s_1 - 3.0_rk * s_n) / (s_1 - s_n)**2
        else
            dpsi_bar = 0.0_rk
        end if
        if (d2_n < params%barrier2 .or. d2_1 < params%barrier2) dpsi_bar = dpsi_bar + &
            barrier_discrete_gradient_derivative(d2_n, d2_1, params)
    end function contact_discrete_gradient_derivative

    !> The barrier's divided difference psi_B_bar (module header), for at least one point in
    !> its support and u > 0 at both times.
    elemental function barrier_discrete_gradient(d2_n, d2_1, params) result(psi_bar)
        real(rk), intent(in) :: d2_n, d2_1
        type(contact_params_t), intent(in) :: params
        real(rk) :: psi_bar
        real(rk) :: s_n, s_1, u_n, u_1
        s_n = params%barrier2 - d2_n
        s_1 = params%barrier2 - d2_1
        u_n = d2_n - params%wall2
        u_1 = d2_1 - params%wall2
        if (s_n > 0.0_rk .and. s_1 > 0.0_rk) then
            psi_bar = -params%barrier_coefficient * (s_1**2 * u_n + s_n**2 * u_1 + &
                params%barrier_span * s_n * s_1) / (u_n * u_1)
        else if (s_n > 0.0_rk) then
            psi_bar = -params%barrier_coefficient * s_n**3 / (u_n * (s_n - s_1))
        else
            psi_bar = -params%barrier_coefficient * s_1**3 / (u_1 * (s_1 - s_n))
        end if
    end function barrier_discrete_gradient

    !> d psi_B_bar / d(d2_1) = -d psi_B_bar / d s_1, branch by branch as
    !> barrier_discrete_gradient.
    elemental function barrier_discrete_gradient_derivative(d2_n, d2_1, params) result(dpsi_bar)
        real(rk), intent(in) :: d2_n, d2_1
        type(contact_params_t), intent(in) :: params
        real(rk) :: dpsi_bar
        real(rk) :: s_n, s_1, u_n, u_1, numerator, kappa, f_1, df_1
        kappa = params%barrier_coefficient
        s_n = params%barrier2 - d2_n
        s_1 = params%barrier2 - d2_1
        u_n = d2_n - params%wall2
        u_1 = d2_1 - params%wall2
        if (s_n > 0.0_rk .and. s_1 > 0.0_rk) then
            ! N / D with N = s_1^2 u_n + s_n^2 u_1 + U s_n s_1, D = u_n u_1: dN/ds_1 =
            ! u_n (2 s_1 + s_n), dD/ds_1 = -u_n, so d(N/D)/ds_1 = (dN u_1 + N) / (u_n u_1^2).
            numerator = s_1**2 * u_n + s_n**2 * u_1 + params%barrier_span * s_n * s_1
            dpsi_bar = kappa * (u_n * (2.0_rk * s_1 + s_n) * u_1 + numerator) / (u_n * u_1**2)
        else if (s_n > 0.0_rk) then
            dpsi_bar = kappa * s_n**3 / (u_n * (s_n - s_1)**2)
        else
            ! psi_B_bar = -f(s_1) / (s_1 - s_n) with f = kappa s^3 / u, f' = kappa (3 s^2 / u
            ! + s^3 / u^2).
            f_1 = kappa * s_1**3 / u_1
            df_1 = kappa * (3.0_rk * s_1**2 / u_1 + s_1**3 / u_1**2)
            dpsi_bar = (df_1 * (s_1 - s_n) - f_1) / (s_1 - s_n)**2
        end if
    end function barrier_discrete_gradient_derivative

    !> Midpoint contact forces (energy gradients, module header) f_a = 2 psi_bar r_mid and
    !> f_b = -f_a on the points a and b, from their positions at t_n (`xa_n`, `xb_n`) and
    !> t_{n+1} (`xa_1`, `xb_1`).
    pure subroutine contact_point_force(xa_n, xb_n, xa_1, xb_1, params, f_a, f_b)
        real(rk), intent(in) :: xa_n(3), xb_n(3), xa_1(3), xb_1(3)
        type(contact_params_t), intent(in) :: params
        real(rk), intent(out) :: f_a(3), f_b(3)
        real(rk) :: r_n(3), r_1(3), psi_bar
        r_n = xa_n - xb_n
        r_1 = xa_1 - xb_1
        psi_bar = contact_discrete_gradient(dot_product(r_n, r_n), dot_product(r_1, r_1), params)
        ! 2 psi_bar r_mid with r_mid = (r_n + r_1) / 2.
        f_a = psi_bar * (r_n + r_1)
        f_b = -f_a
    end subroutine contact_point_force

    !> Jacobian of contact_point_force: tangent(1:6, 1:6) = d(f_a, f_b) / d(xa_1, xb_1), rows
    !> (f_a, f_b) and columns (xa_1, xb_1), the 1/2 of the midpoint included. With
    !> A = psi_bar I + 4 (d psi_bar / d d2_1) r_mid r_1^T it is [[A, -A], [-A, A]] (not symmetric).
    pure subroutine contact_point_tangent(xa_n, xb_n, xa_1, xb_1, params, tangent)
        real(rk), intent(in) :: xa_n(3), xb_n(3), xa_1(3), xb_1(3)
        type(contact_params_t), intent(in) :: params
        real(rk), intent(out) :: tangent(6, 6)
        real(rk) :: r_n(3), r_1(3), d2_n, d2_1, psi_bar, dpsi_bar, a(3, 3)
        integer :: i, j
        r_n = xa_n - xb_n
        r_1 = xa_1 - xb_1
        d2_n = dot_product(r_n, r_n)
        d2_1 = dot_product(r_1, r_1)
        psi_bar = contact_discrete_gradient(d2_n, d2_1, params)
        dpsi_bar = contact_discrete_gradient_derivative(d2_n, d2_1, params)
        ! f_a = psi_bar (r_n + r_1): d r_1 / d xa_1 = I and d d2_1 / d xa_1 = 2 r_1^T.
        do j = 1, 3
            do i = 1, 3
                a(i, j) = 2.0_rk * dpsi_bar * (r_n(i) + r_1(i)) * r_1(j)
            end do
            a(j, j) = a(j, j) + psi_bar
        end do
        tangent(1:3, 1:3) = a
        tangent(1:3, 4:6) = -a
        tangent(4:6, 1:3) = -a
        tangent(4:6, 4:6) = a
    end subroutine contact_point_tangent

    !> contact_point_force for points given by weights: x_a = sum_i weights_a(i) qa(:, i) with the
    !> nodal positions qa (3, size(weights_a)) of element a at t_n (`qa_n`) and t_{n+1} (`qa_1`),
    !> likewise b. Returns the forces f_a, f_b on the two points; the caller distributes them to
    !> the nodes as weights_a(i) f_a and weights_b(j) f_b.
    pure subroutine contact_pair_force(weights_a, weights_b, qa_n, qb_n, qa_1, qb_1, params, &
            f_a, f_b)
        real(rk), intent(in) :: weights_a(:), weights_b(:)
        real(rk), intent(in) :: qa_n(3, size(weights_a)), qa_1(3, size(weights_a))
        real(rk), intent(in) :: qb_n(3, size(weights_b)), qb_1(3, size(weights_b))
        type(contact_params_t), intent(in) :: params
        real(rk), intent(out) :: f_a(3), f_b(3)
        call contact_point_force(matmul(qa_n, weights_a), matmul(qb_n, weights_b), &
            matmul(qa_1, weights_a), matmul(qb_1, weights_b), params, f_a, f_b)
    end subroutine contact_pair_force

    !> contact_point_tangent for points given by weights (as contact_pair_force): the 6 x 6
    !> derivative d(f_a, f_b) / d(x_a,1, x_b,1) with respect to the points. The nodal block of
    !> node i of a (or b) and node j of a (or b) is weight_i weight_j times the 3 x 3 block.
    pure subroutine contact_pair_tangent(weights_a, weights_b, qa_n, qb_n, qa_1, qb_1, params, &
            tangent)
        real(rk), intent(in) :: weights_a(:), weights_b(:)
        real(rk), intent(in) :: qa_n(3, size(weights_a)), qa_1(3, size(weights_a))
        real(rk), intent(in) :: qb_n(3, size(weights_b)), qb_1(3, size(weights_b))
        type(contact_params_t), intent(in) :: params
        real(rk), intent(out) :: tangent(6, 6)
        call contact_point_tangent(matmul(qa_n, weights_a), matmul(qb_n, weights_b), &
            matmul(qa_1, weights_a), matmul(qb_1, weights_b), params, tangent)
    end subroutine contact_pair_tangent

    !> The normal n of the contact's tangent plane (module header, Friction) from the relative
    !> position r_n = x_a - x_b and the unit tangents of the two centrelines at t_n; the zero
    !> vector when r_n = 0 (no friction then).
    pure function contact_friction_normal(r_n, tangent_a, tangent_b) result(normal)
        real(rk), intent(in) :: r_n(3), tangent_a(3), tangent_b(3)
        real(rk) :: normal(3)
        real(rk) :: pa(3), pb(3), q(3)
        ! P_b r then P_a of it, and the other order; their mean is q.
        pb = r_n - dot_product(tangent_b, r_n) * tangent_b
        pa = r_n - dot_product(tangent_a, r_n) * tangent_a
        q = 0.5_rk * (pb - dot_product(tangent_a, pb) * tangent_a + &
            pa - dot_product(tangent_b, pa) * tangent_b)
        normal = 0.0_rk
        if (norm2(q) > 0.0_rk) then
            normal = q / norm2(q)
        else if (norm2(r_n) > 0.0_rk) then
            normal = r_n / norm2(r_n)
        end if
    end function contact_friction_normal

    !> The normal force f_N = |f_a . n| (and the sign of f_a . n), the slip u of a step and the
    !> root sqrt(|u|^2 + eta^2) of a point pair with the contact normal n (module header,
    !> Friction); f_N = 0 where the pair exerts no force.
    pure subroutine slip_of_step(xa_n, xb_n, xa_1, xb_1, params, normal, f_normal, sense, slip, &
            root)
        real(rk), intent(in) :: xa_n(3), xb_n(3), xa_1(3), xb_1(3), normal(3)
        type(contact_params_t), intent(in) :: params
        real(rk), intent(out) :: f_normal, sense, slip(3), root
        real(rk) :: r_n(3), r_1(3), step(3), psi_bar, along
        r_n = xa_n - xb_n
        r_1 = xa_1 - xb_1
        psi_bar = contact_discrete_gradient(dot_product(r_n, r_n), dot_product(r_1, r_1), params)
        along = psi_bar * dot_product(r_n + r_1, normal)
        f_normal = abs(along)
        sense = sign(1.0_rk, along)
        slip = 0.0_rk
        root = params%slip_length
        if (f_normal == 0.0_rk) return
        step = r_1 - r_n
        slip = step - dot_product(normal, step) * normal
        root = sqrt(dot_product(slip, slip) + params%slip_length**2)
    end subroutine slip_of_step

    !> The friction term f_Ta on point a (f_Tb = -f_Ta) of a step with the contact normal n and
    !> its dissipation D = f_Ta . (r_1 - r_n) >= 0 (module header, Friction; zero without
    !> friction or force); optional `slip_length`: |u|, the step's slip of the pair (0 where
    !> it exerts no force).
    pure subroutine contact_point_friction(xa_n, xb_n, xa_1, xb_1, params, normal, f_t, &
            dissipation, slip_length)
        real(rk), intent(in) :: xa_n(3), xb_n(3), xa_1(3), xb_1(3), normal(3)
        type(contact_params_t), intent(in) :: params
        real(rk), intent(out) :: f_t(3), dissipation
        real(rk), intent(out), optional :: slip_length
        real(rk) :: f_normal, sense, slip(3), root
        f_t = 0.0_rk
        dissipation = 0.0_rk
        if (present(slip_length)) slip_length = 0.0_rk
        if (params%mu == 0.0_rk) return
        call slip_of_step(xa_n, xb_n, xa_1, xb_1, params, normal, f_normal, sense, slip, root)
        if (f_normal == 0.0_rk) return
        f_t = (params%mu * f_normal / root) * slip
        dissipation = dot_product(f_t, slip)
        if (present(slip_length)) slip_length = norm2(slip)
    end subroutine contact_point_friction

    !> d f_Ta / d xa_1 (3 x 3) of contact_point_friction; f_Ta depends on the positions at
    !> t_{n+1} through r_1 = xa_1 - xb_1 only, so the pair's tangent is [[T, -T], [-T, T]] as
    !> for the normal force. Through f_N (d f_N = sense n^T A with A the normal tangent of
    !> contact_point_tangent) and the slip (d u = I - n n^T; n is fixed in the step).
    pure subroutine contact_point_friction_tangent(xa_n, xb_n, xa_1, xb_1, params, normal, &
            tangent)
        real(rk), intent(in) :: xa_n(3), xb_n(3), xa_1(3), xb_1(3), normal(3)
        type(contact_params_t), intent(in) :: params
        real(rk), intent(out) :: tangent(3, 3)
        real(rk) :: f_normal, sense, slip(3), root, r_n(3), r_1(3), direction(3)
        real(rk) :: psi_bar, dpsi_bar, d_f_normal(3), d_direction(3, 3)
        integer :: i
        tangent = 0.0_rk
        if (params%mu == 0.0_rk) return
        call slip_of_step(xa_n, xb_n, xa_1, xb_1, params, normal, f_normal, sense, slip, root)
        if (f_normal == 0.0_rk) return
        r_n = xa_n - xb_n
        r_1 = xa_1 - xb_1
        psi_bar = contact_discrete_gradient(dot_product(r_n, r_n), dot_product(r_1, r_1), params)
        dpsi_bar = contact_discrete_gradient_derivative(dot_product(r_n, r_n), &
            dot_product(r_1, r_1), params)
        ! f_a . n = psi_bar (r_n + r_1) . n, A = psi_bar I + 2 dpsi_bar (r_n + r_1) r_1^T.
        d_f_normal = sense * (psi_bar * normal + 2.0_rk * dpsi_bar * dot_product(normal, &
            r_n + r_1) * r_1)
        ! d (u / root) = (I - direction direction^T)(I - n n^T) / root, and (I - n n^T) u = u.
        direction = slip / root
        do i = 1, 3
            d_direction(:, i) = -(normal * normal(i) + direction * direction(i)) / root
            d_direction(i, i) = d_direction(i, i) + 1.0_rk / root
        end do
        do i = 1, 3
            tangent(:, i) = params%mu * (direction * d_f_normal(i) + f_normal * d_direction(:, i))
        end do
    end subroutine contact_point_friction_tangent

end module rs_contact_potential
