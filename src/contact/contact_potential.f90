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
module rs_contact_potential
    use rs_core_kinds, only: rk
    implicit none
    private

    public :: contact_params_t, contact_params_init
    public :: contact_psi, contact_dpsi, contact_d2psi
    public :: contact_discrete_gradient, contact_discrete_gradient_derivative
    public :: contact_point_force, contact_point_tangent
    public :: contact_pair_force, contact_pair_tangent

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
    end type contact_params_t

contains

    !> Parameters for two rods of radii `radius_a`, `radius_b` (> 0), stiffness `stiffness` (> 0)
    !> and an optional `margin` (>= 0, default 0) added to the contact distance. Invalid values
    !> are a programming error of the caller (input validation rejects them first): `ok` is then
    !> false and `params` is the default (zero force everywhere).
    pure subroutine contact_params_init(params, radius_a, radius_b, stiffness, ok, margin)
        type(contact_params_t), intent(out) :: params
        real(rk), intent(in) :: radius_a, radius_b, stiffness
        logical, intent(out) :: ok
        real(rk), intent(in), optional :: margin
        real(rk) :: extra
        extra = 0.0_rk
        if (present(margin)) extra = margin
        ok = radius_a > 0.0_rk .and. radius_b > 0.0_rk .and. stiffness > 0.0_rk &
            .and. extra >= 0.0_rk
        if (.not. ok) return
        params%stiffness = stiffness
        params%contact_distance = radius_a + radius_b + extra
        params%support2 = params%contact_distance**2
        params%coefficient = stiffness / (3.0_rk * params%support2**2)
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
    end function contact_psi

    !> dpsi/d(d2) = -k (r_c^2 - d2)^2 / r_c^4 on the support (<= 0), 0 outside.
    elemental function contact_dpsi(d2, params) result(dpsi)
        real(rk), intent(in) :: d2
        type(contact_params_t), intent(in) :: params
        real(rk) :: dpsi
        real(rk) :: s
        s = params%support2 - d2
        dpsi = 0.0_rk
        if (s > 0.0_rk) dpsi = -3.0_rk * params%coefficient * s**2
    end function contact_dpsi

    !> d2psi/d(d2)^2 = 2 k (r_c^2 - d2) / r_c^4 on the support (>= 0), 0 outside.
    elemental function contact_d2psi(d2, params) result(d2psi)
        real(rk), intent(in) :: d2
        type(contact_params_t), intent(in) :: params
        real(rk) :: d2psi
        real(rk) :: s
        s = params%support2 - d2
        d2psi = 0.0_rk
        if (s > 0.0_rk) d2psi = 6.0_rk * params%coefficient * s
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
    end function contact_discrete_gradient_derivative

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

end module rs_contact_potential
