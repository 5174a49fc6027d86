!> Checks across groups of a scene whose groups were resolved on their own (DESIGN.md §6):
!> unique rod names; &bc, &load and &actuator on rods that exist, an end supported twice
!> (except by several velocity drives), tables that are not increasing, an initial velocity at
!> a clamped, pinned, sliding or held end, a held end's entries named once; the joints
!> (existing rods, no end tied to itself, no redundant joint, ends that coincide, an axis for
!> revolute joints only); the end plates (&plate:
!> existing rods, each tied end on one plate only, without &bc or joint, the centre defaulted
!> to the mean of the tied ends, the time function of a driven plate) and contact (&contact:
!> every rod's contact_radius, defaulted to a circle or tube section's radius, the margin and
!> the skip derived). Every problem is added to `errors`.
module rs_io_input_cross_check
    use rs_core_kinds, only: rk
    use rs_core_error, only: error_list_t, error_t
    use rs_core_strings, only: str, vector_text, did_you_mean
    use rs_model_scene, only: scene_t, rod_input_t, actuator_input_t, bc_input_t, unset_real, &
        unset_int, name_len, body_inertia_tensor, inertia_tensor, plate_input_t
    use rs_model_time_function, only: time_function_t, time_function_from_bc, &
        time_function_from_plate, time_function_from_obstacle
    use rs_model_rod_geometry, only: rod_geometry_t, rod_geometry_of, centreline_point, &
        centreline_frame
    use rs_model_support, only: end_hold_t, end_hold
    use rs_model_capabilities, only: capability_t
    use rs_formulations_registry, only: capability_of
    use rs_io_input_check_common, only: at, rod_index, rod_names, see_matrix, leading_count
    implicit none
    private

    public :: check_unique_names, check_bcs, check_loads, check_actuators, check_joints, &
        resolve_joint_axes, resolve_plates, resolve_contact, resolve_obstacles

    !> Deviation from unit length or orthogonality that counts as round-off.
    real(rk), parameter :: round_off = 4.0_rk * epsilon(1.0_rk)
    !> Largest distance of two joined rod ends, relative to the longer rod's length.
    real(rk), parameter :: joint_tolerance = 1.0e-9_rk
    !> Largest initial speed of a pinned end relative to the rod's speed scale.
    real(rk), parameter :: rest_tolerance = 1.0e-12_rk

contains


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


    !> Supports: an existing rod, each end supported once (several driven &bc on one end add
    !> up their velocities when the rod's formulation drives ends by velocity, capability_t
    !> drive), a clamped end starting at rest (the rod's initial velocity field vanishes
    !> there only without velocity and angular_velocity,
    !> since the director rates are angular_velocity x d_i), a pinned end starting at rest
    !> (it may turn: a rotation about the pin is allowed), sliding and held ends at rest in
    !> what they hold (rs_model_support) and a held end naming each entry once (and the
    !> rotation or its twist, not both).
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
                if (r > 0 .and. (trim(bc%kind) == 'held' .or. trim(bc%kind) == 'sliding')) then
                    if (geometry_ok(r)) call check_held_at_rest(scene, r, bc, errors)
                end if
                if (trim(bc%kind) == 'held') call check_hold_entries(scene, bc, errors)
                call check_driven(scene, bc, errors)
                if (trim(bc%kind) == 'sliding' .and. all(bc%axis /= unset_real)) then
                    if (all(bc%axis == 0.0_rk)) call errors%add(at(scene, bc%input_line) // &
                        '&bc axis: must not be the zero vector (the direction a sliding end ' // &
                        'moves along)')
                end if
                if (trim(bc%kind) == 'body') call check_body_inertia(body_inertia_tensor(bc), &
                    at(scene, bc%input_line) // '&bc inertia, inertia_products', errors)
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


    !> The inertia tensor of a body on an end (kind = 'body') is one of a body: positive
    !> semidefinite, each principal moment at most the sum of the other two (the triangle
    !> inequalities, which also make the Euler tensor E = tr(J)/2 I - J of the director form
    !> positive semidefinite: its kinetic energy is never negative).
    !> `tensor` of a body on an end or of a floating plate; `here` leads the message.
    subroutine check_body_inertia(tensor, here, errors)
        real(rk), intent(in) :: tensor(3, 3)
        character(len=*), intent(in) :: here
        type(error_list_t), intent(inout) :: errors
        real(rk) :: euler(3, 3), scale
        integer :: i, j
        logical :: semidefinite
        euler = -tensor
        do i = 1, 3
            euler(i, i) = euler(i, i) + 0.5_rk * (tensor(1, 1) + tensor(2, 2) + tensor(3, 3))
        end do
        ! Semidefinite: every principal minor is >= 0 (to round-off of the entries).
        scale = max(maxval(abs(tensor)), tiny(1.0_rk))
        semidefinite = all([(euler(i, i) >= -1.0e-12_rk * scale, i = 1, 3)])
        do i = 1, 3
            do j = i + 1, 3
                semidefinite = semidefinite .and. euler(i, i) * euler(j, j) - euler(i, j)**2 >= &
                    -1.0e-12_rk * scale**2
            end do
        end do
        semidefinite = semidefinite .and. determinant3(euler) >= -1.0e-12_rk * scale**3
        if (.not. semidefinite) call errors%add(here // &
            ': not the inertia tensor of a body (a principal ' // &
            'moment exceeds the sum of the other two, or the tensor is not positive ' // &
            'semidefinite; the second moments of its mass would be negative)')
    end subroutine check_body_inertia

    pure real(rk) function determinant3(a)
        real(rk), intent(in) :: a(3, 3)
        determinant3 = a(1, 1) * (a(2, 2) * a(3, 3) - a(2, 3) * a(3, 2)) - &
            a(1, 2) * (a(2, 1) * a(3, 3) - a(2, 3) * a(3, 1)) + &
            a(1, 3) * (a(2, 1) * a(3, 2) - a(2, 2) * a(3, 1))
    end function determinant3

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


    !> A held or sliding end (rs_model_support) starts at rest in what it holds: the initial
    !> velocity velocity + angular_velocity x (p - rotation_center) at the end (point p) has no
    !> component along the held directions, a held rotation does not turn
    !> (angular_velocity = 0, since the director rates are angular_velocity x d_i), and a held
    !> twist does not turn about the end's axis (angular_velocity . d3 = 0 there).
    subroutine check_held_at_rest(scene, r, bc, errors)
        type(scene_t), intent(in) :: scene
        integer, intent(in) :: r
        type(bc_input_t), intent(in) :: bc
        type(error_list_t), intent(inout) :: errors
        type(end_hold_t) :: hold
        real(rk) :: p(3), arm(3), v(3), scale, tangent(3)
        character(len=:), allocatable :: where
        associate (rod => scene%rods(r))
            if (all(rod%velocity == 0.0_rk) .and. all(rod%angular_velocity == 0.0_rk)) return
            hold = end_hold(bc)
            where = at(scene, rod%input_line) // '&rod ''' // trim(rod%name) // ''' '
            if (hold%rotation .and. any(rod%angular_velocity /= 0.0_rk)) call errors%add(where // &
                'angular_velocity: (' // vector_text(rod%angular_velocity) // ') given, but ' // &
                'the ''' // trim(bc%end) // ''' end''s rotation is held (&bc at line ' // &
                str(bc%input_line) // ') and starts at rest; allowed: 0, 0, 0')
            if (hold%twist) then
                tangent = end_tangent(rod, bc%end)
                if (abs(dot_product(rod%angular_velocity, tangent)) > rest_tolerance * &
                    norm2(rod%angular_velocity)) call errors%add(where // 'angular_velocity: (' // &
                    vector_text(rod%angular_velocity) // ') turns the ''' // trim(bc%end) // &
                    ''' end about its axis (' // vector_text(tangent) // '), whose twist is ' // &
                    'held (&bc at line ' // str(bc%input_line) // ') and starts at rest; ' // &
                    'allowed: an angular velocity across the axis')
            end if
            p = end_point(rod, bc%end)
            arm = p - rod%rotation_center
            v = matmul(hold%position, rod%velocity + cross3(rod%angular_velocity, arm))
            scale = norm2(rod%velocity) + norm2(rod%angular_velocity) * norm2(arm)
            if (norm2(v) <= rest_tolerance * scale) return
            call errors%add(where // 'velocity: the initial velocity at the ''' // &
                trim(bc%end) // ''' end has the component (' // vector_text(v) // ') along ' // &
                'the directions its ' // trim(bc%kind) // ' support holds (&bc at line ' // &
                str(bc%input_line) // '), which start at rest; allowed: a velocity there ' // &
                'along the free directions only')
        end associate
    end subroutine check_held_at_rest


    !> A held end names each of x, y, z, rotation, twist at most once, and not both the
    !> rotation and its twist.
    subroutine check_hold_entries(scene, bc, errors)
        type(scene_t), intent(in) :: scene
        type(bc_input_t), intent(in) :: bc
        type(error_list_t), intent(inout) :: errors
        integer :: i
        if (any(bc%hold == 'rotation') .and. any(bc%hold == 'twist')) call errors%add(at(scene, &
            bc%input_line) // '&bc hold: ''rotation'' and ''twist'' are both named; the ' // &
            'whole rotation includes the twist: name ''rotation'' for a clamp, ''twist'' ' // &
            'for an end free to bend but not to turn about its axis')
        do i = 2, size(bc%hold)
            if (len_trim(bc%hold(i)) == 0) cycle
            if (.not. any(bc%hold(1:i - 1) == bc%hold(i))) cycle
            call errors%add(at(scene, bc%input_line) // '&bc hold: ''' // trim(bc%hold(i)) // &
                ''' is named twice; name each of x, y, z, rotation, twist at most once')
            return
        end do
    end subroutine check_hold_entries


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


    !> The reference tangent d3 at end `end_name` ('start' or 'end') of a resolved rod.
    function end_tangent(rod, end_name) result(t)
        type(rod_input_t), intent(in) :: rod
        character(len=*), intent(in) :: end_name
        real(rk) :: t(3)
        type(rod_geometry_t) :: geometry
        real(rk) :: frame(3, 3)
        geometry = rod_geometry_of(rod)
        frame = centreline_frame(geometry, merge(0.0_rk, geometry%length, &
            trim(end_name) == 'start'))
        t = frame(:, 3)
    end function end_tangent


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
                if (plate%mass > 0.0_rk) call check_floating_plate(scene, plate, here, errors)
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


    !> A floating plate (mass > 0, issue 24 item 4; message prefix `here`): not driven, its
    !> rods on ph_director (the body lives on its first rod's end), its inertia one of a body.
    subroutine check_floating_plate(scene, plate, here, errors)
        type(scene_t), intent(in) :: scene
        type(plate_input_t), intent(in) :: plate
        character(len=*), intent(in) :: here
        type(error_list_t), intent(inout) :: errors
        integer :: r
        type(capability_t) :: row
        if (any(plate%displacement /= 0.0_rk) .or. any(plate%rotation /= 0.0_rk)) &
            call errors%add(here // 'mass: a plate with a mass floats, moved by its rods, so it ' // &
            'is not driven: remove displacement and rotation (or the mass, for a driven plate)')
        r = rod_index(scene, plate%rods(1))
        if (r > 0) then
            row = capability_of(trim(scene%rods(r)%formulation))
            if (.not. row%floating_plates) call errors%add(here // 'mass: floating plates ' // &
                'are not available for formulation ''' // trim(scene%rods(r)%formulation) // &
                '''; available for: ph_director (docs/user/capabilities.md)')
        end if
        call check_body_inertia(inertia_tensor(plate%inertia, plate%inertia_products), &
            here // 'inertia, inertia_products', errors)
    end subroutine check_floating_plate

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
    !> skip >= 0, mu >= 0 and slip_velocity > 0 are the reader's (rs_io_input_spec); friction
    !> (mu > 0) needs a dynamic run; that all rods can touch (ph_director): check_capabilities.
    subroutine resolve_contact(scene, geometry_ok, errors)
        type(scene_t), intent(inout) :: scene
        logical, intent(in) :: geometry_ok(:)
        type(error_list_t), intent(inout) :: errors
        character(len=:), allocatable :: here, user
        real(rk) :: r_max, h_min
        integer :: i
        logical :: all_known, obstacles
        all_known = .true.
        obstacles = .false.
        if (allocated(scene%obstacles)) obstacles = size(scene%obstacles) > 0
        if (scene%contact%given) then
            user = '&contact (line ' // str(scene%contact%input_line) // ')'
            if (scene%contact%mu > 0.0_rk .and. scene%time%quasistatic) call errors%add( &
                at(scene, scene%contact%input_line) // '&contact mu: friction acts on the ' // &
                'slip velocity of a time step, and a quasistatic run has none; set mu = 0 or ' // &
                'run dynamically')
        else if (obstacles) then
            user = '&obstacle (line ' // str(scene%obstacles(1)%input_line) // ')'
        end if
        do i = 1, size(scene%rods)
            associate (rod => scene%rods(i))
                here = at(scene, rod%input_line) // '&rod ''' // trim(rod%name) // ''' '
                if (.not. (scene%contact%given .or. obstacles)) then
                    if (rod%contact_radius /= unset_real) call errors%add(here // 'contact_radius: ' // &
                        str(rod%contact_radius) // ' given, but the scene has no &contact or ' // &
                        '&obstacle group, which is what uses it; remove it or add &contact')
                    cycle
                end if
                if (rod%contact_radius == unset_real) then
                    if ((trim(rod%section) == 'circle' .or. trim(rod%section) == 'tube') .and. &
                            rod%radius /= unset_real) then
                        rod%contact_radius = rod%radius
                    else
                        call errors%add(here // 'contact_radius: required with ' // user // &
                            ' for section = ''' // &
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

    !> The obstacles (&obstacle): unique names; a plane takes a normal and no radius, a sphere a
    !> radius and no normal, a cylinder both; normals and axes are normalized.
    subroutine resolve_obstacles(scene, errors)
        type(scene_t), intent(inout) :: scene
        type(error_list_t), intent(inout) :: errors
        type(time_function_t) :: f
        type(error_t), allocatable :: err
        character(len=:), allocatable :: here
        logical :: has_normal, has_radius, wants_normal, wants_radius
        integer :: o, q
        if (.not. allocated(scene%obstacles)) allocate(scene%obstacles(0))
        do o = 1, size(scene%obstacles)
            associate (obstacle => scene%obstacles(o))
                here = at(scene, obstacle%input_line) // '&obstacle ''' // &
                    trim(obstacle%name) // ''' '
                do q = 1, o - 1
                    if (scene%obstacles(q)%name == obstacle%name) call errors%add(here // &
                        'name: also the name of the obstacle at line ' // &
                        str(scene%obstacles(q)%input_line))
                end do
                has_normal = any(obstacle%normal /= unset_real)
                has_radius = obstacle%radius /= unset_real
                wants_normal = trim(obstacle%kind) /= 'sphere'
                wants_radius = trim(obstacle%kind) /= 'plane'
                if (wants_normal .and. .not. has_normal) call errors%add(here // 'normal: ' // &
                    'required for kind = ''' // trim(obstacle%kind) // ''' (the plane''s ' // &
                    'outward normal, the cylinder''s axis)')
                if (.not. wants_normal .and. has_normal) call errors%add(here // 'normal: a ' // &
                    'sphere takes none')
                if (wants_radius .and. .not. has_radius) call errors%add(here // 'radius: ' // &
                    'required for kind = ''' // trim(obstacle%kind) // '''')
                if (.not. wants_radius .and. has_radius) call errors%add(here // 'radius: a ' // &
                    'plane takes none')
                call check_time_function(here, obstacle%time_function, obstacle%t_on, &
                    obstacle%t_off, obstacle%table_times, obstacle%table_values, errors)
                if (any(obstacle%displacement /= 0.0_rk)) then
                    call time_function_from_obstacle(obstacle, f, err)
                    if (allocated(err)) then
                        deallocate(err)
                    else if (f%value(0.0_rk) /= 0.0_rk) then
                        call errors%add(here // 'time_function: f(0) = ' // &
                            str(f%value(0.0_rk)) // '; a moving obstacle (displacement not ' // &
                            'zero) starts where it is given, so f(0) = 0')
                    end if
                end if
                if (obstacle%mu > 0.0_rk .and. scene%time%quasistatic) call errors%add(here // &
                    'mu: friction acts on the slip velocity of a time step, and a quasistatic ' // &
                    'run has none; set mu = 0 or run dynamically')
                if (obstacle%damping > 0.0_rk .and. scene%time%quasistatic) call errors%add( &
                    here // 'damping: it acts on the rate of penetration of a time step, and ' // &
                    'a quasistatic run has none; set damping = 0 or run dynamically')
                if (has_normal) then
                    where (obstacle%normal == unset_real) obstacle%normal = 0.0_rk
                    if (norm2(obstacle%normal) == 0.0_rk) then
                        call errors%add(here // 'normal: the zero vector')
                    else
                        obstacle%normal = obstacle%normal / norm2(obstacle%normal)
                    end if
                end if
            end associate
        end do
    end subroutine resolve_obstacles

end module rs_io_input_cross_check
