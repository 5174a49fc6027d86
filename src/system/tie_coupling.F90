#include "rs_macros.h"
!> Ties (issue 10, issue 22; DESIGN.md §5; docs/theory/bundles.md): joints between two rod ends
!> (&joint: rigid, spherical, revolute) and rod ends tied to a rigid end plate (&plate), each a
!> few holonomic constraint rows g(z) = 0 on the coordinates z = [q_a; q_b] of the tied nodes
!> with their multipliers lambda (a saddle point). The rows are the formulation's own
!> (rod_formulation_t%new_tie: written for its coordinates); this module is what every
!> formulation shares (methods/ph_director_3d.md §5.1, §5.2, §5.6; DESIGN.md §3):
!> - momentum rows of the two nodes: + h G(z_t)^T lambda, z_t = z_n + theta (z_{n+1} - z_n)
!>   (theta = 1/2, 1 in the endpoint equilibrium), G evaluated with the plate's pose at the
!>   load time of the step;
!> - the tie's rows: g(z_{n+1}) = 0 with the pose at the end of the step, imposed at the
!>   endpoint like the nodal constraint rows, so a tie holds to round-off;
!> - Newton blocks: theta h sum_k lambda_k d^2 g_k/dz^2, h G(z_t)^T and G(z_{n+1}).
!> A tie's multipliers are an unknown block owned by its rod a (the plate's rod), so that they
!> follow that rod to its rank.
module rs_system_tie_coupling
    use rs_core_kinds, only: rk
    use rs_core_error, only: error_t, set_error
    use rs_core_strings, only: str
    use rs_model_scene, only: scene_t, unset_real, plate_input_t
    use rs_model_time_function, only: time_function_t, time_function_from_plate
    use rs_assembly_csr_pattern, only: csr_builder_t, csr_pattern_t
    use rs_formulations_formulation, only: rod_formulation_t, node_tie_t, max_node_coordinates, &
        rod_nodes_t
    use rs_math_so3, only: exp_so3, hat
    use rs_system_layout, only: system_layout_t, coupling_block_t
    use rs_system_coupling, only: coupling_t, coupling_record_t
    implicit none
    private

    !> Size of z = [q_a; q_b] at most.
    integer, parameter :: max_z = 2 * max_node_coordinates

    !> A joint between two rod ends or a rod end tied to a plate.
    type :: tie_entry_t
        character(len=16) :: kind = ''
        !> The rows with the pose of the step's load time and of its end (the same for a joint).
        class(node_tie_t), allocatable :: at_force, at_end
        integer :: member_a = 0, node_a = 0, member_b = 0, node_b = 0
        !> The plate (0 for a joint); a rigid tie to a floating plate's carrier end (float_plate).
        integer :: plate = 0
        logical :: floating = .false.
    end type tie_entry_t

    type :: plate_t
        character(len=:), allocatable :: name
        real(rk) :: centre(3) = 0.0_rk
        real(rk) :: displacement(3) = 0.0_rk
        real(rk) :: rotation(3) = 0.0_rk
        type(time_function_t) :: factor
    end type plate_t

    type, extends(coupling_t), public :: tie_coupling_t
        type(tie_entry_t), allocatable :: ties(:)
        type(plate_t), allocatable :: plates(:)
        !> Coordinates per node (the same for every member).
        integer :: nc = 0
        logical :: static = .false.
        real(rk) :: t_static = 0.0_rk
    contains
        procedure :: add_pattern => ties_add_pattern
        procedure :: map_pattern => ties_map_pattern
        procedure :: add_residual => ties_add_residual
        procedure :: add_jacobian => ties_add_jacobian
        procedure :: set_endpoint => ties_set_endpoint
        procedure :: add_results => ties_add_results
        procedure :: add_edges => ties_add_edges
        procedure :: describe => ties_describe
        procedure :: pattern_entries => ties_pattern_entries
        !> Joint ends (member a, node a, member b, node b) per joint: contact leaves their
        !> neighbours alone.
        procedure :: joint_ends
        procedure :: count_ties
    end type tie_coupling_t

    public :: tie_coupling_init

    !> A member's formulation object, for its tie rows (rod_formulation_t%new_tie).
    type, public :: tie_maker_t
        class(rod_formulation_t), pointer :: rod => null()
    end type tie_maker_t

contains

    !> The joints among the members named `names` (scene order of the system) and the rod ends
    !> tied to plates; `makers(m)` gives member m's rows. The layout's node tables give
    !> the reference coordinates (rod_nodes_t%held).
    subroutine tie_coupling_init(this, scene, names, layout, makers, err)
        type(tie_coupling_t), intent(inout) :: this
        type(scene_t), intent(in) :: scene
        character(len=*), intent(in) :: names(:)
        type(system_layout_t), intent(in) :: layout
        type(tie_maker_t), intent(in) :: makers(:)
        type(error_t), allocatable, intent(out) :: err
        type(tie_entry_t), allocatable :: ties(:)
        integer :: j, p, i, n, m
        character(len=:), allocatable :: message
        this%nc = layout%members(1)%nodes%n_coordinates
        call read_plates(this, scene, names, layout, err)
        RS_RETURN_IF_ERROR(err)
        n = 0
        if (allocated(scene%joints)) n = n + size(scene%joints)
        if (allocated(scene%plates)) n = n + size(scene%plates) * size(scene%plates(1)%rods)
        allocate(ties(n))
        n = 0
        if (allocated(scene%joints)) then
            do j = 1, size(scene%joints)
                associate (joint => scene%joints(j))
                    m = member_named(names, joint%rod_a)
                    if (m == 0 .or. member_named(names, joint%rod_b) == 0) cycle
                    n = n + 1
                    associate (tie => ties(n))
                        tie%kind = trim(joint%kind)
                        tie%member_a = m
                        tie%member_b = member_named(names, joint%rod_b)
                        tie%node_a = end_node(layout, tie%member_a, joint%end_a)
                        tie%node_b = end_node(layout, tie%member_b, joint%end_b)
                        call makers(tie%member_a)%rod%new_tie(trim(joint%kind), &
                            layout%members(tie%member_a)%nodes%held(:, tie%node_a), &
                            layout%members(tie%member_b)%nodes%held(:, tie%node_b), joint%axis, &
                            tie%at_force)
                    end associate
                end associate
            end do
        end if
        if (allocated(scene%plates)) then
            do p = 1, size(scene%plates)
                if (scene%plates(p)%mass > 0.0_rk) then
                    call float_plate(scene%plates(p), names, layout, makers, ties, n)
                    cycle
                end if
                do i = 1, size(scene%plates(p)%rods)
                    if (len_trim(scene%plates(p)%rods(i)) == 0) cycle
                    m = member_named(names, scene%plates(p)%rods(i))
                    if (m == 0) cycle
                    n = n + 1
                    associate (tie => ties(n))
                        tie%kind = 'plate'
                        tie%plate = p
                        tie%member_a = m
                        tie%node_a = end_node(layout, m, scene%plates(p)%end)
                        call makers(m)%rod%new_tie('plate', layout%members(m)%nodes%held(:, tie%node_a), &
                            layout%members(m)%nodes%held(:, tie%node_a), [0.0_rk, 0.0_rk, 1.0_rk], &
                            tie%at_force)
                    end associate
                end do
            end do
        end if
        do i = 1, n
            if (.not. allocated(ties(i)%at_force)) then
                message = 'the formulation of rod ''' // trim(names(ties(i)%member_a)) // &
                    ''' has no ' // trim(ties(i)%kind) // ' ties'
                RS_SET_ERROR(err, 'tie_coupling_init', message)
                return
            end if
            allocate(ties(i)%at_end, source=ties(i)%at_force)
        end do
        call move_alloc(ties, this%ties)
        this%ties = this%ties(1:n)
        allocate(this%blocks(n))
        do i = 1, n
            this%blocks(i) = coupling_block_t(owner=this%ties(i)%member_a, size=this%ties(i)%at_force%n)
            if (this%ties(i)%plate == 0) cycle
            call place(this%plates(this%ties(i)%plate), 0.0_rk, this%ties(i)%at_force)
            call place(this%plates(this%ties(i)%plate), 0.0_rk, this%ties(i)%at_end)
        end do
    end subroutine tie_coupling_init

    !> A floating plate (&plate mass > 0; issue 24 item 4): its body is on the tied end of its
    !> first rod (rs_ph_director_body, read with that rod's supports), and every other tied end
    !> is tied to that end rigidly, keeping its reference offset and relative orientation (the
    !> rigid joint's rows, whose pivot offset is carried in the section of the other end:
    !> rs_ph_director_tie). The ties are then joints: no work, and linear and angular momentum
    !> kept (the quadratic tie rows' exact midpoint gradient, methods/ph_director_3d.md §5.3
    !> item 2, as for the nodal orthonormality), so the plate and its rods keep energy and
    !> momenta in free flight. Ties appended
    !> to `ties` from entry n + 1; n is updated.
    subroutine float_plate(plate, names, layout, makers, ties, n)
        type(plate_input_t), intent(in) :: plate
        character(len=*), intent(in) :: names(:)
        type(system_layout_t), intent(in) :: layout
        type(tie_maker_t), intent(in) :: makers(:)
        type(tie_entry_t), intent(inout) :: ties(:)
        integer, intent(inout) :: n
        integer :: i, carrier, m
        carrier = member_named(names, plate%rods(1))
        if (carrier == 0) return
        do i = 2, size(plate%rods)
            if (len_trim(plate%rods(i)) == 0) cycle
            m = member_named(names, plate%rods(i))
            if (m == 0) cycle
            n = n + 1
            associate (tie => ties(n))
                tie%kind = 'rigid'
                tie%floating = .true.
                tie%member_a = carrier
                tie%member_b = m
                tie%node_a = end_node(layout, carrier, plate%end)
                tie%node_b = end_node(layout, m, plate%end)
                call makers(carrier)%rod%new_tie('rigid', &
                    layout%members(carrier)%nodes%held(:, tie%node_a), &
                    layout%members(m)%nodes%held(:, tie%node_b), [0.0_rk, 0.0_rk, 1.0_rk], &
                    tie%at_force)
            end associate
        end do
    end subroutine float_plate

    !> Member index of the rod named `name` (0 if not in the system).
    pure integer function member_named(names, name) result(found)
        character(len=*), intent(in) :: names(:), name
        integer :: m
        found = 0
        do m = 1, size(names)
            if (trim(names(m)) == trim(name)) then
                found = m
                return
            end if
        end do
    end function member_named

    !> Node at end `end_name` ('start' or 'end') of member m.
    pure integer function end_node(layout, m, end_name)
        type(system_layout_t), intent(in) :: layout
        integer, intent(in) :: m
        character(len=*), intent(in) :: end_name
        end_node = merge(1, layout%members(m)%nodes%n_nodes, trim(end_name) == 'start')
    end function end_node

    subroutine read_plates(this, scene, names, layout, err)
        type(tie_coupling_t), intent(inout) :: this
        type(scene_t), intent(in) :: scene
        character(len=*), intent(in) :: names(:)
        type(system_layout_t), intent(in) :: layout
        type(error_t), allocatable, intent(out) :: err
        integer :: p, i, m, n
        real(rk) :: centre(3)
        allocate(this%plates(0))
        if (.not. allocated(scene%plates)) return
        deallocate(this%plates)
        allocate(this%plates(size(scene%plates)))
        do p = 1, size(scene%plates)
            associate (input => scene%plates(p), plate => this%plates(p))
                plate%name = trim(input%name)
                plate%displacement = input%displacement
                plate%rotation = input%rotation
                call time_function_from_plate(input, plate%factor, err)
                RS_RETURN_IF_ERROR(err)
                if (all(input%centre /= unset_real)) then
                    plate%centre = input%centre
                else
                    ! The mean of the tied ends' reference positions.
                    centre = 0.0_rk
                    n = 0
                    do i = 1, size(input%rods)
                        if (len_trim(input%rods(i)) == 0) cycle
                        m = member_named(names, input%rods(i))
                        if (m == 0) cycle
                        centre = centre + layout%members(m)%nodes%held(1:3, end_node(layout, m, input%end))
                        n = n + 1
                    end do
                    plate%centre = centre / real(max(n, 1), rk)
                end if
            end associate
        end do
    end subroutine read_plates

    !> Put a plate tie's rows at the plate's pose at time t.
    subroutine place(plate, t, rows)
        type(plate_t), intent(in) :: plate
        real(rk), intent(in) :: t
        class(node_tie_t), intent(inout) :: rows
        real(rk) :: f
        f = plate%factor%value(t)
        call rows%place(plate%centre, f * plate%displacement, f * plate%rotation)
    end subroutine place

    !> Load time of the step (the mid time, or the endpoint solve's load time), its end time
    !> and the weight theta of the new state in the forces (1/2, or 1 in the endpoint solve).
    pure subroutine step_times(this, t_n, h, t_force, t_end, theta)
        type(tie_coupling_t), intent(in) :: this
        real(rk), intent(in) :: t_n, h
        real(rk), intent(out) :: t_force, t_end, theta
        t_force = merge(this%t_static, t_n + 0.5_rk * h, this%static)
        t_end = merge(this%t_static, t_n + h, this%static)
        theta = merge(1.0_rk, 0.5_rk, this%static)
        if (this%equilibrium_steps .and. .not. this%static) then
            t_force = t_n + h
            theta = 1.0_rk
        end if
    end subroutine step_times

    pure function tie_rows(this, layout, tie) result(rows)
        type(tie_coupling_t), intent(in) :: this
        type(system_layout_t), intent(in) :: layout
        type(tie_entry_t), intent(in) :: tie
        integer :: rows(2 * this%nc)
        rows = 0
        rows(1:this%nc) = layout%momentum_rows(tie%member_a, tie%node_a, this%nc)
        if (tie%member_b > 0) rows(this%nc + 1:) = layout%momentum_rows(tie%member_b, tie%node_b, this%nc)
    end function tie_rows

    pure function tie_cols(this, layout, tie) result(cols)
        type(tie_coupling_t), intent(in) :: this
        type(system_layout_t), intent(in) :: layout
        type(tie_entry_t), intent(in) :: tie
        integer :: cols(2 * this%nc)
        cols = 0
        cols(1:this%nc) = layout%coordinate_cols(tie%member_a, tie%node_a, this%nc)
        if (tie%member_b > 0) cols(this%nc + 1:) = layout%coordinate_cols(tie%member_b, tie%node_b, this%nc)
    end function tie_cols

    !> z = [q_a; q_b] of a tie in a state (from_state) or in step unknowns.
    pure function tie_z(this, layout, tie, v, from_state) result(z)
        type(tie_coupling_t), intent(in) :: this
        type(system_layout_t), intent(in) :: layout
        type(tie_entry_t), intent(in) :: tie
        real(rk), intent(in) :: v(:)
        logical, intent(in) :: from_state
        real(rk) :: z(2 * this%nc)
        z = 0.0_rk
        if (from_state) then
            z(1:this%nc) = layout%node_state(tie%member_a, tie%node_a, v, this%nc)
            if (tie%member_b > 0) z(this%nc + 1:) = layout%node_state(tie%member_b, tie%node_b, v, this%nc)
        else
            z(1:this%nc) = layout%node_unknown(tie%member_a, tie%node_a, v, this%nc)
            if (tie%member_b > 0) z(this%nc + 1:) = layout%node_unknown(tie%member_b, tie%node_b, v, this%nc)
        end if
    end function tie_z

    !> Tie t in a step: its rows placed at the plate's poses of the load time and the end, its
    !> nodes' coordinates at the end (z_1) and where the forces act (z_t), its multipliers
    !> and their indices.
    subroutine tie_in_step(this, layout, t, t_force, t_end, theta, x_n, y, z_1, z_t, lam, &
            lam_index)
        type(tie_coupling_t), intent(inout) :: this
        type(system_layout_t), intent(in) :: layout
        integer, intent(in) :: t
        real(rk), intent(in) :: t_force, t_end, theta, x_n(:), y(:)
        real(rk), intent(out) :: z_1(:), z_t(:), lam(:)
        integer, intent(out) :: lam_index(:)
        real(rk) :: z_n(max_z)
        integer :: i, n, nz
        nz = 2 * this%nc
        associate (tie => this%ties(t), block => this%blocks(t))
            n = block%size
            if (tie%plate > 0) then
                call place(this%plates(tie%plate), t_force, tie%at_force)
                call place(this%plates(tie%plate), t_end, tie%at_end)
            end if
            z_n(1:nz) = tie_z(this, layout, tie, x_n, .true.)
            z_1(1:nz) = tie_z(this, layout, tie, y, .false.)
            z_t(1:nz) = z_n(1:nz) + theta * (z_1(1:nz) - z_n(1:nz))
            lam(1:n) = y(block%unknown_offset + 1:block%unknown_offset + n)
            lam_index(1:n) = [(block%unknown_offset + i, i = 1, n)]
        end associate
    end subroutine tie_in_step

    subroutine ties_add_pattern(this, layout, builder)
        class(tie_coupling_t), intent(inout) :: this
        type(system_layout_t), intent(in) :: layout
        type(csr_builder_t), intent(inout) :: builder
        integer :: t, k, nz
        integer :: rows(max_z), cols(max_z)
        nz = 2 * this%nc
        do t = 1, size(this%ties)
            rows(1:nz) = tie_rows(this, layout, this%ties(t))
            cols(1:nz) = tie_cols(this, layout, this%ties(t))
            associate (lam => [(this%blocks(t)%unknown_offset + k, k = 1, this%blocks(t)%size)])
                call builder%add_block(rows(1:nz), cols(1:nz))
                call builder%add_block(rows(1:nz), lam)
                call builder%add_block(lam, cols(1:nz))
            end associate
        end do
    end subroutine ties_add_pattern

    !> The ties look their positions up in the pattern (few ties: no map kept).
    subroutine ties_map_pattern(this, layout, pattern)
        class(tie_coupling_t), intent(inout) :: this
        type(system_layout_t), intent(in) :: layout
        type(csr_pattern_t), intent(in) :: pattern
    end subroutine ties_map_pattern

    !> + h G(z_t)^T lambda in the momentum rows of the tied nodes, g(z_{n+1}) in the tie's rows.
    subroutine ties_add_residual(this, layout, t_n, h, x_n, y, f, all_rows)
        class(tie_coupling_t), intent(inout) :: this
        type(system_layout_t), intent(in) :: layout
        real(rk), intent(in) :: t_n, h, x_n(:), y(:)
        real(rk), intent(inout) :: f(:)
        logical, intent(in) :: all_rows
        real(rk) :: z_1(max_z), z_t(max_z), lam(6), gradient(6, max_z), force(max_z)
        real(rk) :: g(6), t_force, t_end, theta
        integer :: t, i, n, nz, nc, rows(max_z), lam_index(6)
        nc = this%nc
        nz = 2 * nc
        call step_times(this, t_n, h, t_force, t_end, theta)
        do t = 1, size(this%ties)
            associate (tie => this%ties(t), block => this%blocks(t))
                rows(1:nz) = tie_rows(this, layout, tie)
                if (.not. (all_rows .or. layout%owns_member(tie%member_a) .or. &
                    any([(layout%owns_row(rows(i)), i = 1, nz)]))) cycle
                n = block%size
                call tie_in_step(this, layout, t, t_force, t_end, theta, x_n, y, z_1, z_t, lam, &
                    lam_index)
                call tie%at_force%force_gradient(z_t(1:nz), gradient(1:n, 1:nz))
                force(1:nz) = matmul(lam(1:n), gradient(1:n, 1:nz))
                force(1:nc) = layout%force_scale(tie%member_a, h) * force(1:nc)
                if (tie%member_b > 0) force(nc + 1:nz) = layout%force_scale(tie%member_b, h) * &
                    force(nc + 1:nz)
                do i = 1, nz
                    if (rows(i) <= 0) cycle
                    if (all_rows .or. layout%owns_row(rows(i))) f(rows(i)) = f(rows(i)) + force(i)
                end do
                if (all_rows .or. layout%owns_member(tie%member_a)) then
                    call tie%at_end%value(z_1(1:nz), g(1:n))
                    f(lam_index(1:n)) = g(1:n)
                end if
            end associate
        end do
    end subroutine ties_add_residual

    subroutine ties_add_jacobian(this, layout, pattern, t_n, h, x_n, y, values)
        class(tie_coupling_t), intent(inout) :: this
        type(system_layout_t), intent(in) :: layout
        type(csr_pattern_t), intent(in) :: pattern
        real(rk), intent(in) :: t_n, h, x_n(:), y(:)
        real(rk), intent(inout) :: values(:)
        real(rk) :: z_1(max_z), z_t(max_z), lam(6), gradient(6, max_z)
        real(rk) :: hessian(max_z, max_z), t_force, t_end, theta, scale(max_z)
        integer :: t, i, j, n, nz, nc, p, rows(max_z), cols(max_z), lam_index(6)
        nc = this%nc
        nz = 2 * nc
        call step_times(this, t_n, h, t_force, t_end, theta)
        do t = 1, size(this%ties)
            associate (tie => this%ties(t), block => this%blocks(t))
                rows(1:nz) = tie_rows(this, layout, tie)
                if (.not. (layout%owns_member(tie%member_a) .or. &
                    any([(layout%owns_row(rows(i)), i = 1, nz)]))) cycle
                n = block%size
                call tie_in_step(this, layout, t, t_force, t_end, theta, x_n, y, z_1, z_t, lam, &
                    lam_index)
                call tie%at_force%force_gradient(z_t(1:nz), gradient(1:n, 1:nz))
                cols(1:nz) = tie_cols(this, layout, tie)
                ! h^p of the rows' member (rod_nodes_t%force_h_power).
                scale(1:nc) = layout%force_scale(tie%member_a, h)
                scale(nc + 1:nz) = scale(1)
                if (tie%member_b > 0) scale(nc + 1:nz) = layout%force_scale(tie%member_b, h)
                call tie%at_force%force_hessian(z_t(1:nz), lam(1:n), hessian(1:nz, 1:nz))
                do j = 1, nz
                    hessian(1:nz, j) = theta * scale(1:nz) * hessian(1:nz, j)
                end do
                do i = 1, nz
                    if (rows(i) <= 0) cycle
                    if (.not. layout%owns_row(rows(i))) cycle
                    do j = 1, nz
                        if (cols(j) <= 0 .or. hessian(i, j) == 0.0_rk) cycle
                        p = pattern%position(rows(i), cols(j))
                        values(p) = values(p) + hessian(i, j)
                    end do
                    do j = 1, n
                        p = pattern%position(rows(i), lam_index(j))
                        values(p) = values(p) + scale(i) * gradient(j, i)
                    end do
                end do
                if (layout%owns_member(tie%member_a)) then
                    call tie%at_end%gradient(z_1(1:nz), gradient(1:n, 1:nz))
                    do j = 1, nz
                        if (cols(j) <= 0) cycle
                        do i = 1, n
                            p = pattern%position(lam_index(i), cols(j))
                            values(p) = values(p) + gradient(i, j)
                        end do
                    end do
                end if
            end associate
        end do
    end subroutine ties_add_jacobian

    subroutine ties_set_endpoint(this, on, t_load)
        class(tie_coupling_t), intent(inout) :: this
        logical, intent(in) :: on
        real(rk), intent(in) :: t_load
        this%static = on
        this%t_static = t_load
    end subroutine ties_set_endpoint

    !> The moment about a node of the generalized force g on its coordinates q (rod_nodes_t):
    !> sum_i d_i x g_i on directors (a virtual rotation dtheta turns d_i by dtheta x d_i, so
    !> g . dq = dtheta . sum_i d_i x g_i), R(psi) g_psi on rows of body rotations.
    pure function node_moment(nodes, q, g) result(moment)
        type(rod_nodes_t), intent(in) :: nodes
        real(rk), intent(in) :: q(:), g(:)
        real(rk) :: moment(3)
        integer :: i, at
        moment = 0.0_rk
        if (nodes%directors_at > 0) then
            do i = 0, 2
                at = nodes%directors_at + 3 * i
                moment = moment + matmul(hat(q(at:at + 2)), g(at:at + 2))
            end do
        else if (nodes%rotation_vector_at > 0) then
            at = nodes%rotation_vector_at
            moment = matmul(exp_so3(q(at:at + 2)), g(at:at + 2))
        end if
    end function node_moment

    !> The tie forces and moments on the tied ends at state x (multipliers in y), with the
    !> pose at t.
    subroutine ties_add_results(this, layout, t, x, y, records)
        class(tie_coupling_t), intent(inout) :: this
        type(system_layout_t), intent(in) :: layout
        real(rk), intent(in) :: t, x(:), y(:)
        type(coupling_record_t), intent(inout) :: records(:)
        real(rk) :: z(max_z), lam(6), gradient(6, max_z), force(max_z)
        integer :: k, n, nz, e, nc
        nc = this%nc
        nz = 2 * nc
        do k = 1, size(this%ties)
            associate (tie => this%ties(k), block => this%blocks(k))
                n = block%size
                if (tie%plate > 0) call place(this%plates(tie%plate), t, tie%at_end)
                z(1:nz) = tie_z(this, layout, tie, x, .true.)
                lam(1:n) = y(block%unknown_offset + 1:block%unknown_offset + n)
                call tie%at_end%force_gradient(z(1:nz), gradient(1:n, 1:nz))
                ! The force on a node is minus the position part of F^T lambda (the momentum
                ! rows carry + h^p F^T lambda like an internal force).
                force(1:nz) = -matmul(lam(1:n), gradient(1:n, 1:nz))
                e = merge(1, 2, tie%node_a == 1)
                records(tie%member_a)%tie_force(:, e) = records(tie%member_a)%tie_force(:, e) + &
                    force(1:3)
                records(tie%member_a)%tie_moment(:, e) = records(tie%member_a)%tie_moment(:, e) + &
                    node_moment(layout%members(tie%member_a)%nodes, z(1:nc), force(1:nc))
                if (tie%member_b > 0) then
                    e = merge(1, 2, tie%node_b == 1)
                    records(tie%member_b)%tie_force(:, e) = records(tie%member_b)%tie_force(:, e) + &
                        force(nc + 1:nc + 3)
                    records(tie%member_b)%tie_moment(:, e) = records(tie%member_b)%tie_moment(:, e) + &
                        node_moment(layout%members(tie%member_b)%nodes, z(nc + 1:nz), &
                        force(nc + 1:nz))
                end if
            end associate
        end do
    end subroutine ties_add_results

    !> Joints connect their two rods; the rods of one plate are chained (consecutive ones: the
    !> graph stays sparse).
    subroutine ties_add_edges(this, edge)
        class(tie_coupling_t), intent(in) :: this
        logical, intent(inout) :: edge(:, :)
        integer :: t, k, previous
        do t = 1, size(this%ties)
            associate (tie => this%ties(t))
                if (tie%member_b > 0) call connect(tie%member_a, tie%member_b)
            end associate
        end do
        do k = 1, size(this%plates)
            previous = 0
            do t = 1, size(this%ties)
                if (this%ties(t)%plate /= k) cycle
                if (previous > 0) call connect(previous, this%ties(t)%member_a)
                previous = this%ties(t)%member_a
            end do
        end do
    contains
        subroutine connect(a, b)
            integer, intent(in) :: a, b
            if (a == b) return
            edge(a, b) = .true.
            edge(b, a) = .true.
        end subroutine connect
    end subroutine ties_add_edges

    !> Two nodes' coordinates against each other and against the multipliers, both ways.
    pure integer function ties_pattern_entries(this)
        class(tie_coupling_t), intent(in) :: this
        ties_pattern_entries = size(this%ties) * (4 * this%nc**2 + 4 * this%nc * 6)
    end function ties_pattern_entries

    function ties_describe(this) result(text)
        class(tie_coupling_t), intent(in) :: this
        character(len=:), allocatable :: text
        integer :: n_plate, n_floating
        n_plate = count(this%ties%plate > 0)
        n_floating = count(this%ties%floating)
        text = str(size(this%ties) - n_plate - n_floating) // ' joints, ' // str(n_plate) // &
            ' plate ties'
        if (n_floating > 0) text = text // ', ' // str(n_floating) // ' rigid ties to floating ' // &
            'plates (their bodies on the first rods'' ends)'
    end function ties_describe

    pure function joint_ends(this) result(ends)
        class(tie_coupling_t), intent(in) :: this
        integer, allocatable :: ends(:, :)
        integer :: t, n
        allocate(ends(4, count(this%ties%plate == 0)))
        n = 0
        do t = 1, size(this%ties)
            associate (tie => this%ties(t))
                if (tie%plate > 0) cycle
                n = n + 1
                ends(:, n) = [tie%member_a, tie%node_a, tie%member_b, tie%node_b]
            end associate
        end do
    end function joint_ends

    pure integer function count_ties(this)
        class(tie_coupling_t), intent(in) :: this
        count_ties = size(this%ties)
    end function count_ties

end module rs_system_tie_coupling
