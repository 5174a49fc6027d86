!> Parameter sweeps (DESIGN.md §5, §6; issue 9): the members of a scene's &sweep groups as
!> scene texts of their own. A member is the base scene text with every &sweep group removed
!> and each swept variable set to the member's value; it is then read, resolved and checked like
!> any scene, so every real or integer input variable is sweepable. No MPI: each rank can build
!> just the members it runs.
!>
!> How a swept value gets into the text (the reader refuses a variable given twice in one group,
!> so an override replaces rather than repeats):
!> - the target group assigns the variable (`EI1 = 2.0`, or the element, `force(3) = -1`): that
!>   value is replaced;
!> - it assigns the whole array (`force = 0, 0, -100`) and one element is swept: that entry of
!>   the list is replaced (repeat counts `3*0` expanded; the entry just after the last given one
!>   may be swept too, lengthening the list);
!> - it does not assign the variable: `, variable = value` (or `variable(i) = value`) is added as
!>   the group's last item, before its closing "/";
!> - a single group (&run, &time, &solver, &output) that the scene lacks: `&time dt = value /` is
!>   added at the end.
!> A removed &sweep group leaves its line breaks behind, so every line keeps its number and a
!> member's messages point at the lines of the scene file; the member text starts with one
!> comment line more, `! sweep member 12 of 64: rod(1)%EI1 = 2500.0`. Values are written in
!> the shortest form that reads back to the same double (rs_core_strings str), integers as
!> integers. The &output path is left as it is (the runner chooses each member's file).
module rs_io_sweep
    use rs_core_kinds, only: rk, i8
    use rs_core_error, only: error_list_t
    use rs_core_strings, only: to_lower, str, closest_name, did_you_mean
    use rs_model_scene, only: scene_t, sweep_input_t, unset_real, max_sweep_values, &
        max_sweep_members, sweep_member_count, sweep_values, sweep_value_count
    use rs_io_namelist_lexer, only: group_chunk_t, assignment_t, split_namelist, remove_blanks
    use rs_io_input_spec, only: group_spec_t, variable_spec_t, input_groups, find_group, &
        find_variable, in_range, range_description, group_names, variable_names
    use rs_io_input_reader, only: read_scene_text
    use rs_io_input_check, only: resolve_scene, check_capabilities
    implicit none
    private

    public :: sweep_member_t, sweep_member_count, sweep_members, sweep_member, resolve_sweeps, &
        check_sweep_members

    !> Members whose errors check_sweep_members shows; the others are only counted.
    integer, parameter, public :: max_failed_members_shown = 5

    !> One member of a sweep.
    type, public :: sweep_member_t
        !> 1 .. sweep_member_count(scene), the first sweep varying slowest.
        integer :: id = 0
        !> The member's scene text (comment line, then the base scene with the overrides).
        character(len=:), allocatable :: text
        !> The swept paths in canonical spelling ('rod(1)%EI1'), in file order of &sweep.
        character(len=64), allocatable :: parameters(:)
        !> This member's value of each of them.
        real(rk), allocatable :: values(:)
    end type sweep_member_t

    !> Length of one entry of an array value being edited.
    integer, parameter :: token_len = 80

    !> Where a swept variable lives.
    type :: target_t
        !> Group name, lower case.
        character(len=16) :: group = ''
        logical :: repeatable = .false.
        !> k of group(k)%variable (0 for a single group).
        integer :: occurrence = 0
        !> Spelled as the input reference spells it.
        character(len=32) :: variable = ''
        !> i of variable(i) (0 for a scalar).
        integer :: element = 0
        character(len=8) :: kind = ''
        character(len=64) :: path = ''
    end type target_t

    integer, parameter :: edit_remove = 1, edit_value = 2, edit_insert = 3, edit_append = 4

    !> One edit of the base text: text(first:last) replaced by the edit's text (an insertion
    !> before `first` when last = first - 1).
    type :: edit_t
        integer :: kind = 0
        integer :: first = 0
        integer :: last = -1
        !> edit_remove: the replacement (the line breaks of the removed group).
        character(len=:), allocatable :: fixed
        !> edit_append: the group added.
        character(len=16) :: group = ''
        !> edit_insert: the group has assignments already, so the first new item needs a comma.
        logical :: comma = .true.
        !> The sweeps this edit writes.
        integer, allocatable :: sweeps(:)
        !> edit_value: the entry of `tokens` each sweep replaces, and the entries of the base value.
        integer, allocatable :: slots(:)
        character(len=token_len), allocatable :: tokens(:)
    end type edit_t

    !> Everything needed to write any member: targets, values and edits.
    type :: sweep_plan_t
        type(target_t), allocatable :: targets(:)
        !> values(1:counts(s), s): the values of sweep s.
        real(rk), allocatable :: values(:, :)
        integer, allocatable :: counts(:)
        !> Sweep s > 1 pairs with sweep s - 1 (mode 'zip').
        logical, allocatable :: zipped(:)
        !> Sorted by position.
        type(edit_t), allocatable :: edits(:)
        integer :: n_members = 0
    end type sweep_plan_t

contains

    ! ---- Public ---------------------------------------------------------------------------------

    !> Check the &sweep groups of a scene that was read without errors, as rs_io_input_check
    !> checks the other groups: paths, values, modes, and how each value gets into the text
    !> (scene%source_text). A valid sweep's parameter is rewritten in canonical spelling and
    !> `integral` is set for integer variables. Problems go to `errors`.
    subroutine resolve_sweeps(scene, errors)
        type(scene_t), intent(inout) :: scene
        type(error_list_t), intent(inout) :: errors
        type(sweep_plan_t) :: plan
        integer :: before, s
        if (.not. allocated(scene%sweeps)) return
        if (size(scene%sweeps) == 0) return
        before = errors%count
        ! A sweep continues a killed run with --merge, not restart_from (one file per member).
        if (len_trim(scene%run%restart_from) > 0) call errors%add(scene%source_file // &
            ': &run restart_from: a sweep does not restart from a file; a killed sweep keeps its ' // &
            'finished members, and rodsolve --merge SCENE.nml writes its result file from them')
        call build_plan(scene%source_text, scene%source_file, scene, plan, errors)
        if (errors%count > before) return
        do s = 1, size(scene%sweeps)
            scene%sweeps(s)%parameter = plan%targets(s)%path
            scene%sweeps(s)%integral = plan%targets(s)%kind == 'integer'
        end do
    end subroutine resolve_sweeps

    !> Member `id` of the sweeps of `scene`, whose text is `text` (the contents of `file`).
    subroutine sweep_member(text, file, scene, id, member, errors)
        character(len=*), intent(in) :: text, file
        type(scene_t), intent(in) :: scene
        integer, intent(in) :: id
        type(sweep_member_t), intent(out) :: member
        type(error_list_t), intent(inout) :: errors
        type(sweep_plan_t) :: plan
        integer :: before
        before = errors%count
        call build_plan(text, file, scene, plan, errors)
        if (errors%count > before) return
        if (id < 1 .or. id > plan%n_members) then
            call errors%add(file // ': &sweep: there is no sweep member ' // str(id) // &
                ' (members 1 to ' // str(plan%n_members) // ')')
            return
        end if
        call make_member(text, plan, id, member)
    end subroutine sweep_member

    !> All members of the sweeps of `scene` (none without &sweep), in order of id.
    subroutine sweep_members(text, file, scene, members, errors)
        character(len=*), intent(in) :: text, file
        type(scene_t), intent(in) :: scene
        type(sweep_member_t), allocatable, intent(out) :: members(:)
        type(error_list_t), intent(inout) :: errors
        type(sweep_plan_t) :: plan
        integer :: before, id
        allocate(members(0))
        if (sweep_count(scene) == 0) return
        before = errors%count
        call build_plan(text, file, scene, plan, errors)
        if (errors%count > before) return
        deallocate(members)
        allocate(members(plan%n_members))
        do id = 1, plan%n_members
            call make_member(text, plan, id, members(id))
        end do
    end subroutine sweep_members

    !> Build every member of a valid scene with &sweep and read, resolve and check it as a scene
    !> of its own; a failing member's errors are added with the prefix
    !> "sweep member <id> (<path> = <value>, ...): ", for the first max_failed_members_shown
    !> failing members, followed by the number of failing members.
    subroutine check_sweep_members(text, file, scene, errors)
        character(len=*), intent(in) :: text, file
        type(scene_t), intent(in) :: scene
        type(error_list_t), intent(inout) :: errors
        type(sweep_plan_t) :: plan
        type(scene_t) :: member_scene
        type(error_list_t) :: member_errors
        character(len=:), allocatable :: body, prefix
        integer, allocatable :: indices(:)
        integer :: before, id, n_failed
        if (sweep_count(scene) == 0) return
        before = errors%count
        call build_plan(text, file, scene, plan, errors)
        if (errors%count > before) return
        n_failed = 0
        do id = 1, plan%n_members
            indices = member_indices(plan, id)
            ! The body without the comment line: messages name the lines of the scene file.
            body = member_body(text, plan, indices)
            member_errors = error_list_t()
            call read_scene_text(body, file, member_scene, member_errors)
            if (member_errors%count == 0) call resolve_scene(member_scene, member_errors)
            if (member_errors%count == 0) call check_capabilities(member_scene, member_errors)
            if (member_errors%count == 0) cycle
            n_failed = n_failed + 1
            if (n_failed > max_failed_members_shown) cycle
            prefix = 'sweep member ' // str(id) // ' (' // assignments_text(plan, indices) // '): '
            call add_prefixed(errors, prefix, member_errors%joined())
        end do
        if (n_failed == 0) return
        if (n_failed > max_failed_members_shown) then
            call errors%add(file // ': &sweep: ' // str(n_failed) // ' of ' // str(plan%n_members) // &
                ' sweep members are invalid (the first ' // str(max_failed_members_shown) // &
                ' are shown)')
        else
            call errors%add(file // ': &sweep: ' // str(n_failed) // ' of ' // str(plan%n_members) // &
                ' sweep members are invalid')
        end if
    end subroutine check_sweep_members

    ! ---- Members --------------------------------------------------------------------------------

    !> Member `id` from a valid plan.
    subroutine make_member(text, plan, id, member)
        character(len=*), intent(in) :: text
        type(sweep_plan_t), intent(in) :: plan
        integer, intent(in) :: id
        type(sweep_member_t), intent(out) :: member
        integer, allocatable :: indices(:)
        integer :: s, n
        n = size(plan%targets)
        indices = member_indices(plan, id)
        member%id = id
        allocate(member%parameters(n), member%values(n))
        do s = 1, n
            member%parameters(s) = plan%targets(s)%path
            member%values(s) = plan%values(indices(s), s)
        end do
        member%text = '! sweep member ' // str(id) // ' of ' // str(plan%n_members) // ': ' // &
            assignments_text(plan, indices) // new_line('a') // member_body(text, plan, indices)
    end subroutine make_member

    !> The value index of each sweep in member `id` (as sweep_member_indices, from the plan).
    pure function member_indices(plan, id) result(indices)
        type(sweep_plan_t), intent(in) :: plan
        integer, intent(in) :: id
        integer :: indices(size(plan%targets))
        integer :: s, rest
        rest = id - 1
        do s = size(plan%targets), 1, -1
            if (plan%zipped(s)) cycle
            indices(s) = mod(rest, plan%counts(s)) + 1
            rest = rest / plan%counts(s)
        end do
        do s = 2, size(plan%targets)
            if (plan%zipped(s)) indices(s) = indices(s - 1)
        end do
    end function member_indices

    !> "rod(1)%EI1 = 2500.0, time%dt = 0.01" for the values of `indices`.
    function assignments_text(plan, indices) result(text)
        type(sweep_plan_t), intent(in) :: plan
        integer, intent(in) :: indices(:)
        character(len=:), allocatable :: text
        integer :: s
        text = ''
        do s = 1, size(plan%targets)
            if (s > 1) text = text // ', '
            text = text // trim(plan%targets(s)%path) // ' = ' // &
                value_text(plan%values(indices(s), s), plan%targets(s)%kind)
        end do
    end function assignments_text

    !> The base text with the edits of the plan for the values of `indices`.
    function member_body(text, plan, indices) result(body)
        character(len=*), intent(in) :: text
        type(sweep_plan_t), intent(in) :: plan
        integer, intent(in) :: indices(:)
        character(len=:), allocatable :: body
        integer :: e, position
        body = ''
        position = 1
        do e = 1, size(plan%edits)
            associate (edit => plan%edits(e))
                body = body // text(position:edit%first - 1) // edit_text(edit)
                position = edit%last + 1
            end associate
        end do
        body = body // text(position:)
    contains
        function edit_text(edit) result(out)
            type(edit_t), intent(in) :: edit
            character(len=:), allocatable :: out
            character(len=token_len), allocatable :: tokens(:)
            integer :: k, s
            select case (edit%kind)
            case (edit_remove)
                out = edit%fixed
            case (edit_value)
                tokens = edit%tokens
                do k = 1, size(edit%sweeps)
                    s = edit%sweeps(k)
                    tokens(edit%slots(k)) = value_text(plan%values(indices(s), s), plan%targets(s)%kind)
                end do
                out = ''
                do k = 1, size(tokens)
                    if (k > 1) out = out // ', '
                    out = out // trim(tokens(k))
                end do
            case (edit_insert)
                out = ''
                do k = 1, size(edit%sweeps)
                    s = edit%sweeps(k)
                    if (k > 1 .or. edit%comma) then
                        out = out // ', '
                    else
                        out = out // ' '
                    end if
                    out = out // item_text(s)
                end do
            case default
                out = ''
                if (len(text) > 0) then
                    if (text(len(text):len(text)) /= new_line('a')) out = new_line('a')
                end if
                out = out // '&' // trim(edit%group)
                do k = 1, size(edit%sweeps)
                    if (k > 1) out = out // ','
                    out = out // ' ' // item_text(edit%sweeps(k))
                end do
                out = out // ' /' // new_line('a')
            end select
        end function edit_text

        !> "EI1 = 2.5" or "force(3) = -1.0" for sweep s.
        function item_text(s) result(out)
            integer, intent(in) :: s
            character(len=:), allocatable :: out
            out = trim(plan%targets(s)%variable)
            if (plan%targets(s)%element > 0) out = out // '(' // str(plan%targets(s)%element) // ')'
            out = out // ' = ' // value_text(plan%values(indices(s), s), plan%targets(s)%kind)
        end function item_text
    end function member_body

    !> A value as the scene text gets it: integers as integers, reals in the shortest form that
    !> reads back to the same double.
    function value_text(value, kind) result(text)
        real(rk), intent(in) :: value
        character(len=*), intent(in) :: kind
        character(len=:), allocatable :: text
        if (trim(kind) == 'integer') then
            text = str(nint(value))
        else
            text = str(value)
        end if
    end function value_text

    ! ---- Validation and plan --------------------------------------------------------------------

    !> Check the sweeps of `scene` against `text` and, if all is well, make the plan that writes
    !> any member. Problems go to `errors`.
    subroutine build_plan(text, file, scene, plan, errors)
        character(len=*), intent(in) :: text, file
        type(scene_t), intent(in) :: scene
        type(sweep_plan_t), intent(out) :: plan
        type(error_list_t), intent(inout) :: errors
        type(group_spec_t), allocatable :: groups(:)
        type(group_chunk_t), allocatable :: chunks(:)
        type(error_list_t) :: lexer_errors
        character(len=:), allocatable :: message, here
        real(rk), allocatable :: values(:)
        logical, allocatable :: valid(:)
        integer :: n, s, t, before
        integer(i8) :: members

        n = sweep_count(scene)
        allocate(plan%targets(n), plan%counts(n), plan%zipped(n), valid(n), plan%edits(0))
        allocate(plan%values(max_sweep_values, n))
        plan%counts = 0
        plan%values = 0.0_rk
        plan%zipped = .false.
        if (n == 0) return
        before = errors%count
        groups = input_groups()
        call split_namelist(text, file, chunks, lexer_errors)
        if (lexer_errors%count > 0) then
            call errors%add(lexer_errors%joined())
            return
        end if

        do s = 1, n
            associate (sweep => scene%sweeps(s))
                here = file // ':' // str(sweep%input_line) // ': &sweep '
                call parse_target(sweep%parameter, groups, chunks, plan%targets(s), message)
                valid(s) = len(message) == 0
                if (.not. valid(s)) then
                    call errors%add(here // 'parameter: ' // message)
                    cycle
                end if
                do t = 1, s - 1
                    if (.not. valid(t)) cycle
                    if (plan%targets(t)%path /= plan%targets(s)%path) cycle
                    call errors%add(here // 'parameter: ' // trim(plan%targets(s)%path) // &
                        ' is swept already by the &sweep at line ' // str(scene%sweeps(t)%input_line))
                    valid(s) = .false.
                    exit
                end do
                if (.not. valid(s)) cycle
                call sweep_list(sweep, plan%targets(s), here, values, errors, valid(s))
                if (.not. valid(s)) cycle
                plan%counts(s) = size(values)
                plan%values(1:size(values), s) = values
            end associate
        end do
        if (errors%count > before) return

        ! Zipped sweeps need equal counts; the product of the blocks must stay countable.
        members = 1
        do s = 1, n
            if (s > 1) plan%zipped(s) = trim(scene%sweeps(s)%mode) == 'zip'
            if (plan%zipped(s)) then
                if (plan%counts(s) /= plan%counts(s - 1)) call errors%add(file // ':' // &
                    str(scene%sweeps(s)%input_line) // ': &sweep mode: ''zip'' pairs the ' // &
                    str(plan%counts(s)) // ' value(s) of ' // trim(plan%targets(s)%path) // &
                    ' with the ' // str(plan%counts(s - 1)) // ' value(s) of ' // &
                    trim(plan%targets(s - 1)%path) // ' (the &sweep at line ' // &
                    str(scene%sweeps(s - 1)%input_line) // '); zipped sweeps need the same ' // &
                    'number of values (or use mode = ''product'')')
                cycle
            end if
            members = members * plan%counts(s)
            members = min(members, int(max_sweep_members, i8) + 1)
        end do
        if (errors%count > before) return
        if (members > max_sweep_members) then
            call errors%add(file // ': &sweep: the sweeps have more than ' // str(max_sweep_members) // &
                ' members (the product of their numbers of values); at most ' // &
                str(max_sweep_members) // ' are allowed')
            return
        end if
        plan%n_members = int(members)
        call plan_edits(text, file, scene, chunks, plan, errors)
    end subroutine build_plan

    !> Number of &sweep groups of `scene`.
    pure integer function sweep_count(scene) result(n)
        type(scene_t), intent(in) :: scene
        n = 0
        if (allocated(scene%sweeps)) n = size(scene%sweeps)
    end function sweep_count

    !> The target of the sweep path `path`; `message` is '' when it is valid.
    subroutine parse_target(path, groups, chunks, target, message)
        character(len=*), intent(in) :: path
        type(group_spec_t), intent(in) :: groups(:)
        type(group_chunk_t), intent(in) :: chunks(:)
        type(target_t), intent(out) :: target
        character(len=:), allocatable, intent(out) :: message
        character(len=:), allocatable :: compact, group_name, variable_name, quoted, what
        integer :: percent, g, v, k, n_groups, c
        logical :: ok, group_indexed, variable_indexed

        message = ''
        compact = remove_blanks(path)
        quoted = "'" // trim(path) // "'"
        percent = index(compact, '%')
        ok = percent > 1
        if (ok) ok = index(compact(percent + 1:), '%') == 0
        if (ok) call split_name(compact(1:percent - 1), group_name, k, group_indexed, ok)
        if (ok) call split_name(compact(percent + 1:), variable_name, target%element, &
            variable_indexed, ok)
        if (.not. ok) then
            message = quoted // ' is not a path into the scene; write group%variable ' // &
                '(time%dt), group(k)%variable (rod(1)%EI1) or group(k)%variable(i) ' // &
                '(load(1)%force(3))'
            return
        end if
        g = find_group(groups, group_name)
        if (g == 0) then
            message = 'unknown group "' // group_name // '" in ' // quoted // &
                did_you_mean(group_name, group_names(groups)) // '; groups are ' // &
                sweepable_groups(groups)
            return
        end if
        target%group = groups(g)%name
        target%repeatable = groups(g)%repeatable
        if (trim(target%group) == 'sweep') then
            message = 'a sweep cannot sweep a &sweep group (' // quoted // '); groups are ' // &
                sweepable_groups(groups)
            return
        end if
        if (target%repeatable .and. .not. group_indexed) then
            message = '&' // trim(target%group) // ' may appear several times: name which one ' // &
                'in ' // quoted // ', e.g. ' // trim(target%group) // '(1)%' // variable_name
            return
        end if
        if (.not. target%repeatable .and. group_indexed) then
            message = '&' // trim(target%group) // ' appears at most once: write ' // &
                trim(target%group) // '%' // compact(percent + 1:) // ' without an index'
            return
        end if
        if (target%repeatable) then
            n_groups = 0
            do c = 1, size(chunks)
                if (chunks(c)%name == trim(target%group)) n_groups = n_groups + 1
            end do
            if (k < 1 .or. k > n_groups) then
                message = trim(target%group) // '(' // str(k) // ') in ' // quoted // &
                    ' does not exist: the scene has ' // str(n_groups) // ' &' // &
                    trim(target%group) // ' group(s), counted from 1 in file order'
                return
            end if
            target%occurrence = k
        end if
        v = find_variable(groups(g), variable_name)
        if (v == 0) then
            message = '&' // trim(target%group) // ' has no variable "' // variable_name // '"' // &
                did_you_mean(variable_name, variable_names(groups(g))) // ' (in ' // quoted // ')'
            return
        end if
        associate (spec => groups(g)%variables(v))
            target%variable = spec%name
            target%kind = spec%kind
            what = trim(target%group)
            if (target%repeatable) what = what // '(' // str(k) // ')'
            what = what // '%' // trim(spec%name)
            if (spec%kind /= 'real' .and. spec%kind /= 'integer') then
                message = what // ' is a ' // trim(spec%kind) // ' variable; only real and ' // &
                    'integer variables can be swept in this version'
                return
            end if
            if (spec%max_count > 1) then
                if (.not. variable_indexed) then
                    message = what // ' is an array of ' // count_text(spec) // &
                        ': sweep one element, e.g. ' // what // '(1)'
                    return
                end if
                if (target%element < 1 .or. target%element > spec%max_count) then
                    message = what // '(' // str(target%element) // '): ' // trim(spec%name) // &
                        ' has ' // count_text(spec) // '; allowed elements: 1 to ' // &
                        str(spec%max_count)
                    return
                end if
                what = what // '(' // str(target%element) // ')'
            else if (variable_indexed) then
                message = what // ' is a single value: write it without the element index (' // &
                    str(target%element) // ')'
                return
            end if
            target%path = what
        end associate
    end subroutine parse_target

    !> "3 values" or "1 to 512 values".
    function count_text(spec) result(text)
        type(variable_spec_t), intent(in) :: spec
        character(len=:), allocatable :: text
        if (spec%min_count == spec%max_count) then
            text = str(spec%max_count) // ' values'
        else
            text = str(spec%min_count) // ' to ' // str(spec%max_count) // ' values'
        end if
    end function count_text

    !> `name` or `name(index)` with a name that starts with a letter and a positive whole index.
    subroutine split_name(text, name, index_, indexed, ok)
        character(len=*), intent(in) :: text
        character(len=:), allocatable, intent(out) :: name
        integer, intent(out) :: index_
        logical, intent(out) :: indexed, ok
        integer :: open_, ios
        index_ = 0
        indexed = .false.
        ok = .false.
        name = ''
        open_ = index(text, '(')
        if (open_ == 0) then
            name = text
        else
            name = text(1:open_ - 1)
            if (text(len(text):len(text)) /= ')') return
            if (open_ + 1 > len(text) - 1) return
            if (len(text) - 1 - open_ > 9) return
            if (verify(text(open_ + 1:len(text) - 1), '0123456789') /= 0) return
            read(text(open_ + 1:len(text) - 1), *, iostat=ios) index_
            if (ios /= 0) return
            indexed = .true.
        end if
        if (len(name) == 0) return
        if (verify(to_lower(name(1:1)), 'abcdefghijklmnopqrstuvwxyz') /= 0) return
        if (verify(to_lower(name), 'abcdefghijklmnopqrstuvwxyz0123456789_') /= 0) return
        ok = .true.
    end subroutine split_name

    !> The values of `sweep` for `target` (whole numbers for an integer variable), after checking
    !> that exactly one of values, linspace and logspace is given and is valid and that every
    !> value is allowed for the variable; `valid` is false after a problem (added to `errors`
    !> with the prefix `here`).
    subroutine sweep_list(sweep, target, here, values, errors, valid)
        type(sweep_input_t), intent(in) :: sweep
        type(target_t), intent(in) :: target
        character(len=*), intent(in) :: here
        real(rk), allocatable, intent(out) :: values(:)
        type(error_list_t), intent(inout) :: errors
        logical, intent(inout) :: valid
        type(sweep_input_t) :: raw
        type(variable_spec_t) :: spec
        type(group_spec_t), allocatable :: groups(:)
        character(len=:), allocatable :: given, name
        real(rk) :: rounded
        integer :: n, j, g
        logical :: has_values, has_linspace, has_logspace

        allocate(values(0))
        name = 'values'
        has_values = any(sweep%values /= unset_real)
        has_linspace = any(sweep%linspace /= unset_real)
        has_logspace = any(sweep%logspace /= unset_real)
        given = ''
        if (has_values) given = given // ', values'
        if (has_linspace) given = given // ', linspace'
        if (has_logspace) given = given // ', logspace'
        if (count([has_values, has_linspace, has_logspace]) /= 1) then
            if (len(given) == 0) given = ', none'
            call fail('values, linspace, logspace: give exactly one of them (given: ' // &
                given(3:) // ')')
            return
        end if
        if (has_values) then
            n = sweep_value_count(sweep)
            if (any(sweep%values(n + 1:) /= unset_real)) then
                call fail('values: entry ' // str(n + 1) // ' is not given but a later one is; ' // &
                    'give the values from the first on without gaps')
                return
            end if
        else
            name = trim(merge('linspace', 'logspace', has_linspace))
            if (has_linspace) then
                raw%linspace = sweep%linspace
            else
                raw%logspace = sweep%logspace
            end if
            associate (triple => merge(sweep%linspace, sweep%logspace, has_linspace))
                if (any(triple == unset_real)) then
                    call fail(name // ': give all three of first, last, count')
                    return
                end if
                if (triple(3) /= anint(triple(3)) .or. triple(3) < 2.0_rk .or. &
                        triple(3) > real(max_sweep_values, rk)) then
                    call fail(name // ': the count (third value) must be a whole number from 2 ' // &
                        'to ' // str(max_sweep_values) // ' (given: ' // str(triple(3)) // ')')
                    return
                end if
                if (has_logspace .and. (triple(1) <= 0.0_rk .or. triple(2) <= 0.0_rk)) then
                    call fail(name // ': first and last must be > 0 for geometric spacing ' // &
                        '(given: ' // str(triple(1)) // ', ' // str(triple(2)) // ')')
                    return
                end if
            end associate
        end if
        if (has_values) raw%values = sweep%values
        values = sweep_values(raw)

        groups = input_groups()
        g = find_group(groups, target%group)
        spec = groups(g)%variables(find_variable(groups(g), target%variable))
        do j = 1, size(values)
            if (trim(target%kind) == 'integer') then
                rounded = anint(values(j))
                if (abs(values(j)) > real(huge(1), rk) .or. &
                        abs(values(j) - rounded) > 1.0e-12_rk * max(1.0_rk, abs(values(j)))) then
                    call fail(name // ': ' // trim(target%path) // ' is an integer variable, but ' // &
                        'value ' // str(j) // ', ' // str(values(j)) // ', is not a whole number')
                    return
                end if
                values(j) = rounded
            end if
            if (.not. in_range(spec, values(j))) then
                call fail(name // ': value ' // str(j) // ', ' // str(values(j)) // ', is out of ' // &
                    'range for ' // trim(target%path) // '; allowed: ' // range_description(spec))
                return
            end if
        end do
    contains
        subroutine fail(message)
            character(len=*), intent(in) :: message
            call errors%add(here // message)
            valid = .false.
        end subroutine fail
    end subroutine sweep_list

    !> The edits that write the sweeps' values into `text` (see the module header), sorted by
    !> position; problems (a value that cannot be placed) go to `errors`.
    subroutine plan_edits(text, file, scene, chunks, plan, errors)
        character(len=*), intent(in) :: text, file
        type(scene_t), intent(in) :: scene
        type(group_chunk_t), intent(in) :: chunks(:)
        type(sweep_plan_t), intent(inout) :: plan
        type(error_list_t), intent(inout) :: errors
        type(edit_t) :: edit
        type(edit_t), allocatable :: edits(:)
        character(len=token_len), allocatable :: tokens(:)
        character(len=:), allocatable :: here, variable, group_at
        integer :: s, c, a, e, k, slot
        logical :: ok

        allocate(edits(0))
        do c = 1, size(chunks)
            if (chunks(c)%name /= 'sweep') cycle
            edit = edit_t()
            edit%kind = edit_remove
            edit%first = chunks(c)%first
            edit%last = chunks(c)%last
            edit%fixed = line_breaks(text(edit%first:edit%last))
            edits = [edits, edit]
        end do

        do s = 1, size(plan%targets)
            associate (t => plan%targets(s))
                here = file // ':' // str(scene%sweeps(s)%input_line) // ': &sweep parameter: ' // &
                    trim(t%path) // ': '
                variable = to_lower(trim(t%variable))
                c = target_chunk(chunks, t)
                if (c == 0) then
                    ! A single group the scene lacks: added at the end.
                    e = find_edit(edits, edit_append, len(text) + 1, t%group)
                    if (e == 0) then
                        edit = edit_t()
                        edit%kind = edit_append
                        edit%first = len(text) + 1
                        edit%last = len(text)
                        edit%group = t%group
                        allocate(edit%sweeps(0))
                        edits = [edits, edit]
                        e = size(edits)
                    end if
                    edits(e)%sweeps = [edits(e)%sweeps, s]
                    cycle
                end if
                group_at = 'the &' // trim(t%group) // ' at line ' // str(chunks(c)%line)
                a = 0
                do k = 1, size(chunks(c)%assignments)
                    if (chunks(c)%assignments(k)%name == variable) a = k
                end do
                if (a == 0) then
                    ! Not assigned: added as the group's last item.
                    call insertion(c, s, ok)
                    if (.not. ok) call errors%add(here // 'another sweep sets an element of ' // &
                        trim(t%variable) // ', which ' // group_at // ' does not give; two ' // &
                        'elements of one array can only be swept if the group gives the array ' // &
                        'in full (e.g. ' // trim(t%variable) // ' = ...)')
                    cycle
                end if
                associate (asg => chunks(c)%assignments(a))
                    e = find_edit(edits, edit_value, asg%value_first, '')
                    if (e > 0) then
                        tokens = edits(e)%tokens
                    else
                        call base_tokens(asg, tokens, ok)
                        if (.not. ok) then
                            call errors%add(here // group_at // ' gives ' // trim(t%variable) // &
                                ' as "' // asg%value // '", whose entries cannot be told apart ' // &
                                '(empty values); write them out, e.g. ' // trim(t%variable) // &
                                ' = 0, 0, 0')
                            cycle
                        end if
                    end if
                    slot = 0
                    if (.not. asg%subscripted) then
                        if (t%element == 0) then
                            slot = 1
                        else if (t%element <= size(tokens) + 1) then
                            slot = t%element
                        else
                            call errors%add(here // group_at // ' gives ' // str(size(tokens)) // &
                                ' value(s) of ' // trim(t%variable) // '; a sweep can set one of ' // &
                                'them or the next (element ' // str(size(tokens) + 1) // ')')
                            cycle
                        end if
                    else if (to_lower(asg%target) == variable // '(' // str(t%element) // ')') then
                        slot = 1
                    else
                        call errors%add(here // group_at // ' assigns ' // asg%target // &
                            ' alone; to sweep ' // trim(t%path) // ', give ' // trim(t%variable) // &
                            ' there in full (e.g. ' // trim(t%variable) // ' = ...)')
                        cycle
                    end if
                    if (slot == size(tokens) + 1) tokens = [character(len=token_len) :: tokens, '']
                    if (e == 0) then
                        edit = edit_t()
                        edit%kind = edit_value
                        edit%first = asg%value_first
                        edit%last = asg%value_last
                        allocate(edit%sweeps(0), edit%slots(0))
                        edits = [edits, edit]
                        e = size(edits)
                    end if
                    edits(e)%tokens = tokens
                    edits(e)%sweeps = [edits(e)%sweeps, s]
                    edits(e)%slots = [edits(e)%slots, slot]
                end associate
            end associate
        end do
        call sort_edits(edits)
        plan%edits = edits
    contains
        !> Add sweep s to the insertion at the end of chunk c; not ok if another sweep inserts
        !> the same variable there.
        subroutine insertion(c, s, ok)
            integer, intent(in) :: c, s
            logical, intent(out) :: ok
            integer :: e, k, position, n_assignments
            ok = .true.
            n_assignments = size(chunks(c)%assignments)
            if (n_assignments > 0) then
                position = chunks(c)%assignments(n_assignments)%value_last + 1
            else
                position = chunks(c)%name_end + 1
            end if
            e = find_edit(edits, edit_insert, position, '')
            if (e == 0) then
                edit = edit_t()
                edit%kind = edit_insert
                edit%first = position
                edit%last = position - 1
                edit%comma = n_assignments > 0
                allocate(edit%sweeps(0))
                edits = [edits, edit]
                e = size(edits)
            end if
            do k = 1, size(edits(e)%sweeps)
                if (plan%targets(edits(e)%sweeps(k))%variable == plan%targets(s)%variable) ok = .false.
            end do
            if (ok) edits(e)%sweeps = [edits(e)%sweeps, s]
        end subroutine insertion
    end subroutine plan_edits

    !> The chunk of group occurrence `t` (0 if a single group is absent).
    pure integer function target_chunk(chunks, t) result(c)
        type(group_chunk_t), intent(in) :: chunks(:)
        type(target_t), intent(in) :: t
        integer :: k, seen
        seen = 0
        do k = 1, size(chunks)
            if (chunks(k)%name /= trim(t%group)) cycle
            seen = seen + 1
            if (.not. t%repeatable .or. seen == t%occurrence) then
                c = k
                return
            end if
        end do
        c = 0
    end function target_chunk

    !> Index of the edit of `kind` at `first` (and of `group` for an append), 0 if none.
    pure integer function find_edit(edits, kind, first, group) result(e)
        type(edit_t), intent(in) :: edits(:)
        integer, intent(in) :: kind, first
        character(len=*), intent(in) :: group
        integer :: k
        e = 0
        do k = 1, size(edits)
            if (edits(k)%kind /= kind .or. edits(k)%first /= first) cycle
            if (kind == edit_append .and. edits(k)%group /= group) cycle
            e = k
            return
        end do
    end function find_edit

    !> Edits in order of position (appends in the order made); insertion sort, few edits.
    subroutine sort_edits(edits)
        type(edit_t), intent(inout) :: edits(:)
        type(edit_t) :: held
        integer :: i, j
        do i = 2, size(edits)
            held = edits(i)
            j = i - 1
            do while (j >= 1)
                if (edits(j)%first <= held%first) exit
                edits(j + 1) = edits(j)
                j = j - 1
            end do
            edits(j + 1) = held
        end do
    end subroutine sort_edits

    !> The entries of an assignment's value: separated by commas or blanks, repeat counts
    !> `r*v` expanded; not ok for empty (null) values, `r*` or an entry too long to keep.
    subroutine base_tokens(asg, tokens, ok)
        type(assignment_t), intent(in) :: asg
        character(len=token_len), allocatable, intent(out) :: tokens(:)
        logical, intent(out) :: ok
        integer :: n
        call scan_tokens(asg%value, n, ok)
        allocate(tokens(max(n, 0)))
        if (.not. ok) return
        call scan_tokens(asg%value, n, ok, tokens)
    end subroutine base_tokens

    !> Count (and with `tokens`, fill) the entries of `value`.
    subroutine scan_tokens(value, n, ok, tokens)
        character(len=*), intent(in) :: value
        integer, intent(out) :: n
        logical, intent(out) :: ok
        character(len=token_len), intent(out), optional :: tokens(:)
        integer :: i, start, star, repeat, ios, k
        logical :: after_comma
        character(len=:), allocatable :: token
        n = 0
        ok = .true.
        after_comma = .true.
        i = 1
        do while (i <= len(value))
            if (value(i:i) == ' ') then
                i = i + 1
                cycle
            end if
            if (value(i:i) == ',') then
                if (after_comma) ok = .false.
                after_comma = .true.
                i = i + 1
                cycle
            end if
            start = i
            do while (i <= len(value))
                if (value(i:i) == ' ' .or. value(i:i) == ',') exit
                i = i + 1
            end do
            token = value(start:i - 1)
            after_comma = .false.
            repeat = 1
            star = index(token, '*')
            if (star > 0) then
                read(token(1:star - 1), *, iostat=ios) repeat
                if (ios /= 0 .or. star == len(token) .or. repeat < 1) then
                    ok = .false.
                    return
                end if
                token = token(star + 1:)
            end if
            if (len(token) > token_len) then
                ok = .false.
                return
            end if
            if (present(tokens)) then
                do k = 1, repeat
                    tokens(n + k) = token
                end do
            end if
            n = n + repeat
        end do
    end subroutine scan_tokens

    ! ---- Helpers --------------------------------------------------------------------------------

    !> Add each line of `text` to `errors` with `prefix`.
    subroutine add_prefixed(errors, prefix, text)
        type(error_list_t), intent(inout) :: errors
        character(len=*), intent(in) :: prefix, text
        integer :: start, eol
        start = 1
        do while (start <= len(text))
            eol = index(text(start:), new_line('a'))
            if (eol == 0) then
                call errors%add(prefix // text(start:))
                exit
            end if
            call errors%add(prefix // text(start:start + eol - 2))
            start = start + eol
        end do
    end subroutine add_prefixed

    !> The line breaks of `text`, nothing else.
    pure function line_breaks(text) result(out)
        character(len=*), intent(in) :: text
        character(len=:), allocatable :: out
        integer :: i
        out = ''
        do i = 1, len(text)
            if (text(i:i) == new_line('a')) out = out // new_line('a')
        end do
    end function line_breaks




    !> "run, time, ..., joint": the groups a sweep can reach.
    pure function sweepable_groups(groups) result(text)
        type(group_spec_t), intent(in) :: groups(:)
        character(len=:), allocatable :: text
        integer :: i
        text = ''
        do i = 1, size(groups)
            if (trim(groups(i)%name) == 'sweep') cycle
            if (len(text) > 0) text = text // ', '
            text = text // trim(groups(i)%name)
        end do
    end function sweepable_groups


end module rs_io_sweep
