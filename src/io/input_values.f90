!> Checks of one group's values and the defaults derived from them (DESIGN.md §6), for a scene
!> that was read without errors: dt against t_end and the number of steps, relaxation against
!> quasistatics, output and restart, and each &rod resolved on its own (name, formulation
!> origin, the centreline's start, direction and length, directors, the centre of the
!> initial rotation, Maxwell branches and their shear relaxation times, stiffnesses from
!> section and material, inertia; a helix length that contradicts its turns, a polyline that
!> doubles back, a rest-curvature table whose s goes back). Every problem is added to
!> `errors`, naming the file, line, group and variable.
module rs_io_input_values
    use rs_core_kinds, only: rk
    use rs_core_error, only: error_list_t
    use rs_core_strings, only: str, vector_text, str_significant
    use rs_model_scene, only: scene_t, rod_input_t, time_input_t, unset_real, unset_int, &
        section_derived_names, rod_is_damped, segment_input_t
    use rs_model_rod_geometry, only: rod_geometry_t, straight_geometry, helix_geometry, &
        polyline_geometry, centreline_tangent, default_normal, curvature_geometry, curvature_rows
    use rs_model_section, only: section_properties_t, section_values, circle_section, tube_section, &
        rectangle_section
    use rs_io_result_file, only: unknown_fields, selectable_fields
    use rs_io_input_check_common, only: at, leading_count
    implicit none
    private

    public :: check_step_count, check_relaxation, check_output_and_restart, resolve_rod, &
        default_output_path, resolve_segments

    !> Deviation from unit length or orthogonality that counts as round-off.
    real(rk), parameter :: round_off = 4.0_rk * epsilon(1.0_rk)
    !> Relative difference below which a given length agrees with a derived one.
    real(rk), parameter :: length_tolerance = 1.0e-9_rk
    !> Largest |t_j + t_{j+1}| of consecutive polyline tangents that counts as a reversal.
    real(rk), parameter :: reversal_tolerance = 1.0e-8_rk

contains


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
        call check_continuation(scene, errors)
        call check_order(scene, errors)
        call check_adaptive(scene, errors)
        call check_scheme(scene, errors)
    end subroutine check_relaxation

    !> &time continuation = 'arc_length' (docs/theory/continuation.md): a path of the statics,
    !> so only in quasistatic runs; its step bounds in order; no contact (the pattern changes);
    !> no restart (the path's tangent and step length are not in the checkpoint).
    subroutine check_continuation(scene, errors)
        type(scene_t), intent(in) :: scene
        type(error_list_t), intent(inout) :: errors
        character(len=:), allocatable :: here
        if (trim(scene%time%continuation) /= 'arc_length') return
        here = at(scene, scene%time%input_line) // '&time continuation: '
        if (.not. scene%time%quasistatic) call errors%add(here // '''arc_length'' traces ' // &
            'an equilibrium path, which needs quasistatic = .true.')
        if (scene%time%arc_length_max < scene%time%arc_length) call errors%add(here // &
            'arc_length_max = ' // str(scene%time%arc_length_max) // ' is shorter than ' // &
            'arc_length = ' // str(scene%time%arc_length))
        ! Contact's candidate pairs change the Jacobian's pattern between steps (the stepper is
        ! built again), which the path's factorization and work arrays do not follow.
        if (scene%contact%given) call errors%add(here // 'not with &contact (its pairs change ' // &
            'the Jacobian''s pattern along the path)')
        if (allocated(scene%obstacles)) then
            if (size(scene%obstacles) > 0) call errors%add(here // 'not with &obstacle (its ' // &
                'contact pairs change the Jacobian''s pattern along the path)')
        end if
        if (len_trim(scene%run%restart_from) > 0) call errors%add(here // 'a continuation ' // &
            'cannot be restarted (its path''s tangent and step are not checkpointed); ' // &
            'remove &run restart_from')
    end subroutine check_continuation

    !> &time adaptive (issue 25 item 2): its tolerances and step bounds, the scenes it cannot
    !> step (a load path, relaxation, contact: contact's pairs and motion limit are set per
    !> record interval), and its variables given without it (they would be silently ignored).
    subroutine check_adaptive(scene, errors)
        type(scene_t), intent(in) :: scene
        type(error_list_t), intent(inout) :: errors
        type(time_input_t) :: defaults
        character(len=:), allocatable :: here
        logical :: contact
        here = at(scene, scene%time%input_line) // '&time adaptive: '
        associate (time => scene%time)
            if (.not. time%adaptive) then
                if (time%rtol /= defaults%rtol .or. time%atol /= defaults%atol .or. &
                        time%dt_min /= unset_real .or. time%dt_max /= unset_real .or. &
                        time%dt_initial /= unset_real) call errors%add(at(scene, scene%time%input_line) // &
                    '&time rtol, atol, dt_min, dt_max, dt_initial: given, but they are only ' // &
                    'used with adaptive = .true.; remove them or set adaptive')
                return
            end if
            if (time%quasistatic) call errors%add(here // 'a quasistatic load path has no ' // &
                'local error in time to control; use fixed steps')
            if (time%relaxation) call errors%add(here // 'relaxation runs to rest, not along a ' // &
                'path whose error could be controlled; use fixed steps')
            contact = scene%contact%given
            if (allocated(scene%obstacles)) contact = contact .or. size(scene%obstacles) > 0
            if (contact) call errors%add(here // 'not with contact (&contact, &obstacle): its ' // &
                'pairs and motion limit are set for a whole record interval; use fixed steps')
            if (time%rtol == 0.0_rk .and. time%atol == 0.0_rk) call errors%add(here // &
                'rtol and atol are both 0: no error is small enough')
            if (time%dt_max /= unset_real .and. time%dt /= unset_real) then
                if (time%dt_max > time%dt) call errors%add(at(scene, scene%time%input_line) // '&time dt_max: ' // &
                    str(time%dt_max) // ' is larger than dt = ' // str(time%dt) // ', the ' // &
                    'record interval no step crosses')
            end if
            if (time%dt_initial /= unset_real .and. time%dt_max /= unset_real) then
                if (time%dt_initial > time%dt_max) call errors%add(at(scene, scene%time%input_line) // &
                    '&time dt_initial: ' // str(time%dt_initial) // ' is larger than dt_max = ' // &
                    str(time%dt_max))
            end if
            if (time%dt_min /= unset_real .and. time%dt_initial /= unset_real) then
                if (time%dt_min > time%dt_initial) call errors%add(at(scene, scene%time%input_line) // &
                    '&time dt_min: ' // str(time%dt_min) // ' is larger than dt_initial = ' // &
                    str(time%dt_initial))
            end if
        end associate
    end subroutine check_adaptive

    !> &time scheme = 'generalized_alpha' (issue 25 item 3): the dynamics of se3_pg (which
    !> formulations have it is their capability, rs_io_input_capability_check). It is a scheme
    !> of its own, not a midpoint step: no composition to order 4, no load path, no relaxation;
    !> and the couplings of the system layer are midpoint terms (ties' forces at the
    !> midpoint, contact's discrete gradients, docs/theory/bundles.md), which would act at
    !> the wrong time of its stage (docs/theory/se3_pg.md, "Generalized-alpha").
    subroutine check_scheme(scene, errors)
        type(scene_t), intent(in) :: scene
        type(error_list_t), intent(inout) :: errors
        character(len=:), allocatable :: here
        logical :: joined, plated, obstacles
        if (trim(scene%time%scheme) /= 'generalized_alpha') return
        here = at(scene, scene%time%input_line) // '&time scheme: ''generalized_alpha'' '
        if (scene%time%order /= 2) call errors%add(here // 'is second order and not a ' // &
            'midpoint step that order = ' // str(scene%time%order) // ' could compose; ' // &
            'remove order or use scheme = ''midpoint''')
        if (scene%time%quasistatic) call errors%add(here // 'integrates dynamics; a ' // &
            'quasistatic run has none (its load steps are equilibria): remove scheme or ' // &
            'quasistatic')
        if (scene%time%relaxation) call errors%add(here // 'is not for relaxation (damped ' // &
            'dynamics towards statics): use scheme = ''midpoint''')
        if (scene%time%adaptive) call errors%add(here // 'carries its rates from step to ' // &
            'step for the step it was taken with; a step changed at every step would lose its ' // &
            'order: use fixed steps or scheme = ''midpoint''')
        joined = .false.
        if (allocated(scene%joints)) joined = size(scene%joints) > 0
        plated = .false.
        if (allocated(scene%plates)) plated = size(scene%plates) > 0
        obstacles = .false.
        if (allocated(scene%obstacles)) obstacles = size(scene%obstacles) > 0
        if (joined .or. plated .or. scene%contact%given .or. obstacles) call errors%add(here // &
            'is not available with &joint, &plate, &contact or &obstacle: their forces are ' // &
            'midpoint terms of the system layer and would act at the wrong time of its ' // &
            'stage; use scheme = ''midpoint''')
    end subroutine check_scheme

    !> &time order (issue 25 item 1): 2 or 4; order 4 takes a negative sub-step, which a
    !> dissipative term would turn into an energy source, and which a load path or a
    !> relaxation cannot take.
    subroutine check_order(scene, errors)
        type(scene_t), intent(in) :: scene
        type(error_list_t), intent(inout) :: errors
        character(len=:), allocatable :: here
        integer :: i
        here = at(scene, scene%time%input_line) // '&time order: 4 '
        if (scene%time%order /= 2 .and. scene%time%order /= 4) call errors%add(at(scene, &
            scene%time%input_line) // &
            '&time order: ' // str(scene%time%order) // '; allowed: 2 (the midpoint step) or 4 ' // &
            '(Suzuki''s five-stage composition of midpoint steps)')
        if (scene%time%order /= 4) return
        if (scene%time%quasistatic) call errors%add(here // 'composes steps in time with a ' // &
            'negative sub-step; a quasistatic load path has no dynamics to compose: use order 2')
        if (scene%time%relaxation) call errors%add(here // 'is not for relaxation (damped ' // &
            'dynamics towards statics): use order 2')
        do i = 1, size(scene%rods)
            associate (rod => scene%rods(i))
                if (any(rod%maxwell_fraction /= unset_real)) call errors%add(at(scene, &
                    rod%input_line) // '&rod ''' // trim(rod%name) // ''' maxwell_fraction: ' // &
                    'Maxwell branches dissipate, and order 4''s negative sub-step would make ' // &
                    'them an energy source; use &time order = 2')
                if (rod_is_damped(rod)) call errors%add(at(scene, rod%input_line) // &
                    '&rod ''' // trim(rod%name) // ''' kelvin_voigt_time, drag, angular_drag: ' // &
                    'damping dissipates, and order 4''s negative sub-step would make it an ' // &
                    'energy source; use &time order = 2')
            end associate
        end do
        if (scene%contact%given .and. scene%contact%mu > 0.0_rk) call errors%add(here // &
            'with &contact mu > 0: friction dissipates, and the negative sub-step would make ' // &
            'it an energy source; use order 2')
        if (allocated(scene%obstacles)) then
            do i = 1, size(scene%obstacles)
                if (scene%obstacles(i)%mu > 0.0_rk .or. scene%obstacles(i)%damping > 0.0_rk) &
                    call errors%add(at(scene, scene%obstacles(i)%input_line) // '&obstacle ''' // &
                    trim(scene%obstacles(i)%name) // ''': friction and normal damping ' // &
                    'dissipate, and &time order = 4''s negative sub-step would make them an ' // &
                    'energy source; use order 2')
            end do
        end if
    end subroutine check_order


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
            call resolve_kelvin_voigt(rod, here, errors)
            if (scene%time%quasistatic .and. rod_is_damped(rod)) call errors%add(here // &
                'kelvin_voigt_time, drag, angular_drag: a quasistatic run (&time quasistatic) ' // &
                'follows a load path whose parameter is not a physical time, so viscous ' // &
                'damping has no rate to act on; remove them or run dynamics')
            call resolve_stiffness(rod, here, errors)
            if (.not. scene%time%quasistatic) call check_inertia(rod, here, errors)
        end associate
    end subroutine resolve_rod


    !> &segment groups (issue 26 item 5): each names a resolved rod; the s_end of one rod's
    !> segments increase in file order, stay within its length and fall on nodes of its uniform
    !> mesh (so every element lies in one segment). Each segment's values are the rod's
    !> resolved ones with the segment's given section and material (resolved again as a
    !> section: G from nu when the rod gave nu, not G) and then its given stiffnesses and
    !> inertias on top.
    subroutine resolve_segments(scene, geometry_ok, errors)
        type(scene_t), intent(inout) :: scene
        logical, intent(in) :: geometry_ok(:)
        type(error_list_t), intent(inout) :: errors
        character(len=:), allocatable :: here
        real(rk) :: previous, nodes
        integer :: k, j, r
        if (.not. allocated(scene%segments)) allocate(scene%segments(0))
        do k = 1, size(scene%segments)
            associate (seg => scene%segments(k))
                here = at(scene, seg%input_line) // '&segment (rod ''' // trim(seg%rod) // ''') '
                r = findloc(scene%rods%name, seg%rod, dim=1)
                if (r == 0) then
                    call errors%add(here // 'rod: no &rod is named ''' // trim(seg%rod) // '''')
                    cycle
                end if
                if (.not. geometry_ok(r) .or. scene%rods(r)%length == unset_real) cycle
                associate (rod => scene%rods(r))
                    previous = 0.0_rk
                    do j = 1, k - 1
                        if (scene%segments(j)%rod == seg%rod) previous = scene%segments(j)%s_end
                    end do
                    if (seg%s_end <= previous) then
                        call errors%add(here // 's_end: ' // str(seg%s_end) // ' is not after ' // &
                            'the previous segment''s end ' // str(previous) // '; give the ' // &
                            'segments of a rod in increasing s_end')
                        cycle
                    end if
                    if (seg%s_end > rod%length * (1.0_rk + length_tolerance)) then
                        call errors%add(here // 's_end: ' // str(seg%s_end) // ' is beyond the ' // &
                            'rod''s length ' // str(rod%length))
                        cycle
                    end if
                    if (rod%n_elements /= unset_int) then
                        nodes = seg%s_end / rod%length * real(rod%n_elements, rk)
                        if (abs(nodes - anint(nodes)) > length_tolerance * real(rod%n_elements, rk)) then
                            call errors%add(here // 's_end: ' // str(seg%s_end) // ' is not a ' // &
                                'node of the rod''s uniform mesh of n_elements = ' // &
                                str(rod%n_elements) // ' (element length ' // &
                                str(rod%length / real(rod%n_elements, rk)) // '); give a ' // &
                                'multiple of the element length or change n_elements')
                            cycle
                        end if
                    end if
                    seg%s_start = previous
                    call resolve_segment_values(scene, rod, seg, here, errors)
                end associate
            end associate
        end do
    end subroutine resolve_segments

    !> The values of one segment (resolve_segments) from its resolved rod.
    subroutine resolve_segment_values(scene, rod, seg, here, errors)
        type(scene_t), intent(in) :: scene
        type(rod_input_t), intent(in) :: rod
        type(segment_input_t), intent(inout) :: seg
        character(len=*), intent(in) :: here
        type(error_list_t), intent(inout) :: errors
        type(rod_input_t) :: part
        real(rk) :: given(9), values(9)
        integer :: n_errors
        logical :: material_given
        part = rod
        material_given = any([seg%radius, seg%inner_radius, seg%width, seg%height, seg%E, seg%G, &
            seg%nu, seg%density, seg%shear_factor] /= unset_real) .or. len_trim(seg%section) > 0 &
            .or. len_trim(seg%torsion_constant) > 0
        if (len_trim(seg%section) > 0) part%section = seg%section
        if (seg%radius /= unset_real) part%radius = seg%radius
        if (seg%inner_radius /= unset_real) part%inner_radius = seg%inner_radius
        if (seg%width /= unset_real) part%width = seg%width
        if (seg%height /= unset_real) part%height = seg%height
        if (seg%E /= unset_real) part%E = seg%E
        if (seg%nu /= unset_real) part%nu = seg%nu
        ! A G the rod derived from its nu follows the segment's E and nu.
        if (seg%G /= unset_real) then
            part%G = seg%G
        else if ((seg%E /= unset_real .or. seg%nu /= unset_real) .and. part%nu /= unset_real) then
            part%G = unset_real
        end if
        if (seg%density /= unset_real) part%density = seg%density
        if (seg%shear_factor /= unset_real) part%shear_factor = seg%shear_factor
        if (len_trim(seg%torsion_constant) > 0) part%torsion_constant = seg%torsion_constant
        if (trim(part%section) /= 'none') then
            part%EA = unset_real
            part%GA1 = unset_real
            part%GA2 = unset_real
            part%EI1 = unset_real
            part%EI2 = unset_real
            part%GJ = unset_real
            part%rhoA = unset_real
            part%rhoI1 = unset_real
            part%rhoI2 = unset_real
            n_errors = errors%count
            call resolve_stiffness(part, here, errors)
            if (errors%count > n_errors) return
        else if (material_given) then
            call errors%add(here // 'section: section, material or section sizes given, but ' // &
                'the section is ''none'' (the rod''s stiffnesses are given directly); give ' // &
                'the segment''s section too, or its stiffnesses EA ... rhoI2')
            return
        end if
        values = [part%EA, part%GA1, part%GA2, part%EI1, part%EI2, part%GJ, part%rhoA, &
            part%rhoI1, part%rhoI2]
        if (any([seg%radius_end, seg%inner_radius_end, seg%width_end, seg%height_end] /= &
                unset_real)) then
            n_errors = errors%count
            call resolve_taper(part, seg, here, errors)
            if (errors%count > n_errors) return
        end if
        given = [seg%EA, seg%GA1, seg%GA2, seg%EI1, seg%EI2, seg%GJ, seg%rhoA, seg%rhoI1, seg%rhoI2]
        where (given /= unset_real) values = given
        seg%values = values
        part%rhoA = values(7)
        part%rhoI1 = values(8)
        part%rhoI2 = values(9)
        if (.not. scene%time%quasistatic) call check_inertia(part, here, errors)
    end subroutine resolve_segment_values

    !> A linear taper of segment `seg` (issue 26 item 5): its section `part` (resolved) has
    !> the dimensions given at s_end (radius_end for a circle, radius_end and inner_radius_end
    !> for a tube, width_end and height_end for a rectangle; each not given stays the start's),
    !> positive, a tube's inner radius below its outer one at the end too.
    subroutine resolve_taper(part, seg, here, errors)
        type(rod_input_t), intent(in) :: part
        type(segment_input_t), intent(inout) :: seg
        character(len=*), intent(in) :: here
        type(error_list_t), intent(inout) :: errors
        character(len=16), parameter :: names(4) = [character(len=16) :: 'radius_end', &
            'inner_radius_end', 'width_end', 'height_end']
        real(rk) :: start(4), finish(4)
        character(len=:), allocatable :: allowed
        logical :: used(4)
        integer :: k
        select case (trim(part%section))
        case ('circle')
            used = [.true., .false., .false., .false.]
        case ('tube')
            used = [.true., .true., .false., .false.]
        case ('rectangle')
            used = [.false., .false., .true., .true.]
        case default
            call errors%add(here // 'radius_end: a taper needs a section (circle, tube or ' // &
                'rectangle), not section = ''' // trim(part%section) // '''')
            return
        end select
        allowed = ''
        do k = 1, 4
            if (.not. used(k)) cycle
            if (len(allowed) > 0) allowed = allowed // ' and '
            allowed = allowed // trim(names(k))
        end do
        start = [part%radius, part%inner_radius, part%width, part%height]
        finish = [seg%radius_end, seg%inner_radius_end, seg%width_end, seg%height_end]
        do k = 1, 4
            if (finish(k) /= unset_real .and. .not. used(k)) call errors%add(here // &
                trim(names(k)) // ': not a dimension of a ' // trim(part%section) // &
                ' (a taper gives ' // allowed // ')')
            if (.not. used(k)) start(k) = 0.0_rk
            if (finish(k) == unset_real .or. .not. used(k)) finish(k) = start(k)
        end do
        if (used(2) .and. finish(2) >= finish(1)) call errors%add(here // 'inner_radius_end: ' // &
            str(finish(2)) // ' must be smaller than the outer radius at s_end, ' // str(finish(1)))
        seg%taper = part%section
        seg%taper_dims(:, 1) = start
        seg%taper_dims(:, 2) = finish
        seg%taper_material = [part%E, part%G, part%density, part%shear_factor]
        seg%saint_venant = trim(part%torsion_constant) == 'saint_venant'
    end subroutine resolve_taper

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
        real(rk), allocatable :: points(:, :), s(:), kappa(:, :)
        real(rk), parameter :: e_x(3) = [1.0_rk, 0.0_rk, 0.0_rk]
        real(rk) :: t(3)
        character(len=:), allocatable :: formula, shape
        integer :: n_points, j
        logical :: start_given, direction_given

        ok = .false.
        ! Component by component, so that start(2) = 5 alone keeps the other defaults.
        start_given = any(rod%start /= unset_real)
        direction_given = any(rod%direction /= unset_real)
        where (rod%start == unset_real) rod%start = 0.0_rk
        where (rod%direction == unset_real) rod%direction = e_x
        if (trim(rod%geometry) == 'polyline') then
            if (.not. table_rows(rod%points, 3, here // 'points: ', 'points', &
                'point takes 3 (x, y, z)', 'a polyline', errors, n_points)) return
            points = reshape(rod%points(1:3 * n_points), [3, n_points])
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
            else if (trim(rod%geometry) == 'curvature') then
                if (.not. curvature_ok(rod, here, errors)) return
                call curvature_rows(rod, s, kappa)
                geometry = curvature_geometry(rod%start, rod%direction, s, kappa)
            else
                if (rod%length == unset_real) return
                geometry = straight_geometry(rod%start, rod%direction, rod%length)
            end if
        end if
        if (trim(rod%geometry) /= 'straight') then
            if (rod%length /= unset_real .and. abs(rod%length - geometry%length) > &
                    length_tolerance * geometry%length) then
                shape = trim(rod%geometry)
                if (trim(rod%geometry) == 'helix') then
                    formula = 'helix_turns sqrt((2 pi helix_radius)^2 + helix_pitch^2)'
                else if (trim(rod%geometry) == 'curvature') then
                    shape = 'rod'
                    formula = 'the last s of its rest_curvature_table'
                else
                    formula = 'the sum of its segments'
                end if
                call errors%add(here // 'length: ' // str(rod%length) // ' given, but the ' // &
                    shape // ' is ' // str(geometry%length) // ' long (' // formula // &
                    '); leave length out or give that value')
                return
            end if
            rod%length = geometry%length
        end if
        ok = .true.
    end subroutine resolve_geometry


    !> The rest curvature of a 'curvature' rod (rs_model_rest_curvature): exactly one of
    !> rest_curvature (constant; with length) and rest_curvature_table (rows s, kappa1, kappa2,
    !> kappa3 without gaps: at least two, s from 0, never decreasing, at most two rows at one s
    !> (a jump), the last s > 0, which is the length).
    logical function curvature_ok(rod, here, errors) result(ok)
        type(rod_input_t), intent(in) :: rod
        character(len=*), intent(in) :: here
        type(error_list_t), intent(inout) :: errors
        real(rk), allocatable :: s(:)
        integer :: n_rows, j
        logical :: constant, table
        ok = .false.
        constant = any(rod%rest_curvature /= unset_real)
        table = any(rod%rest_curvature_table /= unset_real)
        if (constant .and. table) then
            call errors%add(here // 'rest_curvature, rest_curvature_table: both given; give ' // &
                'either a constant rest_curvature (with length) or a rest_curvature_table')
            return
        else if (.not. (constant .or. table)) then
            call errors%add(here // 'rest_curvature: geometry = ''curvature'' needs a constant ' // &
                'rest_curvature (with length) or a rest_curvature_table; neither is given')
            return
        else if (constant) then
            ok = rod%length /= unset_real
            if (.not. ok) call errors%add(here // 'length: required with a constant ' // &
                'rest_curvature (a rest_curvature_table gives it as its last s)')
            return
        end if
        if (.not. table_rows(rod%rest_curvature_table, 4, here // 'rest_curvature_table: ', &
            'rows', 'row takes 4 (s, kappa1, kappa2, kappa3)', 'a table', errors, n_rows)) return
        s = rod%rest_curvature_table(1:4 * n_rows:4)
        if (s(1) /= 0.0_rk) then
            call errors%add(here // 'rest_curvature_table: the first row is at s = ' // &
                str(s(1)) // '; the table starts at s = 0')
            return
        end if
        do j = 1, n_rows - 1
            if (s(j + 1) < s(j)) then
                call errors%add(here // 'rest_curvature_table: s decreases from ' // str(s(j)) // &
                    ' (row ' // str(j) // ') to ' // str(s(j + 1)) // ' (row ' // str(j + 1) // &
                    '); s must not decrease')
                return
            end if
            if (j < n_rows - 1) then
                if (s(j + 2) == s(j)) then
                    call errors%add(here // 'rest_curvature_table: rows ' // str(j) // ' to ' // &
                        str(j + 2) // ' are all at s = ' // str(s(j)) // '; at most two rows ' // &
                        'may share an s (a jump)')
                    return
                end if
            end if
        end do
        if (s(n_rows) <= 0.0_rk) then
            call errors%add(here // 'rest_curvature_table: the last s is ' // str(s(n_rows)) // &
                '; it is the length of the rod and must be > 0')
            return
        end if
        ok = .true.
    end function curvature_ok


    !> The rows of a flat table of `width` numbers per row (its leading given entries): false,
    !> with an error after `prefix` (file, line, group, variable), if a given entry follows a
    !> gap, the count is not a multiple of `width` or there are fewer than 2 rows.
    logical function table_rows(values, width, prefix, rows, row_text, owner, errors, n_rows) &
            result(ok)
        real(rk), intent(in) :: values(:)
        integer, intent(in) :: width
        character(len=*), intent(in) :: prefix, rows, row_text, owner
        type(error_list_t), intent(inout) :: errors
        integer, intent(out) :: n_rows
        integer :: n_values
        ok = .false.
        n_values = leading_count(values)
        n_rows = n_values / width
        if (any(values(n_values + 1:) /= unset_real)) then
            call errors%add(prefix // 'entry ' // str(n_values + 1) // ' is not given but a ' // &
                'later one is; give the ' // rows // ' from the first on without gaps')
        else if (mod(n_values, width) /= 0) then
            call errors%add(prefix // str(n_values) // ' values given; each ' // row_text)
        else if (n_rows < 2) then
            call errors%add(prefix // owner // ' needs at least 2 ' // rows // ' (' // &
                str(n_rows) // ' given)')
        else
            ok = .true.
        end if
    end function table_rows


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

    !> Kelvin-Voigt time constants (docs/theory/damping.md): none given is no viscosity, one
    !> is every component's, six are (EA, GA1, GA2, EI1, EI2, GJ)'s; any other count is an
    !> error, since the reader could not tell which components were meant.
    subroutine resolve_kelvin_voigt(rod, here, errors)
        type(rod_input_t), intent(inout) :: rod
        character(len=*), intent(in) :: here
        type(error_list_t), intent(inout) :: errors
        integer :: n
        n = leading_count(rod%kelvin_voigt_time)
        if (any(rod%kelvin_voigt_time(n + 1:) /= unset_real) .or. (n > 1 .and. n < 6)) then
            call errors%add(here // 'kelvin_voigt_time: ' // &
                str(count(rod%kelvin_voigt_time /= unset_real)) // ' value(s) given; give one ' // &
                '(every stress component) or six (EA, GA1, GA2, EI1, EI2, GJ in this order)')
            return
        end if
        select case (n)
        case (0)
            rod%kelvin_voigt_time = 0.0_rk
        case (1)
            rod%kelvin_voigt_time = rod%kelvin_voigt_time(1)
        end select
    end subroutine resolve_kelvin_voigt

    !> Stiffnesses and inertias: given directly (section = 'none'), or from section and material.
    subroutine resolve_stiffness(rod, here, errors)
        type(rod_input_t), intent(inout) :: rod
        character(len=*), intent(in) :: here
        type(error_list_t), intent(inout) :: errors
        real(rk) :: direct(9)
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
        direct = section_values(s, rod%E, rod%G, rod%density, rod%shear_factor, &
            trim(rod%torsion_constant) == 'saint_venant')
        rod%EA = direct(1)
        rod%GA1 = direct(2)
        rod%GA2 = direct(3)
        rod%EI1 = direct(4)
        rod%EI2 = direct(5)
        rod%GJ = direct(6)
        rod%rhoA = direct(7)
        rod%rhoI1 = direct(8)
        rod%rhoI2 = direct(9)
    contains
        logical function need(value, name)
            real(rk), intent(in) :: value
            character(len=*), intent(in) :: name
            need = value /= unset_real
            if (.not. need) call errors%add(here // name // ': required with section = ''' // &
                trim(rod%section) // '''')
        end function need
    end subroutine resolve_stiffness


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

end module rs_io_input_values
