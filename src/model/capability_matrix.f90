!> The capability matrix of docs/user/capabilities.md as Markdown, rendered from capability rows
!> (rs_model_capabilities; `rodsolve --capabilities` passes those of the formulations'
!> descriptors, rs_formulations_registry). The docs hold this output between their
!> GENERATED markers and the input_capabilities_doc test compares the two, so the matrix a
!> reader sees is the one `--check-input` enforces (issue 21 item 15).
module rs_model_capability_matrix
    use rs_core_strings, only: split_list, append_joined
    use rs_model_capabilities, only: capability_t, lists_name
    implicit none
    private

    public :: capability_matrix_markdown

    character(len=*), parameter :: none = '-'

contains

    !> The matrix: one row per available row of `rows`, one column per capability.
    function capability_matrix_markdown(rows) result(text)
        type(capability_t), intent(in) :: rows(:)
        character(len=:), allocatable :: text
        character(len=*), parameter :: nl = new_line('a')
        integer :: i
        text = '| formulation | ends | ends at s = L, if other | driven ends by | end loads | ' // &
            'distributed loads, gravity | curved reference | prestressed | ' // &
            'prestretched starts | constraints | ' // &
            'viscoelasticity | damping | varying along the rod | actuation | joints | end plates | ' // &
            'contact | quasistatics | relaxation | order 4 in time | adaptive steps | ' // &
            'generalized-α | planar | modes |' // nl // '|' // repeat('---|', 24)
        do i = 1, size(rows)
            if (rows(i)%available) text = text // nl // row_markdown(rows(i))
        end do
    end function capability_matrix_markdown

    !> One formulation's row.
    function row_markdown(row) result(line)
        type(capability_t), intent(in) :: row
        character(len=:), allocatable :: line
        line = '| ' // trim(row%formulation) // &
            ' | ' // listed(row%end_kinds) // &
            yes_no(row%held_twist, ' (also `hold = ''twist''`)', '') // &
            ' | ' // listed(row%end_kinds_at_end) // &
            ' | ' // drive_text(row%drive) // &
            ' | ' // end_load_text(row) // &
            ' | ' // distributed_load_text(row) // &
            ' | ' // yes_no(row%curved_reference, 'yes: `geometry` helix, polyline, curvature ' // &
                '(rest curvature and pre-twist of s: `rest_curvature`, `rest_curvature_table`)') // &
            ' | ' // yes_no(row%prestressed, 'yes (`prestressed`)') // &
            ' | ' // prestretched_text(row) // &
            ' | ' // listed(row%constraints) // &
            ' | ' // yes_no(row%viscoelastic, 'generalized Maxwell (`maxwell_*`)') // &
            ' | ' // yes_no(row%damping, 'Kelvin-Voigt (`kelvin_voigt_time`), drag (`drag`, ' // &
            '`angular_drag`)') // &
            ' | ' // yes_no(row%segments, 'piecewise sections and materials (`&segment`)') // &
            ' | ' // yes_no(row%actuation, 'pneumatic chambers, tendons (`&actuator`)') // &
            ' | ' // listed(row%joints) // &
            ' | ' // yes_no(row%end_plates, plates_text(row%floating_plates)) // &
            ' | ' // yes_no(row%contact, 'yes: rod-rod and self (`&contact`), rigid ' // &
            'obstacles (`&obstacle`), with friction') // &
            ' | ' // yes_no(row%quasistatic, 'yes (`&time quasistatic`)' // trim(merge( &
                ', arc-length continuation (`&time continuation`)', '                ' // &
                '                                ', row%continuation))) // &
            ' | ' // yes_no(row%relaxation, 'yes (`&time relaxation`)') // &
            ' | ' // yes_no(row%order_4, 'yes (`&time order = 4`)') // &
            ' | ' // yes_no(row%adaptive, 'yes (`&time adaptive`)') // &
            ' | ' // yes_no(row%generalized_alpha, 'yes (`&time scheme`, `rho_inf`)') // &
            ' | ' // yes_no(row%planar, 'yes: rods and loads in one plane') // &
            ' | ' // yes_no(row%modes, trim(merge('yes (`&modes`)     ', &
            'undamped (`&modes`)', row%damped_modes)) // trim(merge(', buckling', &
            '          ', row%buckling))) // ' |'
    end function row_markdown

    !> A '|'-separated list as 'a, b, c' ('-' when empty).
    function listed(list) result(text)
        character(len=*), intent(in) :: list
        character(len=:), allocatable :: text
        character(len=32), allocatable :: names(:)
        integer :: i
        if (len_trim(list) == 0) then
            text = none
            return
        end if
        names = split_list(list)
        text = trim(names(1))
        do i = 2, size(names)
            text = text // ', ' // trim(names(i))
        end do
    end function listed

    !> The end plates a formulation has (fixed or driven; floating with a mass).
    function plates_text(floating) result(text)
        logical, intent(in) :: floating
        character(len=:), allocatable :: text
        text = 'yes: fixed or driven (`&plate`)'
        if (floating) text = 'yes: fixed, driven or floating (`&plate`, `mass`)'
    end function plates_text

    !> `what` if `flag`, else `otherwise` (default '-').
    function yes_no(flag, what, otherwise) result(text)
        logical, intent(in) :: flag
        character(len=*), intent(in) :: what
        character(len=*), intent(in), optional :: otherwise
        character(len=:), allocatable :: text
        if (flag) then
            text = what
        else if (present(otherwise)) then
            text = otherwise
        else
            text = none
        end if
    end function yes_no

    !> Prestretched starts: which of prestrain, initial equilibrium and release the row has.
    function prestretched_text(row) result(text)
        type(capability_t), intent(in) :: row
        character(len=:), allocatable :: text
        text = ''
        if (row%prestrain) call append_joined(text, ', ', 'prestrain (`prestrain`)')
        if (row%initial_equilibrium) call append_joined(text, ', ', 'initial equilibrium ' // &
            '(`&time initial_equilibrium`)')
        if (row%release) call append_joined(text, ', ', 'released supports (`release_time`)')
        if (len(text) == 0) text = none
    end function prestretched_text

    !> How a driven end is prescribed (the row's `drive`).
    function drive_text(drive) result(text)
        character(len=*), intent(in) :: drive
        character(len=:), allocatable :: text
        select case (trim(drive))
        case ('pose')
            text = 'pose (`displacement`, `rotation`)'
        case ('velocity')
            text = 'velocity (`velocity`, `angular_velocity`; several `&bc` add up)'
        case default
            text = none
        end select
    end function drive_text

    !> End loads: their frames and the ends that take them.
    function end_load_text(row) result(text)
        type(capability_t), intent(in) :: row
        character(len=:), allocatable :: text
        logical :: at_start, at_end
        at_start = lists_name(row%load_places, 'start')
        at_end = lists_name(row%load_places, 'end')
        if (.not. (at_start .or. at_end)) then
            text = none
            return
        end if
        text = 'dead (spatial)'
        if (lists_name(row%load_frames, 'follower')) text = text // ' and follower'
        text = text // ' force and moment'
        if (.not. (at_start .and. at_end)) then
            if (at_end) then
                text = text // ', at s = L only'
            else
                text = text // ', at s = 0 only'
            end if
        end if
    end function end_load_text

    !> Loads per length and gravity.
    function distributed_load_text(row) result(text)
        type(capability_t), intent(in) :: row
        character(len=:), allocatable :: text
        text = ''
        if (lists_name(row%load_places, 'distributed')) text = 'force and moment per length'
        if (lists_name(row%load_places, 'gravity')) then
            if (len(text) > 0) text = text // '; '
            text = text // 'gravity'
        end if
        if (len(text) == 0) text = none
    end function distributed_load_text

end module rs_model_capability_matrix
