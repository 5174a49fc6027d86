!> Contact of two rod elements: the double quadrature of the pair potential of
!> rs_contact_potential over the contact points of two elements, its energy-consistent midpoint
!> forces on the element nodes and their Newton tangent (issue 10, DESIGN.md §5 "Contact that
!> keeps energy"). Pure kernels on plain arrays: no PETSc, no MPI, no allocation (DESIGN.md §2,
!> STYLE.md item 4).
!>
!> The element-pair energy. Element a has n_a nodes X_a,i (Lagrange interpolation of any degree)
!> and m_a contact points with shape values N_i(g) and weights w_a(g) = quadrature weight times
!> length Jacobian (so sum_g w_a(g) = element length); likewise b. With x_a(g) = sum_i N_i(g) X_a,i
!>
!>     E_ab = sum_g sum_h w_a(g) w_b(h) psi(|x_a(g) - x_b(h)|^2),
!>
!> the quadrature of the double line integral of psi ds_a ds_b: psi is an energy per length
!> squared (N/m) and the stiffness k an energy per length^4 (N/m^3).
!>
!> Midpoint forces. With the point-pair discrete gradient f_a(g,h) = -f_b(g,h) of
!> rs_contact_potential (contact_point_force), the nodal forces are
!>
!>     r_a,i = sum_g sum_h w_a w_b N_i(g) f_a(g,h),    r_b,j = sum_g sum_h w_a w_b N_j(h) f_b(g,h),
!>
!> energy gradients that enter the momentum residual as the internal forces do (the caller
!> multiplies by h). Because x is linear in the nodes, exactly (up to round-off)
!>   - E_ab(t_{n+1}) - E_ab(t_n) = r_a . (X_a,1 - X_a,n) + r_b . (X_b,1 - X_b,n) for every step,
!>     also when point pairs enter or leave the support (energy);
!>   - sum_i r_a,i + sum_j r_b,j = 0, since sum_i N_i = 1 (linear momentum);
!>   - sum_i X_a,i,mid x r_a,i + sum_j X_b,j,mid x r_b,j = sum_{g,h} w_a w_b r_mid x f_a = 0,
!>     since x_mid is the same linear combination of the nodal midpoints and f_a is parallel to
!>     r_mid = x_a,mid - x_b,mid (angular momentum). With the positions at t_{n+1} in place of
!>     the midpoints the moment does not vanish.
!> The points are formed relative to node 1 of element a at t_n, x - X_a,1 = sum_i N_i (X_i -
!> X_a,1), so round-off follows the element sizes, not the distance from the coordinate origin.
!>
!> Skipping. A point pair outside the support at both times contributes nothing. Before the
!> point loop, each element gets a bounding sphere per time level: centre c = mean of the nodes,
!> radius R = Lambda max_i |X_i - c| with Lambda = max_g sum_i |N_i(g)| (Lagrange shape values
!> can be negative, so the points need not lie in the hull of the nodes, nor in the sphere of
!> radius max_i |X_i - c|: a folded quadratic element with 8 points reaches 1.04 times it; the
!> bound holds because sum_i N_i = 1). The pair is skipped (zeros, no tangent work) only when
!> |c_a - c_b| - R_a - R_b exceeds r_c by a round-off safety margin at both times.
!>
!> The line-contact law (for choosing k). Two parallel infinite straight centrelines at distance
!> d interact, in the limit of fine quadrature, with the energy per unit length
!> Phi(d) = integral psi(d^2 + u^2) du over the line. On the support psi = c (r_c^2 - d^2 - u^2)^3
!> with c = k / (3 r_c^4), and with a^2 = r_c^2 - d^2 (a = the half-length of the contact
!> patch), integral_{-a}^{a} (a^2 - u^2)^3 du = (32/35) a^7, so
!>
!>     Phi(d) = (32 / 105) k (r_c^2 - d^2)^(7/2) / r_c^4,
!>     f(d) = -dPhi/dd = (32 / 15) k d (r_c^2 - d^2)^(5/2) / r_c^4       (force per length, N/m)
!>
!> for d < r_c (0 beyond). f rises from 0 at d = r_c to its peak f_max = (32/15) 6^(-1/2)
!> (5/6)^(5/2) k r_c^2 = 0.5521 k r_c^2 at d = r_c / sqrt(6) (penetration 0.592 r_c) and falls
!> to 0 at d = 0: a line load above f_max pushes the rods through each other. In terms of the
!> penetration delta = r_c - d, r_c^2 - d^2 = delta (2 r_c - delta), a = sqrt(delta (2 r_c -
!> delta)) ~ sqrt(2 r_c delta), and for delta << r_c
!>
!>     f ~ (128 sqrt(2) / 15) k delta^(5/2) / sqrt(r_c) = 12.07 k delta^(5/2) / sqrt(r_c)
!>
!> (the exact f is smaller by the factor (1 - delta/r_c) (1 - delta/(2 r_c))^(5/2) = 1 - (9/4)
!> delta/r_c + ...). Choosing k: to carry a line load F (N/m) at a penetration delta, take
!>
!>     k = 15 sqrt(r_c) F / (128 sqrt(2) delta^(5/2))                                    (N/m^3),
!>
!> and check the exact delta with contact_line_penetration and F << f_max. Example: two wires of
!> radius 1 mm (r_c = 2 mm) pressed with F = 1000 N/m at delta = 0.02 r_c = 40 um: k = 3.66e11
!> N/m^3; the exact penetration is then 0.0204 r_c, f_max = 8.1e5 N/m, a = 0.20 r_c.
!>
!> Contact-point density. The contact points are the m Gauss-Legendre points of each element
!> (contact_points). The force between two rods is a quadrature over the contact patch of
!> half-length a, so the point spacing h = L/m (L the element length) must be small compared
!> with a, not merely with r_c; otherwise the force ripples as one rod slides along the other:
!> a corrugated contact, felt as bumpy sliding and a spurious tangential force. Since psi' is
!> (a^2 - u^2)^2 up to a factor, the relative ripple depends only on m and h/a. Measured in
!> test_contact_element (sliding_ripple: a straight element of length L with m = 1..8 points
!> sliding along a chain of the same elements), worst case over m:
!>
!>     h / a                                     1       1/2      1/4       1/8
!>     ripple (max - min) / mean of F_n          36%     3.8%     0.52%     0.064%
!>     spurious tangential force / (F_n a / d)   0.22    0.021    0.0034    0.00043
!>
!> Rule: L/m <= a/2 at the working penetration keeps the ripple below 5%, L/m <= a/4 below 1%.
!> Small penetrations need dense points: delta = 0.02 r_c gives a = 0.2 r_c, so L/m <= 0.1 r_c
!> for 5%. The force averaged over a sliding period equals the line law for any m, and the
!> energy identity above holds for any m: the density governs only the corrugation.
module rs_contact_element
    use rs_core_kinds, only: rk, pi
    use rs_math_quadrature, only: gauss_legendre, max_gauss_points
    use rs_math_lagrange, only: lagrange_shape
    use rs_contact_potential, only: contact_params_t, contact_psi, contact_point_force, &
        contact_point_tangent, contact_friction_normal, contact_point_friction, &
        contact_point_friction_tangent
    implicit none
    private

    public :: contact_element_pair, contact_points, contact_element_swept_clear
    public :: contact_line_force, contact_line_peak_force, contact_line_penetration

    ! Relative round-off safety of the bounding-sphere skip, times the coordinate scale.
    real(rk), parameter :: skip_safety = 1.0e-12_rk

contains

    !> Energy, midpoint nodal forces and (optionally) their tangent of the contact of element a
    !> and element b (module header). `shape_a(n_a, m_a)` holds the shape values N_i(g) at the
    !> m_a contact points and `weight_a(m_a)` their weights (summing to the element length);
    !> `xa_n`, `xa_1` (3, n_a) are the nodal centreline positions at t_n and t_{n+1}; likewise b.
    !> Out: `r_a` (3, n_a) and `r_b` (3, n_b), the energy gradients on the nodes; `energy_n`,
    !> `energy_1` the pair energy E_ab at t_n and t_{n+1}; optional `tangent` = d[r_a; r_b] /
    !> d[X_a,1; X_b,1] with rows and columns ordered as the X_a nodes then the X_b nodes, 3 per
    !> node (not symmetric); optional `closest`, the smallest point distance |x_a(g) - x_b(h)| at
    !> t_{n+1}, exact whenever it is below r_c (otherwise a lower bound that is >= r_c when the
    !> pair was skipped by its bounding spheres). With params%mu > 0 the forces and the tangent
!> include friction (rs_contact_potential, Friction), whose contact normals take the centreline
!> tangents at t_n from `slope_a` (n_a, m_a) and `slope_b`, the shape functions' derivatives at
!> the contact points (contact_points; any scale), or, when they are absent, from the element's
!> chord (exact for straight elements); optional `dissipation` is the pair's friction
!> dissipation D of the step (the sum of w_a w_b D over the point pairs, >= 0), optional
!> `friction_a` the sum of the friction terms w_a w_b f_Ta on a (the terms on b sum to its
!> negative), optional `largest_slip` the largest slip |u| of a point pair in contact.
    pure subroutine contact_element_pair(params, shape_a, weight_a, xa_n, xa_1, shape_b, &
            weight_b, xb_n, xb_1, r_a, r_b, energy_n, energy_1, tangent, closest, dissipation, &
            slope_a, slope_b, friction_a, largest_slip)
        type(contact_params_t), intent(in) :: params
        real(rk), intent(in) :: shape_a(:, :), shape_b(:, :)
        real(rk), intent(in) :: weight_a(size(shape_a, 2)), weight_b(size(shape_b, 2))
        real(rk), intent(in) :: xa_n(3, size(shape_a, 1)), xa_1(3, size(shape_a, 1))
        real(rk), intent(in) :: xb_n(3, size(shape_b, 1)), xb_1(3, size(shape_b, 1))
        real(rk), intent(out) :: r_a(3, size(shape_a, 1)), r_b(3, size(shape_b, 1))
        real(rk), intent(out) :: energy_n, energy_1
        real(rk), intent(out), optional :: &
            tangent(3 * (size(shape_a, 1) + size(shape_b, 1)), &
            3 * (size(shape_a, 1) + size(shape_b, 1)))
        real(rk), intent(out), optional :: closest, dissipation
        real(rk), intent(in), optional :: slope_a(size(shape_a, 1), size(shape_a, 2))
        real(rk), intent(in), optional :: slope_b(size(shape_b, 1), size(shape_b, 2))
        real(rk), intent(out), optional :: friction_a(3), largest_slip
        integer :: n_a, n_b, g, h, i, j, ri, cj
        real(rk) :: lambda_a, lambda_b, gap_n, gap_1, rc_safe, origin(3)
        real(rk) :: pa_n(3), pa_1(3), pb_n(3), pb_1(3), rn(3), r1(3), d2_n, d2_1, d2_min
        real(rk) :: w, f_a(3), f_b(3), t6(6, 6), block(3, 3), v_i, v_j, f_t(3), d_t, t3(3, 3)
        real(rk) :: tangent_a(3), normal(3), slip_length
        logical :: friction
        ! The unit tangents of element b's points at t_n (friction only).
        real(rk) :: tangents_b(3, size(shape_b, 2))
        ! Element b's points at t_n and t_{n+1}, once per pair (not once per point of a).
        real(rk) :: points_b_n(3, size(shape_b, 2)), points_b_1(3, size(shape_b, 2))

        n_a = size(shape_a, 1)
        n_b = size(shape_b, 1)
        r_a = 0.0_rk
        r_b = 0.0_rk
        energy_n = 0.0_rk
        energy_1 = 0.0_rk
        if (present(tangent)) tangent = 0.0_rk
        if (present(dissipation)) dissipation = 0.0_rk
        if (present(friction_a)) friction_a = 0.0_rk
        if (present(largest_slip)) largest_slip = 0.0_rk
        friction = params%mu > 0.0_rk

        lambda_a = lebesgue_bound(shape_a)
        lambda_b = lebesgue_bound(shape_b)
        origin = xa_n(:, 1)
        gap_n = sphere_gap(xa_n, lambda_a, xb_n, lambda_b, origin)
        gap_1 = sphere_gap(xa_1, lambda_a, xb_1, lambda_b, origin)
        rc_safe = params%contact_distance * (1.0_rk + skip_safety)
        if (gap_n > rc_safe .and. gap_1 > rc_safe) then
            if (present(closest)) closest = gap_1
            return
        end if

        d2_min = huge(1.0_rk)
        do h = 1, size(shape_b, 2)
            points_b_n(:, h) = point(xb_n, shape_b(:, h), origin)
            points_b_1(:, h) = point(xb_1, shape_b(:, h), origin)
            if (friction) then
                if (present(slope_b)) then
                    tangents_b(:, h) = unit_tangent(xb_n, slope_b(:, h))
                else
                    tangents_b(:, h) = unit_chord(xb_n)
                end if
            end if
        end do
        do g = 1, size(shape_a, 2)
            pa_n = point(xa_n, shape_a(:, g), origin)
            pa_1 = point(xa_1, shape_a(:, g), origin)
            if (friction) then
                if (present(slope_a)) then
                    tangent_a = unit_tangent(xa_n, slope_a(:, g))
                else
                    tangent_a = unit_chord(xa_n)
                end if
            end if
            do h = 1, size(shape_b, 2)
                pb_n = points_b_n(:, h)
                pb_1 = points_b_1(:, h)
                rn = pa_n - pb_n
                r1 = pa_1 - pb_1
                d2_n = dot_product(rn, rn)
                d2_1 = dot_product(r1, r1)
                d2_min = min(d2_min, d2_1)
                ! Exactly the pairs with psi_bar = 0 and d psi_bar = 0 (rs_contact_potential).
                if (d2_n >= params%support2 .and. d2_1 >= params%support2) cycle
                w = weight_a(g) * weight_b(h)
                energy_n = energy_n + w * contact_psi(d2_n, params)
                energy_1 = energy_1 + w * contact_psi(d2_1, params)
                call contact_point_force(pa_n, pb_n, pa_1, pb_1, params, f_a, f_b)
                if (friction) then
                    normal = contact_friction_normal(pa_n - pb_n, tangent_a, tangents_b(:, h))
                    call contact_point_friction(pa_n, pb_n, pa_1, pb_1, params, normal, f_t, d_t, &
                        slip_length)
                    f_a = f_a + f_t
                    f_b = f_b - f_t
                    if (present(dissipation)) dissipation = dissipation + w * d_t
                    if (present(friction_a)) friction_a = friction_a + w * f_t
                    if (present(largest_slip)) largest_slip = max(largest_slip, slip_length)
                end if
                do i = 1, n_a
                    r_a(:, i) = r_a(:, i) + (w * shape_a(i, g)) * f_a
                end do
                do j = 1, n_b
                    r_b(:, j) = r_b(:, j) + (w * shape_b(j, h)) * f_b
                end do
                if (.not. present(tangent)) cycle
                ! The point tangent is [[A, -A], [-A, A]]: node I of the pair (a nodes, then b
                ! nodes) enters with v_I = N_I(g) or -N_I(h), and block (I, J) gets v_I v_J w A.
                call contact_point_tangent(pa_n, pb_n, pa_1, pb_1, params, t6)
                block = w * t6(1:3, 1:3)
                if (friction) then
                    call contact_point_friction_tangent(pa_n, pb_n, pa_1, pb_1, params, normal, &
                        t3)
                    block = block + w * t3
                end if
                do j = 1, n_a + n_b
                    if (j <= n_a) then
                        v_j = shape_a(j, g)
                    else
                        v_j = -shape_b(j - n_a, h)
                    end if
                    cj = 3 * (j - 1)
                    do i = 1, n_a + n_b
                        if (i <= n_a) then
                            v_i = shape_a(i, g)
                        else
                            v_i = -shape_b(i - n_a, h)
                        end if
                        ri = 3 * (i - 1)
                        tangent(ri + 1:ri + 3, cj + 1:cj + 3) = &
                            tangent(ri + 1:ri + 3, cj + 1:cj + 3) + (v_i * v_j) * block
                    end do
                end do
            end do
        end do
        if (present(closest)) closest = sqrt(d2_min)
    end subroutine contact_element_pair

    !> The swept test of the barrier (rs_contact_potential, The barrier; issue 24 item 1): true
    !> when no pair of contact points of elements a and b comes within `wall` of each other
    !> while the nodes move on straight lines from t_n (`xa_n`, `xb_n`) to t_{n+1} (`xa_1`,
    !> `xb_1`). The points are linear in the nodes, so each point pair's relative position
    !> r(tau) = r_n + tau (r_1 - r_n) moves on a straight line too and its smallest distance
    !> over tau in [0, 1] is that of the segment from r_n to r_1 to the origin, in closed form.
    !> A step that crosses two centrelines takes some point pair within the points' spacing,
    !> below the wall, so it fails this test, whatever its size. Pairs of elements whose bounding
    !> spheres at t_n stay further apart than the wall after both elements' largest point motion
    !> are clear without the point loop; so are pairs of linear or quadratic elements whose
    !> chords stay further apart than the wall after the elements' bulges off their chords and
    !> their largest point motion (the test that clears pairs in line contact, whose bounding
    !> spheres overlap).
    pure logical function contact_element_swept_clear(shape_a, xa_n, xa_1, shape_b, xb_n, &
            xb_1, wall) result(clear)
        real(rk), intent(in) :: shape_a(:, :), shape_b(:, :)
        real(rk), intent(in) :: xa_n(3, size(shape_a, 1)), xa_1(3, size(shape_a, 1))
        real(rk), intent(in) :: xb_n(3, size(shape_b, 1)), xb_1(3, size(shape_b, 1))
        real(rk), intent(in) :: wall
        real(rk) :: lambda_a, lambda_b, origin(3), motion_a, motion_b, wall_safe
        real(rk) :: pa_n(3), pa_1(3), rn(3), dr(3), tau, length2
        real(rk) :: points_b_n(3, size(shape_b, 2)), points_b_1(3, size(shape_b, 2))
        integer :: g, h, i
        clear = .true.
        lambda_a = lebesgue_bound(shape_a)
        lambda_b = lebesgue_bound(shape_b)
        origin = xa_n(:, 1)
        motion_a = 0.0_rk
        do i = 1, size(xa_n, 2)
            motion_a = max(motion_a, norm2(xa_1(:, i) - xa_n(:, i)))
        end do
        motion_b = 0.0_rk
        do i = 1, size(xb_n, 2)
            motion_b = max(motion_b, norm2(xb_1(:, i) - xb_n(:, i)))
        end do
        wall_safe = wall * (1.0_rk + skip_safety)
        if (sphere_gap(xa_n, lambda_a, xb_n, lambda_b, origin) - lambda_a * motion_a - &
            lambda_b * motion_b > wall_safe) return
        if (size(xa_n, 2) <= 3 .and. size(xb_n, 2) <= 3) then
            if (chord_gap(xa_n, xb_n, origin) - lambda_a * motion_a - lambda_b * motion_b > &
                wall_safe) return
        end if
        do h = 1, size(shape_b, 2)
            points_b_n(:, h) = point(xb_n, shape_b(:, h), origin)
            points_b_1(:, h) = point(xb_1, shape_b(:, h), origin)
        end do
        do g = 1, size(shape_a, 2)
            pa_n = point(xa_n, shape_a(:, g), origin)
            pa_1 = point(xa_1, shape_a(:, g), origin)
            do h = 1, size(shape_b, 2)
                rn = pa_n - points_b_n(:, h)
                dr = (pa_1 - points_b_1(:, h)) - rn
                length2 = dot_product(dr, dr)
                tau = 0.0_rk
                if (length2 > 0.0_rk) tau = min(1.0_rk, max(0.0_rk, -dot_product(rn, dr) / length2))
                rn = rn + tau * dr
                if (dot_product(rn, rn) <= wall**2) then
                    clear = .false.
                    return
                end if
            end do
        end do
    end function contact_element_swept_clear

    !> The shape values `shape(degree + 1, m)` of the degree-`degree` Lagrange element
    !> (rs_math_lagrange, nodes ascending) at the m Gauss-Legendre points of the element, and
    !> their weights `weight_ref(m)` on the reference length [0, 1] (summing to 1: the caller
    !> multiplies by the element length). Points ascending. The rules with m <=
    !> max_gauss_points are those of rs_math_quadrature; larger m are computed by Newton's method
    !> on the Legendre polynomial (points and weights to a few ulps). `ok` is false (and the
    !> arrays zero) for an unsupported degree or m < 1. Optional `slope`: the derivatives, for
    !> the centreline's tangent at the points.
    pure subroutine contact_points(degree, m, shape, weight_ref, ok, slope)
        integer, intent(in) :: degree, m
        real(rk), intent(out) :: shape(degree + 1, m), weight_ref(m)
        logical, intent(out) :: ok
        !> The shape functions' derivatives d N_i / d xi (xi in [-1, 1]) at the points.
        real(rk), intent(out), optional :: slope(degree + 1, m)
        real(rk) :: xi(m), w(m), derivatives(degree + 1)
        integer :: g
        shape = 0.0_rk
        weight_ref = 0.0_rk
        ok = m >= 1
        if (.not. ok) return
        if (m <= max_gauss_points) then
            call gauss_legendre(m, xi, w, ok)
        else
            call gauss_legendre_newton(m, xi, w)
        end if
        if (.not. ok) return
        do g = 1, m
            call lagrange_shape(degree, xi(g), shape(:, g), derivatives, ok)
            if (.not. ok) then
                shape = 0.0_rk
                return
            end if
            if (present(slope)) slope(:, g) = derivatives
        end do
        weight_ref = 0.5_rk * w
    end subroutine contact_points

    !> The line-contact law (module header): force per unit length between two parallel
    !> infinite straight centrelines at distance `d` >= 0 in the limit of fine quadrature,
    !> f(d) = (32/15) k d (r_c^2 - d^2)^(5/2) / r_c^4 for d < r_c, 0 beyond (N/m, >= 0,
    !> repulsive).
    pure real(rk) function contact_line_force(params, d) result(force)
        type(contact_params_t), intent(in) :: params
        real(rk), intent(in) :: d
        real(rk) :: rc, s
        rc = params%contact_distance
        force = 0.0_rk
        if (abs(d) >= rc) return
        ! (r_c - d)(r_c + d) has no cancellation near the support boundary.
        s = (rc - abs(d)) * (rc + abs(d))
        force = (32.0_rk / 15.0_rk) * params%stiffness * abs(d) * s**2 * sqrt(s) / rc**4
    end function contact_line_force

    !> The largest line load the law carries, f_max = f(r_c / sqrt(6)) = 0.5521 k r_c^2.
    pure real(rk) function contact_line_peak_force(params) result(force)
        type(contact_params_t), intent(in) :: params
        force = contact_line_force(params, params%contact_distance / sqrt(6.0_rk))
    end function contact_line_peak_force

    !> The penetration delta = r_c - d at which the line law carries `force_per_length`, on its
    !> stable branch 0 < delta < delta_max = (1 - 1/sqrt(6)) r_c where f rises with delta:
    !> safeguarded Newton (bisection whenever a step leaves the bracket), to a few ulps. Returns
    !> 0 for a load <= 0, and r_c (the rods pass through each other) for a load at or above
    !> contact_line_peak_force.
    pure real(rk) function contact_line_penetration(params, force_per_length) result(delta)
        type(contact_params_t), intent(in) :: params
        real(rk), intent(in) :: force_per_length
        real(rk) :: rc, lo, hi, residual, slope, step, d, s
        integer :: iteration
        rc = params%contact_distance
        delta = 0.0_rk
        if (force_per_length <= 0.0_rk .or. rc <= 0.0_rk) return
        lo = 0.0_rk
        hi = rc * (1.0_rk - 1.0_rk / sqrt(6.0_rk))
        if (force_per_length >= line_force_of_penetration(params, hi)) then
            delta = rc
            return
        end if
        ! Start from the small-penetration asymptote (module header).
        delta = (15.0_rk * sqrt(rc) * force_per_length &
            / (128.0_rk * sqrt(2.0_rk) * params%stiffness))**0.4_rk
        if (.not. (delta > lo .and. delta < hi)) delta = 0.5_rk * (lo + hi)
        do iteration = 1, 200
            d = rc - delta
            residual = line_force_of_penetration(params, delta) - force_per_length
            if (residual > 0.0_rk) then
                hi = delta
            else if (residual < 0.0_rk) then
                lo = delta
            else
                return
            end if
            ! df/d delta = -df/dd = (32/15) k s^(3/2) (6 d^2 - r_c^2) / r_c^4, s = r_c^2 - d^2.
            s = delta * (2.0_rk * rc - delta)
            slope = (32.0_rk / 15.0_rk) * params%stiffness * s * sqrt(s) &
                * (6.0_rk * d**2 - rc**2) / rc**4
            step = 0.0_rk
            if (slope > 0.0_rk) step = residual / slope
            if (slope > 0.0_rk .and. delta - step > lo .and. delta - step < hi) then
                delta = delta - step
                if (abs(step) <= 2.0_rk * epsilon(1.0_rk) * delta) return
            else
                delta = 0.5_rk * (lo + hi)
                if (hi - lo <= 2.0_rk * epsilon(1.0_rk) * hi) return
            end if
        end do
    end function contact_line_penetration

    ! The line law as a function of the penetration delta = r_c - d, without the cancellation of
    ! r_c - d for small delta: f = (32/15) k (r_c - delta) s^(5/2) / r_c^4 with
    ! s = delta (2 r_c - delta).
    pure real(rk) function line_force_of_penetration(params, delta) result(force)
        type(contact_params_t), intent(in) :: params
        real(rk), intent(in) :: delta
        real(rk) :: rc, s
        rc = params%contact_distance
        s = delta * (2.0_rk * rc - delta)
        force = (32.0_rk / 15.0_rk) * params%stiffness * (rc - delta) * s**2 * sqrt(s) / rc**4
    end function line_force_of_penetration

    !> The unit tangent of an element's centreline at a point, from the shape functions'
    !> derivatives there (any scale).
    pure function unit_tangent(nodes, slope) result(t)
        real(rk), intent(in) :: nodes(:, :), slope(:)
        real(rk) :: t(3)
        t = matmul(nodes, slope)
        if (norm2(t) > 0.0_rk) t = t / norm2(t)
    end function unit_tangent

    !> The unit chord of an element (first to last node).
    pure function unit_chord(nodes) result(t)
        real(rk), intent(in) :: nodes(:, :)
        real(rk) :: t(3)
        t = nodes(:, size(nodes, 2)) - nodes(:, 1)
        if (norm2(t) > 0.0_rk) t = t / norm2(t)
    end function unit_chord

    ! x - origin = sum_i shape(i) (nodes(:, i) - origin), exact since sum_i shape(i) = 1; in
    ! explicit loops (no array temporaries).
    pure function point(nodes, shape, origin) result(x)
        real(rk), intent(in) :: nodes(:, :), shape(:), origin(3)
        real(rk) :: x(3)
        integer :: i
        x = 0.0_rk
        do i = 1, size(shape)
            x = x + shape(i) * (nodes(:, i) - origin)
        end do
    end function point

    ! A lower bound of the distance between any point of a linear or quadratic element a and
    ! any point of element b: the distance of their chords (first to last node) less their
    ! bulges. A quadratic element is x(xi) = chord(xi) + N_2(xi) b with b = X_2 - (X_1 + X_3)/2
    ! (N_1 + N_2/2 = (1 - xi)/2), and 0 <= N_2 <= 1, so it lies within |b| of its chord; a
    ! linear one is its chord. Reduced by the round-off margin of sphere_gap.
    pure real(rk) function chord_gap(xa, xb, origin) result(gap)
        real(rk), intent(in) :: xa(:, :), xb(:, :), origin(3)
        real(rk) :: bulge_a, bulge_b, scale
        bulge_a = 0.0_rk
        bulge_b = 0.0_rk
        if (size(xa, 2) == 3) bulge_a = norm2(xa(:, 2) - 0.5_rk * (xa(:, 1) + xa(:, 3)))
        if (size(xb, 2) == 3) bulge_b = norm2(xb(:, 2) - 0.5_rk * (xb(:, 1) + xb(:, 3)))
        scale = max(maxval(abs(xa - spread(origin, 2, size(xa, 2)))), &
            maxval(abs(xb - spread(origin, 2, size(xb, 2)))))
        gap = segment_distance(xa(:, 1) - origin, xa(:, size(xa, 2)) - origin, &
            xb(:, 1) - origin, xb(:, size(xb, 2)) - origin) - bulge_a - bulge_b - &
            skip_safety * (scale + bulge_a + bulge_b)
    end function chord_gap

    ! The distance between the segments [p0, p1] and [q0, q1]: the closest points on the two
    ! lines, clamped to the segments, the clamp of one then redone on the other (the standard
    ! construction; degenerate segments are points).
    pure real(rk) function segment_distance(p0, p1, q0, q1) result(distance)
        real(rk), intent(in) :: p0(3), p1(3), q0(3), q1(3)
        real(rk) :: u(3), v(3), w(3), a, b, c, d, e, denominator, s, t
        u = p1 - p0
        v = q1 - q0
        w = p0 - q0
        a = dot_product(u, u)
        b = dot_product(u, v)
        c = dot_product(v, v)
        d = dot_product(u, w)
        e = dot_product(v, w)
        if (a <= tiny(1.0_rk) .and. c <= tiny(1.0_rk)) then
            distance = norm2(w)
            return
        end if
        if (a <= tiny(1.0_rk)) then
            s = 0.0_rk
            t = min(1.0_rk, max(0.0_rk, e / c))
        else if (c <= tiny(1.0_rk)) then
            t = 0.0_rk
            s = min(1.0_rk, max(0.0_rk, -d / a))
        else
            denominator = a * c - b * b
            s = 0.0_rk
            if (denominator > 0.0_rk) s = min(1.0_rk, max(0.0_rk, (b * e - c * d) / denominator))
            t = (b * s + e) / c
            if (t < 0.0_rk) then
                t = 0.0_rk
                s = min(1.0_rk, max(0.0_rk, -d / a))
            else if (t > 1.0_rk) then
                t = 1.0_rk
                s = min(1.0_rk, max(0.0_rk, (b - d) / a))
            end if
        end if
        distance = norm2(w + s * u - t * v)
    end function segment_distance

    ! Lambda = max_g sum_i |N_i(g)|: |x(g) - c| <= Lambda max_i |X_i - c| for any c, because
    ! sum_i N_i(g) = 1.
    pure real(rk) function lebesgue_bound(shape) result(lambda)
        real(rk), intent(in) :: shape(:, :)
        integer :: g
        lambda = 0.0_rk
        do g = 1, size(shape, 2)
            lambda = max(lambda, sum(abs(shape(:, g))))
        end do
    end function lebesgue_bound

    ! A lower bound of the distance between any point of element a and any point of element b,
    ! reduced by a round-off margin relative to the coordinates (taken from `origin`, as the
    ! points are), so that a gap > r_c proves that every computed point distance is >= r_c.
    pure real(rk) function sphere_gap(xa, lambda_a, xb, lambda_b, origin) result(gap)
        real(rk), intent(in) :: xa(:, :), lambda_a, xb(:, :), lambda_b, origin(3)
        real(rk) :: ca(3), cb(3), ra, rb, scale
        integer :: i
        ca = 0.0_rk
        scale = 0.0_rk
        do i = 1, size(xa, 2)
            ca = ca + (xa(:, i) - origin)
            scale = max(scale, lambda_a * maxval(abs(xa(:, i) - origin)))
        end do
        ca = ca / size(xa, 2)
        cb = 0.0_rk
        do i = 1, size(xb, 2)
            cb = cb + (xb(:, i) - origin)
            scale = max(scale, lambda_b * maxval(abs(xb(:, i) - origin)))
        end do
        cb = cb / size(xb, 2)
        ra = 0.0_rk
        do i = 1, size(xa, 2)
            ra = max(ra, norm2(xa(:, i) - origin - ca))
        end do
        rb = 0.0_rk
        do i = 1, size(xb, 2)
            rb = max(rb, norm2(xb(:, i) - origin - cb))
        end do
        ra = lambda_a * ra
        rb = lambda_b * rb
        gap = norm2(ca - cb) - ra - rb - skip_safety * (scale + ra + rb)
    end function sphere_gap

    ! The m-point Gauss-Legendre rule on [-1, 1], points ascending, by Newton's method on the
    ! three-term recurrence of P_m from the asymptotic guesses cos(pi (i - 1/4) / (m + 1/2)).
    pure subroutine gauss_legendre_newton(m, xi, w)
        integer, intent(in) :: m
        real(rk), intent(out) :: xi(m), w(m)
        real(rk) :: x, p0, p1, p2, dp, dx
        integer :: i, j, iteration
        do i = 1, (m + 1) / 2
            x = cos(pi * (real(i, rk) - 0.25_rk) / (real(m, rk) + 0.5_rk))
            do iteration = 1, 100
                p0 = 1.0_rk
                p1 = x
                do j = 2, m
                    p2 = (real(2 * j - 1, rk) * x * p1 - real(j - 1, rk) * p0) / real(j, rk)
                    p0 = p1
                    p1 = p2
                end do
                ! p1 = P_m(x), p0 = P_{m-1}(x).
                dp = real(m, rk) * (x * p1 - p0) / (x**2 - 1.0_rk)
                dx = p1 / dp
                x = x - dx
                if (abs(dx) <= 2.0_rk * epsilon(1.0_rk)) exit
            end do
            ! Weight from P_m' at the converged point.
            p0 = 1.0_rk
            p1 = x
            do j = 2, m
                p2 = (real(2 * j - 1, rk) * x * p1 - real(j - 1, rk) * p0) / real(j, rk)
                p0 = p1
                p1 = p2
            end do
            dp = real(m, rk) * (x * p1 - p0) / (x**2 - 1.0_rk)
            xi(m + 1 - i) = x
            xi(i) = -x
            w(i) = 2.0_rk / ((1.0_rk - x**2) * dp**2)
            w(m + 1 - i) = w(i)
        end do
        if (mod(m, 2) == 1) xi((m + 1) / 2) = 0.0_rk
    end subroutine gauss_legendre_newton

end module rs_contact_element
