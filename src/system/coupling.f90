!> A coupling between the members of a system of rods (issue 22, DESIGN.md §5): an abstract
!> type with one implementation per kind, written once for every formulation that offers node
!> access (rod_formulation_t%nodes): ties (joints and end plates, rs_system_tie_coupling),
!> contact (rs_system_contact_coupling) and rigid obstacles (rs_system_obstacle_coupling). A
!> coupling adds terms to the momentum rows of the nodes
!> it touches (h times generalized forces, like the rods' internal forces; methods/
!> ph_director_3d.md §5.2 and §5.6) and may add unknown blocks of its own with their rows (tie
!> multipliers), which the system lays out after the member that owns each block.
!>
!> Distributed assembly: the callbacks get the whole X_n and Y and fill only the rows this rank
!> owns (system_layout_t%owns_row), or every row with all_rows (the coupling forces of an
!> accepted step, for the work on each rod). Each coupling sums its terms in a fixed global
!> order, so a row's value does not depend on the number of ranks.
module rs_system_coupling
    use rs_core_kinds, only: rk
    use rs_assembly_csr_pattern, only: csr_builder_t, csr_pattern_t
    use rs_system_layout, only: system_layout_t, coupling_block_t
    implicit none
    private

    !> What couplings report on a member for its records (rod_history_t's coupling fields):
    !> its share of the contact energy at the state, the contact force on it, its deepest
    !> penetration, and the tie forces and moments on its two ends.
    type, public :: coupling_record_t
        real(rk) :: contact_energy = 0.0_rk
        real(rk) :: contact_force(3) = 0.0_rk
        real(rk) :: penetration = 0.0_rk
        real(rk) :: tie_force(3, 2) = 0.0_rk
        real(rk) :: tie_moment(3, 2) = 0.0_rk
    end type coupling_record_t

    !> The friction of a step on a member: the total friction force on it (the physical force,
    !> against its slip) and the largest slip speed |u| / h of its contact points.
    type, public :: friction_record_t
        real(rk) :: force(3) = 0.0_rk
        real(rk) :: slip_speed = 0.0_rk
    end type friction_record_t

    type, abstract, public :: coupling_t
        !> Its unknown blocks (the system sets their offsets).
        type(coupling_block_t), allocatable :: blocks(:)
        !> Every step is an equilibrium at t_{n+1} (formulation_traits_t%equilibrium_steps):
        !> the coupling acts at X_{n+1} with the poses of t_{n+1}, as in an endpoint solve.
        logical :: equilibrium_steps = .false.
        !> The coupling may refuse a Newton iterate (admissible): the solver then shortens
        !> Newton steps to admissible ones (include/rs_rodmid.h, TSRodmidSetAdmissible).
        logical :: refuses_iterates = .false.
    contains
        !> About how many Jacobian entries the coupling adds (the pattern builder's first
        !> allocation; it grows if short). Default: none.
        procedure :: pattern_entries => default_pattern_entries
        !> Add the Jacobian blocks to the pattern being built, then find their positions in the
        !> built pattern.
        procedure(pattern_interface), deferred :: add_pattern
        procedure(map_interface), deferred :: map_pattern
        !> The layout is new (the partition): start again from the state x (contact: the pairs
        !> of the pattern from the initial state). Default: nothing.
        procedure :: start => default_start
        !> Before a step from x_n: refresh what the step needs (contact pairs); `repattern`
        !> when the Jacobian pattern must be built again. Default: nothing.
        procedure :: prepare_step => default_prepare_step
        !> An iterate y of the step from x_n is admissible (contact: no point moved further than
        !> the pairs found at t_n allow, and no pair of contact points crossed the barrier's
        !> wall on the way). Default: always.
        procedure :: admissible => default_admissible
        !> Add the coupling's terms to the step residual f or the Jacobian values.
        procedure(residual_interface), deferred :: add_residual
        procedure(jacobian_interface), deferred :: add_jacobian
        !> The step solves the endpoint equilibrium at load time t_load (or a time step again).
        procedure(endpoint_interface), deferred :: set_endpoint
        !> Add the coupling's results at state x (unknowns y) to the members' records.
        procedure(results_interface), deferred :: add_results
        !> Edges of the coupling graph among the members (edge(a, b) = .true.).
        procedure(edges_interface), deferred :: add_edges
        !> A short description for the log.
        procedure(describe_interface), deferred :: describe
        !> Add each member's dissipation of the accepted step from (t_n, x_n) to y (friction):
        !> the part of the coupling's work that the system books as dissipated rather than as
        !> external work, and the friction of the step on it (friction_record_t). Default:
        !> none (conservative couplings).
        procedure :: add_dissipation => default_add_dissipation
    end type coupling_t

    abstract interface
        subroutine pattern_interface(this, layout, builder)
            import :: coupling_t, system_layout_t, csr_builder_t
            class(coupling_t), intent(inout) :: this
            type(system_layout_t), intent(in) :: layout
            type(csr_builder_t), intent(inout) :: builder
        end subroutine pattern_interface

        subroutine map_interface(this, layout, pattern)
            import :: coupling_t, system_layout_t, csr_pattern_t
            class(coupling_t), intent(inout) :: this
            type(system_layout_t), intent(in) :: layout
            type(csr_pattern_t), intent(in) :: pattern
        end subroutine map_interface

        subroutine residual_interface(this, layout, t_n, h, x_n, y, f, all_rows)
            import :: coupling_t, system_layout_t, rk
            class(coupling_t), intent(inout) :: this
            type(system_layout_t), intent(in) :: layout
            real(rk), intent(in) :: t_n, h, x_n(:), y(:)
            real(rk), intent(inout) :: f(:)
            logical, intent(in) :: all_rows
        end subroutine residual_interface

        subroutine jacobian_interface(this, layout, pattern, t_n, h, x_n, y, values)
            import :: coupling_t, system_layout_t, csr_pattern_t, rk
            class(coupling_t), intent(inout) :: this
            type(system_layout_t), intent(in) :: layout
            type(csr_pattern_t), intent(in) :: pattern
            real(rk), intent(in) :: t_n, h, x_n(:), y(:)
            real(rk), intent(inout) :: values(:)
        end subroutine jacobian_interface

        subroutine endpoint_interface(this, on, t_load)
            import :: coupling_t, rk
            class(coupling_t), intent(inout) :: this
            logical, intent(in) :: on
            real(rk), intent(in) :: t_load
        end subroutine endpoint_interface

        subroutine results_interface(this, layout, t, x, y, records)
            import :: coupling_t, system_layout_t, coupling_record_t, rk
            class(coupling_t), intent(inout) :: this
            type(system_layout_t), intent(in) :: layout
            real(rk), intent(in) :: t, x(:), y(:)
            type(coupling_record_t), intent(inout) :: records(:)
        end subroutine results_interface

        subroutine edges_interface(this, edge)
            import :: coupling_t
            class(coupling_t), intent(in) :: this
            logical, intent(inout) :: edge(:, :)
        end subroutine edges_interface

        function describe_interface(this) result(text)
            import :: coupling_t
            class(coupling_t), intent(in) :: this
            character(len=:), allocatable :: text
        end function describe_interface
    end interface

    !> A coupling in a list (an array of polymorphic objects).
    type, public :: coupling_slot_t
        class(coupling_t), allocatable :: coupling
    end type coupling_slot_t

contains

    subroutine default_add_dissipation(this, layout, t_n, h, x_n, y, dissipated, friction)
        class(coupling_t), intent(in) :: this
        type(system_layout_t), intent(in) :: layout
        real(rk), intent(in) :: t_n, h, x_n(:), y(:)
        real(rk), intent(inout) :: dissipated(:)
        type(friction_record_t), intent(inout) :: friction(:)
    end subroutine default_add_dissipation

    pure integer function default_pattern_entries(this)
        class(coupling_t), intent(in) :: this
        default_pattern_entries = 0
    end function default_pattern_entries

    subroutine default_start(this, layout, x)
        class(coupling_t), intent(inout) :: this
        type(system_layout_t), intent(in) :: layout
        real(rk), intent(in) :: x(:)
    end subroutine default_start

    subroutine default_prepare_step(this, layout, x_n, repattern)
        class(coupling_t), intent(inout) :: this
        type(system_layout_t), intent(in) :: layout
        real(rk), intent(in) :: x_n(:)
        logical, intent(out) :: repattern
        repattern = .false.
    end subroutine default_prepare_step

    logical function default_admissible(this, layout, t_n, x_n, y)
        class(coupling_t), intent(inout) :: this
        type(system_layout_t), intent(in) :: layout
        real(rk), intent(in) :: t_n, x_n(:), y(:)
        default_admissible = .true.
    end function default_admissible

end module rs_system_coupling
