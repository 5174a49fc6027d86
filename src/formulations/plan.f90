!> The plan of a resolved, checked scene (DESIGN.md §4, `rodsolve --check-input`): what runs and
!> what is skipped, as namelist comments ('!' lines) so that the output of --check-input stays a
!> scene that reads back to itself. Scene-wide: time steps, output, units, how the rods are
!> dealt to the ranks; per rod: its formulation and why (for 'auto': the plane the rods lie in,
!> or why they are 3D), and what that formulation says about it (the plan lines of its
!> descriptor, rs_formulations_registry).
module rs_formulations_plan
    use, intrinsic :: iso_fortran_env, only: int64
    use rs_core_kinds, only: rk
    use rs_core_error, only: error_t
    use rs_core_strings, only: str, text_buffer_t, vector_text
    use rs_model_scene, only: scene_t, step_count, obstacle_input_t, rod_segment_count, unset_real
    use rs_model_units, only: unit_in_system
    use rs_model_coupling, only: coupled_systems, system_costs
    use rs_formulations_formulation, only: rod_formulation_t
    use rs_formulations_descriptor, only: formulation_descriptor_t
    use rs_formulations_registry, only: descriptor_of, is_bundle
    use rs_formulations_factory, only: create_formulation
    use rs_parallel_deal, only: deal_by_cost
    use rs_formulations_memory_estimate, only: memory_estimate_t, run_memory_estimate, &
        bytes_text, available_memory_bytes, rod_memory_bytes
    use rs_formulations_rod_sizes, only: rod_sizes_t, rod_sizes_of
    implicit none
    private

    public :: scene_plan_text

    !> First line of the plan; a reader of --check-input output finds the plan by it.
    character(len=*), parameter, public :: plan_header = &
        '! plan: what runs and what is skipped (DESIGN.md §4)'

contains

    !> The plan of `scene` for a run on `n_ranks` ranks; one '!' line per item, each ending in a
    !> new line. A rod that cannot be built says why in its place.
    function scene_plan_text(scene, n_ranks) result(text)
        type(scene_t), intent(in) :: scene
        integer, intent(in) :: n_ranks
        character(len=:), allocatable :: text, lines, units, why
        type(error_t), allocatable :: err
        type(memory_estimate_t) :: memory
        type(rod_sizes_t) :: sizes
        integer :: i, n_steps, n_records, rank
        type(text_buffer_t) :: buffer
        integer, allocatable :: system_of(:), first(:), members(:), system_rank(:)
        type(formulation_descriptor_t) :: d
        class(rod_formulation_t), allocatable :: mold
        character(len=:), allocatable :: semi_implicit_step, after_path, ending

        units = trim(scene%run%units)
        n_steps = step_count(scene)
        n_records = 1 + n_steps / scene%output%stride
        if (mod(n_steps, scene%output%stride) /= 0) n_records = n_records + 1
        ! The plan grows in `buffer` (doubling), not by copying all of it per line: a scene
        ! of 4,000 rods has 80,000 plan lines (issue 21 item 17).
        call append(plan_header // new_line('a'))
        ! A semi-implicit formulation's step is one linear solve without Newton (issue 21 item
        ! 15: its plan named midpoint steps and Newton).
        semi_implicit_step = semi_implicit_step_of_all()
        if (len(semi_implicit_step) > 0) then
            call add('time: ' // str(n_steps) // ' semi-implicit step(s) of dt = ' // &
                str(scene%time%dt) // ' ' // unit_in_system('s', units) // ' to t_end = ' // &
                str(scene%time%t_end) // ' ' // unit_in_system('s', units) // &
                ' (' // semi_implicit_step // ')')
        else if (trim(scene%time%continuation) == 'arc_length') then
            call add_continuation_lines()
        else if (scene%time%quasistatic) then
            call add('time: quasistatic, ' // str(n_steps) // ' midpoint load step(s) of ' // &
                str(scene%time%dt) // ' to the load factor t_end = ' // str(scene%time%t_end) // &
                ', between equilibrium solves at t = 0 and t_end (ph_director and planar ' // &
                'rods; continued from the state before them)')
        else
            call add('time: ' // str(n_steps) // ' ' // trim(scene%time%scheme) // ' step(s) of dt = ' // &
                str(scene%time%dt) // ' ' // unit_in_system('s', units) // ' to t_end = ' // &
                str(scene%time%t_end) // ' ' // unit_in_system('s', units) // &
                ' (halved up to ' // str(scene%solver%max_cutbacks) // ' times on Newton failure)')
        end if
        if (scene%time%initial_equilibrium) call add('start: the static equilibrium with the ' // &
            'loads and supports at t = 0, continued from the initial placement, then the ' // &
            'dynamics from it at rest (&time initial_equilibrium; docs/theory/' // &
            'prestretched_starts.md)')
        if (len(semi_implicit_step) > 0) then
            call add('Newton: none, one linear solve per step (PETSc''s LU)')
        else
            call add('Newton: stops at the scaled residual norm ' // str(scene%solver%newton_atol) // &
                ', at most ' // str(scene%solver%max_newton) // ' iterations; LU per system: ' // &
                'the chain LU (rodchain) for one rod of ph_director, se3_pg or quasistatic ' // &
                'PH-EM, PETSc''s own LU where the Jacobian needs no pivoting (planar dynamics, ' // &
                'se3_strand), MUMPS for a system the ranks share')
        end if
        if (trim(scene%time%continuation) == 'arc_length') then
            ! The path may pass t_end before its last step; /time holds the step number.
            call add('output: ' // trim(scene%output%path) // ': fields ''' // &
                trim(scene%output%fields) // ''', at most ' // str(n_records) // ' record(s) ' // &
                '(the start, every ' // str(scene%output%stride) // ' path step(s) and the ' // &
                'last; /time holds the step number, /rods/NAME/series/load_time the load ' // &
                'time of each record), flushed every ' // str(scene%output%flush_every) // &
                ' step(s), XDMF sidecar ' // trim(merge('yes', 'no ', scene%output%xdmf)))
        else
            call add('output: ' // trim(scene%output%path) // ': fields ''' // &
                trim(scene%output%fields) // ''', ' // str(n_records) // ' record(s) (t = ' // &
                '0, every ' // str(scene%output%stride) // ' step(s) and the last), flushed ' // &
                'every ' // str(scene%output%flush_every) // ' step(s), XDMF sidecar ' // &
                trim(merge('yes', 'no ', scene%output%xdmf)))
        end if
        ! After a continuation the equilibrium is the path's last point, with the loads of its
        ! own load time, which may be anywhere (rs_app_run_modes, rod_runner_t%load_time).
        after_path = ''
        ending = 't_end'
        if (trim(scene%time%continuation) == 'arc_length') ending = 'the end state''s load time'
        if (trim(scene%time%continuation) == 'arc_length' .and. &
            trim(scene%modes%about) == 'equilibrium') after_path = ' (after the ' // &
            'continuation: about the path''s last point, with the loads of its load time, ' // &
            'past t_end or, after path_steps or past a limit point, anywhere below it; the ' // &
            'attribute load_time of the group says which)'
        if (scene%modes%given .and. trim(scene%modes%kind) == 'buckling') then
            call add('buckling: after the run, the ' // str(scene%modes%n_modes) // &
                ' load factors nearest 0 of the run''s loads (those of ' // ending // &
                ') and their ' // &
                'buckling modes, (K_0 + lambda K_geo) phi = 0 with K_0 the unloaded ' // &
                'reference''s stiffness and K_geo the stiffness of the end equilibrium''s ' // &
                'stresses and of the loads at the reference (se3_pg; ph_planar: K_geo = ' // &
                'K_T(u_1) - K_0 at the equilibrium u_1, ph_director: the same from its ' // &
                'static problem; docs/theory/modes.md), by SLEPc shift-and-invert at 0 with ' // &
                'MUMPS; load factors and modes into /buckling of the result file and its ' // &
                '.modes.xdmf sidecar' // after_path)
        else if (scene%modes%given) then
            call add('modes: after the run, the lowest ' // &
                str(scene%modes%n_modes) // ' modes of every system about its ' // &
                trim(scene%modes%about) // ' state (the linearized equations of motion read from ' // &
                'the step Jacobians at five steps, docs/theory/modes.md), by SLEPc ' // &
                'shift-and-invert with MUMPS on all ranks; frequencies and mode shapes into ' // &
                '/modes of the result file and its .modes.xdmf sidecar' // after_path)
        end if
        call add('units: ''' // units // ''' (length ' // unit_in_system('m', units) // ', mass ' // &
            unit_in_system('kg', units) // ', time ' // unit_in_system('s', units) // ', force ' // &
            unit_in_system('N', units) // ', stress ' // unit_in_system('Pa', units) // '); the ' // &
            'numbers are used as given')
        ! Rods joined by &joint or &plate groups, or all rods with &contact, are one system,
        ! solved together (rs_model_coupling).
        call coupled_systems(scene, system_of, first, members)
        call add('ranks: ' // str(size(scene%rods)) // ' rod(s) in ' // str(size(first) - 1) // &
            ' system(s) (a rod, or rods coupled by &joint, &plate or &contact) on ' // &
            str(n_ranks) // ' rank(s), dealt by estimated cost (nodes; the largest first, each ' // &
            'to the least loaded rank), each solved on its own (no communication in the time ' // &
            'loop but the flushes); on several ranks a bundle is solved by all ranks ' // &
            'together (rods partitioned by METIS; MUMPS in parallel, or GMRES with block ' // &
            'Jacobi over the rods for dynamic bundles of 7 or more rods without joints)')
        system_rank = deal_by_cost(system_costs(scene, first, members), n_ranks)
        memory = run_memory_estimate(scene, n_ranks)
        if (memory%known) then
            call add('memory: estimated peak ' // bytes_text(memory%busiest_rank_bytes) // &
                ' on rank ' // str(memory%busiest_rank) // ' (the busiest), ' // &
                bytes_text(memory%total_bytes) // ' on all ranks together; the largest part ' // &
                'is rod ''' // trim(scene%rods(memory%largest_rod)%name) // ''' (' // &
                bytes_text(memory%largest_rod_bytes) // '); available now: ' // &
                bytes_text(available_memory_bytes()) // ' (MemAvailable); a run that will ' // &
                'not fit is refused (docs/user/getting_started.md, "Memory")')
        else
            call add('memory: no estimate (a rod cannot be built; see its lines below)')
        end if
        if (allocated(scene%obstacles)) then
            do i = 1, size(scene%obstacles)
                call add(obstacle_line(scene%obstacles(i)))
            end do
        end if
        do i = 1, size(scene%rods)
            rank = system_rank(system_of(i))
            if (n_ranks > 1 .and. is_bundle(scene, members(first(system_of(i)):first(system_of(i) + 1) - 1))) &
                rank = -1
            associate (rod => scene%rods(i))
                select case (trim(rod%formulation_origin))
                case ('default')
                    why = 'from &run formulation_default'
                case ('auto')
                    why = 'auto: ' // trim(rod%formulation_reason)
                case default
                    why = 'given in &rod'
                end select
                if (rank < 0) then
                    call add('rod ''' // trim(rod%name) // ''' on all ' // str(n_ranks) // &
                        ' ranks (a shared bundle): ' // trim(rod%formulation) // ' (' // why // ')')
                else
                    call add('rod ''' // trim(rod%name) // ''' on rank ' // str(rank) // ': ' // &
                        trim(rod%formulation) // ' (' // why // ')')
                end if
                if (descriptor_of(trim(rod%formulation), d)) then
                    call d%plan_lines(scene, i, lines, err)
                    if (allocated(err)) lines = '!     cannot be built: ' // err%describe() // new_line('a')
                else
                    lines = '!     formulation not available in this version' // new_line('a')
                end if
                call append(lines)
                call append(segment_plan_lines(scene, i))
                call append(prestretched_plan_lines(scene, i))
                call create_formulation(trim(rod%formulation), mold, err)
                if (.not. allocated(err)) call rod_sizes_of(scene, i, sizes, err, mold)
                if (.not. allocated(err)) call append('!     memory: ' // &
                    bytes_text(rod_memory_bytes(scene, sizes)) // ' estimated (Jacobian ' // &
                    count_text(sizes%n_nonzeros) // ' non-zeros, ' // &
                    count_text(sizes%n_unknown) // ' unknowns, state ' // &
                    count_text(sizes%n_state) // ')' // new_line('a'))
            end associate
        end do
        call append(sweep_plan_lines(scene))
        text = buffer%text()
    contains
        !> '<name>, <where its step is described>' when every rod runs on the same
        !> semi-implicit formulation, else ''.
        function semi_implicit_step_of_all() result(text)
            character(len=:), allocatable :: text
            integer :: r
            text = ''
            do r = 1, size(scene%rods)
                if (.not. descriptor_of(trim(scene%rods(r)%formulation), d)) return
                if (len_trim(d%semi_implicit_step) == 0) return
                if (scene%rods(r)%formulation /= scene%rods(1)%formulation) return
            end do
            if (size(scene%rods) == 0) return
            text = trim(d%name) // ', ' // trim(d%semi_implicit_step)
        end function semi_implicit_step_of_all

        !> An arc-length continuation (&time continuation; docs/theory/continuation.md,
        !> rs_solver_arc_length and rod_run's start_path): its path steps replace the load
        !> steps and the endpoint solve; the bordered solves reuse the stepper's LU.
        subroutine add_continuation_lines()
            character(len=:), allocatable :: switch
            call add('time: quasistatic by arc-length continuation (docs/theory/' // &
                'continuation.md): the load time an unknown, at most ' // &
                str(scene%time%path_steps) // ' path step(s), the first of arc length ' // &
                str(scene%time%arc_length) // ' in the scaled path length (the mean over the ' // &
                'nodes of |dr|^2 / L^2 + |dtheta|^2, plus (d load time / t_end)^2), then ' // &
                'about 4 Newton iterations per step, between ' // &
                str(scene%time%arc_length * 0.5_rk**(2 * scene%solver%max_cutbacks)) // &
                ' (arc_length / 4^max_cutbacks) and arc_length_max = ' // &
                str(max(scene%time%arc_length, scene%time%arc_length_max)) // &
                '; the path ends when its load time passes t_end = ' // &
                str(scene%time%t_end) // '; dt is not used')
            call add('path steps: Riks''s predictor along the tangent at the last point ' // &
                '(oriented by the last secant, so the path turns back at a limit point), ' // &
                'then Newton on the equilibrium in the hyperplane normal to it; a step is ' // &
                'halved when Newton fails, when the corrector ends farther from its ' // &
                'predictor than the step (a jump to another branch) or when a section turns ' // &
                'by more than 0.5 rad')
            call add('bordered solves: the stepper''s LU (below) factors the Jacobian J ' // &
                'once at the step''s start (the tangent, J dY/dlambda = -R_lambda) and once ' // &
                'per Newton iteration, solved twice there, J a = -R and J b = -R_lambda ' // &
                '(R_lambda by a central difference in the load time), the load-time ' // &
                'increment from the arc-length row; the bordered matrix is never formed')
            switch = 'logged, the path goes on (branch_switch = .false.)'
            if (scene%time%branch_switch) switch = 'the path leaves the first one along its ' // &
                'mode (branch_switch)'
            call add('bifurcations: the critical eigenvalue of the stiffness condensed on ' // &
                'the nodes at every point by inverse iteration (3 solves of the tangent''s ' // &
                'factorization), a bifurcation where it changes sign with the load still ' // &
                'rising or falling; ' // switch)
            if (scene%time%equilibrium_solves) then
                call add('equilibrium: at t = 0 before the path (ph_director and planar ' // &
                    'rods; continued from the initial state); no endpoint solve: every path ' // &
                    'point is an equilibrium at its own load time')
            else
                call add('equilibrium: no solve at t = 0 (equilibrium_solves = .false.); no ' // &
                    'endpoint solve: every path point is an equilibrium at its own load time')
            end if
        end subroutine add_continuation_lines

        subroutine add(line)
            character(len=*), intent(in) :: line
            call append('!   ' // line // new_line('a'))
        end subroutine add

        !> A count that may exceed the default integer.
        function count_text(n) result(t)
            integer(int64), intent(in) :: n
            character(len=:), allocatable :: t
            character(len=24) :: digits
            write(digits, '(i0)') n
            t = trim(digits)
        end function count_text

        subroutine append(piece)
            character(len=*), intent(in) :: piece
            call buffer%append(piece)
        end subroutine append
    end function scene_plan_text

    !> An obstacle for the plan: its kind, place, stiffness, and that every rod touches it.
    function obstacle_line(obstacle) result(text)
        type(obstacle_input_t), intent(in) :: obstacle
        character(len=:), allocatable :: text
        text = 'obstacle ''' // trim(obstacle%name) // ''': '
        select case (trim(obstacle%kind))
        case ('plane')
            text = text // 'the ground, the plane through (' // vector_text(obstacle%point) // &
                ') m with outward normal (' // vector_text(obstacle%normal) // ')'
        case ('sphere')
            text = text // 'a sphere of radius ' // str(obstacle%radius) // ' m about (' // &
                vector_text(obstacle%point) // ') m'
        case default
            text = text // 'a cylinder of radius ' // str(obstacle%radius) // ' m about the ' // &
                'axis through (' // vector_text(obstacle%point) // ') m along (' // &
                vector_text(obstacle%normal) // ')'
        end select
        if (any(obstacle%displacement /= 0.0_rk)) then
            text = text // '; moving by f(t) (' // vector_text(obstacle%displacement) // &
                ') m, f = ''' // trim(obstacle%time_function) // ''''
        else
            text = text // '; fixed'
        end if
        text = text // ', stiffness ' // str(obstacle%stiffness) // ' N/m^3, '
        if (obstacle%mu > 0.0_rk) then
            text = text // 'friction mu = ' // str(obstacle%mu) // ' (regularized below ' // &
                str(obstacle%slip_velocity) // ' m/s)'
        else
            text = text // 'frictionless'
        end if
        if (obstacle%damping > 0.0_rk) text = text // ', normal damping alpha = ' // &
            str(obstacle%damping) // ' s/m (Hunt and Crossley)'
        text = text // '; every rod touches it with its contact_radius (&obstacle at line ' // &
            str(obstacle%input_line) // ')'
    end function obstacle_line

    !> The parts of rod i (&segment, issue 26 item 5): each segment's interval, elements and
    !> resolved stiffnesses and line mass; the rest of the rod keeps the &rod values.
    function segment_plan_lines(scene, i) result(text)
        type(scene_t), intent(in) :: scene
        integer, intent(in) :: i
        character(len=:), allocatable :: text
        real(rk) :: previous, element
        integer :: k
        text = ''
        associate (rod => scene%rods(i))
            if (rod_segment_count(scene, rod%name) == 0) return
            element = rod%length / real(rod%n_elements, rk)
            text = '!     varying along the rod: ' // str(rod_segment_count(scene, rod%name)) // &
                ' &segment groups (element boundaries at their ends)' // new_line('a')
            previous = 0.0_rk
            do k = 1, size(scene%segments)
                associate (seg => scene%segments(k))
                    if (seg%rod /= rod%name) cycle
                    text = text // '!       s in [' // str(previous) // ', ' // str(seg%s_end) // &
                        ']: elements ' // str(nint(previous / element) + 1) // ' to ' // &
                        str(nint(seg%s_end / element)) // ', EA = ' // str(seg%values(1)) // &
                        ', GA = ' // str(seg%values(2)) // ', ' // str(seg%values(3)) // &
                        ', EI = ' // str(seg%values(4)) // ', ' // str(seg%values(5)) // &
                        ', GJ = ' // str(seg%values(6)) // ', rhoA = ' // str(seg%values(7)) // &
                        new_line('a')
                    if (len_trim(seg%taper) > 0) text = text // '!         tapered ' // &
                        trim(seg%taper) // ' (values above at its start): ' // &
                        taper_text(seg%taper_dims) // ' at s_end; each element''s ' // &
                        'stiffnesses and inertias are those of its midpoint''s section' // &
                        new_line('a')
                    previous = seg%s_end
                end associate
            end do
            if (previous < rod%length - 0.5_rk * element) text = text // '!       s in [' // &
                str(previous) // ', ' // str(rod%length) // ']: elements ' // &
                str(nint(previous / element) + 1) // ' to ' // str(rod%n_elements) // &
                ', the &rod values' // new_line('a')
        end associate
    contains
        !> The dimensions of a taper that change, 'name start -> end'.
        function taper_text(dims) result(text)
            real(rk), intent(in) :: dims(4, 2)
            character(len=:), allocatable :: text
            character(len=12), parameter :: names(4) = [character(len=12) :: 'radius', &
                'inner_radius', 'width', 'height']
            integer :: j
            text = ''
            do j = 1, 4
                if (dims(j, 1) == 0.0_rk .and. dims(j, 2) == 0.0_rk) cycle
                if (len(text) > 0) text = text // ', '
                text = text // trim(names(j)) // ' ' // str(dims(j, 1)) // ' -> ' // str(dims(j, 2))
            end do
        end function taper_text
    end function segment_plan_lines

    !> Rod `i`'s prestretched start ('' without one; docs/theory/prestretched_starts.md): its
    !> prestrain with the stress-free length and the axial force it starts with, and its
    !> supports released at a time.
    function prestretched_plan_lines(scene, i) result(text)
        type(scene_t), intent(in) :: scene
        integer, intent(in) :: i
        character(len=:), allocatable :: text
        integer :: k
        text = ''
        associate (rod => scene%rods(i))
            if (rod%prestrain /= 0.0_rk) text = '!     prestrain ' // str(rod%prestrain) // &
                ': stress-free length ' // str(rod%length / (1.0_rk + rod%prestrain)) // &
                ' (given ' // str(rod%length) // '), axial force EA prestrain = ' // &
                str(rod%EA * rod%prestrain) // ' at the start; stiffnesses and inertias per ' // &
                'given length scaled by (1 + prestrain)^(+-1)' // new_line('a')
            do k = 1, size(scene%bcs)
                associate (bc => scene%bcs(k))
                    if (bc%rod /= rod%name .or. bc%release_time == unset_real) cycle
                    text = text // '!     released support: the ''' // trim(bc%end) // &
                        ''' end (' // trim(bc%kind) // ') held until t = ' // &
                        str(bc%release_time) // ', free after it (its unknowns held by ' // &
                        'their own rows until then)' // new_line('a')
                end associate
            end do
        end associate
    end function prestretched_plan_lines

    !> The sweep part of the plan ('' without &sweep): the number of members and how the sweeps
    !> combine, each swept variable with its number and range of values, and the values of the
    !> first three members and the last (DESIGN.md §5; rs_io_sweep builds the members).
    function sweep_plan_lines(scene) result(text)
        use rs_model_scene, only: sweep_input_t, sweep_member_count, sweep_member_indices, &
            sweep_values, sweep_value_count, unset_real
        type(scene_t), intent(in) :: scene
        character(len=:), allocatable :: text, blocks, how
        real(rk), allocatable :: values(:)
        integer, allocatable :: shown(:)
        integer :: s, n_members, n_blocks, k
        text = ''
        n_members = sweep_member_count(scene)
        if (n_members == 0) return
        blocks = ''
        n_blocks = 0
        do s = 1, size(scene%sweeps)
            if (s > 1 .and. trim(scene%sweeps(s)%mode) == 'zip') then
                blocks = blocks // ' zip ' // trim(scene%sweeps(s)%parameter)
                cycle
            end if
            if (n_blocks > 0) blocks = blocks // ') x '
            n_blocks = n_blocks + 1
            blocks = blocks // str(sweep_value_count(scene%sweeps(s))) // ' (' // &
                trim(scene%sweeps(s)%parameter)
        end do
        if (n_blocks > 1) then
            blocks = 'product of ' // blocks // ')'
        else
            blocks = blocks(1:index(blocks, ' (') - 1) // ' values of ' // &
                blocks(index(blocks, ' (') + 2:)
        end if
        text = '!   sweep: ' // str(n_members) // ' members (' // blocks // '), each the scene ' // &
            'with its values, checked and run as a scene of its own' // new_line('a')
        do s = 1, size(scene%sweeps)
            associate (sweep => scene%sweeps(s))
                values = sweep_values(sweep)
                if (all(sweep%linspace /= unset_real)) then
                    how = 'evenly spaced'
                else if (all(sweep%logspace /= unset_real)) then
                    how = 'geometrically spaced'
                else
                    how = 'as listed'
                end if
                text = text // '!     ' // trim(sweep%parameter) // ': ' // str(size(values)) // &
                    ' value(s) from ' // value_text(sweep, minval(values)) // ' to ' // &
                    value_text(sweep, maxval(values)) // ', ' // how // new_line('a')
            end associate
        end do
        if (n_members <= 4) then
            shown = [(k, k = 1, n_members)]
        else
            shown = [1, 2, 3, n_members]
        end if
        do k = 1, size(shown)
            if (k == 4 .and. n_members > 4) text = text // '!     ...' // new_line('a')
            text = text // '!     member ' // str(shown(k)) // ': ' // member_text(shown(k)) // &
                new_line('a')
        end do
    contains
        !> "rod(1)%EI1 = 2.5, time%dt = 0.01" for member `id`.
        function member_text(id) result(line)
            integer, intent(in) :: id
            character(len=:), allocatable :: line
            integer, allocatable :: indices(:)
            real(rk), allocatable :: member_values(:)
            integer :: j
            indices = sweep_member_indices(scene%sweeps, id)
            line = ''
            do j = 1, size(scene%sweeps)
                member_values = sweep_values(scene%sweeps(j))
                if (j > 1) line = line // ', '
                line = line // trim(scene%sweeps(j)%parameter) // ' = ' // &
                    value_text(scene%sweeps(j), member_values(indices(j)))
            end do
        end function member_text

        function value_text(sweep, value) result(out)
            type(sweep_input_t), intent(in) :: sweep
            real(rk), intent(in) :: value
            character(len=:), allocatable :: out
            if (sweep%integral) then
                out = str(nint(value))
            else
                out = str(value)
            end if
        end function value_text
    end function sweep_plan_lines

end module rs_formulations_plan
