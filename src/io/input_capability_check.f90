!> A scene against what its formulations can do (DESIGN.md §1: a scene must never silently get
!> less than it asked for), all from the formulations' descriptors (rs_formulations_registry):
!> `formulation = 'auto'` resolved per joint-connected system (the registry's planar choice when
!> the rods lie in a plane and it can run them, rs_model_planarity, else the default
!> formulation), the defaults of formulation-owned &rod variables, one formulation per jointed
!> system, and every rod, support, load, actuator, joint, plate and contact against its
!> formulation's capability row. Every problem is added to `errors`.
module rs_io_input_capability_check
    use rs_core_kinds, only: rk
    use rs_core_error, only: error_list_t
    use rs_core_strings, only: str, split_list
    use rs_model_scene, only: scene_t, rod_input_t, bc_input_t, unset_real, unset_int, rod_is_damped, &
        rod_segment_count
    use rs_model_capabilities, only: capability_t, lists_name, end_kinds_at
    use rs_model_planarity, only: plane_t, plane_of_rods, plane_text
    use rs_model_coupling, only: coupled_systems
    use rs_formulations_descriptor, only: formulation_descriptor_t
    use rs_formulations_registry, only: formulation_descriptors, descriptor_of, capability_of, &
        available_formulations, default_formulation, auto_planar_formulation, is_bundle
    use rs_io_input_check_common, only: at, rod_index, see_matrix
    implicit none
    private

    public :: resolve_auto_formulations, resolve_formulation_options, check_joint_formulations, &
        check_capabilities, check_rod_capabilities, rod_variable_given

contains


    !> `formulation = 'auto'` (DESIGN.md §4): the rods of each system of joined rods
    !> (rs_model_coupling) that say 'auto' get the registry's planar choice when the system,
    !> its loads and initial velocities lie in one plane (rs_model_planarity) and that
    !> formulation can run all they ask for, else the default (3D) formulation;
    !> formulation_reason says why.
    subroutine resolve_auto_formulations(scene)
        type(scene_t), intent(inout) :: scene
        integer, allocatable :: system_of(:), first(:), members(:), rods(:)
        type(plane_t) :: plane
        character(len=:), allocatable :: chosen, reason, obstacle, planar, spatial
        integer :: k, m
        planar = auto_planar_formulation()
        spatial = default_formulation()
        call coupled_systems(scene, system_of, first, members)
        do k = 1, size(first) - 1
            rods = members(first(k):first(k + 1) - 1)
            if (.not. any(scene%rods(rods)%formulation == 'auto')) cycle
            plane = plane_of_rods(scene, rods)
            if (plane%found) then
                obstacle = planar_obstacle(scene, rods)
                if (len(obstacle) == 0) then
                    chosen = planar
                    reason = 'the rods, loads and velocities lie in ' // plane_text(plane)
                else
                    chosen = spatial
                    reason = '3D although the rods lie in ' // plane_text(plane) // &
                        ', because ' // planar // ' cannot run them: ' // obstacle
                end if
            else
                chosen = spatial
                reason = '3D because ' // plane%reason
            end if
            do m = 1, size(rods)
                associate (rod => scene%rods(rods(m)))
                    if (rod%formulation /= 'auto') cycle
                    rod%formulation = chosen
                    rod%formulation_reason = reason
                end associate
            end do
        end do
    end subroutine resolve_auto_formulations


    !> The first thing rods `rods` (one system) ask for that the planar choice of 'auto' cannot
    !> do, without its file and line; '' if it can run them.
    function planar_obstacle(scene, rods) result(text)
        type(scene_t), intent(in) :: scene
        integer, intent(in) :: rods(:)
        character(len=:), allocatable :: text
        type(capability_t) :: row
        type(error_list_t) :: errors
        integer :: m, j, colon
        row = capability_of(auto_planar_formulation())
        do m = 1, size(rods)
            call check_rod_capabilities(scene, rods(m), row, errors)
            call check_bundle_capabilities(scene, rods(m), row, errors)
        end do
        do j = 1, size(scene%joints)
            if (.not. any(scene%rods(rods)%name == scene%joints(j)%rod_a)) cycle
            call check_joint_kind(scene, j, rod_index(scene, scene%joints(j)%rod_a), row, errors)
        end do
        text = ''
        if (errors%count == 0) return
        text = errors%joined()
        if (index(text, new_line('a')) > 0) text = text(1:index(text, new_line('a')) - 1)
        ! Drop "file:line: " (the message starts at the group name).
        colon = index(text, ': &')
        if (colon > 0) text = text(colon + 2:)
    end function planar_obstacle


    !> Rods tied by a joint are one system and need one formulation; a planar system also one
    !> n_gauss and em_variant (its elements are built alike).
    subroutine check_joint_formulations(scene, errors)
        type(scene_t), intent(in) :: scene
        type(error_list_t), intent(inout) :: errors
        character(len=:), allocatable :: why
        type(capability_t) :: row
        integer :: j, ra, rb
        do j = 1, size(scene%joints)
            associate (joint => scene%joints(j))
                ra = rod_index(scene, joint%rod_a)
                rb = rod_index(scene, joint%rod_b)
                if (ra == 0 .or. rb == 0) cycle
                if (scene%rods(ra)%formulation == scene%rods(rb)%formulation) then
                    row = capability_of(trim(scene%rods(ra)%formulation))
                    if (.not. row%planar) cycle
                    if (scene%rods(ra)%n_gauss /= scene%rods(rb)%n_gauss) call errors%add( &
                        at(scene, joint%input_line) // '&joint rod_b: rod ''' // trim(joint%rod_b) // &
                        ''' has n_gauss = ' // str(scene%rods(rb)%n_gauss) // ' but rod ''' // &
                        trim(joint%rod_a) // ''' ' // str(scene%rods(ra)%n_gauss) // '; the rods ' // &
                        'of one planar system share n_gauss')
                    if (scene%rods(ra)%em_variant /= scene%rods(rb)%em_variant) call errors%add( &
                        at(scene, joint%input_line) // '&joint rod_b: rod ''' // trim(joint%rod_b) // &
                        ''' has em_variant = ''' // trim(scene%rods(rb)%em_variant) // ''' but rod ''' // &
                        trim(joint%rod_a) // ''' ''' // trim(scene%rods(ra)%em_variant) // '''; the ' // &
                        'rods of one planar system share em_variant')
                    cycle
                end if
                why = auto_note(ra) // auto_note(rb)
                call errors%add(at(scene, joint%input_line) // '&joint rod_b: rod ''' // &
                    trim(joint%rod_b) // ''' runs on ''' // trim(scene%rods(rb)%formulation) // &
                    ''' but rod ''' // trim(joint%rod_a) // ''' on ''' // &
                    trim(scene%rods(ra)%formulation) // '''; rods tied by joints form one ' // &
                    'system and need one formulation' // why)
            end associate
        end do
    contains
        function auto_note(r) result(text)
            integer, intent(in) :: r
            character(len=:), allocatable :: text
            text = ''
            if (scene%rods(r)%formulation_origin == 'auto') text = ' (rod ''' // &
                trim(scene%rods(r)%name) // ''': ''auto'' chose ' // trim(scene%rods(r)%formulation) // &
                ', ' // trim(scene%rods(r)%formulation_reason) // ')'
        end function auto_note
    end subroutine check_joint_formulations


    !> The defaults of the &rod variables a formulation reads in its own way come from its
    !> descriptor (resolve_rod: e.g. a variant, a reduced quadrature); then n_gauss defaults to 2
    !> (a value given for another formulation is refused by check_formulation_variables).
    subroutine resolve_formulation_options(scene)
        type(scene_t), intent(inout) :: scene
        type(formulation_descriptor_t) :: d
        integer :: i
        do i = 1, size(scene%rods)
            associate (rod => scene%rods(i))
                if (descriptor_of(trim(rod%formulation), d)) then
                    if (associated(d%resolve_rod)) call d%resolve_rod(rod)
                end if
                if (rod%n_gauss == unset_int) rod%n_gauss = 2
            end associate
        end do
    end subroutine resolve_formulation_options


    !> A scene must never silently get less than it asked for (DESIGN.md §1): every rod's
    !> formulation must be available and able to do what the rod, its supports, loads and
    !> actuators and the time settings ask.
    subroutine check_capabilities(scene, errors)
        type(scene_t), intent(in) :: scene
        type(error_list_t), intent(inout) :: errors
        type(capability_t) :: row
        integer :: i, j, ra, rb
        do i = 1, size(scene%rods)
            associate (rod => scene%rods(i))
                row = capability_of(trim(rod%formulation))
                if (.not. row%available) then
                    call errors%add(at(scene, rod%input_line) // '&rod formulation: ''' // &
                        trim(rod%formulation) // ''' is not available in this version; available: ' // &
                        available_formulations() // see_matrix)
                    cycle
                end if
                call check_rod_capabilities(scene, i, row, errors)
                call check_formulation_variables(scene, i, row, errors)
                call check_bundle_capabilities(scene, i, row, errors)
            end associate
        end do
        if (allocated(scene%joints)) then
            do j = 1, size(scene%joints)
                ra = rod_index(scene, scene%joints(j)%rod_a)
                rb = rod_index(scene, scene%joints(j)%rod_b)
                if (ra == 0 .or. rb == 0) cycle
                call check_jointed_ends(scene, j, ra, rb, errors)
                row = capability_of(trim(scene%rods(ra)%formulation))
                if (row%available) call check_joint_kind(scene, j, ra, row, errors)
                if (scene%rods(rb)%formulation == scene%rods(ra)%formulation) cycle
                row = capability_of(trim(scene%rods(rb)%formulation))
                if (row%available) call check_joint_kind(scene, j, rb, row, errors)
            end do
        end if
        call check_planar_systems(scene, errors)
        call check_one_formulation_per_system(scene, errors)
        call check_prestretched_starts(scene, errors)
    end subroutine check_capabilities

    !> Prestretched starts (issue 26 item 3; docs/theory/prestretched_starts.md), besides the
    !> capability rows: the initial equilibrium is a dynamic run's and is solved per member
    !> (the continuation of DESIGN.md §3, which coupled systems do not have); a released end is
    !> a clamped or pinned one that nothing else ties; a prestrain needs an extensible rod.
    subroutine check_prestretched_starts(scene, errors)
        type(scene_t), intent(in) :: scene
        type(error_list_t), intent(inout) :: errors
        integer, allocatable :: system_of(:), first(:), members(:)
        character(len=:), allocatable :: here
        integer :: s, i, j
        here = at(scene, scene%time%input_line) // '&time initial_equilibrium: '
        if (scene%time%initial_equilibrium) then
            if (scene%time%quasistatic) call errors%add(here // 'a quasistatic run starts ' // &
                'in equilibrium already (equilibrium_solves); it is for dynamic runs')
            if (scene%time%relaxation) call errors%add(here // 'relaxation runs to rest from ' // &
                'its start; choose one of relaxation and initial_equilibrium')
            call coupled_systems(scene, system_of, first, members)
            do s = 1, size(first) - 1
                if (.not. is_bundle(scene, members(first(s):first(s + 1) - 1))) cycle
                call errors%add(here // 'rod ''' // trim(scene%rods(members(first(s)))%name) // &
                    ''' is coupled to other rods (&joint, &plate or &contact through the ' // &
                    'system layer), whose equilibrium is not continued yet')
            end do
            if (allocated(scene%obstacles)) then
                if (size(scene%obstacles) > 0) call errors%add(here // 'not with &obstacle ' // &
                    '(an obstacle coupling has no continued equilibrium yet)')
            end if
            do i = 1, size(scene%rods)
                associate (rod => scene%rods(i))
                    if (any(rod%velocity /= 0.0_rk) .or. any(rod%angular_velocity /= 0.0_rk)) &
                        call errors%add(at(scene, rod%input_line) // '&rod velocity, ' // &
                        'angular_velocity: rod ''' // trim(rod%name) // ''' is given an ' // &
                        'initial motion, but with &time initial_equilibrium the dynamics ' // &
                        'start at rest in the equilibrium; allowed: 0, 0, 0')
                end associate
            end do
        end if
        do i = 1, size(scene%rods)
            associate (rod => scene%rods(i))
                if (rod%prestrain == 0.0_rk) cycle
                if (trim(rod%constraint) == 'inextensible' .or. any(rod%rigid == 'EA')) &
                    call errors%add(at(scene, rod%input_line) // '&rod prestrain: rod ''' // &
                    trim(rod%name) // ''' is inextensible (constraint or rigid EA), so it has ' // &
                    'no stress-free length other than its given one; remove prestrain')
            end associate
        end do
        do j = 1, size(scene%bcs)
            associate (bc => scene%bcs(j))
                if (bc%release_time == unset_real) cycle
                if (trim(bc%kind) /= 'clamped' .and. trim(bc%kind) /= 'pinned') &
                    call errors%add(at(scene, bc%input_line) // '&bc release_time: only a ' // &
                    'clamped or pinned end is released, this one is ''' // trim(bc%kind) // '''')
                if (end_is_tied(bc%rod, bc%end)) call errors%add(at(scene, bc%input_line) // &
                    '&bc release_time: the ''' // trim(bc%end) // ''' end of rod ''' // &
                    trim(bc%rod) // ''' is also tied by a &joint or &plate; a released end ' // &
                    'must be held by its support alone')
            end associate
        end do
    contains
        logical function end_is_tied(rod_name, end_name)
            character(len=*), intent(in) :: rod_name, end_name
            integer :: k
            end_is_tied = .false.
            if (allocated(scene%joints)) then
                do k = 1, size(scene%joints)
                    associate (joint => scene%joints(k))
                        if ((joint%rod_a == rod_name .and. joint%end_a == end_name) .or. &
                            (joint%rod_b == rod_name .and. joint%end_b == end_name)) &
                            end_is_tied = .true.
                    end associate
                end do
            end if
            if (allocated(scene%plates)) then
                do k = 1, size(scene%plates)
                    if (any(scene%plates(k)%rods == rod_name) .and. &
                        scene%plates(k)%end == end_name) end_is_tied = .true.
                end do
            end if
        end function end_is_tied
    end subroutine check_prestretched_starts

    !> The rods of one coupled system (joints, plates, contact; rs_model_coupling) run on one
    !> formulation: its couplings act in that formulation's coordinates and rows (ties in its
    !> own coordinates, forces scaled as its rows are; src/system/). 'auto' is resolved per
    !> system elsewhere.
    subroutine check_one_formulation_per_system(scene, errors)
        type(scene_t), intent(in) :: scene
        type(error_list_t), intent(inout) :: errors
        integer, allocatable :: system_of(:), first(:), members(:)
        integer :: s, k, lead, other
        call coupled_systems(scene, system_of, first, members)
        do s = 1, size(first) - 1
            lead = members(first(s))
            if (trim(scene%rods(lead)%formulation) == 'auto') cycle
            do k = first(s) + 1, first(s + 1) - 1
                other = members(k)
                if (trim(scene%rods(other)%formulation) == 'auto') cycle
                if (scene%rods(other)%formulation == scene%rods(lead)%formulation) cycle
                call errors%add(at(scene, scene%rods(other)%input_line) // '&rod formulation: ' // &
                    'rod ''' // trim(scene%rods(other)%name) // ''' runs on ''' // &
                    trim(scene%rods(other)%formulation) // ''' but is coupled (joints, plates ' // &
                    'or contact) with rod ''' // trim(scene%rods(lead)%name) // ''' on ''' // &
                    trim(scene%rods(lead)%formulation) // '''; the rods of one coupled system ' // &
                    'run on one formulation' // see_matrix)
            end do
        end do
    end subroutine check_one_formulation_per_system


    !> End plates and contact against `row` (rod `i`'s formulation, or the planar choice of
    !> 'auto'):
    !> a &plate naming rod `i` needs end plates, &contact needs contact of every rod.
    subroutine check_bundle_capabilities(scene, i, row, errors)
        type(scene_t), intent(in) :: scene
        integer, intent(in) :: i
        type(capability_t), intent(in) :: row
        type(error_list_t), intent(inout) :: errors
        integer :: p
        associate (rod => scene%rods(i))
            if (allocated(scene%plates) .and. .not. row%end_plates) then
                do p = 1, size(scene%plates)
                    if (.not. any(scene%plates(p)%rods == rod%name)) cycle
                    call errors%add(at(scene, scene%plates(p)%input_line) // '&plate rods: end ' // &
                        'plates are not available for formulation ''' // trim(row%formulation) // &
                        ''' (rod ''' // trim(rod%name) // ''')' // see_matrix)
                end do
            end if
            if (scene%contact%given .and. .not. row%contact) call errors%add(at(scene, &
                scene%contact%input_line) // '&contact: rod-rod contact is not available for ' // &
                'formulation ''' // trim(row%formulation) // ''' (rod ''' // trim(rod%name) // &
                '''); with &contact every rod of the scene must run on a formulation with ' // &
                'contact' // see_matrix)
            ! Obstacles act through the same node access as contact (rs_system_obstacle_coupling).
            if (allocated(scene%obstacles) .and. .not. row%contact) then
                if (size(scene%obstacles) > 0) call errors%add(at(scene, &
                    scene%obstacles(1)%input_line) // '&obstacle: obstacles are not available ' // &
                    'for formulation ''' // trim(row%formulation) // ''' (rod ''' // &
                    trim(rod%name) // '''); every rod of a scene with obstacles must run on a ' // &
                    'formulation with contact' // see_matrix)
            end if
        end associate
    end subroutine check_bundle_capabilities


    !> Joints that are constraints with multipliers (a 3D formulation) tie free
    !> ends: a jointed end carries no &bc other than 'free' (a clamped or driven end would be
    !> held twice and the multipliers would not be unique). Planar formulations share the nodal
    !> unknowns instead and keep their supports.
    subroutine check_jointed_ends(scene, j, ra, rb, errors)
        type(scene_t), intent(in) :: scene
        integer, intent(in) :: j, ra, rb
        type(error_list_t), intent(inout) :: errors
        type(capability_t) :: row
        character(len=:), allocatable :: end_name, variable
        integer :: side, r, b
        associate (joint => scene%joints(j))
            do side = 1, 2
                if (side == 1) then
                    r = ra
                    end_name = trim(joint%end_a)
                    variable = 'end_a'
                else
                    r = rb
                    end_name = trim(joint%end_b)
                    variable = 'end_b'
                end if
                row = capability_of(trim(scene%rods(r)%formulation))
                if (.not. row%available .or. row%planar) cycle
                if (.not. lists_name(row%joints, joint%kind)) cycle
                do b = 1, size(scene%bcs)
                    if (scene%bcs(b)%rod /= scene%rods(r)%name .or. trim(scene%bcs(b)%end) /= end_name) &
                        cycle
                    if (trim(scene%bcs(b)%kind) == 'free') cycle
                    call errors%add(at(scene, joint%input_line) // '&joint ' // variable // ': the ''' // &
                        end_name // ''' end of rod ''' // trim(scene%rods(r)%name) // ''' has a ''' // &
                        trim(scene%bcs(b)%kind) // ''' &bc (line ' // str(scene%bcs(b)%input_line) // &
                        '); a clamped or driven end cannot also be jointed (formulation ''' // &
                        trim(row%formulation) // ''' ties joints by multipliers between free ends): ' // &
                        'remove the &bc or the joint')
                end do
            end do
        end associate
    end subroutine check_jointed_ends


    !> Variables that only some formulations read: a formulation's descriptor checks the values
    !> it reads in its own way (check_rod: e.g. the planar elements' n_gauss), and a variable
    !> that another formulation owns (own_rod_variables: e.g. a variant of the element, a
    !> damping of its own) is refused when given, since this rod's formulation would ignore it.
    subroutine check_formulation_variables(scene, i, row, errors)
        type(scene_t), intent(in) :: scene
        integer, intent(in) :: i
        type(capability_t), intent(in) :: row
        type(error_list_t), intent(inout) :: errors
        character(len=:), allocatable :: here, variable
        type(formulation_descriptor_t), allocatable :: list(:)
        type(formulation_descriptor_t) :: own
        character(len=32), allocatable :: variables(:)
        integer :: k, v
        associate (rod => scene%rods(i))
            here = at(scene, rod%input_line) // '&rod ''' // trim(rod%name) // ''' '
            if (descriptor_of(trim(row%formulation), own)) then
                if (associated(own%check_rod)) call own%check_rod(rod, here, errors)
            end if
            list = formulation_descriptors()
            do k = 1, size(list)
                if (trim(list(k)%name) == trim(row%formulation)) cycle
                if (len_trim(list(k)%own_rod_variables) == 0) cycle
                variables = split_list(list(k)%own_rod_variables)
                do v = 1, size(variables)
                    variable = trim(variables(v))
                    if (lists_name(own%own_rod_variables, variable)) cycle
                    if (rod_variable_given(rod, variable)) call errors%add(here // variable // &
                        ': only used with formulation ''' // trim(list(k)%name) // ''' (this ' // &
                        'rod runs on ''' // trim(row%formulation) // '''); remove it')
                end do
            end do
        end associate
    end subroutine check_formulation_variables

    !> The formulation-owned &rod variable `name` has a value on `rod` (a text other than blank,
    !> a number other than 0, the defaults of docs/user/input.md); `known` is false for a name
    !> this function cannot read (then `given` is false: the unit test of this module checks
    !> that every descriptor's own_rod_variables are known).
    logical function rod_variable_given(rod, name, known) result(given)
        type(rod_input_t), intent(in) :: rod
        character(len=*), intent(in) :: name
        logical, intent(out), optional :: known
        if (present(known)) known = .true.
        select case (name)
        case ('em_variant')
            given = len_trim(rod%em_variant) > 0
        case ('free_end')
            given = len_trim(rod%free_end) > 0
        case ('external_damping')
            given = rod%external_damping /= 0.0_rk
        case ('internal_damping')
            given = rod%internal_damping /= 0.0_rk
        case default
            given = .false.
            if (present(known)) known = .false.
        end select
    end function rod_variable_given


    !> The kind of joint `j` against `row`, the capability row of rod `r`'s formulation, and its
    !> axis: a revolute joint of a 3D formulation needs a non-zero axis, a planar formulation
    !> turns about the plane normal and refuses one.
    subroutine check_joint_kind(scene, j, r, row, errors)
        type(scene_t), intent(in) :: scene
        integer, intent(in) :: j, r
        type(capability_t), intent(in) :: row
        type(error_list_t), intent(inout) :: errors
        character(len=:), allocatable :: available, here, what
        associate (joint => scene%joints(j))
            here = at(scene, joint%input_line) // '&joint '
            what = 'formulation ''' // trim(row%formulation) // ''' (rod ''' // &
                trim(scene%rods(r)%name) // ''')'
            if (.not. lists_name(row%joints, joint%kind)) then
                available = trim(row%joints)
                if (len(available) == 0) available = 'none'
                call errors%add(here // 'kind: ''' // trim(joint%kind) // ''' joints are not ' // &
                    'available for ' // what // '; available: ' // available // see_matrix)
                return
            end if
            if (trim(joint%kind) /= 'revolute') return
            if (row%planar) then
                if (any(joint%axis /= unset_real)) call errors%add(here // 'axis: ' // what // &
                    ' is planar: its revolute joints turn about the plane normal and take no ' // &
                    'axis; remove axis')
            else if (all(joint%axis == unset_real)) then
                call errors%add(here // 'axis: required for a revolute joint of ' // what // &
                    ': the hinge axis, about which alone the two ends turn relative to each ' // &
                    'other (e.g. axis = 0, 0, 1)')
            else if (all(joint%axis == 0.0_rk)) then
                call errors%add(here // 'axis: must not be the zero vector (the hinge axis of a ' // &
                    'revolute joint)')
            end if
        end associate
    end subroutine check_joint_kind


    !> A planar formulation needs its system of joined rods, their loads and initial velocities
    !> in one plane (rs_model_planarity); reported once per system, at its first planar rod.
    subroutine check_planar_systems(scene, errors)
        type(scene_t), intent(in) :: scene
        type(error_list_t), intent(inout) :: errors
        integer, allocatable :: system_of(:), first(:), members(:), rods(:)
        type(plane_t) :: plane
        type(capability_t) :: row
        integer :: k, m
        call coupled_systems(scene, system_of, first, members)
        do k = 1, size(first) - 1
            rods = members(first(k):first(k + 1) - 1)
            do m = 1, size(rods)
                row = capability_of(trim(scene%rods(rods(m))%formulation))
                if (.not. row%planar) cycle
                plane = plane_of_rods(scene, rods)
                if (.not. plane%found) call errors%add(at(scene, scene%rods(rods(m))%input_line) // &
                    '&rod formulation: ''' // trim(row%formulation) // ''' is planar, but rod ''' // &
                    trim(scene%rods(rods(m))%name) // '''' // joined_text(size(rods)) // &
                    ' and everything acting on them do not lie in one plane: ' // plane%reason // &
                    '; use ''' // default_formulation() // ''' (3D) or ''auto''')
                exit
            end do
        end do
    contains
        function joined_text(n) result(text)
            integer, intent(in) :: n
            character(len=:), allocatable :: text
            text = ''
            if (n > 1) text = ' (with the ' // str(n - 1) // ' rod(s) joined to it)'
        end function joined_text
    end subroutine check_planar_systems


    !> Rod `i` of `scene` against capability row `row` (that of its formulation; any row in a
    !> unit test): its constraint and Maxwell branches, quasistatics and relaxation, the kinds
    !> of its supports (per end, and how a driven end is moved), loads and actuators.
    subroutine check_rod_capabilities(scene, i, row, errors)
        type(scene_t), intent(in) :: scene
        integer, intent(in) :: i
        type(capability_t), intent(in) :: row
        type(error_list_t), intent(inout) :: errors
        character(len=:), allocatable :: what
        character(len=5), parameter :: end_names(2) = [character(len=5) :: 'start', 'end']
        integer :: j, e
        associate (rod => scene%rods(i))
            what = 'formulation ''' // trim(row%formulation) // ''''
            ! &rod rigid (issue 26 item 2): a formulation whose constraints list 'rigid'.
            if (len_trim(rod%rigid(1)) > 0 .and. .not. lists_name(row%constraints, 'rigid')) &
                call errors%add(at(scene, rod%input_line) // '&rod rigid: infinite stiffnesses ' // &
                'are not available for ' // what // ' (docs/user/capabilities.md)')
            if (.not. lists_name(row%constraints, rod%constraint)) call errors%add(at(scene, &
                rod%input_line) // '&rod constraint: ''' // trim(rod%constraint) // &
                ''' is not available for ' // what // '; available: ' // trim(row%constraints) // &
                see_matrix)
            if (any(rod%maxwell_fraction /= unset_real) .and. .not. row%viscoelastic) call errors%add( &
                at(scene, rod%input_line) // '&rod maxwell_fraction: Maxwell branches ' // &
                '(viscoelasticity) are not available for ' // what // ' (rod ''' // trim(rod%name) // &
                ''')' // see_matrix)
            if (rod_is_damped(rod) .and. .not. row%damping) call errors%add(at(scene, &
                rod%input_line) // '&rod kelvin_voigt_time, drag, angular_drag: damping is not ' // &
                'available for ' // what // ' (rod ''' // trim(rod%name) // ''')' // see_matrix)
            if (rod_segment_count(scene, rod%name) > 0 .and. .not. row%segments) call errors%add( &
                at(scene, rod%input_line) // '&segment: properties that vary along the rod ' // &
                '(rod ''' // trim(rod%name) // ''', ' // str(rod_segment_count(scene, rod%name)) // &
                ' &segment groups) are not available for ' // what // '; give the rod one ' // &
                'section or use another formulation' // see_matrix)
            if (trim(rod%geometry) /= 'straight' .and. .not. row%curved_reference) call errors%add( &
                at(scene, rod%input_line) // '&rod geometry: a curved reference (''' // &
                trim(rod%geometry) // ''') is not available for ' // what // ' (rod ''' // &
                trim(rod%name) // '''); available: ''straight''' // see_matrix)
            if (rod%prestressed .and. .not. row%prestressed) call errors%add(at(scene, &
                rod%input_line) // '&rod prestressed: a straight stress-free shape under a ' // &
                'curved initial one is not available for ' // what // ' (rod ''' // &
                trim(rod%name) // '''): it would be ignored' // see_matrix)
            if (rod%prestrain /= 0.0_rk .and. .not. row%prestrain) call errors%add(at(scene, &
                rod%input_line) // '&rod prestrain: an axial prestrain is not available for ' // &
                what // ' (rod ''' // trim(rod%name) // '''): it would be ignored' // see_matrix)
            if (scene%time%initial_equilibrium .and. .not. row%initial_equilibrium) &
                call errors%add(at(scene, scene%time%input_line) // '&time ' // &
                'initial_equilibrium: a start in static equilibrium is not available for ' // &
                what // ' (rod ''' // trim(rod%name) // '''); start from the stress-free or ' // &
                'prestrained placement instead' // see_matrix)
            if (scene%time%quasistatic .and. .not. row%quasistatic) call errors%add(at(scene, 0) // &
                '&time quasistatic: not available for ' // what // ' (rod ''' // trim(rod%name) // &
                ''')' // see_matrix)
            if (trim(scene%time%continuation) == 'arc_length' .and. .not. row%continuation) &
                call errors%add(at(scene, scene%time%input_line) // '&time continuation: ' // &
                'arc-length continuation is not available for ' // what // ' (rod ''' // &
                trim(rod%name) // '''); use load steps (continuation = ''none'')' // see_matrix)
            if (scene%time%relaxation .and. .not. row%relaxation) call errors%add(at(scene, 0) // &
                '&time relaxation: statics by damped dynamics is not available for ' // what // &
                ' (rod ''' // trim(rod%name) // ''')' // see_matrix)
            if (scene%time%order == 4 .and. .not. row%order_4) call errors%add(at(scene, &
                scene%time%input_line) // '&time order: 4 is not available for ' // what // ' (rod ''' // trim(rod%name) // &
                '''): its step is not symmetric, so composing it gains no order' // see_matrix)
            if (scene%time%adaptive .and. .not. row%adaptive) call errors%add(at(scene, &
                scene%time%input_line) // '&time adaptive: error-controlled steps are not available for ' // what // &
                ' (rod ''' // trim(rod%name) // ''')' // see_matrix)
            if (scene%modes%given) call check_modes(rod, row, what)
            if (trim(scene%time%scheme) == 'generalized_alpha' .and. .not. row%generalized_alpha) &
                call errors%add(at(scene, scene%time%input_line) // '&time scheme: ' // &
                '''generalized_alpha'' is not ' // &
                'available for ' // what // ' (rod ''' // trim(rod%name) // '''); use ' // &
                'scheme = ''midpoint''' // see_matrix)
            do j = 1, size(scene%bcs)
                associate (bc => scene%bcs(j))
                    if (bc%rod /= rod%name .or. len_trim(bc%kind) == 0) cycle
                    if (.not. lists_name(end_kinds_at(row, bc%end), bc%kind)) then
                        if (end_kinds_at(row, bc%end) == trim(row%end_kinds)) then
                            call errors%add(at(scene, bc%input_line) // '&bc kind: a ''' // &
                                trim(bc%kind) // ''' end is not available for ' // what // &
                                '; available: ' // trim(row%end_kinds) // see_matrix)
                        else
                            call errors%add(at(scene, bc%input_line) // '&bc kind: a ''' // &
                                trim(bc%kind) // ''' end is not available at the ''' // &
                                trim(bc%end) // ''' end (s = L) for ' // what // '; available ' // &
                                'there: ' // end_kinds_at(row, bc%end) // ' (at the ''start'' ' // &
                                'end: ' // trim(row%end_kinds) // ')' // trim(row%end_kinds_note) // &
                                see_matrix)
                        end if
                        cycle
                    end if
                    if (trim(bc%kind) == 'driven') call check_drive(bc)
                    if (trim(bc%kind) == 'held' .and. any(bc%hold == 'twist') .and. &
                        .not. row%held_twist) call errors%add(at(scene, bc%input_line) // &
                        '&bc hold: ''twist'' (the rotation about the end''s axis alone) ' // &
                        'is not available for ' // what // '; available: ''x'', ''y'', ' // &
                        '''z'', ''rotation''' // see_matrix)
                    if (bc%release_time /= unset_real .and. .not. row%release) &
                        call errors%add(at(scene, bc%input_line) // '&bc release_time: a ' // &
                        'support released at a time is not available for ' // what // &
                        ' (rod ''' // trim(rod%name) // ''')' // see_matrix)
                end associate
            end do
            ! An end without &bc is free: refused where the formulation cannot leave it free.
            do e = 1, 2
                if (lists_name(end_kinds_at(row, end_names(e)), 'free')) cycle
                if (any(scene%bcs%rod == rod%name .and. scene%bcs%end == end_names(e))) cycle
                call errors%add(at(scene, rod%input_line) // '&bc: rod ''' // trim(rod%name) // &
                    ''' has no &bc at its ''' // trim(end_names(e)) // ''' end, i.e. a free end, ' // &
                    'which is not available there for ' // what // '; available: ' // &
                    end_kinds_at(row, end_names(e)) // trim(row%end_kinds_note) // see_matrix)
            end do
            do j = 1, size(scene%loads)
                associate (load => scene%loads(j))
                    if (load%rod /= rod%name .and. len_trim(load%rod) > 0) cycle
                    if (len_trim(load%where) == 0) cycle
                    if (.not. lists_name(row%load_places, load%where)) call errors%add(at(scene, &
                        load%input_line) // '&load where: ''' // trim(load%where) // &
                        ''' is not available for ' // what // '; available: ' // &
                        trim(row%load_places) // see_matrix)
                    if (.not. lists_name(row%load_frames, load%frame)) call errors%add(at(scene, &
                        load%input_line) // '&load frame: ''' // trim(load%frame) // &
                        ''' loads are not available for ' // what // '; available: ' // &
                        trim(row%load_frames) // see_matrix)
                end associate
            end do
            if (.not. allocated(scene%actuators) .or. row%actuation) return
            do j = 1, size(scene%actuators)
                associate (act => scene%actuators(j))
                    if (act%rod == rod%name) call errors%add(at(scene, act%input_line) // &
                        '&actuator kind: ''' // trim(act%kind) // &
                        ''' actuators (actuation) are not ' // &
                        'available for ' // what // ' (rod ''' // trim(rod%name) // ''')' // see_matrix)
                end associate
            end do
        end associate
    contains
        !> A driven end is moved as the formulation drives ends: by its pose or its velocity.
        subroutine check_drive(bc)
            type(bc_input_t), intent(in) :: bc
            select case (trim(row%drive))
            case ('pose')
                if (any(bc%velocity /= 0.0_rk) .or. any(bc%angular_velocity /= 0.0_rk)) &
                    call errors%add(at(scene, bc%input_line) // '&bc velocity, angular_velocity: ' // &
                    what // ' drives an end by its pose; give displacement and rotation instead' // &
                    see_matrix)
            case ('velocity')
                if (any(bc%displacement /= 0.0_rk) .or. any(bc%rotation /= 0.0_rk)) &
                    call errors%add(at(scene, bc%input_line) // '&bc displacement, rotation: ' // &
                    what // ' drives an end by its velocity; give velocity and angular_velocity ' // &
                    'instead' // see_matrix)
            end select
        end subroutine check_drive

        !> &modes: a formulation with modal analysis, of damped rods where it solves them
        !> (capability_t%damped_modes; docs/theory/modes.md), and about = 'equilibrium'
        !> only after a quasistatic run. The modes are those of the dynamic midpoint step
        !> whatever the run's scheme (rs_app_run_modes builds it). The scene-wide condition
        !> is reported with the first rod only.
        subroutine check_modes(rod, row, what)
            type(rod_input_t), intent(in) :: rod
            type(capability_t), intent(in) :: row
            character(len=*), intent(in) :: what
            character(len=:), allocatable :: here
            here = at(scene, scene%modes%input_line) // '&modes: '
            if (.not. row%modes) then
                call errors%add(here // 'modal analysis is not available for ' // what // &
                    ' (rod ''' // trim(rod%name) // ''')' // see_matrix)
                return
            end if
            if (.not. row%damped_modes .and. rod_is_damped(rod)) call errors%add(here // &
                'modes of a damped rod (''' // trim(rod%name) // ''') are not available for ' // &
                what // ' yet; remove kelvin_voigt_time, drag and angular_drag' // see_matrix)
            if (trim(scene%modes%kind) == 'buckling' .and. .not. row%buckling) &
                call errors%add(here // 'linearized buckling (kind = ''buckling'') is not ' // &
                'available for ' // what // ' (rod ''' // trim(rod%name) // ''')' // see_matrix)
            if (i > 1) return
            if (trim(scene%modes%about) == 'equilibrium' .and. .not. scene%time%quasistatic) &
                call errors%add(here // 'about = ''equilibrium'' is the endpoint of a ' // &
                'quasistatic run (&time quasistatic = .true.); a dynamic run ends in motion')
            if (trim(scene%modes%kind) == 'buckling' .and. trim(scene%modes%about) /= &
                'equilibrium') call errors%add(here // 'kind = ''buckling'' compares the ' // &
                'equilibrium under the loads with the reference state: give about = ' // &
                '''equilibrium'' (docs/theory/modes.md)')
            if (allocated(scene%sweeps)) then
                if (size(scene%sweeps) > 0) call errors%add(here // 'not available with ' // &
                    '&sweep yet: a sweep''s members are written without their modes')
            end if
        end subroutine check_modes
    end subroutine check_rod_capabilities

end module rs_io_input_capability_check
