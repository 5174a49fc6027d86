!> The one-rod contract every rod formulation implements (DESIGN.md §2, issue 22): its unknowns,
!> initial state, the residual and Jacobian of one time step, the energy terms of an accepted
!> step, what it records, and the few node-access procedures that couplings need. A formulation
!> object is one rod, or the rods it joins itself through shared unknowns (ph_planar); systems of
!> rods (joints, end plates, contact, the rank partition, the record ledger, checkpoints) are the
!> system layer's (src/system/, rs_system_rod_system), which drives every run, a single rod
!> included. Implementations live in src/formulations/<name>/ and are created from their
!> descriptor (rs_formulations_registry); nothing here knows PETSc or MPI.
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

    public :: step_energy_t

    !> Residual evaluation status: the state is fine.
    integer, parameter, public :: state_valid = 0
    !> Residual evaluation status: the state is invalid (NaN, inverted element); the step is cut.
    integer, parameter, public :: state_invalid = 1
    !> Largest number of coordinates of a node (ph_director: position and three directors).
    integer, parameter, public :: max_node_coordinates = 12

    !> How the step Jacobian at a state at rest depends on the step h, which is where modal
    !> analysis reads the linearized equations of motion (formulation_traits_t%modal_form,
    !> docs/theory/modes.md): not at all (statics, a scheme other than the midpoint rule) ...
    integer, parameter, public :: modal_none = 0
    !> ... a first-order system B x' + A x = 0 in the step's unknowns, J(h) = B/h + A/2 (each
    !> row may carry a factor h^p, e.g. ph_director's momentum rows, methods §5.2) ...
    integer, parameter, public :: modal_first_order = 1
    !> ... or a second-order one M q'' + C q' + K q = 0 in positions alone (the velocities
    !> eliminated by the midpoint rule), J(h) = 2 M/h^2 + C/h + K/2 ...
    integer, parameter, public :: modal_second_order = 2
    !> ... or a first-order system B x' + A x = 0 in rates and stresses (an intrinsic state
    !> without positions, whose rigid motions are simple zeros) advanced by a consistent
    !> one-step scheme other than the midpoint rule (se3_strand's semi-implicit step, whose
    !> coefficients are frozen at t_n): J(h) = dF/dY = B/h + A_Y and dF/dX_n = -B/h + A_X
    !> (rod_formulation_t%state_jacobian), A = A_Y + A_X (each row may carry a factor h^p).
    integer, parameter, public :: modal_one_step = 3

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
        !> rod_run calls set_step_problem around the last step.
        logical :: wants_endpoint_solve = .false.
        !> The endpoint equilibrium is solved as a continuation from a given state
        !> (set_step_problem with continue_from): rod_run then also solves the initial
        !> equilibrium of a quasistatic run and bounds each increment by the largest rotation
        !> (state_measures; DESIGN.md §3, "Quasistatics"); false: one Newton solve in the last
        !> step's h.
        logical :: continues_equilibrium = .false.
        !> The kind of time scheme for the energy sentinel (energy_consistent,
        !> energy_dissipative, energy_unchecked of rs_formulations_energy_sentinel).
        integer :: energy_scheme = energy_unchecked
        !> Every step solves an equilibrium at t_{n+1} (se3_pg's statics): couplings act at
        !> X_{n+1} with the loads of t_{n+1}, as the rod's own forces.
        logical :: equilibrium_steps = .false.
        !> The object's rods share unknowns (joints by master and slave nodes, ph_planar), so
        !> the work between them is not separable: the record ledger books their summed energy
        !> balance on the first rod and zero on the others (docs/developer/architecture.md).
        logical :: shared_balance = .false.
        !> The form of the step Jacobian at rest (modal_none, modal_first_order,
        !> modal_second_order, modal_one_step): which linear pencil modal analysis reads from it
        !> (rs_system_linearization), checked there against Jacobians at several h.
        integer :: modal_form = modal_none
        !> The step problem of the endpoint equilibrium (set_step_problem(.true., t_load)
        !> without continue_from) is the static equilibrium at t_load whose Jacobian is its
        !> tangent stiffness, every row a force or an algebraic row and no mass term (rows
        !> scaled by the step h, unknowns as those of a step): linearized buckling reads K_T
        !> there (rs_system_linearization's buckling_stiffness; ph_director in quasistatic
        !> runs, whose K_T is the mixed static problem's, stresses and multipliers
        !> included); false: from the dynamic step's second-order pencil (modal_form).
        logical :: static_tangent = .false.
    end type formulation_traits_t

    !> Two measures of a state that the run's control uses (state_measures).
    type, public :: state_measures_t
        !> Kinetic energy of the state, for runs that stop when it is small (&time
        !> relaxation); -1: not reported.
        real(rk) :: kinetic_energy = -1.0_rk
        !> The largest rotation (radians) of a cross-section from the reference state passed
        !> in to the state: the size of a continuation increment; 0: not measured.
        real(rk) :: largest_rotation = 0.0_rk
    end type state_measures_t

    !> Where the coordinates of the rod's nodes are: what couplings (ties, contact) need, and
    !> all they may read of a formulation (rod_formulation_t%nodes). The first three
    !> coordinates of every node are its centreline position; the others are the
    !> formulation's own (ph_director: the directors d1, d2, d3; se3_pg: the rotation vector).
    !> A table of n_nodes = 0 means the formulation offers no node access (no couplings).
    type, public :: rod_nodes_t
        !> Coordinates per node.
        integer :: n_coordinates = 0
        !> The rows carry h^force_h_power times a generalized force (ph_director: 1, its
        !> momentum rows are scaled by h, methods/ph_director_3d.md §5.2; se3_pg: 0, force
        !> rows).
        integer :: force_h_power = 1
        !> Coordinates rotation_vector_at .. rotation_vector_at + 2 are a rotation vector psi
        !> whose rows are virtual rotations in the body basis (se3_pg: 4; methods/
        !> se3_petrov_galerkin.md eqs. 42-45), so a step turns them by T(psi_mid) dpsi; 0: every
        !> row is that of its coordinate.
        integer :: rotation_vector_at = 0
        !> Coordinates directors_at .. directors_at + 8 are the directors d_1, d_2, d_3, whose
        !> generalized forces g_i exert the moment sum_i d_i x g_i (ph_director: 4); 0: none.
        integer :: directors_at = 0
        !> Some held coordinates move in time (driven ends): the held values above are those
        !> of the reference only, so couplings are refused on such a rod.
        logical :: held_moves = .false.
        integer :: n_nodes = 0
        !> Centreline elements: the nodes of element e are (e - 1) degree + 1 .. e degree + 1.
        integer :: n_elements = 0
        integer :: degree = 1
        !> Gauss points per element of the formulation's own quadrature (the fewest contact
        !> points of an element).
        integer :: n_gauss = 1
        !> Reference length of each element (n_elements).
        real(rk), allocatable :: element_length(:)
        !> state(i, k): 1-based index of coordinate i of node k in the state X; unknown(i, k):
        !> in the step unknowns Y, and momentum(i, k): the row of Y's equations that a
        !> generalized force on that coordinate enters (h times the force, like the internal
        !> forces; methods/ph_director_3d.md §5.2). 0: the coordinate is held (a support),
        !> with the value held(i, k).
        integer, allocatable :: state(:, :), unknown(:, :), momentum(:, :)
        !> The values of held coordinates; for every node its reference coordinates, from
        !> which ties are built (a joint holds in the reference).
        real(rk), allocatable :: held(:, :)
    end type rod_nodes_t

    !> A tie: n <= 6 holonomic constraint rows g(z) on the coordinates z = [q_a; q_b] of one
    !> or two nodes (a joint, or a rod end tied to a rigid end plate, DESIGN.md §5), written
    !> by the formulation for its own coordinates (rod_formulation_t%new_tie). The tie
    !> coupling of the system layer (rs_system_tie_coupling) adds h^p F(z_t)^T lambda to the
    !> momentum rows of the nodes (p = rod_nodes_t%force_h_power; F = dg/dz where the rows are
    !> those of the coordinates, as ph_director's; the rows' own basis otherwise, e.g. body
    !> rotations) and g(z_{n+1}) = 0 as the tie's own rows.
    type, abstract, public :: node_tie_t
        !> Number of constraint rows.
        integer :: n = 0
        !> Coordinates per node (the size of q_a and q_b).
        integer :: n_coordinates = 0
    contains
        !> Move a plate tie to the plate's pose: turned by R = exp(rotation) about `centre` and
        !> moved by `displacement` from its reference (a joint ignores it).
        procedure(tie_place_interface), deferred :: place
        !> g(z) (n values).
        procedure(tie_value_interface), deferred :: value
        !> G(z) = dg/dz (n x 2 n_coordinates).
        procedure(tie_gradient_interface), deferred :: gradient
        !> F(z): the rows' generalized forces per unit lambda (n x 2 n_coordinates); default
        !> G(z), for rows in the basis of the coordinates.
        procedure :: force_gradient => default_force_gradient
        !> d(F(z)^T lambda)/dz at z (2 n_coordinates squared; sum_k lambda_k d^2 g_k / dz^2
        !> where F = G).
        procedure(tie_hessian_interface), deferred :: force_hessian
    end type node_tie_t

    !> A rod formulation: one object per rod (or per set of rods joined by shared unknowns).
    type, abstract, public :: rod_formulation_t
    contains
        !> Build the rods `rods` of the scene (indices into scene%rods): one rod, or the rods a
        !> set of joints couples into one object when the formulation joins them itself
        !> (ph_planar; the first leads): mesh, unknowns, loads.
        procedure(init_interface), deferred :: init
        !> Length of the state vector X.
        procedure(size_interface), deferred :: n_state
        !> Number of unknowns Y of a step.
        procedure(size_interface), deferred :: n_unknown
        !> CSR pattern of dF/dY (0-based, columns sorted within a row).
        procedure(pattern_interface), deferred :: jacobian_pattern
        !> X at the start time.
        procedure(state_interface), deferred :: initial_state
        !> First Newton iterate (default: Y = X_n, for formulations with Y = X).
        procedure :: predictor => default_predictor
        !> X_{n+1} from the converged Y (default: X_{n+1} = Y).
        procedure :: update => default_update
        !> F(Y; X_n, t_n, h).
        procedure(residual_interface), deferred :: step_residual
        !> dF/dY in the values of the CSR pattern.
        procedure(jacobian_interface), deferred :: step_jacobian
        !> The energy terms of an accepted (sub)step, one record per rod of the object: the
        !> record ledger (rs_system_ledger) sums them until the next record and the energy
        !> sentinel checks them; the formulation keeps no book-keeping of its own.
        procedure(accept_interface), deferred :: accept_step
        !> Size the output records of the rods (one history per rod, in the order of `rods`).
        procedure(history_init_interface), deferred :: init_history
        !> Append the state X at time t to the rods' histories: the fields of the state (the
        !> ledger's sums are written by the system layer).
        procedure(record_interface), deferred :: record
        !> A short description for the log ("ph_director: 10 elements, p = 2, 750 unknowns").
        procedure(describe_interface), deferred :: describe
        !> The formulation's traits (formulation_traits_t: solver flags, endpoint solves,
        !> energy scheme), constants once init has run; default: formulation_traits_t().
        procedure :: traits => default_traits
        !> Switch the step problem to (endpoint true) or back from the endpoint equilibrium at
        !> load time `t_load`: the next steps solve it instead of a time step. With
        !> continue_from, a step from tau_n to tau_n + h of the pseudo-time tau in [0, 1]
        !> solves R(Y) = (1 - tau_n - h) R(continue_from) (the continuation of DESIGN.md §3);
        !> default: nothing to switch.
        procedure :: set_step_problem => default_set_step_problem
        !> Kinetic energy of x and, with `from`, the largest rotation of a cross-section from
        !> `from` to x (state_measures_t); default: neither reported.
        procedure :: state_measures => default_state_measures
        !> The state entries whose local error adaptive steps control (weigh, n_state): those
        !> that are values at the step's end, smooth in time. Not multipliers or stresses held
        !> at the midpoint (placed at t_{n+1/2}, they would spoil the divided differences of the
        !> estimate when the step changes), nor coordinates that jump (se3_pg's complemented
        !> rotation vectors). Default: every entry.
        procedure :: error_entries => default_error_entries
        !> The state x brought to rest (its velocities zero, the rest kept): what modal analysis
        !> linearizes about after a quasistatic run, whose states carry the load path's rates
        !> (docs/theory/modes.md); default: x unchanged.
        procedure :: rest_state => default_rest_state
        !> The weights w of the step unknowns Y in the length of a continuation path (arc-length
        !> continuation, docs/theory/continuation.md): sum_i w_i dY_i^2 is the mean over the
        !> rod's nodes of |dr|^2 / L^2 + |dtheta|^2 for a change dr of the centreline and a
        !> small turn dtheta of the section (L the rod's length), zero on stresses and
        !> multipliers; default: every unknown alike, w = 1 / n_unknown.
        procedure :: path_weights => default_path_weights
        !> Linearized buckling's stress stiffness (docs/theory/modes.md): with `loaded` (a
        !> state), the internal stresses are held at those of `loaded` in place of the elastic
        !> law, so that the tangent at any state is the stress (geometric) stiffness of those
        !> stresses there, with the loads' tangents; without it, the elastic rod again.
        !> `available` false: the formulation cannot (default), and the buckling analysis takes
        !> the difference of the loaded and the unloaded tangents instead.
        procedure :: stress_only => default_stress_only
        !> dF/dX_n in the values of the CSR pattern of dF/dY, the columns being the entries of
        !> X_n that the predictor copies into Y (x_n(1:n_unknown)): what modal analysis needs
        !> besides dF/dY when the step's coefficients are frozen at t_n (modal_one_step,
        !> docs/theory/modes.md). status state_invalid: not available (the default).
        procedure :: state_jacobian => default_state_jacobian
        !> Where the coordinates of the nodes are (rod_nodes_t), for couplings; default: no
        !> node access.
        procedure :: nodes => default_nodes
        !> A tie of `kind` ('rigid', 'spherical', 'revolute' between two nodes of reference
        !> coordinates q_a, q_b; 'plate' on one node of reference coordinates q_a) in the
        !> formulation's coordinates; `tie` is not allocated when the formulation has none.
        procedure :: new_tie => default_new_tie
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

        subroutine accept_interface(this, t_n, h, x_n, x_1, terms)
            import :: rod_formulation_t, rk, step_energy_t
            class(rod_formulation_t), intent(inout) :: this
            real(rk), intent(in) :: t_n, h, x_n(:), x_1(:)
            !> One per rod of the object (in the order of init's `rods`).
            type(step_energy_t), intent(out) :: terms(:)
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

        pure subroutine tie_place_interface(this, centre, displacement, rotation)
            import :: node_tie_t, rk
            class(node_tie_t), intent(inout) :: this
            real(rk), intent(in) :: centre(3), displacement(3), rotation(3)
        end subroutine tie_place_interface

        pure subroutine tie_value_interface(this, z, g)
            import :: node_tie_t, rk
            class(node_tie_t), intent(in) :: this
            real(rk), intent(in) :: z(:)
            real(rk), intent(out) :: g(:)
        end subroutine tie_value_interface

        pure subroutine tie_gradient_interface(this, z, gradient)
            import :: node_tie_t, rk
            class(node_tie_t), intent(in) :: this
            real(rk), intent(in) :: z(:)
            real(rk), intent(out) :: gradient(:, :)
        end subroutine tie_gradient_interface

        pure subroutine tie_hessian_interface(this, z, lambda, hessian)
            import :: node_tie_t, rk
            class(node_tie_t), intent(in) :: this
            real(rk), intent(in) :: z(:), lambda(:)
            real(rk), intent(out) :: hessian(:, :)
        end subroutine tie_hessian_interface
    end interface

contains

    pure subroutine default_force_gradient(this, z, gradient)
        class(node_tie_t), intent(in) :: this
        real(rk), intent(in) :: z(:)
        real(rk), intent(out) :: gradient(:, :)
        call this%gradient(z, gradient)
    end subroutine default_force_gradient

    pure function default_traits(this) result(traits)
        class(rod_formulation_t), intent(in) :: this
        type(formulation_traits_t) :: traits
        traits = formulation_traits_t()
    end function default_traits

    subroutine default_set_step_problem(this, endpoint, t_load, continue_from)
        class(rod_formulation_t), intent(inout) :: this
        logical, intent(in) :: endpoint
        real(rk), intent(in) :: t_load
        real(rk), intent(in), optional :: continue_from(:)
    end subroutine default_set_step_problem

    function default_state_measures(this, x, from) result(measures)
        class(rod_formulation_t), intent(in) :: this
        real(rk), intent(in) :: x(:)
        real(rk), intent(in), optional :: from(:)
        type(state_measures_t) :: measures
        measures = state_measures_t()
    end function default_state_measures

    subroutine default_error_entries(this, weigh)
        class(rod_formulation_t), intent(in) :: this
        logical, intent(out) :: weigh(:)
        weigh = .true.
    end subroutine default_error_entries

    subroutine default_path_weights(this, w)
        class(rod_formulation_t), intent(in) :: this
        real(rk), intent(out) :: w(:)
        w = 1.0_rk / real(max(1, size(w)), rk)
    end subroutine default_path_weights

    subroutine default_rest_state(this, x)
        class(rod_formulation_t), intent(in) :: this
        real(rk), intent(inout) :: x(:)
    end subroutine default_rest_state

    subroutine default_state_jacobian(this, t_n, h, x_n, y, values, status)
        class(rod_formulation_t), intent(inout) :: this
        real(rk), intent(in) :: t_n, h, x_n(:), y(:)
        real(rk), intent(out) :: values(:)
        integer, intent(out) :: status
        values = 0.0_rk
        status = state_invalid
    end subroutine default_state_jacobian

    subroutine default_stress_only(this, available, loaded)
        class(rod_formulation_t), intent(inout) :: this
        logical, intent(out) :: available
        real(rk), intent(in), optional :: loaded(:)
        available = .false.
    end subroutine default_stress_only

    function default_nodes(this) result(nodes)
        class(rod_formulation_t), intent(in) :: this
        type(rod_nodes_t) :: nodes
        nodes = rod_nodes_t()
    end function default_nodes

    subroutine default_new_tie(this, kind, q_a, q_b, axis, tie)
        class(rod_formulation_t), intent(in) :: this
        character(len=*), intent(in) :: kind
        real(rk), intent(in) :: q_a(:), q_b(:), axis(3)
        class(node_tie_t), allocatable, intent(out) :: tie
    end subroutine default_new_tie

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
