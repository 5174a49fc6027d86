!> Resolution and cross-checks of a scene that was read without errors (DESIGN.md §6): fills
!> derived defaults (rod names, formulations, the centreline's start, direction and length,
!> directors, the centre of the initial rotation, stiffnesses from section and material,
!> Maxwell shear relaxation times, output path) and checks what no single variable can (a &bc
!> on a rod that does not exist, an end supported twice, a table that is not increasing, dt
!> above t_end, Maxwell fractions that leave no elastic branch, an actuator without its force,
!> a helix length that contradicts its turns, a polyline that doubles back, an initial velocity
!> at a clamped end, ...). Every problem is added to `errors`, naming the file, line, group and
!> variable.
module rs_io_input_check
    use rs_core_kinds, only: rk
    use rs_core_error, only: error_list_t
    use rs_core_strings, only: str
    use rs_model_scene, only: scene_t, rod_input_t, actuator_input_t, unset_real, section_derived_names
    use rs_model_rod_geometry, only: rod_geometry_t, straight_geometry, helix_geometry, &
        polyline_geometry, centreline_tangent, default_normal
    use rs_model_section, only: section_properties_t, circle_section, tube_section, rectangle_section
    use rs_model_capabilities, only: capability_t, capability_of, lists_name
    use rs_io_result_file, only: unknown_fields, selectable_fields
    implicit none
    private

    public :: resolve_scene, default_output_path, check_capabilities, check_rod_capabilities

    !> Where capability messages send the reader.
    character(len=*), parameter :: see_matrix = ' (docs/user/capabilities.md)'

    !> Deviation from unit length or orthogonality that counts as round-off.
    real(rk), parameter :: round_off = 4.0_rk * epsilon(1.0_rk)
    !> Relative difference below which a given length agrees with a derived one.
    real(rk), parameter :: length_tolerance = 1.0e-9_rk
    !> Largest |t_j + t_{j+1}| of consecutive polyline tangents that counts as a reversal.
    real(rk), parameter :: reversal_tolerance = 1.0e-8_rk

contains

    !> Fill derived defaults of `scene` and cross-check it; problems go to `errors`.
    subroutine resolve_scene(scene, errors)
        type(scene_t), intent(inout) :: scene
        type(error_list_t), intent(inout) :: errors
        integer :: i

        if (len_trim(scene%output%path) == 0) scene%output%path = default_output_path(scene%source_file)
        if (scene%time%dt /= unset_real .and. scene%time%t_end /= unset_real) then
            if (scene%time%dt > scene%time%t_end) call errors%add(at(scene, 0) // '&time dt: ' // &
                str(scene%time%dt) // ' is larger than t_end = ' // str(scene%time%t_end))
        end if
        call check_output_and_restart(scene, errors)
        if (size(scene%rods) == 0) call errors%add(scene%source_file // ': the scene has no &rod group')
        do i = 1, size(scene%rods)
            call resolve_rod(scene, i, errors)
        end do
        call check_unique_names(scene, errors)
        call check_bcs(scene, errors)
        call check_loads(scene, errors)
        call check_actuators(scene, errors)
    end subroutine resolve_scene

    !> 'out/<scene name>.h5' for scene file '<dir>/<scene name>.nml'.
    pure function default_output_path(source_file) result(path)
        character(len=*), intent(in) :: source_file
        character(len=:), allocatable :: path
        integer :: slash, dot
        slash = index(source_file, '/', back=.true.)
        path = source_file(slash + 1:)
        dot = index(path, '.', back=.true.)
        if (dot > 1) path = path(1:dot - 1)
        path = 'out/' // path // '.h5'
    end function default_output_path

    pure function at(scene, line) result(prefix)
        type(scene_t), intent(in) :: scene
        integer, intent(in) :: line
        character(len=:), allocatable :: prefix
        if (line > 0) then
            prefix = scene%source_file // ':' // str(line) // ': '
        else
            prefix = scene%source_file // ': '
        end if
    end function at

    subroutine resolve_rod(scene, i, errors)
        type(scene_t), intent(inout) :: scene
        integer, intent(in) :: i
        type(error_list_t), intent(inout) :: errors
        character(len=:), allocatable :: here
        type(rod_geometry_t) :: geometry
        real(rk) :: t(3), d1(3)
        logical :: ok

        associate (rod => scene%rods(i))
            if (len_trim(rod%name) == 0) rod%name = 'rod' // str(i)
            here = at(scene, rod%input_line) // '&rod ''' // trim(rod%name) // ''' '
            if (len_trim(rod%formulation) == 0) then
                rod%formulation = scene%run%formulation_default
                rod%formulation_origin = 'default'
            else
                rod%formulation_origin = 'rod'
            end if
            ! 'auto' picks the planar formulation for planar scenes (DESIGN.md §4) once one is
            ! available; until then every scene runs on the 3D ph_director.
            if (rod%formulation == 'auto') then
                rod%formulation = 'ph_director'
                rod%formulation_origin = 'auto'
            end if
            call resolve_geometry(rod, here, geometry, ok, errors)
            if (.not. ok) return
            t = centreline_tangent(geometry, 0.0_rk)
            if (rod%d1(1) == unset_real) then
                rod%d1 = default_normal(t)
            else
                ! Keep the given d1's orientation about the centreline, made orthonormal.
                d1 = rod%d1
                if (abs(dot_product(d1, t)) > round_off) d1 = d1 - dot_product(d1, t) * t
                if (norm2(d1) <= 1.0e-8_rk * max(norm2(rod%d1), tiny(1.0_rk))) then
                    if (trim(rod%geometry) == 'straight') then
                        call errors%add(here // 'd1: must not be parallel to direction')
                    else
                        call errors%add(here // 'd1: (' // vector_text(rod%d1) // ') must not be ' // &
                            'parallel to the tangent of the ' // trim(rod%geometry) // ' at s = 0, (' // &
                            vector_text(t) // ')')
                    end if
                    return
                end if
                if (abs(norm2(d1) - 1.0_rk) > round_off) d1 = d1 / norm2(d1)
                rod%d1 = d1
            end if
            where (rod%rotation_center == unset_real) rod%rotation_center = rod%start
            if (scene%time%quasistatic) then
                if (any(rod%velocity /= 0.0_rk)) call errors%add(here // 'velocity: (' // &
                    vector_text(rod%velocity) // ') given, but a quasistatic run (&time ' // &
                    'quasistatic) has no inertia; allowed: 0, 0, 0')
                if (any(rod%angular_velocity /= 0.0_rk)) call errors%add(here // &
                    'angular_velocity: (' // vector_text(rod%angular_velocity) // ') given, ' // &
                    'but a quasistatic run (&time quasistatic) has no inertia; allowed: 0, 0, 0')
            end if
            call resolve_maxwell(rod, here, errors)
            call resolve_stiffness(rod, here, errors)
        end associate
    end subroutine resolve_rod

    !> The reference centreline of `rod` (rs_model_rod_geometry): start and direction default
    !> to the origin and e_x (a polyline derives both from its points and checks given ones), a
    !> direction is normalized (kept bit for bit when unit to round-off, so that resolving a
    !> resolved scene changes nothing), a helix or polyline derives its length and checks a
    !> given one. `ok` is false if the geometry cannot be built.
    subroutine resolve_geometry(rod, here, geometry, ok, errors)
        type(rod_input_t), intent(inout) :: rod
        character(len=*), intent(in) :: here
        type(rod_geometry_t), intent(out) :: geometry
        logical, intent(out) :: ok
        type(error_list_t), intent(inout) :: errors
        real(rk), allocatable :: points(:, :)
        real(rk), parameter :: e_x(3) = [1.0_rk, 0.0_rk, 0.0_rk]
        real(rk) :: t(3)
        character(len=:), allocatable :: formula
        integer :: n_values, n_points, j
        logical :: start_given, direction_given

        ok = .false.
        ! Component by component, so that start(2) = 5 alone keeps the other defaults.
        start_given = any(rod%start /= unset_real)
        direction_given = any(rod%direction /= unset_real)
        where (rod%start == unset_real) rod%start = 0.0_rk
        where (rod%direction == unset_real) rod%direction = e_x
        if (trim(rod%geometry) == 'polyline') then
            n_values = leading_count(rod%points)
            if (any(rod%points(n_values + 1:) /= unset_real)) then
                call errors%add(here // 'points: entry ' // str(n_values + 1) // ' is not ' // &
                    'given but a later one is; give the points from the first on without gaps')
                return
            end if
            if (mod(n_values, 3) /= 0) then
                call errors%add(here // 'points: ' // str(n_values) // ' values given; each ' // &
                    'point takes 3 (x, y, z)')
                return
            end if
            n_points = n_values / 3
            if (n_points < 2) then
                call errors%add(here // 'points: a polyline needs at least 2 points (' // &
                    str(n_points) // ' given)')
                return
            end if
            points = reshape(rod%points(1:n_values), [3, n_points])
            do j = 1, n_points - 1
                if (all(points(:, j + 1) == points(:, j))) then
                    call errors%add(here // 'points: points ' // str(j) // ' and ' // str(j + 1) // &
                        ' coincide at (' // vector_text(points(:, j)) // '); consecutive points ' // &
                        'must be distinct')
                    return
                end if
            end do
            geometry = polyline_geometry(points)
            do j = 1, n_points - 2
                if (norm2(geometry%tangents(:, j) + geometry%tangents(:, j + 1)) < reversal_tolerance) then
                    call errors%add(here // 'points: the segment from point ' // str(j + 1) // &
                        ' to ' // str(j + 2) // ' reverses the one before it (a 180-degree turn ' // &
                        'has no tangent or frame); allowed: turns of less than 180 degrees')
                    return
                end if
            end do
            if (start_given .and. any(rod%start /= points(:, 1))) then
                call errors%add(here // 'start: (' // vector_text(rod%start) // ') given, but a ' // &
                    'polyline starts at its first point (' // vector_text(points(:, 1)) // &
                    '); leave start out or give that point')
                return
            end if
            rod%start = points(:, 1)
            if (direction_given) then
                t = 0.0_rk
                if (norm2(rod%direction) > 0.0_rk) t = rod%direction / norm2(rod%direction)
                if (norm2(t - geometry%axis) > 1.0e-12_rk) then
                    call errors%add(here // 'direction: (' // vector_text(rod%direction) // &
                        ') given, but a polyline''s direction is that of its first segment, (' // &
                        vector_text(geometry%axis) // '); leave direction out or give that')
                    return
                end if
            end if
            rod%direction = geometry%axis
        else
            if (norm2(rod%direction) == 0.0_rk) then
                call errors%add(here // 'direction: must not be the zero vector')
                return
            end if
            t = rod%direction
            if (abs(norm2(t) - 1.0_rk) > round_off) t = t / norm2(t)
            rod%direction = t
            if (trim(rod%geometry) == 'helix') then
                ! The reader reports missing helix variables; nothing to resolve without them.
                if (any([rod%helix_radius, rod%helix_pitch, rod%helix_turns] == unset_real)) return
                geometry = helix_geometry(rod%start, rod%direction, rod%helix_radius, &
                    rod%helix_pitch, rod%helix_turns)
            else
                if (rod%length == unset_real) return
                geometry = straight_geometry(rod%start, rod%direction, rod%length)
            end if
        end if
        if (trim(rod%geometry) /= 'straight') then
            if (rod%length /= unset_real .and. abs(rod%length - geometry%length) > &
                    length_tolerance * geometry%length) then
                if (trim(rod%geometry) == 'helix') then
                    formula = 'helix_turns sqrt((2 pi helix_radius)^2 + helix_pitch^2)'
                else
                    formula = 'the sum of its segments'
                end if
                call errors%add(here // 'length: ' // str(rod%length) // ' given, but the ' // &
                    trim(rod%geometry) // ' is ' // str(geometry%length) // ' long (' // formula // &
                    '); leave length out or give that value')
                return
            end if
            rod%length = geometry%length
        end if
        ok = .true.
    end subroutine resolve_geometry

    !> "x, y, z" in shortest exact form.
    pure function vector_text(v) result(text)
        real(rk), intent(in) :: v(:)
        character(len=:), allocatable :: text
        integer :: i
        text = ''
        do i = 1, size(v)
            if (i > 1) text = text // ', '
            text = text // str(v(i))
        end do
    end function vector_text

    !> Maxwell branches (methods/ph_director_3d.md §3.1): m = the number of leading given
    !> maxwell_fraction entries, with no gaps; one maxwell_tau_E per branch; maxwell_tau_G
    !> defaults to maxwell_tau_E of the same branch; the fractions leave the elastic branch a
    !> positive share 1 - sum.
    subroutine resolve_maxwell(rod, here, errors)
        type(rod_input_t), intent(inout) :: rod
        character(len=*), intent(in) :: here
        type(error_list_t), intent(inout) :: errors
        integer :: m
        logical :: ok
        m = leading_count(rod%maxwell_fraction)
        ok = no_gap(rod%maxwell_fraction, 'maxwell_fraction')
        ok = no_gap(rod%maxwell_tau_E, 'maxwell_tau_E') .and. ok
        if (.not. ok) return
        if (count(rod%maxwell_tau_E /= unset_real) /= m) then
            call errors%add(here // 'maxwell_tau_E: one relaxation time per Maxwell branch; ' // &
                str(m) // ' maxwell_fraction and ' // str(count(rod%maxwell_tau_E /= unset_real)) // &
                ' maxwell_tau_E given')
            ok = .false.
        end if
        if (any(rod%maxwell_tau_G(m + 1:) /= unset_real)) then
            call errors%add(here // 'maxwell_tau_G: given for branch ' // &
                str(findloc(rod%maxwell_tau_G /= unset_real, .true., dim=1, back=.true.)) // &
                ', but there are ' // str(m) // ' branches (one per maxwell_fraction)')
            ok = .false.
        end if
        if (m > 0) then
            if (sum(rod%maxwell_fraction(1:m)) >= 1.0_rk) then
                call errors%add(here // 'maxwell_fraction: the fractions sum to ' // &
                    str(sum(rod%maxwell_fraction(1:m))) // '; the sum must be < 1 so that the ' // &
                    'elastic branch keeps a positive fraction 1 - sum')
                ok = .false.
            end if
        end if
        if (.not. ok) return
        where (rod%maxwell_tau_G(1:m) == unset_real) rod%maxwell_tau_G(1:m) = rod%maxwell_tau_E(1:m)
    contains
        !> True if the given entries of `values` are leading (no unset entry before a given one).
        logical function no_gap(values, name)
            real(rk), intent(in) :: values(:)
            character(len=*), intent(in) :: name
            integer :: n
            n = leading_count(values)
            no_gap = all(values(n + 1:) == unset_real)
            if (.not. no_gap) call errors%add(here // name // ': entry ' // str(n + 1) // &
                ' is not given but a later one is; Maxwell branches are numbered from 1 without gaps')
        end function no_gap
    end subroutine resolve_maxwell

    !> Number of leading given entries of `values`.
    pure integer function leading_count(values) result(n)
        real(rk), intent(in) :: values(:)
        n = 0
        do while (n < size(values))
            if (values(n + 1) == unset_real) exit
            n = n + 1
        end do
    end function leading_count

    !> Stiffnesses and inertias: given directly (section = 'none'), or from section and material.
    subroutine resolve_stiffness(rod, here, errors)
        type(rod_input_t), intent(inout) :: rod
        character(len=*), intent(in) :: here
        type(error_list_t), intent(inout) :: errors
        real(rk) :: direct(9), torsion
        type(section_properties_t) :: s
        character(len=:), allocatable :: missing
        integer :: k

        direct = [rod%EA, rod%GA1, rod%GA2, rod%EI1, rod%EI2, rod%GJ, rod%rhoA, rod%rhoI1, rod%rhoI2]
        if (trim(rod%section) == 'none') then
            missing = ''
            do k = 1, size(direct)
                if (direct(k) == unset_real) missing = missing // ' ' // trim(section_derived_names(k))
            end do
            if (len(missing) > 0) call errors%add(here // 'section: with section = ''none'' the ' // &
                'stiffnesses and inertias must be given; missing:' // missing // &
                ' (or give section, its dimensions, E and density)')
            if (rod%torsion_constant == '') rod%torsion_constant = 'polar'
            return
        end if
        if (any(direct /= unset_real)) then
            call errors%add(here // 'section: give either section with E and density, or the ' // &
                'stiffnesses EA ... rhoI2 with section = ''none'', not both')
            return
        end if
        select case (trim(rod%section))
        case ('circle')
            if (.not. need(rod%radius, 'radius')) return
            s = circle_section(rod%radius)
        case ('tube')
            if (.not. need(rod%radius, 'radius')) return
            if (.not. need(rod%inner_radius, 'inner_radius')) return
            if (rod%inner_radius >= rod%radius) then
                call errors%add(here // 'inner_radius: ' // str(rod%inner_radius) // &
                    ' must be smaller than radius = ' // str(rod%radius))
                return
            end if
            s = tube_section(rod%radius, rod%inner_radius)
        case ('rectangle')
            if (.not. need(rod%width, 'width')) return
            if (.not. need(rod%height, 'height')) return
            if (rod%torsion_constant == '') then
                call errors%add(here // 'torsion_constant: required for a rectangle (''polar'' or ' // &
                    '''saint_venant''; the two differ for non-circular sections)')
                return
            end if
            s = rectangle_section(rod%width, rod%height)
        end select
        if (rod%torsion_constant == '') rod%torsion_constant = 'polar'
        if (.not. need(rod%E, 'E')) return
        if (.not. need(rod%density, 'density')) return
        if (rod%G == unset_real) then
            if (rod%nu == unset_real) then
                call errors%add(here // 'G: give G or nu with a section')
                return
            end if
            rod%G = rod%E / (2.0_rk * (1.0_rk + rod%nu))
        end if
        torsion = s%polar
        if (trim(rod%torsion_constant) == 'saint_venant') torsion = s%saint_venant
        rod%EA = rod%E * s%area
        rod%GA1 = rod%shear_factor * rod%G * s%area
        rod%GA2 = rod%GA1
        rod%EI1 = rod%E * s%i1
        rod%EI2 = rod%E * s%i2
        rod%GJ = rod%G * torsion
        rod%rhoA = rod%density * s%area
        rod%rhoI1 = rod%density * s%i1
        rod%rhoI2 = rod%density * s%i2
    contains
        logical function need(value, name)
            real(rk), intent(in) :: value
            character(len=*), intent(in) :: name
            need = value /= unset_real
            if (.not. need) call errors%add(here // name // ': required with section = ''' // &
                trim(rod%section) // '''')
        end function need
    end subroutine resolve_stiffness

    subroutine check_unique_names(scene, errors)
        type(scene_t), intent(in) :: scene
        type(error_list_t), intent(inout) :: errors
        integer :: i, j
        do i = 2, size(scene%rods)
            do j = 1, i - 1
                if (scene%rods(i)%name == scene%rods(j)%name) call errors%add(at(scene, &
                    scene%rods(i)%input_line) // '&rod name: ''' // trim(scene%rods(i)%name) // &
                    ''' is already the name of the rod at line ' // str(scene%rods(j)%input_line))
            end do
        end do
    end subroutine check_unique_names

    integer function rod_index(scene, name)
        type(scene_t), intent(in) :: scene
        character(len=*), intent(in) :: name
        integer :: i
        rod_index = 0
        do i = 1, size(scene%rods)
            if (trim(scene%rods(i)%name) == trim(name)) then
                rod_index = i
                return
            end if
        end do
    end function rod_index

    function rod_names(scene) result(text)
        type(scene_t), intent(in) :: scene
        character(len=:), allocatable :: text
        integer :: i
        text = ''
        do i = 1, size(scene%rods)
            if (i > 1) text = text // ', '
            text = text // '''' // trim(scene%rods(i)%name) // ''''
        end do
    end function rod_names

    !> Supports: an existing rod, each end supported once, and a clamped end starting at rest
    !> (the rod's initial velocity field vanishes there only without velocity and
    !> angular_velocity, since the director rates are angular_velocity x d_i).
    subroutine check_bcs(scene, errors)
        type(scene_t), intent(in) :: scene
        type(error_list_t), intent(inout) :: errors
        character(len=:), allocatable :: where
        integer :: i, j, r
        do i = 1, size(scene%bcs)
            associate (bc => scene%bcs(i))
                r = 0
                if (len_trim(bc%rod) > 0) r = rod_index(scene, bc%rod)
                if (len_trim(bc%rod) > 0 .and. r == 0) call errors%add(at(scene, &
                    bc%input_line) // '&bc rod: no rod is named ''' // trim(bc%rod) // '''; rods: ' // &
                    rod_names(scene))
                if (r > 0 .and. trim(bc%kind) == 'clamped') then
                    associate (rod => scene%rods(r))
                        where = at(scene, rod%input_line) // '&rod ''' // trim(rod%name) // ''' '
                        if (any(rod%velocity /= 0.0_rk)) call errors%add(where // 'velocity: (' // &
                            vector_text(rod%velocity) // ') given, but the ''' // trim(bc%end) // &
                            ''' end is clamped (&bc at line ' // str(bc%input_line) // ') and a ' // &
                            'clamped end starts at rest; allowed: 0, 0, 0 (or free that end)')
                        if (any(rod%angular_velocity /= 0.0_rk)) call errors%add(where // &
                            'angular_velocity: (' // vector_text(rod%angular_velocity) // &
                            ') given, but the ''' // trim(bc%end) // ''' end is clamped (&bc at ' // &
                            'line ' // str(bc%input_line) // ') and its directors would start ' // &
                            'turning; allowed: 0, 0, 0 (or free that end)')
                    end associate
                end if
                do j = 1, i - 1
                    if (scene%bcs(j)%rod == bc%rod .and. scene%bcs(j)%end == bc%end .and. &
                            len_trim(bc%end) > 0) call errors%add(at(scene, bc%input_line) // &
                        '&bc end: the ''' // trim(bc%end) // ''' end of rod ''' // trim(bc%rod) // &
                        ''' already has a support (line ' // str(scene%bcs(j)%input_line) // ')')
                end do
            end associate
        end do
    end subroutine check_bcs

    subroutine check_loads(scene, errors)
        type(scene_t), intent(in) :: scene
        type(error_list_t), intent(inout) :: errors
        character(len=:), allocatable :: here
        integer :: i
        do i = 1, size(scene%loads)
            associate (load => scene%loads(i))
                here = at(scene, load%input_line) // '&load '
                if (len_trim(load%rod) == 0) then
                    if (load%where /= 'gravity' .and. len_trim(load%where) > 0) call errors%add(here // &
                        'rod: required unless where = ''gravity''')
                else if (rod_index(scene, load%rod) == 0) then
                    call errors%add(here // 'rod: no rod is named ''' // trim(load%rod) // '''; rods: ' // &
                        rod_names(scene))
                end if
                if (load%where == 'gravity') then
                    if (any(load%force /= 0.0_rk) .or. any(load%moment /= 0.0_rk)) call errors%add(here // &
                        'force: a gravity load takes acceleration, not force or moment')
                    if (all(load%acceleration == 0.0_rk)) call errors%add(here // &
                        'acceleration: a gravity load needs a non-zero acceleration')
                else if (any(load%acceleration /= 0.0_rk)) then
                    call errors%add(here // 'acceleration: only a gravity load takes an acceleration')
                end if
                call check_time_function(here, load%time_function, load%t_on, load%t_off, &
                    load%table_times, load%table_values, errors)
            end associate
        end do
    end subroutine check_loads

    !> The time function of a &load or &actuator (prefix `here`): ramps, hats and pulses need
    !> t_off > t_on; a table needs at least two strictly increasing times and as many values.
    subroutine check_time_function(here, name, t_on, t_off, times, values, errors)
        character(len=*), intent(in) :: here, name
        real(rk), intent(in) :: t_on, t_off, times(:), values(:)
        type(error_list_t), intent(inout) :: errors
        integer :: n_times, n_values
        select case (trim(name))
        case ('ramp', 'hat', 'pulse')
            if (t_off == unset_real) then
                call errors%add(here // 't_off: required by time_function = ''' // trim(name) // '''')
            else if (t_off <= t_on) then
                call errors%add(here // 't_off: ' // str(t_off) // ' must be larger than t_on = ' // &
                    str(t_on))
            end if
        case ('table')
            n_times = count(times /= unset_real)
            n_values = count(values /= unset_real)
            if (n_times < 2 .or. n_times /= n_values) then
                call errors%add(here // 'table_times: a table needs at least 2 times and as many ' // &
                    'table_values (' // str(n_times) // ' and ' // str(n_values) // ' given)')
            else if (leading_count(times) /= n_times .or. leading_count(values) /= n_values) then
                call errors%add(here // 'table_times: the table entries must be given from 1 ' // &
                    'without gaps')
            else if (any(times(2:n_times) <= times(1:n_times - 1))) then
                call errors%add(here // 'table_times: must be strictly increasing')
            end if
        end select
    end subroutine check_time_function

    !> &output fields names only selectable fields (DESIGN.md §7); &run restart_from names an
    !> existing file.
    subroutine check_output_and_restart(scene, errors)
        type(scene_t), intent(in) :: scene
        type(error_list_t), intent(inout) :: errors
        character(len=:), allocatable :: unknown
        logical :: exists
        unknown = unknown_fields(trim(scene%output%fields))
        if (len(unknown) > 0) call errors%add(at(scene, 0) // '&output fields: ' // unknown // &
            ' given; allowed are ''all'' or a comma-separated list of ' // selectable_fields)
        if (len_trim(scene%run%restart_from) > 0) then
            inquire(file=trim(scene%run%restart_from), exist=exists)
            if (.not. exists) call errors%add(at(scene, 0) // '&run restart_from: the file ''' // &
                trim(scene%run%restart_from) // ''' does not exist')
        end if
    end subroutine check_output_and_restart

    !> &actuator (seed 000 §5.2, methods/ph_director_3d.md §3.2): an existing rod; a pneumatic
    !> chamber takes area and pressure, a tendon tension, and neither takes the other's; the
    !> offset lies inside a circle or tube section; the time function as for a load.
    subroutine check_actuators(scene, errors)
        type(scene_t), intent(in) :: scene
        type(error_list_t), intent(inout) :: errors
        character(len=:), allocatable :: here
        integer :: i, r
        if (.not. allocated(scene%actuators)) return
        do i = 1, size(scene%actuators)
            associate (act => scene%actuators(i))
                here = at(scene, act%input_line) // '&actuator '
                r = 0
                if (len_trim(act%rod) > 0) then
                    r = rod_index(scene, act%rod)
                    if (r == 0) call errors%add(here // 'rod: no rod is named ''' // trim(act%rod) // &
                        '''; rods: ' // rod_names(scene))
                end if
                select case (trim(act%kind))
                case ('pneumatic')
                    call need(act%area, 'area')
                    call need(act%pressure, 'pressure')
                    call refuse(act%tension, 'tension', 'a pneumatic chamber takes area and pressure')
                case ('tendon')
                    call need(act%tension, 'tension')
                    call refuse(act%area, 'area', 'a tendon takes tension')
                    call refuse(act%pressure, 'pressure', 'a tendon takes tension')
                end select
                if (count(act%offset /= unset_real) == 1) call errors%add(here // &
                    'offset: both material coordinates (rho^1, rho^2) are needed')
                if (r > 0 .and. all(act%offset /= unset_real)) call check_offset(scene%rods(r), act, &
                    here, errors)
                call check_time_function(here, act%time_function, act%t_on, act%t_off, &
                    act%table_times, act%table_values, errors)
            end associate
        end do
    contains
        subroutine need(value, name)
            real(rk), intent(in) :: value
            character(len=*), intent(in) :: name
            if (value == unset_real) call errors%add(here // name // ': required for kind = ''' // &
                trim(scene%actuators(i)%kind) // '''')
        end subroutine need

        subroutine refuse(value, name, reason)
            real(rk), intent(in) :: value
            character(len=*), intent(in) :: name, reason
            if (value /= unset_real) call errors%add(here // name // ': not allowed for kind = ''' // &
                trim(scene%actuators(i)%kind) // ''' (' // reason // ')')
        end subroutine refuse
    end subroutine check_actuators

    !> The chamber or tendon line must lie inside a circle or tube section of known radius.
    subroutine check_offset(rod, act, here, errors)
        type(rod_input_t), intent(in) :: rod
        type(actuator_input_t), intent(in) :: act
        character(len=*), intent(in) :: here
        type(error_list_t), intent(inout) :: errors
        real(rk) :: distance
        if (trim(rod%section) /= 'circle' .and. trim(rod%section) /= 'tube') return
        if (rod%radius == unset_real) return
        distance = norm2(act%offset)
        if (distance > rod%radius) call errors%add(here // 'offset: |offset| = ' // str(distance) // &
            ' lies outside the ' // trim(rod%section) // ' section of rod ''' // trim(rod%name) // &
            ''' (radius ' // str(rod%radius) // ')')
    end subroutine check_offset

    !> A scene must never silently get less than it asked for (DESIGN.md §1): every rod's
    !> formulation must be available and able to do what the rod, its supports, loads and
    !> actuators and the time settings ask.
    subroutine check_capabilities(scene, errors)
        type(scene_t), intent(in) :: scene
        type(error_list_t), intent(inout) :: errors
        type(capability_t) :: row
        integer :: i
        do i = 1, size(scene%rods)
            associate (rod => scene%rods(i))
                row = capability_of(trim(rod%formulation))
                if (.not. row%available) then
                    call errors%add(at(scene, rod%input_line) // '&rod formulation: ''' // &
                        trim(rod%formulation) // ''' is not available in this version; available: ' // &
                        available_formulation_names() // see_matrix)
                    cycle
                end if
                call check_rod_capabilities(scene, i, row, errors)
            end associate
        end do
    end subroutine check_capabilities

    !> Rod `i` of `scene` against capability row `row` (that of its formulation; any row in a
    !> unit test): its constraint and Maxwell branches, quasistatics, and the kinds of its
    !> supports, loads and actuators.
    subroutine check_rod_capabilities(scene, i, row, errors)
        type(scene_t), intent(in) :: scene
        integer, intent(in) :: i
        type(capability_t), intent(in) :: row
        type(error_list_t), intent(inout) :: errors
        character(len=:), allocatable :: what
        integer :: j
        associate (rod => scene%rods(i))
            what = 'formulation ''' // trim(row%formulation) // ''''
            if (.not. lists_name(row%constraints, rod%constraint)) call errors%add(at(scene, &
                rod%input_line) // '&rod constraint: ''' // trim(rod%constraint) // &
                ''' is not available for ' // what // '; available: ' // trim(row%constraints) // &
                see_matrix)
            if (any(rod%maxwell_fraction /= unset_real) .and. .not. row%viscoelastic) call errors%add( &
                at(scene, rod%input_line) // '&rod maxwell_fraction: Maxwell branches ' // &
                '(viscoelasticity) are not available for ' // what // ' (rod ''' // trim(rod%name) // &
                ''')' // see_matrix)
            if (trim(rod%geometry) /= 'straight' .and. .not. row%curved_reference) call errors%add( &
                at(scene, rod%input_line) // '&rod geometry: a curved reference (''' // &
                trim(rod%geometry) // ''') is not available for ' // what // ' (rod ''' // &
                trim(rod%name) // '''); available: ''straight''' // see_matrix)
            if (scene%time%quasistatic .and. .not. row%quasistatic) call errors%add(at(scene, 0) // &
                '&time quasistatic: not available for ' // what // ' (rod ''' // trim(rod%name) // &
                ''')' // see_matrix)
            do j = 1, size(scene%bcs)
                associate (bc => scene%bcs(j))
                    if (bc%rod /= rod%name .or. len_trim(bc%kind) == 0) cycle
                    if (.not. lists_name(row%end_kinds, bc%kind)) call errors%add(at(scene, &
                        bc%input_line) // '&bc kind: a ''' // trim(bc%kind) // ''' end is not ' // &
                        'available for ' // what // '; available: ' // trim(row%end_kinds) // &
                        see_matrix)
                end associate
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
    end subroutine check_rod_capabilities

    !> Names of the formulations this build can run.
    function available_formulation_names() result(names)
        character(len=:), allocatable :: names
        character(len=*), parameter :: known(5) = [character(len=12) :: 'ph_director', &
            'ph_planar', 'cl_em_planar', 'se3_pg', 'se3_strand']
        type(capability_t) :: row
        integer :: i
        names = ''
        do i = 1, size(known)
            row = capability_of(known(i))
            if (.not. row%available) cycle
            if (len(names) > 0) names = names // ', '
            names = names // trim(known(i))
        end do
    end function available_formulation_names

end module rs_io_input_check
