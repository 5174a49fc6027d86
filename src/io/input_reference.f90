!> The input reference in Markdown, made from the tables of rs_io_input_spec, so the
!> documentation cannot drift from what the reader accepts: `rodsolve --input-reference` prints
!> it and docs/user/input.md holds it between its GENERATED markers (checked by a test).
module rs_io_input_reference
    use rs_core_strings, only: str
    use rs_model_units, only: unit_systems, unit_in_system
    use rs_io_input_spec, only: group_spec_t, variable_spec_t, input_groups, range_description
    implicit none
    private

    public :: input_reference_markdown

contains

    !> One section per group, one table row per variable, then the units of every variable
    !> in each system of &run units.
    function input_reference_markdown() result(text)
        character(len=:), allocatable :: text
        type(group_spec_t), allocatable :: groups(:)
        character(len=*), parameter :: nl = new_line('a')
        integer :: g, v
        groups = input_groups()
        text = ''
        do g = 1, size(groups)
            text = text // '### &' // trim(groups(g)%name) // nl // nl // trim(groups(g)%description)
            if (groups(g)%repeatable) text = text // ' May appear any number of times.'
            if (.not. groups(g)%implemented) then
                text = text // ' *Not available in this version.*' // nl // nl
                cycle
            end if
            text = text // nl // nl // &
                '| variable | type | unit | default | allowed | example | meaning |' // nl // &
                '|---|---|---|---|---|---|---|' // nl
            do v = 1, size(groups(g)%variables)
                text = text // row(groups(g)%variables(v)) // nl
            end do
            text = text // nl
        end do
        text = text // units_table(groups)
    end function input_reference_markdown

    !> "### Units": every unit of the tables above in each system of &run units.
    function units_table(groups) result(text)
        type(group_spec_t), intent(in) :: groups(:)
        character(len=:), allocatable :: text, header, rule, systems, system
        character(len=16), allocatable :: units(:)
        character(len=*), parameter :: nl = new_line('a')
        integer :: g, v, bar, u, n_units
        ! Filled in place: growing a character array by constructor trips gfortran's length
        ! check (-fcheck=all).
        allocate(units(sum([(size(groups(g)%variables), g = 1, size(groups))])))
        n_units = 0
        do g = 1, size(groups)
            do v = 1, size(groups(g)%variables)
                associate (unit => groups(g)%variables(v)%unit)
                    if (trim(unit) == '-') cycle
                    if (any(units(1:n_units) == unit)) cycle
                    n_units = n_units + 1
                    units(n_units) = unit
                end associate
            end do
        end do
        units = units(1:n_units)
        header = '|'
        rule = '|'
        systems = unit_systems // '|'
        do while (len(systems) > 0)
            bar = index(systems, '|')
            header = header // ' `' // systems(1:bar - 1) // '` |'
            rule = rule // '---|'
            systems = systems(bar + 1:)
        end do
        text = '### Units' // nl // nl // &
            '`&run units` names the system every number of a scene is in; rodsolve computes ' // &
            'the same in any consistent system, so the choice only changes the unit names shown ' // &
            '(the tables above give SI). Angles are in radians.' // nl // nl // header // nl // rule // nl
        do u = 1, size(units)
            systems = unit_systems // '|'
            text = text // '|'
            do while (len(systems) > 0)
                bar = index(systems, '|')
                system = systems(1:bar - 1)
                text = text // ' ' // unit_in_system(trim(units(u)), system) // ' |'
                systems = systems(bar + 1:)
            end do
            text = text // nl
        end do
    end function units_table

    function row(spec) result(text)
        type(variable_spec_t), intent(in) :: spec
        character(len=:), allocatable :: text, kind, allowed
        kind = trim(spec%kind)
        if (spec%max_count > 1) then
            if (spec%min_count == spec%max_count) then
                kind = kind // '(' // str(spec%min_count) // ')'
            else
                kind = kind // '(' // str(spec%min_count) // '..' // str(spec%max_count) // ')'
            end if
        end if
        allowed = ''
        if (len_trim(spec%allowed) > 0) then
            allowed = quoted_list(trim(spec%allowed))
        else if (spec%kind == 'integer' .or. spec%kind == 'real') then
            allowed = range_description(spec)
        end if
        text = '| `' // trim(spec%name) // '` | ' // kind // ' | ' // trim(spec%unit) // ' | ' // &
            trim(spec%default_text) // ' | ' // allowed // ' | `' // trim(spec%example) // '` | ' // &
            trim(spec%description) // ' |'
    end function row

    function quoted_list(allowed) result(text)
        character(len=*), intent(in) :: allowed
        character(len=:), allocatable :: text
        integer :: i
        text = "`'"
        do i = 1, len(allowed)
            if (allowed(i:i) == '|') then
                text = text // "'`, `'"
            else
                text = text // allowed(i:i)
            end if
        end do
        text = text // "'`"
    end function quoted_list

end module rs_io_input_reference
