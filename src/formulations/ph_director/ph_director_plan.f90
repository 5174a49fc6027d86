!> What the ph_director formulation will do for one rod of a resolved, checked scene (the plan
!> of `rodsolve --check-input`, DESIGN.md §4): the rod is built as for a run and its unknowns
!> and the parts that run or are skipped are read off the built object, so the plan cannot
!> drift from what runs. It is built with at most 3 elements and its sizes at its own element
!> count come from rs_formulations_rod_sizes, so the plan of a 10^6-element rod costs no more
!> memory than that of a small one (issue 21 item 17). The bundle lines (joints, end plates,
!> contact: issue 10) are read off the resolved scene.
module rs_ph_director_plan
    use rs_core_kinds, only: rk
    use rs_core_error, only: error_t
    use rs_core_strings, only: str
    use rs_model_scene, only: scene_t, unset_real, unset_int, rod_is_damped
    use rs_model_damping, only: damping_plan_text
    use rs_model_rod_geometry, only: centreline_text
    use rs_model_units, only: unit_in_system
    use rs_model_support, only: end_hold, held_coordinates, held_names
    use rs_ph_director, only: ph_director_t
    use rs_formulations_rod_sizes, only: rod_sizes_t, rod_sizes_of, single_rod_scene
    implicit none
    private

    public :: ph_director_plan_lines

contains

    !> The plan of rod `i` of `scene` as comment lines "!     ..." (each ending in a new line),
    !> without the rod's title line; `err` if the rod cannot be built.
    subroutine ph_director_plan_lines(scene, i, text, err)
        type(scene_t), intent(in) :: scene
        integer, intent(in) :: i
        character(len=:), allocatable, intent(out) :: text
        type(error_t), allocatable, intent(out) :: err
        type(ph_director_t), allocatable :: rod
        ! The type the sizes are built with (rs_formulations_rod_sizes).
        type(ph_director_t) :: mold
        type(scene_t) :: small
        type(rod_sizes_t) :: sizes
        character(len=:), allocatable :: units
        integer :: n_free, n_stress, n_pneumatic, n_tendons, nb, p, j, n_elements, n_nodes
        integer :: n_partly_held, n_rotation_held, n_driven, ends(2)
        character(len=:), allocatable :: held_text, driven_text

        text = ''
        ! Built first without condensation, so that a request the rod cannot honour is reported
        ! here rather than logged by init; then as the run builds it. Both small: what does
        ! not depend on the element count is read off them, the sizes come from rod_sizes_of.
        small = single_rod_scene(scene, i, min(scene%rods(i)%n_elements, 3))
        small%solver%condense_stresses = .false.
        allocate(rod)
        call rod%init(small, [1], err)
        if (allocated(err)) return
        if (scene%solver%condense_stresses .and. len(condensation_obstacle()) == 0) then
            ! init does not start by freeing (STYLE.md item 8 is not met yet): a fresh object.
            deallocate(rod)
            allocate(rod)
            small%solver%condense_stresses = .true.
            call rod%init(small, [1], err)
            if (allocated(err)) return
        end if
        call rod_sizes_of(small_at_full_count(), 1, sizes, err, mold)
        if (allocated(err)) return
        units = trim(scene%run%units)
        p = rod%degree
        nb = rod%material%n_branches
        n_elements = int(sizes%n_elements)
        n_nodes = n_elements * p + 1
        ! Only the end nodes are supported (&bc acts at 'start' or 'end'). A clamped or driven
        ! node holds all of q (not a free node); a pinned, sliding or held one the coordinates
        ! it holds, with their velocities and, with the rotation, the multipliers.
        ends = [1, rod%n_nodes]
        n_free = n_nodes - count(all(rod%held(:, ends), dim=1))
        n_driven = count(rod%drive_of(ends) > 0)
        n_rotation_held = count(rod%held(4, ends))
        if (rod%condensed) then
            n_partly_held = 18 * 2 - count(rod%node_unknown(:, ends) > 0) - &
                18 * count(all(rod%held(:, ends), dim=1))
        else
            n_partly_held = 30 * 2 - count(rod%node_dof(:, ends) > 0) - &
                30 * count(all(rod%held(:, ends), dim=1))
        end if
        held_text = ''
        if (n_partly_held > 0) held_text = ', less ' // str(n_partly_held) // ' held at ' // &
            'pinned, sliding or held ends (the held coordinates, their velocities and the ' // &
            'multipliers of a held rotation)'
        driven_text = ''
        if (n_driven > 0) driven_text = '; the state also holds the 12 velocities of each ' // &
            'driven node'
        n_stress = 6 * p * (1 + nb)
        associate (input => scene%rods(i))
            call add('geometry: ' // centreline_text(input, trim(scene%run%units)))
            if (input%prestressed) then
                call add('reference: prestressed: the stress-free shape is straight (Gamma_0 = ' // &
                    '(0, 0, 1), K_0 = 0); the rod starts with the elastic stresses of its ' // &
                    'initial geometry')
            else
                call add('reference: stress-free initial geometry (its strains at the ' // &
                    str(rod%basis%n_gauss) // ' Gauss points of every element are the reference strains)')
            end if
            call add('mesh: ' // str(n_elements) // ' elements of degree ' // str(p) // ', ' // &
                str(n_nodes) // ' nodes at equal arc length, ' // str(rod%basis%n_gauss) // &
                ' Gauss points per element')
            call add('supports: ' // supports_text(scene, i))
            if (rod%condensed) then
                call add('unknowns: ' // str(int(sizes%n_unknown)) // ' Newton unknowns = ' // &
                    str(n_free) // ' free nodes x 18 (q 12, multipliers 6)' // held_text // &
                    '; velocities ' // &
                    'and the ' // &
                    str(n_elements) // ' x ' // str(n_stress) // ' element stresses are ' // &
                    'condensed (state: ' // str(int(sizes%n_state)) // ')')
            else
                call add('unknowns: ' // str(int(sizes%n_unknown)) // ' Newton unknowns = ' // &
                    str(n_free) // ' free nodes x 30 (q 12, v 12, multipliers 6)' // held_text // &
                    ' + ' // &
                    str(n_elements) // &
                    ' elements x ' // str(n_stress) // ' stresses (6 components x ' // str(p) // &
                    ' coefficients x ' // str(1 + nb) // ' branch(es))' // driven_text)
            end if
            call add('orthonormality multipliers: 6 per node whose rotation is free (' // &
                str(6 * (n_nodes - n_rotation_held)) // ')')
            call add('constraint multipliers: ' // rigid_text())
            if (nb > 0) then
                call add('Maxwell internal variables: ' // str(nb) // ' branch(es), ' // &
                    str(6 * p * nb) // ' branch stresses per element; dissipation recorded')
            else
                call add('Maxwell internal variables: none (no maxwell_fraction: skipped)')
            end if
            call add('damping: ' // damping_text())
            if (rod%quasistatic) then
                call add('mass terms: skipped (quasistatic: time is a load factor), then one ' // &
                    'endpoint equilibrium solve at t_end')
            else
                call add('mass terms: consistent mass, rhoA = ' // str(input%rhoA) // ' ' // &
                    unit_in_system('kg/m', units) // ', rhoI = ' // str(input%rhoI1) // ', ' // &
                    str(input%rhoI2) // ' ' // unit_in_system('kg m', units))
            end if
            n_tendons = count(rod%actuators%tendon)
            n_pneumatic = size(rod%actuators) - n_tendons
            if (size(rod%actuators) > 0) then
                call add('actuators: ' // str(n_pneumatic) // ' pneumatic chamber(s), ' // &
                    str(n_tendons) // ' tendon(s)')
            else
                call add('actuators: none (skipped)')
            end if
            call add('loads: ' // loads_text())
            call add('joints: ' // joints_text())
            call add('end plates: ' // plates_text())
            call add('contact: ' // contact_text())
            call add('initial velocity: ' // velocity_text())
            if (rod%condensed) then
                call add('stress condensation: on (condense_stresses = .true.)')
            else if (scene%solver%condense_stresses) then
                call add('stress condensation: requested but ignored: ' // condensation_obstacle() // &
                    ' keep the stresses as unknowns (methods/ph_director_3d.md §5.5)')
            else
                call add('stress condensation: off (condense_stresses = .false.)')
            end if
        end associate
    contains
        subroutine add(line)
            character(len=*), intent(in) :: line
            text = text // '!     ' // line // new_line('a')
        end subroutine add

        !> The small scene with the rod's own element count and the condensation as built.
        function small_at_full_count() result(full)
            type(scene_t) :: full
            full = small
            full%rods(1)%n_elements = scene%rods(i)%n_elements
            full%solver%condense_stresses = rod%condensed
        end function small_at_full_count

        !> The rod's damping as built (docs/theory/ph_director.md "Damping").
        function damping_text() result(t)
            character(len=:), allocatable :: t
            if (.not. rod_is_damped(scene%rods(i))) then
                t = 'none (no kelvin_voigt_time, drag, angular_drag: skipped)'
                return
            end if
            t = damping_plan_text(scene%rods(i))
            if (any(rod%material%viscosity > 0.0_rk)) then
                t = t // '; Kelvin-Voigt as a Maxwell branch of zero compliance, its midpoint ' // &
                    'stress condensed per element (no unknowns)'
                if (any(rod%material%compliance == 0.0_rk)) t = t // ', none on the ' // &
                    'constrained components (their strain rate is zero)'
            end if
            t = t // '; dissipation recorded'
        end function damping_text

        function loads_text() result(t)
            character(len=:), allocatable :: t
            integer :: n_end, n_distributed, n_gravity
            n_end = count(rod%loads%node > 0)
            n_gravity = 0
            do j = 1, size(scene%loads)
                if (trim(scene%loads(j)%where) /= 'gravity') cycle
                if (trim(scene%loads(j)%rod) == rod%name .or. len_trim(scene%loads(j)%rod) == 0) &
                    n_gravity = n_gravity + 1
            end do
            n_distributed = count(rod%loads%distributed) - n_gravity
            if (size(rod%loads) == 0) then
                t = 'none'
            else
                t = str(n_end) // ' end load(s), ' // str(n_distributed) // ' distributed, ' // &
                    str(n_gravity) // ' gravity; ' // str(count(rod%loads%follower)) // &
                    ' follower (components in the director basis, at the midpoint directors; ' // &
                    'their work booked at that value), the others dead (spatial)'
            end if
        end function loads_text

        !> The joints at this rod's ends, counted by kind, each with its other end.
        function joints_text() result(t)
            character(len=:), allocatable :: t, list, mine, other, other_end, tied
            integer :: n_kind(3), k
            character(len=9), parameter :: kinds(3) = [character(len=9) :: 'rigid', 'spherical', &
                'revolute']
            n_kind = 0
            list = ''
            do j = 1, size(scene%joints)
                associate (joint => scene%joints(j))
                    if (joint%rod_a == scene%rods(i)%name) then
                        mine = trim(joint%end_a)
                        other = trim(joint%rod_b)
                        other_end = trim(joint%end_b)
                    else if (joint%rod_b == scene%rods(i)%name) then
                        mine = trim(joint%end_b)
                        other = trim(joint%rod_a)
                        other_end = trim(joint%end_a)
                    else
                        cycle
                    end if
                    select case (trim(joint%kind))
                    case ('rigid')
                        tied = 'position and orientation tied'
                    case ('spherical')
                        tied = 'position tied, free relative rotation'
                    case default
                        tied = 'position tied, relative rotation about (' // &
                            vector_text(joint%axis) // ') only'
                    end select
                    do k = 1, size(kinds)
                        if (trim(joint%kind) == trim(kinds(k))) n_kind(k) = n_kind(k) + 1
                    end do
                    if (len(list) > 0) list = list // '; '
                    list = list // '''' // mine // ''' end ' // trim(joint%kind) // ' with the ''' // &
                        other_end // ''' end of rod ''' // other // ''' (' // tied // '; &joint at ' // &
                        'line ' // str(joint%input_line) // ')'
                end associate
            end do
            if (sum(n_kind) == 0) then
                t = 'none (skipped)'
                return
            end if
            t = str(sum(n_kind)) // ' (' // str(n_kind(1)) // ' rigid, ' // str(n_kind(2)) // &
                ' spherical, ' // str(n_kind(3)) // ' revolute), constraints with multipliers on ' // &
                'the end nodes: ' // list
        end function joints_text

        !> The end plates this rod is tied to: name, end, rods and how the plate moves.
        function plates_text() result(t)
            character(len=:), allocatable :: t, rods, drive
            integer :: p, k
            t = ''
            do p = 1, size(scene%plates)
                associate (plate => scene%plates(p))
                    if (.not. any(plate%rods == scene%rods(i)%name)) cycle
                    rods = ''
                    do k = 1, size(plate%rods)
                        if (len_trim(plate%rods(k)) == 0) exit
                        if (k > 1) rods = rods // ', '
                        rods = rods // '''' // trim(plate%rods(k)) // ''''
                    end do
                    if (plate%mass > 0.0_rk) then
                        drive = 'floating: mass ' // str(plate%mass) // ' ' // &
                            unit_in_system('kg', units) // ', centre of mass (' // &
                            vector_text(plate%centre) // '), inertia (' // &
                            vector_text(plate%inertia) // '), products (' // &
                            vector_text(plate%inertia_products) // ') ' // &
                            unit_in_system('kg m^2', units) // ', its body on the first rod''s end ' // &
                            'and the other ends tied to that end rigidly (6 constraint rows each; ' // &
                            '&plate at line ' // str(plate%input_line) // ')'
                        if (len(t) > 0) t = t // '; '
                        t = t // '''' // trim(plate%name) // ''' at the ''' // trim(plate%end) // &
                            ''' end of ' // rods // ', ' // drive
                        cycle
                    else if (all(plate%displacement == 0.0_rk) .and. all(plate%rotation == 0.0_rk)) then
                        drive = 'fixed'
                    else
                        drive = 'driven: displacement f(t) (' // vector_text(plate%displacement) // &
                            ') ' // unit_in_system('m', units) // ' and rotation f(t) (' // &
                            vector_text(plate%rotation) // ') rad about (' // &
                            vector_text(plate%centre) // '), f = ''' // trim(plate%time_function) // ''''
                    end if
                    if (len(t) > 0) t = t // '; '
                    t = t // '''' // trim(plate%name) // ''' at the ''' // trim(plate%end) // &
                        ''' end of ' // rods // ', ' // drive // ' (6 constraint rows per tied ' // &
                        'end; &plate at line ' // str(plate%input_line) // ')'
                end associate
            end do
            if (len(t) == 0) t = 'none (skipped)'
        end function plates_text

        !> Contact of the scene as this rod takes part in it.
        function contact_text() result(t)
            character(len=:), allocatable :: t, m, points
            real(rk) :: ratio
            if (.not. scene%contact%given) then
                t = 'none (no &contact: no contact search)'
                return
            end if
            m = unit_in_system('m', units)
            associate (c => scene%contact, input => scene%rods(i))
                points = 'derived'
                if (c%points_per_element /= unset_int) points = str(c%points_per_element)
                t = 'stiffness ' // str(c%stiffness) // ' ' // unit_in_system('N/m^3', units) // &
                    ', contact radius ' // str(input%contact_radius) // ' ' // m // ', margin ' // &
                    str(c%margin) // ' ' // m // ', skip ' // str(c%skip) // ' element(s) along a ' // &
                    'rod, points per element: ' // points // ', self contact ' // &
                    trim(merge('on ', 'off', c%self_contact)) // &
                    ', ' // friction_text() // '; candidate pairs from a cell grid ' // &
                    'rebuilt every step'
                ! Not an error: a sheath or a coating may be thicker than the section.
                if ((trim(input%section) == 'circle' .or. trim(input%section) == 'tube') .and. &
                        input%radius /= unset_real) then
                    ratio = input%contact_radius / input%radius
                    if (ratio > 2.0_rk .or. ratio < 0.5_rk) t = t // '; note: the contact ' // &
                        'radius is ' // str(ratio) // ' times the section radius ' // &
                        str(input%radius) // ' ' // m
                end if
            end associate
        end function contact_text

        !> The friction of &contact between rods.
        function friction_text() result(t)
            character(len=:), allocatable :: t
            if (scene%contact%mu == 0.0_rk) then
                t = 'frictionless'
            else
                t = 'friction mu ' // str(scene%contact%mu) // ' (regularized below ' // &
                    str(scene%contact%slip_velocity) // ' ' // unit_in_system('m/s', units) // ')'
            end if
        end function friction_text

        function velocity_text() result(t)
            character(len=:), allocatable :: t
            associate (input => scene%rods(i))
                if (all(input%velocity == 0.0_rk) .and. all(input%angular_velocity == 0.0_rk)) then
                    t = 'at rest'
                else
                    t = 'rigid motion v = (' // vector_text(input%velocity) // ') ' // &
                        unit_in_system('m/s', units) // ' + (' // vector_text(input%angular_velocity) // &
                        ') ' // unit_in_system('rad/s', units) // ' x (phi - (' // &
                        vector_text(input%rotation_center) // ')), director rates omega x d_i'
                end if
            end associate
        end function velocity_text

        !> The rigid stress components (zero compliance: multipliers, methods §2.3), from the
        !> built rod: constraint = 'kirchhoff' or 'inextensible' and &rod rigid.
        function rigid_text() result(t)
            character(len=:), allocatable :: t, names, stresses
            character(len=3), parameter :: stiffness(6) = [character(len=3) :: 'GA1', 'GA2', &
                'EA', 'EI1', 'EI2', 'GJ']
            character(len=2), parameter :: stress(6) = [character(len=2) :: 'N1', 'N2', 'N3', &
                'M1', 'M2', 'M3']
            integer :: c, n_rigid
            n_rigid = count(rod%material%compliance == 0.0_rk)
            if (n_rigid == 0) then
                t = 'none (constraint = ''none'', no rigid)'
                return
            end if
            names = ''
            stresses = ''
            do c = 1, 6
                if (rod%material%compliance(c) /= 0.0_rk) cycle
                names = join(names, trim(stiffness(c)))
                stresses = join(stresses, trim(stress(c)))
            end do
            t = 'constraint = ''' // trim(scene%rods(i)%constraint) // ''''
            if (len_trim(scene%rods(i)%rigid(1)) > 0) t = t // ' and rigid'
            t = t // ': ' // stresses // ' (' // str(n_rigid * p * n_elements) // &
                ' coefficients) are multipliers; ' // names // ' infinite (the values given not used)'
        end function rigid_text

        function condensation_obstacle() result(t)
            character(len=:), allocatable :: t
            t = ''
            if (any(rod%material%compliance == 0.0_rk)) t = 'constrained components'
            if (rod%material%n_branches > 0) t = join(t, 'Maxwell branches')
            if (rod%quasistatic) t = join(t, 'a quasistatic run')
        end function condensation_obstacle

        function join(a, b) result(t)
            character(len=*), intent(in) :: a, b
            character(len=:), allocatable :: t
            if (len(a) == 0) then
                t = b
            else
                t = a // ', ' // b
            end if
        end function join
    end subroutine ph_director_plan_lines

    !> The supports of rod `i`'s two ends: clamped (from the built rod), else held by a plate or a
    !> joint (multipliers, issue 10), else free.
    !> The supports of rod `i`'s two ends: what a &bc holds (rs_model_support), a driven end,
    !> else a body, or held by a plate or a joint (multipliers, issue 10), else free.
    function supports_text(scene, i) result(text)
        type(scene_t), intent(in) :: scene
        integer, intent(in) :: i
        character(len=:), allocatable :: text
        text = 'start ' // end_text('start') // ', end ' // end_text('end')
    contains
        function end_text(end_name) result(t)
            character(len=*), intent(in) :: end_name
            character(len=:), allocatable :: t
            logical :: mask(6), ok
            integer :: k
            do k = 1, size(scene%bcs)
                if (scene%bcs(k)%rod /= scene%rods(i)%name .or. &
                    trim(scene%bcs(k)%end) /= end_name) cycle
                call held_coordinates(end_hold(scene%bcs(k)), mask, ok)
                select case (trim(scene%bcs(k)%kind))
                case ('clamped')
                    t = 'clamped (no unknowns at its node)'
                    return
                case ('driven')
                    t = 'driven (its q prescribed: the reference pose moved by f(t) (' // &
                        vector_text(scene%bcs(k)%displacement) // ') and turned by f(t) (' // &
                        vector_text(scene%bcs(k)%rotation) // '); no unknowns at its node, its ' // &
                        'velocity the midpoint rule''s 2 dq/h - v_n, kept in the state; the ' // &
                        'drive''s work booked)'
                    return
                case ('pinned')
                    t = 'pinned (position held: no phi, v_phi unknowns; directors free with ' // &
                        'their 6 multipliers)'
                    return
                case ('sliding', 'held')
                    t = trim(scene%bcs(k)%kind) // ' (held: ' // held_names(mask) // &
                        '; those coordinates of q and their velocities are no unknowns'
                    if (mask(4)) t = t // ', nor the 6 multipliers'
                    t = t // ')'
                    return
                end select
            end do
            t = 'free'
            associate (name => scene%rods(i)%name)
                do k = 1, size(scene%bcs)
                    if (scene%bcs(k)%rod /= name .or. trim(scene%bcs(k)%end) /= end_name) cycle
                    if (trim(scene%bcs(k)%kind) /= 'body') cycle
                    associate (units => trim(scene%run%units))
                        t = 'a rigid body: mass ' // str(scene%bcs(k)%mass) // ' ' // &
                            unit_in_system('kg', units) // ', centre (' // &
                            vector_text(scene%bcs(k)%centre) // ') ' // unit_in_system('m', &
                            units) // ' from the end, inertia (' // &
                            vector_text(scene%bcs(k)%inertia) // '), products (' // &
                            vector_text(scene%bcs(k)%inertia_products) // ') ' // &
                            unit_in_system('kg m^2', units) // ' (its mass matrix on the ' // &
                            'end node, rs_ph_director_body)'
                    end associate
                    return
                end do
                if (allocated(scene%plates)) then
                    do k = 1, size(scene%plates)
                        if (trim(scene%plates(k)%end) /= end_name) cycle
                        if (.not. any(scene%plates(k)%rods == name)) cycle
                        t = 'tied to &plate ''' // trim(scene%plates(k)%name) // ''' (multipliers)'
                        if (scene%plates(k)%mass > 0.0_rk) then
                            if (scene%plates(k)%rods(1) == name) then
                                t = 'carries the body of the floating &plate ''' // &
                                    trim(scene%plates(k)%name) // ''' (rs_ph_director_body)'
                            else
                                t = 'tied rigidly to the end of rod ''' // &
                                    trim(scene%plates(k)%rods(1)) // ''', which carries the ' // &
                                    'floating &plate ''' // trim(scene%plates(k)%name) // ''' (multipliers)'
                            end if
                        end if
                        return
                    end do
                end if
                if (allocated(scene%joints)) then
                    do k = 1, size(scene%joints)
                        if ((scene%joints(k)%rod_a == name .and. trim(scene%joints(k)%end_a) == end_name) &
                                .or. (scene%joints(k)%rod_b == name .and. &
                                trim(scene%joints(k)%end_b) == end_name)) then
                            t = 'jointed (multipliers)'
                            return
                        end if
                    end do
                end if
            end associate
        end function end_text
    end function supports_text

    function vector_text(v) result(text)
        real(rk), intent(in) :: v(:)
        character(len=:), allocatable :: text
        integer :: k
        text = ''
        do k = 1, size(v)
            if (k > 1) text = text // ', '
            if (v(k) == unset_real) then
                text = text // '-'
            else
                text = text // str(v(k))
            end if
        end do
    end function vector_text

end module rs_ph_director_plan
