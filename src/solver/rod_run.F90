#include "rs_macros.h"
!> Runs one system of a scene through time (DESIGN.md §3 and §5): one rod, or the rods that
!> joints, plates or contact couple (rs_model_coupling). It builds the system
!> (rs_system_rod_system: its members, couplings and record ledger), solves it with its own
!> rodmid stepper (on PETSC_COMM_SELF, or on all ranks for a shared system), and keeps each
!> rod's records until the caller writes them.
!>
!> PETSc calls back into the system through `bind(C)` procedures that receive a plain context
!> holding a pointer to the system (DESIGN.md §3); they wrap the raw arrays and call it.
module rs_solver_rod_run
    use, intrinsic :: iso_c_binding, only: c_int, c_bool, c_double, c_ptr, c_funloc, c_loc, c_f_pointer
    use rs_core_kinds, only: rk
    use rs_core_error, only: error_t, set_error
    use rs_core_logger, only: log_info
    use rs_core_strings, only: str, str_significant
    use rs_core_timer, only: wall_time
    use rs_model_scene, only: scene_t, step_count, record_time
    use rs_model_rod_history, only: rod_history_t
    use rs_formulations_formulation, only: formulation_traits_t, state_measures_t, state_valid
    use rs_formulations_energy_sentinel, only: energy_sentinel_t
    use rs_system_rod_system, only: rod_system_t
    use rs_solver_rod_stepper, only: rod_stepper_t, stepper_traits_t
    use rs_solver_arc_length, only: arc_length_path_t, arc_length_settings_t
    use rs_model_scene, only: solver_input_t, time_input_t, unset_real
    use rs_model_time_function, only: scene_time_kinks
    use rs_parallel_mpi_env, only: world_rank, world_size
    use rs_parallel_metis, only: partition_graph
    use rs_formulations_registry, only: is_bundle
    implicit none
    private

    public :: step_count, system_plan_text

    !> What PETSc's callbacks receive: the system, its traits and the vector sizes.
    type :: callback_context_t
        type(rod_system_t), pointer :: system => null()
        !> The system's traits, read once after its init (constants of the object): the
        !> solver flags of the stepper, the endpoint solves, the energy scheme of the sentinel.
        type(formulation_traits_t) :: traits
        integer :: n_state = 0
        integer :: n_unknown = 0
        integer :: n_values = 0
        !> End of the last accepted (sub)step: where a failed step leaves the state.
        real(rk) :: t_reached = 0.0_rk
        !> Wall time spent in the residual and Jacobian callbacks (assembly).
        real(rk) :: assembly_seconds = 0.0_rk
        !> Checks the energy each accepted (sub)step booked (issue 21 item 12): a scheme that
        !> creates energy beyond its allowance stops the rod after the step.
        type(energy_sentinel_t) :: sentinel
    end type callback_context_t

    !> One system through time (DESIGN.md §3, §5): its formulation, its own sequential stepper
    !> on PETSC_COMM_SELF, its state and each rod's records not yet written. The caller steps
    !> all systems of its rank together, one step at a time, so that the ranks meet at the
    !> flushes.
    type, public :: rod_runner_t
        !> The system's rods (indices into scene%rods; the first leads) and their records.
        integer, allocatable :: rods(:)
        type(rod_history_t), allocatable :: histories(:)
        type(rod_system_t), pointer :: system => null()
        type(callback_context_t), pointer :: context => null()
        type(rod_stepper_t) :: stepper
        !> The system is solved by all ranks together (DESIGN.md §5: a bundle on
        !> PETSC_COMM_WORLD); its state x is whole on every rank.
        logical :: shared = .false.
        !> The scene's solver settings, to build the stepper again when the pattern changes.
        type(solver_input_t) :: solver
        !> The scene's time stepping (&time: order, adaptive steps and their tolerances).
        type(time_input_t) :: time
        !> Adaptive steps: the load kinks they hit exactly (scene_time_kinks: the whole scene's,
        !> also those of other systems' loads, which only add step ends).
        real(rk), allocatable :: kinks(:)
        !> Adaptive steps: the steps taken over the run (the records are steps_done).
        integer :: adaptive_steps = 0
        !> Times the stepper was built again for a new Jacobian pattern (contact pairs).
        integer :: repatterns = 0
        !> Counted by the steppers of this runner that were replaced (pattern changes): Jacobians
        !> computed, steps accepted at the rounding floor.
        integer :: jacobians_before = 0
        integer :: floor_steps_before = 0
        integer :: shortened_before = 0
        !> A bundle (rods coupled by joints, plates or contact): its summary splits the time.
        logical :: bundle = .false.
        !> Wall time in `prepare` (bundles: the contact broad phase and any new stepper).
        real(rk) :: prepare_seconds = 0.0_rk
        !> The state X after the last accepted step.
        real(rk), allocatable :: x(:)
        !> The system stopped: its solver failed (`err` says where and why).
        logical :: failed = .false.
        !> The system stopped because its kinetic energy fell below &time kinetic_energy_tol
        !> (&time relaxation: statics by damped dynamics), or because its continuation's path
        !> passed the load time t_end (&time continuation).
        logical :: relaxed = .false.
        !> An arc-length continuation (&time continuation = 'arc_length'): its path, whose
        !> steps replace the load steps (rs_solver_arc_length).
        logical :: continuation = .false.
        type(arc_length_path_t) :: path
        type(error_t), allocatable :: err
        !> Last step done (the time grid's index) and the time of the last record.
        integer :: step = 0
        real(rk) :: t_recorded = 0.0_rk
        integer :: steps_done = 0
        integer :: total_iterations = 0
        integer :: total_cutbacks = 0
        !> Wall time in `advance` (Newton: assembly and linear solves).
        real(rk) :: solve_seconds = 0.0_rk
        !> Largest |energy-balance error| and |H| of the records so far.
        real(rk) :: max_balance = 0.0_rk
        real(rk) :: max_energy = 0.0_rk
    contains
        !> Build the system and the stepper; record the initial state unless restarting.
        procedure :: start => runner_start
        !> Continue from a checkpoint: the state after step `step` and the record ledger's sums.
        procedure :: restore => runner_restore
        !> Take step n of the scene's time grid (and the endpoint solve after the last one of a
        !> quasistatic run); record at the output stride. A failure records the last good state
        !> and stops the rod.
        procedure :: advance => runner_advance
        !> The record ledger's sums for a checkpoint (rs_system_ledger).
        procedure :: ledger => runner_ledger
        !> The state X for a checkpoint (rank-independent layout).
        procedure :: checkpoint_state => runner_checkpoint_state
        !> Kinetic energy of the state (-1: not reported).
        procedure :: kinetic_energy => runner_kinetic_energy
        !> The load time of the state x: the loads' time functions at it.
        procedure :: load_time => runner_load_time
        !> Wall time spent assembling residuals and Jacobians.
        procedure :: assembly_seconds => runner_assembly_seconds
        !> Destroy the stepper and the system and print the rod's summary line.
        procedure :: finish => runner_finish
        !> The system's name: its rods' names joined by '+'.
        procedure :: name => runner_name
        procedure, private :: stop_here, note_record
    end type rod_runner_t

contains

    !> Build the system of the scene's rods `rods` with room for `capacity` records between two
    !> writes.
    subroutine runner_start(this, scene, rods, capacity, restarting, err, shared)
        class(rod_runner_t), intent(inout) :: this
        type(scene_t), intent(in) :: scene
        integer, intent(in) :: rods(:), capacity
        logical, intent(in) :: restarting
        type(error_t), allocatable, intent(out) :: err
        !> Solve the system on all ranks together (default false: on this rank alone).
        logical, intent(in), optional :: shared
        this%rods = rods
        this%solver = scene%solver
        this%time = scene%time
        if (scene%time%adaptive) this%kinks = scene_time_kinks(scene)
        this%shared = .false.
        if (present(shared)) this%shared = shared .and. world_size() > 1
        this%bundle = is_bundle(scene, rods)
        allocate(this%system)
        call this%system%init(scene, rods, err)
        RS_RETURN_IF_ERROR(err)
        if (this%shared) then
            call distribute_system(this, err)
            RS_RETURN_IF_ERROR(err)
        end if
        call log_info(this%system%describe())

        allocate(this%histories(size(rods)))
        call this%system%init_history(this%histories, capacity)
        allocate(this%x(this%system%n_state()))
        call this%system%initial_state(this%x)

        allocate(this%context)
        this%context%system => this%system
        this%context%traits = this%system%traits()
        if (.not. restarting .and. scene%time%initial_equilibrium) then
            ! A dynamic run that starts in static equilibrium (issue 26 item 3, docs/theory/
            ! prestretched_starts.md): the statics at t = 0, continued from the initial
            ! placement as a quasistatic run's initial equilibrium, on a stepper of plain
            ! midpoint steps in the pseudo-time with a pivoting LU (the static Jacobian lacks
            ! the mass that makes a dynamic one's diagonal safe); the formulation leaves the
            ! state at rest. Then the dynamics' own stepper.
            call build_stepper(this, err, static_stage=.true.)
            RS_RETURN_IF_ERROR(err)
            call continue_equilibrium(this, 0.0_rk, 'initial equilibrium at t = 0')
            if (allocated(this%err)) this%failed = .true.
        end if
        call build_stepper(this, err)
        RS_RETURN_IF_ERROR(err)
        if (.not. restarting .and. this%context%traits%continues_equilibrium .and. &
                scene%time%equilibrium_solves) then
            ! Quasistatics (DESIGN.md §3): the midpoint load steps need a start in equilibrium
            ! with the loads at t = 0 (an unramped load, gravity on a shape that does not hang
            ! that way); otherwise every step reflects the unbalance and the states alternate.
            call continue_equilibrium(this, 0.0_rk, 'initial equilibrium at t = 0')
            if (allocated(this%err)) this%failed = .true.
        end if
        if (trim(scene%time%continuation) == 'arc_length') call start_path(this, scene)
        if (.not. restarting) call this%system%record(this%histories, 0.0_rk, this%x)
        if (this%continuation .and. .not. restarting) call note_load_time(this)
        call this%note_record()
    end subroutine runner_start

    !> The arc-length continuation of a quasistatic run (&time continuation): its path starts
    !> at the initial state, in equilibrium at the load time 0.
    subroutine start_path(this, scene)
        type(rod_runner_t), intent(inout) :: this
        type(scene_t), intent(in) :: scene
        type(arc_length_settings_t) :: settings
        integer :: i
        this%continuation = .true.
        settings = arc_length_settings_t(arc_length=scene%time%arc_length, &
            arc_length_max=max(scene%time%arc_length, scene%time%arc_length_max), &
            load_scale=scene%time%t_end, newton_atol=scene%solver%newton_atol, &
            max_newton=scene%solver%max_newton, branch_switch=scene%time%branch_switch)
        settings%arc_length_min = settings%arc_length * 0.5_rk**(2 * scene%solver%max_cutbacks)
        call this%path%init(this%system, settings, this%context%n_values, 0.0_rk, this%x)
        do i = 1, size(this%histories)
            call this%histories(i)%init_load_time()
        end do
    end subroutine start_path

    !> Step n of an arc-length continuation: one step along the path; the path ends (the
    !> system counts as done, `relaxed`) once its load time passes t_end.
    subroutine advance_path(this, scene, n)
        type(rod_runner_t), intent(inout) :: this
        type(scene_t), intent(in) :: scene
        integer, intent(in) :: n
        real(rk) :: started, load_before
        started = wall_time()
        load_before = this%path%load
        call this%path%advance(this%system, this%stepper, this%x, this%err)
        this%solve_seconds = this%solve_seconds + (wall_time() - started)
        this%total_iterations = this%total_iterations + this%path%iterations
        this%total_cutbacks = this%total_cutbacks + this%path%cutbacks
        if (allocated(this%err)) then
            this%err%message = 'arc-length continuation, step ' // str(n) // ': ' // &
                this%err%message
            this%failed = .true.
            return
        end if
        this%step = n
        this%steps_done = this%steps_done + 1
        this%context%t_reached = real(n, rk)
        if (len(this%path%event) > 0) then
            call log_info('  ' // this%name() // ': path step ' // str(n) // ': ' // &
                this%path%event)
            this%path%event = ''
        end if
        if (this%path%load > scene%time%t_end .and. load_before <= scene%time%t_end) &
            this%relaxed = .true.
        if (mod(n, scene%output%stride) == 0 .or. n == step_count(scene) .or. this%relaxed) then
            this%t_recorded = record_time(scene, n)
            call this%system%record(this%histories, this%t_recorded, this%x)
            call note_load_time(this)
            call this%note_record()
        end if
        if (this%relaxed) call log_info('  ' // this%name() // ': the path passed t_end = ' // &
            str(scene%time%t_end) // ' after ' // str(this%steps_done) // ' steps (load time ' // &
            str_significant(this%path%load, 8) // ')')
    end subroutine advance_path

    !> The path's load time with the newest record of every rod.
    subroutine note_load_time(this)
        type(rod_runner_t), intent(inout) :: this
        integer :: i
        do i = 1, size(this%histories)
            associate (h => this%histories(i))
                if (h%n_stored > 0) h%load_time(h%n_stored) = this%path%load
            end associate
        end do
    end subroutine note_load_time

    !> The equilibrium at load time t_load of a quasistatic run (DESIGN.md §3, "Quasistatics"),
    !> continued from the current state x: the formulation solves R(Y; t_load) = (1 - tau)
    !> R(x; t_load) for a pseudo-time tau from 0 to 1 (a Newton homotopy, so that the solution
    !> is the one connected to x), its rows scaled as a step of unit length: forces, so that
    !> newton_atol means the same whatever dt (with dt = 0.01 as the scale, the backtracking
    !> line search, whose merit function then hardly sees the equilibrium rows, took ten times
    !> the iterations on the unramped cantilever of tests/regression/ph_director/
    !> statics_increments.py). An increment of tau whose Newton fails is halved (by the stepper,
    !> then here); an increment that turns a cross-section by more than max_increment_rotation
    !> is rejected and halved too, because Newton may converge far from its start on another
    !> branch (a folded rod) without failing. Accepted increments are doubled again. On failure
    !> this%err says where; x is the last accepted increment.
    subroutine continue_equilibrium(this, t_load, label)
        type(rod_runner_t), intent(inout) :: this
        real(rk), intent(in) :: t_load
        character(len=*), intent(in) :: label
        !> A quarter radian: the unramped cantilever of tests/regression/ph_director/
        !> statics_increments.py is then followed in 9 increments (115 Newton iterations, failed
        !> attempts included), while the folded state one Newton solve reached from the straight
        !> rod is 1.2 rad from the elastica's at its farthest node.
        real(rk), parameter :: max_increment_rotation = 0.25_rk
        !> The smallest increment of tau this routine tries (the stepper halves it 6 more
        !> times by default): below it the continuation is at a limit point, where no branch
        !> goes on (the cantilever under three times the loads of seed 000 §6.3 reaches one
        !> at tau = 0.694 of its endpoint solve, and halving on spent 12 s approaching it).
        real(rk), parameter :: smallest_increment = 2.0_rk**(-10)
        real(rk), allocatable :: trial(:)
        character(len=:), allocatable :: message
        real(rk) :: tau, dtau, rest, fnorm, rotation, t_reached, started
        type(state_measures_t) :: measures
        integer :: substeps, cutbacks, iterations, total, increments
        t_reached = this%context%t_reached
        started = wall_time()
        call this%system%set_step_problem(.true., t_load, continue_from=this%x)
        tau = 0.0_rk
        dtau = 1.0_rk
        total = 0
        increments = 0
        do
            rest = 1.0_rk - tau
            dtau = min(dtau, rest)
            trial = this%x
            call this%stepper%advance(tau, dtau, trial, substeps, cutbacks, iterations, fnorm, &
                this%err)
            total = total + iterations
            this%total_cutbacks = this%total_cutbacks + cutbacks
            if (allocated(this%err)) then
                ! The stepper halved the increment max_cutbacks times: halve it once more and
                ! start again from the last accepted increment.
                if (0.5_rk * dtau < smallest_increment) then
                    this%err%message = 'continuation in the pseudo-time t from 0 to 1 ' // &
                        '(the share of the unbalance removed): ' // this%err%message // &
                        ' Increments of t below ' // str_significant(smallest_increment, 3) // &
                        ' failed too: a limit point, where no equilibrium branch goes on?'
                    exit
                end if
                deallocate(this%err)
                dtau = 0.5_rk * dtau
                cycle
            end if
            measures = this%system%state_measures(trial, from=this%x)
            rotation = measures%largest_rotation
            if (rotation > max_increment_rotation) then
                this%total_cutbacks = this%total_cutbacks + 1
                if (0.5_rk * dtau < smallest_increment) then
                    message = 'an increment of ' // str_significant(dtau, 3) // ' of the ' // &
                        'load unbalance at tau = ' // str_significant(tau, 6) // ' still ' // &
                        'turns a cross-section by ' // str_significant(rotation, 3) // &
                        ' rad (at most ' // str_significant(max_increment_rotation, 3) // &
                        '): no equilibrium branch to follow (a limit point?)'
                    RS_SET_ERROR(this%err, 'rod_runner%continue_equilibrium', message)
                    exit
                end if
                dtau = 0.5_rk * dtau
                cycle
            end if
            this%x = trial
            increments = increments + 1
            if (dtau == rest) exit
            tau = tau + dtau
            dtau = 2.0_rk * dtau
        end do
        call this%system%set_step_problem(.false., t_load)
        this%context%t_reached = t_reached
        this%total_iterations = this%total_iterations + total
        this%solve_seconds = this%solve_seconds + (wall_time() - started)
        if (allocated(this%err)) then
            this%err%message = label // ': ' // this%err%message
            return
        end if
        if (increments > 1 .or. total > 0) call log_info('  ' // this%name() // ': ' // label // &
            ' in ' // str(increments) // ' increment(s), ' // str(total) // ' Newton iterations')
    end subroutine continue_equilibrium

    !> A shared system's rods to ranks: METIS on the formulation's coupling graph (DESIGN.md
    !> §5; every rank computes the same partition), logged.
    subroutine distribute_system(this, err)
        type(rod_runner_t), intent(inout) :: this
        type(error_t), allocatable, intent(out) :: err
        call partition_system(this%system, err)
    end subroutine distribute_system

    subroutine partition_system(system, err)
        type(rod_system_t), intent(inout) :: system
        type(error_t), allocatable, intent(out) :: err
        integer, allocatable :: xadj(:), adjncy(:), weights(:), part(:)
        integer :: i
        call system%coupling_graph(xadj, adjncy, weights)
        allocate(part(size(weights)))
        if (size(weights) <= world_size()) then
            part = [(i - 1, i = 1, size(weights))]
        else
            call partition_graph(xadj, adjncy, weights, world_size(), part, err)
            RS_RETURN_IF_ERROR(err)
        end if
        call system%distribute(part, world_rank())
    end subroutine partition_system

    !> The plan of a coupled system of the scene's rods `rods` (--check-input): the system a
    !> run builds, its linear solver and, shared by the ranks, its partition with the edge cut
    !> and the load balance (issue 23 item 2), as the run logs them.
    function system_plan_text(scene, rods, shared, err) result(text)
        type(scene_t), intent(in) :: scene
        integer, intent(in) :: rods(:)
        logical, intent(in) :: shared
        type(error_t), allocatable, intent(out) :: err
        character(len=:), allocatable :: text
        type(rod_system_t), allocatable :: system
        text = ''
        allocate(system)
        call system%init(scene, rods, err)
        RS_RETURN_IF_ERROR(err)
        if (shared .and. world_size() > 1) then
            call partition_system(system, err)
            RS_RETURN_IF_ERROR(err)
        end if
        text = system%describe()
    end function system_plan_text

    !> The stepper of the formulation's current pattern (again after a pattern change); with
    !> static_stage, that of the initial equilibrium of a dynamic run: order 2, fixed steps,
    !> the pivoting LU.
    subroutine build_stepper(this, err, static_stage)
        type(rod_runner_t), intent(inout) :: this
        type(error_t), allocatable, intent(out) :: err
        logical, intent(in), optional :: static_stage
        integer, allocatable :: row_ptr(:), cols(:), state_entries(:), unknown_entries(:)
        logical, allocatable :: weigh(:)
        integer :: owned(4)
        integer :: jacobians, floor_steps, shortened
        type(time_input_t) :: time
        type(formulation_traits_t) :: traits
        logical :: static
        static = .false.
        if (present(static_stage)) static = static_stage
        time = this%time
        traits = this%context%traits
        if (static) then
            time%order = 2
            time%adaptive = .false.
            traits%native_lu = .false.
        end if
        call this%system%jacobian_pattern(row_ptr, cols)
        call this%stepper%run_stats(jacobians, floor_steps, shortened)
        this%jacobians_before = this%jacobians_before + jacobians
        this%floor_steps_before = this%floor_steps_before + floor_steps
        this%shortened_before = this%shortened_before + shortened
        this%context%n_state = this%system%n_state()
        this%context%n_unknown = this%system%n_unknown()
        this%context%n_values = size(cols)
        if (this%shared) then
            call this%system%owned_range(owned(1), owned(2), owned(3), owned(4))
            call this%stepper%create(this%context%n_state, this%context%n_unknown, row_ptr, cols, &
                c_funloc(residual_callback), c_funloc(jacobian_callback), &
                c_funloc(predictor_callback), c_funloc(update_callback), c_funloc(poststep_callback), &
                c_loc(this%context), stepper_traits(this%solver, traits, time), err, &
                owned=owned, blocks=this%system%solver_blocks())
            RS_RETURN_IF_ERROR(err)
            call this%system%needed_entries(state_entries, unknown_entries)
            call this%stepper%set_needed(state_entries, unknown_entries, err)
            RS_RETURN_IF_ERROR(err)
        else
            call this%stepper%create(this%context%n_state, this%context%n_unknown, row_ptr, cols, &
                c_funloc(residual_callback), c_funloc(jacobian_callback), &
                c_funloc(predictor_callback), c_funloc(update_callback), c_funloc(poststep_callback), &
                c_loc(this%context), stepper_traits(this%solver, traits, time), err, &
                blocks=this%system%solver_blocks())
            RS_RETURN_IF_ERROR(err)
        end if
        ! Iterates the system may refuse (contact's barrier): Newton steps are shortened to
        ! admissible ones instead of the time step being cut (include/rs_rodmid.h).
        if (this%system%refuses_iterates()) then
            call this%stepper%set_admissible(c_funloc(admissible_callback), err)
            RS_RETURN_IF_ERROR(err)
        end if
        if (time%adaptive) then
            call this%stepper%set_breakpoints(this%kinks, err)
            RS_RETURN_IF_ERROR(err)
            allocate(weigh(this%context%n_state))
            call this%system%error_entries(weigh)
            call this%stepper%set_error_entries(weigh, err)
        end if
    end subroutine build_stepper

    !> What the stepper is built with: the scene's Newton settings (&solver) and the
    !> formulation's solver flags, as the one C struct of include/rs_rod_stepper.h.
    !> The adaptive steps' bounds default to dt_max = dt (the record interval),
    !> dt_initial = min(dt / 100, dt_max) and dt_min = min(1e-12 t_end, dt_initial).
    pure function stepper_traits(solver, traits, time) result(stepper)
        type(solver_input_t), intent(in) :: solver
        type(formulation_traits_t), intent(in) :: traits
        type(time_input_t), intent(in) :: time
        type(stepper_traits_t) :: stepper
        real(rk) :: dt_max, dt_initial, dt_min
        dt_max = merge(time%dt, time%dt_max, time%dt_max == unset_real)
        dt_initial = merge(min(0.01_rk * time%dt, dt_max), time%dt_initial, &
            time%dt_initial == unset_real)
        dt_min = merge(min(1.0e-12_rk * time%t_end, dt_initial), time%dt_min, &
            time%dt_min == unset_real)
        stepper = stepper_traits_t(newton_atol=solver%newton_atol, &
            newton_rtol=solver%newton_rtol, jacobian_reuse=solver%jacobian_reuse, &
            max_newton=solver%max_newton, max_cutbacks=solver%max_cutbacks, &
            native_lu=traits%native_lu, banded_unknowns=traits%banded_unknowns, &
            full_newton=traits%full_newton, linear_step=traits%linear_step, &
            order=int(time%order, c_int), adaptive=logical(time%adaptive, c_bool), &
            atol=time%atol, rtol=time%rtol, dt_min=dt_min, dt_max=dt_max, &
            dt_initial=dt_initial)
    end function stepper_traits

    !> Before a step from x: the formulation refreshes what the step needs (contact pairs) and
    !> the stepper is built again if the Jacobian pattern changed.
    subroutine prepare(this, t_n, h)
        type(rod_runner_t), intent(inout) :: this
        real(rk), intent(in) :: t_n, h
        logical :: repattern
        real(rk) :: started
        started = wall_time()
        call this%system%prepare_step(t_n, h, this%x, repattern)
        if (repattern) then
            this%repatterns = this%repatterns + 1
            call build_stepper(this, this%err)
        end if
        this%prepare_seconds = this%prepare_seconds + (wall_time() - started)
    end subroutine prepare

    subroutine runner_restore(this, scene, step, state, ledger, err)
        class(rod_runner_t), intent(inout) :: this
        type(scene_t), intent(in) :: scene
        integer, intent(in) :: step
        !> The state and the record ledger's sums (rs_system_ledger) of the checkpoint.
        real(rk), intent(in) :: state(:), ledger(:)
        type(error_t), allocatable, intent(out) :: err
        character(len=:), allocatable :: message
        if (size(state) /= size(this%x) .or. size(ledger) /= this%system%n_ledger()) then
            message = 'the checkpoint of rod "' // this%histories(1)%name // '" holds ' // &
                str(size(state)) // ' state and ' // str(size(ledger)) // ' ledger ' // &
                'values; the scene builds ' // str(size(this%x)) // ' and ' // &
                str(this%system%n_ledger()) // ' (a different discretization?)'
            RS_SET_ERROR(err, 'rod_runner%restore', message)
            return
        end if
        call this%system%from_canonical(state, this%x)
        call this%system%restore_ledger(ledger)
        this%step = step
        this%t_recorded = min(real(step, rk) * scene%time%dt, scene%time%t_end)
        this%context%t_reached = this%t_recorded
    end subroutine runner_restore

    subroutine runner_advance(this, scene, n)
        class(rod_runner_t), intent(inout) :: this
        type(scene_t), intent(in) :: scene
        integer, intent(in) :: n
        real(rk) :: t_n, h, fnorm, started, kinetic
        type(state_measures_t) :: measures
        integer :: n_steps, substeps, cutbacks, iterations
        logical :: last_step
        substeps = 0
        cutbacks = 0
        iterations = 0
        fnorm = 0.0_rk

        if (this%failed .or. this%relaxed) return
        if (this%continuation) then
            call advance_path(this, scene, n)
            return
        end if
        n_steps = step_count(scene)
        t_n = real(n - 1, rk) * scene%time%dt
        h = min(scene%time%dt, scene%time%t_end - t_n)
        started = wall_time()
        call prepare(this, t_n, h)
        if (.not. allocated(this%err)) call this%stepper%advance(t_n, h, this%x, substeps, &
            cutbacks, iterations, fnorm, this%err)
        this%solve_seconds = this%solve_seconds + (wall_time() - started)
        this%total_iterations = this%total_iterations + iterations
        this%total_cutbacks = this%total_cutbacks + cutbacks
        this%adaptive_steps = this%adaptive_steps + substeps
        if (.not. allocated(this%err) .and. this%context%sentinel%tripped) then
            ! The state that shows the energy created is recorded, with its balance error.
            RS_SET_ERROR(this%err, 'rod_runner%advance', this%context%sentinel%message())
        end if
        if (allocated(this%err)) then
            ! The stepper left x at the last good state (after any accepted substeps of this
            ! step); record it so it is written.
            call this%stop_here()
            return
        end if
        ! &time equilibrium_solves = .false.: the midpoint load path alone (seed 001).
        last_step = n == n_steps .and. scene%time%equilibrium_solves
        if (last_step .and. this%context%traits%continues_equilibrium) then
            ! Quasistatics (DESIGN.md §3): the midpoint steps are equilibria at the mid loads;
            ! the last record is the equilibrium at the final load itself, continued from the
            ! last step's state.
            call continue_equilibrium(this, scene%time%t_end, 'endpoint equilibrium at t = ' // &
                str(scene%time%t_end))
            if (allocated(this%err)) then
                call this%stop_here()
                return
            end if
        else if (last_step .and. this%context%traits%wants_endpoint_solve) then
            call this%system%set_step_problem(.true., scene%time%t_end)
            started = wall_time()
            call prepare(this, t_n, h)
            if (.not. allocated(this%err)) call this%stepper%advance(t_n, h, this%x, substeps, &
                cutbacks, iterations, fnorm, this%err)
            this%solve_seconds = this%solve_seconds + (wall_time() - started)
            call this%system%set_step_problem(.false., scene%time%t_end)
            this%total_iterations = this%total_iterations + iterations
            this%total_cutbacks = this%total_cutbacks + cutbacks
            if (allocated(this%err)) then
                this%err%message = 'endpoint equilibrium at t = ' // str(scene%time%t_end) // &
                    ': ' // this%err%message
                call this%stop_here()
                return
            end if
            call log_info('  ' // this%name() // ': endpoint equilibrium at t = ' // &
                str(scene%time%t_end) // ' in ' // str(iterations) // ' Newton iterations')
        end if
        this%step = n
        this%steps_done = this%steps_done + 1
        if (mod(n, scene%output%stride) == 0 .or. n == n_steps) then
            ! n dt rather than t_n + h, so that stored times are the grid's own values.
            this%t_recorded = min(real(n, rk) * scene%time%dt, scene%time%t_end)
            call this%system%record(this%histories, this%t_recorded, this%x)
            call this%note_record()
        end if
        if (.not. scene%time%relaxation) return
        ! Statics by damped dynamics (seed 004 §2.4): stop once the motion has died out.
        measures = this%system%state_measures(this%x)
        kinetic = measures%kinetic_energy
        if (kinetic < 0.0_rk .or. kinetic >= scene%time%kinetic_energy_tol) return
        this%relaxed = .true.
        if (this%t_recorded < min(real(n, rk) * scene%time%dt, scene%time%t_end)) then
            this%t_recorded = min(real(n, rk) * scene%time%dt, scene%time%t_end)
            call this%system%record(this%histories, this%t_recorded, this%x)
            call this%note_record()
        end if
        call log_info('  ' // this%name() // ': relaxed after ' // str(this%steps_done) // &
            ' steps (t = ' // str(this%t_recorded) // '): kinetic energy ' // &
            str_significant(kinetic, 3) // ' < ' // str_significant(scene%time%kinetic_energy_tol, 3))
    end subroutine runner_advance

    !> After a failure: record the last good state (if it is new) and stop the rod.
    subroutine stop_here(this)
        class(rod_runner_t), intent(inout) :: this
        this%failed = .true.
        if (this%context%t_reached > this%t_recorded) then
            call this%system%record(this%histories, this%context%t_reached, this%x)
            call this%note_record()
        end if
    end subroutine stop_here

    !> Track the balance error and energy of the newest record (for the progress line): sums
    !> over the system's rods (joints exchange energy between them).
    subroutine note_record(this)
        class(rod_runner_t), intent(inout) :: this
        real(rk) :: balance, energy
        integer :: k, i
        balance = 0.0_rk
        energy = 0.0_rk
        do i = 1, size(this%histories)
            associate (h => this%histories(i))
                k = h%n_stored
                if (k < 1) return
                if (allocated(h%balance_error)) balance = balance + h%balance_error(k)
                if (allocated(h%total)) energy = energy + h%total(k)
            end associate
        end do
        this%max_balance = max(this%max_balance, abs(balance))
        this%max_energy = max(this%max_energy, abs(energy))
    end subroutine note_record

    !> The system's name: its rods' names joined by '+'.
    function runner_name(this) result(name)
        class(rod_runner_t), intent(in) :: this
        character(len=:), allocatable :: name
        integer :: i
        name = this%histories(1)%name
        do i = 2, size(this%histories)
            name = name // '+' // this%histories(i)%name
        end do
    end function runner_name

    !> The state for a checkpoint, in the formulation's rank-independent layout.
    function runner_checkpoint_state(this) result(values)
        class(rod_runner_t), intent(in) :: this
        real(rk), allocatable :: values(:)
        allocate(values(size(this%x)))
        call this%system%canonical_state(this%x, values)
    end function runner_checkpoint_state

    function runner_ledger(this) result(values)
        class(rod_runner_t), intent(in) :: this
        real(rk), allocatable :: values(:)
        allocate(values(this%system%n_ledger()))
        call this%system%save_ledger(values)
    end function runner_ledger

    real(rk) function runner_kinetic_energy(this)
        class(rod_runner_t), intent(in) :: this
        type(state_measures_t) :: measures
        measures = this%system%state_measures(this%x)
        runner_kinetic_energy = measures%kinetic_energy
    end function runner_kinetic_energy

    !> The load time of the state x: a continuation's is its path's current point's (the
    !> load time an unknown of the path, anywhere: past t_end at its end, or below it after
    !> path_steps or past a limit point), a run on the time grid's the time of its last step,
    !> min(step dt, t_end) (t_end once it completed). What &modes about = 'equilibrium'
    !> linearizes with (rs_app_run_modes), not t_end.
    real(rk) function runner_load_time(this)
        class(rod_runner_t), intent(in) :: this
        if (this%continuation) then
            runner_load_time = this%path%load
        else
            runner_load_time = min(real(this%step, rk) * this%time%dt, this%time%t_end)
        end if
    end function runner_load_time

    real(rk) function runner_assembly_seconds(this)
        class(rod_runner_t), intent(in) :: this
        runner_assembly_seconds = 0.0_rk
        if (associated(this%context)) runner_assembly_seconds = this%context%assembly_seconds
    end function runner_assembly_seconds

    subroutine runner_finish(this, quiet)
        class(rod_runner_t), intent(inout) :: this
        !> No summary line (another rank of a shared system prints it).
        logical, intent(in), optional :: quiet
        real(rk) :: elapsed, assembly
        integer :: jacobians, floor_steps, shortened, rejected
        real(rk) :: h_smallest, h_largest
        assembly = this%assembly_seconds()
        call this%stepper%run_stats(jacobians, floor_steps, shortened)
        call this%stepper%adaptive_stats(rejected, h_smallest, h_largest)
        jacobians = this%jacobians_before + jacobians + this%path%factorizations
        floor_steps = this%floor_steps_before + floor_steps
        shortened = this%shortened_before + shortened
        call this%stepper%destroy()
        if (associated(this%context)) deallocate(this%context)
        if (associated(this%system)) deallocate(this%system)
        if (present(quiet)) then
            if (quiet) return
        end if
        ! The summary line is also what tests/bench/ reads (time loop only, output excluded).
        elapsed = this%solve_seconds
        call log_info('  ' // this%name() // ': ' // str(this%steps_done) // ' steps, ' // &
            str(this%total_iterations) // ' Newton iterations, ' // str(this%total_cutbacks) // &
            ' cut-backs; time loop ' // str_significant(elapsed, 4) // ' s, per step ' // &
            str_significant(elapsed / max(1, this%steps_done), 4) // ' s, per Newton ' // &
            'iteration ' // str_significant(elapsed / max(1, this%total_iterations), 4) // ' s; ' // &
            str(jacobians) // ' Jacobians factored')
        if (this%time%adaptive) call log_info('  ' // this%name() // ': adaptive steps: ' // &
            str(this%adaptive_steps) // ' accepted, ' // str(rejected) // ' rejected by the ' // &
            'error control, ' // str(this%total_cutbacks) // ' cut by Newton failures; steps ' // &
            'from ' // str_significant(h_smallest, 3) // ' to ' // str_significant(h_largest, 3) // &
            ' s (rtol ' // str_significant(this%time%rtol, 3) // ', atol ' // &
            str_significant(this%time%atol, 3) // ')')
        if (floor_steps > 0) call log_info('  ' // this%name() // ': ' // str(floor_steps) // &
            ' steps ended above newton_atol at the rounding floor (Newton run to stagnation: ' // &
            'the residual rounding the unknowns makes; far from the origin, docs/stability.md)')
        if (shortened > 0) call log_info('  ' // this%name() // ': ' // str(shortened) // &
            ' Newton steps or predictions shortened to stay admissible (contact''s swept test ' // &
            'and motion limit, ' // &
            'docs/theory/bundles.md)')
        if (this%bundle) call log_info('  ' // this%name() // ': of that, assembly ' // &
            str_significant(assembly, 4) // ' s, contact search ' // &
            str_significant(this%prepare_seconds, 4) // ' s (' // str(this%repatterns) // &
            ' new Jacobian patterns), linear solves and the rest ' // &
            str_significant(elapsed - assembly - this%prepare_seconds, 4) // ' s')
    end subroutine runner_finish

    ! ---- PETSc callbacks (src/solver/rod_stepper.c) -------------------------------------------

    function residual_callback(ctx, t_n, h, x_n, y, f) result(status) bind(C)
        type(c_ptr), value :: ctx, x_n, y, f
        real(c_double), value :: t_n, h
        integer(c_int) :: status
        type(callback_context_t), pointer :: context
        real(rk), pointer :: x_n_(:), y_(:), f_(:)
        real(rk) :: started
        integer :: state
        call c_f_pointer(ctx, context)
        call c_f_pointer(x_n, x_n_, [context%n_state])
        call c_f_pointer(y, y_, [context%n_unknown])
        call c_f_pointer(f, f_, [context%n_unknown])
        started = wall_time()
        call context%system%step_residual(t_n, h, x_n_, y_, f_, state)
        context%assembly_seconds = context%assembly_seconds + (wall_time() - started)
        status = int(state, c_int)
    end function residual_callback

    function admissible_callback(ctx, t_n, h, x_n, y) result(status) bind(C)
        type(c_ptr), value :: ctx, x_n, y
        real(c_double), value :: t_n, h
        integer(c_int) :: status
        type(callback_context_t), pointer :: context
        real(rk), pointer :: x_n_(:), y_(:)
        real(rk) :: started
        call c_f_pointer(ctx, context)
        call c_f_pointer(x_n, x_n_, [context%n_state])
        call c_f_pointer(y, y_, [context%n_unknown])
        started = wall_time()
        status = merge(0_c_int, 1_c_int, context%system%step_admissible(t_n, h, x_n_, y_))
        context%assembly_seconds = context%assembly_seconds + (wall_time() - started)
    end function admissible_callback

    function jacobian_callback(ctx, t_n, h, x_n, y, values) result(status) bind(C)
        type(c_ptr), value :: ctx, x_n, y, values
        real(c_double), value :: t_n, h
        integer(c_int) :: status
        type(callback_context_t), pointer :: context
        real(rk), pointer :: x_n_(:), y_(:), values_(:)
        real(rk) :: started
        integer :: state
        call c_f_pointer(ctx, context)
        call c_f_pointer(x_n, x_n_, [context%n_state])
        call c_f_pointer(y, y_, [context%n_unknown])
        call c_f_pointer(values, values_, [context%n_values])
        started = wall_time()
        call context%system%step_jacobian(t_n, h, x_n_, y_, values_, state)
        context%assembly_seconds = context%assembly_seconds + (wall_time() - started)
        status = int(state, c_int)
    end function jacobian_callback

    function predictor_callback(ctx, t_n, h, x_n, y) result(status) bind(C)
        type(c_ptr), value :: ctx, x_n, y
        real(c_double), value :: t_n, h
        integer(c_int) :: status
        type(callback_context_t), pointer :: context
        real(rk), pointer :: x_n_(:), y_(:)
        call c_f_pointer(ctx, context)
        call c_f_pointer(x_n, x_n_, [context%n_state])
        call c_f_pointer(y, y_, [context%n_unknown])
        call context%system%predictor(t_n, h, x_n_, y_)
        status = state_valid
    end function predictor_callback

    function update_callback(ctx, t_n, h, x_n, y, x_1) result(status) bind(C)
        type(c_ptr), value :: ctx, x_n, y, x_1
        real(c_double), value :: t_n, h
        integer(c_int) :: status
        type(callback_context_t), pointer :: context
        real(rk), pointer :: x_n_(:), y_(:), x_1_(:)
        call c_f_pointer(ctx, context)
        call c_f_pointer(x_n, x_n_, [context%n_state])
        call c_f_pointer(y, y_, [context%n_unknown])
        call c_f_pointer(x_1, x_1_, [context%n_state])
        call context%system%update(t_n, h, x_n_, y_, x_1_)
        status = state_valid
    end function update_callback

    function poststep_callback(ctx, t_n, h, x_n, x_1, newton_iterations, fnorm) result(status) &
            bind(C)
        type(c_ptr), value :: ctx, x_n, x_1
        real(c_double), value :: t_n, h, fnorm
        integer(c_int), value :: newton_iterations
        integer(c_int) :: status
        type(callback_context_t), pointer :: context
        real(rk), pointer :: x_n_(:), x_1_(:)
        call c_f_pointer(ctx, context)
        call c_f_pointer(x_n, x_n_, [context%n_state])
        call c_f_pointer(x_1, x_1_, [context%n_state])
        call context%system%accept_step(t_n, h, x_n_, x_1_, int(newton_iterations), fnorm)
        context%t_reached = t_n + h
        call context%sentinel%check(context%traits%energy_scheme, &
            context%system%step_energy, t_n + h)
        status = state_valid
    end function poststep_callback

end module rs_solver_rod_run
