!> Where everything of a system of rods is in its state X and its step unknowns Y (issue 22,
!> DESIGN.md §5): each member's block (the member's own X and Y at an offset), the unknown blocks
!> of the couplings (tie multipliers) after the member that owns them, and the range of rows each
!> rank owns. Couplings read node coordinates and find rows and columns only through this
!> module and the members' node tables (rs_formulations_formulation's rod_nodes_t), never
!> through a formulation's internals.
!>
!> Layout. Members are ordered by rank (the partition) and, within a rank, by scene order; a
!> member's block of the unknowns is its own unknowns followed by the coupling blocks it owns,
!> so a rank owns one contiguous range of rows; the state is laid out the same way. The
!> canonical layout (checkpoints) is the same with every member on one rank.
module rs_system_layout
    use rs_core_kinds, only: rk
    use rs_formulations_formulation, only: rod_nodes_t
    implicit none
    private

    !> A member's place in the system.
    type, public :: member_layout_t
        !> Its node table (rs_formulations_formulation).
        type(rod_nodes_t) :: nodes
        !> 0-based offsets of its block in the state, the unknowns and the canonical state.
        integer :: state_offset = 0
        integer :: unknown_offset = 0
        integer :: canonical_offset = 0
        !> Lengths of its own X and Y.
        integer :: n_state = 0
        integer :: n_unknown = 0
        !> The rank that assembles it.
        integer :: part = 0
        !> Its first rod among the system's rods (histories, ledger) and its number of rods.
        integer :: first_rod = 1
        integer :: n_rods = 1
        !> Radius for contact (&rod contact_radius, else the section's radius).
        real(rk) :: contact_radius = 0.0_rk
    end type member_layout_t

    !> An unknown block of a coupling (a tie's multipliers): owned by a member, laid out after it.
    type, public :: coupling_block_t
        integer :: owner = 0
        integer :: size = 0
        integer :: state_offset = 0
        integer :: unknown_offset = 0
        integer :: canonical_offset = 0
    end type coupling_block_t

    type, public :: system_layout_t
        type(member_layout_t), allocatable :: members(:)
        integer :: n_state = 0
        integer :: n_unknown = 0
        integer :: rank = 0
        integer :: n_ranks = 1
        !> 0-based owned ranges [lo, hi) of this rank.
        integer :: state_lo = 0, state_hi = 0, unknown_lo = 0, unknown_hi = 0
    contains
        !> Coordinates 1..n of node k of member m in a state x, and in step unknowns y.
        procedure :: node_state
        procedure :: node_unknown
        !> Rows of the momentum equations and columns of coordinates 1..n of node k of member m
        !> (0 where the coordinate is held).
        procedure :: momentum_rows
        procedure :: coordinate_cols
        procedure :: owns_row
        procedure :: owns_member
        !> The factor h^p of member m's rows on a generalized force (rod_nodes_t%force_h_power).
        procedure :: force_scale
    end type system_layout_t

contains

    pure function node_state(this, m, k, x, n) result(q)
        class(system_layout_t), intent(in) :: this
        integer, intent(in) :: m, k, n
        real(rk), intent(in) :: x(:)
        real(rk) :: q(n)
        integer :: i
        associate (nodes => this%members(m)%nodes, offset => this%members(m)%state_offset)
            do i = 1, n
                if (nodes%state(i, k) > 0) then
                    q(i) = x(offset + nodes%state(i, k))
                else
                    q(i) = nodes%held(i, k)
                end if
            end do
        end associate
    end function node_state

    pure function node_unknown(this, m, k, y, n) result(q)
        class(system_layout_t), intent(in) :: this
        integer, intent(in) :: m, k, n
        real(rk), intent(in) :: y(:)
        real(rk) :: q(n)
        integer :: i
        associate (nodes => this%members(m)%nodes, offset => this%members(m)%unknown_offset)
            do i = 1, n
                if (nodes%unknown(i, k) > 0) then
                    q(i) = y(offset + nodes%unknown(i, k))
                else
                    q(i) = nodes%held(i, k)
                end if
            end do
        end associate
    end function node_unknown

    pure function momentum_rows(this, m, k, n) result(rows)
        class(system_layout_t), intent(in) :: this
        integer, intent(in) :: m, k, n
        integer :: rows(n)
        associate (nodes => this%members(m)%nodes)
            rows = merge(this%members(m)%unknown_offset + nodes%momentum(1:n, k), 0, &
                nodes%momentum(1:n, k) > 0)
        end associate
    end function momentum_rows

    pure function coordinate_cols(this, m, k, n) result(cols)
        class(system_layout_t), intent(in) :: this
        integer, intent(in) :: m, k, n
        integer :: cols(n)
        associate (nodes => this%members(m)%nodes)
            cols = merge(this%members(m)%unknown_offset + nodes%unknown(1:n, k), 0, &
                nodes%unknown(1:n, k) > 0)
        end associate
    end function coordinate_cols

    pure logical function owns_row(this, row)
        class(system_layout_t), intent(in) :: this
        integer, intent(in) :: row
        owns_row = row > this%unknown_lo .and. row <= this%unknown_hi
    end function owns_row

    pure real(rk) function force_scale(this, m, h)
        class(system_layout_t), intent(in) :: this
        integer, intent(in) :: m
        real(rk), intent(in) :: h
        force_scale = merge(h, 1.0_rk, this%members(m)%nodes%force_h_power == 1)
    end function force_scale

    pure logical function owns_member(this, m)
        class(system_layout_t), intent(in) :: this
        integer, intent(in) :: m
        owns_member = this%members(m)%part == this%rank
    end function owns_member

end module rs_system_layout
