!> The interface every rod formulation implements (DESIGN.md §2): its unknowns, initial state,
!> the residual and Jacobian of one time step, what it does after an accepted step and what it
!> records for the output. Implementations live in src/formulations/<name>/ and are created by
!> rs_formulations_factory; nothing here knows PETSc or MPI.
!>
!> The time step is a *step problem* (src/solver/rodmid.c): given the state X_n at t_n and the
!> step h, find the unknown Y with F(Y; X_n, t_n, h) = 0, then X_{n+1} = update(Y, X_n). The
!> Jacobian dF/dY is written into the values of a fixed CSR pattern that the formulation
!> declares once (exact preallocation, DESIGN.md §3).
module rs_formulations_formulation
    use rs_core_kinds, only: rk
    use rs_core_error, only: error_t
    use rs_model_scene, only: scene_t
    use rs_model_rod_history, only: rod_history_t
    use rs_formulations_energy_sentinel, only: step_energy_t, energy_unchecked
    implicit none
    private

    !> Residual evaluation status: the state is fine.
    integer, parameter, public :: state_valid = 0
    !> Residual evaluation status: the state is invalid (NaN, inverted element); the step is cut.
    integer, parameter, public :: state_invalid = 1

    !> What a formulation is, as the run and the solver need to know it: constants of the
    !> object once init has run (they follow from the scene: quasistatic or not, condensed
    !> stresses, the scheme), given by one procedure, rod_formulation_t%traits. rod_run hands
    !> the solver flags to the stepper with the scene's Newton settings (stepper_traits_t of
    !> src/solver/rod_stepper.f90, one C struct). The defaults are those of a formulation that
    !> says nothing.
    type, public :: formulation_traits_t
        !> The step Jacobian needs no pivoting (no multipliers, a non-zero diagonal), so
        !> PETSc's own LU may replace the chain LU (DESIGN.md §3).
        logical :: native_lu = .false.
        !> The unknowns are numbered for a narrow band, so the LU keeps their order (with
        !> native_lu); false: nested dissection.
        logical :: banded_unknowns = .false.
        !> The method document runs Newton undamped (full steps, no line search); false:
        !> backtracking.
        logical :: full_newton = .false.
        !> F is affine in Y with a Jacobian that does not depend on Y (coefficients frozen at
        !> t_n, seed 004's semi-implicit scheme): the step is one linear solve, no Newton loop.
        logical :: linear_step = .false.
        !> The run ends with an endpoint equilibrium solve (quasistatic runs, DESIGN.md §3):
        !> rod_run calls set_endpoint_solve around the last step.
        logical :: wants_endpoint_solve = .false.
        !> The endpoint equilibrium is solved as a continuation from a given state
        !> (set_continuation_start): rod_run then also solves the initial equilibrium of a
        !> quasistatic run and bounds each increment by largest_rotation (DESIGN.md §3,
        !> "Quasistatics"); false: one Newton solve in the last step's h.
        logical :: continues_equilibrium = .false.
        !> The kind of time scheme for the energy sentinel (energy_consistent,
        !> energy_dissipative, energy_unchecked of rs_formulations_energy_sentinel).
        integer :: energy_scheme = energy_unchecked
    end type formulation_traits_t

    !> A rod formulation: one object per rod.
    type, abstract, public :: rod_formulation_t
        !> The energy terms of the last accepted (sub)step, booked by accept_step for the run's
        !> energy sentinel (rs_formulations_energy_sentinel); not reported by default.
        type(step_energy_t) :: step_energy
    contains
        !> Build the rods `rods` of the scene (indices into scene%rods): one rod, or the rods a
        !> set of joints couples into one system (the first leads): mesh, unknowns, loads.
        procedure(init_interface), deferred :: init
        !> Length of the state vector X.
        procedure(size_interface), deferred :: n_state
        !> Number of unknowns Y of a step.
        procedure(size_interface), deferred :: n_unknown
        !> CSR pattern of dF/dY (0-based, columns sorted within a row).
        procedure(pattern_interface), deferred :: jacobian_pattern
        !> X at the start time.
        procedure(state_interface), deferred :: initial_state
        !> F(Y; X_n, t_n, h).
        procedure(residual_interface), deferred :: step_residual
        !> dF/dY in the values of the CSR pattern.
        procedure(jacobian_interface), deferred :: step_jacobian
        !> First Newton iterate (default: Y = X_n, for formulations with Y = X).
        procedure :: predictor => default_predictor
        !> X_{n+1} from the converged Y (default: X_{n+1} = Y).
        procedure :: update => default_update
        !> Book-keeping after an accepted (sub)step: work of the loads, Newton statistics.
        procedure(accept_interface), deferred :: accept_step
        !> Size the output records of the rods (one history per rod, in the order of `rods`).
        procedure(history_init_interface), deferred :: init_history
        !> Append the state X at time t to the rods' histories.
        procedure(record_interface), deferred :: record
        !> A short description for the log ("ph_director: 10 elements, p = 2, 750 unknowns").
        procedure(describe_interface), deferred :: describe
        !> The formulation's traits (formulation_traits_t: solver flags, endpoint solves,
        !> energy scheme), constants once init has run; default: formulation_traits_t().
        procedure :: traits => default_traits
        !> Switch the step problem to (or back from) the endpoint equilibrium at load time
        !> `t_load`: the next step solves it instead of a time step; default: nothing to switch.
        procedure :: set_endpoint_solve => default_set_endpoint_solve
        !> In the endpoint solve, continue from the state x_from: a step from tau_n to tau_n + h
        !> of the pseudo-time tau in [0, 1] solves R(Y) = (1 - tau_n - h) R(x_from), the residual
        !> rows in the scaling of a step of length row_scale; default: nothing.
        procedure :: set_continuation_start => default_set_continuation_start
        !> The largest rotation (radians) of a cross-section from state x_from to x_to: the size
        !> of a continuation increment; default 0 (not measured).
        procedure :: largest_rotation => default_largest_rotation
        !> Length of the book-keeping a restart needs besides the state X (sums since the last
        !> record, Newton statistics; DESIGN.md §7 /checkpoint); default 0.
        procedure :: n_internal => default_n_internal
        !> That book-keeping as reals (`values` has n_internal entries).
        procedure :: save_internal => default_save_internal
        !> Restore what save_internal gave.
        procedure :: restore_internal => default_restore_internal
        !> Kinetic energy of the state X, for runs that stop when it is small (&time
        !> relaxation); default -1: not reported.
        procedure :: kinetic_energy => default_kinetic_energy
        !> Before each step from X_n: refresh what the step needs besides X_n (bundles: the
        !> contact candidate pairs). `repattern` is true when the Jacobian pattern changed, so
        !> the stepper must be built again; default: nothing to do.
        procedure :: prepare_step => default_prepare_step
        !> A system solved on all ranks together (DESIGN.md §5: bundles on PETSC_COMM_WORLD):
        !> the rods as the vertices of the coupling graph, in CSR form (0-based adjncy), with
        !> their unknowns as weights; default: no graph (a system of one rank).
        procedure :: coupling_graph => default_coupling_graph
        !> Give the system's rods to ranks (part(i) = rank of rod i of the graph) and say which
        !> rank this is; the unknowns are renumbered so that each rank owns a contiguous range.
        procedure :: distribute => default_distribute
        !> The 0-based half-open ranges [lo, hi) of the state and the unknowns this rank owns;
        !> default: everything.
        procedure :: owned_range => default_owned_range
        !> The state X in a layout that does not depend on the ranks (checkpoints, DESIGN.md
        !> §7: a run may continue on another number of ranks), and back; default: X itself.
        procedure :: canonical_state => default_canonical_state
        procedure :: from_canonical => default_from_canonical
    end type rod_formulation_t

    abstract interface
        subroutine init_interface(this, scene, rods, err)
            import :: rod_formulation_t, scene_t, error_t
            class(rod_formulation_t), intent(inout) :: this
            type(scene_t), intent(in) :: scene
            integer, intent(in) :: rods(:)
            type(error_t), allocatable, intent(out) :: err
        end subroutine init_interface

        pure integer function size_interface(this)
            import :: rod_formulation_t
            class(rod_formulation_t), intent(in) :: this
        end function size_interface

        subroutine pattern_interface(this, row_ptr, cols)
            import :: rod_formulation_t
            class(rod_formulation_t), intent(in) :: this
            integer, allocatable, intent(out) :: row_ptr(:), cols(:)
        end subroutine pattern_interface

        subroutine state_interface(this, x)
            import :: rod_formulation_t, rk
            class(rod_formulation_t), intent(in) :: this
            real(rk), intent(out) :: x(:)
        end subroutine state_interface

        subroutine residual_interface(this, t_n, h, x_n, y, f, status)
            import :: rod_formulation_t, rk
            class(rod_formulation_t), intent(inout) :: this
            real(rk), intent(in) :: t_n, h, x_n(:), y(:)
            real(rk), intent(out) :: f(:)
            integer, intent(out) :: status
        end subroutine residual_interface

        subroutine jacobian_interface(this, t_n, h, x_n, y, values, status)
            import :: rod_formulation_t, rk
            class(rod_formulation_t), intent(inout) :: this
            real(rk), intent(in) :: t_n, h, x_n(:), y(:)
            real(rk), intent(out) :: values(:)
            integer, intent(out) :: status
        end subroutine jacobian_interface

        subroutine accept_interface(this, t_n, h, x_n, x_1, newton_iterations, residual_norm)
            import :: rod_formulation_t, rk
            class(rod_formulation_t), intent(inout) :: this
            real(rk), intent(in) :: t_n, h, x_n(:), x_1(:)
            integer, intent(in) :: newton_iterations
            real(rk), intent(in) :: residual_norm
        end subroutine accept_interface

        subroutine history_init_interface(this, histories, capacity)
            import :: rod_formulation_t, rod_history_t
            class(rod_formulation_t), intent(in) :: this
            type(rod_history_t), intent(inout), target :: histories(:)
            integer, intent(in) :: capacity
        end subroutine history_init_interface

        subroutine record_interface(this, histories, t, x)
            import :: rod_formulation_t, rod_history_t, rk
            class(rod_formulation_t), intent(inout) :: this
            type(rod_history_t), intent(inout), target :: histories(:)
            real(rk), intent(in) :: t, x(:)
        end subroutine record_interface

        function describe_interface(this) result(text)
            import :: rod_formulation_t
            class(rod_formulation_t), intent(in) :: this
            character(len=:), allocatable :: text
        end function describe_interface
    end interface

contains

    pure function default_traits(this) result(traits)
        class(rod_formulation_t), intent(in) :: this
        type(formulation_traits_t) :: traits
        traits = formulation_traits_t()
    end function default_traits

    subroutine default_set_endpoint_solve(this, on, t_load)
        class(rod_formulation_t), intent(inout) :: this
        logical, intent(in) :: on
        real(rk), intent(in) :: t_load
    end subroutine default_set_endpoint_solve

    subroutine default_set_continuation_start(this, x_from, row_scale)
        class(rod_formulation_t), intent(inout) :: this
        real(rk), intent(in) :: x_from(:), row_scale
    end subroutine default_set_continuation_start

    real(rk) function default_largest_rotation(this, x_from, x_to)
        class(rod_formulation_t), intent(in) :: this
        real(rk), intent(in) :: x_from(:), x_to(:)
        default_largest_rotation = 0.0_rk
    end function default_largest_rotation

    real(rk) function default_kinetic_energy(this, x)
        class(rod_formulation_t), intent(in) :: this
        real(rk), intent(in) :: x(:)
        default_kinetic_energy = -1.0_rk
    end function default_kinetic_energy

    pure integer function default_n_internal(this)
        class(rod_formulation_t), intent(in) :: this
        default_n_internal = 0
    end function default_n_internal

    subroutine default_save_internal(this, values)
        class(rod_formulation_t), intent(in) :: this
        real(rk), intent(out) :: values(:)
    end subroutine default_save_internal

    subroutine default_restore_internal(this, values)
        class(rod_formulation_t), intent(inout) :: this
        real(rk), intent(in) :: values(:)
    end subroutine default_restore_internal

    subroutine default_prepare_step(this, t_n, h, x_n, repattern)
        class(rod_formulation_t), intent(inout) :: this
        real(rk), intent(in) :: t_n, h, x_n(:)
        logical, intent(out) :: repattern
        repattern = .false.
    end subroutine default_prepare_step

    subroutine default_coupling_graph(this, xadj, adjncy, weights)
        class(rod_formulation_t), intent(in) :: this
        integer, allocatable, intent(out) :: xadj(:), adjncy(:), weights(:)
        allocate(xadj(0), adjncy(0), weights(0))
    end subroutine default_coupling_graph

    subroutine default_distribute(this, part, rank)
        class(rod_formulation_t), intent(inout) :: this
        integer, intent(in) :: part(:), rank
    end subroutine default_distribute

    subroutine default_owned_range(this, state_lo, state_hi, unknown_lo, unknown_hi)
        class(rod_formulation_t), intent(in) :: this
        integer, intent(out) :: state_lo, state_hi, unknown_lo, unknown_hi
        state_lo = 0
        state_hi = this%n_state()
        unknown_lo = 0
        unknown_hi = this%n_unknown()
    end subroutine default_owned_range

    subroutine default_canonical_state(this, x, canonical)
        class(rod_formulation_t), intent(in) :: this
        real(rk), intent(in) :: x(:)
        real(rk), intent(out) :: canonical(:)
        canonical = x
    end subroutine default_canonical_state

    subroutine default_from_canonical(this, canonical, x)
        class(rod_formulation_t), intent(in) :: this
        real(rk), intent(in) :: canonical(:)
        real(rk), intent(out) :: x(:)
        x = canonical
    end subroutine default_from_canonical

    subroutine default_predictor(this, t_n, h, x_n, y)
        class(rod_formulation_t), intent(inout) :: this
        real(rk), intent(in) :: t_n, h, x_n(:)
        real(rk), intent(out) :: y(:)
        y = x_n
    end subroutine default_predictor

    subroutine default_update(this, t_n, h, x_n, y, x_1)
        class(rod_formulation_t), intent(inout) :: this
        real(rk), intent(in) :: t_n, h, x_n(:), y(:)
        real(rk), intent(out) :: x_1(:)
        x_1 = y
    end subroutine default_update

end module rs_formulations_formulation
