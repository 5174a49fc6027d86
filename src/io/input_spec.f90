!> The input language's tables: every namelist group of DESIGN.md §6 and every variable with its
!> kind, number of values, unit, default, allowed values or range and meaning. The lexer checks
!> names against these tables, the reader checks values generically against them, and
!> `rodsolve --input-reference` prints them as docs/user/input.md (a test keeps the two equal).
!>
!> Groups that later versions fill in (`implemented = .false.`) are known by name, so a scene
!> using them gets "not available in this version" rather than "unknown group".
module rs_io_input_spec
    use rs_core_kinds, only: rk
    use rs_core_strings, only: to_lower, str
    use rs_model_scene, only: max_table, max_branches, max_polyline_points, max_curvature_rows, &
        max_sweep_values, max_sweep_members, max_plate_rods
    use rs_model_units, only: unit_systems
    use rs_model_time_function, only: time_function_names
    use rs_model_support, only: hold_entry_names
    use rs_formulations_registry, only: available_formulations, default_formulation
    implicit none
    private

    public :: variable_spec_t, group_spec_t, input_groups, find_group, find_variable, spec_v
    public :: range_description, in_range, split_condition, group_names, variable_names

    !> One input variable.
    type :: variable_spec_t
        character(len=32) :: name = ''
        !> 'integer', 'real', 'logical' or 'string'.
        character(len=8) :: kind = ''
        !> Number of values: exactly `min_count` when min_count = max_count, else a range.
        integer :: min_count = 1
        integer :: max_count = 1
        character(len=16) :: unit = '-'
        !> Allowed string values separated by '|'; '' means any text.
        character(len=160) :: allowed = ''
        real(rk) :: lower = -huge(1.0_rk)
        real(rk) :: upper = huge(1.0_rk)
        logical :: lower_inclusive = .true.
        logical :: upper_inclusive = .true.
        logical :: required = .false.
        !> 'variable=value' (value unquoted, lower case): the variable is required when the
        !> group's `variable` has that value (given or by default), e.g. 'geometry=helix'.
        character(len=48) :: required_if = ''
        !> 'variable=value': the variable may only be given when that condition holds.
        character(len=48) :: only_if = ''
        character(len=48) :: default_text = ''
        !> A valid value as it would be written in a scene (docs/user/input.md).
        character(len=48) :: example = ''
        character(len=640) :: description = ''
    end type variable_spec_t

    !> One namelist group.
    type :: group_spec_t
        character(len=16) :: name = ''
        logical :: repeatable = .false.
        logical :: implemented = .true.
        character(len=400) :: description = ''
        type(variable_spec_t), allocatable :: variables(:)
    end type group_spec_t

contains

    !> A variable spec; optional arguments as in variable_spec_t. Every variable has an example
    !> (a unit test reads each one back through the reader).
    pure function spec_v(name, kind, unit, default_text, description, count, max_count, allowed, &
            lower, lower_inclusive, upper, upper_inclusive, required, required_if, only_if, &
            example) result(v)
        character(len=*), intent(in) :: name, kind, unit, default_text, description
        integer, intent(in), optional :: count, max_count
        character(len=*), intent(in), optional :: allowed, required_if, only_if, example
        real(rk), intent(in), optional :: lower, upper
        logical, intent(in), optional :: lower_inclusive, upper_inclusive, required
        type(variable_spec_t) :: v
        v%name = name
        v%kind = kind
        v%unit = unit
        v%default_text = default_text
        v%description = description
        if (present(example)) v%example = example
        if (present(required_if)) v%required_if = required_if
        if (present(only_if)) v%only_if = only_if
        if (present(count)) then
            v%min_count = count
            v%max_count = count
        end if
        if (present(max_count)) v%max_count = max_count
        if (present(allowed)) v%allowed = allowed
        if (present(lower)) v%lower = lower
        if (present(upper)) v%upper = upper
        if (present(lower_inclusive)) v%lower_inclusive = lower_inclusive
        if (present(upper_inclusive)) v%upper_inclusive = upper_inclusive
        if (present(required)) v%required = required
    end function spec_v

    !> All groups of the input language, in the order the reference documents them.
    function input_groups() result(groups)
        type(group_spec_t), allocatable :: groups(:)
        allocate(groups(15))
        groups(1) = run_group()
        groups(2) = time_group()
        groups(3) = solver_group()
        groups(4) = output_group()
        groups(5) = rod_group()
        groups(6) = bc_group()
        groups(7) = load_group()
        groups(8) = actuator_group()
        groups(9) = joint_group()
        groups(10) = plate_group()
        groups(11) = contact_group()
        groups(12) = sweep_group()
        groups(13) = obstacle_group()
        groups(14) = segment_group()
        groups(15) = modes_group()
    end function input_groups

    !> Index of group `name` in `groups`, 0 if unknown.
    pure integer function find_group(groups, name) result(index_)
        type(group_spec_t), intent(in) :: groups(:)
        character(len=*), intent(in) :: name
        integer :: i
        index_ = 0
        do i = 1, size(groups)
            if (trim(groups(i)%name) == to_lower(trim(name))) then
                index_ = i
                return
            end if
        end do
    end function find_group

    !> Index of variable `name` in `group`, 0 if unknown.
    pure integer function find_variable(group, name) result(index_)
        type(group_spec_t), intent(in) :: group
        character(len=*), intent(in) :: name
        integer :: i
        index_ = 0
        do i = 1, size(group%variables)
            if (to_lower(trim(group%variables(i)%name)) == to_lower(trim(name))) then
                index_ = i
                return
            end if
        end do
    end function find_variable

    !> The variable and value of a condition 'variable=value' (required_if, only_if).
    pure subroutine split_condition(condition, variable, value)
        character(len=*), intent(in) :: condition
        character(len=:), allocatable, intent(out) :: variable, value
        integer :: eq
        eq = index(condition, '=')
        variable = trim(condition(1:eq - 1))
        value = trim(condition(eq + 1:))
    end subroutine split_condition

    !> True if `value` lies in the allowed range of numeric variable `spec`.
    pure logical function in_range(spec, value)
        type(variable_spec_t), intent(in) :: spec
        real(rk), intent(in) :: value
        in_range = value >= spec%lower .and. value <= spec%upper
        if (.not. spec%lower_inclusive) in_range = in_range .and. value /= spec%lower
        if (.not. spec%upper_inclusive) in_range = in_range .and. value /= spec%upper
    end function in_range

    !> The allowed range of a numeric variable, e.g. "> 0" or ">= 1 and <= 5".
    function range_description(spec) result(text)
        type(variable_spec_t), intent(in) :: spec
        character(len=:), allocatable :: text
        text = ''
        if (spec%lower > -huge(1.0_rk)) then
            if (spec%lower_inclusive) then
                text = '>= ' // bound(spec%lower)
            else
                text = '> ' // bound(spec%lower)
            end if
        end if
        if (spec%upper < huge(1.0_rk)) then
            if (len(text) > 0) text = text // ' and '
            if (spec%upper_inclusive) then
                text = text // '<= ' // bound(spec%upper)
            else
                text = text // '< ' // bound(spec%upper)
            end if
        end if
    contains
        function bound(value) result(b)
            real(rk), intent(in) :: value
            character(len=:), allocatable :: b
            if (spec%kind == 'integer') then
                b = str(nint(value))
            else
                b = str(value)
            end if
        end function bound
    end function range_description

    !> The values of &run formulation_default and &rod formulation: a formulation of this build
    !> (rs_formulations_registry) or 'auto' (DESIGN.md §4).
    function formulation_choices() result(choices)
        character(len=:), allocatable :: choices
        choices = available_formulations('|') // '|auto'
    end function formulation_choices

    function run_group() result(g)
        type(group_spec_t) :: g
        g%name = 'run'
        g%description = 'What the run is, and choices that hold for the whole scene.'
        g%variables = [ &
            spec_v('title', 'string', '-', "''", 'A title stored in the output.', &
                example="'cantilever under a tip load'"), &
            spec_v('formulation_default', 'string', '-', "'" // default_formulation() // "'", &
                'Formulation of rods that do not name one (DESIGN.md §1).', allowed=formulation_choices(), &
                example="'auto'"), &
            spec_v('log_level', 'string', '-', "'info'", 'Most detailed messages printed.', &
                allowed='error|warning|info|debug', example="'debug'"), &
            spec_v('units', 'string', '-', "'si'", &
                'System of units every number of the scene is in (see Units below). The ' // &
                'solver uses the numbers as given, so any consistent system works; this only ' // &
                'names the units shown by --check-input and stored with the results.', &
                allowed=unit_systems, example="'mm_tonne_s'"), &
            spec_v('progress_interval', 'real', 's', '5', &
                'Wall-clock seconds between two progress lines (rank 0: time, step, dt, Newton ' // &
                'iterations, energy-balance error, estimated time left); --quiet turns them off.', &
                lower=0.0_rk, lower_inclusive=.false., example='60'), &
            spec_v('restart_from', 'string', '-', "''", &
                'Continue the run stored in this result file from its checkpoint (the last ' // &
                'flush, DESIGN.md §7): the scene must build the same rods. The records up to the ' // &
                'checkpoint are kept and the run goes on to t_end as an uninterrupted run ' // &
                'would. The output path may be the restart file itself.', example="'out/run.h5'")]
    end function run_group

    function time_group() result(g)
        type(group_spec_t) :: g
        g%name = 'time'
        g%description = 'The time interval and the time-stepping scheme.'
        g%variables = [ &
            spec_v('t_end', 'real', 's', '(required)', 'End time; in quasistatic runs the final load factor.', &
                lower=0.0_rk, lower_inclusive=.false., required=.true., example='2.0'), &
            spec_v('dt', 'real', 's', '(required)', 'Time step (halved on Newton failure, see &solver).', &
                lower=0.0_rk, lower_inclusive=.false., required=.true., example='1e-3'), &
            spec_v('scheme', 'string', '-', "'midpoint'", 'Time integrator of the dynamics: ' // &
                '''midpoint'', the implicit midpoint rule of every formulation (its energy-' // &
                'consistent form where the formulation has one); ''generalized_alpha'', the ' // &
                'first-order generalized-alpha method of Jansen, Whiting and Hulbert (2000) that ' // &
                'seed 002 runs se3_pg with: second order, its high frequencies damped to rho_inf ' // &
                'per step (docs/theory/se3_pg.md, "Generalized-alpha"). generalized_alpha only ' // &
                'for se3_pg dynamics (docs/user/capabilities.md), with order 2, and not with ' // &
                'joints, plates, contact or obstacles.', allowed='midpoint|generalized_alpha', &
                example="'generalized_alpha'"), &
            spec_v('rho_inf', 'real', '-', '0.9', 'Spectral radius of the generalized-alpha ' // &
                'step at infinite frequency: 1 damps nothing (the midpoint rule), 0 damps the ' // &
                'highest frequencies in one step; alpha_m = (3 - rho_inf) / (2 (1 + rho_inf)), ' // &
                'alpha_f = 1 / (1 + rho_inf), gamma = 1/2 + alpha_m - alpha_f. Seed 002 uses 0.9.', &
                lower=0.0_rk, upper=1.0_rk, only_if='scheme=generalized_alpha', example='0.5'), &
            spec_v('order', 'integer', '-', '2', 'Order of the time integrator: 2, the midpoint ' // &
                'step; 4, each step of dt the composition of five midpoint steps of p dt, p dt, ' // &
                '(1 - 4p) dt, p dt, p dt with p = 1 / (4 - 4^(1/3)) (Suzuki''s composition: ' // &
                'symmetric, so order 4; every sub-step keeps its exact energy balance, momenta and ' // &
                'constraints, and all sub-steps stay inside the step; ' // &
                'docs/theory/time_integration.md). Not with what a negative sub-step cannot do: ' // &
                'Maxwell branches, friction, normal damping, quasistatics, relaxation, ' // &
                'se3_strand.', lower=2.0_rk, upper=4.0_rk, &
                example='4'), &
            spec_v('adaptive', 'logical', '-', '.false.', 'Error-controlled time steps (PETSc''s ' // &
                'TSAdapt on a divided-difference estimate of the local error; ' // &
                'docs/theory/time_integration.md): dt becomes the record interval; the steps ' // &
                'inside it keep the local error of the nodes'' positions within atol + rtol |x|, ' // &
                'and hit record times and load kinks exactly; a Newton failure cuts the step. ' // &
                'Every step is a midpoint (or order-4) step with its exact balances. Not with ' // &
                'contact, quasistatics, relaxation, se3_strand or generalized-alpha.', &
                example='.true.'), &
            spec_v('rtol', 'real', '-', '1e-6', 'Relative tolerance of the adaptive steps'' ' // &
                'local error, per state entry.', lower=0.0_rk, example='1e-5'), &
            spec_v('atol', 'real', 'state', '1e-9', 'Absolute tolerance of the adaptive steps'' ' // &
                'local error, per state entry (in the unit of each entry: m, m/s, N, ...).', &
                lower=0.0_rk, example='1e-8'), &
            spec_v('dt_min', 'real', 's', '1e-12 t_end', 'Smallest adaptive step; a step there ' // &
                'is accepted whatever its error.', lower=0.0_rk, lower_inclusive=.false., &
                example='1e-9'), &
            spec_v('dt_max', 'real', 's', 'dt', 'Largest adaptive step (at most dt, the record ' // &
                'interval).', lower=0.0_rk, lower_inclusive=.false., example='1e-2'), &
            spec_v('dt_initial', 'real', 's', 'dt / 100', 'First adaptive step (the error ' // &
                'estimate needs two accepted steps, four at order 4, before it controls: also ' // &
                'the step after each load kink).', lower=0.0_rk, lower_inclusive=.false., &
                example='1e-5'), &
            spec_v('quasistatic', 'logical', '-', '.false.', &
                'No inertia (mass terms dropped): time is a load factor (t_end usually 1). The ' // &
                'loads are stepped with midpoint steps between an equilibrium solve at t = 0 ' // &
                'and an endpoint (non-rate, e.g. Hellinger-Reissner) equilibrium solve at ' // &
                't_end, which gives the last record; both are continued from the state ' // &
                'before them (seed 000 §5, §6.3; methods/ph_director_3d.md §6.3; ' // &
                'Constraints, Maxwell branches, actuators, quasistatics above).', example='.true.'), &
            spec_v('equilibrium_solves', 'logical', '-', '.true.', &
                'Quasistatic runs only: .false. skips the equilibrium solves at t = 0 and t_end, ' // &
                'leaving the midpoint load path alone, as seed 001 computes its quasistatics ' // &
                '(the last record then depends on dt: the open rings of its Fig. 7 right, ' // &
                'methods/ph_planar.md §6.2). se3_pg solves an equilibrium at every step either way.', &
                example='.false.'), &
            spec_v('initial_equilibrium', 'logical', '-', '.false.', &
                'A dynamic run that starts at rest in static equilibrium: before the first ' // &
                'step the static problem with the loads and supports at t = 0 is solved, ' // &
                'continued from the initial placement as in quasistatics, and the dynamics ' // &
                'start from it with zero velocity (a rope hanging between two pins before one ' // &
                'is released: &bc release_time). Not with quasistatic or relaxation, nor with ' // &
                '&plate, &contact, &obstacle or joints between separate members; formulations: ' // &
                'docs/user/capabilities.md (docs/theory/prestretched_starts.md).', &
                example='.true.'), &
            spec_v('continuation', 'string', '-', "'none'", &
                'Quasistatic runs: ''arc_length'' traces the equilibrium path with the load ' // &
                'time as an unknown (Riks''s arc-length method), through limit points where ' // &
                'load steps stop (snap-through, post-buckling); the path ends when the load ' // &
                'time passes t_end or after path_steps steps, and records the load time of ' // &
                'each point (/rods/NAME/series/load_time). dt is not used. Formulations: ' // &
                'docs/user/capabilities.md (docs/theory/continuation.md).', &
                allowed='none|arc_length', &
                example="'arc_length'"), &
            spec_v('arc_length', 'real', '-', '0.05', 'First step of the continuation in its ' // &
                'scaled path length: ds^2 = mean over the nodes of |dr|^2 / L^2 + |dtheta|^2, ' // &
                'plus (d load time / t_end)^2; halved when Newton fails, then adapted to ' // &
                'about 4 Newton iterations per step.', lower=0.0_rk, lower_inclusive=.false., &
                only_if='continuation=arc_length', example='0.02'), &
            spec_v('arc_length_max', 'real', '-', '0.2', 'Longest step of the continuation ' // &
                '(scaled as arc_length).', lower=0.0_rk, lower_inclusive=.false., &
                only_if='continuation=arc_length', example='0.05'), &
            spec_v('path_steps', 'integer', '-', '200', 'Most steps of the continuation; ' // &
                'the records are its steps (/time holds the step number).', lower=1.0_rk, &
                only_if='continuation=arc_length', example='500'), &
            spec_v('branch_switch', 'logical', '-', '.false.', 'At the first bifurcation the ' // &
                'path crosses (the tangent stiffness singular with the load still rising, as ' // &
                'in a perfect column at its buckling load), leave the path for the branch ' // &
                'that bifurcates there, along its buckling mode; false: bifurcations are ' // &
                'logged and the path goes on (docs/theory/continuation.md, Bifurcations).', &
                only_if='continuation=arc_length', example='.true.'), &
            spec_v('relaxation', 'logical', '-', '.false.', &
                'Statics by damped dynamics (seed 004, methods/se3_strands.md §3.7): the ' // &
                'dynamics run with the rods'' damping, and the run stops as soon as the kinetic ' // &
                'energy of every system is below kinetic_energy_tol (t_end is then the latest ' // &
                'time; the last record is the relaxed state). Only for formulations with ' // &
                'relaxation in docs/user/capabilities.md (se3_strand); not with quasistatic.', &
                example='.true.'), &
            spec_v('kinetic_energy_tol', 'real', 'J', '1e-12', &
                'Relaxation: the kinetic energy of a system below which it counts as at rest ' // &
                '(the cantilever of methods/se3_strands.md §3.7: 1e-12 J); only used with ' // &
                'relaxation = .true.', lower=0.0_rk, lower_inclusive=.false., example='1e-10')]
    end function time_group

    function solver_group() result(g)
        type(group_spec_t) :: g
        g%name = 'solver'
        g%description = "Newton's stopping rule, step cut-backs and PETSc options (DESIGN.md §3)."
        g%variables = [ &
            spec_v('newton_atol', 'real', '-', '1e-10', &
                'Newton stops when the scaled residual norm of the method document is at most this.', &
                lower=0.0_rk, lower_inclusive=.false., example='1e-11'), &
            spec_v('newton_rtol', 'real', '-', '0', &
                'Relative decrease that also stops Newton (0: off, as the papers).', lower=0.0_rk, &
                upper=1.0_rk, example='1e-8'), &
            spec_v('max_newton', 'integer', '-', '25', 'Newton iterations per step before a cut-back.', &
                lower=1.0_rk, example='40'), &
            spec_v('max_cutbacks', 'integer', '-', '6', &
                'Halvings of one step before the run stops with its last good state written.', &
                lower=0.0_rk, example='3'), &
            spec_v('condense_stresses', 'logical', '-', '.false.', &
                'Eliminate element unknowns from the Newton system: for ph_director the element ' // &
                'stresses and velocities (methods/ph_director_3d.md §5.5): same solution, fewer ' // &
                'unknowns, but slower and with a higher round-off floor here ' // &
                '(docs/performance.md); for ph_planar the element strains, per element ' // &
                '(methods/ph_planar.md §3.5), leaving 3 unknowns per node.', example='.true.'), &
            spec_v('jacobian_reuse', 'real', '-', '0', &
                'Keep the factored Jacobian across Newton iterations and steps while each ' // &
                'iteration cuts the residual norm at least by this ratio (0: a new Jacobian ' // &
                'at every iteration, Newton''s method). Same solution and stopping test, ' // &
                'fewer factorizations (docs/performance.md); ignored by linear steps.', &
                lower=0.0_rk, upper=1.0_rk, upper_inclusive=.false., example='0.1'), &
            spec_v('petsc_options', 'string', '-', "''", &
                'PETSc options, applied after the scene values and before the command line.', &
                example="'-snes_monitor -snes_linesearch_type bt'")]
    end function solver_group

    function output_group() result(g)
        type(group_spec_t) :: g
        g%name = 'output'
        g%description = 'Where results go and how often (HDF5, DESIGN.md §7).'
        g%variables = [ &
            spec_v('path', 'string', '-', "'out/<scene>.h5'", 'Result file.', example="'out/run1.h5'"), &
            spec_v('stride', 'integer', '-', '1', 'Write every stride-th step.', lower=1.0_rk, example='10'), &
            spec_v('fields', 'string', '-', "'all'", 'Comma-separated fields to write, or all.', &
                example="'position,energy'"), &
            spec_v('flush_every', 'integer', '-', '10', 'Flush the file every this many steps.', &
                lower=1.0_rk, example='50'), &
            spec_v('xdmf', 'logical', '-', '.true.', 'Write an XDMF sidecar for ParaView.', &
                example='.false.')]
    end function output_group

    function rod_group() result(g)
        type(group_spec_t) :: g
        g%name = 'rod'
        g%repeatable = .true.
        g%description = 'One rod: geometry, cross-section, material, discretization and initial velocity.'
        g%variables = [ &
            spec_v('name', 'string', '-', "'rod<i>'", 'Name used by &bc and &load and in the output.', &
                example="'beam'"), &
            spec_v('formulation', 'string', '-', 'formulation_default', 'Formulation of this rod.', &
                allowed=formulation_choices(), example="'" // default_formulation() // "'"), &
            spec_v('n_elements', 'integer', '-', '(required)', 'Number of elements.', lower=1.0_rk, &
                required=.true., example='16'), &
            spec_v('degree', 'integer', '-', '2', 'Polynomial degree of the elements (ph_director; the ' // &
                'planar elements are linear, two-node, whatever the degree).', lower=1.0_rk, &
                upper=2.0_rk, example='1'), &
            spec_v('n_gauss', 'integer', '-', '2 (cl_em_planar: 1)', &
                'Gauss points per element. The planar formulations take 1 or 2; for cl_em_planar ' // &
                'this is the quadrature of the axial and shear terms (methods/ph_planar.md §5.1): ' // &
                '1 = reduced, free of shear locking (its default); 2 = full, which locks in ' // &
                'bending (the roll-up); bending is exact with either.', lower=1.0_rk, upper=5.0_rk, &
                example='3'), &
            spec_v('em_variant', 'string', '-', "'stander_stein'", &
                'cl_em_planar only (an error for any other formulation): ''stander_stein'' is the ' // &
                'classical energy-momentum scheme of Stander and Stein (methods/ph_planar.md ' // &
                '§5.1), ''ph_irreducible'' the displacement-based port-Hamiltonian scheme with ' // &
                'strain history (§5.2), for comparison.', allowed='stander_stein|ph_irreducible', &
                example="'ph_irreducible'"), &
            spec_v('geometry', 'string', '-', "'straight'", &
                "Shape of the reference centreline (stress-free unless prestressed): 'straight' " // &
                "(start, direction, length), 'helix' (start, direction = its axis, helix_radius, " // &
                "helix_pitch, helix_turns), 'polyline' (points) or 'curvature' (start, direction " // &
                '= d3 at s = 0, d1, and rest_curvature with length, or rest_curvature_table: a ' // &
                'rest curvature and pre-twist as functions of s). The nodes are placed at equal ' // &
                'arc length along it.', allowed='straight|helix|polyline|curvature', &
                example="'helix'"), &
            spec_v('start', 'real', 'm', '0, 0, 0', &
                'Position of the end s = 0. Polyline: derived, the first point (a given value must ' // &
                'equal it).', count=3, example='0, 0, 1'), &
            spec_v('direction', 'real', '-', '1, 0, 0', &
                'Straight: the direction of the centreline; helix: the direction of its axis; ' // &
                'curvature: the tangent d3 at s = 0 (normalized). Polyline: derived, the ' // &
                'direction of the first segment (a given value must be parallel to it).', &
                count=3, example='0, 0, 1'), &
            spec_v('d1', 'real', '-', '(derived)', &
                'First cross-section director at s = 0, made orthonormal to the tangent t(0) there ' // &
                '(must not be parallel to it); default: e_z x t(0) normalized, or e_x when t(0) is ' // &
                'along e_z. Along a helix or polyline d1 is carried by parallel transport (no ' // &
                'twist about d3 = the tangent), along a curvature rod by its rest curvature; ' // &
                'd2 = d3 x d1.', count=3, example='0, 1, 0'), &
            spec_v('length', 'real', 'm', '(straight: required)', &
                'Length of a straight rod or of a constant rest_curvature (required there). ' // &
                'Derived for a helix, helix_turns sqrt((2 pi helix_radius)^2 + helix_pitch^2), ' // &
                'for a polyline, the sum of its segments, and for a rest_curvature_table, its ' // &
                'last s; a given value must then agree to 1e-9 relative.', lower=0.0_rk, &
                lower_inclusive=.false., &
                required_if='geometry=straight', example='2.5'), &
            spec_v('helix_radius', 'real', 'm', '(helix: required)', &
                'Radius of the helix. The centreline starts at start; the axis is the line through ' // &
                'start - helix_radius u along direction, with u = cos(helix_phase) n + ' // &
                'sin(helix_phase) (direction x n) and n = e_z x direction normalized (e_x when ' // &
                'direction is along e_z).', lower=0.0_rk, lower_inclusive=.false., &
                required_if='geometry=helix', only_if='geometry=helix', example='0.05'), &
            spec_v('helix_pitch', 'real', 'm', '(helix: required)', &
                'Rise of the helix along its axis per turn: > 0 winds right-handed about ' // &
                'direction, < 0 left-handed, 0 gives a plane circle.', &
                required_if='geometry=helix', only_if='geometry=helix', example='0.02'), &
            spec_v('helix_turns', 'real', '-', '(helix: required)', 'Number of turns (need not be whole).', &
                lower=0.0_rk, lower_inclusive=.false., required_if='geometry=helix', &
                only_if='geometry=helix', example='3.5'), &
            spec_v('helix_phase', 'real', 'rad', '0', &
                'Helix only: the angle phi of the start point about the axis, from n ' // &
                '(helix_radius): ' // &
                'u = cos(phi) n + sin(phi) (direction x n), so the axis passes through start - ' // &
                'helix_radius u. Wires of a strand share one axis when wire k starts at that ' // &
                'axis point + helix_radius u_k with its own phase: phases 0, pi/3, ..., 5 pi/3 ' // &
                'lay six wires around a core.', only_if='geometry=helix', &
                example='1.0471975511965976'), &
            spec_v('points', 'real', 'm', '(polyline: required)', &
                'Vertices of a polyline centreline, x1, y1, z1, x2, y2, z2, ... (2 to ' // &
                str(max_polyline_points) // ' points): consecutive points distinct, no segment ' // &
                'reversing the one before. At a vertex the tangent is the bisector of the two ' // &
                'segments.', count=6, max_count=3 * max_polyline_points, &
                required_if='geometry=polyline', only_if='geometry=polyline', &
                example='0, 0, 0, 1, 0, 0, 1, 1, 0'), &
            spec_v('rest_curvature', 'real', '1/m', '(curvature: this or the table)', &
                'Constant Darboux vector kappa = (kappa1, kappa2, kappa3) of the stress-free ' // &
                'shape in the cross-section frame: kappa1, kappa2 bend about d1, d2, kappa3 ' // &
                'twists about d3 (the pre-twist, rad/m). The frame R = (d1, d2, d3) and ' // &
                'centreline solve R'' = R hat(kappa), phi'' = d3 (docs/theory/rest_curvature.md); ' // &
                'a constant kappa gives a helix of radius kb / |kappa|^2 and pitch 2 pi ' // &
                'kappa3 / |kappa|^2 about R(0) kappa, kb = (kappa1^2 + kappa2^2)^(1/2).', &
                count=3, only_if='geometry=curvature', example='0, 2.0, 0.5'), &
            spec_v('rest_curvature_table', 'real', 'm, 1/m', '(curvature: this or the constant)', &
                'kappa(s) as rows s, kappa1, kappa2, kappa3 (2 to ' // str(max_curvature_rows) // &
                ' rows), linear in s between rows: s from 0, non-decreasing (two rows at one s ' // &
                'make a jump), the last s is the length. Integrated to ~1e-14 relative by ' // &
                'sixth-order Magnus steps (exact where kappa is constant).', count=8, &
                max_count=4 * max_curvature_rows, only_if='geometry=curvature', &
                example='0, 0, 0, 6.28, 1, 0, 0, 6.28'), &
            spec_v('velocity', 'real', 'm/s', '0, 0, 0', &
                'Initial velocity of translation: the centreline starts with v(s) = velocity + ' // &
                'angular_velocity x (phi(s) - rotation_center). A clamped end starts at rest, so ' // &
                'a rod with a clamped end takes no initial velocity.', count=3, example='0, 0, 1.5'), &
            spec_v('angular_velocity', 'real', 'rad/s', '0, 0, 0', &
                'Initial angular velocity of a rigid rotation about rotation_center: the ' // &
                'directors start with rates angular_velocity x d_i.', count=3, example='0, 0, 6.28'), &
            spec_v('rotation_center', 'real', 'm', 'start', 'Point the initial rotation turns about.', &
                count=3, example='0, 0, 0.5'), &
            spec_v('section', 'string', '-', "'none'", &
                "Cross-section shape; 'none': stiffnesses and inertias are given directly.", &
                allowed='none|circle|rectangle|tube', example="'circle'"), &
            spec_v('radius', 'real', 'm', '-', 'Radius of a circle, outer radius of a tube.', &
                lower=0.0_rk, lower_inclusive=.false., example='0.01'), &
            spec_v('contact_radius', 'real', 'm', 'circle, tube: radius', &
                'Radius of the rod''s surface in contact (&contact, &obstacle): two rods touch ' // &
                'when their centrelines come within the sum of their contact radii. Default: ' // &
                'the radius of a ''circle'' or ''tube'' section; required with &contact or ' // &
                '&obstacle for other sections; used only with them (an error without).', &
                lower=0.0_rk, &
                lower_inclusive=.false., example='0.001'), &
            spec_v('inner_radius', 'real', 'm', '-', 'Inner radius of a tube.', lower=0.0_rk, &
                example='0.008'), &
            spec_v('width', 'real', 'm', '-', 'Rectangle side along d1.', lower=0.0_rk, &
                lower_inclusive=.false., example='0.02'), &
            spec_v('height', 'real', 'm', '-', 'Rectangle side along d2.', lower=0.0_rk, &
                lower_inclusive=.false., example='0.005'), &
            spec_v('E', 'real', 'Pa', '-', "Young's modulus.", lower=0.0_rk, lower_inclusive=.false., &
                example='2.1e11'), &
            spec_v('G', 'real', 'Pa', 'E/(2(1+nu))', 'Shear modulus.', lower=0.0_rk, lower_inclusive=.false., &
                example='8.1e10'), &
            spec_v('nu', 'real', '-', '-', "Poisson's ratio (used when G is not given).", lower=-1.0_rk, &
                lower_inclusive=.false., upper=0.5_rk, example='0.3'), &
            spec_v('density', 'real', 'kg/m^3', '-', 'Mass density.', lower=0.0_rk, lower_inclusive=.false., &
                example='7800'), &
            spec_v('EA', 'real', 'N', '(section)', 'Axial stiffness.', lower=0.0_rk, lower_inclusive=.false., &
                example='1e4'), &
            spec_v('GA1', 'real', 'N', '(section)', 'Shear stiffness along d1.', lower=0.0_rk, &
                lower_inclusive=.false., example='1e4'), &
            spec_v('GA2', 'real', 'N', '(section)', 'Shear stiffness along d2.', lower=0.0_rk, &
                lower_inclusive=.false., example='1e4'), &
            spec_v('EI1', 'real', 'N m^2', '(section)', 'Bending stiffness about d1.', lower=0.0_rk, &
                lower_inclusive=.false., example='1e3'), &
            spec_v('EI2', 'real', 'N m^2', '(section)', 'Bending stiffness about d2.', lower=0.0_rk, &
                lower_inclusive=.false., example='1e3'), &
            spec_v('GJ', 'real', 'N m^2', '(section)', 'Torsional stiffness.', lower=0.0_rk, &
                lower_inclusive=.false., example='1e3'), &
            spec_v('rhoA', 'real', 'kg/m', '(section)', 'Mass per unit length.', lower=0.0_rk, &
                example='1.0'), &
            spec_v('rhoI1', 'real', 'kg m', '(section)', 'Rotational inertia per length about d1.', &
                lower=0.0_rk, example='10.0'), &
            spec_v('rhoI2', 'real', 'kg m', '(section)', 'Rotational inertia per length about d2.', &
                lower=0.0_rk, example='10.0'), &
            spec_v('shear_factor', 'real', '-', '1 (section)', &
                'Shear correction factor k in GA = k G A of a section (not with section = ''none'').', &
                lower=0.0_rk, lower_inclusive=.false., example='0.8333333333333334'), &
            spec_v('torsion_constant', 'string', '-', "'polar' (circle, tube)", &
                'Torsion constant of a section: polar moment or Saint-Venant; required for a ' // &
                'rectangle (not with section = ''none'').', &
                allowed='polar|saint_venant', example="'saint_venant'"), &
            spec_v('prestressed', 'logical', '-', '.false.', &
                'False: the initial geometry is stress-free (DESIGN.md §1): the reference strains ' // &
                'are the discrete strains of the initial geometry at the Gauss points, so the rod ' // &
                'starts with zero stress. True: the stress-free shape is straight (reference ' // &
                'strains Gamma_0 = (0, 0, 1), K_0 = 0 everywhere), so a curved initial geometry ' // &
                'starts prestressed, with the elastic stresses of its strains (the projection of ' // &
                'methods/ph_director_3d.md §5.4); the stresses of constrained components and of ' // &
                'Maxwell branches start at zero. Same as false for a straight rod.', example='.true.'), &
            spec_v('prestrain', 'real', '-', '0', &
                'Axial prestrain eps of the given geometry: the stress-free rod is the geometry ' // &
                'shortened along its arc length by 1/(1 + eps), same shape, so the rod starts ' // &
                'with the axial force EA eps and no bending stress (a stretched rope: eps > 0; ' // &
                'compressed: eps < 0). EA ... GJ, rhoA, rhoI1, rhoI2 and density are those of ' // &
                'the stress-free rod (its mass is that of the stress-free length); loads per ' // &
                'length and drags are per unit given length. Not with an inextensible or ' // &
                'EA-rigid rod (docs/theory/prestretched_starts.md).', lower=-1.0_rk, &
                lower_inclusive=.false., example='0.001'), &
            spec_v('constraint', 'string', '-', "'none'", &
                "Kinematic constraint: 'kirchhoff' = shear-rigid, 'inextensible' = shear-rigid " // &
                'and inextensible (seed 000 §2.3, §5; methods/ph_director_3d.md §2.3). The ' // &
                'constrained stress components become Lagrange multipliers; the stiffnesses of ' // &
                "the constrained components (GA1, GA2, and EA for 'inextensible') are ignored, " // &
                'so they may be given or derived from a section.', &
                allowed='none|kirchhoff|inextensible', example="'kirchhoff'"), &
            spec_v('rigid', 'string', '-', '(none)', &
                'Stiffnesses made infinite besides those of constraint, 1 to 6 names (e.g. ' // &
                "'EA' for an inextensible but shearable rod, 'GJ' torsion-rigid): zero " // &
                'compliance, the stress component a Lagrange multiplier (methods/ph_director_3d.md ' // &
                '§2.3); the stiffness given is ignored. ph_director only.', count=1, max_count=6, &
                allowed='EA|GA1|GA2|EI1|EI2|GJ', example="'EA', 'GJ'"), &
            spec_v('maxwell_fraction', 'real', '-', '-', &
                'Generalized Maxwell viscoelasticity (seed 000 §5.1, methods/ph_director_3d.md ' // &
                '§3.1): the fraction of every stiffness taken by branch i = 1..m; the branches ' // &
                'are the leading entries (no gaps) and the purely elastic branch keeps ' // &
                '1 - sum > 0.', count=1, max_count=max_branches, lower=0.0_rk, &
                lower_inclusive=.false., upper=1.0_rk, upper_inclusive=.false., example='0.2, 0.1'), &
            spec_v('maxwell_tau_E', 'real', 's', '-', &
                'Relaxation time of the dilatation and bending components of each Maxwell branch; ' // &
                'exactly one per maxwell_fraction.', count=1, max_count=max_branches, lower=0.0_rk, &
                lower_inclusive=.false., example='0.05, 1.0'), &
            spec_v('maxwell_tau_G', 'real', 's', 'maxwell_tau_E', &
                'Relaxation time of the shear and torsion components of each Maxwell branch; a ' // &
                'branch without one takes its maxwell_tau_E.', count=1, max_count=max_branches, &
                lower=0.0_rk, lower_inclusive=.false., example='0.1, 2.0'), &
            spec_v('external_damping', 'real', 'N s/m^2, N s', '0', &
                'se3_strand only (an error for any other formulation): external drag of seed 004 ' // &
                'eq. 7, D_ex = external_damping I6 acting as the body force -D_ex V on the six ' // &
                'body velocity components (the paper''s convention: one scalar times the ' // &
                'identity, so it is in N s/m^2 on the three force rows and N s on the three ' // &
                'moment rows). Always dissipative (methods/se3_strands.md §2.6).', lower=0.0_rk, &
                example='0.1'), &
            spec_v('internal_damping', 'real', 'N s/m, N s m', '0', &
                'se3_strand only (an error for any other formulation): internal dissipation of ' // &
                'seed 004 eq. 7, D_in = internal_damping I6 acting as the body force -D_in dU/dt ' // &
                '(U the six strains; one scalar times the identity: N s/m on the force rows, ' // &
                'N s m on the moment rows). As the paper writes it, a body force and not a ' // &
                'viscous stress, it is not guaranteed to dissipate (methods/se3_strands.md ' // &
                '§2.6); kelvin_voigt_time is the safe alternative.', lower=0.0_rk, example='1e-4'), &
            spec_v('kelvin_voigt_time', 'real', 's', '0', &
                'Kelvin-Voigt viscosity: the viscous stress tau_i k_i d(strain_i)/dt added to ' // &
                'each elastic stress component, k_i the stiffnesses. One value for all six ' // &
                'components or six in the order EA, GA1, GA2, EI1, EI2, GJ (the planar ' // &
                'formulations read EA, their shear and their bending entry). It dissipates ' // &
                'in every step and enters the energy balance (docs/theory/damping.md).', &
                count=1, max_count=6, lower=0.0_rk, example='1e-3'), &
            spec_v('drag', 'real', 'N s/m^2', '0', &
                'External drag: the force -drag v per length against the centreline velocity v ' // &
                '(a rod moving through a viscous medium; docs/theory/damping.md).', &
                lower=0.0_rk, example='0.5'), &
            spec_v('angular_drag', 'real', 'N s', '0', &
                'External angular drag: the moment -angular_drag w per length against the ' // &
                'angular velocity w of the sections (docs/theory/damping.md).', lower=0.0_rk, &
                example='1e-4'), &
            spec_v('free_end', 'string', '-', "'balanced'", &
                'se3_strand only (an error for any other formulation): the free end''s half ' // &
                'cell. ''balanced'' takes the ad^T term of its one segment in full, so an end ' // &
                'load enters with exactly its power; ''paper'' is seed 004''s average with the ' // &
                'ghost segment, an end moment of about h |f| / 2 that converges away as h^2 ' // &
                '(the paper''s Fig. 3 tip error) but can create energy and blow up under large ' // &
                'end loads (docs/theory/se3_strand.md, "The free end").', &
                allowed='balanced|paper', example="'paper'")]
    end function rod_group

    !> &segment (issue 26 item 5): a part of a rod with its own section and material. Its
    !> section, material, stiffness and inertia variables are &rod's, taken from rod_group so
    !> the two cannot drift; each defaults to the rod's value.
    function segment_group() result(g)
        type(group_spec_t) :: g
        type(group_spec_t) :: rod
        character(len=16), parameter :: taken(20) = [character(len=16) :: 'section', 'radius', &
            'inner_radius', 'width', 'height', 'E', 'G', 'nu', 'density', 'EA', 'GA1', 'GA2', &
            'EI1', 'EI2', 'GJ', 'rhoA', 'rhoI1', 'rhoI2', 'shear_factor', 'torsion_constant']
        integer :: k
        g%name = 'segment'
        g%repeatable = .true.
        g%description = 'A part of a rod with its own section, material, stiffnesses and ' // &
            'inertias, from the previous segment''s s_end (0 for the first) to its s_end; the ' // &
            'rest of the rod keeps the &rod values (docs/user/input.md, "Rods that vary along ' // &
            'their length").'
        rod = rod_group()
        allocate(g%variables(6 + size(taken)))
        g%variables(1) = spec_v('rod', 'string', '-', '(required)', 'Name of the rod (&rod name).', &
            required=.true., example="'beam'")
        g%variables(2) = spec_v('s_end', 'real', 'm', '(required)', &
            'Arc length at which the segment ends, after the previous segment''s s_end of the ' // &
            'same rod and at most its length; a node of the rod''s uniform mesh (a multiple ' // &
            'of length / n_elements to 1e-9 relative), so that every element lies in one segment.', &
            lower=0.0_rk, lower_inclusive=.false., required=.true., example='0.5')
        do k = 1, size(taken)
            g%variables(2 + k) = rod%variables(find_variable(rod, trim(taken(k))))
            g%variables(2 + k)%default_text = '(the rod''s)'
            g%variables(2 + k)%required_if = ''
            g%variables(2 + k)%only_if = ''
        end do
        g%variables(3 + size(taken)) = taper_variable('radius_end', 'Radius of a circle, ' // &
            'outer radius of a tube')
        g%variables(4 + size(taken)) = taper_variable('inner_radius_end', 'Inner radius of a tube')
        g%variables(5 + size(taken)) = taper_variable('width_end', 'Rectangle side along d1')
        g%variables(6 + size(taken)) = taper_variable('height_end', 'Rectangle side along d2')
    contains
        !> A dimension of a linearly tapered segment at its end s_end.
        function taper_variable(name, what) result(v)
            character(len=*), intent(in) :: name, what
            type(variable_spec_t) :: v
            v = spec_v(name, 'real', 'm', '(no taper)', what // ' at s_end: the segment ' // &
                'tapers linearly from its start''s value (its own or the rod''s) to this one, ' // &
                'its stiffnesses and inertias following the section formulas along s, ' // &
                'evaluated at each element''s midpoint (docs/user/input.md, "Tapered ' // &
                'segments"). Directly given EA ... rhoI2 stay constant.', lower=0.0_rk, &
                lower_inclusive=.false., example='0.005')
        end function taper_variable
    end function segment_group

    function bc_group() result(g)
        type(group_spec_t) :: g
        g%name = 'bc'
        g%repeatable = .true.
        g%description = 'The support at one end of a rod; ends without &bc are free.'
        g%variables = [ &
            spec_v('rod', 'string', '-', '(required)', 'Name of the rod.', required=.true., example="'beam'"), &
            spec_v('end', 'string', '-', '(required)', 'Which end.', allowed='start|end', required=.true., &
                example="'start'"), &
            spec_v('kind', 'string', '-', '(required)', &
                "Kind of support: 'clamped' fixes the end's position and rotation, 'pinned' " // &
                'its position only (a ground pin), ''free'' neither, ''driven'' is a clamp ' // &
                'moved by displacement and rotation (se3_pg, ph_director) or by velocity and ' // &
                'angular_velocity (se3_strand; several driven &bc on one end add up), ''body'' ' // &
                'a free end carrying a rigid body (mass, centre, inertia), ''sliding'' a ' // &
                'prismatic support (see axis), ''held'' an end held in chosen directions (see ' // &
                'hold); which kinds a formulation has, at which end, and how it drives an end: ' // &
                'docs/user/capabilities.md.', &
                allowed='clamped|pinned|free|driven|body|sliding|held', required=.true., &
                example="'clamped'"), &
            spec_v('hold', 'string', '-', '(held: required)', 'A held end (kind = ''held''): ' // &
                '1 to 4 names of what is held at the end''s reference: ''x'', ''y'', ''z'' ' // &
                '(inertial position coordinates), ''rotation'' (the whole rotation) or ' // &
                '''twist'' (the rotation about the axis alone; se3_pg, a rod along x). ' // &
                '''x'', ''y'', ''z'' is pinned, with ''rotation'' clamped, with ''twist'' a ' // &
                'ball joint that does not turn about the axis (Greenhill''s shaft, ' // &
                'docs/theory/modes.md); ''y'', ''z'', ''rotation'' slides along x; ''z'' is a ' // &
                'roller on z = z_0. Planar formulations hold the planar coordinates the held ' // &
                'directions fix (none for the plane''s normal; docs/user/capabilities.md).', &
                count=1, &
                max_count=4, allowed=hold_entry_names, required_if='kind=held', &
                only_if='kind=held', example="'z'"), &
            spec_v('axis', 'real', '-', '(sliding: required)', 'A sliding end (kind = ' // &
                '''sliding'', a prismatic support): the direction, in inertial components, along ' // &
                'which the end''s position is free; across it the position is held and the ' // &
                'end''s rotation is held (a rod end in a linear guide; with a dead axial force, ' // &
                'the set-up of a twisted rod buckling into a helix). Formulations that hold ' // &
                'coordinates need a coordinate axis (docs/user/capabilities.md).', count=3, &
                required_if='kind=sliding', only_if='kind=sliding', example='1, 0, 0'), &
            spec_v('release_time', 'real', 's', '(never)', 'A clamped or pinned end held ' // &
                'until this time and free afterwards (a rope released from a pin): steps ' // &
                'whose midpoint is before it hold the end, later ones do not (on the time ' // &
                'grid, the first step that starts there is free; adaptive steps end there); ' // &
                'the initial equilibrium (&time initial_equilibrium) holds it. The end''s ' // &
                'unknowns are in the system throughout, their equations held ones until the ' // &
                'release (docs/theory/prestretched_starts.md).', lower=0.0_rk, &
                example='0.5'), &
            spec_v('displacement', 'real', 'm', '0, 0, 0', 'Driven end of a formulation that ' // &
                'drives the pose (se3_pg, ph_director): its displacement at f(t) = 1 ' // &
                '(inertial components); the end is at its reference position plus f(t) ' // &
                'displacement.', count=3, &
                example='0, 0, 0.1'), &
            spec_v('rotation', 'real', 'rad', '0, 0, 0', 'Driven end of a formulation that ' // &
                'drives the pose (se3_pg, ph_director): its rotation vector at f(t) = 1 ' // &
                '(inertial components, about the end''s reference position); the end''s frame is ' // &
                'Exp(f(t) rotation) times its reference frame.', count=3, &
                example='62.8318530718, 0, 0'), &
            spec_v('velocity', 'real', 'm/s', '0, 0, 0', 'Driven end of a formulation that ' // &
                'drives the velocity (se3_strand, methods/se3_strands.md §3.4): the end section ' // &
                'moves with velocity f(t) velocity (inertial components); it starts at its ' // &
                'reference position.', count=3, example='0, 0, 0.5655'), &
            spec_v('angular_velocity', 'real', 'rad/s', '0, 0, 0', 'Driven end of a ' // &
                'formulation that drives the velocity (se3_strand): the end section turns with ' // &
                'angular velocity f(t) angular_velocity (inertial components) about the end''s ' // &
                'own (moving) position.', count=3, example='0, 0, 6.2831853072'), &
            spec_v('mass', 'real', 'kg', '(body: required)', 'Mass of the rigid body on the ' // &
                'end (kind = ''body''), rigidly attached to the end''s cross-section: its ' // &
                'kinetic energy and momenta are the rod''s, gravity acts on it.', lower=0.0_rk, &
                lower_inclusive=.false., required_if='kind=body', only_if='kind=body', &
                example='0.5'), &
            spec_v('centre', 'real', 'm', '0, 0, 0', 'The body''s centre of mass relative to ' // &
                'the end''s centreline point, inertial components in the reference ' // &
                'configuration (it moves with the end''s cross-section).', count=3, &
                only_if='kind=body', example='0, 0, 0.02'), &
            spec_v('inertia', 'real', 'kg m^2', '0, 0, 0', 'The body''s moments of inertia ' // &
                'about its centre of mass, (I_xx, I_yy, I_zz) in inertial components in the ' // &
                'reference configuration (0: a point mass).', count=3, lower=0.0_rk, &
                only_if='kind=body', example='1e-4, 1e-4, 2e-4'), &
            spec_v('inertia_products', 'real', 'kg m^2', '0, 0, 0', 'The products of inertia ' // &
                '(I_yz, I_xz, I_xy) of the same tensor (entries of the tensor, not their ' // &
                'negatives); the tensor must be positive semidefinite and satisfy the ' // &
                'triangle inequalities of a body.', count=3, only_if='kind=body', &
                example='0, 0, 0'), &
            time_function_variables('motion of a driven end')]
    end function bc_group

    function load_group() result(g)
        type(group_spec_t) :: g
        g%name = 'load'
        g%repeatable = .true.
        g%description = 'An end load, a distributed load or gravity, scaled by a time function.'
        g%variables = [ &
            spec_v('rod', 'string', '-', "'' (all rods, gravity only)", 'Name of the loaded rod.', &
                example="'beam'"), &
            spec_v('where', 'string', '-', '(required)', 'Point of application.', &
                allowed='start|end|distributed|gravity', required=.true., example="'end'"), &
            spec_v('force', 'real', 'N or N/m', '0, 0, 0', 'Force (per length when distributed).', count=3, &
                example='0, 0, -100'), &
            spec_v('moment', 'real', 'N m or N', '0, 0, 0', 'Moment (per length when distributed).', count=3, &
                example='0, 200, 100'), &
            spec_v('acceleration', 'real', 'm/s^2', '0, 0, 0', 'Gravitational acceleration (where = gravity).', &
                count=3, example='0, 0, -9.81'), &
            spec_v('frame', 'string', '-', "'spatial'", 'Dead (spatial) or follower load.', &
                allowed='spatial|follower', example="'spatial'"), &
            time_function_variables('load')]
    end function load_group

    function actuator_group() result(g)
        type(group_spec_t) :: g
        g%name = 'actuator'
        g%repeatable = .true.
        g%description = 'A pneumatic chamber or a tendon along a whole rod (seed 000 §5.2, ' // &
            'methods/ph_director_3d.md §3.2): a force of magnitude tau(t) along its line of ' // &
            'action, added to the stress resultants of the momentum equations.'
        g%variables = [ &
            spec_v('rod', 'string', '-', '(required)', 'Name of the actuated rod.', required=.true., &
                example="'arm'"), &
            spec_v('kind', 'string', '-', '(required)', &
                "'pneumatic': a chamber, line of action d3 (normal to the section), tau(t) = " // &
                "-pressure area f(t). 'tendon': a cable, line of action the tangent of its own line " // &
                'r = phi + rho^1 d1 + rho^2 d2, tau(t) = tension f(t). f is the time function.', &
                allowed='pneumatic|tendon', required=.true., example="'tendon'"), &
            spec_v('offset', 'real', 'm', '(required)', &
                'Material coordinates (rho^1, rho^2) of the chamber centroid or tendon line in the ' // &
                '(d1, d2) director basis; must lie inside a circle or tube section.', count=2, &
                required=.true., example='0, -0.01'), &
            spec_v('area', 'real', 'm^2', '(pneumatic)', &
                'Cross-section area of the chamber; required for a pneumatic chamber, an error for ' // &
                'a tendon.', lower=0.0_rk, lower_inclusive=.false., example='1e-4'), &
            spec_v('pressure', 'real', 'Pa', '(pneumatic)', &
                'Gauge pressure of the chamber; required for a pneumatic chamber, an error for a ' // &
                'tendon. Positive pressure pushes the end caps apart: tau < 0 elongates the rod.', &
                example='5e5'), &
            spec_v('tension', 'real', 'N', '(tendon)', &
                'Tension of the tendon (a tendon only pulls); required for a tendon, an error for ' // &
                'a pneumatic chamber.', lower=0.0_rk, example='20'), &
            time_function_variables('actuator force')]
    end function actuator_group

    function joint_group() result(g)
        type(group_spec_t) :: g
        g%name = 'joint'
        g%repeatable = .true.
        g%description = 'Two rod ends tied together at a point where both ends lie in the ' // &
            'reference geometry (to 1e-9 of the longer rod). Planar formulations share the ' // &
            'nodal unknowns of the two ends; ph_director ties them by constraints with ' // &
            'multipliers. The rods of a chain of joints form one system with one formulation; ' // &
            'a joint that ties ends already tied (directly or through other joints) is ' // &
            'redundant and an error.'
        g%variables = [ &
            spec_v('rod_a', 'string', '-', '(required)', 'Name of the first rod.', required=.true., &
                example="'crank'"), &
            spec_v('end_a', 'string', '-', '(required)', 'Its end at the joint.', allowed='start|end', &
                required=.true., example="'end'"), &
            spec_v('rod_b', 'string', '-', '(required)', 'Name of the second rod.', required=.true., &
                example="'coupler'"), &
            spec_v('end_b', 'string', '-', '(required)', 'Its end at the joint.', allowed='start|end', &
                required=.true., example="'start'"), &
            spec_v('kind', 'string', '-', '(required)', &
                "'rigid': the position and orientation of the two end sections tied. " // &
                "'spherical': the position tied, any relative rotation (a ball joint; 3D only). " // &
                "'revolute': the position tied, relative rotation only about axis (a hinge); " // &
                'in a planar formulation a pin about the plane normal (a shared nodal (x, y), ' // &
                'each rod its own theta). Which kinds a formulation has: ' // &
                'docs/user/capabilities.md. 3D formulations (ph_director, se3_pg): a jointed ' // &
                'end carries no &bc (a clamped or driven end cannot also be jointed) and is ' // &
                'on no &plate; the joined rods run on one formulation.', &
                allowed='revolute|rigid|spherical', required=.true., example="'revolute'"), &
            spec_v('axis', 'real', '-', '(3D revolute: required)', &
                'Revolute joints of 3D formulations (ph_director, se3_pg): the hinge axis in the ' // &
                'reference configuration (inertial components, normalized; not the zero ' // &
                'vector; components not given are 0). It stays fixed in both end sections, ' // &
                'which turn relative to each other about it only. Planar formulations turn ' // &
                'about the plane normal and refuse an axis; rigid and spherical joints take none.', &
                count=3, example='0, 0, 1')]
    end function joint_group

    function plate_group() result(g)
        type(group_spec_t) :: g
        g%name = 'plate'
        g%repeatable = .true.
        g%description = 'A rigid end plate to which rod ends are tied (ph_director, se3_pg): each ' // &
            'listed end keeps its reference position and orientation relative to the plate. ' // &
            'The plate is fixed, or driven: moved by f(t) displacement and turned by the ' // &
            'rotation vector f(t) rotation about centre (f the time function); or, with a mass, ' // &
            'it floats: a rigid body moved by the rods tied to it (ph_director). The rods of a ' // &
            'plate form one system. A tied end carries no &bc and is in no &joint and on no ' // &
            'other &plate.'
        g%variables = [ &
            spec_v('name', 'string', '-', '(required)', 'Name of the plate (unique among the ' // &
                'plates), used in the plan and the output.', required=.true., example="'top'"), &
            spec_v('rods', 'string', '-', '(required)', 'The rods tied to the plate, 1 to ' // &
                str(max_plate_rods) // ' names, each at most once (e.g. every wire of a strand); ' // &
                'all on one formulation with end plates (docs/user/capabilities.md).', count=1, &
                max_count=max_plate_rods, required=.true., &
                example="'core', 'wire1', 'wire2'"), &
            spec_v('end', 'string', '-', '(required)', 'The end of every listed rod that is ' // &
                'tied to the plate (the same for all).', allowed='start|end', required=.true., &
                example="'end'"), &
            spec_v('centre', 'real', 'm', 'mean of the tied ends', 'Centre of the plate''s ' // &
                'rotation (inertial components), and a floating plate''s centre of mass; ' // &
                'default: the mean reference position of its tied ends.', count=3, &
                example='0, 0, 1'), &
            spec_v('mass', 'real', 'kg', '0', 'Mass of a floating plate: with a mass the plate ' // &
                'is a rigid body moved by the rods tied to it (its kinetic energy, momenta and ' // &
                'weight in the books of its first rod; ph_director; docs/theory/ph_director.md, ' // &
                '"Rigid bodies on ends"), not fixed or driven (no displacement, no rotation). ' // &
                '0: a fixed or driven plate.', lower=0.0_rk, example='0.2'), &
            spec_v('inertia', 'real', 'kg m^2', '0, 0, 0', 'A floating plate''s moments of ' // &
                'inertia about its centre of mass, (I_xx, I_yy, I_zz) in inertial components in ' // &
                'the reference configuration.', count=3, lower=0.0_rk, example='1e-4, 1e-4, 2e-4'), &
            spec_v('inertia_products', 'real', 'kg m^2', '0, 0, 0', 'A floating plate''s ' // &
                'products of inertia (I_yz, I_xz, I_xy) of the same tensor (entries of the ' // &
                'tensor, not their negatives); the tensor must be one of a body, as for &bc ' // &
                'kind = ''body''.', count=3, example='0, 0, 0'), &
            spec_v('displacement', 'real', 'm', '0, 0, 0', 'Displacement of the plate at ' // &
                'f(t) = 1 (inertial components): the plate''s reference pose moved by f(t) ' // &
                'displacement; a pull is a displacement along the bundle.', count=3, &
                example='0, 0, 1e-3'), &
            spec_v('rotation', 'real', 'rad', '0, 0, 0', 'Rotation vector of the plate at ' // &
                'f(t) = 1 (inertial components, about centre): the plate turned by Exp(f(t) ' // &
                'rotation); a twist is a rotation about the bundle''s axis. A driven plate ' // &
                '(displacement or rotation not zero) starts at its reference pose: f(0) = 0.', &
                count=3, example='0, 0, 0.1'), &
            time_function_variables('plate motion')]
    end function plate_group

    function contact_group() result(g)
        type(group_spec_t) :: g
        g%name = 'contact'
        g%description = 'Rod-rod and self contact between all rods of the scene (ph_director, ' // &
            'se3_pg; all rods on one formulation; ' // &
            'DESIGN.md §5): a penalty potential between the Gauss points of nearby elements, ' // &
            'energy consistent in the midpoint step, with regularized Coulomb friction (mu); ' // &
            'candidate pairs come from a ' // &
            'cell grid rebuilt every step. With &contact all rods of the scene form one system, ' // &
            'and every rod needs a contact_radius (&rod).'
        g%variables = [ &
            spec_v('stiffness', 'real', 'N/m^3', '(required)', &
                'Penalty stiffness k of the pair potential psi(d2) = k (r_c^2 - d2)^3 / ' // &
                '(3 r_c^4) for d2 < r_c^2 (else 0), d2 the squared distance of two centreline ' // &
                'points and r_c the sum of their rods'' contact_radius. psi is an energy per ' // &
                'length squared (J/m^2), integrated over the arc lengths of both rods. A pair ' // &
                'carrying the force f per length squared penetrates by about sqrt(f r_c / ' // &
                '(8 k)): choose k to keep that well below r_c.', lower=0.0_rk, &
                lower_inclusive=.false., required=.true., example='1e12'), &
            spec_v('margin', 'real', 'm', 'largest contact_radius', &
                'Broad-phase margin: elements whose centrelines come within contact_radius_a + ' // &
                'contact_radius_b + margin of each other are candidate pairs (the boxes of the ' // &
                'cell grid grow by margin / 2). It does not change the potential; a larger ' // &
                'margin finds pairs that close within a step at the cost of more candidates. ' // &
                'A step moves no point by more than margin / 2 or a quarter of the smallest ' // &
                'contact distance (else it is halved).', &
                lower=0.0_rk, example='0.002'), &
            spec_v('skip', 'integer', '-', '(derived)', &
                'Elements of one rod this many or fewer apart along it are never a pair, and ' // &
                'neither are elements within skip of a joint (neighbours are held by the rod ' // &
                'itself). Default: ceiling(3 r_max / h_min) + 1, with r_max the largest ' // &
                'contact_radius and h_min the shortest element (length / n_elements) of the ' // &
                'scene: elements closer along a rod than 1.5 contact distances never pair.', &
                lower=0.0_rk, example='3'), &
            spec_v('points_per_element', 'integer', '-', '(derived)', &
                'Contact points (Gauss points of the contact integral) per element. Default: ' // &
                'enough to resolve the contact patch at a penetration of 5% of the contact ' // &
                'distance (at least the element''s n_gauss; docs/theory/bundles.md); fewer ' // &
                'points keep the energy but give a stiffer, bumpier contact law.', lower=1.0_rk, &
                example='8'), &
            spec_v('self_contact', 'logical', '-', '.true.', &
                'Contact of a rod with itself beyond skip elements (a twisted rod forming a ' // &
                'loop); .false. keeps contact between different rods only.', example='.false.'), &
            spec_v('mu', 'real', '-', '0', 'Coulomb friction coefficient between rods: ' // &
                'the force against the relative slip of two touching points is at most mu ' // &
                'times their normal force (regularized below slip_velocity). Friction acts in ' // &
                'dynamics (a quasistatic run refuses it); its dissipation is booked in ' // &
                'series/energy/dissipated, half on each rod of a pair.', lower=0.0_rk, &
                example='0.2'), &
            spec_v('slip_velocity', 'real', 'm/s', '1e-4', 'Regularization of friction: below ' // &
                'this relative slip velocity the friction force grows linearly from 0 (a ' // &
                'smooth stick branch: rods that should stick creep at a fraction of it).', &
                lower=0.0_rk, lower_inclusive=.false., example='1e-5')]
    end function contact_group

    function modes_group() result(g)
        type(group_spec_t) :: g
        g%name = 'modes'
        g%description = 'Modal analysis (docs/theory/modes.md): the lowest modes of the ' // &
            'equations of motion linearized about the reference state or a static ' // &
            'equilibrium, constraints and couplings kept, computed after the run with SLEPc ' // &
            '(shift-and-invert) from the dynamic midpoint step of the rods'' formulations. ' // &
            'Frequencies and mode shapes go to /modes of the result file and to the XDMF ' // &
            'sidecar; rodplot.py modes plots them.'
        g%variables = [ &
            spec_v('n_modes', 'integer', '-', '10', &
                'Number of modes, lowest first, rigid-body modes (zero frequency) included.', &
                lower=1.0_rk, upper=500.0_rk, example='6'), &
            spec_v('about', 'string', '-', "'reference'", &
                'The state the equations of motion are linearized about: ''reference'', the ' // &
                'initial state of the scene (with the loads of t = 0); ''equilibrium'', the ' // &
                'end state of a quasistatic run with the loads of its load time (prestress ' // &
                'and load stiffness included): t_end after load steps; after a continuation ' // &
                'the path''s last point, whose load time may be past t_end or, after ' // &
                'path_steps or past a limit point, below it (attribute load_time of /modes).', &
                allowed='reference|equilibrium', example="'equilibrium'"), &
            spec_v('kind', 'string', '-', "'modes'", &
                '''modes'': frequencies and mode shapes; ''buckling'': linearized buckling, ' // &
                'the critical load factors lambda of the run''s loads (those of the end ' // &
                'state''s load time, as for about) and ' // &
                'the buckling modes, from (K_0 + lambda K_geo) phi = 0 with K_0 the ' // &
                'stiffness of the reference state (loads of t = 0, give a ramp) and K_geo ' // &
                'that of the stresses of the equilibrium u_1 and of the loads, at the ' // &
                'reference (se3_pg; the planar rods and ph_director: K_T(u_1) - K_0; ' // &
                'docs/theory/modes.md; needs ' // &
                'about = ''equilibrium''; /buckling of the result file).', &
                allowed='modes|buckling', example="'buckling'")]
    end function modes_group

    function obstacle_group() result(g)
        type(group_spec_t) :: g
        g%name = 'obstacle'
        g%repeatable = .true.
        g%description = 'A rigid obstacle, fixed or moving, that every rod touches with its ' // &
            'contact_radius (ph_director, se3_pg): the ground (''plane''), a ''sphere'' or ' // &
            'an infinite ''cylinder''; penalty contact whose midpoint step keeps the ' // &
            'energy exactly (nothing tunnels through a plane), with regularized Coulomb ' // &
            'friction (docs/theory/bundles.md, Obstacles).'
        g%variables = [ &
            spec_v('name', 'string', '-', '(required)', 'Name of the obstacle (unique among ' // &
                'the obstacles), used in the plan.', required=.true., example="'ground'"), &
            spec_v('kind', 'string', '-', '(required)', '''plane'': the half-space behind ' // &
                'the plane through point with outward normal; ''sphere'': the ball of radius ' // &
                'about point; ''cylinder'': the infinite cylinder of radius about the axis ' // &
                'through point along normal.', allowed='plane|sphere|cylinder', required=.true., &
                example="'plane'"), &
            spec_v('point', 'real', 'm', '0, 0, 0', 'A point of the plane, the centre of ' // &
                'the sphere, a point of the cylinder''s axis (inertial components).', count=3, &
                example='0, 0, -0.1'), &
            spec_v('normal', 'real', '-', '(plane, cylinder: required)', 'The plane''s ' // &
                'outward normal (rods stay on its side), or the cylinder''s axis; normalized, ' // &
                'not the zero vector. A sphere takes none.', count=3, example='0, 0, 1'), &
            spec_v('radius', 'real', 'm', '(sphere, cylinder: required)', 'Radius of the ' // &
                'sphere or the cylinder. A plane takes none.', lower=0.0_rk, &
                lower_inclusive=.false., example='0.5'), &
            spec_v('stiffness', 'real', 'N/m^3', '(required)', 'Penalty stiffness k: a ' // &
                'centreline point that penetrates the surface by delta (its distance below ' // &
                'its contact_radius) carries the force k delta^2 per length; a rod of weight ' // &
                'w per length resting on the ground penetrates sqrt(w / k).', lower=0.0_rk, &
                lower_inclusive=.false., required=.true., example='1e9'), &
            spec_v('mu', 'real', '-', '0', 'Coulomb friction coefficient: the force against ' // &
                'the slip is at most mu times the normal force (regularized below ' // &
                'slip_velocity). Friction acts in dynamics (a quasistatic run refuses it); its ' // &
                'dissipation is booked in series/energy/dissipated.', lower=0.0_rk, &
                example='0.3'), &
            spec_v('slip_velocity', 'real', 'm/s', '1e-4', 'Regularization of friction: below ' // &
                'this slip velocity the friction force grows linearly from 0 (a smooth stick ' // &
                'branch: a rod that should stick creeps at a fraction of it).', lower=0.0_rk, &
                lower_inclusive=.false., example='1e-5'), &
            spec_v('damping', 'real', 's/m', '0', 'Normal damping alpha of Hunt and ' // &
                'Crossley''s law: the penalty force k delta^2 becomes k delta^2 (1 + alpha ' // &
                'd delta/dt), so an impact at the speed v loses about alpha v of its energy ' // &
                '(0: elastic). Dynamics only (a quasistatic run refuses it); its dissipation is ' // &
                'booked in series/energy/dissipated.', lower=0.0_rk, example='0.5'), &
            spec_v('displacement', 'real', 'm', '0, 0, 0', 'Translation of the obstacle at ' // &
                'f(t) = 1: it moves rigidly by f(t) displacement (f the time function; a moving ' // &
                'obstacle starts where it is given, f(0) = 0). Its work on the rods is booked ' // &
                'as theirs (external work).', count=3, example='0, 0, 0.01'), &
            time_function_variables('obstacle motion')]
    end function obstacle_group

    function sweep_group() result(g)
        type(group_spec_t) :: g
        g%name = 'sweep'
        g%repeatable = .true.
        g%description = 'One swept variable of a parameter sweep (DESIGN.md §5): every ' // &
            'member is the scene without its &sweep groups, with the swept variables set to ' // &
            'one combination of their values, and is checked as a scene of its own. The ' // &
            'sweeps combine in file order (mode); docs/user/input.md, Parameter sweeps.'
        g%variables = [ &
            spec_v('parameter', 'string', '-', '(required)', &
                'The swept variable, a path into the scene (case-insensitive): ' // &
                'group%variable for &run, &time, &solver, &output and &contact (time%dt; a ' // &
                'group the scene lacks is added), group(k)%variable for the k-th &rod, &bc, ' // &
                '&load, &actuator, &joint or &plate in file order (rod(1)%EI1), and variable(i) ' // &
                'for element ' // &
                'i of an array (load(1)%force(3)); arrays must be swept element by element. ' // &
                'Only real and integer variables can be swept; each variable at most once.', &
                required=.true., example="'rod(1)%EI1'"), &
            spec_v('values', 'real', '-', '-', &
                'The values, in order (the leading given entries), in the unit of the swept ' // &
                'variable. Exactly one of values, ' // &
                'linspace and logspace. For an integer variable every value must be a whole ' // &
                'number; every value must lie in the variable''s allowed range.', count=1, &
                max_count=max_sweep_values, example='1e3, 2e3, 5e3'), &
            spec_v('linspace', 'real', '-', '-', &
                'first, last, count: count values evenly spaced from first to last, both ' // &
                'included (count a whole number from 2 to ' // str(max_sweep_values) // ').', &
                count=3, example='0.5, 2.0, 16'), &
            spec_v('logspace', 'real', '-', '-', &
                'first, last, count: count values geometrically spaced from first to last, ' // &
                'both included and both > 0 (count a whole number from 2 to ' // &
                str(max_sweep_values) // ').', count=3, example='1e2, 1e4, 64'), &
            spec_v('mode', 'string', '-', "'product'", &
                "How this sweep combines with the sweeps before it in the file: 'product' " // &
                "takes every combination with them, 'zip' pairs its values one to one with " // &
                'those of the sweep just before it (same number of values). Ignored for the ' // &
                'first sweep. Members are numbered from 1 with the first sweep varying ' // &
                'slowest; at most ' // str(max_sweep_members) // ' members.', &
                allowed='product|zip', example="'zip'")]
    end function sweep_group

    !> time_function, t_on, t_off, table_times, table_values of a group whose `what` they scale.
    function time_function_variables(what) result(variables)
        character(len=*), intent(in) :: what
        type(variable_spec_t) :: variables(5)
        variables = [ &
            spec_v('time_function', 'string', '-', "'constant'", 'Scaling f(t) of the ' // what // &
                ' in time.', allowed=time_function_names, example="'ramp'"), &
            spec_v('t_on', 'real', 's', '0', 'Start of the ramp, hat, pulse or sine.', lower=0.0_rk, &
                example='0.5'), &
            spec_v('t_off', 'real', 's', '-', 'End of the ramp, hat or pulse; for a sine, t_on plus ' // &
                'its period.', lower=0.0_rk, example='1.5'), &
            spec_v('table_times', 'real', 's', '-', 'Times of a piecewise-linear table (increasing).', &
                count=2, max_count=max_table, example='0, 1, 2'), &
            spec_v('table_values', 'real', '-', '-', 'Factors f at table_times.', count=2, &
                max_count=max_table, example='0, 1, 0.5')]
    end function time_function_variables

    !> The names of `groups`, in order.
    pure function group_names(groups) result(names)
        type(group_spec_t), intent(in) :: groups(:)
        character(len=16), allocatable :: names(:)
        integer :: i
        allocate(names(size(groups)))
        do i = 1, size(groups)
            names(i) = groups(i)%name
        end do
    end function group_names

    !> The names of the variables of `group`, in order.
    pure function variable_names(group) result(names)
        type(group_spec_t), intent(in) :: group
        character(len=32), allocatable :: names(:)
        integer :: i
        allocate(names(size(group%variables)))
        do i = 1, size(group%variables)
            names(i) = group%variables(i)%name
        end do
    end function variable_names

end module rs_io_input_spec
