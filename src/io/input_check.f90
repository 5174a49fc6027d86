!> Resolution and cross-checks of a scene that was read without errors (DESIGN.md §6): fills
!> derived defaults (rod names, formulations, the centreline's start, direction and length,
!> directors, the centre of the initial rotation, stiffnesses from section and material,
!> Maxwell shear relaxation times, output path) and checks what no single variable can (a &bc
!> on a rod that does not exist, an end supported twice (except by several velocity drives),
!> a table that is not increasing, dt above t_end, relaxation with quasistatics, Maxwell
!> fractions that leave no elastic branch, an actuator without its force, a helix length that
!> contradicts its turns, a polyline that doubles back, an initial velocity at a clamped end,
!> ...), resolves `formulation = 'auto'` per joint-connected system of rods
!> (ph_planar when they lie in a plane, rs_model_planarity, else ph_director) and checks the
!> joints (existing rods, no end tied to itself, no redundant joint, ends that coincide, one
!> formulation per system, an axis for revolute joints only); resolves and checks the end
!> plates (&plate: existing rods, each tied end on one plate only, without &bc or joint, the
!> centre defaulted to the mean of the tied ends, the time function of a driven plate) and
!> contact (&contact: every rod's contact_radius, defaulted to a circle or tube section's
!> radius, the margin and the skip derived). Every problem is added to `errors`, naming the
!> file, line, group and variable.
module rs_io_input_check
    use rs_core_kinds, only: rk
    use rs_core_error, only: error_list_t, error_t
    use rs_core_strings, only: str, vector_text, did_you_mean, str_significant
    use rs_model_scene, only: scene_t, rod_input_t, actuator_input_t, bc_input_t, time_input_t, &
        unset_real, unset_int, section_derived_names, name_len
    use rs_model_time_function, only: time_function_t, time_function_from_bc, time_function_from_plate
    use rs_model_rod_geometry, only: rod_geometry_t, straight_geometry, helix_geometry, &
        polyline_geometry, centreline_tangent, default_normal, rod_geometry_of, centreline_point
    use rs_model_section, only: section_properties_t, circle_section, tube_section, rectangle_section
    use rs_model_capabilities, only: capability_t, capability_of, lists_name, end_kinds_at, &
        formulation_names
    use rs_model_planarity, only: plane_t, plane_of_rods, plane_text
    use rs_model_coupling, only: coupled_systems
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
    !> Largest distance of two joined rod ends, relative to the longer rod's length.
    real(rk), parameter :: joint_tolerance = 1.0e-9_rk
    !> Largest initial speed of a pinned end relative to the rod's speed scale.
    real(rk), parameter :: rest_tolerance = 1.0e-12_rk

contains

    !> Fill derived defaults of `scene` and cross-check it; problems go to `errors`.
    subroutine resolve_scene(scene, errors)
        type(scene_t), intent(inout) :: scene
        type(error_list_t), intent(inout) :: errors
        logical, allocatable :: geometry_ok(:)
        integer :: i

        if (len_trim(scene%output%path) == 0) scene%output%path = default_output_path(scene%source_file)
        if (scene%time%dt /= unset_real .and. scene%time%t_end /= unset_real) then
            if (scene%time%dt > scene%time%t_end) call errors%add(at(scene, 0) // '&time dt: ' // &
                str(scene%time%dt) // ' is larger than t_end = ' // str(scene%time%t_end))
            call check_step_count(scene, errors)
        end if
        call check_relaxation(scene, errors)
        call check_output_and_restart(scene, errors)
        if (size(scene%rods) == 0) call errors%add(scene%source_file // ': the scene has no &rod group')
        allocate(geometry_ok(size(scene%rods)))
        do i = 1, size(scene%rods)
            call resolve_rod(scene, i, geometry_ok(i), errors)
        end do
        if (.not. allocated(scene%joints)) allocate(scene%joints(0))
        if (.not. allocated(scene%plates)) allocate(scene%plates(0))
        call check_unique_names(scene, errors)
        call check_bcs(scene, geometry_ok, errors)
        call check_loads(scene, errors)
        call check_actuators(scene, errors)
        call check_joints(scene, geometry_ok, errors)
        call resolve_joint_axes(scene)
        call resolve_plates(scene, geometry_ok, errors)
        call resolve_contact(scene, geometry_ok, errors)
        ! 'auto' needs every rod, load and joint resolved: it looks at whole systems.
        call resolve_auto_formulations(scene)
        call resolve_formulation_options(scene)
        call check_joint_formulations(scene, errors)
    end subroutine resolve_scene

    !> t_end / dt steps, counted in 64-bit reals (a 32-bit count of 2.2e9 steps wrapped to one
    !> step, reported as a success: issue 21 item 6), must fit the step numbers of the result
    !> file's checkpoint (32-bit integers, docs/user/output.md): at most 2147483647 per run.
    subroutine check_step_count(scene, errors)
        type(scene_t), intent(in) :: scene
        type(error_list_t), intent(inout) :: errors
        real(rk) :: steps
        if (scene%time%dt <= 0.0_rk) return
        steps = scene%time%t_end / scene%time%dt
        if (steps <= real(huge(1), rk)) return
        call errors%add(at(scene, 0) // '&time dt: t_end / dt = ' // str(scene%time%t_end) // &
            ' / ' // str(scene%time%dt) // ' = ' // str_significant(steps, 3) // ' steps, more ' // &
            'than the ' // str(huge(1)) // ' steps one run can number; give a larger dt or a ' // &
            'shorter t_end')
    end subroutine check_step_count

    !> &time relaxation (statics by damped dynamics) needs inertia, so not with quasistatic;
    !> kinetic_energy_tol only means something with relaxation, and equilibrium_solves with
    !> quasistatic, so a value other than the default without it would be silently ignored.
    subroutine check_relaxation(scene, errors)
        type(scene_t), intent(in) :: scene
        type(error_list_t), intent(inout) :: errors
        type(time_input_t) :: defaults
        if (scene%time%relaxation .and. scene%time%quasistatic) call errors%add(at(scene, 0) // &
            '&time relaxation: statics by damped dynamics needs the inertia that quasistatic = ' // &
            '.true. drops; choose one of relaxation and quasistatic')
        if (.not. scene%time%relaxation .and. &
                scene%time%kinetic_energy_tol /= defaults%kinetic_energy_tol) call errors%add( &
            at(scene, 0) // '&time kinetic_energy_tol: ' // str(scene%time%kinetic_energy_tol) // &
            ' given, but it is only used with relaxation = .true.; remove it or set relaxation')
        if (.not. scene%time%quasistatic .and. .not. scene%time%equilibrium_solves) &
            call errors%add(at(scene, 0) // '&time equilibrium_solves: .false. given, but ' // &
            'a dynamic run solves no equilibrium; it is only used with quasistatic = .true.')
    end subroutine check_relaxation

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

    !> Resolve rod `i`: name, formulation origin, geometry, d1, rotation centre, Maxwell
    !> branches and stiffnesses; `geometry_ok` is false if its reference geometry cannot be built.
    subroutine resolve_rod(scene, i, geometry_ok, errors)
        type(scene_t), intent(inout) :: scene
        integer, intent(in) :: i
        logical, intent(out) :: geometry_ok
        type(error_list_t), intent(inout) :: errors
        character(len=:), allocatable :: here
        type(rod_geometry_t) :: geometry
        real(rk) :: t(3), d1(3)
        logical :: ok

        geometry_ok = .false.
        associate (rod => scene%rods(i))
            if (len_trim(rod%name) == 0) rod%name = 'rod' // str(i)
            here = at(scene, rod%input_line) // '&rod ''' // trim(rod%name) // ''' '
            if (len_trim(rod%formulation) == 0) then
                rod%formulation = scene%run%formulation_default
                rod%formulation_origin = 'default'
            else
                rod%formulation_origin = 'rod'
            end if
            ! 'auto' is chosen per system of joined rods once the whole scene is resolved
            ! (resolve_auto_formulations).
            if (rod%formulation == 'auto') rod%formulation_origin = 'auto'
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
            geometry_ok = .true.
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
            if (.not. scene%time%quasistatic) call check_inertia(rod, here, errors)
        end associate
    end subroutine resolve_rod

    !> A dynamic run needs mass and rotary inertia: with rhoA or rhoI = 0 the step's equations
    !> have no acceleration for that motion, and the scheme alternates between 0 and twice the
    !> static answer instead of converging to a motion (issue 21 item 13). Statics is
    !> &time quasistatic or relaxation.
    subroutine check_inertia(rod, here, errors)
        type(rod_input_t), intent(in) :: rod
        character(len=*), intent(in) :: here
        type(error_list_t), intent(inout) :: errors
        character(len=:), allocatable :: zero
        zero = ''
        if (rod%rhoA == 0.0_rk) zero = zero // ' rhoA'
        if (rod%rhoI1 == 0.0_rk) zero = zero // ' rhoI1'
        if (rod%rhoI2 == 0.0_rk) zero = zero // ' rhoI2'
        if (len(zero) == 0) return
        if (trim(rod%section) /= 'none') zero = zero // ' (density = 0)'
        call errors%add(here // 'inertia: zero' // zero // ' in a dynamic run, which needs ' // &
            'mass and rotary inertia; give them, or run statics (&time quasistatic = .true.)')
    end subroutine check_inertia

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
                    rod%helix_pitch, rod%helix_turns, rod%helix_phase)
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
            ! Both derive stiffnesses from a section: without one they would be ignored.
            if (rod%shear_factor /= unset_real) call errors%add(here // 'shear_factor: ' // &
                str(rod%shear_factor) // ' given with section = ''none'', where GA1 and GA2 are ' // &
                'given directly; remove it (it scales GA = k G A of a section)')
            if (rod%torsion_constant /= '') call errors%add(here // 'torsion_constant: ''' // &
                trim(rod%torsion_constant) // ''' given with section = ''none'', where GJ is ' // &
                'given directly; remove it (it chooses the J of a section)')
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
        if (rod%shear_factor == unset_real) rod%shear_factor = 1.0_rk
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
        character(len=*), parameter :: name_chars = &
            'abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789_-'
        integer :: i, j, bad
        ! A rod's name is a group of the result file (/rods/<name>) and of its XDMF sidecar:
        ! '/' would nest groups and '.' is a path of its own there (issue 21 item 19).
        do i = 1, size(scene%rods)
            bad = verify(trim(scene%rods(i)%name), name_chars)
            if (bad > 0) call errors%add(at(scene, scene%rods(i)%input_line) // '&rod name: ''' // &
                trim(scene%rods(i)%name) // ''' has the character ''' // &
                scene%rods(i)%name(bad:bad) // '''; a name has letters, digits, _ and - only')
        end do
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

    !> Supports: an existing rod, each end supported once (several driven &bc on one end add
    !> up their velocities when the rod's formulation drives ends by velocity, capability_t
    !> drive), a clamped end starting at rest (the rod's initial velocity field vanishes
    !> there only without velocity and angular_velocity,
    !> since the director rates are angular_velocity x d_i) and a pinned end starting at rest
    !> (it may turn: a rotation about the pin is allowed).
    subroutine check_bcs(scene, geometry_ok, errors)
        type(scene_t), intent(in) :: scene
        logical, intent(in) :: geometry_ok(:)
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
                if (r > 0 .and. trim(bc%kind) == 'pinned') then
                    if (geometry_ok(r)) call check_pinned_at_rest(scene, r, bc%end, bc%input_line, errors)
                end if
                call check_driven(scene, bc, errors)
                do j = 1, i - 1
                    if (scene%bcs(j)%rod /= bc%rod .or. scene%bcs(j)%end /= bc%end .or. &
                            len_trim(bc%end) == 0) cycle
                    if (trim(bc%kind) == 'driven' .and. trim(scene%bcs(j)%kind) == 'driven' .and. &
                            drives_velocity(r)) cycle
                    call errors%add(at(scene, bc%input_line) // '&bc end: the ''' // trim(bc%end) // &
                        ''' end of rod ''' // trim(bc%rod) // ''' already has a support (line ' // &
                        str(scene%bcs(j)%input_line) // ')' // velocity_note(r))
                end do
            end associate
        end do
    contains
        !> True if rod `r` exists and its formulation drives ends by their velocity.
        logical function drives_velocity(r)
            integer, intent(in) :: r
            type(capability_t) :: row
            drives_velocity = .false.
            if (r == 0) return
            row = capability_of(trim(scene%rods(r)%formulation))
            drives_velocity = trim(row%drive) == 'velocity'
        end function drives_velocity

        !> Where several driven &bc on one end are allowed, say so.
        function velocity_note(r) result(text)
            integer, intent(in) :: r
            character(len=:), allocatable :: text
            text = ''
            if (drives_velocity(r)) text = '; only driven ends may be given more than once ' // &
                '(their velocities add up)'
        end function velocity_note
    end subroutine check_bcs

    !> A driven end moves: by its pose (displacement, rotation), with a time function f(0) = 0
    !> so that it starts at its reference pose, or by its velocity (velocity, angular_velocity,
    !> methods/se3_strands.md §3.4), which starts at the reference pose whatever f(0); not
    !> both. Which of the two a formulation takes: check_rod_capabilities. Other kinds take
    !> none of the four.
    subroutine check_driven(scene, bc, errors)
        type(scene_t), intent(in) :: scene
        type(bc_input_t), intent(in) :: bc
        type(error_list_t), intent(inout) :: errors
        type(time_function_t) :: f
        type(error_t), allocatable :: err
        character(len=:), allocatable :: here
        logical :: pose, velocity
        here = at(scene, bc%input_line) // '&bc '
        pose = any(bc%displacement /= 0.0_rk) .or. any(bc%rotation /= 0.0_rk)
        velocity = any(bc%velocity /= 0.0_rk) .or. any(bc%angular_velocity /= 0.0_rk)
        if (trim(bc%kind) /= 'driven') then
            if (pose) call errors%add(here // 'displacement, rotation: only a driven end moves ' // &
                '(kind = ''driven''), this one is ''' // trim(bc%kind) // '''')
            if (velocity) call errors%add(here // 'velocity, angular_velocity: only a driven end ' // &
                'moves (kind = ''driven''), this one is ''' // trim(bc%kind) // '''')
            return
        end if
        if (.not. (pose .or. velocity)) then
            call errors%add(here // 'kind: a driven end needs a displacement or a rotation ' // &
                '(formulations that drive the pose) or a velocity or an angular_velocity ' // &
                '(formulations that drive the velocity)' // see_matrix)
            return
        end if
        if (pose .and. velocity) then
            call errors%add(here // 'velocity, angular_velocity: given with displacement or ' // &
                'rotation; a driven end is moved either by its pose (displacement, rotation) or ' // &
                'by its velocity (velocity, angular_velocity), as its formulation drives ends' // &
                see_matrix)
            return
        end if
        call check_time_function(here, bc%time_function, bc%t_on, bc%t_off, bc%table_times, &
            bc%table_values, errors)
        call time_function_from_bc(bc, f, err)
        if (allocated(err) .or. velocity) return
        if (f%value(0.0_rk) /= 0.0_rk) call errors%add(here // 'time_function: f(0) = ' // &
            str(f%value(0.0_rk)) // '; a driven end starts at its reference pose, so f(0) = 0 ' // &
            '(a ramp, hat, pulse, sine or a table starting at 0)')
    end subroutine check_driven

    !> The initial velocity velocity + angular_velocity x (p - rotation_center) of rod `r` at
    !> its pinned end `end_name` (point p) vanishes.
    subroutine check_pinned_at_rest(scene, r, end_name, bc_line, errors)
        type(scene_t), intent(in) :: scene
        integer, intent(in) :: r, bc_line
        character(len=*), intent(in) :: end_name
        type(error_list_t), intent(inout) :: errors
        real(rk) :: p(3), arm(3), v(3), scale
        associate (rod => scene%rods(r))
            if (all(rod%velocity == 0.0_rk) .and. all(rod%angular_velocity == 0.0_rk)) return
            p = end_point(rod, end_name)
            arm = p - rod%rotation_center
            v = rod%velocity + cross3(rod%angular_velocity, arm)
            scale = norm2(rod%velocity) + norm2(rod%angular_velocity) * norm2(arm)
            if (norm2(v) <= rest_tolerance * scale) return
            call errors%add(at(scene, rod%input_line) // '&rod ''' // trim(rod%name) // &
                ''' velocity: the initial velocity at the ''' // trim(end_name) // ''' end, (' // &
                vector_text(v) // '), is not zero, but that end is pinned (&bc at line ' // &
                str(bc_line) // ') and starts at rest; allowed: no velocity, or a rotation ' // &
                'about the pin (rotation_center = (' // vector_text(p) // '))')
        end associate
    end subroutine check_pinned_at_rest

    !> The reference position of end `end_name` ('start' or 'end') of a resolved rod.
    function end_point(rod, end_name) result(p)
        type(rod_input_t), intent(in) :: rod
        character(len=*), intent(in) :: end_name
        real(rk) :: p(3)
        type(rod_geometry_t) :: geometry
        geometry = rod_geometry_of(rod)
        if (trim(end_name) == 'start') then
            p = centreline_point(geometry, 0.0_rk)
        else
            p = centreline_point(geometry, geometry%length)
        end if
    end function end_point

    pure function cross3(a, b) result(c)
        real(rk), intent(in) :: a(3), b(3)
        real(rk) :: c(3)
        c = [a(2) * b(3) - a(3) * b(2), a(3) * b(1) - a(1) * b(3), a(1) * b(2) - a(2) * b(1)]
    end function cross3

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
                    ! A weight does not turn with the sections (issue 21 item 15: se3_pg and
                    ! se3_strand accepted the frame and ignored it).
                    if (trim(load%frame) == 'follower') call errors%add(here // 'frame: ' // &
                        '''follower'' with where = ''gravity'': a weight is a spatial (dead) ' // &
                        'load; remove frame or set frame = ''spatial''')
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

    !> The time function of a &load, &actuator or driven &bc (prefix `here`): ramps, hats,
    !> pulses and sines need t_off > t_on; a table needs at least two strictly increasing times
    !> and as many values.
    subroutine check_time_function(here, name, t_on, t_off, times, values, errors)
        character(len=*), intent(in) :: here, name
        real(rk), intent(in) :: t_on, t_off, times(:), values(:)
        type(error_list_t), intent(inout) :: errors
        integer :: n_times, n_values
        select case (trim(name))
        case ('ramp', 'hat', 'pulse', 'sine')
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

    !> &joint: an axis for a revolute joint only; both rods exist; a joint ties two different
    !> rod ends; no joint is redundant (the tied ends form a graph whose groups are the joint
    !> points: a joint between ends already in one group, the same pair twice or a cycle, adds
    !> nothing and would make the system singular); and the two ends coincide in the reference
    !> geometry, to joint_tolerance times the longer rod. The joints' kinds, axes and supports
    !> against the formulations: check_capabilities.
    subroutine check_joints(scene, geometry_ok, errors)
        type(scene_t), intent(in) :: scene
        logical, intent(in) :: geometry_ok(:)
        type(error_list_t), intent(inout) :: errors
        character(len=:), allocatable :: here, lines
        integer, allocatable :: parent(:), joint_end(:)
        integer :: j, k, ra, rb, ea, eb
        real(rk) :: pa(3), pb(3), distance, longer
        ! Rod end e = 2 (r - 1) + 1 (start) or + 2 (end); parent(:) is a union-find forest.
        allocate(parent(2 * size(scene%rods)), joint_end(size(scene%joints)))
        parent = [(k, k = 1, size(parent))]
        joint_end = 0
        do j = 1, size(scene%joints)
            associate (joint => scene%joints(j))
                here = at(scene, joint%input_line) // '&joint '
                if (any(joint%axis /= unset_real) .and. len_trim(joint%kind) > 0 .and. &
                        trim(joint%kind) /= 'revolute') call errors%add(here // 'axis: only a ' // &
                    'revolute joint turns about an axis (this one is ''' // trim(joint%kind) // &
                    '''); remove axis')
                ra = rod_of(joint%rod_a, 'rod_a')
                rb = rod_of(joint%rod_b, 'rod_b')
                if (ra == 0 .or. rb == 0) cycle
                if (len_trim(joint%end_a) == 0 .or. len_trim(joint%end_b) == 0) cycle
                if (ra == rb .and. joint%end_a == joint%end_b) then
                    call errors%add(here // 'end_b: the joint ties the ''' // trim(joint%end_a) // &
                        ''' end of rod ''' // trim(joint%rod_a) // ''' to itself; a joint ties two ' // &
                        'different rod ends')
                    cycle
                end if
                ea = end_id(ra, joint%end_a)
                eb = end_id(rb, joint%end_b)
                if (root(ea) == root(eb)) then
                    lines = ''
                    do k = 1, j - 1
                        if (joint_end(k) == 0) cycle
                        if (root(joint_end(k)) /= root(ea)) cycle
                        if (len(lines) > 0) lines = lines // ', '
                        lines = lines // str(scene%joints(k)%input_line)
                    end do
                    call errors%add(here // 'rod_b: redundant joint: the ''' // trim(joint%end_a) // &
                        ''' end of rod ''' // trim(joint%rod_a) // ''' and the ''' // &
                        trim(joint%end_b) // ''' end of rod ''' // trim(joint%rod_b) // &
                        ''' are already tied together by the &joint(s) at line(s) ' // lines // &
                        '; remove this one')
                    cycle
                end if
                parent(max(root(ea), root(eb))) = min(root(ea), root(eb))
                joint_end(j) = ea
                if (.not. (geometry_ok(ra) .and. geometry_ok(rb))) cycle
                pa = end_point(scene%rods(ra), joint%end_a)
                pb = end_point(scene%rods(rb), joint%end_b)
                distance = norm2(pa - pb)
                longer = max(scene%rods(ra)%length, scene%rods(rb)%length)
                if (distance > joint_tolerance * longer) then
                    call errors%add(here // 'end_b: the ''' // &
                        trim(joint%end_b) // ''' end of rod ''' // trim(joint%rod_b) // ''' at (' // &
                        vector_text(pb) // ') is ' // str(distance) // ' away from the ''' // &
                        trim(joint%end_a) // ''' end of rod ''' // trim(joint%rod_a) // ''' at (' // &
                        vector_text(pa) // '); joined ends must coincide in the reference ' // &
                        'geometry (to ' // str(joint_tolerance) // ' times the longer rod, ' // &
                        str(longer) // ')')
                    cycle
                end if
                call check_joint_motion(scene%rods(ra), scene%rods(rb), pa)
            end associate
        end do
    contains
        !> Joined ends start with one velocity, and a rigid joint's rods with one angular
        !> velocity (they move together from the start).
        subroutine check_joint_motion(rod_a, rod_b, p)
            type(rod_input_t), intent(in) :: rod_a, rod_b
            real(rk), intent(in) :: p(3)
            real(rk) :: va(3), vb(3), scale
            va = rod_a%velocity + cross3(rod_a%angular_velocity, p - rod_a%rotation_center)
            vb = rod_b%velocity + cross3(rod_b%angular_velocity, p - rod_b%rotation_center)
            scale = norm2(rod_a%velocity) + norm2(rod_b%velocity) + &
                norm2(rod_a%angular_velocity) * norm2(p - rod_a%rotation_center) + &
                norm2(rod_b%angular_velocity) * norm2(p - rod_b%rotation_center)
            if (norm2(va - vb) > rest_tolerance * scale) call errors%add(here // 'end_b: the ' // &
                'joined ends start with different velocities, (' // vector_text(vb) // ') for rod ''' // &
                trim(rod_b%name) // ''' and (' // vector_text(va) // ') for rod ''' // &
                trim(rod_a%name) // '''; joined ends move together (give the rods initial ' // &
                'motions that agree there)')
            if (trim(scene%joints(j)%kind) /= 'rigid') return
            if (norm2(rod_a%angular_velocity - rod_b%angular_velocity) > rest_tolerance * &
                    (norm2(rod_a%angular_velocity) + norm2(rod_b%angular_velocity))) &
                call errors%add(here // 'kind: a rigid joint turns both ends together, but rod ''' // &
                trim(rod_a%name) // ''' starts with angular_velocity (' // &
                vector_text(rod_a%angular_velocity) // ') and rod ''' // trim(rod_b%name) // &
                ''' with (' // vector_text(rod_b%angular_velocity) // ')')
        end subroutine check_joint_motion

        integer function rod_of(name, variable)
            character(len=*), intent(in) :: name, variable
            rod_of = rod_index(scene, name)
            if (rod_of == 0 .and. len_trim(name) > 0) call errors%add(here // variable // &
                ': no rod is named ''' // trim(name) // '''; rods: ' // rod_names(scene))
        end function rod_of

        pure integer function end_id(r, end_name)
            integer, intent(in) :: r
            character(len=*), intent(in) :: end_name
            end_id = 2 * (r - 1) + merge(1, 2, trim(end_name) == 'start')
        end function end_id

        pure integer function root(e)
            integer, intent(in) :: e
            root = e
            do while (parent(root) /= root)
                root = parent(root)
            end do
        end function root
    end subroutine check_joints

    !> A given &joint axis (revolute joints, DESIGN.md §1): components not given are 0, and a
    !> non-zero axis is normalized (kept bit for bit when unit to round-off, so that resolving a
    !> resolved scene changes nothing). Whether the formulation takes an axis, and a zero axis:
    !> check_joint_kind.
    subroutine resolve_joint_axes(scene)
        type(scene_t), intent(inout) :: scene
        integer :: j
        do j = 1, size(scene%joints)
            associate (axis => scene%joints(j)%axis)
                if (all(axis == unset_real)) cycle
                where (axis == unset_real) axis = 0.0_rk
                if (norm2(axis) > 0.0_rk .and. abs(norm2(axis) - 1.0_rk) > round_off) &
                    axis = axis / norm2(axis)
            end associate
        end do
    end subroutine resolve_joint_axes

    !> &plate (issue 10): a unique name; its rods given from the first entry without gaps, each
    !> an existing rod listed once; every tied end carries no &bc other than 'free', is tied by
    !> no &joint and is on no other plate, and its rod starts at rest (the plate holds the end
    !> as a clamp does); the time function as for a load, and f(0) = 0 for a driven plate (it
    !> starts at its reference pose); `centre` defaults, component by component, to the mean
    !> reference position of the tied ends. That the rods' formulation has end plates:
    !> check_capabilities.
    subroutine resolve_plates(scene, geometry_ok, errors)
        type(scene_t), intent(inout) :: scene
        logical, intent(in) :: geometry_ok(:)
        type(error_list_t), intent(inout) :: errors
        character(len=:), allocatable :: here
        character(len=name_len), allocatable :: names(:)
        type(time_function_t) :: f
        type(error_t), allocatable :: err
        real(rk) :: mean(3)
        integer :: p, q, k, n, r
        logical :: all_ends_known
        allocate(names(size(scene%rods)))
        do r = 1, size(scene%rods)
            names(r) = scene%rods(r)%name
        end do
        do p = 1, size(scene%plates)
            associate (plate => scene%plates(p))
                here = at(scene, plate%input_line) // '&plate ''' // trim(plate%name) // ''' '
                do q = 1, p - 1
                    if (scene%plates(q)%name == plate%name .and. len_trim(plate%name) > 0) &
                        call errors%add(here // 'name: ''' // trim(plate%name) // ''' is already ' // &
                        'the name of the plate at line ' // str(scene%plates(q)%input_line))
                end do
                n = 0
                do while (n < size(plate%rods))
                    if (len_trim(plate%rods(n + 1)) == 0) exit
                    n = n + 1
                end do
                if (any(len_trim(plate%rods(n + 1:)) > 0)) then
                    call errors%add(here // 'rods: entry ' // str(n + 1) // ' is not given but a ' // &
                        'later one is; give the rods from the first entry on without gaps')
                    cycle
                end if
                all_ends_known = len_trim(plate%end) > 0
                mean = 0.0_rk
                do k = 1, n
                    r = rod_index(scene, plate%rods(k))
                    if (r == 0) then
                        call errors%add(here // 'rods: no rod is named ''' // trim(plate%rods(k)) // &
                            '''' // did_you_mean(trim(plate%rods(k)), names) // '; rods: ' // &
                            rod_names(scene))
                        all_ends_known = .false.
                        cycle
                    end if
                    if (any(plate%rods(1:k - 1) == plate%rods(k))) then
                        call errors%add(here // 'rods: rod ''' // trim(plate%rods(k)) // ''' is ' // &
                            'listed twice; list each rod once')
                        cycle
                    end if
                    if (len_trim(plate%end) == 0) cycle
                    call check_tied_end(p, r, here, scene, errors)
                    if (geometry_ok(r)) then
                        mean = mean + end_point(scene%rods(r), plate%end)
                    else
                        all_ends_known = .false.
                    end if
                end do
                if (all_ends_known .and. n > 0) then
                    mean = mean / real(n, rk)
                    where (plate%centre == unset_real) plate%centre = mean
                end if
                call check_time_function(here, plate%time_function, plate%t_on, plate%t_off, &
                    plate%table_times, plate%table_values, errors)
                if (all(plate%displacement == 0.0_rk) .and. all(plate%rotation == 0.0_rk)) cycle
                call time_function_from_plate(plate, f, err)
                if (allocated(err)) then
                    deallocate(err)
                    cycle
                end if
                if (f%value(0.0_rk) /= 0.0_rk) call errors%add(here // 'time_function: f(0) = ' // &
                    str(f%value(0.0_rk)) // '; a driven plate (displacement or rotation not ' // &
                    'zero) starts at its reference pose, so f(0) = 0 (a ramp, hat, pulse, sine ' // &
                    'or a table starting at 0)')
            end associate
        end do
    end subroutine resolve_plates

    !> The end of rod `r` tied to plate `p` (message prefix `here`): no &bc but 'free', no
    !> joint, on no earlier plate, and the rod starts at rest.
    subroutine check_tied_end(p, r, here, scene, errors)
        integer, intent(in) :: p, r
        character(len=*), intent(in) :: here
        type(scene_t), intent(in) :: scene
        type(error_list_t), intent(inout) :: errors
        integer :: b, j, q
        associate (plate => scene%plates(p), rod => scene%rods(r))
            do b = 1, size(scene%bcs)
                if (scene%bcs(b)%rod /= rod%name .or. scene%bcs(b)%end /= plate%end) cycle
                if (trim(scene%bcs(b)%kind) == 'free') cycle
                call errors%add(here // 'rods: the ''' // trim(plate%end) // ''' end of rod ''' // &
                    trim(rod%name) // ''' has a ''' // trim(scene%bcs(b)%kind) // ''' &bc (line ' // &
                    str(scene%bcs(b)%input_line) // '); the plate holds the ends tied to it, so ' // &
                    'they carry no &bc: remove the &bc (a driven plate moves the end)')
            end do
            do j = 1, size(scene%joints)
                if (.not. ((scene%joints(j)%rod_a == rod%name .and. scene%joints(j)%end_a == &
                        plate%end) .or. (scene%joints(j)%rod_b == rod%name .and. &
                        scene%joints(j)%end_b == plate%end))) cycle
                call errors%add(here // 'rods: the ''' // trim(plate%end) // ''' end of rod ''' // &
                    trim(rod%name) // ''' is also tied by the &joint at line ' // &
                    str(scene%joints(j)%input_line) // '; an end is on a plate or in a joint, ' // &
                    'not both (list the other rod on the plate instead)')
            end do
            do q = 1, p - 1
                if (scene%plates(q)%end /= plate%end) cycle
                if (.not. any(scene%plates(q)%rods == rod%name)) cycle
                call errors%add(here // 'rods: the ''' // trim(plate%end) // ''' end of rod ''' // &
                    trim(rod%name) // ''' is already on the &plate ''' // &
                    trim(scene%plates(q)%name) // ''' (line ' // str(scene%plates(q)%input_line) // &
                    '); an end is on one plate at most')
            end do
            if (any(rod%velocity /= 0.0_rk) .or. any(rod%angular_velocity /= 0.0_rk)) &
                call errors%add(at(scene, rod%input_line) // '&rod ''' // trim(rod%name) // &
                ''' velocity, angular_velocity: (' // vector_text(rod%velocity) // '), (' // &
                vector_text(rod%angular_velocity) // ') given, but its ''' // trim(plate%end) // &
                ''' end is tied to the &plate ''' // trim(plate%name) // ''' (line ' // &
                str(plate%input_line) // '), which starts at rest; allowed: 0, 0, 0')
        end associate
    end subroutine check_tied_end

    !> &contact (issue 10, DESIGN.md §5). Without it no rod takes a contact_radius. With it every
    !> rod needs one: a 'circle' or 'tube' section's radius by default, required otherwise; the
    !> margin defaults to the largest contact_radius, and skip to ceiling(3 r_max / h_min) + 1
    !> (r_max the largest contact_radius, h_min the shortest element, length / n_elements):
    !> elements closer along a rod than 1.5 contact distances never pair, the rule of
    !> rs_ph_bundle, resolved here so that the echo and the plan show it. points_per_element is
    !> left to the formulation (it depends on its quadrature). stiffness > 0, margin >= 0,
    !> skip >= 0 and friction 'none' are the reader's (rs_io_input_spec); that all rods can
    !> touch (ph_director): check_capabilities.
    subroutine resolve_contact(scene, geometry_ok, errors)
        type(scene_t), intent(inout) :: scene
        logical, intent(in) :: geometry_ok(:)
        type(error_list_t), intent(inout) :: errors
        character(len=:), allocatable :: here
        real(rk) :: r_max, h_min
        integer :: i
        logical :: all_known
        all_known = .true.
        do i = 1, size(scene%rods)
            associate (rod => scene%rods(i))
                here = at(scene, rod%input_line) // '&rod ''' // trim(rod%name) // ''' '
                if (.not. scene%contact%given) then
                    if (rod%contact_radius /= unset_real) call errors%add(here // 'contact_radius: ' // &
                        str(rod%contact_radius) // ' given, but the scene has no &contact group, ' // &
                        'which is what uses it; remove it or add &contact')
                    cycle
                end if
                if (rod%contact_radius == unset_real) then
                    if ((trim(rod%section) == 'circle' .or. trim(rod%section) == 'tube') .and. &
                            rod%radius /= unset_real) then
                        rod%contact_radius = rod%radius
                    else
                        call errors%add(here // 'contact_radius: required with &contact (line ' // &
                            str(scene%contact%input_line) // ') for section = ''' // &
                            trim(rod%section) // ''' (only a circle or tube section gives it by ' // &
                            'default, its radius); give the radius of the rod''s surface')
                        all_known = .false.
                    end if
                end if
                if (.not. geometry_ok(i) .or. rod%n_elements < 1) all_known = .false.
            end associate
        end do
        if (.not. scene%contact%given .or. .not. all_known .or. size(scene%rods) == 0) return
        r_max = maxval(scene%rods%contact_radius)
        h_min = minval(scene%rods%length / real(scene%rods%n_elements, rk))
        if (scene%contact%margin == unset_real) scene%contact%margin = r_max
        if (scene%contact%skip == unset_int) scene%contact%skip = ceiling(3.0_rk * r_max / h_min) + 1
    end subroutine resolve_contact

    !> `formulation = 'auto'` (DESIGN.md §4): the rods of each system of joined rods
    !> (rs_model_coupling) that say 'auto' get ph_planar when the system, its loads and initial
    !> velocities lie in one plane (rs_model_planarity) and ph_planar can run all they ask
    !> for, else ph_director; formulation_reason says why.
    subroutine resolve_auto_formulations(scene)
        type(scene_t), intent(inout) :: scene
        integer, allocatable :: system_of(:), first(:), members(:), rods(:)
        type(plane_t) :: plane
        character(len=:), allocatable :: chosen, reason, obstacle
        integer :: k, m
        call coupled_systems(scene, system_of, first, members)
        do k = 1, size(first) - 1
            rods = members(first(k):first(k + 1) - 1)
            if (.not. any(scene%rods(rods)%formulation == 'auto')) cycle
            plane = plane_of_rods(scene, rods)
            if (plane%found) then
                obstacle = planar_obstacle(scene, rods)
                if (len(obstacle) == 0) then
                    chosen = 'ph_planar'
                    reason = 'the rods, loads and velocities lie in ' // plane_text(plane)
                else
                    chosen = 'ph_director'
                    reason = '3D although the rods lie in ' // plane_text(plane) // &
                        ', because ph_planar cannot run them: ' // obstacle
                end if
            else
                chosen = 'ph_director'
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

    !> The first thing rods `rods` (one system) ask for that ph_planar cannot do, without its
    !> file and line; '' if it can run them.
    function planar_obstacle(scene, rods) result(text)
        type(scene_t), intent(in) :: scene
        integer, intent(in) :: rods(:)
        character(len=:), allocatable :: text
        type(capability_t) :: row
        type(error_list_t) :: errors
        integer :: m, j, colon
        row = capability_of('ph_planar')
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

    !> em_variant of cl_em_planar rods defaults to 'stander_stein' and free_end of se3_strand
    !> rods to 'balanced' (a value given for another formulation is refused by
    !> check_formulation_variables).
    subroutine resolve_formulation_options(scene)
        type(scene_t), intent(inout) :: scene
        integer :: i
        do i = 1, size(scene%rods)
            associate (rod => scene%rods(i))
                if (trim(rod%formulation) == 'cl_em_planar' .and. len_trim(rod%em_variant) == 0) &
                    rod%em_variant = 'stander_stein'
                if (trim(rod%formulation) == 'se3_strand' .and. len_trim(rod%free_end) == 0) &
                    rod%free_end = 'balanced'
                ! cl_em_planar's full (2-point) quadrature of the axial and shear terms locks
                ! in bending (methods/ph_planar.md §5.1-5.2, the roll-up): its default is the
                ! reduced one (issue 21 item 16).
                if (rod%n_gauss == unset_int) then
                    rod%n_gauss = 2
                    if (trim(rod%formulation) == 'cl_em_planar') rod%n_gauss = 1
                end if
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
                        available_formulation_names() // see_matrix)
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
    end subroutine check_capabilities

    !> End plates and contact against `row` (rod `i`'s formulation, or ph_planar for 'auto'):
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
        end associate
    end subroutine check_bundle_capabilities

    !> Joints that are constraints with multipliers (a 3D formulation, ph_director) tie free
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

    !> Variables that only some formulations read: the planar elements take n_gauss 1 or 2 (for
    !> cl_em_planar the quadrature of the axial and shear terms, 1 reduced, 2 full:
    !> methods/ph_planar.md §5.1); em_variant is cl_em_planar's only; the damping of seed 004
    !> (external_damping, internal_damping, kelvin_voigt_time) and free_end are se3_strand's only.
    subroutine check_formulation_variables(scene, i, row, errors)
        type(scene_t), intent(in) :: scene
        integer, intent(in) :: i
        type(capability_t), intent(in) :: row
        type(error_list_t), intent(inout) :: errors
        character(len=:), allocatable :: here
        associate (rod => scene%rods(i))
            here = at(scene, rod%input_line) // '&rod ''' // trim(rod%name) // ''' '
            if (row%planar .and. rod%n_gauss > 2) call errors%add(here // 'n_gauss: ' // &
                str(rod%n_gauss) // ' given, but the planar elements take 1 or 2 Gauss points ' // &
                '(cl_em_planar: for its axial and shear terms, 1 = reduced, 2 = full); allowed: 1, 2')
            if (trim(row%formulation) /= 'cl_em_planar' .and. len_trim(rod%em_variant) > 0) &
                call errors%add(here // 'em_variant: only used with formulation ''cl_em_planar'' ' // &
                '(this rod runs on ''' // trim(row%formulation) // '''); remove it')
            if (trim(row%formulation) == 'se3_strand') return
            if (len_trim(rod%free_end) > 0) call errors%add(here // 'free_end: only used with ' // &
                'formulation ''se3_strand'' (this rod runs on ''' // trim(row%formulation) // &
                '''); remove it')
            call strand_only(rod%external_damping, 'external_damping')
            call strand_only(rod%internal_damping, 'internal_damping')
            call strand_only(rod%kelvin_voigt_time, 'kelvin_voigt_time')
        end associate
    contains
        !> A nonzero `value` of the se3_strand variable `name` on a rod of another formulation.
        subroutine strand_only(value, name)
            real(rk), intent(in) :: value
            character(len=*), intent(in) :: name
            if (value /= 0.0_rk) call errors%add(here // name // ': only used with formulation ' // &
                '''se3_strand'' (this rod runs on ''' // trim(row%formulation) // '''); remove it')
        end subroutine strand_only
    end subroutine check_formulation_variables

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
                    '; use ''ph_director'' (3D) or ''auto''')
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
            if (rod%prestressed .and. .not. row%prestressed) call errors%add(at(scene, &
                rod%input_line) // '&rod prestressed: a straight stress-free shape under a ' // &
                'curved initial one is not available for ' // what // ' (rod ''' // &
                trim(rod%name) // '''): it would be ignored' // see_matrix)
            if (scene%time%quasistatic .and. .not. row%quasistatic) call errors%add(at(scene, 0) // &
                '&time quasistatic: not available for ' // what // ' (rod ''' // trim(rod%name) // &
                ''')' // see_matrix)
            if (scene%time%relaxation .and. .not. row%relaxation) call errors%add(at(scene, 0) // &
                '&time relaxation: statics by damped dynamics is not available for ' // what // &
                ' (rod ''' // trim(rod%name) // ''')' // see_matrix)
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
                                'end: ' // trim(row%end_kinds) // ')' // strand_reason() // see_matrix)
                        end if
                        cycle
                    end if
                    if (trim(bc%kind) == 'driven') call check_drive(bc)
                end associate
            end do
            ! An end without &bc is free: refused where the formulation cannot leave it free.
            do e = 1, 2
                if (lists_name(end_kinds_at(row, end_names(e)), 'free')) cycle
                if (any(scene%bcs%rod == rod%name .and. scene%bcs%end == end_names(e))) cycle
                call errors%add(at(scene, rod%input_line) // '&bc: rod ''' // trim(rod%name) // &
                    ''' has no &bc at its ''' // trim(end_names(e)) // ''' end, i.e. a free end, ' // &
                    'which is not available there for ' // what // '; available: ' // &
                    end_kinds_at(row, end_names(e)) // strand_reason() // see_matrix)
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

        !> Why se3_strand's ends differ (methods/se3_strands.md §3.4).
        function strand_reason() result(text)
            character(len=:), allocatable :: text
            text = ''
            if (trim(row%formulation) == 'se3_strand') text = '; se3_strand prescribes the ' // &
                'motion at s = 0 and the stress at s = L (methods/se3_strands.md §3.4)'
        end function strand_reason
    end subroutine check_rod_capabilities

    !> Names of the formulations this build can run.
    function available_formulation_names() result(names)
        character(len=:), allocatable :: names
        type(capability_t) :: row
        integer :: i
        names = ''
        do i = 1, size(formulation_names)
            row = capability_of(formulation_names(i))
            if (.not. row%available) cycle
            if (len(names) > 0) names = names // ', '
            names = names // trim(formulation_names(i))
        end do
    end function available_formulation_names

end module rs_io_input_check
