#include "rs_macros.h"
!> A system of rods (issue 22; DESIGN.md §2, §5): what every run steps through time, a single
!> rod included. It owns its members (formulation objects: one per rod, or one for the rods a
!> formulation joins itself through shared unknowns, ph_planar), their offsets and owned ranges
!> (rs_system_layout), the couplings between them (rs_system_coupling: ties and contact, for
!> every formulation that offers node access), the Jacobian pattern, the record ledger
!> (rs_system_ledger) and the checkpoint layout; it assembles the step residual and Jacobian
!> from the members' and the couplings' terms. Pure Fortran: no PETSc, no MPI (the solver,
!> src/solver/rod_run.F90, drives it and gathers X_n and Y on every rank).
!>
!> A system of one member without couplings passes every call straight to the member (offsets
!> 0, the member's own pattern): a single rod pays nothing for the layer.
!>
!> What is kept exactly (docs/theory/bundles.md): with joints, fixed plates and contact the
!> discrete energy H + E_contact is conserved to the Newton tolerance without loads (every
!> coupling force is an exact discrete gradient); joints and contact exert no net force or
!> torque, so linear and angular momentum are kept without supports; ties hold to round-off.
!> The per-rod energy balance books the work of the coupling forces on the rod as external
!> work, so each rod's balance_error stays at the Newton tolerance.
module rs_system_rod_system
    use rs_core_kinds, only: rk
    use rs_core_error, only: error_t, set_error
    use rs_core_strings, only: str, str_significant
    use rs_model_scene, only: scene_t, unset_real
    use rs_model_rod_history, only: rod_history_t
    use rs_assembly_csr_pattern, only: csr_builder_t, csr_pattern_t
    use rs_formulations_formulation, only: rod_formulation_t, formulation_traits_t, &
        state_measures_t, state_valid, state_invalid, max_node_coordinates
    use rs_math_so3, only: tangent_so3, nearest_rotation_vector
    use rs_formulations_energy_sentinel, only: step_energy_t
    use rs_formulations_descriptor, only: formulation_descriptor_t
    use rs_formulations_registry, only: descriptor_of
    use rs_formulations_factory, only: create_formulation
    use rs_system_layout, only: system_layout_t
    use rs_system_ledger, only: record_ledger_t, ledger_entries
    use rs_system_coupling, only: coupling_t, coupling_slot_t, coupling_record_t, &
        friction_record_t
    use rs_system_tie_coupling, only: tie_coupling_t, tie_coupling_init, tie_maker_t
    use rs_system_contact_coupling, only: contact_coupling_t, contact_coupling_init
    use rs_system_obstacle_coupling, only: obstacle_coupling_t, obstacle_coupling_init
    implicit none
    private

    !> A member: its formulation object and where its Jacobian entries go.
    type :: member_t
        class(rod_formulation_t), allocatable :: rod
        character(len=:), allocatable :: name
        !> Global CSR position of each entry of the member's own Jacobian pattern.
        integer, allocatable :: value_map(:)
        real(rk), allocatable :: values(:)
        !> The member's own pattern (0-based).
        integer, allocatable :: row_ptr(:), cols(:)
    end type member_t

    type, public :: rod_system_t
        type(member_t), allocatable :: members(:)
        type(coupling_slot_t), allocatable :: couplings(:)
        type(system_layout_t) :: layout
        type(record_ledger_t) :: ledger
        type(csr_pattern_t) :: pattern
        !> One member without couplings: every call goes straight to it.
        logical :: direct = .true.
        !> In the endpoint equilibrium solve.
        logical :: static = .false.
        !> The scene is quasistatic; a joint ties two members (for the choice of the linear
        !> solver, solver_blocks).
        logical :: quasistatic = .false.
        logical :: joined = .false.
        !> The system has ties (joints or plates: tie_coupling).
        logical :: tied = .false.
        integer :: n_rods = 0
        character(len=:), allocatable :: formulation
        !> The energy terms of the last accepted step summed over the rods (the sentinel's).
        type(step_energy_t) :: step_energy
        !> Coupling results of the members for the records.
        type(coupling_record_t), allocatable :: coupling_records(:)
        !> The friction of the last accepted step on each member (recorded with the state).
        type(friction_record_t), allocatable :: step_friction(:)
        !> Work arrays of the book-keeping (kept between steps: no allocation in the time loop).
        real(rk), allocatable :: work_y(:), work_force(:), work_x(:)
        type(step_energy_t), allocatable :: terms(:)
    contains
        procedure :: init => system_init
        procedure :: n_state => system_n_state
        procedure :: n_unknown => system_n_unknown
        procedure :: jacobian_pattern => system_jacobian_pattern
        procedure :: initial_state => system_initial_state
        procedure :: predictor => system_predictor
        procedure :: update => system_update
        procedure :: step_residual => system_step_residual
        procedure :: step_admissible => system_step_admissible
        procedure :: refuses_iterates => system_refuses_iterates
        procedure :: step_jacobian => system_step_jacobian
        !> dF/dX_n (rod_formulation_t%state_jacobian): one rod's; refused (state_invalid) for
        !> coupled systems, whose couplings have none.
        procedure :: state_jacobian => system_state_jacobian
        !> Book an accepted step: the members' energy terms and the Newton statistics in the
        !> ledger, the work of the couplings on each rod; step_energy for the sentinel.
        procedure :: accept_step => system_accept_step
        procedure :: init_history => system_init_history
        procedure :: record => system_record
        procedure :: describe => system_describe
        procedure :: traits => system_traits
        procedure :: set_step_problem => system_set_step_problem
        !> The statics at load time t_load as the step problem (arc-length continuation,
        !> docs/theory/continuation.md); the first call gives `base`, the state the path goes
        !> on from. Then step_residual(t_n, h, base, y) with (t_n, h) = load_step(t_load) is
        !> the equilibrium residual R(Y; t_load), its rows scaled as a step of unit length.
        procedure :: set_load_problem => system_set_load_problem
        procedure :: load_step => system_load_step
        !> The members' path weights (rod_formulation_t%path_weights) over the system's
        !> unknowns, each member's share over the number of members.
        procedure :: path_weights => system_path_weights
        !> The row of the generalized force conjugate to each step unknown (force_rows).
        procedure :: force_rows => system_force_rows
        procedure :: state_measures => system_state_measures
        !> Each member's state brought to rest (rod_formulation_t%rest_state).
        procedure :: rest_state => system_rest_state
        !> Linearized buckling's stress stiffness (rod_formulation_t%stress_only): with
        !> `loaded`, every member's stresses held at those of its part of `loaded`, and the
        !> couplings' forces (their multipliers' state entries) of `loaded` copied into x, the
        !> state to linearize about; without, the elastic rods again. `available` false when
        !> a member cannot (then none is changed).
        procedure :: stress_only => system_stress_only
        !> The members' error entries (rs_formulations_formulation); coupling unknowns are not.
        procedure :: error_entries => system_error_entries
        !> Before each step from X_n: the couplings refresh what the step needs (contact
        !> pairs); `repattern` when the Jacobian pattern changed.
        procedure :: prepare_step => system_prepare_step
        !> The members as the vertices of the coupling graph in CSR form (0-based adjncy),
        !> weighted by their unknowns; empty for a system without couplings.
        procedure :: coupling_graph => system_coupling_graph
        !> Give the members to ranks (part(m) = rank of member m) and say which rank this is.
        procedure :: distribute => system_distribute
        !> The 0-based half-open ranges [lo, hi) of the state and the unknowns this rank owns.
        procedure :: owned_range => system_owned_range
        !> The 0-based entries of the state and of the unknowns this rank's rows read (the
        !> members its rows couple to, whole), for the gathers of a shared system.
        procedure :: needed_entries => system_needed_entries
        !> The state in the layout of one rank (checkpoints, DESIGN.md §7), and back.
        procedure :: canonical_state => system_canonical_state
        procedure :: from_canonical => system_from_canonical
        !> The ledger's checkpoint entries (ledger_entries per rod) and back.
        procedure :: n_ledger => system_n_ledger
        procedure :: save_ledger => system_save_ledger
        procedure :: restore_ledger => system_restore_ledger
        procedure :: has_couplings
        !> The blocks of block Jacobi for the linear solver (one per member with its coupling
        !> unknowns, in the order of the unknowns), or none where one LU of the whole system
        !> is faster (docs/performance.md, "Bundles: block Jacobi").
        procedure :: solver_blocks
    end type rod_system_t

    !> Members from which block Jacobi beats one LU of a dynamic coupled system without joints
    !> (docs/performance.md, "Bundles: block Jacobi": 2 crossing rods 1.3 times slower, the
    !> 7-wire strand 1.8 times faster, 19 wires 4.7, 37 wires 10.9).
    integer, parameter :: block_jacobi_members = 7

contains

    ! ---- Construction ---------------------------------------------------------------------

    !> Build the system of the scene's rods `rods` (a coupled set, rs_model_coupling; the first
    !> leads): its members from the formulation's descriptor, their layout on one rank, the
    !> couplings the scene declares among them.
    subroutine system_init(this, scene, rods, err)
        class(rod_system_t), intent(inout) :: this
        type(scene_t), intent(in) :: scene
        integer, intent(in) :: rods(:)
        type(error_t), allocatable, intent(out) :: err
        type(formulation_descriptor_t) :: d
        integer :: m, n_members, first
        this%formulation = trim(scene%rods(rods(1))%formulation)
        ! One member per rod where the couplings are the system's; one member for the rods a
        ! formulation joins itself (an unknown name: one member, whose creation reports it).
        n_members = 1
        if (descriptor_of(this%formulation, d)) n_members = merge(size(rods), 1, d%system_couplings)
        allocate(this%members(n_members))
        allocate(this%layout%members(n_members))
        first = 1
        do m = 1, n_members
            call create_formulation(this%formulation, this%members(m)%rod, err)
            RS_RETURN_IF_ERROR(err)
            if (d%system_couplings) then
                call this%members(m)%rod%init(scene, [rods(m)], err)
                this%layout%members(m)%n_rods = 1
                this%members(m)%name = trim(scene%rods(rods(m))%name)
            else
                call this%members(m)%rod%init(scene, rods, err)
                this%layout%members(m)%n_rods = size(rods)
                this%members(m)%name = trim(scene%rods(rods(1))%name)
            end if
            RS_RETURN_IF_ERROR(err)
            associate (member => this%members(m), place => this%layout%members(m))
                place%first_rod = first
                first = first + place%n_rods
                place%n_state = member%rod%n_state()
                place%n_unknown = member%rod%n_unknown()
                place%nodes = member%rod%nodes()
                place%contact_radius = scene%rods(rods(m))%contact_radius
                if (place%contact_radius == unset_real) place%contact_radius = scene%rods(rods(m))%radius
                call member%rod%jacobian_pattern(member%row_ptr, member%cols)
                allocate(member%values(size(member%cols)))
            end associate
        end do
        this%n_rods = first - 1
        this%quasistatic = scene%time%quasistatic
        call this%ledger%init(this%n_rods)
        allocate(this%terms(this%n_rods))
        allocate(this%couplings(0))
        if (d%system_couplings) call read_couplings(this, scene, err)
        RS_RETURN_IF_ERROR(err)
        this%direct = n_members == 1 .and. size(this%couplings) == 0
        allocate(this%coupling_records(n_members), this%step_friction(n_members))
        call this%distribute([(0, m = 1, n_members)], 0)
    end subroutine system_init

    !> The ties (joints, plates), contact and obstacles the scene declares for the members.
    subroutine read_couplings(this, scene, err)
        type(rod_system_t), intent(inout), target :: this
        type(scene_t), intent(in) :: scene
        type(error_t), allocatable, intent(out) :: err
        type(tie_coupling_t), allocatable :: ties
        type(contact_coupling_t), allocatable :: contact
        type(obstacle_coupling_t), allocatable :: obstacles
        character(len=64) :: names(size(this%members))
        integer, allocatable :: joint_ends(:, :)
        type(coupling_slot_t), allocatable :: list(:)
        type(formulation_traits_t) :: traits
        type(tie_maker_t) :: makers(size(this%members))
        character(len=:), allocatable :: message
        integer :: m, n
        do m = 1, size(this%members)
            names(m) = this%members(m)%name
        end do
        allocate(list(3))
        n = 0
        allocate(joint_ends(4, 0))
        if (any_ties(scene)) then
            allocate(ties)
            do m = 1, size(this%members)
                makers(m)%rod => this%members(m)%rod
            end do
            call tie_coupling_init(ties, scene, names, this%layout, makers, err)
            RS_RETURN_IF_ERROR(err)
            if (ties%count_ties() > 0) then
                this%tied = .true.
                joint_ends = ties%joint_ends()
                this%joined = size(joint_ends, 2) > 0
                n = n + 1
                call move_alloc(ties, list(n)%coupling)
            end if
        end if
        if (scene%contact%given) then
            allocate(contact)
            call contact_coupling_init(contact, scene, this%layout, joint_ends, err)
            RS_RETURN_IF_ERROR(err)
            n = n + 1
            call move_alloc(contact, list(n)%coupling)
        end if
        if (allocated(scene%obstacles)) then
            if (size(scene%obstacles) > 0) then
                allocate(obstacles)
                call obstacle_coupling_init(obstacles, scene, this%layout, err)
                RS_RETURN_IF_ERROR(err)
                n = n + 1
                call move_alloc(obstacles, list(n)%coupling)
            end if
        end if
        deallocate(this%couplings)
        allocate(this%couplings(n))
        traits = this%members(1)%rod%traits()
        do m = 1, n
            call move_alloc(list(m)%coupling, this%couplings(m)%coupling)
            this%couplings(m)%coupling%equilibrium_steps = traits%equilibrium_steps
        end do
        if (n == 0) return
        do m = 1, size(this%members)
            if (this%layout%members(m)%nodes%n_nodes > 0 .and. &
                .not. this%layout%members(m)%nodes%held_moves) cycle
            if (this%layout%members(m)%nodes%n_nodes == 0) then
                message = 'rod ''' // this%members(m)%name // ''': its formulation (' // &
                    this%formulation // ') offers no node access, so it cannot be coupled ' // &
                    '(joints, plates, contact; docs/user/capabilities.md)'
            else
                message = 'rod ''' // this%members(m)%name // ''': an end driven in time ' // &
                    'cannot be coupled yet (joints, plates, contact) in ' // this%formulation
            end if
            RS_SET_ERROR(err, 'rod_system%init', message)
            return
        end do
    end subroutine read_couplings

    pure logical function any_ties(scene)
        type(scene_t), intent(in) :: scene
        any_ties = .false.
        if (allocated(scene%joints)) any_ties = size(scene%joints) > 0
        if (allocated(scene%plates)) any_ties = any_ties .or. size(scene%plates) > 0
    end function any_ties

    !> Block Jacobi over the members where it was measured faster than one LU: a dynamic
    !> system (the rods' mass makes their own blocks dominant; in statics the contact couples
    !> them as strongly as their stiffness: 2.9 times slower on the seven-wire strand's
    !> statics, 1.6 on the pressed rods), without joints (a joint's multipliers tie two blocks:
    !> 20 times slower on the jointed chain), of at least block_jacobi_members members.
    function solver_blocks(this) result(lengths)
        class(rod_system_t), intent(in) :: this
        integer, allocatable :: lengths(:)
        integer :: order(size(this%members)), m, k, next, n_state
        allocate(lengths(0))
        if (this%quasistatic .or. this%joined .or. size(this%members) < block_jacobi_members) return
        ! Members in the order of their unknowns (by rank, then scene order); each block is the
        ! member's unknowns with the coupling blocks it owns (member_extent).
        order = [(m, m = 1, size(this%members))]
        do m = 2, size(order)
            k = order(m)
            next = m - 1
            do while (next >= 1)
                if (this%layout%members(order(next))%unknown_offset <= &
                    this%layout%members(k)%unknown_offset) exit
                order(next + 1) = order(next)
                next = next - 1
            end do
            order(next + 1) = k
        end do
        deallocate(lengths)
        allocate(lengths(size(order)))
        do m = 1, size(order)
            call member_extent(this, order(m), n_state, lengths(m))
        end do
    end function solver_blocks

    pure logical function has_couplings(this)
        class(rod_system_t), intent(in) :: this
        has_couplings = size(this%couplings) > 0
    end function has_couplings

    ! ---- Layout and pattern ---------------------------------------------------------------

    !> Members to ranks: lay out the state and the unknowns rank by rank, let the couplings
    !> start from the initial state in that layout and build the Jacobian pattern.
    subroutine system_distribute(this, part, rank)
        class(rod_system_t), intent(inout) :: this
        integer, intent(in) :: part(:), rank
        real(rk), allocatable :: x(:)
        integer :: p, m, c, b, so, uo
        associate (layout => this%layout)
            ! The canonical layout: every member on one rank, in scene order.
            so = 0
            do m = 1, size(layout%members)
                layout%members(m)%canonical_offset = so
                so = so + layout%members(m)%n_state
                do c = 1, size(this%couplings)
                    associate (blocks => this%couplings(c)%coupling%blocks)
                        do b = 1, size(blocks)
                            if (blocks(b)%owner /= m) cycle
                            blocks(b)%canonical_offset = so
                            so = so + blocks(b)%size
                        end do
                    end associate
                end do
            end do
            layout%rank = rank
            layout%n_ranks = maxval(part) + 1
            layout%members%part = part
            so = 0
            uo = 0
            layout%state_lo = -1
            do p = 0, layout%n_ranks - 1
                if (p == rank) then
                    layout%state_lo = so
                    layout%unknown_lo = uo
                end if
                do m = 1, size(layout%members)
                    if (part(m) /= p) cycle
                    layout%members(m)%state_offset = so
                    layout%members(m)%unknown_offset = uo
                    so = so + layout%members(m)%n_state
                    uo = uo + layout%members(m)%n_unknown
                    do c = 1, size(this%couplings)
                        associate (blocks => this%couplings(c)%coupling%blocks)
                            do b = 1, size(blocks)
                                if (blocks(b)%owner /= m) cycle
                                blocks(b)%state_offset = so
                                blocks(b)%unknown_offset = uo
                                so = so + blocks(b)%size
                                uo = uo + blocks(b)%size
                            end do
                        end associate
                    end do
                end do
                if (p == rank) then
                    layout%state_hi = so
                    layout%unknown_hi = uo
                end if
            end do
            if (layout%state_lo < 0) then
                ! A rank without members owns an empty range.
                layout%state_lo = so
                layout%state_hi = so
                layout%unknown_lo = uo
                layout%unknown_hi = uo
            end if
            layout%n_state = so
            layout%n_unknown = uo
        end associate
        if (this%direct) return
        allocate(x(this%layout%n_state))
        call this%initial_state(x)
        do c = 1, size(this%couplings)
            call this%couplings(c)%coupling%start(this%layout, x)
        end do
        call build_pattern(this)
    end subroutine system_distribute

    !> The global pattern: each member's own pattern as a diagonal block, then the couplings'
    !> blocks; the maps from the pieces into it.
    subroutine build_pattern(this)
        type(rod_system_t), intent(inout) :: this
        type(csr_builder_t) :: builder
        integer :: m, i, p, uo, c, n_expected
        n_expected = 0
        do m = 1, size(this%members)
            n_expected = n_expected + size(this%members(m)%cols)
        end do
        do c = 1, size(this%couplings)
            n_expected = n_expected + this%couplings(c)%coupling%pattern_entries()
        end do
        call builder%init(this%layout%n_unknown, n_expected)
        do m = 1, size(this%members)
            associate (member => this%members(m))
                uo = this%layout%members(m)%unknown_offset
                do i = 1, size(member%row_ptr) - 1
                    p = member%row_ptr(i) + 1
                    call builder%add_block([uo + i], uo + 1 + member%cols(p:member%row_ptr(i + 1)))
                end do
            end associate
        end do
        do c = 1, size(this%couplings)
            call this%couplings(c)%coupling%add_pattern(this%layout, builder)
        end do
        call builder%build(this%pattern)
        do m = 1, size(this%members)
            associate (member => this%members(m))
                uo = this%layout%members(m)%unknown_offset
                if (allocated(member%value_map)) deallocate(member%value_map)
                allocate(member%value_map(size(member%cols)))
                do i = 1, size(member%row_ptr) - 1
                    do p = member%row_ptr(i) + 1, member%row_ptr(i + 1)
                        member%value_map(p) = this%pattern%position(uo + i, uo + 1 + member%cols(p))
                    end do
                end do
            end associate
        end do
        do c = 1, size(this%couplings)
            call this%couplings(c)%coupling%map_pattern(this%layout, this%pattern)
        end do
    end subroutine build_pattern

    ! ---- Sizes and states -----------------------------------------------------------------

    pure integer function system_n_state(this)
        class(rod_system_t), intent(in) :: this
        system_n_state = this%layout%n_state
    end function system_n_state

    pure integer function system_n_unknown(this)
        class(rod_system_t), intent(in) :: this
        system_n_unknown = this%layout%n_unknown
    end function system_n_unknown

    subroutine system_owned_range(this, state_lo, state_hi, unknown_lo, unknown_hi)
        class(rod_system_t), intent(in) :: this
        integer, intent(out) :: state_lo, state_hi, unknown_lo, unknown_hi
        state_lo = this%layout%state_lo
        state_hi = this%layout%state_hi
        unknown_lo = this%layout%unknown_lo
        unknown_hi = this%layout%unknown_hi
    end subroutine system_owned_range

    !> A shared system's residual and Jacobian on this rank read the state and the unknowns
    !> of its own members and of the members its rows couple to (the columns of its rows in
    !> the Jacobian pattern: contact neighbours, tied rods), each member whole with the coupling
    !> blocks it owns; rod_stepper.c gathers only these before each evaluation instead of the
    !> whole system (docs/performance.md, "Bundles: block Jacobi over the rods").
    subroutine system_needed_entries(this, state_entries, unknown_entries)
        class(rod_system_t), intent(in) :: this
        integer, allocatable, intent(out) :: state_entries(:), unknown_entries(:)
        logical :: column(this%layout%n_unknown), needed(size(this%members))
        integer :: m, r, n_state, n_unknown, i
        column = .false.
        do r = this%layout%unknown_lo + 1, this%layout%unknown_hi
            column(this%pattern%cols(this%pattern%row_ptr(r):this%pattern%row_ptr(r + 1) - 1)) = &
                .true.
        end do
        do m = 1, size(this%members)
            call member_extent(this, m, n_state, n_unknown)
            associate (place => this%layout%members(m))
                needed(m) = this%layout%owns_member(m) .or. &
                    any(column(place%unknown_offset + 1:place%unknown_offset + n_unknown))
            end associate
        end do
        allocate(state_entries(0), unknown_entries(0))
        do m = 1, size(this%members)
            if (.not. needed(m)) cycle
            call member_extent(this, m, n_state, n_unknown)
            associate (place => this%layout%members(m))
                state_entries = [state_entries, (place%state_offset + i - 1, i = 1, n_state)]
                unknown_entries = [unknown_entries, &
                    (place%unknown_offset + i - 1, i = 1, n_unknown)]
            end associate
        end do
    end subroutine system_needed_entries

    !> Entries of member m in the state and the unknowns with the coupling blocks it owns
    !> (laid out after it, system_distribute).
    subroutine member_extent(this, m, n_state, n_unknown)
        type(rod_system_t), intent(in) :: this
        integer, intent(in) :: m
        integer, intent(out) :: n_state, n_unknown
        integer :: c, b
        n_state = this%layout%members(m)%n_state
        n_unknown = this%layout%members(m)%n_unknown
        do c = 1, size(this%couplings)
            associate (blocks => this%couplings(c)%coupling%blocks)
                do b = 1, size(blocks)
                    if (blocks(b)%owner /= m) cycle
                    n_state = n_state + blocks(b)%size
                    n_unknown = n_unknown + blocks(b)%size
                end do
            end associate
        end do
    end subroutine member_extent

    subroutine system_jacobian_pattern(this, row_ptr, cols)
        class(rod_system_t), intent(in) :: this
        integer, allocatable, intent(out) :: row_ptr(:), cols(:)
        if (this%direct) then
            row_ptr = this%members(1)%row_ptr
            cols = this%members(1)%cols
        else
            call this%pattern%zero_based(row_ptr, cols)
        end if
    end subroutine system_jacobian_pattern

    subroutine system_error_entries(this, weigh)
        class(rod_system_t), intent(in) :: this
        logical, intent(out) :: weigh(:)
        integer :: m
        if (this%direct) then
            call this%members(1)%rod%error_entries(weigh)
            return
        end if
        weigh = .false.
        do m = 1, size(this%members)
            associate (place => this%layout%members(m))
                call this%members(m)%rod%error_entries(weigh(place%state_offset + 1: &
                    place%state_offset + place%n_state))
            end associate
        end do
    end subroutine system_error_entries

    !> Each member's initial state; coupling unknowns (multipliers) start at zero.
    subroutine system_initial_state(this, x)
        class(rod_system_t), intent(in) :: this
        real(rk), intent(out) :: x(:)
        integer :: m
        if (this%direct) then
            call this%members(1)%rod%initial_state(x)
            return
        end if
        x = 0.0_rk
        do m = 1, size(this%members)
            associate (place => this%layout%members(m))
                call this%members(m)%rod%initial_state(x(place%state_offset + 1:place%state_offset + &
                    place%n_state))
            end associate
        end do
    end subroutine system_initial_state

    subroutine system_predictor(this, t_n, h, x_n, y)
        class(rod_system_t), intent(inout) :: this
        real(rk), intent(in) :: t_n, h, x_n(:)
        real(rk), intent(out) :: y(:)
        integer :: m
        if (this%direct) then
            call this%members(1)%rod%predictor(t_n, h, x_n, y)
            return
        end if
        y = 0.0_rk
        do m = 1, size(this%members)
            if (.not. this%layout%owns_member(m)) cycle
            associate (place => this%layout%members(m))
                call this%members(m)%rod%predictor(t_n, h, &
                    x_n(place%state_offset + 1:place%state_offset + place%n_state), &
                    y(place%unknown_offset + 1:place%unknown_offset + place%n_unknown))
            end associate
        end do
        call unknown_blocks_from_state(this, x_n, y, owned_only=.true.)
    end subroutine system_predictor

    subroutine system_update(this, t_n, h, x_n, y, x_1)
        class(rod_system_t), intent(inout) :: this
        real(rk), intent(in) :: t_n, h, x_n(:), y(:)
        real(rk), intent(out) :: x_1(:)
        integer :: m
        if (this%direct) then
            call this%members(1)%rod%update(t_n, h, x_n, y, x_1)
            return
        end if
        x_1 = 0.0_rk
        do m = 1, size(this%members)
            if (.not. this%layout%owns_member(m)) cycle
            associate (place => this%layout%members(m))
                call this%members(m)%rod%update(t_n, h, &
                    x_n(place%state_offset + 1:place%state_offset + place%n_state), &
                    y(place%unknown_offset + 1:place%unknown_offset + place%n_unknown), &
                    x_1(place%state_offset + 1:place%state_offset + place%n_state))
            end associate
        end do
        call copy_coupling_blocks(this, y, .false., x_1, .true., owned_only=.true.)
    end subroutine system_update

    !> The couplings' unknowns (multipliers) of y from their state in x (all, or this rank's).
    subroutine unknown_blocks_from_state(this, x, y, owned_only)
        type(rod_system_t), intent(in) :: this
        real(rk), intent(in) :: x(:)
        real(rk), intent(inout) :: y(:)
        logical, intent(in) :: owned_only
        call copy_coupling_blocks(this, x, .true., y, .false., owned_only)
    end subroutine unknown_blocks_from_state

    !> The couplings' blocks (multipliers) of `from` into `to`, each a state (its blocks at
    !> their state offsets) or step unknowns (at their unknown offsets): all, or this rank's.
    subroutine copy_coupling_blocks(this, from, from_state, to, to_state, owned_only)
        type(rod_system_t), intent(in) :: this
        real(rk), intent(in) :: from(:)
        logical, intent(in) :: from_state, to_state, owned_only
        real(rk), intent(inout) :: to(:)
        integer :: c, b, source, target
        do c = 1, size(this%couplings)
            associate (blocks => this%couplings(c)%coupling%blocks)
                do b = 1, size(blocks)
                    if (owned_only .and. .not. this%layout%owns_member(blocks(b)%owner)) cycle
                    source = merge(blocks(b)%state_offset, blocks(b)%unknown_offset, from_state)
                    target = merge(blocks(b)%state_offset, blocks(b)%unknown_offset, to_state)
                    to(target + 1:target + blocks(b)%size) = &
                        from(source + 1:source + blocks(b)%size)
                end do
            end associate
        end do
    end subroutine copy_coupling_blocks

    ! ---- The step problem -----------------------------------------------------------------

    !> Every coupling admits the iterate y of the step from x_n (system_step_residual reports
    !> an invalid state otherwise); this rank's part.
    logical function system_step_admissible(this, t_n, h, x_n, y) result(ok)
        class(rod_system_t), intent(inout) :: this
        real(rk), intent(in) :: t_n, h, x_n(:), y(:)
        integer :: c
        ok = .true.
        if (this%direct) return
        do c = 1, size(this%couplings)
            ok = this%couplings(c)%coupling%admissible(this%layout, t_n, x_n, y)
            if (.not. ok) return
        end do
    end function system_step_admissible

    !> A coupling may refuse Newton iterates (coupling_t%refuses_iterates: contact).
    logical function system_refuses_iterates(this) result(refuses)
        class(rod_system_t), intent(in) :: this
        integer :: c
        refuses = .false.
        if (this%direct) return
        do c = 1, size(this%couplings)
            refuses = refuses .or. this%couplings(c)%coupling%refuses_iterates
        end do
    end function system_refuses_iterates

    subroutine system_step_residual(this, t_n, h, x_n, y, f, status)
        class(rod_system_t), intent(inout) :: this
        real(rk), intent(in) :: t_n, h, x_n(:), y(:)
        real(rk), intent(out) :: f(:)
        integer, intent(out) :: status
        integer :: m, c
        if (this%direct) then
            call this%members(1)%rod%step_residual(t_n, h, x_n, y, f, status)
            return
        end if
        ! Only this rank's rows are filled and read (rod_stepper.c takes the owned part).
        f(this%layout%unknown_lo + 1:this%layout%unknown_hi) = 0.0_rk
        status = state_valid
        do c = 1, size(this%couplings)
            if (this%couplings(c)%coupling%admissible(this%layout, t_n, x_n, y)) cycle
            status = state_invalid
            return
        end do
        do m = 1, size(this%members)
            if (.not. this%layout%owns_member(m)) cycle
            associate (place => this%layout%members(m))
                call this%members(m)%rod%step_residual(t_n, h, &
                    x_n(place%state_offset + 1:place%state_offset + place%n_state), &
                    y(place%unknown_offset + 1:place%unknown_offset + place%n_unknown), &
                    f(place%unknown_offset + 1:place%unknown_offset + place%n_unknown), status)
            end associate
            if (status /= state_valid) return
        end do
        do c = 1, size(this%couplings)
            call this%couplings(c)%coupling%add_residual(this%layout, t_n, h, x_n, y, f, .false.)
        end do
    end subroutine system_step_residual

    subroutine system_step_jacobian(this, t_n, h, x_n, y, values, status)
        class(rod_system_t), intent(inout) :: this
        real(rk), intent(in) :: t_n, h, x_n(:), y(:)
        real(rk), intent(out) :: values(:)
        integer, intent(out) :: status
        integer :: m, p, c
        if (this%direct) then
            call this%members(1)%rod%step_jacobian(t_n, h, x_n, y, values, status)
            return
        end if
        ! Only this rank's rows are filled and read (rod_stepper.c takes the owned part).
        values(this%pattern%row_ptr(this%layout%unknown_lo + 1): &
            this%pattern%row_ptr(this%layout%unknown_hi + 1) - 1) = 0.0_rk
        status = state_valid
        do m = 1, size(this%members)
            if (.not. this%layout%owns_member(m)) cycle
            associate (member => this%members(m), place => this%layout%members(m))
                call member%rod%step_jacobian(t_n, h, &
                    x_n(place%state_offset + 1:place%state_offset + place%n_state), &
                    y(place%unknown_offset + 1:place%unknown_offset + place%n_unknown), &
                    member%values, status)
                if (status /= state_valid) return
                do p = 1, size(member%values)
                    values(member%value_map(p)) = values(member%value_map(p)) + member%values(p)
                end do
            end associate
        end do
        do c = 1, size(this%couplings)
            call this%couplings(c)%coupling%add_jacobian(this%layout, this%pattern, t_n, h, x_n, &
                y, values)
        end do
    end subroutine system_step_jacobian

    subroutine system_state_jacobian(this, t_n, h, x_n, y, values, status)
        class(rod_system_t), intent(inout) :: this
        real(rk), intent(in) :: t_n, h, x_n(:), y(:)
        real(rk), intent(out) :: values(:)
        integer, intent(out) :: status
        values = 0.0_rk
        status = state_invalid
        if (.not. this%direct) return
        call this%members(1)%rod%state_jacobian(t_n, h, x_n, y, values, status)
    end subroutine system_state_jacobian

    ! ---- Before and after a step ----------------------------------------------------------

    subroutine system_prepare_step(this, t_n, h, x_n, repattern)
        class(rod_system_t), intent(inout) :: this
        real(rk), intent(in) :: t_n, h, x_n(:)
        logical, intent(out) :: repattern
        logical :: changed
        integer :: c
        repattern = .false.
        do c = 1, size(this%couplings)
            call this%couplings(c)%coupling%prepare_step(this%layout, x_n, changed)
            repattern = repattern .or. changed
        end do
        if (repattern) call build_pattern(this)
    end subroutine system_prepare_step

    !> The members' energy terms and the Newton statistics into the ledger, then the work of
    !> the coupling forces on each rod (booked as its external work: each rod's balance closes
    !> by itself); step_energy sums the terms for the sentinel.
    subroutine system_accept_step(this, t_n, h, x_n, x_1, newton_iterations, residual_norm)
        class(rod_system_t), intent(inout) :: this
        real(rk), intent(in) :: t_n, h, x_n(:), x_1(:)
        integer, intent(in) :: newton_iterations
        real(rk), intent(in) :: residual_norm
        type(formulation_traits_t) :: traits
        real(rk), allocatable :: y(:), force(:), x_step(:)
        integer :: m, first, last, r
        do m = 1, size(this%members)
            associate (place => this%layout%members(m))
                first = place%first_rod
                last = first + place%n_rods - 1
                call this%members(m)%rod%accept_step(t_n, h, &
                    x_n(place%state_offset + 1:place%state_offset + place%n_state), &
                    x_1(place%state_offset + 1:place%state_offset + place%n_state), &
                    this%terms(first:last))
                traits = this%members(m)%rod%traits()
                call this%ledger%book_step(first, this%terms(first:last), h, newton_iterations, &
                    residual_norm, traits%linear_step, traits%shared_balance)
            end associate
        end do
        this%step_energy = step_energy_t(reported=all(this%terms%reported))
        do r = 1, this%n_rods
            if (.not. this%terms(r)%reported) cycle
            this%step_energy%before = this%step_energy%before + this%terms(r)%before
            this%step_energy%after = this%step_energy%after + this%terms(r)%after
            this%step_energy%work = this%step_energy%work + this%terms(r)%work
            this%step_energy%actuator_work = this%step_energy%actuator_work + this%terms(r)%actuator_work
            this%step_energy%dissipated = this%step_energy%dissipated + this%terms(r)%dissipated
        end do
        if (size(this%couplings) == 0 .or. this%static) return
        ! The coupling forces of the step (h times their generalized forces in the momentum
        ! rows) at the accepted unknowns, all rows on every rank, and their work on each rod.
        ! Work arrays out of `this` for the calls (no aliasing), back at the end.
        call move_alloc(this%work_y, y)
        call move_alloc(this%work_force, force)
        call move_alloc(this%work_x, x_step)
        call resize(x_step, size(x_1))
        x_step = x_1
        call undo_complements(this, x_n, x_step)
        call unknowns_of(this, x_step, y)
        call resize(force, this%layout%n_unknown)
        force = 0.0_rk
        call coupling_forces(this, t_n, h, x_n, y, force)
        call book_coupling_work(this, t_n, h, x_n, x_step, y, force)
        call move_alloc(y, this%work_y)
        call move_alloc(force, this%work_force)
        call move_alloc(x_step, this%work_x)
    end subroutine system_accept_step

    !> Where a formulation's update replaced rotation vectors by their complements (se3_pg,
    !> methods/se3_petrov_galerkin.md eq. 40), x_1 takes back the representative nearest to
    !> x_n's, so that the step's unknowns and increments are the ones Newton took.
    subroutine undo_complements(this, x_n, x_1)
        type(rod_system_t), intent(in) :: this
        real(rk), intent(in) :: x_n(:)
        real(rk), intent(inout) :: x_1(:)
        integer :: m, k, at, i
        do m = 1, size(this%members)
            associate (place => this%layout%members(m))
                at = place%nodes%rotation_vector_at
                if (at == 0) cycle
                do k = 1, place%nodes%n_nodes
                    if (any(place%nodes%state(at:at + 2, k) <= 0)) cycle
                    i = place%state_offset + place%nodes%state(at, k)
                    x_1(i:i + 2) = nearest_rotation_vector(x_1(i:i + 2), x_n(i:i + 2))
                end do
            end associate
        end do
    end subroutine undo_complements

    subroutine coupling_forces(this, t_n, h, x_n, y, force)
        type(rod_system_t), intent(inout) :: this
        real(rk), intent(in) :: t_n, h, x_n(:), y(:)
        real(rk), intent(inout) :: force(:)
        integer :: c
        do c = 1, size(this%couplings)
            call this%couplings(c)%coupling%add_residual(this%layout, t_n, h, x_n, y, force, .true.)
        end do
    end subroutine coupling_forces

    !> The work of the coupling forces on each member in a step, booked as the rod's external
    !> work in the ledger.
    subroutine book_coupling_work(this, t_n, h, x_n, x_1, y, force)
        type(rod_system_t), intent(inout) :: this
        real(rk), intent(in) :: t_n, h, x_n(:), x_1(:), y(:), force(:)
        real(rk) :: work, step(max_node_coordinates), q_n(max_node_coordinates)
        real(rk) :: q_1(max_node_coordinates), dissipated(size(this%members))
        integer :: m, k, nc, at, c
        ! Friction's share of the work is dissipation (>= 0): booked as such, the rest as
        ! external work, so that work + dissipation is the couplings' whole work.
        dissipated = 0.0_rk
        this%step_friction = friction_record_t()
        do c = 1, size(this%couplings)
            call this%couplings(c)%coupling%add_dissipation(this%layout, t_n, h, x_n, y, &
                dissipated, this%step_friction)
        end do
        do m = 1, size(this%members)
            associate (place => this%layout%members(m))
                nc = place%nodes%n_coordinates
                at = place%nodes%rotation_vector_at
                work = 0.0_rk
                do k = 1, place%nodes%n_nodes
                    associate (rows => this%layout%momentum_rows(m, k, nc))
                        if (any(rows <= 0)) cycle
                        q_n(1:nc) = this%layout%node_state(m, k, x_n, nc)
                        q_1(1:nc) = this%layout%node_state(m, k, x_1, nc)
                        step(1:nc) = q_1(1:nc) - q_n(1:nc)
                        if (at > 0) then
                            ! Rows of body rotations: the step turns the node by T(psi_mid) dpsi.
                            step(at:at + 2) = matmul(tangent_so3(0.5_rk * (q_n(at:at + 2) + &
                                q_1(at:at + 2))), step(at:at + 2))
                        end if
                        work = work - dot_product(force(rows), step(1:nc)) / &
                            this%layout%force_scale(m, h)
                    end associate
                end do
                call this%ledger%book_work(place%first_rod, work + dissipated(m))
                call this%ledger%book_dissipation(place%first_rod, dissipated(m))
                ! The sentinel sees the system's balance as the ledger does: the couplings'
                ! work on the rods is external to each rod.
                this%step_energy%work = this%step_energy%work + work + dissipated(m)
                this%step_energy%dissipated = this%step_energy%dissipated + dissipated(m)
            end associate
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

    !> The step unknowns that correspond to a state x (the nodes' coordinates and the coupling
    !> unknowns; the rest zero).
    subroutine unknowns_of(this, x, y)
        type(rod_system_t), intent(in) :: this
        real(rk), intent(in) :: x(:)
        real(rk), allocatable, intent(inout) :: y(:)
        integer :: m, k, i, nc
        call resize(y, this%layout%n_unknown)
        y = 0.0_rk
        do m = 1, size(this%members)
            associate (place => this%layout%members(m))
                nc = place%nodes%n_coordinates
                do k = 1, place%nodes%n_nodes
                    associate (cols => this%layout%coordinate_cols(m, k, nc), &
                            q => this%layout%node_state(m, k, x, nc))
                        do i = 1, nc
                            if (cols(i) > 0) y(cols(i)) = q(i)
                        end do
                    end associate
                end do
            end associate
        end do
        call unknown_blocks_from_state(this, x, y, owned_only=.false.)
    end subroutine unknowns_of

    ! ---- Records --------------------------------------------------------------------------

    subroutine system_init_history(this, histories, capacity)
        class(rod_system_t), intent(in) :: this
        type(rod_history_t), intent(inout), target :: histories(:)
        integer, intent(in) :: capacity
        integer :: m, first, last
        do m = 1, size(this%members)
            first = this%layout%members(m)%first_rod
            last = first + this%layout%members(m)%n_rods - 1
            call this%members(m)%rod%init_history(histories(first:last), capacity)
            if (size(this%couplings) > 0) call histories(first)%init_coupling(capacity)
        end do
    end subroutine system_init_history

    !> The members' records of the state x at time t, the ledger's sums (then started again)
    !> and the couplings' results.
    subroutine system_record(this, histories, t, x)
        class(rod_system_t), intent(inout) :: this
        type(rod_history_t), intent(inout), target :: histories(:)
        real(rk), intent(in) :: t, x(:)
        real(rk), allocatable :: y(:)
        integer :: m, first, last, i, r, stored(size(histories))
        integer :: c
        if (size(this%couplings) > 0) then
            this%coupling_records = coupling_record_t()
            call move_alloc(this%work_y, y)
            call unknowns_of(this, x, y)
            do c = 1, size(this%couplings)
                call this%couplings(c)%coupling%add_results(this%layout, t, x, y, this%coupling_records)
            end do
            call move_alloc(y, this%work_y)
        end if
        stored = histories%n_stored
        do m = 1, size(this%members)
            associate (place => this%layout%members(m))
                first = place%first_rod
                last = first + place%n_rods - 1
                call this%members(m)%rod%record(histories(first:last), t, &
                    x(place%state_offset + 1:place%state_offset + place%n_state))
                ! A record that found no room leaves the sums for the next one.
                do i = first, last
                    if (histories(i)%n_stored > stored(i)) call this%ledger%write_record(i, histories(i))
                end do
                if (size(this%couplings) == 0) cycle
                r = histories(first)%n_stored
                if (r == stored(first)) cycle
                histories(first)%contact_energy(r) = this%coupling_records(m)%contact_energy
                histories(first)%contact_force(:, r) = this%coupling_records(m)%contact_force
                histories(first)%penetration(r) = this%coupling_records(m)%penetration
                histories(first)%tie_force(:, :, r) = this%coupling_records(m)%tie_force
                histories(first)%tie_moment(:, :, r) = this%coupling_records(m)%tie_moment
                histories(first)%friction_force(:, r) = this%step_friction(m)%force
                histories(first)%slip_speed(r) = this%step_friction(m)%slip_speed
            end associate
        end do
    end subroutine system_record

    function system_describe(this) result(text)
        class(rod_system_t), intent(in) :: this
        character(len=:), allocatable :: text
        integer :: m, c, p, n
        if (this%direct) then
            text = this%members(1)%rod%describe()
            return
        end if
        text = 'system of ' // str(size(this%members)) // ' ' // this%formulation // ' rods ('
        do m = 1, size(this%members)
            if (m > 1) text = text // ', '
            text = text // this%members(m)%name
        end do
        text = text // '): '
        do c = 1, size(this%couplings)
            text = text // this%couplings(c)%coupling%describe() // ', '
        end do
        text = text // str(this%layout%n_unknown) // ' Newton unknowns, ' // &
            str(this%pattern%nnz()) // ' Jacobian non-zeros' // new_line('a') // &
            'linear solver: ' // linear_solver_text(this)
        if (this%layout%n_ranks == 1) return
        text = text // new_line('a') // 'partition over ' // str(this%layout%n_ranks) // &
            ' ranks (METIS on the coupling graph):'
        do p = 0, this%layout%n_ranks - 1
            n = 0
            text = text // new_line('a') // '  rank ' // str(p) // ':'
            do m = 1, size(this%members)
                if (this%layout%members(m)%part /= p) cycle
                text = text // ' ' // this%members(m)%name
                n = n + this%layout%members(m)%n_unknown
            end do
            text = text // ' (' // str(n) // ' rod unknowns)'
        end do
        text = text // new_line('a') // partition_quality(this)
    end function system_describe

    !> The default linear solver of the system's Newton steps and why (solver_blocks); PETSc's
    !> options on the command line override it.
    function linear_solver_text(this) result(text)
        type(rod_system_t), intent(in) :: this
        character(len=:), allocatable :: text
        character(len=:), allocatable :: why
        if (size(this%members) == 1) then
            text = 'the chain LU of the rod (rodchain)'
            return
        end if
        if (size(this%solver_blocks()) > 0) then
            text = 'GMRES preconditioned (on the right) by block Jacobi over the ' // &
                str(size(this%members)) // ' rods, each rod''s block factored by the chain ' // &
                'LU, to a tenth of newton_atol (docs/performance.md, "Bundles: block Jacobi ' // &
                'over the rods"; -ksp_type preonly -pc_type lu -pc_factor_mat_solver_type ' // &
                'mumps selects the direct LU)'
            return
        end if
        if (this%quasistatic) then
            why = 'quasistatic'
        else if (this%joined) then
            why = 'joints tie the rods'' blocks together'
        else
            why = 'fewer than ' // str(block_jacobi_members) // ' rods'
        end if
        text = 'one LU of the whole system by MUMPS (' // why // ': block Jacobi would be ' // &
            'slower, docs/performance.md, "Bundles: block Jacobi over the rods")'
    end function linear_solver_text

    !> The partition's edge cut (coupling-graph edges between members on different ranks, of
    !> all edges: the couplings whose rows cross ranks) and load balance (the largest rank's
    !> unknowns over the mean; 1 is perfect), for the log (issue 23 item 2).
    function partition_quality(this) result(text)
        type(rod_system_t), intent(in) :: this
        character(len=:), allocatable :: text
        integer, allocatable :: xadj(:), adjncy(:), weights(:)
        integer :: m, k, cut, edges, p
        real(rk) :: load(0:this%layout%n_ranks - 1)
        call this%coupling_graph(xadj, adjncy, weights)
        cut = 0
        edges = 0
        do m = 1, size(xadj) - 1
            do k = xadj(m) + 1, xadj(m + 1)
                edges = edges + 1
                if (this%layout%members(adjncy(k) + 1)%part /= this%layout%members(m)%part) &
                    cut = cut + 1
            end do
        end do
        load = 0.0_rk
        do m = 1, size(this%members)
            p = this%layout%members(m)%part
            load(p) = load(p) + real(this%layout%members(m)%n_unknown, rk)
        end do
        text = '  edge cut: ' // str(cut / 2) // ' of ' // str(edges / 2) // ' coupling-graph ' // &
            'edges cross ranks; load balance (largest rank / mean unknowns): ' // &
            str(real(nint(1000 * maxval(load) / max(sum(load) / size(load), 1.0_rk)), rk) / 1000)
    end function partition_quality

    !> A single member's traits; a coupled system's (the energy scheme is its rods': the
    !> sentinel checks the sum of the rods' balances with the couplings' work on them as
    !> external work, system_accept_step; the LU pivots, for the tie multipliers):
    !> - full Newton steps: the tie rows (positions, in m) and the momentum rows (h times
    !>   forces) have different scales, and backtracking on their joint norm takes tiny steps
    !>   where the full step converges quadratically (measured on the strand scenes,
    !>   docs/theory/bundles.md); a failed step is still halved by the stepper;
    !> - quasistatic runs end with the endpoint equilibrium, one Newton solve (no continuation);
    !> - except in quasistatic runs with contact and without ties: there the feasible-step
    !>   filter shortens Newton steps (the contact barrier's swept test), and a shortened step
    !>   taken whole, without the backtracking's decrease test, raised the residual from 3e-4 to
    !>   2.4 at the first touch of the crossing ropes and Newton stalled (docs/theory/
    !>   bundles.md, "No tunnelling"); with backtracking they converge. With ties the scaling
    !>   above rules (the seven-wire strand's quasistatic stretch needs full steps); dynamic
    !>   steps have the mass terms and converge with full steps;
    !> - the members' static tangent (linearized buckling) is the system's: in the endpoint
    !>   equilibrium the couplings act at X_{n+1} (rs_system_coupling).
    function system_traits(this) result(traits)
        class(rod_system_t), intent(in) :: this
        type(formulation_traits_t) :: traits
        traits = this%members(1)%rod%traits()
        if (this%direct) return
        traits = formulation_traits_t(full_newton=.not. (traits%wants_endpoint_solve .and. &
            this%refuses_iterates() .and. .not. this%tied), &
            wants_endpoint_solve=traits%wants_endpoint_solve, energy_scheme=traits%energy_scheme, &
            modal_form=traits%modal_form, static_tangent=traits%static_tangent)
    end function system_traits

    subroutine system_set_step_problem(this, endpoint, t_load, continue_from)
        class(rod_system_t), intent(inout) :: this
        logical, intent(in) :: endpoint
        real(rk), intent(in) :: t_load
        real(rk), intent(in), optional :: continue_from(:)
        call set_problems(this, endpoint, t_load, continue_from, members_continue=this%direct)
    end subroutine system_set_step_problem

    subroutine system_set_load_problem(this, t_load, base)
        class(rod_system_t), intent(inout) :: this
        real(rk), intent(in) :: t_load
        real(rk), intent(in), optional :: base(:)
        call set_problems(this, .true., t_load, base, members_continue=.true.)
    end subroutine system_set_load_problem

    !> The members' and couplings' step problems (set_step_problem, set_load_problem), each
    !> member continued from its part of `base` when given and `members_continue`: always for a
    !> path's statics (whose anchors weigh 0), and for the endpoint equilibrium of one rod
    !> without couplings only (a coupled system's members solve theirs uncontinued, on which
    !> the quasistatic bundles' equilibria rest).
    subroutine set_problems(this, endpoint, t_load, base, members_continue)
        type(rod_system_t), intent(inout) :: this
        logical, intent(in) :: endpoint, members_continue
        real(rk), intent(in) :: t_load
        real(rk), intent(in), optional :: base(:)
        integer :: m, c
        this%static = endpoint
        do m = 1, size(this%members)
            associate (place => this%layout%members(m))
                if (present(base) .and. members_continue) then
                    call this%members(m)%rod%set_step_problem(endpoint, t_load, &
                        continue_from=base(place%state_offset + 1:place%state_offset + &
                        place%n_state))
                else
                    call this%members(m)%rod%set_step_problem(endpoint, t_load)
                end if
            end associate
        end do
        do c = 1, size(this%couplings)
            call this%couplings(c)%coupling%set_endpoint(endpoint, t_load)
        end do
    end subroutine set_problems

    !> The step (t_n, h) whose problem is the statics at load time t_load: a formulation whose
    !> every step is an equilibrium at t_n + h (equilibrium_steps, se3_pg) takes t_n = t_load -
    !> 1, h = 1; the endpoint problem of the others (set_load_problem) is the pseudo-time step
    !> of the continuation from 0 to 1, where the anchor's weight 1 - t_n - h vanishes.
    subroutine system_load_step(this, t_load, t_n, h)
        class(rod_system_t), intent(in) :: this
        real(rk), intent(in) :: t_load
        real(rk), intent(out) :: t_n, h
        type(formulation_traits_t) :: traits
        traits = this%members(1)%rod%traits()
        h = 1.0_rk
        t_n = merge(t_load - 1.0_rk, 0.0_rk, traits%equilibrium_steps)
    end subroutine system_load_step

    !> The equilibrium row of each step unknown: where a generalized force conjugate to it
    !> enters (rod_nodes_t%momentum: ph_director's momentum rows for its q, whose own rows are
    !> kinematic), its own row for an unknown without node access (stresses, multipliers, a
    !> formulation without a node table, ph_planar, whose rows are those of its unknowns).
    !> The continuation's stability test applies forces there (rs_solver_arc_length).
    subroutine system_force_rows(this, rows)
        class(rod_system_t), intent(in) :: this
        integer, intent(out) :: rows(:)
        integer :: i, j, k, m
        rows = [(i, i = 1, size(rows))]
        do m = 1, size(this%layout%members)
            associate (place => this%layout%members(m), nodes => this%layout%members(m)%nodes)
                do k = 1, nodes%n_nodes
                    do j = 1, nodes%n_coordinates
                        if (nodes%unknown(j, k) <= 0 .or. nodes%momentum(j, k) <= 0) cycle
                        rows(place%unknown_offset + nodes%unknown(j, k)) = &
                            place%unknown_offset + nodes%momentum(j, k)
                    end do
                end do
            end associate
        end do
    end subroutine system_force_rows

    subroutine system_path_weights(this, w)
        class(rod_system_t), intent(in) :: this
        real(rk), intent(out) :: w(:)
        integer :: m
        w = 0.0_rk
        do m = 1, size(this%members)
            associate (place => this%layout%members(m))
                call this%members(m)%rod%path_weights(w(place%unknown_offset + 1: &
                    place%unknown_offset + place%n_unknown))
            end associate
        end do
        w = w / size(this%members)
    end subroutine system_path_weights
    subroutine system_stress_only(this, available, x, loaded)
        class(rod_system_t), intent(inout) :: this
        logical, intent(out) :: available
        real(rk), intent(inout) :: x(:)
        real(rk), intent(in), optional :: loaded(:)
        logical :: done
        integer :: m
        available = .true.
        do m = 1, size(this%members)
            associate (place => this%layout%members(m))
                if (present(loaded)) then
                    call this%members(m)%rod%stress_only(done, loaded(place%state_offset + 1: &
                        place%state_offset + place%n_state))
                else
                    call this%members(m)%rod%stress_only(done)
                end if
                available = available .and. done
            end associate
        end do
        if (.not. available .and. present(loaded)) then
            call this%stress_only(done, x)
            available = .false.
            return
        end if
        if (present(loaded)) call copy_coupling_blocks(this, loaded, .true., x, .true., &
            owned_only=.false.)
    end subroutine system_stress_only

    subroutine system_rest_state(this, x)
        class(rod_system_t), intent(in) :: this
        real(rk), intent(inout) :: x(:)
        integer :: m
        do m = 1, size(this%members)
            associate (place => this%layout%members(m))
                call this%members(m)%rod%rest_state(x(place%state_offset + 1: &
                    place%state_offset + place%n_state))
            end associate
        end do
    end subroutine system_rest_state

    !> The kinetic energy summed over the members (-1 if one does not report it) and the
    !> largest rotation of any member.
    function system_state_measures(this, x, from) result(measures)
        class(rod_system_t), intent(in) :: this
        real(rk), intent(in) :: x(:)
        real(rk), intent(in), optional :: from(:)
        type(state_measures_t) :: measures, one
        integer :: m
        if (this%direct) then
            measures = this%members(1)%rod%state_measures(x, from)
            return
        end if
        measures%kinetic_energy = 0.0_rk
        do m = 1, size(this%members)
            associate (place => this%layout%members(m))
                if (present(from)) then
                    one = this%members(m)%rod%state_measures(x(place%state_offset + 1: &
                        place%state_offset + place%n_state), from(place%state_offset + 1: &
                        place%state_offset + place%n_state))
                else
                    one = this%members(m)%rod%state_measures(x(place%state_offset + 1: &
                        place%state_offset + place%n_state))
                end if
            end associate
            if (one%kinetic_energy < 0.0_rk .or. measures%kinetic_energy < 0.0_rk) then
                measures%kinetic_energy = -1.0_rk
            else
                measures%kinetic_energy = measures%kinetic_energy + one%kinetic_energy
            end if
            measures%largest_rotation = max(measures%largest_rotation, one%largest_rotation)
        end do
    end function system_state_measures

    ! ---- Checkpoints ----------------------------------------------------------------------

    subroutine system_canonical_state(this, x, canonical)
        class(rod_system_t), intent(in) :: this
        real(rk), intent(in) :: x(:)
        real(rk), intent(out) :: canonical(:)
        call copy_blocks(this, x, canonical, to_canonical=.true.)
    end subroutine system_canonical_state

    subroutine system_from_canonical(this, canonical, x)
        class(rod_system_t), intent(in) :: this
        real(rk), intent(in) :: canonical(:)
        real(rk), intent(out) :: x(:)
        call copy_blocks(this, canonical, x, to_canonical=.false.)
    end subroutine system_from_canonical

    !> Every block of the state (members, coupling blocks) from its place in `from` to its
    !> place in `to`: from this rank's layout to the canonical one, or back.
    subroutine copy_blocks(this, from, to, to_canonical)
        type(rod_system_t), intent(in) :: this
        real(rk), intent(in) :: from(:)
        real(rk), intent(out) :: to(:)
        logical, intent(in) :: to_canonical
        integer :: m, c, b
        do m = 1, size(this%members)
            associate (place => this%layout%members(m))
                call copy_block(place%state_offset, place%canonical_offset, place%n_state)
            end associate
        end do
        do c = 1, size(this%couplings)
            associate (blocks => this%couplings(c)%coupling%blocks)
                do b = 1, size(blocks)
                    call copy_block(blocks(b)%state_offset, blocks(b)%canonical_offset, &
                        blocks(b)%size)
                end do
            end associate
        end do
    contains
        subroutine copy_block(state_offset, canonical_offset, n)
            integer, intent(in) :: state_offset, canonical_offset, n
            if (to_canonical) then
                to(canonical_offset + 1:canonical_offset + n) = &
                    from(state_offset + 1:state_offset + n)
            else
                to(state_offset + 1:state_offset + n) = &
                    from(canonical_offset + 1:canonical_offset + n)
            end if
        end subroutine copy_block
    end subroutine copy_blocks

    pure integer function system_n_ledger(this)
        class(rod_system_t), intent(in) :: this
        system_n_ledger = ledger_entries * this%n_rods
    end function system_n_ledger

    subroutine system_save_ledger(this, values)
        class(rod_system_t), intent(in) :: this
        real(rk), intent(out) :: values(:)
        call this%ledger%save(values)
    end subroutine system_save_ledger

    subroutine system_restore_ledger(this, values)
        class(rod_system_t), intent(inout) :: this
        real(rk), intent(in) :: values(:)
        call this%ledger%restore(values)
    end subroutine system_restore_ledger

    ! ---- The coupling graph ---------------------------------------------------------------

    subroutine system_coupling_graph(this, xadj, adjncy, weights)
        class(rod_system_t), intent(in) :: this
        integer, allocatable, intent(out) :: xadj(:), adjncy(:), weights(:)
        logical :: edge(size(this%members), size(this%members))
        integer :: c, k, m, t, n
        if (size(this%couplings) == 0) then
            allocate(xadj(0), adjncy(0), weights(0))
            return
        end if
        edge = .false.
        do c = 1, size(this%couplings)
            call this%couplings(c)%coupling%add_edges(edge)
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
            weights(m) = this%layout%members(m)%n_unknown
        end do
    end subroutine system_coupling_graph

end module rs_system_rod_system
