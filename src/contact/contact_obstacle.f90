!> Penalty potential of a rod against a rigid, fixed obstacle and its energy-consistent
!> midpoint force (issue 24 item 3; docs/theory/bundles.md, "Obstacles"). Pure kernels on plain
!> arrays, as rs_contact_potential, whose construction this follows.
!>
!> The support function. A centreline point x of a rod with contact radius r touches the
!> obstacle where s(x) > 0, with s polynomial in x:
!>
!>     plane (point p, outward unit normal n):    s = r - n . (x - p)                  (linear)
!>     sphere (centre p, radius R):               s = (R + r)^2 - |x - p|^2            (quadratic)
!>     cylinder (axis p + t a, radius R):         s = (R + r)^2 - |P (x - p)|^2,  P = I - a a^T
!>
!> and carries the energy psi(s) = c s^3 per length (0 for s <= 0), c = k / 3 for the plane
!> and k / (24 (R + r)^3) for the sphere and the cylinder, so that a point that penetrates by
!> delta (its distance from the surface below r) carries k delta^3 / 3 (exactly for the plane;
!> to first order in delta / (R + r) for the others, where s = 2 (R + r) delta - delta^2) and
!> is pushed out with the force k delta^2 per length. For the plane s grows without bound
!> behind the surface, so no step can carry a point through it; a sphere's or a cylinder's s
!> is largest at the centre (a point pushed that deep has failed the contact anyway: the
!> stated bound is delta << R).
!>
!> The midpoint step. With s_n = s(x_n) and s_1 = s(x_1) the discrete gradient of psi(s(x)) is
!>
!>     f = psi_bar(s_n, s_1) grad_bar,   psi_bar = [psi(s_1) - psi(s_n)] / (s_1 - s_n),
!>     grad_bar = -n (plane),   -2 P (x_mid - p) (sphere: P = I; cylinder),
!>
!> for which grad_bar . (x_1 - x_n) = s_1 - s_n exactly (s is linear or quadratic: the
!> "directionality" of a quadratic at the midpoint, methods/ph_director_3d.md §5.3 item 1,
!> Remark 4.2), hence f . (x_1 - x_n) = psi(s_1) - psi(s_n) for any step: the energy is exact. psi_bar of the cubic
!> is evaluated as in rs_contact_potential (the terminating Taylor form when both s are in the
!> support, the quotient without cancellation when one is), so no step-size switch is needed.
!> f is a gradient of the energy (it enters the momentum residual as the internal forces do);
!> the physical force on the rod is -f.
!>
!> Friction (regularized Coulomb, issue 24 item 2). With the normal force per length
!> f_N = |f| = psi_bar |grad_bar|, the unit outward normal at the midpoint n = -grad_bar /
!> |grad_bar|, the step's slip u = (I - n n^T)(x_1 - x_n) and eta = v_s h (v_s the slip
!> velocity of the regularization, h the step), the friction term is
!>
!>     f_T = mu f_N u / sqrt(|u|^2 + eta^2),
!>
!> whose physical force -f_T opposes the slip with at most mu f_N (Coulomb's bound, reached
!> for |u| >> eta; below v_s the law is viscous, a smooth stick branch). Its work on the step is
!> -f_T . (x_1 - x_n) = -D_T with D_T = mu f_N |u|^2 / sqrt(|u|^2 + eta^2) >= 0 (u is the
!> tangential part of the displacement): the dissipation is non-negative by construction, as
!> the discrete balance H_{n+1} - H_n = W_n - D_n with D_n >= 0 of methods/ph_director_3d.md
!> §5.3 item 1 asks, and obstacle_point_friction returns it for the books.
!>
!> Normal damping (Hunt and Crossley, issue 24: a rope dropped on the ground comes to rest).
!> With alpha (s/m, &obstacle damping), s_bar = (max(s_n, 0) + max(s_1, 0)) / 2 and the
!> constant scale = 1 / |grad s|^2 at the surface (1 for the plane, 1 / (2 (R + r))^2 for the
!> sphere and the cylinder), the term
!>
!>     f_D = alpha scale psi'(s_bar) ((s_1 - s_n) / h) grad_bar
!>
!> is the force k delta^2 alpha (d delta / dt) of Hunt and Crossley's law at the penetration
!> delta (to first order in delta / (R + r) for the curved obstacles): it opposes the rate of
!> penetration in proportion to the elastic force, so it vanishes where the contact starts and
!> ends. Its work on the step is -D_N with D_N = alpha scale psi'(s_bar) (s_1 - s_n)^2 / h >= 0
!> (grad_bar . (x_1 - x_n) = s_1 - s_n exactly): dissipative by construction, the D_n >= 0 of the
!> discrete balance of methods/ph_director_3d.md §5.3 item 1, booked with the friction's.
module rs_contact_obstacle
    use rs_core_kinds, only: rk
    implicit none
    private

    integer, parameter, public :: obstacle_plane = 1, obstacle_sphere = 2, obstacle_cylinder = 3

    !> One obstacle as the kernels see it, with the contact radius of the rod that touches it.
    type, public :: obstacle_params_t
        integer :: kind = obstacle_plane
        real(rk) :: point(3) = 0.0_rk
        !> Unit outward normal (plane) or axis (cylinder).
        real(rk) :: normal(3) = [0.0_rk, 0.0_rk, 1.0_rk]
        real(rk) :: radius = 0.0_rk
        !> Contact radius of the rod.
        real(rk) :: rod_radius = 0.0_rk
        !> c of psi = c s^3.
        real(rk) :: c = 0.0_rk
        !> Friction coefficient and slip velocity of the regularization (m/s).
        real(rk) :: mu = 0.0_rk
        real(rk) :: slip_velocity = 1.0_rk
        !> Normal damping (Hunt and Crossley): alpha (s/m) and the constant 1 / |grad s|^2 at
        !> the surface (plane 1, sphere and cylinder 1 / (2 (R + r))^2).
        real(rk) :: damping = 0.0_rk
        real(rk) :: damping_scale = 1.0_rk
    end type obstacle_params_t

    public :: obstacle_params_init, obstacle_support, obstacle_energy, obstacle_penetration
    public :: obstacle_point_force, obstacle_point_tangent
    public :: obstacle_point_friction, obstacle_point_friction_tangent
    public :: obstacle_point_damping, obstacle_point_damping_tangent

contains

    !> The parameters of obstacle `kind` for a rod of contact radius `rod_radius` (k: N/m^3).
    pure function obstacle_params_init(kind, point, normal, radius, stiffness, rod_radius) &
            result(params)
        integer, intent(in) :: kind
        real(rk), intent(in) :: point(3), normal(3), radius, stiffness, rod_radius
        type(obstacle_params_t) :: params
        params%kind = kind
        params%point = point
        params%normal = normal
        params%radius = radius
        params%rod_radius = rod_radius
        if (kind == obstacle_plane) then
            params%c = stiffness / 3.0_rk
        else
            params%c = stiffness / (24.0_rk * (radius + rod_radius)**3)
            params%damping_scale = 1.0_rk / (2.0_rk * (radius + rod_radius))**2
        end if
    end function obstacle_params_init

    !> P (x - p): the part of x - p that s depends on (all of it for a sphere).
    pure function projected(params, x) result(v)
        type(obstacle_params_t), intent(in) :: params
        real(rk), intent(in) :: x(3)
        real(rk) :: v(3)
        v = x - params%point
        if (params%kind == obstacle_cylinder) v = v - dot_product(params%normal, v) * params%normal
    end function projected

    !> s(x) (module header).
    pure real(rk) function obstacle_support(params, x) result(s)
        type(obstacle_params_t), intent(in) :: params
        real(rk), intent(in) :: x(3)
        real(rk) :: v(3)
        if (params%kind == obstacle_plane) then
            s = params%rod_radius - dot_product(params%normal, x - params%point)
        else
            v = projected(params, x)
            s = (params%radius + params%rod_radius)**2 - dot_product(v, v)
        end if
    end function obstacle_support

    !> psi(s(x)), the energy per length at x.
    pure real(rk) function obstacle_energy(params, x) result(psi)
        type(obstacle_params_t), intent(in) :: params
        real(rk), intent(in) :: x(3)
        real(rk) :: s
        s = obstacle_support(params, x)
        psi = 0.0_rk
        if (s > 0.0_rk) psi = params%c * s**3
    end function obstacle_energy

    !> How far x lies inside the surface grown by the rod's radius (0 outside), m.
    pure real(rk) function obstacle_penetration(params, x) result(delta)
        type(obstacle_params_t), intent(in) :: params
        real(rk), intent(in) :: x(3)
        real(rk) :: v(3)
        if (params%kind == obstacle_plane) then
            delta = max(0.0_rk, obstacle_support(params, x))
        else
            v = projected(params, x)
            delta = max(0.0_rk, params%radius + params%rod_radius - norm2(v))
        end if
    end function obstacle_penetration

    !> psi_bar(s_n, s_1) and its derivative with respect to s_1 (module header).
    pure subroutine divided_difference(c, s_n, s_1, psi_bar, dpsi_bar)
        real(rk), intent(in) :: c, s_n, s_1
        real(rk), intent(out) :: psi_bar, dpsi_bar
        if (s_n > 0.0_rk .and. s_1 > 0.0_rk) then
            psi_bar = c * (s_n * s_n + s_n * s_1 + s_1 * s_1)
            dpsi_bar = c * (s_n + 2.0_rk * s_1)
        else if (s_1 > 0.0_rk) then
            psi_bar = c * s_1**3 / (s_1 - s_n)
            dpsi_bar = c * s_1**2 * (2.0_rk * s_1 - 3.0_rk * s_n) / (s_1 - s_n)**2
        else if (s_n > 0.0_rk) then
            psi_bar = c * s_n**3 / (s_n - s_1)
            dpsi_bar = c * s_n**3 / (s_n - s_1)**2
        else
            psi_bar = 0.0_rk
            dpsi_bar = 0.0_rk
        end if
    end subroutine divided_difference

    !> grad_bar (module header) at the midpoint of x_n and x_1.
    pure function midpoint_gradient(params, x_n, x_1) result(g)
        type(obstacle_params_t), intent(in) :: params
        real(rk), intent(in) :: x_n(3), x_1(3)
        real(rk) :: g(3)
        if (params%kind == obstacle_plane) then
            g = -params%normal
        else
            g = -2.0_rk * projected(params, 0.5_rk * (x_n + x_1))
        end if
    end function midpoint_gradient

    !> The discrete gradient f of the energy per length at a point moving from x_n to x_1
    !> (zero when s <= 0 at both ends); `touching` when it is not zero.
    pure subroutine obstacle_point_force(params, x_n, x_1, f, touching)
        type(obstacle_params_t), intent(in) :: params
        real(rk), intent(in) :: x_n(3), x_1(3)
        real(rk), intent(out) :: f(3)
        logical, intent(out) :: touching
        real(rk) :: s_n, s_1, psi_bar, dpsi_bar
        s_n = obstacle_support(params, x_n)
        s_1 = obstacle_support(params, x_1)
        touching = s_n > 0.0_rk .or. s_1 > 0.0_rk
        f = 0.0_rk
        if (.not. touching) return
        call divided_difference(params%c, s_n, s_1, psi_bar, dpsi_bar)
        f = psi_bar * midpoint_gradient(params, x_n, x_1)
    end subroutine obstacle_point_force

    !> d f / d x_1 (3 x 3) of obstacle_point_force.
    pure subroutine obstacle_point_tangent(params, x_n, x_1, tangent)
        type(obstacle_params_t), intent(in) :: params
        real(rk), intent(in) :: x_n(3), x_1(3)
        real(rk), intent(out) :: tangent(3, 3)
        real(rk) :: s_n, s_1, psi_bar, dpsi_bar
        tangent = 0.0_rk
        s_n = obstacle_support(params, x_n)
        s_1 = obstacle_support(params, x_1)
        if (s_n <= 0.0_rk .and. s_1 <= 0.0_rk) return
        call divided_difference(params%c, s_n, s_1, psi_bar, dpsi_bar)
        call gradient_term_tangent(params, x_n, x_1, dpsi_bar, psi_bar, tangent)
    end subroutine obstacle_point_tangent

    !> grad s at x: -n (plane), -2 P (x - p) (sphere, cylinder).
    pure function support_gradient(params, x) result(g)
        type(obstacle_params_t), intent(in) :: params
        real(rk), intent(in) :: x(3)
        real(rk) :: g(3)
        if (params%kind == obstacle_plane) then
            g = -params%normal
        else
            g = -2.0_rk * projected(params, x)
        end if
    end function support_gradient

    !> d/dx_1 of a term a grad_bar whose factor a changes with s_1 at the rate `along`:
    !> along grad_bar (grad s(x_1))^T + `across` d grad_bar / d x_1, with `across` = a and
    !> d grad_bar / d x_1 = -P on a sphere or a cylinder (the midpoint moves by half of x_1),
    !> 0 on the plane.
    pure subroutine gradient_term_tangent(params, x_n, x_1, along, across, tangent)
        type(obstacle_params_t), intent(in) :: params
        real(rk), intent(in) :: x_n(3), x_1(3), along, across
        real(rk), intent(out) :: tangent(3, 3)
        real(rk) :: g(3), grad_1(3)
        integer :: i
        g = midpoint_gradient(params, x_n, x_1)
        grad_1 = support_gradient(params, x_1)
        do i = 1, 3
            tangent(:, i) = along * g * grad_1(i)
        end do
        if (params%kind == obstacle_plane) return
        do i = 1, 3
            tangent(i, i) = tangent(i, i) - across
        end do
        if (params%kind == obstacle_cylinder) then
            do i = 1, 3
                tangent(:, i) = tangent(:, i) + across * params%normal * params%normal(i)
            end do
        end if
    end subroutine gradient_term_tangent

    !> The normal force per length f_N, the unit outward normal n at the midpoint, and the
    !> slip u of a step (module header); f_N = 0 where the point does not touch.
    pure subroutine slip_of_step(params, x_n, x_1, f_normal, normal, slip)
        type(obstacle_params_t), intent(in) :: params
        real(rk), intent(in) :: x_n(3), x_1(3)
        real(rk), intent(out) :: f_normal, normal(3), slip(3)
        real(rk) :: f(3), g(3), step(3)
        logical :: touching
        call obstacle_point_force(params, x_n, x_1, f, touching)
        g = midpoint_gradient(params, x_n, x_1)
        f_normal = norm2(f)
        normal = 0.0_rk
        slip = 0.0_rk
        if (.not. touching .or. norm2(g) == 0.0_rk) then
            f_normal = 0.0_rk
            return
        end if
        normal = -g / norm2(g)
        step = x_1 - x_n
        slip = step - dot_product(normal, step) * normal
    end subroutine slip_of_step

    !> mu f_N / sqrt(|u|^2 + eta^2) and the slip u of a step of length h (the factor 0 without
    !> friction or contact): f_T = factor u, D_T = factor |u|^2.
    pure subroutine friction_factor(params, x_n, x_1, h, factor, slip)
        type(obstacle_params_t), intent(in) :: params
        real(rk), intent(in) :: x_n(3), x_1(3), h
        real(rk), intent(out) :: factor, slip(3)
        real(rk) :: f_normal, normal(3), eta
        factor = 0.0_rk
        slip = 0.0_rk
        if (params%mu == 0.0_rk) return
        call slip_of_step(params, x_n, x_1, f_normal, normal, slip)
        eta = params%slip_velocity * h
        if (f_normal > 0.0_rk) factor = params%mu * f_normal / &
            sqrt(dot_product(slip, slip) + eta * eta)
    end subroutine friction_factor

    !> The friction term f_T of a step of length h (module header; zero without friction or
    !> contact); optional: its dissipation per length D_T = f_T . (x_1 - x_n) = factor |u|^2
    !> >= 0 and the slip |u|, from the same evaluation.
    pure subroutine obstacle_point_friction(params, x_n, x_1, h, f, dissipation, slip_length)
        type(obstacle_params_t), intent(in) :: params
        real(rk), intent(in) :: x_n(3), x_1(3), h
        real(rk), intent(out) :: f(3)
        real(rk), intent(out), optional :: dissipation, slip_length
        real(rk) :: factor, slip(3)
        call friction_factor(params, x_n, x_1, h, factor, slip)
        f = factor * slip
        if (present(dissipation)) dissipation = factor * dot_product(slip, slip)
        if (present(slip_length)) slip_length = norm2(slip)
    end subroutine obstacle_point_friction

    !> The normal damping term of a step of length h (module header, Normal damping) and its
    !> dissipation per length D_N = f_D . (x_1 - x_n) >= 0; zero without damping or contact.
    pure subroutine obstacle_point_damping(params, x_n, x_1, h, f, dissipation)
        type(obstacle_params_t), intent(in) :: params
        real(rk), intent(in) :: x_n(3), x_1(3), h
        real(rk), intent(out) :: f(3), dissipation
        real(rk) :: s_n, s_1, factor
        f = 0.0_rk
        dissipation = 0.0_rk
        if (params%damping == 0.0_rk) return
        s_n = obstacle_support(params, x_n)
        s_1 = obstacle_support(params, x_1)
        if (s_n <= 0.0_rk .and. s_1 <= 0.0_rk) return
        factor = damping_factor(params, s_n, s_1, h)
        f = (factor * (s_1 - s_n)) * midpoint_gradient(params, x_n, x_1)
        dissipation = factor * (s_1 - s_n)**2
    end subroutine obstacle_point_damping

    !> alpha scale psi'(s_bar) / h with s_bar the mean of max(s, 0) at the two ends.
    pure real(rk) function damping_factor(params, s_n, s_1, h) result(factor)
        type(obstacle_params_t), intent(in) :: params
        real(rk), intent(in) :: s_n, s_1, h
        real(rk) :: s_bar
        s_bar = 0.5_rk * (max(s_n, 0.0_rk) + max(s_1, 0.0_rk))
        factor = params%damping * params%damping_scale * 3.0_rk * params%c * s_bar**2 / h
    end function damping_factor

    !> d f_D / d x_1 (3 x 3) of obstacle_point_damping.
    pure subroutine obstacle_point_damping_tangent(params, x_n, x_1, h, tangent)
        type(obstacle_params_t), intent(in) :: params
        real(rk), intent(in) :: x_n(3), x_1(3), h
        real(rk), intent(out) :: tangent(3, 3)
        real(rk) :: s_n, s_1, s_bar, factor, d_factor
        tangent = 0.0_rk
        if (params%damping == 0.0_rk) return
        s_n = obstacle_support(params, x_n)
        s_1 = obstacle_support(params, x_1)
        if (s_n <= 0.0_rk .and. s_1 <= 0.0_rk) return
        factor = damping_factor(params, s_n, s_1, h)
        ! d factor / d s_1 (s_bar moves by half of s_1 where s_1 > 0).
        s_bar = 0.5_rk * (max(s_n, 0.0_rk) + max(s_1, 0.0_rk))
        d_factor = 0.0_rk
        if (s_1 > 0.0_rk) d_factor = params%damping * params%damping_scale * 3.0_rk * &
            params%c * s_bar / h
        ! f_D = factor (s_1 - s_n) grad_bar.
        call gradient_term_tangent(params, x_n, x_1, d_factor * (s_1 - s_n) + factor, &
            factor * (s_1 - s_n), tangent)
    end subroutine obstacle_point_damping_tangent

    !> d f_T / d x_1 (3 x 3) of obstacle_point_friction: through f_N, the normal (sphere,
    !> cylinder: it turns with the midpoint) and the slip.
    pure subroutine obstacle_point_friction_tangent(params, x_n, x_1, h, tangent)
        type(obstacle_params_t), intent(in) :: params
        real(rk), intent(in) :: x_n(3), x_1(3), h
        real(rk), intent(out) :: tangent(3, 3)
        real(rk) :: f_normal, normal(3), slip(3), step(3), eta, root, direction(3)
        real(rk) :: s_n, s_1, psi_bar, dpsi_bar, grad_1(3), q(3), length
        real(rk) :: d_f_normal(3), d_normal(3, 3), d_slip(3, 3), d_direction(3, 3), projector(3, 3)
        integer :: i
        tangent = 0.0_rk
        if (params%mu == 0.0_rk) return
        call slip_of_step(params, x_n, x_1, f_normal, normal, slip)
        if (f_normal == 0.0_rk) return
        s_n = obstacle_support(params, x_n)
        s_1 = obstacle_support(params, x_1)
        call divided_difference(params%c, s_n, s_1, psi_bar, dpsi_bar)
        step = x_1 - x_n
        eta = params%slip_velocity * h
        root = sqrt(dot_product(slip, slip) + eta * eta)
        direction = slip / root
        ! P: the part of x - p that s depends on (plane: the normal only, which is constant).
        projector = 0.0_rk
        do i = 1, 3
            projector(i, i) = 1.0_rk
        end do
        if (params%kind == obstacle_plane) then
            grad_1 = -params%normal
            ! f_N = psi_bar (|grad_bar| = 1); the normal does not turn.
            d_f_normal = dpsi_bar * grad_1
            d_normal = 0.0_rk
        else
            if (params%kind == obstacle_cylinder) then
                do i = 1, 3
                    projector(:, i) = projector(:, i) - params%normal * params%normal(i)
                end do
            end if
            grad_1 = support_gradient(params, x_1)
            q = projected(params, 0.5_rk * (x_n + x_1))
            length = norm2(q)
            ! f_N = 2 psi_bar |q|, d|q| / d x_1 = n^T P / 2; n = q / |q| turns by
            ! (I - n n^T) P / (2 |q|).
            d_f_normal = 2.0_rk * length * dpsi_bar * grad_1 + psi_bar * matmul(normal, projector)
            do i = 1, 3
                d_normal(:, i) = (projector(:, i) - normal * dot_product(normal, projector(:, i))) / &
                    (2.0_rk * length)
            end do
        end if
        ! u = step - n (n . step): du = I - n n^T - (n . step) dn - n (step^T dn).
        do i = 1, 3
            d_slip(:, i) = -normal * normal(i) - dot_product(normal, step) * d_normal(:, i) - &
                normal * dot_product(step, d_normal(:, i))
            d_slip(i, i) = d_slip(i, i) + 1.0_rk
        end do
        ! d (u / root) = (I - direction direction^T) du / root.
        do i = 1, 3
            d_direction(:, i) = (d_slip(:, i) - direction * dot_product(direction, d_slip(:, i))) / &
                root
        end do
        do i = 1, 3
            tangent(:, i) = params%mu * (direction * d_f_normal(i) + f_normal * d_direction(:, i))
        end do
    end subroutine obstacle_point_friction_tangent

end module rs_contact_obstacle
