!> The resolved scene as namelist text (DESIGN.md §6, STYLE.md item 13): every group with every
!> variable, defaults and derived values included, in a form rodsolve reads back to the same
!> scene. Printed by `--check-input` and stored in the output as /input/resolved.
!>
!> Each group is written with Fortran's namelist output (so no variable can be forgotten) and
!> then tidied: component prefixes dropped, names in the reference's spelling, reals in their
!> shortest exact form, padding inside strings removed, variables that are still unset,
!> variables whose only_if condition does not hold (helix_phase of a straight rod) and
!> components that are not input variables left out. &contact is written when it was given.
module rs_io_scene_writer
    use rs_core_kinds, only: rk
    use rs_core_strings, only: to_lower, str
    use rs_io_input_spec, only: group_spec_t, input_groups, find_group, find_variable, split_condition
    use rs_model_scene, only: section_derived_names, scene_t, run_input_t, time_input_t, solver_input_t, output_input_t, &
        rod_input_t, bc_input_t, load_input_t, actuator_input_t, joint_input_t, plate_input_t, &
        contact_input_t, sweep_input_t, sweep_values, obstacle_input_t, segment_input_t, &
        modes_input_t
    implicit none
    private

    public :: resolved_scene_text

    integer, parameter :: max_lines = 400
    integer, parameter :: line_len = 4096

    !> One variable of a group as gfortran wrote it: its index in the group's spec, raw value.
    type :: entry_t
        integer :: variable = 0
        character(len=:), allocatable :: value
    end type entry_t

contains

    !> The whole scene as namelist text, one group after the other.
    function resolved_scene_text(scene) result(text)
        type(scene_t), intent(in) :: scene
        character(len=:), allocatable :: text
        character(len=line_len), allocatable :: lines(:)
        type(run_input_t) :: run
        type(time_input_t) :: time
        type(solver_input_t) :: solver
        type(output_input_t) :: output
        type(rod_input_t) :: rod
        type(bc_input_t) :: bc
        type(load_input_t) :: load
        type(actuator_input_t) :: actuator
        type(joint_input_t) :: joint
        type(plate_input_t) :: plate
        type(contact_input_t) :: contact
        type(obstacle_input_t) :: obstacle
        type(segment_input_t) :: segment
        type(modes_input_t) :: modes
        namelist /run_nml/ run
        namelist /time_nml/ time
        namelist /solver_nml/ solver
        namelist /output_nml/ output
        namelist /rod_nml/ rod
        namelist /bc_nml/ bc
        namelist /load_nml/ load
        namelist /actuator_nml/ actuator
        namelist /joint_nml/ joint
        namelist /plate_nml/ plate
        namelist /contact_nml/ contact
        namelist /obstacle_nml/ obstacle
        namelist /segment_nml/ segment
        namelist /modes_nml/ modes
        integer :: i

        ! Each group's text ends at its '/' line (tidy_group reads no further), so the lines
        ! are blanked once, not per group: 400 lines of 4096 characters per group was most of
        ! the time of a small sweep member's resolved scene.
        allocate(lines(max_lines))
        lines = ''
        text = '! resolved scene of ' // scene%source_file // ' (defaults and derived values included)' // &
            new_line('a')
        run = scene%run
        write(lines, nml=run_nml, delim='apostrophe')
        text = text // tidy_group('run', lines)
        time = scene%time
        write(lines, nml=time_nml, delim='apostrophe')
        text = text // tidy_group('time', lines)
        solver = scene%solver
        write(lines, nml=solver_nml, delim='apostrophe')
        text = text // tidy_group('solver', lines)
        output = scene%output
        write(lines, nml=output_nml, delim='apostrophe')
        text = text // tidy_group('output', lines)
        do i = 1, size(scene%rods)
            rod = scene%rods(i)
            write(lines, nml=rod_nml, delim='apostrophe')
            text = text // section_values_as_comments(tidy_group('rod', lines), rod%section)
        end do
        do i = 1, size(scene%bcs)
            bc = scene%bcs(i)
            write(lines, nml=bc_nml, delim='apostrophe')
            text = text // tidy_group('bc', lines)
        end do
        do i = 1, size(scene%loads)
            load = scene%loads(i)
            write(lines, nml=load_nml, delim='apostrophe')
            text = text // tidy_group('load', lines)
        end do
        if (allocated(scene%actuators)) then
            do i = 1, size(scene%actuators)
                actuator = scene%actuators(i)
                write(lines, nml=actuator_nml, delim='apostrophe')
                text = text // tidy_group('actuator', lines)
            end do
        end if
        if (allocated(scene%joints)) then
            do i = 1, size(scene%joints)
                joint = scene%joints(i)
                write(lines, nml=joint_nml, delim='apostrophe')
                text = text // tidy_group('joint', lines)
            end do
        end if
        if (allocated(scene%plates)) then
            do i = 1, size(scene%plates)
                plate = scene%plates(i)
                write(lines, nml=plate_nml, delim='apostrophe')
                text = text // tidy_group('plate', lines)
            end do
        end if
        if (scene%contact%given) then
            contact = scene%contact
            write(lines, nml=contact_nml, delim='apostrophe')
            text = text // tidy_group('contact', lines)
        end if
        if (scene%modes%given) then
            modes = scene%modes
            write(lines, nml=modes_nml, delim='apostrophe')
            text = text // tidy_group('modes', lines)
        end if
        if (allocated(scene%obstacles)) then
            do i = 1, size(scene%obstacles)
                obstacle = scene%obstacles(i)
                write(lines, nml=obstacle_nml, delim='apostrophe')
                text = text // tidy_group('obstacle', lines)
            end do
        end if
        if (allocated(scene%segments)) then
            do i = 1, size(scene%segments)
                segment = scene%segments(i)
                write(lines, nml=segment_nml, delim='apostrophe')
                text = text // segment_values_as_comments(tidy_group('segment', lines), segment)
            end do
        end if
        if (allocated(scene%sweeps)) then
            ! The resolved values themselves (a linspace or logspace written out), one per line.
            do i = 1, size(scene%sweeps)
                text = text // sweep_group_text(scene%sweeps(i))
            end do
        end if
    end function resolved_scene_text

    !> A resolved &sweep group: its canonical path, mode and every value.
    function sweep_group_text(sweep) result(text)
        type(sweep_input_t), intent(in) :: sweep
        character(len=:), allocatable :: text
        real(rk), allocatable :: values(:)
        character(len=32) :: number
        integer :: j
        values = sweep_values(sweep)
        text = '&sweep' // new_line('a') // '    parameter = ''' // trim(sweep%parameter) // '''' // &
            new_line('a') // '    mode = ''' // trim(sweep%mode) // '''' // new_line('a') // &
            '    values ='
        do j = 1, size(values)
            write(number, '(es24.16e3)') values(j)
            text = text // ' ' // trim(adjustl(number))
            if (j < size(values)) text = text // ','
            if (j < size(values) .and. mod(j, 4) == 0) text = text // new_line('a') // '        '
        end do
        text = text // new_line('a') // '/' // new_line('a')
    end function sweep_group_text

    !> With a section, the stiffnesses it determines are shown as comments: given again next
    !> to the section they would be an input error (either section or stiffnesses).
    function section_values_as_comments(group_text, section) result(text)
        character(len=*), intent(in) :: group_text, section
        character(len=:), allocatable :: text
        integer :: start, eol, k
        character(len=:), allocatable :: line
        if (trim(section) == 'none') then
            text = group_text
            return
        end if
        text = ''
        start = 1
        do while (start <= len(group_text))
            eol = index(group_text(start:), new_line('a'))
            if (eol == 0) eol = len(group_text) - start + 2
            line = group_text(start:start + eol - 2)
            do k = 1, size(section_derived_names)
                if (index(line, '    ' // trim(section_derived_names(k)) // ' = ') == 1) then
                    line = '    ! ' // line(5:) // '   (from the section)'
                    exit
                end if
            end do
            text = text // line // new_line('a')
            start = start + eol
        end do
    end function section_values_as_comments

    !> A resolved &segment with its resolved values (rs_model_scene segment_input_t values) as
    !> comments before its '/': they are derived, not input.
    function segment_values_as_comments(group_text, segment) result(text)
        character(len=*), intent(in) :: group_text
        type(segment_input_t), intent(in) :: segment
        character(len=:), allocatable :: text
        integer :: k
        character(len=32) :: number
        text = group_text(1:len(group_text) - 2)
        if (segment%values(1) /= huge(1.0_rk)) then
            do k = 1, size(section_derived_names)
                write(number, '(es24.16e3)') segment%values(k)
                text = text // '    ! ' // trim(section_derived_names(k)) // ' = ' // &
                    trim(adjustl(number)) // '   (resolved)' // new_line('a')
            end do
        end if
        text = text // '/' // new_line('a')
    end function segment_values_as_comments

    !> Turn gfortran's namelist output of one group object into `&group` / `name = value` lines;
    !> a variable with an only_if condition that does not hold is left out (its value is the
    !> default the reader would refuse there, e.g. helix_phase = 0 of a straight rod).
    function tidy_group(group, lines) result(text)
        character(len=*), intent(in) :: group
        character(len=*), intent(in) :: lines(:)
        character(len=:), allocatable :: text, name, value, line
        type(group_spec_t), allocatable :: groups(:)
        type(entry_t), allocatable :: entries(:)
        integer :: i, eq, pct, g, v, n
        groups = input_groups()
        g = find_group(groups, group)
        allocate(entries(size(lines)))
        n = 0
        v = 0
        value = ''
        do i = 1, size(lines)
            line = trim(adjustl(lines(i)))
            if (len(line) == 0) cycle
            if (line(1:1) == '/') exit
            if (line(1:1) == '&') cycle
            pct = index(line, '%')
            eq = index(line, '=')
            if (pct > 0 .and. eq > pct .and. verify(line(1:pct - 1), &
                    'abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ_') == 0) then
                call keep(v, value)
                name = to_lower(trim(line(pct + 1:eq - 1)))
                ! The spelling of the reference (EA, rhoI1), not the namelist's upper case;
                ! components that are not input variables (input_line) are left out.
                v = find_variable(groups(g), name)
                value = line(eq + 1:)
            else
                value = value // ' ' // line
            end if
        end do
        call keep(v, value)
        text = '&' // group // new_line('a')
        do i = 1, size(entries(1:n))
            if (.not. condition_holds(entries(i)%variable)) cycle
            associate (spec => groups(g)%variables(entries(i)%variable))
                text = text // variable_line(trim(spec%name), entries(i)%value, &
                    len_trim(spec%allowed) > 0 .or. (spec%kind == 'string' .and. spec%max_count > 1))
            end associate
        end do
        text = text // '/' // new_line('a')
    contains
        !> Note variable `v` (0: not an input variable) with its raw value.
        subroutine keep(v, raw)
            integer, intent(in) :: v
            character(len=*), intent(in) :: raw
            if (v == 0) return
            n = n + 1
            entries(n)%variable = v
            entries(n)%value = raw
        end subroutine keep

        !> True unless variable `v` has an only_if condition that the written values (or the
        !> default of the condition's variable) do not meet.
        logical function condition_holds(v)
            integer, intent(in) :: v
            character(len=:), allocatable :: variable, wanted, actual
            character(len=:), allocatable :: tokens(:)
            integer :: c, k
            condition_holds = .true.
            if (len_trim(groups(g)%variables(v)%only_if) == 0) return
            call split_condition(groups(g)%variables(v)%only_if, variable, wanted)
            c = find_variable(groups(g), variable)
            actual = unquoted(trim(groups(g)%variables(c)%default_text))
            do k = 1, n
                if (entries(k)%variable /= c) cycle
                call split_tokens(entries(k)%value, tokens)
                if (size(tokens) > 0) actual = unquoted(tidy_token(trim(tokens(1))))
            end do
            condition_holds = to_lower(actual) == wanted
        end function condition_holds
    end function tidy_group

    !> `text` without its enclosing quotes and padding inside them.
    pure function unquoted(text) result(out)
        character(len=*), intent(in) :: text
        character(len=:), allocatable :: out
        out = trim(text)
        if (len(out) >= 2) then
            if (out(1:1) == "'" .and. out(len(out):len(out)) == "'") out = trim(out(2:len(out) - 1))
        end if
    end function unquoted

    !> "    name = v1, v2" with values tidied; '' for no name (a component that is not an input
    !> variable) or a value whose every entry is still unset. A blank string of a variable with
    !> a list of allowed values (`choice`) is unset too (blank is never allowed; &rod em_variant
    !> stays blank for formulations other than cl_em_planar), and so is a blank entry of a
    !> string array (the unused places of &plate rods, written as 126*'' by gfortran).
    function variable_line(name, raw, choice) result(text)
        character(len=*), intent(in) :: name, raw
        logical, intent(in) :: choice
        character(len=:), allocatable :: text, token, values
        character(len=:), allocatable :: tokens(:)
        integer :: i, n_kept
        text = ''
        if (len(name) == 0) return
        call split_tokens(raw, tokens)
        values = ''
        n_kept = 0
        do i = 1, size(tokens)
            token = tidy_token(trim(tokens(i)))
            if (len(token) == 0) cycle
            if (choice .and. token == "''") cycle
            if (choice .and. token(1:1) /= "'" .and. index(token, "*''") == len(token) - 2) cycle
            if (n_kept > 0) values = values // ', '
            values = values // token
            n_kept = n_kept + 1
        end do
        if (n_kept == 0) return
        text = '    ' // name // ' = ' // values // new_line('a')
    end function variable_line

    !> One value: strings lose their padding, reals take their shortest exact form, unset
    !> sentinels (huge reals, -huge integers, repeated or not) vanish.
    function tidy_token(raw) result(token)
        character(len=*), intent(in) :: raw
        character(len=:), allocatable :: token
        character(len=:), allocatable :: body
        integer :: star, repeat, ios, i_value
        real(rk) :: r_value
        token = raw
        if (len(token) == 0) return
        if (token(1:1) == "'") then
            token = "'" // trim(token(2:len(token) - 1)) // "'"
            return
        end if
        star = index(token, '*')
        repeat = 1
        body = token
        if (star > 0) then
            read(token(1:star - 1), *, iostat=ios) repeat
            body = token(star + 1:)
        end if
        if (index(body, "'") == 1) then
            ! A repeated string (the blank places of a string array: 126*'  ').
            body = "'" // trim(body(2:len(body) - 1)) // "'"
        else if (scan(body, '.EeDd') > 0 .and. scan(body, 'TF') == 0) then
            read(body, *, iostat=ios) r_value
            if (ios == 0) then
                if (r_value == huge(1.0_rk)) then
                    token = ''
                    return
                end if
                body = str(r_value)
            end if
        else if (scan(body, '0123456789') > 0 .and. scan(body, 'TF') == 0) then
            read(body, *, iostat=ios) i_value
            if (ios == 0 .and. i_value == -huge(1)) then
                token = ''
                return
            end if
        else if (body == 'T') then
            body = '.true.'
        else if (body == 'F') then
            body = '.false.'
        end if
        if (repeat > 1) then
            token = str(repeat) // '*' // body
        else
            token = body
        end if
    end function tidy_token

    !> Split namelist value text at commas and blanks outside quotes.
    subroutine split_tokens(raw, tokens)
        character(len=*), intent(in) :: raw
        character(len=:), allocatable, intent(out) :: tokens(:)
        character(len=len(raw) + 1) :: current
        character :: quote
        integer :: i, n, length
        character(len=len(raw) + 1) :: collected(len(raw) + 1)
        n = 0
        length = 0
        quote = ' '
        current = ''
        do i = 1, len(raw) + 1
            if (i <= len(raw)) then
                if (quote /= ' ') then
                    length = length + 1
                    current(length:length) = raw(i:i)
                    if (raw(i:i) == quote) quote = ' '
                    cycle
                end if
                if (raw(i:i) == "'" .or. raw(i:i) == '"') then
                    quote = raw(i:i)
                    length = length + 1
                    current(length:length) = raw(i:i)
                    cycle
                end if
                if (raw(i:i) /= ',' .and. raw(i:i) /= ' ') then
                    length = length + 1
                    current(length:length) = raw(i:i)
                    cycle
                end if
            end if
            if (length > 0) then
                n = n + 1
                collected(n) = current(1:length)
                current = ''
                length = 0
            end if
        end do
        allocate(character(len=len(raw) + 1) :: tokens(n))
        tokens = collected(1:n)
    end subroutine split_tokens

end module rs_io_scene_writer
