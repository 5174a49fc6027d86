#include "rs_macros.h"
!> A bundle: ph_director rods coupled by joints, end plates and rod-rod contact into one system
!> (issue 10; DESIGN.md §5; docs/theory/bundles.md). Each rod keeps its own ph_director object
!> (its element and node kernels, its unknowns); the bundle adds
!> - ties (rs_ph_director_tie): joints between two rod ends and rod ends tied to a rigid end
!>   plate, each a few quadratic constraint rows with their multipliers (a saddle point: MUMPS);
!> - contact (rs_contact_element): the energy-consistent penalty potential between Gauss points
!>   of candidate element pairs, found by a cell grid (rs_contact_grid) rebuilt before every
!>   step from X_n with a margin;
!> and assembles everything into one residual and one CSR Jacobian. The coupling terms enter
!> the rods' momentum rows like their internal forces, times h (methods/ph_director_3d.md §5.2
!> and §5.6: the row scaling of eq. 38), and the tie rows like the nodal constraint rows
!> g(d_{n+1}) = 0 (§5.3 item 2, DESIGN.md §3).
!>
!> Layout. The rods are ordered by rank (`distribute`: METIS on the coupling graph) and, within
!> a rank, by scene order. A rod's block of the unknowns is its own unknowns followed by the
!> multipliers of the ties it owns (a joint belongs to its rod a, a plate tie to its rod), so a
!> rank owns one contiguous range of rows; the state is laid out the same way.
!>
!> Distributed assembly. The callbacks get the whole X_n and Y (the stepper gathers them on
!> every rank) and fill only the rows this rank owns: the kernels of its rods, the tie rows
!> touching its rods, the contact pairs with one element on its rods. Every row is summed in
!> the same order whatever the partition (rod kernels, then ties, then contact pairs in their
!> global order), so a row's value does not depend on the number of ranks.
!>
!> What is kept exactly (docs/theory/bundles.md): with joints, fixed plates and contact the
!> discrete energy H + E_contact is conserved to the Newton tolerance without loads (every
!> coupling force is an exact discrete gradient); joints and contact exert no net force or
!> torque, so linear and angular momentum are kept without supports; ties hold to round-off.
!> The per-rod energy balance books the work of the coupling forces on the rod as external
!> work, so each rod's balance_error stays at the Newton tolerance.
!>
!> Contact safety. The candidates of a step are the element pairs within the contact distance
!> plus `margin` at t_n; a step in which any centreline point moves more than margin / 2 could
!> miss a pair, so its iterates are rejected as invalid states (the step is halved).
module rs_ph_bundle
    use rs_core_kinds, only: rk
    use rs_core_error, only: error_t, set_error
    use rs_core_strings, only: str
    use rs_core_logger, only: log_info
    use rs_model_scene, only: scene_t, unset_real, unset_int
    use rs_model_rod_history, only: rod_history_t
    use rs_model_time_function, only: time_function_t, time_function_from_plate
    use rs_assembly_csr_pattern, only: csr_builder_t, csr_pattern_t
    use rs_formulations_formulation, only: rod_formulation_t, formulation_traits_t, state_valid, &
        state_invalid
    use rs_ph_director, only: ph_director_t
    use rs_ph_director_tie, only: ph_director_tie_t, ph_director_joint_tie, ph_director_plate_tie, &
        ph_director_tie_value, ph_director_tie_gradient, ph_director_tie_hessian
    use rs_contact_potential, only: contact_params_t, contact_params_init
    use rs_contact_grid, only: contact_grid_t, reserve_int_2
    use rs_contact_element, only: contact_element_pair, contact_points
    use rs_math_lagrange, only: lagrange_shape
    implicit none
    private

    !> Penetration (fraction of the contact distance) at which the default contact points
    !> resolve the contact patch (read_contact).
    real(rk), parameter :: reference_penetration = 0.05_rk

    !> One rod of the bundle with its place in the system.
    type :: bundle_member_t
        type(ph_director_t) :: rod
        integer :: scene_index = 0
        !> 0-based offsets of the rod's block in the state and the unknowns.
        integer :: state_offset = 0
        integer :: unknown_offset = 0
        integer :: part = 0
        !> 0-based offset of the rod's block in the canonical state (all rods on one rank).
        integer :: canonical_offset = 0
        !> Global CSR position of each entry of the rod's own Jacobian pattern.
        integer, allocatable :: value_map(:)
        real(rk), allocatable :: values(:)
        real(rk) :: contact_radius = 0.0_rk
        !> Contact points of its elements: Lagrange shape values (nen, m) and weights on [0, 1].
        real(rk), allocatable :: contact_shape(:, :), contact_weight(:)
        !> First global segment (element) number of the rod in the contact grid.
        integer :: first_segment = 0
        !> Last step's coupling results for the records: contact energy share at t_{n+1},
        !> contact force on the rod, deepest penetration, tie forces on its two ends.
        real(rk) :: contact_energy = 0.0_rk
        real(rk) :: contact_force(3) = 0.0_rk
        real(rk) :: penetration = 0.0_rk
        real(rk) :: tie_force(3, 2) = 0.0_rk
    end type bundle_member_t

    !> A joint between two rod ends or a rod end tied to a plate.
    type :: bundle_tie_t
        character(len=16) :: kind = ''
        type(ph_director_tie_t) :: tie
        integer :: member_a = 0, node_a = 0, member_b = 0, node_b = 0
        !> The plate (0 for a joint) and the tied node's reference coordinates.
        integer :: plate = 0
        real(rk) :: q_ref(12) = 0.0_rk
        integer :: state_offset = 0
        integer :: unknown_offset = 0
        integer :: canonical_offset = 0
    end type bundle_tie_t

    type :: bundle_plate_t
        character(len=:), allocatable :: name
        real(rk) :: centre(3) = 0.0_rk
        real(rk) :: displacement(3) = 0.0_rk
        real(rk) :: rotation(3) = 0.0_rk
        type(time_function_t) :: factor
    end type bundle_plate_t

    !> The bundle.
    type, extends(rod_formulation_t), public :: ph_bundle_t
        type(bundle_member_t), allocatable :: members(:)
        type(bundle_tie_t), allocatable :: ties(:)
        type(bundle_plate_t), allocatable :: plates(:)
        integer :: n_state_total = 0
        integer :: n_unknown_total = 0
        integer :: rank = 0
        integer :: n_ranks = 1
        !> 0-based owned ranges [lo, hi) of this rank.
        integer :: state_lo = 0, state_hi = 0, unknown_lo = 0, unknown_hi = 0
        logical :: quasistatic = .false.
        logical :: static = .false.
        real(rk) :: t_static = 0.0_rk
        ! Contact (&contact).
        logical :: contact = .false.
        real(rk) :: stiffness = 0.0_rk
        real(rk) :: margin = 0.0_rk
        integer :: skip = 0
        logical :: self_contact = .true.
        !> Largest motion of a centreline point allowed in one step (margin / 2) and the bound
        !> of the interpolated motion by the nodal one (the Lebesgue constant of the elements).
        real(rk) :: motion_limit = huge(1.0_rk)
        real(rk) :: lebesgue = 1.0_rk
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
        type(csr_pattern_t) :: pattern
        !> Workspace of the broad phase.
        real(rk), allocatable :: segment_ends(:, :, :), segment_radius(:)
        integer, allocatable :: segment_rod(:), segment_index(:)
        integer :: repatterns = 0
        !> Work arrays of the book-keeping (kept between steps: no allocation in the time loop).
        real(rk), allocatable :: work_y(:), work_force(:)
        !> The first step cut because an iterate moved further than the margin allows was
        !> logged.
        logical :: warned_motion = .false.
    contains
        procedure :: init => bundle_init
        procedure :: n_state => bundle_n_state
        procedure :: n_unknown => bundle_n_unknown
        procedure :: jacobian_pattern => bundle_jacobian_pattern
        procedure :: initial_state => bundle_initial_state
        procedure :: predictor => bundle_predictor
        procedure :: update => bundle_update
        procedure :: step_residual => bundle_step_residual
        procedure :: step_jacobian => bundle_step_jacobian
        procedure :: accept_step => bundle_accept_step
        procedure :: init_history => bundle_init_history
        procedure :: record => bundle_record
        procedure :: describe => bundle_describe
        procedure :: traits => bundle_traits
        procedure :: set_endpoint_solve => bundle_set_endpoint_solve
        procedure :: n_internal => bundle_n_internal
        procedure :: save_internal => bundle_save_internal
        procedure :: restore_internal => bundle_restore_internal
        procedure :: prepare_step => bundle_prepare_step
        procedure :: coupling_graph => bundle_coupling_graph
        procedure :: distribute => bundle_distribute
        procedure :: owned_range => bundle_owned_range
        procedure :: canonical_state => bundle_canonical_state
        procedure :: from_canonical => bundle_from_canonical
        procedure :: partition_summary
    end type ph_bundle_t

contains

    ! ---- Construction ---------------------------------------------------------------------

    !> Build the rods `rods` of the scene, their joints and plate ties, and the contact
    !> settings; one part (this rank owns everything) until `distribute`.
    subroutine bundle_init(this, scene, rods, err)
        class(ph_bundle_t), intent(inout) :: this
        type(scene_t), intent(in) :: scene
        integer, intent(in) :: rods(:)
        type(error_t), allocatable, intent(out) :: err
        integer :: m
        allocate(this%members(size(rods)))
        do m = 1, size(rods)
            associate (member => this%members(m))
                member%scene_index = rods(m)
                call member%rod%init(scene, [rods(m)], err)
                RS_RETURN_IF_ERROR(err)
                member%contact_radius = scene%rods(rods(m))%contact_radius
                if (member%contact_radius == unset_real) member%contact_radius = scene%rods(rods(m))%radius
                allocate(member%values(member%rod%pattern%nnz()))
            end associate
        end do
        this%quasistatic = scene%time%quasistatic
        call read_plates(this, scene, err)
        RS_RETURN_IF_ERROR(err)
        call read_ties(this, scene, err)
        RS_RETURN_IF_ERROR(err)
        call read_contact(this, scene, err)
        RS_RETURN_IF_ERROR(err)
        call this%distribute([(0, m = 1, size(this%members))], 0)
    end subroutine bundle_init

    !> Member index of the rod named `name` (0 if not in the bundle).
    pure integer function member_named(this, scene, name) result(found)
        type(ph_bundle_t), intent(in) :: this
        type(scene_t), intent(in) :: scene
        character(len=*), intent(in) :: name
        integer :: m
        found = 0
        do m = 1, size(this%members)
            if (trim(scene%rods(this%members(m)%scene_index)%name) == trim(name)) then
                found = m
                return
            end if
        end do
    end function member_named

    !> Node at end `end_name` ('start' or 'end') of member m.
    pure integer function end_node(this, m, end_name)
        type(ph_bundle_t), intent(in) :: this
        integer, intent(in) :: m
        character(len=*), intent(in) :: end_name
        end_node = merge(1, this%members(m)%rod%n_nodes, trim(end_name) == 'start')
    end function end_node

    subroutine read_plates(this, scene, err)
        type(ph_bundle_t), intent(inout) :: this
        type(scene_t), intent(in) :: scene
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
                    centre = 0.0_rk
                    n = 0
                    do i = 1, size(input%rods)
                        if (len_trim(input%rods(i)) == 0) cycle
                        m = member_named(this, scene, input%rods(i))
                        if (m == 0) cycle
                        associate (rod => this%members(m)%rod)
                            centre = centre + rod%fixed_q(1:3, end_node(this, m, input%end))
                        end associate
                        n = n + 1
                    end do
                    plate%centre = centre / real(max(n, 1), rk)
                end if
            end associate
        end do
    end subroutine read_plates

    !> The joints among the bundle's rods and the rod ends tied to plates.
    subroutine read_ties(this, scene, err)
        type(ph_bundle_t), intent(inout) :: this
        type(scene_t), intent(in) :: scene
        type(error_t), allocatable, intent(out) :: err
        type(bundle_tie_t), allocatable :: ties(:)
        type(bundle_tie_t) :: tie
        integer :: j, p, i, n
        n = 0
        if (allocated(scene%joints)) n = n + size(scene%joints)
        if (allocated(scene%plates)) n = n + size(scene%plates) * size(scene%plates(1)%rods)
        allocate(ties(n))
        n = 0
        if (allocated(scene%joints)) then
            do j = 1, size(scene%joints)
                associate (joint => scene%joints(j))
                    tie = bundle_tie_t()
                    tie%member_a = member_named(this, scene, joint%rod_a)
                    tie%member_b = member_named(this, scene, joint%rod_b)
                    if (tie%member_a == 0 .or. tie%member_b == 0) cycle
                    tie%kind = trim(joint%kind)
                    tie%node_a = end_node(this, tie%member_a, joint%end_a)
                    tie%node_b = end_node(this, tie%member_b, joint%end_b)
                    tie%tie = ph_director_joint_tie(trim(joint%kind), &
                        this%members(tie%member_a)%rod%fixed_q(:, tie%node_a), &
                        this%members(tie%member_b)%rod%fixed_q(:, tie%node_b), joint%axis)
                    n = n + 1
                    ties(n) = tie
                end associate
            end do
        end if
        if (allocated(scene%plates)) then
            do p = 1, size(scene%plates)
                do i = 1, size(scene%plates(p)%rods)
                    if (len_trim(scene%plates(p)%rods(i)) == 0) cycle
                    tie = bundle_tie_t()
                    tie%kind = 'plate'
                    tie%plate = p
                    tie%member_a = member_named(this, scene, scene%plates(p)%rods(i))
                    if (tie%member_a == 0) cycle
                    tie%node_a = end_node(this, tie%member_a, scene%plates(p)%end)
                    tie%q_ref = this%members(tie%member_a)%rod%fixed_q(:, tie%node_a)
                    tie%tie = plate_tie_at(this, tie, 0.0_rk)
                    n = n + 1
                    ties(n) = tie
                end do
            end do
        end if
        this%ties = ties(1:n)
    end subroutine read_ties

    !> The tie of a plate-tied end with the plate's pose at time t.
    pure function plate_tie_at(this, tie, t) result(moved)
        type(ph_bundle_t), intent(in) :: this
        type(bundle_tie_t), intent(in) :: tie
        real(rk), intent(in) :: t
        type(ph_director_tie_t) :: moved
        real(rk) :: f
        associate (plate => this%plates(tie%plate))
            f = plate%factor%value(t)
            moved = ph_director_plate_tie(tie%q_ref, plate%centre, f * plate%displacement, &
                f * plate%rotation)
        end associate
    end function plate_tie_at

    !> The tie of `tie` at time t: joints do not change, plates move.
    pure function tie_at(this, tie, t) result(current)
        type(ph_bundle_t), intent(in) :: this
        type(bundle_tie_t), intent(in) :: tie
        real(rk), intent(in) :: t
        type(ph_director_tie_t) :: current
        if (tie%plate > 0) then
            current = plate_tie_at(this, tie, t)
        else
            current = tie%tie
        end if
    end function tie_at

    !> Contact settings, the contact points of each rod and the default skip and margin.
    subroutine read_contact(this, scene, err)
        type(ph_bundle_t), intent(inout) :: this
        type(scene_t), intent(in) :: scene
        type(error_t), allocatable, intent(out) :: err
        real(rk) :: smallest_radius, largest_radius, shortest_element, longest_element, rc
        real(rk) :: values(16), slopes(16), xi, sum_abs
        integer :: m, n_points, i, degree
        logical :: ok
        this%contact = scene%contact%given
        if (.not. this%contact) return
        this%stiffness = scene%contact%stiffness
        this%self_contact = scene%contact%self_contact
        smallest_radius = minval(this%members%contact_radius)
        largest_radius = maxval(this%members%contact_radius)
        this%margin = scene%contact%margin
        if (this%margin == unset_real) this%margin = largest_radius
        shortest_element = huge(1.0_rk)
        do m = 1, size(this%members)
            associate (member => this%members(m), rod => this%members(m)%rod)
                longest_element = maxval(rod%element_length)
                shortest_element = min(shortest_element, minval(rod%element_length))
                ! Point spacing at most half the contact patch's half-length a = sqrt(delta
                ! (2 r_c - delta)) at the reference penetration delta = 5% of r_c (ripple of
                ! the sliding force below 4%, rs_contact_element), at least the Gauss rule.
                rc = member%contact_radius + smallest_radius
                n_points = max(rod%basis%n_gauss, ceiling(2.0_rk * longest_element / &
                    (rc * sqrt(reference_penetration * (2.0_rk - reference_penetration)))))
                if (scene%contact%points_per_element /= unset_int) n_points = scene%contact%points_per_element
                allocate(member%contact_shape(rod%degree + 1, n_points), member%contact_weight(n_points))
                call contact_points(rod%degree, n_points, member%contact_shape, member%contact_weight, ok)
                if (.not. ok) then
                    RS_SET_ERROR(err, 'read_contact', 'no contact points of degree ' // str(rod%degree))
                    return
                end if
                ! Lebesgue constant of the element: bounds the motion of any interpolated point
                ! by the largest nodal motion.
                degree = rod%degree
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
        this%motion_limit = 0.5_rk * this%margin
        m = 0
        do i = 1, size(this%members)
            this%members(i)%first_segment = m + 1
            m = m + this%members(i)%rod%n_elements
        end do
        allocate(this%segment_ends(3, 2, m), this%segment_radius(m), this%segment_rod(m), &
            this%segment_index(m))
        do i = 1, size(this%members)
            associate (member => this%members(i))
                this%segment_rod(member%first_segment:member%first_segment + member%rod%n_elements - 1) = i
                this%segment_index(member%first_segment:member%first_segment + member%rod%n_elements - 1) = &
                    [(m, m = 1, member%rod%n_elements)]
            end associate
        end do
        call log_info('bundle contact: stiffness ' // str(this%stiffness) // ' N/m^3, margin ' // &
            str(this%margin) // ' m, skip ' // str(this%skip) // ' elements, ' // &
            trim(merge('with   ', 'without', this%self_contact)) // ' self contact')
    end subroutine read_contact

    ! ---- Layout and pattern ---------------------------------------------------------------

    !> Rods to ranks: lay out the unknowns rank by rank and build the Jacobian pattern.
    subroutine bundle_distribute(this, part, rank)
        class(ph_bundle_t), intent(inout) :: this
        integer, intent(in) :: part(:), rank
        integer :: p, m, t, so, uo
        ! The canonical layout: every rod on one rank, in scene order.
        so = 0
        do m = 1, size(this%members)
            this%members(m)%canonical_offset = so
            so = so + this%members(m)%rod%n_state()
            do t = 1, size(this%ties)
                if (this%ties(t)%member_a /= m) cycle
                this%ties(t)%canonical_offset = so
                so = so + this%ties(t)%tie%n
            end do
        end do
        this%rank = rank
        this%n_ranks = maxval(part) + 1
        this%members%part = part
        so = 0
        uo = 0
        this%state_lo = -1
        do p = 0, this%n_ranks - 1
            if (p == rank) then
                this%state_lo = so
                this%unknown_lo = uo
            end if
            do m = 1, size(this%members)
                if (part(m) /= p) cycle
                this%members(m)%state_offset = so
                this%members(m)%unknown_offset = uo
                so = so + this%members(m)%rod%n_state()
                uo = uo + this%members(m)%rod%n_unknown()
                do t = 1, size(this%ties)
                    if (this%ties(t)%member_a /= m) cycle
                    this%ties(t)%state_offset = so
                    this%ties(t)%unknown_offset = uo
                    so = so + this%ties(t)%tie%n
                    uo = uo + this%ties(t)%tie%n
                end do
            end do
            if (p == rank) then
                this%state_hi = so
                this%unknown_hi = uo
            end if
        end do
        if (this%state_lo < 0) then
            ! A rank without rods owns an empty range.
            this%state_lo = so
            this%state_hi = so
            this%unknown_lo = uo
            this%unknown_hi = uo
        end if
        this%n_state_total = so
        this%n_unknown_total = uo
        if (this%contact) then
            call reference_candidates(this)
        else
            ! No contact: empty pair lists (assigned: distribute runs again on several ranks).
            this%pattern_pairs = reshape([integer ::], [4, 0])
            this%active_pairs = this%pattern_pairs
            this%active_slot = [integer ::]
            this%n_active = 0
        end if
        call build_pattern(this)
    end subroutine bundle_distribute

    !> Candidate pairs of the reference configuration with twice the margin: the first pattern.
    subroutine reference_candidates(this)
        type(ph_bundle_t), intent(inout) :: this
        real(rk), allocatable :: x(:)
        integer, allocatable :: wider(:, :)
        integer :: n
        allocate(x(this%n_state_total))
        call this%initial_state(x)
        call find_pairs(this, x, 2.0_rk * this%margin, wider, n)
        this%pattern_pairs = wider(:, 1:n)
        call find_active_pairs(this, x)
    end subroutine reference_candidates

    !> The element pairs within the contact distance plus `margin` in the state x (broad phase
    !> of rs_contact_grid over all elements; near neighbours along a rod, pairs next to a joint
    !> and, without self contact, pairs of one rod are left out).
    subroutine find_pairs(this, x, margin, pairs, n_pairs)
        type(ph_bundle_t), intent(inout) :: this
        real(rk), intent(in) :: x(:), margin
        !> The pairs (4, n_pairs) in a buffer that only grows (no allocation once it is large
        !> enough: the time loop calls this every step). Never a component of `this`.
        integer, allocatable, intent(inout) :: pairs(:, :)
        integer, intent(out) :: n_pairs
        integer :: m, e, s, k, n, sa, sb, ma, mb
        real(rk) :: nodes(3, 8), bulge(3), lo(3), hi(3), span(3)
        do m = 1, size(this%members)
            associate (rod => this%members(m)%rod)
                do e = 1, rod%n_elements
                    s = this%members(m)%first_segment + e - 1
                    n = rod%degree + 1
                    do k = 1, n
                        nodes(:, k) = node_q_state(this, m, (e - 1) * rod%degree + k, x, 3)
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
                    this%segment_radius(s) = this%members(m)%contact_radius
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
            if (ma /= mb .and. next_to_joint(this, ma, this%segment_index(sa), mb, &
                this%segment_index(sb))) cycle
            k = k + 1
            pairs(:, k) = [ma, this%segment_index(sa), mb, this%segment_index(sb)]
        end do
        n_pairs = k
    end subroutine find_pairs

    !> The active pairs of a step from x (within the contact distance plus the margin) and
    !> their slots in the pattern.
    subroutine find_active_pairs(this, x)
        type(ph_bundle_t), intent(inout) :: this
        real(rk), intent(in) :: x(:)
        integer, allocatable :: pairs(:, :)
        integer :: n
        ! The buffer moves out of `this` for the call (no aliasing) and back, without copies.
        call move_alloc(this%active_pairs, pairs)
        call find_pairs(this, x, this%margin, pairs, n)
        call move_alloc(pairs, this%active_pairs)
        this%n_active = n
        call match_active(this)
    end subroutine find_active_pairs

    !> Elements ea of member ma and eb of member mb lie within `skip` elements of the two ends
    !> of one joint: neighbours through the joint, never a contact pair.
    pure logical function next_to_joint(this, ma, ea, mb, eb)
        type(ph_bundle_t), intent(in) :: this
        integer, intent(in) :: ma, ea, mb, eb
        integer :: t
        next_to_joint = .false.
        do t = 1, size(this%ties)
            associate (tie => this%ties(t))
                if (tie%plate > 0) cycle
                if (tie%member_a == ma .and. tie%member_b == mb) then
                    if (near_end(this, ma, tie%node_a, ea) .and. near_end(this, mb, tie%node_b, eb)) then
                        next_to_joint = .true.
                        return
                    end if
                else if (tie%member_a == mb .and. tie%member_b == ma) then
                    if (near_end(this, mb, tie%node_a, eb) .and. near_end(this, ma, tie%node_b, ea)) then
                        next_to_joint = .true.
                        return
                    end if
                end if
            end associate
        end do
    end function next_to_joint

    pure logical function near_end(this, m, node, e)
        type(ph_bundle_t), intent(in) :: this
        integer, intent(in) :: m, node, e
        if (node == 1) then
            near_end = e <= this%skip
        else
            near_end = e > this%members(m)%rod%n_elements - this%skip
        end if
    end function near_end

    !> Slot of each active pair in the pattern pairs (0 when it is not there). Both lists are
    !> sorted lexicographically by the broad phase.
    subroutine match_active(this)
        type(ph_bundle_t), intent(inout) :: this
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

    !> The global pattern: each rod's own pattern as a diagonal block, the tie blocks and the
    !> contact blocks of the pattern pairs; the maps from the pieces into it.
    subroutine build_pattern(this)
        type(ph_bundle_t), intent(inout) :: this
        type(csr_builder_t) :: builder
        integer :: m, i, p, uo, t, k, n_expected, n
        integer :: rows(48), cols(48)
        n_expected = 0
        do m = 1, size(this%members)
            n_expected = n_expected + this%members(m)%rod%pattern%nnz()
        end do
        call builder%init(this%n_unknown_total, n_expected + 1024 * size(this%ties) + &
            400 * size(this%pattern_pairs, 2))
        do m = 1, size(this%members)
            associate (rod_pattern => this%members(m)%rod%pattern)
                uo = this%members(m)%unknown_offset
                do i = 1, rod_pattern%n_rows
                    p = rod_pattern%row_ptr(i)
                    call builder%add_block([uo + i], uo + rod_pattern%cols(p:rod_pattern%row_ptr(i + 1) - 1))
                end do
            end associate
        end do
        do t = 1, size(this%ties)
            rows(1:24) = tie_rows(this, this%ties(t))
            cols(1:24) = tie_cols(this, this%ties(t))
            associate (lam => [(this%ties(t)%unknown_offset + k, k = 1, this%ties(t)%tie%n)])
                call builder%add_block(rows(1:24), cols(1:24))
                call builder%add_block(rows(1:24), lam)
                call builder%add_block(lam, cols(1:24))
            end associate
        end do
        do k = 1, size(this%pattern_pairs, 2)
            call pair_indices(this, this%pattern_pairs(:, k), rows, cols, n)
            call builder%add_block(rows(1:n), cols(1:n))
        end do
        call builder%build(this%pattern)
        do m = 1, size(this%members)
            associate (member => this%members(m), rod_pattern => this%members(m)%rod%pattern)
                uo = member%unknown_offset
                if (allocated(member%value_map)) deallocate(member%value_map)
                allocate(member%value_map(rod_pattern%nnz()))
                do i = 1, rod_pattern%n_rows
                    do p = rod_pattern%row_ptr(i), rod_pattern%row_ptr(i + 1) - 1
                        member%value_map(p) = this%pattern%position(uo + i, uo + rod_pattern%cols(p))
                    end do
                end do
            end associate
        end do
        if (allocated(this%pair_map)) deallocate(this%pair_map)
        ! The largest block of a pair (rods of different degrees have smaller ones).
        this%pair_block = 3 * 2 * (maxval(this%members%rod%degree) + 1)
        allocate(this%pair_map(this%pair_block, this%pair_block, size(this%pattern_pairs, 2)), source=0)
        do k = 1, size(this%pattern_pairs, 2)
            call pair_indices(this, this%pattern_pairs(:, k), rows, cols, n)
            do p = 1, n
                do i = 1, n
                    this%pair_map(i, p, k) = this%pattern%position(rows(i), cols(p))
                end do
            end do
        end do
        if (this%contact) call match_active(this)
    end subroutine build_pattern

    ! ---- Index helpers --------------------------------------------------------------------

    !> Coordinates (first `n` of q: 3 = the position, 12 = all) of node k of member m in a
    !> bundle state x.
    pure function node_q_state(this, m, k, x, n) result(q)
        type(ph_bundle_t), intent(in) :: this
        integer, intent(in) :: m, k, n
        real(rk), intent(in) :: x(:)
        real(rk) :: q(n)
        associate (rod => this%members(m)%rod)
            if (rod%clamped(k)) then
                q = rod%fixed_q(1:n, k)
            else
                q = x(this%members(m)%state_offset + rod%node_dof(1:n, k))
            end if
        end associate
    end function node_q_state

    !> The same in the unknowns y of a step.
    pure function node_q_unknown(this, m, k, y, n) result(q)
        type(ph_bundle_t), intent(in) :: this
        integer, intent(in) :: m, k, n
        real(rk), intent(in) :: y(:)
        real(rk) :: q(n)
        associate (rod => this%members(m)%rod)
            if (rod%clamped(k)) then
                q = rod%fixed_q(1:n, k)
            else if (rod%condensed) then
                q = y(this%members(m)%unknown_offset + rod%node_unknown(1:n, k))
            else
                q = y(this%members(m)%unknown_offset + rod%node_dof(1:n, k))
            end if
        end associate
    end function node_q_unknown

    !> Global rows of the momentum equations of q(1:n) of node k of member m (0 if clamped).
    pure function momentum_rows(this, m, k, n) result(rows)
        type(ph_bundle_t), intent(in) :: this
        integer, intent(in) :: m, k, n
        integer :: rows(n)
        associate (rod => this%members(m)%rod)
            if (rod%clamped(k)) then
                rows = 0
            else if (rod%condensed) then
                rows = this%members(m)%unknown_offset + rod%node_unknown(1:n, k)
            else
                rows = this%members(m)%unknown_offset + rod%node_dof(13:12 + n, k)
            end if
        end associate
    end function momentum_rows

    !> Global columns of q(1:n) of node k of member m (0 if clamped).
    pure function q_cols(this, m, k, n) result(cols)
        type(ph_bundle_t), intent(in) :: this
        integer, intent(in) :: m, k, n
        integer :: cols(n)
        associate (rod => this%members(m)%rod)
            if (rod%clamped(k)) then
                cols = 0
            else if (rod%condensed) then
                cols = this%members(m)%unknown_offset + rod%node_unknown(1:n, k)
            else
                cols = this%members(m)%unknown_offset + rod%node_dof(1:n, k)
            end if
        end associate
    end function q_cols

    pure function tie_rows(this, tie) result(rows)
        type(ph_bundle_t), intent(in) :: this
        type(bundle_tie_t), intent(in) :: tie
        integer :: rows(24)
        rows = 0
        rows(1:12) = momentum_rows(this, tie%member_a, tie%node_a, 12)
        if (tie%member_b > 0) rows(13:24) = momentum_rows(this, tie%member_b, tie%node_b, 12)
    end function tie_rows

    pure function tie_cols(this, tie) result(cols)
        type(ph_bundle_t), intent(in) :: this
        type(bundle_tie_t), intent(in) :: tie
        integer :: cols(24)
        cols = 0
        cols(1:12) = q_cols(this, tie%member_a, tie%node_a, 12)
        if (tie%member_b > 0) cols(13:24) = q_cols(this, tie%member_b, tie%node_b, 12)
    end function tie_cols

    !> Rows (momentum of the positions) and columns (positions) of a contact pair's nodes:
    !> element a's nodes, then element b's, three per node.
    pure subroutine pair_indices(this, pair, rows, cols, n)
        type(ph_bundle_t), intent(in) :: this
        integer, intent(in) :: pair(4)
        !> rows(1:n), cols(1:n), n = 3 (nodes of a + nodes of b); 48 holds cubic elements.
        integer, intent(out) :: rows(48), cols(48), n
        integer :: na, nb, a, first_a, first_b
        na = this%members(pair(1))%rod%degree + 1
        nb = this%members(pair(3))%rod%degree + 1
        n = 3 * (na + nb)
        rows = 0
        cols = 0
        first_a = (pair(2) - 1) * this%members(pair(1))%rod%degree
        first_b = (pair(4) - 1) * this%members(pair(3))%rod%degree
        do a = 1, na
            rows(3 * a - 2:3 * a) = momentum_rows(this, pair(1), first_a + a, 3)
            cols(3 * a - 2:3 * a) = q_cols(this, pair(1), first_a + a, 3)
        end do
        do a = 1, nb
            rows(3 * (na + a) - 2:3 * (na + a)) = momentum_rows(this, pair(3), first_b + a, 3)
            cols(3 * (na + a) - 2:3 * (na + a)) = q_cols(this, pair(3), first_b + a, 3)
        end do
    end subroutine pair_indices

    pure logical function owns_row(this, row)
        type(ph_bundle_t), intent(in) :: this
        integer, intent(in) :: row
        owns_row = row > this%unknown_lo .and. row <= this%unknown_hi
    end function owns_row

    pure logical function owns_member(this, m)
        type(ph_bundle_t), intent(in) :: this
        integer, intent(in) :: m
        owns_member = this%members(m)%part == this%rank
    end function owns_member

    ! ---- Sizes and states -----------------------------------------------------------------

    pure integer function bundle_n_state(this)
        class(ph_bundle_t), intent(in) :: this
        bundle_n_state = this%n_state_total
    end function bundle_n_state

    pure integer function bundle_n_unknown(this)
        class(ph_bundle_t), intent(in) :: this
        bundle_n_unknown = this%n_unknown_total
    end function bundle_n_unknown

    subroutine bundle_owned_range(this, state_lo, state_hi, unknown_lo, unknown_hi)
        class(ph_bundle_t), intent(in) :: this
        integer, intent(out) :: state_lo, state_hi, unknown_lo, unknown_hi
        state_lo = this%state_lo
        state_hi = this%state_hi
        unknown_lo = this%unknown_lo
        unknown_hi = this%unknown_hi
    end subroutine bundle_owned_range

    subroutine bundle_jacobian_pattern(this, row_ptr, cols)
        class(ph_bundle_t), intent(in) :: this
        integer, allocatable, intent(out) :: row_ptr(:), cols(:)
        call this%pattern%zero_based(row_ptr, cols)
    end subroutine bundle_jacobian_pattern

    !> Each rod's initial state; the multipliers start at zero.
    subroutine bundle_initial_state(this, x)
        class(ph_bundle_t), intent(in) :: this
        real(rk), intent(out) :: x(:)
        integer :: m
        x = 0.0_rk
        do m = 1, size(this%members)
            associate (member => this%members(m))
                call member%rod%initial_state(x(member%state_offset + 1:member%state_offset + &
                    member%rod%n_state()))
            end associate
        end do
    end subroutine bundle_initial_state

    subroutine bundle_predictor(this, t_n, h, x_n, y)
        class(ph_bundle_t), intent(inout) :: this
        real(rk), intent(in) :: t_n, h, x_n(:)
        real(rk), intent(out) :: y(:)
        integer :: m, t
        y = 0.0_rk
        do m = 1, size(this%members)
            if (.not. owns_member(this, m)) cycle
            associate (member => this%members(m))
                call member%rod%predictor(t_n, h, &
                    x_n(member%state_offset + 1:member%state_offset + member%rod%n_state()), &
                    y(member%unknown_offset + 1:member%unknown_offset + member%rod%n_unknown()))
            end associate
        end do
        do t = 1, size(this%ties)
            associate (tie => this%ties(t))
                if (.not. owns_member(this, tie%member_a)) cycle
                y(tie%unknown_offset + 1:tie%unknown_offset + tie%tie%n) = &
                    x_n(tie%state_offset + 1:tie%state_offset + tie%tie%n)
            end associate
        end do
    end subroutine bundle_predictor

    subroutine bundle_update(this, t_n, h, x_n, y, x_1)
        class(ph_bundle_t), intent(inout) :: this
        real(rk), intent(in) :: t_n, h, x_n(:), y(:)
        real(rk), intent(out) :: x_1(:)
        integer :: m, t
        x_1 = 0.0_rk
        do m = 1, size(this%members)
            if (.not. owns_member(this, m)) cycle
            associate (member => this%members(m))
                call member%rod%update(t_n, h, &
                    x_n(member%state_offset + 1:member%state_offset + member%rod%n_state()), &
                    y(member%unknown_offset + 1:member%unknown_offset + member%rod%n_unknown()), &
                    x_1(member%state_offset + 1:member%state_offset + member%rod%n_state()))
            end associate
        end do
        do t = 1, size(this%ties)
            associate (tie => this%ties(t))
                if (.not. owns_member(this, tie%member_a)) cycle
                x_1(tie%state_offset + 1:tie%state_offset + tie%tie%n) = &
                    y(tie%unknown_offset + 1:tie%unknown_offset + tie%tie%n)
            end associate
        end do
    end subroutine bundle_update

    ! ---- The step problem -----------------------------------------------------------------

    !> Load time of the step (the mid time, or the endpoint solve's load time) and the weight
    !> theta of the new state in the forces (1/2, or 1 in the endpoint solve).
    pure subroutine step_times(this, t_n, h, t_force, theta)
        type(ph_bundle_t), intent(in) :: this
        real(rk), intent(in) :: t_n, h
        real(rk), intent(out) :: t_force, theta
        t_force = merge(this%t_static, t_n + 0.5_rk * h, this%static)
        theta = merge(1.0_rk, 0.5_rk, this%static)
    end subroutine step_times

    subroutine bundle_step_residual(this, t_n, h, x_n, y, f, status)
        class(ph_bundle_t), intent(inout) :: this
        real(rk), intent(in) :: t_n, h, x_n(:), y(:)
        real(rk), intent(out) :: f(:)
        integer, intent(out) :: status
        integer :: m
        f = 0.0_rk
        status = state_valid
        if (this%contact) then
            if (.not. motion_within_margin(this, x_n, y)) then
                if (.not. this%warned_motion) call log_info('bundle: at t = ' // str(t_n) // &
                    ' a Newton iterate moved a centreline point more than margin / 2 = ' // &
                    str(this%motion_limit) // ' m, so the step is cut (docs/theory/bundles.md); ' // &
                    'for faster motion raise &contact margin')
                this%warned_motion = .true.
                status = state_invalid
                return
            end if
        end if
        do m = 1, size(this%members)
            if (.not. owns_member(this, m)) cycle
            associate (member => this%members(m))
                call member%rod%step_residual(t_n, h, &
                    x_n(member%state_offset + 1:member%state_offset + member%rod%n_state()), &
                    y(member%unknown_offset + 1:member%unknown_offset + member%rod%n_unknown()), &
                    f(member%unknown_offset + 1:member%unknown_offset + member%rod%n_unknown()), status)
            end associate
            if (status /= state_valid) return
        end do
        call assemble_ties(this, t_n, h, x_n, y, f=f)
        if (this%contact) call assemble_contact(this, h, x_n, y, f=f)
    end subroutine bundle_step_residual

    subroutine bundle_step_jacobian(this, t_n, h, x_n, y, values, status)
        class(ph_bundle_t), intent(inout) :: this
        real(rk), intent(in) :: t_n, h, x_n(:), y(:)
        real(rk), intent(out) :: values(:)
        integer, intent(out) :: status
        integer :: m, p
        values = 0.0_rk
        status = state_valid
        do m = 1, size(this%members)
            if (.not. owns_member(this, m)) cycle
            associate (member => this%members(m))
                call member%rod%step_jacobian(t_n, h, &
                    x_n(member%state_offset + 1:member%state_offset + member%rod%n_state()), &
                    y(member%unknown_offset + 1:member%unknown_offset + member%rod%n_unknown()), &
                    member%values, status)
                if (status /= state_valid) return
                do p = 1, size(member%values)
                    values(member%value_map(p)) = values(member%value_map(p)) + member%values(p)
                end do
            end associate
        end do
        call assemble_ties(this, t_n, h, x_n, y, values=values)
        if (this%contact) call assemble_contact(this, h, x_n, y, values=values)
    end subroutine bundle_step_jacobian

    !> Every centreline point moved by at most the motion limit from x_n to y (the candidate
    !> pairs of the step stay complete, module header).
    pure logical function motion_within_margin(this, x_n, y) result(ok)
        type(ph_bundle_t), intent(in) :: this
        real(rk), intent(in) :: x_n(:), y(:)
        real(rk) :: largest
        integer :: m, k
        largest = 0.0_rk
        do m = 1, size(this%members)
            do k = 1, this%members(m)%rod%n_nodes
                largest = max(largest, norm2(node_q_unknown(this, m, k, y, 3) - &
                    node_q_state(this, m, k, x_n, 3)))
            end do
        end do
        ok = this%lebesgue * largest <= this%motion_limit
    end function motion_within_margin

    !> The tie terms (module rs_ph_director_tie): + h G(z_t)^T lambda in the momentum rows of the
    !> tied nodes, g(z_{n+1}) in the tie's rows, and their derivatives.
    subroutine assemble_ties(this, t_n, h, x_n, y, f, values, all_rows)
        type(ph_bundle_t), intent(in) :: this
        real(rk), intent(in) :: t_n, h, x_n(:), y(:)
        real(rk), intent(inout), optional :: f(:), values(:)
        !> Fill every row, not only this rank's (default false).
        logical, intent(in), optional :: all_rows
        type(ph_director_tie_t) :: tie_force, tie_end
        real(rk) :: z_n(24), z_1(24), z_t(24), lam(6), gradient(6, 24), hessian(24, 24), force(24)
        real(rk) :: t_force, theta, t_end
        integer :: t, i, j, n, rows(24), cols(24), lam_index(6), p
        logical :: everything
        everything = .false.
        if (present(all_rows)) everything = all_rows
        call step_times(this, t_n, h, t_force, theta)
        t_end = merge(this%t_static, t_n + h, this%static)
        do t = 1, size(this%ties)
            associate (tie => this%ties(t))
                rows = tie_rows(this, tie)
                if (.not. (everything .or. owns_member(this, tie%member_a) .or. &
                    any([(owns_row(this, rows(i)), i = 1, 24)]))) cycle
                n = tie%tie%n
                tie_force = tie_at(this, tie, t_force)
                tie_end = tie_at(this, tie, t_end)
                z_n = 0.0_rk
                z_1 = 0.0_rk
                z_n(1:12) = node_q_state(this, tie%member_a, tie%node_a, x_n, 12)
                z_1(1:12) = node_q_unknown(this, tie%member_a, tie%node_a, y, 12)
                if (tie%member_b > 0) then
                    z_n(13:24) = node_q_state(this, tie%member_b, tie%node_b, x_n, 12)
                    z_1(13:24) = node_q_unknown(this, tie%member_b, tie%node_b, y, 12)
                end if
                z_t = z_n + theta * (z_1 - z_n)
                lam(1:n) = y(tie%unknown_offset + 1:tie%unknown_offset + n)
                lam_index(1:n) = [(tie%unknown_offset + i, i = 1, n)]
                gradient(1:n, :) = ph_director_tie_gradient(tie_force, z_t)
                if (present(f)) then
                    force = h * matmul(lam(1:n), gradient(1:n, :))
                    do i = 1, 24
                        if (rows(i) <= 0) cycle
                        if (everything .or. owns_row(this, rows(i))) f(rows(i)) = f(rows(i)) + force(i)
                    end do
                    if (everything .or. owns_member(this, tie%member_a)) f(lam_index(1:n)) = &
                        ph_director_tie_value(tie_end, z_1)
                end if
                if (present(values)) then
                    cols = tie_cols(this, tie)
                    hessian = theta * h * ph_director_tie_hessian(tie_force, lam(1:n))
                    do i = 1, 24
                        if (rows(i) <= 0) cycle
                        if (.not. (everything .or. owns_row(this, rows(i)))) cycle
                        do j = 1, 24
                            if (cols(j) <= 0 .or. hessian(i, j) == 0.0_rk) cycle
                            p = this%pattern%position(rows(i), cols(j))
                            values(p) = values(p) + hessian(i, j)
                        end do
                        do j = 1, n
                            p = this%pattern%position(rows(i), lam_index(j))
                            values(p) = values(p) + h * gradient(j, i)
                        end do
                    end do
                    if (everything .or. owns_member(this, tie%member_a)) then
                        gradient(1:n, :) = ph_director_tie_gradient(tie_end, z_1)
                        do j = 1, 24
                            if (cols(j) <= 0) cycle
                            do i = 1, n
                                p = this%pattern%position(lam_index(i), cols(j))
                                values(p) = values(p) + gradient(i, j)
                            end do
                        end do
                    end if
                end if
            end associate
        end do
    end subroutine assemble_ties

    !> Element positions of a contact pair at t_n (state) and t_{n+1} (unknowns).
    pure subroutine pair_positions(this, pair, x_n, y, xa_n, xa_1, xb_n, xb_1)
        type(ph_bundle_t), intent(in) :: this
        integer, intent(in) :: pair(4)
        real(rk), intent(in) :: x_n(:), y(:)
        real(rk), intent(out) :: xa_n(:, :), xa_1(:, :), xb_n(:, :), xb_1(:, :)
        integer :: a, first
        first = (pair(2) - 1) * this%members(pair(1))%rod%degree
        do a = 1, size(xa_n, 2)
            xa_n(:, a) = node_q_state(this, pair(1), first + a, x_n, 3)
            xa_1(:, a) = node_q_unknown(this, pair(1), first + a, y, 3)
        end do
        first = (pair(4) - 1) * this%members(pair(3))%rod%degree
        do a = 1, size(xb_n, 2)
            xb_n(:, a) = node_q_state(this, pair(3), first + a, x_n, 3)
            xb_1(:, a) = node_q_unknown(this, pair(3), first + a, y, 3)
        end do
    end subroutine pair_positions

    !> The contact terms of the active pairs: + h times the discrete gradient of the contact
    !> energy in the momentum rows of the positions (in the endpoint solve the gradient at
    !> X_{n+1}: both arguments of the discrete gradient at X_{n+1}, whose derivative is twice
    !> the partial one by symmetry).
    subroutine assemble_contact(this, h, x_n, y, f, values, all_rows)
        type(ph_bundle_t), intent(in) :: this
        real(rk), intent(in) :: h, x_n(:), y(:)
        real(rk), intent(inout), optional :: f(:), values(:)
        !> Fill every row, not only this rank's (default false).
        logical, intent(in), optional :: all_rows
        real(rk) :: xa_n(3, 8), xa_1(3, 8), xb_n(3, 8), xb_1(3, 8), r_a(3, 8), r_b(3, 8)
        ! The tangent of the pair in a contiguous buffer, column-major with leading dimension
        ! 3 (na + nb): passed whole to the explicit-shape dummy (sequence association, no copy).
        real(rk) :: tangent(48 * 48), energy_n, energy_1, scale
        type(contact_params_t) :: params
        integer :: k, na, nb, i, j, p, slot, first
        integer :: rows(48), cols(48), n
        logical :: ok
        logical :: everything
        everything = .false.
        if (present(all_rows)) everything = all_rows
        scale = merge(2.0_rk, 1.0_rk, this%static)
        do k = 1, this%n_active
            associate (pair => this%active_pairs(:, k))
                if (.not. (everything .or. owns_member(this, pair(1)) .or. &
                    owns_member(this, pair(3)))) cycle
                associate (a => this%members(pair(1)), b => this%members(pair(3)))
                    na = a%rod%degree + 1
                    nb = b%rod%degree + 1
                    call contact_params_init(params, a%contact_radius, b%contact_radius, this%stiffness, ok)
                    call pair_positions(this, pair, x_n, y, xa_n(:, 1:na), xa_1(:, 1:na), &
                        xb_n(:, 1:nb), xb_1(:, 1:nb))
                    if (this%static) then
                        xa_n(:, 1:na) = xa_1(:, 1:na)
                        xb_n(:, 1:nb) = xb_1(:, 1:nb)
                    end if
                    if (present(values)) then
                        call contact_element_pair(params, a%contact_shape, &
                            a%contact_weight * a%rod%element_length(pair(2)), xa_n(:, 1:na), &
                            xa_1(:, 1:na), b%contact_shape, b%contact_weight * &
                            b%rod%element_length(pair(4)), xb_n(:, 1:nb), xb_1(:, 1:nb), &
                            r_a(:, 1:na), r_b(:, 1:nb), energy_n, energy_1, &
                            tangent=tangent)
                    else
                        call contact_element_pair(params, a%contact_shape, &
                            a%contact_weight * a%rod%element_length(pair(2)), xa_n(:, 1:na), &
                            xa_1(:, 1:na), b%contact_shape, b%contact_weight * &
                            b%rod%element_length(pair(4)), xb_n(:, 1:nb), xb_1(:, 1:nb), &
                            r_a(:, 1:na), r_b(:, 1:nb), energy_n, energy_1)
                    end if
                end associate
                call pair_indices(this, pair, rows, cols, n)
                if (present(f)) then
                    do i = 1, na
                        first = 3 * (i - 1)
                        do j = 1, 3
                            if (rows(first + j) <= 0) cycle
                            if (everything .or. owns_row(this, rows(first + j))) f(rows(first + j)) = &
                                f(rows(first + j)) + h * r_a(j, i)
                        end do
                    end do
                    do i = 1, nb
                        first = 3 * (na + i - 1)
                        do j = 1, 3
                            if (rows(first + j) <= 0) cycle
                            if (everything .or. owns_row(this, rows(first + j))) f(rows(first + j)) = &
                                f(rows(first + j)) + h * r_b(j, i)
                        end do
                    end do
                end if
                if (present(values)) then
                    slot = this%active_slot(k)
                    do j = 1, 3 * (na + nb)
                        if (cols(j) <= 0) cycle
                        do i = 1, 3 * (na + nb)
                            if (rows(i) <= 0) cycle
                            if (.not. (everything .or. owns_row(this, rows(i)))) cycle
                            p = this%pair_map(i, j, slot)
                            values(p) = values(p) + scale * h * tangent(i + (j - 1) * n)
                        end do
                    end do
                end if
            end associate
        end do
    end subroutine assemble_contact

    ! ---- Before and after a step ----------------------------------------------------------

    !> The step's contact candidates from X_n; a new pattern when one is not in it.
    subroutine bundle_prepare_step(this, t_n, h, x_n, repattern)
        class(ph_bundle_t), intent(inout) :: this
        real(rk), intent(in) :: t_n, h, x_n(:)
        logical, intent(out) :: repattern
        integer, allocatable :: wider(:, :)
        integer :: n
        repattern = .false.
        if (.not. this%contact) return
        call find_active_pairs(this, x_n)
        if (all(this%active_slot(1:this%n_active) > 0)) return
        ! A pair outside the pattern: the pattern becomes the pairs within twice the margin,
        ! so that it lasts while the bundle moves (DESIGN.md §3: analysis redone only then).
        call find_pairs(this, x_n, 2.0_rk * this%margin, wider, n)
        this%pattern_pairs = wider(:, 1:n)
        call build_pattern(this)
        this%repatterns = this%repatterns + 1
        repattern = .true.
    end subroutine bundle_prepare_step

    !> Each rod's book-keeping, plus the work of the coupling forces on it (booked as its
    !> external work) and the contact and tie results for its records.
    subroutine bundle_accept_step(this, t_n, h, x_n, x_1, newton_iterations, residual_norm)
        class(ph_bundle_t), intent(inout) :: this
        real(rk), intent(in) :: t_n, h, x_n(:), x_1(:)
        integer, intent(in) :: newton_iterations
        real(rk), intent(in) :: residual_norm
        real(rk), allocatable :: y(:), force(:)
        integer :: m
        ! Work arrays out of `this` for the calls below (no aliasing), back at the end.
        call move_alloc(this%work_y, y)
        call move_alloc(this%work_force, force)
        do m = 1, size(this%members)
            associate (member => this%members(m))
                call member%rod%accept_step(t_n, h, &
                    x_n(member%state_offset + 1:member%state_offset + member%rod%n_state()), &
                    x_1(member%state_offset + 1:member%state_offset + member%rod%n_state()), &
                    newton_iterations, residual_norm)
            end associate
        end do
        if ((size(this%ties) > 0 .or. this%contact) .and. .not. this%static) then
            ! The coupling forces of the step (h times their generalized forces in the momentum
            ! rows) at the accepted unknowns, all rows on every rank, and their work on each rod.
            call unknowns_of(this, x_1, y)
            call resize(force, this%n_unknown_total)
            force = 0.0_rk
            call coupling_forces(this, t_n, h, x_n, y, force)
            call book_coupling_work(this, h, x_n, x_1, force)
        end if
        call move_alloc(y, this%work_y)
        call move_alloc(force, this%work_force)
    end subroutine bundle_accept_step

    !> The work of the coupling forces on each rod in a step, booked as the rod's external work
    !> (module header: each rod's energy balance closes by itself).
    subroutine book_coupling_work(this, h, x_n, x_1, force)
        type(ph_bundle_t), intent(inout) :: this
        real(rk), intent(in) :: h, x_n(:), x_1(:), force(:)
        real(rk) :: work, dq(12)
        integer :: m, k, rows(12)
        do m = 1, size(this%members)
            work = 0.0_rk
            do k = 1, this%members(m)%rod%n_nodes
                rows = momentum_rows(this, m, k, 12)
                if (any(rows <= 0)) cycle
                dq = node_q_state(this, m, k, x_1, 12) - node_q_state(this, m, k, x_n, 12)
                work = work - dot_product(force(rows), dq) / h
            end do
            this%members(m)%rod%work_since_record = this%members(m)%rod%work_since_record + work
            this%members(m)%rod%balance_since_record = this%members(m)%rod%balance_since_record - work
        end do
    end subroutine book_coupling_work

    !> Allocate v with length n unless it has it.
    pure subroutine resize(v, n)
        real(rk), allocatable, intent(inout) :: v(:)
        integer, intent(in) :: n
        if (allocated(v)) then
            if (size(v) == n) return
            deallocate(v)
        end if
        allocate(v(n))
    end subroutine resize

    !> The step unknowns that correspond to a state x (positions, directors, multipliers).
    subroutine unknowns_of(this, x, y)
        type(ph_bundle_t), intent(in) :: this
        real(rk), intent(in) :: x(:)
        real(rk), allocatable, intent(inout) :: y(:)
        integer :: m, k, t
        call resize(y, this%n_unknown_total)
        y = 0.0_rk
        do m = 1, size(this%members)
            associate (member => this%members(m), rod => this%members(m)%rod)
                do k = 1, rod%n_nodes
                    if (rod%clamped(k)) cycle
                    associate (cols => q_cols(this, m, k, 12))
                        y(cols) = node_q_state(this, m, k, x, 12)
                    end associate
                end do
            end associate
        end do
        do t = 1, size(this%ties)
            associate (tie => this%ties(t))
                y(tie%unknown_offset + 1:tie%unknown_offset + tie%tie%n) = &
                    x(tie%state_offset + 1:tie%state_offset + tie%tie%n)
            end associate
        end do
    end subroutine unknowns_of

    !> The tie and contact terms of the momentum rows of ALL rows (whatever the rank owns).
    subroutine coupling_forces(this, t_n, h, x_n, y, force)
        type(ph_bundle_t), intent(in) :: this
        real(rk), intent(in) :: t_n, h, x_n(:), y(:)
        real(rk), intent(inout) :: force(:)
        call assemble_ties(this, t_n, h, x_n, y, f=force, all_rows=.true.)
        if (this%contact) call assemble_contact(this, h, x_n, y, f=force, all_rows=.true.)
    end subroutine coupling_forces

    !> Contact energy shares, contact forces and penetrations of the rods, and the tie forces
    !> on their ends, at the state x (unknowns y), for the records.
    subroutine coupling_results(this, t, x, y)
        type(ph_bundle_t), intent(inout) :: this
        real(rk), intent(in) :: t, x(:), y(:)
        real(rk) :: xa(3, 8), xb(3, 8), xa_other(3, 8), xb_other(3, 8), r_a(3, 8), r_b(3, 8)
        real(rk) :: energy_n, energy_1, closest
        real(rk) :: z(24), lam(6), gradient(6, 24), force(24)
        type(contact_params_t) :: params
        type(ph_director_tie_t) :: current
        integer :: k, na, nb, t_index, n, e
        logical :: ok
        do k = 1, size(this%members)
            this%members(k)%contact_energy = 0.0_rk
            this%members(k)%contact_force = 0.0_rk
            this%members(k)%penetration = 0.0_rk
            this%members(k)%tie_force = 0.0_rk
        end do
        do k = 1, this%n_active
            associate (pair => this%active_pairs(:, k), a => this%members(this%active_pairs(1, k)), &
                    b => this%members(this%active_pairs(3, k)))
                na = a%rod%degree + 1
                nb = b%rod%degree + 1
                call contact_params_init(params, a%contact_radius, b%contact_radius, this%stiffness, ok)
                call pair_positions(this, pair, x, y, xa(:, 1:na), xa_other(:, 1:na), xb(:, 1:nb), &
                    xb_other(:, 1:nb))
                call contact_element_pair(params, a%contact_shape, a%contact_weight * &
                    a%rod%element_length(pair(2)), xa(:, 1:na), xa(:, 1:na), b%contact_shape, &
                    b%contact_weight * b%rod%element_length(pair(4)), xb(:, 1:nb), xb(:, 1:nb), &
                    r_a(:, 1:na), r_b(:, 1:nb), energy_n, energy_1, closest=closest)
                a%contact_energy = a%contact_energy + 0.5_rk * energy_1
                b%contact_energy = b%contact_energy + 0.5_rk * energy_1
                a%contact_force = a%contact_force - sum(r_a(:, 1:na), dim=2)
                b%contact_force = b%contact_force - sum(r_b(:, 1:nb), dim=2)
                a%penetration = max(a%penetration, params%contact_distance - closest)
                b%penetration = max(b%penetration, params%contact_distance - closest)
            end associate
        end do
        do t_index = 1, size(this%ties)
            associate (tie => this%ties(t_index))
                n = tie%tie%n
                current = tie_at(this, tie, t)
                z = 0.0_rk
                z(1:12) = node_q_state(this, tie%member_a, tie%node_a, x, 12)
                if (tie%member_b > 0) z(13:24) = node_q_state(this, tie%member_b, tie%node_b, x, 12)
                lam(1:n) = y(tie%unknown_offset + 1:tie%unknown_offset + n)
                gradient(1:n, :) = ph_director_tie_gradient(current, z)
                ! The force on a node is minus the position part of G^T lambda (the momentum
                ! rows carry + h G^T lambda like an internal force).
                force = -matmul(lam(1:n), gradient(1:n, :))
                e = merge(1, 2, tie%node_a == 1)
                this%members(tie%member_a)%tie_force(:, e) = &
                    this%members(tie%member_a)%tie_force(:, e) + force(1:3)
                if (tie%member_b > 0) then
                    e = merge(1, 2, tie%node_b == 1)
                    this%members(tie%member_b)%tie_force(:, e) = &
                        this%members(tie%member_b)%tie_force(:, e) + force(13:15)
                end if
            end associate
        end do
    end subroutine coupling_results

    ! ---- Records, energy and checkpoints --------------------------------------------------

    subroutine bundle_init_history(this, histories, capacity)
        class(ph_bundle_t), intent(in) :: this
        type(rod_history_t), intent(inout), target :: histories(:)
        integer, intent(in) :: capacity
        integer :: m
        do m = 1, size(this%members)
            call this%members(m)%rod%init_history(histories(m:m), capacity)
            call histories(m)%init_coupling(capacity)
        end do
    end subroutine bundle_init_history

    subroutine bundle_record(this, histories, t, x)
        class(ph_bundle_t), intent(inout) :: this
        type(rod_history_t), intent(inout), target :: histories(:)
        real(rk), intent(in) :: t, x(:)
        real(rk), allocatable :: y(:)
        integer :: m, r
        if (size(this%ties) > 0 .or. this%contact) then
            call move_alloc(this%work_y, y)
            call unknowns_of(this, x, y)
            call coupling_results(this, t, x, y)
            call move_alloc(y, this%work_y)
        end if
        do m = 1, size(this%members)
            associate (member => this%members(m))
                call member%rod%record(histories(m:m), t, &
                    x(member%state_offset + 1:member%state_offset + member%rod%n_state()))
                r = histories(m)%n_stored
                if (r == 0) cycle
                histories(m)%contact_energy(r) = member%contact_energy
                histories(m)%contact_force(:, r) = member%contact_force
                histories(m)%penetration(r) = member%penetration
                histories(m)%tie_force(:, :, r) = member%tie_force
            end associate
        end do
    end subroutine bundle_record

    function bundle_describe(this) result(text)
        class(ph_bundle_t), intent(in) :: this
        character(len=:), allocatable :: text
        integer :: m, n_plate
        n_plate = count(this%ties%plate > 0)
        text = 'bundle of ' // str(size(this%members)) // ' ph_director rods ('
        do m = 1, size(this%members)
            if (m > 1) text = text // ', '
            text = text // this%members(m)%rod%name
        end do
        text = text // '): ' // str(size(this%ties) - n_plate) // ' joints, ' // str(n_plate) // &
            ' plate ties, contact ' // trim(merge('on ', 'off', this%contact)) // ', ' // &
            str(this%n_unknown_total) // ' Newton unknowns, ' // str(this%pattern%nnz()) // &
            ' Jacobian non-zeros'
        if (this%n_ranks > 1) text = text // new_line('a') // this%partition_summary()
    end function bundle_describe

    !> One line per rank: its rods and unknowns (the partition, logged at the start).
    function partition_summary(this) result(text)
        class(ph_bundle_t), intent(in) :: this
        character(len=:), allocatable :: text
        integer :: p, m, n
        text = 'bundle partition over ' // str(this%n_ranks) // ' ranks (METIS on the coupling graph):'
        do p = 0, this%n_ranks - 1
            n = 0
            text = text // new_line('a') // '  rank ' // str(p) // ':'
            do m = 1, size(this%members)
                if (this%members(m)%part /= p) cycle
                text = text // ' ' // this%members(m)%rod%name
                n = n + this%members(m)%rod%n_unknown()
            end do
            text = text // ' (' // str(n) // ' rod unknowns)'
        end do
    end function partition_summary

    !> The traits of a bundle (the energy scheme stays unchecked: the bundle books no step
    !> energy for the sentinel; the LU pivots, for the tie multipliers):
    !> - full Newton steps: the tie rows (positions, in m) and the momentum rows (h times
    !>   forces) have different scales, and backtracking on their joint norm takes tiny steps
    !>   where the full step converges quadratically (measured on the strand scenes,
    !>   docs/theory/bundles.md); a failed step is still halved by the stepper;
    !> - quasistatic runs end with the endpoint equilibrium, one Newton solve (no continuation).
    pure function bundle_traits(this) result(traits)
        class(ph_bundle_t), intent(in) :: this
        type(formulation_traits_t) :: traits
        traits%full_newton = .true.
        traits%wants_endpoint_solve = this%quasistatic
    end function bundle_traits

    subroutine bundle_set_endpoint_solve(this, on, t_load)
        class(ph_bundle_t), intent(inout) :: this
        logical, intent(in) :: on
        real(rk), intent(in) :: t_load
        integer :: m
        this%static = on
        this%t_static = t_load
        do m = 1, size(this%members)
            call this%members(m)%rod%set_endpoint_solve(on, t_load)
        end do
    end subroutine bundle_set_endpoint_solve

    pure integer function bundle_n_internal(this)
        class(ph_bundle_t), intent(in) :: this
        integer :: m
        bundle_n_internal = 0
        do m = 1, size(this%members)
            bundle_n_internal = bundle_n_internal + this%members(m)%rod%n_internal()
        end do
    end function bundle_n_internal

    subroutine bundle_save_internal(this, values)
        class(ph_bundle_t), intent(in) :: this
        real(rk), intent(out) :: values(:)
        integer :: m, at, n
        at = 0
        do m = 1, size(this%members)
            n = this%members(m)%rod%n_internal()
            call this%members(m)%rod%save_internal(values(at + 1:at + n))
            at = at + n
        end do
    end subroutine bundle_save_internal

    subroutine bundle_restore_internal(this, values)
        class(ph_bundle_t), intent(inout) :: this
        real(rk), intent(in) :: values(:)
        integer :: m, at, n
        at = 0
        do m = 1, size(this%members)
            n = this%members(m)%rod%n_internal()
            call this%members(m)%rod%restore_internal(values(at + 1:at + n))
            at = at + n
        end do
    end subroutine bundle_restore_internal

    !> The state in the layout of one rank (checkpoints do not depend on the partition).
    subroutine bundle_canonical_state(this, x, canonical)
        class(ph_bundle_t), intent(in) :: this
        real(rk), intent(in) :: x(:)
        real(rk), intent(out) :: canonical(:)
        integer :: m, t, n
        do m = 1, size(this%members)
            associate (member => this%members(m))
                n = member%rod%n_state()
                canonical(member%canonical_offset + 1:member%canonical_offset + n) = &
                    x(member%state_offset + 1:member%state_offset + n)
            end associate
        end do
        do t = 1, size(this%ties)
            associate (tie => this%ties(t))
                canonical(tie%canonical_offset + 1:tie%canonical_offset + tie%tie%n) = &
                    x(tie%state_offset + 1:tie%state_offset + tie%tie%n)
            end associate
        end do
    end subroutine bundle_canonical_state

    subroutine bundle_from_canonical(this, canonical, x)
        class(ph_bundle_t), intent(in) :: this
        real(rk), intent(in) :: canonical(:)
        real(rk), intent(out) :: x(:)
        integer :: m, t, n
        do m = 1, size(this%members)
            associate (member => this%members(m))
                n = member%rod%n_state()
                x(member%state_offset + 1:member%state_offset + n) = &
                    canonical(member%canonical_offset + 1:member%canonical_offset + n)
            end associate
        end do
        do t = 1, size(this%ties)
            associate (tie => this%ties(t))
                x(tie%state_offset + 1:tie%state_offset + tie%tie%n) = &
                    canonical(tie%canonical_offset + 1:tie%canonical_offset + tie%tie%n)
            end associate
        end do
    end subroutine bundle_from_canonical

    ! ---- The coupling graph ---------------------------------------------------------------

    !> Rods as vertices weighted by their unknowns; edges for joints, rods on one plate
    !> (consecutive ones: a chain keeps the graph sparse) and contact candidate pairs of the
    !> reference configuration.
    subroutine bundle_coupling_graph(this, xadj, adjncy, weights)
        class(ph_bundle_t), intent(in) :: this
        integer, allocatable, intent(out) :: xadj(:), adjncy(:), weights(:)
        logical :: edge(size(this%members), size(this%members))
        integer :: t, k, m, n, previous
        edge = .false.
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
        do k = 1, size(this%pattern_pairs, 2)
            call connect(this%pattern_pairs(1, k), this%pattern_pairs(3, k))
        end do
        n = size(this%members)
        allocate(xadj(n + 1), weights(n))
        allocate(adjncy(count(edge)))
        xadj(1) = 0
        k = 0
        do m = 1, n
            do t = 1, n
                if (.not. edge(t, m)) cycle
                k = k + 1
                adjncy(k) = t - 1
            end do
            xadj(m + 1) = k
            weights(m) = this%members(m)%rod%n_unknown()
        end do
    contains
        subroutine connect(a, b)
            integer, intent(in) :: a, b
            if (a == b) return
            edge(a, b) = .true.
            edge(b, a) = .true.
        end subroutine connect
    end subroutine bundle_coupling_graph

end module rs_ph_bundle
