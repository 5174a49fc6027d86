!> Supports released at a time (&bc release_time; issue 26 item 3, docs/theory/
!> prestretched_starts.md, "Release"), for the formulations that hold supports by eliminating
!> nodal unknowns (ph_planar, se3_pg). A released end's coordinates stay unknowns of the step
!> from the start, so the Jacobian pattern and its factorization never change; while the end
!> is held, the equations of those unknowns are replaced by the held equations
!> y_i - x_n(state_i) = 0 (the coordinate keeps its value; its Jacobian row the unit row), and
!> from the release on they are the formulation's own equations of motion. The held coordinate
!> does not move, so its reaction does no work and every step's energy balance is the
!> formulation's own; after the release nothing holds the end.
!>
!> One object per formulation object, written once here (DESIGN.md: bookkeeping shared by the
!> formulations lives in one type). Pure Fortran on plain arrays: the CSR pattern comes as its
!> 1-based row pointers and columns.
module rs_formulations_held_rows
    use rs_core_kinds, only: rk
    use rs_model_scene, only: end_is_held
    implicit none
    private

    !> The held rows of one formulation object.
    type, public :: held_rows_t
        !> Number of released coordinates.
        integer :: n = 0
        !> Per released coordinate: its row (= unknown) in Y, its index in the state X, the
        !> release time, and the CSR positions of its row (first .. last) and of its diagonal.
        integer, allocatable :: row(:), state(:), first(:), last(:), diagonal(:)
        real(rk), allocatable :: release_time(:)
    contains
        !> Register the released coordinates (their unknowns, state indices and release
        !> times) on the step Jacobian's pattern.
        procedure :: init => held_rows_init
        !> Replace the held rows of the residual f of the step from x_n to y.
        procedure :: apply_residual => held_rows_apply_residual
        !> Replace the held rows of the Jacobian values by unit rows.
        procedure :: apply_jacobian => held_rows_apply_jacobian
        !> The coordinate j is held in this step (see held).
        procedure :: is_held => held_rows_is_held
    end type held_rows_t

contains

    !> `rows` (1-based unknowns of Y), `states` (1-based indices into X) and `release_times` of
    !> the released coordinates; `row_ptr` and `cols` the 1-based CSR pattern of dF/dY, which
    !> must hold every diagonal entry of these rows (their coordinate is an unknown of them).
    pure subroutine held_rows_init(this, rows, states, release_times, row_ptr, cols)
        class(held_rows_t), intent(inout) :: this
        integer, intent(in) :: rows(:), states(:), row_ptr(:), cols(:)
        real(rk), intent(in) :: release_times(:)
        integer :: j, p
        this%n = size(rows)
        this%row = rows
        this%state = states
        this%release_time = release_times
        allocate(this%first(this%n), this%last(this%n), this%diagonal(this%n))
        do j = 1, this%n
            this%first(j) = row_ptr(rows(j))
            this%last(j) = row_ptr(rows(j) + 1) - 1
            this%diagonal(j) = 0
            do p = this%first(j), this%last(j)
                if (cols(p) == rows(j)) this%diagonal(j) = p
            end do
        end do
    end subroutine held_rows_init

    !> Whether released coordinate j is held in the step from t_n of length h, or in the
    !> equilibrium at load time t_n (`static`): rs_model_scene's end_is_held.
    pure logical function held_rows_is_held(this, j, t_n, h, static)
        class(held_rows_t), intent(in) :: this
        integer, intent(in) :: j
        real(rk), intent(in) :: t_n, h
        logical, intent(in) :: static
        held_rows_is_held = end_is_held(this%release_time(j), t_n, h, static)
    end function held_rows_is_held

    !> f(row_j) = y(row_j) - x_n(state_j) for every held coordinate j (a length, satisfied
    !> exactly by a predictor that keeps the coordinate, and by every Newton iterate after).
    pure subroutine held_rows_apply_residual(this, t_n, h, static, x_n, y, f)
        class(held_rows_t), intent(in) :: this
        real(rk), intent(in) :: t_n, h, x_n(:), y(:)
        logical, intent(in) :: static
        real(rk), intent(inout) :: f(:)
        integer :: j
        do j = 1, this%n
            if (this%is_held(j, t_n, h, static)) f(this%row(j)) = y(this%row(j)) - &
                x_n(this%state(j))
        end do
    end subroutine held_rows_apply_residual

    !> The unit row of every held coordinate in the CSR values.
    pure subroutine held_rows_apply_jacobian(this, t_n, h, static, values)
        class(held_rows_t), intent(in) :: this
        real(rk), intent(in) :: t_n, h
        logical, intent(in) :: static
        real(rk), intent(inout) :: values(:)
        integer :: j
        do j = 1, this%n
            if (.not. this%is_held(j, t_n, h, static)) cycle
            values(this%first(j):this%last(j)) = 0.0_rk
            values(this%diagonal(j)) = 1.0_rk
        end do
    end subroutine held_rows_apply_jacobian

end module rs_formulations_held_rows
