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
    use rs_model_scene, only: max_table, max_branches
    implicit none
    private

    public :: variable_spec_t, group_spec_t, input_groups, find_group, find_variable, spec_v
    public :: range_description, in_range

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
        character(len=48) :: default_text = ''
        character(len=480) :: description = ''
    end type variable_spec_t

    !> One namelist group.
    type :: group_spec_t
        character(len=16) :: name = ''
        logical :: repeatable = .false.
        logical :: implemented = .true.
        character(len=400) :: description = ''
        type(variable_spec_t), allocatable :: variables(:)
    end type group_spec_t

    character(len=*), parameter :: formulations = &
        'ph_director|ph_planar|cl_em_planar|se3_pg|se3_strand|auto'

contains

    !> A variable spec; optional arguments as in variable_spec_t.
    pure function spec_v(name, kind, unit, default_text, description, count, max_count, allowed, &
            lower, lower_inclusive, upper, upper_inclusive, required) result(v)
        character(len=*), intent(in) :: name, kind, unit, default_text, description
        integer, intent(in), optional :: count, max_count
        character(len=*), intent(in), optional :: allowed
        real(rk), intent(in), optional :: lower, upper
        logical, intent(in), optional :: lower_inclusive, upper_inclusive, required
        type(variable_spec_t) :: v
        v%name = name
        v%kind = kind
        v%unit = unit
        v%default_text = default_text
        v%description = description
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
        allocate(groups(10))
        groups(1) = run_group()
        groups(2) = time_group()
        groups(3) = solver_group()
        groups(4) = output_group()
        groups(5) = rod_group()
        groups(6) = bc_group()
        groups(7) = load_group()
        groups(8) = actuator_group()
        groups(9) = planned_group('joint', 'Joints between rod ends.')
        groups(10) = planned_group('sweep', 'Parameter sweeps over any input variable.')
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

    function run_group() result(g)
        type(group_spec_t) :: g
        g%name = 'run'
        g%description = 'What the run is, and choices that hold for the whole scene.'
        g%variables = [ &
            spec_v('title', 'string', '-', "''", 'A title stored in the output.'), &
            spec_v('formulation_default', 'string', '-', "'ph_director'", &
                'Formulation of rods that do not name one (DESIGN.md §1).', allowed=formulations), &
            spec_v('seed', 'integer', '-', '1', 'Seed of random perturbations, where a scene asks for them.', &
                lower=0.0_rk), &
            spec_v('log_level', 'string', '-', "'info'", 'Most detailed messages printed.', &
                allowed='error|warning|info|debug')]
    end function run_group

    function time_group() result(g)
        type(group_spec_t) :: g
        g%name = 'time'
        g%description = 'The time interval and the time-stepping scheme.'
        g%variables = [ &
            spec_v('t_end', 'real', 's', '(required)', 'End time; in quasistatic runs the final load factor.', &
                lower=0.0_rk, lower_inclusive=.false., required=.true.), &
            spec_v('dt', 'real', 's', '(required)', 'Time step (halved on Newton failure, see &solver).', &
                lower=0.0_rk, lower_inclusive=.false., required=.true.), &
            spec_v('scheme', 'string', '-', "'midpoint'", 'Time integrator.', allowed='midpoint'), &
            spec_v('quasistatic', 'logical', '-', '.false.', &
                'No inertia (mass terms dropped): time is a load factor (t_end usually 1). The ' // &
                'loads are stepped with midpoint steps, then one endpoint (non-rate ' // &
                'Hellinger-Reissner) equilibrium solve at t_end gives the last record (seed 000 ' // &
                '§5, §6.3; methods/ph_director_3d.md §6.3).')]
    end function time_group

    function solver_group() result(g)
        type(group_spec_t) :: g
        g%name = 'solver'
        g%description = "Newton's stopping rule, step cut-backs and PETSc options (DESIGN.md §3)."
        g%variables = [ &
            spec_v('newton_atol', 'real', '-', '1e-10', &
                'Newton stops when the scaled residual norm of the method document is at most this.', &
                lower=0.0_rk, lower_inclusive=.false.), &
            spec_v('newton_rtol', 'real', '-', '0', &
                'Relative decrease that also stops Newton (0: off, as the papers).', lower=0.0_rk, upper=1.0_rk), &
            spec_v('max_newton', 'integer', '-', '25', 'Newton iterations per step before a cut-back.', &
                lower=1.0_rk), &
            spec_v('max_cutbacks', 'integer', '-', '6', &
                'Halvings of one step before the run stops with its last good state written.', lower=0.0_rk), &
            spec_v('condense_stresses', 'logical', '-', '.false.', &
                'Eliminate element stresses and velocities from the Newton unknowns (methods/' // &
                'ph_director_3d.md §5.5): same solution, fewer unknowns, but slower and with a ' // &
                'higher round-off floor here (docs/performance.md).'), &
            spec_v('petsc_options', 'string', '-', "''", &
                'PETSc options, applied after the scene values and before the command line.')]
    end function solver_group

    function output_group() result(g)
        type(group_spec_t) :: g
        g%name = 'output'
        g%description = 'Where results go and how often (HDF5, DESIGN.md §7).'
        g%variables = [ &
            spec_v('path', 'string', '-', "'out/<scene>.h5'", 'Result file.'), &
            spec_v('stride', 'integer', '-', '1', 'Write every stride-th step.', lower=1.0_rk), &
            spec_v('fields', 'string', '-', "'all'", 'Comma-separated fields to write, or all.'), &
            spec_v('flush_every', 'integer', '-', '10', 'Flush the file every this many steps.', lower=1.0_rk), &
            spec_v('xdmf', 'logical', '-', '.true.', 'Write an XDMF sidecar for ParaView.')]
    end function output_group

    function rod_group() result(g)
        type(group_spec_t) :: g
        g%name = 'rod'
        g%repeatable = .true.
        g%description = 'One rod: geometry, cross-section, material and discretization.'
        g%variables = [ &
            spec_v('name', 'string', '-', "'rod<i>'", 'Name used by &bc and &load and in the output.'), &
            spec_v('formulation', 'string', '-', 'formulation_default', 'Formulation of this rod.', &
                allowed=formulations), &
            spec_v('n_elements', 'integer', '-', '(required)', 'Number of elements.', lower=1.0_rk, &
                required=.true.), &
            spec_v('degree', 'integer', '-', '2', 'Polynomial degree of the elements.', lower=1.0_rk, upper=2.0_rk), &
            spec_v('n_gauss', 'integer', '-', '2', 'Gauss points per element.', lower=1.0_rk, upper=5.0_rk), &
            spec_v('start', 'real', 'm', '0, 0, 0', 'Position of the end s = 0.', count=3), &
            spec_v('direction', 'real', '-', '1, 0, 0', 'Direction of the straight centreline (normalized).', &
                count=3), &
            spec_v('d1', 'real', '-', '(derived)', &
                'First cross-section director; default: a unit vector normal to direction.', count=3), &
            spec_v('length', 'real', 'm', '(required)', 'Length of the rod.', lower=0.0_rk, &
                lower_inclusive=.false., required=.true.), &
            spec_v('section', 'string', '-', "'none'", &
                "Cross-section shape; 'none': stiffnesses and inertias are given directly.", &
                allowed='none|circle|rectangle|tube'), &
            spec_v('radius', 'real', 'm', '-', 'Radius of a circle, outer radius of a tube.', &
                lower=0.0_rk, lower_inclusive=.false.), &
            spec_v('inner_radius', 'real', 'm', '-', 'Inner radius of a tube.', lower=0.0_rk), &
            spec_v('width', 'real', 'm', '-', 'Rectangle side along d1.', lower=0.0_rk, lower_inclusive=.false.), &
            spec_v('height', 'real', 'm', '-', 'Rectangle side along d2.', lower=0.0_rk, lower_inclusive=.false.), &
            spec_v('E', 'real', 'Pa', '-', "Young's modulus.", lower=0.0_rk, lower_inclusive=.false.), &
            spec_v('G', 'real', 'Pa', 'E/(2(1+nu))', 'Shear modulus.', lower=0.0_rk, lower_inclusive=.false.), &
            spec_v('nu', 'real', '-', '-', "Poisson's ratio (used when G is not given).", lower=-1.0_rk, &
                lower_inclusive=.false., upper=0.5_rk), &
            spec_v('density', 'real', 'kg/m^3', '-', 'Mass density.', lower=0.0_rk, lower_inclusive=.false.), &
            spec_v('EA', 'real', 'N', '(section)', 'Axial stiffness.', lower=0.0_rk, lower_inclusive=.false.), &
            spec_v('GA1', 'real', 'N', '(section)', 'Shear stiffness along d1.', lower=0.0_rk, &
                lower_inclusive=.false.), &
            spec_v('GA2', 'real', 'N', '(section)', 'Shear stiffness along d2.', lower=0.0_rk, &
                lower_inclusive=.false.), &
            spec_v('EI1', 'real', 'N m^2', '(section)', 'Bending stiffness about d1.', lower=0.0_rk, &
                lower_inclusive=.false.), &
            spec_v('EI2', 'real', 'N m^2', '(section)', 'Bending stiffness about d2.', lower=0.0_rk, &
                lower_inclusive=.false.), &
            spec_v('GJ', 'real', 'N m^2', '(section)', 'Torsional stiffness.', lower=0.0_rk, &
                lower_inclusive=.false.), &
            spec_v('rhoA', 'real', 'kg/m', '(section)', 'Mass per unit length.', lower=0.0_rk), &
            spec_v('rhoI1', 'real', 'kg m', '(section)', 'Rotational inertia per length about d1.', &
                lower=0.0_rk), &
            spec_v('rhoI2', 'real', 'kg m', '(section)', 'Rotational inertia per length about d2.', &
                lower=0.0_rk), &
            spec_v('shear_factor', 'real', '-', '1', 'Shear correction factor k in GA = k G A.', &
                lower=0.0_rk, lower_inclusive=.false.), &
            spec_v('torsion_constant', 'string', '-', "'polar' (circle, tube)", &
                'Torsion constant of a section: polar moment or Saint-Venant; required for a rectangle.', &
                allowed='polar|saint_venant'), &
            spec_v('prestressed', 'logical', '-', '.false.', &
                'False: the initial geometry is stress-free (DESIGN.md §1).'), &
            spec_v('constraint', 'string', '-', "'none'", &
                "Kinematic constraint: 'kirchhoff' = shear-rigid, 'inextensible' = shear-rigid " // &
                'and inextensible (seed 000 §2.3, §5; methods/ph_director_3d.md §2.3). The ' // &
                'constrained stress components become Lagrange multipliers; the stiffnesses of ' // &
                "the constrained components (GA1, GA2, and EA for 'inextensible') are ignored, " // &
                'so they may be given or derived from a section.', &
                allowed='none|kirchhoff|inextensible'), &
            spec_v('maxwell_fraction', 'real', '-', '-', &
                'Generalized Maxwell viscoelasticity (seed 000 §5.1, methods/ph_director_3d.md ' // &
                '§3.1): the fraction of every stiffness taken by branch i = 1..m; the branches ' // &
                'are the leading entries (no gaps) and the purely elastic branch keeps ' // &
                '1 - sum > 0.', count=1, max_count=max_branches, lower=0.0_rk, &
                lower_inclusive=.false., upper=1.0_rk, upper_inclusive=.false.), &
            spec_v('maxwell_tau_E', 'real', 's', '-', &
                'Relaxation time of the dilatation and bending components of each Maxwell branch; ' // &
                'exactly one per maxwell_fraction.', count=1, max_count=max_branches, lower=0.0_rk, &
                lower_inclusive=.false.), &
            spec_v('maxwell_tau_G', 'real', 's', 'maxwell_tau_E', &
                'Relaxation time of the shear and torsion components of each Maxwell branch; a ' // &
                'branch without one takes its maxwell_tau_E.', count=1, max_count=max_branches, &
                lower=0.0_rk, lower_inclusive=.false.)]
    end function rod_group

    function bc_group() result(g)
        type(group_spec_t) :: g
        g%name = 'bc'
        g%repeatable = .true.
        g%description = 'The support at one end of a rod; ends without &bc are free.'
        g%variables = [ &
            spec_v('rod', 'string', '-', '(required)', 'Name of the rod.', required=.true.), &
            spec_v('end', 'string', '-', '(required)', 'Which end.', allowed='start|end', required=.true.), &
            spec_v('kind', 'string', '-', '(required)', 'Kind of support.', &
                allowed='clamped|pinned|free|driven', required=.true.)]
    end function bc_group

    function load_group() result(g)
        type(group_spec_t) :: g
        g%name = 'load'
        g%repeatable = .true.
        g%description = 'An end load, a distributed load or gravity, scaled by a time function.'
        g%variables = [ &
            spec_v('rod', 'string', '-', "'' (all rods, gravity only)", 'Name of the loaded rod.'), &
            spec_v('where', 'string', '-', '(required)', 'Point of application.', &
                allowed='start|end|distributed|gravity', required=.true.), &
            spec_v('force', 'real', 'N or N/m', '0, 0, 0', 'Force (per length when distributed).', count=3), &
            spec_v('moment', 'real', 'N m or N', '0, 0, 0', 'Moment (per length when distributed).', count=3), &
            spec_v('acceleration', 'real', 'm/s^2', '0, 0, 0', 'Gravitational acceleration (where = gravity).', &
                count=3), &
            spec_v('frame', 'string', '-', "'spatial'", 'Dead (spatial) or follower load.', &
                allowed='spatial|follower'), &
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
            spec_v('rod', 'string', '-', '(required)', 'Name of the actuated rod.', required=.true.), &
            spec_v('kind', 'string', '-', '(required)', &
                "'pneumatic': a chamber, line of action d3 (normal to the section), tau(t) = " // &
                "-pressure area f(t). 'tendon': a cable, line of action the tangent of its own line " // &
                'r = phi + rho^1 d1 + rho^2 d2, tau(t) = tension f(t). f is the time function.', &
                allowed='pneumatic|tendon', required=.true.), &
            spec_v('offset', 'real', 'm', '(required)', &
                'Material coordinates (rho^1, rho^2) of the chamber centroid or tendon line in the ' // &
                '(d1, d2) director basis; must lie inside a circle or tube section.', count=2, &
                required=.true.), &
            spec_v('area', 'real', 'm^2', '(pneumatic)', &
                'Cross-section area of the chamber; required for a pneumatic chamber, an error for ' // &
                'a tendon.', lower=0.0_rk, lower_inclusive=.false.), &
            spec_v('pressure', 'real', 'Pa', '(pneumatic)', &
                'Gauge pressure of the chamber; required for a pneumatic chamber, an error for a ' // &
                'tendon. Positive pressure pushes the end caps apart: tau < 0 elongates the rod.'), &
            spec_v('tension', 'real', 'N', '(tendon)', &
                'Tension of the tendon (a tendon only pulls); required for a tendon, an error for ' // &
                'a pneumatic chamber.', lower=0.0_rk), &
            time_function_variables('actuator force')]
    end function actuator_group

    !> time_function, t_on, t_off, table_times, table_values of a group whose `what` they scale.
    function time_function_variables(what) result(variables)
        character(len=*), intent(in) :: what
        type(variable_spec_t) :: variables(5)
        variables = [ &
            spec_v('time_function', 'string', '-', "'constant'", 'Scaling f(t) of the ' // what // &
                ' in time.', allowed='constant|ramp|hat|pulse|table'), &
            spec_v('t_on', 'real', 's', '0', 'Start of the ramp, hat or pulse.', lower=0.0_rk), &
            spec_v('t_off', 'real', 's', '-', 'End of the ramp, hat or pulse.', lower=0.0_rk), &
            spec_v('table_times', 'real', 's', '-', 'Times of a piecewise-linear table (increasing).', &
                count=2, max_count=max_table), &
            spec_v('table_values', 'real', '-', '-', 'Factors f at table_times.', count=2, &
                max_count=max_table)]
    end function time_function_variables

    function planned_group(name, description) result(g)
        character(len=*), intent(in) :: name, description
        type(group_spec_t) :: g
        g%name = name
        g%repeatable = .true.
        g%implemented = .false.
        g%description = description
        allocate(g%variables(0))
    end function planned_group

end module rs_io_input_spec
