!> Reads scene text into the plain scene type (DESIGN.md §6). Each assignment of each group is
!> checked against the tables of rs_io_input_spec (name, number of values, allowed values,
!> range) and then read on its own through a namelist whose object is the group's plain type,
!> `&rod_nml rod_copy%n_elements = 10 /`, so a wrong value is reported with its file, line, group
!> and variable, and every problem of the file is collected before anything stops.
module rs_io_input_reader
    use rs_core_kinds, only: rk
    use rs_core_error, only: error_list_t
    use rs_core_strings, only: to_lower, str, closest_name, did_you_mean, split_list
    use rs_model_scene, only: scene_t, run_input_t, time_input_t, solver_input_t, output_input_t, &
        rod_input_t, bc_input_t, load_input_t, actuator_input_t, joint_input_t, plate_input_t, &
        contact_input_t, sweep_input_t, obstacle_input_t, segment_input_t, &
        modes_input_t
    use rs_io_namelist_lexer, only: assignment_t, group_chunk_t, split_namelist
    use rs_io_input_spec, only: group_spec_t, variable_spec_t, input_groups, find_group, find_variable, &
        range_description, in_range, split_condition, group_names, variable_names
    implicit none
    private

    public :: read_scene_text

contains

    !> Fill `scene` from `text` (the contents of `file`); every problem is added to `errors`.
    !> Values are as given (defaults where not given); resolution and cross-checks follow in
    !> rs_io_input_check.
    subroutine read_scene_text(text, file, scene, errors)
        character(len=*), intent(in) :: text, file
        type(scene_t), intent(out) :: scene
        type(error_list_t), intent(inout) :: errors
        type(group_spec_t), allocatable :: groups(:)
        type(group_chunk_t), allocatable :: chunks(:)
        integer, allocatable :: first_line(:)
        integer :: c, g
        !> Occurrences read of each repeatable group (rod, bc, load, actuator, joint, plate, sweep,
        !> obstacle, segment).
        integer :: n_read(9)

        scene%source_file = file
        scene%source_text = text
        groups = input_groups()
        allocate(first_line(size(groups)))
        first_line = 0
        call split_namelist(text, file, chunks, errors)
        call allocate_repeatable(chunks, scene, n_read)

        do c = 1, size(chunks)
            g = find_group(groups, chunks(c)%name)
            if (g == 0) then
                call errors%add(file // ':' // str(chunks(c)%line) // ': unknown group &' // &
                    chunks(c)%name // did_you_mean(chunks(c)%name, group_names(groups)) // &
                    '; groups are ' // list_of(group_names(groups)))
                cycle
            end if
            if (.not. groups(g)%implemented) then
                call errors%add(file // ':' // str(chunks(c)%line) // ': the group &' // chunks(c)%name // &
                    ' is not available in this version of rodsolve (docs/user/capabilities.md)')
                cycle
            end if
            if (.not. groups(g)%repeatable .and. first_line(g) > 0) then
                call errors%add(file // ':' // str(chunks(c)%line) // ': &' // chunks(c)%name // &
                    ' is given twice (first at line ' // str(first_line(g)) // '); it may appear once')
                cycle
            end if
            if (first_line(g) == 0) first_line(g) = chunks(c)%line
            call read_chunk(chunks(c), groups(g), file, scene, n_read, errors)
        end do
        call trim_repeatable(scene, n_read)
    end subroutine read_scene_text

    !> Room for every occurrence of each repeatable group, counted before reading, so that
    !> reading stays linear in the number of groups (issue 21 item 17: appending one &load to a
    !> copy of all the loads before it made 4,000 of them take 45 s). trim_repeatable cuts the
    !> arrays to what was read.
    subroutine allocate_repeatable(chunks, scene, n_read)
        type(group_chunk_t), intent(in) :: chunks(:)
        type(scene_t), intent(inout) :: scene
        integer, intent(out) :: n_read(9)
        allocate(scene%rods(occurrences('rod')), scene%bcs(occurrences('bc')), &
            scene%loads(occurrences('load')), scene%actuators(occurrences('actuator')), &
            scene%joints(occurrences('joint')), scene%plates(occurrences('plate')), &
            scene%sweeps(occurrences('sweep')), scene%obstacles(occurrences('obstacle')), &
            scene%segments(occurrences('segment')))
        n_read = 0
    contains
        integer function occurrences(name)
            character(len=*), intent(in) :: name
            integer :: c
            occurrences = 0
            do c = 1, size(chunks)
                if (chunks(c)%name == name) occurrences = occurrences + 1
            end do
        end function occurrences
    end subroutine allocate_repeatable

    !> Cut the arrays of repeatable groups to the occurrences read (a group given in a version
    !> that does not have it is counted but not read).
    subroutine trim_repeatable(scene, n_read)
        type(scene_t), intent(inout) :: scene
        integer, intent(in) :: n_read(9)
        if (size(scene%rods) > n_read(1)) scene%rods = scene%rods(1:n_read(1))
        if (size(scene%bcs) > n_read(2)) scene%bcs = scene%bcs(1:n_read(2))
        if (size(scene%loads) > n_read(3)) scene%loads = scene%loads(1:n_read(3))
        if (size(scene%actuators) > n_read(4)) scene%actuators = scene%actuators(1:n_read(4))
        if (size(scene%joints) > n_read(5)) scene%joints = scene%joints(1:n_read(5))
        if (size(scene%plates) > n_read(6)) scene%plates = scene%plates(1:n_read(6))
        if (size(scene%sweeps) > n_read(7)) scene%sweeps = scene%sweeps(1:n_read(7))
        if (size(scene%obstacles) > n_read(8)) scene%obstacles = scene%obstacles(1:n_read(8))
        if (size(scene%segments) > n_read(9)) scene%segments = scene%segments(1:n_read(9))
    end subroutine trim_repeatable

    !> Check and read the assignments of one group occurrence into its place in `scene`
    !> (the next of its kind after the n_read already read).
    subroutine read_chunk(chunk, group, file, scene, n_read, errors)
        type(group_chunk_t), intent(in) :: chunk
        type(group_spec_t), intent(in) :: group
        character(len=*), intent(in) :: file
        type(scene_t), intent(inout) :: scene
        integer, intent(inout) :: n_read(9)
        type(error_list_t), intent(inout) :: errors
        type(rod_input_t) :: rod
        type(bc_input_t) :: bc
        type(load_input_t) :: load
        type(actuator_input_t) :: actuator
        type(joint_input_t) :: joint
        type(plate_input_t) :: plate
        type(sweep_input_t) :: sweep
        type(obstacle_input_t) :: obstacle
        type(segment_input_t) :: segment
        logical, allocatable :: given(:)
        character(len=:), allocatable :: where, value, message
        integer :: k, v, ios

        allocate(given(size(group%variables)))
        given = .false.
        rod%input_line = chunk%line
        bc%input_line = chunk%line
        load%input_line = chunk%line
        actuator%input_line = chunk%line
        joint%input_line = chunk%line
        plate%input_line = chunk%line
        sweep%input_line = chunk%line
        obstacle%input_line = chunk%line
        segment%input_line = chunk%line
        ! The single &time lives in `scene`: its line places the messages about its scheme.
        if (group%name == 'time') scene%time%input_line = chunk%line
        if (group%name == 'modes') then
            ! The single &modes lives in `scene`; its presence asks for the modes.
            scene%modes%given = .true.
            scene%modes%input_line = chunk%line
        end if
        if (group%name == 'contact') then
            ! The single &contact lives in `scene`; its presence turns contact on.
            scene%contact%given = .true.
            scene%contact%input_line = chunk%line
        end if
        do k = 1, size(chunk%assignments)
            associate (a => chunk%assignments(k))
                v = find_variable(group, a%name)
                if (v == 0) then
                    call errors%add(file // ':' // str(a%line) // ': &' // chunk%name // ': unknown variable "' // &
                        a%name // '"' // did_you_mean(a%name, variable_names(group)))
                    cycle
                end if
                ! Named as the reference spells it (maxwell_tau_E, EA), as the cross-checks do.
                where = file // ':' // str(a%line) // ': &' // chunk%name // ' ' // &
                    trim(group%variables(v)%name) // ': '
                if (given(v)) then
                    call errors%add(where // 'given twice in one group')
                    cycle
                end if
                given(v) = .true.
                call check_value(a, group%variables(v), value, message)
                if (len(message) > 0) then
                    call errors%add(where // message)
                    cycle
                end if
                call read_assignment(trim(group%name), a%target, value, scene, rod, bc, load, &
                    actuator, joint, plate, sweep, obstacle, segment, ios, message)
                if (ios /= 0) call errors%add(where // 'cannot read "' // a%value // '" as ' // &
                    kind_phrase(group%variables(v)) // ' (' // trim(message) // ')')
            end associate
        end do
        do v = 1, size(group%variables)
            if (group%variables(v)%required .and. .not. given(v)) call errors%add(file // ':' // &
                str(chunk%line) // ': &' // chunk%name // ' ' // trim(group%variables(v)%name) // &
                ': required but not given')
        end do
        call check_conditions(chunk, group, file, given, errors)
        ! Into the places allocate_repeatable made, in file order.
        select case (group%name)
        case ('rod')
            n_read(1) = n_read(1) + 1
            scene%rods(n_read(1)) = rod
        case ('bc')
            n_read(2) = n_read(2) + 1
            scene%bcs(n_read(2)) = bc
        case ('load')
            n_read(3) = n_read(3) + 1
            scene%loads(n_read(3)) = load
        case ('actuator')
            n_read(4) = n_read(4) + 1
            scene%actuators(n_read(4)) = actuator
        case ('joint')
            n_read(5) = n_read(5) + 1
            scene%joints(n_read(5)) = joint
        case ('plate')
            n_read(6) = n_read(6) + 1
            scene%plates(n_read(6)) = plate
        case ('sweep')
            n_read(7) = n_read(7) + 1
            scene%sweeps(n_read(7)) = sweep
        case ('obstacle')
            n_read(8) = n_read(8) + 1
            scene%obstacles(n_read(8)) = obstacle
        case ('segment')
            n_read(9) = n_read(9) + 1
            scene%segments(n_read(9)) = segment
        end select
    end subroutine read_chunk

    !> The conditional variables of one group occurrence: one with `required_if` is required
    !> when its condition holds, one with `only_if` may be given only when its condition holds
    !> (e.g. helix_radius with geometry = 'helix'). A condition 'variable=value' holds when
    !> `variable` is given with that value, or not given and that value is its default.
    subroutine check_conditions(chunk, group, file, given, errors)
        type(group_chunk_t), intent(in) :: chunk
        type(group_spec_t), intent(in) :: group
        character(len=*), intent(in) :: file
        logical, intent(in) :: given(:)
        type(error_list_t), intent(inout) :: errors
        character(len=:), allocatable :: name, wanted, actual
        integer :: v, k
        do v = 1, size(group%variables)
            associate (spec => group%variables(v))
                if (len_trim(spec%required_if) > 0 .and. .not. given(v)) then
                    call condition_values(spec%required_if, name, wanted, actual)
                    if (actual == wanted) call errors%add(file // ':' // str(chunk%line) // ': &' // &
                        chunk%name // ' ' // trim(spec%name) // ': required but not given (' // &
                        name // " = '" // wanted // "')")
                end if
                if (len_trim(spec%only_if) > 0 .and. given(v)) then
                    call condition_values(spec%only_if, name, wanted, actual)
                    if (actual == wanted) cycle
                    do k = 1, size(chunk%assignments)
                        if (to_lower(chunk%assignments(k)%name) /= to_lower(trim(spec%name))) cycle
                        call errors%add(file // ':' // str(chunk%assignments(k)%line) // ': &' // &
                            chunk%name // ' ' // trim(spec%name) // ': only used with ' // name // &
                            " = '" // wanted // "' (here " // name // " = '" // actual // &
                            "'); remove it or set " // name // " = '" // wanted // "'")
                        exit
                    end do
                end if
            end associate
        end do
    contains
        !> The variable and wanted value of `condition` and the variable's value in this chunk.
        subroutine condition_values(condition, name, wanted, actual)
            character(len=*), intent(in) :: condition
            character(len=:), allocatable, intent(out) :: name, wanted, actual
            integer :: c, j
            call split_condition(condition, name, wanted)
            c = find_variable(group, name)
            actual = to_lower(unquote(trim(group%variables(c)%default_text)))
            do j = 1, size(chunk%assignments)
                if (to_lower(chunk%assignments(j)%name) == name) actual = &
                    to_lower(unquote(trim(chunk%assignments(j)%value)))
            end do
        end subroutine condition_values
    end subroutine check_conditions

    !> Generic checks of one assignment against its spec; `value` is the text handed to the
    !> namelist reader (allowed strings folded to lower case), `message` is '' when all is well.
    subroutine check_value(a, spec, value, message)
        type(assignment_t), intent(in) :: a
        type(variable_spec_t), intent(in) :: spec
        character(len=:), allocatable, intent(out) :: value, message
        real(rk), allocatable :: numbers(:)
        character(len=:), allocatable :: text
        integer :: ios, i

        value = a%value
        message = ''
        if (a%n_values == 0) then
            message = 'no value given'
            return
        end if
        if (spec%kind == 'string' .and. spec%max_count == 1 .and. &
                (a%n_values /= 1 .or. .not. is_quoted(a%value))) then
            message = 'expects one quoted string, e.g. ''text'' (given: ' // a%value // ')'
            return
        end if
        if (spec%kind == 'string' .and. spec%max_count > 1 .and. .not. all_quoted(a%value)) then
            message = 'expects quoted strings separated by commas, e.g. ''a'', ''b'' (given: ' // &
                a%value // ')'
            return
        end if
        if (a%subscripted) then
            ! The namelist reader would name its internal copy (load_copy%table_times).
            message = subscript_problem(a%target, a%n_values, spec%max_count)
            if (len(message) > 0) return
        end if
        if (.not. a%subscripted) then
            if (a%n_values < spec%min_count .or. a%n_values > spec%max_count) then
                if (spec%min_count == spec%max_count) then
                    message = 'expects ' // str(spec%min_count) // ' value(s), ' // str(a%n_values) // ' given'
                else
                    message = 'expects ' // str(spec%min_count) // ' to ' // str(spec%max_count) // &
                        ' values, ' // str(a%n_values) // ' given'
                end if
                return
            end if
        end if
        select case (spec%kind)
        case ('string')
            if (len_trim(spec%allowed) > 0 .and. spec%max_count == 1) then
                text = to_lower(unquote(a%value))
                if (.not. is_allowed(text, spec%allowed)) then
                    message = '"' // unquote(a%value) // '" is not allowed; allowed: ' // &
                        allowed_list(spec%allowed) // did_you_mean(text, split_list(spec%allowed))
                    return
                end if
                value = "'" // text // "'"
            else if (len_trim(spec%allowed) > 0) then
                call check_entries(a%value, spec%allowed, value, message)
                if (len(message) > 0) return
            end if
        case ('logical')
            ! The namelist reader takes any word after a '.' that starts with t or f
            ! (.FALSE_not is false): only the spellings Fortran means pass here.
            text = to_lower(trim(adjustl(a%value)))
            if (.not. any(text == [character(len=7) :: '.true.', '.false.', '.t.', '.f.', 't', &
                    'f', 'true', 'false'])) then
                message = '"' // trim(a%value) // '" is not a logical; allowed: .true. or .false.'
                return
            end if
        case ('integer', 'real')
            allocate(numbers(a%n_values))
            read(a%value, *, iostat=ios) numbers
            if (ios /= 0) return   ! the namelist read reports the type error
            do i = 1, size(numbers)
                if (.not. in_range(spec, numbers(i))) then
                    message = 'value ' // a%value // ' out of range; allowed: ' // range_description(spec)
                    return
                end if
            end do
        end select
    end subroutine check_value

    !> '' if `target` = name(first) or name(first:last) with `n_values` values stays within
    !> indices 1 .. `max_count`; otherwise what is wrong, in the reference's terms.
    function subscript_problem(target, n_values, max_count) result(message)
        character(len=*), intent(in) :: target
        integer, intent(in) :: n_values, max_count
        character(len=:), allocatable :: message
        character(len=:), allocatable :: inside
        integer :: open_at, close_at, colon, first, last, ios
        message = ''
        open_at = index(target, '(')
        close_at = index(target, ')', back=.true.)
        if (close_at <= open_at + 1) return   ! the namelist read reports a malformed one
        inside = target(open_at + 1:close_at - 1)
        colon = index(inside, ':')
        if (colon > 0) then
            read(inside(1:colon - 1), *, iostat=ios) first
            if (ios == 0) read(inside(colon + 1:), *, iostat=ios) last
        else
            read(inside, *, iostat=ios) first
            last = first + n_values - 1
        end if
        if (ios /= 0) return
        if (first >= 1 .and. last <= max_count .and. last >= first) return
        message = 'index ' // trim(inside) // ' with ' // str(n_values) // ' value(s) is out ' // &
            'of range; allowed: indices 1 to ' // str(max_count)
    end function subscript_problem

    !> Read `target = value` of group `group` through a namelist whose object is a copy of the
    !> group's plain type (`&rod_nml rod%target = value /`), so only that component changes; the
    !> single groups live in `scene`, the occurrence of a repeatable group being read in `rod`,
    !> `bc`, `load`, `actuator`, `joint`, `plate` or `sweep`. On failure nothing changes. All
    !> namelists live in this one procedure, so no group name may equal an object name (hence
    !> the `_nml` suffix).
    subroutine read_assignment(group, target, value, scene, rod, bc, load, actuator, joint, plate, &
            sweep, obstacle, segment, ios, message)
        character(len=*), intent(in) :: group, target, value
        type(scene_t), intent(inout) :: scene
        type(rod_input_t), intent(inout) :: rod
        type(bc_input_t), intent(inout) :: bc
        type(load_input_t), intent(inout) :: load
        type(actuator_input_t), intent(inout) :: actuator
        type(joint_input_t), intent(inout) :: joint
        type(plate_input_t), intent(inout) :: plate
        type(sweep_input_t), intent(inout) :: sweep
        type(obstacle_input_t), intent(inout) :: obstacle
        type(segment_input_t), intent(inout) :: segment
        integer, intent(out) :: ios
        character(len=:), allocatable, intent(out) :: message
        type(run_input_t) :: run_copy
        type(time_input_t) :: time_copy
        type(solver_input_t) :: solver_copy
        type(output_input_t) :: output_copy
        type(rod_input_t) :: rod_copy
        type(bc_input_t) :: bc_copy
        type(load_input_t) :: load_copy
        type(actuator_input_t) :: actuator_copy
        type(joint_input_t) :: joint_copy
        type(plate_input_t) :: plate_copy
        type(contact_input_t) :: contact_copy
        type(sweep_input_t) :: sweep_copy
        type(obstacle_input_t) :: obstacle_copy
        type(segment_input_t) :: segment_copy
        type(modes_input_t) :: modes_copy
        namelist /run_nml/ run_copy
        namelist /time_nml/ time_copy
        namelist /solver_nml/ solver_copy
        namelist /output_nml/ output_copy
        namelist /rod_nml/ rod_copy
        namelist /bc_nml/ bc_copy
        namelist /load_nml/ load_copy
        namelist /actuator_nml/ actuator_copy
        namelist /joint_nml/ joint_copy
        namelist /plate_nml/ plate_copy
        namelist /contact_nml/ contact_copy
        namelist /sweep_nml/ sweep_copy
        namelist /obstacle_nml/ obstacle_copy
        namelist /segment_nml/ segment_copy
        namelist /modes_nml/ modes_copy
        character(len=256) :: msg
        character(len=:), allocatable :: buffer

        ! Only the group being read is copied in and out: a copy of every group type per
        ! assignment (a &sweep alone holds 32 KB) made large scenes slow to read.
        msg = ''
        buffer = '&' // group // '_nml ' // group // '_copy%' // target // ' = ' // value // ' /'
        select case (group)
        case ('run')
            run_copy = scene%run
            read(buffer, nml=run_nml, iostat=ios, iomsg=msg)
            if (ios == 0) scene%run = run_copy
        case ('time')
            time_copy = scene%time
            read(buffer, nml=time_nml, iostat=ios, iomsg=msg)
            if (ios == 0) scene%time = time_copy
        case ('solver')
            solver_copy = scene%solver
            read(buffer, nml=solver_nml, iostat=ios, iomsg=msg)
            if (ios == 0) scene%solver = solver_copy
        case ('output')
            output_copy = scene%output
            read(buffer, nml=output_nml, iostat=ios, iomsg=msg)
            if (ios == 0) scene%output = output_copy
        case ('rod')
            rod_copy = rod
            read(buffer, nml=rod_nml, iostat=ios, iomsg=msg)
            if (ios == 0) rod = rod_copy
        case ('bc')
            bc_copy = bc
            read(buffer, nml=bc_nml, iostat=ios, iomsg=msg)
            if (ios == 0) bc = bc_copy
        case ('load')
            load_copy = load
            read(buffer, nml=load_nml, iostat=ios, iomsg=msg)
            if (ios == 0) load = load_copy
        case ('actuator')
            actuator_copy = actuator
            read(buffer, nml=actuator_nml, iostat=ios, iomsg=msg)
            if (ios == 0) actuator = actuator_copy
        case ('joint')
            joint_copy = joint
            read(buffer, nml=joint_nml, iostat=ios, iomsg=msg)
            if (ios == 0) joint = joint_copy
        case ('plate')
            plate_copy = plate
            read(buffer, nml=plate_nml, iostat=ios, iomsg=msg)
            if (ios == 0) plate = plate_copy
        case ('contact')
            contact_copy = scene%contact
            read(buffer, nml=contact_nml, iostat=ios, iomsg=msg)
            if (ios == 0) scene%contact = contact_copy
        case ('sweep')
            sweep_copy = sweep
            read(buffer, nml=sweep_nml, iostat=ios, iomsg=msg)
            if (ios == 0) sweep = sweep_copy
        case ('obstacle')
            obstacle_copy = obstacle
            read(buffer, nml=obstacle_nml, iostat=ios, iomsg=msg)
            if (ios == 0) obstacle = obstacle_copy
        case ('segment')
            segment_copy = segment
            read(buffer, nml=segment_nml, iostat=ios, iomsg=msg)
            if (ios == 0) segment = segment_copy
        case ('modes')
            modes_copy = scene%modes
            read(buffer, nml=modes_nml, iostat=ios, iomsg=msg)
            if (ios == 0) scene%modes = modes_copy
        case default
            ios = -1
            msg = 'no reader for group &' // group
        end select
        message = trim(msg)
    end subroutine read_assignment

    ! --- message helpers ---------------------------------------------------------------------

    pure logical function is_quoted(text)
        character(len=*), intent(in) :: text
        integer :: n
        n = len_trim(text)
        is_quoted = .false.
        if (n >= 2) is_quoted = (text(1:1) == "'" .and. text(n:n) == "'") .or. &
            (text(1:1) == '"' .and. text(n:n) == '"')
    end function is_quoted

    !> True if every value of the value text `text` (separated by commas or blanks outside
    !> quotes) is a quoted string; repeat counts (3*'a') are not taken for strings.
    pure logical function all_quoted(text)
        character(len=*), intent(in) :: text
        character :: quote
        integer :: i, n
        logical :: in_token, token_quoted
        all_quoted = .true.
        quote = ' '
        in_token = .false.
        token_quoted = .false.
        n = len_trim(text)
        i = 0
        do while (i < n)
            i = i + 1
            if (quote /= ' ') then
                if (text(i:i) /= quote) cycle
                ! A doubled quote stands for one quote inside the string.
                if (i < n) then
                    if (text(i + 1:i + 1) == quote) then
                        i = i + 1
                        cycle
                    end if
                end if
                quote = ' '
                cycle
            end if
            select case (text(i:i))
            case (',', ' ')
                if (in_token .and. .not. token_quoted) all_quoted = .false.
                in_token = .false.
            case ('''', '"')
                ! A quote must open its token (it may not follow other characters).
                if (in_token) all_quoted = .false.
                quote = text(i:i)
                in_token = .true.
                token_quoted = .true.
            case default
                if (in_token .and. token_quoted) all_quoted = .false.
                if (.not. in_token) token_quoted = .false.
                in_token = .true.
            end select
        end do
        if (in_token .and. .not. token_quoted) all_quoted = .false.
        if (quote /= ' ') all_quoted = .false.
    end function all_quoted

    !> Each quoted entry of `text` (quoted strings separated by commas, all_quoted) is one of
    !> the '|'-separated names `allowed`, compared without case; `value` is the entries in the
    !> spelling of `allowed`, `message` what is wrong with the first entry that is not ('' when
    !> all are).
    pure subroutine check_entries(text, allowed, value, message)
        character(len=*), intent(in) :: text, allowed
        character(len=:), allocatable, intent(out) :: value, message
        character(len=32), allocatable :: names(:)
        character(len=:), allocatable :: entry
        integer :: i, first, j
        names = split_list(allowed)
        value = ''
        message = ''
        i = 0
        do while (i < len_trim(text))
            i = i + 1
            if (text(i:i) /= '''' .and. text(i:i) /= '"') cycle
            first = i + 1
            i = index(text(first:), text(first - 1:first - 1)) + first - 1
            if (i < first) i = len_trim(text) + 1
            entry = text(first:i - 1)
            j = findloc([(to_lower(trim(names(j))) == to_lower(entry), j = 1, size(names))], &
                .true., 1)
            if (j == 0) then
                message = '"' // entry // '" is not allowed; allowed: ' // allowed_list(allowed) // &
                    did_you_mean(to_lower(entry), split_list(allowed))
                return
            end if
            if (len(value) > 0) value = value // ', '
            value = value // "'" // trim(names(j)) // "'"
        end do
    end subroutine check_entries

    pure function unquote(text) result(out)
        character(len=*), intent(in) :: text
        character(len=:), allocatable :: out
        out = trim(text)
        if (is_quoted(out)) out = out(2:len(out) - 1)
    end function unquote

    pure logical function is_allowed(text, allowed)
        character(len=*), intent(in) :: text, allowed
        is_allowed = index('|' // trim(allowed) // '|', '|' // trim(text) // '|') > 0
    end function is_allowed

    pure function allowed_list(allowed) result(text)
        character(len=*), intent(in) :: allowed
        character(len=:), allocatable :: text
        character(len=32), allocatable :: names(:)
        integer :: i
        names = split_list(allowed)
        text = ''
        do i = 1, size(names)
            if (i > 1) text = text // ', '
            text = text // "'" // trim(names(i)) // "'"
        end do
    end function allowed_list

    pure function kind_phrase(spec) result(text)
        type(variable_spec_t), intent(in) :: spec
        character(len=:), allocatable :: text
        select case (spec%kind)
        case ('integer')
            text = 'integer'
        case ('real')
            text = 'real number'
        case ('logical')
            text = 'logical (.true. or .false.)'
        case default
            text = 'quoted string'
        end select
        if (spec%max_count > 1) text = text // 's'
    end function kind_phrase




    pure function list_of(names) result(text)
        character(len=*), intent(in) :: names(:)
        character(len=:), allocatable :: text
        integer :: i
        text = ''
        do i = 1, size(names)
            if (i > 1) text = text // ', '
            text = text // '&' // trim(names(i))
        end do
    end function list_of

end module rs_io_input_reader
