#include "rs_macros.h"
!> Rigid, fixed obstacles (&obstacle: the ground, spheres, cylinders; issue 24 item 3) for every
!> formulation with node access: the penalty potential of rs_contact_obstacle integrated along
!> each rod's centreline at the contact points of its elements (Gauss points; the rule of
!> rs_contact_element), its discrete gradient in the momentum rows of the positions (h^p times
!> the generalized force, rod_nodes_t%force_h_power: the h [ ... ] of (M1) in
!> methods/ph_director_3d.md §5.2), as rod-rod contact does. The energy of a
!> step is exact (module header of rs_contact_obstacle), so the obstacles' work, which the
!> system books as external work on each rod, is minus the change of their energy.
!>
!> Every element of every member is evaluated at every step: an obstacle is one surface, and
!> the points away from it cost one support value each (no broad phase is needed). The pattern
!> holds each element's position block, which the rods' own patterns already contain.
module rs_system_obstacle_coupling
    use rs_core_kinds, only: rk
    use rs_core_error, only: error_t, set_error
    use rs_core_strings, only: str
    use rs_model_scene, only: scene_t, unset_int
    use rs_assembly_csr_pattern, only: csr_builder_t, csr_pattern_t
    use rs_contact_obstacle, only: obstacle_params_t, obstacle_params_init, obstacle_energy, &
        obstacle_penetration, obstacle_point_force, obstacle_point_tangent, obstacle_plane, &
        obstacle_sphere, obstacle_cylinder, obstacle_point_friction, &
        obstacle_point_friction_tangent, obstacle_point_damping, obstacle_point_damping_tangent
    use rs_contact_element, only: contact_points
    use rs_model_time_function, only: time_function_t, time_function_from_obstacle
    use rs_system_layout, only: system_layout_t
    use rs_system_coupling, only: coupling_t, coupling_record_t, friction_record_t
    implicit none
    private

    !> Largest number of nodes of an element (cubic).
    integer, parameter :: max_nodes = 4

    !> A member's contact points (Lagrange shape values (nen, m) and weights on [0, 1]), its
    !> obstacles with its contact radius, and the pattern positions of its element blocks.
    type :: obstacle_member_t
        real(rk), allocatable :: shape(:, :), weight(:)
        type(obstacle_params_t), allocatable :: obstacles(:)
        !> map(i, j, e): CSR position of entry (i, j) of element e's position block.
        integer, allocatable :: map(:, :, :)
    end type obstacle_member_t

    !> How an obstacle moves: it is translated by f(t) displacement.
    type :: obstacle_motion_t
        real(rk) :: displacement(3) = 0.0_rk
        type(time_function_t) :: f
    end type obstacle_motion_t

    type, extends(coupling_t), public :: obstacle_coupling_t
        type(obstacle_member_t), allocatable :: members(:)
        type(obstacle_motion_t), allocatable :: motions(:)
        character(len=:), allocatable :: names
        logical :: static = .false.
        !> Load time of the endpoint equilibrium (set_endpoint).
        real(rk) :: t_load = 0.0_rk
        !> Jacobian entries of the element blocks (the pattern builder's first allocation).
        integer :: entries = 0
    contains
        procedure :: add_pattern => obstacle_add_pattern
        procedure :: map_pattern => obstacle_map_pattern
        procedure :: add_residual => obstacle_add_residual
        procedure :: add_jacobian => obstacle_add_jacobian
        procedure :: set_endpoint => obstacle_set_endpoint
        procedure :: add_results => obstacle_add_results
        procedure :: add_edges => obstacle_add_edges
        procedure :: describe => obstacle_describe
        procedure :: pattern_entries => obstacle_pattern_entries
        procedure :: add_dissipation => obstacle_add_dissipation
    end type obstacle_coupling_t

    public :: obstacle_coupling_init

contains

    !> The scene's obstacles for every member, with its contact radius; its contact points:
    !> &contact points_per_element if given, else the element's own Gauss rule with at least
    !> four points (a rod lying on the ground samples its contact line at them).
    subroutine obstacle_coupling_init(this, scene, layout, err)
        type(obstacle_coupling_t), intent(inout) :: this
        type(scene_t), intent(in) :: scene
        type(system_layout_t), intent(in) :: layout
        type(error_t), allocatable, intent(out) :: err
        integer :: m, o, n_points, kind
        logical :: ok
        character(len=:), allocatable :: message
        allocate(this%blocks(0))
        allocate(this%members(size(layout%members)))
        allocate(this%motions(size(scene%obstacles)))
        do o = 1, size(scene%obstacles)
            this%motions(o)%displacement = scene%obstacles(o)%displacement
            call time_function_from_obstacle(scene%obstacles(o), this%motions(o)%f, err)
            RS_RETURN_IF_ERROR(err)
        end do
        this%names = ''
        do o = 1, size(scene%obstacles)
            if (o > 1) this%names = this%names // ', '
            this%names = this%names // '''' // trim(scene%obstacles(o)%name) // ''' (' // &
                trim(scene%obstacles(o)%kind)
            if (any(scene%obstacles(o)%displacement /= 0.0_rk)) this%names = this%names // &
                ', moving'
            this%names = this%names // ')'
        end do
        do m = 1, size(layout%members)
            associate (member => this%members(m), nodes => layout%members(m)%nodes)
                if (nodes%degree + 1 > max_nodes) then
                    message = 'elements of degree ' // str(nodes%degree) // ' (at most ' // &
                        str(max_nodes - 1) // ')'
                    RS_SET_ERROR(err, 'obstacle_coupling_init', message)
                    return
                end if
                n_points = max(nodes%n_gauss, 4)
                if (scene%contact%points_per_element /= unset_int) &
                    n_points = scene%contact%points_per_element
                allocate(member%shape(nodes%degree + 1, n_points), member%weight(n_points))
                call contact_points(nodes%degree, n_points, member%shape, member%weight, ok)
                if (.not. ok) then
                    message = 'no contact points for elements of degree ' // str(nodes%degree)
                    RS_SET_ERROR(err, 'obstacle_coupling_init', message)
                    return
                end if
                this%entries = this%entries + (3 * (nodes%degree + 1))**2 * nodes%n_elements
                allocate(member%obstacles(size(scene%obstacles)))
                do o = 1, size(scene%obstacles)
                    associate (obstacle => scene%obstacles(o))
                        select case (trim(obstacle%kind))
                        case ('sphere')
                            kind = obstacle_sphere
                        case ('cylinder')
                            kind = obstacle_cylinder
                        case default
                            kind = obstacle_plane
                        end select
                        member%obstacles(o) = obstacle_params_init(kind, obstacle%point, &
                            merge(obstacle%normal, 0.0_rk, kind /= obstacle_sphere), &
                            merge(obstacle%radius, 0.0_rk, kind /= obstacle_plane), &
                            obstacle%stiffness, layout%members(m)%contact_radius)
                        member%obstacles(o)%mu = obstacle%mu
                        member%obstacles(o)%slip_velocity = obstacle%slip_velocity
                        member%obstacles(o)%damping = obstacle%damping
                    end associate
                end do
            end associate
        end do
    end subroutine obstacle_coupling_init

    !> Rows (momentum of the positions) and columns (positions) of element e of member m.
    pure subroutine element_indices(layout, m, e, rows, cols, n)
        type(system_layout_t), intent(in) :: layout
        integer, intent(in) :: m, e
        integer, intent(out) :: rows(3 * max_nodes), cols(3 * max_nodes), n
        integer :: a, first
        first = (e - 1) * layout%members(m)%nodes%degree
        n = 3 * (layout%members(m)%nodes%degree + 1)
        do a = 1, layout%members(m)%nodes%degree + 1
            rows(3 * a - 2:3 * a) = layout%momentum_rows(m, first + a, 3)
            cols(3 * a - 2:3 * a) = layout%coordinate_cols(m, first + a, 3)
        end do
    end subroutine element_indices

    !> Positions of element e's nodes of member m in a state (x) or in the unknowns (y).
    pure subroutine element_positions(layout, m, e, x, y, x_e, y_e)
        type(system_layout_t), intent(in) :: layout
        integer, intent(in) :: m, e
        real(rk), intent(in) :: x(:), y(:)
        real(rk), intent(out) :: x_e(:, :), y_e(:, :)
        integer :: a, first
        first = (e - 1) * layout%members(m)%nodes%degree
        do a = 1, size(x_e, 2)
            x_e(:, a) = layout%node_state(m, first + a, x, 3)
            y_e(:, a) = layout%node_unknown(m, first + a, y, 3)
        end do
    end subroutine element_positions

    subroutine obstacle_add_pattern(this, layout, builder)
        class(obstacle_coupling_t), intent(inout) :: this
        type(system_layout_t), intent(in) :: layout
        type(csr_builder_t), intent(inout) :: builder
        integer :: m, e, n, rows(3 * max_nodes), cols(3 * max_nodes)
        do m = 1, size(layout%members)
            do e = 1, layout%members(m)%nodes%n_elements
                call element_indices(layout, m, e, rows, cols, n)
                call builder%add_block(rows(1:n), cols(1:n))
            end do
        end do
    end subroutine obstacle_add_pattern

    subroutine obstacle_map_pattern(this, layout, pattern)
        class(obstacle_coupling_t), intent(inout) :: this
        type(system_layout_t), intent(in) :: layout
        type(csr_pattern_t), intent(in) :: pattern
        integer :: m, e, n, i, j, rows(3 * max_nodes), cols(3 * max_nodes)
        do m = 1, size(layout%members)
            associate (member => this%members(m), nodes => layout%members(m)%nodes)
                if (allocated(member%map)) deallocate(member%map)
                n = 3 * (nodes%degree + 1)
                allocate(member%map(n, n, nodes%n_elements), source=0)
                do e = 1, nodes%n_elements
                    call element_indices(layout, m, e, rows, cols, n)
                    do j = 1, n
                        if (cols(j) <= 0) cycle
                        do i = 1, n
                            if (rows(i) <= 0) cycle
                            member%map(i, j, e) = pattern%position(rows(i), cols(j))
                        end do
                    end do
                end do
            end associate
        end do
    end subroutine obstacle_map_pattern

    subroutine obstacle_add_residual(this, layout, t_n, h, x_n, y, f, all_rows)
        class(obstacle_coupling_t), intent(inout) :: this
        type(system_layout_t), intent(in) :: layout
        real(rk), intent(in) :: t_n, h, x_n(:), y(:)
        real(rk), intent(inout) :: f(:)
        logical, intent(in) :: all_rows
        call assemble(this, layout, t_n, h, x_n, y, all_rows, f=f)
    end subroutine obstacle_add_residual

    subroutine obstacle_add_jacobian(this, layout, pattern, t_n, h, x_n, y, values)
        class(obstacle_coupling_t), intent(inout) :: this
        type(system_layout_t), intent(in) :: layout
        type(csr_pattern_t), intent(in) :: pattern
        real(rk), intent(in) :: t_n, h, x_n(:), y(:)
        real(rk), intent(inout) :: values(:)
        call assemble(this, layout, t_n, h, x_n, y, .false., values=values)
    end subroutine obstacle_add_jacobian

    !> Where each obstacle is at the two ends of the step from t_n by h, as displacements from
    !> its given place: in the endpoint equilibrium both at its load time, in equilibrium steps
    !> both at t_n + h (the coupling acts at X_{n+1} only).
    subroutine step_shifts(this, t_n, h, shift_n, shift_1)
        type(obstacle_coupling_t), intent(in) :: this
        real(rk), intent(in) :: t_n, h
        real(rk), intent(out) :: shift_n(:, :), shift_1(:, :)
        real(rk) :: time_n, time_1
        integer :: o
        time_n = t_n
        time_1 = t_n + h
        if (this%static) then
            time_n = this%t_load
            time_1 = this%t_load
        else if (this%equilibrium_steps) then
            time_n = time_1
        end if
        do o = 1, size(this%motions)
            shift_n(:, o) = this%motions(o)%f%value(time_n) * this%motions(o)%displacement
            shift_1(:, o) = this%motions(o)%f%value(time_1) * this%motions(o)%displacement
        end do
    end subroutine step_shifts

    !> The obstacles' terms: h^p times the discrete gradient of their energy, integrated over
    !> each element at its contact points (in the endpoint solve the gradient at X_{n+1}: both
    !> arguments at X_{n+1}, whose derivative is twice the partial one by symmetry). A moving
    !> obstacle is seen from its own frame: the points are shifted back by its displacement at
    !> each end of the step, which leaves the derivatives in x_1 as they are.
    subroutine assemble(this, layout, t_n, h, x_n, y, all_rows, f, values)
        type(obstacle_coupling_t), intent(in) :: this
        type(system_layout_t), intent(in) :: layout
        real(rk), intent(in) :: t_n, h, x_n(:), y(:)
        logical, intent(in) :: all_rows
        real(rk), intent(inout), optional :: f(:), values(:)
        real(rk) :: x_e(3, max_nodes), y_e(3, max_nodes), p_n(3), p_1(3), force(3), t3(3, 3)
        real(rk) :: friction(3), t3_friction(3, 3), damping(3), d_n
        real(rk) :: shift_n(3, size(this%motions)), shift_1(3, size(this%motions))
        real(rk) :: r(3, max_nodes), tangent(3 * max_nodes, 3 * max_nodes), w, scale, h_m
        integer :: m, e, g, o, a, b, nen, n, i, j, p, rows(3 * max_nodes), cols(3 * max_nodes)
        logical :: touching, any_touching, static
        static = this%static .or. this%equilibrium_steps
        scale = merge(2.0_rk, 1.0_rk, static)
        call step_shifts(this, t_n, h, shift_n, shift_1)
        do m = 1, size(layout%members)
            if (.not. (all_rows .or. layout%owns_member(m))) cycle
            associate (member => this%members(m), nodes => layout%members(m)%nodes)
                nen = nodes%degree + 1
                h_m = layout%force_scale(m, h)
                do e = 1, nodes%n_elements
                    call element_positions(layout, m, e, x_n, y, x_e(:, 1:nen), y_e(:, 1:nen))
                    if (static) x_e(:, 1:nen) = y_e(:, 1:nen)
                    r(:, 1:nen) = 0.0_rk
                    if (present(values)) tangent(1:3 * nen, 1:3 * nen) = 0.0_rk
                    any_touching = .false.
                    do g = 1, size(member%weight)
                        p_n = matmul(x_e(:, 1:nen), member%shape(:, g))
                        p_1 = matmul(y_e(:, 1:nen), member%shape(:, g))
                        w = member%weight(g) * nodes%element_length(e)
                        do o = 1, size(member%obstacles)
                            call obstacle_point_force(member%obstacles(o), p_n - shift_n(:, o), &
                                p_1 - shift_1(:, o), force, touching)
                            if (.not. touching) cycle
                            any_touching = .true.
                            ! Friction and damping act on the motion of a time step (none in
                            ! equilibrium).
                            friction = 0.0_rk
                            if (.not. static) then
                                call obstacle_point_friction(member%obstacles(o), &
                                    p_n - shift_n(:, o), p_1 - shift_1(:, o), h, friction)
                                call obstacle_point_damping(member%obstacles(o), &
                                    p_n - shift_n(:, o), p_1 - shift_1(:, o), h, damping, d_n)
                                friction = friction + damping
                            end if
                            do a = 1, nen
                                r(:, a) = r(:, a) + (w * member%shape(a, g)) * (force + friction)
                            end do
                            if (.not. present(values)) cycle
                            call obstacle_point_tangent(member%obstacles(o), p_n - shift_n(:, o), &
                                p_1 - shift_1(:, o), t3)
                            if (.not. static .and. member%obstacles(o)%mu > 0.0_rk) then
                                call obstacle_point_friction_tangent(member%obstacles(o), &
                                    p_n - shift_n(:, o), p_1 - shift_1(:, o), h, t3_friction)
                                t3 = t3 + t3_friction
                            end if
                            if (.not. static .and. member%obstacles(o)%damping > 0.0_rk) then
                                call obstacle_point_damping_tangent(member%obstacles(o), &
                                    p_n - shift_n(:, o), p_1 - shift_1(:, o), h, t3_friction)
                                t3 = t3 + t3_friction
                            end if
                            do b = 1, nen
                                do a = 1, nen
                                    tangent(3 * a - 2:3 * a, 3 * b - 2:3 * b) = &
                                        tangent(3 * a - 2:3 * a, 3 * b - 2:3 * b) + &
                                        (w * member%shape(a, g) * member%shape(b, g)) * t3
                                end do
                            end do
                        end do
                    end do
                    if (.not. any_touching) cycle
                    call element_indices(layout, m, e, rows, cols, n)
                    if (present(f)) then
                        do a = 1, nen
                            do i = 1, 3
                                p = rows(3 * (a - 1) + i)
                                if (p <= 0) cycle
                                if (all_rows .or. layout%owns_row(p)) f(p) = f(p) + h_m * r(i, a)
                            end do
                        end do
                    end if
                    if (present(values)) then
                        do j = 1, n
                            if (cols(j) <= 0) cycle
                            do i = 1, n
                                if (rows(i) <= 0) cycle
                                p = member%map(i, j, e)
                                values(p) = values(p) + scale * h_m * tangent(i, j)
                            end do
                        end do
                    end if
                end do
            end associate
        end do
    end subroutine assemble

    subroutine obstacle_set_endpoint(this, on, t_load)
        class(obstacle_coupling_t), intent(inout) :: this
        logical, intent(in) :: on
        real(rk), intent(in) :: t_load
        this%static = on
        this%t_load = t_load
    end subroutine obstacle_set_endpoint

    !> Each member's obstacle energy, the force of the obstacles on it and its deepest
    !> penetration at the state x (at the contact points and the nodes: an element's end is
    !> no contact point, and a rod's free end dips below its nearest one), added to its
    !> contact records.
    subroutine obstacle_add_results(this, layout, t, x, y, records)
        class(obstacle_coupling_t), intent(inout) :: this
        type(system_layout_t), intent(in) :: layout
        real(rk), intent(in) :: t, x(:), y(:)
        type(coupling_record_t), intent(inout) :: records(:)
        real(rk) :: x_e(3, max_nodes), y_e(3, max_nodes), point(3), force(3), w
        real(rk) :: shift(3, size(this%motions))
        integer :: m, e, g, o, nen
        logical :: touching
        do o = 1, size(this%motions)
            shift(:, o) = this%motions(o)%f%value(t) * this%motions(o)%displacement
        end do
        do m = 1, size(layout%members)
            associate (member => this%members(m), nodes => layout%members(m)%nodes, &
                    record => records(m))
                nen = nodes%degree + 1
                do e = 1, nodes%n_elements
                    call element_positions(layout, m, e, x, y, x_e(:, 1:nen), y_e(:, 1:nen))
                    do g = 1, size(member%weight)
                        w = member%weight(g) * nodes%element_length(e)
                        do o = 1, size(member%obstacles)
                            point = matmul(x_e(:, 1:nen), member%shape(:, g)) - shift(:, o)
                            call obstacle_point_force(member%obstacles(o), point, point, force, &
                                touching)
                            if (.not. touching) cycle
                            record%contact_energy = record%contact_energy + &
                                w * obstacle_energy(member%obstacles(o), point)
                            record%contact_force = record%contact_force - w * force
                            record%penetration = max(record%penetration, &
                                obstacle_penetration(member%obstacles(o), point))
                        end do
                    end do
                    do g = 1, nen
                        do o = 1, size(member%obstacles)
                            record%penetration = max(record%penetration, &
                                obstacle_penetration(member%obstacles(o), x_e(:, g) - shift(:, o)))
                        end do
                    end do
                end do
            end associate
        end do
    end subroutine obstacle_add_results

    !> Each member's friction dissipation D_T >= 0 of the accepted step from x_n to the
    !> unknowns y (rs_contact_obstacle), integrated as the forces are, the friction force on
    !> it (-f_T integrated) and the largest slip speed of its contact points.
    subroutine obstacle_add_dissipation(this, layout, t_n, h, x_n, y, dissipated, friction)
        class(obstacle_coupling_t), intent(in) :: this
        type(system_layout_t), intent(in) :: layout
        real(rk), intent(in) :: t_n, h, x_n(:), y(:)
        real(rk), intent(inout) :: dissipated(:)
        type(friction_record_t), intent(inout) :: friction(:)
        real(rk) :: x_e(3, max_nodes), y_e(3, max_nodes), p_n(3), p_1(3), w, f_t(3), d_n, d_t
        real(rk) :: slip
        real(rk) :: shift_n(3, size(this%motions)), shift_1(3, size(this%motions))
        integer :: m, e, g, o, nen
        if (this%static .or. this%equilibrium_steps) return
        call step_shifts(this, t_n, h, shift_n, shift_1)
        do m = 1, size(layout%members)
            associate (member => this%members(m), nodes => layout%members(m)%nodes)
                if (all(member%obstacles%mu == 0.0_rk .and. member%obstacles%damping == 0.0_rk)) &
                    cycle
                nen = nodes%degree + 1
                do e = 1, nodes%n_elements
                    call element_positions(layout, m, e, x_n, y, x_e(:, 1:nen), y_e(:, 1:nen))
                    do g = 1, size(member%weight)
                        p_n = matmul(x_e(:, 1:nen), member%shape(:, g))
                        p_1 = matmul(y_e(:, 1:nen), member%shape(:, g))
                        w = member%weight(g) * nodes%element_length(e)
                        do o = 1, size(member%obstacles)
                            associate (params => member%obstacles(o), a => p_n - shift_n(:, o), &
                                    b => p_1 - shift_1(:, o))
                                if (params%damping > 0.0_rk) then
                                    call obstacle_point_damping(params, a, b, h, f_t, d_n)
                                    dissipated(m) = dissipated(m) + w * d_n
                                end if
                                if (params%mu == 0.0_rk) cycle
                                call obstacle_point_friction(params, a, b, h, f_t, d_t, slip)
                                dissipated(m) = dissipated(m) + w * d_t
                                if (all(f_t == 0.0_rk)) cycle
                                friction(m)%force = friction(m)%force - w * f_t
                                friction(m)%slip_speed = max(friction(m)%slip_speed, slip / h)
                            end associate
                        end do
                    end do
                end do
            end associate
        end do
    end subroutine obstacle_add_dissipation

    !> Obstacles couple no members to each other.
    subroutine obstacle_add_edges(this, edge)
        class(obstacle_coupling_t), intent(in) :: this
        logical, intent(inout) :: edge(:, :)
    end subroutine obstacle_add_edges

    pure integer function obstacle_pattern_entries(this)
        class(obstacle_coupling_t), intent(in) :: this
        obstacle_pattern_entries = this%entries
    end function obstacle_pattern_entries

    function obstacle_describe(this) result(text)
        class(obstacle_coupling_t), intent(in) :: this
        character(len=:), allocatable :: text
        text = 'obstacles ' // this%names
    end function obstacle_describe

end module rs_system_obstacle_coupling
