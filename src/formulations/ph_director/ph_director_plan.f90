!> What the ph_director formulation will do for one rod of a resolved, checked scene (the plan
!> of `rodsolve --check-input`, DESIGN.md §4): the rod is built as for a run and its unknowns
!> and the parts that run or are skipped are read off the built object, so the plan cannot
!> drift from what runs.
module rs_ph_director_plan
    use rs_core_kinds, only: rk
    use rs_core_error, only: error_t
    use rs_core_strings, only: str
    use rs_model_scene, only: scene_t, unset_real
    use rs_model_rod_geometry, only: rod_geometry_t, rod_geometry_of, helix_axis_point
    use rs_model_units, only: unit_in_system
    use rs_ph_director, only: ph_director_t
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
        type(scene_t) :: uncondensed
        character(len=:), allocatable :: units
        integer :: n_free, n_stress, n_pneumatic, n_tendons, nb, p, j

        text = ''
        ! Built first without condensation, so that a request the rod cannot honour is reported
        ! here rather than logged by init; then as the run builds it.
        uncondensed = scene
        uncondensed%solver%condense_stresses = .false.
        allocate(rod)
        call rod%init(uncondensed, [i], err)
        if (allocated(err)) return
        if (scene%solver%condense_stresses .and. len(condensation_obstacle()) == 0) then
            ! init does not start by freeing (STYLE.md item 8 is not met yet): a fresh object.
            deallocate(rod)
            allocate(rod)
            call rod%init(scene, [i], err)
            if (allocated(err)) return
        end if
        units = trim(scene%run%units)
        p = rod%degree
        nb = rod%material%n_branches
        n_free = count(.not. rod%clamped)
        n_stress = 6 * p * (1 + nb)
        associate (input => scene%rods(i))
            call add('geometry: ' // geometry_text(scene, i))
            if (input%prestressed) then
                call add('reference: prestressed: the stress-free shape is straight (Gamma_0 = ' // &
                    '(0, 0, 1), K_0 = 0); the rod starts with the elastic stresses of its ' // &
                    'initial geometry')
            else
                call add('reference: stress-free initial geometry (its strains at the ' // &
                    str(rod%basis%n_gauss) // ' Gauss points of every element are the reference strains)')
            end if
            call add('mesh: ' // str(rod%n_elements) // ' elements of degree ' // str(p) // ', ' // &
                str(rod%n_nodes) // ' nodes at equal arc length, ' // str(rod%basis%n_gauss) // &
                ' Gauss points per element')
            call add('supports: ' // supports_text(rod%clamped(1), rod%clamped(rod%n_nodes)))
            if (rod%condensed) then
                call add('unknowns: ' // str(rod%n_unknown()) // ' Newton unknowns = ' // str(n_free) // &
                    ' free nodes x 18 (q 12, multipliers 6); velocities and the ' // &
                    str(rod%n_elements) // ' x ' // str(n_stress) // ' element stresses are ' // &
                    'condensed (state: ' // str(rod%n_state()) // ')')
            else
                call add('unknowns: ' // str(rod%n_unknown()) // ' Newton unknowns = ' // str(n_free) // &
                    ' free nodes x 30 (q 12, v 12, multipliers 6) + ' // str(rod%n_elements) // &
                    ' elements x ' // str(n_stress) // ' stresses (6 components x ' // str(p) // &
                    ' coefficients x ' // str(1 + nb) // ' branch(es))')
            end if
            call add('orthonormality multipliers: 6 per free node (' // str(6 * n_free) // ')')
            select case (trim(input%constraint))
            case ('kirchhoff')
                call add('constraint multipliers: kirchhoff: the shear stresses N1, N2 (' // &
                    str(2 * p * rod%n_elements) // ' coefficients) are multipliers; GA1, GA2 not used')
            case ('inextensible')
                call add('constraint multipliers: inextensible: N1, N2, N3 (' // &
                    str(3 * p * rod%n_elements) // ' coefficients) are multipliers; GA1, GA2, EA not used')
            case default
                call add('constraint multipliers: none (constraint = ''none'')')
            end select
            if (nb > 0) then
                call add('Maxwell internal variables: ' // str(nb) // ' branch(es), ' // &
                    str(6 * p * nb) // ' branch stresses per element; dissipation recorded')
            else
                call add('Maxwell internal variables: none (no maxwell_fraction: skipped)')
            end if
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
                    str(n_gravity) // ' gravity (dead, spatial)'
            end if
        end function loads_text

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

    !> The centreline in words: its kind, parameters, length and, for a helix, its axis.
    function geometry_text(scene, i) result(text)
        type(scene_t), intent(in) :: scene
        integer, intent(in) :: i
        character(len=:), allocatable :: text, m
        type(rod_geometry_t) :: geometry
        m = unit_in_system('m', trim(scene%run%units))
        associate (rod => scene%rods(i))
            geometry = rod_geometry_of(rod)
            select case (trim(rod%geometry))
            case ('helix')
                text = 'helix of radius ' // str(rod%helix_radius) // ' ' // m // ', pitch ' // &
                    str(rod%helix_pitch) // ' ' // m // ', ' // str(rod%helix_turns) // &
                    ' turns, axis through (' // vector_text(helix_axis_point(geometry)) // &
                    ') along (' // vector_text(rod%direction) // ')'
            case ('polyline')
                text = 'polyline of ' // str(size(geometry%vertices, 2)) // ' points from (' // &
                    vector_text(rod%start) // ')'
            case default
                text = 'straight from (' // vector_text(rod%start) // ') along (' // &
                    vector_text(rod%direction) // ')'
            end select
            text = text // ', length ' // str(rod%length) // ' ' // m // ', d1(0) = (' // &
                vector_text(rod%d1) // ')'
        end associate
    end function geometry_text

    function supports_text(start_clamped, end_clamped) result(text)
        logical, intent(in) :: start_clamped, end_clamped
        character(len=:), allocatable :: text
        text = 'start ' // trim(merge('clamped (no unknowns at its node)', 'free                             ', &
            start_clamped)) // ', end ' // trim(merge('clamped (no unknowns at its node)', &
            'free                             ', end_clamped))
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
