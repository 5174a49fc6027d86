#include "rs_macros.h"
!> Rod-rod and self contact (issue 10, issue 22; DESIGN.md §5; docs/theory/bundles.md): the
!> energy-consistent penalty potential between contact points of candidate element pairs
!> (rs_contact_element), for every formulation that offers node access: it needs only the
!> centreline, the first three coordinates of each node (rod_nodes_t). The candidates are
!> found by a cell grid (rs_contact_grid) rebuilt before every step from X_n with a margin; the
!> terms enter the momentum rows of the positions as h times the discrete gradient of the
!> contact energy (in the endpoint solve the gradient at X_{n+1}).
!>
!> Contact safety. The candidates of a step are the element pairs within the contact distance
!> plus `margin` at t_n; a step in which any centreline point moves more than margin / 2 could
!> miss a pair, and one in which it moves more than a quarter of the smallest contact distance
!> could carry it past another centreline unseen, so its iterates are rejected as invalid
!> states (the step is halved).
!>
!> No tunnelling (issue 24 item 1). Each pair of members has a wall d_w above the spacing of
!> their contact points (1.2 times the mean of their largest point gaps along an element and
!> across element ends, at least r_c / 4, at most 0.4 r_c): two centrelines cannot cross without
!> a pair of contact points coming within d_w. The potential gets its barrier at d_w
!> (rs_contact_potential, The barrier), infinite there, so no state of finite energy has a pair
!> inside; and an iterate whose straight path from X_n takes a pair inside
!> (contact_element_swept_clear) is rejected as an invalid state, so no step jumps over it.
!> The 1.2 allows elements 20 % longer than in the reference; a rod with too few contact points
!> for a wall below 0.4 r_c is told so in the log (points_per_element).
!>
!> Friction (&contact mu, slip_velocity; issue 24 item 2): the regularized Coulomb law of
!> rs_contact_potential on every point pair in contact, in dynamic steps (none in the endpoint
!> solve or in equilibrium steps); each pair's dissipation is booked half on each of its rods.
module rs_system_contact_coupling
    use rs_core_kinds, only: rk
    use rs_core_error, only: error_t, set_error
    use rs_core_strings, only: str
    use rs_core_logger, only: log_info
    use rs_model_scene, only: scene_t, unset_real, unset_int
    use rs_assembly_csr_pattern, only: csr_builder_t, csr_pattern_t
    use rs_contact_potential, only: contact_params_t, contact_params_init
    use rs_contact_grid, only: contact_grid_t, reserve_int_2
    use rs_contact_element, only: contact_element_pair, contact_points, contact_element_swept_clear
    use rs_math_lagrange, only: lagrange_shape
    use rs_system_layout, only: system_layout_t
    use rs_system_coupling, only: coupling_t, coupling_record_t, friction_record_t
    implicit none
    private

    !> Penetration (fraction of the contact distance) at which the default contact points
    !> resolve the contact patch.
    real(rk), parameter :: reference_penetration = 0.05_rk
    !> The barrier's wall (module header): at least wall_floor r_c, at most wall_ceiling r_c
    !> (below the barrier's start r_c / 2), wall_stretch times the points' spacing.
    real(rk), parameter :: wall_floor = 0.25_rk, wall_ceiling = 0.4_rk, wall_stretch = 1.2_rk

    !> A member's contact points: Lagrange shape values (nen, m) and weights on [0, 1], and its
    !> first global segment (element) number in the grid.
    type :: contact_member_t
        real(rk), allocatable :: shape(:, :), weight(:)
        !> Derivatives of the shape functions at the points (friction's contact normals).
        real(rk), allocatable :: slope(:, :)
        integer :: first_segment = 0
        !> The largest distance between neighbouring contact points along the rod (within an
        !> element, across element ends, twice the end's), in the reference (m).
        real(rk) :: point_gap = 0.0_rk
    end type contact_member_t

    type, extends(coupling_t), public :: contact_coupling_t
        type(contact_member_t), allocatable :: members(:)
        real(rk) :: stiffness = 0.0_rk
        real(rk) :: margin = 0.0_rk
        integer :: skip = 0
        logical :: self_contact = .true.
        !> Coulomb friction coefficient (0: frictionless) and slip velocity (m/s).
        real(rk) :: mu = 0.0_rk
        real(rk) :: slip_velocity = 1.0_rk
        logical :: static = .false.
        !> Largest motion of a centreline point allowed in one step (margin / 2) and the bound
        !> of the interpolated motion by the nodal one (the Lebesgue constant of the elements).
        real(rk) :: motion_limit = huge(1.0_rk)
        real(rk) :: lebesgue = 1.0_rk
        !> Joint ends (member a, node a, member b, node b): their neighbours never pair.
        integer, allocatable :: joint_ends(:, :)
        type(contact_grid_t) :: grid
        !> Element pairs (member a, element a, member b, element b) in the Jacobian pattern, and
        !> those active in the current step with their slot in the pattern pairs.
        integer, allocatable :: pattern_pairs(:, :)
        integer, allocatable :: active_pairs(:, :)
        integer, allocatable :: active_slot(:)
        integer :: n_active = 0
        !> pair_map(i, j, slot): global CSR position of the contact block entry (i, j).
        integer, allocatable :: pair_map(:, :, :)
        integer :: pair_block = 0
        !> Workspace of the broad phase.
        real(rk), allocatable :: segment_ends(:, :, :), segment_radius(:)
        integer, allocatable :: segment_rod(:), segment_index(:)
        !> The first step cut because an iterate moved further than the margin allows was
        !> logged; likewise the first cut by the swept test of the barrier.
        logical :: warned_motion = .false.
        logical :: warned_wall = .false.
        !> The last iterate found admissible and its step's start: the feasible-step filter
        !> tests an iterate just before the residual does (contact_admissible), so the second
        !> test is a comparison, not another pass over the point pairs.
        real(rk), allocatable :: admitted_x(:), admitted_y(:)
    contains
        procedure :: start => contact_start
        procedure :: add_pattern => contact_add_pattern
        procedure :: map_pattern => contact_map_pattern
        procedure :: prepare_step => contact_prepare_step
        procedure :: admissible => contact_admissible
        procedure :: add_residual => contact_add_residual
        procedure :: add_jacobian => contact_add_jacobian
        procedure :: set_endpoint => contact_set_endpoint
        procedure :: add_results => contact_add_results
        procedure :: add_edges => contact_add_edges
        procedure :: describe => contact_describe
        procedure :: pattern_entries => contact_pattern_entries
        procedure :: add_dissipation => contact_add_dissipation
    end type contact_coupling_t

    public :: contact_coupling_init

contains

    !> Contact settings (&contact), the contact points of each member and the default skip and
    !> margin; `joint_ends` from the ties.
    subroutine contact_coupling_init(this, scene, layout, joint_ends, err)
        type(contact_coupling_t), intent(inout) :: this
        type(scene_t), intent(in) :: scene
        type(system_layout_t), intent(in) :: layout
        integer, intent(in) :: joint_ends(:, :)
        type(error_t), allocatable, intent(out) :: err
        real(rk) :: smallest_radius, largest_radius, shortest_element, longest_element, rc
        real(rk) :: values(16), slopes(16), xi, sum_abs
        integer :: m, n_points, i, degree
        logical :: ok
        allocate(this%blocks(0))
        this%refuses_iterates = .true.
        this%joint_ends = joint_ends
        this%stiffness = scene%contact%stiffness
        this%self_contact = scene%contact%self_contact
        this%mu = scene%contact%mu
        this%slip_velocity = scene%contact%slip_velocity
        smallest_radius = minval(layout%members%contact_radius)
        largest_radius = maxval(layout%members%contact_radius)
        this%margin = scene%contact%margin
        if (this%margin == unset_real) this%margin = largest_radius
        shortest_element = huge(1.0_rk)
        allocate(this%members(size(layout%members)))
        do m = 1, size(layout%members)
            associate (member => this%members(m), nodes => layout%members(m)%nodes)
                longest_element = maxval(nodes%element_length)
                shortest_element = min(shortest_element, minval(nodes%element_length))
                ! Point spacing at most half the contact patch's half-length a = sqrt(delta
                ! (2 r_c - delta)) at the reference penetration delta = 5% of r_c (ripple of
                ! the sliding force below 4%, rs_contact_element), at least the Gauss rule.
                rc = layout%members(m)%contact_radius + smallest_radius
                n_points = max(nodes%n_gauss, ceiling(2.0_rk * longest_element / &
                    (rc * sqrt(reference_penetration * (2.0_rk - reference_penetration)))))
                if (scene%contact%points_per_element /= unset_int) n_points = scene%contact%points_per_element
                allocate(member%shape(nodes%degree + 1, n_points), member%weight(n_points), &
                    member%slope(nodes%degree + 1, n_points))
                call contact_points(nodes%degree, n_points, member%shape, member%weight, ok, &
                    member%slope)
                if (.not. ok) then
                    RS_SET_ERROR(err, 'contact_coupling_init', 'no contact points of degree ' // str(nodes%degree))
                    return
                end if
                member%point_gap = longest_element * largest_point_gap(member%shape, nodes%degree)
                ! Lebesgue constant of the element: bounds the motion of any interpolated point
                ! by the largest nodal motion.
                degree = nodes%degree
                do i = 0, 400
                    xi = real(i, rk) / 400.0_rk
                    call lagrange_shape(degree, 2.0_rk * xi - 1.0_rk, values(1:degree + 1), slopes(1:degree + 1), ok)
                    sum_abs = sum(abs(values(1:degree + 1)))
                    this%lebesgue = max(this%lebesgue, 1.01_rk * sum_abs)
                end do
            end associate
        end do
        this%skip = scene%contact%skip
        ! Default: elements closer along a rod than 1.5 contact distances never pair (their
        ! points would touch through the rod itself).
        if (this%skip == unset_int) this%skip = ceiling(1.5_rk * 2.0_rk * largest_radius / shortest_element) + 1
        ! A quarter of the smallest contact distance too (issue 24 item 1): two points then
        ! close by at most half a contact distance per step, so no step carries a point past
        ! another centreline without the potential seeing the approach (with a wider margin
        ! alone a rope thrown at another passed through it in one step). Equal radii and the
        ! default margin (the largest radius) give the same limit as margin / 2 alone.
        this%motion_limit = min(0.5_rk * this%margin, 0.25_rk * 2.0_rk * smallest_radius)
        m = 0
        do i = 1, size(this%members)
            this%members(i)%first_segment = m + 1
            m = m + layout%members(i)%nodes%n_elements
        end do
        allocate(this%segment_ends(3, 2, m), this%segment_radius(m), this%segment_rod(m), &
            this%segment_index(m))
        do i = 1, size(this%members)
            associate (first => this%members(i)%first_segment, n => layout%members(i)%nodes%n_elements)
                this%segment_rod(first:first + n - 1) = i
                this%segment_index(first:first + n - 1) = [(m, m = 1, n)]
            end associate
        end do
        call log_info('bundle contact: stiffness ' // str(this%stiffness) // ' N/m^3, margin ' // &
            str(this%margin) // ' m, skip ' // str(this%skip) // ' elements, ' // &
            trim(merge('with   ', 'without', this%self_contact)) // ' self contact, ' // &
            friction_text(this) // ', barrier wall ' // str(pair_wall(this, layout, 1, 1)) // ' m')
        do m = 1, size(this%members)
            rc = 2.0_rk * layout%members(m)%contact_radius
            if (wall_needed(this, layout, m, m) <= wall_ceiling * rc) cycle
            call log_info('bundle contact: rod ' // str(m) // ' has contact points ' // &
                str(this%members(m)%point_gap) // ' m apart, too few to keep the barrier''s wall ' // &
                'below ' // str(wall_ceiling) // ' of the contact distance: centrelines can pass ' // &
                'between its points; raise &contact points_per_element (docs/theory/bundles.md)')
        end do
    end subroutine contact_coupling_init

    !> The largest gap between neighbouring contact points of an element of unit length: within
    !> the element, across its ends to the next element's points, and twice the gap from an end
    !> to its nearest point (a rod's last points: the crossing can be beyond them). The points'
    !> reference coordinates are the interpolated nodal coordinates (exact for a linear map).
    pure real(rk) function largest_point_gap(shape, degree) result(gap)
        real(rk), intent(in) :: shape(:, :)
        integer, intent(in) :: degree
        real(rk) :: at(size(shape, 2))
        integer :: g, i
        do g = 1, size(shape, 2)
            at(g) = 0.0_rk
            do i = 1, degree + 1
                at(g) = at(g) + shape(i, g) * real(i - 1, rk) / real(degree, rk)
            end do
        end do
        gap = max(2.0_rk * at(1), 2.0_rk * (1.0_rk - at(size(at))), at(1) + 1.0_rk - at(size(at)))
        do g = 1, size(at) - 1
            gap = max(gap, at(g + 1) - at(g))
        end do
    end function largest_point_gap

    !> The barrier's wall for members ma and mb without the ceiling (module header).
    pure real(rk) function wall_needed(this, layout, ma, mb) result(wall)
        type(contact_coupling_t), intent(in) :: this
        type(system_layout_t), intent(in) :: layout
        integer, intent(in) :: ma, mb
        real(rk) :: rc
        rc = layout%members(ma)%contact_radius + layout%members(mb)%contact_radius
        wall = max(wall_floor * rc, wall_stretch * 0.5_rk * (this%members(ma)%point_gap + &
            this%members(mb)%point_gap))
    end function wall_needed

    !> The barrier's wall d_w of members ma and mb (module header).
    pure real(rk) function pair_wall(this, layout, ma, mb) result(wall)
        type(contact_coupling_t), intent(in) :: this
        type(system_layout_t), intent(in) :: layout
        integer, intent(in) :: ma, mb
        wall = min(wall_needed(this, layout, ma, mb), wall_ceiling * &
            (layout%members(ma)%contact_radius + layout%members(mb)%contact_radius))
    end function pair_wall

    !> The potential's parameters of an element pair (member a, element a, member b, element
    !> b), its barrier included.
    subroutine pair_params(this, layout, pair, params)
        type(contact_coupling_t), intent(in) :: this
        type(system_layout_t), intent(in) :: layout
        integer, intent(in) :: pair(4)
        type(contact_params_t), intent(out) :: params
        logical :: ok
        call contact_params_init(params, layout%members(pair(1))%contact_radius, &
            layout%members(pair(3))%contact_radius, this%stiffness, ok, &
            wall=pair_wall(this, layout, pair(1), pair(3)))
    end subroutine pair_params

    !> Candidate pairs of the state x (the initial state) with twice the margin: the pattern.
    subroutine contact_start(this, layout, x)
        class(contact_coupling_t), intent(inout) :: this
        type(system_layout_t), intent(in) :: layout
        real(rk), intent(in) :: x(:)
        integer, allocatable :: wider(:, :)
        integer :: n
        call find_pairs(this, layout, x, 2.0_rk * this%margin, wider, n)
        this%pattern_pairs = wider(:, 1:n)
        call find_active_pairs(this, layout, x)
        ! A start with two contact points inside the barrier's wall has infinite contact
        ! energy, and every step from it fails the swept test: say so now, not only in
        ! Newton's failure at the first step.
        if (.not. start_clear(this, layout, x)) call log_info('bundle contact: the ' // &
            'initial state has two contact points closer than the barrier''s wall (' // &
            str(pair_wall(this, layout, 1, 1)) // ' m for the first rods: centrelines that ' // &
            'nearly cross); no step can start from it: move the rods apart ' // &
            '(docs/theory/bundles.md, "No tunnelling")')
    end subroutine contact_start

    !> No active pair of the state x has two contact points within the barrier's wall.
    logical function start_clear(this, layout, x) result(clear)
        type(contact_coupling_t), intent(in) :: this
        type(system_layout_t), intent(in) :: layout
        real(rk), intent(in) :: x(:)
        real(rk) :: xa(3, 8), xb(3, 8)
        integer :: k, a, na, nb, first
        clear = .true.
        do k = 1, this%n_active
            associate (pair => this%active_pairs(:, k))
                na = layout%members(pair(1))%nodes%degree + 1
                nb = layout%members(pair(3))%nodes%degree + 1
                first = (pair(2) - 1) * layout%members(pair(1))%nodes%degree
                do a = 1, na
                    xa(:, a) = layout%node_state(pair(1), first + a, x, 3)
                end do
                first = (pair(4) - 1) * layout%members(pair(3))%nodes%degree
                do a = 1, nb
                    xb(:, a) = layout%node_state(pair(3), first + a, x, 3)
                end do
                clear = contact_element_swept_clear(this%members(pair(1))%shape, xa(:, 1:na), &
                    xa(:, 1:na), this%members(pair(3))%shape, xb(:, 1:nb), xb(:, 1:nb), &
                    pair_wall(this, layout, pair(1), pair(3)))
                if (.not. clear) return
            end associate
        end do
    end function start_clear

    !> The element pairs within the contact distance plus `margin` in the state x (broad phase
    !> of rs_contact_grid over all elements; near neighbours along a rod, pairs next to a joint
    !> and, without self contact, pairs of one rod are left out).
    subroutine find_pairs(this, layout, x, margin, pairs, n_pairs)
        type(contact_coupling_t), intent(inout) :: this
        type(system_layout_t), intent(in) :: layout
        real(rk), intent(in) :: x(:), margin
        !> The pairs (4, n_pairs) in a buffer that only grows (no allocation once it is large
        !> enough: the time loop calls this every step). Never a component of `this`.
        integer, allocatable, intent(inout) :: pairs(:, :)
        integer, intent(out) :: n_pairs
        integer :: m, e, s, k, n, sa, sb, ma, mb
        real(rk) :: nodes(3, 8), bulge(3), lo(3), hi(3), span(3)
        do m = 1, size(layout%members)
            associate (rod => layout%members(m)%nodes)
                do e = 1, rod%n_elements
                    s = this%members(m)%first_segment + e - 1
                    n = rod%degree + 1
                    do k = 1, n
                        nodes(:, k) = layout%node_state(m, (e - 1) * rod%degree + k, x, 3)
                    end do
                    ! The box of a curved element: its nodes and, for the interior of a
                    ! quadratic element, the chord shifted by the middle node's offset.
                    lo = minval(nodes(:, 1:n), dim=2)
                    hi = maxval(nodes(:, 1:n), dim=2)
                    if (n >= 3) then
                        bulge = nodes(:, 2) - 0.5_rk * (nodes(:, 1) + nodes(:, n))
                        lo = min(lo, nodes(:, 1) + bulge, nodes(:, n) + bulge)
                        hi = max(hi, nodes(:, 1) + bulge, nodes(:, n) + bulge)
                        if (n > 3) then
                            span = hi - lo
                            lo = lo - (this%lebesgue - 1.0_rk) * span
                            hi = hi + (this%lebesgue - 1.0_rk) * span
                        end if
                    end if
                    this%segment_ends(:, 1, s) = lo
                    this%segment_ends(:, 2, s) = hi
                    this%segment_radius(s) = layout%members(m)%contact_radius
                end do
            end associate
        end do
        call this%grid%build(this%segment_ends, this%segment_rod, this%segment_index, &
            this%segment_radius, margin, this%skip)
        n = this%grid%n_pairs()
        call reserve_int_2(pairs, 4, n)
        k = 0
        do e = 1, n
            associate (ab => this%grid%candidate(e))
                sa = ab(1)
                sb = ab(2)
            end associate
            ma = this%segment_rod(sa)
            mb = this%segment_rod(sb)
            if (ma == mb .and. .not. this%self_contact) cycle
            if (ma /= mb .and. next_to_joint(this, layout, ma, this%segment_index(sa), mb, &
                this%segment_index(sb))) cycle
            k = k + 1
            pairs(:, k) = [ma, this%segment_index(sa), mb, this%segment_index(sb)]
        end do
        n_pairs = k
    end subroutine find_pairs

    !> The active pairs of a step from x (within the contact distance plus the margin) and
    !> their slots in the pattern.
    subroutine find_active_pairs(this, layout, x)
        type(contact_coupling_t), intent(inout) :: this
        type(system_layout_t), intent(in) :: layout
        real(rk), intent(in) :: x(:)
        integer, allocatable :: pairs(:, :)
        integer :: n
        ! The buffer moves out of `this` for the call (no aliasing) and back, without copies.
        call move_alloc(this%active_pairs, pairs)
        call find_pairs(this, layout, x, this%margin, pairs, n)
        call move_alloc(pairs, this%active_pairs)
        this%n_active = n
        call match_active(this)
    end subroutine find_active_pairs

    !> Elements ea of member ma and eb of member mb lie within `skip` elements of the two ends
    !> of one joint: neighbours through the joint, never a contact pair.
    pure logical function next_to_joint(this, layout, ma, ea, mb, eb)
        type(contact_coupling_t), intent(in) :: this
        type(system_layout_t), intent(in) :: layout
        integer, intent(in) :: ma, ea, mb, eb
        integer :: t
        next_to_joint = .false.
        do t = 1, size(this%joint_ends, 2)
            associate (joint => this%joint_ends(:, t))
                if (joint(1) == ma .and. joint(3) == mb) then
                    if (near_end(this, layout, ma, joint(2), ea) .and. &
                        near_end(this, layout, mb, joint(4), eb)) then
                        next_to_joint = .true.
                        return
                    end if
                else if (joint(1) == mb .and. joint(3) == ma) then
                    if (near_end(this, layout, mb, joint(2), eb) .and. &
                        near_end(this, layout, ma, joint(4), ea)) then
                        next_to_joint = .true.
                        return
                    end if
                end if
            end associate
        end do
    end function next_to_joint

    pure logical function near_end(this, layout, m, node, e)
        type(contact_coupling_t), intent(in) :: this
        type(system_layout_t), intent(in) :: layout
        integer, intent(in) :: m, node, e
        if (node == 1) then
            near_end = e <= this%skip
        else
            near_end = e > layout%members(m)%nodes%n_elements - this%skip
        end if
    end function near_end

    !> Slot of each active pair in the pattern pairs (0 when it is not there). Both lists are
    !> sorted lexicographically by the broad phase.
    subroutine match_active(this)
        type(contact_coupling_t), intent(inout) :: this
        integer :: k, p
        if (.not. allocated(this%active_slot)) allocate(this%active_slot(0))
        if (size(this%active_slot) < this%n_active) then
            deallocate(this%active_slot)
            allocate(this%active_slot(size(this%active_pairs, 2)))
        end if
        this%active_slot(1:this%n_active) = 0
        p = 1
        do k = 1, this%n_active
            do while (p <= size(this%pattern_pairs, 2))
                if (.not. pair_less(this%pattern_pairs(:, p), this%active_pairs(:, k))) exit
                p = p + 1
            end do
            if (p <= size(this%pattern_pairs, 2)) then
                if (all(this%pattern_pairs(:, p) == this%active_pairs(:, k))) this%active_slot(k) = p
            end if
        end do
    end subroutine match_active

    pure logical function pair_less(a, b)
        integer, intent(in) :: a(4), b(4)
        integer :: i
        pair_less = .false.
        do i = 1, 4
            if (a(i) /= b(i)) then
                pair_less = a(i) < b(i)
                return
            end if
        end do
    end function pair_less

    !> Rows (momentum of the positions) and columns (positions) of a contact pair's nodes:
    !> element a's nodes, then element b's, three per node.
    pure subroutine pair_indices(layout, pair, rows, cols, n)
        type(system_layout_t), intent(in) :: layout
        integer, intent(in) :: pair(4)
        !> rows(1:n), cols(1:n), n = 3 (nodes of a + nodes of b); 48 holds cubic elements.
        integer, intent(out) :: rows(48), cols(48), n
        integer :: na, nb, a, first_a, first_b
        na = layout%members(pair(1))%nodes%degree + 1
        nb = layout%members(pair(3))%nodes%degree + 1
        n = 3 * (na + nb)
        rows = 0
        cols = 0
        first_a = (pair(2) - 1) * layout%members(pair(1))%nodes%degree
        first_b = (pair(4) - 1) * layout%members(pair(3))%nodes%degree
        do a = 1, na
            rows(3 * a - 2:3 * a) = layout%momentum_rows(pair(1), first_a + a, 3)
            cols(3 * a - 2:3 * a) = layout%coordinate_cols(pair(1), first_a + a, 3)
        end do
        do a = 1, nb
            rows(3 * (na + a) - 2:3 * (na + a)) = layout%momentum_rows(pair(3), first_b + a, 3)
            cols(3 * (na + a) - 2:3 * (na + a)) = layout%coordinate_cols(pair(3), first_b + a, 3)
        end do
    end subroutine pair_indices

    subroutine contact_add_pattern(this, layout, builder)
        class(contact_coupling_t), intent(inout) :: this
        type(system_layout_t), intent(in) :: layout
        type(csr_builder_t), intent(inout) :: builder
        integer :: k, n, rows(48), cols(48)
        do k = 1, size(this%pattern_pairs, 2)
            call pair_indices(layout, this%pattern_pairs(:, k), rows, cols, n)
            call builder%add_block(rows(1:n), cols(1:n))
        end do
    end subroutine contact_add_pattern

    subroutine contact_map_pattern(this, layout, pattern)
        class(contact_coupling_t), intent(inout) :: this
        type(system_layout_t), intent(in) :: layout
        type(csr_pattern_t), intent(in) :: pattern
        integer :: k, n, i, p, rows(48), cols(48)
        if (allocated(this%pair_map)) deallocate(this%pair_map)
        ! The largest block of a pair (rods of different degrees have smaller ones).
        this%pair_block = 3 * 2 * (maxval(layout%members%nodes%degree) + 1)
        allocate(this%pair_map(this%pair_block, this%pair_block, size(this%pattern_pairs, 2)), source=0)
        do k = 1, size(this%pattern_pairs, 2)
            call pair_indices(layout, this%pattern_pairs(:, k), rows, cols, n)
            do p = 1, n
                do i = 1, n
                    this%pair_map(i, p, k) = pattern%position(rows(i), cols(p))
                end do
            end do
        end do
        call match_active(this)
    end subroutine contact_map_pattern

    !> The step's candidates from X_n; a new pattern when one is not in it.
    subroutine contact_prepare_step(this, layout, x_n, repattern)
        class(contact_coupling_t), intent(inout) :: this
        type(system_layout_t), intent(in) :: layout
        real(rk), intent(in) :: x_n(:)
        logical, intent(out) :: repattern
        integer, allocatable :: wider(:, :)
        integer :: n
        repattern = .false.
        call find_active_pairs(this, layout, x_n)
        if (all(this%active_slot(1:this%n_active) > 0)) return
        ! A pair outside the pattern: the pattern becomes the pairs within twice the margin,
        ! so that it lasts while the bundle moves (DESIGN.md §3: analysis redone only then).
        call find_pairs(this, layout, x_n, 2.0_rk * this%margin, wider, n)
        this%pattern_pairs = wider(:, 1:n)
        repattern = .true.
    end subroutine contact_prepare_step

    !> Every centreline point moved by at most the motion limit from x_n to y (the candidate
    !> pairs of the step stay complete, module header).
    logical function contact_admissible(this, layout, t_n, x_n, y) result(ok)
        class(contact_coupling_t), intent(inout) :: this
        type(system_layout_t), intent(in) :: layout
        real(rk), intent(in) :: t_n, x_n(:), y(:)
        real(rk) :: largest
        integer :: m, k
        if (allocated(this%admitted_y)) then
            if (size(this%admitted_y) == size(y) .and. size(this%admitted_x) == size(x_n)) then
                ok = all(y == this%admitted_y) .and. all(x_n == this%admitted_x)
                if (ok) return
            end if
        end if
        ! This rank's members (a shared system agrees on the verdict of all ranks, rod_stepper.c).
        largest = 0.0_rk
        do m = 1, size(layout%members)
            if (.not. layout%owns_member(m)) cycle
            do k = 1, layout%members(m)%nodes%n_nodes
                largest = max(largest, norm2(layout%node_unknown(m, k, y, 3) - &
                    layout%node_state(m, k, x_n, 3)))
            end do
        end do
        ok = this%lebesgue * largest <= this%motion_limit
        if (.not. ok) then
            if (this%warned_motion) return
            call log_info('bundle: at t = ' // str(t_n) // ' a Newton iterate moved a centreline ' // &
                'point more than ' // str(this%motion_limit) // ' m (the smaller of margin / 2 and ' // &
                'a quarter of the smallest contact distance): Newton steps are shortened, or the ' // &
                'time step cut, until none does (docs/theory/bundles.md)')
            this%warned_motion = .true.
            return
        end if
        ok = swept_clear(this, layout, x_n, y)
        if (ok) then
            ! Kept for the same iterate's next test (allocated again only if the sizes change).
            this%admitted_x = x_n
            this%admitted_y = y
            return
        end if
        if (this%warned_wall) return
        call log_info('bundle: at t = ' // str(t_n) // ' a Newton iterate took two contact ' // &
            'points within the barrier''s wall of each other: Newton steps are shortened, or the ' // &
            'time step cut, until none does (docs/theory/bundles.md)')
        this%warned_wall = .true.
    end function contact_admissible

    !> No active pair of this rank's members takes a pair of contact points inside the wall on
    !> the straight path from x_n to y (contact_element_swept_clear).
    logical function swept_clear(this, layout, x_n, y) result(clear)
        type(contact_coupling_t), intent(in) :: this
        type(system_layout_t), intent(in) :: layout
        real(rk), intent(in) :: x_n(:), y(:)
        real(rk) :: xa_n(3, 8), xa_1(3, 8), xb_n(3, 8), xb_1(3, 8)
        integer :: k, na, nb
        clear = .true.
        do k = 1, this%n_active
            associate (pair => this%active_pairs(:, k))
                if (.not. (layout%owns_member(pair(1)) .or. layout%owns_member(pair(3)))) cycle
                na = layout%members(pair(1))%nodes%degree + 1
                nb = layout%members(pair(3))%nodes%degree + 1
                call pair_positions(layout, pair, x_n, y, xa_n(:, 1:na), xa_1(:, 1:na), &
                    xb_n(:, 1:nb), xb_1(:, 1:nb))
                clear = contact_element_swept_clear(this%members(pair(1))%shape, xa_n(:, 1:na), &
                    xa_1(:, 1:na), this%members(pair(3))%shape, xb_n(:, 1:nb), xb_1(:, 1:nb), &
                    pair_wall(this, layout, pair(1), pair(3)))
                if (.not. clear) return
            end associate
        end do
    end function swept_clear

    !> Element positions of a contact pair at t_n (state) and t_{n+1} (unknowns).
    pure subroutine pair_positions(layout, pair, x_n, y, xa_n, xa_1, xb_n, xb_1)
        type(system_layout_t), intent(in) :: layout
        integer, intent(in) :: pair(4)
        real(rk), intent(in) :: x_n(:), y(:)
        real(rk), intent(out) :: xa_n(:, :), xa_1(:, :), xb_n(:, :), xb_1(:, :)
        integer :: a, first
        first = (pair(2) - 1) * layout%members(pair(1))%nodes%degree
        do a = 1, size(xa_n, 2)
            xa_n(:, a) = layout%node_state(pair(1), first + a, x_n, 3)
            xa_1(:, a) = layout%node_unknown(pair(1), first + a, y, 3)
        end do
        first = (pair(4) - 1) * layout%members(pair(3))%nodes%degree
        do a = 1, size(xb_n, 2)
            xb_n(:, a) = layout%node_state(pair(3), first + a, x_n, 3)
            xb_1(:, a) = layout%node_unknown(pair(3), first + a, y, 3)
        end do
    end subroutine pair_positions

    subroutine contact_add_residual(this, layout, t_n, h, x_n, y, f, all_rows)
        class(contact_coupling_t), intent(inout) :: this
        type(system_layout_t), intent(in) :: layout
        real(rk), intent(in) :: t_n, h, x_n(:), y(:)
        real(rk), intent(inout) :: f(:)
        logical, intent(in) :: all_rows
        call assemble(this, layout, h, x_n, y, all_rows, f=f)
    end subroutine contact_add_residual

    subroutine contact_add_jacobian(this, layout, pattern, t_n, h, x_n, y, values)
        class(contact_coupling_t), intent(inout) :: this
        type(system_layout_t), intent(in) :: layout
        type(csr_pattern_t), intent(in) :: pattern
        real(rk), intent(in) :: t_n, h, x_n(:), y(:)
        real(rk), intent(inout) :: values(:)
        call assemble(this, layout, h, x_n, y, .false., values=values)
    end subroutine contact_add_jacobian

    !> The contact terms of the active pairs: + h times the discrete gradient of the contact
    !> energy in the momentum rows of the positions (in the endpoint solve the gradient at
    !> X_{n+1}: both arguments of the discrete gradient at X_{n+1}, whose derivative is twice
    !> the partial one by symmetry).
    subroutine assemble(this, layout, h, x_n, y, all_rows, f, values)
        type(contact_coupling_t), intent(in) :: this
        type(system_layout_t), intent(in) :: layout
        real(rk), intent(in) :: h, x_n(:), y(:)
        logical, intent(in) :: all_rows
        real(rk), intent(inout), optional :: f(:), values(:)
        real(rk) :: xa_n(3, 8), xa_1(3, 8), xb_n(3, 8), xb_1(3, 8), r_a(3, 8), r_b(3, 8)
        ! The tangent of the pair in a contiguous buffer, column-major with leading dimension
        ! 3 (na + nb): passed whole to the explicit-shape dummy (sequence association, no copy).
        real(rk) :: tangent(48 * 48), energy_n, energy_1, scale, h_a, h_b, row_scale(48)
        type(contact_params_t) :: params
        integer :: k, na, nb, i, j, p, slot, first
        integer :: rows(48), cols(48), n
        logical :: static
        static = this%static .or. this%equilibrium_steps
        scale = merge(2.0_rk, 1.0_rk, static)
        do k = 1, this%n_active
            associate (pair => this%active_pairs(:, k))
                if (.not. (all_rows .or. layout%owns_member(pair(1)) .or. &
                    layout%owns_member(pair(3)))) cycle
                associate (a => this%members(pair(1)), b => this%members(pair(3)), &
                        la => layout%members(pair(1)), lb => layout%members(pair(3)))
                    na = la%nodes%degree + 1
                    nb = lb%nodes%degree + 1
                    call pair_params(this, layout, pair, params)
                    ! Friction acts on the slip of a time step (none in equilibrium).
                    if (.not. static) then
                        params%mu = this%mu
                        params%slip_length = this%slip_velocity * h
                    end if
                    call pair_positions(layout, pair, x_n, y, xa_n(:, 1:na), xa_1(:, 1:na), &
                        xb_n(:, 1:nb), xb_1(:, 1:nb))
                    if (static) then
                        xa_n(:, 1:na) = xa_1(:, 1:na)
                        xb_n(:, 1:nb) = xb_1(:, 1:nb)
                    end if
                    if (present(values)) then
                        call contact_element_pair(params, a%shape, &
                            a%weight * la%nodes%element_length(pair(2)), xa_n(:, 1:na), &
                            xa_1(:, 1:na), b%shape, b%weight * &
                            lb%nodes%element_length(pair(4)), xb_n(:, 1:nb), xb_1(:, 1:nb), &
                            r_a(:, 1:na), r_b(:, 1:nb), energy_n, energy_1, &
                            tangent=tangent, slope_a=a%slope, slope_b=b%slope)
                    else
                        call contact_element_pair(params, a%shape, &
                            a%weight * la%nodes%element_length(pair(2)), xa_n(:, 1:na), &
                            xa_1(:, 1:na), b%shape, b%weight * &
                            lb%nodes%element_length(pair(4)), xb_n(:, 1:nb), xb_1(:, 1:nb), &
                            r_a(:, 1:na), r_b(:, 1:nb), energy_n, energy_1, slope_a=a%slope, &
                            slope_b=b%slope)
                    end if
                end associate
                call pair_indices(layout, pair, rows, cols, n)
                ! h^p of each rod's rows (rod_nodes_t%force_h_power).
                h_a = layout%force_scale(pair(1), h)
                h_b = layout%force_scale(pair(3), h)
                if (present(f)) then
                    do i = 1, na
                        first = 3 * (i - 1)
                        do j = 1, 3
                            if (rows(first + j) <= 0) cycle
                            if (all_rows .or. layout%owns_row(rows(first + j))) f(rows(first + j)) = &
                                f(rows(first + j)) + h_a * r_a(j, i)
                        end do
                    end do
                    do i = 1, nb
                        first = 3 * (na + i - 1)
                        do j = 1, 3
                            if (rows(first + j) <= 0) cycle
                            if (all_rows .or. layout%owns_row(rows(first + j))) f(rows(first + j)) = &
                                f(rows(first + j)) + h_b * r_b(j, i)
                        end do
                    end do
                end if
                if (present(values)) then
                    slot = this%active_slot(k)
                    row_scale(1:3 * na) = h_a
                    row_scale(3 * na + 1:3 * (na + nb)) = h_b
                    do j = 1, 3 * (na + nb)
                        if (cols(j) <= 0) cycle
                        do i = 1, 3 * (na + nb)
                            if (rows(i) <= 0) cycle
                            if (.not. (all_rows .or. layout%owns_row(rows(i)))) cycle
                            p = this%pair_map(i, j, slot)
                            values(p) = values(p) + scale * row_scale(i) * tangent(i + (j - 1) * n)
                        end do
                    end do
                end if
            end associate
        end do
    end subroutine assemble

    subroutine contact_set_endpoint(this, on, t_load)
        class(contact_coupling_t), intent(inout) :: this
        logical, intent(in) :: on
        real(rk), intent(in) :: t_load
        this%static = on
    end subroutine contact_set_endpoint

    !> Contact energy shares, contact forces and penetrations of the members at the state x.
    subroutine contact_add_results(this, layout, t, x, y, records)
        class(contact_coupling_t), intent(inout) :: this
        type(system_layout_t), intent(in) :: layout
        real(rk), intent(in) :: t, x(:), y(:)
        type(coupling_record_t), intent(inout) :: records(:)
        real(rk) :: xa(3, 8), xb(3, 8), xa_other(3, 8), xb_other(3, 8), r_a(3, 8), r_b(3, 8)
        real(rk) :: energy_n, energy_1, closest
        type(contact_params_t) :: params
        integer :: k, na, nb
        do k = 1, this%n_active
            associate (pair => this%active_pairs(:, k), a => this%members(this%active_pairs(1, k)), &
                    b => this%members(this%active_pairs(3, k)), &
                    la => layout%members(this%active_pairs(1, k)), &
                    lb => layout%members(this%active_pairs(3, k)), &
                    ra => records(this%active_pairs(1, k)), rb => records(this%active_pairs(3, k)))
                na = la%nodes%degree + 1
                nb = lb%nodes%degree + 1
                call pair_params(this, layout, pair, params)
                call pair_positions(layout, pair, x, y, xa(:, 1:na), xa_other(:, 1:na), xb(:, 1:nb), &
                    xb_other(:, 1:nb))
                call contact_element_pair(params, a%shape, a%weight * &
                    la%nodes%element_length(pair(2)), xa(:, 1:na), xa(:, 1:na), b%shape, &
                    b%weight * lb%nodes%element_length(pair(4)), xb(:, 1:nb), xb(:, 1:nb), &
                    r_a(:, 1:na), r_b(:, 1:nb), energy_n, energy_1, closest=closest)
                ra%contact_energy = ra%contact_energy + 0.5_rk * energy_1
                rb%contact_energy = rb%contact_energy + 0.5_rk * energy_1
                ra%contact_force = ra%contact_force - sum(r_a(:, 1:na), dim=2)
                rb%contact_force = rb%contact_force - sum(r_b(:, 1:nb), dim=2)
                ra%penetration = max(ra%penetration, params%contact_distance - closest)
                rb%penetration = max(rb%penetration, params%contact_distance - closest)
            end associate
        end do
    end subroutine contact_add_results

    !> The friction dissipation D >= 0 of the accepted step from x_n to the unknowns y of each
    !> active pair (rs_contact_potential, Friction), half on each of its two members, the
    !> friction force of the pair on each (the terms' sums, opposite on the two) and the largest
    !> slip speed of its point pairs.
    subroutine contact_add_dissipation(this, layout, t_n, h, x_n, y, dissipated, friction)
        class(contact_coupling_t), intent(in) :: this
        type(system_layout_t), intent(in) :: layout
        real(rk), intent(in) :: t_n, h, x_n(:), y(:)
        real(rk), intent(inout) :: dissipated(:)
        type(friction_record_t), intent(inout) :: friction(:)
        real(rk) :: xa_n(3, 8), xa_1(3, 8), xb_n(3, 8), xb_1(3, 8), r_a(3, 8), r_b(3, 8)
        real(rk) :: energy_n, energy_1, pair_dissipation, friction_a(3), largest_slip
        type(contact_params_t) :: params
        integer :: k, na, nb
        if (this%mu == 0.0_rk .or. this%static .or. this%equilibrium_steps) return
        do k = 1, this%n_active
            associate (pair => this%active_pairs(:, k), a => this%members(this%active_pairs(1, k)), &
                    b => this%members(this%active_pairs(3, k)), &
                    la => layout%members(this%active_pairs(1, k)), &
                    lb => layout%members(this%active_pairs(3, k)))
                na = la%nodes%degree + 1
                nb = lb%nodes%degree + 1
                call pair_params(this, layout, pair, params)
                params%mu = this%mu
                params%slip_length = this%slip_velocity * h
                call pair_positions(layout, pair, x_n, y, xa_n(:, 1:na), xa_1(:, 1:na), &
                    xb_n(:, 1:nb), xb_1(:, 1:nb))
                call contact_element_pair(params, a%shape, a%weight * &
                    la%nodes%element_length(pair(2)), xa_n(:, 1:na), xa_1(:, 1:na), b%shape, &
                    b%weight * lb%nodes%element_length(pair(4)), xb_n(:, 1:nb), xb_1(:, 1:nb), &
                    r_a(:, 1:na), r_b(:, 1:nb), energy_n, energy_1, dissipation=pair_dissipation, &
                    slope_a=a%slope, slope_b=b%slope, friction_a=friction_a, &
                    largest_slip=largest_slip)
                dissipated(pair(1)) = dissipated(pair(1)) + 0.5_rk * pair_dissipation
                dissipated(pair(3)) = dissipated(pair(3)) + 0.5_rk * pair_dissipation
                ! The physical forces are minus the terms: -f_Ta on a, +f_Ta on b.
                friction(pair(1))%force = friction(pair(1))%force - friction_a
                friction(pair(3))%force = friction(pair(3))%force + friction_a
                friction(pair(1))%slip_speed = max(friction(pair(1))%slip_speed, largest_slip / h)
                friction(pair(3))%slip_speed = max(friction(pair(3))%slip_speed, largest_slip / h)
            end associate
        end do
    end subroutine contact_add_dissipation

    !> 'frictionless' or the friction law's parameters, for the log and the plan.
    function friction_text(this) result(text)
        type(contact_coupling_t), intent(in) :: this
        character(len=:), allocatable :: text
        if (this%mu == 0.0_rk) then
            text = 'frictionless'
        else
            text = 'friction mu ' // str(this%mu) // ' (regularized below ' // &
                str(this%slip_velocity) // ' m/s)'
        end if
    end function friction_text

    !> Members with a contact candidate pair of the pattern are neighbours.
    subroutine contact_add_edges(this, edge)
        class(contact_coupling_t), intent(in) :: this
        logical, intent(inout) :: edge(:, :)
        integer :: k, a, b
        do k = 1, size(this%pattern_pairs, 2)
            a = this%pattern_pairs(1, k)
            b = this%pattern_pairs(3, k)
            if (a == b) cycle
            edge(a, b) = .true.
            edge(b, a) = .true.
        end do
    end subroutine contact_add_edges

    !> A pair's block: the positions of two elements' nodes against each other (cubic: 24 x 24).
    pure integer function contact_pattern_entries(this)
        class(contact_coupling_t), intent(in) :: this
        contact_pattern_entries = 400 * size(this%pattern_pairs, 2)
    end function contact_pattern_entries

    function contact_describe(this) result(text)
        class(contact_coupling_t), intent(in) :: this
        character(len=:), allocatable :: text
        text = 'contact on (' // str(this%n_active) // ' element pairs within the margin)'
    end function contact_describe

end module rs_system_contact_coupling
